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

// ---------------------------------------------------------------------------------------------
// Spindle speed zero: a per-revolution feed with no usable spindle speed is a `program` finding
// at the feed move's line, timed at the fallback feed, never an endless machine time.

fn no_speed_findings(out: &pipeline::Outcome) -> Vec<u32> {
    out.findings
        .iter()
        .filter(|f| f.kind == latheguard::finding::Kind::Program && f.message.contains("no spindle speed"))
        .map(|f| f.line)
        .collect()
}

/// The machine time of a program if every feed ran at the fallback feed, plus the rapids: an
/// upper bound for the programs below (a few minutes), far from "astronomical".
const SANE_MACHINE_TIME_S: f64 = 600.0;

#[test]
fn g96_without_s_before_a_per_rev_feed_is_a_program_finding_not_an_endless_move() {
    // Feeds into the chuck at the end, as the hostile test did.
    let src = b"G18 G21 G99\nT0101\nM3\nG0 X50 Z5\nG96\nG1 Z-20 F0.2\nG1 Z-200\nM30\n";
    let t = std::time::Instant::now();
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert!(t.elapsed().as_secs_f64() < 5.0, "took {:?}", t.elapsed());
    assert_eq!(no_speed_findings(&out), vec![6, 7]);
    assert!(out.stats.machine_time_s.is_finite() && out.stats.machine_time_s < SANE_MACHINE_TIME_S);
}

#[test]
fn g96_s0_feed_is_timed_at_the_fallback_feed() {
    let src = b"G18 G21 G99\nT0101\nM3\nG0 X50 Z5\nG96 S0\nG1 Z-20 F0.2\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert_eq!(no_speed_findings(&out), vec![6]);
    // 25 mm at 100 mm/min = 15 s, plus the rapid.
    let t = out.stats.machine_time_s;
    assert!((15.0..20.0).contains(&t), "machine time {t}");
}

#[test]
fn css_with_a_g50_s0_clamp_has_no_spindle_speed() {
    let src = b"G18 G21 G99\nT0101\nG50 S0\nG96 S200 M3\nG0 X50 Z5\nG1 Z-20 F0.2\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert_eq!(no_speed_findings(&out), vec![6]);
    assert!(out.stats.machine_time_s < SANE_MACHINE_TIME_S);
}

#[test]
fn per_rev_feed_at_g97_s0_is_a_program_finding() {
    let src = b"G18 G21 G99 G97 S0 M3\nT0101\nG0 X50 Z5\nG1 Z-20 F0.2\nG1 X60\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert_eq!(no_speed_findings(&out), vec![4, 5]);
}

#[test]
fn per_rev_feed_with_a_spindle_never_given_a_speed_is_a_program_finding() {
    let src = b"G18 G21 G99\nT0101\nG0 X50 Z5\nG1 Z-20 F0.2\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert_eq!(no_speed_findings(&out), vec![4]);
}

#[test]
fn a_stalled_feed_in_a_loop_is_reported_once_per_line() {
    let src = b"G18 G21 G99\nT0101\nG96 S0 M3\nG0 X50 Z5\nM98 P100 L50\nM30\nO100\nG1 Z-1 F0.2\nG1 Z0\nM99\n";
    let (_, run) = pipeline::interpret(src, &Machine::builtin());
    let tl = latheguard::motion::timeline(&run, &Machine::builtin());
    assert_eq!(tl.feed_without_speed.len(), 2, "{:?}", tl.feed_without_speed);
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert_eq!(no_speed_findings(&out), vec![8, 9]);
}

#[test]
fn css_at_a_huge_radius_below_one_rpm_has_no_spindle_speed() {
    // S1 m/min at r = 1000 mm is 0.16 rpm: timed at the fallback feed, not for hours.
    let src = b"G18 G21 G99\nT0101\nG96 S1 M3\nG0 X2000 Z5\nG1 Z-20 F0.2\nM30\n";
    let (_, run) = pipeline::interpret(src, &Machine::builtin());
    let tl = latheguard::motion::timeline(&run, &Machine::builtin());
    assert_eq!(tl.feed_without_speed.len(), 1);
    assert!(tl.total < SANE_MACHINE_TIME_S, "{}", tl.total);
}

#[test]
fn spindle_speed_above_max_rpm_is_clamped_with_a_warning() {
    let m = Machine::builtin();
    let src = format!(
        "G18 G21 G99\nT0101\nG97 S{} M3\nG0 X50 Z5\nG1 Z-20 F0.2\nM30\n",
        m.max_rpm * 2.0
    );
    let out = pipeline::check(src.as_bytes(), &m, &Settings::default());
    let w: Vec<_> = out.findings.iter().filter(|f| f.message.contains("max_rpm")).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!((w[0].line, w[0].col), (3, 5));
    assert_eq!(w[0].severity, latheguard::finding::Severity::Warning);
    // Timed at max_rpm: 25 mm at 0.2 mm/rev.
    let (_, run) = pipeline::interpret(src.as_bytes(), &m);
    let tl = latheguard::motion::timeline(&run, &m);
    let feed = &tl.items[tl.items.len() - 1];
    let expect = 25.0 / (0.2 * m.max_rpm / 60.0);
    assert!((feed.duration - expect).abs() < 1e-9, "{} vs {expect}", feed.duration);
}

#[test]
fn css_above_max_rpm_near_the_axis_is_clamped_with_a_warning() {
    let src = b"G18 G21 G99\nT0101\nG96 S200 M3\nG0 X50 Z5\nG1 Z0 F0.2\nG1 X0\nG0 X100 Z100\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    let w: Vec<_> = out
        .findings
        .iter()
        .filter(|f| f.message.contains("max_rpm"))
        .map(|f| (f.line, f.severity))
        .collect();
    assert_eq!(w, vec![(6, latheguard::finding::Severity::Warning)]);
    // With a program limit at or below max_rpm there is nothing to say.
    let src = b"G18 G21 G99\nT0101\nG50 S2000\nG96 S200 M3\nG0 X50 Z5\nG1 Z0 F0.2\nG1 X0\nG0 X100 Z100\nM30\n";
    let out = pipeline::check(src, &Machine::builtin(), &Settings::default());
    assert!(!out.findings.iter().any(|f| f.message.contains("max_rpm")));
}

// ---------------------------------------------------------------------------------------------
// G4: the dwell words.

fn moves_of(src: &[u8], m: &Machine) -> Vec<latheguard::interp::MoveKind> {
    pipeline::interpret(src, m).1.moves.iter().map(|m| m.kind).collect()
}

#[test]
fn fanuc_g04_x_is_a_dwell_not_a_move() {
    use latheguard::interp::MoveKind;
    let m = Machine::builtin();
    for word in ["X0.5", "U0.5", "P500", "X.5"] {
        let src = format!("G18 G21 G99 G97 S800 M3\nT0101\nG0 X50 Z5\nG1 Z-1 F0.2\nG04 {word}\nG0 X100 Z100\nM30\n");
        let kinds = moves_of(src.as_bytes(), &m);
        let dwell = kinds
            .iter()
            .position(|k| matches!(k, MoveKind::Dwell { .. }))
            .expect("a dwell");
        assert_eq!(kinds[dwell], MoveKind::Dwell { seconds: 0.5 }, "G04 {word}");
        assert!(
            matches!(kinds[dwell + 1], MoveKind::Rapid),
            "G04 {word} moved: {kinds:?}"
        );
        let out = pipeline::check(src.as_bytes(), &m, &Settings::default());
        assert!(out.findings.is_empty(), "G04 {word}: {:?}", out.findings);
    }
}

#[test]
fn fanuc_g04_with_two_dwell_words_or_a_z_word_is_an_error_and_does_not_move() {
    let m = Machine::builtin();
    for (word, col) in [("X0.5 P500", 1), ("X0.5 Z3", 10)] {
        let src = format!("G18 G21 G99 G97 S800 M3\nT0101\nG0 X50 Z5\nG04 {word}\nM30\n");
        let (_, run) = pipeline::interpret(src.as_bytes(), &m);
        assert!(
            run.moves
                .iter()
                .all(|m| m.line != 4 || matches!(m.kind, latheguard::interp::MoveKind::Dwell { .. })),
            "G04 {word} moved: {:?}",
            run.moves
        );
        assert!(
            run.findings.iter().any(|f| f.line == 4 && f.col == col),
            "G04 {word}: {:?}",
            run.findings
        );
    }
}

#[test]
fn linuxcnc_g4_takes_p_seconds_and_x_stays_an_axis_word() {
    use latheguard::interp::MoveKind;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/linuxcnc-small-lathe.toml");
    let m = latheguard::machine::from_toml(&std::fs::read_to_string(&path).unwrap(), "lcnc").unwrap();
    // rs274ngc: G4 reads P (seconds); axis words in the block go to the modal motion (G1 here).
    let src = b"G18 G21 G7\nT1 M6\nS800 M3\nG0 X20 Z5\nG1 Z-1 F50\nG4 P0.5 X10\nM2\n";
    let kinds = moves_of(src, &m);
    let dwell = kinds
        .iter()
        .position(|k| matches!(k, MoveKind::Dwell { .. }))
        .expect("a dwell");
    assert_eq!(kinds[dwell], MoveKind::Dwell { seconds: 0.5 });
    assert!(matches!(kinds[dwell + 1], MoveKind::Line), "{kinds:?}");
    // X alone is no dwell time there.
    let (_, run) = pipeline::interpret(b"G18 G21\nG4 X1\nM2\n", &m);
    assert!(run
        .findings
        .iter()
        .any(|f| f.line == 2 && f.message.contains("G4 needs P")));
}
