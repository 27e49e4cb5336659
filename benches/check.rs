//! Benchmarks of the checker (`cargo bench --bench check`; `-- --quick` for smaller sizes).
//!
//! 1. Step mode at dt = 1 ms on a long generated program (the built-in machine): scene samples
//!    per second and pair tests per second; exact mode on the same program and the ratio.
//! 2. A program of 1e8 samples at dt = 1 ms far from any obstacle, in both modes (what the
//!    motion envelopes skip).
//! 3. Per-block cost with stock removal for generated programs of 10k, 100k and 1M blocks of
//!    repeated passes, and the ratio of the largest to the smallest; the peak memory of the
//!    binary's `check` of the largest (GNU time).
//!
//! 4. Long contacts: a generated 10k-line program whose T01 holder stays buried in the bar for
//!    every move (one crash that goes on), and one whose holder enters the bar on every pass and
//!    leaves it on every return (a crash every two moves), step mode against exact mode: step mode
//!    measures a contact it finds as exact mode does, so the ratio should stay near 1 (issue 10:
//!    at most 2); and for each the same moves turning clear of everything, for the cost of a
//!    block in contact against a clean one.
//!
//! 5. Turn-mill programs on their machines, each the binary's `check` as the README's speed table
//!    gives it (wall time, median of 3): the NX Mori Seiki NL1500Y listing of the corpus (when
//!    `../shared/corpus-extra` is there: the corpus is kept out of the repository), the G12.1
//!    face pocket through the spindle axis and `programs/turn-mill/crash_live_drill_into_jaws.nc`.
//!
//! `-- --stock-only` runs section 3 alone; `-- --contact-only` section 4 alone; `-- --turn-mill-only`
//! section 5 alone. Figures are medians of several runs; compare ratios within one run (shared,
//! noisy machines).

#[allow(dead_code)]
#[path = "../examples/gen_program.rs"]
mod gen;

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use std::time::Instant;

fn median_run(runs: usize, src: &[u8], m: &Machine, s: &Settings) -> (f64, pipeline::Outcome) {
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..runs {
        let t = Instant::now();
        let out = pipeline::check(src, m, s);
        times.push(t.elapsed().as_secs_f64());
        last = Some(out);
    }
    times.sort_by(f64::total_cmp);
    (times[times.len() / 2], last.unwrap())
}

fn far_program(samples: f64) -> Vec<u8> {
    // T01 far above the part at 10 mm/min: each 100 mm move takes 600 s = 600,000 samples.
    let moves = (samples / 600_000.0).ceil() as usize;
    let mut s = String::from("%\nG21 G18 G98 G97 S500 M3\nG0 X500. Z300.\n");
    for k in 0..moves {
        let z = if k % 2 == 0 { 400.0 } else { 300.0 };
        s += &format!("G1 Z{z:.1} F10.\n");
    }
    s += "M30\n%\n";
    s.into_bytes()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let m = Machine::builtin();
    let step = Settings::default();
    let exact = Settings {
        mode: Mode::Exact,
        ..step
    };

    let stock_only = std::env::args().any(|a| a == "--stock-only");
    let contact_only = std::env::args().any(|a| a == "--contact-only");
    let turn_mill_only = std::env::args().any(|a| a == "--turn-mill-only");
    let all = !stock_only && !contact_only && !turn_mill_only;
    if all {
        sections_1_and_2(quick, &m, &step, &exact);
    }
    if all || stock_only {
        section_3(quick, &m, &step);
    }
    if all || contact_only {
        section_4(quick, &m, &step, &exact);
    }
    if all || turn_mill_only {
        section_5();
    }
}

/// The README's turn-mill rows: each program checked by the binary on its machine.
fn section_5() {
    println!("5. turn-mill programs on their machines (the binary's check, wall time, median of 3)");
    let root = env!("CARGO_MANIFEST_DIR");
    let nx = format!("{root}/../shared/corpus-extra/unigraphics-nx-postprocessor/MoriSeiki_NL1500Y_output.txt");
    let rows: [(&str, Vec<String>); 3] = [
        (
            "the NX Mori Seiki NL1500Y listing (396 lines)",
            vec![
                "-m".into(),
                format!("{root}/tests/corpus-jobs/machines/mori-seiki-nl1500y.toml"),
                nx.clone(),
            ],
        ),
        (
            "a G12.1 face pocket through the spindle axis",
            vec![
                "-m".into(),
                format!("{root}/machines/turn-mill.toml"),
                format!("{root}/tests/fixtures/polar/face_pocket_through_axis.nc"),
            ],
        ),
        (
            "programs/turn-mill/crash_live_drill_into_jaws.nc",
            vec![format!("{root}/programs/turn-mill/crash_live_drill_into_jaws.nc")],
        ),
    ];
    let exe = env!("CARGO_BIN_EXE_latheguard");
    for (what, args) in rows {
        if args.last().is_some_and(|p| !std::path::Path::new(p).exists()) {
            println!("   {what}: skipped (no {})", args.last().map_or("", String::as_str));
            continue;
        }
        let mut times = Vec::new();
        for _ in 0..3 {
            let t = Instant::now();
            let status = std::process::Command::new(exe)
                .arg("check")
                .arg("-q")
                .args(&args)
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .status();
            // A program with findings exits 1; anything else is no measurement.
            if !status.as_ref().is_ok_and(|s| matches!(s.code(), Some(0 | 1))) {
                println!("   {what}: the check failed ({status:?})");
                break;
            }
            times.push(t.elapsed().as_secs_f64());
        }
        if times.len() == 3 {
            times.sort_by(f64::total_cmp);
            println!("   {what}: {:.3} s", times[1]);
        }
    }
}

/// `lines` feeds along Z at diameter `x`, one after another, between Z-30 and `z_back`:
/// `X20.` puts the T01 holder 5 mm into the 50 mm bar above the insert's cut; `X46.` has the
/// insert turning the bar clear of everything. On the built-in machine the bar's face is at Z2
/// and the holder sits 7.8 mm behind the tip: returning to Z-10 it stays in the bar (one contact
/// over every block); returning to Z-5 it leaves the bar on every return and enters it again on
/// every pass (a contact of its own every two blocks).
fn moves_at(lines: usize, x: &str, z_back: &str) -> Vec<u8> {
    let mut s = format!("%\nG21 G18 G40 G97 G99\nT0101\nG97 S1000 M3\nG0 X60. Z5.\nG1 {x} F0.2\n");
    for k in 0..lines {
        let z = if k % 2 == 0 { "-30.0" } else { z_back };
        s += &format!("G1 Z{z}\n");
    }
    s += "G0 X120.\nM30\n%\n";
    s.into_bytes()
}

fn section_4(quick: bool, m: &Machine, step: &Settings, exact: &Settings) {
    let lines = if quick { 2_000 } else { 10_000 };
    for (back, what) in [
        (
            "-10.0",
            "the T01 holder buried in the bar for every block (one contact)",
        ),
        (
            "-5.0",
            "the T01 holder entering the bar on every pass and leaving it on every return",
        ),
    ] {
        let src = moves_at(lines, "X20.", back);
        println!("4. long contact: {lines} moves with {what}");
        let (ts, out) = median_run(3, &src, m, step);
        let (te, oute) = median_run(3, &src, m, exact);
        println!(
            "   step dt=1ms: {:.3} s ({} findings, {:.0} s machine time); exact: {:.3} s ({} findings); step / exact = {:.2}x",
            ts,
            out.findings.len(),
            out.stats.machine_time_s,
            te,
            oute.findings.len(),
            ts / te
        );
        // The same moves turning the bar with nothing in contact: what a block costs when no
        // part is inside another (issue 29's measure of a contact's cost per block). Past the
        // first fifth of the blocks: what each block after them adds (the first pass cuts the
        // bar and the holder enters it, a cost every length of the program pays once).
        let clean = moves_at(lines, "X46.", back);
        let (tc, outc) = median_run(3, &clean, m, step);
        assert!(outc.findings.is_empty(), "{:?}", outc.findings);
        let first = lines / 5;
        let (ts1, _) = median_run(3, &moves_at(first, "X20.", back), m, step);
        let (tc1, _) = median_run(3, &moves_at(first, "X46.", back), m, step);
        println!(
            "   the same moves turning clear of everything, step dt=1ms: {:.4} s; a block in contact costs {:.1}x a clean block; \
             past the first {first}: {:.1}x",
            tc,
            ts / tc,
            (ts - ts1) / (tc - tc1)
        );
    }
}

fn sections_1_and_2(quick: bool, m: &Machine, step: &Settings, exact: &Settings) {
    let (m, step, exact) = (m, *step, *exact);
    let lines = if quick { 20_000 } else { 100_000 };
    let src = gen::generate(lines, true, 1);
    println!("1. generated program, {lines} lines, built-in machine, one core");
    let (ts, out) = median_run(3, &src, m, &step);
    let st = &out.stats;
    println!(
        "   step dt=1ms: {:.2} s for {:.0} s of machine time: {:.2} M samples/s, {:.2} M pair tests/s, {} findings",
        ts,
        st.machine_time_s,
        st.steps as f64 / ts / 1e6,
        st.pair_tests as f64 / ts / 1e6,
        out.findings.len()
    );
    println!(
        "   pair tests done {} / skipped by envelopes {} ({:.2}% done)",
        st.pair_tests,
        st.pair_tests_skipped,
        100.0 * st.pair_tests as f64 / (st.pair_tests + st.pair_tests_skipped).max(1) as f64
    );
    let (te, oute) = median_run(3, &src, m, &exact);
    println!(
        "   exact: {:.2} s, {} findings; exact / step = {:.2}x",
        te,
        oute.findings.len(),
        te / ts
    );

    println!("2. 1e8 samples at dt = 1 ms far from any obstacle");
    let far = far_program(1e8);
    for (name, s) in [("step", &step), ("exact", &exact)] {
        let (t, out) = median_run(3, &far, m, s);
        println!(
            "   {name:<5}: {:.4} s for {:.0} s of machine time ({} samples, {} pair tests, {} skipped)",
            t, out.stats.machine_time_s, out.stats.steps, out.stats.pair_tests, out.stats.pair_tests_skipped
        );
    }
}

fn section_3(quick: bool, m: &Machine, step: &Settings) {
    let step = *step;
    println!("3. per-block cost with stock removal (step mode, dt = 1 ms)");
    let sizes: &[usize] = if quick {
        &[10_000, 100_000]
    } else {
        &[10_000, 100_000, 1_000_000]
    };
    let mut first = None;
    for &n in sizes {
        let src = gen::generate(n, true, 7);
        let (t, out) = median_run(if n >= 1_000_000 { 1 } else { 3 }, &src, m, &step);
        let per = t / out.stats.blocks as f64 * 1e6;
        let base = *first.get_or_insert(per);
        println!(
            "   {:>8} blocks: {:.2} s, {:.2} us/block ({:.2}x the 10k cost), effects {:?}",
            out.stats.blocks,
            t,
            per,
            per / base,
            out.stats.effects
        );
    }
    // Peak memory of the binary's check of the largest program (the moves stream to the checker:
    // what is left is the source and the read program, ARCHITECTURE.md "Memory for long programs").
    let n = *sizes.last().unwrap();
    let src = gen::generate(n, true, 7);
    let path = std::env::temp_dir().join(format!("latheguard-bench-check-{}.nc", std::process::id()));
    std::fs::write(&path, &src).unwrap();
    let exe = env!("CARGO_BIN_EXE_latheguard");
    let p = path.to_str().unwrap();
    let check = peak_kib(exe, &["check", "--no-assume", "--format", "json", p]);
    // The default check of a program with no job reads its setup from the program first.
    let assumed = peak_kib(exe, &["check", "--format", "json", p]);
    let read = peak_kib(exe, &["moves", "--format", "canon", p]);
    let _ = std::fs::remove_file(&path);
    let mib = |k: u64| k as f64 / 1024.0;
    let file = src.len() as f64 / (1 << 20) as f64;
    match (check, read) {
        (Some(c), Some(r)) => println!(
            "   peak memory (max RSS), {n} lines ({file:.1} MiB): check {:.1} MiB ({:.1}x the file); \
             moves --format canon (reading alone) {:.1} MiB",
            mib(c),
            mib(c) / file,
            mib(r)
        ),
        _ => println!("   peak memory: not measured (needs GNU time at /usr/bin/time)"),
    }
    if let Some(a) = assumed {
        println!(
            "   the default check, its setup read from the program first: {:.1} MiB ({:.1}x the file)",
            mib(a),
            mib(a) / file
        );
    }
}

/// Peak resident memory of one run of a command, KiB, as GNU time measures it (`None` without
/// `/usr/bin/time`).
fn peak_kib(cmd: &str, args: &[&str]) -> Option<u64> {
    let out = std::process::Command::new("/usr/bin/time")
        .arg("-f")
        .arg("%M")
        .arg(cmd)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .output()
        .ok()?;
    let err = String::from_utf8_lossy(&out.stderr);
    err.lines().rev().find_map(|l| l.trim().parse().ok())
}
