//! The machine a `(test-case: machine=NAME)` option names: `machines/NAME.toml`, else
//! `tests/machines/NAME.toml`, else `tests/fixtures/docs/NAME.toml` (a machine the docs' examples
//! run too; read by the data-driven cases, the step/exact agreement test and the seeded
//! crashes), and the job beside a case applied over it.

use latheguard::job;
use latheguard::machine::{self, Machine};
use std::path::Path;

pub fn case_machine(root: &Path, name: &str) -> Machine {
    let mut path = root.join("machines").join(format!("{name}.toml"));
    if !path.exists() {
        path = root.join("tests/machines").join(format!("{name}.toml"));
    }
    if !path.exists() {
        path = root.join("tests/fixtures/docs").join(format!("{name}.toml"));
    }
    let text = std::fs::read_to_string(&path).unwrap();
    machine::from_toml(&text, &path.display().to_string()).unwrap()
}

/// `machine` with the job beside the case (`NAME.job.toml` for `NAME.nc`) applied, as
/// `latheguard check` applies a job beside a program; `machine` as it is without one.
pub fn with_job_beside(case: &Path, machine: Machine) -> Machine {
    let path = case.with_extension("job.toml");
    let Ok(text) = std::fs::read_to_string(&path) else {
        return machine;
    };
    let shown = path.display().to_string();
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> {
        Err(format!("a case's job reads no other file ({rel})"))
    };
    let layer = job::parse(&text, &shown, ".", &shown, &mut no_files).unwrap_or_else(|e| panic!("{e}"));
    job::apply(&machine, &job::EffectiveJob::merge([&layer])).unwrap_or_else(|e| panic!("{e}"))
}
