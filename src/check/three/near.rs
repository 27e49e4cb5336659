//! Near misses on the 3D path (`--clearance C > 0`): two components of a `never_touch` pair that
//! pass closer than C without touching, once per episode with the closest gap, as the 2D path
//! reports them for the turret and tools against the chuck and the tailstock.
//!
//! The scan follows the pair along the move as conservative advancement does (`collide3::motion`):
//! at `u` the pair is apart by the gap `g` (parry's boundary distance, or the distance of the two
//! bounding spheres when that alone is at least C); their relative motion over the rest of the move
//! is at most `ρ` per unit of `u`, so the gap changes by at most `ρ·δ` over a step `δ`. Outside the
//! band (`g ≥ C`) a step of `(g − C) / ρ` cannot enter it; inside it, a step of `min(C − g, g) / ρ`
//! can neither leave it nor reach contact (an approach that ends in a crash is followed down to the
//! minimum step). Steps are at least `min_step / ρ` (the 2D exact scan's `min(tolerance, C/2)`), so the
//! start and end of an episode are known within that travel, and the closest gap is the least gap
//! seen at the probes (between two probes the gap may dip below it by at most the step's travel). Overlapping (deeper than the pair's touching depth) is a collision, never a
//! near miss: it ends a near-miss episode, as in 2D. At most [`MAX_PROBES`] probes per pair and move.
//!
//! The in-process stock is not a near-miss obstacle, on this path as on the 2D one
//! (`docs/findings/near_miss.md`): `collide3::stock_gap` is a lower bound of the gap (column by
//! column, triangles boxed), good for proving skips but not for stating a closest gap.

use crate::collide3::{self, pair_bound, Path, Shape3, MAX_PROBES};
use crate::kin::{CompId, Kinematics, Poser};

/// One stretch of a move where the pair was within the clearance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct NearSpan {
    /// First and last probe inside the band.
    pub u0: f64,
    pub u1: f64,
    /// The least gap seen, and where.
    pub gap: f64,
    pub u_min: f64,
    /// The band holds to the end of the move (the episode may go on into the next one).
    pub to_end: bool,
}

/// What a near-miss scan of one pair along one move found.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct NearScan {
    pub spans: Vec<NearSpan>,
    pub probes: u64,
    /// The probe budget ran out here: the rest of the move is unchecked.
    pub unchecked: Option<f64>,
}

/// Scan the pair `a`, `b` along `path` for stretches closer than `clearance` (see the module docs).
/// `eps` is the pair's touching depth: overlaps up to it count as a gap of 0.
pub(crate) fn scan(
    k: &Kinematics,
    a: (CompId, &Shape3),
    b: (CompId, &Shape3),
    path: &dyn Path,
    clearance: f64,
    eps: f64,
    min_step: f64,
) -> NearScan {
    let mut out = NearScan::default();
    if clearance.is_nan() || clearance <= 0.0 {
        return out;
    }
    let min_step = min_step.max(collide3::MIN_STEP_MM);
    let spheres = (a.1.sphere(), b.1.sphere());
    let mut poser = Poser::focused(k, &[a.0, b.0]);
    let mut vals = Vec::with_capacity(k.axes.len());
    let mut delta = Vec::with_capacity(k.axes.len());
    let mut open: Option<NearSpan> = None;
    let mut u = 0.0f64;
    loop {
        out.probes += 1;
        if out.probes > MAX_PROBES {
            out.unchecked = Some(u);
            break;
        }
        path.at(u, &mut vals);
        poser.pose(k, &vals);
        let (pa, pb) = (*poser.world(a.0), *poser.world(b.0));
        // The bounding spheres' distance bounds the gap from below at no cost.
        let lb = ((pa * spheres.0.center) - (pb * spheres.1.center)).norm() - spheres.0.radius - spheres.1.radius;
        let (gap, contact) = if lb >= clearance {
            (lb, false)
        } else {
            let d = collide3::distance(a.1, &pa, b.1, &pb);
            if d > 0.0 {
                (d, false)
            } else {
                (0.0, collide3::overlaps(a.1, &pa, b.1, &pb, eps))
            }
        };
        if gap.is_nan() {
            out.unchecked = Some(u);
            break;
        }
        if !contact && gap < clearance {
            let s = open.get_or_insert(NearSpan {
                u0: u,
                u1: u,
                gap,
                u_min: u,
                to_end: false,
            });
            s.u1 = u;
            if gap < s.gap {
                (s.gap, s.u_min) = (gap, u);
            }
        } else if let Some(s) = open.take() {
            out.spans.push(s);
        }
        if u >= 1.0 {
            break;
        }
        path.deltas(u, 1.0, &mut delta);
        let rate = pair_bound(k, &poser, (a.0, &spheres.0), (b.0, &spheres.1), &delta) / (1.0 - u);
        if rate == 0.0 {
            // Nothing moves for the rest of the move: as it is now, so it stays.
            if let Some(s) = open.as_mut() {
                s.u1 = 1.0;
            }
            break;
        }
        if !rate.is_finite() {
            out.unchecked = Some(u);
            break;
        }
        // Inside the band, steps no longer than the gap either: no contact can begin before
        // it, so an approach that ends in a crash is followed down to the minimum step.
        let band = if contact {
            0.0
        } else if gap < clearance {
            (clearance - gap).min(gap)
        } else {
            gap - clearance
        };
        let next = (u + band.max(min_step) / rate).min(1.0);
        u = if next > u { next } else { (u + f64::EPSILON).min(1.0) };
    }
    if let Some(mut s) = open.take() {
        s.to_end = s.u1 >= 1.0 && out.unchecked.is_none();
        out.spans.push(s);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collide3::LinearPath;
    use crate::kin::{Axis, AxisKind, Component, Geometry, Iso, Role};
    use nalgebra::{Point3, Unit, Vector3};

    /// A 10 mm cube on an X slide coming at a fixed block whose face is at x = 0.
    fn two_cubes() -> (Kinematics, Vec<Shape3>) {
        // The fixed block is larger across, so that no faces are coplanar.
        let cube = |x0: f64, h: f64| Geometry::Cuboid {
            min: Point3::new(x0, -h, -h),
            max: Point3::new(x0 + 10.0, h, h),
        };
        let k = Kinematics {
            axes: vec![Axis {
                name: "x".into(),
                letter: 'X',
                kind: AxisKind::Linear {
                    dir: Unit::new_normalize(Vector3::x()),
                },
                zero: 0.0,
                travel: (f64::NEG_INFINITY, f64::INFINITY),
                rapid: 1000.0,
                path: 1,
            }],
            components: vec![
                Component {
                    name: "fixed".into(),
                    parent: None,
                    mount: Iso::identity(),
                    axis: None,
                    geometry: Some(cube(-10.0, 8.0)),
                    role: Role::Structure,
                    station: None,
                    label: None,
                },
                Component {
                    name: "slide".into(),
                    parent: None,
                    mount: Iso::identity(),
                    axis: Some(0),
                    geometry: Some(cube(0.0, 5.0)),
                    role: Role::Holder,
                    station: None,
                    label: None,
                },
            ],
            never_touch: vec![(0, 1)],
        };
        let shapes = k
            .components
            .iter()
            .map(|c| Shape3::meshed(c.geometry.as_ref().unwrap(), 0.01).unwrap())
            .collect();
        (k, shapes)
    }

    fn run(x0: f64, x1: f64, c: f64) -> NearScan {
        let (k, s) = two_cubes();
        let path = LinearPath {
            v0: vec![x0],
            v1: vec![x1],
        };
        scan(&k, (1, &s[1]), (0, &s[0]), &path, c, 0.02, 0.01)
    }

    #[test]
    fn a_pass_that_stops_half_a_millimetre_short_is_one_span_with_its_closest_gap() {
        // The slide comes from 20 mm away to 0.5 mm and back out is not part of this move.
        let r = run(20.0, 0.5, 1.0);
        assert_eq!(r.spans.len(), 1, "{r:?}");
        let s = r.spans[0];
        assert!((s.gap - 0.5).abs() < 1e-6, "{s:?}");
        assert!(s.to_end);
        // It entered the band (gap 1 mm) within the minimum step of u = 19/19.5.
        assert!((s.u0 - 19.0 / 19.5).abs() < 0.02 / 19.5 + 1e-9, "{s:?}");
    }

    #[test]
    fn a_pass_farther_than_the_clearance_has_no_span_and_skips_by_the_gap() {
        let r = run(50.0, 2.0, 1.0);
        assert!(r.spans.is_empty(), "{r:?}");
        // Advancement by the proven gap: a handful of probes, not 48 mm / 0.01 mm.
        assert!(r.probes < 40, "{r:?}");
    }

    #[test]
    fn a_crossing_is_a_collision_not_a_near_miss_and_ends_the_band() {
        // From 3 mm away into the fixed block: the band, then contact to the end.
        let r = run(3.0, -4.0, 1.0);
        assert_eq!(r.spans.len(), 1, "{r:?}");
        assert!(!r.spans[0].to_end, "{r:?}");
        assert!(r.spans[0].gap <= 0.02, "{r:?}");
    }

    #[test]
    fn no_clearance_scans_nothing() {
        let r = run(3.0, 0.5, 0.0);
        assert_eq!(r, NearScan::default());
    }
}
