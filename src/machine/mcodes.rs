//! The M codes of a machine: which code does what (`[mcodes]` in the machine file).
//!
//! The codes that steer the interpreter itself are not in the table and cannot be given there:
//! M6 (tool change), M98/M99 (subprograms) and M70–M73 (saved modal state). Every other M code
//! is looked up here; one the table lacks is a warning that names it (see `docs/mcodes.md`).

use super::Dialect;

/// What an M code does, as far as latheguard models it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MAction {
    /// M0: the program waits for cycle start; nothing moves.
    ProgramStop,
    /// M1: as M0 when the operator's optional-stop switch is on.
    OptionalStop,
    /// M2, M30: the program ends here.
    ProgramEnd,
    SpindleCw,
    SpindleCcw,
    SpindleStop,
    CoolantOn,
    CoolantOff,
    /// The tailstock quill advances (Haas M21): the tailstock is an obstacle from here on.
    TailstockAdvance,
    /// The tailstock quill retracts (Haas M22): the tailstock is no obstacle from here on.
    TailstockRetract,
    /// The chuck opens (unclamps); with the spindle turning, a `program` finding.
    ChuckOpen,
    ChuckClose,
    PartCatcherAdvance,
    PartCatcherRetract,
    BarFeed,
    ConveyorOn,
    ConveyorOff,
    /// A code the control knows that changes nothing latheguard checks (gear range, override
    /// switches, outputs).
    NoEffect,
    /// The main spindle becomes a positioned C axis (Haas M154): it stops turning, and C words
    /// position it. On a machine whose table has this action, a C word outside C-axis mode is
    /// a `program` error.
    CAxisOn,
    /// The spindle leaves C-axis mode (Haas M155; a spindle start leaves it too).
    CAxisOff,
    /// The live tool turns forward at the code's P word, rev/min (Haas M133).
    LiveToolCw,
    /// The live tool turns in reverse at the code's P word (Haas M134).
    LiveToolCcw,
    /// The live tool stops (Haas M135).
    LiveToolStop,
    /// The sub-spindle's chuck clamps (Haas M110): it holds what is in its jaws, and takes the
    /// piece a part-off severs (docs/turn-mill.md, "Pick-off and part-off").
    SubChuckClose,
    /// The sub-spindle's chuck unclamps (Haas M111): a piece it held falls (a part catcher).
    SubChuckOpen,
}

/// The action names of a machine file's `[mcodes]` table.
pub const ACTIONS: [(&str, MAction); 25] = [
    ("program_stop", MAction::ProgramStop),
    ("optional_stop", MAction::OptionalStop),
    ("program_end", MAction::ProgramEnd),
    ("spindle_cw", MAction::SpindleCw),
    ("spindle_ccw", MAction::SpindleCcw),
    ("spindle_stop", MAction::SpindleStop),
    ("coolant_on", MAction::CoolantOn),
    ("coolant_off", MAction::CoolantOff),
    ("tailstock_advance", MAction::TailstockAdvance),
    ("tailstock_retract", MAction::TailstockRetract),
    ("chuck_open", MAction::ChuckOpen),
    ("chuck_close", MAction::ChuckClose),
    ("part_catcher_advance", MAction::PartCatcherAdvance),
    ("part_catcher_retract", MAction::PartCatcherRetract),
    ("bar_feed", MAction::BarFeed),
    ("conveyor_on", MAction::ConveyorOn),
    ("conveyor_off", MAction::ConveyorOff),
    ("no_effect", MAction::NoEffect),
    ("c_axis_on", MAction::CAxisOn),
    ("c_axis_off", MAction::CAxisOff),
    ("live_tool_cw", MAction::LiveToolCw),
    ("live_tool_ccw", MAction::LiveToolCcw),
    ("live_tool_stop", MAction::LiveToolStop),
    ("sub_chuck_close", MAction::SubChuckClose),
    ("sub_chuck_open", MAction::SubChuckOpen),
];

/// Largest M code a table may hold.
pub const MAX_MCODE: u16 = 999;

impl MAction {
    /// The name of the action in a machine file.
    pub fn as_str(self) -> &'static str {
        ACTIONS.iter().find(|(_, a)| *a == self).map_or("no_effect", |(n, _)| n)
    }

    pub fn from_name(name: &str) -> Option<MAction> {
        ACTIONS.iter().find(|(n, _)| *n == name).map(|&(_, a)| a)
    }
}

/// The M codes the interpreter handles itself: never in a table.
pub fn reserved(code: u16) -> bool {
    matches!(code, 6 | 98 | 99 | 70..=73)
}

/// Code → action for one machine, sorted by code.
#[derive(Clone, Debug, PartialEq)]
pub struct McodeTable {
    codes: Vec<(u16, MAction)>,
}

impl McodeTable {
    /// The table of a dialect when the machine file has no `[mcodes]`: the codes both controls
    /// agree on (M0, M1, M2/M30, M3–M5, M7–M9), Fanuc gear ranges M41–M44, the override
    /// switches M48–M53, the common Haas lathe codes that move no axis (M12–M15, M19, M23/M24,
    /// M31/M33, M36/M37, M38/M39, M76/M77, M85/M86, M88/M89) and Haas's live-tool and C-axis codes
    /// (M133–M135, M154/M155); LinuxCNC's M48–M53 overrides, M60 pallet stop and M62–M68
    /// outputs. No tailstock or chuck codes: those differ from builder to builder.
    pub fn builtin(d: Dialect) -> McodeTable {
        use MAction::*;
        let mut codes = vec![
            (0, ProgramStop),
            (1, OptionalStop),
            (2, ProgramEnd),
            (30, ProgramEnd),
            (3, SpindleCw),
            (4, SpindleCcw),
            (5, SpindleStop),
            (7, CoolantOn),
            (8, CoolantOn),
            (9, CoolantOff),
        ];
        codes.extend((48..=53).map(|c| (c, NoEffect)));
        match d {
            Dialect::Fanuc => {
                codes.extend((41..=44).map(|c| (c, NoEffect)));
                // The common Haas lathe codes that move no axis: air blast (M12/M13), spindle
                // brake (M14/M15), thread chamfer-out on/off (M23/M24: the cycles take their
                // pull-out from their own words), spindle speed variation (M38/M39), display
                // (M76/M77), automatic door (M85/M86); the chip conveyor, high-pressure coolant
                // and part catcher by their actions; M19 orients the spindle, which stops it.
                codes.extend([12, 13, 14, 15, 23, 24, 38, 39, 76, 77, 85, 86].map(|c| (c, NoEffect)));
                codes.extend([
                    (19, SpindleStop),
                    (31, ConveyorOn),
                    (33, ConveyorOff),
                    (36, PartCatcherAdvance),
                    (37, PartCatcherRetract),
                    (88, CoolantOn),
                    (89, CoolantOff),
                ]);
                // Haas lathes' live tooling and C axis (their numbers clash with no code above).
                codes.extend([
                    (133, LiveToolCw),
                    (134, LiveToolCcw),
                    (135, LiveToolStop),
                    (154, CAxisOn),
                    (155, CAxisOff),
                ]);
            }
            Dialect::Linuxcnc => {
                codes.push((60, ProgramStop));
                codes.extend((62..=68).map(|c| (c, NoEffect)));
            }
        }
        codes.sort_by_key(|c| c.0);
        McodeTable { codes }
    }

    /// The built-in table of `d` with the actions named in `given` replaced by their codes (an
    /// action given with no codes has none). A code given for one action is taken out of every
    /// built-in action that had it. The caller has checked the codes (range, reserved, given
    /// twice).
    pub fn with(d: Dialect, given: &[(MAction, Vec<u16>)]) -> McodeTable {
        let mut codes = McodeTable::builtin(d).codes;
        codes.retain(|&(c, a)| !given.iter().any(|(ga, gc)| *ga == a || gc.contains(&c)));
        for (a, cs) in given {
            codes.extend(cs.iter().map(|&c| (c, *a)));
        }
        codes.sort_by_key(|c| c.0);
        McodeTable { codes }
    }

    /// What `code` does on this machine; `None` when the table does not know it.
    pub fn action(&self, code: u16) -> Option<MAction> {
        self.codes
            .binary_search_by_key(&code, |c| c.0)
            .ok()
            .map(|i| self.codes[i].1)
    }

    /// The codes of an action, ascending.
    pub fn codes_of(&self, a: MAction) -> impl Iterator<Item = u16> + '_ {
        self.codes.iter().filter(move |c| c.1 == a).map(|c| c.0)
    }

    /// Every (code, action), ascending by code.
    pub fn entries(&self) -> &[(u16, MAction)] {
        &self.codes
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_tables_know_the_common_codes_and_no_tailstock_code() {
        for d in [Dialect::Fanuc, Dialect::Linuxcnc] {
            let t = McodeTable::builtin(d);
            assert_eq!(t.action(3), Some(MAction::SpindleCw));
            assert_eq!(t.action(30), Some(MAction::ProgramEnd));
            assert_eq!(t.action(21), None);
            assert_eq!(t.codes_of(MAction::TailstockAdvance).count(), 0);
            assert!(t.entries().iter().all(|&(c, _)| !reserved(c)));
        }
        assert_eq!(McodeTable::builtin(Dialect::Fanuc).action(42), Some(MAction::NoEffect));
        assert_eq!(McodeTable::builtin(Dialect::Linuxcnc).action(42), None);
    }

    /// On a Haas set, 14 of 24 programs carried `unsupported` only for these codes.
    #[test]
    fn the_fanuc_table_knows_the_common_haas_codes_that_move_no_axis() {
        let t = McodeTable::builtin(Dialect::Fanuc);
        for c in [12, 13, 14, 15, 23, 24, 38, 39, 76, 77, 85, 86] {
            assert_eq!(t.action(c), Some(MAction::NoEffect), "M{c}");
        }
        assert_eq!(t.action(19), Some(MAction::SpindleStop));
        assert_eq!(t.action(31), Some(MAction::ConveyorOn));
        assert_eq!(t.action(33), Some(MAction::ConveyorOff));
        assert_eq!(t.action(88), Some(MAction::CoolantOn));
        assert_eq!(t.action(89), Some(MAction::CoolantOff));
        // M97 (Haas local subprogram call) runs blocks: never silently a no-effect code.
        assert_eq!(t.action(97), None);
        let entries = t.entries();
        assert!(
            entries.windows(2).all(|w| w[0].0 < w[1].0),
            "one action per code, sorted"
        );
    }

    #[test]
    fn the_fanuc_table_has_haas_live_tool_and_c_axis_codes_and_linuxcnc_none() {
        let f = McodeTable::builtin(Dialect::Fanuc);
        assert_eq!(f.action(133), Some(MAction::LiveToolCw));
        assert_eq!(f.action(134), Some(MAction::LiveToolCcw));
        assert_eq!(f.action(135), Some(MAction::LiveToolStop));
        assert_eq!(f.action(154), Some(MAction::CAxisOn));
        assert_eq!(f.action(155), Some(MAction::CAxisOff));
        let l = McodeTable::builtin(Dialect::Linuxcnc);
        for a in [
            MAction::CAxisOn,
            MAction::CAxisOff,
            MAction::LiveToolCw,
            MAction::LiveToolStop,
        ] {
            assert_eq!(l.codes_of(a).count(), 0, "{a:?}");
        }
    }

    #[test]
    fn given_actions_replace_their_builtin_codes_and_take_their_codes_from_others() {
        let t = McodeTable::with(
            Dialect::Fanuc,
            &[
                (MAction::TailstockAdvance, vec![21]),
                (MAction::CoolantOn, vec![8]),
                (MAction::ChuckOpen, vec![9]),
            ],
        );
        assert_eq!(t.action(21), Some(MAction::TailstockAdvance));
        assert_eq!(t.action(7), None, "coolant_on given: its built-in M7 is gone");
        assert_eq!(t.action(8), Some(MAction::CoolantOn));
        assert_eq!(
            t.action(9),
            Some(MAction::ChuckOpen),
            "the file's action wins over coolant_off"
        );
        // M9 went to chuck_open; the Fanuc table's M89 (Haas high-pressure coolant off) stays.
        assert_eq!(t.codes_of(MAction::CoolantOff).collect::<Vec<_>>(), vec![89]);
        for a in ACTIONS {
            assert_eq!(MAction::from_name(a.0), Some(a.1));
            assert_eq!(a.1.as_str(), a.0);
        }
    }
}
