//! The samples a control's interpolator would report running a program
//! (`latheguard moves --format samples`, docs/follow.md "Replay"): the interpreter's moves timed
//! as `check` times them (`motion`), the machine's state every `dt` seconds of machine time and
//! at the end of every move (and at a dogleg rapid's bend), so that a straight line between two
//! samples follows the move it samples: every corner of the programmed path is a sample, an arc
//! is chorded at `dt`. Followed ([`super::Follower`]), these samples give the program's
//! findings: the replay tests hold them to `check`'s.

use super::sample::{Motion, Sample, SpindleDir};
use crate::interp::{self, Interpretation, MoveKind};
use crate::machine::Machine;
use crate::motion::{self, Path};

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
    let mz = machine.machine_zero;
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
        let state = run.states[m.state as usize];
        let sample_at = |t: f64, end: bool| -> Sample {
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
                    let r = motion::reference_at(m, &item, u * item.duration);
                    let mut ex = [0.0; 4];
                    match e {
                        Some(e) => {
                            for (k, v) in ex.iter_mut().enumerate() {
                                *v = e.start[k] + (e.end[k] - e.start[k]) * u;
                            }
                        }
                        None => {
                            // No entry: every extra axis at 0 (as the interpreter keeps them).
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
            // A turret index shows its new tool when it has ended (as a control's tool number
            // pin changes when the change is done).
            let tool = match m.kind {
                MoveKind::ToolChange { from, .. } if !end => from,
                _ => m.station,
            };
            Sample {
                t: Some(t),
                axes,
                tool: Some(tool),
                spindle: Some(match state.spindle.dir {
                    interp::SpindleDir::Off => SpindleDir::Off,
                    interp::SpindleDir::Cw => SpindleDir::Cw,
                    interp::SpindleDir::Ccw => SpindleDir::Ccw,
                }),
                motion: Some(if m.kind == MoveKind::Rapid {
                    Motion::Rapid
                } else {
                    Motion::Feed
                }),
                line: Some(m.line),
                c_axis: Some(e.is_some_and(|e| e.c_mode)),
                live_rpm: Some(e.map_or(0.0, |e| e.live_rpm)),
                tailstock: Some(state.tailstock_advanced),
                sub_chuck: Some(state.sub_chuck_closed),
            }
        };
        if last_t == f64::NEG_INFINITY {
            out(&sample_at(item.t0, false));
            last_t = item.t0;
        }
        let t1 = item.t1();
        let mut bend = match item.path {
            Path::Dogleg { tx, tz, .. } => Some(item.t0 + tx.min(tz)).filter(|&b| b > item.t0 && b < t1),
            _ => None,
        };
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

/// A sample as one JSON line (without its newline): every field it has, numbers as Rust writes
/// them (shortest round trip, so a replay reads back the very values).
pub fn to_json(s: &Sample) -> String {
    use std::fmt::Write;
    let mut o = String::from("{");
    let mut sep = "";
    let mut put = |o: &mut String, k: &str, v: String| {
        let _ = write!(o, "{sep}\"{k}\":{v}");
        sep = ",";
    };
    if let Some(t) = s.t {
        put(&mut o, "t", num(t));
    }
    for (k, v) in s.axes.iter().enumerate() {
        if let Some(v) = v {
            put(&mut o, &super::AXES[k].to_string(), num(*v));
        }
    }
    if let Some(v) = s.tool {
        put(&mut o, "tool", v.to_string());
    }
    if let Some(v) = s.spindle {
        let w = match v {
            SpindleDir::Off => "off",
            SpindleDir::Cw => "cw",
            SpindleDir::Ccw => "ccw",
        };
        put(&mut o, "spindle", format!("\"{w}\""));
    }
    if let Some(v) = s.motion {
        let w = if v == Motion::Rapid { "rapid" } else { "feed" };
        put(&mut o, "motion", format!("\"{w}\""));
    }
    if let Some(v) = s.line {
        put(&mut o, "line", v.to_string());
    }
    if let Some(v) = s.c_axis {
        put(&mut o, "c_axis", v.to_string());
    }
    if let Some(v) = s.live_rpm {
        put(&mut o, "live_rpm", num(v));
    }
    if let Some(v) = s.tailstock {
        put(&mut o, "tailstock", v.to_string());
    }
    if let Some(v) = s.sub_chuck {
        put(&mut o, "sub_chuck", v.to_string());
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
