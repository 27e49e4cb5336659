//! Work offsets G54–G59 (docs/machine.md and docs/job.md, "Work offsets"; docs/programs.md,
//! "G54–G59"): a second operation in G55 that is clean with the job's G55 and hits the chuck
//! with a wrong one, G53 to a tool change point in machine coordinates whatever work offset is
//! in force, an offset not given still reported, the machine file's keys and `latheguard setup`.

use crate::common;
use latheguard::finding::{Kind, Severity};
use latheguard::geom::{P2, V2};
use latheguard::machine::{self, Machine, WorkOffset};
use latheguard::pipeline::{self, Settings};
use std::path::{Path, PathBuf};

fn docs() -> PathBuf {
    common::fixtures().join("docs")
}

fn offsets_lathe() -> Machine {
    let text = std::fs::read_to_string(docs().join("offsets-lathe.toml")).unwrap();
    machine::from_toml(&text, "offsets-lathe.toml").unwrap()
}

fn program(name: &str) -> Vec<u8> {
    std::fs::read(docs().join(name)).unwrap()
}

fn close(a: P2, b: P2) -> bool {
    (a - b).norm() < 1e-9
}

#[test]
fn g53_goes_to_the_tool_change_point_in_machine_coordinates_under_g54_and_g55() {
    let m = offsets_lathe();
    assert_eq!(m.machine_zero, P2::new(150.0, 400.0));
    assert_eq!(
        m.work_zero(1),
        Some(P2::new(0.0, 40.0)),
        "G55 Z -360 from machine zero z 400"
    );
    let (_, run) = pipeline::interpret(&program("tool-change-point.nc"), &m);
    // `G53 G0 X100. Z100.`: the turret reference point at machine zero + (X100 on diameter, Z100),
    // at line 3 (G54 in force), 13 (G55) and 18 (G55, another tool): x 200, z 500 each time.
    for line in [3, 13, 18] {
        let mv = run.moves.iter().rfind(|m| m.line == line).unwrap();
        let reference = mv.end - mv.tip;
        assert!(close(reference, P2::new(200.0, 500.0)), "line {line}: {reference:?}");
    }
    // The move after G55 is in G55: `G0 X54. Z0.` puts T01's tip at radius 27, z 40.
    let mv = run.moves.iter().find(|m| m.line == 7).unwrap();
    assert!(close(mv.end, P2::new(27.0, 40.0)), "{:?}", mv.end);
    assert_eq!(mv.tip, V2::new(-60.0, -12.0));
    let out = pipeline::check(&program("tool-change-point.nc"), &m, &Settings::default());
    assert!(out.findings.is_empty(), "{:#?}", out.findings);
}

#[test]
fn an_offset_not_given_is_reported_at_its_word_and_names_the_key_to_write() {
    let m = Machine::builtin();
    let src = b"G21 G99\nG28 U0 W0\nT0101\nG56\nG0 X60. Z5.\nM30\n";
    let out = pipeline::check(src, &m, &Settings::default());
    let f: Vec<_> = out.findings.iter().filter(|f| f.kind == Kind::Unsupported).collect();
    assert_eq!(f.len(), 1, "{:#?}", out.findings);
    assert_eq!((f[0].line, f[0].col, f[0].severity), (4, 1, Severity::Error));
    assert!(
        f[0].message.contains("[work_offsets] G56 = { z = … }"),
        "{}",
        f[0].message
    );
    // Program zero stays where it was: the move lands at program_zero_z + 5.
    let (_, run) = pipeline::interpret(src, &m);
    let mv = run.moves.iter().find(|m| m.line == 5).unwrap();
    assert!(close(mv.end, P2::new(30.0, 83.0)), "{:?}", mv.end);
    // G54 is always given: program_zero_z.
    let out = pipeline::check(
        b"G21 G99\nG28 U0 W0\nT0101\nG54\nG0 X60. Z5.\nM30\n",
        &m,
        &Settings::default(),
    );
    assert!(out.findings.is_empty(), "{:#?}", out.findings);
}

#[test]
fn a_g50_shift_stays_over_every_work_offset() {
    // Fanuc shifts every workpiece coordinate system by G50 X Z (0i-TD manual, "Setting a
    // workpiece coordinate system"); LinuxCNC's G92 offsets apply in every system too.
    let m = offsets_lathe();
    let src = b"G21\nG53 G0 X100. Z100.\nT0101\nG0 X60. Z10.\nG50 Z0.\nG55\nG0 X60. Z-5.\nM30\n";
    let (_, run) = pipeline::interpret(src, &m);
    // G50 Z0 at z 41 + 10 = 51 shifts program zero by +10; G55 (z 40) keeps the shift: z 50 - 5.
    let mv = run.moves.iter().find(|m| m.line == 7).unwrap();
    assert!(close(mv.end, P2::new(30.0, 45.0)), "{:?}", mv.end);
}

#[test]
fn a_machine_file_gives_work_offsets_in_setup_with_errors_and_warnings_naming_the_key() {
    let base = machine::BUILTIN_TOML;
    let with = |setup: &str| {
        base.replace(
            "[setup]\nprogram_zero_z = 78.0      # 2 mm faced off the bar end\n# The bar, program zero and tools above and below are an example: a program with no job is read\n# for its own (docs/assume.md).\nassume = true\n",
            setup,
        )
    };
    assert_ne!(with("X"), base, "the built-in file's [setup] changed: update this test");
    // G54 written is program zero: z 600 - 530 = 70.
    let m = machine::from_toml(&with("[setup]\nwork_offsets.G54 = { z = -530.0 }\n"), "m.toml").unwrap();
    assert_eq!(m.program_zero_z, 70.0);
    assert_eq!(m.work_offsets[0], Some(WorkOffset { x: 0.0, z: -530.0 }));
    assert!(m
        .describe()
        .contains("  G54         z -530 from machine zero: program zero at z 70\n"));
    // Both ways at once is an error at program_zero_z.
    let e = machine::from_toml(
        &with("[setup]\nprogram_zero_z = 78.0\nwork_offsets.G54 = { z = -530.0 }\n"),
        "m.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(": setup.program_zero_z: program zero is given twice: by setup.program_zero_z and by setup.work_offsets.G54"),
        "{e}"
    );
    let e = machine::from_toml(&with("[setup.work_offsets]\nG55 = { z = \"far\" }\n"), "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("setup.work_offsets.G55.z"), "{e}");
    // Out of the Z travel: a warning, the file loads.
    let m = machine::from_toml(&with("[setup.work_offsets]\nG55 = { z = 20.0 }\n"), "m.toml").unwrap();
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert!(
        m.warnings[0].contains(": setup.work_offsets.G55: program zero at machine Z 20 lies outside the Z travel"),
        "{:?}",
        m.warnings
    );
    // No offsets: every shipped machine is as it was (G54 = program_zero_z, no other).
    for entry in std::fs::read_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("machines")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            let Ok(m) = machine::from_toml(&text, "m.toml") else {
                continue;
            };
            assert_eq!(m.work_offsets, [None; 6], "{}", p.display());
            assert_eq!(m.work_zero(0), Some(P2::new(0.0, m.program_zero_z)));
        }
    }
}

#[test]
fn the_second_operation_is_clean_with_its_g55_and_hits_the_chuck_with_a_wrong_one() {
    let dir = docs();
    let clean = common::latheguard(&dir, &["check", "--no-timing", "second-op.nc"]);
    assert_eq!(
        clean.status.code(),
        Some(0),
        "{}{}",
        common::stdout(&clean),
        common::stderr(&clean)
    );
    // The job beside the program gives G55 Z -560 (z 40); wrong-g55.job.toml, laid over it,
    // -563 (z 37): the OD pass to Z-38. ends at z -1 with the insert over the jaws.
    let crash = common::latheguard(
        &dir,
        &["check", "--no-timing", "--job", "wrong-g55.job.toml", "second-op.nc"],
    );
    let text = common::stdout(&crash);
    assert_eq!(crash.status.code(), Some(1), "{text}{}", common::stderr(&crash));
    assert!(
        text.contains("second-op.nc:11: error[collision]: the T01 insert hits the chuck (depth 1.000 mm"),
        "{text}"
    );
    assert_eq!(text.matches("error[").count(), 1, "{text}");
    // Without a G55 at all, the program is refused where it selects it.
    let none = common::latheguard(
        &dir,
        &[
            "check",
            "--no-timing",
            "--no-config",
            "-m",
            "../../../machines/generic-slant-bed.toml",
            "tool-change-point.nc",
        ],
    );
    let text = common::stdout(&none);
    assert!(
        text.contains("tool-change-point.nc:5:1: error[unsupported]: G55: the work offset G55 is not given"),
        "{text}"
    );
}

#[test]
fn setup_prints_the_work_offsets_in_force_and_where_each_came_from() {
    let dir = docs();
    let o = common::latheguard(&dir, &["setup", "--job", "wrong-g55.job.toml", "second-op.nc"]);
    let text = common::stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{text}{}", common::stderr(&o));
    assert!(
        text.contains("  work offset   G54 z -559 from machine zero: program zero at z 41  [second-op.job.toml]\n"),
        "{text}"
    );
    assert!(
        text.contains("  work offset   G55 z -563 from machine zero: program zero at z 37  [wrong-g55.job.toml]\n"),
        "{text}"
    );
    let o = common::latheguard(
        &dir,
        &[
            "setup",
            "--format",
            "json",
            "-m",
            "offsets-lathe.toml",
            "tool-change-point.nc",
        ],
    );
    let j = common::json(&o);
    let w = j["work_offsets"].as_array().unwrap();
    assert_eq!(w.len(), 2, "{j}");
    assert_eq!(w[1]["name"], "G55");
    assert_eq!(w[1]["z"], -360.0);
    assert_eq!(w[1]["program_zero"], serde_json::json!([0.0, 40.0]));
    assert_eq!(w[1]["from"], "machine");
}
