//! Step 1 of the order of execution: units (G20/G21, group 6), LinuxCNC's lathe diameter and
//! radius modes (G7/G8, group 15), distance mode (G90/G91, group 3) and LinuxCNC's arc distance
//! mode (G90.1/G91.1, group 4); and what reads a value through them (`scale`, `to_radius`).
//! They come first, before LinuxCNC's table puts them (after the plane), because they govern how
//! every later word of the block reads; Fanuc system A's G90 with axis words is the box cycle
//! (group 1, step 9), not the distance mode.

use crate::interp::arc::ArcTolerance;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::{gb, Words};

/// G7/G8, G20/G21, G90/G91, G90.1/G91.1: the codes that change how values read.
const UNIT_AND_DISTANCE_CODES: u128 = gb(70) | gb(80) | gb(200) | gb(210) | gb(900) | gb(910) | gb(901) | gb(911);

impl Run<'_> {
    /// Step 1: units (group 6), diameter/radius mode (15), distance modes (3, 4). Touches
    /// `modal.inch`, `modal.diameter`, `modal.incremental`, `modal.arc_incremental`. Order:
    /// first, ahead of LinuxCNC's "set length units" and "set distance mode" (see `order.rs`).
    pub(crate) fn convert_units(&mut self, w: &Words, cx: &Cx) {
        let Cx { fanuc, sys_b, axis, .. } = *cx;
        if w.any_g(UNIT_AND_DISTANCE_CODES) {
            if !fanuc {
                if w.g(70) {
                    self.modal.diameter = true;
                }
                if w.g(80) {
                    self.modal.diameter = false;
                }
            }
            if w.g(200) {
                self.modal.inch = true;
            }
            if w.g(210) {
                self.modal.inch = false;
            }
            if w.g(900) && !(fanuc && !sys_b && axis) {
                self.modal.incremental = false;
            }
            if w.g(910) && !(fanuc && !sys_b && axis) {
                self.modal.incremental = true;
            }
            if !fanuc {
                if w.g(901) {
                    self.modal.arc_incremental = false;
                }
                if w.g(911) {
                    self.modal.arc_incremental = true;
                }
            }
        }
    }

    /// How far an arc's radii may differ at its ends, for the program's units.
    pub(crate) fn arc_tolerance(&self) -> ArcTolerance {
        if self.modal.inch {
            ArcTolerance::INCH
        } else {
            ArcTolerance::MM
        }
    }

    /// mm per program unit.
    pub(crate) fn scale(&self) -> f64 {
        if self.modal.inch {
            25.4
        } else {
            1.0
        }
    }

    /// X as a radius in program units.
    pub(crate) fn to_radius(&self, x: f64) -> f64 {
        if self.modal.diameter {
            x / 2.0
        } else {
            x
        }
    }
}
