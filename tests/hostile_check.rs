//! Hostile input to the checker (issue 10): each of these once ran for hours or never ended.
//! The rule they hold: the work of a check is bounded by its input and settings — a move's
//! samples, probes and chords are capped, and a cap that would leave part of a move unchecked
//! says so with a finding.

use latheguard::finding::Kind;
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};

fn check(src: &str, settings: Settings) -> Vec<(u32, Kind, Vec<String>)> {
    pipeline::check(src.as_bytes(), &Machine::builtin(), &settings)
        .findings
        .into_iter()
        .map(|f| (f.line, f.kind, f.objects))
        .collect()
}

fn both_modes(src: &str) -> [Vec<(u32, Kind, Vec<String>)>; 2] {
    let step = Settings::default();
    let exact = Settings {
        mode: Mode::Exact,
        ..step
    };
    [check(src, step), check(src, exact)]
}

#[test]
fn a_feed_of_f0_00001_riding_the_bar_finishes_in_step_mode() {
    // 240,000 s of machine time with the holder touching the bar all along: 2.4e8 samples.
    let src = "G21 G18 G40 G97 G99\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X40. F0.2\nG1 Z-30. F0.00001\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
}

#[test]
fn a_feed_of_f0_00001_while_the_holder_is_buried_finishes() {
    // The holder ploughs through the bar for 300 mm of crawl: one long contact.
    let src = "G21 G18 G40 G97 G99\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X20. F0.2\nG1 Z-30. F0.00001\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
    assert!(
        step.iter()
            .any(|f| f.1 == Kind::Collision && f.2 == ["T01 holder", "stock"]),
        "{step:?}"
    );
}

#[test]
fn one_cutting_move_of_1e11_mm_finishes_in_both_modes() {
    let src = "G21 G18 G40 G97 G98\nT0101\nG97 S500 M3\nG0 X40. Z5.\nG1 Z-100000000000. F1000.\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
    assert!(step.iter().any(|f| f.1 == Kind::Collision), "into the chuck: {step:?}");
}

#[test]
fn a_full_circle_of_radius_1e9_through_the_bar_finishes_in_both_modes() {
    let src = "G21 G18 G40 G97 G98\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X46. F100.\nG2 X46. Z5. I-1000000000. K0 F1000.\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
}

#[test]
fn a_timestep_of_1e_9_ms_on_a_shipped_example_finishes() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/od_turning.nc")).unwrap();
    let tiny = Settings {
        dt_ms: 1e-9,
        ..Settings::default()
    };
    let exact = Settings {
        mode: Mode::Exact,
        ..Settings::default()
    };
    assert_eq!(check(&src, tiny), check(&src, exact));
}

#[test]
fn a_wide_clearance_at_a_fine_tolerance_finishes() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/facing.nc")).unwrap();
    let s = Settings {
        mode: Mode::Exact,
        clearance_mm: 100.0,
        tolerance_mm: 0.001,
        ..Settings::default()
    };
    let found = check(&src, s);
    assert!(found.iter().all(|f| f.1 == Kind::NearMiss), "{found:?}");
}

#[test]
fn a_program_that_uses_up_its_work_budget_says_where_the_check_stopped() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/od_turning.nc")).unwrap();
    let s = Settings {
        work_budget: 10,
        ..Settings::default()
    };
    let out = pipeline::check(src.as_bytes(), &Machine::builtin(), &s);
    let stop: Vec<_> = out
        .findings
        .iter()
        .filter(|f| f.message.contains("work budget"))
        .collect();
    assert_eq!(stop.len(), 1, "{:?}", out.findings);
    assert_eq!(stop[0].kind, Kind::Program);
    assert!(out.stats.pair_tests < 1_000, "{}", out.stats.pair_tests);
}
