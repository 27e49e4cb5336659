//! LinuxCNC lathe stock removal with the profile in an o-word subroutine: G70 finishing, G71 /
//! G71.1 / G71.2 turning and G72 / G72.1 / G72.2 facing ("G70 Lathe finishing cycle", "G71 G72
//! Lathe roughing cycles" of the LinuxCNC G-code reference). This file reads the cycle's words,
//! runs the profile subroutine, turns its A/C corners and checks it (monotone along the passes);
//! the passes themselves are computed as rs274ngc computes them in `lcnc_g7x.rs` (see
//! docs/cycles-linuxcnc.md).
//!
//! The checks use a working frame (u, v) where the passes step down in u from the start point
//! and run toward −v, the direction in which the profile travels: for G71 u and v are ±X and ±Z,
//! for G72 ±Z and ±X.

#[path = "lcnc_g7x.rs"]
mod g7x;

use super::common::{emit, feed, Mark, Seg, MAX_PASSES};
use crate::gcode::{Block, OName};
use crate::geom::{P2, V2};
use crate::interp::flow::Run;
use crate::interp::letters::Letters;
use crate::interp::state::Motion;
use crate::interp::MoveKind;
use std::f64::consts::TAU;

const EPS: f64 = 1e-9;

/// The working frame: a reflection and possibly a swap of the axes of the spindle frame.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// u is Z and v is X (G72), rather than u X and v Z.
    swap: bool,
    su: f64,
    sv: f64,
}

impl Frame {
    fn to(self, p: P2) -> V2 {
        if self.swap {
            V2::new(self.su * p.y, self.sv * p.x)
        } else {
            V2::new(self.su * p.x, self.sv * p.y)
        }
    }
    /// The frame reverses orientation (a counter-clockwise arc becomes clockwise).
    fn flips(self) -> bool {
        (self.su * self.sv < 0.0) != self.swap
    }
}

/// A piece of a path in the working frame: a line a → b, or an arc about `center`.
#[derive(Clone, Copy, Debug)]
struct El {
    a: V2,
    b: V2,
    /// Centre and direction (counter-clockwise in the working frame).
    arc: Option<(V2, bool)>,
    /// The profile block this piece comes from.
    line: u32,
}

fn rot_ccw(v: V2) -> V2 {
    V2::new(-v.y, v.x)
}

fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}

impl El {
    /// Unit tangent at point p of the piece (in its direction of travel).
    fn tangent_at(&self, p: V2) -> V2 {
        match self.arc {
            None => (self.b - self.a) / (self.b - self.a).norm(),
            Some((c, ccw)) => {
                let r = rot_ccw(p - c) / (p - c).norm();
                if ccw {
                    r
                } else {
                    -r
                }
            }
        }
    }
    fn start_tangent(&self) -> V2 {
        self.tangent_at(self.a)
    }
    fn end_tangent(&self) -> V2 {
        self.tangent_at(self.b)
    }
    /// Signed sweep of an arc (positive counter-clockwise).
    fn sweep(&self) -> f64 {
        let Some((c, ccw)) = self.arc else { return 0.0 };
        let a0 = (self.a.y - c.y).atan2(self.a.x - c.x);
        let a1 = (self.b.y - c.y).atan2(self.b.x - c.x);
        if ccw {
            let d = (a1 - a0).rem_euclid(TAU);
            if d < 1e-12 {
                TAU
            } else {
                d
            }
        } else {
            let d = (a0 - a1).rem_euclid(TAU);
            -(if d < 1e-12 { TAU } else { d })
        }
    }
    /// This piece offset by d to its left.
    fn offset(&self, d: f64) -> Option<El> {
        match self.arc {
            None => {
                let n = rot_ccw(self.start_tangent()) * d;
                Some(El {
                    a: self.a + n,
                    b: self.b + n,
                    ..*self
                })
            }
            Some((c, ccw)) => {
                let r = (self.a - c).norm();
                let r2 = if ccw { r - d } else { r + d };
                if r2 < 1e-7 {
                    return None;
                }
                let k = r2 / r;
                Some(El {
                    a: c + (self.a - c) * k,
                    // Both ends scaled alike, as rs274 does: an end off the start radius stays
                    // off it by as much.
                    b: c + (self.b - c) * k,
                    ..*self
                })
            }
        }
    }
    fn len(&self) -> f64 {
        match self.arc {
            None => (self.b - self.a).norm(),
            Some((c, _)) => (self.a - c).norm() * self.sweep().abs(),
        }
    }
    /// Points along the piece at equal fractions of it (ends included), for the test that the
    /// profile runs one way (its `y` never rises by more than 1e-3 over the least before): a
    /// line's two ends, an arc's 33 points at its start angle plus fractions of its sweep.
    ///
    /// An arc whose `y` falls all along its sweep ([`falls_all_along`]: its travel turns level
    /// at most 1e-7 rad past either end, where a fillet of a corner at a right angle ends) and
    /// whose radius is under 1e6 gives its two ends only: every point between lies no higher
    /// than its start and no lower than its end but for r·(1 − cos 1e-7) (under 5e-9) and
    /// rounding, so the 31 points left out could not fail the test (by 1e-3) nor lower the
    /// least `y` but by that; their 62 sines and cosines were a tenth of the cost of a program
    /// of G71/G70 cycles.
    fn samples(&self) -> impl Iterator<Item = V2> + '_ {
        let arc = self.arc.map(|(c, _)| {
            (
                c,
                (self.a - c).norm(),
                (self.a.y - c.y).atan2(self.a.x - c.x),
                self.sweep(),
            )
        });
        let n = match arc {
            None => 1,
            Some((_, r, a0, sweep)) if r < 1e6 && falls_all_along(a0, sweep) => 1,
            Some(_) => 32,
        };
        (0..=n).map(move |k| {
            let t = k as f64 / n as f64;
            match arc {
                None => self.a + (self.b - self.a) * t,
                Some((c, r, a0, sweep)) => {
                    let a = a0 + sweep * t;
                    c + V2::new(r * a.cos(), r * a.sin())
                }
            }
        })
    }
}

/// An arc from angle `a0` (radians, as `atan2` gives it) turning by `sweep` (positive
/// counter-clockwise) moves downward (`y` falling) all along: counter-clockwise it stays where
/// the cosine is negative (angles π/2 to 3π/2), clockwise where it is positive (−π/2 to π/2),
/// or goes past those bounds by at most 1e-7 rad (a fillet's end lands on one, to rounding).
fn falls_all_along(a0: f64, sweep: f64) -> bool {
    const M: f64 = -1e-7;
    use std::f64::consts::{FRAC_PI_2, PI};
    if sweep > 0.0 {
        let a = if a0 < 0.0 { a0 + TAU } else { a0 };
        a >= FRAC_PI_2 + M && a + sweep <= PI + FRAC_PI_2 - M
    } else {
        a0 <= FRAC_PI_2 - M && a0 + sweep >= -FRAC_PI_2 + M
    }
}

/// The intersections of the carriers (infinite line or whole circle) of two pieces.
fn intersect(e1: &El, e2: &El) -> Vec<V2> {
    fn line_circle(p: V2, t: V2, c: V2, r: f64) -> Vec<V2> {
        // |p + s t − c|² = r², t unit.
        let f = p - c;
        let b = f.dot(&t);
        let disc = b * b - (f.dot(&f) - r * r);
        if disc < -1e-12 {
            return vec![];
        }
        let s = disc.max(0.0).sqrt();
        vec![p + t * (-b - s), p + t * (-b + s)]
    }
    match (e1.arc, e2.arc) {
        (None, None) => {
            let (t1, t2) = (e1.start_tangent(), e2.start_tangent());
            let den = cross(t1, t2);
            if den.abs() < 1e-12 {
                return vec![];
            }
            let s = cross(e2.a - e1.a, t2) / den;
            vec![e1.a + t1 * s]
        }
        (None, Some((c, _))) => line_circle(e1.a, e1.start_tangent(), c, (e2.a - c).norm()),
        (Some((c, _)), None) => line_circle(e2.a, e2.start_tangent(), c, (e1.a - c).norm()),
        (Some((c1, _)), Some((c2, _))) => {
            let (r1, r2) = ((e1.a - c1).norm(), (e2.a - c2).norm());
            let d = (c2 - c1).norm();
            if d < 1e-12 || d > r1 + r2 + 1e-9 || d < (r1 - r2).abs() - 1e-9 {
                return vec![];
            }
            let a = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
            let h = (r1 * r1 - a * a).max(0.0).sqrt();
            let u = (c2 - c1) / d;
            let m = c1 + u * a;
            vec![m + rot_ccw(u) * h, m - rot_ccw(u) * h]
        }
    }
}

#[cfg(test)]
/// The profile offset by d to its left (toward the start point): round corners where the
/// offsets part, intersections where they cross. `Err` names the profile line that fails.
fn offset_path(prof: &[El], d: f64) -> Result<Vec<El>, u32> {
    let mut out: Vec<El> = Vec::with_capacity(prof.len() * 2);
    // The profile piece each offset piece comes from (None: a round corner).
    let mut from: Vec<Option<usize>> = Vec::with_capacity(prof.len() * 2);
    for (i, e) in prof.iter().enumerate() {
        let Some(mut o) = e.offset(d) else { return Err(e.line) };
        if let Some(prev) = i.checked_sub(1).map(|k| prof[k]) {
            let (t1, t2) = (prev.end_tangent(), e.start_tangent());
            let (cr, dot) = (cross(t1, t2), t1.dot(&t2));
            let last = out.last_mut().ok_or(e.line)?;
            if d < EPS || (cr.abs() < 1e-9 && dot > 0.0) {
                o.a = last.b;
            } else if cr < 0.0 {
                // Turning right: the offsets part; a round corner about the profile's corner.
                let corner = El {
                    a: last.b,
                    b: o.a,
                    arc: Some((e.a, false)),
                    line: e.line,
                };
                out.push(corner);
                from.push(None);
            } else if cr > 0.0 {
                let near = e.a;
                let x = intersect(last, &o)
                    .into_iter()
                    .min_by(|p, q| (p - near).norm().total_cmp(&(q - near).norm()))
                    .ok_or(e.line)?;
                last.b = x;
                o.a = x;
            } else {
                return Err(e.line);
            }
        }
        out.push(o);
        from.push(Some(i));
    }
    // A piece shorter than the offset runs backward once cut at its corners (a step of the
    // profile smaller than D): rs274 trims the offset curve there, latheguard does not.
    for (o, k) in out.iter().zip(&from) {
        let Some(k) = *k else { continue };
        let e = &prof[k];
        let backward = match e.arc {
            None => (o.b - o.a).dot(&(e.b - e.a)) < -1e-9,
            Some(_) => {
                let (so, se) = (o.sweep(), e.sweep());
                (o.b - o.a).norm() > 1e-7 && (so.signum() != se.signum() || so.abs() > se.abs() + 1e-9)
            }
        };
        if backward {
            return Err(e.line);
        }
    }
    out.retain(|e| (e.b - e.a).norm() > 1e-7 || (e.arc.is_some() && e.len() > 1e-7));
    Ok(out)
}

/// The words of one cycle block.
struct Words7x {
    d: f64,
    i: f64,
    r: f64,
    e: f64,
    p: f64,
}

/// A fillet (A word) or a chamfer (C word) a profile move asks for at its end, between it and
/// the next move of the profile (LinuxCNC G7x profiles only; elsewhere A and C stay refused).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Corner {
    /// Index in `Run::moves` of the move whose end is rounded.
    index: usize,
    /// A fillet of radius `size`, else a chamfer: the chord of the fillet of radius `size`.
    fillet: bool,
    /// mm.
    size: f64,
    /// Physical line of the block with the word.
    line: u32,
}

/// The A or C word of a profile block that made a move (called by the block executor while a
/// G7x profile is being collected): noted for the cycle to turn the corner at the move's end.
pub(crate) fn corner_words(run: &mut Run<'_>, b: &Block, w: &mut Letters) {
    if !matches!(
        run.modal.motion,
        Some(Motion::Line | Motion::Rapid | Motion::ArcCw | Motion::ArcCcw)
    ) {
        // Left unused: reported as on any other block.
        return;
    }
    let (a, c) = (w.get(b'A'), w.get(b'C'));
    let (fillet, size, at) = match (a, c) {
        (Some(_), Some(_)) => {
            run.error(
                b,
                w.at(b'C'),
                "A (fillet) and C (chamfer) on one profile move: give one of them".into(),
            );
            return;
        }
        (Some(v), None) => (true, v, w.at(b'A')),
        (None, Some(v)) => (false, v, w.at(b'C')),
        (None, None) => return,
    };
    if size < 0.0 || !size.is_finite() {
        let what = if fillet {
            "A (fillet radius)"
        } else {
            "C (chamfer length)"
        };
        run.error(b, at, format!("{what} must not be negative"));
        return;
    }
    // The move this block made (none when it stayed where it was: nothing to round then).
    let Some(index) = run.moves.len().checked_sub(1).filter(|&i| run.moves[i].line == b.line) else {
        return;
    };
    let size = size * run.scale();
    if let Some(list) = run.cycles.profile_corners.as_mut() {
        if size > 0.0 && list.last().map_or(true, |l| l.index < index) {
            list.push(Corner {
                index,
                fillet,
                size,
                line: b.line,
            });
        }
    }
}

/// A profile move as a piece of path in the spindle frame (x = X radius, y = Z).
fn piece(sg: &Seg) -> El {
    El {
        a: sg.start.coords,
        b: sg.end.coords,
        arc: match sg.kind {
            MoveKind::Arc { center, sweep } => Some((center.coords, sweep > 0.0)),
            _ => None,
        },
        line: sg.line,
    }
}

/// Where point p (on the carrier of e) lies along e: 0 at its start, 1 at its end.
fn fraction(e: &El, p: V2) -> f64 {
    match e.arc {
        None => (p - e.a).dot(&(e.b - e.a)) / (e.b - e.a).norm_squared(),
        Some((c, ccw)) => {
            let turned = cross(e.a - c, p - c).atan2((e.a - c).dot(&(p - c)));
            let along = if ccw { turned } else { -turned };
            let along = if along < -1e-9 { along + TAU } else { along };
            along / e.sweep().abs()
        }
    }
}

/// The point of e's carrier nearest to p.
fn foot(e: &El, p: V2) -> V2 {
    match e.arc {
        None => {
            let t = e.start_tangent();
            e.a + t * (p - e.a).dot(&t)
        }
        Some((c, _)) => c + (p - c) * ((e.a - c).norm() / (p - c).norm()),
    }
}

/// A move with new ends (an arc keeps its centre and direction, its sweep follows the ends).
fn with_ends(sg: Seg, start: P2, end: P2) -> Seg {
    let kind = match sg.kind {
        MoveKind::Arc { center, sweep } => {
            let (a, b) = (start - center, end - center);
            let turned = cross(a, b).atan2(a.dot(&b));
            let mag = if sweep > 0.0 { turned } else { -turned }.rem_euclid(TAU);
            MoveKind::Arc {
                center,
                sweep: mag.copysign(sweep),
            }
        }
        k => k,
    };
    Seg { kind, start, end, ..sg }
}

/// Turn each corner asked for into a tangent arc (fillet) or a straight bevel (chamfer) between
/// the two moves that meet there, as rs274 does: the fillet of radius A is the circle tangent
/// to both moves on the side the path turns to; a chamfer is the chord of the fillet of radius
/// C (between two lines its ends lie C·tan(θ/2) from the corner, θ the turn: C at a right
/// angle). A corner the path passes straight through, or the last move's end, is left as it
/// is. `Err` says why a corner cannot be turned.
fn turn_corners(segs: &mut Vec<Seg>, corners: &[(usize, Corner)]) -> Result<(), String> {
    for &(i, k) in corners.iter().rev() {
        // On the profile's last move there is no corner: rs274 ignores the word.
        let Some(&next) = segs.get(i + 1) else {
            continue;
        };
        let this = segs[i];
        let (e1, e2) = (piece(&this), piece(&next));
        if e1.len() < 1e-9 || e2.len() < 1e-9 {
            continue;
        }
        let turn = cross(e1.end_tangent(), e2.start_tangent());
        if turn.abs() < 1e-9 {
            continue;
        }
        let what = if k.fillet { "fillet" } else { "chamfer" };
        let word = if k.fillet { "A" } else { "C" };
        let too_big = || {
            format!(
                "the {what} at line {} ({word}{:.4} mm) does not fit between the moves it joins",
                k.line, k.size
            )
        };
        // The fillet's centre: on both moves offset by its radius toward the turn.
        let d = k.size * turn.signum();
        let (Some(o1), Some(o2)) = (e1.offset(d), e2.offset(d)) else {
            return Err(too_big());
        };
        let corner = e1.b;
        let Some(c) = intersect(&o1, &o2)
            .into_iter()
            .min_by(|p, q| (p - corner).norm().total_cmp(&(q - corner).norm()))
        else {
            return Err(too_big());
        };
        let (t1, t2) = (foot(&e1, c), foot(&e2, c));
        let (f1, f2) = (fraction(&e1, t1), fraction(&e2, t2));
        if !(1e-9..=1.0 + 1e-9).contains(&f1) || !(-1e-9..=1.0 - 1e-9).contains(&f2) {
            return Err(too_big());
        }
        let (p1, p2) = (P2::from(t1), P2::from(t2));
        let kind = if k.fillet {
            let (a, b) = (t1 - c, t2 - c);
            MoveKind::Arc {
                center: P2::from(c),
                sweep: cross(a, b).atan2(a.dot(&b)).abs() * turn.signum(),
            }
        } else {
            MoveKind::Line
        };
        segs[i] = with_ends(this, this.start, p1);
        segs[i + 1] = with_ends(next, p2, next.end);
        segs.insert(
            i + 1,
            Seg {
                kind,
                start: p1,
                end: p2,
                line: this.line,
            },
        );
    }
    Ok(())
}

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    let name = match code {
        700 => "G70",
        710 => "G71",
        711 => "G71.1",
        712 => "G71.2",
        720 => "G72",
        721 => "G72.1",
        722 => "G72.2",
        _ => return false,
    };
    let modal_after = cycle(run, b, w, code, name, at);
    // rs274 leaves the motion mode the profile set (a block of axis words after the cycle
    // moves as the profile's last motion did); a refused cycle leaves none.
    run.modal.motion = modal_after;
    true
}

/// The cycle; the motion mode to leave in force.
fn cycle(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, name: &str, at: u32) -> Option<Motion> {
    let at_o = (at > 0).then_some(at);
    let s = run.scale();
    let q = w.get(b'Q');
    let mut num = |l: u8, default: f64| w.get(l).map_or(default, |v| v * s);
    let words = Words7x {
        d: num(b'D', 0.0),
        i: num(b'I', s),
        r: num(b'R', 0.5 * s),
        e: num(b'E', 0.0),
        p: w.get(b'P').unwrap_or(1.0),
    };
    if !run.modal.plane_xz {
        run.error(b, at_o, format!("{name} runs in the XZ plane: select G18"));
        return None;
    }
    let Some(q) = q.filter(|q| *q >= 1.0 && q.fract() == 0.0 && *q < u32::MAX as f64) else {
        run.error(
            b,
            at_o,
            format!("{name} needs Q, the number of the o-word subroutine that holds the profile"),
        );
        return None;
    };
    if code == 700 {
        if words.p < 1.0 || words.p.fract() != 0.0 || words.p > MAX_PASSES as f64 {
            run.error(
                b,
                w.at(b'P'),
                format!("{name}: P (the number of passes) must be a whole number from 1 to {MAX_PASSES}"),
            );
            return None;
        }
    } else if words.i <= 0.0 || words.d < 0.0 || words.r < 0.0 {
        run.error(
            b,
            at_o,
            format!("{name}: I (depth of cut) must be positive, D (allowance) and R (retract) not negative"),
        );
        return None;
    }
    let f = feed(run, b, name)?;
    let start = run.target(b, w)?;
    // A refused cycle moves nothing, not even to its start point.
    let mark = Mark::new(run);
    let done = expand(run, b, code, name, at, q, &words, f, start);
    if done.is_none() {
        mark.drop_moves(run);
    }
    done
}

/// The moves of the cycle from `start`; the motion mode to leave in force. `None` after a finding.
#[allow(clippy::too_many_arguments)]
fn expand(
    run: &mut Run<'_>,
    b: &Block,
    code: u16,
    name: &str,
    at: u32,
    q: f64,
    words: &Words7x,
    f: crate::interp::Feed,
    start: P2,
) -> Option<Motion> {
    let at_o = (at > 0).then_some(at);
    // Under compensation (G70 only: rs274 refuses the others) every straight move goes to the
    // compensation stage, those that go nowhere too, as rs274 hands them to its own.
    let keep = run.cycles.lcnc_g70_comp.is_some();
    straight(run, b, MoveKind::Rapid, start, crate::interp::Feed::Rapid, 0, keep);
    let (mut segs, corners, motion) = trace(run, b, OName::Number(q as u32), at, name)?;
    if let (Some(c), Some(last)) = (run.cycles.lcnc_g70_comp.as_mut(), segs.last()) {
        // rs274 reads the profile after the block's own rapid by setting its current point to
        // each profile block's end; under compensation that point is the nose centre, so the
        // cycle's next move measures its corner from the profile's end (docs/comp.md).
        c.read = Some((run.moves.len(), last.end));
    }
    if let Err(why) = turn_corners(&mut segs, &corners) {
        run.unsupported(
            b,
            at_o,
            format!("{name}: {why}; the cycle's moves are not checked"),
            true,
        );
        return None;
    }
    let Some((first, prof)) = segs.split_first().filter(|(_, p)| !p.is_empty()) else {
        run.error(
            b,
            at_o,
            format!("{name}: the profile o{q} needs a move to its first point and at least one more move"),
        );
        return None;
    };
    let p0 = first.end;
    let pe = prof[prof.len() - 1].end;
    let sign = |v: f64| if v < -EPS { -1.0 } else { 1.0 };
    let facing = code >= 720 || (code == 700 && (pe.y - p0.y).abs() < EPS);
    // The passes step toward the profile from the start point's side; a profile that does not
    // climb at all (a face for G72, a diameter for G71) is offset to the left of its travel
    // whatever the start point, as rs274 does.
    let (du, dv, to_start) = if facing {
        (pe.y - p0.y, pe.x - p0.x, start.y - p0.y)
    } else {
        (pe.x - p0.x, pe.y - p0.y, start.x - p0.x)
    };
    let sv = -sign(dv);
    let su = if code == 700 || du.abs() > EPS {
        sign(to_start)
    } else if facing {
        -sv
    } else {
        sv
    };
    let frame = Frame { swap: facing, su, sv };
    let mut els: Vec<El> = Vec::with_capacity(prof.len());
    for e in prof
        .iter()
        .filter(|sg| (sg.end - sg.start).norm() > 1e-9 || matches!(sg.kind, MoveKind::Arc { .. }))
        .map(|sg| El {
            a: frame.to(sg.start),
            b: frame.to(sg.end),
            arc: match sg.kind {
                MoveKind::Arc { center, sweep } => Some((frame.to(center), (sweep > 0.0) != frame.flips())),
                _ => None,
            },
            line: sg.line,
        })
    {
        // Consecutive lines in one direction are one line (as rs274 prints them).
        match els.last_mut() {
            Some(last)
                if last.arc.is_none()
                    && e.arc.is_none()
                    && cross(last.end_tangent(), e.start_tangent()).abs() < 1e-9
                    && last.end_tangent().dot(&e.start_tangent()) > 0.0 =>
            {
                last.b = e.b
            }
            _ => els.push(e),
        }
    }
    // The profile must run one way along the passes (Z for G71, X for G72).
    let along = if facing { "X" } else { "Z" };
    let mut last_v = frame.to(p0).y;
    for e in &els {
        for p in e.samples() {
            // rs274 allows 1e-3 (an arc whose end radius differs a little from its start radius is
            // sampled on its start radius and may end that far past its end).
            if p.y > last_v + 1e-3 {
                run.error(
                    b,
                    at_o,
                    format!("{name}: the profile is not monotone in {along} (line {})", e.line),
                );
                return None;
            }
            last_v = last_v.min(p.y);
        }
    }
    // The passes, as rs274 computes them (`lcnc_g7x`), in program units.
    let s = run.scale();
    let cx = |p: P2| g7x::C::new(p.y / s, p.x / s);
    let mut pieces: Vec<g7x::Piece> = Vec::with_capacity(prof.len() + 1);
    for sg in std::iter::once(first).chain(
        prof.iter()
            .filter(|sg| (sg.end - sg.start).norm() > 1e-9 || matches!(sg.kind, MoveKind::Arc { .. })),
    ) {
        let pc = g7x::Piece {
            s: cx(sg.start),
            e: cx(sg.end),
            arc: match sg.kind {
                MoveKind::Arc { center, sweep } => Some((cx(center), sweep < 0.0)),
                _ => None,
            },
            line: sg.line,
        };
        // Consecutive lines in one direction are one line (rs274 refuses them: "Cannot
        // intersect parallel lines"; latheguard reads them as the one line they make).
        let n = pieces.len();
        match pieces.last_mut() {
            Some(last) if n > 1 && last.arc.is_none() && pc.arc.is_none() => {
                let (t1, t2) = (last.e - last.s, pc.e - pc.s);
                let cr = t1.re * t2.im - t1.im * t2.re;
                if cr.abs() < 1e-9 * t1.norm() * t2.norm() && t1.re * t2.re + t1.im * t2.im > 0.0 {
                    last.e = pc.e;
                } else {
                    pieces.push(pc);
                }
            }
            _ => pieces.push(pc),
        }
    }
    let cap = 16 * MAX_PASSES + 16 * pieces.len();
    let result = if code == 700 {
        g7x::finish(pieces, cx(start), words.d / s, words.e / s, words.p as u32, cap)
    } else {
        let facing = code >= 720;
        g7x::rough(
            pieces,
            facing,
            (code % 10) as u8,
            cx(start),
            words.d / s,
            words.i / s,
            words.r / s,
            cap,
        )
    };
    let cmds = match result {
        Ok(c) => c,
        Err(why) => {
            run.error(b, at_o, format!("{name}: {why}; the cycle is not run"));
            return None;
        }
    };
    if !super::charge(run, b, cmds.len() as u64) {
        return None;
    }
    let back = |c: g7x::C| P2::new(c.im * s, c.re * s);
    for (cmd, line) in cmds {
        match cmd {
            g7x::Cmd::Rapid(p) => straight(run, b, MoveKind::Rapid, back(p), crate::interp::Feed::Rapid, 0, keep),
            g7x::Cmd::Feed(p) => straight(run, b, MoveKind::Line, back(p), f, line, keep),
            g7x::Cmd::Arc { ccw, center, end } => {
                let from = cx(run.programmed());
                let (a0, a1) = ((from - center).arg(), (end - center).arg());
                // G3 turns counter-clockwise in the z + i·x plane: a negative sweep in x, z.
                let sweep = if ccw {
                    -(a1 - a0).rem_euclid(TAU)
                } else {
                    (a0 - a1).rem_euclid(TAU)
                };
                emit(
                    run,
                    b,
                    MoveKind::Arc {
                        center: back(center),
                        sweep,
                    },
                    back(end),
                    f,
                    line,
                );
            }
        }
    }
    motion
}

/// Where rs274 read a G70's profile while compensation offsets: the number of moves made
/// before (the cycle block's own rapid) and the profile's last point, spindle frame. The block
/// executor hands it to the compensation stage (`Comp::profile_read`).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct CompRead {
    pub read: Option<(usize, P2)>,
}

/// A straight move of the cycle; with `keep` also one that goes nowhere (the compensation stage
/// takes it, as rs274's does: it can move the nose).
#[allow(clippy::too_many_arguments)]
fn straight(run: &mut Run<'_>, b: &Block, kind: MoveKind, end: P2, f: crate::interp::Feed, line: u32, keep: bool) {
    let start = run.programmed();
    if keep && (end - start).norm() < 1e-9 {
        run.push_move(b, kind, start, start, f);
        if let Some(m) = run.moves.last_mut() {
            m.profile_line = line;
        }
    } else {
        emit(run, b, kind, end, f, line);
    }
}

/// Run the profile subroutine from the current point and collect its moves; nothing of it stays
/// (moves, modal state, tool, position). Also the motion mode it left. `None` after a finding.
#[allow(clippy::type_complexity)]
fn trace(
    run: &mut Run<'_>,
    b: &Block,
    sub: OName,
    at: u32,
    name: &str,
) -> Option<(Vec<Seg>, Vec<(usize, Corner)>, Option<Motion>)> {
    let mark = Mark::new(run);
    let stopped = run.stopped;
    // The cycle reads every block of the profile with axis words as a move (G0 is a G1 there),
    // so a profile that names no motion code follows the lines it gives.
    if run.modal.motion.is_none() || matches!(run.modal.motion, Some(Motion::Cycle(_))) {
        run.modal.motion = Some(Motion::Line);
    }
    let outer = run.cycles.profile_corners.replace(Vec::new());
    let called = run.run_sub_inline(b, sub, at);
    let returned = called == Some(true);
    let noted = std::mem::replace(&mut run.cycles.profile_corners, outer).unwrap_or_default();
    let segs = mark.segs(run, true);
    // The moves `segs` is made of, in order: a corner's move is found among them.
    let made: Vec<usize> = (mark.moves..run.moves.len())
        .filter(|&i| {
            matches!(
                run.moves[i].kind,
                MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }
            )
        })
        .collect();
    let corners: Vec<(usize, Corner)> = noted
        .into_iter()
        .filter_map(|k| made.binary_search(&k.index).ok().map(|i| (i, k)))
        .collect();
    let motion = run.modal.motion;
    let budget_spent = run.stopped && !stopped;
    mark.restore_modes(run);
    run.stopped = stopped || budget_spent && run.executed > run.limits.max_blocks;
    mark.drop_moves(run);
    if mark.reported(run) || !returned {
        if !run.stopped && called.is_some() {
            let at_o = (at > 0).then_some(at);
            run.error(
                b,
                at_o,
                format!(
                    "{name}: the profile subroutine could not be read (see the findings at its lines); the cycle is not run"
                ),
            );
        }
        return None;
    }
    Some((segs, corners, motion))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::{Feed, Move};
    use proptest::prelude::*;

    fn line(a: (f64, f64), b: (f64, f64)) -> El {
        El {
            a: V2::new(a.0, a.1),
            b: V2::new(b.0, b.1),
            arc: None,
            line: 1,
        }
    }

    fn lcnc() -> crate::machine::Machine {
        let text = include_str!("../../../machines/linuxcnc-small-lathe.toml");
        crate::machine::from_toml(text, "linuxcnc-small-lathe.toml").unwrap()
    }

    fn interpret(src: &str) -> crate::interp::Interpretation {
        let prog = crate::gcode::parse(src.as_bytes());
        crate::interp::interpret(&prog, src.as_bytes(), &lcnc())
    }

    /// Distance from p to the segment a–b.
    fn seg_dist(p: P2, a: P2, b: P2) -> f64 {
        let d = b - a;
        let t = if d.norm() < 1e-12 {
            0.0
        } else {
            ((p - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
        };
        (p - (a + d * t)).norm()
    }

    /// A fillet rounding a corner at a right angle ends where its travel turns level: it is
    /// still sampled by its ends (the A words of a LinuxCNC profile make these).
    #[test]
    fn a_right_angle_fillet_is_sampled_by_its_ends() {
        let c = V2::new(10.0, -4.0);
        for (a, b, ccw) in [
            (V2::new(9.0, -4.0), V2::new(10.0, -5.0), true),
            (V2::new(10.0, -3.0), V2::new(9.0, -4.0), true),
            (V2::new(11.0, -4.0), V2::new(10.0, -5.0), false),
        ] {
            let el = El {
                a,
                b,
                arc: Some((c, ccw)),
                line: 1,
            };
            assert_eq!(el.samples().count(), 2, "{a:?} -> {b:?}");
        }
        // Rising out of the bottom: every point is taken.
        let el = El {
            a: V2::new(10.0, -5.0),
            b: V2::new(11.0, -4.0),
            arc: Some((c, true)),
            line: 1,
        };
        assert_eq!(el.samples().count(), 33);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// The monotonicity test takes an arc's two ends only when its `y` falls all along:
        /// then each of the 33 points it took before lies no higher than the one before it
        /// (to rounding), so none of them could fail the test or lower the least `y` seen.
        #[test]
        fn an_arc_sampled_by_its_ends_falls_through_every_point_left_out(
            a0 in -3.2f64..3.2,
            sweep in -7.0f64..7.0,
            r in 0.01f64..500.0,
        ) {
            let a0 = a0.clamp(-std::f64::consts::PI, std::f64::consts::PI);
            prop_assume!(sweep.abs() > 1e-6);
            let c = V2::new(3.0, -7.0);
            let at = |t: f64| {
                let a = a0 + sweep * t;
                c + V2::new(r * a.cos(), r * a.sin())
            };
            let el = El { a: at(0.0), b: at(1.0), arc: Some((c, sweep > 0.0)), line: 1 };
            let taken: Vec<V2> = el.samples().collect();
            // The 33 points as the arc itself is swept (its sweep from its ends, within a turn).
            let (s0, sw, re) = ((el.a.y - c.y).atan2(el.a.x - c.x), el.sweep(), (el.a - c).norm());
            let all: Vec<V2> = (0..=32)
                .map(|k| {
                    let a = s0 + sw * (k as f64 / 32.0);
                    c + V2::new(re * a.cos(), re * a.sin())
                })
                .collect();
            let rising = all.windows(2).any(|w| w[1].y > w[0].y + 1e-12 * re);
            if taken.len() == 2 {
                prop_assert!(!rising, "a0 {a0} sweep {sw}: a point left out rises");
                prop_assert_eq!(taken[0], all[0]);
                prop_assert_eq!(taken[1], all[32]);
            } else {
                prop_assert_eq!(&taken, &all);
            }
            // The test is not idle: an arc of more than half a turn always rises somewhere.
            if sw.abs() > std::f64::consts::PI + 1e-6 {
                prop_assert_eq!(taken.len(), 33);
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// Roughing never cuts inside the profile plus the allowance D: every point of every
        /// feed move of a G71 on a random staircase (outside turning, X growing along -Z) lies
        /// at least D from the profile; and the cycle makes its final pass.
        #[test]
        fn g71_feeds_stay_d_away_from_a_monotone_profile(
            steps in proptest::collection::vec((0.2f64..3.0, 0.5f64..6.0, 0.0f64..2.0), 1..6),
            d in 0.0f64..1.0,
            i in 0.3f64..2.0,
        ) {
            let (mut x, mut z) = (2.0f64, 0.0f64);
            let mut pts = vec![(x, z)];
            let mut sub = format!("o100 sub\nG1 X{x:.3} Z{z:.3}\n");
            for (dx, dz, slope) in &steps {
                z -= dz;
                sub += &format!("G1 X{x:.3} Z{z:.3}\n");
                pts.push((x, z));
                x += dx;
                z -= slope;
                sub += &format!("G1 X{x:.3} Z{z:.3}\n");
                pts.push((x, z));
            }
            sub += "o100 endsub\n";
            let sx: f64 = format!("{:.3}", x + 3.0).parse().unwrap();
            let src = format!("G18 G8 G21 G90 G94\nF100\n{sub}G0 X{sx:.3} Z3\nG71 Q100 X{sx:.3} Z3 D{d:.3} I{i:.3} R0.3\nM2\n");
            let out = interpret(&src);
            let cycle_line = 2 + sub.lines().count() as u32 + 2;
            let feeds: Vec<&Move> = out.moves.iter().filter(|m| m.line == cycle_line && m.feed != Feed::Rapid).collect();
            if out.findings.iter().any(|f| f.line == cycle_line) {
                // Refused: then it moves nothing.
                prop_assert!(out.moves.iter().all(|m| m.line != cycle_line));
                return Ok(());
            }
            prop_assert!(!feeds.is_empty(), "no feed moves: {:?}", out.findings);
            let origin = out.moves[0].end - V2::new(sx, 3.0); // program zero
            let prof: Vec<P2> = pts.iter().map(|&(px, pz)| {
                // The interpreter rounds nothing: use the printed values.
                let px: f64 = format!("{px:.3}").parse().unwrap();
                let pz: f64 = format!("{pz:.3}").parse().unwrap();
                origin + V2::new(px, pz)
            }).collect();
            let d: f64 = format!("{d:.3}").parse().unwrap();
            // Where the offset folds over a short step rs274's stepwise trim may cut inside D (two
            // 0.2 mm steps 0.5 mm apart under D0.925: its entry feed ends 0.880 from the profile,
            // checked with rs274); latheguard moves as it does, so only the unfolded are held to D.
            let els: Vec<El> = prof
                .windows(2)
                .filter(|w| (w[1] - w[0]).norm() > 1e-9)
                .map(|w| line((w[0].x, w[0].y), (w[1].x, w[1].y)))
                .collect();
            if offset_path(&els, d).is_err() {
                return Ok(());
            }
            for m in feeds {
                for k in 0..=20 {
                    let p = m.start + (m.end - m.start) * (k as f64 / 20.0);
                    let p = if let MoveKind::Arc { center, sweep } = m.kind {
                        let a0 = (m.start - center).y.atan2((m.start - center).x) + sweep * k as f64 / 20.0;
                        center + V2::new(a0.cos(), a0.sin()) * (m.start - center).norm()
                    } else { p };
                    let dist = prof.windows(2).map(|w| seg_dist(p, w[0], w[1])).fold(f64::MAX, f64::min);
                    // Within 1 µm, the resolution of the program's words (printed to 0.001 mm):
                    // a pass level on a slanted step has been seen 0.43 µm inside D (saved seeds).
                    prop_assert!(dist >= d - 1e-3, "feed point {p:?} is {dist} from the profile, D {d}");
                }
            }
        }
    }

    fn seg_line(a: (f64, f64), b: (f64, f64), line: u32) -> Seg {
        Seg {
            kind: MoveKind::Line,
            start: P2::new(a.0, a.1),
            end: P2::new(b.0, b.1),
            line,
        }
    }

    fn corner(fillet: bool, size: f64) -> Corner {
        Corner {
            index: 0,
            fillet,
            size,
            line: 1,
        }
    }

    #[test]
    fn a_fillet_at_a_right_angle_starts_and_ends_its_radius_from_the_corner() {
        let mut segs = vec![
            seg_line((5.0, 0.0), (5.0, -10.0), 1),
            seg_line((5.0, -10.0), (10.0, -10.0), 2),
        ];
        turn_corners(&mut segs, &[(0, corner(true, 1.0))]).unwrap();
        assert_eq!(segs.len(), 3);
        assert!((segs[0].end - P2::new(5.0, -9.0)).norm() < 1e-12);
        assert!((segs[2].start - P2::new(6.0, -10.0)).norm() < 1e-12);
        let MoveKind::Arc { center, sweep } = segs[1].kind else {
            panic!("no fillet arc: {:?}", segs[1]);
        };
        assert!((center - P2::new(6.0, -9.0)).norm() < 1e-12);
        // Down Z, then up X: a left turn, counter-clockwise in (x, z).
        assert!((sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn a_chamfer_is_the_chord_of_the_fillet_of_radius_c() {
        // A shallow turn (a Z line into a 1:2 taper): the bevel ends C·tan(θ/2) from the corner,
        // not C (rs274 prints Z-19.8820 and X8.0528 Z-20.1056 for C0.5 here).
        let mut segs = vec![
            seg_line((8.0, -9.0), (8.0, -20.0), 1),
            seg_line((8.0, -20.0), (10.0, -24.0), 2),
        ];
        turn_corners(&mut segs, &[(0, corner(false, 0.5))]).unwrap();
        assert_eq!(segs[1].kind, MoveKind::Line);
        assert!((segs[1].start - P2::new(8.0, -19.882)).norm() < 1e-4);
        assert!((segs[1].end - P2::new(8.0528, -20.1056)).norm() < 1e-4);
    }

    #[test]
    fn a_corner_word_on_the_last_move_or_a_straight_joint_changes_nothing() {
        let mut segs = vec![
            seg_line((5.0, 0.0), (5.0, -10.0), 1),
            seg_line((5.0, -10.0), (5.0, -20.0), 2),
        ];
        let before = segs.clone();
        turn_corners(&mut segs, &[(0, corner(true, 1.0)), (1, corner(false, 1.0))]).unwrap();
        assert_eq!(format!("{before:?}"), format!("{segs:?}"));
    }

    #[test]
    fn a_fillet_larger_than_its_moves_is_refused() {
        let mut segs = vec![
            seg_line((5.0, 0.0), (5.0, -10.0), 1),
            seg_line((5.0, -10.0), (7.0, -10.0), 2),
        ];
        let err = turn_corners(&mut segs, &[(0, corner(true, 3.0))]).unwrap_err();
        assert!(err.contains("does not fit"), "{err}");
    }

    proptest! {
        #[test]
        fn a_fillet_touches_a_line_and_an_arc_at_its_radius(
            r in 0.1f64..1.0,
            big in 4.0f64..8.0,
            tilt in 0.2f64..0.8,
            left in proptest::bool::ANY,
        ) {
            // A line down Z, tilted either way, into a counter-clockwise arc of radius about
            // `big` that leaves the corner down Z: a corner of some 0.1 to 0.9 rad, filleted by r.
            let tilt = if left { tilt } else { -tilt };
            let p = P2::new(5.0, -10.0);
            let start = p + V2::new(tilt.sin(), tilt.cos()) * 10.0;
            let center = p + V2::new(big, 0.5);
            let (c1, s1) = (1.0f64.cos(), 1.0f64.sin());
            let rv = p - center;
            let end = center + V2::new(c1 * rv.x - s1 * rv.y, s1 * rv.x + c1 * rv.y);
            let arc = Seg {
                kind: MoveKind::Arc { center, sweep: 1.0 },
                start: p,
                end,
                line: 2,
            };
            let mut segs = vec![seg_line((start.x, start.y), (p.x, p.y), 1), arc];
            let before = (piece(&segs[0]), piece(&segs[1]));
            prop_assert!(turn_corners(&mut segs, &[(0, corner(true, r))]).is_ok());
            prop_assert_eq!(segs.len(), 3);
            {
                let MoveKind::Arc { center: c, .. } = segs[1].kind else { panic!("no arc") };
                // Its ends lie on the moves, at distance r from its centre, and the moves
                // meet it tangent (the centre is r from the line and big ± r from the arc's).
                prop_assert!(((segs[1].start - c).norm() - r).abs() < 1e-9);
                prop_assert!(((segs[1].end - c).norm() - r).abs() < 1e-9);
                let t = before.0.start_tangent();
                prop_assert!((cross(t, c.coords - before.0.a).abs() - r).abs() < 1e-9);
                let rb = (p - center).norm();
                let dc = (c - center).norm();
                prop_assert!((dc - (rb - r)).abs() < 1e-9 || (dc - (rb + r)).abs() < 1e-9);
                prop_assert!((segs[0].end - segs[1].start).norm() < 1e-12);
                prop_assert!((segs[1].end - segs[2].start).norm() < 1e-12);
            }
        }
    }
}
