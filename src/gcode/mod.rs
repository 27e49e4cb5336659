//! Reading G-code: physical lines → blocks of words with byte spans.
//!
//! Reading never fails: [`parse`] returns every block it could read and a `syntax` finding for
//! every problem, each with line and column. Values are not evaluated here: a word's value is a
//! number or an expression (`[…]`, `#1`, `#<name>`, `ABS[…]`) that the interpreter evaluates.
//!
//! Storage is flat for speed: words, expressions and assignments live in arenas and blocks hold
//! index ranges into them. A long program's blocks, words and assignments are held a window of
//! blocks at a time and read again from the source when needed (`window.rs`): take a block with
//! [`Program::block`], which gives a [`BlockRef`] with its words and assignments.
//!
//! # What the reader accepts
//!
//! The reference is LinuxCNC's rs274ngc, with the Fanuc program-number forms added. Choices where
//! the documented reading rules (docs/programs.md) are silent:
//!
//! - Lines end at LF, CRLF or a lone CR. A UTF-8 byte-order mark at the start of the file is
//!   skipped and is not counted in the columns of line 1 (editors do not show it).
//! - Spaces and tabs are dropped everywhere outside comments, also inside words, numbers,
//!   keywords and names: `X1 0.5` is `X10.5`, `G 0 1` is `G1`, `o100 end sub` is `endsub`,
//!   `#<z start>` is `#<zstart>`. No other byte counts as a blank (a form feed or a DOS end-of-file
//!   byte 0x1A is an error).
//! - Comments: `( … )` closes at the first `)` (`(a (b) c)` leaves ` c)` outside, an error whose
//!   message says comments do not nest); `;` hides the rest of the line. Comments may stand
//!   between words, not inside a value. Every `( … )` is kept in [`Program::comments`]. The first
//!   `(MSG,…)`, `(PRINT,…)` or `(DEBUG,…)` of a line (any case; blanks allowed before the keyword
//!   and the comma) gives [`Block::message`], and such a line is a block even with no words.
//! - Outside comments only ASCII is allowed.
//! - `%` must be the first non-blank byte; the rest of its line is read as usual (`%O1200`).
//!   `/` must come before everything but `%` and comments. `N` must come before every word,
//!   assignment and O-word (comments may precede it), holds only digits and fits a `u64`.
//! - An O-word must be the first word of its block, and only comments may follow its statement.
//!   `O123` or `:123` with no keyword is [`OOp::ProgramNumber`]; `o<name>` needs a keyword.
//!   Numbers are compared as numbers (`O0002` is `O2`). Call arguments are bracketed
//!   expressions.
//! - A value is an optional single sign and then a number, a parameter, `[expr]` or a function
//!   (`X--1` is an error; `X-#1` and `X-[1]` are negations). Parameter numbers may be written
//!   `#1.0`. Expressions have the rs274ngc operators, all left-associative (`2**3**2` is
//!   `(2**3)**2`); operator and function names are matched as in rs274ngc, by their letters, so
//!   `[1ltabs[2]]` is `1 LT ABS[2]`. There is no `NOT` (rs274ngc has none); [`Expr::Not`] is
//!   never produced by the reader. Brackets, functions and `#` indirections nest at most
//!   [`MAX_NESTING`] deep.
//! - Fanuc macro B is read only by [`parse_fanuc`], which the pipeline uses for machines of the
//!   Fanuc dialect; [`parse`] (LinuxCNC, and any caller that does not know the dialect) reads
//!   exactly as before and refuses those statements as syntax errors. One reader serves both: a
//!   flag turns on, and only on, what Fanuc adds, so no LinuxCNC line can read differently, and
//!   the fast path for plain lines declines every macro statement by itself (their keywords are a
//!   letter followed by a letter, never a plain word). [`parse_fanuc`] adds:
//!   - statements, first in their block after the N number: `GOTO n`, `IF [c] GOTO n`,
//!     `IF [c] THEN #i=…` (its assignments are the block's), `WHILE [c] DOm`, `DOm`, `ENDm`
//!     (m = 1, 2, 3), kept in [`Block::macro_stmt`]; only comments may follow them (assignments
//!     after `THEN`). None of their keywords can start a valid word (`GO`, `IF`, `WH`, `DO`, `EN`),
//!     so reading them first changes no other line;
//!   - the right side of `#i = …` is a whole expression without brackets (`#1 = #2 + 1`);
//!   - `BIN[…]`, `BCD[…]`, `POW[a,b]`, `ATAN[a,b]` (and `ATAN[a]/[b]`);
//!   - Fanuc priorities: `* / AND MOD` above `+ - OR XOR` above the comparisons.
//!
//!   Running them is `interp/macro_b.rs`; `docs/macro-b.md` lists what is read and run.
//! - Not read (syntax errors): Okuma and Philips variable syntax (`X=VAR+5`, `N1=…`).
//! - Not rejected here, left to the interpreter: repeated words, letters that no code uses,
//!   values out of range for their letter (`G1.5`).

mod expr;
mod lexer;
mod shape;
#[cfg(test)]
mod tests;
mod window;

use crate::finding::Finding;
use crate::source::Span;
use std::ops::Range;

pub use lexer::{parse, parse_fanuc, parse_windowed, MAX_NESTING};
pub use window::{BlockRef, Window, WINDOW_BLOCKS};

/// Index of an expression in [`Program::exprs`].
pub type ExprId = u32;
/// Index of a name in [`Program::names`].
pub type NameId = u32;

/// A whole program as read: its blocks (a window of them at a time, see `window.rs`: take them
/// with [`Program::block`] and [`Program::blocks`]), and what the reader found in all of it.
#[derive(Debug)]
pub struct Program<'s> {
    /// The source the blocks are read from (again, for a window that left the cache).
    pub(crate) src: &'s [u8],
    pub exprs: Vec<Expr>,
    /// Interned parameter and subroutine names, lower case, spaces removed.
    pub names: Vec<String>,
    /// `syntax` findings, in source order: at most [`crate::finding::MAX_FINDINGS`].
    pub errors: Vec<Finding>,
    /// The syntax findings not kept in `errors`.
    pub errors_left_out: crate::finding::LeftOut,
    /// Every `( … )` comment, in source order (also those on lines that produce no block), for
    /// reporters that echo comments (rs274ngc's `COMMENT(…)` canonical call). `;` comments are not
    /// kept.
    pub comments: Vec<Comment>,
    /// Physical lines in the source (LF, CRLF and lone CR end one; an empty source is one line).
    line_count: u32,
    store: window::Store,
}

impl Program<'_> {
    /// Physical lines in the source, as [`crate::source::lines`] cuts it.
    pub fn line_count(&self) -> u32 {
        self.line_count
    }

    pub fn expr(&self, id: ExprId) -> &Expr {
        &self.exprs[id as usize]
    }

    pub fn name(&self, id: NameId) -> &str {
        &self.names[id as usize]
    }
}

/// One physical line that holds something to execute (words, assignments, an O-word, `%`, `/`,
/// an N number, a `(MSG,…)`-style message) or that has a syntax error. Lines that hold only
/// comments or white space produce no block.
///
/// 40 bytes: a program holds one per line. What most blocks lack (assignments, an O-word, a
/// message) is in one box, [`Block::rare`]; the N number is a value and a flag ([`Block::n`]).
#[derive(Clone, Debug)]
pub struct Block {
    /// Physical 1-based line.
    pub line: u32,
    /// The line's bytes without terminator.
    pub span: Span,
    /// The N number when `has_n` (see [`Block::n`]).
    n: u64,
    pub words: Range<u32>,
    /// Assignments, O-word and message, when the block has any of them.
    pub rare: Option<Box<Rare>>,
    /// The block starts with `/` (skipped when block delete is on).
    pub block_delete: bool,
    /// The line starts with `%` (program start/end marker); what follows it is read as usual.
    pub percent: bool,
    /// The line had a syntax error; what could be read is kept, but the block is not executed.
    pub bad: bool,
    has_n: bool,
}

/// The parts of a block that most blocks lack.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Rare {
    /// Parameter assignments (`#1=…`), executed after the block's words are read.
    pub assigns: Range<u32>,
    pub oword: Option<OWord>,
    /// `(MSG,…)`, `(PRINT,…)`, `(DEBUG,…)`: the text after the comma.
    pub message: Option<Span>,
    /// A Fanuc macro B statement (only read by [`parse_fanuc`]).
    pub macro_stmt: Option<MacroStmt>,
}

/// A Fanuc macro B control statement. Its column is `at` (the byte offset of the keyword).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MacroStmt {
    pub op: MacroOp,
    pub at: u32,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MacroOp {
    /// `GOTO n` (n may be an expression).
    Goto(ExprId),
    /// `IF [cond] GOTO n`.
    IfGoto(ExprId, ExprId),
    /// `IF [cond] THEN #i = …`: the block's assignments run only when the condition holds.
    IfThen(ExprId),
    /// `WHILE [cond] DOm`, or `DOm` alone (`None`: loop without end), m = 1..3.
    Do(Option<ExprId>, u8),
    /// `ENDm`.
    End(u8),
}

impl Block {
    /// The N number, when the block has one.
    pub fn n(&self) -> Option<u64> {
        self.has_n.then_some(self.n)
    }

    /// The block's parameter assignments, as a range of its window's (see [`BlockRef::assigns`]).
    pub fn assigns(&self) -> Range<u32> {
        self.rare.as_ref().map_or(0..0, |r| r.assigns.clone())
    }

    pub fn oword(&self) -> Option<&OWord> {
        self.rare.as_ref().and_then(|r| r.oword.as_ref())
    }

    /// The text of the line's first `(MSG,…)`, `(PRINT,…)` or `(DEBUG,…)` after the comma.
    pub fn message(&self) -> Option<Span> {
        self.rare.as_ref().and_then(|r| r.message)
    }

    /// The block's Fanuc macro B statement, if any.
    pub fn macro_stmt(&self) -> Option<&MacroStmt> {
        self.rare.as_ref().and_then(|r| r.macro_stmt.as_ref())
    }
}

/// A `( … )` comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Comment {
    /// Physical 1-based line.
    pub line: u32,
    /// The text between the parentheses.
    pub text: Span,
}

/// One word: a letter and its value. (16 bytes: a program holds one for every word it has.)
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The value: a number (always finite), or a NaN that carries an [`ExprId`] (see
    /// [`Word::value`]).
    raw: f64,
    /// Byte offset of the letter.
    pub at: u32,
    /// Bytes from the letter to the end of the value, at most `u16::MAX` (a longer word, a huge
    /// expression, has its span cut there; its start is exact).
    pub len: u16,
    /// Upper-case ASCII letter.
    pub letter: u8,
    /// The number was written with a decimal point (Fanuc `decimal_point` rule). Always false
    /// for [`Value::Expr`].
    pub has_point: bool,
}

/// A quiet NaN; an expression id goes in its low 32 bits.
const EXPR_NAN: u64 = 0x7FF8_0000_0000_0000;

impl Word {
    pub fn new(letter: u8, value: Value, has_point: bool, span: Span) -> Word {
        let raw = match value {
            Value::Num(x) => {
                debug_assert!(x.is_finite());
                x
            }
            Value::Expr(id) => f64::from_bits(EXPR_NAN | id as u64),
        };
        Word {
            raw,
            at: span.start,
            len: (span.end - span.start).min(u16::MAX as u32) as u16,
            letter,
            has_point,
        }
    }

    pub fn value(&self) -> Value {
        if self.raw.is_nan() {
            Value::Expr(self.raw.to_bits() as u32)
        } else {
            Value::Num(self.raw)
        }
    }

    /// From the letter to the end of the value.
    pub fn span(&self) -> Span {
        Span {
            start: self.at,
            end: self.at + self.len as u32,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    Num(f64),
    Expr(ExprId),
}

/// `#target = value`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Assign {
    pub target: Param,
    pub value: ExprId,
    pub span: Span,
}

/// A parameter reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Param {
    /// `#123`
    Numbered(u32),
    /// `#[expr]`, `##1`
    Indirect(ExprId),
    /// `#<name>` (a leading `_` makes it global).
    Named(NameId),
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Expr {
    Num(f64),
    Param(Param),
    Neg(ExprId),
    Not(ExprId),
    Binary(BinOp, ExprId, ExprId),
    Func(Func, ExprId),
    /// `ATAN[y]/[x]`
    Atan(ExprId, ExprId),
    /// `EXISTS[#<name>]`
    Exists(NameId),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Pow,
    Mul,
    Div,
    Mod,
    Add,
    Sub,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Abs,
    Acos,
    Asin,
    Cos,
    Exp,
    Fix,
    Fup,
    Round,
    Ln,
    Sin,
    Sqrt,
    Tan,
    /// Fanuc `BIN[…]`: BCD → binary.
    Bin,
    /// Fanuc `BCD[…]`: binary → BCD.
    Bcd,
}

/// An O-word statement: LinuxCNC `o<name> sub`, `o100 while […]`, … or a Fanuc program number.
#[derive(Clone, Debug, PartialEq)]
pub struct OWord {
    pub name: OName,
    pub op: OOp,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum OName {
    Number(u32),
    Named(NameId),
}

#[derive(Clone, Debug, PartialEq)]
pub enum OOp {
    /// `O1234` or `:1234` alone: a Fanuc program or subprogram number.
    ProgramNumber,
    Sub,
    EndSub(Option<ExprId>),
    Call(Vec<ExprId>),
    Return(Option<ExprId>),
    Do,
    While(ExprId),
    EndWhile,
    If(ExprId),
    ElseIf(ExprId),
    Else,
    EndIf,
    Break,
    Continue,
    Repeat(ExprId),
    EndRepeat,
}
