//! Depth of the cases in `tests/cases/stock/` whose deepest penetration comes in the middle of a
//! move: it rises, then falls before the move ends. Step mode at 0.1, 1 and 10 ms and exact mode
//! must all report the depth computed by hand (DESIGN §4: the depth is the deepest penetration of
//! the episode, the same in every mode within the tolerance, 0.01 mm).
//!
//! Against the stock the depth is the smaller of the largest radial overlap in one column and the
//! axial extent of the overlapping columns (`scene::stock::StockHit`); the hand computations below
//! use that definition. Machine frame: x = radius, z along the spindle, program Z0 is z 78, the
//! uncut bar is r 25 up to z 80.

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};

const TOLERANCE: f64 = 0.01;

fn modes() -> Vec<(String, Settings)> {
    let mut v: Vec<(String, Settings)> = [0.1, 1.0, 10.0]
        .into_iter()
        .map(|dt| {
            (
                format!("step dt={dt}"),
                Settings {
                    dt_ms: dt,
                    ..Settings::default()
                },
            )
        })
        .collect();
    v.push((
        "exact".into(),
        Settings {
            mode: Mode::Exact,
            ..Settings::default()
        },
    ));
    v
}

/// Runs `tests/cases/stock/{name}.nc` in every mode: exactly one finding, at `line`, of `kind`
/// between `objects`, whose depth is `depth` within the tolerance.
fn assert_depth(name: &str, line: u32, kind: &str, objects: [&str; 2], depth: f64) {
    let path = format!("{}/tests/cases/stock/{name}.nc", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read(&path).unwrap();
    let mut depths = Vec::new();
    for (mode, s) in modes() {
        let out = pipeline::check(&src, &Machine::builtin(), &s);
        let f: Vec<_> = out
            .findings
            .iter()
            .map(|f| (f.line, f.kind.to_string(), f.objects.clone(), f.depth_mm))
            .collect();
        assert_eq!(f.len(), 1, "{name} {mode}: {f:?}");
        assert_eq!((f[0].0, f[0].1.as_str()), (line, kind), "{name} {mode}: {f:?}");
        assert_eq!(f[0].2, objects, "{name} {mode}");
        let d = f[0].3.unwrap_or_else(|| panic!("{name} {mode}: no depth"));
        assert!(
            (d - depth).abs() <= TOLERANCE,
            "{name} {mode}: depth {d}, computed by hand {depth}"
        );
        depths.push(d);
    }
    let (lo, hi) = depths
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &d| (a.min(d), b.max(d)));
    assert!(hi - lo <= TOLERANCE, "{name}: depths differ between modes: {depths:?}");
}

#[test]
fn a_bar_corner_clipping_the_bar_end_is_deepest_mid_feed_in_every_mode() {
    // T03 feeds from r 41, z 75 to r 37, z 79 (X82 Z-3 to X74 Z1): tip r = 41 - 4s, z = 75 + 4s.
    // The bar's low front corner is at tip + (-15, +2); the bar end's corner is r 25, z 80.
    // Overlap: r from tip - 15 to 25, z from tip z + 2 to 80, the bar covering all of it.
    //   radial = 25 - (41 - 4s - 15) = 4s - 1,  axial = 80 - (75 + 4s + 2) = 3 - 4s.
    // min(4s - 1, 3 - 4s) is largest where they are equal, s = 0.5: depth 1 mm exactly.
    assert_depth(
        "bar_corner_clips_bar_end_mid_feed",
        14,
        "collision",
        ["T03 holder", "stock"],
        1.0,
    );
}

#[test]
fn a_grooving_insert_clipping_the_bar_end_in_a_rapid_is_deepest_mid_move_in_every_mode() {
    // T04 rapids from r 26, z 77 to r 22, z 81.8 (X52 Z-1 to X44 Z3.8). The dogleg moves each axis
    // at its own rate (x 20000, z 24000 mm/min, 5 : 6) and the move is 4 : 4.8 = 5 : 6, so it is
    // one straight line: r = 26 - 5t, z = 77 + 6t. The groover's face at the programmed r is flat,
    // and its 0.2 mm nose is set as an imaginary tip, lowest point at the programmed z. Overlap
    // with the bar end's corner (r 25, z 80): radial 25 - r = 5t - 1, axial 80 - z = 3 - 6t.
    // Equal at t = 4/11: depth 5 * 4/11 - 1 = 9/11 = 0.8182 mm.
    assert_depth(
        "rapid_insert_clips_bar_end_corner",
        16,
        "rapid_into_stock",
        ["T04 insert", "stock"],
        9.0 / 11.0,
    );
}

#[test]
fn a_bar_front_leading_down_a_taper_is_deepest_mid_move_against_the_stock_at_the_instant() {
    // The ring at the bore step (see the case's comments): r 10 up to the 27 mm pass's bottom edge.
    // T03's 0.4 mm nose is set as an imaginary tip, which moves the tool (insert and bar) by
    // (+0.0393, -0.0393) from its sharp outlines; the insert's bottom edge rises 1 in 12 toward
    // -x, so the 27 mm pass (tip r 13.5 at step z0 = Z-6) leaves the ring's top at
    //   z0 + ((13.5 - 10) + 0.0393) / 12 - 0.0393 = z0 + 0.2556   at r 10.
    // The taper: tip r = 18 - 0.5u, z = z0 - u. The bar front is 2 - 0.0393 = 1.9607 mm above the
    // tip, from tip - 14.9607 to tip - 3.9607 in r. At that height the insert's -x edge (from
    // (-6, 0.5) to (-6.5, 6.5), moved as above) is at tip - 5.9607 - (1.9607 - 0.4607) / 12 =
    // tip - 6.0857, and since the tip only falls, that is also the lowest the cut has reached
    // there so far. So the material the bar front meets is r 10 .. tip - 6.0857, from the bar
    // front up to the ring's top:
    //   radial = 18 - 0.5u - 6.0857 - 10 = 1.9143 - 0.5u   (the bar front's column is the widest)
    //   axial  = (z0 + 0.2556) - (z0 - u + 1.9607) = u - 1.7051
    // Contact from u = 1.7051 (X34.295 Z-7.705); equal at 1.5u = 3.6194, u = 2.4129: depth
    // 0.7078 mm. Afterwards the insert, lower down the taper, cuts the ring away.
    assert_depth(
        "bar_front_leads_down_a_taper",
        30,
        "collision",
        ["T03 holder", "stock"],
        0.7078,
    );
}

#[test]
fn a_boring_bar_facing_deeper_than_its_bar_front_is_as_deep_as_the_stock_at_the_instant() {
    // The bar front, 2 mm above the sharp tip, is 1.9607 mm above the programmed point once the
    // 0.4 mm nose sets the tool (insert and bar move by (+0.0393, -0.0393)): z 78.9607, 1.0393 mm
    // inside the bar end (z 80) from the moment its low corner reaches r 25; the insert, 8.9 mm
    // behind it in r, cuts that band only later. Radial overlap tip - 6.09 - (tip - 15) = 8.9
    // (both moved alike), axial 1.0393: depth 1.0393 mm.
    assert_depth(
        "boring_bar_faces_deeper_than_its_bar_front",
        15,
        "collision",
        ["T03 holder", "stock"],
        1.0393,
    );
}
