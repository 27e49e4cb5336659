//! Property tests of exact mode against step mode on random moves near a stepped chuck jaw.

use latheguard::finding::{Finding, Kind};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use proptest::prelude::*;

fn jaw_machine() -> Machine {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/machines/jaw-test.toml");
    machine::from_toml(&std::fs::read_to_string(path).unwrap(), path).unwrap()
}

fn crashes(src: &str, m: &Machine, mode: Mode, dt_ms: f64) -> Vec<Finding> {
    let s = Settings {
        mode,
        dt_ms,
        ..Settings::default()
    };
    pipeline::check(src.as_bytes(), m, &s)
        .findings
        .into_iter()
        .filter(|f| f.kind == Kind::Collision)
        .collect()
}

/// A program of feed moves through random points near the jaw (radius mode, mm/min).
fn program(points: &[(f64, f64)], feed: f64) -> String {
    let mut s = String::from("G21 G18 G98 G97 S500 M3\nG0 X100 Z30\n");
    s += &format!("G0 X{:.4} Z30\n", points[0].0);
    s += &format!("G1 Z{:.4} F{feed:.1}\n", points[0].1);
    for p in &points[1..] {
        s += &format!("G1 X{:.4} Z{:.4}\n", p.0, p.1);
    }
    s += "G0 X100\nG0 Z30\nM30\n";
    s
}

fn point() -> impl Strategy<Value = (f64, f64)> {
    (15.0..70.0f64, -25.0..10.0f64)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn exact_finds_every_collision_step_mode_finds(pts in prop::collection::vec(point(), 2..5), feed in 200.0..6000.0f64, dt in prop_oneof![Just(5.0), Just(1.0), Just(0.2)]) {
        let m = jaw_machine();
        let src = program(&pts, feed);
        let exact = crashes(&src, &m, Mode::Exact, 1.0);
        for f in crashes(&src, &m, Mode::Step, dt) {
            prop_assert!(
                exact.iter().any(|e| e.objects == f.objects && e.line <= f.end_line && f.line <= e.end_line),
                "step (dt {dt} ms) found {:?} at line {} that exact mode did not: {:?}\n{src}", f.objects, f.line, exact
            );
        }
    }

    #[test]
    fn fine_step_mode_finds_every_exact_collision_deeper_than_one_step(pts in prop::collection::vec(point(), 2..4), feed in 200.0..3000.0f64) {
        let m = jaw_machine();
        let src = program(&pts, feed);
        let dt = 0.01;
        let travel = feed / 60.0 * dt / 1000.0;
        let step = crashes(&src, &m, Mode::Step, dt);
        for e in crashes(&src, &m, Mode::Exact, 1.0) {
            if e.depth_mm.unwrap_or(0.0) <= travel {
                continue;
            }
            prop_assert!(
                step.iter().any(|f| e.objects == f.objects && e.line <= f.end_line && f.line <= e.end_line),
                "exact found {:?} at line {} (depth {:?}) that step mode at {dt} ms missed\n{src}", e.objects, e.line, e.depth_mm
            );
        }
    }
}
