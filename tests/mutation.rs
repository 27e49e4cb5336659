//! Seeded crashes (mutation testing, `docs/mutation.md`): every clean (program, machine) pair of
//! [`pairs`] is mutated at known lines into programs that crash there by construction
//! (`common/mutate.rs` says how each kind is proved), and each mutant is checked in step and in
//! exact mode. A mutant is detected when a finding of severity error is reported at its mutated
//! line. The table per kind is printed (`cargo test --test mutation -- --nocapture`).

#[path = "common/mutate.rs"]
mod mutate;

use latheguard::finding::Severity;
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use mutate::{MutKind, Mutant};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Mutants of one kind taken from one pair, at most (evenly spaced over the program's lines):
/// keeps the test's run time small. `LATHEGUARD_MUTANTS_PER_KIND=N` (0: all) for a full run.
const PER_KIND_PER_PAIR: usize = 3;

fn per_kind() -> usize {
    match std::env::var("LATHEGUARD_MUTANTS_PER_KIND")
        .ok()
        .and_then(|v| v.parse().ok())
    {
        Some(0) => usize::MAX,
        Some(n) => n,
        None => PER_KIND_PER_PAIR,
    }
}

/// Programs whose `.expected` is empty (their case pins step mode at 1 ms) but which exact mode
/// flags: not clean pairs, so not mutated. Each with the reason.
const NOT_CLEAN: &[(&str, &str)] = &[(
    "tests/cases/stock/reenter_final_pose.nc",
    "exact mode (and step mode at dt 0.01) reports a 0.167 mm rapid_into_stock at line 12: the dogleg \
     return leaves the path the pull-off swept; step mode at 1 ms steps over it",
)];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// One clean program and the machine it is written for.
struct Pair {
    program: PathBuf,
    machine: Machine,
}

/// A machine by the name a case uses (`machines/NAME.toml`, else `tests/machines/NAME.toml`), or
/// a path.
fn load_machine(name: &str) -> Machine {
    let mut path = root().join("machines").join(format!("{name}.toml"));
    if !path.exists() {
        path = root().join("tests/machines").join(format!("{name}.toml"));
    }
    if !path.exists() {
        path = root().join(name);
    }
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    machine::from_toml(&text, &path.display().to_string()).unwrap()
}

/// The machine a data-driven case names on its first line (`(test-case: machine=NAME …)`),
/// `None` when it sets anything but the machine (its expectations would not hold on defaults).
fn case_machine(src: &[u8]) -> Option<Machine> {
    let first = String::from_utf8_lossy(src.split(|&b| b == b'\n').next().unwrap_or(&[])).to_string();
    let Some(rest) = first.split("test-case:").nth(1) else {
        return Some(Machine::builtin());
    };
    let mut m = Machine::builtin();
    for kv in rest.trim_end_matches([')', '\r', ' ']).split_whitespace() {
        match kv.split_once('=') {
            Some(("machine", v)) => m = load_machine(v),
            Some(("modes", _)) => {}
            _ => return None,
        }
    }
    Some(m)
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, out);
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "ngc")) {
            out.push(p);
        }
    }
}

/// The clean pairs: every program of `programs/` and `tests/cases/` whose `.expected` file is
/// empty (no finding), on the machine it names, plus [`EXTRA_PAIRS`]. The corpus pairs (program
/// + job) join here as another list.
fn pairs() -> Vec<Pair> {
    let mut files = Vec::new();
    walk(&root().join("programs"), &mut files);
    walk(&root().join("tests/cases"), &mut files);
    files.sort();
    let mut out = Vec::new();
    for f in files {
        if NOT_CLEAN.iter().any(|(p, _)| f.ends_with(p)) {
            continue;
        }
        let expected = std::fs::read_to_string(f.with_extension("expected")).unwrap_or_default();
        if expected
            .lines()
            .any(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        {
            continue;
        }
        let src = std::fs::read(&f).unwrap();
        if let Some(machine) = case_machine(&src) {
            out.push(Pair { program: f, machine });
        }
    }
    for (program, machine) in EXTRA_PAIRS {
        out.push(Pair {
            program: root().join(program),
            machine: load_machine(machine),
        });
    }
    out
}

/// More clean pairs, (program, machine) relative to the repository (or a machine's name).
const EXTRA_PAIRS: &[(&str, &str)] = &[];

fn errors_at(src: &[u8], machine: &Machine, mode: Mode, line: u32) -> (bool, usize) {
    let s = Settings {
        mode,
        ..Settings::default()
    };
    let out = pipeline::check(src, machine, &s);
    let errs = out.findings.iter().filter(|f| f.severity == Severity::Error).count();
    (
        out.findings
            .iter()
            .any(|f| f.severity == Severity::Error && f.line == line),
        errs,
    )
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

#[test]
fn seeded_crashes_are_reported_at_their_line_in_both_modes_and_clean_programs_stay_clean() {
    let pairs = pairs();
    let mut flagged = Vec::new();
    // Per kind: mutants, detected in step, in exact, missed (file:line mode).
    let mut table: BTreeMap<MutKind, (usize, usize, usize, Vec<String>)> = BTreeMap::new();
    let (mut with_mutants, mut available) = (0, 0);
    let per_kind = per_kind();
    for pair in &pairs {
        let src = std::fs::read(&pair.program).unwrap();
        for mode in [Mode::Step, Mode::Exact] {
            let (_, errs) = errors_at(&src, &pair.machine, mode, 0);
            if errs > 0 {
                flagged.push(format!("{} ({mode:?})", rel(&pair.program)));
            }
        }
        let all = mutate::mutants(&src, &pair.machine);
        if !all.is_empty() {
            with_mutants += 1;
        }
        available += all.len();
        for kind in MutKind::ALL {
            let of: Vec<Mutant> = all.iter().filter(|m| m.kind == kind).cloned().collect();
            for m in mutate::sample(&of, per_kind) {
                let row = table.entry(kind).or_default();
                row.0 += 1;
                for (mode, slot) in [(Mode::Step, 1), (Mode::Exact, 2)] {
                    if errors_at(&m.src, &pair.machine, mode, m.line).0 {
                        if slot == 1 {
                            row.1 += 1
                        } else {
                            row.2 += 1
                        }
                    } else {
                        row.3
                            .push(format!("{}:{} ({mode:?})", rel(&pair.program), m.original_line));
                    }
                }
            }
        }
    }
    let (mut n, mut step, mut exact) = (0, 0, 0);
    let cap = if per_kind == usize::MAX {
        "all".to_string()
    } else {
        format!("at most {per_kind}")
    };
    println!(
        "seeded crashes: {} clean pairs, {with_mutants} with mutants; {available} mutants proved, {cap} per kind and pair checked",
        pairs.len()
    );
    println!("{:<26} {:>7} {:>8} {:>8}  missed", "kind", "mutants", "step", "exact");
    for (kind, (m, s, e, missed)) in &table {
        println!("{:<26} {m:>7} {s:>8} {e:>8}  {}", kind.name(), missed.join(", "));
        n += m;
        step += s;
        exact += e;
    }
    println!("{:<26} {n:>7} {step:>8} {exact:>8}", "all");
    assert!(flagged.is_empty(), "clean programs flagged: {flagged:?}");
    assert!(n >= 40, "too few mutants: {n}");
    for kind in MutKind::ALL {
        assert!(table.contains_key(&kind), "no mutant of kind {}", kind.name());
    }
    // At least 99 % detected in each mode.
    assert!(step * 100 >= n * 99, "step mode detected {step} of {n}");
    assert!(exact * 100 >= n * 99, "exact mode detected {exact} of {n}");
}

#[test]
fn every_mutant_differs_from_its_program_and_the_unmutated_lines_are_kept() {
    // The mutation itself: one line changed (or one line inserted), nothing else.
    let pairs = pairs();
    let mut seen = 0;
    for pair in pairs.iter().take(6) {
        let src = std::fs::read(&pair.program).unwrap();
        let text = String::from_utf8_lossy(&src).to_string();
        let orig: Vec<&str> = text.split('\n').collect();
        for m in mutate::mutants(&src, &pair.machine) {
            let mt = String::from_utf8(m.src.clone()).unwrap();
            let new: Vec<&str> = mt.split('\n').collect();
            let l = m.original_line as usize - 1;
            if m.kind == MutKind::SpindleStopBeforeCut {
                assert_eq!(new.len(), orig.len() + 1);
                assert_eq!(&new[..l], &orig[..l]);
                assert_eq!(&new[l + 1..], &orig[l..]);
            } else {
                assert_eq!(new.len(), orig.len());
                assert_ne!(new[l], orig[l]);
                assert!(new.iter().zip(&orig).enumerate().all(|(i, (a, b))| i == l || a == b));
            }
            seen += 1;
        }
    }
    assert!(seen > 0);
}
