//! The setup read from the program: one test per rule of docs/assume.md (the tools' rules are
//! in `tools/tests.rs`).

use super::*;
use crate::machine::Machine;

/// The built-in machine, its setup an example (as shipped).
fn example() -> Machine {
    let m = Machine::builtin();
    assert!(m.assume_setup, "the built-in machine's setup is an example");
    m
}

fn note<'a>(a: &'a Assumed, key: &str) -> &'a Assumption {
    a.notes
        .iter()
        .find(|n| n.key == key)
        .unwrap_or_else(|| panic!("no `{key}` note in {:?}", a.notes))
}

fn stock(a: &Assumed) -> &crate::job::JobStock {
    &a.layer.stock.as_ref().expect("a stock is assumed").value
}

/// A program roughing a Ø40 profile out of a bar it never names: G71 from X62, profile up
/// to X58 at its largest.
const G71: &str = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X62. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X40.\nG1 Z-30.\nX58. Z-40.\nN20 X62.\nG0 X100. Z100.\nM30\n";

#[test]
fn a_bar_is_read_from_a_g71_profile_not_from_its_passes_in_the_air() {
    let a = assume(G71.as_bytes(), "p.nc", &example());
    // The profile reaches X58: the bar is at least that, rounded up to a stock size (60), and
    // no bigger than the cycle's start point X62 allows.
    assert_eq!(stock(&a).diameter, 60.0, "{:?}", a.notes);
    assert!(!note(&a, "stock").kept);
    assert!(note(&a, "stock").reason.contains("X58"), "{:?}", note(&a, "stock"));
}

#[test]
fn a_stock_comment_gives_the_diameter_as_written() {
    let src = G71.replace("T0101\n", "T0101 (STOCK DIA 63)\n");
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 63.0);
    assert!(note(&a, "stock").reason.contains("comment at line 2"));
    // A move to the stock's size named in its comment, in inches.
    let src =
        "G20 G18\nT0101\nG97 S800 M3\nG0 X1.55 Z0.1 (STOCK SIZE)\nG1 Z0. F0.01\nG1 X0.5\nG1 Z-0.4\nG0 X2. Z1.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!((stock(&a).diameter - 1.55 * 25.4).abs() < 1e-9, "{:?}", a.notes);
}

#[test]
fn a_comment_word_that_only_contains_a_marker_is_no_size() {
    // DIAGONAL is not DIA, GOOD is not OD: the crash program's comment gives no bar.
    let src = "G21\nT0101\nG97 S800 M3\nG0 X48. Z3.\nX52. Z0.67 (DIAGONAL PAST THE BAR, GOOD)\nG0 X60.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!(a.layer.stock.is_none(), "{:?}", a.notes);
}

#[test]
fn the_face_is_the_highest_facing_pass_and_program_zero_follows_it() {
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X54. Z1.5\nG1 X-1.6 F0.2\nG0 Z3.\nX54. Z0.\nG1 X-1.6\nG0 Z3.\nX46.\nG1 Z-30.\nU2. W1.\nG0 X100. Z100.\nM30\n";
    let mut m = example();
    m.stock = None;
    let a = assume(src.as_bytes(), "p.nc", &m);
    let s = stock(&a);
    let zero = a.layer.program_zero_z.as_ref().expect("program zero").value;
    // The raw face stands at program Z1.5, the highest pass.
    assert!((s.front.unwrap() - zero - 1.5).abs() < 1e-9);
    // The bar: wider than the X46 pass, no wider than the facing start X54 → Ø48.
    assert_eq!(s.diameter, 48.0, "{:?}", a.notes);
}

#[test]
fn a_machine_bar_that_agrees_with_the_program_stays() {
    // programs/od_turning.nc on the built-in machine: its Ø50 bar 2 mm ahead of Z0 fits.
    let src = std::fs::read("programs/od_turning.nc").unwrap();
    let a = assume(&src, "p.nc", &example());
    assert!(a.layer.stock.is_none());
    assert!(note(&a, "stock").kept, "{:?}", a.notes);
    assert!(a.is_empty() || a.notes.iter().filter(|n| !n.kept).all(|n| n.key != "stock"));
}

#[test]
fn the_stick_out_leaves_room_for_the_deepest_cut_and_a_part_off() {
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X52. Z2.\nG1 X48. Z0. F0.2\nG1 Z-110.\nG0 X60.\nZ2.\nT0808\nG0 X54. Z-113.\nG1 X-1. F0.05\nG0 X60.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    let s = stock(&a);
    let zero = a.layer.program_zero_z.as_ref().unwrap().value;
    // The jaws' faces are at z 0: the deepest cut (Z-113) stays 10 mm in front of them.
    let deepest_z = zero - 113.0;
    assert!(
        (deepest_z - bar::PART_OFF_ROOM).abs() < 1e-6,
        "zero {zero} front {:?}",
        s.front
    );
    // The bar reaches into the chuck as the machine's did.
    assert!(s.length > s.front.unwrap());
}

#[test]
fn a_tube_is_read_only_when_the_first_tool_to_cut_bores() {
    let bore_first = "G21 G18 G99\nT0303\nG97 S800 M3\nG0 X30. Z2.\nG1 Z-20. F0.15\nG1 U-1. W0.5\nG0 Z2.\nX34.\nG1 Z-20.\nU-1. W0.5\nG0 Z2.\nG0 X100. Z100.\nT0101\nG0 X62. Z2.\nG1 Z-30. F0.2\nU2. W1.\nG0 X100. Z100.\nM30\n";
    let a = assume(bore_first.as_bytes(), "p.nc", &example());
    let s = stock(&a);
    // Material under the first pass at X30: bore Ø28.
    assert_eq!(s.bore, 30.0 - bar::BORE_MATERIAL, "{:?}", a.notes);
    // The same passes after OD turning bore into a bar no drill opened: no tube, so the
    // boring bar entering the solid bar is still found.
    let turn_first = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X62. Z2.\nG1 Z-30. F0.2\nU2. W1.\nG0 X100. Z100.\nT0303\nG0 X30. Z2.\nG1 Z-20. F0.15\nG1 U-1. W0.5\nG0 Z2.\nG0 X100. Z100.\nM30\n";
    let a = assume(turn_first.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).bore, 0.0, "{:?}", a.notes);
}

#[test]
fn a_program_that_never_starts_the_spindle_is_read_as_a_dry_run() {
    let src = G71.replace(" M3", "");
    let mut m = example();
    m.stock = None;
    let a = assume(src.as_bytes(), "p.nc", &m);
    assert!(a.layer.stock.is_none(), "{:?}", a.notes);
}

#[test]
fn the_shops_own_bar_is_never_replaced() {
    let mut m = example();
    m.assume_setup = false;
    let a = assume(G71.as_bytes(), "p.nc", &m);
    assert!(a.layer.stock.is_none() && a.layer.program_zero_z.is_none());
    // A machine file with no bar at all is given one.
    m.stock = None;
    let a = assume(G71.as_bytes(), "p.nc", &m);
    assert_eq!(stock(&a).diameter, 60.0);
}

fn small_lathe() -> Machine {
    let text = std::fs::read_to_string("machines/linuxcnc-small-lathe.toml").unwrap();
    let mut m = crate::machine::from_toml(&text, "small.toml").unwrap();
    m.assume_setup = true;
    m
}

#[test]
fn linuxcnc_tool_numbers_past_the_turret_go_to_stations_the_program_leaves_free() {
    let src = "G18 G21 G7\nT1 M6\nS800 M3\nG0 X30 Z2\nG1 Z-10 F100\nG0 X40\nT7 M6\nG0 X30 Z2\nG1 Z-5\nG0 X40\nT303 M6\nG0 X30 Z2\nM2\n";
    let a = assume(src.as_bytes(), "p.ngc", &small_lathe());
    let map: Vec<(u32, u32)> = a.layer.tool_numbers.iter().map(|s| s.value).collect();
    // T1 stays in station 1; T7 takes the first free station; T303 its own digits' station 3.
    assert_eq!(map, vec![(1, 1), (7, 2), (303, 3)]);
    assert_eq!(note(&a, "tool_numbers").value, "T7 in station 2, T303 in station 3");
    // The map is applied: no "no station" finding is left.
    let m = small_lathe();
    let eff = crate::job::EffectiveJob::merge([&a.layer]);
    let applied = crate::job::apply(&m, &eff).expect("the assumed setup fits");
    let out = crate::pipeline::check(src.as_bytes(), &applied, &crate::pipeline::Settings::default());
    assert!(
        out.findings.iter().all(|f| !f.message.contains("no station")),
        "{:?}",
        out.findings
    );
}

#[test]
fn the_tailstock_stays_only_when_the_program_calls_for_it() {
    let m = small_lathe();
    assert!(m.tailstock.is_some() && m.tailstock_advanced);
    let short = "G18 G21 G7\nT1 M6\nS800 M3\nG0 X20 Z2\nG1 Z-10 F100\nG0 X30\nM2\n";
    let a = assume(short.as_bytes(), "p.ngc", &m);
    assert_eq!(a.layer.tailstock_in_use.as_ref().map(|s| s.value), Some(false));
    let named = short.replace("S800 M3", "S800 M3 (LIVE CENTER IN)");
    let a = assume(named.as_bytes(), "p.ngc", &m);
    assert_ne!(a.layer.tailstock_in_use.as_ref().map(|s| s.value), Some(false));
    assert!(note(&a, "tailstock").reason.contains("live center"), "{:?}", a.notes);
}

#[test]
fn a_fanuc_program_on_a_linuxcnc_example_machine_is_read_as_fanuc() {
    let src = "O0001\nN1 T0202\nN2 G97 S800 M3\nN3 G0 X30. Z2.\nN4 G1 Z-10. F0.2\nN5 G0 X40.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &small_lathe());
    assert_eq!(
        a.layer.dialect.as_ref().map(|d| d.value),
        Some(crate::job::DialectChoice::Fanuc)
    );
    // A shop's own machine keeps its dialect.
    let mut m = small_lathe();
    m.assume_setup = false;
    assert!(assume(src.as_bytes(), "p.nc", &m).layer.dialect.is_none());
}

#[test]
fn what_is_read_is_applied_as_a_job_is() {
    let m = example();
    let a = apply(G71.as_bytes(), "p.nc", &m);
    let (applied, job) = a.machine.expect("the read setup fits the built-in machine");
    assert_eq!(job.layers, vec![LABEL.to_string()]);
    assert_eq!(applied.stock.as_ref().unwrap().diameter, 60.0);
    // The jaws close on the new bar, as they do on a job's.
    assert_ne!(applied.chuck, m.chuck);
    assert!(a.notes.iter().any(|n| n.key == "stock" && !n.kept));
    // Nothing read (a program that never moves): the machine as it is.
    let none = apply(b"G21\nM30\n", "p.nc", &m);
    assert!(none.machine.is_none() && none.notes.is_empty());
}

#[test]
fn hostile_programs_give_no_panic_and_no_absurd_bar() {
    let bad: [&[u8]; 6] = [
        b"",
        b"G0 X1e30 Z1e30\nM3 S100\nG1 Z-1e30 F1\n",
        b"M3 S100\nG1 X-0 Z-0 F1\nG1 X0 Z0\n",
        b"(STOCK DIA 1e400)\nM3 S100\nG1 X10 Z-5 F1\n",
        b"(STOCK DIA -5)\n(BAR OD)\nM3 S100\nG1 X10 Z-5 F1\n",
        b"\xff\xfe(\xe2\x8c\x80 STOCK \x00 DIA \xe2)\nT99999999999 M6\n",
    ];
    for src in bad {
        let a = assume(src, "p.nc", &example());
        if let Some(s) = &a.layer.stock {
            // A bar of a finite size, or none (a blank no chuck holds).
            assert!(
                s.value.none || s.value.diameter.is_finite() && s.value.diameter > 0.0,
                "{:?}",
                a.notes
            );
        }
        // Whatever it assumed applies, or is refused with an error.
        let _ = crate::job::apply(&example(), &crate::job::EffectiveJob::merge([&a.layer]));
    }
}

/// The front face in program Z of what was assumed: the bar's front less program zero.
fn face_z(a: &Assumed) -> f64 {
    let zero = a.layer.program_zero_z.as_ref().expect("program zero").value;
    stock(a).front.expect("front") - zero
}

#[test]
fn the_machine_files_example_face_stays_only_where_the_program_leaves_room_for_it() {
    // The built-in machine's example bar stands 2 mm ahead of Z0. This program rapids to Z1.5
    // inside the bar before it faces at Z1: its raw face is at Z1.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X40. Z1.5\nX54.\nG1 Z1. F0.2\nG1 X-1.6\nG0 Z3.\nX42.\nG1 Z-30.\nX50.\nG0 X100. Z100.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!((face_z(&a) - 1.0).abs() < 1e-9, "{:?}", a.notes);
    // No facing pass, and a rapid to Z1 inside the bar: the face at program Z0.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X46. Z1.\nG1 Z-30. F0.2\nX52.\nG0 Z2.\nG0 X100. Z100.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!(face_z(&a).abs() < 1e-9, "{:?}", a.notes);
    // A thread cycle starting at Z2, the example face's plane: its insert would stand in the
    // raw face, so the face is at Z0.
    let src = "G21 G18 G99\nT0505\nG97 S500 M3\nG0 X25. Z2.\nG76 P010060 Q100 R0.05\nG76 X22.4 Z-20 P1300 Q400 F2.0\nG0 X100 Z100\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!(face_z(&a).abs() < 1e-9, "{:?}", a.notes);
}

#[test]
fn a_rapid_into_the_middle_a_facing_pass_left_shows_the_face_is_at_the_facing_pass() {
    // The program faces at Z0 only down to X12 and later rapids to X10 at Z1 for a chamfer: it
    // takes its raw face to be at Z0, so the example face 2 mm ahead does not stay.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X54. Z0.\nG1 X12. F0.2\nG0 Z2.\nX44.\nG1 Z-30.\nX52.\nG0 Z1.\nX10.\nG1 Z0. F0.1\nX14. Z-2.\nG0 X100. Z100.\nM30\n";
    let m = example();
    let face = |a: &Assumed| {
        let zero = a.layer.program_zero_z.as_ref().map_or(m.program_zero_z, |z| z.value);
        let front = a.layer.stock.as_ref().and_then(|s| s.value.front);
        front.unwrap_or(m.stock.as_ref().map_or(0.0, |s| s.front)) - zero
    };
    let a = assume(src.as_bytes(), "p.nc", &m);
    assert!(face(&a).abs() < 1e-9, "{:?}", a.notes);
    // The same without the chamfer's rapid: nothing says the example face is not there.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X54. Z0.\nG1 X12. F0.2\nG0 Z2.\nX44.\nG1 Z-30.\nX52.\nG0 X100. Z100.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &m);
    assert!((face(&a) - 2.0).abs() < 1e-9, "{:?}", a.notes);
}

#[test]
fn a_short_lead_in_on_a_slant_after_a_rapid_is_no_cut() {
    // Stepped facing passes, each entered from X14.47 on a 0.2 mm slant: the bar is no wider
    // than the rapids at X14.47 allow, so the slants start in the air (Ø14 bar, not Ø16).
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X14.47 Z2.7\nG1 X14.32 Z2.5 F0.1\nX13.8 Z2.42\nX13.7 Z2.4\nX4.\nG0 Z3.\nX14.47\nZ2.3\nG1 X14.32 Z2.1\nX13.8 Z2.02\nX13.7 Z2.\nX4.\nG0 Z3.\nG0 X100. Z100.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 14.0, "{:?}", a.notes);
}

#[test]
fn outside_what_an_earlier_pass_turned_there_is_only_air() {
    // The OD is turned to X24 over 30 mm; a later lead-out arc beyond X24 over that length cuts
    // nothing: the bar is Ø25, not sized by the arc.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X24. Z2.\nG1 Z-30. F0.2\nX27.\nG0 Z2.\nX20. Z0.\nG1 Z-5.\nG2 X30. Z-10. R5.\nG0 X100. Z100.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 25.0, "{:?}", a.notes);
}

#[test]
fn a_feed_from_the_face_into_a_facing_pass_starts_outside_the_bar() {
    // A tool beyond the axis rapids to at the face, feeds 2 mm along Z and faces 2 mm
    // off: the bar is inside X25.5 (the largest stock size 2 mm inside it).
    let src = "T0101\nG00 Z0 X-25.5\nG97 M03 S500\nG01 F50 Z-2\nG01 F50 X0\nG00 Z5\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 22.0, "{:?}", a.notes);
}

#[test]
fn a_german_stock_comment_gives_the_diameter() {
    let src = G71.replace("T0101\n", "(Rohteil Außendurchmesser: 63.000 mm)\nT0101\n");
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 63.0, "{:?}", a.notes);
    // An inner diameter is a tube's bore, not the bar.
    let src = G71.replace("T0101\n", "(Rohteil Innendurchmesser: 20.000 mm)\nT0101\n");
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert_eq!(stock(&a).diameter, 60.0, "{:?}", a.notes);
}

#[test]
fn what_a_tool_cuts_inside_the_part_lies_inside_the_bar() {
    // A tube faced from X86 out to X118, then grooved inside from X97 out to X118: the bar is
    // no smaller than the groove's floor.
    let src = "O0001\nG00 T0202\nG97 S450 M03\nX86.\nZ0.25\nG01 X118. F0.3\nZ0.45\nG00 X96.\nG01 Z-51.4\nX95.6\nG00 Z0.45\nZ220.\nT0505\nX97.04\nZ-45.\nG01 X118. F0.3\nG00 X97.\nZ150.\nM30\n";
    let a = assume(src.as_bytes(), "p.nc", &example());
    assert!(stock(&a).diameter >= 118.0 - 1e-9, "{:?}", a.notes);
}

#[test]
fn linuxcnc_operator_messages_keep_the_linuxcnc_dialect() {
    let src = "O0001\nN1 T0202\n(MSG, load the roughing tool)\nM0\nN2 S800 M3\nN3 G0 X30. Z2.\nN4 G1 Z-10. F0.2\nN5 G0 X40.\nM2\n";
    let a = assume(src.as_bytes(), "p.ngc", &small_lathe());
    assert!(a.layer.dialect.is_none(), "{:?}", a.notes);
}

/// A flange turned at X300: no jaws of the built-in chuck close on a Ø300 bar, so the blank is
/// held some other way. No stock is assumed (the note says why and that its material goes
/// unchecked), and program zero is still read from the face and the deepest cut (Z-90, past the
/// machine file's stick-out).
#[test]
fn a_blank_wider_than_the_chuck_can_grip_is_no_bar() {
    let src = "G21 G18 G99\nT0101\nG97 S300 M3\nG0 X304. Z2.\nG1 Z0. F0.2\nX200.\nG0 Z2.\nX300.\nG1 Z-90.\nG0 X320. Z100.\nM30\n";
    let m = example();
    let a = assume(src.as_bytes(), "p.nc", &m);
    let s = stock(&a);
    assert!(s.none, "{:?}", a.notes);
    let n = note(&a, "stock");
    assert!(!n.kept);
    assert!(n.reason.contains("wider than this chuck can grip"), "{n:?}");
    assert!(n.reason.contains("not found"), "{n:?}");
    assert!(note(&a, "program_zero_z").reason.contains("Z-90"), "{:?}", a.notes);
    assert!(a.layer.program_zero_z.is_some());
    let applied = apply(src.as_bytes(), "p.nc", &m);
    let (read, _) = applied.machine.expect("the setup fits the machine");
    assert!(read.stock.is_none());
    // The same program at X100 is a bar in the jaws.
    let small = src
        .replace("X304.", "X104.")
        .replace("X300.", "X100.")
        .replace("X200.", "X60.");
    let a = assume(small.as_bytes(), "p.nc", &m);
    assert!(!stock(&a).none, "{:?}", a.notes);
}

/// The reading's lines are those `str::lines` cuts from the lossy text (line ends `\n` and
/// `\r\n`, a lone `\r` kept, bytes that are not UTF-8 replaced, a last line with no end).
#[test]
fn the_readings_lines_are_the_lossy_texts_lines() {
    use proptest::prelude::*;
    let bytes = prop::collection::vec(
        prop::sample::select(vec![b'\n', b'\r', b'G', b'1', b' ', 0xff, 0xc3, 0xa9, 0xe2]),
        0..40,
    );
    proptest!(|(src in bytes)| {
        let text = String::from_utf8_lossy(&src);
        let want: Vec<&str> = text.lines().collect();
        let lines = reading::Lines::of(&src);
        let got: Vec<String> = lines.iter().map(|l| l.into_owned()).collect();
        prop_assert_eq!(&got, &want);
        prop_assert_eq!(lines.len(), want.len());
        prop_assert!(lines.get(want.len()).is_none());
    });
}

/// Issue 26's ten million short lines took 2 GB for their setup reading (72 bytes a segment and
/// a copy of the text): the reading now holds a few bytes a line beside the source, so its
/// memory stays a small multiple of the file's size.
#[test]
fn a_long_programs_setup_reading_holds_a_few_bytes_a_line() {
    let mut src = String::from("G21 G18 G99 F0.2\nT0101\nM3 S500\n");
    for _ in 0..25_000 {
        src += "G0 X52.010 Z2.0\nG1 X51 Z1\n";
    }
    src += "M30\n";
    let m = example();
    let r = reading::Reading::of(src.as_bytes(), &m);
    assert!(r.segs.len() >= 50_000, "{} segments", r.segs.len());
    let per_line = r.held_bytes() as f64 / r.lines.len() as f64;
    // 13 bytes a line of source: the reading adds less than that.
    assert!(per_line < 13.0, "{per_line:.1} bytes a line");
}
