//! Benchmark: reading and interpreting a generated 100k-line lathe program, as lines per second,
//! against `wc -l` on the same file, and `latheguard moves --format canon` against LinuxCNC's
//! `rs274 -g` (when `scripts/rs274-ref.sh` can provide it) on the same program in the same run and
//! on a LinuxCNC G71/G70 program,
//! and `latheguard check --mode exact` of the program's Fanuc twin (stock removal on the built-in
//! machine) against the same rs274 figure.
//!
//! `cargo bench --bench read` (add `-- --lines N` for another size, `-- --cycles` for the
//! cycles row alone). Figures are medians of
//! several runs; compare ratios, not absolute times (shared, noisy machines).

#[allow(dead_code)]
#[path = "../examples/gen_program.rs"]
mod gen;

use latheguard::machine::{self, Machine};
use latheguard::{interp, pipeline};
use std::process::{Command, Stdio};
use std::time::Instant;

/// Median and best of several runs, seconds.
#[derive(Clone, Copy)]
struct Times {
    median: f64,
    best: f64,
}

fn times<F: FnMut()>(runs: usize, mut f: F) -> Times {
    let mut v: Vec<f64> = (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64()
        })
        .collect();
    v.sort_by(f64::total_cmp);
    Times {
        median: v[v.len() / 2],
        best: v[0],
    }
}

fn time<F: FnMut()>(runs: usize, f: F) -> f64 {
    times(runs, f).median
}

fn time_cmd(runs: usize, cmd: &str, args: &[&str]) -> Option<f64> {
    times_cmd(runs, cmd, args).map(|t| t.median)
}

/// [`time_cmd`] with the best run too: on a shared machine the best of several runs is the
/// figure least disturbed by the other load.
fn times_cmd(runs: usize, cmd: &str, args: &[&str]) -> Option<Times> {
    let ok = Command::new(cmd)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .ok()?
        .success();
    if !ok {
        return None;
    }
    Some(times(runs, || {
        let _ = Command::new(cmd)
            .args(args)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
    }))
}

/// Peak resident memory of one run of a command, KiB, as GNU time measures it (`None` without
/// `/usr/bin/time`). `rs274-ref.sh` runs rs274 as a child of bash; the figure is the largest
/// process of the tree (Linux's `ru_maxrss` of a waited child), which is rs274.
fn peak_kib(cmd: &str, args: &[&str]) -> Option<u64> {
    let out = Command::new("/usr/bin/time")
        .arg("-f")
        .arg("%M")
        .arg(cmd)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .ok()?;
    let err = String::from_utf8_lossy(&out.stderr);
    err.lines().rev().find_map(|l| l.trim().parse().ok())
}

fn main() {
    let mut lines = 100_000usize;
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--lines") {
        lines = args.get(i + 1).and_then(|v| v.parse().ok()).unwrap_or(lines);
    }
    if args.iter().any(|a| a == "--cycles") {
        // The cycles row alone (profiling the cycles without the other rows and rs274).
        cycles(lines, &Machine::builtin());
        return;
    }
    let root = env!("CARGO_MANIFEST_DIR");
    let lcnc_text = std::fs::read_to_string(format!("{root}/machines/linuxcnc-small-lathe.toml")).unwrap();
    let lcnc = machine::from_toml(&lcnc_text, "linuxcnc-small-lathe.toml").unwrap();
    let fanuc = Machine::builtin();
    let dir = std::env::temp_dir().join(format!("latheguard-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    println!("reading + interpreting a generated program, one core, 15 runs: median (best)");
    println!(
        "{:<10} {:>9} {:>16} {:>22} {:>8}",
        "dialect", "lines", "ms", "lines/s", "moves"
    );
    for (name, fan, m) in [("linuxcnc", false, &lcnc), ("fanuc", true, &fanuc)] {
        let src = gen::generate(lines, fan, 1);
        let n = src.iter().filter(|&&b| b == b'\n').count();
        let mut moves = 0;
        let all = times(15, || {
            let p = pipeline::read(&src, m);
            let r = interp::interpret(&p, &src, m);
            moves = r.moves.len();
        });
        let t = all.median;
        let tp = time(15, || {
            std::hint::black_box(pipeline::read(&src, m));
        });
        println!(
            "{name:<10} {n:>9} {:>7.2} ({:>6.2}) {:>11.0} ({:>8.0}) {moves:>8}   (reading alone: {:.0} lines/s)",
            t * 1e3,
            all.best * 1e3,
            n as f64 / t,
            n as f64 / all.best,
            n as f64 / tp
        );
        let path = dir.join(format!("p-{name}.ngc"));
        std::fs::write(&path, &src).unwrap();
        if let Some(wc) = time_cmd(7, "wc", &["-l", path.to_str().unwrap()]) {
            println!(
                "{:<10} wc -l: {:.2} ms; latheguard read+interpret / wc -l = {:.1}x",
                "",
                wc * 1e3,
                t / wc
            );
        }
    }
    cycles(lines, &fanuc);
    // moves --format canon against rs274 on the LinuxCNC program.
    let path = dir.join("p-linuxcnc.ngc");
    let p = path.to_str().unwrap();
    let exe = env!("CARGO_BIN_EXE_latheguard");
    let machine_file = format!("{root}/machines/linuxcnc-small-lathe.toml");
    let rs274 = canon_row("", root, &machine_file, p);
    // The same on LinuxCNC G71/G70: roughing and finishing cycles over one o-word profile.
    let g7x_path = dir.join("p-lcnc-g7x.ngc");
    std::fs::write(&g7x_path, lcnc_g7x_program(G7X_UNITS)).unwrap();
    let label = format!(", LinuxCNC G71/G70 ({G7X_UNITS} of each)");
    canon_row(&label, root, &machine_file, g7x_path.to_str().unwrap());
    // The exact check with stock removal of the Fanuc program on the built-in machine, against
    // rs274 merely interpreting its LinuxCNC twin (issue 29's first figure).
    let fanuc_path = dir.join("p-fanuc.ngc");
    let check_args = [
        "check",
        "-q",
        "--no-assume",
        "--mode",
        "exact",
        fanuc_path.to_str().unwrap(),
    ];
    match (time_cmd(5, exe, &check_args), rs274) {
        (Some(c), Some(r)) => println!(
            "check --mode exact (Fanuc twin, stock removal): {:.1} ms; rs274 -g: {:.1} ms; rs274 / latheguard = {:.2}x",
            c * 1e3,
            r * 1e3,
            r / c
        ),
        (Some(c), None) => println!("check --mode exact (Fanuc twin, stock removal): {:.1} ms", c * 1e3),
        _ => println!("latheguard check failed or found a crash in the generated program"),
    }
    let ours = peak_kib(exe, &["moves", "--format", "canon", "-m", &machine_file, p]);
    let rs274 = peak_kib(&format!("{root}/scripts/rs274-ref.sh"), &["-g", p]);
    match (ours, rs274) {
        (Some(o), Some(r)) => println!(
            "peak memory (max RSS): moves --format canon {:.1} MiB; rs274 -g {:.1} MiB",
            o as f64 / 1024.0,
            r as f64 / 1024.0
        ),
        (Some(o), None) => println!(
            "peak memory (max RSS): moves --format canon {:.1} MiB",
            o as f64 / 1024.0
        ),
        _ => println!("peak memory: not measured (needs GNU time at /usr/bin/time)"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// One row: `moves --format canon` of `program` on `machine_file` against `rs274 -g` through
/// `scripts/rs274-ref.sh`, whole processes; `label` follows the row's name. Returns rs274's time
/// (seconds), when it ran.
fn canon_row(label: &str, root: &str, machine_file: &str, program: &str) -> Option<f64> {
    let exe = env!("CARGO_BIN_EXE_latheguard");
    let ours = times_cmd(9, exe, &["moves", "--format", "canon", "-m", machine_file, program]);
    let rs274 = times_cmd(5, &format!("{root}/scripts/rs274-ref.sh"), &["-g", program]);
    match (ours, rs274) {
        (Some(o), Some(r)) => println!(
            "moves --format canon{label}: {:.1} ms; rs274 -g: {:.1} ms; rs274 / latheguard = {:.1}x \
             (best runs: {:.1} ms, {:.1} ms, {:.1}x)",
            o.median * 1e3,
            r.median * 1e3,
            r.median / o.median,
            o.best * 1e3,
            r.best * 1e3,
            r.best / o.best
        ),
        (Some(o), None) => println!(
            "moves --format canon{label}: {:.1} ms; rs274 not available (scripts/rs274-ref.sh failed)",
            o.median * 1e3
        ),
        _ => println!("latheguard moves failed on {program}"),
    }
    rs274.map(|r| r.median)
}

/// Cycles of each kind in the LinuxCNC G71/G70 program.
const G7X_UNITS: usize = 5_000;

/// A LinuxCNC program of `units` G71 roughing and G70 finishing cycles over one o-word profile
/// (straight moves whose A words round their corners), each from the same start point: about 74
/// moves a unit, as rs274 makes them.
fn lcnc_g7x_program(units: usize) -> String {
    let mut s = String::from(
        "G18 G7 G21 G90 G95\nT1 M6\nS800 M3\nF0.2\no100 sub\n  G1 X10 Z1.5\n  G1 Z-10 A1\n  G1 X16\n  \
         G1 Z-20 A1.5\n  G1 X21 A0.8\n  G1 X23 Z-26\n  G1 X24 A0.5\no100 endsub\n",
    );
    for _ in 0..units {
        s += "G0 X30 Z3\nG71 Q100 X30 Z3 D0.5 I1 R0.3\nG70 Q100 X30 Z3 D0.5 E0 P1\nG0 X40 Z20\n";
    }
    s += "M2\n";
    s
}

/// One unit of a cycle-heavy Fanuc program: G71 (two-block) roughing over a six-block profile
/// with an arc, G70 finishing along it, and a G76 (two-block) thread. P and Q find the first N
/// after the cycle block, so every unit reuses N10–N60.
const CYCLE_UNIT: &str = "G0 X52 Z3\nG71 U2 R0.5\nG71 P10 Q60 U0.4 W0.1 F0.25\nN10 G0 X20\nN20 G1 Z-10\nN30 X30 Z-15\nN40 Z-30\nN50 G2 X40 Z-35 R5\nN60 G1 X52\nG70 P10 Q60\nG0 X40 Z5\nG76 P010060 Q100 R0.05\nG76 X37.4 Z-25 P1300 Q400 F2\nG0 X60 Z5\n";

/// The other roughing and grooving cycles, one each: G72 (two-block) facing over a three-block
/// profile, G73 (two-block) pattern repeating over a three-block profile, and G75 (two-block)
/// grooving with pecks and shifts. With [`CYCLE_UNIT`], every Fanuc cycle of the five kinds.
const CYCLE_UNIT_2: &str = "G0 X52 Z3\nG72 W2 R0.5\nG72 P70 Q90 U0.4 W0.1 F0.25\nN70 G0 Z-8\nN80 G1 X30\nN90 X20 Z2\nG0 X60 Z5\nG73 U5 W1 R4\nG73 P100 Q120 U0.4 W0.1 F0.25\nN100 G0 X20 Z2\nN110 G1 Z-20\nN120 X52 Z-30\nG0 X54 Z-12\nG75 R0.5\nG75 X30 Z-20 P2000 Q2500 F0.1\nG0 X60 Z5\n";

/// Canned cycles (issue 11): a generated program of G71/G70/G76 blocks with their profiles,
/// read, interpreted and expanded into moves.
/// One row of the cycles table: lines and moves per second, median (best).
fn cycle_row(name: &str, lines: usize, t: Times, moves: usize, note: &str) {
    println!(
        "{name:<18} {lines:>9} {:>7.2} ({:>6.2}) {:>11.0} ({:>8.0}) {moves:>8}   {:.1} M moves/s; {note}",
        t.median * 1e3,
        t.best * 1e3,
        lines as f64 / t.median,
        lines as f64 / t.best,
        moves as f64 / t.median / 1e6,
    );
}

fn cycles(lines: usize, fanuc: &Machine) {
    cycles_of("cycles", CYCLE_UNIT, lines, fanuc);
    let both = format!("{CYCLE_UNIT}{CYCLE_UNIT_2}");
    cycles_of("all five", &both, lines, fanuc);
}

/// The rows of a generated program of `unit` repeated to about `lines` lines: read, interpreted
/// and expanded into a move list, and the same streamed.
fn cycles_of(name: &str, unit: &str, lines: usize, fanuc: &Machine) {
    let mut text = String::from("G21 G18 G99 G97 S800 M3\nT0101\n");
    let units = lines.saturating_sub(3) / unit.lines().count();
    text.push_str(&unit.repeat(units.max(1)));
    text.push_str("M30\n");
    let src = text.into_bytes();
    let n = src.iter().filter(|&&b| b == b'\n').count();
    let mut moves = 0;
    let mut unsupported = 0;
    let all = times(15, || {
        let p = pipeline::read(&src, fanuc);
        let r = interp::interpret(&p, &src, fanuc);
        moves = r.moves.len();
        unsupported = r.findings.len();
    });
    cycle_row(name, n, all, moves, &format!("{unsupported} findings"));
    // The same, with the moves handed to a sink as they are made (what `moves --format canon`
    // does): no move list grows, so no fresh pages are touched for it.
    let mut streamed = 0;
    let st = times(15, || {
        let p = pipeline::read(&src, fanuc);
        let mut count = 0usize;
        let r = interp::interpret_streaming(&p, &src, fanuc, |c| count += c.moves.len());
        streamed = count + r.moves.len();
    });
    assert_eq!(streamed, moves, "streaming hands over every move");
    cycle_row(&format!("{name}, streamed"), n, st, streamed, "streamed");
}
