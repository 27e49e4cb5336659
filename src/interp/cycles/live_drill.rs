//! Fanuc's drilling cycles for live tools, on a machine with `drilling_cycles = "fanuc"`
//! (Fanuc Series 0i-TD operator's manual B-64304EN and the 16i/18i-TB manuals, "Canned cycle for
//! drilling"): the face cycles drill along Z, the side cycles along X, each hole at the C angle
//! (and, on a machine with one, the Y) of its block.
//!
//! | face | side | cycle |
//! |------|------|-------|
//! | G83  | G87  | drilling; with Q, pecking |
//! | G84  | G88  | tapping: in at F, the tool reverses, out at F |
//! | G85  | G89  | boring: in at F, out at F |
//!
//! Words: `G83 X(U) C(H) Z(W) R Q P F K` and `G87 Z(W) C(H) X(U) R Q P F K`.
//! - The hole's position: X and C on the face, Z and C on the side (Y too on a machine with a
//!   Y axis), reached at rapid at the initial level (where the drilling axis stood when the cycle
//!   began).
//! - The bottom of the hole: Z (face) or X (side); absolute, or W/U from the initial level.
//! - R: the distance from the initial level to the R point, signed along the drilling axis
//!   (`G83 Z-40. R-5.` from Z5 starts feeding at Z0); along X a radius. No R: the R point is
//!   the initial level.
//! - Q: the peck (least input increment unless written with a point); each peck is followed by
//!   a rapid out to the R point and a rapid back to 1 mm above the last depth (the normal peck,
//!   parameter 5101#2 RTR = 1; the high-speed peck backs off only that 1 mm: its moves lie on
//!   the same stretch of the hole's line, already drilled).
//! - P: the dwell at the bottom (ms; s with a decimal point, as G4 reads it).
//! - K: the number of repeats. K0 keeps the cycle's words without drilling; K above 1 (holes
//!   repeated at an incremental step) is reported as `unsupported`.
//! - The return: to the initial level in G-code system A (where G98/G99 are the feed modes); G98
//!   initial, G99 R point in system B.
//!
//! R, Q, P and the bottom stay in force until G80 or another group-01 code: a later block with
//! only C (or X, Z) drills the next hole. The tapping cycles reverse the live tool (nothing
//! latheguard models changes: the tool still turns) and, for a turret tap on the spindle axis
//! with the spindle turning, the spindle. G81, G82 and G86 keep the spindle-axis meaning of
//! `drill.rs` (they are not Fanuc lathe drilling cycles).

use super::super::flow::Run;
use super::super::state::Motion;
use super::super::{Feed, MoveKind};
use super::box_::go;
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::letters::Letters;
use crate::machine::GcodeSystem;

/// The cycles this module runs (×10): the face and side drilling, tapping and boring cycles.
pub(super) fn runs(code: u16) -> bool {
    matches!(code, 830 | 840 | 850 | 870 | 880 | 890)
}

/// The side cycles drill along X.
fn side(code: u16) -> bool {
    matches!(code, 870 | 880 | 890)
}

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) -> bool {
    // Another cycle along the same axis keeps the words in force (R, Q, P, the bottom, the
    // initial level); any other starts afresh.
    let same_axis = matches!(run.modal.motion, Some(Motion::Cycle(c)) if runs(c) && side(c) == side(code));
    if !same_axis {
        run.cycle = super::Sticky {
            level: level(run, code),
            ..Default::default()
        };
    }
    run.modal.motion = Some(Motion::Cycle(code));
    hole(run, b, w, code);
    run.check_unused(b, w);
    true
}

pub(super) fn repeat(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    hole(run, b, w, code);
}

/// Where the tool stands along the drilling axis (spindle frame: x a radius, or z).
fn level(run: &Run<'_>, code: u16) -> f64 {
    let p = run.programmed();
    if side(code) {
        p.x
    } else {
        p.y
    }
}

/// A point of the hole's line: `along` on the drilling axis, `at` the position on the other.
fn point(code: u16, along: f64, at: f64) -> P2 {
    if side(code) {
        P2::new(along, at)
    } else {
        P2::new(at, along)
    }
}

fn hole(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    let name = format!("G{}", code / 10);
    let side = side(code);
    let s_ = run.scale();
    // Whether the block names the bottom (the drilling axis's word).
    let bottom_named = if side {
        w.peek(b'X') || w.peek(b'U')
    } else {
        w.peek(b'Z') || w.peek(b'W')
    };
    let r_word = w.get(b'R');
    let q_word = super::least(run, w, b'Q');
    let p_word = super::drill::dwell_word(w);
    let k_word = w.get(b'K');
    let Some(t) = run.target(b, w) else { return };
    let Some(extra) = run.extra_end(b, w, false) else {
        return;
    };
    if let Some(r) = r_word {
        run.cycle.r = Some(run.cycle.level + r * s_);
    }
    run.cycle.q = q_word.or(run.cycle.q);
    run.cycle.p = p_word.or(run.cycle.p);
    let (at, named_bottom) = if side { (t.y, t.x) } else { (t.x, t.y) };
    if bottom_named {
        if side {
            run.cycle.x = Some(named_bottom);
        } else {
            run.cycle.z = Some(named_bottom);
        }
    }
    let bottom = if side { run.cycle.x } else { run.cycle.z };
    let Some(bottom) = bottom else {
        let axis = if side { "X (or U)" } else { "Z (or W)" };
        run.error(b, None, format!("{name} needs {axis}, the bottom of the hole"));
        return;
    };
    match k_word {
        Some(0.0) => return, // the words are stored, no hole drilled
        Some(k) if k != 1.0 => {
            run.unsupported(
                b,
                w.at(b'K'),
                format!("{name} K{k}: repeated holes (K above 1) are not modelled: write each hole"),
                true,
            );
            return;
        }
        _ => {}
    }
    let Some(feed) = run.feed(b) else { return };
    let level0 = run.cycle.level;
    let r = run.cycle.r.unwrap_or(level0);
    let dir = (bottom - r).signum();
    if dir == 0.0 {
        run.error(b, None, format!("{name}: the bottom of the hole is at the R point"));
        return;
    }
    let pecks = match (code, run.cycle.q) {
        (830 | 870, Some(q)) if q > 0.0 => {
            let n = ((bottom - r).abs() / q - 1e-9).ceil().max(1.0);
            if n > super::drill::MAX_PECKS as f64 {
                run.error(
                    b,
                    None,
                    format!("{name} would make more than {} pecks", super::drill::MAX_PECKS),
                );
                return;
            }
            n as u64
        }
        (830 | 870, Some(q)) if q < 0.0 => {
            run.error(b, None, format!("{name} Q (peck) must not be negative"));
            return;
        }
        _ => 1,
    };
    let dwell = run.cycle.p.unwrap_or(0.0);
    if dwell < 0.0 {
        run.error(b, None, format!("negative dwell {dwell} s"));
        return;
    }
    let sys_b = run.machine.gcode_system == GcodeSystem::B;
    let ret = if sys_b && run.cycles.return_r { r } else { level0 };
    if !super::charge(run, b, pecks * 3 + 6) {
        return;
    }

    // To the hole's position at the initial level (the C, Y of the block turn with it).
    let start = run.programmed();
    let over = point(code, level(run, code), at);
    super::drill::position(run, b, start, over, extra);
    let rp = point(code, r, at);
    go(run, b, MoveKind::Rapid, over, rp, Feed::Rapid);
    let q = run.cycle.q.unwrap_or(0.0);
    let here = super::drill::feed_in(run, b, &|level| point(code, level, at), (r, bottom), q, pecks, feed);
    if dwell > 0.0 {
        run.push_move(b, MoveKind::Dwell { seconds: dwell }, here, here, Feed::Rapid);
    }
    match code {
        840 | 880 => {
            // A live tap reverses the live tool (still turning); a turret tap on the spindle
            // axis, the spindle.
            let live = run.tm.as_deref().is_some_and(|t| t.c_mode || t.live_rpm > 0.0);
            let before = run.spindle_dir;
            if !live {
                run.spindle_dir = super::drill::reversed(before);
            }
            go(run, b, MoveKind::Line, here, rp, feed);
            run.spindle_dir = before;
        }
        850 | 890 => go(run, b, MoveKind::Line, here, rp, feed),
        _ => go(run, b, MoveKind::Rapid, here, rp, Feed::Rapid),
    }
    go(run, b, MoveKind::Rapid, rp, point(code, ret, at), Feed::Rapid);
}
