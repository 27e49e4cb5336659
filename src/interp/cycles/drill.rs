//! Drilling cycles on the spindle axis, as Haas lathes run them (Haas lathe operator's manual,
//! G81–G89, G80) and as Fanuc lathes run the same codes with a turret drill: a stationary drill,
//! boring bar or tap on the turret, the part turning.
//!
//! Words: Z (or W) the bottom of the hole, R the R plane (default the initial level), read as
//! the machine's `drill_r` says: Haas's absolute program Z of the R plane, or Fanuc's distance
//! from the initial level to the R point, signed along Z (Fanuc 0i-TD, "Canned cycle for
//! drilling": `G83 Z-20. R-2.` from Z3 feeds from Z1); Q the peck (G83; least input increment
//! unless written with a decimal point), P the dwell at the bottom (G82, G88, G89; ms, or s with
//! a decimal point, as G4 reads it), F the feed (G84: the pitch), X (or U) the hole's X — 0 on a
//! 2-axis lathe (off the axis a stationary drill meets a turning part); on a machine with a C
//! axis, C (and Y) index the spindle for a live tool's hole, and with the spindle in C-axis mode
//! X may be off the axis (Haas: axial live drilling with these same cycles).
//!
//! Passes: rapid to the hole's X at the initial level, rapid to R, then
//! - G81 feed to Z; G82 feed to Z, dwell; G83 pecks of Q, each followed by a rapid out to R and a
//!   rapid back down to 1 mm above the last depth (the clearance Fanuc parameter 5114 and Haas
//!   Setting 22 set; 1 mm here);
//! - G84 feed to Z, spindle reversed, feed out to R, spindle direction restored;
//! - G85 feed in, feed out to R; G86 feed in, spindle stop, rapid out to R, spindle on again;
//! - G87 feed in, spindle stop (G88: dwell, then stop), a manual retract — modelled as a rapid out
//!   to R with the spindle stopped, and reported as `unsupported` (a warning);
//! - G89 feed in, dwell, feed out to R;
//!
//! then the rapid to the return level: the initial level in G-code system A (where G98/G99 are
//! the feed modes), G98 initial / G99 R level in system B. Modal until G80 or a group-01 code: a
//! later block with Z (or X0) drills the next hole with the same R, Q, P.

use super::super::flow::Run;
use super::super::state::Motion;
use super::super::{ExtraAxes, Feed, MoveKind, SpindleDir};
use super::box_::go;
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::letters::Letters;
use crate::machine::{DrillR, GcodeSystem};

/// The clearance above the last depth where a G83 peck's rapid back down stops, mm.
pub(crate) const PECK_CLEARANCE_MM: f64 = 1.0;
/// Most pecks of one hole; more is a `program` finding.
pub(crate) const MAX_PECKS: u64 = 10_000;

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    if code % 10 != 0 {
        return false;
    }
    if run.modal.motion != Some(Motion::Cycle(code)) {
        let keep = run.cycle;
        run.cycle = super::Sticky::default();
        run.cycle.level = run.programmed().y;
        // A cycle following another drilling cycle keeps its words (R, Q, P) until G80.
        if matches!(run.modal.motion, Some(Motion::Cycle(c)) if (810..=890).contains(&c)) {
            run.cycle.r = keep.r;
            run.cycle.q = keep.q;
            run.cycle.p = keep.p;
            run.cycle.z = keep.z;
            run.cycle.level = keep.level;
        }
    }
    run.modal.motion = Some(Motion::Cycle(code));
    let _ = at;
    hole(run, b, w, code);
    run.check_unused(b, w);
    true
}

pub(super) fn repeat(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    hole(run, b, w, code);
}

fn hole(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    let s_ = run.scale();
    let gz = w.peek(b'Z') || w.peek(b'W');
    // A machine with a C axis indexes the spindle for a live tool's holes (Haas: C, and Y, on
    // the drilling block); on one without, C has no meaning here.
    let c_axis = run.tm.as_deref().is_some_and(|t| t.axes[1].is_some());
    if let (Some(at), false) = (w.at(b'C'), c_axis) {
        consume_all(w);
        run.unsupported(
            b,
            Some(at),
            "a drilling cycle with C (a spindle-indexed hole) needs a machine with a C axis and live tools (docs/turn-mill.md)".into(),
            true,
        );
        return;
    }
    if code == 830 && (w.peek(b'I') || w.peek(b'J') || w.peek(b'K')) {
        let at = w.at(b'I').or(w.at(b'J')).or(w.at(b'K'));
        consume_all(w);
        run.unsupported(
            b,
            at,
            "G83 with I/J/K (Haas pecks shrinking from I by J down to K) is not modelled: give a constant Q".into(),
            true,
        );
        return;
    }
    // Words of the cycle (read before any early return, so none is reported unused).
    let r_word = w.get(b'R');
    let q_word = super::least(run, w, b'Q');
    let p_word = dwell_word(w);
    let Some(t) = run.target(b, w) else { return };
    let Some(extra) = run.extra_end(b, w, false) else {
        return;
    };
    if let Some(r) = r_word {
        run.cycle.r = Some(match run.machine.drill_r() {
            // Haas: the R plane's program Z.
            DrillR::Absolute => run.origin().y + r * s_,
            // Fanuc: the distance from the initial level to the R point, signed along Z.
            DrillR::Incremental => run.cycle.level + r * s_,
        });
    }
    run.cycle.q = q_word.or(run.cycle.q);
    run.cycle.p = p_word.or(run.cycle.p);
    let z = if gz { Some(t.y) } else { run.cycle.z };
    let Some(z) = z else {
        if w.peek(b'X') || w.peek(b'U') || gz {
            run.error(
                b,
                None,
                format!("G{} needs Z (or W), the bottom of the hole", code / 10),
            );
        }
        return;
    };
    run.cycle.z = Some(z);
    let x = t.x;
    // Off the axis a hole needs the spindle positioned (C-axis mode) and a live tool: a
    // stationary drill would meet a turning part.
    let positioned = run.tm.as_deref().is_some_and(|t| t.c_mode);
    if x.abs() > 1e-6 && !positioned {
        let why = if c_axis {
            "put the spindle in C-axis mode first (the machine's c_axis_on code)"
        } else {
            "drilling there needs a live tool, which this lathe has not (X must be 0)"
        };
        run.error(
            b,
            None,
            format!(
                "G{}: a hole at X{} is off the spindle axis; {why}",
                code / 10,
                short(run.frame().to_program(P2::new(x, t.y)).0)
            ),
        );
        return;
    }
    let Some(feed) = run.feed(b) else { return };
    let start = run.programmed();
    let z0 = start.y;
    let r = run.cycle.r.unwrap_or(z0);
    let dir = (z - r).signum();
    if dir == 0.0 {
        run.error(b, None, format!("G{}: the bottom Z is at the R plane", code / 10));
        return;
    }
    let pecks = match (code, run.cycle.q) {
        (830, Some(q)) if q > 0.0 => {
            // A whole number of pecks is that many, whatever the division's last bit says.
            let n = ((z - r).abs() / q - 1e-9).ceil().max(1.0);
            if n > MAX_PECKS as f64 {
                run.error(b, None, format!("G83 would make more than {MAX_PECKS} pecks"));
                return;
            }
            n as u64
        }
        (830, Some(q)) if q < 0.0 => {
            run.error(b, None, "G83 Q (peck) must not be negative".into());
            return;
        }
        _ => 1,
    };
    let dwell = run.cycle.p.unwrap_or(0.0);
    if matches!(code, 820 | 880 | 890) && dwell < 0.0 {
        run.error(b, None, format!("negative dwell {dwell} s"));
        return;
    }
    let sys_b = run.machine.gcode_system == GcodeSystem::B;
    let ret = if sys_b && run.cycles.return_r {
        r
    } else {
        run.cycle.level
    };

    if !super::charge(run, b, pecks * 3 + 6) {
        return;
    }
    let at_x = P2::new(x, z0);
    position(run, b, start, at_x, extra);
    let rp = P2::new(x, r);
    go(run, b, MoveKind::Rapid, at_x, rp, Feed::Rapid);
    let q = run.cycle.q.unwrap_or(0.0);
    let here = feed_in(run, b, &|level| P2::new(x, level), (r, z), q, pecks, feed);
    if matches!(code, 820 | 880 | 890) && dwell > 0.0 {
        run.push_move(b, MoveKind::Dwell { seconds: dwell }, here, here, Feed::Rapid);
    }
    let dir_before = run.spindle_dir;
    match code {
        840 => {
            run.spindle_dir = reversed(dir_before);
            go(run, b, MoveKind::Line, here, rp, feed);
            run.spindle_dir = dir_before;
        }
        850 | 890 => go(run, b, MoveKind::Line, here, rp, feed),
        860 | 870 | 880 => {
            if code != 860 {
                run.unsupported(
                    b,
                    None,
                    format!(
                        "G{}: the manual retract is modelled as a rapid out to the R plane with the spindle stopped",
                        code / 10
                    ),
                    false,
                );
            }
            run.spindle_dir = SpindleDir::Off;
            go(run, b, MoveKind::Rapid, here, rp, Feed::Rapid);
            run.spindle_dir = dir_before;
        }
        _ => go(run, b, MoveKind::Rapid, here, rp, Feed::Rapid),
    }
    go(run, b, MoveKind::Rapid, rp, P2::new(x, ret), Feed::Rapid);
}

/// The feed from the R point to the bottom of a hole along its line (`point(level)`): `pecks` of
/// `q` (the last one to the bottom), each but the last followed by a rapid out to the R point and
/// a rapid back to [`PECK_CLEARANCE_MM`] above the depth reached; one feed when `pecks` is 1.
/// Returns the bottom. Shared by the spindle-axis and the live-tool cycles.
pub(super) fn feed_in(
    run: &mut Run<'_>,
    b: &Block,
    point: &dyn Fn(f64) -> P2,
    (r, bottom): (f64, f64),
    q: f64,
    pecks: u64,
    feed: Feed,
) -> P2 {
    let dir = (bottom - r).signum();
    let rp = point(r);
    let mut here = rp;
    for i in 1..=pecks {
        let depth = if i == pecks { bottom } else { r + dir * q * i as f64 };
        let to = point(depth);
        go(run, b, MoveKind::Line, here, to, feed);
        here = to;
        if i == pecks {
            break;
        }
        go(run, b, MoveKind::Rapid, to, rp, Feed::Rapid);
        let back = depth - dir * PECK_CLEARANCE_MM;
        let down = point(if (back - r) * dir > 0.0 { back } else { r });
        go(run, b, MoveKind::Rapid, rp, down, Feed::Rapid);
        here = down;
    }
    here
}

/// The rapid to a hole's position, with the extra axes (C, Y) of the block: made even when only
/// they move, so that the spindle turns to the hole's angle before the tool goes in.
pub(super) fn position(run: &mut Run<'_>, b: &Block, from: P2, to: P2, extra: Option<ExtraAxes>) {
    let turns = match (extra, run.tm.as_deref()) {
        (Some(e), Some(tm)) => e != tm.pos,
        _ => false,
    };
    if let Some(e) = extra {
        run.set_pending(e, None);
    }
    if turns || from != to {
        run.push_move(b, MoveKind::Rapid, from, to, Feed::Rapid);
    }
}

/// A drilling cycle's P word, the dwell at the bottom in seconds: ms, or s when written with a
/// decimal point (as G4 reads it).
pub(super) fn dwell_word(w: &mut Letters) -> Option<f64> {
    let point = w.has_point(b'P');
    let v = w.get(b'P')?;
    Some(if point { v } else { v / 1000.0 })
}

/// The other direction of a turning spindle (a tap backing out).
pub(super) fn reversed(d: SpindleDir) -> SpindleDir {
    match d {
        SpindleDir::Cw => SpindleDir::Ccw,
        SpindleDir::Ccw => SpindleDir::Cw,
        SpindleDir::Off => SpindleDir::Off,
    }
}

/// A block whose cycle is reported as a whole: its words are accounted for by that finding.
fn consume_all(w: &mut Letters) {
    for l in b'A'..=b'Z' {
        w.get(l);
    }
}

/// A coordinate as a program would write it: at most four decimals, no trailing zeros.
fn short(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
