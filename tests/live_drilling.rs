//! Fanuc's live-tool drilling cycles (`drilling_cycles = "fanuc"`: face G83/G84/G85, side
//! G87/G88/G89 at a C angle), builder G codes (`[gcodes]`), the live tool's speed from S on its
//! line, and the turn-mill programs of `../shared/corpus-extra` on machines like theirs (issue
//! 16; docs/turn-mill.md, "Live-tool drilling cycles" and "The corpus's turn-mill programs").

use std::process::Command;

use crate::files;

const TM: &str = "machines/turn-mill.toml";
const F16T: &str = "tests/corpus-jobs/machines/fanuc-16t-mill-turn.toml";
const NL: &str = "tests/corpus-jobs/machines/mori-seiki-nl1500y.toml";

fn run(args: &[&str]) -> (String, String, Option<i32>) {
    let out = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(args)
        .output()
        .unwrap();
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.code(),
    )
}

/// A program in a temporary folder of its own (both removed when dropped).
struct Temp {
    _dir: tempfile::TempDir,
    path: std::path::PathBuf,
}

impl Temp {
    fn new(name: &str, text: &str) -> Temp {
        let dir = tempfile::Builder::new().prefix("lg-live-drilling-").tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, text).unwrap();
        Temp { _dir: dir, path }
    }
    fn path(&self) -> &str {
        self.path.to_str().unwrap()
    }
}

/// The canonical moves: (line, kind, x radius, z, c) for traverses and feeds, (line, "DWELL",
/// seconds, 0, 0) for dwells.
fn canon(machine: &str, program: &str) -> Vec<(u32, String, f64, f64, f64)> {
    let (out, err, _) = run(&["moves", "--machine", machine, "--format", "canon", program]);
    let mut v = Vec::new();
    for l in out.lines() {
        let l = l.trim();
        let Some((line, rest)) = l.split_once(' ') else {
            continue;
        };
        let Some((kind, args)) = rest.split_once('(') else {
            continue;
        };
        let n: Vec<f64> = args
            .trim_end_matches(')')
            .split(',')
            .filter_map(|s| s.trim().parse().ok())
            .collect();
        let line: u32 = line.parse().unwrap();
        match kind {
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => v.push((line, kind.to_string(), n[0], n[2], n[5])),
            "DWELL" => v.push((line, kind.to_string(), n[0], 0.0, 0.0)),
            _ => {}
        }
    }
    assert!(!v.is_empty(), "no moves: {err}");
    v
}

fn findings(machine: &str, program: &str) -> Vec<serde_json::Value> {
    let (out, err, _) = run(&["check", "--format", "json", "--machine", machine, program]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}{err}"));
    v["files"][0]["findings"].as_array().cloned().unwrap_or_default()
}

/// The interpreter's findings (what `moves` prints on stderr): reading, not checking.
fn read_findings(machine: &str, program: &str) -> String {
    run(&["moves", "--machine", machine, "--format", "canon", program]).1
}

fn kinds(f: &[serde_json::Value]) -> Vec<(u64, String)> {
    f.iter()
        .map(|x| (x["line"].as_u64().unwrap(), x["kind"].as_str().unwrap().to_string()))
        .collect()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-4
}

/// Worked by hand (Fanuc 0i-TD, G83): from Z5, `R-3.` puts the R point at Z2; Q5 pecks reach
/// Z-3, -8, -13 and the bottom Z-15, each followed by a rapid out to R and back to 1 mm above
/// the last depth; the return is the initial level Z5 (system A). The next holes turn C first.
#[test]
fn face_g83_pecks_from_an_r_point_signed_from_the_initial_level() {
    let m = canon(TM, "tests/fixtures/live-drilling/face_holes_g83.nc");
    let hole: Vec<_> = m.iter().filter(|e| e.0 == 9).collect();
    let expect = [
        ("STRAIGHT_TRAVERSE", 2.0),
        ("STRAIGHT_FEED", -3.0),
        ("STRAIGHT_TRAVERSE", 2.0),
        ("STRAIGHT_TRAVERSE", -2.0),
        ("STRAIGHT_FEED", -8.0),
        ("STRAIGHT_TRAVERSE", 2.0),
        ("STRAIGHT_TRAVERSE", -7.0),
        ("STRAIGHT_FEED", -13.0),
        ("STRAIGHT_TRAVERSE", 2.0),
        ("STRAIGHT_TRAVERSE", -12.0),
        ("STRAIGHT_FEED", -15.0),
        ("STRAIGHT_TRAVERSE", 2.0),
        ("STRAIGHT_TRAVERSE", 5.0),
    ];
    assert_eq!(hole.len(), expect.len(), "{hole:?}");
    for (got, (kind, z)) in hole.iter().zip(expect) {
        assert_eq!(got.1, kind, "{got:?}");
        assert!(
            close(got.2, 15.0) && close(got.3, z) && close(got.4, 0.0),
            "{got:?} vs Z{z}"
        );
    }
    // C120: the first move of line 10 turns the spindle, at the initial level, nothing else.
    let turn = m.iter().find(|e| e.0 == 10).unwrap();
    assert_eq!(turn.1, "STRAIGHT_TRAVERSE");
    assert!(
        close(turn.2, 15.0) && close(turn.3, 5.0) && close(turn.4, 120.0),
        "{turn:?}"
    );
    assert!(m.iter().any(|e| e.0 == 11 && close(e.3, -15.0) && close(e.4, 240.0)));
}

/// G87 from X70: R-5. is a radius, so the R point is X60 (radius 30); Q3. pecks to radius 27,
/// 24, 21, 18 and the bottom X30 (radius 15).
#[test]
fn side_g87_reads_r_as_a_radius_and_drills_along_x() {
    let m = canon(TM, "tests/fixtures/live-drilling/cross_holes_g87.nc");
    let feeds: Vec<f64> = m
        .iter()
        .filter(|e| e.0 == 9 && e.1 == "STRAIGHT_FEED")
        .map(|e| e.2)
        .collect();
    assert_eq!(feeds.len(), 5, "{m:?}");
    for (got, want) in feeds.iter().zip([27.0, 24.0, 21.0, 18.0, 15.0]) {
        assert!(close(*got, want), "{feeds:?}");
    }
    assert!(m.iter().filter(|e| e.0 == 9).all(|e| close(e.3, -20.0)));
    let first = m.iter().find(|e| e.0 == 9).unwrap();
    assert!(close(first.2, 30.0), "the rapid to the R point: {first:?}");
    // Each later block drills at its C; the cycle ends at the initial level X70.
    for (line, c) in [(10, 90.0), (11, 180.0), (12, 270.0)] {
        let at: Vec<_> = m.iter().filter(|e| e.0 == line).collect();
        assert!(at.iter().all(|e| close(e.4, c)), "{at:?}");
        assert!(close(at.last().unwrap().2, 35.0));
    }
}

#[test]
fn cross_and_face_holes_drilled_as_programmed_are_clean() {
    for p in [
        "tests/fixtures/live-drilling/cross_holes_g87.nc",
        "tests/fixtures/live-drilling/face_holes_g83.nc",
    ] {
        let f = findings(TM, p);
        assert!(f.is_empty(), "{p}: {f:?}");
    }
}

/// `R-12.` from X70 puts the R point at radius 23, 2 mm inside the Ø50 bar: each hole's rapid
/// to it drives the drill in (the R point signed toward the hole, as Fanuc reads it).
#[test]
fn an_r_point_inside_the_bar_is_a_rapid_into_the_stock_at_every_hole() {
    let f = findings(TM, "tests/fixtures/live-drilling/crash_g87_r_point_inside_the_bar.nc");
    let k = kinds(&f);
    let want: Vec<(u64, String)> = (9..=12).map(|l| (l, "rapid_into_stock".to_string())).collect();
    assert_eq!(k, want, "{f:?}");
    for x in &f {
        assert!((x["depth_mm"].as_f64().unwrap() - 2.0).abs() < 0.05, "{x}");
    }
}

/// G88 taps in and out at feed with a dwell; G89 turns C to its angle first and dwells P0.5 s;
/// K0 keeps the words and drills nothing; K2 is reported.
#[test]
fn tapping_boring_and_repeats_follow_the_manual() {
    let prog = Temp::new(
        "g88.nc",
        "G21 G18 G99\nT0808\nM154\nG0 X70. Z-20. C0.\nG98\nM133 P1500\nG88 X40. Z-20. R-5. P200 F100.\n\
         G89 X40. Z-30. C45. P0.5 F50.\nG80\nG87 X40. Z-40. K0 R-4. F60.\nG87 X40. Z-40. K2\nM30\n",
    );
    let m = canon(TM, prog.path());
    let tap: Vec<_> = m.iter().filter(|e| e.0 == 7).map(|e| (e.1.as_str(), e.2)).collect();
    assert_eq!(
        tap,
        [
            ("STRAIGHT_TRAVERSE", 30.0),
            ("STRAIGHT_FEED", 20.0),
            ("DWELL", 0.2),
            ("STRAIGHT_FEED", 30.0),
            ("STRAIGHT_TRAVERSE", 35.0)
        ]
    );
    let bore: Vec<_> = m.iter().filter(|e| e.0 == 8).collect();
    assert!(close(bore[0].4, 45.0) && close(bore[0].2, 35.0) && close(bore[0].3, -30.0));
    assert!(bore.iter().any(|e| e.1 == "DWELL" && close(e.2, 0.5)));
    assert!(!m.iter().any(|e| e.0 == 10), "K0 drills nothing");
    let f = findings(TM, prog.path());
    assert_eq!(kinds(&f), [(11, "unsupported".to_string())], "{f:?}");
}

/// The same hex with the builder's G121/G120 as with G12.1/G13.1: the same moves; G140 and the
/// other ignored codes give no finding.
#[test]
fn builder_codes_run_as_the_codes_the_machine_file_names() {
    let hex = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/polar/hex_g12_1.nc"
    ))
    .unwrap()
    .replace("M154", "M43")
    .replace("M133 P3000", "G262 S3000 M13")
    .replace("M135", "M15")
    .replace("M155", "M40");
    let std = Temp::new("hex_std.nc", &hex);
    let builder = Temp::new(
        "hex_builder.nc",
        &hex.replace("G21 G18", "G21 G140 G18")
            .replace("G12.1", "G145 G121")
            .replace("G13.1", "G120"),
    );
    assert_eq!(canon(F16T, std.path()), canon(F16T, builder.path()));
    let f = read_findings(F16T, builder.path());
    assert!(f.is_empty(), "{f}");
    // On a machine without the table, G121 is what it always was: unknown.
    let f = read_findings(TM, builder.path());
    assert!(f.contains(":11: error[unsupported]: G121 is not a fanuc code"), "{f}");
}

/// `S3000 M13` with no P: the S is the live tool's speed (no "taken as stopped" warning, no
/// spindle_stopped finding) and not the main spindle's.
#[test]
fn an_s_word_on_the_live_tool_line_is_the_live_tool_speed() {
    let hex = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/polar/hex_g12_1.nc"
    ))
    .unwrap()
    .replace("M133 P3000", "S3000 M133");
    let p = Temp::new("hex_s.nc", &hex);
    let f = findings(TM, p.path());
    assert!(f.is_empty(), "{f:?}");
    let stopped = Temp::new("hex_no_speed.nc", &hex.replace("S3000 M133", "M133"));
    let f = read_findings(TM, stopped.path());
    assert!(f.contains("starts the live tool without a speed"), "{f}");
}

#[test]
fn bad_builder_codes_and_drilling_keys_are_refused_with_the_key() {
    let base =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/machines/generic-slant-bed.toml")).unwrap();
    let cases = [
        ("[gcodes]\nM121 = \"G12.1\"\n", "gcodes.M121", "is not a G code"),
        (
            "[gcodes]\nG121 = \"G12.3\"\n",
            "gcodes.G121",
            "G12.3 is not a fanuc code",
        ),
        (
            "[gcodes]\nG140 = { ignore = \" \" }\n",
            "gcodes.G140",
            "needs the reason",
        ),
        ("[gcodes]\nG140 = 3\n", "gcodes", "a G code such as"),
    ];
    for (extra, key, msg) in cases {
        let m = Temp::new("bad.toml", &format!("{base}\n{extra}"));
        let (out, err, code) = run(&["machine", m.path()]);
        assert_eq!(code, Some(2), "{extra}: {out}{err}");
        assert!(err.contains(key) && err.contains(msg), "{extra}: {err}");
    }
    let lcnc = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/machines/linuxcnc-small-lathe.toml"
    ))
    .unwrap()
    .replace("[machine]\n", "[machine]\ndrilling_cycles = \"fanuc\"\n");
    let m = Temp::new("lcnc.toml", &lcnc);
    let (_, err, code) = run(&["machine", m.path()]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("machine.drilling_cycles"), "{err}");
}

/// The turn-mill programs of `../shared/corpus-extra` read on the machines like theirs with no
/// `unsupported` finding; what else they give is the programs' own (docs/turn-mill.md).
/// Read with `moves` (the interpreter's findings): checking the NX sample takes minutes (its
/// tool numbers leave live drills plunging into the chuck; docs/turn-mill.md).
#[test]
fn the_corpus_turn_mill_programs_read_with_no_unsupported_code() {
    let dir = files::shared().join("corpus-extra");
    if !dir.is_dir() {
        println!("skipped: no corpus at {}", dir.display());
        return;
    }
    let cases = [
        ("srhart-polar/O131.nc", F16T),
        ("unigraphics-nx-postprocessor/MoriSeiki_NL1500Y_output.txt", NL),
        ("unigraphics-nx-postprocessor/MoriSeiki_NL1500Y_polar_output.txt", NL),
    ];
    for (rel, machine) in cases {
        let p = dir.join(rel);
        let (_, err, _) = run(&["moves", "--machine", machine, "--format", "canon", p.to_str().unwrap()]);
        let unsupported: Vec<u32> = err
            .lines()
            .filter(|l| l.contains("[unsupported]"))
            .map(|l| l.split(':').nth(1).unwrap().parse().unwrap())
            .collect();
        assert!(unsupported.is_empty(), "{rel}: unsupported at {unsupported:?}: {err}");
        // Each program's codes were read: no finding says a code is unknown.
        assert!(
            !err.contains("not a fanuc code") && !err.contains("M-code table"),
            "{rel}: {err}"
        );
    }
}

/// The turn-mill machine read with Haas's drilling cycles (the default `drilling_cycles`).
fn haas_turn_mill() -> latheguard::machine::Machine {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(TM);
    let dir = path.parent().unwrap().to_path_buf();
    let mut m =
        latheguard::machine::from_toml_with(&std::fs::read_to_string(&path).unwrap(), TM, &move |name: &str| {
            std::fs::read(dir.join(name)).map_err(|e| e.to_string())
        })
        .unwrap();
    m.drilling_cycles = latheguard::machine::DrillingCycles::Haas;
    m
}

/// Haas's axial live drilling (the Haas lathe manual's G81–G89 with C): in C-axis mode a G81 at
/// X30 C0 (R the absolute R plane, Z2) drills at radius 15, and a block with only C drills the
/// next hole there after the spindle turns; off the axis without C-axis mode it is the
/// control's refusal, as before.
#[test]
fn haas_g81_with_c_drills_a_live_hole_in_c_axis_mode() {
    let m = haas_turn_mill();
    let src = "G21 G18 G99\nT0707\nM154\nG0 X30. Z5. C0.\nM133 P2000\nG98\nG81 X30. C0. Z-10. R2. F100.\nC90.\nG80\nM135\nG0 Z50.\nM155\nM30\n";
    let (_, i) = latheguard::pipeline::interpret(src.as_bytes(), &m);
    assert!(i.findings.is_empty(), "{:?}", i.findings);
    let holes: Vec<(u32, f64, f64, f64)> = i
        .moves
        .iter()
        .enumerate()
        .filter(|(_, mv)| mv.line == 7 || mv.line == 8)
        .map(|(k, mv)| {
            let (x, z) = i.frame(mv).to_program(mv.end);
            (mv.line, x, z, i.extra_of(k).map_or(f64::NAN, |e| e.end[1]))
        })
        .collect();
    // Line 7: to R (Z2), feed to Z-10, out to R, back to the initial Z5; all at X30 C0.
    let l7: Vec<_> = holes.iter().filter(|h| h.0 == 7).collect();
    assert_eq!(l7.len(), 4, "{holes:?}");
    for (h, z) in l7.iter().zip([2.0, -10.0, 2.0, 5.0]) {
        assert!(close(h.1, 30.0) && close(h.2, z) && close(h.3, 0.0), "{h:?}");
    }
    // Line 8: the spindle turns to C90 first, then the same hole.
    let l8: Vec<_> = holes.iter().filter(|h| h.0 == 8).collect();
    assert!(close(l8[0].2, 5.0) && close(l8[0].3, 90.0), "{l8:?}");
    assert!(l8.iter().any(|h| close(h.2, -10.0) && close(h.3, 90.0)), "{l8:?}");
    let off = src.replace("M154\n", "");
    let (_, i) = latheguard::pipeline::interpret(off.as_bytes(), &m);
    assert!(
        i.findings.iter().any(|f| f.message.contains("not in C-axis mode")),
        "{:?}",
        i.findings
    );
    let no_c = off
        .replace("G81 X30. C0.", "G81 X30.")
        .replace("G0 X30. Z5. C0.", "G0 X30. Z5.");
    let (_, i) = latheguard::pipeline::interpret(no_c.as_bytes(), &m);
    assert!(
        i.findings
            .iter()
            .any(|f| f.line == 6 && f.message.contains("put the spindle in C-axis mode first")),
        "{:?}",
        i.findings
    );
}
