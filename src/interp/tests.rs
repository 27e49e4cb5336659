//! Tests of the interpreter's internals (behaviour is tested by the data-driven cases).

use super::flow::Run;
use super::Limits;
use crate::gcode;
use crate::machine::Machine;
use proptest::prelude::*;

/// Interpret with or without the fast path for plain blocks.
fn run(src: &str, machine: &Machine, fast: bool) -> String {
    let prog = gcode::parse(src.as_bytes());
    let mut r = Run::new(&prog, src.as_bytes(), machine, Limits::for_program(&prog));
    r.plain_blocks_fast = fast;
    r.run();
    let i = r.finish();
    format!("{:?}\n{:?}\n{:?}\n{:?}", i.moves, i.states, i.findings, i.extra)
}

#[test]
fn every_g_code_the_block_executor_tests_has_a_bit() {
    // `Words::g(code)` is false for a code outside KNOWN_G: a code asked about but missing from
    // the list would silently never be seen. The codes are asked about by the order of execution
    // and its converters.
    let sources = [
        include_str!("block.rs"),
        include_str!("groups.rs"),
        include_str!("order.rs"),
        include_str!("convert/coords.rs"),
        include_str!("convert/cycle.rs"),
        include_str!("convert/dwell.rs"),
        include_str!("convert/feed.rs"),
        include_str!("convert/flow.rs"),
        include_str!("convert/m_codes.rs"),
        include_str!("convert/motion.rs"),
        include_str!("convert/plane.rs"),
        include_str!("convert/spindle.rs"),
        include_str!("convert/tool.rs"),
        include_str!("convert/units.rs"),
    ];
    let mut asked = 0;
    for (src, pat) in sources.iter().flat_map(|s| ["w.g(", "has_g(", "gb("].map(|p| (s, p))) {
        for (i, _) in src.match_indices(pat) {
            let rest = &src[i + pat.len()..];
            let digits: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
            if digits.is_empty() || !rest[digits.len()..].starts_with(')') {
                continue;
            }
            let code: u16 = digits.parse().unwrap();
            assert!(
                super::words::KNOWN_G.contains(&code),
                "G code x10 {code} is not in KNOWN_G"
            );
            asked += 1;
        }
    }
    assert!(asked > 40, "found only {asked} codes: has the pattern changed?");
}

fn linuxcnc() -> Machine {
    let text = include_str!("../../machines/linuxcnc-small-lathe.toml");
    crate::machine::from_toml(text, "linuxcnc-small-lathe.toml").unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn plain_blocks_run_the_same_with_and_without_their_fast_path(
        lines in proptest::collection::vec(
            "(G[0-3] |G1 F0\\.[1-3] |G4 P1 |G4[0-2] |G91 |G90 |G20 |G21 |G7 |G8 |G53 |G28 |M3 S500 |T[12] M6 |F-1 |#1=2 |)?((X|Z|U|W|I|K|R|F|Y|P)-?[0-9]{1,2}(\\.[0-9])? ?){0,4}",
            1..25,
        ),
        fanuc in any::<bool>(),
    ) {
        let src = lines.join("\n");
        let m = if fanuc { Machine::builtin() } else { linuxcnc() };
        prop_assert_eq!(run(&src, &m, true), run(&src, &m, false));
    }

    /// On a turn-mill machine the fast path declines blocks with extra-axis words, and the plain
    /// blocks it still takes get the same extra-axis entries (C-axis mode, live tool, plane).
    #[test]
    fn plain_blocks_on_a_turn_mill_machine_run_the_same_with_and_without_their_fast_path(
        lines in proptest::collection::vec(
            "(G[0-3] |G1 F0\\.[1-3] |G17 |G18 |G19 |G91 |G90 |G20 |G21 |G53 |G28 |G92 |M3 S500 |M154 |M155 |M133 P900 |M135 |)?((X|Z|U|W|I|J|K|R|F|Y|V|C|H|B|A)-?[0-9]{1,2}(\\.[0-9])? ?){0,4}",
            1..25,
        ),
        fanuc in any::<bool>(),
    ) {
        let src = lines.join("\n");
        let mut m = if fanuc { Machine::builtin() } else { linuxcnc() };
        m.kinematics = Some(std::sync::Arc::new(turn_mill_kinematics()));
        prop_assert_eq!(run(&src, &m, true), run(&src, &m, false));
    }
}

/// `interpret_streaming` hands over exactly the moves `interpret` returns, in order, with the
/// states they refer to, across many chunks and with cycles (whose passes look back at the moves
/// of their own block) on both sides of chunk boundaries.
#[test]
fn streamed_moves_equal_the_moves_of_a_whole_run() {
    let unit = "G0 X52 Z3\nG71 U2 R0.5\nG71 P10 Q60 U0.4 W0.1 F0.25\nN10 G0 X20\nN20 G1 Z-10\nN30 X30 Z-15\nN40 Z-30\nN50 G2 X40 Z-35 R5\nN60 G1 X52\nG70 P10 Q60\nG0 X40 Z5\nG76 P010060 Q100 R0.05\nG76 X37.4 Z-25 P1300 Q400 F2\nG0 X60 Z5\n";
    let mut src = String::from("G21 G18 G99\nT0101\nG97 S800 M3\n");
    for i in 0..200 {
        src.push_str(unit);
        // A few plain moves of varying count, so cycles start at every offset of a chunk.
        for k in 0..(i % 7) {
            src.push_str(&format!("G1 X{} Z2 F0.2\n", 50 + k));
        }
        // Moves nose-radius compensation holds back across blocks.
        src.push_str("G0 X30 Z5\nG42 G1 X20 Z2 F0.2\nG1 Z-10\nX40 Z-20\nG40 G0 X60 Z5\n");
    }
    src.push_str("M30\n");
    let machine = Machine::builtin();
    let prog = gcode::parse(src.as_bytes());
    let whole = super::interpret(&prog, src.as_bytes(), &machine);
    assert!(
        whole.moves.len() > 3 * super::flow::STREAM_CHUNK,
        "{}",
        whole.moves.len()
    );
    let mut streamed = Vec::new();
    let mut chunks = 0;
    let rest = super::interpret_streaming(&prog, src.as_bytes(), &machine, |c| {
        assert_eq!(c.first, streamed.len());
        chunks += 1;
        streamed.extend(c.moves.iter().map(|m| (*m, c.states[m.state as usize])));
    });
    assert!(chunks > 3);
    assert!(rest.moves.is_empty());
    let expected: Vec<_> = whole
        .moves
        .iter()
        .map(|m| (*m, whole.states[m.state as usize]))
        .collect();
    assert_eq!(streamed, expected);
    assert_eq!(rest.states, whole.states);
    assert_eq!(format!("{:?}", rest.findings), format!("{:?}", whole.findings));
    assert_eq!(rest.blocks_executed, whole.blocks_executed);
}

/// `spindle.start_rpm`: the program starts as if `M3 S<rpm>` had come before its first line.
#[test]
fn a_spindle_start_speed_turns_the_spindle_before_any_m3() {
    let src = "G21 G97\nG0 X50 Z5\nG1 Z0 F0.2\nM5\nG1 Z-1\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = Machine::builtin();
    let stopped = super::interpret(&prog, src.as_bytes(), &m);
    assert_eq!(stopped.spindle(&stopped.moves[0]).rpm_at(10.0), 0.0);
    m.start_rpm = Some(800.0);
    let on = super::interpret(&prog, src.as_bytes(), &m);
    assert_eq!(on.spindle(&on.moves[0]).rpm_at(10.0), 800.0);
    assert_eq!(on.spindle(&on.moves[1]).rpm_at(10.0), 800.0);
    // The program's own M5 still stops it.
    assert_eq!(on.spindle(&on.moves[2]).rpm_at(10.0), 0.0);
}

/// A job's manual tool change switches the tool before the words of its line, each time the
/// line runs, as a T word would (a tool change move at that line, then the new station).
#[test]
fn a_manual_tool_change_switches_the_tool_at_its_line_each_time_it_runs() {
    let src = "G21\nG0 X50 Z5\nM0 (PUT IN T3)\nG0 X60\nT0101\nG0 X70\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = Machine::builtin();
    m.tool_changes = vec![(3, 3)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let seen: Vec<(u32, u32, bool)> = i
        .moves
        .iter()
        .map(|mv| {
            (
                mv.line,
                mv.station,
                matches!(mv.kind, super::MoveKind::ToolChange { .. }),
            )
        })
        .collect();
    assert_eq!(
        seen,
        vec![(2, 1, false), (3, 3, true), (4, 3, false), (5, 1, true), (6, 1, false)],
        "{:?}",
        i.findings
    );
    // On a line that also moves, the change comes first: the move is made with the new tool.
    m.tool_changes = vec![(4, 2)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let at4: Vec<u32> = i.moves.iter().filter(|mv| mv.line == 4).map(|mv| mv.station).collect();
    assert_eq!(at4, vec![2, 2]);
    // A subroutine line runs twice: the change happens each time (LinuxCNC o-words).
    let src = "o100 sub\nG0 X40\no100 endsub\nT1 M6\no100 call\nT1 M6\no100 call\nM2\n";
    let prog = gcode::parse(src.as_bytes());
    let mut m = linuxcnc();
    m.tool_changes = vec![(2, 2)];
    let i = super::interpret(&prog, src.as_bytes(), &m);
    let changes: Vec<(u32, u32)> = i
        .moves
        .iter()
        .filter(|mv| matches!(mv.kind, super::MoveKind::ToolChange { .. }))
        .map(|mv| (mv.line, mv.station))
        .collect();
    assert_eq!(changes, vec![(2, 2), (6, 1), (2, 2)], "{:?}", i.findings);
}

/// Axes X, Z, Y (linear), C (rotary), B (linear: a sub-spindle's Z), A (rotary), as a turn-mill
/// machine's kinematics would give them.
pub(crate) fn turn_mill_kinematics() -> crate::kin::Kinematics {
    use crate::kin::{Axis, AxisKind, Kinematics};
    use nalgebra::{Point3, Unit, Vector3};
    let axis = |letter: char, linear: bool, dir: Vector3<f64>, rapid: f64| Axis {
        name: letter.to_ascii_lowercase().to_string(),
        letter,
        kind: if linear {
            AxisKind::Linear {
                dir: Unit::new_normalize(dir),
            }
        } else {
            AxisKind::Rotary {
                origin: Point3::origin(),
                dir: Unit::new_normalize(dir),
            }
        },
        zero: 0.0,
        travel: (f64::NEG_INFINITY, f64::INFINITY),
        rapid,
        path: 1,
    };
    Kinematics {
        axes: vec![
            axis('X', true, Vector3::x(), 12000.0),
            axis('Z', true, Vector3::z(), 16000.0),
            axis('Y', true, Vector3::y(), 6000.0),
            axis('C', false, Vector3::z(), 36000.0),
            axis('B', true, Vector3::z(), 12000.0),
            axis('A', false, Vector3::x(), 18000.0),
        ],
        ..Default::default()
    }
}

fn turn_mill(mut m: Machine) -> Machine {
    m.kinematics = Some(std::sync::Arc::new(turn_mill_kinematics()));
    m
}

fn interp(src: &str, m: &Machine) -> super::Interpretation {
    let prog = gcode::parse(src.as_bytes());
    super::interpret(&prog, src.as_bytes(), m)
}

#[test]
fn a_move_stays_128_bytes() {
    assert!(
        std::mem::size_of::<super::Move>() <= 128,
        "{}",
        std::mem::size_of::<super::Move>()
    );
}

/// A turning program on a turn-mill machine: the same moves as on the 2-axis machine and no
/// extra-axis entry; the extra words of a 2-axis machine stay refused as before.
#[test]
fn turning_on_a_turn_mill_machine_has_no_extra_entries_and_the_same_moves() {
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X52 Z3\nG1 Z-20 F0.2\nG2 X60 Z-24 R4\nG0 X80 Z10\nG28 U0 W0\nM30\n";
    let plain = interp(src, &Machine::builtin());
    let tm = interp(src, &turn_mill(Machine::builtin()));
    assert_eq!(plain.moves, tm.moves);
    assert!(tm.extra.is_empty());
    let with_c = "G21\nG0 X50 Z5 C30\nG0 Y2\nM30\n";
    let plain = interp(with_c, &Machine::builtin());
    assert!(plain.extra.is_empty());
    assert!(plain
        .findings
        .iter()
        .any(|f| f.line == 2 && f.message.contains("no such axis")));
    assert!(plain
        .findings
        .iter()
        .any(|f| f.line == 3 && f.message.contains("no Y axis")));
}

/// Extra-axis entries carry their move's index across a streaming run's chunks, and a C word
/// outside C-axis mode makes no move.
#[test]
fn extra_entries_name_their_moves_in_whole_and_streamed_runs() {
    let mut src = String::from("G21 G18 G98\nT0101\nM154\n");
    for i in 0..3000 {
        src.push_str(&format!(
            "G0 X{} Z5\nG0 C{}\nG1 Z-5 Y{} F500\n",
            40 + i % 5,
            i % 360,
            i % 3
        ));
    }
    src.push_str("M155\nC10\nM30\n");
    let m = turn_mill(Machine::builtin());
    let prog = gcode::parse(src.as_bytes());
    let whole = super::interpret(&prog, src.as_bytes(), &m);
    // Streamed, each chunk hands over its moves' entries (none stays behind in the run), and
    // the canonical text written chunk by chunk is the whole run's: in chunks of the default
    // size, and of one block each.
    let mut canon_whole = Vec::new();
    super::canon::write(&whole, &mut canon_whole).unwrap();
    for chunk in [super::STREAM_CHUNK, 1] {
        let mut extra = Vec::new();
        let mut canon_streamed = Vec::new();
        let mut next = 0;
        let rest = super::interpret_streaming_by(&prog, src.as_bytes(), &m, chunk, |c| {
            assert_eq!(c.first, next);
            next += c.moves.len();
            assert!(c
                .extra
                .iter()
                .all(|e| (c.first..c.first + c.moves.len()).contains(&(e.index as usize))));
            extra.extend_from_slice(c.extra);
            super::canon::write_chunk(c, &mut canon_streamed).unwrap();
        });
        assert!(rest.extra.is_empty());
        assert_eq!(next, whole.moves.len());
        assert_eq!(whole.extra, extra, "chunk {chunk}");
        assert_eq!(canon_whole, canon_streamed, "chunk {chunk}");
    }
    assert!(whole.moves.len() > 2 * super::flow::STREAM_CHUNK);
    // Every move after M154 is in C-axis mode: one entry each, index order.
    assert_eq!(whole.extra.len(), whole.moves.len());
    for (k, e) in whole.extra.iter().enumerate() {
        assert_eq!(e.index as usize, k);
        assert!(e.c_mode);
        assert_eq!(whole.extra_of(k), Some(e));
    }
    let c = whole
        .extra
        .iter()
        .find(|e| whole.moves[e.index as usize].line == 8)
        .unwrap();
    assert_eq!(c.end[1], 1.0, "C1 on the second pass");
    let last_line = src.lines().count() as u32 - 1;
    assert!(whole.moves.iter().all(|mv| mv.line != last_line));
    assert!(whole
        .findings
        .iter()
        .any(|f| f.line == last_line && f.message.contains("not in C-axis mode")));
}

/// Timing: a rapid takes as long as its slowest axis; a rotary-only feed runs F in deg/min; a
/// feed with Y runs F over the combined path; moves without an entry keep their time.
#[test]
fn extra_axes_are_timed_by_their_own_rates_and_the_combined_path() {
    let m = linuxcnc();
    let tm = turn_mill(m.clone());
    // Y rapid 6000 mm/min: 100 mm in 1 s, slower than X's few mm.
    let src = "G18 G21 G90 G94\nG0 X0 Z0\nG0 X10 Y100\nG1 C90 F900\nG1 Y30 Z40 F600\nG1 Z50\nM2\n";
    let run = interp(src, &tm);
    let tl = crate::motion::timeline(&run, &tm);
    let by_line = |l: u32| tl.items.iter().find(|t| run.moves[t.index].line == l).unwrap().duration;
    assert!((by_line(3) - 1.0).abs() < 1e-9, "{}", by_line(3));
    assert!((by_line(4) - 6.0).abs() < 1e-9, "90 deg at 900 deg/min: {}", by_line(4));
    // (y 100 → 30, z 0 → 40): 80.62 mm at 600 mm/min.
    let d = (70.0f64 * 70.0 + 40.0 * 40.0).sqrt() / 10.0;
    assert!((by_line(5) - d).abs() < 1e-9, "{}", by_line(5));
    // The same program without Y/C on the 2-axis machine: the plain move keeps its time.
    let plain = interp("G18 G21 G90 G94\nG0 X0 Z40\nG1 Z50 F600\nM2\n", &m);
    let tp = crate::motion::timeline(&plain, &m);
    assert!((by_line(6) - tp.items[1].duration).abs() < 1e-12);
}

fn arb_plane_arc_move() -> impl Strategy<Value = (super::Move, super::ExtraMove)> {
    (
        prop_oneof![Just(super::Plane::Xy), Just(super::Plane::Yz)],
        -50.0..50.0f64,
        -50.0..50.0f64,
        1.0..40.0f64,
        -3.0..3.0f64,
        -6.0..6.0f64,
        -20.0..20.0f64,
        -20.0..20.0f64,
    )
        .prop_map(|(plane, c0, c1, r, a0, sweep, third0, third1)| {
            let p0 = [c0 + r * a0.cos(), c1 + r * a0.sin()];
            let p1 = [c0 + r * (a0 + sweep).cos(), c1 + r * (a0 + sweep).sin()];
            let (s2, e2, ys, ye) = match plane {
                super::Plane::Xy => (
                    crate::geom::P2::new(p0[0], third0),
                    crate::geom::P2::new(p1[0], third1),
                    p0[1],
                    p1[1],
                ),
                _ => (
                    crate::geom::P2::new(third0, p0[1]),
                    crate::geom::P2::new(third1, p1[1]),
                    p0[0],
                    p1[0],
                ),
            };
            let mv = super::Move {
                kind: super::MoveKind::Line,
                line: 1,
                n: None,
                profile_line: 0,
                start: s2,
                end: e2,
                tip: crate::geom::V2::zeros(),
                station: 1,
                feed: super::Feed::PerMinute(100.0),
                state: 0,
            };
            let e = super::ExtraMove {
                index: 0,
                start: [ys, 0.0, 0.0, 0.0],
                end: [ye, 15.0, 0.0, 0.0],
                plane,
                c_mode: true,
                live_rpm: 0.0,
                origin: [0.0; 4],
                arc: Some(super::PlaneArc {
                    plane,
                    center: [c0, c1],
                    sweep,
                }),
            };
            (mv, e)
        })
}

fn arb_xz_move() -> impl Strategy<Value = super::Move> {
    (
        -50.0..50.0f64,
        -50.0..50.0f64,
        -50.0..50.0f64,
        -50.0..50.0f64,
        prop::option::of(-6.0..6.0f64),
    )
        .prop_map(|(x0, z0, x1, z1, arc)| {
            let start = crate::geom::P2::new(x0, z0);
            let end = crate::geom::P2::new(x1, z1);
            let kind = match arc {
                Some(sweep) => super::MoveKind::Arc {
                    center: crate::geom::P2::new((x0 + x1) / 2.0 + 3.0, (z0 + z1) / 2.0),
                    sweep,
                },
                None => super::MoveKind::Line,
            };
            super::Move {
                kind,
                line: 1,
                n: None,
                profile_line: 0,
                start,
                end,
                tip: crate::geom::V2::zeros(),
                station: 1,
                feed: super::Feed::PerMinute(100.0),
                state: 0,
            }
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// position3: t = 0 is the start, t = 1 the end, and every point of an XY or YZ arc is at
    /// its radius from the centre, with the third coordinate and the other axes linear.
    #[test]
    fn position3_of_a_plane_arc_starts_ends_and_keeps_its_radius((mv, e) in arb_plane_arc_move(), t in 0.0..=1.0f64) {
        let (p0, a0) = super::position3(&mv, Some(&e), 0.0);
        let (p1, a1) = super::position3(&mv, Some(&e), 1.0);
        prop_assert!((p0[0] - mv.start.x).abs() < 1e-9 && (p0[1] - e.start[0]).abs() < 1e-9 && (p0[2] - mv.start.y).abs() < 1e-9);
        prop_assert!((p1[0] - mv.end.x).abs() < 1e-9 && (p1[1] - e.end[0]).abs() < 1e-9 && (p1[2] - mv.end.y).abs() < 1e-9);
        prop_assert_eq!(a0, e.start);
        prop_assert_eq!(a1, e.end);
        let arc = e.arc.unwrap();
        let (p, a) = super::position3(&mv, Some(&e), t);
        let (u, v, third, t0, t1) = match arc.plane {
            super::Plane::Xy => (p[0], p[1], p[2], mv.start.y, mv.end.y),
            _ => (p[1], p[2], p[0], mv.start.x, mv.end.x),
        };
        let (s0, s1) = match arc.plane {
            super::Plane::Xy => (mv.start.x, e.start[0]),
            _ => (e.start[0], mv.start.y),
        };
        let r = ((s0 - arc.center[0]).powi(2) + (s1 - arc.center[1]).powi(2)).sqrt();
        let rt = ((u - arc.center[0]).powi(2) + (v - arc.center[1]).powi(2)).sqrt();
        prop_assert!((rt - r).abs() < 1e-6 * (1.0 + r), "radius {} at t {} against {}", rt, t, r);
        prop_assert!((third - (t0 + (t1 - t0) * t)).abs() < 1e-9);
        prop_assert!((a[1] - 15.0 * t).abs() < 1e-9);
        prop_assert!((a[0] - p[1]).abs() < 1e-12, "the Y axis is the point's y");
    }

    /// position3 of an XZ move (line or arc) is the 2D path of `Move::point_at`, with y from the
    /// entry (0 without one).
    #[test]
    fn position3_of_an_xz_move_agrees_with_the_2d_path(mv in arb_xz_move(), t in 0.0..=1.0f64, y0 in -10.0..10.0f64, y1 in -10.0..10.0f64) {
        let p2 = mv.point_at(t);
        let (p, a) = super::position3(&mv, None, t);
        prop_assert_eq!(p, [p2.x, 0.0, p2.y]);
        prop_assert_eq!(a, [0.0; 4]);
        let e = super::ExtraMove {
            index: 0,
            start: [y0, 0.0, 0.0, 0.0],
            end: [y1, 0.0, 0.0, 0.0],
            plane: super::Plane::Zx,
            c_mode: false,
            live_rpm: 0.0,
            origin: [0.0; 4],
            arc: None,
        };
        let (p, _) = super::position3(&mv, Some(&e), t);
        prop_assert_eq!([p[0], p[2]], [p2.x, p2.y]);
        prop_assert!((p[1] - (y0 + (y1 - y0) * t)).abs() < 1e-12);
    }
}

/// LinuxCNC's predefined named parameters that a program may test (`o100 if [#<_vmajor> GE 2]`):
/// the version whose rs274 these rules follow, compensation, spindle and arc-centre modes, the
/// o-word call level.
#[test]
fn linuxcnc_predefined_named_parameters_read_the_modes_in_force() {
    let src = "G7 G18 G21 G90.1\n\
               G0 X[#<_vmajor>] Z[#<_vminor>]\n\
               G0 X[#<_ccomp> / 100] Z[#<_ijk_absolute_mode>]\n\
               G96 S100 D1000 M3\n\
               G0 X[#<_spindle_css_mode> * 10 + #<_spindle_rpm_mode>] Z[#<_call_level>]\n\
               o100 sub\n\
               G0 X[#<_call_level> * 2] Z[#<_remap_level> + #<_inverse_time>]\n\
               o100 endsub\n\
               o100 call\n\
               M2\n";
    let i = interp(src, &linuxcnc());
    assert!(i.findings.is_empty(), "{:?}", i.findings);
    // X words are diameters (G7): the spindle frame holds radii. Program zero is the machine's.
    let dz = i.moves[0].ref_end().y + i.moves[0].tip.y - 9.0;
    let ends: Vec<(f64, f64)> = i
        .moves
        .iter()
        .map(|m| {
            let p = m.ref_end() + m.tip;
            ((2.0 * p.x * 1e6).round() / 1e6, ((p.y - dz) * 1e6).round() / 1e6)
        })
        .collect();
    assert_eq!(ends, vec![(2.0, 9.0), (4.0, 1.0), (10.0, 0.0), (2.0, 0.0)], "{ends:?}");
}

/// M99 at the end of a main program (a bar-feed loop: the control runs the program again from its
/// start, no alarm) is a warning that says one pass is checked, not an error; in both dialects,
/// with and without custom macro B, and with `M99 Pn`. The moves of the pass are kept.
#[test]
fn m99_in_the_main_program_is_a_warning_not_an_error() {
    use crate::finding::Severity;
    let fanuc = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X52 Z3\nG1 Z-20 F0.2\nG0 X80 Z10\nM99\n";
    let lcnc = "G21 G18\nT1 M6\nS800 M3\nG0 X26 Z3\nG1 Z-20 F100\nG0 X40 Z10\nM99\n";
    let macro_p = "G21 G18 G99\nT0101\nN10 G0 X52 Z3\n#100 = 1\nG0 X60\nM99 P10\n";
    for (src, m) in [
        (fanuc, Machine::builtin()),
        (lcnc, linuxcnc()),
        (macro_p, Machine::builtin()),
    ] {
        // Read as the machine's dialect reads it (Fanuc: with macro B, whose M99 is its own).
        let (_, i) = crate::pipeline::interpret(src.as_bytes(), &m);
        let at: Vec<_> = i
            .findings
            .iter()
            .filter(|f| f.message.contains("main program"))
            .collect();
        assert_eq!(at.len(), 1, "{src}: {:?}", i.findings);
        assert_eq!(at[0].severity, Severity::Warning, "{src}: {:?}", at[0]);
        assert!(
            i.findings.iter().all(|f| f.severity == Severity::Warning),
            "{src}: {:?}",
            i.findings
        );
        assert!(i.moves.len() >= 2, "{src}: the pass before M99 is interpreted");
    }
}

/// Fanuc keeps one modal F for feed and thread lead: a G32 without F or E cuts at the F in
/// force, a G1 after a thread without F feeds at the lead, and a K in a G32 block (LinuxCNC's
/// G33 lead word) is a warning, the thread cut at the modal F. Before, a G32 without F was refused
/// ("threading move needs its lead"): 32 false errors on two NX posts of the corpus.
#[test]
fn fanuc_g32_without_f_cuts_at_the_modal_f_and_its_f_stays_the_feed() {
    use crate::finding::Severity;
    use crate::interp::Feed;
    let src = "G21 G18 G99\nT0101\nG97 S300 M3\nG0 X120 Z30\nG1 X118 F0.2\nG32 Z10 K1.5\nG0 X122\nZ30\nX118\nG32 Z10 F1.5\nG0 X122\nZ30\nX118\nG32 Z10\nG0 X122\nG1 Z40\nM30\n";
    let (_, i) = crate::pipeline::interpret(src.as_bytes(), &Machine::builtin());
    let feed = |line: u32| i.moves.iter().find(|m| m.line == line).map(|m| m.feed);
    assert_eq!(feed(6), Some(Feed::PerRev(0.2)));
    assert_eq!(feed(10), Some(Feed::PerRev(1.5)));
    assert_eq!(feed(14), Some(Feed::PerRev(1.5)));
    assert_eq!(feed(16), Some(Feed::PerRev(1.5)));
    let k: Vec<_> = i.findings.iter().filter(|f| f.message.contains("not K")).collect();
    assert_eq!(k.len(), 1, "{:?}", i.findings);
    assert_eq!((k[0].line, k[0].severity), (6, Severity::Warning));
    assert!(
        i.findings.iter().all(|f| f.severity == Severity::Warning),
        "{:?}",
        i.findings
    );
}

#[test]
fn a_cycle_finds_its_profile_next_to_it_and_thousands_of_blocks_away_alike() {
    // G71 P10 Q60 finds N10 and N60 by searching near the cycle first and asking the index of
    // every numbered block only past `NEAR` blocks: a profile 10 blocks and 6,000 blocks after
    // the cycle gives the same roughing passes. (N10-N60 also stand earlier, before the cycle:
    // the first after it counts, near or far.)
    let profile = "N10 G0 X20\nN20 G1 Z-10\nN30 X30 Z-15\nN40 Z-30\nN50 G2 X40 Z-35 R5\nN60 G1 X52\n";
    let program = |gap: usize| {
        format!(
            "G21 G18 G99 G97 S800 M3\nT0101\n{p0}G0 X52 Z3\nG71 U2 R0.5\nG71 P10 Q60 U0.4 W0.1 F0.25\n\
             G0 X100 Z100\nM30\n{gap}{profile}",
            p0 = profile.replace("X20", "X24").replace("X52", "X60"),
            gap = "G0 X100 Z100\n".repeat(gap)
        )
    };
    let m = Machine::builtin();
    let moves = |src: &str| {
        let prog = gcode::parse(src.as_bytes());
        let run = super::interpret(&prog, src.as_bytes(), &m);
        let cycle: Vec<_> = run
            .moves
            .iter()
            .filter(|mv| mv.line == 11)
            .map(|mv| (mv.start, mv.end))
            .collect();
        (cycle, run.findings.len())
    };
    let (near, far) = (moves(&program(10)), moves(&program(6000)));
    assert!(near.0.len() > 10, "{near:?}");
    assert_eq!(near, far);
}
