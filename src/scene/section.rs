//! Another station's tool in the radial section `(r, z)`.
//!
//! A drum turret holds its other stations' tools turned by their station's angle about the
//! turret axis (parallel to the spindle axis). A point of a tool lies in its station's plane,
//! `d` from the turret axis (negative toward the spindle) and at `z`; the turret axis stands
//! `a` from the spindle axis (the reference point's `x` plus `turret_axis`). In 3D the point is
//! at `(a + d cos θ, d sin θ, z)`, so its distance from the spindle axis is
//!
//! ```text
//! r(d) = sqrt((d − d*)² + h²),   d* = −a cos θ,   h = a |sin θ|
//! ```
//!
//! — `h` is how far the station's plane passes from the spindle axis and `d*` the foot of that
//! perpendicular. Along `d`, `r` falls to `h` at `d*` and rises again: the map `(d, z) → (r, z)`
//! folds the station's plane along the line `d = d*`. A tool wholly on one side of that line
//! maps one to one, and its section is the image of its outline (straight edges become curves,
//! cut into chords within the tolerance). A tool across the line folds over itself: the image
//! of its outline is no simple polygon, and its part nearest the spindle axis — the line,
//! at `r = h` — lies inside the outline's image, not on it. So the tool is cut along the line
//! into convex pieces (its convex pieces, each clipped to either side), each of which maps one
//! to one; the section is their images together ([`Section::Folded`]).

use super::Scene;

/// How many times a convex piece whose chords cross is halved before its hull stands for it.
const SPLITS: u32 = 12;
use crate::geom::{convex, Aabb, Polygon, P2, V2};

/// A part in the radial section: one simple polygon, or (another station's tool across the
/// fold of its station's plane) the sections of its pieces, whose union is the part's section.
/// A contact with the part is a contact with one of them; its depth is the deepest piece's and
/// its gap the nearest piece's. (A tool whose outline's image has chords that cross, a thin
/// feature's, is in pieces too: its convex pieces, halved where their own chords cross.)
#[derive(Clone, Debug)]
pub enum Section {
    Whole(Polygon),
    Folded(Vec<Polygon>),
}

impl Section {
    /// The polygons whose union is the section (one for a whole one).
    pub fn pieces(&self) -> &[Polygon] {
        match self {
            Section::Whole(p) => std::slice::from_ref(p),
            Section::Folded(v) => v,
        }
    }

    /// The section as one polygon, when it is one.
    pub fn whole(&self) -> Option<&Polygon> {
        match self {
            Section::Whole(p) => Some(p),
            Section::Folded(_) => None,
        }
    }
}

/// What the box of a shape's section needs of the shape: the range of `d` (its points' distance
/// from the turret axis in the station's plane) and of `z` (from the reference point) over its
/// points, the tip included.
#[derive(Clone, Copy, Debug)]
pub struct Extent {
    pub d: (f64, f64),
    pub z: (f64, f64),
}

impl Extent {
    /// The extent of a shape whose programmed point is `tip` from the reference point, on a
    /// turret whose axis stands `turret_axis` from it.
    pub fn of(shape: &Polygon, tip: V2, turret_axis: f64) -> Extent {
        let mut e = Extent {
            d: (f64::INFINITY, f64::NEG_INFINITY),
            z: (f64::INFINITY, f64::NEG_INFINITY),
        };
        for q in shape.points() {
            let (d, z) = (q.x + tip.x - turret_axis, q.y + tip.y);
            e.d = (e.d.0.min(d), e.d.1.max(d));
            e.z = (e.z.0.min(z), e.z.1.max(z));
        }
        e
    }
}

impl Scene {
    /// A tool shape (relative to its programmed point) in the radial section `(r, z)` when the
    /// turret reference point is at `r_ref` and the tool is turned `angle` out of the working
    /// plane about the turret axis (module docs). At angle 0 this is the folded in-plane shape.
    /// `None` when no piece of it maps to a polygon (a degenerate shape).
    pub fn map_to_section(&self, shape: &Polygon, tip: V2, r_ref: P2, angle: f64) -> Option<Section> {
        let (s, c) = angle.sin_cos();
        let axis_x = r_ref.x + self.turret_axis;
        // The fold line `d = d*` in the shape's own coordinates (`d = q.x + tip.x − turret_axis`).
        let fold = -axis_x * c + self.turret_axis - tip.x;
        let bb = shape.aabb();
        let across = bb.min.x < fold && fold < bb.max.x;
        if !across {
            if let Some(p) = self.map_ring(shape.points(), tip, r_ref, (s, c)) {
                return Some(Section::Whole(p));
            }
            // The chords of a thin feature crossed: the shape in convex pieces, as below.
        }
        let mut out = Vec::new();
        for piece in convex::convex_pieces(shape.points()) {
            if !across {
                self.map_convex(&piece, tip, r_ref, (s, c), SPLITS, &mut out);
                continue;
            }
            for side in [1.0, -1.0] {
                let half = convex::keep_where(&piece, |p: P2| side * (p.x - fold));
                if half.len() >= 3 {
                    self.map_convex(&half, tip, r_ref, (s, c), SPLITS, &mut out);
                }
            }
        }
        (!out.is_empty()).then_some(Section::Folded(out))
    }

    /// The image of a convex ring that does not cross the fold, into `out`: its chords' ring, or,
    /// where the chords of a thin piece cross (no simple ring), the images of its halves (cut
    /// across its longer side), `splits` times at most, and then the hull of its mapped points.
    fn map_convex(&self, ring: &[P2], tip: V2, r_ref: P2, sc: (f64, f64), splits: u32, out: &mut Vec<Polygon>) {
        let pts = self.map_points(ring, tip, r_ref, sc);
        if let Ok(p) = Polygon::new(&pts) {
            out.push(p);
            return;
        }
        let bb = Aabb::of_points(ring);
        if splits == 0 {
            out.extend(Polygon::new(&crate::tooling::outline::hull(&pts)).ok());
            return;
        }
        let wide = bb.max.x - bb.min.x >= bb.max.y - bb.min.y;
        let mid = if wide {
            0.5 * (bb.min.x + bb.max.x)
        } else {
            0.5 * (bb.min.y + bb.max.y)
        };
        for side in [1.0, -1.0] {
            let half = convex::keep_where(ring, |p: P2| side * (if wide { p.x } else { p.y } - mid));
            if half.len() >= 3 {
                self.map_convex(&half, tip, r_ref, sc, splits - 1, out);
            }
        }
    }

    /// A box holding the section of a shape (its extent `e`) turned `angle` out of the working
    /// plane, for every reference point in `rb`; at one reference point, the section's box.
    /// A point's radius `r = sqrt((x + turret_axis + d cos θ)² + (d sin θ)²)` depends on the
    /// reference point's `x` and the point's `d` only, and is convex in them together (the norm
    /// of an affine map): over the shape's `d` range its largest is at an end and its least at
    /// `d*` clamped into the range; over an `x` range the largest is at a corner, and the least at
    /// an end of the range unless `x + turret_axis + d cos θ` passes 0 between them for some `d`,
    /// where `r` falls to `|d sin θ|`, no less than `|sin θ|` times the least `|d|`.
    pub fn section_box(&self, e: &Extent, rb: &Aabb, angle: f64) -> Aabb {
        self.section_box_turned(e, rb, angle.sin_cos())
    }

    /// [`Self::section_box`] with the angle's sine and cosine (`Scene::station_sin_cos`).
    pub fn section_box_turned(&self, e: &Extent, rb: &Aabb, (s, c): (f64, f64)) -> Aabb {
        let t = self.turret_axis;
        let r = |x: f64, d: f64| {
            let (u, v) = (x + t + d * c, d * s);
            (u * u + v * v).sqrt()
        };
        let ((x0, x1), (d0, d1)) = ((rb.min.x, rb.max.x), e.d);
        let hi = r(x0, d0).max(r(x0, d1)).max(r(x1, d0)).max(r(x1, d1));
        let least_at = |x: f64| r(x, (-(x + t) * c).clamp(d0.min(d1), d1.max(d0)));
        let mut lo = least_at(x0).min(least_at(x1));
        let (dc0, dc1) = ((d0 * c).min(d1 * c), (d0 * c).max(d1 * c));
        if x1 > x0 && x0 + t + dc0 < 0.0 && x1 + t + dc1 > 0.0 {
            let least_d = if d0 <= 0.0 && d1 >= 0.0 {
                0.0
            } else {
                d0.abs().min(d1.abs())
            };
            lo = lo.min(s.abs() * least_d);
        }
        Aabb {
            min: P2::new(lo, rb.min.y + e.z.0),
            max: P2::new(hi, rb.max.y + e.z.1),
        }
    }

    /// The image of a ring that does not cross the fold (module docs), its edges cut into chords
    /// within the tolerance.
    fn map_ring(&self, pts: &[P2], tip: V2, r_ref: P2, sc: (f64, f64)) -> Option<Polygon> {
        Polygon::new(&self.map_points(pts, tip, r_ref, sc)).ok()
    }

    /// The points of [`Self::map_ring`]'s ring: each edge's image cut into chords.
    fn map_points(&self, pts: &[P2], tip: V2, r_ref: P2, (s, c): (f64, f64)) -> Vec<P2> {
        let axis_x = r_ref.x + self.turret_axis;
        let n = pts.len();
        let mut out = Vec::with_capacity(n * 4);
        let map = |q: P2| {
            let p = q + tip; // relative to the reference point
            let d = p.x - self.turret_axis; // from the turret axis, in the station's plane
            let x3 = axis_x + d * c;
            let y3 = d * s;
            P2::new((x3 * x3 + y3 * y3).sqrt(), r_ref.y + p.y)
        };
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            // Straight edges map to curves: split so chords stay within the tolerance. Along an
            // edge `r'' = α² h² / r³ ≤ 1 / r` (`α` the edge's slope in `d`), so chords of
            // `sqrt(8 r tol)` at the edge's least radius (an end: no edge crosses the fold) are
            // within `tol` of the curve.
            let len = (b - a).norm();
            let r_least = map(a).x.min(map(b).x).max(1.0);
            let step = (8.0 * r_least * self.tolerance).sqrt().max(0.05);
            let k = ((len / step).ceil() as usize).clamp(1, 64);
            for j in 0..k {
                out.push(map(a + (b - a) * (j as f64 / k as f64)));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::query::{locate, point_segment_distance, Location};
    use crate::geom::Aabb;

    /// The distance from `p` to a polygon's boundary, 0 inside.
    fn outside_by(p: P2, poly: &Polygon) -> f64 {
        if locate(p, poly) != Location::Outside {
            return 0.0;
        }
        poly.edges()
            .map(|(a, b)| point_segment_distance(p, a, b))
            .fold(f64::INFINITY, f64::min)
    }

    /// Every tool of every machine of `machines/` (the built-in one's holders are L and T
    /// shapes), turned to stations' angles and near them, with the turret reference point from
    /// the spindle axis to 300 mm out: the section holds the image of every point of the tool
    /// (within the chords' tolerance), and every point of the section is the image of a point of
    /// the tool (the same). The oracle maps points one by one in 3D: a point of the section at
    /// radius `r` and `z` is the image of the station's plane's points at `d* ± sqrt(r² − h²)`.
    #[test]
    fn a_tool_across_the_fold_of_its_station_plane_has_the_section_its_points_map_to() {
        let mut rnd = crate::test_util::unit_random(7u64);
        let tol = 0.01;
        let (mut folded, mut poses) = (0, 0);
        let mut files: Vec<_> = std::fs::read_dir("machines")
            .unwrap()
            .map(|f| f.unwrap().path())
            .collect();
        files.sort();
        for path in files.iter().filter(|p| p.extension().is_some_and(|e| e == "toml")) {
            let text = std::fs::read_to_string(path).unwrap();
            let Ok(machine) = crate::machine::from_toml(&text, path.to_str().unwrap()) else {
                continue; // a machine whose tree needs its STL files: no drum of 2D tools
            };
            let scene = Scene::new(&machine, tol);
            let n = scene.stations.max(1) as f64;
            for t in &scene.tools {
                for shape in [&t.holder, &t.insert] {
                    for _ in 0..60 {
                        let r_ref = P2::new(300.0 * rnd(), 200.0 * rnd() - 100.0);
                        let k = (rnd() * n).floor();
                        let angle = std::f64::consts::TAU * k / n + 0.2 * (rnd() - 0.5);
                        let Some(sec) = scene.map_to_section(shape, t.tip, r_ref, angle) else {
                            panic!("{path:?} T{}: no section at {r_ref:?}, {angle}", t.station);
                        };
                        poses += 1;
                        folded += usize::from(sec.whole().is_none());
                        let (s, c) = angle.sin_cos();
                        let a = r_ref.x + scene.turret_axis;
                        let d_star = -a * c;
                        let h = a * s.abs();
                        let d_of = |q: P2| q.x + t.tip.x - scene.turret_axis;
                        let image = |q: P2| {
                            let d = d_of(q);
                            P2::new(((d - d_star).powi(2) + h * h).sqrt(), r_ref.y + q.y + t.tip.y)
                        };
                        let bb = shape.aabb();
                        let mut sample = || {
                            P2::new(
                                bb.min.x + (bb.max.x - bb.min.x) * rnd(),
                                bb.min.y + (bb.max.y - bb.min.y) * rnd(),
                            )
                        };
                        // Coverage: the image of every point of the tool.
                        for _ in 0..300 {
                            let q = sample();
                            if locate(q, shape) == Location::Outside {
                                continue;
                            }
                            let m = image(q);
                            let off = sec
                                .pieces()
                                .iter()
                                .map(|p| outside_by(m, p))
                                .fold(f64::INFINITY, f64::min);
                            assert!(off <= 2.0 * tol, "{path:?} T{}: {q:?} maps {off} mm outside", t.station);
                        }
                        // No excess: each point of the section lies within the chords' tolerance of
                        // the image of a point of the tool. Along a line `z` of the tool, its
                        // cross-section's intervals in `d` map to intervals in `r` (down to `h`
                        // where one spans `d*`); a point is near the image when it is near such an
                        // interval on a line within the tolerance of its own `z`.
                        let ranges = |z: f64| -> Vec<(f64, f64)> {
                            let y = z - r_ref.y - t.tip.y;
                            let mut xs: Vec<f64> = shape
                                .edges()
                                .filter(|(a, b)| (a.y > y) != (b.y > y))
                                .map(|(a, b)| a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y))
                                .collect();
                            xs.sort_by(f64::total_cmp);
                            xs.chunks(2)
                                .filter(|w| w.len() == 2)
                                .map(|w| {
                                    let (d0, d1) = (d_of(P2::new(w[0], y)), d_of(P2::new(w[1], y)));
                                    let r = |d: f64| ((d - d_star).powi(2) + h * h).sqrt();
                                    let lo = if d0 <= d_star && d_star <= d1 {
                                        h
                                    } else {
                                        r(d0).min(r(d1))
                                    };
                                    (lo, r(d0).max(r(d1)))
                                })
                                .collect()
                        };
                        let pb = sec.pieces().iter().fold(Aabb::empty(), |b, p| b.union(p.aabb()));
                        for _ in 0..300 {
                            let m = P2::new(
                                pb.min.x + (pb.max.x - pb.min.x) * rnd(),
                                pb.min.y + (pb.max.y - pb.min.y) * rnd(),
                            );
                            if sec.pieces().iter().all(|p| locate(m, p) == Location::Outside) {
                                continue;
                            }
                            let near = (-4..=4).any(|k| {
                                ranges(m.y + 0.5 * tol * k as f64)
                                    .iter()
                                    .any(|&(lo, hi)| m.x >= lo - 2.0 * tol && m.x <= hi + 2.0 * tol)
                            });
                            assert!(near, "{path:?} T{}: {m:?} maps from no point of the tool", t.station);
                        }
                    }
                }
            }
        }
        assert!(poses > 3000 && folded > 100, "{poses} poses, {folded} folded");
    }

    /// A sliver 0.05 mm thin and 30 mm long, turned out of the plane: the chords of its two long
    /// edges' images cross, so its outline maps to no simple polygon (the pose was dropped: a
    /// part that counted as clear). Its halves map: the section holds the image of every point of
    /// it, and no point of the section lies farther than the tolerance from that image.
    #[test]
    fn a_sliver_whose_chords_cross_is_mapped_in_pieces() {
        let machine = crate::machine::Machine::builtin();
        let scene = Scene::new(&machine, 0.01);
        let p = |x: f64, y: f64| P2::new(x, y);
        let shape = Polygon::new(&[
            p(-140.43297707660415, 47.06920774048412),
            p(-118.60255458328484, 26.17032048113946),
            p(-96.85982074102675, 5.3591218728560435),
        ])
        .unwrap();
        let (r_ref, angle, tip) = (p(38.06559579063545, 0.0), 1.6118609454853663f64, V2::zeros());
        let sc = angle.sin_cos();
        assert!(
            scene.map_ring(shape.points(), tip, r_ref, sc).is_none(),
            "the case no longer fails whole"
        );
        let sec = scene.map_to_section(&shape, tip, r_ref, angle).expect("a section");
        let a = r_ref.x + scene.turret_axis;
        let (d_star, h) = (-a * sc.1, a * sc.0.abs());
        let image = |q: P2| {
            let d = q.x + tip.x - scene.turret_axis;
            p(((d - d_star).powi(2) + h * h).sqrt(), r_ref.y + q.y + tip.y)
        };
        let pts = shape.points();
        let mut rnd = crate::test_util::unit_random(5u64);
        let mut images = Vec::new();
        for _ in 0..2000 {
            let (u, v) = (rnd(), rnd());
            let (u, v) = if u + v > 1.0 { (1.0 - u, 1.0 - v) } else { (u, v) };
            let q = pts[0] + (pts[1] - pts[0]) * u + (pts[2] - pts[0]) * v;
            let m = image(q);
            let off = sec
                .pieces()
                .iter()
                .map(|pc| outside_by(m, pc))
                .fold(f64::INFINITY, f64::min);
            assert!(off <= 0.02, "{q:?} maps {off} mm outside the section");
            images.push(m);
        }
        // No excess: every vertex of every piece (the pieces' extreme points) maps back to a
        // point within the tolerance of the sliver (it lies far from the fold here: the inverse
        // map is well conditioned).
        for pc in sec.pieces() {
            for &v in pc.points() {
                let u = (v.x * v.x - h * h).max(0.0).sqrt();
                let z = v.y - r_ref.y - tip.y;
                let near = [d_star + u, d_star - u]
                    .map(|d| outside_by(p(d + scene.turret_axis - tip.x, z), &shape))
                    .into_iter()
                    .fold(f64::INFINITY, f64::min);
                assert!(near <= 0.02, "{v:?} maps back {near} mm from the sliver");
            }
        }
        assert!(!images.is_empty());
    }
}
