//! The text report: compiler-style, `path:line: error[kind]: message`, the source line under it,
//! and a summary line.

use super::Report;
use crate::finding::{Finding, Severity};
use crate::source::LineIndex;
use std::borrow::Cow;
use std::fmt::Write;

#[derive(Clone, Copy, Debug, Default)]
pub struct TextOptions {
    /// ANSI colours.
    pub color: bool,
    /// Only the summary line and errors (no warnings, no source lines).
    pub quiet: bool,
}

/// Longest piece of a source line shown under a finding.
const SHOW: usize = 160;

pub fn text(r: &Report, opt: TextOptions) -> String {
    let mut out = String::new();
    let (red, yellow, bold, dim, reset) = if opt.color {
        ("\x1b[31;1m", "\x1b[33;1m", "\x1b[1m", "\x1b[2m", "\x1b[0m")
    } else {
        ("", "", "", "", "")
    };
    for f in &r.files {
        if let (false, Some((d, why))) = (opt.quiet, &f.stats.dialect) {
            let _ = writeln!(
                out,
                "{bold}{}:{reset} {dim}dialect {} ({}){reset}",
                terminal_safe(&f.path),
                d.as_str(),
                terminal_safe(why)
            );
        }
        if let (false, Some(line)) = (opt.quiet, crate::assume::sentence(&f.assumed)) {
            let _ = writeln!(
                out,
                "{bold}{}:{reset} {dim}{}{reset}",
                terminal_safe(&f.path),
                terminal_safe(&line)
            );
        }
        if !opt.quiet && f.status() == super::Status::NoMotion {
            let _ = writeln!(
                out,
                "{bold}{}:{reset} {dim}no_motion{reset}: {}",
                terminal_safe(&f.path),
                super::NO_MOTION_MESSAGE
            );
        }
        let lines = (!f.findings.is_empty()).then(|| LineIndex::new(&f.source));
        // The characters of the last line shown: findings on one line are consecutive, and a
        // long line with many findings must be decoded once, not once per finding.
        let mut shown_line: (u32, Vec<char>) = (0, Vec::new());
        for x in &f.findings {
            if opt.quiet && x.severity != Severity::Error {
                continue;
            }
            let sev_color = if x.severity == Severity::Error { red } else { yellow };
            let col = if x.col > 0 {
                format!(":{}", x.col)
            } else {
                String::new()
            };
            let _ = writeln!(
                out,
                "{bold}{}:{}{col}:{reset} {sev_color}{}[{}]{reset}{bold}: {}{reset}",
                terminal_safe(&f.path),
                x.line,
                x.severity.name(),
                x.kind,
                terminal_safe(&describe(x))
            );
            if opt.quiet {
                continue;
            }
            if let Some(li) = lines.as_ref().filter(|_| !f.source.is_empty()) {
                if x.line >= 1 && (x.line as usize) <= li.line_count() {
                    if shown_line.0 != x.line {
                        let span = li.line_span(&f.source, x.line);
                        let raw = String::from_utf8_lossy(&f.source[span.range()]);
                        // Tabs as spaces; other control bytes (NUL, ^Z, escape sequences) and bidi
                        // controls never reach the terminal: they show as U+FFFD, one column each
                        // like the caret counts.
                        let chars = raw.chars().map(|c| match c {
                            '\t' => ' ',
                            c if unsafe_char(c) => '\u{FFFD}',
                            c => c,
                        });
                        shown_line = (x.line, chars.collect());
                    }
                    let chars = &shown_line.1;
                    let caret = x.col.saturating_sub(1) as usize;
                    let from = if chars.len() > SHOW && caret > SHOW / 2 {
                        (caret - SHOW / 2).min(chars.len() - SHOW)
                    } else {
                        0
                    };
                    let to = (from + SHOW).min(chars.len());
                    let shown: String = chars[from..to].iter().collect();
                    let more_l = if from > 0 { "…" } else { "" };
                    let more_r = if to < chars.len() { "…" } else { "" };
                    let gutter = format!("{:>5}", x.line);
                    let _ = writeln!(out, "{dim}{gutter} |{reset} {more_l}{shown}{more_r}");
                    if x.col > 0 {
                        let pad = caret - from + more_l.chars().count();
                        let _ = writeln!(out, "{dim}{:>5} |{reset} {}{sev_color}^{reset}", "", " ".repeat(pad));
                    }
                }
            }
        }
    }
    let _ = writeln!(out, "{bold}{}{reset}", summary_line(r));
    out
}

/// The last line of the text report, without colour: `checked N files: …`.
pub fn summary_line(r: &Report) -> String {
    let s = r.summary();
    let no_motion = match s.no_motion {
        0 => String::new(),
        n => format!(", {n} with no motion"),
    };
    let suppressed = match s.suppressed {
        0 => String::new(),
        n => format!(", {n} suppressed"),
    };
    format!(
        "checked {} file{}: {} clean{no_motion}, {} with findings ({} error{}, {} warning{}{suppressed})",
        s.files,
        plural(s.files),
        s.clean,
        s.with_findings,
        s.errors,
        plural(s.errors),
        s.warnings,
        plural(s.warnings)
    )
}

/// Unicode's bidirectional formatting characters: they reorder what a terminal shows (a file
/// named `a\u{202e}cn.exe` shows as `aexe.nc`).
fn is_bidi_control(c: char) -> bool {
    matches!(c, '\u{061c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// A character a terminal must not be handed raw: a control or a bidirectional control.
fn unsafe_char(c: char) -> bool {
    c.is_control() || is_bidi_control(c)
}

/// Text from outside (a file name, a message quoting a file) made safe to print on a terminal:
/// control characters (ESC, newline, CR, DEL, C1) and bidirectional controls are written as
/// escapes (`\x1b`, `\n`, `\u{202e}`); everything else, backslashes included, is unchanged.
pub fn terminal_safe(s: &str) -> Cow<'_, str> {
    if !s.chars().any(unsafe_char) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c {
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if c.is_ascii_control() => {
                let _ = write!(out, "\\x{:02x}", c as u32);
            }
            c if unsafe_char(c) => {
                let _ = write!(out, "\\u{{{:x}}}", c as u32);
            }
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// One finding as the text report's first line writes it after the path and line:
/// `error[kind]: message (depth …, at … s, …)`, safe for a terminal (`latheguard follow`).
pub fn finding_text(x: &Finding) -> String {
    format!("{}[{}]: {}", x.severity.name(), x.kind, terminal_safe(&describe(x)))
}

/// The message with the motion facts a machinist looks for.
fn describe(x: &Finding) -> String {
    with_facts(x.message.clone(), x, true, true)
}

/// `message (depth …, at … s[, X… Z…], until line …[, N…])`: the motion facts of a finding after
/// its message, as every reporter that writes one line per finding shows them.
pub(crate) fn with_facts(mut s: String, x: &Finding, point: bool, n: bool) -> String {
    let mut facts = Vec::new();
    if let Some(d) = x.depth_mm {
        // Three decimals; six when three would show a contact as 0.000 mm.
        let shown = if d != 0.0 && d.abs() < 0.0005 {
            format!("{d:.6}")
        } else {
            format!("{d:.3}")
        };
        facts.push(format!("depth {shown} mm"));
    }
    if let Some(d) = x.moved_mm {
        facts.push(format!("moved {d:.3} mm"));
    }
    if let Some(t) = x.time_s {
        facts.push(format!("at {t:.3} s"));
    }
    if let (true, Some(px), Some(pz)) = (point, x.x, x.z) {
        facts.push(format!("X{} Z{}", fmt_num(px), fmt_num(pz)));
    }
    if x.end_line != x.line {
        facts.push(format!("until line {}", x.end_line));
    }
    if let Some(p) = x.profile_line {
        facts.push(format!("profile line {p}"));
    }
    if let Some(o) = x.operation {
        facts.push(format!("operation {o}"));
    }
    if let (true, Some(nn)) = (n, x.n) {
        facts.push(format!("N{nn}"));
    }
    if let Some(p) = &x.follow_on {
        facts.push(p.describe());
    }
    if let Some(p) = &x.picture {
        facts.push(format!("picture {p}"));
    }
    if x.repeats > 1 {
        facts.push(match x.time_s {
            Some(_) => format!("{} times: on every pass of a loop", x.repeats),
            None => format!("{} times in this file, the first here", x.repeats),
        });
    }
    if !facts.is_empty() {
        let _ = write!(s, " ({})", facts.join(", "));
    }
    s
}

/// A length in mm for people: up to three decimals, no trailing zeros (shared with the pictures).
pub(crate) fn fmt_num(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}
