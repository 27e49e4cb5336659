//! Jobs: what changes from program to program on one machine (docs/job.md).
//!
//! A machine file describes the lathe; a **job** describes the stock, program zero, the jaws
//! (a chuck outline, or `[chuck.jaws]` over the machine file's body and jaws), whether the
//! tailstock is in use, the program's units and dialect, which tool sits in which station, and
//! the operations of a part turned round. Jobs come in layers (the machine's own setup,
//! `latheguard.toml`, its overrides, the file beside the program, `--job`, one-off flags):
//! [`parse`] reads one layer, [`EffectiveJob::merge`] lays them over one another (a later layer
//! wins key by key, `[stock]` and `chuck.outline` as whole tables, `[chuck.jaws]` key by key,
//! `[[tools]]` station by station, `[[operations]]` as a whole list), and [`apply`] turns a
//! machine and the merged job into the [`Machine`] the checker runs, validated as a machine file
//! is (the jaws fit together, the stock fits the chuck, every part clear at home). On a machine
//! whose chuck is given by its body and jaws, the jaws close on the job's bar unless a layer
//! gives `chuck.jaws.grip_diameter` ([`grip_from_stock`]).
//!
//! The library does no I/O: a job that names a tool library or a LinuxCNC tool table gets their
//! text through a [`Resolve`]r, which the binary backs with the file system.
//!
//! Errors are [`JobError`]s (the machine file's error type): file, line, column, dotted key.

mod parse;
#[cfg(test)]
mod tests;

use crate::geom::Polygon;
use crate::machine::{self, jaws, ChuckForm, Dialect, Machine, McodeTable, Stock, Tool, WorkOffset};

pub use parse::{parse, parse_embedded, schema, Embedded, JobSchema, RawJob, MAX_JOB_TOOLS};

/// A job that cannot be used: where and why (`file:line:col: key: message`, one line per
/// problem). The same type as a machine file's errors.
pub type JobError = machine::MachineError;

/// Gives the text of a file a job names (`tool_library`, `tool_table`).
pub trait Resolve {
    /// The file `rel` names, relative to the folder `base` (as the layer's caller gave it):
    /// the name messages show for it and its text, or why it cannot be read.
    fn read(&mut self, base: &str, rel: &str) -> Result<(String, String), String>;
}

impl<F: FnMut(&str, &str) -> Result<(String, String), String>> Resolve for F {
    fn read(&mut self, base: &str, rel: &str) -> Result<(String, String), String> {
        self(base, rel)
    }
}

/// Where a value was written: file, 1-based line and column, and its dotted key.
#[derive(Clone, Debug, PartialEq)]
pub struct Place {
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub key: String,
}

impl Place {
    /// A place on the command line: `(command line):1:1: --stock`.
    pub fn command_line(flag: &str) -> Place {
        Place {
            file: "(command line)".into(),
            line: 1,
            col: 1,
            key: flag.into(),
        }
    }

    pub fn err(&self, message: impl Into<String>) -> JobError {
        self.err_key(&self.key, message)
    }

    fn err_key(&self, key: &str, message: impl Into<String>) -> JobError {
        JobError {
            file: self.file.clone(),
            line: self.line,
            col: self.col,
            key: key.to_string(),
            message: message.into(),
            also: Vec::new(),
        }
    }
}

/// A value a layer sets: the value, where it was written, and the layer's label.
#[derive(Clone, Debug, PartialEq)]
pub struct Set<T> {
    pub value: T,
    pub at: Place,
    pub layer: String,
}

/// `dialect = "fanuc" | "linuxcnc" | "auto"`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DialectChoice {
    Fanuc,
    Linuxcnc,
    /// Keeps the machine file's dialect: a machine whose file says `dialect = "auto"` reads it
    /// from each program's own signs (`machine::auto`), any other keeps its own.
    Auto,
}

impl DialectChoice {
    pub fn as_str(self) -> &'static str {
        match self {
            DialectChoice::Fanuc => "fanuc",
            DialectChoice::Linuxcnc => "linuxcnc",
            DialectChoice::Auto => "auto",
        }
    }
}

/// A job's stock: a bar or tube, a revolved outline (`outline`), or none at all (`none`).
/// `front` (`stick_out` in job files) is None only from `--stock` without `@STICKOUT`, when the
/// machine's stock front applies. With an outline, `diameter`, `length` and `front` are its
/// bounding bar; with `none`, the sizes are 0 and mean nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct JobStock {
    pub diameter: f64,
    pub length: f64,
    pub front: Option<f64>,
    pub bore: f64,
    /// A revolved outline in the half plane x ≥ 0 (a casting, a forging, a second operation).
    pub outline: Option<Polygon>,
    /// `block = { width, height }`: a prismatic block (`length`, `front` as the bar's;
    /// `diameter` is then its corners' diameter).
    pub block: Option<machine::Block>,
    /// `none = true`: no stock in the scene (a dry run in the air).
    pub none: bool,
    /// Where `diameter` and `length` were written (errors of a stock that does not fit).
    pub diameter_at: Place,
    pub length_at: Place,
}

impl JobStock {
    /// `none = true`, written at `at`: no stock in the scene.
    pub fn none_at(at: Place) -> JobStock {
        JobStock {
            diameter: 0.0,
            length: 0.0,
            front: None,
            bore: 0.0,
            outline: None,
            block: None,
            none: true,
            diameter_at: at.clone(),
            length_at: at,
        }
    }
}

/// A job's `[chuck.jaws]`: each key it gives, over the machine file's jaws (key by key, also
/// from layer to layer). The machine's chuck must be given by its `body` and `jaws`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct JobJaws {
    /// Where the (last) `[chuck.jaws]` table was written: set whenever a layer gives one, even
    /// an empty one.
    pub table: Option<Set<()>>,
    pub grip: Option<Set<jaws::Grip>>,
    pub kind: Option<Set<jaws::JawType>>,
    pub grip_diameter: Option<Set<f64>>,
    pub grip_length: Option<Set<f64>>,
    pub height: Option<Set<f64>>,
    pub width: Option<Set<f64>>,
    pub step: Option<Set<f64>>,
}

impl JobJaws {
    /// Whether no layer gave `[chuck.jaws]`.
    pub fn is_empty(&self) -> bool {
        self.table.is_none()
    }

    fn lay_over(&mut self, l: &JobJaws) {
        fn over<T: Clone>(to: &mut Option<Set<T>>, from: &Option<Set<T>>) {
            if from.is_some() {
                to.clone_from(from);
            }
        }
        over(&mut self.table, &l.table);
        over(&mut self.grip, &l.grip);
        over(&mut self.kind, &l.kind);
        over(&mut self.grip_diameter, &l.grip_diameter);
        over(&mut self.grip_length, &l.grip_length);
        over(&mut self.height, &l.height);
        over(&mut self.width, &l.width);
        over(&mut self.step, &l.step);
    }

    /// `jaws`'s values with this job's keys over them.
    fn over(&self, jaws: &jaws::Jaws) -> jaws::Jaws {
        let v = |s: &Option<Set<f64>>, d: f64| s.as_ref().map_or(d, |s| s.value);
        jaws::Jaws {
            grip: self.grip.as_ref().map_or(jaws.grip, |s| s.value),
            kind: self.kind.as_ref().map_or(jaws.kind, |s| s.value),
            grip_diameter: v(&self.grip_diameter, jaws.grip_diameter),
            grip_length: v(&self.grip_length, jaws.grip_length),
            height: v(&self.height, jaws.height),
            width: v(&self.width, jaws.width),
            step: v(&self.step, jaws.step),
        }
    }

    /// Where this job wrote a size of the jaws (`jaws.step`, as [`jaws::JawError`] names them).
    fn place_of(&self, key: &str) -> Option<&Place> {
        let at = match key {
            "jaws.grip_diameter" => self.grip_diameter.as_ref().map(|s| &s.at),
            "jaws.grip_length" => self.grip_length.as_ref().map(|s| &s.at),
            "jaws.height" => self.height.as_ref().map(|s| &s.at),
            "jaws.width" => self.width.as_ref().map(|s| &s.at),
            "jaws.step" => self.step.as_ref().map(|s| &s.at),
            _ => None,
        };
        at
    }

    /// The labels of the layers that gave a key of the jaws, in the order of the keys, once each.
    pub fn layers(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        let labels = [
            self.grip.as_ref().map(|s| s.layer.as_str()),
            self.kind.as_ref().map(|s| s.layer.as_str()),
            self.grip_diameter.as_ref().map(|s| s.layer.as_str()),
            self.grip_length.as_ref().map(|s| s.layer.as_str()),
            self.height.as_ref().map(|s| s.layer.as_str()),
            self.width.as_ref().map(|s| s.layer.as_str()),
            self.step.as_ref().map(|s| s.layer.as_str()),
            self.table.as_ref().map(|s| s.layer.as_str()),
        ];
        for l in labels.into_iter().flatten() {
            if !out.contains(&l) {
                out.push(l);
            }
        }
        out
    }
}

/// One of a job's operations after the first (`[[operations]]`, docs/job.md "Operations"),
/// validated: where it starts and how the part then stands.
#[derive(Clone, Debug, PartialEq)]
pub struct JobOperation {
    pub start: machine::OpStart,
    pub reverse: bool,
    pub stand: crate::scene::Stand,
    /// Its own jaws (`chuck.outline`); None: the job's chuck.
    pub chuck: Option<Polygon>,
    /// G54's program zero from this operation on.
    pub program_zero_z: Option<f64>,
    pub note: Option<String>,
    /// Where its `chuck.outline` (or `chuck.jaws`) was written (errors of jaws that meet the
    /// turret at home).
    pub chuck_at: Option<Place>,
    /// Its own jaws as keys over the job's (`chuck.jaws`); the machine's chuck must be given by
    /// its body and jaws.
    pub jaws: Option<JobJaws>,
    /// `tailstock.in_use`: the tailstock advanced as the operation begins (true) or no obstacle
    /// from then on (false); None: as it stood.
    pub tailstock_in_use: Option<bool>,
    /// `tailstock.z`: where its live centre's tip stands in this operation.
    pub tailstock_z: Option<f64>,
    /// Where its `tailstock` table was written.
    pub tailstock_at: Option<Place>,
}

/// A tool a job puts in a station, built, and how it was described.
#[derive(Clone, Debug, PartialEq)]
pub struct JobTool {
    pub tool: Tool,
    /// `outlines`, `catalogue: …`, `use T-ROUGH (tools.toml)`, `tbl 3 (lathe.tbl)`.
    pub origin: String,
    /// Given as the control's geometry offset (`geometry_offset`): `tool.tip` is set from it
    /// with the machine's machine zero when the job is applied.
    pub geometry_offset: Option<machine::GeometryOffset>,
}

/// `[tool_numbers] from_table = true`: the tools of a layer's LinuxCNC tool table, each in its
/// pocket (docs/job.md "Tool numbers").
#[derive(Clone, Debug, PartialEq)]
pub struct TableNumbers {
    /// The table as messages name it (`lathe.tbl`).
    pub file: String,
    /// `(tool, pocket, its tool built from the row as `[[tools]] tbl` builds it)`, in the
    /// table's order; the tool's station is set where it lands.
    pub rows: Vec<(u32, u32, JobTool)>,
}

/// One layer of a job, validated on its own (values in range, outlines simple, tools complete).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    /// What set it, for `latheguard setup` and the reports: a file name, `latheguard.toml [job]`,
    /// `command line`.
    pub label: String,
    /// The files read for it: the job file (when it is one), its tool library and tool table.
    pub files: Vec<String>,
    pub units_inch: Option<Set<bool>>,
    pub dialect: Option<Set<DialectChoice>>,
    pub program_zero_z: Option<Set<f64>>,
    /// `[work_offsets]`: G54–G59 as the control's work offset page stores them (index 0 is
    /// G54, which is program zero itself: a layer gives it or `program_zero_z`, not both).
    pub work_offsets: [Option<Set<WorkOffset>>; 6],
    pub stock: Option<Set<JobStock>>,
    pub chuck: Option<Set<Polygon>>,
    /// `[chuck.jaws]`: the jaws of this job over the machine file's (not with `chuck`).
    pub jaws: JobJaws,
    pub tailstock_in_use: Option<Set<bool>>,
    /// `tailstock.z`: the z of the live centre's tip (the smallest z of the tailstock outline).
    pub tailstock_z: Option<Set<f64>>,
    /// `diameter_mode`: X words are diameters (true) or radii (false) at program start.
    pub diameter_mode: Option<Set<bool>>,
    /// `spindle.start_rpm`: the spindle turns at this speed from program start (0: stopped).
    pub start_rpm: Option<Set<f64>>,
    /// `[[tool_changes]]`: `(line, station)`, at most one per line.
    pub tool_changes: Vec<Set<(u32, u32)>>,
    /// `[[operations]]`, in the order they start (each `Set`'s place is its table,
    /// `operations[i]`); a layer that gives them replaces every operation below it (`Some` of
    /// an empty list: none).
    pub operations: Option<Vec<Set<JobOperation>>>,
    /// At most one per station.
    pub tools: Vec<Set<JobTool>>,
    /// `[tool_numbers] T<tool> = <station>`: `(tool, station)`, at most one per tool.
    pub tool_numbers: Vec<Set<(u32, u32)>>,
    /// `[tool_numbers] from_table = true`: the tool table's tools in their pockets.
    pub tool_numbers_table: Option<Set<TableNumbers>>,
    /// Values accepted but suspicious (an outline's spike), as `file:line:col: key: message`.
    pub warnings: Vec<String>,
}

impl Layer {
    /// An empty layer (for one-off command-line values).
    pub fn new(label: impl Into<String>) -> Layer {
        Layer {
            label: label.into(),
            ..Layer::default()
        }
    }

    /// Whether the layer sets nothing.
    pub fn is_empty(&self) -> bool {
        self.units_inch.is_none()
            && self.dialect.is_none()
            && self.program_zero_z.is_none()
            && self.work_offsets.iter().all(Option::is_none)
            && self.stock.is_none()
            && self.chuck.is_none()
            && self.jaws.is_empty()
            && self.tailstock_in_use.is_none()
            && self.tailstock_z.is_none()
            && self.diameter_mode.is_none()
            && self.start_rpm.is_none()
            && self.tool_changes.is_empty()
            && self.operations.is_none()
            && self.tools.is_empty()
            && self.tool_numbers.is_empty()
            && self.tool_numbers_table.is_none()
    }
}

/// The layers of one program's job merged: each value from the last layer that set it. Its
/// values are a [`Layer`] (labelled `merged`; `files` and `warnings` of every layer, in order),
/// reached through `Deref`.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EffectiveJob {
    /// Labels of the layers merged, lowest first (empty layers included: they applied).
    pub layers: Vec<String>,
    /// The values: tool changes sorted by line and tools by station, one each.
    pub merged: Layer,
}

impl std::ops::Deref for EffectiveJob {
    type Target = Layer;
    fn deref(&self) -> &Layer {
        &self.merged
    }
}

impl std::ops::DerefMut for EffectiveJob {
    fn deref_mut(&mut self) -> &mut Layer {
        &mut self.merged
    }
}

impl Layer {
    /// Lay `l` over this layer: scalars key by key, `stock` and `chuck.outline` as whole tables,
    /// `chuck.jaws` key by key, tool changes line by line, tools station by station; files and
    /// warnings accumulate.
    fn lay_over(&mut self, l: &Layer) {
        for f in &l.files {
            if !self.files.contains(f) {
                self.files.push(f.clone());
            }
        }
        fn over<T: Clone>(to: &mut Option<Set<T>>, from: &Option<Set<T>>) {
            if from.is_some() {
                to.clone_from(from);
            }
        }
        over(&mut self.units_inch, &l.units_inch);
        over(&mut self.dialect, &l.dialect);
        over(&mut self.program_zero_z, &l.program_zero_z);
        // G54 and `program_zero_z` are one value (program zero at start): the later layer's
        // wins, whichever key it wrote.
        if l.program_zero_z.is_some() {
            self.work_offsets[0] = None;
        }
        if l.work_offsets[0].is_some() {
            self.program_zero_z = None;
        }
        for (to, from) in self.work_offsets.iter_mut().zip(&l.work_offsets) {
            over(to, from);
        }
        over(&mut self.stock, &l.stock);
        // A chuck outline replaces the whole chuck, jaws too; jaws are laid over the machine
        // file's body and jaws, so they drop an outline below them.
        if l.chuck.is_some() {
            self.jaws = JobJaws::default();
        }
        if !l.jaws.is_empty() {
            self.chuck = None;
        }
        over(&mut self.chuck, &l.chuck);
        self.jaws.lay_over(&l.jaws);
        over(&mut self.tailstock_in_use, &l.tailstock_in_use);
        over(&mut self.tailstock_z, &l.tailstock_z);
        over(&mut self.diameter_mode, &l.diameter_mode);
        over(&mut self.start_rpm, &l.start_rpm);
        for c in &l.tool_changes {
            self.tool_changes.retain(|o| o.value.0 != c.value.0);
            self.tool_changes.push(c.clone());
        }
        // The operations describe one sequence of set-ups together: a later layer's replace
        // them all.
        if l.operations.is_some() {
            self.operations.clone_from(&l.operations);
        }
        for t in &l.tools {
            self.tools.retain(|o| o.value.tool.station != t.value.tool.station);
            self.tools.push(t.clone());
        }
        for n in &l.tool_numbers {
            self.tool_numbers.retain(|o| o.value.0 != n.value.0);
            self.tool_numbers.push(n.clone());
        }
        over(&mut self.tool_numbers_table, &l.tool_numbers_table);
        self.warnings.extend(l.warnings.iter().cloned());
    }
}

impl EffectiveJob {
    /// Lay `layers` over one another, lowest first (see `Layer::lay_over`).
    pub fn merge<'a>(layers: impl IntoIterator<Item = &'a Layer>) -> EffectiveJob {
        let mut out = EffectiveJob {
            layers: Vec::new(),
            merged: Layer::new("merged"),
        };
        for l in layers {
            out.layers.push(l.label.clone());
            out.merged.lay_over(l);
        }
        out.merged.tools.sort_by_key(|t| t.value.tool.station);
        out.merged.tool_changes.sort_by_key(|c| c.value.0);
        out.merged.tool_numbers.sort_by_key(|c| c.value.0);
        out
    }
}

/// The machine the checker runs for `job` on `machine`: the job's values over the machine's,
/// validated as a machine file is (every station exists, the stock fits the chuck, the turret
/// and every tool clear of the chuck and the tailstock at home). Every problem is reported;
/// each names the job key that caused it.
pub fn apply(machine: &Machine, job: &EffectiveJob) -> Result<Machine, JobError> {
    let mut m = machine.clone();
    let mut errors: Vec<JobError> = Vec::new();
    if let Some(u) = &job.units_inch {
        m.inch = u.value;
    }
    if let Some(d) = &job.dialect {
        let to = match d.value {
            DialectChoice::Fanuc => Some(Dialect::Fanuc),
            DialectChoice::Linuxcnc => Some(Dialect::Linuxcnc),
            DialectChoice::Auto => None,
        };
        if let Some(to) = to {
            if let Err(e) = switch_dialect(&mut m, to, &d.at) {
                errors.push(e);
            }
        }
    }
    if let Some(c) = &job.chuck {
        m.chuck = Some(c.value.clone());
        m.chuck_form = Some(ChuckForm::Outline);
    }
    match job_jaws(machine, job) {
        Ok(Some((p, c))) => {
            m.chuck = Some(p);
            m.chuck_form = Some(ChuckForm::Jaws(c));
        }
        Ok(None) => {}
        Err(e) => errors.push(e),
    }
    // A turn-mill machine's 3D chuck is revolved from the same outline: it follows.
    if let (Some(k), Some(old), Some(new)) = (&m.kinematics, &machine.chuck, &m.chuck) {
        if old != new {
            if let Some(k) = k.with_chuck(old.points(), new.points()) {
                m.kinematics = Some(std::sync::Arc::new(k));
            }
        }
    }
    if let Some(d) = &job.diameter_mode {
        m.diameter_mode = d.value;
        if let Some(auto) = m.auto_dialect.as_mut() {
            auto.fanuc.diameter_mode = d.value;
            auto.linuxcnc.diameter_mode = d.value;
        }
    }
    if let Some(r) = &job.start_rpm {
        if r.value > m.max_rpm {
            errors.push(r.at.err(format!(
                "start_rpm = {} is faster than the machine's spindle.max_rpm = {}",
                r.value, m.max_rpm
            )));
        }
        m.start_rpm = (r.value > 0.0).then_some(r.value);
    }
    if let Some(z) = &job.tailstock_z {
        match &m.tailstock {
            None => errors
                .push(z.at.err("the machine has no tailstock to move: describe it in the machine file's [tailstock]")),
            Some(t) => {
                let tip = t.aabb().min.y;
                m.tailstock = Some(t.translated(crate::geom::V2::new(0.0, z.value - tip)));
            }
        }
    }
    if let Some(t) = &job.tailstock_in_use {
        if t.value {
            if m.tailstock.is_none() {
                errors.push(t.at.err("the machine has no tailstock: describe it in the machine file's [tailstock]"));
            }
            m.tailstock_advanced = true;
        } else {
            m.tailstock = None;
            m.tailstock_advanced = false;
        }
    }
    if let Some(s) = &job.stock {
        let st = &s.value;
        let front = st.front.or(machine.stock.as_ref().map(|s| s.front));
        match (front, &st.outline) {
            _ if st.none => m.stock = None,
            (Some(front), _) if st.block.is_some() => {
                if let Some(b) = st.block {
                    if let Err(e) = block_grip(&m, b) {
                        errors.push(st.diameter_at.err(e));
                    }
                    m.stock = Some(Stock::block(b, st.length, front, m.chuck.as_ref()));
                }
            }
            (_, Some(o)) => m.stock = Some(Stock::from_outline(o.clone())),
            (Some(front), None) => m.stock = Some(Stock::bar(st.diameter, st.length, front, st.bore)),
            (None, None) => errors.push(s.at.err(
                "the stick-out is not given and the machine has no stock to take it from: write DIAxLEN@STICKOUT",
            )),
        }
    }
    // Program zero at start (G54): the job's G54, its program_zero_z, its stock's front, else
    // the machine file's (whose written G54, if any, then stays).
    let zero = match (&job.work_offsets[0], &job.program_zero_z, &m.stock, &job.stock) {
        (Some(g54), _, _, _) => Some(m.machine_zero.y + g54.value.z),
        (None, Some(z), _, _) => Some(z.value),
        (None, None, Some(st), Some(_)) => Some(st.front),
        _ => None,
    };
    if let Some(z) = zero {
        m.program_zero_z = z;
        m.work_offsets[0] = None;
    }
    for (to, from) in m.work_offsets.iter_mut().zip(&job.work_offsets) {
        if let Some(o) = from {
            *to = Some(o.value);
        }
    }
    for t in &job.tools {
        let station = t.value.tool.station;
        if station > m.turret.stations {
            errors.push(t.at.err_key(
                &format!("{}.station", t.at.key),
                format!(
                    "station {station} does not exist: the turret of {} has stations 1 to {}",
                    machine.name, m.turret.stations
                ),
            ));
            continue;
        }
        let mut tool = t.value.tool.clone();
        if let Some(g) = &t.value.geometry_offset {
            tool.tip = g.tip(m.machine_zero);
        }
        m.tools.retain(|o| o.station != station);
        m.tools.push(tool.clone());
        // A milling tool on a machine with a tree: its 3D parts replace the station's cutter.
        if let (Some(mt), Some(k)) = (&tool.mill, &m.kinematics) {
            if let Some(k) = crate::kin::station::fit(k, station, tool.tip, mt) {
                m.kinematics = Some(std::sync::Arc::new(k));
            }
        }
    }
    m.tools.sort_by_key(|t| t.station);
    tool_numbers(&mut m, machine, job, &mut errors);
    for c in &job.tool_changes {
        let (line, station) = c.value;
        if m.tool(station).is_none() {
            errors.push(c.at.err_key(
                &format!("{}.station", c.at.key),
                format!(
                    "station {station} holds no tool on {} with this job: the operator cannot put its tool in at line {line}",
                    machine.name
                ),
            ));
        }
    }
    m.tool_changes = job.tool_changes.iter().map(|c| c.value).collect();
    operations(&mut m, machine, job, &mut errors);
    if let Some(e) = JobError::gather(errors) {
        return Err(e);
    }

    // The setup checks of a machine file, on the job's parts; each problem is blamed on the job
    // value that brought the parts together.
    let mut errors = Vec::new();
    let jaws_at = job.jaws.table.as_ref().map(|t| &t.at);
    if let Some(st) = &m.stock {
        if let Some((key, message)) = machine::stock_clash(&m, st) {
            let grip_at = job.jaws.grip_diameter.as_ref().map(|g| &g.at);
            let e = match (&job.stock, &job.chuck, grip_at) {
                (_, None, Some(g)) if key != machine::StockKey::Length => g.err(format!(
                    "{message} (the jaws grip Ø{})",
                    machine::num(job.jaws.grip_diameter.as_ref().map_or(0.0, |g| g.value))
                )),
                (Some(s), _, _) => match key {
                    machine::StockKey::Length => s.value.length_at.err(message),
                    machine::StockKey::Diameter | machine::StockKey::Outline => s.value.diameter_at.err(message),
                },
                (None, Some(c), _) => c.at.err(message),
                (None, None, _) => jaws_at.map_or_else(
                    || Place::command_line("job").err(message.clone()),
                    |a| a.err(message.clone()),
                ),
            };
            errors.push(e);
        }
    }
    for c in machine::home_clashes(&m) {
        let by_tool = c.tool.and_then(|(station, part)| {
            job.tools
                .iter()
                .find(|t| t.value.tool.station == station)
                .map(|t| t.at.err_key(&format!("{}.{part}", t.at.key), c.message.clone()))
        });
        let by_obstacle = || match c.obstacle {
            "chuck" => job
                .chuck
                .as_ref()
                .map(|s| &s.at)
                .or(jaws_at)
                .or_else(|| grip_from_stock(machine, job).map(|(_, s)| &s.at))
                .map(|at| at.err(c.message.clone())),
            _ => job
                .tailstock_z
                .as_ref()
                .map(|s| s.at.err(c.message.clone()))
                .or_else(|| job.tailstock_in_use.as_ref().map(|s| s.at.err(c.message.clone()))),
        };
        errors.push(
            by_tool
                .or_else(by_obstacle)
                .unwrap_or_else(|| Place::command_line("job").err(c.message.clone())),
        );
    }
    operation_home_clashes(&m, job, &mut errors);
    if let Some(e) = JobError::gather(errors) {
        return Err(e);
    }
    m.warnings.extend(job.warnings.iter().cloned());
    Ok(m)
}

/// The job's `[tool_numbers]` → `m.tool_numbers`: the table's tools in their pockets, explicit
/// `T<tool> = <station>` entries over them; a table tool's shape goes to its station unless a
/// `[[tools]]` entry of the job describes that station. Errors: a station past the turret's,
/// two shaped tools in one station.
fn tool_numbers(m: &mut Machine, machine: &Machine, job: &EffectiveJob, errors: &mut Vec<JobError>) {
    // tool → (station, where the mapping was written, how it is named, the table's tool)
    let mut map: std::collections::BTreeMap<u32, (u32, &Place, String, Option<&JobTool>)> = Default::default();
    if let Some(t) = &job.tool_numbers_table {
        for (tool, pocket, built) in &t.value.rows {
            let how = format!("{} puts T{tool} in pocket {pocket}", t.value.file);
            map.insert(*tool, (*pocket, &t.at, how, Some(built)));
        }
    }
    for n in &job.tool_numbers {
        let (tool, station) = n.value;
        let shape = map.get(&tool).and_then(|e| e.3);
        map.insert(tool, (station, &n.at, format!("{} = {station}", n.at.key), shape));
    }
    let stations = m.turret.stations;
    let described: Vec<u32> = job.tools.iter().map(|t| t.value.tool.station).collect();
    let mut shaped: Vec<(u32, u32, &Place)> = Vec::new(); // (station, tool, place)
    let mut out = Vec::new();
    for (&tool, (station, at, how, shape)) in &map {
        if *station > stations {
            errors.push(at.err(format!(
                "T{tool}: station {station} does not exist ({how}): the turret of {} has stations 1 to {stations}",
                machine.name
            )));
            continue;
        }
        out.push((tool, *station));
        let Some(built) = shape else { continue };
        if described.contains(station) {
            continue;
        }
        if let Some(&(_, other, other_at)) = shaped.iter().find(|s| s.0 == *station) {
            // Blame an explicit `T<tool> = <station>` over the table's pocket.
            let table = |p: &Place| p.key.ends_with("from_table");
            let (blame, moved) = if table(at) && !table(other_at) {
                (other_at, other)
            } else {
                (*at, tool)
            };
            let (a, b) = (other.min(tool), other.max(tool));
            errors.push(blame.err(format!(
                "T{a} and T{b} are both in station {station} and both have a shape in the tool table: map one of them elsewhere (tool_numbers.T{moved} = STATION)"
            )));
            continue;
        }
        shaped.push((*station, tool, at));
        let mut t = built.tool.clone();
        t.station = *station;
        m.tools.retain(|o| o.station != *station);
        m.tools.push(t);
    }
    m.tools.sort_by_key(|t| t.station);
    // The machine file's own map, under the job's (its stations were checked as it was read).
    for &(tool, station) in &machine.tool_numbers {
        if !map.contains_key(&tool) {
            out.push((tool, station));
        }
    }
    out.sort_unstable();
    m.tool_numbers = out;
}

/// The diameter a job's jaws close on when no layer gives `chuck.jaws.grip_diameter`, on a
/// machine whose chuck is given by its body and jaws: the job's bar or tube (its outer diameter)
/// when the jaws grip outside, a tube's bore when they grip inside; with the stock it comes from.
/// None otherwise (a job's chuck outline, a revolved stock, no stock in the job, a solid bar with
/// an inside grip): the grip stays the machine file's.
pub fn grip_from_stock<'j>(machine: &Machine, job: &'j EffectiveJob) -> Option<(f64, &'j Set<JobStock>)> {
    let base = machine.chuck_jaws()?;
    if job.chuck.is_some() || job.jaws.grip_diameter.is_some() {
        return None;
    }
    let s = job.stock.as_ref()?;
    if s.value.none || s.value.outline.is_some() {
        return None;
    }
    let grip = job.jaws.grip.as_ref().map_or(base.jaws.grip, |g| g.value);
    if let Some(b) = s.value.block {
        // The jaws close on the block's nearer flats.
        return (grip == jaws::Grip::Outside).then_some((2.0 * b.inscribed(), s));
    }
    match grip {
        jaws::Grip::Outside => Some((s.value.diameter, s)),
        jaws::Grip::Inside if s.value.bore > 0.0 => Some((s.value.bore, s)),
        jaws::Grip::Inside => None,
    }
}

/// Whether the jaws `m` sets up can grip block `b`: they grip outside, on its nearer flats
/// (their grip diameter the block's narrower size, within 0.01 mm). A chuck given as an outline
/// is checked by its overlap with the block's envelope alone (`machine::stock_clash`).
fn block_grip(m: &Machine, b: machine::Block) -> Result<(), String> {
    let Some(c) = m.chuck_jaws() else { return Ok(()) };
    let across = 2.0 * b.inscribed();
    if c.jaws.grip != jaws::Grip::Outside {
        return Err(
            "a block is gripped outside, on its flats: the jaws grip inside (chuck.jaws.grip = \"inside\"); give grip = \"outside\""
                .to_string(),
        );
    }
    if (c.jaws.grip_diameter - across).abs() > 0.01 {
        let how = if c.jaws.grip_diameter > across {
            "stand off its flats: they do not hold it"
        } else {
            "would close inside it"
        };
        return Err(format!(
            "the jaws grip Ø{} but the block is {} mm across its nearer flats: they {how} (leave chuck.jaws.grip_diameter out to close them on the block)",
            machine::num(c.jaws.grip_diameter),
            machine::num(across)
        ));
    }
    Ok(())
}

/// The chuck a job's jaws give on `machine`: the machine file's body with the job's
/// `[chuck.jaws]` over its jaws, closed on the job's bar when no layer gives the grip diameter
/// ([`grip_from_stock`]). None: the job changes no jaws. A job's jaws on a machine whose chuck
/// is an outline (or Fanuc's barrier, or none) are an error at the job's `[chuck.jaws]`.
fn job_jaws(machine: &Machine, job: &EffectiveJob) -> Result<Option<(Polygon, jaws::Chuck)>, JobError> {
    if job.chuck.is_some() {
        return Ok(None);
    }
    let Some(base) = machine.chuck_jaws() else {
        let Some(t) = &job.jaws.table else { return Ok(None) };
        let how = match machine.chuck_form {
            Some(ChuckForm::Outline) => "gives its chuck as an outline",
            Some(ChuckForm::Barrier) => "gives its chuck as Fanuc's barrier parameters",
            Some(ChuckForm::Jaws(_)) | None => "has no chuck",
        };
        return Err(t.at.err(format!(
            "the machine file {how}; jaws need chuck.body in the machine file"
        )));
    };
    let mut jaws = job.jaws.over(&base.jaws);
    let from_stock = grip_from_stock(machine, job);
    if let Some((d, _)) = from_stock {
        jaws.grip_diameter = d;
    }
    if job.jaws.is_empty() && from_stock.is_none() {
        return Ok(None);
    }
    let c = jaws::Chuck { body: base.body, jaws };
    match c.polygon() {
        Ok(p) => Ok(Some((p, c))),
        Err(e) => {
            let by_size = e.keys.iter().find_map(|k| job.jaws.place_of(k));
            let by_key = by_size
                .or(job.jaws.grip.as_ref().map(|s| &s.at))
                .or(job.jaws.kind.as_ref().map(|s| &s.at));
            let by_stock = from_stock
                .filter(|_| e.keys.contains(&"jaws.grip_diameter"))
                .map(|(_, s)| &s.value.diameter_at);
            let at = by_key
                .or(by_stock)
                .or(job.jaws.table.as_ref().map(|t| &t.at))
                .or(from_stock.map(|(_, s)| &s.at));
            let machine_key = e.keys.first().map_or("jaws".to_string(), |k| format!("chuck.{k}"));
            let mut message = e.message;
            if let Some((d, _)) = from_stock {
                message.push_str(&format!(
                    " (the jaws close on the job's bar, Ø{}; give chuck.jaws.grip_diameter for another grip)",
                    machine::num(d)
                ));
            }
            if by_size.is_none() && by_stock.is_none() {
                message.push_str(&format!(" (the machine file's {machine_key} with this job's jaws)"));
            }
            Err(at.map_or_else(
                || Place::command_line("job").err(message.clone()),
                |a| a.err(message.clone()),
            ))
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Operations (`[[operations]]`, docs/job.md "Operations").

/// The job's operations on the machine: each with its jaws (its own, else the job's chuck).
fn operations(m: &mut Machine, machine: &Machine, job: &EffectiveJob, errors: &mut Vec<JobError>) {
    let Some(ops) = job.operations.as_ref().filter(|o| !o.is_empty()) else {
        return;
    };
    if m.kinematics.is_some() {
        errors.push(ops[0].at.err(
            "operations are not built for a machine with [kinematics] (a turn-mill machine) yet: check each operation as a program of its own, with its part as `[stock] from`",
        ));
        return;
    }
    let mut out = Vec::with_capacity(ops.len());
    for o in ops {
        let v = &o.value;
        let chuck = match &v.jaws {
            Some(j) => match operation_jaws(m, j) {
                Ok(p) => Some(p),
                Err(e) => {
                    errors.push(e);
                    continue;
                }
            },
            None => v.chuck.clone().or_else(|| m.chuck.clone()),
        };
        let tailstock = match operation_tailstock(machine, job, v) {
            Ok(t) => t,
            Err(e) => {
                errors.push(e);
                continue;
            }
        };
        out.push(machine::Operation {
            start: v.start,
            reverse: v.reverse,
            stand: v.stand,
            chuck,
            program_zero_z: v.program_zero_z,
            tailstock,
            origin: format!("{}:{}:{}: {}", o.at.file, o.at.line, o.at.col, o.at.key),
        });
    }
    m.operations = out;
}

/// An operation's `tailstock` (`in_use`, `z`): the machine file's tailstock outline with its
/// live centre's tip at the operation's `z`, else at the job's, else where the machine file puts
/// it. Either key needs a machine with a tailstock.
fn operation_tailstock(
    machine: &Machine,
    job: &EffectiveJob,
    v: &JobOperation,
) -> Result<machine::OpTailstock, JobError> {
    let Some(at) = &v.tailstock_at else {
        return Ok(machine::OpTailstock::AsItStood);
    };
    if v.tailstock_in_use == Some(false) {
        return Ok(machine::OpTailstock::Out);
    }
    let Some(outline) = &machine.tailstock else {
        return Err(at.err("the machine has no tailstock: describe it in the machine file's [tailstock]"));
    };
    let z = v.tailstock_z.or(job.tailstock_z.as_ref().map(|z| z.value));
    let outline = match z {
        Some(z) => outline.translated(crate::geom::V2::new(0.0, z - outline.aabb().min.y)),
        None => outline.clone(),
    };
    Ok(machine::OpTailstock::At {
        outline,
        advance: v.tailstock_in_use == Some(true),
    })
}

/// An operation's `chuck.jaws`: its keys over the jaws the job set up (the machine file's with
/// the job's `[chuck.jaws]`, closed on the job's bar), drawn over the machine's body. Its own
/// `grip_diameter` is the part's diameter it holds; without one the jaws stay as they were.
fn operation_jaws(m: &Machine, j: &JobJaws) -> Result<Polygon, JobError> {
    let table = j.table.as_ref().map(|t| &t.at);
    let Some(base) = m.chuck_jaws() else {
        let how = match m.chuck_form {
            Some(ChuckForm::Outline) => "the chuck is an outline (the machine file's or the job's)",
            Some(ChuckForm::Barrier) => "the machine file gives its chuck as Fanuc's barrier parameters",
            Some(ChuckForm::Jaws(_)) | None => "the machine has no chuck",
        };
        let message =
            format!("{how}; an operation's jaws need chuck.body in the machine file (or give its chuck.outline)");
        return Err(table.map_or_else(
            || Place::command_line("job").err(message.clone()),
            |t| t.err(message.clone()),
        ));
    };
    let c = jaws::Chuck {
        body: base.body,
        jaws: j.over(&base.jaws),
    };
    c.polygon().map_err(|e| {
        let at = e.keys.iter().find_map(|k| j.place_of(k)).or(table);
        at.map_or_else(
            || Place::command_line("job").err(e.message.clone()),
            |a| a.err(e.message.clone()),
        )
    })
}

/// An operation's own jaws checked as the job's chuck is: the turret and every tool clear of
/// them at home.
fn operation_home_clashes(m: &Machine, job: &EffectiveJob, errors: &mut Vec<JobError>) {
    let Some(ops) = &job.operations else { return };
    for (i, o) in ops.iter().enumerate() {
        // Its own jaws: an outline as written, or `chuck.jaws` as `operations` drew them.
        let drawn = (o.value.jaws.is_some() && m.operations.len() == ops.len())
            .then(|| m.operations[i].chuck.clone())
            .flatten();
        let (Some(chuck), Some(at)) = (o.value.chuck.clone().or(drawn), &o.value.chuck_at) else {
            continue;
        };
        let mut with = m.clone();
        with.chuck = Some(chuck);
        with.tailstock = None;
        for c in machine::home_clashes(&with) {
            if c.obstacle == "chuck" {
                errors.push(at.err(format!("{} (the jaws of operation {})", c.message, i + 2)));
            }
        }
    }
}

/// The job's work offsets that look like mistakes on `machine` (program zero outside the Z
/// travel), as `file:line:col: key: message` (the binary prints them as warnings).
pub fn warnings(machine: &Machine, job: &EffectiveJob) -> Vec<String> {
    job.work_offsets
        .iter()
        .flatten()
        .filter_map(|o| {
            let why = machine::work_offset_doubt(&machine.z, machine.machine_zero, o.value)?;
            let e = o.at.err(why);
            Some(e.to_string())
        })
        .collect()
}

/// Another dialect than the machine file's: its defaults follow (diameter mode, the built-in M
/// codes) unless the machine file set them for its own dialect.
fn switch_dialect(m: &mut Machine, to: Dialect, at: &Place) -> Result<(), JobError> {
    let from = m.dialect;
    if from == to {
        return Ok(());
    }
    if m.mcodes != McodeTable::builtin(from) {
        return Err(at.err(format!(
            "the machine file's [mcodes] are written for {}: a job cannot change the dialect of this machine",
            from.as_str()
        )));
    }
    if to == Dialect::Linuxcnc
        && (m.decimal_point != machine::DecimalPoint::Calculator || m.gcode_system != machine::GcodeSystem::A)
    {
        return Err(at.err(
            "the machine file sets a Fanuc decimal point or G-code system: a job cannot make it a LinuxCNC machine",
        ));
    }
    let default_diameter = |d: Dialect| d == Dialect::Fanuc;
    if m.diameter_mode == default_diameter(from) {
        m.diameter_mode = default_diameter(to);
    }
    m.mcodes = McodeTable::builtin(to);
    m.dialect = to;
    Ok(())
}

/// `--stock DIAxLEN[@STICKOUT]` or `DIA/BOAxLEN[@STICKOUT]` (a tube): mm.
pub fn parse_stock_flag(s: &str) -> Result<(f64, f64, Option<f64>, f64), String> {
    let bad = || {
        format!("`{s}` is not a stock: write DIAxLEN or DIAxLEN@STICKOUT (mm), e.g. 50x120@80; a tube DIA/BORExLEN@STICKOUT")
    };
    let (size, stick) = match s.split_once('@') {
        Some((a, b)) => (a, Some(b)),
        None => (s, None),
    };
    let (dia, len) = size.split_once(['x', 'X']).ok_or_else(bad)?;
    let (dia, bore) = match dia.split_once('/') {
        Some((d, b)) => (d, Some(b)),
        None => (dia, None),
    };
    let num = |t: &str| -> Result<f64, String> {
        let v: f64 = t.trim().parse().map_err(|_| bad())?;
        if v.is_finite() && v.abs() <= machine::MAX_COORD_MM {
            Ok(v)
        } else {
            Err(bad())
        }
    };
    let (d, l) = (num(dia)?, num(len)?);
    let b = bore.map(num).transpose()?.unwrap_or(0.0);
    let front = stick.map(num).transpose()?;
    if d <= 0.0 || l <= 0.0 {
        return Err(format!("`{s}`: the diameter and the length must be greater than 0"));
    }
    if !(0.0..d).contains(&b) {
        return Err(format!("`{s}`: the bore must be from 0 to less than the diameter"));
    }
    Ok((d, l, front, b))
}

/// A layer from one-off command-line values (`--stock`, `--units`, `--program-zero`); the
/// tools of `--tools` come from [`parse`] of that file.
pub fn flags_layer(
    stock: Option<&str>,
    units_inch: Option<bool>,
    program_zero_z: Option<f64>,
) -> Result<Layer, String> {
    let mut l = Layer::new("command line");
    fn set<T>(value: T, flag: &str) -> Set<T> {
        Set {
            value,
            at: Place::command_line(flag),
            layer: "command line".into(),
        }
    }
    if let Some(s) = stock {
        let (diameter, length, front, bore) = parse_stock_flag(s)?;
        l.stock = Some(set(
            JobStock {
                diameter,
                length,
                front,
                bore,
                outline: None,
                block: None,
                none: false,
                diameter_at: Place::command_line("--stock"),
                length_at: Place::command_line("--stock"),
            },
            "--stock",
        ));
    }
    l.units_inch = units_inch.map(|u| set(u, "--units"));
    if let Some(z) = program_zero_z {
        if !z.is_finite() || z.abs() > machine::MAX_COORD_MM {
            return Err(format!("--program-zero {z}: must be from -100000 to 100000 mm"));
        }
        l.program_zero_z = Some(set(z, "--program-zero"));
    }
    Ok(l)
}
