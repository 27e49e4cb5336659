//! The box cycles (Fanuc 0i-TD B-64304EN, "canned cycle", G-code system A; system B names them
//! G77/G78/G79): G90 outer/inner diameter turning, G92 threading, G94 end-face turning.
//!
//! From the start point S (where the tool is when the block runs) to the end point E (X/U, Z/W):
//! - G90: rapid in X to E.x + R, feed to E, feed out in X to S.x, rapid back along Z to S.
//! - G92: as G90 with the feed moves spindle-synchronised (lead F), and the move out in X rapid.
//! - G94: rapid in Z to E.z + R, feed to E, feed out in Z to S.z, rapid back along X to S.
//!
//! R is the taper: the difference (radius for G90/G92, Z for G94) between the cut's start and its
//! end; 0 for a straight cut. X(U), Z(W) and R are modal while the cycle is: a later block with
//! only X (or Z) makes the next box from the same start point with the other values kept.

use super::super::flow::Run;
use super::super::state::Motion;
use super::super::{Feed, MoveKind};
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::letters::Letters;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Turn,
    Thread,
    Face,
}

fn kind(code: u16) -> Kind {
    match code {
        920 | 780 => Kind::Thread,
        940 | 790 => Kind::Face,
        _ => Kind::Turn,
    }
}

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, _at: u32) -> bool {
    if !w.axis_words() {
        // No axis words: no cycle. G90 is then the absolute mode (step 1), G94 the feed per
        // minute (step 2) and G92 S the spindle clamp (step 3), as programs written for G-code
        // system B or C use them; the motion mode in force stays.
        run.check_unused(b, w);
        return true;
    }
    if run.modal.motion != Some(Motion::Cycle(code)) {
        run.cycle = super::Sticky::default();
    }
    run.modal.motion = Some(Motion::Cycle(code));
    one_box(run, b, w, code);
    run.check_unused(b, w);
    true
}

pub(super) fn repeat(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    one_box(run, b, w, code);
}

/// The cycle's end point: the axis words of the block, the modal ones for the axes it does not
/// name. `None` (reported) when an axis was never given.
pub(super) fn end_point(run: &mut Run<'_>, b: &Block, w: &mut Letters, what: &str) -> Option<P2> {
    let gx = w.peek(b'X') || w.peek(b'U');
    let gz = w.peek(b'Z') || w.peek(b'W');
    let t = run.target(b, w)?;
    let x = if gx { Some(t.x) } else { run.cycle.x };
    let z = if gz { Some(t.y) } else { run.cycle.z };
    let (Some(x), Some(z)) = (x, z) else {
        run.error(
            b,
            None,
            format!("{what} needs both end point axes: X (U) and Z (W) in its first block"),
        );
        return None;
    };
    run.cycle.x = Some(x);
    run.cycle.z = Some(z);
    Some(P2::new(x, z))
}

fn one_box(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16) {
    let k = kind(code);
    let name = format!("G{}", code / 10);
    if let Some(r) = w.get(b'R') {
        run.cycle.r = Some(r * run.scale());
    }
    let Some(e) = end_point(run, b, w, &name) else {
        return;
    };
    let r = run.cycle.r.unwrap_or(0.0);
    let s = run.programmed();
    let feed = match k {
        Kind::Thread => {
            let lead = run.modal.feed;
            if lead <= 0.0 {
                run.error(b, None, format!("{name} threading needs its lead (F word)"));
                return;
            }
            Feed::PerRev(lead * run.scale())
        }
        _ => match run.feed(b) {
            Some(f) => f,
            None => return,
        },
    };
    match k {
        Kind::Turn | Kind::Thread => {
            let a = P2::new(e.x + r, s.y);
            let c = P2::new(s.x, e.y);
            go(run, b, MoveKind::Rapid, s, a, Feed::Rapid);
            go(run, b, MoveKind::Line, a, e, feed);
            if k == Kind::Thread {
                go(run, b, MoveKind::Rapid, e, c, Feed::Rapid);
            } else {
                go(run, b, MoveKind::Line, e, c, feed);
            }
            go(run, b, MoveKind::Rapid, c, s, Feed::Rapid);
        }
        Kind::Face => {
            let a = P2::new(s.x, e.y + r);
            let c = P2::new(e.x, s.y);
            go(run, b, MoveKind::Rapid, s, a, Feed::Rapid);
            go(run, b, MoveKind::Line, a, e, feed);
            go(run, b, MoveKind::Line, e, c, feed);
            go(run, b, MoveKind::Rapid, c, s, Feed::Rapid);
        }
    }
}

/// One move of a cycle at the cycle block's line; a move that goes nowhere is left out.
pub(super) fn go(run: &mut Run<'_>, b: &Block, kind: MoveKind, from: P2, to: P2, feed: Feed) {
    if from != to {
        run.push_move(b, kind, from, to, feed);
    }
}
