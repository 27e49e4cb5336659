//! A `[[tools]]` entry's catalogue forms, read the same way in machine files and jobs: an insert
//! or holder given by its ISO designation or by its outline ([`Shape`]), a drill by its sizes
//! ([`RawDrill`]), and the tool built from them ([`build`]) with the cutter it names
//! ([`cutter`]). Errors name the file, line, column and key through the file's [`Cx`].

use schemars::JsonSchema;
use serde::de::{Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

use super::load::{Cx, MachineError, Num, Point};
use super::MAX_OUTLINE_POINTS;
use crate::geom::{Polygon, P2};
use crate::tooling::{self, BuiltTool, CatalogueSpec, Cutter, DrillSpec};

/// An insert or holder as written: a catalogue designation or an outline.
pub(crate) enum Shape {
    Name(String),
    Outline(Vec<Point>),
}

/// The schema of [`Shape`].
#[derive(JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub(crate) enum ShapeSchema {
    /// An ISO designation: `"CNMG 120408"`, `"PCLNR 2525M12"`.
    Name(String),
    /// An outline relative to the programmed point, `[[x, z], …]`.
    Outline(Vec<[f64; 2]>),
}

impl<'de> Deserialize<'de> for Shape {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Shape, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Shape;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a catalogue designation (a string) or an outline [[x, z], ...]")
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Shape, E> {
                Ok(Shape::Name(v.to_string()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Shape, A::Error> {
                let mut pts = Vec::new();
                while let Some(p) = seq.next_element::<Point>()? {
                    if pts.len() > MAX_OUTLINE_POINTS {
                        return Err(serde::de::Error::custom(format!(
                            "too many points; an outline may have at most {MAX_OUTLINE_POINTS}"
                        )));
                    }
                    pts.push(p);
                }
                Ok(Shape::Outline(pts))
            }
        }
        d.deserialize_any(V)
    }
}

// `drill = { diameter, length, point_angle }` as written (no doc comment: the schemas show none).
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { diameter, length, point_angle }")]
pub(crate) struct RawDrill {
    #[schemars(with = "f64")]
    diameter: Num,
    #[schemars(with = "f64")]
    length: Num,
    #[schemars(with = "Option<f64>")]
    point_angle: Option<Num>,
}

/// An insert or holder, validated: an outline, or a designation for [`build`] to read.
pub(crate) enum Geom {
    Outline(Polygon),
    Name(String),
}

impl Shape {
    /// The outline's points (an outline) or None (a designation).
    pub(crate) fn points(&self) -> Option<&[Point]> {
        match self {
            Shape::Outline(pts) => Some(pts),
            Shape::Name(_) => None,
        }
    }
}

/// `key` (`tools[2].insert`) validated: a designation that is not blank, or a valid outline.
pub(crate) fn geom(cx: &Cx<'_>, key: &str, v: &Spanned<Shape>) -> Result<Geom, MachineError> {
    match v.get_ref() {
        Shape::Name(s) if s.trim().is_empty() => Err(cx.err(v.span(), key, "the designation is empty")),
        Shape::Name(s) => Ok(Geom::Name(s.trim().to_string())),
        Shape::Outline(pts) => Ok(Geom::Outline(cx.outline(key, &Spanned::new(v.span(), pts.clone()))?)),
    }
}

/// `key` (`tools[2].drill`) validated: its sizes, each under its own key.
pub(crate) fn drill(cx: &Cx<'_>, key: &str, d: &RawDrill) -> Result<DrillSpec, MachineError> {
    Ok(DrillSpec {
        diameter: cx.length(&format!("{key}.diameter"), &d.diameter)?,
        length: cx.length(&format!("{key}.length"), &d.length)?,
        point_angle: match &d.point_angle {
            None => None,
            Some(a) => Some(cx.within(&format!("{key}.point_angle"), a, (1.0, 180.0), "degrees")?),
        },
    })
}

/// The tool an entry's catalogue forms build, if it gives any: the designations of `insert` and
/// `holder`, and `drill` where an outline does not stand for the insert or the holder. Each of
/// the three comes with where it was written (`P`: the file's place of the key); an error is
/// placed at the key [`tooling::build`] blames, else at the first of them given.
pub(crate) fn build<P: Clone>(
    insert: Option<(&Geom, &P)>,
    holder: Option<(&Geom, &P)>,
    drill: Option<(&DrillSpec, &P)>,
) -> Result<Option<BuiltTool>, (P, String)> {
    let name_of = |g: Option<(&Geom, &P)>| match g {
        Some((Geom::Name(s), _)) => Some(s.clone()),
        _ => None,
    };
    let spec = CatalogueSpec {
        insert: name_of(insert),
        holder: name_of(holder),
        drill: match (drill, insert, holder) {
            (Some((d, _)), None, _) | (Some((d, _)), _, None) => Some(d.clone()),
            _ => None,
        },
    };
    if spec.insert.is_none() && spec.holder.is_none() && spec.drill.is_none() {
        return Ok(None);
    }
    tooling::build(&spec).map(Some).map_err(|e| {
        let blamed = match e.key {
            "insert" => insert.map(|g| g.1),
            "holder" => holder.map(|g| g.1),
            _ => drill.map(|g| g.1),
        };
        let at = blamed
            .or(insert.map(|g| g.1))
            .or(holder.map(|g| g.1))
            .or(drill.map(|g| g.1));
        // One of the three is given, or the spec would be empty.
        let at = at.cloned().expect("a catalogue form was given");
        (
            at,
            format!("cannot build the tool from its catalogue description: {}", e.message),
        )
    })
}

/// A value with where it was written, by reference (the form [`build`] takes).
pub(crate) fn given<T, P>(v: &Option<(T, P)>) -> Option<(&T, &P)> {
    v.as_ref().map(|(v, at)| (v, at))
}

/// What a tool's cutting part is: the built tool's when it is not an insert (a drill from
/// `drill = { … }`, a mill or tap), else what its name says.
pub(crate) fn cutter(built: Option<&BuiltTool>, name: &str) -> Cutter {
    built
        .map(|b| b.cutter)
        .filter(|c| *c != Cutter::Insert)
        .unwrap_or_else(|| Cutter::from_name(name))
}

// `geometry_offset = { x, z }` as written (no doc comment: the schemas show none). A table
// only: `[x, z]` would read as a `tip` does, with another meaning.
#[derive(JsonSchema)]
pub(crate) struct RawGeometryOffset {
    /// X on diameter, as the control's geometry offset page shows it (mm).
    #[schemars(with = "f64")]
    x: Num,
    /// Z, as the page shows it (mm).
    #[schemars(with = "f64")]
    z: Num,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct GeometryOffsetKeys {
    x: Num,
    z: Num,
}

impl<'de> Deserialize<'de> for RawGeometryOffset {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<RawGeometryOffset, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = RawGeometryOffset;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table { x, z } (X on diameter and Z, as the geometry offset page shows them)")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<RawGeometryOffset, A::Error> {
                let k = GeometryOffsetKeys::deserialize(serde::de::value::MapAccessDeserializer::new(map))?;
                Ok(RawGeometryOffset { x: k.x, z: k.z })
            }
        }
        d.deserialize_map(V)
    }
}

/// A tool's geometry offset as the control's geometry offset page shows it, in mm: `x` on
/// diameter, measured to the spindle axis; `z` the tool's length (docs/machine.md, "`tip` from
/// the control's geometry page").
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GeometryOffset {
    pub x: f64,
    pub z: f64,
}

impl GeometryOffset {
    /// The tool's `tip` (its programmed point from the turret reference point, `x` a radius) on
    /// a machine whose machine zero is `machine_zero`: `[-(machine_zero.x + X/2), -Z]`.
    pub fn tip(&self, machine_zero: P2) -> P2 {
        P2::new(-(machine_zero.x + self.x / 2.0), -self.z)
    }

    /// `X-480 Z12`, as the page shows it.
    pub fn show(&self) -> String {
        format!("X{} Z{}", super::num(self.x), super::num(self.z))
    }
}

/// How an entry places its tool: its `tip`, or its `geometry_offset` (turned into a tip with the
/// machine's machine zero, which a job only knows when it is applied).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Placing {
    Tip(P2),
    Offset(GeometryOffset),
}

impl Placing {
    /// The tip on a machine whose machine zero is `machine_zero`.
    pub(crate) fn tip(&self, machine_zero: P2) -> P2 {
        match self {
            Placing::Tip(t) => *t,
            Placing::Offset(g) => g.tip(machine_zero),
        }
    }
}

/// An entry's `tip` or `geometry_offset` (`key`: the entry's key, `tools[2]`), validated: one of
/// the two at most (None: neither given), each value finite and within the coordinate range.
pub(crate) fn placing(
    cx: &Cx<'_>,
    key: &str,
    tip: Option<&Point>,
    offset: Option<&Spanned<RawGeometryOffset>>,
) -> Result<Option<Placing>, MachineError> {
    match (tip, offset) {
        (Some(_), Some(g)) => Err(cx.err(
            g.span(),
            format!("{key}.geometry_offset"),
            "give a tool's `tip` or its `geometry_offset`, not both (geometry_offset is the control's page, X on diameter; tip the programmed point from the turret reference point)",
        )),
        (Some(t), None) => Ok(Some(Placing::Tip(cx.point(&format!("{key}.tip"), t)?))),
        (None, Some(g)) => {
            let r = g.get_ref();
            let x = cx.coord(&format!("{key}.geometry_offset.x"), &r.x)?;
            let z = cx.coord(&format!("{key}.geometry_offset.z"), &r.z)?;
            Ok(Some(Placing::Offset(GeometryOffset { x, z })))
        }
        (None, None) => Ok(None),
    }
}
