//! The bar and program zero, read from what the program cuts and how it approaches
//! (docs/assume.md, "The bar").
//!
//! The evidence, in program coordinates (`r` radius, `z` from program zero, mm):
//! - **the face**: the highest Z at which a feed move faces to the centre (a radial move at
//!   constant Z, inward, ending within 0.5 mm of the axis); the raw front face is at or ahead of
//!   it. Without one, program Z0 stands for the face.
//! - **what is cut** (a lower bound on the bar's radius): below the face, the radius of every
//!   feed move along −Z (a turning pass), the end of every inward feed move (a plunge may start
//!   in the air, it ends in the material) and the start of every outward one (a pull-off or a
//!   shoulder may end in the air). A bar thinner than that would let the program cut air where
//!   it cuts, and would hide a rapid into the bar at the approach: the bar is never assumed
//!   smaller.
//! - **how it approaches** (an upper bound): the start of each facing pass (it starts outside
//!   the bar), and every rapid below the face before the first feed move (the bar is whole
//!   then). A bound below what is cut is the program's own crash, and is not used.
//! - **a stock comment**: `(STOCK DIA 50)`, `(BAR Ø2.0)`, `(MATERIAL … D=50 …)`, or a move whose
//!   comment says it goes to the stock diameter (`G0 X1.25 (START AT STOCK OD)`): the diameter
//!   as written wins over the moves.
//! - **the deepest cut**: the lowest Z of any feed move; the bar sticks out far enough for it
//!   and [`PART_OFF_ROOM`] more, clear of the jaws.
//! - **a tube**: when the first tool that cuts bores (its first pass below the face pulls off
//!   toward the axis), the bar is a tube whose bore is [`BORE_MATERIAL`] under that pass.
//!
//! The machine's own bar stays when it agrees with the evidence (its diameter between the two
//! bounds, its face at or ahead of the facing pass, its stick-out long enough); only the values
//! it contradicts are replaced.

use super::reading::{Reading, Seg, SegKind};
use super::segs::Step;
use super::words::split_comment;
use super::{set, Assumed, Assumption};
use crate::job::{JobStock, Place};
use crate::machine::{num, ChuckForm, Machine};

/// Room past the deepest cut before the jaws, mm: a parting blade, and the turret behind it
/// when it parts off at the axis (a drum's face stands some 30 mm behind the tool's tip).
pub const PART_OFF_ROOM: f64 = 40.0;

/// The machine file's stick-out stays when it leaves at least this much room past the deepest
/// cut, mm (a parting blade's).
pub const KEEP_ROOM: f64 = 10.0;

/// A rapid this close outside the bar's radius still meets a raw face standing in front of it
/// (the tool's nose and insert), mm.
const SLAB_REACH: f64 = 2.0;

/// The largest pull-off of a boring pass toward the axis, mm.
const PULL_OFF: f64 = 2.0;

/// Material left under a tube's first boring pass, mm on the diameter.
pub const BORE_MATERIAL: f64 = 2.0;

/// A facing pass more than this far behind program Z0 faces a shoulder or parts off, mm.
const FACE_BEHIND: f64 = 0.5;

/// A radius this small is the spindle axis, mm.
const AT_AXIS: f64 = 0.5;

/// Clearance a program keeps outside the bar where it approaches, mm on the diameter.
const APPROACH_CLEARANCE: f64 = 2.0;

/// How far below the face a point must be to count as inside the bar, mm.
const INSIDE: f64 = 0.05;

/// Standard bar diameters, mm.
const METRIC: [f64; 52] = [
    3., 4., 5., 6., 8., 10., 12., 14., 16., 18., 20., 22., 25., 28., 30., 32., 35., 36., 38., 40., 42., 45., 48., 50.,
    52., 55., 56., 60., 63., 65., 70., 75., 80., 85., 90., 95., 100., 110., 120., 125., 130., 140., 150., 160., 170.,
    180., 190., 200., 220., 250., 280., 300.,
];

/// Standard bar diameters for an inch program, inches: sixteenths to 1 in, eighths to 3 in,
/// quarters to 6 in, halves to 12 in.
fn inch_sizes() -> Vec<f64> {
    let mut v: Vec<f64> = (2..=16).map(|k| k as f64 / 16.0).collect();
    v.extend((9..=24).map(|k| k as f64 / 8.0));
    v.extend((13..=24).map(|k| k as f64 / 4.0));
    v.extend((13..=24).map(|k| k as f64 / 2.0));
    v
}

/// A value and the program line it rests on.
#[derive(Clone, Copy, Debug, PartialEq)]
struct At {
    v: f64,
    line: u32,
}

/// What the moves say of the bar.
#[derive(Clone, Debug, Default)]
struct Evidence {
    /// The highest full facing pass: its Z and its start radius.
    face: Option<(At, f64)>,
    /// The largest radius a turning pass cuts at below the face: the bar is wider.
    cut: Option<At>,
    /// The largest radius a radial move reaches inside the bar: the bar is at least as wide.
    reach: Option<At>,
    /// The smallest radius the program approaches from outside the bar.
    approach: Option<At>,
    /// The lowest Z of a feed move.
    deepest: Option<At>,
    /// The first pass below the face bores: its radius.
    tube: Option<At>,
    /// The smallest radius a facing pass outward starts from (inside a tube's bore).
    face_out: Option<At>,
    /// The smallest radius a feed along Z from the face leads into a facing pass from (the
    /// pass starts outside the bar).
    faced_from: Option<At>,
    /// A stock comment's diameter, mm.
    comment: Option<At>,
    /// The program's units: mm per unit.
    scale: f64,
    diameter_words: bool,
}

fn max_at(to: &mut Option<At>, v: f64, line: u32) {
    if to.map_or(true, |a| v > a.v) {
        *to = Some(At { v, line });
    }
}

fn min_at(to: &mut Option<At>, v: f64, line: u32) {
    if to.map_or(true, |a| v < a.v) {
        *to = Some(At { v, line });
    }
}

/// A facing pass: a feed move at constant Z across at least 2 mm of radius, inward or outward
/// (a tube's face is faced from the bore).
fn is_facing(s: &Seg) -> bool {
    s.kind == SegKind::Feed && (s.b[1] - s.a[1]).abs() < 1e-3 && (s.a[0] - s.b[0]).abs() >= 2.0
}

/// Whether piece `st` is the plunge before a facing pass: an axial feed move whose station's
/// next move faces inward from where it ends (the plunge is made outside the bar).
fn plunge_before_facing(st: &Step) -> bool {
    let s = &st.seg;
    st.find_after(|n| n.station == s.station).is_some_and(|n| {
        is_facing(&n) && n.b[0] < n.a[0] && (n.a[0] - s.b[0]).abs() < 1e-6 && (n.a[1] - s.b[1]).abs() < 1e-6
    })
}

/// Whether piece `st` comes straight after a rapid of its station.
fn after_rapid(st: &Step) -> bool {
    st.prev
        .is_some_and(|p| p.station == st.seg.station && p.kind == SegKind::Rapid)
}

/// Longest entry on a slant, mm: a lead-in may start and end in the air.
const ENTRY: f64 = 1.0;

/// Whether piece `st` is an entry: a short feed toward the axis and the chuck at once, straight
/// after a rapid of its station and followed by more cutting (a lead-in, which may start and end
/// in the air before the pass proper cuts).
fn is_entry(st: &Step) -> bool {
    let s = &st.seg;
    let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
    let leads_on = st
        .next
        .is_some_and(|n| n.station == s.station && n.kind == SegKind::Feed);
    after_rapid(st) && leads_on && dr < -1e-6 && dz < -1e-6 && dr.hypot(dz) <= ENTRY
}

impl Evidence {
    fn of(r: &Reading, machine: &Machine) -> Evidence {
        let mut e = Evidence {
            scale: 1.0,
            diameter_words: true,
            ..Evidence::default()
        };
        if let Some(s) = r.segs.first() {
            e.scale = s.scale;
            e.diameter_words = s.diameter;
        }
        // The face: the highest facing pass (not a part-off far behind it).
        for s in r.segs.iter().filter(is_facing) {
            if e.face.map_or(true, |(f, _)| s.a[1] > f.v) {
                e.face = Some((
                    At {
                        v: s.a[1],
                        line: s.line,
                    },
                    s.a[0].max(s.b[0]),
                ));
            }
        }
        for s in r.segs.iter().filter(|s| is_facing(s) && s.b[0] > s.a[0]) {
            min_at(&mut e.face_out, s.a[0], s.line);
        }
        // A facing pass well behind program Z0 faces a shoulder or parts off: Z0 is the face.
        if e.face.is_some_and(|(f, _)| f.v < -FACE_BEHIND) {
            e.face = None;
        }
        let face = e.face.map_or(0.0, |(f, _)| f.v);
        let below = face - INSIDE;
        // A boring bar's or a drill's passes are inside the part: not the bar's outside.
        let inside = super::tools::inside_stations(r, machine, face);
        let mut first_feed = None;
        let mut cycle_starts: Vec<At> = Vec::new();
        // What earlier turning passes left: along each, nothing outside its radius (top z,
        // bottom z, radius).
        let mut turned = Turned::default();
        // The rapids before the first cut: in the air.
        let mut approach: Option<At> = None;
        for st in r.segs.walk() {
            let (i, s) = (st.index, &st.seg);
            if first_feed.is_none() && s.kind == SegKind::Rapid {
                for p in [s.a, s.b] {
                    if p[1] < below && p[0] > 0.5 {
                        min_at(&mut approach, p[0], s.line);
                    }
                }
            }
            // A roughing cycle's first move starts from its start point, outside the bar.
            if s.cycle && st.prev.map_or(true, |p| !p.cycle || p.line != s.line) {
                cycle_starts.push(At {
                    v: s.a[0],
                    line: s.line,
                });
            }
            if s.kind != SegKind::Feed {
                continue;
            }
            min_at(&mut e.deepest, s.a[1].min(s.b[1]), s.line);
            if inside.contains(&s.station) {
                if first_feed.is_none() && s.b[1] < below {
                    first_feed = Some(i);
                }
                // An internal groove's floor lies inside the bar: a plunge away from the axis,
                // straight after a rapid, reaches no further than the bar's wall.
                let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
                if after_rapid(&st) && dr > 1e-3 && dr > 2.0 * dz.abs() && s.a[1] < below {
                    max_at(&mut e.reach, s.b[0], s.line);
                }
                continue;
            }
            let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
            // A roughing cycle's passes start from its start point, often in the air: only its
            // profile counts, as what the part reaches (it lies inside the bar), never as a pass.
            let in_cycle = s.cycle;
            if in_cycle && !s.profile {
                continue;
            }
            if dz < 0.0 && plunge_before_facing(&st) {
                // Made from the face, it leads the tool to where the facing pass starts,
                // outside the bar.
                if s.a[1] >= face - INSIDE {
                    min_at(&mut e.faced_from, s.b[0], s.line);
                }
                continue;
            }
            if is_entry(&st) {
                continue;
            }
            // The radius this piece certainly cuts at, below the face: a pass along −Z removes
            // material there (the bar is wider); a radial move reaches it (at least as wide).
            let (cut, reach) = if dz < -INSIDE && dz.abs() >= dr.abs() {
                // Along −Z: the part below the face, at its larger radius.
                // Its smaller radius there: an entry on a slant may start in the air.
                let c = (s.b[1] < below).then(|| {
                    let t = ((below - s.a[1]) / dz).clamp(0.0, 1.0);
                    let r_in = s.a[0] + t * dr;
                    r_in.min(s.b[0])
                });
                (c, None)
            } else if dr < 0.0 {
                (None, (s.b[1] < below).then_some(s.b[0]))
            } else {
                (None, (s.a[1] < below).then_some(s.a[0]))
            };
            let (cut, reach) = if in_cycle { (None, cut.or(reach)) } else { (cut, reach) };
            // Outside what an earlier pass turned to, over its length, there is only air.
            let (zlo, zhi) = (s.a[1].min(s.b[1]), s.a[1].max(s.b[1]));
            let in_air = |c: f64, zlo: f64, zhi: f64| turned.air(c, zlo, zhi);
            let cut = cut.filter(|c| !in_air(*c, zlo, zhi));
            let reach = reach.filter(|c| {
                let z = if dr < 0.0 { s.b[1] } else { s.a[1] };
                !in_air(*c, z, z)
            });
            if !in_cycle && dz < -INSIDE && dz.abs() >= dr.abs() && s.b[1] < below {
                turned.push([s.a[1].min(below), s.b[1], s.a[0].min(s.b[0])]);
            }
            if (cut.is_some() || reach.is_some()) && first_feed.is_none() {
                first_feed = Some(i);
            }
            // At the axis a move says nothing of the bar's size (a facing pass ends there).
            if let Some(c) = cut.filter(|c| *c > AT_AXIS) {
                max_at(&mut e.cut, c, s.line);
            }
            if let Some(c) = reach.filter(|c| *c > AT_AXIS) {
                max_at(&mut e.reach, c, s.line);
            }
        }
        // Approach: facing passes start outside the bar; rapids before the first cut are in air.
        if let Some((f, r0)) = e.face {
            min_at(&mut e.approach, r0, f.line);
        }
        if let Some(f) = e.faced_from {
            min_at(&mut e.approach, f.v, f.line);
        }
        for c in cycle_starts {
            min_at(&mut e.approach, c.v, c.line);
        }
        if let Some(a) = approach {
            min_at(&mut e.approach, a.v, a.line);
        }
        if let Some(i) = first_feed {
            e.tube = bores_first(r, i, face);
        }
        e.comment = stock_comment(r);
        e
    }
}

/// What earlier turning passes left, each as (top z, bottom z, radius): along a pass, nothing
/// outside its radius. Only passes no other one covers are kept (one that spans at least the
/// same z at no larger radius answers every question the other would), so a program that turns
/// the same shoulders over and over keeps a handful; past [`Turned::MOST`] of them the oldest
/// goes, so the reading stays linear in the program's length.
#[derive(Default)]
struct Turned {
    passes: std::collections::VecDeque<[f64; 3]>,
}

impl Turned {
    /// Passes kept at most.
    const MOST: usize = 256;

    /// Whether `a` covers `b`: every point `b` says is air, `a` says is air too.
    fn covers(a: &[f64; 3], b: &[f64; 3]) -> bool {
        a[0] >= b[0] && a[1] <= b[1] && a[2] <= b[2]
    }

    fn push(&mut self, t: [f64; 3]) {
        if self.passes.iter().any(|p| Self::covers(p, &t)) {
            return;
        }
        self.passes.retain(|p| !Self::covers(&t, p));
        if self.passes.len() == Self::MOST {
            self.passes.pop_front();
        }
        self.passes.push_back(t);
    }

    /// Whether radius `c` from `zlo` to `zhi` lies outside what some earlier pass turned, over
    /// its length.
    fn air(&self, c: f64, zlo: f64, zhi: f64) -> bool {
        self.passes
            .iter()
            .any(|t| c > t[2] + 1e-6 && zhi <= t[0] + 1e-9 && zlo >= t[1] - 1e-9)
    }
}

/// When the first cutting piece `i` is a boring pass, its radius (the bar is a tube): a pass
/// along −Z, then a pull-off of at most [`PULL_OFF`] toward the axis, then the way out along +Z
/// past the face, inside the pass's radius. (An OD pass may also move toward the axis after
/// it, down a shoulder, but it goes on cutting there instead of leaving the bore.)
fn bores_first(r: &Reading, i: usize, face: f64) -> Option<At> {
    let mut rest = r.segs.iter_from(i);
    let s = rest.next()?;
    if s.b[1] - s.a[1] > -INSIDE || s.a[0] <= 0.5 {
        return None;
    }
    let mut rest = rest.filter(|n| n.station == s.station);
    let pull = rest.next()?;
    let out = rest.next()?;
    let pulls_in = pull.b[0] < s.b[0] - 0.01
        && s.b[0] - pull.b[0] <= PULL_OFF
        && (pull.b[1] - pull.a[1]).abs() <= 2.0 * (s.b[0] - pull.b[0]) + 1e-9;
    let leaves = out.b[1] > face && out.b[0] <= pull.b[0] + 1e-6 && out.a[0] <= pull.b[0] + 1e-6;
    (pulls_in && leaves).then_some(At {
        v: s.a[0].min(s.b[0]),
        line: s.line,
    })
}

/// The bar's diameter as a comment writes it, in mm.
fn stock_comment(r: &Reading) -> Option<At> {
    let scale = r.segs.first().map_or(1.0, |s| s.scale);
    for (i, text) in r.lines.iter().enumerate() {
        let (code, comment) = split_comment(&text);
        let c = comment.to_uppercase();
        if !["STOCK", "BAR", "MATERIAL", "BLANK", "ROHTEIL"]
            .iter()
            .any(|k| c.contains(k))
        {
            continue;
        }
        let Some(after) = marker(&c) else {
            continue;
        };
        if let Some(v) = first_number(after) {
            if v > 0.0 {
                return Some(At {
                    v: v * scale,
                    line: i as u32 + 1,
                });
            }
        }
        // `G0 X1.25 (START AT STOCK OD)`: the move's X word is the diameter.
        if let Some(x) = x_word(&code.to_uppercase()) {
            let diameter = r.segs.first().map_or(true, |s| s.diameter);
            let d = if diameter { x } else { 2.0 * x };
            if d > 0.0 {
                return Some(At {
                    v: d * scale,
                    line: i as u32 + 1,
                });
            }
        }
    }
    None
}

/// What follows the first diameter marker of an upper-case comment: `Ø` or `D=` anywhere, or
/// the word `DIA`, `DIA.`, `DIAMETER` or `OD` (not `DIAGONAL`, `GOOD`).
fn marker(c: &str) -> Option<&str> {
    let mut best: Option<usize> = None;
    let mut take = |k: usize| {
        if best.map_or(true, |b| k < b) {
            best = Some(k);
        }
    };
    for m in ["Ø", "D="] {
        if let Some(k) = c.find(m) {
            take(k + m.len());
        }
    }
    let bytes = c.as_bytes();
    // German: `Durchmesser`, `Außendurchmesser` (not `Innendurchmesser`, a tube's bore).
    for m in ["DIAMETER", "DIA.", "DIA", "OD", "SIZE", "DURCHMESSER"] {
        let mut from = 0;
        while let Some(k) = c[from..].find(m).map(|k| k + from) {
            let end = k + m.len();
            let before_ok =
                k == 0 || !bytes[k - 1].is_ascii_alphabetic() || (m == "DURCHMESSER" && c[..k].ends_with("AUSSEN"));
            let after_ok = end >= bytes.len() || !bytes[end].is_ascii_alphabetic();
            if before_ok && after_ok {
                take(end);
                break;
            }
            from = end;
        }
    }
    best.map(|k| &c[k..])
}

/// The first number in `s` after any spaces, `:`, `=` or `-`: `: 50.8 X 120` → 50.8.
fn first_number(s: &str) -> Option<f64> {
    let s = s.trim_start_matches([' ', ':', '=', '-', '\t']);
    let end = s.find(|c: char| !(c.is_ascii_digit() || c == '.')).unwrap_or(s.len());
    s[..end].parse().ok().filter(|v: &f64| v.is_finite())
}

/// The value of the X word of a line of code.
fn x_word(code: &str) -> Option<f64> {
    let k = code.find('X')?;
    let rest = &code[k + 1..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == '+'))
        .unwrap_or(rest.len());
    rest[..end].parse().ok().filter(|v: &f64| v.is_finite())
}

/// The standard sizes for a program in these units, mm.
fn sizes(scale: f64) -> Vec<f64> {
    if (scale - 25.4).abs() < 1e-9 {
        inch_sizes().into_iter().map(|v| v * 25.4).collect()
    } else {
        METRIC.to_vec()
    }
}

/// Material a turning pass removes at least, mm on the diameter: the bar is this much wider
/// than the largest pass.
const PASS_MATERIAL: f64 = 0.2;

/// The bar diameter at least `lo` (mm) and at most `hi` (when given): the smallest standard
/// size that fits, else `lo` itself, and how it was chosen.
fn choose(lo: f64, hi: Option<f64>, scale: f64) -> (f64, &'static str) {
    let fits = |d: f64| d >= lo - 1e-6 && hi.map_or(true, |h| d <= h + 1e-6);
    match sizes(scale).into_iter().find(|&d| fits(d)) {
        Some(d) if (d - lo).abs() < 1e-6 => (d, "a stock size"),
        Some(d) => (d, "rounded up to a stock size"),
        None => (lo, "as cut"),
    }
}

/// The largest standard size under `hi` (mm; the program approaches from there) by
/// [`APPROACH_CLEARANCE`], else just under it, else `hi`.
fn below_size(hi: f64, scale: f64) -> (f64, &'static str) {
    let sizes = sizes(scale);
    let inside = |room: f64| sizes.iter().rev().copied().find(|&d| d < hi - room - 1e-6);
    match inside(APPROACH_CLEARANCE).or_else(|| inside(0.0)) {
        Some(d) => (d, "the largest stock size inside it"),
        None => (hi, "as approached"),
    }
}

/// The highest z the chuck outline reaches inside radius `r` (the bar's back end may go no
/// deeper), or `None` when nothing of it is inside `r`.
fn reach_back(chuck: &crate::geom::Polygon, r: f64) -> Option<f64> {
    let pts = chuck.points();
    let mut top: Option<f64> = None;
    for (k, a) in pts.iter().enumerate() {
        let b = pts[(k + 1) % pts.len()];
        // The part of edge a-b with x < r.
        let (p, q) = if a.x <= b.x { (*a, b) } else { (b, *a) };
        if p.x >= r - 1e-9 {
            continue;
        }
        let z_at_r = if q.x > r && q.x > p.x {
            p.y + (q.y - p.y) * (r - p.x) / (q.x - p.x)
        } else {
            q.y
        };
        let z = p.y.max(z_at_r);
        top = Some(top.map_or(z, |t: f64| t.max(z)));
    }
    top
}

/// Writes a diameter in the program's units: `Ø50` or `Ø1.25 in`.
fn dia_text(d: f64, scale: f64) -> String {
    if (scale - 25.4).abs() < 1e-9 {
        format!("Ø{} in", num(round4(d / 25.4)))
    } else {
        format!("Ø{}", num(round4(d)))
    }
}

fn round4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

/// An X word as the program writes it, for radius `r` mm.
fn x_text(e: &Evidence, r: f64) -> String {
    let x = r / e.scale;
    let x = if e.diameter_words { 2.0 * x } else { x };
    format!("X{}", num(round4(x)))
}

fn z_text(e: &Evidence, z: f64) -> String {
    format!("Z{}", num(round4(z / e.scale)))
}

/// Read the bar and program zero; returns the raw front face in program Z (mm) the tools are
/// read against.
pub fn assume(r: &Reading, file: &str, machine: &Machine, out: &mut Assumed) -> f64 {
    let e = Evidence::of(r, machine);
    let face_seen = e.face.map(|(f, _)| f);
    let replaceable = machine.stock.is_none() || machine.assume_setup;
    let ms = machine.stock.as_ref().filter(|s| s.outline.is_none());
    // The machine's face in program Z.
    let machine_face = ms.map(|s| s.front - machine.program_zero_z);
    let no_cut = e.cut.is_none() && e.reach.is_none();
    if !replaceable || !r.spindle_runs || (no_cut && e.comment.is_none() && e.face.is_none() && e.faced_from.is_none())
    {
        return machine_face.unwrap_or(face_seen.map_or(0.0, |f| f.v));
    }
    // The bar is at least as wide as every radial move reaches and wider than every pass.
    let (lo, lo_at) = match (e.cut, e.reach) {
        (Some(c), Some(r)) if 2.0 * r.v >= 2.0 * c.v + PASS_MATERIAL => (2.0 * r.v, r),
        (Some(c), _) => (2.0 * c.v + PASS_MATERIAL, c),
        (None, Some(r)) => (2.0 * r.v, r),
        (None, None) => (0.0, At { v: 0.0, line: 0 }),
    };
    let hi = e.approach.map(|a| 2.0 * a.v).filter(|h| *h >= lo);
    let mut notes = Vec::new();
    // Diameter.
    let (diameter, why_d, line_d) = if let Some(c) = e.comment {
        let keep = ms.is_some_and(|s| (s.diameter - c.v).abs() < 1e-6);
        let d = if keep { ms.map_or(c.v, |s| s.diameter) } else { c.v };
        (d, format!("the program's comment at line {} gives it", c.line), c.line)
    } else {
        let bounds = match e.approach.filter(|_| hi.is_some()) {
            Some(a) if no_cut => format!("the program approaches from {} (line {})", x_text(&e, a.v), a.line),
            Some(a) => format!(
                "the program cuts at {} (line {}) and approaches from {} (line {})",
                x_text(&e, lo_at.v),
                lo_at.line,
                x_text(&e, a.v),
                a.line
            ),
            None => format!("the program cuts at {} (line {})", x_text(&e, lo_at.v), lo_at.line),
        };
        let (d, how) = match (no_cut, hi, ms.map(|s| s.diameter)) {
            (true, Some(h), _) => below_size(h, e.scale),
            // Between both bounds, the machine file's example bar is as good a reading as any.
            (false, Some(h), Some(m)) if m >= lo - 1e-6 && m <= h + 1e-6 => {
                (m, "the machine file's bar fits between them")
            }
            _ => choose(lo, hi, e.scale),
        };
        (
            d,
            format!("{bounds}; {how}"),
            lo_at.line.max(e.approach.map_or(0, |a| a.line)),
        )
    };
    // Where the face is, in program Z: at the highest facing pass, else at program Z0; the
    // machine file's example face, up to 5 mm ahead of that, stays when the program leaves
    // room for it: no rapid before that facing pass ends in the slab between them, within the
    // bar (a program that rapids there has its raw face at the facing pass).
    let seen = face_seen.map_or(0.0, |f| f.v);
    let slab_clear = |m: f64| {
        let first_face = r
            .segs
            .iter()
            .position(|s| is_facing(&s) && (s.a[1] - seen).abs() < 1e-6)
            .unwrap_or(r.segs.len());
        // The facing passes at that level clear the slab only down to the smallest radius
        // they reach: a rapid after them into what is left of it shows the program, too,
        // takes its face to be there.
        let faced_to = r
            .segs
            .iter()
            .filter(|s| is_facing(s) && (s.a[1] - seen).abs() < 1e-6)
            .map(|s| s.a[0].min(s.b[0]))
            .fold(f64::INFINITY, f64::min);
        // A rapid into the slab, or to its front plane where a cycle starts (a cycle's passes
        // begin at its start point at feed: it stands clear in front of the raw face).
        !r.segs.walk().any(|st| {
            let (i, s) = (st.index, &st.seg);
            if s.kind != SegKind::Rapid {
                return false;
            }
            let below = if i < first_face {
                diameter / 2.0 + SLAB_REACH
            } else {
                faced_to - 1e-6
            };
            let starts_cycle = st.next.is_some_and(|n| {
                n.station == s.station
                    && super::words::g_codes(&super::words::code_of(&r.line(n.line)))
                        .iter()
                        .any(|g| matches!(g, 710 | 720 | 730 | 760 | 780 | 920))
            });
            let top = if starts_cycle { m + 1e-9 } else { m - INSIDE };
            // Along the rapid's path, not only where it ends.
            (0..=8).any(|k| {
                let t = f64::from(k) / 8.0;
                let (pr, pz) = (s.a[0] + t * (s.b[0] - s.a[0]), s.a[1] + t * (s.b[1] - s.a[1]));
                pz > seen + INSIDE && pz <= top && pr < below
            })
        })
    };
    let face = match machine_face {
        Some(m) if m >= seen - 1e-9 && m - seen <= 5.0 && slab_clear(m) => m,
        Some(m) if face_seen.is_none() && (-5.0..0.0).contains(&m) => m,
        _ => seen,
    };
    let why_face = match face_seen {
        Some(f) => format!("the program faces at {} (line {})", z_text(&e, f.v), f.line),
        None => "no facing pass: program Z0 at the face".to_string(),
    };
    // Stick-out: the deepest cut and room to part off, clear of the jaws.
    let jaw_face = machine.chuck.as_ref().map_or(0.0, |c| c.aabb().max.y);
    let deepest = e.deepest.map_or(0.0, |d| d.v);
    let need_front = jaw_face + (face - deepest.min(face)) + PART_OFF_ROOM;
    let (front, why_front) = match ms {
        // The machine file's stick-out stays when it leaves a parting blade's room past the
        // deepest cut, with its face where the program has it.
        Some(s)
            if s.front >= need_front - (PART_OFF_ROOM - KEEP_ROOM) - 1e-9
                && machine_face.is_some_and(|m| (m - face).abs() < 1e-9) =>
        {
            (s.front, "the machine file's stick-out leaves room".to_string())
        }
        _ => (
            need_front,
            match e.deepest {
                Some(d) => format!(
                    "the deepest cut is at {} (line {}), {} mm of room behind it before the jaws",
                    z_text(&e, d.v),
                    d.line,
                    num(PART_OFF_ROOM)
                ),
                None => format!("{} mm out of the jaws", num(need_front - jaw_face)),
            },
        ),
    };
    // A bar no jaws of this chuck can close on is not a bar: the blank is held some other way,
    // and only program zero is read (the face, with room past the deepest cut).
    if let Some(limit) = grip_limit(machine).filter(|&g| diameter >= g - 1e-9) {
        no_bar(
            file,
            line_d,
            why_d.trim_end_matches("; as cut"),
            diameter,
            limit,
            &e,
            out,
        );
        let line = face_seen.map_or(line_d, |f| f.line);
        let kept = (machine.program_zero_z - (front - face)).abs() < 1e-9;
        if !kept {
            out.layer.program_zero_z = Some(set(front - face, file, line, "program_zero_z"));
        }
        out.notes.push(Assumption {
            key: "program_zero_z".into(),
            value: format!("program Z0 {} mm out of the jaws", num(round4(front - face - jaw_face))),
            reason: format!("{why_face}; {why_front}"),
            line,
            kept,
        });
        return face;
    }
    let inside = ms.map_or(20.0, |s| (s.length - (s.front - jaw_face)).max(0.0));
    // A bar wider than the chuck's through bore is a blank that sits in the jaws; with a chuck
    // drawn as an outline (whose jaws do not close on a new bar), in front of what it meets.
    let inside = match (&machine.chuck_form, &machine.chuck) {
        (Some(ChuckForm::Jaws(c)), _) => {
            if c.body.bore <= 0.0 || diameter > c.body.bore + 1e-9 {
                inside.min((jaw_face - c.body.face - 0.5).max(1.0))
            } else {
                inside
            }
        }
        (_, Some(chuck)) => match reach_back(chuck, diameter / 2.0) {
            Some(z) => inside.min((jaw_face - z).max(0.0)),
            None => inside,
        },
        _ => inside,
    };
    let length = front - jaw_face + inside;
    let bore = e
        .tube
        .map(|t| {
            let under_pass = 2.0 * t.v - BORE_MATERIAL;
            e.face_out.map_or(under_pass, |f| under_pass.min(2.0 * f.v)).max(0.0)
        })
        .filter(|b| *b > 0.0 && *b < diameter);
    let same = ms.is_some_and(|s| {
        (s.diameter - diameter).abs() < 1e-9
            && (s.front - front).abs() < 1e-9
            && (s.bore - bore.unwrap_or(0.0)).abs() < 1e-9
            && machine_face.is_some_and(|m| (m - face).abs() < 1e-9)
    });
    let kind = match bore {
        Some(b) => format!("tube {}/{}", dia_text(diameter, e.scale), dia_text(b, e.scale)),
        None => format!("bar {}", dia_text(diameter, e.scale)),
    };
    let value = format!(
        "{kind} × {} mm, {} mm out of the jaws",
        num(round4(length)),
        num(round4(front - jaw_face))
    );
    let mut reason = format!("{why_d}; {why_face}; {why_front}");
    if let (Some(t), Some(_)) = (e.tube, bore) {
        reason.push_str(&format!(
            "; the first tool to cut bores at {} (line {}): a tube",
            x_text(&e, t.v),
            t.line
        ));
    }
    if same {
        notes.push(Assumption {
            key: "stock".into(),
            value,
            reason,
            line: line_d,
            kept: true,
        });
    } else {
        let at = |key: &str| Place {
            file: file.to_string(),
            line: line_d,
            col: 1,
            key: key.to_string(),
        };
        out.layer.stock = Some(set(
            JobStock {
                diameter,
                length,
                front: Some(front),
                bore: bore.unwrap_or(0.0),
                outline: None,
                block: None,
                none: false,
                diameter_at: at("stock.diameter"),
                length_at: at("stock.length"),
            },
            file,
            line_d,
            "stock",
        ));
        out.layer.program_zero_z = Some(set(
            front - face,
            file,
            face_seen.map_or(line_d, |f| f.line),
            "program_zero_z",
        ));
        notes.push(Assumption {
            key: "stock".into(),
            value,
            reason,
            line: line_d,
            kept: false,
        });
    }
    out.notes.extend(notes);
    face
}

/// The smallest bar diameter this machine's chuck cannot grip from outside: its body's diameter
/// for jaws set on a body (the jaws of a wider bar stand off it, and the job check refuses
/// them), the widest point of a chuck drawn as an outline; `None` for jaws that open inside a
/// bore and for a machine with no chuck.
fn grip_limit(machine: &Machine) -> Option<f64> {
    match (&machine.chuck_form, &machine.chuck) {
        (Some(ChuckForm::Jaws(c)), _) => {
            (c.jaws.grip == crate::machine::jaws::Grip::Outside).then_some(c.body.diameter)
        }
        (Some(ChuckForm::Barrier), _) | (_, None) => None,
        (_, Some(chuck)) => Some(2.0 * chuck.aabb().max.x),
    }
}

/// No stock, for a program whose cuts say the blank is wider than the chuck can grip (a casting,
/// a forging, the part of an earlier operation held on a fixture or in its bore): no bar of any
/// size is this setup, so none is assumed, and the note says that rapids into the blank are not
/// checked until a job gives its outline.
fn no_bar(file: &str, line: u32, why_d: &str, diameter: f64, limit: f64, e: &Evidence, out: &mut Assumed) {
    let at = Place {
        file: file.to_string(),
        line,
        col: 1,
        key: "stock.none".to_string(),
    };
    out.layer.stock = Some(set(JobStock::none_at(at), file, line, "stock"));
    out.notes.push(Assumption {
        key: "stock".into(),
        value: "no stock (the blank is not a bar)".into(),
        reason: format!(
            "a bar {} ({why_d}) is wider than this chuck can grip (its jaws close on bars under \
             {}): the blank is held some other way (a casting, a forging, an earlier \
             operation's part), so no stock is assumed and rapids into it are not found; give \
             its outline in a job ([stock] outline)",
            dia_text(diameter, e.scale),
            dia_text(limit, e.scale)
        ),
        line,
        kept: false,
    });
}

#[cfg(test)]
mod turned_tests {
    use super::Turned;
    use proptest::prelude::*;

    proptest! {
        /// Keeping only the passes no other one covers answers every question as the whole list
        /// of passes does (below the cap).
        #[test]
        fn the_passes_kept_say_air_where_every_pass_does(
            passes in prop::collection::vec((-60i32..10, 1i32..40, 0i32..30), 0..120),
            queries in prop::collection::vec((0i32..35, -70i32..12, 0i32..20), 1..60),
        ) {
            let mut kept = Turned::default();
            let mut all: Vec<[f64; 3]> = Vec::new();
            for (bottom, len, r) in passes {
                // Whole and half millimetres, so that equal ends and radii occur.
                let t = [f64::from(bottom + len) / 2.0, f64::from(bottom) / 2.0, f64::from(r) / 2.0];
                kept.push(t);
                all.push(t);
            }
            prop_assert!(kept.passes.len() <= Turned::MOST);
            for (c, zlo, len) in queries {
                let (c, zlo) = (f64::from(c) / 2.0 + 0.25, f64::from(zlo) / 2.0);
                let zhi = zlo + f64::from(len) / 2.0;
                let every = all.iter().any(|t| c > t[2] + 1e-6 && zhi <= t[0] + 1e-9 && zlo >= t[1] - 1e-9);
                prop_assert_eq!(kept.air(c, zlo, zhi), every);
            }
        }
    }

    /// However many passes a program turns, at most `Turned::MOST` are kept.
    #[test]
    fn a_program_of_many_different_passes_keeps_a_bounded_number() {
        let mut kept = Turned::default();
        for k in 0..100_000 {
            // Each pass longer and wider than the last: none covers another.
            let k = f64::from(k);
            kept.push([0.0, -1.0 - k, 1.0 + k]);
        }
        assert_eq!(kept.passes.len(), Turned::MOST);
    }
}
