//! What a station does, read from its moves below the bar's face: the kind of tool it takes, the
//! line and words of the evidence, and the sizes the tool is chosen by.

use super::super::reading::{LineSet, Reading, Seg, SegKind};
use super::super::segs::Step;
use super::ToolKind;
use crate::assume::words::{code_of, g_codes};
use crate::machine::num;

/// How far below the face a point must be to count as inside the bar, mm.
pub const INSIDE: f64 = 0.05;
/// A radial pass to the axis within this of the face faces it; deeper, it parts off, mm.
pub const FACE_BAND: f64 = 5.0;
/// The smallest lead a thread is cut at, mm per revolution (above any turning feed).
pub const THREAD_LEAD: f64 = 0.5;

/// The first evidence of one kind: its line and its words.
#[derive(Clone, Debug, PartialEq)]
pub struct Seen {
    pub line: u32,
    pub words: String,
}

/// What one station's moves show.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Work {
    /// Index in `Reading::segs` of its first feed move below the face.
    pub first: Option<usize>,
    pub drill: Option<Seen>,
    pub tap: Option<Seen>,
    pub thread: Option<Seen>,
    /// Its thread passes' pull-offs toward the axis and away from it: more toward the axis is
    /// an internal thread.
    pub pulls_in: usize,
    pub pulls_out: usize,
    /// The lead of its thread or tap passes, mm per revolution.
    pub lead: Option<f64>,
    pub bore: Option<Seen>,
    pub bores: usize,
    pub od: Option<Seen>,
    pub ods: usize,
    pub part: Option<Seen>,
    pub groove: Option<Seen>,
    /// Plunges away from the axis behind the face, each straight after a rapid: an internal
    /// groove cut from inside a bore.
    pub groove_in: Option<Seen>,
    pub plunges_out: usize,
    pub face: Option<Seen>,
    pub profile: Option<Seen>,
    /// The smallest radius of its passes along −Z and its thread passes, mm (the smallest bore
    /// it works in).
    pub pass_r: Option<f64>,
    /// The lowest Z of its feed moves below the face (program Z, mm).
    pub deepest: Option<f64>,
    /// The lowest Z of its feed moves on the spindle axis.
    pub axis_deepest: Option<f64>,
    /// Plunges (radial feeds inward below the face band): their Z, start and end radius.
    pub plunges: Vec<[f64; 3]>,
    /// Length of its feed moves along Z below the face (not on the axis), mm.
    pub along_z: f64,
    /// It feeds down a slope steeper than 5° toward the axis while moving toward the chuck (a
    /// profile that needs a tool with back clearance).
    pub descends: bool,
}

fn x_of(s: &Seg, r: f64) -> String {
    format!("X{}", num(s.x_word(r)))
}

fn z_of(s: &Seg, z: f64) -> String {
    format!("Z{}", num(s.z_word(z)))
}

fn first(to: &mut Option<Seen>, line: u32, words: impl FnOnce() -> String) {
    if to.is_none() {
        *to = Some(Seen { line, words: words() });
    }
}

/// The largest lead read as a thread's, mm a revolution: more is a feed misread (a feed per
/// minute under G95), not a thread.
const MAX_LEAD: f64 = 12.0;

/// Turning or boring passes beside threading that make a station's moves say nothing.
const MIXED_PASSES: usize = 3;

/// The largest pull-off of a boring pass toward the axis, mm.
const PULL_OFF: f64 = 2.0;

/// The next piece the same station moves after `st`'s, straight after it.
fn next_of(st: &Step) -> Option<Seg> {
    st.next.filter(|n| n.station == st.seg.station)
}

/// Each line's cutting mode as the program text sets it (index 0 = line 1): it threads (G32,
/// G33, Fanuc's G92 and the modal motion after them; G76 and G78 on their own line) or taps
/// (G33.1, G84 and its kin, until G80 or another motion code). A feed alone never makes a
/// thread: a turning or drilling feed per revolution can be as large as a fine thread's lead
/// (0.02 in a revolution is 0.508 mm), and a control cuts a thread only in a threading code.
pub fn thread_modes(r: &Reading, fanuc: bool) -> ThreadModes {
    let (mut threading, mut tapping) = (false, false);
    let mut out = ThreadModes {
        threading: LineSet::with_lines(r.lines.len()),
        tapping: LineSet::with_lines(r.lines.len()),
    };
    for (i, l) in r.lines.iter().enumerate() {
        let mut once = false;
        for c in g_codes(&code_of(&l)) {
            match c {
                320 | 330 => (threading, tapping) = (true, false),
                920 if fanuc => (threading, tapping) = (true, false),
                760 | 780 => once = true,
                331 | 840 | 842 | 843 | 880 => (threading, tapping) = (false, true),
                0 | 10 | 20 | 30 | 700 | 710 | 720 | 730 | 740 | 750 | 800 | 810 | 820 | 830 | 850 | 860 | 870
                | 890 => (threading, tapping) = (false, false),
                900 | 940 if fanuc => (threading, tapping) = (false, false),
                _ => {}
            }
        }
        let line = i as u32 + 1;
        if threading || once {
            out.threading.insert(line);
        }
        if tapping {
            out.tapping.insert(line);
        }
    }
    out
}

/// Which lines thread and which tap ([`thread_modes`]), a bit a line each.
#[derive(Clone, Debug, Default)]
pub struct ThreadModes {
    threading: LineSet,
    tapping: LineSet,
}

impl ThreadModes {
    /// Whether 1-based `line` threads, and whether it taps (neither past the program's lines).
    pub fn at(&self, line: u32) -> (bool, bool) {
        (self.threading.contains(line), self.tapping.contains(line))
    }
}

/// Whether piece `s` is a thread pass: along Z in a threading code.
fn thread_pass(s: &Seg, modes: &ThreadModes) -> bool {
    let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
    let threading = modes.at(s.line).0;
    threading && dz.abs() > dr.abs() && dz.abs() > 1e-3
}

/// Read each piece of each of `stations`' moves (in increasing order) below `face` (program Z,
/// mm), in one walk of the segments; `modes` is the program's [`thread_modes`].
pub fn works(r: &Reading, stations: &[u32], face: f64, modes: &ThreadModes) -> Vec<(u32, Work)> {
    debug_assert!(stations.windows(2).all(|w| w[0] < w[1]), "{stations:?}");
    let mut out: Vec<(u32, Work)> = stations.iter().map(|&s| (s, Work::default())).collect();
    for st in r.segs.walk() {
        if let Ok(k) = stations.binary_search(&st.seg.station) {
            take(&mut out[k].1, &st, face, modes);
        }
    }
    out
}

/// Read piece `st` of its station's moves into `w`.
fn take(w: &mut Work, st: &Step, face: f64, modes: &ThreadModes) {
    let station = st.seg.station;
    let below = face - INSIDE;
    let (i, s) = (st.index, &st.seg);
    if s.kind != SegKind::Feed || s.a[1].min(s.b[1]) >= below {
        return;
    }
    w.first.get_or_insert(i);
    let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
    let zlo = s.a[1].min(s.b[1]);
    w.deepest = Some(w.deepest.map_or(zlo, |d: f64| d.min(zlo)));
    let (thread_code, tap_code) = modes.at(s.line);
    let lead = s
        .per_rev
        .filter(|f| (THREAD_LEAD..=MAX_LEAD).contains(f) && (thread_code || tap_code));
    let on_axis = s.a[0] < 0.05 && s.b[0] < 0.05;
    let next = next_of(st);
    if on_axis && dz.abs() > 1e-6 {
        // The evidence is the deepest feed on the axis: where the hole ends.
        let tap = tap_code || thread_code;
        let to = if tap { &mut w.tap } else { &mut w.drill };
        if to.is_none() || w.axis_deepest.map_or(true, |d| zlo < d) {
            w.axis_deepest = Some(zlo);
            let how = if tap { " as a tap does" } else { "" };
            *to = Some(Seen {
                line: s.line,
                words: format!(
                    "it feeds along the spindle axis to {}{how} (line {})",
                    z_of(s, zlo),
                    s.line
                ),
            });
        }
        w.lead = w.lead.or(lead.filter(|_| tap));
        return;
    }
    if dz.abs() > dr.abs() {
        w.along_z += dz.abs();
    }
    if thread_pass(s, modes) {
        w.lead = w.lead.or(lead);
        let rr = s.a[0].min(s.b[0]);
        w.pass_r = Some(w.pass_r.map_or(rr, |p: f64| p.min(rr)));
        // The pull-off: the next piece, unless it threads on (a thread along a taper or
        // round a corner goes on cutting).
        if let Some(n) = next.filter(|n| !thread_pass(n, modes)) {
            if n.b[0] < n.a[0] - 0.05 {
                w.pulls_in += 1;
            } else if n.b[0] > n.a[0] + 0.05 {
                w.pulls_out += 1;
            }
        }
        first(&mut w.thread, s.line, || {
            let how = lead.map_or(String::new(), |l| format!(" at {} mm a revolution", num(l)));
            format!(
                "it threads: a pass along Z{how} at {} (line {})",
                x_of(s, s.a[0].min(s.b[0])),
                s.line
            )
        });
        return;
    }
    if dz < -0.5 && dz.abs() >= 2.0 * dr.abs() {
        let rr = s.a[0].min(s.b[0]);
        w.pass_r = Some(w.pass_r.map_or(rr, |p: f64| p.min(rr)));
        let pull = next.map(|n| (n.b[0] - n.a[0], (n.b[1] - n.a[1]).abs()));
        // A boring bar pulls off a little toward the axis and leaves the bore along +Z
        // inside the pass (an OD tool may move toward the axis after a pass too, down a
        // shoulder, but then it goes on cutting).
        let leaves = || {
            next.is_some_and(|n| {
                st.rest()
                    .skip(1)
                    .find(|o| o.station == station)
                    .is_some_and(|o| o.b[1] > o.a[1] + 1e-3 && o.b[0] <= n.b[0] + 1e-6 && o.a[0] <= n.b[0] + 1e-6)
            })
        };
        match pull {
            Some((pr, pz)) if (-PULL_OFF..-0.05).contains(&pr) && pz <= 2.0 * pr.abs() + 1e-9 && leaves() => {
                w.bores += 1;
                first(&mut w.bore, s.line, || {
                    format!(
                        "it bores: passes along -Z at {} (line {}) pulled off toward the axis",
                        x_of(s, rr),
                        s.line
                    )
                });
            }
            Some((pr, pz)) if pr > 0.05 && pz <= pr + 1e-9 => {
                w.ods += 1;
                first(&mut w.od, s.line, || {
                    format!(
                        "it turns: passes along -Z at {} (line {}) pulled off outward",
                        x_of(s, rr),
                        s.line
                    )
                });
            }
            _ => first(&mut w.profile, s.line, || {
                format!("it cuts a profile (line {})", s.line)
            }),
        }
        return;
    }
    let after_rapid = st
        .prev
        .is_some_and(|p| p.station == station && p.kind == SegKind::Rapid);
    if dr > 1e-3 && dr > 2.0 * dz.abs() && after_rapid && s.a[1] < face - FACE_BAND {
        w.plunges_out += 1;
        w.plunges.push([s.a[1], s.b[0], s.a[0]]);
        first(&mut w.groove_in, s.line, || {
            format!(
                "it plunges away from the axis from {} at {} (line {})",
                x_of(s, s.a[0]),
                z_of(s, s.a[1]),
                s.line
            )
        });
        return;
    }
    if dr < -1e-3 && dr.abs() > 2.0 * dz.abs() {
        let z = s.b[1];
        let at_face = z >= face - FACE_BAND - 1e-9;
        if s.b[0] <= 0.5 {
            if at_face {
                first(&mut w.face, s.line, || {
                    format!("it faces to the axis at {} (line {})", z_of(s, z), s.line)
                });
            } else {
                w.plunges.push([z, s.a[0], s.b[0]]);
                first(&mut w.part, s.line, || {
                    format!(
                        "it plunges to the axis at {}, behind the face (line {})",
                        z_of(s, z),
                        s.line
                    )
                });
            }
        } else if at_face {
            first(&mut w.face, s.line, || {
                format!("it faces at {} (line {})", z_of(s, z), s.line)
            });
        } else if next.is_some_and(|n| n.b[0] > n.a[0] + 0.05 && (n.b[1] - n.a[1]).abs() <= 1e-3) {
            w.plunges.push([z, s.a[0], s.b[0]]);
            first(&mut w.groove, s.line, || {
                format!(
                    "it plunges to {} at {} (line {}) and pulls straight out",
                    x_of(s, s.b[0]),
                    z_of(s, z),
                    s.line
                )
            });
        } else {
            first(&mut w.profile, s.line, || {
                format!("it cuts a profile (line {})", s.line)
            });
        }
        return;
    }
    if dz < 0.0 && dr < 0.0 && dr.abs() > 0.09 * dz.abs() {
        w.descends = true;
    }
    if s.a[0].max(s.b[0]) > 0.05 {
        first(&mut w.profile, s.line, || {
            format!("it cuts a profile (line {})", s.line)
        });
    }
}

/// The kind of tool `w`'s moves ask for, whether it works inside, and the words of the evidence
/// with its line. `None`: it cuts nothing below the face.
pub fn kind(w: &Work) -> Option<(ToolKind, bool, &Seen)> {
    let plunged: f64 = w.plunges.iter().map(|p| p[1] - p[2]).sum();
    let narrow = w.groove.is_some() && w.along_z <= plunged;
    // A station that threads and also makes several turning or boring passes holds more than
    // one tool over the program (a T number used twice): its moves decide nothing.
    if w.thread.is_some() && w.ods + w.bores >= MIXED_PASSES {
        return None;
    }
    if let Some(s) = &w.tap {
        Some((ToolKind::Tapping, true, s))
    } else if let Some(s) = &w.drill {
        Some((ToolKind::Drilling, true, s))
    } else if let Some(s) = &w.thread {
        Some((ToolKind::Threading, w.pulls_in > w.pulls_out, s))
    } else if let Some(s) = w.bore.as_ref().filter(|_| w.bores > w.ods) {
        Some((ToolKind::Boring, true, s))
    } else if let Some(s) = w.groove_in.as_ref().filter(|_| w.plunges_out >= w.ods) {
        Some((ToolKind::Grooving, true, s))
    } else if let Some(s) = &w.part {
        Some((ToolKind::Parting, false, s))
    } else if let Some(s) = w.groove.as_ref().filter(|_| narrow) {
        Some((ToolKind::Grooving, false, s))
    } else if let Some(s) = w.od.as_ref().or(w.profile.as_ref()).or(w.groove.as_ref()) {
        Some((ToolKind::OdTurning, false, s))
    } else {
        w.face.as_ref().map(|s| (ToolKind::Facing, false, s))
    }
}
