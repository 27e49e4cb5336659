//! Waiting M codes: when each path runs, in the machine's one time.
//!
//! Each path runs in its own time until it reaches a waiting M code (a [`MoveKind::Wait`] mark).
//! It stands there until every path the code names has reached its next wait with the same code
//! and the same set of paths; then all of them go on together, at the latest of their
//! arrivals. A path's time in the machine's clock is its own time plus how long it has stood at
//! its waits so far ([`Schedule::global`]).
//!
//! When the paths can never meet — a path's next wait has another code, or it ends without one —
//! the machine stops there (the control waits forever): a [`Deadlock`] for each path left
//! waiting, and nothing after the first such instant is timed.
//!
//! [`MoveKind::Wait`]: crate::interp::MoveKind::Wait

/// One wait of a path, in its own time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaitAt {
    /// The index of the wait's mark in the path's moves.
    pub index: usize,
    /// When the path reaches it, in its own time (s).
    pub t: f64,
    pub code: u16,
    /// The paths that meet (bit `p - 1` for path `p`).
    pub mask: u8,
    pub line: u32,
}

/// A path as the synchronisation sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct Lane {
    pub path: u32,
    pub waits: Vec<WaitAt>,
    /// When its program ends, in its own time.
    pub end: f64,
    /// Its last line (where it ends).
    pub last_line: u32,
}

/// A path that waits for ever.
#[derive(Clone, Debug, PartialEq)]
pub struct Deadlock {
    pub path: u32,
    pub line: u32,
    /// The machine time it began to wait.
    pub at: f64,
    pub message: String,
}

/// A wait a path met: where, when it arrived and when it went on (machine time).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Met {
    /// The wait's move index.
    pub index: usize,
    /// When the path reached it, in its own time.
    pub local: f64,
    pub arrival: f64,
    pub release: f64,
    /// How much later than its own time the path runs after it.
    pub shift: f64,
}

/// When a path's moves run in the machine's time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Schedule {
    /// The waits met, in order.
    pub met: Vec<Met>,
}

impl Schedule {
    /// How much later than its own time the path's move `index` starts: the time it stood at the
    /// waits before it.
    pub fn shift(&self, index: usize) -> f64 {
        let k = self.met.partition_point(|w| w.index < index);
        if k == 0 {
            0.0
        } else {
            self.met[k - 1].shift
        }
    }

    /// The machine time of the path's own instant `t` (an instant at a wait: its arrival).
    pub fn global_of_local(&self, t: f64) -> f64 {
        let k = self.met.partition_point(|w| w.local < t);
        if k == 0 {
            t
        } else {
            t + self.met[k - 1].shift
        }
    }

    /// The machine time of instant `t` of move `index` (its own time `t`).
    pub fn global(&self, index: usize, t: f64) -> f64 {
        t + self.shift(index)
    }
}

/// The schedules of the lanes (in their order) and the paths that wait for ever; with a
/// deadlock, the machine time at which the first path began to wait for ever (nothing is timed
/// past it).
pub fn schedule(lanes: &[Lane]) -> (Vec<Schedule>, Vec<Deadlock>, Option<f64>) {
    let n = lanes.len();
    let mut next = vec![0usize; n];
    let mut shift = vec![0.0f64; n];
    let mut out = vec![Schedule::default(); n];
    let bit = |p: u32| 1u8 << (p - 1);
    let lane_of = |p: u32| lanes.iter().position(|l| l.path == p);
    loop {
        let mut progress = false;
        for i in 0..n {
            let Some(w) = lanes[i].waits.get(next[i]).copied() else {
                continue;
            };
            // Every path the wait names is at its next wait, with the same code and set.
            let mut members = Vec::new();
            let mut ready = true;
            for p in 1..=8u32 {
                if w.mask & bit(p) == 0 {
                    continue;
                }
                match lane_of(p) {
                    Some(j) => match lanes[j].waits.get(next[j]) {
                        Some(v) if v.code == w.code && v.mask == w.mask => members.push(j),
                        _ => ready = false,
                    },
                    None => ready = false,
                }
            }
            if !ready {
                continue;
            }
            let release = members
                .iter()
                .map(|&j| lanes[j].waits[next[j]].t + shift[j])
                .fold(f64::NEG_INFINITY, f64::max);
            for &j in &members {
                let v = lanes[j].waits[next[j]];
                let arrival = v.t + shift[j];
                shift[j] = release - v.t;
                out[j].met.push(Met {
                    index: v.index,
                    local: v.t,
                    arrival,
                    release,
                    shift: shift[j],
                });
                next[j] += 1;
            }
            progress = true;
        }
        if !progress {
            break;
        }
    }
    // Whatever is left waits for ever.
    let mut dead = Vec::new();
    for i in 0..n {
        let Some(w) = lanes[i].waits.get(next[i]) else { continue };
        let at = w.t + shift[i];
        let others: Vec<String> = (1..=8u32)
            .filter(|&p| p != lanes[i].path && w.mask & bit(p) != 0)
            .map(|p| match lane_of(p) {
                None => format!("path {p} has no program in this file"),
                Some(j) => match lanes[j].waits.get(next[j]) {
                    Some(v) if v.code != w.code => {
                        format!("path {p} waits at M{} (line {})", v.code, v.line)
                    }
                    Some(v) if v.mask != w.mask => {
                        format!("path {p} waits at M{} (line {}) for other paths", v.code, v.line)
                    }
                    Some(_) => format!("path {p} is held elsewhere"),
                    None => format!("path {p} ends at line {} without reaching it", lanes[j].last_line),
                },
            })
            .collect();
        dead.push(Deadlock {
            path: lanes[i].path,
            line: w.line,
            at,
            message: format!(
                "path {} waits at M{} for ever: {} (the control stops here; nothing after it is checked against the other paths)",
                lanes[i].path,
                w.code,
                others.join("; ")
            ),
        });
    }
    let stop = dead
        .iter()
        .map(|d| d.at)
        .fold(None, |a: Option<f64>, t| Some(a.map_or(t, |a| a.min(t))));
    (out, dead, stop)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wait(index: usize, t: f64, code: u16, line: u32) -> WaitAt {
        WaitAt {
            index,
            t,
            code,
            mask: 0b11,
            line,
        }
    }

    fn lane(path: u32, waits: Vec<WaitAt>, end: f64) -> Lane {
        Lane {
            path,
            waits,
            end,
            last_line: 99,
        }
    }

    #[test]
    fn the_path_that_arrives_first_stands_until_the_other_arrives() {
        // Path 1 reaches M100 at 3 s, path 2 at 5 s: both go on at 5 s; path 1's next move
        // starts 2 s later than in its own time. Then M101 at 4 s (own) for path 1 = 6 s, and
        // 5.5 s for path 2 = 5.5 s: both go on at 6 s.
        let lanes = [
            lane(1, vec![wait(4, 3.0, 100, 10), wait(9, 4.0, 101, 20)], 8.0),
            lane(2, vec![wait(2, 5.0, 100, 40), wait(5, 5.5, 101, 50)], 9.0),
        ];
        let (s, dead, stop) = schedule(&lanes);
        assert!(dead.is_empty());
        assert_eq!(stop, None);
        let met = |s: &Schedule| {
            s.met
                .iter()
                .map(|m| (m.index, m.arrival, m.release))
                .collect::<Vec<_>>()
        };
        assert_eq!(met(&s[0]), vec![(4, 3.0, 5.0), (9, 6.0, 6.0)]);
        assert_eq!(met(&s[1]), vec![(2, 5.0, 5.0), (5, 5.5, 6.0)]);
        assert_eq!(s[0].shift(3), 0.0);
        assert_eq!(s[0].shift(5), 2.0);
        assert_eq!(s[0].shift(10), 2.0);
        assert_eq!(s[1].shift(6), 0.5);
        assert_eq!(s[0].global(5, 3.5), 5.5);
    }

    #[test]
    fn different_codes_never_meet_and_say_where() {
        let lanes = [
            lane(1, vec![wait(1, 1.0, 100, 10)], 8.0),
            lane(2, vec![wait(1, 2.0, 101, 40)], 9.0),
        ];
        let (_, dead, stop) = schedule(&lanes);
        assert_eq!(dead.len(), 2);
        assert_eq!(stop, Some(1.0));
        assert_eq!((dead[0].path, dead[0].line), (1, 10));
        assert!(
            dead[0].message.contains("path 2 waits at M101 (line 40)"),
            "{}",
            dead[0].message
        );
    }

    #[test]
    fn a_path_that_ends_without_the_wait_leaves_the_other_waiting() {
        let lanes = [lane(1, vec![wait(1, 1.0, 100, 10)], 8.0), lane(2, vec![], 9.0)];
        let (_, dead, _) = schedule(&lanes);
        assert_eq!(dead.len(), 1);
        assert!(
            dead[0].message.contains("path 2 ends at line 99"),
            "{}",
            dead[0].message
        );
    }

    #[test]
    fn a_wait_for_its_own_path_alone_goes_on_at_once() {
        let mut w = wait(1, 1.0, 100, 10);
        w.mask = 0b01;
        let lanes = [lane(1, vec![w], 8.0), lane(2, vec![], 9.0)];
        let (s, dead, _) = schedule(&lanes);
        assert!(dead.is_empty());
        assert_eq!((s[0].met[0].arrival, s[0].met[0].release), (1.0, 1.0));
    }
}
