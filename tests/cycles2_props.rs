//! The Fanuc/Haas box, threading, grooving and drilling cycles (issue 11, `interp/cycles`): their
//! passes by property over random words, and the rules the hand-worked cases in
//! `tests/cases/cycles2/` do not cover (system B, the spindle during tapping, bounded work on
//! hostile words).

use latheguard::finding::Kind;
use latheguard::interp::{Feed, Interpretation, Move, MoveKind, SpindleDir};
use latheguard::machine::{GcodeSystem, Machine};
use latheguard::pipeline;
use proptest::prelude::*;

const Z0: f64 = 78.0; // program Z0 of the built-in machine, spindle frame

fn run(src: &str) -> Interpretation {
    run_on(src, &Machine::builtin())
}

fn run_on(src: &str, m: &Machine) -> Interpretation {
    pipeline::interpret(src.as_bytes(), m).1
}

/// The moves of one source line.
fn line(i: &Interpretation, n: u32) -> Vec<Move> {
    i.moves.iter().filter(|m| m.line == n).copied().collect()
}

fn errors(i: &Interpretation) -> Vec<String> {
    i.findings
        .iter()
        .filter(|f| f.kind == Kind::Program || f.kind == Kind::Unsupported)
        .map(|f| format!("{}: {}", f.line, f.message))
        .collect()
}

/// As the program writes it: three decimals.
fn r3(v: f64) -> f64 {
    format!("{v:.3}").parse().unwrap()
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// G90 / G94 with a taper: four moves per block, rapid in, two feeds, rapid back to the start
    /// point; every point inside the box spanned by the start, the end and the tapered corner.
    #[test]
    fn box_cycles_return_to_their_start_and_stay_in_their_box(
        sx in 30.0f64..80.0, sz in 1.0f64..10.0,
        ex in 2.0f64..28.0, ez in -60.0f64..-1.0,
        r in -3.0f64..3.0, face in any::<bool>(), passes in 1usize..4,
    ) {
        let code = if face { 94 } else { 90 };
        let mut src = format!("G21 G99 S500 M3\nT0101\nG0 X{sx:.3} Z{sz:.3}\nG{code} X{ex:.3} Z{ez:.3} R{r:.3} F0.2\n");
        for k in 1..passes {
            src += &format!("X{:.3}\n", ex - k as f64);
        }
        let i = run(&src);
        prop_assert!(errors(&i).is_empty(), "{:?}", errors(&i));
        let (sx, sz, r, ex, ez) = (r3(sx) / 2.0, r3(sz) + Z0, r3(r), r3(ex), r3(ez) + Z0);
        for k in 0..passes {
            let ms = line(&i, 4 + k as u32);
            prop_assert_eq!(ms.len(), 4);
            let kinds: Vec<bool> = ms.iter().map(|m| m.feed == Feed::Rapid).collect();
            prop_assert_eq!(kinds, vec![true, false, false, true]);
            let last = ms[3].end;
            prop_assert!(close(last.x, sx) && close(last.y, sz));
            let ex = (ex - k as f64) / 2.0;
            // The first feed ends on the end point.
            prop_assert!(close(ms[1].end.x, ex) && close(ms[1].end.y, ez));
            for m in &ms {
                for p in [m.start, m.end] {
                    let (lo_x, hi_x) = (ex.min(sx) - r.abs() - 1e-6, ex.max(sx) + r.abs() + 1e-6);
                    let (lo_z, hi_z) = (ez.min(sz) - r.abs() - 1e-6, ez.max(sz) + r.abs() + 1e-6);
                    prop_assert!(p.x >= lo_x && p.x <= hi_x && p.y >= lo_z && p.y <= hi_z, "{p:?} outside the box");
                }
            }
        }
    }

    /// G76 (two-block form): the pass depths grow, every roughing increment but the last is at
    /// least Δdmin, roughing ends at k − d, the m finishing passes run at the root, the one-edge
    /// infeed keeps each pass on the flank (Z shift = (k − depth)·tan(a/2)), and every pass is
    /// spindle-synchronised at the lead.
    #[test]
    fn g76_passes_follow_constant_area_infeed_with_a_least_increment(
        k_um in 300u32..3000, first_frac in 0.05f64..0.9, dmin_um in 0u32..200,
        d_um in 0u32..100, m in 1u32..4, angle in prop::sample::select(vec![0u32, 29, 30, 55, 60, 80]),
        lead in 0.5f64..3.0,
    ) {
        let dd_um = ((k_um as f64 * first_frac) as u32).max(10);
        prop_assume!(d_um < k_um);
        let src = format!(
            "G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 P{m:02}00{angle:02} Q{dmin_um} R{:.3}\nG76 X40 Z-30 P{k_um} Q{dd_um} F{lead:.3}\n",
            d_um as f64 / 1000.0
        );
        let i = run(&src);
        prop_assert!(errors(&i).is_empty(), "{:?}", errors(&i));
        let (k, dmin, d) = (k_um as f64 / 1000.0, dmin_um as f64 / 1000.0, d_um as f64 / 1000.0);
        let lead = r3(lead);
        let tan = (f64::from(angle).to_radians() / 2.0).tan();
        let threads: Vec<Move> = line(&i, 5).into_iter().filter(|m| m.feed != Feed::Rapid).collect();
        prop_assert!(threads.iter().all(|t| t.feed == Feed::PerRev(lead)));
        // Depth of each pass from its X: root radius 20, external thread.
        let depths: Vec<f64> = threads.iter().map(|t| k - (t.end.x - 20.0)).collect();
        let n = depths.len();
        prop_assert!(n > m as usize);
        for w in depths.windows(2) {
            prop_assert!(w[1] >= w[0] - 1e-9);
        }
        let rough = &depths[..n - m as usize];
        for (j, pair) in rough.windows(2).enumerate() {
            if j + 2 < rough.len() {
                prop_assert!(pair[1] - pair[0] >= dmin - 1e-9, "increment below Δdmin: {:?}", depths);
            }
        }
        prop_assert!(close(*rough.last().unwrap(), k - d));
        for f in &depths[n - m as usize..] {
            prop_assert!(close(*f, k));
        }
        for (t, dep) in threads.iter().zip(&depths) {
            prop_assert!((t.end.y - (Z0 - 30.0 + (k - dep) * tan)).abs() < 1e-9);
        }
    }

    /// G75: no feed along X longer than the peck, each groove reaches the bottom, the grooves
    /// step by at most the shift, and the cycle ends at its start point.
    #[test]
    fn g75_pecks_reach_the_bottom_in_steps_no_longer_than_the_peck(
        depth in 1.0f64..12.0, peck_um in 200u32..5000, width in 0.0f64..10.0, shift_um in 500u32..4000,
    ) {
        let src = format!(
            "G21 G99 S500 M3\nT0404\nG0 X60 Z-5\nG75 R0.3\nG75 X{:.3} Z{:.3} P{peck_um} Q{shift_um} F0.05\n",
            60.0 - 2.0 * depth,
            -5.0 - width
        );
        let i = run(&src);
        prop_assert!(errors(&i).is_empty(), "{:?}", errors(&i));
        let ms = line(&i, 5);
        let (peck, shift) = (peck_um as f64 / 1000.0, shift_um as f64 / 1000.0);
        let bottom = r3(60.0 - 2.0 * depth) / 2.0;
        let mut groove_z = Vec::new();
        for m in &ms {
            if m.feed != Feed::Rapid {
                prop_assert!((m.start.x - m.end.x).abs() <= peck + 0.3 + 1e-9);
                if close(m.end.x, bottom) {
                    groove_z.push(m.end.y);
                }
            }
        }
        prop_assert!(!groove_z.is_empty());
        for w in groove_z.windows(2) {
            prop_assert!(w[0] - w[1] <= shift + 1e-9 && w[0] > w[1]);
        }
        prop_assert!(close(*groove_z.last().unwrap(), Z0 - 5.0 - r3(width)));
        let last = ms.last().unwrap().end;
        prop_assert!(close(last.x, 30.0) && close(last.y, Z0 - 5.0));
    }

    /// G83: no feed deeper than one peck past the previous depth, the hole reaches its bottom,
    /// and the drill ends at the initial level.
    #[test]
    fn g83_pecks_never_feed_more_than_q_and_end_at_the_initial_level(
        bottom in 1.0f64..40.0, q_um in 500u32..10_000, r in 0.5f64..3.0,
    ) {
        let src = format!("G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG83 Z-{bottom:.3} R-{r:.3} Q{q_um} F0.1\n");
        let i = run(&src);
        prop_assert!(errors(&i).is_empty(), "{:?}", errors(&i));
        let ms = line(&i, 4);
        let q = q_um as f64 / 1000.0;
        let mut deepest = f64::INFINITY;
        for m in &ms {
            prop_assert!(close(m.start.x, 0.0) && close(m.end.x, 0.0));
            if m.feed != Feed::Rapid {
                prop_assert!(m.start.y - m.end.y <= q + 1.0 + 1e-9);
                deepest = deepest.min(m.end.y);
            }
        }
        prop_assert!(close(deepest, Z0 - r3(bottom)));
        prop_assert!(close(ms.last().unwrap().end.y, Z0 + 10.0));
    }
}

#[test]
fn g84_feeds_out_with_the_spindle_reversed_and_restores_it() {
    // The built-in machine reads R as Fanuc does: R-7. from the initial level Z10 is Z3.
    let i = run("G21 G99 S300 M3\nT0606\nG0 X0 Z10\nG84 Z-10 R-7. F1.5\nG0 Z20\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    let ms = line(&i, 4);
    let feeds: Vec<&Move> = ms.iter().filter(|m| m.feed != Feed::Rapid).collect();
    assert_eq!(feeds.len(), 2);
    assert_eq!(i.spindle(feeds[0]).dir, SpindleDir::Cw);
    assert_eq!(i.spindle(feeds[1]).dir, SpindleDir::Ccw);
    assert_eq!(feeds[1].end.y, Z0 + 3.0);
    let after = line(&i, 5);
    assert_eq!(i.spindle(&after[0]).dir, SpindleDir::Cw);
}

#[test]
fn g86_rapids_out_with_the_spindle_stopped() {
    let i = run("G21 G99 S300 M3\nT0606\nG0 X0 Z10\nG86 Z-10 R3. F0.1\n");
    let ms = line(&i, 4);
    let out = ms
        .iter()
        .find(|m| m.feed == Feed::Rapid && m.start.y == Z0 - 10.0)
        .unwrap();
    assert_eq!(i.spindle(out).dir, SpindleDir::Off);
    assert_eq!(i.spindle(ms.last().unwrap()).dir, SpindleDir::Cw);
}

#[test]
fn system_b_reads_g92_as_coordinate_setting_and_g77_to_g79_as_box_cycles() {
    let mut m = Machine::builtin();
    m.gcode_system = GcodeSystem::B;
    // G92 X Z: the current point becomes X100 Z50; G91 is incremental here; G78 threads.
    let i = run_on(
        "G21 G95 S500 M3\nT0505\nG0 X60 Z5\nG92 X100 Z50\nG90 G0 X100 Z60\nG78 X96 Z20 F1.5\nX95\nG0 X110\n",
        &m,
    );
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    let first = line(&i, 5)[0];
    // The program point X100 Z60 is 10 mm (Z) past the point that became X100 Z50.
    assert!(close(first.end.y, Z0 + 5.0 + 10.0) && close(first.end.x, 30.0));
    let thread = line(&i, 6);
    assert_eq!(thread.len(), 4);
    assert_eq!(thread[1].feed, Feed::PerRev(1.5));
    assert_eq!(line(&i, 7).len(), 4, "G78 is modal");
    // In system A the same G92 is a thread cycle.
    let a = run("G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG92 X50 Z-20 F1.5\n");
    assert!(errors(&a).is_empty(), "{:?}", errors(&a));
    assert_eq!(line(&a, 4).len(), 4);
}

#[test]
fn system_b_g99_returns_drilling_to_the_r_plane() {
    let mut m = Machine::builtin();
    m.gcode_system = GcodeSystem::B;
    // from the initial level Z10: the R point Z2 (Fanuc's R, as the built-in machine reads it).
    let i = run_on("G21 G95 S500 M3\nT0606\nG0 X0 Z10\nG99 G81 Z-5 R-8. F0.1\n", &m);
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    assert!(close(line(&i, 4).last().unwrap().end.y, Z0 + 2.0));
    let a = run("G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG81 Z-5 R2. F0.1\n");
    assert!(close(line(&a, 4).last().unwrap().end.y, Z0 + 10.0));
}

#[test]
fn g80_is_not_in_group_01_on_fanuc_and_cancels_the_cycle() {
    let i = run("G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG81 Z-5 R2. F0.1\nG0 G40 G80 X0 Z30\nZ40\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    // Line 6 is a plain rapid, not another hole.
    let six = line(&i, 6);
    assert_eq!(six.len(), 1);
    assert_eq!(six[0].kind, MoveKind::Rapid);
}

#[test]
fn g92_s_without_axis_words_is_the_spindle_clamp_not_a_cycle() {
    let i = run("G21 G99 M3\nT0101\nG92 S1500\nG96 S200\nG0 X60 Z5\nG1 X50 F0.2\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    assert_eq!(line(&i, 6).len(), 1);
}

#[test]
fn hostile_cycle_words_are_findings_with_bounded_work() {
    for (src, needle) in [
        (
            "G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 P010060 Q0 R0\nG76 X40 Z-30 P99999999 Q1 F1\n",
            "passes",
        ),
        (
            "G21 G99 S500 M3\nT0404\nG0 X60 Z-5\nG75 X-1000000 Z-1000 P1 Q1 F0.1\n",
            "moves",
        ),
        ("G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG83 Z-100000 R2. Q1 F0.1\n", "pecks"),
        (
            "G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG81 Z-5 R2. F0.1\nX3.\n",
            "a hole at X3 is off the spindle axis",
        ),
        (
            "G21 G99 S500 M3\nT0101\nG0 X60 Z5\nG90 X40 F0.2\n",
            "both end point axes",
        ),
        ("G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 P000060\n", "repetitions"),
        (
            "G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 X60 Z-30 P1000 Q300 F1\n",
            "differ from the start",
        ),
        (
            "G21 G99 S500 M3\nT0404\nG0 X60 Z-5\nG75 X50 Z-9 P1000 F0.1\n",
            "shift amount is 0",
        ),
        (
            "G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG83 Z-20 R2. I3. J0.5 K1. F0.1\n",
            "I/J/K",
        ),
    ] {
        let i = run(src);
        assert!(i.moves.len() < 200_000, "{src}: {} moves", i.moves.len());
        assert!(
            errors(&i).iter().any(|e| e.contains(needle)),
            "{src}: expected a finding with {needle:?}, got {:?}",
            errors(&i)
        );
    }
}

#[test]
fn m30_on_a_cycle_line_ends_the_program_and_m99_there_is_reported() {
    let i = run("G21 G99 S500 M3\nT0101\nG0 X60 Z5\nG90 X50 Z-10 F0.2 M30\nG0 X80\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    assert!(line(&i, 5).is_empty(), "nothing runs after M30");
    let i = run("G21 G99 S500 M3\nT0101\nG0 X60 Z5\nG90 X50 Z-10 F0.2 M99\n");
    assert!(errors(&i).iter().any(|e| e.starts_with("4: M99")), "{:?}", errors(&i));
}

#[test]
fn cycles_carry_the_cycle_blocks_line() {
    let i = run("G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 P010060 Q100 R0\nG76 X56 Z-30 P1000 Q300 F1\nG0 X80\n");
    let five = line(&i, 5);
    assert!(five.len() >= 8);
    assert!(i.moves.iter().all(|m| [2, 3, 5, 6].contains(&m.line)));
}

#[test]
fn g75_relief_is_in_the_least_increment_and_goes_back_toward_the_start() {
    // R500 = 0.5 mm; the grooves advance toward -Z, so the relief at the bottom goes +Z.
    let i = run("G21 G99 S500 M3\nT0404\nG0 X54 Z-10\nG75 R0.5\nG75 X40 Z-16 P3000 Q2500 R500 F0.08\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    let reliefs: Vec<Move> = line(&i, 5)
        .into_iter()
        .filter(|m| m.feed != Feed::Rapid && close(m.start.x, 20.0) && close(m.end.x, 20.0))
        .collect();
    assert_eq!(reliefs.len(), 4, "one relief per groove");
    for r in reliefs {
        assert!(close(r.end.y - r.start.y, 0.5), "{r:?}");
    }
}

#[test]
fn an_unsupported_drilling_block_is_one_finding_not_a_list_of_unused_words() {
    let i = run("G21 G99 S500 M3\nT0606\nG0 X0 Z10\nG83 X20 C90 Z-20 R2. Q3000 F0.1\n");
    assert_eq!(errors(&i).len(), 1, "{:?}", errors(&i));
}

#[test]
fn many_long_cycles_stop_at_the_work_budget() {
    // 400 G76 blocks of 2,000+ passes each: far more moves than the 2,000,000 budget allows.
    let mut src = String::from("G21 G99 S500 M3\nT0505\nG0 X60 Z5\nG76 P010060 Q1 R0\n");
    for _ in 0..400 {
        src += "G76 X40 Z-30 P9000 Q200 F1\n";
    }
    let i = run(&src);
    assert!(i.moves.len() <= 2_100_000, "{} moves", i.moves.len());
    assert!(
        errors(&i).iter().any(|e| e.contains("work budget")),
        "{:?}",
        errors(&i).last()
    );
}

#[test]
fn box_cycles_read_u_and_w_from_the_start_point() {
    let abs = run("G21 G99 S500 M3\nT0101\nG0 X60 Z5\nG90 X52 Z-20 F0.2\n");
    let inc = run("G21 G99 S500 M3\nT0101\nG0 X60 Z5\nG90 U-8 W-25 F0.2\n");
    assert!(errors(&inc).is_empty(), "{:?}", errors(&inc));
    assert_eq!(line(&abs, 4), line(&inc, 4));
}

#[test]
fn g76_in_inch_reads_p_and_q_in_ten_thousandths() {
    // P500 = 0.05 in = 1.27 mm thread height; Q200 = 0.02 in first depth; X in inches.
    let i = run("G20 G99 S500 M3\nT0505\nG0 X2. Z0.2\nG76 P010060 Q0 R0\nG76 X1.8 Z-1. P500 Q200 F0.0625\n");
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    let threads: Vec<Move> = line(&i, 5).into_iter().filter(|m| m.feed != Feed::Rapid).collect();
    let first = threads[0];
    // Depth 0.02 in of 0.05: X = root + 0.03 in (radius), root radius 0.9 in.
    assert!(close(first.end.x, (0.9 + 0.03) * 25.4), "{first:?}");
    assert_eq!(first.feed, Feed::PerRev(0.0625 * 25.4));
    assert!(close(threads.last().unwrap().end.x, 0.9 * 25.4));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    /// G74 (Fanuc form): feeds along Z no longer than the peck, grooves stepping along X by at
    /// most the shift, the last at the end X, and the cycle back at its start point.
    #[test]
    fn g74_face_grooves_step_along_x_and_peck_along_z(
        depth in 1.0f64..10.0, peck_um in 300u32..4000, width in 0.5f64..8.0, shift_um in 500u32..3000,
    ) {
        let src = format!(
            "G21 G99 S500 M3\nT0404\nG0 X40 Z2\nG74 R0.2\nG74 X{:.3} Z{:.3} P{shift_um} Q{peck_um} F0.05\n",
            40.0 - 2.0 * width,
            2.0 - depth
        );
        let i = run(&src);
        prop_assert!(errors(&i).is_empty(), "{:?}", errors(&i));
        let ms = line(&i, 5);
        let (peck, shift) = (peck_um as f64 / 1000.0, shift_um as f64 / 1000.0);
        let bottom = Z0 + r3(2.0 - depth);
        let mut xs = Vec::new();
        for m in &ms {
            if m.feed != Feed::Rapid {
                prop_assert!((m.start.y - m.end.y).abs() <= peck + 0.2 + 1e-9);
                if close(m.end.y, bottom) && close(m.start.x, m.end.x) {
                    xs.push(m.end.x);
                }
            }
        }
        for w in xs.windows(2) {
            prop_assert!(w[0] > w[1] && w[0] - w[1] <= shift + 1e-9);
        }
        prop_assert!(close(*xs.last().unwrap(), r3(40.0 - 2.0 * width) / 2.0));
        let last = ms.last().unwrap().end;
        prop_assert!(close(last.x, 20.0) && close(last.y, Z0 + 2.0));
    }
}

/// One cycle block of random words (any code of this family, any subset of its letters, values
/// from tiny to huge, with and without a decimal point).
fn cycle_block() -> impl Strategy<Value = String> {
    let code = prop::sample::select(vec![
        "G90", "G92", "G94", "G76", "G74", "G75", "G81", "G82", "G83", "G84", "G85", "G86", "G87", "G88", "G89", "G80",
        "",
    ]);
    let value = prop_oneof![
        (-100_000i64..100_000).prop_map(|v| format!("{v}")),
        (-1000.0f64..1000.0).prop_map(|v| format!("{v:.3}")),
        (0.0f64..0.01).prop_map(|v| format!("{v:.5}")),
    ];
    let word = (prop::sample::select(b"XZUWRPQKDIFAC".to_vec()), value);
    (code, prop::collection::vec(word, 0..7)).prop_map(|(c, ws)| {
        let mut s = c.to_string();
        for (l, v) in ws {
            s += &format!(" {}{v}", l as char);
        }
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    /// Random cycle words never panic, and a block makes a bounded number of moves.
    #[test]
    fn random_cycle_words_end_in_moves_or_findings_never_a_panic(
        blocks in prop::collection::vec(cycle_block(), 1..6),
    ) {
        let src = format!("G21 G99 S500 M3\nT0101\nG0 X60 Z5\n{}\n", blocks.join("\n"));
        let i = run(&src);
        prop_assert!(i.moves.len() <= 3 + blocks.len() * 100_010, "{} moves", i.moves.len());
        for m in &i.moves {
            prop_assert!(m.start.x.is_finite() && m.end.y.is_finite());
        }
    }
}

/// A depth that is a whole number of pecks (9.149 mm in pecks of 1.307 mm: 7) makes exactly that
/// many pecks; the division's rounding once made an eighth peck of zero length at the bottom.
#[test]
fn a_depth_of_a_whole_number_of_pecks_makes_no_extra_zero_length_peck() {
    let src = "G21 G99 S500 M3\nT0404\nG0 X60 Z-5\nG75 R0.3\nG75 X41.702 Z-5 P1307 Q500 F0.05\n";
    let i = run(src);
    assert!(errors(&i).is_empty(), "{:?}", errors(&i));
    let feeds = line(&i, 5).iter().filter(|m| m.feed != Feed::Rapid).count();
    assert_eq!(feeds, 7);
}
