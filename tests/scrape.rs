//! The shoulder scrape (`rapid_scrape`, docs/findings/rapid_scrape.md) against the geometry of
//! the wedge: a tool whose leading edge leans `δ` past square, turning 2 mm deep up to a
//! shoulder and rapiding straight out, leaves a wedge no thicker than `2·sin δ`; it is a scrape
//! for every lean up to 20° and a crash (`rapid_into_stock`) beyond, in both modes.

use latheguard::finding::{Kind, Severity};
use latheguard::machine::{self, BUILTIN_TOML};
use latheguard::pipeline::{self, Mode, Settings};

/// The built-in machine with T01's leading edge leaning `lean` degrees.
fn machine_with_lean(lean: f64) -> latheguard::machine::Machine {
    let rise = 12.0 * lean.to_radians().tan();
    let text = BUILTIN_TOML.replace(
        "insert = [[0, 0], [12, 2], [14, 14], [2, 12]]",
        &format!(
            "insert = [[0, 0], [12, {rise}], [14, {}], [2, 12]]",
            (rise + 2.0).max(14.0)
        ),
    );
    assert_ne!(text, BUILTIN_TOML, "the built-in T01 insert changed: update this test");
    machine::from_toml(&text, "lean.toml").unwrap()
}

const RETRACT: &str = "G21 G18 G99 G97 S800 M3\nT0101\nG0 X52. Z2.\nG0 X46.\nG1 Z-30. F0.2\nG0 X52.\nG0 Z2.\nM30\n";

#[test]
fn a_straight_retract_scrapes_up_to_a_20_degree_lean_and_crashes_past_it() {
    for lean in [3.0, 5.0, 9.5, 15.0, 19.0, 24.0, 35.0] {
        let m = machine_with_lean(lean);
        for mode in [Mode::Step, Mode::Exact] {
            let s = Settings {
                mode,
                ..Settings::default()
            };
            let out = pipeline::check(RETRACT.as_bytes(), &m, &s);
            let f: Vec<_> = out.findings.iter().filter(|f| f.line == 6).collect();
            assert_eq!(f.len(), 1, "lean {lean}° {mode:?}: {:#?}", out.findings);
            let f = f[0];
            let wedge = 2.0 * lean.to_radians().sin();
            if lean <= 20.0 {
                assert_eq!(
                    (f.kind, f.severity),
                    (Kind::RapidScrape, Severity::Warning),
                    "lean {lean}° {mode:?}"
                );
                let d = f.depth_mm.unwrap();
                assert!(
                    d > 0.0 && d <= wedge + 0.02,
                    "lean {lean}° {mode:?}: {d} mm, the wedge is {wedge} mm"
                );
            } else {
                assert_eq!(
                    (f.kind, f.severity),
                    (Kind::RapidIntoStock, Severity::Error),
                    "lean {lean}° {mode:?}"
                );
            }
        }
    }
}

#[test]
fn a_wedge_over_a_millimetre_thick_stays_rapid_into_stock() {
    // The built-in T01 (9.5°) 8 mm deep: the wedge reaches 8·sin 9.5° = 1.3 mm, past the 1 mm a
    // scrape may be.
    let prog = "G21 G18 G99 G97 S800 M3\nT0101\nG0 X52. Z2.\nG0 X34.\nG1 Z-30. F0.2\nG0 X52.\nM30\n";
    let m = latheguard::machine::Machine::builtin();
    for mode in [Mode::Step, Mode::Exact] {
        let out = pipeline::check(
            prog.as_bytes(),
            &m,
            &Settings {
                mode,
                ..Settings::default()
            },
        );
        let kinds: Vec<_> = out.findings.iter().map(|f| (f.line, f.kind, f.severity)).collect();
        assert_eq!(kinds, vec![(6, Kind::RapidIntoStock, Severity::Error)], "{mode:?}");
    }
    // 4 mm deep (0.66 mm of wedge) is a scrape.
    let prog = prog.replace("X34.", "X42.");
    let out = pipeline::check(prog.as_bytes(), &m, &Settings::default());
    assert_eq!(out.findings.len(), 1);
    assert_eq!(out.findings[0].kind, Kind::RapidScrape);
}

#[test]
fn a_scrape_is_a_warning_that_passes_the_gate_and_ignore_removes_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("retract.nc"), RETRACT).unwrap();
    let run = |args: &[&str]| crate::common::latheguard(dir.path(), args);
    let out = run(&["check", "retract.nc"]);
    assert_eq!(out.status.code(), Some(0), "{}", crate::common::stdout(&out));
    assert!(crate::common::stdout(&out).contains("warning[rapid_scrape]"));
    let out = run(&["check", "--ignore", "LG06", "retract.nc"]);
    assert_eq!(out.status.code(), Some(0));
    assert!(
        crate::common::stdout(&out).contains("1 clean"),
        "{}",
        crate::common::stdout(&out)
    );
}
