//! The machine file's `[kinematics]` section → [`Kinematics`] (every key: `docs/machine.md`,
//! "The kinematic machine": `docs/turn-mill.md`).
//!
//! Read after the 2D sections are valid, with the machine loader's [`Cx`]: errors are
//! `file:line:col: key: message` with keys such as `kinematics.components[3].parent`.
//!
//! - `[[kinematics.axes]]`: `name`, `letter` (one of X Z Y C B A, each at most once; X and Z are
//!   required, linear along +x and +z, with the travel, rapid and zero — `axes.home` — of the 2D
//!   `[axes]`; Y is linear), `type` (`"linear"` | `"rotary"`), `direction` `[x, y, z]` (any
//!   length but zero), `origin` (rotary: a point on the axis line; default `[0, 0, 0]`), `zero`
//!   (value at program start; default 0, or home for X and Z), `travel` `[min, max]` (required for
//!   a linear axis; a rotary axis without it turns without limit), `rapid` (mm/min or °/min).
//! - `[[kinematics.components]]`: `name`, `parent` (a component's name; none: fixed to the
//!   machine frame), `mount` (`{ translate = [x, y, z], rotate = [ax, ay, az] }`: the rotation in
//!   degrees about the parent's fixed x, then y, then z axes — R = Rz·Ry·Rx —, then the
//!   translation), `axis` (an axis name; one axis may drive several components), `geometry`
//!   (exactly one of `stl = "file.stl"`, `revolved = [[r, z], …]` or `"chuck"` / `"tailstock"`
//!   (the 2D outline), `extruded = [[x, z], …]` with `width`, `box = { min, max }`,
//!   `cylinder = { radius, z0, z1 }`; none: a frame only), `role` (`structure` (default),
//!   `chuck`, `tailstock`, `holder`, `cutter`), `station` (a tool's turret station).
//!   Components may be listed in any order; they are stored parents first.
//! - `never_touch = [[a, b], …]`: pairs of component names, or `"role:NAME"` (every component of
//!   that role) or `"*"` (every component). A pattern never pairs a component with itself, an
//!   ancestor or a descendant (parts fixed to each other touch by design); two names given
//!   explicitly must be different components.
//!
//! STL paths are read through the caller's resolver (relative to the machine file in the binary):
//! the library does no I/O. Caps: [`MAX_AXES`] axes, [`MAX_COMPONENTS`] components,
//! [`MAX_STL_TRIANGLES`] triangles over all STL files, [`MAX_NEVER_TOUCH`] pairs after expansion.

use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

use nalgebra::{Point3, Translation3, Unit, UnitQuaternion, Vector3};
use schemars::JsonSchema;
use serde::Deserialize;
use toml::Spanned;

use super::{Axis, AxisKind, Component, Geometry, Iso, Kinematics, Role};
use crate::geom::P2;
use crate::machine::{Cx, Machine, MachineError, Num, Outline, MAX_COORD_MM, MAX_OUTLINE_POINTS};

use super::shape::MAX_SHAPE_POINTS;
use super::stl::{read_stl, MAX_STL_TRIANGLES};

/// At most this many axes.
pub const MAX_AXES: usize = 16;
/// At most this many components.
pub const MAX_COMPONENTS: usize = 256;
/// At most this many `never_touch` pairs after wildcards are expanded.
pub const MAX_NEVER_TOUCH: usize = 10_000;
/// Rotary axis travel and rates: degrees within ±this, °/min up to `RAPID_RANGE`.
pub const MAX_DEGREES: f64 = 1e6;
/// The letters a kinematic axis may have.
pub const LETTERS: [char; 6] = ['X', 'Z', 'Y', 'C', 'B', 'A'];

/// Reads a file an STL geometry names (relative to the machine file): its bytes, or why not.
pub type Resolve<'r> = &'r dyn Fn(&str) -> Result<Vec<u8>, String>;

type P3 = Spanned<Vec<f64>>;
/// `never_touch` as written: pairs of names, each with its span.
type RawPairs = Spanned<Vec<Spanned<Vec<Spanned<String>>>>>;

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(crate) struct RawKinematics {
    #[schemars(with = "Vec<RawKinAxis>")]
    axes: Spanned<Vec<Spanned<RawKinAxis>>>,
    #[schemars(with = "Vec<RawComponent>")]
    components: Spanned<Vec<Spanned<RawComponent>>>,
    /// Pairs of component names (or `"role:NAME"`, `"*"`) that must never touch.
    #[schemars(with = "Option<Vec<[String; 2]>>")]
    never_touch: Option<RawPairs>,
}

#[derive(Deserialize, JsonSchema, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase")]
enum RawAxisType {
    Linear,
    Rotary,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawKinAxis {
    #[schemars(with = "String")]
    name: Spanned<String>,
    /// X, Z, Y, C, B or A.
    #[schemars(with = "String")]
    letter: Spanned<String>,
    #[serde(rename = "type")]
    kind: RawAxisType,
    #[schemars(with = "[f64; 3]")]
    direction: P3,
    #[schemars(with = "Option<[f64; 3]>")]
    origin: Option<P3>,
    #[schemars(with = "Option<f64>")]
    zero: Option<Num>,
    #[schemars(with = "Option<[f64; 2]>")]
    travel: Option<Spanned<Vec<f64>>>,
    #[schemars(with = "f64")]
    rapid: Num,
    /// The program path whose lines drive the axis (1 to the machine's number of paths;
    /// default 1): its letter is that path's, and its X and Z agree with that path's 2D axes.
    #[schemars(with = "Option<u32>")]
    path: Option<Spanned<u32>>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawMount {
    #[schemars(with = "Option<[f64; 3]>")]
    translate: Option<P3>,
    /// Degrees about the parent's x, then y, then z.
    #[schemars(with = "Option<[f64; 3]>")]
    rotate: Option<P3>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(untagged, expecting = "an outline [[r, z], …] or \"chuck\" or \"tailstock\"")]
enum RawRevolved {
    Named(String),
    Outline(Vec<Vec<f64>>),
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { min, max }")]
struct RawBox {
    #[schemars(with = "[f64; 3]")]
    min: P3,
    #[schemars(with = "[f64; 3]")]
    max: P3,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { radius, z0, z1, end }")]
struct RawCylinder {
    #[schemars(with = "f64")]
    radius: Num,
    #[schemars(with = "f64")]
    z0: Num,
    #[schemars(with = "f64")]
    z1: Num,
    /// A milling cutter's end at `z0` (its point): "flat" (the default), "ball",
    /// `{ corner_radius = r }` (a bull nose) or `{ point_angle = deg }` (a drill's cone).
    #[schemars(with = "Option<RawEnd>")]
    end: Option<Spanned<RawEnd>>,
}

/// A cutter's end (`cylinder.end`).
#[derive(Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "\"flat\", \"ball\", { corner_radius = r } or { point_angle = degrees }"
)]
enum RawEnd {
    Named(String),
    Corner(RawCorner),
    Point(RawPoint),
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawCorner {
    /// A bull nose's corner radius (mm): above 0, at most the cylinder's radius.
    corner_radius: f64,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawPoint {
    /// A drill's included point angle (degrees): between 0 and 180.
    point_angle: f64,
}

#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table with one of stl, revolved, extruded, box, cylinder"
)]
struct RawGeometry {
    #[schemars(with = "Option<String>")]
    stl: Option<Spanned<String>>,
    #[schemars(with = "Option<RawRevolved>")]
    revolved: Option<Spanned<RawRevolved>>,
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    extruded: Option<Outline>,
    /// The extrusion's width along y (centred on y = 0), with `extruded`.
    #[schemars(with = "Option<f64>")]
    width: Option<Num>,
    #[serde(rename = "box")]
    cuboid: Option<RawBox>,
    cylinder: Option<RawCylinder>,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum RawRole {
    Structure,
    Chuck,
    Tailstock,
    Holder,
    Cutter,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawComponent {
    #[schemars(with = "String")]
    name: Spanned<String>,
    #[schemars(with = "Option<String>")]
    parent: Option<Spanned<String>>,
    mount: Option<RawMount>,
    #[schemars(with = "Option<String>")]
    axis: Option<Spanned<String>>,
    #[schemars(with = "Option<RawGeometry>")]
    geometry: Option<Spanned<RawGeometry>>,
    role: Option<RawRole>,
    #[schemars(with = "Option<u32>")]
    station: Option<Spanned<u32>>,
    /// What findings and pictures call the component ("sub-spindle's chuck"); without it the
    /// name says it ("main_chuck": "main chuck"; a tool's part by its station: "T08 drill").
    #[schemars(with = "Option<String>")]
    label: Option<Spanned<String>>,
}

/// Most characters of a component's `label`.
const MAX_LABEL_CHARS: usize = 60;

/// A component's `label`, trimmed: a few words on one line.
fn label(text: &str) -> Result<String, String> {
    let l = text.trim();
    if l.is_empty() {
        Err("must not be blank".into())
    } else if l.chars().count() > MAX_LABEL_CHARS {
        Err(format!("a label is a few words: at most {MAX_LABEL_CHARS} characters"))
    } else if l.chars().any(char::is_control) {
        Err("a label is one line: no tabs, line breaks or other control characters".into())
    } else {
        Ok(l.to_string())
    }
}

fn show(x: f64) -> String {
    format!("{x}")
}

/// A 3-vector within ±[`MAX_COORD_MM`].
fn vec3(cx: &Cx<'_>, key: &str, p: &P3) -> Result<Vector3<f64>, MachineError> {
    match p.get_ref().as_slice() {
        &[x, y, z] if [x, y, z].iter().all(|v| v.abs() <= MAX_COORD_MM) => Ok(Vector3::new(x, y, z)),
        &[x, y, z] => Err(cx.err(
            p.span(),
            key,
            format!(
                "[{}, {}, {}] is out of range: each number must be finite and from {} to {}",
                show(x),
                show(y),
                show(z),
                show(-MAX_COORD_MM),
                show(MAX_COORD_MM)
            ),
        )),
        v => Err(cx.err(
            p.span(),
            key,
            format!("expected 3 numbers [x, y, z], found {}", v.len()),
        )),
    }
}

/// `[kinematics]` of a machine whose 2D sections are valid → the tree.
pub(crate) fn kinematics(
    cx: &Cx<'_>,
    raw: &RawKinematics,
    machine: &Machine,
    resolve: Resolve<'_>,
) -> Result<Kinematics, MachineError> {
    let axes = raw.axes.get_ref();
    let comps = raw.components.get_ref();
    if axes.len() > MAX_AXES {
        return Err(cx.err(
            axes[MAX_AXES].span(),
            format!("kinematics.axes[{MAX_AXES}]"),
            format!("too many axes: {}; a machine may have at most {MAX_AXES}", axes.len()),
        ));
    }
    if comps.len() > MAX_COMPONENTS {
        return Err(cx.err(
            comps[MAX_COMPONENTS].span(),
            format!("kinematics.components[{MAX_COMPONENTS}]"),
            format!(
                "too many components: {}; a machine may have at most {MAX_COMPONENTS}",
                comps.len()
            ),
        ));
    }
    let mut errors: Vec<MachineError> = Vec::new();

    // Axes.
    let mut out_axes: Vec<Axis> = Vec::new();
    let mut axis_ids: HashMap<String, usize> = HashMap::new();
    let mut letters: HashMap<(u32, char), usize> = HashMap::new();
    for (i, a) in axes.iter().enumerate() {
        match axis(cx, i, a.get_ref(), machine) {
            Ok(ax) => {
                let r = a.get_ref();
                if let Some(j) = axis_ids.get(&ax.name) {
                    errors.push(cx.err(
                        r.name.span(),
                        format!("kinematics.axes[{i}].name"),
                        format!("axis {:?} is already defined by kinematics.axes[{j}]", ax.name),
                    ));
                    continue;
                }
                if let Some(j) = letters.get(&(ax.path, ax.letter)) {
                    errors.push(cx.err(
                        r.letter.span(),
                        format!("kinematics.axes[{i}].letter"),
                        format!(
                            "letter {} already drives kinematics.axes[{j}] ({:?}): a letter drives one axis of a path",
                            ax.letter, out_axes[*j].name
                        ),
                    ));
                    continue;
                }
                letters.insert((ax.path, ax.letter), out_axes.len());
                axis_ids.insert(ax.name.clone(), out_axes.len());
                out_axes.push(ax);
            }
            Err(e) => errors.push(e),
        }
    }
    for p in 1..=machine.paths.count() as u32 {
        for l in ['X', 'Z'] {
            if !letters.contains_key(&(p, l)) && errors.is_empty() {
                let what = if p == 1 {
                    format!("no axis has letter {l}: a kinematic machine has the X and Z axes of the 2D [axes]")
                } else {
                    format!("no axis of path {p} has letter {l}: each path's carrier has the X and Z axes of its [[paths]] table (path = {p})")
                };
                errors.push(cx.err(raw.axes.span(), "kinematics.axes", what));
            }
        }
    }

    // Components: names first, so that parents may come in any order.
    let mut names: HashMap<&str, usize> = HashMap::new();
    for (i, c) in comps.iter().enumerate() {
        let c = c.get_ref();
        let n = c.name.get_ref().trim();
        if n.is_empty() || n == "*" || n.starts_with("role:") {
            errors.push(cx.err(
                c.name.span(),
                format!("kinematics.components[{i}].name"),
                "a component's name must not be blank, `*` or start with `role:`",
            ));
        } else if let Some(j) = names.get(n) {
            errors.push(cx.err(
                c.name.span(),
                format!("kinematics.components[{i}].name"),
                format!("component {n:?} is already defined by kinematics.components[{j}]"),
            ));
        } else {
            names.insert(n, i);
        }
    }
    let mut parent: Vec<Option<usize>> = vec![None; comps.len()];
    for (i, c) in comps.iter().enumerate() {
        if let Some(p) = &c.get_ref().parent {
            match names.get(p.get_ref().trim()) {
                Some(&j) if j == i => errors.push(cx.err(
                    p.span(),
                    format!("kinematics.components[{i}].parent"),
                    "a component cannot be its own parent",
                )),
                Some(&j) => parent[i] = Some(j),
                None => errors.push(cx.err(
                    p.span(),
                    format!("kinematics.components[{i}].parent"),
                    format!("no component is named {:?}", p.get_ref()),
                )),
            }
        }
    }
    // Parents first (a depth-first order); a cycle is an error at its first member in the file.
    let mut order: Vec<usize> = Vec::with_capacity(comps.len());
    let mut state = vec![0u8; comps.len()]; // 0 new, 1 on the path, 2 placed
    for start in 0..comps.len() {
        let mut path = Vec::new();
        let mut c = start;
        loop {
            match state[c] {
                2 => break,
                1 => {
                    let from = path.iter().position(|&k| k == c).unwrap_or(0);
                    let cycle = &path[from..];
                    let first = cycle.iter().copied().min().unwrap_or(c);
                    let r = comps[first].get_ref();
                    let at = r.parent.as_ref().map_or(r.name.span(), |p| p.span());
                    let names: Vec<String> = path
                        .iter()
                        .map(|&k: &usize| comps[k].get_ref().name.get_ref().clone())
                        .collect();
                    errors.push(cx.err(
                        at,
                        format!("kinematics.components[{first}].parent"),
                        format!("the parents form a cycle: {}", names.join(" → ")),
                    ));
                    for &k in &path {
                        state[k] = 2;
                        parent[k] = None;
                    }
                    path.clear();
                    break;
                }
                _ => {
                    state[c] = 1;
                    path.push(c);
                    match parent[c] {
                        Some(p) => c = p,
                        None => break,
                    }
                }
            }
        }
        for &k in path.iter().rev() {
            state[k] = 2;
            order.push(k);
        }
    }
    let mut new_id = vec![0usize; comps.len()];
    for (n, &i) in order.iter().enumerate() {
        new_id[i] = n;
    }

    let mut triangles = 0usize;
    let mut out_comps: Vec<Option<Component>> = vec![None; comps.len()];
    for (i, c) in comps.iter().enumerate() {
        let r = c.get_ref();
        let key = |k: &str| format!("kinematics.components[{i}].{k}");
        let mount = match &r.mount {
            None => Some(Iso::identity()),
            Some(m) => {
                let t = m.translate.as_ref().map(|t| vec3(cx, &key("mount.translate"), t));
                let a = m.rotate.as_ref().map(|t| vec3(cx, &key("mount.rotate"), t));
                match (t.transpose(), a.transpose()) {
                    (Ok(t), Ok(a)) => {
                        let t = t.unwrap_or_else(Vector3::zeros);
                        let a = a.unwrap_or_else(Vector3::zeros);
                        let rot =
                            UnitQuaternion::from_euler_angles(a.x.to_radians(), a.y.to_radians(), a.z.to_radians());
                        Some(Iso::from_parts(Translation3::from(t), rot))
                    }
                    (Err(e), _) | (_, Err(e)) => {
                        errors.push(e);
                        None
                    }
                }
            }
        };
        let axis = match &r.axis {
            None => Some(None),
            Some(a) => match axis_ids.get(a.get_ref().trim()) {
                Some(&id) => Some(Some(id)),
                None => {
                    errors.push(cx.err(a.span(), key("axis"), format!("no axis is named {:?}", a.get_ref())));
                    None
                }
            },
        };
        let role = match r.role.unwrap_or(RawRole::Structure) {
            RawRole::Structure => Role::Structure,
            RawRole::Chuck => Role::Chuck,
            RawRole::Tailstock => Role::Tailstock,
            RawRole::Holder => Role::Holder,
            RawRole::Cutter => Role::Cutter,
        };
        let station = match &r.station {
            None => Some(None),
            // The station's own turret is known once the tree is (`stations_on_their_paths`).
            Some(s) if machine.paths.count() > 1 && *s.get_ref() >= 1 => Some(Some(*s.get_ref())),
            Some(s) if (1..=machine.turret.stations).contains(s.get_ref()) => Some(Some(*s.get_ref())),
            Some(s) => {
                errors.push(cx.err(
                    s.span(),
                    key("station"),
                    format!(
                        "station {} does not exist: the turret has stations 1 to {}",
                        s.get_ref(),
                        machine.turret.stations
                    ),
                ));
                None
            }
        };
        let geometry = match &r.geometry {
            None => Some(None),
            Some(g) => match geometry(cx, &key("geometry"), g, machine, resolve, &mut triangles) {
                Ok(g) => Some(Some(g)),
                Err(e) => {
                    errors.push(e);
                    None
                }
            },
        };
        let label = match &r.label {
            None => Some(None),
            Some(l) => match label(l.get_ref()) {
                Ok(l) => Some(Some(l)),
                Err(why) => {
                    errors.push(cx.err(l.span(), key("label"), why));
                    None
                }
            },
        };
        if let (Some(mount), Some(axis), Some(station), Some(geometry), Some(label)) =
            (mount, axis, station, geometry, label)
        {
            out_comps[i] = Some(Component {
                name: r.name.get_ref().trim().to_string(),
                parent: parent[i].map(|p| new_id[p]),
                mount,
                axis,
                geometry,
                role,
                station,
                label,
            });
        }
    }

    if let Some(e) = MachineError::gather(errors) {
        return Err(e);
    }
    let mut components = Vec::with_capacity(comps.len());
    for &i in &order {
        match out_comps[i].take() {
            Some(c) => components.push(c),
            None => return Err(cx.err(0..0, "kinematics", "invalid component")),
        }
    }
    let mut k = Kinematics {
        axes: out_axes,
        components,
        never_touch: Vec::new(),
    };
    stations_on_their_paths(cx, comps, &new_id, &k, machine)?;
    if let Some(nt) = &raw.never_touch {
        k.never_touch = never_touch(cx, nt, &k)?;
    }
    Ok(k)
}

/// On a machine with several paths, each tool's `station` is one of the turret of the path whose
/// axes carry it; a tool carried by two paths' axes at once has no turret.
fn stations_on_their_paths(
    cx: &Cx<'_>,
    comps: &[Spanned<RawComponent>],
    new_id: &[usize],
    k: &Kinematics,
    machine: &Machine,
) -> Result<(), MachineError> {
    if machine.paths.count() < 2 {
        return Ok(());
    }
    let masks = k.path_masks();
    for (i, raw) in comps.iter().enumerate() {
        let Some(s) = &raw.get_ref().station else { continue };
        let mask = masks[new_id[i]];
        let key = format!("kinematics.components[{i}].station");
        let path = match mask.count_ones() {
            0 => 1,
            1 => mask.trailing_zeros(),
            _ => {
                return Err(cx.err(
                    s.span(),
                    key,
                    "a tool moved by the axes of two paths is on no one carrier: hang it below one path's axes",
                ))
            }
        };
        let stations = if path == 1 {
            machine.turret.stations
        } else {
            machine
                .paths
                .carriers
                .iter()
                .find(|c| c.path == path)
                .map_or(0, |c| c.turret.stations)
        };
        if !(1..=stations).contains(s.get_ref()) {
            return Err(cx.err(
                s.span(),
                key,
                format!(
                    "station {} does not exist: the turret of path {path}, whose axes carry this tool, has stations 1 to {stations}",
                    s.get_ref()
                ),
            ));
        }
    }
    Ok(())
}

fn axis(cx: &Cx<'_>, i: usize, a: &RawKinAxis, machine: &Machine) -> Result<Axis, MachineError> {
    let key = |k: &str| format!("kinematics.axes[{i}].{k}");
    let name = a.name.get_ref().trim().to_string();
    if name.is_empty() {
        return Err(cx.err(a.name.span(), key("name"), "must not be blank"));
    }
    let letter = match a.letter.get_ref().trim() {
        l if l.len() == 1 && LETTERS.contains(&l.chars().next().unwrap_or(' ').to_ascii_uppercase()) => {
            l.chars().next().unwrap_or(' ').to_ascii_uppercase()
        }
        l => {
            return Err(cx.err(
                a.letter.span(),
                key("letter"),
                format!("{l:?} is not an axis letter: give one of X, Z, Y, C, B, A"),
            ))
        }
    };
    let dir = vec3(cx, &key("direction"), &a.direction)?;
    let Some(dir) = Unit::try_new(dir, 1e-9) else {
        return Err(cx.err(a.direction.span(), key("direction"), "the direction must not be zero"));
    };
    let origin = match &a.origin {
        None => Point3::origin(),
        Some(o) if a.kind == RawAxisType::Rotary => Point3::from(vec3(cx, &key("origin"), o)?),
        Some(o) => return Err(cx.err(o.span(), key("origin"), "only a rotary axis has an origin")),
    };
    let linear = a.kind == RawAxisType::Linear;
    let unit = if linear { "mm" } else { "degrees" };
    let rapid = cx.within(
        &key("rapid"),
        &a.rapid,
        crate::machine::RAPID_RANGE,
        if linear { "mm/min" } else { "degrees/min" },
    )?;
    let limit = if linear { MAX_COORD_MM } else { MAX_DEGREES };
    let travel = match &a.travel {
        None if linear => {
            return Err(cx.err(
                a.name.span(),
                key("travel"),
                "missing required key `travel`: a linear axis has [min, max]",
            ))
        }
        None => (f64::NEG_INFINITY, f64::INFINITY),
        Some(t) => match t.get_ref().as_slice() {
            &[lo, hi] if lo.abs() <= limit && hi.abs() <= limit && lo < hi => (lo, hi),
            &[lo, hi] if lo.abs() <= limit && hi.abs() <= limit => {
                return Err(cx.err(
                    t.span(),
                    key("travel"),
                    format!("min = {} must be less than max = {}", show(lo), show(hi)),
                ))
            }
            &[lo, hi] => {
                return Err(cx.err(
                    t.span(),
                    key("travel"),
                    format!(
                        "[{}, {}] is out of range: from {} to {} {unit}",
                        show(lo),
                        show(hi),
                        show(-limit),
                        show(limit)
                    ),
                ))
            }
            v => {
                return Err(cx.err(
                    t.span(),
                    key("travel"),
                    format!("expected [min, max], found {} numbers", v.len()),
                ))
            }
        },
    };
    let paths = machine.paths.count() as u32;
    let path = match &a.path {
        None => 1,
        Some(p) if (1..=paths).contains(p.get_ref()) => *p.get_ref(),
        Some(p) => {
            return Err(cx.err(
                p.span(),
                key("path"),
                if paths == 1 {
                    format!(
                        "path {} does not exist: this machine has one path (no [[paths]])",
                        p.get_ref()
                    )
                } else {
                    format!(
                        "path {} does not exist: this machine has paths 1 to {paths}",
                        p.get_ref()
                    )
                },
            ))
        }
    };
    // The 2D axes this one must agree with: its path's.
    let (ax_x, ax_z, home, section) = match machine.paths.carriers.iter().find(|c| c.path == path) {
        Some(c) => (&c.x, &c.z, c.home, format!("paths[{}].axes", path - 2)),
        None => (&machine.x, &machine.z, machine.home, "axes".to_string()),
    };
    let twod = match letter {
        'X' => Some((ax_x, home.x, Vector3::x())),
        'Z' => Some((ax_z, home.y, Vector3::z())),
        _ => None,
    };
    if matches!(letter, 'X' | 'Z' | 'Y') && !linear {
        return Err(cx.err(
            a.letter.span(),
            key("type"),
            format!("axis {letter} is linear: give type = \"linear\""),
        ));
    }
    let zero = match &a.zero {
        Some(z) => cx.within(&key("zero"), z, (-limit, limit), unit)?,
        None => twod.map_or(0.0, |t| t.1),
    };
    if let Some((ax, home, want)) = twod {
        let l = letter.to_ascii_lowercase();
        if (dir.into_inner() - want).norm() > 1e-9 {
            return Err(cx.err(
                a.direction.span(),
                key("direction"),
                format!(
                    "axis {letter} moves along +{l} as the 2D axes do: direction = [{}]",
                    if l == 'x' { "1, 0, 0" } else { "0, 0, 1" }
                ),
            ));
        }
        if travel != (ax.min, ax.max) {
            let at = a.travel.as_ref().map_or(a.name.span(), |t| t.span());
            return Err(cx.err(
                at,
                key("travel"),
                format!(
                    "travel [{}, {}] differs from {section}.{l} ({} .. {}): the two must be the same",
                    show(travel.0),
                    show(travel.1),
                    show(ax.min),
                    show(ax.max)
                ),
            ));
        }
        if rapid != ax.rapid {
            return Err(cx.err(
                a.rapid.span(),
                key("rapid"),
                format!(
                    "rapid {} differs from {section}.{l}.rapid = {}",
                    show(rapid),
                    show(ax.rapid)
                ),
            ));
        }
        if zero != home {
            let at: Range<usize> = a.zero.as_ref().map_or(a.name.span(), |z| z.span());
            return Err(cx.err(
                at,
                key("zero"),
                format!(
                    "zero {} differs from home {l} = {} ({section}.home)",
                    show(zero),
                    show(home)
                ),
            ));
        }
    }
    if zero < travel.0 || zero > travel.1 {
        let at = a.zero.as_ref().map_or(a.name.span(), |z| z.span());
        return Err(cx.err(
            at,
            key("zero"),
            format!(
                "zero {} lies outside the travel {} .. {}",
                show(zero),
                show(travel.0),
                show(travel.1)
            ),
        ));
    }
    let kind = if linear {
        AxisKind::Linear { dir }
    } else {
        AxisKind::Rotary { origin, dir }
    };
    Ok(Axis {
        name,
        letter,
        kind,
        zero,
        travel,
        rapid,
        path,
    })
}

/// An outline of `[r, z]` or `[x, z]` points for a mesh: simple, at most [`MAX_SHAPE_POINTS`].
fn shape_outline(cx: &Cx<'_>, key: &str, o: &Outline) -> Result<Vec<P2>, MachineError> {
    let n = o.get_ref().len();
    if n > MAX_SHAPE_POINTS.min(MAX_OUTLINE_POINTS) {
        return Err(cx.err(
            o.span(),
            key,
            format!("too many points: {n}; a kinematic outline may have at most {MAX_SHAPE_POINTS}"),
        ));
    }
    Ok(cx.outline(key, o)?.points().to_vec())
}

fn geometry(
    cx: &Cx<'_>,
    key: &str,
    g: &Spanned<RawGeometry>,
    machine: &Machine,
    resolve: Resolve<'_>,
    triangles: &mut usize,
) -> Result<Geometry, MachineError> {
    let r = g.get_ref();
    let given = [
        r.stl.is_some(),
        r.revolved.is_some(),
        r.extruded.is_some(),
        r.cuboid.is_some(),
        r.cylinder.is_some(),
    ];
    let n = given.iter().filter(|&&b| b).count();
    if n != 1 {
        return Err(cx.err(
            g.span(),
            key,
            format!("give exactly one of stl, revolved, extruded, box, cylinder (found {n})"),
        ));
    }
    if let (Some(w), None) = (&r.width, &r.extruded) {
        return Err(cx.err(w.span(), format!("{key}.width"), "`width` goes with `extruded` only"));
    }
    if let Some(s) = &r.stl {
        let k = format!("{key}.stl");
        let bytes = resolve(s.get_ref())
            .map_err(|why| cx.err(s.span(), &k, format!("cannot read {:?}: {why}", s.get_ref())))?;
        let mesh = read_stl(&bytes, s.get_ref()).map_err(|e| cx.err(s.span(), &k, e.to_string()))?;
        *triangles += mesh.triangles.len();
        if *triangles > MAX_STL_TRIANGLES {
            return Err(cx.err(
                s.span(),
                &k,
                format!("too many triangles: the STL files up to this one have {triangles}; a machine may have at most {MAX_STL_TRIANGLES} in all"),
            ));
        }
        return Ok(Geometry::Mesh(Arc::new(mesh)));
    }
    if let Some(rv) = &r.revolved {
        let k = format!("{key}.revolved");
        let at = rv.span();
        let pts = match rv.get_ref() {
            RawRevolved::Named(n) => {
                let part = match n.as_str() {
                    "chuck" => machine.chuck.as_ref(),
                    "tailstock" => machine.tailstock.as_ref(),
                    other => {
                        return Err(cx.err(
                            at,
                            &k,
                            format!("{other:?}: a named outline is \"chuck\" or \"tailstock\""),
                        ))
                    }
                };
                match part {
                    Some(p) => p.points().to_vec(),
                    None => return Err(cx.err(at, &k, format!("the machine has no [{n}] outline to revolve"))),
                }
            }
            RawRevolved::Outline(o) => {
                // The points have the span of the whole value (an untagged value keeps no others).
                let o: Outline = Spanned::new(
                    at.clone(),
                    o.iter().map(|p| Spanned::new(at.clone(), p.clone())).collect(),
                );
                let pts = shape_outline(cx, &k, &o)?;
                if let Some(p) = pts.iter().find(|p| p.x < 0.0) {
                    return Err(cx.err(
                        at,
                        &k,
                        format!(
                            "a revolved outline is [r, z] with r ≥ 0; [{}, {}] has r < 0",
                            show(p.x),
                            show(p.y)
                        ),
                    ));
                }
                if pts.iter().all(|p| p.x <= 0.0) {
                    return Err(cx.err(at, &k, "the outline has no material off the axis"));
                }
                pts
            }
        };
        return Ok(Geometry::Revolved(pts));
    }
    if let Some(o) = &r.extruded {
        let k = format!("{key}.extruded");
        let pts = shape_outline(cx, &k, o)?;
        let Some(w) = &r.width else {
            return Err(cx.err(
                g.span(),
                format!("{key}.width"),
                "missing required key `width` (with `extruded`)",
            ));
        };
        let w = cx.length(&format!("{key}.width"), w)?;
        return Ok(Geometry::Extruded {
            outline: pts,
            half_width: w / 2.0,
        });
    }
    if let Some(b) = &r.cuboid {
        let lo = vec3(cx, &format!("{key}.box.min"), &b.min)?;
        let hi = vec3(cx, &format!("{key}.box.max"), &b.max)?;
        if !(lo.x < hi.x && lo.y < hi.y && lo.z < hi.z) {
            return Err(cx.err(
                b.min.span(),
                format!("{key}.box.min"),
                "min must be less than max in x, y and z",
            ));
        }
        return Ok(Geometry::Cuboid {
            min: Point3::from(lo),
            max: Point3::from(hi),
        });
    }
    if let Some(c) = &r.cylinder {
        let radius = cx.length(&format!("{key}.cylinder.radius"), &c.radius)?;
        let z0 = cx.coord(&format!("{key}.cylinder.z0"), &c.z0)?;
        let z1 = cx.coord(&format!("{key}.cylinder.z1"), &c.z1)?;
        if z0 >= z1 {
            return Err(cx.err(
                c.z0.span(),
                format!("{key}.cylinder.z0"),
                format!("z0 = {} must be less than z1 = {}", show(z0), show(z1)),
            ));
        }
        let Some(e) = &c.end else {
            return Ok(Geometry::Cylinder { radius, z0, z1 });
        };
        use crate::grid::CutterKind as K;
        let ek = format!("{key}.cylinder.end");
        let end = match e.get_ref() {
            RawEnd::Named(n) if n == "flat" => return Ok(Geometry::Cylinder { radius, z0, z1 }),
            RawEnd::Named(n) if n == "ball" => K::Ball,
            RawEnd::Named(n) => {
                return Err(cx.err(
                    e.span(),
                    &ek,
                    format!(
                        "{n:?}: an end is \"flat\", \"ball\", {{ corner_radius = r }} or {{ point_angle = degrees }}"
                    ),
                ))
            }
            RawEnd::Corner(b) => K::Bull {
                corner_radius: b.corner_radius,
            },
            RawEnd::Point(p) => K::Drill {
                point_angle_deg: p.point_angle,
            },
        };
        // The cutter's own checks (a corner radius within the radius, a point angle in
        // (0°, 180°), a ball's flutes at least its radius), said against the key.
        let sub = match end {
            K::Bull { .. } => ".corner_radius",
            K::Drill { .. } => ".point_angle",
            _ => "",
        };
        crate::grid::Cutter::new(end, 2.0 * radius, z1 - z0).map_err(|why| {
            let why = if why.starts_with("flute length") {
                format!("{why} (the flutes are z1 − z0 = {})", show(z1 - z0))
            } else {
                why
            };
            cx.err(e.span(), format!("{ek}{sub}"), why)
        })?;
        return Ok(Geometry::Cutter { end, radius, z0, z1 });
    }
    Err(cx.err(g.span(), key, "no geometry"))
}

fn never_touch(cx: &Cx<'_>, nt: &RawPairs, k: &Kinematics) -> Result<Vec<(usize, usize)>, MachineError> {
    let related = |a: usize, b: usize| a == b || k.is_ancestor(a, b) || k.is_ancestor(b, a);
    let mut pairs = std::collections::BTreeSet::new();
    for (i, p) in nt.get_ref().iter().enumerate() {
        let key = format!("never_touch[{i}]");
        let key = format!("kinematics.{key}");
        let [a, b] = p.get_ref().as_slice() else {
            return Err(cx.err(
                p.span(),
                &key,
                format!("a pair is [a, b]: expected 2 names, found {}", p.get_ref().len()),
            ));
        };
        let set = |s: &Spanned<String>, j: usize| -> Result<(Vec<usize>, bool), MachineError> {
            let n = s.get_ref().trim();
            let k2 = format!("{key}[{j}]");
            if n == "*" {
                return Ok(((0..k.components.len()).collect(), true));
            }
            if let Some(role) = n.strip_prefix("role:") {
                let role = match role {
                    "structure" => Role::Structure,
                    "chuck" => Role::Chuck,
                    "tailstock" => Role::Tailstock,
                    "holder" => Role::Holder,
                    "cutter" => Role::Cutter,
                    _ => {
                        return Err(cx.err(
                            s.span(),
                            k2,
                            format!("{role:?} is not a role: structure, chuck, tailstock, holder or cutter"),
                        ))
                    }
                };
                let ids: Vec<usize> = (0..k.components.len())
                    .filter(|&c| k.components[c].role == role)
                    .collect();
                return Ok((ids, true));
            }
            match k.components.iter().position(|c| c.name == n) {
                Some(c) => Ok((vec![c], false)),
                None => Err(cx.err(s.span(), k2, format!("no component is named {n:?}"))),
            }
        };
        let (sa, wa) = set(a, 0)?;
        let (sb, wb) = set(b, 1)?;
        if !wa && !wb && sa[0] == sb[0] {
            return Err(cx.err(p.span(), &key, "a component cannot be paired with itself"));
        }
        for &x in &sa {
            for &y in &sb {
                if (wa || wb) && related(x, y) || x == y {
                    continue;
                }
                pairs.insert((x.min(y), x.max(y)));
                if pairs.len() > MAX_NEVER_TOUCH {
                    return Err(cx.err(
                        p.span(),
                        &key,
                        format!("too many pairs: a machine may have at most {MAX_NEVER_TOUCH} never_touch pairs after wildcards are expanded"),
                    ));
                }
            }
        }
    }
    Ok(pairs.into_iter().collect())
}
