//! A posed component against the milled stock (`grid::Stock`, issue 16).
//!
//! The stock's material lies on its cylindrical grid's rays (every grid cuts the cylindrical
//! grid's material down; a block without one: its first face grid's rays). The query walks the
//! rays of the nodes under the component's box (in the part's frame: the spindle turned by C),
//! finds each ray's stretches inside the component (boundary crossings by ray casting, the start
//! by point containment), and keeps those that meet the ray's material and that every grid
//! calls material (sampled at the grid's spacing). The depth is the longest such stretch along a
//! ray: a lower bound of the penetration. An overlap narrower than a node's spacing across the
//! rays can pass between them: the query resolves what the grid resolves.

use nalgebra::Vector3;
use parry3d_f64::math::Vector;
use parry3d_f64::query::Ray;

use super::{to_pose, Hit, Shape3};
use crate::grid::Stock;
use crate::kin::Iso;

/// Most boundary crossings followed along one ray.
const MAX_CROSSINGS: usize = 64;

/// The stretches of the ray `o + t·u`, `t ∈ [t0, t1]`, inside the shape (posed at `pose`).
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
    let mut t = t0;
    let mut inside = s.contains_point(&pos, at(t));
    let mut start = t;
    for _ in 0..MAX_CROSSINGS {
        let ray = Ray::new(at(t), dir);
        match s.cast_ray(&pos, &ray, t1 - t, false) {
            Some(toi) if t + toi < t1 => {
                let th = t + toi;
                if inside {
                    out.push((start, th));
                } else {
                    start = th;
                }
                inside = !inside;
                t = th + 1e-7;
                if t >= t1 {
                    break;
                }
            }
            _ => break,
        }
    }
    if inside {
        out.push((start, t1));
    }
}

/// Does the shape (posed at `pose`, machine frame) overlap the stock by more than `eps`? The
/// stock's frame is `part` (machine frame of the part: the main spindle's pose).
pub fn grid_overlap(shape: &Shape3, pose: &Iso, part: &Iso, stock: &Stock, eps: f64) -> Option<Hit> {
    // The shape in the part's frame.
    let local = part.inverse() * pose;
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
    let ppose = to_pose(&local);
    let step = stock.tolerance.max(1e-3);
    let mut best: Option<Hit> = None;
    let mut spans = Vec::new();
    let mut consider = |o: Vector3<f64>, u: Vector3<f64>, a: f64, b: f64, best: &mut Option<Hit>| {
        inside_stretches(shape, &ppose, o, u, a, b, &mut spans);
        for &(s0, s1) in &spans {
            if s1 - s0 <= eps {
                continue;
            }
            // The stretch's material by every grid, sampled.
            let n = (((s1 - s0) / step).ceil() as usize).clamp(1, 4096);
            let dt = (s1 - s0) / n as f64;
            let mut run = 0.0f64;
            let mut longest = 0.0f64;
            let mut at = None;
            for k in 0..n {
                let t = s0 + (k as f64 + 0.5) * dt;
                let p = o + t * u;
                if stock.contains(p) {
                    run += dt;
                    if run > longest {
                        longest = run;
                        at = Some(p);
                    }
                } else {
                    run = 0.0;
                }
            }
            if let Some(p) = at {
                if longest > eps && best.map_or(true, |h| longest > h.depth) {
                    *best = Some(Hit {
                        depth: longest,
                        point: part * nalgebra::Point3::from(p),
                    });
                }
            }
        }
    };
    if let Some(c) = stock.cyl.as_ref() {
        let (j0, j1) = c.columns(min.z, max.z)?;
        let arcs = c.angles(&min, &max);
        let reach = max.x.max(-min.x).hypot(max.y.max(-min.y));
        for j in j0..=j1 {
            let z = c.z(j);
            let ri = c.inner[j];
            for &(a, b) in &arcs {
                for i in a..=b {
                    let r = c.radius(i, j);
                    if r <= ri {
                        continue;
                    }
                    let th = c.theta(i);
                    let u = Vector3::new(th.cos(), th.sin(), 0.0);
                    consider(Vector3::new(0.0, 0.0, z), u, ri, r.min(reach), &mut best);
                }
            }
        }
    } else if let Some(f) = stock.faces.first() {
        for j in 0..f.nv {
            for i in 0..f.nu {
                let o = f.node(i, j);
                let d = f.depth(i, j);
                if d >= f.thickness {
                    continue;
                }
                let (pa, pb) = (o + d * f.n, o + f.thickness * f.n);
                let (lo, hi) = (pa.inf(&pb), pa.sup(&pb));
                if (0..3).any(|k| hi[k] < min[k] || lo[k] > max[k]) {
                    continue;
                }
                consider(o, f.n, d, f.thickness, &mut best);
            }
        }
    }
    best
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

    #[test]
    fn a_block_over_a_milled_flat_clears_it_and_the_same_block_on_the_round_bar_hits() {
        let s = milled_bar();
        let b = cube(2.0);
        let part = Iso::identity();
        // Above the flat (x 15 .. 19 at y 0): where the bar was, now air.
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &part, &s, 1e-6).is_none());
        // The same place 15 mm along z, where the bar is still round: a hit, 2.5 deep or so.
        let h = grid_overlap(&b, &at(17.5, 0.0, 48.0), &part, &s, 1e-6).expect("hits the round bar");
        assert!(h.depth > 2.0 && h.depth < 4.5, "{h:?}");
        // Dipping 1 mm under the flat: a hit.
        assert!(grid_overlap(&b, &at(16.0, 0.0, 30.0), &part, &s, 1e-6).is_some());
        // The part turned by 180° about the axis: the flat is on the other side.
        let turned = Iso::from_parts(
            Translation3::identity(),
            nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI),
        );
        assert!(grid_overlap(&b, &at(-17.5, 0.0, 30.0), &turned, &s, 1e-6).is_none());
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &turned, &s, 1e-6).is_some());
    }

    /// Against sampling: a box whose centre region holds material is found; a box the query
    /// finds holds material within a node's reach of it.
    #[test]
    fn the_grid_query_agrees_with_sampling_the_box() {
        let s = milled_bar();
        let b = cube(1.5);
        let mut seed = 99u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut hits = 0;
        for _ in 0..150 {
            let c = Vector3::new(10.0 + 12.0 * rnd(), 8.0 * rnd() - 4.0, 15.0 + 30.0 * rnd());
            let got = grid_overlap(&b, &at(c.x, c.y, c.z), &Iso::identity(), &s, 1e-6);
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
}
