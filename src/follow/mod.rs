//! The online check (`latheguard follow`, docs/follow.md): live axis positions, one sample at a
//! time, checked as they come.
//!
//! Each pair of consecutive samples becomes one short straight move of the turret reference
//! point (every axis linear over the interval, with the sample's tool, spindle and rapid or feed
//! state), handed to the same checker `check` feeds move by move ([`crate::check::Stream`],
//! through [`Stream::feed_timed`], which takes the samples' times instead of timing the move
//! from its feed). So the stock is cut by the samples, the 3D path poses only the parts whose
//! axes moved (`kin::Poser`), and a replay of the samples the interpreter's own timing makes of
//! a program ([`replay`]) gives that program's findings. A sample in which nothing moved costs a
//! comparison. No I/O: the caller reads the lines ([`sample::Reader`]) and writes the findings.

pub mod replay;
pub mod sample;

use crate::check::{takes_3d, Stream};
use crate::finding::Finding;
use crate::geom::{P2, V2};
use crate::interp::{
    self, ExtraMove, Feed, Interpretation, Move, MoveKind, MoveState, Plane, ProgFrame, Spindle, SpindleSpeed,
};
use crate::machine::Machine;
use crate::paths::{cross, cross3, sync::Schedule};
use crate::pipeline::Settings;
pub use sample::{Carrier, Format, Layout, Motion, Reader, Sample, SampleError, SpindleDir, AXES};

/// Which of the [`AXES`] a machine has: X and Z always, the others by its kinematic tree.
pub fn machine_axes(machine: &Machine) -> [bool; 6] {
    let mut has = [true, true, false, false, false, false];
    if let Some(k) = &machine.kinematics {
        for (i, &a) in AXES.iter().enumerate().skip(2) {
            has[i] = k.axis_by_letter(a).is_some();
        }
    }
    has
}

/// The lathe each path's carrier runs on ([`Machine::for_path`]), path 1 first: what
/// [`Follower::new`] follows. One lathe, the machine itself, on a machine with one path.
pub fn lathes(machine: &Machine) -> Vec<Machine> {
    (1..=machine.paths.count() as u32)
        .filter_map(|p| machine.for_path(p).map(std::borrow::Cow::into_owned))
        .collect()
}

/// Most probes the check of the carriers against each other spends on one sample interval;
/// past them an `unsupported` warning says the rest of the interval is unchecked.
pub const MAX_CROSS_PROBES: u64 = 5_000;

/// The machine's state after a sample, as one path's carrier sees it: every field a sample may
/// leave out, as the last sample that gave it left it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Now {
    t: f64,
    /// [`AXES`] values: X and Z of the reference point from machine zero (X a radius), then Y C B A.
    axes: [f64; 6],
    tool: u32,
    spindle: SpindleDir,
    motion: Motion,
    line: u32,
    c_axis: bool,
    live_rpm: f64,
    tailstock: bool,
    sub_chuck: bool,
}

/// What one sample did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Step {
    /// Moves handed to the checker (0: nothing moved; 2 per carrier: a turret index and a motion).
    pub moves: u32,
}

/// A move of one carrier in the interval since the sample before, with its machine times: the
/// carriers' check reads the interval's moves of every carrier.
#[derive(Clone)]
struct Timed {
    m: Move,
    e: Option<ExtraMove>,
    t0: f64,
    duration: f64,
}

/// One path's carrier: its lathe, its check and its state.
struct Lane<'m> {
    path: u32,
    machine: &'m Machine,
    stream: Stream<'m>,
    now: Option<Now>,
    /// When the carrier last moved (a turret index ends at the sample that shows the new tool and
    /// began at most one index time earlier, but not before this).
    moved_at: f64,
    has: [bool; 6],
    /// Its moves since the sample before, the interval covered from its start (standing moves
    /// where it stood).
    window: Vec<Timed>,
    /// Its moves of the last [`Follower::horizon`] seconds, for the look back over a turret
    /// index (several paths only).
    history: std::collections::VecDeque<Timed>,
}

/// The checker of one machine's live samples: each path's carrier on its lathe, and on a machine
/// with several paths the carriers against each other.
pub struct Follower<'m> {
    lanes: Vec<Lane<'m>>,
    /// The carriers against each other (several paths): in the working plane, or in 3D on a
    /// tree whose axes several paths drive.
    cross: Option<Cross>,
    /// What reports call each lane's carrier, and whether it stands across the spindle axis.
    names: Vec<(String, bool)>,
    /// The search of the look back over a turret index (its own state: a stretch already
    /// searched, searched again with the swing).
    lookback: Option<Cross>,
    /// How far back a turret index may have begun: the longest index of the machine's turrets.
    horizon: f64,
    /// The contacts between carriers found by the look back, to write with the next findings.
    late: Vec<Finding>,
    /// The line and parts of each contact between carriers written in the last `horizon`
    /// seconds, with its time (a look back reports none of them again).
    reported: std::collections::VecDeque<(f64, u32, Vec<String>)>,
    samples: u64,
    moves: u64,
}

/// The search between carriers a machine takes.
enum Cross {
    Plane(cross::Search),
    Tree(cross3::Search),
}

impl Cross {
    fn run(&mut self, carriages: &[cross::Carriage], from: f64, to: f64) {
        match self {
            Cross::Plane(s) => s.run(carriages, from, to, MAX_CROSS_PROBES),
            Cross::Tree(s) => s.run(carriages, from, to, MAX_CROSS_PROBES),
        }
    }

    fn take_final(&mut self) -> Vec<Finding> {
        match self {
            Cross::Plane(s) => s.take_final(),
            Cross::Tree(s) => s.take_final(),
        }
    }

    fn take_all(&mut self) -> Vec<Finding> {
        match self {
            Cross::Plane(s) => s.take_all(),
            Cross::Tree(s) => s.take_all(),
        }
    }

    /// The line and parts of each finding held.
    fn held(&self) -> Vec<(u32, Vec<String>)> {
        match self {
            Cross::Plane(s) => s.held().map(|(l, o)| (l, o.to_vec())).collect(),
            Cross::Tree(s) => s.held().map(|(l, o)| (l, o.to_vec())).collect(),
        }
    }

    fn finish(self) -> (Vec<Finding>, u64) {
        match self {
            Cross::Plane(s) => s.finish(),
            Cross::Tree(s) => s.finish(),
        }
    }
}

impl<'m> Follower<'m> {
    /// A follower on `machine` (a job already applied) whose paths run on `lathes`
    /// ([`lathes`] of the machine). The work budget of `settings` does not apply: a stream has no
    /// end, and each sample's work is bounded by its moves' caps.
    pub fn new(machine: &'m Machine, lathes: &'m [Machine], settings: &Settings) -> Follower<'m> {
        let settings = Settings {
            work_budget: u64::MAX,
            snapshots: false,
            part_mesh: false,
            ..*settings
        };
        let several = lathes.len() > 1;
        let lanes: Vec<Lane> = lathes
            .iter()
            .zip(1u32..)
            .map(|(m, path)| {
                // Whether the 3D path runs cannot wait for the whole run: on a machine with a
                // tree it always does (moves that stay in the working plane take its 2D route
                // all the same).
                let three = takes_3d(m, true, true);
                let mut stream = Stream::new(m, &settings, three, usize::MAX);
                if several {
                    // The stock is shared: each carrier's cuts come off the others' stock.
                    stream.record_cuts();
                }
                Lane {
                    path,
                    machine: m,
                    stream,
                    now: None,
                    moved_at: 0.0,
                    has: machine_axes(m),
                    window: Vec::new(),
                    history: Default::default(),
                }
            })
            .collect();
        let names = lanes
            .iter()
            .map(|l| match machine.paths.carriers.iter().find(|c| c.path == l.path) {
                Some(c) => (c.name.clone(), c.opposite),
                None if l.path == 1 => (machine.paths.first.clone(), false),
                None => (format!("path {} carrier", l.path), false),
            })
            .collect();
        let search = || {
            let paths: Vec<(u32, &Machine)> = lanes.iter().map(|l| (l.path, l.machine)).collect();
            match machine.kinematics.as_deref().filter(|k| k.is_multi_path()) {
                Some(kin) => Cross::Tree(cross3::Search::new(kin, &paths, settings.tolerance_mm, false)),
                None => {
                    let machines: Vec<&Machine> = paths.iter().map(|p| p.1).collect();
                    Cross::Plane(cross::Search::new(&machines, settings.tolerance_mm, false))
                }
            }
        };
        let (cross, lookback) = if several {
            (Some(search()), Some(search()))
        } else {
            (None, None)
        };
        // The longest index: half the stations of a drum, station by station; a gang slide's one
        // step.
        let horizon = lathes
            .iter()
            .map(|m| {
                let steps = match m.turret.kind {
                    crate::machine::TurretKind::Drum => m.turret.stations / 2,
                    crate::machine::TurretKind::Gang => 1,
                };
                f64::from(steps.max(1)) * m.turret.index_time
            })
            .fold(0.0, f64::max);
        Follower {
            lanes,
            cross,
            names,
            lookback,
            horizon,
            late: Vec::new(),
            reported: Default::default(),
            samples: 0,
            moves: 0,
        }
    }

    /// What this machine's samples may name: each path's axes and stations.
    pub fn layout(&self) -> Layout {
        Layout {
            paths: self.lanes.iter().map(|l| (l.has, l.machine.turret.stations)).collect(),
        }
    }

    /// A reader of samples for this machine: paths, axes and stations it lacks are errors at
    /// their column.
    pub fn reader(&self, format: Format) -> Reader {
        Reader::new(format).for_machine(self.layout())
    }

    /// The time of the last sample taken, s.
    pub fn time(&self) -> Option<f64> {
        self.lanes.first().and_then(|l| l.now).map(|n| n.t)
    }

    /// Samples taken and moves checked so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.samples, self.moves)
    }

    /// Take the sample read at line `at` of the source: check each carrier's move from the
    /// sample before to it, and the carriers against each other over the interval. A sample out
    /// of order (its time not after the last one's) is an error and changes nothing; `period`
    /// times a sample that has none.
    pub fn push(&mut self, at: u64, s: &Sample, period: Option<f64>) -> Result<Step, SampleError> {
        let err = |message: String| SampleError {
            line: at,
            col: 0,
            message,
        };
        let last = self.time();
        let t = match (s.t, last, period) {
            (Some(t), _, _) => t,
            (None, Some(n), Some(p)) => n + p,
            (None, None, Some(_)) => 0.0,
            (None, _, None) => return Err(err("the sample has no time `t`".into())),
        };
        if let Some(n) = last {
            if t <= n {
                return Err(err(format!(
                    "time {t} s is not after the last sample's {n} s: the sample is out of order and is skipped"
                )));
            }
        }
        if s.carriers.len() > self.lanes.len() {
            let n = self.lanes.len();
            return Err(err(format!(
                "the sample names path {}, but the machine has {n} path{}",
                s.carriers.len(),
                if n == 1 { "" } else { "s" }
            )));
        }
        for (lane, c) in self.lanes.iter().zip(&s.carriers) {
            lane.validate(c).map_err(err)?;
        }
        self.samples += 1;
        let mut step = Step::default();
        let none = Carrier::default();
        for (i, lane) in self.lanes.iter_mut().enumerate() {
            step.moves += lane.take(t, s, s.carriers.get(i).unwrap_or(&none));
        }
        self.moves += u64::from(step.moves);
        if self.lanes.len() > 1 {
            self.share_cuts();
            if let Some(from) = last {
                self.cross_check(from, t);
            }
        }
        Ok(step)
    }

    /// Each carrier's cuts of the interval taken off the other carriers' stock, before their next
    /// moves (a cut that has ended by a move's start, as `check` shares them).
    fn share_cuts(&mut self) {
        for i in 0..self.lanes.len() {
            let cuts = self.lanes[i].stream.take_cuts();
            for (_, removed) in &cuts {
                for (j, other) in self.lanes.iter_mut().enumerate() {
                    if j != i {
                        other.stream.cut_now(removed);
                    }
                }
            }
        }
    }

    /// The carriers against each other over the interval `from`..`to`: each carrier's moves of
    /// the interval as a run of its own in the machine's clock. A turret index learnt at this
    /// sample began before `from`: the stretch since it began is searched again first, with the
    /// swing, against where the other carriers were ([`Self::look_back`]).
    fn cross_check(&mut self, from: f64, to: f64) {
        if self.cross.is_none() {
            return;
        }
        for l in &mut self.lanes {
            l.remember(to, self.horizon);
        }
        let start = self
            .lanes
            .iter()
            .filter_map(|l| l.window.first())
            .map(|w| w.t0)
            .fold(from, f64::min);
        if start < from {
            self.look_back(start, from);
        }
        let runs: Vec<(Interpretation, crate::motion::Timeline)> =
            self.lanes.iter_mut().map(|l| l.window_run(from, to)).collect();
        let carriages = carriages(&self.lanes, &runs, &self.names);
        if let Some(c) = self.cross.as_mut() {
            c.run(&carriages, from, to);
        }
    }

    /// Search the carriers against each other again from `start` (where a turret index learnt at
    /// this sample began) to `from`: every carrier as its moves of that stretch had it (the
    /// indexing one swinging), a contact kept unless the same two parts at the same lines were
    /// already reported or are being followed.
    fn look_back(&mut self, start: f64, from: f64) {
        let runs: Vec<(Interpretation, crate::motion::Timeline)> =
            self.lanes.iter().map(|l| l.history_run(start, from)).collect();
        let carriages = carriages(&self.lanes, &runs, &self.names);
        let found = match self.lookback.as_mut() {
            Some(c) => {
                c.run(&carriages, start, from);
                c.take_all()
            }
            None => Vec::new(),
        };
        let held = self.cross.as_ref().map_or_else(Vec::new, Cross::held);
        for f in found {
            let known = held.iter().any(|(l, o)| *l == f.line && *o == f.objects)
                || self.reported.iter().any(|(_, l, o)| *l == f.line && *o == f.objects);
            if !known {
                self.reported.push_back((from, f.line, f.objects.clone()));
                self.late.push(f);
            }
        }
    }

    /// The findings that are final so far ([`Stream::take_final`]): write them now.
    pub fn findings(&mut self) -> Vec<Finding> {
        let mut out: Vec<Finding> = self.lanes.iter_mut().flat_map(|l| l.stream.take_final()).collect();
        let cross = self.cross.as_mut().map_or_else(Vec::new, Cross::take_final);
        if let Some(now) = self.time() {
            // What a look back must not report again.
            for f in &cross {
                self.reported.push_back((now, f.line, f.objects.clone()));
            }
            while self.reported.front().is_some_and(|r| r.0 < now - self.horizon) {
                self.reported.pop_front();
            }
        }
        out.extend(cross);
        out.append(&mut self.late);
        out
    }

    /// The end of the stream: the findings still open, and the statistics of the check (every
    /// carrier's, summed).
    pub fn finish(self) -> (Vec<Finding>, crate::pipeline::Stats) {
        let mut out = Vec::new();
        let mut stats = crate::pipeline::Stats::default();
        for mut l in self.lanes {
            out.extend(l.stream.take_rest());
            let result = l.stream.finish();
            out.extend(result.findings);
            let st = result.stats;
            stats.moves += st.moves;
            stats.steps += st.steps;
            stats.pair_tests += st.pair_tests;
            stats.pair_tests_skipped += st.pair_tests_skipped;
            stats.grid_rays += st.grid_rays;
            stats.refined += st.refined;
            stats.travel_samples += st.travel_samples;
            stats.machine_time_s = stats.machine_time_s.max(st.machine_time_s);
            for e in st.effects {
                if !stats.effects.contains(&e) {
                    stats.effects.push(e);
                }
            }
        }
        out.extend(self.late);
        let cross = self.cross.map(Cross::finish);
        if let Some((findings, probes)) = cross {
            out.extend(findings);
            stats.pair_tests += probes;
            stats.effects.push("paths".to_string());
        }
        (out, stats)
    }
}

/// Whether `w` goes on from `h` as one move: straight on at the same speed (the point where they
/// meet within 1e-9 mm of where one move from `h`'s start to `w`'s end puts it then, every extra
/// axis too), right after it, with the same kind, station, line and modes. Kept moves that go
/// on so are kept as one (a replay's samples of one move are one move again): what a look back
/// searches is then as many pieces as moves, not samples.
fn continues(h: &Timed, w: &Timed) -> bool {
    let same = h.m.kind == w.m.kind
        && matches!(h.m.kind, MoveKind::Line | MoveKind::Rapid)
        && h.m.station == w.m.station
        && h.m.line == w.m.line
        && h.m.tip == w.m.tip
        && h.m.end == w.m.start
        // Right after it: its start where `h` ends, but for the rounding of sums of times.
        && (h.t0 + h.duration - w.t0).abs() <= 1e-9;
    if !same || h.duration <= 0.0 || w.duration <= 0.0 {
        return false;
    }
    let f = h.duration / (h.duration + w.duration);
    let on = |a: f64, b: f64, c: f64| (a + (c - a) * f - b).abs() <= 1e-9;
    let point = on(h.m.start.x, h.m.end.x, w.m.end.x) && on(h.m.start.y, h.m.end.y, w.m.end.y);
    let extra = match (&h.e, &w.e) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.arc.is_none()
                && b.arc.is_none()
                && a.c_mode == b.c_mode
                && a.live_rpm == b.live_rpm
                && a.plane == b.plane
                && a.origin == b.origin
                && a.end == b.start
                && (0..4).all(|k| on(a.start[k], a.end[k], b.end[k]))
        }
        _ => false,
    };
    point && extra
}

/// Each lane with its run (of an interval, or of a look back) as the carriers' check reads it.
fn carriages<'a>(
    lanes: &'a [Lane],
    runs: &'a [(Interpretation, crate::motion::Timeline)],
    names: &'a [(String, bool)],
) -> Vec<cross::Carriage<'a>> {
    static SCHEDULE: std::sync::OnceLock<Schedule> = std::sync::OnceLock::new();
    let schedule = SCHEDULE.get_or_init(Schedule::default);
    lanes
        .iter()
        .zip(runs)
        .zip(names)
        .map(|((l, (run, timeline)), (name, opposite))| cross::Carriage {
            path: l.path,
            name: name.clone(),
            machine: l.machine,
            run,
            timeline,
            schedule,
            opposite: *opposite,
        })
        .collect()
}

impl<'m> Lane<'m> {
    /// Whether carrier sample `c` names only axes and stations this carrier has.
    fn validate(&self, c: &Carrier) -> Result<(), String> {
        let of = if self.path == 1 {
            String::new()
        } else {
            format!(" of path {}", self.path)
        };
        for (k, v) in c.axes.iter().enumerate() {
            if v.is_some() && !self.has[k] {
                return Err(format!("the carrier{of} has no {} axis", AXES[k]));
            }
        }
        if let Some(tool) = c.tool {
            if tool == 0 || tool > self.machine.turret.stations {
                return Err(format!(
                    "tool {tool}: the turret{of} has stations 1 to {}",
                    self.machine.turret.stations
                ));
            }
        }
        Ok(())
    }

    /// Take the sample at time `t` (its shared fields `s`, this carrier's `c`): check the move
    /// from the sample before. Returns the moves handed to the checker.
    fn take(&mut self, t: f64, s: &Sample, c: &Carrier) -> u32 {
        self.window.clear();
        let prev = self.now.unwrap_or_else(|| self.start());
        let mut next = Now {
            t,
            axes: prev.axes,
            tool: c.tool.unwrap_or(prev.tool),
            spindle: s.spindle.unwrap_or(prev.spindle),
            motion: c.motion.unwrap_or(prev.motion),
            line: c.line.unwrap_or(prev.line),
            c_axis: s.c_axis.unwrap_or(prev.c_axis),
            live_rpm: c.live_rpm.unwrap_or(prev.live_rpm),
            tailstock: s.tailstock.unwrap_or(prev.tailstock),
            sub_chuck: s.sub_chuck.unwrap_or(prev.sub_chuck),
        };
        for (k, v) in c.axes.iter().enumerate() {
            if let Some(v) = v {
                next.axes[k] = *v;
            }
        }
        // While the main spindle turns, C is its angle: the part is revolved, C moves nothing.
        if next.spindle != SpindleDir::Off && !next.c_axis {
            next.axes[3] = prev.axes[3];
        }
        let Some(prev) = self.now.replace(next) else {
            // The first sample: where the machine stands, nothing moved yet.
            self.moved_at = t;
            return 0;
        };
        let mut moves = 0;
        let moved = next.axes != prev.axes;
        if next.tool != prev.tool {
            // The index ended at this sample and took the turret's index time, within the
            // interval since the carrier last moved.
            let probe = Move {
                kind: MoveKind::ToolChange {
                    from: prev.tool,
                    to: next.tool,
                },
                ..self.motion(&prev, &prev, &next)
            };
            let index = crate::motion::Clock::new(self.machine)
                .time(&probe, &spindle(&next), None)
                .duration;
            let end = if moved { 0.5 * (prev.t + t) } else { t };
            let t0 = (end - index).max(self.moved_at).min(end);
            if t0 > prev.t {
                self.stand(&prev, &next, prev.t, t0);
            }
            let at = Now {
                tool: next.tool,
                ..prev
            };
            let m = Move {
                kind: probe.kind,
                ..self.motion(&at, &at, &next)
            };
            let e = self.extra(&at, &at, &next);
            self.feed(m, e, &next, t0, end - t0);
            moves += 1;
            if moved {
                let from = Now {
                    tool: next.tool,
                    ..prev
                };
                let m = self.motion(&from, &next, &next);
                let e = self.extra(&from, &next, &next);
                self.feed(m, e, &next, end, t - end);
                moves += 1;
            } else if end < t {
                self.stand(&next, &next, end, t);
            }
        } else if moved {
            let m = self.motion(&prev, &next, &next);
            let e = self.extra(&prev, &next, &next);
            self.feed(m, e, &next, prev.t, t - prev.t);
            moves += 1;
        } else {
            self.stand(&prev, &next, prev.t, t);
        }
        if moves > 0 {
            self.moved_at = t;
        }
        moves
    }

    /// Check move `m` from `t0` for `duration` s, and keep it for the carriers' check.
    fn feed(&mut self, m: Move, e: Option<ExtraMove>, next: &Now, t0: f64, duration: f64) {
        self.stream.feed_timed(&m, &self.state(next), e.as_ref(), t0, duration);
        self.window.push(Timed { m, e, t0, duration });
    }

    /// The carrier stood where `a` has it from `t0` to `t1`: nothing to check on its lathe, but
    /// the carriers' check needs where it stood.
    fn stand(&mut self, a: &Now, s: &Now, t0: f64, t1: f64) {
        let m = Move {
            kind: MoveKind::Line,
            ..self.motion(a, a, s)
        };
        let e = self.extra(a, a, s);
        self.window.push(Timed {
            m,
            e,
            t0,
            duration: t1 - t0,
        });
    }

    /// The interval's moves as a run of their own, timed in the machine's clock.
    fn window_run(&mut self, from: f64, to: f64) -> (Interpretation, crate::motion::Timeline) {
        if self.window.is_empty() {
            // The first sample: standing where it is.
            if let Some(n) = self.now {
                self.stand(&n, &n, from, to);
            }
        }
        let items = std::mem::take(&mut self.window);
        self.run_of(items.iter())
    }

    /// Keep the interval's moves for a look back: they take the place of the moves kept from
    /// their first one's start on (a turret index learnt now began before the sample before, and
    /// the carrier was indexing, not standing, since), and what ended more than `horizon` seconds
    /// before `now` is let go.
    fn remember(&mut self, now: f64, horizon: f64) {
        if let Some(w0) = self.window.first().map(|w| w.t0) {
            while self.history.back().is_some_and(|h| h.t0 >= w0) {
                self.history.pop_back();
            }
        }
        for w in &self.window {
            match self.history.back_mut() {
                Some(h) if continues(h, w) => {
                    h.m.end = w.m.end;
                    h.duration = w.t0 + w.duration - h.t0;
                    if let (Some(he), Some(we)) = (h.e.as_mut(), w.e.as_ref()) {
                        he.end = we.end;
                    }
                }
                _ => self.history.push_back(w.clone()),
            }
        }
        while self.history.front().is_some_and(|h| h.t0 + h.duration < now - horizon) {
            self.history.pop_front();
        }
    }

    /// The moves kept that overlap `start`..`end`, as a run of their own.
    fn history_run(&self, start: f64, end: f64) -> (Interpretation, crate::motion::Timeline) {
        self.run_of(self.history.iter().filter(|h| h.t0 < end && h.t0 + h.duration > start))
    }

    /// Timed moves (in order) as a run of their own, timed in the machine's clock.
    fn run_of<'a>(&self, timed: impl Iterator<Item = &'a Timed>) -> (Interpretation, crate::motion::Timeline) {
        let mut run = Interpretation::default();
        let mut items = Vec::new();
        if let Some(n) = self.now {
            run.states.push(self.state(&n));
        }
        for (index, w) in timed.enumerate() {
            let path = match w.m.kind {
                MoveKind::Rapid | MoveKind::Line => crate::motion::Path::Line {
                    from: w.m.ref_start(),
                    to: w.m.ref_end(),
                },
                _ => crate::motion::Path::Still(w.m.ref_start()),
            };
            items.push(crate::motion::Timed {
                index,
                t0: w.t0,
                duration: w.duration.max(0.0),
                path,
            });
            if let Some(mut e) = w.e {
                e.index = index as u32;
                run.extra.push(e);
            }
            run.moves.push(Move { state: 0, ..w.m });
        }
        let total = items.last().map_or(0.0, |it: &crate::motion::Timed| it.t1());
        (
            run,
            crate::motion::Timeline {
                items,
                total,
                feed_without_speed: Vec::new(),
            },
        )
    }

    /// The machine before its first sample: at home, the start station, every extra axis at its
    /// start value, the spindle stopped, feeding.
    fn start(&self) -> Now {
        let mz = self.machine.machine_zero;
        let home = self.machine.home;
        let mut axes = [home.x - mz.x, home.y - mz.y, 0.0, 0.0, 0.0, 0.0];
        if let Some(k) = &self.machine.kinematics {
            for (i, &a) in AXES.iter().enumerate().skip(2) {
                if let Some(id) = k.axis_by_letter(a) {
                    axes[i] = k.axes[id].zero;
                }
            }
        }
        Now {
            t: 0.0,
            axes,
            tool: self.machine.turret.start_station,
            spindle: SpindleDir::Off,
            motion: Motion::Feed,
            line: 0,
            c_axis: false,
            live_rpm: 0.0,
            tailstock: self.machine.tailstock_advanced,
            sub_chuck: false,
        }
    }

    fn reference(&self, n: &Now) -> P2 {
        let mz = self.machine.machine_zero;
        P2::new(mz.x + n.axes[0], mz.y + n.axes[1])
    }

    fn tip(&self, station: u32) -> V2 {
        self.machine.tool(station).map_or(V2::new(0.0, 0.0), |t| t.tip.coords)
    }

    /// The straight move of the reference point from `a` to `b` with `a`'s tool, in the motion
    /// and at the line of `s`.
    fn motion(&self, a: &Now, b: &Now, s: &Now) -> Move {
        let tip = self.tip(a.tool);
        let (start, end) = (self.reference(a) + tip, self.reference(b) + tip);
        let dt = (s.t - a.t).max(1e-9);
        let kind = match s.motion {
            Motion::Rapid => MoveKind::Rapid,
            Motion::Feed => MoveKind::Line,
        };
        Move {
            kind,
            line: s.line,
            n: None,
            profile_line: 0,
            start,
            end,
            tip,
            station: a.tool,
            feed: match s.motion {
                Motion::Rapid => Feed::Rapid,
                Motion::Feed => Feed::PerMinute(((end - start).norm() / dt * 60.0).max(1e-6)),
            },
            state: 0,
        }
    }

    /// The extra-axis entry of the move from `a` to `b` in the modes of `s`, when it needs one
    /// (as the interpreter keeps them: an extra axis away from 0, the C-axis mode, a live tool).
    fn extra(&self, a: &Now, b: &Now, s: &Now) -> Option<ExtraMove> {
        let start: interp::ExtraAxes = [a.axes[2], a.axes[3], a.axes[4], a.axes[5]];
        let end: interp::ExtraAxes = [b.axes[2], b.axes[3], b.axes[4], b.axes[5]];
        let keep = start.iter().chain(end.iter()).any(|&v| v != 0.0) || s.c_axis || s.live_rpm > 0.0;
        keep.then_some(ExtraMove {
            index: self.stream.next_index() as u32,
            start,
            end,
            plane: Plane::Zx,
            c_mode: s.c_axis,
            live_rpm: s.live_rpm,
            origin: [0.0; 4],
            arc: None,
        })
    }

    fn state(&self, s: &Now) -> MoveState {
        MoveState {
            spindle: spindle(s),
            // Points in reports: the tool tip in machine coordinates, X a radius.
            frame: ProgFrame {
                origin: self.machine.machine_zero,
                scale: 1.0,
                diameter: false,
            },
            tailstock_advanced: s.tailstock,
            tool_unknown: self.machine.tool(s.tool).is_none(),
            sub_chuck_closed: s.sub_chuck,
        }
    }
}

fn spindle(s: &Now) -> Spindle {
    Spindle {
        dir: match s.spindle {
            SpindleDir::Off => interp::SpindleDir::Off,
            SpindleDir::Cw => interp::SpindleDir::Cw,
            SpindleDir::Ccw => interp::SpindleDir::Ccw,
        },
        speed: SpindleSpeed::Rpm(0.0),
    }
}

/// Per-sample processing times: median, 99th percentile and maximum (docs/follow.md,
/// "Latency"). Kept in a histogram of 1 µs buckets up to 100 ms (and one bucket past it), so a
/// stream of any length keeps a fixed size.
#[derive(Clone, Debug)]
pub struct Latency {
    buckets: Vec<u64>,
    count: u64,
    max_ns: u64,
    total_ns: u128,
}

const BUCKETS: usize = 100_000;

impl Default for Latency {
    fn default() -> Latency {
        Latency {
            buckets: vec![0; BUCKETS + 1],
            count: 0,
            max_ns: 0,
            total_ns: 0,
        }
    }
}

/// A summary of [`Latency`], µs.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LatencySummary {
    pub samples: u64,
    pub median_us: f64,
    pub p99_us: f64,
    pub max_us: f64,
    pub mean_us: f64,
}

impl Latency {
    pub fn add(&mut self, ns: u64) {
        let b = ((ns / 1000) as usize).min(BUCKETS);
        self.buckets[b] += 1;
        self.count += 1;
        self.max_ns = self.max_ns.max(ns);
        self.total_ns += u128::from(ns);
    }

    /// The time below which a fraction `q` of the samples took, µs (a bucket's upper end).
    fn quantile(&self, q: f64) -> f64 {
        if self.count == 0 {
            return 0.0;
        }
        let want = ((q * self.count as f64).ceil() as u64).clamp(1, self.count);
        let mut seen = 0;
        for (b, &n) in self.buckets.iter().enumerate() {
            seen += n;
            if seen >= want {
                return ((b + 1) as f64).min(self.max_ns as f64 / 1000.0);
            }
        }
        self.max_ns as f64 / 1000.0
    }

    pub fn summary(&self) -> LatencySummary {
        LatencySummary {
            samples: self.count,
            median_us: self.quantile(0.5),
            p99_us: self.quantile(0.99),
            max_us: self.max_ns as f64 / 1000.0,
            mean_us: if self.count == 0 {
                0.0
            } else {
                self.total_ns as f64 / self.count as f64 / 1000.0
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn timed(from: (f64, f64), to: (f64, f64), t0: f64, duration: f64, line: u32) -> Timed {
        Timed {
            m: Move {
                kind: MoveKind::Line,
                line,
                n: None,
                profile_line: 0,
                start: P2::new(from.0, from.1),
                end: P2::new(to.0, to.1),
                tip: V2::new(-60.0, -12.0),
                station: 1,
                feed: Feed::PerMinute(100.0),
                state: 0,
            },
            e: None,
            t0,
            duration,
        }
    }

    /// The samples of one straight move at one speed are kept as one move (so a look back
    /// searches moves, not samples); a bend, a change of speed, a gap in time or another line
    /// keeps them apart.
    #[test]
    fn samples_of_one_straight_move_are_kept_as_one() {
        let a = timed((0.0, 0.0), (1.0, 2.0), 0.0, 0.1, 5);
        assert!(continues(&a, &timed((1.0, 2.0), (2.0, 4.0), 0.1, 0.1, 5)));
        assert!(continues(&a, &timed((1.0, 2.0), (1.5, 3.0), 0.1, 0.05, 5)));
        // A bend, another speed, a gap, another line.
        assert!(!continues(&a, &timed((1.0, 2.0), (2.0, 4.5), 0.1, 0.1, 5)));
        assert!(!continues(&a, &timed((1.0, 2.0), (2.0, 4.0), 0.1, 0.2, 5)));
        assert!(!continues(&a, &timed((1.0, 2.0), (2.0, 4.0), 0.11, 0.1, 5)));
        assert!(!continues(&a, &timed((1.0, 2.0), (2.0, 4.0), 0.1, 0.1, 6)));
        // Standing is one move too.
        let s = timed((1.0, 2.0), (1.0, 2.0), 0.0, 0.1, 5);
        assert!(continues(&s, &timed((1.0, 2.0), (1.0, 2.0), 0.1, 0.3, 5)));
    }
}
