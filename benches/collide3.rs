//! Benchmarks of the 3D collision queries (`cargo bench --bench collide3`).
//!
//! 1. Pair tests per second (one `overlap` and, when apart, one `distance`): mesh–mesh (a
//!    1,152-triangle tool sphere against a 10k-triangle sphere) and mesh–primitive (the tool
//!    against a box and a cylinder), at poses spread across contact.
//! 2. The cost of one pair test against the number of triangles of the other component: spheres of
//!    about 10k, 100k and 1M triangles against the tool, the same poses scaled; the ratios against
//!    10k show the growth (a bounding-volume hierarchy: sub-linear).

use latheguard::collide3::{distance, overlap, uv_sphere, Shape3};
use latheguard::kin::{Geometry, Iso};
use nalgebra::{Point3, Translation3, UnitQuaternion};
use std::time::Instant;

fn pose(x: f64, y: f64, z: f64, a: f64) -> Iso {
    Iso::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(a, 0.3 * a, 0.0),
    )
}

/// Poses of the tool around a sphere of radius `r`: across its surface, in and out.
fn poses(r: f64, n: usize) -> Vec<Iso> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 2.399963; // golden angle
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let rr = r * (0.97 + 0.08 * ((i % 7) as f64 / 6.0));
            pose(rr * s * t.cos(), rr * s * t.sin(), rr * z, t)
        })
        .collect()
}

fn sphere(r: f64, rings: usize) -> Shape3 {
    let (v, t) = uv_sphere(r, rings, 2 * rings);
    Shape3::mesh(v, t).expect("sphere mesh")
}

/// Median seconds per pair test over several rounds.
fn per_test(a: &Shape3, b: &Shape3, ps: &[Iso], rounds: usize) -> (f64, usize) {
    let mut times = Vec::new();
    let mut hits = 0;
    for _ in 0..rounds {
        hits = 0;
        let t = Instant::now();
        for p in ps {
            match overlap(b, &Iso::identity(), a, p, 1e-6) {
                Some(_) => hits += 1,
                None => {
                    std::hint::black_box(distance(b, &Iso::identity(), a, p));
                }
            }
        }
        times.push(t.elapsed().as_secs_f64() / ps.len() as f64);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], hits)
}

fn main() {
    let tool = sphere(5.0, 24); // 1,104 triangles
    let ps = poses(50.0, 400);
    println!(
        "3D pair tests (overlap, then distance when apart), {} poses across contact",
        ps.len()
    );
    let target = sphere(50.0, 50);
    let (t, h) = per_test(&tool, &target, &ps, 5);
    println!(
        "  mesh–mesh ({} vs {} triangles): {:.0} pair tests/s ({} overlapping)",
        tool.triangles(),
        target.triangles(),
        1.0 / t,
        h
    );
    let boxed = Shape3::from_geometry(
        &Geometry::Cuboid {
            min: Point3::new(-40.0, -40.0, -40.0),
            max: Point3::new(40.0, 40.0, 40.0),
        },
        0.01,
    )
    .unwrap();
    let (t, h) = per_test(&tool, &boxed, &poses(45.0, 400), 5);
    println!("  mesh–box: {:.0} pair tests/s ({} overlapping)", 1.0 / t, h);
    let cyl = Shape3::from_geometry(
        &Geometry::Cylinder {
            radius: 45.0,
            z0: -45.0,
            z1: 45.0,
        },
        0.01,
    )
    .unwrap();
    let (t, h) = per_test(&tool, &cyl, &ps, 5);
    println!("  mesh–cylinder: {:.0} pair tests/s ({} overlapping)", 1.0 / t, h);

    println!("cost of one pair test against the triangles of the other component");
    let mut base = None;
    for rings in [50usize, 158, 500] {
        let t0 = Instant::now();
        let s = sphere(50.0, rings);
        let build = t0.elapsed().as_secs_f64();
        let (t, h) = per_test(&tool, &s, &ps, 3);
        let b = *base.get_or_insert(t);
        println!(
            "  {:>8} triangles: {:8.1} µs per pair test, ratio {:5.2} (build {:.2} s, {} overlapping)",
            s.triangles(),
            t * 1e6,
            t / b,
            build,
            h
        );
    }
}
