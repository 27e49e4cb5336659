//! One block: its words read, its assignments made, then executed in the order of execution
//! (`order.rs`, the spine: one converter per modal group, `convert/`), or, for the commonest
//! block, by the plain-block fast path; and the making of a move (`push_move`: the state it
//! carries, the range check, nose-radius compensation, the extra axes' side table).

use super::flow::Run;
use super::letters::bit;
use super::state::Motion;
use super::words::{gb, Words};
use super::{Feed, Move, MoveKind, MoveState, ProgFrame, SpindleDir, MAX_COORD};
use crate::finding::{Finding, Kind, Severity};
use crate::gcode::{Block, BlockRef};
use crate::geom::P2;

/// The motion codes of a plain block (see [`Run::plain_block`]).
const PLAIN_MOTION_CODES: u128 = gb(0) | gb(10) | gb(20) | gb(30);
/// The letters of a plain block.
const PLAIN_LETTERS: u32 = bit(b'F') | bit(b'I') | bit(b'K') | bit(b'R') | bit(b'X') | bit(b'Z');

/// A point within ±[`MAX_COORD`] mm on both axes (false for NaN).
#[inline]
pub(crate) fn in_range(p: P2) -> bool {
    p.x.abs() <= MAX_COORD && p.y.abs() <= MAX_COORD
}

impl Run<'_> {
    pub(crate) fn origin(&self) -> P2 {
        self.base_origin + self.shift
    }

    pub(crate) fn frame(&self) -> ProgFrame {
        ProgFrame {
            origin: self.origin(),
            scale: self.scale(),
            diameter: self.modal.diameter,
        }
    }

    /// The programmed point (tool tip), spindle frame.
    pub(crate) fn programmed(&self) -> P2 {
        self.reference + self.tip()
    }

    /// The programmed point in program coordinates (X as the program writes it).
    pub(crate) fn program_position(&self) -> (f64, f64) {
        self.frame().to_program(self.programmed())
    }

    pub(super) fn push_move(&mut self, b: &Block, kind: MoveKind, start: P2, end: P2, feed: Feed) {
        let center = match kind {
            MoveKind::Arc { center, .. } => center,
            _ => start,
        };
        if (!(in_range(start) && in_range(end) && in_range(center)) || self.out_of_range.is_some())
            && self.move_out_of_range(b, start, end, center)
        {
            return;
        }
        if matches!(kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }) {
            self.reference = end - self.tip();
        }
        let state = MoveState {
            spindle: self.spindle(),
            frame: self.frame(),
            tailstock_advanced: self.devices.tailstock_advanced,
            tool_unknown: self.devices.tool_unknown,
            sub_chuck_closed: self.devices.sub_chuck_closed,
        };
        if self.states.last() != Some(&state) {
            self.states.push(state);
        }
        let m = Move {
            kind,
            line: b.line,
            n: b.n(),
            profile_line: 0,
            start,
            end,
            tip: self.tip(),
            station: self.station,
            feed,
            state: (self.states.len() - 1) as u32,
        };
        if self.modal.spindle_css && feed != Feed::Rapid && self.spindle_dir != SpindleDir::Off {
            self.css_above_max_rpm(b, &m, &state.spindle);
        }
        if self.tm.is_none() {
            match self.comp.as_deref_mut() {
                Some(c) if c.engaged() => self.compensate(b, m),
                _ => self.moves.push(m),
            }
            return;
        }
        let first = self.moves.len();
        match self.comp.as_deref_mut() {
            Some(c) if c.engaged() => self.compensate(b, m),
            _ => self.moves.push(m),
        }
        let count = self.moves.len().saturating_sub(first);
        self.record_extra(kind, first, count);
    }

    /// Whether a move of block `b` is refused: it goes out of range (a word of a cycle, a
    /// computed point), or an earlier move of the block did. The first is reported at the block;
    /// no later move of the block is made (a cycle stops at its first such move).
    #[cold]
    fn move_out_of_range(&mut self, b: &Block, start: P2, end: P2, center: P2) -> bool {
        let key = b as *const Block as usize;
        if self.out_of_range == Some(key) {
            return true;
        }
        if in_range(start) && in_range(end) && in_range(center) {
            return false;
        }
        self.out_of_range = Some(key);
        self.error(
            b,
            None,
            format!(
                "a move of this block goes out of any range (a coordinate beyond ±{MAX_COORD:e} mm, or not a number): \
                 it is not made, nor the rest of the block's moves"
            ),
        );
        true
    }

    /// A move through nose-radius compensation (src/interp/comp.rs). An error of the control
    /// is a `program` finding at the move's line; compensation then stops and the move is made
    /// as programmed from where the tool is.
    #[cold]
    fn compensate(&mut self, b: &Block, m: Move) {
        let Some(c) = self.comp.as_deref_mut() else {
            self.moves.push(m);
            return;
        };
        if let Err(msg) = c.take(m, &mut self.moves) {
            c.abandon(&mut self.moves);
            let _ = c.take(m, &mut self.moves);
            self.error(
                b,
                None,
                format!("{msg}; nose radius compensation stops here and the rest is checked as programmed"),
            );
        }
    }

    /// Let the moves that nose-radius compensation still holds out (the program ended).
    pub(super) fn comp_flush(&mut self) {
        if let Some(c) = self.comp.as_deref_mut() {
            c.flush(&mut self.moves);
        }
    }

    /// A `program` warning, unless the same one was just reported for this line (a line in a
    /// loop would repeat it on every pass).
    pub(crate) fn warn_once(&mut self, b: &Block, col_offset: Option<u32>, msg: String) {
        let col = col_offset.map_or(0, |o| crate::source::col_of(self.src, o));
        let repeat = self
            .findings
            .iter()
            .rev()
            .take(8)
            .any(|f| f.line == b.line && f.col == col && f.message == msg);
        // A warning does not refuse the move, so it is kept apart from `report` (and its
        // refusal count), under the same cap.
        if !repeat && self.findings.len() < crate::finding::MAX_FINDINGS {
            self.findings
                .push(Finding::at(Kind::Program, Severity::Warning, b.line, col, msg).with_n(b.n()));
        }
    }

    /// Execute one block that is not an o-word.
    pub(crate) fn execute(&mut self, b: &BlockRef) {
        let ops = self.ops_pending();
        if ops {
            self.operation_before(b);
        }
        if !self.machine.tool_changes.is_empty() {
            self.manual_tool_change(b);
        }
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.pending = None;
        }
        // The group-01 motion in force as this block begins (set by any path, the plain-block
        // one too): what a Fanuc G80 gives back.
        if let Some(m) = self.modal.motion.filter(|m| !m.is_drilling()) {
            self.modal.group1 = Some(m);
        }
        // One word table serves every block (see `Words::clear`).
        let mut w = self.words.take().unwrap_or_else(|| Box::new(Words::new()));
        w.clear();
        let stops = self.stops_made();
        self.execute_words(b, &mut w);
        self.words = Some(w);
        if ops && self.stops_made() != stops {
            self.operation_after(b, stops);
        }
    }

    /// The words of the block: read, assigned, then executed in the order of execution
    /// ([`Run::execute_in_order`]), unless the block is a plain one.
    fn execute_words(&mut self, b: &BlockRef, w: &mut Words) {
        if !self.read_words(b, w) {
            return;
        }
        if !self.assign_parameters(b) {
            return;
        }
        if w.is_empty() {
            return;
        }
        let plain_codes = w.ng == 0 || (w.ng == 1 && w.any_g(PLAIN_MOTION_CODES));
        if self.plain_blocks_fast && plain_codes && w.nm == 0 && w.has & !PLAIN_LETTERS == 0 && b.assigns().is_empty() {
            self.plain_block(b, w);
            return;
        }
        self.execute_in_order(b, w);
    }

    /// Parameter assignments: evaluate every right side first, then assign. `false` when one
    /// could not be evaluated or assigned (reported): the block is not run.
    fn assign_parameters(&mut self, b: &BlockRef) -> bool {
        let assigns = b.assigns();
        if assigns.is_empty() {
            return true;
        }
        let mut vals = Vec::with_capacity(assigns.len());
        for a in assigns {
            match self.eval_assign(a.value) {
                Ok(v) => vals.push((a.target, v, a.span.start)),
                Err(m) => {
                    self.eval_error(b, Some(a.span.start), m);
                    return false;
                }
            }
        }
        for (t, v, at) in vals {
            if let Err(m) = self.assign(t, v) {
                self.eval_error(b, Some(at), m);
                return false;
            }
        }
        true
    }

    /// A block of the commonest kind: at most one of G0–G3, and only X, Z, F, I, K, R words (no M
    /// code, no assignment). What [`Run::execute_in_order`] would do with it, without the steps that
    /// have nothing to do for it (tests run both ways and compare).
    fn plain_block(&mut self, b: &Block, w: &mut Words) {
        self.feed_word(b, w);
        if w.ng == 1 {
            self.modal.motion = Some(match w.g[0].0 {
                0 => Motion::Rapid,
                10 => Motion::Line,
                20 => Motion::ArcCw,
                _ => Motion::ArcCcw,
            });
        }
        if w.axis_words() {
            let before = self.reports;
            self.motion(b, w, false, false);
            if self.reports > before {
                w.used = w.has;
            }
        }
        self.check_unused(b, w);
    }
}
