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
    assert!((start_up.end.x - x).abs() < 1e-9 && (start_up.end.y - z).abs() < 1e-9, "{start_up:?}");
    let (_, run) = pipeline::interpret(src.replace(" / ", "\n").as_bytes(), &m);
    assert!(run.findings.is_empty(), "{:?}", run.findings);
}
