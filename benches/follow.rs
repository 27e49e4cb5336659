//! Benchmark of the online check (`cargo bench --bench follow`; docs/follow.md, "Latency").
//!
//! The shipped turn-mill machine (`machines/turn-mill.toml`) followed at 1 kHz: the samples
//! `moves --format samples --dt 1` makes of `programs/turn-mill/cross_drill.nc`, in two streams —
//! its facing (turning, the first 5,000 samples) and its radial live drilling (samples 10,000 to
//! 13,000) — each sample read from its JSON line and checked (`Follower::push`, then the findings
//! taken), timed one by one: median, 99th percentile and maximum per sample against the budget of
//! 1 ms. Baseline in the same run: `check` of the whole program, and the ratio of a stream's
//! total time per machine second to the check's (shared machines are noisy: compare within one
//! run). Then each two-path example of `programs/twin-turret/` and `programs/mill-turn-head/`
//! named below, sampled at 1 ms (`replay::samples_of_paths`) and followed whole: every carrier
//! and the carriers against each other. `-- --quick` follows the first 1,000 samples of each
//! stream.

use latheguard::follow::{replay, Follower, Format, Latency};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::{self, Settings};
use std::path::PathBuf;
use std::time::Instant;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn load(name: &str) -> Machine {
    let path = root().join(name);
    let dir = path.parent().unwrap().to_path_buf();
    let text = std::fs::read_to_string(&path).unwrap();
    machine::from_toml_with(&text, name, &move |name: &str| {
        std::fs::read(dir.join(name)).map_err(|e| e.to_string())
    })
    .unwrap()
}

fn turn_mill() -> Machine {
    load("machines/turn-mill.toml")
}

/// Follow `lines` on `m`, each sample timed: the latency summary and the total time, s.
fn follow(m: &Machine, settings: &Settings, lines: &[String]) -> (latheguard::follow::LatencySummary, f64) {
    let lathes = latheguard::follow::lathes(m);
    let mut f = Follower::new(m, &lathes, settings);
    let mut reader = f.reader(Format::Json);
    let mut lat = Latency::default();
    let t = Instant::now();
    for (k, line) in lines.iter().enumerate() {
        let t0 = Instant::now();
        if let Ok(Some(s)) = reader.read(k as u64 + 1, line) {
            let _ = f.push(k as u64 + 1, &s, None);
        }
        let _ = f.findings();
        lat.add(t0.elapsed().as_nanos() as u64);
    }
    (lat.summary(), t.elapsed().as_secs_f64())
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let m = turn_mill();
    let settings = Settings::default();
    let src = std::fs::read(root().join("programs/turn-mill/cross_drill.nc")).unwrap();

    let t = Instant::now();
    let out = pipeline::check(&src, &m, &settings);
    let check_s = t.elapsed().as_secs_f64();
    let machine_s = out.stats.machine_time_s;
    println!(
        "check of cross_drill.nc: {:.3} s for {machine_s:.3} s of machine time ({:.1} µs per machine ms)",
        check_s,
        check_s * 1e6 / (machine_s * 1000.0)
    );

    let (_, run) = pipeline::interpret(&src, &m);
    let mut lines = Vec::new();
    replay::samples(&run, &m, 0.001, |s| lines.push(replay::to_json(s)));
    let n = if quick { 1000 } else { usize::MAX };
    for (name, from, to) in [
        ("facing (turning)", 0usize, 5000usize),
        ("radial live drilling", 10_000, 13_000),
    ] {
        let to = to.min(lines.len()).min(from.saturating_add(n));
        let lathes = latheguard::follow::lathes(&m);
        let mut f = Follower::new(&m, &lathes, &settings);
        let mut reader = f.reader(Format::Json);
        // The stream starts where the machine stands at its first sample (no move to get there).
        let mut lat = Latency::default();
        let t = Instant::now();
        for (k, line) in lines[from..to].iter().enumerate() {
            let t0 = Instant::now();
            if let Ok(Some(s)) = reader.read(k as u64 + 1, line) {
                let _ = f.push(k as u64 + 1, &s, None);
            }
            let _ = f.findings();
            lat.add(t0.elapsed().as_nanos() as u64);
        }
        let total = t.elapsed().as_secs_f64();
        let s = lat.summary();
        let per_ms = total * 1e6 / s.samples.max(1) as f64;
        println!(
            "follow, {name}: {} samples at 1 kHz: median {:.1} µs, p99 {:.1} µs, max {:.1} µs per sample (budget 1000 µs); {:.1} µs per machine ms, {:.1}× check's",
            s.samples,
            s.median_us,
            s.p99_us,
            s.max_us,
            per_ms,
            per_ms / (check_s * 1e6 / (machine_s * 1000.0))
        );
    }

    // Two-path machines: every carrier, and the carriers against each other (in the working
    // plane on the twin-turret lathe, in 3D on the milling head with a lower turret), the whole
    // program at 1 kHz.
    for (machine, program) in [
        (
            "machines/twin-turret.toml",
            "programs/twin-turret/centre_drill_handover.nc",
        ),
        (
            "machines/mill-turn-head.toml",
            "programs/mill-turn-head/face_then_centre_drill.nc",
        ),
    ] {
        let m = load(machine);
        let src = std::fs::read(root().join(program)).unwrap();
        let t = Instant::now();
        let out = pipeline::check(&src, &m, &settings);
        let check_s = t.elapsed().as_secs_f64();
        let machine_s = out.stats.machine_time_s;
        let timed = latheguard::paths::timed(&src, &m, &settings);
        let mut lines = Vec::new();
        replay::samples_of_paths(&timed.paths, 0.001, timed.stop, |s| lines.push(replay::to_json(s)));
        lines.truncate(if quick { 1000 } else { usize::MAX });
        let (s, total) = follow(&m, &settings, &lines);
        let per_ms = total * 1e6 / s.samples.max(1) as f64;
        println!(
            "follow, {program} (two paths): {} samples at 1 kHz: median {:.1} µs, p99 {:.1} µs, max {:.1} µs per sample (budget 1000 µs); {:.1} µs per machine ms, {:.1}× check's ({:.3} s for {machine_s:.3} s)",
            s.samples,
            s.median_us,
            s.p99_us,
            s.max_us,
            per_ms,
            per_ms / (check_s * 1e6 / (machine_s * 1000.0)),
            check_s
        );
    }
}
