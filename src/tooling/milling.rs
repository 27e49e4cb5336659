//! Milling tools by their sizes: flat, ball and bull end mills, drills, spot drills and
//! taps in a live station, with their shank and holder.
//!
//! One description gives three things: the 2D section in the working plane (the `insert` is the
//! cutting part, the `holder` the shank and the holder behind it), the kinematic parts of the
//! station for a machine with a `[kinematics]` tree (`kin::station`), and [`MillTool`], the
//! typed description the milled stock (`grid::Cutter`) reads.
//!
//! Frames: the programmed point is the cutter's point on its axis. A **radial** tool points at
//! the spindle axis (−x): the cutter stands along +x from its point. An **axial** tool points at
//! the part's face (−z): the cutter stands along +z from its point.

use super::outline::polygon;
use super::{fmt_mm, BuiltTool};
use crate::geom::P2;

/// Largest cutter or holder diameter read, mm.
pub const MAX_DIAMETER: f64 = 200.0;
/// Longest flute, stick-out or holder read, mm.
pub const MAX_LENGTH: f64 = 500.0;
/// Default point angles, degrees: a twist drill and a spot drill.
pub const DRILL_POINT: f64 = 118.0;
pub const SPOT_POINT: f64 = 90.0;

/// The cutter's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MillKind {
    Flat,
    Ball,
    /// A flat end with rounded corners.
    Bull {
        corner_radius: f64,
    },
    /// A twist drill or a spot drill: a cone of this included angle.
    Drill {
        point_angle: f64,
    },
    /// A tap of this pitch: modelled as its major diameter (the 2D section and the 3D parts) and
    /// as its minor diameter in the milled stock (`grid::CutterKind::Tap`).
    Tap {
        pitch: f64,
    },
}

/// Which way a live station points the cutter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Live {
    /// Along the spindle axis, at the part's face (−z).
    Axial,
    /// At the spindle axis (−x).
    Radial,
}

/// A milling tool as a tool entry gives it (`mill = { … }`, `live = "…"`).
#[derive(Clone, Debug, PartialEq)]
pub struct MillSpec {
    /// `"flat"`, `"ball"`, `"bull"`, `"drill"`, `"spot"` or `"tap"`.
    pub kind: String,
    pub diameter: f64,
    pub flute_length: f64,
    /// Length out of the holder (flutes and the bare shank), ≥ the flute length.
    pub stick_out: f64,
    pub corner_radius: Option<f64>,
    pub point_angle: Option<f64>,
    pub pitch: Option<f64>,
    /// Shank diameter; the cutter's diameter when not given.
    pub shank: Option<f64>,
    /// The holder (a collet chuck's nut, a side-lock holder) as a cylinder: diameter and length.
    pub holder_diameter: f64,
    pub holder_length: f64,
    pub live: Live,
}

/// A milling tool, validated: what the 2D section, the 3D parts and the milled stock read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MillTool {
    pub kind: MillKind,
    pub diameter: f64,
    pub flute_length: f64,
    pub stick_out: f64,
    pub shank: f64,
    pub holder_diameter: f64,
    pub holder_length: f64,
    pub live: Live,
}

impl MillTool {
    /// The cutter's half outline from its point: `(a, w)`, `a` along the axis from the point
    /// (0 .. flute length), `w ≥ 0` the half width there, from the axis point to the flutes'
    /// end.
    pub fn profile(&self) -> Vec<(f64, f64)> {
        let r = self.diameter / 2.0;
        let fl = self.flute_length;
        let arc = |c: (f64, f64), rad: f64, from: f64, to: f64, out: &mut Vec<(f64, f64)>| {
            // A quarter arc as the polygon of 12 of its tangents: its ends on the arc, the
            // tangents' crossings at rad / cos(Δ/2) from its centre, so the section holds the
            // cutter (by 0.0021·rad at most) and stays within its radius and its point.
            let at = |t: f64, rr: f64| (c.0 - rr * t.to_radians().cos(), c.1 + rr * t.to_radians().sin());
            let step = (to - from) / 12.0;
            let big = rad / (step / 2.0).to_radians().cos();
            out.push(at(from, rad));
            for k in 0..12 {
                out.push(at(from + step * (k as f64 + 0.5), big));
            }
            out.push(at(to, rad));
        };
        let mut p = vec![(0.0, 0.0)];
        match self.kind {
            MillKind::Flat | MillKind::Tap { .. } => p.push((0.0, r)),
            MillKind::Ball => {
                p.pop();
                arc((r, 0.0), r, 0.0, 90.0, &mut p);
            }
            MillKind::Bull { corner_radius: c } => {
                p.push((0.0, r - c));
                arc((c, r - c), c, 0.0, 90.0, &mut p);
                p.remove(2);
            }
            MillKind::Drill { point_angle } => {
                if point_angle < 180.0 {
                    p.push((r / (point_angle / 2.0).to_radians().tan(), r));
                } else {
                    p.push((0.0, r));
                }
            }
        }
        p.push((fl, r));
        p
    }

    /// The cutter for the milled stock.
    pub fn grid_kind(&self) -> crate::grid::CutterKind {
        use crate::grid::CutterKind as K;
        match self.kind {
            MillKind::Flat => K::Flat,
            MillKind::Ball => K::Ball,
            MillKind::Bull { corner_radius } => K::Bull { corner_radius },
            // A drill ground flat (180°) cuts as a flat end.
            MillKind::Drill { point_angle } if point_angle >= 180.0 => K::Flat,
            MillKind::Drill { point_angle } => K::Drill {
                point_angle_deg: point_angle,
            },
            MillKind::Tap { pitch } => K::Tap { pitch },
        }
    }
}

fn within(what: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<f64, String> {
    if v.is_finite() && v > lo && v <= hi {
        Ok(v)
    } else {
        Err(format!("{what} is {v}; expected above {lo} and at most {hi} {unit}"))
    }
}

/// Validate a milling tool's sizes.
pub fn tool(s: &MillSpec) -> Result<MillTool, String> {
    let d = within("diameter", s.diameter, 0.0, MAX_DIAMETER, "mm")?;
    let fl = within("flute_length", s.flute_length, 0.0, MAX_LENGTH, "mm")?;
    let so = within("stick_out", s.stick_out, 0.0, MAX_LENGTH, "mm")?;
    if so < fl {
        return Err(format!(
            "stick_out {} mm is shorter than the flutes ({} mm): the holder would cover the cutting part",
            fmt_mm(so),
            fmt_mm(fl)
        ));
    }
    let shank = within("shank", s.shank.unwrap_or(d), 0.0, MAX_DIAMETER, "mm")?;
    let hd = within("holder.diameter", s.holder_diameter, 0.0, MAX_DIAMETER, "mm")?;
    let hl = within("holder.length", s.holder_length, 0.0, MAX_LENGTH, "mm")?;
    if hd < shank {
        return Err(format!(
            "holder.diameter {} mm is less than the shank ({} mm) it holds",
            fmt_mm(hd),
            fmt_mm(shank)
        ));
    }
    let only = |key: &str, v: Option<f64>, kinds: &str| match v {
        Some(_) => Err(format!("{key} is for {kinds} only")),
        None => Ok(()),
    };
    let kind = match s.kind.as_str() {
        "flat" | "ball" => {
            only("corner_radius", s.corner_radius, "a bull end mill")?;
            only("point_angle", s.point_angle, "a drill or a spot drill")?;
            only("pitch", s.pitch, "a tap")?;
            if s.kind == "flat" {
                MillKind::Flat
            } else {
                if fl < d / 2.0 {
                    return Err(format!(
                        "a ball end mill's flutes ({} mm) are shorter than its radius",
                        fmt_mm(fl)
                    ));
                }
                MillKind::Ball
            }
        }
        "bull" => {
            only("point_angle", s.point_angle, "a drill or a spot drill")?;
            only("pitch", s.pitch, "a tap")?;
            let c = s.corner_radius.ok_or("a bull end mill needs corner_radius")?;
            let c = within("corner_radius", c, 0.0, d / 2.0, "mm (the cutter's radius)")?;
            if fl < c {
                return Err("the flutes are shorter than the corner radius".into());
            }
            MillKind::Bull { corner_radius: c }
        }
        "drill" | "spot" => {
            only("corner_radius", s.corner_radius, "a bull end mill")?;
            only("pitch", s.pitch, "a tap")?;
            let a = s
                .point_angle
                .unwrap_or(if s.kind == "drill" { DRILL_POINT } else { SPOT_POINT });
            if !(a.is_finite() && (60.0..=180.0).contains(&a)) {
                return Err(format!("point_angle is {a}; expected 60 to 180 degrees"));
            }
            if a < 180.0 && d / 2.0 / (a / 2.0).to_radians().tan() >= fl {
                return Err("the point is longer than the flutes".into());
            }
            MillKind::Drill { point_angle: a }
        }
        "tap" => {
            only("corner_radius", s.corner_radius, "a bull end mill")?;
            only("point_angle", s.point_angle, "a drill or a spot drill")?;
            let p = s.pitch.ok_or("a tap needs pitch")?;
            let p = within("pitch", p, 0.0, d / 2.0, "mm")?;
            MillKind::Tap { pitch: p }
        }
        other => {
            return Err(format!(
            "type {other:?} is not a milling tool: give \"flat\", \"ball\", \"bull\", \"drill\", \"spot\" or \"tap\""
        ))
        }
    };
    Ok(MillTool {
        kind,
        diameter: d,
        flute_length: fl,
        stick_out: so,
        shank,
        holder_diameter: hd,
        holder_length: hl,
        live: s.live,
    })
}

/// What a milling tool's description stands for, in reading order (`kind`, `diameter`, …).
pub type Facts = Vec<(&'static str, String)>;

/// The 2D section of a milling tool in its station's frame, and its facts for `tools show`.
pub fn build(s: &MillSpec) -> Result<(BuiltTool, MillTool, Facts), String> {
    let m = tool(s)?;
    // (a, w) along the cutter's axis → the station frame's (x, z).
    let place = |a: f64, w: f64| match m.live {
        Live::Radial => P2::new(a, w),
        Live::Axial => P2::new(w, a),
    };
    let half = m.profile();
    let mut ins: Vec<P2> = half.iter().map(|&(a, w)| place(a, w)).collect();
    ins.extend(half.iter().rev().filter(|p| p.1 > 0.0).map(|&(a, w)| place(a, -w)));
    ins.dedup_by(|p, q| (p.x - q.x).abs() < 1e-12 && (p.y - q.y).abs() < 1e-12);
    let (fl, so, rs) = (m.flute_length, m.stick_out, m.shank / 2.0);
    let (hr, he) = (m.holder_diameter / 2.0, m.stick_out + m.holder_length);
    let mut hold = Vec::new();
    if so > fl {
        hold.extend([place(fl, -rs), place(so, -rs)]);
    }
    hold.extend([place(so, -hr), place(he, -hr), place(he, hr), place(so, hr)]);
    if so > fl {
        hold.extend([place(so, rs), place(fl, rs)]);
    }
    // Counter-clockwise either way round (the axial frame is the radial one mirrored).
    if m.live == Live::Axial {
        ins.reverse();
        hold.reverse();
    }
    let insert = polygon("milling cutter", &ins)?;
    let holder = polygon("milling holder", &hold)?;
    let kind = match m.kind {
        MillKind::Flat => "flat end mill".to_string(),
        MillKind::Ball => "ball end mill".into(),
        MillKind::Bull { corner_radius } => format!("bull end mill, corner r{}", fmt_mm(corner_radius)),
        MillKind::Drill { point_angle } => format!("drill, {}° point", fmt_mm(point_angle)),
        MillKind::Tap { pitch } => format!("tap, pitch {}", fmt_mm(pitch)),
    };
    let way = match m.live {
        Live::Axial => "axial live station (points at the part's face, −z)",
        Live::Radial => "radial live station (points at the spindle axis, −x)",
    };
    let summary = format!(
        "{kind} Ø{}, {} flutes, {} out of a Ø{} × {} holder, {}",
        fmt_mm(m.diameter),
        fmt_mm(fl),
        fmt_mm(so),
        fmt_mm(m.holder_diameter),
        fmt_mm(m.holder_length),
        match m.live {
            Live::Axial => "axial",
            Live::Radial => "radial",
        }
    );
    let facts = vec![
        ("kind", kind),
        ("station", way.to_string()),
        ("diameter", format!("{} mm", fmt_mm(m.diameter))),
        ("flute length", format!("{} mm", fmt_mm(fl))),
        ("shank", format!("Ø{} mm", fmt_mm(m.shank))),
        ("stick-out", format!("{} mm", fmt_mm(so))),
        (
            "holder",
            format!("Ø{} × {} mm", fmt_mm(m.holder_diameter), fmt_mm(m.holder_length)),
        ),
        ("summary", summary.clone()),
    ];
    Ok((
        BuiltTool {
            insert,
            holder,
            nose_radius: 0.0,
            tip_direction: 0,
            summary,
            cutter: match m.kind {
                MillKind::Drill { .. } => crate::tooling::Cutter::Drill,
                MillKind::Tap { .. } => crate::tooling::Cutter::Tap,
                _ => crate::tooling::Cutter::Mill,
            },
        },
        m,
        facts,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec(kind: &str, live: Live) -> MillSpec {
        MillSpec {
            kind: kind.into(),
            diameter: 10.0,
            flute_length: 22.0,
            stick_out: 30.0,
            corner_radius: None,
            point_angle: None,
            pitch: None,
            shank: None,
            holder_diameter: 42.0,
            holder_length: 20.0,
            live,
        }
    }

    fn extent(p: &crate::geom::Polygon) -> (f64, f64, f64, f64) {
        let pts = p.points();
        let f = |g: fn(&P2) -> f64| {
            (
                pts.iter().map(g).fold(f64::INFINITY, f64::min),
                pts.iter().map(g).fold(f64::NEG_INFINITY, f64::max),
            )
        };
        let ((x0, x1), (z0, z1)) = (f(|p| p.x), f(|p| p.y));
        (x0, x1, z0, z1)
    }

    #[test]
    fn a_radial_flat_end_mill_stands_along_x_from_its_point_with_its_holder_behind() {
        let (t, m, _) = build(&spec("flat", Live::Radial)).unwrap();
        assert_eq!(m.kind, MillKind::Flat);
        assert_eq!(extent(&t.insert), (0.0, 22.0, -5.0, 5.0));
        // The bare shank to 30, then the Ø42 holder 20 long.
        assert_eq!(extent(&t.holder), (22.0, 50.0, -21.0, 21.0));
        assert!((t.insert.area() - 220.0).abs() < 1e-9);
    }

    #[test]
    fn an_axial_drill_stands_along_z_with_its_point() {
        let (t, m, _) = build(&spec("drill", Live::Axial)).unwrap();
        assert_eq!(m.kind, MillKind::Drill { point_angle: 118.0 });
        let (x0, x1, z0, z1) = extent(&t.insert);
        assert_eq!((x0, x1, z0, z1), (-5.0, 5.0, 0.0, 22.0));
        // The point: 5 / tan 59° = 3.004 mm long; the section's area is the rectangle less it.
        let point = 5.0 / 59f64.to_radians().tan();
        assert!(
            (t.insert.area() - (220.0 - 5.0 * point)).abs() < 1e-9,
            "{}",
            t.insert.area()
        );
    }

    #[test]
    fn ball_and_bull_ends_are_rounded_by_their_radii() {
        let (t, _, _) = build(&spec("ball", Live::Radial)).unwrap();
        // A half disc of r5 and a 17 × 10 rectangle (the arcs drawn as 12 tangents a quarter:
        // 2 × 12 × 25 (tan 3.75° − 3.75° in radians) = 0.055 mm² over the half disc, never
        // under it).
        let want = std::f64::consts::PI * 25.0 / 2.0 + 17.0 * 10.0;
        let a = t.insert.area();
        assert!(a >= want && a - want < 0.06, "{a}");
        let mut s = spec("bull", Live::Radial);
        s.corner_radius = Some(2.0);
        let (t, m, _) = build(&s).unwrap();
        assert_eq!(m.kind, MillKind::Bull { corner_radius: 2.0 });
        // Two corners of r2 off the rectangle: 2 × (4 − π) mm² less (the tangents hold 0.009 more).
        let want = 220.0 - 2.0 * (4.0 - std::f64::consts::PI);
        let a = t.insert.area();
        assert!(a >= want && a - want < 0.01, "{a}");
    }

    #[test]
    fn sizes_that_do_not_make_a_tool_are_refused_with_their_key() {
        type Change = Box<dyn Fn(&mut MillSpec)>;
        let cases: Vec<(Change, &str)> = vec![
            (Box::new(|s| s.diameter = 0.0), "diameter is 0"),
            (
                Box::new(|s| s.stick_out = 10.0),
                "stick_out 10 mm is shorter than the flutes",
            ),
            (
                Box::new(|s| s.holder_diameter = 8.0),
                "holder.diameter 8 mm is less than the shank",
            ),
            (
                Box::new(|s| s.kind = "bull".into()),
                "a bull end mill needs corner_radius",
            ),
            (
                Box::new(|s| {
                    s.kind = "bull".into();
                    s.corner_radius = Some(6.0)
                }),
                "corner_radius is 6",
            ),
            (
                Box::new(|s| s.corner_radius = Some(1.0)),
                "corner_radius is for a bull end mill only",
            ),
            (Box::new(|s| s.kind = "tap".into()), "a tap needs pitch"),
            (
                Box::new(|s| s.kind = "reamer".into()),
                "type \"reamer\" is not a milling tool",
            ),
            (Box::new(|s| s.flute_length = f64::NAN), "flute_length is NaN"),
            (
                Box::new(|s| {
                    s.kind = "drill".into();
                    s.point_angle = Some(20.0)
                }),
                "point_angle is 20",
            ),
        ];
        for (change, want) in cases {
            let mut s = spec("flat", Live::Radial);
            change(&mut s);
            let e = build(&s).unwrap_err();
            assert!(e.contains(want), "{e} (want {want})");
        }
    }
}
