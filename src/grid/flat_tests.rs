//! Flat faces across the axis written as one polygon each (`flat_faces.rs`): the surface stays
//! closed and facing out, holds the same volume and area, and has fewer triangles.

use super::flat_faces::{self, FlatFaces};
use super::mesh::{self, Surface};
use super::tests::{bar, closed_stl_volume, flat, sweep};
use super::*;
use nalgebra::Vector3;
use std::collections::{HashMap, HashSet};

fn area(m: &Surface) -> f64 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| Vector3::from(m.vertices[i as usize]));
            (b - a).cross(&(c - a)).norm() / 2.0
        })
        .sum()
}

/// Every edge run once each way by the triangles (by vertex index), and no triangle of no area.
fn assert_closed(m: &Surface) {
    let mut runs: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &m.triangles {
        let [a, b, c] = t.map(|i| Vector3::from(m.vertices[i as usize]));
        assert!((b - a).cross(&(c - a)).norm() > 0.0, "a triangle of no area: {t:?}");
        for k in 0..3 {
            *runs.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &runs {
        assert_eq!(n, 1, "edge {a} → {b} run {n} times");
        assert_eq!(runs.get(&(b, a)), Some(&1), "edge {a} → {b} has no partner");
    }
}

/// The lattice's surface of `s` and the same surface merged: both closed, the same volume and
/// area, fewer triangles after.
fn merged(s: &Stock, cells: usize) -> (Surface, Surface, FlatFaces) {
    let (raw, h) = mesh::lattice(s, cells).expect("a surface");
    // The pictures' merge (points left where they were) makes the same triangles.
    let mut kept_points = raw.clone();
    let pictures = flat_faces::merge(&mut kept_points, mesh::PLANE_TOL * h, false);
    assert_closed(&kept_points);
    let mut m = raw.clone();
    let got = flat_faces::merge(&mut m, mesh::PLANE_TOL * h, true);
    assert_eq!(pictures, got);
    assert!(
        kept_points.triangles == m.triangles,
        "the same triangles, snapped or not"
    );
    assert_eq!(got.triangles_before, raw.triangles.len());
    assert_closed(&raw);
    assert_closed(&m);
    let (v0, v1) = (raw.volume(), m.volume());
    assert!(v0 > 0.0 && (v1 - v0).abs() < 1e-7 * v0, "volume {v1} against {v0}");
    let (a0, a1) = (area(&raw), area(&m));
    assert!((a1 - a0).abs() < 1e-7 * a0, "area {a1} against {a0}");
    // The STL (f32 points) is closed too and holds the same volume.
    let (s0, s1) = (closed_stl_volume(&raw.stl()), closed_stl_volume(&m.stl()));
    assert!((s1 - s0).abs() < 1e-5 * s0, "STL volume {s1} against {s0}");
    if got.merged > 0 {
        assert!(m.triangles.len() < raw.triangles.len());
    }
    (raw, m, got)
}

/// The planes across the axis the merged surface holds (every point of a triangle at one z),
/// lowest first, with their triangles and points.
fn planes(m: &Surface) -> Vec<(f64, usize, usize)> {
    let mut by_z: HashMap<u64, (usize, HashSet<u32>)> = HashMap::new();
    for t in &m.triangles {
        let z = m.vertices[t[0] as usize][2];
        if t.iter().all(|&i| m.vertices[i as usize][2] == z) {
            let e = by_z.entry(z.to_bits()).or_default();
            e.0 += 1;
            e.1.extend(t);
        }
    }
    let mut out: Vec<(f64, usize, usize)> = by_z
        .into_iter()
        .map(|(z, (n, p))| (f64::from_bits(z), n, p.len()))
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// The plane nearest `z` (within `within`): its z, its triangles and points.
fn plane_near(m: &Surface, z: f64, within: f64) -> (f64, usize, usize) {
    let ps = planes(m);
    let p = ps.iter().filter(|p| (p.0 - z).abs() < within).max_by_key(|p| p.1);
    let p = p.unwrap_or_else(|| panic!("no plane near z {z}: {ps:?}"));
    *p
}

#[test]
fn a_plain_turned_bar_has_two_flat_ends_of_a_polygon_each() {
    let s = bar(20.0, 60.0, 0.2);
    let (raw, m, got) = merged(&s, 60);
    assert_eq!((got.merged, got.kept), (2, 0));
    // Each end (within a column of the bar's): its outline points less two triangles, where the
    // lattice had hundreds.
    for z in [0.0, 60.0] {
        let (at, tris, points) = plane_near(&m, z, 0.5);
        assert_eq!(tris, points - 2, "end at z {z}");
        let before = raw
            .triangles
            .iter()
            .filter(|t| t.iter().all(|&i| (raw.vertices[i as usize][2] - at).abs() < 1e-3))
            .count();
        assert!(tris * 4 < before, "end at z {z}: {tris} triangles, {before} before");
    }
    // What `surface` returns is the merged one.
    let surf = s.surface(60).unwrap();
    assert_eq!(surf.triangles.len(), m.triangles.len());
    assert_eq!(surf.flat, got);
}

#[test]
fn a_shoulder_is_a_ring_with_its_hole() {
    // Ø40 for z < 30, Ø24 above: the shoulder at z 30 faces +z around the small diameter.
    let s = Stock::turned(0.0, 60.0, 20.0, 0.2, |z| {
        Some((0.0, if z < 30.0 { 20.0 } else { 12.0 }))
    })
    .unwrap();
    let (_, m, got) = merged(&s, 60);
    assert_eq!((got.merged, got.kept), (3, 0));
    // The ring: points + 2 × 1 hole − 2 triangles.
    let (_, tris, points) = plane_near(&m, 30.0, 0.5);
    assert_eq!(tris, points);
}

#[test]
fn a_face_slot_keeps_its_floor_and_the_face_around_it() {
    // The turn-mill example's Ø50 × 120 bar with a Ø10 slot 5 deep across its front face.
    let tol = 0.2;
    let mut s = bar(25.0, 120.0, tol);
    s.cut(&sweep(
        &flat(10.0, 30.0),
        [0.0, 0.0, 1.0],
        [10.0, -8.0, 115.0],
        [10.0, 8.0, 115.0],
        tol,
    ));
    let (raw, m, got) = merged(&s, 100);
    // The back end, the front face (the slot a hole in it), the slot's floor.
    assert_eq!((got.merged, got.kept), (3, 0));
    for z in [0.0, 115.0, 120.0] {
        plane_near(&m, z, 0.5);
    }
    assert!(
        m.triangles.len() * 3 < raw.triangles.len(),
        "{} against {}",
        m.triangles.len(),
        raw.triangles.len()
    );
}

#[test]
fn a_face_pocket_and_a_drilled_hole_are_holes_in_the_face() {
    let tol = 0.2;
    let mut s = bar(25.0, 80.0, tol);
    // A flat-bottomed pocket 4 deep, and a Ø8 drill 10 deep with its point.
    s.cut(&sweep(
        &flat(12.0, 30.0),
        [0.0, 0.0, 1.0],
        [-12.0, 0.0, 76.0],
        [-4.0, 0.0, 76.0],
        tol,
    ));
    let drill = Cutter::new(CutterKind::Drill { point_angle_deg: 118.0 }, 8.0, 30.0).unwrap();
    s.cut(&sweep(
        &drill,
        [0.0, 0.0, 1.0],
        [10.0, 8.0, 82.0],
        [10.0, 8.0, 70.0],
        tol,
    ));
    let (_, m, got) = merged(&s, 100);
    // Back end, front face with two holes, pocket floor; the drill's cone stays as it is.
    assert_eq!((got.merged, got.kept), (3, 0));
    plane_near(&m, 76.0, 0.5);
}

#[test]
fn a_block_pocketed_on_its_top_face_keeps_the_pocket() {
    let mut s = Stock::block(Vector3::zeros(), Vector3::new(60.0, 40.0, 30.0), 128, 0.3).unwrap();
    s.cut(&sweep(
        &flat(10.0, 30.0),
        [0.0, 0.0, 1.0],
        [15.0, 20.0, 25.0],
        [45.0, 20.0, 25.0],
        0.3,
    ));
    let (_, m, got) = merged(&s, 60);
    // Bottom, top with the pocket a hole in it, the pocket's floor.
    assert_eq!((got.merged, got.kept), (3, 0));
    plane_near(&m, 25.0, 0.5);
}

/// Random radial and axial cuts into small bars: whatever the faces look like, the merge keeps
/// the surface closed with its volume and area, and leaves alone what it cannot prove.
#[test]
fn random_milled_bars_stay_closed_with_their_volume() {
    let mut rnd = crate::test_util::unit_random(99u64);
    let tol = 0.25;
    let (mut merged_faces, mut kept) = (0, 0);
    for _ in 0..6 {
        let mut s = bar(10.0 + 5.0 * rnd(), 30.0, tol);
        for _ in 0..4 {
            let c = flat(3.0 + 6.0 * rnd(), 20.0);
            if rnd() < 0.6 {
                // Axial: a pocket or slot into the front face, or a step milled on its edge.
                let (x, y) = (16.0 * rnd() - 8.0, 16.0 * rnd() - 8.0);
                let z = 30.0 - 1.0 - 5.0 * rnd();
                s.cut(&sweep(
                    &c,
                    [0.0, 0.0, 1.0],
                    [x, y, z],
                    [x + 10.0 * rnd() - 5.0, y + 6.0 * rnd() - 3.0, z],
                    tol,
                ));
            } else {
                // Radial: a flat across the side.
                let phi = rnd() * std::f64::consts::TAU;
                let (c0, s0) = (phi.cos(), phi.sin());
                let (d, z) = (8.0 + 2.0 * rnd(), 5.0 + 20.0 * rnd());
                s.cut(&sweep(
                    &c,
                    [c0, s0, 0.0],
                    [d * c0 - 15.0 * s0, d * s0 + 15.0 * c0, z],
                    [d * c0 + 15.0 * s0, d * s0 - 15.0 * c0, z],
                    tol,
                ));
            }
        }
        let (_, _, got) = merged(&s, 40);
        merged_faces += got.merged;
        kept += got.kept;
    }
    eprintln!("{merged_faces} faces merged, {kept} kept");
    assert!(merged_faces >= 12, "{merged_faces} faces merged, {kept} kept");
}

/// A face whose outline the triangulation cannot take (points past what it accepts) is left as
/// the lattice made it, and counted; so is a surface with an edge run twice the same way.
#[test]
fn faces_that_cannot_be_merged_safely_are_left_and_counted() {
    let s = Stock::block(Vector3::zeros(), Vector3::new(60.0, 40.0, 30.0), 64, 0.5).unwrap();
    let (raw, h) = mesh::lattice(&s, 30).unwrap();
    let scale = 1e62;
    let mut huge = raw.clone();
    for p in &mut huge.vertices {
        *p = p.map(|x| x * scale);
    }
    let before = huge.triangles.clone();
    let got = flat_faces::merge(&mut huge, mesh::PLANE_TOL * h * scale, true);
    assert_eq!((got.merged, got.kept), (0, 2));
    assert!(huge.triangles == before, "the faces' triangles are kept as they were");
    // One triangle twice: not a closed surface, nothing done.
    let mut twice = raw.clone();
    twice.triangles.push(twice.triangles[0]);
    let got = flat_faces::merge(&mut twice, mesh::PLANE_TOL * h, true);
    assert_eq!((got.merged, got.kept, got.small), (0, 0, 0));
    assert_eq!(twice.triangles.len(), raw.triangles.len() + 1);
}
