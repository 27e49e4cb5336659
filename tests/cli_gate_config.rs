//! The gate set in `latheguard.toml` (`select`, `extend-select`, `ignore`, `fail-on`,
//! `[per-file-ignores]`, `unused-suppressions`) and the command line over it; `--config FILE`,
//! `--show-settings`, `check` with no path, `--stdin-filename`, `--output-format`,
//! `--statistics --format json`, and unused suppressions reported.

use crate::common;

use common::{json, stderr, stdout, Tree};
use std::io::Write;
use std::process::{Command, Output, Stdio};

/// Put `keys` at the top of a configuration of the tree (before its tables).
fn prepend(t: &Tree, config: &str, keys: &str) {
    let p = t.path().join(config);
    let old = std::fs::read_to_string(&p).unwrap();
    std::fs::write(&p, format!("{keys}{old}")).unwrap();
}

fn with_stdin(t: &Tree, args: &[&str], input: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(args)
        .current_dir(t.path())
        .env("CI", "true")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input).unwrap();
    child.wait_with_output().unwrap()
}

fn kinds_of(doc: &serde_json::Value) -> Vec<String> {
    let mut out = Vec::new();
    for f in doc["files"].as_array().unwrap() {
        for x in f["findings"].as_array().unwrap() {
            out.push(x["kind"].as_str().unwrap().to_string());
        }
    }
    out.sort();
    out.dedup();
    out
}

#[test]
fn select_in_the_file_and_the_command_line_over_it_as_ruff_does() {
    let t = Tree::new();
    prepend(&t, "latheguard.toml", "select = [\"collision\"]\n");
    let doc = json(&t.run(&["check", "--format", "json", "cell-a"]));
    assert_eq!(kinds_of(&doc), ["collision"]);
    // --select replaces the file's select.
    let doc = json(&t.run(&["check", "--format", "json", "--select", "syntax", "cell-a"]));
    assert_eq!(kinds_of(&doc), ["syntax"]);
    // --extend-select adds to it.
    let doc = json(&t.run(&["check", "--format", "json", "--extend-select", "LG10", "cell-a"]));
    let both = kinds_of(&doc);
    assert!(both.contains(&"collision".to_string()) && both.len() == 2, "{both:?}");
    // --ignore adds to the file's ignore: nothing is left, and the run passes.
    let out = t.run(&["check", "--format", "json", "--ignore", "collision", "cell-a"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(kinds_of(&json(&out)).is_empty());
}

#[test]
fn ignore_extend_select_fail_on_and_per_file_ignores_in_the_file() {
    let t = Tree::new();
    prepend(&t, "cell-b/latheguard.toml", "fail-on = \"warning\"\n");
    // The near miss of cell-b/legacy is a warning: the file's fail-on makes it fail.
    assert_eq!(t.run(&["check", "cell-b"]).status.code(), Some(1));
    assert_eq!(t.run(&["check", "--fail-on", "error", "cell-b"]).status.code(), Some(0));
    // Another folder's programs keep the default.
    assert_eq!(t.run(&["check", "cell-c"]).status.code(), Some(0));
    prepend(
        &t,
        "cell-b/latheguard.toml",
        "[per-file-ignores]\n\"legacy/**/*.nc\" = [\"near_miss\", \"LG06\"]\n\n",
    );
    // The table must come after the top-level keys: put it at the end instead.
    let p = t.path().join("cell-b/latheguard.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    let (table, rest) = text.split_at(text.find("fail-on").unwrap());
    std::fs::write(&p, format!("{rest}\n{table}")).unwrap();
    let out = t.run(&["check", "--format", "json", "cell-b"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(kinds_of(&json(&out)).is_empty());
    // ignore + extend-select in the root configuration.
    prepend(&t, "cell-c/latheguard.toml", "ignore = [\"unsupported\"]\n");
    assert!(kinds_of(&json(&t.run(&["check", "--format", "json", "cell-c"]))).is_empty());
    let doc = json(&t.run(&["check", "--format", "json", "--extend-select", "LG12", "cell-c"]));
    assert_eq!(kinds_of(&doc), ["unsupported"]);
}

#[test]
fn an_unknown_kind_in_the_file_is_an_error_at_its_place() {
    let t = Tree::new();
    prepend(&t, "cell-c/latheguard.toml", "ignore = [\"LG12\", \"nearmiss\"]\n");
    let out = t.run(&["check", "cell-c"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cell-c/latheguard.toml:1:19: ignore[1]: `nearmiss` is not a finding kind"),
        "{}",
        stderr(&out)
    );
    std::fs::write(
        t.path().join("cell-c/latheguard.toml"),
        "[per-file-ignores]\n\"*.ngc\" = [\"crash\"]\n",
    )
    .unwrap();
    let out = t.run(&["check", "cell-c"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("cell-c/latheguard.toml:2:12: per-file-ignores.\"*.ngc\"[0]: `crash`"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn config_names_the_file_used_for_every_program() {
    let t = Tree::new();
    std::fs::write(
        t.path().join("ci.toml"),
        "machine = \"machines/slant-bed.toml\"\nignore = [\"collision\"]\n",
    )
    .unwrap();
    let out = t.run(&["check", "--config", "ci.toml", "cell-a/crash_holder.nc"]);
    assert_eq!(out.status.code(), Some(0), "{}{}", stdout(&out), stderr(&out));
    let out = t.run(&["check", "--config", "ci.toml", "--no-config", "cell-a"]);
    assert_eq!(out.status.code(), Some(2));
    let out = t.run(&["check", "--config", "nope.toml", "cell-a"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("nope.toml"), "{}", stderr(&out));
}

#[test]
fn show_settings_says_what_applies_and_where_it_came_from() {
    let t = Tree::new();
    prepend(
        &t,
        "cell-b/latheguard.toml",
        "ignore = [\"LG06\"]\nfail-on = \"warning\"\n",
    );
    let out = t.run(&["check", "--show-settings", "cell-b/legacy/near_miss.nc"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    for want in [
        "program: cell-b/legacy/near_miss.nc",
        "configuration: cell-b/latheguard.toml (the nearest)",
        "machine: machines/slant-bed.toml  (cell-b/latheguard.toml)",
        "mode: exact  (cell-b/latheguard.toml)",
        "dt: 1 ms  (default)",
        "clearance: 0.5 mm  (cell-b/latheguard.toml [[override]] glob = \"legacy/*.nc\")",
        "  ignore = [rapid_scrape]  (cell-b/latheguard.toml)",
        "  fail-on: warning  (cell-b/latheguard.toml)",
    ] {
        assert!(text.contains(want), "no {want:?} in:\n{text}");
    }
    let out = t.run(&[
        "check",
        "--mode",
        "step",
        "--show-settings",
        "cell-b/legacy/near_miss.nc",
    ]);
    assert!(stdout(&out).contains("mode: step  (command line)"), "{}", stdout(&out));
    // No PATH: the first program of the paths checked.
    let out = t.run(&["check", "--show-settings", "--", "cell-c"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("program: cell-c/"), "{}", stdout(&out));
}

#[test]
fn check_with_no_path_checks_the_working_folder() {
    let t = Tree::new();
    let here = t.run(&["check", "--format", "json"]);
    let dot = t.run(&["check", "--format", "json", "."]);
    assert_eq!(here.status.code(), dot.status.code());
    assert_eq!(json(&here)["summary"], json(&dot)["summary"]);
    assert!(json(&here)["summary"]["files"].as_u64().unwrap() > 3);
}

#[test]
fn stdin_filename_looks_up_configuration_and_names_the_report() {
    let t = Tree::new();
    let program = std::fs::read(t.path().join("cell-b/legacy/near_miss.nc")).unwrap();
    // As `-`, the root configuration applies: no clearance, no near miss.
    let out = with_stdin(&t, &["check", "--format", "json", "-"], &program);
    assert!(kinds_of(&json(&out)).is_empty(), "{}", stdout(&out));
    let out = with_stdin(
        &t,
        &[
            "check",
            "--format",
            "json",
            "--stdin-filename",
            "cell-b/legacy/near_miss.nc",
        ],
        &program,
    );
    let doc = json(&out);
    assert_eq!(doc["files"][0]["path"], "cell-b/legacy/near_miss.nc");
    assert_eq!(kinds_of(&doc), ["near_miss"]);
    // Per-file ignores are looked up as for that path too.
    let p = t.path().join("cell-b/latheguard.toml");
    let text = std::fs::read_to_string(&p).unwrap();
    std::fs::write(
        &p,
        format!("{text}\n[per-file-ignores]\n\"legacy/*\" = [\"near_miss\"]\n"),
    )
    .unwrap();
    let out = with_stdin(
        &t,
        &[
            "check",
            "--format",
            "json",
            "--stdin-filename",
            "cell-b/legacy/near_miss.nc",
            "-",
        ],
        &program,
    );
    assert!(kinds_of(&json(&out)).is_empty(), "{}", stdout(&out));
}

#[test]
fn output_format_is_format_and_statistics_obey_json() {
    let t = Tree::new();
    let a = t.run(&["check", "--no-timing", "--output-format", "json", "cell-a"]);
    let b = t.run(&["check", "--no-timing", "--format", "json", "cell-a"]);
    assert_eq!(stdout(&a), stdout(&b));
    let out = t.run(&["check", "--statistics", "--format", "json", "."]);
    assert_eq!(out.status.code(), Some(1));
    let doc = json(&out);
    assert_eq!(doc["kinds"][0]["count"], doc["counts"]["syntax"]);
    assert!(doc["counts"]["collision"].as_u64().unwrap() >= 1);
    assert_eq!(doc["kinds"][0]["kind"], "syntax");
    assert_eq!(doc["kinds"][0]["code"], "LG10");
    assert!(doc["summary"]["errors"].as_u64().unwrap() > 0);
}

#[test]
fn an_unused_suppression_is_a_warning_unless_the_file_turns_it_off() {
    let t = Tree::new();
    let p = t.path().join("cell-a/od_turning.nc");
    let text = std::fs::read_to_string(&p).unwrap();
    let text = text.replace(
        "N80 G0 Z2.",
        "N80 G0 Z2. (latheguard: allow collision -- never crashes)",
    );
    std::fs::write(&p, &text).unwrap();
    let line = text.lines().position(|l| l.starts_with("N80")).unwrap() + 1;
    let out = t.run(&["check", "--format", "json", "cell-a/od_turning.nc"]);
    assert_eq!(out.status.code(), Some(0), "a warning does not fail the run");
    let doc = json(&out);
    let f = &doc["files"][0]["findings"][0];
    assert_eq!(f["kind"], "program");
    assert_eq!(f["severity"], "warning");
    assert_eq!(f["line"], line);
    assert_eq!(f["message"], "unused suppression: no collision finding on this line");
    prepend(&t, "latheguard.toml", "unused-suppressions = false\n");
    let doc = json(&t.run(&["check", "--format", "json", "cell-a/od_turning.nc"]));
    assert!(kinds_of(&doc).is_empty());
}
