//! Fanuc custom macro B: variables (vacant values, locals per macro level, common and system
//! variables), expression evaluation with the Fanuc rules, `GOTO`, `IF`, `WHILE … DOm` / `ENDm`,
//! `G65` / `G66` / `G67` macro calls and `M99 Pn`. What is read and what is not: `docs/macro-b.md`.
//!
//! Only the Fanuc dialect has a [`State`] (`Run::macro_b`); a LinuxCNC run never enters this
//! module, and a Fanuc program that uses no macro costs one check of each block's words for
//! G65–G67 and the bookkeeping of the last D, H, M, T words.
//!
//! Vacant variables are stored as NaN in `Params::numbered` and evaluate to `None`.

use super::eval::bool_f;
use super::flow::Run;
use crate::finding::{push_capped, Finding, Kind, LeftOut, Severity};
use crate::gcode::{BinOp, Block, BlockRef, Expr, ExprId, Func, MacroOp, OName, OOp, Param, Program, Value};
use std::cell::Cell;
use std::collections::HashMap;

/// Deepest expression tree evaluated.
const MAX_DEPTH: u32 = 400;

/// A vacant variable (`#0`) as stored.
pub(crate) const VACANT: f64 = f64::NAN;

/// Deepest nesting of `DO` loops (Fanuc: three).
const MAX_LOOP_NESTING: usize = 3;

/// A macro value: `None` is vacant.
type MVal = Option<f64>;

/// What macro B keeps beside the run.
pub(crate) struct State {
    /// First block of each program of the file (a program starts at its `O` line; blocks before
    /// the first `O` line belong to the first program).
    seg_starts: Vec<usize>,
    /// The O number of each program (0 before the first `O` line).
    seg_o: Vec<u32>,
    /// `DOm` block → its `ENDm` block, and `ENDm` → its `DOm`.
    loops: HashMap<usize, usize>,
    /// (program, N number) → blocks with that N, ascending; built at the first jump.
    seq: Option<HashMap<(usize, u64), Vec<usize>>>,
    /// Active `G65`/`G66` macro levels: the frame depth each owns and its arguments (restored at
    /// each repetition of `L`).
    levels: Vec<(usize, Box<[f64; 33]>)>,
    /// `G66` in force: program block, count, arguments, frame depth where it was given.
    modal_call: Option<ModalCall>,
    /// Last D, H, M, T words and the N number of the preceding blocks (#4107 … #4120).
    last: [MVal; 4],
    last_n: MVal,
    /// #3901, #3902.
    parts: [f64; 2],
    /// Some expression reads #4107 … #4120 or a computed variable number: only then are the
    /// D, H, M, T words and N numbers noted as blocks run.
    reads_last_words: bool,
    /// The last evaluation failed on a variable latheguard does not model (an `unsupported`
    /// finding rather than a `program` one).
    pub unsupported: Cell<bool>,
}

#[derive(Clone)]
struct ModalCall {
    start: usize,
    count: u64,
    args: Box<[f64; 33]>,
    depth: usize,
}

impl State {
    /// What of macro B's own state a loop can read, for the endless-loop test
    /// (`Run::back_edge`): the call levels and their arguments, a modal call, the last words
    /// and the part counters.
    pub(super) fn loop_state(&self, v: &mut Vec<u64>) {
        for (depth, args) in &self.levels {
            v.push(*depth as u64);
            v.extend(args.iter().map(|x| x.to_bits()));
        }
        if let Some(c) = &self.modal_call {
            v.extend([c.start as u64, c.count, c.depth as u64]);
            v.extend(c.args.iter().map(|x| x.to_bits()));
        }
        v.extend(
            self.last
                .iter()
                .chain([&self.last_n])
                .map(|x| x.map_or(u64::MAX, f64::to_bits)),
        );
        v.extend(self.parts.iter().map(|x| x.to_bits()));
    }

    /// The programs of the file and the `DO`/`END` pairs, with a `program` finding for every
    /// loop the manual forbids.
    pub fn new(prog: &Program, findings: &mut Vec<Finding>, left_out: &mut LeftOut) -> State {
        let mut s = State {
            seg_starts: vec![0],
            seg_o: vec![0],
            loops: HashMap::new(),
            seq: None,
            levels: Vec::new(),
            modal_call: None,
            last: [None; 4],
            last_n: None,
            parts: [0.0; 2],
            reads_last_words: prog.exprs.iter().any(|e| {
                matches!(
                    e,
                    Expr::Param(Param::Numbered(4107..=4120)) | Expr::Param(Param::Indirect(_))
                )
            }),
            unsupported: Cell::new(false),
        };
        // Open DOs of the current program: (m, block).
        let mut open: Vec<(u8, usize)> = Vec::new();
        let mut err = |b: &Block, msg: String| {
            push_capped(findings, left_out, Finding::program(b.line, 0, msg).with_n(b.n()));
        };
        let close_all = |open: &mut Vec<(u8, usize)>, err: &mut dyn FnMut(&Block, String)| {
            for (m, k) in open.drain(..) {
                err(&prog.block(k), format!("DO{m} without END{m} in its program"));
            }
        };
        for b in prog.rare_blocks() {
            let i = b.index();
            if b.bad {
                continue;
            }
            if let Some(o) = b.oword() {
                if let (OOp::ProgramNumber, OName::Number(n)) = (&o.op, o.name) {
                    close_all(&mut open, &mut err);
                    if i == 0 {
                        s.seg_o[0] = n;
                    } else {
                        s.seg_starts.push(i);
                        s.seg_o.push(n);
                    }
                }
            }
            let Some(st) = b.macro_stmt() else { continue };
            match st.op {
                MacroOp::Do(_, m) => {
                    if let Some(&(_, k)) = open.iter().find(|(o, _)| *o == m) {
                        err(
                            &b,
                            format!(
                                "DO{m} inside the range of DO{m} of line {}: nested loops need different numbers",
                                prog.block(k).line
                            ),
                        );
                    } else if open.len() >= MAX_LOOP_NESTING {
                        err(&b, format!("DO{m}: loops nest at most {MAX_LOOP_NESTING} deep"));
                    } else {
                        open.push((m, i));
                        continue;
                    }
                    // A loop that cannot run: it is never entered (see `statement`).
                }
                MacroOp::End(m) => match open.iter().rposition(|(o, _)| *o == m) {
                    Some(p) if p + 1 == open.len() => {
                        let (_, k) = open.pop().unwrap_or((m, i));
                        s.loops.insert(k, i);
                        s.loops.insert(i, k);
                    }
                    Some(p) => {
                        // The overlapping DOm is dropped (never runs); the inner loops stay open.
                        open.remove(p);
                        let (inner, k) = open[open.len() - 1];
                        err(
                            &b,
                            format!(
                                "END{m} closes DO{m} while DO{inner} of line {} is still open: loop ranges overlap",
                                prog.block(k).line
                            ),
                        );
                    }
                    None => err(&b, format!("END{m} without a DO{m} before it in its program")),
                },
                _ => {}
            }
        }
        close_all(&mut open, &mut err);
        s
    }

    /// The program (index into `seg_starts`) block `i` belongs to.
    fn segment(&self, i: usize) -> usize {
        self.seg_starts.partition_point(|&s| s <= i).saturating_sub(1)
    }

    /// A `G66` is in force.
    pub fn modal_call_active(&self) -> bool {
        self.modal_call.is_some()
    }

    /// Block `i` has a G65, G66 or G67 word.
    pub fn is_call_block(b: &BlockRef) -> bool {
        b.words()
            .iter()
            .any(|w| w.letter == b'G' && matches!(w.value(), Value::Num(x) if x == 65.0 || x == 66.0 || x == 67.0))
    }

    /// Whether [`State::note`] has anything to do.
    pub fn notes_words(&self) -> bool {
        self.reads_last_words
    }

    /// Note the D, H, M, T words and the N number of a block just executed (plain numbers;
    /// not M98, M99).
    pub fn note(&mut self, b: &BlockRef) {
        if !self.reads_last_words {
            return;
        }
        if let Some(n) = b.n() {
            self.last_n = Some(n as f64);
        }
        for w in b.words() {
            let k = match w.letter {
                b'D' => 0,
                b'H' => 1,
                b'M' => 2,
                b'T' => 3,
                _ => continue,
            };
            match w.value() {
                // M98 and M99 are the control's own, not M codes sent to the machine.
                Value::Num(x) if k == 2 && (x == 98.0 || x == 99.0) => {}
                Value::Num(x) => self.last[k] = Some(x),
                Value::Expr(_) => {}
            }
        }
    }
}

fn vacant_of(x: f64) -> MVal {
    (!x.is_nan()).then_some(x)
}

/// Fanuc's mapping of argument specification I for the letters that are not I, J, K.
fn spec_one(letter: u8) -> Option<usize> {
    Some(match letter {
        b'A' => 1,
        b'B' => 2,
        b'C' => 3,
        b'D' => 7,
        b'E' => 8,
        b'F' => 9,
        b'H' => 11,
        b'M' => 13,
        b'Q' => 17,
        b'R' => 18,
        b'S' => 19,
        b'T' => 20,
        b'U' => 21,
        b'V' => 22,
        b'W' => 23,
        b'X' => 24,
        b'Y' => 25,
        b'Z' => 26,
        _ => return None,
    })
}

impl Run<'_> {
    fn mstate(&self) -> Option<&State> {
        self.macro_b.as_deref()
    }

    /// Evaluate with the Fanuc rules; `None` is vacant.
    pub(crate) fn macro_eval(&self, id: ExprId) -> Result<MVal, String> {
        if let Some(m) = self.mstate() {
            m.unsupported.set(false);
        }
        let v = self.m_eval(id, 0)?;
        match v {
            Some(x) if !x.is_finite() => Err("the expression's value is not a finite number".into()),
            v => Ok(v),
        }
    }

    fn unsupported_var(&self, msg: String) -> String {
        if let Some(m) = self.mstate() {
            m.unsupported.set(true);
        }
        msg
    }

    fn m_eval(&self, id: ExprId, depth: u32) -> Result<MVal, String> {
        if depth > MAX_DEPTH {
            return Err(format!("expression nested deeper than {MAX_DEPTH} levels"));
        }
        let d = depth + 1;
        let num = |v: MVal| v.unwrap_or(0.0);
        Ok(match *self.prog.expr(id) {
            Expr::Num(x) => Some(x),
            Expr::Param(p) => self.m_param(p, d)?,
            // `-#1` with #1 vacant stays vacant (in arithmetic it is 0 anyway).
            Expr::Neg(a) => self.m_eval(a, d)?.map(|x| -x),
            Expr::Not(a) => Some(bool_f(num(self.m_eval(a, d)?) == 0.0)),
            Expr::Binary(op, a, b) => {
                let x = self.m_eval(a, d)?;
                let y = self.m_eval(b, d)?;
                Some(binary(op, x, y)?)
            }
            Expr::Func(f, a) => Some(func(f, num(self.m_eval(a, d)?))?),
            Expr::Atan(y, x) => {
                let (y, x) = (num(self.m_eval(y, d)?), num(self.m_eval(x, d)?));
                if y == 0.0 && x == 0.0 {
                    return Err("ATAN[0,0] is undefined".into());
                }
                // Fanuc (parameter NAT = 0): 0° up to 360°.
                Some(y.atan2(x).to_degrees().rem_euclid(360.0))
            }
            Expr::Exists(name) => Some(bool_f(self.named(name).is_some())),
        })
    }

    fn m_param(&self, p: Param, depth: u32) -> Result<MVal, String> {
        match p {
            Param::Numbered(n) => self.m_read(n),
            Param::Indirect(e) => match self.m_eval(e, depth + 1)? {
                None => Ok(None), // #[#0] is #0
                Some(v) => self.m_read(var_index(v)?),
            },
            Param::Named(name) => self
                .named(name)
                .map(Some)
                .ok_or_else(|| format!("named parameter #<{}> is not defined", self.prog.name(name))),
        }
    }

    /// Read variable `#n`.
    fn m_read(&self, n: u32) -> Result<MVal, String> {
        let store = |n: u32| Ok(vacant_of(self.params.numbered[n as usize]));
        match n {
            0 => Ok(None),
            1..=33 | 100..=999 => store(n),
            34..=99 => Err(format!("variable #{n} does not exist (locals are #1–#33)")),
            _ => self.system_var(n),
        }
    }

    /// The system variables a lathe program reads (see `docs/macro-b.md`).
    fn system_var(&self, n: u32) -> Result<MVal, String> {
        let m = &self.modal;
        let (x, z) = self.program_position();
        let offsets = |n: u32| -> Option<(u32, u32)> {
            // (kind, offset number): kinds 0 X wear, 1 Z wear, 2 R wear, 3 T, 4 X geometry,
            // 5 Z geometry, 6 R geometry.
            match n {
                2001..=2064 => Some((0, n - 2000)),
                2101..=2164 => Some((1, n - 2100)),
                2201..=2264 => Some((2, n - 2200)),
                2301..=2364 => Some((3, n - 2300)),
                2701..=2764 => Some((4, n - 2700)),
                2801..=2864 => Some((5, n - 2800)),
                2901..=2964 => Some((6, n - 2900)),
                10001..=10999 => Some((0, n - 10000)),
                11001..=11999 => Some((1, n - 11000)),
                12001..=12999 => Some((2, n - 12000)),
                13001..=13999 => Some((3, n - 13000)),
                15001..=15999 => Some((4, n - 15000)),
                16001..=16999 => Some((5, n - 16000)),
                17001..=17999 => Some((6, n - 17000)),
                _ => None,
            }
        };
        if let Some((kind, k)) = offsets(n) {
            let tool = self.machine.tool(k);
            let units = self.scale();
            return Ok(Some(match kind {
                0..=2 => 0.0, // the machine file has no wear offsets
                3 => {
                    return Err(
                        self.unsupported_var(format!("#{n} (imaginary tip of offset {k}) is not known to latheguard"))
                    )
                }
                4 => {
                    let tx = tool.map_or(0.0, |t| t.tip.x) / units;
                    if m.diameter {
                        2.0 * tx
                    } else {
                        tx
                    }
                }
                5 => tool.map_or(0.0, |t| t.tip.y) / units,
                _ => tool.map_or(0.0, |t| t.nose_radius) / units,
            }));
        }
        let st = self.mstate();
        let motion_code = || match m.motion {
            Some(super::state::Motion::Rapid) => 0.0,
            Some(super::state::Motion::Line) => 1.0,
            Some(super::state::Motion::ArcCw) => 2.0,
            Some(super::state::Motion::ArcCcw) => 3.0,
            Some(super::state::Motion::Thread) => 32.0,
            Some(super::state::Motion::Cycle(code)) => f64::from(code) / 10.0,
            None => 0.0,
        };
        let v = match n {
            3901 | 3902 => st.map_or(0.0, |s| s.parts[(n - 3901) as usize]),
            4001 => motion_code(),
            4002 => {
                if m.spindle_css {
                    96.0
                } else {
                    97.0
                }
            }
            4003 => {
                if m.incremental {
                    91.0
                } else {
                    90.0
                }
            }
            4005 => {
                if m.feed_per_rev {
                    99.0
                } else {
                    98.0
                }
            }
            4006 => {
                if m.inch {
                    20.0
                } else {
                    21.0
                }
            }
            4012 => {
                if st.is_some_and(|s| s.modal_call.is_some()) {
                    66.0
                } else {
                    67.0
                }
            }
            4016 => {
                if m.plane_xy {
                    17.0
                } else if m.plane_xz {
                    18.0
                } else {
                    19.0
                }
            }
            4107 => return Ok(st.and_then(|s| s.last[0])),
            4109 => m.feed,
            4111 => return Ok(st.and_then(|s| s.last[1])),
            4113 => return Ok(st.and_then(|s| s.last[2])),
            4114 => return Ok(st.and_then(|s| s.last_n)),
            4115 => st.map_or(0.0, |s| f64::from(s.seg_o[s.segment(self.pc.saturating_sub(1))])),
            4119 => m.s,
            4120 => return Ok(st.and_then(|s| s.last[3])),
            5001 | 5041 => x,
            5002 | 5042 => z,
            5021 | 5022 => {
                // Machine coordinates as latheguard knows them: the spindle axis and the jaw
                // faces, in program units, X as a diameter in diameter mode.
                let p = self.programmed();
                let s = self.scale();
                if n == 5022 {
                    p.y / s
                } else if m.diameter {
                    2.0 * p.x / s
                } else {
                    p.x / s
                }
            }
            _ => {
                return Err(self.unsupported_var(format!(
                    "system variable #{n} is not modelled by latheguard (docs/macro-b.md lists those that are)"
                )))
            }
        };
        Ok(Some(v))
    }

    /// `#n = v` (v NaN: vacant) in the Fanuc dialect.
    pub(crate) fn macro_assign(&mut self, p: Param, v: f64) -> Result<(), String> {
        let n = match p {
            Param::Numbered(n) => n,
            Param::Indirect(e) => match self.macro_eval(e)? {
                Some(x) => var_index(x)?,
                None => 0,
            },
            Param::Named(_) => return self.assign_named(p, v),
        };
        match n {
            0 => Err("#0 is always vacant and cannot be set".into()),
            1..=33 | 100..=999 => {
                self.params.numbered[n as usize] = v;
                Ok(())
            }
            34..=99 => Err(format!("variable #{n} does not exist (locals are #1–#33)")),
            3000 => {
                let msg = self.line_comment();
                let code = if v.is_nan() { 0.0 } else { v };
                self.stopped = true;
                Err(format!("macro alarm #3000={code}{}: the program stops here", msg))
            }
            3006 => {
                let msg = self.line_comment();
                let f = Finding::at(
                    Kind::Program,
                    Severity::Warning,
                    self.current_line,
                    0,
                    format!("#3006 stop with message{msg}: the control waits for cycle start; checked as if it were pressed"),
                );
                self.report_finding(f);
                Ok(())
            }
            3901 | 3902 => {
                if let Some(s) = self.macro_b.as_deref_mut() {
                    s.parts[(n - 3901) as usize] = if v.is_nan() { 0.0 } else { v };
                }
                Ok(())
            }
            _ => {
                if let Some(m) = self.mstate() {
                    m.unsupported.set(true);
                }
                Err(format!("setting system variable #{n} is not modelled by latheguard"))
            }
        }
    }

    /// `(text)` of the current line's first comment, as ` (text)`, or nothing.
    fn line_comment(&self) -> String {
        let line = self.current_line;
        let c = &self.prog.comments;
        let k = c.partition_point(|c| c.line < line);
        match c.get(k).filter(|c| c.line == line) {
            Some(c) => format!(
                " ({})",
                String::from_utf8_lossy(&self.src[c.text.start as usize..c.text.end as usize]).trim()
            ),
            None => String::new(),
        }
    }

    /// A condition: vacant is false.
    fn m_cond(&mut self, b: &Block, e: ExprId) -> Option<bool> {
        match self.macro_eval(e) {
            Ok(v) => Some(v.is_some_and(|x| x != 0.0)),
            Err(m) => {
                self.eval_error(b, None, m);
                None
            }
        }
    }

    /// Execute a macro statement at block `i` (the program counter is already `i + 1`).
    pub(crate) fn macro_statement(&mut self, i: usize, b: &BlockRef, op: MacroOp) {
        if self.macro_b.is_none() {
            self.error(b, None, "Fanuc macro B statements need the Fanuc dialect".into());
            return;
        }
        match op {
            MacroOp::Goto(t) => self.goto(i, b, t),
            MacroOp::IfGoto(c, t) => {
                if self.m_cond(b, c) == Some(true) {
                    self.goto(i, b, t);
                }
            }
            MacroOp::IfThen(c) => {
                if self.m_cond(b, c) == Some(true) {
                    self.execute(b);
                }
            }
            MacroOp::Do(cond, m) => {
                let Some(end) = self.mstate().and_then(|s| s.loops.get(&i).copied()) else {
                    // Reported when the program was read: the loop cannot run.
                    self.error(b, None, format!("DO{m} has no matching END{m}: the program stops here"));
                    self.stopped = true;
                    return;
                };
                let go_on = match cond {
                    None => true,
                    Some(c) => match self.m_cond(b, c) {
                        Some(t) => t,
                        None => {
                            self.stopped = true;
                            return;
                        }
                    },
                };
                if !go_on {
                    self.pc = end + 1;
                }
            }
            MacroOp::End(m) => match self.mstate().and_then(|s| s.loops.get(&i).copied()) {
                Some(start) => {
                    if self.back_edge(i, b) {
                        self.pc = start;
                    }
                }
                None => {
                    self.error(b, None, format!("END{m} has no matching DO{m}: the program stops here"));
                    self.stopped = true;
                }
            },
        }
    }

    fn goto(&mut self, i: usize, b: &Block, t: ExprId) {
        let n = match self.macro_eval(t) {
            Ok(Some(v)) if (1.0..=99999.0).contains(&v.round()) => v.round() as u64,
            Ok(v) => {
                let shown = v.map_or("vacant".to_string(), |v| v.to_string());
                self.error(b, None, format!("GOTO {shown}: a sequence number is 1 to 99999"));
                self.stopped = true;
                return;
            }
            Err(m) => {
                self.eval_error(b, None, m);
                self.stopped = true;
                return;
            }
        };
        match self.find_seq(i, n) {
            // A jump back is a loop's back edge: an endless one whose state repeats stops there.
            Some(k) if k <= i && !self.back_edge(i, b) => {}
            Some(k) => self.pc = k,
            None => {
                self.error(b, None, format!("GOTO {n}: no block N{n} in this program"));
                self.stopped = true;
            }
        }
    }

    /// The block N`n` a jump from block `i` reaches: the first after `i` in `i`'s program, else
    /// the first from the program's top (the Fanuc search order).
    fn find_seq(&mut self, i: usize, n: u64) -> Option<usize> {
        let prog = self.prog;
        let s = self.macro_b.as_deref_mut()?;
        let seg = s.segment(i);
        if s.seq.is_none() {
            let mut map: HashMap<(usize, u64), Vec<usize>> = HashMap::new();
            let mut seg_k = 0;
            for blk in prog.blocks() {
                let k = blk.index();
                while seg_k + 1 < s.seg_starts.len() && s.seg_starts[seg_k + 1] <= k {
                    seg_k += 1;
                }
                if let (Some(bn), false) = (blk.n(), blk.bad) {
                    map.entry((seg_k, bn)).or_default().push(k);
                }
            }
            s.seq = Some(map);
        }
        let list = s.seq.as_ref()?.get(&(seg, n))?;
        let after = list.partition_point(|&k| k <= i);
        list.get(after).or(list.first()).copied()
    }

    /// A block with G65, G66 or G67 (plain-number G words): handled here; false for other blocks.
    pub(crate) fn macro_call_block(&mut self, b: &BlockRef) -> bool {
        let words = b.words();
        let code = words.iter().find_map(|w| match (w.letter, w.value()) {
            (b'G', Value::Num(x)) if x == 65.0 || x == 66.0 || x == 67.0 => Some((x as u8, w.at)),
            _ => None,
        });
        let Some((code, at)) = code else { return false };
        if code == 67 {
            if let Some(s) = self.macro_b.as_deref_mut() {
                s.modal_call = None;
            }
            if words.len() > 1 {
                self.error(
                    b,
                    Some(at),
                    "G67 stands alone in its block; the other words are ignored".into(),
                );
            }
            return true;
        }
        // Arguments: both specifications, in the order written; a later word wins.
        let mut args = Box::new([VACANT; 33]);
        let (mut p, mut l) = (None, None);
        let mut set = 0usize;
        let mut last_ijk: Option<usize> = None;
        for w in words {
            let v = match self.word_value(w.value()) {
                Ok(v) => v,
                Err(m) => {
                    self.eval_error(b, Some(w.at), m);
                    return true;
                }
            };
            let var = match w.letter {
                b'G' => continue,
                b'P' => {
                    p = v;
                    continue;
                }
                b'L' => {
                    l = v;
                    continue;
                }
                b'I' | b'J' | b'K' => {
                    let k = (w.letter - b'I') as usize;
                    if let Some(prev) = last_ijk {
                        if k <= prev {
                            set += 1;
                        }
                    }
                    last_ijk = Some(k);
                    if set >= 10 {
                        self.error(b, Some(w.at), "more than ten I, J, K argument sets".into());
                        return true;
                    }
                    4 + 3 * set + k
                }
                letter => match spec_one(letter) {
                    Some(var) => var,
                    None => {
                        let msg = format!("G{code}: {} is not an argument letter", letter as char);
                        self.error(b, Some(w.at), msg);
                        return true;
                    }
                },
            };
            if let Some(v) = v {
                args[var - 1] = v;
            }
        }
        let Some(p) = p else {
            self.error(b, Some(at), format!("G{code} needs P, the macro's program number"));
            return true;
        };
        if p < 0.0 || p.fract() != 0.0 || p > 99_999_999.0 {
            self.error(b, Some(at), format!("G{code} P{p}: not a program number"));
            return true;
        }
        let count = match l {
            None => 1,
            Some(l) if l >= 0.0 && l.fract() == 0.0 => l.min(1e9) as u64,
            Some(l) => {
                self.error(
                    b,
                    Some(at),
                    format!("G{code} L{l}: the repeat count must be a whole number"),
                );
                return true;
            }
        };
        let Some(&start) = self.labels.programs.get(&(p as u32)) else {
            self.error(b, Some(at), format!("G{code}: program O{p} is not in this file"));
            return true;
        };
        if code == 66 {
            let depth = self.frames.len();
            if let Some(s) = self.macro_b.as_deref_mut() {
                s.modal_call = Some(ModalCall {
                    start,
                    count,
                    args,
                    depth,
                });
            }
            return true;
        }
        self.macro_call(b, start, count, args, at);
        true
    }

    /// After block `b` moved the machine: the `G66` macro, when one is in force at this level.
    pub(crate) fn after_move_block(&mut self, b: &Block) {
        let Some(mc) = self.mstate().and_then(|s| s.modal_call.clone()) else {
            return;
        };
        if mc.depth != self.frames.len() {
            return;
        }
        let at = b.span.start;
        self.macro_call(b, mc.start, mc.count, mc.args, at);
    }

    /// Call the macro at block `start` `count` times with a new level of locals.
    fn macro_call(&mut self, b: &Block, start: usize, count: u64, args: Box<[f64; 33]>, at: u32) {
        if !self.enter_fanuc_program(b, Some(at), start, count, "macro calls") {
            return;
        }
        self.params.numbered[1..34].copy_from_slice(&args[..]);
        let depth = self.frames.len();
        if let Some(s) = self.macro_b.as_deref_mut() {
            s.levels.push((depth, args));
        }
    }

    /// `M99` (with `P`: return to that N number of the caller) in the Fanuc dialect. A `G65`
    /// level gives its locals back; an `M98` subprogram shares its caller's.
    pub(crate) fn macro_m99(&mut self, b: &Block, p: Option<f64>) {
        let depth = self.frames.len();
        let level = self
            .mstate()
            .and_then(|s| s.levels.last())
            .filter(|l| l.0 == depth)
            .map(|l| l.1.clone());
        let Some(f) = self.frames.last_mut() else {
            let msg = match p {
                Some(p) => {
                    format!("M99 P{p} in the main program jumps back without end (a bar-feed loop); checked once")
                }
                None => "M99 in the main program restarts it without end (a bar-feed loop); checked once".into(),
            };
            // Not an alarm: the control runs the program again (see `m99`). One pass is checked.
            self.warn_once(b, None, msg);
            self.stopped = true;
            return;
        };
        if f.repeats_left > 0 && p.is_none() {
            f.repeats_left -= 1;
            self.pc = f.body_pc;
            if let Some(args) = level {
                self.params.numbered[1..34].copy_from_slice(&args[..]);
            }
            return;
        }
        let Some(f) = self.frames.pop() else { return };
        if level.is_some() {
            self.params.numbered[1..34].copy_from_slice(&f.saved_locals);
            if let Some(s) = self.macro_b.as_deref_mut() {
                s.levels.pop();
            }
        }
        self.pc = f.return_pc;
        if let Some(p) = p {
            let n = p.round();
            if !(1.0..=99999.0).contains(&n) {
                self.error(b, None, format!("M99 P{p}: a sequence number is 1 to 99999"));
                self.stopped = true;
                return;
            }
            match self.find_seq(f.return_pc.saturating_sub(1), n as u64) {
                Some(k) => self.pc = k,
                None => {
                    self.error(b, None, format!("M99 P{n}: no block N{n} in the calling program"));
                    self.stopped = true;
                }
            }
        }
    }
}

fn var_index(v: f64) -> Result<u32, String> {
    super::eval::whole_index(v, "variable")
}

/// A 32-bit integer for the bit operations.
fn bits(x: f64) -> Result<i64, String> {
    let r = x.round();
    if r.abs() > u32::MAX as f64 {
        return Err(format!("{x} is too large for AND, OR, XOR (32-bit values)"));
    }
    Ok(r as i64)
}

/// A binary operation with Fanuc's vacant rules: EQ and NE tell vacant from 0, every other
/// operation reads vacant as 0.
fn binary(op: BinOp, a: MVal, b: MVal) -> Result<f64, String> {
    let (x, y) = (a.unwrap_or(0.0), b.unwrap_or(0.0));
    Ok(match op {
        BinOp::Pow => {
            if x < 0.0 && y.fract() != 0.0 {
                return Err(format!("POW[{x},{y}]: a negative number to a fractional power"));
            }
            if x == 0.0 && y <= 0.0 {
                return Err(format!("POW[0,{y}] is undefined"));
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
            // Both values rounded to whole numbers; the remainder has the dividend's sign.
            let (x, y) = (x.round(), y.round());
            if y == 0.0 {
                return Err("MOD by zero".into());
            }
            x % y
        }
        BinOp::Add => x + y,
        BinOp::Sub => x - y,
        BinOp::Gt => bool_f(x > y),
        BinOp::Ge => bool_f(x >= y),
        BinOp::Lt => bool_f(x < y),
        BinOp::Le => bool_f(x <= y),
        BinOp::And => (bits(x)? & bits(y)?) as f64,
        BinOp::Or => (bits(x)? | bits(y)?) as f64,
        BinOp::Xor => (bits(x)? ^ bits(y)?) as f64,
        BinOp::Eq | BinOp::Ne => bool_f((op == BinOp::Eq) == (a == b)),
    })
}

fn func(f: Func, x: f64) -> Result<f64, String> {
    Ok(match f {
        Func::Abs => x.abs(),
        // Fanuc (NAT = 0): ASIN 270°…90° (negative results as 270°…360°), ACOS 180°…0°.
        Func::Asin => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("ASIN[{x}]: argument out of [-1, 1]"));
            }
            x.asin().to_degrees().rem_euclid(360.0)
        }
        Func::Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(format!("ACOS[{x}]: argument out of [-1, 1]"));
            }
            x.acos().to_degrees()
        }
        Func::Cos => x.to_radians().cos(),
        Func::Sin => x.to_radians().sin(),
        Func::Tan => {
            let r = x.rem_euclid(180.0);
            if r == 90.0 {
                return Err(format!("TAN[{x}] is undefined"));
            }
            x.to_radians().tan()
        }
        Func::Exp => x.exp(),
        // Fanuc: FIX drops the fraction (toward zero), FUP raises it (away from zero).
        Func::Fix => x.trunc(),
        Func::Fup => {
            let t = x.trunc();
            if t == x {
                x
            } else {
                t + x.signum()
            }
        }
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
        Func::Bin => {
            let v = bits(x)?;
            if v < 0 {
                return Err(format!("BIN[{x}]: negative value"));
            }
            let (mut v, mut out, mut scale) = (v, 0i64, 1i64);
            while v > 0 {
                let d = v & 0xF;
                if d > 9 {
                    return Err(format!("BIN[{x}]: not a BCD value"));
                }
                out += d * scale;
                scale *= 10;
                v >>= 4;
            }
            out as f64
        }
        Func::Bcd => {
            let v = bits(x)?;
            if !(0..=99_999_999).contains(&v) {
                return Err(format!("BCD[{x}]: out of 0 to 99999999"));
            }
            let (mut v, mut out, mut shift) = (v, 0i64, 0);
            while v > 0 {
                out |= (v % 10) << shift;
                shift += 4;
                v /= 10;
            }
            out as f64
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::Limits;
    use crate::machine::Machine;
    use proptest::prelude::*;

    /// Interpret Fanuc text on the built-in machine; the canonical output and the findings.
    fn run(src: &str, fast: bool, max_blocks: u64) -> String {
        let prog = crate::gcode::parse_fanuc(src.as_bytes());
        let machine = Machine::builtin();
        let limits = Limits {
            max_blocks,
            max_call_depth: 16,
        };
        let mut r = Run::new(&prog, src.as_bytes(), &machine, limits);
        r.plain_blocks_fast = fast;
        r.run();
        let out = r.finish();
        let mut canon = Vec::new();
        crate::interp::canon::write(&out, &mut canon).unwrap();
        format!("{}{:?}", String::from_utf8_lossy(&canon), out.findings)
    }

    #[test]
    fn fix_and_fup_round_toward_and_away_from_zero() {
        assert_eq!(func(Func::Fix, -1.2), Ok(-1.0));
        assert_eq!(func(Func::Fup, -1.2), Ok(-2.0));
        assert_eq!(func(Func::Fix, 1.7), Ok(1.0));
        assert_eq!(func(Func::Fup, 1.2), Ok(2.0));
        assert_eq!(func(Func::Fup, 3.0), Ok(3.0));
    }

    #[test]
    fn bin_and_bcd_convert_both_ways_and_refuse_non_bcd() {
        assert_eq!(func(Func::Bcd, 1234.0), Ok(0x1234 as f64));
        assert_eq!(func(Func::Bin, 0x1234 as f64), Ok(1234.0));
        assert!(func(Func::Bin, 0x1A as f64).is_err());
        assert!(func(Func::Bcd, -1.0).is_err());
    }

    #[test]
    fn eq_and_ne_tell_vacant_from_zero_other_operations_do_not() {
        assert_eq!(binary(BinOp::Eq, None, Some(0.0)), Ok(0.0));
        assert_eq!(binary(BinOp::Eq, None, None), Ok(1.0));
        assert_eq!(binary(BinOp::Ne, None, Some(0.0)), Ok(1.0));
        assert_eq!(binary(BinOp::Ge, None, Some(0.0)), Ok(1.0));
        assert_eq!(binary(BinOp::Add, None, Some(2.0)), Ok(2.0));
        assert!(binary(BinOp::Div, Some(1.0), None).is_err());
    }

    #[test]
    fn a_goto_into_another_program_is_not_taken() {
        // N20 exists only in O2000: the jump from O0001 finds nothing.
        let out = run("O0001\nGOTO 20\nM30\nO2000\nN20 G0 X100\nM99\n", true, 1000);
        assert!(out.contains("GOTO 20: no block N20"), "{out}");
        assert!(!out.contains("STRAIGHT_TRAVERSE"), "{out}");
    }

    #[test]
    fn g66_is_not_called_after_a_tool_change_or_a_dwell() {
        let src = "O0001\nG0 X200 Z100\nG66 P9000\nT0202\nG4 X1\nG0 Z50\nG67\nM30\nO9000\nG0 U-2\nM99\n";
        let out = run(src, true, 1000);
        // One call, after the move of line 6.
        assert_eq!(out.matches(" 10 STRAIGHT_TRAVERSE").count(), 1, "{out}");
    }

    #[test]
    fn an_unsupported_system_variable_in_a_word_is_an_unsupported_finding() {
        let out = run("O0001\nG0 X#5061 Z100\n", true, 1000);
        assert!(out.contains("Unsupported") && out.contains("#5061"), "{out}");
    }

    #[test]
    fn a_macro_calling_itself_stops_at_the_call_depth_limit() {
        let out = run("O0001\nG65 P9000\nM30\nO9000\nG65 P9000\nM99\n", true, 100_000);
        assert!(out.contains("macro calls nested deeper than 16"), "{out}");
    }

    #[test]
    fn an_endless_while_loop_stops_at_the_budget() {
        let out = run("O0001\nWHILE [1] DO1\n#1 = #1 + 1\nEND1\n", true, 5000);
        assert!(out.contains("stopped after executing 5000 blocks"), "{out}");
    }

    /// An endless loop whose state never changes (found by fuzzing: it ran the whole 2M-block
    /// budget, over 2 s) stops after 2048 passes with a finding at its END; a long loop whose
    /// counter changes is never stopped by that test.
    #[test]
    fn a_loop_whose_state_repeats_stops_early_and_a_counting_loop_runs_out() {
        let out = run(
            "O0001\nG0 X200 Z100\nWHILE [1] DO1\nG0 X21 Z2\nG0 X40 Z5\nEND1\nM30\n",
            true,
            1_000_000,
        );
        assert!(out.contains("this loop never ends: after 2048 passes"), "{out}");
        assert!(out.contains("line: 6,"), "at its END1: {out}");
        assert!(!out.contains("stopped after executing"), "{out}");
        let out = run(
            "O0001\n#1 = 0\nWHILE [#1 LT 5000] DO1\n#1 = #1 + 1\nEND1\nM30\n",
            true,
            1_000_000,
        );
        assert!(!out.contains("never ends") && !out.contains("stopped after"), "{out}");
    }

    /// The same for a loop made by a backward GOTO (found by fuzzing: a part-family program whose
    /// counter assignment reads an unmodelled variable ran its 2M-block budget, 24 s).
    #[test]
    fn a_goto_loop_whose_state_repeats_stops_early() {
        let src = "O0001\nN1 G0 X100 Z5\nG0 X60 Z5\nIF [#1 LT 3] GOTO 1\nM30\n";
        let out = run(src, true, 1_000_000);
        assert!(out.contains("this loop never ends: after 2048 passes"), "{out}");
        assert!(out.contains("line: 4,"), "at the GOTO: {out}");
        // A counted GOTO loop runs its passes.
        let src = "O0001\n#1 = 0\nN1 G0 X100 Z5\n#1 = #1 + 1\nIF [#1 LT 3000] GOTO 1\nM30\n";
        let out = run(src, true, 1_000_000);
        assert!(!out.contains("never ends") && !out.contains("stopped after"), "{out}");
    }

    #[test]
    fn g65_words_are_not_the_modal_m_and_t_of_4113_and_4120() {
        // M13 and T20 of the G65 are arguments; #4113 stays the M3 of line 2.
        let src = "O0001\nM3\nG65 P9000 M13 T20\nG0 X200 Z[#4113]\nM30\nO9000\nM99\n";
        let out = run(src, true, 1000);
        assert!(out.contains("STRAIGHT_TRAVERSE(100.0000, 0.0000, 3.0000"), "{out}");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn random_macro_programs_never_panic_and_read_the_same_fast_or_not(
            lines in proptest::collection::vec(
                "(N[1-5] )?(#[1-3]=[0-9#\\[\\]+*/ ]{1,8}|#[1-3] ?= ?#[0-9]{1,4}|IF ?\\[#[1-3] ?(EQ|NE|LT|GE) ?[0-9#]{1,2}\\] ?(GOTO ?[1-5]|THEN #[1-3]=[0-9]{1,2})|WHILE ?\\[#[1-3] ?LT ?[0-9]\\] ?DO[1-3]|END[1-3]|GOTO ?#?[1-5]|G65 ?P900[0-1]( [ABIJKXZ][0-9#]{1,2}){0,4}|G66 ?P9000 A1|G67|M98 ?P900[0-1]( L[0-3])?|M99( P[1-5])?|G[01] ?X#?[0-9]{1,3} ?Z#?[0-9]{1,3}( F0.2)?|O900[0-1]|#3000=1|#3006=1)",
                1..25,
            ),
        ) {
            let src = lines.join("\n");
            let fast = run(&src, true, 3000);
            let general = run(&src, false, 3000);
            prop_assert_eq!(fast, general);
        }
    }
}
