//! Benchmarks of the milled stock (`cargo bench --bench grid`; issue 16, seed 002).
//!
//! 1. The seed's example: a 300 × 300 × 200 mm block milled on its top and two side faces with a
//!    Ø14 and a Ø6 flat end mill (zig-zag passes, 1 mm steps), on 256 × 256 and 512 × 512 grids
//!    per face: time per move and the bytes of the grids.
//! 2. The cost of one move against the program's length: a zig-zag pocket program of 1M short
//!    moves (the Ø6 mill, 2 mm per move, stepping down 0.01 mm a layer so that every move cuts),
//!    timed over its first and its last 10k moves on one stock: the ratio must stay at or under
//!    1.5 (a move visits the nodes under its own sweep only).
//! 3. The cost of one move against the grid's density: the same Ø14 pass on 128² … 1024².
//!
//! 4. Polar interpolation through the spindle axis (issue 29): the G12.1 face pocket of
//!    `tests/fixtures/polar/face_pocket_through_axis.nc` (three passes across the face of the
//!    Ø50 bar, the middle one through the axis, a Ø10 flat end mill) checked on the turn-mill
//!    machine, the best of three runs, against the G12.1 hex of `tests/fixtures/polar/hex_g12_1.nc`
//!    (its cutter keeps off the axis) in the same run, with the rays each check's cuts cast
//!    (`stats.grid_rays`). Alone: `-- polar`.
//!
//! `-- quick` runs a tenth of every count (for a rough look; the README's figures are full runs).

use latheguard::grid::{Cutter, CutterKind, Stock, Sweep};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use nalgebra::Vector3;
use std::path::PathBuf;
use std::time::Instant;

fn flat(d: f64) -> Cutter {
    Cutter::new(CutterKind::Flat, d, 40.0).unwrap()
}

fn block(n: usize) -> Stock {
    Stock::block(Vector3::zeros(), Vector3::new(300.0, 300.0, 200.0), n, 0.5).unwrap()
}

/// Zig-zag passes on a face: the mill's axis `axis`, passes along `run` stepped along `step`,
/// `moves` moves of `len` mm at the depth `depth` below the face point `at`.
#[allow(clippy::too_many_arguments)]
fn passes(
    c: &Cutter,
    axis: Vector3<f64>,
    at: Vector3<f64>,
    run: Vector3<f64>,
    step: Vector3<f64>,
    len: f64,
    moves: usize,
    depth_per_layer: f64,
) -> Vec<Sweep> {
    let mut out = Vec::with_capacity(moves);
    let per_row = (200.0 / len).floor().max(1.0) as usize;
    let rows = 200;
    let mut p = at - axis * 1.0;
    for k in 0..moves {
        let row = (k / per_row) % rows;
        let layer = k / (per_row * rows);
        let i = k % per_row;
        let dir = if row % 2 == 0 { 1.0 } else { -1.0 };
        let base = at - axis * (1.0 + depth_per_layer * layer as f64) + step * row as f64;
        let x0 = if dir > 0.0 {
            i as f64 * len
        } else {
            200.0 - i as f64 * len
        };
        let a = base + run * x0;
        let b = a + run * (dir * len);
        p = b;
        out.push(Sweep::new(c, axis, a, b, 0.5).unwrap());
    }
    let _ = p;
    out
}

/// The Ø14 mill's passes on the top face, 10 mm moves.
fn top_passes(moves: usize) -> Vec<Sweep> {
    passes(
        &flat(14.0),
        Vector3::z(),
        Vector3::new(50.0, 50.0, 200.0),
        Vector3::x(),
        Vector3::y(),
        10.0,
        moves,
        1.0,
    )
}

fn time_moves(stock: &mut Stock, sweeps: &[Sweep]) -> f64 {
    let t = Instant::now();
    let mut removed = 0.0;
    for sw in sweeps {
        removed += stock.cut(sw);
    }
    std::hint::black_box(removed);
    t.elapsed().as_secs_f64() / sweeps.len().max(1) as f64
}

/// The shipped turn-mill machine, its STL parts read from `machines/`.
fn turn_mill() -> Machine {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("machines");
    let text = std::fs::read_to_string(dir.join("turn-mill.toml")).expect("machine file");
    machine::from_toml_with(&text, "machines/turn-mill.toml", &|name: &str| {
        std::fs::read(dir.join(name)).map_err(|e| e.to_string())
    })
    .expect("turn-mill machine")
}

/// 4: the pocket through the axis against the hex beside it, each the best of `rounds` checks.
fn polar(rounds: usize) {
    println!("4. G12.1 on the turn-mill machine: a face pocket through the spindle axis, a hex beside it");
    let m = turn_mill();
    let settings = Settings::default();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let check = |name: &str| {
        let src = std::fs::read(root.join("tests/fixtures/polar").join(name)).expect("program");
        let mut best = f64::INFINITY;
        let mut rays = 0;
        for _ in 0..rounds {
            let t = Instant::now();
            let out = pipeline::check(&src, &m, &settings);
            best = best.min(t.elapsed().as_secs_f64());
            rays = out.stats.grid_rays;
        }
        (best, rays)
    };
    let (hex, hex_rays) = check("hex_g12_1.nc");
    let (pocket, pocket_rays) = check("face_pocket_through_axis.nc");
    println!("   hex_g12_1.nc: {hex:.3} s, {hex_rays} rays cast");
    println!(
        "   face_pocket_through_axis.nc: {pocket:.3} s, {pocket_rays} rays cast: {:.2}× the hex",
        pocket / hex
    );
}

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let scale = if quick { 10 } else { 1 };
    if std::env::args().any(|a| a == "polar") {
        polar(if quick { 1 } else { 3 });
        return;
    }
    let top = Vector3::new(50.0, 50.0, 200.0);
    println!("1. The seed's block, 300 × 300 × 200, three faces milled");
    for n in [256usize, 512] {
        let mut s = block(n);
        let mut all = Vec::new();
        all.extend(top_passes(4000 / scale));
        all.extend(passes(
            &flat(6.0),
            Vector3::x(),
            Vector3::new(300.0, 50.0, 50.0),
            Vector3::y(),
            Vector3::z(),
            10.0,
            4000 / scale,
            1.0,
        ));
        all.extend(passes(
            &flat(6.0),
            -Vector3::y(),
            Vector3::new(50.0, 0.0, 50.0),
            Vector3::x(),
            Vector3::z(),
            10.0,
            4000 / scale,
            1.0,
        ));
        let per = time_moves(&mut s, &all);
        println!(
            "   {n}×{n} per face: {:.1} µs per move ({} moves), grids {:.1} MB, volume left {:.0} mm³",
            per * 1e6,
            all.len(),
            s.bytes() as f64 / 1e6,
            s.volume()
        );
    }
    println!("2. Cost per move against program length (Ø6, 2 mm moves, 256² grids)");
    let total = 1_000_000 / scale;
    let window = 10_000 / scale;
    let mut s = block(256);
    let sweeps = passes(
        &flat(6.0),
        Vector3::z(),
        top,
        Vector3::x(),
        Vector3::y(),
        2.0,
        total,
        0.01,
    );
    let first = time_moves(&mut s, &sweeps[..window]);
    let _ = time_moves(&mut s, &sweeps[window..total - window]);
    let last = time_moves(&mut s, &sweeps[total - window..]);
    println!(
        "   first {window}: {:.2} µs per move; last {window} of {total}: {:.2} µs per move; ratio {:.2}",
        first * 1e6,
        last * 1e6,
        last / first
    );
    println!("3. Cost per move against grid density (Ø14, 10 mm moves)");
    let mut base = None;
    for n in [128usize, 256, 512, 1024] {
        let mut s = block(n);
        let sw = top_passes(2000 / scale);
        let per = time_moves(&mut s, &sw);
        let b = *base.get_or_insert(per);
        println!("   {n}²: {:.1} µs per move ({:.2}× the 128² cost)", per * 1e6, per / b);
    }
    polar(if quick { 1 } else { 3 });
}
