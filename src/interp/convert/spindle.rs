//! Step 3 of the order of execution: the spindle speed S, constant surface speed (G96/G97,
//! group 14) and its clamp (Fanuc G50 S / system B G92 S, LinuxCNC G96 D); and the spindle state
//! a move carries, with the warning for a surface speed the machine's `max_rpm` holds back.
//! The spindle's direction is an M code (step 5).

use crate::gcode::Block;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::{gb, Words};
use crate::interp::{Move, MoveKind, Spindle, SpindleSpeed};
use crate::machine::Dialect;

/// G96/G97: constant surface speed on and off.
const SPINDLE_CODES: u128 = gb(960) | gb(970);

impl Run<'_> {
    /// Step 3: spindle speed and mode (G96/G97, group 14). Touches `modal.s`,
    /// `modal.spindle_css`, `modal.css_clamp`. Order: LinuxCNC's "set spindle speed", after the
    /// feed and before the tool.
    pub(crate) fn convert_spindle(&mut self, b: &Block, w: &mut Words, cx: &Cx) {
        let Cx { fanuc, axis, .. } = *cx;
        if w.peek(b'S') || w.any_g(SPINDLE_CODES) {
            let clamp_block = fanuc && (w.g(500) || w.g(920)) && !axis;
            // `S2000 M13`: the S is the live tool's speed, not the main spindle's.
            let live_s = self.live_start_takes_s(w, w.m_codes());
            if let Some(s) = w.peek(b'S').then(|| w.get(b'S')).flatten() {
                if !s.is_finite() {
                    self.error(b, w.at(b'S'), format!("spindle speed S{s} is not a finite number"));
                } else if s < 0.0 {
                    self.error(b, w.at(b'S'), format!("negative spindle speed S{s}"));
                } else if clamp_block {
                    self.modal.css_clamp = Some(s);
                } else if !live_s {
                    self.modal.s = s;
                }
            }
            if w.g(960) {
                self.modal.spindle_css = true;
                if !fanuc {
                    if let Some(dv) = w.get(b'D') {
                        self.modal.css_clamp = Some(dv);
                    }
                }
            }
            if w.g(970) {
                self.modal.spindle_css = false;
            }
            // A speed in rpm above the machine's limit: the control holds it at max_rpm.
            let max = self.machine.max_rpm;
            if w.peek(b'S') && !clamp_block && !live_s && !self.modal.spindle_css && self.modal.s > max {
                let msg = format!(
                    "spindle speed S{} is above the machine's max_rpm ({max} rpm): the spindle runs at {max} rpm",
                    self.modal.s
                );
                self.warn_once(b, w.at(b'S'), msg);
            }
        }
    }

    pub(crate) fn spindle(&self) -> Spindle {
        let max = self.machine.max_rpm;
        let clamp = self.modal.css_clamp.map_or(max, |c| c.min(max));
        let speed = if self.modal.spindle_css {
            // Surface speed: m/min, or ft/min in inch mode.
            let v = if self.modal.inch {
                self.modal.s * 0.3048
            } else {
                self.modal.s
            };
            SpindleSpeed::Css {
                m_per_min: v,
                max_rpm: clamp,
            }
        } else {
            SpindleSpeed::Rpm(self.modal.s.min(max))
        };
        Spindle {
            dir: self.spindle_dir,
            speed,
        }
    }

    /// A feed move under constant surface speed that would need more than the machine's
    /// `max_rpm` somewhere (near the axis) while the program set no lower limit (Fanuc G50 S,
    /// LinuxCNC G96 D): the control holds the spindle at `max_rpm`; a warning at the move's line.
    #[cold]
    pub(crate) fn css_above_max_rpm(&mut self, b: &Block, m: &Move, spindle: &Spindle) {
        let max = self.machine.max_rpm;
        if self.modal.css_clamp.is_some_and(|c| c <= max) {
            return;
        }
        let SpindleSpeed::Css { m_per_min, .. } = spindle.speed else {
            return;
        };
        if m_per_min.is_nan() || m_per_min <= 0.0 {
            return; // no speed at all: the timing reports that move
        }
        // The smallest radius on the move (an arc is sampled; a sign change means the axis).
        let mut r_min = f64::INFINITY;
        let mut prev_x = m.start.x;
        let pieces = if matches!(m.kind, MoveKind::Arc { .. }) { 32 } else { 1 };
        for k in 0..=pieces {
            let x = m.point_at(k as f64 / pieces as f64).x;
            r_min = if prev_x * x <= 0.0 { 0.0 } else { r_min.min(x.abs()) };
            prev_x = x;
        }
        let needed = m_per_min * 1000.0 / (2.0 * std::f64::consts::PI * r_min);
        if needed <= max {
            return;
        }
        let msg = format!(
            "constant surface speed S{} needs more than the machine's max_rpm ({} rpm) on this move: the spindle is held at {} rpm (set a lower limit with {})",
            self.modal.s,
            max,
            max,
            if self.machine.dialect == Dialect::Fanuc { "G50 S" } else { "G96 D" }
        );
        self.warn_once(b, None, msg);
    }
}
