//! `latheguard machine FILE` and `check -m FILE` on machine files with problems (issue 14 item
//! 2): every error reported at once with exit 2, a warning for an outline's spike, and a stock
//! that does not fit the chuck refused.

use crate::common;
use std::path::{Path, PathBuf};

use std::process::Output;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn machine(name: &str) -> PathBuf {
    root().join("tests/machines").join(name)
}

fn run(args: &[&str]) -> Output {
    common::latheguard(root(), args)
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Both commands that read a machine file, for `file`.
fn commands(file: &Path) -> Vec<Vec<String>> {
    let f = file.display().to_string();
    let prog = root().join("programs/facing.nc").display().to_string();
    vec![
        vec!["machine".into(), f.clone()],
        vec!["check".into(), "-m".into(), f, prog],
    ]
}

#[test]
fn three_mistakes_in_a_machine_file_are_all_printed_with_exit_2() {
    for args in commands(&machine("refused/three-mistakes.toml")) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        let e = err(&o);
        let lines: Vec<&str> = e.lines().filter(|l| l.contains("three-mistakes.toml:")).collect();
        assert_eq!(lines.len(), 3, "{args:?}: {e}");
        for (line, key) in lines.iter().zip(["axes.x.min", "spindle.max_rpm", "tools[0].station"]) {
            assert!(line.starts_with("latheguard: "), "{line}");
            assert!(line.contains(&format!(": {key}: ")), "{key} not in {line}");
        }
        assert!(!e.contains("panicked"), "{e}");
    }
}

#[test]
fn a_spike_in_an_outline_is_a_warning_and_the_machine_loads() {
    for args in commands(&machine("turret-spike.toml")) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args);
        assert_ne!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        let e = err(&o);
        assert!(
            e.contains("warning: ") && e.contains("turret.outline: point [2] [260, 40] is a spike"),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn a_stock_wider_than_the_chuck_bore_is_refused_with_exit_2() {
    for args in commands(&machine("refused/stock-too-wide.toml")) {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let o = run(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains(": stock.diameter: the bar (Ø50"),
            "{args:?}: {}",
            err(&o)
        );
    }
}

/// `machine.dialect = "auto"`: each file is read in the dialect its own signs show, and the text
/// and JSON reports say which and why.
#[test]
fn dialect_auto_chooses_per_file_and_the_reports_say_which() {
    let dir = tempfile::tempdir().unwrap();
    let m = dir.path().join("auto.toml");
    let text = std::fs::read_to_string(root().join("machines/generic-slant-bed.toml")).unwrap();
    std::fs::write(&m, text.replace("dialect = \"fanuc\"", "dialect = \"auto\"")).unwrap();
    let lc = dir.path().join("lc.ngc");
    std::fs::write(
        &lc,
        "o<face> sub\nG0 X60 Z5\no<face> endsub\nG7 G18 G21\nT1 M6\nG0 X60 Z85\nM2\n",
    )
    .unwrap();
    let fanuc = root().join("programs/facing.nc");
    let (m, lc, fanuc) = (
        m.display().to_string(),
        lc.display().to_string(),
        fanuc.display().to_string(),
    );
    let o = run(&["check", "-m", &m, &lc, &fanuc]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("lc.ngc: dialect linuxcnc (auto: a named o-word at line 1)"),
        "{out}"
    );
    assert!(
        out.contains("facing.nc: dialect fanuc (auto: a program number `O…` at line 2)"),
        "{out}"
    );
    // `moves` reads each program in its own dialect too (it once read them all as the machine
    // file's fallback: G7 unsupported in the LinuxCNC program).
    let o = run(&["moves", "-m", &m, &lc]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(!err(&o).contains("unsupported"), "{}", err(&o));
    // `setup` says the same of each program, as `check` reads it.
    let o = run(&["setup", "-m", &m, &lc]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("dialect       linuxcnc (auto: a named o-word at line 1)"),
        "{out}"
    );
    let o = run(&["setup", "-m", &m, &fanuc, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["dialect"]["value"], "fanuc", "{v}");
    assert_eq!(v["dialect"]["auto"], "a program number `O…` at line 2", "{v}");
    let o = run(&["check", "-m", &m, &lc, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["files"][0]["dialect"], "linuxcnc");
    // Without auto, the reports say nothing about the dialect.
    let o = run(&["check", &fanuc, "--format", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["files"][0].get("dialect").is_none());
}

/// `latheguard machine new`: the default starter file (snapshot) loads with `latheguard machine`,
/// and an existing file is never overwritten without `--force`.
#[test]
fn machine_new_writes_a_starter_that_loads_and_never_overwrites_without_force() {
    let o = run(&[
        "machine",
        "new",
        "--name",
        "Shop lathe",
        "--stations",
        "6",
        "--units",
        "inch",
    ]);
    assert!(o.status.success(), "{}", err(&o));
    let text = String::from_utf8(o.stdout).unwrap();
    insta::assert_snapshot!("machine_new_starter", text);
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("m.toml");
    let fs = f.display().to_string();
    assert!(run(&["machine", "new", "-o", &fs, "--type", "gang"]).status.success());
    let o = run(&["machine", &fs]);
    assert!(o.status.success(), "{}", err(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains("gang slide"));
    let o = run(&["machine", "new", "-o", &fs]);
    assert_eq!(o.status.code(), Some(2));
    assert!(err(&o).contains("--force"), "{}", err(&o));
    assert!(
        std::fs::read_to_string(&f).unwrap().contains("type = \"gang\""),
        "the file is untouched"
    );
    assert!(run(&["machine", "new", "-o", &fs, "--force"]).status.success());
    assert!(std::fs::read_to_string(&f).unwrap().contains("type = \"drum\""));
}
