//! Data-driven static cases: each runs as written, swapped, rewritten (winding, start vertex,
//! duplicates, collinear points) and moved by ±1e7 mm, and must give the same answer every time.

use super::util::{pts, rewritings, shifted};
use crate::geom::{distance, interiors_overlap, overlap, penetration_depth, Polygon, P2, V2};

#[derive(Clone, Copy, Debug)]
enum Want {
    /// Interiors apart or touching: `overlap` is None and the distance is this.
    Clear(f64),
    /// Overlap with this depth (distance 0).
    Overlap(f64),
}

struct Case {
    name: &'static str,
    a: &'static [(f64, f64)],
    b: &'static [(f64, f64)],
    want: Want,
}

const JAW: &[(f64, f64)] = &[(-5.0, -3.0), (5.0, -3.0), (5.0, 0.0), (-5.0, 0.0)];
/// A stepped jaw: its notch (x 5..10, z 5..10) is inside its box and its convex hull.
const STEP: &[(f64, f64)] = &[
    (0.0, 0.0),
    (10.0, 0.0),
    (10.0, 5.0),
    (5.0, 5.0),
    (5.0, 10.0),
    (0.0, 10.0),
];
const S2: f64 = std::f64::consts::SQRT_2;

const CASES: &[Case] = &[
    Case {
        name: "edge exactly on a face",
        a: &[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)],
        b: JAW,
        want: Want::Clear(0.0),
    },
    Case {
        name: "edge on a face, overhanging its end",
        a: &[(4.0, 0.0), (7.0, 0.0), (7.0, 1.0), (4.0, 1.0)],
        b: JAW,
        want: Want::Clear(0.0),
    },
    Case {
        name: "edge 1 um into a face",
        a: &[(0.0, -0.001), (2.0, -0.001), (2.0, 1.0), (0.0, 1.0)],
        b: JAW,
        want: Want::Overlap(0.001),
    },
    Case {
        name: "insert corner touching a face",
        a: &[(0.0, 0.0), (1.2, 1.0), (0.0, 2.0), (-1.2, 1.0)],
        b: JAW,
        want: Want::Clear(0.0),
    },
    Case {
        name: "insert corner 1 um into a face",
        a: &[(0.0, -0.001), (1.2, 0.999), (0.0, 1.999), (-1.2, 0.999)],
        b: JAW,
        want: Want::Overlap(0.001),
    },
    Case {
        name: "insert corner 1 um short of a face",
        a: &[(0.0, 0.001), (1.2, 1.001), (0.0, 2.001), (-1.2, 1.001)],
        b: JAW,
        want: Want::Clear(0.001),
    },
    Case {
        name: "insert corner 1 um into a jaw corner",
        a: &[(4.999, -0.001), (6.0, 0.5), (7.0, 2.0), (5.5, 1.0)],
        b: JAW,
        want: Want::Overlap(0.001),
    },
    Case {
        name: "insert in the notch of a stepped jaw, clear",
        a: &[(6.0, 6.0), (9.0, 6.0), (9.0, 9.0), (6.0, 9.0)],
        b: STEP,
        want: Want::Clear(1.0),
    },
    Case {
        name: "insert seated in the notch of a stepped jaw",
        a: &[(5.0, 5.0), (9.0, 5.0), (9.0, 9.0), (5.0, 9.0)],
        b: STEP,
        want: Want::Clear(0.0),
    },
    Case {
        name: "insert corner in the notch, 1 um into its wall",
        a: &[(4.999, 7.0), (8.0, 6.0), (9.0, 9.0)],
        b: STEP,
        want: Want::Overlap(0.001),
    },
    Case {
        name: "insert diamond touching the reflex corner of the notch",
        a: &[(5.0, 5.0), (8.0, 6.0), (9.0, 9.0), (6.0, 8.0)],
        b: STEP,
        want: Want::Clear(0.0),
    },
    Case {
        name: "boxes sharing an edge",
        a: &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
        b: &[(1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0)],
        want: Want::Clear(0.0),
    },
    Case {
        name: "boxes sharing a corner",
        a: &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
        b: &[(1.0, 1.0), (2.0, 1.0), (2.0, 2.0), (1.0, 2.0)],
        want: Want::Clear(0.0),
    },
    Case {
        name: "vertex on the middle of a slanted edge",
        a: &[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)],
        b: &[(2.0, 2.0), (5.0, 3.0), (3.0, 5.0)],
        want: Want::Clear(0.0),
    },
    Case {
        name: "vertex 1 um into a slanted edge",
        a: &[(0.0, 0.0), (4.0, 0.0), (0.0, 4.0)],
        b: &[(1.999, 2.0), (5.0, 3.0), (3.0, 5.0)],
        want: Want::Overlap(0.001 / S2),
    },
    Case {
        name: "boxes apart",
        a: &[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
        b: &[(3.0, 0.5), (4.0, 0.5), (4.0, 1.5), (3.0, 1.5)],
        want: Want::Clear(2.0),
    },
    Case {
        name: "crossing bars, no vertex inside the other",
        a: &[(-10.0, -1.0), (10.0, -1.0), (10.0, 1.0), (-10.0, 1.0)],
        b: &[(-2.0, -10.0), (2.0, -10.0), (2.0, 10.0), (-2.0, 10.0)],
        want: Want::Overlap(2.0),
    },
    Case {
        name: "part inside another",
        a: &[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)],
        b: &[(4.0, 4.0), (6.0, 4.0), (6.0, 6.0), (4.0, 6.0)],
        want: Want::Overlap(4.0),
    },
    Case {
        name: "triangle with every vertex on the square's outline",
        a: &[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)],
        b: &[(0.0, 0.0), (2.0, 0.0), (0.0, 2.0)],
        want: Want::Overlap(1.0),
    },
    Case {
        name: "identical outlines",
        a: &[(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)],
        b: &[(0.0, 2.0), (0.0, 0.0), (2.0, 0.0), (2.0, 2.0)],
        want: Want::Overlap(1.0),
    },
];

fn check(case: &Case, label: &str, a: &[P2], b: &[P2], tol: f64) {
    let (pa, pb) = (Polygon::new(a).unwrap(), Polygon::new(b).unwrap());
    let ctx = format!("{} [{}]", case.name, label);
    let ov = overlap(&pa, &pb);
    let d = distance(&pa, &pb);
    match case.want {
        Want::Clear(want) => {
            assert_eq!(ov, None, "{ctx}: overlap");
            if want == 0.0 {
                assert_eq!(d, 0.0, "{ctx}: distance");
                assert_eq!(penetration_depth(&pa, &pb), 0.0, "{ctx}: touching has no depth");
                assert!(!interiors_overlap(&pa, &pb), "{ctx}: interiors");
            } else {
                assert!((d - want).abs() <= tol, "{ctx}: distance {d}, want {want}");
            }
        }
        Want::Overlap(want) => {
            let depth = ov.unwrap_or_else(|| panic!("{ctx}: no overlap"));
            assert!((depth - want).abs() <= tol, "{ctx}: depth {depth}, want {want}");
            assert_eq!(d, 0.0, "{ctx}: distance");
        }
    }
}

#[test]
fn static_cases_hold_for_every_rewriting_order_and_position() {
    for case in CASES {
        let (a, b) = (pts(case.a), pts(case.b));
        for (la, ra) in rewritings(&a) {
            for (lb, rb) in rewritings(&b) {
                let label = format!("a {la}, b {lb}");
                check(case, &label, &ra, &rb, 1e-9);
                check(case, &format!("{label}, swapped"), &rb, &ra, 1e-9);
            }
        }
        // 1e7 is exactly representable and these coordinates need few bits, so most shifts are
        // exact; 4.999 and the like round to within 0.93 nm of their true place.
        for s in [
            V2::new(1e7, 1e7),
            V2::new(-1e7, 1e7),
            V2::new(1e7, -2e7),
            V2::new(1e7 + 0.5, 1e7 - 0.25),
        ] {
            let (sa, sb) = (shifted(&a, s), shifted(&b, s));
            check(case, &format!("shifted by {s:?}"), &sa, &sb, 2e-9);
            check(case, &format!("shifted by {s:?}, swapped"), &sb, &sa, 2e-9);
            for (la, ra) in rewritings(&sa) {
                check(case, &format!("shifted by {s:?}, a {la}"), &ra, &sb, 2e-9);
            }
        }
    }
}

#[test]
fn depth_of_a_corner_pushed_into_a_face_is_the_push() {
    // A 80° insert corner pushed 1 µm, 10 µm, 0.1 mm and 1 mm into a jaw face.
    let half = 40f64.to_radians();
    for push in [0.5e-6, 1e-6, 2e-6, 1e-3, 0.01, 0.1, 1.0] {
        let tip = (0.3, -push);
        let a = [
            tip,
            (tip.0 + 5.0 * half.sin(), tip.1 + 5.0 * half.cos()),
            (tip.0 - 5.0 * half.sin(), tip.1 + 5.0 * half.cos()),
        ];
        let pa = Polygon::new(&pts(&a)).unwrap();
        let pb = Polygon::new(&pts(JAW)).unwrap();
        let d = penetration_depth(&pa, &pb);
        assert!((d - push).abs() <= 1e-12, "push {push}: depth {d}");
        if push != 1e-6 {
            // Exactly at TOUCH_EPS either answer is right.
            assert_eq!(overlap(&pa, &pb).is_some(), push > 1e-6, "push {push}");
        }
    }
}

#[test]
fn stepped_jaw_bounding_shapes_would_be_wrong() {
    // Guards against a narrow phase that trusts the box or the convex hull of a part.
    let step = Polygon::new(&pts(STEP)).unwrap();
    let insert = Polygon::new(&pts(&[(6.0, 6.0), (9.0, 6.0), (9.0, 9.0), (6.0, 9.0)])).unwrap();
    assert!(step.aabb().meets(insert.aabb(), 0.0));
    assert_eq!(overlap(&step, &insert), None);
    assert_eq!(distance(&step, &insert), 1.0);
}

#[test]
fn rounding_slivers_along_a_shared_edge_have_no_depth() {
    // b's edge lies on a's slanted edge; moved by an amount that is not on the grid, the
    // coordinates round so that the two edges cross at a 1e-16 angle. The overlap is a sliver
    // 1e-16 thick, and a piece of a's edge inside b must not be measured from b's far vertex
    // (a depth of 2.83 was once reported here).
    let a = pts(&[(1.0, -3.0), (1.0, 2.0), (-4.0, 2.0)]);
    let b = pts(&[(-2.0, 0.0), (-5.0, -4.0), (-2.0, -6.0), (0.0, -2.0)]);
    for frac in [0.0, 0.2302125512662313, 0.1, 0.7, 1.0 / 3.0] {
        let s = V2::new(frac, 1.0 - frac) + V2::new(0.0, 1e7 * (frac * 3.0).floor());
        let (pa, pb) = (
            Polygon::new(&shifted(&a, s)).unwrap(),
            Polygon::new(&shifted(&b, s)).unwrap(),
        );
        let d = penetration_depth(&pa, &pb);
        assert!(d < 1e-9, "frac {frac}: depth {d}");
        assert_eq!(overlap(&pa, &pb), None);
        assert!(distance(&pa, &pb) < 1e-9);
    }
}
