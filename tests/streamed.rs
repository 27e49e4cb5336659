//! The streamed check against the whole run: `pipeline::check` feeds the checker the moves as
//! the interpreter makes them (`check::Stream`), `pipeline::check_whole` interprets the whole
//! program first and checks its move list. Their outcomes are the same byte for byte — findings
//! with their snapshots, statistics, final stock, part and part mesh — on every program of
//! `programs/` (the turn-mill folders with their machine and job), `tests/cases/` and the
//! corpora (with the job `tests/corpus-jobs/index.toml` gives, else the setup `latheguard check`
//! assumes from the program), in both modes, with the moves handed over one at a time: every
//! move starts a chunk, so whatever the checker carries from one move to the next crosses a
//! chunk's edge everywhere, and the program's blocks held one a window, so that every jump of
//! the program's flow (subroutines, loops, `GOTO`, a cycle's profile) reads its window again
//! (ARCHITECTURE.md, "Memory for long programs").

use crate::case_machine::{case_machine, with_case_job, with_job};
use crate::corpus::{case_targets, corpus_job_targets, extra_dialects, linuxcnc, machine_for, root, shared, Target};
use crate::files;
use crate::turn_mill::turn_mill;
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Outcome, Settings};
use std::path::Path;
use std::time::Instant;

/// The programs `corpus.rs`'s targets leave out: the turn-mill folders (the shipped turn-mill
/// machine, the folder's job, the job beside each program) and the cases with a hand-made tree.
fn turn_mill_targets(out: &mut Vec<Target>) {
    let mut programs = Vec::new();
    files::walk(
        &root().join("programs/turn-mill"),
        &|p| p.extension().is_some_and(|e| e == "nc"),
        &mut programs,
    );
    programs.sort();
    let tm = turn_mill();
    for p in programs {
        let folder_job = p.parent().unwrap().join("sub-chuck-empty.job.toml");
        let machine = with_case_job(with_job(tm.clone(), &folder_job), &p);
        out.push(Target {
            name: p.strip_prefix(root()).unwrap().display().to_string(),
            src: std::fs::read(&p).unwrap(),
            machine,
            settings: Settings::default(),
        });
    }
    let mut cases = Vec::new();
    files::walk(
        &root().join("tests/cases"),
        &|p| p.extension().is_some_and(|e| e == "nc" || e == "ngc"),
        &mut cases,
    );
    cases.sort();
    for p in cases {
        let src = std::fs::read(&p).unwrap();
        let first = String::from_utf8_lossy(src.split(|&b| b == b'\n').next().unwrap_or(&[])).into_owned();
        if !first.contains("kin=turnmill") {
            continue;
        }
        let mut machine = match first.split("machine=").nth(1) {
            Some(rest) => case_machine(&root(), rest.split([' ', ')']).next().unwrap()),
            None => Machine::builtin(),
        };
        machine.kinematics = Some(std::sync::Arc::new(crate::cases::turn_mill_kinematics()));
        out.push(Target {
            name: p.strip_prefix(root()).unwrap().display().to_string(),
            src,
            machine,
            settings: Settings::default(),
        });
    }
}

/// Every corpus program without a job of its own, on the setup `latheguard check` assumes from
/// it over the machine its dialect picks (`corpus.rs`), else that machine.
fn corpus_targets(out: &mut Vec<Target>) {
    let with_job: Vec<String> = {
        let mut v = Vec::new();
        corpus_job_targets(&mut v);
        v.into_iter().map(|t| t.name).collect()
    };
    let (fanuc, lcnc) = (Machine::builtin(), linuxcnc());
    for name in ["corpus", "corpus-extra"] {
        let dir = shared(name);
        let dialects = extra_dialects(&dir);
        let mut programs = Vec::new();
        files::walk(&dir, &files::is_program, &mut programs);
        programs.sort();
        for p in programs {
            let rel = p.strip_prefix(&dir).unwrap().display().to_string();
            let full = format!("{name}/{rel}");
            if with_job.contains(&full) {
                continue;
            }
            let base = match dialects.get(&rel) {
                Some(true) => lcnc.clone(),
                Some(false) => fanuc.clone(),
                None => machine_for(Path::new(&rel), &fanuc, &lcnc),
            };
            let src = std::fs::read(&p).unwrap();
            let machine = match latheguard::assume::apply(&src, &full, &base).machine {
                Some((m, _)) => m,
                None => base,
            };
            out.push(Target {
                name: full,
                src,
                machine,
                settings: Settings::default(),
            });
        }
    }
}

/// Where two outcomes differ, if they do: every field, byte for byte (`Debug` prints each
/// number so that it reads back to the same bits).
fn difference(whole: &Outcome, streamed: &Outcome) -> Option<String> {
    let fields = |o: &Outcome| {
        [
            format!("{:?}", o.findings),
            format!("{:?}", o.stats),
            format!("{:?}", o.stock),
            format!("{:?}", o.part),
        ]
    };
    let names = ["findings", "stats", "stock", "part"];
    for ((a, b), name) in fields(whole).iter().zip(fields(streamed).iter()).zip(names) {
        if a != b {
            let at = a.bytes().zip(b.bytes()).take_while(|(x, y)| x == y).count();
            let from = at.saturating_sub(200);
            return Some(format!(
                "{name} differ from byte {at}:\n  whole:    {}\n  streamed: {}",
                &a[from..(at + 200).min(a.len())],
                &b[from..(at + 200).min(b.len())]
            ));
        }
    }
    (whole.part_stl != streamed.part_stl).then(|| "part meshes differ".to_string())
}

#[test]
fn the_streamed_check_is_the_whole_runs_byte_for_byte_with_chunks_of_one_move_and_windows_of_one_block() {
    let mut targets = Vec::new();
    case_targets(&root().join("programs"), &mut targets);
    case_targets(&root().join("tests/cases"), &mut targets);
    turn_mill_targets(&mut targets);
    let local = targets.len();
    if files::shared().join("corpus").is_dir() {
        corpus_job_targets(&mut targets);
        corpus_targets(&mut targets);
    } else {
        println!(
            "streamed against whole: corpus skipped: no corpus at {}",
            files::shared().display()
        );
    }
    assert!(local > 120, "too few programs and cases: {local}");
    let t = Instant::now();
    let mut failures = Vec::new();
    let (mut findings, mut moves, mut three, mut snapshots) = (0, 0, 0, 0);
    for x in &targets {
        for mode in [Mode::Step, Mode::Exact] {
            let s = Settings {
                mode,
                snapshots: true,
                // The mesh is made from the final stock alone: one mode makes it.
                part_mesh: mode == Mode::Exact,
                ..x.settings
            };
            let whole = pipeline::check_whole(&x.src, &x.machine, &s);
            // One move a chunk, and the program's blocks held one a window: every jump of the
            // program's flow reads its window again.
            let streamed = pipeline::check_streamed_windowed(&x.src, &x.machine, &s, 1, 1);
            if let Some(why) = difference(&whole, &streamed) {
                failures.push(format!("{} ({mode:?}): {why}", x.name));
            }
            findings += whole.findings.len();
            moves += whole.stats.moves;
            three += usize::from(whole.stats.effects.iter().any(|e| e == "kinematic_3d"));
            snapshots += whole.findings.iter().filter(|f| f.snapshot.is_some()).count();
        }
    }
    println!(
        "streamed against whole: {} programs ({local} programs and cases) in both modes, {moves} moves, \
         {findings} findings ({snapshots} with a snapshot), {three} checks on the 3D path, in {:.1} s",
        targets.len(),
        t.elapsed().as_secs_f64()
    );
    assert!(
        failures.is_empty(),
        "streamed and whole checks differ:\n{}",
        failures.join("\n")
    );
    // Not vacuous: the window's edges meet findings with pictures and the 3D path.
    assert!(
        snapshots > 100 && three > 10,
        "{snapshots} snapshots, {three} 3D checks"
    );
}

/// The check that stops at its work budget, and the moves timed at the fallback feed (a feed
/// per revolution with no spindle speed), streamed one move at a time: where it stops, the moves
/// timed after it and the lines reported are the whole run's.
#[test]
fn a_streamed_check_stops_at_the_same_move_of_its_work_budget_and_reports_the_same_stalls() {
    let src = "G21 G18 G99\nT0101\nG97 S0 M3\nG0 X60 Z2\nG1 X40 F0.2\nG97 S800\n\
               #1 = 0\nWHILE [#1 LT 40] DO1\n#1 = #1 + 1\nG0 X60 Z2\nG1 X40 Z-5 F0.2\nG1 Z-20\nG0 X60\nEND1\n\
               G97 S0\nG1 Z-25\nG0 X100 Z100\nM30\n";
    let machine = Machine::builtin();
    let full = pipeline::check_whole(src.as_bytes(), &machine, &Settings::default());
    let tests = full.stats.pair_tests;
    assert!(tests > 1000, "{tests}");
    for mode in [Mode::Step, Mode::Exact] {
        for budget in [0, 10, tests / 3, tests / 2] {
            let s = Settings {
                mode,
                work_budget: budget,
                snapshots: true,
                ..Settings::default()
            };
            let whole = pipeline::check_whole(src.as_bytes(), &machine, &s);
            let streamed = pipeline::check_streamed(src.as_bytes(), &machine, &s, 1);
            assert_eq!(difference(&whole, &streamed), None, "{mode:?}, budget {budget}");
            let said = |needle: &str| whole.findings.iter().filter(|f| f.message.contains(needle)).count();
            assert_eq!(said("no spindle speed"), 2, "{mode:?}, budget {budget}");
            assert_eq!(said("work budget"), 1, "{mode:?}, budget {budget}");
        }
    }
}
