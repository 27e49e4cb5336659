//! A job's operations (docs/job.md, "Operations"): a program that turns one side of a part,
//! stops at M00 while the operator turns the part round, and finishes the other side on G55.
//! The two-operation case `tests/cases/ops/two_ops.nc` is clean with its job's `[[operations]]`
//! and shows the false crashes without them; a real crash after the turn-round is found at its
//! line; the part written by `--stock-out part.toml` and read back with `[stock] from` gives the
//! second operation, as a program of its own, the findings the one program gives; every job
//! error names its file, line, column and key.

use crate::common;
use latheguard::finding::{Finding, Kind, Severity};
use latheguard::job::{self, EffectiveJob};
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Settings};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn ops_dir() -> PathBuf {
    root().join("tests/cases/ops")
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// The built-in machine with a job file's text applied (files it names read from `dir`).
fn apply(text: &str, name: &str, dir: &Path) -> Result<Machine, String> {
    let mut resolve = |base: &str, rel: &str| -> Result<(String, String), String> {
        let p = Path::new(base).join(rel);
        std::fs::read_to_string(&p)
            .map(|t| (rel.to_string(), t))
            .map_err(|e| e.to_string())
    };
    let layer = job::parse(text, name, &dir.display().to_string(), name, &mut resolve).map_err(|e| e.to_string())?;
    job::apply(&Machine::builtin(), &EffectiveJob::merge([&layer])).map_err(|e| e.to_string())
}

/// The job's error for `text` (a job file named `part.job.toml` in `dir`).
fn job_error(text: &str, dir: &Path) -> String {
    match apply(text, "part.job.toml", dir) {
        Ok(_) => panic!("the job was accepted:\n{text}"),
        Err(e) => e,
    }
}

fn check(src: &str, machine: &Machine) -> Vec<Finding> {
    pipeline::check(src.as_bytes(), machine, &Settings::default()).findings
}

/// (line, kind, objects) of each finding.
fn facts(f: &[Finding]) -> Vec<(u32, Kind, Vec<String>)> {
    f.iter().map(|f| (f.line, f.kind, f.objects.clone())).collect()
}

/// The two-operation job without its `[[operations]]`.
fn without_operations(job: &str) -> String {
    job[..job.find("[[operations]]").unwrap()].to_string()
}

#[test]
fn the_two_operation_program_is_clean_with_its_operations_and_crashes_falsely_without_them() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("two_ops.job.toml")),
    );
    let with = apply(&job, "two_ops.job.toml", &ops_dir()).unwrap();
    let out = pipeline::check(prog.as_bytes(), &with, &Settings::default());
    assert!(out.findings.is_empty(), "{:#?}", out.findings);
    assert!(
        out.stats.effects.iter().any(|e| e == "turn_round"),
        "{:?}",
        out.stats.effects
    );
    // The final part is the part turned round: its old front (z 57) held at z -20, its old
    // chucked end (z -12) faced from z 49 to 48 by the second operation.
    let part = out.part.unwrap();
    let zs: Vec<f64> = part.outline.iter().map(|p| p[1]).collect();
    let (lo, hi) = zs.iter().fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    assert!((lo + 20.0).abs() < 0.011 && (hi - 48.0).abs() < 0.011, "z {lo} .. {hi}");
    // Without the turn-round, operation 2 runs against the part as operation 1 left it, where
    // the material that was the chucked end and the Ø50 in the jaws still stand: its rapids
    // back from the face and into the groove's place are crashes that are not there.
    let bare = apply(&without_operations(&job), "two_ops.job.toml", &ops_dir()).unwrap();
    let got = facts(&check(&prog, &bare));
    let insert = |t: &str| vec![format!("{t} insert"), "stock".to_string()];
    assert_eq!(
        got,
        vec![
            (24, Kind::RapidIntoStock, insert("T01")),
            (33, Kind::RapidIntoStock, insert("T04")),
            (35, Kind::RapidIntoStock, insert("T04")),
        ]
    );
}

#[test]
fn a_rapid_into_the_shoulder_of_the_part_turned_round_is_found_at_its_line_in_operation_2() {
    let dir = ops_dir();
    let prog = read(&dir.join("two_ops_rapid_into_shoulder.nc"));
    let m = apply(
        &read(&dir.join("two_ops_rapid_into_shoulder.job.toml")),
        "j.job.toml",
        &dir,
    )
    .unwrap();
    let f = check(&prog, &m);
    assert_eq!(f.len(), 1, "{f:#?}");
    assert_eq!(
        (f[0].line, f[0].kind, f[0].severity),
        (27, Kind::RapidIntoStock, Severity::Error)
    );
    assert_eq!(f[0].operation, Some(2));
    // About 2 mm into the Ø50 shoulder (the 3 mm rapid less the nose radius's fillet).
    assert!(f[0].depth_mm.unwrap() > 1.5, "{:?}", f[0].depth_mm);
}

#[test]
fn an_operation_at_the_first_program_stop_is_the_operation_at_the_m00_line() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("two_ops.job.toml")),
    );
    let by_stop = job.replace("line = 17", "stop = 1");
    assert_ne!(by_stop, job);
    let m = apply(&by_stop, "j.job.toml", &ops_dir()).unwrap();
    assert!(check(&prog, &m).is_empty());
    // The crash variant: found the same with either start.
    let crash = read(&ops_dir().join("two_ops_rapid_into_shoulder.nc"));
    assert_eq!(facts(&check(&crash, &m))[0].0, 27);
}

#[test]
fn an_operation_can_move_g54_instead_of_the_program_selecting_g55() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("two_ops.job.toml")),
    );
    // The operator touches off the new face at z 48 and the program stays in G54.
    let prog = prog.replace("\nG55\n", "\nG54\n");
    let job = job.replace("grip = 20.0", "grip = 20.0\nprogram_zero_z = 48.0");
    let m = apply(&job, "j.job.toml", &ops_dir()).unwrap();
    assert!(check(&prog, &m).is_empty());
    // Without it, G54 stays at z 57: operation 2's Z words land 9 mm farther out, and the rapid
    // to its groove lands in the Ø50 shoulder.
    let stays = apply(&job.replace("program_zero_z = 48.0", ""), "j.job.toml", &ops_dir()).unwrap();
    assert!(!check(&prog, &stays).is_empty());
}

#[test]
fn an_operation_that_never_starts_is_a_warning_naming_its_key() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("two_ops.job.toml")),
    );
    let m = apply(&job.replace("line = 17", "line = 2"), "j.job.toml", &ops_dir()).unwrap();
    let f = check(&prog, &m);
    let w: Vec<&Finding> = f.iter().filter(|f| f.kind == Kind::Program).collect();
    assert_eq!(w.len(), 1, "{f:#?}");
    assert_eq!((w[0].line, w[0].severity), (2, Severity::Warning));
    assert!(
        w[0].message
            .starts_with("j.job.toml:14:1: operations[0]: operation 2 never started: the block at line 2 never ran"),
        "{}",
        w[0].message
    );
}

#[test]
fn a_part_the_jaws_of_its_operation_would_cut_into_is_an_error_naming_the_operation() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("two_ops.job.toml")),
    );
    // Held 35 mm: the Ø50 (from z 10 - 15 = -5 on) reaches into the jaws bored to Ø40.
    let m = apply(
        &job.replace("grip = 20.0", "grip = 35.0"),
        "two_ops.job.toml",
        &ops_dir(),
    )
    .unwrap();
    let f = check(&prog, &m);
    let hit = f
        .iter()
        .find(|f| f.objects == ["stock", "chuck"])
        .unwrap_or_else(|| panic!("{f:#?}"));
    assert_eq!(
        (hit.line, hit.kind, hit.severity),
        (17, Kind::Collision, Severity::Error)
    );
    assert!(
        hit.message.starts_with(
            "two_ops.job.toml:14:1: operations[0]: the part as operation 2 holds it (z -35 .. 34, Ø50 max) overlaps its chuck by"
        ),
        "{}",
        hit.message
    );
}

fn program_lines(prog: &str, from: usize, to: usize) -> String {
    prog.lines()
        .skip(from - 1)
        .take(to + 1 - from)
        .map(|l| format!("{l}\n"))
        .collect()
}

/// JSON findings of `latheguard check` as (line, kind, objects, depth).
fn json_findings(dir: &Path, program: &str) -> Vec<(u64, String, Vec<String>, f64)> {
    let o = common::latheguard(dir, &["check", "--format", "json", program]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap_or_else(|_| panic!("{}", common::stderr(&o)));
    doc["files"][0]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            (
                f["line"].as_u64().unwrap(),
                f["kind"].as_str().unwrap().to_string(),
                f["objects"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|s| s.as_str().unwrap().to_string())
                    .collect(),
                f["depth_mm"].as_f64().unwrap_or(0.0),
            )
        })
        .collect()
}

#[test]
fn the_part_written_by_stock_out_gives_operation_2_as_its_own_program_the_same_findings() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    for name in ["two_ops", "two_ops_rapid_into_shoulder"] {
        let prog = read(&ops_dir().join(format!("{name}.nc")));
        let job = read(&ops_dir().join(format!("{name}.job.toml")));
        std::fs::write(d.join("whole.nc"), &prog).unwrap();
        std::fs::write(d.join("whole.job.toml"), &job).unwrap();
        // Operation 1 alone (lines 1 .. 16, then the end), with the job's stock and G54.
        std::fs::write(d.join("op1.nc"), program_lines(&prog, 1, 16) + "M30\n").unwrap();
        std::fs::write(d.join("op1.job.toml"), without_operations(&job)).unwrap();
        // Operation 2 alone: its header, then lines 18 .. of the one program (line k there is
        // line k - 16 here).
        let op2 =
            "O3002 (OPERATION 2 OF TWO_OPS.NC AS A PROGRAM OF ITS OWN)\n".to_string() + &program_lines(&prog, 18, 99);
        std::fs::write(d.join("op2.nc"), op2).unwrap();
        let jaws = job
            .lines()
            .find(|l| l.starts_with("chuck = "))
            .unwrap()
            .replace("chuck = { outline = ", "outline = ")
            .trim_end_matches(" }")
            .to_string();
        std::fs::write(
            d.join("op2.job.toml"),
            format!(
                "[stock]\nfrom = \"part.toml\"\nreverse = true\ngrip = 20.0\n\n[chuck]\n{jaws}\n\n[work_offsets]\nG55 = {{ z = -552.0 }}\n"
            ),
        )
        .unwrap();
        let o = common::latheguard(d, &["check", "op1.nc", "--stock-out", "part.toml"]);
        assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
        let part = read(&d.join("part.toml"));
        assert!(
            part.starts_with("# The part made by op1.nc (latheguard check --stock-out).\n"),
            "{part}"
        );
        assert!(part.contains("\n# The whole stock (no part-off).\n"), "{part}");
        assert!(
            part.contains("\n[stock]\noutline = [\n  [0.0, -12.0], [25.0, -12.0], "),
            "{part}"
        );
        let one: Vec<_> = json_findings(d, "whole.nc")
            .into_iter()
            .filter(|f| f.0 > 17)
            .map(|(l, k, o, depth)| (l - 16, k, o, depth))
            .collect();
        let two = json_findings(d, "op2.nc");
        assert_eq!(one.len(), two.len(), "{name}: {one:?} against {two:?}");
        for (a, b) in one.iter().zip(&two) {
            assert_eq!((a.0, &a.1, &a.2), (b.0, &b.1, &b.2), "{name}");
            // The part read back is re-sampled from its outline: within a column.
            assert!((a.3 - b.3).abs() <= 0.011, "{name}: depth {} against {}", a.3, b.3);
        }
    }
}

#[test]
fn stock_out_toml_after_a_part_off_writes_the_piece_cut_off() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // The built-in bar (Ø50, z -40 .. 80): turn Ø40 over 30 mm, part off 25 mm from the front.
    let prog = "O3003\nG21 G99\nT0101\nG97 S1200 M3\nG0 X40. Z2.\nG1 Z-30. F0.25\nX52.\nG0 Z2.\nG28 U0 W0\n\
                T0808\nG0 X54. Z-28.5\nG1 X-1. F0.05\nG0 X54.\nG28 U0 W0\nM30\n";
    std::fs::write(d.join("partoff.nc"), prog).unwrap();
    let o = common::latheguard(d, &["check", "partoff.nc", "--stock-out", "piece.toml"]);
    assert_eq!(o.status.code(), Some(0), "{}", common::stderr(&o));
    let piece = read(&d.join("piece.toml"));
    assert!(
        piece.contains("# The piece the part-off cut off; the bar left in the jaws is not written.\n"),
        "{piece}"
    );
    // Program zero at z 78: the piece runs from the groove's far side (z 78 - 28.5 + 2.5 = 52) to
    // the bar's front (z 80, not faced), Ø40.
    assert!(piece.contains("Ø40 max, z 52 .. 80."), "{piece}");
    // Read back as a stock, turned round and gripped 10 mm.
    std::fs::write(
        d.join("p.job.toml"),
        "[stock]\nfrom = \"piece.toml\"\nreverse = true\ngrip = 10.0\n",
    )
    .unwrap();
    let m = apply(&read(&d.join("p.job.toml")), "p.job.toml", d).unwrap();
    let st = m.stock.unwrap();
    assert!(
        (st.front - 18.0).abs() < 1e-6 && (st.length - 28.0).abs() < 1e-6 && (st.diameter - 40.0).abs() < 1e-6,
        "{st:?}"
    );
}

#[test]
fn setup_lists_each_operation_and_moves_marks_the_turn_round() {
    let dir = ops_dir();
    let o = common::latheguard(&dir, &["setup", "two_ops.nc"]);
    let text = common::stdout(&o);
    assert!(
        text.contains(
            "  operation 2   from line 17 (M00): part turned round, held 20 mm in the jaws (back end at z -20), jaws x 20 .. 105, z -100 .. 0 (10 points), note: M00: turn the part round, grip it on the Ø40 over 20 mm  [two_ops.job.toml]\n"
        ),
        "{text}"
    );
    let o = common::latheguard(&dir, &["setup", "--format", "json", "two_ops.nc"]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let op = &doc["operations"][0];
    assert_eq!(op["operation"], 2);
    assert_eq!(op["key"], "operations[0]");
    assert_eq!(op["line"], 17);
    assert_eq!(op["reverse"], true);
    assert_eq!(op["grip"], 20.0);
    assert_eq!(op["chuck"]["own"], true);
    let o = common::latheguard(&dir, &["moves", "two_ops.nc"]);
    let canon = common::stdout(&o);
    assert!(
        canon.contains(
            "   17 COMMENT(\"latheguard: operation 2 starts: the part turned round or re-clamped (job operations[0])\")\n"
        ),
        "{canon}"
    );
    let o = common::latheguard(&dir, &["moves", "--format", "json", "two_ops.nc"]);
    let moves: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let op = moves
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["kind"] == "operation")
        .unwrap();
    assert_eq!(op["line"], 17);
    assert_eq!(op["arc"]["operation"], 2);
}

#[test]
fn the_json_report_says_which_operation_a_finding_began_in() {
    let o = common::latheguard(
        &ops_dir(),
        &["check", "--format", "json", "two_ops_rapid_into_shoulder.nc"],
    );
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["files"][0]["findings"][0]["operation"], 2);
    let o = common::latheguard(&ops_dir(), &["check", "two_ops_rapid_into_shoulder.nc"]);
    assert!(
        common::stdout(&o).contains("until line 28, operation 2)"),
        "{}",
        common::stdout(&o)
    );
}

#[test]
fn each_job_error_of_operations_and_part_files_names_file_line_column_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let bad = |text: &str| job_error(text, d);
    let cases: &[(&str, &str)] = &[
        (
            "[[operations]]\nreverse = true\ngrip = 10.0\n",
            "part.job.toml:1:1: operations[0].line: missing required key `line` (the program line where the operation starts; or `stop`, the program stop after which it starts; or `work_offset`, the work offset whose first selection starts it)",
        ),
        (
            "[[operations]]\nline = 5\nstop = 1\n",
            "part.job.toml:3:8: operations[0].stop: an operation starts at one place: give one of `line`, `stop` and `work_offset`, not `line` and `stop`",
        ),
        (
            "[[operations]]\nstop = 1\nwork_offset = \"G55\"\n",
            "part.job.toml:3:15: operations[0].work_offset: an operation starts at one place: give one of `line`, `stop` and `work_offset`, not `stop` and `work_offset`",
        ),
        (
            "[[operations]]\nwork_offset = \"G60\"\n",
            "part.job.toml:2:15: operations[0].work_offset: \"G60\" is not a work offset: give one of \"G54\" to \"G59\"",
        ),
        (
            "[[operations]]\nline = 40\ntailstock = { z = 60.0 }\n",
            "part.job.toml:3:13: operations[0].tailstock: the machine has no tailstock: describe it in the machine file's [tailstock]",
        ),
        (
            "[[operations]]\nline = 40\ntailstock = { z = \"far\" }\n",
            "part.job.toml:3:19: operations[0].tailstock.z: invalid type: string \"far\", expected a number",
        ),
        ("[[operations]]\nline = 0\n", "part.job.toml:2:8: operations[0].line: 0 is not a line: lines count from 1"),
        (
            "[[operations]]\nstop = 0\n",
            "part.job.toml:2:8: operations[0].stop: 0 is not a program stop: the first is stop = 1",
        ),
        (
            "[[operations]]\nline = 40\n[[operations]]\nline = 30\n",
            "part.job.toml:4:8: operations[1].line: line 30 does not come after line 40 of operations[0]: list the operations in the order they start",
        ),
        (
            "[[operations]]\nline = 40\nreverse = true\n",
            "part.job.toml:3:11: operations[0].reverse: a part turned round needs where it then stands: give `front` (z of its front face) or `grip` (the length held in the jaws)",
        ),
        (
            "[[operations]]\nline = 40\nfront = 41.0\ngrip = 12.0\n",
            "part.job.toml:4:8: operations[0].grip: give where the part stands once: `front` (z of its front face) or `grip` (the length held in the jaws), not both",
        ),
        (
            "[[operations]]\nline = 40\ngrip = -1.0\n",
            "part.job.toml:3:8: operations[0].grip: must not be negative, not -1",
        ),
        (
            "[[operations]]\nline = 40\nchuck = { outline = [[0, 0], [1, 1]] }\n",
            "part.job.toml:3:21: operations[0].chuck.outline: invalid outline",
        ),
        (
            "[[operations]]\nline = 40\nturn = true\n",
            "part.job.toml:3:1: operations[0].turn: unknown key `turn`, expected one of `line`, `stop`, `work_offset`, `tailstock`, `reverse`, `front`, `grip`, `chuck`, `program_zero_z`, `note`",
        ),
        (
            "[stock]\nfrom = \"nowhere.toml\"\n",
            "part.job.toml:2:8: stock.from: cannot read the part file nowhere.toml: No such file",
        ),
        (
            "[stock]\nfrom = \"part.toml\"\ndiameter = 50.0\n",
            "part.job.toml:3:12: stock.diameter: a stock `from` a part file takes its outline from that file: give `from` or the stock's sizes, not both",
        ),
        (
            "[stock]\ndiameter = 50.0\nlength = 70.0\nstick_out = 58.0\nreverse = true\n",
            "part.job.toml:5:11: stock.reverse: `reverse` places a part given by its outline (`outline` or `from`); a bar is placed by `stick_out`",
        ),
        (
            "[stock]\noutline = [[0, 0], [20, 0], [20, 30], [0, 30]]\nreverse = true\n",
            "part.job.toml:3:11: stock.reverse: a part turned round needs where it then stands",
        ),
        (
            "[stock]\noutline = [[0, 0], [30, 0], [30, 30], [0, 30]]\nreverse = true\ngrip = 40.0\n",
            "part.job.toml:4:8: stock.grip: the stock outline (Ø60 max, z -40 .. -10) overlaps the chuck by",
        ),
    ];
    std::fs::write(
        d.join("part.toml"),
        "[stock]\noutline = [[0, 0], [20, 0], [20, 30], [0, 30]]\n",
    )
    .unwrap();
    std::fs::write(
        d.join("bad-part.toml"),
        "# a part\n[stock]\noutline = [[0, 0], [-20, 0], [-20, 30]]\n",
    )
    .unwrap();
    for (text, want) in cases {
        let e = bad(text);
        assert!(e.starts_with(want), "{text}\n  gave: {e}\n  want: {want}");
    }
    // An error inside the part file names that file.
    let e = bad("[stock]\nfrom = \"bad-part.toml\"\n");
    assert!(
        e.starts_with("bad-part.toml:3:20: stock.outline[1]: a stock outline is the revolved section: its x (radius) must be 0 or more"),
        "{e}"
    );
    // A machine with a kinematic tree: not built yet, said at the operation.
    let tm = root().join("machines/turn-mill.toml");
    let machine = latheguard::machine::from_toml_with(&read(&tm), "turn-mill.toml", &|rel: &str| {
        std::fs::read(root().join("machines").join(rel)).map_err(|e| e.to_string())
    })
    .unwrap();
    let mut none = |_: &str, _: &str| -> Result<(String, String), String> { Err("no".into()) };
    let layer = job::parse("[[operations]]\nline = 9\n", "t.job.toml", ".", "t", &mut none).unwrap();
    let e = job::apply(&machine, &EffectiveJob::merge([&layer]))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("t.job.toml:1:1: operations[0]: operations are not built for a machine with [kinematics]"),
        "{e}"
    );
}

#[test]
fn an_operation_closes_the_jaws_on_the_diameter_it_grips() {
    // Operation 2 as the case's job gives it, with its jaws as `chuck.jaws` over the built-in
    // machine's hard jaws: closed on the Ø40 it holds, the jaws slide in 5 mm from the Ø50 bar of
    // operation 1 (x 20 .. 65 behind the step, 20 .. 40 at the tips, up to the jaw faces at z 0).
    let dir = ops_dir();
    let (prog, job) = (read(&dir.join("two_ops.nc")), read(&dir.join("two_ops.job.toml")));
    let outline_line = job.lines().find(|l| l.starts_with("chuck = { outline")).unwrap();
    let with_jaws = job.replace(outline_line, "chuck = { jaws = { grip_diameter = 40.0 } }");
    let m = apply(&with_jaws, "two_ops.job.toml", &dir).unwrap();
    let mut got: Vec<[f64; 2]> = m.operations[0]
        .chuck
        .as_ref()
        .unwrap()
        .points()
        .iter()
        .map(|p| [p.x, p.y])
        .collect();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut want = vec![
        [25.0, -100.0],
        [105.0, -100.0],
        [105.0, -30.0],
        [65.0, -30.0],
        [65.0, -12.0],
        [40.0, -12.0],
        [40.0, 0.0],
        [20.0, 0.0],
        [20.0, -30.0],
        [25.0, -30.0],
    ];
    want.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(got, want, "{got:?}");
    // The job's own chuck (operation 1) stays closed on the Ø50 bar.
    assert!(m
        .chuck
        .as_ref()
        .unwrap()
        .points()
        .iter()
        .any(|p| (p.x - 45.0).abs() < 1e-9));
    assert!(check(&prog, &m).is_empty());

    // Errors: jaws on a machine whose chuck is an outline; jaws and an outline together.
    let outline_job = format!("{with_jaws}\n[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]\n");
    let e = job_error(&outline_job, &dir);
    assert!(
        e.contains("operations[0].chuck.jaws") && e.contains("need chuck.body"),
        "{e}"
    );
    let both = job.replace(
        outline_line,
        &format!(
            "{}, jaws = {{ grip_diameter = 40.0 }} }}",
            outline_line.trim_end_matches(" }")
        ),
    );
    let e = job_error(&both, &dir);
    assert!(
        e.contains("operations[0].chuck.outline") && e.contains("not both"),
        "{e}"
    );
    let bad = job.replace(outline_line, "chuck = { jaws = { grip_diameter = 40.0, step = 60.0 } }");
    let e = job_error(&bad, &dir);
    assert!(e.contains("operations[0].chuck.jaws.step"), "{e}");
}

/// The lines where the interpreter marks an operation's start (a Fanuc program).
fn operation_marks(prog: &str, m: &Machine) -> Vec<u32> {
    let p = latheguard::gcode::parse_fanuc(prog.as_bytes());
    let run = latheguard::interp::interpret(&p, prog.as_bytes(), m);
    run.moves
        .iter()
        .filter(|mv| matches!(mv.kind, latheguard::interp::MoveKind::Operation { .. }))
        .map(|mv| mv.line)
        .collect()
}

#[test]
fn an_operation_by_work_offset_starts_at_the_first_block_that_selects_it() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("work_offset_start.job.toml")),
    );
    let m = apply(&job, "j.job.toml", &ops_dir()).unwrap();
    assert_eq!(m.operations[0].start, latheguard::machine::OpStart::WorkOffset(1));
    assert!(check(&prog, &m).is_empty());
    assert_eq!(operation_marks(&prog, &m), vec![20], "the first block with G55");
    // A G55 written as an expression, or a second G55, starts it at the first one all the same.
    let twice = prog
        .replacen("\nG55\n", "\nG[50+5]\n", 1)
        .replacen("G28 U0 W0\nT0404", "G55\nG28 U0 W0\nT0404", 1);
    assert_ne!(twice, prog);
    assert_eq!(operation_marks(&twice, &m), vec![20]);
    // The crash variant is found with this start too.
    let crash = read(&ops_dir().join("two_ops_rapid_into_shoulder.nc"));
    assert_eq!(facts(&check(&crash, &m))[0].0, 27);
}

#[test]
fn an_operation_by_a_work_offset_the_program_never_selects_is_a_warning() {
    let (prog, job) = (
        read(&ops_dir().join("two_ops.nc")),
        read(&ops_dir().join("work_offset_start.job.toml")),
    );
    let m = apply(&job.replace("\"G55\"", "\"G56\""), "j.job.toml", &ops_dir()).unwrap();
    let f = check(&prog, &m);
    let w: Vec<&Finding> = f.iter().filter(|f| f.kind == Kind::Program).collect();
    assert_eq!(w.len(), 1, "{f:#?}");
    assert!(
        w[0].message
            .contains("operations[0]: operation 2 never started: no block selected G56"),
        "{}",
        w[0].message
    );
}

/// The small LinuxCNC lathe (its tailstock advanced from the start) with a job's text applied.
fn on_small_lathe(text: &str) -> Result<Machine, String> {
    let m = latheguard::machine::from_toml(
        &read(&root().join("machines/linuxcnc-small-lathe.toml")),
        "linuxcnc-small-lathe.toml",
    )
    .unwrap();
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no file {rel}")) };
    let layer = job::parse(text, "t.job.toml", ".", "t.job.toml", &mut no_files).map_err(|e| e.to_string())?;
    job::apply(&m, &EffectiveJob::merge([&layer])).map_err(|e| e.to_string())
}

/// Nothing cut: the turret stands clear while the part is turned round at the M0 (line 4).
const AIR: &str = "G21 G18 G95 G97\nT1 M6\nG0 X30 Z20\nM0\nG0 X30 Z40\nM2\n";

#[test]
fn the_tailstock_as_it_stood_meets_the_part_turned_round_at_the_operations_line() {
    // Operation 1: the live centre at the bar's face (z 50, touching). Turned round and held
    // 8 mm: z -8 .. 72, and the centre, where it stood, is 22 mm inside.
    let job = "[tailstock]\nz = 50.0\n\n[[operations]]\nline = 4\nreverse = true\ngrip = 8.0\n";
    let f = check(AIR, &on_small_lathe(job).unwrap());
    assert_eq!(
        facts(&f),
        vec![(4, Kind::Collision, vec!["tailstock".into(), "stock".into()])],
        "{f:#?}"
    );
    assert_eq!(f[0].operation, Some(2));
    assert!(
        f[0].message
            .starts_with("t.job.toml:4:1: operations[0]: the tailstock in use (live centre at z 50) runs"),
        "{}",
        f[0].message
    );
    // Brought to the new face, or taken out of use: clean.
    for op in ["tailstock = { z = 72.0 }", "tailstock = { in_use = false }"] {
        let f = check(AIR, &on_small_lathe(&format!("{job}{op}\n")).unwrap());
        assert!(f.is_empty(), "{op}: {f:#?}");
    }
    // Not in use in operation 1 (the job's in_use = false) and brought in by the operation.
    let f = check(
        AIR,
        &on_small_lathe("[tailstock]\nin_use = false\n\n[[operations]]\nline = 4\nreverse = true\ngrip = 8.0\ntailstock = { in_use = true, z = 60.0 }\n").unwrap(),
    );
    assert_eq!(
        facts(&f),
        vec![(4, Kind::Collision, vec!["tailstock".into(), "stock".into()])],
        "{f:#?}"
    );
}

#[test]
fn the_tailstock_of_an_operation_against_its_jaws_is_an_error_of_the_job() {
    // The live centre brought to z -30: through the part, its r 10 .. 17 housing into the jaws
    // (r 12.5 .. 22 over z -8 .. 0).
    let job = "[[operations]]\nline = 4\nreverse = true\ngrip = 8.0\ntailstock = { z = -30.0 }\n";
    let f = check(AIR, &on_small_lathe(job).unwrap());
    let objects: Vec<Vec<String>> = f.iter().map(|f| f.objects.clone()).collect();
    assert!(
        objects.contains(&vec!["tailstock".to_string(), "chuck".to_string()]),
        "{f:#?}"
    );
    // Both of the job's errors at the operation's line (the move after it then meets the
    // tailstock standing where the job put it).
    let at_start: Vec<&Finding> = f.iter().filter(|f| f.line == 4).collect();
    assert_eq!(at_start.len(), 2, "{f:#?}");
    assert!(at_start.iter().all(|f| f.kind == Kind::Collision
        && f.message
            .starts_with("t.job.toml:1:1: operations[0]: the tailstock in use")));
}
