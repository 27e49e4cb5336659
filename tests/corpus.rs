//! Every program of `../shared/corpus` and `../shared/corpus-extra` (real lathe programs by
//! others) is read, interpreted and checked without a panic; each test prints a table of findings
//! by kind and program, with the time each program took, and the read rate (programs with no
//! `syntax` and no `unsupported` finding; docs/corpus.md).
//!
//! The corpora are kept out of this repository; CI has them beside the checkout. Without one the
//! test prints "skipped" and passes (a developer machine without `shared/`).
//!
//! Also here: step mode against exact mode on every program of `programs/`, `tests/cases/` and
//! the corpus programs with a job (`tests/corpus-jobs/`): every error exact mode reports, step
//! mode reports too (ARCHITECTURE.md, "What step mode guarantees").

use crate::case_machine::{case_machine, with_case_job};
use latheguard::finding::{Finding, Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A program that takes longer than this in the (debug) test build is named in the output.
const SLOW: Duration = Duration::from_secs(10);

use crate::corpus_job;
use crate::files;

pub(crate) fn shared(name: &str) -> PathBuf {
    files::shared().join(name)
}

pub(crate) fn linuxcnc() -> Machine {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("machines/linuxcnc-small-lathe.toml");
    machine::from_toml(&std::fs::read_to_string(&path).unwrap(), "linuxcnc-small-lathe.toml").unwrap()
}

/// The machine a corpus program is meant for: LinuxCNC for `.ngc` and generic G-code, the
/// built-in Fanuc lathe for `.nc` files.
pub(crate) fn machine_for(p: &Path, fanuc: &Machine, lcnc: &Machine) -> Machine {
    let name = p.to_string_lossy().to_lowercase();
    if name.ends_with(".nc") {
        fanuc.clone()
    } else {
        lcnc.clone()
    }
}

/// `corpus-extra/SOURCES.md` names each file's dialect: LinuxCNC and GRBL programs run on the
/// LinuxCNC machine, the rest (Fanuc-style lathes and their relatives) on the built-in one.
pub(crate) fn extra_dialects(dir: &Path) -> BTreeMap<String, bool> {
    let text = std::fs::read_to_string(dir.join("SOURCES.md")).unwrap_or_default();
    let mut linuxcnc = BTreeMap::new();
    for line in text.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        // | corpus path | class | repository | path | commit | licence | dialect | …
        if cols.len() > 7 && cols[1].starts_with('`') {
            let path = cols[1].trim_matches('`').to_string();
            let d = cols[7].to_lowercase();
            linuxcnc.insert(path, d.contains("linuxcnc") || d.contains("grbl"));
        }
    }
    linuxcnc
}

/// Check every file of a corpus and print the table; `machine` picks the machine by relative path.
fn run_corpus(name: &str, min_files: usize, machine: &dyn Fn(&str) -> Machine) -> Option<usize> {
    let dir = shared(name);
    if !dir.is_dir() {
        println!("{name}: skipped: no corpus at {}", dir.display());
        eprintln!("{name}: skipped: no corpus at {}", dir.display());
        return None;
    }
    let mut files = Vec::new();
    files::walk(&dir, &files::is_program, &mut files);
    files.sort();
    assert!(
        files.len() >= min_files,
        "{name} looks incomplete: {} files",
        files.len()
    );
    let mut table: BTreeMap<String, (BTreeMap<Kind, usize>, Duration)> = BTreeMap::new();
    let mut totals: BTreeMap<Kind, usize> = BTreeMap::new();
    let mut moves_total = 0usize;
    let mut slow = Vec::new();
    // The read rate: programs with no `syntax` and no `unsupported` finding (any severity).
    let mut read = 0usize;
    for f in &files {
        let src = std::fs::read(f).unwrap();
        let rel = f.strip_prefix(&dir).unwrap().display().to_string();
        let m = machine(&rel);
        let t = Instant::now();
        let (_, run) = pipeline::interpret(&src, &m);
        moves_total += run.moves.len();
        let out = pipeline::check(&src, &m, &Settings::default());
        let took = t.elapsed();
        if took > SLOW {
            slow.push(format!("{rel}: {:.1} s", took.as_secs_f64()));
        }
        if !out
            .findings
            .iter()
            .any(|x| matches!(x.kind, Kind::Syntax | Kind::Unsupported))
        {
            read += 1;
        }
        let row = table.entry(rel).or_default();
        row.1 = took;
        for x in &out.findings {
            *row.0.entry(x.kind).or_default() += 1;
            *totals.entry(x.kind).or_default() += 1;
        }
    }
    let kinds = [
        Kind::Syntax,
        Kind::Program,
        Kind::Unsupported,
        Kind::Collision,
        Kind::RapidIntoStock,
        Kind::SpindleStopped,
        Kind::Overtravel,
    ];
    let mut s = format!("{:<72}", format!("{name}: program"));
    for k in kinds {
        s += &format!(" {:>7}", &k.name()[..k.name().len().min(7)]);
    }
    s += "   time s";
    println!("{s}");
    for (file, (row, took)) in &table {
        let mut s = format!("{file:<72}");
        for k in kinds {
            s += &format!(" {:>7}", row.get(&k).copied().unwrap_or(0));
        }
        s += &format!(" {:>8.2}", took.as_secs_f64());
        println!("{s}");
    }
    let mut s = format!(
        "{:<72}",
        format!("TOTAL ({} files, {} moves)", files.len(), moves_total)
    );
    for k in kinds {
        s += &format!(" {:>7}", totals.get(&k).copied().unwrap_or(0));
    }
    println!("{s}");
    println!(
        "{name}: read rate: {read} of {} programs ({:.0} %) with no syntax and no unsupported finding",
        files.len(),
        100.0 * read as f64 / files.len().max(1) as f64
    );
    for x in &slow {
        println!("{name}: SLOW (over {} s in this build): {x}", SLOW.as_secs());
    }
    Some(moves_total)
}

#[test]
fn every_corpus_program_is_read_interpreted_and_checked() {
    let fanuc = Machine::builtin();
    let lcnc = linuxcnc();
    let Some(moves_total) = run_corpus("corpus", 50, &|rel| machine_for(Path::new(rel), &fanuc, &lcnc)) else {
        return;
    };
    assert!(
        moves_total > 10_000,
        "the corpus should produce real motion, got {moves_total} moves"
    );
}

#[test]
fn every_corpus_extra_program_is_read_interpreted_and_checked() {
    let fanuc = Machine::builtin();
    let lcnc = linuxcnc();
    let dialects = extra_dialects(&shared("corpus-extra"));
    let Some(moves_total) = run_corpus("corpus-extra", 15, &|rel| match dialects.get(rel) {
        Some(true) => lcnc.clone(),
        Some(false) => fanuc.clone(),
        None => machine_for(Path::new(rel), &fanuc, &lcnc),
    }) else {
        return;
    };
    assert!(
        moves_total > 1_000,
        "corpus-extra should produce real motion, got {moves_total} moves"
    );
}

pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A program to check in both modes, with the machine and settings it is written for.
pub(crate) struct Target {
    pub(crate) name: String,
    pub(crate) src: Vec<u8>,
    pub(crate) machine: Machine,
    pub(crate) settings: Settings,
}

/// The programs of `programs/` and `tests/cases/` with the machine and the settings their
/// `(test-case: …)` line gives and the job beside them (as `tests/cases.rs` reads them; the mode
/// and dt are the test's).
/// Left out: folders with their own `latheguard.toml` (the turn-mill examples, compared in both
/// modes by `tests/turn_mill.rs`) and cases with a hand-made kinematic tree (`kin=`).
pub(crate) fn case_targets(dir: &Path, out: &mut Vec<Target>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = rd.flatten().map(|e| e.path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            if !p.join("latheguard.toml").exists() {
                case_targets(&p, out);
            }
            continue;
        }
        if !matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "ngc")) {
            continue;
        }
        let src = std::fs::read(&p).unwrap();
        let first = String::from_utf8_lossy(src.split(|&b| b == b'\n').next().unwrap_or(&[])).into_owned();
        let mut machine = Machine::builtin();
        let mut settings = Settings::default();
        let mut hand_made_tree = false;
        if let Some(rest) = first.split("test-case:").nth(1) {
            for kv in rest.trim_end_matches([')', '\r', ' ']).split_whitespace() {
                let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                match k {
                    "machine" => machine = case_machine(&root(), v),
                    "kin" => hand_made_tree = true,
                    "tolerance" => settings.tolerance_mm = v.parse().unwrap(),
                    "clearance" => settings.clearance_mm = v.parse().unwrap(),
                    "min_depth" => settings.min_depth_mm = Some(v.parse().unwrap()),
                    _ => {}
                }
            }
        }
        if !hand_made_tree {
            let machine = with_case_job(machine, &p);
            let name = p.strip_prefix(root()).unwrap().display().to_string();
            out.push(Target {
                name,
                src,
                machine,
                settings,
            });
        }
    }
}

/// The corpus programs of `tests/corpus-jobs/index.toml` with their machine and job, as
/// `tests/corpus_setups.rs` checks them; none without `../shared`.
pub(crate) fn corpus_job_targets(out: &mut Vec<Target>) {
    if !files::shared().join("corpus").is_dir() {
        println!(
            "step against exact: corpus programs skipped: no corpus at {}",
            files::shared().display()
        );
        return;
    }
    let jobs = root().join("tests/corpus-jobs");
    let index: toml::Table = std::fs::read_to_string(jobs.join("index.toml"))
        .unwrap()
        .parse()
        .unwrap();
    for e in index["program"].as_array().unwrap() {
        let field = |k: &str| e[k].as_str().unwrap().to_string();
        let (program, machine_file, job) = (field("path"), field("machine"), field("job"));
        let text = std::fs::read_to_string(root().join(&machine_file)).unwrap();
        let machine = corpus_job::apply(&text, &machine_file, &jobs.join(&job)).unwrap();
        out.push(Target {
            src: std::fs::read(files::shared().join(&program)).unwrap(),
            name: program,
            machine,
            settings: Settings::default(),
        });
    }
}

/// The errors of a check as (line, kind, objects).
fn errors(findings: &[Finding]) -> Vec<(u32, Kind, Vec<String>)> {
    findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .map(|f| (f.line, f.kind, f.objects.clone()))
        .collect()
}

#[test]
fn step_mode_reports_every_error_exact_mode_reports() {
    let mut targets = Vec::new();
    case_targets(&root().join("programs"), &mut targets);
    case_targets(&root().join("tests/cases"), &mut targets);
    let cases = targets.len();
    corpus_job_targets(&mut targets);
    assert!(cases > 100, "too few programs and cases: {cases}");
    let t = Instant::now();
    let mut failures = Vec::new();
    let mut proof_failures = Vec::new();
    for x in &targets {
        let step = Settings {
            mode: Mode::Step,
            ..x.settings
        };
        let exact = Settings {
            mode: Mode::Exact,
            ..x.settings
        };
        let step = errors(&pipeline::check(&x.src, &x.machine, &step).findings);
        let exact_findings = pipeline::check(&x.src, &x.machine, &exact).findings;
        for e in errors(&exact_findings) {
            if !step.contains(&e) {
                failures.push(format!("{}:{}: {} {:?}", x.name, e.0, e.1.name(), e.2));
            }
        }
        // The proofs of stretches clear or in contact (check/exact.rs) against measuring probe
        // by probe: the same findings, depths within half the tolerance.
        let probed = Settings {
            prove_stretches: false,
            ..exact
        };
        let probed = pipeline::check(&x.src, &x.machine, &probed).findings;
        if let Some(why) = same_findings(&exact_findings, &probed, 0.5 * x.settings.tolerance_mm) {
            proof_failures.push(format!("{}: {why}", x.name));
        }
    }
    println!(
        "step against exact: {} programs ({cases} programs and cases, {} corpus programs with a job) in {:.1} s",
        targets.len(),
        targets.len() - cases,
        t.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "errors of exact mode that step mode (dt 1 ms) does not report:\n{}",
        failures.join("\n")
    );
    assert!(
        proof_failures.is_empty(),
        "exact mode with proven stretches against probe by probe:\n{}",
        proof_failures.join("\n")
    );
}

/// Why two checks' findings differ (none: they agree): the same lines with the same kinds,
/// parts and severities, and per line, kind and parts the same greatest depth within
/// `depth_tol`. How many contacts one line makes may differ: probing in contact strides by half
/// the depth, so a separation shorter than the stride may fall between probes in one measure
/// and on a probe in the other.
fn same_findings(a: &[Finding], b: &[Finding], depth_tol: f64) -> Option<String> {
    type Facts = (u32, Kind, Vec<String>, Severity);
    let deepest = |v: &[Finding]| {
        let mut m: BTreeMap<Facts, f64> = BTreeMap::new();
        for f in v {
            let e = m.entry((f.line, f.kind, f.objects.clone(), f.severity)).or_insert(0.0);
            *e = e.max(f.depth_mm.unwrap_or(0.0));
        }
        m
    };
    let (x, y) = (deepest(a), deepest(b));
    if x.keys().ne(y.keys()) {
        let only = |p: &BTreeMap<Facts, f64>, q: &BTreeMap<Facts, f64>| {
            p.keys().filter(|k| !q.contains_key(*k)).cloned().collect::<Vec<_>>()
        };
        return Some(format!(
            "only proven: {:?}; only probed: {:?}",
            only(&x, &y),
            only(&y, &x)
        ));
    }
    x.iter()
        .zip(&y)
        .find(|((_, dx), (_, dy))| (*dx - *dy).abs() > depth_tol + 1e-9)
        .map(|((k, dx), (_, dy))| format!("line {}: depth {dx} against {dy}", k.0))
}
