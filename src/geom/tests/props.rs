//! Property tests of the static queries, and a differential test against the `geo` crate.
//!
//! Polygons are random star-shaped outlines (sorted angles, random radii) with coordinates on a
//! 1/64 mm grid, so that exact contacts — shared vertices, collinear edges — happen by chance and
//! moving by ±1e7 mm is exact. A second strategy builds touching pairs on purpose (a polygon and
//! its mirror image across the vertical line through its rightmost point).

use super::util::rewritings;
use crate::geom::{distance, interiors_overlap, overlap, penetration_depth, Polygon, P2, TOUCH_EPS, V2};
use geo::{Area, BooleanOps, Distance, Euclidean, Intersects, Relate};
use proptest::prelude::*;

/// A random star-shaped polygon around `center`, coordinates on a 1/64 mm grid.
pub fn star(center: (f64, f64), rmin: f64, rmax: f64) -> impl Strategy<Value = Polygon> {
    star_on(center, rmin, rmax, 64.0)
}

/// A random star-shaped polygon around `center`, coordinates on a `1/grid` mm grid.
pub fn star_on(center: (f64, f64), rmin: f64, rmax: f64, grid: f64) -> impl Strategy<Value = Polygon> {
    let snap = move |v: f64| (v * grid).round() / grid;
    (3usize..12)
        .prop_flat_map(move |k| {
            (
                proptest::collection::vec((0.2f64..1.0, rmin..rmax), k),
                0.0..std::f64::consts::TAU,
            )
        })
        .prop_filter_map("not a simple polygon", move |(parts, phase)| {
            let total: f64 = parts.iter().map(|p| p.0).sum();
            let mut ang = phase;
            let mut v = Vec::new();
            for (gap, r) in parts {
                v.push(P2::new(snap(center.0 + r * ang.cos()), snap(center.1 + r * ang.sin())));
                ang += gap / total * std::f64::consts::TAU;
            }
            Polygon::new(&v).ok()
        })
}

/// Two random polygons near each other: fine coordinates (contacts are rare), or whole mm
/// (shared vertices, vertices on edges and collinear edges are common).
fn pair() -> impl Strategy<Value = (Polygon, Polygon)> {
    let fine = ((-6.0f64..6.0, -6.0f64..6.0), 0.5f64..3.0, 3.0f64..8.0)
        .prop_flat_map(|(c, rmin, rmax)| (star((0.0, 0.0), 1.0, 6.0), star(c, rmin, rmax)));
    let coarse = ((-5i32..=5, -5i32..=5), 1.0f64..3.0, 3.0f64..5.0).prop_flat_map(|(c, rmin, rmax)| {
        let c = (c.0 as f64, c.1 as f64);
        (star_on((0.0, 0.0), 2.0, 5.0, 1.0), star_on(c, rmin, rmax, 1.0))
    });
    prop_oneof![fine, coarse]
}

/// A polygon and its mirror image across the vertical line through its rightmost vertex: they
/// touch (at that vertex, or along a vertical edge) and never overlap.
fn touching_pair() -> impl Strategy<Value = (Polygon, Polygon)> {
    star((0.0, 0.0), 1.0, 6.0).prop_map(|a| {
        let xm = a.aabb().max.x;
        let b: Vec<P2> = a.points().iter().map(|p| P2::new(2.0 * xm - p.x, p.y)).collect();
        (a.clone(), Polygon::new(&b).unwrap())
    })
}

fn to_geo(p: &Polygon) -> geo::Polygon<f64> {
    let mut c: Vec<geo::Coord<f64>> = p.points().iter().map(|q| geo::coord! { x: q.x, y: q.y }).collect();
    c.push(c[0]);
    geo::Polygon::new(geo::LineString::new(c), vec![])
}

fn moved(p: &Polygon, s: V2) -> Polygon {
    Polygon::new(&p.points().iter().map(|q| q + s).collect::<Vec<_>>()).unwrap()
}

proptest! {
    #![proptest_config(super::util::cases(256))]

    #[test]
    fn overlap_and_distance_are_symmetric((a, b) in pair()) {
        prop_assert_eq!(overlap(&a, &b), overlap(&b, &a));
        prop_assert_eq!(penetration_depth(&a, &b), penetration_depth(&b, &a));
        prop_assert_eq!(distance(&a, &b), distance(&b, &a));
    }

    #[test]
    fn answers_do_not_depend_on_how_the_outline_is_written((a, b) in pair()) {
        let (ov, dist, depth) = (overlap(&a, &b), distance(&a, &b), penetration_depth(&a, &b));
        for (label, ra) in rewritings(a.points()) {
            let ra = Polygon::new(&ra).unwrap();
            prop_assert_eq!(overlap(&ra, &b).is_some(), ov.is_some(), "{}", label);
            prop_assert!((penetration_depth(&ra, &b) - depth).abs() <= 1e-9, "{}", label);
            prop_assert_eq!(distance(&ra, &b), dist, "{}", label);
        }
    }

    #[test]
    fn answers_do_not_depend_on_position((a, b) in pair(), sx in -1i32..=1, sy in -1i32..=1, frac in 0.0f64..1.0) {
        let (ov, dist, depth) = (overlap(&a, &b), distance(&a, &b), penetration_depth(&a, &b));
        // An exact move (whole 1e7 mm steps on the 1/64 grid): everything is identical but for
        // rounding in the depth search.
        let s = V2::new(1e7 * sx as f64, 1e7 * sy as f64 + 1e7);
        let (ma, mb) = (moved(&a, s), moved(&b, s));
        prop_assert_eq!(overlap(&ma, &mb).is_some(), ov.is_some());
        prop_assert_eq!(interiors_overlap(&ma, &mb), interiors_overlap(&a, &b));
        prop_assert!((penetration_depth(&ma, &mb) - depth).abs() <= 1e-9);
        prop_assert!((distance(&ma, &mb) - dist).abs() <= 1e-9);
        // An inexact move: coordinates round by up to 1 nm, so a contact may become a 1 nm gap
        // or overlap. Booleans must agree unless the depth is within 0.1 µm of TOUCH_EPS.
        let s = s + V2::new(frac, 1.0 - frac);
        let (ma, mb) = (moved(&a, s), moved(&b, s));
        let d2 = penetration_depth(&ma, &mb);
        prop_assert!((d2 - depth).abs() <= 1e-6, "depth {} vs {}", d2, depth);
        prop_assert!((distance(&ma, &mb) - dist).abs() <= 1e-6);
        if (depth - TOUCH_EPS).abs() > 1e-7 {
            prop_assert_eq!(overlap(&ma, &mb).is_some(), ov.is_some());
        }
    }

    #[test]
    fn distance_is_zero_exactly_when_the_parts_meet((a, b) in pair()) {
        let d = distance(&a, &b);
        prop_assert!(d >= 0.0);
        // geo's Intersects is exact on these inputs (robust predicates on the input vertices).
        prop_assert_eq!(d == 0.0, to_geo(&a).intersects(&to_geo(&b)));
        if interiors_overlap(&a, &b) {
            prop_assert_eq!(d, 0.0);
            prop_assert!(penetration_depth(&a, &b) > 0.0);
        } else {
            prop_assert_eq!(penetration_depth(&a, &b), 0.0);
            prop_assert_eq!(overlap(&a, &b), None);
        }
        if d > 0.0 {
            let g = Euclidean.distance(&to_geo(&a), &to_geo(&b));
            prop_assert!((g - d).abs() <= 1e-9, "distance {} vs geo {}", d, g);
        }
    }

    #[test]
    fn touching_is_not_overlap((a, b) in touching_pair(), sx in -1i32..=1) {
        let s = V2::new(1e7 * sx as f64, 0.0);
        let (a, b) = (moved(&a, s), moved(&b, s));
        prop_assert!(!interiors_overlap(&a, &b));
        prop_assert_eq!(overlap(&a, &b), None);
        prop_assert_eq!(distance(&a, &b), 0.0);
        // Pushed into each other by 2 µm they overlap, no deeper than the push (corner into
        // corner can be shallower).
        let pushed = moved(&b, V2::new(-2e-6, 0.0));
        let d = penetration_depth(&a, &pushed);
        prop_assert!(d > 0.0 && d <= 2e-6 + 1e-9, "depth {}", d);
        // Drawn 2 µm apart they are 2 µm apart.
        let apart = moved(&b, V2::new(2e-6, 0.0));
        prop_assert!((distance(&a, &apart) - 2e-6).abs() <= 1e-9);
    }

    /// Differential test against `geo`. `Relate`'s interior/interior entry is computed from
    /// robust predicates and must agree exactly with `interiors_overlap`. The area of geo's
    /// boolean intersection is computed in floating point, so it is compared with margins:
    /// an intersection area above 1e-9 mm² implies overlapping interiors, and a depth above
    /// 1e-3 mm implies an area above 1e-9 mm² (every random polygon is at least ~1/64 mm wide
    /// where it overlaps). Cases between these margins are not judged.
    #[test]
    fn agrees_with_geo((a, b) in pair()) {
        let (ga, gb) = (to_geo(&a), to_geo(&b));
        let m = ga.relate(&gb);
        let ii = m.get(geo::coordinate_position::CoordPos::Inside, geo::coordinate_position::CoordPos::Inside) != geo::dimensions::Dimensions::Empty;
        prop_assert_eq!(interiors_overlap(&a, &b), ii, "relate {:?}", m);
        let area = ga.intersection(&gb).unsigned_area();
        let depth = penetration_depth(&a, &b);
        if area > 1e-9 {
            prop_assert!(depth > 0.0, "area {} but no depth", area);
        }
        if depth > 1e-3 {
            prop_assert!(area > 1e-9, "depth {} but area {}", depth, area);
        }
        if depth == 0.0 {
            prop_assert!(area < 1e-9, "no depth but area {}", area);
        }
    }
}
