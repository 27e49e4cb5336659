//! A milling head on a B swivel (issue 15), on the test machine `tests/machines/turn-mill-bhead.toml`:
//! a swivel next to the advanced sub-spindle swings the head's body into its chuck (a crash found
//! through the rotary motion bound), and a B-tilted hole drilled and backed out along its own line
//! is clean — in both modes, with lines and components.

use latheguard::finding::{Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bhead() -> Machine {
    let text = std::fs::read_to_string(root().join("tests/machines/turn-mill-bhead.toml")).unwrap();
    machine::from_toml(&text, "tests/machines/turn-mill-bhead.toml").unwrap()
}

fn program(name: &str) -> String {
    std::fs::read_to_string(root().join("tests/fixtures/bhead").join(name)).unwrap()
}

/// The errors of a program as (line, kind, objects), and whether the 3D path ran.
fn errors(src: &str, mode: Mode) -> (Vec<(u32, Kind, Vec<String>)>, bool) {
    let out = pipeline::check(
        src.as_bytes(),
        &bhead(),
        &Settings {
            mode,
            ..Settings::default()
        },
    );
    let errs = out
        .findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .map(|f| (f.line, f.kind, f.objects.clone()))
        .collect();
    (errs, out.stats.effects.iter().any(|e| e == "kinematic_3d"))
}

fn owned(want: &[(u32, Kind, [&str; 2])]) -> Vec<(u32, Kind, Vec<String>)> {
    want.iter()
        .map(|(l, k, o)| (*l, *k, o.iter().map(|s| s.to_string()).collect()))
        .collect()
}

#[test]
fn a_b_swivel_beside_the_advanced_sub_spindle_swings_the_head_into_its_chuck() {
    let src = program("crash_b_swivel_into_sub_chuck.nc");
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, ran) = errors(&src, mode);
        assert_eq!(
            errs,
            owned(&[(12, Kind::Collision, ["head_body", "sub_chuck"])]),
            "{mode:?}"
        );
        assert!(ran);
    }
}

/// With the sub-spindle parked the same swivel is clean: the crash is the swivel's, not the
/// head's place.
#[test]
fn the_same_swivel_with_the_sub_spindle_parked_is_clean() {
    let src = program("crash_b_swivel_into_sub_chuck.nc").replace("G0 A-500.", "G0 A0.");
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, ran) = errors(&src, mode);
        assert!(errs.is_empty(), "{mode:?}: {errs:?}");
        assert!(ran);
    }
}

/// Swivelling only part of the way (B-30) keeps the body out of the chuck; the full swivel goes
/// deep into it.
#[test]
fn a_partial_swivel_stops_short_of_the_chuck_and_the_full_one_goes_deep() {
    let part = program("crash_b_swivel_into_sub_chuck.nc").replace("G0 B-90.", "G0 B-30.");
    for mode in [Mode::Step, Mode::Exact] {
        assert!(errors(&part, mode).0.is_empty(), "{mode:?}");
    }
    let src = program("crash_b_swivel_into_sub_chuck.nc");
    for mode in [Mode::Step, Mode::Exact] {
        let out = pipeline::check(
            src.as_bytes(),
            &bhead(),
            &Settings {
                mode,
                ..Settings::default()
            },
        );
        let hit = out.findings.iter().find(|f| f.kind == Kind::Collision).unwrap();
        assert!(hit.depth_mm.unwrap() > 1.0, "{hit:?}");
    }
}

#[test]
fn a_b_tilted_hole_drilled_and_backed_out_along_its_line_is_clean() {
    let src = program("b_tilted_drilling.nc");
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, ran) = errors(&src, mode);
        assert!(errs.is_empty(), "{mode:?}: {errs:?}");
        assert!(ran);
    }
}

/// On this machine a rapid is a dogleg (Z at 24 m/min arrives before X at 20 m/min): backing out
/// of the tilted hole at a rapid leaves the hole's line by about 5° and drags the drill through
/// its wall, a crash the milled stock sees (the plunge line of issue 15 let it pass).
#[test]
fn a_dogleg_rapid_out_of_a_tilted_hole_drags_the_drill_through_its_wall() {
    let src = program("b_tilted_drilling.nc").replace("G1 X-14.437 Z79.782 F2000.", "G0 X-14.437 Z79.782");
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, _) = errors(&src, mode);
        assert_eq!(
            errs,
            vec![(
                17,
                Kind::RapidIntoStock,
                vec!["head_drill".to_string(), "stock".to_string()]
            )],
            "{mode:?}"
        );
    }
}

/// The clean hole is a real cut: the same line at a rapid drives the drill into the bar, and
/// backing out sideways (Z first) drags it through the part.
#[test]
fn the_tilted_hole_reaches_the_bar_a_rapid_along_it_is_a_crash() {
    let src = program("b_tilted_drilling.nc");
    let rapid = src.replace("G1 X-42.721 Z65.640 F100.", "G0 X-42.721 Z65.640");
    assert_ne!(rapid, src);
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, _) = errors(&rapid, mode);
        assert_eq!(
            errs,
            owned(&[(16, Kind::RapidIntoStock, ["head_drill", "stock"])]),
            "{mode:?}"
        );
    }
    let sideways = src.replace("G1 X-14.437 Z79.782 F2000. (BACK OUT", "G0 Z79.782 (BACK OUT");
    assert_ne!(sideways, src);
    for mode in [Mode::Step, Mode::Exact] {
        let (errs, _) = errors(&sideways, mode);
        assert_eq!(
            errs,
            owned(&[(17, Kind::RapidIntoStock, ["head_drill", "stock"])]),
            "{mode:?}"
        );
    }
}

/// `--clearance` on the B head: swivelled to B-80 the body passes the advanced sub chuck at
/// about 2 mm: a near miss at the swivel's line with its closest gap, never a collision.
#[test]
fn a_swivel_that_clears_the_sub_chuck_by_little_is_a_near_miss_at_a_clearance() {
    let src = program("crash_b_swivel_into_sub_chuck.nc").replace("G0 B-90.", "G0 B-80.");
    for mode in [Mode::Step, Mode::Exact] {
        let run = |clearance_mm: f64| {
            pipeline::check(
                src.as_bytes(),
                &bhead(),
                &Settings {
                    mode,
                    clearance_mm,
                    ..Settings::default()
                },
            )
            .findings
        };
        let f = run(5.0);
        assert!(f.iter().all(|f| f.severity != Severity::Error), "{mode:?}: {f:#?}");
        let near = f
            .iter()
            .find(|f| f.kind == Kind::NearMiss && f.objects == ["head_body", "sub_chuck"])
            .expect("a near miss");
        assert_eq!((near.line, near.end_line), (12, 13), "{mode:?}");
        assert!(near.message.contains("(closest 1.9"), "{}", near.message);
        // At a clearance below the gap, no near miss with the chuck.
        assert!(
            !run(1.5).iter().any(|f| f.objects == ["head_body", "sub_chuck"]),
            "{mode:?}"
        );
    }
}
