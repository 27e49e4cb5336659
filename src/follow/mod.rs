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
use crate::interp::{self, ExtraMove, Feed, Move, MoveKind, MoveState, Plane, ProgFrame, Spindle, SpindleSpeed};
use crate::machine::Machine;
use crate::pipeline::Settings;
pub use sample::{Format, Motion, Reader, Sample, SampleError, SpindleDir, AXES};

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

/// On a machine with several paths, what `follow` leaves unchecked, said once before the first
/// sample: it follows path 1's carrier only (its samples are path 1's axes), so the other
/// carriers — their tools against the chuck and the stock, and their contacts with path 1's —
/// are not checked, and a stream with no finding would not mean they cannot crash. An
/// `unsupported` error (a run on such a machine never ends clean), at no line.
pub fn unfollowed(machine: &Machine) -> Option<Finding> {
    let n = machine.paths.count();
    if n < 2 {
        return None;
    }
    let others: Vec<String> = machine
        .paths
        .carriers
        .iter()
        .map(|c| format!("path {} ({})", c.path, c.name))
        .collect();
    let others = if others.is_empty() {
        format!("the other {} paths", n - 1)
    } else {
        others.join(", ")
    };
    Some(Finding::at(
        crate::finding::Kind::Unsupported,
        crate::finding::Severity::Error,
        0,
        0,
        format!(
            "this machine has {n} paths and follow checks path 1's carrier only (the samples are its axes): {others} is not checked, nor its contacts with path 1's"
        ),
    ))
}

/// The machine's state after a sample: every field a sample may leave out, as the last sample
/// that gave it left it.
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
    /// Moves handed to the checker (0: nothing moved; 2: a turret index and a motion).
    pub moves: u32,
}

/// The checker of one machine's live samples.
pub struct Follower<'m> {
    machine: &'m Machine,
    stream: Stream<'m>,
    now: Option<Now>,
    /// When the machine last moved (a turret index ends at the sample that shows the new tool and
    /// began at most one index time earlier, but not before this).
    moved_at: f64,
    has: [bool; 6],
    samples: u64,
    moves: u64,
}

impl<'m> Follower<'m> {
    /// A follower on `machine` (a job already applied). The work budget of `settings` does not
    /// apply: a stream has no end, and each sample's work is bounded by its move's caps.
    pub fn new(machine: &'m Machine, settings: &Settings) -> Follower<'m> {
        let settings = Settings {
            work_budget: u64::MAX,
            snapshots: false,
            part_mesh: false,
            ..*settings
        };
        // Whether the 3D path runs cannot wait for the whole run: on a machine with a tree it
        // always does (moves that stay in the working plane take its 2D route all the same).
        let three = takes_3d(machine, true, true);
        Follower {
            machine,
            stream: Stream::new(machine, &settings, three, usize::MAX),
            now: None,
            moved_at: 0.0,
            has: machine_axes(machine),
            samples: 0,
            moves: 0,
        }
    }

    /// A reader of samples for this machine: axes it lacks and stations its turret lacks are
    /// errors at their column.
    pub fn reader(&self, format: Format) -> Reader {
        Reader::new(format).for_machine(self.has, self.machine.turret.stations)
    }

    /// The time of the last sample taken, s.
    pub fn time(&self) -> Option<f64> {
        self.now.map(|n| n.t)
    }

    /// Samples taken and moves checked so far.
    pub fn counts(&self) -> (u64, u64) {
        (self.samples, self.moves)
    }

    /// Take the sample read at line `at` of the source: check the move from the sample before to
    /// it. A sample out of order (its time not after the last one's) is an error and changes
    /// nothing; `period` times a sample that has none.
    pub fn push(&mut self, at: u64, s: &Sample, period: Option<f64>) -> Result<Step, SampleError> {
        let err = |message: String| SampleError {
            line: at,
            col: 0,
            message,
        };
        let t = match (s.t, self.now, period) {
            (Some(t), _, _) => t,
            (None, Some(n), Some(p)) => n.t + p,
            (None, None, Some(_)) => 0.0,
            (None, _, None) => return Err(err("the sample has no time `t`".into())),
        };
        if let Some(n) = self.now {
            if t <= n.t {
                return Err(err(format!(
                    "time {t} s is not after the last sample's {} s: the sample is out of order and is skipped",
                    n.t
                )));
            }
        }
        for (k, v) in s.axes.iter().enumerate() {
            if v.is_some() && !self.has[k] {
                return Err(err(format!("the machine has no {} axis", AXES[k])));
            }
        }
        if let Some(tool) = s.tool {
            if tool == 0 || tool > self.machine.turret.stations {
                return Err(err(format!(
                    "tool {tool}: the turret has stations 1 to {}",
                    self.machine.turret.stations
                )));
            }
        }
        self.samples += 1;
        let prev = self.now.unwrap_or_else(|| self.start());
        let mut next = Now {
            t,
            axes: prev.axes,
            tool: s.tool.unwrap_or(prev.tool),
            spindle: s.spindle.unwrap_or(prev.spindle),
            motion: s.motion.unwrap_or(prev.motion),
            line: s.line.unwrap_or(prev.line),
            c_axis: s.c_axis.unwrap_or(prev.c_axis),
            live_rpm: s.live_rpm.unwrap_or(prev.live_rpm),
            tailstock: s.tailstock.unwrap_or(prev.tailstock),
            sub_chuck: s.sub_chuck.unwrap_or(prev.sub_chuck),
        };
        for (k, v) in s.axes.iter().enumerate() {
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
            return Ok(Step::default());
        };
        let mut step = Step::default();
        let moved = next.axes != prev.axes;
        if next.tool != prev.tool {
            // The index ended at this sample and took the turret's index time, within the
            // interval since the machine last moved.
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
            let at = Now {
                tool: next.tool,
                ..prev
            };
            let m = Move {
                kind: probe.kind,
                ..self.motion(&at, &at, &next)
            };
            let e = self.extra(&at, &at, &next);
            self.stream.feed_timed(&m, &self.state(&next), e.as_ref(), t0, end - t0);
            step.moves += 1;
            if moved {
                let from = Now {
                    tool: next.tool,
                    ..prev
                };
                let m = self.motion(&from, &next, &next);
                let e = self.extra(&from, &next, &next);
                self.stream.feed_timed(&m, &self.state(&next), e.as_ref(), end, t - end);
                step.moves += 1;
            }
        } else if moved {
            let m = self.motion(&prev, &next, &next);
            let e = self.extra(&prev, &next, &next);
            self.stream
                .feed_timed(&m, &self.state(&next), e.as_ref(), prev.t, t - prev.t);
            step.moves += 1;
        }
        if step.moves > 0 {
            self.moved_at = t;
            self.moves += u64::from(step.moves);
        }
        Ok(step)
    }

    /// The findings that are final so far ([`Stream::take_final`]): write them now.
    pub fn findings(&mut self) -> Vec<Finding> {
        self.stream.take_final()
    }

    /// The end of the stream: the findings still open, and the statistics of the check.
    pub fn finish(mut self) -> (Vec<Finding>, crate::pipeline::Stats) {
        let mut out = self.stream.take_rest();
        let result = self.stream.finish();
        out.extend(result.findings);
        (out, result.stats)
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
