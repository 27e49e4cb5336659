//! Step 7 of the order of execution: the plane (G17/G18/G19, group 2), Fanuc's polar coordinate
//! interpolation (G12.1/G13.1, group 21; `polar.rs`), nose-radius compensation (G40/G41/G42 and
//! LinuxCNC's G41.1/G42.1, group 7; the stage itself is `comp.rs`), tool length offsets (G43/G49,
//! group 8), the work coordinate systems (G54–G59, group 12; `coords.rs` selects them) and path
//! mode (G61/G64, group 13), in LinuxCNC's order for these groups. Before the whole order,
//! Fanuc's cylindrical interpolation G7.1 (group 21, `cylindrical.rs`): its C word is the
//! cylinder's radius, not an axis word.

use crate::gcode::Block;
use crate::interp::comp;
use crate::interp::flow::Run;
use crate::interp::groups::g_name;
use crate::interp::order::Cx;
use crate::interp::words::{gb, Words};
use crate::machine::Dialect;

/// Plane, nose-radius compensation, length offsets, work offsets, path mode.
const PLANE_COMP_OFFSET_CODES: u128 = gb(170)
    | gb(180)
    | gb(190)
    | gb(400)
    | gb(410)
    | gb(420)
    | gb(411)
    | gb(421)
    | gb(430)
    | gb(431)
    | gb(540)
    | gb(550)
    | gb(560)
    | gb(570)
    | gb(580)
    | gb(590)
    | gb(640);

impl Run<'_> {
    /// Before step 1 (Fanuc): G7.1 takes the cylinder's radius from its C word
    /// (`cylindrical.rs`). Touches the cylindrical-interpolation mode.
    pub(crate) fn convert_cylindrical(&mut self, b: &Block, w: &mut Words) {
        if self.machine.dialect == Dialect::Fanuc && w.ng > 0 {
            if let Some(at) = w.find_g(71).or(w.find_g(1070)) {
                let g40 = w.has_g(400);
                self.cylindrical_code(b, w, at, g40);
            }
        }
    }

    /// Step 7: plane (group 2), polar interpolation (21), compensation (7), length offset (8),
    /// work coordinate system (12), path mode (13). Touches `modal.plane_xz`/`plane_xy`, the
    /// polar mode, the compensation stage, program zero (G54–G59); sets
    /// [`Cx::plane_error_here`]. Order: LinuxCNC's "set active plane", "cutter radius
    /// compensation", "cutter length compensation", "coordinate system selection", "set path
    /// control mode", in that order.
    pub(crate) fn convert_plane_and_comp(&mut self, b: &Block, w: &mut Words, cx: &mut Cx) {
        let fanuc = cx.fanuc;
        // LinuxCNC lathe programs select G17 to drill along Z (src/interp/cycles/lcnc_drill.rs).
        // A machine with a Y axis has all three planes.
        let has_y = self.has_y_axis();
        let g17_ok = !fanuc || has_y;
        cx.plane_error_here = !has_y && ((w.g(170) && !g17_ok) || w.g(190));
        if fanuc && w.ng > 0 {
            // Polar coordinate interpolation (`polar.rs`).
            if let Some(at) = w.find_g(121).or(w.find_g(1120)) {
                self.polar_start(b, at);
            }
            if let Some(at) = w.find_g(131).or(w.find_g(1130)) {
                self.polar_stop(b, at, w.has_g(400));
            }
        }
        if w.any_g(PLANE_COMP_OFFSET_CODES) {
            let refused = if has_y {
                None
            } else if g17_ok {
                w.has_g(190)
            } else {
                w.has_g(170).or(w.has_g(190))
            };
            if let Some(at) = refused {
                self.error(b, Some(at), "only the XZ plane (G18) exists on a 2-axis lathe".into());
                self.modal.plane_xz = false;
                self.modal.plane_xy = false;
            } else if w.g(170) && self.modal.plane_xz && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                // rs274ngc refuses a change of plane while compensation is on.
                self.error(
                    b,
                    w.has_g(170),
                    "G17 cannot change the plane with nose radius compensation on: cancel it with G40 first".into(),
                );
            } else if w.g(190)
                && has_y
                && !self.modal.plane_xy
                && self.modal.plane_xz
                && self.comp.as_ref().is_some_and(|c| c.is_on())
            {
                self.error(
                    b,
                    w.has_g(190),
                    "G19 cannot change the plane with nose radius compensation on: cancel it with G40 first".into(),
                );
            } else if w.g(170) {
                self.modal.plane_xz = false;
                self.modal.plane_xy = true;
            } else if w.g(190) {
                self.modal.plane_xz = false;
                self.modal.plane_xy = false;
            }
            if w.g(180) {
                self.modal.plane_xz = true;
                self.modal.plane_xy = false;
            }
            if let Some(at) = w.has_g(400) {
                self.comp_off(b, at);
            }
            for code in [410u16, 420, 411, 421] {
                if let Some(at) = w.has_g(code) {
                    self.comp_on(b, w, code, at);
                }
            }
            if w.g(430) {
                w.get(b'H');
            }
            if let Some(at) = w.has_g(431) {
                self.unsupported(
                    b,
                    Some(at),
                    "G43.1 dynamic tool length offset is not modelled".into(),
                    true,
                );
            }
            for code in [540u16, 550, 560, 570, 580, 590] {
                if let Some(at) = w.has_g(code) {
                    self.select_work_offset(b, code, at);
                }
            }
            if w.g(640) {
                w.get(b'P');
                w.get(b'Q');
            }
        }
    }

    /// G40: compensation off (the next move leaves the offset).
    fn comp_off(&mut self, b: &Block, at: u32) {
        if self.contour_comp_engaged() {
            self.contour_comp_off(b, at);
            return;
        }
        if self.comp.is_none() && self.cycles.profile_comp.is_none() {
            return;
        }
        self.comp_word(b, at, comp::Word::Off);
    }

    /// A G41/G42/G40 word to the compensation stage, or, while a Fanuc stock-removal cycle reads
    /// its profile, to the cycle (`cycles::ProfileComp`): roughing drops it, G70 has it replayed
    /// at its move (`run_cycle`).
    fn comp_word(&mut self, b: &Block, at: u32, word: comp::Word) {
        if let Some(words) = self.cycles.profile_comp.as_mut() {
            words.push(crate::interp::cycles::ProfileComp {
                at: self.moves.len(),
                word,
            });
            return;
        }
        let c = self.comp.get_or_insert_with(Default::default);
        if let Err(msg) = c.word(word, &mut self.moves) {
            self.error(b, Some(at), msg);
        }
    }

    /// G41/G42 (the radius and tip direction of the tool: the active one, or LinuxCNC's D
    /// tool), LinuxCNC G41.1/G42.1 (D the diameter, L the tip direction).
    fn comp_on(&mut self, b: &Block, w: &mut Words, code: u16, at: u32) {
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let side = if code == 410 || code == 411 {
            comp::Side::Left
        } else {
            comp::Side::Right
        };
        let (radius, dir) = if code == 411 || code == 421 {
            let d = w.get(b'D');
            let l = w.get(b'L');
            let Some(d) = d else {
                self.error(b, Some(at), format!("{} needs D, the tool diameter", g_name(code)));
                return;
            };
            let dir = match l {
                None => 0,
                Some(l) if l.fract() == 0.0 && (0.0..=9.0).contains(&l) => l as u8,
                Some(l) => {
                    self.error(
                        b,
                        w.at(b'L'),
                        format!("L{l}: the tip direction must be a whole number from 0 to 9"),
                    );
                    return;
                }
            };
            (d / 2.0 * self.scale(), dir)
        } else {
            let station = if !fanuc && w.peek(b'D') {
                let d = w.get(b'D').unwrap_or(0.0);
                if d.fract() != 0.0 || d < 0.0 {
                    self.error(
                        b,
                        w.at(b'D'),
                        format!("D{d}: {} takes a tool number in D", g_name(code)),
                    );
                    return;
                }
                if d > 0.0 && self.machine.tool(d as u32).is_none() {
                    self.error(
                        b,
                        w.at(b'D'),
                        format!("D{d}: the machine file has no tool {d} to take the nose radius from"),
                    );
                    return;
                }
                d as u32
            } else {
                self.station
            };
            let tool = self.machine.tool(station);
            (tool.map_or(0.0, |t| t.nose_radius), tool.map_or(0, |t| t.tip_direction))
        };
        if matches!(code, 410 | 420) {
            // In a contour mode the contour is offset in the mode's plane before the transform
            // (`contour_comp.rs`).
            let plane = if self.polar_on() {
                Some(crate::interp::contour_comp::Plane::Polar)
            } else {
                self.cylindrical().map(crate::interp::contour_comp::Plane::Cylinder)
            };
            if let Some(plane) = plane {
                self.contour_comp_on(b, code == 410, &g_name(code), at, plane);
                return;
            }
        }
        if !self.modal.plane_xz && dir != 0 && dir != 9 {
            self.error(
                b,
                Some(at),
                format!("{} with a lathe tip direction needs the XZ plane (G18)", g_name(code)),
            );
            return;
        }
        let style = if fanuc { comp::Style::Fanuc } else { comp::Style::Rs274 };
        let tip = comp::tip_vector(dir, radius.abs(), fanuc, self.machine.turret_side);
        // (Fanuc switches sides or tools without G40: a new start-up from where the tool is.)
        let word = comp::Word::On {
            side,
            radius,
            tip,
            style,
            unit: self.scale(),
        };
        self.comp_word(b, at, word);
    }
}
