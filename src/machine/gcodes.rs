//! Builder G codes and the meaning of the drilling cycles: what a machine's control does with G
//! codes that its builder numbered its own way (`[gcodes]` in the machine file) and whether
//! G83–G89 are the Haas spindle-axis cycles or Fanuc's live-tool face and side cycles
//! (`machine.drilling_cycles`). docs/machine.md, "Builder G codes".

/// What one builder G code does (`[gcodes]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GAlias {
    /// The code runs as this standard code (×10: G12.1 → 121): the builder's number for it.
    As(u16),
    /// A mode switch that moves nothing latheguard checks (a spindle or path selection the
    /// machine has only one of, a display mode): read and dropped, never `unsupported`.
    Ignore,
}

/// The machine's `[gcodes]` table: builder codes (×10) and what they do. Empty for a machine
/// without the table (every shipped lathe).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GcodeTable {
    entries: Vec<(u16, GAlias)>,
}

impl GcodeTable {
    /// The table of these entries (later entries for the same code win; the loader refuses
    /// duplicates before this).
    pub fn new(mut entries: Vec<(u16, GAlias)>) -> GcodeTable {
        entries.sort_by_key(|e| e.0);
        entries.dedup_by_key(|e| e.0);
        GcodeTable { entries }
    }

    /// What the builder code `code` (×10) does on this machine, if the table names it.
    #[inline]
    pub fn get(&self, code: u16) -> Option<GAlias> {
        if self.entries.is_empty() {
            return None;
        }
        self.entries
            .binary_search_by_key(&code, |e| e.0)
            .ok()
            .map(|i| self.entries[i].1)
    }

    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The entries, by code.
    pub fn entries(&self) -> &[(u16, GAlias)] {
        &self.entries
    }
}

/// Which drilling cycles G83–G89 are (`machine.drilling_cycles`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DrillingCycles {
    /// Haas lathes (and Fanuc's spindle-axis reading): G81–G89 drill along Z on the spindle
    /// axis with a turret drill, the part turning (`interp/cycles/drill.rs`). The default.
    #[default]
    Haas,
    /// Fanuc 0i/16i/18i lathes with live tools: G83/G84/G85 drill, tap and bore along Z on
    /// the face, G87/G88/G89 along X on the side, at the hole's C angle
    /// (`interp/cycles/live_drill.rs`).
    Fanuc,
}

impl DrillingCycles {
    /// The name in machine files: `haas`, `fanuc`.
    pub fn as_str(self) -> &'static str {
        match self {
            DrillingCycles::Haas => "haas",
            DrillingCycles::Fanuc => "fanuc",
        }
    }
}

/// A G code as written in a machine file (`G12.1`, `G121`, `g87.6`) → ×10; `None` if it is not
/// one (a letter other than G, no digits, more than one decimal, above G999.9).
pub fn parse_code(s: &str) -> Option<u16> {
    let rest = s.strip_prefix('G').or_else(|| s.strip_prefix('g'))?;
    let (int, frac) = match rest.split_once('.') {
        Some((i, f)) => (i, Some(f)),
        None => (rest, None),
    };
    if int.is_empty() || int.len() > 3 || !int.bytes().all(|c| c.is_ascii_digit()) {
        return None;
    }
    let tenth = match frac {
        None => 0,
        Some(f) if f.len() == 1 && f.as_bytes()[0].is_ascii_digit() => u16::from(f.as_bytes()[0] - b'0'),
        Some(_) => return None,
    };
    Some(int.parse::<u16>().ok()? * 10 + tenth)
}

/// A code (×10) as a program writes it: `G12.1`, `G121`.
pub fn code_name(code: u16) -> String {
    if code % 10 == 0 {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_read_as_programs_write_them() {
        assert_eq!(parse_code("G12.1"), Some(121));
        assert_eq!(parse_code("G121"), Some(1210));
        assert_eq!(parse_code("g87.6"), Some(876));
        assert_eq!(parse_code("G0"), Some(0));
        for bad in ["", "G", "M3", "G1.23", "G1000", "G-1", "G1.", "G.5", "G 1"] {
            assert_eq!(parse_code(bad), None, "{bad}");
        }
        assert_eq!(code_name(121), "G12.1");
        assert_eq!(code_name(1210), "G121");
    }

    #[test]
    fn a_table_answers_only_for_its_codes() {
        let t = GcodeTable::new(vec![(1210, GAlias::As(121)), (1400, GAlias::Ignore)]);
        assert_eq!(t.get(1210), Some(GAlias::As(121)));
        assert_eq!(t.get(1400), Some(GAlias::Ignore));
        assert_eq!(t.get(121), None);
        assert_eq!(GcodeTable::default().get(1210), None);
    }
}
