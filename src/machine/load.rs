//! TOML → [`Machine`], with errors that name the file, line, column and key.
//!
//! # The machine file
//!
//! The keys, their types, defaults and limits, with examples, are documented in
//! `docs/machine.md` (a test holds every key of the JSON Schema named there). Every table refuses
//! keys it does not know. Lengths are mm in the spindle frame; points are `[x, z]`. Integers are
//! accepted wherever a number is expected; `nan` and `inf` are refused everywhere.
//!
//! Every coordinate (axis limits, home, points of outlines, tips, `stock.front`,
//! `setup.program_zero_z`, `turret.axis`) lies within ±[`MAX_COORD_MM`] (100 m), and every length
//! (`stock.diameter`, `stock.length`) is at most that: beyond it squared distances lose their
//! precision and results would be silently wrong. A file is at most [`MAX_TEXT_BYTES`] (1 MiB),
//! checked before it is parsed. Values in range that look like unit mistakes (a rapid of 1 mm/min)
//! are accepted with a warning in [`Machine::warnings`].
//!
//! At home with the start station facing the spindle, the turret and every tool's holder and
//! insert must be clear of the chuck and the tailstock (posed as the checker poses them);
//! otherwise the error names the part: `turret.outline`, `tools[2].holder`.
//!
//! An outline is an array of `[x, z]` points: a simple polygon in either winding. Repeated and
//! collinear points are dropped; a self-intersecting or degenerate outline (fewer than three
//! points that are not all on one line) is an error. A dropped point where the outline turns back
//! on itself is a warning naming the key and the point: a spike (one point whose two edges fold
//! back on each other) or a zero-width feature (a run of dropped points along which the outline
//! turns back more than once, such as a zero-width slot or T). To keep validation fast on any input, an
//! outline may have at most [`MAX_OUTLINE_POINTS`] points and a file at most
//! [`MAX_TOTAL_OUTLINE_POINTS`] in all; these limits are checked before any outline is
//! normalised.
//!
//! # Errors
//!
//! One load reports every error of the file: a [`MachineError`] is the first in file order and
//! holds the others in [`MachineError::also`]; its `Display` gives one line per error. Some
//! problems still stop loading at once, because what would follow is noise: a file over
//! [`MAX_TEXT_BYTES`], a TOML syntax error, an unknown key, a missing key or a value of the wrong
//! type (the file does not have the shape the checks read), no `[[tools]]` or too many, and too
//! many outline points. A value that depends on a refused one is not checked (the tools'
//! stations when `turret.stations` is refused, `axes.home` when an axis is), and the setup checks
//! (parts clear at home, the stock in the chuck) run only on a file whose values are all valid.
//!
//! Each error carries the file name, the 1-based line
//! and column (in characters) and the dotted key path it is about: `axes.x.min`,
//! `tools[2].holder`, `chuck.outline[3]`. Array indices count from 0, so `tools[0]` is the first
//! `[[tools]]` table. A key that is missing is named as it would be written (`tools[1].station`)
//! and placed at the table that lacks it; a missing top-level table or key is placed at line 1,
//! column 1. A TOML syntax error is placed where the parser found it and named after the key
//! being read there (or the table it is in); an error outside every table is named
//! `(top level)`.

use std::ops::Range;

use schemars::JsonSchema;
use serde::Deserialize;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

use super::tool_entry::{self, RawDrill, RawGeometryOffset, Shape, ShapeSchema};
use super::{
    Axis, DecimalPoint, Dialect, GcodeSystem, MAction, Machine, McodeTable, RapidMode, Stock, Tool, Turret, MAX_MCODE,
    MCODE_ACTIONS,
};
use crate::geom::{p2, Polygon, PolygonError, P2};
use crate::source::LineIndex;

/// At most this many points in one outline.
pub const MAX_OUTLINE_POINTS: usize = 10_000;
/// At most this many outline points in one machine file, all outlines together.
pub const MAX_TOTAL_OUTLINE_POINTS: usize = 20_000;
/// At most this many turret stations.
pub const MAX_STATIONS: u32 = 64;
/// At most this many `[[tools]]` tables.
pub const MAX_TOOLS: usize = 256;

/// At most this many bytes in a machine file (1 MiB), checked before anything is parsed: a real
/// machine file is a few kilobytes.
pub const MAX_TEXT_BYTES: usize = 1 << 20;
/// Every coordinate and length of a machine file lies within ±this many mm (100 m).
pub const MAX_COORD_MM: f64 = 1e5;
/// Rapid rates, mm/min.
pub const RAPID_RANGE: (f64, f64) = (1.0, 1e6);
/// Spindle speed limit, rpm.
pub const MAX_RPM_RANGE: (f64, f64) = (1.0, 1e6);
/// Seconds per station indexed.
pub const INDEX_TIME_RANGE: (f64, f64) = (0.0, 60.0);
/// Tool nose radius, mm.
pub const NOSE_RADIUS_RANGE: (f64, f64) = (0.0, 100.0);
/// The tolerance the home-clearance test rounds tool noses with (the default `--tolerance`).
const HOME_CHECK_TOLERANCE: f64 = 0.01;

/// The key shown for an error that is about no table or key in particular.
pub const TOP_LEVEL: &str = "(top level)";

/// A machine file that cannot be used: where and why. The fields are the first problem in the
/// file; `also` holds the others found in the same pass, in file order. `Display` gives one
/// `file:line:col: key: message` line per problem.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineError {
    pub file: String,
    /// 1-based; 0 when unknown.
    pub line: u32,
    pub col: u32,
    /// Dotted TOML key path, e.g. `tools[2].holder`.
    pub key: String,
    pub message: String,
    /// The file's other problems, after this one in file order (each with an empty `also`).
    pub also: Vec<MachineError>,
}

impl MachineError {
    /// Every problem, this one first, in file order.
    pub fn all(&self) -> impl Iterator<Item = &MachineError> {
        std::iter::once(self).chain(self.also.iter())
    }

    /// Problems in any order → the first in file order, holding the rest. None when empty.
    pub(crate) fn gather(mut errors: Vec<MachineError>) -> Option<MachineError> {
        errors.sort_by_key(|e| (e.line, e.col));
        errors.dedup();
        let mut rest = errors.into_iter();
        let mut first = rest.next()?;
        first.also = rest.collect();
        Some(first)
    }
}

impl std::fmt::Display for MachineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for (i, e) in self.all().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{}:{}:{}: {}: {}", e.file, e.line, e.col, e.key, e.message)?;
        }
        Ok(())
    }
}

impl std::error::Error for MachineError {}

/// Parse and validate a machine description. `file` is only used in error messages.
///
/// A `[kinematics]` geometry that names an STL file is refused here (the library does no I/O):
/// load such a machine with [`from_toml_with`].
pub fn from_toml(text: &str, file: &str) -> Result<Machine, MachineError> {
    from_toml_with(text, file, &|_: &str| {
        Err("an STL file is read relative to the machine file, which this caller does not give (load the machine with `machine::from_toml_with` and a resolver; the binary does)".to_string())
    })
}

/// [`from_toml`], with `resolve` reading the files a `[kinematics]` geometry names (`stl =
/// "part.stl"`, relative to the machine file: the caller decides what that means).
pub fn from_toml_with(text: &str, file: &str, resolve: crate::kin::load::Resolve<'_>) -> Result<Machine, MachineError> {
    let cx = Cx::new(text, file);
    let raw: RawDoc = deserialize(&cx, "a machine file")?;
    validate(&cx, raw, resolve)
}

/// The root table of `cx`'s text: at most [`MAX_TEXT_BYTES`], TOML syntax errors placed and
/// named. `what` names the kind of file in the size error (`a machine file`).
fn root_table<'t>(cx: &Cx<'t>, what: &str) -> Result<Spanned<DeTable<'t>>, MachineError> {
    let text = cx.text;
    if text.len() > MAX_TEXT_BYTES {
        return Err(cx.err(
            0..0,
            TOP_LEVEL,
            format!(
                "the file is {} bytes; {what} may have at most {MAX_TEXT_BYTES} (1 MiB)",
                text.len()
            ),
        ));
    }
    let (root, errors) = DeTable::parse_recoverable(text);
    // The parser may report several errors, not in text order: the first in the text is the one
    // the others follow from.
    if let Some(e) = errors.iter().min_by_key(|e| e.span().map_or(usize::MAX, |s| s.start)) {
        let at = e.span().unwrap_or(0..0);
        let key = syntax_key(&root, &at, e.message(), text);
        return Err(cx.err(at, key, format!("TOML syntax error: {}", e.message())));
    }
    Ok(root)
}

/// A machine file's `[tool_numbers]`: `T<tool> = <station>` entries, `(tool, station)` by tool;
/// a bad key or a station past the turret's is an error (`stations` None: the turret's own count
/// was refused, already an error).
fn machine_tool_numbers(
    cx: &Cx<'_>,
    raw: Option<&std::collections::BTreeMap<Spanned<String>, Spanned<i64>>>,
    stations: Option<u32>,
) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (k, v) in raw.into_iter().flatten() {
        let name = k.get_ref().as_str();
        let key = format!("tool_numbers.{name}");
        let tool = name
            .strip_prefix(['T', 't'])
            .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|d| d.parse::<u32>().ok())
            .filter(|t| (1..=crate::tooling::tbl::MAX_NUMBER).contains(t));
        let Some(tool) = tool else {
            cx.push(cx.err(
                k.span(),
                key,
                format!(
                    "`{name}` is not a tool number: write T<tool> = <station> (T12 = 3, tools 1 to {})",
                    crate::tooling::tbl::MAX_NUMBER
                ),
            ));
            continue;
        };
        let station = *v.get_ref();
        let Some(stations) = stations else { continue };
        if !(1..=i64::from(stations)).contains(&station) {
            cx.push(cx.err(
                v.span(),
                key,
                format!("station {station} does not exist: the turret has stations 1 to {stations}"),
            ));
            continue;
        }
        if out.iter().any(|o: &(u32, u32)| o.0 == tool) {
            cx.push(cx.err(k.span(), key, format!("tool {tool} is given twice")));
            continue;
        }
        out.push((tool, station as u32));
    }
    out.sort_unstable();
    out
}

/// Parse `cx`'s text as a `T` (the raw types of a TOML file with spans), with errors that name
/// the file, line, column and dotted key. Shared by machine and job files.
pub(crate) fn deserialize<T: serde::de::DeserializeOwned>(cx: &Cx<'_>, what: &str) -> Result<T, MachineError> {
    let root = root_table(cx, what)?;
    let tree = root.clone();
    T::deserialize(toml::de::Deserializer::from(root)).map_err(|e| cx.serde_error(&e, &tree))
}

/// A value inside another file (`job` in `latheguard.toml`, or `override[2].job`): a string,
/// or a table read as a `T` with errors that name the whole key path.
pub(crate) enum Embedded<T> {
    Str(Spanned<String>),
    Table(T),
}

/// The value at `path` (keys, and array indices as numbers in strings: `["override", "2",
/// "job"]`) of `cx`'s text, if there is one.
pub(crate) fn deserialize_at<T: serde::de::DeserializeOwned>(
    cx: &Cx<'_>,
    path: &[&str],
    what: &str,
) -> Result<Option<Embedded<T>>, MachineError> {
    let root = root_table(cx, what)?;
    let mut here: Option<&Spanned<DeValue<'_>>> = None;
    let mut table: Option<&DeTable<'_>> = Some(root.get_ref());
    for seg in path {
        let next = match (here.map(|v| v.get_ref()), table) {
            (Some(DeValue::Array(a)), _) => seg.parse::<usize>().ok().and_then(|i| a.get(i)),
            (_, Some(t)) => t.get(*seg),
            _ => None,
        };
        let Some(v) = next else { return Ok(None) };
        table = match v.get_ref() {
            DeValue::Table(t) => Some(t),
            _ => None,
        };
        here = Some(v);
    }
    let Some(v) = here else { return Ok(None) };
    let key = path.join(".");
    match v.get_ref() {
        DeValue::String(s) => Ok(Some(Embedded::Str(Spanned::new(v.span(), s.to_string())))),
        DeValue::Table(t) => {
            let sub = Spanned::new(v.span(), t.clone());
            T::deserialize(toml::de::Deserializer::from(sub))
                .map(|t| Some(Embedded::Table(t)))
                .map_err(|e| cx.serde_error(&e, &root))
        }
        _ => Err(cx.err(v.span(), key, "expected a file name (a string) or a table")),
    }
}

/// The JSON Schema (draft 2020-12) of a machine file, generated from the types the loader reads
/// (`latheguard machine --schema`): for editors that complete and validate TOML with a schema
/// (Taplo, Even Better TOML). It says the keys, their types and which are required; the ranges
/// and the geometry rules (simple outlines, a stock that fits the chuck …) are the loader's, with
/// the message and the key of every problem.
pub fn schema() -> String {
    let mut schema = schemars::schema_for!(RawDoc);
    schema.insert("title".into(), "latheguard machine file".into());
    let mut s = serde_json::to_string_pretty(&schema).unwrap_or_default();
    s.push('\n');
    s
}

// ---------------------------------------------------------------------------------------------
// The file as written. (These types also give the JSON Schema of the file: [`schema`].)

pub(crate) type Num = Spanned<f64>;
pub(crate) type Point = Spanned<Vec<f64>>;
pub(crate) type Outline = Spanned<Vec<Point>>;

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawDoc {
    machine: RawHeader,
    axes: RawAxes,
    spindle: RawSpindle,
    chuck: Option<RawPart>,
    tailstock: Option<RawTailstock>,
    #[schemars(with = "Option<RawStock>")]
    stock: Option<Spanned<RawStock>>,
    setup: Option<RawSetup>,
    turret: RawTurret,
    #[schemars(with = "Option<Vec<RawTool>>")]
    tools: Option<Spanned<Vec<Spanned<RawTool>>>>,
    #[schemars(with = "Option<std::collections::BTreeMap<String, RawCodes>>")]
    mcodes: Option<std::collections::BTreeMap<String, Spanned<RawCodes>>>,
    /// Builder G codes: each key a code the builder numbered its own way, each value the
    /// standard code it runs as or `{ ignore = "…" }` (docs/machine.md, "Builder G codes").
    #[schemars(with = "Option<std::collections::BTreeMap<String, RawGcode>>")]
    gcodes: Option<std::collections::BTreeMap<String, Spanned<RawGcode>>>,
    /// The kinematic machine (turn-mill): axes, components, pairs that must never touch
    /// (`docs/turn-mill.md`).
    kinematics: Option<crate::kin::load::RawKinematics>,
    /// LinuxCNC tool numbers → turret stations: `T12 = 3` (docs/machine.md, "Tool numbers").
    #[schemars(with = "Option<std::collections::BTreeMap<String, u32>>")]
    tool_numbers: Option<std::collections::BTreeMap<Spanned<String>, Spanned<i64>>>,
    /// The tool carriers of paths 2, 3, … of a multi-path control, each with its own axes,
    /// turret and tools (docs/paths.md).
    #[schemars(with = "Option<Vec<super::paths::RawPath>>")]
    paths: Option<Spanned<Vec<Spanned<super::paths::RawPath>>>>,
    /// How the paths of a multi-path control wait for each other (docs/paths.md).
    #[schemars(with = "Option<super::paths::RawSync>")]
    sync: Option<Spanned<super::paths::RawSync>>,
}

/// The codes of one action in `[mcodes]`: one number or an array.
#[derive(Deserialize, JsonSchema)]
#[serde(untagged, expecting = "an M code number or an array of M code numbers")]
enum RawCodes {
    One(i64),
    Many(Vec<i64>),
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawTailstock {
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
    /// Fanuc's tailstock barrier parameters, instead of `outline` (docs/machine.md).
    barrier: Option<RawTailstockBarrier>,
    advanced: Option<bool>,
}

/// `[tailstock] barrier`: Fanuc's tailstock barrier (TZ in the workpiece coordinate system,
/// D… diameters), mm.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawTailstockBarrier {
    #[schemars(with = "f64")]
    tz: Num,
    #[schemars(with = "f64")]
    l: Num,
    #[schemars(with = "f64")]
    d: Num,
    #[schemars(with = "f64")]
    l1: Num,
    #[schemars(with = "f64")]
    d1: Num,
    #[schemars(with = "f64")]
    l2: Num,
    #[schemars(with = "f64")]
    d2: Num,
    #[schemars(with = "f64")]
    d3: Num,
}

/// `[chuck] barrier`: Fanuc's chuck barrier (CX, CZ in the workpiece coordinate system, CX a
/// diameter, W and W1 radii), mm.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawChuckBarrier {
    #[schemars(with = "u8")]
    ty: Spanned<i64>,
    #[schemars(with = "f64")]
    cx: Num,
    #[schemars(with = "f64")]
    cz: Num,
    #[schemars(with = "f64")]
    l: Num,
    #[schemars(with = "f64")]
    w: Num,
    #[schemars(with = "f64")]
    l1: Num,
    #[schemars(with = "f64")]
    w1: Num,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawHeader {
    #[schemars(with = "String")]
    name: Spanned<String>,
    dialect: Option<RawDialect>,
    diameter_mode: Option<bool>,
    rapid: Option<RawRapid>,
    #[schemars(with = "Option<RawDecimalPoint>")]
    decimal_point: Option<Spanned<RawDecimalPoint>>,
    #[schemars(with = "Option<RawGcodeSystem>")]
    gcode_system: Option<Spanned<RawGcodeSystem>>,
    /// Which drilling cycles G83-G89 are: "haas" (spindle axis, the default) or "fanuc" (live
    /// tools: face G83/G84/G85, side G87/G88/G89 at a C angle). docs/machine.md.
    #[schemars(with = "Option<RawDrilling>")]
    drilling_cycles: Option<Spanned<RawDrilling>>,
    /// How R of the spindle-axis drilling cycles G81-G89 is read: "absolute" (Haas: the R
    /// plane's Z; the default with drilling_cycles = "haas") or "incremental" (Fanuc: the
    /// distance from the initial level; the default with drilling_cycles = "fanuc").
    /// docs/machine.md.
    #[schemars(with = "Option<RawDrillR>")]
    drill_r: Option<Spanned<RawDrillR>>,
    /// How a G71/G72 one-block D without a decimal point is read: "length" (as written, the
    /// default) or "increment" (Fanuc 0-TC/10T/15T: D1500 = 1.5 mm). docs/machine.md.
    #[schemars(with = "Option<RawG71D>")]
    g71_d: Option<Spanned<RawG71D>>,
    turret_side: Option<RawTurretSide>,
    units: Option<RawUnits>,
    #[schemars(with = "Option<f64>")]
    min_depth: Option<Num>,
}

// "mm" or "inch": machine files' `machine.units` and jobs' `units` (one type for both).
#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"mm\" or \"inch\"")]
pub(crate) enum RawUnits {
    Mm,
    Inch,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"rear\" or \"front\"")]
enum RawTurretSide {
    Rear,
    Front,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(expecting = "\"A\" or \"B\"")]
enum RawGcodeSystem {
    A,
    B,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"haas\" or \"fanuc\"")]
enum RawDrilling {
    Haas,
    Fanuc,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"absolute\" or \"incremental\"")]
enum RawDrillR {
    Absolute,
    Incremental,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"length\" or \"increment\"")]
enum RawG71D {
    Length,
    Increment,
}

/// One builder code of `[gcodes]`: the standard code it runs as (`"G12.1"`), or a mode switch
/// that moves nothing (`{ ignore = "why" }`).
#[derive(Deserialize, JsonSchema)]
#[serde(
    untagged,
    expecting = "a G code such as \"G12.1\", or { ignore = \"what the code does\" }"
)]
enum RawGcode {
    As(String),
    Ignore(RawGcodeIgnore),
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawGcodeIgnore {
    /// What the code does on the control, and why nothing of it needs checking.
    ignore: String,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"fanuc\", \"linuxcnc\" or \"auto\"")]
enum RawDialect {
    Fanuc,
    Linuxcnc,
    Auto,
}

#[derive(Deserialize, JsonSchema, Clone, Copy, PartialEq)]
#[serde(rename_all = "lowercase", expecting = "\"drum\" or \"gang\"")]
enum RawTurretKind {
    Drum,
    Gang,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"dogleg\" or \"linear\"")]
enum RawRapid {
    Dogleg,
    Linear,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"calculator\" or \"increment\"")]
enum RawDecimalPoint {
    Calculator,
    Increment,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawAxes {
    x: RawAxis,
    z: RawAxis,
    #[schemars(with = "Option<[f64; 2]>")]
    home: Option<Point>,
    #[schemars(with = "Option<[f64; 2]>")]
    machine_zero: Option<Point>,
    /// The 2nd, 3rd and 4th reference points (Fanuc G30 P2/P3/P4), each `[x, z]`.
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    reference_points: Option<Spanned<Vec<Point>>>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { min, max, rapid }")]
struct RawAxis {
    #[schemars(with = "f64")]
    min: Num,
    #[schemars(with = "f64")]
    max: Num,
    #[schemars(with = "f64")]
    rapid: Num,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawSpindle {
    #[schemars(with = "f64")]
    max_rpm: Num,
    #[schemars(with = "Option<f64>")]
    start_rpm: Option<Num>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawPart {
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
    /// Fanuc's chuck barrier parameters, instead of `outline` (docs/machine.md).
    barrier: Option<RawChuckBarrier>,
    /// The chuck body, with `jaws`, instead of `outline` (docs/machine.md).
    #[schemars(with = "Option<RawBody>")]
    body: Option<Spanned<RawBody>>,
    /// The jaws on the body: what they grip and their sizes (docs/machine.md).
    #[schemars(with = "Option<RawJaws>")]
    jaws: Option<Spanned<RawJaws>>,
}

/// `[chuck] body`: the chuck body, mm.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { diameter, bore, face, depth }")]
struct RawBody {
    /// The body's outer diameter.
    #[schemars(with = "f64")]
    diameter: Num,
    /// The through bore's diameter (default 0: none).
    #[schemars(with = "Option<f64>")]
    bore: Option<Num>,
    /// The z of the chuck face, where the jaws stand.
    #[schemars(with = "f64")]
    face: Num,
    /// How far the body reaches back from its face (toward -z).
    #[schemars(with = "f64")]
    depth: Num,
}

/// `[chuck.jaws]` of a machine file: what the jaws grip and their sizes, mm.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawJaws {
    /// "outside" (the jaws close on an outer diameter, the default) or "inside" (they open in a
    /// bore).
    #[schemars(with = "Option<RawGrip>")]
    grip: Option<Spanned<RawGrip>>,
    /// "hard" (a gripping step at the tip, the default) or "soft" (bored to the grip, a seat
    /// behind).
    #[serde(rename = "type")]
    #[schemars(rename = "type", with = "Option<RawJawType>")]
    kind: Option<Spanned<RawJawType>>,
    /// The diameter held.
    #[schemars(with = "f64")]
    grip_diameter: Num,
    /// How long (along z, back from the jaw faces) the jaws hold it.
    #[schemars(with = "f64")]
    grip_length: Num,
    /// How far the jaws stand out of the chuck face.
    #[schemars(with = "f64")]
    height: Num,
    /// A jaw's whole radial extent.
    #[schemars(with = "f64")]
    width: Num,
    /// Hard jaws: the radial width of the gripping step; soft jaws: how far the seat reaches past
    /// the grip diameter.
    #[schemars(with = "f64")]
    step: Num,
}

/// `chuck.jaws.grip`: machine files and jobs.
#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"outside\" or \"inside\"")]
pub(crate) enum RawGrip {
    Outside,
    Inside,
}

impl RawGrip {
    pub(crate) fn value(self) -> super::jaws::Grip {
        match self {
            RawGrip::Outside => super::jaws::Grip::Outside,
            RawGrip::Inside => super::jaws::Grip::Inside,
        }
    }
}

/// `chuck.jaws.type`: machine files and jobs.
#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"hard\" or \"soft\"")]
pub(crate) enum RawJawType {
    Hard,
    Soft,
}

impl RawJawType {
    pub(crate) fn value(self) -> super::jaws::JawType {
        match self {
            RawJawType::Hard => super::jaws::JawType::Hard,
            RawJawType::Soft => super::jaws::JawType::Soft,
        }
    }
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawStock {
    #[schemars(with = "Option<f64>")]
    diameter: Option<Num>,
    #[schemars(with = "Option<f64>")]
    length: Option<Num>,
    #[schemars(with = "Option<f64>")]
    front: Option<Num>,
    #[schemars(with = "Option<f64>")]
    bore: Option<Num>,
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawSetup {
    #[schemars(with = "Option<f64>")]
    program_zero_z: Option<Num>,
    /// Work offsets G54–G59 as the control's work offset page stores them (docs/machine.md).
    work_offsets: Option<RawWorkOffsets>,
    /// The stock, program zero and tools are an example that a program's own evidence replaces
    /// when it has no job (docs/assume.md).
    assume: Option<bool>,
}

/// `work_offsets`: G54–G59, each `{ x, z }` (a machine file's `[setup.work_offsets]`, a job's
/// `[work_offsets]`).
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table of work offsets G54 to G59")]
pub(crate) struct RawWorkOffsets {
    #[serde(rename = "G54")]
    #[schemars(rename = "G54", with = "Option<RawWorkOffset>")]
    g54: Option<Spanned<RawWorkOffset>>,
    #[serde(rename = "G55")]
    #[schemars(rename = "G55", with = "Option<RawWorkOffset>")]
    g55: Option<Spanned<RawWorkOffset>>,
    #[serde(rename = "G56")]
    #[schemars(rename = "G56", with = "Option<RawWorkOffset>")]
    g56: Option<Spanned<RawWorkOffset>>,
    #[serde(rename = "G57")]
    #[schemars(rename = "G57", with = "Option<RawWorkOffset>")]
    g57: Option<Spanned<RawWorkOffset>>,
    #[serde(rename = "G58")]
    #[schemars(rename = "G58", with = "Option<RawWorkOffset>")]
    g58: Option<Spanned<RawWorkOffset>>,
    #[serde(rename = "G59")]
    #[schemars(rename = "G59", with = "Option<RawWorkOffset>")]
    g59: Option<Spanned<RawWorkOffset>>,
}

/// One work offset as the control stores it, mm.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { x, z }")]
struct RawWorkOffset {
    /// Program X0's distance from the spindle axis, a radius (default 0: on the axis).
    #[schemars(with = "Option<f64>")]
    x: Option<Num>,
    /// Program zero's machine Z coordinate: its distance from machine zero (`axes.machine_zero`)
    /// along Z, as G53 Z measures it.
    #[schemars(with = "f64")]
    z: Num,
}

/// A work offset as written: its value, the span of its table and its key.
pub(crate) struct GivenOffset {
    pub n: usize,
    pub value: super::WorkOffset,
    pub at: Range<usize>,
    pub key: String,
}

/// The work offsets of `raw`, each within range (errors are kept in `cx`); `prefix` is the
/// dotted key of the table (`setup.work_offsets`, `work_offsets`).
pub(crate) fn work_offsets(cx: &Cx<'_>, raw: &RawWorkOffsets, prefix: &str) -> Vec<GivenOffset> {
    let mut out = Vec::new();
    let all = [&raw.g54, &raw.g55, &raw.g56, &raw.g57, &raw.g58, &raw.g59];
    for (n, (o, name)) in all.into_iter().zip(super::WORK_OFFSET_NAMES).enumerate() {
        let Some(o) = o else { continue };
        let key = format!("{prefix}.{name}");
        let r = o.get_ref();
        let x = match &r.x {
            None => Some(0.0),
            Some(x) => cx.keep(cx.coord(&format!("{key}.x"), x)),
        };
        let z = cx.keep(cx.coord(&format!("{key}.z"), &r.z));
        if let (Some(x), Some(z)) = (x, z) {
            out.push(GivenOffset {
                n,
                value: super::WorkOffset { x, z },
                at: o.span(),
                key,
            });
        }
    }
    out
}

/// Why a work offset looks like a mistake on machine `m` (its program zero's machine Z outside
/// the Z travel: a sign or a unit slip), or None.
pub(crate) fn work_offset_doubt(m_z: &super::Axis, machine_zero: P2, o: super::WorkOffset) -> Option<String> {
    let (lo, hi) = (m_z.min - machine_zero.y, m_z.max - machine_zero.y);
    if (lo..=hi).contains(&o.z) {
        return None;
    }
    Some(format!(
        "program zero at machine Z {} lies outside the Z travel (machine Z {} .. {}, from axes.z and axes.machine_zero): is the sign or the unit wrong? (the work offset page's Z is the distance from machine zero to program zero, mm)",
        show(o.z),
        show(lo),
        show(hi)
    ))
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawTurret {
    #[serde(rename = "type")]
    kind: Option<RawTurretKind>,
    /// How many stations the turret has: 1 to 64.
    // Read as any whole number, so that the error for -1 states the range too ([`MAX_STATIONS`]).
    #[schemars(with = "u32", range(min = 1, max = 64))]
    stations: Spanned<i64>,
    #[schemars(with = "Option<u32>")]
    start_station: Option<Spanned<u32>>,
    #[schemars(with = "Option<f64>")]
    axis: Option<Num>,
    #[schemars(with = "f64")]
    index_time: Num,
    #[schemars(with = "Vec<[f64; 2]>")]
    pub(super) outline: Outline,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawTool {
    #[schemars(with = "u32")]
    station: Spanned<u32>,
    #[schemars(with = "String")]
    name: Spanned<String>,
    /// The programmed point from the turret reference point, `[x, z]` (x a radius); or give
    /// `geometry_offset`.
    #[schemars(with = "Option<[f64; 2]>")]
    tip: Option<Point>,
    /// The tool's geometry offset as the control's page shows it (X on diameter, Z; mm),
    /// instead of `tip`.
    #[schemars(with = "Option<RawGeometryOffset>")]
    geometry_offset: Option<Spanned<RawGeometryOffset>>,
    /// An outline, or an ISO designation (`"CNMG 120408"`); may be left out with `holder` or
    /// `drill` as a designation (docs/tools.md).
    #[schemars(with = "Option<ShapeSchema>")]
    insert: Option<Spanned<Shape>>,
    /// An outline, or an ISO designation (`"PCLNR 2525M12"`).
    #[schemars(with = "Option<ShapeSchema>")]
    holder: Option<Spanned<Shape>>,
    #[schemars(with = "Option<f64>")]
    nose_radius: Option<Num>,
    #[schemars(with = "Option<i64>")]
    tip_direction: Option<Spanned<i64>>,
    /// A drill by its sizes, instead of `insert` and `holder`.
    #[schemars(with = "Option<RawDrill>")]
    drill: Option<Spanned<RawDrill>>,
}

impl RawTool {
    /// Where the entry's insert or holder (`part`) was given: that key, else its `drill`, else
    /// its `station`.
    fn span_of(&self, part: &str) -> Range<usize> {
        let shape = if part == "holder" { &self.holder } else { &self.insert };
        match (shape, &self.drill) {
            (Some(v), _) => v.span(),
            (None, Some(d)) => d.span(),
            (None, None) => self.station.span(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Validation.

/// Where values of one TOML text are checked: errors and warnings with file, line, column and
/// key. Shared with job files (`crate::job`), which are checked as machine files are.
pub(crate) struct Cx<'a> {
    text: &'a str,
    file: &'a str,
    lines: LineIndex,
    /// Values that are valid but look like unit mistakes, as `file:line:col: key: message`.
    warnings: std::cell::RefCell<Vec<String>>,
    /// Problems found so far by checks that let validation go on.
    errors: std::cell::RefCell<Vec<MachineError>>,
    /// Put before every key an error names: `paths[0].` while a path's carrier is read with the
    /// same functions as the machine's own `[axes]`, `[turret]` and `[[tools]]`.
    prefix: std::cell::RefCell<String>,
}

impl<'a> Cx<'a> {
    pub(crate) fn new(text: &'a str, file: &'a str) -> Cx<'a> {
        Cx {
            text,
            file,
            lines: LineIndex::new(text.as_bytes()),
            warnings: std::cell::RefCell::new(Vec::new()),
            errors: std::cell::RefCell::new(Vec::new()),
            prefix: std::cell::RefCell::new(String::new()),
        }
    }

    /// Run `f` with every key its errors name prefixed by `prefix`.
    pub(crate) fn prefixed<T>(&self, prefix: &str, f: impl FnOnce() -> T) -> T {
        let old = self.prefix.replace(prefix.to_string());
        let out = f();
        self.prefix.replace(old);
        out
    }

    /// The warnings kept so far, as `file:line:col: key: message`.
    pub(crate) fn take_warnings(&self) -> Vec<String> {
        self.warnings.take()
    }
}

impl Cx<'_> {
    pub(crate) fn err(&self, at: Range<usize>, key: impl Into<String>, message: impl Into<String>) -> MachineError {
        let offset = at.start.min(self.text.len()).min(u32::MAX as usize) as u32;
        let key = format!("{}{}", self.prefix.borrow(), key.into());
        MachineError {
            file: self.file.to_string(),
            line: self.lines.line_of(offset),
            col: self.lines.col_of(self.text.as_bytes(), offset),
            key: if key.is_empty() { TOP_LEVEL.to_string() } else { key },
            message: message.into(),
            also: Vec::new(),
        }
    }

    /// The value, or None with its error kept for the report: validation goes on.
    pub(crate) fn keep<T>(&self, r: Result<T, MachineError>) -> Option<T> {
        match r {
            Ok(v) => Some(v),
            Err(e) => {
                self.errors.borrow_mut().push(e);
                None
            }
        }
    }

    /// Keep an error for the report.
    pub(crate) fn push(&self, e: MachineError) {
        self.errors.borrow_mut().push(e);
    }

    /// Every error kept so far, as one (None when there are none).
    pub(crate) fn kept(&self) -> Option<MachineError> {
        MachineError::gather(self.errors.take())
    }

    /// A serde error (unknown key, wrong type, missing key): find the key from its span.
    pub(crate) fn serde_error(&self, e: &toml::de::Error, tree: &Spanned<DeTable<'_>>) -> MachineError {
        let at = e.span().unwrap_or(0..0);
        let message = e.message();
        if let Some(field) = message
            .strip_prefix("missing field `")
            .and_then(|m| m.strip_suffix('`'))
        {
            let mut path = table_at(tree, &at).unwrap_or_default();
            path.push(Seg::Key(field.to_string()));
            return self.err(at, render(&path), format!("missing required key `{field}`"));
        }
        let path = containing(tree, at.start).unwrap_or_default();
        self.err(at, render(&path), plain_words(message))
    }

    pub(crate) fn finite(&self, key: &str, v: &Num) -> Result<f64, MachineError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("{} is not a finite number", show(x))))
        }
    }

    pub(crate) fn warn(&self, at: Range<usize>, key: &str, message: String) {
        let e = self.err(at, key, message);
        self.warnings.borrow_mut().push(e.to_string());
    }

    /// A number within `lo ..= hi` (its physical range), else an error naming the range.
    pub(crate) fn within(&self, key: &str, v: &Num, (lo, hi): (f64, f64), unit: &str) -> Result<f64, MachineError> {
        let x = self.finite(key, v)?;
        if (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            Err(self.err(
                v.span(),
                key,
                format!(
                    "{} is out of range: must be from {} to {} {unit}",
                    show(x),
                    show(lo),
                    show(hi)
                ),
            ))
        }
    }

    /// A coordinate: within ±[`MAX_COORD_MM`].
    pub(crate) fn coord(&self, key: &str, v: &Num) -> Result<f64, MachineError> {
        self.within(key, v, (-MAX_COORD_MM, MAX_COORD_MM), "mm")
    }

    /// A length: greater than 0 and at most [`MAX_COORD_MM`].
    pub(crate) fn length(&self, key: &str, v: &Num) -> Result<f64, MachineError> {
        let x = self.positive(key, v)?;
        if x > MAX_COORD_MM {
            return Err(self.err(
                v.span(),
                key,
                format!(
                    "{} is out of range: must be greater than 0 and at most {} mm",
                    show(x),
                    show(MAX_COORD_MM)
                ),
            ));
        }
        Ok(x)
    }

    pub(crate) fn positive(&self, key: &str, v: &Num) -> Result<f64, MachineError> {
        let x = self.finite(key, v)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must be greater than 0, not {}", show(x))))
        }
    }

    pub(crate) fn non_negative(&self, key: &str, v: &Num) -> Result<f64, MachineError> {
        let x = self.finite(key, v)?;
        if x >= 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must not be negative, not {}", show(x))))
        }
    }

    pub(crate) fn point(&self, key: &str, p: &Point) -> Result<P2, MachineError> {
        match p.get_ref().as_slice() {
            &[x, z] if x.abs() <= MAX_COORD_MM && z.abs() <= MAX_COORD_MM => Ok(p2(x, z)),
            &[x, z] if x.is_finite() && z.is_finite() => Err(self.err(
                p.span(),
                key,
                format!(
                    "[{}, {}] is out of range: coordinates must be from {} to {} mm",
                    show(x),
                    show(z),
                    show(-MAX_COORD_MM),
                    show(MAX_COORD_MM)
                ),
            )),
            &[x, z] => Err(self.err(
                p.span(),
                key,
                format!("[{}, {}] is not a point: both numbers must be finite", show(x), show(z)),
            )),
            v => Err(self.err(
                p.span(),
                key,
                format!("a point is [x, z]: expected 2 numbers, found {}", v.len()),
            )),
        }
    }

    /// A revolved stock outline (`stock.outline`): a simple outline of at most
    /// [`MAX_OUTLINE_POINTS`] points in the half plane x ≥ 0, with some material off the axis.
    pub(crate) fn stock_outline(&self, key: &str, o: &Outline) -> Result<Polygon, MachineError> {
        if o.get_ref().len() > MAX_OUTLINE_POINTS {
            return Err(self.err(
                o.span(),
                key,
                format!("too many points; an outline may have at most {MAX_OUTLINE_POINTS}"),
            ));
        }
        let poly = self.outline(key, o)?;
        if let Some((i, p)) = o
            .get_ref()
            .iter()
            .enumerate()
            .find(|(_, p)| p.get_ref().first().is_some_and(|&x| x < 0.0))
        {
            return Err(self.err(
                p.span(),
                format!("{key}[{i}]"),
                "a stock outline is the revolved section: its x (radius) must be 0 or more",
            ));
        }
        if poly.aabb().max.x <= 0.0 {
            return Err(self.err(o.span(), key, "the outline has no material off the axis"));
        }
        Ok(poly)
    }

    pub(crate) fn outline(&self, key: &str, o: &Outline) -> Result<Polygon, MachineError> {
        let mut pts = Vec::with_capacity(o.get_ref().len());
        for (i, p) in o.get_ref().iter().enumerate() {
            pts.push(self.point(&format!("{key}[{i}]"), p)?);
        }
        match Polygon::new(&pts) {
            Ok(poly) => {
                self.warn_folds(key, o, &pts);
                Ok(poly)
            }
            Err(e @ PolygonError::SelfIntersecting(..)) => match crossing_edges(&pts) {
                Some(((a, b), (c, d))) => Err(self.err(
                    o.get_ref()[a].span(),
                    key,
                    format!(
                        "invalid outline: the edge from point [{a}] to point [{b}] meets the edge from point [{c}] to point [{d}] (counting from 0); after dropping repeated and collinear points: {e}"
                    ),
                )),
                None => Err(self.err(o.span(), key, format!("invalid outline: {e}"))),
            },
            Err(e) => Err(self.err(o.span(), key, format!("invalid outline: {e}"))),
        }
    }

    /// Warn about what normalising a valid outline drops besides repeated and collinear points:
    /// a spike (one point whose two edges fold back on each other) or a zero-width feature (a
    /// run of dropped points along which the outline turns back more than once, such as a
    /// zero-width slot or T). Both are usually a typing mistake, and the outline checked is not
    /// the one drawn.
    fn warn_folds(&self, key: &str, o: &Outline, pts: &[P2]) {
        for run in folds(pts) {
            let (first, last) = (run.points[0], run.points[run.points.len() - 1]);
            let at = o.get_ref()[run.turns[0]].span();
            let p = pts[run.turns[0]];
            let message = if run.turns.len() == 1 {
                format!(
                    "point [{}] [{}, {}] is a spike (its two edges fold back on each other): it was dropped, and the outline checked is the one without it",
                    run.turns[0],
                    show(p.x),
                    show(p.y)
                )
            } else {
                format!(
                    "points [{first}] to [{last}] (from [{}, {}]) are a zero-width feature (the outline runs back over itself {} times): they were dropped, and the outline checked is the one without them",
                    show(pts[first].x),
                    show(pts[first].y),
                    run.turns.len()
                )
            };
            self.warn(at, key, message);
        }
    }

    fn axis(&self, key: &str, a: &RawAxis) -> Result<Axis, MachineError> {
        let min = self.coord(&format!("{key}.min"), &a.min)?;
        let max = self.coord(&format!("{key}.max"), &a.max)?;
        if min >= max {
            return Err(self.err(
                a.min.span(),
                format!("{key}.min"),
                format!("min = {} must be less than max = {}", show(min), show(max)),
            ));
        }
        let rapid = self.within(&format!("{key}.rapid"), &a.rapid, RAPID_RANGE, "mm/min")?;
        if rapid < 100.0 {
            self.warn(
                a.rapid.span(),
                &format!("{key}.rapid"),
                format!(
                    "rapid = {} mm/min is implausibly slow for a rapid: the unit is mm/min (was it m/min or inch/s?)",
                    show(rapid)
                ),
            );
        }
        Ok(Axis { min, max, rapid })
    }
}

/// A tool's insert or holder with its place, if given (None: not given).
type GivenShape = Option<(tool_entry::Geom, (Range<usize>, String))>;

fn validate(cx: &Cx<'_>, raw: RawDoc, resolve: crate::kin::load::Resolve<'_>) -> Result<Machine, MachineError> {
    let RawDoc {
        machine: hdr,
        axes,
        spindle,
        chuck,
        tailstock,
        stock,
        setup,
        turret,
        tools,
        mcodes,
        gcodes,
        kinematics,
        tool_numbers,
        paths,
        sync,
    } = raw;

    // Bound the work before doing any of it.
    let tools = tools_given(cx, tools)?;
    outlines_bounded(cx, chuck.as_ref(), tailstock.as_ref(), &turret, &tools)?;

    // From here on each check that fails is kept and validation goes on, so that one run reports
    // every problem; a value that depends on a refused one is not checked.
    let header = header_of(cx, &hdr);
    let gcodes = cx
        .keep(gcode_table(cx, header.dialect, gcodes.as_ref()))
        .unwrap_or_default();
    let ax = axes_of(cx, &axes);
    let (max_rpm, start_rpm) = spindle_of(cx, &spindle);
    let tailstock_advanced = tailstock.as_ref().and_then(|t| t.advanced).unwrap_or(true);
    let mcodes_linuxcnc = if header.auto {
        cx.keep(mcode_table(cx, Dialect::Linuxcnc, mcodes.as_ref()))
    } else {
        None
    };
    // The codes `[mcodes]` gives (the waiting M codes of `[sync]` may not take them).
    let given: Vec<i64> = mcodes
        .iter()
        .flat_map(|t| t.values())
        .flat_map(|c| match c.get_ref() {
            RawCodes::One(c) => vec![*c],
            RawCodes::Many(v) => v.clone(),
        })
        .collect();
    let mcodes = cx.keep(mcode_table(cx, header.dialect, mcodes.as_ref()));
    let raw_stock = stock;
    let stock = stock_of(cx, raw_stock.as_ref());
    let (work_offsets, program_zero_z) = setup_of(cx, setup.as_ref(), ax.z, ax.machine_zero, stock.as_ref());

    // [chuck], [tailstock]: an outline, or Fanuc's barrier parameters (measured from program Z0).
    let chuck = chuck.map(|c| chuck_part(cx, &c, program_zero_z));
    let chuck_form = chuck.as_ref().and_then(|c| c.as_ref().map(|c| c.1.clone()));
    let chuck = chuck.map(|c| c.map(|c| c.0));
    let tailstock = tailstock.map(|t| tailstock_part(cx, &t, program_zero_z));

    let (stations, turret_built) = turret_of(cx, &turret);
    let out = tools_of(cx, &tools, stations, ax.machine_zero);
    let numbers = machine_tool_numbers(cx, tool_numbers.as_ref(), stations);

    if let Some(e) = cx.kept() {
        return Err(e);
    }
    // No error was kept, so every value is there.
    let (
        Some(x),
        Some(z),
        Some(home),
        Some(machine_zero),
        Some(reference_points),
        Some(max_rpm),
        Some(start_rpm),
        Some(mcodes),
        Some(stock),
        Some(program_zero_z),
        Some(turret_built),
    ) = (
        ax.x,
        ax.z,
        ax.home,
        ax.machine_zero,
        ax.reference_points,
        max_rpm,
        start_rpm,
        mcodes,
        stock,
        program_zero_z,
        turret_built,
    )
    else {
        return Err(cx.err(0..0, TOP_LEVEL, "invalid machine file"));
    };
    let (Some(chuck), Some(tailstock)) = (
        chuck.map_or(Some(None), |c| c.map(Some)),
        tailstock.map_or(Some(None), |t| t.map(Some)),
    ) else {
        return Err(cx.err(0..0, TOP_LEVEL, "invalid machine file"));
    };

    let Header {
        name,
        auto,
        dialect,
        diameter_mode,
        rapid,
        decimal_point,
        gcode_system,
        drilling_cycles,
        drill_r,
        g71_d,
        min_depth,
        turret_side,
        inch,
    } = header;
    let machine = Machine {
        name,
        dialect,
        diameter_mode,
        rapid,
        decimal_point,
        gcode_system,
        drilling_cycles,
        drill_r,
        g71_d,
        gcodes,
        turret_side,
        inch,
        min_depth,
        x,
        z,
        home,
        machine_zero,
        reference_points,
        max_rpm,
        start_rpm,
        chuck,
        chuck_form,
        tailstock,
        tailstock_advanced,
        mcodes,
        stock,
        program_zero_z,
        work_offsets,
        turret: turret_built,
        tools: out,
        tool_changes: Vec::new(),
        tool_numbers: numbers,
        operations: Vec::new(),
        auto_dialect: None,
        warnings: Vec::new(),
        kinematics: None,
        assume_setup: setup.as_ref().and_then(|s| s.assume).unwrap_or(false),
        paths: super::paths::Paths::default(),
    };
    let auto_dialect = match (auto, mcodes_linuxcnc) {
        (true, Some(lc)) => Some(Box::new(super::AutoDialect {
            fanuc: super::DialectParts {
                diameter_mode,
                decimal_point,
                gcode_system,
                mcodes: machine.mcodes.clone(),
            },
            linuxcnc: super::DialectParts {
                diameter_mode: hdr.diameter_mode.unwrap_or(false),
                decimal_point: DecimalPoint::Calculator,
                gcode_system: GcodeSystem::A,
                mcodes: lc,
            },
        })),
        _ => None,
    };
    let machine = Machine {
        auto_dialect,
        ..machine
    };
    clear_at_home(cx, &machine, &turret.outline, &tools);
    if let (Some(s), Some(raw)) = (&machine.stock, &raw_stock) {
        cx.keep(stock_fits_chuck(cx, &machine, s, raw.get_ref()));
    }
    if let Some(e) = cx.kept() {
        return Err(e);
    }
    // [[paths]]: read once the machine they share is valid.
    let paths = super::paths::paths_of(cx, paths, sync, &machine, &given)?;
    let machine = Machine { paths, ..machine };
    // [kinematics]: read once the 2D sections it refers to (every path's) are valid.
    let kinematics = match &kinematics {
        None => None,
        Some(k) => Some(std::sync::Arc::new(crate::kin::load::kinematics(
            cx, k, &machine, resolve,
        )?)),
    };
    Ok(Machine {
        warnings: cx.warnings.take(),
        kinematics,
        ..machine
    })
}

/// `[[tools]]` present, not empty and at most [`MAX_TOOLS`]: checked before any other work.
pub(super) fn tools_given(
    cx: &Cx<'_>,
    tools: Option<Spanned<Vec<Spanned<RawTool>>>>,
) -> Result<Vec<Spanned<RawTool>>, MachineError> {
    let tools = match tools {
        Some(t) if t.get_ref().is_empty() => {
            return Err(cx.err(
                t.span(),
                "tools",
                "missing tools: at least one [[tools]] table is required",
            ))
        }
        Some(t) => t.into_inner(),
        None => return Err(cx.err(0..0, "tools", "missing tools: at least one [[tools]] table is required")),
    };
    if tools.len() > MAX_TOOLS {
        return Err(cx.err(
            tools[MAX_TOOLS].span(),
            format!("tools[{MAX_TOOLS}]"),
            format!(
                "too many tools: {}; a machine file may have at most {MAX_TOOLS}",
                tools.len()
            ),
        ));
    }
    Ok(tools)
}

/// Every outline of the file (chuck, tailstock, turret, the tools' inserts and holders) within
/// [`MAX_OUTLINE_POINTS`], and all of them together within [`MAX_TOTAL_OUTLINE_POINTS`]:
/// checked before any outline is normalised.
fn outlines_bounded(
    cx: &Cx<'_>,
    chuck: Option<&RawPart>,
    tailstock: Option<&RawTailstock>,
    turret: &RawTurret,
    tools: &[Spanned<RawTool>],
) -> Result<(), MachineError> {
    let mut outlines: Vec<(String, Range<usize>, &[Point])> = Vec::new();
    for (key, o) in [
        ("chuck.outline", chuck.and_then(|c| c.outline.as_ref())),
        ("tailstock.outline", tailstock.and_then(|t| t.outline.as_ref())),
        ("turret.outline", Some(&turret.outline)),
    ] {
        if let Some(o) = o {
            outlines.push((key.into(), o.span(), o.get_ref()));
        }
    }
    for (i, t) in tools.iter().enumerate() {
        for (which, v) in [("insert", &t.get_ref().insert), ("holder", &t.get_ref().holder)] {
            if let Some(pts) = v.as_ref().and_then(|v| v.get_ref().points()) {
                outlines.push((
                    format!("tools[{i}].{which}"),
                    v.as_ref().map_or(0..0, |v| v.span()),
                    pts,
                ));
            }
        }
    }
    let mut total = 0usize;
    for (key, span, o) in &outlines {
        let n = o.len();
        if n > MAX_OUTLINE_POINTS {
            return Err(cx.err(
                span.clone(),
                key.as_str(),
                format!("too many points: {n}; an outline may have at most {MAX_OUTLINE_POINTS}"),
            ));
        }
        total += n;
        if total > MAX_TOTAL_OUTLINE_POINTS {
            return Err(cx.err(
                span.clone(),
                key.as_str(),
                format!("too many outline points: the outlines up to this one have {total}; a machine file may have at most {MAX_TOTAL_OUTLINE_POINTS} in all"),
            ));
        }
    }
    Ok(())
}

/// `[machine]` read: the dialect and the settings that depend on it, each refused where it does
/// not apply (the default then stands in for it).
struct Header {
    name: String,
    /// `dialect = "auto"`: Fanuc's settings here, LinuxCNC's beside them (`Machine::auto_dialect`).
    auto: bool,
    dialect: Dialect,
    diameter_mode: bool,
    rapid: RapidMode,
    decimal_point: DecimalPoint,
    gcode_system: GcodeSystem,
    drilling_cycles: super::DrillingCycles,
    drill_r: Option<super::DrillR>,
    g71_d: super::G71D,
    min_depth: Option<f64>,
    turret_side: super::TurretSide,
    inch: bool,
}

/// `[machine]`: see [`Header`]; its errors are kept in `cx`.
fn header_of(cx: &Cx<'_>, hdr: &RawHeader) -> Header {
    let name = hdr.name.get_ref().trim().to_string();
    if name.is_empty() {
        cx.push(cx.err(hdr.name.span(), "machine.name", "must not be blank"));
    }
    let auto = matches!(hdr.dialect, Some(RawDialect::Auto));
    let dialect = match hdr.dialect.unwrap_or(RawDialect::Fanuc) {
        RawDialect::Fanuc | RawDialect::Auto => Dialect::Fanuc,
        RawDialect::Linuxcnc => Dialect::Linuxcnc,
    };
    let diameter_mode = hdr.diameter_mode.unwrap_or(dialect == Dialect::Fanuc);
    let rapid = match hdr.rapid.unwrap_or(RawRapid::Dogleg) {
        RawRapid::Dogleg => RapidMode::Dogleg,
        RawRapid::Linear => RapidMode::Linear,
    };
    let decimal_point = match &hdr.decimal_point {
        None => DecimalPoint::Calculator,
        Some(d) => match d.get_ref() {
            RawDecimalPoint::Calculator => DecimalPoint::Calculator,
            RawDecimalPoint::Increment if dialect == Dialect::Fanuc => DecimalPoint::Increment,
            RawDecimalPoint::Increment => {
                cx.push(cx.err(
                    d.span(),
                    "machine.decimal_point",
                    "\"increment\" applies to fanuc only: linuxcnc always reads X60 as 60",
                ));
                DecimalPoint::Calculator
            }
        },
    };
    let gcode_system = match &hdr.gcode_system {
        None => GcodeSystem::A,
        Some(g) => match g.get_ref() {
            RawGcodeSystem::A => GcodeSystem::A,
            RawGcodeSystem::B if dialect == Dialect::Fanuc => GcodeSystem::B,
            RawGcodeSystem::B => {
                cx.push(cx.err(
                    g.span(),
                    "machine.gcode_system",
                    "G-code system \"B\" applies to fanuc only: linuxcnc has one set of codes",
                ));
                GcodeSystem::A
            }
        },
    };
    let drilling_cycles = match &hdr.drilling_cycles {
        None => super::DrillingCycles::Haas,
        Some(d) => match d.get_ref() {
            RawDrilling::Haas => super::DrillingCycles::Haas,
            RawDrilling::Fanuc if dialect == Dialect::Fanuc && !auto => super::DrillingCycles::Fanuc,
            RawDrilling::Fanuc => {
                cx.push(cx.err(
                    d.span(),
                    "machine.drilling_cycles",
                    "drilling_cycles = \"fanuc\" applies to the fanuc dialect only",
                ));
                super::DrillingCycles::Haas
            }
        },
    };
    // The R of the drilling cycles and the D of G71/G72 are Fanuc-dialect words (LinuxCNC's
    // cycles have their own rules); Fanuc's live-tool cycles always read R from the initial level.
    let drill_r = hdr.drill_r.as_ref().and_then(|d| {
        let r = match d.get_ref() {
            RawDrillR::Absolute => super::DrillR::Absolute,
            RawDrillR::Incremental => super::DrillR::Incremental,
        };
        let why = if dialect != Dialect::Fanuc {
            Some("drill_r applies to the fanuc dialect only: linuxcnc's drilling cycles read R as rs274ngc does")
        } else if r == super::DrillR::Absolute && drilling_cycles == super::DrillingCycles::Fanuc {
            Some("drill_r = \"absolute\" does not go with drilling_cycles = \"fanuc\": Fanuc's drilling cycles read R as the distance from the initial level")
        } else {
            None
        };
        match why {
            Some(why) => {
                cx.push(cx.err(d.span(), "machine.drill_r", why));
                None
            }
            None => Some(r),
        }
    });
    let g71_d = match &hdr.g71_d {
        None => super::G71D::Length,
        Some(d) => match d.get_ref() {
            RawG71D::Length => super::G71D::Length,
            RawG71D::Increment if dialect == Dialect::Fanuc => super::G71D::Increment,
            RawG71D::Increment => {
                cx.push(cx.err(
                    d.span(),
                    "machine.g71_d",
                    "g71_d = \"increment\" applies to the fanuc dialect only",
                ));
                super::G71D::Length
            }
        },
    };
    let min_depth = hdr
        .min_depth
        .as_ref()
        .and_then(|v| cx.keep(cx.within("machine.min_depth", v, crate::pipeline::MIN_DEPTH_MM, "mm")));
    Header {
        name,
        auto,
        dialect,
        diameter_mode,
        rapid,
        decimal_point,
        gcode_system,
        drilling_cycles,
        drill_r,
        g71_d,
        min_depth,
        turret_side: match hdr.turret_side {
            None | Some(RawTurretSide::Rear) => super::TurretSide::Rear,
            Some(RawTurretSide::Front) => super::TurretSide::Front,
        },
        inch: matches!(hdr.units, Some(RawUnits::Inch)),
    }
}

/// `[axes]` read; each value None where refused (or where what it is checked against is).
pub(super) struct AxesOf {
    pub(super) x: Option<Axis>,
    pub(super) z: Option<Axis>,
    pub(super) home: Option<P2>,
    pub(super) machine_zero: Option<P2>,
    pub(super) reference_points: Option<Vec<P2>>,
}

/// `[axes]`: the two axes, home inside their limits (default: both maxima), machine zero
/// (default: home) and the reference points.
pub(super) fn axes_of(cx: &Cx<'_>, axes: &RawAxes) -> AxesOf {
    let x = cx.keep(cx.axis("axes.x", &axes.x));
    let z = cx.keep(cx.axis("axes.z", &axes.z));
    let home = match (&axes.home, x, z) {
        (None, Some(x), Some(z)) => Some(p2(x.max, z.max)),
        (None, _, _) => None,
        (Some(h), x, z) => {
            let p = cx.keep(cx.point("axes.home", h));
            match (p, x, z) {
                (Some(p), Some(x), Some(z)) if p.x < x.min || p.x > x.max || p.y < z.min || p.y > z.max => {
                    cx.push(cx.err(
                        h.span(),
                        "axes.home",
                        format!(
                            "home [{}, {}] lies outside the axis limits (x {} .. {}, z {} .. {})",
                            show(p.x),
                            show(p.y),
                            show(x.min),
                            show(x.max),
                            show(z.min),
                            show(z.max)
                        ),
                    ));
                    None
                }
                (p, _, _) => p,
            }
        }
    };
    let machine_zero = match &axes.machine_zero {
        None => home,
        Some(p) => cx.keep(cx.point("axes.machine_zero", p)),
    };
    let reference_points = reference_points(cx, axes.reference_points.as_ref(), x, z);
    AxesOf {
        x,
        z,
        home,
        machine_zero,
        reference_points,
    }
}

/// `[stock]`: a bar (`diameter`, `length`, `front`, `bore`) or a revolved `outline`, not both;
/// Some(None) when the file has none, None when refused.
fn stock_of(cx: &Cx<'_>, raw: Option<&Spanned<RawStock>>) -> Option<Option<Stock>> {
    let Some(raw) = raw else { return Some(None) };
    let (table, s) = (raw.span(), raw.get_ref());
    if s.outline.is_some() {
        let mut ok = true;
        for (k, v) in [
            ("diameter", s.diameter.as_ref()),
            ("length", s.length.as_ref()),
            ("front", s.front.as_ref()),
            ("bore", s.bore.as_ref()),
        ] {
            if let Some(v) = v {
                cx.push(cx.err(
                    v.span(),
                    format!("stock.{k}"),
                    "a stock with an `outline` takes its sizes from it: give the outline or diameter, length and front, not both",
                ));
                ok = false;
            }
        }
        let o = s
            .outline
            .as_ref()
            .and_then(|o| cx.keep(cx.stock_outline("stock.outline", o)));
        return o.filter(|_| ok).map(|o| Some(Stock::from_outline(o)));
    }
    for (k, v) in [("diameter", &s.diameter), ("length", &s.length), ("front", &s.front)] {
        if v.is_none() {
            cx.push(cx.err(
                table.clone(),
                format!("stock.{k}"),
                format!("missing required key `{k}` (or give a revolved `outline` instead)"),
            ));
        }
    }
    let (rd, rl, rf) = (s.diameter.as_ref(), s.length.as_ref(), s.front.as_ref());
    let diameter = rd.and_then(|v| cx.keep(cx.length("stock.diameter", v)));
    let length = rl.and_then(|v| cx.keep(cx.length("stock.length", v)));
    let front = rf.and_then(|v| cx.keep(cx.coord("stock.front", v)));
    let bore = match &s.bore {
        None => Some(0.0),
        Some(b) => cx.keep(cx.non_negative("stock.bore", b)),
    };
    if let (Some(front), Some(length), Some(rl)) = (front, length, rl) {
        if front - length < -MAX_COORD_MM {
            cx.push(cx.err(
                rl.span(),
                "stock.length",
                format!(
                    "the bar's back end (front − length = {}) is out of range: coordinates must be from {} to {} mm",
                    show(front - length),
                    show(-MAX_COORD_MM),
                    show(MAX_COORD_MM)
                ),
            ));
        }
    }
    if let (Some(bore), Some(diameter)) = (bore, diameter) {
        if bore >= diameter {
            let at = s.bore.as_ref().map_or(0..0, |b| b.span());
            cx.push(cx.err(
                at,
                "stock.bore",
                format!(
                    "the bore ({}) must be smaller than the diameter ({})",
                    show(bore),
                    show(diameter)
                ),
            ));
        }
    }
    match (diameter, length, front, bore) {
        (Some(diameter), Some(length), Some(front), Some(bore)) => {
            Some(Some(Stock::bar(diameter, length, front, bore)))
        }
        _ => None,
    }
}

/// `[setup]`: the work offsets (each doubted against the Z travel, when `z` and `machine_zero`
/// are valid) and program zero's Z — `program_zero_z`, else G54, else the stock's front (the
/// jaw faces without stock); None when refused.
fn setup_of(
    cx: &Cx<'_>,
    setup: Option<&RawSetup>,
    z: Option<Axis>,
    machine_zero: Option<P2>,
    stock: Option<&Option<Stock>>,
) -> ([Option<super::WorkOffset>; 6], Option<f64>) {
    let given = setup
        .and_then(|s| s.work_offsets.as_ref())
        .map(|w| work_offsets(cx, w, "setup.work_offsets"))
        .unwrap_or_default();
    let mut offsets: [Option<super::WorkOffset>; 6] = [None; 6];
    for g in &given {
        offsets[g.n] = Some(g.value);
        if let (Some(z), Some(mz)) = (z, machine_zero) {
            if let Some(why) = work_offset_doubt(&z, mz, g.value) {
                cx.warn(g.at.clone(), &g.key, why);
            }
        }
    }
    let g54 = given.iter().find(|g| g.n == 0);
    let program_zero_z = match (setup.and_then(|s| s.program_zero_z.as_ref()), g54) {
        (Some(v), Some(g)) => {
            cx.push(cx.err(
                v.span(),
                "setup.program_zero_z",
                format!(
                    "program zero is given twice: by setup.program_zero_z and by {} (G54 is program zero at start); give one of them",
                    g.key
                ),
            ));
            None
        }
        (Some(v), None) => cx.keep(cx.coord("setup.program_zero_z", v)),
        (None, Some(g)) => machine_zero.map(|mz| mz.y + g.value.z),
        (None, None) => stock.map(|s| s.as_ref().map_or(0.0, |s| s.front)),
    };
    (offsets, program_zero_z)
}

/// `[turret]`: its station count (None where refused; the tools are checked against it) and
/// the turret, None when any of its values is refused.
pub(super) fn turret_of(cx: &Cx<'_>, turret: &RawTurret) -> (Option<u32>, Option<Turret>) {
    let stations = *turret.stations.get_ref();
    let stations = if (1..=i64::from(MAX_STATIONS)).contains(&stations) {
        Some(stations as u32)
    } else {
        cx.push(cx.err(
            turret.stations.span(),
            "turret.stations",
            format!("{stations} stations: a turret has 1 to {MAX_STATIONS}"),
        ));
        None
    };
    let start_station = match (&turret.start_station, stations) {
        (None, _) => Some(1),
        (Some(_), None) => None,
        (Some(s), Some(stations)) => {
            let v = *s.get_ref();
            if (1..=stations).contains(&v) {
                Some(v)
            } else {
                cx.push(cx.err(
                    s.span(),
                    "turret.start_station",
                    format!("station {v} does not exist: the turret has stations 1 to {stations}"),
                ));
                None
            }
        }
    };
    let kind = match turret.kind.unwrap_or(RawTurretKind::Drum) {
        RawTurretKind::Drum => super::TurretKind::Drum,
        RawTurretKind::Gang => super::TurretKind::Gang,
    };
    let axis = match (&turret.axis, kind) {
        (Some(a), _) => cx.keep(cx.coord("turret.axis", a)),
        // A gang slide turns nothing: its axis is never used.
        (None, super::TurretKind::Gang) => Some(0.0),
        (None, super::TurretKind::Drum) => {
            cx.push(cx.err(
                turret.stations.span(),
                "turret.axis",
                "missing required key `turret.axis`: a drum turret needs its axis (only a gang slide, `type = \"gang\"`, has none)",
            ));
            None
        }
    };
    let index_time = cx.keep(cx.within(
        "turret.index_time",
        &turret.index_time,
        INDEX_TIME_RANGE,
        "s per station",
    ));
    if let Some(t) = index_time.filter(|&t| t > 5.0) {
        cx.warn(
            turret.index_time.span(),
            "turret.index_time",
            format!(
                "index_time = {} s per station is implausibly slow: the unit is seconds",
                show(t)
            ),
        );
    }
    let outline = cx.keep(cx.outline("turret.outline", &turret.outline));
    let turret = match (stations, start_station, axis, index_time, outline) {
        (Some(stations), Some(start_station), Some(axis), Some(index_time), Some(outline)) => Some(Turret {
            kind,
            stations,
            start_station,
            axis,
            index_time,
            outline,
        }),
        _ => None,
    };
    (stations, turret)
}

/// `[spindle]`: `max_rpm`, and `start_rpm` (Some(None) when not given); None where refused.
fn spindle_of(cx: &Cx<'_>, spindle: &RawSpindle) -> (Option<f64>, Option<Option<f64>>) {
    let max_rpm = cx.keep(cx.within("spindle.max_rpm", &spindle.max_rpm, MAX_RPM_RANGE, "rpm"));
    match max_rpm {
        Some(r) if r < 100.0 => cx.warn(
            spindle.max_rpm.span(),
            "spindle.max_rpm",
            format!(
                "max_rpm = {} is implausibly low for a lathe spindle: the unit is rev/min (was it rev/s?)",
                show(r)
            ),
        ),
        Some(r) if r > 50_000.0 => cx.warn(
            spindle.max_rpm.span(),
            "spindle.max_rpm",
            format!(
                "max_rpm = {} is implausibly high for a lathe spindle: the unit is rev/min",
                show(r)
            ),
        ),
        _ => {}
    }
    let start_rpm = match (&spindle.start_rpm, max_rpm) {
        (None, _) => Some(None),
        (Some(v), max) => match cx.keep(cx.within("spindle.start_rpm", v, MAX_RPM_RANGE, "rpm")) {
            Some(r) if max.is_some_and(|m| r > m) => {
                cx.push(cx.err(
                    v.span(),
                    "spindle.start_rpm",
                    format!(
                        "start_rpm = {} is faster than max_rpm = {}",
                        show(r),
                        show(max.unwrap_or(0.0))
                    ),
                ));
                None
            }
            r => r.map(Some),
        },
    };
    (max_rpm, start_rpm)
}

/// `[[tools]]`: each entry validated (its station against `stations`, when that is valid), the
/// valid ones by station.
pub(super) fn tools_of(
    cx: &Cx<'_>,
    tools: &[Spanned<RawTool>],
    stations: Option<u32>,
    machine_zero: Option<P2>,
) -> Vec<Tool> {
    let mut owner: Vec<Option<usize>> = vec![None; stations.unwrap_or(0) as usize + 1];
    let mut out = Vec::with_capacity(tools.len());
    for (i, t) in tools.iter().enumerate() {
        let entry = t.span();
        let t = t.get_ref();
        let key = |k: &str| format!("tools[{i}].{k}");
        let station = *t.station.get_ref();
        let station_ok = match stations {
            None => false,
            Some(stations) if !(1..=stations).contains(&station) => {
                cx.push(cx.err(
                    t.station.span(),
                    key("station"),
                    format!("station {station} does not exist: the turret has stations 1 to {stations}"),
                ));
                false
            }
            Some(_) => match owner[station as usize] {
                Some(j) => {
                    cx.push(cx.err(
                        t.station.span(),
                        key("station"),
                        format!(
                            "station {station} is already taken by tools[{j}] ({:?})",
                            tools[j].get_ref().name.get_ref()
                        ),
                    ));
                    false
                }
                None => {
                    owner[station as usize] = Some(i);
                    true
                }
            },
        };
        let name = t.name.get_ref().trim().to_string();
        if name.is_empty() {
            cx.push(cx.err(t.name.span(), key("name"), "must not be blank"));
        }
        // `tip`, or `geometry_offset` turned into one with machine zero (None when that is invalid:
        // its own error is kept).
        let tip = match cx.keep(tool_entry::placing(
            cx,
            &format!("tools[{i}]"),
            t.tip.as_ref(),
            t.geometry_offset.as_ref(),
        )) {
            Some(Some(p)) => machine_zero.map(|mz| p.tip(mz)),
            Some(None) => {
                cx.push(cx.err(
                    entry.clone(),
                    key("tip"),
                    "missing required key `tip` (the programmed point from the turret reference point; or `geometry_offset`, as the control's geometry page shows it)",
                ));
                None
            }
            None => None,
        };
        // An outline or a designation (Some(None): not given), then the catalogue's tool.
        let shape = |which: &str, v: &Option<Spanned<Shape>>| match v {
            None => Some(None),
            Some(v) => cx
                .keep(tool_entry::geom(cx, &key(which), v))
                .map(|g| Some((g, (v.span(), key(which))))),
        };
        let (insert, holder) = (shape("insert", &t.insert), shape("holder", &t.holder));
        let drill = match &t.drill {
            None => Some(None),
            Some(d) => cx
                .keep(tool_entry::drill(cx, &key("drill"), d.get_ref()))
                .map(|s| Some((s, (d.span(), key("drill"))))),
        };
        let built = match (&insert, &holder, &drill) {
            (Some(i), Some(h), Some(d)) => {
                use tool_entry::given;
                match tool_entry::build(given(i), given(h), given(d)) {
                    Ok(b) => Some(b),
                    Err(((span, k), message)) => {
                        cx.push(cx.err(span, k, message));
                        None
                    }
                }
            }
            _ => None,
        };
        let outline = |which: &str, g: Option<GivenShape>| match (g, &built) {
            (Some(Some((tool_entry::Geom::Outline(o), _))), _) => Some(o),
            (Some(_), Some(Some(b))) => Some(if which == "insert" {
                b.insert.clone()
            } else {
                b.holder.clone()
            }),
            (Some(None), Some(None)) => {
                cx.push(cx.err(
                    entry.clone(),
                    key(which),
                    format!("missing required key `{which}`: give an outline, a catalogue designation or `drill`"),
                ));
                None
            }
            _ => None,
        };
        let (insert, holder) = (outline("insert", insert), outline("holder", holder));
        let built = built.flatten();
        let nose_radius = match &t.nose_radius {
            None => Some(built.as_ref().map_or(0.0, |b| b.nose_radius)),
            Some(r) => cx.keep(cx.within(&key("nose_radius"), r, NOSE_RADIUS_RANGE, "mm")),
        };
        let tip_direction = match &t.tip_direction {
            None => Some(built.as_ref().map_or(0, |b| b.tip_direction)),
            Some(d) => match u8::try_from(*d.get_ref()) {
                Ok(v) if v <= 9 => Some(v),
                _ => {
                    cx.push(cx.err(
                        d.span(),
                        key("tip_direction"),
                        format!(
                            "{} is not a tip direction: give a whole number from 0 to 9",
                            d.get_ref()
                        ),
                    ));
                    None
                }
            },
        };
        if let (true, Some(tip), Some(insert), Some(holder), Some(nose_radius), Some(tip_direction)) =
            (station_ok, tip, insert, holder, nose_radius, tip_direction)
        {
            out.push(Tool {
                station,
                cutter: tool_entry::cutter(built.as_ref(), &name),
                name,
                tip,
                insert,
                holder,
                nose_radius,
                tip_direction,
                mill: None,
            });
        }
    }
    out.sort_by_key(|t| t.station);
    out
}

/// `axes.reference_points`: at most 3 points (the 2nd to 4th reference points), each inside both
/// axes' limits; empty when absent (G30 then returns home).
fn reference_points(
    cx: &Cx<'_>,
    raw: Option<&Spanned<Vec<Point>>>,
    x: Option<Axis>,
    z: Option<Axis>,
) -> Option<Vec<P2>> {
    let Some(raw) = raw else { return Some(Vec::new()) };
    if raw.get_ref().len() > 3 {
        cx.push(cx.err(
            raw.span(),
            "axes.reference_points",
            format!(
                "{} points: these are the 2nd, 3rd and 4th reference points (G30 P2 to P4), at most 3",
                raw.get_ref().len()
            ),
        ));
        return None;
    }
    let mut out = Vec::with_capacity(3);
    let mut ok = true;
    for (i, p) in raw.get_ref().iter().enumerate() {
        let key = format!("axes.reference_points[{i}]");
        match (cx.keep(cx.point(&key, p)), x, z) {
            (Some(q), Some(x), Some(z)) if q.x < x.min || q.x > x.max || q.y < z.min || q.y > z.max => {
                cx.push(cx.err(
                    p.span(),
                    key,
                    format!(
                        "the {} reference point [{}, {}] lies outside the axis limits (x {} .. {}, z {} .. {})",
                        ["2nd", "3rd", "4th"][i],
                        show(q.x),
                        show(q.y),
                        show(x.min),
                        show(x.max),
                        show(z.min),
                        show(z.max)
                    ),
                ));
                ok = false;
            }
            (Some(q), _, _) => out.push(q),
            (None, _, _) => ok = false,
        }
    }
    ok.then_some(out)
}

/// `[chuck]`: its `outline`, its `barrier` or its `body` and `jaws`, exactly one; None when
/// refused (or when the barrier's program zero is).
fn chuck_part(cx: &Cx<'_>, c: &RawPart, program_zero_z: Option<f64>) -> Option<(Polygon, super::ChuckForm)> {
    use super::ChuckForm;
    let parts = c.body.is_some() || c.jaws.is_some();
    if let (true, Some(o)) = (parts, &c.outline) {
        cx.push(cx.err(
            o.span(),
            "chuck.outline",
            "give the chuck either as `outline` or as its `body` and `jaws`, not both",
        ));
        return None;
    }
    if let (true, Some(b)) = (parts, &c.barrier) {
        cx.push(cx.err(
            b.ty.span(),
            "chuck.barrier",
            "give the chuck either as Fanuc's `barrier` parameters or as its `body` and `jaws`, not both",
        ));
        return None;
    }
    if parts {
        return chuck_of_parts(cx, c).map(|(p, ch)| (p, ChuckForm::Jaws(ch)));
    }
    let polygon = chuck_drawn(cx, c, program_zero_z)?;
    let form = if c.outline.is_some() {
        ChuckForm::Outline
    } else {
        ChuckForm::Barrier
    };
    Some((polygon, form))
}

/// `[chuck] body` and `[chuck.jaws]`, both given: their sizes and the outline drawn from them.
fn chuck_of_parts(cx: &Cx<'_>, c: &RawPart) -> Option<(Polygon, super::jaws::Chuck)> {
    use super::jaws;
    let (body, raw_jaws) = match (&c.body, &c.jaws) {
        (Some(b), Some(j)) => (b, j),
        (Some(b), None) => {
            cx.push(cx.err(
                b.span(),
                "chuck.jaws",
                "missing required table `[chuck.jaws]`: a chuck given by its `body` needs its jaws",
            ));
            return None;
        }
        (None, Some(j)) => {
            cx.push(cx.err(
                j.span(),
                "chuck.body",
                "missing required key `chuck.body`: jaws stand on a chuck body, `body = { diameter, bore, face, depth }`",
            ));
            return None;
        }
        (None, None) => return None,
    };
    let (b, j) = (body.get_ref(), raw_jaws.get_ref());
    let diameter = cx.keep(cx.length("chuck.body.diameter", &b.diameter));
    let bore = match &b.bore {
        None => Some(0.0),
        Some(v) => cx.keep(cx.non_negative("chuck.body.bore", v)),
    };
    let face = cx.keep(cx.coord("chuck.body.face", &b.face));
    let depth = cx.keep(cx.length("chuck.body.depth", &b.depth));
    let grip_diameter = cx.keep(cx.length("chuck.jaws.grip_diameter", &j.grip_diameter));
    let grip_length = cx.keep(cx.length("chuck.jaws.grip_length", &j.grip_length));
    let height = cx.keep(cx.length("chuck.jaws.height", &j.height));
    let width = cx.keep(cx.length("chuck.jaws.width", &j.width));
    let step = cx.keep(cx.length("chuck.jaws.step", &j.step));
    let (
        Some(diameter),
        Some(bore),
        Some(face),
        Some(depth),
        Some(grip_diameter),
        Some(grip_length),
        Some(height),
        Some(width),
        Some(step),
    ) = (
        diameter,
        bore,
        face,
        depth,
        grip_diameter,
        grip_length,
        height,
        width,
        step,
    )
    else {
        return None;
    };
    let chuck = jaws::Chuck {
        body: jaws::Body {
            diameter,
            bore,
            face,
            depth,
        },
        jaws: jaws::Jaws {
            grip: j.grip.as_ref().map_or(jaws::Grip::Outside, |g| g.get_ref().value()),
            kind: j.kind.as_ref().map_or(jaws::JawType::Hard, |k| k.get_ref().value()),
            grip_diameter,
            grip_length,
            height,
            width,
            step,
        },
    };
    let span = |key: &str| match key {
        "body.diameter" => b.diameter.span(),
        "body.bore" => b.bore.as_ref().map_or(body.span(), |v| v.span()),
        "body.face" => b.face.span(),
        "body.depth" => b.depth.span(),
        "jaws.grip_diameter" => j.grip_diameter.span(),
        "jaws.grip_length" => j.grip_length.span(),
        "jaws.height" => j.height.span(),
        "jaws.width" => j.width.span(),
        "jaws.step" => j.step.span(),
        _ => raw_jaws.span(),
    };
    let polygon = chuck
        .polygon()
        .map_err(|e| {
            let key = e.keys.first().copied().unwrap_or("jaws");
            cx.push(cx.err(span(key), format!("chuck.{key}"), e.message));
        })
        .ok()?;
    Some((polygon, chuck))
}

/// `[chuck]` drawn: its `outline` or its `barrier`, exactly one.
fn chuck_drawn(cx: &Cx<'_>, c: &RawPart, program_zero_z: Option<f64>) -> Option<Polygon> {
    match (&c.outline, &c.barrier) {
        (Some(o), None) => cx.keep(cx.outline("chuck.outline", o)),
        (None, Some(b)) => {
            let ty = *b.ty.get_ref();
            let ty = if (0..=1).contains(&ty) {
                Some(ty as u8)
            } else {
                cx.push(cx.err(
                    b.ty.span(),
                    "chuck.barrier.ty",
                    format!(
                        "TY is 0 (the jaws hold the part on its inner surface) or 1 (on its outer surface), not {ty}"
                    ),
                ));
                None
            };
            let cxv = cx.keep(cx.coord("chuck.barrier.cx", &b.cx));
            let cz = cx.keep(cx.coord("chuck.barrier.cz", &b.cz));
            let l = cx.keep(cx.length("chuck.barrier.l", &b.l));
            let w = cx.keep(cx.length("chuck.barrier.w", &b.w));
            let l1 = cx.keep(cx.length("chuck.barrier.l1", &b.l1));
            let w1 = cx.keep(cx.length("chuck.barrier.w1", &b.w1));
            let (Some(ty), Some(cxv), Some(cz), Some(l), Some(w), Some(l1), Some(w1), Some(pz)) =
                (ty, cxv, cz, l, w, l1, w1, program_zero_z)
            else {
                return None;
            };
            let bar = super::barrier::ChuckBarrier {
                ty,
                cx: cxv,
                cz,
                l,
                w,
                l1,
                w1,
            };
            let span = |k: &str| match k {
                "ty" => b.ty.span(),
                "cx" => b.cx.span(),
                "cz" => b.cz.span(),
                "l" => b.l.span(),
                "w" => b.w.span(),
                "l1" => b.l1.span(),
                _ => b.w1.span(),
            };
            barrier_polygon(cx, "chuck", bar.outline(pz), span, b.cz.span())
        }
        (Some(o), Some(_)) => {
            cx.push(cx.err(
                o.span(),
                "chuck.outline",
                "give the chuck either as `outline` or as Fanuc's `barrier` parameters, not both",
            ));
            None
        }
        (None, None) => {
            cx.push(cx.err(
                0..0,
                "chuck.outline",
                "missing required key `chuck.outline` (or `chuck.barrier`, or `chuck.body` with `[chuck.jaws]`)",
            ));
            None
        }
    }
}

/// `[tailstock]`: its `outline` or its `barrier`, exactly one, as [`chuck_part`].
fn tailstock_part(cx: &Cx<'_>, t: &RawTailstock, program_zero_z: Option<f64>) -> Option<Polygon> {
    match (&t.outline, &t.barrier) {
        (Some(o), None) => cx.keep(cx.outline("tailstock.outline", o)),
        (None, Some(b)) => {
            let tz = cx.keep(cx.coord("tailstock.barrier.tz", &b.tz));
            let l = cx.keep(cx.length("tailstock.barrier.l", &b.l));
            let d = cx.keep(cx.length("tailstock.barrier.d", &b.d));
            let l1 = cx.keep(cx.length("tailstock.barrier.l1", &b.l1));
            let d1 = cx.keep(cx.length("tailstock.barrier.d1", &b.d1));
            let l2 = cx.keep(cx.length("tailstock.barrier.l2", &b.l2));
            let d2 = cx.keep(cx.length("tailstock.barrier.d2", &b.d2));
            let d3 = cx.keep(cx.non_negative("tailstock.barrier.d3", &b.d3)).and_then(|v| {
                (v <= MAX_COORD_MM).then_some(v).or_else(|| {
                    cx.push(cx.err(
                        b.d3.span(),
                        "tailstock.barrier.d3",
                        format!("{} is out of range: at most {} mm", show(v), show(MAX_COORD_MM)),
                    ));
                    None
                })
            });
            let (Some(tz), Some(l), Some(d), Some(l1), Some(d1), Some(l2), Some(d2), Some(d3), Some(pz)) =
                (tz, l, d, l1, d1, l2, d2, d3, program_zero_z)
            else {
                return None;
            };
            let bar = super::barrier::TailstockBarrier {
                tz,
                l,
                d,
                l1,
                d1,
                l2,
                d2,
                d3,
            };
            let span = |k: &str| match k {
                "tz" => b.tz.span(),
                "l" => b.l.span(),
                "d" => b.d.span(),
                "l1" => b.l1.span(),
                "d1" => b.d1.span(),
                "l2" => b.l2.span(),
                "d2" => b.d2.span(),
                _ => b.d3.span(),
            };
            barrier_polygon(cx, "tailstock", bar.outline(pz), span, b.tz.span())
        }
        (Some(o), Some(_)) => {
            cx.push(cx.err(
                o.span(),
                "tailstock.outline",
                "give the tailstock either as `outline` or as Fanuc's `barrier` parameters, not both",
            ));
            None
        }
        (None, None) => {
            cx.push(cx.err(
                0..0,
                "tailstock.outline",
                "missing required key `tailstock.outline` (or `tailstock.barrier`)",
            ));
            None
        }
    }
}

/// The polygon of a barrier's outline, or its error at the key it names (`chuck.barrier.l1`).
/// A point out of range (program zero plus CZ or TZ past ±100 m) is the position's error.
fn barrier_polygon(
    cx: &Cx<'_>,
    part: &str,
    pts: Result<Vec<P2>, super::barrier::BarrierError>,
    span: impl Fn(&str) -> Range<usize>,
    position: Range<usize>,
) -> Option<Polygon> {
    let pts = match pts {
        Ok(p) => p,
        Err(e) => {
            cx.push(cx.err(span(e.key), format!("{part}.barrier.{}", e.key), e.message));
            return None;
        }
    };
    let pos_key = if part == "chuck" { "cz" } else { "tz" };
    if let Some(p) = pts
        .iter()
        .find(|p| p.x.abs() > MAX_COORD_MM || p.y.abs() > MAX_COORD_MM)
    {
        cx.push(cx.err(
            position,
            format!("{part}.barrier.{pos_key}"),
            format!(
                "the outline reaches [{}, {}] from program Z0 at z = setup.program_zero_z: coordinates must be from {} to {} mm",
                show(p.x),
                show(p.y),
                show(-MAX_COORD_MM),
                show(MAX_COORD_MM)
            ),
        ));
        return None;
    }
    match Polygon::new(&pts) {
        Ok(p) => Some(p),
        Err(e) => {
            cx.push(cx.err(
                position,
                format!("{part}.barrier"),
                format!("the barrier gives no outline: {e}"),
            ));
            None
        }
    }
}

/// A part that overlaps the chuck or the tailstock at home: [`home_clashes`].
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HomeClash {
    /// None: the turret; Some((station, "holder" | "insert")): that tool's part.
    pub(crate) tool: Option<(u32, &'static str)>,
    /// `"chuck"` or `"tailstock"`.
    pub(crate) obstacle: &'static str,
    pub(crate) message: String,
}

/// At home with the start station facing the spindle, the turret and every tool (the start
/// station's in the working plane, the others turned out of it) must be clear of the chuck and
/// the tailstock: a machine whose parts already overlap before anything moves is a setup error.
/// The test poses the parts as the checker does ([`Scene`](crate::scene::Scene)). Shared by
/// machine files and jobs (which change the chuck, the tailstock and the tools).
pub(crate) fn home_clashes(machine: &Machine) -> Vec<HomeClash> {
    use crate::geom::overlap;
    use crate::scene::{Scene, Section};
    let mut out = Vec::new();
    if machine.chuck.is_none() && machine.tailstock.is_none() {
        return out;
    }
    let scene = Scene::new(machine, HOME_CHECK_TOLERANCE);
    let home = machine.home;
    let start = machine.turret.start_station;
    let statics: Vec<_> = [&scene.chuck, &scene.tailstock].into_iter().flatten().collect();
    let hit = |shape: &Polygon, in_plane: bool| -> Option<(&'static str, f64)> {
        statics.iter().find_map(|r| {
            let d = overlap(shape, &r.outline).or_else(|| if in_plane { overlap(shape, &r.mirror) } else { None });
            d.map(|d| (r.name, d))
        })
    };
    let where_ = format!(
        "at home [{}, {}] with station {start} facing the spindle",
        show(home.x),
        show(home.y)
    );
    if let Some((what, d)) = hit(&scene.turret.translated(home.coords), true) {
        out.push(HomeClash {
            tool: None,
            obstacle: what,
            message: format!("{where_}, the turret overlaps the {what} by {d:.3} mm: move axes.home or the parts"),
        });
    }
    for tool in &machine.tools {
        let station = tool.station;
        let Some(t) = scene.tool(station) else { continue };
        for (part, shape) in [("holder", &t.holder), ("insert", &t.insert)] {
            let (posed, in_plane) = if station == start {
                (Some(Section::Whole(shape.translated(home.coords + t.tip))), true)
            } else {
                let angle = scene.station_angle(station, start as f64);
                (scene.map_to_section(shape, t.tip, home, angle), false)
            };
            let Some(posed) = posed else { continue };
            // The deepest piece of a folded section (scene/section.rs).
            let found = posed.pieces().iter().filter_map(|p| hit(p, in_plane));
            if let Some((what, d)) = found.fold(None, |a: Option<(&str, f64)>, b| match a {
                Some(a) if a.1 >= b.1 => Some(a),
                _ => Some(b),
            }) {
                out.push(HomeClash {
                    tool: Some((station, part)),
                    obstacle: what,
                    message: format!(
                        "{where_}, the {part} of the tool in station {station} overlaps the {what} by {d:.3} mm: move axes.home or the tool"
                    ),
                });
            }
        }
    }
    out
}

pub(super) fn clear_at_home(cx: &Cx<'_>, machine: &Machine, turret_outline: &Outline, raw_tools: &[Spanned<RawTool>]) {
    for c in home_clashes(machine) {
        match c.tool {
            None => cx.push(cx.err(turret_outline.span(), "turret.outline", c.message)),
            Some((station, part)) => {
                let Some(i) = raw_tools.iter().position(|t| *t.get_ref().station.get_ref() == station) else {
                    continue;
                };
                let raw = raw_tools[i].get_ref();
                cx.push(cx.err(raw.span_of(part), format!("tools[{i}].{part}"), c.message));
            }
        }
    }
}

/// Which key a stock that does not fit the chuck is about: [`stock_clash`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum StockKey {
    Length,
    Diameter,
    /// A revolved outline overlaps the chuck.
    Outline,
}

/// The stock (a bar or tube from `front − length` to `front`, radius `diameter / 2`, bore
/// `bore / 2`, revolved like the chuck) must not overlap the chuck: the jaws grip it at their
/// faces, where the two touch. When even the innermost skin of the stock overlaps the chuck, no
/// diameter would fit and the problem is the length (the bar reaches into the chuck body);
/// otherwise the diameter (the bar is wider than the chuck's bore where it reaches). Shared by
/// machine files and jobs.
pub(crate) fn stock_clash(machine: &Machine, stock: &Stock) -> Option<(StockKey, String)> {
    use crate::geom::overlap;
    let chuck = machine.chuck.as_ref()?;
    if let Some(o) = &stock.outline {
        let d = overlap(o, chuck)?;
        return Some((
            StockKey::Outline,
            format!(
                "the stock outline (Ø{} max, z {} .. {}) overlaps the chuck by {d:.3} mm: the jaws grip it where their faces touch it, they cannot reach into it",
                show(stock.diameter),
                show(stock.front - stock.length),
                show(stock.front)
            ),
        ));
    }
    let (r_in, r_out) = (stock.bore / 2.0, stock.diameter / 2.0);
    let (back, front) = (stock.front - stock.length, stock.front);
    let rect = |x0: f64, x1: f64| Polygon::new(&[p2(x0, back), p2(x1, back), p2(x1, front), p2(x0, front)]).ok();
    let bar = rect(r_in, r_out)?;
    let d = overlap(&bar, chuck)?;
    let skin = rect(r_in, r_in + (r_out - r_in).min(0.1));
    let kind = if stock.bore > 0.0 { "tube" } else { "bar" };
    let what = format!(
        "the {kind} (Ø{}, z {} .. {}) overlaps the chuck by {d:.3} mm",
        show(stock.diameter),
        show(back),
        show(front)
    );
    // A part in soft jaws rests on their seat: a bar that fits the bored grip but reaches past
    // the seat is too long, not too wide.
    if let Some(c) = machine.chuck_jaws() {
        let j = &c.jaws;
        let seat = c.faces() - j.grip_length;
        let soft_outside = j.kind == super::jaws::JawType::Soft && j.grip == super::jaws::Grip::Outside;
        if soft_outside && r_out <= j.grip_diameter / 2.0 && back < seat {
            return Some((
                StockKey::Length,
                format!(
                    "{what}: its back end reaches past the soft jaws' seat at z {} (a part in soft jaws rests on it); make it at most {} mm long or move stock.front",
                    show(seat),
                    show(front - seat)
                ),
            ));
        }
    }
    if skin.and_then(|s| overlap(&s, chuck)).is_some() {
        Some((
            StockKey::Length,
            format!("{what}: its back end reaches into the chuck body, whatever its diameter; shorten it or move stock.front"),
        ))
    } else {
        Some((
            StockKey::Diameter,
            format!("{what}: it is wider than the chuck's bore where it reaches (the jaws grip it where their faces touch it)"),
        ))
    }
}

fn stock_fits_chuck(cx: &Cx<'_>, machine: &Machine, stock: &Stock, raw: &RawStock) -> Result<(), MachineError> {
    let span = |v: &Option<Num>| v.as_ref().map_or(0..0, |v| v.span());
    match stock_clash(machine, stock) {
        None => Ok(()),
        Some((StockKey::Outline, m)) => {
            Err(cx.err(raw.outline.as_ref().map_or(0..0, |o| o.span()), "stock.outline", m))
        }
        Some((StockKey::Length, m)) => Err(cx.err(span(&raw.length), "stock.length", m)),
        Some((StockKey::Diameter, m)) => Err(cx.err(span(&raw.diameter), "stock.diameter", m)),
    }
}

/// `[mcodes]`: each key an action, each value its codes (0 ..= 999, none reserved for the
/// interpreter, none given for two actions), over the dialect's built-in table.
fn mcode_table(
    cx: &Cx<'_>,
    dialect: Dialect,
    raw: Option<&std::collections::BTreeMap<String, Spanned<RawCodes>>>,
) -> Result<McodeTable, MachineError> {
    let Some(raw) = raw else {
        return Ok(McodeTable::builtin(dialect));
    };
    let mut given: Vec<(MAction, Vec<u16>)> = Vec::new();
    let mut owner: std::collections::HashMap<u16, &str> = std::collections::HashMap::new();
    for (name, v) in raw {
        let key = format!("mcodes.{name}");
        let Some(action) = MAction::from_name(name) else {
            let names: Vec<&str> = MCODE_ACTIONS.iter().map(|a| a.0).collect();
            return Err(cx.err(
                v.span(),
                key,
                format!("unknown M-code action `{name}`: expected one of {}", names.join(", ")),
            ));
        };
        let list = match v.get_ref() {
            RawCodes::One(c) => vec![*c],
            RawCodes::Many(cs) => cs.clone(),
        };
        if list.len() > usize::from(MAX_MCODE) + 1 {
            return Err(cx.err(v.span(), key, "too many codes for one action"));
        }
        let mut codes = Vec::with_capacity(list.len());
        for c in list {
            if !(0..=i64::from(MAX_MCODE)).contains(&c) {
                return Err(cx.err(
                    v.span(),
                    key,
                    format!("M{c} is not an M code: codes run from 0 to {MAX_MCODE}"),
                ));
            }
            let c = c as u16;
            if super::mcodes::reserved(c) {
                return Err(cx.err(
                    v.span(),
                    key,
                    format!("M{c} is handled by the interpreter itself (tool change, subprograms, modal state) and cannot be given an action"),
                ));
            }
            if let Some(other) = owner.insert(c, name.as_str()) {
                return Err(cx.err(v.span(), key, format!("M{c} is already given to `{other}`")));
            }
            codes.push(c);
        }
        given.push((action, codes));
    }
    Ok(McodeTable::with(dialect, &given))
}

/// `[gcodes]`: each key a builder's G code (`G121`, `"G87.6"`), each value the code it runs as
/// (one latheguard models in the machine's dialect) or `{ ignore = "…" }` with a reason.
fn gcode_table(
    cx: &Cx<'_>,
    dialect: Dialect,
    raw: Option<&std::collections::BTreeMap<String, Spanned<RawGcode>>>,
) -> Result<super::GcodeTable, MachineError> {
    use super::gcodes::{code_name, parse_code, GAlias};
    let Some(raw) = raw else {
        return Ok(super::GcodeTable::default());
    };
    if raw.len() > 100 {
        return Err(cx.err(0..0, "gcodes", "too many builder G codes: at most 100"));
    }
    let mut out: Vec<(u16, GAlias)> = Vec::with_capacity(raw.len());
    for (name, v) in raw {
        let key = format!("gcodes.{name}");
        let Some(code) = parse_code(name) else {
            return Err(cx.err(
                v.span(),
                key,
                format!("`{name}` is not a G code: write it as a program does (G121, \"G87.6\")"),
            ));
        };
        if out.iter().any(|e| e.0 == code) {
            return Err(cx.err(v.span(), key, format!("{} is given twice", code_name(code))));
        }
        let alias = match v.get_ref() {
            RawGcode::As(target) => {
                let Some(t) = parse_code(target) else {
                    return Err(cx.err(
                        v.span(),
                        key,
                        format!("`{target}` is not a G code: write the standard code it runs as (\"G12.1\")"),
                    ));
                };
                if !crate::interp::models_g(t, dialect) {
                    return Err(cx.err(
                        v.span(),
                        key,
                        format!("{} is not a {} code latheguard models", code_name(t), dialect.as_str()),
                    ));
                }
                GAlias::As(t)
            }
            RawGcode::Ignore(i) => {
                if i.ignore.trim().is_empty() {
                    return Err(cx.err(
                        v.span(),
                        key,
                        "`ignore` needs the reason: what the code does, and why nothing of it needs checking",
                    ));
                }
                GAlias::Ignore
            }
        };
        out.push((code, alias));
    }
    Ok(super::GcodeTable::new(out))
}

/// Points of an outline that normalisation drops and along which the outline turns back.
#[derive(Debug, PartialEq)]
pub(super) struct Fold {
    /// The file's indices of a run of consecutive dropped points, in outline order.
    pub(super) points: Vec<usize>,
    /// Those of them where the outline reversed (its two edges pointed opposite ways).
    pub(super) turns: Vec<usize>,
}

/// Normalise `pts` as [`Polygon::new`] does (drop repeated points, then collinear vertices until
/// none is left) keeping the file's indices, and return each run of dropped points that holds a
/// reversal. Only called for outlines that [`Polygon::new`] accepted.
pub(super) fn folds(pts: &[P2]) -> Vec<Fold> {
    use crate::geom::orient;
    let n0 = pts.len();
    let mut kept: Vec<usize> = Vec::with_capacity(n0);
    for i in 0..n0 {
        if kept.last().map(|&k| pts[k]) != Some(pts[i]) {
            kept.push(i);
        }
    }
    while kept.len() > 1 && kept.first().map(|&k| pts[k]) == kept.last().map(|&k| pts[k]) {
        kept.pop();
    }
    let mut turned = vec![false; n0];
    loop {
        let n = kept.len();
        if n < 3 {
            return Vec::new();
        }
        let mut out: Vec<usize> = Vec::with_capacity(n);
        for i in 0..n {
            let prev = out.last().copied().unwrap_or(kept[(i + n - 1) % n]);
            let (a, b, c) = (pts[prev], pts[kept[i]], pts[kept[(i + 1) % n]]);
            if orient(a, b, c) == 0.0 {
                if (b - a).dot(&(c - b)) < 0.0 {
                    turned[kept[i]] = true;
                }
            } else {
                out.push(kept[i]);
            }
        }
        let removed = out.len() != n;
        kept = out;
        if !removed {
            break;
        }
    }
    if kept.len() < 3 {
        return Vec::new();
    }
    // Runs of dropped indices between consecutive kept ones (cyclically).
    let mut runs = Vec::new();
    for (j, &k) in kept.iter().enumerate() {
        let next = kept[(j + 1) % kept.len()];
        let mut points = Vec::new();
        let mut i = (k + 1) % n0;
        while i != next {
            points.push(i);
            i = (i + 1) % n0;
        }
        let turns: Vec<usize> = points.iter().copied().filter(|&i| turned[i]).collect();
        if !turns.is_empty() {
            runs.push(Fold { points, turns });
        }
    }
    runs.sort_by_key(|r| r.turns[0]);
    runs
}

/// A number as a machine file would write it: `inf`, `nan`, `1e90`, `-0.5`.
fn show(x: f64) -> String {
    if x.is_nan() {
        "nan".to_string()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.to_string()
    } else if x != 0.0 && !(1e-6..1e15).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Serde's words for Rust types, in the words of a machine file; an unknown key or value gets
/// the closest expected one as a suggestion.
fn plain_words(message: &str) -> String {
    with_suggestion(&plain_types(message), message)
}

/// `shown` with the suggestion [`did_you_mean`] finds in serde's `message`, if any.
pub fn with_suggestion(shown: &str, message: &str) -> String {
    match did_you_mean(message) {
        Some(s) => format!("{shown}: did you mean `{s}`?"),
        None => shown.to_string(),
    }
}

/// For serde's "unknown field `x`, expected one of `a`, `b`" (or "expected `a` or `b`", and the
/// same for variants): the expected name closest to `x`, when it is a likely slip — at most a
/// third of its letters apart (one letter for short names; a name in other case is one).
pub fn did_you_mean(message: &str) -> Option<String> {
    let rest = message
        .strip_prefix("unknown field `")
        .or_else(|| message.strip_prefix("unknown variant `"))?;
    let (got, expected) = rest.split_once('`')?;
    let expected = expected.split_once("expected")?.1;
    let candidates = expected.split('`').skip(1).step_by(2);
    let got_l = got.to_lowercase();
    candidates
        .map(|c| (strsim::damerau_levenshtein(&got_l, &c.to_lowercase()), c))
        .filter(|&(d, c)| c != got && d <= (c.chars().count() / 3).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c.to_string())
}

/// Serde's words for Rust types, in the words of a machine file.
fn plain_types(message: &str) -> String {
    message
        .replace("unknown field", "unknown key")
        .replace("unknown variant", "unknown value")
        .replace("expected f64", "expected a number")
        .replace("expected u32", "expected a whole number from 0 to 4294967295")
        .replace("expected i64", "expected a whole number")
        .replace("expected a sequence", "expected an array")
        .replace("expected a boolean", "expected true or false")
}

/// The first two edges of a closed outline that are not neighbours and share a point, each as
/// the file's indices of its two ends (repeated points are skipped). Only used to explain an
/// outline that [`Polygon::new`] already refused, so plain floating point is good enough here.
fn crossing_edges(pts: &[P2]) -> Option<((usize, usize), (usize, usize))> {
    let mut kept: Vec<(usize, P2)> = Vec::with_capacity(pts.len());
    for (i, &p) in pts.iter().enumerate() {
        if kept.last().map(|k| k.1) != Some(p) {
            kept.push((i, p));
        }
    }
    while kept.len() > 1 && kept.first().map(|k| k.1) == kept.last().map(|k| k.1) {
        kept.pop();
    }
    let n = kept.len();
    let orient = |a: P2, b: P2, c: P2| (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    let within =
        |a: P2, b: P2, c: P2| c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y);
    let meet = |a: P2, b: P2, c: P2, d: P2| {
        let (d1, d2, d3, d4) = (orient(c, d, a), orient(c, d, b), orient(a, b, c), orient(a, b, d));
        (d1 * d2 < 0.0 && d3 * d4 < 0.0)
            || (d1 == 0.0 && within(c, d, a))
            || (d2 == 0.0 && within(c, d, b))
            || (d3 == 0.0 && within(a, b, c))
            || (d4 == 0.0 && within(a, b, d))
    };
    for i in 0..n {
        let (a, b) = (kept[i], kept[(i + 1) % n]);
        for j in (i + 2)..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            let (c, d) = (kept[j], kept[(j + 1) % n]);
            if meet(a.1, b.1, c.1, d.1) {
                return Some(((a.0, b.0), (c.0, d.0)));
            }
        }
    }
    None
}

// ---------------------------------------------------------------------------------------------
// Key paths from spans.

#[derive(Clone, Debug)]
enum Seg {
    Key(String),
    Index(usize),
}

fn render(path: &[Seg]) -> String {
    let mut s = String::new();
    for seg in path {
        match seg {
            Seg::Key(k) => {
                if !s.is_empty() {
                    s.push('.');
                }
                let bare = !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
                if bare {
                    s.push_str(k);
                } else {
                    s.push_str(&format!("{k:?}"));
                }
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// One entry of the parsed tree: its key's span (for table entries), its value's span, and
/// whether the value is a table.
struct Node<'p> {
    path: &'p [Seg],
    key: Option<Range<usize>>,
    value: Range<usize>,
    is_table: bool,
}

fn walk_table(t: &DeTable<'_>, path: &mut Vec<Seg>, f: &mut dyn FnMut(&Node<'_>)) {
    for (k, v) in t.iter() {
        path.push(Seg::Key(k.get_ref().to_string()));
        visit(v, Some(k.span()), path, f);
        path.pop();
    }
}

fn visit(v: &Spanned<DeValue<'_>>, key: Option<Range<usize>>, path: &mut Vec<Seg>, f: &mut dyn FnMut(&Node<'_>)) {
    f(&Node {
        path,
        key,
        value: v.span(),
        is_table: matches!(v.get_ref(), DeValue::Table(_)),
    });
    match v.get_ref() {
        DeValue::Table(t) => walk_table(t, path, f),
        DeValue::Array(a) => {
            for (i, c) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                visit(c, None, path, f);
                path.pop();
            }
        }
        _ => {}
    }
}

/// The deepest table whose span is exactly `at` (serde places a missing key at its table).
fn table_at(root: &Spanned<DeTable<'_>>, at: &Range<usize>) -> Option<Vec<Seg>> {
    if root.span() == *at {
        return Some(Vec::new());
    }
    let mut best: Option<Vec<Seg>> = None;
    walk_table(root.get_ref(), &mut Vec::new(), &mut |n| {
        if n.is_table && n.value == *at && deeper(&best, n.path) {
            best = Some(n.path.to_vec());
        }
    });
    best
}

fn deeper(best: &Option<Vec<Seg>>, path: &[Seg]) -> bool {
    match best {
        None => true,
        Some(b) => path.len() >= b.len(),
    }
}

fn contains(r: &Range<usize>, pos: usize) -> bool {
    (r.start <= pos && pos < r.end) || (r.start == pos && r.end == pos)
}

/// The deepest key or value whose span contains `pos`.
fn containing(root: &Spanned<DeTable<'_>>, pos: usize) -> Option<Vec<Seg>> {
    let mut best: Option<Vec<Seg>> = None;
    walk_table(root.get_ref(), &mut Vec::new(), &mut |n| {
        let hit = contains(&n.value, pos) || n.key.as_ref().is_some_and(|k| contains(k, pos));
        if hit && deeper(&best, n.path) {
            best = Some(n.path.to_vec());
        }
    });
    best
}

/// The key a syntax error at `at` is about. A table header is named by its own text; a
/// duplicate key by its table and itself. Otherwise the recovered tree tells: the key or value
/// the error lies in; else the key last written before it on the same line; else the table
/// whose header or key-value pair comes last before it.
fn syntax_key(root: &Spanned<DeTable<'_>>, at: &Range<usize>, message: &str, text: &str) -> String {
    let pos = at.start.min(text.len());
    let line_start = text[..floor_boundary(text, pos)].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].split('\n').next().unwrap_or("");
    if let Some(header) = header_name(line) {
        return header;
    }
    let mut path = syntax_path(root, pos, text);
    // The parser recovers a missing key as an empty one: name what is around it instead.
    if let Some(i) = path.iter().position(|s| matches!(s, Seg::Key(k) if k.is_empty())) {
        path.truncate(i);
    }
    if message == "duplicate key" {
        let key = text.get(at.clone()).unwrap_or("");
        let bare = !key.is_empty() && key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
        if bare && !matches!(path.last(), Some(Seg::Key(k)) if k == key) {
            path.push(Seg::Key(key.to_string()));
        }
    }
    render(&path)
}

fn floor_boundary(text: &str, mut i: usize) -> usize {
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

/// `stock` for a line that is (or begins to be) the table header `[stock]` or `[[stock]]`; None
/// for any other line, such as one row of a multi-line array.
fn header_name(line: &str) -> Option<String> {
    let rest = line.trim_start().strip_prefix('[')?;
    let rest = rest.strip_prefix('[').unwrap_or(rest).trim_start();
    let first = rest.chars().next()?;
    if !(first.is_ascii_alphabetic() || first == '_' || first == '"' || first == '\'') {
        return None;
    }
    let name = rest.split([']', '#']).next().unwrap_or("");
    let parts: Vec<&str> = name.split('.').map(str::trim).collect();
    let ok = |p: &&str| {
        !p.is_empty()
            && p.chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '"' || c == '\'' || c == ' ')
    };
    if parts.iter().all(ok) {
        Some(parts.join("."))
    } else {
        None
    }
}

fn syntax_path(root: &Spanned<DeTable<'_>>, pos: usize, text: &str) -> Vec<Seg> {
    if let Some(p) = containing(root, pos) {
        return p;
    }
    let line_of = |offset: usize| {
        text.as_bytes()[..offset.min(text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    };
    // (start, path, is a key-value pair)
    let mut best: Option<(usize, Vec<Seg>, bool)> = None;
    walk_table(root.get_ref(), &mut Vec::new(), &mut |n| {
        let header = n.is_table && text.as_bytes().get(n.value.start) == Some(&b'[');
        let anchor = match &n.key {
            // A key written inside a table header (`[stock]`) is not a key-value pair.
            Some(k) if !header && k.start < n.value.start => Some((k.start, true)),
            _ if header => Some((n.value.start, false)),
            _ => None,
        };
        if let Some((start, is_pair)) = anchor {
            if start <= pos && best.as_ref().map_or(true, |b| start >= b.0) {
                best = Some((start, n.path.to_vec(), is_pair));
            }
        }
    });
    match best {
        None => Vec::new(),
        Some((start, mut path, is_pair)) => {
            if is_pair && line_of(start) != line_of(pos) {
                path.pop();
            }
            path
        }
    }
}
