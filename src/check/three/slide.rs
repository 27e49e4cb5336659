//! A part sliding along the dexel stock: stretches of a move proven clear in one query.
//!
//! Conservative advancement steps by the proven gap, at least the tolerance; a part that slides
//! along the bar at a gap of 0 (a live holder's flat face on the bar's radius while a drill feeds
//! along z) then steps by the tolerance over the whole move. As the 2D check's proven stretches
//! (ARCHITECTURE.md, "Exact mode"), a stretch `[u0, u1]` is proven instead: when the part's pose
//! only translates along a polyline of axis values over it ([`Follow::corners`]), every pose in
//! between lies in the convex hull of the poses at the polyline's corners, and
//! `collide3::stock_hull_depth` bounds the depth any of those poses can have in the stock as the
//! advancement's probes measure it (the same view, which does not change along the search). A
//! bound of at most half of `TOUCH_EPS` proves that no probe in the stretch could find a contact:
//! the stretch is skipped. So a proof never hides a contact; it changes only where the probes
//! fall. A proven stretch doubles the next one; a failed one quarters it, and no proof is tried
//! again until the probes have covered that much.

use super::{Follow, Three};
use crate::collide3::{self, Shape3};
use crate::geom::TOUCH_EPS;
use crate::interp::MoveKind;
use crate::kin::{AxisKind, CompId, Poser};
use crate::motion::Path as Timing;
use crate::scene::{DexelStock, View};

/// Stretches proven and failed along one pair's advancement, and the next one's length.
pub(super) struct Slide {
    /// The next stretch's length in `u`; never below `base`.
    reach: f64,
    base: f64,
    /// No proof is tried before this `u` (after a failed one).
    hold: f64,
}

impl Slide {
    /// `base`: the shortest stretch worth a proof (in `u`), a few of the advancement's shortest
    /// steps.
    pub fn new(base: f64) -> Slide {
        Slide {
            reach: base,
            base,
            hold: 0.0,
        }
    }

    /// Where the advancement may go on from `u` instead of stepping by `step`: the end of a
    /// stretch proven clear, or `None` (step as before). Tried only when the step is shorter
    /// than the stretch.
    #[allow(clippy::too_many_arguments)]
    pub fn skip(
        &mut self,
        three: &Three,
        f: &Follow,
        a: CompId,
        sa: &Shape3,
        stock: &mut DexelStock,
        u: f64,
        step: f64,
    ) -> Option<f64> {
        if !collide3::positive(self.base) || step >= self.reach || u < self.hold || u >= 1.0 {
            return None;
        }
        let end = (u + self.reach).min(1.0);
        if proven(three, f, a, sa, stock, u, end) {
            self.reach *= 2.0;
            return Some(end);
        }
        self.hold = u + self.reach;
        self.reach = (self.reach / 4.0).max(self.base);
        None
    }
}

/// Whether no pose of component `a` over `[u0, u1]` overlaps the stock (as it is now) by more
/// than `TOUCH_EPS` (see the module docs).
fn proven(three: &Three, f: &Follow, a: CompId, sa: &Shape3, stock: &mut DexelStock, u0: f64, u1: f64) -> bool {
    let k = &three.kin;
    // A rotary joint that turns over the move carries the part along an arc: no proof.
    let mut at = Some(a);
    while let Some(i) = at {
        let Some(c) = k.components.get(i) else { return false };
        if let Some(ax) = c.axis {
            let rotary = matches!(k.axes.get(ax).map(|x| &x.kind), Some(AxisKind::Rotary { .. }));
            let moves = f.rates.get(ax).copied().unwrap_or(0.0) != 0.0 && f.index.map_or(true, |(ix, _)| ix != ax);
            if rotary && moves {
                return false;
            }
        }
        at = c.parent;
    }
    let Some(corners) = f.corners(u0, u1) else {
        return false;
    };
    let mut poser = Poser::focused(k, &[a]);
    let mut vals = Vec::new();
    let poses: Vec<_> = corners
        .iter()
        .map(|&u| {
            collide3::Path::at(f, u, &mut vals);
            poser.pose(k, &vals);
            *poser.world(a)
        })
        .collect();
    collide3::stock_hull_depth(sa, &poses, stock, View::Now) <= 0.5 * TOUCH_EPS
}

impl Follow<'_> {
    /// The instants from `u0` to `u1` at the corners of a polyline that the axis values follow
    /// between them (between two consecutive corners, every axis goes linearly in one common
    /// parameter): the ends, and a dogleg's arrivals of X and of Z in between. `None` on an arc
    /// (G2/G3 in the plane or out of it) and on a feed whose speed varies along a line while an
    /// extra axis moves (the extra axes go linearly in time, X and Z not).
    pub(super) fn corners(&self, u0: f64, u1: f64) -> Option<Vec<f64>> {
        if matches!(self.m.kind, MoveKind::Arc { .. } | MoveKind::ToolChange { .. }) {
            return None;
        }
        if self.e.is_some_and(|e| e.arc.is_some()) {
            return None;
        }
        let extras_still = self.e.map_or(true, |e| e.start == e.end);
        let mut out = vec![u0];
        match &self.item.path {
            Timing::Still(_) | Timing::Line { .. } | Timing::Uniform => {}
            Timing::Varying { .. } if extras_still => {}
            Timing::Varying { .. } => return None,
            Timing::Dogleg { tx, tz, .. } => {
                let d = self.item.duration;
                if !collide3::positive(d) {
                    return None;
                }
                let mut bends = [tx / d, tz / d];
                bends.sort_by(f64::total_cmp);
                out.extend(bends.into_iter().filter(|&b| b > u0 && b < u1));
            }
        }
        out.push(u1);
        Some(out)
    }
}
