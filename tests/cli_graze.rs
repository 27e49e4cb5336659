//! `min_depth` from the user's side: a 0.01 mm contact is a warning (JSON severity, SARIF level)
//! and exits 0; `--min-depth 0`, `latheguard.toml` and `machine.min_depth` change it, in that
//! order of precedence (command line over configuration over machine file); out of range is exit 2.

use crate::common;

use common::{json, latheguard, stderr};
use std::path::Path;

const GRAZE: &str = "G21 G18 G98 G97 S500 M3\nG0 X25 Z5\nG1 Z-0.01 F100\nG0 Z5\nM30\n";

fn setup(machine_extra: &str, config: Option<&str>) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let m = std::fs::read_to_string(root.join("tests/machines/jaw-test.toml")).unwrap();
    let m = m.replacen("[machine]\n", &format!("[machine]\n{machine_extra}"), 1);
    std::fs::write(dir.path().join("m.toml"), m).unwrap();
    std::fs::write(dir.path().join("graze.nc"), GRAZE).unwrap();
    if let Some(c) = config {
        std::fs::write(dir.path().join("latheguard.toml"), format!("machine = \"m.toml\"\n{c}")).unwrap();
    } else {
        std::fs::write(dir.path().join("latheguard.toml"), "machine = \"m.toml\"\n").unwrap();
    }
    dir
}

fn severity(dir: &Path, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec!["check", "--format", "json", "graze.nc"];
    args.extend_from_slice(extra);
    let out = latheguard(dir, &args);
    let doc = json(&out);
    let f = &doc["files"][0]["findings"][0];
    assert_eq!(f["kind"], "collision", "{doc}");
    (out.status.code(), f["severity"].as_str().unwrap().to_string())
}

#[test]
fn a_graze_is_a_warning_in_json_and_sarif_and_exits_0() {
    let t = setup("", None);
    let (code, sev) = severity(t.path(), &[]);
    assert_eq!((code, sev.as_str()), (Some(0), "warning"));
    let out = latheguard(t.path(), &["check", "--format", "json", "graze.nc"]);
    let msg = json(&out)["files"][0]["findings"][0]["message"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        msg.contains("(a graze: shallower than min_depth 0.1 mm)") && !msg.contains("0.010"),
        "{msg}"
    );
    let out = latheguard(t.path(), &["check", "--format", "sarif", "graze.nc"]);
    let doc = json(&out);
    assert_eq!(doc["runs"][0]["results"][0]["level"], "warning", "{doc}");
    // --fail-on warning fails on it.
    let out = latheguard(t.path(), &["check", "--fail-on", "warning", "graze.nc"]);
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
}

#[test]
fn min_depth_precedence_is_command_line_then_latheguard_toml_then_machine_file() {
    // The machine file alone turns grazes off.
    let t = setup("min_depth = 0\n", None);
    assert_eq!(severity(t.path(), &[]), (Some(1), "error".into()));
    // latheguard.toml over the machine file.
    let t = setup("min_depth = 0\n", Some("min_depth = 0.05\n"));
    assert_eq!(severity(t.path(), &[]), (Some(0), "warning".into()));
    // An [[override]] over the top level.
    let t = setup(
        "",
        Some("min_depth = 0.05\n[[override]]\nglob = \"*.nc\"\nmin_depth = 0.005\n"),
    );
    assert_eq!(severity(t.path(), &[]), (Some(1), "error".into()));
    // The command line over everything.
    let t = setup("min_depth = 0\n", Some("min_depth = 0\n"));
    assert_eq!(severity(t.path(), &["--min-depth", "0.5"]), (Some(0), "warning".into()));
}

#[test]
fn min_depth_out_of_range_is_exit_2_everywhere() {
    let t = setup("", None);
    for bad in ["1.5", "-0.1", "nan"] {
        let out = latheguard(t.path(), &["check", "--min-depth", bad, "graze.nc"]);
        assert_eq!(out.status.code(), Some(2), "--min-depth {bad}");
    }
    let t = setup("", Some("min_depth = 3\n"));
    let out = latheguard(t.path(), &["check", "graze.nc"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("min_depth"), "{}", stderr(&out));
    let t = setup("min_depth = 3\n", None);
    let out = latheguard(t.path(), &["check", "graze.nc"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("machine.min_depth"), "{}", stderr(&out));
    // accuracy takes it too.
    let out = latheguard(t.path(), &["accuracy", "-m", "m.toml", "--min-depth", "2", "graze.nc"]);
    assert_eq!(out.status.code(), Some(2));
}
