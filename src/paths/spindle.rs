//! One spindle, several paths: a path whose lines never command the spindle runs with the
//! spindle another path commands (docs/paths.md, "The spindle").
//!
//! On a twin-turret lathe with one spindle, one path's program (usually path 1's) starts, stops
//! and sets the spindle, and the other path feeds while it turns. Each path is interpreted alone,
//! so the other path would see a spindle that never turns (a `spindle_stopped` at every cut, its
//! feeds per revolution timed at the fallback feed). Here each move of such a path — an **heir**
//! — takes the spindle of the **donor** (the lowest-numbered path whose lines command it) as it
//! stands in the machine's clock when the move starts; the heir's own frame, tailstock and tool
//! states stay its own. A donor's constant surface speed (G96) reaches the heir as the speed it
//! gives at the donor's tool then, not at the heir's.

use super::sync::Schedule;
use super::Lane;
use crate::interp::{MoveState, Spindle, SpindleSpeed};
use crate::machine::Machine;

/// Which lanes take their spindle from which.
pub(super) struct Sharing {
    donor: usize,
    /// Per heir lane: its moves' own states, as interpreted.
    heirs: Vec<(usize, Vec<u32>, Vec<MoveState>)>,
}

/// Whether a lane's lines command the spindle: it turns during one of its moves (the machine
/// starts with it stopped: [`plan`]).
fn commands(l: &Lane) -> bool {
    l.run
        .moves
        .iter()
        .any(|m| l.run.states[m.state as usize].spindle.is_on())
}

/// The sharing of a program's lanes; `None` when every path commands the spindle, or none
/// does, or the machine starts with its spindle turning (`spindle.start_rpm`: every path then
/// has it from its start).
pub(super) fn plan(lanes: &[Lane], machine: &Machine) -> Option<Sharing> {
    if machine.start_rpm.is_some() {
        return None;
    }
    let donor = lanes.iter().position(commands)?;
    let heirs: Vec<(usize, Vec<u32>, Vec<MoveState>)> = lanes
        .iter()
        .enumerate()
        .filter(|(i, l)| *i != donor && !l.run.moves.is_empty() && !commands(l))
        .map(|(i, l)| (i, l.run.moves.iter().map(|m| m.state).collect(), l.run.states.clone()))
        .collect();
    (!heirs.is_empty()).then_some(Sharing { donor, heirs })
}

impl Sharing {
    /// Give each heir's moves the donor's spindle at their start, by the current `schedules`.
    pub(super) fn apply(&self, lanes: &mut [Lane], schedules: &[Schedule]) {
        for (h, own, own_states) in &self.heirs {
            // Each heir move's spindle, read from the donor before the heir's moves change.
            let spindles = self.donor_spindles(&lanes[self.donor], &schedules[self.donor], &lanes[*h], &schedules[*h]);
            let lane = &mut lanes[*h];
            let mut states: Vec<MoveState> = own_states.clone();
            let mut made: std::collections::HashMap<(u32, SpindleKey), u32> = std::collections::HashMap::new();
            for (k, m) in lane.run.moves.iter_mut().enumerate() {
                let own_state = own[k];
                let Some((spindle, key)) = spindles[k] else {
                    m.state = own_state;
                    continue;
                };
                let next = states.len() as u32;
                m.state = *made.entry((own_state, key)).or_insert_with(|| {
                    let mut s = own_states[own_state as usize];
                    s.spindle = spindle;
                    states.push(s);
                    next
                });
            }
            lane.run.states = states;
        }
    }

    /// For each move of `heir`, the donor's spindle when it starts (none before the donor's
    /// first move: the spindle as the machine starts) with a key of equal spindles. Under G96
    /// the spindle turns at the speed the donor's surface speed gives at the donor's tool, where
    /// it is when the heir's move starts (not at the heir's own radius): that speed, as G97, for
    /// the whole of the heir's move.
    fn donor_spindles(
        &self,
        d: &Lane,
        ds: &Schedule,
        heir: &Lane,
        hs: &Schedule,
    ) -> Vec<Option<(Spindle, SpindleKey)>> {
        let items = &d.timeline.items;
        // The donor's moves' starts in the machine's clock.
        let starts: Vec<f64> = items.iter().map(|it| ds.global(it.index, it.t0)).collect();
        let spindle_of = |k: usize| d.run.states[d.run.moves[items[k].index].state as usize].spindle;
        // A key per run of equal spindles: states are made once per run, not per move.
        let mut ids = vec![0usize; items.len()];
        for k in 1..items.len() {
            ids[k] = if spindle_of(k) == spindle_of(k - 1) {
                ids[k - 1]
            } else {
                k
            };
        }
        (0..heir.run.moves.len())
            .map(|k| {
                let t0 = heir.timeline.items.get(k).map_or(0.0, |it| hs.global(it.index, it.t0));
                let j = starts.partition_point(|&s| s <= t0).checked_sub(1)?;
                let mut spindle = spindle_of(j);
                let mut key = (ids[j], 0u64);
                if let SpindleSpeed::Css { .. } = spindle.speed {
                    let it = &items[j];
                    let dm = &d.run.moves[it.index];
                    let r = crate::motion::reference_at(dm, it, t0 - starts[j]) + dm.tip;
                    let rpm = spindle.rpm_at(r.x);
                    if rpm.is_finite() {
                        spindle.speed = SpindleSpeed::Rpm(rpm);
                        key.1 = rpm.to_bits();
                    }
                }
                Some((spindle, key))
            })
            .collect()
    }
}

/// Which of the donor's spindles a state takes: its run of equal spindles, and under G96 the
/// speed it gives (its bits).
type SpindleKey = (usize, u64);
