//! Nose-radius compensation around the Fanuc/Haas stock-removal cycles and the start-up's start
//! point (docs/comp.md, "Canned cycles"; docs/cycles.md): the moves the interpreter makes,
//! compared with hand-worked points and with the same blocks run as plain blocks.

use latheguard::interp::{Move, MoveKind};
use latheguard::machine::Machine;
use latheguard::pipeline;
use std::path::PathBuf;

fn machine(name: &str) -> Machine {
    crate::case_machine::case_machine(&PathBuf::from(env!("CARGO_MANIFEST_DIR")), name)
}

/// The motions (rapids, lines, arcs) of a program, `/` separating its blocks.
fn motions(src: &str, m: &Machine) -> Vec<Move> {
    let text = src.replace(" / ", "\n");
    let (_, run) = pipeline::interpret(text.as_bytes(), m);
    run.moves
        .into_iter()
        .filter(|m| matches!(m.kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }))
        .collect()
}

/// The reproducer: the second start-up (line 12) starts where line 11's rapid left the
/// tool (X1.6 Z0.1), not at the end of the first compensated stretch (X1.6 Z-2.157).
#[test]
fn a_start_up_after_g40_and_a_retract_starts_where_the_tool_is() {
    let m = machine("haas-style-inch");
    let src = "G18 G20 G40 G99 / T0202 / G97 S1000 M03 / G00 G54 X1.6 Z0.1 / G00 G42 X1.455 Z-1.98 / \
               G01 X1.415 F0.004 / X1.375 Z-2.0 / Z-2.157 / X1.455 / G00 G40 X1.6 / G00 Z0.1 / \
               G00 G42 X-0.062 Z0.1 / G01 Z0.0 F0.005 / X0.3 / G00 G40 X1.6 / M30";
    let mv = motions(src, &m);
    let at = |line: u32| mv.iter().find(|m| m.line == line).copied().unwrap();
    let retract = at(11);
    let start_up = at(12);
    assert_eq!(start_up.start, retract.end, "{start_up:?}");
    // Where it goes (mm, radius): the imaginary tip at X-0.062 (radius -0.031 in) and Z0.1 less
    // the nose radius (0.2 mm), program Z0 being at z 63.5 of the machine.
    let (x, z) = (-0.031 * 25.4, 63.5 + 0.1 * 25.4 - 0.2);
    assert!(
        (start_up.end.x - x).abs() < 1e-9 && (start_up.end.y - z).abs() < 1e-9,
        "{start_up:?}"
    );
    let (_, run) = pipeline::interpret(src.replace(" / ", "\n").as_bytes(), &m);
    assert!(run.findings.is_empty(), "{:?}", run.findings);
}

/// (kind, end) of each motion of line `line` (or of every line when `None`), ends rounded to 1 nm.
fn path(mv: &[Move], lines: &[u32]) -> Vec<(String, i64, i64)> {
    mv.iter()
        .filter(|m| lines.is_empty() || lines.contains(&m.line))
        .map(|m| {
            let kind = match m.kind {
                MoveKind::Rapid => "rapid",
                MoveKind::Line => "line",
                _ => "arc",
            };
            (
                kind.to_string(),
                (m.end.x * 1e6).round() as i64,
                (m.end.y * 1e6).round() as i64,
            )
        })
        .collect()
}

/// The roughing cycles read their profile without compensation: with G41/G42 on block P and
/// G40 on block Q (or none) their passes are exactly those of the profile without the words.
#[test]
fn roughing_passes_ignore_the_profiles_compensation_words() {
    let m = machine("comp-fanuc-rear");
    let head = "G21 G18 G99 G97 S800 M3 / T0404";
    let programs = [
        format!("{head} / G0 X44 Z3 / G71 U3 R0.5 / G71 P10 Q40 U1 W0.2 F0.3 / N10 G0 G42 X30 / N20 G1 Z-15 F0.1 / N30 X40 / N40 G40 X46 / M30"),
        format!("{head} / G0 X44 Z3 / G71 P10 Q30 U1 W0.2 D3 F0.3 / N10 G0 G42 X30 / N20 G1 Z-15 F0.1 / N30 X46 / M30"),
        format!("{head} / G0 X54 Z2 / G72 W1.5 R0.5 / G72 P10 Q40 U0 W0.2 F0.2 / N10 G0 G41 Z-4 / N20 G1 X20 / N30 Z2 / N40 G40 X16 Z3 / M30"),
        format!("{head} / G0 X56 Z5 / G73 U4 W2 R3 / G73 P10 Q40 U1 W0.5 F0.2 / N10 G0 G42 X30 Z0 / N20 G1 Z-20 / N30 X52 / N40 G40 X56 / M30"),
        // Compensation already on before the cycle: the words of the profile change nothing either.
        format!("{head} / G0 X50 Z8 / G42 G0 X44 Z3 / G71 P10 Q30 U1 W0 D3 F0.3 / N10 G1 G42 X36 F0.1 / N20 Z-15 / N30 G40 X46 / G40 G0 X60 Z5 / M30"),
    ];
    for with in &programs {
        // The same program without the profile's words.
        let without = ["N10 G0 G42", "N10 G0 G41", "N10 G1 G42"]
            .iter()
            .fold(with.clone(), |t, w| t.replace(w, &w[..w.len() - 4]))
            .replace("N30 G40", "N30")
            .replace("N40 G40", "N40");
        assert_ne!(&without, with);
        // The cycle's line: its block's place in the program.
        let line = with.split(" / ").position(|b| b.contains("P10")).unwrap() as u32 + 1;
        let (a, b) = (motions(with, &m), motions(&without, &m));
        assert!(a.iter().filter(|m| m.line == line).count() > 4, "{with}: {a:?}");
        assert_eq!(path(&a, &[line]), path(&b, &[line]), "{with}");
        let (_, run) = pipeline::interpret(with.replace(" / ", "\n").as_bytes(), &m);
        assert!(run.findings.is_empty(), "{with}: {:?}", run.findings);
    }
}

/// G70 runs its profile through compensation as plain blocks: the profile's G42 starts it on
/// block P's move, G40 on block Q cancels it, and the way back to the start point follows — the
/// same path as the blocks written out, followed by the cycle's return (Z first, then X). A
/// compensated stretch before (G42 … G40) leaves a stage that the G70 must use, not replace.
#[test]
fn g70_compensates_its_profile_as_plain_blocks_would() {
    let m = machine("comp-fanuc-rear");
    let before = "G21 G18 G99 G97 S800 M3 / T0404 / G0 X60 Z10 / G42 G1 X50 Z5 F0.2 / Z4 / G40 G0 X60 Z8";
    let profile = "N10 G0 G42 X30 / N20 G1 Z-15 F0.1 / N30 X40 / N40 G40 X46";
    for (profile, back) in [
        (profile.to_string(), "G0 Z3 / X44"),
        // No G40 in the profile: compensation stays on through the way back, until line G40.
        (profile.replace("N40 G40", "N40"), "G0 Z3 / X44"),
    ] {
        let cycle = format!("{before} / G0 X44 Z3 / G70 P10 Q40 / G40 G0 X70 Z10 / M30 / {profile}");
        let plain = format!("{before} / G0 X44 Z3 / {profile} / {back} / G40 G0 X70 Z10 / M30");
        let (a, b) = (motions(&cycle, &m), motions(&plain, &m));
        assert_eq!(path(&a, &[]), path(&b, &[]), "{cycle}");
        let (_, run) = pipeline::interpret(cycle.replace(" / ", "\n").as_bytes(), &m);
        assert!(run.findings.is_empty(), "{cycle}: {:?}", run.findings);
    }
}

/// A start-up block right before G70 ends normal to the G70's first move, as before a plain
/// block (it was let out before the cycle, perpendicular to itself: 1.4 mm off on diameter).
#[test]
fn a_start_up_before_g70_ends_normal_to_its_first_move() {
    let m = machine("comp-fanuc-rear");
    let head = "G21 G18 G99 G97 S800 M3 / T0404 / G0 X50 Z8 / G42 G0 X44 Z3";
    let cycle = format!("{head} / G70 P10 Q30 / G40 G0 X60 Z5 / M30 / N10 G1 X36 F0.1 / N20 Z-15 / N30 X46");
    let plain = format!("{head} / N10 G1 X36 F0.1 / N20 Z-15 / N30 X46 / G0 Z3 / X44 / G40 G0 X60 Z5 / M30");
    let (a, b) = (motions(&cycle, &m), motions(&plain, &m));
    assert_eq!(path(&a, &[]), path(&b, &[]));
    // By hand: the vector is normal to N10 (toward -X, tool on its right: -Z), centre (22, 2.2);
    // the tip (tip 3) at (21.2, 1.4).
    let s = a.iter().find(|m| m.line == 4).unwrap();
    assert!((s.end.x - 21.2).abs() < 1e-9 && (s.end.y - 1.4).abs() < 1e-9, "{s:?}");
}
