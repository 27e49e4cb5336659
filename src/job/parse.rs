//! Job files (and `[job]` tables of `latheguard.toml`) → a validated [`Layer`].

use std::ops::Range;

use schemars::JsonSchema;
use serde::Deserialize;
use toml::Spanned;

use super::{
    DialectChoice, JobError, JobJaws, JobOperation, JobStock, JobTool, Layer, Place, Resolve, Set, TableNumbers,
};
use crate::geom::{Polygon, P2};
use crate::machine::tool_entry::{self, Geom, Placing, RawDrill, RawGeometryOffset, Shape, ShapeSchema};
use crate::machine::{self, Cx, Num, OpStart, Outline, Point, RawGrip, RawJawType, RawUnits, RawWorkOffsets, Tool};
use crate::scene::{Stand, StockTransform};
use crate::tooling::milling::{Live, MillSpec, MillTool};
use crate::tooling::{self, tbl, BuiltTool, DrillSpec};

// ---------------------------------------------------------------------------------------------
// The file as written (also its JSON Schema: [`schema`]).

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
#[schemars(title = "latheguard job")]
/// A job file as written (its fields are read by the job module only).
pub struct RawJob {
    #[schemars(with = "Option<RawUnits>")]
    units: Option<Spanned<RawUnits>>,
    #[schemars(with = "Option<RawDialect>")]
    dialect: Option<Spanned<RawDialect>>,
    #[schemars(with = "Option<String>")]
    tool_library: Option<Spanned<String>>,
    #[schemars(with = "Option<String>")]
    tool_table: Option<Spanned<String>>,
    /// The units of the `tool_table`'s X, Z and D (the LinuxCNC machine's units): "mm" or
    /// "inch"; by default this job's `units`, else mm.
    #[schemars(with = "Option<RawUnits>")]
    tool_table_units: Option<Spanned<RawUnits>>,
    #[schemars(with = "Option<f64>")]
    program_zero_z: Option<Num>,
    /// Work offsets G54–G59 as the control's work offset page stores them (docs/job.md).
    work_offsets: Option<RawWorkOffsets>,
    #[schemars(with = "Option<RawStock>")]
    stock: Option<Spanned<RawStock>>,
    #[schemars(with = "Option<RawChuck>")]
    chuck: Option<Spanned<RawChuck>>,
    tailstock: Option<RawTailstock>,
    #[schemars(with = "Option<bool>")]
    diameter_mode: Option<Spanned<bool>>,
    spindle: Option<RawSpindle>,
    #[schemars(with = "Option<Vec<RawToolChange>>")]
    tool_changes: Option<Spanned<Vec<Spanned<RawToolChange>>>>,
    #[schemars(with = "Option<Vec<RawTool>>")]
    tools: Option<Spanned<Vec<Spanned<RawTool>>>>,
    /// LinuxCNC tool numbers → turret stations (docs/job.md "Tool numbers").
    #[schemars(with = "Option<RawToolNumbersSchema>")]
    tool_numbers: Option<Spanned<std::collections::BTreeMap<Spanned<String>, Spanned<RawTn>>>>,
    /// The operations after the first: the part turned round or re-clamped (docs/job.md,
    /// "Operations").
    #[schemars(with = "Option<Vec<RawOperation>>")]
    operations: Option<Spanned<Vec<Spanned<RawOperation>>>>,
}

/// A value of `[tool_numbers]`: a station (`T12 = 3`) or `from_table = true`.
#[derive(Deserialize)]
#[serde(untagged, expecting = "a station number (or `from_table = true`)")]
enum RawTn {
    Number(i64),
    Flag(bool),
}

/// `[tool_numbers]`: which turret station each LinuxCNC tool number is in (LinuxCNC dialect
/// only; Fanuc T words name the station). Keys `T<tool> = <station>`, and `from_table = true`: every
/// tool of the job's `tool_table` is in its pocket P (an explicit `T<tool>` wins), and its shape
/// comes from the table for a station no `[[tools]]` entry describes.
#[derive(JsonSchema)]
#[allow(dead_code)]
struct RawToolNumbersSchema {
    /// Every tool of the job's `tool_table` is in the station of its pocket P.
    from_table: Option<bool>,
    /// `T12 = 3`: tool 12 is in station 3 (read as a map of [`RawTn`]).
    #[serde(flatten)]
    tools: std::collections::BTreeMap<String, u32>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawSpindle {
    /// The spindle turns forward at this speed from program start (a manual lathe switched on
    /// by hand), as if `M3 S…` came before line 1; 0: stopped, over the machine's value.
    #[schemars(with = "Option<f64>")]
    start_rpm: Option<Num>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { line, station }")]
struct RawToolChange {
    /// The program's line (1-based) at which the operator has put the tool in.
    #[schemars(with = "i64")]
    line: Option<Spanned<i64>>,
    /// The station whose tool it is.
    #[schemars(with = "i64")]
    station: Option<Spanned<i64>>,
    /// What the operator does (the M0's message), for the reader of the job only.
    #[schemars(with = "Option<String>")]
    #[allow(dead_code)]
    note: Option<Spanned<String>>,
}

#[derive(Deserialize, JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase", expecting = "\"fanuc\", \"linuxcnc\" or \"auto\"")]
enum RawDialect {
    Fanuc,
    Linuxcnc,
    Auto,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawStock {
    #[schemars(with = "Option<f64>")]
    diameter: Option<Num>,
    #[schemars(with = "Option<f64>")]
    length: Option<Num>,
    #[schemars(with = "Option<f64>")]
    stick_out: Option<Num>,
    /// The machine file's name for `stick_out`.
    #[schemars(with = "Option<f64>")]
    front: Option<Num>,
    #[schemars(with = "Option<f64>")]
    bore: Option<Num>,
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
    /// `none = true`: no stock at all (a dry run in the air).
    #[schemars(with = "Option<bool>")]
    none: Option<Spanned<bool>>,
    /// A part file (`latheguard check --stock-out part.toml`) whose `[stock] outline` is this
    /// stock, relative to the job file: a second operation's part made by the first's program.
    #[schemars(with = "Option<String>")]
    from: Option<Spanned<String>>,
    /// With `outline` or `from`: the part turned end for end (z mirrored); needs `front` or
    /// `grip`.
    #[schemars(with = "Option<bool>")]
    reverse: Option<Spanned<bool>>,
    /// With `outline` or `from`: the length held in the jaws from the part's back end (its
    /// smallest z at -grip); instead of `front`.
    #[schemars(with = "Option<f64>")]
    grip: Option<Num>,
    /// A prismatic block held in the jaws (a square bar), milled on its faces by live tools:
    /// its section `{ width, height }` (along x and y at C0, centred on the spindle axis), with
    /// `length` and `stick_out` (or `front`) as a bar's.
    #[schemars(with = "Option<RawBlock>")]
    block: Option<Spanned<RawBlock>>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { width, height }")]
struct RawBlock {
    /// Across the spindle axis along x at C0 (mm).
    #[schemars(with = "f64")]
    width: Num,
    /// Across the spindle axis along y at C0 (mm).
    #[schemars(with = "f64")]
    height: Num,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawChuck {
    /// The chuck as set up for this job, drawn: replaces the machine's chuck (not with `jaws`).
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
    /// The jaws of this job, key by key over the machine file's (whose chuck must be given by
    /// `body` and `jaws`); not with `outline`.
    #[schemars(with = "Option<RawJaws>")]
    jaws: Option<Spanned<RawJaws>>,
}

/// `[chuck.jaws]` of a job: any of the machine file's keys.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawJaws {
    /// "outside" or "inside".
    #[schemars(with = "Option<RawGrip>")]
    grip: Option<Spanned<RawGrip>>,
    /// "hard" or "soft".
    #[serde(rename = "type")]
    #[schemars(rename = "type", with = "Option<RawJawType>")]
    kind: Option<Spanned<RawJawType>>,
    /// The diameter held (default: the job's bar, when the job gives one).
    #[schemars(with = "Option<f64>")]
    grip_diameter: Option<Num>,
    #[schemars(with = "Option<f64>")]
    grip_length: Option<Num>,
    #[schemars(with = "Option<f64>")]
    height: Option<Num>,
    #[schemars(with = "Option<f64>")]
    width: Option<Num>,
    #[schemars(with = "Option<f64>")]
    step: Option<Num>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawTailstock {
    #[schemars(with = "Option<bool>")]
    in_use: Option<Spanned<bool>>,
    /// The z of the live centre's tip: the machine's tailstock outline moved along z so that
    /// its smallest z is here.
    #[schemars(with = "Option<f64>")]
    z: Option<Num>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawTool {
    #[schemars(with = "Option<u32>")]
    station: Option<Spanned<u32>>,
    /// Tool library entries only: the name `use` picks it by.
    #[schemars(with = "Option<String>")]
    id: Option<Spanned<String>>,
    #[schemars(with = "Option<String>")]
    name: Option<Spanned<String>>,
    #[schemars(with = "Option<[f64; 2]>")]
    tip: Option<Point>,
    /// The tool's geometry offset as the control's page shows it (X on diameter, Z; mm),
    /// instead of `tip`.
    #[schemars(with = "Option<RawGeometryOffset>")]
    geometry_offset: Option<Spanned<RawGeometryOffset>>,
    #[schemars(with = "Option<ShapeSchema>")]
    insert: Option<Spanned<Shape>>,
    #[schemars(with = "Option<ShapeSchema>")]
    holder: Option<Spanned<Shape>>,
    #[schemars(with = "Option<f64>")]
    nose_radius: Option<Num>,
    #[schemars(with = "Option<i64>")]
    tip_direction: Option<Spanned<i64>>,
    #[schemars(with = "Option<RawDrill>")]
    drill: Option<Spanned<RawDrill>>,
    /// A milling tool by its sizes (docs/tools.md, "Milling tools"); with `live`.
    #[schemars(with = "Option<RawMill>")]
    mill: Option<Spanned<RawMill>>,
    /// `"axial"` or `"radial"`: which way the live station points a `mill`.
    #[schemars(with = "Option<String>")]
    live: Option<Spanned<String>>,
    #[serde(rename = "use")]
    #[schemars(rename = "use", with = "Option<String>")]
    use_: Option<Spanned<String>>,
    #[schemars(with = "Option<u32>")]
    tbl: Option<Spanned<u32>>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table { type, diameter, flute_length, stick_out, holder, … }"
)]
struct RawMill {
    #[serde(rename = "type")]
    #[schemars(rename = "type", with = "String")]
    kind: Spanned<String>,
    #[schemars(with = "f64")]
    diameter: Num,
    #[schemars(with = "f64")]
    flute_length: Num,
    #[schemars(with = "f64")]
    stick_out: Num,
    #[schemars(with = "Option<f64>")]
    corner_radius: Option<Num>,
    #[schemars(with = "Option<f64>")]
    point_angle: Option<Num>,
    #[schemars(with = "Option<f64>")]
    pitch: Option<Num>,
    #[schemars(with = "Option<f64>")]
    shank: Option<Num>,
    holder: RawMillHolder,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { diameter, length }")]
struct RawMillHolder {
    #[schemars(with = "f64")]
    diameter: Num,
    #[schemars(with = "f64")]
    length: Num,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawLibrary {
    #[schemars(with = "Vec<RawTool>")]
    tools: Vec<Spanned<RawTool>>,
}

// Operations and part files (docs/job.md, "Operations") as written.

#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table { line, stop or work_offset, reverse, front or grip, chuck, tailstock, … }"
)]
struct RawOperation {
    /// The program's file line (1-based) where this operation starts, before the block's
    /// words (usually the M0 that stops for the turn-round); instead of `stop`.
    #[schemars(with = "Option<i64>")]
    line: Option<Spanned<i64>>,
    /// The program stop (M0 or M1, counted from 1 as they run) after which this operation
    /// starts; instead of `line`.
    #[schemars(with = "Option<i64>")]
    stop: Option<Spanned<i64>>,
    /// The work offset (`"G55"`: G54 to G59) whose first selection starts this operation,
    /// before that block's words; instead of `line` or `stop`.
    #[schemars(with = "Option<String>")]
    work_offset: Option<Spanned<String>>,
    /// The tailstock in this operation: `in_use` (advanced as it begins, or not an obstacle)
    /// and `z` (its live centre's tip); default: as it stood.
    #[schemars(with = "Option<RawTailstock>")]
    tailstock: Option<Spanned<RawTailstock>>,
    /// The part turned end for end (z mirrored); needs `front` or `grip`.
    #[schemars(with = "Option<bool>")]
    reverse: Option<Spanned<bool>>,
    /// z of the part's front face (its largest z) in this operation.
    #[schemars(with = "Option<f64>")]
    front: Option<Num>,
    /// The length held in the jaws from the part's back end: its smallest z at -grip.
    #[schemars(with = "Option<f64>")]
    grip: Option<Num>,
    /// The jaws of this operation (default: the job's chuck).
    #[schemars(with = "Option<RawOpChuck>")]
    chuck: Option<Spanned<RawOpChuck>>,
    /// G54's program zero from this operation on (the operator touched off the new face).
    #[schemars(with = "Option<f64>")]
    program_zero_z: Option<Num>,
    /// What the operator does, for the reader of the job (and `latheguard setup`).
    #[schemars(with = "Option<String>")]
    note: Option<Spanned<String>>,
}

/// An operation's jaws: `chuck = { outline = [...] }`, or `[operations.chuck.jaws]` over the
/// job's jaws (`grip_diameter`: the diameter of the part this operation holds).
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table { outline } or { jaws }")]
struct RawOpChuck {
    #[schemars(with = "Option<Vec<[f64; 2]>>")]
    outline: Option<Outline>,
    #[schemars(with = "Option<RawJaws>")]
    jaws: Option<Spanned<RawJaws>>,
}

/// A part file: `[stock] outline = [...]` (what `latheguard check --stock-out part.toml` writes).
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table")]
struct RawPartFile {
    stock: Spanned<RawPartStock>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table { outline }")]
struct RawPartStock {
    outline: Outline,
}

/// The JSON Schema (draft 2020-12) of a job file (`latheguard schema job`).
pub fn schema() -> String {
    let mut schema = schemars::schema_for!(RawJob);
    schema.insert("title".into(), "latheguard job".into());
    let mut s = serde_json::to_string_pretty(&schema).unwrap_or_default();
    s.push('\n');
    s
}

/// The schema of a `job` value in `latheguard.toml`: a job file's name or an inline job.
#[derive(JsonSchema)]
#[serde(untagged)]
#[allow(dead_code)]
pub enum JobSchema {
    /// A job file, relative to the configuration's folder.
    File(String),
    Inline(Box<RawJob>),
}

// ---------------------------------------------------------------------------------------------
// Reading.

/// At most this many `[[tools]]` in a job or a tool library.
pub const MAX_JOB_TOOLS: usize = machine::MAX_TOOLS;

/// At most this many `[[tool_changes]]` in a job.
pub const MAX_TOOL_CHANGES: usize = 1000;

/// At most this many `[[operations]]` in a job.
pub const MAX_OPERATIONS: usize = 100;

/// Read one job file. `file` names it in messages, `base` is the folder its `tool_library` and
/// `tool_table` are relative to (handed to `resolve` as is), `label` names the layer.
pub fn parse(text: &str, file: &str, base: &str, label: &str, resolve: &mut dyn Resolve) -> Result<Layer, JobError> {
    let cx = Cx::new(text, file);
    let raw: RawJob = machine::deserialize(&cx, "a job file")?;
    let mut layer = layer(&cx, raw, "", base, label, resolve)?;
    layer.files.insert(0, file.to_string());
    Ok(layer)
}

/// A `job` value inside a `latheguard.toml`: a file name, or a table read as a job.
pub enum Embedded {
    /// `job = "…"`: the name as written and where.
    File {
        name: String,
        at: Place,
    },
    Inline(Box<Layer>),
}

/// The `job` at `path` (`["job"]`, `["override", "2", "job"]`) of a configuration's text, if
/// there is one. Errors name the whole key path (`override[2].job.stock.diameter`).
pub fn parse_embedded(
    text: &str,
    file: &str,
    path: &[&str],
    base: &str,
    label: &str,
    resolve: &mut dyn Resolve,
) -> Result<Option<Embedded>, JobError> {
    let cx = Cx::new(text, file);
    let prefix = key_path(path);
    match machine::deserialize_at::<RawJob>(&cx, path, "a configuration")? {
        None => Ok(None),
        Some(machine::Embedded::Str(s)) => {
            if s.get_ref().trim().is_empty() {
                return Err(cx.err(s.span(), prefix, "the job file name is empty"));
            }
            Ok(Some(Embedded::File {
                name: s.get_ref().clone(),
                at: place(&cx, s.span(), &prefix),
            }))
        }
        Some(machine::Embedded::Table(raw)) => {
            let l = layer(&cx, raw, &format!("{prefix}."), base, label, resolve)?;
            Ok(Some(Embedded::Inline(Box::new(l))))
        }
    }
}

/// `["override", "2", "job"]` → `override[2].job`.
fn key_path(path: &[&str]) -> String {
    let mut s = String::new();
    for p in path {
        if p.parse::<usize>().is_ok() {
            s.push_str(&format!("[{p}]"));
        } else {
            if !s.is_empty() {
                s.push('.');
            }
            s.push_str(p);
        }
    }
    s
}

fn place(cx: &Cx<'_>, at: Range<usize>, key: &str) -> Place {
    let e = cx.err(at, key, "");
    Place {
        file: e.file,
        line: e.line,
        col: e.col,
        key: key.to_string(),
    }
}

/// Files a layer refers to, read at most once each.
struct Refs<'r> {
    base: &'r str,
    resolve: &'r mut dyn Resolve,
    library: Option<(String, String)>,
    table: Option<(String, Vec<tbl::TblTool>)>,
}

fn layer(
    cx: &Cx<'_>,
    raw: RawJob,
    prefix: &str,
    base: &str,
    label: &str,
    resolve: &mut dyn Resolve,
) -> Result<Layer, JobError> {
    let key = |k: &str| format!("{prefix}{k}");
    fn mk<T>(cx: &Cx<'_>, value: T, at: Range<usize>, key: String, label: &str) -> Set<T> {
        Set {
            value,
            at: place(cx, at, &key),
            layer: label.to_string(),
        }
    }
    macro_rules! set {
        ($v:expr, $at:expr, $k:expr) => {
            mk(cx, $v, $at, key($k), label)
        };
    }
    let mut l = Layer::new(label);
    l.units_inch = raw
        .units
        .as_ref()
        .map(|u| set!(matches!(u.get_ref(), RawUnits::Inch), u.span(), "units"));
    if let (Some(u), None) = (&raw.tool_table_units, &raw.tool_table) {
        cx.push(cx.err(
            u.span(),
            key("tool_table_units"),
            format!("`tool_table_units` says the units of the job's tool table: give `{prefix}tool_table = \"FILE.tbl\"` too"),
        ));
    }
    l.dialect = raw.dialect.as_ref().map(|d| {
        let v = match d.get_ref() {
            RawDialect::Fanuc => DialectChoice::Fanuc,
            RawDialect::Linuxcnc => DialectChoice::Linuxcnc,
            RawDialect::Auto => DialectChoice::Auto,
        };
        set!(v, d.span(), "dialect")
    });
    if let Some(z) = &raw.program_zero_z {
        let v = cx.keep(cx.coord(&key("program_zero_z"), z));
        l.program_zero_z = v.map(|v| set!(v, z.span(), "program_zero_z"));
    }
    if let Some(w) = &raw.work_offsets {
        for g in machine::work_offsets(cx, w, &key("work_offsets")) {
            if let (0, Some(z)) = (g.n, &raw.program_zero_z) {
                cx.push(cx.err(
                    z.span(),
                    key("program_zero_z"),
                    format!(
                        "program zero is given twice: by {} and by {} (G54 is program zero at start); give one of them",
                        key("program_zero_z"),
                        g.key
                    ),
                ));
                continue;
            }
            l.work_offsets[g.n] = Some(Set {
                value: g.value,
                at: place(cx, g.at, &g.key),
                layer: label.to_string(),
            });
        }
    }
    if let Some(s) = &raw.stock {
        let v = match &s.get_ref().from {
            Some(f) => stock_from(cx, s, f, &key("stock"), base, &mut *resolve).map(|(v, file)| {
                l.files.push(file);
                v
            }),
            None => stock(cx, s, &key("stock")),
        };
        l.stock = cx.keep(v).map(|v| set!(v, s.span(), "stock"));
    }
    if let Some(c) = &raw.chuck {
        match (&c.get_ref().outline, &c.get_ref().jaws) {
            (Some(o), Some(_)) => cx.push(cx.err(
                o.span(),
                key("chuck.outline"),
                "give the chuck either as an `outline` or as `[chuck.jaws]` over the machine file's jaws, not both",
            )),
            (None, None) => cx.push(cx.err(
                c.span(),
                key("chuck.outline"),
                "missing required key `chuck.outline` (or a `[chuck.jaws]` table)",
            )),
            (Some(o), None) if o.get_ref().len() > machine::MAX_OUTLINE_POINTS => {
                cx.push(cx.err(o.span(), key("chuck.outline"), "too many points"));
            }
            (Some(o), None) => {
                l.chuck = cx
                    .keep(cx.outline(&key("chuck.outline"), o))
                    .map(|p| set!(p, c.span(), "chuck.outline"));
            }
            (None, Some(j)) => l.jaws = job_jaws(cx, j, &key("chuck.jaws"), label),
        }
    }
    l.tailstock_in_use = raw
        .tailstock
        .as_ref()
        .and_then(|t| t.in_use.as_ref())
        .map(|u| set!(*u.get_ref(), u.span(), "tailstock.in_use"));
    if let Some(z) = raw.tailstock.as_ref().and_then(|t| t.z.as_ref()) {
        l.tailstock_z = cx
            .keep(cx.coord(&key("tailstock.z"), z))
            .map(|v| set!(v, z.span(), "tailstock.z"));
    }
    l.diameter_mode = raw
        .diameter_mode
        .as_ref()
        .map(|d| set!(*d.get_ref(), d.span(), "diameter_mode"));
    if let Some(r) = raw.spindle.as_ref().and_then(|s| s.start_rpm.as_ref()) {
        let k = key("spindle.start_rpm");
        let v = if *r.get_ref() == 0.0 {
            Ok(0.0)
        } else {
            cx.within(&k, r, machine::MAX_RPM_RANGE, "rpm")
        };
        l.start_rpm = cx.keep(v).map(|v| set!(v, r.span(), "spindle.start_rpm"));
    }
    if let Some(changes) = &raw.tool_changes {
        if changes.get_ref().len() > MAX_TOOL_CHANGES {
            return Err(cx.err(
                changes.span(),
                key("tool_changes"),
                format!("too many tool changes: at most {MAX_TOOL_CHANGES}"),
            ));
        }
        for (i, c) in changes.get_ref().iter().enumerate() {
            let k = key(&format!("tool_changes[{i}]"));
            let rc = c.get_ref();
            let (Some(line), Some(station)) = (&rc.line, &rc.station) else {
                let which = if rc.line.is_none() { "line" } else { "station" };
                cx.push(cx.err(
                    c.span(),
                    format!("{k}.{which}"),
                    format!("missing required key `{which}`"),
                ));
                continue;
            };
            let l_ = *line.get_ref();
            if !(1..=i64::from(u32::MAX)).contains(&l_) {
                cx.push(cx.err(
                    line.span(),
                    format!("{k}.line"),
                    format!("{l_} is not a line: lines count from 1"),
                ));
                continue;
            }
            let s_ = *station.get_ref();
            if !(1..=i64::from(machine::MAX_STATIONS)).contains(&s_) {
                cx.push(cx.err(
                    station.span(),
                    format!("{k}.station"),
                    format!(
                        "station {s_} does not exist: stations run from 1 to {}",
                        machine::MAX_STATIONS
                    ),
                ));
                continue;
            }
            if let Some(o) = l.tool_changes.iter().find(|o| i64::from(o.value.0) == l_) {
                cx.push(cx.err(
                    line.span(),
                    format!("{k}.line"),
                    format!("line {l_} already has a tool change ({})", o.at.key),
                ));
                continue;
            }
            l.tool_changes.push(Set {
                value: (l_ as u32, s_ as u32),
                at: place(cx, c.span(), &k),
                layer: label.to_string(),
            });
        }
    }
    if let Some(ops) = &raw.operations {
        l.operations = operations(cx, ops, prefix, label);
    }
    let mut refs = Refs {
        base,
        resolve,
        library: None,
        table: None,
    };
    if let Some(tools) = &raw.tools {
        if tools.get_ref().len() > MAX_JOB_TOOLS {
            return Err(cx.err(
                tools.span(),
                key("tools"),
                format!("too many tools: at most {MAX_JOB_TOOLS}"),
            ));
        }
        let mut total = 0usize;
        for (i, t) in tools.get_ref().iter().enumerate() {
            let k = key(&format!("tools[{i}]"));
            let rt = t.get_ref();
            total += [&rt.insert, &rt.holder]
                .iter()
                .map(|s| match s.as_ref().map(|s| s.get_ref()) {
                    Some(Shape::Outline(p)) => p.len(),
                    _ => 0,
                })
                .sum::<usize>();
            if total > machine::MAX_TOTAL_OUTLINE_POINTS {
                return Err(cx.err(t.span(), k, "too many outline points in the tools of one job"));
            }
            let Some(station) = &rt.station else {
                cx.push(cx.err(t.span(), format!("{k}.station"), "missing required key `station`"));
                continue;
            };
            let s = *station.get_ref();
            if !(1..=machine::MAX_STATIONS).contains(&s) {
                cx.push(cx.err(
                    station.span(),
                    format!("{k}.station"),
                    format!(
                        "station {s} does not exist: stations run from 1 to {}",
                        machine::MAX_STATIONS
                    ),
                ));
                continue;
            }
            if let Some(j) = l.tools.iter().position(|o| o.value.tool.station == s) {
                cx.push(cx.err(
                    station.span(),
                    format!("{k}.station"),
                    format!("station {s} is already given by {}", l.tools[j].at.key),
                ));
                continue;
            }
            if let Some(id) = &rt.id {
                cx.push(cx.err(
                    id.span(),
                    format!("{k}.id"),
                    "`id` names an entry of a tool library file; in a job, give `station` (and `use` to take a library entry)",
                ));
                continue;
            }
            if let Some(tool) = cx.keep(job_tool(cx, &raw, rt, s, &k, prefix, &mut refs)) {
                l.tools.push(Set {
                    value: tool,
                    at: place(cx, t.span(), &k),
                    layer: label.to_string(),
                });
            }
        }
    }
    if let Some(map) = &raw.tool_numbers {
        tool_numbers(cx, &raw, map, prefix, label, &mut refs, &mut l);
    }
    if let Some((f, _)) = &refs.library {
        l.files.push(f.clone());
    }
    if let Some((f, _)) = &refs.table {
        l.files.push(f.clone());
    }
    if let Some(e) = cx.kept() {
        return Err(e);
    }
    l.warnings = cx.take_warnings();
    Ok(l)
}

fn stock(cx: &Cx<'_>, s: &Spanned<RawStock>, key: &str) -> Result<JobStock, JobError> {
    let r = s.get_ref();
    let k = |n: &str| format!("{key}.{n}");
    let given: Vec<(&str, Range<usize>)> = [
        ("diameter", &r.diameter),
        ("length", &r.length),
        ("stick_out", &r.stick_out),
        ("front", &r.front),
        ("bore", &r.bore),
    ]
    .into_iter()
    .filter_map(|(n, v)| v.as_ref().map(|v| (n, v.span())))
    .collect();
    if let Some(n) = &r.none {
        if !*n.get_ref() {
            return Err(cx.err(
                n.span(),
                k("none"),
                "`none = false` says nothing: leave it out, or give the stock's sizes or outline",
            ));
        }
        let other = given
            .first()
            .cloned()
            .or(r.outline.as_ref().map(|o| ("outline", o.span())))
            .or(r.reverse.as_ref().map(|o| ("reverse", o.span())))
            .or(r.grip.as_ref().map(|o| ("grip", o.span())))
            .or(r.block.as_ref().map(|o| ("block", o.span())));
        if let Some((name, at)) = other {
            return Err(cx.err(
                at,
                k(name),
                "`none = true` means no stock: give no sizes or outline with it",
            ));
        }
        let at = place(cx, n.span(), &k("none"));
        return Ok(JobStock::none_at(at));
    }
    if let Some(b) = &r.block {
        let other = given
            .iter()
            .find(|(n, _)| matches!(*n, "diameter" | "bore"))
            .cloned()
            .or(r.outline.as_ref().map(|o| ("outline", o.span())))
            .or(r.reverse.as_ref().map(|o| ("reverse", o.span())))
            .or(r.grip.as_ref().map(|o| ("grip", o.span())));
        if let Some((name, at)) = other {
            return Err(cx.err(
                at,
                k(name),
                "a block takes its section from `block = { width, height }`: give no diameter, bore, outline, reverse or grip with it",
            ));
        }
        let bk = |n: &str| format!("{key}.block.{n}");
        let width = cx.length(&bk("width"), &b.get_ref().width)?;
        let height = cx.length(&bk("height"), &b.get_ref().height)?;
        let bar = bar_sizes(cx, s, key, None)?;
        let block = machine::Block { width, height };
        return Ok(JobStock {
            diameter: 2.0 * block.circumscribed(),
            block: Some(block),
            diameter_at: place(cx, b.span(), &k("block")),
            ..bar
        });
    }
    if let Some(o) = &r.outline {
        if let Some((name, at)) = given
            .iter()
            .find(|(n, _)| !matches!(*n, "stick_out" | "front"))
            .cloned()
        {
            return Err(cx.err(
                at,
                k(name),
                "a stock with an `outline` takes its sizes from it: give the outline or the bar's sizes, not both",
            ));
        }
        let poly = cx.stock_outline(&k("outline"), o)?;
        let at = place(cx, o.span(), &k("outline"));
        return placed_part(cx, r, poly, key, at);
    }
    for (name, given) in [
        ("reverse", r.reverse.as_ref().map(|v| v.span())),
        ("grip", r.grip.as_ref().map(|v| v.span())),
    ] {
        if let Some(at) = given {
            return Err(cx.err(
                at,
                k(name),
                format!(
                    "`{name}` places a part given by its outline (`outline` or `from`); a bar is placed by `stick_out`"
                ),
            ));
        }
    }
    let need = |v: &Option<Num>, n: &str| -> Result<Num, JobError> {
        v.clone()
            .ok_or_else(|| cx.err(s.span(), k(n), format!("missing required key `{n}`")))
    };
    let diameter = need(&r.diameter, "diameter")?;
    bar_sizes(cx, s, key, Some(&diameter))
}

/// A bar's sizes (`diameter` when given: a block has none), `length`, `stick_out` or
/// `front`, `bore`.
fn bar_sizes(cx: &Cx<'_>, s: &Spanned<RawStock>, key: &str, diameter: Option<&Num>) -> Result<JobStock, JobError> {
    let r = s.get_ref();
    let k = |n: &str| format!("{key}.{n}");
    let need = |v: &Option<Num>, n: &str| -> Result<Num, JobError> {
        v.clone()
            .ok_or_else(|| cx.err(s.span(), k(n), format!("missing required key `{n}`")))
    };
    let length = need(&r.length, "length")?;
    let (front, front_key) = match (&r.stick_out, &r.front) {
        (Some(a), None) => (a.clone(), "stick_out"),
        (None, Some(b)) => (b.clone(), "front"),
        (Some(_), Some(b)) => {
            return Err(cx.err(
                b.span(),
                k("front"),
                "give `stick_out` or `front` (the same value), not both",
            ))
        }
        (None, None) => {
            return Err(cx.err(s.span(), k("stick_out"), "missing required key `stick_out`"));
        }
    };
    let d = match diameter {
        Some(v) => cx.length(&k("diameter"), v)?,
        None => 0.0,
    };
    let len = cx.length(&k("length"), &length)?;
    let f = cx.coord(&k(front_key), &front)?;
    let bore = match &r.bore {
        None => 0.0,
        Some(b) => {
            let v = cx.non_negative(&k("bore"), b)?;
            if v >= d {
                return Err(cx.err(
                    b.span(),
                    k("bore"),
                    format!("the bore ({v}) must be smaller than the diameter ({d})"),
                ));
            }
            v
        }
    };
    if f - len < -machine::MAX_COORD_MM {
        return Err(cx.err(length.span(), k("length"), "the bar's back end is out of range"));
    }
    Ok(JobStock {
        diameter: d,
        length: len,
        front: Some(f),
        bore,
        outline: None,
        block: None,
        none: false,
        diameter_at: place(cx, diameter.map_or(s.span(), |d| d.span()), &k("diameter")),
        length_at: place(cx, length.span(), &k("length")),
    })
}

// ---------------------------------------------------------------------------------------------
// A part placed by its outline (`[stock] outline` or `from`, with `reverse`, `front`, `grip`).

/// Where a part stands: `front` (or `stick_out`) or `grip`, at most one; None: as written.
fn stand_of(
    cx: &Cx<'_>,
    front: Option<(&Num, String)>,
    grip: Option<(&Num, String)>,
) -> Result<Option<(Stand, Place)>, JobError> {
    match (front, grip) {
        (Some(_), Some((g, gk))) => Err(cx.err(
            g.span(),
            gk,
            "give where the part stands once: `front` (z of its front face) or `grip` (the length held in the jaws), not both",
        )),
        (Some((f, fk)), None) => Ok(Some((Stand::Front(cx.coord(&fk, f)?), place(cx, f.span(), &fk)))),
        (None, Some((g, gk))) => {
            let v = cx.non_negative(&gk, g)?;
            if v > machine::MAX_COORD_MM {
                return Err(cx.err(g.span(), gk, "the grip is out of range"));
            }
            Ok(Some((Stand::Grip(v), place(cx, g.span(), &gk))))
        }
        (None, None) => Ok(None),
    }
}

/// The part `poly` (its outline as written), turned round when `reverse` and standing where
/// `front`/`grip` say, as the job's stock. Errors of a part that does not fit the chuck name the
/// key that placed it (else `at`, the outline or the file).
fn placed_part(cx: &Cx<'_>, r: &RawStock, poly: Polygon, key: &str, at: Place) -> Result<JobStock, JobError> {
    let k = |n: &str| format!("{key}.{n}");
    if let (Some(_), Some(b)) = (&r.stick_out, &r.front) {
        return Err(cx.err(
            b.span(),
            k("front"),
            "give `stick_out` or `front` (the same value), not both",
        ));
    }
    let front = match (&r.stick_out, &r.front) {
        (Some(a), _) => Some((a, k("stick_out"))),
        (_, Some(b)) => Some((b, k("front"))),
        _ => None,
    };
    let stand = stand_of(cx, front, r.grip.as_ref().map(|g| (g, k("grip"))))?;
    let reverse = r.reverse.as_ref().is_some_and(|v| *v.get_ref());
    if let (true, None, Some(rv)) = (reverse, &stand, &r.reverse) {
        return Err(cx.err(
            rv.span(),
            k("reverse"),
            "a part turned round needs where it then stands: give `front` (z of its front face) or `grip` (the length held in the jaws)",
        ));
    }
    let poly = match &stand {
        None => poly,
        Some((s, s_at)) => {
            let bb = poly.aabb();
            let t = StockTransform::placing(bb.min.y, bb.max.y, reverse, *s);
            Polygon::new(&t.outline(poly.points()))
                .map_err(|e| s_at.err(format!("the part placed here is no outline: {e}")))?
        }
    };
    let st = machine::Stock::from_outline(poly);
    let at = stand.map_or(at, |(_, p)| p);
    Ok(JobStock {
        diameter: st.diameter,
        length: st.length,
        front: Some(st.front),
        bore: 0.0,
        outline: st.outline,
        block: None,
        none: false,
        diameter_at: at.clone(),
        length_at: at,
    })
}

/// `[stock] from = "part.toml"`: the outline of a part file (relative to the job's folder),
/// placed by the table's own `reverse`, `front`, `grip`. Returns the stock and the file's name.
fn stock_from(
    cx: &Cx<'_>,
    s: &Spanned<RawStock>,
    from: &Spanned<String>,
    key: &str,
    base: &str,
    resolve: &mut dyn Resolve,
) -> Result<(JobStock, String), JobError> {
    let r = s.get_ref();
    let k = |n: &str| format!("{key}.{n}");
    let other = [
        ("diameter", r.diameter.as_ref().map(|v| v.span())),
        ("length", r.length.as_ref().map(|v| v.span())),
        ("bore", r.bore.as_ref().map(|v| v.span())),
        ("outline", r.outline.as_ref().map(|v| v.span())),
        ("none", r.none.as_ref().map(|v| v.span())),
        ("block", r.block.as_ref().map(|v| v.span())),
    ];
    if let Some((name, Some(at))) = other.into_iter().find(|(_, v)| v.is_some()) {
        return Err(cx.err(
            at,
            k(name),
            "a stock `from` a part file takes its outline from that file: give `from` or the stock's sizes, not both",
        ));
    }
    if from.get_ref().trim().is_empty() {
        return Err(cx.err(from.span(), k("from"), "the part file name is empty"));
    }
    let (name, text) = resolve.read(base, from.get_ref()).map_err(|why| {
        cx.err(
            from.span(),
            k("from"),
            format!("cannot read the part file {}: {why}", from.get_ref()),
        )
    })?;
    let pcx = Cx::new(&text, &name);
    let part: RawPartFile = machine::deserialize(&pcx, "a part file ([stock] outline = [...])")?;
    let poly = pcx.stock_outline("stock.outline", &part.stock.get_ref().outline)?;
    let at = place(cx, from.span(), &k("from"));
    Ok((placed_part(cx, r, poly, key, at)?, name))
}

// ---------------------------------------------------------------------------------------------
// Operations (`[[operations]]`).

/// The latest start of one kind (a line, a stop) so far, and the key of its operation.
type Latest = Option<(i64, String)>;

/// A `[chuck.jaws]` table (a job's, or an operation's `chuck.jaws`) as the keys it gives, each
/// with its place: `key` is the table's full key (`chuck.jaws`, `operations[0].chuck.jaws`).
fn job_jaws(cx: &Cx<'_>, j: &Spanned<RawJaws>, key: &str, label: &str) -> JobJaws {
    let set = |v, at: Range<usize>, k: String| Set {
        value: v,
        at: place(cx, at, &k),
        layer: label.to_string(),
    };
    let r = j.get_ref();
    let size = |name: &str, v: &Option<Num>| -> Option<Set<f64>> {
        let v = v.as_ref()?;
        let k = format!("{key}.{name}");
        cx.keep(cx.length(&k, v)).map(|x| set(x, v.span(), k))
    };
    JobJaws {
        table: Some(Set {
            value: (),
            at: place(cx, j.span(), key),
            layer: label.to_string(),
        }),
        grip: r.grip.as_ref().map(|g| Set {
            value: g.get_ref().value(),
            at: place(cx, g.span(), &format!("{key}.grip")),
            layer: label.to_string(),
        }),
        kind: r.kind.as_ref().map(|k| Set {
            value: k.get_ref().value(),
            at: place(cx, k.span(), &format!("{key}.type")),
            layer: label.to_string(),
        }),
        grip_diameter: size("grip_diameter", &r.grip_diameter),
        grip_length: size("grip_length", &r.grip_length),
        height: size("height", &r.height),
        width: size("width", &r.width),
        step: size("step", &r.step),
    }
}

fn operations(
    cx: &Cx<'_>,
    ops: &Spanned<Vec<Spanned<RawOperation>>>,
    prefix: &str,
    label: &str,
) -> Option<Vec<Set<JobOperation>>> {
    if ops.get_ref().len() > MAX_OPERATIONS {
        cx.push(cx.err(
            ops.span(),
            format!("{prefix}operations"),
            format!("too many operations: at most {MAX_OPERATIONS}"),
        ));
        return None;
    }
    let mut out: Vec<Set<JobOperation>> = Vec::new();
    let (mut last_line, mut last_stop): (Latest, Latest) = (None, None);
    for (i, o) in ops.get_ref().iter().enumerate() {
        let k = format!("{prefix}operations[{i}]");
        let Some(v) = cx.keep(operation(cx, o, &k, label, &mut last_line, &mut last_stop)) else {
            continue;
        };
        out.push(Set {
            value: v,
            at: place(cx, o.span(), &k),
            layer: label.to_string(),
        });
    }
    Some(out)
}

/// One `[[operations]]` entry. `last_line` and `last_stop`: the latest start of each kind so far
/// (operations start in the order they are listed).
fn operation(
    cx: &Cx<'_>,
    o: &Spanned<RawOperation>,
    k: &str,
    label: &str,
    last_line: &mut Latest,
    last_stop: &mut Latest,
) -> Result<JobOperation, JobError> {
    let r = o.get_ref();
    let kk = |n: &str| format!("{k}.{n}");
    let given: Vec<(&str, std::ops::Range<usize>)> = [
        ("line", r.line.as_ref().map(|v| v.span())),
        ("stop", r.stop.as_ref().map(|v| v.span())),
        ("work_offset", r.work_offset.as_ref().map(|v| v.span())),
    ]
    .into_iter()
    .filter_map(|(k, at)| at.map(|at| (k, at)))
    .collect();
    if given.len() > 1 {
        let (second, at) = given[1].clone();
        return Err(cx.err(
            at,
            kk(second),
            format!(
                "an operation starts at one place: give one of `line`, `stop` and `work_offset`, not `{}` and `{second}`",
                given[0].0
            ),
        ));
    }
    let start = match (&r.line, &r.stop, &r.work_offset) {
        (None, None, None) => {
            return Err(cx.err(
                o.span(),
                kk("line"),
                "missing required key `line` (the program line where the operation starts; or `stop`, the program stop after which it starts; or `work_offset`, the work offset whose first selection starts it)",
            ))
        }
        (Some(l), _, _) => {
            let v = *l.get_ref();
            if !(1..=i64::from(u32::MAX)).contains(&v) {
                return Err(cx.err(l.span(), kk("line"), format!("{v} is not a line: lines count from 1")));
            }
            if let Some((before, by)) = last_line.as_ref().filter(|(b, _)| *b >= v) {
                return Err(cx.err(
                    l.span(),
                    kk("line"),
                    format!("line {v} does not come after line {before} of {by}: list the operations in the order they start"),
                ));
            }
            *last_line = Some((v, k.to_string()));
            OpStart::Line(v as u32)
        }
        (None, Some(s), _) => {
            let v = *s.get_ref();
            if !(1..=i64::from(u32::MAX)).contains(&v) {
                return Err(cx.err(s.span(), kk("stop"), format!("{v} is not a program stop: the first is stop = 1")));
            }
            if let Some((before, by)) = last_stop.as_ref().filter(|(b, _)| *b >= v) {
                return Err(cx.err(
                    s.span(),
                    kk("stop"),
                    format!("stop {v} does not come after stop {before} of {by}: list the operations in the order they start"),
                ));
            }
            *last_stop = Some((v, k.to_string()));
            OpStart::Stop(v as u32)
        }
        (None, None, Some(w)) => {
            let name = w.get_ref().trim().to_ascii_uppercase();
            match machine::WORK_OFFSET_NAMES.iter().position(|n| *n == name) {
                Some(n) => OpStart::WorkOffset(n as u8),
                None => {
                    return Err(cx.err(
                        w.span(),
                        kk("work_offset"),
                        format!("{:?} is not a work offset: give one of \"G54\" to \"G59\"", w.get_ref()),
                    ))
                }
            }
        }
    };
    let reverse = r.reverse.as_ref().is_some_and(|v| *v.get_ref());
    let stand = stand_of(
        cx,
        r.front.as_ref().map(|f| (f, kk("front"))),
        r.grip.as_ref().map(|g| (g, kk("grip"))),
    )?;
    let stand = match (stand, &r.reverse) {
        (Some((s, _)), _) => s,
        (None, Some(rv)) if reverse => {
            return Err(cx.err(
                rv.span(),
                kk("reverse"),
                "a part turned round needs where it then stands: give `front` (z of its front face) or `grip` (the length held in the jaws)",
            ))
        }
        (None, _) => Stand::Stay,
    };
    let (mut chuck, mut chuck_at, mut jaws) = (None, None, None);
    if let Some(c) = &r.chuck {
        match (&c.get_ref().outline, &c.get_ref().jaws) {
            (Some(ol), None) => {
                if ol.get_ref().len() > machine::MAX_OUTLINE_POINTS {
                    return Err(cx.err(ol.span(), kk("chuck.outline"), "too many points"));
                }
                chuck = Some(cx.outline(&kk("chuck.outline"), ol)?);
                chuck_at = Some(place(cx, c.span(), &kk("chuck.outline")));
            }
            (None, Some(j)) => {
                jaws = Some(job_jaws(cx, j, &kk("chuck.jaws"), label));
                chuck_at = Some(place(cx, j.span(), &kk("chuck.jaws")));
            }
            (Some(ol), Some(_)) => {
                return Err(cx.err(
                    ol.span(),
                    kk("chuck.outline"),
                    "give an operation's jaws either as an `outline` or as `jaws` over the job's jaws, not both",
                ))
            }
            (None, None) => {
                return Err(cx.err(
                    c.span(),
                    kk("chuck"),
                    "missing required key `outline` (or a `jaws` table)",
                ))
            }
        }
    }
    let program_zero_z = match &r.program_zero_z {
        None => None,
        Some(z) => Some(cx.coord(&kk("program_zero_z"), z)?),
    };
    let (mut tailstock_in_use, mut tailstock_z, mut tailstock_at) = (None, None, None);
    if let Some(t) = &r.tailstock {
        let raw = t.get_ref();
        tailstock_in_use = raw.in_use.as_ref().map(|v| *v.get_ref());
        if let Some(z) = &raw.z {
            tailstock_z = Some(cx.coord(&kk("tailstock.z"), z)?);
        }
        tailstock_at = Some(place(cx, t.span(), &kk("tailstock")));
    }
    Ok(JobOperation {
        tailstock_in_use,
        tailstock_z,
        tailstock_at,
        start,
        reverse,
        stand,
        chuck,
        program_zero_z,
        note: r.note.as_ref().map(|n| n.get_ref().clone()),
        chuck_at,
        jaws,
    })
}

/// A tool entry's values, validated, before they are laid over one another (`tbl`, then `use`,
/// then the entry's own keys).
#[derive(Default)]
struct Partial {
    name: Option<String>,
    tip: Option<Placing>,
    insert: Option<(Geom, Place)>,
    holder: Option<(Geom, Place)>,
    nose_radius: Option<f64>,
    tip_direction: Option<u8>,
    drill: Option<(DrillSpec, Place)>,
    mill: Option<(MillSpec, Place)>,
}

impl Partial {
    fn over(&mut self, top: Partial) {
        macro_rules! take {
            ($($f:ident),*) => { $( if top.$f.is_some() { self.$f = top.$f; } )* };
        }
        take!(name, tip, insert, holder, nose_radius, tip_direction, drill, mill);
    }

    fn from_built(b: BuiltTool, at: &Place) -> Partial {
        Partial {
            insert: Some((Geom::Outline(b.insert), at.clone())),
            holder: Some((Geom::Outline(b.holder), at.clone())),
            nose_radius: Some(b.nose_radius),
            tip_direction: Some(b.tip_direction),
            ..Partial::default()
        }
    }
}

/// The validated values of one raw tool entry (of a job or a library), in its own file.
fn partial(cx: &Cx<'_>, t: &RawTool, key: &str) -> Result<Partial, JobError> {
    let k = |n: &str| format!("{key}.{n}");
    let mut p = Partial::default();
    if let Some(n) = &t.name {
        let name = n.get_ref().trim().to_string();
        if name.is_empty() {
            return Err(cx.err(n.span(), k("name"), "must not be blank"));
        }
        p.name = Some(name);
    }
    p.tip = tool_entry::placing(cx, key, t.tip.as_ref(), t.geometry_offset.as_ref())?;
    for (which, v) in [("insert", &t.insert), ("holder", &t.holder)] {
        let Some(v) = v else { continue };
        let g = tool_entry::geom(cx, &k(which), v)?;
        let slot = (g, place(cx, v.span(), &k(which)));
        if which == "insert" {
            p.insert = Some(slot);
        } else {
            p.holder = Some(slot);
        }
    }
    if let Some(r) = &t.nose_radius {
        p.nose_radius = Some(cx.within(&k("nose_radius"), r, machine::NOSE_RADIUS_RANGE, "mm")?);
    }
    if let Some(d) = &t.tip_direction {
        match u8::try_from(*d.get_ref()) {
            Ok(v) if v <= 9 => p.tip_direction = Some(v),
            _ => {
                return Err(cx.err(
                    d.span(),
                    k("tip_direction"),
                    format!(
                        "{} is not a tip direction: give a whole number from 0 to 9",
                        d.get_ref()
                    ),
                ))
            }
        }
    }
    if let Some(d) = &t.drill {
        let spec = tool_entry::drill(cx, &k("drill"), d.get_ref())?;
        p.drill = Some((spec, place(cx, d.span(), &k("drill"))));
    }
    match (&t.mill, &t.live) {
        (Some(m), Some(l)) => {
            let r = m.get_ref();
            let live = match l.get_ref().as_str() {
                "axial" => Live::Axial,
                "radial" => Live::Radial,
                other => {
                    return Err(cx.err(
                        l.span(),
                        k("live"),
                        format!("{other:?} is not a live station: give \"axial\" or \"radial\""),
                    ))
                }
            };
            let opt = |n: &str, v: &Option<Num>| -> Result<Option<f64>, JobError> {
                v.as_ref().map(|v| cx.length(&k(&format!("mill.{n}")), v)).transpose()
            };
            let spec = MillSpec {
                kind: r.kind.get_ref().clone(),
                diameter: cx.length(&k("mill.diameter"), &r.diameter)?,
                flute_length: cx.length(&k("mill.flute_length"), &r.flute_length)?,
                stick_out: cx.length(&k("mill.stick_out"), &r.stick_out)?,
                corner_radius: opt("corner_radius", &r.corner_radius)?,
                point_angle: match &r.point_angle {
                    None => None,
                    Some(a) => Some(cx.within(&k("mill.point_angle"), a, (1.0, 180.0), "degrees")?),
                },
                pitch: opt("pitch", &r.pitch)?,
                shank: opt("shank", &r.shank)?,
                holder_diameter: cx.length(&k("mill.holder.diameter"), &r.holder.diameter)?,
                holder_length: cx.length(&k("mill.holder.length"), &r.holder.length)?,
                live,
            };
            p.mill = Some((spec, place(cx, m.span(), &k("mill"))));
        }
        (Some(m), None) => {
            return Err(cx.err(
                m.span(),
                k("live"),
                "a milling tool needs `live = \"axial\"` or `live = \"radial\"`: which way its station points it",
            ))
        }
        (None, Some(l)) => {
            return Err(cx.err(l.span(), k("live"), "`live` goes with `mill = { … }`"));
        }
        (None, None) => {}
    }
    Ok(p)
}

fn job_tool(
    cx: &Cx<'_>,
    job: &RawJob,
    t: &RawTool,
    station: u32,
    key: &str,
    prefix: &str,
    refs: &mut Refs<'_>,
) -> Result<JobTool, JobError> {
    let k = |n: &str| format!("{key}.{n}");
    let mut origin = Vec::new();
    let mut p = Partial::default();
    let mut default_name = None;
    if let Some(n) = &t.tbl {
        let Some(table) = &job.tool_table else {
            return Err(cx.err(
                n.span(),
                k("tbl"),
                format!("`tbl` takes a tool of the job's tool table: give `{prefix}tool_table = \"FILE.tbl\"`"),
            ));
        };
        let (shown, tools) = read_table(cx, job, table, prefix, refs)?;
        let want = *n.get_ref();
        let Some(row) = tools.iter().find(|r| r.tool == want) else {
            return Err(cx.err(n.span(), k("tbl"), format!("{shown} has no tool T{want}")));
        };
        let at = place(cx, n.span(), &k("tbl"));
        let (base, name) = tbl_partial(row, shown, &at)?;
        p = base;
        default_name = Some(name);
        origin.push(format!("tbl {want} ({shown})"));
    }
    if let Some(id) = &t.use_ {
        let Some(lib) = &job.tool_library else {
            return Err(cx.err(
                id.span(),
                k("use"),
                format!("`use` takes an entry of the job's tool library: give `{prefix}tool_library = \"FILE.toml\"`"),
            ));
        };
        if refs.library.is_none() {
            let got = refs.resolve.read(refs.base, lib.get_ref()).map_err(|why| {
                cx.err(
                    lib.span(),
                    format!("{prefix}tool_library"),
                    format!("cannot read {}: {why}", lib.get_ref()),
                )
            })?;
            refs.library = Some(got);
        }
        let Some((shown, text)) = &refs.library else {
            unreachable!()
        };
        let lcx = Cx::new(text, shown);
        let raw: RawLibrary = machine::deserialize(&lcx, "a tool library")?;
        if raw.tools.len() > MAX_JOB_TOOLS {
            return Err(lcx.err(0..0, "tools", format!("too many tools: at most {MAX_JOB_TOOLS}")));
        }
        let want = id.get_ref().as_str();
        let mut found = None;
        for (i, e) in raw.tools.iter().enumerate() {
            let lk = format!("tools[{i}]");
            let r = e.get_ref();
            let Some(eid) = &r.id else {
                return Err(lcx.err(e.span(), format!("{lk}.id"), "missing required key `id`"));
            };
            for (bad, v) in [
                ("station", r.station.is_some()),
                ("use", r.use_.is_some()),
                ("tbl", r.tbl.is_some()),
            ] {
                if v {
                    return Err(lcx.err(
                        e.span(),
                        format!("{lk}.{bad}"),
                        format!("a tool library entry has no `{bad}`: the job that uses it says that"),
                    ));
                }
            }
            if eid.get_ref() == want {
                found = Some((i, e));
            }
        }
        let Some((i, e)) = found else {
            return Err(cx.err(id.span(), k("use"), format!("{shown} has no tool with id = {want:?}")));
        };
        p.over(partial(&lcx, e.get_ref(), &format!("tools[{i}]"))?);
        if default_name.is_none() || p.name.is_some() {
            default_name = Some(want.to_string());
        }
        origin.push(format!("use {want} ({shown})"));
    }
    p.over(partial(cx, t, key)?);

    // Catalogue designations and drills.
    use tool_entry::given;
    let mut built: Option<BuiltTool> = None;
    let mut mill: Option<MillTool> = None;
    if let Some((m, at)) = &p.mill {
        if p.insert.is_some() || p.holder.is_some() || p.drill.is_some() {
            return Err(
                at.err("a milling tool is given by its sizes alone: leave out insert, holder and drill".to_string())
            );
        }
        let (b, t, _) =
            tooling::milling::build(m).map_err(|e| at.err(format!("cannot build the milling tool: {e}")))?;
        origin.push(format!("mill: {}", b.summary));
        built = Some(b);
        mill = Some(t);
    } else if let Some(b) = tool_entry::build(given(&p.insert), given(&p.holder), given(&p.drill))
        .map_err(|(at, message)| at.err(message))?
    {
        origin.push(format!("catalogue: {}", b.summary));
        built = Some(b);
    }
    let outline = |g: Option<(Geom, Place)>, which: &str, built: Option<&Polygon>| -> Result<Polygon, JobError> {
        match (g, built) {
            (Some((Geom::Outline(o), _)), _) => Ok(o),
            (_, Some(b)) => Ok(b.clone()),
            _ => Err(cx.err(
                0..0,
                k(which),
                format!(
                    "missing required key `{which}`: give an outline, a catalogue designation, `drill`, `use` or `tbl`"
                ),
            )),
        }
    };
    let place_of_entry = |n: &str| -> JobError {
        let e = cx.err(0..0, k(n), format!("missing required key `{n}`"));
        e
    };
    let insert = outline(p.insert, "insert", built.as_ref().map(|b| &b.insert)).map_err(|e| relocate(e, cx, t))?;
    let holder = outline(p.holder, "holder", built.as_ref().map(|b| &b.holder)).map_err(|e| relocate(e, cx, t))?;
    let placing = p.tip.ok_or_else(|| relocate(place_of_entry("tip"), cx, t))?;
    // A geometry offset becomes a tip where the job meets the machine (its machine zero).
    let (tip, geometry_offset) = match placing {
        Placing::Tip(tip) => (tip, None),
        Placing::Offset(g) => (P2::new(0.0, 0.0), Some(g)),
    };
    let name = p
        .name
        .or(default_name)
        .ok_or_else(|| relocate(place_of_entry("name"), cx, t))?;
    if origin.is_empty() {
        origin.push("outlines".into());
    }
    if let Some(g) = &geometry_offset {
        origin.push(format!("geometry offset {}", g.show()));
    }
    let cutter = tool_entry::cutter(built.as_ref(), &name);
    Ok(JobTool {
        tool: Tool {
            station,
            cutter,
            name,
            tip,
            insert,
            holder,
            nose_radius: p.nose_radius.or(built.as_ref().map(|b| b.nose_radius)).unwrap_or(0.0),
            tip_direction: p.tip_direction.or(built.as_ref().map(|b| b.tip_direction)).unwrap_or(0),
            mill,
        },
        origin: origin.join(", "),
        geometry_offset,
    })
}

/// The job's tool table, read once per layer: the name messages show and its rows.
fn read_table<'a>(
    cx: &Cx<'_>,
    raw: &RawJob,
    table: &Spanned<String>, // `raw.tool_table`, which the caller has found given
    prefix: &str,
    refs: &'a mut Refs<'_>,
) -> Result<(&'a str, &'a [tbl::TblTool]), JobError> {
    if refs.table.is_none() {
        let (shown, text) = refs.resolve.read(refs.base, table.get_ref()).map_err(|why| {
            cx.err(
                table.span(),
                format!("{prefix}tool_table"),
                format!("cannot read {}: {why}", table.get_ref()),
            )
        })?;
        let tools = tbl::parse(&text).map_err(|e| {
            cx.err(
                table.span(),
                format!("{prefix}tool_table"),
                format!("{shown}:{}:{}: {}", e.line, e.col, e.message),
            )
        })?;
        // The table's lengths are in the LinuxCNC machine's units; the job's are mm.
        let inch = raw
            .tool_table_units
            .as_ref()
            .or(raw.units.as_ref())
            .is_some_and(|u| matches!(u.get_ref(), RawUnits::Inch));
        let tools = tools.iter().map(|t| t.in_mm(inch)).collect();
        refs.table = Some((shown, tools));
    }
    let Some((shown, tools)) = &refs.table else {
        unreachable!()
    };
    Ok((shown, tools))
}

/// A tool table's row as a tool entry's values (`[[tools]] tbl = N`, `[tool_numbers]
/// from_table`): its shape from D, I, J and Q, its tip [X, Z], and its name (the comment, else
/// `T<n>`).
fn tbl_partial(row: &tbl::TblTool, shown: &str, at: &Place) -> Result<(Partial, String), JobError> {
    let want = row.tool;
    let built = tooling::tbl::shape(row).map_err(|e| {
        at.err(format!(
            "cannot build tool T{want} of {shown} ({}): {}",
            e.key, e.message
        ))
    })?;
    let mut base = Partial::from_built(built, at);
    base.tip = Some(Placing::Tip(crate::geom::p2(row.x, row.z)));
    let name = if row.comment.trim().is_empty() {
        format!("T{want}")
    } else {
        row.comment.trim().to_string()
    };
    Ok((base, name))
}

/// `[tool_numbers]`: `T<tool> = <station>` entries and `from_table = true` (docs/job.md "Tool
/// numbers"). Stations are checked against the turret when the job is applied.
fn tool_numbers(
    cx: &Cx<'_>,
    raw: &RawJob,
    map: &Spanned<std::collections::BTreeMap<Spanned<String>, Spanned<RawTn>>>,
    prefix: &str,
    label: &str,
    refs: &mut Refs<'_>,
    l: &mut Layer,
) {
    let key = |k: &str| format!("{prefix}tool_numbers.{k}");
    let mut from_table = None;
    for (k, v) in map.get_ref() {
        let name = k.get_ref().as_str();
        if name == "from_table" {
            match v.get_ref() {
                RawTn::Flag(true) => from_table = Some(v.span()),
                RawTn::Flag(false) => {}
                RawTn::Number(_) => cx.push(cx.err(v.span(), key(name), "invalid type: expected true or false")),
            }
            continue;
        }
        let tool = name
            .strip_prefix(['T', 't'])
            .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|d| d.parse::<u32>().ok());
        let Some(tool) = tool.filter(|t| (1..=tbl::MAX_NUMBER).contains(t)) else {
            cx.push(cx.err(
                k.span(),
                key(name),
                format!(
                    "`{name}` is not a tool number: write T<tool> = <station> (T12 = 3, tools 1 to {}) or from_table = true",
                    tbl::MAX_NUMBER
                ),
            ));
            continue;
        };
        let RawTn::Number(station) = *v.get_ref() else {
            cx.push(cx.err(v.span(), key(name), "invalid type: expected a station number"));
            continue;
        };
        if !(1..=i64::from(machine::MAX_STATIONS)).contains(&station) {
            cx.push(cx.err(
                v.span(),
                key(name),
                format!(
                    "station {station} does not exist: stations run from 1 to {}",
                    machine::MAX_STATIONS
                ),
            ));
            continue;
        }
        let kk = key(&format!("T{tool}"));
        if let Some(o) = l.tool_numbers.iter().find(|o| o.value.0 == tool) {
            cx.push(cx.err(k.span(), kk, format!("tool {tool} is already given by {}", o.at.key)));
            continue;
        }
        l.tool_numbers.push(Set {
            value: (tool, station as u32),
            at: place(cx, v.span(), &kk),
            layer: label.to_string(),
        });
    }
    let Some(span) = from_table else { return };
    let fk = key("from_table");
    let Some(table) = &raw.tool_table else {
        cx.push(cx.err(
            span,
            fk,
            format!("`from_table` takes the tools of the job's tool table: give `{prefix}tool_table = \"FILE.tbl\"`"),
        ));
        return;
    };
    let at = place(cx, span.clone(), &fk);
    let (shown, rows) = match read_table(cx, raw, table, prefix, refs) {
        Ok(t) => t,
        Err(e) => {
            cx.push(e);
            return;
        }
    };
    let mut out = Vec::new();
    for row in rows {
        if row.pocket == 0 && !l.tool_numbers.iter().any(|n| n.value.0 == row.tool) {
            cx.push(at.err(format!(
                "{shown}: T{} is in pocket 0, which is no turret station: give its station with tool_numbers.T{} = STATION",
                row.tool, row.tool
            )));
            continue;
        }
        let built = tbl_partial(row, shown, &at).map(|(p, name)| {
            let outline = |g: Option<(Geom, Place)>| match g {
                Some((Geom::Outline(o), _)) => o,
                _ => unreachable!("a table row's shape is outlines"),
            };
            JobTool {
                tool: Tool {
                    station: row.pocket,
                    cutter: tooling::Cutter::from_name(&name),
                    name,
                    tip: p.tip.map_or_else(P2::default, |t| t.tip(P2::default())),
                    insert: outline(p.insert),
                    holder: outline(p.holder),
                    nose_radius: p.nose_radius.unwrap_or(0.0),
                    tip_direction: p.tip_direction.unwrap_or(0),
                    mill: None,
                },
                origin: format!("tbl {} ({shown})", row.tool),
                geometry_offset: None,
            }
        });
        match built {
            Ok(t) => out.push((row.tool, row.pocket, t)),
            Err(e) => cx.push(e),
        }
    }
    l.tool_numbers_table = Some(Set {
        value: TableNumbers {
            file: shown.to_string(),
            rows: out,
        },
        at,
        layer: label.to_string(),
    });
}

/// An error about a missing key of a tool entry, placed at the entry (its `station`).
fn relocate(mut e: JobError, cx: &Cx<'_>, t: &RawTool) -> JobError {
    if let Some(s) = &t.station {
        let p = place(cx, s.span(), "");
        e.line = p.line;
        e.col = p.col;
    }
    e
}
