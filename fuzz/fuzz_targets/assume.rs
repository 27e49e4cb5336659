//! A first run's path on arbitrary bytes: a program with no job on the built-in machine (whose
//! setup is an example, `[setup] assume = true`) has its setup read from the program
//! (`assume::apply`), and the program is then checked on the machine so read, with the check
//! fuzz target's bounds (a work budget of 20,000 pair tests, 200,000 blocks, a 0.05 mm
//! tolerance, a 5 ms timestep; the reading itself runs the program to the real 2M-block budget).
//! What a fuzzer finds here is a panic or an endless stage in the reading, or a
//! machine it builds that the checker cannot take.
#![no_main]

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

static MACHINE: OnceLock<Machine> = OnceLock::new();

fuzz_target!(|data: &[u8]| {
    let m = MACHINE.get_or_init(Machine::builtin);
    let applied = latheguard::assume::apply(data, "fuzz.nc", m);
    let machine = applied.machine.as_ref().map_or(m, |(read, _)| read);
    let settings = Settings {
        mode: if data.first().is_some_and(|b| b & 1 == 1) {
            Mode::Exact
        } else {
            Mode::Step
        },
        dt_ms: 5.0,
        tolerance_mm: 0.05,
        work_budget: 20_000,
        max_blocks: Some(200_000),
        ..Settings::default()
    };
    let out = pipeline::check(data, machine, &settings);
    let lines = latheguard::source::LineIndex::new(data).line_count() as u32;
    for f in &out.findings {
        assert!(f.line >= 1 && f.line <= lines.max(1));
    }
});
