//! Each station's tool, read from its comment and from what it does (docs/assume.md, "Tools").
//!
//! Per station the program uses: the kind of tool from the comment at its T word
//! ([`comment`]), else from its moves below the face ([`moves`]); the machine file's tool stays
//! when it is of that kind (or when the machine's setup is the shop's truth and the station
//! holds one); otherwise a catalogue tool of that kind, sized from the program ([`build`]), at
//! the station's tip.

mod build;
pub mod comment;
pub mod moves;
#[cfg(test)]
mod tests;

use super::reading::Reading;
use super::{set, Assumed, Assumption};
use crate::job::JobTool;
use crate::machine::{Dialect, Machine, Tool};
use crate::tooling::Cutter;
use std::collections::BTreeMap;

/// What a station's tool does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ToolKind {
    OdTurning,
    Facing,
    Boring,
    Grooving,
    Parting,
    Threading,
    Drilling,
    Tapping,
}

impl ToolKind {
    /// The tool in a report's words.
    pub fn word(self) -> &'static str {
        match self {
            ToolKind::OdTurning => "OD turning tool",
            ToolKind::Facing => "facing tool",
            ToolKind::Boring => "boring bar",
            ToolKind::Grooving => "grooving tool",
            ToolKind::Parting => "parting tool",
            ToolKind::Threading => "threading tool",
            ToolKind::Drilling => "drill",
            ToolKind::Tapping => "tap",
        }
    }

    /// A tool of this kind does the work `want` asks for (a turning tool faces; a parting
    /// blade grooves).
    pub fn does(self, want: ToolKind) -> bool {
        self == want
            || matches!(
                (self, want),
                (ToolKind::OdTurning, ToolKind::Facing) | (ToolKind::Parting, ToolKind::Grooving)
            )
    }

    /// It stands along the spindle axis (a boring bar, a drill, an internal tool).
    fn axial(self, internal: bool) -> bool {
        match self {
            ToolKind::Boring | ToolKind::Drilling | ToolKind::Tapping => true,
            ToolKind::Threading | ToolKind::Grooving => internal,
            _ => false,
        }
    }

    /// The kind of a machine file's tool, from its cutter and the words of its name.
    pub fn of_tool(t: &Tool) -> Option<ToolKind> {
        match t.cutter {
            Cutter::Drill => Some(ToolKind::Drilling),
            Cutter::Tap => Some(ToolKind::Tapping),
            _ => comment::kind_of(&t.name).map(|k| k.0),
        }
    }
}

/// A station's kind of tool and why.
struct Evidence {
    kind: ToolKind,
    internal: bool,
    line: u32,
    reason: String,
    said: Option<f64>,
    finish: bool,
}

/// The kind for `station`: its comment's, else its moves'.
fn evidence(said: Option<&comment::Said>, work: &moves::Work) -> Option<Evidence> {
    let from_moves = moves::kind(work);
    if let Some(s) = said {
        let up = s.text.to_uppercase();
        return Some(Evidence {
            kind: s.kind,
            internal: s.internal || from_moves.is_some_and(|m| m.0 == s.kind && m.1),
            line: s.line,
            reason: format!("the comment at line {} says {}", s.line, s.text),
            said: s.size,
            finish: up.contains("FINISH") || up.contains("PROFIL"),
        });
    }
    let (kind, internal, seen) = from_moves?;
    Some(Evidence {
        kind,
        internal,
        line: seen.line,
        reason: seen.words.clone(),
        said: None,
        finish: false,
    })
}

/// What the comments say of each station, each line's threading and tapping modes
/// ([`moves::thread_modes`], read once for every station), and the stations the program's moves
/// run at, in order.
type StationsRead = (BTreeMap<u32, comment::Said>, moves::ThreadModes, Vec<u32>);

fn stations_read(r: &Reading, machine: &Machine) -> StationsRead {
    let scale = r.segs.first().map_or(1.0, |s| s.scale);
    let said = comment::read(r, scale);
    let modes = moves::thread_modes(r, machine.dialect == Dialect::Fanuc);
    // Inserted one by one: a set collected from the iterator would hold every segment's station
    // first (4 bytes a segment of a long program).
    let mut set = std::collections::BTreeSet::new();
    for s in r.segs.iter() {
        set.insert(s.station);
    }
    let stations: Vec<u32> = set.into_iter().collect();
    (said, modes, stations)
}

/// The stations whose tool works inside the part (a boring bar, a drill, a tap, an internal
/// threading or grooving tool), by their comment or their moves: their passes say nothing of
/// the bar's outside diameter.
pub fn inside_stations(r: &Reading, machine: &Machine, face: f64) -> Vec<u32> {
    let (said, modes, stations) = stations_read(r, machine);
    moves::works(r, &stations, face, &modes)
        .into_iter()
        .filter(|(s, work)| {
            evidence(said.get(s), work).is_some_and(|e| {
                e.internal || matches!(e.kind, ToolKind::Boring | ToolKind::Drilling | ToolKind::Tapping)
            })
        })
        .map(|(s, _)| s)
        .collect()
}

/// `T03` (Fanuc) or `T3` (LinuxCNC).
fn t_name(machine: &Machine, station: u32) -> String {
    match machine.dialect {
        Dialect::Fanuc => format!("T{station:02}"),
        Dialect::Linuxcnc => format!("T{station}"),
    }
}

/// Read the tool of each station the program uses; `face` is the bar's raw front face in
/// program Z (mm). Adds the assumed tools to `out.layer.tools` and a note for each station.
pub fn assume(r: &Reading, file: &str, machine: &Machine, face: f64, out: &mut Assumed) {
    let (said, modes, mut stations) = stations_read(r, machine);
    stations.retain(|s| (1..=machine.turret.stations).contains(s));
    let works = moves::works(r, &stations, face, &modes);
    for (station, work) in &works {
        let station = *station;
        let ev = evidence(said.get(&station), work);
        let have = machine.tool(station);
        let t = t_name(machine, station);
        let key = format!("tools.{station}");
        let keep = match (have, &ev) {
            (Some(h), Some(e)) => !machine.assume_setup || ToolKind::of_tool(h).map_or(true, |k| k.does(e.kind)),
            (Some(_), None) => true,
            (None, _) => false,
        };
        if keep {
            let h = have.expect("kept tools exist");
            let reason = match (&ev, ToolKind::of_tool(h)) {
                (Some(e), Some(k)) if k.does(e.kind) => format!("{}: the machine file's tool is one", e.reason),
                (Some(e), None) => format!(
                    "{}; the machine file's tool stays: its name does not say what it is",
                    e.reason
                ),
                (Some(e), _) => format!("{}; the machine file's tool stays: its setup is the shop's", e.reason),
                (None, _) => "the program says nothing of it: the machine file's tool stays".to_string(),
            };
            out.notes.push(Assumption {
                key,
                value: format!("{t} {}", h.name),
                reason,
                line: ev.as_ref().map_or(0, |e| e.line),
                kept: true,
            });
            continue;
        }
        let Some(e) = ev else { continue };
        // The smallest bore a boring bar cuts at after this station's first cut.
        let later_bore = works
            .iter()
            .filter(|(s, w)| {
                let bores = said.get(s).map_or_else(
                    || moves::kind(w).is_some_and(|k| k.0 == ToolKind::Boring),
                    |c| c.kind == ToolKind::Boring,
                );
                *s != station && w.first > work.first && bores
            })
            .filter_map(|(_, w)| w.pass_r)
            .filter(|r| *r > 0.0)
            .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.min(r))));
        let sizing = build::Sizing {
            work,
            said: e.said,
            internal: e.internal,
            later_bore,
            finish: e.finish,
        };
        let tip = build::tip_for(machine, station, e.kind.axial(e.internal));
        let Some(made) = build::make(e.kind, &sizing, face, station, tip, machine) else {
            continue;
        };
        out.notes.push(Assumption {
            key: key.clone(),
            value: format!("{t} {} {}", e.kind.word(), made.designation),
            reason: e.reason,
            line: e.line,
            kept: false,
        });
        out.layer.tools.push(set(
            JobTool {
                tool: made.tool,
                origin: format!("catalogue: {}", made.summary),
                geometry_offset: None,
            },
            file,
            e.line,
            &key,
        ));
    }
}
