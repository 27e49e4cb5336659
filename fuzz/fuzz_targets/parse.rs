//! `cargo +nightly fuzz run parse`: the G-code reader never panics, never recurses without bound,
//! and what it returns is consistent with its input; read two blocks a window (every window past
//! the cache read again from the source), it is the program read whole.
#![no_main]

use latheguard::gcode::{parse, parse_fanuc, parse_windowed, Program, Value};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    // Both readers: LinuxCNC's, and the Fanuc one with macro B statements.
    check(data, parse(data));
    check(data, parse_fanuc(data));
    for fanuc in [false, true] {
        let whole = if fanuc { parse_fanuc(data) } else { parse(data) };
        let windowed = parse_windowed(data, fanuc, 2);
        assert_eq!(whole.len(), windowed.len());
        assert_eq!(format!("{:?}", whole.exprs), format!("{:?}", windowed.exprs));
        assert_eq!(whole.names, windowed.names);
        // From the last block back: each window read again.
        for i in (0..whole.len()).rev() {
            let (a, b) = (whole.block(i), windowed.block(i));
            assert_eq!((a.line, a.span, a.n(), a.bad), (b.line, b.span, b.n(), b.bad));
            assert_eq!((a.oword(), a.message(), a.macro_stmt()), (b.oword(), b.message(), b.macro_stmt()));
            assert_eq!(format!("{:?} {:?}", a.words(), a.assigns()), format!("{:?} {:?}", b.words(), b.assigns()));
        }
    }
});

fn check(data: &[u8], prog: Program) {
    let lines = prog.line_count();
    for e in &prog.errors {
        assert!(e.line >= 1 && e.line <= lines && e.col >= 1);
    }
    let mut last_line = 0;
    for b in prog.blocks() {
        assert!(b.line > last_line && b.line <= lines);
        last_line = b.line;
        assert!(b.span.start <= b.span.end && b.span.end as usize <= data.len());
        for w in b.words() {
            assert!(w.letter.is_ascii_uppercase());
            assert!(b.span.start <= w.span().start && w.span().start < w.span().end);
            assert!(w.span().end <= b.span.end);
            if let Value::Num(x) = w.value() {
                assert!(x.is_finite());
            }
        }
        for a in b.assigns() {
            assert!((a.value as usize) < prog.exprs.len());
        }
    }
    assert_eq!(
        prog.errors.len() + prog.errors_left_out.count as usize,
        prog.blocks().filter(|b| b.bad).count()
    );
}
