//! Setups for the corpus: every Fanuc/Haas and LinuxCNC lathe program of `../shared/corpus` and
//! `../shared/corpus-extra` has a job under `tests/corpus-jobs/` that describes the lathe and the
//! job it was written for, and `tests/corpus-jobs/index.toml` maps each program to its machine,
//! its job and the lines of its error findings, each classified with its argument: a real crash
//! (`real_crashes`), an error the control itself would raise (`real_errors`), latheguard's mistake
//! (`checker_false_positives`), a machine or job that does not match the program yet
//! (`setup_false_alarms`), a setup the formats cannot say (`not_expressible`) or not yet decided
//! (`unexplained`). Checked with its job (step mode, default settings), a program gives no
//! error finding of any kind (crash kinds, `program`, `unsupported`, `syntax`) but on those lines,
//! and each listed line is still reported (a stale entry fails): a `real_crashes` line as a crash
//! finding, a `real_errors` line as an error of another kind. One entry may cover several lines
//! of one argument (`lines = [36, 61, 63]` instead of `line = 36`).
//! The test prints error findings by kind per program with the shipped machine as
//! `tests/corpus.rs` picks it ("before") against the job ("after"), and the count of listed
//! lines per category.
//!
//! The corpora are kept out of this repository; without `../shared` the test prints "skipped".
//!
//! Exploring: `LG_CORPUS_ONLY=substring` checks only matching programs and prints each finding of
//! a crash kind (grazes and follow-ons too, with their severity) and each other error;
//! `LG_CORPUS_DUMP=dir` also writes there, per program, the `latheguard check --machine … --job …`
//! command line that checks it as this test does (add `--svg …` or `--format json`).

use crate::corpus_job;
use crate::files;

use latheguard::finding::{Finding, Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn shared() -> PathBuf {
    files::shared()
}

fn jobs_dir() -> PathBuf {
    root().join("tests/corpus-jobs")
}

/// The crash kinds: a finding of one of these says the program would crash when it is an error
/// — not a follow-on warning, and not a graze (a contact shallower than `min_depth`, reported as
/// a warning).
const CRASH_KINDS: [Kind; 4] = [
    Kind::Collision,
    Kind::RapidIntoStock,
    Kind::SpindleStopped,
    Kind::Overtravel,
];

/// Every kind an error finding can have, as the printed table's columns: the crash kinds, then
/// the errors of reading and running the program.
const ERROR_KINDS: [Kind; 7] = [
    Kind::Collision,
    Kind::RapidIntoStock,
    Kind::SpindleStopped,
    Kind::Overtravel,
    Kind::Program,
    Kind::Unsupported,
    Kind::Syntax,
];

/// A finding the index must classify: any finding of severity error.
fn is_error(f: &Finding) -> bool {
    f.severity == Severity::Error
}

/// `corpus-extra/SOURCES.md`: relative path → (class, dialect) columns.
fn extra_sources() -> BTreeMap<String, (String, String)> {
    let text = std::fs::read_to_string(shared().join("corpus-extra/SOURCES.md")).unwrap_or_default();
    let mut out = BTreeMap::new();
    for line in text.lines() {
        let cols: Vec<&str> = line.split('|').map(str::trim).collect();
        // | corpus path | class | repository | path | commit | licence | dialect | …
        if cols.len() > 7 && cols[1].starts_with('`') {
            out.insert(
                cols[1].trim_matches('`').to_string(),
                (cols[2].to_string(), cols[7].to_string()),
            );
        }
    }
    out
}

/// The programs this test covers, as `corpus/…` and `corpus-extra/…` paths: the Fanuc/Haas and
/// LinuxCNC lathe programs. Left aside: `corpus`'s other dialects (Okuma, Philips), the
/// nanoELS/lathecode programs and LibLathe's generic output; `corpus-extra`'s turn-mill files
/// and its programs for other controls (GRBL, Jones & Lamson, Okuma, Mazak, Mitsubishi, G&L).
fn targets() -> Vec<String> {
    let mut out = Vec::new();
    let mut files = Vec::new();
    files::walk(&shared().join("corpus"), &files::is_program, &mut files);
    for f in files {
        let rel = f
            .strip_prefix(shared().join("corpus"))
            .unwrap()
            .to_string_lossy()
            .to_string();
        let aside = ["gcodeworkshop-examples/other-dialects/", "lathecode/", "liblathe/"];
        if !aside.iter().any(|a| rel.starts_with(a)) {
            out.push(format!("corpus/{rel}"));
        }
    }
    for (rel, (class, dialect)) in extra_sources() {
        let d = dialect.to_lowercase();
        if class == "lathe" && (d.starts_with("fanuc") || d.starts_with("linuxcnc") || d.starts_with("haas")) {
            out.push(format!("corpus-extra/{rel}"));
        }
    }
    out.sort();
    out
}

fn load_machine(path: &Path) -> Machine {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    machine::from_toml(&text, &path.display().to_string()).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The shipped machine `tests/corpus.rs` checks a program on.
fn shipped_machine(program: &str, extra: &BTreeMap<String, (String, String)>) -> Machine {
    let lcnc = || load_machine(&root().join("machines/linuxcnc-small-lathe.toml"));
    if let Some(rel) = program.strip_prefix("corpus-extra/") {
        if let Some((_, d)) = extra.get(rel) {
            let d = d.to_lowercase();
            return if d.contains("linuxcnc") || d.contains("grbl") {
                lcnc()
            } else {
                Machine::builtin()
            };
        }
    }
    if program.to_lowercase().ends_with(".nc") {
        Machine::builtin()
    } else {
        lcnc()
    }
}

struct Entry {
    program: String,
    machine: String,
    job: String,
    /// Per category of [`CATEGORIES`]: line → the evidence.
    lines: BTreeMap<&'static str, BTreeMap<u32, String>>,
}

/// Why an error finding of a program checked with its job may stand, as index.toml's keys; each
/// line listed must still be reported (a stale entry fails the test):
/// - `real_crashes`: the program itself would crash there (a crash kind: collision,
///   rapid_into_stock, spindle_stopped, overtravel);
/// - `real_errors`: a `program`, `unsupported` or `syntax` error the control itself would raise
///   there (its manual, or for LinuxCNC what LinuxCNC reports), argued without choosing a
///   dialect or an invented setup that makes it one;
/// - `checker_false_positives`: latheguard's mistake, not the program's (with a reproducer;
///   remove the entry when the checker is fixed);
/// - `setup_false_alarms`: the program is right, the checked machine or job does not match what
///   it needs (a turret with fewer stations than it calls), and the fix is not made yet;
/// - `not_expressible`: the lathe or job does what the program needs, but neither the machine
///   file nor the job format can say so yet (a spindle run by hand, tools changed by hand);
/// - `unexplained`: looked at, not yet decided; the entry says what was tried.
const CATEGORIES: [&str; 6] = [
    "real_crashes",
    "real_errors",
    "checker_false_positives",
    "setup_false_alarms",
    "not_expressible",
    "unexplained",
];

/// Whether a category may hold an error finding of this kind: `real_crashes` only the crash
/// kinds, `real_errors` only the others, the rest either.
fn category_fits(cat: &str, kind: Kind) -> bool {
    match cat {
        "real_crashes" => CRASH_KINDS.contains(&kind),
        "real_errors" => !CRASH_KINDS.contains(&kind),
        _ => true,
    }
}

fn index() -> Vec<Entry> {
    let path = jobs_dir().join("index.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let t: toml::Table = text.parse().unwrap_or_else(|e| panic!("index.toml: {e}"));
    let list = t
        .get("program")
        .and_then(|v| v.as_array())
        .expect("index.toml: [[program]] entries");
    let mut out = Vec::new();
    for e in list {
        let s = |k: &str| {
            e.get(k)
                .and_then(|v| v.as_str())
                .unwrap_or_else(|| panic!("index.toml: entry without `{k}`: {e:?}"))
                .to_string()
        };
        let lines = |key: &str| {
            let mut m = BTreeMap::new();
            for c in e.get(key).and_then(|v| v.as_array()).into_iter().flatten() {
                let one = c.get("line").and_then(|v| v.as_integer());
                let many: Vec<i64> = c
                    .get("lines")
                    .and_then(|v| v.as_array())
                    .map(|a| a.iter().map(|v| v.as_integer().expect("lines: integers")).collect())
                    .unwrap_or_default();
                assert!(
                    one.is_some() == many.is_empty(),
                    "index.toml: {}: a {key} entry needs `line = N` or `lines = [N, …]` (one of them): {c:?}",
                    s("path")
                );
                for k in c.as_table().unwrap().keys() {
                    assert!(
                        ["line", "lines", "why"].contains(&k.as_str()),
                        "index.toml: {}: {key}: unknown key `{k}`",
                        s("path")
                    );
                }
                let why = c.get("why").and_then(|v| v.as_str()).unwrap_or_default();
                for line in one.into_iter().chain(many) {
                    let line = line as u32;
                    assert!(
                        why.len() > 20,
                        "index.toml: {}: {key} line {line} needs its evidence in `why`",
                        s("path")
                    );
                    let twice = m.insert(line, why.to_string()).is_some();
                    assert!(!twice, "index.toml: {}: {key} lists line {line} twice", s("path"));
                }
            }
            m
        };
        for k in e.as_table().unwrap().keys() {
            let known = ["path", "machine", "job"].contains(&k.as_str()) || CATEGORIES.contains(&k.as_str());
            assert!(known, "index.toml: {}: unknown key `{k}`", s("path"));
        }
        out.push(Entry {
            program: s("path"),
            machine: s("machine"),
            job: s("job"),
            lines: CATEGORIES.iter().map(|c| (*c, lines(c))).collect(),
        });
    }
    out
}

fn counts(findings: &[Finding]) -> BTreeMap<Kind, usize> {
    let mut m = BTreeMap::new();
    for f in findings.iter().filter(|f| is_error(f)) {
        *m.entry(f.kind).or_default() += 1;
    }
    m
}

fn row(c: &BTreeMap<Kind, usize>) -> String {
    ERROR_KINDS
        .iter()
        .map(|k| format!("{:>5}", c.get(k).copied().unwrap_or(0)))
        .collect::<Vec<_>>()
        .join("")
}

#[test]
fn every_corpus_program_checked_with_its_job_errs_only_where_its_index_says() {
    if !shared().join("corpus").is_dir() {
        println!("corpus_setups: skipped: no corpus at {}", shared().display());
        eprintln!("corpus_setups: skipped: no corpus at {}", shared().display());
        return;
    }
    let entries = index();
    let only = std::env::var("LG_CORPUS_ONLY").ok();
    let dump = std::env::var("LG_CORPUS_DUMP").ok().map(PathBuf::from);
    let extra = extra_sources();

    // Every target has exactly one entry, and every entry is a target.
    let listed: BTreeSet<&str> = entries.iter().map(|e| e.program.as_str()).collect();
    assert_eq!(listed.len(), entries.len(), "index.toml lists a program twice");
    let targets = targets();
    let missing: Vec<&String> = targets.iter().filter(|t| !listed.contains(t.as_str())).collect();
    assert!(missing.is_empty(), "programs without a job in index.toml: {missing:?}");
    let stray: Vec<&&str> = listed.iter().filter(|p| !targets.iter().any(|t| t == *p)).collect();
    assert!(
        stray.is_empty(),
        "index.toml entries that are not target programs: {stray:?}"
    );
    assert!(
        targets.len() >= 60,
        "the corpora look incomplete: {} target programs",
        targets.len()
    );

    let mut failures = Vec::new();
    let (mut before_total, mut after_total) = (BTreeMap::new(), BTreeMap::new());
    let mut table = String::new();
    let mut red_before = 0;
    let mut listed_lines: BTreeMap<&str, usize> = BTreeMap::new();
    let mut classified: BTreeMap<(&str, Kind), usize> = BTreeMap::new();
    for e in &entries {
        if only.as_deref().is_some_and(|o| !e.program.contains(o)) {
            continue;
        }
        let src = std::fs::read(shared().join(&e.program)).unwrap();
        let shipped = shipped_machine(&e.program, &extra);
        let before = counts(&pipeline::check(&src, &shipped, &Settings::default()).findings);

        let machine_path = root().join(&e.machine);
        let machine_text = std::fs::read_to_string(&machine_path).unwrap_or_else(|x| panic!("{}: {x}", e.machine));
        let job_path = jobs_dir().join(&e.job);
        if let Some(d) = &dump {
            // One command line per program: the same machine and job through the binary.
            std::fs::create_dir_all(d).unwrap();
            let name = e.program.replace('/', "__") + ".sh";
            let cmd = format!(
                "latheguard check --no-config --machine {} --job {} {} \"$@\"\n",
                machine_path.display(),
                job_path.display(),
                shared().join(&e.program).display()
            );
            std::fs::write(d.join(name), cmd).unwrap();
        }
        let m = corpus_job::apply(&machine_text, &e.machine, &job_path)
            .unwrap_or_else(|x| panic!("{}: job {}: {x}", e.program, e.job));
        let findings = pipeline::check(&src, &m, &Settings::default()).findings;
        let after = counts(&findings);

        // Each listed line must still be reported with an error its category can hold.
        let reported: BTreeSet<(u32, bool)> = findings
            .iter()
            .filter(|f| is_error(f))
            .map(|f| (f.line, CRASH_KINDS.contains(&f.kind)))
            .collect();
        for f in &findings {
            if only.is_some() && (CRASH_KINDS.contains(&f.kind) || is_error(f)) {
                println!(
                    "  {}:{}-{}: {} {:?} {:?} depth {:?} at X{:?} Z{:?} t={:?}: {}",
                    e.program,
                    f.line,
                    f.end_line,
                    f.kind.name(),
                    f.severity,
                    f.objects,
                    f.depth_mm,
                    f.x,
                    f.z,
                    f.time_s,
                    f.message
                );
            }
            if !is_error(f) {
                continue;
            }
            let cat = CATEGORIES
                .iter()
                .find(|c| category_fits(c, f.kind) && e.lines[*c].contains_key(&f.line));
            match cat {
                Some(c) => *classified.entry((*c, f.kind)).or_insert(0) += 1,
                None => failures.push(format!(
                    "{}:{}: {} {:?}: {}",
                    e.program,
                    f.line,
                    f.kind.name(),
                    f.objects,
                    f.message
                )),
            }
        }
        for (cat, m) in &e.lines {
            for line in m.keys() {
                let found = match *cat {
                    "real_crashes" => reported.contains(&(*line, true)),
                    "real_errors" => reported.contains(&(*line, false)),
                    _ => reported.contains(&(*line, true)) || reported.contains(&(*line, false)),
                };
                if !found {
                    failures.push(format!(
                        "{}:{line}: listed in index.toml's {cat} but no error of its kind is reported there",
                        e.program
                    ));
                }
            }
            *listed_lines.entry(*cat).or_insert(0) += m.len();
        }
        if !before.is_empty() {
            red_before += 1;
        }
        for (k, n) in &before {
            *before_total.entry(*k).or_insert(0) += n;
        }
        for (k, n) in &after {
            *after_total.entry(*k).or_insert(0) += n;
        }
        table += &format!("{:<78} {}   {}\n", e.program, row(&before), row(&after));
    }
    let head = "coll rapid spin  over  prog unsup  synt";
    println!(
        "{:<78} {:>34}   {:>34}\n{:<78} {head}   {head}",
        "error findings by kind", "shipped machine", "with the job", "program",
    );
    print!("{table}");
    println!("{:<78} {}   {}", "TOTAL", row(&before_total), row(&after_total));
    println!("programs with an error finding on the shipped machine: {red_before}");
    for (cat, n) in &listed_lines {
        println!("lines listed as {cat}: {n}");
    }
    for ((cat, kind), n) in &classified {
        println!("error findings with the job, {cat}, {}: {n}", kind.name());
    }
    assert!(
        failures.is_empty(),
        "error findings not classified in index.toml (or listed lines no longer reported):\n{}",
        failures.join("\n")
    );
}
