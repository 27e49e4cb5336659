//! Step 9 of the order of execution: motion (group 1: G0–G3, Fanuc G32 and LinuxCNC G33, the
//! canned cycles; Fanuc's G80 in group 9 here), as G53 may modify it. The motion code becomes the
//! modal motion; the axis words a non-motion code did not take (steps 6 and 8) make the move:
//! a line, an arc (from R or I/K), a thread, the next hole of a modal cycle, or a move in the
//! polar or cylindrical mode. A canned cycle is handed over through `cycle.rs` (the cycle's words
//! as plain data, compensation standing aside); its passes are ordinary moves.

use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::arc::{arc_from_center, arc_from_radius};
use crate::interp::block::in_range;
use crate::interp::cycles;
use crate::interp::flow::Run;
use crate::interp::groups::g_name;
use crate::interp::letters::Letters;
use crate::interp::order::Cx;
use crate::interp::state::Motion;
use crate::interp::words::Words;
use crate::interp::{Feed, MoveKind};
use crate::machine::Dialect;
use std::ops::ControlFlow;

impl Run<'_> {
    /// Step 9: the motion code (group 1; Fanuc's G80 group 9 here) and the move of the axis
    /// words. Touches `modal.motion` and makes the block's moves. Order: LinuxCNC's "perform
    /// motion, as modified (possibly) by G53", after every modal setting of the block. `Break` when a canned cycle ran (the block is done) or a motion
    /// code latheguard does not model stopped the block (reported).
    pub(crate) fn convert_motion(&mut self, b: &Block, w: &mut Words, cx: &Cx) -> ControlFlow<()> {
        let Cx {
            fanuc,
            axis,
            unknown,
            motion_code,
            ..
        } = *cx;
        if let Some((code, at)) = motion_code {
            match code {
                0 => self.modal.motion = Some(Motion::Rapid),
                10 => self.modal.motion = Some(Motion::Line),
                20 => self.modal.motion = Some(Motion::ArcCw),
                30 => self.modal.motion = Some(Motion::ArcCcw),
                320 | 330 => self.modal.motion = Some(Motion::Thread),
                800 => self.modal.motion = None,
                // Canned cycles latheguard expands (src/interp/cycles): the cycle sets the modes.
                _ if self.run_cycle(b, w, code, at) => return ControlFlow::Break(()),
                _ => {
                    let what = match code {
                        700..=760 => "lathe canned cycle",
                        810..=890 => "drilling cycle",
                        900 | 920 | 940 => "turning/threading/facing box cycle",
                        331 => "rigid tapping",
                        _ => "motion code",
                    };
                    self.unsupported(
                        b,
                        Some(at),
                        format!(
                            "{} ({what}) is not modelled yet: its moves are not checked",
                            g_name(code)
                        ),
                        true,
                    );
                    self.modal.motion = None;
                    return ControlFlow::Break(());
                }
            }
        }
        if fanuc && motion_code.is_none() && w.g(800) {
            // Fanuc G80 (group 9 here) cancels the drilling cycle only: the group-01 motion it
            // ran over (G0 or G1, usually) is in force again, so `X… Z…` after it moves.
            // A box cycle (G90/G92/G94) ends with no motion mode, as before.
            self.modal.motion = match self.modal.motion {
                Some(m) if m.is_drilling() => self.modal.group1.filter(|g| !matches!(g, Motion::Cycle(_))),
                Some(Motion::Cycle(_)) => None,
                m => m,
            };
        }
        let g53 = w.has_g(530);
        if unknown && axis {
            // An unknown code may be the one that uses the axis words: do not guess a motion.
        } else if (axis || w.peek(b'Y')) && !cx.axes_taken {
            // (`axis` counts the machine's extra-axis words.)
            let before = self.reports;
            self.motion(b, w, g53.is_some(), cx.plane_error_here);
            if self.reports > before {
                // The move was refused: its words are accounted for by that finding.
                w.used = w.has;
            } else if self.cycles.profile_corners.is_some() && (w.peek(b'A') || w.peek(b'C')) {
                // A LinuxCNC G7x profile: A and C round or bevel the corner after this move.
                cycles::lcnc_rough::corner_words(self, b, w);
            }
        } else if let Some(at) = g53 {
            // A G53 block with no axis word: Fanuc runs it as a one-shot with nothing to move
            // (posts write it alone before a tool change); rs274ngc refuses it (G53 needs G0 or
            // G1, and a motion needs an axis word).
            if !axis && self.machine.dialect != Dialect::Fanuc {
                self.error(b, Some(at), "G53 without axis words".into());
            }
        }
        ControlFlow::Continue(())
    }

    /// The lead of a Fanuc G32 block without F or E: the modal F, with a warning when the block
    /// gives its lead as K (a LinuxCNC G33 word) and the two differ.
    fn modal_lead(&mut self, b: &Block, w: &mut Letters) -> Option<f64> {
        let f = self.modal.feed;
        if let Some(k) = w.get(b'K') {
            if f > 0.0 && (k - f).abs() > 1e-12 {
                self.warn_once(
                    b,
                    w.at(b'K'),
                    format!(
                        "G32 takes its lead from F, not K (LinuxCNC's G33 word): this thread is cut at the modal F{} as its lead, not K{}",
                        crate::tooling::fmt_mm(f),
                        crate::tooling::fmt_mm(k)
                    ),
                );
            }
        }
        (f > 0.0).then_some(f)
    }

    /// Target programmed point of the axis words (X/Z absolute or incremental, U/W incremental).
    pub(crate) fn target(&mut self, b: &Block, w: &mut Letters) -> Option<P2> {
        let cur = self.programmed();
        let origin = self.origin();
        let s = self.scale();
        // U and W are incremental X and Z on Fanuc, and in a LinuxCNC G70-G72 profile (LinuxCNC's
        // own `g71-endless-loop_2` test: `W-5` then `U0.5`); elsewhere LinuxCNC's U and W are axes.
        let incremental_uw = self.machine.dialect == Dialect::Fanuc || self.cycles.profile_corners.is_some();
        let mut x = cur.x;
        let mut z = cur.y;
        let (xw, uw) = (w.peek(b'X'), incremental_uw && w.peek(b'U'));
        let (zw, ww) = (w.peek(b'Z'), incremental_uw && w.peek(b'W'));
        if xw && uw {
            self.error(b, w.at(b'U'), "X and U in one block".into());
            return None;
        }
        if zw && ww {
            self.error(b, w.at(b'W'), "Z and W in one block".into());
            return None;
        }
        if let Some(v) = w.get(b'X') {
            let r = self.to_radius(v) * s;
            x = if self.modal.incremental {
                cur.x + r
            } else {
                origin.x + r
            };
        }
        if uw {
            let v = w.get(b'U').unwrap_or(0.0);
            x = cur.x + self.to_radius(v) * s;
        }
        if let Some(v) = w.get(b'Z') {
            z = if self.modal.incremental {
                cur.y + v * s
            } else {
                origin.y + v * s
            };
        }
        if ww {
            z = cur.y + w.get(b'W').unwrap_or(0.0) * s;
        }
        if let Some(y) = (!self.has_y_axis()).then(|| w.get(b'Y')).flatten() {
            if y != 0.0 {
                self.error(b, w.at(b'Y'), format!("Y{y}: this lathe has no Y axis"));
                return None;
            }
            // rs274ngc reads Y on any machine and a lathe without a Y joint does not move for
            // it: Y0 is simply where it is. A Fanuc 2-axis control has no Y address at all.
            if !self.y_reported && self.machine.dialect != Dialect::Linuxcnc {
                self.y_reported = true;
                self.unsupported(
                    b,
                    w.at(b'Y'),
                    "Y0: a 2-axis lathe has no Y axis; Y0 words are ignored (reported once)".into(),
                    false,
                );
            }
        }
        if !in_range(P2::new(x, z)) {
            self.error(b, None, "the target point is out of any range".into());
            return None;
        }
        Some(P2::new(x, z))
    }

    pub(crate) fn motion(&mut self, b: &Block, w: &mut Words, g53: bool, plane_error_here: bool) {
        if self.polar_on() && !g53 {
            self.polar_motion(b, w);
            return;
        }
        if let Some(r) = self.cylindrical().filter(|_| !g53) {
            self.cylindrical_motion(b, w, r);
            return;
        }
        if let (Some(Motion::Cycle(code)), false) = (self.modal.motion, g53) {
            // A later block of a modal cycle: the cycle again with the new words.
            let mut cw = super::cycle::cycle_words(w, code, 0);
            let ran = cycles::repeat(self, b, &mut cw);
            w.letters = cw.letters;
            if ran {
                return;
            }
        }
        let Some(mut end) = self.target(b, w) else {
            return;
        };
        let Some(extra_end) = self.extra_end(b, w, g53) else {
            return;
        };
        let start = self.programmed();
        if g53 {
            // G53: machine coordinates: the turret reference point goes to machine zero
            // (`axes.machine_zero`, by default home as on Fanuc and Haas lathes) + the values.
            let tip = self.tip();
            let home = self.machine.machine_zero;
            let s = self.scale();
            let mut r = self.reference;
            if let Some(v) = w.peek(b'X').then(|| self.val(w, b'X')) {
                r.x = home.x + self.to_radius(v) * s;
            }
            if let Some(v) = w.peek(b'Z').then(|| self.val(w, b'Z')) {
                r.y = home.y + v * s;
            }
            end = r + tip;
        }
        let straight = !matches!(self.modal.motion, Some(Motion::ArcCw | Motion::ArcCcw));
        let has_y = self.has_y_axis();
        if let Some(e) = extra_end {
            self.set_pending(e, None);
        }
        if self.modal.plane_xy && !straight && !has_y {
            self.unsupported(
                b,
                None,
                "an arc in the XY plane (G17) leaves the lathe's XZ plane and is not modelled: select G18".into(),
                true,
            );
            w.used = w.has;
            return;
        }
        if !self.modal.plane_xz && !self.modal.plane_xy && !has_y {
            if !plane_error_here {
                self.error(b, None, "motion in the G17/G19 plane is not checked: select G18".into());
            } else {
                w.used = w.has;
            }
            return;
        }
        let motion = match self.modal.motion {
            Some(m) => m,
            None => {
                if !self.motion_reported {
                    self.motion_reported = true;
                    self.error(
                        b,
                        None,
                        "axis words but no motion mode in force (no G0/G1 given yet, or G80); assuming G1 from here"
                            .into(),
                    );
                }
                self.modal.motion = Some(Motion::Line);
                Motion::Line
            }
        };
        let motion = if g53 && motion != Motion::Line {
            Motion::Rapid
        } else {
            motion
        };
        match motion {
            // A cycle its family declined (reported there), or a G53 block under a cycle: no move.
            Motion::Cycle(_) => {}
            Motion::Rapid => {
                self.push_move(b, MoveKind::Rapid, start, end, Feed::Rapid);
            }
            Motion::Line => {
                let Some(feed) = self.feed(b) else { return };
                self.push_move(b, MoveKind::Line, start, end, feed);
            }
            Motion::Thread => {
                let fanuc = self.machine.dialect == Dialect::Fanuc;
                let lead = if fanuc {
                    match w.get(b'F').or(w.get(b'E')) {
                        Some(l) => Some(l),
                        // No F or E: the lead is the F register's value (one register for feed
                        // and lead, modal), as a Fanuc or a Haas cuts it. A K there is LinuxCNC's
                        // G33 lead word, which a Fanuc G32 does not read: the thread comes out
                        // at the modal F, not at K.
                        None => self.modal_lead(b, w),
                    }
                } else {
                    w.get(b'K')
                };
                let Some(lead) = lead.filter(|l| *l > 0.0) else {
                    self.error(
                        b,
                        None,
                        format!("threading move needs its lead ({} word)", if fanuc { "F" } else { "K" }),
                    );
                    return;
                };
                self.push_move(b, MoveKind::Line, start, end, Feed::PerRev(lead * self.scale()));
            }
            Motion::ArcCw | Motion::ArcCcw => {
                // G2 turns from +X toward +Z: counter-clockwise in (x right, z up).
                let ccw = motion == Motion::ArcCw;
                let Some(feed) = self.feed(b) else { return };
                let turns = match w.get(b'P') {
                    Some(p) if p >= 1.0 && p.fract() == 0.0 && p <= 1000.0 => p as u32,
                    Some(p) => {
                        self.error(
                            b,
                            w.at(b'P'),
                            format!("P{p}: the number of turns must be a whole number from 1 to 1000"),
                        );
                        return;
                    }
                    None => 1,
                };
                if has_y && !self.modal.plane_xz {
                    let e = extra_end.unwrap_or([0.0; 4]);
                    self.plane_arc(b, w, motion, start, end, e, feed, turns);
                    return;
                }
                let tol = self.arc_tolerance();
                let s = self.scale();
                let has_r = w.peek(b'R');
                let has_ik = w.peek(b'I') || w.peek(b'K');
                if has_r && has_ik {
                    self.error(b, w.at(b'R'), "an arc takes R or I/K, not both".into());
                    return;
                }
                if w.peek(b'J') {
                    return; // reported as unused
                }
                let result = if has_r {
                    let r = w.get(b'R').unwrap_or(0.0) * s;
                    arc_from_radius(start, end, r, ccw, turns, tol)
                } else if has_ik {
                    let i = w.get(b'I').unwrap_or(0.0) * s;
                    let k = w.get(b'K').unwrap_or(0.0) * s;
                    let center = if self.modal.arc_incremental {
                        P2::new(start.x + i, start.y + k)
                    } else {
                        let o = self.origin();
                        P2::new(o.x + i, o.y + k)
                    };
                    arc_from_center(start, end, center, ccw, turns, tol).map(|sw| (center, sw))
                } else {
                    self.error(b, None, "an arc needs R or I/K".into());
                    return;
                };
                match result {
                    Ok((center, sweep)) => self.push_move(b, MoveKind::Arc { center, sweep }, start, end, feed),
                    Err(e) => self.error(b, None, e.to_string()),
                }
            }
        }
    }

    fn val(&self, w: &mut Letters, letter: u8) -> f64 {
        w.get(letter).unwrap_or(0.0)
    }
}
