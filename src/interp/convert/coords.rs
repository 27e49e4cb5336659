//! Step 8 of the order of execution: the non-modal codes of group 0 that use the axis words —
//! the returns home and to a reference point (G28, G30), the coordinate setting (Fanuc G50 X Z,
//! system B G92 X Z; LinuxCNC G92, G92.1/G92.2, G52), G10 and G28.1/G30.1 (not modelled) — and
//! the selection of a work coordinate system (G54–G59, read in step 7). After them, the axis
//! words belong to no motion (step 9).

use crate::gcode::Block;
use crate::geom::{P2, V2};
use crate::interp::flow::Run;
use crate::interp::groups::g_name;
use crate::interp::order::Cx;
use crate::interp::words::{gb, Words};
use crate::interp::{Feed, MoveKind};

/// Non-modal codes that use the axis words themselves: G28, G30, G10, G50, G52, G92.
const NONMODAL_CODES: u128 =
    gb(280) | gb(281) | gb(300) | gb(301) | gb(100) | gb(500) | gb(520) | gb(920) | gb(921) | gb(922);

impl Run<'_> {
    /// Step 8: G28, G30, G10, G50/G92, G52 (group 0). Touches the shift of program zero and the
    /// machine's position (the returns); sets [`Cx::axes_taken`]. Order: LinuxCNC's "go to
    /// reference location, change coordinate system data, set axis offsets", just before motion.
    pub(crate) fn convert_coordinates(&mut self, b: &Block, w: &mut Words, cx: &mut Cx) {
        let Cx { fanuc, sys_b, axis, .. } = *cx;
        if w.any_g(NONMODAL_CODES) {
            if w.g(280) {
                if !fanuc && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                    // rs274ngc refuses G28 while compensation is on.
                    self.error(
                        b,
                        w.has_g(280),
                        "G28 cannot run with nose radius compensation on: cancel it with G40 first".into(),
                    );
                    w.used = w.has;
                } else {
                    self.home_return(b, w);
                }
                cx.axes_taken = true;
            }
            if w.g(300) {
                if !fanuc && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                    // rs274ngc refuses G30 while compensation is on, as G28.
                    self.error(
                        b,
                        w.has_g(300),
                        "G30 cannot run with nose radius compensation on: cancel it with G40 first".into(),
                    );
                    w.used = w.has;
                } else {
                    self.reference_return(b, w, fanuc);
                }
                cx.axes_taken = true;
            }
            if let Some(at) = w.has_g(281).or(w.has_g(301)).or(w.has_g(100)) {
                let code = [281u16, 301, 100]
                    .into_iter()
                    .find(|&c| w.has_g(c).is_some())
                    .unwrap_or(281);
                self.unsupported(b, Some(at), format!("{} is not modelled", g_name(code)), false);
                w.used = w.has;
                cx.axes_taken = true;
            }
            if fanuc && w.g(500) && axis {
                self.set_origin(b, w);
                cx.axes_taken = true;
            }
            if sys_b && w.g(920) && axis {
                // G-code system B: G92 is the coordinate setting (G50 of system A).
                self.set_origin(b, w);
                cx.axes_taken = true;
            }
            if !fanuc {
                if w.g(920) {
                    self.set_origin(b, w);
                    cx.axes_taken = true;
                }
                if w.g(921) || w.g(922) {
                    self.shift = V2::zeros();
                    self.extra_clear_shift();
                }
                if w.g(520) {
                    let x = w.get(b'X').map(|x| self.to_radius(x)).unwrap_or(0.0) * self.scale();
                    let z = w.get(b'Z').unwrap_or(0.0) * self.scale();
                    self.shift = V2::new(x, z);
                    self.extra_set_origin(w, true);
                    cx.axes_taken = true;
                }
            }
        }
    }

    /// G28: through the intermediate point given by the axis words to home, for the axes named
    /// (all axes when none is named).
    fn home_return(&mut self, b: &Block, w: &mut Words) {
        let home = self.machine.home;
        self.return_through(b, w, home);
    }

    /// G30: as G28, to another point. Fanuc: the 2nd, 3rd or 4th reference point (`P2` when no P
    /// word; `axes.reference_points`, home for a point the machine file does not give).
    /// LinuxCNC: the point in parameters #5181 (X) and #5183 (Z), machine coordinates (as G53
    /// reads them: from `axes.machine_zero`), X a radius, in the machine's native units, as
    /// rs274ngc keeps them.
    fn reference_return(&mut self, b: &Block, w: &mut Words, fanuc: bool) {
        let target = if fanuc {
            let at = w.at(b'P');
            let p = w.get(b'P').unwrap_or(2.0);
            let n = if p.fract() == 0.0 && (2.0..=4.0).contains(&p) {
                p as usize
            } else {
                self.error(
                    b,
                    at,
                    format!("G30 P{p}: the reference point is P2, P3 or P4 (the 2nd to 4th)"),
                );
                w.used = w.has;
                return;
            };
            self.machine
                .reference_points
                .get(n - 2)
                .copied()
                .unwrap_or(self.machine.home)
        } else {
            // rs274ngc keeps the point in the machine's native units: inch on a machine that
            // starts programs in inch (rs274 without an INI file is one), mm otherwise.
            let unit = if self.machine.inch { 25.4 } else { 1.0 };
            let param = |n: usize| self.params.numbered.get(n).copied().unwrap_or(0.0) * unit;
            let zero = self.machine.machine_zero;
            crate::geom::p2(zero.x + param(5181), zero.y + param(5183))
        };
        self.return_through(b, w, target);
    }

    /// G28/G30: a rapid to the intermediate point given by the axis words, then a rapid that
    /// takes the turret reference point to `target` on the axes named (all axes when none is
    /// named).
    fn return_through(&mut self, b: &Block, w: &mut Words, target: P2) {
        let named_x = w.peek(b'X') || w.peek(b'U');
        let named_z = w.peek(b'Z') || w.peek(b'W');
        let named_extra = self.extra_named(w);
        let any_extra = named_extra.iter().any(|&n| n);
        let start = self.programmed();
        let Some(mid) = self.target(b, w) else { return };
        let extra_start = self.tm.as_deref().map(|t| t.pos);
        let Some(extra_mid) = self.extra_end(b, w, false) else {
            return;
        };
        if mid != start || extra_mid != extra_start {
            if let Some(e) = extra_mid {
                self.set_pending(e, None);
            }
            self.push_move(b, MoveKind::Rapid, start, mid, Feed::Rapid);
        }
        let (hx, hz) = if named_x || named_z || any_extra {
            (named_x, named_z)
        } else {
            (true, true)
        };
        // The extra axes named (all of them when no axis is named) go to their home: the axis
        // value they start the program at.
        let extra_end = extra_mid.map(|mut e| {
            let all = !(named_x || named_z || any_extra);
            if let Some(kin) = self.machine.kinematics.as_deref() {
                for k in 0..4 {
                    if all || named_extra[k] {
                        if let Some(a) = kin.axis_by_letter(crate::interp::EXTRA_LETTERS[k]) {
                            e[k] = kin.axes[a].zero;
                        }
                    }
                }
            }
            e
        });
        let tip = self.tip();
        let mut r = mid - tip;
        if hx {
            r.x = target.x;
        }
        if hz {
            r.y = target.y;
        }
        let end = r + tip;
        if end != mid || extra_end != extra_mid {
            if let Some(e) = extra_end {
                self.set_pending(e, None);
            }
            self.push_move(b, MoveKind::Rapid, mid, end, Feed::Rapid);
        }
        self.reference = r;
    }

    /// G54–G59: the work offset `code` names becomes program zero for what follows (the
    /// machine's or the job's `work_offsets`; G54 without one is `program_zero_z`). A G50/G92
    /// or G52 shift stays in force over it, as both controls shift every work coordinate system
    /// by it. An offset that is not given leaves program zero where it is, as an `unsupported`
    /// error that names the key to write.
    pub(crate) fn select_work_offset(&mut self, b: &Block, code: u16, at: u32) {
        let n = usize::from((code - 540) / 10);
        let zero = match n {
            0 => self.g54_zero().or(self.machine.work_zero(0)),
            _ => self.machine.work_zero(n),
        };
        match zero {
            Some(p) => {
                self.base_origin = p;
                self.coord_system = n as u8;
            }
            None => {
                let name = g_name(code);
                self.unsupported(
                    b,
                    Some(at),
                    format!(
                        "{name}: the work offset {name} is not given, so program zero stays where it was: write it in the job as `[work_offsets] {name} = {{ z = … }}` (the control's work offset page: Z from machine zero, mm) or in the machine file's [setup.work_offsets]"
                    ),
                    true,
                );
            }
        }
    }

    /// Fanuc G50 X Z / LinuxCNC G92 X Z: the current point gets the given program coordinates.
    fn set_origin(&mut self, b: &Block, w: &mut Words) {
        let cur = self.programmed();
        let s = self.scale();
        let mut origin = self.origin();
        if let Some(x) = w.get(b'X') {
            origin.x = cur.x - self.to_radius(x) * s;
        }
        if let Some(z) = w.get(b'Z') {
            origin.y = cur.y - z * s;
        }
        let _ = b;
        self.shift = origin - self.base_origin;
        self.extra_set_origin(w, false);
    }
}
