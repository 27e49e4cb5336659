//! A catalogue tool of a kind, sized from the program's evidence, placed at a station's tip.

use super::moves::Work;
use super::ToolKind;
use crate::geom::P2;
use crate::machine::{Dialect, Machine, Tool};
use crate::tooling::{self, fmt_mm, holder::LENGTHS, BuiltTool, CatalogueSpec, Cutter, DrillSpec};

/// Clearance kept between a bar and the far wall of the smallest bore it works in, mm.
const BORE_CLEAR: f64 = 0.5;
/// Boring bar diameters tried, largest first, mm.
const BARS: [u32; 8] = [40, 32, 25, 20, 16, 12, 10, 8];
/// A drill a bit under a later boring bar's bore: this much less on the diameter, mm.
const DRILL_UNDER: f64 = 1.0;
/// A drill's diameter when nothing sizes it, mm.
const DEFAULT_DRILL: f64 = 10.0;

/// What the sizes come from besides the station's own moves.
pub struct Sizing<'a> {
    pub work: &'a Work,
    /// A size the comment gives (mm): a drill's or tap's diameter, a bar's, a groove's width.
    pub said: Option<f64>,
    pub internal: bool,
    /// The smallest radius a boring bar cuts at after this station's first cut (mm).
    pub later_bore: Option<f64>,
    /// The comment says finishing or profiling.
    pub finish: bool,
}

/// A tool built for a station: the machine tool, its designation in words, its origin.
pub struct Made {
    pub tool: Tool,
    /// `S16R-SCLCR09`, `CNMG 120408 in PCLNR 2525M12`, `Ø20 × 45`.
    pub designation: String,
    pub summary: String,
}

/// Rounded down to a half millimetre.
fn floor_half(v: f64) -> f64 {
    (v * 2.0).floor() / 2.0
}

/// The smallest catalogue length letter at least `need` mm (the longest when none is).
fn length_letter(need: f64) -> char {
    LENGTHS.iter().find(|l| l.1 >= need).map_or('Y', |l| l.0)
}

/// The tool's whole outline spans `[min x, max x]` from its tip.
fn x_span(b: &BuiltTool) -> (f64, f64) {
    let bb = b.insert.aabb().union(b.holder.aabb());
    (bb.min.x, bb.max.x)
}

/// A tool whose tip sits on the wall of a bore of radius `r` fits it: its far side stays
/// [`BORE_CLEAR`] off the opposite wall.
fn fits_bore(b: &BuiltTool, r: f64) -> bool {
    x_span(b).0 >= -2.0 * r + BORE_CLEAR
}

/// A standard ISO metric tap's major diameter for a pitch, mm.
fn tap_for_pitch(p: f64) -> f64 {
    const TAPS: [(f64, f64); 10] = [
        (0.5, 3.0),
        (0.7, 4.0),
        (0.8, 5.0),
        (1.0, 6.0),
        (1.25, 8.0),
        (1.5, 10.0),
        (1.75, 12.0),
        (2.0, 16.0),
        (2.5, 20.0),
        (3.0, 24.0),
    ];
    TAPS.iter()
        .min_by(|a, b| (a.0 - p).abs().total_cmp(&(b.0 - p).abs()))
        .map_or(10.0, |t| t.1)
}

fn catalogue(insert: Option<String>, holder: Option<String>) -> Option<BuiltTool> {
    tooling::build(&CatalogueSpec {
        insert,
        holder,
        drill: None,
    })
    .ok()
}

/// How deep below the face the station cuts, mm.
fn depth(w: &Work, face: f64) -> f64 {
    w.deepest.map_or(0.0, |d| (face - d).max(0.0))
}

/// The drill: the comment's diameter, else a bit under the smallest bore a later boring bar
/// starts in (so the hole it leaves never hides that bar's crash), else [`DEFAULT_DRILL`].
pub fn drill_diameter(said: Option<f64>, later_bore: Option<f64>) -> (f64, &'static str) {
    if let Some(d) = said {
        return (d, "the comment's diameter");
    }
    match later_bore.map(|r| floor_half(2.0 * r - DRILL_UNDER)) {
        Some(d) if d >= 1.0 => (d, "a bit under the bore a later boring bar starts in"),
        Some(_) => (0.5, "under the bore a later boring bar starts in"),
        None => (DEFAULT_DRILL, "a usual size: nothing in the program sizes it"),
    }
}

/// Build the catalogue tool of `kind` for `station`, sized from `z`, at `tip`.
pub fn make(kind: ToolKind, z: &Sizing<'_>, face: f64, station: u32, tip: P2, machine: &Machine) -> Option<Made> {
    let w = z.work;
    let deep = depth(w, face);
    let (built, designation, why) = match kind {
        ToolKind::OdTurning | ToolKind::Facing => {
            let finishing = z.finish || w.descends;
            let pick = if finishing {
                ("VNMG 160404", "MVJNR 2525M16")
            } else {
                ("CNMG 120408", "PCLNR 2525M12")
            };
            let b = catalogue(Some(pick.0.into()), Some(pick.1.into()))?;
            (b, format!("{} in {}", pick.0, pick.1), String::new())
        }
        ToolKind::Boring => {
            let r = w.pass_r.filter(|r| *r > 0.5);
            let len = length_letter((deep + 30.0).max(-tip.y + 20.0));
            let code = |d: u32| {
                let size = if d >= 25 {
                    12
                } else if d >= 16 {
                    9
                } else {
                    6
                };
                format!("S{d:02}{len}-SCLCR{size:02}")
            };
            let said = z.said.map(|d| d.round() as u32).filter(|d| (6..=60).contains(d));
            let mut found = said.and_then(|d| catalogue(None, Some(code(d))).map(|b| (b, code(d))));
            if found.is_none() {
                for d in BARS {
                    if let Some(b) = catalogue(None, Some(code(d))) {
                        let fits = r.map_or(true, |r| fits_bore(&b, r)) && (r.is_some() || d <= 16);
                        if fits || d == *BARS.last().expect("bars") {
                            found = Some((b, code(d)));
                            break;
                        }
                    }
                }
            }
            let (b, c) = found?;
            (b, c, String::new())
        }
        ToolKind::Drilling | ToolKind::Tapping => {
            let (d, why) = if kind == ToolKind::Tapping {
                match (z.said, w.lead) {
                    (Some(d), _) => (d, "the comment's size"),
                    (None, Some(p)) => (tap_for_pitch(p), "the metric tap of its pitch"),
                    (None, None) => (DEFAULT_DRILL, "a usual size"),
                }
            } else {
                drill_diameter(z.said, z.later_bore)
            };
            let length = ((deep + 10.0).max(2.0 * d) / 5.0).ceil() * 5.0;
            let spec = DrillSpec {
                diameter: d,
                length,
                point_angle: (kind == ToolKind::Tapping).then_some(180.0),
            };
            let mut b = tooling::drill::build(&spec).ok()?.tool;
            b.cutter = if kind == ToolKind::Tapping {
                Cutter::Tap
            } else {
                Cutter::Drill
            };
            let designation = if kind == ToolKind::Tapping {
                format!("M{} × {}", fmt_mm(d), fmt_mm(length))
            } else {
                format!("Ø{} × {}", fmt_mm(d), fmt_mm(length))
            };
            (b, designation, why.to_string())
        }
        ToolKind::Threading => {
            let pitch = w.lead.filter(|p| *p <= 6.0);
            let pitch_code = pitch.map_or("AG60".to_string(), |p| format!("{}ISO", fmt_mm(p)));
            let mut made = None;
            if z.internal {
                let r = w.pass_r;
                for d in [32u32, 25, 20, 16, 12, 10] {
                    let size = if d >= 16 { 16 } else { 11 };
                    let len = length_letter((deep + 30.0).max(-tip.y + 20.0));
                    let (ins, hold) = (format!("{size}IR {pitch_code}"), format!("SIR 00{d:02}{len}{size}"));
                    if let Some(b) = catalogue(Some(ins.clone()), Some(hold.clone())) {
                        if r.map_or(true, |r| fits_bore(&b, r)) || d == 10 {
                            made = Some((b, format!("{ins} in {hold}")));
                            break;
                        }
                    }
                }
            } else {
                let ins = format!("16ER {pitch_code}");
                made = catalogue(Some(ins.clone()), None).map(|b| (b, ins));
            }
            let (b, c) = made?;
            (b, c, String::new())
        }
        ToolKind::Grooving | ToolKind::Parting => {
            let mut zs: Vec<f64> = w.plunges.iter().map(|p| p[0]).collect();
            zs.sort_by(f64::total_cmp);
            let step = zs
                .windows(2)
                .map(|p| p[1] - p[0])
                .filter(|d| *d > 0.01)
                .fold(f64::INFINITY, f64::min);
            let reach = w.plunges.iter().map(|p| p[1]).fold(0.0, f64::max)
                - w.plunges.iter().map(|p| p[2]).fold(f64::INFINITY, f64::min);
            let usual = if kind == ToolKind::Parting && reach < 20.0 {
                2.0
            } else {
                3.0
            };
            let width = (z.said.unwrap_or(usual).min(step) * 10.0).floor() / 10.0;
            let width = width.clamp(0.5, 50.0);
            let deepest = if reach.is_finite() { reach.max(1.0) } else { 10.0 };
            let depth = (deepest.ceil() + 2.0).min(200.0);
            let code = format!(
                "GROOVE {}x{} R{}{}",
                fmt_mm(width),
                fmt_mm(depth),
                fmt_mm((0.1 * width).min(0.2)),
                if z.internal { " INT" } else { "" }
            );
            let b = catalogue(Some(code.clone()), None)?;
            (b, code, String::new())
        }
    };
    let name = format!("{} {}", kind.word(), designation);
    let cutter = if built.cutter != Cutter::Insert {
        built.cutter
    } else {
        Cutter::from_name(&name)
    };
    let tip_direction = match machine.dialect {
        Dialect::Linuxcnc => tooling::tbl::fanuc_tip(built.tip_direction),
        Dialect::Fanuc => built.tip_direction,
    };
    let summary = if why.is_empty() {
        built.summary.clone()
    } else {
        format!("{}; {why}", built.summary)
    };
    Some(Made {
        tool: Tool {
            station,
            name,
            tip,
            insert: built.insert,
            holder: built.holder,
            nose_radius: built.nose_radius,
            tip_direction,
            mill: None,
            cutter,
        },
        designation,
        summary,
    })
}

/// Whether a tool stands along the spindle axis (a boring bar, a drill) rather than radially.
pub fn is_axial(t: &Tool) -> bool {
    let b = t.insert.aabb().union(t.holder.aabb());
    b.max.y - b.min.y > b.max.x - b.min.x
}

/// The tip for a new tool in `station`: the station's own tool's when it stands the same way,
/// else a machine tool's that stands the same way, else the station's own, else the turret's
/// usual place for such a tool.
pub fn tip_for(machine: &Machine, station: u32, axial: bool) -> P2 {
    let own = machine.tool(station);
    own.filter(|t| is_axial(t) == axial)
        .or_else(|| machine.tools.iter().find(|t| is_axial(t) == axial))
        .or(own)
        .map_or(
            if axial {
                P2::new(-40.0, -100.0)
            } else {
                P2::new(-60.0, -12.0)
            },
            |t| t.tip,
        )
}
