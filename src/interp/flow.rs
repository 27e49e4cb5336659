//! The run: program counter, o-word control flow, subroutines (LinuxCNC `o… call`) and
//! subprograms (Fanuc `M98 P… L…` / `M99`), and the execution budget.

use super::state::{Frame, Modal, Params};
use super::{Interpretation, Limits, Move, SpindleDir};
use crate::finding::{Finding, Kind, Severity};
use crate::gcode::{Block, OName, OOp, Program};
use crate::geom::{P2, V2};
use crate::machine::{Dialect, Machine};
use std::collections::HashMap;

/// Where o-word structures jump, computed once before the run.
#[derive(Default)]
pub(crate) struct Labels {
    /// Subroutine name → block of its `sub`.
    pub subs: HashMap<OName, usize>,
    /// `sub` block → its `endsub` block.
    pub sub_end: HashMap<usize, usize>,
    /// Fanuc program number → block of its `O…` line.
    pub programs: HashMap<u32, usize>,
    /// For `while`/`repeat`/`do`, `if`/`elseif`/`else`: the matching end or next branch; for
    /// ends and `break`/`continue`: the structure's start.
    pub jump: HashMap<usize, usize>,
    /// `elseif`/`else` → their `endif`; `break` → the loop end; `while` closing a `do` → the `do`.
    pub end_of: HashMap<usize, usize>,
}

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Open {
    Sub,
    While,
    Do,
    If,
    Repeat,
}

impl Labels {
    fn build(prog: &Program, findings: &mut Vec<Finding>) -> Labels {
        let mut l = Labels::default();
        // (name, kind, block index, last branch of an if)
        let mut stack: Vec<(OName, Open, usize, usize)> = Vec::new();
        let name_text = |n: OName| match n {
            OName::Number(k) => format!("o{k}"),
            OName::Named(id) => format!("o<{}>", prog.name(id)),
        };
        for (i, b) in prog.blocks.iter().enumerate() {
            let Some(o) = &b.oword else { continue };
            if b.bad {
                continue;
            }
            let mut err = |msg: String| findings.push(Finding::program(b.line, 0, msg).with_n(b.n));
            let top = |stack: &Vec<(OName, Open, usize, usize)>, kinds: &[Open]| {
                stack
                    .iter()
                    .rposition(|&(n, k, _, _)| n == o.name && kinds.contains(&k))
            };
            match &o.op {
                OOp::ProgramNumber => {
                    if let OName::Number(n) = o.name {
                        l.programs.entry(n).or_insert(i);
                    }
                }
                OOp::Sub => {
                    if l.subs.insert(o.name, i).is_some() {
                        err(format!("subroutine {} is defined twice", name_text(o.name)));
                    }
                    stack.push((o.name, Open::Sub, i, i));
                }
                OOp::EndSub(_) => match top(&stack, &[Open::Sub]) {
                    Some(k) => {
                        let (_, _, start, _) = stack[k];
                        stack.truncate(k);
                        l.sub_end.insert(start, i);
                    }
                    None => err(format!("{} endsub without a matching sub", name_text(o.name))),
                },
                OOp::Do => stack.push((o.name, Open::Do, i, i)),
                OOp::While(_) => {
                    if let Some(k) = top(&stack, &[Open::Do]).filter(|&k| k + 1 == stack.len()) {
                        let (_, _, start, _) = stack[k];
                        stack.truncate(k);
                        l.end_of.insert(i, start); // do … while: the while ends the loop
                        l.jump.insert(start, i);
                    } else {
                        stack.push((o.name, Open::While, i, i));
                    }
                }
                OOp::EndWhile => match top(&stack, &[Open::While]) {
                    Some(k) => {
                        let (_, _, start, _) = stack[k];
                        stack.truncate(k);
                        l.jump.insert(start, i);
                        l.jump.insert(i, start);
                    }
                    None => err(format!("{} endwhile without a matching while", name_text(o.name))),
                },
                OOp::Repeat(_) => stack.push((o.name, Open::Repeat, i, i)),
                OOp::EndRepeat => match top(&stack, &[Open::Repeat]) {
                    Some(k) => {
                        let (_, _, start, _) = stack[k];
                        stack.truncate(k);
                        l.jump.insert(start, i);
                        l.jump.insert(i, start);
                    }
                    None => err(format!("{} endrepeat without a matching repeat", name_text(o.name))),
                },
                OOp::If(_) => stack.push((o.name, Open::If, i, i)),
                OOp::ElseIf(_) | OOp::Else => match top(&stack, &[Open::If]) {
                    Some(k) => {
                        let last = stack[k].3;
                        l.jump.insert(last, i);
                        stack[k].3 = i;
                    }
                    None => err(format!("{} else/elseif without a matching if", name_text(o.name))),
                },
                OOp::EndIf => match top(&stack, &[Open::If]) {
                    Some(k) => {
                        let (_, _, start, last) = stack[k];
                        stack.truncate(k);
                        l.jump.insert(last, i);
                        // Every branch of the chain ends at this endif.
                        let mut j = start;
                        while let Some(&next) = l.jump.get(&j) {
                            l.end_of.insert(j, i);
                            if next == i {
                                break;
                            }
                            j = next;
                        }
                    }
                    None => err(format!("{} endif without a matching if", name_text(o.name))),
                },
                OOp::Break | OOp::Continue => {
                    if top(&stack, &[Open::While, Open::Do, Open::Repeat]).is_none() {
                        err(format!(
                            "{} break/continue outside a loop of that name",
                            name_text(o.name)
                        ));
                    }
                    // Resolved at run time from the loop's start (its end may not be known yet).
                    if let Some(k) = top(&stack, &[Open::While, Open::Do, Open::Repeat]) {
                        l.end_of.insert(i, stack[k].2);
                    }
                }
                OOp::Call(_) | OOp::Return(_) => {}
            }
        }
        for (name, kind, i, _) in stack {
            let b = &prog.blocks[i];
            let what = match kind {
                Open::Sub => "sub without endsub",
                Open::While => "while without endwhile",
                Open::Do => "do without a closing while",
                Open::If => "if without endif",
                Open::Repeat => "repeat without endrepeat",
            };
            findings.push(Finding::program(b.line, 0, format!("{} {what}", name_text(name))).with_n(b.n));
        }
        l
    }
}

/// The interpreter's whole state during one run.
pub(crate) struct Run<'a> {
    pub prog: &'a Program,
    pub src: &'a [u8],
    pub machine: &'a Machine,
    pub limits: Limits,
    pub labels: Labels,
    pub modal: Modal,
    pub params: Params,
    pub frames: Vec<Frame>,
    /// Turret reference point, spindle frame.
    pub reference: P2,
    pub station: u32,
    /// The tip of the tool in `station`, relative to the turret reference point.
    pub tip: V2,
    /// LinuxCNC `T…` waiting for `M6`.
    pub selected: Option<u32>,
    pub spindle_dir: SpindleDir,
    /// Spindle-frame point of program X0 Z0 before G92/G52/G50 shifts.
    pub base_origin: P2,
    pub shift: V2,
    pub moves: Vec<Move>,
    pub states: Vec<super::MoveState>,
    pub findings: Vec<Finding>,
    pub executed: u64,
    pub pc: usize,
    pub stopped: bool,
    pub percent_seen: u32,
    pub current_line: u32,
    pub last_value: f64,
    pub value_returned: bool,
    pub saved_modal: Option<Modal>,
    /// Remaining passes of `repeat` loops of the main program.
    pub main_repeats: HashMap<usize, u64>,
    /// `Y0` was already reported once.
    pub y_reported: bool,
    /// The "no motion mode" problem was already reported.
    pub motion_reported: bool,
    /// Take [`Run::plain_block`] for the blocks it serves (off only in tests that compare).
    pub(crate) plain_blocks_fast: bool,
    /// The word table of [`Run::execute`], kept between blocks.
    pub(super) words: Option<Box<super::block::Words>>,
}

impl<'a> Run<'a> {
    pub fn new(prog: &'a Program, src: &'a [u8], machine: &'a Machine, limits: Limits) -> Run<'a> {
        let mut findings = Vec::new();
        let labels = Labels::build(prog, &mut findings);
        let fanuc = machine.dialect == Dialect::Fanuc;
        let modal = Modal {
            inch: false,
            incremental: false,
            arc_incremental: true,
            diameter: machine.diameter_mode,
            motion: None,
            feed_per_rev: fanuc,
            feed: 0.0,
            spindle_css: false,
            s: 0.0,
            css_clamp: None,
            plane_xz: true,
        };
        let station = machine.turret.start_station;
        Run {
            prog,
            src,
            machine,
            limits,
            labels,
            modal,
            params: Params::new(),
            frames: Vec::new(),
            reference: machine.home,
            station,
            tip: super::block::tip_of(machine, station),
            selected: None,
            spindle_dir: SpindleDir::Off,
            base_origin: P2::new(0.0, machine.program_zero_z),
            shift: V2::zeros(),
            moves: Vec::with_capacity(prog.blocks.len().min(1 << 22)),
            states: Vec::new(),
            findings,
            executed: 0,
            pc: 0,
            stopped: false,
            percent_seen: 0,
            current_line: 0,
            last_value: 0.0,
            value_returned: false,
            saved_modal: None,
            main_repeats: HashMap::new(),
            y_reported: false,
            motion_reported: false,
            words: None,
            plain_blocks_fast: true,
        }
    }

    pub fn finish(self) -> Interpretation {
        Interpretation {
            moves: self.moves,
            states: self.states,
            findings: self.findings,
            blocks_executed: self.executed,
        }
    }

    pub(crate) fn block(&self, i: usize) -> &'a Block {
        &self.prog.blocks[i]
    }

    pub(crate) fn error(&mut self, b: &Block, col_offset: Option<u32>, msg: String) {
        let col = col_offset.map_or(0, |o| self.prog.lines.col_of(self.src, o));
        self.findings.push(Finding::program(b.line, col, msg).with_n(b.n));
    }

    /// An `unsupported` finding: an error when the code moves the machine (the checked path is
    /// then incomplete), a warning when it does not.
    pub(crate) fn unsupported(&mut self, b: &Block, col_offset: Option<u32>, msg: String, moves_machine: bool) {
        let col = col_offset.map_or(0, |o| self.prog.lines.col_of(self.src, o));
        let sev = if moves_machine {
            Severity::Error
        } else {
            Severity::Warning
        };
        self.findings
            .push(Finding::at(Kind::Unsupported, sev, b.line, col, msg).with_n(b.n));
    }

    pub fn run(&mut self) {
        let n = self.prog.blocks.len();
        while self.pc < n && !self.stopped {
            let i = self.pc;
            let b = self.block(i);
            self.executed += 1;
            if self.executed > self.limits.max_blocks {
                self.error(
                    b,
                    None,
                    format!(
                        "stopped after executing {} blocks: the program seems to loop without end here",
                        self.limits.max_blocks
                    ),
                );
                break;
            }
            self.current_line = b.line;
            self.pc = i + 1;
            if b.bad {
                continue;
            }
            if b.percent {
                self.percent_seen += 1;
                if self.percent_seen >= 2 && self.frames.is_empty() {
                    break;
                }
            }
            if let Some(o) = &b.oword {
                self.oword(i, b, &o.op, o.name, o.span.start);
                if b.words.is_empty() && b.assigns.is_empty() {
                    continue;
                }
                if !matches!(o.op, OOp::ProgramNumber) {
                    continue;
                }
            }
            self.execute(b);
        }
    }

    fn cond(&mut self, b: &Block, e: crate::gcode::ExprId) -> Option<bool> {
        match self.eval(e) {
            Ok(v) => Some(v != 0.0),
            Err(m) => {
                self.error(b, None, m);
                None
            }
        }
    }

    fn oword(&mut self, i: usize, b: &Block, op: &OOp, name: OName, at: u32) {
        let jump = |s: &Self, k: usize| s.labels.jump.get(&k).copied();
        let end_of = |s: &Self, k: usize| s.labels.end_of.get(&k).copied();
        match op {
            OOp::ProgramNumber => {}
            OOp::Sub => {
                // A definition met in the flow of the program: skip its body.
                match self.labels.sub_end.get(&i) {
                    Some(&e) => self.pc = e + 1,
                    None => self.stopped = true,
                }
            }
            OOp::EndSub(v) | OOp::Return(v) => {
                if let Some(e) = v {
                    match self.eval(*e) {
                        Ok(x) => {
                            self.last_value = x;
                            self.value_returned = true;
                        }
                        Err(m) => self.error(b, None, m),
                    }
                } else {
                    self.value_returned = false;
                }
                self.return_from_call();
            }
            OOp::Call(args) => self.call(b, name, args, at),
            OOp::Do => {}
            OOp::While(c) => {
                let Some(t) = self.cond(b, *c) else {
                    self.pc = jump(self, i).map_or(self.pc, |e| e + 1);
                    return;
                };
                if let Some(start) = end_of(self, i) {
                    // The end of a do … while loop.
                    if t {
                        self.pc = start + 1;
                    }
                } else if !t {
                    match jump(self, i) {
                        Some(e) => self.pc = e + 1,
                        None => self.stopped = true,
                    }
                }
            }
            OOp::EndWhile => {
                if let Some(s) = jump(self, i) {
                    self.pc = s;
                }
            }
            OOp::Repeat(c) => {
                let counts = match self.frames.last() {
                    Some(f) => &f.repeat_counts,
                    None => &self.main_repeats,
                };
                let count = match counts.get(&i).copied() {
                    Some(c) => c,
                    None => match self.eval(*c) {
                        Ok(v) if v >= 0.0 => v.round().min(u64::MAX as f64) as u64,
                        Ok(v) => {
                            self.error(b, None, format!("repeat count {v} is negative"));
                            0
                        }
                        Err(m) => {
                            self.error(b, None, m);
                            0
                        }
                    },
                };
                if count == 0 {
                    self.repeat_counts_mut().remove(&i);
                    match jump(self, i) {
                        Some(e) => self.pc = e + 1,
                        None => self.stopped = true,
                    }
                } else {
                    self.repeat_counts_mut().insert(i, count - 1);
                }
            }
            OOp::EndRepeat => {
                if let Some(s) = jump(self, i) {
                    self.pc = s;
                }
            }
            OOp::If(c) => {
                let mut taken = self.cond(b, *c).unwrap_or(false);
                let mut k = i;
                while !taken {
                    let Some(next) = jump(self, k) else {
                        self.stopped = true;
                        return;
                    };
                    let nb = self.block(next);
                    match nb.oword.as_ref().map(|o| &o.op) {
                        Some(OOp::ElseIf(c2)) => {
                            taken = self.cond(nb, *c2).unwrap_or(false);
                            k = next;
                        }
                        _ => {
                            // else or endif: continue after it
                            k = next;
                            taken = true;
                        }
                    }
                }
                self.pc = k + 1;
            }
            OOp::ElseIf(_) | OOp::Else => {
                // Reached by falling out of a taken branch.
                if let Some(e) = end_of(self, i) {
                    self.pc = e + 1;
                }
            }
            OOp::EndIf => {}
            OOp::Break | OOp::Continue => {
                let Some(start) = end_of(self, i) else { return };
                let is_break = matches!(op, OOp::Break);
                let end = jump(self, start);
                let start_op = self.block(start).oword.as_ref().map(|o| o.op.clone());
                match (is_break, start_op) {
                    (true, Some(OOp::Repeat(_))) => {
                        self.repeat_counts_mut().remove(&start);
                        self.pc = end.map_or(self.prog.blocks.len(), |e| e + 1);
                    }
                    (true, _) => self.pc = end.map_or(self.prog.blocks.len(), |e| e + 1),
                    (false, Some(OOp::Do)) => self.pc = end.unwrap_or(start),
                    (false, _) => self.pc = start,
                }
            }
        }
    }

    fn repeat_counts_mut(&mut self) -> &mut HashMap<usize, u64> {
        match self.frames.last_mut() {
            Some(f) => &mut f.repeat_counts,
            None => &mut self.main_repeats,
        }
    }

    fn locals_snapshot(&self) -> [f64; 33] {
        let mut s = [0.0; 33];
        s.copy_from_slice(&self.params.numbered[1..34]);
        s
    }

    fn call(&mut self, b: &Block, name: OName, args: &[crate::gcode::ExprId], at: u32) {
        let Some(&start) = self.labels.subs.get(&name) else {
            let text = match name {
                OName::Number(k) => format!("o{k}"),
                OName::Named(id) => format!("o<{}>", self.prog.name(id)),
            };
            self.error(
                b,
                Some(at),
                format!("subroutine {text} is not defined in this file (latheguard reads one file; subroutine files are not searched)"),
            );
            return;
        };
        if self.call_depth() >= self.limits.max_call_depth {
            self.error(
                b,
                Some(at),
                format!("subroutine calls nested deeper than {}", self.limits.max_call_depth),
            );
            self.stopped = true;
            return;
        }
        let mut values = Vec::with_capacity(args.len());
        for &a in args {
            match self.eval(a) {
                Ok(v) => values.push(v),
                Err(m) => {
                    self.error(b, Some(at), m);
                    return;
                }
            }
        }
        if values.len() > 30 {
            self.error(
                b,
                Some(at),
                format!("{} arguments; a call takes at most 30", values.len()),
            );
            return;
        }
        let saved = self.locals_snapshot();
        self.frames.push(Frame {
            return_pc: self.pc,
            body_pc: start + 1,
            repeats_left: 0,
            saved_locals: saved,
            locals: HashMap::new(),
            autorestore: None,
            repeat_counts: HashMap::new(),
            fanuc: false,
        });
        for k in 1..=30 {
            self.params.numbered[k] = values.get(k - 1).copied().unwrap_or(0.0);
        }
        self.value_returned = false;
        self.pc = start + 1;
    }

    fn call_depth(&self) -> usize {
        self.frames.len()
    }

    /// Return from the innermost o-word call (endsub/return).
    fn return_from_call(&mut self) {
        if let Some(f) = self.frames.pop() {
            self.params.numbered[1..34].copy_from_slice(&f.saved_locals);
            if let Some(m) = f.autorestore {
                self.modal = m;
            }
            self.pc = f.return_pc;
        }
    }

    /// Fanuc `M98 P… L…`: call subprogram `O…` of this file.
    pub(crate) fn m98(&mut self, b: &Block, p: Option<f64>, l: Option<f64>, col: Option<u32>) {
        let Some(p) = p else {
            self.error(b, col, "M98 needs P, the subprogram number".into());
            return;
        };
        if p < 0.0 || p.fract() != 0.0 || p > 99_999_999.0 {
            self.error(b, col, format!("M98 P{p}: not a program number"));
            return;
        }
        let p = p as u64;
        // Fanuc: P with more than 4 digits holds the repeat count in front of the number.
        let (count, number) = if p > 9999 && l.is_none() {
            (p / 10000, (p % 10000) as u32)
        } else {
            (1, p as u32)
        };
        let count = match l {
            Some(l) if l >= 0.0 && l.fract() == 0.0 => l as u64,
            Some(l) => {
                self.error(b, col, format!("M98 L{l}: the repeat count must be a whole number"));
                return;
            }
            None => count.max(1),
        };
        let Some(&start) = self.labels.programs.get(&number) else {
            self.error(b, col, format!("M98: subprogram O{number} is not in this file"));
            return;
        };
        if count == 0 {
            return;
        }
        if self.call_depth() >= self.limits.max_call_depth {
            self.error(
                b,
                col,
                format!("subprogram calls nested deeper than {}", self.limits.max_call_depth),
            );
            self.stopped = true;
            return;
        }
        let saved = self.locals_snapshot();
        self.frames.push(Frame {
            return_pc: self.pc,
            body_pc: start + 1,
            repeats_left: count - 1,
            saved_locals: saved,
            locals: HashMap::new(),
            autorestore: None,
            repeat_counts: HashMap::new(),
            fanuc: true,
        });
        self.pc = start + 1;
    }

    /// `M99`: end of a subprogram pass.
    pub(crate) fn m99(&mut self, b: &Block) {
        match self.frames.last() {
            Some(f) if f.fanuc => {
                let f = self.frames.last_mut().unwrap();
                if f.repeats_left > 0 {
                    f.repeats_left -= 1;
                    self.pc = f.body_pc;
                } else {
                    let f = self.frames.pop().unwrap();
                    self.params.numbered[1..34].copy_from_slice(&f.saved_locals);
                    self.pc = f.return_pc;
                }
            }
            Some(_) => {
                self.error(b, None, "M99 ends an o-word subroutine: use endsub or return".into());
                self.return_from_call();
            }
            None => {
                self.error(
                    b,
                    None,
                    "M99 in the main program restarts it without end (a bar-feed loop); checked once".into(),
                );
                self.stopped = true;
            }
        }
    }
}
