//! `latheguard check`: collect the files, give each its machine and settings (command line over
//! `latheguard.toml` over the defaults), check them in parallel, report in path order.

use super::args::{CheckArgs, ColorArg, FailOnArg, FormatArg, ModeArg};
use super::setup::Planner;
use super::walk::{self, Entry, NC_EXTENSIONS};
use super::{
    emit, plain, read_capped, say, shown, Trouble, EXIT_CLEAN, EXIT_FINDINGS, EXIT_TROUBLE, MAX_PROGRAM_BYTES,
};
use latheguard::finding::{code, Finding, Kind};
use latheguard::gate::{self, FailOn};
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use latheguard::report::{self, FileReport, JunitOptions, Report, TextOptions};
use rayon::prelude::*;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// At most this many pictures of one file's findings are written with `--svg` (and `--glb`: a
/// finding's picture and scene are kept or left out together).
pub const MAX_PICTURES_PER_FILE: usize = 100;
/// At most this many pictures in all are written with `--svg`.
pub const MAX_PICTURES: usize = 1000;

/// The machine and settings when no file gives others (the command line's, or the defaults).
type Defaults = (Arc<Machine>, Settings);

/// One file to check, with what applies to it.
struct Job {
    entry: Entry,
    machine: Arc<Machine>,
    settings: Settings,
    /// The job layers that applied (docs/job.md).
    job: Vec<String>,
    /// The name the report gives it (`--stdin-filename` for `-`).
    name: String,
    /// The gate's rules for it (latheguard.toml, the command line, per-file-ignores).
    rules: gate::Rules,
    /// Its latheguard.toml's `fail-on`.
    fail_on: Option<FailOn>,
    /// The program has no job: read its setup from it (`setup::assumed_machine`).
    assume: bool,
}

pub fn run(mut a: CheckArgs, color: ColorArg) -> Result<u8, Trouble> {
    if let Some(kind) = &a.explain {
        let k = gate::kind_by_name_or_code(kind).ok_or_else(|| {
            let all: Vec<_> = Kind::ALL
                .iter()
                .map(|&k| format!("{} ({})", k.name(), code(k)))
                .collect();
            format!("unknown finding kind `{kind}`; the kinds are: {}", all.join(", "))
        })?;
        emit(None, latheguard::finding::explain(k))?;
        return Ok(EXIT_CLEAN);
    }
    if a.paths.is_empty() {
        a.paths = vec![PathBuf::from(if a.stdin_filename.is_some() { "-" } else { "." })];
    }
    let exts: Vec<String> = match &a.ext {
        Some(list) => list.clone(),
        None => NC_EXTENSIONS.iter().map(|e| e.to_string()).collect(),
    };
    // A path named on the command line that does not exist is a mistake of the run, not a
    // finding about a program: all of them are named, and nothing is checked (exit 2).
    let missing: Vec<String> = a
        .paths
        .iter()
        .filter(|p| !is_stdin(p) && std::fs::symlink_metadata(p).is_err())
        .map(|p| format!("{}: no such file or folder", shown(p)))
        .collect();
    if let Some((last, rest)) = missing.split_last() {
        for m in rest {
            say(m);
        }
        return Err(last.clone());
    }
    if let Some(p) = &a.show_settings {
        let p = if p.is_empty() {
            a.paths[0].clone()
        } else {
            PathBuf::from(p)
        };
        return show_settings(&a, &p, &exts);
    }
    let stdin = if a.paths.iter().any(|p| is_stdin(p)) {
        Some(read_stdin()?)
    } else {
        None
    };
    let mut entries = walk::collect(&a.paths, &exts);
    if let Some(s) = a.shard {
        entries = walk::shard(entries, s.index, s.count);
    }
    if entries.is_empty() && !a.quiet {
        say(&format!(
            "no NC files to check (extensions: {}; see --ext)",
            exts.join(", ")
        ));
    }
    let (defaults, jobs, inputs) = plan(&a, entries)?;
    // Refuse before any work: a report or a picture written over a program is a program lost.
    let mut protected: Vec<&Path> = jobs.iter().map(|j| j.entry.path.as_path()).collect();
    protected.extend(inputs.iter().map(PathBuf::as_path));
    if let Some(out) = &a.output {
        refuse_overwrite(out, "--output", &protected, &exts)?;
    }
    if let Some(out) = &a.stock_out {
        refuse_overwrite(out, "--stock-out", &protected, &exts)?;
    }
    let show_progress = !a.quiet && std::io::stderr().is_terminal() && std::env::var_os("CI").is_none();
    let input = Input {
        stdin: stdin.as_deref(),
        timing: !a.no_timing,
    };
    let reports = check_all(&jobs, a.jobs, show_progress, &input)?;
    let internal = reports.iter().any(|(_, crashed)| *crashed);
    let mut report = assemble(defaults, &jobs, reports.into_iter().map(|(r, _)| r).collect());
    report.fail_on = match a.fail_on {
        Some(FailOnArg::Warning) => FailOn::Warning,
        _ => FailOn::Error,
    };
    if a.fail_on.is_none() {
        // Each file fails on what its latheguard.toml says; the command line's is over all.
        for (f, j) in report.files.iter_mut().zip(&jobs) {
            f.fail_on = j.fail_on;
        }
    }

    if let Some(out) = &a.stock_out {
        match report.files.as_slice() {
            [f] => {
                let bytes = if is_stl(out) {
                    f.part_stl
                        .clone()
                        .ok_or_else(|| format!("{}: the final part has no surface to write (no stock)", shown(out)))?
                } else if is_toml(out) {
                    let part = f
                        .part
                        .as_ref()
                        .ok_or_else(|| format!("{}: the final part has no material to write (no stock)", shown(out)))?;
                    report::part::part_toml(&f.path, part).into_bytes()
                } else {
                    report::part_svg::part_svg(&f.path, &f.stock, f.part.as_ref()).into_bytes()
                };
                std::fs::write(out, bytes).map_err(|e| format!("{}: cannot write: {}", shown(out), plain(&e)))?;
            }
            files => {
                return Err(format!(
                    "--stock-out draws one program's part; {} files were checked",
                    files.len()
                ))
            }
        }
    }
    if a.svg.is_none() {
        // Only --glb: the working plane's snapshots are not drawn, nor counted.
        for f in &mut report.files {
            for x in &mut f.findings {
                x.snapshot = None;
            }
        }
    }
    let left_out = limit_pictures(&mut report);
    if let Some(dir) = &a.glb {
        // Only findings of the 3D path have a scene to write: for the others, nothing is
        // written and nothing said (not even the folder is made).
        let n = write_scenes(dir, &report)?;
        if !a.quiet && n > 0 {
            say(&format!(
                "wrote {n} 3D scene{} (glTF) to {}",
                if n == 1 { "" } else { "s" },
                shown(dir)
            ));
        }
    }
    if let Some(dir) = &a.svg {
        let n = write_pictures(dir, &mut report)?;
        if !a.quiet && n > 0 {
            say(&format!(
                "wrote {n} picture{} to {}",
                if n == 1 { "" } else { "s" },
                shown(dir)
            ));
        }
    }
    if left_out > 0 {
        say(&format!(
            "left out {left_out} picture{} (at most {MAX_PICTURES_PER_FILE} per file and {MAX_PICTURES} per run)",
            if left_out == 1 { "" } else { "s" }
        ));
    }
    let text = match a.format {
        FormatArg::Json if a.statistics => report::statistics_json(&report),
        _ if a.statistics => report::statistics(&report),
        FormatArg::Text => {
            let color = match color {
                ColorArg::Always => true,
                ColorArg::Never => false,
                ColorArg::Auto => {
                    a.output.is_none()
                        && std::io::stdout().is_terminal()
                        && std::env::var_os("NO_COLOR").map_or(true, |v| v.is_empty())
                }
            };
            report::text(&report, TextOptions { color, quiet: a.quiet })
        }
        FormatArg::Json => report::json(&report),
        FormatArg::Junit => report::junit(&report, JunitOptions { timing: !a.no_timing }),
        FormatArg::Sarif => report::sarif(&report),
        FormatArg::Github => report::github(&report),
        FormatArg::Gitlab => report::gitlab(&report),
    };
    emit(a.output.as_deref(), &text)?;
    if a.output.is_some() && !a.quiet {
        // The report went to a file: the log of the run still says how it went.
        say(&report::summary_line(&report));
    }
    Ok(if internal {
        EXIT_TROUBLE
    } else if report.fails() {
        EXIT_FINDINGS
    } else {
        EXIT_CLEAN
    })
}

/// The machine and settings of every file. Every configuration, machine and job file is read
/// here, each once, so a bad one stops the run (exit 2) before anything is checked. Also returns
/// the files read, which no output may overwrite.
fn plan(a: &CheckArgs, entries: Vec<Entry>) -> Result<(Defaults, Vec<Job>, Vec<PathBuf>), Trouble> {
    let mut planner = Planner::new(a.machine.as_deref(), a.no_config, &a.job)?;
    if let Some(c) = &a.config {
        planner.force_config(c)?;
    }
    let selection = cli_selection(a);
    let cli = |mut s: Settings| {
        if let Some(m) = a.mode {
            s.mode = match m {
                ModeArg::Step => Mode::Step,
                ModeArg::Exact => Mode::Exact,
            };
        }
        s.dt_ms = a.dt.unwrap_or(s.dt_ms);
        s.tolerance_mm = a.tolerance.unwrap_or(s.tolerance_mm);
        s.clearance_mm = a.clearance.unwrap_or(s.clearance_mm);
        s.min_depth_mm = a.min_depth.or(s.min_depth_mm);
        // The 3D path's scenes (--glb) are taken with the pictures' snapshots.
        s.snapshots = a.svg.is_some() || a.glb.is_some();
        s.part_mesh = a.stock_out.as_deref().is_some_and(is_stl);
        s
    };
    let defaults = (planner.default_machine(), cli(Settings::default()));
    let mut jobs = Vec::with_capacity(entries.len());
    for entry in entries {
        let as_path = looked_up_as(a, &entry.path);
        let r = planner.resolve(as_path)?;
        let abs = std::env::current_dir().unwrap_or_default().join(as_path);
        jobs.push(Job {
            name: as_path.display().to_string(),
            rules: super::config::rules_for(r.cfg.as_deref(), &abs, &selection),
            fail_on: r.cfg.as_ref().and_then(|c| c.gate.fail_on),
            entry,
            machine: r.machine,
            settings: cli(r.settings),
            job: r.job.layers.clone(),
            assume: r.assume,
        });
    }
    Ok((defaults, jobs, planner.inputs))
}

/// Check every job on a pool of `jobs` threads; the results keep the jobs' order. The flag is
/// true for a file whose check failed inside latheguard.
/// What every file's check shares: standard input's program (for `-`), the gate's rules, and
/// whether run times are reported.
struct Input<'a> {
    stdin: Option<&'a [u8]>,
    timing: bool,
}

/// The path a program's configuration, job and per-file-ignores are looked up as: its own, or
/// `--stdin-filename` for `-`.
fn looked_up_as<'p>(a: &'p CheckArgs, path: &'p Path) -> &'p Path {
    match &a.stdin_filename {
        Some(name) if is_stdin(path) => name,
        _ => path,
    }
}

/// The command line's layer of kind selection.
fn cli_selection(a: &CheckArgs) -> gate::Selection {
    gate::Selection {
        select: a.select.clone(),
        extend_select: a.extend_select.clone().unwrap_or_default(),
        ignore: a.ignore.clone().unwrap_or_default(),
    }
}

fn kinds(ks: &[Kind]) -> String {
    let names: Vec<&str> = ks.iter().map(|k| k.name()).collect();
    format!("[{}]", names.join(", "))
}

/// `--show-settings`: what applies to one program (the first found under `path`) and where each
/// value came from.
fn show_settings(a: &CheckArgs, path: &Path, exts: &[String]) -> Result<u8, Trouble> {
    use std::fmt::Write as _;
    let program = if is_stdin(path) {
        path.to_path_buf()
    } else {
        walk::collect(std::slice::from_ref(&path.to_path_buf()), exts)
            .into_iter()
            .next()
            .map(|e| e.path)
            .ok_or_else(|| format!("{}: no NC file to show the settings of", shown(path)))?
    };
    let as_path = looked_up_as(a, &program);
    let mut planner = Planner::new(a.machine.as_deref(), a.no_config, &a.job)?;
    if let Some(c) = &a.config {
        planner.force_config(c)?;
    }
    let r = planner.resolve(as_path)?;
    let abs = std::env::current_dir().unwrap_or_default().join(as_path);
    let cfg = r.cfg.as_deref();
    let cfg_name = cfg.map(|c| c.shown.clone()).unwrap_or_default();
    let mut o = String::new();
    let _ = writeln!(o, "program: {}", shown(as_path));
    let _ = writeln!(
        o,
        "configuration: {}",
        match (cfg, a.no_config, &a.config) {
            (Some(c), _, Some(_)) => format!("{} (--config)", c.shown),
            (Some(c), _, None) => format!("{} (the nearest)", c.shown),
            (None, true, _) => "none (--no-config)".into(),
            (None, false, _) => "none found".into(),
        }
    );
    // Which layer of the configuration last set a key.
    let layers: Vec<(String, &super::config::Layer)> = match cfg {
        None => Vec::new(),
        Some(c) => {
            let mut v = vec![(c.shown.clone(), &c.base)];
            for (g, l) in &c.overrides {
                if c.layers_for(&abs).iter().any(|x| std::ptr::eq(*x, l)) {
                    v.push((format!("{} [[override]] glob = \"{}\"", c.shown, g.glob().glob()), l));
                }
            }
            v
        }
    };
    let from = |cli: bool, set: &dyn Fn(&super::config::Layer) -> bool| -> String {
        if cli {
            return "command line".into();
        }
        layers
            .iter()
            .rev()
            .find(|(_, l)| set(l))
            .map_or_else(|| "default".into(), |(n, _)| n.clone())
    };
    let machine_from = if a.machine.is_some() {
        "command line".to_string()
    } else {
        from(false, &|l| l.machine.is_some())
    };
    let _ = writeln!(o, "machine: {}  ({machine_from})", r.machine_file);
    let mode = a
        .mode
        .map(|m| if m == ModeArg::Exact { Mode::Exact } else { Mode::Step })
        .unwrap_or(r.settings.mode);
    let mode_name = if mode == Mode::Exact { "exact" } else { "step" };
    let _ = writeln!(
        o,
        "mode: {mode_name}  ({})",
        from(a.mode.is_some(), &|l| l.mode.is_some())
    );
    let _ = writeln!(
        o,
        "dt: {} ms  ({})",
        a.dt.unwrap_or(r.settings.dt_ms),
        from(a.dt.is_some(), &|l| l.dt_ms.is_some())
    );
    let _ = writeln!(
        o,
        "tolerance: {} mm  ({})",
        a.tolerance.unwrap_or(r.settings.tolerance_mm),
        from(a.tolerance.is_some(), &|l| l.tolerance_mm.is_some())
    );
    let _ = writeln!(
        o,
        "clearance: {} mm  ({})",
        a.clearance.unwrap_or(r.settings.clearance_mm),
        from(a.clearance.is_some(), &|l| l.clearance_mm.is_some())
    );
    let min_depth = a.min_depth.or(r.settings.min_depth_mm);
    let _ = writeln!(
        o,
        "min_depth: {}  ({})",
        min_depth.map_or_else(
            || "the machine's min_depth, else 0.1 mm".to_string(),
            |d| format!("{d} mm")
        ),
        from(a.min_depth.is_some(), &|l| l.min_depth_mm.is_some())
    );
    if r.job.layers.is_empty() {
        let _ = writeln!(o, "job: none");
    } else {
        let _ = writeln!(o, "job: {}  (lowest first)", r.job.layers.join(", "));
    }
    let _ = writeln!(o, "gate:");
    if let Some(c) = cfg {
        let g = &c.gate.selection;
        if let Some(s) = &g.select {
            let _ = writeln!(o, "  select = {}  ({cfg_name})", kinds(s));
        }
        if !g.extend_select.is_empty() {
            let _ = writeln!(o, "  extend-select = {}  ({cfg_name})", kinds(&g.extend_select));
        }
        if !g.ignore.is_empty() {
            let _ = writeln!(o, "  ignore = {}  ({cfg_name})", kinds(&g.ignore));
        }
        for (glob, ks) in c.per_file_ignores(&abs) {
            let _ = writeln!(o, "  per-file-ignores \"{glob}\" = {}  ({cfg_name})", kinds(ks));
        }
    }
    if let Some(s) = &a.select {
        let _ = writeln!(o, "  --select {}  (command line)", kinds(s));
    }
    if let Some(s) = &a.extend_select {
        let _ = writeln!(o, "  --extend-select {}  (command line)", kinds(s));
    }
    if let Some(s) = &a.ignore {
        let _ = writeln!(o, "  --ignore {}  (command line)", kinds(s));
    }
    let rules = super::config::rules_for(cfg, &abs, &cli_selection(a));
    let reported: Vec<Kind> = Kind::ALL.into_iter().filter(|&k| rules.reports(k)).collect();
    let _ = writeln!(
        o,
        "  reported: {}",
        if reported.len() == Kind::ALL.len() {
            "every kind".to_string()
        } else {
            kinds(&reported)
        }
    );
    let (fail_on, fail_from) = match (a.fail_on, cfg.and_then(|c| c.gate.fail_on)) {
        (Some(f), _) => (f == FailOnArg::Warning, "command line".to_string()),
        (None, Some(f)) => (f == FailOn::Warning, cfg_name.clone()),
        (None, None) => (false, "default".into()),
    };
    let _ = writeln!(
        o,
        "  fail-on: {}  ({fail_from})",
        if fail_on { "warning" } else { "error" }
    );
    let unused = cfg.and_then(|c| c.gate.unused_suppressions);
    let _ = writeln!(
        o,
        "  unused-suppressions: {}  ({})",
        unused.unwrap_or(true),
        if unused.is_some() { cfg_name.as_str() } else { "default" }
    );
    emit(None, &o)?;
    Ok(EXIT_CLEAN)
}

fn is_stdin(p: &Path) -> bool {
    p.as_os_str() == "-"
}

/// Standard input, read whole (capped as a program file is).
fn read_stdin() -> Result<Vec<u8>, Trouble> {
    use std::io::Read;
    let mut bytes = Vec::new();
    std::io::stdin()
        .lock()
        .take(MAX_PROGRAM_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read standard input: {}", plain(&e)))?;
    if bytes.len() as u64 > MAX_PROGRAM_BYTES {
        return Err(format!(
            "standard input is larger than the {} MiB latheguard reads",
            MAX_PROGRAM_BYTES >> 20
        ));
    }
    Ok(bytes)
}

fn check_all(
    jobs: &[Job],
    threads: Option<u16>,
    progress: bool,
    input: &Input,
) -> Result<Vec<(FileReport, bool)>, Trouble> {
    let mut pool = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("latheguard-{i}"));
    if let Some(n) = threads {
        // Never more threads than files.
        pool = pool.num_threads(usize::from(n).min(jobs.len()).max(1));
    }
    let pool = pool.build().map_err(|e| format!("cannot start worker threads: {e}"))?;
    let bar = if progress {
        let bar =
            indicatif::ProgressBar::with_draw_target(Some(jobs.len() as u64), indicatif::ProgressDrawTarget::stderr());
        if let Ok(style) =
            indicatif::ProgressStyle::with_template("{bar:40.cyan/blue} {pos}/{len} files  {per_sec}  {eta} left")
        {
            bar.set_style(style);
        }
        bar
    } else {
        indicatif::ProgressBar::hidden()
    };
    let out = pool.install(|| {
        jobs.par_iter()
            .map(|j| {
                let r = check_one(j, input);
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    Ok(out)
}

fn check_one(job: &Job, input: &Input) -> (FileReport, bool) {
    let timing = input.timing;
    let path = job.name.clone();
    let unread = |why: String| FileReport {
        path: path.clone(),
        findings: gate::apply(
            vec![Finding::syntax(1, 0, why)],
            &job.rules,
            &gate::Suppressions::default(),
            Vec::new(),
        )
        .findings,
        ..FileReport::default()
    };
    if let Some(problem) = &job.entry.problem {
        return (unread(problem.clone()), false);
    }
    let started = Instant::now();
    let src = match (input.stdin, is_stdin(&job.entry.path)) {
        (Some(bytes), true) => bytes.to_vec(),
        _ => match read_program(&job.entry.path) {
            Ok(src) => src,
            Err(why) => return (unread(why), false),
        },
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let (machine, assumed) = if job.assume {
            let (m, _, notes) = super::setup::assumed_machine(&src, &path, &job.machine);
            (m, notes)
        } else {
            (job.machine.clone(), Vec::new())
        };
        (pipeline::check(&src, &machine, &job.settings), assumed)
    }));
    match run {
        Ok((mut out, assumed)) => {
            out.stats.elapsed_ms = if timing {
                started.elapsed().as_secs_f64() * 1000.0
            } else {
                0.0
            };
            let (sup, problems) = gate::Suppressions::read(&src);
            let gated = gate::apply(out.findings, &job.rules, &sup, problems);
            let keep_source = !gated.findings.is_empty() || !gated.suppressed.is_empty();
            (
                FileReport {
                    path,
                    findings: gated.findings,
                    suppressed: gated.suppressed,
                    stats: out.stats,
                    source: if keep_source { src } else { Vec::new() },
                    stock: out.stock,
                    part_stl: out.part_stl,
                    part: out.part,
                    assumed,
                    ..FileReport::default()
                },
                false,
            )
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_default();
            let f = Finding::program(
                1,
                0,
                format!("latheguard failed inside while checking this file ({what}); please report it"),
            );
            (
                FileReport {
                    path,
                    findings: vec![f],
                    ..FileReport::default()
                },
                true,
            )
        }
    }
}

/// The bytes of a program, or why they cannot be had.
pub(super) fn read_program(path: &Path) -> Result<Vec<u8>, String> {
    read_capped(path, MAX_PROGRAM_BYTES).map_err(|why| format!("cannot read the file: {why}"))
}

/// Refuse to write `out` (given as `flag`) when that would destroy an input: a program being
/// checked, a machine or configuration file read (`inputs`, compared by file identity), any
/// `latheguard.toml`, or any existing file with an NC extension of `exts` (but `.txt`, which
/// reports are often written to; a `.txt` program being checked is still protected).
pub fn refuse_overwrite(out: &Path, flag: &str, inputs: &[&Path], exts: &[String]) -> Result<(), Trouble> {
    let refuse = |what: &str| {
        Err(format!(
            "{flag} {}: refusing to write over {what}; choose another file",
            shown(out)
        ))
    };
    if out.file_name().is_some_and(|n| n == super::config::FILE_NAME) {
        return refuse("a latheguard configuration");
    }
    let Ok(target) = std::fs::canonicalize(out) else {
        return Ok(()); // nothing there yet
    };
    // By file identity (device and inode, or the file index on Windows), not by path: a hard
    // link to a program has a path of its own, and writing through it replaces the program.
    if let Ok(out_file) = same_file::Handle::from_path(out) {
        if inputs
            .iter()
            .any(|p| same_file::Handle::from_path(p).is_ok_and(|h| h == out_file))
        {
            return refuse("an input of this run");
        }
    }
    let nc: Vec<String> = exts
        .iter()
        .filter(|e| !e.eq_ignore_ascii_case("txt"))
        .cloned()
        .collect();
    if walk::has_extension(&target, &nc) || walk::has_extension(out, &nc) {
        return refuse("an existing NC program");
    }
    Ok(())
}

/// The batch: the report's machine and settings are the first file's (or the command line's when
/// there is no file); a file that differs carries its own.
fn assemble(defaults: Defaults, jobs: &[Job], files: Vec<FileReport>) -> Report {
    let (machine, settings) = match jobs.first() {
        Some(j) => (j.machine.name.clone(), j.settings),
        None => (defaults.0.name.clone(), defaults.1),
    };
    let files = files
        .into_iter()
        .zip(jobs)
        .map(|(mut f, j)| {
            if j.machine.name != machine {
                f.machine = Some(j.machine.name.clone());
            }
            if j.settings != settings {
                f.settings = Some(j.settings);
            }
            f.job.clone_from(&j.job);
            f
        })
        .collect();
    Report {
        machine,
        settings,
        files,
        fail_on: FailOn::Error,
        docs_url: docs_url(),
    }
}

/// Where the finding pages are published: `LATHEGUARD_DOCS_URL` (the folder of the `KIND.md`
/// pages), else the package's repository (`Cargo.toml` `repository`) + `/blob/main/docs/findings`,
/// else none.
fn docs_url() -> Option<String> {
    let from_env = std::env::var("LATHEGUARD_DOCS_URL")
        .ok()
        .filter(|u| !u.trim().is_empty());
    let from_package = option_env!("CARGO_PKG_REPOSITORY")
        .filter(|r| !r.is_empty())
        .map(|r| format!("{}/blob/main/docs/findings", r.trim_end_matches('/')));
    from_env
        .or(from_package)
        .map(|u| u.trim().trim_end_matches('/').to_string())
}

/// Drop the snapshots beyond [`MAX_PICTURES_PER_FILE`] of a file and [`MAX_PICTURES`] in all
/// (in path and line order); returns how many were dropped.
fn limit_pictures(report: &mut Report) -> usize {
    let (mut kept, mut dropped) = (0, 0);
    for f in &mut report.files {
        let mut in_file = 0;
        for x in &mut f.findings {
            if x.snapshot.is_none() && x.snapshot3.is_none() {
                continue;
            }
            if in_file < MAX_PICTURES_PER_FILE && kept < MAX_PICTURES {
                in_file += 1;
                kept += 1;
            } else {
                x.snapshot = None;
                x.snapshot3 = None;
                dropped += 1;
            }
        }
    }
    dropped
}

/// One `.glb` per finding that has a 3D snapshot; returns how many were written. The folder is
/// made only when there is one to write.
fn write_scenes(dir: &Path, report: &Report) -> Result<usize, Trouble> {
    let files = report::glb::files(report);
    if files.is_empty() {
        return Ok(0);
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create folder: {}", shown(dir), plain(&e)))?;
    for g in &files {
        let p = dir.join(&g.name);
        std::fs::write(&p, &g.bytes).map_err(|e| format!("{}: cannot write scene: {}", shown(&p), plain(&e)))?;
    }
    Ok(files.len())
}

/// One SVG per finding that has a snapshot; returns how many were written.
/// Each finding written gets its picture's path (`Finding::picture`), for the reports to link.
fn write_pictures(dir: &Path, report: &mut Report) -> Result<usize, Trouble> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create folder: {}", shown(dir), plain(&e)))?;
    let mut n = 0;
    for pic in report::svg::pictures(report) {
        let p = dir.join(&pic.name);
        std::fs::write(&p, pic.svg).map_err(|e| format!("{}: cannot write picture: {}", shown(&p), plain(&e)))?;
        if let Some(x) = report
            .files
            .get_mut(pic.file)
            .and_then(|f| f.findings.get_mut(pic.finding))
        {
            x.picture = Some(walk::tidy(&p).display().to_string().replace('\\', "/"));
        }
        n += 1;
    }
    Ok(n)
}

/// Whether `--stock-out` asks for a mesh (`.stl`, any case) rather than the SVG section.
fn is_stl(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("stl"))
}

/// Whether `--stock-out` asks for the part as a job fragment (`.toml`, any case): the next
/// operation's `[stock] from`.
fn is_toml(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}
