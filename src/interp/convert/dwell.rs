//! Step 6 of the order of execution: the dwell G4 (group 0). On Fanuc lathes the X, U or P word
//! of a G4 block is the dwell time and never an axis word: such a block does not move (a Z or W
//! there has no use and is reported). LinuxCNC reads the time from P only; its axis words go to
//! the modal motion, as in rs274ngc.

use crate::gcode::Block;
use crate::interp::flow::Run;
use crate::interp::letters::{bit, Letters};
use crate::interp::order::Cx;
use crate::interp::words::Words;
use crate::interp::{Feed, MoveKind};

impl Run<'_> {
    /// Step 6: G4 (group 0). Makes the dwell; sets [`Cx::axes_taken`] when Fanuc's G4 took the
    /// axis words. Order: LinuxCNC's "dwell", after the M codes and before the plane.
    pub(crate) fn convert_dwell(&mut self, b: &Block, w: &mut Words, cx: &mut Cx) {
        if w.g(40) {
            self.dwell(b, w.has_g(40), w, cx.fanuc);
            cx.axes_taken = cx.fanuc;
        }
    }

    /// The dwell of a G4 (`at`, its word) from the block's P, X or U.
    fn dwell(&mut self, b: &Block, at: Option<u32>, w: &mut Letters, fanuc: bool) {
        let seconds = if fanuc {
            // P in milliseconds (seconds when written with a decimal point, as Haas reads it);
            // X or U in seconds. Each of them is the dwell here, never an axis word.
            let given = [b'P', b'X', b'U'].into_iter().filter(|&l| w.peek(l)).count();
            let p = w.peek(b'P').then(|| w.get(b'P')).flatten();
            let x = w.peek(b'X').then(|| w.get(b'X')).flatten();
            let u = w.peek(b'U').then(|| w.get(b'U')).flatten();
            if given > 1 {
                self.error(b, at, "G4 takes one dwell time: P (ms), X or U (s), not several".into());
                return;
            }
            if let Some(p) = p {
                if w.point & bit(b'P') != 0 {
                    p
                } else {
                    p / 1000.0
                }
            } else if let Some(x) = x.or(u) {
                x
            } else {
                self.error(b, at, "G4 needs P (ms), X or U (s)".into());
                return;
            }
        } else {
            match w.get(b'P') {
                Some(p) => p,
                None => {
                    self.error(b, at, "G4 needs P, the dwell in seconds".into());
                    return;
                }
            }
        };
        if seconds < 0.0 {
            self.error(b, at, format!("negative dwell {seconds} s"));
            return;
        }
        let p = self.programmed();
        self.push_move(b, MoveKind::Dwell { seconds }, p, p, Feed::Rapid);
    }
}
