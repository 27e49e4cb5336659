//! The JSON report (docs/cli.md, "The JSON report").

use super::{Report, Summary};
use crate::finding::Finding;
use crate::pipeline::{Settings, Stats};
use serde::Serialize;

#[derive(Serialize)]
struct Doc<'a> {
    tool: &'static str,
    version: &'static str,
    machine: &'a str,
    settings: &'a Settings,
    files: Vec<FileDoc<'a>>,
    summary: Summary,
}

#[derive(Serialize)]
struct FileDoc<'a> {
    path: &'a str,
    /// Only for a file checked on another machine or with other settings than the report's.
    #[serde(skip_serializing_if = "Option::is_none")]
    machine: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    settings: Option<&'a Settings>,
    /// The job layers that applied to this file (absent when none did).
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    job: &'a [String],
    /// The setup read from the program (absent when nothing was read).
    #[serde(skip_serializing_if = "Option::is_none")]
    setup: Option<SetupDoc<'a>>,
    /// Only with `machine.dialect = "auto"`: the dialect chosen for this file and why.
    #[serde(skip_serializing_if = "Option::is_none")]
    dialect: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    dialect_reason: Option<&'a str>,
    status: &'static str,
    findings: Vec<FindingDoc<'a>>,
    /// Findings set aside by suppression comments, each with its reason (absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    suppressed: Vec<SuppressedDoc<'a>>,
    stats: &'a Stats,
    stock: Vec<Vec<[f64; 2]>>,
}

/// `setup`: each value read from the program (`kept`: the machine file's, which the program
/// agrees with).
#[derive(Serialize)]
struct SetupDoc<'a> {
    assumed: &'a [crate::assume::Assumption],
}

#[derive(Serialize)]
struct FindingDoc<'a> {
    line: u32,
    end_line: u32,
    column: Option<u32>,
    n: Option<u64>,
    kind: &'static str,
    severity: &'static str,
    objects: &'a [String],
    time_s: Option<f64>,
    depth_mm: Option<f64>,
    /// How far a part that should have stood still moved, mm (absent for every other finding).
    #[serde(skip_serializing_if = "Option::is_none")]
    moved_mm: Option<f64>,
    x: Option<f64>,
    z: Option<f64>,
    message: &'a str,
    /// The crash this contact is a follow-on of (absent for an independent finding).
    #[serde(skip_serializing_if = "Option::is_none")]
    follow_on: Option<FollowOnDoc<'a>>,
    /// The profile block a canned cycle's move follows (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    profile_line: Option<u32>,
    /// With a job that has operations: the operation the contact began in, from 1 (absent
    /// otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    operation: Option<u32>,
    /// The picture of the finding written with `--svg` (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    picture: Option<&'a str>,
    /// How many identical findings this one stands for (absent when 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    repeats: Option<u32>,
}

#[derive(Serialize)]
struct SuppressedDoc<'a> {
    #[serde(flatten)]
    finding: FindingDoc<'a>,
    /// The reason the suppression comment gives, and its line.
    reason: &'a str,
    suppressed_at: u32,
}

impl<'a> From<&'a Finding> for FindingDoc<'a> {
    fn from(f: &'a Finding) -> FindingDoc<'a> {
        FindingDoc {
            line: f.line,
            end_line: f.end_line,
            column: (f.col > 0).then_some(f.col),
            n: f.n,
            kind: f.kind.name(),
            severity: f.severity.name(),
            objects: &f.objects,
            time_s: f.time_s.map(round6),
            depth_mm: f.depth_mm.map(round6),
            moved_mm: f.moved_mm.map(round6),
            x: f.x.map(round6),
            z: f.z.map(round6),
            message: &f.message,
            follow_on: f.follow_on.as_ref().map(FollowOnDoc::of),
            profile_line: f.profile_line,
            operation: f.operation,
            picture: f.picture.as_deref(),
            repeats: (f.repeats > 1).then_some(f.repeats),
        }
    }
}

/// One finding as one line of JSON, the fields of the JSON report's findings (`latheguard
/// follow`'s JSON lines).
pub fn finding_json(f: &Finding) -> String {
    serde_json::to_string(&FindingDoc::from(f)).unwrap_or_default()
}

/// The crash a follow-on contact comes from, its time rounded as every JSON number is (the
/// JSON report's `follow_on`, and the SARIF result's `properties.follow_on`).
#[derive(Serialize)]
pub(super) struct FollowOnDoc<'a> {
    line: u32,
    objects: &'a [String],
    time_s: f64,
}

impl<'a> FollowOnDoc<'a> {
    pub(super) fn of(p: &'a crate::finding::FollowOn) -> FollowOnDoc<'a> {
        FollowOnDoc {
            line: p.line,
            objects: &p.objects,
            time_s: round6(p.time_s),
        }
    }
}

/// Six decimals: nm and µs, stable across platforms' last-bit differences.
fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// The whole batch as one pretty-printed JSON document, with a trailing newline.
pub fn json(r: &Report) -> String {
    let doc = Doc {
        tool: "latheguard",
        version: env!("CARGO_PKG_VERSION"),
        machine: &r.machine,
        settings: &r.settings,
        files: r
            .files
            .iter()
            .map(|f| FileDoc {
                path: &f.path,
                machine: f.machine.as_deref(),
                settings: f.settings.as_ref(),
                job: &f.job,
                setup: (!f.assumed.is_empty()).then_some(SetupDoc { assumed: &f.assumed }),
                dialect: f.stats.dialect.as_ref().map(|d| d.0.as_str()),
                dialect_reason: f.stats.dialect.as_ref().map(|d| d.1.as_str()),
                status: f.status().name(),
                findings: f.findings.iter().map(FindingDoc::from).collect(),
                suppressed: f
                    .suppressed
                    .iter()
                    .map(|s| SuppressedDoc {
                        finding: FindingDoc::from(&s.finding),
                        reason: &s.reason,
                        suppressed_at: s.at,
                    })
                    .collect(),
                stats: &f.stats,
                stock: f
                    .stock
                    .iter()
                    .map(|o| o.iter().map(|p| [round6(p[0]), round6(p[1])]).collect())
                    .collect(),
            })
            .collect(),
        summary: r.summary(),
    };
    let mut s = serde_json::to_string_pretty(&doc).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}
