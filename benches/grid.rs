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
//! `-- quick` runs a tenth of every count (for a rough look; the README's figures are full runs).

use latheguard::grid::{Cutter, CutterKind, Stock, Sweep};
use nalgebra::Vector3;
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

fn main() {
    let quick = std::env::args().any(|a| a == "quick");
    let scale = if quick { 10 } else { 1 };
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
}
