//! A triangle mesh against the revolved in-process stock (`scene::DexelStock`), exact per column.
//!
//! The stock's material is known on the plane `z = c` through each column's centre, as radial
//! intervals (the 2D checker's model, ARCHITECTURE.md "the stock"). A triangle meets that plane in
//! a segment (a point, or the whole triangle when it lies in the plane); the distances of the
//! segment's points from the spindle axis fill exactly `[d_min, d_max]`, `d_min` the 2D distance
//! from the axis to the segment and `d_max` at an endpoint (distance to a point is convex along a
//! segment). Material at radius ρ on the plane is a whole ring, so the triangle meets the material
//! iff `[d_min, d_max]` meets one of the column's intervals. A closed mesh meets the material
//! also when a ring of material lies wholly inside it with no triangle reaching it: tested with
//! one point of the ring (the ring is connected and meets no triangle, so it is all inside or
//! all outside).

use parry3d_f64::math::Vector;

use super::{to_point, to_pose, Hit, Shape3};
use crate::kin::Iso;
use crate::scene::stock::{DexelStock, View};

/// Distance from the origin to the segment `a b` in the plane.
fn seg_dist(a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (-(a.0 * dx + a.1 * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.0 + t * dx).hypot(a.1 + t * dy)
}

/// Distance from the origin to the triangle projected on the xy plane: the smallest distance
/// from the spindle axis of any point of the triangle.
fn tri_axis_dist(p: &[Vector; 3]) -> f64 {
    let q: [(f64, f64); 3] = [(p[0].x, p[0].y), (p[1].x, p[1].y), (p[2].x, p[2].y)];
    let side = |a: (f64, f64), b: (f64, f64)| a.0 * b.1 - a.1 * b.0; // origin relative to edge
    let s = [side(q[0], q[1]), side(q[1], q[2]), side(q[2], q[0])];
    let inside = (s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)) && s.iter().any(|&v| v != 0.0);
    if inside {
        return 0.0;
    }
    seg_dist(q[0], q[1]).min(seg_dist(q[1], q[2])).min(seg_dist(q[2], q[0]))
}

/// A triangle's section by a column's plane: its radius range and a point (x, y) at each end.
struct Section {
    dmin: f64,
    dmax: f64,
    near: (f64, f64),
    far: (f64, f64),
}

/// The radius range `[d_min, d_max]` of the triangle's section by the plane `z = c`, and a
/// section point at each end of it, or `None` when the plane misses the triangle.
fn section(p: &[Vector; 3], c: f64) -> Option<Section> {
    if p.iter().all(|v| v.z == c) {
        let r = |v: &Vector| v.x.hypot(v.y);
        let far = p.iter().copied().max_by(|a, b| r(a).total_cmp(&r(b)))?;
        return Some(Section {
            dmin: tri_axis_dist(p),
            dmax: r(&far),
            near: (0.0, 0.0),
            far: (far.x, far.y),
        });
    }
    let mut pts: [(f64, f64); 3] = [(0.0, 0.0); 3];
    let mut n = 0;
    for i in 0..3 {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        if a.z == c {
            pts[n.min(2)] = (a.x, a.y);
            n += 1;
        }
        if (a.z - c) * (b.z - c) < 0.0 {
            let t = (c - a.z) / (b.z - a.z);
            pts[n.min(2)] = (a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
            n += 1;
        }
    }
    let n = n.min(3);
    if n == 0 {
        return None;
    }
    // The segment: the two section points farthest apart (all are on one line).
    let (mut a, mut b) = (pts[0], pts[0]);
    let mut best = -1.0;
    for i in 0..n {
        for j in i..n {
            let d = (pts[i].0 - pts[j].0).hypot(pts[i].1 - pts[j].1);
            if d > best {
                best = d;
                (a, b) = (pts[i], pts[j]);
            }
        }
    }
    let (ra, rb) = (a.0.hypot(a.1), b.0.hypot(b.1));
    let dmax = ra.max(rb);
    let dmin = seg_dist(a, b).min(dmax);
    let far = if ra >= rb { a } else { b };
    // The point nearest the axis.
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (-(a.0 * dx + a.1 * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let near = (a.0 + t * dx, a.1 + t * dy);
    Some(Section { dmin, dmax, near, far })
}

/// The mesh's triangles in the world (a primitive's circumscribing surface).
/// The posed solid's triangles that can come within `reach` of the spindle axis and within
/// `[zlo, zhi]` along it, in ascending order, as world points: a mesh's bounding-volume hierarchy
/// prunes whole subtrees whose box (its bounding sphere, posed) stays farther (parry's BVH leaves
/// are the triangles' indices). A convex shape gives every triangle of its surface. What is left
/// out has no point within `reach` of the axis or within the z range, so no query below can find
/// anything in it; the world box is that of the whole solid (its local box, posed).
struct Near {
    tris: Vec<[Vector; 3]>,
    bbox: (Vector, Vector),
}

fn near_triangles(shape: &Shape3, pose: &Iso, reach: f64, zlo: f64, zhi: f64) -> Near {
    let p = to_pose(pose);
    let (v, t) = shape.surface();
    let tri = |i: usize| {
        let [a, b, c] = t[i];
        [p * v[a as usize], p * v[b as usize], p * v[c as usize]]
    };
    let bbox = world_box(shape, pose);
    let tris = match shape.as_trimesh() {
        Some(mesh) => {
            let keep = |lo: Vector, hi: Vector| {
                let c = p * ((lo + hi) * 0.5);
                let h = (hi - lo).length() * 0.5;
                c.z + h >= zlo && c.z - h <= zhi && c.x.hypot(c.y) - h <= reach
            };
            let mut idx: Vec<u32> = mesh.bvh().leaves(|n| keep(n.mins(), n.maxs())).collect();
            idx.sort_unstable();
            idx.into_iter().map(|i| tri(i as usize)).collect()
        }
        None => (0..t.len()).map(tri).collect(),
    };
    Near { tris, bbox }
}

/// The world box of the posed solid: its local box's corners, posed.
fn world_box(shape: &Shape3, pose: &Iso) -> (Vector, Vector) {
    let p = to_pose(pose);
    let b = shape.local_box();
    let corners: Vec<Vector> = (0..8)
        .map(|k| {
            let pick = |bit: usize, lo: f64, hi: f64| if k & bit == 0 { lo } else { hi };
            p * Vector::new(
                pick(1, b.mins.x, b.maxs.x),
                pick(2, b.mins.y, b.maxs.y),
                pick(4, b.mins.z, b.maxs.z),
            )
        })
        .collect();
    bounds(&corners)
}

/// Does the solid (posed at `pose`) overlap the stock's material, as `view` sees it, by more than
/// `eps` (radially, on some column's plane)? The depth is the largest radial depth into the
/// material of a point of a triangle's section: `max over ρ in [d_min, d_max] ∩ [lo, hi] of
/// min(ρ − lo, hi − ρ)`; for a ring of material inside the solid, `min` of the ring's half
/// width and the ring point's depth inside the mesh.
pub fn stock_overlap(shape: &Shape3, pose: &Iso, stock: &mut DexelStock, view: View, eps: f64) -> Option<Hit> {
    let (zmin, zmax) = {
        let (lo, hi) = world_box(shape, pose);
        (lo.z, hi.z)
    };
    let pad = |z: f64| 1e-12 * (1.0 + z.abs());
    let (j0, j1) = stock.columns_within(zmin - pad(zmin), zmax + pad(zmax))?;
    // Per column in range: whether any triangle's section lies on its plane.
    let mut cut = vec![false; j1 - j0 + 1];
    let mut best: Option<Hit> = None;
    // The largest radius of material in range: a triangle whose (x, y) box keeps farther from
    // the axis than that has no section point in any material (a quick reject that changes
    // nothing, only skips sections that would find nothing). Subtrees of the mesh that keep
    // farther are not visited at all; their columns count as cut (below), which only adds
    // containment tests.
    let mut rmax = f64::NEG_INFINITY;
    for j in j0..=j1 {
        for &(_, hi) in stock.column_material(j, view) {
            rmax = rmax.max(hi);
        }
    }
    if rmax == f64::NEG_INFINITY {
        return None;
    }
    let near = near_triangles(shape, pose, rmax + eps, zmin, zmax);
    cut.iter_mut().for_each(|c| *c = true);
    for p in &near.tris {
        let p = *p;
        let (a, b) = (p[0].z.min(p[1].z).min(p[2].z), p[0].z.max(p[1].z).max(p[2].z));
        let Some((k0, k1)) = stock.columns_within(a - pad(a), b + pad(b)) else {
            continue;
        };
        let (x0, x1) = (p[0].x.min(p[1].x).min(p[2].x), p[0].x.max(p[1].x).max(p[2].x));
        let (y0, y1) = (p[0].y.min(p[1].y).min(p[2].y), p[0].y.max(p[1].y).max(p[2].y));
        let bx = x0.max(-x1).max(0.0);
        let by = y0.max(-y1).max(0.0);
        if bx.hypot(by) >= rmax + eps {
            for j in k0.max(j0)..=k1.min(j1) {
                cut[j - j0] = true;
            }
            continue;
        }
        for j in k0.max(j0)..=k1.min(j1) {
            let c = stock.column_center(j);
            let Some(Section { dmin, dmax, near, far }) = section(&p, c) else {
                continue;
            };
            cut[j - j0] = true;
            for &(lo, hi) in stock.column_material(j, view) {
                let (x0, x1) = (dmin.max(lo), dmax.min(hi));
                if x1 < x0 {
                    continue;
                }
                let m = (lo + hi) / 2.0;
                let rho = m.clamp(x0, x1);
                let depth = (rho - lo).min(hi - rho);
                if depth > eps && best.map_or(true, |h: Hit| depth > h.depth) {
                    // A section point inside the material: the end nearer the ring's middle.
                    let q = if (dmin - m).abs() <= (dmax - m).abs() {
                        near
                    } else {
                        far
                    };
                    best = Some(Hit {
                        depth,
                        point: to_point(Vector::new(q.0, q.1, c)),
                    });
                }
            }
        }
    }
    if best.is_some() {
        return best;
    }
    // Rings of material inside the solid with no triangle reaching them. A convex primitive's
    // section by a plane is convex: a ring around the axis inside it would need the axis inside
    // too, where the ring's hole is; the ring's point on the +x side tests both kinds.
    let wp = to_pose(pose);
    let bbox = near.bbox;
    for (i, &hit) in cut.iter().enumerate() {
        if !hit {
            continue;
        }
        let j = j0 + i;
        let c = stock.column_center(j);
        for &(lo, hi) in stock.column_material(j, view) {
            let q = Vector::new((lo + hi) / 2.0, 0.0, c);
            if !in_box(bbox, q) {
                continue; // outside the surface's box: not inside the solid
            }
            if shape.contains(&wp, q) {
                let depth = ((hi - lo) / 2.0).min(shape.depth_of(&wp, q));
                if depth > eps {
                    return Some(Hit {
                        depth,
                        point: to_point(q),
                    });
                }
            }
        }
    }
    None
}

/// The box of the points `v`.
fn bounds(v: &[Vector]) -> (Vector, Vector) {
    let (mut lo, mut hi) = (Vector::splat(f64::INFINITY), Vector::splat(f64::NEG_INFINITY));
    for p in v {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    (lo, hi)
}

/// Whether `q` lies in the box `(lo, hi)`.
fn in_box((lo, hi): (Vector, Vector), q: Vector) -> bool {
    q.x >= lo.x && q.x <= hi.x && q.y >= lo.y && q.y <= hi.y && q.z >= lo.z && q.z <= hi.z
}

/// A lower bound of the distance from the solid (posed at `pose`) to the stock's material as
/// `view` sees it (material on the columns' centre planes, as the overlap test sees it), looking
/// no further than `window` mm: returns `window` when nothing is that close, 0 when they
/// overlap. Per triangle and column: the triangle lies in the box `[ρ_min, ρ_max] × [z0, z1]` of
/// the (radius, z) half plane and a material ring is the segment `[lo, hi] × {c}`; the 3D distance
/// of two sets symmetric about the axis is their distance in that half plane, at least the
/// distance of the box to the segment.
pub fn stock_gap(shape: &Shape3, pose: &Iso, stock: &mut DexelStock, view: View, window: f64) -> f64 {
    if window.is_nan() {
        return 0.0;
    }
    if stock_overlap(shape, pose, stock, view, 0.0).is_some() {
        return 0.0;
    }
    let (lo, hi) = world_box(shape, pose);
    let Some((j0, j1)) = stock.columns_within(lo.z - window, hi.z + window) else {
        return window;
    };
    let mut rmax = f64::NEG_INFINITY;
    for j in j0..=j1 {
        for &(_, top) in stock.column_material(j, view) {
            rmax = rmax.max(top);
        }
    }
    if rmax == f64::NEG_INFINITY {
        return window;
    }
    // A triangle all of whose points keep farther than rmax + window from the axis, or farther
    // than window along z from every column with material, improves nothing below.
    let near = near_triangles(shape, pose, rmax + window, lo.z - window, hi.z + window);
    let mut best = window;
    for p in &near.tris {
        let p = *p;
        let (z0, z1) = (p[0].z.min(p[1].z).min(p[2].z), p[0].z.max(p[1].z).max(p[2].z));
        let Some((k0, k1)) = stock.columns_within(z0 - best, z1 + best) else {
            continue;
        };
        let rmin = tri_axis_dist(&p);
        let rmax = p.iter().map(|q| q.x.hypot(q.y)).fold(0.0, f64::max);
        for j in k0..=k1 {
            let c = stock.column_center(j);
            let dz = (c - z1).max(z0 - c).max(0.0);
            if dz >= best {
                continue;
            }
            for &(lo, hi) in stock.column_material(j, view) {
                let dr = (lo - rmax).max(rmin - hi).max(0.0);
                best = best.min(dz.hypot(dr));
            }
        }
        if best <= 0.0 {
            return 0.0;
        }
    }
    best.max(0.0)
}

/// An upper bound of the depth [`stock_overlap`] reports (whatever its `eps`) for the solid posed
/// anywhere in the convex hull of its poses `poses`: of every pose `P(u)` whose points (surface
/// and interior) lie in the convex hull `H` of the surface's vertices posed at `poses` — every
/// pose of a translation along the polyline through them. 0 when `poses` is empty.
///
/// The proof. Every depth the overlap test reports on a column's plane `z = c` is
/// `min(ρ − lo, hi − ρ)` for a material ring `[lo, hi]` and a radius `ρ` of a point of the solid
/// on that plane (a triangle's section point, or the ring's point inside the solid, whose depth is
/// at most the ring's half width, its middle's tent). Those points lie in `H`, so `ρ` lies in
/// `[a, b]`: `a` the distance from the axis to the (x, y) projection of `H` (the 2D convex hull
/// of the projected vertices), `b` the largest radius of a vertex; and the plane meets the solid
/// only within `H`'s z range. The bound is the largest tent over `[a, b] ∩ [lo, hi]` of every
/// ring of every column in that range (padded as the overlap test pads, and `a`, `b` widened by
/// a few rounding units).
pub fn stock_hull_depth(shape: &Shape3, poses: &[Iso], stock: &mut DexelStock, view: View) -> f64 {
    let (v, _) = shape.surface();
    let mut pts: Vec<crate::geom::P2> = Vec::with_capacity(v.len() * poses.len());
    let (mut zmin, mut zmax, mut b) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for pose in poses {
        let p = to_pose(pose);
        for &q in v {
            let w = p * q;
            zmin = zmin.min(w.z);
            zmax = zmax.max(w.z);
            b = b.max(w.x.hypot(w.y));
            pts.push(crate::geom::P2::new(w.x, w.y));
        }
    }
    if pts.is_empty() {
        return 0.0;
    }
    if !(zmin.is_finite() && zmax.is_finite() && b.is_finite()) {
        return f64::INFINITY;
    }
    let a = hull_axis_dist(&pts);
    let slack = |r: f64| 1e-9 * (1.0 + r);
    let (a, b) = ((a - slack(a)).max(0.0), b + slack(b));
    let pad = |z: f64| 1e-9 * (1.0 + z.abs());
    let Some((j0, j1)) = stock.columns_within(zmin - pad(zmin), zmax + pad(zmax)) else {
        return 0.0;
    };
    let mut best = 0.0f64;
    for j in j0..=j1 {
        for &(lo, hi) in stock.column_material(j, view) {
            let (x0, x1) = (a.max(lo), b.min(hi));
            if x1 < x0 {
                continue;
            }
            let rho = ((lo + hi) / 2.0).clamp(x0, x1);
            best = best.max((rho - lo).min(hi - rho));
        }
    }
    best
}

/// The distance from the origin to the convex hull of the points (0 inside it).
fn hull_axis_dist(pts: &[crate::geom::P2]) -> f64 {
    let h = crate::tooling::outline::hull(pts);
    let q: Vec<(f64, f64)> = h.iter().map(|p| (p.x, p.y)).collect();
    match q.len() {
        0 => f64::INFINITY,
        1 => q[0].0.hypot(q[0].1),
        2 => seg_dist(q[0], q[1]),
        n => {
            let side = |a: (f64, f64), b: (f64, f64)| a.0 * b.1 - a.1 * b.0;
            let s: Vec<f64> = (0..n).map(|i| side(q[i], q[(i + 1) % n])).collect();
            if s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0) {
                return 0.0;
            }
            (0..n)
                .map(|i| seg_dist(q[i], q[(i + 1) % n]))
                .fold(f64::INFINITY, f64::min)
        }
    }
}
