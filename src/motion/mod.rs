//! Motion: when the machine is where. Every move gets a duration from its feed (per-revolution
//! feeds with the spindle speed in force, CSS at the current radius), rapids run at the
//! machine's per-axis rates (`dogleg`: each axis at its own rate, a bent path; `linear`: both
//! interpolated), dwells stand still, and a turret index takes `index_time` per station.
//!
//! A move with an extra-axis entry (turn-mill machines, [`crate::interp::ExtraMove`]) is timed
//! with its extra axes too: a rapid takes as long as its slowest axis, each extra axis at its own
//! `rapid` from the machine's kinematics; a feed runs F along the combined linear path (x, y, z,
//! and a linear B), and a feed move that moves only rotary axes takes F as degrees per minute
//! over the rotary travel (the Fanuc rule). Moves without an entry are timed as before.
//!
//! [`Timeline`] answers "where is the turret reference point at machine time t"; the fixed-step
//! sampler of the checker and the exact sweeps both read it.

use crate::geom::{P2, V2};
use crate::interp::{ExtraMove, Feed, Interpretation, Move, MoveKind, Spindle, EXTRA_LETTERS};
use crate::machine::{Machine, RapidMode};

/// Pieces used to integrate a per-revolution feed under constant surface speed.
const CSS_PIECES: usize = 32;

/// The feed assumed for a per-revolution feed that has no usable spindle speed (no S, `S0`,
/// `G96 S0`, a `G50 S0` clamp, or a speed below [`MIN_RPM`] anywhere on the move): the move is
/// timed at this rate and reported, rather than taking forever.
pub const FALLBACK_FEED_MM_MIN: f64 = 100.0;

/// Below this spindle speed (rpm) a per-revolution feed counts as having no spindle speed.
pub const MIN_RPM: f64 = 1.0;

/// One move with its timing.
#[derive(Clone, Debug, PartialEq)]
pub struct Timed {
    /// Index into the move list.
    pub index: usize,
    pub t0: f64,
    pub duration: f64,
    pub path: Path,
}

/// How the turret reference point travels during a move.
#[derive(Clone, Debug, PartialEq)]
pub enum Path {
    /// Standing still (dwell, tool change).
    Still(P2),
    /// Straight at constant speed.
    Line { from: P2, to: P2 },
    /// Dogleg rapid: each axis at its own rate; `tx`/`tz` are when each axis arrives.
    Dogleg { from: P2, to: P2, tx: f64, tz: f64 },
    /// A feed whose speed varies along the path (CSS): arc-length fraction at equally spaced
    /// times, `table[k]` is the path fraction at time `k/(len-1) * duration`.
    Varying { table: Vec<f64> },
    /// Constant speed along an arc or line of the programmed point (path fraction = t/duration).
    Uniform,
}

impl Timed {
    pub fn t1(&self) -> f64 {
        self.t0 + self.duration
    }
}

/// All moves of a program, timed back to back.
#[derive(Clone, Debug, Default)]
pub struct Timeline {
    pub items: Vec<Timed>,
    pub total: f64,
    /// Moves whose per-revolution feed has no usable spindle speed (below [`MIN_RPM`] at some
    /// point of the move, CSS included): timed at [`FALLBACK_FEED_MM_MIN`]. Move indices, the
    /// first move of each source line only (a line in a loop is listed once).
    pub feed_without_speed: Vec<usize>,
}

/// Time a move list (all of it at once; the checker times one move at a time with [`Timer`]).
pub fn timeline(run: &Interpretation, machine: &Machine) -> Timeline {
    let mut timer = Timer::new(run, machine);
    let items: Vec<Timed> = timer.by_ref().collect();
    let (total, feed_without_speed) = timer.finish();
    Timeline {
        items,
        total,
        feed_without_speed,
    }
}

/// Moves timed back to back as they come, one at a time: the checker needs only the move in
/// hand, so a long program is never held as a second list beside its moves, and a streamed one
/// ([`crate::interp::interpret_streaming`]) is timed as its chunks arrive.
pub struct Clock<'a> {
    machine: &'a Machine,
    next: usize,
    t: f64,
    stalled: Vec<usize>,
    stalled_lines: std::collections::HashSet<u32>,
}

impl<'a> Clock<'a> {
    pub fn new(machine: &'a Machine) -> Self {
        Clock {
            machine,
            next: 0,
            t: 0.0,
            stalled: Vec::new(),
            stalled_lines: std::collections::HashSet::new(),
        }
    }

    /// Time the next move of the program: `m` with the spindle in force and its extra-axis entry.
    pub fn time(&mut self, m: &Move, spindle: &Spindle, e: Option<&ExtraMove>) -> Timed {
        let i = self.next;
        self.next += 1;
        let (stalled, stalled_lines) = (&mut self.stalled, &mut self.stalled_lines);
        let mut on_stall = || {
            if stalled_lines.insert(m.line) {
                stalled.push(i);
            }
        };
        let (duration, path) = match e {
            Some(e) => time_move_extra(m, e, spindle, self.machine, &mut on_stall),
            None => time_move(m, spindle, self.machine, &mut on_stall),
        };
        let duration = if duration.is_finite() && duration >= 0.0 {
            duration
        } else {
            0.0
        };
        let item = Timed {
            index: i,
            t0: self.t,
            duration,
            path,
        };
        self.t += duration;
        item
    }

    /// The moves timed so far whose per-revolution feed had no usable spindle speed (see
    /// [`Timeline::feed_without_speed`]).
    pub fn stalled(&self) -> &[usize] {
        &self.stalled
    }

    /// The machine time of the moves timed, and the moves of [`Clock::stalled`].
    pub fn finish(self) -> (f64, Vec<usize>) {
        (self.t, self.stalled)
    }
}

/// The moves of an interpreted program timed back to back, one at a time (a [`Clock`] over
/// [`Interpretation::moves`]).
pub struct Timer<'a> {
    run: &'a Interpretation,
    clock: Clock<'a>,
    /// The next entry of `run.extra` not passed yet.
    next_extra: usize,
}

impl<'a> Timer<'a> {
    pub fn new(run: &'a Interpretation, machine: &'a Machine) -> Self {
        Timer {
            run,
            clock: Clock::new(machine),
            next_extra: 0,
        }
    }

    /// Time the moves not taken yet, then return the total machine time and the moves whose
    /// per-revolution feed had no usable spindle speed (see [`Timeline::feed_without_speed`]).
    pub fn finish(mut self) -> (f64, Vec<usize>) {
        for _ in self.by_ref() {}
        self.clock.finish()
    }
}

impl Iterator for Timer<'_> {
    type Item = Timed;

    fn next(&mut self) -> Option<Timed> {
        let i = self.clock.next;
        let m = self.run.moves.get(i)?;
        let extra = &self.run.extra;
        while self.next_extra < extra.len() && (extra[self.next_extra].index as usize) < i {
            self.next_extra += 1;
        }
        let e = extra.get(self.next_extra).filter(|e| e.index as usize == i);
        Some(self.clock.time(m, self.run.spindle(m), e))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let left = self.run.moves.len() - self.clock.next;
        (left, Some(left))
    }
}

/// How far each extra axis travels in a move, and whether it is linear; the rapid rate of each
/// (mm/min or degrees/min) from the machine's kinematics (0 when the machine lacks the axis).
fn extra_axes_of(e: &ExtraMove, machine: &Machine) -> [(f64, bool, f64); 4] {
    let mut out = [(0.0, true, 0.0); 4];
    for (k, o) in out.iter_mut().enumerate() {
        let d = (e.end[k] - e.start[k]).abs();
        let (linear, rapid) = machine
            .kinematics
            .as_deref()
            .and_then(|kin| kin.axis_by_letter(EXTRA_LETTERS[k]).map(|a| &kin.axes[a]))
            .map_or((k != 1 && k != 3, 0.0), |a| {
                (matches!(a.kind, crate::kin::AxisKind::Linear { .. }), a.rapid)
            });
        *o = (d, linear, rapid);
    }
    out
}

/// [`time_move`] for a move with an extra-axis entry.
fn time_move_extra(
    m: &Move,
    e: &ExtraMove,
    spindle: &Spindle,
    machine: &Machine,
    stalled: &mut dyn FnMut(),
) -> (f64, Path) {
    let axes = extra_axes_of(e, machine);
    match m.kind {
        MoveKind::Rapid => {
            let (d2, path) = time_move(m, spindle, machine, stalled);
            let slowest = axes
                .iter()
                .filter(|a| a.0 > 0.0)
                .map(|&(d, _, rapid)| if rapid > 0.0 { d / (rapid / 60.0) } else { 0.0 })
                .fold(d2, f64::max);
            (slowest, path)
        }
        MoveKind::Line | MoveKind::Arc { .. } => {
            // The combined linear path: the 2D path (or the G17/G19 helix) with y, and a
            // linear B; without any linear travel, the rotary travel in degrees.
            let base = crate::interp::length3(m, e);
            let other_linear: f64 = axes[1..].iter().filter(|a| a.1).map(|a| a.0 * a.0).sum();
            let linear = (base * base + other_linear).sqrt();
            let len = if linear > 1e-9 {
                linear
            } else {
                axes.iter().filter(|a| !a.1).map(|a| a.0 * a.0).sum::<f64>().sqrt()
            };
            time_feed(m, len, spindle, stalled)
        }
        _ => time_move(m, spindle, machine, stalled),
    }
}

fn time_move(m: &Move, spindle: &Spindle, machine: &Machine, stalled: &mut dyn FnMut()) -> (f64, Path) {
    let from = m.ref_start();
    let to = m.ref_end();
    match m.kind {
        MoveKind::Dwell { seconds } => (seconds, Path::Still(from)),
        // The operator's turn-round: the machine stands; its time is the operator's, not counted.
        MoveKind::Operation { .. } | MoveKind::Wait { .. } => (0.0, Path::Still(from)),
        MoveKind::ToolChange { from: a, to: b } => {
            // A drum turns station by station; a gang slide changes tools in one step.
            let steps = match machine.turret.kind {
                crate::machine::TurretKind::Drum => index_steps(a, b, machine.turret.stations),
                crate::machine::TurretKind::Gang => u32::from(a != b),
            };
            (steps as f64 * machine.turret.index_time, Path::Still(from))
        }
        MoveKind::Rapid => {
            let d = to - from;
            let tx = d.x.abs() / (machine.x.rapid / 60.0);
            let tz = d.y.abs() / (machine.z.rapid / 60.0);
            match machine.rapid {
                RapidMode::Dogleg => (tx.max(tz), Path::Dogleg { from, to, tx, tz }),
                RapidMode::Linear => (tx.max(tz), Path::Line { from, to }),
            }
        }
        MoveKind::Line | MoveKind::Arc { .. } => time_feed(m, m.length(), spindle, stalled),
    }
}

/// A feed move of path length `len` (mm, or degrees for a rotary-only move).
fn time_feed(m: &Move, len: f64, spindle: &Spindle, stalled: &mut dyn FnMut()) -> (f64, Path) {
    match m.feed {
        Feed::Rapid => (0.0, Path::Uniform),
        Feed::PerMinute(f) => (len / (f / 60.0), Path::Uniform),
        Feed::PerRev(f) => {
            let mut sp = *spindle;
            if !sp.is_on() {
                // Timing as if on: the check reports cutting with the spindle stopped.
                sp.dir = crate::interp::SpindleDir::Cw;
            }
            let css = matches!(sp.speed, crate::interp::SpindleSpeed::Css { .. });
            let fallback = (len / (FALLBACK_FEED_MM_MIN / 60.0), Path::Uniform);
            if !css {
                let rpm = sp.rpm_at(m.start.x);
                // NaN (no speed at all) counts as no speed.
                if rpm.is_nan() || rpm < MIN_RPM {
                    stalled();
                    return fallback;
                }
                return (len / (f * rpm / 60.0), Path::Uniform);
            }
            // Integrate dt = ds / (f · rpm(r)) over the path, then tabulate the
            // inverse (fraction at equal times). A surface speed of 0 (G96 without S,
            // G96 S0), a clamp of 0, or a radius so large that the speed falls below
            // MIN_RPM has no usable speed: the whole move takes the fallback feed.
            let n = CSS_PIECES;
            let mut cum = vec![0.0f64; n + 1];
            for k in 0..n {
                let u = (k as f64 + 0.5) / n as f64;
                let r = m.point_at(u).x.abs();
                let rpm = sp.rpm_at(r);
                if rpm.is_nan() || rpm < MIN_RPM {
                    stalled();
                    return fallback;
                }
                let v = f * rpm / 60.0;
                cum[k + 1] = cum[k] + (len / n as f64) / v;
            }
            let total = cum[n];
            let mut table = Vec::with_capacity(n + 1);
            let mut k = 0;
            for j in 0..=n {
                let target = total * j as f64 / n as f64;
                while k < n && cum[k + 1] < target {
                    k += 1;
                }
                let span = cum[(k + 1).min(n)] - cum[k];
                let frac = if span > 0.0 { (target - cum[k]) / span } else { 0.0 };
                table.push(((k as f64 + frac.clamp(0.0, 1.0)) / n as f64).min(1.0));
            }
            (total, Path::Varying { table })
        }
    }
}

/// Stations the turret passes to go from `a` to `b` the short way round.
pub fn index_steps(a: u32, b: u32, stations: u32) -> u32 {
    let n = stations.max(1);
    let fwd = (b + n - a % n) % n;
    fwd.min(n - fwd)
}

/// The signed station steps of an index the short way round (ties go forward).
pub fn index_direction(a: u32, b: u32, stations: u32) -> i64 {
    let n = stations.max(1) as i64;
    let fwd = ((b as i64 - a as i64) % n + n) % n;
    if fwd <= n - fwd {
        fwd
    } else {
        fwd - n
    }
}

/// The programmed point's path as the machine drives a dogleg rapid, where that differs from the
/// programmed line: start, the bend where the first axis arrives, end. Empty for every other move
/// (and a dogleg where only one axis moves: the machine follows the line). For pictures.
pub fn machine_path(m: &Move, item: &Timed) -> Vec<P2> {
    match &item.path {
        Path::Dogleg { from, to, tx, tz }
            if (tx - tz).abs() > 1e-12 && (to.x - from.x).abs() > 1e-9 && (to.y - from.y).abs() > 1e-9 =>
        {
            let corner = reference_at(m, item, tx.min(*tz));
            vec![from + m.tip, corner + m.tip, to + m.tip]
        }
        _ => Vec::new(),
    }
}

/// Where the turret reference point is `dt` seconds into a move (clamped to the move).
pub fn reference_at(m: &Move, item: &Timed, dt: f64) -> P2 {
    let d = item.duration;
    let u = if d > 0.0 { (dt / d).clamp(0.0, 1.0) } else { 1.0 };
    match &item.path {
        Path::Still(p) => *p,
        Path::Line { from, to } => from + (to - from) * u,
        Path::Dogleg { from, to, tx, tz } => {
            let fx = if *tx > 0.0 { (dt / tx).clamp(0.0, 1.0) } else { 1.0 };
            let fz = if *tz > 0.0 { (dt / tz).clamp(0.0, 1.0) } else { 1.0 };
            P2::new(from.x + (to.x - from.x) * fx, from.y + (to.y - from.y) * fz)
        }
        Path::Uniform | Path::Varying { .. } => m.point_at(fraction_at(item, dt)) - m.tip,
    }
}

/// Axis-aligned box of the turret reference point over a whole move.
pub fn reference_box(m: &Move, item: &Timed) -> crate::geom::Aabb {
    let mut b = crate::geom::Aabb::of_points(&[m.ref_start(), m.ref_end()]);
    if let MoveKind::Arc { center, sweep } = m.kind {
        // Include the axis-extreme points the arc passes.
        let a = m.start - center;
        let r = a.norm().max((m.end - center).norm());
        let a0 = a.y.atan2(a.x);
        let tip = m.tip;
        let (lo, hi) = if sweep >= 0.0 {
            (a0, a0 + sweep)
        } else {
            (a0 + sweep, a0)
        };
        let first = (lo / std::f64::consts::FRAC_PI_2).ceil() as i64;
        let last = (hi / std::f64::consts::FRAC_PI_2).floor() as i64;
        let mut k = first;
        while k <= last && k - first < 8 {
            let ang = k as f64 * std::f64::consts::FRAC_PI_2;
            b.add(center + V2::new(r * ang.cos(), r * ang.sin()) - tip);
            k += 1;
        }
        // A spiral's radius lies between the two; pad by the difference.
        let pad = ((m.end - center).norm() - a.norm()).abs();
        b = b.inflate(pad);
    }
    let _ = item;
    b
}

/// The path of the turret reference point between two instants `ta` ≤ `tb` of a move (seconds
/// from the move's start) when it is a polyline that never turns back along itself: `Some(None)`
/// when it is the straight segment between the two points, `Some(Some(c))` when it bends once at
/// `c` (a dogleg rapid whose first axis arrives in between), `None` on an arc.
pub fn polyline_between(m: &Move, item: &Timed, ta: f64, tb: f64) -> Option<Option<P2>> {
    match &item.path {
        Path::Still(_) | Path::Line { .. } => Some(None),
        Path::Dogleg { tx, tz, .. } => {
            let tc = tx.min(*tz);
            Some((tc > ta && tc < tb).then(|| reference_at(m, item, tc)))
        }
        Path::Uniform | Path::Varying { .. } => (!matches!(m.kind, MoveKind::Arc { .. })).then_some(None),
    }
}

/// An upper bound of the speed of the turret reference point during a move, mm/s.
pub fn max_speed(m: &Move, item: &Timed) -> f64 {
    let d = item.duration;
    if d <= 0.0 {
        return f64::INFINITY;
    }
    let upper_len = match m.kind {
        MoveKind::Arc { center, sweep } => {
            let (r0, r1) = ((m.start - center).norm(), (m.end - center).norm());
            r0.max(r1) * sweep.abs() + (r1 - r0).abs()
        }
        _ => (m.end - m.start).norm(),
    };
    let v = match &item.path {
        Path::Still(_) => 0.0,
        Path::Line { from, to } => (to - from).norm() / d,
        Path::Dogleg { from, to, tx, tz } => {
            let vx = if *tx > 0.0 { (to.x - from.x).abs() / tx } else { 0.0 };
            let vz = if *tz > 0.0 { (to.y - from.y).abs() / tz } else { 0.0 };
            vx.hypot(vz)
        }
        Path::Uniform => upper_len / d,
        Path::Varying { table } => {
            let n = (table.len() - 1).max(1) as f64;
            let step = table.windows(2).map(|w| w[1] - w[0]).fold(0.0f64, f64::max);
            step * upper_len / (d / n)
        }
    };
    v * (1.0 + 1e-9) + 1e-12
}

/// The fraction of the programmed path a feed move has covered `dt` seconds into it (the
/// parameter of [`Move::point_at`]); 1 for moves that do not follow the programmed path.
pub fn fraction_at(item: &Timed, dt: f64) -> f64 {
    let d = item.duration;
    let u = if d > 0.0 { (dt / d).clamp(0.0, 1.0) } else { 1.0 };
    match &item.path {
        Path::Uniform => u,
        Path::Varying { table } => {
            let n = table.len() - 1;
            let x = u * n as f64;
            let k = (x.floor() as usize).min(n.saturating_sub(1));
            table[k] + (table[(k + 1).min(n)] - table[k]) * (x - k as f64)
        }
        _ => 1.0,
    }
}

/// One path's axes on a kinematic tree (`kin`): the axis X, Z and each extra letter
/// (`interp::EXTRA_LETTERS`: Y, C, B, A) drive, by index. The one place a move's axis values and
/// their rates are read for the tree (the 3D path, `check/three.rs`; the carriers between paths,
/// `paths/cross3.rs`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TreeAxes {
    pub x: Option<usize>,
    pub z: Option<usize>,
    pub extra: [Option<usize>; 4],
}

impl TreeAxes {
    /// Write the axis values at time fraction `u` of move `m` into `out`: X and Z the turret
    /// reference point as [`reference_at`] times it (dogleg rapids too), the extra axes linearly
    /// over the move, a G17/G19 arc along `interp::position3`. Without an extra-axis entry the
    /// extra axes keep the values `out` holds (their start values, as the caller fills it).
    pub fn values(&self, m: &Move, e: Option<&crate::interp::ExtraMove>, item: &Timed, u: f64, out: &mut [f64]) {
        let (x, y, z, ex) = match e.filter(|e| e.arc.is_some()) {
            Some(e) => {
                let (p, ex) = crate::interp::position3(m, Some(e), u);
                (p[0] - m.tip.x, p[1], p[2] - m.tip.y, ex)
            }
            None => {
                let r = reference_at(m, item, u * item.duration);
                let mut ex = [0.0; 4];
                for (k, v) in ex.iter_mut().enumerate() {
                    *v = match e {
                        Some(e) => e.start[k] + (e.end[k] - e.start[k]) * u,
                        None => self.extra[k].and_then(|a| out.get(a).copied()).unwrap_or(0.0),
                    };
                }
                (r.x, ex[0], r.y, ex)
            }
        };
        let mut set = |a: Option<usize>, v: f64| {
            if let Some(slot) = a.and_then(|a| out.get_mut(a)) {
                *slot = v;
            }
        };
        set(self.x, x);
        set(self.z, z);
        for (k, a) in self.extra.iter().enumerate() {
            set(*a, if k == 0 { y } else { ex[k] });
        }
    }

    /// Write, per axis, a bound of how far its value travels over the whole move (its rate per
    /// unit of the time fraction `u`): the reference point's greatest speed bounds each of its
    /// coordinates' (dogleg rapids included), an arc's length its axes'.
    pub fn rates(&self, m: &Move, e: Option<&crate::interp::ExtraMove>, item: &Timed, out: &mut [f64]) {
        let v = if item.duration > 0.0 {
            max_speed(m, item) * item.duration
        } else {
            0.0
        };
        let v = if v.is_finite() { v } else { f64::MAX };
        let arc = e.and_then(|e| e.arc.map(|_| crate::interp::length3(m, e)));
        let lin = arc.map_or(v, |l| l.max(v));
        let mut set = |a: Option<usize>, v: f64| {
            if let Some(slot) = a.and_then(|a| out.get_mut(a)) {
                *slot = v;
            }
        };
        set(self.x, lin);
        set(self.z, lin);
        if let Some(e) = e {
            for (k, a) in self.extra.iter().enumerate() {
                set(
                    *a,
                    if k == 0 && arc.is_some() {
                        lin
                    } else {
                        (e.end[k] - e.start[k]).abs()
                    },
                );
            }
        }
    }
}
