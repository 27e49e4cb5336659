//! Reporters: the findings of a batch as text, JSON, JUnit and SARIF, and a picture (SVG) of
//! each finding's scene.
//!
//! A finding of the 3D path (turn-mill) carries a [`scene3::Snapshot3`] beside (or instead of) the
//! 2D snapshot (`Finding::snapshot3`): `--svg` draws it as three orthographic views
//! ([`views3`]), `--glb` writes it as a glTF binary ([`glb`]).
//!
//! Every reporter takes the same [`Report`] and returns a string; choosing one is the binary's
//! job. Reporters never reorder findings: the caller sorts files by path and findings by line.

mod fingerprint;
mod github;
mod gitlab;
pub mod glb;
mod json;
mod junit;
pub mod machine_svg;
pub mod part;
mod part_dims;
pub mod part_svg;
mod sarif;
pub mod scene3;
mod statistics;
pub mod svg;
mod text;
pub mod views3;

use crate::finding::{Finding, Severity};
use crate::pipeline::{Settings, Stats};

pub use github::github;
pub use gitlab::gitlab;
pub use json::{finding_json, json};
pub use junit::{junit, JunitOptions};
pub use sarif::sarif;
pub use statistics::{statistics, statistics_json};
pub use text::{finding_text, summary_line, terminal_safe, text, TextOptions};

/// One checked file.
#[derive(Clone, Debug, Default)]
pub struct FileReport {
    pub path: String,
    pub findings: Vec<Finding>,
    pub stats: Stats,
    /// The program's bytes, for showing source lines (text reports).
    pub source: Vec<u8>,
    /// The final stock outlines, `[x, z]` (see [`crate::pipeline::Outcome::stock`]).
    pub stock: Vec<Vec<[f64; 2]>>,
    /// The final part as binary STL, when asked for (`--stock-out FILE.stl`).
    pub part_stl: Option<Vec<u8>>,
    /// The part the next operation takes (`--stock-out FILE.toml`).
    pub part: Option<crate::pipeline::FinalPart>,
    /// The machine's name, when it is not the report's (a per-folder `latheguard.toml`).
    pub machine: Option<String>,
    /// The settings, when they are not the report's.
    pub settings: Option<Settings>,
    /// The job layers that applied (docs/job.md), lowest first; empty when none did.
    pub job: Vec<String>,
    /// The setup read from the program (docs/assume.md): each value assumed, or kept from the
    /// machine file because the program agrees with it. Empty when nothing was read.
    pub assumed: Vec<crate::assume::Assumption>,
    /// Findings set aside by suppression comments in the program (never counted as errors).
    pub suppressed: Vec<crate::gate::Suppressed>,
    /// The file's own `fail-on` (its `latheguard.toml`'s), over [`Report::fail_on`].
    pub fail_on: Option<crate::gate::FailOn>,
}

/// What became of one checked file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    /// Moves reached the machine and nothing was found.
    Clean,
    /// At least one finding.
    Findings,
    /// No finding, and no move ever reached the machine (a subroutine library nobody calls, a
    /// program of settings only): nothing was checked, so it is not called clean.
    NoMotion,
}

impl Status {
    /// The name in the reports: `clean`, `findings`, `no_motion`.
    pub fn name(self) -> &'static str {
        match self {
            Status::Clean => "clean",
            Status::Findings => "findings",
            Status::NoMotion => "no_motion",
        }
    }
}

/// The message every report gives a file of status [`Status::NoMotion`].
pub const NO_MOTION_MESSAGE: &str = "no move reaches the machine (nothing was checked)";

impl FileReport {
    pub fn status(&self) -> Status {
        if !self.findings.is_empty() {
            Status::Findings
        } else if self.stats.moves == 0 {
            Status::NoMotion
        } else {
            Status::Clean
        }
    }
}

/// A whole batch.
#[derive(Clone, Debug)]
pub struct Report {
    pub machine: String,
    pub settings: Settings,
    pub files: Vec<FileReport>,
    /// Which severity fails the run (`--fail-on`).
    pub fail_on: crate::gate::FailOn,
    /// Where the finding pages (`docs/findings/KIND.md`) are published, without the trailing
    /// slash: SARIF links each rule to its page (`helpUri`). `None`: no links (the pages' text is
    /// in SARIF's `help` either way).
    pub docs_url: Option<String>,
}

/// Counts over a batch.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct Summary {
    pub files: usize,
    pub clean: usize,
    pub with_findings: usize,
    /// Files with no finding whose moves never reach the machine (counted apart from `clean`).
    pub no_motion: usize,
    pub errors: usize,
    pub warnings: usize,
    /// Findings set aside by suppression comments (not in `errors` or `warnings`).
    pub suppressed: usize,
}

impl Report {
    pub fn summary(&self) -> Summary {
        let mut s = Summary {
            files: self.files.len(),
            ..Summary::default()
        };
        for f in &self.files {
            match f.status() {
                Status::Clean => s.clean += 1,
                Status::Findings => s.with_findings += 1,
                Status::NoMotion => s.no_motion += 1,
            }
            for x in &f.findings {
                match x.severity {
                    Severity::Error => s.errors += 1,
                    Severity::Warning => s.warnings += 1,
                }
            }
            s.suppressed += f.suppressed.len();
        }
        s
    }

    /// Exit status 1 (docs/cli.md): a reported (not suppressed) finding of a severity
    /// [`Report::fail_on`] names (by default, an error).
    pub fn fails(&self) -> bool {
        self.files.iter().any(|f| {
            f.findings
                .iter()
                .any(|x| f.fail_on.unwrap_or(self.fail_on).fails(x.severity))
        })
    }
}
