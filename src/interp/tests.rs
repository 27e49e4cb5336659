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
