//! The whole pipeline (read, interpret, check) on arbitrary bytes, built-in machine: step mode,
//! or exact mode when the first byte is odd. Each input's work is bounded tighter than a real
//! check's (a work budget of 20,000 pair tests, 200,000 blocks, a 0.05 mm tolerance, a 5 ms
//! timestep): what a fuzzer finds is a panic or an endless stage, and an input past its budget still runs every
//! stage up to it and the budget's own finding; a million runs then fit in an hour or so on one
//! core instead of a day (docs/testing.md).
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
        dt_ms: 5.0,
        tolerance_mm: 0.05,
        work_budget: 20_000,
        max_blocks: Some(200_000),
        ..Settings::default()
    };
    let out = pipeline::check(data, m, &settings);
    let lines = latheguard::source::LineIndex::new(data).line_count() as u32;
    for f in &out.findings {
        assert!(f.line >= 1 && f.line <= lines.max(1));
    }
});
