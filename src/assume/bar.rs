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
use super::{set, Assumed, Assumption};
use crate::job::{JobStock, Place};
use crate::machine::{num, Machine};

/// Room past the deepest cut before the jaws, mm: a parting blade and its clearance.
pub const PART_OFF_ROOM: f64 = 10.0;

/// Material left under a tube's first boring pass, mm on the diameter.
pub const BORE_MATERIAL: f64 = 2.0;

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
    /// The largest radius cut below the face.
    cut: Option<At>,
    /// The smallest radius the program approaches from outside the bar.
    approach: Option<At>,
    /// The lowest Z of a feed move.
    deepest: Option<At>,
    /// The first pass below the face bores: its radius.
    tube: Option<At>,
    /// A stock comment's diameter, mm.
    comment: Option<At>,
    /// The program's units: mm per unit.
    scale: f64,
    diameter_words: bool,
}

fn max_at(to: &mut Option<At>, v: f64, line: u32) {
    if to.is_none_or(|a| v > a.v) {
        *to = Some(At { v, line });
    }
}

fn min_at(to: &mut Option<At>, v: f64, line: u32) {
    if to.is_none_or(|a| v < a.v) {
        *to = Some(At { v, line });
    }
}

fn is_facing(s: &Seg) -> bool {
    s.kind == SegKind::Feed && (s.b[1] - s.a[1]).abs() < 1e-3 && s.a[0] - s.b[0] >= 2.0 && s.b[0] <= 0.5
}

impl Evidence {
    fn of(r: &Reading) -> Evidence {
        let mut e = Evidence {
            scale: 1.0,
            diameter_words: true,
            ..Evidence::default()
        };
        if let Some(s) = r.segs.first() {
            e.scale = s.scale;
            e.diameter_words = s.diameter;
        }
        // The face: the highest full facing pass (not a part-off far behind it).
        for s in r.segs.iter().filter(|s| is_facing(s)) {
            if e.face.is_none_or(|(f, _)| s.a[1] > f.v) {
                e.face = Some((
                    At {
                        v: s.a[1],
                        line: s.line,
                    },
                    s.a[0],
                ));
            }
        }
        let face = e.face.map_or(0.0, |(f, _)| f.v);
        let below = face - INSIDE;
        let mut first_feed = None;
        for (i, s) in r.segs.iter().enumerate() {
            if s.kind != SegKind::Feed {
                continue;
            }
            min_at(&mut e.deepest, s.a[1].min(s.b[1]), s.line);
            let (dr, dz) = (s.b[0] - s.a[0], s.b[1] - s.a[1]);
            // The radius this piece certainly cuts at, below the face.
            let cut = if dz < -INSIDE && dz.abs() >= dr.abs() {
                // Along −Z: the part below the face, at its larger radius.
                (s.b[1] < below).then(|| {
                    let t = ((below - s.a[1]) / dz).clamp(0.0, 1.0);
                    let r_in = s.a[0] + t * dr;
                    r_in.max(s.b[0])
                })
            } else if dr < 0.0 {
                (s.b[1] < below).then_some(s.b[0])
            } else {
                (s.a[1] < below).then_some(s.a[0])
            };
            if let Some(c) = cut {
                if first_feed.is_none() {
                    first_feed = Some(i);
                }
                max_at(&mut e.cut, c, s.line);
            }
        }
        // Approach: facing passes start outside the bar; rapids before the first cut are in air.
        if let Some((f, r0)) = e.face {
            min_at(&mut e.approach, r0, f.line);
        }
        for s in &r.segs[..first_feed.unwrap_or(r.segs.len())] {
            if s.kind != SegKind::Rapid {
                continue;
            }
            for p in [s.a, s.b] {
                if p[1] < below && p[0] > 0.5 {
                    min_at(&mut e.approach, p[0], s.line);
                }
            }
        }
        if let Some(i) = first_feed {
            e.tube = bores_first(r, i);
        }
        e.comment = stock_comment(r);
        e
    }
}

/// When the first cutting piece `i` is a pass along −Z that pulls off toward the axis, its
/// radius (the tool bores: the bar is a tube).
fn bores_first(r: &Reading, i: usize) -> Option<At> {
    let s = &r.segs[i];
    if s.b[1] - s.a[1] > -INSIDE || s.a[0] <= 0.5 {
        return None;
    }
    let next = r.segs[i + 1..].iter().find(|n| n.station == s.station)?;
    let pulls_in = next.b[0] < s.b[0] - 0.05 && (next.b[1] - next.a[1]).abs() <= (next.a[0] - next.b[0]).abs() + 1e-9;
    (pulls_in && next.station == s.station).then_some(At {
        v: s.a[0].min(s.b[0]),
        line: s.line,
    })
}

/// The bar's diameter as a comment writes it, in mm.
fn stock_comment(r: &Reading) -> Option<At> {
    let scale = r.segs.first().map_or(1.0, |s| s.scale);
    for (i, text) in r.lines.iter().enumerate() {
        let (code, comment) = split_comment(text);
        let c = comment.to_uppercase();
        if !["STOCK", "BAR", "MATERIAL", "BLANK", "ROHTEIL"]
            .iter()
            .any(|k| c.contains(k))
        {
            continue;
        }
        let Some(after) = ["Ø", "DIAMETER", "DIA", "D=", "OD"]
            .iter()
            .find_map(|m| c.find(m).map(|k| &c[k + m.len()..]))
        else {
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
            let diameter = r.segs.first().is_none_or(|s| s.diameter);
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

/// A line's code and its comments (`( … )` and `;` to the end).
fn split_comment(line: &str) -> (String, String) {
    let (mut code, mut comment) = (String::new(), String::new());
    let mut depth = 0;
    for (k, ch) in line.char_indices() {
        match ch {
            '(' => depth += 1,
            ')' if depth > 0 => {
                depth -= 1;
                comment.push(' ');
            }
            ';' if depth == 0 => {
                comment.push_str(&line[k + 1..]);
                break;
            }
            _ if depth > 0 => comment.push(ch),
            _ => code.push(ch),
        }
    }
    (code, comment)
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

/// The bar diameter between `lo` and `hi` (mm, either may be absent): the machine's when it
/// fits, else the largest standard size that fits, else the smallest one above `lo`, else `lo`
/// itself. `None` keeps the machine's.
fn choose(lo: Option<f64>, hi: Option<f64>, machine: Option<f64>, scale: f64) -> Option<(f64, &'static str)> {
    let fits = |d: f64| lo.is_none_or(|l| d >= l - 1e-6) && hi.is_none_or(|h| d <= h + 1e-6);
    if let Some(m) = machine {
        if fits(m) {
            return None;
        }
    }
    let sizes = sizes(scale);
    if let Some(h) = hi {
        if let Some(&d) = sizes.iter().rev().find(|&&d| fits(d) && d <= h) {
            return Some((d, "the largest stock size that fits"));
        }
    }
    if let Some(l) = lo {
        if let Some(&d) = sizes.iter().find(|&&d| d >= l - 1e-6) {
            return Some((d, "rounded up to a stock size"));
        }
        return Some((l, "as cut"));
    }
    hi.map(|h| (h, "as approached"))
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
    let e = Evidence::of(r);
    let face_seen = e.face.map(|(f, _)| f);
    let replaceable = machine.stock.is_none() || machine.assume_setup;
    let ms = machine.stock.as_ref().filter(|s| s.outline.is_none());
    // The machine's face in program Z.
    let machine_face = ms.map(|s| s.front - machine.program_zero_z);
    if !replaceable || (e.cut.is_none() && e.comment.is_none()) {
        return machine_face.unwrap_or(face_seen.map_or(0.0, |f| f.v));
    }
    let lo = e.cut.map(|c| 2.0 * c.v);
    let hi = e.approach.map(|a| 2.0 * a.v).filter(|h| lo.is_none_or(|l| *h >= l));
    let mut notes = Vec::new();
    // Diameter.
    let (diameter, why_d, line_d) = if let Some(c) = e.comment {
        let keep = ms.is_some_and(|s| (s.diameter - c.v).abs() < 1e-6);
        let d = if keep { ms.map_or(c.v, |s| s.diameter) } else { c.v };
        (d, format!("the program's comment at line {} gives it", c.line), c.line)
    } else {
        let cut = e.cut.expect("evidence");
        let bounds = match e.approach.filter(|_| hi.is_some()) {
            Some(a) => format!(
                "the program cuts at {} (line {}) and approaches from {} (line {})",
                x_text(&e, cut.v),
                cut.line,
                x_text(&e, a.v),
                a.line
            ),
            None => format!("the program cuts at {} (line {})", x_text(&e, cut.v), cut.line),
        };
        match choose(lo, hi, ms.map(|s| s.diameter), e.scale) {
            None => (
                ms.map_or(0.0, |s| s.diameter),
                format!("{bounds}: the machine file's bar fits"),
                cut.line,
            ),
            Some((d, how)) => (d, format!("{bounds}; {how}"), cut.line),
        }
    };
    // Where the face is, in program Z: the machine's when at or ahead of the facing pass.
    let face = match (face_seen, machine_face) {
        (Some(f), Some(m)) if m >= f.v - 1e-9 && m - f.v <= 5.0 => m,
        (Some(f), _) => f.v,
        (None, Some(m)) if m.abs() <= 5.0 => m,
        (None, _) => 0.0,
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
        Some(s) if s.front >= need_front - 1e-9 && machine_face.is_some_and(|m| (m - face).abs() < 1e-9) => {
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
    let inside = ms.map_or(20.0, |s| (s.length - (s.front - jaw_face)).max(0.0));
    let length = front - jaw_face + inside.max(10.0);
    let bore = e
        .tube
        .map(|t| (2.0 * t.v - BORE_MATERIAL).max(0.0))
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
