//! Motion bounds and conservative advancement along a move.
//!
//! **The bound** ([`motion_bound`]). A point `x` of component `comp` is posed by the joints on the
//! path from the root to `comp`. Along a linear path of axis values, each joint moves `x` at a
//! rate of at most `|Δ|` (a linear axis: the translation is a rotated unit direction times the
//! value) or `|Δθ| · dist(x, L)` (a rotary axis: angular speed `|Δθ|` in radians about its line
//! `L`, which the joints above it carry along rigidly). The speeds add (the chain rule of the
//! composed transform). The distance of `x` to `L` changes only through the joints below that
//! joint (its own rotation keeps it, the joints above move `L` and `x` together), so along the
//! path it is at most `R + D_below`: `R` the largest distance from `L` of the component's bounding
//! sphere posed at the start values (distance to a line is convex, so a sphere's is its centre's
//! plus its radius), `D_below` the bound of the joints below, found first. Integrating over the
//! path: `D = Σ_linear |Δ| + Σ_rotary |Δθ| · (R + D_below)`, an upper bound of how far any point
//! of the geometry moves. Over a part `[u, u + δ]` of a linear path every `Δ` scales by
//! `δ / (1 − u)` and `D_below` does not grow, so the bound of the part is at most that fraction
//! of the bound of `[u, 1]`: the rate used by the advancement.
//!
//! **A pair's bound** ([`pair_bound`]). The joints at and above the pair's nearest common
//! ancestor move both parts by one rigid motion, which changes no distance between them: the
//! pair's relative motion is bounded by the sum of each part's bound over its joints below that
//! ancestor (the same integral, stopped there).
//!
//! **Conservative advancement** ([`first_contact`]). At `u` the pair is apart by the proven
//! distance `d` (a lower bound of the boundaries' distance, `distance_bound`; 0 when
//! overlapping); their relative motion over the
//! next `δ` is at most `ρ · δ`, `ρ` the pair's rate ([`pair_bound`]), so no overlap can start
//! before `d / ρ`: the step is `max(d, m) / ρ`, `m` the caller's minimum step (at least
//! [`MIN_STEP_MM`]). A step longer than the proven gap moves any point at most `m` further than
//! the gap, so a contact it could step over reaches at most `m` into the other solid: with
//! `m ≤ eps` (the tests take `eps / 2`) shallower than the touching tolerance; the 3D path takes
//! `m` = the `--tolerance`, as the 2D check's advancement does. A probe that overlaps ends the search: the
//! contact boundary in the last step is bisected to 1e-9 in `u`. At most [`MAX_PROBES`] probes
//! are spent on one pair along one move; past them the rest of the move is `Unchecked`.

use nalgebra::{Point3, Vector3};

use super::{box_gap, distance_bound, overlap, overlaps, touches, Hit, Shape3, Sphere};
use crate::kin::{AxisKind, CompId, Geometry, Kinematics, Poser};

/// Most probes (overlap or distance tests) on one pair along one move.
pub const MAX_PROBES: u64 = 100_000;
/// The smallest advancement step, mm of relative motion.
pub const MIN_STEP_MM: f64 = 1e-6;
/// Parts whose measured distance exceeds this (mm) neither touch nor cross: parry's contact
/// and distance of the same triangles agree far closer than this.
const APART: f64 = 1e-6;
/// Bisection of a contact boundary stops at this width in the path parameter.
const BISECT_U: f64 = 1e-9;
/// The shortest step (a share of the move's path parameter) the posed boxes' gap is taken for
/// instead of a distance query.
const BOX_STRIDE: f64 = 1.0 / 512.0;

/// A move of the machine: axis values for each `u ∈ [0, 1]`, and a bound of how far each moves.
pub trait Path {
    /// The axis values at `u` (one per axis of the kinematics).
    fn at(&self, u: f64, out: &mut Vec<f64>);
    /// Per axis, an upper bound of how far its value travels while `u` goes from `u0` to `u1`;
    /// over `[u0, u0 + t·(u1 − u0)]` at most `t` times it.
    fn deltas(&self, u0: f64, u1: f64, out: &mut Vec<f64>);
}

/// Axis values going linearly from `v0` to `v1`.
#[derive(Clone, Debug)]
pub struct LinearPath {
    pub v0: Vec<f64>,
    pub v1: Vec<f64>,
}

impl Path for LinearPath {
    fn at(&self, u: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.v0.iter().zip(&self.v1).map(|(a, b)| a + (b - a) * u));
    }

    fn deltas(&self, u0: f64, u1: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.v0.iter().zip(&self.v1).map(|(a, b)| (b - a).abs() * (u1 - u0)));
    }
}

/// Scale of a revolved outline's circumscribed mesh with the fewest segments (`kin::shape`).
fn revolve_scale() -> f64 {
    1.0 / (std::f64::consts::PI / crate::kin::shape::MIN_SEGMENTS as f64).cos()
}

/// A sphere holding a geometry (and the collision shape `collide3` builds from it), own frame.
pub fn geometry_sphere(g: &Geometry) -> (Point3<f64>, f64) {
    let boxed = |lo: Point3<f64>, hi: Point3<f64>| {
        let c = nalgebra::center(&lo, &hi);
        (c, (hi - lo).norm() / 2.0)
    };
    match g {
        Geometry::Mesh(m) => {
            let mut lo = Point3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
            let mut hi = -lo;
            for p in &m.vertices {
                lo = lo.inf(p);
                hi = hi.sup(p);
            }
            if m.vertices.is_empty() {
                return (Point3::origin(), 0.0);
            }
            let c = nalgebra::center(&lo, &hi);
            let r = m.vertices.iter().map(|p| (p - c).norm()).fold(0.0, f64::max);
            (c, r)
        }
        Geometry::Revolved(o) => {
            let rmax = o.iter().map(|p| p.x.abs()).fold(0.0, f64::max) * revolve_scale();
            let z0 = o.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let z1 = o.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            boxed(Point3::new(-rmax, -rmax, z0), Point3::new(rmax, rmax, z1))
        }
        Geometry::Extruded { outline, half_width } => {
            let x0 = outline.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
            let x1 = outline.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max);
            let z0 = outline.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
            let z1 = outline.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
            let hw = half_width.abs();
            boxed(Point3::new(x0, -hw, z0), Point3::new(x1, hw, z1))
        }
        Geometry::Cuboid { min, max } => boxed(*min, *max),
        Geometry::Cylinder { radius, z0, z1 } => {
            let r = radius.abs();
            boxed(Point3::new(-r, -r, z0.min(*z1)), Point3::new(r, r, z0.max(*z1)))
        }
        Geometry::Cutter { radius, z0, z1, .. } => {
            // Its outline stays within the cylinder of its radius and flutes, then revolved.
            let r = radius.abs() * revolve_scale();
            boxed(Point3::new(-r, -r, z0.min(*z1)), Point3::new(r, r, z0.max(*z1)))
        }
    }
}

/// An upper bound of how far any point of `comp`'s geometry moves when the axis values go
/// linearly from `v0` to `v1` (see the module docs for the proof). 0 for a component without
/// geometry; infinite for non-finite values.
pub fn motion_bound(k: &Kinematics, comp: CompId, v0: &[f64], v1: &[f64]) -> f64 {
    let Some(c) = k.components.get(comp) else {
        return 0.0;
    };
    let Some(g) = &c.geometry else {
        return 0.0;
    };
    let (center, radius) = geometry_sphere(g);
    let mut poser = Poser::focused(k, &[comp]);
    poser.pose(k, v0);
    let value = |v: &[f64], a: usize| v.get(a).copied().unwrap_or(0.0);
    let delta: Vec<f64> = (0..k.axes.len()).map(|a| (value(v1, a) - value(v0, a)).abs()).collect();
    bound_from(k, &poser, comp, &Sphere { center, radius }, &delta)
}

/// [`motion_bound`] from its parts: `poser` posed at the start of the motion, a sphere holding
/// the component's solid (own frame), and per axis how far its value travels (`delta`). The
/// callers that advance along a move pass their posed tree and the collision shape's sphere, so
/// a bound costs a walk up the tree, not a pass over the geometry.
pub fn bound_from(k: &Kinematics, poser: &Poser, comp: CompId, sphere: &Sphere, delta: &[f64]) -> f64 {
    bound_below(k, poser, comp, sphere, delta, None)
}

/// The nearest common ancestor of two components (`None`: they share no root).
fn common_ancestor(k: &Kinematics, a: CompId, b: CompId) -> Option<CompId> {
    let mut chain = Vec::new();
    let mut p = Some(a);
    while let Some(q) = p {
        chain.push(q);
        p = k.components.get(q).and_then(|c| c.parent);
    }
    let mut p = Some(b);
    while let Some(q) = p {
        if chain.contains(&q) {
            return Some(q);
        }
        p = k.components.get(q).and_then(|c| c.parent);
    }
    None
}

/// An upper bound of how far the pair `a`, `b` can move relative to each other: the joints at
/// and above their nearest common ancestor carry both rigidly (distances between them do not
/// change), so each side's bound counts only its joints below it ([`bound_from`]'s sum,
/// stopped there). Two parts fixed to one slide that a move carries: 0.
pub fn pair_bound(k: &Kinematics, poser: &Poser, a: (CompId, &Sphere), b: (CompId, &Sphere), delta: &[f64]) -> f64 {
    let lca = common_ancestor(k, a.0, b.0);
    bound_below(k, poser, a.0, a.1, delta, lca) + bound_below(k, poser, b.0, b.1, delta, lca)
}

/// [`bound_from`] over the joints from `comp` up to, not including, `stop`.
fn bound_below(
    k: &Kinematics,
    poser: &Poser,
    comp: CompId,
    sphere: &Sphere,
    delta: &[f64],
    stop: Option<CompId>,
) -> f64 {
    if comp >= k.components.len() {
        return 0.0;
    }
    let (center, radius) = (sphere.center, sphere.radius);
    let centre_w = poser.world(comp) * center;
    let mut d = 0.0f64;
    let mut at = Some(comp);
    while let Some(i) = at {
        if Some(i) == stop {
            break;
        }
        let ci = &k.components[i];
        if let Some(a) = ci.axis {
            let delta = delta.get(a).copied().unwrap_or(0.0);
            match &k.axes[a].kind {
                AxisKind::Linear { .. } => d += delta.abs(),
                AxisKind::Rotary { origin, dir } => {
                    let frame = ci.parent.map_or(crate::kin::Iso::identity(), |p| *poser.world(p)) * ci.mount;
                    let o = frame * origin;
                    let u: Vector3<f64> = frame.rotation * dir.into_inner();
                    let w = centre_w - o;
                    let r = (w - u * w.dot(&u)).norm() + radius;
                    d += delta.to_radians().abs() * (r + d);
                }
            }
        }
        at = ci.parent;
    }
    if d.is_nan() {
        f64::INFINITY
    } else {
        d
    }
}

/// The outcome of conservative advancement for one pair along one move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Advance {
    /// No overlap deeper than `eps` anywhere on the move.
    Clear,
    /// First contact at `u` (within 1e-9 after the last clear probe).
    Contact { u: f64, hit: Hit },
    /// The probe budget ran out at `u`: the rest of the move is unchecked.
    Unchecked { u: f64 },
}

/// Conservative advancement of the pair `a`, `b` (components with their shapes) along `path`
/// (see the module docs): the first `u` where they overlap by more than `eps`.
pub fn first_contact(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &dyn Path,
    eps: f64,
    min_step: f64,
) -> Advance {
    first_contact_from(k, a, b, path, eps, min_step, 0.0).0
}

/// [`first_contact`] given a lower bound `start_gap` of the pair's gap at the path's start (0:
/// none known), and returning with it a lower bound of the gap at its end (0 after a contact or
/// when unknown) and the probes (overlap and distance queries) it spent. The broad phase first:
/// the gap of the two parts' posed boxes at the start ([`box_gap`]) is a lower bound of the
/// gap too, and a pair whose known gap exceeds the most its parts can move over the whole path
/// is clear without a query (0 probes): the gap at the end is then at least their difference.
/// (A run of short moves — the chords of polar interpolation — then costs one query now and
/// then instead of one per move; a tool far from a chuck costs none.)
pub fn first_contact_from(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &dyn Path,
    eps: f64,
    min_step: f64,
    start_gap: f64,
) -> (Advance, f64, u64) {
    first_contact_proving(k, a, b, path, eps, min_step, start_gap, None)
}

/// [`first_contact_from`] with a proof of stretches, when given: `prove(u0, u1)` true says that
/// no pose of the pair over `[u0, u1]` overlaps at all; the advancement then goes on from `u1` instead of
/// stepping through it ([`Stretches`]: tried where the steps are short). A proof never hides a
/// contact: it changes only where the probes fall.
#[allow(clippy::too_many_arguments)]
pub fn first_contact_proving(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &dyn Path,
    eps: f64,
    min_step: f64,
    start_gap: f64,
    prove: Option<&mut dyn FnMut(f64, f64) -> bool>,
) -> (Advance, f64, u64) {
    let mut poser = Poser::focused(k, &[a.0, b.0]);
    let mut vals = Vec::with_capacity(k.axes.len());
    let mut delta = Vec::with_capacity(k.axes.len());
    path.at(0.0, &mut vals);
    poser.pose(k, &vals);
    let start_gap = start_gap.max(box_gap(a.1, poser.world(a.0), b.1, poser.world(b.0)));
    if start_gap > 0.0 {
        path.deltas(0.0, 1.0, &mut delta);
        let reach = pair_bound(k, &poser, (a.0, &a.1.sphere()), (b.0, &b.1.sphere()), &delta);
        if reach.is_finite() && start_gap - reach > 0.0 {
            return (Advance::Clear, start_gap - reach, 0);
        }
    }
    let mut end_gap = 0.0;
    let (adv, probes) = advance(k, a, b, path, eps, min_step, &mut end_gap, prove);
    (adv, end_gap, probes)
}

/// Stretches of an advancement proven clear in one query each: tried where a step is shorter
/// than the next stretch (or, with `steps`, whatever the step: the stretch then covers at least
/// that many steps); a proven stretch doubles the next one, a failed one quarters it, and none
/// is tried again until the probes have covered that much.
pub struct Stretches {
    /// The next stretch's length in `u`; never below `base`.
    reach: f64,
    base: f64,
    steps: f64,
    /// No proof is tried before this `u` (after a failed one).
    hold: f64,
}

impl Stretches {
    /// `base`: the shortest stretch worth a proof (in `u`), a few of the advancement's shortest
    /// steps.
    pub fn new(base: f64) -> Stretches {
        Stretches {
            reach: base,
            base,
            steps: 0.0,
            hold: 0.0,
        }
    }

    /// Stretches tried at every step, each at least `steps` steps long.
    pub fn every_step(base: f64, steps: f64) -> Stretches {
        Stretches {
            steps,
            ..Stretches::new(base)
        }
    }

    /// Where the advancement may go on from `u` instead of stepping by `step`: the end of a
    /// stretch `prove` proves clear, or `None` (step as before).
    pub fn skip(&mut self, u: f64, step: f64, prove: impl FnOnce(f64, f64) -> bool) -> Option<f64> {
        if self.steps > 0.0 {
            self.reach = self.reach.max(self.steps * step);
        }
        if !super::positive(self.base) || step >= self.reach || u < self.hold || u >= 1.0 {
            return None;
        }
        let end = (u + self.reach).min(1.0);
        if prove(u, end) {
            self.reach *= 2.0;
            return Some(end);
        }
        self.hold = u + self.reach;
        self.reach = (self.reach / 4.0).max(self.base);
        None
    }
}

/// The shortest stretch an advancement proves clear (`Stretches`), in its shortest steps, and
/// in the steps it would take there.
const PROOF_STEPS: f64 = 16.0;
const PROOF_STRIDE: f64 = 8.0;

#[allow(clippy::too_many_arguments)]
fn advance(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &dyn Path,
    eps: f64,
    min_step: f64,
    end_gap: &mut f64,
    mut prove: Option<&mut dyn FnMut(f64, f64) -> bool>,
) -> (Advance, u64) {
    let mut poser = Poser::focused(k, &[a.0, b.0]);
    let mut vals = Vec::with_capacity(k.axes.len());
    let mut delta = Vec::with_capacity(k.axes.len());
    let spheres = (a.1.sphere(), b.1.sphere());
    let mut probes: u64 = 0;
    let min_step = min_step.max(MIN_STEP_MM);
    // The first probe's floor from the pair's bound over the whole move.
    path.at(0.0, &mut vals);
    poser.pose(k, &vals);
    path.deltas(0.0, 1.0, &mut delta);
    let mut floor = pair_bound(k, &poser, (a.0, &spheres.0), (b.0, &spheres.1), &delta) * BOX_STRIDE;
    if floor.is_nan() {
        floor = f64::INFINITY;
    }
    // A step's probe at `u`: whether the parts overlap, and a lower bound of the gap. The
    // posed boxes' gap (`box_gap`) is that bound at no query's cost when it is at least `floor`
    // (a step worth taking); else, when the last probe found the parts apart, the distance,
    // which when they are still measured [`APART`] answers the overlap too (none); else the
    // overlap test (`touches`: whether only), and the distance 0 without a query when it found
    // the parts touching or crossing. (Measured first on touching parts, the distance is the
    // dearer.)
    let mut apart = false;
    let mut probe = |u: f64, floor: f64, poser: &mut Poser| {
        path.at(u, &mut vals);
        poser.pose(k, &vals);
        let (pa, pb) = (*poser.world(a.0), *poser.world(b.0));
        let g = box_gap(a.1, &pa, b.1, &pb);
        if g > 0.0 && g >= floor {
            return (false, g);
        }
        if apart {
            let d = distance_bound(a.1, &pa, b.1, &pb);
            if d > APART {
                return (false, d);
            }
        }
        let (hit, touch) = touches(a.1, &pa, b.1, &pb, eps);
        let d = if hit || touch {
            0.0
        } else {
            distance_bound(a.1, &pa, b.1, &pb)
        };
        apart = d > APART;
        (hit, d)
    };
    // The pair's poses at `u` (the bisection's).
    let mut at_vals = Vec::with_capacity(k.axes.len());
    let mut poses_at = |u: f64, poser: &mut Poser| {
        path.at(u, &mut at_vals);
        poser.pose(k, &at_vals);
        (*poser.world(a.0), *poser.world(b.0))
    };
    let mut u = 0.0f64;
    let mut prev = 0.0f64;
    let mut stretches: Option<Stretches> = None;
    loop {
        probes += 1;
        if probes > MAX_PROBES {
            return (Advance::Unchecked { u }, probes);
        }
        // The move's end measures the gap the next move may carry.
        let (hit, d) = probe(u, if u >= 1.0 { f64::INFINITY } else { floor }, &mut poser);
        if hit {
            // Bisect the boundary between the last clear probe and this one, asking whether
            // only; then the hit at the boundary found.
            let (mut lo, mut hi) = (prev, u);
            while u > 0.0 && hi - lo > BISECT_U {
                probes += 1;
                if probes > MAX_PROBES {
                    return (Advance::Unchecked { u: lo }, probes);
                }
                let mid = lo + (hi - lo) / 2.0;
                if mid <= lo || mid >= hi {
                    break;
                }
                let (pa, pb) = poses_at(mid, &mut poser);
                if overlaps(a.1, &pa, b.1, &pb, eps) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let (pa, pb) = poses_at(hi, &mut poser);
            let Some(best) = overlap(a.1, &pa, b.1, &pb, eps) else {
                return (Advance::Unchecked { u: hi }, probes);
            };
            return (Advance::Contact { u: hi, hit: best }, probes);
        }
        if u >= 1.0 {
            *end_gap = d;
            return (Advance::Clear, probes);
        }
        path.deltas(u, 1.0, &mut delta);
        let rate = pair_bound(k, &poser, (a.0, &spheres.0), (b.0, &spheres.1), &delta) / (1.0 - u);
        if rate == 0.0 {
            *end_gap = d;
            return (Advance::Clear, probes); // nothing moves for the rest of the move
        }
        if !rate.is_finite() || d.is_nan() {
            return (Advance::Unchecked { u }, probes);
        }
        let step = d.max(min_step) / rate;
        prev = u;
        let proven = prove.as_mut().and_then(|prove| {
            let st =
                stretches.get_or_insert_with(|| Stretches::every_step(PROOF_STEPS * min_step / rate, PROOF_STRIDE));
            st.skip(u, step, |u0, u1| {
                probes += 1;
                prove(u0, u1)
            })
        });
        let next = proven.unwrap_or_else(|| (u + step).min(1.0));
        u = if next > u { next } else { (u + f64::EPSILON).min(1.0) };
        // The boxes' gap serves the next probe when it steps at least a share of the move (or
        // to its end): a box gap far below the distance would make many short steps.
        floor = rate * (1.0 - u).min(BOX_STRIDE);
    }
}
