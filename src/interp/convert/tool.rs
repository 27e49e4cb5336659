//! Step 4 of the order of execution: tool selection (T) and change (LinuxCNC M6; a Fanuc lathe
//! indexes the turret at the T word, as its operator's manual has it, and M6 has nothing left to
//! do), a job's manual tool changes, and the findings for a tool the machine lacks.

use crate::gcode::Block;
use crate::geom::V2;
use crate::interp::flow::Run;
use crate::interp::order::Cx;
use crate::interp::words::Words;
use crate::interp::{Feed, MoveKind};

/// `Run::selected` after a LinuxCNC T word for a tool number the job's `[tool_numbers]` lacks:
/// no station (past any turret's), so the M6 that follows leaves the moves unchecked.
pub(crate) const UNMAPPED: u32 = u32::MAX;

/// The tip of the tool in a station (zero for an empty station).
pub(crate) fn tip_of(machine: &crate::machine::Machine, station: u32) -> V2 {
    machine.tool(station).map_or(V2::zeros(), |t| t.tip.coords)
}

impl Run<'_> {
    /// Step 4: T and M6 (M group 6). Touches the station, the tool tip, `selected`,
    /// `devices.tool_unknown` (and makes the index move). Order: LinuxCNC's "select tool", then
    /// "change tool", before the spindle codes; a Fanuc lathe indexes at the T word.
    pub(crate) fn convert_tool(&mut self, b: &Block, w: &mut Words, cx: &Cx) {
        let fanuc = cx.fanuc;
        if w.peek(b'T') || w.nm > 0 {
            if let Some(t) = w.get(b'T') {
                self.tool_word(b, t, w.at(b'T'), fanuc);
            }
            if !fanuc {
                if let Some(at) = w.has_m(61) {
                    self.set_tool_number(b, w, at);
                }
            }
            if let Some(at) = w.has_m(6) {
                if fanuc {
                    // Fanuc lathes index at the T word; M6 has nothing left to do.
                } else {
                    if let Some(t) = self.selected {
                        self.change_tool(b, t, Some(at));
                    }
                }
            }
        }
    }

    fn tool_word(&mut self, b: &Block, t: f64, at: Option<u32>, fanuc: bool) {
        if t < 0.0 || t.fract() != 0.0 || t > 9999.0 {
            // The control changes to some tool here, which one latheguard cannot tell: the moves
            // until the next tool change are not checked (as after a T for an unknown station).
            self.error(
                b,
                at,
                format!("T{t} is not a tool number; the moves until the next tool change are not checked"),
            );
            self.devices.tool_unknown = true;
            return;
        }
        let t = t as u32;
        // Fanuc T0101 / T101: station in front of the last two digits (offset number); T1..T99:
        // the station itself. LinuxCNC: the tool number is the station, unless the job maps tool
        // numbers to stations (`[tool_numbers]`: the tool table's pockets).
        let station = if fanuc && t >= 100 {
            t / 100
        } else if !fanuc && t != 0 && !self.machine.tool_numbers.is_empty() {
            match self.machine.station_of_tool(t) {
                Some(s) => s,
                None => {
                    self.unmapped_tool(b, t, at);
                    return;
                }
            }
        } else {
            t
        };
        if station == 0 {
            // T0 / T0000: cancel the offset, keep the station (no index).
            return;
        }
        if station > self.machine.turret.stations || self.machine.tool(station).is_none() {
            self.unknown_tool(b, t, station, at, fanuc);
        }
        if fanuc {
            self.change_tool(b, station, at);
        } else {
            self.selected = Some(station);
        }
    }

    /// LinuxCNC `M61 Q<tool>`: the control takes tool Q as the one in place, without a tool
    /// change (nothing moves). When Q is the tool the turret holds (its station, through the
    /// job's `[tool_numbers]`), nothing changes. Otherwise the program says a tool is in place
    /// that the setup does not put there: latheguard checks the tool the turret holds, and says
    /// so as an `unsupported` error (the offsets LinuxCNC then applies are tool Q's).
    fn set_tool_number(&mut self, b: &Block, w: &mut Words, at: u32) {
        let Some(q) = w.get(b'Q') else {
            self.error(b, Some(at), "M61 needs Q, the tool number now in place".into());
            return;
        };
        if q < 0.0 || q.fract() != 0.0 || q > 9999.0 {
            self.error(b, w.at(b'Q'), format!("M61 Q{q}: Q is not a tool number"));
            return;
        }
        let t = q as u32;
        let station = if self.machine.tool_numbers.is_empty() {
            Some(t)
        } else {
            self.machine.station_of_tool(t)
        };
        if t == 0 || station == Some(self.station) {
            return;
        }
        let held = self.station;
        let at_station = station.map_or_else(
            || format!("tool {t} is in no station of the job's [tool_numbers]"),
            |s| format!("tool {t} is in station {s}"),
        );
        self.unsupported(
            b,
            Some(at),
            format!(
                "M61 Q{t} says tool {t} is in place without a tool change, but the turret holds station {held} ({at_station}): \
                 the moves are checked with station {held}'s tool; if tool {t} is in place when the program starts, set turret.start_station in the machine file"
            ),
            true,
        );
    }

    fn change_tool(&mut self, b: &Block, station: u32, _at: Option<u32>) {
        // A station the turret lacks cannot be indexed to; one the machine file has no tool for
        // can. Either way the moves that follow are not checked (`tool_unknown`, see
        // `unknown_tool`) until the next change to a described tool; the index to an empty
        // station is checked, the one out of it is not (the turret's place was unknown).
        let known = self.machine.tool(station).is_some();
        if station == self.station || station > self.machine.turret.stations {
            self.devices.tool_unknown = !known;
            return;
        }
        let from = self.station;
        self.station = station;
        self.tip = tip_of(self.machine, station);
        // The reference point stays; the programmed point becomes the new tool's tip.
        let end = self.programmed();
        self.push_move(b, MoveKind::ToolChange { from, to: station }, end, end, Feed::Rapid);
        self.devices.tool_unknown = !known;
    }

    /// A job's manual tool change at this block's line (`[[tool_changes]]`): the operator has put
    /// the tool of that station in, as a T word would switch to it, before the block runs.
    #[cold]
    pub(crate) fn manual_tool_change(&mut self, b: &Block) {
        let changes = &self.machine.tool_changes;
        if let Ok(i) = changes.binary_search_by_key(&b.line, |c| c.0) {
            let station = changes[i].1;
            self.change_tool(b, station, None);
        }
    }

    /// A LinuxCNC `T` for a tool number the job's `[tool_numbers]` map lacks: a `program`
    /// finding at the T word; the M6 that follows changes to a tool latheguard does not know
    /// (`UNMAPPED`), so the moves until the next tool change are not checked.
    #[cold]
    fn unmapped_tool(&mut self, b: &Block, t: u32, at: Option<u32>) {
        self.error(
            b,
            at,
            format!(
                "T{t}: tool {t} is in no station: add tool_numbers.T{t} = STATION to the job (or list it in its tool_table); the moves after M6 until the next tool change are not checked"
            ),
        );
        self.selected = Some(UNMAPPED);
    }

    /// A `T` for a station the turret lacks or the machine file has no tool in: a `program`
    /// finding at the T word. What follows is not checked as if another tool were there.
    #[cold]
    fn unknown_tool(&mut self, b: &Block, t: u32, station: u32, at: Option<u32>, fanuc: bool) {
        let stations = self.machine.turret.stations;
        let with: Vec<String> = self.machine.tools.iter().map(|t| t.station.to_string()).collect();
        let what = if station > stations {
            format!("the turret has no station {station} (it has 1 to {stations}; a control refuses it)")
        } else {
            format!(
                "the machine file has no tool in station {station} (stations with tools: {})",
                with.join(", ")
            )
        };
        let when = if fanuc { "" } else { " after M6" };
        self.error(
            b,
            at,
            format!(
                "T{t}: {what}; the moves{when} until the next tool change are not checked: where the turret is depends on that tool's offsets"
            ),
        );
    }

    /// The active tool's tip relative to the turret reference point.
    pub(crate) fn tip(&self) -> V2 {
        self.tip
    }
}
