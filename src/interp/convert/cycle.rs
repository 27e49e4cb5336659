//! The canned cycles' hand-over, for the motion converter (step 9 of the order of execution): a
//! cycle's block becomes plain data, [`CycleWords`] (built here and nowhere else), the cycle runs
//! (`cycles::run`) with nose-radius compensation standing aside, and what compensation does
//! with the cycle's moves afterwards (a G70 finishing pass is compensated like any path).

use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::comp;
use crate::interp::cycles::{self, CycleWords};
use crate::interp::flow::Run;
use crate::interp::groups::g_name;
use crate::interp::words::Words;
use crate::interp::{Move, MoveKind};
use crate::machine::Dialect;

impl Run<'_> {
    /// A canned cycle with nose-radius compensation standing aside while it expands (its
    /// profile machinery reads and rewrites the moves it made). A G70 finishing pass is then
    /// compensated like any path; roughing and other cycles run on the programmed profile, and
    /// compensation starts again with the next move (docs/comp.md).
    pub(crate) fn run_cycle(&mut self, b: &Block, w: &mut Words, code: u16, at: u32) -> bool {
        let mut cw = cycle_words(w, code, at);
        let ran = self.cycle_with_comp_aside(b, &mut cw);
        w.letters = cw.letters;
        ran
    }

    /// [`Self::run_cycle`] with the cycle's words as the cycles read them.
    fn cycle_with_comp_aside(&mut self, b: &Block, cw: &mut CycleWords) -> bool {
        let (code, at) = (cw.code, cw.at);
        if code == 700 && self.machine.dialect == Dialect::Fanuc {
            return self.fanuc_g70(b, cw);
        }
        let Some(mut comp) = self.comp.take() else {
            return cycles::run(self, b, cw);
        };
        if comp.is_on()
            && self.machine.dialect == Dialect::Linuxcnc
            && matches!(code, 710..=712 | 720..=722 | 810..=890)
        {
            // rs274ngc refuses G71/G72 and the drilling cycles while compensation is on.
            self.comp = Some(comp);
            self.error(
                b,
                Some(at),
                format!(
                    "{} cannot run with nose radius compensation on: cancel it with G40 first",
                    g_name(code)
                ),
            );
            self.modal.motion = None;
            return true;
        }
        // rs274 keeps the moves that wait for their corner across a G70: its first move settles it.
        let lcnc_g70 = code == 700 && self.machine.dialect == Dialect::Linuxcnc && comp.offsets();
        if !lcnc_g70 {
            comp.flush(&mut self.moves);
        }
        let m0 = self.moves.len();
        if lcnc_g70 {
            self.cycles.lcnc_g70_comp = Some(Default::default());
        }
        let ran = cycles::run(self, b, cw);
        // Where rs274 read the profile, as an index into the cycle's moves.
        let read = self
            .cycles
            .lcnc_g70_comp
            .take()
            .and_then(|c| c.read)
            .and_then(|(i, p)| i.checked_sub(m0).map(|k| (k, p)));
        if !comp.is_on() && ran && m0 < self.moves.len() {
            // After G40 the cycle's first move starts where compensation left the tool.
            if let Some(p) = comp.take_resume() {
                let first = &mut self.moves[m0];
                if matches!(first.kind, MoveKind::Rapid | MoveKind::Line) {
                    first.start = p;
                }
            }
        }
        if comp.is_on() && ran && m0 < self.moves.len() {
            if code == 700 {
                self.replay_through_comp(b, &mut comp, m0, read, &[]);
            } else {
                if let Some(p) = comp.last_out() {
                    let first = &mut self.moves[m0];
                    if matches!(first.kind, MoveKind::Rapid | MoveKind::Line) {
                        first.start = p;
                    }
                }
                comp.restart();
            }
        }
        self.comp = Some(comp);
        ran
    }

    /// Fanuc G70: the profile blocks and the way back to the start point run through
    /// compensation as plain blocks would: what waits for its corner (a start-up block just
    /// before the G70) is settled by the cycle's first move, and the profile's own G41/G42/G40
    /// act before the moves of their blocks. Compensation is then as the profile left it.
    fn fanuc_g70(&mut self, b: &Block, cw: &mut CycleWords) -> bool {
        let comp = self.comp.take();
        let m0 = self.moves.len();
        let ran = cycles::run(self, b, cw);
        let words = std::mem::take(&mut self.cycles.g70_comp);
        let mut comp = match comp {
            Some(c) => c,
            None if words.is_empty() => return ran,
            None => Box::default(),
        };
        self.replay_through_comp(b, &mut comp, m0, None, &words);
        self.comp = Some(comp);
        ran
    }

    /// Hand the moves a cycle made from `m0` on to compensation, with rs274's reading of the
    /// profile (`read`: the index of the move it comes before, and the profile's last point)
    /// and the profile's G41/G42/G40 (`words`, at absolute move indices) taken where they fall.
    /// An error of the control is one finding at the cycle's line; compensation stops there.
    fn replay_through_comp(
        &mut self,
        b: &Block,
        comp: &mut comp::Comp,
        m0: usize,
        read: Option<(usize, P2)>,
        words: &[cycles::ProfileComp],
    ) {
        let made: Vec<Move> = self.moves.drain(m0..).collect();
        let mut failed = None;
        let mut words = words.iter().peekable();
        let word = |comp: &mut comp::Comp, w: comp::Word, out: &mut Vec<Move>, failed: &mut Option<String>| {
            if failed.is_none() {
                *failed = comp.word(w, out).err();
            }
        };
        for (k, m) in made.into_iter().enumerate() {
            while let Some(pw) = words.next_if(|pw| pw.at <= m0 + k) {
                word(comp, pw.word, &mut self.moves, &mut failed);
            }
            if let Some((_, p)) = read.filter(|&(i, _)| i == k) {
                comp.profile_read(p);
            }
            if failed.is_none() {
                if let Err(msg) = comp.take(m, &mut self.moves) {
                    comp.abandon(&mut self.moves);
                    failed = Some(msg);
                    let _ = comp.take(m, &mut self.moves);
                }
            } else {
                let _ = comp.take(m, &mut self.moves);
            }
        }
        for pw in words {
            word(comp, pw.word, &mut self.moves, &mut failed);
        }
        if let Some(msg) = failed {
            self.error(
                b,
                None,
                format!("{msg}; nose radius compensation stops here and the rest is checked as programmed"),
            );
        }
    }
}

/// The plain data a canned cycle reads of its block ([`CycleWords`]), built here and nowhere
/// else: the cycle's code and word, the block's letter words, and the program flow on its line.
pub(crate) fn cycle_words(w: &Words, code: u16, at: u32) -> CycleWords {
    CycleWords {
        code,
        at,
        letters: w.letters,
        ends: w.has_m(2).is_some() || w.has_m(30).is_some(),
        m98: w.has_m(98),
        m99: w.has_m(99),
    }
}
