//! Findings: what latheguard reports about a program, one value per problem.
//!
//! Every stage (reader, interpreter, checker) produces [`Finding`]s; the reporters turn them into
//! text, JSON, JUnit or SARIF. A finding always names a physical 1-based source line.

use serde::Serialize;

/// What kind of problem a finding is. The names are a stable contract (JSON `kind`, SARIF rule ids,
/// `--explain`): never rename one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    Collision,
    RapidIntoStock,
    RapidScrape,
    SpindleStopped,
    NearMiss,
    Overtravel,
    Syntax,
    Program,
    Unsupported,
}

impl Kind {
    pub const ALL: [Kind; 9] = [
        Kind::Collision,
        Kind::RapidIntoStock,
        Kind::RapidScrape,
        Kind::SpindleStopped,
        Kind::NearMiss,
        Kind::Overtravel,
        Kind::Syntax,
        Kind::Program,
        Kind::Unsupported,
    ];

    /// The stable name used in reports (`rapid_into_stock`, …).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Collision => "collision",
            Kind::RapidIntoStock => "rapid_into_stock",
            Kind::RapidScrape => "rapid_scrape",
            Kind::SpindleStopped => "spindle_stopped",
            Kind::NearMiss => "near_miss",
            Kind::Overtravel => "overtravel",
            Kind::Syntax => "syntax",
            Kind::Program => "program",
            Kind::Unsupported => "unsupported",
        }
    }

    pub fn from_name(name: &str) -> Option<Kind> {
        Kind::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    Error,
    Warning,
}

impl Severity {
    pub fn name(self) -> &'static str {
        match self {
            Severity::Error => "error",
            Severity::Warning => "warning",
        }
    }
}

/// One problem at one place of one program.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    /// Physical 1-based line where the problem begins.
    pub line: u32,
    /// Physical 1-based line where a collision episode ends (same as `line` otherwise).
    pub end_line: u32,
    /// 1-based column (in characters) on `line`, 0 when the finding is about the whole line.
    #[serde(skip)]
    pub col: u32,
    /// The block's N number, when it has one.
    pub n: Option<u64>,
    pub kind: Kind,
    pub severity: Severity,
    /// The parts involved, for collisions (`["T03 holder", "chuck"]`).
    pub objects: Vec<String>,
    /// The same parts in a machinist's words, in the order of `objects`, where the ids are not
    /// words (the turn-mill path: `t9_holder` is "T09 holder"); empty where `objects` already are
    /// (the working plane's "T03 holder", "chuck"). Read it through [`Finding::parts_in_words`].
    #[serde(skip)]
    pub words: Vec<String>,
    /// Machine time at first contact, seconds from program start.
    pub time_s: Option<f64>,
    /// Largest penetration depth of the episode, mm.
    pub depth_mm: Option<f64>,
    /// How far a part moved that should have stood still, mm: a sub-spindle clamped on a bar
    /// the main chuck still holds (no depth: nothing went into anything).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub moved_mm: Option<f64>,
    /// Programmed point at first contact, in program coordinates (X as the program writes it).
    pub x: Option<f64>,
    pub z: Option<f64>,
    pub message: String,
    /// A contact that began while an earlier crash was still in progress (one part already
    /// inside another): it exists because of that crash, and is reported as its follow-on, a
    /// warning, rather than as a new crash.
    pub follow_on: Option<FollowOn>,
    /// For a move a canned cycle made along its profile: the profile block's line (the finding
    /// itself is at the cycle's line, where the control runs the passes).
    pub profile_line: Option<u32>,
    /// Machine time of the last contact of the episode.
    #[serde(skip)]
    pub end_time_s: Option<f64>,
    /// How many identical findings this one stands for (1; more when [`crate::gate::collapse`]
    /// merged repeats of a loop or of one reading problem on many lines into it).
    #[serde(skip)]
    pub repeats: u32,
    /// Where the picture of this finding was written (`--svg`), as the report shows the path.
    #[serde(skip)]
    pub picture: Option<String>,
    /// The scene at first contact, when the check was asked for pictures.
    #[serde(skip)]
    pub snapshot: Option<Box<crate::scene::Snapshot>>,
    /// The scene at first contact in 3D, for a finding of the 3D path when the check was asked
    /// for pictures (`--svg`: three views instead of the working plane; `--glb`).
    #[serde(skip)]
    pub snapshot3: Option<Box<crate::report::scene3::Snapshot3>>,
    /// With a job that has operations (`[[operations]]`): the operation a finding of the check
    /// began in, from 1 (the job's start) to the last (docs/job.md, "Operations"); `None`
    /// without operations, and for the reader's and the interpreter's findings.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub operation: Option<u32>,
}

/// The crash a follow-on contact comes from: its line, parts and time of first contact.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FollowOn {
    pub line: u32,
    /// The crash's parts as the machine file names them (the JSON and SARIF `objects`).
    pub objects: Vec<String>,
    pub time_s: f64,
    /// The crash's parts in the words its own finding uses ([`Finding::parts_in_words`]).
    #[serde(skip)]
    pub words: Vec<String>,
}

impl FollowOn {
    /// What the text report and the pictures say of it, naming the crash's parts in the words
    /// its own finding uses: "follow-on of the crash at line 33 between the T09 holder and the
    /// part in the sub chuck".
    pub fn describe(&self) -> String {
        let parts = if self.words.is_empty() {
            &self.objects
        } else {
            &self.words
        };
        match parts.as_slice() {
            [] => format!("follow-on of the crash at line {}", self.line),
            [a, b] => format!(
                "follow-on of the crash at line {} between the {a} and the {b}",
                self.line
            ),
            more => format!(
                "follow-on of the crash at line {} of the {}",
                self.line,
                more.join(", the ")
            ),
        }
    }
}

impl Finding {
    /// A finding about a place in the source with no motion data.
    pub fn at(kind: Kind, severity: Severity, line: u32, col: u32, message: impl Into<String>) -> Finding {
        Finding {
            line,
            end_line: line,
            col,
            n: None,
            kind,
            severity,
            objects: Vec::new(),
            words: Vec::new(),
            time_s: None,
            depth_mm: None,
            moved_mm: None,
            x: None,
            z: None,
            message: message.into(),
            follow_on: None,
            profile_line: None,
            end_time_s: None,
            repeats: 1,
            picture: None,
            snapshot: None,
            snapshot3: None,
            operation: None,
        }
    }

    pub fn syntax(line: u32, col: u32, message: impl Into<String>) -> Finding {
        Finding::at(Kind::Syntax, Severity::Error, line, col, message)
    }

    pub fn program(line: u32, col: u32, message: impl Into<String>) -> Finding {
        Finding::at(Kind::Program, Severity::Error, line, col, message)
    }

    /// The parts involved in a machinist's words: `words` where the finding has them, else
    /// `objects` (already words on the working plane).
    pub fn parts_in_words(&self) -> &[String] {
        if self.words.len() == self.objects.len() && !self.words.is_empty() {
            &self.words
        } else {
            &self.objects
        }
    }

    /// What a picture's message line adds for a follow-on: "follow-on of the crash at line 33"
    /// when the crash is between the finding's own two parts (always, under the follow-on rule:
    /// the message has just named them, and the line keeps its width), else
    /// [`FollowOn::describe`] with the crash's parts in words.
    pub fn follow_on_note(&self) -> Option<String> {
        let p = self.follow_on.as_ref()?;
        let theirs = if p.words.is_empty() { &p.objects } else { &p.words };
        let mut a: Vec<&String> = theirs.iter().collect();
        let mut b: Vec<&String> = self.parts_in_words().iter().collect();
        a.sort();
        b.sort();
        Some(if a == b && !a.is_empty() {
            format!("follow-on of the crash at line {}", p.line)
        } else {
            p.describe()
        })
    }

    pub fn with_n(mut self, n: Option<u64>) -> Finding {
        self.n = n;
        self
    }
}

/// The most findings a file's report keeps (bounded work and memory on any input, docs/limits.md). Each
/// stage stops storing findings at this many and counts the rest; the report then ends with one
/// `program` finding that says how many were left out ([`LeftOut::finding`]).
pub const MAX_FINDINGS: usize = 10_000;

/// Findings a stage did not keep because it already held [`MAX_FINDINGS`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LeftOut {
    pub count: u64,
    /// The smallest line of a finding left out (meaningless when `count` is 0).
    pub first_line: u32,
}

impl LeftOut {
    pub fn add(&mut self, line: u32, count: u64) {
        if count == 0 {
            return;
        }
        self.first_line = if self.count == 0 {
            line
        } else {
            self.first_line.min(line)
        };
        self.count = self.count.saturating_add(count);
    }

    pub fn merge(&mut self, other: LeftOut) {
        self.add(other.first_line, other.count);
    }

    /// The `program` finding that reports what was left out, placed at the first line left out.
    pub fn finding(&self) -> Option<Finding> {
        (self.count > 0).then(|| {
            let s = if self.count == 1 { "" } else { "s" };
            Finding::program(
                self.first_line,
                0,
                format!(
                    "{} more finding{s} not listed, the first of them on this line: a report keeps at most {MAX_FINDINGS} findings per file",
                    self.count
                ),
            )
        })
    }
}

/// Push `f` unless `list` already holds [`MAX_FINDINGS`]; count it in `left_out` then.
pub fn push_capped(list: &mut Vec<Finding>, left_out: &mut LeftOut, f: Finding) {
    if list.len() >= MAX_FINDINGS {
        left_out.add(f.line, 1);
        return;
    }
    list.push(f);
}

/// Findings in report order: by line, then column, then time to the microsecond the reports
/// print (findings with no time first), then kind and message.
///
/// The time is compared as printed, not by its bits: two contacts that begin in the same printed
/// microsecond (two symmetric parts meeting a chuck at once) are ordered by what they are, not by
/// which one's contact time came out a few ulps earlier — a difference any change to where the
/// search's probes fall can turn round.
pub fn sort_findings(findings: &mut [Finding]) {
    findings.sort_by(|a, b| {
        (a.line, a.col)
            .cmp(&(b.line, b.col))
            .then_with(|| match (a.time_s, b.time_s) {
                (Some(x), Some(y)) => printed_us(x).total_cmp(&printed_us(y)),
                (x, y) => x.is_some().cmp(&y.is_some()),
            })
            .then_with(|| (a.kind, &a.message).cmp(&(b.kind, &b.message)))
    });
}

/// A time in whole microseconds, as the reports print it.
fn printed_us(t: f64) -> f64 {
    (t * 1e6).round()
}

/// A short stable code per kind (for SARIF rule ids and the docs): never reuse one.
pub fn code(kind: Kind) -> &'static str {
    match kind {
        Kind::Collision => "LG01",
        Kind::RapidIntoStock => "LG02",
        Kind::RapidScrape => "LG06",
        Kind::SpindleStopped => "LG03",
        Kind::NearMiss => "LG04",
        Kind::Overtravel => "LG05",
        Kind::Syntax => "LG10",
        Kind::Program => "LG11",
        Kind::Unsupported => "LG12",
    }
}

/// The documentation of a finding kind (Markdown): what it means, why it matters, an example.
pub fn explain(kind: Kind) -> &'static str {
    match kind {
        Kind::Collision => include_str!("../docs/findings/collision.md"),
        Kind::RapidIntoStock => include_str!("../docs/findings/rapid_into_stock.md"),
        Kind::RapidScrape => include_str!("../docs/findings/rapid_scrape.md"),
        Kind::SpindleStopped => include_str!("../docs/findings/spindle_stopped.md"),
        Kind::NearMiss => include_str!("../docs/findings/near_miss.md"),
        Kind::Overtravel => include_str!("../docs/findings/overtravel.md"),
        Kind::Syntax => include_str!("../docs/findings/syntax.md"),
        Kind::Program => include_str!("../docs/findings/program.md"),
        Kind::Unsupported => include_str!("../docs/findings/unsupported.md"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn follow_on(words: &[&str]) -> FollowOn {
        FollowOn {
            line: 33,
            objects: vec!["t9_holder".into(), "part_in_sub_chuck".into()],
            time_s: 1.0,
            words: words.iter().map(|w| w.to_string()).collect(),
        }
    }

    #[test]
    fn a_follow_on_names_its_crash_in_words_and_falls_back_on_the_ids() {
        let p = follow_on(&["T09 holder", "part in the sub chuck"]);
        assert_eq!(
            p.describe(),
            "follow-on of the crash at line 33 between the T09 holder and the part in the sub chuck"
        );
        assert_eq!(
            follow_on(&[]).describe(),
            "follow-on of the crash at line 33 between the t9_holder and the part_in_sub_chuck"
        );
    }

    #[test]
    fn a_picture_note_names_the_parts_only_when_they_are_not_the_findings_own() {
        let mut f = Finding::at(Kind::Collision, Severity::Warning, 34, 0, "the T09 holder hits it");
        f.objects = vec!["part_in_sub_chuck".into(), "t9_holder".into()];
        f.words = vec!["part in the sub chuck".into(), "T09 holder".into()];
        f.follow_on = Some(follow_on(&["T09 holder", "part in the sub chuck"]));
        assert_eq!(f.follow_on_note().as_deref(), Some("follow-on of the crash at line 33"));
        f.words = vec!["stock".into(), "T09 holder".into()];
        assert_eq!(
            f.follow_on_note().as_deref(),
            Some("follow-on of the crash at line 33 between the T09 holder and the part in the sub chuck")
        );
        f.follow_on = None;
        assert_eq!(f.follow_on_note(), None);
    }

    /// Two findings at one line whose times print alike are ordered by what they say, whichever
    /// time's last bits came out earlier; times a printed microsecond apart keep their order.
    #[test]
    fn findings_of_the_same_printed_instant_are_ordered_by_what_they_say() {
        let at = |t: f64, msg: &str| {
            let mut f = Finding::at(Kind::Collision, Severity::Error, 12, 0, msg);
            f.time_s = Some(t);
            f
        };
        let messages = |v: &[Finding]| v.iter().map(|f| f.message.clone()).collect::<Vec<_>>();
        let want = ["the T03 holder hits the chuck", "the T09 holder hits the chuck"];
        for (ta, tb) in [
            (68.012_001_000_1, 68.012_000_999_9),
            (68.012_000_999_9, 68.012_001_000_1),
        ] {
            let mut v = vec![at(tb, want[1]), at(ta, want[0])];
            sort_findings(&mut v);
            assert_eq!(messages(&v), want);
        }
        let mut v = vec![at(68.012_002, want[0]), at(68.012_001, want[1])];
        sort_findings(&mut v);
        assert_eq!(messages(&v), [want[1], want[0]]);
    }
}
