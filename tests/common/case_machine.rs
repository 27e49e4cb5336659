//! The machine a `(test-case: machine=NAME)` option names: `machines/NAME.toml`, else
//! `tests/machines/NAME.toml`, else `tests/fixtures/docs/NAME.toml` (a machine the docs' examples
//! run too; read by the data-driven cases, the step/exact agreement test and the seeded
//! crashes), and the job beside a case applied over it.

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

/// `machine` with the job beside case `program` applied (`NAME.job.toml` for `NAME.nc`, as
/// `latheguard check` reads the file beside a program), when there is one: parsed, merged as the
/// one job layer and applied by the library, the files it names read relative to it.
pub fn with_case_job(machine: Machine, program: &Path) -> Machine {
    with_job(machine, &program.with_extension("job.toml"))
}

/// `machine` with the job file `job` applied, when there is one (as [`with_case_job`]).
pub fn with_job(machine: Machine, job: &Path) -> Machine {
    let Ok(text) = std::fs::read_to_string(job) else {
        return machine;
    };
    let shown = job.display().to_string();
    let dir = job.parent().unwrap_or(Path::new(".")).display().to_string();
    let mut resolve = |base: &str, rel: &str| -> Result<(String, String), String> {
        let p = Path::new(base).join(rel);
        std::fs::read_to_string(&p)
            .map(|t| (p.display().to_string(), t))
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let layer = latheguard::job::parse(&text, &shown, &dir, &shown, &mut resolve).unwrap();
    let effective = latheguard::job::EffectiveJob::merge([&layer]);
    latheguard::job::apply(&machine, &effective).unwrap()
}
