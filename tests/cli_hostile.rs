//! Hostile input at the command line (issue 10): arguments that would make the work unbounded,
//! files that block or never end, outputs that cannot be written or would destroy an input, and
//! names that would inject terminal control sequences. Every run here has a deadline: a run that
//! hangs fails its test instead of hanging the suite.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Long enough for the slowest command here (`accuracy --repeats 1` in a debug build) on a loaded
/// 2-core machine; a hang still fails, only later.
const DEADLINE: Duration = Duration::from_secs(60);

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn program(name: &str) -> PathBuf {
    root().join("programs").join(name)
}

fn builtin_machine() -> PathBuf {
    root().join("machines/generic-slant-bed.toml")
}

/// Run latheguard in `cwd` with `stdout` as its standard output (piped when `None`); kill it and
/// fail when it does not end within the deadline.
fn run_with(cwd: &Path, args: &[&str], stdout: Option<Stdio>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(args)
        .current_dir(cwd)
        .env("CI", "true")
        .env_remove("NO_COLOR")
        .stdin(Stdio::null())
        .stdout(stdout.unwrap_or_else(Stdio::piped))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Read the pipes on threads so a large output cannot stall the child.
    let mut out_pipe = child.stdout.take();
    let mut err_pipe = child.stderr.take().unwrap();
    let out_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        if let Some(p) = out_pipe.as_mut() {
            let _ = std::io::Read::read_to_end(p, &mut v);
        }
        v
    });
    let err_reader = std::thread::spawn(move || {
        let mut v = Vec::new();
        let _ = std::io::Read::read_to_end(&mut err_pipe, &mut v);
        v
    });
    let started = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if started.elapsed() > DEADLINE {
            let _ = child.kill();
            let _ = child.wait();
            panic!("latheguard {args:?} did not finish within {DEADLINE:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    Output {
        status,
        stdout: out_reader.join().unwrap(),
        stderr: err_reader.join().unwrap(),
    }
}

fn run(cwd: &Path, args: &[&str]) -> Output {
    run_with(cwd, args, None)
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn no_panic(o: &Output) {
    assert!(!err(o).contains("panicked"), "{}", err(o));
    assert_ne!(o.status.code(), Some(101), "{}", err(o));
}

fn tmp() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("latheguard-hostile").tempdir().unwrap()
}

fn mkfifo(p: &Path) {
    let st = Command::new("mkfifo").arg(p).status().unwrap();
    assert!(st.success());
}

// 1. Numbers that make the work unbounded.

#[test]
fn jobs_65535_is_refused_at_once_with_exit_2() {
    let dir = tmp();
    let p = program("od_turning.nc");
    let p = p.to_str().unwrap();
    for n in ["65535", "257", "0"] {
        let o = run(dir.path(), &["check", "-q", "-j", n, p]);
        assert_eq!(o.status.code(), Some(2), "-j {n}: {}", err(&o));
        assert!(err(&o).contains("--jobs"), "{}", err(&o));
        no_panic(&o);
    }
    // The maximum is accepted, and no more threads than files are started.
    let o = run(dir.path(), &["check", "-q", "-j", "256", p]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
}

#[test]
fn dt_tolerance_and_clearance_out_of_range_are_refused_with_exit_2() {
    let dir = tmp();
    let p = program("od_turning.nc");
    let p = p.to_str().unwrap();
    for (flag, v) in [
        ("--dt", "1e-9"),
        ("--dt", "0"),
        ("--dt", "-1"),
        ("--dt", "NaN"),
        ("--dt", "inf"),
        ("--dt", "1e6"),
        ("--tolerance", "1e-6"),
        ("--tolerance", "100"),
        ("--tolerance", "nan"),
        ("--clearance", "100"),
        ("--clearance", "-0.5"),
        ("--clearance", "-inf"),
    ] {
        let arg = format!("{flag}={v}");
        let o = run(dir.path(), &["check", "-q", "--mode", "exact", &arg, p]);
        assert_eq!(o.status.code(), Some(2), "{flag} {v}: {}", err(&o));
        assert!(err(&o).contains("must be a number from"), "{flag} {v}: {}", err(&o));
        no_panic(&o);
    }
    let o = run(dir.path(), &["accuracy", "--clearance", "100", p]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    // The edges of the ranges are accepted.
    let o = run(
        dir.path(),
        &[
            "check",
            "-q",
            "--dt",
            "1000",
            "--tolerance",
            "1",
            "--clearance",
            "10",
            p,
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
}

#[test]
fn config_settings_out_of_range_are_config_errors_with_the_key() {
    let dir = tmp();
    std::fs::copy(program("od_turning.nc"), dir.path().join("p.nc")).unwrap();
    for (text, key) in [
        (
            "tolerance = 1e-6\n",
            "latheguard.toml:1:13: tolerance: must be a number from 0.001 to 1",
        ),
        (
            "dt = 1e-9\n",
            "latheguard.toml:1:6: dt: must be a number from 0.001 to 1000",
        ),
        (
            "[[override]]\nglob = \"*.nc\"\nclearance = 100\n",
            "latheguard.toml:3:13: override[0].clearance: must be a number from 0 to 10",
        ),
    ] {
        std::fs::write(dir.path().join("latheguard.toml"), text).unwrap();
        let o = run(dir.path(), &["check", "-q", "."]);
        assert_eq!(o.status.code(), Some(2), "{text}: {}", err(&o));
        assert!(err(&o).contains(key), "{text}: {}", err(&o));
    }
}

// 2. accuracy --repeats.

#[test]
fn accuracy_repeats_18446744073709551615_is_refused_without_a_panic() {
    let dir = tmp();
    let p = program("od_turning.nc");
    for n in ["18446744073709551615", "101", "0", "-1"] {
        let flag = format!("--repeats={n}");
        let o = run(dir.path(), &["accuracy", &flag, p.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(2), "--repeats {n}: {}", err(&o));
        assert!(err(&o).contains("--repeats"), "{}", err(&o));
        no_panic(&o);
    }
}

// 3. FIFOs, devices and size caps.

#[test]
fn fifo_inside_a_walked_folder_is_skipped_without_blocking() {
    let dir = tmp();
    std::fs::create_dir(dir.path().join("progs")).unwrap();
    std::fs::copy(program("od_turning.nc"), dir.path().join("progs/real.nc")).unwrap();
    mkfifo(&dir.path().join("progs/pipe.nc"));
    std::os::unix::fs::symlink("pipe.nc", dir.path().join("progs/link-to-pipe.nc")).unwrap();
    let o = run(dir.path(), &["check", "--format", "json", "--no-timing", "progs"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let paths: Vec<&str> = doc["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, ["progs/real.nc"]);
}

#[test]
fn fifo_named_as_a_program_is_a_finding_of_that_file_and_never_blocks() {
    let dir = tmp();
    mkfifo(&dir.path().join("pipe.nc"));
    std::fs::copy(program("od_turning.nc"), dir.path().join("real.nc")).unwrap();
    let o = run(dir.path(), &["check", "-q", "pipe.nc", "real.nc"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(
        out(&o).contains("pipe.nc:1: error[syntax]: cannot read the file: it is a FIFO"),
        "{}",
        out(&o)
    );
    assert!(
        out(&o).contains("checked 2 files: 1 clean, 1 with findings"),
        "{}",
        out(&o)
    );
    for cmd in ["moves", "accuracy"] {
        let o = run(dir.path(), &[cmd, "pipe.nc"]);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {}", err(&o));
        assert!(err(&o).contains("it is a FIFO"), "{cmd}: {}", err(&o));
    }
}

#[test]
fn fifo_given_as_machine_is_exit_2_and_never_blocks() {
    let dir = tmp();
    mkfifo(&dir.path().join("m.toml"));
    let p = program("od_turning.nc");
    let p = p.to_str().unwrap();
    for args in [
        &["machine", "m.toml"][..],
        &["check", "-m", "m.toml", p],
        &["moves", "-m", "m.toml", p],
        &["accuracy", "-m", "m.toml", p],
    ] {
        let o = run(dir.path(), args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains("m.toml: cannot read machine file: it is a FIFO (named pipe), not a regular file"),
            "{args:?}: {}",
            err(&o)
        );
    }
    // Named by a latheguard.toml.
    std::fs::copy(program("od_turning.nc"), dir.path().join("p.nc")).unwrap();
    std::fs::write(dir.path().join("latheguard.toml"), "machine = \"m.toml\"\n").unwrap();
    let o = run(dir.path(), &["check", "p.nc"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("it is a FIFO"), "{}", err(&o));
}

#[test]
fn dev_zero_as_machine_fails_fast_with_a_clear_error() {
    let dir = tmp();
    let p = program("od_turning.nc");
    for args in [
        &["machine", "/dev/zero"][..],
        &["check", "-m", "/dev/zero", p.to_str().unwrap()],
    ] {
        let o = run(dir.path(), args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains("/dev/zero: cannot read machine file: it is a device, not a regular file"),
            "{}",
            err(&o)
        );
    }
}

#[test]
fn machine_file_larger_than_4_mib_is_refused_naming_file_and_cap() {
    let dir = tmp();
    let big = dir.path().join("big.toml");
    let mut f = std::fs::File::create(&big).unwrap();
    let line = format!("# {}\n", "x".repeat(1000));
    for _ in 0..4300 {
        f.write_all(line.as_bytes()).unwrap();
    }
    drop(f);
    let o = run(dir.path(), &["machine", "big.toml"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(
        err(&o).contains("big.toml: cannot read machine file: it is"),
        "{}",
        err(&o)
    );
    assert!(
        err(&o).contains("larger than the 4 MiB latheguard reads"),
        "{}",
        err(&o)
    );
}

#[test]
fn program_larger_than_256_mib_is_a_finding_without_being_read() {
    let dir = tmp();
    // Sparse: no disk space, no time.
    let f = std::fs::File::create(dir.path().join("huge.nc")).unwrap();
    f.set_len((256 << 20) + 1).unwrap();
    drop(f);
    let o = run(dir.path(), &["check", "-q", "huge.nc"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(
        out(&o).contains("larger than the 256 MiB latheguard reads"),
        "{}",
        out(&o)
    );
}

// 4. Output errors.

/// Every command that writes to standard output, with its exit status when all goes well.
fn output_commands() -> Vec<(Vec<String>, i32)> {
    let p = program("crash_dogleg.nc").display().to_string();
    let m = builtin_machine().display().to_string();
    let v = |a: &[&str]| a.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        (v(&["check", &p]), 1),
        (v(&["check", "--format", "json", &p]), 1),
        (v(&["moves", &p]), 0),
        (v(&["moves", "--format", "json", &p]), 0),
        (v(&["accuracy", "--repeats", "1", &p]), 0),
        (v(&["machine", &m]), 0),
        (v(&["completions", "bash"]), 0),
        (v(&["man"]), 0),
        (v(&["check", "--explain", "collision"]), 0),
        (v(&["--help"]), 0),
    ]
}

#[test]
fn full_disk_on_standard_output_is_an_error_with_exit_2_never_a_panic() {
    let dir = tmp();
    for (args, _) in output_commands() {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let o = run_with(dir.path(), &args, Some(Stdio::from(full)));
        no_panic(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains("cannot write to standard output: No space left on device"),
            "{args:?}: {}",
            err(&o)
        );
    }
    // -o to a full disk.
    let p = program("od_turning.nc");
    let o = run(dir.path(), &["check", "-o", "/dev/full", p.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("/dev/full: cannot write report"), "{}", err(&o));
}

#[test]
fn closed_pipe_on_standard_output_exits_quietly_with_the_usual_status() {
    let dir = tmp();
    for (args, usual) in output_commands() {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        // A pipe whose reading end is closed before latheguard starts: every write fails.
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = run_with(dir.path(), &args, Some(Stdio::from(writer)));
        no_panic(&o);
        assert!(!err(&o).contains("standard output"), "{args:?}: {}", err(&o));
        assert_eq!(o.status.code(), Some(usual), "{args:?}: {}", err(&o));
    }
}

// 5. Lost data.

#[test]
fn output_over_a_checked_program_or_an_input_is_refused_and_nothing_is_lost() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(program("crash_dogleg.nc"), d.join("prog.nc")).unwrap();
    std::fs::copy(program("od_turning.nc"), d.join("other.ngc")).unwrap();
    std::fs::copy(builtin_machine(), d.join("m.toml")).unwrap();
    let before = |p: &str| std::fs::read(d.join(p)).unwrap();
    let (prog, other, machine) = (before("prog.nc"), before("other.ngc"), before("m.toml"));
    for (args, why) in [
        (&["check", "prog.nc", "-o", "prog.nc"][..], "an input of this run"),
        (&["check", "prog.nc", "-o", "./sub/../prog.nc"], "an input of this run"),
        (&["check", "prog.nc", "--stock-out", "prog.nc"], "an input of this run"),
        (
            &["check", ".", "--format", "json", "-o", "prog.nc"],
            "an input of this run",
        ),
        (&["check", "prog.nc", "-o", "other.ngc"], "an existing NC program"),
        (
            &["check", "prog.nc", "-m", "m.toml", "-o", "m.toml"],
            "an input of this run",
        ),
        (
            &["check", "prog.nc", "-o", "latheguard.toml"],
            "a latheguard configuration",
        ),
        (&["accuracy", "prog.nc", "--plot", "prog.nc"], "an input of this run"),
    ] {
        std::fs::create_dir_all(d.join("sub")).unwrap();
        let o = run(d, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains(&format!("refusing to write over {why}")),
            "{args:?}: {}",
            err(&o)
        );
    }
    assert_eq!(before("prog.nc"), prog);
    assert_eq!(before("other.ngc"), other);
    assert_eq!(before("m.toml"), machine);
    assert!(!d.join("latheguard.toml").exists());
    // The machine named by a latheguard.toml is protected too.
    std::fs::write(d.join("latheguard.toml"), "machine = \"m.toml\"\n").unwrap();
    let o = run(d, &["check", "prog.nc", "-o", "m.toml"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert_eq!(before("m.toml"), machine);
    // A new file, or an old report, is written as before.
    let o = run(d, &["check", "prog.nc", "-o", "report.txt"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    let o = run(d, &["check", "prog.nc", "-o", "report.txt"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
}

/// A report or a stock written to a hard link of the program (or of the machine file) would
/// replace it: outputs are compared with inputs by file identity, not by path.
#[test]
fn output_through_a_hard_link_to_an_input_is_refused_and_nothing_is_lost() {
    let dir = tmp();
    let d = dir.path();
    std::fs::copy(program("crash_dogleg.nc"), d.join("p.nc")).unwrap();
    std::fs::copy(builtin_machine(), d.join("m.toml")).unwrap();
    std::fs::hard_link(d.join("p.nc"), d.join("r.txt")).unwrap();
    std::fs::hard_link(d.join("p.nc"), d.join("part.svg")).unwrap();
    std::fs::hard_link(d.join("m.toml"), d.join("m.txt")).unwrap();
    let prog = std::fs::read(d.join("p.nc")).unwrap();
    let machine = std::fs::read(d.join("m.toml")).unwrap();
    for args in [
        &["check", "p.nc", "-o", "r.txt"][..],
        &["check", "p.nc", "--stock-out", "part.svg"],
        &["check", "p.nc", "-m", "m.toml", "-o", "m.txt"],
        &["accuracy", "p.nc", "--plot", "part.svg"],
    ] {
        let o = run(d, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains("refusing to write over an input of this run"),
            "{args:?}: {}",
            err(&o)
        );
    }
    assert_eq!(std::fs::read(d.join("p.nc")).unwrap(), prog);
    assert_eq!(std::fs::read(d.join("m.toml")).unwrap(), machine);
}

// 6. Globs.

#[test]
fn nested_brace_glob_in_latheguard_toml_is_a_config_error_never_a_panic() {
    let dir = tmp();
    std::fs::create_dir(dir.path().join("a")).unwrap();
    std::fs::copy(program("od_turning.nc"), dir.path().join("a/p.nc")).unwrap();
    for depth in [9, 300, 5000] {
        let glob = format!("{}b{}/*.nc", "{a,".repeat(depth), "}".repeat(depth));
        std::fs::write(
            dir.path().join("latheguard.toml"),
            format!("[[override]]\nglob = \"{glob}\"\nclearance = 1\n"),
        )
        .unwrap();
        let o = run(dir.path(), &["check", "-q", "."]);
        no_panic(&o);
        assert_eq!(o.status.code(), Some(2), "depth {depth}: {}", err(&o));
        assert!(
            err(&o).contains("latheguard.toml:2:8: override[0].glob: not a glob"),
            "{}",
            err(&o)
        );
    }
    // Shallow nesting is a glob like any other.
    std::fs::write(
        dir.path().join("latheguard.toml"),
        "[[override]]\nglob = \"{a,{b,c}}/*.nc\"\nclearance = 1\n",
    )
    .unwrap();
    let o = run(dir.path(), &["check", "--format", "json", "."]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["settings"]["clearance_mm"], 1.0, "{}", out(&o));
}

// 7. Terminal injection.

#[test]
fn control_and_bidi_characters_in_file_names_are_escaped_in_text_and_on_stderr() {
    let dir = tmp();
    let name = "a\u{1b}[31mb\nc\rd\u{202e}e\u{2066}f.nc";
    std::fs::copy(program("crash_dogleg.nc"), dir.path().join(name)).unwrap();
    let raw = |s: &str| s.contains(['\u{1b}', '\r', '\u{202e}', '\u{2066}']);

    let o = run(dir.path(), &["check", "."]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(!raw(&out(&o)) && !raw(&err(&o)), "{:?}", out(&o));
    assert!(
        out(&o).contains("a\\x1b[31mb\\nc\\rd\\u{202e}e\\u{2066}f.nc:24: error[rapid_into_stock]"),
        "{}",
        out(&o)
    );
    // JSON keeps the true path.
    let o = run(dir.path(), &["check", "--format", "json", "."]);
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["files"][0]["path"], name);
    // Standard error: a machine file that does not exist, the moves of the program.
    let bad = format!("{name}.toml");
    let o = run(dir.path(), &["check", "-m", &bad, name]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!raw(&err(&o)), "{:?}", err(&o));
    assert!(err(&o).contains("a\\x1b[31mb\\nc"), "{}", err(&o));
    let o = run(dir.path(), &["moves", name]);
    assert!(!raw(&err(&o)), "{:?}", err(&o));
    let o = run(dir.path(), &["accuracy", "--repeats", "1", name]);
    assert!(!raw(&out(&o)), "{:?}", out(&o));
    // The final part picture stays well-formed XML.
    let o = run(dir.path(), &["check", "-q", name, "--stock-out", "part.svg"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    let svg = std::fs::read_to_string(dir.path().join("part.svg")).unwrap();
    assert!(roxmltree::Document::parse(&svg).is_ok());
}

// 8. Pictures.

#[test]
fn svg_pictures_are_capped_at_100_per_file_and_the_rest_counted() {
    let dir = tmp();
    let mut prog = String::from("G18 G21 G90 G95\nT0101\nG97 S1000 M3\n");
    for _ in 0..120 {
        prog.push_str("G0 X60 Z2\nG0 X40\nG0 Z-5\nG0 X60\n");
    }
    prog.push_str("M30\n");
    std::fs::write(dir.path().join("many.nc"), prog).unwrap();
    let o = run(dir.path(), &["check", "-q", "--svg", "pics", "many.nc"]);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    assert!(out(&o).contains("120 errors"), "{}", out(&o));
    assert_eq!(std::fs::read_dir(dir.path().join("pics")).unwrap().count(), 100);
    assert!(
        err(&o).contains("left out 20 pictures (at most 100 per file and 1000 per run)"),
        "{}",
        err(&o)
    );
}

#[test]
fn a_machine_value_that_looks_like_a_unit_mistake_is_warned_on_standard_error() {
    let dir = tmp();
    let text = std::fs::read_to_string(builtin_machine()).unwrap();
    let bad = dir.path().join("unit.toml");
    std::fs::write(&bad, text.replace("rapid = 20000.0", "rapid = 1.0")).unwrap();
    let bad_s = bad.to_str().unwrap();
    for args in [
        vec!["machine", bad_s],
        vec!["check", "-m", bad_s, program("facing.nc").to_str().unwrap()],
    ] {
        let o = run(dir.path(), &args);
        no_panic(&o);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {}", err(&o));
        assert!(
            err(&o).contains("warning:") && err(&o).contains("axes.x.rapid"),
            "{args:?}: {}",
            err(&o)
        );
    }
}

#[test]
fn sarif_of_one_long_line_with_many_findings_does_not_copy_the_line_per_finding() {
    // 100,000 findings on one 1 MB line: each SARIF result used to quote the whole line (10 GB).
    let dir = tmp();
    let prog = format!("G0 X10 Z5\n{}\n", "G1 X10 Q1 ".repeat(100_000));
    std::fs::write(dir.path().join("long.nc"), &prog).unwrap();
    let o = run(dir.path(), &["check", "--format", "sarif", "long.nc"]);
    no_panic(&o);
    assert_eq!(o.status.code(), Some(1), "{}", err(&o));
    let log = out(&o);
    assert!(log.contains("\"ruleId\""), "{}", &log[..log.len().min(2000)]);
    assert!(log.len() < 50 * prog.len(), "SARIF log of {} bytes", log.len());
    // A short line is still quoted.
    std::fs::write(dir.path().join("short.nc"), "G0 X10 Z5\nG1 X10 Q1\n").unwrap();
    let o = run(dir.path(), &["check", "--format", "sarif", "short.nc"]);
    assert!(out(&o).contains("\"snippet\""), "{}", out(&o));
}
