//! Tools from their catalogue names: ISO 1832 insert designations (`CNMG 120408`), ISO 5608
//! holder designations (`PCLNR 2525M12`), ISO 6261 boring bars (`S20S-SCLCR09`), grooving and
//! threading inserts, drills by diameter and length; and LinuxCNC tool tables (`.tbl`).
//!
//! The outlines built here are in the frame of a machine file's `[[tools]]` entry: relative to
//! the programmed point (the tool tip, at the origin), `x` = radius direction (+x toward the
//! turret), `z` along the spindle axis (+z toward the tailstock). Pure functions: no I/O.
//!
//! (Interface fixed first so that the job module can build against it; the decoders fill it in.)

use crate::geom::{Polygon, P2};

pub mod drill;
pub mod holder;
pub mod insert;
pub mod milling;
pub mod outline;
pub mod tbl;

#[cfg(test)]
mod tests;

use holder::{AnyHolder, Body, Holder, ThreadHolder};
use insert::{Groove, Insert, Iso1832, ShapeKind, Threading};
use outline::{hull, in_cone, mirror_x, mirror_z, polygon, shrink, walk};

/// A drill given by its sizes (no ISO code): it points toward the chuck (-z) on the spindle axis.
#[derive(Clone, Debug, PartialEq)]
pub struct DrillSpec {
    /// mm, > 0.
    pub diameter: f64,
    /// Flute (cutting) length, mm, > 0.
    pub length: f64,
    /// Point angle in degrees (118 when not given; 180 for a flat-bottom drill).
    pub point_angle: Option<f64>,
}

/// What a tool entry gives in catalogue form. At least one of the three is given; `insert` and
/// `holder` go together for turning tools (a holder alone implies its insert's shape and size).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CatalogueSpec {
    /// ISO 1832 insert designation, e.g. `"CNMG 120408"`, `"VNMG160404"`, `"16ER 1.5ISO"`.
    pub insert: Option<String>,
    /// ISO 5608 holder (`"PCLNR 2525M12"`) or ISO 6261 boring bar (`"S20S-SCLCR09"`).
    pub holder: Option<String>,
    pub drill: Option<DrillSpec>,
}

/// What a tool's cutting part is, as a machinist names it in a report ("the T04 drill hits the
/// jaws", not "the T04 insert").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Cutter {
    /// A turning, grooving, parting or threading insert (and any tool drawn by its outlines
    /// whose name says nothing else).
    #[default]
    Insert,
    /// A twist, spot or centre drill.
    Drill,
    /// A tap.
    Tap,
    /// An end mill (flat, ball or bull nose).
    Mill,
}

impl Cutter {
    /// The word for the cutting part in a report.
    pub fn word(self) -> &'static str {
        match self {
            Cutter::Insert => "insert",
            Cutter::Drill => "drill",
            Cutter::Tap => "tap",
            Cutter::Mill => "mill",
        }
    }

    /// The cutter a tool drawn by its outlines is, by its name: a "drill" (also "centre drill",
    /// "spot drill"), a "tap", an "end mill"; anything else is an insert.
    pub fn from_name(name: &str) -> Cutter {
        let lower = name.to_ascii_lowercase();
        let words: Vec<&str> = lower
            .split(|c: char| !c.is_ascii_alphanumeric())
            .filter(|w| !w.is_empty())
            .collect();
        let has = |w: &str| words.contains(&w);
        if has("drill") || has("drills") {
            Cutter::Drill
        } else if has("tap") {
            Cutter::Tap
        } else if has("mill") || has("endmill") {
            Cutter::Mill
        } else {
            Cutter::Insert
        }
    }
}

/// The geometry a catalogue tool stands for, in a `[[tools]]` entry's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltTool {
    /// The cutting part: may cut stock at feed.
    pub insert: Polygon,
    /// Everything behind it up to the turret: must never touch.
    pub holder: Polygon,
    pub nose_radius: f64,
    /// Imaginary-tip direction 0–9 (docs/comp.md), as a rear-turret Fanuc chart reads it; from
    /// [`tbl::shape`], the table's Q unchanged (LinuxCNC's orientation: [`tbl::fanuc_tip`]
    /// converts).
    pub tip_direction: u8,
    /// One line for `latheguard setup`: what the codes were read as (`80° rhombic, 12.9 mm
    /// IC, r0.8, 95° right-hand holder, 25 × 25 shank, 150 mm`).
    pub summary: String,
    /// What the cutting part is (a drill from `drill = { … }`, a mill or tap from `mill`).
    pub cutter: Cutter,
}

/// A designation that cannot be used: which of `insert`, `holder`, `drill` and why.
#[derive(Clone, Debug, PartialEq)]
pub struct CatalogueError {
    /// `"insert"`, `"holder"` or `"drill"`.
    pub key: &'static str,
    pub message: String,
}

/// A built tool with what its codes were read as, for `latheguard tools show`.
#[derive(Clone, Debug, PartialEq)]
pub struct Decoded {
    pub tool: BuiltTool,
    /// (what, value) in reading order: `shape`, `corner angle`, `inscribed circle`, …
    pub facts: Vec<(&'static str, String)>,
}

/// Decode the designations and build the tool's outlines.
pub fn build(spec: &CatalogueSpec) -> Result<BuiltTool, CatalogueError> {
    decode(spec).map(|d| d.tool)
}

fn err<T>(key: &'static str, message: impl Into<String>) -> Result<T, CatalogueError> {
    Err(CatalogueError {
        key,
        message: message.into(),
    })
}

/// `12.7`, `0.8`, `150`: at most three decimals, no trailing zeros.
pub fn fmt_mm(v: f64) -> String {
    let s = format!("{:.3}", v);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// Decode the designations, build the outlines, and say what the codes were read as.
pub fn decode(spec: &CatalogueSpec) -> Result<Decoded, CatalogueError> {
    if let Some(d) = &spec.drill {
        if spec.insert.is_some() || spec.holder.is_some() {
            return err(
                "drill",
                "a drill is given by its sizes alone: leave out insert and holder",
            );
        }
        return drill::build(d)
            .map(|mut b| {
                b.tool.cutter = Cutter::Drill;
                b
            })
            .map_err(|m| CatalogueError {
                key: "drill",
                message: m,
            });
    }
    let ins = match &spec.insert {
        Some(code) => Some(insert::parse(code).map_err(|m| CatalogueError {
            key: "insert",
            message: format!("{code:?}: {m}"),
        })?),
        None => None,
    };
    let hold = match &spec.holder {
        Some(code) => Some(holder::parse(code).map_err(|m| CatalogueError {
            key: "holder",
            message: format!("{code:?}: {m}"),
        })?),
        None => None,
    };
    match (ins, hold) {
        (None, None) => err("insert", "nothing to build: give an insert, a holder or a drill"),
        (Some(Insert::Turning(i)), Some(AnyHolder::Turning(h))) => {
            agree(&i, &h)?;
            turning(&i, &h, false)
        }
        (Some(Insert::Turning(i)), None) => {
            let h = default_holder(&i)?;
            turning(&i, &h, true)
        }
        (None, Some(AnyHolder::Turning(h))) => {
            let i = implied_insert(&h);
            turning(&i, &h, false).map(|mut d| {
                d.facts.insert(0, ("insert", "implied by the holder".into()));
                d
            })
        }
        (Some(Insert::Threading(t)), h) => {
            let th = match h {
                None => None,
                Some(AnyHolder::Threading(th)) => Some(th),
                Some(AnyHolder::Turning(_)) => {
                    return err(
                        "holder",
                        "a threading insert needs a threading holder (SER/SEL 2525M16, SIR/SIL 0020P16), not a turning holder",
                    )
                }
            };
            threading(&t, th.as_ref())
        }
        (None, Some(AnyHolder::Threading(th))) => {
            let t = insert::parse_threading(&format!("{}{}{}AG60", th.size, if th.internal { 'I' } else { 'E' }, th.hand))
                .map_err(|m| CatalogueError { key: "holder", message: m })?;
            threading(&t, Some(&th)).map(|mut d| {
                d.facts.insert(0, ("insert", "implied by the holder (AG60)".into()));
                d
            })
        }
        (Some(Insert::Turning(_)), Some(AnyHolder::Threading(_))) => err(
            "holder",
            "a threading holder takes a threading insert (16ER 1.5ISO), not a turning insert",
        ),
        (Some(Insert::Groove(g)), None) => grooving(&g),
        (Some(Insert::Groove(_)), Some(_)) => err(
            "holder",
            "grooving holders are not decoded: give the GROOVE insert alone (its blade is built from width and depth) or the holder as an outline",
        ),
    }
}

/// An insert and a holder must agree: shape, clearance and size.
fn agree(i: &Iso1832, h: &Holder) -> Result<(), CatalogueError> {
    if i.shape.letter != h.shape.letter {
        return err(
            "holder",
            format!(
                "the holder takes {} inserts (shape {}), the insert is {} (shape {})",
                insert::shape_name(h.shape.letter),
                h.shape.letter,
                insert::shape_name(i.shape.letter),
                i.shape.letter
            ),
        );
    }
    if i.clearance_letter != h.clearance_letter {
        return err(
            "holder",
            format!(
                "the holder takes inserts of {}° clearance ({}), the insert has {}° ({})",
                h.clearance, h.clearance_letter, i.clearance, i.clearance_letter
            ),
        );
    }
    if (i.ic - h.ic).abs() > 0.05 {
        return err(
            "holder",
            format!(
                "the holder takes size {:02} inserts ({} mm inscribed circle), the insert's is {} mm",
                h.size,
                fmt_mm(h.ic),
                fmt_mm(i.ic)
            ),
        );
    }
    Ok(())
}

/// The holder an insert given alone is drawn in: a right-hand 25 × 25 shank, 150 mm, in the
/// usual style for its shape (docs/tools.md).
pub fn default_style(shape: char) -> Option<char> {
    Some(match shape {
        'C' | 'W' => 'L',
        'D' | 'V' | 'E' | 'M' | 'A' | 'B' | 'K' => 'J',
        'T' => 'G',
        'S' => 'S',
        'P' => 'T',
        'H' => 'D',
        'R' => 'G',
        _ => return None,
    })
}

fn default_holder(i: &Iso1832) -> Result<Holder, CatalogueError> {
    let Some(style) = default_style(i.shape.letter).and_then(holder::style) else {
        return err(
            "insert",
            format!(
                "a {} insert has no default holder: give `holder`",
                insert::shape_name(i.shape.letter)
            ),
        );
    };
    Ok(Holder {
        clamping: 'P',
        shape: i.shape,
        style,
        clearance_letter: i.clearance_letter,
        clearance: i.clearance,
        hand: 'R',
        body: Body::Shank {
            height: 25.0,
            width: 25.0,
            length: 150.0,
        },
        size: i.edge.floor() as u32,
        ic: i.ic,
    })
}

/// The insert a holder given alone implies: its shape, clearance and size, type G, tolerance M,
/// 4.76 mm thick, nose radius 0.8 (0.4 below 9.525 mm inscribed circle).
fn implied_insert(h: &Holder) -> Iso1832 {
    let nose_radius = if h.shape.kind == ShapeKind::Round {
        0.0
    } else if h.ic < 9.5 {
        0.4
    } else {
        0.8
    };
    Iso1832 {
        shape: h.shape,
        clearance_letter: h.clearance_letter,
        clearance: h.clearance,
        tolerance: 'M',
        kind: 'G',
        ic: h.ic,
        edge: insert::edge_length(h.shape, h.ic),
        thickness: 4.76,
        nose_radius,
        inch: false,
        suffix: String::new(),
    }
}

/// Tip direction (rear-turret Fanuc chart) of a tool cutting toward the chuck (`R`), the
/// tailstock (`L`) or straight in (`N`), external or in a bore.
pub fn tip_direction(hand: char, bore: bool) -> u8 {
    match (hand, bore) {
        ('R', false) => 3,
        ('L', false) => 4,
        ('N', false) => 8,
        ('R', true) => 2,
        ('L', true) => 1,
        _ => 6,
    }
}

/// The insert's outline in the canonical frame with its cutting corner at the origin, the edges
/// at the corner leaving at `lo` and `lo + angle` degrees.
fn insert_points(i: &Iso1832, lo: f64) -> Vec<P2> {
    let e = i.shape.angle;
    let l = i.edge;
    match i.shape.kind {
        ShapeKind::Rhombic => walk(lo, &[l; 4], &[180.0 - e, e, 180.0 - e]),
        ShapeKind::Regular(n) => {
            let n = usize::from(n);
            walk(lo, &vec![l; n], &vec![e; n - 1])
        }
        ShapeKind::Trigon => walk(lo, &[l; 6], &[160.0, 80.0, 160.0, 80.0, 160.0]),
        ShapeKind::Round => round_points(i.ic / 2.0),
    }
}

/// A round insert of radius `r` touching both axes at the origin's corner: the corner, then the
/// circle from (r, 0) counter-clockwise round to (0, r). With the nose radius r the scene's
/// rounding of the corner gives the circle back.
fn round_points(r: f64) -> Vec<P2> {
    let mut pts = vec![P2::new(0.0, 0.0)];
    let n = 48;
    for k in 0..=n {
        let a = (-90.0 + 270.0 * f64::from(k) / f64::from(n)).to_radians();
        pts.push(P2::new(r + r * a.cos(), r + r * a.sin()));
    }
    pts
}

/// Shank offset f (tip to the shank's far side face) for an offset-style holder of width `b`.
fn offset_f(b: f64) -> f64 {
    match b as u32 {
        12 => 16.0,
        16 => 20.0,
        20 => 25.0,
        25 => 32.0,
        32 => 40.0,
        40 => 50.0,
        _ => 1.25 * b,
    }
}

/// The holder: the hull of the insert's seat and the body, placed so that near the tip only the
/// insert can cut. `body(s)` is the body starting `s` along its axis, its two near corners
/// first. Tried: set-backs along the bisector of the cutting corner (0, then 0.5 mm growing by
/// a quarter each step) and, for each, starts from half the insert's reach in quarter-mm steps;
/// taken: the first whose near corners lie behind both cutting edges and whose hull leaves the
/// tip and the cutting edges (`edges`: the insert's vertices next to the tip) uncovered.
pub(crate) fn place_body(
    seat: &[P2],
    edges: &[P2],
    reach: f64,
    body: impl Fn(f64) -> Vec<P2>,
    lo: f64,
    hi: f64,
) -> Option<Vec<P2>> {
    let bis = outline::dir((lo + hi) / 2.0);
    let s0 = 0.5 * reach;
    let mut probes = vec![P2::new(0.0, 0.0)];
    for e in edges {
        for k in 1..=18 {
            let f = f64::from(k) * 0.05;
            probes.push(P2::new(e.x * f, e.y * f));
        }
    }
    for k in 0..=80 {
        let t = if k == 0 { 0.0 } else { 0.5 * 1.25f64.powi(k - 1) };
        for j in 0..400 {
            let s = s0 + 0.25 * f64::from(j);
            let pts: Vec<P2> = body(s)
                .into_iter()
                .map(|p| P2::new(p.x + bis.x * t, p.y + bis.y * t))
                .collect();
            if !pts.iter().take(2).all(|&p| in_cone(p, lo, hi)) {
                continue;
            }
            let mut all = seat.to_vec();
            all.extend(pts);
            let h = hull(&all);
            if !probes.iter().any(|&p| outline::strictly_inside_convex(&h, p)) {
                return Some(h);
            }
        }
    }
    None
}

fn turning(i: &Iso1832, h: &Holder, default_holder: bool) -> Result<Decoded, CatalogueError> {
    let e = i.shape.angle;
    let bore = matches!(h.body, Body::Bar { .. });
    let round = i.shape.kind == ShapeKind::Round;
    // The cone of the cutting corner in the canonical frame.
    // A bar bores: every style is read against a feed toward the chuck.
    let facing = h.style.facing && !bore;
    let (lo, hi) = if round {
        (0.0, 90.0)
    } else if facing {
        (180.0 - h.style.kappa - e, 180.0 - h.style.kappa)
    } else {
        (h.style.kappa - 90.0, h.style.kappa - 90.0 + e)
    };
    let key = if default_holder { "insert" } else { "holder" };
    if !round {
        if hi >= 90.0 - 1e-9 && !facing {
            return err(
                key,
                format!(
                    "a {}° insert in a {}° style ({}) leaves its trailing edge no clearance: it would cut behind the tip",
                    e, h.style.kappa, h.style.letter
                ),
            );
        }
        if lo <= 1e-9 && facing {
            return err(
                key,
                format!(
                    "a {}° insert in a {}° facing style ({}) leaves its trailing edge no clearance",
                    e, h.style.kappa, h.style.letter
                ),
            );
        }
        if h.hand == 'N' && (lo + hi).abs() > 2.0 {
            return err(
                "holder",
                format!(
                    "hand N (neutral) needs a style that sets the insert symmetric about the radius; a {}° insert in style {} leans {}°",
                    e,
                    h.style.letter,
                    fmt_mm((lo + hi) / 2.0)
                ),
            );
        }
    }
    let mut ins = if round && h.hand == 'N' {
        // A neutral round tool touches the axis line at its -x point: centre at (r, 0).
        let r = i.ic / 2.0;
        (0..48)
            .map(|k| {
                let a = (180.0 + 7.5 * f64::from(k)).to_radians();
                P2::new(r + r * a.cos(), r * a.sin())
            })
            .collect()
    } else {
        insert_points(i, lo)
    };
    let reach_x = ins.iter().map(|p| p.x).fold(0.0, f64::max);
    let reach_z = ins.iter().map(|p| p.y).fold(0.0, f64::max);
    let seat = shrink(&ins[1..], 0.9);
    let edges = [ins[1], ins[ins.len() - 1]];
    let (placed, facts_body) = match h.body {
        Body::Shank { height, width, length } => {
            let zlo = if h.hand == 'N' {
                -width / 2.0
            } else if h.style.straight {
                1.0f64.min(width / 10.0)
            } else {
                offset_f(width) - width
            };
            let zhi = zlo + width;
            (
                place_body(
                    &seat,
                    &edges,
                    reach_x,
                    |s| {
                        let xe = length.max(s + 1.0);
                        vec![P2::new(s, zlo), P2::new(s, zhi), P2::new(xe, zhi), P2::new(xe, zlo)]
                    },
                    lo,
                    hi,
                ),
                vec![
                    (
                        "shank",
                        format!("{} × {} mm (height × width)", fmt_mm(height), fmt_mm(width)),
                    ),
                    ("length", format!("{} mm", fmt_mm(length))),
                ],
            )
        }
        Body::Bar { kind, diameter, length } => {
            let f = 0.65 * diameter;
            let (x0, x1) = (f - diameter / 2.0, f + diameter / 2.0);
            (
                place_body(
                    &seat,
                    &edges,
                    reach_z,
                    |s| {
                        let ze = length.max(s + 1.0);
                        vec![P2::new(x0, s), P2::new(x1, s), P2::new(x1, ze), P2::new(x0, ze)]
                    },
                    lo,
                    hi,
                ),
                vec![
                    (
                        "bar",
                        format!(
                            "Ø{} mm, {}, tip {} mm from its axis",
                            fmt_mm(diameter),
                            holder::BAR_KINDS.iter().find(|b| b.0 == kind).map_or("?", |b| b.1),
                            fmt_mm(f)
                        ),
                    ),
                    ("length", format!("{} mm", fmt_mm(length))),
                ],
            )
        }
    };
    let Some(mut hold) = placed else {
        return err(
            key,
            format!(
                "the holder's body cannot be placed behind the cutting edges of a {}° insert in style {}",
                fmt_mm(e),
                h.style.letter
            ),
        );
    };
    if bore {
        ins = mirror_x(&ins);
        hold = mirror_x(&hold);
    }
    if h.hand == 'L' {
        ins = mirror_z(&ins);
        hold = mirror_z(&hold);
    }
    let insert_poly = polygon("insert", &ins).or_else(|m| err(key, m))?;
    let holder_poly = polygon("holder", &hold).or_else(|m| err(key, m))?;
    let nose_radius = if round { i.ic / 2.0 } else { i.nose_radius };
    let td = tip_direction(h.hand, bore);
    let hand = match h.hand {
        'R' => "right (cuts toward the chuck)",
        'L' => "left (cuts toward the tailstock)",
        _ => "neutral",
    };
    let mut facts = vec![
        (
            "shape",
            format!("{} ({})", insert::shape_name(i.shape.letter), i.shape.letter),
        ),
        (
            "corner angle",
            if round {
                "round".into()
            } else {
                format!("{}°", fmt_mm(e))
            },
        ),
        (
            "clearance",
            format!("{}° ({})", fmt_mm(i.clearance), i.clearance_letter),
        ),
        ("tolerance", i.tolerance.to_string()),
        ("type", i.kind.to_string()),
        ("inscribed circle", format!("{} mm", fmt_mm(i.ic))),
        ("cutting edge", format!("{} mm", fmt_mm(i.edge))),
        ("thickness", format!("{} mm", fmt_mm(i.thickness))),
        ("nose radius", format!("{} mm", fmt_mm(nose_radius))),
    ];
    if i.inch {
        facts.push((
            "form",
            "inch (IC in 1/8\", thickness in 1/16\", nose radius in 1/64\")".into(),
        ));
    }
    if !i.suffix.is_empty() {
        facts.push(("suffix", format!("{} (not read)", i.suffix)));
    }
    facts.push((
        "holder",
        if default_holder {
            format!(
                "default for the shape: style {}, right hand, 25 × 25 shank, 150 mm",
                h.style.letter
            )
        } else {
            format!(
                "{} ({})",
                if bore { "boring bar" } else { "external" },
                holder::CLAMPINGS
                    .iter()
                    .find(|c| c.0 == h.clamping)
                    .map_or("?", |c| c.1)
            )
        },
    ));
    facts.push((
        "style",
        format!(
            "{} (κr {}°{})",
            h.style.letter,
            fmt_mm(h.style.kappa),
            if h.style.facing && !bore { ", facing" } else { "" }
        ),
    ));
    facts.push(("hand", hand.into()));
    facts.extend(facts_body);
    facts.push(("tip direction", td.to_string()));
    let summary = format!(
        "{}, {} mm IC, r{}, {}° {} {}{}",
        insert::shape_name(i.shape.letter),
        fmt_mm(i.ic),
        fmt_mm(nose_radius),
        fmt_mm(h.style.kappa),
        match h.hand {
            'R' => "right-hand",
            'L' => "left-hand",
            _ => "neutral",
        },
        if bore { "boring bar" } else { "holder" },
        match h.body {
            Body::Shank { height, width, length } =>
                format!(", {} × {} shank, {} mm", fmt_mm(height), fmt_mm(width), fmt_mm(length)),
            Body::Bar { diameter, length, .. } => format!(", Ø{} bar, {} mm", fmt_mm(diameter), fmt_mm(length)),
        }
    );
    Ok(finish(insert_poly, holder_poly, nose_radius, td, summary, facts))
}

pub(crate) fn finish(
    insert: Polygon,
    holder: Polygon,
    nose_radius: f64,
    tip_direction: u8,
    summary: String,
    mut facts: Vec<(&'static str, String)>,
) -> Decoded {
    let b = insert.aabb().union(holder.aabb());
    facts.push((
        "extent",
        format!(
            "x {} .. {}, z {} .. {} mm from the tip",
            fmt_mm(b.min.x),
            fmt_mm(b.max.x),
            fmt_mm(b.min.y),
            fmt_mm(b.max.y)
        ),
    ));
    Decoded {
        tool: BuiltTool {
            insert,
            holder,
            nose_radius,
            tip_direction,
            summary,
            cutter: Cutter::Insert,
        },
        facts,
    }
}

fn threading(t: &Threading, th: Option<&ThreadHolder>) -> Result<Decoded, CatalogueError> {
    if let Some(th) = th {
        if th.internal != t.internal {
            return err(
                "holder",
                format!(
                    "the holder is for {} threads, the insert for {}",
                    if th.internal { "internal" } else { "external" },
                    if t.internal { "internal" } else { "external" }
                ),
            );
        }
        if th.hand != t.hand {
            return err(
                "holder",
                format!("the holder is {}-hand, the insert {}-hand", th.hand, t.hand),
            );
        }
        if th.size != t.size {
            return err(
                "holder",
                format!(
                    "the holder takes size {} inserts, the insert is size {}",
                    th.size, t.size
                ),
            );
        }
    }
    let half = (t.angle / 2.0).to_radians().tan();
    let d = 0.85 * t.ic;
    let xb = 1.5 * t.ic;
    let w = d * half;
    let mut ins = vec![
        P2::new(0.0, 0.0),
        P2::new(d, w),
        P2::new(xb, w),
        P2::new(xb, -w),
        P2::new(d, -w),
    ];
    let body = th.map(|h| h.body.clone()).unwrap_or(if t.internal {
        Body::Bar {
            kind: 'S',
            diameter: 20.0,
            length: 200.0,
        }
    } else {
        Body::Shank {
            height: 25.0,
            width: 25.0,
            length: 150.0,
        }
    });
    let (mut hold, body_fact) = match body {
        Body::Shank { height, width, length } => {
            let zlo = -w - 1.0;
            let xs = d + 0.5;
            (
                vec![
                    P2::new(xs, zlo),
                    P2::new(length.max(xs + 1.0), zlo),
                    P2::new(length.max(xs + 1.0), zlo + width),
                    P2::new(xs, zlo + width),
                ],
                format!("{} × {} shank, {} mm", fmt_mm(height), fmt_mm(width), fmt_mm(length)),
            )
        }
        Body::Bar { diameter, length, .. } => {
            // The insert sits at the bar's end, its flanks half out of the bar's side.
            let x0 = (0.15 * diameter).max(0.5 * d);
            let zs = -w - 1.0;
            (
                vec![
                    P2::new(x0, zs),
                    P2::new(x0 + diameter, zs),
                    P2::new(x0 + diameter, length.max(zs + 1.0)),
                    P2::new(x0, length.max(zs + 1.0)),
                ],
                format!("Ø{} bar, {} mm", fmt_mm(diameter), fmt_mm(length)),
            )
        }
    };
    if t.internal {
        ins = mirror_x(&ins);
        hold = mirror_x(&hold);
    }
    if t.hand == 'L' {
        hold = mirror_z(&hold);
    }
    let insert_poly = polygon("insert", &ins).or_else(|m| err("insert", m))?;
    let holder_poly = polygon("holder", &hold).or_else(|m| err("holder", m))?;
    let td = if t.internal { 6 } else { 8 };
    let pitch = match t.pitch {
        insert::Pitch::Mm(p) => format!("{} mm (full profile)", fmt_mm(p)),
        insert::Pitch::Tpi(n) => format!("{} threads per inch (full profile)", fmt_mm(n)),
        insert::Pitch::Range(code, lo, hi) => {
            format!("{code}: {} .. {} mm (partial profile)", fmt_mm(lo), fmt_mm(hi))
        }
    };
    let facts = vec![
        (
            "kind",
            format!(
                "{} threading insert, laydown",
                if t.internal { "internal" } else { "external" }
            ),
        ),
        ("size", format!("{} ({} mm inscribed circle)", t.size, fmt_mm(t.ic))),
        ("hand", t.hand.to_string()),
        ("pitch", pitch),
        ("profile", format!("{} ({}°)", t.profile, fmt_mm(t.angle))),
        ("nose radius", format!("{} mm", fmt_mm(t.nose_radius))),
        (
            "holder",
            if th.is_some() {
                body_fact.clone()
            } else {
                format!("default: {body_fact}")
            },
        ),
        ("tip direction", td.to_string()),
    ];
    let summary = format!(
        "{} {}° threading insert size {}, r{}, {}",
        if t.internal { "internal" } else { "external" },
        fmt_mm(t.angle),
        t.size,
        fmt_mm(t.nose_radius),
        body_fact
    );
    Ok(finish(insert_poly, holder_poly, t.nose_radius, td, summary, facts))
}

fn grooving(g: &Groove) -> Result<Decoded, CatalogueError> {
    let taper = 0.04 * g.width;
    let reach = g.depth + 1.0;
    let mut ins = vec![
        P2::new(0.0, 0.0),
        P2::new(0.0, g.width),
        P2::new(reach, g.width - taper),
        P2::new(reach, taper),
    ];
    let neck = 0.1 * g.width;
    let (mut hold, body) = if g.internal {
        // A bar along +z whose -z end is flush with the insert's chuck-side face.
        let d = (2.0 * g.depth).max(12.0);
        let x0 = reach - 0.5;
        (
            vec![
                P2::new(x0, 0.0),
                P2::new(x0 + d, 0.0),
                P2::new(x0 + d, 10.0 * d),
                P2::new(x0, 10.0 * d),
            ],
            format!("Ø{} bar, {} mm", fmt_mm(d), fmt_mm(10.0 * d)),
        )
    } else {
        // A blade a little narrower than the groove, then a 25 mm shank flush with the
        // insert's chuck-side face.
        let x1 = 0.8 * reach;
        let x2 = reach + 8.0;
        let end = x2 + 100.0;
        (
            vec![
                P2::new(x1, neck),
                P2::new(x2, neck),
                P2::new(x2, 0.0),
                P2::new(end, 0.0),
                P2::new(end, 25.0),
                P2::new(x2, 25.0),
                P2::new(x2, g.width - neck),
                P2::new(x1, g.width - neck),
            ],
            format!("blade to {} mm, 25 mm shank", fmt_mm(x2)),
        )
    };
    if g.internal {
        ins = mirror_x(&ins);
        hold = mirror_x(&hold);
    }
    let insert_poly = polygon("insert", &ins).or_else(|m| err("insert", m))?;
    let holder_poly = polygon("holder", &hold).or_else(|m| err("insert", m))?;
    let td = if g.internal { 2 } else { 3 };
    let facts = vec![
        (
            "kind",
            format!("{} grooving insert", if g.internal { "internal" } else { "external" }),
        ),
        ("width", format!("{} mm", fmt_mm(g.width))),
        ("depth", format!("{} mm", fmt_mm(g.depth))),
        ("nose radius", format!("{} mm", fmt_mm(g.nose_radius))),
        ("programmed point", "the insert's chuck-side corner".into()),
        ("holder", body.clone()),
        ("tip direction", td.to_string()),
    ];
    let summary = format!(
        "{} groove {} wide, {} deep, r{}, {}",
        if g.internal { "internal" } else { "external" },
        fmt_mm(g.width),
        fmt_mm(g.depth),
        fmt_mm(g.nose_radius),
        body
    );
    Ok(finish(insert_poly, holder_poly, g.nose_radius, td, summary, facts))
}
