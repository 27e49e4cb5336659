//! Step 10 of the order of execution: program flow — Fanuc's subprogram call and return
//! (M98/M99, run by `flow.rs`), the words no code of the block used (a `program` finding each),
//! and the program's end (M2/M30, noted in step 5), which takes effect after the block's motion.

use crate::gcode::Block;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::Words;

impl Run<'_> {
    /// Step 10: M98/M99 (M group 10), the unused words, the program's
    /// end. Touches the call stack and `stopped`. Order: LinuxCNC's "stop" (M2, M30) comes
    /// last, after motion; Fanuc's subprogram call and return end the block the same way.
    pub(crate) fn convert_flow(&mut self, b: &Block, w: &mut Words, cx: &Cx) {
        if w.m(98) {
            let p = w.get(b'P');
            let l = w.get(b'L');
            self.check_unused(b, w);
            self.m98(b, p, l, w.has_m(98));
            return;
        }
        if w.m(99) {
            let p = w.peek(b'P').then(|| w.at(b'P'));
            let p = p.map(|at| (w.get(b'P').unwrap_or(0.0), at));
            self.check_unused(b, w);
            self.m99(b, p);
            return;
        }
        self.check_unused(b, w);
        if cx.ends {
            self.stopped = true;
        }
    }
}
