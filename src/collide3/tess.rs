//! The small polygon and mesh helpers `collide3` needs beside `kin::shape` (which turns every
//! primitive into a closed mesh): whether an extruded outline is convex (then it is a parry
//! convex polyhedron, exact), and a UV sphere for tests and benchmarks.

use parry3d_f64::math::Vector;

/// Flip every triangle when the mesh's signed volume is negative (inward facing).
fn orient_outward(v: &[Vector], t: &mut [[u32; 3]]) {
    let vol: f64 = t
        .iter()
        .map(|tr| {
            let (a, b, c) = (v[tr[0] as usize], v[tr[1] as usize], v[tr[2] as usize]);
            a.dot(b.cross(c))
        })
        .sum();
    if vol < 0.0 {
        for tr in t.iter_mut() {
            tr.swap(1, 2);
        }
    }
}

/// A tessellated sphere (UV, `rings` × `segs`), for tests and benchmarks.
pub fn uv_sphere(radius: f64, rings: usize, segs: usize) -> (Vec<Vector>, Vec<[u32; 3]>) {
    let rings = rings.max(2);
    let segs = segs.max(3);
    let mut v = vec![Vector::new(0.0, 0.0, -radius)];
    for i in 1..rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        let (r, z) = (radius * th.sin(), -radius * th.cos());
        for j in 0..segs {
            let ph = std::f64::consts::TAU * j as f64 / segs as f64;
            v.push(Vector::new(r * ph.cos(), r * ph.sin(), z));
        }
    }
    let top = v.len() as u32;
    v.push(Vector::new(0.0, 0.0, radius));
    let ring = |i: usize, j: usize| (1 + (i - 1) * segs + j % segs) as u32;
    let mut t = Vec::new();
    for j in 0..segs {
        t.push([0, ring(1, j + 1), ring(1, j)]);
        t.push([top, ring(rings - 1, j), ring(rings - 1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segs {
            t.push([ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)]);
            t.push([ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)]);
        }
    }
    orient_outward(&v, &mut t);
    (v, t)
}
