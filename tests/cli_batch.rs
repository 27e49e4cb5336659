//! The batch checker end to end: folders, per-folder configuration, exit codes, parallel and
//! sharded runs, and the CI formats' structure (the binary run on a copy of `tests/fixtures/tree`).

use crate::common;

use common::{json, latheguard, stderr, stdout, Tree};
use latheguard::finding::Kind;
use std::collections::BTreeMap;

/// Every file of a JSON report: path → (status, kinds of its findings).
fn results(doc: &serde_json::Value) -> BTreeMap<String, (String, Vec<String>)> {
    doc["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            let kinds = f["findings"].as_array().unwrap().iter();
            (
                f["path"].as_str().unwrap().to_string(),
                (
                    f["status"].as_str().unwrap().to_string(),
                    kinds.map(|x| x["kind"].as_str().unwrap().to_string()).collect(),
                ),
            )
        })
        .collect()
}

fn expect(rows: &[(&str, &str, &[&str])]) -> BTreeMap<String, (String, Vec<String>)> {
    rows.iter()
        .map(|(p, s, k)| {
            (
                p.to_string(),
                (s.to_string(), k.iter().map(|x| x.to_string()).collect()),
            )
        })
        .collect()
}

#[test]
fn tree_gives_the_expected_results_per_file_and_exit_code() {
    let t = Tree::new();
    let out = t.run(&["check", "--format", "json", "--no-timing", "."]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    let doc = json(&out);
    assert_eq!(
        results(&doc),
        expect(&[
            ("cell-a/crash_holder.nc", "findings", &["collision", "collision"]),
            (
                "cell-a/garbage.nc",
                "findings",
                &["syntax", "syntax", "syntax", "syntax"]
            ),
            ("cell-a/od_turning.nc", "clean", &[]),
            ("cell-a/unreadable.nc", "findings", &["syntax"]),
            // cell-b: exact mode; only the legacy folder asks for 0.5 mm of clearance.
            ("cell-b/legacy/facing.nc", "clean", &[]),
            ("cell-b/legacy/near_miss.nc", "findings", &["near_miss"]),
            ("cell-b/near_miss.nc", "clean", &[]),
            // cell-c: the LinuxCNC lathe; the unknown M code is a warning.
            ("cell-c/flow.ngc", "clean", &[]),
            ("cell-c/unsupported.ngc", "findings", &["unsupported"]),
        ])
    );
    assert_eq!(doc["summary"]["files"], 9);
    // The near miss and the unknown M code (crash_holder's holder reaching the chuck while its
    // insert is in it is a crash of its own: other parts).
    assert_eq!(doc["summary"]["warnings"], 2);
    // The report's machine and settings are the first file's; the others carry their own.
    assert_eq!(doc["machine"], "Generic 2-axis slant-bed lathe");
    assert_eq!(doc["settings"]["mode"], "step");
    let file = |p: &str| {
        doc["files"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["path"] == p)
            .unwrap()
            .clone()
    };
    assert!(file("cell-a/od_turning.nc").get("settings").is_none());
    assert_eq!(file("cell-b/near_miss.nc")["settings"]["mode"], "exact");
    assert_eq!(file("cell-b/near_miss.nc")["settings"]["clearance_mm"], 0.0);
    assert_eq!(file("cell-b/legacy/near_miss.nc")["settings"]["clearance_mm"], 0.5);
    assert!(file("cell-b/near_miss.nc").get("machine").is_none());
    assert_eq!(file("cell-c/flow.ngc")["machine"], "Small LinuxCNC bench lathe");
    assert!(file("cell-a/unreadable.nc")["findings"][0]["message"]
        .as_str()
        .unwrap()
        .starts_with("cannot read the file"));
    // --no-timing: no run time in the report.
    assert_eq!(file("cell-a/od_turning.nc")["stats"]["elapsed_ms"], 0.0);
}

#[test]
fn warnings_alone_exit_0_and_a_clean_file_exits_0() {
    let t = Tree::new();
    let out = t.run(&["check", "cell-b", "cell-c"]);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    assert!(stdout(&out).contains("checked 5 files: 3 clean, 2 with findings (0 errors, 2 warnings)"));
    let out = t.run(&["check", "cell-a/od_turning.nc"]);
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn the_command_line_overrides_the_configuration() {
    let t = Tree::new();
    let out = t.run(&[
        "check",
        "--format",
        "json",
        "--mode",
        "step",
        "--clearance",
        "0.5",
        "cell-b",
    ]);
    let doc = json(&out);
    assert_eq!(doc["settings"]["mode"], "step");
    assert_eq!(doc["settings"]["clearance_mm"], 0.5);
    let r = results(&doc);
    assert_eq!(r["cell-b/near_miss.nc"].1, vec!["near_miss"]);
    // -m replaces every configuration's machine.
    let m = common::fixtures().join("tree/machines/slant-bed.toml");
    let out = t.run(&["check", "--format", "json", "-m", m.to_str().unwrap(), "cell-c"]);
    let doc = json(&out);
    assert_eq!(doc["machine"], "Generic 2-axis slant-bed lathe");
    assert!(doc["files"]
        .as_array()
        .unwrap()
        .iter()
        .all(|f| f.get("machine").is_none()));
    // --no-config: the built-in machine everywhere.
    let out = t.run(&["check", "--format", "json", "--no-config", "--no-assume", "cell-b"]);
    let doc = json(&out);
    assert!(doc["files"].as_array().unwrap().iter().all(|f| f["status"] == "clean"));
    assert_eq!(doc["settings"]["mode"], "step");
}

#[test]
fn a_bad_configuration_stops_with_exit_2_and_its_place() {
    let t = Tree::new();
    std::fs::write(
        t.path().join("cell-b/latheguard.toml"),
        "machine = \"../machines/slant-bed.toml\"\nmode = \"exact\"\nclerance = 0.5\n",
    )
    .unwrap();
    let out = t.run(&["check", "."]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stdout(&out).is_empty());
    assert!(
        stderr(&out).contains("cell-b/latheguard.toml:3:1: clerance: unknown field `clerance`"),
        "{}",
        stderr(&out)
    );
    // A configuration naming a machine file that is not there.
    std::fs::write(
        t.path().join("cell-b/latheguard.toml"),
        "\nmachine = \"../machines/nope.toml\"\n",
    )
    .unwrap();
    let out = t.run(&["check", "cell-b"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cell-b/latheguard.toml:2:11: machine: cannot read machine file machines/nope.toml"),
        "{}",
        stderr(&out)
    );
    // A configuration naming an invalid machine file: the machine file's own place.
    std::fs::write(
        t.path().join("machines/bad.toml"),
        "[machine]\nname = \"x\"\nspeed = 1\n",
    )
    .unwrap();
    std::fs::write(
        t.path().join("cell-b/latheguard.toml"),
        "machine = \"../machines/bad.toml\"\n",
    )
    .unwrap();
    let out = t.run(&["check", "cell-b"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("machines/bad.toml:3:1"), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cell-b/latheguard.toml:1:11: machine"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_arguments_exit_2() {
    let t = Tree::new();
    for args in [
        &["check", "--shard", "4/3", "."][..],
        &["check", "--shard", "0/3", "."],
        &["check", "--jobs", "0", "."],
        &["check", "--format", "xml", "."],
        &["check", "--dt", "-1", "."],
    ] {
        let out = t.run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
    }
}

#[test]
fn walking_honours_gitignore_hidden_folders_and_extensions() {
    let t = Tree::new();
    let doc = json(&t.run(&["check", "--format", "json", "."]));
    let paths: Vec<String> = results(&doc).into_keys().collect();
    assert!(!paths
        .iter()
        .any(|p| p.contains("scratch") || p.contains(".hidden") || p.contains("old-crash")));
    assert!(!paths.iter().any(|p| p.ends_with(".md") || p.ends_with(".toml")));
    // --ext picks other files; a file named directly is always checked.
    let doc = json(&t.run(&["check", "--format", "json", "--ext", "md,NGC", "."]));
    let paths: Vec<String> = results(&doc).into_keys().collect();
    assert_eq!(paths, ["cell-a/notes.md", "cell-c/flow.ngc", "cell-c/unsupported.ngc"]);
    let doc = json(&t.run(&["check", "--format", "json", "cell-a/scratch/ignored.nc"]));
    assert_eq!(results(&doc).len(), 1);
}

#[test]
fn two_runs_give_byte_identical_output_whatever_the_jobs() {
    let t = Tree::new();
    for format in ["text", "json", "junit", "sarif"] {
        let one = t.run(&["check", "--no-timing", "--format", format, "--jobs", "1", "."]);
        let two = t.run(&["check", "--no-timing", "--format", format, "--jobs", "2", "."]);
        let again = t.run(&["check", "--no-timing", "--format", format, "--jobs", "2", "."]);
        assert!(!one.stdout.is_empty());
        assert_eq!(one.stdout, two.stdout, "{format}");
        assert_eq!(two.stdout, again.stdout, "{format}");
    }
}

#[test]
fn shards_cover_every_file_exactly_once() {
    let t = Tree::new();
    let all: Vec<String> = results(&json(&t.run(&["check", "--format", "json", "."])))
        .into_keys()
        .collect();
    let mut seen = Vec::new();
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let part: Vec<String> = results(&json(&t.run(&["check", "--format", "json", "--shard", &shard, "."])))
            .into_keys()
            .collect();
        assert!(part.len() == 3, "{shard}: {part:?}");
        seen.extend(part);
    }
    seen.sort();
    assert_eq!(seen, all);
}

#[test]
fn junit_parses_with_the_right_counts() {
    let t = Tree::new();
    let out = t.run(&["check", "--format", "junit", "."]);
    assert_eq!(out.status.code(), Some(1));
    let xml = stdout(&out);
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "testsuites");
    assert_eq!(root.attribute("tests"), Some("9"));
    assert_eq!(root.attribute("failures"), Some("3"));
    assert!(root.attribute("time").is_some());
    let cases: Vec<_> = doc.descendants().filter(|n| n.has_tag_name("testcase")).collect();
    assert_eq!(cases.len(), 9);
    let failed: Vec<&str> = cases
        .iter()
        .filter(|c| c.children().any(|n| n.has_tag_name("failure")))
        .map(|c| c.attribute("name").unwrap())
        .collect();
    assert_eq!(
        failed,
        ["cell-a/crash_holder.nc", "cell-a/garbage.nc", "cell-a/unreadable.nc"]
    );
    let crash = cases
        .iter()
        .find(|c| c.attribute("name") == Some("cell-a/crash_holder.nc"))
        .unwrap();
    let failure = crash.children().find(|n| n.has_tag_name("failure")).unwrap();
    assert_eq!(failure.attribute("type"), Some("collision"));
    let body = failure.text().unwrap();
    assert_eq!(
        body.lines().filter(|l| l.starts_with("line ")).count(),
        2,
        "one entry per finding: {body}"
    );
    // Each with the programmed point and its source line.
    assert!(body.contains("X140 Z-108"), "{body}");
    assert!(
        body.contains("    | N70 Z-120. (Z-120 IS 42 MM BEHIND THE JAW FACES)"),
        "{body}"
    );
    // A warning does not fail its test case; it is in its output.
    let warned = cases
        .iter()
        .find(|c| c.attribute("name") == Some("cell-c/unsupported.ngc"))
        .unwrap();
    assert!(warned.children().any(|n| n.has_tag_name("system-out")));
    // Without timing, no time attributes at all.
    let xml = stdout(&t.run(&["check", "--format", "junit", "--no-timing", "."]));
    assert!(!xml.contains("time="));
}

#[test]
fn sarif_validates_against_the_sarif_2_1_0_schema() {
    let t = Tree::new();
    let out = t.run(&["check", "--format", "sarif", "."]);
    assert_eq!(out.status.code(), Some(1));
    let log = json(&out);
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(common::fixtures().join("sarif-schema-2.1.0.json")).unwrap())
            .unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let errors: Vec<String> = validator
        .iter_errors(&log)
        .map(|e| format!("{} at {}", e, e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{errors:#?}");
    // And the schema does catch a broken log.
    let mut broken = log.clone();
    broken["runs"][0]["results"][0]["level"] = "fatal".into();
    assert!(!validator.is_valid(&broken));

    let run = &log["runs"][0];
    let rules = run["tool"]["driver"]["rules"].as_array().unwrap();
    assert_eq!(rules.len(), Kind::ALL.len(), "one rule per finding kind");
    assert!(rules
        .iter()
        .all(|r| r["help"]["markdown"].as_str().unwrap().contains("## What it means")));
    let results = run["results"].as_array().unwrap();
    assert_eq!(results.len(), 9);
    let first = &results[0];
    assert_eq!(first["ruleId"], "LG01");
    assert_eq!(first["level"], "error");
    let loc = &first["locations"][0]["physicalLocation"];
    assert_eq!(loc["artifactLocation"]["uri"], "cell-a/crash_holder.nc");
    assert_eq!(loc["region"]["startLine"], 10);
    let warning = results.iter().find(|r| r["ruleId"] == "LG12").unwrap();
    assert_eq!(warning["level"], "warning");
    // No address of the published pages is known to this build: no helpUri.
    assert!(rules.iter().all(|r| r.get("helpUri").is_none()));
}

#[test]
fn sarif_rules_link_to_their_page_where_the_docs_are_published() {
    let t = Tree::new();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["check", "--format", "sarif", "."])
        .current_dir(t.path())
        .env("LATHEGUARD_DOCS_URL", "https://example.com/latheguard/docs/findings/")
        .output()
        .unwrap();
    let log = json(&out);
    let rules = log["runs"][0]["tool"]["driver"]["rules"].as_array().unwrap();
    let collision = rules.iter().find(|r| r["name"] == "collision").unwrap();
    assert_eq!(
        collision["helpUri"],
        "https://example.com/latheguard/docs/findings/collision.md"
    );
    assert!(rules.iter().all(|r| r["helpUri"].as_str().unwrap().ends_with(".md")));
}

#[test]
fn pictures_are_written_for_findings_with_a_scene() {
    let t = Tree::new();
    let out = t.run(&["check", "--svg", "pictures", "cell-a", "cell-b"]);
    assert_eq!(out.status.code(), Some(1));
    let mut names: Vec<String> = std::fs::read_dir(t.path().join("pictures"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "cell-a__crash_holder.nc.L10.collision.T01-holder.chuck.svg",
            "cell-a__crash_holder.nc.L10.collision.T01-insert.chuck.svg",
            "cell-b__legacy__near_miss.nc.L9.near_miss.T01-insert.chuck.svg",
        ]
    );
    for n in &names {
        let svg = std::fs::read_to_string(t.path().join("pictures").join(n)).unwrap();
        let doc = roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{n}: {e}"));
        assert_eq!(doc.root_element().tag_name().name(), "svg");
    }
    assert!(stderr(&out).contains("wrote 3 pictures to pictures"));
}

#[test]
fn shell_completions_man_pages_and_colour() {
    let here = std::env::temp_dir();
    let bash = latheguard(&here, &["completions", "bash"]);
    assert_eq!(bash.status.code(), Some(0));
    assert!(stdout(&bash).contains("--shard"));
    let man = latheguard(&here, &["man"]);
    assert!(stdout(&man).starts_with(".ie"));
    assert!(stdout(&man).contains(".TH latheguard"));
    let dir = tempfile::tempdir().unwrap();
    let out = latheguard(dir.path(), &["man", "pages"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(dir.path().join("pages/latheguard-check.1").is_file());

    let t = Tree::new();
    let always = stdout(&t.run(&["check", "--color", "always", "cell-a/crash_holder.nc"]));
    assert!(always.contains("\x1b["));
    let never = stdout(&t.run(&["--color", "never", "check", "cell-a/crash_holder.nc"]));
    assert!(!never.contains("\x1b["));
    // In a pipe, auto means no colour and no progress bar.
    let auto = t.run(&["check", "cell-a/crash_holder.nc"]);
    assert!(!stdout(&auto).contains("\x1b["));
    assert!(stderr(&auto).is_empty());
    let quiet = stdout(&t.run(&["check", "--quiet", "."]));
    assert!(!quiet.contains("warning["));
    assert!(!quiet.contains(" | "));
}

/// Every number of a JSON report is rounded to six decimals (nm and µs), nested ones too: the
/// time of the crash a follow-on names was once printed raw (29.512500250000002).
#[test]
fn every_number_of_the_json_report_has_at_most_six_decimals() {
    fn walk(v: &serde_json::Value, path: &str, bad: &mut Vec<String>) {
        match v {
            serde_json::Value::Number(n) => {
                if let Some(x) = n.as_f64() {
                    if ((x * 1e6).round() / 1e6 - x).abs() > 0.0 && !path.ends_with("elapsed_ms") {
                        bad.push(format!("{path} = {x}"));
                    }
                }
            }
            serde_json::Value::Array(a) => a
                .iter()
                .enumerate()
                .for_each(|(i, x)| walk(x, &format!("{path}[{i}]"), bad)),
            serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| walk(x, &format!("{path}.{k}"), bad)),
            _ => {}
        }
    }
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    for mode in ["step", "exact"] {
        let o = latheguard(
            &root,
            &[
                "check",
                "--format",
                "json",
                "--mode",
                mode,
                "tests/fixtures/follow-on/rapid_then_stopped_feed.nc",
            ],
        );
        let mut bad = Vec::new();
        let doc = json(&o);
        walk(&doc["files"][0]["findings"], "findings", &mut bad);
        assert!(
            doc["files"][0]["findings"].to_string().contains("follow_on"),
            "no follow-on to test"
        );
        assert!(bad.is_empty(), "{mode}: {bad:?}");
    }
}

#[test]
fn a_file_whose_moves_never_reach_the_machine_is_no_motion_in_every_format() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path();
    // A subroutine library nobody calls, a program of settings only, and one that moves.
    std::fs::write(p.join("library.ngc"), "o100 sub\nG1 X10 Z-5 F0.1\no100 endsub\nM2\n").unwrap();
    std::fs::write(p.join("settings.nc"), "%\nO0001\nG21 G18 G40 G99\nG50 S2000\nM30\n%\n").unwrap();
    std::fs::write(
        p.join("moves.nc"),
        "%\nO0002\nG21 G99\nG28 U0 W0\nG0 X200. Z300.\nM30\n%\n",
    )
    .unwrap();
    let run = |args: &[&str]| common::latheguard(p, args);

    let out = run(&["check", "--format", "json", "."]);
    assert_eq!(out.status.code(), Some(0), "no motion is not an error");
    let doc = json(&out);
    let status: BTreeMap<String, String> = doc["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| {
            (
                f["path"].as_str().unwrap().to_string(),
                f["status"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    assert_eq!(status["library.ngc"], "no_motion");
    assert_eq!(status["settings.nc"], "no_motion");
    assert_eq!(status["moves.nc"], "clean");
    assert_eq!(doc["summary"]["clean"], 1);
    assert_eq!(doc["summary"]["no_motion"], 2);
    assert_eq!(doc["summary"]["with_findings"], 0);
    assert_eq!(doc["files"][0]["stats"]["moves"], 0);

    let text = stdout(&run(&["check", "--color", "never", "."]));
    assert!(
        text.contains("library.ngc: no_motion: no move reaches the machine"),
        "{text}"
    );
    assert!(text.contains("1 clean, 2 with no motion, 0 with findings"), "{text}");

    let xml = stdout(&run(&["check", "--format", "junit", "."]));
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let skipped: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("testcase") && n.children().any(|c| c.has_tag_name("skipped")))
        .map(|c| c.attribute("name").unwrap())
        .collect();
    assert_eq!(skipped, ["library.ngc", "settings.nc"]);

    let log = json(&run(&["check", "--format", "sarif", "."]));
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(common::fixtures().join("sarif-schema-2.1.0.json")).unwrap())
            .unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    assert!(validator.is_valid(&log));
    let notes = log["runs"][0]["invocations"][0]["toolExecutionNotifications"]
        .as_array()
        .unwrap();
    let uris: Vec<&str> = notes
        .iter()
        .map(|n| {
            n["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
                .as_str()
                .unwrap()
        })
        .collect();
    assert_eq!(uris, ["library.ngc", "settings.nc"]);
    assert!(notes
        .iter()
        .all(|n| n["descriptor"]["id"] == "no_motion" && n["level"] == "note"));
}

#[test]
fn moves_reads_fanuc_macro_b_as_check_does() {
    let dir = tempfile::tempdir().unwrap();
    let prog = "%\nO0001\nG21 G99\n#1=2\nWHILE [#1 GT 0] DO1\nG0 X[100+#1*10] Z50.\n#1=#1-1\nEND1\nM30\n%\n";
    std::fs::write(dir.path().join("m.nc"), prog).unwrap();
    let out = latheguard(dir.path(), &["moves", "m.nc"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
    let text = stdout(&out);
    assert_eq!(
        text.lines().filter(|l| l.contains("STRAIGHT_TRAVERSE")).count(),
        2,
        "{text}"
    );
}

/// A follow-on contact says which crash it follows in SARIF too (`properties.follow_on`), as the
/// JSON report does: a code-scanning view must not show it as a crash of its own making.
#[test]
fn sarif_results_name_the_crash_a_follow_on_follows_as_json_does() {
    let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let file = "tests/fixtures/follow-on/rapid_then_stopped_feed.nc";
    let doc = json(&latheguard(&root, &["check", "--format", "json", file]));
    let sarif = json(&latheguard(&root, &["check", "--format", "sarif", file]));
    let findings = doc["files"][0]["findings"].as_array().unwrap();
    let results = sarif["runs"][0]["results"].as_array().unwrap();
    assert_eq!(findings.len(), results.len());
    let mut seen = 0;
    for (f, r) in findings.iter().zip(results) {
        assert_eq!(f["line"], r["locations"][0]["physicalLocation"]["region"]["startLine"]);
        assert_eq!(f["follow_on"], r["properties"]["follow_on"], "line {}", f["line"]);
        seen += usize::from(!f["follow_on"].is_null());
    }
    assert!(seen > 0, "no follow-on to test");
}
