//! A ray against a convex piece of a cutter swept along a segment, exactly.
//!
//! A cutter's pieces (`cutter.rs`) are discs (cylinders about the cutter axis between two
//! heights) and balls. A piece moved along the segment `p0 → p0 + v` with its axis fixed sweeps
//! a convex solid (the Minkowski sum of a convex piece and a segment), so a ray `o + t·u` meets
//! it in one interval of `t`. In the plane of `(t, s)` (`s` the fraction of the move) the pairs
//! with the ray point inside the piece at `s` form a convex set: one convex quadratic constraint
//! (the radius) and a few linear ones (the heights, `0 ≤ s ≤ 1`, the ray's range). Its extreme
//! `t` lie at a vertex of the linear constraints' polygon inside the quadratic, where an edge of
//! that polygon crosses the quadratic's boundary, or at the boundary's own extreme `t`: all
//! closed forms, tried in turn.

use nalgebra::{Vector2, Vector3};

/// `Q(t, s) = |c + t·p − s·q|² − r²`, as `A t² + 2B ts + C s² + 2D t + 2E s + F`.
#[derive(Clone, Copy, Debug)]
struct Quad {
    a: f64,
    b: f64,
    c: f64,
    d: f64,
    e: f64,
    f: f64,
}

impl Quad {
    /// From the dot products of `c`, `p`, `q` (any dimension) and the radius.
    fn from_dots([pp, pq, qq, cp, cq, cc]: [f64; 6], r: f64) -> Quad {
        Quad {
            a: pp,
            b: -pq,
            c: qq,
            d: cp,
            e: -cq,
            f: cc - r * r,
        }
    }

    fn new3(c: Vector3<f64>, p: Vector3<f64>, q: Vector3<f64>, r: f64) -> Quad {
        Quad::from_dots([p.dot(&p), p.dot(&q), q.dot(&q), c.dot(&p), c.dot(&q), c.dot(&c)], r)
    }

    fn new2(c: Vector2<f64>, p: Vector2<f64>, q: Vector2<f64>, r: f64) -> Quad {
        Quad::from_dots([p.dot(&p), p.dot(&q), q.dot(&q), c.dot(&p), c.dot(&q), c.dot(&c)], r)
    }

    fn at(&self, t: f64, s: f64) -> f64 {
        self.a * t * t + 2.0 * self.b * t * s + self.c * s * s + 2.0 * self.d * t + 2.0 * self.e * s + self.f
    }
}

/// A linear constraint `α t + β s + γ ≥ 0`.
type Lin = [f64; 3];

/// Roots of `a x² + 2 b x + c = 0` (a tangent counts once; none when there is none).
fn roots(a: f64, b: f64, c: f64) -> ([f64; 2], usize) {
    if a.abs() < 1e-300 {
        if b.abs() < 1e-300 {
            return ([0.0; 2], 0);
        }
        return ([-c / (2.0 * b), 0.0], 1);
    }
    let disc = b * b - a * c;
    let scale = (b * b).max((a * c).abs()).max(1e-300);
    if disc < -1e-12 * scale {
        return ([0.0; 2], 0);
    }
    let sq = disc.max(0.0).sqrt();
    // The stable pair of formulas: x = k / a and x = c / k with k = −(b ± √disc), sign of b.
    let k = -(b + if b >= 0.0 { sq } else { -sq });
    if k == 0.0 {
        // b = 0 and disc = 0: a double root at 0.
        return ([0.0, 0.0], 2);
    }
    let (x1, x2) = (k / a, c / k);
    ([x1.min(x2), x1.max(x2)], 2)
}

/// The interval of `t` over the convex set `{Q ≤ 0} ∩ {t0 ≤ t ≤ t1, 0 ≤ s ≤ 1} ∩ lins`.
fn extreme_t(q: &Quad, lins: &[Lin], t0: f64, t1: f64) -> Option<(f64, f64)> {
    // The polygon of the linear constraints: the (t, s) box clipped by each (at most 4 + 1 per
    // constraint vertices: on the stack).
    const CAP: usize = 12;
    let mut poly = [[0.0f64; 2]; CAP];
    let mut len = 4;
    poly[..4].copy_from_slice(&[[t0, 0.0], [t1, 0.0], [t1, 1.0], [t0, 1.0]]);
    let mut next = [[0.0f64; 2]; CAP];
    for l in lins {
        let mut n = 0;
        let val = |p: &[f64; 2]| l[0] * p[0] + l[1] * p[1] + l[2];
        for i in 0..len {
            let (a, b) = (poly[i], poly[(i + 1) % len]);
            let (va, vb) = (val(&a), val(&b));
            if va >= 0.0 && n < CAP {
                next[n] = a;
                n += 1;
            }
            if (va >= 0.0) != (vb >= 0.0) && n < CAP {
                let w = va / (va - vb);
                next[n] = [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])];
                n += 1;
            }
        }
        std::mem::swap(&mut poly, &mut next);
        len = n;
        if len == 0 {
            return None;
        }
    }
    let poly = &poly[..len];
    let inside_lin = |t: f64, s: f64| {
        let eps = 1e-9 * (1.0 + t.abs());
        (t0 - eps..=t1 + eps).contains(&t)
            && (-1e-12..=1.0 + 1e-12).contains(&s)
            && lins
                .iter()
                .all(|l| l[0] * t + l[1] * s + l[2] >= -1e-9 * (1.0 + l[2].abs()))
    };
    let tol_q = |t: f64, s: f64| 1e-9 * (1.0 + q.f.abs() + q.a * t * t + q.c * s * s);
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut take = |t: f64| {
        lo = lo.min(t);
        hi = hi.max(t);
    };
    // Vertices inside the quadratic.
    for v in poly {
        if q.at(v[0], v[1]) <= tol_q(v[0], v[1]) {
            take(v[0]);
        }
    }
    // Edges crossing its boundary.
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[(i + 1) % poly.len()]);
        let (dt, ds) = (b[0] - a[0], b[1] - a[1]);
        // Q(a + λ (b − a)) as a quadratic in λ.
        let qa = q.a * dt * dt + 2.0 * q.b * dt * ds + q.c * ds * ds;
        let qb = q.a * a[0] * dt + q.b * (a[0] * ds + a[1] * dt) + q.c * a[1] * ds + q.d * dt + q.e * ds;
        let qc = q.at(a[0], a[1]);
        let (r, n) = roots(qa, qb, qc);
        for &lam in &r[..n] {
            if (-1e-12..=1.0 + 1e-12).contains(&lam) {
                take(a[0] + lam.clamp(0.0, 1.0) * dt);
            }
        }
    }
    // The boundary's own extreme t (where ∂Q/∂s = 0), when inside the polygon.
    if q.c > 1e-300 {
        let a2 = q.a - q.b * q.b / q.c;
        let b2 = q.d - q.b * q.e / q.c;
        let c2 = q.f - q.e * q.e / q.c;
        let (r, n) = roots(a2, b2, c2);
        for &t in &r[..n] {
            let s = -(q.b * t + q.e) / q.c;
            if inside_lin(t, s) {
                take(t);
            }
        }
    }
    (lo <= hi).then_some((lo.max(t0), hi.min(t1)))
}

/// A ray seen across a sweep's axis: what [`ray_disc`] needs of the ray and the sweep, the
/// same for every disc piece of one cutter (computed once per ray).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Across {
    /// The ray's start, direction and the sweep's motion, projected across the axis.
    pw: Vector2<f64>,
    pu: Vector2<f64>,
    pv: Vector2<f64>,
    /// Their components along the axis: `h(t, s) = ha + t·ua − s·va`.
    ha: f64,
    ua: f64,
    va: f64,
}

/// A basis `(e1, e2)` of the plane across the unit axis `a`.
pub(crate) fn basis_across(a: Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let e1 = a
        .cross(&if a.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() })
        .normalize();
    (e1, a.cross(&e1))
}

impl Across {
    /// The ray `o + t·u` against a cutter whose tip moves from `p0` by `v` along the axis `a`
    /// with `(e1, e2)` its [`basis_across`].
    pub(crate) fn new(
        o: Vector3<f64>,
        u: Vector3<f64>,
        p0: Vector3<f64>,
        v: Vector3<f64>,
        a: Vector3<f64>,
        (e1, e2): (Vector3<f64>, Vector3<f64>),
    ) -> Across {
        let w = o - p0;
        let proj = |x: Vector3<f64>| Vector2::new(x.dot(&e1), x.dot(&e2));
        Across {
            pw: proj(w),
            pu: proj(u),
            pv: proj(v),
            ha: w.dot(&a),
            ua: u.dot(&a),
            va: v.dot(&a),
        }
    }

    /// What [`Across::disc_bound`] and [`Across::disc`] answer for this ray and a disc piece of
    /// heights `h0..h1` depends on, as bits, when the ray's height along the axis does not
    /// matter: the ray square to the axis (`ua` 0) and the motion too (`va` 0), not along it,
    /// and its height `ha` within the piece's (`ha − h0 ≥ 0`, `h1 − ha ≥ 0`, as `disc` computes
    /// them). Then `ha` enters only through those two signs: the height strip of `disc_bound`
    /// holds `ha` whatever it is, and the height constraints of `disc` are constants at least 0,
    /// which clip nothing from the `(t, s)` box and pass every candidate's test. So two rays of
    /// one sweep with the same key (a column of the cylindrical grid under a flat end mill fed
    /// across its axis, one height after another) get bit for bit the same interval. `None`:
    /// the answer may depend on the height.
    pub(crate) fn level_key(&self, (h0, h1): (f64, f64), (t0, t1): (f64, f64)) -> Option<[u64; 8]> {
        let level = self.ua == 0.0
            && self.va == 0.0
            && self.pu.norm_squared() >= 1e-24
            && self.ha - h0 >= 0.0
            && h1 - self.ha >= 0.0
            && t0.is_finite()
            && t1.is_finite();
        level.then(|| [self.pw.x, self.pw.y, self.pu.x, self.pu.y, self.pv.x, self.pv.y, t0, t1].map(f64::to_bits))
    }

    /// For a ray along the axis (`pu` 0, [`Across::disc`]'s first branch) of a sweep moved
    /// square to it (`va` 0): the `t` at which `disc` says the ray leaves the disc piece
    /// (heights `h0..h1`, the ray's range ending at `t1`) whenever it says the ray meets it.
    /// There every candidate is `(h − ha + s·va) / ua` with `s·va` a zero, whatever the
    /// fractions `s` the radius allows: the exit is the greatest over `h0`, `h1`, clipped to `t1`,
    /// the same number for every ray at this height (a face grid under a flat end mill fed
    /// across its axis: a node whose material already begins past the exit is left as it is,
    /// met or not). `None`: not such a ray.
    pub(crate) fn exit_along_axis(&self, (h0, h1): (f64, f64), t1: f64) -> Option<f64> {
        if !(self.form() == Form::RayAlongAxis && self.va == 0.0) {
            return None;
        }
        let hi = [h0, h1]
            .iter()
            .fold(f64::NEG_INFINITY, |hi, &h| hi.max((h - self.ha) / self.ua));
        Some(hi.min(t1))
    }

    /// An outer bound of the `t` where the ray can be inside the disc piece (radius `r`, heights
    /// `h0..h1`) at some instant of the move, within `[t0, t1]`: from the heights and from the
    /// radius alone, each a strip linear in `t` and `s`. `None`: certainly outside it. Closed
    /// forms, no clipping: a cheap test of whether [`Across::disc`] can say anything new.
    pub(crate) fn disc_bound(&self, (t0, t1): (f64, f64), r: f64, (h0, h1): (f64, f64)) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (t0, t1);
        // Heights: h0 ≤ ha + t·ua − s·va ≤ h1 for some s in [0, 1].
        let h_slack = 1e-9 * (1.0 + self.ha.abs() + h0.abs() + h1.abs() + self.va.abs());
        if self.ua.abs() > 1e-9 {
            let mut a = f64::INFINITY;
            let mut b = f64::NEG_INFINITY;
            for s in [0.0, 1.0] {
                for h in [h0 - h_slack, h1 + h_slack] {
                    let t = (h - self.ha + s * self.va) / self.ua;
                    a = a.min(t);
                    b = b.max(t);
                }
            }
            lo = lo.max(a);
            hi = hi.min(b);
        } else {
            // Height all but fixed along the ray: only the motion moves it.
            let reach = self.ua.abs() * t0.abs().max(t1.abs());
            let (a, b) = (self.ha - self.va.max(0.0) - reach, self.ha - self.va.min(0.0) + reach);
            if b < h0 - h_slack || a > h1 + h_slack {
                return None;
            }
        }
        // Radius: |pw + t·pu − s·pv| ≤ r bounds the projection on pu.
        let pp = self.pu.norm_squared();
        if pp > 1e-18 {
            let n = pp.sqrt();
            let half = r / n * (1.0 + 1e-9) + 1e-9;
            let c0 = -self.pw.dot(&self.pu) / pp;
            let c1 = -(self.pw - self.pv).dot(&self.pu) / pp;
            lo = lo.max(c0.min(c1) - half);
            hi = hi.min(c0.max(c1) + half);
        }
        let pad = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
        (lo <= hi + pad).then_some((lo - pad, hi + pad))
    }

    /// Which way [`Across::disc`] answers for this ray and motion.
    fn form(&self) -> Form {
        if self.pu.norm_squared() < 1e-24 {
            Form::RayAlongAxis
        } else if self.pv.norm_squared() <= STILL_MM * STILL_MM {
            Form::MotionAlongAxis
        } else if self.va.abs() <= STILL_MM {
            Form::MotionAcrossAxis
        } else {
            Form::General
        }
    }

    /// Whether [`Across::disc`] answers in closed form (a ray along the axis, a motion along or
    /// across it alone): then it costs about what [`Across::disc_bound`] does, and the bound is
    /// no cheaper test of a miss.
    pub(crate) fn closed_form(&self) -> bool {
        self.form() != Form::General
    }

    /// The `t ∈ [t0, t1]` where the ray is inside the disc piece (radius `r` about the axis, from
    /// height `h0` to `h1` above the tip) at some instant of the move.
    pub(crate) fn disc(&self, t: (f64, f64), r: f64, h: (f64, f64)) -> Option<(f64, f64)> {
        match self.form() {
            Form::RayAlongAxis => self.disc_ray_along_axis(t, r, h),
            Form::MotionAlongAxis => self.disc_along_axis(t, r, h),
            Form::MotionAcrossAxis => self.disc_across_axis(t, r, h),
            Form::General => self.disc_general(t, r, h),
        }
    }

    /// [`Across::disc`] for a ray along the cutter's axis (a face grid under an end mill): the
    /// fractions `s` that put the ray inside the disc's circle, then the heights at their ends.
    fn disc_ray_along_axis(&self, (t0, t1): (f64, f64), r: f64, (h0, h1): (f64, f64)) -> Option<(f64, f64)> {
        let Across { pw, pv, ha, ua, va, .. } = *self;
        let (qq, qw, ww) = (pv.norm_squared(), pw.dot(&pv), pw.norm_squared() - r * r);
        let (s0, s1) = if qq < 1e-24 {
            if ww > 0.0 {
                return None;
            }
            (0.0, 1.0)
        } else {
            let (rt, n) = roots(qq, -qw, ww);
            if n == 0 {
                return None;
            }
            (rt[0].max(0.0), rt[n - 1].min(1.0))
        };
        if s0 > s1 {
            return None;
        }
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for s in [s0, s1] {
            for h in [h0, h1] {
                let t = (h - ha + s * va) / ua;
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
        let (lo, hi) = (lo.max(t0), hi.min(t1));
        (lo <= hi).then_some((lo, hi))
    }

    /// [`Across::disc`] by the general method: the extreme `t` of the convex set of `(t, s)`
    /// (the oracle of the closed forms for motions along or across the axis alone).
    pub(crate) fn disc_general(&self, (t0, t1): (f64, f64), r: f64, (h0, h1): (f64, f64)) -> Option<(f64, f64)> {
        let Across { pw, pu, pv, ha, ua, va } = *self;
        let q = Quad::new2(pw, pu, pv, r);
        let lins = [[ua, -va, ha - h0], [-ua, va, h1 - ha]];
        extreme_t(&q, &lins, t0, t1)
    }

    /// [`Across::disc`] for a motion along the axis alone (across it, `pv`, taken as none): the
    /// disc piece stretched along the axis, a cylinder. The radius bounds `t` alone (the ray's
    /// shadow across the axis inside the circle), and so do the heights: some instant puts the
    /// ray's height `ha + t·ua − s·va` within the piece's when `ha + t·ua` lies within
    /// `[h0 + min(0, va), h1 + max(0, va)]`.
    fn disc_along_axis(&self, (t0, t1): (f64, f64), r: f64, (h0, h1): (f64, f64)) -> Option<(f64, f64)> {
        let (rl, rh) = chord(self.pw, self.pu, r)?;
        let (hl, hh) = within(self.ha, self.ua, (h0 + self.va.min(0.0), h1 + self.va.max(0.0)))?;
        let (lo, hi) = (t0.max(rl).max(hl), t1.min(rh).min(hh));
        (lo <= hi).then_some((lo, hi))
    }

    /// [`Across::disc`] for a motion across the axis alone (along it, `va`, taken as none): the
    /// heights bound `t` alone, and the ray's shadow across the axis meets the disc swept along
    /// `pv`, a capsule: the union of its end circles and the strip between them (convex, so one
    /// interval).
    fn disc_across_axis(&self, (t0, t1): (f64, f64), r: f64, (h0, h1): (f64, f64)) -> Option<(f64, f64)> {
        let Across { pw, pu, pv, ha, ua, .. } = *self;
        let (hl, hh) = within(ha, ua, (h0, h1))?;
        let (lo, hi) = (t0.max(hl), t1.min(hh));
        if lo > hi {
            return None;
        }
        let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
        let cross = |x: Vector2<f64>, y: Vector2<f64>| x.x * y.y - x.y * y.x;
        let len = pv.norm();
        let strip = within(pw.dot(&pv), pu.dot(&pv), (0.0, pv.norm_squared())).and_then(|(l0, l1)| {
            let (c0, c1) = within(cross(pw, pv), cross(pu, pv), (-r * len, r * len))?;
            Some((l0.max(c0), l1.min(c1))).filter(|(x, y)| x <= y)
        });
        for iv in [chord(pw, pu, r), chord(pw - pv, pu, r), strip].into_iter().flatten() {
            a = a.min(iv.0);
            b = b.max(iv.1);
        }
        let (lo, hi) = (lo.max(a), hi.min(b));
        (lo <= hi).then_some((lo, hi))
    }
}

/// How [`Across::disc`] answers: three closed forms, else the general method.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Form {
    /// The ray along the cutter's axis (`pu` 0).
    RayAlongAxis,
    /// The motion along the axis alone (`pv` below [`STILL_MM`]).
    MotionAlongAxis,
    /// The motion across the axis alone (`va` below [`STILL_MM`]).
    MotionAcrossAxis,
    General,
}

/// A motion shorter than this (mm) across the cutter's axis, or along it, is taken as none by
/// [`Across::disc`]: the swept solid then moves by at most a nanometre, orders of magnitude
/// below any grid's spacing, and its interval has a closed form. (The motions of a drill's
/// plunge across its axis, and of a mill fed square to its axis along it, are rounding:
/// 1e-14 mm on the NL1500Y sample.)
const STILL_MM: f64 = 1e-9;

/// The `t` for which `|c + t·p| ≤ r` (`p` not zero), `None` when none.
fn chord(c: Vector2<f64>, p: Vector2<f64>, r: f64) -> Option<(f64, f64)> {
    let (x, n) = roots(p.norm_squared(), c.dot(&p), c.norm_squared() - r * r);
    (n == 2).then_some((x[0], x[1]))
}

/// The `t` for which `a + t·b` lies within `[lo, hi]`: every `t` when `b` is 0 and `a` does.
fn within(a: f64, b: f64, (lo, hi): (f64, f64)) -> Option<(f64, f64)> {
    if b == 0.0 {
        return (lo <= a && a <= hi).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let (x, y) = ((lo - a) / b, (hi - a) / b);
    Some((x.min(y), x.max(y))).filter(|(x, y)| x <= y)
}

/// The ray `o + t·u`, `t ∈ [t0, t1]`, against a disc piece (radius `r` about the axis `a`, from
/// height `h0` to `h1` above the tip) of a cutter whose tip moves from `p0` by `v` (one piece
/// alone: the oracle of [`Sweep`](super::cutter::Sweep)'s skips).
#[cfg(test)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn ray_disc(
    o: Vector3<f64>,
    u: Vector3<f64>,
    t: (f64, f64),
    p0: Vector3<f64>,
    v: Vector3<f64>,
    a: Vector3<f64>,
    r: f64,
    h: (f64, f64),
) -> Option<(f64, f64)> {
    Across::new(o, u, p0, v, a, basis_across(a)).disc(t, r, h)
}

/// The ray against a ball of radius `r` whose centre moves from `c0` by `v` (a capsule).
pub fn ray_ball(
    o: Vector3<f64>,
    u: Vector3<f64>,
    (t0, t1): (f64, f64),
    c0: Vector3<f64>,
    v: Vector3<f64>,
    r: f64,
) -> Option<(f64, f64)> {
    let q = Quad::new3(o - c0, u, v, r);
    extreme_t(&q, &[], t0, t1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Slow oracle: sample t and s finely.
    fn brute_disc(
        o: Vector3<f64>,
        u: Vector3<f64>,
        p0: Vector3<f64>,
        v: Vector3<f64>,
        a: Vector3<f64>,
        r: f64,
        h: (f64, f64),
    ) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for i in 0..=2000 {
            let t = -20.0 + 40.0 * i as f64 / 2000.0;
            let x = o + t * u;
            let inside = (0..=400).any(|j| {
                let s = j as f64 / 400.0;
                let d = x - p0 - s * v;
                let hh = d.dot(&a);
                let rad = (d - hh * a).norm();
                hh >= h.0 && hh <= h.1 && rad <= r
            });
            if inside {
                lo = lo.min(t);
                hi = hi.max(t);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    #[test]
    fn a_ray_across_a_flat_mill_swept_sideways_meets_it_where_sampling_does() {
        let a = Vector3::new(0.0, 0.0, 1.0);
        let cases = [
            (
                Vector3::new(-10.0, 0.5, 1.0),
                Vector3::new(1.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(5.0, 0.0, 0.0),
            ),
            (
                Vector3::new(0.0, -10.0, 2.0),
                Vector3::new(0.0, 1.0, 0.0),
                Vector3::new(1.0, 1.0, 0.0),
                Vector3::new(3.0, 4.0, -1.0),
            ),
            (
                Vector3::new(1.0, 1.0, -10.0),
                Vector3::new(0.0, 0.6, 0.8),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(0.0, 2.0, 0.0),
            ),
            (
                Vector3::new(3.0, 0.0, 0.5),
                Vector3::new(-0.6, 0.0, 0.8),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, 0.0),
            ),
        ];
        for (o, u, p0, v) in cases {
            let got = ray_disc(o, u, (-20.0, 20.0), p0, v, a, 2.0, (0.0, 4.0));
            let want = brute_disc(o, u, p0, v, a, 2.0, (0.0, 4.0));
            match (got, want) {
                (Some(g), Some(w)) => {
                    assert!((g.0 - w.0).abs() < 0.05 && (g.1 - w.1).abs() < 0.05, "{g:?} vs {w:?}");
                }
                (None, None) => {}
                _ => panic!("{got:?} vs {want:?} for {o:?} {u:?}"),
            }
        }
    }

    #[test]
    fn a_ray_along_the_axis_of_a_mill_moving_across_it_meets_it_where_sampling_does() {
        let a = Vector3::new(0.0, 0.0, 1.0);
        for (o, p0, v) in [
            (
                Vector3::new(1.0, 0.5, 10.0),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(5.0, 0.0, -1.0),
            ),
            (
                Vector3::new(6.5, 0.0, 10.0),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(5.0, 0.0, -2.0),
            ),
            (
                Vector3::new(3.0, 2.9, 10.0),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(5.0, 0.0, 0.0),
            ),
            (
                Vector3::new(0.0, 3.0, 10.0),
                Vector3::new(0.0, 0.0, 0.0),
                Vector3::new(0.0, 0.0, -3.0),
            ),
        ] {
            let u = -a;
            let got = ray_disc(o, u, (-20.0, 20.0), p0, v, a, 2.0, (0.0, 4.0));
            let want = brute_disc(o, u, p0, v, a, 2.0, (0.0, 4.0));
            match (got, want) {
                (Some(g), Some(w)) => assert!((g.0 - w.0).abs() < 0.05 && (g.1 - w.1).abs() < 0.05, "{g:?} vs {w:?}"),
                (None, None) => {}
                _ => panic!("{got:?} vs {want:?} for {o:?}"),
            }
        }
    }

    /// The closed forms of a motion along the axis alone and across it alone answer as the
    /// general method: random rays against random disc pieces, the motion's other part exactly
    /// 0; the same interval to 1e-9 of the sizes, or no interval, but where the ray grazes the
    /// piece (an interval of under 1e-6 mm that the two round apart).
    #[test]
    fn a_motion_along_or_across_the_axis_alone_meets_the_ray_where_the_general_method_does() {
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut met = [0usize; 2];
        for case in 0..20_000 {
            let mut v2 = || Vector2::new(40.0 * rnd() - 20.0, 40.0 * rnd() - 20.0);
            let (pw, mut pu, pv) = (v2(), v2(), v2());
            let mut u = || if rnd() < 0.2 { 0.0 } else { 2.0 * rnd() - 1.0 };
            let ua = u();
            if case % 7 == 0 {
                // Square to the motion, or along it.
                pu = if case % 2 == 0 {
                    Vector2::new(-pv.y, pv.x)
                } else {
                    pv * 0.3
                };
            }
            let along = case % 2 == 0;
            let across = Across {
                pw,
                pu: pu / pu.norm().max(1e-9),
                pv: if along { Vector2::zeros() } else { pv },
                ha: 60.0 * rnd() - 30.0,
                ua,
                va: if along { 60.0 * rnd() - 30.0 } else { 0.0 },
            };
            let r = 0.5 + 8.0 * rnd();
            let (h0, h1) = (10.0 * rnd() - 5.0, 5.0 + 20.0 * rnd());
            let t = (-40.0 * rnd(), 40.0 * rnd());
            let fast = across.disc(t, r, (h0, h1));
            let slow = across.disc_general(t, r, (h0, h1));
            match (fast, slow) {
                (Some(f), Some(s)) => {
                    met[usize::from(along)] += 1;
                    let tol = 1e-9 * 100.0;
                    assert!(
                        (f.0 - s.0).abs() <= tol && (f.1 - s.1).abs() <= tol,
                        "case {case}: {f:?} against {s:?} for {across:?} r {r} h {h0} {h1} t {t:?}"
                    );
                }
                (None, None) => {}
                (Some(i), None) | (None, Some(i)) => {
                    assert!(
                        i.1 - i.0 < 1e-6,
                        "case {case}: {fast:?} against {slow:?} for {across:?}"
                    );
                }
            }
        }
        assert!(met[0] > 800 && met[1] > 800, "{met:?}");
    }

    #[test]
    fn a_ray_through_a_capsule_meets_its_round_ends() {
        // Ball of radius 1 from (0,0,0) to (4,0,0); the ray along x at y = 0.6.
        let got = ray_ball(
            Vector3::new(-5.0, 0.6, 0.0),
            Vector3::x(),
            (-10.0, 20.0),
            Vector3::zeros(),
            Vector3::new(4.0, 0.0, 0.0),
            1.0,
        )
        .unwrap();
        let half = (1.0f64 - 0.36).sqrt();
        assert!(
            (got.0 - (5.0 - half)).abs() < 1e-9 && (got.1 - (9.0 + half)).abs() < 1e-9,
            "{got:?}"
        );
        assert!(ray_ball(
            Vector3::new(-5.0, 1.1, 0.0),
            Vector3::x(),
            (-10.0, 20.0),
            Vector3::zeros(),
            Vector3::new(4.0, 0.0, 0.0),
            1.0
        )
        .is_none());
    }
}
