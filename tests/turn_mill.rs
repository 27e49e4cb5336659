//! The turn-mill examples (issue 15) on `machines/turn-mill.toml`, in both modes: each crash at
//! its line between the components it names, the clean program clean, and plain turning on the
//! turn-mill machine exactly what it is on the same machine without its kinematic tree.

use latheguard::finding::{Kind, Severity};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The turn-mill machine with its STL files read beside it.
fn turn_mill() -> Machine {
    let path = root().join("machines/turn-mill.toml");
    let dir = path.parent().unwrap().to_path_buf();
    let text = std::fs::read_to_string(&path).unwrap();
    machine::from_toml_with(&text, "machines/turn-mill.toml", &move |name: &str| {
        std::fs::read(dir.join(name)).map_err(|e| e.to_string())
    })
    .unwrap()
}

/// The errors of a program as (line, kind, objects), in one mode.
fn errors(rel: &str, m: &Machine, mode: Mode) -> Vec<(u32, Kind, Vec<String>)> {
    let src = std::fs::read(root().join(rel)).unwrap();
    let settings = Settings {
        mode,
        ..Settings::default()
    };
    let out = pipeline::check(&src, m, &settings);
    out.findings
        .iter()
        .filter(|f| f.severity == Severity::Error)
        .map(|f| (f.line, f.kind, f.objects.clone()))
        .collect()
}

fn both_modes(rel: &str, want: &[(u32, Kind, [&str; 2])]) {
    let m = turn_mill();
    for mode in [Mode::Step, Mode::Exact] {
        let got = errors(rel, &m, mode);
        let want: Vec<(u32, Kind, Vec<String>)> = want
            .iter()
            .map(|(l, k, o)| (*l, *k, o.iter().map(|s| s.to_string()).collect()))
            .collect();
        assert_eq!(got, want, "{rel} in {mode:?} mode");
    }
}

#[test]
fn cross_drilling_with_c_indexing_is_clean_and_runs_the_3d_path() {
    let m = turn_mill();
    let src = std::fs::read(root().join("programs/turn-mill/cross_drill.nc")).unwrap();
    for mode in [Mode::Step, Mode::Exact] {
        let out = pipeline::check(
            &src,
            &m,
            &Settings {
                mode,
                ..Settings::default()
            },
        );
        let errs: Vec<_> = out.findings.iter().filter(|f| f.severity == Severity::Error).collect();
        assert!(errs.is_empty(), "{mode:?}: {errs:#?}");
        assert!(
            out.stats.effects.iter().any(|e| e == "kinematic_3d"),
            "{:?}",
            out.stats.effects
        );
    }
}

#[test]
fn a_c_index_with_the_radial_drill_in_its_hole_is_a_rapid_into_the_stock() {
    both_modes(
        "programs/turn-mill/crash_c_index_drill_in_hole.nc",
        &[(23, Kind::RapidIntoStock, ["t8_drill", "stock"])],
    );
}

#[test]
fn a_live_drill_fed_past_the_bar_hits_the_jaws() {
    both_modes(
        "programs/turn-mill/crash_live_drill_into_jaws.nc",
        &[(13, Kind::Collision, ["t7_drill", "main_chuck"])],
    );
}

#[test]
fn a_y_move_beside_the_advanced_sub_spindle_hits_its_chuck() {
    both_modes(
        "programs/turn-mill/crash_y_move_into_sub_chuck.nc",
        &[(13, Kind::Collision, ["t8_drill", "sub_chuck"])],
    );
}

/// Turning never leaves the working plane: the turn-mill machine gives exactly the findings and
/// stats of the same machine without its tree, and no 3D effect.
#[test]
fn plain_turning_on_the_turn_mill_machine_is_the_2d_check_unchanged() {
    let tm = turn_mill();
    let flat = Machine {
        kinematics: None,
        ..tm.clone()
    };
    for p in [
        "programs/od_turning.nc",
        "programs/facing.nc",
        "programs/crash_rapid_into_bar.nc",
    ] {
        let src = std::fs::read(Path::new(&root()).join(p)).unwrap();
        for mode in [Mode::Step, Mode::Exact] {
            let s = Settings {
                mode,
                ..Settings::default()
            };
            let a = pipeline::check(&src, &tm, &s);
            let b = pipeline::check(&src, &flat, &s);
            assert_eq!(format!("{:?}", a.findings), format!("{:?}", b.findings), "{p} {mode:?}");
            assert_eq!(a.stats.effects, b.stats.effects, "{p} {mode:?}");
            assert_eq!(a.stats.pair_tests, b.stats.pair_tests, "{p} {mode:?}");
            assert!(!a.stats.effects.iter().any(|e| e == "kinematic_3d"));
        }
    }
}
