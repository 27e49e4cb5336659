//! The gate: which findings a run reports, which it sets aside, and which fail it.
//!
//! After a program is checked, its findings pass through here (the command's job; the library does
//! no I/O, so this takes the program's bytes and the options as values):
//!
//! 1. **Select and ignore** (`--select`, `--ignore`, as ruff does it): kinds named by name
//!    (`rapid_into_stock`) or stable code (`LG02`). A finding of a kind not selected, or ignored,
//!    is dropped — it is not reported at all.
//! 2. **In-file suppressions**: a comment in the program that names the kinds it accepts and why,
//!    `(latheguard: allow rapid_into_stock -- the bar is pre-turned to 40 here)`, for the line it
//!    is on (or, on a line of comments only, for the next line with words), or
//!    `(latheguard: allow-file near_miss -- …)` for the whole file. A suppressed finding is kept
//!    apart with its reason: reports list it as suppressed (JSON, SARIF), and it never fails the
//!    gate. A suppression without a reason or with an unknown kind suppresses nothing and is a
//!    `program` warning at its line, so a typo cannot silently hide a crash.
//! 3. **Repeats collapsed**: findings that say the same thing again — a block in a loop that
//!    crashes on every pass (same line, kind, parts and message), or the same reading problem on
//!    many lines (same kind and message, no motion data) — become one finding with a count
//!    ([`Finding::repeats`]) at the first place.
//! 4. **Fail on** (`--fail-on error|warning`): which severity fails the run.

use crate::finding::{code, Finding, Kind, Severity};
use std::collections::HashMap;

/// `--select` / `--ignore`: which kinds are reported.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Rules {
    /// Only these kinds (`None`: every kind).
    pub select: Option<Vec<Kind>>,
    /// Never these kinds (wins over `select`).
    pub ignore: Vec<Kind>,
    /// Do not report suppressions that suppress nothing (`unused-suppressions = false`).
    pub quiet_unused: bool,
}

impl Rules {
    pub fn reports(&self, kind: Kind) -> bool {
        self.select.as_ref().map_or(true, |s| s.contains(&kind)) && !self.ignore.contains(&kind)
    }

    /// Resolve layers of selection, lowest first, as ruff does: a layer's `select` starts over
    /// from its kinds (dropping what the layers below selected, extended and ignored), its
    /// `extend_select` adds kinds, its `ignore` removes kinds (it wins over its own layer's
    /// `select` and `extend_select`). No `select` in any layer: every kind.
    pub fn resolve<'a>(layers: impl IntoIterator<Item = &'a Selection>) -> Rules {
        let mut set: Option<Vec<Kind>> = None;
        let mut removed: Vec<Kind> = Vec::new();
        for l in layers {
            if let Some(s) = &l.select {
                set = Some(s.clone());
                removed.clear();
            }
            for k in &l.extend_select {
                removed.retain(|r| r != k);
                if let Some(set) = &mut set {
                    if !set.contains(k) {
                        set.push(*k);
                    }
                }
            }
            for k in &l.ignore {
                if !removed.contains(k) {
                    removed.push(*k);
                }
            }
        }
        let select = set.map(|s| s.into_iter().filter(|k| !removed.contains(k)).collect());
        Rules {
            select,
            ignore: removed,
            quiet_unused: false,
        }
    }
}

/// One layer of kind selection (`latheguard.toml` or the command line).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Selection {
    pub select: Option<Vec<Kind>>,
    pub extend_select: Vec<Kind>,
    pub ignore: Vec<Kind>,
}

/// The least severity that fails a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FailOn {
    /// Errors fail the run (the default).
    #[default]
    Error,
    /// Errors and warnings fail the run.
    Warning,
}

impl FailOn {
    pub fn fails(self, s: Severity) -> bool {
        match self {
            FailOn::Error => s == Severity::Error,
            FailOn::Warning => true,
        }
    }
}

/// A kind from its name (`collision`) or its code (`LG01`, any case).
pub fn kind_by_name_or_code(s: &str) -> Option<Kind> {
    let s = s.trim();
    Kind::from_name(&s.to_ascii_lowercase())
        .or_else(|| Kind::ALL.into_iter().find(|&k| code(k).eq_ignore_ascii_case(s)))
}

/// A finding set aside by a suppression comment, with that comment's reason and line.
#[derive(Clone, Debug, PartialEq)]
pub struct Suppressed {
    pub finding: Finding,
    pub reason: String,
    /// The line of the suppression comment.
    pub at: u32,
}

/// The suppression comments of one program.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Suppressions {
    /// (the line it covers, kinds, reason, line of the comment).
    lines: Vec<(u32, Vec<Kind>, String, u32)>,
    /// (kinds, reason, line of the comment) for the whole file.
    file: Vec<(Vec<Kind>, String, u32)>,
}

/// The marker that starts a suppression inside a comment.
const MARK: &str = "latheguard:";

impl Suppressions {
    /// Read the suppression comments of a program (`( … )` or `; …`), with a `program` warning for
    /// each one that cannot be used. Lines are physical, 1-based, as findings count them; lines
    /// that are not UTF-8 are skipped (the reader reports them).
    pub fn read(src: &[u8]) -> (Suppressions, Vec<Finding>) {
        let mut out = Suppressions::default();
        let mut problems = Vec::new();
        // Suppressions on comment-only lines, waiting for the next line with words.
        let mut waiting: Vec<(Vec<Kind>, String, u32)> = Vec::new();
        let text = String::from_utf8_lossy(src);
        for (i, line) in text.split('\n').enumerate() {
            let line_no = (i + 1) as u32;
            let (comments, words) = split_comments(line);
            if words && !waiting.is_empty() {
                for (kinds, reason, at) in waiting.drain(..) {
                    out.lines.push((line_no, kinds, reason, at));
                }
            }
            for c in comments {
                let Some(pos) = c.find(MARK) else { continue };
                let body = c[pos + MARK.len()..].trim();
                let (file_wide, rest) = if let Some(r) = body.strip_prefix("allow-file") {
                    (true, r)
                } else if let Some(r) = body.strip_prefix("allow") {
                    (false, r)
                } else {
                    // Another latheguard comment (the test cases' options): not ours.
                    continue;
                };
                match parse_allow(rest) {
                    Ok((kinds, reason)) => {
                        if file_wide {
                            out.file.push((kinds, reason, line_no));
                        } else if words {
                            out.lines.push((line_no, kinds, reason, line_no));
                        } else {
                            waiting.push((kinds, reason, line_no));
                        }
                    }
                    Err(why) => problems.push(Finding::at(
                        Kind::Program,
                        Severity::Warning,
                        line_no,
                        0,
                        format!("this suppression suppresses nothing: {why}"),
                    )),
                }
            }
        }
        (out, problems)
    }

    /// The suppression that covers `f`, if one does: a line one (`Ok(index)`) before a
    /// file-wide one (`Err(index)`).
    fn covering(&self, f: &Finding) -> Option<Result<usize, usize>> {
        self.lines
            .iter()
            .position(|(line, kinds, _, _)| *line == f.line && kinds.contains(&f.kind))
            .map(Ok)
            .or_else(|| {
                self.file
                    .iter()
                    .position(|(kinds, _, _)| kinds.contains(&f.kind))
                    .map(Err)
            })
    }

    /// The reason and comment line of a suppression found by [`Suppressions::covering`].
    fn reason(&self, which: Result<usize, usize>) -> (&str, u32) {
        match which {
            Ok(i) => (self.lines[i].2.as_str(), self.lines[i].3),
            Err(i) => (self.file[i].1.as_str(), self.file[i].2),
        }
    }

    /// A `program` warning for each kind of each suppression that covered no finding in `used`
    /// ((suppression, kind) pairs), at the suppression's line, in line order.
    fn unused(&self, used: &[(Result<usize, usize>, Kind)]) -> Vec<Finding> {
        let mut out = Vec::new();
        for (i, (line, kinds, _, at)) in self.lines.iter().enumerate() {
            for &k in kinds {
                if !used.contains(&(Ok(i), k)) {
                    let place = if line == at {
                        "on this line".to_string()
                    } else {
                        format!("on line {line}, the line it covers")
                    };
                    out.push(unused_warning(*at, k, &place));
                }
            }
        }
        for (i, (kinds, _, at)) in self.file.iter().enumerate() {
            for &k in kinds {
                if !used.contains(&(Err(i), k)) {
                    out.push(unused_warning(*at, k, "in this file"));
                }
            }
        }
        out.sort_by_key(|f| f.line);
        out
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty() && self.file.is_empty()
    }
}

fn unused_warning(line: u32, k: Kind, place: &str) -> Finding {
    Finding::at(
        Kind::Program,
        Severity::Warning,
        line,
        0,
        format!("unused suppression: no {} finding {place}", k.name()),
    )
}

/// The comments of one line (their text, without `(`, `)` or `;`) and whether anything but
/// comments and blanks is on it.
fn split_comments(line: &str) -> (Vec<&str>, bool) {
    let mut comments = Vec::new();
    let mut words = false;
    let mut rest = line;
    loop {
        let Some(i) = rest.find(['(', ';']) else {
            words |= !rest.trim().is_empty();
            break;
        };
        words |= !rest[..i].trim().is_empty();
        if rest.as_bytes()[i] == b';' {
            comments.push(&rest[i + 1..]);
            break;
        }
        match rest[i + 1..].find(')') {
            Some(j) => {
                comments.push(&rest[i + 1..i + 1 + j]);
                rest = &rest[i + 2 + j..];
            }
            None => {
                comments.push(&rest[i + 1..]);
                break;
            }
        }
    }
    (comments, words)
}

/// ` KIND[, KIND…] -- REASON` → the kinds and the reason.
fn parse_allow(rest: &str) -> Result<(Vec<Kind>, String), String> {
    let Some((kinds, reason)) = rest.split_once("--") else {
        return Err("write the kinds it allows, then `--` and the reason (`allow near_miss -- why`)".into());
    };
    let reason = reason.trim();
    if reason.is_empty() {
        return Err("it gives no reason after `--`".into());
    }
    let mut out = Vec::new();
    for name in kinds.split([',', ' ', '\t']).filter(|s| !s.is_empty()) {
        match kind_by_name_or_code(name) {
            Some(k) => out.push(k),
            None => return Err(format!("`{name}` is not a finding kind or code")),
        }
    }
    if out.is_empty() {
        return Err("it names no finding kind".into());
    }
    Ok((out, reason.to_string()))
}

/// The findings of one file after the gate: those reported, and those suppressed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Gated {
    pub findings: Vec<Finding>,
    pub suppressed: Vec<Suppressed>,
}

/// Pass a file's findings (in report order) through the gate: drop the kinds not reported, set
/// aside the suppressed ones, add the warnings about unusable suppressions and (unless
/// [`Rules::quiet_unused`]) about suppressions that cover no finding, collapse repeats. The order
/// of what remains is kept.
///
/// A suppression is used when it covers a finding of the check, reported or not: one that
/// covers a finding of a kind not selected is not called unused (it is needed again when the
/// kind is).
pub fn apply(findings: Vec<Finding>, rules: &Rules, sup: &Suppressions, problems: Vec<Finding>) -> Gated {
    let mut out = Gated::default();
    let mut kept = Vec::with_capacity(findings.len() + problems.len());
    let mut used = Vec::new();
    let mut resort = !problems.is_empty();
    for f in findings.into_iter().chain(problems) {
        let cover = sup.covering(&f);
        if let Some(c) = cover {
            if !used.contains(&(c, f.kind)) {
                used.push((c, f.kind));
            }
        }
        if !rules.reports(f.kind) {
            continue;
        }
        match cover {
            Some(c) => {
                let (reason, at) = sup.reason(c);
                out.suppressed.push(Suppressed {
                    reason: reason.to_string(),
                    at,
                    finding: f,
                })
            }
            None => kept.push(f),
        }
    }
    if !rules.quiet_unused && rules.reports(Kind::Program) {
        let unused = sup.unused(&used);
        resort |= !unused.is_empty();
        kept.extend(unused);
    }
    if resort {
        crate::finding::sort_findings(&mut kept);
    }
    out.findings = collapse(kept);
    out
}

/// Merge findings that repeat one another into the first of them, counting them in
/// [`Finding::repeats`]: the same line, kind, severity, parts and message (a block that crashes
/// on every pass of a loop), or, for findings with no motion data (reading and interpreting
/// problems), the same kind, severity and message on any line. Never an error into a warning (a
/// crash into a follow-on or a graze on the same line): that would hide the crash.
pub fn collapse(findings: Vec<Finding>) -> Vec<Finding> {
    /// Line (findings with motion data), kind, is an error, parts, message.
    type Repeat = (Option<u32>, Kind, bool, Vec<String>, String);
    let mut out: Vec<Finding> = Vec::with_capacity(findings.len());
    let mut seen: HashMap<Repeat, usize> = HashMap::new();
    for f in findings {
        let key = (
            f.time_s.is_some().then_some(f.line),
            f.kind,
            f.severity == Severity::Error,
            f.objects.clone(),
            f.message.clone(),
        );
        match seen.get(&key) {
            Some(&i) => {
                let first = &mut out[i];
                first.repeats = first.repeats.saturating_add(f.repeats.max(1));
            }
            None => {
                seen.insert(key, out.len());
                out.push(f);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unsupported(line: u32, msg: &str) -> Finding {
        Finding::at(Kind::Unsupported, Severity::Warning, line, 1, msg)
    }

    fn crash(line: u32, t: f64) -> Finding {
        let mut f = Finding::at(
            Kind::Collision,
            Severity::Error,
            line,
            0,
            "the T01 holder hits the chuck",
        );
        f.time_s = Some(t);
        f.objects = vec!["T01 holder".into(), "chuck".into()];
        f
    }

    #[test]
    fn kinds_are_named_by_name_or_code_in_any_case() {
        assert_eq!(kind_by_name_or_code("LG02"), Some(Kind::RapidIntoStock));
        assert_eq!(kind_by_name_or_code("lg02"), Some(Kind::RapidIntoStock));
        assert_eq!(kind_by_name_or_code("near_miss"), Some(Kind::NearMiss));
        assert_eq!(kind_by_name_or_code("Near_Miss"), Some(Kind::NearMiss));
        assert_eq!(kind_by_name_or_code("LG99"), None);
        assert_eq!(kind_by_name_or_code("crash"), None);
    }

    #[test]
    fn select_and_ignore_drop_findings_and_ignore_wins() {
        let rules = Rules {
            select: Some(vec![Kind::Collision, Kind::Unsupported]),
            ignore: vec![Kind::Unsupported],
            ..Rules::default()
        };
        let g = apply(
            vec![unsupported(1, "G41"), crash(2, 1.0), Finding::program(3, 0, "no feed")],
            &rules,
            &Suppressions::default(),
            Vec::new(),
        );
        assert_eq!(g.findings.len(), 1);
        assert_eq!(g.findings[0].kind, Kind::Collision);
    }

    #[test]
    fn a_suppression_covers_its_line_or_after_a_comment_line_the_next_line_with_words() {
        let src = b"G0 X10 Z5 (latheguard: allow collision -- fixture clears it)\n(latheguard: allow LG12, program -- known)\n\nG41 X3\nG1 X4\n";
        let (sup, problems) = Suppressions::read(src);
        assert!(problems.is_empty(), "{problems:?}");
        let g = apply(
            vec![
                crash(1, 0.5),
                unsupported(4, "G41"),
                unsupported(5, "other"),
                crash(5, 2.0),
            ],
            // `program` covers nothing on line 4: not said here.
            &Rules {
                quiet_unused: true,
                ..Rules::default()
            },
            &sup,
            problems,
        );
        let kept: Vec<u32> = g.findings.iter().map(|f| f.line).collect();
        assert_eq!(kept, [5, 5]);
        let set_aside: Vec<(u32, &str, u32)> = g
            .suppressed
            .iter()
            .map(|s| (s.finding.line, s.reason.as_str(), s.at))
            .collect();
        assert_eq!(set_aside, [(1, "fixture clears it", 1), (4, "known", 2)]);
    }

    #[test]
    fn a_file_wide_suppression_covers_every_line_of_its_kinds_only() {
        let (sup, problems) = Suppressions::read(b"%\n; latheguard: allow-file unsupported -- old post\nG1 X1\n");
        assert!(problems.is_empty());
        let g = apply(
            vec![unsupported(3, "a"), unsupported(9, "b"), crash(9, 1.0)],
            &Rules::default(),
            &sup,
            problems,
        );
        assert_eq!(g.suppressed.len(), 2);
        assert_eq!(g.findings.len(), 1);
    }

    #[test]
    fn a_suppression_without_reason_or_with_an_unknown_kind_suppresses_nothing_and_says_so() {
        let src = b"G0 X1 (latheguard: allow collision)\nG0 X2 (latheguard: allow colision -- typo)\nG0 X3 (latheguard: allow collision --  )\n(latheguard: machine=x mode=exact)\n";
        let (sup, problems) = Suppressions::read(src);
        assert!(sup.is_empty());
        let lines: Vec<u32> = problems.iter().map(|p| p.line).collect();
        assert_eq!(lines, [1, 2, 3]);
        assert!(problems[1].message.contains("`colision` is not a finding kind"));
        assert!(problems.iter().all(|p| p.severity == Severity::Warning));
        let g = apply(vec![crash(1, 0.1)], &Rules::default(), &sup, problems);
        assert_eq!(g.findings.len(), 4, "the crash stays, with the three warnings");
        assert!(g.findings.iter().any(|f| f.kind == Kind::Collision && f.line == 1));
    }

    #[test]
    fn repeats_of_a_loop_and_of_a_reading_problem_collapse_with_a_count() {
        let g = collapse(vec![
            unsupported(2, "G41: not modelled"),
            crash(3, 1.0),
            crash(3, 2.0),
            crash(3, 3.0),
            unsupported(7, "G41: not modelled"),
            crash(8, 4.0),
            unsupported(9, "G42: not modelled"),
        ]);
        let got: Vec<(u32, Kind, u32)> = g.iter().map(|f| (f.line, f.kind, f.repeats)).collect();
        assert_eq!(
            got,
            [
                (2, Kind::Unsupported, 2),
                (3, Kind::Collision, 3),
                (8, Kind::Collision, 1),
                (9, Kind::Unsupported, 1)
            ]
        );
    }

    #[test]
    fn layers_of_selection_resolve_as_ruff_does() {
        use Kind::*;
        let file = Selection {
            select: Some(vec![Collision, NearMiss, Unsupported]),
            extend_select: vec![Program],
            ignore: vec![NearMiss],
        };
        let r = Rules::resolve([&file]);
        assert_eq!(r.select, Some(vec![Collision, Unsupported, Program]));
        // The command line's select starts over: the file's ignore and extend-select are gone.
        let cli = Selection {
            select: Some(vec![NearMiss]),
            ..Selection::default()
        };
        assert_eq!(Rules::resolve([&file, &cli]).select, Some(vec![NearMiss]));
        // The command line's ignore adds to the file's; its extend-select takes back an ignore.
        let cli = Selection {
            extend_select: vec![NearMiss],
            ignore: vec![Unsupported],
            ..Selection::default()
        };
        let r = Rules::resolve([&file, &cli]);
        assert!(r.reports(NearMiss) && r.reports(Collision) && !r.reports(Unsupported));
        // No select anywhere: every kind but the ignored.
        let r = Rules::resolve([&Selection {
            ignore: vec![Syntax],
            ..Selection::default()
        }]);
        assert_eq!(r.select, None);
        assert!(!r.reports(Syntax) && r.reports(Collision));
    }

    #[test]
    fn a_suppression_that_covers_nothing_is_a_warning_at_its_line_unless_quiet() {
        let src = b"G0 X1 (latheguard: allow collision, near_miss -- ok)\n(latheguard: allow unsupported -- old)\nG1 X2\n; latheguard: allow-file syntax -- post\n";
        let (sup, problems) = Suppressions::read(src);
        let g = apply(vec![crash(1, 0.1)], &Rules::default(), &sup, problems.clone());
        let got: Vec<(u32, Kind, &str)> = g
            .findings
            .iter()
            .map(|f| (f.line, f.kind, f.message.as_str()))
            .collect();
        assert_eq!(
            got,
            [
                (
                    1,
                    Kind::Program,
                    "unused suppression: no near_miss finding on this line"
                ),
                (
                    2,
                    Kind::Program,
                    "unused suppression: no unsupported finding on line 3, the line it covers"
                ),
                (4, Kind::Program, "unused suppression: no syntax finding in this file"),
            ]
        );
        assert_eq!(g.suppressed.len(), 1);
        // A suppression of a finding not selected is not unused.
        let only_program = Rules {
            select: Some(vec![Kind::Program]),
            ..Rules::default()
        };
        let g = apply(vec![crash(1, 0.1)], &only_program, &sup, problems.clone());
        assert_eq!(g.findings.len(), 3);
        let quiet = Rules {
            quiet_unused: true,
            ..Rules::default()
        };
        assert!(apply(vec![crash(1, 0.1)], &quiet, &sup, problems).findings.is_empty());
    }

    #[test]
    fn fail_on_warning_fails_on_both_severities() {
        assert!(FailOn::Error.fails(Severity::Error));
        assert!(!FailOn::Error.fails(Severity::Warning));
        assert!(FailOn::Warning.fails(Severity::Warning));
    }
}
