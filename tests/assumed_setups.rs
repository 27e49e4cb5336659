//! The setup read from the program (docs/assume.md), against what it must not change and what it
//! is for:
//! - every program of `programs/` without a job of its own gives the same error findings with its
//!   setup read from it as with the built-in machine's setup it was written for (no crash hidden);
//! - on the corpus (`../shared`, skipped without it), each program with its job in
//!   `tests/corpus-jobs/` against the same program with no job, its setup read from it: how many
//!   give the same error lines (the figure docs/assume.md gives), and no program whose machine
//!   file alone already agreed with its job disagrees once its setup is read.

use crate::corpus_job;
use crate::files;
use latheguard::finding::{Finding, Severity};
use latheguard::job::{self, EffectiveJob};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn errors(findings: &[Finding]) -> BTreeSet<(u32, &'static str)> {
    findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .map(|f| (f.line, f.kind.name()))
        .collect()
}

fn error_lines(findings: &[Finding]) -> BTreeSet<u32> {
    errors(findings).into_iter().map(|e| e.0).collect()
}

/// The machine `src` is checked on with its setup read from it (the machine itself when
/// nothing is read or the reading does not fit).
fn assumed_machine(src: &[u8], name: &str, m: &Machine) -> Machine {
    match latheguard::assume::apply(src, name, m).machine {
        Some((am, _)) => am,
        None => m.clone(),
    }
}

/// On a dry-run machine (no stock on purpose: the program runs in the air), the setup read from
/// `src` but its bar: program zero where the part it would cut stands clear of the jaws, the
/// tools, tool numbers, tailstock and dialect it reads.
fn assumed_in_the_air(src: &[u8], name: &str, m: &Machine) -> Machine {
    let mut a = latheguard::assume::assume(src, name, m);
    a.layer.stock = None;
    job::apply(m, &EffectiveJob::merge([&a.layer])).unwrap_or_else(|_| m.clone())
}

#[test]
fn assumed_setups_hide_no_crash_program() {
    let m = Machine::builtin();
    assert!(m.assume_setup);
    let mut checked = 0;
    let mut entries: Vec<PathBuf> = std::fs::read_dir(root().join("programs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "nc"))
        .collect();
    entries.sort();
    for p in entries {
        // A program with a job of its own is not read for its setup.
        if p.with_extension("job.toml").exists() {
            continue;
        }
        let src = std::fs::read(&p).unwrap();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let plain = errors(&pipeline::check(&src, &m, &Settings::default()).findings);
        let read = errors(&pipeline::check(&src, &assumed_machine(&src, &name, &m), &Settings::default()).findings);
        assert_eq!(read, plain, "{name}: with the setup read from the program");
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} programs checked");
}

/// What the corpus comparison measured when it was last looked at: programs whose error lines
/// with the setup read from them equal those with their job (of 69).
const AGREE_AT_LEAST: usize = 63;

/// Programs the machine file alone gets right and the reading does not, each with what it reads
/// wrong (docs/assume.md, "Measured on the corpus").
const KNOWN_LOSSES: [(&str, &str); 0] = [];

/// The corpora's folder and `tests/corpus-jobs/index.toml`; `None` (printed as skipped) without
/// the corpora.
fn corpus_and_index() -> Option<(PathBuf, toml::Table)> {
    let shared = files::shared();
    if !shared.join("corpus").is_dir() {
        println!("assumed_setups: skipped: no corpus at {}", shared.display());
        return None;
    }
    let index = std::fs::read_to_string(root().join("tests/corpus-jobs/index.toml")).unwrap();
    Some((shared, toml::from_str(&index).unwrap()))
}

#[test]
fn corpus_verdicts_with_the_setup_read_from_the_program_against_their_jobs() {
    let Some((shared, index)) = corpus_and_index() else {
        return;
    };
    let programs = index["program"].as_array().unwrap();
    let (mut agree, mut total, mut regressions) = (0, 0, Vec::new());
    // Programs whose verdict (clean, or with errors) is the job's.
    let mut same_verdict = 0;
    let (mut with_job, mut machine_only, mut read) = (0, 0, 0);
    for p in programs {
        let path = p["path"].as_str().unwrap();
        let machine_rel = p["machine"].as_str().unwrap();
        let job = root().join("tests/corpus-jobs").join(p["job"].as_str().unwrap());
        let src = std::fs::read(shared.join(path)).unwrap();
        let text = std::fs::read_to_string(root().join(machine_rel)).unwrap();
        let jm = corpus_job::apply(&text, machine_rel, &job).unwrap();
        let want = error_lines(&pipeline::check(&src, &jm, &Settings::default()).findings);
        let mut m = machine::from_toml(&text, machine_rel).unwrap();
        let plain = error_lines(&pipeline::check(&src, &m, &Settings::default()).findings);
        // The machine's setup taken as an example, as the shipped machines' is. A dry-run
        // machine says "no stock" on purpose (the program runs in the air: its job would say
        // `stock = { none = true }`), so no bar is read for it, only the rest of its setup.
        m.assume_setup = true;
        let name = Path::new(path).file_name().unwrap().to_string_lossy().to_string();
        let read_machine = if machine_rel.contains("dry-run") {
            assumed_in_the_air(&src, &name, &m)
        } else {
            assumed_machine(&src, &name, &m)
        };
        let got = error_lines(&pipeline::check(&src, &read_machine, &Settings::default()).findings);
        total += 1;
        with_job += want.len();
        machine_only += plain.len();
        read += got.len();
        if got.is_empty() == want.is_empty() {
            same_verdict += 1;
        }
        if got == want {
            agree += 1;
        } else if plain == want {
            regressions.push(path.to_string());
        }
        println!(
            "{} {path}: job {} · machine file alone {} · read from the program {}; lost {:?}, new {:?}",
            if got == want { "same" } else { "DIFF" },
            want.len(),
            plain.len(),
            got.len(),
            want.difference(&got).collect::<Vec<_>>(),
            got.difference(&want).take(8).collect::<Vec<_>>()
        );
    }
    println!(
        "assumed_setups: {agree} of {total} programs give their job's error lines with the setup read from them, {same_verdict} its verdict; error lines: with jobs {with_job}, machine file alone {machine_only}, read from the program {read}"
    );
    let unknown: Vec<&String> = regressions
        .iter()
        .filter(|r| !KNOWN_LOSSES.iter().any(|k| k.0 == r.as_str()))
        .collect();
    assert!(
        unknown.is_empty(),
        "the reading loses what the machine file alone got right: {unknown:?}"
    );
    assert!(
        agree >= AGREE_AT_LEAST,
        "{agree} of {total} agree; {AGREE_AT_LEAST} did"
    );
}

/// The corpus programs with no job (every file under `../shared/corpus*` that
/// `tests/corpus-jobs/index.toml` does not list, but the reference outputs and tool tables) as a
/// new user's first run meets them: `latheguard check FILE` on the built-in machine, with the
/// setup read from the program and with `--no-assume`. Prints the error findings of each, before
/// and after (the table of docs/assume.md, "The corpus without jobs"), and fails when the reading
/// adds errors in all, or when either total moves from the figures written there.
#[test]
fn corpus_programs_without_a_job_before_and_after_the_reading() {
    let Some((shared, index)) = corpus_and_index() else {
        return;
    };
    let listed: BTreeSet<String> = index["program"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["path"].as_str().unwrap().to_string())
        .collect();
    let mut programs = Vec::new();
    for base in ["corpus", "corpus-extra"] {
        let mut stack = vec![shared.join(base)];
        while let Some(dir) = stack.pop() {
            for e in std::fs::read_dir(&dir).unwrap() {
                let p = e.unwrap().path();
                let name = p.file_name().unwrap().to_string_lossy().to_string();
                if p.is_dir() {
                    stack.push(p);
                } else if !(name.ends_with(".md") || name.ends_with(".tbl") || name == "expected") {
                    let rel = p.strip_prefix(&shared).unwrap().to_string_lossy().replace('\\', "/");
                    if !listed.contains(&rel) {
                        programs.push(rel);
                    }
                }
            }
        }
    }
    programs.sort();
    let count = |args: &[&str]| -> usize {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_latheguard"))
            .current_dir(&shared)
            .args(["check", "--format", "json", "--no-timing"])
            .args(args)
            .output()
            .unwrap();
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        report["files"][0]["findings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|f| f["severity"] == "error")
            .count()
    };
    let (mut before, mut after) = (0, 0);
    for p in &programs {
        let (b, a) = (count(&["--no-assume", p]), count(&[p]));
        println!("{p}: {b} → {a}");
        before += b;
        after += a;
    }
    println!(
        "assumed_setups: {} programs without a job: {before} error findings with the machine file's setup, {after} with the setup read from them",
        programs.len()
    );
    assert!(after <= before, "the reading adds errors: {before} → {after}");
    assert_eq!(
        (programs.len(), before, after),
        (22, 514, 496),
        "update docs/assume.md's table"
    );
}
