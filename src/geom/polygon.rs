//! Simple polygons: normalisation and validation.

use super::{Aabb, P2};
use robust::{orient2d, Coord};

/// A simple polygon, counter-clockwise (positive area, `x` right, `y` up), with no repeated and no
/// collinear consecutive vertices. Construct it with [`Polygon::new`].
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    pts: Vec<P2>,
    aabb: Aabb,
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PolygonError {
    #[error("a coordinate is not a finite number")]
    NotFinite,
    #[error("fewer than 3 distinct, non-collinear points")]
    Degenerate,
    #[error("edges {0} and {1} cross or touch: the outline intersects itself")]
    SelfIntersecting(usize, usize),
}

/// Sign of the turn a→b→c: > 0 left (counter-clockwise), < 0 right, 0 collinear. Exact.
pub fn orient(a: P2, b: P2, c: P2) -> f64 {
    orient2d(
        Coord { x: a.x, y: a.y },
        Coord { x: b.x, y: b.y },
        Coord { x: c.x, y: c.y },
    )
}

impl Polygon {
    /// Normalise an outline: drop repeated points and collinear vertices, make it
    /// counter-clockwise, and reject it if it is degenerate or self-intersecting.
    pub fn new(points: &[P2]) -> Result<Polygon, PolygonError> {
        if points.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) {
            return Err(PolygonError::NotFinite);
        }
        let mut pts: Vec<P2> = Vec::with_capacity(points.len());
        for &p in points {
            if pts.last() != Some(&p) {
                pts.push(p);
            }
        }
        while pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        // Remove collinear vertices until none is left (removing one can make its neighbour
        // collinear, e.g. a spike that doubles back).
        loop {
            let n = pts.len();
            if n < 3 {
                return Err(PolygonError::Degenerate);
            }
            let mut removed = false;
            let mut out = Vec::with_capacity(n);
            for i in 0..n {
                let prev = if out.is_empty() {
                    pts[(i + n - 1) % n]
                } else {
                    *out.last().unwrap()
                };
                let cur = pts[i];
                let next = pts[(i + 1) % n];
                if orient(prev, cur, next) == 0.0 {
                    removed = true;
                } else {
                    out.push(cur);
                }
            }
            pts = out;
            if !removed {
                break;
            }
        }
        if pts.len() < 3 {
            return Err(PolygonError::Degenerate);
        }
        if signed_area2(&pts) < 0.0 {
            pts.reverse();
        }
        check_simple(&pts)?;
        let aabb = Aabb::of_points(&pts);
        Ok(Polygon { pts, aabb })
    }

    pub fn points(&self) -> &[P2] {
        &self.pts
    }

    pub fn aabb(&self) -> &Aabb {
        &self.aabb
    }

    /// Twice the signed area (positive: counter-clockwise).
    pub fn area(&self) -> f64 {
        signed_area2(&self.pts) / 2.0
    }

    /// Edges as (start, end) pairs, closing edge included.
    pub fn edges(&self) -> impl Iterator<Item = (P2, P2)> + '_ {
        let n = self.pts.len();
        (0..n).map(move |i| (self.pts[i], self.pts[(i + 1) % n]))
    }

    /// The polygon mirrored about the spindle axis (x → −x), still counter-clockwise.
    pub fn mirrored_x(&self) -> Polygon {
        let mut pts: Vec<P2> = self.pts.iter().map(|p| P2::new(-p.x, p.y)).collect();
        pts.reverse();
        let aabb = Aabb::of_points(&pts);
        Polygon { pts, aabb }
    }

    /// The polygon moved by `v`. Translation keeps it simple and counter-clockwise; collinearity
    /// after rounding is harmless.
    pub fn translated(&self, v: super::V2) -> Polygon {
        let pts: Vec<P2> = self.pts.iter().map(|p| p + v).collect();
        Polygon {
            aabb: self.aabb.translate(v),
            pts,
        }
    }
}

fn signed_area2(pts: &[P2]) -> f64 {
    let n = pts.len();
    // Shoelace about the first point, to keep precision far from the origin.
    let o = pts[0];
    let mut s = 0.0;
    for i in 1..n.saturating_sub(1) {
        let a = pts[i] - o;
        let b = pts[i + 1] - o;
        s += a.x * b.y - a.y * b.x;
    }
    s
}

/// Do closed segments ab and cd share a point? Exact.
pub fn segments_meet(a: P2, b: P2, c: P2, d: P2) -> bool {
    let d1 = orient(c, d, a);
    let d2 = orient(c, d, b);
    let d3 = orient(a, b, c);
    let d4 = orient(a, b, d);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return true;
    }
    let on = |p: P2, q: P2, r: P2| {
        // r collinear with pq: is it within the box of pq?
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    (d1 == 0.0 && on(c, d, a)) || (d2 == 0.0 && on(c, d, b)) || (d3 == 0.0 && on(a, b, c)) || (d4 == 0.0 && on(a, b, d))
}

fn check_simple(pts: &[P2]) -> Result<(), PolygonError> {
    // Sweep and prune: edges sorted by their boxes' least x, each compared only with the edges
    // after it whose boxes overlap its own (two segments that meet share a point, which lies in
    // both boxes). A crossing found is reported as the scan of every pair reports it: the first
    // in the order of edge indices.
    let n = pts.len();
    let boxes: Vec<[f64; 4]> = (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            [a.x.min(b.x), a.x.max(b.x), a.y.min(b.y), a.y.max(b.y)]
        })
        .collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_unstable_by(|&i, &j| boxes[i][0].total_cmp(&boxes[j][0]));
    for (k, &i) in order.iter().enumerate() {
        let bi = boxes[i];
        for &j in &order[k + 1..] {
            let bj = boxes[j];
            if bj[0] > bi[1] {
                break;
            }
            if bj[2] > bi[3] || bj[3] < bi[2] {
                continue;
            }
            let (lo, hi) = (i.min(j), i.max(j));
            if meet_apart(pts, lo, hi) {
                return check_simple_every_pair(pts);
            }
        }
    }
    Ok(())
}

/// Whether edges `i < j` that are not adjacent meet. Adjacent edges share a vertex by
/// construction; they are bad only if they overlap (a spike), which collinear removal already
/// ruled out.
fn meet_apart(pts: &[P2], i: usize, j: usize) -> bool {
    let n = pts.len();
    if j == i + 1 || (i == 0 && j == n - 1) {
        return false;
    }
    segments_meet(pts[i], pts[(i + 1) % n], pts[j], pts[(j + 1) % n])
}

/// Every pair of edges in index order: the first pair that meets (the oracle of the sweep, and
/// the pair it reports).
fn check_simple_every_pair(pts: &[P2]) -> Result<(), PolygonError> {
    let n = pts.len();
    for i in 0..n {
        for j in (i + 1)..n {
            if meet_apart(pts, i, j) {
                return Err(PolygonError::SelfIntersecting(i, j));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        /// The sweep finds what comparing every pair of edges finds, and the same pair: rings of
        /// up to 40 points on a coarse grid (crossings, touching vertices, collinear overlaps)
        /// or spread wide (mostly simple), scaled so boxes meet only at their edges too.
        #[test]
        fn the_sweep_finds_the_crossing_every_pair_finds(
            pts in prop::collection::vec((0i32..8, 0i32..8), 3..40),
            spread in prop_oneof![Just(1.0f64), Just(0.37), Just(1e3)],
        ) {
            let ring: Vec<P2> = pts.iter().map(|&(x, y)| P2::new(x as f64 * spread, y as f64 * spread)).collect();
            prop_assert_eq!(check_simple(&ring), check_simple_every_pair(&ring));
        }
    }

    #[test]
    fn a_bow_tie_is_refused_and_a_square_kept() {
        let p = |x: f64, y: f64| P2::new(x, y);
        let bow = [p(0.0, 0.0), p(1.0, 1.0), p(1.0, 0.0), p(0.0, 1.0)];
        assert_eq!(check_simple(&bow), Err(PolygonError::SelfIntersecting(0, 2)));
        assert!(Polygon::new(&bow).is_err());
        let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
        assert_eq!(check_simple(&square), Ok(()));
    }
}
