//! Collision episodes: one finding per pair from the sample where contact begins to the last
//! sample in contact.

use crate::finding::{Finding, FollowOn, Kind, Severity};
use std::collections::BTreeMap;

/// What is known at one contact sample.
#[derive(Clone, Debug)]
pub struct Contact {
    pub kind: Kind,
    pub objects: [String; 2],
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
}

struct Open {
    first: Contact,
    end_line: u32,
    max_depth: Option<f64>,
    /// Smallest gap seen, for near misses.
    min_gap: Option<f64>,
    /// The episode was touched in the current round.
    seen: bool,
    /// Time of the last contact seen.
    end_time: f64,
}

/// Open episodes by pair key.
#[derive(Default)]
pub struct Episodes {
    open: BTreeMap<u64, Open>,
    pub findings: Vec<Finding>,
}

impl Episodes {
    /// Record contact of pair `key` at a sample.
    pub fn contact(&mut self, key: u64, c: Contact) {
        match self.open.get_mut(&key) {
            Some(o) => {
                o.end_line = c.line;
                o.end_time = o.end_time.max(c.time);
                o.seen = true;
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
                self.open.insert(
                    key,
                    Open {
                        end_line: c.line,
                        max_depth: depth,
                        min_gap: gap,
                        first: c,
                        seen: true,
                        end_time: time,
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

    pub fn is_open(&self, key: u64) -> bool {
        self.open.contains_key(&key)
    }

    fn emit(&mut self, o: Open) {
        let c = o.first;
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
            time_s: Some(c.time),
            depth_mm: if c.kind == Kind::NearMiss { None } else { o.max_depth },
            x: Some(c.x),
            z: Some(c.z),
            message,
            follow_on: None,
            profile_line: (c.profile_line != 0).then_some(c.profile_line),
            end_time_s: Some(o.end_time),
            repeats: 1,
            picture: None,
            snapshot: c.snapshot,
        });
    }
}

/// Mark every crash that began while an earlier one was still in progress (one part already
/// inside another) as that crash's follow-on, a warning: it exists because of the first crash.
/// Contacts that begin at the same instant are separate crashes; near misses are never either.
pub fn mark_follow_ons(findings: &mut [Finding]) {
    let crash = |f: &Finding| f.kind != Kind::NearMiss && f.time_s.is_some() && f.end_time_s.is_some();
    let mut order: Vec<usize> = (0..findings.len()).filter(|&i| crash(&findings[i])).collect();
    order.sort_by(|&a, &b| findings[a].time_s.unwrap().total_cmp(&findings[b].time_s.unwrap()));
    // Crashes in progress: (start, end, index), the earliest first.
    let mut active: Vec<(f64, f64, usize)> = Vec::new();
    for i in order {
        let (start, end) = (findings[i].time_s.unwrap(), findings[i].end_time_s.unwrap());
        active.retain(|&(_, e, _)| e >= start - 1e-9);
        if let Some(&(t, _, j)) = active.iter().find(|&&(t, _, _)| t < start - 1e-9) {
            let parent = FollowOn {
                line: findings[j].line,
                objects: findings[j].objects.clone(),
                time_s: t,
            };
            let f = &mut findings[i];
            f.follow_on = Some(parent);
            f.severity = Severity::Warning;
        }
        active.push((start, end, i));
    }
}
