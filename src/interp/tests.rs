//! Tests of the interpreter's internals (behaviour is tested by the data-driven cases).

use super::flow::Run;
use super::Limits;
use crate::gcode;
use crate::machine::Machine;
use proptest::prelude::*;

/// Interpret with or without the fast path for plain blocks.
fn run(src: &str, machine: &Machine, fast: bool) -> String {
    let prog = gcode::parse(src.as_bytes());
    let mut r = Run::new(&prog, src.as_bytes(), machine, Limits::for_program(&prog));
    r.plain_blocks_fast = fast;
    r.run();
    let i = r.finish();
    format!("{:?}\n{:?}\n{:?}", i.moves, i.states, i.findings)
}

#[test]
fn every_g_code_the_block_executor_tests_has_a_bit() {
    // `Words::g(code)` is false for a code outside KNOWN_G: a code asked about but missing from
    // the list would silently never be seen.
    let src = include_str!("block.rs");
    let mut asked = 0;
    for pat in ["w.g(", "has_g(", "gb("] {
        for (i, _) in src.match_indices(pat) {
            let rest = &src[i + pat.len()..];
            let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
            if digits.is_empty() || !rest[digits.len()..].starts_with(')') {
                continue;
            }
            let code: u16 = digits.parse().unwrap();
            assert!(
                super::block::KNOWN_G.contains(&code),
                "G code x10 {code} is not in KNOWN_G"
            );
            asked += 1;
        }
    }
    assert!(asked > 40, "found only {asked} codes: has the pattern changed?");
}

fn linuxcnc() -> Machine {
    let text = include_str!("../../machines/linuxcnc-small-lathe.toml");
    crate::machine::from_toml(text, "linuxcnc-small-lathe.toml").unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn plain_blocks_run_the_same_with_and_without_their_fast_path(
        lines in proptest::collection::vec(
            "(G[0-3] |G1 F0\\.[1-3] |G4 P1 |G4[0-2] |G91 |G90 |G20 |G21 |G7 |G8 |G53 |G28 |M3 S500 |T[12] M6 |F-1 |#1=2 |)?((X|Z|U|W|I|K|R|F|Y|P)-?[0-9]{1,2}(\\.[0-9])? ?){0,4}",
            1..25,
        ),
        fanuc in any::<bool>(),
    ) {
        let src = lines.join("\n");
        let m = if fanuc { Machine::builtin() } else { linuxcnc() };
        prop_assert_eq!(run(&src, &m, true), run(&src, &m, false));
    }
}

/// `interpret_streaming` hands over exactly the moves `interpret` returns, in order, with the
/// states they refer to, across many chunks and with cycles (whose passes look back at the moves
/// of their own block) on both sides of chunk boundaries.
#[test]
fn streamed_moves_equal_the_moves_of_a_whole_run() {
    let unit = "G0 X52 Z3\nG71 U2 R0.5\nG71 P10 Q60 U0.4 W0.1 F0.25\nN10 G0 X20\nN20 G1 Z-10\nN30 X30 Z-15\nN40 Z-30\nN50 G2 X40 Z-35 R5\nN60 G1 X52\nG70 P10 Q60\nG0 X40 Z5\nG76 P010060 Q100 R0.05\nG76 X37.4 Z-25 P1300 Q400 F2\nG0 X60 Z5\n";
    let mut src = String::from("G21 G18 G99\nT0101\nG97 S800 M3\n");
    for i in 0..200 {
        src.push_str(unit);
        // A few plain moves of varying count, so cycles start at every offset of a chunk.
        for k in 0..(i % 7) {
            src.push_str(&format!("G1 X{} Z2 F0.2\n", 50 + k));
        }
        // Moves nose-radius compensation holds back across blocks.
        src.push_str("G0 X30 Z5\nG42 G1 X20 Z2 F0.2\nG1 Z-10\nX40 Z-20\nG40 G0 X60 Z5\n");
    }
    src.push_str("M30\n");
    let machine = Machine::builtin();
    let prog = gcode::parse(src.as_bytes());
    let whole = super::interpret(&prog, src.as_bytes(), &machine);
    assert!(
        whole.moves.len() > 3 * super::flow::STREAM_CHUNK,
        "{}",
        whole.moves.len()
    );
    let mut streamed = Vec::new();
    let mut chunks = 0;
    let rest = super::interpret_streaming(&prog, src.as_bytes(), &machine, |moves, states| {
        chunks += 1;
        streamed.extend(moves.iter().map(|m| (*m, states[m.state as usize])));
    });
    assert!(chunks > 3);
    assert!(rest.moves.is_empty());
    let expected: Vec<_> = whole
        .moves
        .iter()
        .map(|m| (*m, whole.states[m.state as usize]))
        .collect();
    assert_eq!(streamed, expected);
    assert_eq!(rest.states, whole.states);
    assert_eq!(format!("{:?}", rest.findings), format!("{:?}", whole.findings));
    assert_eq!(rest.blocks_executed, whole.blocks_executed);
}

/// `spindle.start_rpm`: the program starts as if `M3 S<rpm>` had come before its first line.
#[test]
fn a_spindle_start_speed_turns_the_spindle_before_any_m3() {
    let src = "G21 G97\nG0 X50 Z5\nG1 Z0 F0.2\nM5\nG1 Z-1\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = Machine::builtin();
    let stopped = super::interpret(&prog, src.as_bytes(), &m);
    assert_eq!(stopped.spindle(&stopped.moves[0]).rpm_at(10.0), 0.0);
    m.start_rpm = Some(800.0);
    let on = super::interpret(&prog, src.as_bytes(), &m);
    assert_eq!(on.spindle(&on.moves[0]).rpm_at(10.0), 800.0);
    assert_eq!(on.spindle(&on.moves[1]).rpm_at(10.0), 800.0);
    // The program's own M5 still stops it.
    assert_eq!(on.spindle(&on.moves[2]).rpm_at(10.0), 0.0);
}

/// A job's manual tool change switches the tool before the words of its line, each time the
/// line runs, as a T word would (a tool change move at that line, then the new station).
#[test]
fn a_manual_tool_change_switches_the_tool_at_its_line_each_time_it_runs() {
    let src = "G21\nG0 X50 Z5\nM0 (PUT IN T3)\nG0 X60\nT0101\nG0 X70\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = Machine::builtin();
    m.tool_changes = vec![(3, 3)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let seen: Vec<(u32, u32, bool)> = i
        .moves
        .iter()
        .map(|mv| {
            (
                mv.line,
                mv.station,
                matches!(mv.kind, super::MoveKind::ToolChange { .. }),
            )
        })
        .collect();
    assert_eq!(
        seen,
        vec![(2, 1, false), (3, 3, true), (4, 3, false), (5, 1, true), (6, 1, false)],
        "{:?}",
        i.findings
    );
    // On a line that also moves, the change comes first: the move is made with the new tool.
    m.tool_changes = vec![(4, 2)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let at4: Vec<u32> = i.moves.iter().filter(|mv| mv.line == 4).map(|mv| mv.station).collect();
    assert_eq!(at4, vec![2, 2]);
    // A subroutine line runs twice: the change happens each time (LinuxCNC o-words).
    let src = "o100 sub\nG0 X40\no100 endsub\nT1 M6\no100 call\nT1 M6\no100 call\nM2\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = linuxcnc();
    m.tool_changes = vec![(2, 2)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let changes: Vec<(u32, u32)> = i
        .moves
        .iter()
        .filter(|mv| matches!(mv.kind, super::MoveKind::ToolChange { .. }))
        .map(|mv| (mv.line, mv.station))
        .collect();
    assert_eq!(changes, vec![(2, 2), (6, 1), (2, 2)], "{:?}", i.findings);
}
