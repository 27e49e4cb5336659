//! Nose-radius compensation on random monotone OD profiles (the diameter grows toward the chuck,
//! so every corner turns less than 90°): the nose centre never comes nearer the programmed profile
//! than the nose radius — it never cuts into the part — and it touches every segment of the
//! profile — the offset is tangent to it —, in both dialects (rs274ngc's corner arcs, Fanuc's
//! intersection vectors), and the control raises no error on such a profile. (Within the corner
//! tolerance both controls use: see [`slack`].)

use latheguard::finding::Severity;
use latheguard::geom::P2;
use latheguard::interp::MoveKind;
use latheguard::machine::Machine;
use latheguard::pipeline;
use proptest::prelude::*;
use std::path::PathBuf;

/// The nose radius of the comp test machines' tools.
const R: f64 = 0.8;

/// How far the nose may dip under the radius: both controls take a corner that turns less than
/// 0.05 rad (rs274ngc's corner tolerance) as straight, so at such a corner the nose keeps the
/// first segment's offset and comes within `R·cos(0.05)` of the second.
fn slack() -> f64 {
    R * (1.0 - 0.05f64.cos()) + 1e-9
}

fn machine(name: &str) -> Machine {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/machines/{name}.toml"));
    latheguard::machine::from_toml(&std::fs::read_to_string(&path).unwrap(), &path.display().to_string()).unwrap()
}

/// Distance from `p` to the segment `a`–`b`.
fn dist_seg(p: P2, a: P2, b: P2) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// The program: a rapid near the start, G42 with a start-up line onto the first point, the
/// profile, G40 away. Returns the text and the line of the first profile block (1-based).
fn program(fanuc: bool, pts: &[P2]) -> (String, u32) {
    let mut s = String::new();
    if fanuc {
        s += "G99 G97 S500 M3\nF0.2\nT0101\n";
    } else {
        s += "G18 G7 G95 S500 M3\nF0.2\nT1 M6\n";
    }
    let first = pts[0];
    s += &format!("G0 X{:.4} Z5\n", 2.0 * (first.x + 5.0));
    s += &format!("G42 G1 X{:.4} Z{:.4}\n", 2.0 * first.x, first.y);
    for p in &pts[1..] {
        s += &format!("X{:.4} Z{:.4}\n", 2.0 * p.x, p.y);
    }
    let last = pts[pts.len() - 1];
    s += &format!("G40 G0 X{:.4} Z{:.4}\n", 2.0 * (last.x + 10.0), last.y);
    s += if fanuc { "M30\n" } else { "M2\n" };
    (s, 6)
}

/// Random monotone profiles: from radius 10 at Z0, 1–7 segments each 2–10 mm toward the chuck
/// and 0–8 mm outward (points rounded to the 4 decimals the program prints).
fn profile() -> impl Strategy<Value = Vec<P2>> {
    prop::collection::vec((2.0f64..10.0, 0.0f64..8.0), 1..8).prop_map(|steps| {
        let mut pts = vec![P2::new(10.0, 0.0)];
        let round = |v: f64| (v * 1e4).round() / 1e4;
        for (dz, dx) in steps {
            let p = pts[pts.len() - 1];
            pts.push(P2::new(round(p.x + dx / 2.0), round(p.y - dz)));
        }
        pts
    })
}

fn check(fanuc: bool, pts: &[P2]) -> Result<(), TestCaseError> {
    let m = machine(if fanuc { "comp-fanuc-rear" } else { "comp-linuxcnc" });
    let (text, first_line) = program(fanuc, pts);
    let (_, run) = pipeline::interpret(text.as_bytes(), &m);
    let errors: Vec<_> = run.findings.iter().filter(|f| f.severity == Severity::Error).collect();
    prop_assert!(errors.is_empty(), "{errors:?}\n{text}");
    let last_line = first_line + pts.len() as u32 - 2;
    // The nose centre (tip direction 0) from the end of the start-up to the end of the profile.
    let mut samples = Vec::new();
    for mv in &run.moves {
        if mv.line == first_line - 1 {
            samples.push(mv.end);
        } else if (first_line..=last_line).contains(&mv.line) {
            let cut = matches!(mv.kind, MoveKind::Line | MoveKind::Arc { .. });
            prop_assert!(cut, "a rapid in the profile");
            for k in 0..=40 {
                samples.push(mv.point_at(k as f64 / 40.0));
            }
        }
    }
    prop_assert!(samples.len() > 1, "no compensated moves\n{text}");
    for s in &samples {
        let d = pts
            .windows(2)
            .map(|w| dist_seg(*s, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(
            d >= R - slack(),
            "the nose centre {s:?} is {d} mm from the profile, inside the nose radius\n{text}"
        );
    }
    for w in pts.windows(2) {
        let d = samples
            .iter()
            .map(|s| dist_seg(*s, w[0], w[1]))
            .fold(f64::INFINITY, f64::min);
        prop_assert!(
            (d - R).abs() < slack(),
            "the nose never touches {w:?} (nearest {d} mm)\n{text}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn rs274_nose_centre_is_tangent_to_a_monotone_profile_and_never_inside_it(pts in profile()) {
        check(false, &pts)?;
    }

    #[test]
    fn fanuc_nose_centre_is_tangent_to_a_monotone_profile_and_never_inside_it(pts in profile()) {
        check(true, &pts)?;
    }
}
