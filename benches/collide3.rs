//! Benchmarks of the 3D collision queries (`cargo bench --bench collide3`).
//!
//! 1. Pair tests per second (one `overlap` and, when apart, one `distance`): mesh–mesh (a
//!    2,208-triangle tool sphere against a 9,800-triangle sphere) and mesh–primitive (the tool
//!    against a box and a cylinder), for near misses (2 mm apart) and crossings (2 mm deep).
//! 2. The cost of one pair test against the number of triangles of the other component: spheres of
//!    about 10k, 100k and 1M triangles against the tool, the same poses scaled; the ratios against
//!    10k show the growth (a bounding-volume hierarchy: sub-linear).
//! 3. The turn-mill machine (`machines/turn-mill.toml`) checking the examples of
//!    `programs/turn-mill/` in exact mode: pair tests per second of the whole check, and the cost
//!    per move with every STL part of the machine subdivided (each triangle into four, the surface
//!    unchanged) to about 10k, 50k and 200k triangles per part (the machine file's cap is 2M in all; alone:
//!    `-- turn-mill`).

use latheguard::collide3::{distance, overlap, uv_sphere, Shape3};
use latheguard::kin::stl::{read_stl, write_stl};
use latheguard::kin::{Geometry, Iso, Mesh};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Mode, Settings};
use nalgebra::{Point3, Translation3, UnitQuaternion};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

fn pose(x: f64, y: f64, z: f64, a: f64) -> Iso {
    Iso::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_euler_angles(a, 0.3 * a, 0.0),
    )
}

/// Poses of the tool (radius 5) around a body of radius about `r`, spread over its surface, with
/// the tool's centre at `r + off` (`off` > 5: apart, a near miss; < 5: crossing).
fn poses(r: f64, off: f64, n: usize) -> Vec<Iso> {
    (0..n)
        .map(|i| {
            let t = i as f64 * 2.399963; // golden angle
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let rr = r + off;
            pose(rr * s * t.cos(), rr * s * t.sin(), rr * z, t)
        })
        .collect()
}

fn sphere(r: f64, rings: usize) -> Shape3 {
    let (v, t) = uv_sphere(r, rings, 2 * rings);
    Shape3::mesh(v, t).expect("sphere mesh")
}

/// Median seconds per pair test over several rounds. Each round moves the poses by a
/// different nanometre, so that every question is a new one (the collision queries answer a
/// question asked again from the answers held, by the poses' bits).
fn per_test(a: &Shape3, b: &Shape3, ps: &[Iso], rounds: usize) -> (f64, usize) {
    let mut times = Vec::new();
    let mut hits = 0;
    for round in 0..rounds {
        hits = 0;
        let shift = Iso::translation(1e-6 * (round + 1) as f64, 0.0, 0.0);
        let ps: Vec<Iso> = ps.iter().map(|p| shift * p).collect();
        let t = Instant::now();
        for p in &ps {
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
    // `cargo bench --bench collide3 -- turn-mill` runs only the turn-mill machine's section.
    if std::env::args().any(|a| a == "turn-mill") {
        turn_mill_machine();
        return;
    }
    let tool = sphere(5.0, 24);
    let near = poses(50.0, 7.0, 400); // apart by about 2 mm: overlap, then distance
    let deep = poses(50.0, 3.0, 400); // crossing by about 2 mm: overlap with its depth
    println!("3D pair tests: the tool ({} triangles) 2 mm from (near miss) or 2 mm into (crossing) the other part, 400 poses", tool.triangles());
    let target = sphere(50.0, 50);
    let boxed = Shape3::from_geometry(
        &Geometry::Cuboid {
            min: Point3::new(-50.0, -50.0, -50.0),
            max: Point3::new(50.0, 50.0, 50.0),
        },
        0.01,
    )
    .unwrap();
    let cyl = Shape3::from_geometry(
        &Geometry::Cylinder {
            radius: 50.0,
            z0: -50.0,
            z1: 50.0,
        },
        0.01,
    )
    .unwrap();
    for (name, other) in [
        ("mesh–mesh (9,800 triangles)", &target),
        ("mesh–box", &boxed),
        ("mesh–cylinder", &cyl),
    ] {
        let (tn, hn) = per_test(&tool, other, &near, 5);
        let (td, hd) = per_test(&tool, other, &deep, 5);
        println!(
            "  {name}: near miss {:.0} pair tests/s ({hn} overlapping), crossing {:.0} pair tests/s ({hd} overlapping)",
            1.0 / tn,
            1.0 / td
        );
    }

    println!("cost of one pair test against the triangles of the other component (sphere, radius 50)");
    let mut base = None;
    for rings in [50usize, 158, 500] {
        let t0 = Instant::now();
        let s = sphere(50.0, rings);
        let build = t0.elapsed().as_secs_f64();
        let (tn, _) = per_test(&tool, &s, &near, 3);
        let (td, _) = per_test(&tool, &s, &deep, 3);
        let (bn, bd) = *base.get_or_insert((tn, td));
        println!(
            "  {:>8} triangles: near miss {:8.1} µs (ratio {:5.2}), crossing {:8.1} µs (ratio {:5.2}); build {:.2} s",
            s.triangles(),
            tn * 1e6,
            tn / bn,
            td * 1e6,
            td / bd,
            build
        );
    }

    turn_mill_machine();
}

/// Each triangle into four through its edges' midpoints (shared between neighbours, so the mesh
/// stays welded, closed and consistently wound).
fn subdivide(m: &Mesh) -> Mesh {
    let mut vertices = m.vertices.clone();
    let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
    let mut at = |a: u32, b: u32, v: &mut Vec<Point3<f64>>| -> u32 {
        let key = (a.min(b), a.max(b));
        *mid.entry(key).or_insert_with(|| {
            let p = v[a as usize] + (v[b as usize] - v[a as usize]) * 0.5;
            v.push(p);
            (v.len() - 1) as u32
        })
    };
    let mut triangles = Vec::with_capacity(m.triangles.len() * 4);
    for &[a, b, c] in &m.triangles {
        let ab = at(a, b, &mut vertices);
        let bc = at(b, c, &mut vertices);
        let ca = at(c, a, &mut vertices);
        triangles.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    Mesh { vertices, triangles }
}

/// The turn-mill machine with every STL part subdivided to about `target` triangles (none: as
/// shipped); also the largest part's triangle count.
fn turn_mill_with(target: Option<usize>) -> (Machine, usize) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = root.join("machines");
    let text = std::fs::read_to_string(dir.join("turn-mill.toml")).expect("machine file");
    let most = std::cell::Cell::new(0usize);
    let m = machine::from_toml_with(&text, "machines/turn-mill.toml", &|name: &str| {
        let bytes = std::fs::read(dir.join(name)).map_err(|e| e.to_string())?;
        let Some(target) = target else {
            return Ok(bytes);
        };
        let mut mesh = read_stl(&bytes, name).map_err(|e| e.message)?;
        while mesh.triangles.len() * 2 < target {
            mesh = subdivide(&mesh);
        }
        most.set(most.get().max(mesh.triangles.len()));
        Ok(write_stl(&mesh, name, false))
    })
    .expect("turn-mill machine");
    (m, most.get())
}

fn turn_mill_machine() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut programs: Vec<PathBuf> = std::fs::read_dir(root.join("programs/turn-mill"))
        .expect("programs/turn-mill")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "nc"))
        .collect();
    programs.sort();
    let settings = Settings {
        mode: Mode::Exact,
        ..Settings::default()
    };
    let run = |m: &Machine, rounds: usize| -> (f64, u64, u64) {
        let mut best = f64::INFINITY;
        let (mut tests, mut moves) = (0, 0);
        for _ in 0..rounds {
            let t = Instant::now();
            tests = 0;
            moves = 0;
            for p in &programs {
                let src = std::fs::read(p).expect("program");
                let out = pipeline::check(&src, m, &settings);
                tests += out.stats.pair_tests;
                moves += out.stats.moves;
            }
            best = best.min(t.elapsed().as_secs_f64());
        }
        (best, tests, moves)
    };
    println!(
        "the turn-mill machine, the {} programs of programs/turn-mill/ in exact mode",
        programs.len()
    );
    let (m, _) = turn_mill_with(None);
    let (secs, tests, moves) = run(&m, 5);
    println!(
        "  as shipped: {tests} pair tests, {moves} moves in {:.1} ms: {:.0} pair tests/s, {:.1} µs per move",
        secs * 1e3,
        tests as f64 / secs,
        secs * 1e6 / moves as f64
    );
    let mut base = None;
    // The machine file caps a machine at 2,000,000 STL triangles in all (four parts here), so
    // the largest level is about 200k per part.
    for target in [10_000usize, 50_000, 200_000] {
        let t0 = Instant::now();
        let (m, most) = turn_mill_with(Some(target));
        let load = t0.elapsed().as_secs_f64();
        let (secs, tests, moves) = run(&m, 3);
        let per_move = secs / moves as f64;
        let b = *base.get_or_insert(per_move);
        println!(
            "  STL parts of up to {most} triangles: {:.1} µs per move (ratio {:.2}), {:.0} pair tests/s; load {:.2} s",
            per_move * 1e6,
            per_move / b,
            tests as f64 / secs,
            load
        );
    }
}
