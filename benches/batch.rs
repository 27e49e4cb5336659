//! Benchmark: `latheguard check` over a folder of generated programs, as files per second, with
//! 1 and 2 jobs.
//!
//! `cargo bench --bench batch` (defaults: 10,000 programs of about 200 lines, jobs 1 and 2, one
//! timed run each). Options after `--`: `--files N`, `--lines L`, `--jobs 1,2,4`, `--runs R`
//! (median of R runs). The programs are Fanuc programs for the built-in machine from
//! `examples/gen_program.rs` (seeds 1..=N, so the folder is the same on every machine), written
//! once to `target/tmp/batch-bench-N-L/`. Each run is the release binary, as a user runs it:
//! `latheguard check DIR --jobs J --no-timing --quiet -o FILE` (walk, read, check, report).
//! Compare ratios, not absolute times: machines, and their neighbours, differ.

#[allow(dead_code)]
#[path = "../examples/gen_program.rs"]
mod gen;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> T {
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn corpus(files: usize, lines: usize) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("batch-bench-{files}-{lines}"));
    let done = dir.join(".complete");
    if done.exists() {
        return dir;
    }
    std::fs::create_dir_all(&dir).expect("create the corpus folder");
    for seed in 1..=files {
        let src = gen::generate(lines, true, seed as u64);
        std::fs::write(dir.join(format!("p{seed:05}.nc")), src).expect("write a program");
    }
    std::fs::write(&done, "").expect("mark the corpus complete");
    dir
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let files: usize = arg(&args, "--files", 10_000);
    let lines: usize = arg(&args, "--lines", 200);
    let runs: usize = arg(&args, "--runs", 1).max(1);
    let jobs: Vec<usize> = arg(&args, "--jobs", "1,2".to_string())
        .split(',')
        .filter_map(|j| j.trim().parse().ok())
        .collect();
    let dir = corpus(files, lines);
    let bin = env!("CARGO_BIN_EXE_latheguard");
    let total_lines: usize = std::fs::read_dir(&dir)
        .expect("list the corpus")
        .filter_map(|e| std::fs::read(e.ok()?.path()).ok())
        .map(|b| b.iter().filter(|&&c| c == b'\n').count())
        .sum();
    println!(
        "latheguard check: {files} generated programs, {:.0} lines each on average, in {}",
        total_lines as f64 / files as f64,
        dir.display()
    );
    println!("{:>5}  {:>10}  {:>10}  {:>8}", "jobs", "seconds", "files/s", "speed-up");
    let report = Path::new(env!("CARGO_TARGET_TMPDIR")).join("batch-bench-report.txt");
    let mut base = None;
    let mut summary = String::new();
    for &j in &jobs {
        let mut times: Vec<f64> = (0..runs)
            .map(|_| {
                let t = Instant::now();
                let status = Command::new(bin)
                    .args(["check", "--no-timing", "--quiet", "-o"])
                    .arg(&report)
                    .arg("--jobs")
                    .arg(j.to_string())
                    .arg(&dir)
                    .stdout(Stdio::null())
                    .stderr(Stdio::null())
                    .status()
                    .expect("run latheguard");
                assert!(status.code().is_some_and(|c| c <= 1), "latheguard failed: {status}");
                t.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let text = std::fs::read_to_string(&report).unwrap_or_default();
        summary = text.lines().last().unwrap_or("").to_string();
        let t = times[times.len() / 2];
        let base_t = *base.get_or_insert(t);
        println!("{j:>5}  {t:>10.2}  {:>10.1}  {:>7.2}x", files as f64 / t, base_t / t);
    }
    // What the programs give (so that a speed-up is not a change of findings).
    println!("  {summary}");
}
