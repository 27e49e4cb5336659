//! `--statistics`: how many findings of each kind a batch has, most frequent first (as ruff
//! prints its statistics), then the summary line.
//!
//! ```text
//!     12  LG12  unsupported  warning
//!      3  LG01  collision    error
//!      1  LG02  rapid_into_stock  error  (1 more suppressed)
//! ```
//!
//! A finding that stands for repeats ([`crate::finding::Finding::repeats`]) counts as many;
//! suppressed findings are counted in their own column, not in the first.

use super::Report;
use crate::finding::{code, Kind, Severity};
use std::collections::BTreeMap;
use std::fmt::Write;

/// (kind, (reported, suppressed, errors among both)), most frequent first.
type Rows = Vec<(Kind, (u64, u64, u64))>;

fn rows(r: &Report) -> Rows {
    // kind → (reported, suppressed, errors among both)
    let mut counts: BTreeMap<Kind, (u64, u64, u64)> = BTreeMap::new();
    for f in &r.files {
        for x in &f.findings {
            let c = counts.entry(x.kind).or_default();
            let n = u64::from(x.repeats.max(1));
            c.0 += n;
            if x.severity == Severity::Error {
                c.2 += n;
            }
        }
        for s in &f.suppressed {
            let c = counts.entry(s.finding.kind).or_default();
            let n = u64::from(s.finding.repeats.max(1));
            c.1 += n;
            if s.finding.severity == Severity::Error {
                c.2 += n;
            }
        }
    }
    let mut rows: Vec<(Kind, (u64, u64, u64))> = counts.into_iter().collect();
    rows.sort_by(|a, b| b.1 .0.cmp(&a.1 .0).then(a.0.cmp(&b.0)));
    rows
}

fn severity(n: u64, suppressed: u64, errors: u64) -> &'static str {
    match errors {
        0 => "warning",
        e if e == n + suppressed => "error",
        _ => "error/warning",
    }
}

/// `--statistics --format json`: `{"counts": {KIND: N, …}, "kinds": [{"kind", "code", "count",
/// "suppressed", "severity"}, …] (most frequent first), "summary": {…}}`.
pub fn statistics_json(r: &Report) -> String {
    let rows = rows(r);
    let counts: serde_json::Map<String, serde_json::Value> = rows
        .iter()
        .map(|(k, (n, _, _))| (k.name().to_string(), (*n).into()))
        .collect();
    let kinds: Vec<serde_json::Value> = rows
        .iter()
        .map(|(k, (n, suppressed, errors))| {
            serde_json::json!({
                "kind": k.name(),
                "code": code(*k),
                "count": n,
                "suppressed": suppressed,
                "severity": severity(*n, *suppressed, *errors),
            })
        })
        .collect();
    let doc = serde_json::json!({ "counts": counts, "kinds": kinds, "summary": r.summary() });
    let mut s = serde_json::to_string_pretty(&doc).unwrap_or_default();
    s.push('\n');
    s
}

pub fn statistics(r: &Report) -> String {
    let rows = rows(r);
    let width = rows.iter().map(|(k, _)| k.name().len()).max().unwrap_or(0);
    let mut out = String::new();
    for (k, (n, suppressed, errors)) in rows {
        let severity = severity(n, suppressed, errors);
        let more = if suppressed > 0 {
            format!("  ({suppressed} more suppressed)")
        } else {
            String::new()
        };
        let _ = writeln!(out, "{n:>7}  {}  {:<width$}  {severity}{more}", code(k), k.name());
    }
    let _ = writeln!(out, "{}", super::summary_line(r));
    out
}
