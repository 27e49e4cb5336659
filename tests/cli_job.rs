//! Jobs from the command line's point of view (docs/job.md): which layer wins, errors with
//! file:line:col:key and exit 2, a job that makes a crash program clean and one that makes a
//! clean program crash, and `latheguard setup` in text and JSON.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Output;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn fixtures() -> PathBuf {
    root().join("tests/fixtures/job")
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    common::latheguard(dir, args)
}

fn run(args: &[&str]) -> Output {
    run_in(root(), args)
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn setup_json(dir: &Path, args: &[&str]) -> serde_json::Value {
    let mut all = vec!["setup", "--format", "json"];
    all.extend_from_slice(args);
    let o = run_in(dir, &all);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    serde_json::from_str(&out(&o)).unwrap()
}

#[test]
fn a_job_that_thins_the_bar_makes_a_crash_program_clean() {
    let crash = run(&["check", "--no-timing", "programs/crash_rapid_into_bar.nc"]);
    assert_eq!(crash.status.code(), Some(1), "{}", out(&crash));
    let clean = run(&[
        "check",
        "--no-timing",
        "--job",
        "tests/fixtures/job/thin-bar.job.toml",
        "programs/crash_rapid_into_bar.nc",
    ]);
    assert_eq!(clean.status.code(), Some(0), "{}{}", out(&clean), err(&clean));
    // The same with the one-off flag.
    let flag = run(&["check", "--stock", "40x120@80", "programs/crash_rapid_into_bar.nc"]);
    assert_eq!(flag.status.code(), Some(0), "{}{}", out(&flag), err(&flag));
}

#[test]
fn a_job_with_a_fat_slug_makes_a_clean_program_crash() {
    let clean = run(&["check", "programs/od_turning.nc"]);
    assert_eq!(clean.status.code(), Some(0), "{}", out(&clean));
    let crash = run(&[
        "check",
        "--format",
        "json",
        "--no-timing",
        "--job",
        "tests/fixtures/job/fat-bar.job.toml",
        "programs/od_turning.nc",
    ]);
    assert_eq!(crash.status.code(), Some(1), "{}{}", out(&crash), err(&crash));
    let doc: serde_json::Value = serde_json::from_str(&out(&crash)).unwrap();
    let f = &doc["files"][0];
    // The first roughing pass buries the T01 holder in the 80 mm slug (a 50 mm bar it clears).
    assert_eq!(f["findings"][0]["kind"], "collision", "{f}");
    assert_eq!(f["findings"][0]["n"], 100, "{f}");
    // The report says which job applied to the file.
    assert_eq!(f["job"], serde_json::json!(["tests/fixtures/job/fat-bar.job.toml"]));
    // Without a job, a file carries no `job` key.
    let plain = run(&["check", "--format", "json", "--no-timing", "programs/od_turning.nc"]);
    let doc: serde_json::Value = serde_json::from_str(&out(&plain)).unwrap();
    assert!(doc["files"][0].get("job").is_none());
}

#[test]
fn every_layer_wins_over_the_one_below_it() {
    let tree = fixtures().join("tree");
    // cell/other.nc: the machine, then latheguard.toml's job (units, program zero, T05).
    let j = setup_json(&tree, &["cell/other.nc"]);
    assert_eq!(j["job"]["layers"], serde_json::json!(["base.job.toml"]));
    assert_eq!(
        j["units"],
        serde_json::json!({"value": "inch", "from": "base.job.toml"})
    );
    assert_eq!(j["program_zero_z"]["value"], 70.0);
    assert_eq!(j["program_zero_z"]["from"], "base.job.toml");
    assert_eq!(j["stock"]["from"], "machine");
    assert_eq!(j["tailstock"]["from"], "machine");
    let t5 = &j["tools"][4];
    assert_eq!(t5["station"], 5);
    assert_eq!(t5["name"], "Finisher from the library");
    assert_eq!(t5["from"], "base.job.toml");
    assert_eq!(t5["origin"], "use FIN-35 (../tools.toml)");
    assert_eq!(j["tools"][0]["from"], "machine");

    // cell/sub/part.nc: + the override's inline job (program zero, tailstock) + the file beside
    // it (stock; program zero stays the override's, which names it).
    let j = setup_json(&tree, &["cell/sub/part.nc"]);
    assert_eq!(
        j["job"]["layers"],
        serde_json::json!([
            "base.job.toml",
            "latheguard.toml override[0].job",
            "cell/sub/part.job.toml"
        ])
    );
    assert_eq!(j["program_zero_z"]["value"], 75.0);
    assert_eq!(j["program_zero_z"]["from"], "latheguard.toml override[0].job");
    assert_eq!(j["tailstock"]["from"], "latheguard.toml override[0].job");
    assert_eq!(j["tailstock"]["outline"], serde_json::Value::Null);
    assert_eq!(j["stock"]["from"], "cell/sub/part.job.toml");
    assert_eq!(j["stock"]["value"]["diameter"], 40.0);

    // + --job, then the one-off flags over everything.
    let job = fixtures().join("fat-bar.job.toml").display().to_string();
    let j = setup_json(&tree, &["cell/sub/part.nc", "--job", &job]);
    assert_eq!(j["stock"]["value"]["diameter"], 80.0);
    assert!(j["stock"]["from"].as_str().unwrap().ends_with("fat-bar.job.toml"));
    let tools = fixtures().join("station8.tools.toml").display().to_string();
    let j = setup_json(
        &tree,
        &[
            "cell/sub/part.nc",
            "--job",
            &job,
            "--stock",
            "30x60@55",
            "--units",
            "mm",
            "--program-zero",
            "50",
            "--tools",
            &tools,
        ],
    );
    assert_eq!(j["stock"]["value"]["diameter"], 30.0);
    assert_eq!(j["stock"]["from"], "command line");
    assert_eq!(j["units"], serde_json::json!({"value": "mm", "from": "command line"}));
    assert_eq!(j["program_zero_z"]["value"], 50.0);
    assert_eq!(j["tools"][7]["name"], "Flag tool");

    // --no-config leaves only the file beside the program.
    let j = setup_json(&tree, &["--no-config", "cell/sub/part.nc"]);
    assert_eq!(j["job"]["layers"], serde_json::json!(["cell/sub/part.job.toml"]));
    assert_eq!(j["units"]["from"], "machine");
}

#[test]
fn a_bad_job_file_stops_the_run_with_file_line_column_and_key() {
    let o = run(&[
        "check",
        "--job",
        "tests/fixtures/job/bad.job.toml",
        "programs/facing.nc",
    ]);
    assert_eq!(o.status.code(), Some(2));
    let e = err(&o);
    assert!(
        e.starts_with("latheguard: tests/fixtures/job/bad.job.toml:5:10: stock.length: must be greater than 0"),
        "{e}"
    );
    for cmd in ["moves", "setup", "accuracy"] {
        let o = run(&[cmd, "--job", "tests/fixtures/job/bad.job.toml", "programs/facing.nc"]);
        assert_eq!(o.status.code(), Some(2), "{cmd}");
        assert!(
            err(&o).contains("bad.job.toml:5:10: stock.length:"),
            "{cmd}: {}",
            err(&o)
        );
    }
    // A job that does not fit the machine: the key of the job that caused it.
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(root().join("programs/facing.nc"), dir.path().join("p.nc")).unwrap();
    std::fs::write(
        dir.path().join("p.job.toml"),
        "[stock]\ndiameter = 60\nlength = 120\nstick_out = 80\n",
    )
    .unwrap();
    let o = run_in(dir.path(), &["check", "p.nc"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err(&o).starts_with("latheguard: p.job.toml:2:12: stock.diameter: the bar"),
        "{}",
        err(&o)
    );
    // A bad --stock is a usage error (exit 2).
    let o = run(&["check", "--stock", "fat", "programs/facing.nc"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(err(&o).contains("--stock: `fat` is not a stock"), "{}", err(&o));
    // An error in an inline job of latheguard.toml names the whole key.
    std::fs::write(dir.path().join("p.job.toml"), "").unwrap();
    std::fs::write(dir.path().join("latheguard.toml"), "[job]\nunits = \"furlong\"\n").unwrap();
    let o = run_in(dir.path(), &["check", "p.nc"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err(&o).starts_with("latheguard: latheguard.toml:2:9: job.units: unknown value `furlong`"),
        "{}",
        err(&o)
    );
}

#[test]
fn job_files_beside_programs_are_never_checked_as_programs() {
    let o = run_in(
        &fixtures().join("tree"),
        &["check", "--ext", "nc,toml", "--format", "json", "--no-timing", "."],
    );
    let doc: serde_json::Value = serde_json::from_str(&out(&o)).unwrap();
    let paths: Vec<&str> = doc["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, vec!["cell/other.nc", "cell/sub/part.nc"]);
}

#[test]
fn setup_prints_each_layer_and_where_each_value_came_from() {
    let tree = fixtures().join("tree");
    let o = run_in(&tree, &["setup", "cell/sub/part.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    insta::assert_snapshot!("setup_text", out(&o));
    let o = run_in(&tree, &["setup", "--format", "json", "cell/other.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    insta::assert_snapshot!("setup_json", out(&o));
}

#[test]
fn the_committed_job_schema_is_the_generated_one_and_the_fixtures_validate() {
    let committed = std::fs::read_to_string(root().join("machines/job.schema.json")).unwrap();
    assert_eq!(
        committed,
        latheguard::job::schema(),
        "run `cargo run -- schema job > machines/job.schema.json`"
    );
    let schema: serde_json::Value = serde_json::from_str(&committed).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let mut n = 0;
    for dir in [fixtures(), fixtures().join("tree"), fixtures().join("tree/cell/sub")] {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !name.ends_with(".job.toml") {
                continue;
            }
            let doc: toml::Value = toml::from_str(&std::fs::read_to_string(e.path()).unwrap()).unwrap();
            let doc = serde_json::to_value(doc).unwrap();
            let errors: Vec<String> = validator.iter_errors(&doc).map(|e| e.to_string()).collect();
            assert!(errors.is_empty(), "{name}: {errors:?}");
            n += 1;
        }
    }
    assert!(n >= 4, "{n}");
    let typo = serde_json::json!({"stock": {"diameter": 40, "lenght": 100}});
    assert!(!validator.is_valid(&typo), "an unknown key is refused");
    let config = std::fs::read_to_string(root().join("machines/config.schema.json")).unwrap();
    assert_eq!(
        config,
        out(&run(&["schema", "config"])),
        "run `cargo run -- schema config > machines/config.schema.json`"
    );
}

fn check_json(args: &[&str]) -> (Option<i32>, serde_json::Value) {
    let mut all = vec!["check", "--format", "json", "--no-timing"];
    all.extend_from_slice(args);
    let o = run(&all);
    let doc = serde_json::from_str(&out(&o)).unwrap_or_else(|_| panic!("{}{}", out(&o), err(&o)));
    (o.status.code(), doc)
}

/// The file lines of the findings of the first file of a JSON report, with their kinds.
fn finding_lines(doc: &serde_json::Value) -> Vec<(u64, String)> {
    doc["files"][0]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| (f["line"].as_u64().unwrap(), f["kind"].as_str().unwrap().to_string()))
        .collect()
}

#[test]
fn an_outline_stock_is_cut_where_its_outline_is_not_where_its_bounding_bar_is() {
    let job = "tests/fixtures/job/flange-second-op.job.toml";
    // X44 at Z-10 passes over the Ø30 boss: clean with the outline, a crash for any Ø80 bar.
    let o = run(&["check", "--no-timing", "--job", job, "programs/crash_rapid_into_bar.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    let o = run(&[
        "check",
        "--no-timing",
        "--stock",
        "80x80@80",
        "programs/crash_rapid_into_bar.nc",
    ]);
    assert_eq!(o.status.code(), Some(1), "{}{}", out(&o), err(&o));
    // A rapid into the flange is caught at its line (N80 is line 10).
    let (code, doc) = check_json(&["--job", job, "tests/fixtures/job/flange-rapid.nc"]);
    assert_eq!(code, Some(1), "{doc}");
    let lines = finding_lines(&doc);
    assert_eq!(lines.first().map(|l| l.0), Some(10), "{doc}");
    // Without the outline (the built-in Ø50 bar) the same program is clean: the flange did it.
    let o = run(&["check", "--no-timing", "tests/fixtures/job/flange-rapid.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
}

#[test]
fn an_outline_stock_shows_in_setup_and_stock_out() {
    let job = "tests/fixtures/job/flange-second-op.job.toml";
    let doc = setup_json(root(), &["--job", job, "programs/facing.nc"]);
    let st = &doc["stock"]["value"];
    assert_eq!(st["outline"].as_array().map(|a| a.len()), Some(8), "{doc}");
    assert_eq!(st["diameter"], 80.0, "{doc}");
    assert_eq!(doc["program_zero_z"]["value"], 80.0, "{doc}");
    let o = run(&["setup", "--job", job, "programs/facing.nc"]);
    assert!(
        out(&o).contains("stock         revolved outline, Ø80 max, z -40 .. 80 (8 points)"),
        "{}",
        out(&o)
    );
    // --stock-out draws the part as cut from the outline (a program that cuts nothing of it
    // leaves the flange there: the picture reaches radius 40).
    let dir = tempfile::tempdir().unwrap();
    let svg = dir.path().join("part.svg");
    let o = run(&[
        "check",
        "--no-timing",
        "--job",
        job,
        "--stock-out",
        svg.to_str().unwrap(),
        "programs/crash_rapid_into_bar.nc",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg"), "{text}");
}

#[test]
fn an_outline_stock_that_reaches_into_the_jaws_is_an_error_naming_the_outline() {
    let o = run(&[
        "check",
        "--job",
        "tests/fixtures/job/flange-too-wide.job.toml",
        "programs/facing.nc",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", out(&o));
    assert!(
        err(&o).starts_with(
            "latheguard: tests/fixtures/job/flange-too-wide.job.toml:3:11: stock.outline: the stock outline"
        ),
        "{}",
        err(&o)
    );
}

#[test]
fn a_job_without_stock_is_a_dry_run_in_the_air() {
    let crash = run(&["check", "--no-timing", "programs/crash_rapid_into_bar.nc"]);
    assert_eq!(crash.status.code(), Some(1));
    let o = run(&[
        "check",
        "--no-timing",
        "--job",
        "tests/fixtures/job/no-stock.job.toml",
        "programs/crash_rapid_into_bar.nc",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    let doc = setup_json(
        root(),
        &["--job", "tests/fixtures/job/no-stock.job.toml", "programs/facing.nc"],
    );
    assert!(doc["stock"]["value"].is_null(), "{doc}");
    // Program zero stays the machine's (78), not a stock's face.
    assert_eq!(doc["program_zero_z"]["value"], 78.0, "{doc}");
    assert_eq!(doc["program_zero_z"]["from"], "machine", "{doc}");
}

#[test]
fn a_spindle_started_by_hand_lets_a_program_without_m3_cut() {
    let prog = "tests/fixtures/job/no-spindle.nc";
    let (code, doc) = check_json(&[prog]);
    assert_eq!(code, Some(1), "{doc}");
    let lines = finding_lines(&doc);
    assert!(
        lines.iter().any(|(l, _)| *l == 7),
        "the cut at N50 (line 7) with the spindle stopped: {doc}"
    );
    assert!(lines.iter().any(|(l, k)| *l == 7 && k == "spindle_stopped"), "{doc}");
    let (code, doc) = check_json(&["--job", "tests/fixtures/job/spindle-on.job.toml", prog]);
    assert_eq!(code, Some(0), "{doc}");
    let doc = setup_json(root(), &["--job", "tests/fixtures/job/spindle-on.job.toml", prog]);
    assert_eq!(doc["spindle_start_rpm"]["value"], 800.0, "{doc}");
}

#[test]
fn a_manual_tool_change_runs_the_rest_with_that_stations_tool() {
    let prog = "tests/fixtures/job/wide-tool-change.nc";
    let o = run(&["check", "--no-timing", prog]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    // The same tool in station 2 but no tool change: still clean (T01 does the moves).
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(fixtures().join("tool-change.job.toml")).unwrap();
    let without = dir.path().join("no-change.job.toml");
    std::fs::write(&without, text.split("[[tool_changes]]").next().unwrap()).unwrap();
    let o = run(&["check", "--no-timing", "--job", without.to_str().unwrap(), prog]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
    // With the change at line 8, the wide holder meets the bar at N80 (line 10).
    let (code, doc) = check_json(&["--job", "tests/fixtures/job/tool-change.job.toml", prog]);
    assert_eq!(code, Some(1), "{doc}");
    let lines = finding_lines(&doc);
    assert_eq!(lines.first(), Some(&(10, "collision".to_string())), "{doc}");
    // The interpreter changes the tool at line 8, as a T word would.
    let o = run(&["moves", "--job", "tests/fixtures/job/tool-change.job.toml", prog]);
    assert!(out(&o).contains("    8 CHANGE_TOOL(2)"), "{}", out(&o));
    let o = run(&["setup", "--job", "tests/fixtures/job/tool-change.job.toml", prog]);
    assert!(
        out(&o).contains("tool change   at line 8: the operator puts in T02 wide form tool"),
        "{}",
        out(&o)
    );
    // A change to a station that holds no tool is refused, at the change.
    std::fs::write(&without, "[[tool_changes]]\nline = 8\nstation = 9\n").unwrap();
    let o = run(&["check", "--job", without.to_str().unwrap(), prog]);
    assert_eq!(o.status.code(), Some(2), "{}", out(&o));
    assert!(
        err(&o).contains(":1:1: tool_changes[0].station: station 9 holds no tool"),
        "{}",
        err(&o)
    );
}

#[test]
fn a_job_moves_the_tailstock_and_sets_diameter_mode() {
    let m = "machines/linuxcnc-small-lathe.toml";
    let doc = setup_json(
        root(),
        &[
            "--machine",
            m,
            "--job",
            "tests/fixtures/job/tailstock-z.job.toml",
            "programs/facing.nc",
        ],
    );
    let pts = doc["tailstock"]["outline"].as_array().unwrap();
    let min_z = pts.iter().map(|p| p[1].as_f64().unwrap()).fold(f64::INFINITY, f64::min);
    assert_eq!(min_z, 150.0, "{doc}");
    assert_eq!(doc["tailstock"]["advanced_at_start"], true, "{doc}");
    // The built-in machine has no tailstock to move.
    let o = run(&[
        "check",
        "--job",
        "tests/fixtures/job/tailstock-z.job.toml",
        "programs/facing.nc",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(err(&o).contains("tailstock"), "{}", err(&o));
    // Radius mode: X44 is a radius of 44, outside the Ø50 bar.
    let job = "tests/fixtures/job/radius-mode.job.toml";
    let doc = setup_json(root(), &["--job", job, "programs/facing.nc"]);
    assert_eq!(doc["diameter_mode"]["value"], false, "{doc}");
    let o = run(&["check", "--no-timing", "--job", job, "programs/crash_rapid_into_bar.nc"]);
    assert_eq!(o.status.code(), Some(0), "{}{}", out(&o), err(&o));
}

#[test]
fn setup_lists_the_tool_numbers_and_the_tools_the_table_shaped() {
    let m = "machines/linuxcnc-small-lathe.toml";
    let prog = "tests/cases/tools/tnum_from_table.ngc";
    let o = run(&["setup", "--machine", m, prog]);
    let text = out(&o);
    let table = "tests/fixtures/tools/small-lathe-mm.tbl";
    let line = text
        .lines()
        .find(|l| l.contains("tool numbers"))
        .unwrap_or_else(|| panic!("{text}"));
    assert!(
        line.starts_with(&format!(
            "  tool numbers  T7 → station 4; T12 → station 1, T13 → station 3, T14 → station 4, T21 → station 2 ({table} pockets)  [tests/cases/tools/tnum_from_table.job.toml]"
        )),
        "{text}"
    );
    assert!(text.contains("    T02 OD finish  tip [-40, -10]"), "{text}");
    assert!(text.contains(&format!("tbl 21 ({table})]")), "{text}");
    let j = setup_json(root(), &["--machine", m, prog]);
    let rows = j["tool_numbers"].as_array().unwrap();
    assert_eq!(rows.len(), 5, "{j}");
    assert_eq!(
        (&rows[0]["tool"], &rows[0]["station"], &rows[0]["table"]),
        (&serde_json::json!(7), &serde_json::json!(4), &serde_json::Value::Null),
        "{j}"
    );
    assert_eq!(
        (&rows[1]["tool"], &rows[1]["station"]),
        (&serde_json::json!(12), &serde_json::json!(1))
    );
    assert_eq!(rows[1]["table"], serde_json::json!(table));
    // Without a map, setup says nothing of tool numbers.
    let o = run(&["setup", "--machine", m, "tests/cases/tools/tnum_unmapped.ngc"]);
    assert!(!out(&o).contains("tool numbers"), "{}", out(&o));
}

#[test]
fn a_tool_number_the_map_lacks_is_an_error_at_its_t_word_naming_the_key_to_add() {
    let m = "machines/linuxcnc-small-lathe.toml";
    let (code, doc) = check_json(&["--machine", m, "tests/cases/tools/tnum_from_table.ngc"]);
    assert_eq!(code, Some(1), "{doc}");
    let f = &doc["files"][0]["findings"][0];
    assert_eq!(
        (f["line"].as_u64(), f["kind"].as_str()),
        (Some(13), Some("program")),
        "{doc}"
    );
    assert_eq!(
        f["message"].as_str(),
        Some("T9: tool 9 is in no station: add tool_numbers.T9 = STATION to the job (or list it in its tool_table); the moves after M6 until the next tool change are not checked"),
        "{doc}"
    );
    // Without the map the old error: T12 read as a station of the 4-station turret.
    let (_, doc) = check_json(&["--machine", m, "tests/cases/tools/tnum_unmapped.ngc"]);
    let f = &doc["files"][0]["findings"][0];
    assert!(
        f["message"]
            .as_str()
            .unwrap()
            .starts_with("T12: the turret has no station 12 (it has 1 to 4"),
        "{doc}"
    );
}
