//! LinuxCNC tool numbers on a turret with fewer stations (docs/assume.md, "Tool numbers"): a
//! LinuxCNC program's `T7 M6` names tool 7 of the control's tool table, not a station. When the
//! program names tools the turret has no station for, and neither the machine file nor a job
//! maps them, each is read as a tool put in a station the program does not use otherwise — on a
//! machine whose setup is an example (`[setup] assume = true`) only: elsewhere those stations'
//! tools are the shop's.

use super::words::{numbered, split_comment};
use super::{set, Assumed, Assumption};
use crate::machine::{Dialect, Machine};

/// Map the program's tool numbers to stations when some have none. Returns the machine with
/// the map, for reading the program's moves station by station; `None` when nothing is mapped.
pub fn assume(src: &[u8], file: &str, machine: &Machine, out: &mut Assumed) -> Option<Machine> {
    let (m, _) = crate::pipeline::resolve(src, machine);
    // The stations' tools are the machine file's: only an example setup lends them out.
    if !m.assume_setup || m.dialect != Dialect::Linuxcnc || !m.tool_numbers.is_empty() || m.kinematics.is_some() {
        return None;
    }
    let stations = m.turret.stations;
    // Tool numbers in order of first use, with their line.
    let mut used: Vec<(u32, u32)> = Vec::new();
    for (i, line) in String::from_utf8_lossy(src).lines().enumerate() {
        let (code, _) = split_comment(line);
        for t in numbered(&code, 'T') {
            if t != 0 && !used.iter().any(|u| u.0 == t) {
                used.push((t, i as u32 + 1));
            }
            if used.len() > 1000 {
                return None;
            }
        }
    }
    if used.iter().all(|&(t, _)| t <= stations) {
        return None;
    }
    let mut taken: Vec<u32> = used.iter().map(|u| u.0).filter(|&t| t <= stations).collect();
    let mut map: Vec<(u32, u32, u32)> = Vec::new();
    for &(t, line) in &used {
        let station = if t <= stations {
            t
        } else {
            // A Fanuc-style number (T303) keeps its station digits when that station is free.
            let wish = [t / 100, t % 100]
                .into_iter()
                .find(|&s| s >= 1 && s <= stations && !taken.contains(&s));
            match wish.or_else(|| (1..=stations).find(|s| !taken.contains(s))) {
                Some(s) => s,
                None => continue,
            }
        };
        if t > stations {
            taken.push(station);
        }
        map.push((t, station, line));
    }
    let mut numbered_machine = m.into_owned();
    numbered_machine.tool_numbers = map.iter().map(|&(t, s, _)| (t, s)).collect();
    numbered_machine.tool_numbers.sort_unstable();
    for &(t, s, line) in &map {
        out.layer
            .tool_numbers
            .push(set((t, s), file, line, &format!("tool_numbers.T{t}")));
    }
    let moved: Vec<String> = map
        .iter()
        .filter(|m| m.0 > stations)
        .map(|&(t, s, _)| format!("T{t} in station {s}"))
        .collect();
    let first = map.iter().find(|m| m.0 > stations).map_or(0, |m| m.2);
    out.notes.push(Assumption {
        key: "tool_numbers".into(),
        value: moved.join(", "),
        reason: format!(
            "the program names tools the {stations}-station turret has no station for (first at line {first}): tool numbers of the control's tool table, each put in a station the program does not use"
        ),
        line: first,
        kept: false,
    });
    Some(numbered_machine)
}
