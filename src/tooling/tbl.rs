//! LinuxCNC tool tables (`.tbl`): one tool a line, `T<n> P<pocket> X Z D I J Q ;comment`.
//!
//! Words may come in any order, with or without spaces between them (`T1 P1` or `T1P1`);
//! letters in either case; `;` starts the comment (the tool's name); blank lines are skipped.
//! The axis words LinuxCNC also accepts (Y A B C U V W) are read and ignored: a lathe uses X and
//! Z. Every problem is an error with its 1-based line and column (in characters).
//!
//! **Offsets.** A lathe table's X and Z are the tool's offsets: the vector from the point the
//! control positions with no tool offset (latheguard's turret reference point) to the tool's
//! programmed point (its imaginary tip), in machine units. latheguard takes them as `tip =
//! [X, Z]` of a `[[tools]]` entry, X as a radius (LinuxCNC keeps tool offsets in axis units, and
//! its lathe X axis is a radius axis whatever G7/G8 says), scaled to mm for an inch table.
//!
//! **Orientation.** Q is LinuxCNC's orientation 0–9, in its X/Z axes; it becomes the tool's
//! `tip_direction` unchanged — what a LinuxCNC-dialect machine file reads (docs/comp.md). A
//! Fanuc machine reads tip codes off the rear-turret chart instead: [`fanuc_tip`] converts.

use super::outline::{dir, hull, polygon, shrink, walk};
use super::{finish, fmt_mm, place_body, BuiltTool, CatalogueError, Decoded};
use crate::geom::P2;

/// One line of a tool table, as written (lengths in the table's units, angles in degrees).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TblTool {
    pub tool: u32,
    pub pocket: u32,
    /// X offset (LinuxCNC lathe tables give it as written; see the decoder's docs for its sense).
    pub x: f64,
    pub z: f64,
    /// Tool diameter (D): twice the nose radius for a lathe tool.
    pub diameter: f64,
    /// Front angle I, back angle J (degrees), orientation Q (0–9).
    pub front_angle: f64,
    pub back_angle: f64,
    pub orientation: u8,
    pub comment: String,
}

/// A table that cannot be read: 1-based line and column, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct TblError {
    pub line: usize,
    pub col: usize,
    pub message: String,
}

impl std::fmt::Display for TblError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.col, self.message)
    }
}

/// Most tools a table may hold.
pub const MAX_TOOLS: usize = 10_000;
/// Largest tool or pocket number.
pub const MAX_NUMBER: u32 = 99_999;
/// Largest magnitude of an offset, diameter or angle.
pub const MAX_VALUE: f64 = 1e6;

impl TblTool {
    /// The same line with its lengths (X, Z, D) in mm, from a table in inches when `inch`.
    pub fn in_mm(&self, inch: bool) -> TblTool {
        let k = if inch { 25.4 } else { 1.0 };
        TblTool {
            x: self.x * k,
            z: self.z * k,
            diameter: self.diameter * k,
            ..self.clone()
        }
    }

    /// `tip` of the tool's `[[tools]]` entry: `[X, Z]` (lengths as in this value).
    pub fn tip(&self) -> [f64; 2] {
        [self.x, self.z]
    }
}

/// Read a tool table.
pub fn parse(text: &str) -> Result<Vec<TblTool>, TblError> {
    let mut tools: Vec<TblTool> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (li, raw) in text.split('\n').enumerate() {
        let line = li + 1;
        let raw = raw.strip_suffix('\r').unwrap_or(raw);
        let (words, comment) = match raw.find(';') {
            Some(k) => (&raw[..k], raw[k + 1..].trim()),
            None => (raw, ""),
        };
        let chars: Vec<char> = words.chars().collect();
        if chars.iter().all(|c| c.is_whitespace()) {
            // A blank line, or a comment alone on its line: nothing to read.
            continue;
        }
        let e = |col: usize, message: String| TblError {
            line,
            col: col + 1,
            message,
        };
        let mut t = TblTool {
            comment: comment.to_string(),
            ..TblTool::default()
        };
        let mut got = String::new();
        let mut tool_col = None;
        let mut i = 0;
        while i < chars.len() {
            let c = chars[i];
            if c.is_whitespace() {
                i += 1;
                continue;
            }
            let col = i;
            let letter = c.to_ascii_uppercase();
            if !"TPXYZABCUVWDIJQ".contains(letter) || !c.is_ascii_alphabetic() {
                return Err(e(
                    col,
                    format!(
                        "{c:?} is not a tool table word; expected one of T P X Z D I J Q (Y A B C U V W are ignored)"
                    ),
                ));
            }
            if got.contains(letter) {
                return Err(e(col, format!("{letter} appears twice on this line")));
            }
            got.push(letter);
            i += 1;
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || matches!(chars[i], '.' | '+' | '-')) {
                i += 1;
            }
            let num: String = chars[start..i].iter().collect();
            if i < chars.len() && !chars[i].is_whitespace() && !chars[i].is_ascii_alphabetic() {
                return Err(e(i, format!("{:?} cannot follow the number of {letter}", chars[i])));
            }
            let v: f64 = match num.parse::<f64>() {
                Ok(v) if v.is_finite() && v.abs() <= MAX_VALUE => v,
                Ok(_) => {
                    return Err(e(
                        start,
                        format!("{letter}{num}: the value is out of range (|v| <= {MAX_VALUE})"),
                    ))
                }
                Err(_) if num.is_empty() => return Err(e(col, format!("{letter} needs a number"))),
                Err(_) => return Err(e(start, format!("{letter}{num}: {num:?} is not a number"))),
            };
            let whole = |lo: f64, hi: f64| -> Result<u32, TblError> {
                if v.fract() == 0.0 && v >= lo && v <= hi {
                    Ok(v as u32)
                } else {
                    Err(e(
                        start,
                        format!("{letter}{num}: expected a whole number from {lo} to {hi}"),
                    ))
                }
            };
            match letter {
                'T' => {
                    t.tool = whole(0.0, f64::from(MAX_NUMBER))?;
                    tool_col = Some(col);
                }
                'P' => t.pocket = whole(0.0, f64::from(MAX_NUMBER))?,
                'X' => t.x = v,
                'Z' => t.z = v,
                'D' => {
                    if v < 0.0 {
                        return Err(e(start, format!("D{num}: a tool diameter is not negative")));
                    }
                    t.diameter = v;
                }
                'I' => t.front_angle = v,
                'J' => t.back_angle = v,
                'Q' => t.orientation = whole(0.0, 9.0)? as u8,
                _ => {}
            }
        }
        let Some(tcol) = tool_col else {
            return Err(e(
                0,
                "this line has no T word: every tool table line starts a tool with T<n>".into(),
            ));
        };
        if !got.contains('P') {
            t.pocket = t.tool;
        }
        if !seen.insert(t.tool) {
            return Err(e(tcol, format!("tool T{} is already in the table", t.tool)));
        }
        if tools.len() >= MAX_TOOLS {
            return Err(e(0, format!("more than {MAX_TOOLS} tools")));
        }
        tools.push(t);
    }
    Ok(tools)
}

/// Front and back angle LinuxCNC's own lathe-comp table gives each orientation, used when a
/// line gives none (I = J).
pub const DEFAULT_ANGLES: [(f64, f64); 10] = [
    (0.0, 0.0),
    (95.0, 155.0),
    (85.0, 25.0),
    (275.0, 335.0),
    (265.0, 205.0),
    (210.0, 150.0),
    (120.0, 60.0),
    (-30.0, 30.0),
    (240.0, 300.0),
    (0.0, 0.0),
];

/// Fanuc rear-turret tip code of a LinuxCNC orientation: the same corner of the nose, read off
/// the other chart (docs/comp.md).
pub fn fanuc_tip(q: u8) -> u8 {
    match q {
        1 => 4,
        2 => 3,
        3 => 2,
        4 => 1,
        6 => 8,
        8 => 6,
        q => q,
    }
}

/// Length of each edge of the insert drawn for a table line, mm (the table has no size).
pub const INSERT_EDGE: f64 = 10.0;
/// Width of the generic holder bar, mm, and how far it runs behind the insert.
pub const HOLDER_WIDTH: f64 = 16.0;
pub const HOLDER_LENGTH: f64 = 80.0;

/// The outlines a table line stands for (insert from the front and back angles and the nose
/// radius, a generic holder behind it). Lengths are read as mm: convert with
/// [`TblTool::in_mm`] first.
pub fn shape(t: &TblTool) -> Result<BuiltTool, CatalogueError> {
    shape_decoded(t).map(|d| d.tool)
}

/// [`shape`] with what the line was read as.
pub fn shape_decoded(t: &TblTool) -> Result<Decoded, CatalogueError> {
    let bad = |m: String| CatalogueError {
        key: "insert",
        message: format!("T{}: {m}", t.tool),
    };
    let r = t.diameter / 2.0;
    if !(r.is_finite() && r <= 100.0) {
        return Err(bad(format!("the nose radius D/2 = {} is more than 100 mm", fmt_mm(r))));
    }
    let q = t.orientation;
    let (mut i, mut j) = (t.front_angle, t.back_angle);
    let given = i != j;
    if !given && (1..=8).contains(&q) {
        (i, j) = DEFAULT_ANGLES[usize::from(q)];
    }
    let mut s = INSERT_EDGE.max(6.0 * r);
    let (ins, lo, eps) = if i == j {
        // No angles: a round nose about the programmed point (orientation 0 or 9).
        let rr = r.max(1.0);
        let pts: Vec<P2> = (0..24)
            .map(|k| {
                let a = (f64::from(k) * 15.0).to_radians();
                P2::new(rr * a.cos(), rr * a.sin())
            })
            .collect();
        (pts, -90.0, 180.0)
    } else {
        // LinuxCNC's angles run from +Z toward +X; the kernel's from +x toward +z.
        let a = 90.0 - i;
        let b = 90.0 - j;
        let mut d = (b - a).rem_euclid(360.0);
        if d > 180.0 {
            d -= 360.0;
        }
        let (lo, eps) = if d >= 0.0 { (a, d) } else { (b, -d) };
        if !(1.0..=179.0).contains(&eps) {
            return Err(bad(format!(
                "front angle I{} and back angle J{} leave {}° of insert; expected 1 to 179",
                fmt_mm(t.front_angle),
                fmt_mm(t.back_angle),
                fmt_mm(eps)
            )));
        }
        let half = (eps / 2.0).to_radians();
        let back = r / half.sin();
        let centred = q == 0 || q == 9;
        if centred {
            // The insert's long diagonal must reach past the nose centre.
            s = s.max(back / half.cos());
        }
        let mut pts = walk(lo, &[s; 4], &[180.0 - eps, eps, 180.0 - eps]);
        if centred {
            // The programmed point is the nose centre: put the corner r from it, outward.
            let bis = dir(lo + eps / 2.0);
            for p in &mut pts {
                *p = P2::new(p.x - bis.x * back, p.y - bis.y * back);
            }
        }
        (pts, lo, eps)
    };
    // The holder: a bar along the axis direction nearest the insert's bisector, from behind the
    // insert back HOLDER_LENGTH, with the insert's seat.
    let bis = dir(lo + eps / 2.0);
    let (ax, n) = if bis.x.abs() >= bis.y.abs() {
        (P2::new(bis.x.signum(), 0.0), P2::new(0.0, 1.0))
    } else {
        (P2::new(0.0, bis.y.signum()), P2::new(1.0, 0.0))
    };
    let k = ins.len() as f64;
    let c = P2::new(
        ins.iter().map(|p| p.x).sum::<f64>() / k,
        ins.iter().map(|p| p.y).sum::<f64>() / k,
    );
    let cn = c.x * n.x + c.y * n.y;
    let reach = ins.iter().map(|p| p.x * ax.x + p.y * ax.y).fold(0.0, f64::max);
    let w = HOLDER_WIDTH / 2.0;
    // The bar's centre line across its axis: on the insert's centroid, or shifted so that the
    // bar's side lies on the insert's extreme across the axis (a holder offset to the side the
    // insert leans to, as real offset-style shanks are). Of the placements found, the one that
    // ends nearest the tip: a bar lined up on the centroid behind a 93° edge must start 100 mm
    // back to stay behind the leading edge, and would reach through the turret.
    let (amin, amax) = ins
        .iter()
        .map(|p| p.x * n.x + p.y * n.y)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    // A round nose's bar stays on its centre line.
    let centres = if i == j { vec![cn] } else { vec![cn, amin + w, amax - w] };
    let place = |centre: f64| -> Option<Vec<P2>> {
        let at = |s: f64, off: f64| P2::new(ax.x * s + n.x * (centre + off), ax.y * s + n.y * (centre + off));
        let body = |s: f64| {
            let s1 = s.max(reach) + HOLDER_LENGTH;
            vec![at(s, -w), at(s, w), at(s1, w), at(s1, -w)]
        };
        if i == j {
            // A round nose: the bar alone, from half its radius out (every point of the nose may
            // cut).
            Some(hull(&body(0.5 * reach)))
        } else {
            // The seat: the insert less its cutting corner, a little inside it.
            let n = ins.len();
            place_body(
                &shrink(&ins[1..], 0.9),
                &[ins[1], ins[n - 1]],
                reach,
                body,
                lo,
                lo + eps,
            )
        }
    };
    let far = |h: &Vec<P2>| {
        h.iter()
            .map(|p| p.x * ax.x + p.y * ax.y)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let hold = centres
        .into_iter()
        .filter_map(place)
        .min_by(|a, b| far(a).total_cmp(&far(b)))
        .ok_or_else(|| bad("the generic holder cannot be placed behind the insert".into()))?;
    let insert = polygon("insert", &ins).map_err(bad)?;
    let holder = polygon("holder", &hold).map_err(bad)?;
    let facts = vec![
        ("tool", format!("T{} (pocket {})", t.tool, t.pocket)),
        ("tip", format!("[{}, {}] (X, Z offsets)", fmt_mm(t.x), fmt_mm(t.z))),
        ("nose radius", format!("{} mm (D/2)", fmt_mm(r))),
        (
            "angles",
            if i == j {
                "none: a round nose about the programmed point".to_string()
            } else {
                format!(
                    "front {}°, back {}°{}: {}° insert",
                    fmt_mm(i),
                    fmt_mm(j),
                    if given { "" } else { " (the orientation's default)" },
                    fmt_mm(eps)
                )
            },
        ),
        (
            "orientation",
            format!("Q{q} (LinuxCNC; Fanuc rear-turret tip {})", fanuc_tip(q)),
        ),
    ];
    let summary = format!(
        "T{}{}: {}r{}, Q{}",
        t.tool,
        if t.comment.is_empty() {
            String::new()
        } else {
            format!(" {}", t.comment)
        },
        if i == j {
            "round nose, ".to_string()
        } else {
            format!("{}° insert, ", fmt_mm(eps))
        },
        fmt_mm(r),
        q
    );
    Ok(finish(insert, holder, r, q, summary, facts))
}
