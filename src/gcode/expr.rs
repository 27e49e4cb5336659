//! Values: numbers, parameters, bracketed expressions and functions.
//!
//! value   := [ '+' | '-' ] ( number | '#' param | '[' expr ']' | function )
//! number  := digits with at most one '.', at least one digit (no exponent: `E` is a word)
//! param   := digits | '#' param | '[' expr ']' | '<' name '>'
//! expr    := value { binop value }      binary operators are left-associative, lowest first:
//!            AND OR XOR · EQ NE GT GE LT LE · + - · * / MOD · **
//! function:= ABS ACOS ASIN COS EXP FIX FUP ROUND LN SIN SQRT TAN '[' expr ']'
//!          | ATAN '[' expr ']' '/' '[' expr ']' | EXISTS '[' '#' '<' name '>' ']'
//!
//!
//! Fanuc macro B ([`super::parse_fanuc`]) adds `BIN[…]`, `BCD[…]`, `POW[a,b]` and `ATAN[a,b]`, and
//! uses the Fanuc priorities (0i-F / 16i-T operator's manuals, "Custom macro", priority of
//! operations): functions, then `* / AND MOD`, then `+ - OR XOR`, then the comparisons; `**`
//! stays above `*`.
//!
//! Recursion only follows brackets, functions and `#` indirections, and stops with a syntax error
//! past [`MAX_NESTING`](super::MAX_NESTING) levels; within one bracket level the precedence
//! climbing recurses at most once per precedence level.

use super::lexer::{Error, Reader, Res};
use super::{BinOp, Expr, ExprId, Func, Param, Value, MAX_NESTING};

/// Exact powers of ten for the fast number path.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20,
    1e21, 1e22,
];

/// Mantissas up to this are exact in an f64.
const EXACT_MANTISSA: u64 = 1 << 53;

const FUNCS: [(&[u8], Func); 12] = [
    (b"abs", Func::Abs),
    (b"acos", Func::Acos),
    (b"asin", Func::Asin),
    (b"cos", Func::Cos),
    (b"exp", Func::Exp),
    (b"fix", Func::Fix),
    (b"fup", Func::Fup),
    (b"round", Func::Round),
    (b"ln", Func::Ln),
    (b"sin", Func::Sin),
    (b"sqrt", Func::Sqrt),
    (b"tan", Func::Tan),
];

/// Where a value is read, for messages.
#[derive(Clone, Copy)]
enum Ctx {
    /// After a word letter.
    Word(u8),
    /// After `=` of an assignment.
    Assign,
    /// An operand inside an expression.
    Operand,
}

impl Ctx {
    fn what(self) -> String {
        match self {
            Ctx::Word(letter) => format!("a value after {}", letter as char),
            Ctx::Assign => "a value after '='".into(),
            Ctx::Operand => "a number, a parameter, '[' or a function".into(),
        }
    }
}

/// A value as read: a plain number (with its `has_point`) or an expression.
enum Val {
    Num(f64, bool),
    Expr(ExprId),
}

/// The run of decimal digits at `i`: where it ends, and `mant` with its digits appended (wrapping
/// on overflow: callers bound the number of digits they accept).
#[inline(always)]
pub(super) fn digit_run(src: &[u8], mut i: usize, mut mant: u64) -> (usize, u64) {
    while let Some(&b) = src.get(i) {
        let d = b.wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        mant = mant.wrapping_mul(10).wrapping_add(d as u64);
        i += 1;
    }
    (i, mant)
}

/// The first offset at or after `i` that does not hold a space or a tab.
#[inline(always)]
pub(super) fn skip_blanks(src: &[u8], mut i: usize) -> usize {
    while matches!(src.get(i), Some(b' ' | b'\t')) {
        i += 1;
    }
    i
}

/// The usual number at `start`, read fast: at most 15 digits and one point, no blanks inside, and
/// then a byte that cannot continue it (blanks may: `X1 0.5` is `X10.5`, so they are looked past).
/// Returns the value, whether it has a point, and where it ends; `None` when the general reader
/// must decide.
#[inline(always)]
pub(super) fn plain_number(src: &[u8], start: usize) -> Option<(f64, bool, usize)> {
    let (end, x, point) = plain_value(src, start)?;
    if matches!(src.get(skip_blanks(src, end)), Some(b'0'..=b'9' | b'.')) {
        return None;
    }
    Some((x, point, end))
}

/// The digits of a plain number at `i` of `s`, without the look past blanks of
/// [`plain_number`]: where they end, the value (its mantissa exact, so one division rounds
/// correctly), and whether it has a point; `None` for no digits or more than 15.
#[inline(always)]
pub(super) fn plain_value(s: &[u8], start: usize) -> Option<(usize, f64, bool)> {
    let (mut i, mut mant) = digit_run(s, start, 0);
    let point = s.get(i) == Some(&b'.');
    let mut frac = 0;
    if point {
        let frac_start = i + 1;
        (i, mant) = digit_run(s, frac_start, mant);
        frac = i - frac_start;
    }
    let digits = i - start - point as usize;
    if !(1..=15).contains(&digits) {
        return None;
    }
    // At most 15 digits: the mantissa fits an i64, whose conversion is one instruction (a u64's
    // is several), and is exact either way.
    let m = mant as i64 as f64;
    let x = if frac == 0 { m } else { m / POW10[frac] };
    Some((i, x, point))
}

impl Reader<'_> {
    fn push(&mut self, e: Expr) -> ExprId {
        let id = self.expr_base + self.prog.exprs.len() as ExprId;
        self.prog.exprs.push(e);
        id
    }

    fn expr_of(&mut self, v: Val) -> ExprId {
        match v {
            Val::Num(x, _) => self.push(Expr::Num(x)),
            Val::Expr(id) => id,
        }
    }

    /// The value of a word whose letter was just read.
    #[inline]
    pub(super) fn value(&mut self, letter: u8) -> Res<(Value, bool)> {
        // Fast path for the common case, a number right after the letter.
        if let Some(b) = self.peek() {
            if b.is_ascii_digit() {
                let (x, point) = self.number()?;
                return Ok((Value::Num(x), point));
            }
            if b == b'-' && self.src[..self.end].get(self.pos + 1).is_some_and(u8::is_ascii_digit) {
                self.pos += 1;
                let (x, point) = self.number()?;
                return Ok((Value::Num(-x), point));
            }
        }
        Ok(match self.signed(Ctx::Word(letter))? {
            Val::Num(x, point) => (Value::Num(x), point),
            Val::Expr(id) => (Value::Expr(id), false),
        })
    }

    /// A signed value as an expression (a GOTO target); `what` names it in the error.
    pub(super) fn operand_expr(&mut self, what: &str) -> Res<ExprId> {
        match self.peek() {
            Some(b) if b.is_ascii_alphanumeric() || matches!(b, b'.' | b'#' | b'[' | b'+' | b'-') => {}
            _ => return Err(self.expected(self.pos, what)),
        }
        let v = self.signed(Ctx::Operand)?;
        Ok(self.expr_of(v))
    }

    /// The value of an assignment (after `=`), as an expression.
    pub(super) fn value_expr(&mut self) -> Res<ExprId> {
        if self.macro_b {
            // Fanuc: the right side is a whole expression (`#1 = #2 + 1`), no brackets needed.
            match self.peek() {
                Some(b) if b.is_ascii_alphanumeric() || matches!(b, b'.' | b'#' | b'[' | b'+' | b'-') => {}
                _ => return Err(self.expected(self.pos, &Ctx::Assign.what())),
            }
            return self.expr(1);
        }
        let v = self.signed(Ctx::Assign)?;
        Ok(self.expr_of(v))
    }

    /// An optional sign, then a number, a parameter, a bracketed expression or a function.
    fn signed(&mut self, ctx: Ctx) -> Res<Val> {
        let sign = match self.peek() {
            Some(s @ (b'+' | b'-')) => {
                self.pos += 1;
                Some(s)
            }
            _ => None,
        };
        let v = match sign {
            None => self.primary(ctx)?,
            Some(s) => {
                match self.peek() {
                    Some(b) if b.is_ascii_alphanumeric() || matches!(b, b'.' | b'#' | b'[') => {}
                    _ => {
                        let what = format!("a number, a parameter, '[' or a function after '{}'", s as char);
                        return Err(self.expected(self.pos, &what));
                    }
                }
                self.primary(Ctx::Operand)?
            }
        };
        Ok(match (sign, v) {
            (Some(b'-'), Val::Num(x, p)) => Val::Num(-x, p),
            (Some(b'-'), Val::Expr(id)) => Val::Expr(self.push(Expr::Neg(id))),
            (_, v) => v,
        })
    }

    fn primary(&mut self, ctx: Ctx) -> Res<Val> {
        let at = self.pos;
        match self.peek() {
            Some(b) if b.is_ascii_digit() || b == b'.' => {
                let (x, point) = self.number()?;
                Ok(Val::Num(x, point))
            }
            Some(b'#') => {
                self.pos += 1;
                let p = self.param()?;
                Ok(Val::Expr(self.push(Expr::Param(p))))
            }
            Some(b'[') => Ok(Val::Expr(self.bracketed()?)),
            Some(b) if b.is_ascii_alphabetic() => self.function(ctx).map(Val::Expr),
            _ => Err(self.expected(at, &ctx.what())),
        }
    }

    /// A number at the cursor (a digit or '.'), without sign.
    fn number(&mut self) -> Res<(f64, bool)> {
        if let Some((x, point, end)) = plain_number(&self.src[..self.end], self.pos) {
            self.pos = end;
            return Ok((x, point));
        }
        self.number_general()
    }

    /// Any number: blanks between digits, long mantissas, and the errors.
    #[cold]
    #[inline(never)]
    fn number_general(&mut self) -> Res<(f64, bool)> {
        let src = &self.src[..self.end];
        let start = self.pos;
        let mut i = start;
        let mut mant: u64 = 0;
        let mut exact = true;
        let mut digits = 0usize;
        let mut point: Option<usize> = None; // digits before the point
        let mut last = start;
        loop {
            match src.get(i) {
                Some(&b) if b.is_ascii_digit() => {
                    if mant < EXACT_MANTISSA / 10 {
                        mant = mant * 10 + (b - b'0') as u64;
                    } else {
                        exact = false;
                    }
                    digits += 1;
                    i += 1;
                    last = i;
                }
                Some(b'.') => {
                    if point.is_some() {
                        return Err(Error {
                            at: i,
                            msg: "number has two decimal points".into(),
                        });
                    }
                    point = Some(digits);
                    i += 1;
                    last = i;
                }
                Some(b' ' | b'\t') => i += 1,
                _ => break,
            }
        }
        let frac = point.map_or(0, |before| digits - before);
        let point = point.is_some();
        self.pos = last;
        if digits == 0 {
            return Err(Error {
                at: start,
                msg: "number has no digits (a '.' alone is not a number)".into(),
            });
        }
        if exact && frac < POW10.len() {
            // Both operands are exact, so the quotient is correctly rounded.
            let x = if frac == 0 {
                mant as f64
            } else {
                mant as f64 / POW10[frac]
            };
            return Ok((x, point));
        }
        self.scratch.clear();
        let text = &self.src[start..last];
        self.scratch.extend(text.iter().filter(|&&b| b != b' ' && b != b'\t'));
        let x = std::str::from_utf8(&self.scratch)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .unwrap_or(f64::INFINITY);
        if !x.is_finite() {
            return Err(Error {
                at: start,
                msg: "number is too large (not a finite value)".into(),
            });
        }
        Ok((x, point))
    }

    /// A parameter reference, the `#` already consumed.
    pub(super) fn param(&mut self) -> Res<Param> {
        let at = self.pos;
        match self.peek() {
            Some(b) if b.is_ascii_digit() || b == b'.' => {
                let (x, _) = self.number()?;
                if x.fract() != 0.0 || x > u32::MAX as f64 {
                    return Err(Error {
                        at,
                        msg: "a parameter number must be a whole number (at most 4294967295)".into(),
                    });
                }
                Ok(Param::Numbered(x as u32))
            }
            Some(b'#') => {
                self.nest(at)?;
                self.pos += 1;
                let inner = self.param()?;
                self.depth -= 1;
                Ok(Param::Indirect(self.push(Expr::Param(inner))))
            }
            Some(b'[') => Ok(Param::Indirect(self.bracketed()?)),
            Some(b'<') => Ok(Param::Named(self.name()?)),
            _ => Err(self.expected(at, "a parameter number, '#', '[' or '<name>' after '#'")),
        }
    }

    fn nest(&mut self, at: usize) -> Res<()> {
        self.depth += 1;
        if self.depth > MAX_NESTING {
            return Err(Error {
                at,
                msg: format!("value nested deeper than {MAX_NESTING} levels"),
            });
        }
        Ok(())
    }

    /// `[ expr ]` at the cursor (on the `[`).
    pub(super) fn bracketed(&mut self) -> Res<ExprId> {
        let open = self.pos;
        self.nest(open)?;
        self.pos += 1;
        let e = self.expr(1)?;
        match self.peek() {
            Some(b']') => self.pos += 1,
            None => {
                return Err(Error {
                    at: open,
                    msg: "unclosed '[': no ']' on its line".into(),
                });
            }
            Some(_) => return Err(self.expected(self.pos, "an operator or ']'")),
        }
        self.depth -= 1;
        Ok(e)
    }

    /// Binary operators of precedence `min_prec` and up, left-associative.
    fn expr(&mut self, min_prec: u8) -> Res<ExprId> {
        let v = self.signed(Ctx::Operand)?;
        let mut lhs = self.expr_of(v);
        while let Some((op, prec, end)) = self.binop() {
            if prec < min_prec {
                break;
            }
            self.pos = end;
            let rhs = self.expr(prec + 1)?;
            lhs = self.push(Expr::Binary(op, lhs, rhs));
        }
        Ok(lhs)
    }

    /// The binary operator at the cursor: operator, precedence (1 lowest), offset after it.
    fn binop(&mut self) -> Option<(BinOp, u8, usize)> {
        let (op, prec, end) = self.binop_rs274()?;
        if !self.macro_b {
            return Some((op, prec, end));
        }
        let prec = match op {
            BinOp::Pow => 5,
            BinOp::Mul | BinOp::Div | BinOp::And | BinOp::Mod => 4,
            BinOp::Add | BinOp::Sub | BinOp::Or | BinOp::Xor => 3,
            _ => 2,
        };
        Some((op, prec, end))
    }

    /// The binary operator at the cursor with its rs274ngc precedence.
    fn binop_rs274(&mut self) -> Option<(BinOp, u8, usize)> {
        let c = self.peek()?;
        let one = self.pos + 1;
        let op = match c.to_ascii_lowercase() {
            b'*' => {
                return Some(match self.match_kw(b"**") {
                    Some(end) => (BinOp::Pow, 5, end),
                    None => (BinOp::Mul, 4, one),
                })
            }
            b'/' => (BinOp::Div, 4, one),
            b'+' => (BinOp::Add, 3, one),
            b'-' => (BinOp::Sub, 3, one),
            b'a' => self.kw_op(b"and", BinOp::And, 1)?,
            b'o' => self.kw_op(b"or", BinOp::Or, 1)?,
            b'x' => self.kw_op(b"xor", BinOp::Xor, 1)?,
            b'e' => self.kw_op(b"eq", BinOp::Eq, 2)?,
            b'n' => self.kw_op(b"ne", BinOp::Ne, 2)?,
            b'g' => self
                .kw_op(b"gt", BinOp::Gt, 2)
                .or_else(|| self.kw_op(b"ge", BinOp::Ge, 2))?,
            b'l' => self
                .kw_op(b"lt", BinOp::Lt, 2)
                .or_else(|| self.kw_op(b"le", BinOp::Le, 2))?,
            b'm' => self.kw_op(b"mod", BinOp::Mod, 4)?,
            _ => return None,
        };
        Some(op)
    }

    fn kw_op(&self, kw: &[u8], op: BinOp, prec: u8) -> Option<(BinOp, u8, usize)> {
        self.match_kw(kw).map(|end| (op, prec, end))
    }

    /// A function call at the cursor (on a letter).
    fn function(&mut self, ctx: Ctx) -> Res<ExprId> {
        let at = self.pos;
        if self.macro_b {
            if let Some(f) = self.fanuc_function()? {
                return Ok(f);
            }
        }
        if let Some(end) = self.match_kw(b"atan") {
            self.pos = end;
            let y = self.func_arg("ATAN")?;
            if self.peek() != Some(b'/') {
                return Err(self.expected(self.pos, "'/' after ATAN[y] (the form is ATAN[y]/[x])"));
            }
            self.pos += 1;
            let x = self.func_arg("ATAN[y]/")?;
            return Ok(self.push(Expr::Atan(y, x)));
        }
        if let Some(end) = self.match_kw(b"exists") {
            self.pos = end;
            let form = "the form is EXISTS[#<name>]";
            if self.peek() != Some(b'[') {
                return Err(self.expected(self.pos, &format!("'[' after EXISTS ({form})")));
            }
            self.pos += 1;
            if self.peek() != Some(b'#') {
                return Err(self.expected(self.pos, &format!("'#' ({form})")));
            }
            self.pos += 1;
            if self.peek() != Some(b'<') {
                return Err(self.expected(self.pos, &format!("'<' ({form})")));
            }
            let name = self.name()?;
            if self.peek() != Some(b']') {
                return Err(self.expected(self.pos, &format!("']' ({form})")));
            }
            self.pos += 1;
            return Ok(self.push(Expr::Exists(name)));
        }
        for (kw, f) in FUNCS {
            if let Some(end) = self.match_kw(kw) {
                self.pos = end;
                let name = std::str::from_utf8(kw).unwrap_or("").to_ascii_uppercase();
                let arg = self.func_arg(&name)?;
                return Ok(self.push(Expr::Func(f, arg)));
            }
        }
        match ctx {
            Ctx::Word(_) => Err(self.expected(at, &ctx.what())),
            _ => {
                let mut i = at;
                let mut name = String::new();
                while let Some(&b) = self.src[..self.end].get(i) {
                    if b.is_ascii_alphabetic() && name.len() < 16 {
                        name.push(b.to_ascii_uppercase() as char);
                    } else if b != b' ' && b != b'\t' {
                        break;
                    }
                    i += 1;
                }
                Err(Error {
                    at,
                    msg: format!("unknown function '{name}' (expected ABS, ACOS, ASIN, ATAN, COS, EXISTS, EXP, FIX, FUP, LN, ROUND, SIN, SQRT or TAN)"),
                })
            }
        }
    }

    /// The Fanuc forms: `ATAN[a,b]` (and `ATAN[a]/[b]`), `POW[a,b]`, `BIN[…]`, `BCD[…]`; `None`
    /// (cursor unmoved) for any other name.
    fn fanuc_function(&mut self) -> Res<Option<ExprId>> {
        for (kw, f) in [(&b"bin"[..], Func::Bin), (b"bcd", Func::Bcd)] {
            if let Some(end) = self.match_kw(kw) {
                self.pos = end;
                let name = if f == Func::Bin { "BIN" } else { "BCD" };
                let arg = self.func_arg(name)?;
                return Ok(Some(self.push(Expr::Func(f, arg))));
            }
        }
        let (name, pow) = if let Some(end) = self.match_kw(b"pow") {
            self.pos = end;
            ("POW", true)
        } else if let Some(end) = self.match_kw(b"atan") {
            self.pos = end;
            ("ATAN", false)
        } else {
            return Ok(None);
        };
        if self.peek() != Some(b'[') {
            return Err(self.expected(self.pos, &format!("'[' after {name}")));
        }
        let open = self.pos;
        self.nest(open)?;
        self.pos += 1;
        let a = self.expr(1)?;
        let b = match self.peek() {
            Some(b',') => {
                self.pos += 1;
                let b = self.expr(1)?;
                if self.peek() != Some(b']') {
                    return Err(self.expected(self.pos, "an operator or ']'"));
                }
                self.pos += 1;
                Some(b)
            }
            Some(b']') => {
                self.pos += 1;
                None
            }
            None => {
                return Err(Error {
                    at: open,
                    msg: "unclosed '[': no ']' on its line".into(),
                })
            }
            Some(_) => return Err(self.expected(self.pos, "an operator, ',' or ']'")),
        };
        self.depth -= 1;
        let e = match (pow, b) {
            (true, Some(b)) => Expr::Binary(BinOp::Pow, a, b),
            (true, None) => return Err(self.expected(self.pos, "POW[a,b]: ',' and a second value")),
            (false, Some(b)) => Expr::Atan(a, b),
            (false, None) => {
                if self.peek() != Some(b'/') {
                    return Err(self.expected(self.pos, "'/' after ATAN[y] (the forms are ATAN[y]/[x] and ATAN[y,x])"));
                }
                self.pos += 1;
                let x = self.func_arg("ATAN[y]/")?;
                Expr::Atan(a, x)
            }
        };
        Ok(Some(self.push(e)))
    }

    /// The bracketed argument of a function.
    fn func_arg(&mut self, name: &str) -> Res<ExprId> {
        if self.peek() != Some(b'[') {
            return Err(self.expected(self.pos, &format!("'[' after {name}")));
        }
        self.bracketed()
    }
}
