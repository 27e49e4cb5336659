//! One program through the whole pipeline: read → interpret → (motion → scene → check).
//!
//! This is the library's entry point for checking; it does no I/O: the caller hands it the
//! program's bytes and gets findings and statistics back.

use crate::finding::{sort_findings, Finding, LeftOut, MAX_FINDINGS};
use crate::gcode;
use crate::interp::{self, Interpretation};
use crate::machine::{Dialect, Machine};
use serde::Serialize;
use std::borrow::Cow;

/// The default [`Settings::work_budget`]: about ten minutes of pair tests on one core.
pub const DEFAULT_WORK_BUDGET: u64 = 1_000_000_000;

/// The default graze threshold, mm: a contact shallower than this is a warning, not an error.
/// Holder and turret outlines are drawn to about ±0.1 mm, and the one false contact seen on real
/// programs was a 0.02 mm graze at a holder's leading edge: a contact shallower than the drawing's
/// own accuracy is not evidence of a crash (`docs/findings/collision.md`, "Grazes").
pub const DEFAULT_MIN_DEPTH_MM: f64 = 0.1;

/// The accepted range of `min_depth` (command line, `latheguard.toml`, machine file): at most
/// 1 mm, so that no real crash can be waved through as a graze by a slip of the unit.
pub const MIN_DEPTH_MM: (f64, f64) = (0.0, 1.0);

/// How a check runs (docs/checking.md, docs/cli.md).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Settings {
    pub mode: Mode,
    pub dt_ms: f64,
    pub tolerance_mm: f64,
    pub clearance_mm: f64,
    /// Contacts whose greatest depth stays below this are grazes, reported as warnings
    /// (`docs/findings/collision.md`). `None`: the machine's `machine.min_depth`, else
    /// [`DEFAULT_MIN_DEPTH_MM`]; see [`Settings::min_depth`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_depth_mm: Option<f64>,
    /// Most pair tests one program may cost; past it the rest of the program is reported
    /// unchecked (a `program` finding), so one file can never hold up a batch.
    #[serde(skip)]
    pub work_budget: u64,
    /// Most blocks the interpreter executes before it stops with a `program` finding, instead of
    /// [`interp::Limits::for_program`]'s (2 million, or 4 times the program's length): the fuzz
    /// targets bound each input tighter, as they bound its pair tests.
    #[serde(skip)]
    pub max_blocks: Option<u64>,
    /// Record a [`crate::scene::Snapshot`] of the scene at each finding's first contact.
    #[serde(skip)]
    pub snapshots: bool,
    /// Make the final part as a triangle mesh ([`Outcome::part_stl`], `--stock-out FILE.stl`).
    #[serde(skip)]
    pub part_mesh: bool,
    /// Let conservative advancement step over a stretch of a move it proves clear, or in contact
    /// and no deeper, by one query (`check/exact.rs`). Off only for the test that holds the
    /// proofs to the probe-by-probe measure (`tests/corpus.rs`).
    #[serde(skip)]
    pub prove_stretches: bool,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            mode: Mode::Step,
            dt_ms: 1.0,
            tolerance_mm: 0.01,
            clearance_mm: 0.0,
            min_depth_mm: None,
            work_budget: DEFAULT_WORK_BUDGET,
            max_blocks: None,
            snapshots: false,
            part_mesh: false,
            prove_stretches: true,
        }
    }
}

impl Settings {
    /// The graze threshold in effect on `machine`: these settings' own, else the machine
    /// file's `machine.min_depth`, else [`DEFAULT_MIN_DEPTH_MM`].
    /// The interpreter's limits for `prog` under these settings (`max_blocks`).
    pub fn limits(&self, prog: &gcode::Program) -> interp::Limits {
        let mut limits = interp::Limits::for_program(prog);
        if let Some(b) = self.max_blocks {
            limits.max_blocks = b;
        }
        limits
    }

    pub fn min_depth(&self, machine: &Machine) -> f64 {
        self.min_depth_mm.or(machine.min_depth).unwrap_or(DEFAULT_MIN_DEPTH_MM)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// Sample the scene every `dt` of machine time.
    Step,
    /// Check every move as a continuous sweep.
    Exact,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

/// What a check cost and which effects ran (the JSON report's `stats`).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Stats {
    pub blocks: u64,
    /// Motions that reach the machine: rapids, feeds, arcs and turret indexes (dwells are not
    /// counted). A program with none has the status `no_motion`.
    pub moves: u64,
    pub machine_time_s: f64,
    pub steps: u64,
    pub pair_tests: u64,
    pub pair_tests_skipped: u64,
    /// Rays the milled stock's cuts cast into its grids (`grid`): the work of milling, shown only
    /// when a program milled.
    #[serde(skip_serializing_if = "is_zero")]
    pub grid_rays: u64,
    /// Step mode: pairs whose stretch between two samples the proven gaps could not clear, so
    /// that their move was measured as exact mode measures it (`check::sample`).
    #[serde(skip)]
    pub refined: u64,
    /// Points of moves sampled for over-travel (`check::Checker::overtravel`): moves that reach
    /// past a travel limit are scanned; the bounded-work tests read it.
    #[serde(skip)]
    pub travel_samples: u64,
    pub effects: Vec<String>,
    pub elapsed_ms: f64,
    /// With `machine.dialect = "auto"`: the dialect chosen for this program and why (the
    /// reports show it per file).
    #[serde(skip)]
    pub dialect: Option<(Dialect, String)>,
}

/// The result of checking one program.
#[derive(Clone, Debug, Default)]
pub struct Outcome {
    pub findings: Vec<Finding>,
    pub stats: Stats,
    /// The stock at the end of the program: closed `[x, z]` outlines in the half plane x ≥ 0
    /// (the raw stock when the program never reached it; empty when the machine has none).
    pub stock: Vec<Vec<[f64; 2]>>,
    /// With [`Settings::part_mesh`]: the final part as binary STL (the milled stock when the
    /// program milled, else the section revolved).
    pub part_stl: Option<Vec<u8>>,
    /// The part a later operation takes (`--stock-out part.toml`), as a job's turn-round takes
    /// it; `None` when the machine has no stock or none is left.
    pub part: Option<FinalPart>,
}

/// The final part as the next operation takes it (docs/cli.md, `--stock-out part.toml`): after
/// a part-off the piece cut off, else the whole stock (`scene::turn_round::the_part`, what a
/// job's operation turns round); of several pieces left in it (a ring cut loose), the largest.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FinalPart {
    /// Its closed outline, `[x, z]` in the half plane x ≥ 0 (the spindle frame of this check).
    pub outline: Vec<[f64; 2]>,
    /// It is the piece a part-off cut off (the bar left in the jaws is not the part).
    pub parted_off: bool,
    /// Other pieces of material in it that `outline` leaves out.
    pub pieces_left_out: usize,
}

impl FinalPart {
    /// The part in `stock` (the checker's final stock). Its outline goes through the radius of
    /// every column where the profile bends, simplified only within 1e-6 mm — a coarser
    /// simplification cuts corners outward, and a part read back a µm fatter than it was meets
    /// jaws that touched it — and only as far as `tol` when an outline would have more points
    /// than a stock outline may (`machine::MAX_OUTLINE_POINTS`).
    pub fn of(stock: &crate::scene::DexelStock, tol: f64) -> Option<FinalPart> {
        let (part, parted_off) = crate::scene::turn_round::the_part(stock)?;
        let mut eps = 1e-6;
        let mut pieces = part.outlines(eps);
        while eps < tol && pieces.iter().any(|o| o.len() > crate::machine::MAX_OUTLINE_POINTS) {
            eps = (eps * 8.0).min(tol);
            pieces = part.outlines(eps);
        }
        let area = |o: &Vec<[f64; 2]>| {
            let n = o.len();
            (0..n)
                .map(|i| {
                    let (a, b) = (o[i], o[(i + 1) % n]);
                    a[0] * b[1] - b[0] * a[1]
                })
                .sum::<f64>()
                .abs()
        };
        let n = pieces.len();
        let outline = pieces.into_iter().max_by(|a, b| area(a).total_cmp(&area(b)))?;
        Some(FinalPart {
            outline,
            parted_off,
            pieces_left_out: n - 1,
        })
    }
}

/// The machine as it reads this program: with `dialect = "auto"`, the dialect the program's own
/// signs choose (`machine::auto`) and why; otherwise the machine itself.
pub fn resolve<'m>(src: &[u8], machine: &'m Machine) -> (Cow<'m, Machine>, Option<(Dialect, String)>) {
    if machine.auto_dialect.is_none() {
        return (Cow::Borrowed(machine), None);
    }
    let (d, why) = crate::machine::auto::detect(src);
    match machine.with_dialect(d) {
        Some(m) => (Cow::Owned(m), Some((d, why))),
        None => (Cow::Borrowed(machine), None),
    }
}

/// Read and interpret a program: the syntax, program and unsupported findings, and the moves.
pub fn interpret<'s>(src: &'s [u8], machine: &Machine) -> (gcode::Program<'s>, Interpretation) {
    let (machine, _) = resolve(src, machine);
    let machine = machine.as_ref();
    let prog = read(src, machine);
    let run = interp::interpret(&prog, src, machine);
    (prog, run)
}

/// Read a program as the machine's dialect reads it (Fanuc: with macro B statements).
pub fn read<'s>(src: &'s [u8], machine: &Machine) -> gcode::Program<'s> {
    read_by(src, machine, gcode::WINDOW_BLOCKS)
}

/// [`read`], holding `per_window` blocks a window (the blocks read are the same; a smaller window
/// holds less memory and reads more windows again when the program jumps far back and forth).
pub fn read_by<'s>(src: &'s [u8], machine: &Machine, per_window: usize) -> gcode::Program<'s> {
    gcode::parse_windowed(src, machine.dialect == crate::machine::Dialect::Fanuc, per_window)
}

/// The reader's and the interpreter's findings, taken out of `prog` and `run`, with the count of
/// those the stages left out.
fn take_findings(prog: &mut gcode::Program, run: &mut Interpretation) -> (Vec<Finding>, LeftOut) {
    let mut findings = std::mem::take(&mut prog.errors);
    findings.append(&mut run.findings);
    let mut left_out = prog.errors_left_out;
    left_out.merge(run.findings_left_out);
    (findings, left_out)
}

/// Findings in report order, once each, at most [`MAX_FINDINGS`] of them and then one `program`
/// finding that says how many more there were (counting those the stages already left out).
fn report_order(mut findings: Vec<Finding>, mut left_out: LeftOut) -> Vec<Finding> {
    sort_findings(&mut findings);
    // A block inside a loop or a repeated subprogram reports its problem once.
    findings.dedup_by(|a, b| {
        a.time_s.is_none()
            && b.time_s.is_none()
            && (a.line, a.col, a.kind) == (b.line, b.col, b.kind)
            && a.message == b.message
    });
    if findings.len() > MAX_FINDINGS {
        for f in &findings[MAX_FINDINGS..] {
            left_out.add(f.line, 1);
        }
        findings.truncate(MAX_FINDINGS);
    }
    if let Some(f) = left_out.finding() {
        findings.push(f);
        sort_findings(&mut findings);
    }
    findings
}

/// The syntax, program and unsupported findings of a read and interpreted program in report
/// order (what [`check`] reports before the checker adds its own), capped as [`check`] caps them.
pub fn read_findings(prog: &mut gcode::Program, run: &mut Interpretation) -> Vec<Finding> {
    let (findings, left_out) = take_findings(prog, run);
    report_order(findings, left_out)
}

/// Check one program on a machine. The checker takes the moves as the interpreter makes them
/// (`check::Stream`), so a long program's moves are never all in memory; the outcome is
/// [`check_whole`]'s, byte for byte (`tests/streamed.rs`).
pub fn check(src: &[u8], machine: &Machine, settings: &Settings) -> Outcome {
    if crate::paths::is_multi_path(src, machine) {
        // Several paths: each checked alone on its carrier, then the carriers against each
        // other (docs/paths.md).
        return crate::paths::check(src, machine, settings);
    }
    check_streamed(src, machine, settings, interp::STREAM_CHUNK)
}

/// [`check`] with the moves handed to the checker `chunk` at a time (at least 1; the tests hold
/// a chunk of one move to the whole run).
pub fn check_streamed(src: &[u8], machine: &Machine, settings: &Settings, chunk: usize) -> Outcome {
    check_streamed_windowed(src, machine, settings, chunk, gcode::WINDOW_BLOCKS)
}

/// [`check_streamed`] with the program's blocks held `per_window` at a time (`gcode::Program`;
/// the tests hold a window of one block to the whole run).
#[doc(hidden)]
pub fn check_streamed_windowed(
    src: &[u8],
    machine: &Machine,
    settings: &Settings,
    chunk: usize,
    per_window: usize,
) -> Outcome {
    let (machine, dialect) = resolve(src, machine);
    let machine = machine.as_ref();
    let mut prog = gcode::parse_windowed(src, machine.dialect == crate::machine::Dialect::Fanuc, per_window);
    let limits = settings.limits(&prog);
    let three = if crate::check::takes_3d_depends_on_run(machine) {
        // A turn-mill machine whose tailstock starts advanced: whether the 3D path runs depends on
        // the whole run, so a first pass of the interpreter learns it (its moves are dropped as
        // they come).
        let mut any_extra = false;
        let run = interp::interpret_streaming_limited(&prog, src, machine, interp::STREAM_CHUNK, limits, |c| {
            any_extra |= !c.extra.is_empty()
        });
        let withdrawn = run.states.iter().any(|s| !s.tailstock_advanced);
        crate::check::takes_3d(machine, any_extra, withdrawn)
    } else {
        crate::check::takes_3d(machine, false, false)
    };
    let chunk = chunk.max(1);
    let mut stream = crate::check::Stream::new(machine, settings, three, MAX_FINDINGS);
    let mut run = interp::interpret_streaming_limited(&prog, src, machine, chunk, limits, |c| {
        // The interpreter hands a block's moves over together: cut them to `chunk` here too.
        let mut first = 0;
        while first < c.moves.len() {
            let end = (first + chunk).min(c.moves.len());
            let index = |k: usize| c.first + k;
            let extra = &c.extra[c.extra.partition_point(|e| (e.index as usize) < index(first))..];
            let extra = &extra[..extra.partition_point(|e| (e.index as usize) < index(end))];
            stream.feed(interp::Chunk {
                first: index(first),
                moves: &c.moves[first..end],
                states: c.states,
                extra,
            });
            first = end;
        }
    });
    let (findings, left_out) = take_findings(&mut prog, &mut run);
    drop(prog);
    let blocks = run.blocks_executed;
    outcome(findings, left_out, stream.finish(), blocks, dialect, machine, settings)
}

/// [`check`] the way it ran before the checker streamed: the whole run interpreted, then
/// checked (`check::check`). The oracle of the streamed check's tests; `accuracy` and the
/// tests that need the moves too read the run this way.
pub fn check_whole(src: &[u8], machine: &Machine, settings: &Settings) -> Outcome {
    let (machine, dialect) = resolve(src, machine);
    let machine = machine.as_ref();
    let (findings, left_out, run) = interpret_whole(src, machine, settings);
    check_run(findings, left_out, &run, dialect, machine, settings)
}

/// The first half of [`check_whole`]: `src` read and interpreted whole on `machine` (already
/// [`resolve`]d), with the reader's and the interpreter's findings taken out of the run.
pub fn interpret_whole(src: &[u8], machine: &Machine, settings: &Settings) -> (Vec<Finding>, LeftOut, Interpretation) {
    let mut prog = read(src, machine);
    let limits = settings.limits(&prog);
    let mut run = interp::interpret_with(&prog, src, machine, limits);
    let (findings, left_out) = take_findings(&mut prog, &mut run);
    (findings, left_out, run)
}

/// The second half of [`check_whole`]: the moves of `run` checked on `machine`, with the
/// reader's and interpreter's `findings`.
pub fn check_run(
    findings: Vec<Finding>,
    left_out: LeftOut,
    run: &Interpretation,
    dialect: Option<(Dialect, String)>,
    machine: &Machine,
    settings: &Settings,
) -> Outcome {
    check_run_sharing(findings, left_out, run, dialect, machine, settings, Vec::new(), false).0
}

/// [`check_run`] of one path of a multi-path program whose stock the paths share
/// (`check::check_sharing`): `foreign` what the other paths cut, each before the move it
/// precedes; with `record`, this path's own cuts beside the outcome. The multi-path check
/// (`crate::paths`) runs it on a run whose spindle states it may have set from another path.
#[allow(clippy::too_many_arguments)]
pub fn check_run_sharing(
    findings: Vec<Finding>,
    left_out: LeftOut,
    run: &Interpretation,
    dialect: Option<(Dialect, String)>,
    machine: &Machine,
    settings: &Settings,
    foreign: Vec<crate::check::Cut>,
    record: bool,
) -> (Outcome, Vec<crate::check::Cut>) {
    let mut result = crate::check::check_sharing(run, machine, settings, foreign, record);
    let cuts = std::mem::take(&mut result.cuts);
    result.stats.moves = run
        .moves
        .iter()
        .filter(|m| {
            !matches!(
                m.kind,
                interp::MoveKind::Dwell { .. } | interp::MoveKind::Operation { .. } | interp::MoveKind::Wait { .. }
            )
        })
        .count() as u64;
    let out = outcome(
        findings,
        left_out,
        result,
        run.blocks_executed,
        dialect,
        machine,
        settings,
    );
    (out, cuts)
}

/// The outcome of a check: the reader's and interpreter's findings (`findings`, `left_out`)
/// with the checker's in report order, the statistics, and the final stock and part.
fn outcome(
    mut findings: Vec<Finding>,
    left_out: LeftOut,
    result: crate::check::CheckResult,
    blocks: u64,
    dialect: Option<(Dialect, String)>,
    machine: &Machine,
    settings: &Settings,
) -> Outcome {
    findings.extend(result.findings);
    let findings = report_order(findings, left_out);
    let mut stats = result.stats;
    stats.dialect = dialect;
    stats.blocks = blocks;
    let stock = match (&result.stock, &machine.stock) {
        (Some(s), _) => s.outlines(settings.tolerance_mm),
        (None, Some(s)) => vec![s.section()],
        (None, None) => Vec::new(),
    };
    let part_stl = result.part_stl;
    let part = match (&result.stock, &machine.stock) {
        (Some(s), _) => FinalPart::of(s, settings.tolerance_mm),
        (None, Some(s)) => Some(FinalPart {
            outline: s.section(),
            parted_off: false,
            pieces_left_out: 0,
        }),
        (None, None) => None,
    };
    Outcome {
        findings,
        stats,
        stock,
        part_stl,
        part,
    }
}
