//! The line reader: bytes → blocks. See the module docs of [`crate::gcode`].
//!
//! One [`Reader`] walks the physical lines given by [`crate::source::lines`] and reads each line in a
//! single left-to-right pass with a cursor that steps over spaces and tabs wherever it looks for
//! the next byte (rs274ngc removes them before reading, so `X1 0.5` is `X10.5`). Items are read
//! in place — no copy of the line, no per-line allocation — and pushed straight into the arenas of
//! the [`Program`]. The first problem on a line becomes one `syntax` finding; the rest of the line
//! is skipped. Values and expressions are read in `expr.rs`.

use super::expr::{digit_run, plain_value, skip_blanks};
use super::shape;
use super::window::{Mark, Store, Window, CACHED_WINDOWS, WINDOW_BLOCKS};
use super::{Assign, Block, Comment, Expr, NameId, OName, OOp, OWord, Program, Rare, Value, Word};
use crate::finding::{push_capped, Finding};
use crate::source::{after_terminator, count_lf, lines, lines_from, Span};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::rc::Rc;

/// How deep brackets, function calls and parameter indirections (`##1`) may nest in one value.
/// Deeper nesting is a syntax error (the reader never recurses further).
pub const MAX_NESTING: u32 = 64;

const BOM: &[u8] = b"\xEF\xBB\xBF";

/// Read a whole program. Never fails; problems become `syntax` findings in [`Program::errors`].
pub fn parse(src: &[u8]) -> Program<'_> {
    parse_with(src, true, false, WINDOW_BLOCKS)
}

/// Read a whole program of the Fanuc dialect: as [`parse`], and also the Fanuc macro B
/// statements (`GOTO`, `IF`, `WHILE … DO`, `END`), the functions `BIN`, `BCD`, `POW[a,b]`,
/// `ATAN[a,b]`, and the Fanuc operator priorities (see the module docs of [`crate::gcode`]).
pub fn parse_fanuc(src: &[u8]) -> Program<'_> {
    parse_with(src, true, true, WINDOW_BLOCKS)
}

/// [`parse`] (or, with `macro_b`, [`parse_fanuc`]) holding `per_window` blocks a window (at
/// least 1): the same blocks in less memory, read again more often where the program jumps far.
/// The setup reading holds a quarter of [`WINDOW_BLOCKS`] (`assume::reading`); the tests read
/// programs a block a window, so that every jump reads windows again.
pub fn parse_windowed(src: &[u8], macro_b: bool, per_window: usize) -> Program<'_> {
    parse_with(src, true, macro_b, per_window)
}

/// [`parse`] or [`parse_fanuc`], with or without the fast path for plain lines (tests compare
/// the two), `per_window` blocks a window.
pub(super) fn parse_with(src: &[u8], plain_lines_fast: bool, macro_b: bool, per_window: usize) -> Program<'_> {
    let per_window = per_window.max(1);
    // One pass over the lines reads each as it is found. No index of the lines is kept: a
    // window's mark keeps where its first line starts, and a column is counted back from its
    // offset to the line's start (`source::ColCursor`).
    let terminators = count_lf(src);
    let mut line_count = 0u32;
    let mut reader = Reader::new(src);
    reader.plain_lines_fast = plain_lines_fast;
    reader.macro_b = macro_b;
    // Most lines are blocks of a few words: reserving once saves the copies of growing (the
    // memory a reservation does not use is never touched, and is given back below).
    reader.prog.blocks.reserve((terminators + 1).min(per_window));
    // Words of real programs lie three or more bytes apart.
    reader
        .prog
        .words
        .reserve((src.len() / 3).min(per_window.saturating_mul(8)));
    let mut marks = vec![Mark {
        first_block: 0,
        line: 1,
        start: 0,
        expr_base: 0,
        rare: false,
    }];
    let mut kept: Vec<Rc<Window>> = Vec::new();
    let mut len = 0;
    // Blocks of the current window counted, not read: once the cache is full the windows read
    // are dropped, so a plain line there is only counted (`shape.rs`: it adds nothing else).
    let mut skimmed = 0;
    for (line, (line_start, end)) in (1u32..).zip(lines(src)) {
        line_count = line;
        let skim = plain_lines_fast && kept.len() == CACHED_WINDOWS;
        match skim.then(|| shape::plain_shape(&src[line_start..end])).flatten() {
            Some(block) => skimmed += block as usize,
            None => reader.read_line(line, line_start, end),
        }
        if reader.prog.blocks.len() + skimmed == per_window {
            // The window is full: keep it while the cache has room, and start the next.
            reader.mark_rare(&mut marks);
            len += per_window;
            if kept.len() < CACHED_WINDOWS {
                kept.push(Rc::new(reader.take_window(len - per_window, true)));
            } else {
                reader.prog.blocks.clear();
                reader.prog.words.clear();
                reader.prog.assigns.clear();
                skimmed = 0;
            }
            marks.push(Mark {
                first_block: len,
                line: line + 1,
                start: after_terminator(src, end).min(src.len()) as u32,
                expr_base: reader.prog.exprs.len() as u32,
                rare: false,
            });
        }
    }
    if reader.prog.blocks.len() + skimmed == 0 && marks.len() > 1 {
        // The last window ended on the last block.
        marks.pop();
    } else {
        reader.mark_rare(&mut marks);
        len += reader.prog.blocks.len() + skimmed;
        let last = Rc::new(reader.take_window(marks.last().map_or(0, |m| m.first_block), false));
        if kept.len() < CACHED_WINDOWS {
            kept.push(last);
        }
    }
    let Arenas {
        exprs,
        names,
        comments,
        errors,
        errors_left_out,
        ..
    } = reader.prog;
    Program {
        src,
        exprs,
        names,
        errors,
        errors_left_out,
        comments,
        line_count,
        store: Store {
            len,
            marks,
            macro_b,
            plain_lines_fast,
            interned: RefCell::new(reader.interned),
            // Most recently used first: the first window, where the interpreter starts.
            cache: RefCell::new(kept),
            rereads: Cell::new(0),
            jumps: Cell::new(0),
        },
    }
}

/// What the fast reader makes of `line` alone: `None` when it declines it, else whether it made a
/// block (the tests of `shape.rs` hold [`shape::plain_shape`] to it).
#[cfg(test)]
pub(super) fn fast_reading(line: &[u8]) -> Option<bool> {
    let mut reader = Reader::new(line);
    if reader.read_plain_line(1, 0, line.len()) {
        Some(!reader.prog.blocks.is_empty())
    } else {
        None
    }
}

/// A window of `prog` read again from the source: `count` blocks from where `mark` starts, with
/// the whole program's name table (see `window.rs`).
pub(super) fn reread(
    prog: &Program,
    mark: Mark,
    count: usize,
    interned: &mut HashMap<String, NameId>,
    spare: Option<Window>,
) -> Window {
    let src = prog.src;
    let mut reader = Reader::new(src);
    if let Some(w) = spare {
        // Cleared, the buffers of a window no longer held: what they held is gone.
        let Window {
            mut blocks,
            mut words,
            mut assigns,
            ..
        } = w;
        blocks.clear();
        words.clear();
        assigns.clear();
        (reader.prog.blocks, reader.prog.words, reader.prog.assigns) = (blocks, words, assigns);
    }
    reader.plain_lines_fast = prog.store.plain_lines_fast;
    reader.macro_b = prog.store.macro_b;
    reader.expr_base = mark.expr_base;
    reader.rereading = true;
    std::mem::swap(&mut reader.interned, interned);
    reader.prog.blocks.reserve(count);
    for (line, (line_start, end)) in (mark.line..).zip(lines_from(src, mark.start as usize)) {
        reader.read_line(line, line_start, end);
        if reader.prog.blocks.len() == count {
            break;
        }
    }
    std::mem::swap(&mut reader.interned, interned);
    debug_assert_eq!(reader.prog.blocks.len(), count);
    reader.take_window(mark.first_block, false)
}

/// What the reader builds: the current window's blocks, words and assignments, and what it keeps
/// for the whole program.
#[derive(Default)]
pub(super) struct Arenas {
    pub blocks: Vec<Block>,
    pub words: Vec<Word>,
    pub assigns: Vec<Assign>,
    pub exprs: Vec<Expr>,
    pub names: Vec<String>,
    pub errors: Vec<Finding>,
    pub errors_left_out: crate::finding::LeftOut,
    pub comments: Vec<Comment>,
}

/// A syntax error: where (byte offset in the source) and what.
pub(super) struct Error {
    pub at: usize,
    pub msg: String,
}

pub(super) type Res<T> = Result<T, Error>;

/// What has been read of the current line so far.
#[derive(Default)]
struct Partial {
    n: Option<u64>,
    block_delete: bool,
    percent: bool,
    oword: Option<OWord>,
    message: Option<Span>,
    macro_stmt: Option<super::MacroStmt>,
    /// A word, an assignment or an O-word was read.
    started: bool,
}

pub(super) struct Reader<'a> {
    pub src: &'a [u8],
    pub prog: Arenas,
    /// The id of `prog.exprs[0]` (a window read again numbers its expressions as at first).
    pub expr_base: u32,
    /// Reading a window again: every name is in the table already.
    rereading: bool,
    /// Reused buffer for names and long numbers.
    pub scratch: Vec<u8>,
    interned: HashMap<String, NameId>,
    /// Cursor: byte offset in `src`.
    pub pos: usize,
    /// End of the current line (exclusive, without terminator).
    pub end: usize,
    line_start: usize,
    line: u32,
    /// Current nesting of brackets, functions and indirections.
    pub depth: u32,
    /// Try [`Reader::read_plain_line`] first.
    plain_lines_fast: bool,
    /// Read Fanuc macro B statements, functions and operator priorities.
    pub macro_b: bool,
}

impl<'a> Reader<'a> {
    fn new(src: &'a [u8]) -> Reader<'a> {
        Reader {
            src,
            prog: Arenas::default(),
            expr_base: 0,
            rereading: false,
            scratch: Vec::new(),
            interned: HashMap::new(),
            pos: 0,
            end: 0,
            line_start: 0,
            line: 0,
            depth: 0,
            plain_lines_fast: true,
            macro_b: false,
        }
    }

    /// Whether the window read since the last one was taken holds a [`Block::rare`] part, in its
    /// mark (the last of `marks`).
    fn mark_rare(&self, marks: &mut [Mark]) {
        if let Some(m) = marks.last_mut() {
            m.rare = self.prog.blocks.iter().any(|b| b.rare.is_some());
        }
    }

    /// The window read since the last one was taken, its first block the program's `first`;
    /// `more`: another window is read after it.
    fn take_window(&mut self, first: usize, more: bool) -> Window {
        let mut w = Window {
            first,
            blocks: std::mem::take(&mut self.prog.blocks),
            words: std::mem::take(&mut self.prog.words),
            assigns: std::mem::take(&mut self.prog.assigns),
        };
        if w.blocks.capacity() > 2 * w.blocks.len() {
            w.blocks.shrink_to_fit();
        }
        if w.words.capacity() > 2 * w.words.len() {
            w.words.shrink_to_fit();
        }
        if more {
            // The next window grows as large as this one.
            self.prog.blocks.reserve(w.blocks.len());
            self.prog.words.reserve(w.words.len());
        }
        w
    }

    /// The next byte that is not a space or a tab, moving the cursor onto it; `None` at the end of
    /// the line.
    #[inline]
    pub fn peek(&mut self) -> Option<u8> {
        while self.pos < self.end {
            let b = self.src[self.pos];
            if b != b' ' && b != b'\t' {
                return Some(b);
            }
            self.pos += 1;
        }
        None
    }

    /// If the next non-blank bytes spell `kw` (lower case, blanks allowed between its letters),
    /// the offset just after it.
    pub fn match_kw(&self, kw: &[u8]) -> Option<usize> {
        let mut i = self.pos;
        for &k in kw {
            loop {
                let b = *self.src[..self.end].get(i)?;
                if b == b' ' || b == b'\t' {
                    i += 1;
                    continue;
                }
                if b.to_ascii_lowercase() != k {
                    return None;
                }
                i += 1;
                break;
            }
        }
        Some(i)
    }

    /// `end` moved back over blanks, not before `start`.
    pub fn trim_end(&self, start: usize, mut end: usize) -> usize {
        while end > start && matches!(self.src[end - 1], b' ' | b'\t') {
            end -= 1;
        }
        end
    }

    /// An error at `at`: "expected {what}, found …", with the special messages for bytes outside
    /// ASCII and for a stray `)`.
    pub fn expected(&self, at: usize, what: &str) -> Error {
        let mut at = at;
        while at < self.end && matches!(self.src[at], b' ' | b'\t') {
            at += 1;
        }
        Error {
            at,
            msg: self.expected_msg(at, what),
        }
    }

    pub fn expected_msg(&self, at: usize, what: &str) -> String {
        match self.src[..self.end].get(at) {
            None => format!("expected {what}, found end of line"),
            Some(&b) if b >= 0x80 => non_ascii_msg(b),
            Some(&b')') => format!("expected {what}, found ')'{}", self.nesting_hint(at)),
            Some(&b) => format!("expected {what}, found {}", show(b)),
        }
    }

    /// When a stray `)` follows a comment that held a `(`: the likely cause.
    fn nesting_hint(&self, at: usize) -> &'static str {
        if self.src[self.line_start..at].contains(&b'(') {
            " (comments do not nest: the first ')' closes a comment)"
        } else {
            ""
        }
    }

    /// Intern the name in `scratch`.
    pub fn intern_scratch(&mut self) -> NameId {
        // The scratch holds ASCII only (callers reject other bytes).
        let name = std::str::from_utf8(&self.scratch).unwrap_or("");
        if let Some(&id) = self.interned.get(name) {
            return id;
        }
        debug_assert!(!self.rereading, "a window read again met a new name");
        let id = self.prog.names.len() as NameId;
        self.prog.names.push(name.to_owned());
        self.interned.insert(name.to_owned(), id);
        id
    }

    /// 1-based column in characters of a byte offset on the current line.
    fn col(&self, at: usize) -> u32 {
        let at = at.clamp(self.line_start, self.end);
        let text = &self.src[self.line_start..at];
        let chars = text.iter().filter(|&&b| (b & 0xC0) != 0x80).count();
        chars as u32 + 1
    }

    /// The usual line, read fast: an optional N number, then words whose values are plain numbers
    /// (an optional `-` and what [`plain_number`] reads), blanks between, nothing else. Returns
    /// false, having stored nothing, for any other line: the general reader then reads it and gives
    /// the same result this would have given. (`shape.rs` decides the same lines without reading
    /// them; a test holds the two to each other.)
    ///
    /// The line is walked as a slice of its own, so every look ahead stops at its end.
    pub(super) fn read_plain_line(&mut self, line: u32, start: usize, end: usize) -> bool {
        let s = &self.src[start..end];
        let len = s.len();
        let continues_number = |i: usize| matches!(s.get(i), Some(b'0'..=b'9' | b'.'));
        let mut i = skip_blanks(s, 0);
        let mut n = None;
        if i < len && s[i] & !0x20 == b'N' {
            let first = i + 1;
            let (j, v) = digit_run(s, first, 0);
            i = skip_blanks(s, j);
            // At most 18 digits always fit; anything that may continue the number goes the long way.
            if j == first || j - first > 18 || continues_number(i) {
                return false;
            }
            n = Some(v);
        }
        let words0 = self.prog.words.len();
        while i < len {
            let at = i;
            let letter = s[i] & !0x20;
            if !letter.is_ascii_uppercase() || letter == b'N' || letter == b'O' {
                self.prog.words.truncate(words0);
                return false;
            }
            let negative = s.get(i + 1) == Some(&b'-');
            let Some((value_end, x, has_point)) = plain_value(s, i + 1 + negative as usize) else {
                self.prog.words.truncate(words0);
                return false;
            };
            i = skip_blanks(s, value_end);
            if continues_number(i) {
                self.prog.words.truncate(words0);
                return false;
            }
            self.prog.words.push(Word::new(
                letter,
                Value::Num(if negative { -x } else { x }),
                has_point,
                Span::new(start + at, start + value_end),
            ));
        }
        let words = words0 as u32..self.prog.words.len() as u32;
        if words.is_empty() && n.is_none() {
            return true; // a blank line
        }
        self.prog.blocks.push(Block {
            line,
            span: Span::new(start, end),
            n: n.unwrap_or(0),
            words,
            rare: None,
            block_delete: false,
            percent: false,
            bad: false,
            has_n: n.is_some(),
        });
        true
    }

    fn read_line(&mut self, line: u32, start: usize, end: usize) {
        // A byte-order mark at the start of the file is no part of line 1.
        let start = if line == 1 && self.src.starts_with(BOM) {
            BOM.len().min(end)
        } else {
            start
        };
        if self.plain_lines_fast && self.read_plain_line(line, start, end) {
            return;
        }
        self.pos = start;
        self.end = end;
        self.line_start = start;
        self.line = line;
        self.depth = 0;
        let words0 = self.prog.words.len() as u32;
        let assigns0 = self.prog.assigns.len() as u32;
        let mut part = Partial::default();
        let result = self.read_items(&mut part);
        let bad = result.is_err();
        if let Err(e) = result {
            let col = self.col(e.at);
            let f = Finding::syntax(line, col, e.msg).with_n(part.n);
            push_capped(&mut self.prog.errors, &mut self.prog.errors_left_out, f);
        }
        let words = words0..self.prog.words.len() as u32;
        let assigns = assigns0..self.prog.assigns.len() as u32;
        let something = part.started || part.percent || part.block_delete || part.n.is_some() || part.message.is_some();
        if !(bad || something) {
            return;
        }
        let rare = (!assigns.is_empty() || part.oword.is_some() || part.message.is_some() || part.macro_stmt.is_some())
            .then(|| {
                Box::new(Rare {
                    assigns,
                    oword: part.oword,
                    message: part.message,
                    macro_stmt: part.macro_stmt,
                })
            });
        self.prog.blocks.push(Block {
            line,
            span: Span::new(start, end),
            n: part.n.unwrap_or(0),
            words,
            rare,
            block_delete: part.block_delete,
            percent: part.percent,
            bad,
            has_n: part.n.is_some(),
        });
    }

    fn read_items(&mut self, part: &mut Partial) -> Res<()> {
        if self.peek() == Some(b'%') {
            part.percent = true;
            self.pos += 1;
        }
        while let Some(c) = self.peek() {
            let at = self.pos;
            if part.oword.is_some() && c != b'(' && c != b';' {
                return Err(self.expected(at, "nothing but comments after an O-word statement"));
            }
            if let Some(m) = part.macro_stmt {
                let then = matches!(m.op, super::MacroOp::IfThen(_));
                if c != b'(' && c != b';' && !(then && c == b'#') {
                    let what = if then {
                        "an assignment (#i=…) or a comment after THEN"
                    } else {
                        "nothing but comments after a macro statement"
                    };
                    return Err(self.expected(at, what));
                }
            }
            if self.macro_b && !part.started && c.is_ascii_alphabetic() {
                if let Some(op) = self.macro_statement()? {
                    part.started = true;
                    part.macro_stmt = Some(super::MacroStmt { op, at: at as u32 });
                    continue;
                }
            }
            match c {
                b'(' => self.comment(part)?,
                b';' => return Ok(()),
                b'/' => {
                    if part.started || part.n.is_some() || part.block_delete {
                        return Err(Error {
                            at,
                            msg: "'/' (block delete) must be the first character of the block".into(),
                        });
                    }
                    part.block_delete = true;
                    self.pos += 1;
                }
                b'n' | b'N' => {
                    if part.started || part.n.is_some() {
                        return Err(Error {
                            at,
                            msg: "an N word (line number) must be at the start of the block".into(),
                        });
                    }
                    self.pos += 1;
                    part.n = Some(self.line_number(at)?);
                }
                b'o' | b'O' | b':' => {
                    if part.started {
                        return Err(Error {
                            at,
                            msg: "an O-word must be the first word of the block".into(),
                        });
                    }
                    part.started = true;
                    part.oword = Some(self.oword(at)?);
                }
                b'#' => {
                    part.started = true;
                    self.pos += 1;
                    let target = self.param()?;
                    if self.peek() != Some(b'=') {
                        let what = "'=' after the parameter (outside a value a parameter can only be set, as in #1=2)";
                        return Err(self.expected(self.pos, what));
                    }
                    self.pos += 1;
                    let value = self.value_expr()?;
                    let span = Span::new(at, self.trim_end(at, self.pos));
                    self.prog.assigns.push(super::Assign { target, value, span });
                }
                b'%' => {
                    return Err(Error {
                        at,
                        msg: "'%' must be the first character of its line".into(),
                    })
                }
                _ if c.is_ascii_alphabetic() => {
                    part.started = true;
                    let letter = c.to_ascii_uppercase();
                    self.pos += 1;
                    let (value, has_point) = self.value(letter)?;
                    let span = Span::new(at, self.trim_end(at, self.pos));
                    self.prog.words.push(Word::new(letter, value, has_point, span));
                }
                b')' => {
                    return Err(Error {
                        at,
                        msg: format!("')' outside a comment{}", self.nesting_hint(at)),
                    })
                }
                _ => return Err(self.expected(at, "a word (a letter and a value)")),
            }
        }
        Ok(())
    }

    /// `( … )` at the cursor; the first `)` closes it.
    fn comment(&mut self, part: &mut Partial) -> Res<()> {
        let open = self.pos;
        let body = open + 1;
        let Some(k) = self.src[body..self.end].iter().position(|&b| b == b')') else {
            return Err(Error {
                at: open,
                msg: "unclosed comment: '(' has no ')' on its line".into(),
            });
        };
        let close = body + k;
        self.prog.comments.push(Comment {
            line: self.line,
            text: Span::new(body, close),
        });
        if part.message.is_none() {
            part.message = message_text(self.src, body, close);
        }
        self.pos = close + 1;
        Ok(())
    }

    /// Digits of an N word, the `N` already consumed at `at`.
    fn line_number(&mut self, at: usize) -> Res<u64> {
        match self.peek() {
            Some(b) if b.is_ascii_digit() => {}
            _ => return Err(self.expected(self.pos, "a line number after N")),
        }
        let n = self.uint(at, u64::MAX, "line number")?;
        if self.peek() == Some(b'.') {
            return Err(Error {
                at: self.pos,
                msg: "a line number must be a whole number".into(),
            });
        }
        Ok(n)
    }

    /// Unsigned decimal digits (blanks allowed between them) at the cursor, at most `max`.
    fn uint(&mut self, at: usize, max: u64, what: &str) -> Res<u64> {
        let mut n: u64 = 0;
        let mut overflow = false;
        let mut last = self.pos;
        while let Some(b) = self.peek() {
            if !b.is_ascii_digit() {
                break;
            }
            match n.checked_mul(10).and_then(|v| v.checked_add((b - b'0') as u64)) {
                Some(v) if v <= max => n = v,
                _ => overflow = true,
            }
            self.pos += 1;
            last = self.pos;
        }
        self.pos = last;
        if overflow {
            return Err(Error {
                at,
                msg: format!("{what} is too large (at most {max})"),
            });
        }
        Ok(n)
    }

    /// An O-word statement, or a Fanuc program number (`O1234`, `:1234`), at `at`.
    fn oword(&mut self, at: usize) -> Res<OWord> {
        let colon = self.src[at] == b':';
        self.pos += 1;
        let name = match self.peek() {
            Some(b) if b.is_ascii_digit() => {
                let n = self.uint(at, u32::MAX as u64, "an O number")?;
                if self.peek() == Some(b'.') {
                    return Err(Error {
                        at: self.pos,
                        msg: "an O number must be a whole number".into(),
                    });
                }
                OName::Number(n as u32)
            }
            Some(b'<') if !colon => OName::Named(self.name()?),
            _ => {
                let what = if colon {
                    "a program number after ':'"
                } else {
                    "a number or <name> after O"
                };
                return Err(self.expected(self.pos, what));
            }
        };
        let name_end = self.pos;
        let after_name = self.peek();
        let keyword = matches!(after_name, Some(b) if b.is_ascii_alphabetic());
        if colon || !keyword {
            if let OName::Named(_) = name {
                return Err(self.expected(self.pos, "sub, endsub, call, return, do, while, endwhile, if, elseif, else, endif, break, continue, repeat or endrepeat after the O-word name"));
            }
            return Ok(OWord {
                name,
                op: OOp::ProgramNumber,
                span: Span::new(at, name_end),
            });
        }
        let kw_at = self.pos;
        let mut kw = [0u8; 10];
        let mut len = 0;
        let mut last = self.pos;
        while let Some(b) = self.peek() {
            if !b.is_ascii_alphabetic() {
                break;
            }
            if len < kw.len() {
                kw[len] = b.to_ascii_lowercase();
            }
            len += 1;
            self.pos += 1;
            last = self.pos;
        }
        self.pos = last;
        let op = match &kw[..len.min(kw.len())] {
            _ if len > kw.len() => None,
            b"sub" => Some(OOp::Sub),
            b"endsub" => Some(OOp::EndSub(self.optional_bracketed()?)),
            b"call" => {
                let mut args = Vec::new();
                while self.peek() == Some(b'[') {
                    args.push(self.bracketed()?);
                }
                Some(OOp::Call(args))
            }
            b"return" => Some(OOp::Return(self.optional_bracketed()?)),
            b"do" => Some(OOp::Do),
            b"while" => Some(OOp::While(self.condition("WHILE")?)),
            b"endwhile" => Some(OOp::EndWhile),
            b"if" => Some(OOp::If(self.condition("IF")?)),
            b"elseif" => Some(OOp::ElseIf(self.condition("ELSEIF")?)),
            b"else" => Some(OOp::Else),
            b"endif" => Some(OOp::EndIf),
            b"break" => Some(OOp::Break),
            b"continue" => Some(OOp::Continue),
            b"repeat" => Some(OOp::Repeat(self.condition("REPEAT")?)),
            b"endrepeat" => Some(OOp::EndRepeat),
            _ => None,
        };
        let Some(op) = op else {
            // One letter: most likely a word after a Fanuc program number.
            if let (OName::Number(n), 1) = (name, len) {
                let found = show(self.src[kw_at].to_ascii_uppercase());
                return Err(Error {
                    at: kw_at,
                    msg: format!("expected an O-word keyword (sub, call, if, …) or nothing after O{n} (a program number stands alone on its line), found {found}"),
                });
            }
            let word = String::from_utf8_lossy(&kw[..len.min(kw.len())]);
            let dots = if len > kw.len() { "…" } else { "" };
            return Err(Error {
                at: kw_at,
                msg: format!("unknown O-word keyword '{word}{dots}' (expected sub, endsub, call, return, do, while, endwhile, if, elseif, else, endif, break, continue, repeat or endrepeat)"),
            });
        };
        Ok(OWord {
            name,
            op,
            span: Span::new(at, self.trim_end(at, self.pos)),
        })
    }

    /// A Fanuc macro B statement at the cursor (on a letter), or `None` (cursor unmoved) when the
    /// letters there are no statement keyword. None of the keywords can begin a valid word (`GO`,
    /// `IF`, `WH`, `EN`, `DO`: a letter followed by a letter), so reading them first changes
    /// nothing for other lines.
    fn macro_statement(&mut self) -> Res<Option<super::MacroOp>> {
        use super::MacroOp;
        if let Some(end) = self.match_kw(b"goto") {
            self.pos = end;
            return Ok(Some(MacroOp::Goto(self.operand_expr("a sequence number after GOTO")?)));
        }
        if let Some(end) = self.match_kw(b"while") {
            self.pos = end;
            let cond = self.condition("WHILE")?;
            let Some(end) = self.match_kw(b"do") else {
                return Err(self.expected(self.pos, "DO1, DO2 or DO3 after WHILE [...]"));
            };
            self.pos = end;
            return Ok(Some(MacroOp::Do(Some(cond), self.loop_id("DO")?)));
        }
        if let Some(end) = self.match_kw(b"do") {
            self.pos = end;
            return Ok(Some(MacroOp::Do(None, self.loop_id("DO")?)));
        }
        if let Some(end) = self.match_kw(b"end") {
            self.pos = end;
            return Ok(Some(MacroOp::End(self.loop_id("END")?)));
        }
        if let Some(end) = self.match_kw(b"if") {
            self.pos = end;
            let cond = self.condition("IF")?;
            if let Some(end) = self.match_kw(b"goto") {
                self.pos = end;
                return Ok(Some(MacroOp::IfGoto(
                    cond,
                    self.operand_expr("a sequence number after GOTO")?,
                )));
            }
            if let Some(end) = self.match_kw(b"then") {
                self.pos = end;
                if self.peek() != Some(b'#') {
                    return Err(self.expected(self.pos, "an assignment (#i=…) after THEN"));
                }
                return Ok(Some(MacroOp::IfThen(cond)));
            }
            return Err(self.expected(self.pos, "GOTO or THEN after IF [...]"));
        }
        Ok(None)
    }

    /// The loop number of `DOm` / `ENDm`: 1, 2 or 3.
    fn loop_id(&mut self, what: &str) -> Res<u8> {
        let at = self.pos;
        match self.peek() {
            Some(b) if b.is_ascii_digit() => {}
            _ => return Err(self.expected(at, &format!("1, 2 or 3 after {what}"))),
        }
        let m = self.uint(at, 999, "a loop number")?;
        if !(1..=3).contains(&m) {
            return Err(Error {
                at,
                msg: format!("{what}{m}: the loop number must be 1, 2 or 3"),
            });
        }
        Ok(m as u8)
    }

    /// The bracketed expression a WHILE, IF, ELSEIF or REPEAT needs.
    fn condition(&mut self, what: &str) -> Res<super::ExprId> {
        if self.peek() != Some(b'[') {
            return Err(self.expected(self.pos, &format!("'[' after {what}")));
        }
        self.bracketed()
    }

    fn optional_bracketed(&mut self) -> Res<Option<super::ExprId>> {
        if self.peek() == Some(b'[') {
            return self.bracketed().map(Some);
        }
        Ok(None)
    }

    /// `<name>` at the cursor (on the `<`): lower case, blanks removed, interned.
    pub fn name(&mut self) -> Res<NameId> {
        let open = self.pos;
        self.scratch.clear();
        let mut i = open + 1;
        loop {
            let Some(&b) = self.src[..self.end].get(i) else {
                return Err(Error {
                    at: open,
                    msg: "unclosed name: '<' has no '>'".into(),
                });
            };
            match b {
                b'>' => break,
                b' ' | b'\t' => {}
                0x80.. => {
                    return Err(Error {
                        at: i,
                        msg: non_ascii_msg(b),
                    })
                }
                _ => self.scratch.push(b.to_ascii_lowercase()),
            }
            i += 1;
        }
        if self.scratch.is_empty() {
            return Err(Error {
                at: open,
                msg: "empty name '<>'".into(),
            });
        }
        self.pos = i + 1;
        Ok(self.intern_scratch())
    }
}

/// `MSG,`, `PRINT,` or `DEBUG,` (any case, blanks allowed) opening the comment text
/// `src[body..close]`: the span of the text after the comma.
fn message_text(src: &[u8], body: usize, close: usize) -> Option<Span> {
    let text = &src[body..close];
    let mut i = 0;
    while i < text.len() && (text[i] == b' ' || text[i] == b'\t') {
        i += 1;
    }
    for kw in [&b"msg"[..], b"print", b"debug"] {
        let Some(word) = text.get(i..i + kw.len()) else {
            continue;
        };
        if !word.eq_ignore_ascii_case(kw) {
            continue;
        }
        let mut j = i + kw.len();
        while j < text.len() && (text[j] == b' ' || text[j] == b'\t') {
            j += 1;
        }
        if text.get(j) == Some(&b',') {
            return Some(Span::new(body + j + 1, close));
        }
    }
    None
}

pub(super) fn non_ascii_msg(b: u8) -> String {
    format!("byte 0x{b:02X} outside a comment (only comments may hold text that is not ASCII)")
}

/// A byte as a message shows it.
pub(super) fn show(b: u8) -> String {
    if b.is_ascii_graphic() {
        format!("'{}'", b as char)
    } else {
        format!("control byte 0x{b:02X}")
    }
}
