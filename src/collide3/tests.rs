use super::*;
use crate::kin::{Axis, AxisKind, CompId, Component, Kinematics, Mesh, Poser, Role};
use crate::scene::stock::{DexelStock, View};
use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};
use proptest::prelude::*;
use std::sync::Arc;

fn at(x: f64, y: f64, z: f64) -> Iso {
    Iso::from_parts(Translation3::new(x, y, z), UnitQuaternion::identity())
}

fn rot(x: f64, y: f64, z: f64, ax: f64, ay: f64, az: f64) -> Iso {
    Iso::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(ax, ay, az),
    )
}

fn sphere_mesh(r: f64, rings: usize) -> Geometry {
    let (v, t) = uv_sphere(r, rings, 2 * rings);
    Geometry::Mesh(Arc::new(Mesh {
        vertices: v.iter().map(|p| Point3::new(p.x, p.y, p.z)).collect(),
        triangles: t,
    }))
}

fn boxg(hx: f64, hy: f64, hz: f64) -> Geometry {
    Geometry::Cuboid {
        min: Point3::new(-hx, -hy, -hz),
        max: Point3::new(hx, hy, hz),
    }
}

/// A box as a triangle mesh (not the primitive).
fn box_mesh(hx: f64, hy: f64, hz: f64) -> Shape3 {
    let (v, t) = parry3d_f64::shape::Cuboid::new(Vector::new(hx, hy, hz)).to_trimesh();
    Shape3::mesh(v, t).unwrap()
}

fn shape(g: &Geometry) -> Shape3 {
    Shape3::from_geometry(g, 0.01).unwrap()
}

#[test]
fn mesh_boxes_overlap_and_separate() {
    let a = box_mesh(1.0, 1.0, 1.0);
    let b = box_mesh(1.0, 1.0, 1.0);
    let h = overlap(&a, &at(0.0, 0.0, 0.0), &b, &at(1.5, 0.2, 0.1), 1e-6).expect("overlap");
    // The deepest crossing triangle pair: a lower bound of the solids' penetration (0.5).
    assert!(h.depth > 0.1 && h.depth <= 0.5 + 1e-9, "{h:?}");
    assert!(overlap(&a, &at(0.0, 0.0, 0.0), &b, &at(2.5, 0.0, 0.0), 1e-6).is_none());
    assert!((distance(&a, &at(0.0, 0.0, 0.0), &b, &at(2.5, 0.0, 0.0)) - 0.5).abs() < 1e-9);
}

#[test]
fn touching_is_not_colliding() {
    for (a, b) in [
        (box_mesh(1.0, 1.0, 1.0), box_mesh(1.0, 1.0, 1.0)),
        (shape(&boxg(1.0, 1.0, 1.0)), shape(&boxg(1.0, 1.0, 1.0))),
        (box_mesh(1.0, 1.0, 1.0), shape(&boxg(1.0, 1.0, 1.0))),
    ] {
        assert!(overlap(&a, &at(0.0, 0.0, 0.0), &b, &at(2.0, 0.3, 0.0), 1e-6).is_none());
        assert!(overlap(&a, &at(0.0, 0.0, 0.0), &b, &at(1.99, 0.3, 0.0), 1e-6).is_some());
    }
}

#[test]
fn containment_detected() {
    let big = shape(&sphere_mesh(10.0, 16));
    let small = box_mesh(1.0, 1.0, 1.0);
    let h = overlap(&big, &at(0.0, 0.0, 0.0), &small, &at(1.0, 0.5, 0.0), 1e-6).expect("small inside big");
    assert!(h.depth > 5.0, "{h:?}");
    assert!(overlap(&small, &at(1.0, 0.5, 0.0), &big, &at(0.0, 0.0, 0.0), 1e-6).is_some());
    assert_eq!(distance(&big, &at(0.0, 0.0, 0.0), &small, &at(1.0, 0.5, 0.0)), 0.0);
    // A primitive inside a mesh, and a mesh inside a primitive.
    let cyl = shape(&Geometry::Cylinder {
        radius: 20.0,
        z0: -30.0,
        z1: 30.0,
    });
    assert!(overlap(&cyl, &at(0.0, 0.0, 0.0), &small, &at(0.0, 5.0, 10.0), 1e-6).is_some());
    assert!(overlap(
        &big,
        &at(0.0, 0.0, 0.0),
        &shape(&boxg(1.0, 1.0, 1.0)),
        &at(0.0, 0.0, 2.0),
        1e-6
    )
    .is_some());
    // Outside the cylinder: apart.
    assert!(overlap(&cyl, &at(0.0, 0.0, 0.0), &small, &at(0.0, 25.0, 10.0), 1e-6).is_none());
}

#[test]
fn cylinder_axis_is_z() {
    let cyl = shape(&Geometry::Cylinder {
        radius: 2.0,
        z0: 0.0,
        z1: 50.0,
    });
    let probe = box_mesh(0.1, 0.1, 0.1);
    // Along z inside the cylinder's length: overlap; beyond its radius in y: none.
    assert!(overlap(&cyl, &at(0.0, 0.0, 0.0), &probe, &at(0.0, 0.0, 40.0), 1e-6).is_some());
    assert!(overlap(&cyl, &at(0.0, 0.0, 0.0), &probe, &at(0.0, 3.0, 1.0), 1e-6).is_none());
    assert!(overlap(&cyl, &at(0.0, 0.0, 0.0), &probe, &at(0.0, 0.0, 51.0), 1e-6).is_none());
}

/// A ring outline (a bore) and a stepped, coned outline with a z tip.
fn outlines() -> Vec<Vec<P2>> {
    vec![
        vec![
            P2::new(5.0, 0.0),
            P2::new(20.0, 0.0),
            P2::new(20.0, 30.0),
            P2::new(5.0, 30.0),
        ],
        vec![
            P2::new(0.0, 0.0),
            P2::new(30.0, 0.0),
            P2::new(30.0, 10.0),
            P2::new(15.0, 25.0),
            P2::new(8.0, 40.0),
            P2::new(4.0, 12.0),
            P2::new(0.0, 12.0),
        ],
        vec![P2::new(5.0, 0.0), P2::new(10.0, 10.0), P2::new(0.0, 10.0)],
    ]
}

/// Whether (r, z) is inside a polygon (even-odd).
fn inside2(p: &[P2], r: f64, z: f64) -> bool {
    let mut c = false;
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        if (a.y > z) != (b.y > z) && r < a.x + (z - a.y) / (b.y - a.y) * (b.x - a.x) {
            c = !c;
        }
    }
    c
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn revolved_circumscription_never_smaller_than_solid(
        which in 0usize..3, r in 0.0f64..1.0, z in 0.0f64..1.0, th in 0.0f64..std::f64::consts::TAU, tol in 0.001f64..2.0
    ) {
        let o = &outlines()[which];
        let rmax = o.iter().map(|p| p.x).fold(0.0, f64::max);
        let zmax = o.iter().map(|p| p.y).fold(0.0, f64::max);
        let (rr, zz) = (r * rmax, z * zmax);
        prop_assume!(inside2(o, rr, zz));
        let s = Shape3::from_geometry(&Geometry::Revolved(o.clone()), tol).unwrap();
        let p = Vector::new(rr * th.cos(), rr * th.sin(), zz);
        prop_assert!(s.contains(&Pose::IDENTITY, p), "({rr}, {zz}) at {th} not in the mesh");
    }

    #[test]
    fn overlap_symmetric_and_distance_zero_iff_overlap(
        x in -4.0f64..4.0, y in -4.0f64..4.0, z in -4.0f64..4.0,
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, kind in 0usize..4
    ) {
        let a = shape(&sphere_mesh(1.5, 8));
        let b = match kind {
            0 => box_mesh(1.0, 0.5, 2.0),
            1 => shape(&boxg(1.0, 0.5, 2.0)),
            2 => shape(&Geometry::Cylinder { radius: 0.8, z0: -1.0, z1: 1.5 }),
            _ => shape(&Geometry::Revolved(outlines()[0].iter().map(|p| P2::new(p.x / 10.0, p.y / 10.0)).collect())),
        };
        let (pa, pb) = (at(0.0, 0.0, 0.0), rot(x, y, z, ax, ay, 0.0));
        let ab = overlap(&a, &pa, &b, &pb, 1e-9);
        let ba = overlap(&b, &pb, &a, &pa, 1e-9);
        prop_assert_eq!(ab.is_some(), ba.is_some());
        if let (Some(h1), Some(h2)) = (ab, ba) {
            prop_assert!((h1.depth - h2.depth).abs() < 1e-6 * (1.0 + h1.depth), "{:?} {:?}", h1, h2);
        }
        let d = distance(&a, &pa, &b, &pb);
        prop_assert!(d >= 0.0);
        if ab.is_some() {
            prop_assert_eq!(d, 0.0);
        } else if d == 0.0 {
            // Not overlapping deeper than the tolerance, yet at distance 0: touching.
            prop_assert!(overlap(&a, &pa, &b, &pb, -1.0).is_some());
        }
        if d > 1e-6 {
            prop_assert!(ab.is_none());
        }
    }
}

// ---- the pair walks (`pairs`) against parry's own queries ----

/// The mesh shapes of the pair walks' oracle tests: a sphere, a box, two revolved outlines
/// (a ring and a stepped cone: fans of long slivers on their faces), scaled.
fn pair_mesh(kind: usize, scale: f64) -> Shape3 {
    let g = match kind {
        0 => sphere_mesh(1.5 * scale, 8),
        1 => return box_mesh(scale, 0.5 * scale, 2.0 * scale),
        k => Geometry::Revolved(
            outlines()[k - 2]
                .iter()
                .map(|p| P2::new(p.x * scale / 10.0, p.y * scale / 10.0))
                .collect(),
        ),
    };
    Shape3::meshed(&g, 0.01 * scale).unwrap()
}

fn trimesh(s: &Shape3) -> (&TriMesh, &pairs::Tree) {
    let Shape3::Mesh(m) = s else { panic!("not a mesh") };
    (&m.mesh, m.tree.get(&m.mesh))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    /// The walk of both trees gives parry's distance of two meshes (exact with no slack), and
    /// with the slack a lower bound no more than the slack short of it.
    #[test]
    fn the_pair_walks_distance_is_parrys(
        ka in 0usize..4, kb in 0usize..4, scale in 0.5f64..20.0, far in 0.0f64..40.0,
        x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0,
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, az in -3.0f64..3.0
    ) {
        let (a, b) = (pair_mesh(ka, scale), pair_mesh(kb, 1.0));
        let (pa, pb) = (rot(1.0, -2.0, 0.5, 0.3, 0.0, 1.1), rot(x * far, y * far, z * far, ax, ay, az));
        let (qa, qb) = (to_pose(&pa), to_pose(&pb));
        let (ma, mb) = (trimesh(&a), trimesh(&b));
        let parry = query::distance(&qa, ma.0, &qb, mb.0).unwrap().distance;
        let exact = pairs::mesh_distance(ma, mb, &qa.inv_mul(&qb), f64::INFINITY, pairs::SLACK);
        prop_assert!((exact - parry).abs() <= 1e-9 * (1.0 + parry), "walk {exact}, parry {parry}");
        for slack in [pairs::SLACK, pairs::ADVANCE_SLACK] {
            let bound = pairs::mesh_distance(ma, mb, &qa.inv_mul(&qb), 0.0, slack);
            prop_assert!(bound <= exact + 1e-12 && bound >= (1.0 - slack) * exact - 1e-9, "bound {bound}, exact {exact}, slack {slack}");
        }
        let d = distance(&a, &pa, &b, &pb);
        if d < EXACT_BELOW || exact < EXACT_BELOW {
            prop_assert!((d - exact).abs() <= 1e-9 * (1.0 + exact) || (d == 0.0 && overlap(&a, &pa, &b, &pb, -1.0).is_some()));
        }
    }

    /// The walk's deepest contact of two meshes is parry's: the same distance and points; the
    /// lighter questions (`Ask::Over`, `Ask::Touch`) answer what the deepest says, and the
    /// public queries built on them (`overlaps`, `touches`, `overlap_beyond`) what
    /// `overlap_touch` says.
    #[test]
    fn the_pair_walks_contact_is_parrys(
        ka in 0usize..4, kb in 0usize..4, scale in 0.5f64..3.0, spread in 0.0f64..3.0,
        x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0,
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, az in -3.0f64..3.0,
        eps in 0.0f64..0.5, floor in 0.0f64..1.0
    ) {
        let (a, b) = (pair_mesh(ka, scale), pair_mesh(kb, 1.0));
        let (pa, pb) = (rot(0.2, 0.1, -0.3, 0.0, 0.4, 0.0), rot(x * spread, y * spread, z * spread, ax, ay, az));
        let (qa, qb) = (to_pose(&pa), to_pose(&pb));
        let (ma, mb) = (trimesh(&a), trimesh(&b));
        let parry = query::contact(&qa, ma.0, &qb, mb.0, 0.0).unwrap();
        let walk = pairs::mesh_contact(ma.0, mb.0, &qa, &qb, pairs::Ask::Deepest);
        prop_assert_eq!(parry.map(|c| (c.dist, c.point1, c.point2)), walk.map(|c| (c.dist, c.point1, c.point2)));
        let deepest = parry.map_or(f64::NEG_INFINITY, |c| -c.dist);
        let over = pairs::mesh_contact(ma.0, mb.0, &qa, &qb, pairs::Ask::Over { eps, floor });
        let over_depth = over.map_or(f64::NEG_INFINITY, |c| -c.dist);
        prop_assert_eq!(over_depth > eps, deepest > eps);
        if deepest > floor.max(eps) {
            prop_assert_eq!(over_depth, deepest);
        }
        let touch = pairs::mesh_contact(ma.0, mb.0, &qa, &qb, pairs::Ask::Touch { eps });
        prop_assert_eq!(touch.is_some(), parry.is_some());
        prop_assert_eq!(touch.is_some_and(|c| -c.dist > eps), deepest > eps);
        // The public queries, asked before the full one is held.
        let eps = eps + 1e-6;
        let (whether, touching) = touches(&a, &pa, &b, &pb, eps);
        let any = overlaps(&a, &pa, &b, &pb, eps);
        let beyond = overlap_beyond(&a, &pa, &b, &pb, eps, floor);
        let (hit, full_touch) = overlap_touch(&a, &pa, &b, &pb, eps);
        prop_assert_eq!((whether, touching), (hit.is_some(), full_touch));
        prop_assert_eq!(any, hit.is_some());
        prop_assert_eq!(beyond.is_some(), hit.is_some());
        if let (Some(h), Some(g)) = (hit, beyond) {
            if h.depth > floor + BEYOND_MM {
                prop_assert_eq!(g.depth, h.depth);
            } else {
                prop_assert!(g.depth <= floor + BEYOND_MM + 1e-6);
            }
        }
    }
}

/// Two triangles apart get a crossing bound of at most minus their gap (the contact query skips
/// them by it), and two crossing ones a bound of at least their depth.
#[test]
fn triangles_apart_are_bounded_by_minus_their_gap() {
    use parry3d_f64::math::Vector;
    use parry3d_f64::shape::Triangle;
    let a = [
        Vector::new(0.0, 0.0, 0.0),
        Vector::new(4.0, 0.0, 0.0),
        Vector::new(0.0, 4.0, 0.0),
    ];
    let lift = |z: f64| {
        [
            Vector::new(0.5, 0.5, z),
            Vector::new(3.0, 0.5, z),
            Vector::new(0.5, 3.0, z + 0.2),
        ]
    };
    let apart = lift(1.5);
    let bound = pairs::crossing_bound(&a, &apart);
    assert!(bound <= -1.5 + 1e-12, "{bound}");
    let tri = |t: &[Vector; 3]| Triangle::new(t[0], t[1], t[2]);
    let none = query::contact(&Pose::IDENTITY, &tri(&a), &Pose::IDENTITY, &tri(&apart), 0.0).unwrap();
    assert!(none.is_none());
    // A triangle standing through the other: crossing, so the bound is no less than the depth.
    let through = [
        Vector::new(1.0, 1.0, -1.0),
        Vector::new(2.0, 1.0, -1.0),
        Vector::new(1.5, 1.0, 1.0),
    ];
    let c = query::contact(&Pose::IDENTITY, &tri(&a), &Pose::IDENTITY, &tri(&through), 0.0)
        .unwrap()
        .unwrap();
    assert!(pairs::crossing_bound(&a, &through) >= -c.dist - 1e-9);
}

#[test]
fn a_far_pair_is_measured_to_within_the_slack_and_a_near_one_exactly() {
    let (a, b) = (pair_mesh(3, 10.0), pair_mesh(2, 10.0));
    for (gap, exact) in [(5.0, true), (300.0, false)] {
        let (pa, pb) = (at(0.0, 0.0, 0.0), rot(0.0, 0.0, 40.0 + gap, 0.2, 0.0, 0.0));
        let (qa, qb) = (to_pose(&pa), to_pose(&pb));
        let parry = query::distance(&qa, trimesh(&a).0, &qb, trimesh(&b).0)
            .unwrap()
            .distance;
        let d = distance(&a, &pa, &b, &pb);
        let bound = distance_bound(&a, &pa, &b, &pb);
        if exact {
            assert!((d - parry).abs() < 1e-9, "{d} {parry}");
        }
        assert!(d <= parry + 1e-9 && d >= (1.0 - pairs::SLACK) * parry, "{d} {parry}");
        assert!(
            bound <= parry + 1e-9 && bound >= (1.0 - pairs::ADVANCE_SLACK) * parry,
            "{bound} {parry}"
        );
    }
}

// ---- the stock ----

/// Brute force: the deepest radial depth into the material (`material_at`) of a section point of
/// any triangle on any column's centre plane, the sections found by sampling: a dense grid of
/// points on each triangle, and the crossings of the plane by the grid's edges. Depths of `eps`
/// or less count as none. Returns the depth and the grid spacing (the oracle's resolution).
fn stock_oracle(s: &Shape3, pose: &Iso, stock: &DexelStock, eps: f64) -> (f64, f64) {
    let p = to_pose(pose);
    let (v, t) = s.surface();
    let n = 120usize;
    let mut best: f64 = 0.0;
    let mut spacing: f64 = 0.0;
    for tr in t {
        let q = [p * v[tr[0] as usize], p * v[tr[1] as usize], p * v[tr[2] as usize]];
        let e = (q[1] - q[0])
            .length()
            .max((q[2] - q[0]).length())
            .max((q[2] - q[1]).length());
        spacing = spacing.max(e / n as f64);
        let g =
            |i: usize, j: usize| q[0] + (q[1] - q[0]) * (i as f64 / n as f64) + (q[2] - q[0]) * (j as f64 / n as f64);
        let (z0, z1) = (q[0].z.min(q[1].z).min(q[2].z), q[0].z.max(q[1].z).max(q[2].z));
        let Some((k0, k1)) = stock.columns_within(z0 - 1e-9, z1 + 1e-9) else {
            continue;
        };
        for k in k0..=k1 {
            let c = stock.column_center(k);
            let mat = stock.material_at(c);
            for i in 0..=n {
                for j in 0..=(n - i) {
                    let a = g(i, j);
                    let mut nb = vec![];
                    if i + j < n {
                        nb.push(g(i + 1, j));
                        nb.push(g(i, j + 1));
                    }
                    if i > 0 && j < n {
                        nb.push(g(i - 1, j + 1));
                    }
                    for b in nb {
                        if (a.z - c) * (b.z - c) > 0.0 || a.z == b.z {
                            continue;
                        }
                        let x = a + (b - a) * ((c - a.z) / (b.z - a.z));
                        let rho = x.x.hypot(x.y);
                        for &(lo, hi) in &mat {
                            let d = (rho - lo).min(hi - rho);
                            if d > eps {
                                best = best.max(d);
                            }
                        }
                    }
                }
            }
        }
    }
    (best, spacing)
}

/// The smallest distance from points sampled on the triangles to the material rings on the
/// columns' centre planes: at least the true distance.
fn sampled_gap(s: &Shape3, pose: &Iso, stock: &DexelStock) -> f64 {
    let p = to_pose(pose);
    let (v, t) = s.surface();
    let n = 12;
    let mut best = f64::INFINITY;
    for tr in t {
        let q = [p * v[tr[0] as usize], p * v[tr[1] as usize], p * v[tr[2] as usize]];
        for i in 0..=n {
            for j in 0..=(n - i) {
                let x = q[0] + (q[1] - q[0]) * (i as f64 / n as f64) + (q[2] - q[0]) * (j as f64 / n as f64);
                let rho = x.x.hypot(x.y);
                for k in 0..stock.columns() {
                    let c = stock.column_center(k);
                    for (lo, hi) in stock.material_at(c) {
                        let dr = (lo - rho).max(rho - hi).max(0.0);
                        best = best.min(dr.hypot(x.z - c));
                    }
                }
            }
        }
    }
    best
}

#[test]
fn stock_overlap_a_drill_into_the_bar() {
    let mut stock = DexelStock::new(40.0, 0.0, 50.0, 0.0, 0.5);
    let drill = shape(&Geometry::Cylinder {
        radius: 2.0,
        z0: 0.0,
        z1: 30.0,
    });
    // A cross drill along -x (the cylinder's z turned onto x), its tip at radius 15.
    let pose = rot(15.0, 0.0, -20.0, 0.0, std::f64::consts::FRAC_PI_2, 0.0);
    let h = stock_overlap(&drill, &pose, &mut stock, View::Now, 1e-6).expect("drill in the bar");
    assert!(h.depth > 2.0, "{h:?}");
    let away = rot(25.0, 0.0, -20.0, 0.0, std::f64::consts::FRAC_PI_2, 0.0);
    assert!(stock_overlap(&drill, &away, &mut stock, View::Now, 1e-6).is_none());
    let g = stock_gap(&drill, &away, &mut stock, View::Now, 100.0);
    assert!(g > 4.0 && g <= 5.0 + 1e-9, "{g}");
    assert_eq!(stock_gap(&drill, &pose, &mut stock, View::Now, 100.0), 0.0);
}

#[test]
fn stock_ring_inside_a_mesh_is_an_overlap() {
    // A closed hollow-free mesh around the whole bar (a big sphere) overlaps it.
    let mut stock = DexelStock::new(10.0, 0.0, 10.0, 0.0, 0.5);
    let ball = shape(&sphere_mesh(40.0, 16));
    assert!(stock_overlap(&ball, &at(0.0, 0.0, -5.0), &mut stock, View::Now, 1e-6).is_some());
}

#[test]
fn stock_inside_a_mesh_whose_triangles_are_all_pruned_is_an_overlap() {
    // A long box mesh around the bar: its sides stand 60 mm from the axis, its ends far past the
    // stock along z, so the hierarchy prunes every triangle; the rings inside it still count.
    let mut stock = DexelStock::new(25.0, 0.0, 50.0, 0.0, 0.5);
    let sleeve = box_mesh(60.0, 60.0, 500.0);
    let h = stock_overlap(&sleeve, &at(0.0, 0.0, 0.0), &mut stock, View::Now, 1e-6);
    assert!(h.is_some_and(|h| h.depth > 1.0), "{h:?}");
    assert_eq!(
        stock_gap(&sleeve, &at(0.0, 0.0, 0.0), &mut stock, View::Now, 100.0),
        0.0
    );
    // Moved off the bar altogether: apart, and the gap found through the pruned hierarchy is
    // the true one (the sleeve's near side at y 30, the bar's surface at radius 12.5).
    let off = at(0.0, 90.0, 0.0);
    assert!(stock_overlap(&sleeve, &off, &mut stock, View::Now, 1e-6).is_none());
    let g = stock_gap(&sleeve, &off, &mut stock, View::Now, 100.0);
    assert!((g - 17.5).abs() < 0.5, "{g}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn stock_query_equals_brute_force_oracle(
        x in -25.0f64..25.0, y in -25.0f64..25.0, z in -40.0f64..10.0, ax in -3.0f64..3.0, ay in -3.0f64..3.0
    ) {
        // A tube (bore 10, diameter 30) and a box too small to hold a ring of it: every overlap
        // is a triangle's section in the material.
        let mut stock = DexelStock::new(30.0, 10.0, 30.0, 0.0, 1.0);
        let b = box_mesh(3.0, 1.0, 4.0);
        let pose = rot(x, y, z, ax, ay, 0.0);
        let eps = 1e-6;
        let fast = stock_overlap(&b, &pose, &mut stock, View::Now, eps).map_or(0.0, |h| h.depth);
        let (oracle, spacing) = stock_oracle(&b, &pose, &stock, eps);
        // Radial depth is 1-Lipschitz in the point: the samples are within `spacing` of it.
        prop_assert!((fast - oracle).abs() <= spacing + 1e-9, "exact {} oracle {} (spacing {})", fast, oracle, spacing);
        let gap = stock_gap(&b, &pose, &mut stock, View::Now, 50.0);
        if fast > 0.0 {
            prop_assert_eq!(gap, 0.0);
        }
        // A lower bound: never more than the distance of any sampled point to the material.
        let sampled = sampled_gap(&b, &pose, &stock);
        prop_assert!(gap >= 0.0 && gap <= sampled.min(50.0) + 1e-9, "gap {} sampled {}", gap, sampled);
    }
}

// ---- motion ----

/// A machine: a Z slide carrying an X slide carrying a B head (rotary about y) with a tool, and a
/// spindle with C (rotary about z) holding a plate.
fn machine(tool: Geometry, plate: Geometry) -> Kinematics {
    let axes = vec![
        Axis {
            name: "z".into(),
            letter: 'Z',
            kind: AxisKind::Linear { dir: Vector3::z_axis() },
            zero: 0.0,
            travel: (-1e3, 1e3),
            rapid: 1e4,
            path: 1,
        },
        Axis {
            name: "x".into(),
            letter: 'X',
            kind: AxisKind::Linear { dir: Vector3::x_axis() },
            zero: 0.0,
            travel: (-1e3, 1e3),
            rapid: 1e4,
            path: 1,
        },
        Axis {
            name: "b".into(),
            letter: 'B',
            kind: AxisKind::Rotary {
                origin: Point3::new(0.0, 0.0, 0.0),
                dir: Vector3::y_axis(),
            },
            zero: 0.0,
            travel: (f64::NEG_INFINITY, f64::INFINITY),
            rapid: 1e4,
            path: 1,
        },
        Axis {
            name: "c".into(),
            letter: 'C',
            kind: AxisKind::Rotary {
                origin: Point3::new(0.0, 0.0, 0.0),
                dir: Unit::new_normalize(Vector3::new(0.0, 0.0, 1.0)),
            },
            zero: 0.0,
            travel: (f64::NEG_INFINITY, f64::INFINITY),
            rapid: 1e4,
            path: 1,
        },
    ];
    let comp = |name: &str, parent, mount, axis, geometry| Component {
        name: name.into(),
        parent,
        mount,
        axis,
        geometry,
        role: Role::Structure,
        station: None,
        label: None,
    };
    Kinematics {
        axes,
        components: vec![
            comp("zslide", None, Iso::identity(), Some(0), None),
            comp("xslide", Some(0), Iso::identity(), Some(1), None),
            comp("head", Some(1), at(0.0, 0.0, 10.0), Some(2), None),
            comp("tool", Some(2), at(0.0, 0.0, 5.0), None, Some(tool)),
            comp("spindle", None, Iso::identity(), Some(3), None),
            comp("plate", Some(4), Iso::identity(), None, Some(plate)),
        ],
        never_touch: vec![(3, 5)],
    }
}

fn vertices(g: &Geometry) -> Vec<Point3<f64>> {
    match g {
        Geometry::Mesh(m) => m.vertices.clone(),
        Geometry::Cuboid { min, max } => (0..8)
            .map(|i| {
                Point3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                )
            })
            .collect(),
        _ => Vec::new(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn motion_bound_never_smaller_than_vertex_displacement(
        v0 in proptest::collection::vec(-200.0f64..200.0, 4),
        v1 in proptest::collection::vec(-200.0f64..200.0, 4),
        comp in prop_oneof![Just(3usize), Just(5usize)],
    ) {
        let k = machine(boxg(2.0, 1.0, 30.0), boxg(40.0, 3.0, 1.0));
        let bound = motion_bound(&k, comp, &v0, &v1);
        let verts = vertices(k.components[comp].geometry.as_ref().unwrap());
        let mut poser = Poser::new(&k);
        poser.pose(&k, &v0);
        let start: Vec<Point3<f64>> = verts.iter().map(|p| poser.world(comp) * p).collect();
        let path = LinearPath { v0: v0.clone(), v1: v1.clone() };
        let mut vals = Vec::new();
        for i in 1..=200 {
            path.at(i as f64 / 200.0, &mut vals);
            poser.pose(&k, &vals);
            for (p, s) in verts.iter().zip(&start) {
                let moved = (poser.world(comp) * p - s).norm();
                prop_assert!(moved <= bound * (1.0 + 1e-12) + 1e-9, "moved {} > bound {}", moved, bound);
            }
        }
    }
}

/// Dense sampling: the first sample of the path where the pair overlaps by more than `eps`.
fn oracle_first(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &LinearPath,
    eps: f64,
    n: usize,
) -> Option<f64> {
    let mut poser = Poser::new(k);
    let mut vals = Vec::new();
    (0..=n).map(|i| i as f64 / n as f64).find(|&u| {
        path.at(u, &mut vals);
        poser.pose(k, &vals);
        overlap(a.1, poser.world(a.0), b.1, poser.world(b.0), eps).is_some()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn first_contact_never_tunnels_thin_plates_fast_moves(
        x0 in -150.0f64..150.0, x1 in -150.0f64..150.0,
        z0 in -60.0f64..20.0, z1 in -60.0f64..20.0,
        b0 in -180.0f64..180.0, b1 in -180.0f64..180.0,
        c0 in -360.0f64..360.0, c1 in -360.0f64..360.0,
        rotary in any::<bool>(),
    ) {
        // A thin tool blade and a thin plate (0.2 mm) on the spindle.
        let k = machine(boxg(0.1, 4.0, 20.0), boxg(60.0, 0.1, 60.0));
        let ta = Shape3::from_geometry(k.components[3].geometry.as_ref().unwrap(), 0.01).unwrap();
        let tb = Shape3::from_geometry(k.components[5].geometry.as_ref().unwrap(), 0.01).unwrap();
        let (b0, b1, c0, c1) = if rotary { (b0, b1, c0, c1) } else { (0.0, 0.0, 0.0, 0.0) };
        let path = LinearPath { v0: vec![z0, x0, b0, c0], v1: vec![z1, x1, b1, c1] };
        let eps = 1e-3;
        let got = first_contact(&k, (3, &ta), (5, &tb), &path, eps, eps / 2.0);
        let want = oracle_first(&k, (3, &ta), (5, &tb), &path, eps * 10.0, 2000);
        match (got, want) {
            (Advance::Unchecked { .. }, _) => {}
            (Advance::Clear, Some(u)) => prop_assert!(false, "tunnelled: oracle overlap at u = {}", u),
            (Advance::Contact { u, .. }, Some(w)) => prop_assert!(u <= w + 1e-9, "contact at {} after the oracle's {}", u, w),
            (Advance::Contact { u, hit }, None) => {
                // A contact the samples missed: it must be real.
                let mut poser = Poser::new(&k);
                let mut vals = Vec::new();
                path.at(u, &mut vals);
                poser.pose(&k, &vals);
                prop_assert!(overlap(&ta, poser.world(3), &tb, poser.world(5), eps).is_some(), "{:?}", hit);
            }
            (Advance::Clear, None) => {}
        }
    }
}

#[test]
fn first_contact_finds_a_thin_plate_in_one_fast_move() {
    let k = machine(boxg(0.1, 4.0, 20.0), boxg(60.0, 0.1, 60.0));
    let ta = Shape3::from_geometry(k.components[3].geometry.as_ref().unwrap(), 0.01).unwrap();
    let tb = Shape3::from_geometry(k.components[5].geometry.as_ref().unwrap(), 0.01).unwrap();
    // The plate in the x-z plane at y = 0; C turns it 90° (into y-z) under the blade at x = 30.
    let path = LinearPath {
        v0: vec![-50.0, 30.0, 0.0, 90.0],
        v1: vec![-50.0, 30.0, 0.0, 0.0],
    };
    // Start: the plate in the y-z plane, the blade at x = 30 with its centre z = 10 + 5 - 50.
    match first_contact(&k, (3, &ta), (5, &tb), &path, 1e-3, 1e-3 / 2.0) {
        Advance::Contact { u, .. } => assert!(u > 0.0 && u < 1.0, "{u}"),
        other => panic!("{other:?}"),
    }
    // Endpoints both clear, the middle is not: sampling only the ends would tunnel.
    let far = LinearPath {
        v0: vec![-50.0, 100.0, 0.0, 0.0],
        v1: vec![-50.0, -100.0, 0.0, 0.0],
    };
    assert!(matches!(
        first_contact(&k, (3, &ta), (5, &tb), &far, 1e-3, 1e-3 / 2.0),
        Advance::Contact { .. }
    ));
}

/// A stepped tube: bore 8 (radius 4) from z −30 to 0, outer radius 15 up to z −10 and 10 beyond
/// (a shoulder at z −10), a groove at z −20 .. −18 down to radius 12.
fn stepped_stock() -> DexelStock {
    let h = 0.5;
    let cols = (0..60)
        .map(|j| {
            let z = -30.0 + (j as f64 + 0.5) * h;
            let outer = if z > -10.0 {
                10.0
            } else if (-20.0..-18.0).contains(&z) {
                12.0
            } else {
                15.0
            };
            vec![(4.0, outer)]
        })
        .collect();
    DexelStock::from_columns(-30.0, h, cols)
}

/// A part sliding along the bar at its radius (a flat face on it) is proven clear; the same
/// part 0.1 mm into it is not.
#[test]
fn the_hull_of_a_box_sliding_along_the_bar_is_clear_and_into_it_is_not() {
    let mut stock = DexelStock::new(50.0, 0.0, 120.0, 80.0, 0.01);
    let b = box_mesh(25.0, 25.0, 30.0);
    // The box's near face at x = 25, the bar's radius; it slides 100 mm along z.
    let poses = [at(50.0, 0.0, 110.0), at(50.0, 0.0, 10.0)];
    assert!(stock_hull_depth(&b, &poses, &mut stock, View::Now) <= 0.5 * crate::geom::TOUCH_EPS);
    let into = [at(49.9, 0.0, 110.0), at(49.9, 0.0, 10.0)];
    let d = stock_hull_depth(&b, &into, &mut stock, View::Now);
    assert!((d - 0.1).abs() < 1e-6, "{d}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// The hull bound against the slow, plain oracle: every pose of the part translated along
    /// the polyline through the given poses (sampled densely) has an overlap depth, as the
    /// advancement's probes measure it, no deeper than the bound.
    #[test]
    fn the_hull_depth_bounds_every_pose_along_the_polyline(
        kind in 0usize..3,
        x in -30.0f64..30.0, y in -30.0f64..30.0, z in -45.0f64..15.0,
        ax in -3.0f64..3.0, ay in -3.0f64..3.0,
        wx in -20.0f64..20.0, wy in -20.0f64..20.0, wz in -30.0f64..30.0,
        bend in proptest::option::of((-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0)),
    ) {
        let mut stock = stepped_stock();
        let part = match kind {
            0 => box_mesh(3.0, 1.5, 5.0),
            1 => shape(&Geometry::Cylinder { radius: 2.5, z0: 0.0, z1: 12.0 }),
            _ => shape(&sphere_mesh(4.0, 8)),
        };
        let p0 = rot(x, y, z, ax, ay, 0.0);
        let shift = |p: &Iso, v: Vector3<f64>| Iso::from_parts(Translation3::from(p.translation.vector + v), p.rotation);
        let w = Vector3::new(wx, wy, wz);
        let mut corners = vec![p0];
        if let Some((bx, by, bz)) = bend {
            corners.push(shift(&p0, w / 2.0 + Vector3::new(bx, by, bz)));
        }
        corners.push(shift(&p0, w));
        let bound = stock_hull_depth(&part, &corners, &mut stock, View::Now);
        let mut deepest = 0.0f64;
        for pair in corners.windows(2) {
            let (a, b) = (pair[0].translation.vector, pair[1].translation.vector);
            for k in 0..=64 {
                let s = k as f64 / 64.0;
                let pose = shift(&p0, a + (b - a) * s - p0.translation.vector);
                let d = stock_overlap(&part, &pose, &mut stock, View::Now, 0.0).map_or(0.0, |h| h.depth);
                deepest = deepest.max(d);
            }
        }
        prop_assert!(deepest <= bound + 1e-9, "a pose {} deep, bound {}", deepest, bound);
    }
}

/// The advancement with stretches proven by the shape cast of the pair's translations
/// (`first_contact_proving` with `swept_clear`) answers as the plain one: clear where it is
/// clear, the first contact where it finds one (both bisect to 1e-9), and the proofs are taken
/// (not vacuous). A box tool translating past and into a plate and a cylinder primitive.
#[test]
fn stretches_proven_by_the_swept_pair_change_no_answer() {
    let tools = [
        boxg(2.0, 4.0, 20.0),
        Geometry::Cylinder {
            radius: 3.0,
            z0: 0.0,
            z1: 30.0,
        },
    ];
    let mut rnd = crate::test_util::unit_random(5u64);
    let (mut proofs, mut contacts, mut clear) = (0, 0, 0);
    for i in 0..160 {
        let k = machine(tools[i % 2].clone(), boxg(60.0, 1.0, 60.0));
        let ta = Shape3::from_geometry(k.components[3].geometry.as_ref().unwrap(), 0.01).unwrap();
        let tb = Shape3::from_geometry(k.components[5].geometry.as_ref().unwrap(), 0.01).unwrap();
        // C fixed at a random angle; z and x translate.
        let c = 360.0 * rnd();
        let path = LinearPath {
            v0: vec![-80.0 + 60.0 * rnd(), 150.0 * rnd() - 75.0, 0.0, c],
            v1: vec![-80.0 + 60.0 * rnd(), 150.0 * rnd() - 75.0, 0.0, c],
        };
        let tol = 0.01;
        let plain = first_contact_from(&k, (3, &ta), (5, &tb), &path, 2.0 * tol, tol, 0.0).0;
        let mut poser = Poser::new(&k);
        let mut vals = Vec::new();
        let mut pose = |u: f64| {
            path.at(u, &mut vals);
            poser.pose(&k, &vals);
            (*poser.world(3), *poser.world(5))
        };
        let mut prove = |u0: f64, u1: f64| {
            let ((a0, b0), (a1, b1)) = (pose(u0), pose(u1));
            let ok = swept_clear(&ta, (&a0, &a1), &tb, (&b0, &b1), 1e-8);
            proofs += usize::from(ok);
            ok
        };
        let proving = first_contact_proving(&k, (3, &ta), (5, &tb), &path, 2.0 * tol, tol, 0.0, Some(&mut prove)).0;
        match (plain, proving) {
            (Advance::Clear, Advance::Clear) => clear += 1,
            (Advance::Contact { u: a, .. }, Advance::Contact { u: b, .. }) => {
                assert!((a - b).abs() <= 2e-9, "case {i}: first contact at {a} and {b}");
                contacts += 1;
            }
            other => panic!("case {i}: {other:?}"),
        }
    }
    assert!(
        proofs > 20 && contacts > 10 && clear > 10,
        "proofs {proofs}, contacts {contacts}, clear {clear}"
    );
}

/// `swept_clear` against sampling: where it says a translating pair stays apart, no sampled pose
/// of the path overlaps (a pair that overlaps at the start and moves apart included); and a path
/// through the plate is never called clear. Primitives and meshes (a shape cast of surfaces, a
/// small cube that may start inside the plate: containment).
#[test]
fn a_swept_pair_called_clear_overlaps_at_no_sampled_pose() {
    let tools = [boxg(2.0, 4.0, 20.0), boxg(0.3, 0.3, 0.3)];
    let mut rnd = crate::test_util::unit_random(17u64);
    let (mut yes, mut no) = (0, 0);
    for i in 0..300 {
        let k = machine(tools[i % 2].clone(), boxg(60.0, 1.0, 60.0));
        let shape = |c: usize| {
            let g = k.components[c].geometry.as_ref().unwrap();
            if i % 3 == 0 {
                Shape3::from_geometry(g, 0.01).unwrap()
            } else {
                Shape3::meshed(g, 0.01).unwrap()
            }
        };
        let (ta, tb) = (shape(3), shape(5));
        // Every fifth case with the plate square to the tool's plane (a small cube inside it).
        let c = if i % 5 == 0 { 0.0 } else { 360.0 * rnd() };
        let path = LinearPath {
            v0: vec![-80.0 + 60.0 * rnd(), 150.0 * rnd() - 75.0, 0.0, c],
            v1: vec![-80.0 + 60.0 * rnd(), 150.0 * rnd() - 75.0, 0.0, c],
        };
        let mut poser = Poser::new(&k);
        let mut vals = Vec::new();
        let mut pose = |u: f64| {
            path.at(u, &mut vals);
            poser.pose(&k, &vals);
            (*poser.world(3), *poser.world(5))
        };
        let ((a0, b0), (a1, b1)) = (pose(0.0), pose(1.0));
        let clear = swept_clear(&ta, (&a0, &a1), &tb, (&b0, &b1), 1e-8);
        let hit = (0..=400).any(|i| {
            let (a, b) = pose(i as f64 / 400.0);
            overlap(&ta, &a, &tb, &b, 0.0).is_some()
        });
        assert!(!(clear && hit), "case {i}: called clear, overlaps: {path:?}");
        if clear {
            yes += 1;
        } else {
            no += 1;
        }
    }
    assert!(yes > 30 && no > 30, "clear {yes}, not {no}");
}

/// The answers held (`memo`) are the answers computed: a question asked again, or a question
/// that differs from one held only in a shape (of the same size class, at the same poses), a
/// pose's last bit or the depth threshold, gets what computing it gives, bit for bit.
#[test]
fn a_held_answer_is_the_answer_computed_for_the_same_question_only() {
    let bits = |r: (Option<Hit>, bool)| {
        let c = |h: Hit| [h.depth, h.point.x, h.point.y, h.point.z].map(f64::to_bits);
        (r.0.map(c), r.1)
    };
    let (small, big, other) = (
        box_mesh(1.0, 1.0, 1.0),
        box_mesh(2.0, 2.0, 2.0),
        box_mesh(1.0, 1.0, 1.0),
    );
    let prim = shape(&boxg(1.5, 1.0, 1.0));
    let pa = rot(0.3, 0.2, 0.1, 0.2, 0.1, 0.3);
    let pb = at(1.5, 0.0, 0.0);
    let nudged = Iso::from_parts(
        Translation3::new(f64::from_bits(1.5f64.to_bits() + 1), 0.0, 0.0),
        UnitQuaternion::identity(),
    );
    let far = at(9.0, 0.0, 0.0);
    let mut answers = Vec::new();
    for _ in 0..2 {
        for a in [&small, &big, &prim] {
            for b in [&other, &prim] {
                for p in [&pb, &nudged, &far] {
                    for eps in [1e-6, 0.2, 5.0] {
                        let held = overlap_touch(a, &pa, b, p, eps);
                        assert_eq!(bits(held), bits(overlap_touch_computed(a, &pa, b, p, eps)));
                        answers.push(bits(held));
                    }
                    let d = distance(a, &pa, b, p);
                    assert_eq!(d.to_bits(), distance_computed(a, &pa, b, p, EXACT_BELOW).to_bits());
                }
            }
        }
    }
    // The questions differ in their answers (a key that left out a shape, a pose or the
    // threshold would give one of them another's).
    let mut distinct = answers.clone();
    distinct.sort();
    distinct.dedup();
    assert!(distinct.len() >= 10, "{} of {}", distinct.len(), answers.len());
}

/// Two triangles that `pairs::beyond_best` says lie further apart than a best distance are at
/// least that far apart by GJK, as the pair walk measures them (its triangle second, posed back
/// into its frame): the walk may skip their GJK without changing its answer. Random triangles
/// at random distances, with the best just below, at and just above the widest gap of their
/// shadows; the skip must fire on some.
#[test]
fn triangles_beyond_the_best_by_their_shadows_are_beyond_it_by_gjk() {
    use parry3d_f64::math::Vector;
    use parry3d_f64::query::{DefaultQueryDispatcher, QueryDispatcher};
    use parry3d_f64::shape::Triangle;
    let mut rnd = crate::test_util::unit_random(17u64);
    let mut point = |c: Vector, s: f64| c + Vector::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * s;
    let (mut fired, mut cases) = (0, 0);
    for i in 0..3000 {
        let scale = [0.1, 1.0, 20.0, 300.0][i % 4];
        let ca = Vector::new(100.0, -50.0, 30.0);
        let cb = point(ca, 4.0 * scale);
        let a = [point(ca, scale), point(ca, scale), point(ca, scale)];
        let b = [point(cb, scale), point(cb, scale), point(cb, scale)];
        let gjk = DefaultQueryDispatcher
            .distance(
                &Pose::IDENTITY,
                &Triangle::new(b[0], b[1], b[2]),
                &Triangle::new(a[0], a[1], a[2]),
            )
            .unwrap()
            .distance;
        let widest = -pairs::crossing_bound(&a, &b);
        for best in [
            0.5 * widest,
            widest * (1.0 - 1e-12),
            widest,
            widest * (1.0 + 1e-12),
            2.0 * widest,
        ] {
            if best <= 0.0 {
                continue;
            }
            cases += 1;
            if pairs::beyond_best(&a, &b, best) {
                fired += 1;
                assert!(gjk >= best, "GJK {gjk} below the best {best} (shadows {widest})");
            }
        }
    }
    assert!(fired > cases / 10 && fired < cases, "{fired} of {cases}");
}

proptest! {
    /// A shape holds a point exactly when parry's point query says so: the box's early answer
    /// (a point beyond the shape's own box is outside) changes none. Meshes (a sphere, a box,
    /// revolved outlines) and primitives (a box, a cylinder), posed anyhow, against points near
    /// their boxes' faces, inside them and beyond.
    #[test]
    fn a_shape_holds_a_point_as_parrys_query_says(
        x in -3.0f64..3.0, y in -3.0f64..3.0, z in -3.0f64..3.0,
        ax in -3.0f64..3.0, ay in -3.0f64..3.0, az in -3.0f64..3.0, kind in 0usize..7,
        scale in 0.5f64..1.5,
    ) {
        let s = match kind {
            0..=4 => pair_mesh(kind.min(3), scale),
            5 => shape(&boxg(scale, 0.5 * scale, 2.0 * scale)),
            _ => shape(&Geometry::Cylinder { radius: 0.8 * scale, z0: -scale, z1: 1.5 * scale }),
        };
        let pose = to_pose(&rot(0.3, -0.2, 0.1, ax, ay, az));
        let b = s.local_box();
        let p = pose * ((b.mins + b.maxs) * 0.5 + Vector::new(x, y, z) * ((b.maxs - b.mins).max_element() / 4.0));
        let (sh, pos) = s.parts(&pose);
        prop_assert_eq!(s.contains(&pose, p), sh.contains_point(&pos, p));
    }
}
