//! A posed component against the milled stock (`grid::Stock`, issue 16).
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

use super::{to_pose, Hit, Shape3};
use crate::grid::Stock;
use crate::kin::Iso;
use crate::scene::DexelStock;

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
    if inside {
        out.push((start, t1));
    }
    // A ray through an edge or a vertex can count a crossing twice: each stretch must hold the
    // solid at its middle.
    out.retain(|&(a, b)| s.contains_point(&pos, at((a + b) / 2.0)));
}

/// Does the shape (posed at `pose`, machine frame) overlap the stock by more than `eps`? The
/// stock's frame is `part` (machine frame of the part: the main spindle's pose).
///
/// `dexel`: the checker's dexel stock, which turning cuts after the hand-over; the material is
/// what both hold (its radial intervals are intersected with each ray's, exactly).
pub fn grid_overlap(
    shape: &Shape3,
    pose: &Iso,
    part: &Iso,
    stock: &Stock,
    eps: f64,
    dexel: Option<&DexelStock>,
) -> Option<Hit> {
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
    // The face grids a cut changed, by their boxes: only there can they disagree with the
    // cylindrical grid (their starting depths follow the same profile).
    let touched: Vec<(usize, Vector3<f64>, Vector3<f64>)> = stock
        .faces
        .iter()
        .enumerate()
        .filter_map(|(k, f)| f.touched.map(|(a, b)| (k, a, b)))
        .filter(|(_, a, b)| (0..3).all(|i| b[i] >= min[i] && a[i] <= max[i]))
        .collect();
    let keep = |p0: Vector3<f64>, best: &mut Option<Hit>| {
        let depth = shape.depth_of(&ppose, Vector::new(p0.x, p0.y, p0.z));
        if depth > eps && best.map_or(true, |h| depth > h.depth) {
            *best = Some(Hit {
                depth,
                point: part * nalgebra::Point3::from(p0),
            });
        }
    };
    // Runs of material along [a, b] of a ray by the face grids that were cut near it.
    let runs = |o: Vector3<f64>, u: Vector3<f64>, a: f64, b: f64, faces: &[usize], best: &mut Option<Hit>| {
        if faces.is_empty() {
            keep(o + (a + b) / 2.0 * u, best);
            return;
        }
        let n = (((b - a) / step).ceil() as usize).clamp(1, 4096);
        let dt = (b - a) / n as f64;
        let mat = |k: usize| {
            let p = o + (a + (k as f64 + 0.5) * dt) * u;
            faces.iter().all(|&i| stock.faces[i].contains(p))
        };
        let mut k = 0;
        while k < n {
            if !mat(k) {
                k += 1;
                continue;
            }
            let first = k;
            while k < n && mat(k) {
                k += 1;
            }
            keep(o + (a + (first + k) as f64 / 2.0 * dt) * u, best);
        }
    };
    if let Some(c) = stock.cyl.as_ref() {
        let (j0, j1) = c.columns(min.z, max.z)?;
        let arcs = c.angles(&min, &max);
        let mut faces_here: Vec<usize> = Vec::new();
        for j in j0..=j1 {
            let z = c.z(j);
            let ri = c.inner[j];
            let dex = dexel.map(|d| d.material_at(z));
            if dex.as_ref().is_some_and(|m| m.is_empty()) {
                continue;
            }
            for &(a, b) in &arcs {
                for i in a..=b {
                    let r = c.radius(i, j);
                    if r <= ri {
                        continue;
                    }
                    let th = c.theta(i);
                    let u = Vector3::new(th.cos(), th.sin(), 0.0);
                    // The ray's stretch inside the box's x and y slabs.
                    let (mut t0, mut t1) = (ri, r);
                    for (d, lo, hi) in [(u.x, min.x, max.x), (u.y, min.y, max.y)] {
                        if d.abs() < 1e-15 {
                            if 0.0 < lo || 0.0 > hi {
                                t1 = f64::NEG_INFINITY;
                            }
                        } else {
                            let (x0, x1) = (lo / d, hi / d);
                            t0 = t0.max(x0.min(x1));
                            t1 = t1.min(x0.max(x1));
                        }
                    }
                    if t1 <= t0 {
                        continue;
                    }
                    let o = Vector3::new(0.0, 0.0, z);
                    // Cast from outside the component's box (its faces may be the component's
                    // own: a start on the boundary would leave the parity to chance), then keep
                    // the node's material stretch.
                    inside_stretches(shape, &ppose, o, u, t0 - 1.0, t1 + 1.0, &mut spans);
                    for &(s0, s1) in &spans {
                        let (s0, s1) = (s0.max(t0), s1.min(t1));
                        if s1 <= s0 {
                            continue;
                        }
                        let mut pieces: Vec<(f64, f64)> = Vec::new();
                        match &dex {
                            Some(m) => pieces.extend(
                                m.iter()
                                    .map(|&(lo, hi)| (s0.max(lo), s1.min(hi)))
                                    .filter(|(a, b)| b > a),
                            ),
                            None => pieces.push((s0, s1)),
                        }
                        for (a, b) in pieces {
                            let (pa, pb) = (o + a * u, o + b * u);
                            faces_here.clear();
                            faces_here.extend(
                                touched
                                    .iter()
                                    .filter(|(_, lo, hi)| {
                                        (0..3).all(|k| pa[k].max(pb[k]) >= lo[k] && pa[k].min(pb[k]) <= hi[k])
                                    })
                                    .map(|t| t.0),
                            );
                            runs(o, u, a, b, &faces_here, &mut best);
                        }
                    }
                }
            }
        }
    } else if let Some(f) = stock.faces.first() {
        let all: Vec<usize> = (0..stock.faces.len()).collect();
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
                inside_stretches(shape, &ppose, o, f.n, d, f.thickness, &mut spans);
                for &(s0, s1) in &spans.clone() {
                    runs(o, f.n, s0, s1, &all, &mut best);
                }
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
            let h = grid_overlap(&drill, &pose, &Iso::identity(), &s, touch, None);
            assert!(h.is_none(), "tip at y −{tip}: {h:?}");
        }
        let along_x = nalgebra::UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2);
        let pose = Iso::from_parts(Translation3::new(15.7, 0.0, 58.0), along_x);
        assert!(grid_overlap(&drill, &pose, &Iso::identity(), &s, touch, None).is_none());
        // Off its hole's axis by a millimetre, the drill cuts into the wall.
        let off = Iso::from_parts(Translation3::new(1.0, -17.0, 58.0), down);
        assert!(grid_overlap(&drill, &off, &Iso::identity(), &s, touch, None).is_some());
    }

    #[test]
    fn a_block_over_a_milled_flat_clears_it_and_the_same_block_on_the_round_bar_hits() {
        let s = milled_bar();
        let b = cube(2.0);
        let part = Iso::identity();
        // Above the flat (x 15 .. 19 at y 0): where the bar was, now air.
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &part, &s, 1e-6, None).is_none());
        // The same place 15 mm along z, where the bar is still round: a hit (the depth is a lower
        // bound: the deepest material point's distance to the block's surface, about 2).
        let h = grid_overlap(&b, &at(17.5, 0.0, 48.0), &part, &s, 1e-6, None).expect("hits the round bar");
        assert!(h.depth > 1.5 && h.depth < 4.5, "{h:?}");
        // Dipping 1 mm under the flat: a hit.
        assert!(grid_overlap(&b, &at(16.0, 0.0, 30.0), &part, &s, 1e-6, None).is_some());
        // The part turned by 180° about the axis: the flat is on the other side.
        let turned = Iso::from_parts(
            Translation3::identity(),
            nalgebra::UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI),
        );
        assert!(grid_overlap(&b, &at(-17.5, 0.0, 30.0), &turned, &s, 1e-6, None).is_none());
        assert!(grid_overlap(&b, &at(17.5, 0.0, 30.0), &turned, &s, 1e-6, None).is_some());
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
            let got = grid_overlap(&b, &at(c.x, c.y, c.z), &Iso::identity(), &s, 1e-6, None);
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
