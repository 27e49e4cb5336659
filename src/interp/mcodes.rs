//! The M codes of a block, by the machine's table ([`crate::machine::McodeTable`]): spindle,
//! coolant, tailstock, chuck and the other devices, program stops and end. M6 (step 4 of the
//! order of execution, `convert/tool.rs`), M70–M73 (step 5, `convert/m_codes.rs`) and M98/M99
//! (step 10, `convert/flow.rs`, run by `flow.rs`) steer the interpreter.
//!
//! What latheguard does with each action (see `docs/mcodes.md`): the spindle codes set the
//! spindle of the following moves; the tailstock codes decide whether the tailstock is an
//! obstacle (moves carry it in their [`MoveState`](super::MoveState)); opening the chuck while the
//! spindle turns, or starting the spindle with the chuck open, is a `program` finding; the other
//! devices (coolant, part catcher, bar feeder, conveyor) change nothing that is checked. A code the
//! table lacks is a warning that names it.

use super::flow::Run;
use super::letters::Letters;
use super::SpindleDir;
use crate::gcode::Block;
use crate::machine::MAction;

/// The state of the machine's devices that the checker or the interpreter's own findings need.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Devices {
    /// The tailstock is advanced: an obstacle.
    pub tailstock_advanced: bool,
    /// The chuck is open (unclamped).
    pub chuck_open: bool,
    /// The sub-spindle's chuck is clamped.
    pub sub_chuck_closed: bool,
    /// The active station holds no tool the machine file describes (or does not exist): the
    /// moves until the next tool change are not checked.
    pub tool_unknown: bool,
}

impl Devices {
    pub fn new(machine: &crate::machine::Machine) -> Devices {
        Devices {
            tailstock_advanced: machine.tailstock_advanced,
            chuck_open: false,
            sub_chuck_closed: false,
            tool_unknown: false,
        }
    }
}

impl Run<'_> {
    /// Run the M codes of a block (`list`, with their offsets, in block order) that the
    /// machine's table maps (step 5 of the order of execution, `convert/m_codes.rs`); `w` the
    /// block's letter words. Returns whether one of them ends the program (run after the block's
    /// motion and flow).
    pub(crate) fn m_codes(&mut self, b: &Block, list: &[(u16, u32)], w: &mut Letters) -> bool {
        let mut ends = false;
        let mut chuck_opened_at = None;
        let mut spindle_started_at = None;
        // In block order; the chuck is judged against the spindle as the block leaves it.
        let codes: [(u16, u32); 16] = {
            let mut c = [(0u16, 0u32); 16];
            c[..list.len()].copy_from_slice(list);
            c
        };
        let n = list.len();
        for &(code, at) in &codes[..n] {
            if crate::machine::mcodes_reserved(code)
                || (code == 61 && self.machine.dialect == crate::machine::Dialect::Linuxcnc)
            {
                // LinuxCNC's M61 (set the tool number) is the tool step's (`convert/tool.rs`).
                continue;
            }
            if self.machine.paths.is_wait(code) {
                self.wait_code(b, code, at, w);
                continue;
            }
            let Some(action) = self.machine.mcodes.action(code) else {
                self.unsupported(
                    b,
                    Some(at),
                    format!(
                        "M{code} is not in this machine's M-code table (`[mcodes]` in the machine file, docs/mcodes.md): ignored"
                    ),
                    false,
                );
                continue;
            };
            match action {
                MAction::SpindleCw | MAction::SpindleCcw => {
                    self.spindle_dir = if action == MAction::SpindleCw {
                        SpindleDir::Cw
                    } else {
                        SpindleDir::Ccw
                    };
                    spindle_started_at = Some((code, at));
                    self.spindle_started();
                }
                MAction::SpindleStop => self.spindle_dir = SpindleDir::Off,
                MAction::TailstockAdvance => self.devices.tailstock_advanced = true,
                MAction::TailstockRetract => self.devices.tailstock_advanced = false,
                MAction::ChuckOpen => {
                    self.devices.chuck_open = true;
                    chuck_opened_at = Some((code, at));
                }
                MAction::ChuckClose => self.devices.chuck_open = false,
                MAction::SubChuckClose => self.devices.sub_chuck_closed = true,
                MAction::SubChuckOpen => self.devices.sub_chuck_closed = false,
                MAction::ProgramEnd => ends = true,
                MAction::ProgramStop | MAction::OptionalStop => self.program_stop(),
                MAction::CoolantOn
                | MAction::CoolantOff
                | MAction::PartCatcherAdvance
                | MAction::PartCatcherRetract
                | MAction::BarFeed
                | MAction::ConveyorOn
                | MAction::ConveyorOff
                | MAction::NoEffect => {}
                MAction::CAxisOn
                | MAction::CAxisOff
                | MAction::LiveToolCw
                | MAction::LiveToolCcw
                | MAction::LiveToolStop => {
                    self.turn_mill_m_code(b, w, action, code, at);
                }
            }
        }
        if self.spindle_dir != SpindleDir::Off && self.devices.chuck_open {
            if let Some((code, at)) = chuck_opened_at {
                self.error(
                    b,
                    Some(at),
                    format!(
                        "M{code} opens the chuck while the spindle turns: the part is thrown out (a control's chuck interlock would refuse it, or stop the spindle first)"
                    ),
                );
            } else if let Some((code, at)) = spindle_started_at {
                self.error(
                    b,
                    Some(at),
                    format!(
                        "M{code} starts the spindle with the chuck open: the part is not held (a control's chuck interlock would refuse it)"
                    ),
                );
            }
        }
        ends
    }
}

impl Run<'_> {
    /// A waiting M code of a multi-path control (`[sync]`): a [`MoveKind::Wait`] mark where the
    /// path stands. `P` lists the paths that meet by their digits (`M100 P12`: paths 1 and 2);
    /// without it, every path of the machine.
    ///
    /// [`MoveKind::Wait`]: super::MoveKind::Wait
    fn wait_code(&mut self, b: &Block, code: u16, at: u32, w: &mut Letters) {
        let count = self.machine.paths.count() as u32;
        let all = ((1u32 << count) - 1) as u8;
        let paths = match w.take(b'P') {
            None => all,
            Some(p) => match path_digits(p, count) {
                Some(mask) => mask,
                None => {
                    self.error(
                        b,
                        Some(at),
                        format!(
                            "M{code} P{p}: P lists the paths that wait by their digits, each 1 to {count} (P12: paths 1 and 2)"
                        ),
                    );
                    return;
                }
            },
        };
        let here = self.programmed();
        self.push_move(b, super::MoveKind::Wait { code, paths }, here, here, super::Feed::Rapid);
    }
}

/// The paths a wait's `P` names, as a mask (bit `p - 1` for path `p`): each decimal digit one
/// path from 1 to `count`; `None` when `p` is not such a number.
fn path_digits(p: f64, count: u32) -> Option<u8> {
    if !((1.0..1e9).contains(&p) && p.fract() == 0.0) {
        return None;
    }
    let mut n = p as u64;
    let mut mask = 0u8;
    while n > 0 {
        let d = (n % 10) as u32;
        if d == 0 || d > count {
            return None;
        }
        mask |= 1 << (d - 1);
        n /= 10;
    }
    Some(mask)
}
