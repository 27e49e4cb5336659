//! The samples a control's interpolator would report running a program
//! (`latheguard moves --format samples`, docs/follow.md "Replay"): the interpreter's moves timed
//! as `check` times them (`motion`), the machine's state every `dt` seconds of machine time and
//! at the end of every move (and at a dogleg rapid's bend), so that a straight line between two
//! samples follows the move it samples: every corner of the programmed path is a sample, an arc
//! is chorded at `dt`. Followed ([`super::Follower`]), these samples give the program's
//! findings: the replay tests hold them to `check`'s.

use super::sample::{Carrier, Motion, Sample, SpindleDir};
use crate::interp::{self, Interpretation, MoveKind};
use crate::machine::Machine;
use crate::motion::{self, Path};
use crate::paths::TimedPath;

/// Most samples one move is cut into; past it the move's samples are further apart than `dt`.
pub const MAX_SAMPLES_PER_MOVE: u64 = 1_000_000;

/// Samples closer than this to the one before are not written (a move shorter than this has its
/// end in the next sample): times read back from text stay in order.
const MIN_GAP_S: f64 = 1e-7;

/// Hand `out` the samples of `run` on `machine` every `dt` seconds (> 0) of machine time and at
/// every move's end, in time order; a job's later operation (the part turned round) has no
/// sample and is left out.
pub fn samples(run: &Interpretation, machine: &Machine, dt: f64, mut out: impl FnMut(&Sample)) {
    let dt = if dt.is_finite() && dt > 0.0 { dt } else { 0.001 };
    let has = super::machine_axes(machine);
    let mut last_t = f64::NEG_INFINITY;
    let mut extra = run.extra.iter().peekable();
    for item in motion::Timer::new(run, machine) {
        let Some(m) = run.moves.get(item.index) else { break };
        while extra.peek().is_some_and(|e| (e.index as usize) < item.index) {
            extra.next();
        }
        let e = extra.peek().copied().filter(|e| e.index as usize == item.index);
        if matches!(m.kind, MoveKind::Operation { .. }) {
            continue;
        }
        let sample_at = |t: f64, end: bool| -> Sample {
            let (carrier, shared) = state_at(run, m, e, &item, t, end, machine, &has);
            Sample {
                t: Some(t),
                carriers: vec![carrier],
                ..shared
            }
        };
        if last_t == f64::NEG_INFINITY {
            out(&sample_at(item.t0, false));
            last_t = item.t0;
        }
        let t1 = item.t1();
        let mut bend = bend_of(&item);
        let step = dt.max(item.duration / MAX_SAMPLES_PER_MOVE as f64);
        let mut k = (item.t0 / step).floor() + 1.0;
        loop {
            let t = k * step;
            if t >= t1 - MIN_GAP_S {
                break;
            }
            if let Some(b) = bend.filter(|&b| b <= t) {
                if b > last_t + MIN_GAP_S {
                    out(&sample_at(b, false));
                    last_t = b;
                }
                bend = None;
            }
            if t > last_t + MIN_GAP_S {
                out(&sample_at(t, false));
                last_t = t;
            }
            k += 1.0;
        }
        if let Some(b) = bend.filter(|&b| b > last_t + MIN_GAP_S && b < t1 - MIN_GAP_S) {
            out(&sample_at(b, false));
            last_t = b;
        }
        if t1 > last_t + MIN_GAP_S {
            out(&sample_at(t1, true));
            last_t = t1;
        }
    }
}

/// Where a dogleg rapid bends (its first axis arrives), inside the move.
fn bend_of(item: &motion::Timed) -> Option<f64> {
    match item.path {
        Path::Dogleg { tx, tz, .. } => Some(item.t0 + tx.min(tz)).filter(|&b| b > item.t0 && b < item.t1()),
        _ => None,
    }
}

/// One path's carrier at instant `t` of move `m` (timed `item`, extra-axis entry `e`), and the
/// machine's state then; `end`: the move has ended (a turret index shows its new tool).
#[allow(clippy::too_many_arguments)]
fn state_at(
    run: &Interpretation,
    m: &interp::Move,
    e: Option<&interp::ExtraMove>,
    item: &motion::Timed,
    t: f64,
    end: bool,
    machine: &Machine,
    has: &[bool; 6],
) -> (Carrier, Sample) {
    let mz = machine.machine_zero;
    let state = run.states[m.state as usize];
    let u = if item.duration > 0.0 {
        ((t - item.t0) / item.duration).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let (x, z, ex) = match e.filter(|e| e.arc.is_some()) {
        Some(e) => {
            let (p, ex) = interp::position3(m, Some(e), u);
            (p[0] - m.tip.x, p[2] - m.tip.y, ex)
        }
        None => {
            let r = motion::reference_at(m, item, u * item.duration);
            let mut ex = [0.0; 4];
            // No entry: every extra axis at 0 (as the interpreter keeps them).
            if let Some(e) = e {
                for (k, v) in ex.iter_mut().enumerate() {
                    *v = e.start[k] + (e.end[k] - e.start[k]) * u;
                }
            }
            (r.x, r.y, ex)
        }
    };
    let mut axes = [Some(x - mz.x), Some(z - mz.y), None, None, None, None];
    for k in 0..4 {
        if has[k + 2] {
            axes[k + 2] = Some(ex[k]);
        }
    }
    // A turret index shows its new tool when it has ended (as a control's tool number pin
    // changes when the change is done).
    let tool = match m.kind {
        MoveKind::ToolChange { from, .. } if !end => from,
        _ => m.station,
    };
    let carrier = Carrier {
        axes,
        tool: Some(tool),
        motion: Some(if m.kind == MoveKind::Rapid {
            Motion::Rapid
        } else {
            Motion::Feed
        }),
        line: Some(m.line),
        live_rpm: Some(e.map_or(0.0, |e| e.live_rpm)),
    };
    let shared = Sample {
        t: Some(t),
        carriers: Vec::new(),
        spindle: Some(match state.spindle.dir {
            interp::SpindleDir::Off => SpindleDir::Off,
            interp::SpindleDir::Cw => SpindleDir::Cw,
            interp::SpindleDir::Ccw => SpindleDir::Ccw,
        }),
        c_axis: Some(e.is_some_and(|e| e.c_mode)),
        tailstock: Some(state.tailstock_advanced),
        sub_chuck: Some(state.sub_chuck_closed),
    };
    (carrier, shared)
}

/// Hand `out` the samples of a multi-path program's paths (`paths`, path 1 first) running
/// together: every `dt` seconds of machine time and at every move's end and dogleg bend of any
/// path, each sample giving every path's carrier (path `p`'s keys with `p` after them), up to
/// `stop` (a deadlock) or the last path's end. At an instant, each path is in the move under way
/// just before it (a sample's motion and line are the interval's that ends at it), standing at
/// its last move's end past it (a wait, its program ended), at its first move's start before it.
/// The machine's state (spindle, C-axis mode, tailstock, sub-spindle chuck) is path 1's, the
/// tailstock and the sub-spindle's chuck as any path last commanded them.
pub fn samples_of_paths(paths: &[TimedPath], dt: f64, stop: Option<f64>, mut out: impl FnMut(&Sample)) {
    let dt = if dt.is_finite() && dt > 0.0 { dt } else { 0.001 };
    let end = paths
        .iter()
        .flat_map(|p| p.items.iter().map(motion::Timed::t1))
        .fold(0.0, f64::max)
        .min(stop.unwrap_or(f64::INFINITY));
    let mut instants: Vec<f64> = Vec::new();
    for p in paths {
        for it in &p.items {
            if matches!(p.run.moves[it.index].kind, MoveKind::Operation { .. }) {
                continue;
            }
            instants.push(it.t1());
            instants.extend(bend_of(it));
        }
    }
    let grid = (end / dt).ceil().min(MAX_SAMPLES_PER_MOVE as f64) as u64;
    let step = dt.max(end / MAX_SAMPLES_PER_MOVE as f64);
    instants.extend((0..=grid).map(|k| k as f64 * step));
    instants.retain(|t| t.is_finite() && *t <= end);
    instants.sort_by(f64::total_cmp);
    let has: Vec<[bool; 6]> = paths.iter().map(|p| super::machine_axes(&p.machine)).collect();
    let mut last_t = f64::NEG_INFINITY;
    for t in instants {
        if t <= last_t + MIN_GAP_S && last_t != f64::NEG_INFINITY {
            continue;
        }
        let mut sample: Option<Sample> = None;
        for (p, h) in paths.iter().zip(&has) {
            // The move under way just before `t` (its interval (t0, t1] holds `t`), or the last
            // one that ended; at the first instant, the first move.
            let moving = p
                .items
                .iter()
                .filter(|it| !matches!(p.run.moves[it.index].kind, MoveKind::Operation { .. }));
            let Some(item) = moving
                .clone()
                .take_while(|it| it.t0 < t)
                .last()
                .or_else(|| moving.clone().next())
            else {
                continue;
            };
            let m = &p.run.moves[item.index];
            let e = p.run.extra_of(item.index);
            let ended = t >= item.t1();
            let (carrier, shared) = state_at(&p.run, m, e, item, t.min(item.t1()), ended, &p.machine, h);
            let s = sample.get_or_insert(Sample {
                t: Some(t),
                ..shared.clone()
            });
            s.tailstock = Some(s.tailstock.unwrap_or(false) || shared.tailstock.unwrap_or(false));
            s.sub_chuck = Some(s.sub_chuck.unwrap_or(false) || shared.sub_chuck.unwrap_or(false));
            *s.carrier_mut(p.path as usize) = carrier;
        }
        if let Some(s) = sample {
            out(&s);
            last_t = t;
        }
    }
}

/// A sample as one JSON line (without its newline): every field it has, numbers as Rust writes
/// them (shortest round trip, so a replay reads back the very values).
pub fn to_json(s: &Sample) -> String {
    use std::fmt::Write;
    let mut o = String::from("{");
    let mut put = |k: &str, suffix: &str, v: String| {
        let sep = if o.len() > 1 { "," } else { "" };
        let _ = write!(o, "{sep}\"{k}{suffix}\":{v}");
    };
    let word = |w: &str| format!("\"{w}\"");
    if let Some(t) = s.t {
        put("t", "", num(t));
    }
    // Path 1's keys as they are, in the order of the one-path samples; path p's after them, with
    // p after each key.
    let none = Carrier::default();
    let first = s.carriers.first().unwrap_or(&none);
    let axes = |put: &mut dyn FnMut(&str, &str, String), c: &Carrier, suffix: &str| {
        for (k, v) in c.axes.iter().enumerate() {
            if let Some(v) = v {
                put(&super::AXES[k].to_string(), suffix, num(*v));
            }
        }
        if let Some(v) = c.tool {
            put("tool", suffix, v.to_string());
        }
    };
    let motion = |put: &mut dyn FnMut(&str, &str, String), c: &Carrier, suffix: &str| {
        if let Some(v) = c.motion {
            put(
                "motion",
                suffix,
                word(if v == Motion::Rapid { "rapid" } else { "feed" }),
            );
        }
        if let Some(v) = c.line {
            put("line", suffix, v.to_string());
        }
    };
    axes(&mut put, first, "");
    if let Some(v) = s.spindle {
        let w = match v {
            SpindleDir::Off => "off",
            SpindleDir::Cw => "cw",
            SpindleDir::Ccw => "ccw",
        };
        put("spindle", "", word(w));
    }
    motion(&mut put, first, "");
    if let Some(v) = s.c_axis {
        put("c_axis", "", v.to_string());
    }
    if let Some(v) = first.live_rpm {
        put("live_rpm", "", num(v));
    }
    if let Some(v) = s.tailstock {
        put("tailstock", "", v.to_string());
    }
    if let Some(v) = s.sub_chuck {
        put("sub_chuck", "", v.to_string());
    }
    for (i, c) in s.carriers.iter().enumerate().skip(1) {
        let suffix = (i + 1).to_string();
        axes(&mut put, c, &suffix);
        motion(&mut put, c, &suffix);
        if let Some(v) = c.live_rpm {
            put("live_rpm", &suffix, num(v));
        }
    }
    o.push('}');
    o
}

/// A finite number as JSON: shortest round trip, `-0` as `0`.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}
