//! A posed component against the milled stock (`grid::Stock`).
//!
//! The stock's material lies on its cylindrical grid's rays (every grid cuts the cylindrical
//! grid's material down; a block without one: its first face grid's rays). The query walks the
//! rays of the nodes under the component's box (in the part's frame: the spindle turned by C),
//! finds each ray's stretches inside the component (boundary crossings by ray casting, the start
//! by point containment), and keeps those that meet the ray's material and that every grid
//! calls material (sampled at the grid's spacing). The depth of a run of material inside the
//! component is its middle point's distance to the component's boundary; the hit is the deepest,
//! and only depths above `eps` count (the caller passes the grid's resolution: a milled wall
//! stands up to a node spacing off the cutter's true surface). An overlap narrower than a node's
//! spacing across the rays can pass between them: the query resolves what the grid resolves.

use nalgebra::Vector3;
use parry3d_f64::math::Vector;
use parry3d_f64::query::Ray;

use super::{to_pose, Hit, Shape3, BEYOND_MM};
use crate::grid::Stock;
use crate::kin::Iso;
use crate::scene::DexelStock;

/// Most boundary crossings followed along one ray.
const MAX_CROSSINGS: usize = 64;

/// Most rays a depth search ranks by their bound (16 bytes each); a longer walk goes in its own
/// order (the same answer, more rays cast).
const MAX_RANKED: usize = 1 << 20;

/// The stretches of the ray `o + t·u`, `t ∈ [t0, t1]`, inside the shape (posed at `pose`); both
/// ends of the ray lie outside the shape.
fn inside_stretches(
    shape: &Shape3,
    pose: &parry3d_f64::math::Pose,
    o: Vector3<f64>,
    u: Vector3<f64>,
    t0: f64,
    t1: f64,
    out: &mut Vec<(f64, f64)>,
) {
    out.clear();
    let (s, pos) = shape.parts(pose);
    let at = |t: f64| Vector::new(o.x + t * u.x, o.y + t * u.y, o.z + t * u.z);
    let dir = Vector::new(u.x, u.y, u.z);
    if let Some(iv) = shape.line_interval(pose, at(0.0), dir, t0, t1) {
        // A cylinder or a box: its stretch in closed form.
        out.extend(iv);
        return;
    }
    if shape.is_convex() {
        // One stretch at most: in from one end, out from the other.
        let fwd = s.cast_ray(&pos, &Ray::new(at(t0), dir), t1 - t0, false);
        let back = s.cast_ray(&pos, &Ray::new(at(t1), -dir), t1 - t0, false);
        if let (Some(a), Some(b)) = (fwd, back) {
            if t1 - b > t0 + a {
                out.push((t0 + a, t1 - b));
            }
        }
        return;
    }
    let mut t = t0;
    let mut inside = false;
    let mut start = t;
    // Two crossings this close may be one counted twice (a ray through an edge or a vertex).
    let mut doubtful = false;
    let mut last = f64::NEG_INFINITY;
    for _ in 0..MAX_CROSSINGS {
        let ray = Ray::new(at(t), dir);
        match s.cast_ray(&pos, &ray, t1 - t, false) {
            Some(toi) if t + toi < t1 => {
                let th = t + toi;
                doubtful |= th - last < 1e-3;
                last = th;
                if inside {
                    out.push((start, th));
                } else {
                    start = th;
                }
                inside = !inside;
                // Past the crossing by more than a grazing ray's second hit on the neighbouring
                // triangle of the same edge.
                t = th + 1e-5;
                if t >= t1 {
                    break;
                }
            }
            _ => break,
        }
    }
    // Both ends are outside: an odd count is a crossing counted twice (or a missed one).
    if inside {
        doubtful = true;
        out.push((start, t1));
    }
    if doubtful {
        // Each stretch must hold the solid at its middle; between two stretches that do not, the
        // gap may be solid too: rebuild from containment at the crossings' midpoints.
        let mut cuts: Vec<f64> = std::iter::once(t0)
            .chain(out.iter().flat_map(|&(a, b)| [a, b]))
            .chain(std::iter::once(t1))
            .collect();
        cuts.dedup();
        out.clear();
        for w in cuts.windows(2) {
            let (a, b) = (w[0], w[1]);
            if b > a && s.contains_point(&pos, at((a + b) / 2.0)) {
                match out.last_mut() {
                    Some(l) if l.1 == a => l.1 = b,
                    _ => out.push((a, b)),
                }
            }
        }
    }
}

/// The grid whose node rays carry a query.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Rays {
    Cyl,
    Face(usize),
}

/// The stretch `[t0, t1]` of the ray `o + t·u` inside the box `[min, max]`, within `[lo, hi]`.
fn slab(
    o: Vector3<f64>,
    u: Vector3<f64>,
    min: &Vector3<f64>,
    max: &Vector3<f64>,
    lo: f64,
    hi: f64,
) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (lo, hi);
    for k in 0..3 {
        if u[k].abs() < 1e-15 {
            if o[k] < min[k] || o[k] > max[k] {
                return None;
            }
        } else {
            let (x0, x1) = ((min[k] - o[k]) / u[k], (max[k] - o[k]) / u[k]);
            t0 = t0.max(x0.min(x1));
            t1 = t1.min(x0.max(x1));
        }
    }
    (t1 > t0).then_some((t0, t1))
}

/// The box `[min, max]`'s extent along `e` (relative to the point `o`).
fn extent(min: &Vector3<f64>, max: &Vector3<f64>, o: &Vector3<f64>, e: &Vector3<f64>) -> (f64, f64) {
    let c = (min + max) / 2.0 - o;
    let h = (max - min) / 2.0;
    let r = h.x * e.x.abs() + h.y * e.y.abs() + h.z * e.z.abs();
    (c.dot(e) - r, c.dot(e) + r)
}

/// An upper bound of the depth in the box `[min, max]` (the distance to its boundary) of the
/// points `o + t·u`, `t ∈ [lo, hi]`, grown by far more than rounding. The depth along the
/// segment is the least of six linear functions of `t` (the distances to the faces), concave:
/// its largest value is at an end or where a rising one meets a falling one. A point of a solid
/// inside the box lies no deeper in the solid than in the box (a ball inside the solid is inside
/// the box).
fn box_depth_bound(min: &Vector3<f64>, max: &Vector3<f64>, o: Vector3<f64>, u: Vector3<f64>, lo: f64, hi: f64) -> f64 {
    let (lines, scale) = box_face_lines(min, max, o, u);
    let at = |t: f64| lines.iter().fold(f64::INFINITY, |m, &(c, s)| m.min(c + s * t));
    let mut best = at(lo).max(at(hi));
    // The rising lines and the falling ones (at most three of each: an axis's two faces have
    // opposite slopes), so that only the pairs of one of each are looked at.
    let (mut rising, mut falling) = ([(0.0, 0.0); 3], [(0.0, 0.0); 3]);
    let (mut nr, mut nf) = (0, 0);
    for &(c, s) in &lines {
        if s > 0.0 {
            rising[nr] = (c, s);
            nr += 1;
        } else if s < 0.0 {
            falling[nf] = (c, s);
            nf += 1;
        }
    }
    for &(c1, s1) in &rising[..nr] {
        for &(c2, s2) in &falling[..nf] {
            let t = (c2 - c1) / (s1 - s2);
            if t > lo && t < hi {
                best = best.max(at(t));
            }
        }
    }
    // The crossings' own rounding is far below this margin.
    best + 1e-9 * (scale + lo.abs() + hi.abs())
}

/// The distance of `o + t·u` to each face of the box `[min, max]` as `c + s·t`, and the box's
/// largest coordinate (at least 1): what [`box_depth_bound`]'s margin scales with.
fn box_face_lines(min: &Vector3<f64>, max: &Vector3<f64>, o: Vector3<f64>, u: Vector3<f64>) -> ([(f64, f64); 6], f64) {
    let mut lines = [(0.0, 0.0); 6];
    let mut scale = 1.0f64;
    for k in 0..3 {
        lines[2 * k] = (o[k] - min[k], u[k]);
        lines[2 * k + 1] = (max[k] - o[k], -u[k]);
        scale = scale.max(min[k].abs()).max(max[k].abs());
    }
    (lines, scale)
}

/// A stock query: the box of the posed component in the part's frame and what it needs.
struct Query<'a> {
    stock: &'a Stock,
    dexel: Option<&'a DexelStock>,
    min: Vector3<f64>,
    max: Vector3<f64>,
}

/// The node rays of one grid that may meet a query's box, numbered in the order of the walk
/// (`Query::each`) so that one can be asked for by its number (`Query::ray`).
enum Walk {
    None,
    /// Columns `j0..=j1`, and in each the angles `dirs`; `reach`: the box's nearest approach to
    /// the axis.
    Cyl {
        j0: usize,
        j1: usize,
        reach: f64,
        dirs: Vec<Dir>,
    },
    /// Face grid `k`'s nodes `i0..=i1` by `j0..=j1` (i fastest); `n1`: the box's reach along its
    /// normal.
    Face {
        k: usize,
        i0: usize,
        i1: usize,
        j0: usize,
        j1: usize,
        n1: f64,
    },
}

/// An angle of the cylindrical grid's walk: its index `i`, its direction `u` (from the axis,
/// across it), and the stretch `[t0, t1]` of its rays within the box's x and y slabs, which is
/// the same for every column (the rays start on the axis and keep their z): [`slab`]'s x and y
/// steps, taken once per angle instead of once per ray; `None` when a slab the direction runs
/// along misses the axis. A column's ray is then the z slab's test and two comparisons, the
/// same stretch `slab` gives (the max and min of the same numbers, in any order).
#[derive(Clone, Copy, Debug)]
struct Dir {
    i: usize,
    u: Vector3<f64>,
    across: Option<(f64, f64)>,
}

impl Dir {
    fn new(i: usize, u: Vector3<f64>, min: &Vector3<f64>, max: &Vector3<f64>) -> Dir {
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut across = true;
        for k in 0..2 {
            if u[k].abs() < 1e-15 {
                across &= !(0.0 < min[k] || 0.0 > max[k]);
            } else {
                let (x0, x1) = ((min[k] - 0.0) / u[k], (max[k] - 0.0) / u[k]);
                t0 = t0.max(x0.min(x1));
                t1 = t1.min(x0.max(x1));
            }
        }
        Dir {
            i,
            u,
            across: across.then_some((t0, t1)),
        }
    }
}

/// A node ray: the point `o`, the direction `u`, the stretch `[t0, t1]` of its material in the
/// box.
type NodeRay = (Vector3<f64>, Vector3<f64>, f64, f64);

/// One row of a face grid against a query's box, as linear functions of the node's index `i`:
/// where each node's ray enters and leaves the box's slab along each axis the normal crosses,
/// and where the node lies along each axis the normal runs along (within 1e-15). With them,
/// [`RowLines::decide`] answers whether [`Query::face_ray`] is `Some` for most nodes with a few
/// multiplications instead of its divisions, and says when it cannot tell.
///
/// Why an answer is `face_ray`'s: `face_ray` is `Some` exactly when `d` is below the thickness
/// and the box's reach, the node lies in the box's slab of each axis the normal runs along, and
/// the latest entry (`d` or a slab's) comes before the earliest exit (the thickness or a
/// slab's): maxima and minima of computed numbers, which round nothing. The lines give each
/// slab's entry and exit, and the node's place, to within `err` (`err_o`) of the numbers
/// `face_ray` computes: both are a few roundings of magnitudes no larger than the box's
/// corners, the face's origin and its extent along the row (relative 1e-16 each), and the
/// allowance is 1e-12 of them, divided by the normal's component where `slab` divides. A
/// comparison is decided only when its sides lie further apart than the two allowances;
/// otherwise `decide` gives `None` and the caller asks `face_ray`.
struct RowLines {
    /// Per crossed axis: entry at `i = 0`, exit at `i = 0`, and their common slope.
    lines: [(f64, f64, f64); 3],
    crossed: usize,
    /// Per axis the normal runs along: the node's coordinate at `i = 0`, its slope, the slab.
    flats: [(f64, f64, f64, f64); 3],
    flat: usize,
    err: f64,
    err_o: f64,
    /// The ray's reach: the thickness, and the least of it and the box's reach along the
    /// normal (`face_ray`'s rejection of `d`).
    thickness: f64,
    reach: f64,
}

impl RowLines {
    fn new(q: &Query<'_>, k: usize, j: usize, n1: f64) -> RowLines {
        let g = &q.stock.faces[k];
        let (min, max) = (&q.min, &q.max);
        let a = g.node(0, j);
        let step = g.du * g.eu;
        let mut lines = [(0.0, 0.0, 0.0); 3];
        let mut flats = [(0.0, 0.0, 0.0, 0.0); 3];
        let (mut crossed, mut flat) = (0, 0);
        let (mut err, mut err_o) = (0.0f64, 0.0f64);
        for m in 0..3 {
            // The largest magnitude of the numbers `face_ray` computes along this axis.
            let extent = g.origin[m].abs()
                + (g.nu as f64 + 1.0) * g.du * g.eu[m].abs()
                + (g.nv as f64 + 1.0) * g.dv * g.ev[m].abs();
            let size = 1.0 + min[m].abs() + max[m].abs() + extent + a[m].abs();
            let u = g.n[m];
            if u.abs() < 1e-15 {
                flats[flat] = (a[m], step[m], min[m], max[m]);
                flat += 1;
                err_o = err_o.max(1e-12 * size);
            } else {
                let (x0, x1) = ((min[m] - a[m]) / u, (max[m] - a[m]) / u);
                lines[crossed] = (x0.min(x1), x0.max(x1), -step[m] / u);
                crossed += 1;
                err = err.max(1e-12 * size / u.abs());
            }
        }
        RowLines {
            lines,
            crossed,
            flats,
            flat,
            err,
            err_o,
            thickness: g.thickness,
            reach: g.thickness.min(n1),
        }
    }

    /// Whether [`Query::face_ray`] of node `i` (its depth `d`) is `Some`; `None` when the lines
    /// cannot tell. (The count takes its tests apart, [`RowLines::flat_spans`] and
    /// [`RowLines::decide_crossed`]; this is their oracle.)
    #[cfg(test)]
    fn decide(&self, i: usize, d: f64) -> Option<bool> {
        if d >= self.reach {
            return Some(false);
        }
        let x = i as f64;
        let mut sure = true;
        for &(o, s, lo, hi) in &self.flats[..self.flat] {
            let at = o + s * x;
            if at < lo - self.err_o || at > hi + self.err_o {
                return Some(false);
            }
            sure &= at >= lo + self.err_o && at <= hi - self.err_o;
        }
        self.decide_crossed(i, d, sure)
    }

    /// Of the nodes `a..=b`, those no flat rules out ([`RowLines::decide`]'s test of the node's
    /// place), and of those the ones every flat is sure of; `None`: no node is left. Each test
    /// is a comparison of `o + s·i` with a fixed number, and that expression, rounded, never
    /// falls as `i` grows when `s ≥ 0` (nor rises when `s ≤ 0`): a product and a sum round
    /// monotonically. So each test holds on a prefix or a suffix of the nodes, found by halving
    /// with the very expression `decide` computes: the same answer for every node. A flat whose
    /// numbers are not finite leaves every node to the per-node tests (none sure).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    fn flat_spans(&self, a: usize, b: usize) -> Option<(NodeSpan, Option<NodeSpan>)> {
        let (mut live, mut sure) = (Some((a, b)), Some((a, b)));
        for &(o, s, lo, hi) in &self.flats[..self.flat] {
            if !(o.is_finite() && s.is_finite()) {
                return Some(((a, b), None));
            }
            let at = |i: usize| o + s * i as f64;
            let e = self.err_o;
            live = live
                .and_then(|span| true_span(span, |i| !(at(i) < lo - e)))
                .and_then(|span| true_span(span, |i| !(at(i) > hi + e)));
            sure = sure
                .and_then(|span| true_span(span, |i| at(i) >= lo + e))
                .and_then(|span| true_span(span, |i| at(i) <= hi - e));
        }
        let (a, b) = live?;
        Some(((a, b), sure.filter(|&(c, d)| c.max(a) <= d.min(b))))
    }

    /// [`RowLines::decide`] once the node's place is known in the box's flat slabs (`sure`:
    /// inside each by more than the allowance).
    fn decide_crossed(&self, i: usize, d: f64, sure: bool) -> Option<bool> {
        let x = i as f64;
        let (mut enter, mut leave) = (f64::NEG_INFINITY, self.thickness);
        for &(a, b, s) in &self.lines[..self.crossed] {
            enter = enter.max(a + s * x);
            leave = leave.min(b + s * x);
        }
        self.decide_level(d, sure, (enter, leave))
    }

    /// The slabs' latest entry and earliest exit (the thickness among them) when they are the
    /// same for every node of the row: every crossed axis's slope is zero (a face square to an
    /// axis of the box), so `a + s·i` is `a` (to the sign of a zero, which no comparison, maximum
    /// or difference here sees).
    fn level(&self) -> Option<(f64, f64)> {
        let lines = &self.lines[..self.crossed];
        lines.iter().all(|&(_, _, s)| s == 0.0).then(|| {
            lines
                .iter()
                .fold((f64::NEG_INFINITY, self.thickness), |(e, l), &(a, b, _)| {
                    (e.max(a), l.min(b))
                })
        })
    }

    /// [`RowLines::decide_crossed`] given the slabs' latest entry and earliest exit at the node.
    #[inline]
    fn decide_level(&self, d: f64, sure: bool, (enter, leave): (f64, f64)) -> Option<bool> {
        if d >= self.reach {
            return Some(false);
        }
        let gap = leave - d.max(enter);
        if gap < -2.0 * self.err {
            Some(false)
        } else if sure && gap > 2.0 * self.err {
            Some(true)
        } else {
            None
        }
    }
}

impl Query<'_> {
    fn walk(&self, rays: Rays) -> Walk {
        let (min, max) = (&self.min, &self.max);
        match rays {
            Rays::Cyl => {
                let Some(c) = self.stock.cyl.as_ref() else {
                    return Walk::None;
                };
                let Some((j0, j1)) = c.columns(min.z, max.z) else {
                    return Walk::None;
                };
                // The box's nearest reach to the axis: a column whose outermost radius stays
                // inside it holds nothing in the box.
                let dx = (min.x.max(0.0) + (-max.x).max(0.0)).max(0.0);
                let dy = (min.y.max(0.0) + (-max.y).max(0.0)).max(0.0);
                let dirs = c
                    .angles(min, max)
                    .into_iter()
                    .flat_map(|(a, b)| a..=b)
                    .map(|i| {
                        let (co, s) = c.direction(i);
                        Dir::new(i, Vector3::new(co, s, 0.0), min, max)
                    })
                    .collect();
                Walk::Cyl {
                    j0,
                    j1,
                    reach: dx.hypot(dy),
                    dirs,
                }
            }
            Rays::Face(k) => {
                let g = &self.stock.faces[k];
                let (u0, u1) = extent(min, max, &g.origin, &g.eu);
                let (v0, v1) = extent(min, max, &g.origin, &g.ev);
                let (n0, n1) = extent(min, max, &g.origin, &g.n);
                let (Some((i0, i1)), Some((j0, j1))) = (
                    crate::grid::FaceGrid::range(u0, u1, g.du, g.nu),
                    crate::grid::FaceGrid::range(v0, v1, g.dv, g.nv),
                ) else {
                    return Walk::None;
                };
                if n1 <= 0.0 || n0 >= g.thickness {
                    return Walk::None;
                }
                Walk::Face { k, i0, i1, j0, j1, n1 }
            }
        }
    }

    /// Whether column `j` of the cylindrical grid may hold material in the box.
    fn column_live(&self, j: usize, reach: f64) -> bool {
        let Some(c) = self.stock.cyl.as_ref() else { return false };
        !(c.col_max[j] <= reach || self.dexel.is_some_and(|d| d.material_at(c.z(j)).is_empty()))
    }

    /// The cylindrical grid's ray of column `j` at angle `i` (direction `u`), when its material
    /// meets the box.
    /// (`slab` of the ray `o + t·u` within `[inner, R]`, its x and y steps taken from `dir`.)
    fn cyl_ray(&self, j: usize, dir: &Dir, reach: f64) -> Option<NodeRay> {
        let c = self.stock.cyl.as_ref()?;
        let r = c.radius(dir.i, j);
        if r <= c.inner[j].max(reach) {
            return None;
        }
        let (a0, a1) = dir.across?;
        let z = c.z(j);
        if z < self.min.z || z > self.max.z {
            return None;
        }
        let (t0, t1) = (c.inner[j].max(a0), r.min(a1));
        (t1 > t0).then_some((Vector3::new(0.0, 0.0, z), dir.u, t0, t1))
    }

    /// Face grid `k`'s ray of node `(i, j)`, when its material meets the box.
    fn face_ray(&self, k: usize, i: usize, j: usize, n1: f64) -> Option<NodeRay> {
        let g = &self.stock.faces[k];
        let d = g.depth(i, j);
        // The box's reach along the normal (all of it, for any node): a cheap rejection before
        // the ray's own slab.
        if d >= g.thickness || d >= n1 {
            return None;
        }
        let o = g.node(i, j);
        slab(o, g.n, &self.min, &self.max, d, g.thickness).map(|(t0, t1)| (o, g.n, t0, t1))
    }

    /// The nodes `i` of face grid `k`'s row `j` (within `[ia, ib]`) whose ray's reach
    /// `[0, thickness]` along the normal may meet the box: every node whose [`Query::face_ray`]
    /// is `Some` (its material `[d, thickness]` lies within that reach), and more.
    ///
    /// The segment `o + t·n`, `t ∈ [0, T]`, meets the box exactly when `o` lies in the box swept
    /// by `−T·n`: a zonotope of four generators (the box's three edges and `T·n`), the
    /// intersection of the slabs normal to each pair's cross product. Along the row `o` moves
    /// linearly with `i`, so each slab keeps an interval of `i`. The slabs are grown by a
    /// distance far above rounding (1e-6 mm and a billionth of the coordinates), so a node left
    /// out has its segment that far from the box and its `slab` finds no stretch; the interval's
    /// ends are widened by a node besides.
    fn face_row(&self, k: usize, j: usize, ia: usize, ib: usize) -> Option<(usize, usize)> {
        let g = &self.stock.faces[k];
        let (min, max) = (&self.min, &self.max);
        let half_t = g.thickness / 2.0;
        let c = (min + max) / 2.0 - half_t * g.n;
        let h = (max - min) / 2.0;
        let a = g.node(0, j);
        let step = g.du * g.eu;
        let scale = min.abs().max().max(max.abs().max()).max(a.abs().max());
        let grow = 1e-6 + 1e-9 * scale;
        let (mut lo, mut hi) = (ia as f64, ib as f64);
        let axes = [Vector3::x(), Vector3::y(), Vector3::z()];
        for m in axes.iter().copied().chain(axes.iter().map(|e| e.cross(&g.n))) {
            let len = m.norm();
            if len < 1e-9 {
                continue;
            }
            let reach = h.x * m.x.abs() + h.y * m.y.abs() + h.z * m.z.abs() + half_t * m.dot(&g.n).abs() + grow * len;
            let (alpha, beta) = (m.dot(&(a - c)), m.dot(&step));
            if beta.abs() < 1e-12 * len {
                if alpha.abs() > reach {
                    return None;
                }
                continue;
            }
            let (x0, x1) = ((-reach - alpha) / beta, (reach - alpha) / beta);
            lo = lo.max(x0.min(x1).floor() - 1.0);
            hi = hi.min(crate::grid::ceil(x0.max(x1)) + 1.0);
            if lo > hi {
                return None;
            }
        }
        Some((lo as usize, hi as usize))
    }

    /// The walk's ray number `id` ([`Walk`]), when its material meets the box.
    fn ray(&self, w: &Walk, id: usize) -> Option<NodeRay> {
        match w {
            Walk::None => None,
            Walk::Cyl { j0, reach, dirs, .. } => {
                let j = j0 + id / dirs.len();
                if !self.column_live(j, *reach) {
                    return None;
                }
                self.cyl_ray(j, &dirs[id % dirs.len()], *reach)
            }
            Walk::Face { k, i0, i1, j0, n1, .. } => {
                let w = i1 - i0 + 1;
                self.face_ray(*k, i0 + id % w, j0 + id / w, *n1)
            }
        }
    }

    /// Calls `f(id, ray)` for each node ray of the walk whose material meets the box, in the
    /// order of their numbers, stopping when `f` returns false. (The searches walk with
    /// [`Query::each_within`]; this is the counts' oracle.)
    #[cfg(test)]
    fn each(&self, w: &Walk, f: impl FnMut(usize, NodeRay) -> bool) {
        self.each_within(w, None, f);
    }

    /// [`Query::each`], leaving out the rays that cannot meet `inner` (a box inside the query's):
    /// the same rays, numbers and order but for those. Without `inner`, every ray.
    fn each_within(
        &self,
        w: &Walk,
        inner: Option<&(Vector3<f64>, Vector3<f64>)>,
        mut f: impl FnMut(usize, NodeRay) -> bool,
    ) {
        match w {
            Walk::None => {}
            Walk::Cyl { j0, j1, reach, dirs } => {
                // Within `inner`: the columns whose height lies in it, and the angles whose ray
                // can meet it (`CylGrid::angles`, with a node's spacing of margin).
                let (ja, jb, keep) = match (inner, self.stock.cyl.as_ref()) {
                    (None, _) => (*j0, *j1, None),
                    (Some((lo, hi)), Some(c)) => {
                        let Some((ja, jb)) = c.columns(lo.z, hi.z) else { return };
                        let arcs = c.angles(lo, hi);
                        let keep: Vec<bool> = dirs
                            .iter()
                            .map(|&Dir { i, .. }| arcs.iter().any(|&(a, b)| (a..=b).contains(&i)))
                            .collect();
                        (ja.max(*j0), jb.min(*j1), Some(keep))
                    }
                    (Some(_), None) => return,
                };
                for j in ja..=jb {
                    if !self.column_live(j, *reach) {
                        continue;
                    }
                    let base = (j - j0) * dirs.len();
                    for (d, dir) in dirs.iter().enumerate() {
                        if keep.as_ref().is_some_and(|k| !k[d]) {
                            continue;
                        }
                        if let Some(r) = self.cyl_ray(j, dir, *reach) {
                            if !f(base + d, r) {
                                return;
                            }
                        }
                    }
                }
            }
            Walk::Face { k, i0, i1, j0, j1, n1 } => {
                // Within `inner`: the nodes whose ray (along the face's normal) lies within its
                // extent across the face.
                let (ia, ib, ja, jb) = match inner {
                    None => (*i0, *i1, *j0, *j1),
                    Some((lo, hi)) => {
                        let g = &self.stock.faces[*k];
                        let (u0, u1) = extent(lo, hi, &g.origin, &g.eu);
                        let (v0, v1) = extent(lo, hi, &g.origin, &g.ev);
                        let (Some((ia, ib)), Some((ja, jb))) = (
                            crate::grid::FaceGrid::range(u0, u1, g.du, g.nu),
                            crate::grid::FaceGrid::range(v0, v1, g.dv, g.nv),
                        ) else {
                            return;
                        };
                        (ia.max(*i0), ib.min(*i1), ja.max(*j0), jb.min(*j1))
                    }
                };
                let w = i1 - i0 + 1;
                for j in ja..=jb {
                    // The row's nodes whose ray can meet the box at all.
                    let Some((ra, rb)) = self.face_row(*k, j, ia, ib) else {
                        continue;
                    };
                    for i in ra..=rb {
                        if let Some(r) = self.face_ray(*k, i, j, *n1) {
                            if !f((j - j0) * w + (i - i0), r) {
                                return;
                            }
                        }
                    }
                }
            }
        }
    }

    /// How many rays of `rays` meet the box's material, counting no further than `cap`.
    fn count(&self, rays: Rays, cap: usize) -> usize {
        self.count_walk(&self.walk(rays), cap)
    }

    /// How many rays of the walk meet the box's material, counting no further than `cap` (past
    /// it, `cap + 1`).
    fn count_walk(&self, w: &Walk, cap: usize) -> usize {
        match *w {
            Walk::None => 0,
            Walk::Cyl {
                j0,
                j1,
                reach,
                ref dirs,
            } => self.count_cyl(j0, j1, reach, dirs, cap),
            Walk::Face { k, i0, i1, j0, j1, n1 } => self.count_face(k, (i0, i1), (j0, j1), n1, cap),
        }
    }

    /// [`Query::count_walk`] of face grid `k`'s walk, row by row, each node decided by the row's
    /// lines where they can tell ([`RowLines`]), else by its ray: the count `each` gives.
    fn count_face(&self, k: usize, (i0, i1): NodeSpan, (j0, j1): NodeSpan, n1: f64, cap: usize) -> usize {
        let g = &self.stock.faces[k];
        let mut n = 0;
        for j in j0..=j1 {
            let Some((ra, rb)) = self.face_row(k, j, i0, i1) else {
                continue;
            };
            let lines = RowLines::new(self, k, j, n1);
            // The nodes the flats rule out are none of the count; of the others, those every
            // flat is sure of need only the crossed axes' tests.
            let Some(((ra, rb), sure)) = lines.flat_spans(ra, rb) else {
                continue;
            };
            let (sa, sb) = sure.unwrap_or((1, 0));
            let row = &g.d[j * g.nu..(j + 1) * g.nu];
            let level = lines.level();
            for (i, &d) in row.iter().enumerate().take(rb + 1).skip(ra) {
                let sure = sa <= i && i <= sb;
                let decided = match level {
                    Some(level) => lines.decide_level(d, sure, level),
                    None => lines.decide_crossed(i, d, sure),
                };
                let some = match decided {
                    Some(b) => b,
                    None => self.face_ray(k, i, j, n1).is_some(),
                };
                n += usize::from(some);
                if n > cap {
                    return n;
                }
            }
        }
        n
    }

    /// [`Query::count_walk`] of the cylindrical grid's walk: [`Query::cyl_ray`]'s tests, column
    /// by column, those that hang on the column alone (its height, inner radius and nodes) taken
    /// once for all its angles, and the angles whose direction misses the box's x and y slabs
    /// left out beforehand. The same comparisons of the same numbers, so the same count; the cap
    /// is looked at once a column.
    fn count_cyl(&self, j0: usize, j1: usize, reach: f64, dirs: &[Dir], cap: usize) -> usize {
        let Some(c) = self.stock.cyl.as_ref() else {
            return 0;
        };
        let across: Vec<(usize, f64, f64)> = dirs
            .iter()
            .filter_map(|d| d.across.map(|(a0, a1)| (d.i, a0, a1)))
            .collect();
        let mut n = 0;
        for j in j0..=j1 {
            let z = c.z(j);
            if z < self.min.z || z > self.max.z || !self.column_live(j, reach) {
                continue;
            }
            let inner = c.inner[j];
            let floor = inner.max(reach);
            let meets = |r: f64, a0: f64, a1: f64| if r <= floor { false } else { r.min(a1) > inner.max(a0) };
            n += match c.column_nodes(j) {
                Ok(nodes) => across.iter().filter(|&&(i, a0, a1)| meets(nodes[i], a0, a1)).count(),
                Err(r) => across.iter().filter(|&&(_, a0, a1)| meets(r, a0, a1)).count(),
            };
            if n > cap {
                return cap + 1;
            }
        }
        n
    }

    /// The grid of `options` whose rays meet the box's material fewest times (the first such in
    /// the order given), with its count and walk; `None` when one grid has no such ray (the box
    /// is clear).
    ///
    /// The grids are counted smallest walk first, each no further than it could still win, so
    /// a large walk is cut short by a small one's count; the grid chosen and its count are those
    /// of counting each in full in the order given (a grid before the best so far wins a tie,
    /// one after it must count fewer).
    fn fewest(&self, options: &[Rays]) -> Option<(Rays, usize, Walk)> {
        let walks = options.iter().map(|&r| self.walk(r)).collect();
        fewest_of(walks, Walk::len, |w, cap| self.count_walk(w, cap)).map(|(i, n, w)| (options[i], n, w))
    }
}

/// The nodes `a..=b` of a row, as `(a, b)`.
type NodeSpan = (usize, usize);

/// Of the indices `a..=b`, the span where `p` holds, `p` holding on a prefix or a suffix of them
/// (`None`: nowhere): its ends looked at, and the change between them found by halving.
fn true_span((a, b): NodeSpan, p: impl Fn(usize) -> bool) -> Option<NodeSpan> {
    match (p(a), p(b)) {
        (true, true) => Some((a, b)),
        (false, false) => None,
        // Between `lo` (where `p` is as at `a`) and `hi` (as at `b`), the last of the first kind.
        (first, _) => {
            let (mut lo, mut hi) = (a, b);
            while hi - lo > 1 {
                let m = lo + (hi - lo) / 2;
                if p(m) == first {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            Some(if first { (a, lo) } else { (hi, b) })
        }
    }
}

/// Of `items` (in their order), the first whose count is least, with its index and count; `None`
/// when one counts none (or there are none). `count(item, cap)` counts no further than `cap`
/// (past it, `cap + 1`). The items are counted in increasing `size` (a bound of their count),
/// each no further than it could still win: one before the best so far wins a tie, one after it
/// must count fewer. So the answer is counting each in full in order's.
fn fewest_of<W>(
    items: Vec<W>,
    size: impl Fn(&W) -> usize,
    mut count: impl FnMut(&W, usize) -> usize,
) -> Option<(usize, usize, W)> {
    let mut items: Vec<(usize, W)> = items.into_iter().enumerate().collect();
    items.sort_by_key(|(_, w)| size(w));
    let mut best: Option<(usize, usize, W)> = None;
    for (i, w) in items {
        let cap = match &best {
            None => usize::MAX,
            Some((b, n, _)) if i < *b => *n,
            Some((_, n, _)) => n - 1,
        };
        let n = count(&w, cap);
        if n == 0 {
            return None;
        }
        if n <= cap {
            best = Some((i, n, w));
        }
    }
    best
}

impl Walk {
    /// Node rays the walk may visit.
    fn len(&self) -> usize {
        match self {
            Walk::None => 0,
            Walk::Cyl { j0, j1, dirs, .. } => (j1 - j0 + 1) * dirs.len(),
            Walk::Face { i0, i1, j0, j1, .. } => (i1 - i0 + 1) * (j1 - j0 + 1),
        }
    }
}

/// The box of the shape posed at `local` (part frame), grown by `margin` on every side.
fn part_box(shape: &Shape3, local: &Iso, margin: f64) -> (Vector3<f64>, Vector3<f64>) {
    let lb = shape.local_box();
    let mut min = Vector3::repeat(f64::INFINITY);
    let mut max = Vector3::repeat(f64::NEG_INFINITY);
    for k in 0..8 {
        let p = nalgebra::Point3::new(
            if k & 1 == 0 { lb.mins.x } else { lb.maxs.x },
            if k & 2 == 0 { lb.mins.y } else { lb.maxs.y },
            if k & 4 == 0 { lb.mins.z } else { lb.maxs.z },
        );
        let w = (local * p).coords;
        min = min.inf(&w);
        max = max.sup(&w);
    }
    (min.add_scalar(-margin), max.add_scalar(margin))
}

/// The face grids that must be sampled for a box (a cut changed them near it: elsewhere a face
/// grid holds at least the cylindrical grid's material, its starting depths following the same
/// profile; a block has no cylindrical grid and every face grid counts), and the grids whose
/// rays can carry the query.
fn walks(stock: &Stock, min: &Vector3<f64>, max: &Vector3<f64>) -> (Vec<usize>, Vec<Rays>) {
    let near = |(a, b): &(Vector3<f64>, Vector3<f64>)| (0..3).all(|i| b[i] >= min[i] && a[i] <= max[i]);
    let touched: Vec<usize> = if stock.cyl.is_some() {
        (0..stock.faces.len())
            .filter(|&k| stock.faces[k].touched.as_ref().is_some_and(near))
            .collect()
    } else {
        (0..stock.faces.len()).collect()
    };
    let mut options: Vec<Rays> = touched.iter().map(|&k| Rays::Face(k)).collect();
    if stock.cyl.is_some() {
        options.push(Rays::Cyl);
    }
    (touched, options)
}

/// Whether the shape's box (posed at `pose`, grown by `margin`) holds no material by at least
/// one of the stock's grids: then no point of the stock's material lies deeper than a node
/// spacing (`Stock::spacing`) inside the shape, and none lies closer to it than `margin` less
/// a node spacing. (A material point's node ray passes within a spacing of it, and a point of
/// the shape within a spacing of its box's boundary is within a spacing of its surface.)
pub fn grid_clear(shape: &Shape3, pose: &Iso, part: &Iso, stock: &Stock, margin: f64) -> bool {
    let (min, max) = part_box(shape, &(part.inverse() * pose), margin);
    let q = Query {
        stock,
        dexel: None,
        min,
        max,
    };
    let (_, options) = walks(stock, &min, &max);
    options.is_empty() || options.iter().any(|&r| q.count(r, 0) == 0)
}

/// Whether the dexel stock alone proves that [`grid_overlap`] with this `dexel` and a touch depth
/// `touch` finds nothing for the solid `shape` (posed at `pose`; the grid may query a primitive
/// inside it): `stock_overlap` finds no overlap at all (depth 0) on any column's plane, and
/// `touch` exceeds a column's width. A grid contact is a point `p` of the solid deeper than
/// `touch` that the dexel column holding `p.z` holds (its radius within one of the column's
/// radial intervals, which have positive width); the column's plane is within half a column of
/// `p`, so the solid's section by that plane holds a disc of positive radius about the point
/// over `p`, whose radii reach into the interval: the overlap test measures a positive depth
/// there (a triangle's section inside the interval, or the ring inside the solid).
pub fn dexel_clears_grid(shape: &Shape3, pose: &Iso, dexel: &mut DexelStock, touch: f64) -> bool {
    touch > dexel.column_width() && super::stock_overlap(shape, pose, dexel, crate::scene::View::Now, 0.0).is_none()
}

/// Does the shape (posed at `pose`, machine frame) overlap the stock by more than `eps`? The
/// stock's frame is `part` (machine frame of the part: the main spindle's pose).
///
/// `dexel`: the checker's dexel stock, which turning cuts after the hand-over; the material is
/// what both hold. `any`: only whether (the first contact found, not the deepest).
///
/// Every grid spans the stock's box and a point is material only when every grid says so, so
/// the rays of any one grid find all of it. The query walks the grid with the fewest rays whose
/// material meets the component's box (a drill in the hole it cut: the hole's own side grid,
/// whose rays there end above the hole's floor — none), and samples the others along each
/// stretch of material inside the component. A grid with no such ray proves the box clear.
pub fn grid_overlap(
    shape: &Shape3,
    pose: &Iso,
    part: &Iso,
    stock: &Stock,
    eps: f64,
    dexel: Option<&DexelStock>,
    any: bool,
) -> Option<Hit> {
    overlap_by(shape, pose, part, stock, eps, dexel, any, Some(MAX_RANKED))
}

/// [`grid_overlap`] asked how deep only beyond `floor` (the deepest depth already known, say, of
/// a contact whose samples are being taken): the same hit as [`grid_overlap`] when that lies
/// deeper than `floor + BEYOND_MM` ([`BEYOND_MM`]); else whether there is contact at all, as a
/// hit deeper than `eps` and no deeper than `floor + BEYOND_MM`, or `None`.
///
/// Why the first answer is [`grid_overlap`]'s: its search skips only rays, stretches and runs
/// whose bound cannot beat the best so far or `eps`; raising `eps` to `floor + BEYOND_MM` skips
/// besides only those that hold no point deeper than that, so the points deeper than it the
/// search measures are the same, and so is the deepest of them (ties to the same ray).
///
/// The second: a point that search measured deeper than `eps` (kept as it goes: a contact held
/// at one depth measures many just short of `floor`) is a contact; when it measured none, the
/// walk asked only whether, on the same choice of grid (made once for the pose).
#[allow(clippy::too_many_arguments)]
pub fn grid_overlap_beyond(
    shape: &Shape3,
    pose: &Iso,
    part: &Iso,
    stock: &Stock,
    eps: f64,
    dexel: Option<&DexelStock>,
    floor: f64,
) -> Option<Hit> {
    if floor <= eps {
        return grid_overlap(shape, pose, part, stock, eps, dexel, false);
    }
    let mut at = At::new(shape, pose, part, stock, dexel);
    let (deep, touch) = at.search((floor + BEYOND_MM, eps), false, Some(MAX_RANKED));
    deep.or(touch)
        .or_else(|| at.search((eps, eps), true, Some(MAX_RANKED)).0)
}

/// [`grid_overlap`], ranking at most `rank` rays by their bound (more: the walk in its order,
/// the bounds still skipping); with `rank` `None`, the slow answer it must equal: every ray in
/// the walk's order, every run of material measured (the tests' oracle).
#[allow(clippy::too_many_arguments)]
fn overlap_by(
    shape: &Shape3,
    pose: &Iso,
    part: &Iso,
    stock: &Stock,
    eps: f64,
    dexel: Option<&DexelStock>,
    any: bool,
    rank: Option<usize>,
) -> Option<Hit> {
    At::new(shape, pose, part, stock, dexel).search((eps, eps), any, rank).0
}

/// A component posed against the stock: its box in the part's frame, and the grid its searches
/// walk (chosen by the first search that needs one: `Query::fewest` depends on the box alone).
struct At<'a> {
    shape: &'a Shape3,
    /// The part's frame, and the shape's pose in it.
    part: &'a Iso,
    local: Iso,
    q: Query<'a>,
    /// The face grids a cut changed near the box, and the grids that may carry the walk.
    touched: Vec<usize>,
    options: Vec<Rays>,
    chosen: Option<Option<(Rays, usize, Walk)>>,
}

impl<'a> At<'a> {
    fn new(shape: &'a Shape3, pose: &Iso, part: &'a Iso, stock: &'a Stock, dexel: Option<&'a DexelStock>) -> At<'a> {
        // The shape in the part's frame.
        let local = part.inverse() * pose;
        let (min, max) = part_box(shape, &local, 0.0);
        let (touched, options) = walks(stock, &min, &max);
        At {
            shape,
            part,
            local,
            q: Query { stock, dexel, min, max },
            touched,
            options,
            chosen: None,
        }
    }

    /// The deepest point deeper than `eps` (with `any`, the first found), and the first point
    /// measured deeper than `touch` (at most `eps`: a contact however deep): see [`overlap_by`].
    fn search(&mut self, (eps, touch): (f64, f64), any: bool, rank: Option<usize>) -> (Option<Hit>, Option<Hit>) {
        let prune = rank.is_some();
        let (min, max) = (self.q.min, self.q.max);
        // A point deeper than `eps` in the shape lies deeper than `eps` in its box, so inside the box
        // shrunk by `eps` on every side: a ray that misses that inner box (shrunk a little less, far
        // more than rounding) has no point the search could keep, and is not enumerated (the rays
        // left keep their numbers and order, so the answer is the same); with no inner box, none has.
        let inner = if prune { inner_box(&min, &max, eps) } else { None };
        if inner.is_some_and(|(a, b)| (0..3).any(|i| a[i] > b[i])) {
            return (None, None);
        }
        let q = &self.q;
        let Some((best_rays, best_n, walk)) = self.chosen.get_or_insert_with(|| q.fewest(&self.options)) else {
            return (None, None);
        };
        let (best_rays, best_n, walk) = (*best_rays, *best_n, &*walk);
        let (stock, dexel, local, touched) = (q.stock, q.dexel, &self.local, &self.touched);
        let (shape, part) = (self.shape, self.part);
        // Whether a point is material by the grids other than the walked one (and the dexel stock,
        // unless the walk already holds to its intervals).
        let others: Vec<usize> = touched
            .iter()
            .copied()
            .filter(|&k| Rays::Face(k) != best_rays)
            .collect();
        let sample_cyl = best_rays != Rays::Cyl && stock.cyl.is_some();
        // `sure`: whether the point is known to be material by the cylindrical grid, and by the
        // dexel stock (`surely_material`).
        let material = |p: Vector3<f64>, (cyl, dex): (bool, bool)| {
            (!sample_cyl || cyl || stock.cyl.as_ref().is_some_and(|c| c.contains(p)))
                && others.iter().all(|&k| stock.faces[k].contains(p))
                && (best_rays == Rays::Cyl || dex || dexel.map_or(true, |d| d.holds(p.x.hypot(p.y), p.z)))
        };
        let needs_samples = sample_cyl || !others.is_empty() || (dexel.is_some() && best_rays != Rays::Cyl);
        let ppose = to_pose(local);
        let step = stock.tolerance.max(1e-3);
        // A bound of how deep the points of a ray's stretch `[t0, t1]` the search may measure lie
        // in the box. When the cylindrical grid is sampled, every point kept is material by it,
        // so within its reach (`CylGrid::may_hold`) grown by a sample's spacing (a run's ends
        // lie up to half a sample beyond its samples): a face grid's ray crossing the bar (its
        // material runs to the stock box's far side) is bounded by its chord through the bar.
        // Only bounds: the stretches, pieces and samples measured stay the ray's own.
        let ray_bound = |o: Vector3<f64>, u: Vector3<f64>, t0: f64, t1: f64| {
            let reach = match (sample_cyl, stock.cyl.as_ref()) {
                (true, Some(c)) => c
                    .may_hold(o, u, t0, t1)
                    .map(|(lo, hi)| (t0.max(lo - step), t1.min(hi + step))),
                _ => Some((t0, t1)),
            };
            reach.map_or(f64::NEG_INFINITY, |(a, b)| box_depth_bound(&min, &max, o, u, a, b))
        };
        // A run `[a, b]` of material inside the shape's stretch `[c0, c1]` of the ray: no point of it
        // lies deeper in the shape than its distance along the ray to the stretch's ends (they are on
        // the surface), so a run that cannot beat the best so far (or `eps`) is not measured. Its
        // deepest point is at one of its ends (where the material ends inside the shape) or, on a run
        // through the shape, near its middle.
        let keep_run = |best: &mut Deepest,
                        ray: usize,
                        o: Vector3<f64>,
                        u: Vector3<f64>,
                        (a, b): (f64, f64),
                        (c0, c1): (f64, f64)| {
            let m = ((c0 + c1) / 2.0).clamp(a, b);
            if best.beats((m - c0).min(c1 - m), ray) {
                return;
            }
            for t in [a, (a + b) / 2.0, b] {
                let p0 = o + t * u;
                let depth = shape.depth_of(&ppose, Vector::new(p0.x, p0.y, p0.z));
                best.offer(depth, part * nalgebra::Point3::from(p0), ray);
            }
        };
        let mut best = Deepest {
            eps,
            prune,
            hit: None,
            ray: 0,
            touch,
            touched: None,
        };
        let mut spans = Vec::new();
        let mut pieces: Vec<(f64, f64)> = Vec::new();
        // One node ray (the `ray`-th of the walk).
        let mut visit = |best: &mut Deepest, ray: usize, o: Vector3<f64>, u: Vector3<f64>, t0: f64, t1: f64| {
            // No point of the ray's material in the box can lie deeper than the box allows: when
            // that cannot beat the best so far (or `eps`), the ray is not cast.
            if best.beats(ray_bound(o, u, t0, t1), ray) {
                return true;
            }
            // Cast from outside the component's box (its faces may be the component's own: a start
            // on the boundary would leave the parity to chance), then keep the node's material.
            let Some((b0, b1)) = slab(o, u, &min, &max, f64::NEG_INFINITY, f64::INFINITY) else {
                return true;
            };
            inside_stretches(shape, &ppose, o, u, b0 - 1.0, b1 + 1.0, &mut spans);
            for &(c0, c1) in &spans {
                let (s0, s1) = (c0.max(t0), c1.min(t1));
                if s1 <= s0 {
                    continue;
                }
                // No point of the stretch lies deeper in the shape than half its length (its ends are
                // on the surface): when that cannot beat the best so far (or `eps`), no run in it is
                // measured (`keep_run`'s bound is at most that), so its samples are not taken.
                if best.beats((c1 - c0) / 2.0, ray) {
                    continue;
                }
                pieces.clear();
                // Along a radial ray the dexel stock's material is its column's radial intervals.
                match (best_rays, dexel) {
                    (Rays::Cyl, Some(d)) => pieces.extend(
                        d.material_at(o.z)
                            .iter()
                            .map(|&(lo, hi)| (s0.max(lo), s1.min(hi)))
                            .filter(|(a, b)| b > a),
                    ),
                    _ => pieces.push((s0, s1)),
                }
                for &(a, b) in &pieces {
                    // No run of the piece can beat the best so far (or `eps`): the box's depth and the
                    // distance along the ray to the stretch's ends bound every point of it.
                    let m = ((c0 + c1) / 2.0).clamp(a, b);
                    let along = (m - c0).min(c1 - m);
                    if best.beats(along.min(box_depth_bound(&min, &max, o, u, a, b)), ray) {
                        continue;
                    }
                    if !needs_samples {
                        keep_run(best, ray, o, u, (a, b), (c0, c1));
                        continue;
                    }
                    // Runs of material by the other grids, sampled at the stock's tolerance: only
                    // within the cylindrical grid's reach when it is sampled (outside it no sample
                    // is material, so the runs are every sample's).
                    let n = (crate::grid::ceil((b - a) / step) as usize).clamp(1, 4096);
                    let dt = (b - a) / n as f64;
                    let (mut k, n) = match (sample_cyl, stock.cyl.as_ref()) {
                        (true, Some(c)) => match c.may_hold(o, u, a, b) {
                            None => continue,
                            Some((lo, hi)) => {
                                let r = crate::grid::samples_within(a, b, n, lo, hi);
                                (r.start, r.end)
                            }
                        },
                        _ => (0, n),
                    };
                    // Where the cylindrical grid and the dexel stock surely hold the ray, its
                    // samples need not ask them (the oracle asks every sample).
                    let sure = match (prune && sample_cyl, stock.cyl.as_ref()) {
                        (true, Some(c)) => surely_material(c, dexel, o, u, a, b),
                        _ => None,
                    };
                    let mat = |k: usize| {
                        let t = a + (k as f64 + 0.5) * dt;
                        let known = |(lo, hi): (f64, f64)| t >= lo && t <= hi;
                        material(
                            o + t * u,
                            sure.map_or((false, false), |(s, dex)| (known(s), dex && known(s))),
                        )
                    };
                    while k < n {
                        if !mat(k) {
                            k += 1;
                            continue;
                        }
                        let first = k;
                        while k < n && mat(k) {
                            k += 1;
                        }
                        keep_run(best, ray, o, u, (a + first as f64 * dt, a + k as f64 * dt), (c0, c1));
                    }
                }
            }
            // Asked only whether: the first contact deeper than `eps` answers it.
            !(any && best.hit.is_some())
        };
        let inner = inner.as_ref();
        if any || rank.map_or(true, |r| best_n > r) {
            // Asked only whether: the walk in its order, to the first contact. (And so the oracle,
            // and a walk too long to rank in bounded memory, the bounds still skipping.)
            q.each_within(walk, inner, |id, (o, u, t0, t1)| visit(&mut best, id, o, u, t0, t1));
            return (best.hit, best.touched);
        }
        // Asked how deep: the rays by how deep the box lets their material lie, deepest first, until
        // no ray left can beat the best (`Deepest` answers as the walk in its order would).
        let mut ranked = Vec::with_capacity(best_n);
        q.each_within(walk, inner, |id, (o, u, t0, t1)| {
            let bound = ray_bound(o, u, t0, t1);
            if bound > eps {
                ranked.push(Ranked(bound, id));
            }
            true
        });
        let mut order = std::collections::BinaryHeap::from(ranked);
        while let Some(Ranked(bound, id)) = order.pop() {
            if best.hit.is_some_and(|h| bound < h.depth) {
                break;
            }
            if let Some((o, u, t0, t1)) = q.ray(walk, id) {
                visit(&mut best, id, o, u, t0, t1);
            }
        }
        (best.hit, best.touched)
    }
}

/// A part `[lo, hi]` of `[a, b]` on which every point `o + t·u` is material by the cylindrical
/// grid `c` ([`CylGrid::surely_holds`]); and whether it is by the dexel stock too, when given
/// (every column its heights fall in holds one interval spanning its radii, both grown by a
/// margin far above rounding, 1e-7 mm: the radius along a line is convex, largest at an end of
/// the part and least at its point nearest the axis).
fn surely_material(
    c: &crate::grid::CylGrid,
    dexel: Option<&DexelStock>,
    o: Vector3<f64>,
    u: Vector3<f64>,
    a: f64,
    b: f64,
) -> Option<((f64, f64), bool)> {
    const MARGIN: f64 = 1e-7;
    let (lo, hi) = c.surely_holds(o, u, a, b)?;
    let Some(d) = dexel else { return Some(((lo, hi), true)) };
    let rho = |t: f64| (o.x + t * u.x).hypot(o.y + t * u.y);
    let qa = u.x * u.x + u.y * u.y;
    let nearest = if qa < 1e-24 {
        lo
    } else {
        (-(o.x * u.x + o.y * u.y) / qa).clamp(lo, hi)
    };
    let (z0, z1) = (o.z + lo * u.z, o.z + hi * u.z);
    let held = d.holds_all(
        rho(nearest) - MARGIN,
        rho(lo).max(rho(hi)) + MARGIN,
        z0.min(z1) - MARGIN,
        z0.max(z1) + MARGIN,
    );
    Some(((lo, hi), held))
}

/// The box `[min, max]` shrunk on every side by `depth` less a margin far larger than rounding
/// (1e-6 mm and a millionth of the box's reach): every point deeper than `depth` in the box lies
/// inside it. `None` when that shrinks nothing. It may be empty (a corner past its opposite).
fn inner_box(min: &Vector3<f64>, max: &Vector3<f64>, depth: f64) -> Option<(Vector3<f64>, Vector3<f64>)> {
    let reach = min.abs().max().max(max.abs().max());
    let s = depth - 1e-6 - 1e-6 * reach;
    (s > 0.0).then(|| (min.add_scalar(s), max.add_scalar(-s)))
}

/// A ray's number ranked by a bound of its depth (the deeper first).
struct Ranked(f64, usize);

impl PartialEq for Ranked {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == std::cmp::Ordering::Equal
    }
}

impl Eq for Ranked {}

impl PartialOrd for Ranked {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}

impl Ord for Ranked {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0).then(o.1.cmp(&self.1))
    }
}

/// The deepest point found so far, and the walk's order among equally deep ones: of two points
/// as deep, the one of the earlier ray (`ray`, its index in the walk), and on one ray the first
/// offered (a ray's points come in its order). Visiting rays out of order then answers as the
/// walk in order would.
struct Deepest {
    eps: f64,
    /// Whether the bounds may skip (else every point is measured: the oracle).
    prune: bool,
    hit: Option<Hit>,
    ray: usize,
    /// The first point offered deeper than `touch` (a contact, however deep).
    touch: f64,
    touched: Option<Hit>,
}

impl Deepest {
    /// Whether no point of ray `ray` lying at most `bound` deep can replace the best (or lie
    /// deeper than `eps`).
    fn beats(&self, bound: f64, ray: usize) -> bool {
        if !self.prune {
            return false;
        }
        bound <= self.eps
            || self
                .hit
                .is_some_and(|h| bound < h.depth || (bound == h.depth && ray >= self.ray))
    }

    fn offer(&mut self, depth: f64, point: nalgebra::Point3<f64>, ray: usize) {
        let better = match self.hit {
            None => true,
            Some(h) => depth > h.depth || (depth == h.depth && ray < self.ray),
        };
        if depth > self.touch && self.touched.is_none() {
            self.touched = Some(Hit { depth, point });
        }
        if depth > self.eps && better {
            (self.hit, self.ray) = (Some(Hit { depth, point }), ray);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Cutter, CutterKind, Sweep};
    use crate::kin::Geometry;
    use nalgebra::{Point3, Translation3};

    /// A Ø40 bar 60 long with a flat 5 deep at x = 15 over z 22 .. 38.
    fn milled_bar() -> Stock {
        let mut s = Stock::turned(0.0, 60.0, 20.0, 0.1, |_| Some((0.0, 20.0))).unwrap();
        let c = Cutter::new(CutterKind::Flat, 16.0, 30.0).unwrap();
        let sw = Sweep::new(
            &c,
            Vector3::x(),
            Vector3::new(15.0, -30.0, 30.0),
            Vector3::new(15.0, 30.0, 30.0),
            0.1,
        )
        .unwrap();
        s.cut(&sw);
        s
    }

    /// [`milled_bar`] with a radial hole at 45° (a side grid oblique to the part's axes) and a
    /// face pocket.
    fn holed_bar() -> Stock {
        let mut s = milled_bar();
        let drill = Cutter::new(CutterKind::Flat, 10.0, 40.0).unwrap();
        let d = Vector3::new(1.0, 1.0, 0.0).normalize();
        let z12 = Vector3::new(0.0, 0.0, 12.0);
        s.cut(&Sweep::new(&drill, -d, 30.0 * d + z12, 12.0 * d + z12, 0.1).unwrap());
        let mill = Cutter::new(CutterKind::Flat, 12.0, 30.0).unwrap();
        let (p0, p1) = (Vector3::new(-8.0, -6.0, 57.0), Vector3::new(4.0, -6.0, 57.0));
        s.cut(&Sweep::new(&mill, Vector3::z(), p0, p1, 0.1).unwrap());
        s
    }

    fn cube(half: f64) -> Shape3 {
        Shape3::meshed(
            &Geometry::Cuboid {
                min: Point3::new(-half, -half, -half),
                max: Point3::new(half, half, half),
            },
            0.1,
        )
        .unwrap()
    }

    fn at(x: f64, y: f64, z: f64) -> Iso {
        Iso::from_parts(Translation3::new(x, y, z), nalgebra::UnitQuaternion::identity())
    }

    /// A drill posed in the second of two radial holes clears the stock (its rays leave the
    /// drill's side through the edges of its facets: a crossing counted twice once made a
    /// stretch outside it count as inside), and a ray along the drill's side is no depth.
    #[test]
    fn a_drill_in_its_own_radial_hole_clears_the_milled_stock() {
        let mut s = Stock::turned(0.0, 120.0, 25.0, 0.05, |_| Some((0.0, 25.0))).unwrap();
        let c = Cutter::new(CutterKind::Flat, 8.0, 40.0).unwrap();
        let hole = |s: &mut Stock, axis: Vector3<f64>, a: Vector3<f64>, b: Vector3<f64>| {
            s.cut(&Sweep::new(&c, axis, a, b, 0.05).unwrap());
        };
        hole(
            &mut s,
            Vector3::x(),
            Vector3::new(35.0, 0.0, 58.0),
            Vector3::new(15.0, 0.0, 58.0),
        );
        hole(
            &mut s,
            -Vector3::y(),
            Vector3::new(0.0, -35.0, 58.0),
            Vector3::new(0.0, -15.0, 58.0),
        );
        let g = Geometry::Cylinder {
            radius: 4.0,
            z0: 0.0,
            z1: 40.0,
        };
        let drill = Shape3::meshed(&g, 0.01).unwrap();
        let touch = 0.1;
        let down = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::FRAC_PI_2);
        for tip in [15.76, 17.0, 20.0] {
            let pose = Iso::from_parts(Translation3::new(0.0, -tip, 58.0), down);
            let h = grid_overlap(&drill, &pose, &Iso::identity(), &s, touch, None, false);
            assert!(h.is_none(), "tip at y −{tip}: {h:?}");
        }
        let along_x = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let pose = Iso::from_parts(Translation3::new(15.7, 0.0, 58.0), along_x);
        assert!(grid_overlap(&drill, &pose, &Iso::identity(), &s, touch, None, false).is_none());
        // Off its hole's axis by a millimetre, the drill cuts into the wall.
        let off = Iso::from_parts(Translation3::new(1.0, -17.0, 58.0), down);
        assert!(grid_overlap(&drill, &off, &Iso::identity(), &s, touch, None, false).is_some());
    }

    #[test]
    fn a_block_over_a_milled_flat_clears_it_and_the_same_block_on_the_round_bar_hits() {
        let s = milled_bar();
        let b = cube(2.0);
        let part = Iso::identity();
        // Above the flat (x 15 .. 19 at y 0): where the bar was, now air.
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &part, &s, 1e-6, None, false).is_none());
        // The same place 15 mm along z, where the bar is still round: a hit (the depth is a lower
        // bound: the deepest material point's distance to the block's surface, about 2).
        let h = grid_overlap(&b, &at(17.5, 0.0, 48.0), &part, &s, 1e-6, None, false).expect("hits the round bar");
        assert!(h.depth > 1.5 && h.depth < 4.5, "{h:?}");
        // Dipping 1 mm under the flat: a hit.
        assert!(grid_overlap(&b, &at(16.0, 0.0, 30.0), &part, &s, 1e-6, None, false).is_some());
        // The part turned by 180° about the axis: the flat is on the other side.
        let turned = Iso::from_parts(
            Translation3::identity(),
            nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI),
        );
        assert!(grid_overlap(&b, &at(-17.5, 0.0, 30.0), &turned, &s, 1e-6, None, false).is_none());
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &turned, &s, 1e-6, None, false).is_some());
    }

    /// Against sampling: a box whose centre region holds material is found; a box the query
    /// finds holds material within a node's reach of it.
    /// `Query::face_row` lets the walks leave out a row's nodes whose ray cannot meet the box
    /// (a face grid at 45° under a large box reaches it only along a narrow band): it must keep
    /// every node whose `face_ray` finds material in the box. Oracle: every node of every row,
    /// on face grids turned every way, under boxes of every size; and it leaves out most nodes.
    #[test]
    fn a_face_grids_row_keeps_every_node_whose_ray_meets_the_box() {
        let mut rnd = crate::test_util::unit_random(7u64);
        let mut s = milled_bar();
        for _ in 0..4 {
            let a = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5).normalize();
            let b = Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let ev = (b - b.dot(&a) * a).normalize();
            let origin = Vector3::new(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0, 60.0 * rnd());
            let g = crate::grid::FaceGrid::flat(origin, a, ev, (0.7, 0.9), (60, 50), 30.0)
                .with_start(|u, v| Some(10.0 * (0.5 + 0.5 * (u * 0.3).sin() * (v * 0.2).cos())));
            s.faces.push(g);
        }
        let (mut met, mut left_out, mut nodes) = (0usize, 0usize, 0usize);
        for _ in 0..120 {
            let c = Vector3::new(60.0 * rnd() - 30.0, 60.0 * rnd() - 30.0, 80.0 * rnd() - 10.0);
            let h = Vector3::new(0.2 + 30.0 * rnd(), 0.2 + 30.0 * rnd(), 0.2 + 30.0 * rnd());
            let q = Query {
                stock: &s,
                dexel: None,
                min: c - h,
                max: c + h,
            };
            for k in 0..s.faces.len() {
                let g = &s.faces[k];
                for j in 0..g.nv {
                    let row = q.face_row(k, j, 0, g.nu - 1);
                    for i in 0..g.nu {
                        nodes += 1;
                        let kept = row.is_some_and(|(a, b)| (a..=b).contains(&i));
                        left_out += usize::from(!kept);
                        if q.face_ray(k, i, j, f64::INFINITY).is_some() {
                            met += 1;
                            assert!(
                                kept,
                                "face {k} node ({i}, {j}) meets the box {c:?} ± {h:?}, row {row:?}"
                            );
                        }
                    }
                }
            }
        }
        assert!(
            met > 10_000 && left_out > nodes / 2,
            "{met} met, {left_out} of {nodes} left out"
        );
    }

    #[test]
    fn the_grid_query_agrees_with_sampling_the_box() {
        let s = milled_bar();
        let b = cube(1.5);
        let mut rnd = crate::test_util::unit_random(99u64);
        let mut hits = 0;
        for _ in 0..150 {
            let c = Vector3::new(10.0 + 12.0 * rnd(), 8.0 * rnd() - 4.0, 15.0 + 30.0 * rnd());
            let got = grid_overlap(&b, &at(c.x, c.y, c.z), &Iso::identity(), &s, 1e-6, None, false);
            let sample = |half: f64| {
                let n = 12;
                (0..n * n * n).any(|k| {
                    let f = |i: usize| -half + 2.0 * half * (i as f64 + 0.5) / n as f64;
                    s.contains(c + Vector3::new(f(k % n), f((k / n) % n), f(k / (n * n))))
                })
            };
            if sample(1.0) {
                assert!(got.is_some(), "material well inside the box at {c:?} not found");
            }
            if got.is_some() {
                hits += 1;
                assert!(sample(1.8), "a hit at {c:?} with no material near the box");
            }
        }
        assert!(hits > 10 && hits < 150, "{hits}");
    }

    /// The grid a query walks, counted smallest walk first and cut short, is the one counting
    /// every grid in full in order picks (the first with the fewest rays), with the same count:
    /// boxes of every size over a bar milled through its side and a face grid of its own.
    #[test]
    fn the_grid_with_the_fewest_rays_is_the_one_a_full_count_picks() {
        let mut s = milled_bar();
        let c = Cutter::new(CutterKind::Flat, 10.0, 30.0).unwrap();
        let face = Sweep::new(
            &c,
            Vector3::z(),
            Vector3::new(-8.0, -6.0, 57.0),
            Vector3::new(4.0, -6.0, 57.0),
            0.1,
        )
        .unwrap();
        s.cut(&face);
        let mut rnd = crate::test_util::unit_random(7u64);
        let (mut walked, mut clear) = (std::collections::BTreeSet::new(), 0);
        for _ in 0..300 {
            let c = Vector3::new(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0, 70.0 * rnd() - 5.0);
            let h = Vector3::new(0.2 + 12.0 * rnd(), 0.2 + 12.0 * rnd(), 0.2 + 12.0 * rnd());
            let q = Query {
                stock: &s,
                dexel: None,
                min: c - h,
                max: c + h,
            };
            let (_, options) = walks(&s, &q.min, &q.max);
            // Every grid counted in full, in order: the first with the fewest wins.
            let counts: Vec<usize> = options.iter().map(|&r| q.count(r, usize::MAX)).collect();
            let want = match counts.iter().min() {
                Some(&0) | None => None,
                Some(&n) => Some((options[counts.iter().position(|&k| k == n).unwrap()], n)),
            };
            let got = q.fewest(&options).map(|(r, n, _)| (r, n));
            assert_eq!(got, want, "box {c:?} ± {h:?}, counts {counts:?} of {options:?}");
            match got {
                Some((r, _)) => {
                    walked.insert(format!("{r:?}"));
                }
                None => clear += 1,
            }
        }
        // Both kinds of grid were walked, and some boxes were clear.
        assert!(walked.len() >= 2 && clear > 0, "{walked:?}, {clear} clear");
    }

    /// A face grid's row lines ([`RowLines`]) decide a node only as its ray does, and decide
    /// nearly all of them; so a walk's count row by row is the count of its rays, capped alike.
    /// On a bar with a flat (the turned part's face grids), a radial hole at 45° (a side grid
    /// oblique to the part's axes) and a face pocket, against random boxes, every fourth with a
    /// face where a node's material begins, across the normal (the node's ray leaves the box
    /// where its material begins: `face_ray`'s answer is its rounding's, and the lines cannot
    /// tell), and every fourth with a face through a node along the normal.
    #[test]
    fn a_face_rows_lines_decide_its_nodes_as_their_rays_do() {
        let s = holed_bar();
        assert!(s.faces.len() >= 2, "{} face grids", s.faces.len());
        let mut rnd = crate::test_util::unit_random(5u64);
        let (mut decided, mut asked, mut some, mut levels) = (0usize, 0usize, 0usize, 0usize);
        for case in 0..160 {
            let k = case % s.faces.len();
            let g = &s.faces[k];
            let mut c = Vector3::new(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0, 70.0 * rnd() - 5.0);
            let h = Vector3::new(0.2 + 8.0 * rnd(), 0.2 + 8.0 * rnd(), 0.2 + 8.0 * rnd());
            // A node near the walk's middle, and where its material begins.
            let (i, j) = ((rnd() * g.nu as f64) as usize, (rnd() * g.nv as f64) as usize);
            let start = g.node(i, j) + g.depth(i, j) * g.n;
            if case % 4 >= 2 {
                c = start;
            }
            let (mut min, mut max) = (c - h, c + h);
            let m = (0..3).max_by(|&a, &b| g.n[a].abs().total_cmp(&g.n[b].abs())).unwrap();
            match case % 4 {
                2 if g.n[m] > 0.0 => max[m] = start[m],
                2 => min[m] = start[m],
                3 => {
                    let o = g.node(i, j);
                    let across = (0..3).find(|&a| g.n[a].abs() < 1e-15 && a != m);
                    if let Some(a) = across {
                        min[a] = o[a];
                    }
                }
                _ => {}
            }
            let q = Query {
                stock: &s,
                dexel: None,
                min,
                max,
            };
            let w = q.walk(Rays::Face(k));
            let Walk::Face { i0, i1, j0, j1, n1, .. } = w else {
                continue;
            };
            for j in j0..=j1 {
                let Some((ra, rb)) = q.face_row(k, j, i0, i1) else {
                    continue;
                };
                let lines = RowLines::new(&q, k, j, n1);
                let spans = lines.flat_spans(ra, rb);
                for i in ra..=rb {
                    let ray = q.face_ray(k, i, j, n1).is_some();
                    some += usize::from(ray);
                    // The flats' spans and the crossed axes' tests decide as `decide` does.
                    let apart = match spans {
                        Some(((a, b), sure)) if (a..=b).contains(&i) => {
                            let sure = sure.is_some_and(|(c, d)| (c..=d).contains(&i));
                            let crossed = lines.decide_crossed(i, g.depth(i, j), sure);
                            // A row whose slabs are level is decided by its one entry and exit.
                            // (Of any depth, not only the node's.)
                            if let Some(level) = lines.level() {
                                let x = i as f64;
                                let at = lines.lines[..lines.crossed]
                                    .iter()
                                    .fold((f64::NEG_INFINITY, g.thickness), |(e, l), &(a, b, s)| {
                                        (e.max(a + s * x), l.min(b + s * x))
                                    });
                                assert!(at.0 == level.0 && at.1 == level.1, "{at:?} against {level:?}");
                                let t = g.thickness;
                                for d in [g.depth(i, j), 0.0, 0.3 * t, 0.5 * t, 0.9 * t] {
                                    assert_eq!(lines.decide_level(d, sure, level), lines.decide_crossed(i, d, sure));
                                }
                                levels += 1;
                            }
                            crossed
                        }
                        _ => Some(false),
                    };
                    assert_eq!(apart, lines.decide(i, g.depth(i, j)), "node ({i}, {j}) of grid {k}");
                    match lines.decide(i, g.depth(i, j)) {
                        Some(b) => {
                            assert_eq!(b, ray, "node ({i}, {j}) of grid {k}, box {min:?} {max:?}");
                            decided += 1;
                        }
                        None => asked += 1,
                    }
                }
            }
            let mut every = 0;
            q.each(&w, |_, _| {
                every += 1;
                true
            });
            assert_eq!(q.count_walk(&w, usize::MAX), every, "box {min:?} {max:?}");
            for cap in [0, every / 2, every] {
                assert_eq!(q.count_walk(&w, cap), every.min(cap + 1), "cap {cap}");
            }
        }
        assert!(
            some > 1000 && decided > 10 * asked && levels > 1000,
            "{decided} decided, {asked} asked, {some} rays, {levels} nodes of level rows"
        );
    }

    /// The span where a predicate true on a prefix or a suffix holds is the one looking at
    /// every index gives: every range and every place of the change, both ways round.
    #[test]
    fn a_true_span_is_where_the_predicate_holds() {
        for a in 0..6usize {
            for b in a..a + 12 {
                for cut in a.saturating_sub(1)..=b + 1 {
                    for prefix in [true, false] {
                        let p = |i: usize| (i < cut) == prefix;
                        let held: Vec<usize> = (a..=b).filter(|&i| p(i)).collect();
                        let want = held.first().map(|&f| (f, *held.last().unwrap()));
                        assert_eq!(
                            true_span((a, b), p),
                            want,
                            "{a}..={b}, change at {cut}, prefix {prefix}"
                        );
                    }
                }
            }
        }
    }

    /// The box's depth bound along a segment is the one that looks at every pair of faces (a
    /// rising and a falling one cross), bit for bit, and no point of the segment sampled lies
    /// deeper in the box: random boxes and segments, some of them along an axis or in a plane
    /// of two (slopes of zero, and of minus zero).
    #[test]
    fn the_box_depth_bound_pairs_only_rising_and_falling_faces() {
        fn every_pair(
            min: &Vector3<f64>,
            max: &Vector3<f64>,
            o: Vector3<f64>,
            u: Vector3<f64>,
            lo: f64,
            hi: f64,
        ) -> f64 {
            let (lines, scale) = box_face_lines(min, max, o, u);
            let at = |t: f64| lines.iter().fold(f64::INFINITY, |m, &(c, s)| m.min(c + s * t));
            let mut best = at(lo).max(at(hi));
            for &(c1, s1) in &lines {
                for &(c2, s2) in &lines {
                    if s1 > 0.0 && s2 < 0.0 {
                        let t = (c2 - c1) / (s1 - s2);
                        if t > lo && t < hi {
                            best = best.max(at(t));
                        }
                    }
                }
            }
            best + 1e-9 * (scale + lo.abs() + hi.abs())
        }
        let mut rnd = crate::test_util::unit_random(31u64);
        let mut crossings = 0;
        for case in 0..4000 {
            let c = Vector3::new(100.0 * rnd() - 50.0, 100.0 * rnd() - 50.0, 100.0 * rnd() - 50.0);
            let h = Vector3::new(0.1 + 20.0 * rnd(), 0.1 + 20.0 * rnd(), 0.1 + 20.0 * rnd());
            let (min, max) = (c - h, c + h);
            let o = c + Vector3::new(60.0 * rnd() - 30.0, 60.0 * rnd() - 30.0, 60.0 * rnd() - 30.0);
            let mut u = Vector3::new(2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0, 2.0 * rnd() - 1.0);
            for k in 0..3 {
                match (case + k) % 5 {
                    0 => u[k] = 0.0,
                    1 if case % 3 == 0 => u[k] = -0.0,
                    _ => {}
                }
            }
            let (lo, hi) = (-40.0 * rnd(), 40.0 * rnd());
            let bound = box_depth_bound(&min, &max, o, u, lo, hi);
            assert_eq!(
                bound.to_bits(),
                every_pair(&min, &max, o, u, lo, hi).to_bits(),
                "case {case}"
            );
            let depth = |p: Vector3<f64>| {
                (0..3)
                    .map(|k| (p[k] - min[k]).min(max[k] - p[k]))
                    .fold(f64::INFINITY, f64::min)
            };
            for s in 0..=200 {
                let t = lo + (hi - lo) * s as f64 / 200.0;
                assert!(depth(o + t * u) <= bound, "case {case}, t {t}");
            }
            crossings += usize::from(bound > depth(o + lo * u).max(depth(o + hi * u)) + 1e-6);
        }
        assert!(crossings > 500, "{crossings} segments deepest inside");
    }

    /// A walk's count (a face grid's by rows of lines, [`RowLines`]) is the number of rays `each`
    /// visits, capped alike: every grid of a milled bar (a flat, a radial hole at 45°, a face
    /// pocket), against random boxes, with and without a dexel stock turned down under them
    /// (columns with no material); and a bored bar with a flat milled on it (inner radii, and
    /// columns of uniform nodes beside columns a cut wrote).
    #[test]
    fn a_walks_count_is_the_number_of_rays_it_visits() {
        let mut bored =
            Stock::turned(0.0, 60.0, 20.0, 0.1, |z| Some((if z > 20.0 { 9.0 } else { 0.0 }, 20.0))).unwrap();
        let c = Cutter::new(CutterKind::Flat, 16.0, 30.0).unwrap();
        let (p0, p1) = (Vector3::new(16.0, -30.0, 40.0), Vector3::new(16.0, 30.0, 40.0));
        assert!(bored.cut(&Sweep::new(&c, Vector3::x(), p0, p1, 0.1).unwrap()) > 0.0);
        let kinds = walks_count_their_rays(&holed_bar());
        assert!(kinds.len() >= 3, "{kinds:?}");
        assert!(walks_count_their_rays(&bored).contains("Cyl"));
    }

    /// The kinds of walk that visited a ray.
    fn walks_count_their_rays(s: &Stock) -> std::collections::BTreeSet<String> {
        let mut dexel = DexelStock::new(40.0, 0.0, 60.0, 60.0, 0.05);
        let groove = [(0.0, 20.0), (25.0, 20.0), (25.0, 40.0), (0.0, 40.0)];
        dexel.cut(&groove.map(|(x, z)| crate::geom::p2(x, z)));
        let mut rnd = crate::test_util::unit_random(9u64);
        let mut kinds = std::collections::BTreeSet::new();
        for case in 0..200 {
            let c = Vector3::new(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0, 70.0 * rnd() - 5.0);
            let h = Vector3::new(0.2 + 10.0 * rnd(), 0.2 + 10.0 * rnd(), 0.2 + 10.0 * rnd());
            let q = Query {
                stock: s,
                dexel: (case % 2 == 1).then_some(&dexel),
                min: c - h,
                max: c + h,
            };
            for r in walks(s, &q.min, &q.max).1 {
                let w = q.walk(r);
                let mut every = 0;
                q.each(&w, |_, _| {
                    every += 1;
                    true
                });
                if every > 0 {
                    kinds.insert(format!("{r:?}"));
                }
                for cap in [usize::MAX, every, every / 2, 0] {
                    assert_eq!(
                        q.count_walk(&w, cap),
                        every.min(cap.saturating_add(1)),
                        "{r:?}, cap {cap}, box {c:?} ± {h:?}"
                    );
                }
            }
        }
        kinds
    }

    proptest::proptest! {
        /// The first of the fewest, counted smallest bound first and cut short, is the one a full
        /// count in order picks, ties and all.
        #[test]
        fn the_fewest_counted_short_is_the_first_of_the_fewest(
            items in proptest::collection::vec((0usize..6, 0usize..4), 0..7)
        ) {
            // (count, slack of the size bound over it); small counts make ties.
            let want = match items.iter().map(|&(c, _)| c).min() {
                Some(0) | None => None,
                Some(n) => Some((items.iter().position(|&(c, _)| c == n).unwrap(), n)),
            };
            let got = fewest_of(
                items.clone(),
                |&(c, slack)| c + slack,
                |&(c, _), cap| c.min(cap.saturating_add(1)),
            );
            proptest::prop_assert_eq!(got.map(|(i, n, _)| (i, n)), want);
        }
    }

    /// Against the grid query itself: wherever the dexel stock proves the part clear, the grid
    /// query (with the dexel stock, at a touch depth) finds nothing; and poses into the bar are
    /// found by both (the proof is not vacuous).
    #[test]
    fn the_dexel_stock_clears_only_what_the_grid_query_finds_clear() {
        let s = milled_bar();
        let mut dexel = DexelStock::new(40.0, 0.0, 60.0, 60.0, 0.05);
        let b = cube(1.5);
        let touch = 2.0 * s.spacing();
        let mut rnd = crate::test_util::unit_random(7u64);
        let (mut cleared, mut hits) = (0, 0);
        for _ in 0..400 {
            let c = Vector3::new(14.0 + 10.0 * rnd(), 6.0 * rnd() - 3.0, -3.0 + 66.0 * rnd());
            let pose = at(c.x, c.y, c.z);
            let clear = dexel_clears_grid(&b, &pose, &mut dexel, touch);
            let got = grid_overlap(&b, &pose, &Iso::identity(), &s, touch, Some(&dexel), false);
            if clear {
                cleared += 1;
                assert!(got.is_none(), "the dexel stock cleared {c:?}, the grid found {got:?}");
            }
            hits += usize::from(got.is_some());
        }
        assert!(cleared > 50 && hits > 50, "cleared {cleared}, hits {hits}");
    }

    /// A cylindrical grid's ray with its x and y slabs taken once per angle (`Dir`) is bit for
    /// bit `slab` of the whole ray within its material: boxes at random (across the axis, off
    /// it, beside it, thin in x or y), every angle of the walk, its columns and the columns
    /// just beyond them (whose middle lies outside the box's z).
    #[test]
    fn a_radial_ray_slabbed_per_angle_is_the_whole_slab() {
        let s = milled_bar();
        let c = s.cyl.as_ref().unwrap();
        let mut rnd = crate::test_util::unit_random(23u64);
        let mut met = 0;
        for n in 0..200 {
            let lo = Vector3::new(50.0 * rnd() - 30.0, 50.0 * rnd() - 30.0, 70.0 * rnd() - 5.0);
            let mut size = Vector3::new(20.0 * rnd(), 20.0 * rnd(), 5.0 * rnd());
            if n % 5 == 0 {
                size[n % 2] = 0.0;
            }
            let q = Query {
                stock: &s,
                dexel: None,
                min: lo,
                max: lo + size,
            };
            let Walk::Cyl { j0, j1, reach, dirs } = q.walk(Rays::Cyl) else {
                continue;
            };
            // The walk's columns and two beyond each end (their middles outside the box's z).
            for j in j0.saturating_sub(2)..=(j1 + 2).min(c.nz - 1) {
                for d in &dirs {
                    let got = q.cyl_ray(j, d, reach);
                    let r = c.radius(d.i, j);
                    let o = Vector3::new(0.0, 0.0, c.z(j));
                    let want = (r > c.inner[j].max(reach))
                        .then(|| slab(o, d.u, &q.min, &q.max, c.inner[j], r))
                        .flatten()
                        .map(|(t0, t1)| (o, d.u, t0, t1));
                    let bits = |x: Option<NodeRay>| {
                        x.map(|(o, u, a, b)| (o.map(f64::to_bits), u.map(f64::to_bits), a.to_bits(), b.to_bits()))
                    };
                    assert_eq!(bits(got), bits(want), "column {j}, angle {}", d.i);
                    met += usize::from(got.is_some());
                }
            }
        }
        assert!(met > 1000, "{met} rays met a box");
    }

    /// A contact held at the floor's depth (a block pressed into the bar, sampled again at the
    /// deepest depth its contact reached) is answered by the deep search's own measures: a point
    /// deeper than the touch depth, no deeper than the floor, with no second walk; and the same
    /// pose lifted clear answers none.
    #[test]
    fn a_contact_at_the_floor_is_answered_by_the_deep_search() {
        let s = Stock::turned(0.0, 60.0, 20.0, 0.1, |_| Some((0.0, 20.0))).unwrap();
        let b = cube(3.0);
        let eps = 2.0 * s.spacing();
        let pose = at(21.0, 0.0, 30.0);
        let deepest = grid_overlap(&b, &pose, &Iso::identity(), &s, eps, None, false).unwrap();
        assert!(deepest.depth > 1.5, "{deepest:?}");
        let identity = Iso::identity();
        let mut q = At::new(&b, &pose, &identity, &s, None);
        let (deep, touched) = q.search((deepest.depth, eps), false, Some(MAX_RANKED));
        assert!(deep.is_none(), "{deep:?}");
        let t = touched.expect("the deep search measured a contact");
        assert!(t.depth > eps && t.depth <= deepest.depth, "{t:?}");
        let beyond = grid_overlap_beyond(&b, &pose, &Iso::identity(), &s, eps, None, deepest.depth);
        assert!(beyond.is_some_and(|h| h.depth <= deepest.depth), "{beyond:?}");
        let clear = at(24.0, 0.0, 30.0);
        assert!(grid_overlap_beyond(&b, &clear, &Iso::identity(), &s, eps, None, deepest.depth).is_none());
    }

    /// The deepest search (rays by their box's bound, deepest first; rays, stretches, pieces and
    /// runs skipped when they cannot beat the best) answers bit for bit as measuring every run
    /// of every ray in the walk's order: on a bar with a flat, a radial hole at 45° (a side grid
    /// whose rays lie oblique to the part's axes) and a face pocket, against a mesh and a
    /// primitive at random poses; and so does the same search on a walk too long to rank (in
    /// its order, the bounds skipping); a query for any contact finds one exactly when it does;
    /// and a query beyond a floor gives the same hit where it lies deeper than the floor, else
    /// one no deeper exactly when there is contact.
    #[test]
    fn the_deepest_search_answers_as_measuring_every_run_in_order() {
        let mut s = milled_bar();
        let drill = Cutter::new(CutterKind::Flat, 10.0, 40.0).unwrap();
        let d = Vector3::new(1.0, 1.0, 0.0).normalize();
        s.cut(
            &Sweep::new(
                &drill,
                -d,
                30.0 * d + Vector3::new(0.0, 0.0, 12.0),
                12.0 * d + Vector3::new(0.0, 0.0, 12.0),
                0.1,
            )
            .unwrap(),
        );
        let mill = Cutter::new(CutterKind::Flat, 12.0, 30.0).unwrap();
        s.cut(
            &Sweep::new(
                &mill,
                Vector3::z(),
                Vector3::new(-8.0, -6.0, 57.0),
                Vector3::new(4.0, -6.0, 57.0),
                0.1,
            )
            .unwrap(),
        );
        let prim = Shape3::from_geometry(
            &Geometry::Cylinder {
                radius: 6.0,
                z0: 0.0,
                z1: 30.0,
            },
            0.1,
        )
        .unwrap();
        let shapes = [cube(4.0), prim];
        let mut rnd = crate::test_util::unit_random(11u64);
        let (mut hits, mut cases) = (0, 0);
        for i in 0..40 {
            let c = Vector3::new(30.0 * rnd() - 10.0, 30.0 * rnd() - 15.0, 70.0 * rnd() - 5.0);
            let axis = nalgebra::Unit::new_normalize(Vector3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5));
            // Every third pose square to the grid: many points equally deep (the order among
            // them decides the point).
            let turn = if i % 3 == 0 { 0.0 } else { 6.0 * rnd() };
            let pose = Iso::from_parts(
                Translation3::from(c),
                nalgebra::UnitQuaternion::from_axis_angle(&axis, turn),
            );
            let part = Iso::from_parts(
                Translation3::identity(),
                nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), turn * rnd()),
            );
            for (k, shape) in shapes.iter().enumerate() {
                for eps in [1e-6, 0.3] {
                    // The dexel stock turned down after the hand-over (a groove the grid
                    // still holds): material is what both hold.
                    let dexel = (k == 1).then(|| {
                        let mut d = DexelStock::new(40.0, 0.0, 60.0, 60.0, 0.05);
                        let groove = [(14.0, 20.0), (25.0, 20.0), (25.0, 40.0), (14.0, 40.0)];
                        d.cut(&groove.map(|(x, z)| crate::geom::p2(x, z)));
                        d
                    });
                    let fast = grid_overlap(shape, &pose, &part, &s, eps, dexel.as_ref(), false);
                    let slow = overlap_by(shape, &pose, &part, &s, eps, dexel.as_ref(), false, None);
                    // A walk too long to rank: in its order, the bounds skipping.
                    let long = overlap_by(shape, &pose, &part, &s, eps, dexel.as_ref(), false, Some(0));
                    let bits = |h: Option<Hit>| h.map(|h| (h.depth.to_bits(), h.point.coords.map(f64::to_bits)));
                    assert_eq!(bits(fast), bits(slow), "at {c:?}: {fast:?} against {slow:?}");
                    assert_eq!(bits(long), bits(slow), "at {c:?}: {long:?} against {slow:?}");
                    let any = grid_overlap(shape, &pose, &part, &s, eps, dexel.as_ref(), true);
                    assert_eq!(any.is_some(), slow.is_some(), "at {c:?}");
                    // Asked only beyond a floor: the same hit where it lies deeper by more than
                    // `BEYOND_MM`, else whether there is one (floors below, within `BEYOND_MM`
                    // of, at and above the deepest depth).
                    let deepest = slow.map_or(0.0, |h| h.depth);
                    let floors = [
                        0.0,
                        0.5 * deepest,
                        deepest - 2.0 * BEYOND_MM,
                        deepest - 0.5 * BEYOND_MM,
                        deepest,
                        deepest + 1e-9,
                        2.0 * deepest + 0.5,
                    ];
                    for floor in floors {
                        let beyond = grid_overlap_beyond(shape, &pose, &part, &s, eps, dexel.as_ref(), floor);
                        if slow.is_some_and(|h| h.depth > floor + BEYOND_MM || floor <= eps) {
                            assert_eq!(bits(beyond), bits(slow), "at {c:?} beyond {floor}");
                        } else {
                            assert_eq!(beyond.is_some(), slow.is_some(), "at {c:?} beyond {floor}");
                            assert!(
                                beyond.map_or(true, |h| h.depth <= (floor + BEYOND_MM).max(eps)),
                                "at {c:?} beyond {floor}"
                            );
                        }
                    }
                    hits += usize::from(slow.is_some());
                    cases += 1;
                }
            }
        }
        assert!(hits > cases / 5 && hits < cases, "{hits} of {cases}");
    }

    /// A cylinder as parry's primitive (cast in closed form) and as its mesh give the same
    /// answers in a face slot: clear above its floor, 0.2 and 1 mm deep below it. (The rays are
    /// cast from outside the component's box, not from the material's start: a start inside the
    /// cutter once hid the contact.)
    #[test]
    fn a_cylinder_primitive_and_its_mesh_agree_in_a_face_slot() {
        let mut s = Stock::turned(-100.0, 0.0, 25.0, 0.05, |_| Some((0.0, 25.0))).unwrap();
        let c = Cutter::new(CutterKind::Flat, 10.0, 30.0).unwrap();
        let a = Vector3::new(10.0, -8.0, -3.0);
        s.cut(&Sweep::new(&c, Vector3::z(), a, Vector3::new(10.0, 8.0, -3.0), 0.05).unwrap());
        let g = Geometry::Cylinder {
            radius: 5.0,
            z0: 0.0,
            z1: 40.0,
        };
        let mesh = Shape3::meshed(&g, 0.05).unwrap();
        let prim = Shape3::from_geometry(&g, 0.05).unwrap();
        assert!(prim.is_convex() && !mesh.is_convex());
        for (z, want) in [(-2.0, None), (-3.2, Some(0.2)), (-4.0, Some(1.0))] {
            for shape in [&mesh, &prim] {
                let h = grid_overlap(shape, &at(10.0, 0.0, z), &Iso::identity(), &s, 0.1, None, false);
                match (h, want) {
                    (None, None) => {}
                    (Some(h), Some(d)) => assert!((h.depth - d).abs() < 0.02, "z {z}: {h:?}"),
                    _ => panic!("z {z}: {h:?}, want {want:?}"),
                }
            }
        }
    }
}
