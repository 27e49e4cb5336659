//! What the cycle families share: finding profile blocks by N number, tracing a profile through
//! the interpreter's own block executor, and emitting moves at the cycle's line.

use super::super::flow::Run;
use super::super::{Feed, Move, MoveKind};
use crate::gcode::{Block, BlockRef};
use crate::geom::{P2, V2};

/// Most blocks one profile (P to Q) may span. Fanuc controls allow far fewer; the cap keeps a
/// hostile program (thousands of cycles over one huge range) linear in its size.
pub(crate) const MAX_PROFILE_BLOCKS: usize = 2000;

/// Most passes one roughing cycle may make (a tiny depth of cut on a large part is a program
/// error, never an unbounded list of moves).
pub(crate) const MAX_PASSES: usize = 10_000;

/// Most moves one cycle block may make (pockets on every level, or many G73 passes over a long
/// profile, must not grow the move list without bound).
pub(crate) const MAX_CYCLE_MOVES: usize = 1_000_000;

/// A cycle that made too many moves: a finding at its line, and the caller stops expanding it.
pub(crate) fn too_many_moves(run: &mut Run<'_>, b: &Block, m0: usize, name: &str) -> bool {
    if run.moves.len() - m0 <= MAX_CYCLE_MOVES {
        return false;
    }
    run.error(
        b,
        None,
        format!("{name} makes more than {MAX_CYCLE_MOVES} moves; the rest of the cycle is not checked"),
    );
    true
}

/// One piece of a traced profile: where the programmed point went, and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Seg {
    pub kind: MoveKind,
    pub start: P2,
    pub end: P2,
    /// Physical line of the profile block.
    pub line: u32,
}

impl Seg {
    pub fn shifted(&self, d: V2) -> Seg {
        let kind = match self.kind {
            MoveKind::Arc { center, sweep } => MoveKind::Arc {
                center: center + d,
                sweep,
            },
            k => k,
        };
        Seg {
            kind,
            start: self.start + d,
            end: self.end + d,
            line: self.line,
        }
    }

    /// The point at fraction `t` of the path.
    pub fn point_at(&self, t: f64) -> P2 {
        crate::interp::path_point(self.kind, self.start, self.end, t)
    }
}

/// A profile traced from the cycle's start point.
pub(crate) struct Traced {
    /// The move of block P (start point → first profile point), when block P moves.
    pub approach: Option<Seg>,
    /// The profile proper, first point to last.
    pub segs: Vec<Seg>,
    /// Block P names both axes (X or U, and Z or W): Fanuc's type II.
    pub p_names_both: bool,
    /// Block indices of P and Q.
    pub q: usize,
}

/// A G41/G42/G40 of a Fanuc stock-removal cycle's profile block, kept from the compensation
/// stage while the profile is read (docs/comp.md, "Canned cycles"): roughing reads the profile
/// uncompensated and drops it; G70 has the block executor replay it before the move at `at`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ProfileComp {
    /// Index in the run's moves of the first move made after the word.
    pub at: usize,
    pub word: super::super::comp::Word,
}

/// What the cycles remember between blocks.
#[derive(Default, Debug)]
pub(crate) struct Memory {
    /// Fanuc `G71 U(Δd) R(e)`: depth of cut and retract, mm.
    pub g71: Option<(f64, f64)>,
    /// Fanuc `G72 W(Δd) R(e)`.
    pub g72: Option<(f64, f64)>,
    /// Fanuc `G73 U(Δi) W(Δk) R(d)`: relief in X (radius) and Z, mm, and the number of passes.
    pub g73: Option<(f64, f64, f64)>,
    /// (N number, block index) of every numbered block, sorted (built on first use): the
    /// blocks holding one N number are a run of it, in program order.
    n_index: Option<Vec<(u64, usize)>>,
    /// Searches for an N number near their block that found none (see `find_n`).
    near_misses: u32,
    /// G76 first-block words (Fanuc parameters 5142, 5130, 5143, 5140, 5141).
    pub g76: super::thread::G76Params,
    /// G74/G75 first block: the return amount e (mm; Fanuc parameter 5139).
    pub groove_e: Option<f64>,
    /// Drilling, G-code system B: G99 (return to the R plane) rather than G98 (initial level).
    pub return_r: bool,
    /// The LinuxCNC cycles' modal values (R plane, initial level, retract mode, …).
    pub lcnc: super::lcnc_drill::LcncMemory,
    /// While a LinuxCNC G7x profile runs: the A (fillet) and C (chamfer) words of its moves.
    pub profile_corners: Option<Vec<super::lcnc_rough::Corner>>,
    /// A LinuxCNC G70 running while nose-radius compensation offsets (set by the block
    /// executor): the cycle keeps its moves that go nowhere and says where rs274 re-read the
    /// profile (`lcnc_rough::CompRead`).
    pub lcnc_g70_comp: Option<super::lcnc_rough::CompRead>,
    /// While a Fanuc G70–G73 runs its profile blocks: their G41/G42/G40, in order (the block
    /// executor hands them here instead of to the compensation stage).
    pub profile_comp: Option<Vec<ProfileComp>>,
    /// The G41/G42/G40 of the profile the last Fanuc G70 finished, for the block executor to
    /// replay at their moves (`Run::run_cycle`).
    pub g70_comp: Vec<ProfileComp>,
}

/// The block with N number `n`: the first one after block `from`, else the first in the file.
pub(crate) fn find_n(run: &mut Run<'_>, n: u64, from: usize) -> Option<usize> {
    let near = from + 1..(from + 1 + NEAR).min(run.prog.len());
    if let Some(i) = near_n(run, n, near) {
        return Some(i);
    }
    let list = n_blocks(run, n);
    let k = list.partition_point(|&(_, i)| i <= from);
    list.get(k).or(list.first()).map(|&(_, i)| i)
}

/// How far [`find_n`] and [`find_n_before`] look from their block before they ask the index of
/// every numbered block: a profile is next to its cycle, so a long program's cycles find theirs
/// without the index (about 16 bytes a numbered block: `Cycles::n_index`).
const NEAR: usize = 4096;

/// Searches that looked [`NEAR`] blocks and found nothing, after which the index is asked first.
const NEAR_MISSES: u32 = 16;

/// The first block of `range` numbered `n`, while near searches pay (see [`NEAR_MISSES`]): what
/// the index would give from the same blocks, since none before it in `range` has that number.
fn near_n(run: &mut Run<'_>, n: u64, mut range: impl Iterator<Item = usize>) -> Option<usize> {
    if run.cycles.n_index.is_some() || run.cycles.near_misses >= NEAR_MISSES {
        return None;
    }
    let found = range.find(|&i| run.block(i).n() == Some(n));
    if found.is_none() {
        run.cycles.near_misses += 1;
    }
    found
}

/// The blocks numbered `n`, ascending, as (n, block index).
fn n_blocks<'r>(run: &'r mut Run<'_>, n: u64) -> &'r [(u64, usize)] {
    let index = run.cycles.n_index.get_or_insert_with(|| {
        let mut v: Vec<(u64, usize)> = run
            .prog
            .blocks()
            .filter_map(|b| b.n().map(|k| (k, b.index())))
            .collect();
        v.sort_unstable();
        v
    });
    let lo = index.partition_point(|&(k, _)| k < n);
    let hi = lo + index[lo..].partition_point(|&(k, _)| k == n);
    &index[lo..hi]
}

/// The block with N number `n` for G70, whose profile is the roughing cycle's before it: the
/// last one before block `from`, else the first after it. (A program that repeats its N numbers
/// from one operation to the next, as posts do, finishes the profile it just roughed.)
pub(crate) fn find_n_before(run: &mut Run<'_>, n: u64, from: usize) -> Option<usize> {
    if let Some(i) = near_n(run, n, (from.saturating_sub(NEAR)..from).rev()) {
        return Some(i);
    }
    let list = n_blocks(run, n);
    let k = list.partition_point(|&(_, i)| i < from);
    if k > 0 {
        Some(list[k - 1].1)
    } else {
        list.get(k).map(|&(_, i)| i)
    }
}

/// A P or Q word as an N number.
pub(crate) fn n_word(v: f64) -> Option<u64> {
    (v >= 0.0 && v.fract() == 0.0 && v < 1e15).then_some(v as u64)
}

/// The feed of a cutting move now, or a finding at the cycle's line.
pub(crate) fn feed(run: &mut Run<'_>, b: &Block, what: &str) -> Option<Feed> {
    run.feed_or(b, || format!("{what} needs a feed rate (F) and none is in force"))
}

/// Emit a move from the current programmed point at the cycle's line (skipped when it goes
/// nowhere), recording the profile block's line when there is one.
pub(crate) fn emit(run: &mut Run<'_>, b: &Block, kind: MoveKind, end: P2, feed: Feed, profile_line: u32) {
    let start = run.programmed();
    if matches!(kind, MoveKind::Rapid | MoveKind::Line) && (end - start).norm() < 1e-9 {
        return;
    }
    run.push_move(b, kind, start, end, feed);
    if let Some(m) = run.moves.last_mut() {
        m.profile_line = profile_line;
    }
}

pub(crate) fn rapid(run: &mut Run<'_>, b: &Block, end: P2) {
    emit(run, b, MoveKind::Rapid, end, Feed::Rapid, 0);
}

/// A segment of a profile followed at the given feed (rapids stay rapids).
pub(crate) fn follow(run: &mut Run<'_>, b: &Block, s: &Seg, feed: Feed) {
    let (kind, f) = match s.kind {
        MoveKind::Rapid => (MoveKind::Rapid, Feed::Rapid),
        k => (k, feed),
    };
    emit(run, b, kind, s.end, f, s.line);
}

/// A block of the profile that a cycle cannot run: a call, a return, an o-word, a program end.
fn forbidden_in_profile(pb: &BlockRef) -> Option<&'static str> {
    if pb.oword().is_some() {
        return Some("an o-word");
    }
    for w in pb.words() {
        if let crate::gcode::Value::Num(v) = w.value() {
            if w.letter == b'M' && matches!(v as i64, 2 | 30 | 98 | 99) && v.fract() == 0.0 {
                return Some("M2, M30, M98 or M99");
            }
            if w.letter == b'G' && (70.0..=76.0).contains(&v) {
                return Some("another cycle");
            }
        }
    }
    None
}

/// Run blocks P..=Q from the current point through the block executor and collect the moves
/// they make. With `keep` false (roughing) nothing of it stays: the moves, the modal state, the
/// tool and the position are as before; with `keep` true (G70) the moves stay in the run and
/// only the modal state is restored. `None` after a finding at the cycle's line.
pub(crate) fn trace(
    run: &mut Run<'_>,
    b: &Block,
    here: usize,
    p: f64,
    q: f64,
    name: &str,
    keep: bool,
) -> Option<Traced> {
    let (Some(pn), Some(qn)) = (n_word(p), n_word(q)) else {
        run.error(b, None, format!("{name}: P{p} Q{q} must be N numbers"));
        return None;
    };
    // G70 (`keep`) finishes a profile that is normally before it; the roughing cycles' profile
    // follows them.
    let found = if keep {
        find_n_before(run, pn, here)
    } else {
        find_n(run, pn, here)
    };
    let Some(pi) = found else {
        run.error(
            b,
            None,
            format!("{name}: no block N{pn} (P, the profile's first block) in this file"),
        );
        return None;
    };
    let Some(qi) = find_n(run, qn, if keep { pi } else { pi.max(here) })
        .filter(|&qi| qi >= pi)
        .or_else(|| find_n(run, qn, pi))
    else {
        run.error(
            b,
            None,
            format!("{name}: no block N{qn} (Q, the profile's last block) in this file"),
        );
        return None;
    };
    if qi < pi {
        run.error(
            b,
            None,
            format!(
                "{name}: Q (N{qn}, line {}) comes before P (N{pn}, line {})",
                run.block(qi).line,
                run.block(pi).line
            ),
        );
        return None;
    }
    if (pi..=qi).contains(&here) {
        run.error(
            b,
            None,
            format!("{name}: the profile N{pn}–N{qn} holds the cycle block itself"),
        );
        return None;
    }
    if qi - pi + 1 > MAX_PROFILE_BLOCKS {
        run.error(
            b,
            None,
            format!(
                "{name}: the profile N{pn}–N{qn} spans {} blocks; latheguard reads at most {MAX_PROFILE_BLOCKS}",
                qi - pi + 1
            ),
        );
        return None;
    }
    for i in pi..=qi {
        let pb = &run.block(i);
        if let Some(what) = forbidden_in_profile(pb) {
            let line = pb.line;
            run.error(
                b,
                None,
                format!("{name}: the profile holds {what} (line {line}), which a cycle cannot run"),
            );
            return None;
        }
    }
    let p_block = run.block(pi);
    let names = |l: &[u8]| p_block.words().iter().any(|w| l.contains(&w.letter));
    let p_names_both = names(b"XU") && names(b"ZW");
    let p_line = p_block.line;

    let mark = Mark::new(run);
    let (stopped, pc) = (run.stopped, run.pc);
    // The profile's G41/G42/G40 stay out of the compensation stage (see `ProfileComp`).
    let outer = run.cycles.profile_comp.replace(Vec::new());
    for i in pi..=qi {
        let pb = &run.block(i);
        if pb.bad {
            continue;
        }
        if !run.count_executed(pb) {
            run.cycles.profile_comp = outer;
            return None;
        }
        run.execute(pb);
    }
    let comp_words = std::mem::replace(&mut run.cycles.profile_comp, outer).unwrap_or_default();
    let refused = mark.reported(run);
    let mut segs = mark.segs(run, false);
    mark.restore_modes(run);
    run.stopped = stopped;
    run.pc = pc;
    if keep {
        run.cycles.g70_comp = comp_words;
        let line = b.line;
        let n = b.n();
        for m in &mut run.moves[mark.moves..] {
            m.profile_line = m.line;
            m.line = line;
            m.n = n;
        }
    } else {
        mark.drop_moves(run);
    }
    if refused {
        return None;
    }
    let approach = if segs.first().is_some_and(|s| s.line == p_line) {
        Some(segs.remove(0))
    } else {
        None
    };
    Some(Traced {
        approach,
        segs,
        p_names_both,
        q: qi,
    })
}

/// What running a cycle's profile through the block executor changes in a run, saved before it
/// so that it can be put back: the modal state and frame shift, and the moves with the tool and
/// position they leave.
pub(crate) struct Mark {
    modal: super::super::state::Modal,
    shift: V2,
    reference: P2,
    station: u32,
    tip: V2,
    selected: Option<u32>,
    /// Moves and states before the profile ran.
    pub moves: usize,
    states: usize,
    reports: u64,
}

impl Mark {
    pub fn new(run: &Run<'_>) -> Mark {
        Mark {
            modal: run.modal.clone(),
            shift: run.shift,
            reference: run.reference,
            station: run.station,
            tip: run.tip,
            selected: run.selected,
            moves: run.moves.len(),
            states: run.states.len(),
            reports: run.reports,
        }
    }

    /// A finding was reported since the mark.
    pub fn reported(&self, run: &Run<'_>) -> bool {
        run.reports > self.reports
    }

    /// The motions made since the mark as profile segments (rapids as lines when
    /// `rapid_as_line`: LinuxCNC reads a profile's G0 as G1).
    pub fn segs(&self, run: &Run<'_>, rapid_as_line: bool) -> Vec<Seg> {
        run.moves[self.moves..]
            .iter()
            .filter(|m| matches!(m.kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }))
            .map(|m: &Move| Seg {
                kind: if rapid_as_line && m.kind == MoveKind::Rapid {
                    MoveKind::Line
                } else {
                    m.kind
                },
                start: m.start,
                end: m.end,
                line: m.line,
            })
            .collect()
    }

    /// Put back the modal state and the frame shift.
    pub fn restore_modes(&self, run: &mut Run<'_>) {
        run.modal = self.modal.clone();
        run.shift = self.shift;
    }

    /// Drop the moves made since the mark, and the tool and position they left.
    pub fn drop_moves(&self, run: &mut Run<'_>) {
        run.moves.truncate(self.moves);
        run.states.truncate(self.states);
        run.reference = self.reference;
        run.station = self.station;
        run.tip = self.tip;
        run.selected = self.selected;
    }
}

/// Execution resumes after block Q when Q follows the cycle block, whatever becomes of the cycle
/// (a refused cycle must not leave its profile to run as plain moves, one full-depth cut).
pub(crate) fn skip_profile(run: &mut Run<'_>, here: usize, q: f64) {
    if let Some(qi) = n_word(q).and_then(|qn| find_n(run, qn, here)) {
        resume_after(run, here, qi);
    }
}

/// After a cycle whose profile follows it, execution resumes after block Q.
pub(crate) fn resume_after(run: &mut Run<'_>, here: usize, q: usize) {
    if q > here {
        run.pc = q + 1;
    }
}
