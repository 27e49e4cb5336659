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

fn linuxcnc() -> Machine {
    let text = include_str!("../../machines/linuxcnc-small-lathe.toml");
    crate::machine::from_toml(text, "linuxcnc-small-lathe.toml").unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn plain_blocks_run_the_same_with_and_without_their_fast_path(
        lines in proptest::collection::vec(
            "(G[0-3] |G1 F0\\.[1-3] |G4 P1 |G91 |G90 |G20 |G21 |G7 |G8 |G53 |G28 |M3 S500 |T[12] M6 |F-1 |#1=2 |)?((X|Z|U|W|I|K|R|F|Y|P)-?[0-9]{1,2}(\\.[0-9])? ?){0,4}",
            1..25,
        ),
        fanuc in any::<bool>(),
    ) {
        let src = lines.join("\n");
        let m = if fanuc { Machine::builtin() } else { linuxcnc() };
        prop_assert_eq!(run(&src, &m, true), run(&src, &m, false));
    }
}
