//! Outlines of inserts and holders, built in one canonical frame and then mirrored.
//!
//! The canonical frame is a right-hand external tool on a rear turret: tip at the origin, the
//! insert toward +x (the turret) and +z (away from the chuck), the shank standing along +x. A
//! left-hand tool is its mirror in z, a boring bar its mirror in x (the bar then lies along +z
//! on the −x side of the tip).

use crate::geom::{Polygon, P2, V2};

/// Angles in degrees, measured counter-clockwise from +x toward +z (the kernel's x and y).
pub fn dir(deg: f64) -> P2 {
    let (s, c) = deg.to_radians().sin_cos();
    P2::new(c, s)
}

/// Walk from the origin: first along `start` degrees for `sides[0]`, then at each vertex turn
/// left by 180° less that vertex's interior angle. `interior[i]` is the angle at the vertex
/// after side `i`. Counter-clockwise when the interior angles are.
pub fn walk(start: f64, sides: &[f64], interior: &[f64]) -> Vec<P2> {
    let mut pts = vec![P2::new(0.0, 0.0)];
    let mut heading = start;
    let mut p = P2::new(0.0, 0.0);
    for (i, &len) in sides.iter().enumerate() {
        let d = dir(heading);
        p = P2::new(p.x + d.x * len, p.y + d.y * len);
        if i + 1 < sides.len() {
            pts.push(p);
            heading += 180.0 - interior[i];
        }
    }
    pts
}

/// Convex hull (counter-clockwise, no collinear points) of a set of points.
pub fn hull(points: &[P2]) -> Vec<P2> {
    let mut p: Vec<P2> = points
        .iter()
        .copied()
        .filter(|q| q.x.is_finite() && q.y.is_finite())
        .collect();
    p.sort_by(by_x_then_y);
    hull_of_sorted(p)
}

/// The order [`hull`] sorts its points in.
fn by_x_then_y(a: &P2, b: &P2) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y))
}

/// [`hull`] of finite points already in its order: Andrew's monotone chains.
fn hull_of_sorted(mut p: Vec<P2>) -> Vec<P2> {
    let n = dedup_sorted(&mut p);
    hull_of_deduped(&p[..n])
}

/// Drops the repeats of sorted points in place (as `Vec::dedup` does); returns how many are
/// left at the front.
fn dedup_sorted(p: &mut [P2]) -> usize {
    if p.is_empty() {
        return 0;
    }
    let mut n = 1;
    for i in 1..p.len() {
        if p[i] != p[n - 1] {
            p[n] = p[i];
            n += 1;
        }
    }
    n
}

/// Andrew's monotone chains over sorted points without repeats, into one buffer: the lower
/// chain, then the upper one pushed onto it (popping only its own points), less the first
/// point it comes back to. The same vertices, in the same order, as a lower and an upper
/// chain built apart and joined.
fn hull_of_deduped(p: &[P2]) -> Vec<P2> {
    if p.len() < 3 {
        return p.to_vec();
    }
    let cross = |o: P2, a: P2, b: P2| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    let mut h: Vec<P2> = Vec::with_capacity(2 * p.len());
    for &q in p {
        while h.len() >= 2 && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
            h.pop();
        }
        h.push(q);
    }
    // The upper chain begins at the last point, the lower chain's end.
    let base = h.len();
    for &q in p.iter().rev().skip(1) {
        while h.len() > base && cross(h[h.len() - 2], h[h.len() - 1], q) <= 0.0 {
            h.pop();
        }
        h.push(q);
    }
    h.pop();
    h
}

/// How many points [`hull_of_translates`] merges on the stack (a holder's or an insert's
/// outline and one or two translates of it).
const SMALL_HULL: usize = 24;

/// [`hull`] of the points of `base` (with `with_base`) and of `q + c` for every `q` of `base`
/// and `c` of `offsets` (a part's poses along a path, translated): the same polygon, bit for
/// bit, without sorting them all. The translates of one sorted `base` are sorted too (rounding
/// is monotone) unless a rounding tie reorders two of them, which a check finds and a sort
/// mends; sorted runs merge in linear time. A few points are merged on the stack.
pub fn hull_of_translates(base: &[P2], with_base: bool, offsets: &[V2]) -> Vec<P2> {
    let n = base.len();
    let finite = |q: &P2| q.x.is_finite() && q.y.is_finite();
    let plain = || {
        let mut all: Vec<P2> = if with_base { base.to_vec() } else { Vec::new() };
        for c in offsets {
            all.extend(base.iter().map(|q| q + c));
        }
        hull(&all)
    };
    if !base.iter().all(finite) {
        return plain();
    }
    let total = n * (offsets.len() + usize::from(with_base));
    // The buffers: on the stack for a few points, else on the heap.
    let origin = P2::origin();
    let (mut small, mut large);
    let [sorted, run, a, b]: [&mut [P2]; 4] = if n <= SMALL_HULL && total <= SMALL_HULL {
        small = [[origin; SMALL_HULL]; 4];
        let [s, r, a, b] = &mut small;
        [&mut s[..n], &mut r[..n], &mut a[..], &mut b[..]]
    } else {
        large = [
            vec![origin; n],
            vec![origin; n],
            vec![origin; total],
            vec![origin; total],
        ];
        let [s, r, a, b] = &mut large;
        [&mut s[..], &mut r[..], &mut a[..], &mut b[..]]
    };
    let Some(merged) = merge_translates(base, with_base, offsets, sorted, run, a, b) else {
        return plain();
    };
    let kept = dedup_sorted(merged);
    hull_of_deduped(&merged[..kept])
}

/// The points of `base` (with `with_base`) and its translates by `offsets`, merged in the order
/// [`hull`] sorts them into one of `a` and `b` (each long enough for all of them; `sorted` and
/// `run` as long as `base`): the points, or `None` when a translate is not finite.
fn merge_translates<'a>(
    base: &[P2],
    with_base: bool,
    offsets: &[V2],
    sorted: &mut [P2],
    run: &mut [P2],
    a: &'a mut [P2],
    b: &'a mut [P2],
) -> Option<&'a mut [P2]> {
    let n = base.len();
    sorted.copy_from_slice(base);
    sorted.sort_by(by_x_then_y);
    let (mut merged, mut out) = (a, b);
    let mut len = 0;
    if with_base {
        merged[..n].copy_from_slice(sorted);
        len = n;
    }
    for c in offsets {
        for (r, q) in run.iter_mut().zip(sorted.iter()) {
            *r = q + c;
        }
        if !run.iter().all(|q| q.x.is_finite() && q.y.is_finite()) {
            return None;
        }
        if run.windows(2).any(|w| by_x_then_y(&w[0], &w[1]).is_gt()) {
            run.sort_by(by_x_then_y);
        }
        len = merge_sorted(&merged[..len], run, out);
        std::mem::swap(&mut merged, &mut out);
    }
    Some(&mut merged[..len])
}

/// Merges two sorted runs into `out` (long enough for both), a point of `run` before an equal
/// one of `merged`; returns how many points it wrote.
fn merge_sorted(merged: &[P2], run: &[P2], out: &mut [P2]) -> usize {
    let (mut i, mut j, mut k) = (0, 0, 0);
    while i < merged.len() && j < run.len() {
        if by_x_then_y(&run[j], &merged[i]).is_lt() {
            out[k] = run[j];
            j += 1;
        } else {
            out[k] = merged[i];
            i += 1;
        }
        k += 1;
    }
    for &q in merged[i..].iter().chain(&run[j..]) {
        out[k] = q;
        k += 1;
    }
    k
}

/// Whether `p` lies in the closed cone from direction `lo` counter-clockwise to `hi` (degrees,
/// `hi` − `lo` < 180).
pub fn in_cone(p: P2, lo: f64, hi: f64) -> bool {
    let a = dir(lo);
    let b = dir(hi);
    a.x * p.y - a.y * p.x >= -1e-12 && p.x * b.y - p.y * b.x >= -1e-12
}

/// The points scaled toward their centroid (a holder seat a little inside the insert).
pub fn shrink(points: &[P2], f: f64) -> Vec<P2> {
    let n = points.len().max(1) as f64;
    let cx = points.iter().map(|p| p.x).sum::<f64>() / n;
    let cy = points.iter().map(|p| p.y).sum::<f64>() / n;
    points
        .iter()
        .map(|p| P2::new(cx + (p.x - cx) * f, cy + (p.y - cy) * f))
        .collect()
}

/// Mirror in z (a left-hand tool).
pub fn mirror_z(points: &[P2]) -> Vec<P2> {
    points.iter().map(|p| P2::new(p.x, -p.y)).collect()
}

/// Mirror in x (a boring bar or an internal tool).
pub fn mirror_x(points: &[P2]) -> Vec<P2> {
    points.iter().map(|p| P2::new(-p.x, p.y)).collect()
}

/// A polygon from points that were built to be simple, or why not (a message).
pub fn polygon(what: &str, points: &[P2]) -> Result<Polygon, String> {
    // Rounded to 1e-9 mm so that outlines print and compare cleanly.
    let pts: Vec<P2> = points
        .iter()
        .map(|p| P2::new((p.x * 1e9).round() / 1e9 + 0.0, (p.y * 1e9).round() / 1e9 + 0.0))
        .collect();
    Polygon::new(&pts).map_err(|e| format!("the {what} outline cannot be built: {e}"))
}

/// Whether `p` is strictly inside a convex counter-clockwise polygon.
pub fn strictly_inside_convex(poly: &[P2], p: P2) -> bool {
    let n = poly.len();
    n >= 3
        && (0..n).all(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x) > 1e-9
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

        /// The monotone chains built in one buffer are the textbook's two chains joined, bit for
        /// bit (the oracle), on points snapped to grids (collinear runs, ties in x).
        #[test]
        fn the_one_buffer_chains_are_the_two_chains_joined(
            raw in proptest::collection::vec((-30.0f64..30.0, -30.0f64..30.0), 0..40),
            grid in proptest::sample::select(vec![0.0, 0.5, 1.0, 5.0]),
        ) {
            let snap = |v: f64| if grid > 0.0 { (v / grid).round() * grid } else { v };
            let mut p: Vec<P2> = raw.iter().map(|&(x, y)| P2::new(snap(x), snap(y))).collect();
            p.sort_by(by_x_then_y);
            p.dedup();
            // The chains built apart, the lower one's last point and the upper one's last
            // dropped where they join (the textbook form of Andrew's algorithm).
            let two_chains = |p: &[P2]| -> Vec<P2> {
                if p.len() < 3 {
                    return p.to_vec();
                }
                let cross = |o: P2, a: P2, b: P2| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
                let mut lower: Vec<P2> = Vec::new();
                for &q in p {
                    while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], q) <= 0.0 {
                        lower.pop();
                    }
                    lower.push(q);
                }
                let mut upper: Vec<P2> = Vec::new();
                for &q in p.iter().rev() {
                    while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], q) <= 0.0 {
                        upper.pop();
                    }
                    upper.push(q);
                }
                lower.pop();
                upper.pop();
                lower.extend(upper);
                lower
            };
            let bits = |h: Vec<P2>| -> Vec<(u64, u64)> { h.iter().map(|q| (q.x.to_bits(), q.y.to_bits())).collect() };
            proptest::prop_assert_eq!(bits(hull_of_deduped(&p)), bits(two_chains(&p)));
        }

        /// The hull of a part's translates, merged from sorted runs, is bit for bit the hull of
        /// all their points sorted together (the oracle): on coordinates snapped to a grid (ties,
        /// repeated points, collinear edges), zeros of either sign, offsets of zero, and no
        /// offsets at all; outlines of a few points (merged on the stack) and of many.
        #[test]
        fn the_hull_of_translates_is_the_hull_of_all_their_points(
            raw in proptest::collection::vec((-30.0f64..30.0, -30.0f64..30.0), 1..30),
            offsets in proptest::collection::vec((-20.0f64..20.0, -20.0f64..20.0), 0..5),
            grid in proptest::sample::select(vec![0.0, 0.5, 1.0]),
            with_base in proptest::bool::ANY,
            negative_zero in proptest::bool::ANY,
        ) {
            let snap = |v: f64| {
                let v = if grid > 0.0 { (v / grid).round() * grid } else { v };
                if v == 0.0 && negative_zero { -0.0 } else { v }
            };
            let base: Vec<P2> = raw.iter().map(|&(x, y)| P2::new(snap(x), snap(y))).collect();
            let offsets: Vec<V2> = offsets.iter().map(|&(x, y)| V2::new(snap(x), snap(y))).collect();
            let mut all: Vec<P2> = if with_base { base.clone() } else { Vec::new() };
            for c in &offsets {
                all.extend(base.iter().map(|q| q + c));
            }
            let bits = |h: Vec<P2>| -> Vec<(u64, u64)> { h.iter().map(|q| (q.x.to_bits(), q.y.to_bits())).collect() };
            proptest::prop_assert_eq!(bits(hull_of_translates(&base, with_base, &offsets)), bits(hull(&all)));
        }
    }
}
