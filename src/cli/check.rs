//! `latheguard check`.

use super::args::{CheckArgs, FormatArg, ModeArg};
use super::{emit, load_machine, walk, Trouble, EXIT_CLEAN, EXIT_FINDINGS};
use latheguard::finding::{Finding, Kind};
use latheguard::pipeline::{self, Mode, Settings};
use latheguard::report::{self, FileReport, Report, TextOptions};
use std::io::IsTerminal;
use std::time::Instant;

pub fn run(a: CheckArgs) -> Result<u8, Trouble> {
    if let Some(kind) = &a.explain {
        let k = Kind::from_name(kind).ok_or_else(|| {
            let all: Vec<_> = Kind::ALL.iter().map(|k| k.name()).collect();
            format!("unknown finding kind `{kind}`; the kinds are: {}", all.join(", "))
        })?;
        emit(None, latheguard::finding::explain(k))?;
        return Ok(EXIT_CLEAN);
    }
    let machine = load_machine(a.machine.as_deref())?;
    let settings = Settings {
        mode: match a.mode {
            ModeArg::Step => Mode::Step,
            ModeArg::Exact => Mode::Exact,
        },
        dt_ms: a.dt,
        tolerance_mm: a.tolerance,
        clearance_mm: a.clearance,
        snapshots: false,
    };
    let files = walk::collect(&a.paths);
    let mut reports = Vec::with_capacity(files.len());
    for path in files {
        let shown = path.display().to_string();
        let started = Instant::now();
        let rep = match std::fs::read(&path) {
            Ok(src) => {
                let mut out = pipeline::check(&src, &machine, &settings);
                out.stats.elapsed_ms = started.elapsed().as_secs_f64() * 1000.0;
                FileReport {
                    path: shown,
                    findings: out.findings,
                    stats: out.stats,
                    source: src,
                    stock: out.stock,
                }
            }
            Err(e) => FileReport {
                path: shown,
                findings: vec![Finding::syntax(1, 0, format!("cannot read the file: {e}"))],
                stats: Default::default(),
                source: Vec::new(),
                stock: Vec::new(),
            },
        };
        reports.push(rep);
    }
    let report = Report {
        machine: machine.name.clone(),
        settings,
        files: reports,
    };
    let text = match a.format {
        FormatArg::Text => {
            let color = a.output.is_none() && std::io::stdout().is_terminal() && std::env::var_os("NO_COLOR").is_none();
            report::text(&report, TextOptions { color, quiet: a.quiet })
        }
        FormatArg::Json => report::json(&report),
    };
    emit(a.output.as_deref(), &text)?;
    Ok(if report.has_errors() { EXIT_FINDINGS } else { EXIT_CLEAN })
}
