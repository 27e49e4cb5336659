//! What applies to a program: its machine (command line, `latheguard.toml`, built-in), its
//! settings and its job layers (docs/job.md), each file read once per run; and `latheguard
//! setup`, which prints the result.

use super::args::{JobArgs, SetupArgs, TableFormat, UnitsArg};
use super::config::{Finder, MachineRef, FILE_NAME};
use super::{emit, load_machine, plain, read_text, safe_lines, Trouble, EXIT_CLEAN, MAX_MACHINE_BYTES};
use latheguard::assume::Assumption;
use latheguard::job::{self, EffectiveJob, Layer};
use latheguard::machine::{self, num, Machine};
use latheguard::pipeline::Settings;
use serde_json::json;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A program's machine, settings and job.
pub struct Resolved {
    /// The machine the checker runs: the machine file with the job applied.
    pub machine: Arc<Machine>,
    /// The machine file (`built-in: …` for the built-in machine).
    pub machine_file: String,
    /// `latheguard.toml`'s settings (the command line's are not applied here).
    pub settings: Settings,
    /// The configuration that applied, if any.
    pub config: Option<PathBuf>,
    /// That configuration, read.
    pub cfg: Option<Arc<super::config::Config>>,
    pub job: Arc<EffectiveJob>,
    /// The program has no job and its machine is one the reading knows (`crate::assume`): its
    /// setup is read from it (`assumed_machine`). False with `--no-assume`.
    pub assume: bool,
    /// What `setup` read from the program (filled by `run`).
    pub assumed: Vec<Assumption>,
}

/// The machine a program with no job is checked on: `machine` with the setup read from `src`
/// (shown as `file`) applied, and that job; `machine` itself and no job when nothing was read or
/// it does not fit (a note says why). With the notes of what was read.
pub fn assumed_machine(
    src: &[u8],
    file: &str,
    machine: &Arc<Machine>,
) -> (Arc<Machine>, Option<EffectiveJob>, Vec<Assumption>) {
    let a = latheguard::assume::apply(src, file, machine);
    match a.machine {
        Some((m, job)) => (Arc::new(m), Some(job), a.notes),
        None => (machine.clone(), None, a.notes),
    }
}

/// A machine with a job applied, and the job.
type Applied = (Arc<Machine>, Arc<EffectiveJob>);

/// Resolves programs one after the other, reading every file once.
pub struct Planner {
    finder: Finder,
    no_config: bool,
    cli_machine: Option<(Arc<Machine>, String)>,
    /// The built-in machine, read when a program first needs it (a run with `-m` never does).
    builtin: std::sync::OnceLock<Arc<Machine>>,
    machines: HashMap<PathBuf, Arc<Machine>>,
    cli_layers: Vec<Arc<Layer>>,
    /// `--no-assume`.
    no_assume: bool,
    /// (machine, layers) → the machine with the job applied.
    applied: HashMap<(usize, Vec<usize>), Applied>,
    /// Every machine, configuration and job file read (no output may overwrite them).
    pub inputs: Vec<PathBuf>,
}

impl Planner {
    pub fn new(machine: Option<&Path>, no_config: bool, a: &JobArgs) -> Result<Planner, Trouble> {
        let cli_machine = match machine {
            Some(p) => Some((Arc::new(load_machine(Some(p))?), super::shown(p))),
            None => None,
        };
        let mut finder = Finder::new();
        let mut inputs: Vec<PathBuf> = machine.iter().map(|p| p.to_path_buf()).collect();
        // Lowest first: --job, then the one-off flags (--tools, --stock, --units, --program-zero).
        let mut cli_layers = Vec::new();
        if let Some(j) = &a.job {
            inputs.push(j.clone());
            cli_layers.push(finder.job_file(j, None)?);
        }
        if let Some(t) = &a.tools {
            let l = finder.job_file(t, None)?;
            let only_tools = Layer {
                label: l.label.clone(),
                files: l.files.clone(),
                tools: l.tools.clone(),
                warnings: l.warnings.clone(),
                ..Layer::default()
            };
            if *l != only_tools {
                return Err(format!(
                    "--tools {}: the file sets more than [[tools]] (and tool_library, tool_table); give a whole job with --job",
                    super::shown(t)
                ));
            }
            inputs.push(t.clone());
            cli_layers.push(l);
        }
        let flags = job::flags_layer(a.stock.as_deref(), a.units.map(|u| u == UnitsArg::Inch), a.program_zero)
            .map_err(|e| {
                if a.stock.is_some() && e.starts_with('`') {
                    format!("--stock: {e}")
                } else {
                    e
                }
            })?;
        if !flags.is_empty() {
            cli_layers.push(Arc::new(flags));
        }
        Ok(Planner {
            finder,
            no_config,
            cli_machine,
            builtin: std::sync::OnceLock::new(),
            machines: HashMap::new(),
            cli_layers,
            no_assume: a.no_assume,
            applied: HashMap::new(),
            inputs,
        })
    }

    /// `--config FILE`: that configuration for every program, read now.
    pub fn force_config(&mut self, file: &Path) -> Result<(), Trouble> {
        self.finder.force(file).map_err(|e| e.to_string())?;
        self.inputs.push(file.to_path_buf());
        Ok(())
    }

    /// The machine of the command line, else the built-in one (without any job).
    pub fn default_machine(&self) -> Arc<Machine> {
        self.cli_machine
            .as_ref()
            .map_or_else(|| self.builtin(), |m| m.0.clone())
    }

    fn builtin(&self) -> Arc<Machine> {
        self.builtin.get_or_init(|| Arc::new(Machine::builtin())).clone()
    }

    /// The machine, settings and job of one program (`-`: standard input, which has no file
    /// beside it).
    pub fn resolve(&mut self, program: &Path) -> Result<Resolved, Trouble> {
        let mut settings = Settings::default();
        let mut named: Option<MachineRef> = None;
        let mut layers: Vec<Arc<Layer>> = Vec::new();
        let mut config = None;
        let mut cfg_read = None;
        let stdin = program.as_os_str() == "-";
        if !self.no_config {
            let abs = self.finder.absolute(program);
            if let Some(cfg) = self.finder.config_for(&abs).map_err(|e| e.to_string())? {
                let file = cfg.dir.join(FILE_NAME);
                if !self.inputs.contains(&file) {
                    self.inputs.push(file.clone());
                }
                config = Some(file);
                cfg_read = Some(cfg.clone());
                for layer in cfg.layers_for(&abs) {
                    if let Some(m) = layer.mode {
                        settings.mode = m;
                    }
                    settings.dt_ms = layer.dt_ms.unwrap_or(settings.dt_ms);
                    settings.tolerance_mm = layer.tolerance_mm.unwrap_or(settings.tolerance_mm);
                    settings.clearance_mm = layer.clearance_mm.unwrap_or(settings.clearance_mm);
                    settings.min_depth_mm = layer.min_depth_mm.or(settings.min_depth_mm);
                    if layer.machine.is_some() {
                        named = layer.machine.clone();
                    }
                    if let Some(j) = &layer.job {
                        layers.push(self.finder.job(j)?);
                    }
                }
            }
        }
        if !stdin {
            if let Some(b) = self.finder.beside(program)? {
                if let Some(p) = super::config::beside_path(program) {
                    if !self.inputs.contains(&p) {
                        self.inputs.push(p);
                    }
                }
                layers.push(b);
            }
        }
        layers.extend(self.cli_layers.iter().cloned());
        let (base, machine_file) = match (&self.cli_machine, named) {
            (Some((m, shown)), _) => (m.clone(), shown.clone()),
            (None, Some(r)) => {
                let shown = self.finder.shown(&r.path);
                (self.machine_for(&r)?, shown)
            }
            (None, None) => (self.builtin(), format!("built-in: {}", machine::BUILTIN_NAME)),
        };
        let (machine, job) = self.apply(&base, &layers, program)?;
        // The files the job read besides its own (tool libraries, tool tables, part files), as
        // shown (relative to the working folder): no output may overwrite them either.
        for f in &job.files {
            let p = PathBuf::from(f);
            if !self.inputs.contains(&p) {
                self.inputs.push(p);
            }
        }
        // Only a program with no job at all is read for its setup: a job, even of one key,
        // says the setup is written down.
        let assume = !self.no_assume && layers.is_empty() && base.kinematics.is_none();
        Ok(Resolved {
            machine,
            machine_file,
            settings,
            config,
            cfg: cfg_read,
            job,
            assume,
            assumed: Vec::new(),
        })
    }

    /// The machine with the job of `layers` applied, once per machine and list of layers.
    fn apply(&mut self, base: &Arc<Machine>, layers: &[Arc<Layer>], program: &Path) -> Result<Applied, Trouble> {
        let key = (
            Arc::as_ptr(base) as usize,
            layers.iter().map(|l| Arc::as_ptr(l) as usize).collect::<Vec<_>>(),
        );
        if let Some(got) = self.applied.get(&key) {
            return Ok(got.clone());
        }
        let job = Arc::new(EffectiveJob::merge(layers.iter().map(|l| l.as_ref())));
        let machine = if job.is_empty() {
            base.clone()
        } else {
            let m = job::apply(base, &job).map_err(|e| {
                format!(
                    "{}\n  (the job of {} on {})",
                    super::error_lines(&e),
                    super::shown(program),
                    base.name
                )
            })?;
            for w in job::warnings(base, &job) {
                super::say(&format!("warning: {w}"));
            }
            Arc::new(m)
        };
        self.applied.insert(key, (machine.clone(), job.clone()));
        Ok((machine, job))
    }

    /// Load a machine file named by a configuration, once per file.
    fn machine_for(&mut self, r: &MachineRef) -> Result<Arc<Machine>, Trouble> {
        let shown = self.finder.shown(&r.path);
        let key = std::fs::canonicalize(&r.path)
            .map_err(|e| format!("{}: cannot read machine file {shown}: {}", r.at, plain(&e)))?;
        if let Some(m) = self.machines.get(&key) {
            return Ok(m.clone());
        }
        let text = read_text(&key, MAX_MACHINE_BYTES)
            .map_err(|why| format!("{}: cannot read machine file {shown}: {why}", r.at))?;
        let m = super::parse_machine(&text, &shown, &key)
            .map_err(|e| format!("{}\n  (the machine of {})", super::error_lines(&e), r.at))?;
        super::warn_machine(&m);
        let m = Arc::new(m);
        self.machines.insert(key.clone(), m.clone());
        self.inputs.push(key);
        Ok(m)
    }
}

/// `latheguard setup PROGRAM`.
pub fn run(a: SetupArgs) -> Result<u8, Trouble> {
    if std::fs::symlink_metadata(&a.program).is_err() {
        return Err(format!("{}: no such file", super::shown(&a.program)));
    }
    let mut planner = Planner::new(a.machine.as_deref(), a.no_config, &a.job)?;
    let mut r = planner.resolve(&a.program)?;
    let assumed = read_setup(&a.program, &mut r);
    r.assumed = assumed;
    let auto = auto_dialect(&a.program, &r);
    let text = match a.format {
        TableFormat::Text => safe_lines(&text(&a.program, &r, &auto)),
        TableFormat::Json => {
            let mut s = serde_json::to_string_pretty(&json(&a.program, &r, &auto)).unwrap_or_default();
            s.push('\n');
            s
        }
    };
    emit(None, &text)?;
    Ok(EXIT_CLEAN)
}

const MACHINE: &str = "machine";

/// The setup read from the program (docs/assume.md), laid under the job: `r` then shows the
/// machine and job the check runs with. The notes, each value with its reason.
fn read_setup(program: &Path, r: &mut Resolved) -> Vec<Assumption> {
    if !r.assume {
        return Vec::new();
    }
    let Ok(src) = super::check::read_program(program) else {
        return Vec::new();
    };
    let (machine, job, notes) = assumed_machine(&src, &super::shown(program), &r.machine);
    if let Some(job) = job {
        r.machine = machine;
        r.job = Arc::new(job);
    }
    notes
}

/// On a machine whose file says `dialect = "auto"`: the dialect the program's own signs choose
/// and why, as `check` reads it (`pipeline::resolve`), or why the program could not be read.
fn auto_dialect(program: &Path, r: &Resolved) -> Option<Result<(machine::Dialect, String), String>> {
    r.machine.auto_dialect.as_ref()?;
    match super::check::read_program(program) {
        Ok(src) => latheguard::pipeline::resolve(&src, &r.machine).1.map(Ok),
        Err(why) => Some(Err(why)),
    }
}

/// Which layer set a value: the last job layer that did, else the machine file.
fn from<T>(s: &Option<job::Set<T>>) -> &str {
    s.as_ref().map_or(MACHINE, |s| s.layer.as_str())
}

fn stock_text(m: &Machine) -> String {
    match &m.stock {
        None => "none".into(),
        Some(s @ machine::Stock { block: Some(b), .. }) => {
            format!(
                "block {} × {} (x × y at C0) × {} mm, z {} .. {}; its revolved envelope Ø{} (the corners) in front of the jaws",
                num(b.width),
                num(b.height),
                num(s.length),
                num(s.front - s.length),
                num(s.front),
                num(s.diameter)
            )
        }
        Some(s) if s.outline.is_some() => format!(
            "revolved outline, Ø{} max, z {} .. {} ({} points)",
            num(s.diameter),
            num(s.front - s.length),
            num(s.front),
            s.outline.as_ref().map_or(0, |o| o.points().len())
        ),
        Some(s) => {
            let kind = if s.bore > 0.0 {
                format!("tube Ø{}/Ø{}", num(s.diameter), num(s.bore))
            } else {
                format!("bar Ø{}", num(s.diameter))
            };
            format!(
                "{kind} × {} mm, front face at z {} (the stick-out)",
                num(s.length),
                num(s.front)
            )
        }
    }
}

/// One of the job's operations after the first, as `setup` lists it.
struct OperationRow<'a> {
    /// 2 for the first of `[[operations]]`.
    number: usize,
    set: &'a job::Set<job::JobOperation>,
    /// The operation as the machine holds it (its jaws resolved).
    op: &'a machine::Operation,
    text: String,
    layer: &'a str,
}

/// The job's operations, each described in words: where it starts (with the program stop the
/// program writes on that line, if any), how the part stands, its jaws, its program zero, its
/// note.
fn operation_rows<'a>(program: &Path, r: &'a Resolved) -> Vec<OperationRow<'a>> {
    let Some(ops) = r.job.operations.as_ref() else {
        return Vec::new();
    };
    let src = if ops.iter().any(|o| matches!(o.value.start, machine::OpStart::Line(_))) {
        super::check::read_program(program).unwrap_or_default()
    } else {
        Vec::new()
    };
    ops.iter()
        .zip(&r.machine.operations)
        .enumerate()
        .map(|(i, (set, op))| {
            let v = &set.value;
            let mut t = match v.start {
                machine::OpStart::Line(l) => match stop_word(&src, l) {
                    Some(m) => format!("from line {l} ({m}): "),
                    None => format!("from line {l}: "),
                },
                machine::OpStart::Stop(n) => format!("after program stop {n} (the {n}. M0 or M1 the program makes): "),
                machine::OpStart::WorkOffset(n) => {
                    format!("at the first block that selects {}: ", work_offset_name(n))
                }
            };
            t.push_str(if v.reverse {
                "part turned round"
            } else {
                "part re-clamped"
            });
            match v.stand {
                latheguard::scene::Stand::Front(f) => {
                    let _ = write!(t, ", front at z {}", num(f));
                }
                latheguard::scene::Stand::Grip(g) => {
                    let _ = write!(t, ", held {} mm in the jaws (back end at z {})", num(g), num(-g));
                }
                latheguard::scene::Stand::Stay => t.push_str(", where it stood"),
            }
            let _ = write!(t, ", jaws {}", machine::outline_text(op.chuck.as_ref()),);
            if v.chuck.is_none() {
                t.push_str(" (the job's chuck)");
            }
            if let Some(z) = v.program_zero_z {
                let _ = write!(t, ", G54 program zero at z {}", num(z));
            }
            match &op.tailstock {
                machine::OpTailstock::AsItStood => {}
                machine::OpTailstock::Out => t.push_str(", tailstock not in use"),
                machine::OpTailstock::At { outline, advance } => {
                    let _ = write!(
                        t,
                        ", tailstock {}live centre at z {}",
                        if *advance { "advanced, " } else { "" },
                        num(outline.aabb().min.y)
                    );
                }
            }
            if let Some(n) = &v.note {
                let _ = write!(t, ", note: {n}");
            }
            OperationRow {
                number: i + 2,
                set,
                op,
                text: t,
                layer: set.layer.as_str(),
            }
        })
        .collect()
}

/// `G55` for work offset 1.
fn work_offset_name(n: u8) -> &'static str {
    machine::WORK_OFFSET_NAMES[usize::from(n).min(5)]
}

/// The program stop (M0, M00, M1, M01 as written) on file line `line` of `src`, outside
/// comments, if there is one.
fn stop_word(src: &[u8], line: u32) -> Option<String> {
    let text = src.split(|&b| b == b'\n').nth(line.checked_sub(1)? as usize)?;
    let text = String::from_utf8_lossy(text).to_ascii_uppercase();
    let mut code = String::new();
    let mut depth = 0u32;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '(' => depth += 1,
            ')' => depth = depth.saturating_sub(1),
            ';' if depth == 0 => break,
            'M' if depth == 0 => {
                code.clear();
                while let Some(d) = chars.peek().copied().filter(char::is_ascii_digit) {
                    code.push(d);
                    chars.next();
                }
                if !code.is_empty() && matches!(code.parse::<u32>(), Ok(0 | 1)) {
                    return Some(format!("M{code}"));
                }
            }
            _ => {}
        }
    }
    None
}

/// Where each tool came from: the job layer that put it in its station, else the machine file.
fn tool_rows(r: &Resolved) -> Vec<(&latheguard::machine::Tool, String, String)> {
    r.machine
        .tools
        .iter()
        .map(
            |t| match r.job.tools.iter().find(|j| j.value.tool.station == t.station) {
                Some(j) => (t, j.layer.clone(), j.value.origin.clone()),
                None => match from_table(r, t) {
                    Some((layer, origin)) => (t, layer, origin),
                    None => (t, MACHINE.to_string(), String::new()),
                },
            },
        )
        .collect()
}

/// A tool `[tool_numbers] from_table` put in its station: the layer and `tbl 12 (lathe.tbl)`.
fn from_table(r: &Resolved, t: &latheguard::machine::Tool) -> Option<(String, String)> {
    let table = r.job.tool_numbers_table.as_ref()?;
    r.machine
        .tool_numbers
        .iter()
        .filter(|n| n.1 == t.station)
        .find_map(|n| table.value.rows.iter().find(|row| row.0 == n.0))
        .filter(|row| row.2.tool.insert == t.insert && row.2.tool.holder == t.holder)
        .map(|row| (table.layer.clone(), row.2.origin.clone()))
}

/// The tool-number map in force: `(tool, station, the layer that gave it, the tool table whose
/// pocket it is when it came from one)`, by tool.
fn tool_number_rows(r: &Resolved) -> Vec<(u32, u32, String, Option<String>)> {
    let j = &r.job;
    r.machine
        .tool_numbers
        .iter()
        .map(
            |&(tool, station)| match j.tool_numbers.iter().find(|n| n.value.0 == tool) {
                Some(n) => (tool, station, n.layer.clone(), None),
                None => match j
                    .tool_numbers_table
                    .as_ref()
                    .filter(|t| t.value.rows.iter().any(|row| row.0 == tool))
                {
                    Some(t) => (tool, station, t.layer.clone(), Some(t.value.file.clone())),
                    // The machine file's own `[tool_numbers]`.
                    None => (tool, station, MACHINE.to_string(), None),
                },
            },
        )
        .collect()
}

/// The work offsets in force, each with its text and the layer that gave it: G54 always (the
/// program zero at start), G55–G59 when given.
fn offset_rows(r: &Resolved) -> Vec<(usize, String, String)> {
    let (m, j) = (&r.machine, &r.job);
    (0..machine::WORK_OFFSET_NAMES.len())
        .filter_map(|n| {
            let text = m.work_offset_text(n)?;
            let from = match (&j.work_offsets[n], n) {
                (Some(o), _) => o.layer.clone(),
                (None, 0) => program_zero_from(m, j).to_string(),
                (None, _) => MACHINE.to_string(),
            };
            Some((n, text, from))
        })
        .collect()
}

/// Which layers set the jaws: those that gave a key of `[chuck.jaws]`, and the one whose bar the
/// jaws close on; else the machine file.
fn jaws_from(r: &Resolved) -> String {
    if r.machine.chuck_jaws().is_none() {
        return MACHINE.to_string();
    }
    let mut layers: Vec<&str> = r.job.jaws.layers();
    if let Some((_, s)) = job::grip_from_stock(&r.machine, &r.job) {
        if !layers.contains(&s.layer.as_str()) {
            layers.push(s.layer.as_str());
        }
    }
    if layers.is_empty() {
        MACHINE.to_string()
    } else {
        layers.join(", ")
    }
}

/// Which layer set program zero at start (G54): its `program_zero_z` or `work_offsets.G54`, or
/// the stock it was taken from, else the machine file.
fn program_zero_from<'a>(m: &Machine, j: &'a EffectiveJob) -> &'a str {
    match (&j.work_offsets[0], &j.program_zero_z, &j.stock) {
        (Some(o), _, _) => o.layer.as_str(),
        (None, Some(z), _) => z.layer.as_str(),
        (None, None, Some(st)) if m.stock.is_some() => st.layer.as_str(),
        _ => MACHINE,
    }
}

fn text(program: &Path, r: &Resolved, auto: &Option<Result<(machine::Dialect, String), String>>) -> String {
    let m = &r.machine;
    let j = &r.job;
    let mut s = String::new();
    let _ = writeln!(s, "{}", super::shown(program));
    let _ = writeln!(s, "  machine       {} ({})", m.name, r.machine_file);
    if let Some(c) = &r.config {
        let _ = writeln!(
            s,
            "  config        {}",
            super::shown(c.strip_prefix(std::env::current_dir().unwrap_or_default()).unwrap_or(c))
        );
    }
    if j.layers.is_empty() {
        let _ = writeln!(s, "  job           none (the machine file's setup)");
    } else {
        for (i, l) in j.layers.iter().enumerate() {
            let _ = writeln!(s, "  {:<13} {l}", if i == 0 { "job layers" } else { "" });
        }
    }
    let units = if m.inch { "inch (G20)" } else { "mm (G21)" };
    let _ = writeln!(s, "  units         {units}  [{}]", from(&j.units_inch));
    let dialect = match auto {
        Some(Ok((d, why))) => format!("{} ({why})", d.as_str()),
        Some(Err(why)) => format!("{} (auto: the program could not be read: {why})", m.dialect.as_str()),
        None if j.dialect.as_ref().is_some_and(|d| d.value == job::DialectChoice::Auto) => format!(
            "{} (auto in a job keeps the machine's; `dialect = \"auto\"` in the machine file reads each program's)",
            m.dialect.as_str()
        ),
        None => m.dialect.as_str().to_string(),
    };
    let _ = writeln!(s, "  dialect       {dialect}  [{}]", from(&j.dialect));
    let _ = writeln!(s, "  stock         {}  [{}]", stock_text(m), from(&j.stock));
    let pz_from = program_zero_from(m, j);
    let _ = writeln!(s, "  program Z0    z {}  [{pz_from}]", num(m.program_zero_z));
    for (n, text, from) in offset_rows(r) {
        let name = machine::WORK_OFFSET_NAMES[n];
        let _ = writeln!(s, "  work offset   {name} {text}  [{from}]");
    }
    let jaws_from = jaws_from(r);
    let chuck_from = match (&j.chuck, m.chuck_jaws()) {
        (None, Some(_)) => jaws_from.clone(),
        _ => from(&j.chuck).to_string(),
    };
    let _ = writeln!(
        s,
        "  chuck         {}  [{chuck_from}]",
        machine::outline_text(m.chuck.as_ref()),
    );
    if let Some(c) = m.chuck_jaws() {
        let _ = writeln!(s, "  jaws          {}  [{jaws_from}]", c.describe_jaws());
    }
    let tail = match (&m.tailstock, m.tailstock_advanced) {
        (None, _) => "none".to_string(),
        (Some(_), adv) => format!(
            "{}, {}",
            machine::outline_text(m.tailstock.as_ref()),
            if adv { "advanced at start" } else { "retracted at start" }
        ),
    };
    let tail_from = match (&j.tailstock_in_use, &j.tailstock_z) {
        (Some(a), Some(b)) if a.layer != b.layer => format!("{}, z: {}", a.layer, b.layer),
        (_, Some(z)) => z.layer.clone(),
        (a, None) => from(a).to_string(),
    };
    let _ = writeln!(s, "  tailstock     {tail}  [{tail_from}]");
    let _ = writeln!(
        s,
        "  X words       {}  [{}]",
        if m.diameter_mode { "diameters" } else { "radii" },
        from(&j.diameter_mode)
    );
    let spindle = match m.start_rpm {
        Some(r) => format!(
            "turning at {} rpm from program start (as if M3 S{} came first)",
            num(r),
            num(r)
        ),
        None => "stopped at program start".into(),
    };
    let _ = writeln!(s, "  spindle       {spindle}  [{}]", from(&j.start_rpm));
    for c in &j.tool_changes {
        let (line, station) = c.value;
        let name = m.tool(station).map_or("", |t| t.name.as_str());
        let _ = writeln!(
            s,
            "  tool change   at line {line}: the operator puts in T{station:02} {name}  [{}]",
            c.layer
        );
    }
    let numbers = tool_number_rows(r);
    if !numbers.is_empty() {
        let shown = |table: bool| {
            numbers
                .iter()
                .filter(|n| n.3.is_some() == table)
                .map(|n| format!("T{} → station {}", n.0, n.1))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut text = shown(false);
        if let Some(file) = numbers.iter().find_map(|n| n.3.as_ref()) {
            if !text.is_empty() {
                text.push_str("; ");
            }
            let _ = write!(text, "{} ({file} pockets)", shown(true));
        }
        let mut layers: Vec<&str> = Vec::new();
        for n in &numbers {
            if !layers.contains(&n.2.as_str()) {
                layers.push(&n.2);
            }
        }
        let _ = writeln!(s, "  tool numbers  {text}  [{}]", layers.join(", "));
    }
    for row in operation_rows(program, r) {
        let _ = writeln!(
            s,
            "  {:<13} {}  [{}]",
            format!("operation {}", row.number),
            row.text,
            row.layer
        );
    }
    let carriers = &r.machine.paths.carriers;
    if carriers.is_empty() {
        let _ = writeln!(s, "  tools");
    } else {
        // A multi-path machine: each path's carrier has its own tools (a job's go to path 1's).
        let _ = writeln!(s, "  tools of path 1 ({})", r.machine.paths.first);
    }
    for (t, layer, origin) in tool_rows(r) {
        let _ = writeln!(s, "{}", tool_line(t, &layer, &origin));
    }
    for c in carriers {
        let _ = writeln!(s, "  tools of path {} ({})", c.path, c.name);
        for t in &c.tools {
            let _ = writeln!(s, "{}", tool_line(t, MACHINE, ""));
        }
    }
    if !r.assumed.is_empty() {
        let _ = writeln!(s, "  read from the program (a job, or --no-assume, turns this off)");
        for n in &r.assumed {
            let what = if n.kept { "kept" } else { "assumed" };
            let _ = writeln!(s, "    {}: {} ({what}): {}", n.key, n.value, n.reason);
        }
    }
    for w in &j.warnings {
        let _ = writeln!(s, "  warning: {w}");
    }
    s
}

/// A tool's line in the text form: station, name, tip, nose, and where it came from.
fn tool_line(t: &latheguard::machine::Tool, layer: &str, origin: &str) -> String {
    let mut line = format!(
        "    T{:02} {}  tip [{}, {}]",
        t.station,
        t.name,
        num(t.tip.x),
        num(t.tip.y)
    );
    if t.nose_radius > 0.0 {
        let _ = write!(line, "  nose r{}", num(t.nose_radius));
    }
    if t.tip_direction != 0 {
        let _ = write!(line, "  tip direction {}", t.tip_direction);
    }
    if origin.is_empty() {
        let _ = write!(line, "  [{layer}]");
    } else {
        let _ = write!(line, "  [{layer}: {origin}]");
    }
    line
}

/// A tool in the JSON form.
fn tool_json(t: &latheguard::machine::Tool, layer: &str, origin: &str) -> serde_json::Value {
    json!({
        "station": t.station, "name": t.name, "tip": [t.tip.x, t.tip.y],
        "nose_radius": t.nose_radius, "tip_direction": t.tip_direction,
        "insert": t.insert.points().iter().map(|q| [q.x, q.y]).collect::<Vec<_>>(),
        "holder": t.holder.points().iter().map(|q| [q.x, q.y]).collect::<Vec<_>>(),
        "from": layer, "origin": origin,
    })
}

fn json(program: &Path, r: &Resolved, auto: &Option<Result<(machine::Dialect, String), String>>) -> serde_json::Value {
    let m = &r.machine;
    let j = &r.job;
    let outline = |p: &Option<latheguard::geom::Polygon>| {
        p.as_ref()
            .map(|p| p.points().iter().map(|q| [q.x, q.y]).collect::<Vec<_>>())
    };
    json!({
        "program": super::shown(program),
        "machine": { "name": m.name, "file": r.machine_file },
        "config": r.config.as_ref().map(|c| super::shown(c.strip_prefix(std::env::current_dir().unwrap_or_default()).unwrap_or(c))),
        "job": { "layers": j.layers, "files": j.files },
        "units": { "value": if m.inch { "inch" } else { "mm" }, "from": from(&j.units_inch) },
        "dialect": match auto {
            Some(Ok((d, why))) => json!({
                "value": d.as_str(), "from": from(&j.dialect), "auto": why.strip_prefix("auto: ").unwrap_or(why) }),
            Some(Err(why)) => json!({ "value": m.dialect.as_str(), "from": from(&j.dialect), "auto": why }),
            None => json!({ "value": m.dialect.as_str(), "from": from(&j.dialect) }),
        },
        "stock": {
            "value": m.stock.as_ref().map(|s| match &s.outline {
                Some(o) => json!({
                    "outline": o.points().iter().map(|q| [q.x, q.y]).collect::<Vec<_>>(),
                    "diameter": s.diameter, "length": s.length, "stick_out": s.front }),
                None => json!({
                    "diameter": s.diameter, "length": s.length, "stick_out": s.front, "bore": s.bore }),
            }),
            "from": from(&j.stock),
        },
        "program_zero_z": { "value": m.program_zero_z, "from": program_zero_from(m, j) },
        "work_offsets": offset_rows(r).iter().map(|(n, _, from)| {
            let (o, p) = (m.work_offset(*n), m.work_zero(*n));
            json!({
                "name": machine::WORK_OFFSET_NAMES[*n],
                "x": o.map(|o| o.x), "z": o.map(|o| o.z),
                "program_zero": p.map(|p| [p.x, p.y]),
                "from": from,
            })
        }).collect::<Vec<_>>(),
        "chuck": {
            "outline": outline(&m.chuck),
            "from": match (&j.chuck, m.chuck_jaws()) {
                (None, Some(_)) => jaws_from(r),
                _ => from(&j.chuck).to_string(),
            },
        },
        "jaws": m.chuck_jaws().map(|c| json!({
            "grip": c.jaws.grip.as_str(),
            "type": c.jaws.kind.as_str(),
            "grip_diameter": c.jaws.grip_diameter,
            "grip_length": c.jaws.grip_length,
            "height": c.jaws.height,
            "width": c.jaws.width,
            "step": c.jaws.step,
            "faces_z": c.faces(),
            "from": jaws_from(r),
        })),
        "tailstock": {
            "outline": outline(&m.tailstock),
            "advanced_at_start": m.tailstock.is_some() && m.tailstock_advanced,
            "from": from(&j.tailstock_in_use),
            "z_from": from(&j.tailstock_z),
        },
        "diameter_mode": { "value": m.diameter_mode, "from": from(&j.diameter_mode) },
        "spindle_start_rpm": { "value": m.start_rpm, "from": from(&j.start_rpm) },
        "tool_changes": j.tool_changes.iter().map(|c| json!({
            "line": c.value.0, "station": c.value.1, "from": c.layer,
        })).collect::<Vec<_>>(),
        "tool_numbers": tool_number_rows(r).iter().map(|(tool, station, layer, table)| json!({
            "tool": tool, "station": station, "from": layer, "table": table,
        })).collect::<Vec<_>>(),
        "operations": operation_rows(program, r).iter().map(|row| {
            let (o, v) = (&row.op, &row.set.value);
            json!({
                "operation": row.number,
                "key": row.set.at.key,
                "line": match v.start { machine::OpStart::Line(l) => Some(l), _ => None },
                "stop": match v.start { machine::OpStart::Stop(n) => Some(n), _ => None },
                "work_offset": match v.start { machine::OpStart::WorkOffset(n) => Some(work_offset_name(n)), _ => None },
                "tailstock": match &o.tailstock {
                    machine::OpTailstock::AsItStood => json!(null),
                    machine::OpTailstock::Out => json!({ "in_use": false }),
                    machine::OpTailstock::At { outline, advance } => json!({
                        "in_use": advance.then_some(true), "z": outline.aabb().min.y,
                    }),
                },
                "reverse": v.reverse,
                "front": match v.stand { latheguard::scene::Stand::Front(f) => Some(f), _ => None },
                "grip": match v.stand { latheguard::scene::Stand::Grip(g) => Some(g), _ => None },
                "chuck": { "outline": outline(&o.chuck), "own": v.chuck.is_some() },
                "program_zero_z": v.program_zero_z,
                "note": v.note,
                "from": row.layer,
            })
        }).collect::<Vec<_>>(),
        "tools": tool_rows(r).iter().map(|(t, layer, origin)| tool_json(t, layer, origin)).collect::<Vec<_>>(),
        // The other paths' carriers and their tools (a multi-path machine; empty otherwise).
        "paths": r.machine.paths.carriers.iter().map(|c| json!({
            "path": c.path, "carrier": c.name,
            "tools": c.tools.iter().map(|t| tool_json(t, MACHINE, "")).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
        "warnings": j.warnings,
        "assumed": r.assumed,
    })
}
