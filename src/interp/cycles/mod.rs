//! Canned cycles: a cycle block (and the profile blocks it names) turned into ordinary moves,
//! each at the cycle's line, so every pass is checked like any other move.
//!
//! The block executor (`block.rs`, step 9) hands over every motion code it does not run itself;
//! [`run`] answers whether a family here took it. One file per family:
//! `rough.rs`: Fanuc/Haas G70 finishing, G71/G72 stock removal, G73 pattern repeat.

mod common;
mod rough;

pub(crate) use common::Memory;

use super::block::Words;
use super::flow::Run;
use crate::gcode::Block;

/// Expand the cycle `code` (G number ×10) of block `b`, whose G word is at byte `at`. True when
/// a family here handled it (moves made, or a finding at the cycle's line); false leaves the
/// code to the executor's `unsupported` report.
pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Words, code: u16, at: u32) -> bool {
    match code {
        700..=730 => rough::run(run, b, w, code, at),
        _ => false,
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
