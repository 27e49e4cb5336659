//! The tools read from a program: a kind per rule, the machine's tool kept or a station filled,
//! the sizes that must never hide a crash, comments in both dialects, and hostile comments.

use super::comment::{kind_of, read, size_of};
use super::ToolKind;
use crate::assume::reading::Reading;
use crate::assume::{Assumed, Assumption};
use crate::job::{self, EffectiveJob, Layer};
use crate::machine::{self, Machine};

fn linuxcnc() -> Machine {
    machine::from_toml(include_str!("../../../machines/linuxcnc-small-lathe.toml"), "small").unwrap()
}

/// The built-in machine with no tool in `station`.
fn builtin_without(station: u32) -> Machine {
    let mut m = Machine::builtin();
    m.tools.retain(|t| t.station != station);
    m
}

fn assumed(src: &str, m: &Machine) -> Assumed {
    crate::assume::assume(src.as_bytes(), "p.nc", m)
}

fn note(a: &Assumed, station: u32) -> Assumption {
    let key = format!("tools.{station}");
    a.notes
        .iter()
        .find(|n| n.key == key)
        .cloned()
        .unwrap_or_else(|| panic!("no note for {key}: {:?}", a.notes))
}

/// Only the tools of the assumed layer, applied to `m`: the machine the check would run.
fn apply_tools(a: &Assumed, m: &Machine) -> Machine {
    let mut layer = Layer::new("tools");
    layer.tools = a.layer.tools.clone();
    job::apply(m, &EffectiveJob::merge([&layer])).unwrap_or_else(|e| panic!("{e:?}\n{:?}", a.notes))
}

/// The value assumed for `station` of the built-in machine without its tool there.
fn filled(src: &str, station: u32) -> Assumption {
    let m = builtin_without(station);
    let a = assumed(src, &m);
    let n = note(&a, station);
    assert!(!n.kept, "{n:?}");
    assert!(a.layer.tools.iter().any(|t| t.value.tool.station == station));
    apply_tools(&a, &m);
    n
}

const BORE: &str = "O1000\nT0303 (BORING BAR)\nG97 S800 M3\nG0 X18 Z5\nG1 Z-20 F0.1\nG0 X16\nZ5\nG0 X200 Z200\nM30\n";
const BORE_BY_MOVES: &str = "O1000\nT0303\nG97 S800 M3\nG0 X18 Z5\nG1 Z-20 F0.1\nG0 X16\nZ5\nG0 X200 Z200\nM30\n";
const DRILL: &str = "T0606\nG97 S500 M3\nG0 X0 Z5\nG74 R1\nG74 Z-30 Q5000 F0.1\nG0 X100 Z100\nM30\n";
const G76: &str =
    "T0505\nG97 S500 M3\nG0 X32 Z5\nG76 P010060 Q100 R0.05\nG76 X27.4 Z-20 P1300 Q400 F2.0\nG0 X100 Z100\nM30\n";
const G92: &str = "T0505\nG97 S500 M3\nG0 X32 Z5\nG92 X29 Z-20 F2.0\nX28.5\nG0 X100 Z100\nM30\n";
const G32: &str = "T0505\nG97 S500 M3\nG0 X29 Z5\nG32 Z-20 F2.0\nG0 X32\nZ5\nG0 X100 Z100\nM30\n";
const PART: &str = "T0808\nG97 S500 M3\nG0 X54 Z-40\nG1 X-1 F0.05\nG0 X54\nG0 X100 Z100\nM30\n";
const GROOVE: &str =
    "T0404\nG97 S500 M3\nG0 X52 Z-20\nG1 X40 F0.05\nG0 X52\nZ-17.5\nG1 X40\nG0 X52\nG0 X100 Z100\nM30\n";
const FACE: &str = "T0101\nG97 S500 M3\nG0 X54 Z1\nG1 X-1.6 F0.1\nG0 Z3\nX54 Z0\nG1 X-1.6\nG0 X100 Z100\nM30\n";
const TURN: &str = "T0101\nG97 S500 M3\nG0 X46 Z3\nG1 Z-30 F0.2\nX52\nG0 Z3\nX42\nG1 Z-20\nX48\nG0 X100 Z100\nM30\n";

#[test]
fn a_boring_bar_is_read_from_the_comment_at_its_t_word() {
    let n = filled(BORE, 3);
    assert!(n.value.starts_with("T03 boring bar S"), "{n:?}");
    assert_eq!(n.reason, "the comment at line 2 says BORING BAR");
    assert_eq!(n.line, 2);
}

#[test]
fn a_boring_bar_is_read_from_passes_pulled_off_toward_the_axis() {
    let n = filled(BORE_BY_MOVES, 3);
    assert!(n.value.starts_with("T03 boring bar"), "{n:?}");
    assert_eq!(
        n.reason,
        "it bores: passes along -Z at X18 (line 5) pulled off toward the axis"
    );
}

#[test]
fn the_boring_bar_fits_the_smallest_bore_it_works_in() {
    let m = builtin_without(3);
    let a = assumed(BORE_BY_MOVES, &m);
    let t = &a.layer.tools[0].value.tool;
    // Its tip on the wall of the Ø18 bore, its far side clear of the opposite wall.
    let b = t.insert.aabb().union(t.holder.aabb());
    assert!(9.0 + b.min.x > -9.0, "{:?}", b);
}

#[test]
fn a_drill_is_read_from_feeds_on_the_spindle_axis() {
    let n = filled(DRILL, 6);
    assert!(n.value.starts_with("T06 drill Ø10"), "{n:?}");
    assert!(n.reason.starts_with("it feeds along the spindle axis to Z-30"), "{n:?}");
}

#[test]
fn a_threading_tool_is_read_from_g76_g92_and_g32() {
    for src in [G76, G92, G32] {
        let n = filled(src, 5);
        assert_eq!(n.value, "T05 threading tool 16ER 2ISO", "{src}");
        assert!(
            n.reason.starts_with("it threads: a pass along Z at 2 mm a revolution"),
            "{n:?}"
        );
    }
}

#[test]
fn a_parting_tool_is_read_from_a_plunge_to_the_axis_behind_the_face() {
    let n = filled(PART, 8);
    assert!(n.value.starts_with("T08 parting tool GROOVE 3x"), "{n:?}");
    assert!(n.reason.contains("plunges to the axis at Z-40"), "{n:?}");
}

#[test]
fn a_grooving_tool_is_read_from_plunges_no_wider_than_their_step() {
    let n = filled(GROOVE, 4);
    assert!(n.value.starts_with("T04 grooving tool GROOVE 2.5x"), "{n:?}");
    assert!(n.reason.contains("plunges to X40 at Z-20"), "{n:?}");
}

#[test]
fn a_facing_tool_is_read_from_radial_passes_at_the_face() {
    let n = filled(FACE, 1);
    assert!(n.value.starts_with("T01 facing tool"), "{n:?}");
    assert!(n.reason.starts_with("it faces to the axis at Z1"), "{n:?}");
}

#[test]
fn an_od_turning_tool_is_read_from_passes_pulled_off_outward() {
    let n = filled(TURN, 1);
    assert_eq!(n.value, "T01 OD turning tool CNMG 120408 in PCLNR 2525M12");
    assert_eq!(n.reason, "it turns: passes along -Z at X46 (line 4) pulled off outward");
}

#[test]
fn a_machine_tool_of_the_same_kind_is_kept() {
    let mut m = Machine::builtin();
    m.assume_setup = true;
    let a = assumed(BORE, &m);
    let n = note(&a, 3);
    assert!(n.kept, "{n:?}");
    assert_eq!(n.value, "T03 Boring bar D12 min bore 16");
    assert!(a.layer.tools.is_empty());
}

#[test]
fn the_shops_setup_stays_when_the_program_disagrees() {
    // assume = false: the machine file's T03 stays even though the comment says drill.
    let mut m = Machine::builtin();
    m.assume_setup = false;
    let a = assumed(&BORE.replace("BORING BAR", "DRILL 12MM"), &m);
    assert!(note(&a, 3).kept);
    assert!(a.layer.tools.is_empty());
}

#[test]
fn an_example_setup_gives_way_to_a_tool_of_another_kind() {
    let mut m = Machine::builtin();
    m.assume_setup = true;
    let a = assumed(&BORE.replace("BORING BAR", "DRILL 12MM"), &m);
    let n = note(&a, 3);
    assert!(!n.kept);
    assert!(n.value.starts_with("T03 drill Ø12"), "{n:?}");
    apply_tools(&a, &m);
}

#[test]
fn a_missing_station_is_filled_at_its_own_kind_of_tip() {
    let m = builtin_without(3);
    let a = assumed(BORE, &m);
    let t = &a.layer.tools[0].value.tool;
    assert_eq!(t.station, 3);
    // An axial tool takes an axial station's tip (T06's drill, the first one standing that way).
    assert_eq!(t.tip, m.tool(6).unwrap().tip);
    let applied = apply_tools(&a, &m);
    assert!(applied.tool(3).is_some());
}

#[test]
fn the_drill_is_never_larger_than_the_bore_a_later_boring_bar_starts_in() {
    for x in ["21", "20.4", "12"] {
        let src = format!(
            "T0606\nG97 S500 M3\nG0 X0 Z5\nG1 Z-30 F0.1\nG0 Z5\nG0 X100 Z100\nT0303\nG0 X{x} Z3\nG1 Z-25 F0.1\nG0 X8\nZ3\nG0 X100 Z100\nM30\n"
        );
        let m = builtin_without(6);
        let a = assumed(&src, &m);
        let t = &a
            .layer
            .tools
            .iter()
            .find(|t| t.value.tool.station == 6)
            .unwrap()
            .value
            .tool;
        let b = t.insert.aabb();
        let bore: f64 = x.parse().unwrap();
        assert!(b.max.x - b.min.x < bore - 0.4, "drill {:?} in a Ø{bore} bore", b);
        assert!(note(&a, 6).value.starts_with("T06 drill Ø"), "{:?}", a.notes);
        apply_tools(&a, &m);
    }
}

#[test]
fn comments_name_kinds_in_the_words_setters_write() {
    let cases = [
        ("BORING BAR", ToolKind::Boring),
        ("T3 BORE", ToolKind::Boring),
        ("ID ROUGH", ToolKind::Boring),
        ("OD ROUGH", ToolKind::OdTurning),
        ("FINISH", ToolKind::OdTurning),
        ("TAPER TURN", ToolKind::OdTurning),
        ("FACE AND TURN", ToolKind::OdTurning),
        ("FACE", ToolKind::Facing),
        ("drill 10mm", ToolKind::Drilling),
        ("U-DRILL D20", ToolKind::Drilling),
        ("CENTER DRILL", ToolKind::Drilling),
        ("SPOT", ToolKind::Drilling),
        ("TAP M10X1.5", ToolKind::Tapping),
        ("OD GROOVE 3MM", ToolKind::Grooving),
        ("PART OFF", ToolKind::Parting),
        ("CUT-OFF", ToolKind::Parting),
        ("CUTOFF 3MM", ToolKind::Parting),
        ("PARTING", ToolKind::Parting),
        ("OD THREAD M20X1.5", ToolKind::Threading),
    ];
    for (text, kind) in cases {
        assert_eq!(kind_of(text).map(|k| k.0), Some(kind), "{text}");
    }
    assert_eq!(kind_of("PART NO 1234"), None);
    assert_eq!(kind_of("PROGRAM 12"), None);
    assert_eq!(kind_of("ID GROOVE"), Some((ToolKind::Grooving, true)));
}

#[test]
fn comments_give_sizes_with_or_without_their_unit() {
    let d = ToolKind::Drilling;
    for (text, kind, want) in [
        ("DRILL 10MM", d, 10.0),
        ("D=10", d, 10.0),
        ("Ø12", d, 12.0),
        ("12MM DRILL", d, 12.0),
        ("drill 10", d, 10.0),
        ("T0606 DRILL 8.5", d, 8.5),
        ("BORING BAR D16", ToolKind::Boring, 16.0),
        ("TAP M10X1.5", ToolKind::Tapping, 10.0),
        ("GROOVE W2.5", ToolKind::Grooving, 2.5),
    ] {
        assert_eq!(size_of(text, kind, 1.0), Some(want), "{text}");
    }
    assert_eq!(size_of("DRILL .5", d, 25.4), Some(12.7));
    assert_eq!(size_of("DRILL 118 DEG", d, 1.0), None);
    assert_eq!(size_of("T3 BORE", ToolKind::Boring, 1.0), None);
    assert_eq!(size_of("OD ROUGH CNMG 120408", ToolKind::OdTurning, 1.0), None);
}

#[test]
fn fanuc_comments_are_read_at_the_station_the_moves_run() {
    let src = "O1\n(T6 DRILL 20)\nN30 T0101 (OD ROUGH)\nG0 X50 Z2\n(T3 BORE)\nT0303\nG0 X20 Z2\nT0505\n(THREAD)\nG0 X30 Z2\nT0606\nG0 X0 Z2\nM30\n";
    let said = read(&Reading::of(src.as_bytes(), &Machine::builtin()), 1.0);
    let got: Vec<(u32, ToolKind, u32)> = said.iter().map(|(s, c)| (*s, c.kind, c.line)).collect();
    assert_eq!(
        got,
        [
            (1, ToolKind::OdTurning, 3),
            (3, ToolKind::Boring, 5),
            (5, ToolKind::Threading, 9),
            (6, ToolKind::Drilling, 2),
        ]
    );
    assert_eq!(said[&6].size, Some(20.0));
}

#[test]
fn a_comment_next_to_a_t_word_is_not_taken_from_another_tool() {
    // `(T3 BORE)` after T0101 and `(FINISH)` before T0202 belong to the tools they stand by.
    let src = "T0101\n(T3 BORE)\nT0303\nG0 X20 Z2\nT0101\n(FINISH)\nT0202\nG0 X50 Z2\nM30\n";
    let said = read(&Reading::of(src.as_bytes(), &Machine::builtin()), 1.0);
    let got: Vec<(u32, ToolKind, u32)> = said.iter().map(|(s, c)| (*s, c.kind, c.line)).collect();
    assert_eq!(got, [(2, ToolKind::OdTurning, 6), (3, ToolKind::Boring, 2)]);
}

#[test]
fn linuxcnc_comments_are_read_at_the_tool_the_moves_run() {
    let src =
        "G18 G21 G7\nT3 M6 (drill 10mm)\nS500 M3\nG0 X0 Z5\nG1 Z-10 F50\nG0 Z5\nT2 M6 ; boring bar\nG0 X14 Z2\nM2\n";
    let m = linuxcnc();
    let said = read(&Reading::of(src.as_bytes(), &m), 1.0);
    assert_eq!(said[&3].kind, ToolKind::Drilling);
    assert_eq!(said[&3].size, Some(10.0));
    assert_eq!(said[&2].kind, ToolKind::Boring);
}

#[test]
fn machine_tools_are_known_by_their_names() {
    let kinds: Vec<Option<ToolKind>> = Machine::builtin().tools.iter().map(ToolKind::of_tool).collect();
    use ToolKind::*;
    assert_eq!(
        kinds,
        [
            Some(OdTurning),
            Some(OdTurning),
            Some(Boring),
            Some(Grooving),
            Some(Threading),
            Some(Drilling),
            Some(Boring),
            Some(Parting)
        ]
    );
    let small: Vec<Option<ToolKind>> = linuxcnc().tools.iter().map(ToolKind::of_tool).collect();
    assert_eq!(small, [Some(OdTurning), Some(Boring), Some(Threading), Some(Parting)]);
}

#[test]
fn every_assumed_tool_is_a_valid_setup_on_the_builtin_machine() {
    let mut m = Machine::builtin();
    m.assume_setup = true;
    // Each program's tool in stations whose machine tools are of other kinds.
    let programs = [
        BORE.replace("T0303", "T0101"),
        DRILL.replace("T0606", "T0202"),
        G76.replace("T0505", "T0303"),
        PART.replace("T0808", "T0606"),
        GROOVE.replace("T0404", "T0707"),
        FACE.replace("T0101", "T0808"),
        TURN.replace("T0101", "T0303"),
        BORE.replace("BORING BAR", "TAP M10")
            .replace("X18", "X0")
            .replace("X16", "X0"),
        BORE.replace("BORING BAR", "ID THREAD"),
        BORE.replace("BORING BAR", "ID GROOVE"),
    ];
    for src in &programs {
        let a = assumed(src, &m);
        assert_eq!(a.layer.tools.len(), 1, "{src}\n{:?}", a.notes);
        apply_tools(&a, &m);
    }
    // And every station filled at once, on a turret with no tools at all.
    let mut bare = Machine::builtin();
    bare.tools.clear();
    let all = [BORE, DRILL, G92, PART, GROOVE, TURN]
        .map(|p| p.replace("M30\n", ""))
        .concat();
    let a = assumed(&all, &bare);
    assert_eq!(a.layer.tools.len(), 6, "{:?}", a.notes);
    apply_tools(&a, &bare);
}

#[test]
fn every_assumed_tool_is_a_valid_setup_on_the_small_linuxcnc_lathe() {
    let mut m = linuxcnc();
    m.assume_setup = true;
    let head = "G18 G21 G7 G95\n";
    let programs = [
        "T1 M6 (BORING BAR)\nS500 M3\nG0 X12 Z2\nG1 Z-15 F0.1\nG0 X10\nZ2\nG0 X60 Z60\nM2\n",
        "T4 M6 (drill 8mm)\nS500 M3\nG0 X0 Z2\nG1 Z-15 F0.1\nG0 Z2\nG0 X60 Z60\nM2\n",
        "T2 M6 (OD ROUGH)\nS500 M3\nG0 X22 Z2\nG1 Z-15 F0.1\nX26\nG0 Z2\nG0 X60 Z60\nM2\n",
        "T3 M6 (GROOVE 2MM)\nS500 M3\nG0 X27 Z-10\nG1 X20 F0.05\nG0 X27\nG0 X60 Z60\nM2\n",
        "T1 M6 (THREAD)\nS500 M3\nG0 X24 Z2\nG33 Z-10 K1.5\nG0 X27\nZ2\nG0 X60 Z60\nM2\n",
    ];
    for p in programs {
        let src = format!("{head}{p}");
        let a = assumed(&src, &m);
        assert_eq!(a.layer.tools.len(), 1, "{src}\n{:?}", a.notes);
        let applied = apply_tools(&a, &m);
        // The chart a LinuxCNC machine reads its tip directions on.
        let t = &a.layer.tools[0].value.tool;
        assert_eq!(applied.tool(t.station).unwrap().tip_direction, t.tip_direction);
    }
}

#[test]
fn garbage_comments_and_t_words_give_no_panic() {
    let mut m = Machine::builtin();
    m.assume_setup = true;
    let bad: [&[u8]; 16] = [
        b"(((((\n",
        b"T\nT0303 (\nG0 X20 Z2\n",
        b"T0303 ()\nG0 X20 Z2\n",
        b"T0606 (\xc3\x98)\n(D=)(D=.)\nG0 X0 Z2\nG1 Z-5 F0.1\n",
        b"T0606 (DRILL 1e400)\nG0 X0 Z2\nG1 Z-5 F0.1\n",
        b"T0606 (DRILL 99999999999999999999999999999999)\nG0 X0 Z2\nG1 Z-5 F0.1\n",
        b"T0606 (DRILL 0.0001)\nG0 X0 Z2\nG1 Z-5 F0.1\n",
        b"T0606 (DRILL 0)\nG0 X0 Z2\nG1 Z-5 F0.1\n",
        b"T99999999999999999999 (BORE)\nG0 X20 Z2\n",
        b"(T99999999999999999999 BORE)\n(T0 DRILL)\n(T BORE)\n",
        b"T0303 (BORE) ; ;;; (\nG0 X20 Z2\nG1 Z-5 F0.1\nG0 X18\n",
        b"T0303 (\xff\xfe BORING \x00 BAR \xe2\x8c\x80..5)\nG0 X20 Z2\nG1 Z-5 F0.1\n",
        b"T0404 (GROOVE W0.0000001)\nG0 X52 Z-10\nG1 X40 F0.05\nG0 X52\n",
        b"T0808 (PART 200MM)\nG0 X54 Z-40\nG1 X0 F0.05\n",
        b"T0303 (BORING BAR D999)\nG0 X20 Z2\nG1 Z-5 F0.1\nG0 X18\n",
        b"T0505 (THREAD)\nG0 X20 Z2\nG32 Z-5 F150\nG0 X30\n",
    ];
    for src in bad {
        let a = crate::assume::assume(src, "p.nc", &m);
        let mut layer = Layer::new("tools");
        layer.tools = a.layer.tools.clone();
        // Whatever it assumed is a tool the job code can apply (or reject with an error).
        let _ = job::apply(&m, &EffectiveJob::merge([&layer]));
    }
}

/// A drill at the axis to `depth`, then the T03 boring bar along the bore at X21 to Z-25.
fn drill_then_bore(depth: &str) -> String {
    format!(
        "T0606\nG97 S1200 M3\nG0 X0 Z5\nG1 Z{depth} F0.08\nG0 Z5\nG28 U0 W0\nT0303\nG97 S800 M3\nG0 X21 Z2\nG1 Z-25 F0.1\nG1 U-1. W1.\nG0 Z5\nG28 U0 W0\nM30\n"
    )
}

#[test]
fn the_assumed_drill_never_hides_a_boring_bar_entering_a_bore_no_move_made() {
    let m = builtin_without(6);
    let crashes = |src: &str| {
        let a = assumed(src, &m);
        let applied = apply_tools(&a, &m);
        crate::pipeline::check(src.as_bytes(), &applied, &crate::pipeline::Settings::default())
            .findings
            .into_iter()
            .filter(|f| f.severity == crate::finding::Severity::Error)
            .map(|f| (f.line, f.kind))
            .collect::<Vec<_>>()
    };
    // Drilled 30 deep: the bar bores the drilled hole and meets nothing it should not.
    assert_eq!(crashes(&drill_then_bore("-30")), []);
    // Drilled 10 deep: past it the bar meets the core no move removed.
    let found = crashes(&drill_then_bore("-10"));
    assert!(found.iter().any(|(line, _)| *line == 10), "{found:?}");
}

#[test]
fn a_feed_alone_never_makes_a_thread_or_a_tap() {
    // An inch program roughing at 0.02 in a revolution (0.508 mm) in a G71 cycle and drilling at
    // 0.025 in a revolution: turning and drilling, not threading and tapping.
    let turn = "G20 G99\nT0505\nG97 S800 M3\nG0 X2. Z0.1\nG71 U0.025 R0.01\nG71 P10 Q20 U0.01 W0 F0.02\nN10 G0 X1.\nG1 Z-2.\nN20 X2.\nG0 X4. Z4.\nM30\n";
    let n = filled(turn, 5);
    assert!(n.value.starts_with("T05 OD turning tool"), "{n:?}");
    let drill = "G20 G99\nT0606\nG97 S800 M3\nG0 X0 Z0.1\nG1 Z-1. F0.025\nG0 Z0.1\nG0 X4. Z4.\nM30\n";
    let n = filled(drill, 6);
    assert!(n.value.starts_with("T06 drill"), "{n:?}");
}

#[test]
fn a_thread_is_internal_only_when_most_pull_offs_go_toward_the_axis() {
    // A G76 whose first passes lie outside its start point (the cycle's X is the root) pulls off
    // toward the axis three times and away from it more often: an external thread.
    let src = "G20 G99\nT0505 (THREADING TOOL)\nG97 S800 M3\nG0 X0.25 Z0.1\nG76 X0.2 Z-0.25 K0.044 D0.01 F0.05\nG0 X3. Z3.\nM30\n";
    let n = filled(src, 5);
    assert!(n.value.starts_with("T05 threading tool 16ER"), "{n:?}");
    // Passes pulled off toward the axis each time: internal.
    let int = "G21 G99\nT0505\nG97 S500 M3\nG0 X18 Z5\nG32 Z-20 F1.5\nG0 X16\nZ5\nX18.4\nG32 Z-20\nG0 X16\nZ5\nG0 X100 Z100\nM30\n";
    let n = filled(int, 5);
    assert!(n.value.contains("IR"), "{n:?}");
}

#[test]
fn german_words_and_step_comments_name_tools() {
    for (text, kind, internal) in [
        ("CCMT Aussendrehen", ToolKind::OdTurning, false),
        ("VCMT Innendrehen", ToolKind::Boring, true),
        ("Abspanen ausdrehen", ToolKind::Boring, true),
        ("Außengewinde MMT11er AG60", ToolKind::Threading, false),
        ("Innengewinde MMT11ir AG60", ToolKind::Threading, true),
        ("Einstechen Innen", ToolKind::Grooving, true),
        ("Abstechen 3 mm", ToolKind::Parting, false),
        ("Spiralbohrer 8", ToolKind::Drilling, false),
        ("Gewindebohrer M8", ToolKind::Tapping, false),
        ("Bohrstange D16", ToolKind::Boring, true),
    ] {
        assert_eq!(kind_of(text), Some((kind, internal)), "{text}");
    }
    // A CAM step's comment names the station's tool after `T2:`.
    let src =
        "T2 M6\nG0 X60 Z90\n(Step 4: abspanen | T2: CCMT Aussendrehen)\nS800 M3\nG0 X30 Z2\nG1 Z-10 F0.2\nG0 X40\nM2\n";
    let r = Reading::of(src.as_bytes(), &linuxcnc());
    let said = read(&r, 1.0);
    assert_eq!(said.get(&2).map(|s| s.kind), Some(ToolKind::OdTurning), "{said:?}");
}

#[test]
fn a_cam_step_heading_names_the_tool_no_other_comment_names() {
    // `(Werkzeug T05)` says nothing of the tool; the step heading after the tool change does.
    let src = "(Werkzeug T05)\nT5 M6\nG0 X52 Z6\n(Step 3: abspanen)\nS800 M3\nG0 X20 Z1\n(STEP: 5. Abspanen Ausdrehen, 2, 0.0 5)\nG1 Z-10 F0.2\nG0 X18\nG0 Z6\n(Werkzeug T09)\nT9 M6\n(STEP: 6. Planen)\nG0 X60 Z1\nG1 X-1 F0.1\nG0 Z6\nM2\n";
    let r = Reading::of(src.as_bytes(), &linuxcnc());
    let said = read(&r, 1.0);
    let boring: Vec<_> = said.values().filter(|s| s.kind == ToolKind::Boring).collect();
    assert!(
        boring.len() == 1 && boring[0].line == 7 && boring[0].internal,
        "{said:?}"
    );
    // Without the heading's tool word, nothing names T5's tool.
    let src = src.replace("Ausdrehen", "");
    let r = Reading::of(src.as_bytes(), &linuxcnc());
    assert!(read(&r, 1.0).values().all(|s| s.kind != ToolKind::Boring));
}

#[test]
fn an_internal_groove_is_read_from_plunges_away_from_the_axis() {
    let src = "O0001\nG00 T0505\nG97 S450 M03\nX97.04\nZ-45.\nG01 X118. F0.3\nG00 X97.\nZ-42.\nG01 X118.\nG00 X97.\nZ150.\nM30\n";
    let n = filled(src, 5);
    assert!(
        n.value.starts_with("T05 grooving tool") && n.value.ends_with("INT"),
        "{n:?}"
    );
}
