//! Property tests of the in-process stock model (`scene::stock::DexelStock`).

use latheguard::geom::{p2, P2};
use latheguard::scene::DexelStock;
use proptest::prelude::*;

const H: f64 = 0.01;

fn bar() -> DexelStock {
    DexelStock::new(50.0, 0.0, 120.0, 80.0, H)
}

fn rect(r0: f64, z0: f64, r1: f64, z1: f64) -> Vec<P2> {
    vec![p2(r0, z0), p2(r1, z0), p2(r1, z1), p2(r0, z1)]
}

fn circle(rc: f64, zc: f64, radius: f64, n: usize) -> Vec<P2> {
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            p2(rc + radius * a.cos(), zc + radius * a.sin())
        })
        .collect()
}

fn any_cut() -> impl Strategy<Value = Vec<P2>> {
    prop_oneof![
        (-30.0..30.0f64, -45.0..85.0f64, 0.1..20.0f64, 0.1..30.0f64).prop_map(|(x, z, w, h)| rect(x, z, x + w, z + h)),
        (-30.0..30.0f64, -45.0..85.0f64, 0.5..15.0f64).prop_map(|(x, z, r)| circle(x, z, r, 24)),
        (
            (-30.0..30.0f64, -45.0..85.0f64),
            (-30.0..30.0f64, -45.0..85.0f64),
            (-30.0..30.0f64, -45.0..85.0f64)
        )
            .prop_map(|(a, b, c)| vec![p2(a.0, a.1), p2(b.0, b.1), p2(c.0, c.1)]),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn removal_is_monotone_the_stock_never_grows(cuts in prop::collection::vec(any_cut(), 1..12)) {
        let mut s = bar();
        let mut area = s.section_area();
        for c in &cuts {
            s.cut(c);
            let a = s.section_area();
            prop_assert!(a <= area + 1e-9, "area grew from {area} to {a}");
            area = a;
        }
    }

    #[test]
    fn removal_does_not_depend_on_order(a in any_cut(), b in any_cut()) {
        let mut ab = bar();
        ab.cut(&a);
        ab.cut(&b);
        let mut ba = bar();
        ba.cut(&b);
        ba.cut(&a);
        prop_assert_eq!(ab.outlines(0.0), ba.outlines(0.0));
    }

    #[test]
    fn a_cut_part_reentering_its_pose_only_touches(c in any_cut()) {
        let mut s = bar();
        s.cut(&c);
        prop_assert!(s.overlap(&c, 1e-6).is_none());
    }

    #[test]
    fn removed_area_of_a_rectangle_is_exact_within_the_tolerance(
        r0 in 0.0..20.0f64, w in 0.5..5.0f64, z0 in -30.0..60.0f64, h in 0.5..20.0f64
    ) {
        let mut s = bar();
        let before = s.section_area();
        s.cut(&rect(r0, z0, r0 + w, z0 + h));
        let removed = before - s.section_area();
        // Along z the edges sit at column boundaries: at most one column width off at each end.
        prop_assert!((removed - w * h).abs() <= 2.0 * w * H + 1e-9, "removed {removed}, exact {}", w * h);
    }

    #[test]
    fn removed_area_of_a_circle_matches_within_the_tolerance(
        rc in 6.0..19.0f64, zc in -25.0..60.0f64, radius in 0.5..5.0f64
    ) {
        let mut s = bar();
        let before = s.section_area();
        // A fine polygon: its own area differs from the circle's by less than 1e-4 relative.
        let n = 720;
        s.cut(&circle(rc, zc, radius, n));
        let removed = before - s.section_area();
        let poly_area = 0.5 * n as f64 * radius * radius * (std::f64::consts::TAU / n as f64).sin();
        prop_assert!((removed - poly_area).abs() <= 2.0 * radius * H * 2.0 + 1e-6,
            "removed {removed}, exact {poly_area}");
    }
}

#[test]
fn a_tool_far_above_the_bar_costs_no_column_visit_and_finds_nothing() {
    let mut s = bar();
    assert!(s.overlap(&rect(26.0, -40.0, 60.0, 80.0), 1e-6).is_none());
    assert!(!s.cut(&rect(26.0, -40.0, 60.0, 80.0)));
}
