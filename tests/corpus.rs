//! Every program of `../shared/corpus` (real lathe programs by others) is read, interpreted and
//! checked without a panic; the test prints a table of findings by kind and program.
//!
//! The corpus is kept out of this repository; CI has it beside the checkout. Without it the test
//! says so and passes (a developer machine without `shared/`).

use latheguard::finding::Kind;
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn corpus_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/corpus")
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, out);
        } else {
            let name = p.file_name().unwrap().to_string_lossy().to_lowercase();
            let skip = name == "expected" || name.ends_with(".md") || name.ends_with(".tbl") || name == "result";
            if !skip {
                out.push(p);
            }
        }
    }
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

#[test]
fn every_corpus_program_is_read_interpreted_and_checked() {
    let dir = corpus_dir();
    if !dir.is_dir() {
        eprintln!("no corpus at {}: skipped", dir.display());
        return;
    }
    let mut files = Vec::new();
    walk(&dir, &mut files);
    files.sort();
    assert!(files.len() >= 50, "corpus looks incomplete: {} files", files.len());
    let fanuc = Machine::builtin();
    let lcnc = linuxcnc();
    let mut table: BTreeMap<String, BTreeMap<Kind, usize>> = BTreeMap::new();
    let mut totals: BTreeMap<Kind, usize> = BTreeMap::new();
    let mut moves_total = 0usize;
    for f in &files {
        let src = std::fs::read(f).unwrap();
        let m = machine_for(f, &fanuc, &lcnc);
        let (_, run) = pipeline::interpret(&src, &m);
        moves_total += run.moves.len();
        let out = pipeline::check(&src, &m, &Settings::default());
        let rel = f.strip_prefix(&dir).unwrap().display().to_string();
        let row = table.entry(rel).or_default();
        for x in &out.findings {
            *row.entry(x.kind).or_default() += 1;
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
    let mut s = format!("{:<72}", "program");
    for k in kinds {
        s += &format!(" {:>7}", &k.name()[..k.name().len().min(7)]);
    }
    println!("{s}");
    for (name, row) in &table {
        let mut s = format!("{name:<72}");
        for k in kinds {
            s += &format!(" {:>7}", row.get(&k).copied().unwrap_or(0));
        }
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
    assert!(
        moves_total > 10_000,
        "the corpus should produce real motion, got {moves_total} moves"
    );
}
