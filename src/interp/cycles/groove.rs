//! G74 end-face peck drilling / grooving (pecks along Z) and G75 outer/inner diameter grooving
//! (pecks along X).
//!
//! Two-block form (Fanuc 0i-TD B-64304EN, "multiple repetitive cycle"): `G74 R(e)` (or `G75 R(e)`)
//! sets the return amount e after each peck (kept until the next such block); then
//! `G74 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F` / `G75 X(U) Z(W) P(Δi) Q(Δk) R(Δd) F`: Δi the X step
//! (radius), Δk the Z step, both in the least input increment unless written with a decimal point;
//! Δd the relief at the bottom of each groove (also in the least increment without a decimal point).
//!
//! One-block form (Haas lathe operator's manual): `G74 X(U) Z(W) K I [D] F` (K the Z peck, I the
//! X shift) and `G75 X(U) Z(W) I K [D] F` (I the X peck, K the Z shift), in program units; the
//! return amount is the one of the last `R(e)` block, else 1 mm (Haas Setting 22 plays this part).
//!
//! From the start point S: for each groove position along the shift axis (S, then steps of the
//! shift amount, the last one exactly at the end point), feed along the peck axis by the peck
//! amount, rapid back by e, feed on (e + peck) …, up to the end point's depth; then the relief
//! (a feed along the shift axis, back toward S), the rapid out along the peck axis to S's level,
//! and the rapid along the shift axis to the next groove. At the end a rapid back to S.

use super::super::flow::Run;
use super::super::{Feed, MoveKind};
use super::box_::go;
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::letters::Letters;

/// The return amount e when no `G74 R` / `G75 R` block set one, mm.
pub(crate) const DEFAULT_RETURN_MM: f64 = 1.0;
/// Most moves one grooving cycle may make; more is a `program` finding.
pub(crate) const MAX_MOVES: usize = 100_000;

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    let face = code == 740;
    let name = if face { "G74" } else { "G75" };
    let axis = w.peek(b'X') || w.peek(b'Z') || w.peek(b'U') || w.peek(b'W');
    if !axis {
        match w.get(b'R') {
            Some(e) if e >= 0.0 => run.cycles.groove_e = Some(e * run.scale()),
            Some(e) => run.error(
                b,
                w.at(b'R'),
                format!("{name} R{e}: the return amount must not be negative"),
            ),
            None => run.error(
                b,
                Some(at),
                format!("{name} needs R (return amount) or an end point X/Z"),
            ),
        }
        run.check_unused(b, w);
        return true;
    }
    let s_ = run.scale();
    let haas = w.peek(b'I') || w.peek(b'K');
    let Some(end) = run.target(b, w) else {
        run.check_unused(b, w);
        return true;
    };
    // (X step, Z step, relief), mm.
    let (di, dk, relief) = if haas {
        let i = w.get(b'I').unwrap_or(0.0) * s_;
        let k = w.get(b'K').unwrap_or(0.0) * s_;
        (i, k, w.get(b'D').unwrap_or(0.0) * s_)
    } else {
        let i = super::least(run, w, b'P').unwrap_or(0.0);
        let k = super::least(run, w, b'Q').unwrap_or(0.0);
        (i, k, super::least(run, w, b'R').unwrap_or(0.0))
    };
    let e = run.cycles.groove_e.unwrap_or(DEFAULT_RETURN_MM);
    if let Some(feed) = run.feed(b) {
        if di < 0.0 || dk < 0.0 {
            run.error(
                b,
                None,
                format!("{name}: the peck and shift amounts are given without a sign"),
            );
        } else {
            let s = run.programmed();
            // Peck along Z (G74) or X (G75); (peck coordinate, shift coordinate) ↔ P2.
            let (peck, shift) = if face { (dk, di) } else { (di, dk) };
            let split = |p: P2| if face { (p.y, p.x) } else { (p.x, p.y) };
            let join = move |pk: f64, sh: f64| if face { P2::new(sh, pk) } else { P2::new(pk, sh) };
            let (p0, q0) = split(s);
            let (p1, q1) = split(end);
            grooves(run, b, name, [p0, q0, p1, q1], peck, shift, e, relief, feed, &join);
        }
    }
    run.check_unused(b, w);
    true
}

/// Emit the grooves; `c` = [start peck, start shift, end peck, end shift] coordinates.
#[allow(clippy::too_many_arguments)]
fn grooves(
    run: &mut Run<'_>,
    b: &Block,
    name: &str,
    c: [f64; 4],
    peck: f64,
    shift: f64,
    e: f64,
    relief: f64,
    feed: Feed,
    join: &dyn Fn(f64, f64) -> P2,
) {
    let [p0, q0, p1, q1] = c;
    let pdir = (p1 - p0).signum();
    let qdir = (q1 - q0).signum();
    if p1 == p0 {
        run.error(
            b,
            None,
            format!("{name}: the end point does not move along the peck axis"),
        );
        return;
    }
    if q1 != q0 && shift == 0.0 {
        run.error(
            b,
            None,
            format!("{name}: the end point is off the start's line but the shift amount is 0"),
        );
        return;
    }
    // Count before emitting: both counts are bounded by MAX_MOVES.
    // A length that is a whole number of steps (9.149 mm of 1.307 mm pecks) is that many steps,
    // whatever the last bit of the division says: never one more peck of zero length.
    let count = |len: f64, step: f64| {
        if step > 0.0 {
            (len / step - 1e-9).ceil().max(0.0)
        } else {
            1.0
        }
    };
    let n_grooves = if q1 == q0 {
        1.0
    } else {
        count((q1 - q0).abs(), shift) + 1.0
    };
    let n_pecks = count((p1 - p0).abs(), peck).max(1.0);
    if n_grooves * (2.0 * n_pecks + 3.0) > MAX_MOVES as f64 {
        run.error(b, None, format!("{name} would make more than {MAX_MOVES} moves"));
        return;
    }
    if !super::charge(run, b, (n_grooves * (2.0 * n_pecks + 3.0)) as u64) {
        return;
    }
    // The relief goes back toward the start along the shift axis.
    let rel = if qdir != 0.0 { -qdir * relief.abs() } else { relief };
    let mut here = join(p0, q0);
    // Positions by index (never by repeated addition, which a tiny step could stall).
    let n_grooves = n_grooves as u64;
    let n_pecks = n_pecks as u64;
    for j in 0..n_grooves {
        let q = if j + 1 == n_grooves {
            q1
        } else {
            q0 + qdir * shift * j as f64
        };
        let start = join(p0, q);
        go(run, b, MoveKind::Rapid, here, start, Feed::Rapid);
        here = start;
        for i in 1..=n_pecks {
            let next = if i == n_pecks { p1 } else { p0 + pdir * peck * i as f64 };
            let to = join(next, q);
            go(run, b, MoveKind::Line, here, to, feed);
            here = to;
            if i == n_pecks {
                break;
            }
            if e > 0.0 {
                let back = join(next - pdir * e.min((next - p0).abs()), q);
                go(run, b, MoveKind::Rapid, here, back, Feed::Rapid);
                here = back;
            }
        }
        let bottom = join(p1, q + rel);
        go(run, b, MoveKind::Line, here, bottom, feed);
        let out = join(p0, q + rel);
        go(run, b, MoveKind::Rapid, bottom, out, Feed::Rapid);
        here = out;
    }
    go(run, b, MoveKind::Rapid, here, join(p0, q0), Feed::Rapid);
}
