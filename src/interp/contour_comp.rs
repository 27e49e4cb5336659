//! Cutter compensation in the contour modes (G41/G42/G40 in polar coordinate interpolation G12.1
//! and in cylindrical interpolation G7.1): the contour programmed in the mode's plane — (X, the
//! hypothetical C) for polar, (Z, the unrolled length s) for cylindrical — is offset by the
//! cutter's radius before it is turned into X, Z and C moves, as the Fanuc 0i-TD / 16i/18i-TB
//! manuals describe the functions (compensation is applied to the plane's path).
//!
//! The offsetting is the lathe's own compensation stage (`comp.rs`, Fanuc style: the start-up
//! block ends normal to the next block, outside corners between lines take the intersection or
//! two vectors, arcs about the programmed corner otherwise, inside corners cut back), run on the
//! plane's moves: a plane point (p, q) enters the stage as the spindle-frame point (q, p), whose
//! compensation plane is then (p, q) itself, so G41 keeps the cutter on the left of the path seen
//! with p to the right and q up — from +Z for polar, from +X (the radial tool's side) for
//! cylindrical —, as a milling control does. What leaves the stage is the cutter centre's path;
//! the mode's module makes its chords.
//!
//! The cutter's radius is the active tool's: its milling diameter (`mill = { diameter }` in the
//! job) halved, else the radius of the station's cylindrical cutter in the machine's kinematic
//! tree, else its nose radius. A tool with none is `unsupported` (the control's offset table has
//! a radius latheguard does not know), and the path is checked as programmed.
//!
//! The axis out of the plane (Z for polar, X for cylindrical) may move in a compensated block (a
//! plunge, the retract of the G40 block): each block's end on it is kept with its line until the
//! stage lets the block's moves out, and their chords run it linearly there.

use super::comp::{Comp, Side, Style};
use super::flow::Run;
use super::{Feed, Move, MoveKind};
use crate::gcode::{Block, BlockRef};
use crate::geom::{P2, V2};

/// Which contour mode's plane the stage works in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Plane {
    /// Polar interpolation: (x radius, c), Z out of the plane.
    Polar,
    /// Cylindrical interpolation on a cylinder of this radius (mm): (z, s), X out of the plane.
    Cylinder(f64),
}

/// The stage and the out-of-plane ends of the blocks whose moves wait in it.
#[derive(Clone, Debug)]
pub(crate) struct ContourComp {
    comp: Comp,
    plane: Plane,
    /// (line, the out-of-plane coordinate at the end of that block, spindle frame) of the
    /// blocks not yet out.
    ends: Vec<(u32, f64)>,
}

/// The mode's name in findings.
fn mode_name(plane: Plane) -> &'static str {
    match plane {
        Plane::Polar => "polar coordinate interpolation",
        Plane::Cylinder(_) => "cylindrical interpolation",
    }
}

impl ContourComp {
    /// G41/G42 is in force (not cancelled by G40).
    pub(crate) fn is_on(&self) -> bool {
        self.comp.is_on()
    }
}

/// The radius of the cutter in `station`: its milling diameter (a job's `mill`) halved, else the
/// radius of the station's cylindrical cutter in the kinematic tree, else its nose radius; 0
/// when none is known.
fn cutter_radius(machine: &crate::machine::Machine, station: u32) -> f64 {
    let tool = machine.tool(station);
    if let Some(m) = tool.and_then(|t| t.mill.as_ref()) {
        return m.diameter / 2.0;
    }
    let from_tree = machine.kinematics.as_deref().and_then(|k| {
        k.components
            .iter()
            .find_map(|c| match (&c.geometry, c.role, c.station) {
                (
                    Some(crate::kin::Geometry::Cylinder { radius, .. } | crate::kin::Geometry::Cutter { radius, .. }),
                    crate::kin::Role::Cutter,
                    Some(s),
                ) if s == station => Some(*radius),
                _ => None,
            })
    });
    from_tree.unwrap_or_else(|| tool.map_or(0.0, |t| t.nose_radius))
}

/// A plane point (p, q) as the stage's spindle-frame point, and back.
fn to_stage(p: P2) -> P2 {
    P2::new(p.y, p.x)
}

fn from_stage(p: P2) -> P2 {
    P2::new(p.y, p.x)
}

impl Run<'_> {
    /// The cutter-radius compensation of a contour mode is on (or its moves still wait).
    pub(crate) fn contour_comp_engaged(&self) -> bool {
        self.tm
            .as_ref()
            .and_then(|t| t.contour_comp.as_ref())
            .is_some_and(|c| c.comp.engaged())
    }

    /// G41/G42 while a contour mode is on (its `plane`). `false` when the cutter's radius is
    /// unknown (reported): the path is then checked as programmed.
    pub(crate) fn contour_comp_on(&mut self, b: &Block, left: bool, code_name: &str, at: u32, plane: Plane) -> bool {
        let radius = cutter_radius(self.machine, self.station);
        if radius <= 0.0 {
            self.unsupported(
                b,
                Some(at),
                format!(
                    "{code_name} in {}: the cutter's radius is unknown (give the tool `mill = {{ diameter = … }}` in the job, docs/tools.md); the cutter's centre is checked on the programmed path",
                    mode_name(plane)
                ),
                true,
            );
            return false;
        }
        let side = if left { Side::Left } else { Side::Right };
        let scale = self.scale();
        let Some(tm) = self.tm.as_deref_mut() else { return false };
        let pc = tm.contour_comp.get_or_insert_with(|| {
            Box::new(ContourComp {
                comp: Comp::new(),
                plane,
                ends: Vec::new(),
            })
        });
        pc.plane = plane;
        match pc.comp.on(side, radius, V2::zeros(), Style::Fanuc, scale) {
            Ok(()) => true,
            Err(msg) => {
                self.error(b, Some(at), msg);
                false
            }
        }
    }

    /// G40 in a contour mode: the next move leaves the offset.
    pub(crate) fn contour_comp_off(&mut self, b: &Block, at: u32) {
        let mut out = Vec::new();
        let res = match self.tm.as_deref_mut().and_then(|t| t.contour_comp.as_deref_mut()) {
            Some(pc) => pc.comp.off(&mut out),
            None => return,
        };
        // What the stage let out comes before what an abandon lets out after it.
        self.contour_comp_emit(out);
        if let Err(msg) = res {
            self.contour_comp_abandon();
            self.error(b, Some(at), msg);
        }
    }

    /// A contour mode's programmed move of block `b` from `ps` to `pe` (plane points), the arc
    /// about a centre by a sweep (counter-clockwise with the plane's first axis to the right and
    /// its second up) or a line, at `f` mm/min, `end` the block's end on the axis out of the
    /// plane: into the compensation stage when it is engaged (`true`); `false` leaves the chords
    /// to the caller (the move as programmed).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn contour_comp_route(
        &mut self,
        b: &Block,
        ps: P2,
        pe: P2,
        arc: Option<(P2, f64)>,
        f: f64,
        end: f64,
    ) -> bool {
        if !self.contour_comp_engaged() {
            return false;
        }
        let stage = Move {
            kind: match arc {
                None => MoveKind::Line,
                Some((c, sweep)) => MoveKind::Arc {
                    center: to_stage(c),
                    sweep: -sweep,
                },
            },
            line: b.line,
            n: None,
            profile_line: 0,
            start: to_stage(ps),
            end: to_stage(pe),
            tip: V2::zeros(),
            station: self.station,
            feed: Feed::PerMinute(f),
            state: 0,
        };
        self.contour_comp_take(b, stage, end);
        true
    }

    /// A stage move of a compensated block (or one that follows G40 while moves wait), `end` its
    /// block's end on the axis out of the plane: into the stage; what it lets out is made into
    /// chords.
    fn contour_comp_take(&mut self, b: &Block, stage: Move, end: f64) {
        let line = stage.line;
        let mut out = Vec::new();
        let res = {
            let Some(pc) = self.tm.as_deref_mut().and_then(|t| t.contour_comp.as_deref_mut()) else {
                return;
            };
            match pc.ends.last_mut() {
                Some(last) if last.0 == line => last.1 = end,
                _ => pc.ends.push((line, end)),
            }
            pc.comp.take(stage, &mut out)
        };
        // What the stage let out comes before what an abandon lets out after it.
        self.contour_comp_emit(out);
        if let Err(msg) = res {
            // As on the lathe: the move is refused, compensation stops, the rest is checked as
            // programmed.
            self.contour_comp_abandon();
            self.error(
                b,
                None,
                format!("{msg}; cutter compensation stops here and the rest is checked as programmed"),
            );
        }
    }

    /// The contour mode of `plane` ends at `at` (G13.1, G7.1 C0): G40 on that line (`g40`, its
    /// offset) cancels the compensation first; still on, it is the control's alarm. What the
    /// stage holds goes out, and the stage ends with the mode.
    pub(crate) fn contour_comp_end(&mut self, b: &Block, at: u32, g40: Option<u32>, plane: Plane) {
        if let (Some(a40), true) = (g40, self.contour_comp_engaged()) {
            self.contour_comp_off(b, a40);
        }
        let on = self
            .tm
            .as_deref()
            .and_then(|t| t.contour_comp.as_deref())
            .is_some_and(|c| c.is_on());
        if on {
            self.error(
                b,
                Some(at),
                format!(
                    "{} cancelled with cutter compensation on: a control alarms here (give G40 first)",
                    mode_name(plane)
                ),
            );
        }
        self.contour_comp_flush();
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.contour_comp = None;
        }
    }

    /// Everything the stage holds goes out (the mode's end, the end of the program).
    pub(crate) fn contour_comp_flush(&mut self) {
        let mut out = Vec::new();
        if let Some(pc) = self.tm.as_deref_mut().and_then(|t| t.contour_comp.as_deref_mut()) {
            pc.comp.flush(&mut out);
        }
        self.contour_comp_emit(out);
    }

    /// Compensation stops after an error: what waits leaves as it is.
    fn contour_comp_abandon(&mut self) {
        let mut out = Vec::new();
        if let Some(pc) = self.tm.as_deref_mut().and_then(|t| t.contour_comp.as_deref_mut()) {
            pc.comp.abandon(&mut out);
        }
        self.contour_comp_emit(out);
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.contour_comp = None;
        }
    }

    /// The stage's moves as chords, each at its own block's line and out-of-plane end.
    fn contour_comp_emit(&mut self, out: Vec<Move>) {
        for m in out {
            if !matches!(m.kind, MoveKind::Line | MoveKind::Rapid | MoveKind::Arc { .. }) {
                continue;
            }
            let Some((plane, end)) = self.tm.as_deref().and_then(|t| t.contour_comp.as_deref()).map(|pc| {
                let end = pc.ends.iter().find(|e| e.0 == m.line).map(|e| e.1);
                (pc.plane, end)
            }) else {
                continue;
            };
            let f = match m.feed {
                Feed::PerMinute(f) => f,
                _ => continue,
            };
            let arc = match m.kind {
                MoveKind::Arc { center, sweep } => Some((from_stage(center), -sweep)),
                _ => None,
            };
            let Some(b) = &self.block_at_line(m.line) else { continue };
            let extra = self.tm.as_deref().map_or([0.0; 4], |t| t.pos);
            let here = self.programmed();
            let (ps, pe) = (from_stage(m.start), from_stage(m.end));
            match plane {
                Plane::Polar => self.polar_chords(b, ps, pe, arc, end.unwrap_or(here.y), f, extra),
                Plane::Cylinder(r) => self.cylindrical_chords(b, ps, pe, arc, end.unwrap_or(here.x), f, extra, r),
            }
            // The blocks before this one are out: their Z ends are no longer needed.
            if let Some(pc) = self.tm.as_deref_mut().and_then(|t| t.contour_comp.as_deref_mut()) {
                pc.ends.retain(|e| e.0 >= m.line);
            }
        }
    }
}

impl<'a> Run<'a> {
    /// The block at a physical line (the blocks are in line order).
    fn block_at_line(&self, line: u32) -> Option<BlockRef> {
        self.prog.block_at_line(line)
    }
}
