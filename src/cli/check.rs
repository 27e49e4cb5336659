//! `latheguard check`: collect the files, give each its machine and settings (command line over
//! `latheguard.toml` over the defaults), check them in parallel, report in path order.

use super::args::{CheckArgs, ColorArg, FormatArg, ModeArg};
use super::config::{ConfigError, Finder, MachineRef};
use super::walk::{self, Entry, NC_EXTENSIONS};
use super::{emit, load_machine, plain, Trouble, EXIT_CLEAN, EXIT_FINDINGS, EXIT_TROUBLE};
use latheguard::finding::{Finding, Kind};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use latheguard::report::{self, FileReport, JunitOptions, Report, TextOptions};
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::{IsTerminal, Read};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// Programs larger than this are not read (a finding says so).
pub const MAX_PROGRAM_BYTES: u64 = 256 << 20;

/// The machine and settings when no file gives others (the command line's, or the defaults).
type Defaults = (Arc<Machine>, Settings);

/// One file to check, with what applies to it.
struct Job {
    entry: Entry,
    machine: Arc<Machine>,
    settings: Settings,
}

pub fn run(a: CheckArgs, color: ColorArg) -> Result<u8, Trouble> {
    if let Some(kind) = &a.explain {
        let k = Kind::from_name(kind).ok_or_else(|| {
            let all: Vec<_> = Kind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown finding kind `{kind}`; the kinds are: {}", all.join(", "))
        })?;
        emit(None, latheguard::finding::explain(k))?;
        return Ok(EXIT_CLEAN);
    }
    let exts: Vec<String> = match &a.ext {
        Some(list) => list.clone(),
        None => NC_EXTENSIONS.iter().map(|e| e.to_string()).collect(),
    };
    let mut entries = walk::collect(&a.paths, &exts);
    if let Some(s) = a.shard {
        entries = walk::shard(entries, s.index, s.count);
    }
    if entries.is_empty() && !a.quiet {
        eprintln!(
            "latheguard: no NC files to check (extensions: {}; see --ext)",
            exts.join(", ")
        );
    }
    let (defaults, jobs) = plan(&a, entries)?;
    let show_progress = !a.quiet && std::io::stderr().is_terminal() && std::env::var_os("CI").is_none();
    let reports = check_all(&jobs, a.jobs, show_progress, !a.no_timing)?;
    let internal = reports.iter().any(|(_, crashed)| *crashed);
    let report = assemble(defaults, &jobs, reports.into_iter().map(|(r, _)| r).collect());

    if let Some(out) = &a.stock_out {
        match report.files.as_slice() {
            [f] => {
                let svg = report::part::part_svg(&f.path, &f.stock);
                std::fs::write(out, svg).map_err(|e| format!("{}: cannot write: {e}", out.display()))?;
            }
            files => {
                return Err(format!(
                    "--stock-out draws one program's part; {} files were checked",
                    files.len()
                ))
            }
        }
    }
    if let Some(dir) = &a.svg {
        let n = write_pictures(dir, &report)?;
        if !a.quiet && n > 0 {
            eprintln!(
                "latheguard: wrote {n} picture{} to {}",
                if n == 1 { "" } else { "s" },
                dir.display()
            );
        }
    }
    let text = match a.format {
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
    };
    emit(a.output.as_deref(), &text)?;
    Ok(if internal {
        EXIT_TROUBLE
    } else if report.has_errors() {
        EXIT_FINDINGS
    } else {
        EXIT_CLEAN
    })
}

/// The machine and settings of every file. Every configuration and machine file is read here,
/// each once, so a bad one stops the run (exit 2) before anything is checked.
fn plan(a: &CheckArgs, entries: Vec<Entry>) -> Result<(Defaults, Vec<Job>), Trouble> {
    let cli_machine = match &a.machine {
        Some(p) => Some(Arc::new(load_machine(Some(p))?)),
        None => None,
    };
    let builtin = Arc::new(Machine::builtin());
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
        s.snapshots = a.svg.is_some();
        s
    };
    let defaults = (
        cli_machine.clone().unwrap_or_else(|| builtin.clone()),
        cli(Settings::default()),
    );

    let mut finder = Finder::new();
    let mut machines: HashMap<PathBuf, Arc<Machine>> = HashMap::new();
    let mut jobs = Vec::with_capacity(entries.len());
    for entry in entries {
        let mut settings = Settings::default();
        let mut named: Option<MachineRef> = None;
        if !a.no_config {
            let abs = finder.absolute(&entry.path);
            if let Some(cfg) = finder.config_for(&abs).map_err(|e: ConfigError| e.to_string())? {
                for layer in cfg.layers_for(&abs) {
                    if let Some(m) = layer.mode {
                        settings.mode = m;
                    }
                    settings.dt_ms = layer.dt_ms.unwrap_or(settings.dt_ms);
                    settings.tolerance_mm = layer.tolerance_mm.unwrap_or(settings.tolerance_mm);
                    settings.clearance_mm = layer.clearance_mm.unwrap_or(settings.clearance_mm);
                    if layer.machine.is_some() {
                        named = layer.machine.clone();
                    }
                }
            }
        }
        let machine = match (&cli_machine, named) {
            (Some(m), _) => m.clone(),
            (None, Some(r)) => machine_for(&r, &finder, &mut machines)?,
            (None, None) => builtin.clone(),
        };
        jobs.push(Job {
            entry,
            machine,
            settings: cli(settings),
        });
    }
    Ok((defaults, jobs))
}

/// Load a machine file named by a configuration, once per file.
fn machine_for(
    r: &MachineRef,
    finder: &Finder,
    cache: &mut HashMap<PathBuf, Arc<Machine>>,
) -> Result<Arc<Machine>, Trouble> {
    let shown = finder.shown(&r.path);
    let key = std::fs::canonicalize(&r.path)
        .map_err(|e| format!("{}: cannot read machine file {shown}: {}", r.at, plain(&e)))?;
    if let Some(m) = cache.get(&key) {
        return Ok(m.clone());
    }
    let text = std::fs::read_to_string(&key)
        .map_err(|e| format!("{}: cannot read machine file {shown}: {}", r.at, plain(&e)))?;
    let m = machine::from_toml(&text, &shown).map_err(|e| format!("{e}\n  (the machine of {})", r.at))?;
    let m = Arc::new(m);
    cache.insert(key, m.clone());
    Ok(m)
}

/// Check every job on a pool of `jobs` threads; the results keep the jobs' order. The flag is
/// true for a file whose check failed inside latheguard.
fn check_all(
    jobs: &[Job],
    threads: Option<u16>,
    progress: bool,
    timing: bool,
) -> Result<Vec<(FileReport, bool)>, Trouble> {
    let mut pool = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("latheguard-{i}"));
    if let Some(n) = threads {
        pool = pool.num_threads(n as usize);
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
                let r = check_one(j, timing);
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    Ok(out)
}

fn check_one(job: &Job, timing: bool) -> (FileReport, bool) {
    let path = job.entry.path.display().to_string();
    let unread = |why: String| FileReport {
        path: path.clone(),
        findings: vec![Finding::syntax(1, 0, why)],
        ..FileReport::default()
    };
    if let Some(problem) = &job.entry.problem {
        return (unread(problem.clone()), false);
    }
    let started = Instant::now();
    let src = match read_program(&job.entry.path) {
        Ok(src) => src,
        Err(why) => return (unread(why), false),
    };
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        pipeline::check(&src, &job.machine, &job.settings)
    }));
    match run {
        Ok(mut out) => {
            out.stats.elapsed_ms = if timing {
                started.elapsed().as_secs_f64() * 1000.0
            } else {
                0.0
            };
            let keep_source = !out.findings.is_empty();
            (
                FileReport {
                    path,
                    findings: out.findings,
                    stats: out.stats,
                    source: if keep_source { src } else { Vec::new() },
                    stock: out.stock,
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
fn read_program(path: &Path) -> Result<Vec<u8>, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read the file: {}", plain(&e)))?;
    let meta = file
        .metadata()
        .map_err(|e| format!("cannot read the file: {}", plain(&e)))?;
    if meta.is_dir() {
        return Err("cannot read the file: it is a folder".into());
    }
    if meta.len() > MAX_PROGRAM_BYTES {
        return Err(format!(
            "the file is {} bytes, more than the {} MiB latheguard reads",
            meta.len(),
            MAX_PROGRAM_BYTES >> 20
        ));
    }
    let mut src = Vec::with_capacity(meta.len() as usize);
    file.take(MAX_PROGRAM_BYTES + 1)
        .read_to_end(&mut src)
        .map_err(|e| format!("cannot read the file: {}", plain(&e)))?;
    if src.len() as u64 > MAX_PROGRAM_BYTES {
        return Err(format!(
            "the file is more than the {} MiB latheguard reads",
            MAX_PROGRAM_BYTES >> 20
        ));
    }
    Ok(src)
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
            f
        })
        .collect();
    Report {
        machine,
        settings,
        files,
    }
}

/// One SVG per finding that has a snapshot; returns how many were written.
fn write_pictures(dir: &Path, report: &Report) -> Result<usize, Trouble> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: cannot create folder: {}", dir.display(), plain(&e)))?;
    let mut n = 0;
    for (name, svg) in report::svg::pictures(report) {
        let p = dir.join(&name);
        std::fs::write(&p, svg).map_err(|e| format!("{}: cannot write picture: {}", p.display(), plain(&e)))?;
        n += 1;
    }
    Ok(n)
}
