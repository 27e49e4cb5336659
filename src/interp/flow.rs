//! The run: program counter, o-word control flow, subroutines (LinuxCNC `o… call`) and
//! subprograms (Fanuc `M98 P… L…` / `M99`), and the execution budget.

use super::state::{Frame, Modal, Params};
use super::{Interpretation, Limits, Move, SpindleDir};
use crate::finding::{push_capped, Finding, Kind, LeftOut, Severity};
use crate::gcode::{Block, BlockRef, OName, OOp, Program};
use crate::geom::{P2, V2};
use crate::machine::{Dialect, Machine};
use std::collections::{HashMap, HashSet};

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

#[derive(Clone, Copy, PartialEq, Eq, Hash, Debug)]
enum Open {
    Sub,
    While,
    Do,
    If,
    Repeat,
}

/// The o-word structures open while [`Labels::build`] reads the program, with an index from
/// (name, kind) to their places in the stack, so that finding the innermost open structure of a
/// name costs the same however deep the stack is (a closer that matches nothing must not scan it).
#[derive(Default)]
struct OpenStack {
    /// (name, kind, block index, last branch of an if)
    items: Vec<(OName, Open, usize, usize)>,
    /// Places in `items` of each (name, kind), ascending.
    at: HashMap<(OName, Open), Vec<usize>>,
}

impl OpenStack {
    fn push(&mut self, name: OName, kind: Open, block: usize) {
        self.at.entry((name, kind)).or_default().push(self.items.len());
        self.items.push((name, kind, block, block));
    }

    /// The place of the innermost open structure named `name` of one of `kinds`.
    fn top(&self, name: OName, kinds: &[Open]) -> Option<usize> {
        kinds
            .iter()
            .filter_map(|&k| self.at.get(&(name, k)).and_then(|v| v.last().copied()))
            .max()
    }

    /// Close the structure at place `k` and every one opened inside it.
    fn truncate(&mut self, k: usize) {
        while self.items.len() > k {
            let Some((name, kind, _, _)) = self.items.pop() else {
                break;
            };
            if let Some(v) = self.at.get_mut(&(name, kind)) {
                v.pop();
                if v.is_empty() {
                    self.at.remove(&(name, kind));
                }
            }
        }
    }
}

impl Labels {
    fn build(prog: &Program, findings: &mut Vec<Finding>, left_out: &mut LeftOut) -> Labels {
        let mut l = Labels::default();
        let mut stack = OpenStack::default();
        let name_text = |n: OName| match n {
            OName::Number(k) => format!("o{k}"),
            OName::Named(id) => format!("o<{}>", prog.name(id)),
        };
        for b in prog.rare_blocks() {
            let i = b.index();
            let Some(o) = b.oword() else { continue };
            if b.bad {
                continue;
            }
            let mut err = |msg: String| {
                push_capped(findings, left_out, Finding::program(b.line, 0, msg).with_n(b.n()));
            };
            let top = |stack: &OpenStack, kinds: &[Open]| stack.top(o.name, kinds);
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
                    stack.push(o.name, Open::Sub, i);
                }
                OOp::EndSub(_) => match top(&stack, &[Open::Sub]) {
                    Some(k) => {
                        let (_, _, start, _) = stack.items[k];
                        stack.truncate(k);
                        l.sub_end.insert(start, i);
                    }
                    None => err(format!("{} endsub without a matching sub", name_text(o.name))),
                },
                OOp::Do => stack.push(o.name, Open::Do, i),
                OOp::While(_) => {
                    // A `while` right after its `do` (innermost open structure) closes it.
                    if let Some(&(_, Open::Do, start, _)) = stack.items.last().filter(|t| t.0 == o.name) {
                        stack.truncate(stack.items.len() - 1);
                        l.end_of.insert(i, start); // do … while: the while ends the loop
                        l.jump.insert(start, i);
                    } else {
                        stack.push(o.name, Open::While, i);
                    }
                }
                OOp::EndWhile => match top(&stack, &[Open::While]) {
                    Some(k) => {
                        let (_, _, start, _) = stack.items[k];
                        stack.truncate(k);
                        l.jump.insert(start, i);
                        l.jump.insert(i, start);
                    }
                    None => err(format!("{} endwhile without a matching while", name_text(o.name))),
                },
                OOp::Repeat(_) => stack.push(o.name, Open::Repeat, i),
                OOp::EndRepeat => match top(&stack, &[Open::Repeat]) {
                    Some(k) => {
                        let (_, _, start, _) = stack.items[k];
                        stack.truncate(k);
                        l.jump.insert(start, i);
                        l.jump.insert(i, start);
                    }
                    None => err(format!("{} endrepeat without a matching repeat", name_text(o.name))),
                },
                OOp::If(_) => stack.push(o.name, Open::If, i),
                OOp::ElseIf(_) | OOp::Else => match top(&stack, &[Open::If]) {
                    Some(k) => {
                        let last = stack.items[k].3;
                        l.jump.insert(last, i);
                        stack.items[k].3 = i;
                    }
                    None => err(format!("{} else/elseif without a matching if", name_text(o.name))),
                },
                OOp::EndIf => match top(&stack, &[Open::If]) {
                    Some(k) => {
                        let (_, _, start, last) = stack.items[k];
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
                    // Resolved at run time from the loop's start (its end may not be known yet).
                    match top(&stack, &[Open::While, Open::Do, Open::Repeat]) {
                        Some(k) => {
                            l.end_of.insert(i, stack.items[k].2);
                        }
                        None => err(format!(
                            "{} break/continue outside a loop of that name",
                            name_text(o.name)
                        )),
                    }
                }
                OOp::Call(_) | OOp::Return(_) => {}
            }
        }
        for (name, kind, i, _) in stack.items {
            let b = prog.block(i);
            let what = match kind {
                Open::Sub => "sub without endsub",
                Open::While => "while without endwhile",
                Open::Do => "do without a closing while",
                Open::If => "if without endif",
                Open::Repeat => "repeat without endrepeat",
            };
            let f = Finding::program(b.line, 0, format!("{} {what}", name_text(name))).with_n(b.n());
            push_capped(findings, left_out, f);
        }
        l
    }
}

/// A consumer of moves as they are made, with the states they refer to.
pub(super) type MoveSink<'a> = Box<dyn FnMut(super::Chunk<'_>) + 'a>;

/// Moves collected before a streaming run hands them over.
pub const STREAM_CHUNK: usize = 4096;

/// The interpreter's whole state during one run.
pub(crate) struct Run<'a> {
    pub prog: &'a Program<'a>,
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
    /// Tailstock, chuck, unknown tool (src/interp/mcodes.rs).
    pub(super) devices: super::mcodes::Devices,
    /// Spindle-frame point of program X0 Z0 before G92/G52/G50 shifts.
    pub base_origin: P2,
    /// The work offset in force: 0 = G54 … 5 = G59 (`Machine::work_zero` gives its zero).
    pub coord_system: u8,
    pub shift: V2,
    pub moves: Vec<Move>,
    /// Where moves go as they are made, when the caller streams them ([`super::interpret_streaming`]):
    /// `moves` is handed over and emptied between top-level blocks once it holds `chunk`.
    pub(super) sink: Option<MoveSink<'a>>,
    /// With a sink: hand `moves` over once it holds this many (between top-level blocks).
    pub(super) chunk: usize,
    /// Moves handed to the sink so far (the index of `moves[0]` in the whole run).
    pub(super) handed: u64,
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
    /// Loop back edges (block index) → passes made and the state at the last checked pass
    /// ([`Run::back_edge`]).
    pub(super) loop_marks: HashMap<usize, (u64, Vec<u64>)>,
    /// `Y0` was already reported once.
    pub y_reported: bool,
    /// The block (its address) one of whose moves went out of range ([`super::MAX_COORD`]): its
    /// later moves are not made either (a cycle stops at its first such move). Cleared before
    /// each block of the program's flow.
    pub(super) out_of_range: Option<usize>,
    /// The "no motion mode" problem was already reported.
    pub motion_reported: bool,
    /// Take [`Run::plain_block`] for the blocks it serves (off only in tests that compare).
    pub(crate) plain_blocks_fast: bool,
    /// The word table of [`Run::execute`], kept between blocks.
    pub(super) words: Option<Box<super::words::Words>>,
    /// What canned cycles remember between blocks (Fanuc two-block forms, N-number index).
    pub(super) cycles: super::cycles::Memory,
    /// The modal words of the canned cycle in force (Fanuc box and drilling cycles).
    pub(super) cycle: super::cycles::Sticky,
    /// Columns of findings, counted on from the last one (many findings on one long line).
    cols: crate::source::ColCursor,
    /// The findings kept so far (a block in a loop reports its problem once, and repeats do not
    /// fill the [`crate::finding::MAX_FINDINGS`] cap).
    reported: HashSet<(u32, u32, Kind, String)>,
    /// Findings not kept: the cap was reached.
    pub left_out: LeftOut,
    /// Findings reported by blocks so far, kept or not (a block learns from it that a step of
    /// its own was refused).
    pub reports: u64,
    /// Nose-radius compensation (src/interp/comp.rs): none until the first G41/G42.
    pub(super) comp: Option<Box<super::comp::Comp>>,
    /// Fanuc macro B (the Fanuc dialect only): see `macro_b.rs`.
    pub(crate) macro_b: Option<Box<super::macro_b::State>>,
    /// The extra axes and turn-mill modes, on a machine whose kinematics has extra axes
    /// (`turnmill.rs`); `None` on a 2-axis lathe.
    pub(crate) tm: Option<Box<super::turnmill::TurnMill>>,
    /// The job's operations after the first: which starts next (`operations.rs`).
    pub(super) ops: super::operations::Ops,
}

impl<'a> Run<'a> {
    pub fn new(prog: &'a Program, src: &'a [u8], machine: &'a Machine, limits: Limits) -> Run<'a> {
        let mut findings = Vec::new();
        let mut left_out = LeftOut::default();
        let labels = Labels::build(prog, &mut findings, &mut left_out);
        let fanuc = machine.dialect == Dialect::Fanuc;
        let macro_b = fanuc.then(|| Box::new(super::macro_b::State::new(prog, &mut findings, &mut left_out)));
        let mut params = Params::new();
        if fanuc {
            // Fanuc: locals and common variables start vacant.
            params.numbered[1..34].fill(super::macro_b::VACANT);
            params.numbered[100..1000].fill(super::macro_b::VACANT);
        }
        let modal = Modal {
            inch: machine.inch,
            incremental: false,
            arc_incremental: true,
            diameter: machine.diameter_mode,
            motion: None,
            group1: None,
            feed_per_rev: fanuc,
            feed: 0.0,
            spindle_css: false,
            // `spindle.start_rpm`: running from program start, as if `M3 S…` came first.
            s: machine.start_rpm.unwrap_or(0.0),
            css_clamp: None,
            plane_xz: true,
            plane_xy: false,
        };
        let station = machine.turret.start_station;
        Run {
            prog,
            src,
            machine,
            limits,
            labels,
            modal,
            params,
            frames: Vec::new(),
            reference: machine.home,
            station,
            tip: super::convert::tip_of(machine, station),
            selected: None,
            spindle_dir: if machine.start_rpm.is_some() {
                SpindleDir::Cw
            } else {
                SpindleDir::Off
            },
            devices: super::mcodes::Devices::new(machine),
            base_origin: machine.work_zero(0).unwrap_or(P2::new(0.0, machine.program_zero_z)),
            coord_system: 0,
            shift: V2::zeros(),
            moves: Vec::new(),
            sink: None,
            chunk: STREAM_CHUNK,
            handed: 0,
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
            loop_marks: HashMap::new(),
            y_reported: false,
            out_of_range: None,
            motion_reported: false,
            words: None,
            cycles: Default::default(),
            cycle: Default::default(),
            plain_blocks_fast: true,
            cols: crate::source::ColCursor::new(),
            reported: HashSet::new(),
            left_out,
            reports: 0,
            comp: None,
            macro_b,
            tm: super::turnmill::TurnMill::new(machine).map(Box::new),
            ops: Default::default(),
        }
    }

    /// Give the moves made so far to the sink, if there is one, with their extra-axis entries
    /// (which leave the run with them: a streamed run keeps neither list whole).
    pub(super) fn hand_over(&mut self) {
        let Some(sink) = self.sink.as_mut() else {
            return;
        };
        let first = self.handed;
        let end = first + self.moves.len() as u64;
        // Between top-level blocks the entries of these moves are final (a cycle takes back only
        // moves of its own block); entries past `end` are of moves taken back, dropped later.
        let extra = match self.tm.as_deref() {
            Some(tm) => &tm.list[..tm.list.partition_point(|e| u64::from(e.index) < end)],
            None => &[][..],
        };
        let handed_extra = extra.len();
        sink(super::Chunk {
            first: first as usize,
            moves: &self.moves,
            states: &self.states,
            extra,
        });
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.list.drain(..handed_extra);
            tm.handed = end;
        }
        self.handed = end;
        self.moves.clear();
    }

    pub fn finish(mut self) -> Interpretation {
        // Moves nose-radius compensation still holds (the program ended with it on).
        self.comp_flush();
        self.contour_comp_flush();
        if self.ops_pending() {
            self.operations_not_started();
        }
        self.hand_over();
        // The moves were reserved for one per block; give back a large unused part (address
        // space counts against a memory cap even when never touched).
        if self.moves.capacity() - self.moves.len() > self.moves.len() / 4 + 1024 {
            self.moves.shrink_to_fit();
        }
        Interpretation {
            extra: self.take_extra(),
            moves: self.moves,
            states: self.states,
            findings: self.findings,
            findings_left_out: self.left_out,
            blocks_executed: self.executed,
        }
    }

    pub(crate) fn block(&self, i: usize) -> BlockRef {
        self.prog.block(i)
    }

    pub(crate) fn error(&mut self, b: &Block, col_offset: Option<u32>, msg: String) {
        if self.macro_b.as_ref().is_some_and(|m| m.unsupported.take()) {
            // The evaluation failed on a variable latheguard does not model.
            self.unsupported(b, col_offset, msg, true);
            return;
        }
        let col = col_offset.map_or(0, |o| self.cols.col_of(self.src, o));
        self.report(Finding::program(b.line, col, msg).with_n(b.n()));
    }

    /// A value the control cannot compute (division by zero, a function outside its domain, a
    /// parameter number out of range, …): a `program` finding at `b`, and the run stops, as the
    /// control stops with an alarm (Fanuc) or aborts the program (LinuxCNC) — nothing after it
    /// runs (docs/macro-b.md, docs/reference-rs274.md). A failure on a variable latheguard does
    /// not model is an `unsupported` finding and the run goes on (`error`).
    pub(crate) fn eval_error(&mut self, b: &Block, col_offset: Option<u32>, msg: String) {
        if self.macro_b.as_ref().is_some_and(|m| m.unsupported.get()) {
            self.error(b, col_offset, msg);
            return;
        }
        self.error(
            b,
            col_offset,
            format!("{msg}: the control stops here with an alarm (nothing after it runs)"),
        );
        self.stopped = true;
    }

    /// Keep a finding of the run, once, up to the cap.
    pub(crate) fn report_finding(&mut self, f: Finding) {
        self.report(f);
    }

    /// Keep a finding of the run, once, up to the cap.
    fn report(&mut self, f: Finding) {
        self.reports += 1;
        let key = (f.line, f.col, f.kind, f.message);
        if self.reported.contains(&key) {
            return;
        }
        let (line, col, kind, message) = key;
        let f = Finding { message, ..f };
        if self.findings.len() < crate::finding::MAX_FINDINGS {
            self.reported.insert((line, col, kind, f.message.clone()));
        }
        push_capped(&mut self.findings, &mut self.left_out, f);
    }

    /// An `unsupported` finding: an error when the code moves the machine (the checked path is
    /// then incomplete), a warning when it does not.
    pub(crate) fn unsupported(&mut self, b: &Block, col_offset: Option<u32>, msg: String, moves_machine: bool) {
        let col = col_offset.map_or(0, |o| self.cols.col_of(self.src, o));
        let sev = if moves_machine {
            Severity::Error
        } else {
            Severity::Warning
        };
        self.report(Finding::at(Kind::Unsupported, sev, b.line, col, msg).with_n(b.n()));
    }

    pub fn run(&mut self) {
        let n = self.prog.len();
        while self.pc < n && !self.stopped {
            // Between top-level blocks no cycle holds a mark into the moves: they may go.
            if self.moves.len() >= self.chunk {
                self.hand_over();
            }
            let i = self.pc;
            let b = &self.block(i);
            if !self.count_executed(b) {
                break;
            }
            self.current_line = b.line;
            self.pc = i + 1;
            self.out_of_range = None;
            if b.bad {
                continue;
            }
            if b.percent {
                self.percent_seen += 1;
                if self.percent_seen >= 2 && self.frames.is_empty() {
                    break;
                }
            }
            if let Some(o) = b.oword() {
                self.oword(i, b, &o.op, o.name, o.span.start);
                if b.words.is_empty() && b.assigns().is_empty() {
                    continue;
                }
                if !matches!(o.op, OOp::ProgramNumber) {
                    continue;
                }
            }
            if let Some(m) = b.macro_stmt() {
                self.macro_statement(i, b, m.op);
                continue;
            }
            if self.macro_b.is_some() {
                self.execute_fanuc(b);
            } else {
                self.execute(b);
            }
        }
    }

    /// A Fanuc block: G65–G67 macro calls, the block, then a `G66` call after a move, and the
    /// D, H, M, T, N bookkeeping of the modal variables.
    fn execute_fanuc(&mut self, b: &BlockRef) {
        let Some(m) = self.macro_b.as_deref() else {
            self.execute(b);
            return;
        };
        // A failed evaluation nobody reported must not mark a later finding.
        m.unsupported.set(false);
        let (call, modal_call, note) = (
            super::macro_b::State::is_call_block(b),
            m.modal_call_active(),
            m.notes_words(),
        );
        if call && self.macro_call_block(b) {
            // Its words are arguments, not the modal D, H, M, T of #4107 … #4120.
            return;
        }
        if !(modal_call || note) {
            self.execute(b);
            return;
        }
        let (moves, depth) = (self.moves.len(), self.frames.len());
        self.execute(b);
        if modal_call && self.frames.len() == depth && !self.stopped {
            let moved = self.moves[moves.min(self.moves.len())..].iter().any(|m| {
                !matches!(
                    m.kind,
                    super::MoveKind::Dwell { .. }
                        | super::MoveKind::ToolChange { .. }
                        | super::MoveKind::Operation { .. }
                        | super::MoveKind::Wait { .. }
                )
            });
            if moved {
                self.after_move_block(b);
            }
        }
        if let Some(m) = self.macro_b.as_deref_mut() {
            m.note(b);
        }
    }

    /// A loop's back edge at block `i` (macro B `ENDm`, a LinuxCNC `endwhile`) is taken: false,
    /// with a `program` error at `b` and the run stopped, when the loop provably never ends. At
    /// the 1024th pass and every power of two after it, everything a loop's condition and body
    /// can read (parameters and system variables: the positions, the modal state, the tool, the
    /// call frames, macro B's levels and counters) is compared with that state at the previous
    /// such pass: the same state at the same block means the run is in a cycle that repeats for
    /// ever (interpreting is deterministic). So an endless loop ends after about 2048 passes
    /// instead of the whole block budget. A loop whose state changes (a counter, a position) is
    /// never stopped here; its work stays bounded by the budget.
    pub(super) fn back_edge(&mut self, i: usize, b: &Block) -> bool {
        let passes = {
            let e = self.loop_marks.entry(i).or_insert((0, Vec::new()));
            e.0 += 1;
            e.0
        };
        if passes < 1024 || !passes.is_power_of_two() {
            return true;
        }
        let state = self.loop_state();
        let Some(mark) = self.loop_marks.get_mut(&i) else {
            return true;
        };
        if mark.1 == state {
            self.error(
                b,
                None,
                format!(
                    "this loop never ends: after {} passes the program's state is what it was {} passes earlier; \
                     the run stops here",
                    passes,
                    passes / 2
                ),
            );
            self.stopped = true;
            return false;
        }
        mark.1 = state;
        true
    }

    /// The state a loop can read, as words to compare (see [`Run::back_edge`]).
    fn loop_state(&self) -> Vec<u64> {
        let mut v: Vec<u64> = self.params.numbered.iter().map(|x| x.to_bits()).collect();
        let mut named: Vec<(u32, u64)> = self.params.global.iter().map(|(k, x)| (*k, x.to_bits())).collect();
        named.sort_unstable();
        v.extend(named.into_iter().flat_map(|(k, x)| [u64::from(k), x]));
        for p in [self.reference.coords, self.tip, self.shift, self.base_origin.coords] {
            v.extend([p.x.to_bits(), p.y.to_bits()]);
        }
        v.extend([
            u64::from(self.station),
            self.selected.map_or(u64::MAX, u64::from),
            u64::from(self.coord_system),
        ]);
        // Modes and frames by their printed form (exact for numbers; a map printed in another
        // order only makes two states look different, never alike).
        let text = format!("{:?}|{:?}|{:?}", self.modal, self.frames, self.spindle_dir);
        v.extend(text.bytes().map(u64::from));
        if let Some(m) = self.macro_b.as_deref() {
            m.loop_state(&mut v);
        }
        v
    }

    /// Count one block executed (or one `elseif` tested) against the budget; false, with a
    /// `program` finding at `b`, when the budget is spent.
    pub(super) fn count_executed(&mut self, b: &Block) -> bool {
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
            self.stopped = true;
            return false;
        }
        true
    }

    fn cond(&mut self, b: &Block, e: crate::gcode::ExprId) -> Option<bool> {
        match self.eval(e) {
            Ok(v) => Some(v != 0.0),
            Err(m) => {
                self.eval_error(b, None, m);
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
                        Err(m) => self.eval_error(b, None, m),
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
                    if self.back_edge(i, b) {
                        self.pc = s;
                    }
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
                            self.eval_error(b, None, m);
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
                    let nb = &self.block(next);
                    match nb.oword().map(|o| &o.op) {
                        Some(OOp::ElseIf(c2)) => {
                            // Each branch tested is a block executed: a long chain in a loop
                            // must not outlast the budget.
                            if !self.count_executed(nb) {
                                return;
                            }
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
                let start_op = self.block(start).oword().map(|o| o.op.clone());
                match (is_break, start_op) {
                    (true, Some(OOp::Repeat(_))) => {
                        self.repeat_counts_mut().remove(&start);
                        self.pc = end.map_or(self.prog.len(), |e| e + 1);
                    }
                    (true, _) => self.pc = end.map_or(self.prog.len(), |e| e + 1),
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
                    self.eval_error(b, Some(at), m);
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

    /// Run subroutine `name` from here to its return, as a call with no arguments made by block
    /// `b` (a LinuxCNC G70–G72 cycle reading its profile, `cycles/lcnc_rough.rs`). The program
    /// counter and the current line are as before afterwards; `false` when the subroutine does
    /// not exist (`None`, a finding at `b`) or did not return (the program stopped, or the budget
    /// ran out).
    pub(crate) fn run_sub_inline(&mut self, b: &Block, name: OName, at: u32) -> Option<bool> {
        let depth = self.frames.len();
        let (pc, line) = (self.pc, self.current_line);
        self.call(b, name, &[], at);
        if self.frames.len() == depth {
            return None;
        }
        let n = self.prog.len();
        while self.frames.len() > depth && !self.stopped && self.pc < n {
            let i = self.pc;
            let blk = &self.block(i);
            if !self.count_executed(blk) {
                break;
            }
            self.current_line = blk.line;
            self.pc = i + 1;
            if blk.bad {
                continue;
            }
            if let Some(o) = blk.oword() {
                self.oword(i, blk, &o.op, o.name, o.span.start);
                if blk.words.is_empty() && blk.assigns().is_empty() {
                    continue;
                }
                if !matches!(o.op, OOp::ProgramNumber) {
                    continue;
                }
            }
            self.execute(blk);
        }
        let returned = self.frames.len() == depth;
        while self.frames.len() > depth {
            self.return_from_call();
        }
        self.pc = pc;
        self.current_line = line;
        Some(returned)
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
        self.enter_fanuc_program(b, col, start, count, "subprogram calls");
    }

    /// Enter the Fanuc program (or macro) whose `O` block is `start` for `count` passes, as `M98`
    /// and `G65`/`G66` do: a frame that returns after this block and keeps the caller's locals;
    /// calls deeper than the limit stop the run with a finding naming `what`. False when nothing
    /// was entered (no pass, or too deep).
    pub(super) fn enter_fanuc_program(
        &mut self,
        b: &Block,
        col: Option<u32>,
        start: usize,
        count: u64,
        what: &str,
    ) -> bool {
        if count == 0 {
            return false;
        }
        if self.call_depth() >= self.limits.max_call_depth {
            self.error(
                b,
                col,
                format!("{what} nested deeper than {}", self.limits.max_call_depth),
            );
            self.stopped = true;
            return false;
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
        true
    }

    /// `M99` (`p`: its P word and column): end of a subprogram pass.
    pub(crate) fn m99(&mut self, b: &Block, p: Option<(f64, Option<u32>)>) {
        if self.macro_b.is_some() && self.frames.last().map_or(true, |f| f.fanuc) {
            self.macro_m99(b, p.map(|p| p.0));
            return;
        }
        if let Some((_, at)) = p {
            self.unsupported(
                b,
                at,
                "M99 P (return to a sequence number) is not modelled".into(),
                true,
            );
        }
        match self.frames.last() {
            Some(f) if f.fanuc => {
                let f = self.frames.last_mut().unwrap();
                if f.repeats_left > 0 {
                    f.repeats_left -= 1;
                    self.pc = f.body_pc;
                } else {
                    // An M98 subprogram shares #1…#33 with its caller (Fanuc, and LinuxCNC's
                    // `m98m99-07` test): what it set stays set after M99.
                    let f = self.frames.pop().unwrap();
                    self.pc = f.return_pc;
                }
            }
            Some(_) => {
                self.error(b, None, "M99 ends an o-word subroutine: use endsub or return".into());
                self.return_from_call();
            }
            None => {
                // Fanuc (and LinuxCNC) run the program again from its start: no alarm, a loop by
                // design (a bar feeder's next part). One pass is checked.
                self.warn_once(
                    b,
                    None,
                    "M99 in the main program restarts it without end (a bar-feed loop); checked once".into(),
                );
                self.stopped = true;
            }
        }
    }
}
