//! A planar face grid (a matrix grid, docs/grid-stock.md): the depth `d(u, v)` of material removed from a
//! face along its inward normal.
//!
//! Node `(i, j)` stands for the ray from the face point `origin + u_i·e_u + v_j·e_v` along the
//! inward normal `n`: material from depth `d(i, j)` to the grid's `thickness`. A cut changes a
//! node only where the swept solid reaches the ray at its current depth (the material is taken
//! from the face in): `d` becomes where the ray leaves the sweep.

use nalgebra::Vector3;

use super::cutter::Sweep;

/// A face grid.
#[derive(Clone, Debug)]
pub struct FaceGrid {
    pub(crate) origin: Vector3<f64>,
    pub(crate) eu: Vector3<f64>,
    pub(crate) ev: Vector3<f64>,
    /// Inward normal.
    pub(crate) n: Vector3<f64>,
    pub(crate) du: f64,
    pub(crate) dv: f64,
    pub(crate) nu: usize,
    pub(crate) nv: usize,
    /// How deep the material goes along a ray.
    pub(crate) thickness: f64,
    /// Depth removed per node, u fastest.
    pub(crate) d: Vec<f64>,
    /// A box holding every sweep that removed something from this grid (world coordinates).
    pub(crate) touched: Option<(Vector3<f64>, Vector3<f64>)>,
    /// Rays cast by cuts so far (`Stock::rays`).
    pub(crate) rays: u64,
    /// What the last cut left for lack of air, while nothing else has changed the grid since.
    retrace: Option<Box<Retrace>>,
}

/// The nodes a cut left as they were for lack of air: the sweep held their ray from beyond where
/// the material begins, with material between by the stock's other grids. With that sweep, all a
/// cut by the same sweep again (a retract along a plunge) must look at (see
/// [`FaceGrid::cut_nodes`]).
#[derive(Clone, Debug)]
struct Retrace {
    sweep: Sweep,
    /// The node, and where its ray enters and leaves the sweep.
    nodes: Vec<(u32, f64, f64)>,
}

/// The most nodes a retrace keeps (24 bytes each, 6 MiB); a cut that leaves more keeps none.
const MAX_RETRACE_NODES: usize = 1 << 18;

impl FaceGrid {
    /// This face with its material from depth `start(u, v)` (`None`: no material on that ray) to
    /// its thickness, `(u, v)` a node's place on the face.
    pub fn with_start(mut self, start: impl Fn(f64, f64) -> Option<f64>) -> FaceGrid {
        let (nu, nv, t) = (self.nu, self.nv, self.thickness);
        for j in 0..nv {
            for i in 0..nu {
                let (u, v) = ((i as f64 + 0.5) * self.du, (j as f64 + 0.5) * self.dv);
                self.d[j * nu + i] = start(u, v).map_or(t, |s| s.clamp(0.0, t));
            }
        }
        self
    }

    /// A face over `origin + [0, nu·du]·e_u + [0, nv·dv]·e_v` (unit, orthogonal) whose material
    /// starts at the face on every ray and goes `thickness` deep along `n = e_u × e_v` (another
    /// start: [`FaceGrid::with_start`]). Its depths are a zeroed allocation: the pages of nodes no
    /// cut reaches are never touched (a side grid of millions of nodes costs nothing until a
    /// drill reaches it).
    pub fn flat(
        origin: Vector3<f64>,
        eu: Vector3<f64>,
        ev: Vector3<f64>,
        (du, dv): (f64, f64),
        (nu, nv): (usize, usize),
        thickness: f64,
    ) -> FaceGrid {
        FaceGrid {
            origin,
            eu,
            ev,
            n: eu.cross(&ev),
            du,
            dv,
            nu,
            nv,
            thickness,
            d: vec![0.0; nu * nv],
            touched: None,
            rays: 0,
            retrace: None,
        }
    }

    /// A grid of no nodes (a placeholder while a grid is being cut).
    pub(crate) fn empty() -> FaceGrid {
        FaceGrid {
            origin: Vector3::zeros(),
            eu: Vector3::x(),
            ev: Vector3::y(),
            n: Vector3::z(),
            du: 1.0,
            dv: 1.0,
            nu: 0,
            nv: 0,
            thickness: 0.0,
            d: Vec::new(),
            touched: None,
            rays: 0,
            retrace: None,
        }
    }

    /// The depth removed at node `(i, j)`.
    pub fn depth(&self, i: usize, j: usize) -> f64 {
        self.d[j * self.nu + i]
    }

    /// The face point of node `(i, j)`.
    pub fn node(&self, i: usize, j: usize) -> Vector3<f64> {
        self.origin + (i as f64 + 0.5) * self.du * self.eu + (j as f64 + 0.5) * self.dv * self.ev
    }

    /// The node range `[a, b]` along one face axis whose centres lie in `[lo, hi]`.
    pub(crate) fn range(lo: f64, hi: f64, step: f64, n: usize) -> Option<(usize, usize)> {
        let a = (lo / step - 0.5).ceil().max(0.0);
        let b = (hi / step - 0.5).floor();
        if !(a.is_finite() && b.is_finite()) || b < a || a >= n as f64 || b < 0.0 {
            return None;
        }
        Some((a as usize, (b as usize).min(n - 1)))
    }

    /// Apply a sweep (or with `apply` false only measure it); returns the volume removed (mm³).
    /// A node's ray loses the stretch the sweep holds when the sweep holds its boundary `d`, or
    /// when everything between `d` and the sweep is air by the stock's other grids (`air`,
    /// sampled every `step` mm, asked only where `span` says material may be).
    ///
    /// A node whose material begins at or past where its ray would leave the sweep is left
    /// without casting the ray when that exit is known beforehand (`Sweep::exit_along_axis`:
    /// a flat end mill fed across its axis, the rays along it): cast, its answer would leave the
    /// node as it is, met or not (tested against casting every ray).
    pub fn cut(
        &mut self,
        sw: &Sweep,
        air: &dyn Fn(Vector3<f64>) -> bool,
        span: Span<'_>,
        step: f64,
        apply: bool,
    ) -> f64 {
        self.cut_nodes(sw, air, span, step, apply, true)
    }

    /// [`FaceGrid::cut`], with or without the nodes left by their known exit (without: every
    /// ray cast, the oracle).
    pub(crate) fn cut_nodes(
        &mut self,
        sw: &Sweep,
        air: &dyn Fn(Vector3<f64>) -> bool,
        span: Span<'_>,
        step: f64,
        apply: bool,
        known_exits: bool,
    ) -> f64 {
        if apply && known_exits {
            if let Some(r) = self.retrace.take().filter(|r| r.sweep.same_bits(sw)) {
                return self.cut_retrace(r, air, span, step);
            }
        }
        // The nodes left for lack of air (kept when the cut applies and leaves nodes by their
        // known exits: the memo's cut, not the oracle's).
        let mut left = (apply && known_exits).then(Vec::new);
        let removed = self.cut_every_node(sw, air, span, step, apply, known_exits, &mut left);
        if apply {
            self.retrace = left.map(|nodes| {
                Box::new(Retrace {
                    sweep: sw.clone(),
                    nodes,
                })
            });
        }
        removed
    }

    /// A cut by the sweep of the last cut, nothing else having changed the grid since: only the
    /// nodes that cut left for lack of air can change (`Retrace`), and they are asked again
    /// whether the stretch above the sweep is air now.
    ///
    /// Why that is the cut: every other node's depth is what that cut left, and the same sweep
    /// gives its ray the same answer (bit for bit, the same numbers), so it is left again: the
    /// ray missed the sweep or left it at or before the node's depth (the cut left it so, or
    /// moved the depth to where the ray leaves); or the new depth was within 1e-9 of the old.
    /// A node's own grid never answers its air, so the order of the nodes does not matter.
    fn cut_retrace(
        &mut self,
        mut r: Box<Retrace>,
        air: &dyn Fn(Vector3<f64>) -> bool,
        span: Span<'_>,
        step: f64,
    ) -> f64 {
        let mut removed = 0.0;
        let mut kept = 0;
        for x in 0..r.nodes.len() {
            let (k, t_in, t_out) = r.nodes[x];
            let k = k as usize;
            let d = self.d[k];
            let o = self.node(k % self.nu, k / self.nu);
            if !air_along(o, self.n, d, t_in, step, air, span) {
                r.nodes[kept] = r.nodes[x];
                kept += 1;
                continue;
            }
            let nd = t_out.min(self.thickness);
            if nd <= d + 1e-9 {
                continue;
            }
            removed += (nd - d) * self.du * self.dv;
            self.d[k] = nd;
        }
        r.nodes.truncate(kept);
        if removed > 0.0 {
            self.note_touched(&r.sweep);
        }
        self.retrace = Some(r);
        removed
    }

    /// [`FaceGrid::cut_nodes`] casting the ray of every node under the sweep; the nodes it
    /// leaves for lack of air pushed on `left`, when given.
    #[allow(clippy::too_many_arguments)]
    fn cut_every_node(
        &mut self,
        sw: &Sweep,
        air: &dyn Fn(Vector3<f64>) -> bool,
        span: Span<'_>,
        step: f64,
        apply: bool,
        known_exits: bool,
        left: &mut Option<Vec<(u32, f64, f64)>>,
    ) -> f64 {
        // The sweep's box in face coordinates.
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for k in 0..8 {
            let c = Vector3::new(
                if k & 1 == 0 { sw.min.x } else { sw.max.x },
                if k & 2 == 0 { sw.min.y } else { sw.max.y },
                if k & 4 == 0 { sw.min.z } else { sw.max.z },
            ) - self.origin;
            for (a, e) in [self.eu, self.ev, self.n].iter().enumerate() {
                let x = c.dot(e);
                lo[a] = lo[a].min(x);
                hi[a] = hi[a].max(x);
            }
        }
        // Nothing within the material's depth.
        if hi[2] < 0.0 || lo[2] > self.thickness {
            return 0.0;
        }
        let (Some((i0, i1)), Some((j0, j1))) = (
            Self::range(lo[0], hi[0], self.du, self.nu),
            Self::range(lo[1], hi[1], self.dv, self.nv),
        ) else {
            return 0.0;
        };
        let mut removed = 0.0;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let k = j * self.nu + i;
                let d = self.d[k];
                if d >= self.thickness || d > hi[2] + 1e-9 {
                    continue;
                }
                let o = self.node(i, j);
                let across = sw.across_of(o, self.n);
                if known_exits && sw.exit_along_axis(&across, self.thickness).is_some_and(|t| t <= d) {
                    continue;
                }
                self.rays += 1;
                let Some((t_in, t_out)) = sw.ray_across(&across, o, self.n, lo[2].max(0.0), self.thickness) else {
                    continue;
                };
                if t_out <= d {
                    continue;
                }
                if t_in > d + 1e-9 && !air_along(o, self.n, d, t_in, step, air, span) {
                    // Past the most a retrace keeps, none is kept.
                    match left {
                        Some(l) if l.len() < MAX_RETRACE_NODES => l.push((k as u32, t_in, t_out)),
                        _ => *left = None,
                    }
                    continue;
                }
                let nd = t_out.min(self.thickness);
                if nd <= d + 1e-9 {
                    continue;
                }
                removed += (nd - d) * self.du * self.dv;
                if apply {
                    self.d[k] = nd;
                }
            }
        }
        if apply && removed > 0.0 {
            self.note_touched(sw);
        }
        removed
    }

    /// A sweep removed something: [`FaceGrid::touched`] grown to hold its box.
    fn note_touched(&mut self, sw: &Sweep) {
        let (a, b) = self.touched.unwrap_or((sw.min, sw.max));
        self.touched = Some((a.inf(&sw.min), b.sup(&sw.max)));
    }

    /// Whether the point is material by this grid.
    pub fn contains(&self, p: Vector3<f64>) -> bool {
        let w = p - self.origin;
        let (u, v, t) = (w.dot(&self.eu), w.dot(&self.ev), w.dot(&self.n));
        let (i, j) = (super::floor(u / self.du), super::floor(v / self.dv));
        if !(0.0..self.nu as f64).contains(&i) || !(0.0..self.nv as f64).contains(&j) {
            // Outside the face: this grid takes nothing there.
            return t >= 0.0;
        }
        t >= self.d[j as usize * self.nu + i as usize] && t <= self.thickness
    }

    /// The volume removed from the face so far (mm³): depth × node area.
    pub fn removed(&self) -> f64 {
        self.d.iter().sum::<f64>() * self.du * self.dv
    }

    pub fn bytes(&self) -> usize {
        self.d.len() * std::mem::size_of::<f64>()
    }
}

/// Of `n` samples at the middles of `n` equal steps over `[a, b]` (sample k at
/// `a + (b − a)(k + ½)/n`), those whose points lie within `[lo, hi]`, with a sample of margin on
/// each side (rounding never leaves one out).
pub(crate) fn samples_within(a: f64, b: f64, n: usize, lo: f64, hi: f64) -> std::ops::Range<usize> {
    let per = n as f64 / (b - a).max(f64::MIN_POSITIVE);
    let first = super::floor((lo - a) * per - 0.5) - 1.0;
    let end = super::ceil((hi - a) * per - 0.5) + 2.0;
    let clamp = |x: f64, or: usize| {
        if x.is_finite() {
            x.clamp(0.0, n as f64) as usize
        } else {
            or
        }
    };
    clamp(first, 0)..clamp(end, n)
}

/// Where along a ray material may be: the part of `[a, b]` of the ray `o + t·u` outside which
/// every point is air (`None`: all of it is), a superset ([`crate::grid::CylGrid::may_hold`]).
pub(crate) type Span<'a> = &'a dyn Fn(Vector3<f64>, Vector3<f64>, f64, f64) -> Option<(f64, f64)>;

/// The whole of `[a, b]`: no part of a ray proven air.
pub(crate) fn anywhere(_: Vector3<f64>, _: Vector3<f64>, a: f64, b: f64) -> Option<(f64, f64)> {
    Some((a, b))
}

/// Whether the ray `o + t·u` is air by `air` over `[a, b)`, sampled every `step` (at most 4096
/// samples: past them, not air). The middle sample is asked first, then only the samples within
/// `span`'s part of the ray: the others are air by it, so the answer is every sample's. No
/// sample is asked twice.
#[inline]
pub(crate) fn air_along(
    o: Vector3<f64>,
    u: Vector3<f64>,
    a: f64,
    b: f64,
    step: f64,
    air: &dyn Fn(Vector3<f64>) -> bool,
    span: Span<'_>,
) -> bool {
    let n = super::ceil((b - a) / step.max(1e-6));
    if !(n.is_finite() && n <= 4096.0) {
        return false;
    }
    let n = n.max(1.0) as usize;
    let sample = |k: usize| air(o + (a + (b - a) * (k as f64 + 0.5) / n as f64) * u);
    // The middle sample first, before the span is worked out: a stretch through the bar is
    // most often material there, and a sample that is material answers for all of them. (One
    // outside the span is air by it, so asking it changes nothing.)
    if !sample(n / 2) {
        return false;
    }
    let Some((lo, hi)) = span(o, u, a, b) else {
        return true;
    };
    let within = samples_within(a, b, n, lo, hi);
    if within.is_empty() {
        return true;
    }
    let (first, m) = (within.start, within.len());
    // The middle is known air now: not asked again.
    let at = |k: usize| first + k == n / 2 || sample(first + k);
    // Every sample must be air, so the order does not change the answer, only how soon
    // material is met: coarse to fine, so that a stretch of material of any width is met
    // after about `m / width` samples, not after every sample before it.
    let mut stride = m.next_power_of_two();
    at(m - 1)
        && loop {
            let top = stride >= m;
            if !(0..m)
                .step_by(stride.max(1))
                .filter(|&k| (top || k % (2 * stride) != 0) && k != m - 1)
                .all(at)
            {
                break false;
            }
            if stride <= 1 {
                break true;
            }
            stride /= 2;
        }
}
