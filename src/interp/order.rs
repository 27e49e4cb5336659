//! The order of execution: the spine of the interpreter.
//!
//! The words of a block are not run in the order they are written: a control runs them in a
//! fixed order of steps, each step one modal group (or a few related ones), so that `G1 X10 F0.2
//! G95` feeds per revolution at 0.2 before it moves. rs274ngc (LinuxCNC's interpreter) is built
//! that way, one converter per step; latheguard follows the model. [`Run::execute_in_order`] is
//! the order, one `convert_*` call per step, each converter a small function in `convert/`, in a
//! module by subject:
//!
//! | step | converter | codes (modal group) | module |
//! |---|---|---|---|
//! | 0 | `convert_cylindrical`, `check_modal_groups` | G7.1 (21); every G and M code's group | `convert/plane.rs`, `groups.rs` |
//! | 1 | `convert_units` | G20/G21 (6), G7/G8 (15), G90/G91 (3), G90.1/G91.1 (4) | `convert/units.rs` |
//! | 2 | `convert_feed` | G93/G94/G95 (5), G98/G99 (5 or 10), F | `convert/feed.rs` |
//! | 3 | `convert_spindle` | S, G96/G97 (14), Fanuc G50 S / G92 S | `convert/spindle.rs` |
//! | 4 | `convert_tool` | T, M6 | `convert/tool.rs` |
//! | 5 | `convert_m_codes` | the machine's M-code table (spindle, coolant, devices, stops), M70–M73 | `convert/m_codes.rs` |
//! | 6 | `convert_dwell` | G4 (0) | `convert/dwell.rs` |
//! | 7 | `convert_plane_and_comp` | G17/G18/G19 (2), G12.1/G13.1 (21), G40–G42 (7), G43/G49 (8), G54–G59 (12), G61/G64 (13) | `convert/plane.rs` |
//! | 8 | `convert_coordinates` | G28/G30, G10, G50/G92 X Z, G52, G92.1/G92.2 (0) | `convert/coords.rs` |
//! | 9 | `convert_motion` | G0–G3, G32/G33, the canned cycles (1), G80 (Fanuc 9), G53 | `convert/motion.rs`, `convert/cycle.rs` |
//! | 10 | `convert_flow` | M98/M99, program end, the words no code used | `convert/flow.rs` |
//!
//! Where the order comes from: the "Order of Execution" table of LinuxCNC's G-code overview
//! (feed mode, feed, speed, tool selection, tool change, spindle, coolant and the other M codes,
//! dwell, plane, units, cutter compensation, length offset, coordinate system, path mode,
//! distance mode, retract mode, the non-modal coordinate codes and returns home, motion, stop).
//! The Fanuc dialect runs the same order over the codes, modal groups and G-code systems A and B
//! (`G50`/`G92`, `G90`/`G77`…) of the Series 0i-TD operator's manual (B-64304EN).
//! Where latheguard's order differs from LinuxCNC's table, in both dialects: units, diameter and
//! distance modes come first (step 1), since they govern how every later value reads; the
//! retract mode G98/G99 is read with the feed modes (step 2: on Fanuc they are feed modes in
//! system A); every M code of the machine's table runs in step 5 (LinuxCNC splits them between
//! tool change, spindle, coolant and the stops), but the program's end (M2/M30) takes effect
//! last (step 10), after the block's motion.
//!
//! Invariants: a block's words are executed in this order, whatever order they are written
//! in; a converter touches only its group's state (a converter that needs what an earlier one
//! decided reads it from [`Cx`], never from another converter's state); a block the
//! plain-block fast path takes (`Run::plain_block`: at most one of G0–G3, only X Z F I K R)
//! ends as this order would leave it (tests run both ways and compare).

use super::flow::Run;
use super::words::Words;
use crate::gcode::Block;
use std::ops::ControlFlow;

/// What the steps of one block learn and hand on: set by the modal-group check, then by the
/// steps named on each field.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Cx {
    /// The machine reads the Fanuc dialect.
    pub fanuc: bool,
    /// Fanuc G-code system B (G77–G79 box cycles, G92 coordinate setting).
    pub sys_b: bool,
    /// The block has axis words (X Z U W, or the machine's extra axes).
    pub axis: bool,
    /// A G code the dialect does not model is in the block (its words are not checked for use).
    pub unknown: bool,
    /// The block's group-01 motion code and its offset, if any.
    pub motion_code: Option<(u16, u32)>,
    /// Step 5: an M code ends the program (after the block's motion and flow).
    pub ends: bool,
    /// Steps 6 and 8: a non-motion code took the axis words (Fanuc G4 X/U, G28, G50 X Z …).
    pub axes_taken: bool,
    /// Step 7: the block itself asked for a plane a 2-axis lathe lacks (reported there).
    pub plane_error_here: bool,
}

impl Run<'_> {
    /// Execute the words of a block in the order of execution (see the module's table). The
    /// words are read, the assignments made and the plain-block fast path declined before this.
    pub(crate) fn execute_in_order(&mut self, b: &Block, w: &mut Words) {
        self.convert_cylindrical(b, w); // its C word is no axis word: before the words are counted
        let Some(mut cx) = self.check_modal_groups(b, w) else {
            return;
        };
        self.convert_units(w, &cx); // 1
        self.convert_feed(b, w, &cx); // 2
        self.convert_spindle(b, w, &cx); // 3
        self.convert_tool(b, w, &cx); // 4
        self.convert_m_codes(b, w, &mut cx); // 5
        self.convert_dwell(b, w, &mut cx); // 6
        self.convert_plane_and_comp(b, w, &mut cx); // 7
        self.convert_coordinates(b, w, &mut cx); // 8
        if let ControlFlow::Break(()) = self.convert_motion(b, w, &cx) {
            return; // 9: a cycle ran, or a motion code latheguard does not model
        }
        self.convert_flow(b, w, &cx); // 10
    }
}
