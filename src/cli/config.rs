//! `latheguard.toml`: per-folder machine and settings (the schema is in `docs/config.md`).
//!
//! The nearest `latheguard.toml` (in the program's folder or the closest parent) applies to a
//! program; configurations are not merged. Its `[[override]]` tables whose glob matches the
//! program's path (relative to the configuration's folder) apply on top, in file order. The
//! command line applies on top of everything.

use super::args::{out_of_range, CLEARANCE_MM, DT_MS, TOLERANCE_MM};
use globset::{GlobBuilder, GlobMatcher};
use latheguard::finding::Kind;
use latheguard::gate::{FailOn, Rules, Selection};
use latheguard::job;
use latheguard::pipeline::Mode;
use latheguard::pipeline::MIN_DEPTH_MM;
use latheguard::source::LineIndex;
use serde::Deserialize;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use toml::de::{DeTable, DeValue};
use toml::Spanned;

/// The file name looked for in each folder.
pub const FILE_NAME: &str = "latheguard.toml";

/// At most this many `[[override]]` tables in one file.
pub const MAX_OVERRIDES: usize = 1000;

/// A configuration that cannot be used: where and why (`file:line:col: key: message`).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{file}:{line}:{col}: {key}: {message}")]
pub struct ConfigError {
    pub file: String,
    pub line: u32,
    pub col: u32,
    pub key: String,
    pub message: String,
}

/// Settings one table of a configuration sets; `None` leaves the value to the layer below.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Layer {
    pub machine: Option<MachineRef>,
    pub mode: Option<Mode>,
    pub dt_ms: Option<f64>,
    pub tolerance_mm: Option<f64>,
    pub clearance_mm: Option<f64>,
    pub min_depth_mm: Option<f64>,
    /// `job = "FILE"` or an inline `[job]` table (docs/job.md).
    pub job: Option<JobRef>,
}

/// A job named by a configuration: a file (read once per run by [`Finder::job_file`]) or a
/// table written in the configuration.
#[derive(Clone, Debug, PartialEq)]
pub enum JobRef {
    File { path: PathBuf, at: String },
    Inline(Arc<job::Layer>),
}

/// A machine file named by a configuration: where it is, and where it was written (for errors).
#[derive(Clone, Debug, PartialEq)]
pub struct MachineRef {
    /// The path, resolved against the configuration's folder.
    pub path: PathBuf,
    /// `file:line:col: key`, to prefix an error about the machine file.
    pub at: String,
}

/// One loaded `latheguard.toml`.
#[derive(Debug)]
pub struct Config {
    /// Its folder, absolute.
    pub dir: PathBuf,
    /// The file, as shown in messages.
    pub shown: String,
    pub base: Layer,
    pub overrides: Vec<(GlobMatcher, Layer)>,
    pub gate: Gate,
}

/// The gate keys of a configuration (docs/config.md): which kinds are reported and what fails.
#[derive(Debug, Default)]
pub struct Gate {
    /// `select`, `extend-select`, `ignore`.
    pub selection: Selection,
    /// `fail-on`.
    pub fail_on: Option<FailOn>,
    /// `per-file-ignores`: (glob as written, matcher, kinds), in file order.
    pub per_file: Vec<(String, GlobMatcher, Vec<Kind>)>,
    /// `unused-suppressions` (default true).
    pub unused_suppressions: Option<bool>,
}

impl Config {
    /// The `per-file-ignores` entries that match `file` (absolute): glob and kinds.
    pub fn per_file_ignores(&self, file: &Path) -> Vec<(&str, &[Kind])> {
        let Ok(rel) = file.strip_prefix(&self.dir) else {
            return Vec::new();
        };
        let rel = slash_path(rel);
        self.gate
            .per_file
            .iter()
            .filter(|(_, g, _)| g.is_match(&rel))
            .map(|(s, _, k)| (s.as_str(), k.as_slice()))
            .collect()
    }
}

/// The rules of the gate for one program (absolute path): the configuration's selection, then
/// the command line's (`cli`), resolved as ruff does ([`Rules::resolve`]), then the
/// configuration's `per-file-ignores` that match, then `unused-suppressions`.
pub fn rules_for(cfg: Option<&Config>, file: &Path, cli: &Selection) -> Rules {
    let mut layers = Vec::new();
    if let Some(c) = cfg {
        layers.push(&c.gate.selection);
    }
    layers.push(cli);
    let mut rules = Rules::resolve(layers);
    if let Some(c) = cfg {
        for (_, kinds) in c.per_file_ignores(file) {
            for k in kinds {
                if !rules.ignore.contains(k) {
                    rules.ignore.push(*k);
                }
            }
        }
        rules.quiet_unused = c.gate.unused_suppressions == Some(false);
    }
    rules
}

impl Config {
    /// The layers that apply to `file` (absolute), lowest first.
    pub fn layers_for(&self, file: &Path) -> Vec<&Layer> {
        let mut out = vec![&self.base];
        if let Ok(rel) = file.strip_prefix(&self.dir) {
            let rel = slash_path(rel);
            out.extend(self.overrides.iter().filter(|(g, _)| g.is_match(&rel)).map(|(_, l)| l));
        }
        out
    }
}

/// `a/b/../c` → `a/c`, without asking the file system.
fn normalize(p: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            std::path::Component::CurDir => {}
            std::path::Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            other => out.push(other),
        }
    }
    out
}

/// A path with `/` separators, as globs are written.
fn slash_path(p: &Path) -> String {
    let parts: Vec<String> = p.iter().map(|c| c.to_string_lossy().into_owned()).collect();
    parts.join("/")
}

// ---------------------------------------------------------------------------------------------
// Finding the configuration of a program.

/// Finds and loads the nearest configuration of each program, each file once.
pub struct Finder {
    cwd: PathBuf,
    /// `--config FILE`: this configuration for every program.
    forced: Option<Arc<Config>>,
    /// Absolute folder → the configuration that applies in it.
    nearest: HashMap<PathBuf, Option<Arc<Config>>>,
    /// Files jobs refer to (tool libraries, tool tables), by path: each read once.
    texts: Texts,
    /// Job files, by path: each read once.
    jobs: HashMap<PathBuf, Arc<job::Layer>>,
}

/// The texts of the files jobs name, each read once per run.
#[derive(Default)]
pub struct Texts {
    cwd: PathBuf,
    read: HashMap<PathBuf, Result<(String, String), String>>,
}

impl job::Resolve for Texts {
    fn read(&mut self, base: &str, rel: &str) -> Result<(String, String), String> {
        let path = normalize(&Path::new(base).join(rel));
        let cwd = self.cwd.clone();
        self.read
            .entry(path.clone())
            .or_insert_with(|| {
                let shown = super::shown(&relative(&path, &cwd));
                super::read_text(&path, super::MAX_CONFIG_BYTES).map(|t| (shown, t))
            })
            .clone()
    }
}

impl Finder {
    pub fn new() -> Finder {
        let cwd = std::env::current_dir().unwrap_or_default();
        Finder {
            nearest: HashMap::new(),
            texts: Texts {
                cwd: cwd.clone(),
                read: HashMap::new(),
            },
            jobs: HashMap::new(),
            forced: None,
            cwd,
        }
    }

    /// `--config FILE`: read that file now, and use it for every program instead of looking
    /// for the nearest one.
    pub fn force(&mut self, file: &Path) -> Result<(), ConfigError> {
        let abs = normalize(&self.absolute(file));
        let dir = abs.parent().unwrap_or(Path::new("/")).to_path_buf();
        self.forced = Some(Arc::new(self.load(&abs, &dir)?));
        Ok(())
    }

    /// The absolute form of a path (not resolving links).
    pub fn absolute(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.cwd.join(p)
        }
    }

    /// A path as shown in messages: relative to the working folder when under it.
    pub fn shown(&self, p: &Path) -> String {
        super::shown(p.strip_prefix(&self.cwd).unwrap_or(p))
    }

    /// The configuration that applies to a program (absolute path), if any.
    pub fn config_for(&mut self, file_abs: &Path) -> Result<Option<Arc<Config>>, ConfigError> {
        if let Some(c) = &self.forced {
            return Ok(Some(c.clone()));
        }
        let Some(dir) = file_abs.parent() else {
            return Ok(None);
        };
        let mut visited = Vec::new();
        let mut found = None;
        for d in dir.ancestors() {
            if let Some(c) = self.nearest.get(d) {
                found = c.clone();
                break;
            }
            visited.push(d.to_path_buf());
            let candidate = d.join(FILE_NAME);
            if candidate.is_file() {
                found = Some(Arc::new(self.load(&candidate, d)?));
                break;
            }
        }
        for d in visited {
            self.nearest.insert(d, found.clone());
        }
        Ok(found)
    }

    fn load(&mut self, file: &Path, dir: &Path) -> Result<Config, ConfigError> {
        let shown = self.shown(file);
        let text = super::read_text(file, super::MAX_CONFIG_BYTES).map_err(|why| ConfigError {
            file: shown.clone(),
            line: 0,
            col: 0,
            key: TOP_LEVEL.into(),
            message: format!("cannot read: {why}"),
        })?;
        parse(&text, &shown, dir, &mut self.texts)
    }

    /// A job file, read and validated once per run. `at` says who named it (for errors).
    pub fn job_file(&mut self, path: &Path, at: Option<&str>) -> Result<Arc<job::Layer>, String> {
        let abs = normalize(&self.absolute(path));
        if let Some(l) = self.jobs.get(&abs) {
            return Ok(l.clone());
        }
        let shown = self.shown(&abs);
        let named = at.map(|a| format!("\n  (the job of {a})")).unwrap_or_default();
        let text = super::read_text(&abs, super::MAX_CONFIG_BYTES)
            .map_err(|why| format!("{shown}: cannot read job file: {why}{named}"))?;
        let base = abs.parent().unwrap_or(Path::new("")).display().to_string();
        let layer = job::parse(&text, &shown, &base, &shown, &mut self.texts)
            .map_err(|e| format!("{}{named}", super::error_lines(&e)))?;
        for w in &layer.warnings {
            super::say(&format!("warning: {w}"));
        }
        let layer = Arc::new(layer);
        self.jobs.insert(abs, layer.clone());
        Ok(layer)
    }

    /// The job file beside a program: `part.job.toml` for `part.nc`, if there is one.
    pub fn beside(&mut self, program: &Path) -> Result<Option<Arc<job::Layer>>, String> {
        let Some(p) = beside_path(program) else { return Ok(None) };
        if !p.is_file() {
            return Ok(None);
        }
        self.job_file(&p, None).map(Some)
    }

    /// The layer of a configuration's job.
    pub fn job(&mut self, r: &JobRef) -> Result<Arc<job::Layer>, String> {
        match r {
            JobRef::Inline(l) => Ok(l.clone()),
            JobRef::File { path, at } => self.job_file(path, Some(at)),
        }
    }
}

/// `path` relative to the folder `from` (both absolute and normalised), with `..` where it
/// lies outside; `path` itself when they share no root.
fn relative(path: &Path, from: &Path) -> PathBuf {
    let (p, f): (Vec<_>, Vec<_>) = (path.components().collect(), from.components().collect());
    let common = p.iter().zip(&f).take_while(|(a, b)| a == b).count();
    if common == 0 {
        return path.to_path_buf();
    }
    let mut out = PathBuf::new();
    for _ in common..f.len() {
        out.push("..");
    }
    for c in &p[common..] {
        out.push(c);
    }
    out
}

/// `dir/part.job.toml` for `dir/part.nc` (the file name without its last extension).
pub fn beside_path(program: &Path) -> Option<PathBuf> {
    let stem = program.file_stem()?;
    if program.as_os_str() == "-" {
        return None;
    }
    let mut name = stem.to_os_string();
    name.push(".job.toml");
    Some(program.with_file_name(name))
}

// ---------------------------------------------------------------------------------------------
// Reading one file.

const TOP_LEVEL: &str = "(top level)";

/// The JSON Schema of `latheguard.toml` (`latheguard schema config`), from the types the reader
/// reads; ranges, globs and machine paths are checked by the reader with their place.
pub fn schema() -> String {
    let mut schema = schemars::schema_for!(RawConfig);
    schema.insert("title".into(), "latheguard.toml".into());
    let mut s = serde_json::to_string_pretty(&schema).unwrap_or_default();
    s.push('\n');
    s
}

#[derive(Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawConfig {
    #[schemars(with = "Option<String>")]
    machine: Option<Spanned<String>>,
    #[schemars(with = "Option<RawMode>")]
    mode: Option<Spanned<RawMode>>,
    #[schemars(with = "Option<f64>")]
    dt: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    tolerance: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    clearance: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    min_depth: Option<Spanned<f64>>,
    #[schemars(with = "Option<job::JobSchema>")]
    job: Option<serde::de::IgnoredAny>,
    /// Report only these finding kinds, by name or code (`collision`, `LG01`).
    #[schemars(with = "Option<Vec<String>>")]
    select: Option<Vec<Spanned<String>>>,
    /// Report these kinds too, over `select`.
    #[serde(rename = "extend-select")]
    #[schemars(with = "Option<Vec<String>>")]
    extend_select: Option<Vec<Spanned<String>>>,
    /// Never report these kinds; wins over `select` and `extend-select`.
    #[schemars(with = "Option<Vec<String>>")]
    ignore: Option<Vec<Spanned<String>>>,
    /// The least severity that fails the run.
    #[serde(rename = "fail-on")]
    #[schemars(with = "Option<RawFailOn>")]
    fail_on: Option<Spanned<RawFailOn>>,
    /// Kinds never reported in the programs a glob matches (relative to this file's folder).
    #[serde(rename = "per-file-ignores")]
    #[schemars(with = "Option<std::collections::BTreeMap<String, Vec<String>>>")]
    per_file_ignores: Option<std::collections::BTreeMap<Spanned<String>, Vec<Spanned<String>>>>,
    /// Report suppression comments that suppress nothing (default true).
    #[serde(rename = "unused-suppressions")]
    unused_suppressions: Option<bool>,
    #[serde(rename = "override", default)]
    #[schemars(with = "Vec<RawOverride>")]
    overrides: Vec<Spanned<RawOverride>>,
}

#[derive(Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
struct RawOverride {
    #[schemars(with = "String")]
    glob: Spanned<String>,
    #[schemars(with = "Option<String>")]
    machine: Option<Spanned<String>>,
    #[schemars(with = "Option<RawMode>")]
    mode: Option<Spanned<RawMode>>,
    #[schemars(with = "Option<f64>")]
    dt: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    tolerance: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    clearance: Option<Spanned<f64>>,
    #[schemars(with = "Option<f64>")]
    min_depth: Option<Spanned<f64>>,
    #[schemars(with = "Option<job::JobSchema>")]
    job: Option<serde::de::IgnoredAny>,
}

#[derive(Deserialize, schemars::JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum RawMode {
    Step,
    Exact,
}

#[derive(Deserialize, schemars::JsonSchema, Clone, Copy)]
#[serde(rename_all = "lowercase")]
enum RawFailOn {
    Error,
    Warning,
}

struct Cx<'a> {
    file: &'a str,
    dir: &'a Path,
    lines: LineIndex,
    text: &'a str,
}

impl Cx<'_> {
    fn err(&self, at: Range<usize>, key: impl Into<String>, message: impl Into<String>) -> ConfigError {
        let (line, col) = self.place(at.start);
        ConfigError {
            file: self.file.to_string(),
            line,
            col,
            key: key.into(),
            message: message.into(),
        }
    }

    /// 1-based line and column (in characters) of a byte offset.
    fn place(&self, offset: usize) -> (u32, u32) {
        let offset = offset.min(self.text.len()) as u32;
        (
            self.lines.line_of(offset),
            self.lines.col_of(self.text.as_bytes(), offset),
        )
    }

    #[allow(clippy::too_many_arguments)]
    fn layer(
        &self,
        prefix: &str,
        machine: Option<Spanned<String>>,
        mode: Option<Spanned<RawMode>>,
        dt: Option<Spanned<f64>>,
        tolerance: Option<Spanned<f64>>,
        clearance: Option<Spanned<f64>>,
        min_depth: Option<Spanned<f64>>,
    ) -> Result<Layer, ConfigError> {
        let key = |k: &str| format!("{prefix}{k}");
        let machine = match machine {
            None => None,
            Some(m) => {
                if m.get_ref().trim().is_empty() {
                    return Err(self.err(m.span(), key("machine"), "the machine file name is empty"));
                }
                let (line, col) = self.place(m.span().start);
                Some(MachineRef {
                    path: normalize(&self.dir.join(m.get_ref())),
                    at: format!("{}:{line}:{col}: {}", self.file, key("machine")),
                })
            }
        };
        let number = |v: Option<Spanned<f64>>, k: &str, range: (f64, f64)| -> Result<Option<f64>, ConfigError> {
            let Some(v) = v else { return Ok(None) };
            match out_of_range(*v.get_ref(), range) {
                None => Ok(Some(*v.get_ref())),
                Some(why) => Err(self.err(v.span(), key(k), why)),
            }
        };
        Ok(Layer {
            machine,
            mode: mode.map(|m| match m.into_inner() {
                RawMode::Step => Mode::Step,
                RawMode::Exact => Mode::Exact,
            }),
            dt_ms: number(dt, "dt", DT_MS)?,
            tolerance_mm: number(tolerance, "tolerance", TOLERANCE_MM)?,
            clearance_mm: number(clearance, "clearance", CLEARANCE_MM)?,
            min_depth_mm: number(min_depth, "min_depth", MIN_DEPTH_MM)?,
            job: None,
        })
    }

    /// Kinds by name or code; an unknown one is an error at its place.
    fn kinds(&self, key: &str, names: Vec<Spanned<String>>) -> Result<Vec<Kind>, ConfigError> {
        let mut out = Vec::new();
        for (i, n) in names.into_iter().enumerate() {
            let k = latheguard::gate::kind_by_name_or_code(n.get_ref()).ok_or_else(|| {
                let all: Vec<String> = Kind::ALL
                    .iter()
                    .map(|&k| format!("{} ({})", k.name(), latheguard::finding::code(k)))
                    .collect();
                self.err(
                    n.span(),
                    format!("{key}[{i}]"),
                    format!(
                        "`{}` is not a finding kind; the kinds are: {}",
                        n.get_ref(),
                        all.join(", ")
                    ),
                )
            })?;
            if !out.contains(&k) {
                out.push(k);
            }
        }
        Ok(out)
    }

    /// The `job` at `path` of this configuration, if any.
    fn job(&self, path: &[&str], resolve: &mut dyn job::Resolve) -> Result<Option<JobRef>, ConfigError> {
        let base = self.dir.display().to_string();
        let label = match path {
            [_, i, _] => format!("{} override[{i}].job", self.file),
            _ => format!("{} [job]", self.file),
        };
        let got = job::parse_embedded(self.text, self.file, path, &base, &label, resolve).map_err(|e| ConfigError {
            file: e.file.clone(),
            line: e.line,
            col: e.col,
            key: e.key.clone(),
            message: e.message.clone(),
        })?;
        Ok(got.map(|g| match g {
            job::Embedded::Inline(l) => JobRef::Inline(Arc::new(*l)),
            job::Embedded::File { name, at } => JobRef::File {
                path: normalize(&self.dir.join(name)),
                at: format!("{}:{}:{}: {}", at.file, at.line, at.col, at.key),
            },
        }))
    }
}

/// Parse and validate a configuration. `file` is used in messages; `dir` is the folder machine
/// paths are relative to.
pub fn parse(text: &str, file: &str, dir: &Path, resolve: &mut dyn job::Resolve) -> Result<Config, ConfigError> {
    let cx = Cx {
        file,
        dir,
        lines: LineIndex::new(text.as_bytes()),
        text,
    };
    let (root, errors) = DeTable::parse_recoverable(text);
    if let Some(e) = errors.iter().min_by_key(|e| e.span().map_or(usize::MAX, |s| s.start)) {
        let at = e.span().unwrap_or(0..0);
        let key = render(&path_at(root.get_ref(), at.start));
        return Err(cx.err(at, key, format!("TOML syntax error: {}", one_line(e.message()))));
    }
    let tree = root.clone();
    let raw = RawConfig::deserialize(toml::de::Deserializer::from(root)).map_err(|e| {
        let at = e.span().unwrap_or(0..0);
        let mut path = path_at(tree.get_ref(), at.start);
        let message = one_line(e.message());
        if let Some(field) = message
            .strip_prefix("missing field `")
            .and_then(|m| m.strip_suffix('`'))
        {
            path.push(field.to_string());
            return cx.err(at, render(&path), format!("missing required key `{field}`"));
        }
        let message = latheguard::machine::with_suggestion(&message, &message);
        cx.err(at, render(&path), message)
    })?;
    if raw.overrides.len() > MAX_OVERRIDES {
        let at = raw.overrides[MAX_OVERRIDES].span();
        return Err(cx.err(at, "override", format!("at most {MAX_OVERRIDES} [[override]] tables")));
    }
    let mut base = cx.layer(
        "",
        raw.machine,
        raw.mode,
        raw.dt,
        raw.tolerance,
        raw.clearance,
        raw.min_depth,
    )?;
    if raw.job.is_some() {
        base.job = cx.job(&["job"], resolve)?;
    }
    let mut gate = Gate {
        selection: Selection {
            select: raw.select.map(|s| cx.kinds("select", s)).transpose()?,
            extend_select: cx.kinds("extend-select", raw.extend_select.unwrap_or_default())?,
            ignore: cx.kinds("ignore", raw.ignore.unwrap_or_default())?,
        },
        fail_on: raw.fail_on.map(|f| match f.into_inner() {
            RawFailOn::Error => FailOn::Error,
            RawFailOn::Warning => FailOn::Warning,
        }),
        per_file: Vec::new(),
        unused_suppressions: raw.unused_suppressions,
    };
    let mut per_file: Vec<_> = raw.per_file_ignores.unwrap_or_default().into_iter().collect();
    per_file.sort_by_key(|(g, _)| g.span().start);
    if per_file.len() > MAX_OVERRIDES {
        let at = per_file[MAX_OVERRIDES].0.span();
        return Err(cx.err(at, "per-file-ignores", format!("at most {MAX_OVERRIDES} globs")));
    }
    for (glob, kinds) in per_file {
        let key = format!("per-file-ignores.\"{}\"", glob.get_ref());
        let matcher = glob_matcher(glob.get_ref()).map_err(|why| cx.err(glob.span(), key.clone(), why))?;
        let kinds = cx.kinds(&key, kinds)?;
        gate.per_file.push((glob.into_inner(), matcher, kinds));
    }
    let mut overrides = Vec::with_capacity(raw.overrides.len());
    for (i, o) in raw.overrides.into_iter().enumerate() {
        let prefix = format!("override[{i}].");
        let o = o.into_inner();
        let matcher =
            glob_matcher(o.glob.get_ref()).map_err(|why| cx.err(o.glob.span(), format!("{prefix}glob"), why))?;
        let mut layer = cx.layer(&prefix, o.machine, o.mode, o.dt, o.tolerance, o.clearance, o.min_depth)?;
        if o.job.is_some() {
            let i = i.to_string();
            layer.job = cx.job(&["override", &i, "job"], resolve)?;
        }
        overrides.push((matcher, layer));
    }
    Ok(Config {
        dir: dir.to_path_buf(),
        shown: file.to_string(),
        base,
        overrides,
        gate,
    })
}

/// A glob longer than this is refused.
pub const MAX_GLOB_CHARS: usize = 1000;
/// Braces nested deeper than this are refused (`{a,{b,c}}` is depth 2).
pub const MAX_GLOB_BRACE_DEPTH: usize = 8;

/// Compile an override's glob, or say why not. The glob library turns a glob into a regular
/// expression and panics when that expression is too deep or too large, so the size and the
/// brace nesting are bounded first, and a panic that still escapes is an error too.
fn glob_matcher(glob: &str) -> Result<GlobMatcher, String> {
    if glob.chars().count() > MAX_GLOB_CHARS {
        return Err(format!("not a glob: longer than {MAX_GLOB_CHARS} characters"));
    }
    if brace_depth(glob) > MAX_GLOB_BRACE_DEPTH {
        return Err(format!(
            "not a glob: braces nested more than {MAX_GLOB_BRACE_DEPTH} deep"
        ));
    }
    let built = std::panic::catch_unwind(|| {
        GlobBuilder::new(glob)
            .literal_separator(true)
            .build()
            .map(|g| g.compile_matcher())
    });
    match built {
        Ok(Ok(m)) => Ok(m),
        Ok(Err(e)) => Err(format!("not a glob: {}", e.kind())),
        Err(_) => Err("not a glob: too complex to match".into()),
    }
}

/// The deepest nesting of `{…}` in a glob (a `\`-escaped brace does not count).
fn brace_depth(glob: &str) -> usize {
    let (mut depth, mut deepest, mut escaped) = (0usize, 0usize, false);
    for c in glob.chars() {
        match c {
            _ if escaped => escaped = false,
            '\\' => escaped = true,
            '{' => {
                depth += 1;
                deepest = deepest.max(depth);
            }
            '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    deepest
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn contains(r: &Range<usize>, pos: usize) -> bool {
    r.start <= pos && (pos < r.end || r.start == r.end)
}

/// The dotted key path of the innermost key or value at a byte offset.
fn path_at(t: &DeTable<'_>, pos: usize) -> Vec<String> {
    for (k, v) in t.iter() {
        if contains(&k.span(), pos) {
            return vec![k.get_ref().to_string()];
        }
        match v.get_ref() {
            DeValue::Table(inner) => {
                let sub = path_at(inner, pos);
                if !sub.is_empty() || contains(&v.span(), pos) {
                    let mut p = vec![k.get_ref().to_string()];
                    p.extend(sub);
                    return p;
                }
            }
            DeValue::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    let sub = match item.get_ref() {
                        DeValue::Table(inner) => path_at(inner, pos),
                        _ => Vec::new(),
                    };
                    if !sub.is_empty() || contains(&item.span(), pos) {
                        let mut p = vec![format!("{}[{i}]", k.get_ref())];
                        p.extend(sub);
                        return p;
                    }
                }
                if contains(&v.span(), pos) {
                    return vec![k.get_ref().to_string()];
                }
            }
            _ => {
                if contains(&v.span(), pos) {
                    return vec![k.get_ref().to_string()];
                }
            }
        }
    }
    Vec::new()
}

fn render(path: &[String]) -> String {
    if path.is_empty() {
        TOP_LEVEL.to_string()
    } else {
        path.join(".")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse(text, "latheguard.toml", Path::new("/shop"), &mut Texts::default())
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn full_file() {
        let c = parse(
            "machine = \"m/a.toml\"\nmode = \"exact\"\ndt = 2\ntolerance = 0.02\nclearance = 0\n\n\
             [[override]]\nglob = \"legacy/*.nc\"\nclearance = 0.5\n\n[[override]]\nglob = \"**/*.tap\"\nmachine = \"b.toml\"\n",
            "latheguard.toml",
            Path::new("/shop"),
            &mut Texts::default(),
        )
        .unwrap();
        assert_eq!(c.base.mode, Some(Mode::Exact));
        assert_eq!(c.base.dt_ms, Some(2.0));
        assert_eq!(c.base.clearance_mm, Some(0.0));
        assert_eq!(c.base.machine.as_ref().unwrap().path, Path::new("/shop/m/a.toml"));
        assert_eq!(c.base.machine.as_ref().unwrap().at, "latheguard.toml:1:11: machine");
        let layers = c.layers_for(Path::new("/shop/legacy/x.nc"));
        assert_eq!(layers.len(), 2);
        assert_eq!(layers[1].clearance_mm, Some(0.5));
        assert_eq!(c.layers_for(Path::new("/shop/legacy/deeper/x.nc")).len(), 1);
        assert_eq!(c.layers_for(Path::new("/shop/a/b/c.tap")).len(), 2);
        assert_eq!(c.layers_for(Path::new("/elsewhere/legacy/x.nc")).len(), 1);
    }

    #[test]
    fn min_depth_at_top_level_and_in_an_override_and_its_range() {
        let c = parse(
            "min_depth = 0.05\n[[override]]\nglob = \"old/*\"\nmin_depth = 0\n",
            "latheguard.toml",
            Path::new("/shop"),
            &mut Texts::default(),
        )
        .unwrap();
        assert_eq!(c.base.min_depth_mm, Some(0.05));
        let layers = c.layers_for(Path::new("/shop/old/a.nc"));
        assert_eq!(layers.last().unwrap().min_depth_mm, Some(0.0));
        assert_eq!(
            err("min_depth = 1.5\n"),
            "latheguard.toml:1:13: min_depth: must be a number from 0 to 1, not 1.5"
        );
    }

    #[test]
    fn errors_name_file_line_and_key() {
        assert_eq!(
            err("mode = \"exact\"\nclerance = 1\n"),
            "latheguard.toml:2:1: clerance: unknown field `clerance`, expected one of `machine`, `mode`, `dt`, \
             `tolerance`, `clearance`, `min_depth`, `job`, `select`, `extend-select`, `ignore`, `fail-on`, \
             `per-file-ignores`, `unused-suppressions`, `override`: did you mean `clearance`?"
        );
        assert_eq!(
            err("mode = \"fast\"\n"),
            "latheguard.toml:1:8: mode: unknown variant `fast`, expected `step` or `exact`"
        );
        assert_eq!(
            err("dt = 0\n"),
            "latheguard.toml:1:6: dt: must be a number from 0.001 to 1000, not 0"
        );
        assert_eq!(
            err("[[override]]\nglob = \"a/*\"\n[[override]]\nclearance = 1\n"),
            "latheguard.toml:3:1: override[1].glob: missing required key `glob`"
        );
        assert_eq!(
            err("[[override]]\nglob = \"a/*\"\nspeed = 1\n"),
            "latheguard.toml:3:1: override[0].speed: unknown field `speed`, expected one of `glob`, `machine`, \
             `mode`, `dt`, `tolerance`, `clearance`, `min_depth`, `job`"
        );
        assert_eq!(
            err("[[override]]\nglob = \"a/[\"\n"),
            "latheguard.toml:2:8: override[0].glob: not a glob: unclosed character class; missing ']'"
        );
        assert_eq!(
            err("clearance = \"big\"\n"),
            "latheguard.toml:1:13: clearance: invalid type: string \"big\", expected f64"
        );
        assert!(err("mode = \n").starts_with("latheguard.toml:1:8: mode: TOML syntax error"));
        assert!(err("select = [\"LG01\", \"crash\"]\n").starts_with(
            "latheguard.toml:1:19: select[1]: `crash` is not a finding kind; the kinds are: collision (LG01)"
        ));
        assert!(err("[per-file-ignores]\n\"old/*.nc\" = [\"nearmiss\"]\n")
            .starts_with("latheguard.toml:2:15: per-file-ignores.\"old/*.nc\"[0]: `nearmiss` is not a finding kind"));
        assert_eq!(
            err("fail-on = \"never\"\n"),
            "latheguard.toml:1:11: fail-on: unknown variant `never`, expected `error` or `warning`"
        );
    }

    #[test]
    fn the_gate_keys_and_per_file_ignores() {
        let c = parse(
            "select = [\"collision\", \"LG04\"]\nextend-select = [\"program\"]\nignore = [\"LG04\"]\nfail-on = \"warning\"\n\
             unused-suppressions = false\n[per-file-ignores]\n\"legacy/**/*.nc\" = [\"near_miss\", \"LG06\"]\n",
            "latheguard.toml",
            Path::new("/shop"),
            &mut Texts::default(),
        )
        .unwrap();
        assert_eq!(c.gate.fail_on, Some(FailOn::Warning));
        let none = Selection::default();
        let r = rules_for(Some(&c), Path::new("/shop/a.nc"), &none);
        assert_eq!(r.select, Some(vec![Kind::Collision, Kind::Program]));
        assert!(r.quiet_unused);
        let r = rules_for(Some(&c), Path::new("/shop/legacy/x/a.nc"), &none);
        assert_eq!(c.per_file_ignores(Path::new("/shop/legacy/x/a.nc")).len(), 1);
        assert!(r.ignore.contains(&Kind::NearMiss) && r.reports(Kind::Collision));
    }
}
