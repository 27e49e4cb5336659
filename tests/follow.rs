//! `latheguard follow` (issue 30 §3, docs/follow.md): a stream of samples with a crash in the
//! middle, malformed and out-of-order samples, the reader's formats, two carriers against each
//! other, and the replay of every turn-mill and two-path example against `check`.

use latheguard::follow::{sample, Format, Latency, Reader};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_latheguard"));
    c.current_dir(root());
    c
}

/// `follow` with `args`, `input` on standard input: (exit code, stdout lines).
fn follow(args: &[&str], input: &str) -> (i32, Vec<String>) {
    let mut child = bin()
        .arg("follow")
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    (out.status.code().unwrap(), text.lines().map(str::to_string).collect())
}

fn json_lines(lines: &[String]) -> Vec<serde_json::Value> {
    lines.iter().map(|l| serde_json::from_str(l).unwrap()).collect()
}

#[test]
fn a_rapid_into_the_bar_in_the_middle_of_a_stream_is_one_error_at_its_line_and_sample_time() {
    // T01 rapids from home to 5 mm off the bar, then (line 4, t 0.06 to 0.08 s) 9 mm in x and
    // 15 mm in z toward the chuck: its tip enters the bar (radius 25, face at z 80) 4 mm deep
    // (its holder's low corner, 4.82 mm above the tip, stays 0.82 mm clear of the bar).
    let (code, out) = follow(&["--format", "json", "tests/fixtures/follow/crash.jsonl"], "");
    assert_eq!(code, 1, "{out:?}");
    let docs = json_lines(&out);
    assert_eq!(docs.len(), 1, "{out:?}");
    let f = &docs[0];
    assert_eq!(f["kind"], "rapid_into_stock");
    assert_eq!(f["severity"], "error");
    assert_eq!(f["line"], 4);
    assert_eq!(f["objects"], serde_json::json!(["T01 insert", "stock"]));
    let t = f["time_s"].as_f64().unwrap();
    // The tip crosses the face z 80 two thirds of the way through the sample interval 0.06–0.07.
    assert!((0.06..=0.07).contains(&t), "{t}");
    assert!((t - 0.0666667).abs() < 2e-3, "{t}");
    assert!((f["depth_mm"].as_f64().unwrap() - 4.0).abs() < 0.05, "{f}");
}

#[test]
fn malformed_and_out_of_order_samples_are_errors_at_their_line_and_column_and_the_stream_goes_on() {
    let (code, out) = follow(&["tests/fixtures/follow/bad.csv"], "");
    // The crash after the bad rows is still found; exit 1.
    assert_eq!(code, 1, "{out:?}");
    assert_eq!(
        out,
        [
            "tests/fixtures/follow/bad.csv:4:10: error[sample]: `abc` is not a number",
            "tests/fixtures/follow/bad.csv:6: error[sample]: time 0.01 s is not after the last sample's 0.02 s: the sample is out of order and is skipped",
            "tests/fixtures/follow/bad.csv:7: error[sample]: the sample has no time `t` (or give --period)",
            "tests/fixtures/follow/bad.csv: line 4: error[rapid_into_stock]: rapid move drives the T01 insert into the stock (depth 4.000 mm, at 0.067 s, X-275 Z-523.334, until line 5)",
        ]
    );
}

#[test]
fn bad_json_samples_name_their_column_and_rejected_samples_alone_exit_1_as_unreadable_program_lines_do() {
    let input = "{\"t\": 0, \"X\": 0}\n{\"t\": 0.1, \"U\": 1}\n{\"t\": 0.2, \"Y\": 1}\n{\"X\": 3}\n{\"t\": 0.3, \"X\": 1\n{\"t\": 0.4, \"tool\": 9}\n{\"t\": 0.5, \"spindle\": \"fast\"}\n";
    let (code, out) = follow(&["--format", "json"], input);
    assert_eq!(code, 1, "{out:?}");
    let got: Vec<(u64, Option<u64>, String)> = json_lines(&out)
        .iter()
        .map(|d| {
            assert_eq!(d["kind"], "sample");
            (
                d["input_line"].as_u64().unwrap(),
                d["column"].as_u64(),
                d["message"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let want = [
        (2, Some(12), "unknown axis `U`: the axes are X, Z, Y, C, B and A"),
        (3, Some(12), "the machine has no Y axis"),
        (4, None, "the sample has no time `t` (or give --period)"),
        (5, Some(17), "not a JSON sample: EOF while parsing an object"),
        (6, Some(12), "tool: tool `9`: the turret has stations 1 to 8"),
        (
            7,
            Some(12),
            "spindle: `\"fast\"` is not a spindle state (cw, ccw, off, or a signed speed)",
        ),
    ];
    let want: Vec<(u64, Option<u64>, String)> = want.iter().map(|(l, c, m)| (*l, *c, m.to_string())).collect();
    assert_eq!(got, want);
}

#[test]
fn halsampler_columns_separated_by_spaces_read_with_a_period() {
    // halsampler writes the pins' values separated by spaces; a header line names them, `-`
    // skips a column, and --period times samples that carry no clock.
    let mut r = Reader::new(Format::Auto).with_period(0.001);
    assert_eq!(r.read(1, "X Z - spindle motion line").unwrap(), None);
    let s = r.read(2, "-12.5 -300.25 7 -800.0 1 42").unwrap().unwrap();
    assert_eq!(r.format(), Format::Csv);
    assert_eq!(s.t, None);
    let c = s.carrier(1).unwrap();
    assert_eq!(c.axes[0], Some(-12.5));
    assert_eq!(c.axes[1], Some(-300.25));
    assert_eq!(s.spindle, Some(sample::SpindleDir::Ccw));
    assert_eq!(c.motion, Some(sample::Motion::Rapid));
    assert_eq!(c.line, Some(42));
    let e = r.read(3, "1 2 3").unwrap_err();
    assert_eq!((e.line, e.col), (3, 0));
    assert_eq!(e.message, "3 values where the header names 6 columns");
    // Without a period, a sample without a time is an error.
    let mut r = Reader::new(Format::Csv);
    r.read(1, "X,Z").unwrap();
    assert_eq!(
        r.read(2, "1,2").unwrap_err().message,
        "the sample has no time `t` (or give --period)"
    );
}

#[test]
fn the_latency_summary_is_the_median_p99_and_max_of_what_was_added() {
    let mut l = Latency::default();
    // 98 samples of 10 µs, one of 500 µs, one of 2 ms.
    for _ in 0..98 {
        l.add(10_000);
    }
    l.add(500_000);
    l.add(2_000_000);
    let s = l.summary();
    assert_eq!(s.samples, 100);
    // A quantile is the upper end of its 1 µs bucket: never below the time it stands for.
    assert_eq!(s.median_us, 11.0);
    assert_eq!(s.p99_us, 501.0);
    assert_eq!(s.max_us, 2000.0);
    assert!((s.mean_us - (98.0 * 10.0 + 500.0 + 2000.0) / 100.0).abs() < 1e-9);
}

/// Every NC program under `dir`, sorted.
fn programs(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            programs(&p, out);
        } else if p.extension().is_some_and(|e| e == "nc") {
            out.push(p);
        }
    }
}

/// The samples step of the replay test, ms: coarse, since a sample costs a move's check whatever
/// its length (the live-tool examples cost milliseconds a sample), and the equality is claimed
/// for any step.
const REPLAY_DT_MS: &str = "100";

/// The errors of a JSON finding list as (line, kind, objects, time).
fn errors_of(findings: &[serde_json::Value]) -> Vec<(u64, String, String, f64)> {
    let mut v: Vec<_> = findings
        .iter()
        .filter(|f| f["severity"] == "error" && f["kind"] != "sample")
        .map(|f| {
            (
                f["line"].as_u64().unwrap(),
                f["kind"].as_str().unwrap().to_string(),
                f["objects"].to_string(),
                f["time_s"].as_f64().unwrap_or(0.0),
            )
        })
        .collect();
    v.sort_by(|a, b| (a.0, &a.1, &a.2).cmp(&(b.0, &b.1, &b.2)));
    v
}

/// The replay (docs/follow.md, "Replay"): the samples `moves --format samples` makes of each
/// turn-mill and two-path example, followed with the setup `check` uses for it, give `check`'s errors: the
/// same lines, kinds and parts, each first contact within one sample step of `check`'s.
#[test]
fn replaying_every_turn_mill_and_two_path_example_gives_the_errors_check_gives() {
    let mut files = Vec::new();
    // The one-turret turn-mill, and the two-path machines: the twin-turret lathe (its carriers
    // against each other in the working plane) and the milling head with a lower turret (in 3D).
    for dir in ["programs/turn-mill", "programs/twin-turret", "programs/mill-turn-head"] {
        programs(&root().join(dir), &mut files);
    }
    assert!(files.len() >= 20, "{files:?}");
    let step = REPLAY_DT_MS.parse::<f64>().unwrap() / 1000.0;
    for p in files {
        let rel = p.strip_prefix(root()).unwrap().to_str().unwrap().to_string();
        let check = bin().args(["check", "--format", "json", &rel]).output().unwrap();
        let doc: serde_json::Value = serde_json::from_slice(&check.stdout).unwrap();
        let want = errors_of(doc["files"][0]["findings"].as_array().unwrap());
        let samples = bin()
            .args(["moves", "--format", "samples", "--dt", REPLAY_DT_MS, &rel])
            .output()
            .unwrap();
        assert!(
            samples.status.success(),
            "{rel}: {}",
            String::from_utf8_lossy(&samples.stderr)
        );
        let input = String::from_utf8(samples.stdout).unwrap();
        let (code, out) = follow(&["--program", &rel, "--format", "json"], &input);
        let got = errors_of(&json_lines(&out));
        assert!(
            out.iter().all(|l| !l.contains("\"kind\":\"sample\"")),
            "{rel}: the replay's own samples are rejected: {out:?}"
        );
        assert_eq!(code, if got.is_empty() { 0 } else { 1 }, "{rel}");
        let key = |v: &[(u64, String, String, f64)]| -> Vec<(u64, String, String)> {
            v.iter().map(|(l, k, o, _)| (*l, k.clone(), o.clone())).collect()
        };
        assert_eq!(key(&got), key(&want), "{rel}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g.3 - w.3).abs() <= step + 1e-6, "{rel}: {g:?} against check's {w:?}");
        }
    }
}

/// The samples of `tests/fixtures/follow/crash.jsonl` served on a socket the test listens on:
/// `follow` connects, reads them as it would standard input and reports the same crash.
fn follow_from_socket(source: &str, serve: impl FnOnce(&[u8]) + Send + 'static) -> (i32, Vec<String>) {
    let samples = std::fs::read(root().join("tests/fixtures/follow/crash.jsonl")).unwrap();
    let server = std::thread::spawn(move || serve(&samples));
    let out = bin()
        .args(["follow", "--format", "json", source])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    server.join().unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    (out.status.code().unwrap(), text.lines().map(str::to_string).collect())
}

/// `follow`'s answer to `crash.jsonl`: the one rapid into the bar at line 4, exit 1.
fn assert_the_crash_of_crash_jsonl(code: i32, out: &[String]) {
    assert_eq!(code, 1, "{out:?}");
    let docs = json_lines(out);
    assert_eq!(docs.len(), 1, "{out:?}");
    assert_eq!(
        (docs[0]["kind"].as_str(), docs[0]["line"].as_u64()),
        (Some("rapid_into_stock"), Some(4))
    );
}

#[test]
fn samples_read_from_a_tcp_socket_give_the_crash_standard_input_gives() {
    let listener = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let (code, out) = follow_from_socket(&format!("tcp:127.0.0.1:{port}"), move |samples| {
        let (mut conn, _) = listener.accept().unwrap();
        conn.write_all(samples).unwrap();
    });
    assert_the_crash_of_crash_jsonl(code, &out);
}

#[cfg(unix)]
#[test]
fn samples_read_from_a_unix_socket_give_the_crash_standard_input_gives() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("samples.sock");
    let listener = std::os::unix::net::UnixListener::bind(&path).unwrap();
    let (code, out) = follow_from_socket(&format!("unix:{}", path.display()), move |samples| {
        let (mut conn, _) = listener.accept().unwrap();
        conn.write_all(samples).unwrap();
    });
    assert_the_crash_of_crash_jsonl(code, &out);
    // A socket nobody listens on is a clear error, exit 2.
    let gone = dir.path().join("nobody.sock");
    let out = bin()
        .args(["follow", &format!("unix:{}", gone.display())])
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nobody.sock"));
}

/// Two carriers at the same Z, their tips 5 mm from the spindle axis on either side (the
/// twin-turret machine: machine zero at home, X 300 Z 600; T01's tip -60, -12 from the
/// reference point, so a tip at radius `r`, z 100 is X `r - 240`, Z -488 on either carrier).
/// Path 1 feeds its tip to radius -1 (line 10, 0 to 0.1 s); then path 2 feeds its tip to -1
/// (line 20, 0.1 to 0.2 s), `ahead` while path 1 is still there, else after path 1 has gone
/// back to radius 5 (line 11, 0.1 to 0.2 s; path 2 from 0.2 to 0.3 s).
fn two_turret_stream(ahead: bool) -> String {
    let head = "{\"t\": 0, \"X\": -235, \"Z\": -488, \"X2\": -235, \"Z2\": -488, \"motion\": \"feed\", \"motion2\": \"feed\", \"line\": 9, \"line2\": 19}\n{\"t\": 0.1, \"X\": -241, \"line\": 10}\n";
    if ahead {
        format!("{head}{{\"t\": 0.2, \"X2\": -241, \"line2\": 20}}\n{{\"t\": 0.3, \"X\": -235, \"line\": 11}}\n")
    } else {
        format!("{head}{{\"t\": 0.2, \"X\": -235, \"line\": 11}}\n{{\"t\": 0.3, \"X2\": -241, \"line2\": 20}}\n")
    }
}

/// `follow` checks every carrier of a two-path machine, and the carriers against each other:
/// the lower turret driven into the upper one's insert while the upper stands past the axis is a
/// A stream's output that is one crash between two carriers: exit 1, a `collision` at each of
/// `lines`, each naming both `parts`, from `t` (within 1 ms). Returns the two findings.
fn one_crash_between_carriers(
    code: i32,
    out: &[String],
    lines: [u64; 2],
    parts: [&str; 2],
    t: f64,
) -> Vec<serde_json::Value> {
    assert_eq!(code, 1, "{out:?}");
    let docs = json_lines(out);
    assert_eq!(docs.len(), 2, "{out:?}");
    let mut at: Vec<u64> = docs.iter().map(|d| d["line"].as_u64().unwrap()).collect();
    at.sort_unstable();
    assert_eq!(at, lines, "{out:?}");
    for d in &docs {
        assert_eq!(d["kind"], "collision", "{d}");
        let objects = d["objects"].to_string();
        assert!(parts.iter().all(|p| objects.contains(p)), "{d}");
        assert!((d["time_s"].as_f64().unwrap() - t).abs() < 1e-3, "{d}");
    }
    docs
}

/// `collision` at each path's line, from when the tips meet (path 2's tip at radius 1, two
/// thirds of its move: 0.1667 s); the same move once path 1 has gone back is clean.
#[test]
fn a_crash_between_two_carriers_that_exists_only_when_path_2_runs_ahead() {
    let (code, out) = follow(
        &["-m", "machines/twin-turret.toml", "--format", "json"],
        &two_turret_stream(true),
    );
    let docs = one_crash_between_carriers(
        code,
        &out,
        [10, 20],
        ["path1:T01 insert", "path2:T01 insert"],
        0.1 + 0.1 * 2.0 / 3.0,
    );
    for d in &docs {
        let depth = d["depth_mm"].as_f64().unwrap();
        // The tips pass each other by 2 mm at most.
        assert!(depth > 0.5 && depth <= 2.0 + 1e-6, "{d}");
    }
    let (code, out) = follow(&["-m", "machines/twin-turret.toml"], &two_turret_stream(false));
    assert_eq!((code, out.len()), (0, 0), "{out:?}");
}

/// A key of a path the machine lacks, an axis or a station the carrier lacks: errors at their
/// column, and the stream goes on.
#[test]
fn keys_of_a_path_or_an_axis_the_machine_lacks_are_sample_errors() {
    let input = "{\"t\": 0, \"X3\": 1}\n{\"t\": 0.1, \"Y2\": 1}\n{\"t\": 0.2, \"tool2\": 9}\n{\"t\": 0.3, \"X2\": 1}\n";
    let (code, out) = follow(&["-m", "machines/twin-turret.toml"], input);
    assert_eq!(code, 1, "{out:?}");
    assert_eq!(
        out,
        [
            "<stdin>:1:10: error[sample]: `X3` is path 3's, but the machine has 2 paths",
            "<stdin>:2:12: error[sample]: path 2's carrier has no Y axis (`Y2`)",
            "<stdin>:3:12: error[sample]: tool2: tool `9`: the turret has stations 1 to 4",
        ],
        "{out:?}"
    );
    let (code, out) = follow(&["-m", "machines/turn-mill.toml"], "{\"t\": 0, \"X2\": 1}\n");
    assert_eq!(code, 1, "{out:?}");
    assert_eq!(
        out,
        ["<stdin>:1:10: error[sample]: `X2` is path 2's, but the machine has 1 path"]
    );
}

/// A sample that jumps 847 m (found by the fuzzer: one sample took 0.66 s, the carriers' search
/// stepping through the contact at the tolerance): each sample interval's search of the
/// carriers against each other stops at its budget with a warning, so a sample's work stays a
/// move's, and the contact it did find is still written.
#[test]
fn a_sample_jumping_far_through_the_other_carrier_stops_at_the_interval_budget() {
    let input = "{\"t\": 0, \"X\": 0, \"Z\": -100}\n{\"t\": 0.01, \"X\": -847000}\n";
    let (code, out) = follow(
        &["-m", "machines/twin-turret.toml", "--format", "json", "--stats"],
        input,
    );
    assert_eq!(code, 1, "{out:?}");
    let docs = json_lines(&out);
    assert!(docs.iter().any(|d| d["kind"] == "collision"), "{out:?}");
    let budget = latheguard::follow::MAX_CROSS_PROBES;
    assert!(
        docs.iter().any(|d| d["kind"] == "unsupported"
            && d["message"]
                .as_str()
                .unwrap()
                .contains(&format!("stopped after {budget} probes"))),
        "{out:?}"
    );
    let tests = docs.last().unwrap()["summary"]["pair_tests"].as_u64().unwrap();
    assert!(tests <= budget + 1_000, "{tests} pair tests");
}

/// The replay of a two-path program whose waits never meet: its samples stop where the machine
/// stops, and the waits left standing are errors on standard error (exit 1), as a one-path
/// program's findings are.
#[test]
fn the_replay_of_two_paths_that_never_meet_writes_their_waits_as_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("dead.nc");
    std::fs::write(
        &p,
        "%\nO1\n$1\nG21 G18 G99\nT0101\nG0 X60 Z5\nM100\nG0 X50 Z5\nM30\n$2\nG21 G18 G99\nG0 X60 Z5\nM101\nG0 X50 Z5\nM30\n%\n",
    )
    .unwrap();
    let out = bin()
        .args([
            "moves",
            "--format",
            "samples",
            "--dt",
            "100",
            "-m",
            "machines/twin-turret.toml",
        ])
        .arg(&p)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(":7: error[program]: path 1 waits at M100 for ever"),
        "{err}"
    );
    assert!(
        err.contains(":13: error[program]: path 2 waits at M101 for ever"),
        "{err}"
    );
    // Every sample names both carriers, and none comes after the machine stopped.
    let samples = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<serde_json::Value> = samples.lines().map(|l| serde_json::from_str(l).unwrap()).collect();
    assert!(lines.len() >= 2, "{samples}");
    assert!(
        lines.iter().all(|s| s.get("X").is_some() && s.get("X2").is_some()),
        "{samples}"
    );
    assert!(!samples.contains("\"line\":8"), "{samples}");
}

/// A turret index is learnt at the sample that shows the new tool, after it has turned: the
/// check between carriers looks back over it. Path 1 stands at radius 0, Z 220 with T01 and
/// indexes to T03 (two stations, 1 s), learnt at 1.2 s: its swing (every station at every angle,
/// x from -60 to 340 and z from 110 to 241 in the working plane) began at 0.2 s, when path 2's
/// T01 insert stood inside it (radius 40 to 54 across the axis, z 140 to 154) and left by
/// 0.22 s. No sample interval holds both the swing and path 2 there, so only the look back
/// finds the crash (without it the stream was clean).
#[test]
fn a_turret_index_learnt_late_is_checked_against_where_the_other_carrier_was_while_it_turned() {
    let input = [
        r#"{"t": 0, "X": -300, "Z": -380, "tool": 1, "line": 9, "X2": -200, "Z2": -448, "tool2": 1, "line2": 19, "motion": "rapid", "motion2": "rapid"}"#,
        r#"{"t": 0.2}"#,
        r#"{"t": 0.4, "X2": 0, "line2": 20}"#,
        r#"{"t": 1.2, "tool": 3, "line": 10}"#,
    ]
    .join("\n");
    let (code, out) = follow(&["-m", "machines/twin-turret.toml", "--format", "json"], &input);
    // Path 2 stood at its line 19 when the swing began.
    one_crash_between_carriers(code, &out, [10, 19], ["path1:tools indexing", "path2:T01 insert"], 0.2);
}
