//! Seeded crashes (mutation testing, `docs/mutation.md`): every clean (program, machine) pair of
//! [`pairs`] is mutated at known lines into programs that crash there by construction
//! (`common/mutate.rs` says how each kind is proved), and each mutant is checked in step and in
//! exact mode. A mutant is detected when a finding of severity error is reported at its mutated
//! line. The table per kind is printed (`cargo test --test all mutation:: -- --nocapture`).

use crate::corpus_job;
use crate::mutate;

use latheguard::finding::{Finding, Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use mutate::{MutKind, Mutant};
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Mutants of one kind taken from one pair, at most (evenly spaced over the program's lines):
/// keeps the test's run time small. `LATHEGUARD_MUTANTS_PER_KIND=N` (0: all) for a full run.
const PER_KIND_PER_PAIR: usize = 12;

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

/// Where a pair comes from: this repository's programs and cases, or a corpus program with its
/// job (`tests/corpus-jobs/index.toml`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Source {
    Repository,
    Corpus,
}

impl Source {
    fn name(self) -> &'static str {
        match self {
            Source::Repository => "repository",
            Source::Corpus => "corpus",
        }
    }
}

/// One clean program and the machine it is written for.
struct Pair {
    program: PathBuf,
    machine: Machine,
    source: Source,
    /// Lines the index lists as crashing in the unmutated program (real crashes, checker false
    /// positives, not expressible, unexplained): their findings are allowed, and only mutants
    /// after the last of them are judged.
    listed: BTreeSet<u32>,
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
            // A folder with its own latheguard.toml is written for another machine.
            if !p.join("latheguard.toml").exists() {
                walk(&p, out);
            }
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "ngc")) {
            out.push(p);
        }
    }
}

/// The clean pairs: every program of `programs/` and `tests/cases/` whose `.expected` file is
/// empty (no finding) and that has no job beside it, on the machine it names, plus
/// [`EXTRA_PAIRS`]. The corpus pairs (program
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
        // A case with a job beside it (`tests/cases/ops`: the part turned round at an M00) is
        // clean only with its job, and the mutator's proofs take the machine's own stock as it
        // stands: not a pair.
        if f.with_extension("job.toml").exists() {
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
            out.push(Pair {
                program: f,
                machine,
                source: Source::Repository,
                listed: BTreeSet::new(),
            });
        }
    }
    for (program, machine) in EXTRA_PAIRS {
        out.push(Pair {
            program: root().join(program),
            machine: load_machine(machine),
            source: Source::Repository,
            listed: BTreeSet::new(),
        });
    }
    out
}

fn shared() -> PathBuf {
    root().join("../shared")
}

/// The corpus pairs: every program `tests/corpus-jobs/index.toml` lists, from `../shared`, on its
/// machine with its job applied (`common/corpus_job.rs`). `None` without `../shared`. A job that
/// does not apply (the jobs change outside this test) skips its program with a message.
fn corpus_pairs() -> Option<Vec<Pair>> {
    if !shared().join("corpus").is_dir() {
        return None;
    }
    let text = std::fs::read_to_string(root().join("tests/corpus-jobs/index.toml")).unwrap();
    let t: toml::Table = text.parse().unwrap_or_else(|e| panic!("index.toml: {e}"));
    let mut out = Vec::new();
    for e in t.get("program").and_then(|v| v.as_array()).into_iter().flatten() {
        let s = |k: &str| e.get(k).and_then(|v| v.as_str()).unwrap_or_default().to_string();
        let (path, machine, job) = (s("path"), s("machine"), s("job"));
        let mut listed = BTreeSet::new();
        for (_, v) in e.as_table().into_iter().flatten() {
            for c in v.as_array().into_iter().flatten() {
                if let Some(l) = c.get("line").and_then(|v| v.as_integer()) {
                    listed.insert(l as u32);
                }
                // One entry may list several lines of one argument.
                for l in c.get("lines").and_then(|v| v.as_array()).into_iter().flatten() {
                    listed.extend(l.as_integer().map(|l| l as u32));
                }
            }
        }
        let program = shared().join(&path);
        let m = std::fs::read_to_string(root().join(&machine))
            .map_err(|x| x.to_string())
            .and_then(|mt| corpus_job::apply(&mt, &machine, &root().join("tests/corpus-jobs").join(&job)));
        match m {
            Ok(machine) if program.is_file() => out.push(Pair {
                program,
                machine,
                source: Source::Corpus,
                listed,
            }),
            Ok(_) => println!("seeded crashes: skipped {path}: no such program"),
            Err(x) => println!("seeded crashes: skipped {path}: its job does not apply: {x}"),
        }
    }
    Some(out)
}

/// More clean pairs, (program, machine) relative to the repository (or a machine's name).
const EXTRA_PAIRS: &[(&str, &str)] = &[];

fn findings(src: &[u8], machine: &Machine, mode: Mode) -> Vec<Finding> {
    let s = Settings {
        mode,
        ..Settings::default()
    };
    pipeline::check(src, machine, &s).findings
}

/// A finding that says the machine crashes: an error of a crash kind (a collision, a rapid into
/// the stock, a cut with the spindle stopped, an overtravel).
fn is_crash(f: &Finding) -> bool {
    f.severity == Severity::Error
        && matches!(
            f.kind,
            Kind::Collision | Kind::RapidIntoStock | Kind::SpindleStopped | Kind::Overtravel
        )
}

/// The mutant (text `src`) is reported: a crash finding at its line (or a line of `also`).
fn detected(m: &Mutant, src: &[u8], machine: &Machine, mode: Mode) -> bool {
    let machine = m.machine.as_ref().unwrap_or(machine);
    findings(src, machine, mode)
        .iter()
        .any(|f| is_crash(f) && (f.line == m.line || m.also.contains(&f.line)))
}

/// Whether one of the unmutated program's crash episodes (`(line, end_line)`) is still in
/// progress when `line` begins: it began on an earlier line and ends on this one or later. A
/// contact a mutant of such a line makes begins while that crash goes on, so the checker rightly
/// reports it as the crash's follow-on (a warning, `episodes::mark_follow_ons`), not as a crash
/// of its own: such a line proves nothing and is not mutated.
fn crash_in_progress(line: u32, episodes: &[(u32, u32)]) -> bool {
    episodes.iter().any(|&(start, end)| start < line && line <= end)
}

fn rel(p: &Path) -> String {
    p.strip_prefix(root()).unwrap_or(p).display().to_string()
}

#[test]
fn seeded_crashes_are_reported_at_their_line_in_both_modes_and_clean_programs_stay_clean() {
    let t0 = Instant::now();
    let mut pairs = pairs();
    let with_corpus = match corpus_pairs() {
        Some(c) => {
            pairs.extend(c);
            true
        }
        None => {
            println!(
                "seeded crashes: corpus pairs skipped: no corpus at {}",
                shared().display()
            );
            false
        }
    };
    let mut flagged = Vec::new();
    let mut skipped = Vec::new();
    // Per (kind, source): mutants, detected in step, in exact, missed (file:line mode).
    type Row = (usize, usize, usize, Vec<String>);
    let mut table: BTreeMap<(MutKind, Source), Row> = BTreeMap::new();
    let (mut with_mutants, mut available, mut dropped) = (0, 0, 0);
    let per_kind = per_kind();
    let verbose = std::env::var_os("LATHEGUARD_MUTANTS_VERBOSE").is_some();
    // Exploring: `LATHEGUARD_MUTANTS_ONLY=substring` runs only the pairs whose program path holds
    // it (the bars on the totals are not asserted then).
    let only = std::env::var("LATHEGUARD_MUTANTS_ONLY").ok();
    if let Some(o) = &only {
        pairs.retain(|p| p.program.display().to_string().contains(o.as_str()));
    }
    for pair in &pairs {
        let tp = Instant::now();
        let src = std::fs::read(&pair.program).unwrap();
        // The unmutated program: no error at all (repository), no crash finding but at the
        // index's lines (corpus). Lines with an error of any kind are not mutated.
        let mut erring = BTreeSet::new();
        let mut episodes = Vec::new();
        let mut clean = true;
        for mode in [Mode::Step, Mode::Exact] {
            for f in findings(&src, &pair.machine, mode) {
                if f.severity == Severity::Error {
                    erring.insert(f.line);
                }
                if is_crash(&f) {
                    episodes.push((f.line, f.end_line));
                }
                let bad = match pair.source {
                    Source::Repository => f.severity == Severity::Error,
                    Source::Corpus => is_crash(&f) && !pair.listed.contains(&f.line),
                };
                if bad && clean {
                    clean = false;
                    let what = format!(
                        "{}:{} ({mode:?}): {} {}",
                        rel(&pair.program),
                        f.line,
                        f.kind.name(),
                        f.message
                    );
                    match pair.source {
                        Source::Repository => flagged.push(what),
                        Source::Corpus => skipped.push(what),
                    }
                }
            }
        }
        if !clean {
            continue;
        }
        let last_listed = pair.listed.iter().next_back().copied().unwrap_or(0);
        let set = mutate::mutants(&src, &pair.machine);
        let all: Vec<&Mutant> = set
            .list
            .iter()
            .filter(|m| {
                m.original_line > last_listed
                    && !erring.contains(&m.original_line)
                    && !crash_in_progress(m.original_line, &episodes)
            })
            .collect();
        if !all.is_empty() {
            with_mutants += 1;
        }
        available += all.len();
        for kind in MutKind::ALL {
            let of: Vec<&Mutant> = all.iter().copied().filter(|m| m.kind == kind).collect();
            for m in mutate::sample(&of, per_kind) {
                let Some(msrc) = set.realise(m) else {
                    dropped += 1;
                    continue;
                };
                let row = table.entry((kind, pair.source)).or_default();
                row.0 += 1;
                for mode in [Mode::Step, Mode::Exact] {
                    if detected(m, &msrc, &pair.machine, mode) {
                        if mode == Mode::Step {
                            row.1 += 1
                        } else {
                            row.2 += 1
                        }
                    } else {
                        row.3
                            .push(format!("{}:{} ({mode:?})", rel(&pair.program), m.original_line));
                        if verbose {
                            let text = String::from_utf8_lossy(&msrc);
                            let line = text.split('\n').nth(m.line as usize - 1).unwrap_or("");
                            eprintln!("  missed {:?} at line {} ({mode:?}): {line}", m.kind, m.line);
                            let mm = m.machine.as_ref().unwrap_or(&pair.machine);
                            for f in findings(&msrc, mm, mode) {
                                eprintln!(
                                    "    {}-{} {:?} {} {} (t {:?}-{:?}, depth {:?}, follows {:?})",
                                    f.line,
                                    f.end_line,
                                    f.severity,
                                    f.kind.name(),
                                    f.message,
                                    f.time_s,
                                    f.end_time_s,
                                    f.depth_mm,
                                    f.follow_on.as_ref().map(|p| p.line)
                                );
                            }
                        }
                    }
                }
            }
        }
        if verbose {
            eprintln!(
                "  {}: {} mutants, {:.1} s",
                rel(&pair.program),
                all.len(),
                tp.elapsed().as_secs_f64()
            );
        }
    }
    let cap = if per_kind == usize::MAX {
        "all".to_string()
    } else {
        format!("at most {per_kind}")
    };
    println!(
        "seeded crashes: {} clean pairs ({} repository, {} corpus), {with_mutants} with mutants; {available} mutants found, {cap} per kind and pair made, {dropped} of those dropped (reading back did not prove them)",
        pairs.len(),
        pairs.iter().filter(|p| p.source == Source::Repository).count(),
        pairs.iter().filter(|p| p.source == Source::Corpus).count()
    );
    for s in &skipped {
        println!("seeded crashes: corpus pair skipped, not clean unmutated: {s}");
    }
    println!(
        "{:<26} {:<11} {:>7} {:>8} {:>8}  missed",
        "kind", "source", "mutants", "step", "exact"
    );
    let mut per_kind_total: BTreeMap<MutKind, (usize, usize, usize)> = BTreeMap::new();
    let mut per_source: BTreeMap<Source, (usize, usize, usize)> = BTreeMap::new();
    for ((kind, source), (m, s, e, missed)) in &table {
        println!(
            "{:<26} {:<11} {m:>7} {s:>8} {e:>8}  {}",
            kind.name(),
            source.name(),
            missed.join(", ")
        );
        for t in [
            per_kind_total.entry(*kind).or_default(),
            per_source.entry(*source).or_default(),
        ] {
            t.0 += m;
            t.1 += s;
            t.2 += e;
        }
    }
    println!("per kind:");
    for (kind, (m, s, e)) in &per_kind_total {
        println!("{:<26} {:<11} {m:>7} {s:>8} {e:>8}", kind.name(), "all");
    }
    println!("per source:");
    for (source, (m, s, e)) in &per_source {
        println!("{:<26} {:<11} {m:>7} {s:>8} {e:>8}", "all", source.name());
    }
    let (n, step, exact) = per_source
        .values()
        .fold((0, 0, 0), |a, b| (a.0 + b.0, a.1 + b.1, a.2 + b.2));
    println!("{:<26} {:<11} {n:>7} {step:>8} {exact:>8}", "all", "all");
    println!("seeded crashes: {:.1} s", t0.elapsed().as_secs_f64());
    assert!(flagged.is_empty(), "clean programs flagged: {flagged:?}");
    if only.is_some() {
        return;
    }
    assert!(n >= 40, "too few mutants: {n}");
    // The bar: with the corpus pairs, at least 500 mutants at the default sampling.
    if with_corpus && per_kind == PER_KIND_PER_PAIR {
        assert!(n >= 500, "too few mutants with the corpus: {n}");
    }
    for kind in MutKind::ALL {
        assert!(per_kind_total.contains_key(&kind), "no mutant of kind {}", kind.name());
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
        let set = mutate::mutants(&src, &pair.machine);
        let text = set.text().to_string();
        let orig: Vec<&str> = text.split('\n').collect();
        for m in &set.list {
            let Some(msrc) = set.realise(m) else { continue };
            let mt = String::from_utf8(msrc).unwrap();
            let new: Vec<&str> = mt.split('\n').collect();
            let l = m.original_line as usize - 1;
            if m.kind == MutKind::LongToolAtIndex {
                // A machine mutation: the program is kept, the machine differs.
                assert_eq!(mt, text);
                assert!(m.machine.as_ref().is_some_and(|mm| *mm != pair.machine));
            } else if m.kind == MutKind::SpindleStopBeforeCut {
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

#[test]
fn a_line_reached_while_an_unmutated_crash_goes_on_is_not_mutated() {
    // Test_Gewinde_innen.ngc: T09's bar enters the bore wall at line 131 and leaves it during the
    // G0 Z6 of line 133: line 133 begins inside that crash, line 134 after it.
    let episodes = [(81, 83), (131, 133)];
    assert!(crash_in_progress(133, &episodes));
    assert!(crash_in_progress(132, &episodes));
    assert!(
        !crash_in_progress(131, &episodes),
        "the crash's own line is an erring line instead"
    );
    assert!(!crash_in_progress(134, &episodes));
    assert!(!crash_in_progress(100, &episodes));
    // An episode of one line leaves every other line free.
    assert!(!crash_in_progress(41, &[(40, 40)]));
}

mod oracle {
    use super::mutate;
    use proptest::prelude::*;

    proptest! {
        /// The long tool's clearance proof rests on `min_radius` never overstating how close the
        /// standing tool comes to the spindle axis.
        #[test]
        fn min_radius_is_never_above_the_distance_of_any_point_it_bounds(
            a0 in -300.0..300.0f64, wa in 0.0..100.0f64,
            d0 in -300.0..300.0f64, wd in 0.0..100.0f64,
            th in 0.0..std::f64::consts::TAU, u in 0.0..=1.0f64, v in 0.0..=1.0f64,
        ) {
            let (s, c) = th.sin_cos();
            let r = mutate::min_radius(a0, a0 + wa, d0, d0 + wd, c, s);
            let (a, d) = (a0 + wa * u, d0 + wd * v);
            let at = ((a + c * d).powi(2) + (s * d).powi(2)).sqrt();
            prop_assert!(r <= at + 1e-6, "bound {r} above the distance {at} at a={a} d={d}");
            prop_assert!(r >= 0.0);
        }
    }

    #[test]
    fn min_radius_is_reached_where_the_turret_axis_passes_closest() {
        // Angle 0: the points lie on the x axis at a + d; the box holds a + d = 5 at best.
        assert!((mutate::min_radius(100.0, 120.0, -95.0, -80.0, 1.0, 0.0) - 5.0).abs() < 1e-6);
        // Angle 90°: the points stand at (a, d): the nearest is (100, 0) when d may be 0.
        assert!((mutate::min_radius(100.0, 120.0, -10.0, 10.0, 0.0, 1.0) - 100.0).abs() < 1e-6);
    }
}
