//! A part sliding along the dexel stock: stretches of a move proven clear in one query.
//!
//! Conservative advancement steps by the proven gap, at least the tolerance; a part that slides
//! along the bar at a gap of 0 (a live holder's flat face on the bar's radius while a drill feeds
//! along z) then steps by the tolerance over the whole move. As the 2D check's proven stretches
//! (ARCHITECTURE.md, "Exact mode"), a stretch `[u0, u1]` is proven instead: when the part's pose
//! only translates along a polyline of axis values over it ([`Follow::corners`]), every pose in
//! between lies in the convex hull of the poses at the polyline's corners, and
//! `collide3::stock_hull_depth` bounds the depth any of those poses can have in the stock as the
//! advancement's probes measure it (the same view, which does not change along the search); with
//! a milled stock too, whose material the dexel stock holds (`mill.rs`: material is what both
//! hold), so a stretch clear of the dexel stock is clear of it. A
//! bound of at most half of `TOUCH_EPS` proves that no probe in the stretch could find a contact:
//! the stretch is skipped. So a proof never hides a contact; it changes only where the probes
//! fall. A proven stretch doubles the next one; a failed one quarters it, and no proof is tried
//! again until the probes have covered that much.

use super::{Follow, Three};
use crate::collide3::{self, Shape3};
use crate::geom::TOUCH_EPS;
use crate::interp::MoveKind;
use crate::kin::{AxisKind, CompId, Iso, Poser};
use crate::motion::Path as Timing;
use crate::scene::{DexelStock, View};

/// Stretches proven and failed along one part's advancement against the stock.
pub(super) struct Slide(collide3::Stretches);

impl Slide {
    /// `base`: the shortest stretch worth a proof (in `u`), a few of the advancement's shortest
    /// steps.
    pub fn new(base: f64) -> Slide {
        Slide(collide3::Stretches::new(base))
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
        self.0.skip(u, step, |u0, u1| proven(three, f, a, sa, stock, u0, u1))
    }
}

/// Whether component `a`'s pose only translates over the move (no rotary joint above it turns,
/// the turret's index aside: a tool of another station stands at its angle).
fn translates_only(three: &Three, f: &Follow, a: CompId) -> bool {
    let k = &three.kin;
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
    true
}

/// The poses (world frame) of each of `parts` at the corners of the polyline the move follows
/// over `[u0, u1]` ([`Follow::corners`]), one list per corner, when every part only translates
/// there (between two corners each then goes linearly); `None` otherwise (no proof).
fn corner_poses(three: &Three, f: &Follow, parts: &[CompId], u0: f64, u1: f64) -> Option<Vec<Vec<Iso>>> {
    // A rotary joint that turns over the move carries a part along an arc.
    if !parts.iter().all(|&c| translates_only(three, f, c)) {
        return None;
    }
    let corners = f.corners(u0, u1)?;
    let k = &three.kin;
    let mut poser = Poser::focused(k, parts);
    let mut vals = Vec::new();
    Some(
        corners
            .iter()
            .map(|&u| {
                collide3::Path::at(f, u, &mut vals);
                poser.pose(k, &vals);
                parts.iter().map(|&c| *poser.world(c)).collect()
            })
            .collect(),
    )
}

/// Whether no pose of the pair `a`, `b` over `[u0, u1]` overlaps at all: both only translate,
/// each going linearly between the polyline's corners, and over each piece between two corners
/// the two solids stay apart (`collide3::swept_clear`, a shape cast of the pieces'
/// translations, with a margin of a hundredth of the touching tolerance).
pub(super) fn pair_proven(
    three: &Three,
    f: &Follow,
    (a, sa): (CompId, &Shape3),
    (b, sb): (CompId, &Shape3),
    u0: f64,
    u1: f64,
) -> bool {
    let Some(poses) = corner_poses(three, f, &[a, b], u0, u1) else {
        return false;
    };
    poses
        .windows(2)
        .all(|w| collide3::swept_clear(sa, (&w[0][0], &w[1][0]), sb, (&w[0][1], &w[1][1]), 0.01 * TOUCH_EPS))
}

/// Whether no pose of component `a` over `[u0, u1]` overlaps the stock (as it is now) by more
/// than `TOUCH_EPS` (see the module docs).
fn proven(three: &Three, f: &Follow, a: CompId, sa: &Shape3, stock: &mut DexelStock, u0: f64, u1: f64) -> bool {
    let Some(poses) = corner_poses(three, f, &[a], u0, u1) else {
        return false;
    };
    let poses: Vec<Iso> = poses.into_iter().map(|p| p[0]).collect();
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
