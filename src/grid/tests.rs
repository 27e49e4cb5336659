//! Volumes removed against closed forms, and the grids against a slow oracle.

use super::*;
use nalgebra::Vector3;
use std::f64::consts::PI;

pub(super) fn bar(r: f64, len: f64, tol: f64) -> Stock {
    Stock::turned(0.0, len, r, tol, |_| Some((0.0, r))).unwrap()
}

pub(super) fn flat(d: f64, l: f64) -> Cutter {
    Cutter::new(CutterKind::Flat, d, l).unwrap()
}

pub(super) fn sweep(c: &Cutter, axis: [f64; 3], a: [f64; 3], b: [f64; 3], tol: f64) -> Sweep {
    Sweep::new(c, Vector3::from(axis), Vector3::from(a), Vector3::from(b), tol).unwrap()
}

/// A flat of depth h across a bar of radius R by the end face of a radial mill moved across it:
/// the circular segment's area × the mill's diameter.
fn segment(r: f64, h: f64) -> f64 {
    r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt()
}

#[test]
fn a_milled_flat_removes_the_circular_segment_times_its_width() {
    let (r, h, d, tol) = (20.0, 5.0, 16.0, 0.1);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    assert!((v0 - PI * r * r * 60.0).abs() < 0.01 * v0, "{v0}");
    // Axis +x (the shank outward), the end face at x = R − h, moved along y across the bar.
    let sw = sweep(
        &flat(d, 30.0),
        [1.0, 0.0, 0.0],
        [r - h, -30.0, 30.0],
        [r - h, 30.0, 30.0],
        tol,
    );
    let cut = s.cut(&sw);
    assert!(cut > 0.0);
    let want = segment(r, h) * d;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.03 * want, "removed {got}, closed form {want}");
    // The flat is there: a point just under where the surface was is air, one under the flat is
    // material, and the far side is untouched.
    assert!(!s.contains(Vector3::new(r - 1.0, 0.0, 30.0)));
    assert!(s.contains(Vector3::new(r - h - 0.5, 0.0, 30.0)));
    assert!(s.contains(Vector3::new(-(r - 1.0), 0.0, 30.0)));
    assert!(s.contains(Vector3::new(r - 1.0, 0.0, 45.0)));
}

#[test]
fn six_flats_leave_a_hex_across_flats() {
    let (r, af, tol) = (20.0, 30.0, 0.1);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    for k in 0..6 {
        let phi = (k as f64) * PI / 3.0;
        let (c, sn) = (phi.cos(), phi.sin());
        let a = af / 2.0;
        // 20 mm wide band: z 20 .. 40.
        let sw = sweep(
            &flat(20.0, 30.0),
            [c, sn, 0.0],
            [a * c + 30.0 * sn, a * sn - 30.0 * c, 30.0],
            [a * c - 30.0 * sn, a * sn + 30.0 * c, 30.0],
            tol,
        );
        s.cut(&sw);
    }
    let hex = 3.0f64.sqrt() / 2.0 * af * af;
    let want = (PI * r * r - hex) * 20.0;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.03 * want, "removed {got}, closed form {want}");
}

#[test]
fn a_slot_around_the_circumference_removes_a_ring() {
    let (r, h, w, tol) = (20.0, 3.0, 6.0, 0.1);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    // A radial mill of width w: the part turns under it (chords of its path in the part frame).
    let n = 180;
    for k in 0..n {
        let (p0, p1) = (2.0 * PI * k as f64 / n as f64, 2.0 * PI * (k + 1) as f64 / n as f64);
        let mid = (p0 + p1) / 2.0;
        let rr = r - h;
        let sw = sweep(
            &flat(w, 20.0),
            [mid.cos(), mid.sin(), 0.0],
            [rr * p0.cos(), rr * p0.sin(), 30.0],
            [rr * p1.cos(), rr * p1.sin(), 30.0],
            tol,
        );
        s.cut(&sw);
    }
    let want = PI * (r * r - (r - h) * (r - h)) * w;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.03 * want, "removed {got}, closed form {want}");
}

#[test]
fn a_cross_hole_through_a_bar_removes_the_cylinders_intersection() {
    // Equal diameters: Steinmetz's 16 r³ / 3.
    let (r, tol) = (10.0, 0.1);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    let sw = sweep(
        &flat(2.0 * r, 40.0),
        [1.0, 0.0, 0.0],
        [15.0, 0.0, 30.0],
        [-15.0, 0.0, 30.0],
        tol,
    );
    s.cut(&sw);
    let want = 16.0 * r * r * r / 3.0;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.04 * want, "removed {got}, Steinmetz {want}");
    assert!(
        !s.contains(Vector3::new(0.0, 0.0, 30.0)),
        "the hole goes through the axis"
    );
    assert!(!s.contains(Vector3::new(0.0, 9.0, 30.0)));
}

#[test]
fn a_face_pocket_removes_its_box_and_round_ends() {
    // A Ø10 flat mill along z into the front face 4 deep, moved 20 mm along x: a slot of
    // (20 × 10 + π 5²) × 4.
    let (r, tol) = (30.0, 0.1);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    let sw0 = sweep(
        &flat(10.0, 20.0),
        [0.0, 0.0, 1.0],
        [-10.0, 5.0, 61.0],
        [-10.0, 5.0, 56.0],
        tol,
    );
    let sw1 = sweep(
        &flat(10.0, 20.0),
        [0.0, 0.0, 1.0],
        [-10.0, 5.0, 56.0],
        [10.0, 5.0, 56.0],
        tol,
    );
    s.cut(&sw0);
    s.cut(&sw1);
    let want = (20.0 * 10.0 + PI * 25.0) * 4.0;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.04 * want, "removed {got}, closed form {want}");
    assert!(!s.contains(Vector3::new(0.0, 5.0, 58.0)));
    assert!(s.contains(Vector3::new(0.0, 5.0, 55.0)));
}

#[test]
fn a_dry_run_measures_without_cutting() {
    let mut s = bar(20.0, 60.0, 0.1);
    let sw = sweep(
        &flat(16.0, 30.0),
        [1.0, 0.0, 0.0],
        [15.0, -30.0, 30.0],
        [15.0, 30.0, 30.0],
        0.1,
    );
    let v0 = s.volume();
    let would = s.would_remove(&sw);
    assert!(would > 0.0);
    assert_eq!(s.volume(), v0);
    assert!((s.cut(&sw) - would).abs() < 1e-9);
    // Air: the same sweep again removes nothing.
    assert_eq!(s.would_remove(&sw), 0.0);
}

#[test]
fn cutters_are_checked_and_their_pieces_stay_inside_their_profile() {
    assert!(Cutter::new(CutterKind::Flat, 0.0, 10.0).is_err());
    assert!(Cutter::new(CutterKind::Bull { corner_radius: 6.0 }, 10.0, 20.0).is_err());
    assert!(Cutter::new(CutterKind::Drill { point_angle_deg: 180.0 }, 10.0, 20.0).is_err());
    assert!(Cutter::new(CutterKind::Tap { pitch: 10.0 }, 10.0, 20.0).is_err());
    for kind in [
        CutterKind::Flat,
        CutterKind::Ball,
        CutterKind::Bull { corner_radius: 2.0 },
        CutterKind::Drill { point_angle_deg: 118.0 },
        CutterKind::Tap { pitch: 1.5 },
    ] {
        let c = Cutter::new(kind, 10.0, 20.0).unwrap();
        for p in c.pieces(0.05) {
            let (r, h0, h1) = match p {
                cutter::Piece::Disc { r, h0, h1 } => (r, h0, h1),
                cutter::Piece::Ball { r, h } => (r, h - r, h + r),
            };
            for k in 0..=10 {
                let h = h0 + (h1 - h0) * k as f64 / 10.0;
                let width = match p {
                    cutter::Piece::Ball { r: br, h: bh } => (br * br - (h - bh) * (h - bh)).max(0.0).sqrt(),
                    _ => r,
                };
                assert!(width <= c.radius_at(h) + 1e-9, "{kind:?}: piece {p:?} at h {h}");
            }
        }
    }
}

#[test]
fn a_ball_end_groove_along_the_bar_is_a_half_round() {
    // A Ø8 ball end along z, its centre on the bar's surface: a groove of half a Ø8 circle.
    let (r, tol) = (20.0, 0.05);
    let mut s = bar(r, 60.0, tol);
    let v0 = s.volume();
    let c = Cutter::new(CutterKind::Ball, 8.0, 20.0).unwrap();
    // Axis +x, tip at x = r − 4 (centre at x = r), from z 10 to z 50.
    s.cut(&sweep(
        &c,
        [1.0, 0.0, 0.0],
        [r - 4.0, 0.0, 10.0],
        [r - 4.0, 0.0, 50.0],
        tol,
    ));
    let got = v0 - s.volume();
    // Inside the bar: about half the Ø8 disc (the bar's curvature takes a little) × 40, plus the
    // round ends.
    let lens = {
        // Area of the Ø8 disc centred on the circle of radius r, inside it.
        let (a, b) = (4.0f64, r);
        let d = r;
        a * a * ((d * d + a * a - b * b) / (2.0 * d * a)).acos()
            + b * b * ((d * d + b * b - a * a) / (2.0 * d * b)).acos()
            - 0.5 * ((-d + a + b) * (d + a - b) * (d - a + b) * (d + a + b)).sqrt()
    };
    let want = lens * 40.0 + 2.0 / 3.0 * PI * 64.0 * 0.5 * 2.0 * 0.5;
    assert!((got - want).abs() < 0.06 * want, "removed {got}, about {want}");
}

/// Oracle: a point the grids call air was inside some sweep (never removed what no cut
/// removed), on random radial and axial cuts.
#[test]
fn the_grids_never_remove_what_no_sweep_holds() {
    let mut rnd = crate::test_util::unit_random(12345u64);
    let tol = 0.2;
    let mut s = bar(15.0, 40.0, tol);
    let mut sweeps = Vec::new();
    for _ in 0..12 {
        let phi = rnd() * 2.0 * PI;
        let axial = rnd() < 0.3;
        let c = Cutter::new(
            if rnd() < 0.5 {
                CutterKind::Flat
            } else {
                CutterKind::Ball
            },
            4.0 + 6.0 * rnd(),
            20.0,
        )
        .unwrap();
        let sw = if axial {
            let (x, y) = (10.0 * rnd() - 5.0, 10.0 * rnd() - 5.0);
            sweep(
                &c,
                [0.0, 0.0, 1.0],
                [x, y, 42.0],
                [x + 4.0 * rnd() - 2.0, y, 40.0 - 6.0 * rnd()],
                tol,
            )
        } else {
            let depth = 15.0 - 4.0 * rnd();
            let z = 5.0 + 30.0 * rnd();
            let (c0, s0) = (phi.cos(), phi.sin());
            sweep(
                &c,
                [c0, s0, 0.0],
                [depth * c0 - 8.0 * s0, depth * s0 + 8.0 * c0, z],
                [depth * c0 + 8.0 * s0, depth * s0 - 8.0 * c0, z + 6.0 * rnd()],
                tol,
            )
        };
        s.cut(&sw);
        sweeps.push(sw);
    }
    let mut air = 0;
    for _ in 0..20000 {
        let p = Vector3::new(30.0 * rnd() - 15.0, 30.0 * rnd() - 15.0, 40.0 * rnd());
        if p.x.hypot(p.y) > 14.5 || p.z < 0.5 || p.z > 39.5 {
            continue;
        }
        if !s.contains(p) {
            air += 1;
            // Within a node's size of a sweep.
            let near = sweeps.iter().any(|sw| {
                (0..27).any(|k| {
                    let o = Vector3::new((k % 3) as f64 - 1.0, ((k / 3) % 3) as f64 - 1.0, (k / 9) as f64 - 1.0) * 0.3;
                    sw.contains(p + o)
                })
            });
            assert!(near, "{p:?} is air but no sweep holds it");
        }
    }
    assert!(air > 100, "the cuts removed something: {air}");
}

/// The volume a binary STL encloses (divergence theorem over its triangles), after checking that
/// it is closed: every edge (by its `f32` points) run by as many triangles one way as the other.
pub(super) fn closed_stl_volume(stl: &[u8]) -> f64 {
    let n = u32::from_le_bytes(stl[80..84].try_into().unwrap()) as usize;
    assert_eq!(stl.len(), 84 + 50 * n);
    let mut vol = 0.0;
    let mut edges = std::collections::HashMap::new();
    let key = |p: [f32; 3]| (p[0].to_bits(), p[1].to_bits(), p[2].to_bits());
    for t in 0..n {
        let b = &stl[84 + 50 * t..84 + 50 * t + 50];
        let f = |o: usize| f32::from_le_bytes(b[o..o + 4].try_into().unwrap());
        let v: Vec<[f32; 3]> = (0..3)
            .map(|k| [f(12 + 12 * k), f(16 + 12 * k), f(20 + 12 * k)])
            .collect();
        let a = Vector3::new(v[0][0] as f64, v[0][1] as f64, v[0][2] as f64);
        let bb = Vector3::new(v[1][0] as f64, v[1][1] as f64, v[1][2] as f64);
        let c = Vector3::new(v[2][0] as f64, v[2][1] as f64, v[2][2] as f64);
        vol += a.dot(&bb.cross(&c)) / 6.0;
        for k in 0..3 {
            *edges.entry((key(v[k]), key(v[(k + 1) % 3]))).or_insert(0i32) += 1;
        }
    }
    for ((a, b), c) in &edges {
        let back = edges.get(&(*b, *a)).copied().unwrap_or(0);
        assert_eq!(*c, back, "edge {a:?} → {b:?}");
    }
    vol
}

#[test]
fn the_stl_of_a_milled_bar_is_closed_and_holds_its_volume() {
    let mut s = bar(20.0, 60.0, 0.2);
    s.cut(&sweep(
        &flat(16.0, 30.0),
        [1.0, 0.0, 0.0],
        [15.0, -30.0, 30.0],
        [15.0, 30.0, 30.0],
        0.2,
    ));
    let vol = closed_stl_volume(&s.stl().unwrap());
    // The mesh runs between the first and last column centres: about one column short.
    let want = s.volume();
    assert!((vol - want).abs() < 0.02 * want, "mesh {vol} vs grid {want}");
}

#[test]
fn a_block_milled_on_two_faces_loses_both_pockets() {
    let mut s = Stock::block(Vector3::zeros(), Vector3::new(300.0, 300.0, 200.0), 256, 0.5).unwrap();
    let v0 = s.volume();
    // Top face (z = 200): a Ø14 mill 5 deep along x from 50 to 250 at y 150.
    let c = flat(14.0, 30.0);
    s.cut(&sweep(
        &c,
        [0.0, 0.0, 1.0],
        [50.0, 150.0, 195.0],
        [250.0, 150.0, 195.0],
        0.5,
    ));
    // Side face (x = 300): a Ø6 mill 3 deep along y.
    let c6 = flat(6.0, 30.0);
    s.cut(&sweep(
        &c6,
        [1.0, 0.0, 0.0],
        [297.0, 50.0, 100.0],
        [297.0, 250.0, 100.0],
        0.5,
    ));
    let want = (200.0 * 14.0 + PI * 49.0) * 5.0 + (200.0 * 6.0 + PI * 9.0) * 3.0;
    let got = v0 - s.volume();
    assert!((got - want).abs() < 0.05 * want, "removed {got}, closed form {want}");
}

/// A random cutter of every kind, and a random move of it near a Ø40 bar.
fn random_sweeps(n: usize) -> Vec<Sweep> {
    let mut rnd = crate::test_util::unit_random(987_654_321u64);
    let mut out = Vec::new();
    while out.len() < n {
        let d = 2.0 + 14.0 * rnd();
        let l = d + 30.0 * rnd();
        let kind = match (rnd() * 4.0) as u32 {
            0 => CutterKind::Flat,
            1 => CutterKind::Ball,
            2 => CutterKind::Bull {
                corner_radius: d / 2.0 * (0.1 + 0.8 * rnd()),
            },
            _ => CutterKind::Drill {
                point_angle_deg: 90.0 + 50.0 * rnd(),
            },
        };
        let c = Cutter::new(kind, d, l).unwrap();
        let mut p = || Vector3::new(60.0 * rnd() - 30.0, 60.0 * rnd() - 30.0, 40.0 * rnd());
        let (a, b) = (p(), p());
        // Half of the moves short, as a C turn's chords are.
        let b = if rnd() < 0.5 { a + (b - a) * 0.05 } else { b };
        let axis = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
        if let Some(sw) = Sweep::new(&c, axis, a, b, 0.02 + 0.1 * rnd()) {
            out.push(sw);
        }
    }
    out
}

#[test]
fn a_ray_skipping_pieces_by_their_bounds_meets_the_sweep_where_every_piece_does() {
    // Oracle: every piece measured exactly. The skips (a piece whose outer bound lies within
    // the interval so far, a ray that misses the hull) may never change the answer.
    let mut rnd = crate::test_util::unit_random(42u64);
    let mut hits = 0;
    for sw in random_sweeps(300) {
        for _ in 0..200 {
            // Rays from the axis outward (the cylindrical grid's) and along a random direction
            // through the sweep's box (a face grid's).
            let (o, u) = if rnd() < 0.5 {
                let th = std::f64::consts::TAU * rnd();
                (
                    Vector3::new(0.0, 0.0, 40.0 * rnd()),
                    Vector3::new(th.cos(), th.sin(), 0.0),
                )
            } else {
                let m = sw.min + (sw.max - sw.min).component_mul(&Vector3::new(rnd(), rnd(), rnd()));
                let u = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
                (m - 30.0 * u, u)
            };
            let (t0, t1) = (0.0, 60.0 * rnd());
            let got = sw.ray(o, u, t0, t1);
            let want = sw.ray_every_piece(o, u, t0, t1);
            match (got, want) {
                (Some(g), Some(w)) => {
                    hits += 1;
                    assert!((g.0 - w.0).abs() < 1e-9 && (g.1 - w.1).abs() < 1e-9, "{g:?} vs {w:?}");
                }
                (None, None) => {}
                _ => panic!("{got:?} vs {want:?}: ray {o:?} {u:?} on {sw:?}"),
            }
        }
    }
    assert!(hits > 5000, "the rays must meet the sweeps often: {hits}");
}

#[test]
fn the_arc_of_nodes_a_sweep_can_reach_holds_every_node_whose_ray_meets_it() {
    // Oracle: every node of every column under the sweep, each ray cast against it.
    let g = CylGrid::new(0.0, 1.0, 40, 360, |_| Some((0.0, 40.0)));
    let mut narrower = 0;
    for sw in random_sweeps(200) {
        let arcs = g.sweep_angles(&sw);
        let inside = |i: usize| arcs.iter().any(|&(a, b)| (a..=b).contains(&i));
        let Some((j0, j1)) = g.columns(sw.min.z, sw.max.z) else {
            continue;
        };
        for j in j0..=j1 {
            for i in 0..g.nth {
                let th = g.theta(i);
                let u = Vector3::new(th.cos(), th.sin(), 0.0);
                if sw.ray(Vector3::new(0.0, 0.0, g.z(j)), u, 0.0, 100.0).is_some() {
                    assert!(
                        inside(i),
                        "node {i} of column {j} meets the sweep outside {arcs:?}: {sw:?}"
                    );
                }
            }
        }
        let width = |v: &[(usize, usize)]| v.iter().map(|&(a, b)| b - a + 1).sum::<usize>();
        if width(&arcs) < width(&g.angles(&sw.min, &sw.max)) {
            narrower += 1;
        }
    }
    assert!(
        narrower > 50,
        "the sweep's own arc is narrower than its box's on most moves: {narrower}"
    );
}

#[test]
fn air_along_a_ray_asks_each_sample_once_and_answers_as_every_sample_in_order_does() {
    // Oracle: every sample from the near end on. The coarse-to-fine order may only change how
    // soon material is met.
    use std::cell::RefCell;
    for n in [1usize, 2, 3, 7, 8, 9, 100, 257] {
        for pattern in 0..40u64 {
            // Material on a stretch of samples (none for pattern 0).
            let (from, len) = (
                (pattern * 7919) as usize % n,
                (pattern as usize % 5) * (pattern as usize % 3),
            );
            let solid = |k: usize| pattern != 0 && k >= from && k < from + len;
            let asked = RefCell::new(Vec::new());
            let air = |p: Vector3<f64>| {
                let k = (p.x - 0.5).round() as usize;
                asked.borrow_mut().push(k);
                !solid(k)
            };
            let got = face::air_along(
                Vector3::zeros(),
                Vector3::x(),
                0.0,
                n as f64,
                1.0,
                &air,
                &face::anywhere,
            );
            assert_eq!(got, (0..n).all(|k| !solid(k)), "n {n}, pattern {pattern}");
            // Told where material may be (the stretch, or nowhere), it answers the same.
            let near = |_: Vector3<f64>, _: Vector3<f64>, _: f64, _: f64| {
                (len > 0 && pattern != 0).then_some((from as f64, (from + len) as f64))
            };
            let told = face::air_along(
                Vector3::zeros(),
                Vector3::x(),
                0.0,
                n as f64,
                1.0,
                &|p| !solid((p.x - 0.5).round() as usize),
                &near,
            );
            assert_eq!(told, got, "n {n}, pattern {pattern}: with a span");
            let mut seen = asked.into_inner();
            let len = seen.len();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), len, "n {n}: a sample asked twice");
            if got {
                assert_eq!(len, n, "n {n}: every sample asked when all are air");
            }
        }
    }
}

/// The floor an end of each shape leaves when plunged along its axis into a block's top face
/// (z = 0), read at radius `rho` from the plunge's axis: where the material begins below the
/// face, by bisection on [`Stock::contains`] down the line (x = rho, y = 0).
fn floor_depth(s: &Stock, rho: f64) -> f64 {
    let (mut air, mut mat) = (0.0f64, 12.0f64);
    assert!(s.contains(Vector3::new(rho, 0.0, -mat)));
    for _ in 0..40 {
        let mid = (air + mat) / 2.0;
        if s.contains(Vector3::new(rho, 0.0, -mid)) {
            mat = mid;
        } else {
            air = mid;
        }
    }
    (air + mat) / 2.0
}

/// A 20 × 20 × 20 block under the top face at z = 0, 0.05 mm nodes, cut by `cutter` plunged from
/// 5 mm above to `depth` below the face at the origin (its axis +z).
fn plunged(cutter: Cutter, depth: f64) -> Stock {
    let mut s = Stock::block(
        Vector3::new(-10.0, -10.0, -20.0),
        Vector3::new(10.0, 10.0, 0.0),
        400,
        0.01,
    )
    .unwrap();
    let sw = sweep(&cutter, [0.0, 0.0, 1.0], [0.0, 0.0, 5.0], [0.0, 0.0, -depth], 0.01);
    assert!(s.cut(&sw) > 0.0);
    s
}

/// Hand-worked: a Ø10 ball plunged 2 mm has its centre 3 mm above the floor's lowest point, so
/// the dimple's depth at radius ρ is 2 − 5 + √(25 − ρ²): 2 at the centre, 1 at ρ = 3, 0 at ρ = 4
/// (its rim on the face); a flat end of the same size would leave 2 everywhere out to ρ = 5.
#[test]
fn a_ball_end_plunged_2_mm_leaves_a_spherical_dimple() {
    let s = plunged(Cutter::new(CutterKind::Ball, 10.0, 20.0).unwrap(), 2.0);
    for (rho, want) in [
        (0.0, 2.0),
        (2.0, 2.0 - 5.0 + 21.0f64.sqrt()),
        (3.0, 1.0),
        (3.5, 2.0 - 5.0 + 12.75f64.sqrt()),
    ] {
        let d = floor_depth(&s, rho);
        assert!((d - want).abs() < 0.06, "ρ {rho}: depth {d}, worked {want}");
    }
    // Past the rim the face is uncut.
    assert!(floor_depth(&s, 4.3) < 0.01);
    // The cap's volume, πh²(3r − h)/3 = 52π/3 = 54.45 mm³ (face grids along z see it once).
    let top = &s.faces.iter().find(|f| f.n.z < -0.5).unwrap();
    let v = top.removed();
    assert!((v - 52.0 * PI / 3.0).abs() < 0.04 * v, "{v}");
}

/// Hand-worked: a Ø10 drill with a 90° point plunged 3 mm leaves a cone: depth 3 − ρ (ρ < 3);
/// with 118° the cone is flatter: 3 − ρ / tan 59°, out to ρ = 3 tan 59° = 4.99.
#[test]
fn a_drill_point_plunged_leaves_a_cone() {
    let s = plunged(
        Cutter::new(CutterKind::Drill { point_angle_deg: 90.0 }, 10.0, 20.0).unwrap(),
        3.0,
    );
    for (rho, want) in [(0.0, 3.0), (1.0, 2.0), (2.5, 0.5)] {
        let d = floor_depth(&s, rho);
        assert!((d - want).abs() < 0.06, "90°, ρ {rho}: depth {d}, worked {want}");
    }
    assert!(floor_depth(&s, 3.3) < 0.01);
    let k = 59.0f64.to_radians().tan();
    let s = plunged(
        Cutter::new(CutterKind::Drill { point_angle_deg: 118.0 }, 10.0, 20.0).unwrap(),
        3.0,
    );
    for rho in [0.0, 1.0, 2.0, 4.0] {
        let (d, want) = (floor_depth(&s, rho), 3.0 - rho / k);
        assert!((d - want).abs() < 0.06, "118°, ρ {rho}: depth {d}, worked {want}");
    }
}

/// Hand-worked: a Ø10 bull nose with 2 mm corners plunged 1 mm leaves a floor 1 deep out to
/// ρ = 3, then the corner: depth 1 − 2 + √(4 − (ρ − 3)²), 0.732 at ρ = 4, 0 at ρ = 3 + √3.
#[test]
fn a_bull_nose_plunged_leaves_a_flat_floor_and_its_corner() {
    let s = plunged(
        Cutter::new(CutterKind::Bull { corner_radius: 2.0 }, 10.0, 20.0).unwrap(),
        1.0,
    );
    for (rho, want) in [
        (0.0, 1.0),
        (2.9, 1.0),
        (4.0, 3.0f64.sqrt() - 1.0),
        (4.5, 1.75f64.sqrt() - 1.0),
    ] {
        let d = floor_depth(&s, rho);
        assert!((d - want).abs() < 0.06, "ρ {rho}: depth {d}, worked {want}");
    }
    assert!(floor_depth(&s, 3.0 + 3.0f64.sqrt() + 0.2) < 0.01);
}

/// `CylGrid::may_hold` is what lets the air checks and the stock query skip samples: a sample it
/// leaves out must be air by the grid. Oracle: every point of many rays, asked one by one, on a
/// stepped, bored and milled grid (rays across, along and through the axis, grazing and missing).
/// A stepped and bored Ø40 bar with a flat and a cross hole, which lower some nodes' R below
/// their column's.
fn stepped_bored_milled() -> Stock {
    let mut s = Stock::turned(-10.0, 70.0, 20.0, 0.1, |z| {
        Some((if z > 40.0 { 6.0 } else { 0.0 }, if z < 20.0 { 20.0 } else { 12.0 }))
    })
    .unwrap();
    // A flat and a cross hole lower some nodes' R below their column's.
    s.cut(&sweep(
        &flat(10.0, 30.0),
        [1.0, 0.0, 0.0],
        [15.0, -30.0, 5.0],
        [15.0, 30.0, 5.0],
        0.1,
    ));
    s.cut(&sweep(
        &flat(6.0, 30.0),
        [0.0, 1.0, 0.0],
        [0.0, 30.0, 30.0],
        [0.0, 4.0, 30.0],
        0.1,
    ));
    s
}

#[test]
fn the_cylindrical_grids_reach_leaves_out_no_material_point() {
    let s = stepped_bored_milled();
    let c = s.cyl.as_ref().unwrap();
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut checked, mut inside, mut skipped) = (0usize, 0usize, 0usize);
    for k in 0..3000 {
        let o = Vector3::new(60.0 * next() - 30.0, 60.0 * next() - 30.0, 100.0 * next() - 20.0);
        let u = match k % 4 {
            0 => Vector3::new(next() - 0.5, next() - 0.5, 0.0),
            1 => Vector3::new(0.0, 0.0, 1.0),
            2 => Vector3::new(-o.x, -o.y, 0.0),
            _ => Vector3::new(next() - 0.5, next() - 0.5, next() - 0.5),
        };
        let Some(u) = u.try_normalize(1e-9) else { continue };
        let (a, b) = (-10.0 * next(), 80.0 * next());
        let span = c.may_hold(o, u, a, b);
        for i in 0..=400 {
            let t = (a + (b - a) * i as f64 / 400.0).clamp(a, b);
            let p = o + t * u;
            checked += 1;
            if c.contains(p) {
                inside += 1;
                let (lo, hi) = span.unwrap_or_else(|| panic!("ray {k}: material at t {t}, span None"));
                assert!(t >= lo && t <= hi, "ray {k}: material at t {t} outside [{lo}, {hi}]");
            } else if span.map_or(true, |(lo, hi)| t < lo || t > hi) {
                skipped += 1;
            }
        }
    }
    // The rays meet material and the span leaves most of the air out.
    assert!(
        inside > 10_000 && skipped > checked / 3,
        "{inside} {skipped} of {checked}"
    );
}

/// `CylGrid::surely_holds` is what lets the stock query take samples as material without asking
/// the grid: every point it answers for must be material by the grid. Oracle: every point of
/// many rays asked one by one, on the stepped, bored and milled grid turned down in part
/// (rays across, along and through the axis); and it answers for most of the material.
#[test]
fn the_cylindrical_grid_surely_holds_only_material() {
    let mut s = stepped_bored_milled();
    s.cyl.as_mut().unwrap().turn(50.0, 60.0, 9.0);
    let c = s.cyl.as_ref().unwrap();
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut inside, mut sure) = (0usize, 0usize);
    for k in 0..3000 {
        let o = Vector3::new(60.0 * next() - 30.0, 60.0 * next() - 30.0, 100.0 * next() - 20.0);
        let u = match k % 4 {
            0 => Vector3::new(next() - 0.5, next() - 0.5, 0.0),
            1 => Vector3::new(0.0, 0.0, 1.0),
            2 => Vector3::new(-o.x, -o.y, 0.0),
            _ => Vector3::new(next() - 0.5, next() - 0.5, 0.05 * (next() - 0.5)),
        };
        let Some(u) = u.try_normalize(1e-9) else { continue };
        let (a, b) = (-10.0 * next(), 80.0 * next());
        let span = c.surely_holds(o, u, a, b);
        if let Some((lo, hi)) = span {
            assert!(
                a <= lo && lo <= hi && hi <= b,
                "ray {k}: [{lo}, {hi}] outside [{a}, {b}]"
            );
        }
        for i in 0..=400 {
            let t = (a + (b - a) * i as f64 / 400.0).clamp(a, b);
            let p = o + t * u;
            let held = c.contains(p);
            inside += usize::from(held);
            if span.is_some_and(|(lo, hi)| t >= lo && t <= hi) {
                assert!(held, "ray {k}: t {t} answered for, not material");
                sure += 1;
            }
        }
    }
    assert!(sure > inside / 3, "{sure} of {inside}");
}

/// The cylindrical grid writes out a column's nodes only when a cut changes one of them: a bar
/// whose flat spans a few columns holds those columns' nodes, and every node reads as before
/// (the uniform radius elsewhere, turned down by a turning pass without writing it out).
#[test]
fn the_cylindrical_grid_writes_out_only_the_columns_a_cut_reaches() {
    let mut s = bar(20.0, 60.0, 0.1);
    let c = s.cyl.as_ref().unwrap();
    let (nth, nz) = (c.nth, c.nz);
    let empty = c.bytes();
    assert!(empty < nz * 64, "{empty} bytes before any cut");
    s.cut(&sweep(
        &flat(8.0, 30.0),
        [1.0, 0.0, 0.0],
        [15.0, -30.0, 30.0],
        [15.0, 30.0, 30.0],
        0.1,
    ));
    let c = s.cyl.as_mut().unwrap();
    let written = (c.bytes() - empty) / 8;
    assert!(
        written >= nth && written % nth == 0 && written / nth < nz / 4,
        "{written} nodes of {nth} × {nz}"
    );
    let (j_far, j_flat) = (nz / 8, nz / 2);
    assert!((0..nth).all(|i| c.radius(i, j_far) == 20.0));
    let low = |c: &CylGrid| (0..nth).map(|i| c.radius(i, j_flat)).fold(f64::INFINITY, f64::min);
    assert!(low(c) < 15.1, "{}", low(c));
    // A turning pass lowers a column that was never written out, and one that was.
    c.turn(0.0, 60.0, 18.0);
    assert!((0..nth).all(|i| c.radius(i, j_far) == 18.0));
    assert!((0..nth).all(|i| c.radius(i, j_flat) <= 18.0));
    assert!(low(c) < 15.1, "{}", low(c));
}

/// Every node of every grid, as bits.
fn node_bits(s: &Stock) -> Vec<u64> {
    let mut out = Vec::new();
    if let Some(c) = &s.cyl {
        for j in 0..c.nz {
            out.extend(c.column(j).iter().map(|r| r.to_bits()));
            out.push(c.col_max[j].to_bits());
        }
    }
    for f in &s.faces {
        out.extend(f.d.iter().map(|d| d.to_bits()));
    }
    out
}

/// Moves of a face pocket near and through the spindle axis (axis along ±z, fed square to it
/// as polar interpolation's chords are, short and long, some through the axis, some standing
/// still on it), with a few others (tilted, plunging, radial; ball and drill ends).
fn sweeps_at_the_axis(n: usize, seed: u64) -> Vec<Sweep> {
    let mut rnd = crate::test_util::unit_random(seed);
    let mut out = Vec::new();
    while out.len() < n {
        let d = 2.0 + 10.0 * rnd();
        let kind = match (rnd() * 8.0) as u32 {
            0 => CutterKind::Ball,
            1 => CutterKind::Drill { point_angle_deg: 118.0 },
            2 => CutterKind::Tap { pitch: 0.5 },
            _ => CutterKind::Flat,
        };
        let c = Cutter::new(kind, d, d + 20.0 * rnd()).unwrap();
        let z = 20.0 - 8.0 * rnd();
        let near = |(rho, th): (f64, f64)| {
            let th = std::f64::consts::TAU * th;
            Vector3::new(8.0 * rho * th.cos(), 8.0 * rho * th.sin(), z)
        };
        let a = near((rnd(), rnd()));
        let other = near((rnd(), rnd()));
        let b = match (rnd() * 7.0) as u32 {
            // Standing on the axis (a C turn there), or still anywhere.
            0 => Vector3::new(0.0, 0.0, z),
            1 => a,
            // Through the axis.
            2 => Vector3::new(-a.x, -a.y, z),
            // A short chord.
            3 => a + (other - a) * 0.05,
            // Plunging, or ramping across the face, down or up.
            4 => a - Vector3::new(0.0, 0.0, 3.0 * rnd()),
            5 => other + Vector3::new(0.0, 0.0, 6.0 * rnd() - 3.0),
            _ => other,
        };
        let a = if rnd() < 0.1 { Vector3::new(0.0, 0.0, z) } else { a };
        let axis = match (rnd() * 10.0) as u32 {
            0 => Vector3::new(0.0, 0.0, -1.0),
            1 => Vector3::new(0.1 * rnd(), 0.1 * rnd(), 1.0),
            2 => Vector3::new(1.0, 0.0, 0.0),
            _ => Vector3::z(),
        };
        let (a, b) = if axis.z < 0.0 {
            // From below: the tip under the part's back.
            (a - Vector3::new(0.0, 0.0, 17.0), b - Vector3::new(0.0, 0.0, 17.0))
        } else {
            (a, b)
        };
        if let Some(sw) = Sweep::new(&c, axis, a, b, 0.05) {
            out.push(sw);
        }
        // Now and then a pass of a pocket: chords of one line at one depth, each a little past
        // the one before (polar interpolation's), toward the axis and through it.
        if rnd() < 0.3 {
            let mill = flat(4.0 + 8.0 * rnd(), 20.0);
            let (from, to) = (near((rnd(), rnd())), near((rnd(), rnd())));
            let to = Vector3::new(-from.x, -from.y, from.z) + (to - from) * 0.1;
            let chords = 10 + (rnd() * 20.0) as usize;
            for k in 0..chords {
                let at = |f: f64| from + (to - from) * f;
                let (f0, f1) = (k as f64 / chords as f64, (k + 1) as f64 / chords as f64);
                out.extend(Sweep::new(&mill, Vector3::z(), at(f0), at(f1), 0.05));
            }
        }
    }
    out
}

#[test]
fn the_memo_and_the_known_exits_cut_the_nodes_every_ray_cast_cuts() {
    // Oracle: the same cuts with every ray cast. Nodes, volumes removed and changed columns bit
    // for bit; the cylindrical grid's memo answers many of its rays (those under a flat end mill
    // fed across its axis), and the face grid leaves most of its nodes the pocket's earlier
    // moves already cut to their exit.
    for (seed, bore) in [(7u64, 0.0), (8, 0.0), (9, 2.5)] {
        let stock = || Stock::turned(0.0, 20.0, 10.0, 0.2, |_| Some((bore, 10.0))).unwrap();
        let (mut fast, mut slow) = (stock(), stock());
        for (k, sw) in sweeps_at_the_axis(60, seed).iter().enumerate() {
            let (a, b) = (fast.cut(sw), slow.cut_casting_every_ray(sw));
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "seed {seed}, cut {k}: removed {a} against {b}"
            );
            assert!(node_bits(&fast) == node_bits(&slow), "seed {seed}, cut {k}: {sw:?}");
        }
        let cyl = |s: &Stock| s.cyl.as_ref().unwrap().rays;
        let (f, s) = (cyl(&fast), cyl(&slow));
        assert!(
            f * 5 < s * 4,
            "seed {seed}: {f} rays of the cylindrical grid cast against {s}"
        );
        let face = |s: &Stock| s.faces.iter().map(|f| f.rays).sum::<u64>();
        let (f, s) = (face(&fast), face(&slow));
        assert!(f < s, "seed {seed}: {f} rays of the face grid cast against {s}");
    }
}

#[test]
fn a_retract_along_its_plunge_cuts_what_casting_every_ray_cuts() {
    // Radial drills at several angles into a bar (each gets a side grid across its axis, and
    // every grid sees every drill), each plunge followed by its retract, then a deeper one and
    // its retract. Oracle: the same cuts with every ray cast; the same nodes, bit for bit, after
    // each cut. A retract is its plunge's sweep (`Sweep::new` keeps the lesser end first), so
    // the face grids cast no ray for it, yet some retracts still remove material: nodes the
    // plunge left for the material another grid held above them, that grid cut by the plunge
    // after them.
    let drill = Cutter::new(CutterKind::Drill { point_angle_deg: 118.0 }, 6.0, 40.0).unwrap();
    let (mut fast, mut slow) = (bar(20.0, 40.0, 0.2), bar(20.0, 40.0, 0.2));
    let face_rays = |s: &Stock| s.faces.iter().map(|f| f.rays).sum::<u64>();
    let mut retraced = 0.0;
    for (k, deg) in [0.0f64, 45.0, 90.0, 135.0, 30.0, 60.0].iter().enumerate() {
        let (c, s) = (deg.to_radians().cos(), deg.to_radians().sin());
        let at = |r: f64| [r * c, r * s, 8.0 + 5.0 * k as f64];
        let axis = [c, s, 0.0];
        assert!(sweep(&drill, axis, at(30.0), at(12.0), 0.05).same_bits(&sweep(
            &drill,
            axis,
            at(12.0),
            at(30.0),
            0.05
        )));
        for (from, to) in [(30.0, 12.0), (12.0, 30.0), (30.0, 3.0), (3.0, 30.0)] {
            let sw = sweep(&drill, axis, at(from), at(to), 0.05);
            let rays = face_rays(&fast);
            let (a, b) = (fast.cut(&sw), slow.cut_casting_every_ray(&sw));
            assert_eq!(
                a.to_bits(),
                b.to_bits(),
                "drill {k}, {from} to {to}: removed {a} against {b}"
            );
            assert!(node_bits(&fast) == node_bits(&slow), "drill {k}, {from} to {to}");
            if from < to {
                assert_eq!(face_rays(&fast), rays, "drill {k}: the retract to {to} cast face rays");
                retraced += a;
            }
        }
    }
    assert!(
        retraced > 0.0,
        "no retract removed anything: the nodes asked again are never air"
    );
    assert!(face_rays(&fast) < face_rays(&slow));
}

#[test]
fn a_sweep_repeated_in_a_run_is_cut_once_it_changes_nothing() {
    // A C turn with the tip on the spindle axis: the same sweep for every chord. Oracle: every
    // chord cut; the same stock, bit for bit, after each chord, with far fewer rays.
    let c = flat(10.0, 30.0);
    let (mut run_cut, mut each) = (bar(25.0, 20.0, 0.2), bar(25.0, 20.0, 0.2));
    let mut run = CutRun::default();
    let mut chords = Vec::new();
    // A pass up to the axis, the turn on it (36 identical sweeps), a pass away from it.
    for k in 0..5 {
        let x = 12.0 - 3.0 * k as f64;
        chords.push(sweep(&c, [0.0, 0.0, 1.0], [x, 0.0, 17.0], [x - 3.0, 0.0, 17.0], 0.05));
    }
    chords.extend((0..36).map(|_| sweep(&c, [0.0, 0.0, 1.0], [0.0, 0.0, 17.0], [0.0, 0.0, 17.0], 0.05)));
    chords.push(sweep(&c, [0.0, 0.0, 1.0], [0.0, 0.0, 17.0], [0.0, -12.0, 17.0], 0.05));
    chords.extend((0..3).map(|_| sweep(&c, [0.0, 0.0, 1.0], [0.0, -12.0, 17.0], [0.0, -12.0, 17.0], 0.05)));
    for (k, sw) in chords.iter().enumerate() {
        let (a, b) = (run_cut.cut_in_run(sw, &mut run), each.cut(sw));
        assert_eq!(a.to_bits(), b.to_bits(), "chord {k}");
        assert!(node_bits(&run_cut) == node_bits(&each), "chord {k}");
    }
    assert!(
        run_cut.rays() * 2 < each.rays(),
        "{} rays against {}",
        run_cut.rays(),
        each.rays()
    );
    // Only a sweep that changed nothing is left out when it comes again: one that cut is cut
    // again (it may cut more where its first cut opened the way), then no more.
    let sw = sweep(&c, [0.0, 0.0, 1.0], [20.0, 0.0, 17.0], [20.0, 0.0, 17.0], 0.05);
    let mut run = CutRun::default();
    assert!(run_cut.cut_in_run(&sw, &mut run) > 0.0);
    let mut rays = run_cut.rays();
    let mut again = 0;
    while run_cut.cut_in_run(&sw, &mut run) > 0.0 {
        again += 1;
        assert!(again < 5, "a cut repeated comes to rest");
        rays = run_cut.rays();
    }
    assert!(run_cut.rays() > rays, "cut again after a cut that changed something");
    let rays = run_cut.rays();
    assert_eq!(run_cut.cut_in_run(&sw, &mut run), 0.0);
    assert_eq!(run_cut.rays(), rays, "left out after one that changed nothing");
}

#[test]
fn a_rays_answer_from_the_memo_is_the_answer_cast() {
    // Oracle: `Sweep::ray`. Rays at one angle, one height after another, share a memo (as a cut's
    // columns do), with bores and ends from a few values: every answer the memo gives is the
    // cast one, bit for bit, on sweeps level or not (ramps, plunges, tilted axes, balls).
    let mut memo_hits = 0;
    for (k, sw) in sweeps_at_the_axis(400, 11).iter().enumerate() {
        for a in 0..24 {
            let th = std::f64::consts::TAU * (a as f64 + 0.37) / 24.0;
            let u = Vector3::new(th.cos(), th.sin(), 0.0);
            let mut memo = None;
            for h in 0..60 {
                let o = Vector3::new(0.0, 0.0, sw.min.z - 1.0 + h as f64 * 0.5);
                let (t0, t1) = ([0.0, 2.5][h % 2 * (k % 2)], [10.0, 7.5, 12.0][(h / 7 + k) % 3]);
                let want = sw.ray(o, u, t0, t1);
                let (got, cast) = sw.ray_memo(o, u, t0, t1, &mut memo);
                memo_hits += usize::from(!cast);
                let bits = |x: Option<(f64, f64)>| x.map(|(a, b)| (a.to_bits(), b.to_bits()));
                assert_eq!(bits(got), bits(want), "sweep {k}, angle {a}, height {h}: {sw:?}");
            }
        }
    }
    assert!(memo_hits > 100_000, "the memo answers: {memo_hits}");
}

/// A turned part's front face grid starts each node's material at the frontmost column that
/// holds its radius: the same depths as scanning every column from the front, on a profile of
/// steps, a bore and an empty stretch over hundreds of columns (blocks of columns passed over
/// whole where none holds the radius).
#[test]
fn a_turned_parts_face_starts_at_the_frontmost_column_holding_each_radius() {
    let profile = |z: f64| -> Option<(f64, f64)> {
        match z {
            z if z > 95.0 => Some((4.0, 6.0)),
            z if z > 80.0 => None,
            z if z > 60.0 => Some((3.0, 12.0)),
            z if z > 20.0 => Some((0.0, 9.0 + (z * 0.7).sin())),
            _ => Some((0.0, 15.0)),
        }
    };
    let s = Stock::turned(0.0, 100.0, 15.0, 0.1, profile).unwrap();
    let c = s.cyl.as_ref().unwrap();
    let g = &s.faces[0];
    assert!(c.nz > 512, "{} columns", c.nz);
    let mut held = 0;
    for j in 0..g.nv {
        for i in 0..g.nu {
            let p = g.node(i, j);
            let rho = p.x.hypot(p.y);
            let want = (0..c.nz)
                .rev()
                .find(|&k| profile(c.z(k)).is_some_and(|(ri, ro)| rho >= ri && rho <= ro))
                .map_or(g.thickness, |k| {
                    (100.0 - (c.z0 + (k as f64 + 1.0) * c.dz)).clamp(0.0, g.thickness)
                });
            assert_eq!(
                g.depth(i, j).to_bits(),
                want.to_bits(),
                "node ({i}, {j}) at radius {rho}"
            );
            held += usize::from(want < g.thickness);
        }
    }
    assert!(held > 1000, "{held}");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(20_000))]

    /// The grids' inline floor and ceiling are `f64::floor` and `f64::ceil` bit for bit: any bit pattern (NaNs, infinities,
    /// subnormals, signed zeros, whole numbers past 2^52), and values within a few units of
    /// rounding of a whole number, where truncation and flooring part.
    #[test]
    fn the_inline_floor_and_ceil_are_f64s_bit_for_bit(bits in proptest::prelude::any::<u64>(), k in -1e6f64..1e6, ulps in -4i64..=4) {
        let x = f64::from_bits(bits);
        let y = f64::from_bits((k.round().to_bits() as i64 + ulps) as u64);
        for v in [x, y, -y, x / 1e300, k] {
            for (fast, slow) in [(super::floor(v), v.floor()), (super::ceil(v), v.ceil())] {
                proptest::prop_assert!(
                    fast.to_bits() == slow.to_bits() || (fast.is_nan() && slow.is_nan()),
                    "{v:e}: {fast:e} against {slow:e}"
                );
            }
        }
    }
}

/// A node angle's direction is its cosine and sine as `sin_cos` gives them, bit for bit, before
/// a cut has made the table of them and after (the stock queries take it from there, the cuts
/// compute it the other way round).
#[test]
fn a_node_angles_direction_is_its_sin_cos_with_the_table_or_without() {
    let mut s = bar(20.0, 30.0, 0.1);
    let same = |s: &Stock| {
        let c = s.cyl.as_ref().unwrap();
        (0..c.nth).all(|i| {
            let (sin, cos) = c.theta(i).sin_cos();
            let (x, y) = c.direction(i);
            x.to_bits() == cos.to_bits() && y.to_bits() == sin.to_bits()
        })
    };
    assert!(same(&s));
    assert!(s.cyl.as_ref().unwrap().dirs.is_empty());
    s.cut(&sweep(
        &flat(16.0, 30.0),
        [1.0, 0.0, 0.0],
        [15.0, -30.0, 15.0],
        [15.0, 30.0, 15.0],
        0.1,
    ));
    assert!(!s.cyl.as_ref().unwrap().dirs.is_empty(), "the cut made the table");
    assert!(same(&s));
}
