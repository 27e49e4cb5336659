//! Canned cycles: a cycle block (and the profile blocks it names) turned into ordinary moves,
//! each at the cycle's line, so every pass is checked like any other move.
//!
//! The block executor (`block.rs`, step 9) hands over every motion code it does not run itself;
//! [`run`] answers whether a family here took it. One file per family:
//! `rough.rs`: Fanuc/Haas G70 finishing, G71/G72 stock removal, G73 pattern repeat.
//! `lcnc_thread.rs`: LinuxCNC G33.1 rigid tapping and G76 threading.
//! `lcnc_drill.rs`: LinuxCNC G73, G74, G81–G89 drilling and tapping along Z in G17.

mod common;
mod lcnc_drill;
mod lcnc_thread;
mod rough;

pub(crate) use common::Memory;

use super::block::Words;
use super::flow::Run;
use crate::gcode::Block;

/// Expand the cycle `code` (G number ×10) of block `b`, whose G word is at byte `at`. True when
/// a family here handled it (moves made, or a finding at the cycle's line); false leaves the
/// code to the executor's `unsupported` report.
pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Words, code: u16, at: u32) -> bool {
    let lcnc = run.machine.dialect == crate::machine::Dialect::Linuxcnc;
    match code {
        331 | 760 if lcnc => lcnc_thread::run(run, b, w, code, at),
        730 | 740 | 810..=890 if lcnc => lcnc_drill::run(run, b, w, code, at),
        700..=730 => rough::run(run, b, w, code, at),
        _ => false,
    }
}
