//! Job applier for `tests/corpus_setups.rs`: the real loader, as `latheguard check --machine M
//! --job J` uses it. The machine file is read with `latheguard::machine::from_toml`, the job
//! file with `latheguard::job::parse` (catalogue designations, `drill`, tool libraries and
//! LinuxCNC tool tables included; the files a job names are read relative to the job file),
//! merged as the one job layer over the machine's own setup (`EffectiveJob::merge`) and applied
//! with `latheguard::job::apply`, so every value goes through the same validation as in the
//! binary.
#![allow(dead_code)]

use latheguard::job::{self, EffectiveJob};
use latheguard::machine::{self, Machine};
use std::path::Path;

/// The machine file `machine_toml` (named `machine_name` in messages) with the job file at
/// `job_path` applied.
pub fn apply(machine_toml: &str, machine_name: &str, job_path: &Path) -> Result<Machine, String> {
    let base = machine::from_toml(machine_toml, machine_name).map_err(|e| format!("{machine_name}: {e}"))?;
    let job_text = std::fs::read_to_string(job_path).map_err(|e| format!("{}: {e}", job_path.display()))?;
    let shown = job_path.display().to_string();
    let dir = job_path.parent().unwrap_or(Path::new(".")).display().to_string();
    let mut resolve = |base: &str, rel: &str| -> Result<(String, String), String> {
        let p = Path::new(base).join(rel);
        std::fs::read_to_string(&p)
            .map(|t| (p.display().to_string(), t))
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let layer = job::parse(&job_text, &shown, &dir, &shown, &mut resolve).map_err(|e| e.to_string())?;
    let effective = EffectiveJob::merge([&layer]);
    job::apply(&base, &effective).map_err(|e| format!("{machine_name} with {shown}: {e}"))
}
