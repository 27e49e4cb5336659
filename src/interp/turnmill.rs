//! Turn-mill axes and modes (docs/turn-mill.md): the extra axes Y, C, B and A ([`EXTRA_LETTERS`]) on a
//! machine whose kinematic tree has them, the G17/G19 planes with their arcs, the spindle's
//! C-axis mode and the live tool. A machine without kinematics never builds a [`TurnMill`]: its
//! programs run exactly as before (docs/turn-mill.md, "Axes and modes in programs").

use super::arc::{arc_from_center, arc_from_radius};
use super::flow::Run;
use super::letters::Letters;
use super::state::Motion;
use super::{ExtraAxes, ExtraMove, Feed, MoveKind, Plane, PlaneArc, EXTRA_LETTERS};
use crate::gcode::Block;
use crate::geom::P2;
use crate::machine::{Dialect, MAction};

/// What the interpreter needs of one extra axis of the machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AxisInfo {
    /// mm (converted from inch programs) rather than degrees.
    pub linear: bool,
}

/// The extra axes and turn-mill modes of a run.
#[derive(Clone, Debug)]
pub(crate) struct TurnMill {
    /// The machine's axis for each of [`EXTRA_LETTERS`], if it has one.
    pub axes: [Option<AxisInfo>; 4],
    /// Where each axis is (axis values: mm or degrees).
    pub pos: ExtraAxes,
    /// The axis value of program zero of each axis (G92 / G50 / G52 shifts; 0 under G54).
    pub shift: ExtraAxes,
    /// The main spindle is a positioned C axis.
    pub c_mode: bool,
    /// The live tool's speed (rev/min), 0 when stopped.
    pub live_rpm: f64,
    /// The last speed a live-tool code was given (its P word).
    pub live_speed: f64,
    /// The machine's M-code table has a code that puts the spindle in C-axis mode: C words
    /// need that mode.
    pub c_needs_mode: bool,
    /// The entries made so far (index order, see [`Run::record_extra`]).
    pub list: Vec<ExtraMove>,
    /// Moves handed to a streaming sink before the ones in `Run::moves`.
    pub handed: u64,
    /// The extra-axis end and plane arc of the move about to be pushed.
    pub pending: Option<(ExtraAxes, Option<PlaneArc>)>,
    /// Polar coordinate interpolation (G12.1) and its hypothetical point (`polar.rs`).
    pub polar: Option<super::polar::Polar>,
    /// Cylindrical interpolation (G7.1): the cylinder's radius, mm (`cylindrical.rs`).
    pub cylinder: Option<f64>,
    /// Cylindrical interpolation under cutter compensation: the programmed point (z, C degrees),
    /// where the tool is not (`cylindrical.rs`).
    pub cylinder_prog: Option<P2>,
    /// Cutter compensation in a contour mode (`contour_comp.rs`), once G41/G42 was given in
    /// polar or cylindrical interpolation.
    pub contour_comp: Option<Box<super::contour_comp::ContourComp>>,
}

impl TurnMill {
    /// The turn-mill state of a machine with a kinematic tree naming any of the extra axes;
    /// `None` otherwise (the run is a 2-axis lathe's).
    pub fn new(machine: &crate::machine::Machine) -> Option<TurnMill> {
        let kin = machine.kinematics.as_ref()?;
        let mut axes = [None; 4];
        let mut pos = [0.0; 4];
        for (k, &l) in EXTRA_LETTERS.iter().enumerate() {
            if let Some(a) = kin.axis_by_letter(l) {
                let a = &kin.axes[a];
                axes[k] = Some(AxisInfo {
                    linear: matches!(a.kind, crate::kin::AxisKind::Linear { .. }),
                });
                pos[k] = a.zero;
            }
        }
        if axes.iter().all(Option::is_none) {
            return None;
        }
        Some(TurnMill {
            axes,
            pos,
            shift: [0.0; 4],
            c_mode: false,
            live_rpm: 0.0,
            live_speed: 0.0,
            c_needs_mode: machine.mcodes.codes_of(MAction::CAxisOn).next().is_some(),
            list: Vec::new(),
            handed: 0,
            pending: None,
            polar: None,
            contour_comp: None,
            cylinder_prog: None,
            cylinder: None,
        })
    }

    pub fn has_y(&self) -> bool {
        self.axes[0].is_some()
    }
}

/// The Fanuc incremental address of an extra axis (V for Y, H for C), if it has one.
fn incremental_letter(k: usize) -> Option<u8> {
    match k {
        0 => Some(b'V'),
        1 => Some(b'H'),
        _ => None,
    }
}

impl Run<'_> {
    /// The plane in force.
    pub(crate) fn plane(&self) -> Plane {
        if self.modal.plane_xy {
            Plane::Xy
        } else if self.modal.plane_xz {
            Plane::Zx
        } else {
            Plane::Yz
        }
    }

    /// The machine has a Y axis (so G17 and G19 are real planes).
    pub(crate) fn has_y_axis(&self) -> bool {
        self.tm.as_ref().is_some_and(|t| t.has_y())
    }

    /// The block has a word for one of the machine's extra axes (Fanuc: also V, H).
    pub(crate) fn extra_words(&self, w: &Letters) -> bool {
        let Some(tm) = self.tm.as_deref() else {
            return false;
        };
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        (0..4).any(|k| {
            tm.axes[k].is_some()
                && (w.peek(EXTRA_LETTERS[k] as u8) || (fanuc && incremental_letter(k).is_some_and(|l| w.peek(l))))
        })
    }

    /// Which extra axes the block names (absolute or incremental word).
    pub(crate) fn extra_named(&self, w: &Letters) -> [bool; 4] {
        let mut named = [false; 4];
        let Some(tm) = self.tm.as_deref() else {
            return named;
        };
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        for (k, n) in named.iter_mut().enumerate() {
            *n = tm.axes[k].is_some()
                && (w.peek(EXTRA_LETTERS[k] as u8) || (fanuc && incremental_letter(k).is_some_and(|l| w.peek(l))));
        }
        named
    }

    /// The extra axes' target of the block's words: absolute (program zero + value) or
    /// incremental (G91, or Fanuc V/H), linear axes in mm (inch programs converted), rotary in
    /// degrees with no wrap; with `g53`, axis values. `None` after a finding (a C word with the
    /// spindle not in C-axis mode, an absolute and incremental word together, a value out of
    /// range).
    pub(crate) fn extra_target(&mut self, b: &Block, w: &mut Letters, g53: bool) -> Option<ExtraAxes> {
        let tm = self.tm.as_deref()?;
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let s = self.scale();
        let incremental = self.modal.incremental;
        let (axes, pos, shift, c_allowed) = (tm.axes, tm.pos, tm.shift, tm.c_mode || !tm.c_needs_mode);
        let mut out = pos;
        for k in 0..4 {
            let Some(info) = axes[k] else { continue };
            let letter = EXTRA_LETTERS[k] as u8;
            let inc_letter = incremental_letter(k).filter(|_| fanuc);
            let has_abs = w.peek(letter);
            let has_inc = inc_letter.is_some_and(|l| w.peek(l));
            if !has_abs && !has_inc {
                continue;
            }
            if let (true, Some(l)) = (has_abs && has_inc, inc_letter) {
                self.error(
                    b,
                    w.at(l),
                    format!("{} and {} in one block", EXTRA_LETTERS[k], l as char),
                );
                return None;
            }
            let unit = if info.linear { s } else { 1.0 };
            let (v, at, inc) = if has_abs {
                (w.get(letter).unwrap_or(0.0), w.at(letter), incremental && !g53)
            } else {
                let l = inc_letter.unwrap_or(letter);
                (w.get(l).unwrap_or(0.0), w.at(l), true)
            };
            if k == 1 && !c_allowed {
                let word = if has_abs { 'C' } else { 'H' };
                self.error(
                    b,
                    at,
                    format!(
                        "{word}{v}: the spindle is not in C-axis mode (give the machine's c_axis_on M code first, docs/mcodes.md): a control alarms here"
                    ),
                );
                return None;
            }
            out[k] = if inc {
                pos[k] + v * unit
            } else if g53 {
                v * unit
            } else {
                shift[k] + v * unit
            };
            if !super::in_range_value(out[k]) {
                self.error(b, at, "the target point is out of any range".into());
                return None;
            }
        }
        Some(out)
    }

    /// The extra axes' target of the block ([`Self::extra_target`]) on a turn-mill machine,
    /// `Some(None)` on a 2-axis one (nothing to read), `None` after a finding.
    pub(crate) fn extra_end(&mut self, b: &Block, w: &mut Letters, g53: bool) -> Option<Option<ExtraAxes>> {
        if self.tm.is_none() {
            return Some(None);
        }
        self.extra_target(b, w, g53).map(Some)
    }

    /// Set the extra-axis end (and plane arc) of the next move pushed.
    pub(crate) fn set_pending(&mut self, end: ExtraAxes, arc: Option<PlaneArc>) {
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.pending = Some((end, arc));
        }
    }

    /// Record the extra-axis entry of the `count` moves just added to `moves` (one, or what
    /// compensation let out), `kind` the kind of the move made. An entry is kept when an extra
    /// axis is away from 0 or moves, the spindle is in C-axis mode, the live tool turns, the plane
    /// is not G18 or an extra axis's program zero is shifted.
    pub(crate) fn record_extra(&mut self, kind: MoveKind, first: usize, count: usize) {
        let plane = self.plane();
        let Some(tm) = self.tm.as_deref_mut() else {
            return;
        };
        let (end, arc) = tm.pending.take().unwrap_or((tm.pos, None));
        let moving = matches!(kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. });
        let start = tm.pos;
        let end = if moving { end } else { start };
        tm.pos = end;
        let keep = start.iter().chain(end.iter()).chain(tm.shift.iter()).any(|&v| v != 0.0)
            || tm.c_mode
            || tm.live_rpm > 0.0
            || plane != Plane::Zx
            || arc.is_some();
        if !keep {
            return;
        }
        for i in first..first + count {
            let index = (tm.handed + i as u64) as u32;
            // Moves a cycle took back (and made again) drop their entries.
            while tm.list.last().is_some_and(|e| e.index >= index) {
                tm.list.pop();
            }
            tm.list.push(ExtraMove {
                index,
                start,
                end,
                plane,
                c_mode: tm.c_mode,
                live_rpm: tm.live_rpm,
                origin: tm.shift,
                arc,
            });
        }
    }

    /// The entries of the whole run: those of moves a cycle took back at the end are dropped.
    pub(crate) fn take_extra(&mut self) -> Vec<ExtraMove> {
        let total = self.moves.len() as u64;
        match self.tm.as_deref_mut() {
            Some(tm) => {
                let n = tm.handed + total;
                let mut list = std::mem::take(&mut tm.list);
                list.retain(|e| u64::from(e.index) < n);
                list
            }
            None => Vec::new(),
        }
    }

    /// G92 / G50 (coordinate setting): the current extra-axis values get the given program
    /// values. G52: the offsets are the given values (0 for the axes not named).
    pub(crate) fn extra_set_origin(&mut self, w: &mut Letters, g52: bool) {
        let s = self.scale();
        let Some(tm) = self.tm.as_deref_mut() else {
            return;
        };
        for (k, &letter) in EXTRA_LETTERS.iter().enumerate() {
            let Some(info) = tm.axes[k] else { continue };
            let unit = if info.linear { s } else { 1.0 };
            match w.get(letter as u8) {
                Some(v) if g52 => tm.shift[k] = v * unit,
                Some(v) => tm.shift[k] = tm.pos[k] - v * unit,
                None if g52 => tm.shift[k] = 0.0,
                None => {}
            }
        }
    }

    /// G92.1 / G92.2: the extra axes' program zero back at axis value 0.
    pub(crate) fn extra_clear_shift(&mut self) {
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.shift = [0.0; 4];
        }
    }

    /// A turn-mill M code (c_axis_on, c_axis_off, live_tool_*). Returns whether it was one.
    pub(crate) fn turn_mill_m_code(&mut self, b: &Block, w: &mut Letters, action: MAction, code: u16, at: u32) -> bool {
        if !matches!(
            action,
            MAction::CAxisOn | MAction::CAxisOff | MAction::LiveToolCw | MAction::LiveToolCcw | MAction::LiveToolStop
        ) {
            return false;
        }
        let speed = if matches!(action, MAction::LiveToolCw | MAction::LiveToolCcw) {
            // Without P, an S on the code's line is the live tool's speed (`S600 M13`).
            match w.get(b'P').or_else(|| w.get(b'S')) {
                Some(p) if p.is_finite() && p >= 0.0 => Some(p),
                Some(p) => {
                    self.error(
                        b,
                        w.at(b'P').or(w.at(b'S')),
                        format!("{p}: a live-tool speed (P, or S on its line) is a rev/min of 0 or more"),
                    );
                    return true;
                }
                None => None,
            }
        } else {
            None
        };
        let Some(tm) = self.tm.as_deref_mut() else {
            // A 2-axis machine: nothing it could move (the code is still known, so no warning).
            return true;
        };
        match action {
            MAction::CAxisOn => {
                tm.c_mode = true;
                // The spindle is held by its C-axis drive: it does not turn.
                self.spindle_dir = super::SpindleDir::Off;
            }
            MAction::CAxisOff => tm.c_mode = false,
            MAction::LiveToolCw | MAction::LiveToolCcw => {
                if let Some(p) = speed {
                    tm.live_speed = p;
                }
                tm.live_rpm = tm.live_speed;
                if tm.live_rpm <= 0.0 {
                    let msg =
                        format!("M{code} starts the live tool without a speed (P, or S on its line, rev/min): it is taken as stopped");
                    self.warn_once(b, Some(at), msg);
                }
            }
            _ => tm.live_rpm = 0.0,
        }
        true
    }

    /// The block starts the live tool with no P word: its S word is the live tool's speed
    /// (Mori Seiki's and other Fanuc builders' `S2000 M13`), not the main spindle's. `m_codes`:
    /// the block's M codes with their offsets.
    pub(crate) fn live_start_takes_s(&self, w: &Letters, m_codes: &[(u16, u32)]) -> bool {
        self.tm.is_some()
            && !w.peek(b'P')
            && m_codes.iter().any(|&(c, _)| {
                matches!(
                    self.machine.mcodes.action(c),
                    Some(MAction::LiveToolCw | MAction::LiveToolCcw)
                )
            })
    }

    /// A spindle start (M3/M4) leaves C-axis mode: the spindle turns again.
    pub(crate) fn spindle_started(&mut self) {
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.c_mode = false;
        }
    }

    /// G2/G3 in the XY (G17) or YZ (G19) plane on a machine with a Y axis: the arc about the
    /// centre of I, J (G17; I a radius even in diameter mode, as rs274ngc and Fanuc read it) or
    /// J, K (G19), or of R, with the third coordinate moving linearly (a helix). The move's 2D
    /// fields are a line from start to end; the arc is in its entry ([`PlaneArc`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn plane_arc(
        &mut self,
        b: &Block,
        w: &mut Letters,
        motion: Motion,
        start: P2,
        end: P2,
        extra_end: ExtraAxes,
        feed: Feed,
        turns: u32,
    ) {
        let plane = self.plane();
        let Some(tm) = self.tm.as_deref() else { return };
        let y0 = tm.pos[0];
        let y1 = extra_end[0];
        let y_shift = tm.shift[0];
        let s = self.scale();
        let tol = self.arc_tolerance();
        // Plane coordinates (first, second) of start and end, the centre's offset letters and
        // the program zero of the two coordinates.
        let origin = self.origin();
        let (ps, pe, (l1, l2), zero) = match plane {
            Plane::Xy => (
                P2::new(start.x, y0),
                P2::new(end.x, y1),
                (b'I', b'J'),
                P2::new(origin.x, y_shift),
            ),
            _ => (
                P2::new(y0, start.y),
                P2::new(y1, end.y),
                (b'J', b'K'),
                P2::new(y_shift, origin.y),
            ),
        };
        let other = if plane == Plane::Xy { b'K' } else { b'I' };
        if w.peek(other) {
            return; // reported as unused
        }
        let has_r = w.peek(b'R');
        let has_c = w.peek(l1) || w.peek(l2);
        if has_r && has_c {
            self.error(
                b,
                w.at(b'R'),
                format!("an arc takes R or {}/{}, not both", l1 as char, l2 as char),
            );
            return;
        }
        // G3 turns from the first axis toward the second (counter-clockwise seen from the
        // plane's normal, +z for G17 and +x for G19).
        let ccw = motion == Motion::ArcCcw;
        let result = if has_r {
            let r = w.get(b'R').unwrap_or(0.0) * s;
            arc_from_radius(ps, pe, r, ccw, turns, tol)
        } else if has_c {
            let i = w.get(l1).unwrap_or(0.0) * s;
            let j = w.get(l2).unwrap_or(0.0) * s;
            let center = if self.modal.arc_incremental {
                P2::new(ps.x + i, ps.y + j)
            } else {
                P2::new(zero.x + i, zero.y + j)
            };
            arc_from_center(ps, pe, center, ccw, turns, tol).map(|sw| (center, sw))
        } else {
            self.error(b, None, format!("an arc needs R or {}/{}", l1 as char, l2 as char));
            return;
        };
        match result {
            Ok((center, sweep)) => {
                let arc = PlaneArc {
                    plane,
                    center: [center.x, center.y],
                    sweep,
                };
                self.set_pending(extra_end, Some(arc));
                self.push_move(b, MoveKind::Line, start, end, feed);
            }
            Err(e) => self.error(b, None, e.to_string()),
        }
    }
}
