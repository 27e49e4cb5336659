//! Canned cycles: the hand-worked cases of `tests/cases/cycles/` pin their moves, and random
//! monotone (type I) profiles show that G71 roughing never cuts inside the profile plus its
//! allowance, leaves at most one depth of cut anywhere, and that G70 ends on the profile.

use latheguard::interp::{canon, Interpretation, MoveKind};
use latheguard::machine::Machine;
use latheguard::pipeline;
use proptest::prelude::*;
use std::path::PathBuf;

fn canon_of(src: &[u8]) -> (Interpretation, String) {
    canon_on(src, &Machine::builtin())
}

fn canon_on(src: &[u8], machine: &Machine) -> (Interpretation, String) {
    let (_, run) = pipeline::interpret(src, machine);
    let mut out = Vec::new();
    canon::write(&run, &mut out).unwrap();
    (run, String::from_utf8(out).unwrap())
}

/// A type I OD profile: radius and z of each vertex from the first profile point (A') on, x never
/// falling and z never rising.
#[derive(Debug, Clone)]
struct Profile {
    pts: Vec<(f64, f64)>,
}

/// With `pockets`, X may also fall (a type II profile): Z never rises, X stays above 1.
fn profile(pockets: bool) -> impl Strategy<Value = Profile> {
    let step = (0u8..if pockets { 4 } else { 3 }, 1u32..8000, 1u32..4000);
    (2000u32..15000, prop::collection::vec(step, 1..7)).prop_map(|(xa, steps)| {
        let mut x = xa as f64 / 1000.0;
        let mut z = 0.0;
        let mut pts = vec![(x, z)];
        for (kind, dz, dx) in steps {
            let (dz, dx) = (dz as f64 / 1000.0, dx as f64 / 1000.0);
            match kind {
                0 => z -= dz,
                1 => x += dx,
                2 => {
                    z -= dz;
                    x += dx;
                }
                _ => {
                    z -= dz;
                    x = (x - dx).max(1.0);
                }
            }
            pts.push((x, z));
        }
        Profile { pts }
    })
}

/// The least radius of the profile (shifted by `off`) at `z`, when `z` lies in its range.
fn radius_at(pts: &[(f64, f64)], off: (f64, f64), z: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for w in pts.windows(2) {
        let (a, b) = ((w[0].0 + off.0, w[0].1 + off.1), (w[1].0 + off.0, w[1].1 + off.1));
        let (lo, hi) = (a.1.min(b.1), a.1.max(b.1));
        if z < lo - 1e-12 || z > hi + 1e-12 {
            continue;
        }
        let x = if (hi - lo).abs() < 1e-12 {
            a.0.min(b.0)
        } else {
            a.0 + (b.0 - a.0) * (z - a.1) / (b.1 - a.1)
        };
        best = Some(best.map_or(x, |v: f64| v.min(x)));
    }
    best
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn g71_type1_never_cuts_inside_the_allowance_leaves_at_most_one_depth_and_g70_ends_on_the_profile(
        p in profile(false),
        depth in 300u32..4000,
        du in 0u32..1000,
        dw in 0u32..500,
    ) {
        g71_properties(p, depth, du, dw, false)?;
    }

    #[test]
    fn g71_type2_with_pockets_never_cuts_inside_the_allowance_and_leaves_at_most_one_depth(
        p in profile(true),
        depth in 300u32..4000,
        du in 0u32..1000,
        dw in 0u32..500,
    ) {
        g71_properties(p, depth, du, dw, true)?;
    }
}

/// Run G71 (type I, or type II when `type2`: block P names Z too) and G70 on the profile and check
/// the properties named by the tests above.
fn g71_properties(p: Profile, depth: u32, du: u32, dw: u32, type2: bool) -> Result<(), TestCaseError> {
    let depth = depth as f64 / 1000.0;
    let (du, dw) = (du as f64 / 1000.0, dw as f64 / 1000.0);
    let top = p.pts.iter().map(|q| q.0).fold(0.0, f64::max);
    let x0 = top + 2.0;
    let z0 = 3.0;
    let mut src = format!(
            "G21 G18 G99 G97 S500 M3\nT0101\nG0 X{:.3} Z{z0:.3}\nG71 U{depth:.3} R0.5\nG71 P10 Q{} U{du:.3} W{dw:.3} F0.2\n",
            2.0 * x0,
            10 * p.pts.len()
        );
    src += &format!(
        "N10 G0 X{:.3}{}\n",
        2.0 * p.pts[0].0,
        if type2 { format!(" Z{z0:.3}") } else { String::new() }
    );
    for (i, q) in p.pts.iter().enumerate().skip(1) {
        src += &format!("N{} G1 X{:.3} Z{:.3} F0.1\n", 10 * (i + 1), 2.0 * q.0, q.1);
    }
    src += &format!("G70 P10 Q{}\nM30\n", 10 * p.pts.len());
    let (run, _) = canon_of(src.as_bytes());
    prop_assert!(
        run.findings
            .iter()
            .all(|f| f.kind != latheguard::finding::Kind::Program),
        "{:?}\n{src}",
        run.findings
    );
    // The profile as programmed: the first point keeps the start's z (type I).
    let mut pts = p.pts.clone();
    pts[0].1 = z0;
    let off = (du / 2.0, dw);
    let o = run.frame(&run.moves[0]).origin;
    let prog = |q: latheguard::geom::P2| (q.x - o.x, q.y - o.y);
    let g71: Vec<_> = run.moves.iter().filter(|m| m.line == 5).collect();
    let g70: Vec<_> = run
        .moves
        .iter()
        .filter(|m| m.line as usize == 6 + p.pts.len())
        .collect();
    prop_assert!(!g71.is_empty() && !g70.is_empty(), "{src}");
    // 1. No move of G71 (feed or rapid) goes inside the offset profile.
    let mut reached: Vec<(f64, f64, f64)> = Vec::new(); // (z from, z to, level) of Z passes
    for m in &g71 {
        let (s, e) = (prog(m.start), prog(m.end));
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            let (x, z) = (s.0 + (e.0 - s.0) * t, s.1 + (e.1 - s.1) * t);
            if let Some(r) = radius_at(&pts, off, z) {
                prop_assert!(x >= r - 1e-6, "cuts inside at x {x} z {z} (profile {r})\n{src}");
            }
        }
        if m.kind == MoveKind::Line && (s.0 - e.0).abs() < 1e-12 {
            reached.push((s.1.min(e.1), s.1.max(e.1), s.0));
        }
    }
    // 2. The Z passes leave at most one depth of cut above the offset profile.
    // (In front of the start point, z > z0, is air: the start point lies outside the stock.)
    let (zmin, zmax) = (pts.last().unwrap().1 + dw, z0);
    for k in 0..=200 {
        let z = zmax + (zmin - zmax) * k as f64 / 200.0;
        let Some(r) = radius_at(&pts, off, z) else { continue };
        let lowest = reached
            .iter()
            .filter(|(a, b, _)| *a <= z + 1e-9 && z <= *b + 1e-9)
            .map(|p| p.2)
            .fold(x0, f64::min);
        prop_assert!(
            lowest - r <= depth + 1e-6,
            "leaves {} at z {z} (depth {depth})\n{src}",
            lowest - r
        );
    }
    // 3. G70 runs through every profile vertex, in order (the approach of N10 first), and ends on
    // the last one.
    let ends: Vec<_> = g70.iter().take(pts.len()).map(|m| prog(m.end)).collect();
    prop_assert_eq!(ends.len(), pts.len());
    for (got, want) in ends.iter().zip(&pts) {
        prop_assert!(
            (got.0 - want.0).abs() < 1e-9 && (got.1 - want.1).abs() < 1e-9,
            "{got:?} {want:?}"
        );
    }
    // 4. Both cycles leave the machine at the start point.
    let last = run.moves.last().unwrap();
    prop_assert!((prog(last.end).0 - x0).abs() < 1e-9 && (prog(last.end).1 - z0).abs() < 1e-9);
    Ok(())
}

fn program_messages(run: &Interpretation) -> Vec<String> {
    run.findings
        .iter()
        .filter(|f| f.kind == latheguard::finding::Kind::Program)
        .map(|f| format!("{}: {}", f.line, f.message))
        .collect()
}

#[test]
fn a_tiny_depth_of_cut_is_a_finding_at_the_cycle_never_a_million_passes() {
    let src = "G21 G99 S500 M3\nG0 X100 Z3\nG71 P10 Q20 U0 W0 D0.00001 F0.2\nN10 G0 X20\nN20 G1 Z-50\nM30\n";
    let (run, _) = canon_of(src.as_bytes());
    let msgs = program_messages(&run);
    assert!(
        msgs.len() == 1 && msgs[0].starts_with("3: G71") && msgs[0].contains("too many passes"),
        "{msgs:?}"
    );
    assert!(run.moves.len() < 5, "{}", run.moves.len());
}

#[test]
fn a_profile_longer_than_the_cap_is_a_finding_and_is_not_run() {
    let mut src = String::from("G21 G99 S500 M3\nG0 X100 Z3\nG71 P1 Q99999 U0 W0 D1 F0.2\nN1 G0 X20\n");
    for k in 0..2100 {
        src += &format!("G1 Z-{}.0\n", k % 50);
    }
    src += "N99999 X102\nM30\n";
    let (run, _) = canon_of(src.as_bytes());
    let msgs = program_messages(&run);
    assert!(msgs.len() == 1 && msgs[0].contains("at most 2000"), "{msgs:?}");
    // Execution resumes nowhere inside the profile: only the start move and nothing of it.
    assert_eq!(run.moves.len(), 1);
}

#[test]
fn p_and_q_must_be_n_numbers_and_the_profile_must_not_hold_a_cycle_or_the_cycle_itself() {
    let head = "G21 G99 S500 M3\nG0 X100 Z3\nG71 U1 R0.5\n";
    for (body, want) in [
        (
            "G71 P10.5 Q20 U0 W0 F0.2\nN10 G0 X20\nN20 G1 Z-50\n",
            "4: G71: P10.5 Q20 must be N numbers",
        ),
        (
            "G71 P10 Q20 U0 W0 F0.2\nN10 G0 X20\nG70 P10 Q20\nN20 G1 Z-50\n",
            "4: G71: the profile holds another cycle (line 6)",
        ),
        // G70 skips nothing after it (the control reads the block after G70), so N20 then runs
        // as the next block: with no feed in force, a finding of its own.
        (
            "N10 G0 X20\nG70 P10 Q20\nN20 G1 Z-50\n",
            "5: G70: the profile N10–N20 holds the cycle block itself",
        ),
    ] {
        let src = format!("{head}{body}M30\n");
        let (run, _) = canon_of(src.as_bytes());
        let msgs = program_messages(&run);
        let expected = if want.contains("G70") { 2 } else { 1 };
        assert!(msgs.len() == expected && msgs[0].starts_with(want), "{msgs:?}\n{src}");
    }
}

/// A refused cycle still skips its profile: the blocks P..Q never run as plain moves (one
/// full-depth cut through the bar, and noise after it).
#[test]
fn a_refused_cycle_does_not_run_its_profile_as_plain_moves() {
    let src = "G21 G99 S500 M3\nG0 X100 Z3\nG71 P10 Q20 U0 W0 F0.2\nN10 G0 X20\nN20 G1 Z-50\nG0 X110\nM30\n";
    let (run, canon) = canon_of(src.as_bytes());
    assert!(program_messages(&run)[0].contains("needs a positive depth of cut"));
    assert_eq!(
        canon,
        "    2 STRAIGHT_TRAVERSE(50.0000, 0.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n    6 STRAIGHT_TRAVERSE(55.0000, 0.0000, 3.0000, 0.0000, 0.0000, 0.0000)\n"
    );
}

#[test]
fn inch_programs_scale_depth_allowance_and_retract() {
    // G20: D0.1 in = 2.54 mm, U0.02 in (diameter) = 0.254 mm on the radius, R0.02 in = 0.508 mm.
    let src = "G20 G99 S500 M3\nG0 X2.0 Z0.1\nG71 P10 Q20 U0.02 W0 D0.1 R0.02 F0.01\nN10 G0 X1.6\nN20 G1 Z-1.0\nG0 X3.0\nM30\n";
    let (_, canon) = canon_of(src.as_bytes());
    // Start radius 1.0 in, first point 0.8 + 0.01 = 0.81 in: span 0.19 in, D 0.1 in: 2 passes.
    let want = "    2 STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(0.9000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_FEED(0.9000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(0.9200, 0.0000, -0.9800, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(0.9200, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(0.8100, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_FEED(0.8100, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(1.0000, 0.0000, -1.0000, 0.0000, 0.0000, 0.0000)
    3 STRAIGHT_TRAVERSE(1.0000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
    6 STRAIGHT_TRAVERSE(1.5000, 0.0000, 0.1000, 0.0000, 0.0000, 0.0000)
";
    assert_eq!(canon, want);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn g72_facing_never_cuts_inside_the_allowance_leaves_at_most_one_depth_and_g70_ends_on_the_profile(
        p in profile(false),
        depth in 300u32..4000,
        du in 0u32..1000,
        dw in 0u32..500,
    ) {
        g72_properties(p, depth, du, dw)?;
    }
}

/// G72 on a type I facing profile made from a G71 one by exchanging the axes: radius 30 + z
/// (falling toward the axis) and Z -30 + (x - x0) (rising toward the front); the start point lies
/// outside radius 30 and in front of the profile.
fn g72_properties(p: Profile, depth: u32, du: u32, dw: u32) -> Result<(), TestCaseError> {
    let depth = depth as f64 / 1000.0;
    let (du, dw) = (du as f64 / 1000.0, dw as f64 / 1000.0);
    let x0 = 32.0;
    let mut pts: Vec<(f64, f64)> = p.pts.iter().map(|q| (30.0 + q.1, -30.0 + (q.0 - p.pts[0].0))).collect();
    pts[0].0 = x0; // block P names Z only: A' keeps the start's X
    let z0 = pts.iter().map(|q| q.1).fold(f64::MIN, f64::max) + 2.0;
    let mut src = format!(
        "G21 G18 G99 G97 S500 M3\nT0101\nG0 X{:.3} Z{z0:.3}\nG72 W{depth:.3} R0.5\nG72 P10 Q{} U{du:.3} W{dw:.3} F0.2\n",
        2.0 * x0,
        10 * pts.len()
    );
    src += &format!("N10 G0 Z{:.3}\n", pts[0].1);
    for (i, q) in pts.iter().enumerate().skip(1) {
        src += &format!("N{} G1 X{:.3} Z{:.3} F0.1\n", 10 * (i + 1), 2.0 * q.0, q.1);
    }
    src += &format!("G70 P10 Q{}\nM30\n", 10 * pts.len());
    let (run, _) = canon_of(src.as_bytes());
    prop_assert!(program_messages(&run).is_empty(), "{:?}\n{src}", run.findings);
    let o = run.frame(&run.moves[0]).origin;
    let prog = |q: latheguard::geom::P2| (q.x - o.x, q.y - o.y);
    // The same checks as G71's with the axes exchanged: (Z, X) pairs, the least Z at an X.
    let swapped: Vec<(f64, f64)> = pts.iter().map(|q| (q.1, q.0)).collect();
    let off = (dw, du / 2.0);
    let g72: Vec<_> = run.moves.iter().filter(|m| m.line == 5).collect();
    let g70: Vec<_> = run.moves.iter().filter(|m| m.line as usize == 6 + pts.len()).collect();
    prop_assert!(!g72.is_empty() && !g70.is_empty(), "{src}");
    let mut reached: Vec<(f64, f64, f64)> = Vec::new(); // (x from, x to, z) of X passes
    for m in &g72 {
        let (s, e) = (prog(m.start), prog(m.end));
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            let (x, z) = (s.0 + (e.0 - s.0) * t, s.1 + (e.1 - s.1) * t);
            if let Some(face) = radius_at(&swapped, off, x) {
                prop_assert!(z >= face - 1e-6, "cuts inside at x {x} z {z} (face {face})\n{src}");
            }
        }
        if m.kind == MoveKind::Line && (s.1 - e.1).abs() < 1e-12 {
            reached.push((s.0.min(e.0), s.0.max(e.0), s.1));
        }
    }
    let (xmin, xmax) = (pts.last().unwrap().0 + du / 2.0, x0);
    for k in 0..=200 {
        let x = xmax + (xmin - xmax) * k as f64 / 200.0;
        let Some(face) = radius_at(&swapped, off, x) else {
            continue;
        };
        let lowest = reached
            .iter()
            .filter(|(a, b, _)| *a <= x + 1e-9 && x <= *b + 1e-9)
            .map(|q| q.2)
            .fold(z0, f64::min);
        prop_assert!(
            lowest - face <= depth + 1e-6,
            "leaves {} at x {x} (depth {depth})\n{src}",
            lowest - face
        );
    }
    let ends: Vec<_> = g70.iter().take(pts.len()).map(|m| prog(m.end)).collect();
    prop_assert_eq!(ends.len(), pts.len());
    for (got, want) in ends.iter().zip(&pts) {
        prop_assert!(
            (got.0 - want.0).abs() < 1e-9 && (got.1 - want.1).abs() < 1e-9,
            "{got:?} {want:?}"
        );
    }
    let last = run.moves.last().unwrap();
    prop_assert!((prog(last.end).0 - x0).abs() < 1e-9 && (prog(last.end).1 - z0).abs() < 1e-9);
    Ok(())
}

#[test]
fn absurd_cycle_values_are_a_finding_not_moves_out_of_any_range() {
    // (Numbers have no exponent in G-code: the large values are written out.)
    let big = "1".to_string() + &"0".repeat(300);
    for words in [
        format!("D1 R{big}"),
        format!("D1 U{big}"),
        "D1 W-99999".into(),
        format!("D{big}"),
    ] {
        let src = format!("G21 G99 S500 M3\nG0 X100 Z3\nG71 P10 Q20 {words} F0.2\nN10 G0 X20\nN20 G1 Z-50\nM30\n");
        let (run, _) = canon_of(src.as_bytes());
        let msgs = program_messages(&run);
        assert!(msgs.len() == 1 && msgs[0].starts_with("3: G71"), "{words}: {msgs:?}");
        assert_eq!(run.moves.len(), 1, "{words}");
    }
    let src = "G21 G99 S500 M3\nG0 X100 Z3\nG73 P10 Q20 I1000000000 D2 F0.2\nN10 G0 X20\nN20 G1 Z-50\nM30\n";
    let (run, _) = canon_of(src.as_bytes());
    assert!(program_messages(&run)[0].contains("beyond"), "{:?}", run.findings);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100))]

    /// G73 cuts the whole profile d times, shifted by the allowance plus (d - k)/(d - 1) of the
    /// relief on pass k: the first pass furthest out, the last on the allowance.
    #[test]
    fn g73_repeats_the_profile_shifted_by_a_shrinking_relief(
        p in profile(true),
        passes in 1u32..6,
        ri in 0u32..5000,
        rk in 0u32..3000,
        du in 0u32..1000,
        dw in 0u32..500,
    ) {
        let (ri, rk) = (ri as f64 / 1000.0, rk as f64 / 1000.0);
        let (du, dw) = (du as f64 / 1000.0, dw as f64 / 1000.0);
        let top = p.pts.iter().map(|q| q.0).fold(0.0, f64::max);
        let (x0, z0) = (top + ri + 3.0, 3.0 + rk + 1.0);
        let mut src = format!(
            "G21 G18 G99 G97 S500 M3\nT0101\nG0 X{:.3} Z{z0:.3}\nG73 U{ri:.3} W{rk:.3} R{passes}\nG73 P10 Q{} U{du:.3} W{dw:.3} F0.2\n",
            2.0 * x0,
            10 * p.pts.len()
        );
        src += &format!("N10 G0 X{:.3} Z3.000\n", 2.0 * p.pts[0].0);
        for (i, q) in p.pts.iter().enumerate().skip(1) {
            src += &format!("N{} G1 X{:.3} Z{:.3} F0.1\n", 10 * (i + 1), 2.0 * q.0, q.1);
        }
        src += "M30\n";
        let (run, _) = canon_of(src.as_bytes());
        prop_assert!(program_messages(&run).is_empty(), "{:?}\n{src}", run.findings);
        let mut pts = p.pts.clone();
        pts[0].1 = 3.0;
        let o = run.frame(&run.moves[0]).origin;
        let prog = |q: latheguard::geom::P2| (q.x - o.x, q.y - o.y);
        let feeds: Vec<_> = run.moves.iter().filter(|m| m.line == 5 && m.kind == MoveKind::Line).map(|m| prog(m.end)).collect();
        let n = passes as usize;
        prop_assert_eq!(feeds.len(), n * (pts.len() - 1));
        for k in 1..=n {
            let frac = if n == 1 { 0.0 } else { (n - k) as f64 / (n - 1) as f64 };
            let shift = (du / 2.0 + ri * frac, dw + rk * frac);
            for (j, want) in pts.iter().skip(1).enumerate() {
                let got = feeds[(k - 1) * (pts.len() - 1) + j];
                prop_assert!(
                    (got.0 - want.0 - shift.0).abs() < 1e-9 && (got.1 - want.1 - shift.1).abs() < 1e-9,
                    "pass {k} point {j}: {got:?} want {want:?} + {shift:?}\n{src}"
                );
            }
        }
        let last = prog(run.moves.last().unwrap().end);
        prop_assert!((last.0 - x0).abs() < 1e-9 && (last.1 - z0).abs() < 1e-9);
    }
}

/// A crash in a roughing pass is reported at the cycle's line and names the profile block the
/// pass follows (text, JSON and SARIF carry `profile_line`), in both modes.
#[test]
fn a_crash_in_a_cycle_pass_names_the_cycle_line_and_the_profile_line() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/cases/cycles/fanuc_g71_into_the_chuck.nc");
    let src = std::fs::read(&path).unwrap();
    for mode in [pipeline::Mode::Step, pipeline::Mode::Exact] {
        let settings = pipeline::Settings {
            mode,
            ..pipeline::Settings::default()
        };
        let out = pipeline::check(&src, &Machine::builtin(), &settings);
        let crashes: Vec<_> = out.findings.iter().filter(|f| f.objects.len() == 2).collect();
        assert!(!crashes.is_empty(), "{mode:?}: no crash found");
        for f in crashes {
            // Line 8 is the G71 block; line 11 is `N20 G1 Z-79`, the profile block into the jaws.
            assert_eq!((f.line, f.profile_line), (8, Some(11)), "{mode:?}: {}", f.message);
        }
    }
    // A finding of a plain move has no profile line.
    let plain = b"G21 G18 G99 G97 S800 M3\nT0101\nG0 X50 Z3\nG1 Z-79 F0.25\nM30\n";
    let out = pipeline::check(plain, &Machine::builtin(), &pipeline::Settings::default());
    assert!(out.findings.iter().any(|f| f.line == 4));
    assert!(out.findings.iter().all(|f| f.profile_line.is_none()));
}

/// Posts repeat N numbers from one operation to the next: each G70 finishes the profile its own
/// G71 roughed just before it (the nearest N before the G70), and the blocks after G70 run next —
/// nothing between one G70 and the next operation's profile is skipped.
#[test]
fn g70_finishes_the_profile_before_it_when_n_numbers_repeat_and_skips_nothing_after_it() {
    let unit = "G0 X52 Z3\nG71 U2 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X20\nN20 G1 Z-30\nG70 P10 Q20\nG0 X60 Z5\nG1 X58 F0.2\n";
    let src = format!("G21 G18 G99 G97 S800 M3\nT0101\n{unit}{unit}M30\n");
    let (run, _) = canon_of(src.as_bytes());
    assert!(program_messages(&run).is_empty(), "{:?}", program_messages(&run));
    // The G70 blocks are lines 8 and 16; each of their moves lies on its own unit's profile.
    for g70 in [8u32, 16] {
        assert!(
            run.moves.iter().any(|m| m.line == g70),
            "G70 at line {g70} made no moves"
        );
    }
    // The lines after each G70 (9, 10 and 17, 18) ran, and the second G71 (line 13) roughed.
    for line in [9u32, 10, 13, 17, 18] {
        assert!(run.moves.iter().any(|m| m.line == line), "line {line} did not run");
    }
    // Each G70 follows the profile N10/N20 before it: its feed moves end on X20 (radius 10) or
    // at Z-30, never beyond the profile.
    for m in run.moves.iter().filter(|m| m.line == 8 || m.line == 16) {
        assert!(
            m.profile_line == 0 || m.profile_line < m.line,
            "G70 at {} used line {}",
            m.line,
            m.profile_line
        );
    }
}
