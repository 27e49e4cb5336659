//! The modal state of the interpreter and the parameter store.

use crate::gcode::NameId;
use std::collections::HashMap;

/// The motion mode in force (modal group 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Motion {
    Rapid,
    Line,
    ArcCw,
    ArcCcw,
    /// Spindle-synchronised straight move (Fanuc G32/G33 with F as lead, LinuxCNC G33 with K).
    Thread,
    /// A modal canned cycle (G code ×10): a later block with axis words and no motion code runs
    /// it again — Fanuc G90/G92/G94 and G81–G89 through `cycles::repeat`, LinuxCNC G33.1, G76,
    /// G73 and G81–G89 through `cycles/lcnc_*.rs`.
    Cycle(u16),
}

impl Motion {
    /// A drilling cycle G81–G89 (group 10 on Fanuc, where it runs over the group-01 motion).
    pub fn is_drilling(self) -> bool {
        matches!(self, Motion::Cycle(810..=890))
    }
}

/// Everything M70 saves and M72 restores.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Modal {
    pub inch: bool,
    pub incremental: bool,
    /// G91.1 (default): I/K relative to the start point.
    pub arc_incremental: bool,
    pub diameter: bool,
    pub motion: Option<Motion>,
    /// Fanuc: the group-01 motion (G0–G3, G32, G90/G92/G94) last in force; a drilling cycle
    /// (group 10) runs over it and G80 gives it back (Fanuc 0i-TD manual, G-code groups).
    pub group1: Option<Motion>,
    pub feed_per_rev: bool,
    /// F in program units per minute or per revolution; 0 = never set.
    pub feed: f64,
    pub spindle_css: bool,
    /// The last S word in rpm (G97) or surface speed (G96, m/min or ft/min).
    pub s: f64,
    /// G50 S / G92 S / G96 D clamp, rpm.
    pub css_clamp: Option<f64>,
    pub plane_xz: bool,
    /// G17 (LinuxCNC: lathe programs select it for drilling along Z): straight moves and
    /// drilling cycles run, arcs are refused.
    pub plane_xy: bool,
}

/// Parameters: numbered (`#1`…`#5602`, Fanuc `#1`…`#999`) and named (`#<name>`).
#[derive(Clone, Debug)]
pub(crate) struct Params {
    pub numbered: Vec<f64>,
    pub global: HashMap<NameId, f64>,
}

pub(crate) const NUMBERED_PARAMS: usize = 6000;

impl Params {
    pub fn new() -> Params {
        Params {
            numbered: vec![0.0; NUMBERED_PARAMS],
            global: HashMap::new(),
        }
    }
}

/// One active subroutine or subprogram call.
#[derive(Clone, Debug)]
pub(crate) struct Frame {
    /// Block to continue at after the return.
    pub return_pc: usize,
    /// Block index of the first block of the called body (for M98 L repeats).
    pub body_pc: usize,
    /// Further passes of an M98 … L call.
    pub repeats_left: u64,
    /// `#1`…`#33` of the caller.
    pub saved_locals: [f64; 33],
    /// Named locals of this call.
    pub locals: HashMap<NameId, f64>,
    /// Modal state to restore at return (M73).
    pub autorestore: Option<Modal>,
    /// Remaining passes of `repeat` loops, by the block index of the `repeat`.
    pub repeat_counts: HashMap<usize, u64>,
    /// A Fanuc M98 subprogram (ended by M99) rather than an o-word subroutine.
    pub fanuc: bool,
}
