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
use crate::interp::MoveState;
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
        let d = &lanes[self.donor];
        let ds = &schedules[self.donor];
        // The donor's moves' starts in the machine's clock, and their spindles.
        let starts: Vec<f64> = d.timeline.items.iter().map(|it| ds.global(it.index, it.t0)).collect();
        let spindles: Vec<crate::interp::Spindle> = d
            .timeline
            .items
            .iter()
            .map(|it| d.run.states[d.run.moves[it.index].state as usize].spindle)
            .collect();
        // Where the donor's tool is during each move (its G96 speed at the heir's move starts).
        let donor_moves: Vec<(crate::interp::Move, crate::motion::Timed)> = d
            .timeline
            .items
            .iter()
            .map(|it| (d.run.moves[it.index], it.clone()))
            .collect();
        // A key per run of equal spindles: states are made once per run, not per move.
        let mut ids = vec![0usize; spindles.len()];
        for k in 1..spindles.len() {
            ids[k] = if spindles[k] == spindles[k - 1] { ids[k - 1] } else { k };
        }
        for (h, own, own_states) in &self.heirs {
            let hs = &schedules[*h];
            let lane = &mut lanes[*h];
            let mut states: Vec<MoveState> = own_states.clone();
            let mut made: std::collections::HashMap<(u32, usize, u64), u32> = std::collections::HashMap::new();
            for (k, m) in lane.run.moves.iter_mut().enumerate() {
                let t0 = lane.timeline.items.get(k).map_or(0.0, |it| hs.global(it.index, it.t0));
                // The donor's last move started by then (none: the spindle as the machine starts).
                let j = starts.partition_point(|&s| s <= t0);
                let Some(donor_at) = j.checked_sub(1) else {
                    m.state = own[k];
                    continue;
                };
                let own_state = own[k];
                let next = states.len() as u32;
                // Under G96 the spindle turns at the speed the donor's surface speed gives at the
                // donor's tool, where it is when the heir's move starts (not at the heir's own
                // radius): that speed, as G97, for the whole of the heir's move.
                let mut spindle = spindles[donor_at];
                let mut key = (own_state, ids[donor_at], 0u64);
                if let crate::interp::SpindleSpeed::Css { .. } = spindle.speed {
                    let (dm, it) = &donor_moves[donor_at];
                    let r = crate::motion::reference_at(dm, it, t0 - starts[donor_at]) + dm.tip;
                    let rpm = spindle.rpm_at(r.x);
                    if rpm.is_finite() {
                        spindle.speed = crate::interp::SpindleSpeed::Rpm(rpm);
                        key.2 = rpm.to_bits();
                    }
                }
                let id = *made.entry(key).or_insert_with(|| {
                    let mut s = own_states[own_state as usize];
                    s.spindle = spindle;
                    states.push(s);
                    next
                });
                m.state = id;
            }
            lane.run.states = states;
        }
    }
}
