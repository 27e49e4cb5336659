//! Expression and parameter evaluation (rs274ngc semantics).

use super::flow::Run;
use crate::gcode::{BinOp, Expr, ExprId, Func, Param, Value};

/// Deepest expression tree evaluated; deeper ones are an error, never a stack overflow.
const MAX_DEPTH: u32 = 400;

pub(crate) type EvalResult = Result<f64, String>;

impl Run<'_> {
    pub(crate) fn eval(&self, id: ExprId) -> EvalResult {
        if self.macro_b.is_some() {
            // Fanuc: a vacant value is 0 where a number is needed.
            return self.macro_eval(id).map(|v| v.unwrap_or(0.0));
        }
        let v = self.eval_at(id, 0)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err("the expression's value is not a finite number".into())
        }
    }

    /// A word's value; `None` when it is vacant (Fanuc: the word is as if absent).
    #[inline]
    pub(crate) fn word_value(&self, v: Value) -> Result<Option<f64>, String> {
        match v {
            Value::Num(x) => Ok(Some(x)),
            Value::Expr(e) if self.macro_b.is_some() => self.macro_eval(e),
            Value::Expr(e) => self.eval(e).map(Some),
        }
    }

    /// The right side of an assignment: as [`Run::eval`], but a vacant value (Fanuc) is kept, as
    /// [`crate::interp::macro_b::VACANT`].
    pub(crate) fn eval_assign(&self, id: ExprId) -> EvalResult {
        if self.macro_b.is_some() {
            return self.macro_eval(id).map(|v| v.unwrap_or(super::macro_b::VACANT));
        }
        self.eval(id)
    }

    fn eval_at(&self, id: ExprId, depth: u32) -> EvalResult {
        if depth > MAX_DEPTH {
            return Err(format!("expression nested deeper than {MAX_DEPTH} levels"));
        }
        let d = depth + 1;
        Ok(match *self.prog.expr(id) {
            Expr::Num(x) => x,
            Expr::Param(p) => self.param(p, d)?,
            Expr::Neg(a) => -self.eval_at(a, d)?,
            Expr::Not(a) => bool_f(self.eval_at(a, d)? == 0.0),
            Expr::Binary(op, a, b) => {
                let x = self.eval_at(a, d)?;
                let y = self.eval_at(b, d)?;
                binary(op, x, y)?
            }
            Expr::Func(f, a) => func(f, self.eval_at(a, d)?)?,
            Expr::Atan(y, x) => {
                let (y, x) = (self.eval_at(y, d)?, self.eval_at(x, d)?);
                y.atan2(x).to_degrees()
            }
            Expr::Exists(name) => bool_f(self.named(name).is_some()),
        })
    }

    /// Read a parameter.
    pub(crate) fn param(&self, p: Param, depth: u32) -> EvalResult {
        match p {
            Param::Numbered(n) => self.numbered(n),
            Param::Indirect(e) => {
                let n = self.eval_at(e, depth + 1)?;
                self.numbered(param_index(n)?)
            }
            Param::Named(name) => self
                .named(name)
                .ok_or_else(|| format!("named parameter #<{}> is not defined", self.prog.name(name))),
        }
    }

    fn numbered(&self, n: u32) -> EvalResult {
        if let Some(v) = self.system_param(n) {
            return Ok(v);
        }
        self.params.numbered.get(n as usize).copied().ok_or_else(|| {
            format!(
                "parameter #{n} does not exist (largest is #{})",
                self.params.numbered.len() - 1
            )
        })
    }

    /// A named parameter: a local of the current call, a global, or a predefined one.
    pub(crate) fn named(&self, name: crate::gcode::NameId) -> Option<f64> {
        let text = self.prog.name(name);
        if !text.starts_with('_') {
            if let Some(f) = self.frames.last() {
                return f.locals.get(&name).copied();
            }
            return self.params.global.get(&name).copied();
        }
        if let Some(v) = self.params.global.get(&name) {
            return Some(*v);
        }
        self.predefined(text)
    }

    /// Resolve `#n` (possibly computed) to an index.
    pub(crate) fn assign(&mut self, p: Param, value: f64) -> Result<(), String> {
        if self.macro_b.is_some() {
            return self.macro_assign(p, value);
        }
        match p {
            Param::Numbered(n) => self.set_numbered(n, value),
            Param::Indirect(e) => {
                let n = param_index(self.eval(e)?)?;
                self.set_numbered(n, value)
            }
            Param::Named(_) => self.assign_named(p, value),
        }
    }

    /// `#<name> = value`.
    pub(crate) fn assign_named(&mut self, p: Param, value: f64) -> Result<(), String> {
        match p {
            Param::Numbered(_) | Param::Indirect(_) => Err("not a named parameter".into()),
            Param::Named(name) => {
                let text = self.prog.name(name);
                if text.starts_with('_') {
                    if self.predefined(text).is_some() {
                        return Err(format!("#<{text}> is read-only"));
                    }
                    self.params.global.insert(name, value);
                } else if let Some(f) = self.frames.last_mut() {
                    f.locals.insert(name, value);
                } else {
                    self.params.global.insert(name, value);
                }
                Ok(())
            }
        }
    }

    fn set_numbered(&mut self, n: u32, value: f64) -> Result<(), String> {
        if self.system_param(n).is_some() {
            return Err(format!("parameter #{n} is read-only"));
        }
        match self.params.numbered.get_mut(n as usize) {
            Some(slot) if n > 0 => {
                *slot = value;
                Ok(())
            }
            _ => Err(format!("parameter #{n} does not exist")),
        }
    }

    /// Read-only numbered parameters computed from the state.
    fn system_param(&self, n: u32) -> Option<f64> {
        let (x, z) = self.position_params();
        Some(match n {
            5400 => self.station as f64,
            5410 => 2.0 * self.machine.tool(self.station).map_or(0.0, |t| t.nose_radius) / self.scale(),
            5420 => x,
            5421 => 0.0,
            5422 => z,
            5423..=5428 => 0.0,
            _ => return None,
        })
    }

    /// The current position as rs274 returns it in `#5420`/`#5422` and `#<_x>`/`#<_z>`: the
    /// programmed point in program coordinates and units, with X always a radius (rs274 gives
    /// the radius in G7 diameter mode too: `G7 G0 X10` reads back as 5).
    fn position_params(&self) -> (f64, f64) {
        let (x, z) = self.program_position();
        (if self.modal.diameter { x / 2.0 } else { x }, z)
    }

    fn predefined(&self, name: &str) -> Option<f64> {
        let m = &self.modal;
        let (x, z) = self.position_params();
        Some(match name {
            "_metric" => bool_f(!m.inch),
            "_imperial" => bool_f(m.inch),
            "_absolute" => bool_f(!m.incremental),
            "_incremental" => bool_f(m.incremental),
            "_lathe_diameter_mode" => bool_f(m.diameter),
            "_lathe_radius_mode" => bool_f(!m.diameter),
            "_x" => x,
            "_y" | "_a" | "_b" | "_c" | "_u" | "_v" | "_w" => 0.0,
            "_z" => z,
            "_spindle_on" => bool_f(self.spindle_dir != super::SpindleDir::Off),
            "_spindle_cw" => bool_f(self.spindle_dir == super::SpindleDir::Cw),
            "_current_tool" => self.station as f64,
            "_selected_tool" => match self.selected.unwrap_or(self.station) {
                super::convert::UNMAPPED => -1.0,
                t => f64::from(t),
            },
            "_feed" => m.feed,
            "_rpm" => m.s,
            "_value" => self.last_value,
            "_value_returned" => bool_f(self.value_returned),
            "_motion_mode" => match m.motion {
                Some(super::state::Motion::Rapid) => 0.0,
                Some(super::state::Motion::Line) => 10.0,
                Some(super::state::Motion::ArcCw) => 20.0,
                Some(super::state::Motion::ArcCcw) => 30.0,
                Some(super::state::Motion::Thread) => 330.0,
                Some(super::state::Motion::Cycle(code)) => f64::from(code),
                None => 800.0,
            },
            "_plane" => {
                if m.plane_xy {
                    170.0
                } else if m.plane_xz {
                    180.0
                } else {
                    190.0
                }
            }
            "_coord_system" => 540.0 + 10.0 * f64::from(self.coord_system),
            "_units_per_rev" | "_feed_per_rev" => bool_f(m.feed_per_rev),
            "_units_per_minute" => bool_f(!m.feed_per_rev),
            "_line" => self.current_line as f64,
            "_task" => 0.0,
            // The LinuxCNC version whose rs274 these rules follow (2.9).
            "_vmajor" => 2.0,
            "_vminor" => 9.0,
            "_ccomp" => match self.comp.as_ref().and_then(|c| c.side()) {
                None => 400.0,
                Some(super::comp::Side::Left) => 410.0,
                Some(super::comp::Side::Right) => 420.0,
            },
            "_spindle_css_mode" => bool_f(m.spindle_css),
            "_spindle_rpm_mode" => bool_f(!m.spindle_css),
            "_ijk_absolute_mode" => bool_f(!m.arc_incremental),
            "_inverse_time" => 0.0,
            "_call_level" => self.frames.len() as f64,
            "_remap_level" => 0.0,
            _ => return None,
        })
    }
}

pub(super) fn bool_f(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

fn param_index(v: f64) -> Result<u32, String> {
    whole_index(v, "parameter")
}

/// The number of a parameter or variable (`what`) from a value: whole within 1e-4, in `u32`.
pub(super) fn whole_index(v: f64, what: &str) -> Result<u32, String> {
    let r = v.round();
    if (v - r).abs() > 1e-4 || r < 0.0 || r > u32::MAX as f64 {
        return Err(format!("{what} number {v} is not a whole number in range"));
    }
    Ok(r as u32)
}

fn binary(op: BinOp, x: f64, y: f64) -> EvalResult {
    Ok(match op {
        BinOp::Pow => {
            if x < 0.0 && y.fract() != 0.0 {
                return Err(format!("{x} ** {y}: a negative number to a fractional power"));
            }
            x.powf(y)
        }
        BinOp::Mul => x * y,
        BinOp::Div => {
            if y == 0.0 {
                return Err("division by zero".into());
            }
            x / y
        }
        BinOp::Mod => {
            if y == 0.0 {
                return Err("MOD by zero".into());
            }
            x.rem_euclid(y.abs())
        }
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Eq => bool_f(x == y),
        BinOp::Ne => bool_f(x != y),
        BinOp::Gt => bool_f(x > y),
        BinOp::Ge => bool_f(x >= y),
        BinOp::Lt => bool_f(x < y),
        BinOp::Le => bool_f(x <= y),
        BinOp::And => bool_f(x != 0.0 && y != 0.0),
        BinOp::Or => bool_f(x != 0.0 || y != 0.0),
        BinOp::Xor => bool_f((x != 0.0) != (y != 0.0)),
    })
}

fn func(f: Func, x: f64) -> EvalResult {
    Ok(match f {
        Func::Abs => x.abs(),
        Func::Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("ACOS[{x}]: argument out of [-1, 1]"));
            }
            x.acos().to_degrees()
        }
        Func::Asin => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("ASIN[{x}]: argument out of [-1, 1]"));
            }
            x.asin().to_degrees()
        }
        Func::Cos => x.to_radians().cos(),
        Func::Sin => x.to_radians().sin(),
        Func::Tan => x.to_radians().tan(),
        Func::Exp => x.exp(),
        Func::Fix => x.floor(),
        Func::Fup => x.ceil(),
        Func::Round => x.round(),
        Func::Ln => {
            if x <= 0.0 {
                return Err(format!("LN[{x}]: argument must be positive"));
            }
            x.ln()
        }
        Func::Sqrt => {
            if x < 0.0 {
                return Err(format!("SQRT[{x}]: negative argument"));
            }
            x.sqrt()
        }
        // Read only by the Fanuc reader, evaluated in `macro_b`.
        Func::Bin | Func::Bcd => return Err("BIN and BCD are Fanuc macro B functions".into()),
    })
}
