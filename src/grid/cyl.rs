//! The cylindrical grid: a turned part's outer surface as `R(θ, z)`, with its bore `r_in(z)`.
//!
//! Node `(i, j)` stands for the ray from the spindle axis at angle `θ_i = (i + ½)·2π/nθ` and
//! height `z_j = z0 + (j + ½)·dz`: material from `r_in(z_j)` out to `R(i, j)`. A cut changes a
//! node only where the swept solid reaches the ray's outer end (the material is taken from
//! outside in): `R` becomes where the ray enters the sweep. A void a ray cannot see from outside
//! (a cross hole's far wall seen along another ray) is left as material: the grid never holds
//! less material than the part has.

use nalgebra::Vector3;

use super::cutter::{RayMemo, Sweep};

/// Most node angles whose rays' answers one cut keeps ([`CylGrid::cut`]): the angles past them
/// are cast in every column (the memo's memory stays a few MB whatever the grid).
const MEMO_ANGLES: usize = 1 << 15;

/// The cylindrical grid.
#[derive(Clone, Debug)]
pub struct CylGrid {
    pub(crate) z0: f64,
    pub(crate) dz: f64,
    pub(crate) nz: usize,
    pub(crate) nth: usize,
    /// `R` per node, θ fastest, of the columns a cut has reached (`ready`); the others' nodes
    /// all hold their column's `uniform` value and are never written (a zeroed allocation: a
    /// grid of millions of nodes costs only the pages its cuts reach).
    r: Vec<f64>,
    /// Whether column `j`'s nodes are in `r`.
    ready: Vec<bool>,
    /// The `R` of every node of a column not `ready`.
    uniform: Vec<f64>,
    /// The bore per z column.
    pub(crate) inner: Vec<f64>,
    /// The largest `R` per column (for quick rejects and the revolved envelope).
    pub(crate) col_max: Vec<f64>,
    /// The smallest `R` per column: a point of the column between its bore and this radius is
    /// material at every angle ([`CylGrid::surely_holds`]).
    col_min: Vec<f64>,
    /// At least every column's `col_max` (cuts only lower them, so the first value stays a
    /// bound): the radius outside which no point is material ([`CylGrid::may_hold`]).
    pub(crate) r_bound: f64,
    /// Rays cast by cuts so far (`Stock::rays`): a ray whose answer a cut took from its memo
    /// is not cast.
    pub(crate) rays: u64,
    /// Per node angle, the answer of the last ray cast at it in the cut under way
    /// ([`Sweep::ray_memo`]: the columns under a flat end mill fed square to its axis ask the
    /// same question at every height); emptied at each cut's start.
    memo: Vec<RayMemo>,
    /// `(cos θ_i, sin θ_i)` of the first node angles (at most `MEMO_ANGLES`), computed once as
    /// each ray of a cut computes them.
    pub(super) dirs: Vec<(f64, f64)>,
}

impl CylGrid {
    /// A grid of `nth × nz` nodes over `z0 .. z0 + nz·dz`, each column's material from the
    /// revolved profile `profile(z) → (r_in, r_out)` at the column's centre (`None`: empty).
    pub fn new(z0: f64, dz: f64, nz: usize, nth: usize, profile: impl Fn(f64) -> Option<(f64, f64)>) -> CylGrid {
        let r = vec![0.0; nth * nz];
        let mut inner = vec![0.0; nz];
        let mut col_max = vec![0.0; nz];
        for j in 0..nz {
            let z = z0 + (j as f64 + 0.5) * dz;
            let (ri, ro) = profile(z).unwrap_or((0.0, 0.0));
            let ro = ro.max(ri);
            inner[j] = ri;
            col_max[j] = ro;
        }
        let uniform = col_max.clone();
        let col_min = col_max.clone();
        let r_bound = col_max.iter().copied().fold(0.0, f64::max);
        CylGrid {
            z0,
            dz,
            nz,
            nth,
            r,
            ready: vec![false; nz],
            uniform,
            inner,
            col_max,
            col_min,
            r_bound,
            rays: 0,
            memo: Vec::new(),
            dirs: Vec::new(),
        }
    }

    pub fn theta(&self, i: usize) -> f64 {
        (i as f64 + 0.5) * std::f64::consts::TAU / self.nth as f64
    }

    /// `(cos θ_i, sin θ_i)`: from the table the cuts keep once a cut has made it, else worked
    /// out as the table's entries are.
    pub(crate) fn direction(&self, i: usize) -> (f64, f64) {
        match self.dirs.get(i) {
            Some(&cs) => cs,
            None => {
                let th = self.theta(i);
                (th.cos(), th.sin())
            }
        }
    }

    pub fn z(&self, j: usize) -> f64 {
        self.z0 + (j as f64 + 0.5) * self.dz
    }

    /// `R` at node `(i, j)`.
    pub fn radius(&self, i: usize, j: usize) -> f64 {
        if self.ready[j] {
            self.r[j * self.nth + i]
        } else {
            self.uniform[j]
        }
    }

    /// Column `j`'s `R` per node (θ fastest).
    pub(crate) fn column(&self, j: usize) -> std::borrow::Cow<'_, [f64]> {
        if self.ready[j] {
            std::borrow::Cow::Borrowed(&self.r[j * self.nth..(j + 1) * self.nth])
        } else {
            std::borrow::Cow::Owned(vec![self.uniform[j]; self.nth])
        }
    }

    /// Column `j`'s `R` per node (θ fastest) when a cut has reached it (`Ok`), else the one `R`
    /// all its nodes hold (`Err`).
    pub(crate) fn column_nodes(&self, j: usize) -> Result<&[f64], f64> {
        if self.ready[j] {
            Ok(&self.r[j * self.nth..(j + 1) * self.nth])
        } else {
            Err(self.uniform[j])
        }
    }

    /// Whether columns `a` and `b` hold the same `R` at every node.
    pub(crate) fn same_nodes(&self, a: usize, b: usize) -> bool {
        match (self.ready[a], self.ready[b]) {
            (false, false) => self.uniform[a] == self.uniform[b],
            _ => self.column(a).iter().zip(self.column(b).iter()).all(|(x, y)| x == y),
        }
    }

    /// Column `j`'s nodes, written out so that they can change one by one.
    fn column_mut(&mut self, j: usize) -> &mut [f64] {
        let nodes = &mut self.r[j * self.nth..(j + 1) * self.nth];
        if !self.ready[j] {
            nodes.fill(self.uniform[j]);
            self.ready[j] = true;
        }
        nodes
    }

    /// The columns whose centre lies in `[lo, hi]`.
    pub(crate) fn columns(&self, lo: f64, hi: f64) -> Option<(usize, usize)> {
        let a = ((lo - self.z0) / self.dz - 0.5).ceil().max(0.0);
        let b = ((hi - self.z0) / self.dz - 0.5).floor();
        if !(a.is_finite() && b.is_finite()) || b < a || a >= self.nz as f64 || b < 0.0 {
            return None;
        }
        Some((a as usize, (b as usize).min(self.nz - 1)))
    }

    /// The node angles whose ray can meet the box `[min, max]` in x, y: all of them when the box
    /// holds the axis, else the arc it spans seen from the axis.
    pub(crate) fn angles(&self, min: &Vector3<f64>, max: &Vector3<f64>) -> Vec<(usize, usize)> {
        if min.x <= 0.0 && max.x >= 0.0 && min.y <= 0.0 && max.y >= 0.0 {
            return vec![(0, self.nth - 1)];
        }
        let corners = [(min.x, min.y), (max.x, min.y), (max.x, max.y), (min.x, max.y)];
        // The box does not hold the axis: its corners' angles lie within less than π of its
        // centre's; the arc is from the least to the greatest of them, unwrapped about it.
        let c = ((min.y + max.y) / 2.0).atan2((min.x + max.x) / 2.0);
        let (lo, hi) = Self::spread(c, corners.iter().map(|&(x, y)| (y.atan2(x), 0.0)));
        self.arc_nodes(c, lo, hi)
    }

    /// The node angles whose ray can meet the sweep: the arc that the quadrilateral of its axis
    /// segment's ends, grown by the cutter's radius, spans seen from the axis (each corner's disc
    /// seen from the axis gives its angle ± asin(radius / distance), and the extreme tangents of
    /// a convex set grown by a disc touch the discs of its corners). Where that grown
    /// quadrilateral comes within a hair of the axis, the box's arc ([`CylGrid::angles`]).
    pub(crate) fn sweep_angles(&self, sw: &Sweep) -> Vec<(usize, usize)> {
        let corners = sw.corners_xy();
        let r = sw.reach();
        let clear = distance_to_quad(&corners) - r;
        if clear.is_nan() || clear <= 1e-6 * (1.0 + r) {
            return self.angles(&sw.min, &sw.max);
        }
        let (cx, cy) = corners
            .iter()
            .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / 4.0, b + y / 4.0));
        let c = cy.atan2(cx);
        let (lo, hi) = Self::spread(
            c,
            corners
                .iter()
                .map(|&(x, y)| (y.atan2(x), (r / x.hypot(y)).min(1.0).asin())),
        );
        self.arc_nodes(c, lo, hi)
    }

    /// The least and greatest of `angle ± half` about `c` (each unwrapped to within π of it).
    fn spread(c: f64, angles: impl Iterator<Item = (f64, f64)>) -> (f64, f64) {
        let tau = std::f64::consts::TAU;
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for (a, half) in angles {
            let mut a = a - c;
            a -= tau * (a / tau).round();
            lo = lo.min(a - half);
            hi = hi.max(a + half);
        }
        (lo, hi)
    }

    /// The node ranges whose angles lie in `[c + lo, c + hi]`, with a node's spacing of margin.
    fn arc_nodes(&self, c: f64, lo: f64, hi: f64) -> Vec<(usize, usize)> {
        let tau = std::f64::consts::TAU;
        let step = tau / self.nth as f64;
        let i0 = ((c + lo) / step - 0.5).floor() as i64;
        let i1 = ((c + hi) / step - 0.5).ceil() as i64;
        let n = self.nth as i64;
        if hi - lo >= tau || hi.is_nan() || lo.is_nan() || i1 - i0 + 1 >= n {
            return vec![(0, self.nth - 1)];
        }
        let (a, b) = (i0.rem_euclid(n) as usize, i1.rem_euclid(n) as usize);
        if a <= b {
            vec![(a, b)]
        } else {
            vec![(a, self.nth - 1), (0, b)]
        }
    }

    /// Apply a sweep (or with `apply` false only measure it): the volume removed and the
    /// columns changed. Column by column, the node angles under the sweep
    /// (`CylGrid::sweep_angles`). A ray whose question was asked at the same angle in an earlier
    /// column of this cut with the same answer's key (`Sweep::ray_memo`) takes that answer
    /// instead of being cast: bit for bit the same, so the same nodes change (tested against
    /// casting every ray).
    pub fn cut(
        &mut self,
        sw: &Sweep,
        air: &dyn Fn(Vector3<f64>) -> bool,
        step: f64,
        apply: bool,
    ) -> (f64, Option<(usize, usize)>) {
        self.cut_nodes(sw, air, step, apply, true)
    }

    /// [`CylGrid::cut`], with or without the memo of the rays' answers (without: every ray cast,
    /// the oracle of the memo).
    pub(crate) fn cut_nodes(
        &mut self,
        sw: &Sweep,
        air: &dyn Fn(Vector3<f64>) -> bool,
        step: f64,
        apply: bool,
        memo: bool,
    ) -> (f64, Option<(usize, usize)>) {
        let Some((j0, j1)) = self.columns(sw.min.z, sw.max.z) else {
            return (0.0, None);
        };
        // The sweep reaches no nearer the axis than its box's distance from it.
        let reach = (sw.max.x.max(-sw.min.x)).hypot(sw.max.y.max(-sw.min.y));
        // Nor nearer than the box's nearest point: material inside that radius is out of reach
        // (a node's ray meets the sweep only beyond it, so this skips only rays that miss).
        let near = (sw.min.x.max(-sw.max.x).max(0.0)).hypot(sw.min.y.max(-sw.max.y).max(0.0));
        let dth = std::f64::consts::TAU / self.nth as f64;
        let mut removed = 0.0;
        let mut changed: Option<(usize, usize)> = None;
        let arcs = self.sweep_angles(sw);
        // The node angles' directions, kept for all cuts (the oracle computes them every time).
        if memo && self.dirs.is_empty() {
            self.dirs = (0..self.nth.min(MEMO_ANGLES))
                .map(|i| {
                    let th = self.theta(i);
                    (th.cos(), th.sin())
                })
                .collect();
        }
        // The memo of this cut: its angles' entries emptied (the others are never read).
        let mut memos = std::mem::take(&mut self.memo);
        let keep = memo && sw.one_disc();
        if keep {
            memos.resize(self.nth.min(MEMO_ANGLES), None);
            for &(a, b) in &arcs {
                for m in memos.iter_mut().take(b + 1).skip(a) {
                    *m = None;
                }
            }
        }
        for j in j0..=j1 {
            if self.col_max[j] <= self.inner[j] || self.col_max[j] + 1e-9 < near {
                continue;
            }
            let z = self.z(j);
            let ri = self.inner[j];
            let mut col_changed = false;
            for &(a, b) in &arcs {
                for i in a..=b {
                    let rr = self.radius(i, j);
                    if rr <= ri {
                        continue;
                    }
                    let (c, s) = match self.dirs.get(i).filter(|_| memo) {
                        Some(&cs) => cs,
                        None => {
                            let th = self.theta(i);
                            (th.cos(), th.sin())
                        }
                    };
                    let u = Vector3::new(c, s, 0.0);
                    let o = Vector3::new(0.0, 0.0, z);
                    let (answer, cast) = match memos.get_mut(i).filter(|_| keep) {
                        Some(m) => sw.ray_memo(o, u, ri, rr.min(reach), m),
                        None => (sw.ray(o, u, ri, rr.min(reach)), true),
                    };
                    self.rays += u64::from(cast);
                    let Some((t_in, t_out)) = answer else {
                        continue;
                    };
                    if t_in >= rr {
                        continue;
                    }
                    // The sweep short of the boundary: only through air.
                    if t_out + 1e-9 < rr && !super::face::air_along(o, u, t_out, rr, step, air, &super::face::anywhere)
                    {
                        continue;
                    }
                    let nr = t_in.max(ri);
                    if nr < rr - 1e-9 {
                        removed += (rr * rr - nr * nr) / 2.0 * dth * self.dz;
                        if apply {
                            self.column_mut(j)[i] = nr;
                            col_changed = true;
                        }
                    }
                }
            }
            if col_changed {
                let nodes = self.column(j);
                let (hi, lo) = nodes
                    .iter()
                    .fold((ri, f64::INFINITY), |(hi, lo), &r| (hi.max(r), lo.min(r)));
                (self.col_max[j], self.col_min[j]) = (hi, lo);
                changed = Some(changed.map_or((j, j), |(a, b)| (a.min(j), b.max(j))));
            }
        }
        self.memo = memos;
        (removed, changed)
    }

    /// A turning cut: every node of the columns in `[lo, hi]` gets `R = min(R, r)`.
    pub fn turn(&mut self, lo: f64, hi: f64, r: f64) {
        let Some((j0, j1)) = self.columns(lo, hi) else { return };
        for j in j0..=j1 {
            let ri = self.inner[j];
            if self.ready[j] {
                for x in &mut self.r[j * self.nth..(j + 1) * self.nth] {
                    *x = x.min(r.max(ri));
                }
            } else {
                self.uniform[j] = self.uniform[j].min(r.max(ri));
            }
            self.col_max[j] = self.col_max[j].min(r.max(ri));
            self.col_min[j] = self.col_min[j].min(r.max(ri));
        }
    }

    /// The part `[lo, hi]` of `[a, b]` outside which no point `o + t·u` of the ray is material by
    /// this grid ([`CylGrid::contains`] is false there), or `None` when no point of `[a, b]` can
    /// be: the ray clipped to the grid's columns and to the cylinder of radius at most every
    /// column's largest `R` (of the columns the clipped ray spans, or all of them). A superset
    /// with a margin far above rounding, so a sampler that skips the points outside it answers
    /// as one that asks every point.
    pub(crate) fn may_hold(&self, o: Vector3<f64>, u: Vector3<f64>, a: f64, b: f64) -> Option<(f64, f64)> {
        const MARGIN: f64 = 1e-7;
        if a.is_nan() || b.is_nan() || a > b {
            return None;
        }
        let (z_lo, z_hi) = (self.z0, self.z0 + self.dz * self.nz as f64);
        let (mut lo, mut hi) = (a, b);
        if u.z.abs() < 1e-12 {
            if o.z < z_lo - MARGIN || o.z > z_hi + MARGIN {
                return None;
            }
        } else {
            let (t0, t1) = ((z_lo - o.z) / u.z, (z_hi - o.z) / u.z);
            lo = lo.max(t0.min(t1) - MARGIN);
            hi = hi.min(t0.max(t1) + MARGIN);
        }
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return None;
        }
        // The largest radius of the columns the clipped ray spans (a few: a ray across the axis)
        // or the bound of all of them (a ray along it).
        let col = |t: f64| super::floor((o.z + t * u.z - self.z0) / self.dz);
        let (c0, c1) = (col(lo).min(col(hi)) - 1.0, col(lo).max(col(hi)) + 1.0);
        let r = if c1 - c0 <= 64.0 && c0.is_finite() && c1.is_finite() {
            let (j0, j1) = (
                c0.max(0.0) as usize,
                (c1.max(0.0) as usize).min(self.nz.saturating_sub(1)),
            );
            self.col_max
                .get(j0..=j1)
                .map_or(self.r_bound, |s| s.iter().copied().fold(0.0, f64::max))
        } else {
            self.r_bound
        };
        let r = r * (1.0 + 1e-12) + MARGIN;
        // |(o + t·u)_xy|² ≤ r²: a t² + b t + c ≤ 0.
        let qa = u.x * u.x + u.y * u.y;
        let qb = 2.0 * (o.x * u.x + o.y * u.y);
        let qc = o.x * o.x + o.y * o.y - r * r;
        if qa < 1e-24 {
            return (qc <= 0.0).then_some((lo, hi));
        }
        let disc = qb * qb - 4.0 * qa * qc;
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let sq = disc.sqrt();
        let (t0, t1) = ((-qb - sq) / (2.0 * qa), (-qb + sq) / (2.0 * qa));
        let (lo, hi) = (lo.max(t0 - MARGIN), hi.min(t1 + MARGIN));
        (lo <= hi).then_some((lo, hi))
    }

    /// A part `[lo, hi]` of `[a, b]` on which every point `o + t·u` is material by this grid
    /// ([`CylGrid::contains`] is true there, the points' rounding included), or `None`: where
    /// the ray stays within the columns it spans, no nearer the axis than their largest bore and
    /// no farther than their smallest `R`, every node of those columns holds it. The distance
    /// from the axis is convex along a line, so the stretch within a radius is one interval
    /// whose ends bound it; both ends are checked with a margin far above rounding (1e-7 mm).
    pub(crate) fn surely_holds(&self, o: Vector3<f64>, u: Vector3<f64>, a: f64, b: f64) -> Option<(f64, f64)> {
        const MARGIN: f64 = 1e-7;
        /// Most columns one answer looks at (a longer span: `None`, the caller samples).
        const MAX_COLUMNS: f64 = 256.0;
        if a.is_nan() || b.is_nan() || a > b {
            return None;
        }
        let (za, zb) = (o.z + a * u.z, o.z + b * u.z);
        let (j0, j1) = (
            ((za.min(zb) - MARGIN - self.z0) / self.dz).floor(),
            ((za.max(zb) + MARGIN - self.z0) / self.dz).floor(),
        );
        if !(j0 >= 0.0 && j1 < self.nz as f64 && j1 - j0 <= MAX_COLUMNS) {
            return None;
        }
        let cols = j0 as usize..=j1 as usize;
        let r_min = self.col_min[cols.clone()].iter().copied().fold(f64::INFINITY, f64::min);
        let bore = self.inner[cols].iter().copied().fold(0.0, f64::max);
        let r = r_min * (1.0 - 1e-12) - MARGIN;
        if r.is_nan() || r <= bore + MARGIN {
            return None;
        }
        // |(o + t·u)_xy|² ≤ r²: qa t² + qb t + qc ≤ 0.
        let qa = u.x * u.x + u.y * u.y;
        let qb = 2.0 * (o.x * u.x + o.y * u.y);
        let rho = |t: f64| (o.x + t * u.x).hypot(o.y + t * u.y);
        let (lo, hi) = if qa < 1e-24 {
            (a, b)
        } else {
            let qc = o.x * o.x + o.y * o.y - r * r;
            let disc = qb * qb - 4.0 * qa * qc;
            if disc.is_nan() || disc < 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            (a.max((-qb - sq) / (2.0 * qa)), b.min((-qb + sq) / (2.0 * qa)))
        };
        // The ends within the radius less half the margin (the farthest points of the stretch)...
        let outer = r_min * (1.0 - 1e-12) - MARGIN / 2.0;
        if !(lo <= hi && rho(lo) <= outer && rho(hi) <= outer) {
            return None;
        }
        // ...and its nearest point to the axis beyond the bore.
        if bore > 0.0 {
            let t = if qa < 1e-24 {
                lo
            } else {
                (-qb / (2.0 * qa)).clamp(lo, hi)
            };
            let near = rho(t);
            if near.is_nan() || near < bore + MARGIN / 2.0 {
                return None;
            }
        }
        Some((lo, hi))
    }

    /// Whether the point is material by this grid (the node of its cell in θ and z).
    pub fn contains(&self, p: Vector3<f64>) -> bool {
        let j = super::floor((p.z - self.z0) / self.dz);
        if !(0.0..self.nz as f64).contains(&j) {
            return false;
        }
        let j = j as usize;
        let rho2 = p.x * p.x + p.y * p.y;
        let ri = self.inner[j];
        if rho2 < ri * ri || rho2 > self.col_max[j] * self.col_max[j] {
            return false;
        }
        let i = (super::floor(angle(p.x, p.y) / std::f64::consts::TAU * self.nth as f64) as usize).min(self.nth - 1);
        let r = self.radius(i, j);
        rho2 <= r * r
    }

    /// The volume of material (mm³): each node a wedge of its angle and column.
    pub fn volume(&self) -> f64 {
        let dth = std::f64::consts::TAU / self.nth as f64;
        let mut v = 0.0;
        for j in 0..self.nz {
            let ri = self.inner[j];
            for &r in self.column(j).iter() {
                v += (r * r - ri * ri).max(0.0) / 2.0;
            }
        }
        v * dth * self.dz
    }

    /// The largest radius of material in column `j` (the revolved envelope a turning spindle
    /// sweeps).
    pub fn envelope(&self, j: usize) -> f64 {
        self.col_max[j]
    }

    /// Nodes, written out or not.
    pub fn nodes(&self) -> usize {
        self.r.len()
    }

    /// The memory of its nodes and columns (a column's nodes count once a cut writes them out).
    pub fn bytes(&self) -> usize {
        let written = self.ready.iter().filter(|&&w| w).count() * self.nth;
        (written + 3 * self.inner.len()) * std::mem::size_of::<f64>() + self.ready.len()
    }
}

/// The angle of `(x, y)` in `[0, 2π)`, within 2e-5 rad of `atan2` (an octant reduction and an
/// odd polynomial on `[0, 1]`), at a fraction of its cost: the grid's point tests take it
/// millions of times per move, and 2e-5 rad is 1 µm at 50 mm, far below any node's spacing.
pub(crate) fn angle(x: f64, y: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    let (n, d, swap) = if ay <= ax { (ay, ax, false) } else { (ax, ay, true) };
    let t = n / d;
    let t2 = t * t;
    let mut a = t * (0.999_866_0 + t2 * (-0.330_299_5 + t2 * (0.180_141_0 + t2 * (-0.085_133_0 + t2 * 0.020_835_1))));
    if swap {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 {
        a = TAU - a;
    }
    if a >= TAU {
        a -= TAU;
    }
    a
}

/// The distance from the axis (the origin of x, y) to the quadrilateral of `corners` (0 inside).
fn distance_to_quad(corners: &[(f64, f64); 4]) -> f64 {
    let mut best = f64::INFINITY;
    let mut sign = 0i32;
    let mut convex_inside = true;
    for k in 0..4 {
        let (ax, ay) = corners[k];
        let (bx, by) = corners[(k + 1) % 4];
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (-(ax * dx + ay * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        best = best.min((ax + t * dx).hypot(ay + t * dy));
        // The origin's side of each edge: inside when the same for all (the quadrilateral is a
        // parallelogram, convex, possibly flat).
        let cross = dx * (-ay) - dy * (-ax);
        let s = if cross > 0.0 {
            1
        } else if cross < 0.0 {
            -1
        } else {
            0
        };
        if s != 0 {
            if sign == 0 {
                sign = s;
            } else if s != sign {
                convex_inside = false;
            }
        }
    }
    if convex_inside {
        0.0
    } else {
        best
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_fast_angle_is_within_2e5_rad_of_atan2_all_round() {
        let tau = std::f64::consts::TAU;
        for k in 0..100_000 {
            let th = tau * k as f64 / 100_000.0;
            let r = 0.1 + (k % 97) as f64;
            let (x, y) = (r * th.cos(), r * th.sin());
            let want = y.atan2(x).rem_euclid(tau);
            let mut d = (super::angle(x, y) - want).abs();
            d = d.min(tau - d);
            assert!(d < 2e-5, "{th}: {d}");
            assert!((0.0..tau).contains(&super::angle(x, y)));
        }
    }
}
