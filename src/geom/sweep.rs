//! Continuous first contact of a translating polygon (`--mode exact`, docs/checking.md).
//!
//! Polygon `a` translates along a path — a straight line, or a circle traced by its reference
//! point without rotating — while `b` stays put; `t ∈ [0, 1]` is the fraction of the path. A
//! *contact episode* is a maximal run of `t` where the penetration depth of
//! [`super::query`] exceeds [`TOUCH_EPS`].
//!
//! # Method
//!
//! 1. **Events.** Whether the interiors overlap can only change when a vertex of `a` crosses an
//!    edge of `b` or a vertex of `b` crosses an edge of `a` (between such times every
//!    orientation of a moving vertex against a fixed edge, and the reverse, keeps its sign, so
//!    the arrangement of the two outlines keeps its combinatorics). For a line the crossing time
//!    solves `n·d t = k`; for the circle `n·r (u(θ) − u(θ₀)) = k`, i.e. `cos(θ − φ) = c`, two
//!    roots a turn, kept when they fall in the swept range (a full turn works like any other
//!    sweep). A root counts when the crossing point lies on the edge (with a 1e-9 relative
//!    slack: an extra event is harmless, a missed one is not). Boxes prefilter the pairs.
//! 2. **Intervals.** Between consecutive events the overlap state is constant, so one exact
//!    [`interiors_overlap`](super::query::interiors_overlap) test at the midpoint classifies
//!    each interval. The set of overlapping times is open, so this classification is complete.
//! 3. **Depth.** In each overlapping interval the depth is evaluated at both ends and the
//!    middle. If all three exceed `TOUCH_EPS` the interval is taken as deep throughout (the depth
//!    is continuous; a dip below 1 µm in the middle of an overlap would merge two episodes, never
//!    lose one). Otherwise [`INTERIOR_SAMPLES`] more points are sampled, and if none of them
//!    exceeds `TOUCH_EPS` a golden-section search around the deepest looks for a narrow
//!    excursion. Runs of samples deeper than `TOUCH_EPS` are the episodes; their ends are located
//!    by regula falsi (Illinois) on the continuous depth, to 1e-13 in `t` or 1e-12 mm in depth, so
//!    `t_start` is the first time the depth exceeds `TOUCH_EPS` — not the first touch, which is
//!    earlier by `TOUCH_EPS` over the approach speed. `max_depth` is the larger of the depth at
//!    the deepest sample of the episode and at the peak a golden-section search (16 steps, on
//!    the boundary term of the depth) finds between its neighbours: exact when the depth peaks at
//!    an event, close when it is unimodal between samples (a corner sliding through a corner),
//!    otherwise a lower bound.
//!
//! # Precision
//!
//! Both polygons are moved to a local origin (the low corner of the swept box of `a` joined with
//! the box of `b`) before anything is computed, so a scene near 1e7 mm behaves like one near 0.
//! Arc offsets use `r·(u(θ) − u(θ₀)) = 2r·sin(Δθ/2)·(−sin θₘ, cos θₘ)`, which is exactly 0 at
//! `t = 0` and accurate for small `Δθ`. Grazing (touching only) is decided by the exact interval
//! tests and never reports a contact.

use super::query::{boxes_interiors_meet, depth_rings_above, finite_box, interiors_overlap_pts, local_origin, Ring};
use super::{Aabb, Polygon, P2, TOUCH_EPS, V2};
use std::f64::consts::{FRAC_PI_2, TAU};

/// One contact episode of a sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// First `t` at which the depth exceeds [`TOUCH_EPS`] (0 when the move starts overlapping).
    pub t_start: f64,
    /// Last `t` of the episode (1 when the move ends overlapping).
    pub t_end: f64,
    /// Largest depth reached in the episode, mm.
    pub max_depth: f64,
}

/// Arcs of more than this many turns are analysed over their first `MAX_TURNS` turns: later turns
/// repeat the same positions, and an episode still open at that point is reported to last to 1.
pub const MAX_TURNS: f64 = 16.0;
/// Depth samples inside each overlapping interval, besides its two ends.
pub const INTERIOR_SAMPLES: usize = 8;
const PEAK_ITERS: usize = 16;
const BISECT_ITERS: usize = 64;
const T_RES: f64 = 1e-13;
const LAMBDA_SLACK: f64 = 1e-9;
const T_SLACK: f64 = 1e-12;

/// First contact of `a` moving by `t·d`, `t ∈ [0, 1]`, against the fixed `b`: the first episode
/// of [`sweep_line_episodes`]. `None` when the move never overlaps `b` by more than
/// [`TOUCH_EPS`] (touching and grazing are not contact).
pub fn sweep_line(a: &Polygon, b: &Polygon, d: V2) -> Option<Contact> {
    sweep_line_episodes(a, b, d).into_iter().next()
}

/// Every contact episode of `a` moving by `t·d`, in order of `t`.
pub fn sweep_line_episodes(a: &Polygon, b: &Polygon, d: V2) -> Vec<Contact> {
    if !(d.x.is_finite() && d.y.is_finite()) {
        return Vec::new();
    }
    episodes(a, b, Path::Line(d), 1.0)
}

/// First contact of `a` translating along a circular path against the fixed `b`: the first
/// episode of [`sweep_arc_episodes`].
pub fn sweep_arc(a: &Polygon, b: &Polygon, center: P2, start: P2, sweep_angle: f64) -> Option<Contact> {
    sweep_arc_episodes(a, b, center, start, sweep_angle).into_iter().next()
}

/// Every contact episode of `a` translating, without rotating, so that its reference point —
/// at `start` in the pose `a` is given in — runs along the circle about `center` through
/// `start`, turning by `sweep_angle` radians (positive: counter-clockwise, from +x toward +y,
/// i.e. from +radius toward +z). `t` is the fraction of the swept angle. A full circle is
/// `sweep_angle = ±2π`; sweeps beyond [`MAX_TURNS`] turns are cut there.
pub fn sweep_arc_episodes(a: &Polygon, b: &Polygon, center: P2, start: P2, sweep_angle: f64) -> Vec<Contact> {
    let finite = [center.x, center.y, start.x, start.y, sweep_angle]
        .iter()
        .all(|v| v.is_finite());
    if !finite {
        return Vec::new();
    }
    let rv = start - center;
    let r = rv.norm();
    if r == 0.0 || sweep_angle == 0.0 || !r.is_finite() {
        return episodes(a, b, Path::Line(V2::zeros()), 1.0);
    }
    let th0 = rv.y.atan2(rv.x);
    let t_hi = (MAX_TURNS * TAU / sweep_angle.abs()).min(1.0);
    let mut out = episodes(
        a,
        b,
        Path::Arc {
            r,
            th0,
            dth: sweep_angle,
        },
        t_hi,
    );
    if t_hi < 1.0 {
        if let Some(last) = out.last_mut() {
            if last.t_end >= t_hi {
                last.t_end = 1.0;
            }
        }
    }
    out
}

#[derive(Clone, Copy, Debug)]
enum Path {
    Line(V2),
    Arc { r: f64, th0: f64, dth: f64 },
}

impl Path {
    /// Displacement of the moving polygon at `t`.
    fn offset(&self, t: f64) -> V2 {
        match *self {
            Path::Line(d) => d * t,
            Path::Arc { r, th0, dth } => {
                let h = 0.5 * t * dth;
                let m = th0 + h;
                let s = 2.0 * r * h.sin();
                V2::new(-s * m.sin(), s * m.cos())
            }
        }
    }

    /// Append the `t ∈ [0, t_hi]` where `n · offset(t) = k`.
    fn roots(&self, n: V2, k: f64, t_hi: f64, out: &mut Vec<f64>) {
        match *self {
            Path::Line(d) => {
                let nd = n.dot(&d);
                if nd != 0.0 {
                    let t = k / nd;
                    if (-T_SLACK..=t_hi + T_SLACK).contains(&t) {
                        out.push(t.clamp(0.0, t_hi));
                    }
                }
            }
            Path::Arc { r, th0, dth } => {
                let nn = n.norm();
                if nn == 0.0 || r == 0.0 || dth == 0.0 {
                    return;
                }
                let c = (k / r + n.x * th0.cos() + n.y * th0.sin()) / nn;
                if c.is_nan() || c.abs() > 1.0 + 1e-12 {
                    return; // no crossing (or not a number)
                }
                let phi = n.y.atan2(n.x);
                let alpha = c.clamp(-1.0, 1.0).acos();
                let step = TAU / dth.abs();
                let roots = [phi + alpha, phi - alpha];
                let count = if alpha == 0.0 { 1 } else { 2 };
                for &th in &roots[..count] {
                    let mut t = ((th - th0) / dth).rem_euclid(step);
                    // At most MAX_TURNS + 1 iterations: t_hi <= MAX_TURNS * step.
                    let mut guard = 0;
                    while t <= t_hi + T_SLACK && guard <= MAX_TURNS as usize + 1 {
                        out.push(t.min(t_hi));
                        t += step;
                        guard += 1;
                    }
                }
            }
        }
    }

    /// Box of the displacements over `t ∈ [0, t_hi]` (conservative).
    fn bbox(&self, t_hi: f64) -> Aabb {
        let mut b = Aabb::empty();
        b.add(P2::origin());
        b.add(P2::from(self.offset(t_hi)));
        if let Path::Arc { r, th0, dth } = *self {
            let span = t_hi * dth;
            let at = |th: f64| P2::new(r * (th.cos() - th0.cos()), r * (th.sin() - th0.sin()));
            if span.abs() >= TAU || th0.abs() > 1e3 {
                for k in 0..4 {
                    b.add(at(k as f64 * FRAC_PI_2));
                }
            } else {
                let (lo, hi) = if span > 0.0 {
                    (th0, th0 + span)
                } else {
                    (th0 + span, th0)
                };
                let mut k = (lo / FRAC_PI_2).ceil();
                let mut guard = 0;
                while k * FRAC_PI_2 <= hi && guard < 6 {
                    b.add(at(k * FRAC_PI_2));
                    k += 1.0;
                    guard += 1;
                }
            }
            b = b.inflate(1e-9 * r);
        }
        b
    }
}

/// A sweep in local coordinates.
struct Sweep<'a> {
    a: &'a Ring,
    b: &'a Ring,
    path: Path,
    t_hi: f64,
}

#[derive(Clone, Copy, Debug)]
struct Sample {
    t: f64,
    depth: f64,
}

fn episodes(a: &Polygon, b: &Polygon, path: Path, t_hi: f64) -> Vec<Contact> {
    let (ab, bb) = (a.aabb(), b.aabb());
    let pbox = path.bbox(t_hi);
    if !finite_box(ab) || !finite_box(bb) || !finite_box(&pbox) || t_hi.is_nan() || t_hi <= 0.0 {
        return Vec::new();
    }
    let swept = Aabb {
        min: ab.min + pbox.min.coords,
        max: ab.max + pbox.max.coords,
    };
    if !boxes_interiors_meet(&swept, bb) {
        return Vec::new();
    }
    let o = local_origin(&swept, bb);
    let la = Ring::shifted(a.points(), o);
    let lb = Ring::shifted(b.points(), o);
    let sw = Sweep {
        a: &la,
        b: &lb,
        path,
        t_hi,
    };
    sw.run(&pbox)
}

impl Sweep<'_> {
    fn moved(&self, t: f64) -> Ring {
        let off = self.path.offset(t);
        Ring::new(self.a.pts.iter().map(|p| p + off).collect())
    }

    fn overlaps_at(&self, t: f64) -> bool {
        let m = self.moved(t);
        interiors_overlap_pts(&m.pts, &m.aabb, &self.b.pts, &self.b.aabb)
    }

    /// The depth at `t`.
    fn depth_at(&self, t: f64) -> f64 {
        self.depth_above(t, f64::INFINITY)
    }

    /// The depth at `t`, or a lower bound of it above `enough` (see `depth_rings_above`).
    fn depth_above(&self, t: f64, enough: f64) -> f64 {
        let m = self.moved(t);
        if !interiors_overlap_pts(&m.pts, &m.aabb, &self.b.pts, &self.b.aabb) {
            return 0.0;
        }
        depth_rings_above(&m, self.b, enough)
    }

    /// Enough of the depth at `t` to compare it with `TOUCH_EPS`.
    fn depth_vs_eps(&self, t: f64) -> f64 {
        self.depth_above(t, TOUCH_EPS)
    }

    /// Times where a vertex of one polygon crosses an edge of the other, with 0 and `t_hi`.
    fn events(&self, pbox: &Aabb) -> Vec<f64> {
        let (a, b) = (self.a, self.b);
        let (n, m) = (a.pts.len(), b.pts.len());
        let swept = Aabb {
            min: a.aabb.min + pbox.min.coords,
            max: a.aabb.max + pbox.max.coords,
        };
        let mut ev = vec![0.0, self.t_hi];
        let mut roots = Vec::new();
        let meets = |p: P2, q: P2, bx: &Aabb| {
            p.x.max(q.x) >= bx.min.x && p.x.min(q.x) <= bx.max.x && p.y.max(q.y) >= bx.min.y && p.y.min(q.y) <= bx.max.y
        };
        let eb: Vec<usize> = (0..m)
            .filter(|&j| meets(b.pts[j], b.pts[(j + 1) % m], &swept))
            .collect();
        // Vertices of a against edges of b.
        for &v in &a.pts {
            let vbox = Aabb {
                min: v + pbox.min.coords,
                max: v + pbox.max.coords,
            };
            for &j in &eb {
                let (f0, f1) = b.edge(j);
                if !meets(f0, f1, &vbox) {
                    continue;
                }
                let fd = f1 - f0;
                let l2 = fd.norm_squared();
                let nrm = V2::new(-fd.y, fd.x);
                roots.clear();
                self.path.roots(nrm, nrm.dot(&(f0 - v)), self.t_hi, &mut roots);
                for &t in &roots {
                    let q = v + self.path.offset(t);
                    let lam = (q - f0).dot(&fd) / l2;
                    if (-LAMBDA_SLACK..=1.0 + LAMBDA_SLACK).contains(&lam) {
                        ev.push(t);
                    }
                }
            }
        }
        // Vertices of b against the moving edges of a.
        for &w in &b.pts {
            if !meets(w, w, &swept) {
                continue;
            }
            for i in 0..n {
                let (a0, a1) = a.edge(i);
                let ebox = Aabb {
                    min: P2::new(a0.x.min(a1.x), a0.y.min(a1.y)) + pbox.min.coords,
                    max: P2::new(a0.x.max(a1.x), a0.y.max(a1.y)) + pbox.max.coords,
                };
                if !meets(w, w, &ebox) {
                    continue;
                }
                let ed = a1 - a0;
                let l2 = ed.norm_squared();
                let nrm = V2::new(-ed.y, ed.x);
                roots.clear();
                self.path.roots(nrm, nrm.dot(&(w - a0)), self.t_hi, &mut roots);
                for &t in &roots {
                    let lam = (w - a0 - self.path.offset(t)).dot(&ed) / l2;
                    if (-LAMBDA_SLACK..=1.0 + LAMBDA_SLACK).contains(&lam) {
                        ev.push(t);
                    }
                }
            }
        }
        ev.retain(|t| t.is_finite());
        ev.sort_by(f64::total_cmp);
        ev.dedup_by(|x, y| *x - *y <= T_RES);
        if let Some(last) = ev.last_mut() {
            *last = self.t_hi; // dedup may have kept a neighbour instead
        }
        ev
    }

    fn run(&self, pbox: &Aabb) -> Vec<Contact> {
        let ev = self.events(pbox);
        let mut samples: Vec<Sample> = Vec::new();
        let mut prev_hi: Option<Sample> = None;
        for w in ev.windows(2) {
            let (lo, hi) = (w[0], w[1]);
            if hi <= lo {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            if !self.overlaps_at(mid) {
                samples.push(Sample { t: mid, depth: 0.0 });
                prev_hi = None;
                continue;
            }
            let d_lo = match prev_hi {
                Some(p) if p.t == lo => p.depth,
                _ => self.depth_vs_eps(lo),
            };
            let (d_mid, d_hi) = (self.depth_vs_eps(mid), self.depth_vs_eps(hi));
            let first = samples.len();
            samples.push(Sample { t: lo, depth: d_lo });
            samples.push(Sample { t: mid, depth: d_mid });
            samples.push(Sample { t: hi, depth: d_hi });
            prev_hi = Some(Sample { t: hi, depth: d_hi });
            if d_lo.min(d_mid).min(d_hi) > TOUCH_EPS {
                continue; // deep throughout (the depth is continuous and was deep at both ends)
            }
            // The depth crosses TOUCH_EPS here, or stays below it: sample densely.
            let k = INTERIOR_SAMPLES + 1;
            for i in 1..k {
                let t = lo + (hi - lo) * (i as f64) / (k as f64);
                samples.push(Sample {
                    t,
                    depth: self.depth_vs_eps(t),
                });
            }
            samples[first..].sort_by(|x, y| x.t.total_cmp(&y.t));
            if samples[first..].iter().all(|x| x.depth <= TOUCH_EPS) {
                // Look for a narrow excursion above TOUCH_EPS around the deepest sample.
                let (t0, t1) = peak_bracket(&samples[first..]);
                let found = self.golden_max(t0, t1);
                samples.push(found);
            }
        }
        samples.sort_by(|x, y| x.t.total_cmp(&y.t));
        samples.dedup_by(|x, y| {
            if x.t == y.t {
                y.depth = y.depth.max(x.depth);
                true
            } else {
                false
            }
        });
        self.collect(&samples)
    }

    /// Golden-section search for the deepest point of `[lo, hi]`, on the boundary term of the
    /// depth (the cheap one); the depth is then evaluated in full at the point found.
    fn golden_max(&self, lo: f64, hi: f64) -> Sample {
        let (t, _) = super::golden_section_max(lo, hi, T_RES, PEAK_ITERS, |t| self.depth_above(t, 0.0));
        Sample {
            t,
            depth: self.depth_at(t),
        }
    }

    /// The `t` where the depth crosses `TOUCH_EPS` between `lo` and `hi` (exactly one of them
    /// deeper), by regula falsi with the Illinois modification: exact in one step where the
    /// depth is linear in `t` (a corner moving into a face), never slower than bisection by
    /// much. Returns a `t` on the deep side, within 1e-13 or within 1e-12 mm of depth.
    fn crossing(&self, lo: Sample, hi: Sample) -> f64 {
        let rising = hi.depth > TOUCH_EPS;
        let (mut a, mut fa) = (lo.t, lo.depth - TOUCH_EPS);
        let (mut b, mut fb) = (hi.t, hi.depth - TOUCH_EPS);
        let mut side = 0;
        for i in 0..BISECT_ITERS {
            if b - a <= T_RES {
                break;
            }
            let mut t = if i % 8 == 7 {
                0.5 * (a + b)
            } else {
                (a * fb - b * fa) / (fb - fa)
            };
            if !(t > a && t < b) {
                t = 0.5 * (a + b);
            }
            let ft = self.depth_vs_eps(t) - TOUCH_EPS;
            let deep = ft > 0.0;
            if deep && ft <= 1e-6 * TOUCH_EPS {
                return t;
            }
            if deep != rising {
                // t lies on the side of `a`.
                a = t;
                fa = ft;
                if side == 1 {
                    fb *= 0.5;
                }
                side = 1;
            } else {
                b = t;
                fb = ft;
                if side == -1 {
                    fa *= 0.5;
                }
                side = -1;
            }
        }
        if rising {
            b
        } else {
            a
        }
    }

    fn collect(&self, s: &[Sample]) -> Vec<Contact> {
        let mut out = Vec::new();
        let mut i = 0;
        while i < s.len() {
            if s[i].depth <= TOUCH_EPS {
                i += 1;
                continue;
            }
            let t_start = if i == 0 { s[0].t } else { self.crossing(s[i - 1], s[i]) };
            let mut j = i;
            let mut k = i;
            while j < s.len() && s[j].depth > TOUCH_EPS {
                if s[j].depth > s[k].depth {
                    k = j;
                }
                j += 1;
            }
            let t_end = if j == s.len() {
                s[j - 1].t
            } else {
                self.crossing(s[j - 1], s[j])
            };
            // Refine the deepest sample between its neighbours.
            let lo = s[k.saturating_sub(1)].t;
            let hi = s[(k + 1).min(s.len() - 1)].t;
            let max_depth = self.depth_at(s[k].t).max(self.golden_max(lo, hi).depth);
            out.push(Contact {
                t_start,
                t_end,
                max_depth,
            });
            i = j;
        }
        out
    }
}

/// The neighbours of the deepest of some samples (in order of `t`).
fn peak_bracket(s: &[Sample]) -> (f64, f64) {
    let mut k = 0;
    for (i, x) in s.iter().enumerate() {
        if x.depth > s[k].depth {
            k = i;
        }
    }
    (s[k.saturating_sub(1)].t, s[(k + 1).min(s.len() - 1)].t)
}
