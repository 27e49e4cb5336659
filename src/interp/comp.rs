//! Tool-nose-radius compensation (G41/G42/G40): a stage between the interpreter and the moves.
//!
//! The interpreter hands every move to [`Run::push_move`](super::flow::Run); while compensation
//! is on (or its last moves still wait) the move comes here instead of going straight into the
//! move list. The stage keeps the path of the **nose centre** offset by the nose radius to the
//! side G41 (left) or G42 (right) names, as LinuxCNC's rs274ngc makes it: the entry move ends
//! perpendicular to its own direction (rs274) or to the next block's (Fanuc start-up), outside
//! corners are rounded with an arc about the programmed corner (Fanuc: intersection vectors
//! between lines), inside corners are cut back to the intersection of the offset paths, and the
//! first move after G40 goes from the offset position to the programmed point. A move is held
//! back until the next move decides where it ends (a queue of usually one move, kept across
//! blocks that do not move: the controls' look-ahead). What leaves the stage is the controlled
//! point: the nose centre plus the vector from the centre to the imaginary tip of the tool's
//! tip direction (0 and 9: the centre itself).
//!
//! All geometry is in the plane of the arcs as rs274ngc sees G18: first coordinate `z`, second
//! `x` (a [`P2`] here holds `(z, x)`; [`pl`] swaps to and from the spindle frame's `(x, z)`),
//! so "left" is a quarter turn counter-clockwise in that plane and an arc's `turn` is positive
//! counter-clockwise there (G3). Lengths are mm.
//!
//! When compensation is off and nothing waits, the stage is not consulted at all (the run keeps
//! no `Comp` until the first G41/G42), so programs without compensation pay nothing.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::{Move, MoveKind};
use crate::geom::{P2, V2};
use crate::machine::TurretSide;

/// Angle under which a corner counts as straight (rs274ngc's concave-corner tolerance), radians.
const SMALL: f64 = 0.05;
/// Two numbers this close are equal (rs274ngc's `TOLERANCE_EQUAL`).
const TOLERANCE_EQUAL: f64 = 1e-6;
/// How much more a corrected arc may sweep than the programmed one before it gouges, in mm
/// programs (rs274ngc: 0.0254 there, 0.001 in inch programs).
const ARC_GROWTH_MM: f64 = 0.0254;

/// Which side of the programmed path the tool runs on, seen from +Y.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// How the control makes the start-up and the outside corners between lines.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Style {
    /// LinuxCNC rs274ngc: the entry move ends perpendicular to itself; outside corners get an arc.
    Rs274,
    /// Fanuc/Haas: the start-up block ends perpendicular to the next block; outside corners
    /// between lines take the intersection of the offset lines (at most 90° of turn) or two
    /// vectors along the extended lines (sharper corners).
    Fanuc,
}

/// The vector from the nose centre to the imaginary tip, spindle frame `(x, z)`, for a tip
/// direction (0–9) of a tool of nose radius `r`.
///
/// LinuxCNC (rs274ngc's tool-table orientation), in the X/Z axes:
/// ```text
///   +X  3 8 4
///       7 0 5     (0 and 9: the centre)
///       2 6 1
///          +Z →
/// ```
/// Fanuc/Haas tip codes (the manuals' chart, drawn with +X up, away from the operator — a rear
/// turret), mirrored about the spindle axis on a front turret:
/// ```text
///   +X  2 6 1
///       7 0 5
///       3 8 4
///          +Z →
/// ```
pub(crate) fn tip_vector(dir: u8, r: f64, fanuc: bool, side: TurretSide) -> V2 {
    // LinuxCNC's chart in (x, z) signs.
    let (sx, sz) = match dir {
        1 => (-1.0, 1.0),
        2 => (-1.0, -1.0),
        3 => (1.0, -1.0),
        4 => (1.0, 1.0),
        5 => (0.0, 1.0),
        6 => (-1.0, 0.0),
        7 => (0.0, -1.0),
        8 => (1.0, 0.0),
        _ => (0.0, 0.0),
    };
    // Fanuc's chart is LinuxCNC's mirrored about the Z axis; a front turret mirrors it back.
    let mirror = fanuc && side == TurretSide::Rear;
    let sx = if mirror { -sx } else { sx };
    V2::new(sx * r, sz * r)
}

/// Swap between the spindle frame's `(x, z)` and the comp plane's `(z, x)`.
#[inline]
pub(crate) fn pl(p: P2) -> P2 {
    P2::new(p.y, p.x)
}

fn unit(angle: f64) -> V2 {
    V2::new(angle.cos(), angle.sin())
}

fn angle_of(v: V2) -> f64 {
    v.y.atan2(v.x)
}

/// Tool inside an arc turning `turn` (rs274ngc's test).
fn inside(side: Side, turn: i32) -> bool {
    (side == Side::Left && turn > 0) || (side == Side::Right && turn < 0)
}

/// Signed angle (counter-clockwise positive) an arc turning `turn` travels from `a` to `b`
/// about `c`, all in the plane; `turn` counts full or partial circles (rs274ngc's rule).
pub(crate) fn find_turn(a: P2, c: P2, turn: i32, b: P2) -> f64 {
    if turn == 0 {
        return 0.0;
    }
    let mut alpha = angle_of(a - c);
    let mut beta = angle_of(b - c);
    if turn > 0 {
        if beta <= alpha {
            beta += TAU;
        }
        beta - alpha + (turn - 1) as f64 * TAU
    } else {
        if alpha <= beta {
            alpha += TAU;
        }
        beta - alpha + (turn + 1) as f64 * TAU
    }
}

/// A G41/G42 or G40 as the stage takes it: from a block as it runs, or from a G70's profile
/// block, replayed before the move of that block (the cycle expands with the stage aside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Word {
    /// G41/G42: the side, the nose radius (mm; negative swaps the side), the vector from the
    /// nose centre to the imaginary tip (spindle frame), the control's style, mm per program unit.
    On {
        side: Side,
        radius: f64,
        tip: V2,
        style: Style,
        unit: f64,
    },
    /// G40.
    Off,
}

#[derive(Clone, Copy, Debug)]
enum QKind {
    /// A line or rapid; `dir` is the direction it was made in (a correction that reverses it
    /// gouges).
    Straight { rapid: bool, dir: V2 },
    /// An arc of the nose centre about `center`; `original` is the angle it sweeps as made
    /// (0 for a corner arc, whose end never moves).
    Arc { center: P2, turn: i32, original: f64 },
    /// A move that is not a motion (dwell): kept in order.
    Other,
}

#[derive(Clone, Copy, Debug)]
struct Queued {
    kind: QKind,
    /// Nose-centre end point, plane.
    end: P2,
    /// The programmed move it comes from (its line, feed, state, tool).
    m: Move,
}

/// The compensation stage of one run.
#[derive(Clone, Debug)]
pub(crate) struct Comp {
    side: Option<Side>,
    radius: f64,
    /// Nose centre → controlled point, plane `(z, x)`.
    tip: V2,
    /// The tool's direction is a lathe tip (not 0 or 9).
    lathe_tip: bool,
    style: Style,
    /// mm per program unit (rs274ngc's tolerances are in program units).
    unit: f64,
    first: bool,
    /// Nose centre now (after the queued moves), plane.
    cur: P2,
    /// Programmed point now, plane.
    prog: P2,
    queue: Vec<Queued>,
    /// Where the queued moves start (a correction is measured from here).
    endpoint: Option<P2>,
    /// Where the controlled point is after the last move that left the stage, spindle frame.
    last_out: Option<P2>,
    /// Compensation was cancelled: the next move starts where the last one left the tool.
    resume: bool,
    /// A Fanuc start-up block waits in the queue for the next block.
    entry_pending: bool,
}

impl Default for Comp {
    fn default() -> Self {
        Comp::new()
    }
}

impl Comp {
    pub(crate) fn new() -> Comp {
        Comp {
            side: None,
            radius: 0.0,
            tip: V2::zeros(),
            lathe_tip: false,
            style: Style::Rs274,
            unit: 1.0,
            first: true,
            cur: P2::origin(),
            prog: P2::origin(),
            queue: Vec::new(),
            endpoint: None,
            last_out: None,
            resume: false,
            entry_pending: false,
        }
    }

    /// The side compensation is on (none after G40).
    pub(crate) fn side(&self) -> Option<Side> {
        self.side
    }

    /// Compensation is on (G41/G42 in force).
    pub(crate) fn is_on(&self) -> bool {
        self.side.is_some()
    }

    /// Compensation is on with a nose radius: moves are offset.
    pub(crate) fn offsets(&self) -> bool {
        self.side.is_some() && self.radius > 0.0
    }

    /// rs274ngc reads a G70's profile (after the cycle block's own move) by setting its current
    /// point to the end of each profile block; under compensation its current point is the
    /// nose centre, so the cycle's next move takes its corner (and, when that move goes nowhere,
    /// its end) from the profile's last point `p` (spindle frame) as though the nose stood
    /// there. The moves that wait keep their ends.
    pub(crate) fn profile_read(&mut self, p: P2) {
        if self.offsets() && !self.first && self.style == Style::Rs274 {
            self.cur = pl(p);
        }
    }

    /// Moves must come through the stage: compensation is on, moves wait, or the next move
    /// starts where a cancelled compensation left the tool.
    pub(crate) fn engaged(&self) -> bool {
        self.side.is_some() || !self.queue.is_empty() || self.resume
    }

    /// G41/G42: compensation on to `side` with a nose radius (mm, negative swaps the side) and
    /// the vector from nose centre to imaginary tip (spindle frame).
    pub(crate) fn on(&mut self, side: Side, radius: f64, tip: V2, style: Style, unit: f64) -> Result<(), String> {
        if self.side.is_some() {
            return Err("nose radius compensation is already on: cancel it with G40 first".into());
        }
        let (side, radius) = if radius < 0.0 {
            (if side == Side::Left { Side::Right } else { Side::Left }, -radius)
        } else {
            (side, radius)
        };
        if !self.resume {
            // Moves made while the stage stood aside (after G40 and the move that left the
            // offset) went where the program put them: the start-up starts where the tool is.
            self.last_out = None;
        }
        self.side = Some(side);
        self.radius = radius;
        self.tip = V2::new(tip.y, tip.x);
        self.lathe_tip = tip != V2::zeros();
        self.style = style;
        self.unit = unit;
        self.first = true;
        Ok(())
    }

    /// G40: compensation off. The last move keeps its offset end; the next move starts there.
    pub(crate) fn off(&mut self, out: &mut Vec<Move>) -> Result<(), String> {
        let mut res = Ok(());
        if self.side.is_some() && self.radius > 0.0 && !self.first {
            res = self.move_endpoint_and_flush(self.cur, out);
            self.dequeue(out);
            self.resume = true;
        }
        self.side = None;
        self.first = true;
        self.entry_pending = false;
        res
    }

    /// Take a G41/G42/G40 word. A Fanuc G41/G42 while compensation is on switches: a new
    /// start-up from where the tool is. An error is the control's; when cancelling failed,
    /// compensation has stopped (what waited has left as it was).
    pub(crate) fn word(&mut self, w: Word, out: &mut Vec<Move>) -> Result<(), String> {
        let cancel = match w {
            Word::Off => true,
            Word::On { style, .. } => style == Style::Fanuc && self.is_on(),
        };
        if cancel {
            if let Err(msg) = self.off(out) {
                self.abandon(out);
                return Err(msg);
            }
        }
        match w {
            Word::On {
                side,
                radius,
                tip,
                style,
                unit,
            } => self.on(side, radius, tip, style, unit),
            Word::Off => Ok(()),
        }
    }

    /// Let every waiting move out (end of the program, or before a canned cycle runs).
    pub(crate) fn flush(&mut self, out: &mut Vec<Move>) {
        self.dequeue(out);
    }

    /// Stop compensating after an error: what waits leaves as it is, and the next move starts
    /// where the tool is.
    pub(crate) fn abandon(&mut self, out: &mut Vec<Move>) {
        self.dequeue(out);
        self.side = None;
        self.first = true;
        self.entry_pending = false;
        self.resume = self.last_out.is_some();
    }

    /// A canned cycle ran on the programmed profile: compensation starts again with the next
    /// move as it does after G41/G42 (the tool is where the cycle left it).
    pub(crate) fn restart(&mut self) {
        self.queue.clear();
        self.endpoint = None;
        self.first = true;
        self.entry_pending = false;
        self.last_out = None;
    }

    /// Where the next move must start when compensation was just cancelled (and forget it):
    /// for moves made past the stage (a canned cycle's).
    pub(crate) fn take_resume(&mut self) -> Option<P2> {
        if !self.resume {
            return None;
        }
        self.resume = false;
        self.last_out.take()
    }

    /// The controlled point after the last move that left the stage (spindle frame).
    pub(crate) fn last_out(&self) -> Option<P2> {
        self.last_out
    }

    /// Take one programmed move (spindle frame; an arc's sweep as the interpreter made it).
    /// Moves that leave the stage are appended to `out`. An error is the control's: the move is
    /// refused and compensation stops (the caller reports it at the move's line).
    pub(crate) fn take(&mut self, mut m: Move, out: &mut Vec<Move>) -> Result<(), String> {
        let motion = matches!(m.kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. });
        if !motion {
            if self.queue.is_empty() {
                if let Some(p) = self.last_out {
                    if matches!(m.kind, MoveKind::Dwell { .. }) {
                        m.start = p;
                        m.end = p;
                    }
                }
                out.push(m);
            } else {
                self.queue.push(Queued {
                    kind: QKind::Other,
                    end: self.cur,
                    m,
                });
            }
            return Ok(());
        }
        let Some(side) = self.side.filter(|_| self.radius > 0.0) else {
            // Off (or a zero radius): the move as programmed, from where the tool is.
            self.dequeue(out);
            if self.resume {
                if let Some(p) = self.last_out {
                    m.start = p;
                }
                self.resume = false;
                if let MoveKind::Arc { center, sweep } = m.kind {
                    // The arc's start moved: keep its direction and full turns about the centre.
                    let turn = if sweep > 0.0 { -1 } else { 1 } * (sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i32;
                    let s = -find_turn(pl(m.start), pl(center), turn, pl(m.end));
                    m.kind = MoveKind::Arc { center, sweep: s };
                }
            }
            self.last_out = Some(m.end);
            out.push(m);
            return Ok(());
        };
        if self.first {
            self.cur = pl(m.start);
            self.prog = pl(m.start);
            if self.last_out.is_none() {
                self.last_out = Some(m.start);
            }
        }
        let p = pl(m.end);
        match m.kind {
            MoveKind::Arc { center, sweep } => {
                // rs274ngc's turn: counter-clockwise in (z, x) is clockwise in (x, z).
                let n = (sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i32;
                let turn = if sweep > 0.0 { -n } else { n };
                if self.first {
                    self.arc_comp1(side, m, p, pl(center), turn)
                } else {
                    self.arc_comp2(side, m, p, pl(center), turn, out)
                }
            }
            _ => {
                let rapid = m.kind == MoveKind::Rapid;
                if self.first {
                    self.straight_comp1(side, m, p, rapid)
                } else {
                    self.straight_comp2(side, m, p, rapid, out)
                }
            }
        }
    }

    fn enqueue(&mut self, kind: QKind, end: P2, m: Move) {
        self.queue.push(Queued { kind, end, m });
    }

    /// Let the waiting moves leave, as controlled points.
    fn dequeue(&mut self, out: &mut Vec<Move>) {
        self.endpoint = None;
        if self.queue.is_empty() {
            return;
        }
        for q in std::mem::take(&mut self.queue) {
            let start = self.last_out.unwrap_or(q.m.start);
            let end = pl(q.end + self.tip);
            let mut m = q.m;
            match q.kind {
                QKind::Straight { rapid, .. } => {
                    m.kind = if rapid { MoveKind::Rapid } else { MoveKind::Line };
                    m.start = start;
                    m.end = end;
                }
                QKind::Arc { center, turn, .. } => {
                    let c = center + self.tip;
                    let sweep = -find_turn(pl(start), c, turn, pl(end));
                    m.kind = MoveKind::Arc { center: pl(c), sweep };
                    m.start = start;
                    m.end = end;
                }
                QKind::Other => {
                    if matches!(m.kind, MoveKind::Dwell { .. }) {
                        m.start = start;
                        m.end = start;
                    }
                    out.push(m);
                    continue;
                }
            }
            self.last_out = Some(end);
            out.push(m);
        }
    }

    fn set_endpoint(&mut self, p: P2) {
        self.endpoint = Some(p);
    }

    /// Move the end of every waiting move to `x` (a corner decided where they stop), refusing a
    /// correction that would reverse a line or lengthen an arc: that gouges.
    fn move_endpoint_and_flush(&mut self, x: P2, out: &mut Vec<Move>) -> Result<(), String> {
        if self.queue.is_empty() {
            return Ok(());
        }
        let endpoint = self.endpoint;
        let unit = self.unit;
        for q in &mut self.queue {
            match q.kind {
                QKind::Arc { center, turn, original } => {
                    let r1 = (q.end - center).norm();
                    let r2 = (x - center).norm();
                    if (r1 - r2).abs() > 0.01 * unit {
                        return Err(format!(
                            "nose radius compensation made an arc whose radii differ ({} and {} mm)",
                            round4(r1),
                            round4(r2)
                        ));
                    }
                    if let Some(e) = endpoint {
                        let l2 = find_turn(e, center, turn, x);
                        // rs274ngc compares the angles with its length tolerance in program
                        // units (0.001 in, 0.0254 mm), as radians.
                        let tol = if unit > 1.0 { 0.001 } else { ARC_GROWTH_MM };
                        if original != 0.0 && l2.abs() > original.abs() + tol {
                            return Err(
                                "the arc into this inside corner cannot be followed by the tool nose without gouging"
                                    .into(),
                            );
                        }
                    }
                    q.end = x;
                }
                QKind::Straight { dir, .. } => {
                    if let Some(e) = endpoint {
                        if dir.dot(&(x - e)) < 0.0 {
                            return Err(
                                "the move into this inside corner is shorter than the nose radius needs: the tool nose would reverse along it and gouge"
                                    .into(),
                            );
                        }
                    }
                    q.end = x;
                }
                QKind::Other => {}
            }
        }
        self.dequeue(out);
        self.set_endpoint(x);
        Ok(())
    }

    fn straight_comp1(&mut self, side: Side, m: Move, p: P2, rapid: bool) -> Result<(), String> {
        let r = self.radius;
        let c = self.cur;
        let distance = (p - c).norm();
        // rs274ngc refuses a short entry; a Fanuc start-up block may be any length (CAM lead-ins
        // are often shorter than the nose radius): the vector is taken on all the same.
        if distance <= r && self.style == Style::Rs274 {
            return Err(format!(
                "the compensation entry move ({} mm) is not longer than the nose radius ({} mm)",
                round4(distance),
                round4(r)
            ));
        }
        let alpha = angle_of(p - c) + if side == Side::Left { FRAC_PI_2 } else { -FRAC_PI_2 };
        let end = p + r * unit(alpha);
        self.set_endpoint(c);
        // rs274ngc records the entry's offset direction as its direction (a later correction
        // is checked against that); the Fanuc start-up checks against the move itself.
        let dir = if self.style == Style::Fanuc { p - c } else { unit(alpha) };
        self.enqueue(QKind::Straight { rapid, dir }, end, m);
        self.entry_pending = self.style == Style::Fanuc;
        self.first = false;
        self.cur = end;
        self.prog = p;
        Ok(())
    }

    /// Fanuc start-up: the start-up block waits until the next block says which way the offset
    /// vector points at its start; then it ends there.
    fn fanuc_startup(&mut self, start_normal: V2, out: &mut Vec<Move>) -> Result<(), String> {
        let target = self.prog + self.radius * start_normal;
        self.entry_pending = false;
        // The start-up block goes wherever the vector puts its end (a lead-in shorter than the
        // nose may run backward): no reversal check for it.
        self.endpoint = None;
        self.move_endpoint_and_flush(target, out)?;
        self.cur = target;
        Ok(())
    }

    fn straight_comp2(&mut self, side: Side, m: Move, p: P2, rapid: bool, out: &mut Vec<Move>) -> Result<(), String> {
        let r = self.radius;
        let op = self.prog;
        if p == op {
            // No motion in the plane: the nose stays where it is.
            let c = self.cur;
            self.enqueue(
                QKind::Straight {
                    rapid,
                    dir: V2::zeros(),
                },
                c,
                m,
            );
            return Ok(());
        }
        let gamma = if side == Side::Left { FRAC_PI_2 } else { -FRAC_PI_2 };
        if self.style == Style::Fanuc && self.startup_waiting() {
            let a = angle_of(p - op);
            self.fanuc_startup(unit(a + gamma), out)?;
        }
        let c = self.cur;
        let mut theta = angle_of(c - op);
        let mut alpha = angle_of(p - op);
        let beta = if side == Side::Left {
            if theta < alpha {
                theta += TAU;
            }
            theta - alpha - FRAC_PI_2
        } else {
            if alpha < theta {
                alpha += TAU;
            }
            alpha - theta - FRAC_PI_2
        };
        let end = p + r * unit(alpha + gamma);
        let mid = op + r * unit(alpha + gamma);
        let front_arc = self.queue.first().and_then(|q| match q.kind {
            QKind::Arc { center, turn, .. } => Some((q.end, center, turn)),
            _ => None,
        });
        let concave = !(-SMALL..=PI + SMALL).contains(&beta)
            || (beta > PI - SMALL
                && front_arc
                    .is_some_and(|(_, _, turn)| (side == Side::Right && turn > 0) || (side == Side::Left && turn < 0)));
        if !concave && beta > SMALL {
            let front_straight = matches!(self.queue.first().map(|q| q.kind), Some(QKind::Straight { .. }));
            if self.style == Style::Fanuc && front_straight {
                // Fanuc: no arc; the intersection of the offset lines, or two vectors along the
                // extended lines at a corner sharper than 90°.
                let n1 = (c - op) / r;
                let n2 = unit(alpha + gamma);
                if beta <= FRAC_PI_2 + 1e-9 {
                    let x = op + r * (n1 + n2) / (1.0 + n1.dot(&n2));
                    self.move_endpoint_and_flush(x, out)?;
                } else {
                    let t1 = unit(theta - gamma);
                    let t2 = unit(alpha);
                    let p1 = c + r * t1;
                    let p2 = mid - r * t2;
                    self.move_endpoint_and_flush(p1, out)?;
                    self.enqueue(QKind::Straight { rapid, dir: p2 - p1 }, p2, m);
                    self.dequeue(out);
                    self.set_endpoint(p2);
                }
            } else {
                self.move_endpoint_and_flush(c, out)?;
                if !rapid {
                    let turn = if side == Side::Left { -1 } else { 1 };
                    self.enqueue(
                        QKind::Arc {
                            center: op,
                            turn,
                            original: 0.0,
                        },
                        mid,
                        m,
                    );
                } else {
                    self.enqueue(
                        QKind::Straight {
                            rapid,
                            dir: V2::zeros(),
                        },
                        mid,
                        m,
                    );
                }
                self.dequeue(out);
                self.set_endpoint(mid);
            }
        } else if concave {
            match front_arc {
                None => {
                    let halfcorner = (beta + PI) / 2.0;
                    if halfcorner == 0.0 {
                        return Err("a zero-degree inside corner cannot be compensated".into());
                    }
                    let retreat = r / halfcorner.tan();
                    let mid = c + retreat * unit(theta + gamma);
                    self.move_endpoint_and_flush(mid, out)?;
                }
                Some((prev_end, prev_center, prev_turn)) => {
                    let oldrad = (prev_center - prev_end).norm();
                    let base_dir = angle_of(p - op);
                    let th = if prev_turn > 0 {
                        base_dir + FRAC_PI_2
                    } else {
                        base_dir - FRAC_PI_2
                    };
                    let phi = angle_of(prev_center - op);
                    let ins = inside(side, prev_turn);
                    let oldrad_uncomp = if ins { oldrad + r } else { oldrad - r };
                    let d = oldrad_uncomp * (th - phi).cos();
                    let l = if ins { (d - r) / oldrad } else { (d + r) / oldrad };
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(
                            "the corner from this arc into the line is too tight for the tool nose: it would gouge"
                                .into(),
                        );
                    }
                    let angle = match (ins, prev_turn > 0) {
                        (true, true) | (false, false) => -l.acos() + th + PI,
                        _ => l.acos() + th + PI,
                    };
                    let mid = prev_center + oldrad * unit(angle);
                    self.move_endpoint_and_flush(mid, out)?;
                }
            }
        } else {
            // Straight on (or a tangent arc into the line).
            self.dequeue(out);
            self.set_endpoint(c);
        }
        self.enqueue(QKind::Straight { rapid, dir: p - op }, end, m);
        self.cur = end;
        self.prog = p;
        Ok(())
    }

    /// A Fanuc start-up block waits for the next block to say where it ends.
    fn startup_waiting(&self) -> bool {
        self.style == Style::Fanuc && self.entry_pending
    }

    fn arc_comp1(&mut self, side: Side, m: Move, p: P2, center: P2, turn: i32) -> Result<(), String> {
        let r = self.radius;
        let c = self.cur;
        if self.style == Style::Fanuc {
            return Err("the start-up of nose radius compensation cannot be an arc (G2/G3): start it on a line".into());
        }
        if (p - c).norm() <= r {
            return Err(format!(
                "the compensation entry arc ends {} mm away, not farther than the nose radius ({} mm)",
                round4((p - c).norm()),
                round4(r)
            ));
        }
        let gamma = if inside(side, turn) {
            angle_of(center - p)
        } else {
            angle_of(p - center)
        };
        self.first = false;
        self.prog = p;
        let end = p + r * unit(gamma);
        // The nose-centre arc runs from where the nose is to the offset end: its centre lies on
        // the line from the end through the programmed centre, equally far from both ends.
        let b_len = (c - end).norm() / 2.0;
        let ab = angle_of(center - end);
        let a = angle_of(c - end) - ab;
        if a.cos().abs() < TOLERANCE_EQUAL {
            return Err(self.arc_too_small());
        }
        let c_len = b_len / a.cos();
        let new_center = end + c_len * unit(ab);
        if self.lathe_tip {
            // The controlled point first moves to where the nose centre's path begins.
            self.enqueue(
                QKind::Straight {
                    rapid: false,
                    dir: V2::zeros(),
                },
                c,
                m,
            );
        }
        self.set_endpoint(c);
        let original = find_turn(c, new_center, turn, end);
        self.enqueue(
            QKind::Arc {
                center: new_center,
                turn,
                original,
            },
            end,
            m,
        );
        self.cur = end;
        Ok(())
    }

    fn arc_too_small(&self) -> String {
        format!(
            "the nose radius ({} mm) is not smaller than the radius of this arc, on the side the tool runs inside it",
            round4(self.radius)
        )
    }

    fn arc_comp2(
        &mut self,
        side: Side,
        m: Move,
        p: P2,
        center: P2,
        turn: i32,
        out: &mut Vec<Move>,
    ) -> Result<(), String> {
        let r = self.radius;
        let op = self.prog;
        let arc_radius = (center - p).norm();
        let tool_inside = inside(side, turn);
        let fanuc = self.style == Style::Fanuc;
        if tool_inside && (arc_radius <= r && !fanuc || arc_radius < r - 1e-6) {
            return Err(self.arc_too_small());
        }
        if fanuc && tool_inside && arc_radius <= r + 1e-6 {
            // A fillet of exactly the nose radius: the nose centre stands at the arc's centre
            // (the offset arc has no length); the corners around it are made from there.
            if self.startup_waiting() {
                self.fanuc_startup(unit(angle_of(center - op)), out)?;
            }
            self.move_endpoint_and_flush(center, out)?;
            self.enqueue(
                QKind::Straight {
                    rapid: false,
                    dir: V2::zeros(),
                },
                center,
                m,
            );
            self.cur = center;
            self.prog = p;
            return Ok(());
        }
        if self.startup_waiting() {
            let d = angle_of(center - op);
            let n = if tool_inside { unit(d) } else { -unit(d) };
            self.fanuc_startup(n, out)?;
        }
        let c = self.cur;
        let mut theta = angle_of(c - op);
        theta = if side == Side::Left {
            theta - FRAC_PI_2
        } else {
            theta + FRAC_PI_2
        };
        let mut delta = angle_of(center - op);
        let alpha = if turn > 0 { delta - FRAC_PI_2 } else { delta + FRAC_PI_2 };
        let mut beta = if side == Side::Left {
            theta - alpha
        } else {
            alpha - theta
        };
        if beta > 1.5 * PI {
            beta -= TAU;
        } else if beta < -FRAC_PI_2 {
            beta += TAU;
        }
        let gamma = if tool_inside {
            angle_of(center - p)
        } else {
            delta += PI;
            angle_of(p - center)
        };
        let new_end = p + r * unit(gamma);
        let original = find_turn(op, center, turn, p);
        let main = QKind::Arc { center, turn, original };
        if !(-SMALL..=PI + SMALL).contains(&beta) || ((beta - PI).abs() < SMALL && !tool_inside) {
            // Concave: cut the waiting move back to where the offset paths meet.
            let front_arc = self.queue.first().and_then(|q| match q.kind {
                QKind::Arc { center, turn, .. } => Some((q.end, center, turn)),
                _ => None,
            });
            let mid = match front_arc {
                None => {
                    let cy = arc_radius * (beta - FRAC_PI_2).sin();
                    let (dist, toward) = if tool_inside {
                        (arc_radius - r, cy + r)
                    } else {
                        (arc_radius + r, cy - r)
                    };
                    let l = toward / dist;
                    if !(-1.0..=1.0).contains(&l) {
                        return Err(
                            "the arc in this inside corner cannot be reached by the tool nose without gouging".into(),
                        );
                    }
                    let angle = match (tool_inside, turn > 0) {
                        (true, true) => theta + l.asin(),
                        (true, false) => theta - l.asin(),
                        (false, true) => theta + PI - l.asin(),
                        (false, false) => theta + PI + l.asin(),
                    };
                    center + dist * unit(angle)
                }
                Some((prev_end, prev_center, prev_turn)) => {
                    let oldrad = (prev_center - prev_end).norm();
                    let newrad = if tool_inside { arc_radius - r } else { arc_radius + r };
                    let arc_cc = (prev_center - center).norm();
                    if oldrad == 0.0 || arc_cc == 0.0 {
                        return Err(
                            "two arcs with the same centre meet in a corner: nose radius compensation cannot join them"
                                .into(),
                        );
                    }
                    let a = (oldrad * oldrad + arc_cc * arc_cc - newrad * newrad) / (2.0 * oldrad * arc_cc);
                    if !(-1.0..=1.0).contains(&a) {
                        return Err(
                            "the corner between these arcs is too tight for the tool nose: it would gouge".into(),
                        );
                    }
                    let pullback = a.acos();
                    let cc_dir = angle_of(center - prev_center);
                    let dir = if inside(side, prev_turn) == (turn > 0) {
                        cc_dir + pullback
                    } else {
                        cc_dir - pullback
                    };
                    prev_center + oldrad * unit(dir)
                }
            };
            self.move_endpoint_and_flush(mid, out)?;
            self.enqueue(main, new_end, m);
        } else if beta > SMALL {
            // Convex: an arc about the programmed corner, then the arc.
            let mid = op + r * unit(delta);
            self.dequeue(out);
            let t = if side == Side::Left { -1 } else { 1 };
            self.enqueue(
                QKind::Arc {
                    center: op,
                    turn: t,
                    original: 0.0,
                },
                mid,
                m,
            );
            self.dequeue(out);
            self.set_endpoint(mid);
            self.enqueue(main, new_end, m);
        } else {
            self.dequeue(out);
            self.set_endpoint(c);
            self.enqueue(main, new_end, m);
        }
        self.prog = p;
        self.cur = new_end;
        Ok(())
    }
}

fn round4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::Feed;

    const R: f64 = 0.8;

    /// A programmed move in the spindle frame (x radius, z).
    fn mv(kind: MoveKind, start: (f64, f64), end: (f64, f64), line: u32) -> Move {
        Move {
            kind,
            line,
            n: None,
            profile_line: 0,
            start: P2::new(start.0, start.1),
            end: P2::new(end.0, end.1),
            tip: V2::zeros(),
            station: 1,
            feed: Feed::PerMinute(100.0),
            state: 0,
        }
    }

    fn line(start: (f64, f64), end: (f64, f64), n: u32) -> Move {
        mv(MoveKind::Line, start, end, n)
    }

    fn close(p: P2, x: f64, z: f64) -> bool {
        (p.x - x).abs() < 1e-9 && (p.y - z).abs() < 1e-9
    }

    /// Run moves through compensation (G42 unless `left`), then G40 and the end of the program.
    fn run(style: Style, left: bool, tip: V2, moves: &[Move]) -> Vec<Move> {
        let mut c = Comp::new();
        let side = if left { Side::Left } else { Side::Right };
        c.on(side, R, tip, style, 1.0).unwrap();
        let mut out = Vec::new();
        for m in moves {
            c.take(*m, &mut out).unwrap();
        }
        c.off(&mut out).unwrap();
        c.flush(&mut out);
        out
    }

    /// rs274's G70 under G42 (lathe_g70_71_demo.ngc, worked by hand with r 0.8, no tip): the
    /// cycle block's rapid from X15 Z-25 to X15 Z3 is the entry (nose centre at X14.2 Z3); reading
    /// the profile puts rs274's current point at the profile's end X15 Z-20; the first pass's rapid
    /// to the start point, which goes nowhere as programmed, takes the nose there, and the rapid
    /// toward the axis then runs straight on from it (no corner), so the entry keeps its end.
    /// Without the reading the rapid toward the axis would make an inside corner at Z2.2.
    #[test]
    fn a_g70_profile_read_moves_the_nose_to_the_profile_end() {
        let moves = [
            mv(MoveKind::Rapid, (15.0, -25.0), (15.0, 3.0), 1),
            mv(MoveKind::Rapid, (15.0, 3.0), (15.0, 3.0), 1),
            mv(MoveKind::Rapid, (15.0, 3.0), (5.0, 3.0), 1),
        ];
        let ends = |read: bool, style: Style| {
            let mut c = Comp::new();
            c.on(Side::Right, R, V2::zeros(), style, 1.0).unwrap();
            let mut out = Vec::new();
            for (k, m) in moves.iter().enumerate() {
                if read && k == 1 {
                    c.profile_read(P2::new(15.0, -20.0));
                }
                c.take(*m, &mut out).unwrap();
            }
            c.off(&mut out).unwrap();
            c.flush(&mut out);
            out.iter().map(|m| m.end).collect::<Vec<_>>()
        };
        let e = ends(true, Style::Rs274);
        assert_eq!(e.len(), 3, "{e:?}");
        assert!(close(e[0], 14.2, 3.0), "{e:?}");
        assert!(close(e[1], 15.0, -20.0), "{e:?}");
        assert!(close(e[2], 5.0, 2.2), "{e:?}");
        // Without the reading: an inside corner where the offsets meet, the nose never behind Z0.
        let e = ends(false, Style::Rs274);
        assert!(close(e[0], 14.2, 2.2), "{e:?}");
        assert!(e.iter().all(|p| p.y > 0.0), "{e:?}");
        // A Fanuc G70 reads no profile so: the reading changes nothing there.
        assert_eq!(ends(true, Style::Fanuc), ends(false, Style::Fanuc));
    }

    #[test]
    fn tip_vectors_follow_the_fanuc_and_linuxcnc_charts() {
        let rear = TurretSide::Rear;
        let front = TurretSide::Front;
        // Fanuc tip 3 (OD turning toward the chuck): the tip is below and left of the centre.
        assert_eq!(tip_vector(3, 1.0, true, rear), V2::new(-1.0, -1.0));
        // On a front turret the operator's chart is mirrored about the spindle axis.
        assert_eq!(tip_vector(3, 1.0, true, front), V2::new(1.0, -1.0));
        assert_eq!(tip_vector(2, 1.0, true, rear), V2::new(1.0, -1.0));
        assert_eq!(tip_vector(6, 1.0, true, rear), V2::new(1.0, 0.0));
        assert_eq!(tip_vector(8, 1.0, true, rear), V2::new(-1.0, 0.0));
        // LinuxCNC's orientations are fixed in its X/Z axes (rs274ngc), whatever the turret.
        assert_eq!(tip_vector(2, 1.0, false, rear), V2::new(-1.0, -1.0));
        assert_eq!(tip_vector(2, 1.0, false, front), V2::new(-1.0, -1.0));
        assert_eq!(tip_vector(5, 1.0, false, rear), V2::new(0.0, 1.0));
        for dir in [0, 9] {
            assert_eq!(tip_vector(dir, 1.0, true, rear), V2::zeros());
            assert_eq!(tip_vector(dir, 1.0, false, rear), V2::zeros());
        }
    }

    /// Worked by hand: G42, tip 3, r 0.8 on an OD at radius 10 toward the chuck. The nose centre
    /// runs at radius 10.8; the imaginary tip (centre − (0.8, 0.8)) at radius 10, the programmed
    /// diameter, 0.8 mm behind the centre in z.
    #[test]
    fn od_line_with_tip_3_runs_at_the_programmed_diameter() {
        let tip = tip_vector(3, R, true, TurretSide::Rear);
        let moves = [line((15.0, 5.0), (10.0, 1.0), 1), line((10.0, 1.0), (10.0, -10.0), 2)];
        let out = run(Style::Fanuc, false, tip, &moves);
        assert_eq!(out.len(), 2, "{out:?}");
        // Fanuc start-up: the offset at the end of the start-up block is perpendicular to the
        // next block (+x for a cut toward -z with the tool on +x).
        assert!(close(out[0].start, 15.0, 5.0));
        assert!(close(out[0].end, 10.0, 0.2), "{:?}", out[0].end);
        assert!(close(out[1].end, 10.0, -10.8), "{:?}", out[1].end);
        // rs274ngc: the entry ends perpendicular to the entry move itself, then the next block
        // turns toward the tool's side (an inside corner), so the entry is cut back to where its
        // offset line meets the offset of the cut: radius 10.8, 0.8 mm from the entry's line.
        let out = run(Style::Rs274, false, V2::zeros(), &moves);
        assert_eq!(out.len(), 2, "{out:?}");
        let e = out[0].end;
        assert!((e.x - 10.8).abs() < 1e-9, "{e:?}");
        let d = V2::new(-5.0, -4.0).normalize();
        let off = e - P2::new(10.0, 1.0);
        assert!(((off.x * d.y - off.y * d.x).abs() - R).abs() < 1e-9, "{e:?}");
        assert!(close(out[1].end, 10.8, -10.0));
    }

    /// rs274ngc: an outside corner is rounded with an arc of the nose radius about the
    /// programmed corner; Fanuc takes the intersection of the offset lines.
    #[test]
    fn outside_corner_is_an_arc_for_rs274_and_an_intersection_for_fanuc() {
        // Toward the chuck at radius 10, then straight down a face to radius 5 (convex).
        let moves = [
            line((15.0, 5.0), (10.0, 1.0), 1),
            line((10.0, 1.0), (10.0, -10.0), 2),
            line((10.0, -10.0), (5.0, -10.0), 3),
        ];
        let out = run(Style::Rs274, false, V2::zeros(), &moves);
        let arc = out
            .iter()
            .find(|m| matches!(m.kind, MoveKind::Arc { .. }))
            .expect("a corner arc");
        let MoveKind::Arc { center, sweep } = arc.kind else {
            unreachable!()
        };
        assert!(close(center, 10.0, -10.0));
        assert!(close(arc.start, 10.8, -10.0) && close(arc.end, 10.0, -10.8), "{arc:?}");
        assert!((sweep.abs() - FRAC_PI_2).abs() < 1e-9);
        assert_eq!(arc.line, 3, "the corner arc belongs to the block that turns");
        let last = out.last().unwrap();
        assert!(close(last.end, 5.0, -10.8));
        let out = run(Style::Fanuc, false, V2::zeros(), &moves);
        assert!(out.iter().all(|m| !matches!(m.kind, MoveKind::Arc { .. })));
        assert!(close(out[1].end, 10.8, -10.8), "{:?}", out[1].end);
    }

    /// An inside corner: both controls stop where the two offset lines meet.
    #[test]
    fn inside_corner_stops_where_the_offsets_meet() {
        // Toward the chuck at radius 10, then up a shoulder to radius 15 (concave).
        let moves = [
            line((15.0, 5.0), (10.0, 1.0), 1),
            line((10.0, 1.0), (10.0, -10.0), 2),
            line((10.0, -10.0), (15.0, -10.0), 3),
        ];
        for style in [Style::Rs274, Style::Fanuc] {
            let out = run(style, false, V2::zeros(), &moves);
            assert_eq!(out.len(), 3, "{out:?}");
            assert!(close(out[1].end, 10.8, -9.2), "{style:?}: {:?}", out[1].end);
            assert!(close(out[2].end, 15.0, -9.2), "{style:?}: {:?}", out[2].end);
        }
    }

    /// A move that does not move in the plane waits with the others (look-ahead across it).
    #[test]
    fn a_dwell_between_moves_does_not_break_the_corner() {
        let dwell = mv(MoveKind::Dwell { seconds: 1.0 }, (10.0, -10.0), (10.0, -10.0), 3);
        let moves = [
            line((15.0, 5.0), (10.0, 1.0), 1),
            line((10.0, 1.0), (10.0, -10.0), 2),
            dwell,
            line((10.0, -10.0), (15.0, -10.0), 4),
        ];
        let out = run(Style::Rs274, false, V2::zeros(), &moves);
        assert_eq!(out.len(), 4, "{out:?}");
        assert!(close(out[1].end, 10.8, -9.2));
        assert!(matches!(out[2].kind, MoveKind::Dwell { .. }) && close(out[2].start, 10.8, -9.2));
    }

    #[test]
    fn inside_arc_smaller_than_the_nose_is_refused() {
        let mut c = Comp::new();
        c.on(Side::Right, R, V2::zeros(), Style::Rs274, 1.0).unwrap();
        let mut out = Vec::new();
        c.take(line((15.0, 5.0), (10.0, 1.0), 1), &mut out).unwrap();
        c.take(line((10.0, 1.0), (10.0, -10.0), 2), &mut out).unwrap();
        // A G2 (sweep > 0) of radius 0.5 with its centre on the tool's side.
        let arc = mv(
            MoveKind::Arc {
                center: P2::new(10.5, -10.0),
                sweep: FRAC_PI_2,
            },
            (10.0, -10.0),
            (10.5, -10.5),
            3,
        );
        let e = c.take(arc, &mut out).unwrap_err();
        assert!(e.contains("not smaller than the radius"), "{e}");
    }

    #[test]
    fn negative_radius_swaps_the_side() {
        let mut a = Comp::new();
        a.on(Side::Left, -R, V2::zeros(), Style::Rs274, 1.0).unwrap();
        assert_eq!(a.side, Some(Side::Right));
        assert_eq!(a.radius, R);
    }
}
