//! `--format github`: GitHub Actions workflow commands, one a line, which the Actions runner turns
//! into annotations on the files of a pull request:
//!
//! ```text
//! ::error file=cell-a/crash_holder.nc,line=10,endLine=11,title=collision (LG01)::the T01 insert hits the chuck (depth 42.000 mm, …)
//! ```
//!
//! Errors are `::error`, warnings `::warning`, a file with no motion a `::notice`; suppressed
//! findings are not annotated. Values are escaped as the runner expects (`%`, CR and LF in the
//! message; also `:` and `,` in properties). The summary line comes last, as a plain line.

use super::{Report, Status};
use crate::finding::{code, Severity};
use std::fmt::Write;

fn escape_data(s: &str) -> String {
    s.replace('%', "%25").replace('\r', "%0D").replace('\n', "%0A")
}

fn escape_property(s: &str) -> String {
    escape_data(s).replace(':', "%3A").replace(',', "%2C")
}

pub fn github(r: &Report) -> String {
    let mut out = String::new();
    for f in &r.files {
        let file = escape_property(&f.path.replace('\\', "/"));
        if f.status() == Status::NoMotion {
            let _ = writeln!(
                out,
                "::notice file={file},title=no_motion::{}",
                escape_data(super::NO_MOTION_MESSAGE)
            );
        }
        for x in &f.findings {
            let level = match x.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
            };
            let mut props = format!("file={file},line={}", x.line.max(1));
            if x.col > 0 {
                let _ = write!(props, ",col={}", x.col);
            }
            if x.end_line > x.line {
                let _ = write!(props, ",endLine={}", x.end_line);
            }
            let title = format!("{} ({})", x.kind.name(), code(x.kind));
            let message = super::text::with_facts(x.message.clone(), x, true, true);
            let _ = writeln!(
                out,
                "::{level} {props},title={}::{}",
                escape_property(&title),
                escape_data(&message)
            );
        }
    }
    let _ = writeln!(out, "{}", super::summary_line(r));
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn workflow_command_values_are_escaped() {
        assert_eq!(super::escape_data("50% done\r\nnext"), "50%25 done%0D%0Anext");
        assert_eq!(super::escape_property("a:b,c%"), "a%3Ab%2Cc%25");
    }
}
