//! A job's operations after the first (`[[operations]]`, docs/job.md "Operations"): where each
//! begins in the run, and the mark the interpreter leaves there for the checker.
//!
//! An operation starts before the words of the block at its line (the first time that block
//! runs), or after the block of the program stop it names has run (the n-th M0/M1 of the run).
//! Operations start in the order the job lists them: one waits for the one before it. At the
//! start the run emits a [`MoveKind::Operation`] move that goes nowhere (the machine stands while
//! the operator turns the part round); the checker replaces the stock there. With the
//! operation's `program_zero_z`, G54's program zero moves there from then on. An operation that
//! never starts is a `program` warning at the end of the run: everything after its place was
//! checked against the part as it stood before.

use super::flow::Run;
use super::{Feed, MoveKind};
use crate::finding::{Finding, Kind, Severity};
use crate::gcode::{Block, BlockRef};
use crate::geom::P2;
use crate::machine::{OpStart, OpTailstock};

/// Where the run stands among the job's operations.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Ops {
    /// The next operation to start (an index into `Machine::operations`).
    next: usize,
    /// Program stops (M0, M1) made so far.
    stops: u32,
    /// G54's program zero as the last operation that moved it left it.
    g54_z: Option<f64>,
}

impl Run<'_> {
    /// Before a block's words: the next operation, if it starts at this block's line.
    #[cold]
    pub(super) fn operation_before(&mut self, b: &BlockRef) {
        let start = self.machine.operations.get(self.ops.next).map(|o| o.start);
        let starts = match start {
            Some(OpStart::Line(l)) => l == b.line,
            Some(OpStart::WorkOffset(n)) => self.selects_work_offset(b, n),
            _ => false,
        };
        if starts {
            self.start_operation(b);
        }
    }

    /// Whether the block has a G word that selects work offset `n` (0: G54): its value read as
    /// the block's words will read it (an expression evaluated, a builder's number through the
    /// machine's `[gcodes]`). A word that cannot be read selects nothing (its error comes with
    /// the words).
    fn selects_work_offset(&self, b: &BlockRef, n: u8) -> bool {
        let want = 540 + 10 * u16::from(n);
        b.words().iter().filter(|w| w.letter == b'G').any(|w| {
            let Ok(Some(v)) = self.word_value(w.value()) else {
                return false;
            };
            let scaled = v * 10.0;
            let code = scaled.round();
            if (scaled - code).abs() > 1e-6 || !(0.0..=9999.0).contains(&code) {
                return false;
            }
            let code = match self.machine.gcodes.get(code as u16) {
                Some(crate::machine::GAlias::As(c)) => c,
                Some(crate::machine::GAlias::Ignore) => return false,
                None => code as u16,
            };
            code == want
        })
    }

    /// A program stop (M0 or M1) in this block: counted, for the operations that start at one.
    pub(super) fn program_stop(&mut self) {
        self.ops.stops = self.ops.stops.saturating_add(1);
    }

    /// After a block has run: the next operation, if it starts at a program stop this block made.
    #[cold]
    pub(super) fn operation_after(&mut self, b: &Block, stops_before: u32) {
        let start = self.machine.operations.get(self.ops.next).map(|o| o.start);
        if let Some(OpStart::Stop(n)) = start {
            if stops_before < n && self.ops.stops >= n {
                self.start_operation(b);
            }
        }
    }

    /// Whether an operation is still to start (false on every run of a job without any).
    #[inline]
    pub(super) fn ops_pending(&self) -> bool {
        self.ops.next < self.machine.operations.len()
    }

    pub(super) fn stops_made(&self) -> u32 {
        self.ops.stops
    }

    /// G54's program zero now: the machine's, or where an operation moved it.
    pub(super) fn g54_zero(&self) -> Option<P2> {
        let z = self.ops.g54_z?;
        let x = self.machine.work_zero(0).map_or(0.0, |p| p.x);
        Some(P2::new(x, z))
    }

    fn start_operation(&mut self, b: &Block) {
        let i = self.ops.next;
        self.ops.next += 1;
        if let Some(z) = self.machine.operations[i].program_zero_z {
            self.ops.g54_z = Some(z);
            if self.coord_system == 0 {
                self.base_origin.y = z;
            }
        }
        match &self.machine.operations[i].tailstock {
            OpTailstock::Out => self.devices.tailstock_advanced = false,
            OpTailstock::At { advance: true, .. } => self.devices.tailstock_advanced = true,
            OpTailstock::At { advance: false, .. } | OpTailstock::AsItStood => {}
        }
        let here = self.programmed();
        self.push_move(b, MoveKind::Operation { op: i as u32 }, here, here, Feed::Rapid);
    }

    /// At the end of the run: each operation that never started, a warning.
    pub(super) fn operations_not_started(&mut self) {
        let ops = &self.machine.operations;
        for (i, op) in ops.iter().enumerate().skip(self.ops.next) {
            let (line, where_) = match op.start {
                OpStart::Line(l) => (l, format!("the block at line {l} never ran")),
                OpStart::Stop(n) => (
                    1,
                    format!("the program made {} program stop(s), not {n}", self.ops.stops),
                ),
                OpStart::WorkOffset(n) => {
                    let name = crate::machine::WORK_OFFSET_NAMES[usize::from(n).min(5)];
                    (1, format!("no block selected {name}"))
                }
            };
            let after = if i > self.ops.next {
                format!(" (it waits for operation {} before it)", self.ops.next + 2)
            } else {
                String::new()
            };
            let msg = format!(
                "{}: operation {} never started: {where_}{after}; the program was checked against the part as it stood before",
                op.origin,
                i + 2
            );
            self.report_finding(Finding::at(Kind::Program, Severity::Warning, line, 0, msg));
        }
    }
}
