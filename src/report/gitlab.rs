//! `--format gitlab`: a GitLab Code Quality report (a JSON array of issues, the subset of the
//! Code Climate format GitLab reads: `description`, `check_name`, `fingerprint`, `severity`,
//! `location.path`, `location.lines.begin`), for `artifacts: reports: codequality:`.
//!
//! Severity: crash findings (`collision`, `rapid_into_stock`, `spindle_stopped`, `overtravel`)
//! are `critical`; other errors (`syntax`, `program`, an `unsupported` code that moves the
//! machine) `major`; warnings `minor`; a file with no motion `info`. Suppressed findings are
//! left out. Fingerprints are stable from run to run ([`super::fingerprint`]).

use super::{Report, Status};
use crate::finding::{code, Kind, Severity};
use serde::Serialize;

#[derive(Serialize)]
struct Issue {
    description: String,
    check_name: String,
    fingerprint: String,
    severity: &'static str,
    location: Location,
}

#[derive(Serialize)]
struct Location {
    path: String,
    lines: Lines,
}

#[derive(Serialize)]
struct Lines {
    begin: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    end: Option<u32>,
}

fn severity(kind: Kind, s: Severity) -> &'static str {
    match (s, kind) {
        (Severity::Warning, _) => "minor",
        (_, Kind::Collision | Kind::RapidIntoStock | Kind::SpindleStopped | Kind::Overtravel) => "critical",
        _ => "major",
    }
}

pub fn gitlab(r: &Report) -> String {
    let mut issues = Vec::new();
    for f in &r.files {
        let path = f.path.replace('\\', "/");
        if f.status() == Status::NoMotion {
            issues.push(Issue {
                description: super::NO_MOTION_MESSAGE.into(),
                check_name: "no_motion".into(),
                fingerprint: super::fingerprint::file_fingerprint(&f.path, "no_motion"),
                severity: "info",
                location: Location {
                    path: path.clone(),
                    lines: Lines { begin: 1, end: None },
                },
            });
        }
        let list: Vec<_> = f.findings.iter().collect();
        let prints = super::fingerprint::fingerprints(f, &list);
        for (x, fingerprint) in list.into_iter().zip(prints) {
            issues.push(Issue {
                description: format!(
                    "{}: {}",
                    x.kind.name(),
                    super::text::with_facts(x.message.clone(), x, true, true)
                ),
                check_name: format!("{} {}", code(x.kind), x.kind.name()),
                fingerprint,
                severity: severity(x.kind, x.severity),
                location: Location {
                    path: path.clone(),
                    lines: Lines {
                        begin: x.line.max(1),
                        end: (x.end_line > x.line).then_some(x.end_line),
                    },
                },
            });
        }
    }
    let mut s = serde_json::to_string_pretty(&issues).unwrap_or_else(|_| "[]".into());
    s.push('\n');
    s
}
