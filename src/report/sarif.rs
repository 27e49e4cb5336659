//! SARIF 2.1.0 (OASIS): one rule per finding kind, documented from `docs/findings/`, and one
//! result per finding with its file and line, so code review shows findings inline.
//!
//! Written with our own serde types for the handful of SARIF objects used (checked against the
//! SARIF 2.1.0 JSON schema in the tests). Nothing in it depends on time: two runs on the same
//! files give the same bytes.

use super::Report;
use crate::finding::{code, explain, Finding, Kind, Severity};
use crate::source::LineIndex;
use serde::Serialize;

const SCHEMA: &str = "https://json.schemastore.org/sarif-2.1.0.json";

#[derive(Serialize)]
struct Log<'a> {
    #[serde(rename = "$schema")]
    schema: &'static str,
    version: &'static str,
    runs: Vec<Run<'a>>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Run<'a> {
    tool: Tool,
    /// Where relative URIs are resolved: the folder latheguard ran in (the repository root in CI).
    original_uri_base_ids: BaseIds,
    artifacts: Vec<Artifact>,
    results: Vec<SarifResult<'a>>,
    /// Present when some file made no move: a note per such file (status `no_motion`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    invocations: Vec<Invocation>,
    column_kind: &'static str,
    properties: RunProperties<'a>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Invocation {
    execution_successful: bool,
    tool_execution_notifications: Vec<Notification>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Notification {
    level: &'static str,
    message: Message,
    locations: Vec<Location>,
    descriptor: Descriptor,
}

#[derive(Serialize)]
struct Descriptor {
    id: &'static str,
}

#[derive(Serialize)]
struct BaseIds {
    #[serde(rename = "%SRCROOT%")]
    src_root: BaseId,
}

#[derive(Serialize)]
struct BaseId {
    description: Message,
}

#[derive(Serialize)]
struct Tool {
    driver: Driver,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Driver {
    name: &'static str,
    version: &'static str,
    semantic_version: &'static str,
    rules: Vec<Rule>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Rule {
    id: &'static str,
    name: &'static str,
    short_description: Message,
    full_description: Message,
    help: Help,
    #[serde(skip_serializing_if = "Option::is_none")]
    help_uri: Option<String>,
    default_configuration: Configuration,
}

#[derive(Serialize)]
struct Help {
    text: String,
    markdown: String,
}

#[derive(Serialize)]
struct Configuration {
    level: &'static str,
}

#[derive(Serialize)]
struct Message {
    text: String,
}

#[derive(Serialize)]
struct Artifact {
    location: ArtifactLocation,
}

#[derive(Serialize, Clone)]
#[serde(rename_all = "camelCase")]
struct ArtifactLocation {
    uri: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    uri_base_id: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    index: Option<usize>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct SarifResult<'a> {
    rule_id: &'static str,
    rule_index: usize,
    level: &'static str,
    message: Message,
    locations: Vec<Location>,
    /// The picture written with `--svg`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    attachments: Vec<Attachment>,
    /// Stable from run to run (see `report::fingerprint`), so code scanning tracks a finding.
    partial_fingerprints: Fingerprints,
    /// Identical findings this one stands for (a loop's passes), when more than one.
    #[serde(skip_serializing_if = "Option::is_none")]
    occurrence_count: Option<u32>,
    /// Present for a finding a suppression comment sets aside.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    suppressions: Vec<SarifSuppression<'a>>,
    properties: ResultProperties<'a>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Attachment {
    description: Message,
    artifact_location: ArtifactLocation,
}

#[derive(Serialize)]
struct Fingerprints {
    #[serde(rename = "latheguard/v1")]
    v1: String,
}

#[derive(Serialize)]
struct SarifSuppression<'a> {
    kind: &'static str,
    justification: &'a str,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Location {
    physical_location: PhysicalLocation,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct PhysicalLocation {
    artifact_location: ArtifactLocation,
    /// Absent for a note about a whole file.
    #[serde(skip_serializing_if = "Option::is_none")]
    region: Option<Region>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
struct Region {
    start_line: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    start_column: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    end_line: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    snippet: Option<Message>,
}

/// The finding's facts beyond the message, under the names of the JSON report.
#[derive(Serialize)]
struct ResultProperties<'a> {
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    n: Option<u64>,
    #[serde(skip_serializing_if = "<[String]>::is_empty")]
    objects: &'a [String],
    #[serde(skip_serializing_if = "Option::is_none")]
    time_s: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    depth_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    moved_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    x: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    z: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    machine: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    profile_line: Option<u32>,
    /// With a job that has operations: the operation the contact began in (as in the JSON report).
    #[serde(skip_serializing_if = "Option::is_none")]
    operation: Option<u32>,
    /// Only for a follow-on contact: the crash it follows (as in the JSON report).
    #[serde(skip_serializing_if = "Option::is_none")]
    follow_on: Option<super::json::FollowOnDoc<'a>>,
}

#[derive(Serialize)]
struct RunProperties<'a> {
    machine: &'a str,
    settings: &'a crate::pipeline::Settings,
}

fn rule(kind: Kind, docs_url: Option<&str>) -> Rule {
    let doc = explain(kind);
    let meaning = section(doc, "What it means").unwrap_or_else(|| kind.name().replace('_', " "));
    let first = first_sentence(&meaning);
    Rule {
        id: code(kind),
        name: kind.name(),
        short_description: Message { text: first },
        full_description: Message { text: meaning },
        help: Help {
            text: doc.to_string(),
            markdown: doc.to_string(),
        },
        help_uri: docs_url.map(|base| format!("{base}/{}.md", kind.name())),
        default_configuration: Configuration {
            level: match kind {
                Kind::NearMiss | Kind::RapidScrape => "warning",
                _ => "error",
            },
        },
    }
}

/// The paragraph under a `## title` heading, joined into one line.
fn section(doc: &str, title: &str) -> Option<String> {
    let mut lines = doc.lines().skip_while(|l| l.trim() != format!("## {title}")).skip(1);
    let mut out = Vec::new();
    for l in lines.by_ref() {
        if l.trim().is_empty() {
            if out.is_empty() {
                continue;
            }
            break;
        }
        if l.starts_with('#') {
            break;
        }
        out.push(l.trim());
    }
    (!out.is_empty()).then(|| out.join(" "))
}

fn first_sentence(s: &str) -> String {
    match s.find(". ") {
        Some(i) => s[..=i].to_string(),
        None => s.to_string(),
    }
}

/// A report path as a URI reference: `/` separators, and percent-encoding of what a URI does not
/// allow as is. Absolute paths become `file://` URIs.
fn uri(path: &str) -> (String, Option<&'static str>) {
    let slashed = path.replace('\\', "/");
    let mut out = String::with_capacity(slashed.len());
    for b in slashed.bytes() {
        if b.is_ascii_alphanumeric() || b"-._~/!$&'()*+,;=:@".contains(&b) {
            out.push(b as char);
        } else {
            out.push_str(&format!("%{b:02X}"));
        }
    }
    if slashed.starts_with('/') {
        (format!("file://{out}"), None)
    } else {
        (out, Some("%SRCROOT%"))
    }
}

fn round6(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// The longest source line quoted as a snippet. A longer line (a generated or hostile file) is
/// not quoted: each finding would copy it whole, so a file of one long line with many findings
/// made the log grow with findings × line length (10 GB for a 1 MB line).
pub const MAX_SNIPPET_BYTES: usize = 1000;

/// The source text of a 1-based line, when the report has it and it is short enough to quote.
fn line_text(li: &LineIndex, source: &[u8], line: u32) -> Option<String> {
    if line == 0 || line as usize > li.line_count() {
        return None;
    }
    let range = li.line_span(source, line).range();
    if range.len() > MAX_SNIPPET_BYTES {
        return None;
    }
    let text = String::from_utf8_lossy(&source[range]).into_owned();
    (!text.trim().is_empty()).then_some(text)
}

fn message(f: &Finding) -> String {
    super::text::with_facts(f.message.clone(), f, false, false)
}

/// A note about a whole file (no region): what became of it, or what was read from it.
fn file_note(path: &str, text: String, id: &'static str) -> Notification {
    let (uri, uri_base_id) = uri(path);
    Notification {
        level: "note",
        message: Message { text },
        locations: vec![Location {
            physical_location: PhysicalLocation {
                artifact_location: ArtifactLocation {
                    uri,
                    uri_base_id,
                    index: None,
                },
                region: None,
            },
        }],
        descriptor: Descriptor { id },
    }
}

/// The whole batch as one SARIF 2.1.0 log (pretty-printed, with a trailing newline).
pub fn sarif(r: &Report) -> String {
    let rules: Vec<Rule> = Kind::ALL.iter().map(|&k| rule(k, r.docs_url.as_deref())).collect();
    let mut artifacts = Vec::new();
    let mut results = Vec::new();
    let mut notes = Vec::new();
    for f in &r.files {
        if f.status() == super::Status::NoMotion {
            notes.push(file_note(&f.path, super::NO_MOTION_MESSAGE.into(), "no_motion"));
        }
        if let Some(line) = crate::assume::sentence(&f.assumed) {
            notes.push(file_note(&f.path, line, "setup_assumed"));
        }
        if f.findings.is_empty() && f.suppressed.is_empty() {
            continue;
        }
        let (u, base) = uri(&f.path);
        let index = artifacts.len();
        artifacts.push(Artifact {
            location: ArtifactLocation {
                uri: u.clone(),
                uri_base_id: base,
                index: None,
            },
        });
        let lines = (!f.source.is_empty()).then(|| LineIndex::new(&f.source));
        let all: Vec<(&Finding, Option<&str>)> = f
            .findings
            .iter()
            .map(|x| (x, None))
            .chain(f.suppressed.iter().map(|s| (&s.finding, Some(s.reason.as_str()))))
            .collect();
        let prints = super::fingerprint::fingerprints(f, &all.iter().map(|(x, _)| *x).collect::<Vec<_>>());
        for ((x, reason), print) in all.into_iter().zip(prints) {
            let rule_index = Kind::ALL.iter().position(|&k| k == x.kind).unwrap_or(0);
            let snippet = lines.as_ref().and_then(|li| line_text(li, &f.source, x.line));
            results.push(SarifResult {
                rule_id: code(x.kind),
                rule_index,
                level: match x.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                },
                message: Message { text: message(x) },
                locations: vec![Location {
                    physical_location: PhysicalLocation {
                        artifact_location: ArtifactLocation {
                            uri: u.clone(),
                            uri_base_id: base,
                            index: Some(index),
                        },
                        region: Some(Region {
                            start_line: x.line.max(1),
                            start_column: (x.col > 0).then_some(x.col),
                            end_line: (x.end_line > x.line).then_some(x.end_line),
                            snippet: snippet.map(|text| Message { text }),
                        }),
                    },
                }],
                attachments: x
                    .picture
                    .iter()
                    .map(|p| {
                        let (uri, uri_base_id) = uri(p);
                        Attachment {
                            description: Message {
                                text: "the working plane at first contact (SVG)".into(),
                            },
                            artifact_location: ArtifactLocation {
                                uri,
                                uri_base_id,
                                index: None,
                            },
                        }
                    })
                    .collect(),
                partial_fingerprints: Fingerprints { v1: print },
                occurrence_count: (x.repeats > 1).then_some(x.repeats),
                suppressions: reason
                    .map(|justification| SarifSuppression {
                        kind: "inSource",
                        justification,
                    })
                    .into_iter()
                    .collect(),
                properties: ResultProperties {
                    kind: x.kind.name(),
                    n: x.n,
                    objects: &x.objects,
                    time_s: x.time_s.map(round6),
                    depth_mm: x.depth_mm.map(round6),
                    moved_mm: x.moved_mm.map(round6),
                    x: x.x.map(round6),
                    z: x.z.map(round6),
                    machine: f.machine.as_deref(),
                    profile_line: x.profile_line,
                    operation: x.operation,
                    follow_on: x.follow_on.as_ref().map(super::json::FollowOnDoc::of),
                },
            });
        }
    }
    let log = Log {
        schema: SCHEMA,
        version: "2.1.0",
        runs: vec![Run {
            tool: Tool {
                driver: Driver {
                    name: "latheguard",
                    version: env!("CARGO_PKG_VERSION"),
                    semantic_version: env!("CARGO_PKG_VERSION"),
                    rules,
                },
            },
            original_uri_base_ids: BaseIds {
                src_root: BaseId {
                    description: Message {
                        text: "The folder latheguard ran in; report paths are relative to it.".into(),
                    },
                },
            },
            artifacts,
            results,
            invocations: if notes.is_empty() {
                Vec::new()
            } else {
                vec![Invocation {
                    execution_successful: true,
                    tool_execution_notifications: notes,
                }]
            },
            column_kind: "unicodeCodePoints",
            properties: RunProperties {
                machine: &r.machine,
                settings: &r.settings,
            },
        }],
    };
    let mut s = serde_json::to_string_pretty(&log).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}
