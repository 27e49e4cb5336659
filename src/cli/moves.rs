//! `latheguard moves`: the interpreted motion.

use super::args::{MovesArgs, MovesFormat};
use super::{emit, read_capped, shown, Trouble, EXIT_CLEAN, EXIT_FINDINGS, MAX_PROGRAM_BYTES};
use latheguard::finding::Severity;
use latheguard::interp::{self, canon, Feed, MoveKind};
use latheguard::pipeline;
use latheguard::report::terminal_safe;
use serde_json::json;
use std::io::Write;

pub fn run(a: MovesArgs) -> Result<u8, Trouble> {
    // The machine of -m (or the built-in one) with the program's job: the file beside it,
    // --job and the one-off flags. latheguard.toml is read only for the samples, which
    // `latheguard follow --program` checks on the machine `check` uses.
    let samples = matches!(a.format, MovesFormat::Samples);
    let resolved = super::setup::Planner::new(a.machine.as_deref(), !samples, &a.job)?.resolve(&a.program)?;
    let machine = resolved.machine;
    let src = read_capped(&a.program, MAX_PROGRAM_BYTES)
        .map_err(|why| format!("{}: cannot read: {why}", shown(&a.program)))?;
    if samples && latheguard::paths::is_multi_path(&src, &machine) {
        // Every path at once, in the machine's clock: what `follow` of the whole machine reads.
        return samples_of_paths(&shown(&a.program), &src, &machine, &resolved.settings, a.dt / 1000.0);
    }
    // One path of a multi-path program (docs/paths.md): its lines (the others blanked, so line
    // numbers stay the file's) on its carrier's lathe; a file without `$` lines is all one path's.
    let src = match latheguard::paths::split::split(&src) {
        None => src,
        Some(s) => match s.paths.into_iter().find(|(p, _)| *p == a.path) {
            Some((_, text)) => text,
            None => {
                return Err(format!(
                    "{}: has no ${} lines: no path {} to print",
                    shown(&a.program),
                    a.path,
                    a.path
                ))
            }
        },
    };
    let machine = match machine.for_path(a.path) {
        Some(std::borrow::Cow::Owned(m)) => std::sync::Arc::new(m),
        Some(std::borrow::Cow::Borrowed(_)) => machine,
        None => {
            return Err(format!(
                "--path {}: the machine has {} path{} (`[[paths]]`, docs/paths.md)",
                a.path,
                machine.paths.count(),
                if machine.paths.count() == 1 { "" } else { "s" }
            ))
        }
    };
    // A machine whose file says `dialect = "auto"` reads the program in the dialect its own
    // signs show, as `check` does.
    let (machine, _) = pipeline::resolve(&src, &machine);
    let machine = machine.as_ref();
    let mut prog = pipeline::read(&src, machine);
    let mut written: std::io::Result<()> = Ok(());
    let mut run = match a.format {
        MovesFormat::Canon => {
            // Streamed: the moves go out as the interpreter makes them, so neither the canonical
            // text nor the moves of a long program are ever whole in memory.
            let mut sink = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
            let run = interp::interpret_streaming(&prog, &src, machine, |c| {
                if written.is_ok() {
                    written = canon::write_chunk(c, &mut sink);
                }
            });
            if written.is_ok() {
                written = std::io::Write::flush(&mut sink);
            }
            run
        }
        MovesFormat::Json => interp::interpret(&prog, &src, machine),
        MovesFormat::Samples => {
            let run = interp::interpret(&prog, &src, machine);
            let mut sink = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
            latheguard::follow::replay::samples(&run, machine, a.dt / 1000.0, |s| {
                if written.is_ok() {
                    let line = latheguard::follow::replay::to_json(s);
                    written = writeln!(sink, "{line}");
                }
            });
            if written.is_ok() {
                written = std::io::Write::flush(&mut sink);
            }
            run
        }
    };
    let findings = pipeline::read_findings(&mut prog, &mut run);
    drop(prog);
    say_findings(&shown(&a.program), &findings);
    let out = match a.format {
        MovesFormat::Canon | MovesFormat::Samples => {
            match written {
                // A closed pipe (`latheguard moves … | head`) is not a failure.
                Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
                    return Err(format!("cannot write to standard output: {}", super::plain(&e)))
                }
                _ => {}
            }
            String::new()
        }
        MovesFormat::Json => {
            let list: Vec<_> = run
                .moves
                .iter()
                .map(|m| {
                    let (sx, sz) = run.frame(m).to_program(m.start);
                    let (ex, ez) = run.frame(m).to_program(m.end);
                    let (kind, extra) = match m.kind {
                        MoveKind::Rapid => ("rapid", json!(null)),
                        MoveKind::Line => ("line", json!(null)),
                        MoveKind::Arc { center, sweep } => {
                            let (cx, cz) = run.frame(m).to_program(center);
                            ("arc", json!({"center": [cx, cz], "sweep_deg": sweep.to_degrees()}))
                        }
                        MoveKind::Dwell { seconds } => ("dwell", json!({"seconds": seconds})),
                        MoveKind::ToolChange { from, to } => ("tool_change", json!({"from": from, "to": to})),
                        MoveKind::Operation { op } => (
                            "operation",
                            json!({"operation": op + 2, "job_key": format!("operations[{op}]")}),
                        ),
                        MoveKind::Wait { code, paths } => (
                            "wait",
                            json!({"mcode": code, "paths": (1..=8u8).filter(|p| paths & (1 << (p - 1)) != 0).collect::<Vec<_>>()}),
                        ),
                    };
                    let feed = match m.feed {
                        Feed::Rapid => json!(null),
                        Feed::PerMinute(f) => json!({"mm_per_min": f}),
                        Feed::PerRev(f) => json!({"mm_per_rev": f}),
                    };
                    json!({
                        "line": m.line, "n": m.n, "kind": kind, "station": m.station,
                        "from": [sx, sz], "to": [ex, ez], "feed": feed,
                        "spindle_rpm": run.spindle(m).rpm_at(m.start.x), "arc": extra,
                    })
                })
                .collect();
            let mut text = serde_json::to_string_pretty(&list).unwrap_or_default();
            text.push('\n');
            text
        }
    };
    emit(None, &out)?;
    Ok(if findings.iter().any(|f| f.severity == Severity::Error) {
        EXIT_FINDINGS
    } else {
        EXIT_CLEAN
    })
}

/// The samples of every path of a multi-path program (docs/follow.md, "Replay"), each sample
/// with every carrier's keys; the program's findings of reading and interpreting on standard
/// error, as for one path (exit 1 with an error among them).
fn samples_of_paths(
    name: &str,
    src: &[u8],
    machine: &latheguard::machine::Machine,
    settings: &pipeline::Settings,
    dt: f64,
) -> Result<u8, Trouble> {
    let timed = latheguard::paths::timed(src, machine, settings);
    let mut sink = std::io::BufWriter::with_capacity(1 << 16, std::io::stdout().lock());
    let mut written: std::io::Result<()> = Ok(());
    latheguard::follow::replay::samples_of_paths(&timed.paths, dt, timed.stop, |s| {
        if written.is_ok() {
            written = writeln!(sink, "{}", latheguard::follow::replay::to_json(s));
        }
    });
    if written.is_ok() {
        written = sink.flush();
    }
    say_findings(name, &timed.findings);
    match written {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(format!("cannot write to standard output: {}", super::plain(&e)))
        }
        _ if timed.findings.iter().any(|f| f.severity == Severity::Error) => Ok(EXIT_FINDINGS),
        _ => Ok(EXIT_CLEAN),
    }
}

/// A program's findings of reading and interpreting on standard error, one a line (what cannot
/// be written there is ignored: nowhere is left to say it).
fn say_findings(name: &str, findings: &[latheguard::finding::Finding]) {
    let mut err = std::io::stderr().lock();
    for f in findings {
        let _ = writeln!(
            err,
            "{name}:{}: {}[{}]: {}",
            f.line,
            f.severity.name(),
            f.kind,
            terminal_safe(&f.message)
        );
    }
}
