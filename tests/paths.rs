//! Multi-path programs on the twin-turret lathe (`machines/twin-turret.toml`, docs/paths.md):
//! the paths read from `$1`/`$2` lines, synchronised at their waiting M codes, each checked on its
//! own carrier, and the carriers checked against each other — with answers worked by hand, and
//! the carriers' search against a dense-sampling oracle.

use latheguard::finding::{Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};

use crate::common::root;

fn twin() -> Machine {
    crate::common::repo_machine("machines/twin-turret.toml")
}

fn program(name: &str) -> String {
    std::fs::read_to_string(root().join("programs/twin-turret").join(name)).unwrap()
}

/// The errors of a program as (line, kind, objects).
fn errors(src: &str, machine: &Machine, mode: Mode) -> Vec<(u32, Kind, Vec<String>)> {
    let out = pipeline::check(
        src.as_bytes(),
        machine,
        &Settings {
            mode,
            ..Settings::default()
        },
    );
    out.findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .map(|f| (f.line, f.kind, f.objects.clone()))
        .collect()
}

#[test]
fn the_two_drills_meet_on_the_axis_only_when_the_lower_turret_does_not_wait() {
    let m = twin();
    for mode in [Mode::Step, Mode::Exact] {
        // With M100 the lower turret's centre drill comes to the axis after the upper U-drill
        // has left it (the drill feeds until 17.0 s and goes home; the lower turret stands at
        // its M100 from 9.65 s).
        assert_eq!(
            errors(&program("centre_drill_handover.nc"), &m, mode),
            vec![],
            "{mode:?}"
        );
        // Without it the lower turret's rapid to X0 Z5 (line 22) starts at 10.15 s, while the
        // U-drill feeds to Z-25 (line 8, 2.0 s to 17.0 s): both drills on the spindle axis,
        // the holders (each from 60 mm behind its point) overlap, first at 10.47 s.
        let errs = errors(&program("crash_drills_meet_at_centre.nc"), &m, mode);
        let out = pipeline::check(
            program("crash_drills_meet_at_centre.nc").as_bytes(),
            &m,
            &Settings::default(),
        );
        let t = out.findings[0].time_s.unwrap();
        assert!((10.15..10.6).contains(&t), "{t}");
        assert_eq!(
            errs,
            vec![
                (
                    8,
                    Kind::Collision,
                    vec!["path1:T03 holder".to_string(), "path2:T02 holder".to_string()]
                ),
                (
                    22,
                    Kind::Collision,
                    vec!["path2:T02 holder".to_string(), "path1:T03 holder".to_string()]
                ),
            ],
            "{mode:?}"
        );
    }
}

#[test]
fn a_finding_of_the_second_path_is_at_its_line_of_the_file_and_in_the_machines_time() {
    // Path 2 drives its rough turning tool into the chuck jaws (Z-45 with the jaws' faces at
    // z 0, program zero at z 78: Z-78 is the jaw face; the holder of T01 reaches back 33 mm).
    let src = "%\n$1\nG21 G18 G99\nG4 X2.\nM100\nM30\n$2\nG21 G18 G99\nM100\nG97 S800 M3\nG0 X52. Z2.\nG1 Z-80. F0.3\nM30\n%\n";
    let out = pipeline::check(src.as_bytes(), &twin(), &Settings::default());
    let errs: Vec<_> = out.findings.iter().filter(|f| f.severity == Severity::Error).collect();
    assert!(!errs.is_empty(), "{:#?}", out.findings);
    assert!(errs.iter().all(|f| f.line == 12), "{errs:#?}");
    // Path 2 stood 2 s at M100 waiting for path 1's dwell: its contact is after that.
    assert!(errs[0].time_s.unwrap() > 2.0, "{errs:#?}");
}

#[test]
fn waits_that_never_meet_are_a_program_error_at_each_waiting_line() {
    let src = "$1\nG21\nM100\nM30\n$2\nG21\nM101\nM30\n";
    let out = pipeline::check(src.as_bytes(), &twin(), &Settings::default());
    let progs: Vec<_> = out
        .findings
        .iter()
        .filter(|f| f.kind == Kind::Program)
        .map(|f| (f.line, f.message.clone()))
        .collect();
    assert_eq!(progs.len(), 2, "{progs:#?}");
    assert_eq!(progs[0].0, 3);
    assert!(progs[0].1.contains("path 2 waits at M101 (line 7)"), "{}", progs[0].1);
    assert_eq!(progs[1].0, 7);
    // A wait whose P names a path that does not exist.
    let out = pipeline::check(b"$1\nM100 P13\nM30\n", &twin(), &Settings::default());
    assert!(
        out.findings
            .iter()
            .any(|f| f.kind == Kind::Program && f.line == 2 && f.message.contains("P13")),
        "{:#?}",
        out.findings
    );
}

#[test]
fn a_path_the_machine_does_not_have_is_unsupported_and_says_so() {
    let out = pipeline::check(
        b"$1\nG0 X100 Z100\nM30\n$2\nG0 X100 Z100\nM30\n",
        &Machine::builtin(),
        &Settings::default(),
    );
    let u: Vec<_> = out.findings.iter().filter(|f| f.kind == Kind::Unsupported).collect();
    assert_eq!(u.len(), 1, "{:#?}", out.findings);
    assert_eq!(u[0].line, 4);
    assert_eq!(u[0].severity, Severity::Error);
    assert!(u[0].message.contains("`[[paths]]`"), "{}", u[0].message);
}

#[test]
fn a_one_path_program_on_the_twin_turret_lathe_keeps_the_lower_turret_parked() {
    // No `$` lines: path 1 runs the program, the lower turret stands at home and is checked
    // against it. The U-drill at the centre: clean.
    let src = "G21 G18 G99\nG97 S1200 M3\nT0303\nG0 X0. Z5.\nG1 Z-25. F0.1\nG0 Z5.\nG0 X200. Z150.\nM30\n";
    assert_eq!(errors(src, &twin(), Mode::Step), vec![]);
}

#[test]
fn paths_in_the_machine_file_are_checked_with_their_keys() {
    let base = std::fs::read_to_string(root().join("machines/twin-turret.toml")).unwrap();
    // A path's own key is named with its index.
    let bad = base.replacen("[paths.turret]\nstations = 4", "[paths.turret]\nstations = 0", 1);
    let e = machine::from_toml(&bad, "twin.toml").unwrap_err();
    assert_eq!(e.key, "paths[0].turret.stations", "{e}");
    // Waiting codes that [mcodes] gives another meaning.
    let bad = base.replacen("[sync]", "[mcodes]\nsub_chuck_close = 110\n\n[sync]", 1);
    let e = machine::from_toml(&bad, "twin.toml").unwrap_err();
    assert_eq!(e.key, "sync.wait_mcodes", "{e}");
    assert!(e.message.contains("M110"), "{e}");
    // [sync] alone.
    let one = std::fs::read_to_string(root().join("machines/generic-slant-bed.toml")).unwrap();
    let e = machine::from_toml(&format!("{one}\n[sync]\nwait_mcodes = [100, 199]\n"), "one.toml").unwrap_err();
    assert_eq!(e.key, "sync", "{e}");
}

/// The carriers' search never misses a contact that dense sampling sees: random rapids of both
/// turrets' drills toward the spindle axis, each checked by the search and by sampling every
/// 0.2 ms (a rapid travels at most 0.0067 mm between samples), whose deepest overlap a search
/// that steps by at least the tolerance could only miss below it.
#[test]
fn the_carriers_search_finds_every_overlap_dense_sampling_finds() {
    let m = twin();
    let mut seed = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    const CASES: usize = 40;
    let mut contacts = 0;
    for case in 0..CASES {
        // Half the cases stand a while at the first point (long contacts), half pass through
        // (contacts of a few milliseconds).
        let mut p = || (next() * 70.0, next() * 100.0 - 30.0);
        let (a1, b1, a2, b2) = (p(), p(), p(), p());
        let (d1, d2) = if case % 2 == 0 {
            (next() * 2.0, next() * 2.0)
        } else {
            (0.0, 0.0)
        };
        let src = format!(
            "$1\nG21 G18\nT0303\nG0 X{:.3} Z{:.3}\nG4 X{d1:.3}\nG0 X{:.3} Z{:.3}\nG0 X200. Z150.\nM30\n$2\nG21 G18\nT0202\nG0 X{:.3} Z{:.3}\nG4 X{d2:.3}\nG0 X{:.3} Z{:.3}\nG0 X200. Z150.\nM30\n",
            a1.0, a1.1, b1.0, b1.1, a2.0, a2.1, b2.0, b2.1
        );
        let out = pipeline::check(src.as_bytes(), &m, &Settings::default());
        let first = out
            .findings
            .iter()
            .filter(|f| f.kind == Kind::Collision && f.objects[0].starts_with("path"))
            .filter_map(|f| f.time_s)
            .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.min(t))));
        let found = first.is_some();
        if let Some(t) = oracle_first(&src, &m, 2.0 * Settings::default().tolerance_mm) {
            // Found, and no later than the sample that sees it (a search that steps past the
            // beginning of a contact finds it late or not at all).
            assert!(
                first.is_some_and(|f| f <= t + 1e-3),
                "case {case}: sampling finds an overlap at {t:.4} s, the search at {first:?}:\n{src}"
            );
        }
        contacts += usize::from(found);
    }
    // The cases reach both answers.
    assert!(
        contacts > 4 && contacts < CASES - 4,
        "{contacts} of {CASES} cases in contact"
    );
}

/// The first sample (every 0.2 ms) at which the two carriers' active drills and holders overlap
/// by more than `depth`: the obvious way, with no bound and no skip.
fn oracle_first(src: &str, m: &Machine, depth: f64) -> Option<f64> {
    use latheguard::geom::{query, Polygon, P2};
    use latheguard::interp::MoveKind;
    let split = latheguard::paths::split::split(src.as_bytes()).unwrap();
    let mut lanes = Vec::new();
    for (p, text) in &split.paths {
        let view = m.for_path(*p).unwrap().into_owned();
        let (_, run) = pipeline::interpret(text, &view);
        let tl = latheguard::motion::timeline(&run, &view);
        lanes.push((view, run, tl, *p == 2));
    }
    let shapes = |view: &Machine, station: u32, opposite: bool, r: P2| -> Vec<Polygon> {
        let t = view.tools.iter().find(|t| t.station == station).unwrap();
        [&t.insert, &t.holder]
            .iter()
            .map(|s| {
                let pts: Vec<P2> = s
                    .points()
                    .iter()
                    .map(|q| {
                        let p = q + t.tip.coords + r.coords;
                        P2::new(if opposite { -p.x } else { p.x }, p.y)
                    })
                    .collect();
                Polygon::new(&pts).unwrap()
            })
            .collect()
    };
    let at = |lane: &(
        Machine,
        latheguard::interp::Interpretation,
        latheguard::motion::Timeline,
        bool,
    ),
              t: f64| {
        let (_, run, tl, _) = lane;
        let mut pose = (run.moves[0].ref_start(), run.moves[0].station);
        for it in &tl.items {
            let mv = &run.moves[it.index];
            if t < it.t0 {
                break;
            }
            pose = (latheguard::motion::reference_at(mv, it, t - it.t0), mv.station);
            if matches!(mv.kind, MoveKind::ToolChange { .. }) && t < it.t1() {
                return None;
            }
        }
        Some(pose)
    };
    let end = lanes.iter().map(|l| l.2.total).fold(0.0, f64::max);
    let mut t = 0.0;
    while t <= end {
        if let (Some(a), Some(b)) = (at(&lanes[0], t), at(&lanes[1], t)) {
            for x in shapes(&lanes[0].0, a.1, false, a.0) {
                for y in shapes(&lanes[1].0, b.1, true, b.0) {
                    if query::penetration_depth(&x, &y) > depth {
                        return Some(t);
                    }
                }
            }
        }
        t += 0.0002;
    }
    None
}

#[test]
fn a_path_without_spindle_words_turns_with_the_spindle_path_1_commands() {
    // Path 1 starts the spindle and waits; path 2 has no spindle word and turns after the wait:
    // machining, no finding. Path 2 without the wait turns at once, while the spindle is still
    // stopped (path 1 starts it after a 2 s dwell): `spindle_stopped` at its cut (line 12).
    let with_wait = "$1\nG21 G18 G99\nG97 S800 M3\nM100\nG4 X5.\nM30\n$2\nG21 G18 G99\nM100\nT0101\nG0 X46. Z2.\nG1 Z-20. F0.2\nG0 X200. Z150.\nM30\n";
    assert_eq!(errors(with_wait, &twin(), Mode::Step), vec![]);
    let early = "$1\nG21 G18 G99\nG4 X2.\nG97 S800 M3\nG4 X5.\nM30\n$2\nG21 G18 G99\nT0101\nG0 X46. Z2.\nG1 Z-20. F0.2\nG0 X200. Z150.\nM30\n";
    let errs = errors(early, &twin(), Mode::Step);
    // (With it, the feed per revolution has no speed either: a `program` finding at the cut.)
    assert!(errs.iter().any(|e| e.1 == Kind::SpindleStopped), "{errs:?}");
    assert!(
        errs.iter()
            .all(|e| e.0 == 11 && matches!(e.1, Kind::SpindleStopped | Kind::Program)),
        "{errs:?}"
    );
}

/// Under G96 the shared spindle turns at the speed the commanding path's surface speed gives at
/// the commanding path's own tool, not at the other path's: path 1 holds 200 m/min with its tool
/// at radius 50 (636.6 rpm) while path 2 feeds 10 mm in the air at 0.1 mm/rev with its tool at
/// radius 10 — 9.42 s at 636.6 rpm, where its own radius would give 3183 rpm and 1.88 s.
#[test]
fn a_path_under_another_paths_g96_turns_at_the_speed_of_the_commanding_tool() {
    let m = twin();
    let src = "$1\nG21 G18 G99\nG96 S200 M3\nT0101\nG0 X100. Z5.\nG4 X2.\nM30\n$2\nG21 G18 G99\nG4 X1.\nT0101\nG0 X20. Z30.\nG1 Z20. F0.1\nM30\n";
    let out = pipeline::check(src.as_bytes(), &m, &Settings::default());
    assert!(
        out.findings.iter().all(|f| f.severity != Severity::Error),
        "{:?}",
        out.findings
    );
    // Path 2: 1 s of dwell, its rapid (x 230 mm at 333.3 mm/s, z 480 mm at 400 mm/s: 1.2 s),
    // then the feed at 636.6 rpm: 10 / (0.1 · 636.6 / 60) = 9.42 s.
    let rpm = 200_000.0 / (2.0 * std::f64::consts::PI * 50.0);
    let want = 1.0 + 480.0 / 400.0 + 10.0 / (0.1 * rpm / 60.0);
    let t = out.stats.machine_time_s;
    assert!((t - want).abs() < 0.05, "machine time {t:.3} s, worked {want:.3} s");
}

/// The paths share the stock: what path 1 turned away before path 2's rapid is not there for
/// it (no `rapid_into_stock` through material gone), while a rapid made before the cut has
/// ended still meets the material — and the final part holds both paths' cuts.
#[test]
fn a_path_meets_the_stock_another_path_has_already_cut_as_it_is_then() {
    let m = twin();
    let shared = "$1\nG21 G18 G99\nG97 S1000 M3\nT0101\nG0 X40. Z2.\nG1 Z-30. F0.3\nG0 X60.\nG0 X200. Z150.\nM100\nM30\n$2\nG21 G18 G99\nM100\nT0101\nG0 X60. Z-10.\nG0 X44.\nG0 X200. Z150.\nM30\n";
    for mode in [Mode::Step, Mode::Exact] {
        // Path 1 turns Ø40 for Z2 to Z-30 (ending at 7.7 s) and waits at M100; path 2 waits
        // there too, then rapids to Ø44 at Z-10: inside the Ø50 bar, outside what is left.
        assert_eq!(errors(shared, &m, mode), vec![], "{mode:?}");
        // Without the waits the rapid comes at 1.3 s, before the cut: into the bar.
        let early = shared.replace("M100\n", "(NO WAIT)\n");
        let errs = errors(&early, &m, mode);
        assert_eq!(errs.len(), 1, "{mode:?}: {errs:?}");
        assert_eq!((errs[0].0, errs[0].1), (16, Kind::RapidIntoStock), "{mode:?}");
    }
    // The final part is Ø40 from Z2 to Z-30 whichever path cut it: here path 2 turns it after
    // path 1 has done nothing, and the part drawn is path 1's stock with path 2's cut.
    let by_path_2 = "$1\nG21 G18 G99\nG97 S1000 M3\nG4 X1.\nM30\n$2\nG21 G18 G99\nT0101\nG0 X40. Z2.\nG1 Z-30. F0.3\nG0 X60.\nG0 X200. Z150.\nM30\n";
    let out = pipeline::check(by_path_2.as_bytes(), &m, &Settings::default());
    let r_min_at = |z: f64| {
        out.stock
            .iter()
            .flat_map(|o| o.windows(2))
            .filter(|w| (w[0][1] - z) * (w[1][1] - z) <= 0.0 && (w[0][1] - w[1][1]).abs() > 1e-9)
            .map(|w| w[0][0] + (w[1][0] - w[0][0]) * (z - w[0][1]) / (w[1][1] - w[0][1]))
            .fold(f64::INFINITY, f64::min)
    };
    // z -10 in program coordinates is z 68 in the machine frame (program zero at 78).
    let r = r_min_at(68.0);
    assert!((r - 20.0).abs() < 0.05, "the part's radius at Z-10 is {r}");
}

/// `latheguard moves --path N` prints one path of a multi-path program, on its carrier, at its
/// lines of the file; a path the file or the machine lacks is exit 2 with the reason.
#[test]
fn moves_prints_the_path_it_is_asked_for_at_its_lines_of_the_file() {
    let run = |args: &[&str]| {
        let out = crate::common::latheguard(&root(), &[&["moves"], args].concat());
        let code = out.status.code().unwrap();
        (code, crate::common::stdout(&out), crate::common::stderr(&out))
    };
    let file = "programs/twin-turret/centre_drill_handover.nc";
    let (code, out, err) = run(&["-m", "machines/twin-turret.toml", "--path", "2", file]);
    assert_eq!(code, 0, "{err}");
    let lines: Vec<u32> = out
        .lines()
        .filter_map(|l| l.split_whitespace().next()?.parse().ok())
        .collect();
    // Path 2's lines are 13 to 25 of the file; its roughing feed (line 17) runs along X52 (a
    // radius of 26 in the canonical calls), its centre drill (line 23) on the axis.
    assert!(lines.iter().all(|l| (13..=25).contains(l)), "{out}");
    assert!(out.contains("   17 STRAIGHT_FEED(26.0000, 0.0000, -30.0000"), "{out}");
    assert!(out.contains("   23 STRAIGHT_FEED(0.0000, 0.0000, -2.0000"), "{out}");
    // Path 1 by default: its U-drill's feed at line 8, nothing of path 2's.
    let (code, out, _) = run(&["-m", "machines/twin-turret.toml", file]);
    assert_eq!(code, 0);
    assert!(out.contains("    8 STRAIGHT_FEED(0.0000, 0.0000, -25.0000"), "{out}");
    assert!(!out.contains("   17 "), "{out}");
    let (code, _, err) = run(&["-m", "machines/twin-turret.toml", "--path", "3", file]);
    assert_eq!(code, 2);
    assert!(err.contains("no $3 lines"), "{err}");
    let (code, _, err) = run(&["--path", "2", "programs/grooving.nc"]);
    assert_eq!(code, 2);
    assert!(err.contains("the machine has 1 path"), "{err}");
}

/// A contact between two carriers has a picture at each path's finding, drawn from that path:
/// its turret and active tool where they are at first contact, the part that hit and the other
/// carrier's part it met (touching or overlapping there), the other carrier's parts as
/// outlines, the move under way drawn as the machine moves it (the lower turret's dogleg
/// rapid), and the legend names the other carrier's outlines.
#[test]
fn a_contact_between_carriers_has_a_picture_from_each_path() {
    let out = pipeline::check(
        program("crash_drills_meet_at_centre.nc").as_bytes(),
        &twin(),
        &Settings::default(),
    );
    let hits: Vec<_> = out.findings.iter().filter(|f| f.kind == Kind::Collision).collect();
    assert_eq!(hits.len(), 2);
    for f in &hits {
        let s = f
            .snapshot
            .as_ref()
            .unwrap_or_else(|| panic!("no picture at line {}", f.line));
        let poly = |p: &[latheguard::geom::P2]| latheguard::geom::Polygon::new(p).unwrap();
        let (a, b) = (poly(&s.part_a), poly(&s.part_b[0]));
        assert_eq!(
            latheguard::geom::query::distance(&a, &b),
            0.0,
            "line {}: the parts meet",
            f.line
        );
        // The hitting part is this path's holder, drawn as its active tool's holder.
        assert_eq!(s.part_a, s.holder, "line {}", f.line);
        assert!(!s.turret.is_empty() && !s.insert.is_empty());
        assert!(
            s.others.iter().any(|(l, _)| l.starts_with(if f.line == 8 {
                "lower turret"
            } else {
                "turret of path 1"
            })),
            "{:?}",
            s.others.iter().map(|o| &o.0).collect::<Vec<_>>()
        );
        assert!(s.path.len() > 2);
    }
    // The lower turret (line 22) is across the axis from path 1's: its picture has it at x < 0,
    // and its rapid to X0 Z5 bends where Z arrives.
    let lower = hits.iter().find(|f| f.line == 22).unwrap().snapshot.as_ref().unwrap();
    assert!(lower.holder.iter().all(|p| p.x < 0.0));
    assert_eq!(lower.machine_path.len(), 3);
    let upper = hits.iter().find(|f| f.line == 8).unwrap().snapshot.as_ref().unwrap();
    assert!(upper.insert.iter().any(|p| p.x.abs() < 1e-6 || p.x > 0.0));
    // The pictures `--svg` writes say what the dashed outlines are.
    let dir = tempfile::tempdir().unwrap();
    let out = crate::common::latheguard(
        &root(),
        &[
            "check",
            "-q",
            "--svg",
            dir.path().to_str().unwrap(),
            "programs/twin-turret/crash_drills_meet_at_centre.nc",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", crate::common::stderr(&out));
    let svgs: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap())
        .collect();
    assert_eq!(svgs.len(), 2);
    assert!(svgs
        .iter()
        .all(|s| s.contains("other carrier, other stations (working plane)")));
}

/// `setup` of a program on a multi-path machine lists each path's carrier with its own tools
/// (text and JSON): the lower turret's centre drill is T02 of path 2, not path 1's T02.
#[test]
fn setup_lists_the_tools_of_each_paths_carrier() {
    let prog = "programs/twin-turret/crash_drills_meet_at_centre.nc";
    let out = crate::common::latheguard(&root(), &["setup", prog]);
    assert_eq!(out.status.code(), Some(0), "{}", crate::common::stderr(&out));
    let text = crate::common::stdout(&out);
    let (one, two) = text.split_once("  tools of path 2 (lower turret)\n").expect(&text);
    assert!(
        one.contains("  tools of path 1 (turret of path 1)\n    T01 OD rough"),
        "{text}"
    );
    assert!(
        one.contains("T02 Face and chamfer") && !one.contains("Centre drill"),
        "{text}"
    );
    assert!(
        two.starts_with("    T01 OD rough") && two.contains("T02 Centre drill D10  tip [-40, -110]  [machine]"),
        "{text}"
    );
    let j = crate::common::json(&crate::common::latheguard(
        &root(),
        &["setup", "--format", "json", prog],
    ));
    assert_eq!(j["tools"].as_array().unwrap().len(), 4);
    assert_eq!(j["paths"][0]["path"], 2);
    assert_eq!(j["paths"][0]["carrier"], "lower turret");
    assert_eq!(j["paths"][0]["tools"][1]["name"], "Centre drill D10");
    // A one-path machine has no other paths.
    let j = crate::common::json(&crate::common::latheguard(
        &root(),
        &["setup", "--format", "json", "programs/facing.nc"],
    ));
    assert_eq!(j["paths"], serde_json::json!([]));
}
