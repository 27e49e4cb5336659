//! The whole pipeline (read, interpret, step-mode check) on arbitrary bytes, built-in machine.
#![no_main]

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Settings};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

static MACHINE: OnceLock<Machine> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let m = MACHINE.get_or_init(Machine::builtin);
    let out = pipeline::check(data, m, &Settings::default());
    let lines = latheguard::source::LineIndex::new(data).line_count() as u32;
    for f in &out.findings {
        assert!(f.line >= 1 && f.line <= lines.max(1));
    }
});
