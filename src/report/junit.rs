//! JUnit XML: one test suite for the batch, one test case per program.
//!
//! A program with at least one error finding is a failed test case. JUnit allows one `<failure>`
//! per test case (CI systems show only the first), so the failure's message names the first error
//! and its count, its `type` is that error's kind, and its body lists every finding of the file
//! as `line N: error[kind]: message (facts, the programmed point, …)` with its source line under
//! it (`    | N70 Z-120.`). A program with warnings only passes, with its
//! warnings in `<system-out>`. A program whose moves never reach the machine (status `no_motion`)
//! is a skipped test case. Test case names are the program paths; the class name is the
//! program's folder.

use super::{FileReport, Report};
use crate::finding::{Finding, Severity};
use crate::pipeline::{Mode, Settings};
use quick_junit::{NonSuccessKind, Property, TestCase, TestCaseStatus, TestSuite};
use std::time::Duration;

#[derive(Clone, Copy, Debug)]
pub struct JunitOptions {
    /// Write `time` attributes (run times vary between runs).
    pub timing: bool,
}

impl Default for JunitOptions {
    fn default() -> JunitOptions {
        JunitOptions { timing: true }
    }
}

/// One finding as a line of the failure's body: where, what, the facts (the programmed point
/// included), and the source line under it.
fn line(f: &Finding, src: Option<&str>) -> String {
    let head = format!("line {}: {}[{}]: {}", f.line, f.severity.name(), f.kind, f.message);
    let mut s = super::text::with_facts(head, f, true, true);
    if let Some(text) = src.map(str::trim).filter(|t| !t.is_empty()) {
        s.push_str("\n    | ");
        s.push_str(&super::terminal_safe(text));
    }
    s
}

fn settings_properties(machine: &str, s: &Settings) -> Vec<Property> {
    vec![
        Property::new("machine", machine),
        Property::new(
            "mode",
            match s.mode {
                Mode::Step => "step",
                Mode::Exact => "exact",
            },
        ),
        Property::new("dt_ms", s.dt_ms.to_string()),
        Property::new("tolerance_mm", s.tolerance_mm.to_string()),
        Property::new("clearance_mm", s.clearance_mm.to_string()),
    ]
}

fn folder(path: &str) -> String {
    match path.rfind(['/', '\\']) {
        Some(i) if i > 0 => path[..i].to_string(),
        _ => ".".to_string(),
    }
}

fn case(r: &Report, f: &FileReport, opt: JunitOptions) -> TestCase {
    let errors: Vec<&Finding> = f.findings.iter().filter(|x| x.severity == Severity::Error).collect();
    let lines = (!f.source.is_empty()).then(|| crate::source::LineIndex::new(&f.source));
    let source_line = |n: u32| {
        let li = lines.as_ref()?;
        (n >= 1 && n as usize <= li.line_count())
            .then(|| String::from_utf8_lossy(&f.source[li.line_span(&f.source, n).range()]).into_owned())
    };
    let listing = f
        .findings
        .iter()
        .map(|x| line(x, source_line(x.line).as_deref()))
        .collect::<Vec<_>>()
        .join("\n");
    let status = match errors.first() {
        None if f.status() == super::Status::NoMotion => {
            let mut st = TestCaseStatus::skipped();
            st.set_message(format!("no_motion: {}", super::NO_MOTION_MESSAGE));
            st
        }
        None => TestCaseStatus::success(),
        Some(first) => {
            let mut st = TestCaseStatus::non_success(NonSuccessKind::Failure);
            let more = match errors.len() {
                1 => String::new(),
                n => format!(" (and {} more error{})", n - 1, if n == 2 { "" } else { "s" }),
            };
            st.set_message(format!("line {}: {}{more}", first.line, first.message))
                .set_type(first.kind.name())
                .set_description(listing.clone());
            st
        }
    };
    let mut tc = TestCase::new(f.path.as_str(), status);
    tc.set_classname(folder(&f.path));
    if opt.timing {
        tc.set_time(Duration::from_secs_f64((f.stats.elapsed_ms / 1000.0).max(0.0)));
    }
    if errors.is_empty() && !f.findings.is_empty() {
        tc.set_system_out(listing);
    }
    if f.machine.is_some() || f.settings.is_some() {
        let machine = f.machine.as_deref().unwrap_or(&r.machine);
        tc.add_properties(settings_properties(machine, f.settings.as_ref().unwrap_or(&r.settings)));
    }
    tc
}

/// The whole batch as a JUnit XML document.
pub fn junit(r: &Report, opt: JunitOptions) -> String {
    let mut suite = TestSuite::new("latheguard check");
    suite.add_properties(settings_properties(&r.machine, &r.settings));
    let mut total = 0.0;
    for f in &r.files {
        total += f.stats.elapsed_ms;
        suite.add_test_case(case(r, f, opt));
    }
    let mut report = quick_junit::Report::new("latheguard");
    if opt.timing {
        let t = Duration::from_secs_f64((total / 1000.0).max(0.0));
        suite.set_time(t);
        report.set_time(t);
    }
    report.add_test_suite(suite);
    let mut s = report
        .to_string()
        .unwrap_or_else(|e| format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- {e} -->\n"));
    if !s.ends_with('\n') {
        s.push('\n');
    }
    s
}
