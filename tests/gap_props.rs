//! The checker's gap bound against the stock (`DexelStock::gap_bound_view`): step mode skips the
//! samples a pair cannot collide in, and exact mode advances time, by this bound, so it must never
//! be larger than the true distance from the part to the material as the query sees it — the
//! stock at the instant of the cutting move under way, before the move, or now.
//!
//! The oracle is slow and independent of the code under test: the stock at an instant is built by
//! cutting a copy of the stock from before the move with the swept region up to that instant
//! (`DexelStock::cut`, the ordinary cut), and the distance is measured column by column with `geo`
//! from the part to each radial interval of material at the column's centre plane (and its mirror
//! image: parts are folded about the axis).

use geo::{Distance, Euclidean};
use latheguard::geom::{p2, P2};
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use latheguard::scene::{DexelStock, Swept, View};
use proptest::prelude::*;

/// Rounding allowed between the bound and the oracle, mm (far below `geom::TOUCH_EPS`).
const ROUNDING: f64 = 1e-9;

fn geo_poly(pts: &[P2]) -> geo::Polygon<f64> {
    let mut c: Vec<geo::Coord<f64>> = pts.iter().map(|p| geo::coord! { x: p.x, y: p.y }).collect();
    c.push(c[0]);
    geo::Polygon::new(geo::LineString::new(c), vec![])
}

/// The distance from a part to every radial interval of material, column by column.
fn oracle_distance(stock: &DexelStock, z0: f64, part: &[P2]) -> f64 {
    let poly = geo_poly(part);
    let h = stock.column_width();
    let mut best = f64::INFINITY;
    for j in 0..stock.columns() {
        let c = z0 + (j as f64 + 0.5) * h;
        for (lo, hi) in stock.material_at(c) {
            for (a, b) in [(lo, hi), (-hi, -lo)] {
                let seg = geo::Line::new(geo::coord! { x: a, y: c }, geo::coord! { x: b, y: c });
                best = best.min(Euclidean.distance(&poly, &seg));
            }
        }
    }
    best
}

/// The region a convex insert sweeps moving from `a` toward `b`, up to fraction `f`: the insert at
/// the start, each edge swept along the path, the insert at the end (as the checker builds it).
fn swept_until(insert: &[P2], a: P2, b: P2, f: f64) -> Swept {
    let at = |p: P2| -> Vec<P2> { insert.iter().map(|q| p + q.coords).collect() };
    let end = a + (b - a) * f;
    let d = end - a;
    let mut sw = Swept::default();
    sw.push(at(a));
    let start = at(a);
    let n = start.len();
    for i in 0..n {
        let (p, q) = (start[i], start[(i + 1) % n]);
        sw.push(vec![p, q, q + d, p + d]);
    }
    sw.push(at(end));
    sw
}

fn rect(x0: f64, z0: f64, x1: f64, z1: f64) -> Vec<P2> {
    vec![p2(x0, z0), p2(x1, z0), p2(x1, z1), p2(x0, z1)]
}

/// Part shapes, relative to their reference point: a boring bar in its block (the built-in
/// machine's T03 holder, not convex), a rectangle, a sliver of a triangle.
fn shape(kind: u8, s: f64) -> Vec<P2> {
    match kind % 3 {
        0 => [
            (-15.0, 2.0),
            (-4.0, 2.0),
            (-3.0, 8.0),
            (-3.0, 50.0),
            (31.0, 50.0),
            (31.0, 110.0),
            (-29.0, 110.0),
            (-29.0, 50.0),
            (-15.0, 50.0),
        ]
        .iter()
        .map(|&(x, z)| p2(x * s * 0.2, z * s * 0.2))
        .collect(),
        1 => rect(0.0, 0.0, 3.0 * s, 2.0 * s),
        _ => vec![p2(0.0, 0.0), p2(6.0 * s, -0.5 * s), p2(7.0 * s, 3.0 * s)],
    }
}

fn posed(shape: &[P2], at: P2) -> Vec<P2> {
    shape.iter().map(|q| at + q.coords).collect()
}

#[derive(Debug, Clone)]
struct Case {
    tube: bool,
    h: f64,
    precuts: Vec<(f64, f64, f64, f64)>,
    insert_size: f64,
    from: (f64, f64),
    to: (f64, f64),
    f: f64,
    f2: f64,
    part: u8,
    scale: f64,
    at: (f64, f64),
    window: f64,
}

fn case() -> impl Strategy<Value = Case> {
    (
        any::<bool>(),
        prop_oneof![Just(0.05), Just(0.1), Just(0.37)],
        prop::collection::vec((-22.0..22.0f64, -2.0..32.0f64, 0.5..12.0f64, 0.5..10.0f64), 0..4),
        0.5..4.0f64,
        ((-28.0..28.0f64), (-5.0..35.0f64)),
        ((-28.0..28.0f64), (-5.0..35.0f64)),
        (0.0..1.0f64, 0.0..1.0f64),
        any::<u8>(),
        0.2..1.5f64,
        ((-30.0..30.0f64), (-10.0..40.0f64)),
        prop_oneof![Just(2.0), Just(10.0), Just(20.0)],
    )
        .prop_map(
            |(tube, h, precuts, insert_size, from, to, (f, g), part, scale, at, window)| Case {
                tube,
                h,
                precuts,
                insert_size,
                from,
                to,
                f: f.min(g),
                f2: f.max(g),
                part,
                scale,
                at,
                window,
            },
        )
}

/// The stock of a case: a bar (or tube) of Ø40, 30 long, its front at z = 30, with a few pieces
/// already cut away.
const Z0: f64 = 0.0;

fn stock_of(c: &Case) -> DexelStock {
    let mut s = DexelStock::new(40.0, if c.tube { 12.0 } else { 0.0 }, 30.0, Z0 + 30.0, c.h);
    for &(x, z, w, l) in &c.precuts {
        s.cut(&rect(x, z, x + w, z + l));
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// During a cutting move, the bound against the stock at an instant is never larger than the
    /// distance to the stock at that instant, nor to the stock at any later instant of the move
    /// (which holds less material); before the move and after it, the same against the stock
    /// then.
    #[test]
    fn the_gap_bound_never_exceeds_the_distance_to_the_stock_at_the_instant(c in case()) {
        let insert = vec![
            p2(0.0, 0.0),
            p2(-c.insert_size, 0.3 * c.insert_size),
            p2(-c.insert_size, c.insert_size),
            p2(-0.2 * c.insert_size, c.insert_size),
        ];
        let (a, b) = (p2(c.from.0, c.from.1), p2(c.to.0, c.to.1));
        let part = posed(&shape(c.part, c.scale), p2(c.at.0, c.at.1));
        let before = stock_of(&c);
        let mut s = before.clone();
        s.begin_move();
        for p in swept_until(&insert, a, b, 1.0).polygons() {
            s.cut(p);
        }
        let at = |f: f64| {
            let mut o = before.clone();
            for p in swept_until(&insert, a, b, f).polygons() {
                o.cut(p);
            }
            o
        };
        let sw = swept_until(&insert, a, b, c.f);
        let bound = s.gap_bound_view(&part, c.window, View::Instant(&sw));
        prop_assert!(bound <= c.window);
        // The blocks taken nearest first: the walk in the order of z, to rounding (a box's bound
        // and an edge's distance round apart: the saved case differs in the last bit).
        let walked = s.gap_bound_view_in_order(&part, c.window, View::Instant(&sw));
        prop_assert!((bound - walked).abs() <= 1e-12 * (1.0 + bound.abs()), "{bound} against {walked} in the order of z");
        let truth = oracle_distance(&at(c.f), Z0, &part);
        prop_assert!(bound <= truth + ROUNDING, "instant {}: bound {bound} > distance {truth}", c.f);
        let later = oracle_distance(&at(c.f2), Z0, &part);
        prop_assert!(bound <= later + ROUNDING, "instant {} bound {bound} > distance {later} at {}", c.f, c.f2);

        // The insert's own spindle-stopped test: the stock before the move.
        let empty = Swept::default();
        let pre = s.gap_bound_view(&part, c.window, View::Instant(&empty));
        let truth = oracle_distance(&before, Z0, &part);
        prop_assert!(pre <= truth + ROUNDING, "before the move: bound {pre} > distance {truth}");

        s.end_move();
        let now = s.gap_bound(&part, c.window);
        let walked = s.gap_bound_view_in_order(&part, c.window, View::Now);
        prop_assert!((now - walked).abs() <= 1e-12 * (1.0 + now.abs()), "{now} against {walked} in the order of z");
        let truth = oracle_distance(&at(1.0), Z0, &part);
        prop_assert!(now <= truth + ROUNDING, "after the move: bound {now} > distance {truth}");
    }
}

/// A shoulder at a block boundary (64 columns a block): the material of the first block reaches
/// r 20, the next block is turned down to r 3. A sloping part's lowest corner sits 0.3 mm past the
/// boundary at r 20, its body crosses the first block's slab further out. The old block bound used
/// the part's radial range within each block's slab only and said 5.77 mm; the truth is 0.30.
#[test]
fn gap_bound_never_exceeds_the_distance_to_a_shoulder_across_a_block_edge() {
    let h = 0.01;
    let mut s = DexelStock::new(40.0, 0.0, 1.28, 1.28, h); // 128 columns, 2 blocks
    assert_eq!(s.columns(), 128);
    s.cut(&rect(3.0, 0.64, 30.0, 2.0));
    let part = vec![p2(20.0, 0.94), p2(45.0, -0.36), p2(60.0, 5.64)];
    let truth = oracle_distance(&s, 0.0, &part);
    assert!(truth > 0.3 && truth < 0.306, "{truth}");
    let bound = s.gap_bound(&part, 10.0);
    assert!(bound <= truth + ROUNDING, "bound {bound} > distance {truth}");
    assert!(bound > truth - 1e-6, "the bound is exact for a box: {bound} < {truth}");
}

/// The bound in a changed column is the distance to its material at the instant, not before the
/// move: a bar running 3 mm below a surface its insert has just cut and 2 mm behind the uncut
/// wall ahead is about 2 mm clear — before the move, its top was inside the wall.
#[test]
fn a_boring_bar_behind_its_insert_is_bounded_against_the_bore_it_has_cut() {
    let mut s = DexelStock::new(60.0, 20.0, 40.0, 0.0, 0.01); // a tube, bore r 10
    let insert = vec![p2(0.0, 0.0), p2(-6.0, 0.5), p2(-6.5, 6.5), p2(-0.5, 6.0)];
    let bar = shape(0, 5.0); // the T03 holder, full size
    let (a, b) = (p2(13.5, 3.0), p2(13.5, -23.0));
    s.begin_move();
    for p in swept_until(&insert, a, b, 1.0).polygons() {
        s.cut(p);
    }
    let f = 0.5;
    let tip = a + (b - a) * f;
    let sw = swept_until(&insert, a, b, f);
    let g = s.gap_bound_view(&posed(&bar, tip), 10.0, View::Instant(&sw));
    let mut at_f = DexelStock::new(60.0, 20.0, 40.0, 0.0, 0.01);
    for p in sw.polygons() {
        at_f.cut(p);
    }
    let truth = oracle_distance(&at_f, -40.0, &posed(&bar, tip));
    assert!(g > 1.7 && g <= truth + ROUNDING, "bound {g}, distance {truth}");
    // Before the move the bar's top (r 10.5) was in the wall (r 10).
    let empty = Swept::default();
    assert_eq!(s.gap_bound_view(&posed(&bar, tip), 10.0, View::Instant(&empty)), 0.0);
}

/// A plain boring pass on the built-in machine: T06 drills Ø20 to Z-25, T03 bores Ø27 to Z-18, its
/// bar 0.5 mm into the drilled wall but behind the insert all along. The bar is clear, and proven
/// clear for long stretches, so the pass is not tested sample by sample (12,784 pair tests at
/// dt 0.1 ms and 4,134 probes in exact mode before the bound used the stock at the instant; 642
/// and 2,454 after, most of both the drill's and the insert's rapids along their own cut walls).
#[test]
fn a_boring_pass_with_the_bar_in_the_drilled_wall_is_not_tested_every_sample() {
    let src = "%\nG21 G18 G40 G97 G99\nG28 U0 W0\nT0606\nG97 S1500 M3\nG0 X0. Z5.\nG1 Z-25. F0.2\n\
               G0 Z5.\nG28 U0 W0\nT0303\nG97 S2500 M3\nG0 X27. Z3.\nG1 Z-18. F0.3\nG0 W3.\nX18.\nZ5.\n\
               G28 U0 W0\nM30\n%\n";
    let m = Machine::builtin();
    for (mode, dt, most) in [
        (Mode::Step, 0.1, 1_500),
        (Mode::Step, 1.0, 300),
        (Mode::Exact, 1.0, 3_000),
    ] {
        let settings = Settings {
            mode,
            dt_ms: dt,
            ..Settings::default()
        };
        let out = pipeline::check(src.as_bytes(), &m, &settings);
        assert!(
            out.findings.iter().all(|f| f.line != 13),
            "{mode:?}: {:?}",
            out.findings
        );
        assert!(
            out.stats.pair_tests <= most,
            "{mode:?} dt {dt}: {} pair tests",
            out.stats.pair_tests
        );
    }
}
