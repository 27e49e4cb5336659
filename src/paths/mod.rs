//! Multi-path programs (docs/paths.md): one file whose `$1`, `$2`, … lines start each path's
//! lines, run on a machine whose `[[paths]]` give each path after the first its own tool
//! carrier.
//!
//! How a program is checked ([`check`]):
//!
//! 1. `split.rs` cuts the file into one copy per path, every other path's lines blanked (lines,
//!    columns and offsets stay the file's).
//! 2. Each path is checked alone on the lathe it runs on ([`Machine::for_path`]: its carrier's
//!    axes, turret and tools): its tools against the chuck, the tailstock and the stock, its
//!    travel, its own program's findings — exactly the one-path check.
//! 3. `sync.rs` times the paths in the machine's one clock from their waiting M codes; paths
//!    that can never meet are a `program` finding at each wait left standing.
//! 4. `cross.rs` checks the carriers against each other over that common time.
//!
//! The paths share the stock (`shared_stock`): a path's move meets the stock less every other
//! path's cut that has ended by the move's start — at least the material there is at any
//! instant of it (docs/paths.md).

pub mod cross;
pub mod cross3;
mod spindle;
pub mod split;
pub mod sync;

use crate::finding::{Finding, Kind, Severity};
use crate::interp::MoveKind;
use crate::machine::Machine;
use crate::pipeline::{self, Outcome, Settings};

/// Whether a program on `machine` goes through the multi-path check: the machine has several
/// paths, or the file starts paths with `$` lines.
pub fn is_multi_path(src: &[u8], machine: &Machine) -> bool {
    !machine.paths.carriers.is_empty() || split::split(src).is_some()
}

/// A program's paths, each interpreted on its lathe and timed in the machine's clock.
struct Prepared {
    lanes: Vec<Lane>,
    schedules: Vec<sync::Schedule>,
    /// Findings of the program as a whole: paths the machine lacks, waits that never meet.
    extra: Vec<Finding>,
    /// The machine time past which nothing runs (a deadlock).
    stop: Option<f64>,
    /// What reports call each lane's carrier.
    names: Vec<String>,
}

/// Read, interpret and time every path of a program.
fn prepare(src: &[u8], machine: &Machine, settings: &Settings) -> Prepared {
    let split = split::split(src);
    let count = machine.paths.count() as u32;
    let mut extra: Vec<Finding> = Vec::new();
    // Each path's source: its copy of the file, or the whole file for path 1 of a file without
    // markers; a path without lines runs nothing (its carrier stands at home).
    let mut sources: Vec<(u32, Vec<u8>)> = Vec::new();
    match &split {
        None => sources.push((1, src.to_vec())),
        Some(s) => {
            for m in &s.markers {
                if m.path > count {
                    extra.push(Finding::at(
                        Kind::Unsupported,
                        Severity::Error,
                        m.line,
                        1,
                        format!(
                            "${} starts path {}, but this machine has {} (`[[paths]]` in the machine file, docs/paths.md): the path's lines are not checked",
                            m.path, m.path, count
                        ),
                    ));
                }
            }
            for (p, text) in &s.paths {
                if *p <= count {
                    sources.push((*p, text.clone()));
                }
            }
        }
    }
    // Dedupe the unsupported findings of a path started more than once.
    extra.dedup_by(|a, b| a.message == b.message);
    for p in 1..=count {
        if !sources.iter().any(|s| s.0 == p) {
            sources.push((p, Vec::new()));
        }
    }
    sources.sort_by_key(|s| s.0);

    let mut lanes: Vec<Lane> = Vec::new();
    for (p, text) in &sources {
        let Some(view) = machine.for_path(*p) else { continue };
        let (resolved, dialect) = pipeline::resolve(text, &view);
        let m = resolved.into_owned();
        let (findings, left_out, run) = pipeline::interpret_whole(text, &m, settings);
        let timeline = crate::motion::timeline(&run, &m);
        lanes.push(Lane {
            path: *p,
            machine: m,
            findings,
            left_out,
            dialect,
            run,
            timeline,
        });
    }

    // The waits, in each path's own time; a path that leaves the spindle to another takes its
    // spindle, which changes its own time (feeds per revolution): timed again, twice at most.
    let mut timed = schedule_of(&lanes, count);
    if let Some(sharing) = spindle::plan(&lanes, machine) {
        for _ in 0..2 {
            sharing.apply(&mut lanes, &timed.0);
            for l in lanes.iter_mut() {
                l.timeline = crate::motion::timeline(&l.run, &l.machine);
            }
            timed = schedule_of(&lanes, count);
        }
    }
    let (schedules, dead, stop) = timed;
    for d in &dead {
        extra.push(Finding::program(d.line, 1, d.message.clone()));
    }

    let names: Vec<String> = lanes
        .iter()
        .map(|l| {
            if l.path == 1 {
                machine.paths.first.clone()
            } else {
                machine
                    .paths
                    .carriers
                    .iter()
                    .find(|c| c.path == l.path)
                    .map_or_else(|| format!("path {} carrier", l.path), |c| c.name.clone())
            }
        })
        .collect();
    Prepared {
        lanes,
        schedules,
        extra,
        stop,
        names,
    }
}

/// One path of a program as `check` times it: its number, its lathe, its run, and its moves
/// timed in the machine's clock (its own times shifted by its waits).
pub struct TimedPath {
    pub path: u32,
    pub machine: Machine,
    pub run: crate::interp::Interpretation,
    pub items: Vec<crate::motion::Timed>,
}

/// A program's paths as [`timed`] gives them.
pub struct Timed {
    /// Path 1 first.
    pub paths: Vec<TimedPath>,
    /// The machine time past which nothing runs (a deadlock).
    pub stop: Option<f64>,
    /// The program's findings of reading and interpreting (every path's, a line before the first
    /// `$` once; waits that never meet; paths the machine lacks), in line order.
    pub findings: Vec<Finding>,
}

/// Every path of a program as `check` times it (the replay's samples,
/// `latheguard moves --format samples`).
pub fn timed(src: &[u8], machine: &Machine, settings: &Settings) -> Timed {
    let mut p = prepare(src, machine, settings);
    let mut findings = std::mem::take(&mut p.extra);
    for l in &mut p.lanes {
        findings.append(&mut l.findings);
        findings.append(&mut l.run.findings);
    }
    crate::finding::sort_findings(&mut findings);
    findings.dedup_by(|a, b| (a.line, a.col, a.kind, &a.message) == (b.line, b.col, b.kind, &b.message));
    let paths = p
        .lanes
        .into_iter()
        .zip(&p.schedules)
        .map(|(l, s)| TimedPath {
            path: l.path,
            items: l
                .timeline
                .items
                .iter()
                .map(|it| crate::motion::Timed {
                    t0: s.global(it.index, it.t0),
                    ..it.clone()
                })
                .collect(),
            machine: l.machine,
            run: l.run,
        })
        .collect();
    Timed {
        paths,
        stop: p.stop,
        findings,
    }
}

/// Run `f` on the carriers of a program on a machine whose kinematic tree several paths drive,
/// as the 3D check between carriers poses them (`cross3::Carriers`): for the tests' oracle.
/// `None` on another machine.
pub fn with_carriers3<R>(
    src: &[u8],
    machine: &Machine,
    settings: &Settings,
    f: impl FnOnce(&cross3::Carriers) -> R,
) -> Option<R> {
    let kin = machine.kinematics.as_deref().filter(|k| k.is_multi_path())?;
    let p = prepare(src, machine, settings);
    let lanes = carriages(&p, machine);
    let carriers = cross3::Carriers::new(kin, &lanes, settings.tolerance_mm);
    Some(f(&carriers))
}

/// Each lane as the checks between carriers read it.
fn carriages<'a>(p: &'a Prepared, machine: &Machine) -> Vec<cross::Carriage<'a>> {
    p.lanes
        .iter()
        .zip(&p.schedules)
        .zip(&p.names)
        .map(|((l, s), name)| cross::Carriage {
            path: l.path,
            name: name.clone(),
            machine: &l.machine,
            run: &l.run,
            timeline: &l.timeline,
            schedule: s,
            opposite: machine.paths.carriers.iter().any(|c| c.path == l.path && c.opposite),
        })
        .collect()
}

/// Check a program on a machine with several paths, or a program written for several paths.
pub fn check(src: &[u8], machine: &Machine, settings: &Settings) -> Outcome {
    let p = prepare(src, machine, settings);
    // The carriers against each other: in 3D on a tree whose axes several paths drive, else in
    // the working plane.
    let lanes = carriages(&p, machine);
    let (cross_findings, probes) = match machine.kinematics.as_deref().filter(|k| k.is_multi_path()) {
        Some(kin) => cross3::check(kin, &lanes, settings.tolerance_mm, p.stop, settings.snapshots),
        None => cross::check(&lanes, settings.tolerance_mm, p.stop),
    };
    drop(lanes);
    let Prepared {
        lanes,
        schedules,
        extra,
        ..
    } = p;

    // One outcome: every path's findings at their lines, their times in the machine's clock.
    let mut out = Outcome::default();
    let mut seen = std::collections::HashSet::new();
    let mut machine_time = 0.0f64;
    let outcomes = shared_stock(&lanes, &schedules, settings);
    for ((l, s), o) in lanes.into_iter().zip(&schedules).zip(outcomes) {
        for mut f in o.findings {
            if let Some(t) = f.time_s.as_mut() {
                *t = s.global_of_local(*t);
            }
            if let Some(t) = f.end_time_s.as_mut() {
                *t = s.global_of_local(*t);
            }
            // The lines before the first `$` are read by every path: report their findings once.
            if f.time_s.is_none() && !seen.insert((f.line, f.col, f.kind, f.message.clone())) {
                continue;
            }
            out.findings.push(f);
        }
        let st = &o.stats;
        out.stats.blocks += st.blocks;
        out.stats.moves += st.moves;
        out.stats.steps += st.steps;
        out.stats.pair_tests += st.pair_tests;
        out.stats.pair_tests_skipped += st.pair_tests_skipped;
        out.stats.grid_rays += st.grid_rays;
        out.stats.refined += st.refined;
        out.stats.travel_samples += st.travel_samples;
        out.stats.elapsed_ms += st.elapsed_ms;
        for e in &st.effects {
            if !out.stats.effects.contains(e) {
                out.stats.effects.push(e.clone());
            }
        }
        if out.stats.dialect.is_none() {
            out.stats.dialect = st.dialect.clone();
        }
        machine_time = machine_time.max(s.global_of_local(st.machine_time_s));
        if l.path == 1 {
            // The final part is path 1's stock, which has every other path's cuts too
            // (`shared_stock` takes off the ones after its last move at its end).
            out.stock = o.stock;
            out.part = o.part;
            out.part_stl = o.part_stl;
        }
    }
    out.stats.machine_time_s = machine_time;
    out.stats.pair_tests += probes;
    out.stats.effects.push("paths".to_string());
    out.findings.extend(extra);
    out.findings.extend(cross_findings);
    crate::finding::sort_findings(&mut out.findings);
    out
}

/// Each lane checked on the stock the paths share: first each alone, its cuts recorded; then
/// each lane that another path cut before one of its moves again, with those cuts taken off its
/// stock before that move (every cut that has ended by the move's start in the machine's clock;
/// a cut still under way is not, so the stock a move meets holds at least the material there is).
/// A cut after the lane's last move is taken off its final part. The cuts of a lane do not
/// depend on what another took off before them (a cut is the insert's sweep), so one round is
/// exact.
fn shared_stock(lanes: &[Lane], schedules: &[sync::Schedule], settings: &Settings) -> Vec<Outcome> {
    let run = |l: &Lane, foreign: Vec<crate::check::Cut>, record: bool| {
        pipeline::check_run_sharing(
            l.findings.clone(),
            l.left_out,
            &l.run,
            l.dialect.clone(),
            &l.machine,
            settings,
            foreign,
            record,
        )
    };
    let (alone, cuts): (Vec<Outcome>, Vec<Vec<crate::check::Cut>>) =
        lanes.iter().map(|l| run(l, Vec::new(), lanes.len() > 1)).unzip();
    // Each lane's cuts with the machine time they end at.
    let ended: Vec<Vec<(f64, &crate::check::Removed)>> = lanes
        .iter()
        .zip(schedules)
        .zip(&cuts)
        .map(|((l, s), cuts)| {
            cuts.iter()
                .filter_map(|(k, removed)| {
                    let j = l.timeline.items.partition_point(|it| it.index < *k);
                    let it = l.timeline.items.get(j).filter(|it| it.index == *k)?;
                    Some((s.global(it.index, it.t0) + it.duration, removed))
                })
                .collect()
        })
        .collect();
    let mut out = Vec::with_capacity(lanes.len());
    for (p, ((l, s), o)) in lanes.iter().zip(schedules).zip(alone).enumerate() {
        let starts: Vec<f64> = l.timeline.items.iter().map(|it| s.global(it.index, it.t0)).collect();
        let foreign: Vec<crate::check::Cut> = ended
            .iter()
            .enumerate()
            .filter(|(q, _)| *q != p)
            .flat_map(|(_, cuts)| cuts.iter())
            .map(|(end, removed)| {
                let j = starts.partition_point(|&t| t < *end);
                let before = l.timeline.items.get(j).map_or(usize::MAX, |it| it.index);
                (before, (*removed).clone())
            })
            .collect();
        if foreign.is_empty() {
            out.push(o);
            continue;
        }
        out.push(run(l, foreign, false).0);
    }
    out
}

/// One path of the program: its lathe, its run and its own time.
struct Lane {
    path: u32,
    machine: Machine,
    findings: Vec<Finding>,
    left_out: crate::finding::LeftOut,
    dialect: Option<(crate::machine::Dialect, String)>,
    run: crate::interp::Interpretation,
    timeline: crate::motion::Timeline,
}

/// The lanes' waits timed in the machine's clock (`sync::schedule`).
fn schedule_of(lanes: &[Lane], count: u32) -> (Vec<sync::Schedule>, Vec<sync::Deadlock>, Option<f64>) {
    let sync_lanes: Vec<sync::Lane> = lanes
        .iter()
        .map(|l| sync::Lane {
            path: l.path,
            waits: l
                .timeline
                .items
                .iter()
                .filter_map(|it| match l.run.moves[it.index].kind {
                    MoveKind::Wait { code, paths } => Some(sync::WaitAt {
                        index: it.index,
                        t: it.t0,
                        code,
                        mask: paths & (((1u32 << count) - 1) as u8),
                        line: l.run.moves[it.index].line,
                    }),
                    _ => None,
                })
                .collect(),
            end: l.timeline.total,
            last_line: l.run.moves.last().map_or(1, |m| m.line),
        })
        .collect();
    sync::schedule(&sync_lanes)
}
