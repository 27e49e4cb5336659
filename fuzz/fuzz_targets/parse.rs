//! `cargo +nightly fuzz run parse`: the G-code reader never panics, never recurses without bound,
//! and what it returns is consistent with its input.
#![no_main]

use latheguard::gcode::{parse, parse_fanuc, Program, Value};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Both readers: LinuxCNC's, and the Fanuc one with macro B statements.
    check(data, parse(data));
    check(data, parse_fanuc(data));
});

fn check(data: &[u8], prog: Program) {
    let lines = prog.lines.line_count() as u32;
    for e in &prog.errors {
        assert!(e.line >= 1 && e.line <= lines && e.col >= 1);
    }
    let mut last_line = 0;
    for b in &prog.blocks {
        assert!(b.line > last_line && b.line <= lines);
        last_line = b.line;
        assert!(b.span.start <= b.span.end && b.span.end as usize <= data.len());
        for w in prog.words_of(b) {
            assert!(w.letter.is_ascii_uppercase());
            assert!(b.span.start <= w.span().start && w.span().start < w.span().end);
            assert!(w.span().end <= b.span.end);
            if let Value::Num(x) = w.value() {
                assert!(x.is_finite());
            }
        }
        for a in prog.assigns_of(b) {
            assert!((a.value as usize) < prog.exprs.len());
        }
    }
    assert_eq!(
        prog.errors.len() + prog.errors_left_out.count as usize,
        prog.blocks.iter().filter(|b| b.bad).count()
    );
}
