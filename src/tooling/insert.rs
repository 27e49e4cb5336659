//! ISO 1832 indexable insert designations (`CNMG 120408`, `CNMG 432`), laydown threading inserts
//! (`16ER 1.5 ISO`, `16IR AG60`) and latheguard's neutral grooving form (`GROOVE 3x20 R0.2`).
//!
//! Only what the outline needs is decoded into numbers: the corner angle, the inscribed circle,
//! the thickness and the nose radius. Tolerance class and type are checked against their letter
//! sets and kept as letters. See docs/tools.md for the tables.

use super::fmt_mm;

/// Shape letter (ISO 1832 position 1): the corner angle and the outline's kind.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    pub letter: char,
    /// Included angle at the cutting corner, degrees.
    pub angle: f64,
    pub kind: ShapeKind,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeKind {
    /// Two sharp corners of `angle` and two of 180° − `angle` (C D E M V, and the parallelograms
    /// A B K drawn as rhombi of their corner angle).
    Rhombic,
    /// A regular polygon of `n` sides (T S P H O).
    Regular(u8),
    /// Trigon (W): three corners of `angle`, three of 160°.
    Trigon,
    /// Round (R): the nose is the whole insert.
    Round,
}

/// The shape letters latheguard knows: letter, corner angle, kind, name.
pub const SHAPES: &[(char, f64, ShapeKind, &str)] = &[
    ('A', 85.0, ShapeKind::Rhombic, "85° parallelogram"),
    ('B', 82.0, ShapeKind::Rhombic, "82° parallelogram"),
    ('C', 80.0, ShapeKind::Rhombic, "80° rhombic"),
    ('D', 55.0, ShapeKind::Rhombic, "55° rhombic"),
    ('E', 75.0, ShapeKind::Rhombic, "75° rhombic"),
    ('H', 120.0, ShapeKind::Regular(6), "hexagonal"),
    ('K', 55.0, ShapeKind::Rhombic, "55° parallelogram"),
    ('M', 86.0, ShapeKind::Rhombic, "86° rhombic"),
    ('O', 135.0, ShapeKind::Regular(8), "octagonal"),
    ('P', 108.0, ShapeKind::Regular(5), "pentagonal"),
    ('R', 360.0, ShapeKind::Round, "round"),
    ('S', 90.0, ShapeKind::Regular(4), "square"),
    ('T', 60.0, ShapeKind::Regular(3), "triangular"),
    ('V', 35.0, ShapeKind::Rhombic, "35° rhombic"),
    ('W', 80.0, ShapeKind::Trigon, "80° trigon"),
];

/// Normal clearance letters (ISO 1832 position 2), degrees.
pub const CLEARANCES: &[(char, f64)] = &[
    ('A', 3.0),
    ('B', 5.0),
    ('C', 7.0),
    ('D', 15.0),
    ('E', 20.0),
    ('F', 25.0),
    ('G', 30.0),
    ('N', 0.0),
    ('P', 11.0),
];

/// Tolerance classes (position 3).
pub const TOLERANCES: &str = "ACEFGHJKLMNU";
/// Insert types: hole, fixing and chip breaker (position 4).
pub const TYPES: &str = "ABCFGHJMNQRTUWX";

/// Metric thickness codes (position 6), mm.
pub const THICKNESSES: &[(&str, f64)] = &[
    ("01", 1.59),
    ("T1", 1.98),
    ("02", 2.38),
    ("03", 3.18),
    ("T3", 3.97),
    ("04", 4.76),
    ("05", 5.56),
    ("06", 6.35),
    ("07", 7.94),
    ("09", 9.52),
    ("12", 12.7),
];

/// Standard inscribed circles, mm: a metric size code names the one whose edge length it is.
pub const STANDARD_IC: &[f64] = &[3.97, 4.76, 5.56, 6.35, 7.94, 9.525, 12.7, 15.875, 19.05, 25.4, 31.75];

pub fn shape(letter: char) -> Option<Shape> {
    SHAPES
        .iter()
        .find(|s| s.0 == letter)
        .map(|&(letter, angle, kind, _)| Shape { letter, angle, kind })
}

pub fn shape_name(letter: char) -> &'static str {
    SHAPES.iter().find(|s| s.0 == letter).map_or("?", |s| s.3)
}

pub fn clearance(letter: char) -> Option<f64> {
    CLEARANCES.iter().find(|c| c.0 == letter).map(|c| c.1)
}

/// Length of one edge of an insert of this shape and inscribed circle, mm.
pub fn edge_length(shape: Shape, ic: f64) -> f64 {
    let a = shape.angle.to_radians();
    match shape.kind {
        ShapeKind::Rhombic => ic / a.sin(),
        ShapeKind::Regular(n) => ic * (std::f64::consts::PI / f64::from(n)).tan(),
        // A trigon: the hexagon of equal sides with 80° and 160° corners whose six edges are
        // `ic` / 2 from the centre (each corner's bisector runs through the centre, so an edge
        // is `ic` / 2 × (cot 40° + cot 80°) long).
        ShapeKind::Trigon => ic / 2.0 * (1.0 / 40f64.to_radians().tan() + 1.0 / 80f64.to_radians().tan()),
        ShapeKind::Round => ic,
    }
}

/// The inscribed circle a metric size code (the cutting edge length, whole mm) stands for: the
/// standard circle whose edge length truncates to it, else the circle of that exact edge length.
pub fn ic_from_size(shape: Shape, size: u32) -> f64 {
    if shape.kind == ShapeKind::Round {
        // Round inserts are named by their diameter.
        return match size {
            6 => 6.35,
            9 => 9.525,
            15 => 15.875,
            19 => 19.05,
            n => f64::from(n),
        };
    }
    // The code is the edge length without its decimals; nominal lengths a hair under the whole
    // millimetre (6.35 mm triangles: 10.998) count as that millimetre.
    for &ic in STANDARD_IC {
        let e = edge_length(shape, ic);
        if e.floor() as u32 == size || (e + 0.05).floor() as u32 == size {
            return ic;
        }
    }
    f64::from(size) / edge_length(shape, 1.0)
}

/// A turning insert read from its ISO 1832 designation.
#[derive(Clone, Debug, PartialEq)]
pub struct Iso1832 {
    pub shape: Shape,
    pub clearance_letter: char,
    pub clearance: f64,
    pub tolerance: char,
    pub kind: char,
    /// Inscribed circle, mm.
    pub ic: f64,
    /// Cutting edge length, mm.
    pub edge: f64,
    pub thickness: f64,
    pub nose_radius: f64,
    /// Written in the inch form (`CNMG 432`).
    pub inch: bool,
    /// What followed the nose radius code (chip breaker, grade), as written.
    pub suffix: String,
}

/// A laydown threading insert (`16ER 1.5 ISO`).
#[derive(Clone, Debug, PartialEq)]
pub struct Threading {
    /// Size code: 11, 16, 22, 27 (edge length, mm).
    pub size: u32,
    pub ic: f64,
    pub internal: bool,
    pub hand: char,
    /// Pitch in mm (full profile), or the range letters (partial profile).
    pub pitch: Pitch,
    /// Included angle of the thread form, degrees (60 or 55).
    pub angle: f64,
    pub profile: String,
    pub nose_radius: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Pitch {
    /// A full-profile insert for one pitch, mm.
    Mm(f64),
    /// A full-profile insert for one thread count per inch.
    Tpi(f64),
    /// A partial-profile insert for a range of pitches, mm: code, smallest, largest.
    Range(&'static str, f64, f64),
}

/// Partial-profile pitch ranges, mm (smallest, largest).
pub const PITCH_RANGES: &[(&str, f64, f64)] = &[
    ("AG", 0.5, 3.0),
    ("A", 0.5, 1.5),
    ("G", 1.75, 3.0),
    ("N", 3.5, 5.0),
    ("Q", 5.5, 6.0),
];

/// Thread profiles: code, included angle.
pub const PROFILES: &[(&str, f64)] = &[
    ("ISO", 60.0),
    ("UN", 60.0),
    ("NPT", 60.0),
    ("60", 60.0),
    ("W", 55.0),
    ("BSPT", 55.0),
    ("55", 55.0),
];

/// Threading insert sizes: code → inscribed circle, mm.
pub const THREAD_SIZES: &[(u32, f64)] = &[(11, 6.35), (16, 9.525), (22, 12.7), (27, 15.875)];

/// A grooving or parting insert, latheguard's neutral form `GROOVE <width>x<depth> [R<r>] [INT]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Groove {
    pub width: f64,
    pub depth: f64,
    pub nose_radius: f64,
    pub internal: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Insert {
    Turning(Iso1832),
    Threading(Threading),
    Groove(Groove),
}

/// Longest designation read (anything longer is no catalogue code).
pub const MAX_CODE: usize = 64;

/// Decode an insert designation.
pub fn parse(code: &str) -> Result<Insert, String> {
    if code.chars().count() > MAX_CODE {
        return Err(format!("is longer than {MAX_CODE} characters: no designation is"));
    }
    let up = code.trim().to_ascii_uppercase();
    if up.is_empty() {
        return Err("is empty".into());
    }
    if up.starts_with("GROOVE") {
        return parse_groove(&up).map(Insert::Groove);
    }
    if up.starts_with(|c: char| c.is_ascii_digit()) {
        return parse_threading(&up).map(Insert::Threading);
    }
    parse_iso1832(&up).map(Insert::Turning)
}

/// The letters of `set` as `A B C`.
fn letters(set: impl IntoIterator<Item = char>) -> String {
    let v: Vec<String> = set.into_iter().map(|c| c.to_string()).collect();
    v.join(" ")
}

fn shown(c: char) -> String {
    if c.is_ascii_graphic() {
        format!("'{c}'")
    } else {
        format!("{:?}", c)
    }
}

pub fn parse_iso1832(up: &str) -> Result<Iso1832, String> {
    // The four letters, then the numbers with or without a space between; the rest is a
    // manufacturer's suffix after a space or a dash.
    let chars: Vec<char> = up.chars().collect();
    let at = |i: usize| chars.get(i).copied();
    let need = |i: usize, what: &str| at(i).ok_or_else(|| format!("ends before position {} ({what})", i + 1));
    let c = need(0, "shape")?;
    let shape = shape(c).ok_or_else(|| {
        format!(
            "position 1 (shape) is {}; accepted: {}",
            shown(c),
            letters(SHAPES.iter().map(|s| s.0))
        )
    })?;
    let c = need(1, "clearance")?;
    let clear = clearance(c).ok_or_else(|| {
        format!(
            "position 2 (normal clearance) is {}; accepted: {}",
            shown(c),
            letters(CLEARANCES.iter().map(|s| s.0))
        )
    })?;
    let tol = need(2, "tolerance class")?;
    if !TOLERANCES.contains(tol) {
        return Err(format!(
            "position 3 (tolerance class) is {}; accepted: {}",
            shown(tol),
            letters(TOLERANCES.chars())
        ));
    }
    let kind = need(3, "type")?;
    if !TYPES.contains(kind) {
        return Err(format!(
            "position 4 (type: hole and chip breaker) is {}; accepted: {}",
            shown(kind),
            letters(TYPES.chars())
        ));
    }
    let mut i = 4;
    while at(i) == Some(' ') {
        i += 1;
    }
    // The size block: up to the first space or dash.
    let start = i;
    while let Some(c) = at(i) {
        if c == ' ' || c == '-' {
            break;
        }
        i += 1;
    }
    let block: String = chars[start..i].iter().collect();
    let suffix: String = chars[i..].iter().collect::<String>().trim().to_string();
    let digits = block
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == 'T' || *c == 'M')
        .count();
    let (ic, edge, thickness, nose_radius, inch, extra) = if block.len() >= 6 && digits >= 4 {
        metric_block(shape, &block, start)?
    } else if block.len() >= 3 && block.chars().take(3).all(|c| c.is_ascii_digit()) {
        inch_block(shape, &block, start)?
    } else {
        return Err(format!(
            "position {} (size, thickness, nose radius) is {:?}; expected six digits as in `CNMG 120408` or three as in `CNMG 432`",
            start + 1,
            block
        ));
    };
    let mut suffix_all = extra;
    if !suffix.is_empty() {
        if !suffix_all.is_empty() {
            suffix_all.push(' ');
        }
        suffix_all.push_str(&suffix);
    }
    Ok(Iso1832 {
        shape,
        clearance_letter: up.chars().nth(1).unwrap_or('N'),
        clearance: clear,
        tolerance: tol,
        kind,
        ic,
        edge,
        thickness,
        nose_radius,
        inch,
        suffix: suffix_all,
    })
}

type Block = (f64, f64, f64, f64, bool, String);

fn metric_block(shape: Shape, block: &str, start: usize) -> Result<Block, String> {
    let b: Vec<char> = block.chars().collect();
    let size_s: String = b[0..2].iter().collect();
    let size: u32 = size_s
        .parse()
        .map_err(|_| format!("position {} (size) is {size_s:?}; expected two digits", start + 1))?;
    if size == 0 {
        return Err(format!("position {} (size) is 00; an insert has a size", start + 1));
    }
    let thick_s: String = b[2..4].iter().collect();
    let thickness = THICKNESSES
        .iter()
        .find(|t| t.0 == thick_s)
        .map(|t| t.1)
        .ok_or_else(|| {
            format!(
                "position {} (thickness) is {thick_s:?}; accepted: {}",
                start + 3,
                THICKNESSES.iter().map(|t| t.0).collect::<Vec<_>>().join(" ")
            )
        })?;
    let nose_s: String = b[4..6].iter().collect();
    let nose_radius = if nose_s == "M0" || nose_s == "00" {
        0.0
    } else {
        let n: u32 = nose_s.parse().map_err(|_| {
            format!(
                "position {} (nose radius) is {nose_s:?}; expected two digits in tenths of a mm (04 = 0.4 mm) or M0 (round)",
                start + 5
            )
        })?;
        f64::from(n) / 10.0
    };
    let ic = ic_from_size(shape, size);
    let edge = edge_length(shape, ic);
    check_nose(shape, ic, nose_radius, start + 5)?;
    let extra: String = b[6..].iter().collect();
    Ok((ic, edge, thickness, nose_radius, false, extra))
}

fn inch_block(shape: Shape, block: &str, start: usize) -> Result<Block, String> {
    let b: Vec<char> = block.chars().collect();
    let d = |i: usize| f64::from(b[i].to_digit(10).unwrap_or(0));
    if d(0) == 0.0 {
        return Err(format!("position {} (size) is 0; an insert has a size", start + 1));
    }
    if d(1) == 0.0 {
        return Err(format!(
            "position {} (thickness) is 0; an insert has a thickness",
            start + 2
        ));
    }
    // IC in eighths of an inch, thickness in sixteenths, nose radius in sixty-fourths.
    let ic = d(0) * 25.4 / 8.0;
    let thickness = d(1) * 25.4 / 16.0;
    let nose_radius = d(2) * 25.4 / 64.0;
    check_nose(shape, ic, nose_radius, start + 3)?;
    let extra: String = b[3..].iter().collect();
    Ok((ic, edge_length(shape, ic), thickness, nose_radius, true, extra))
}

fn check_nose(shape: Shape, ic: f64, r: f64, pos: usize) -> Result<(), String> {
    if shape.kind != ShapeKind::Round && r >= ic / 2.0 {
        return Err(format!(
            "position {pos} (nose radius): r{} does not fit an insert of {} mm inscribed circle",
            fmt_mm(r),
            fmt_mm(ic)
        ));
    }
    Ok(())
}

pub fn parse_threading(up: &str) -> Result<Threading, String> {
    let s: String = up.chars().filter(|c| *c != ' ').collect();
    let chars: Vec<char> = s.chars().collect();
    let n = chars.iter().take_while(|c| c.is_ascii_digit()).count();
    let size: u32 = s[..n]
        .parse()
        .map_err(|_| "position 1 (size) is not a number".to_string())?;
    let ic = THREAD_SIZES.iter().find(|t| t.0 == size).map(|t| t.1).ok_or_else(|| {
        format!(
            "position 1 (threading insert size) is {size}; accepted: {}",
            THREAD_SIZES
                .iter()
                .map(|t| t.0.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        )
    })?;
    let pos = n + 1;
    let internal = match chars.get(n) {
        Some('E') => false,
        Some('I') => true,
        Some(&c) => {
            return Err(format!(
                "position {pos} (external/internal) is {}; accepted: E I",
                shown(c)
            ));
        }
        None => return Err(format!("ends before position {pos} (E external or I internal)")),
    };
    let hand = match chars.get(n + 1) {
        Some(&c @ ('R' | 'L')) => c,
        Some(&c) => return Err(format!("position {} (hand) is {}; accepted: R L", pos + 1, shown(c))),
        None => return Err(format!("ends before position {} (hand R or L)", pos + 1)),
    };
    let rest: String = chars[n + 2..].iter().collect();
    if rest.is_empty() {
        return Err(format!("ends before position {} (pitch or pitch range)", pos + 2));
    }
    // Pitch: a number (mm, or TPI when the profile is UN/W/NPT/BSPT), or a range code.
    let num_len = rest.chars().take_while(|c| c.is_ascii_digit() || *c == '.').count();
    let (pitch_raw, profile_s) = if num_len > 0 {
        let v: f64 = rest[..num_len].parse().map_err(|_| {
            format!(
                "position {} (pitch) is {:?}; expected a number",
                pos + 2,
                &rest[..num_len]
            )
        })?;
        if !(v > 0.0 && v <= 100.0) {
            return Err(format!(
                "position {} (pitch) is {v}; expected 0 < pitch <= 100",
                pos + 2
            ));
        }
        (Some(v), rest[num_len..].to_string())
    } else {
        (None, rest.clone())
    };
    let (pitch, profile_s) = match pitch_raw {
        Some(v) => (Pitch::Mm(v), profile_s),
        None => {
            let (code, lo, hi) = PITCH_RANGES
                .iter()
                .find(|r| profile_s.starts_with(r.0))
                .copied()
                .ok_or_else(|| {
                    format!(
                        "position {} (pitch) is {:?}; expected a pitch in mm (1.5) or a range: {}",
                        pos + 2,
                        profile_s,
                        PITCH_RANGES.iter().map(|r| r.0).collect::<Vec<_>>().join(" ")
                    )
                })?;
            (Pitch::Range(code, lo, hi), profile_s[code.len()..].to_string())
        }
    };
    let (profile, angle) = PROFILES
        .iter()
        .find(|p| p.0 == profile_s)
        .map(|p| (p.0.to_string(), p.1))
        .ok_or_else(|| {
            format!(
                "the thread profile is {:?}; accepted: {}",
                profile_s,
                PROFILES.iter().map(|p| p.0).collect::<Vec<_>>().join(" ")
            )
        })?;
    // UN, W, NPT, BSPT pitches are threads per inch.
    let pitch = match pitch {
        Pitch::Mm(v) if matches!(profile.as_str(), "UN" | "W" | "NPT" | "BSPT") => Pitch::Tpi(v),
        p => p,
    };
    let nose_radius = match pitch {
        Pitch::Mm(p) => p / 8.0,
        Pitch::Tpi(t) => 25.4 / t / 8.0,
        Pitch::Range(_, lo, _) => lo / 8.0,
    };
    Ok(Threading {
        size,
        ic,
        internal,
        hand,
        pitch,
        angle,
        profile,
        nose_radius,
    })
}

pub fn parse_groove(up: &str) -> Result<Groove, String> {
    let body = up["GROOVE".len()..].trim();
    let mut tokens = body.split_whitespace();
    let dims = tokens
        .next()
        .ok_or("GROOVE needs <width>x<depth> in mm, as in `GROOVE 3x20`")?;
    let (w, d) = dims
        .split_once('X')
        .ok_or_else(|| format!("GROOVE size is {dims:?}; expected <width>x<depth> in mm, as in `GROOVE 3x20`"))?;
    let num = |s: &str, what: &str, lo: f64, hi: f64| -> Result<f64, String> {
        let v: f64 = s
            .parse()
            .map_err(|_| format!("GROOVE {what} is {s:?}; expected a number of mm"))?;
        if v.is_finite() && v > lo && v <= hi {
            Ok(v)
        } else {
            Err(format!("GROOVE {what} is {s}; expected {lo} < {what} <= {hi} mm"))
        }
    };
    let width = num(w, "width", 0.0, 50.0)?;
    let depth = num(d, "depth", 0.0, 200.0)?;
    let mut nose_radius = 0.0;
    let mut internal = false;
    for t in tokens {
        if let Some(r) = t.strip_prefix('R') {
            nose_radius = num(r, "nose radius", -1e-300, 25.0)?;
            if nose_radius > width / 2.0 {
                return Err(format!(
                    "GROOVE nose radius r{} is more than half the width {}",
                    fmt_mm(nose_radius),
                    fmt_mm(width)
                ));
            }
        } else if t == "INT" || t == "INTERNAL" {
            internal = true;
        } else if t == "EXT" || t == "EXTERNAL" {
            internal = false;
        } else {
            return Err(format!(
                "GROOVE does not take {t:?}; accepted after the size: R<radius>, INT, EXT"
            ));
        }
    }
    Ok(Groove {
        width,
        depth,
        nose_radius,
        internal,
    })
}
