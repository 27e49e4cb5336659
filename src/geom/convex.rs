//! Convex pieces of a simple polygon and the intersection of convex polygons.
//!
//! The checker proves that a translating part stays in contact over a stretch of a move by a
//! region every pose of the part holds: for a convex piece `K` of the part and a translation
//! along a segment `δ`, the poses `K + sδ` (`0 ≤ s ≤ 1`) all hold `K ∩ (K + δ)` (a point of both
//! lies in every pose between, by convexity). A non-convex part is split into convex pieces
//! first ([`convex_pieces`]).
//!
//! Along an arc, or for a part whose section is not a rigid translate from pose to pose, the
//! poses are no translates along one segment; but when no point of the part's outline moves more
//! than `s` between two poses, every pose holds the piece eroded by `s` ([`erode_convex`]: the
//! points at least `s` inside it).

use super::{orient, P2, V2};

/// Triangles of a counter-clockwise simple polygon, by ear clipping (indices into `pts`).
pub fn triangulate(pts: &[P2]) -> Vec<[u32; 3]> {
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    let mut out = Vec::with_capacity(pts.len().saturating_sub(2));
    let inside =
        |a: P2, b: P2, c: P2, p: P2| orient(a, b, p) >= 0.0 && orient(b, c, p) >= 0.0 && orient(c, a, p) >= 0.0;
    while idx.len() > 3 {
        let n = idx.len();
        let mut clipped = None;
        for i in 0..n {
            let (ia, ib, ic) = (idx[(i + n - 1) % n], idx[i], idx[(i + 1) % n]);
            let (a, b, c) = (pts[ia], pts[ib], pts[ic]);
            if orient(a, b, c) <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&j| {
                j != ia && j != ib && j != ic && pts[j] != a && pts[j] != b && pts[j] != c && inside(a, b, c, pts[j])
            });
            if !blocked {
                clipped = Some(i);
                break;
            }
        }
        // A simple polygon always has an ear; rounding may hide it: clip the first convex corner.
        let i = clipped.unwrap_or_else(|| {
            (0..n)
                .find(|&i| orient(pts[idx[(i + n - 1) % n]], pts[idx[i]], pts[idx[(i + 1) % n]]) > 0.0)
                .unwrap_or(0)
        });
        out.push([idx[(i + n - 1) % n] as u32, idx[i] as u32, idx[(i + 1) % n] as u32]);
        idx.remove(i);
    }
    if idx.len() == 3 {
        out.push([idx[0] as u32, idx[1] as u32, idx[2] as u32]);
    }
    out
}

/// Whether a ring of points (at least 3, either winding) is convex: it turns the same way, or
/// goes straight, at every vertex (exact orientation).
pub fn is_convex(p: &[P2]) -> bool {
    let n = p.len();
    let mut sign = 0.0;
    for i in 0..n {
        let o = orient(p[i], p[(i + 1) % n], p[(i + 2) % n]);
        if o != 0.0 {
            if sign != 0.0 && o.signum() != sign {
                return false;
            }
            sign = o.signum();
        }
    }
    n >= 3
}

/// The region a convex counter-clockwise polygon `ring` sweeps when it moves from `a + ring`
/// to `a + d + ring` in a straight line, written into `out` (counter-clockwise): the edges that
/// face against `d` (outward normal · `d` ≤ 0) at `a`, those that face along it at `a + d`, and
/// at the two vertices where the sides change, the segment along `d` between the poses. This is
/// the union of the two poses and of every edge's quad `p, q, q + d, p + d` (the same vertices,
/// the same arithmetic). Returns false, with `out` left as it was, when the sides do not split
/// in at most two runs (the ring is not convex, or rounding made an edge nearly parallel to `d`
/// change sides twice): the caller then sweeps edge by edge.
pub fn sweep_convex(ring: &[P2], a: P2, d: V2, out: &mut Vec<P2>) -> bool {
    let n = ring.len();
    if n < 3 {
        return false;
    }
    let facing = |i: usize| {
        let (p, q) = (ring[i], ring[(i + 1) % n]);
        // Outward normal of a counter-clockwise edge e: (e.z, -e.x).
        (q.y - p.y) * d.x - (q.x - p.x) * d.y > 0.0
    };
    // Each edge's side found once (an insert has a few edges; a longer ring asks again).
    let mut bits = 0u64;
    if n <= 64 {
        for i in 0..n {
            bits |= u64::from(facing(i)) << i;
        }
    }
    let front = |i: usize| if n <= 64 { bits >> i & 1 == 1 } else { facing(i) };
    let changes = (0..n).filter(|&i| front(i) != front((i + 1) % n)).count();
    if changes > 2 {
        return false;
    }
    let start = out.len();
    let mut before = front(n - 1);
    for (i, q) in ring.iter().enumerate() {
        let after = front(i);
        let at_a = a + q.coords;
        match (before, after) {
            (false, false) => out.push(at_a),
            (true, true) => out.push(at_a + d),
            (false, true) => {
                out.push(at_a);
                out.push(at_a + d);
            }
            (true, false) => {
                out.push(at_a + d);
                out.push(at_a);
            }
        }
        before = after;
    }
    debug_assert!(out.len() - start <= n + 2);
    true
}

/// Convex pieces whose union is a counter-clockwise simple polygon: the polygon itself when it
/// is convex, else its triangles merged across shared edges while the union stays convex (at
/// most a few pieces for a tool holder's L or T shape).
pub fn convex_pieces(pts: &[P2]) -> Vec<Vec<P2>> {
    if is_convex(pts) {
        return vec![pts.to_vec()];
    }
    let mut pieces: Vec<Vec<u32>> = triangulate(pts).into_iter().map(|t| t.to_vec()).collect();
    let ring = |ix: &[u32]| -> Vec<P2> { ix.iter().map(|&i| pts[i as usize]).collect() };
    let mut merged = true;
    while merged {
        merged = false;
        'outer: for a in 0..pieces.len() {
            for b in a + 1..pieces.len() {
                if let Some(u) = union_across_edge(&pieces[a], &pieces[b]) {
                    if is_convex(&ring(&u)) {
                        pieces[a] = u;
                        pieces.swap_remove(b);
                        merged = true;
                        break 'outer;
                    }
                }
            }
        }
    }
    pieces.iter().map(|ix| ring(ix)).collect()
}

/// The ring of two counter-clockwise index rings that share one edge (in opposite directions),
/// joined across it.
fn union_across_edge(a: &[u32], b: &[u32]) -> Option<Vec<u32>> {
    let (na, nb) = (a.len(), b.len());
    for i in 0..na {
        let (p, q) = (a[i], a[(i + 1) % na]);
        if let Some(j) = (0..nb).find(|&j| b[j] == q && b[(j + 1) % nb] == p) {
            // a: … p, q …; b: … q, p …: walk a from q round to p, then b from p round to q.
            let mut out = Vec::with_capacity(na + nb - 2);
            for k in 0..na {
                out.push(a[(i + 1 + k) % na]);
            }
            // b after p up to (not including) q.
            for k in 2..nb {
                out.push(b[(j + k) % nb]);
            }
            return Some(out);
        }
    }
    None
}

/// The intersection of two convex counter-clockwise polygons (Sutherland–Hodgman): a convex
/// counter-clockwise ring, empty (or under 3 points) when they share no area.
pub fn clip_convex(subject: &[P2], clip: &[P2]) -> Vec<P2> {
    let mut out: Vec<P2> = subject.to_vec();
    let n = clip.len();
    let mut input = Vec::with_capacity(out.len() + n);
    for i in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        std::mem::swap(&mut input, &mut out);
        keep_side(&input, &mut out, |p: P2| {
            (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
        });
    }
    out
}

/// The part of a convex ring where the affine function `side` is not negative (one step of
/// Sutherland–Hodgman): a convex ring, under 3 points when that part has no area.
pub fn keep_where(ring: &[P2], side: impl Fn(P2) -> f64) -> Vec<P2> {
    let mut out = Vec::with_capacity(ring.len() + 1);
    keep_side(ring, &mut out, side);
    out
}

/// One step of Sutherland–Hodgman: the part of the ring `input` where `side` is not negative
/// (`side` affine), into `out` (cleared first).
fn keep_side(input: &[P2], out: &mut Vec<P2>, side: impl Fn(P2) -> f64) {
    out.clear();
    let m = input.len();
    for k in 0..m {
        let (p, q) = (input[k], input[(k + 1) % m]);
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            let t = sp / (sp - sq);
            out.push(p + (q - p) * t);
        }
    }
}

/// The points of a convex counter-clockwise polygon at least `s` inside it (`s ≥ 0`): every half
/// plane of an edge moved inwards by `s`. A convex counter-clockwise ring, empty (or under 3
/// points) when the polygon is nowhere that thick.
pub fn erode_convex(k: &[P2], s: f64) -> Vec<P2> {
    let n = k.len();
    let mut out: Vec<P2> = k.to_vec();
    let mut input = Vec::with_capacity(n + 4);
    for i in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (k[i], k[(i + 1) % n]);
        let len = (b - a).norm();
        if len <= 0.0 {
            continue;
        }
        std::mem::swap(&mut input, &mut out);
        // Signed distance to the left of the edge's line, less `s`.
        keep_side(&input, &mut out, |p: P2| {
            ((b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)) / len - s
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::p2;

    fn area(p: &[P2]) -> f64 {
        let n = p.len();
        0.5 * (0..n)
            .map(|i| p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y)
            .sum::<f64>()
    }

    #[test]
    fn two_overlapping_squares_clip_to_their_common_square() {
        let a = [p2(0.0, 0.0), p2(2.0, 0.0), p2(2.0, 2.0), p2(0.0, 2.0)];
        let b = [p2(1.0, 1.0), p2(3.0, 1.0), p2(3.0, 3.0), p2(1.0, 3.0)];
        let c = clip_convex(&a, &b);
        assert!((area(&c) - 1.0).abs() < 1e-12, "{c:?}");
        assert!(clip_convex(&a, &[p2(5.0, 5.0), p2(6.0, 5.0), p2(6.0, 6.0)]).len() < 3);
    }

    #[test]
    fn an_l_shaped_holder_splits_into_convex_pieces_of_its_whole_area() {
        // The built-in boring bar's holder block: a T shape.
        let pts = [
            p2(-15.0, 2.0),
            p2(-4.0, 2.0),
            p2(-3.0, 8.0),
            p2(-3.0, 50.0),
            p2(31.0, 50.0),
            p2(31.0, 110.0),
            p2(-29.0, 110.0),
            p2(-29.0, 50.0),
            p2(-15.0, 50.0),
        ];
        let pieces = convex_pieces(&pts);
        assert!(pieces.len() <= 4, "{pieces:?}");
        assert!(pieces.iter().all(|p| is_convex(p)));
        let total: f64 = pieces.iter().map(|p| area(p)).sum();
        assert!((total - area(&pts)).abs() < 1e-9, "{total} vs {}", area(&pts));
    }

    #[test]
    fn a_square_eroded_by_a_quarter_of_its_side_keeps_its_middle_half() {
        let a = [p2(0.0, 0.0), p2(4.0, 0.0), p2(4.0, 4.0), p2(0.0, 4.0)];
        let e = erode_convex(&a, 1.0);
        assert!((area(&e) - 4.0).abs() < 1e-12, "{e:?}");
        assert!(erode_convex(&a, 2.5).len() < 3);
        assert!((area(&erode_convex(&a, 0.0)) - 16.0).abs() < 1e-12);
    }

    proptest::proptest! {
        /// Every point of a convex piece eroded by `s` lies in every pose of the piece whose
        /// outline moved by at most `s` (here: a translate by up to `s`, in any direction), so the
        /// eroded piece is held by every pose along an arc of length `s`.
        #[test]
        fn the_eroded_piece_lies_in_every_pose_moved_by_at_most_the_erosion(
            pts in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 3..12),
            s in 0.0f64..8.0,
            dir in 0.0f64..std::f64::consts::TAU,
            frac in 0.0f64..=1.0,
        ) {
            let pts: Vec<P2> = pts.into_iter().map(|(x, z)| p2(x, z)).collect();
            let k = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(k.len() >= 3 && area(&k) > 1e-6);
            let e = erode_convex(&k, s);
            let d = crate::geom::V2::new(dir.cos(), dir.sin()) * (s * frac);
            let pose: Vec<P2> = k.iter().map(|q| q + d).collect();
            let n = pose.len();
            for c in &e {
                for i in 0..n {
                    let (a, b) = (pose[i], pose[(i + 1) % n]);
                    let side = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
                    proptest::prop_assert!(side >= -1e-9 * (1.0 + (b - a).norm()), "{c:?} outside the pose moved by {d:?}");
                }
            }
            // Not vacuous: a piece eroded by nothing is itself.
            proptest::prop_assert!((area(&erode_convex(&k, 0.0)) - area(&k)).abs() < 1e-9 * (1.0 + area(&k)));
        }
    }

    /// Crossing-number membership, and the distance to the outline (for the tests' margins).
    fn inside_by(p: &[P2], c: P2) -> (bool, f64) {
        let n = p.len();
        let (mut odd, mut near) = (false, f64::INFINITY);
        for i in 0..n {
            let (a, b) = (p[i], p[(i + 1) % n]);
            if (a.y > c.y) != (b.y > c.y) && c.x < a.x + (b.x - a.x) * ((c.y - a.y) / (b.y - a.y)) {
                odd = !odd;
            }
            near = near.min(crate::geom::point_segment_distance(c, a, b));
        }
        (odd, near)
    }

    #[test]
    fn a_square_swept_along_x_is_a_rectangle_of_six_vertices() {
        let sq = [p2(0.0, 0.0), p2(1.0, 0.0), p2(1.0, 1.0), p2(0.0, 1.0)];
        let mut out = Vec::new();
        assert!(sweep_convex(&sq, p2(0.0, 0.0), V2::new(1.0, 0.0), &mut out));
        assert_eq!(
            out,
            [
                p2(0.0, 0.0),
                p2(1.0, 0.0),
                p2(2.0, 0.0),
                p2(2.0, 1.0),
                p2(1.0, 1.0),
                p2(0.0, 1.0)
            ]
        );
        assert!((area(&out) - 2.0).abs() < 1e-12);
    }

    proptest::proptest! {
        /// The sweep of a convex piece along a segment covers exactly the union of its two poses
        /// and of its edges' quads (what a cut removed before, edge by edge): a point away from
        /// every outline lies in one exactly when it lies in the other.
        #[test]
        fn a_convex_sweep_is_the_union_of_the_poses_and_the_edges_quads(
            pts in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 3..12),
            a in (-50.0f64..50.0, -50.0f64..50.0),
            d in (-15.0f64..15.0, -15.0f64..15.0),
            probes in proptest::collection::vec((-80.0f64..80.0, -80.0f64..80.0), 200),
        ) {
            let pts: Vec<P2> = pts.into_iter().map(|(x, z)| p2(x, z)).collect();
            let k = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(k.len() >= 3 && area(&k) > 1e-6);
            let (a, d) = (p2(a.0, a.1), V2::new(d.0, d.1));
            let mut sw = Vec::new();
            proptest::prop_assert!(sweep_convex(&k, a, d, &mut sw));
            proptest::prop_assert!(sw.len() <= k.len() + 2);
            let n = k.len();
            let mut parts: Vec<Vec<P2>> = vec![
                k.iter().map(|q| a + q.coords).collect(),
                k.iter().map(|q| a + q.coords + d).collect(),
            ];
            for i in 0..n {
                let (p, q) = (a + k[i].coords, a + k[(i + 1) % n].coords);
                parts.push(vec![p, q, q + d, p + d]);
            }
            for (x, z) in probes {
                let c = p2(x, z);
                let (in_sweep, m) = inside_by(&sw, c);
                let mut in_union = false;
                let mut margin = m;
                for part in &parts {
                    let (i, m) = inside_by(part, c);
                    in_union |= i;
                    margin = margin.min(m);
                }
                if margin > 1e-7 {
                    proptest::prop_assert_eq!(in_sweep, in_union, "{:?}", c);
                }
            }
            // Not vacuous: the sweep's area is the pose's and the band's.
            let cross = k.iter().map(|p| p.x * d.y - p.y * d.x);
            let width = cross.clone().fold(f64::NEG_INFINITY, f64::max) - cross.fold(f64::INFINITY, f64::min);
            proptest::prop_assert!((area(&sw) - area(&k) - width).abs() < 1e-6 * (1.0 + area(&sw)), "{} {}", area(&sw), width);
        }
    }

    proptest::proptest! {
        /// The common region of a convex piece and its translate lies in every pose between
        /// them (what the checker's proof of a stretch in contact rests on).
        #[test]
        fn the_common_region_of_two_poses_lies_in_every_pose_between(
            pts in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 3..12),
            d in (-15.0f64..15.0, -15.0f64..15.0),
            s in 0.0f64..=1.0,
        ) {
            let pts: Vec<P2> = pts.into_iter().map(|(x, z)| p2(x, z)).collect();
            let k = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(k.len() >= 3 && area(&k) > 1e-6);
            let d = crate::geom::V2::new(d.0, d.1);
            let moved: Vec<P2> = k.iter().map(|q| q + d).collect();
            let common = clip_convex(&k, &moved);
            // Not vacuous: with no translation the common region is the piece itself.
            proptest::prop_assert!(is_convex(&k));
            proptest::prop_assert!((area(&clip_convex(&k, &k)) - area(&k)).abs() < 1e-9 * (1.0 + area(&k)));
            let pose: Vec<P2> = k.iter().map(|q| q + d * s).collect();
            let n = pose.len();
            for c in &common {
                for i in 0..n {
                    let (a, b) = (pose[i], pose[(i + 1) % n]);
                    let side = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
                    proptest::prop_assert!(side >= -1e-9 * (1.0 + (b - a).norm()), "{c:?} outside the pose at {s}");
                }
            }
        }
    }
}
