//! The machine a `(test-case: machine=NAME)` option names: `machines/NAME.toml`, else
//! `tests/machines/NAME.toml`, else `tests/fixtures/docs/NAME.toml` (a machine the docs' examples
//! run too; read by the data-driven cases and the step/exact agreement test).

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
