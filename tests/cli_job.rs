//! Jobs from the command line's point of view (docs/job.md): which layer wins, errors with
//! file:line:col:key and exit 2, a job that makes a crash program clean and one that makes a
//! clean program crash, and `latheguard setup` in text and JSON.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn fixtures() -> PathBuf {
    root().join("tests/fixtures/job")
}

fn run_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(args)
        .current_dir(dir)
        .env("CI", "true")
        .output()
        .unwrap()
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
