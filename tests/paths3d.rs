//! Two tool carriers in 3D (`machines/mill-turn-head.toml`, docs/paths.md "Two carriers in 3D"):
//! a milling head on B (path 1) and a lower turret (path 2) whose axes drive one kinematic tree,
//! each path checked on the parts its own axes carry, the carriers against each other over the
//! machine's one clock — with answers worked by hand from the machine file, and the search
//! against a dense-sampling oracle.

use latheguard::collide3;
use latheguard::finding::{Kind, Severity};
use latheguard::kin::Poser;
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};

use crate::common::root;

fn head_machine() -> Machine {
    crate::common::repo_machine("machines/mill-turn-head.toml")
}

fn program(name: &str) -> String {
    std::fs::read_to_string(root().join("programs/mill-turn-head").join(name)).unwrap()
}

/// The errors of a program as (line, kind, objects, time).
fn errors(src: &str, machine: &Machine, mode: Mode) -> Vec<(u32, Kind, Vec<String>, f64)> {
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
        .map(|f| (f.line, f.kind, f.objects.clone(), f.time_s.unwrap_or(-1.0)))
        .collect()
}

#[test]
fn the_head_facing_to_the_centre_meets_the_lower_centre_drill_at_both_lines() {
    let m = head_machine();
    for mode in [Mode::Step, Mode::Exact] {
        let errs = errors(&program("crash_facing_meets_centre_drill.nc"), &m, mode);
        // Path 1 rapids to X54 Z0 (T01's reference point from x 300, z 600 to 117, 80: z the
        // longer at 500 mm/s, 1.04 s), then faces at 0.1 mm/rev and 1200 rpm (2 mm/s). Path 2
        // indexes to T02 (0.4 s), rapids to X0 Z5 (z the longer, 407 mm at 400 mm/s: 1.02 s)
        // and feeds its Ø10 drill toward Z-20 at 1 mm/s from 1.42 s. The insert's lowest point
        // (its tip) reaches the drill's surface 5 mm from the axis when the tip has faced 22 mm:
        // at 1.04 + 11 = 12.04 s, the drill's point then at Z-5.6, so the insert (Z0 to Z14 above
        // its tip) is beside the drill's flutes.
        assert_eq!(errs.len(), 2, "{mode:?}: {errs:?}");
        assert_eq!(
            (errs[0].0, errs[0].1, errs[0].2.clone()),
            (
                8,
                Kind::Collision,
                vec!["path1:t1_insert".to_string(), "path2:l2_drill".to_string()]
            )
        );
        assert_eq!(
            (errs[1].0, errs[1].1, errs[1].2.clone()),
            (
                16,
                Kind::Collision,
                vec!["path2:l2_drill".to_string(), "path1:t1_insert".to_string()]
            )
        );
        for e in &errs {
            assert!((12.03..12.06).contains(&e.3), "{mode:?}: {}", e.3);
        }
    }
}

#[test]
fn with_the_wait_both_carriers_cut_the_part_at_once_without_touching() {
    let m = head_machine();
    for mode in [Mode::Step, Mode::Exact] {
        // The head faces and turns Ø46 while the lower turret roughs Ø52 on the other side of
        // the bar (both cutting from 1.0 s on); the lower drill comes to the centre only after
        // the M100 both paths meet at, once the head has gone home; the head then swivels on B.
        let out = pipeline::check(
            program("face_then_centre_drill.nc").as_bytes(),
            &m,
            &Settings {
                mode,
                ..Settings::default()
            },
        );
        assert!(
            out.findings.iter().all(|f| f.severity != Severity::Error),
            "{mode:?}: {:?}",
            out.findings
        );
        assert!(out.stats.effects.iter().any(|e| e == "paths"));
    }
}

#[test]
fn the_sub_spindle_coming_forward_hits_the_head_standing_in_its_way() {
    let m = head_machine();
    for mode in [Mode::Step, Mode::Exact] {
        let errs = errors(&program("crash_sub_spindle_into_head.nc"), &m, mode);
        // The head's T01 stands with its tip at X100 Z250 (radius 50, z 328): its shank from
        // radius 55 up, z 332 to 357. Path 2 dwells 2 s and rapids its sub-spindle slide (B) at
        // 333.3 mm/s toward the main spindle: the chuck's step at radius 55 to 80, 15 mm behind
        // its jaw faces (z 715 + B), reaches the shank's far side (z 357) at B = -358, at
        // 2 + 358 / 333.3 = 3.074 s.
        assert_eq!(errs.len(), 2, "{mode:?}: {errs:?}");
        assert_eq!((errs[0].0, errs[0].2[1].as_str()), (7, "path2:sub_chuck"));
        assert_eq!((errs[1].0, errs[1].2[0].as_str()), (13, "path2:sub_chuck"));
        for e in &errs {
            assert_eq!(e.1, Kind::Collision);
            assert!((3.070..3.078).contains(&e.3), "{mode:?}: {}", e.3);
        }
    }
}

#[test]
fn each_path_checks_the_parts_its_own_axes_carry_and_the_chucks() {
    let m = head_machine();
    let k = m.kinematics.as_deref().unwrap();
    let id = |k: &latheguard::kin::Kinematics, n: &str| k.component(n);
    // The main spindle's C turns its chuck about itself: no path's carrier, every path sees it.
    let masks = k.path_masks();
    assert_eq!(masks[id(k, "main_chuck").unwrap()], 0);
    assert_eq!(masks[id(k, "t1_insert").unwrap()], 1 << 1);
    assert_eq!(masks[id(k, "l2_drill").unwrap()], 1 << 2);
    assert_eq!(masks[id(k, "sub_chuck").unwrap()], 1 << 2);
    let p1 = m.for_path(1).unwrap().kinematics.clone().unwrap();
    let p2 = m.for_path(2).unwrap().kinematics.clone().unwrap();
    for n in ["head", "t1_insert", "main_chuck", "headstock"] {
        assert!(id(&p1, n).is_some(), "{n} on path 1");
    }
    for n in ["lower_turret", "l2_drill", "sub_chuck"] {
        assert!(id(&p1, n).is_none(), "{n} not on path 1");
    }
    for n in ["lower_turret", "l2_drill", "sub_chuck", "main_chuck"] {
        assert!(id(&p2, n).is_some(), "{n} on path 2");
    }
    assert!(id(&p2, "head").is_none());
    // Each path's letters drive its own axes.
    assert_eq!(p2.axes[p2.axis_by_letter('X').unwrap()].name, "x2");
    assert_eq!(p2.axes[p2.axis_by_letter('B').unwrap()].name, "sub_z");
    assert_eq!(p1.axes[p1.axis_by_letter('B').unwrap()].name, "b_head");
    assert!(p2.axis_by_letter('C').is_none());
    // The pairs between carriers are the cross check's; no pair of a path's own check is.
    let cross = k.cross_pairs();
    let has = |a: &str, b: &str| {
        let (a, b) = (id(k, a).unwrap(), id(k, b).unwrap());
        cross.contains(&(a.min(b), a.max(b)))
    };
    assert!(has("head", "lower_turret"));
    assert!(has("t1_holder", "sub_chuck"));
    assert!(has("t1_insert", "l2_drill"));
    assert!(!has("lower_turret", "main_chuck") && !has("head", "main_chuck"));
    let own: usize = [&p1, &p2].iter().map(|t| t.never_touch.len()).sum();
    assert_eq!(own + cross.len(), k.never_touch.len());
}

#[test]
fn a_one_path_program_on_the_two_carrier_machine_keeps_the_lower_turret_at_home() {
    let m = head_machine();
    let src = "G21 G18 G99\nG97 S1000 M3\nT0101\nG0 X54. Z2.\nG1 X46. F0.2\nG1 Z-30.\nG0 X200. Z150.\nM30\n";
    assert_eq!(errors(src, &m, Mode::Step), vec![]);
    // Without the head's Y, X and Z a turning program crashes the head's tool as on any lathe.
    let crash = "G21 G18 G99\nG97 S1000 M3\nT0101\nG0 X30. Z2.\nG0 Z-20.\nM30\n";
    assert!(errors(crash, &m, Mode::Step).iter().any(|e| e.0 == 5));
}

#[test]
fn axes_of_several_paths_are_checked_with_their_keys() {
    let text = std::fs::read_to_string(root().join("machines/mill-turn-head.toml")).unwrap();
    let err = |from: &str, to: &str| {
        assert!(text.contains(from), "{from}");
        let t = text.replacen(from, to, 1);
        match machine::from_toml(&t, "m.toml") {
            Ok(_) => panic!("{to} was accepted"),
            Err(e) => e.to_string(),
        }
    };
    // A path the machine does not have.
    let e = err("rapid = 24000\npath = 2\n", "rapid = 24000\npath = 3\n");
    assert!(
        e.contains("kinematics.axes[6].path") && e.contains("paths 1 to 2"),
        "{e}"
    );
    // Path 2's X agrees with path 2's 2D axes, and says which.
    let e = err(
        "travel = [-10, 300]\nrapid = 20000\npath = 2",
        "travel = [-10, 310]\nrapid = 20000\npath = 2",
    );
    assert!(e.contains("paths[0].axes.x"), "{e}");
    // A letter drives one axis of a path; the same letter on two paths is fine (above).
    let e = err("letter = \"A\"\ntype = \"rotary\"", "letter = \"B\"\ntype = \"rotary\"");
    assert!(e.contains("a letter drives one axis of a path"), "{e}");
    // A station of the lower turret's is one of its 8.
    let e = err(
        "role = \"cutter\"\nstation = 2\n\n# The sub",
        "role = \"cutter\"\nstation = 9\n\n# The sub",
    );
    assert!(e.contains("station 9") && e.contains("path 2"), "{e}");
    // The name of path 1's carrier is not blank.
    let e = err("first = \"milling head\"", "first = \" \"");
    assert!(e.contains("sync.first"), "{e}");
    // On a one-path machine no axis has a path past 1.
    let one = std::fs::read_to_string(root().join("machines/turn-mill.toml")).unwrap();
    let t = one.replacen("rapid = 10000\n", "rapid = 10000\npath = 2\n", 1);
    let e = machine::from_toml(&t, "machines/turn-mill.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("one path"), "{e}");
}

/// The 3D search between carriers never misses a contact that dense sampling sees: the head's
/// facing cut and the lower turret's centre drill timed against each other in many ways (the
/// facing depth, the feeds, a dwell before the drill), each checked by the search and by sampling
/// the same poses every millisecond (the fastest part moves 0.5 mm between samples, so the
/// sampling looks for overlaps deeper than that).
#[test]
fn the_3d_carriers_search_finds_every_overlap_dense_sampling_finds() {
    let m = head_machine();
    let settings = Settings::default();
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    const CASES: usize = 12;
    let mut contacts = 0;
    for case in 0..CASES {
        let x_end = 12.0 - next() * 17.0; // the facing ends from X12 to X-5
        let f1 = 0.2 + next() * 0.4; // mm/rev, 1200 rpm
        let f2 = 0.05 + next() * 0.2;
        let dwell = next() * 6.0;
        let z_drill = -5.0 - next() * 20.0;
        let src = format!(
            "$1\nG21 G18 G40 G99\nG97 S1200 M3\nT0101\nG0 X54. Z0.\nG1 X{x_end:.3} F{f1:.3}\nG0 Z2.\nG0 X200. Z150.\nM30\n$2\nG21 G18 G40 G99\nT0202\nG4 X{dwell:.3}\nG0 X0. Z5.\nG1 Z{z_drill:.3} F{f2:.3}\nG0 Z5.\nG0 X200. Z150.\nM30\n"
        );
        let out = pipeline::check(src.as_bytes(), &m, &settings);
        let first = out
            .findings
            .iter()
            .filter(|f| f.kind == Kind::Collision && f.objects.first().is_some_and(|o| o.starts_with("path")))
            .filter_map(|f| f.time_s)
            .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.min(t))));
        let sampled = latheguard::paths::with_carriers3(src.as_bytes(), &m, &settings, |c| {
            let k = c.tree();
            let mut poser = Poser::new(k);
            let mut vals = Vec::new();
            let mut t = 0.0;
            let end = c.end();
            while t <= end {
                c.values_at(t, &mut vals);
                poser.pose(k, &vals);
                for &(a, b) in c.pairs() {
                    if !c.present(a, t) || !c.present(b, t) {
                        continue;
                    }
                    let (sa, sb) = (c.shape(a).unwrap(), c.shape(b).unwrap());
                    if collide3::overlap(sa, poser.world(a), sb, poser.world(b), 0.5).is_some() {
                        return Some(t);
                    }
                }
                t += 0.001;
            }
            None
        })
        .unwrap();
        if let Some(t) = sampled {
            assert!(
                first.is_some_and(|f| f <= t + 1e-3),
                "case {case}: sampling finds an overlap at {t:.4} s, the search at {first:?}:\n{src}"
            );
        }
        contacts += usize::from(first.is_some());
    }
    // The cases reach both answers.
    assert!(
        contacts > 2 && contacts < CASES - 2,
        "{contacts} of {CASES} cases in contact"
    );
}

#[test]
fn a_contact_between_the_carriers_has_its_3d_picture_with_both_parts_marked() {
    use latheguard::report::scene3::Role3;
    let m = head_machine();
    let settings = Settings {
        snapshots: true,
        ..Settings::default()
    };
    let out = pipeline::check(program("crash_facing_meets_centre_drill.nc").as_bytes(), &m, &settings);
    let errs: Vec<_> = out.findings.iter().filter(|f| f.severity == Severity::Error).collect();
    assert_eq!(errs.len(), 2);
    for f in errs {
        let s = f.snapshot3.as_ref().expect("a picture");
        assert_eq!((s.line, s.title.as_str()), (f.line, f.message.as_str()));
        let a = s.part(Role3::CollidingA).unwrap();
        let b = s.part(Role3::CollidingB).unwrap();
        let mut names = [a.name.as_str(), b.name.as_str()];
        names.sort();
        assert_eq!(names, ["T01 insert", "T02 drill"]);
        // The contact is where the insert's tip meets the drill's flutes: 5 mm from the axis,
        // at the face (z 78).
        let c = s.contact.unwrap();
        assert!((c.x - 5.0).abs() < 0.2 && (c.z - 78.0).abs() < 0.2, "{c:?}");
        // The head's housing and the lower turret are drawn too; the head's other tool is in
        // its magazine.
        assert!(s.parts.iter().any(|p| p.name == "milling head"));
        let t02: Vec<&str> = s
            .parts
            .iter()
            .map(|p| p.name.as_str())
            .filter(|n| n.starts_with("T02"))
            .collect();
        assert_eq!(t02, ["T02 holder", "T02 drill"]);
    }
}

/// A job's milling tool goes to path 1's station of its number: the lower turret's station of
/// the same number keeps its own tool.
#[test]
fn a_job_milling_tool_replaces_path_1s_station_not_the_other_carriers() {
    let m = head_machine();
    let job = "[[tools]]\nstation = 2\nname = \"Radial live drill D8\"\ntip = [-130.0, 0.0]\nlive = \"radial\"\nmill = { type = \"drill\", diameter = 8, flute_length = 40, stick_out = 50, holder = { diameter = 35, length = 25 } }\n";
    let mut no_files = |_: &str, _: &str| -> Result<(String, String), String> { Err("no files".to_string()) };
    let layer = latheguard::job::parse(job, "j.toml", "", "job", &mut no_files).unwrap();
    let jm = latheguard::job::apply(&m, &latheguard::job::EffectiveJob::merge([&layer])).unwrap();
    let k = jm.kinematics.as_deref().unwrap();
    // The head's end mill is gone (its station's cutter replaced); the lower turret's T02 drill
    // and the head's holder stay.
    assert!(k.component("t2_mill").is_none());
    assert!(k.component("l2_drill").is_some());
    assert!(k.component("t2_holder").is_some());
    let masks = k.path_masks();
    let new: Vec<_> = (0..k.components.len())
        .filter(|&c| k.components[c].station == Some(2) && masks[c] == 1 << 1)
        .map(|c| k.components[c].name.clone())
        .collect();
    assert!(new.iter().any(|n| n != "t2_holder"), "{new:?}");
}
