//! Collision episodes: one finding per pair from the sample where contact begins to the last
//! sample in contact.

use crate::finding::{Finding, FollowOn, Kind, Severity, MAX_FINDINGS};
use std::collections::{BTreeMap, BinaryHeap};

/// What is known at one contact sample.
#[derive(Clone, Debug)]
pub struct Contact {
    pub kind: Kind,
    pub objects: [String; 2],
    /// The same parts in a machinist's words, where `objects` are machine-file ids (the
    /// turn-mill path); `None` where `objects` already are words.
    pub words: Option<[String; 2]>,
    pub line: u32,
    pub n: Option<u64>,
    /// The profile block a canned cycle's move follows (0: none).
    pub profile_line: u32,
    pub time: f64,
    /// Programmed point in program coordinates.
    pub x: f64,
    pub z: f64,
    /// Penetration depth (collisions), or the gap (near misses).
    pub depth: Option<f64>,
    pub message: String,
    pub snapshot: Option<Box<crate::scene::Snapshot>>,
    /// The 3D scene at first contact (a finding of the 3D path, with pictures asked for).
    pub snapshot3: Option<Box<crate::report::scene3::Snapshot3>>,
}

struct Open {
    first: Contact,
    end_line: u32,
    max_depth: Option<f64>,
    /// Smallest gap seen, for near misses.
    min_gap: Option<f64>,
    /// Time of the last contact seen.
    end_time: f64,
    /// The job's operation when it began (0: the job has none).
    operation: u32,
}

/// Open episodes by pair key.
pub struct Episodes {
    open: BTreeMap<u64, Open>,
    pub findings: Vec<Finding>,
    /// The lines of the findings emitted so far: the smallest `cap` of them, the largest on top.
    lowest: BinaryHeap<u32>,
    /// How many findings a file's report keeps ([`MAX_FINDINGS`]; smaller in tests).
    pub cap: usize,
    /// The job's operation in progress, from 1, which findings opened now carry (0: the job
    /// has no operations, and findings carry none).
    pub operation: u32,
    /// The latest time a finding emitted so far began at.
    latest: f64,
}

impl Default for Episodes {
    fn default() -> Episodes {
        Episodes {
            open: BTreeMap::new(),
            findings: Vec::new(),
            lowest: BinaryHeap::new(),
            cap: MAX_FINDINGS,
            operation: 0,
            latest: f64::NEG_INFINITY,
        }
    }
}

impl Episodes {
    /// Whether a finding at `line` is certainly left out of the report: `cap` findings at smaller
    /// lines are already made, and the report keeps the first `cap` findings of the file in line
    /// order (`pipeline::check`). Such a finding still counts (the report says how many were
    /// left out and the first line of them), but its facts are never shown.
    pub fn left_out(&self, line: u32) -> bool {
        self.left_out_at(line, f64::NEG_INFINITY)
    }

    /// Whether a finding at `line` that begins at `time` is certainly left out of the report:
    /// as [`Self::left_out`], or on the last line kept when it begins after every finding made so
    /// far (a finding of the same line sorts by its time, so the `cap` made already come first).
    pub fn left_out_at(&self, line: u32, time: f64) -> bool {
        self.lowest.len() >= self.cap
            && self
                .lowest
                .peek()
                .is_some_and(|&top| line > top || (line == top && time > self.latest))
    }

    /// The line where the open episode of pair `key` began.
    pub fn open_line(&self, key: u64) -> Option<u32> {
        self.open.get(&key).map(|o| o.first.line)
    }

    /// Record contact of pair `key` at a sample.
    pub fn contact(&mut self, key: u64, c: Contact) {
        match self.open.get_mut(&key) {
            Some(o) => {
                o.end_line = c.line;
                o.end_time = o.end_time.max(c.time);
                if c.kind == Kind::NearMiss {
                    o.min_gap = Some(
                        o.min_gap
                            .map_or(c.depth.unwrap_or(0.0), |g| g.min(c.depth.unwrap_or(0.0))),
                    );
                } else if let Some(d) = c.depth {
                    o.max_depth = Some(o.max_depth.map_or(d, |m| m.max(d)));
                }
            }
            None => {
                let gap = (c.kind == Kind::NearMiss).then_some(c.depth).flatten();
                let depth = (c.kind != Kind::NearMiss).then_some(c.depth).flatten();
                let time = c.time;
                let operation = self.operation;
                self.open.insert(
                    key,
                    Open {
                        end_line: c.line,
                        max_depth: depth,
                        min_gap: gap,
                        first: c,
                        end_time: time,
                        operation,
                    },
                );
            }
        }
    }

    /// Contact of pair `key` at a sample of an episode already open: extend it and return true;
    /// false when no episode is open (the caller then builds a full [`Contact`]).
    pub fn extend(&mut self, key: u64, line: u32, time: f64, depth: f64, near_miss: bool) -> bool {
        let Some(o) = self.open.get_mut(&key) else { return false };
        o.end_line = line;
        o.end_time = o.end_time.max(time);
        if near_miss {
            o.min_gap = Some(o.min_gap.map_or(depth, |g| g.min(depth)));
        } else {
            o.max_depth = Some(o.max_depth.map_or(depth, |m| m.max(depth)));
        }
        true
    }

    /// The deepest depth of pair `key`'s open contact so far (`None`: no open contact, or a near
    /// miss).
    pub fn max_depth(&self, key: u64) -> Option<f64> {
        self.open.get(&key).and_then(|o| o.max_depth)
    }

    /// The contact of pair `key` lasts at least until `time`.
    pub fn lasts_until(&mut self, key: u64, time: f64) {
        if let Some(o) = self.open.get_mut(&key) {
            o.end_time = o.end_time.max(time);
        }
    }

    /// Pair `key` was tested and is clear: close its episode.
    pub fn clear(&mut self, key: u64) {
        if let Some(o) = self.open.remove(&key) {
            self.emit(o);
        }
    }

    /// Close every open episode whose key is not in `keep`.
    pub fn close_except(&mut self, keep: impl Fn(u64) -> bool) {
        let keys: Vec<u64> = self.open.keys().copied().filter(|k| !keep(*k)).collect();
        for k in keys {
            self.clear(k);
        }
    }

    pub fn close_all(&mut self) {
        let open = std::mem::take(&mut self.open);
        for (_, o) in open {
            self.emit(o);
        }
    }

    /// When the earliest contact still going on began (infinity when none is open).
    pub fn earliest_open(&self) -> f64 {
        self.open.values().map(|o| o.first.time).fold(f64::INFINITY, f64::min)
    }

    /// Forget the lines of the findings emitted so far, which only a capped report reads
    /// ([`Self::left_out`]): a stream with no end and no cap (`follow`) keeps no list that grows.
    pub fn forget_lines(&mut self) {
        if self.cap == usize::MAX {
            self.lowest.clear();
        }
    }

    pub fn is_open(&self, key: u64) -> bool {
        self.open.contains_key(&key)
    }

    fn emit(&mut self, o: Open) {
        let c = o.first;
        self.latest = self.latest.max(c.time);
        self.lowest.push(c.line);
        if self.lowest.len() > self.cap {
            self.lowest.pop();
        }
        let severity = if c.kind == Kind::NearMiss {
            Severity::Warning
        } else {
            Severity::Error
        };
        let message = match (c.kind, o.min_gap) {
            (Kind::NearMiss, Some(g)) => format!("{} (closest {:.4} mm)", c.message, g),
            _ => c.message,
        };
        self.findings.push(Finding {
            line: c.line,
            end_line: o.end_line.max(c.line),
            col: 0,
            n: c.n,
            kind: c.kind,
            severity,
            objects: c.objects.to_vec(),
            words: c.words.map(|w| w.to_vec()).unwrap_or_default(),
            time_s: Some(c.time),
            depth_mm: if c.kind == Kind::NearMiss { None } else { o.max_depth },
            moved_mm: None,
            x: Some(c.x),
            z: Some(c.z),
            message,
            follow_on: None,
            profile_line: (c.profile_line != 0).then_some(c.profile_line),
            end_time_s: Some(o.end_time),
            repeats: 1,
            picture: None,
            snapshot: c.snapshot,
            snapshot3: c.snapshot3,
            operation: (o.operation > 0).then_some(o.operation),
        });
    }
}

/// Whether a contact of this kind is a graze (a warning) when its greatest depth stays below
/// `min_depth`: every contact measured against an outline drawn to a finite accuracy —
/// `collision` (holder, turret, other stations against stock, chuck, tailstock; the insert
/// against chuck or tailstock; the tailstock against chuck or stock in the setup),
/// `rapid_into_stock` and `spindle_stopped` (the insert against the stock). Not `near_miss`
/// (no contact) nor `overtravel` (an axis limit is a number, not an outline).
pub fn grazes(kind: Kind) -> bool {
    matches!(kind, Kind::Collision | Kind::RapidIntoStock | Kind::SpindleStopped)
}

/// Report every contact whose greatest depth stays below `min_depth` as a warning, a graze, with
/// the depth and the threshold in its message. Runs before [`mark_follow_ons`]: a graze is not a
/// crash in progress that later contacts follow on from.
pub fn mark_grazes(findings: &mut [Finding], min_depth: f64) {
    for f in findings.iter_mut() {
        let Some(d) = f.depth_mm else { continue };
        if grazes(f.kind) && f.severity == Severity::Error && d < min_depth {
            f.severity = Severity::Warning;
            f.message = format!("{} (a graze: shallower than min_depth {min_depth} mm)", f.message);
        }
    }
}

/// Mark every contact that is a follow-on of an earlier crash as a warning that names it. The
/// rule (ARCHITECTURE.md, "Invariants"): a follow-on is a contact between the **same two parts**
/// that an earlier episode put inside each other and that have not separated since — its episode
/// begins after that crash began and no later than it ended (the same parts, under another rule:
/// an insert still in the bar when a rapid becomes a feed with the spindle stopped, a 2D and a 3D
/// view of one pair). Nothing else is a follow-on: a contact of other parts is a crash of its
/// own, however soon after another it begins; an over-travel puts nothing inside anything, so
/// nothing follows on from it; near misses and grazes neither follow on nor are followed.
pub fn mark_follow_ons(findings: &mut [Finding]) {
    let crash = |f: &Finding| {
        !matches!(f.kind, Kind::NearMiss | Kind::Overtravel) && f.time_s.is_some() && f.end_time_s.is_some()
    };
    let mut order: Vec<usize> = (0..findings.len()).filter(|&i| crash(&findings[i])).collect();
    order.sort_by(|&a, &b| findings[a].time_s.unwrap().total_cmp(&findings[b].time_s.unwrap()));
    // Crashes in progress: (start, end, index), the earliest first.
    let mut active: Vec<(f64, f64, usize)> = Vec::new();
    for i in order {
        let (start, end) = (findings[i].time_s.unwrap(), findings[i].end_time_s.unwrap());
        active.retain(|&(_, e, _)| e >= start - 1e-9);
        let parent = active.iter().find(|&&(t, _, j)| {
            // A turn-round between them (a job's operations) puts another part in the jaws.
            t < start - 1e-9
                && same_parts(&findings[j].objects, &findings[i].objects)
                && findings[j].operation == findings[i].operation
        });
        if let Some(&(t, _, j)) = parent {
            let parent = FollowOn {
                line: findings[j].line,
                objects: findings[j].objects.clone(),
                time_s: t,
                words: findings[j].parts_in_words().to_vec(),
            };
            let f = &mut findings[i];
            f.follow_on = Some(parent);
            f.severity = Severity::Warning;
        } else if findings[i].severity == Severity::Warning {
            // A graze is reported on its own; nothing follows on from it.
            continue;
        }
        active.push((start, end, i));
    }
}

/// The two parts of a contact, in either order.
fn same_parts(a: &[String], b: &[String]) -> bool {
    match (a, b) {
        ([a0, a1], [b0, b1]) => (a0 == b0 && a1 == b1) || (a0 == b1 && a1 == b0),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::{self, Machine, BUILTIN_TOML};
    use crate::pipeline::{Settings, DEFAULT_MIN_DEPTH_MM};

    fn contact(kind: Kind, depth: f64, start: f64, end: f64) -> Finding {
        let mut f = Finding::at(kind, Severity::Error, 1, 0, "the T01 holder hits the stock");
        f.objects = vec!["T01 holder".into(), "stock".into()];
        f.depth_mm = Some(depth);
        f.time_s = Some(start);
        f.end_time_s = Some(end);
        f
    }

    #[test]
    fn contacts_shallower_than_min_depth_are_warnings_that_say_graze_and_deeper_ones_stay_errors() {
        let mut fs = vec![
            contact(Kind::Collision, 0.02, 0.0, 1.0),
            contact(Kind::RapidIntoStock, 0.5, 2.0, 3.0),
            contact(Kind::SpindleStopped, 0.099, 4.0, 5.0),
            contact(Kind::Collision, 0.1, 6.0, 7.0),
        ];
        mark_grazes(&mut fs, 0.1);
        let sev: Vec<_> = fs.iter().map(|f| f.severity).collect();
        assert_eq!(
            sev,
            [Severity::Warning, Severity::Error, Severity::Warning, Severity::Error]
        );
        assert_eq!(
            fs[0].message,
            "the T01 holder hits the stock (a graze: shallower than min_depth 0.1 mm)"
        );
        assert_eq!(fs[1].message, "the T01 holder hits the stock");
    }

    #[test]
    fn overtravel_and_findings_without_depth_never_graze() {
        let mut o = contact(Kind::Overtravel, 0.01, 0.0, 1.0);
        let mut p = Finding::at(Kind::Program, Severity::Error, 1, 0, "x");
        p.depth_mm = None;
        let mut fs = vec![o.clone(), p];
        mark_grazes(&mut fs, 0.1);
        assert!(fs.iter().all(|f| f.severity == Severity::Error));
        o.kind = Kind::NearMiss;
        assert!(!grazes(o.kind) && !grazes(Kind::Overtravel));
    }

    #[test]
    fn a_crash_that_begins_during_a_graze_is_not_its_follow_on() {
        // A graze from 0 to 10 s, a deep crash from 1 s, and a contact from 2 s, during both.
        let mut fs = vec![
            contact(Kind::Collision, 0.01, 0.0, 10.0),
            contact(Kind::Collision, 3.0, 1.0, 10.0),
            contact(Kind::Collision, 2.0, 2.0, 3.0),
        ];
        mark_grazes(&mut fs, 0.1);
        mark_follow_ons(&mut fs);
        assert_eq!(fs[0].severity, Severity::Warning);
        assert!(fs[0].follow_on.is_none());
        assert_eq!(fs[1].severity, Severity::Error, "the deep crash stands on its own");
        assert!(fs[1].follow_on.is_none());
        // The third follows on from the deep crash, not from the graze that began earlier.
        assert_eq!(fs[2].follow_on.as_ref().map(|p| p.time_s), Some(1.0));
    }

    fn between(mut f: Finding, a: &str, b: &str) -> Finding {
        f.objects = vec![a.into(), b.into()];
        f
    }

    #[test]
    fn a_contact_of_other_parts_during_a_crash_is_a_crash_of_its_own() {
        // The insert in the bar from 1 s; the holder and the turret reach the chuck while it is.
        let mut fs = vec![
            between(contact(Kind::RapidIntoStock, 5.0, 1.0, 9.0), "T01 insert", "stock"),
            between(contact(Kind::Collision, 2.0, 2.0, 9.0), "T01 holder", "chuck"),
            between(contact(Kind::Collision, 26.0, 3.0, 9.0), "turret", "chuck"),
        ];
        mark_follow_ons(&mut fs);
        assert!(fs
            .iter()
            .all(|f| f.severity == Severity::Error && f.follow_on.is_none()));
    }

    #[test]
    fn the_same_parts_still_inside_each_other_under_another_rule_follow_on() {
        // A rapid drives the insert into the bar; the next feed, spindle stopped, is still in it
        // (either order of the names).
        let mut fs = vec![
            between(contact(Kind::RapidIntoStock, 5.0, 1.0, 2.0), "T01 insert", "stock"),
            between(contact(Kind::SpindleStopped, 5.0, 2.0, 3.0), "stock", "T01 insert"),
            // After they separated (the first episode ended at 2 s), a new contact is a crash.
            between(contact(Kind::SpindleStopped, 1.0, 4.0, 5.0), "T01 insert", "stock"),
        ];
        mark_follow_ons(&mut fs);
        assert_eq!(fs[0].severity, Severity::Error);
        assert_eq!(fs[1].severity, Severity::Warning);
        assert_eq!(fs[1].follow_on.as_ref().map(|p| p.line), Some(1));
        assert_eq!(fs[2].severity, Severity::Error);
        assert!(fs[2].follow_on.is_none());
    }

    #[test]
    fn nothing_follows_on_from_an_overtravel() {
        let mut ot = contact(Kind::Overtravel, 26.0, 0.0, 10.0);
        ot.objects = vec!["turret".into(), "X travel".into()];
        let mut fs = vec![
            ot,
            between(contact(Kind::Collision, 26.0, 1.0, 2.0), "turret", "chuck"),
            between(contact(Kind::Collision, 1.0, 1.5, 2.0), "turret", "X travel"),
        ];
        mark_follow_ons(&mut fs);
        assert!(fs
            .iter()
            .all(|f| f.severity == Severity::Error && f.follow_on.is_none()));
    }

    #[test]
    fn min_depth_comes_from_settings_then_the_machine_file_then_the_default() {
        let plain = Machine::builtin();
        let with = BUILTIN_TOML.replacen("[machine]\n", "[machine]\nmin_depth = 0.3\n", 1);
        let m = machine::from_toml(&with, "m.toml").unwrap();
        assert_eq!(m.min_depth, Some(0.3));
        let s = Settings::default();
        assert_eq!(s.min_depth(&plain), DEFAULT_MIN_DEPTH_MM);
        assert_eq!(s.min_depth(&m), 0.3);
        let s = Settings {
            min_depth_mm: Some(0.0),
            ..s
        };
        assert_eq!(s.min_depth(&m), 0.0);
        // Out of range or not a number: a machine-file error naming the key.
        for bad in ["min_depth = 2.0", "min_depth = -0.1", "min_depth = nan"] {
            let text = BUILTIN_TOML.replacen("[machine]\n", &format!("[machine]\n{bad}\n"), 1);
            let e = machine::from_toml(&text, "m.toml").unwrap_err().to_string();
            assert!(e.contains("machine.min_depth"), "{bad}: {e}");
        }
    }
}
