//! Property tests: no input makes the pipeline panic, hang or blow up.

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Settings};
use proptest::prelude::*;

fn gcode_like() -> impl Strategy<Value = String> {
    let word = prop_oneof![
        "[GMXZUWIKRFSTPQLDNO][-+]?[0-9]{0,4}(\\.[0-9]{0,3})?",
        "#[0-9]{1,4}=[-0-9.]{1,6}",
        "#<[a-z_]{1,6}>=\\[[0-9+*/ ]{1,8}\\]",
        "o[0-9]{1,3} (sub|endsub|call|while \\[1\\]|endwhile|if \\[0\\]|endif|do|repeat \\[2\\]|endrepeat|break|continue|return)",
        "\\([^)]{0,8}\\)?",
        ";[ -~]{0,8}",
        "[ \\t/%\\[\\]]",
    ];
    prop::collection::vec(prop::collection::vec(word, 0..8).prop_map(|w| w.join(" ")), 0..30).prop_map(|l| l.join("\n"))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic_the_pipeline(src in prop::collection::vec(any::<u8>(), 0..400)) {
        let m = Machine::builtin();
        let out = pipeline::check(&src, &m, &Settings::default());
        let lines = latheguard::source::LineIndex::new(&src).line_count() as u32;
        for f in &out.findings {
            prop_assert!(f.line >= 1 && f.line <= lines.max(1), "finding on line {} of {}", f.line, lines);
        }
    }

    #[test]
    fn gcode_like_text_never_panics_the_pipeline(src in gcode_like()) {
        let m = Machine::builtin();
        let _ = pipeline::check(src.as_bytes(), &m, &Settings::default());
    }
}

#[test]
fn an_endless_loop_stops_with_a_program_finding_at_the_looping_line() {
    let src = b"G21 G18\no100 while [1]\nG4 P0\no100 endwhile\nM30\n";
    let (_, run) = pipeline::interpret(src, &Machine::builtin());
    let f = run
        .findings
        .iter()
        .find(|f| f.message.contains("loop"))
        .expect("a loop finding");
    assert!((2..=4).contains(&f.line), "line {}", f.line);
}

#[test]
fn m99_in_the_main_program_is_checked_once() {
    let src = b"G21 G18\nG0 X100 Z50\nM99\n";
    let (_, run) = pipeline::interpret(src, &Machine::builtin());
    assert!(run.findings.iter().any(|f| f.line == 3 && f.message.contains("M99")));
    assert_eq!(run.moves.len(), 1);
}

#[test]
fn a_one_megabyte_line_is_read() {
    let mut src = b"G21 G18\nG0 X100 Z50 (".to_vec();
    src.extend(std::iter::repeat_n(b'a', 1 << 20));
    src.extend(b")\nG0 X120\nM30\n");
    let (prog, run) = pipeline::interpret(&src, &Machine::builtin());
    assert!(prog.errors.is_empty());
    assert_eq!(run.moves.len(), 2);
}

#[test]
fn deeply_nested_expressions_are_an_error_not_a_stack_overflow() {
    let mut src = String::from("G21 G18\nG0 X");
    src.push_str(&"[".repeat(100_000));
    src.push('1');
    src.push_str(&"]".repeat(100_000));
    src.push_str(" Z50\n");
    let out = pipeline::check(src.as_bytes(), &Machine::builtin(), &Settings::default());
    assert!(out.findings.iter().any(|f| f.line == 2));
}

#[test]
fn a_long_sum_is_evaluated_or_refused_without_overflow() {
    let mut src = String::from("G21 G18\n#1=[0");
    src.push_str(&"+1".repeat(200_000));
    src.push_str("]\nG0 X#1 Z50\n");
    let _ = pipeline::check(src.as_bytes(), &Machine::builtin(), &Settings::default());
}
