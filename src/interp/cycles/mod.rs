//! Canned cycles: a cycle block (and its profile, for the stock-removal cycles) becomes ordinary
//! moves, each made through the same `push_move` path as a programmed move and carrying the
//! cycle block's source line (and, for a move that follows a profile block, that block's line in
//! `Move::profile_line`), so the checker sees them like any other move.
//!
//! The order of execution's motion converter (`convert/motion.rs`, step 9) hands every motion
//! code it does not run itself to [`run`]; a later block of a modal cycle (box, drilling and
//! LinuxCNC cycles) comes back through [`repeat`]. Both take the cycle's block as plain data,
//! [`CycleWords`], which the motion converter builds in one place: the cycle's code, its letter
//! words and the program flow written on its line. No cycle sees the block's G or M codes. One file per family: `rough` (Fanuc/Haas G70 finishing, G71/G72
//! stock removal, G73 pattern repeat; `common` holds their profile reading), `box_`
//! (G90/G92/G94, system B G77/G78/G79), `thread` (G76), `groove` (G74/G75), `drill` (G80–G89
//! on the spindle axis), `live_drill` (Fanuc's face and side cycles for live tools);
//! LinuxCNC: `lcnc_thread` (G33.1 rigid tapping, G76), `lcnc_drill` (G73, G74, G81–G89
//! along Z in G17) and `lcnc_rough` (G70, G71, G72 and their .1/.2 forms, o-word profiles).

use super::flow::Run;
use super::letters::Letters;
use crate::gcode::Block;

mod box_;
mod common;
mod drill;
mod groove;
mod lcnc_drill;
pub(crate) mod lcnc_rough;
mod lcnc_thread;
mod live_drill;
mod rough;
mod thread;

pub(crate) use common::{Memory, ProfileComp};

/// A length word (Fanuc P/Q/R of the threading, grooving and drilling cycles) in the least input
/// increment (0.001 mm, 0.0001 in) unless written with a decimal point; in mm.
pub(super) fn least(run: &Run<'_>, w: &mut Letters, letter: u8) -> Option<f64> {
    let point = w.has_point(letter);
    let v = w.get(letter)?;
    let unit = if point {
        1.0
    } else if run.modal.inch {
        0.0001
    } else {
        0.001
    };
    Some(v * unit * run.scale())
}

/// The words of the modal cycle in force (box and drilling cycles), kept between its blocks and
/// cleared when another cycle starts.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Sticky {
    /// Cycle end point X (radius) and Z, spindle frame, once given.
    pub x: Option<f64>,
    pub z: Option<f64>,
    /// Box cycles: the taper R (mm, radius). Drilling: the R plane (spindle-frame z).
    pub r: Option<f64>,
    /// Drilling: peck Q (mm) and dwell P (s).
    pub q: Option<f64>,
    pub p: Option<f64>,
    /// Drilling: the initial level (where the cycle began) along the drilling axis: z, or x for
    /// the side cycles of `live_drill`.
    pub level: f64,
}

/// A cycle's block as the cycles read it, plain data built by the motion converter
/// (`Run::cycle_words`): the letter words come back to the block afterwards, with the ones the
/// cycle used marked (the rest are reported unused, as on any block).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CycleWords {
    /// The cycle's G code (×10).
    pub code: u16,
    /// The offset of its G word (0 when a later block repeats a modal cycle).
    pub at: u32,
    /// The block's letter words.
    pub letters: Letters,
    /// Program flow on the cycle's line: M2 or M30 (the program ends after the cycle).
    pub ends: bool,
    /// The offsets of an M98 or M99 word on the cycle's line (not run: reported).
    pub m98: Option<u32>,
    pub m99: Option<u32>,
}

/// Run the cycle `cw.code` (G number ×10) of block `b`. `true` when the cycle is one this module
/// runs (its findings, if any, are reported); `false` leaves the code to the motion converter's
/// `unsupported` report.
pub(crate) fn run(run: &mut Run<'_>, b: &Block, cw: &mut CycleWords) -> bool {
    let (code, at, w) = (cw.code, cw.at, &mut cw.letters);
    let lcnc = run.machine.dialect == crate::machine::Dialect::Linuxcnc;
    // One dialect's families each: a Fanuc family never sees a LinuxCNC block, nor the reverse.
    let handled = if lcnc {
        match code {
            700..=722 => lcnc_rough::run(run, b, w, code, at),
            _ => run_lcnc(run, b, w, code, at),
        }
    } else {
        match code {
            700..=730 => rough::run(run, b, w, code, at),
            740 | 750 => groove::run(run, b, w, code, at),
            760 => thread::g76(run, b, w, at),
            770 | 780 | 790 | 900 | 920 | 940 => box_::run(run, b, w, code, at),
            c if fanuc_live(run, c) => live_drill::run(run, b, w, code),
            810..=890 => drill::run(run, b, w, code, at),
            _ => false,
        }
    };
    // (Fanuc G70–G73 handle the flow codes of their own lines.)
    if handled && (lcnc || !(700..=730).contains(&code)) {
        flow_codes_on_a_cycle_line(run, b, cw);
    }
    handled
}

/// The machine reads `code` as one of Fanuc's live-tool drilling cycles (`drilling_cycles =
/// "fanuc"`), not as the spindle-axis cycle of `drill.rs`.
fn fanuc_live(run: &Run<'_>, code: u16) -> bool {
    run.machine.drilling_cycles == crate::machine::DrillingCycles::Fanuc && live_drill::runs(code)
}

/// The executor returns after a cycle: program flow written on the cycle's own line is done
/// here (M2/M30 end the program) or reported (M98/M99), never dropped.
fn flow_codes_on_a_cycle_line(run: &mut Run<'_>, b: &Block, cw: &CycleWords) {
    if cw.ends {
        run.stopped = true;
    }
    for (m, at) in [(98u16, cw.m98), (99, cw.m99)] {
        if let Some(at) = at {
            run.unsupported(
                b,
                Some(at),
                format!("M{m} on a cycle's line is not run: write it on a line of its own"),
                true,
            );
        }
    }
}

/// Charge the moves a cycle is about to make to the run's execution budget (`Limits::max_blocks`
/// counts executed blocks and cycle moves alike), so that a program of many long cycles stays
/// bounded. `false` (reported at the cycle's line, the run stops) when the budget is spent.
pub(super) fn charge(run: &mut Run<'_>, b: &Block, moves: u64) -> bool {
    run.executed = run.executed.saturating_add(moves);
    if run.executed > run.limits.max_blocks {
        run.error(
            b,
            None,
            format!(
                "this cycle's {moves} moves exceed the program's work budget ({} blocks and cycle moves): stopped here",
                run.limits.max_blocks
            ),
        );
        run.stopped = true;
        return false;
    }
    true
}

/// A block with axis words and no motion code while the modal cycle `cw.code` is in force: the
/// cycle again with the new words. `false` when no family here runs it (the block then moves as
/// an ordinary one).
pub(crate) fn repeat(run: &mut Run<'_>, b: &Block, cw: &mut CycleWords) -> bool {
    let (code, w) = (cw.code, &mut cw.letters);
    if run.machine.dialect == crate::machine::Dialect::Linuxcnc {
        return run_lcnc(run, b, w, code, 0);
    }
    match code {
        770 | 780 | 790 | 900 | 920 | 940 => box_::repeat(run, b, w, code),
        c if fanuc_live(run, c) => live_drill::repeat(run, b, w, code),
        810..=890 => drill::repeat(run, b, w, code),
        _ => return false,
    }
    true
}

/// The LinuxCNC threading and drilling cycles: on their own block, and run again by a later
/// block with axis words while in force (as rs274ngc does; `at` is then 0).
fn run_lcnc(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    match code {
        331 | 760 => lcnc_thread::run(run, b, w, code, at),
        730 | 740 | 810..=890 => lcnc_drill::run(run, b, w, code, at),
        _ => false,
    }
}

/// What the LinuxCNC cycles' unit tests share: the small LinuxCNC lathe and a run on it.
#[cfg(test)]
mod test_support {
    use crate::interp::Interpretation;
    use crate::machine::Machine;

    pub(super) fn lathe() -> Machine {
        let text = include_str!("../../../machines/linuxcnc-small-lathe.toml");
        crate::machine::from_toml(text, "linuxcnc-small-lathe.toml").unwrap()
    }

    pub(super) fn run(src: &str) -> Interpretation {
        crate::pipeline::interpret(src.as_bytes(), &lathe()).1
    }
}

#[cfg(test)]
mod tests {
    /// `Move::profile_line` (the profile block a cycle's move follows) fits in what was padding:
    /// a program holds one move per block, so a move must not grow.
    #[test]
    fn a_move_stays_128_bytes_with_its_profile_line() {
        assert_eq!(std::mem::size_of::<super::super::Move>(), 128);
    }
}
