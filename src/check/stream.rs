//! The checker fed one chunk of moves at a time, as the interpreter makes them
//! (`interp::interpret_streaming`; ARCHITECTURE.md, "Memory for long programs"): a long program's
//! moves are never all in memory. [`super::check`] feeds a whole run's moves as one chunk.
//!
//! What a move's check reads of the run, and where the stream keeps it:
//! - the move itself, the state it refers to and its extra-axis entry: from the chunk in hand
//!   (chunks carry every state made so far and their moves' entries);
//! - the move just before it (a snapshot's path) and the last move before it that is no dwell
//!   (the feed a rapid scrape follows, `scrape.rs`): copies carried from move to move
//!   (`Behind`), whatever chunk they came in;
//! - its start time: the [`motion::Clock`], which times the moves in order;
//! - two facts of the whole run, which decide before the first move whether the 3D path runs:
//!   [`takes_3d`], whose caller learns them in a first pass of the interpreter when the machine
//!   does not decide alone ([`takes_3d_depends_on_run`]).
//!
//! Nothing else of the run is read, and no rule looks ahead: so the findings, statistics and
//! stock are the same whatever the chunks (`tests/streamed.rs` holds them byte for byte to the
//! whole run's, with chunks of one move).

use super::{checker, episodes, CheckResult, Checker};
use crate::finding::Finding;
use crate::interp::{Chunk, ExtraMove, Move, MoveKind, MoveState};
use crate::machine::Machine;
use crate::motion;
use crate::pipeline::Settings;

/// Whether a program's check takes the 3D path (`three.rs`), from two facts of its whole run:
/// some move has an extra-axis entry (`any_extra`), some move has the tailstock withdrawn
/// (`tailstock_withdrawn`). It does on a machine with a kinematic tree that describes a part
/// (some component has a geometry) when either holds or the tailstock starts withdrawn; a tree
/// of axes alone, or a program with no extra-axis word while the 2D tailstock outline (on a
/// turn-mill, the parked sub-spindle) is in the scene throughout, stays with the 2D checker.
pub fn takes_3d(machine: &Machine, any_extra: bool, tailstock_withdrawn: bool) -> bool {
    machine.kinematics.as_ref().is_some_and(|k| {
        let tailstock_out = !machine.tailstock_advanced || tailstock_withdrawn;
        (any_extra || tailstock_out) && k.components.iter().any(|c| c.geometry.is_some())
    })
}

/// Whether [`takes_3d`] needs the run's facts on this machine (else any facts give its answer).
pub fn takes_3d_depends_on_run(machine: &Machine) -> bool {
    takes_3d(machine, true, true) != takes_3d(machine, false, false)
}

/// The checker of one program, fed its moves in order ([`Stream::feed`]), then finished.
pub struct Stream<'a> {
    c: Checker<'a>,
    clock: motion::Clock<'a>,
    /// The index of the next move fed.
    next: usize,
    /// The tailstock's setup was checked (before the first move).
    started: bool,
    /// The work budget ran out: the moves after are timed, not checked.
    stopped: bool,
    /// Moves that reach the machine ([`crate::pipeline::Stats::moves`]).
    motions: u64,
    /// The line and N number of each move the clock timed at the fallback feed.
    stalls: Vec<(u32, Option<u64>)>,
    /// The end of the latest move fed by [`Stream::feed_timed`], s.
    now: f64,
    /// The lengths of the last two moves fed by [`Stream::feed_timed`], s.
    spans: [f64; 2],
    /// Findings whose contact may go on in the next move (`take_final`).
    pending: Vec<Finding>,
    /// The crashes [`Stream::take_final`] handed out that a later contact may still follow on
    /// from.
    released: Vec<Finding>,
    /// What other paths cut, each before the move of this index (`share_cuts`), in order.
    foreign: std::collections::VecDeque<super::Cut>,
}

impl<'a> Stream<'a> {
    /// A check on `machine` that keeps the first `cap` findings in line order (see
    /// `check_capped`); with the 3D path when `three` ([`takes_3d`]).
    pub fn new(machine: &'a Machine, settings: &Settings, three: bool, cap: usize) -> Stream<'a> {
        let mut c = checker(machine, settings, three);
        c.episodes.cap = cap;
        if !machine.operations.is_empty() {
            c.episodes.operation = 1;
        }
        Stream {
            c,
            clock: motion::Clock::new(machine),
            next: 0,
            started: false,
            stopped: false,
            motions: 0,
            stalls: Vec::new(),
            now: 0.0,
            spans: [0.0; 2],
            pending: Vec::new(),
            released: Vec::new(),
            foreign: Default::default(),
        }
    }

    /// Check the next moves of the program (`chunk.first` is the index of the next move).
    pub fn feed(&mut self, chunk: Chunk<'_>) {
        debug_assert_eq!(chunk.first, self.next);
        let mut extra = chunk.extra.iter().peekable();
        for m in chunk.moves {
            let i = self.next;
            self.next += 1;
            while extra.peek().is_some_and(|e| (e.index as usize) < i) {
                extra.next();
            }
            let e = extra.peek().copied().filter(|e| e.index as usize == i);
            while self.foreign.front().is_some_and(|f| f.0 <= i) {
                if let Some((_, removed)) = self.foreign.pop_front() {
                    self.c.cut_foreign(&removed);
                }
            }
            let state = &chunk.states[m.state as usize];
            let stalled = self.clock.stalled().len();
            let item = self.clock.time(m, &state.spindle, e);
            if self.clock.stalled().len() > stalled {
                self.stalls.push((m.line, m.n));
            }
            self.step(i, m, state, e, &item);
        }
    }

    /// Share the stock with the other paths of a multi-path program (`paths`): take off it what
    /// they cut, each cut `(i, polygons)` just before move `i` (every path's cut that has ended by
    /// then, in the machine's clock; `usize::MAX`: at the end, for the final part), and with
    /// `record`, keep this path's own cuts in [`CheckResult::cuts`].
    pub fn share_cuts(&mut self, mut foreign: Vec<super::Cut>, record: bool) {
        foreign.sort_by_key(|f| f.0);
        self.foreign = foreign.into();
        self.c.record_cuts = record;
    }

    /// Keep this path's own cuts from now on, for [`Stream::take_cuts`] (`latheguard follow` on
    /// a machine with several paths: each carrier's cuts are taken off the others' stock).
    pub fn record_cuts(&mut self) {
        self.c.record_cuts = true;
    }

    /// The cuts recorded since the last call ([`Stream::record_cuts`]).
    pub fn take_cuts(&mut self) -> Vec<super::Cut> {
        std::mem::take(&mut self.c.cuts)
    }

    /// Take off the stock now, before the next move, what another path cut.
    pub fn cut_now(&mut self, removed: &super::Removed) {
        self.c.cut_foreign(removed);
    }

    /// The index the next move fed gets (an extra-axis entry's `index`).
    pub fn next_index(&self) -> usize {
        self.next
    }

    /// Check one move whose timing the caller knows (`latheguard follow`: the interval between
    /// two samples of a live machine, `crate::follow`): it starts at `t0` and lasts `duration`
    /// seconds, the turret reference point straight from its start to its end at constant speed
    /// (standing still for a turret index). `m` is the next move of the run; its `state` field
    /// is not read (the state is `state`), and `e`'s index must be the move's.
    pub fn feed_timed(&mut self, m: &Move, state: &MoveState, e: Option<&ExtraMove>, t0: f64, duration: f64) {
        let i = self.next;
        self.next += 1;
        let path = match m.kind {
            MoveKind::Rapid | MoveKind::Line => motion::Path::Line {
                from: m.ref_start(),
                to: m.ref_end(),
            },
            _ => motion::Path::Still(m.ref_start()),
        };
        let item = motion::Timed {
            index: i,
            t0,
            duration: if duration.is_finite() && duration >= 0.0 {
                duration
            } else {
                0.0
            },
            path,
        };
        self.now = self.now.max(item.t1());
        self.spans = [self.spans[1], item.duration];
        self.step(i, m, state, e, &item);
    }

    /// The findings of the moves fed so far that are final: their contact ended, and no contact
    /// still going on began before them (so none can still turn out to be the crash they follow
    /// on from). Grazes and follow-ons are marked as [`Stream::finish`] marks them; a finding
    /// taken here is not in the result of `finish`. For a stream with no end (`follow`).
    pub fn take_final(&mut self) -> Vec<Finding> {
        let open_from = self.c.episodes.earliest_open();
        let eps = &mut self.c.episodes;
        eps.forget_lines();
        let mut new = std::mem::take(&mut eps.findings);
        new.sort_by(|a, b| a.time_s.unwrap_or(0.0).total_cmp(&b.time_s.unwrap_or(0.0)));
        // A contact that goes on from one move into the next at the same line is one finding, as
        // it is when that line is one move (the 3D path ends its episodes with each move, and
        // its last contact may lie a probe before the move's end): a contact of the same parts
        // under the same rule that begins within a move's length of one's end continues it.
        let gap = self.spans[0].max(self.spans[1]) + 1e-6;
        for f in new {
            let joins = |p: &Finding| {
                p.kind == f.kind
                    && p.objects == f.objects
                    && p.line == f.line
                    && p.operation == f.operation
                    && matches!((p.end_time_s, f.time_s), (Some(e), Some(t)) if t >= e - 1e-6 && t - e <= gap)
            };
            match self.pending.iter_mut().find(|p| joins(p)) {
                Some(p) => {
                    p.end_time_s = match (p.end_time_s, f.end_time_s) {
                        (Some(a), Some(b)) => Some(a.max(b)),
                        (a, b) => a.or(b),
                    };
                    p.end_line = p.end_line.max(f.end_line);
                    p.depth_mm = match (p.depth_mm, f.depth_mm) {
                        (Some(a), Some(b)) => Some(a.max(b)),
                        (a, b) => a.or(b),
                    };
                }
                None => self.pending.push(f),
            }
        }
        // Final: its contact ended before the end of the last move fed (else the next move may
        // go on with it), and no contact still open began before it.
        let now = self.now;
        let hold_from = now - gap;
        let (ready, held): (Vec<Finding>, Vec<Finding>) =
            std::mem::take(&mut self.pending).into_iter().partition(|f| {
                f.time_s.map_or(true, |t| t <= open_from + 1e-9) && f.end_time_s.map_or(true, |e| e < hold_from)
            });
        self.pending = held;
        if ready.is_empty() {
            return ready;
        }
        let mut ready = ready;
        episodes::mark_grazes(&mut ready, self.c.settings.min_depth(self.c.machine));
        // Follow-ons against the crashes already handed out whose contact may still be the
        // parent of a later one.
        let n = self.released.len();
        let mut all = std::mem::take(&mut self.released);
        all.append(&mut ready);
        episodes::mark_follow_ons(&mut all);
        let ready = all.split_off(n);
        let horizon = open_from.min(now) - 1.0;
        all.extend(ready.iter().cloned());
        all.retain(|f| f.end_time_s.is_some_and(|e| e >= horizon));
        for f in &mut all {
            f.snapshot = None;
            f.snapshot3 = None;
        }
        self.released = all;
        ready
    }

    /// The end of a stream with no end fixed in advance: every contact still open ends here, and
    /// every finding not taken yet is final ([`Stream::take_final`]).
    pub fn take_rest(&mut self) -> Vec<Finding> {
        self.c.episodes.close_all();
        self.now = f64::INFINITY;
        let mut out = self.take_final();
        out.sort_by(|a, b| a.time_s.unwrap_or(0.0).total_cmp(&b.time_s.unwrap_or(0.0)));
        out
    }

    /// Check move `i` of the run, timed.
    fn step(&mut self, i: usize, m: &Move, state: &MoveState, e: Option<&ExtraMove>, item: &motion::Timed) {
        if !matches!(
            m.kind,
            MoveKind::Dwell { .. } | MoveKind::Operation { .. } | MoveKind::Wait { .. }
        ) {
            self.motions += 1;
        }
        if !self.started {
            self.started = true;
            self.c.static_pairs(m.line);
        }
        if !self.stopped {
            let budget = self.c.settings.work_budget;
            if self.c.stats.pair_tests > budget {
                self.c.budget.push((
                    m.line,
                    format!(
                        "latheguard stopped checking here: the program used up its work budget of {budget} pair tests; \
                         this line and the ones after it are unchecked"
                    ),
                ));
                self.stopped = true;
            } else {
                self.c.move_index = i;
                self.c.one_move(m, state, e, item);
            }
        }
        let b = &mut self.c.behind;
        b.prev = Some(*m);
        if !matches!(m.kind, MoveKind::Dwell { .. }) {
            b.motion = Some((i, *m));
        }
    }

    /// The findings, statistics and stock of the program fed.
    pub fn finish(self) -> CheckResult {
        let Stream {
            mut c,
            clock,
            started,
            motions,
            stalls,
            foreign: mut self_foreign,
            ..
        } = self;
        if !started {
            c.static_pairs(1);
        }
        // Other paths' cuts after this path's last move: the final part has them too.
        for (_, removed) in std::mem::take(&mut self_foreign) {
            c.cut_foreign(&removed);
        }
        let settings = c.settings;
        let (machine_time_s, _) = clock.finish();
        c.episodes.close_all();
        let mut findings = std::mem::take(&mut c.episodes.findings);
        episodes::mark_grazes(&mut findings, settings.min_depth(c.machine));
        episodes::mark_follow_ons(&mut findings);
        c.budget.dedup();
        for (line, message) in std::mem::take(&mut c.budget) {
            findings.push(Finding::program(line, 0, message));
        }
        for (line, n) in stalls {
            findings.push(
                Finding::program(
                    line,
                    0,
                    "feed per revolution with no spindle speed: the move would never finish (timed at 100 mm/min)",
                )
                .with_n(n),
            );
        }
        let part_stl = if settings.part_mesh { c.part_stl() } else { None };
        let mut stats = std::mem::take(&mut c.stats);
        stats.machine_time_s = machine_time_s;
        stats.moves = motions;
        if c.three.as_ref().is_some_and(|t| t.ran) {
            stats.effects.push("kinematic_3d".into());
        }
        if c.cut_any {
            stats.effects.push("stock_removal".into());
        }
        if c.turned {
            stats.effects.push("turn_round".into());
        }
        if let Some(m) = &c.mill {
            stats.effects.push("grid_stock".into());
            stats.grid_rays = m.stock.rays();
        }
        if c.machine.stock.as_ref().is_some_and(|s| s.block.is_some()) && c.mill.is_none() {
            // A block checked without the 3D path: its revolved envelope alone.
            stats.effects.push("block_envelope".into());
        }
        if c.indexed {
            stats.effects.push("turret_index".into());
        }
        if c.others_tested {
            stats.effects.push("other_stations".into());
        }
        if c.long_moves {
            stats.effects.push("long_moves_exact".into());
        }
        if settings.clearance_mm > 0.0 {
            stats.effects.push("near_miss".into());
        }
        CheckResult {
            findings,
            stats,
            stock: c.stock,
            part_stl,
            cuts: c.cuts,
        }
    }
}
