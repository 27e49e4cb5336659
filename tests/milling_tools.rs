//! Milling tools given by their sizes in a job (issue 16; docs/tools.md, "Milling tools"): the
//! station's 3D parts are built from them on the turn-mill machine, the milled stock cuts with
//! them, and bad sizes are refused with their key.

use std::process::{Command, Output};

const DIR: &str = "tests/fixtures/milling-job";

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap()
}

fn check(job: &str, program: &str) -> serde_json::Value {
    let out = run(&[
        "check",
        "--machine",
        "machines/turn-mill.toml",
        "--job",
        job,
        "--format",
        "json",
        program,
    ]);
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}: {}", String::from_utf8_lossy(&out.stderr)))
}

#[test]
fn a_job_radial_drill_fed_into_the_jaws_is_a_collision_of_its_generated_cutter() {
    let doc = check(
        &format!("{DIR}/drill12.job.toml"),
        &format!("{DIR}/crash_drill_into_jaws.nc"),
    );
    let f = &doc["files"][0]["findings"];
    let all: Vec<_> = f
        .as_array()
        .unwrap()
        .iter()
        .map(|x| {
            (
                x["line"].as_u64().unwrap(),
                x["kind"].as_str().unwrap(),
                x["objects"].clone(),
                x["severity"].as_str().unwrap(),
            )
        })
        .collect();
    // Issue 26: the rapid to Z-80. (z -2) first drives T11's axial end mill, on the next station
    // (30° round the drum, 105 mm below the turret's reference point), 7 mm into the headstock's
    // face at z -100 — hidden while only the active station was checked; the job drill's crash
    // into the jaws is a crash of its own (other parts: not a follow-on).
    assert_eq!(
        all,
        vec![
            (11, "collision", serde_json::json!(["t11_mill", "headstock"]), "error"),
            (
                12,
                "collision",
                serde_json::json!(["t12_cutter", "main_chuck"]),
                "error"
            ),
        ],
        "{f:#}"
    );
}

#[test]
fn a_radial_hole_with_the_job_drill_is_clean_and_cut_into_the_milled_stock() {
    let doc = check(&format!("{DIR}/drill12.job.toml"), &format!("{DIR}/radial_hole.nc"));
    let file = &doc["files"][0];
    assert_eq!(file["status"], "clean", "{file:#}");
    let effects = file["stats"]["effects"].as_array().unwrap();
    assert!(effects.iter().any(|e| e == "grid_stock"), "{effects:?}");
}

/// The job's setup lists the tool with what its sizes were read as.
#[test]
fn setup_shows_the_milling_tool_as_read() {
    let out = run(&[
        "setup",
        "--machine",
        "machines/turn-mill.toml",
        "--job",
        &format!("{DIR}/drill12.job.toml"),
        &format!("{DIR}/radial_hole.nc"),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("T12 Radial live drill D8  tip [-130, 0]")
            && text.contains("mill: drill, 118° point Ø8, 40 flutes, 50 out of a Ø35 × 25 holder, radial"),
        "{text}"
    );
}

#[test]
fn bad_milling_tool_entries_are_refused_with_file_line_and_key() {
    let dir = std::env::temp_dir().join(format!("lg-mill-job-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string(format!("{}/{DIR}/drill12.job.toml", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let cases = [
        ("live = \"radial\"\n", "", "tools[0].live: a milling tool needs `live"),
        (
            "live = \"radial\"",
            "live = \"sideways\"",
            "tools[0].live: \"sideways\" is not a live station",
        ),
        (
            "type = \"drill\"",
            "type = \"reamer\"",
            "tools[0].mill: cannot build the milling tool: type \"reamer\"",
        ),
        (
            "stick_out = 50",
            "stick_out = 30",
            "stick_out 30 mm is shorter than the flutes (40 mm)",
        ),
        (
            "diameter = 35",
            "diameter = 6",
            "holder.diameter 6 mm is less than the shank (8 mm)",
        ),
        ("diameter = 8,", "diameter = -8,", "tools[0].mill.diameter"),
        (
            "holder = { diameter = 35, length = 25 }",
            "holder = 35",
            "tools[0].mill.holder",
        ),
    ];
    for (from, to, want) in cases {
        assert!(base.contains(from), "{from}");
        let job = dir.join("bad.job.toml");
        std::fs::write(&job, base.replacen(from, to, 1)).unwrap();
        let out = run(&[
            "check",
            "--machine",
            "machines/turn-mill.toml",
            "--job",
            job.to_str().unwrap(),
            &format!("{DIR}/radial_hole.nc"),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{to}: {err}");
        assert!(err.contains("bad.job.toml:") && err.contains(want), "{to}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
