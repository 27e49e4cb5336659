//! Primitives → closed, consistently wound triangle meshes ([`Mesh`], counter-clockwise seen
//! from outside), for the 3D queries.
//!
//! A revolved outline becomes a polygonal solid that contains the true solid of revolution. With
//! `n` segments a ring of vertices at radius `R` is a regular n-gon; the half plane at angle φ
//! from a segment's middle cuts the band between two segments at `R · c`,
//! `c = cos(π/n) / cos φ ∈ [cos(π/n), 1]`. The ends of every outline edge going toward +z (its
//! outward normal points away from the axis: an outer surface) are rings at `R = r / cos(π/n)`,
//! so the edge's section radius is `r · c / cos(π/n) ≥ r`; the ends of every edge going toward −z
//! (a bore) keep `R = r`, so its section radius is `r · c ≤ r`, on the material side. A point
//! where an outer and a bore edge meet becomes two rings, one of each kind, joined by a flat
//! annulus. On every half plane each slice `[a, b]` of the outline (a on a bore edge, b on an
//! outer edge) therefore becomes `[c·a, c·b/cos(π/n)] ⊇ [a, b]`: the mesh holds the solid. (Gaps
//! inside the outline narrower than `r · (1/cos(π/n) − 1)` may close up: the mesh then overlaps
//! itself but still holds the solid.) `n` (segments round the
//! axis) is the least for which the outward excess `r_max · (1/cos(π/n) − 1)` is at most the
//! tolerance, from [`MIN_SEGMENTS`] to [`MAX_SEGMENTS`] (at the cap the excess may exceed the
//! tolerance: the mesh is still never smaller than the solid).
//!
//! An extruded outline is triangulated by ear clipping: at most [`MAX_SHAPE_POINTS`] points.

use nalgebra::Point3;

use super::{Geometry, Mesh};
use crate::geom::{Polygon, P2};

/// Fewest segments round the axis of a revolved mesh.
pub const MIN_SEGMENTS: usize = 8;
/// Most segments round the axis of a revolved mesh.
pub const MAX_SEGMENTS: usize = 512;
/// Most points of an outline made into a mesh.
pub const MAX_SHAPE_POINTS: usize = 2_000;

/// How many segments round the axis keep the outward excess of a radius `r_max` within `tol`.
pub fn segments_for(r_max: f64, tol: f64) -> usize {
    let mut n = MIN_SEGMENTS;
    if r_max.is_nan() || r_max <= 0.0 {
        return MIN_SEGMENTS;
    }
    if tol.is_nan() || tol <= 0.0 {
        return MAX_SEGMENTS;
    }
    while n < MAX_SEGMENTS && r_max * (1.0 / (std::f64::consts::PI / n as f64).cos() - 1.0) > tol {
        n += 1;
    }
    n
}

/// A geometry as a mesh (a [`Geometry::Mesh`] is returned as it is).
pub fn mesh_of(g: &Geometry, tol: f64) -> Result<Mesh, String> {
    match g {
        Geometry::Mesh(m) => Ok((**m).clone()),
        Geometry::Revolved(o) => revolved(o, tol),
        Geometry::Extruded { outline, half_width } => extruded(outline, *half_width),
        Geometry::Cuboid { min, max } => Ok(cuboid(*min, *max)),
        Geometry::Cylinder { radius, z0, z1 } => cylinder(*radius, *z0, *z1, tol),
        Geometry::Cutter { end, radius, z0, z1 } => revolved(&cutter_outline(*end, *radius, *z0, *z1, tol), tol),
    }
}

/// A cutter's half outline in (r, z) from its point at `z0` up to `z1`, closed along the axis,
/// holding the true profile: a ball's or a bull nose's corner arc as the polygon of its tangents
/// (from the arc's lowest point, the tangents' crossings at `rc / cos(Δ/2)` from its centre, `Δ`
/// the step, to its outermost point: it stands at most `tol` outside the arc, never below `z0`
/// nor beyond the radius; two to 64 steps a quarter), a drill's cone as it is (its point clipped
/// at `z1` when the flutes are shorter). Revolved ([`revolved`]), the mesh holds the cutter.
pub fn cutter_outline(end: crate::grid::CutterKind, radius: f64, z0: f64, z1: f64, tol: f64) -> Vec<P2> {
    use crate::grid::CutterKind as K;
    let (r, len) = (radius, z1 - z0);
    let mut out = Vec::new();
    let arc = |rc: f64, out: &mut Vec<P2>| {
        // The corner's centre at (r − rc, z0 + rc), from straight down (−90°) to straight out.
        let tol = if tol.is_finite() && tol > 0.0 { tol } else { 1e-3 };
        let mut n = 2usize;
        while n < 64 && rc * (1.0 / (std::f64::consts::FRAC_PI_4 / n as f64).cos() - 1.0) > tol {
            n += 1;
        }
        let step = std::f64::consts::FRAC_PI_2 / n as f64;
        let big = rc / (step / 2.0).cos();
        let (cx, cz) = (r - rc, z0 + rc);
        out.push(P2::new(0.0, z0));
        if cx > 0.0 {
            out.push(P2::new(cx, z0));
        }
        for k in 0..n {
            let a = -std::f64::consts::FRAC_PI_2 + step * (k as f64 + 0.5);
            out.push(P2::new((cx + big * a.cos()).min(r), (cz + big * a.sin()).max(z0)));
        }
        out.push(P2::new(r, cz));
    };
    match end {
        K::Ball => arc(r.min(len), &mut out),
        K::Bull { corner_radius } => arc(corner_radius.min(r).min(len), &mut out),
        K::Drill { point_angle_deg } => {
            let k = (point_angle_deg.to_radians() / 2.0).tan();
            let tip = if k > 0.0 { (r / k).min(len) } else { len };
            out.push(P2::new(0.0, z0));
            out.push(P2::new((tip * k).min(r), z0 + tip));
        }
        K::Flat | K::Tap { .. } => {
            out.push(P2::new(0.0, z0));
            out.push(P2::new(r, z0));
        }
    }
    if out.last().is_some_and(|p| p.y < z1) {
        out.push(P2::new(r, z1));
    }
    out.push(P2::new(0.0, z1));
    out
}

/// A simple outline as a counter-clockwise polygon, with the checks a mesh needs.
fn polygon(outline: &[P2]) -> Result<Polygon, String> {
    if outline.len() > MAX_SHAPE_POINTS {
        return Err(format!(
            "{} points; an outline made into a mesh may have at most {MAX_SHAPE_POINTS}",
            outline.len()
        ));
    }
    Polygon::new(outline).map_err(|e| format!("invalid outline: {e}"))
}

/// The outline in (r, z), r ≥ 0, revolved about z.
pub fn revolved(outline: &[P2], tol: f64) -> Result<Mesh, String> {
    let poly = polygon(outline)?;
    let pts = poly.points();
    if let Some(p) = pts.iter().find(|p| p.x < 0.0) {
        return Err(format!(
            "a revolved outline has r ≥ 0; point [{}, {}] has not",
            p.x, p.y
        ));
    }
    let r_max = pts.iter().fold(0.0f64, |m, p| m.max(p.x));
    if r_max <= 0.0 {
        return Err("the outline has no material off the axis".into());
    }
    let n = segments_for(r_max, tol);
    let stretch = 1.0 / (std::f64::consts::PI / n as f64).cos();
    let m = pts.len();
    // Counter-clockwise in (r, z): the outward normal of edge p→q is (dz, −dr); it faces away
    // from the axis when dz > 0 (scaled ring) and toward it when dz < 0 (a bore: kept).
    let rise = |i: usize| {
        let (p, q) = (pts[i % m], pts[(i + 1) % m]);
        (q.y - p.y).partial_cmp(&0.0).unwrap_or(std::cmp::Ordering::Equal)
    };
    use std::cmp::Ordering::{Equal, Greater, Less};
    let scale = |k: std::cmp::Ordering| if k == Less { 1.0 } else { stretch };
    // One ring per outline point, two where an outer edge meets a bore edge (joined by a flat
    // annulus), so that neither edge's ring takes the other's radius.
    let mut rings: Vec<(P2, f64)> = Vec::with_capacity(2 * m);
    for (i, &p) in pts.iter().enumerate() {
        let (before, after) = (rise(i + m - 1), rise(i));
        match (before, after) {
            (Greater, Less) | (Less, Greater) => {
                rings.push((p, scale(before)));
                rings.push((p, scale(after)));
            }
            (Equal, k) | (k, Equal) => rings.push((p, scale(k))),
            (k, _) => rings.push((p, scale(k))),
        }
    }
    let mut vertices = Vec::new();
    // For each ring: its first vertex index, and whether it is a point on the axis (one vertex).
    let mut first: Vec<(u32, bool)> = Vec::with_capacity(rings.len());
    for &(p, k) in &rings {
        first.push((vertices.len() as u32, p.x == 0.0));
        if p.x == 0.0 {
            vertices.push(Point3::new(0.0, 0.0, p.y));
            continue;
        }
        let r = p.x * k;
        for j in 0..n {
            let a = std::f64::consts::TAU * j as f64 / n as f64;
            vertices.push(Point3::new(r * a.cos(), r * a.sin(), p.y));
        }
    }
    let at = |(v, on_axis): (u32, bool), j: usize| if on_axis { v } else { v + (j % n) as u32 };
    let mut triangles = Vec::new();
    let l = rings.len();
    for i in 0..l {
        let (a, b) = (first[i], first[(i + 1) % l]);
        if a.1 && b.1 {
            continue;
        }
        for j in 0..n {
            let (a0, a1, b0, b1) = (at(a, j), at(a, j + 1), at(b, j), at(b, j + 1));
            if !a.1 {
                triangles.push([a0, a1, b1]);
            }
            if !b.1 {
                triangles.push([a0, b1, b0]);
            }
        }
    }
    outward(Mesh { vertices, triangles })
}

/// The mesh wound outward (a closed consistent mesh is either all right or all wrong).
fn outward(m: Mesh) -> Result<Mesh, String> {
    let v = m.volume();
    if v > 0.0 {
        Ok(m)
    } else if v < 0.0 {
        Ok(m.flipped())
    } else {
        Err("the shape encloses no volume".into())
    }
}

/// The outline in the (x, z) plane extruded along y from `-half_width` to `half_width`.
pub fn extruded(outline: &[P2], half_width: f64) -> Result<Mesh, String> {
    if half_width.is_nan() || half_width <= 0.0 || half_width.is_infinite() {
        return Err(format!("half width {half_width} must be a positive number"));
    }
    let poly = polygon(outline)?;
    let pts = poly.points();
    let m = pts.len() as u32;
    let mut vertices = Vec::with_capacity(2 * pts.len());
    for y in [-half_width, half_width] {
        for p in pts {
            vertices.push(Point3::new(p.x, y, p.y));
        }
    }
    let mut triangles = Vec::new();
    for t in crate::geom::convex::triangulate(pts) {
        // Counter-clockwise in (x, z) faces −y: the cap at −y as it is, the one at +y reversed.
        triangles.push(t);
        triangles.push([t[0] + m, t[2] + m, t[1] + m]);
    }
    for i in 0..m {
        let j = (i + 1) % m;
        // The cap at −y runs i → j: the side runs j → i there.
        triangles.push([j, i, i + m]);
        triangles.push([j, i + m, j + m]);
    }
    outward(Mesh { vertices, triangles })
}

/// An axis-aligned box (corners in any order).
pub fn cuboid(a: Point3<f64>, b: Point3<f64>) -> Mesh {
    let (lo, hi) = (a.inf(&b), a.sup(&b));
    let v = |i: u32| {
        Point3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    Mesh {
        vertices: (0..8).map(v).collect(),
        triangles: vec![
            [0, 2, 3],
            [0, 3, 1], // z = lo
            [4, 5, 7],
            [4, 7, 6], // z = hi
            [0, 1, 5],
            [0, 5, 4], // y = lo
            [2, 6, 7],
            [2, 7, 3], // y = hi
            [0, 4, 6],
            [0, 6, 2], // x = lo
            [1, 3, 7],
            [1, 7, 5], // x = hi
        ],
    }
}

/// A cylinder of `radius` about z from `z0` to `z1` (circumscribing, as [`revolved`]).
pub fn cylinder(radius: f64, z0: f64, z1: f64, tol: f64) -> Result<Mesh, String> {
    let (z0, z1) = (z0.min(z1), z0.max(z1));
    revolved(
        &[
            P2::new(0.0, z0),
            P2::new(radius, z0),
            P2::new(radius, z1),
            P2::new(0.0, z1),
        ],
        tol,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kin::stl::check_mesh;
    use std::f64::consts::PI;

    fn closed(m: &Mesh) {
        check_mesh(m, "shape").unwrap();
    }

    #[test]
    fn cuboid_is_closed_with_its_volume() {
        let m = cuboid(Point3::new(1.0, 5.0, -2.0), Point3::new(-1.0, 2.0, 4.0));
        closed(&m);
        assert!((m.volume() - 2.0 * 3.0 * 6.0).abs() < 1e-12);
    }

    #[test]
    fn cylinder_circumscribes_with_the_polygon_volume() {
        let (r, tol) = (40.0, 0.05);
        let m = cylinder(r, -10.0, 30.0, tol).unwrap();
        closed(&m);
        let n = segments_for(r, tol);
        assert!(r * (1.0 / (PI / n as f64).cos() - 1.0) <= tol);
        assert!(r * (1.0 / (PI / (n - 1) as f64).cos() - 1.0) > tol, "n is the least");
        // A regular n-gon with apothem r has area n r² tan(π/n).
        let want = n as f64 * r * r * (PI / n as f64).tan() * 40.0;
        assert!((m.volume() - want).abs() < 1e-6 * want, "{} vs {want}", m.volume());
        assert!(m.volume() >= PI * r * r * 40.0);
    }

    #[test]
    fn tube_keeps_its_bore_vertices_on_the_circle() {
        // Outer r 20, bore r 10, z 0..50: outer ring circumscribes, bore ring is inscribed.
        let o = [
            P2::new(10.0, 0.0),
            P2::new(20.0, 0.0),
            P2::new(20.0, 50.0),
            P2::new(10.0, 50.0),
        ];
        let tol = 0.01;
        let m = revolved(&o, tol).unwrap();
        closed(&m);
        let n = segments_for(20.0, tol) as f64;
        let outer = n * 400.0 * (PI / n).tan();
        let inner = n / 2.0 * 100.0 * (2.0 * PI / n).sin();
        let want = (outer - inner) * 50.0;
        assert!((m.volume() - want).abs() < 1e-6 * want, "{} vs {want}", m.volume());
        assert!(m.volume() >= PI * (400.0 - 100.0) * 50.0);
    }

    #[test]
    fn cone_with_points_on_the_axis_is_closed() {
        let o = [P2::new(0.0, 0.0), P2::new(30.0, 0.0), P2::new(0.0, 60.0)];
        let m = revolved(&o, 0.1).unwrap();
        closed(&m);
        let v = PI * 900.0 * 60.0 / 3.0;
        assert!(m.volume() >= v && m.volume() < v * 1.02);
    }

    #[test]
    fn extruded_l_shape_has_area_times_width() {
        // Either winding.
        let o = [
            P2::new(0.0, 0.0),
            P2::new(0.0, 30.0),
            P2::new(10.0, 30.0),
            P2::new(10.0, 10.0),
            P2::new(40.0, 10.0),
            P2::new(40.0, 0.0),
        ];
        let m = extruded(&o, 6.0).unwrap();
        closed(&m);
        assert!((m.volume() - (300.0 + 300.0) * 12.0).abs() < 1e-9);
    }

    #[test]
    fn extruded_comb_with_many_reflex_corners_is_closed() {
        let mut o = vec![P2::new(0.0, 0.0), P2::new(100.0, 0.0)];
        for k in (0..10).rev() {
            let x = 10.0 * k as f64;
            o.push(P2::new(x + 10.0, 20.0));
            o.push(P2::new(x + 5.0, 20.0));
            o.push(P2::new(x + 5.0, 5.0));
            o.push(P2::new(x, 5.0));
        }
        let m = extruded(&o, 1.0).unwrap();
        closed(&m);
        let area = 100.0 * 5.0 + 10.0 * 5.0 * 15.0;
        assert!((m.volume() - area * 2.0).abs() < 1e-9, "{}", m.volume());
    }

    #[test]
    fn bad_shapes_are_errors_not_panics() {
        assert!(revolved(&[P2::new(-1.0, 0.0), P2::new(5.0, 0.0), P2::new(5.0, 5.0)], 0.1).is_err());
        assert!(revolved(&[P2::new(0.0, 0.0), P2::new(0.0, 5.0), P2::new(0.0, 9.0)], 0.1).is_err());
        assert!(extruded(&[P2::new(0.0, 0.0), P2::new(1.0, 0.0), P2::new(0.0, 1.0)], 0.0).is_err());
        assert!(extruded(&[P2::new(0.0, 0.0), P2::new(1.0, 0.0), P2::new(0.0, 1.0)], f64::NAN).is_err());
        assert_eq!(segments_for(100.0, 0.0), MAX_SEGMENTS);
    }

    /// A cutter's mesh holds its true shape: closed, every point of the true profile (sampled
    /// up its height and round the axis) inside it, and no more than the tolerance proud of it
    /// (its volume against the true solid's).
    #[test]
    fn cutter_meshes_hold_their_true_shape_within_the_tolerance() {
        use crate::grid::{Cutter, CutterKind as K};
        let tol = 0.01;
        for end in [
            K::Ball,
            K::Bull { corner_radius: 2.0 },
            K::Drill { point_angle_deg: 118.0 },
            K::Drill { point_angle_deg: 60.0 },
        ] {
            let m = mesh_of(
                &Geometry::Cutter {
                    end,
                    radius: 5.0,
                    z0: 1.0,
                    z1: 21.0,
                },
                tol,
            )
            .unwrap();
            closed(&m);
            let c = Cutter::new(end, 10.0, 20.0).unwrap();
            // The true volume by slices, and each slice's circle against the mesh's section.
            let n = 4000;
            let mut v_true = 0.0;
            for k in 0..n {
                let h = 20.0 * (k as f64 + 0.5) / n as f64;
                v_true += std::f64::consts::PI * c.radius_at(h).powi(2) * 20.0 / n as f64;
            }
            let v = m.volume();
            assert!(v >= v_true - 1e-6, "{end:?}: mesh {v} < true {v_true}");
            assert!(v <= v_true * 1.01, "{end:?}: mesh {v} against true {v_true}");
            // Inside by the parity of a ray's crossings (a skew direction: no edge hit).
            let inside = |p: nalgebra::Point3<f64>| {
                let d = nalgebra::Vector3::new(1.0, 0.3137, 0.1713);
                let mut n = 0;
                for t in &m.triangles {
                    let [a, b, c] = t.map(|i| m.vertices[i as usize]);
                    let (e1, e2) = (b - a, c - a);
                    let q = d.cross(&e2);
                    let det = e1.dot(&q);
                    if det.abs() < 1e-15 {
                        continue;
                    }
                    let sv = p - a;
                    let u = sv.dot(&q) / det;
                    let r = sv.cross(&e1);
                    let v = d.dot(&r) / det;
                    if u >= 0.0 && v >= 0.0 && u + v <= 1.0 && e2.dot(&r) / det > 0.0 {
                        n += 1;
                    }
                }
                n % 2 == 1
            };
            for k in 0..=40 {
                let h = 20.0 * k as f64 / 40.0;
                let r = c.radius_at(h) * 0.999;
                for j in 0..12 {
                    let a = std::f64::consts::TAU * j as f64 / 12.0;
                    let p = nalgebra::Point3::new(r * a.cos(), r * a.sin(), 1.0 + h.clamp(1e-3, 20.0 - 1e-3));
                    assert!(inside(p), "{end:?}: h {h}, r {r}");
                }
            }
        }
    }
}
