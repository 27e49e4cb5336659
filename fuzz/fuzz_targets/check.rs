//! The whole pipeline (read, interpret, check) on arbitrary bytes, built-in machine: step mode,
//! or exact mode when the first byte is odd.
#![no_main]

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

static MACHINE: OnceLock<Machine> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let m = MACHINE.get_or_init(Machine::builtin);
    let mode = if data.first().is_some_and(|b| b & 1 == 1) {
        Mode::Exact
    } else {
        Mode::Step
    };
    let settings = Settings {
        mode,
        ..Settings::default()
    };
    let out = pipeline::check(data, m, &settings);
    let lines = latheguard::source::LineIndex::new(data).line_count() as u32;
    for f in &out.findings {
        assert!(f.line >= 1 && f.line <= lines.max(1));
    }
});
