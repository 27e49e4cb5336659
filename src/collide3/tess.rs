//! Minimal primitive → triangle-mesh conversions for the 3D collision queries.
//!
//! `kin::shape` (another part of issue 15) will own the general tessellation; these are the few
//! conversions `collide3` needs now, each built so that the mesh is never smaller than the true
//! solid.
//!
//! **Revolved outlines are circumscribed.** The outline (points `(r, z)`, a simple polygon,
//! r ≥ 0) is first made counter-clockwise. With `n` spokes, a ring of mesh vertices at radius `R`
//! is a regular n-gon; the half plane at angle φ from a sector's middle cuts the band between two
//! spokes at `R · c`, `c = cos(π/n) / cos φ ∈ [cos(π/n), 1]`. Every outline edge going toward +z
//! (its outward normal points away from the axis: an outer surface) has its vertices at
//! `R = r / cos(π/n)`, so its section radius is `r · c / cos(π/n) ≥ r`; every edge going toward
//! −z (an inner surface, a bore) keeps `R = r`, so its section radius is `r · c ≤ r`. A vertex
//! where an outer and an inner edge meet is split into two rings (one of each kind) joined by a
//! flat annulus. On every half plane each slice `[a, b]` of the outline (a on an inner edge, b on
//! an outer edge) therefore becomes `[c·a, c·b/cos(π/n)] ⊇ [a, b]`: the mesh holds the solid.
//! (Assumption: gaps inside the outline narrower than `r · (1/cos(π/n) − 1)` may close up; the
//! mesh then overlaps itself but still holds the solid.)

use parry3d_f64::math::Vector;

use super::positive;
use crate::geom::P2;

/// Fewest and most spokes of a revolved mesh.
pub const MIN_SPOKES: usize = 8;
pub const MAX_SPOKES: usize = 720;

/// Spokes for a revolved outline of largest radius `rmax` so that the circumscribed mesh is at
/// most `tol` larger than the solid radially: `rmax · (1/cos(π/n) − 1) ≤ tol`, capped.
pub fn spokes(rmax: f64, tol: f64) -> usize {
    if !positive(rmax) || !positive(tol) {
        return MIN_SPOKES;
    }
    let c = 1.0 / (1.0 + tol / rmax);
    let n = std::f64::consts::PI / c.clamp(-1.0, 1.0).acos();
    if n.is_finite() {
        (n.ceil() as usize).clamp(MIN_SPOKES, MAX_SPOKES)
    } else {
        MAX_SPOKES
    }
}

/// Twice the signed area of a polygon (positive counter-clockwise).
fn area2(p: &[P2]) -> f64 {
    (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a.x * b.y - b.x * a.y
        })
        .sum()
}

/// The outline cleaned: finite points, r clamped to ≥ 0, consecutive duplicates dropped.
fn clean(outline: &[P2]) -> Vec<P2> {
    let mut v: Vec<P2> = Vec::with_capacity(outline.len());
    for p in outline {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Vec::new();
        }
        let q = P2::new(p.x, p.y);
        if v.last() != Some(&q) {
            v.push(q);
        }
    }
    while v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    v
}

/// A closed mesh circumscribing the revolution of `outline` about z (see the module docs), or
/// `None` when the outline encloses no area.
pub fn revolved(outline: &[P2], tol: f64) -> Option<(Vec<Vector>, Vec<[u32; 3]>)> {
    let mut p: Vec<P2> = clean(outline).into_iter().map(|q| P2::new(q.x.max(0.0), q.y)).collect();
    if p.len() < 3 {
        return None;
    }
    let a = area2(&p);
    if !positive(a.abs()) {
        return None;
    }
    if a < 0.0 {
        p.reverse();
    }
    let rmax = p.iter().map(|q| q.x).fold(0.0, f64::max);
    let n = spokes(rmax, tol);
    let s = 1.0 / (std::f64::consts::PI / n as f64).cos();
    // Outline vertices with their ring scale: split where an outer edge (toward +z) meets an
    // inner one (toward −z).
    let m = p.len();
    let mut ring: Vec<(P2, f64)> = Vec::with_capacity(2 * m);
    let kind = |i: usize| {
        let (a, b) = (p[i % m], p[(i + 1) % m]);
        (b.y - a.y).partial_cmp(&0.0).unwrap_or(std::cmp::Ordering::Equal)
    };
    use std::cmp::Ordering::*;
    for (i, &q) in p.iter().enumerate() {
        let before = kind(i + m - 1);
        let after = kind(i);
        let scale = |k: std::cmp::Ordering| if k == Less { 1.0 } else { s };
        match (before, after) {
            (Greater, Less) | (Less, Greater) => {
                ring.push((q, scale(before)));
                ring.push((q, scale(after)));
            }
            (Equal, k) | (k, Equal) => ring.push((q, scale(k))),
            (k, _) => ring.push((q, scale(k))),
        }
    }
    let mut verts: Vec<Vector> = Vec::new();
    // First vertex of each ring; a point on the axis is one vertex.
    let mut first: Vec<(u32, bool)> = Vec::with_capacity(ring.len());
    for &(q, k) in &ring {
        if q.x == 0.0 {
            first.push((verts.len() as u32, true));
            verts.push(Vector::new(0.0, 0.0, q.y));
        } else {
            first.push((verts.len() as u32, false));
            let r = q.x * k;
            for j in 0..n {
                let t = std::f64::consts::TAU * j as f64 / n as f64;
                verts.push(Vector::new(r * t.cos(), r * t.sin(), q.y));
            }
        }
    }
    let idx = |v: (u32, bool), j: usize| if v.1 { v.0 } else { v.0 + (j % n) as u32 };
    let mut tris: Vec<[u32; 3]> = Vec::new();
    let l = ring.len();
    for i in 0..l {
        let (a, b) = (first[i], first[(i + 1) % l]);
        if a.1 && b.1 {
            continue;
        }
        for j in 0..n {
            let (a0, a1, b0, b1) = (idx(a, j), idx(a, j + 1), idx(b, j), idx(b, j + 1));
            if !a.1 {
                tris.push([a0, a1, b1]);
            }
            if !b.1 {
                tris.push([a0, b1, b0]);
            }
        }
    }
    orient_outward(&verts, &mut tris);
    Some((verts, tris))
}

/// Flip every triangle when the mesh's signed volume is negative (inward facing).
pub fn orient_outward(v: &[Vector], t: &mut [[u32; 3]]) {
    let vol: f64 = t
        .iter()
        .map(|tr| {
            let (a, b, c) = (v[tr[0] as usize], v[tr[1] as usize], v[tr[2] as usize]);
            a.dot(b.cross(c))
        })
        .sum();
    if vol < 0.0 {
        for tr in t.iter_mut() {
            tr.swap(1, 2);
        }
    }
}

/// Whether a polygon (at least 3 points, either winding) is convex.
pub fn is_convex(p: &[P2]) -> bool {
    let n = p.len();
    let mut sign = 0.0;
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let cr = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
        if cr != 0.0 {
            if sign != 0.0 && cr.signum() != sign {
                return false;
            }
            sign = cr.signum();
        }
    }
    true
}

/// Triangles of a simple counter-clockwise polygon by ear clipping (O(n²)); `None` when no ear is
/// found (the polygon is not simple).
pub fn ear_clip(p: &[P2]) -> Option<Vec<[u32; 3]>> {
    let mut idx: Vec<usize> = (0..p.len()).collect();
    let mut out = Vec::with_capacity(p.len().saturating_sub(2));
    let cross = |a: P2, b: P2, c: P2| (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    while idx.len() > 3 {
        let m = idx.len();
        let mut found = None;
        for i in 0..m {
            let (ia, ib, ic) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            let (a, b, c) = (p[ia], p[ib], p[ic]);
            if cross(a, b, c) <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&k| {
                if k == ia || k == ib || k == ic {
                    return false;
                }
                let q = p[k];
                cross(a, b, q) >= 0.0 && cross(b, c, q) >= 0.0 && cross(c, a, q) >= 0.0
            });
            if !blocked {
                found = Some(i);
                break;
            }
        }
        let i = found?;
        out.push([idx[(i + m - 1) % m] as u32, idx[i] as u32, idx[(i + 1) % m] as u32]);
        idx.remove(i);
    }
    if idx.len() == 3 {
        out.push([idx[0] as u32, idx[1] as u32, idx[2] as u32]);
    }
    Some(out)
}

/// A closed mesh of an outline in (x, z) extruded along y over `[-hw, hw]`, or `None` when the
/// outline is not a simple polygon with area (the caller then uses its convex hull, which holds
/// it).
pub fn extruded(outline: &[P2], hw: f64) -> Option<(Vec<Vector>, Vec<[u32; 3]>)> {
    let mut p = clean(outline);
    if p.len() < 3 || !positive(hw) {
        return None;
    }
    let a = area2(&p);
    if !positive(a.abs()) {
        return None;
    }
    if a < 0.0 {
        p.reverse();
    }
    let caps = ear_clip(&p)?;
    let n = p.len() as u32;
    let mut v = Vec::with_capacity(2 * p.len());
    for y in [-hw, hw] {
        for q in &p {
            v.push(Vector::new(q.x, y, q.y));
        }
    }
    let mut t = Vec::with_capacity(2 * caps.len() + 2 * p.len());
    for c in &caps {
        t.push(*c);
        t.push([c[0] + n, c[2] + n, c[1] + n]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        t.push([i, j, j + n]);
        t.push([i, j + n, i + n]);
    }
    orient_outward(&v, &mut t);
    Some((v, t))
}

/// A tessellated sphere (UV, `rings` × `segs`), for tests and benchmarks.
pub fn uv_sphere(radius: f64, rings: usize, segs: usize) -> (Vec<Vector>, Vec<[u32; 3]>) {
    let rings = rings.max(2);
    let segs = segs.max(3);
    let mut v = vec![Vector::new(0.0, 0.0, -radius)];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        let (r, z) = (radius * th.sin(), -radius * th.cos());
        for j in 0..segs {
            let ph = std::f64::consts::TAU * j as f64 / segs as f64;
            v.push(Vector::new(r * ph.cos(), r * ph.sin(), z));
        }
    }
    let top = v.len() as u32;
    v.push(Vector::new(0.0, 0.0, radius));
    let ring = |i: usize, j: usize| (1 + (i - 1) * segs + j % segs) as u32;
    let mut t = Vec::new();
    for j in 0..segs {
        t.push([0, ring(1, j + 1), ring(1, j)]);
        t.push([top, ring(rings - 1, j), ring(rings - 1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segs {
            t.push([ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)]);
        }
    }
    orient_outward(&v, &mut t);
    (v, t)
}
