//! Step 2 of the order of execution: the feed mode (G93/G94/G95, group 5; Fanuc system A's
//! G98/G99), the drilling cycles' return level (G98/G99: Fanuc system B, LinuxCNC group 10) and
//! the F word; and the feed of a cutting move as the modes make it. As in LinuxCNC's table, the
//! mode comes before the feed, so `G95 F0.2` is 0.2 mm per revolution. Fanuc's G32/G33 take F
//! as the thread lead (step 9), not as the feed.

use crate::gcode::Block;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::{gb, Words};
use crate::interp::Feed;

/// G93/G94/G95, G98/G99: the feed modes.
const FEED_MODE_CODES: u128 = gb(930) | gb(940) | gb(950) | gb(980) | gb(990);

impl Run<'_> {
    /// Step 2: feed mode and feed (group 5; G98/G99 group 10 or, Fanuc system A, 5). Touches
    /// `modal.feed_per_rev`, `modal.feed` and the drilling cycles' return level. Order:
    /// LinuxCNC's "set feed rate mode", then "set feed rate" (its "set retract mode" is read here
    /// too, see `order.rs`).
    pub(crate) fn convert_feed(&mut self, b: &Block, w: &mut Words, cx: &Cx) {
        let Cx { fanuc, sys_b, axis, .. } = *cx;
        if w.any_g(FEED_MODE_CODES) {
            if fanuc {
                // System A: G98/G99 (G94/G95 without axis words); system B: G94/G95.
                if (w.g(980) && !sys_b) || (w.g(940) && (sys_b || !axis)) {
                    self.modal.feed_per_rev = false;
                }
                if (w.g(990) && !sys_b) || (w.g(950) && (sys_b || !axis)) {
                    self.modal.feed_per_rev = true;
                }
                if sys_b && (w.g(980) || w.g(990)) {
                    // System B: G98/G99 choose the drilling cycles' return level.
                    self.cycles.return_r = w.g(990);
                }
            } else {
                if w.g(940) {
                    self.modal.feed_per_rev = false;
                }
                if w.g(950) {
                    self.modal.feed_per_rev = true;
                }
                // G98/G99: where a LinuxCNC drilling cycle retracts to.
                if w.g(980) || w.g(990) {
                    self.cycles.lcnc.retract_to_old_z = w.g(980);
                }
                if let Some(at) = w.has_g(930) {
                    self.unsupported(b, Some(at), "G93 inverse-time feed is not modelled".into(), false);
                }
            }
        }
        // In a Fanuc G32 block F is the thread's lead (the motion step reads it); it is the same
        // modal F register, so it stays the feed of later blocks too (as on the control: a G1
        // after the thread without F feeds at the lead).
        let thread_lead_f = fanuc && (w.g(320) || w.g(330));
        if !thread_lead_f {
            self.feed_word(b, w);
        } else if let Some(f) = w.get(b'F').filter(|f| *f > 0.0) {
            self.modal.feed = f;
        }
    }

    /// The F word: the feed rate from here on.
    pub(crate) fn feed_word(&mut self, b: &Block, w: &mut Words) {
        if let Some(f) = w.get(b'F') {
            if f < 0.0 {
                self.error(b, w.at(b'F'), format!("negative feed F{f}"));
            } else {
                self.modal.feed = f;
            }
        }
    }

    /// The feed of a cutting move now, or a finding at the block's line.
    pub(crate) fn feed(&mut self, b: &Block) -> Option<Feed> {
        self.feed_or(b, || "feed move without a feed rate (no F word in force)".into())
    }

    /// [`Self::feed`] with the finding's message given by `missing`.
    pub(crate) fn feed_or(&mut self, b: &Block, missing: impl FnOnce() -> String) -> Option<Feed> {
        if self.modal.feed <= 0.0 {
            self.error(b, None, missing());
            return None;
        }
        let f = self.modal.feed * self.scale();
        Some(if self.modal.feed_per_rev {
            Feed::PerRev(f)
        } else {
            Feed::PerMinute(f)
        })
    }
}
