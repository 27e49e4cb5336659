//! Hostile programs against the reader and the interpreter: work linear in the input, findings
//! capped per file (issue 10, item 5: quadratic time and unbounded memory).
//!
//! Each input is large enough that the old quadratic code took minutes on it; the code under test
//! is linear and finishes in well under a second. The bound each test waits for is generous (a
//! loaded machine must not make them flaky): what they catch is a return to quadratic work.

use latheguard::finding::{Kind, MAX_FINDINGS};
use latheguard::gcode;
use latheguard::interp;
use latheguard::machine::{Dialect, Machine};
use latheguard::pipeline::{self, Settings};
use std::sync::mpsc;
use std::time::Duration;

/// Run `f` on its own thread; fail if it has not finished after `secs` seconds.
fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(Duration::from_secs(secs)) {
        Ok(v) => v,
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("did not finish within {secs} s: quadratic work is back"),
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("the worker panicked"),
    }
}

fn linuxcnc() -> Machine {
    let mut m = Machine::builtin();
    m.dialect = Dialect::Linuxcnc;
    m
}

#[test]
fn many_findings_on_one_line_count_columns_incrementally() {
    // One line of 320,000 X words: every one after the first is "given twice", each with its
    // column. Counting each column from the line start was quadratic (5e10 byte reads).
    const N: usize = 320_000;
    let (clean, run) = within(60, || {
        let src = "X1 ".repeat(N).into_bytes();
        let m = linuxcnc();
        let prog = gcode::parse(&src);
        let run = interp::interpret(&prog, &src, &m);
        (prog.errors.is_empty(), run)
    });
    assert!(clean);
    assert_eq!(run.findings.len(), MAX_FINDINGS);
    assert_eq!(run.findings_left_out.count, (N - 1 - MAX_FINDINGS) as u64);
    for (k, f) in run.findings.iter().enumerate() {
        assert_eq!((f.line, f.kind), (1, Kind::Program));
        assert_eq!(f.col as usize, 3 * (k + 1) + 1, "{}", f.message);
    }
}

#[test]
fn columns_of_findings_on_one_line_count_characters_after_non_ascii_comments() {
    // The column cursor counts on from the previous finding: characters, not bytes, in between.
    let src = "G1 (\u{e9}\u{e9}) X1 (\u{20ac}) X2 (\u{1F600}) X3\n"
        .as_bytes()
        .to_vec();
    let prog = gcode::parse(&src);
    let run = interp::interpret(&prog, &src, &linuxcnc());
    let cols: Vec<u32> = run
        .findings
        .iter()
        .filter(|f| f.message.contains("twice"))
        .map(|f| f.col)
        .collect();
    assert_eq!(cols, [16, 23], "{:?}", run.findings);
}

#[test]
fn unmatched_o_word_closers_do_not_scan_the_open_stack() {
    // 150,000 open `if`s, then 150,000 `endif`s of another name: each closer used to search the
    // whole stack of open structures for its name (2e10 comparisons).
    const N: usize = 150_000;
    let (clean, run) = within(60, || {
        let mut src = "o1 if [1]\n".repeat(N);
        src.push_str(&"o2 endif\n".repeat(N));
        let src = src.into_bytes();
        let prog = gcode::parse(&src);
        let run = interp::interpret(&prog, &src, &linuxcnc());
        (prog.errors.is_empty(), run)
    });
    assert!(clean);
    assert_eq!(run.findings.len(), MAX_FINDINGS);
    assert_eq!(run.findings_left_out.count, (2 * N - MAX_FINDINGS) as u64);
    assert!(run.findings[0].message.contains("o2 endif without a matching if"));
}

#[test]
fn o_word_closers_still_match_the_innermost_structure_of_their_name() {
    // The indexed stack keeps the old matching: innermost of the name, inner ones closed with it,
    // a `while` right after its `do` closes the `do`.
    let src = b"o1 if [1]\no2 if [1]\no1 if [0]\no1 endif\no2 endif\no1 endif\no3 do\no3 while [0]\n\
o4 while [0]\no4 endwhile\no5 endif\n"
        .to_vec();
    let prog = gcode::parse(&src);
    let run = interp::interpret(&prog, &src, &linuxcnc());
    let msgs: Vec<(u32, &str)> = run.findings.iter().map(|f| (f.line, f.message.as_str())).collect();
    assert_eq!(msgs, [(11, "o5 endif without a matching if")]);
}

#[test]
fn elseif_chains_count_against_the_block_budget() {
    // A loop around an `if` with 100,000 false `elseif`s: the branches tested used not to count
    // as executed, so the two-million-block budget allowed 5e10 condition tests.
    const N: usize = 100_000;
    let run = within(60, || {
        let mut src = String::from("o1 while [1]\no2 if [0]\n");
        src.push_str(&"o2 elseif [0]\n".repeat(N));
        src.push_str("o2 endif\no1 endwhile\n");
        let src = src.into_bytes();
        let prog = gcode::parse(&src);
        interp::interpret(&prog, &src, &linuxcnc())
    });
    assert!(
        run.findings
            .iter()
            .any(|f| f.message.contains("seems to loop without end")),
        "{:?}",
        run.findings
    );
    assert!(run.blocks_executed <= 2_000_001 + N as u64);
}

#[test]
fn findings_are_capped_per_file_as_they_are_read() {
    // A syntax error on every line: the reader keeps MAX_FINDINGS and counts the rest.
    const N: usize = 30_000;
    let src = "X\n".repeat(N).into_bytes();
    let prog = gcode::parse(&src);
    assert_eq!(prog.errors.len(), MAX_FINDINGS);
    assert_eq!(prog.errors_left_out.count, (N - MAX_FINDINGS) as u64);
    assert_eq!(prog.errors_left_out.first_line, MAX_FINDINGS as u32 + 1);
}

#[test]
fn a_capped_report_ends_with_one_program_finding_that_counts_the_rest() {
    // Syntax errors on the first lines, interpreter errors on the later ones: the report keeps
    // the first MAX_FINDINGS by line and one `program` finding counts every other one.
    const N: usize = 8_000;
    let mut src = "X\n".repeat(N);
    src.push_str(&"G1 X1 X2\n".repeat(N));
    let out = pipeline::check(src.as_bytes(), &Machine::builtin(), &Settings::default());
    assert_eq!(out.findings.len(), MAX_FINDINGS + 1);
    let last = out
        .findings
        .iter()
        .filter(|f| f.message.contains("not listed"))
        .collect::<Vec<_>>();
    assert_eq!(last.len(), 1);
    let note = last[0];
    assert_eq!(note.kind, Kind::Program);
    assert_eq!(note.line, MAX_FINDINGS as u32 + 1);
    assert!(
        note.message
            .starts_with(&format!("{} more findings", 2 * N - MAX_FINDINGS)),
        "{}",
        note.message
    );
    assert!(out.findings.windows(2).all(|w| w[0].line <= w[1].line));
}

#[test]
fn a_block_in_a_loop_reports_its_problem_once_and_does_not_fill_the_cap() {
    // 20,000 passes over a bad block, then 5 other problems: all reported, the loop's once.
    let src = b"o1 repeat [20000]\nG1 X1 X2\no1 endrepeat\nX1 X1\nZ1 Z1\nF1 F1\nS1 S1\nT1 T1\n".to_vec();
    let prog = gcode::parse(&src);
    let run = interp::interpret(&prog, &src, &linuxcnc());
    assert_eq!(run.findings_left_out.count, 0);
    let lines: Vec<u32> = run.findings.iter().map(|f| f.line).collect();
    assert_eq!(lines, [2, 4, 5, 6, 7, 8], "{:?}", run.findings);
}

#[test]
fn many_findings_on_one_long_line_decode_the_line_once_in_the_text_report() {
    // MAX_FINDINGS findings on one line of two megabytes: the text report decoded the whole line
    // for each of them (2e10 characters, 40 s in a release build); it now decodes it once.
    use latheguard::report::{text, FileReport, Report, TextOptions};
    const N: usize = 640_000;
    let out = within(30, || {
        let src = "X1 ".repeat(N).into_bytes();
        let outcome = pipeline::check(&src, &linuxcnc(), &Settings::default());
        let report = Report {
            machine: "m".into(),
            settings: Settings::default(),
            fail_on: Default::default(),
            docs_url: None,
            files: vec![FileReport {
                path: "p.ngc".into(),
                findings: outcome.findings,
                stats: outcome.stats,
                source: src,
                stock: Vec::new(),
                part_stl: None,
                part: None,
                machine: None,
                settings: None,
                assumed: Vec::new(),
                job: Vec::new(),
                suppressed: Vec::new(),
                fail_on: None,
            }],
        };
        text(&report, TextOptions::default())
    });
    assert!(out.contains("p.ngc:1:7: error[program]: X word given twice in one block"));
    assert!(out.contains("more findings not listed"));
}
