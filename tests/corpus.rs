//! Every program of `../shared/corpus` and `../shared/corpus-extra` (real lathe programs by
//! others) is read, interpreted and checked without a panic; each test prints a table of findings
//! by kind and program, with the time each program took.
//!
//! The corpora are kept out of this repository; CI has them beside the checkout. Without one the
//! test prints "skipped" and passes (a developer machine without `shared/`).

use latheguard::finding::Kind;
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// A program that takes longer than this in the (debug) test build is named in the output.
const SLOW: Duration = Duration::from_secs(10);

use crate::files;

fn shared(name: &str) -> PathBuf {
    files::shared().join(name)
}

fn linuxcnc() -> Machine {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("machines/linuxcnc-small-lathe.toml");
    machine::from_toml(&std::fs::read_to_string(&path).unwrap(), "linuxcnc-small-lathe.toml").unwrap()
}

/// The machine a corpus program is meant for: LinuxCNC for `.ngc` and generic G-code, the
/// built-in Fanuc lathe for `.nc` files.
fn machine_for(p: &Path, fanuc: &Machine, lcnc: &Machine) -> Machine {
    let name = p.to_string_lossy().to_lowercase();
    if name.ends_with(".nc") {
        fanuc.clone()
    } else {
        lcnc.clone()
    }
}

/// `corpus-extra/SOURCES.md` names each file's dialect: LinuxCNC and GRBL programs run on the
/// LinuxCNC machine, the rest (Fanuc-style lathes and their relatives) on the built-in one.
fn extra_dialects(dir: &Path) -> BTreeMap<String, bool> {
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
