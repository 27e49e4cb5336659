//! Static queries between two polygons: point location, distances, overlap and its depth.
//!
//! # Method
//!
//! *Touching or overlapping* is decided exactly. Every decision about topology goes through the
//! exact orientation predicate [`orient`] on the caller's own coordinates, so shared edges, a
//! vertex lying on an edge, or an edge lying on a face are recognised as such however far the
//! parts are from the origin:
//!
//! * [`locate`] is a winding-number test whose only arithmetic is `orient` and comparisons.
//! * [`interiors_overlap`] scans the edge pairs whose boxes meet. A proper crossing means overlap.
//!   Every point where the outlines touch is a vertex of one outline lying on the other; there
//!   the two interiors are, locally, two wedges with a common apex, and whether two wedges share
//!   an open set is decided by `orient` on the input vertices. If the outlines do not meet at all,
//!   one part lies inside the other or they are apart: one point-in-polygon test each way
//!   decides. (If interiors overlap, some piece of one outline runs inside the other part; it
//!   ends at a crossing or at a touching point whose wedges overlap, so the scan is complete.)
//!
//! *Depth and distance* are measured quantities. They are computed after moving both polygons
//! to a local origin (the low corner of their joint box): near 1e7 mm the subtraction is exact
//! (Sterbenz), so the remaining arithmetic works on numbers of the size of the parts and keeps
//! about 1e-13 mm of precision instead of 1e-9.
//!
//! # Penetration depth
//!
//! `depth(A, B) = max(D, R)` with
//!
//! * `D = max( sup { d(p, ∂B) : p ∈ ∂A ∩ B },  sup { d(q, ∂A) : q ∈ ∂B ∩ A } )` — how far the
//!   deepest point of either outline lies inside the other part, and
//! * `R` = the radius of the largest disc inside both parts.
//!
//! Both terms are lower bounds of the minimum translation distance (a point of `∂A` at distance
//! `D` inside `B`, or a disc of radius `R` inside both, keeps the interiors overlapping under any
//! shorter move), so the depth never overstates. It is symmetric, depends only on the two point
//! sets (not on winding, start vertex, duplicate or collinear points), is continuous under
//! motion, is 0 when the parts only touch and > 0 exactly when their interiors overlap.
//!
//! * A corner (or an edge) of one part pushed into a face of the other: `D` is the distance of
//!   the corner from that face — the true penetration (0.001 for a corner 1 µm in).
//! * Two bars crossing with no vertex inside the other: `D` is half the width of the wider bar,
//!   reached where the edges of one bar cross the middle of the other.
//! * Two parts of the same shape nearly on top of each other: `D` is only the offset, but `R` is
//!   about their inradius — why `R` is there.
//!
//! `D` is found edge by edge by branch and bound: the distance from a point moving along a line
//! to one edge is convex, so on a parameter interval the distance to the boundary is bounded by
//! the larger end value of the distance to the edge nearest at either end (exact for runs
//! parallel to an edge) and by the 1-Lipschitz bound; intervals are split where the chords of the
//! two nearest-edge distances cross (the kink, exactly, when both are perpendicular distances).
//! `R` is found by branch and bound over rectangles (the "pole of inaccessibility" search); it is
//! skipped when half the smaller side of the joint box cannot beat `D`, the usual case. Both
//! searches stop within [`DEPTH_TOL`] (plus 1e-4 relative for `R`) or after [`DEPTH_EVALS`]
//! evaluations, when the result is a lower bound. A depth reached at a vertex — the common case
//! — is exact to rounding.

use super::polygon::{orient, segments_meet};
use super::{Aabb, Polygon, P2, TOUCH_EPS, V2};
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// Absolute tolerance of the depth search, mm.
pub const DEPTH_TOL: f64 = 1e-10;
/// Evaluation budget of the depth search along one piece of an edge.
pub const DEPTH_EVALS: usize = 256;

/// Where a point lies with respect to a polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Location {
    /// Strictly inside.
    Inside,
    /// On an edge or a vertex.
    Boundary,
    /// Strictly outside.
    Outside,
}

/// Locate `p` with respect to `poly`. Exact.
pub fn locate(p: P2, poly: &Polygon) -> Location {
    locate_in(p, poly.points())
}

/// Distance from `p` to the closed segment `ab` (`a == b` allowed).
pub fn point_segment_distance(p: P2, a: P2, b: P2) -> f64 {
    let ab = b - a;
    let ap = p - a;
    let l2 = ab.norm_squared();
    if l2 == 0.0 {
        return ap.norm();
    }
    let t = ap.dot(&ab) / l2;
    if t <= 0.0 {
        ap.norm()
    } else if t >= 1.0 {
        (p - b).norm()
    } else {
        // Perpendicular distance; the cross product keeps tiny distances accurate.
        cross(ab, ap).abs() / l2.sqrt()
    }
}

/// Distance between the closed segments `ab` and `cd`: exactly 0 when they meet.
pub fn segment_distance(a: P2, b: P2, c: P2, d: P2) -> f64 {
    if segments_meet(a, b, c, d) {
        return 0.0;
    }
    // Work relative to `a` so that the result does not depend on where the pair lies.
    let o = a;
    let (a, b, c, d) = (P2::from(a - o), P2::from(b - o), P2::from(c - o), P2::from(d - o));
    seg_seg_apart(a, b, c, d)
}

/// Do the interiors of `a` and `b` share a point? Exact; touching is not overlap.
pub fn interiors_overlap(a: &Polygon, b: &Polygon) -> bool {
    if !finite_box(a.aabb()) || !finite_box(b.aabb()) {
        return false;
    }
    interiors_overlap_pts(a.points(), a.aabb(), b.points(), b.aabb())
}

/// The penetration depth of `a` and `b` as defined in the module documentation: > 0 exactly
/// when their interiors overlap, 0 when they touch or are apart.
pub fn penetration_depth(a: &Polygon, b: &Polygon) -> f64 {
    if !interiors_overlap(a, b) {
        return 0.0;
    }
    let o = local_origin(a.aabb(), b.aabb());
    let la = Ring::shifted(a.points(), o);
    let lb = Ring::shifted(b.points(), o);
    depth_rings(&la, &lb)
}

/// `Some(depth)` when the interiors of `a` and `b` overlap by more than [`TOUCH_EPS`]
/// (docs/checking.md), with the penetration depth of the module documentation, in mm. Touching — shared edges
/// or vertices, an edge lying on a face — is `None`.
pub fn overlap(a: &Polygon, b: &Polygon) -> Option<f64> {
    let d = penetration_depth(a, b);
    (d > TOUCH_EPS).then_some(d)
}

/// Euclidean distance between the closed polygons: 0 exactly when they touch or overlap, > 0
/// otherwise (never rounded down to 0 for parts that are apart).
pub fn distance(a: &Polygon, b: &Polygon) -> f64 {
    let (ab, bb) = (a.aabb(), b.aabb());
    if !finite_box(ab) || !finite_box(bb) {
        return f64::INFINITY;
    }
    let (pa, pb) = (a.points(), b.points());
    if ab.meets(bb, 0.0) {
        if outlines_meet(pa, pb, ab, bb) {
            return 0.0;
        }
        // Outlines apart: one inside the other, or apart.
        if locate_in(pa[0], pb) != Location::Outside || locate_in(pb[0], pa) != Location::Outside {
            return 0.0;
        }
    }
    let o = local_origin(ab, bb);
    let la = Ring::shifted(pa, o);
    let lb = Ring::shifted(pb, o);
    let d = ring_distance(&la, &lb);
    if d > 0.0 {
        d
    } else {
        f64::MIN_POSITIVE
    }
}

// ---------------------------------------------------------------------------------------------
// Internals shared with the sweeps.

/// A closed outline in working coordinates with its box; counter-clockwise by construction.
#[derive(Clone, Debug)]
pub(crate) struct Ring {
    pub pts: Vec<P2>,
    pub aabb: Aabb,
}

impl Ring {
    pub fn new(pts: Vec<P2>) -> Ring {
        let aabb = Aabb::of_points(&pts);
        Ring { pts, aabb }
    }

    /// The outline moved by `-o`.
    pub fn shifted(pts: &[P2], o: V2) -> Ring {
        Ring::new(pts.iter().map(|p| p - o).collect())
    }

    pub fn edge(&self, i: usize) -> (P2, P2) {
        let n = self.pts.len();
        (self.pts[i], self.pts[(i + 1) % n])
    }
}

/// Local origin for a pair: the low corner of the joint box.
pub(crate) fn local_origin(a: &Aabb, b: &Aabb) -> V2 {
    V2::new(a.min.x.min(b.min.x), a.min.y.min(b.min.y))
}

pub(crate) fn finite_box(b: &Aabb) -> bool {
    b.min.x.is_finite() && b.min.y.is_finite() && b.max.x.is_finite() && b.max.y.is_finite()
}

pub(crate) fn cross(a: V2, b: V2) -> f64 {
    a.x * b.y - a.y * b.x
}

fn seg_box(a: P2, b: P2) -> Aabb {
    Aabb {
        min: P2::new(a.x.min(b.x), a.y.min(b.y)),
        max: P2::new(a.x.max(b.x), a.y.max(b.y)),
    }
}

/// Do the open boxes overlap (positive-area intersection)?
pub(crate) fn boxes_interiors_meet(a: &Aabb, b: &Aabb) -> bool {
    a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y
}

fn box_distance_sq(a: &Aabb, b: &Aabb) -> f64 {
    let dx = (a.min.x - b.max.x).max(b.min.x - a.max.x).max(0.0);
    let dy = (a.min.y - b.max.y).max(b.min.y - a.max.y).max(0.0);
    dx * dx + dy * dy
}

/// Is `r` inside the closed box of `p`, `q`? (For `r` collinear with `pq`: is it on the segment?)
fn in_seg_box(p: P2, q: P2, r: P2) -> bool {
    r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
}

pub(crate) fn locate_in(p: P2, pts: &[P2]) -> Location {
    let n = pts.len();
    let mut wn: i64 = 0;
    for i in 0..n {
        let a = pts[i];
        let b = pts[(i + 1) % n];
        if (a.y > p.y && b.y > p.y) || (a.y < p.y && b.y < p.y) || (a.x < p.x && b.x < p.x) {
            // Cannot contain p, and cannot cross the ray from p toward +x.
            continue;
        }
        let o = orient(a, b, p);
        if o == 0.0 && in_seg_box(a, b, p) {
            return Location::Boundary;
        }
        if a.y <= p.y {
            if b.y > p.y && o > 0.0 {
                wn += 1;
            }
        } else if b.y <= p.y && o < 0.0 {
            wn -= 1;
        }
    }
    if wn != 0 {
        Location::Inside
    } else {
        Location::Outside
    }
}

/// The interior of a polygon near a point of its outline: the open cone at `apex` from the ray
/// toward `r1` counter-clockwise to the ray toward `r2`. At a vertex `r1` is the next vertex and
/// `r2` the previous one; inside an edge `r1` is its end and `r2` its start (a half plane).
#[derive(Clone, Copy, Debug)]
struct Wedge {
    apex: P2,
    r1: P2,
    r2: P2,
}

impl Wedge {
    /// Is the direction from the apex toward `q` (`q != apex`) strictly inside? Exact.
    fn contains(&self, q: P2) -> bool {
        let turn = orient(self.r2, self.apex, self.r1);
        let l1 = orient(self.apex, self.r1, q) > 0.0;
        let l2 = orient(self.r2, self.apex, q) > 0.0;
        if turn > 0.0 {
            l1 && l2
        } else if turn < 0.0 {
            l1 || l2
        } else {
            l1
        }
    }
}

/// Do `p` and `q` lie in the same direction from `o`? Exact (the sign of a difference of two
/// floats is exact).
fn same_direction(o: P2, p: P2, q: P2) -> bool {
    let sign = |v: f64| (v > 0.0) as i8 - (v < 0.0) as i8;
    orient(o, p, q) == 0.0 && sign(p.x - o.x) == sign(q.x - o.x) && sign(p.y - o.y) == sign(q.y - o.y)
}

/// Do two wedges with a common apex share an open set? Exact. (If they do, either a boundary ray
/// of one lies strictly inside the other, or they start or end on the same ray.)
fn wedges_overlap(a: &Wedge, b: &Wedge) -> bool {
    a.contains(b.r1)
        || a.contains(b.r2)
        || b.contains(a.r1)
        || b.contains(a.r2)
        || same_direction(a.apex, a.r1, b.r1)
        || same_direction(a.apex, a.r2, b.r2)
}

fn vertex_wedge(pts: &[P2], i: usize) -> Wedge {
    let n = pts.len();
    Wedge {
        apex: pts[i],
        r1: pts[(i + 1) % n],
        r2: pts[(i + n - 1) % n],
    }
}

/// Indices of the edges of `pts` whose closed box meets `b`.
fn edges_meeting(pts: &[P2], b: &Aabb, out: &mut Vec<usize>) {
    let n = pts.len();
    out.clear();
    for i in 0..n {
        let (p, q) = (pts[i], pts[(i + 1) % n]);
        if p.x.max(q.x) >= b.min.x && p.x.min(q.x) <= b.max.x && p.y.max(q.y) >= b.min.y && p.y.min(q.y) <= b.max.y {
            out.push(i);
        }
    }
}

/// Exact interior-overlap test on two counter-clockwise simple outlines.
pub(crate) fn interiors_overlap_pts(a: &[P2], ab: &Aabb, b: &[P2], bb: &Aabb) -> bool {
    if !boxes_interiors_meet(ab, bb) || a.len() < 3 || b.len() < 3 {
        return false;
    }
    let (n, m) = (a.len(), b.len());
    let mut ea = Vec::with_capacity(n);
    let mut eb = Vec::with_capacity(16);
    edges_meeting(a, bb, &mut ea);
    edges_meeting(b, ab, &mut eb);
    let mut meet = false;
    for &i in &ea {
        let (a0, a1) = (a[i], a[(i + 1) % n]);
        let abox = seg_box(a0, a1);
        for &j in &eb {
            let (b0, b1) = (b[j], b[(j + 1) % m]);
            if b0.x.max(b1.x) < abox.min.x
                || b0.x.min(b1.x) > abox.max.x
                || b0.y.max(b1.y) < abox.min.y
                || b0.y.min(b1.y) > abox.max.y
            {
                continue;
            }
            let o1 = orient(b0, b1, a0);
            let o2 = orient(b0, b1, a1);
            if (o1 > 0.0 && o2 > 0.0) || (o1 < 0.0 && o2 < 0.0) {
                continue;
            }
            let o3 = orient(a0, a1, b0);
            let o4 = orient(a0, a1, b1);
            if (o3 > 0.0 && o4 > 0.0) || (o3 < 0.0 && o4 < 0.0) {
                continue;
            }
            // The closed segments meet (collinear ones only if their boxes overlap, checked above).
            meet = true;
            if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
                return true; // proper crossing
            }
            // Vertex a0 on edge j (a0 == b1 is handled with edge j + 1, where it is b0).
            if o1 == 0.0 && a0 != b1 && in_seg_box(b0, b1, a0) {
                let wa = vertex_wedge(a, i);
                let wb = if a0 == b0 {
                    vertex_wedge(b, j)
                } else {
                    Wedge {
                        apex: a0,
                        r1: b1,
                        r2: b0,
                    }
                };
                if wedges_overlap(&wa, &wb) {
                    return true;
                }
            }
            // Vertex b0 inside edge i (at a0 or a1 it is a vertex-vertex contact, handled above).
            if o3 == 0.0 && b0 != a0 && b0 != a1 && in_seg_box(a0, a1, b0) {
                let wa = Wedge {
                    apex: b0,
                    r1: a1,
                    r2: a0,
                };
                let wb = vertex_wedge(b, j);
                if wedges_overlap(&wa, &wb) {
                    return true;
                }
            }
        }
    }
    if meet {
        return false;
    }
    locate_in(a[0], b) == Location::Inside || locate_in(b[0], a) == Location::Inside
}

/// Do the closed outlines share a point? Exact.
fn outlines_meet(a: &[P2], b: &[P2], ab: &Aabb, bb: &Aabb) -> bool {
    let (n, m) = (a.len(), b.len());
    let mut ea = Vec::with_capacity(n);
    let mut eb = Vec::with_capacity(16);
    edges_meeting(a, bb, &mut ea);
    edges_meeting(b, ab, &mut eb);
    for &i in &ea {
        let (a0, a1) = (a[i], a[(i + 1) % n]);
        for &j in &eb {
            if segments_meet(a0, a1, b[j], b[(j + 1) % m]) {
                return true;
            }
        }
    }
    false
}

/// Distance between segments known not to meet.
fn seg_seg_apart(a: P2, b: P2, c: P2, d: P2) -> f64 {
    point_segment_distance(a, c, d)
        .min(point_segment_distance(b, c, d))
        .min(point_segment_distance(c, a, b))
        .min(point_segment_distance(d, a, b))
}

/// Distance between two outlines that are apart (no containment, no contact).
fn ring_distance(a: &Ring, b: &Ring) -> f64 {
    let (n, m) = (a.pts.len(), b.pts.len());
    // Order b's edges by their box distance to a's box so that a good bound comes early.
    let mut order: Vec<(f64, usize)> = (0..m)
        .map(|j| (box_distance_sq(&seg_box(b.pts[j], b.pts[(j + 1) % m]), &a.aabb), j))
        .collect();
    order.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut best = f64::INFINITY;
    for &(bd, j) in &order {
        if bd >= best * best {
            break;
        }
        let (b0, b1) = b.edge(j);
        let bbox = seg_box(b0, b1);
        for i in 0..n {
            let (a0, a1) = a.edge(i);
            if box_distance_sq(&seg_box(a0, a1), &bbox) >= best * best {
                continue;
            }
            best = best.min(seg_seg_apart(a0, a1, b0, b1));
        }
    }
    best
}

// ---------------------------------------------------------------------------------------------
// Depth.

/// Depth of two outlines whose interiors overlap (0 if they do not), in shared local coordinates.
pub(crate) fn depth_rings(a: &Ring, b: &Ring) -> f64 {
    depth_rings_above(a, b, f64::INFINITY)
}

/// The depth, or — when the boundary term alone already exceeds `enough` — that term, a lower
/// bound of the depth that is cheaper to get (the sweeps only need to know "deeper than
/// `TOUCH_EPS`" at most of their samples).
pub(crate) fn depth_rings_above(a: &Ring, b: &Ring, enough: f64) -> f64 {
    let d = outline_depth(a, b).max(outline_depth(b, a));
    if d > enough {
        return d;
    }
    d.max(inscribed_radius(a, b, d))
}

/// `sup { d(p, ∂q) : p ∈ ∂p ∩ q }`.
fn outline_depth(p: &Ring, q: &Ring) -> f64 {
    let n = p.pts.len();
    let cand = near_edges(q, &p.aabb);
    let mut best: f64 = 0.0;
    let mut pieces = Vec::new();
    let mut params = Vec::new();
    for i in 0..n {
        let (e0, e1) = p.edge(i);
        let eb = seg_box(e0, e1);
        if !eb.meets(&q.aabb, 0.0) {
            continue;
        }
        inside_pieces(e0, e1, q, &cand, &mut params, &mut pieces);
        for &(s0, s1) in &pieces {
            best = best.max(sup_distance_on_piece(e0, e1, s0, s1, q, &cand, best));
        }
    }
    best
}

/// The edges of `q` that can be nearest to a point of the box `w`. Any edge `f` bounds the
/// distance from a point of `w` to the outline by the largest distance from a corner of `w` to
/// `f` (the distance to a segment is convex); an edge whose box is farther than the smallest such
/// bound can never be nearest. The bound is taken over the edges whose boxes meet `w`.
fn near_edges(q: &Ring, w: &Aabb) -> Vec<usize> {
    let m = q.pts.len();
    let corners = [w.min, P2::new(w.max.x, w.min.y), w.max, P2::new(w.min.x, w.max.y)];
    let mut r = f64::INFINITY;
    for j in 0..m {
        let (f0, f1) = q.edge(j);
        if seg_box(f0, f1).meets(w, 0.0) {
            let rj = corners
                .iter()
                .map(|&c| point_segment_distance(c, f0, f1))
                .fold(0.0, f64::max);
            r = r.min(rj);
        }
    }
    if !r.is_finite() {
        return (0..m).collect();
    }
    let r2 = (r * (1.0 + 1e-12) + 1e-12).powi(2);
    (0..m)
        .filter(|&j| {
            let (f0, f1) = q.edge(j);
            box_distance_sq(&seg_box(f0, f1), w) <= r2
        })
        .collect()
}

/// The parameter intervals of segment `e0 e1` that lie inside `q` (`cand`: the edges of `q` that
/// can meet the segment; point location uses the whole outline).
fn inside_pieces(e0: P2, e1: P2, q: &Ring, cand: &[usize], params: &mut Vec<f64>, out: &mut Vec<(f64, f64)>) {
    out.clear();
    params.clear();
    params.push(0.0);
    params.push(1.0);
    let d = e1 - e0;
    let l2 = d.norm_squared();
    if l2 == 0.0 {
        return;
    }
    let eb = seg_box(e0, e1);
    for &j in cand {
        let (f0, f1) = q.edge(j);
        if f0.x.max(f1.x) < eb.min.x
            || f0.x.min(f1.x) > eb.max.x
            || f0.y.max(f1.y) < eb.min.y
            || f0.y.min(f1.y) > eb.max.y
        {
            continue;
        }
        if !segments_meet(e0, e1, f0, f1) {
            continue;
        }
        // Where e crosses the line of f, from the (accurate, correctly signed) heights of e's
        // ends over that line: well conditioned even for nearly parallel edges, where the
        // textbook cross-product quotient is not.
        let h0 = orient(f0, f1, e0);
        let h1 = orient(f0, f1, e1);
        if h0 == 0.0 && h1 == 0.0 {
            params.push(((f0 - e0).dot(&d) / l2).clamp(0.0, 1.0));
            params.push(((f1 - e0).dot(&d) / l2).clamp(0.0, 1.0));
        } else if h0 == 0.0 {
            params.push(0.0);
        } else if h1 == 0.0 {
            params.push(1.0);
        } else {
            params.push((h0 / (h0 - h1)).clamp(0.0, 1.0));
        }
    }
    params.sort_by(f64::total_cmp);
    params.dedup();
    for w in params.windows(2) {
        let (s0, s1) = (w[0], w[1]);
        if s1 > s0 && locate_in(e0 + d * (0.5 * (s0 + s1)), &q.pts) == Location::Inside {
            out.push((s0, s1));
        }
    }
}

/// Distance from `x` to the boundary of `q` over the edges `cand`, with the index of the nearest.
fn nearest_edge(x: P2, q: &Ring, cand: impl Iterator<Item = usize>) -> (f64, usize) {
    let mut best = f64::INFINITY;
    let mut arg = usize::MAX;
    for j in cand {
        let (f0, f1) = q.edge(j);
        // Box lower bound first.
        let dx = (f0.x.min(f1.x) - x.x).max(x.x - f0.x.max(f1.x)).max(0.0);
        let dy = (f0.y.min(f1.y) - x.y).max(x.y - f0.y.max(f1.y)).max(0.0);
        if dx >= best || dy >= best {
            continue;
        }
        let d = point_segment_distance(x, f0, f1);
        if d < best {
            best = d;
            arg = j;
        }
    }
    (best, arg)
}

#[derive(Clone, Copy)]
struct Sample {
    s: f64,
    g: f64,
    j: usize,
}

struct Interval {
    ub: f64,
    a: Sample,
    b: Sample,
    /// Distance at `b` to the edge nearest at `a`, and at `a` to the edge nearest at `b`.
    ab: f64,
    ba: f64,
    /// Split at the midpoint next (after a split at a predicted kink), to guarantee progress.
    halve: bool,
}

impl PartialEq for Interval {
    fn eq(&self, o: &Self) -> bool {
        self.ub.total_cmp(&o.ub) == Ordering::Equal
    }
}
impl Eq for Interval {}
impl PartialOrd for Interval {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Interval {
    fn cmp(&self, o: &Self) -> Ordering {
        self.ub.total_cmp(&o.ub)
    }
}

/// `sup { d(e(s), ∂q) : s ∈ [s0, s1] }` for a piece of the segment lying inside `q`, by branch
/// and bound (see the module documentation). Values that cannot beat `floor` are pruned.
///
/// An interval whose ends have different nearest edges `i` and `k` is split where the chords of
/// `d_i` and `d_k` cross: where both distances are perpendicular distances (linear in `s`) that
/// is exactly the kink of the lower envelope, so the search usually closes in one step there;
/// every other split is a halving, so the search never stalls.
fn sup_distance_on_piece(e0: P2, e1: P2, s0: f64, s1: f64, q: &Ring, near: &[usize], floor: f64) -> f64 {
    let dir = e1 - e0;
    let len = dir.norm();
    let at = |s: f64| e0 + dir * s;
    let (g0, j0) = nearest_edge(at(s0), q, near.iter().copied());
    let (g1, j1) = nearest_edge(at(s1), q, near.iter().copied());
    if j0 == usize::MAX || j1 == usize::MAX {
        return 0.0;
    }
    let dj = |j: usize, s: f64| {
        let (f0, f1) = q.edge(j);
        point_segment_distance(at(s), f0, f1)
    };
    let make = |a: Sample, b: Sample, halve: bool| -> Interval {
        let ab = dj(a.j, b.s);
        let ba = dj(b.j, a.s);
        let lip = 0.5 * (a.g + b.g + (b.s - a.s) * len);
        let ub = lip.min(a.g.max(ab)).min(b.g.max(ba));
        Interval {
            ub,
            a,
            b,
            ab,
            ba,
            halve,
        }
    };
    let first = make(Sample { s: s0, g: g0, j: j0 }, Sample { s: s1, g: g1, j: j1 }, false);
    let (mut best, mut arg) = if g0 >= g1 { (g0, s0) } else { (g1, s1) };
    // The piece was classified from one rounded point; where it lies within rounding of the
    // outline of q (a nearly collinear edge) that can be wrong, and then the distances measured
    // along it are distances from outside. The deepest point must itself be inside.
    let checked = |best: f64, arg: f64| {
        if best > 0.0 && locate_in(at(arg), &q.pts) != Location::Inside {
            0.0
        } else {
            best
        }
    };
    if first.ub <= best.max(floor) + DEPTH_TOL {
        return checked(best, arg);
    }
    // Only edges that can be nearest somewhere on the piece matter.
    let pbox = seg_box(at(s0), at(s1));
    let top = first.ub * (1.0 + 1e-12) + 1e-12;
    let cand: Vec<usize> = near
        .iter()
        .copied()
        .filter(|&j| {
            let (f0, f1) = q.edge(j);
            box_distance_sq(&seg_box(f0, f1), &pbox) <= top * top
        })
        .collect();
    let mut heap = BinaryHeap::new();
    heap.push(first);
    let mut evals = 0;
    while let Some(iv) = heap.pop() {
        if iv.ub <= best.max(floor) + DEPTH_TOL || evals >= DEPTH_EVALS {
            break;
        }
        let (a, b) = (iv.a, iv.b);
        let mut sm = 0.5 * (a.s + b.s);
        let mut kink = false;
        if !iv.halve && a.j != b.j {
            // Chords: d_a(u) = a.g + (ab - a.g) u, d_b(u) = ba + (b.g - ba) u.
            let den = (iv.ab - a.g) - (b.g - iv.ba);
            let u = (iv.ba - a.g) / den;
            if den > 0.0 && u > 0.02 && u < 0.98 {
                sm = a.s + (b.s - a.s) * u;
                kink = true;
            }
        }
        if sm <= a.s || sm >= b.s {
            continue;
        }
        let (gm, jm) = nearest_edge(at(sm), q, cand.iter().copied());
        evals += 1;
        if jm == usize::MAX {
            continue;
        }
        if gm > best {
            best = gm;
            arg = sm;
        }
        let mid = Sample { s: sm, g: gm, j: jm };
        for (x, y) in [(a, mid), (mid, b)] {
            let child = make(x, y, kink);
            if child.ub > best.max(floor) + DEPTH_TOL {
                heap.push(child);
            }
        }
    }
    checked(best, arg)
}

/// Signed distance from `x` to the outline of `q` (positive inside), over the edges `near`.
fn signed_distance(x: P2, q: &Ring, near: &[usize]) -> f64 {
    let (d, j) = nearest_edge(x, q, near.iter().copied());
    if j == usize::MAX {
        return f64::NEG_INFINITY;
    }
    match locate_in(x, &q.pts) {
        Location::Inside => d,
        Location::Boundary => 0.0,
        Location::Outside => -d,
    }
}

struct Cell {
    ub: f64,
    c: P2,
    hw: f64,
    hh: f64,
}

impl PartialEq for Cell {
    fn eq(&self, o: &Self) -> bool {
        self.ub.total_cmp(&o.ub) == Ordering::Equal
    }
}
impl Eq for Cell {}
impl PartialOrd for Cell {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Cell {
    fn cmp(&self, o: &Self) -> Ordering {
        self.ub.total_cmp(&o.ub)
    }
}

/// Radius of the largest disc inside both `a` and `b` — `max_p min(sd_a(p), sd_b(p))` — when it
/// exceeds `floor`; otherwise some value not above `floor`. Branch and bound over rectangles of the
/// joint box (the function is 1-Lipschitz, so a cell cannot beat its centre value plus its half
/// diagonal), to [`DEPTH_TOL`] plus 1e-4 relative or [`DEPTH_EVALS`] evaluations.
fn inscribed_radius(a: &Ring, b: &Ring, floor: f64) -> f64 {
    let w = Aabb {
        min: P2::new(a.aabb.min.x.max(b.aabb.min.x), a.aabb.min.y.max(b.aabb.min.y)),
        max: P2::new(a.aabb.max.x.min(b.aabb.max.x), a.aabb.max.y.min(b.aabb.max.y)),
    };
    let (hw, hh) = (0.5 * (w.max.x - w.min.x), 0.5 * (w.max.y - w.min.y));
    // A disc inside both fits in the joint box.
    let cap = hw.min(hh);
    if cap.is_nan() || cap <= floor + DEPTH_TOL {
        return 0.0;
    }
    let (na, nb) = (near_edges(a, &w), near_edges(b, &w));
    let f = |x: P2| signed_distance(x, a, &na).min(signed_distance(x, b, &nb));
    let tol = |best: f64| DEPTH_TOL + 1e-4 * best;
    let c = P2::new(w.min.x + hw, w.min.y + hh);
    let fc = f(c);
    let mut best = fc.max(0.0);
    let mut heap = BinaryHeap::new();
    heap.push(Cell {
        ub: (fc + hw.hypot(hh)).min(cap),
        c,
        hw,
        hh,
    });
    let mut evals = 1;
    while let Some(cell) = heap.pop() {
        let bar = best.max(floor);
        if cell.ub <= bar + tol(bar) || evals >= DEPTH_EVALS {
            break;
        }
        // Halve the longer side.
        let (d, hw, hh) = if cell.hw >= cell.hh {
            (V2::new(0.5 * cell.hw, 0.0), 0.5 * cell.hw, cell.hh)
        } else {
            (V2::new(0.0, 0.5 * cell.hh), cell.hw, 0.5 * cell.hh)
        };
        for c in [cell.c - d, cell.c + d] {
            let fc = f(c);
            evals += 1;
            best = best.max(fc);
            let ub = (fc + hw.hypot(hh)).min(cap);
            let bar = best.max(floor);
            if ub > bar + tol(bar) {
                heap.push(Cell { ub, c, hw, hh });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::p2;

    fn poly(pts: &[(f64, f64)]) -> Polygon {
        Polygon::new(&pts.iter().map(|&(x, y)| p2(x, y)).collect::<Vec<_>>()).unwrap()
    }

    #[test]
    fn locate_distinguishes_inside_boundary_outside() {
        let l = poly(&[
            (0.0, 0.0),
            (10.0, 0.0),
            (10.0, 5.0),
            (5.0, 5.0),
            (5.0, 10.0),
            (0.0, 10.0),
        ]);
        assert_eq!(locate(p2(1.0, 1.0), &l), Location::Inside);
        assert_eq!(locate(p2(7.0, 7.0), &l), Location::Outside); // in the notch
        assert_eq!(locate(p2(5.0, 7.0), &l), Location::Boundary);
        assert_eq!(locate(p2(5.0, 5.0), &l), Location::Boundary); // reflex vertex
        assert_eq!(locate(p2(10.0, 0.0), &l), Location::Boundary);
        assert_eq!(locate(p2(7.0, 5.0), &l), Location::Boundary);
        assert_eq!(locate(p2(-1.0, 5.0), &l), Location::Outside);
        assert_eq!(locate(p2(11.0, 5.0), &l), Location::Outside); // level with a horizontal edge
        assert_eq!(locate(p2(4.0, 5.0), &l), Location::Inside);
    }

    #[test]
    fn point_segment_distance_clamps_to_ends() {
        let (a, b) = (p2(0.0, 0.0), p2(10.0, 0.0));
        assert_eq!(point_segment_distance(p2(5.0, 3.0), a, b), 3.0);
        assert_eq!(point_segment_distance(p2(-3.0, 4.0), a, b), 5.0);
        assert_eq!(point_segment_distance(p2(13.0, -4.0), a, b), 5.0);
        assert_eq!(point_segment_distance(p2(1.0, 1.0), a, a), 2f64.sqrt());
        // Far from the origin the perpendicular distance stays exact.
        let o = V2::new(1e7, 1e7);
        let d = point_segment_distance(p2(5.0, 0.001) + o, a + o, b + o);
        assert!((d - 0.001).abs() < 1e-9, "{d}");
    }

    #[test]
    fn segment_distance_is_zero_exactly_when_segments_meet() {
        let d = |a: (f64, f64), b: (f64, f64), c: (f64, f64), e: (f64, f64)| {
            segment_distance(p2(a.0, a.1), p2(b.0, b.1), p2(c.0, c.1), p2(e.0, e.1))
        };
        assert_eq!(d((0.0, 0.0), (2.0, 2.0), (0.0, 2.0), (2.0, 0.0)), 0.0); // crossing
        assert_eq!(d((0.0, 0.0), (2.0, 0.0), (2.0, 0.0), (3.0, 1.0)), 0.0); // shared end
        assert_eq!(d((0.0, 0.0), (2.0, 0.0), (1.0, 0.0), (3.0, 0.0)), 0.0); // collinear overlap
        assert_eq!(d((0.0, 0.0), (2.0, 0.0), (3.0, 0.0), (4.0, 0.0)), 1.0); // collinear apart
        assert_eq!(d((0.0, 0.0), (2.0, 0.0), (1.0, 1.0), (1.0, 3.0)), 1.0); // T, apart
        assert_eq!(d((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)), 1.0); // parallel
        let tiny = d((0.0, 0.0), (2.0, 0.0), (1.0, 1e-300), (1.0, 3.0));
        assert!(tiny > 0.0);
    }

    #[test]
    fn wedge_overlap_covers_shared_rays_and_half_planes() {
        let o = p2(0.0, 0.0);
        let w = |r1: (f64, f64), r2: (f64, f64)| Wedge {
            apex: o,
            r1: p2(r1.0, r1.1),
            r2: p2(r2.0, r2.1),
        };
        // Quadrant I vs quadrant II: share only a ray.
        assert!(!wedges_overlap(&w((1.0, 0.0), (0.0, 1.0)), &w((0.0, 1.0), (-1.0, 0.0))));
        // Identical wedges.
        assert!(wedges_overlap(&w((1.0, 0.0), (0.0, 1.0)), &w((2.0, 0.0), (0.0, 3.0))));
        // Same start ray, different end.
        assert!(wedges_overlap(&w((1.0, 0.0), (0.0, 1.0)), &w((1.0, 0.0), (-1.0, 1.0))));
        // Upper and lower half planes.
        assert!(!wedges_overlap(
            &w((1.0, 0.0), (-1.0, 0.0)),
            &w((-1.0, 0.0), (1.0, 0.0))
        ));
        // Reflex wedge (three quadrants) vs the quadrant IV it leaves out, and vs a wedge
        // straddling its start ray.
        assert!(!wedges_overlap(
            &w((1.0, 0.0), (0.0, -1.0)),
            &w((0.0, -1.0), (1.0, 0.0))
        ));
        assert!(wedges_overlap(&w((1.0, 0.0), (0.0, -1.0)), &w((1.0, -1.0), (1.0, 1.0))));
    }
}
