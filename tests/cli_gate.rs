//! The gate controls of `check`, as a CI engineer uses them: `--select`/`--ignore` by kind or
//! code, in-file suppressions with a reason, `--fail-on`, `--statistics`, repeats collapsed,
//! `-` for standard input, a path that does not exist (exit 2), the summary on standard error
//! with `-o`, and `--explain` by code.

use crate::common;

use common::{json, stderr, stdout, Tree};
use std::io::Write;
use std::process::{Command, Stdio};

#[test]
fn select_and_ignore_by_kind_or_code_choose_what_is_reported_and_what_fails() {
    let t = Tree::new();
    // Only the near miss and the unknown M code are left: warnings, exit 0.
    let out = t.run(&["check", "--format", "json", "--ignore", "LG01,syntax", "."]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let doc = json(&out);
    assert_eq!(doc["summary"]["errors"], 0);
    assert_eq!(doc["summary"]["warnings"], 2);
    // --select one kind by code.
    let out = t.run(&["check", "--format", "json", "--select", "LG04", "."]);
    assert_eq!(out.status.code(), Some(0));
    let doc = json(&out);
    assert_eq!(doc["summary"]["with_findings"], 1);
    // --ignore wins over --select.
    let out = t.run(&[
        "check",
        "--format",
        "json",
        "--select",
        "collision",
        "--ignore",
        "collision",
        ".",
    ]);
    assert_eq!(json(&out)["summary"]["with_findings"], 0);
    // An unknown kind is a bad argument (exit 2) that lists the kinds.
    let out = t.run(&["check", "--select", "crash", "."]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("rapid_into_stock (LG02)"), "{}", stderr(&out));
}

#[test]
fn fail_on_warning_makes_warnings_fail_the_gate() {
    let t = Tree::new();
    let out = t.run(&["check", "cell-c/unsupported.ngc"]);
    assert_eq!(out.status.code(), Some(0));
    let out = t.run(&["check", "--fail-on", "warning", "cell-c/unsupported.ngc"]);
    assert_eq!(out.status.code(), Some(1));
    let out = t.run(&["check", "--fail-on", "error", "cell-c/unsupported.ngc"]);
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn a_suppression_comment_with_a_reason_sets_a_crash_aside_in_every_format() {
    let t = Tree::new();
    let crash = std::fs::read_to_string(t.path().join("cell-a/crash_holder.nc")).unwrap();
    // The crash's line (N70 Z-120.: see the fixture) gets a suppression; the rest stays.
    let line = crash
        .lines()
        .position(|l| l.contains("N70 Z-120."))
        .expect("the crashing line")
        + 1;
    let edited: Vec<String> = crash
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == line {
                format!("{l} (latheguard: allow collision -- the jaws are bored soft jaws here)")
            } else {
                l.to_string()
            }
        })
        .collect();
    std::fs::write(t.path().join("cell-a/crash_holder.nc"), edited.join("\n") + "\n").unwrap();
    let out = t.run(&["check", "--format", "json", "cell-a/crash_holder.nc"]);
    assert_eq!(out.status.code(), Some(0), "{}", stdout(&out));
    let doc = json(&out);
    let file = &doc["files"][0];
    assert_eq!(file["status"], "clean");
    let sup = file["suppressed"].as_array().unwrap();
    assert_eq!(sup.len(), 2, "the insert's crash and the holder's follow-on");
    assert!(sup.iter().all(|s| s["reason"] == "the jaws are bored soft jaws here"));
    assert!(sup.iter().all(|s| s["suppressed_at"] == line));
    assert_eq!(doc["summary"]["suppressed"], 2);

    let text = stdout(&t.run(&["check", "--color", "never", "cell-a/crash_holder.nc"]));
    assert!(!text.contains("error[collision]"), "{text}");
    assert!(text.contains("2 suppressed"), "{text}");

    let log = json(&t.run(&["check", "--format", "sarif", "cell-a/crash_holder.nc"]));
    let results = log["runs"][0]["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    assert!(results.iter().all(|r| r["suppressions"][0]["kind"] == "inSource"
        && r["suppressions"][0]["justification"] == "the jaws are bored soft jaws here"));

    // Without a reason it suppresses nothing, and says so.
    let no_reason = crash.replacen("N70 Z-120.", "N70 Z-120. (latheguard: allow collision)", 1);
    std::fs::write(t.path().join("cell-a/crash_holder.nc"), no_reason).unwrap();
    let out = t.run(&["check", "--color", "never", "cell-a/crash_holder.nc"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(
        stdout(&out).contains("this suppression suppresses nothing"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn statistics_count_findings_per_kind_most_frequent_first() {
    let t = Tree::new();
    let out = t.run(&["check", "--statistics", "."]);
    assert_eq!(out.status.code(), Some(1), "--statistics keeps the exit status");
    let text = stdout(&out);
    let rows: Vec<&str> = text.lines().collect();
    assert!(rows[0].trim_start().starts_with("5  LG10  syntax"), "{text}");
    assert!(text.contains("LG01  collision"), "{text}");
    assert!(rows.last().unwrap().starts_with("checked 9 files"), "{text}");
}

#[test]
fn a_crash_on_every_pass_of_a_loop_is_one_finding_with_a_count() {
    let dir = tempfile::tempdir().unwrap();
    // The built-in machine; five passes of a subprogram whose rapid runs into the bar.
    let prog = "%\nO0001\nG21 G99\nT0101\nG97 S800 M3\nM98 P1000 L5\nG28 U0 W0\nM30\nO1000\nG0 X60. Z5.\nG0 X44. Z-10.\nG0 X60.\nZ5.\nM99\n%\n";
    std::fs::write(dir.path().join("loop.nc"), prog).unwrap();
    let out = common::latheguard(dir.path(), &["check", "--format", "json", "loop.nc"]);
    let doc = json(&out);
    let f = &doc["files"][0]["findings"];
    let rapid: Vec<&serde_json::Value> = f
        .as_array()
        .unwrap()
        .iter()
        .filter(|x| x["kind"] == "rapid_into_stock")
        .collect();
    assert_eq!(rapid.len(), 1, "{f:#}");
    assert_eq!(rapid[0]["line"], 11);
    assert_eq!(rapid[0]["repeats"], 5, "{f:#}");
}

#[test]
fn a_dash_reads_the_program_from_standard_input() {
    let t = Tree::new();
    let crash = std::fs::read(t.path().join("cell-a/crash_holder.nc")).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["check", "--color", "never", "-"])
        .current_dir(t.path())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(&crash).unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let text = stdout(&out);
    assert!(text.starts_with("-:"), "{text}");
    assert!(text.contains("checked 1 file: 0 clean, 1 with findings"), "{text}");
}

#[test]
fn a_path_that_does_not_exist_stops_the_run_with_exit_2_and_is_not_a_syntax_finding() {
    let t = Tree::new();
    let out = t.run(&["check", "cell-a/od_turnin.nc", "cell-a", "no-such-folder/"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("cell-a/od_turnin.nc: no such file or folder"), "{err}");
    assert!(err.contains("no-such-folder/: no such file or folder"), "{err}");
    assert!(stdout(&out).is_empty(), "nothing is checked");
}

#[test]
fn with_an_output_file_the_summary_line_goes_to_standard_error() {
    let t = Tree::new();
    let out = t.run(&["check", "--format", "json", "-o", "report.json", "cell-a"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(stdout(&out).is_empty());
    assert!(
        stderr(&out).contains("checked 4 files: 1 clean, 3 with findings"),
        "{}",
        stderr(&out)
    );
    assert!(t.path().join("report.json").exists());
    // --quiet keeps standard error quiet.
    let out = t.run(&["check", "-q", "--format", "json", "-o", "report2.json", "cell-a"]);
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

#[test]
fn explain_takes_a_code_as_well_as_a_name() {
    let t = Tree::new();
    let by_code = stdout(&t.run(&["check", "--explain", "LG02"]));
    let by_name = stdout(&t.run(&["check", "--explain", "rapid_into_stock"]));
    assert_eq!(by_code, by_name);
    assert!(by_code.starts_with("# rapid_into_stock"), "{by_code}");
}

#[test]
fn github_annotations_have_the_workflow_command_shape() {
    let t = Tree::new();
    let out = t.run(&["check", "--format", "github", "."]);
    assert_eq!(out.status.code(), Some(1));
    let text = stdout(&out);
    let lines: Vec<&str> = text.lines().collect();
    let (summary, commands) = lines.split_last().unwrap();
    assert!(summary.starts_with("checked 9 files"), "{summary}");
    assert_eq!(commands.len(), 9, "{text}");
    for c in commands {
        let (head, message) = c[2..].split_once("::").expect("::level props::message");
        let (level, props) = head.split_once(' ').unwrap();
        assert!(["error", "warning", "notice"].contains(&level), "{c}");
        let keys: Vec<&str> = props.split(',').map(|p| p.split_once('=').unwrap().0).collect();
        assert_eq!(keys[0], "file", "{c}");
        assert!(
            keys.iter()
                .all(|k| ["file", "line", "col", "endLine", "title"].contains(k)),
            "{c}"
        );
        assert!(!message.is_empty() && !message.contains('\n'));
    }
    assert!(
        text.contains("::error file=cell-a/crash_holder.nc,line=10,endLine=12,title=collision (LG01)::"),
        "{text}"
    );
}

#[test]
fn gitlab_code_quality_has_the_fields_gitlab_reads_and_unique_stable_fingerprints() {
    let t = Tree::new();
    let run = || json(&t.run(&["check", "--format", "gitlab", "."]));
    let doc = run();
    let issues = doc.as_array().unwrap();
    assert_eq!(issues.len(), 9);
    let mut prints = std::collections::BTreeSet::new();
    for i in issues {
        assert!(i["description"].as_str().is_some_and(|d| !d.is_empty()));
        assert!(i["check_name"].as_str().is_some());
        assert!(["info", "minor", "major", "critical", "blocker"].contains(&i["severity"].as_str().unwrap()));
        assert!(i["location"]["path"].as_str().is_some());
        assert!(i["location"]["lines"]["begin"].as_u64().unwrap() >= 1);
        assert!(
            prints.insert(i["fingerprint"].as_str().unwrap().to_string()),
            "duplicate fingerprint"
        );
    }
    assert_eq!(run(), doc, "the same report, fingerprints included, from run to run");
    let crash = issues
        .iter()
        .find(|i| i["location"]["path"] == "cell-a/crash_holder.nc")
        .unwrap();
    assert_eq!(crash["severity"], "critical");
}

#[test]
fn help_and_man_pages_give_the_exit_statuses_and_environment() {
    let t = Tree::new();
    for args in [&["--help"][..], &["check", "--help"][..]] {
        let help = stdout(&t.run(args));
        assert!(help.contains("Exit status:") && help.contains("NO_COLOR"), "{help}");
        assert!(help.contains("2  latheguard could not run"), "{help}");
    }
    let out = t.run(&["man", "man"]);
    assert_eq!(out.status.code(), Some(0));
    let page = std::fs::read_to_string(t.path().join("man/latheguard-check.1")).unwrap();
    assert!(page.contains("NO_COLOR") && page.contains("Exit status"), "{page}");
}

#[test]
fn with_svg_every_report_links_a_finding_to_its_picture() {
    let t = Tree::new();
    let pic = "pictures/cell-a__crash_holder.nc.L10.collision.T01-insert.chuck.svg";
    let doc = json(&t.run(&[
        "check",
        "--svg",
        "pictures",
        "--format",
        "json",
        "cell-a/crash_holder.nc",
    ]));
    assert_eq!(doc["files"][0]["findings"][0]["picture"], pic, "{doc:#}");
    assert!(t.path().join(pic).exists());
    let text = stdout(&t.run(&[
        "check",
        "--svg",
        "pictures",
        "--color",
        "never",
        "cell-a/crash_holder.nc",
    ]));
    assert!(text.contains(&format!("picture {pic}")), "{text}");
    let log = json(&t.run(&[
        "check",
        "--svg",
        "pictures",
        "--format",
        "sarif",
        "cell-a/crash_holder.nc",
    ]));
    assert_eq!(
        log["runs"][0]["results"][0]["attachments"][0]["artifactLocation"]["uri"],
        pic
    );
    let schema: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(common::fixtures().join("sarif-schema-2.1.0.json")).unwrap())
            .unwrap();
    assert!(jsonschema::validator_for(&schema).unwrap().is_valid(&log));
    let xml = stdout(&t.run(&[
        "check",
        "--svg",
        "pictures",
        "--format",
        "junit",
        "cell-a/crash_holder.nc",
    ]));
    assert!(xml.contains(pic), "{xml}");
    // Without --svg no report names a picture.
    let doc = json(&t.run(&["check", "--format", "json", "cell-a/crash_holder.nc"]));
    assert!(doc["files"][0]["findings"][0].get("picture").is_none());
}

/// Issue 26: an allowed over-travel (a tool change point above a raised soft limit) must not
/// hide the crash two lines later — the insert into the bar, the holder and the turret into the
/// chuck are errors of their own at line 5 — and an allow of one line's over-travel never
/// removes the next line's.
#[test]
fn an_allowed_overtravel_hides_neither_the_crash_after_it_nor_the_next_overtravel() {
    let dir = tempfile::tempdir().unwrap();
    let allow = "(latheguard: allow overtravel -- tool change point, soft limit raised on this machine)";
    std::fs::write(
        dir.path().join("p.nc"),
        format!("G21 G18\nT0101\nG0 X500. Z200. {allow}\nG0 X54. Z144.\nG0 X38. Z-200.\nM30\n"),
    )
    .unwrap();
    std::fs::write(
        dir.path().join("q.nc"),
        format!("G21 G18\nT0101\nG0 X500. Z200. {allow}\nG0 X700. Z300.\nG0 X54. Z144.\nM30\n"),
    )
    .unwrap();
    let out = common::latheguard(dir.path(), &["check", "--format", "json", "p.nc"]);
    assert_eq!(out.status.code(), Some(1), "{}", stdout(&out));
    let doc = json(&out);
    let errors: Vec<(u64, String, String)> = doc["files"][0]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["severity"] == "error")
        .map(|f| {
            (
                f["line"].as_u64().unwrap(),
                f["kind"].as_str().unwrap().to_string(),
                f["objects"].to_string(),
            )
        })
        .collect();
    for (kind, objects) in [
        ("rapid_into_stock", r#"["T01 insert","stock"]"#),
        ("collision", r#"["T01 holder","chuck"]"#),
        ("collision", r#"["turret","chuck"]"#),
    ] {
        assert!(
            errors.contains(&(5, kind.to_string(), objects.to_string())),
            "{kind} {objects} at line 5: {errors:?}"
        );
    }
    assert_eq!(doc["files"][0]["suppressed"].as_array().unwrap().len(), 1);

    let out = common::latheguard(dir.path(), &["check", "--format", "json", "q.nc"]);
    assert_eq!(out.status.code(), Some(1), "{}", stdout(&out));
    let doc = json(&out);
    let f = &doc["files"][0]["findings"];
    assert_eq!(f[0]["line"], 4, "{f}");
    assert_eq!(f[0]["kind"], "overtravel");
    assert_eq!(f[0]["severity"], "error");
}
