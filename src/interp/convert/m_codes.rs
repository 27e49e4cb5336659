//! Step 5 of the order of execution: the M codes by the machine's table (`mcodes.rs`: spindle,
//! coolant, tailstock, chuck, the other devices, program stops; the program's end is noted here
//! and takes effect after the block's motion, step 10) and LinuxCNC's modal state M70–M73
//! (save, invalidate, restore, save with autorestore). M6 is the tool change (step 4), M98/M99
//! program flow (step 10).

use crate::gcode::Block;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::Words;

impl Run<'_> {
    /// Step 5: the block's M codes (the M groups of `groups.rs`: spindle 7, coolant 8,
    /// overrides 9, stops 4, modal state 11). Touches the spindle direction, the devices, the saved modal state; sets
    /// [`Cx::ends`]. Order: LinuxCNC's "spindle on or off", "save/restore state", "coolant",
    /// "overrides", after the tool change and before the dwell.
    pub(crate) fn convert_m_codes(&mut self, b: &Block, w: &mut Words, cx: &mut Cx) {
        if w.nm > 0 {
            cx.ends = self.m_codes(b, &w.m[..w.nm], &mut w.letters);
            if w.m(70) || w.m(73) {
                if w.m(73) {
                    let m = self.modal.clone();
                    match self.frames.last_mut() {
                        Some(f) => f.autorestore = Some(m),
                        None => self.saved_modal = Some(m),
                    }
                } else {
                    self.saved_modal = Some(self.modal.clone());
                }
            }
            if w.m(71) {
                self.saved_modal = None;
            }
            if let Some(at) = w.has_m(72) {
                match self.saved_modal.clone() {
                    Some(m) => self.modal = m,
                    None => self.error(b, Some(at), "M72 without a state saved by M70".into()),
                }
            }
        }
    }
}
