//! Sweep tests: first contact computable by hand, grazing, tiny and deep contacts, full circles,
//! and agreement with dense static sampling.

use super::props::star;
use super::util::pts;
use crate::geom::{
    interiors_overlap, p2, penetration_depth, sweep_arc, sweep_arc_episodes, sweep_line, sweep_line_episodes, Contact,
    Polygon, P2, TOUCH_EPS, V2,
};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

fn poly(v: &[(f64, f64)]) -> Polygon {
    Polygon::new(&pts(v)).unwrap()
}

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
    poly(&[(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
}

fn moved(p: &Polygon, s: V2) -> Polygon {
    p.translated(s)
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:.15}, want {want:.15} (diff {:e})",
        got - want
    );
}

/// Run a line sweep as given and moved by 1e7 mm (both parts): same answer, up to the rounding
/// of the moved coordinates (0.93 nm each, so up to ~2 nm of travel).
fn line_both_places(a: &Polygon, b: &Polygon, d: V2) -> Vec<Contact> {
    let here = sweep_line_episodes(a, b, d);
    let tol = 1e-9 + 4e-9 / d.norm();
    for s in [V2::new(1e7, 1e7), V2::new(-1e7, 2e7)] {
        let there = sweep_line_episodes(&moved(a, s), &moved(b, s), d);
        assert_eq!(here.len(), there.len(), "episodes here {here:?} there {there:?}");
        for (h, t) in here.iter().zip(&there) {
            close(t.t_start, h.t_start, tol, "t_start moved by 1e7");
            close(t.t_end, h.t_end, tol, "t_end moved by 1e7");
            close(t.max_depth, h.max_depth, 1e-6, "max_depth moved by 1e7");
        }
    }
    here
}

#[test]
fn box_moving_into_box_first_contact_is_exact() {
    // The right face x = 1 + 4t meets x = 3 at t = 0.5; the depth is 4t − 2 until it reaches
    // TOUCH_EPS at t = 0.5 + 2.5e-7. The boxes pass through each other (coinciding at t = 0.75)
    // and part at t = 1.
    let a = rect(0.0, 0.0, 1.0, 1.0);
    let b = rect(3.0, 0.0, 4.0, 1.0);
    let ep = line_both_places(&a, &b, V2::new(4.0, 0.0));
    assert_eq!(ep.len(), 1, "{ep:?}");
    close(ep[0].t_start, 0.5 + TOUCH_EPS / 4.0, 1e-12, "t_start");
    close(ep[0].t_end, 1.0 - TOUCH_EPS / 4.0, 1e-12, "t_end");
    close(ep[0].max_depth, 0.5, 1e-6, "max_depth");
    // Offset sideways by half its height: same first contact.
    let b2 = rect(3.0, 0.5, 4.0, 1.5);
    let c = sweep_line(&a, &b2, V2::new(4.0, 0.0)).unwrap();
    close(c.t_start, 0.5 + TOUCH_EPS / 4.0, 1e-12, "t_start, offset box");
    // Stopping short: the move ends touching.
    assert_eq!(sweep_line(&a, &b, V2::new(2.0, 0.0)), None);
}

#[test]
fn short_move_ending_inside_is_found() {
    // 0.02 mm down onto a jaw face, ending 0.01 mm inside it.
    let jaw = rect(-5.0, -3.0, 5.0, 0.0);
    let a = rect(0.0, 0.01, 1.0, 1.0);
    let ep = line_both_places(&a, &jaw, V2::new(0.0, -0.02));
    assert_eq!(ep.len(), 1, "{ep:?}");
    close(ep[0].t_start, 0.5 + TOUCH_EPS / 0.02, 1e-9, "t_start");
    assert_eq!(ep[0].t_end, 1.0);
    close(ep[0].max_depth, 0.01, 1e-9, "max_depth");
}

#[test]
fn corner_grazing_a_corner_briefly_in_a_long_move_is_found() {
    // The lower-right corner of a 3 mm box travels 707 mm along y = x + 9.95 and cuts the upper
    // left corner of b for 0.05 mm of x: the depth min(x, 0.05 − x) peaks at 25 µm. Sampling the
    // move at 10,000 points would step 0.05 mm in x and could miss it.
    let b = rect(0.0, 0.0, 10.0, 10.0);
    let (cx, cy) = (-250.0, -240.05);
    let a = rect(cx - 3.0, cy, cx, cy + 3.0);
    let ep = line_both_places(&a, &b, V2::new(500.0, 500.0));
    assert_eq!(ep.len(), 1, "{ep:?}");
    close(ep[0].t_start, (250.0 + TOUCH_EPS) / 500.0, 1e-11, "t_start");
    close(ep[0].t_end, (250.05 - TOUCH_EPS) / 500.0, 1e-11, "t_end");
    close(ep[0].max_depth, 0.025, 1e-6, "max_depth");
}

#[test]
fn grazing_and_touching_moves_are_not_contact() {
    let jaw = rect(-5.0, -3.0, 5.0, 0.0);
    // Sliding along the face.
    assert_eq!(sweep_line(&rect(0.0, 0.0, 1.0, 1.0), &jaw, V2::new(3.0, 0.0)), None);
    // Sliding along a slanted face (x + y = 4): positions round off the line by ~1e-16.
    let tri = poly(&[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)]);
    let on = poly(&[(3.0, 1.0), (4.0, 2.0), (2.0, 2.0)]);
    assert_eq!(sweep_line(&on, &tri, V2::new(-2.0, 2.0)), None);
    // A corner passing exactly through a corner (a above y = x, b below, both touching it).
    let a = poly(&[(1.0, 1.0), (0.0, 1.0), (-1.0, 0.0)]);
    let b = poly(&[(2.0, 2.0), (4.0, 2.0), (4.0, 0.0)]);
    assert_eq!(sweep_line(&a, &b, V2::new(2.0, 2.0)), None);
    // Approaching and stopping exactly on the face.
    assert_eq!(sweep_line(&rect(0.0, 2.0, 1.0, 3.0), &jaw, V2::new(0.0, -2.0)), None);
    // Corner 0.5 µm into the face: overlapping, but not by more than TOUCH_EPS.
    assert_eq!(
        sweep_line(&rect(0.0, 2.0, 1.0, 3.0), &jaw, V2::new(0.0, -2.0000005)),
        None
    );
}

#[test]
fn a_move_that_starts_overlapping_reports_t_zero() {
    let a = rect(0.0, 0.0, 1.0, 1.0);
    let b = rect(0.5, 0.0, 2.0, 1.0);
    let ep = line_both_places(&a, &b, V2::new(-2.0, 0.0));
    assert_eq!(ep.len(), 1, "{ep:?}");
    assert_eq!(ep[0].t_start, 0.0);
    close(ep[0].t_end, 0.25 - TOUCH_EPS / 2.0, 1e-12, "t_end");
    close(ep[0].max_depth, 0.5, 1e-9, "max_depth");
    // Not moving at all.
    let c = sweep_line(&a, &b, V2::zeros()).unwrap();
    assert_eq!((c.t_start, c.t_end), (0.0, 1.0));
    close(c.max_depth, 0.5, 1e-9, "max_depth, standing");
}

#[test]
fn every_episode_is_reported() {
    // A fork with two prongs; a small box crosses both.
    let fork = poly(&[
        (0.0, 0.0),
        (10.0, 0.0),
        (10.0, 2.0),
        (7.0, 2.0),
        (7.0, 1.0),
        (3.0, 1.0),
        (3.0, 2.0),
        (0.0, 2.0),
    ]);
    let a = rect(-2.0, 1.5, -1.0, 2.5);
    let ep = line_both_places(&a, &fork, V2::new(14.0, 0.0));
    assert_eq!(ep.len(), 2, "{ep:?}");
    // Prong x 0..3, box x −2+14t .. −1+14t.
    close(ep[0].t_start, (1.0 + TOUCH_EPS) / 14.0, 1e-12, "first start");
    close(ep[0].t_end, (5.0 - TOUCH_EPS) / 14.0, 1e-12, "first end");
    close(ep[1].t_start, (8.0 + TOUCH_EPS) / 14.0, 1e-12, "second start");
    close(ep[1].t_end, (12.0 - TOUCH_EPS) / 14.0, 1e-12, "second end");
    for e in &ep {
        close(e.max_depth, 0.5, 1e-6, "prong depth"); // the box dips 0.5 into the prongs
    }
    assert_eq!(sweep_line(&a, &fork, V2::new(14.0, 0.0)), Some(ep[0]));
}

#[test]
fn box_on_an_arc_first_contact_is_exact() {
    // The box's lower-left corner is the reference point, at (10, 0) on a circle of radius 10
    // about the origin; turning a quarter counter-clockwise lifts its top edge y = 1 + 10 sin θ
    // into the bar 5 ≤ y ≤ 6, and out again when its bottom edge 10 sin θ passes 6.
    let a = rect(10.0, 0.0, 11.0, 1.0);
    let bar = rect(-100.0, 5.0, 100.0, 6.0);
    for s in [V2::zeros(), V2::new(1e7, -1e7)] {
        let (a, bar) = (moved(&a, s), moved(&bar, s));
        let (c, start) = (p2(0.0, 0.0) + s, p2(10.0, 0.0) + s);
        let ep = sweep_arc_episodes(&a, &bar, c, start, FRAC_PI_2);
        assert_eq!(ep.len(), 1, "{ep:?}");
        let tol = if s == V2::zeros() { 1e-12 } else { 1e-9 };
        close(
            ep[0].t_start,
            (0.4 + TOUCH_EPS / 10.0).asin() / FRAC_PI_2,
            tol,
            "t_start",
        );
        close(ep[0].t_end, (0.6 - TOUCH_EPS / 10.0).asin() / FRAC_PI_2, tol, "t_end");
        close(ep[0].max_depth, 0.5, 1e-6, "max_depth");
        // Clockwise from the top of the same quarter circle: the mirror image in t.
        let top = rect(0.0, 10.0, 1.0, 11.0);
        let (top, start) = (moved(&top, s), p2(0.0, 10.0) + s);
        let back = sweep_arc(&top, &bar, c, start, -FRAC_PI_2).unwrap();
        close(back.t_start, 1.0 - ep[0].t_end, 1e-9, "reversed t_start");
    }
}

#[test]
fn full_circle_that_crosses_b_and_returns_is_found() {
    // A 1 mm box centred on its reference point (10, 0) goes once round the origin; b sits on
    // the far side. It enters through b's top face when its centre is at y = 1.5 (θ = π − asin
    // 0.15) and leaves through the bottom face symmetrically; start and end are clear.
    let a = rect(9.5, -0.5, 10.5, 0.5);
    let b = rect(-12.0, -1.0, -8.0, 1.0);
    let enter = (PI - (0.15 - TOUCH_EPS / 10.0).asin()) / TAU;
    let leave = (PI + (0.15 - TOUCH_EPS / 10.0).asin()) / TAU;
    let ep = sweep_arc_episodes(&a, &b, p2(0.0, 0.0), p2(10.0, 0.0), TAU);
    assert_eq!(ep.len(), 1, "{ep:?}");
    close(ep[0].t_start, enter, 1e-12, "t_start");
    close(ep[0].t_end, leave, 1e-12, "t_end");
    close(ep[0].max_depth, 1.0, 1e-6, "max_depth"); // centred in b: 1 from its top and bottom
    let cw = sweep_arc_episodes(&a, &b, p2(0.0, 0.0), p2(10.0, 0.0), -TAU);
    assert_eq!(cw.len(), 1, "{cw:?}");
    close(cw[0].t_start, 1.0 - leave, 1e-12, "clockwise t_start");
    // Two turns: the same episode twice, at half the t.
    let two = sweep_arc_episodes(&a, &b, p2(0.0, 0.0), p2(10.0, 0.0), 2.0 * TAU);
    assert_eq!(two.len(), 2, "{two:?}");
    close(two[0].t_start, enter / 2.0, 1e-12, "two turns, first");
    close(two[1].t_start, 0.5 + enter / 2.0, 1e-12, "two turns, second");
}

#[test]
fn degenerate_and_hostile_inputs_do_not_hang_or_panic() {
    let a = rect(0.0, 0.0, 1.0, 1.0);
    let b = rect(0.5, 0.5, 2.0, 2.0);
    assert_eq!(sweep_line(&a, &b, V2::new(f64::NAN, 0.0)), None);
    assert_eq!(sweep_line(&a, &b, V2::new(f64::INFINITY, 0.0)), None);
    assert_eq!(sweep_arc(&a, &b, p2(0.0, 0.0), p2(f64::NAN, 0.0), 1.0), None);
    assert_eq!(sweep_arc(&a, &b, p2(0.0, 0.0), p2(1.0, 0.0), f64::INFINITY), None);
    // Zero radius or zero angle: standing still, overlapping.
    assert_eq!(
        sweep_arc(&a, &b, p2(3.0, 3.0), p2(3.0, 3.0), 1.0).map(|c| c.t_start),
        Some(0.0)
    );
    assert_eq!(
        sweep_arc(&a, &b, p2(3.0, 3.0), p2(4.0, 3.0), 0.0).map(|c| c.t_start),
        Some(0.0)
    );
    // Absurd turns and sizes finish.
    let far = rect(-30.0, -0.5, -15.0, 0.5);
    let c = sweep_arc(&a, &far, p2(-10.0, 0.0), p2(0.0, 0.0), 1e9).unwrap();
    assert!(c.t_start > 0.0 && c.t_start < 1e-8, "{c:?}");
    let _ = sweep_line(&a, &b, V2::new(1e300, -1e300));
    let _ = sweep_arc(&a, &b, p2(1e300, 0.0), p2(0.0, 0.0), 1.0);
}

// ---------------------------------------------------------------------------------------------
// Agreement with dense static sampling.

#[derive(Clone, Debug)]
enum Path {
    Line(V2),
    Arc { center: P2, sweep: f64 },
}

/// Displacement of the moving part at `t`, written independently of the kernel.
fn offset(path: &Path, start: P2, t: f64) -> V2 {
    match *path {
        Path::Line(d) => d * t,
        Path::Arc { center, sweep } => {
            let r = (start - center).norm();
            let th0 = (start.y - center.y).atan2(start.x - center.x);
            let th = th0 + sweep * t;
            V2::new(r * (th.cos() - th0.cos()), r * (th.sin() - th0.sin()))
        }
    }
}

fn scene() -> impl Strategy<Value = (Polygon, Polygon, Path)> {
    let line = (
        (-30.0f64..30.0, -30.0f64..30.0),
        0.0f64..1.0,
        (-4.0f64..4.0, -4.0f64..4.0),
    )
        .prop_flat_map(|(d, s, j)| {
            let d = V2::new(d.0, d.1);
            let c = (d.x * s + j.0, d.y * s + j.1);
            (star((0.0, 0.0), 0.5, 3.0), star(c, 1.0, 5.0), Just(Path::Line(d)))
        });
    let arc = (
        (-15.0f64..15.0, -15.0f64..15.0),
        prop_oneof![Just(TAU), Just(-TAU), -TAU..TAU],
        0.0f64..TAU,
        (-3.0f64..3.0, -3.0f64..3.0),
    )
        .prop_flat_map(|(c, sweep, at, j)| {
            let center = p2(c.0, c.1);
            let r = center.coords.norm();
            let c = (center.x + r * at.cos() + j.0, center.y + r * at.sin() + j.1);
            (
                star((0.0, 0.0), 0.5, 3.0),
                star(c, 1.0, 5.0),
                Just(Path::Arc { center, sweep }),
            )
        });
    prop_oneof![line, arc]
}

fn run(a: &Polygon, b: &Polygon, path: &Path) -> Vec<Contact> {
    match *path {
        Path::Line(d) => sweep_line_episodes(a, b, d),
        Path::Arc { center, sweep } => sweep_arc_episodes(a, b, center, P2::origin(), sweep),
    }
}

proptest! {
    #![proptest_config(super::util::cases(48))]

    /// The sweep never misses what sampling the move at 10,000 points sees, and its first
    /// contact is never later. Samples deeper than 2·TOUCH_EPS are judged (a sample just over
    /// TOUCH_EPS may sit on a bump that the sweep's own bisection rounds the other way).
    #[test]
    fn sweep_agrees_with_dense_static_sampling((a, b, path) in scene()) {
        let ep = run(&a, &b, &path);
        for e in &ep {
            prop_assert!(e.t_start <= e.t_end && e.t_start >= 0.0 && e.t_end <= 1.0, "{:?}", e);
            prop_assert!(e.max_depth > TOUCH_EPS, "{:?}", e);
            let mid = a.translated(offset(&path, P2::origin(), 0.5 * (e.t_start + e.t_end)));
            prop_assert!(interiors_overlap(&mid, &b), "episode {:?} not overlapping in its middle", e);
        }
        const N: usize = 10_000;
        let mut checked = 0;
        let mut first = true;
        for k in 0..N {
            let t = k as f64 / (N - 1) as f64;
            let m = a.translated(offset(&path, P2::origin(), t));
            if !interiors_overlap(&m, &b) {
                continue;
            }
            // The first overlapping samples, then every 25th (depth is the costly part).
            checked += 1;
            if !first && checked % 25 != 0 {
                continue;
            }
            let depth = penetration_depth(&m, &b);
            if depth <= 2.0 * TOUCH_EPS {
                continue;
            }
            if first {
                prop_assert!(!ep.is_empty(), "sampling overlaps at t = {} (depth {}) but the sweep found nothing", t, depth);
                prop_assert!(ep[0].t_start <= t + 1e-9, "sampling overlaps at t = {} but the sweep starts at {:?}", t, ep[0]);
                first = false;
            }
            prop_assert!(
                ep.iter().any(|e| e.t_start - 1e-9 <= t && t <= e.t_end + 1e-9),
                "sampled overlap at t = {} (depth {}) outside every episode {:?}", t, depth, ep
            );
        }
    }
}
