//! The interpreter: blocks → moves in the spindle frame, for the Fanuc and LinuxCNC dialects.
//!
//! It keeps the modal state (units, distance and diameter modes, feed and spindle modes, the
//! active tool, offsets), evaluates parameters and expressions, runs LinuxCNC o-word flow and
//! subroutines, Fanuc M98/M99 subprograms and Fanuc custom macro B (`macro_b.rs`), and emits one [`Move`] per motion with its source
//! line. Problems become `program` findings, codes it does not model `unsupported` findings; it
//! never stops at the first one, and a bounded execution budget stops endless loops.

mod arc;
mod block;
pub mod canon;
mod comp;
mod contour_comp;
mod convert;
mod cycles;
mod cylindrical;
mod eval;
mod flow;
mod groups;
mod letters;
mod macro_b;
mod mcodes;
mod operations;
mod order;
mod polar;
mod state;
#[cfg(test)]
mod tests;
mod turnmill;
mod words;

use crate::finding::Finding;
use crate::gcode::Program;
use crate::geom::{P2, V2};
use crate::machine::Machine;

pub use arc::{arc_from_center, arc_from_radius, ArcError, ArcTolerance};

/// The range of every coordinate a move may reach, mm (and of the extra axes' values, in their
/// units): a target point, an arc's radius and centre, a point a canned cycle computes from its
/// words. Past it a block is a `program` finding and makes no move. Far beyond any machine, and
/// small enough that the checker's arithmetic on it stays exact to well under a millimetre.
pub const MAX_COORD: f64 = 1e12;

/// A value within ±[`MAX_COORD`] (false for NaN).
#[inline]
pub(crate) fn in_range_value(v: f64) -> bool {
    v.abs() <= MAX_COORD
}
pub(crate) use groups::models_g;

/// Direction of the spindle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpindleDir {
    Off,
    Cw,
    Ccw,
}

/// How the spindle speed is commanded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpindleSpeed {
    /// G97: revolutions per minute.
    Rpm(f64),
    /// G96: constant surface speed in m/min, clamped to `max_rpm`.
    Css { m_per_min: f64, max_rpm: f64 },
}

/// The spindle as a move sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spindle {
    pub dir: SpindleDir,
    pub speed: SpindleSpeed,
}

impl Spindle {
    pub fn is_on(&self) -> bool {
        self.dir != SpindleDir::Off
    }

    /// Speed in rpm with the tool tip at radius `r` mm (0 when stopped).
    pub fn rpm_at(&self, r: f64) -> f64 {
        if !self.is_on() {
            return 0.0;
        }
        match self.speed {
            SpindleSpeed::Rpm(s) => s,
            SpindleSpeed::Css { m_per_min, max_rpm } => {
                let r = r.abs();
                let rpm = if r > 1e-9 {
                    m_per_min * 1000.0 / (2.0 * std::f64::consts::PI * r)
                } else {
                    f64::INFINITY
                };
                rpm.min(max_rpm)
            }
        }
    }
}

/// The feed of a move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Feed {
    /// A rapid: each axis at the machine's rapid rate.
    Rapid,
    /// mm/min.
    PerMinute(f64),
    /// mm per spindle revolution (G95/G99, and threading where it is the lead).
    PerRev(f64),
}

/// How to turn a spindle-frame point back into the program's coordinates (for reports).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProgFrame {
    /// Spindle-frame point of program X0 Z0.
    pub origin: P2,
    /// mm per program unit (1 or 25.4).
    pub scale: f64,
    /// X words are diameters.
    pub diameter: bool,
}

impl ProgFrame {
    /// Program (X as written, Z) of a spindle-frame point.
    pub fn to_program(&self, p: P2) -> (f64, f64) {
        let x = (p.x - self.origin.x) / self.scale;
        let z = (p.y - self.origin.y) / self.scale;
        (if self.diameter { 2.0 * x } else { x }, z)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// G0, and the legs of G28/G53 moves.
    Rapid,
    /// G1 (and G32/G33 threading, with a per-revolution feed).
    Line,
    /// G2/G3: the programmed point turns about `center` by `sweep` radians (positive =
    /// counter-clockwise in the (x, z) plane with x right and z up, which is G2 seen from +Y).
    /// Its radius may change linearly from start to end (rs274ngc tolerates a small spiral).
    Arc { center: P2, sweep: f64 },
    /// G4: the machine stands still.
    Dwell { seconds: f64 },
    /// The turret indexes from one station to another (at the T word on Fanuc, at M6 on
    /// LinuxCNC); the reference point stays where it is.
    ToolChange { from: u32, to: u32 },
    /// A job's operation after the first begins (`Machine::operations[op]`): the operator has
    /// turned the part round or re-clamped it; nothing moves, the checker replaces the stock.
    Operation { op: u32 },
    /// A waiting M code of a multi-path control (`[sync]`, docs/paths.md): this path stands
    /// here until every path of `paths` (bit `p - 1` for path `p`) has reached the same code.
    /// Nothing moves; the multi-path check (`crate::paths`) times the wait.
    Wait { code: u16, paths: u8 },
}

/// One motion of the machine.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub kind: MoveKind,
    /// Physical 1-based source line.
    pub line: u32,
    pub n: Option<u64>,
    /// For a move a canned cycle made along its profile: the physical line of the profile
    /// block it follows (so a finding can name both); 0 otherwise.
    pub profile_line: u32,
    /// Programmed point (tool tip) at the start and end, spindle frame. The turret reference
    /// point is `start - tip` / `end - tip`.
    pub start: P2,
    pub end: P2,
    /// The active tool's tip relative to the turret reference point.
    pub tip: V2,
    /// Station facing the spindle during the move (after the change for a tool change).
    pub station: u32,
    pub feed: Feed,
    /// Index of the move's spindle and frame in [`Interpretation::states`].
    pub state: u32,
}

/// What runs of moves share and what changes rarely: the spindle and the program frame. Moves
/// refer to it by index, which keeps a [`Move`] small (a program holds one per block).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MoveState {
    pub spindle: Spindle,
    pub frame: ProgFrame,
    /// The tailstock is advanced (an obstacle) during the move (`tailstock.advanced` and the
    /// machine's tailstock M codes).
    pub tailstock_advanced: bool,
    /// The active station holds no tool the machine file describes (a `T` for an empty or
    /// missing station): where the turret is depends on that tool's offsets, so the checker
    /// does not check the move.
    pub tool_unknown: bool,
    /// The sub-spindle's chuck is clamped (`[mcodes]` `sub_chuck_close`/`sub_chuck_open`).
    pub sub_chuck_closed: bool,
}

impl Move {
    pub fn ref_start(&self) -> P2 {
        self.start - self.tip
    }

    pub fn ref_end(&self) -> P2 {
        self.end - self.tip
    }

    /// The programmed point at fraction `t` ∈ [0, 1] of the path (arcs: of the angle).
    pub fn point_at(&self, t: f64) -> P2 {
        path_point(self.kind, self.start, self.end, t)
    }

    /// Path length of the programmed point, mm.
    pub fn length(&self) -> f64 {
        match self.kind {
            MoveKind::Arc { center, sweep } => {
                let r0 = (self.start - center).norm();
                let r1 = (self.end - center).norm();
                let r = 0.5 * (r0 + r1);
                let arc = r * sweep.abs();
                (arc * arc + (r1 - r0) * (r1 - r0)).sqrt()
            }
            MoveKind::Dwell { .. }
            | MoveKind::ToolChange { .. }
            | MoveKind::Operation { .. }
            | MoveKind::Wait { .. } => 0.0,
            _ => (self.end - self.start).norm(),
        }
    }
}

/// The point at fraction `t` ∈ [0, 1] of a path of `kind` from `start` to `end`: along the line,
/// or along the angle of an arc whose radius changes linearly (the small spiral rs274ngc
/// tolerates).
pub(crate) fn path_point(kind: MoveKind, start: P2, end: P2, t: f64) -> P2 {
    match kind {
        MoveKind::Arc { center, sweep } => {
            let a = start - center;
            let r0 = a.norm();
            let r1 = (end - center).norm();
            let r = r0 + (r1 - r0) * t;
            let ang = a.y.atan2(a.x) + sweep * t;
            P2::new(center.x + r * ang.cos(), center.y + r * ang.sin())
        }
        _ => start + (end - start) * t,
    }
}

/// The address letters of the axes beyond X and Z that the interpreter tracks (turn-mill), in
/// the order of [`ExtraAxes`]. Which of them a machine has, and whether each is linear (mm, in
/// the spindle frame; inch programs are converted) or rotary (degrees), its kinematic tree says
/// (`Machine::kinematics`, `Kinematics::axis_by_letter`).
pub const EXTRA_LETTERS: [char; 4] = ['Y', 'C', 'B', 'A'];

/// Values of the [`EXTRA_LETTERS`] axes, in that order.
pub type ExtraAxes = [f64; 4];

/// The working plane (G17 XY, G18 ZX — a lathe's own —, G19 YZ).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Plane {
    Xy,
    #[default]
    Zx,
    Yz,
}

/// A move's extra axes and turn-mill modes, kept only for the moves where any of them is not at
/// its default (an extra axis away from its start value or moving, the main spindle in C-axis
/// mode, a live tool turning, a plane other than G18). A sparse side table, so a turning program
/// keeps [`Move`] at its size and the 2D checker's path untouched.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtraMove {
    /// Index of the move in [`Interpretation::moves`].
    pub index: u32,
    pub start: ExtraAxes,
    pub end: ExtraAxes,
    pub plane: Plane,
    /// The main spindle is a positioned C axis (not turning) during the move.
    pub c_mode: bool,
    /// The live tool's speed in rev/min (0: stopped).
    pub live_rpm: f64,
    /// The axis value of program zero of each extra axis during the move (0 plus the G92 / G50 /
    /// G52 shift in force), so a value can be told back in program coordinates.
    pub origin: ExtraAxes,
    /// For an arc in the XY (G17) or YZ (G19) plane: its centre and sweep. The move's 2D fields
    /// then hold a [`MoveKind::Line`] from its start to its end (the XZ projection of the arc is
    /// no arc of the lathe's plane); [`position3`] follows the arc.
    pub arc: Option<PlaneArc>,
}

/// An arc in the XY (G17) or YZ (G19) plane, spindle frame, mm. The programmed point turns
/// about `center` by `sweep` radians in the plane's (first, second) coordinates — G17 (x, y),
/// G19 (y, z); x a radius — positive from the first axis toward the second (G3, counter-clockwise
/// seen from +z for G17 and from +x for G19). Its radius may change linearly (the small spiral
/// rs274ngc tolerates), and the third coordinate (z for G17, x for G19) moves linearly from
/// start to end (a helix).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneArc {
    pub plane: Plane,
    pub center: [f64; 2],
    pub sweep: f64,
}

/// The length of a move's path in its three linear coordinates (x a radius, y, z: mm), for a
/// move with an extra-axis entry: a G17/G19 arc's helix, or a straight move's (x, y, z) line.
/// Rotary axes and the B axis are not in it (see `motion`).
pub fn length3(m: &Move, e: &ExtraMove) -> f64 {
    let dy = e.end[0] - e.start[0];
    match e.arc {
        Some(a) => {
            let (s, f, along) = plane_coords(m, e, a.plane);
            let r0 = ((s[0] - a.center[0]).powi(2) + (s[1] - a.center[1]).powi(2)).sqrt();
            let r1 = ((f[0] - a.center[0]).powi(2) + (f[1] - a.center[1]).powi(2)).sqrt();
            let arc = 0.5 * (r0 + r1) * a.sweep.abs();
            (arc * arc + (r1 - r0).powi(2) + along * along).sqrt()
        }
        None => {
            let l = m.length();
            (l * l + dy * dy).sqrt()
        }
    }
}

/// Start and end of a plane arc in the plane's coordinates, and the travel along its normal.
fn plane_coords(m: &Move, e: &ExtraMove, plane: Plane) -> ([f64; 2], [f64; 2], f64) {
    match plane {
        Plane::Xy => ([m.start.x, e.start[0]], [m.end.x, e.end[0]], m.end.y - m.start.y),
        Plane::Yz | Plane::Zx => ([e.start[0], m.start.y], [e.end[0], m.end.y], m.end.x - m.start.x),
    }
}

/// The programmed point (x a radius, y, z; spindle frame, mm) and the extra axes ([`ExtraAxes`])
/// at fraction `t` ∈ [0, 1] of a move's path: the one function every check of a move with extra
/// axes reads. A move without an entry (`e` = `None`) is a move of the lathe's plane with every
/// extra axis at 0; with an entry, the extra axes move linearly with `t`, an XZ move follows its
/// 2D path ([`Move::point_at`]) with y linear, and a G17/G19 arc its [`PlaneArc`] (the angle
/// linear in `t`, the radius and the third coordinate linear too).
pub fn position3(m: &Move, e: Option<&ExtraMove>, t: f64) -> ([f64; 3], ExtraAxes) {
    let Some(e) = e else {
        let p = m.point_at(t);
        return ([p.x, 0.0, p.y], [0.0; 4]);
    };
    let mut axes = [0.0; 4];
    for (k, a) in axes.iter_mut().enumerate() {
        *a = e.start[k] + (e.end[k] - e.start[k]) * t;
    }
    match e.arc {
        Some(a) => {
            let (s, f, _) = plane_coords(m, e, a.plane);
            let (c0, c1) = (a.center[0], a.center[1]);
            let r0 = ((s[0] - c0).powi(2) + (s[1] - c1).powi(2)).sqrt();
            let r1 = ((f[0] - c0).powi(2) + (f[1] - c1).powi(2)).sqrt();
            let r = r0 + (r1 - r0) * t;
            let ang = (s[1] - c1).atan2(s[0] - c0) + a.sweep * t;
            let (u, v) = if t >= 1.0 {
                (f[0], f[1])
            } else if t <= 0.0 {
                (s[0], s[1])
            } else {
                (c0 + r * ang.cos(), c1 + r * ang.sin())
            };
            match a.plane {
                Plane::Xy => {
                    let z = m.start.y + (m.end.y - m.start.y) * t;
                    axes[0] = v;
                    ([u, v, z], axes)
                }
                Plane::Yz | Plane::Zx => {
                    let x = m.start.x + (m.end.x - m.start.x) * t;
                    axes[0] = u;
                    ([x, u, v], axes)
                }
            }
        }
        None => {
            let p = m.point_at(t);
            ([p.x, axes[0], p.y], axes)
        }
    }
}

/// What the interpreter produced.
#[derive(Clone, Debug, Default)]
pub struct Interpretation {
    pub moves: Vec<Move>,
    /// The extra axes and turn-mill modes of the moves that have any, sorted by move index
    /// ([`ExtraMove`]); empty for a program that only turns.
    pub extra: Vec<ExtraMove>,
    /// The spindles and frames the moves refer to ([`Move::state`]).
    pub states: Vec<MoveState>,
    /// `program` and `unsupported` findings (syntax findings stay with the reader).
    pub findings: Vec<Finding>,
    /// The findings not kept in `findings` (at most [`crate::finding::MAX_FINDINGS`] are).
    pub findings_left_out: crate::finding::LeftOut,
    /// Blocks executed (a block in a loop counts each time).
    pub blocks_executed: u64,
}

impl Interpretation {
    /// The extra-axis entry of move `index`, if it has one ([`ExtraMove`]).
    pub fn extra_of(&self, index: usize) -> Option<&ExtraMove> {
        self.extra
            .binary_search_by_key(&index, |e| e.index as usize)
            .ok()
            .map(|k| &self.extra[k])
    }

    /// The spindle during a move.
    pub fn spindle(&self, m: &Move) -> &Spindle {
        &self.states[m.state as usize].spindle
    }

    /// How to turn a move's points back into program coordinates.
    pub fn frame(&self, m: &Move) -> &ProgFrame {
        &self.states[m.state as usize].frame
    }
}

/// Limits that keep a run bounded whatever the program does.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// Most blocks executed before the run stops with a `program` finding (endless loops).
    pub max_blocks: u64,
    /// Deepest subroutine nesting.
    pub max_call_depth: usize,
}

impl Limits {
    /// Enough for any real program: 2 million blocks, or 4 times the program's length.
    pub fn for_program(prog: &Program) -> Limits {
        Limits {
            max_blocks: (prog.len() as u64 * 4).max(2_000_000),
            max_call_depth: 64,
        }
    }
}

/// Interpret a program read by [`crate::gcode::parse`] on a machine.
pub fn interpret(prog: &Program, src: &[u8], machine: &Machine) -> Interpretation {
    interpret_with(prog, src, machine, Limits::for_program(prog))
}

pub fn interpret_with(prog: &Program, src: &[u8], machine: &Machine, limits: Limits) -> Interpretation {
    let mut run = flow::Run::new(prog, src, machine, limits);
    run.moves = Vec::with_capacity(prog.len().min(1 << 22));
    run.run();
    run.finish()
}

pub use flow::STREAM_CHUNK;

/// Moves handed over by [`interpret_streaming`]: the next run of the program's moves.
#[derive(Clone, Copy, Debug)]
pub struct Chunk<'a> {
    /// The index of `moves[0]` in the whole run (the chunks follow each other without a gap).
    pub first: usize,
    pub moves: &'a [Move],
    /// The states made so far: every move's [`Move::state`] indexes this list.
    pub states: &'a [MoveState],
    /// The extra-axis entries of these moves ([`ExtraMove`], index order, indices of the whole
    /// run, each in `first..first + moves.len()`).
    pub extra: &'a [ExtraMove],
}

/// Interpret a program handing its moves to `sink` as they are made (in order, in chunks of
/// about [`STREAM_CHUNK`], each with the states its moves refer to and their extra-axis
/// entries), so a long program's moves are never all in memory. The [`Interpretation`] returned
/// has every field but `moves` and `extra`, which are empty. The moves and entries handed over
/// are exactly those [`interpret`] returns.
pub fn interpret_streaming<'a>(
    prog: &'a Program,
    src: &'a [u8],
    machine: &'a Machine,
    sink: impl FnMut(Chunk<'_>) + 'a,
) -> Interpretation {
    interpret_streaming_by(prog, src, machine, STREAM_CHUNK, sink)
}

/// [`interpret_streaming`] handing the moves over once `chunk` of them are made (at least 1;
/// the moves of one top-level block, a canned cycle's passes, always go over together).
pub fn interpret_streaming_by<'a>(
    prog: &'a Program,
    src: &'a [u8],
    machine: &'a Machine,
    chunk: usize,
    sink: impl FnMut(Chunk<'_>) + 'a,
) -> Interpretation {
    interpret_streaming_limited(prog, src, machine, chunk, Limits::for_program(prog), sink)
}

/// [`interpret_streaming_by`] within `limits`.
pub fn interpret_streaming_limited<'a>(
    prog: &'a Program,
    src: &'a [u8],
    machine: &'a Machine,
    chunk: usize,
    limits: Limits,
    sink: impl FnMut(Chunk<'_>) + 'a,
) -> Interpretation {
    let mut run = flow::Run::new(prog, src, machine, limits);
    run.chunk = chunk.max(1);
    run.moves = Vec::with_capacity(2 * run.chunk.min(STREAM_CHUNK));
    run.sink = Some(Box::new(sink));
    run.run();
    run.finish()
}
