//! Polar coordinate interpolation: Fanuc G12.1 / G13.1, written G112 / G113 in
//! Fanuc's G-code system A (docs/turn-mill.md, "Polar coordinate interpolation").
//!
//! Between G12.1 and G13.1 a milling contour on the part's face is programmed in a Cartesian
//! plane normal to the spindle: X (a diameter in diameter mode, as everywhere on a lathe) and
//! the hypothetical axis C, a length in mm (radius values), with G1 and G2/G3 (R, or I for X and
//! J for C, both radius values) and F the feed along the contour. The control turns each point
//! into the real axes: X the point's distance from the spindle axis, C its angle. Rules read from
//! the Fanuc 0i-TD / 16i/18i-TB operator's manuals' description of the function (no text of them
//! here): the plane's origin is the workpiece origin, the hypothetical axis starts at 0 at
//! G12.1, a rapid (G0) is not allowed in the mode, and the mode is cancelled by G13.1 (and must
//! be, before the program ends).
//!
//! The moves made: each programmed segment or arc as chords of at most 1 mm and 1° of C, each a
//! line in X (radius) and C (degrees, unwrapped so that C never jumps by a turn), timed so that
//! the chord takes its Cartesian length at F. A chord's X–C line strays from the Cartesian chord
//! by less than 0.01 mm at a radius of 1 mm and by far less farther out (the chord is at most 1°
//! of a circle about the axis and 1 mm long). Through the spindle axis itself the angle turns by
//! 180° at once, as on the control: the segment is split there, and the C turn happens at X0.
//!
//! C turns so that the tool meets the part's point of polar angle φ: the part is turned by −φ
//! (the 3D path poses the part turned by C), so the programmed (X, C) picture is the part seen
//! from +Z in its own frame.
//!
//! Cutter compensation in the mode (G41/G42 after G12.1) is `contour_comp.rs`: the contour is
//! offset in the plane before the chords are made. Not modelled: incremental addresses U and H
//! in the mode (`unsupported`), and feeds per revolution.

use super::arc::{arc_from_center, arc_from_radius};
use super::flow::Run;
use super::letters::Letters;
use super::state::Motion;
use super::{Feed, MoveKind};
use crate::gcode::Block;
use crate::geom::P2;

/// Longest chord (mm), and widest one (degrees of C) where it keeps [`ANGLE_FROM_MM`] or more
/// from the axis.
const CHORD_MM: f64 = 1.0;
const CHORD_DEG: f64 = 1.0;
const ANGLE_FROM_MM: f64 = 1.0;
/// How far a chord's X–C line may stray from the programmed contour (mm).
const CHORD_TOL_MM: f64 = 0.005;
/// Most chords one programmed move makes.
const MAX_CHORDS: usize = 20_000;

/// The mode's state: the hypothetical point (x a radius, c) in mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Polar {
    pub x: f64,
    pub c: f64,
}

impl Run<'_> {
    /// Whether polar coordinate interpolation is on.
    pub(crate) fn polar_on(&self) -> bool {
        self.tm.as_ref().is_some_and(|t| t.polar.is_some())
    }

    /// G12.1 / G112: polar coordinate interpolation on, from where the tool is (C must be a
    /// positioned axis of the machine).
    pub(crate) fn polar_start(&mut self, b: &Block, at: u32) {
        let x = self.programmed().x;
        let Some(tm) = self.tm.as_deref_mut() else {
            self.unsupported(
                b,
                Some(at),
                "polar coordinate interpolation needs a C axis: this machine has none (docs/turn-mill.md)".into(),
                true,
            );
            return;
        };
        if tm.axes[1].is_none() {
            self.unsupported(
                b,
                Some(at),
                "polar coordinate interpolation needs a C axis: this machine's tree has none".into(),
                true,
            );
            return;
        }
        if !tm.c_mode && tm.c_needs_mode {
            self.error(
                b,
                Some(at),
                "polar coordinate interpolation with the spindle not in C-axis mode: a control alarms here".into(),
            );
            return;
        }
        if self.comp.as_deref().is_some_and(|c| c.engaged()) {
            self.unsupported(
                b,
                Some(at),
                "polar coordinate interpolation with nose-radius compensation on is not modelled: cancel it with G40 first".into(),
                true,
            );
            return;
        }
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.polar = Some(Polar { x, c: 0.0 });
        }
    }

    /// G13.1 / G113 at `at`: the mode off (`g40`: a G40 on the same line, which cancels the
    /// cutter compensation first; `contour_comp_end`).
    pub(crate) fn polar_stop(&mut self, b: &Block, at: u32, g40: Option<u32>) {
        self.contour_comp_end(b, at, g40, super::contour_comp::Plane::Polar);
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.polar = None;
        }
    }

    /// A motion block in the mode: G1, G2, G3 in the X–C plane (Z may move along).
    pub(crate) fn polar_motion(&mut self, b: &Block, w: &mut Letters) {
        let Some(p) = self.tm.as_ref().and_then(|t| t.polar) else {
            return;
        };
        for (letter, why) in [(b'U', "U"), (b'H', "H")] {
            if w.peek(letter) {
                self.unsupported(
                    b,
                    w.at(letter),
                    format!("{why} (an incremental address) in polar coordinate interpolation is not modelled: give X and C"),
                    true,
                );
                w.use_all();
                return;
            }
        }
        let s = self.scale();
        let had_x = w.peek(b'X');
        // C is the hypothetical axis here (mm), not the rotary axis: read and gone.
        let c_word = w.take(b'C');
        // X and Z as any block reads them (X a diameter in diameter mode); C is read here.
        let Some(end) = self.target(b, w) else { return };
        let Some(extra) = self.extra_target(b, w, false) else {
            return;
        };
        let ex = if had_x { end.x } else { p.x };
        let ec = c_word.map_or(p.c, |c| c * s);
        if !super::in_range_value(ec) {
            self.error(b, w.at(b'C'), "the target point is out of any range".into());
            return;
        }
        let Some((ccw, f)) = self.contour_motion(b, "polar coordinate interpolation", "G13.1") else {
            return;
        };
        let (ps, pe) = (P2::new(p.x, p.c), P2::new(ex, ec));
        // The path as a function of its fraction, and its length.
        let arc = match ccw {
            None => None,
            Some(ccw) => {
                let tol = self.arc_tolerance();
                let has_r = w.peek(b'R');
                let has_ij = w.peek(b'I') || w.peek(b'J');
                let arc = if has_r && !has_ij {
                    arc_from_radius(ps, pe, w.get(b'R').unwrap_or(0.0) * s, ccw, 1, tol)
                } else if has_ij && !has_r {
                    let c = P2::new(
                        ps.x + w.get(b'I').unwrap_or(0.0) * s,
                        ps.y + w.get(b'J').unwrap_or(0.0) * s,
                    );
                    arc_from_center(ps, pe, c, ccw, 1, tol).map(|sw| (c, sw))
                } else {
                    self.error(
                        b,
                        None,
                        "an arc in polar coordinate interpolation takes R or I/J".into(),
                    );
                    return;
                };
                match arc {
                    Ok(a) => Some(a),
                    Err(e) => {
                        self.error(b, None, format!("{e}"));
                        return;
                    }
                }
            }
        };
        if !self.contour_comp_route(b, ps, pe, arc, f, end.y) {
            self.polar_chords(b, ps, pe, arc, end.y, f, extra);
        }
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.polar = Some(Polar { x: ex, c: ec });
        }
    }
}

impl Run<'_> {
    /// The chords of one plane move from `ps` to `pe` (x radius, c; the arc about a centre by a
    /// sweep, or a line), Z running from where it is to `z_end`, at `f` mm/min along the contour;
    /// `extra` the other extra axes.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn polar_chords(
        &mut self,
        b: &Block,
        ps: P2,
        pe: P2,
        arc: Option<(P2, f64)>,
        z_end: f64,
        f: f64,
        extra: super::ExtraAxes,
    ) {
        let z0 = self.programmed().y;
        let path = contour_path(ps, pe, arc);
        let c_zero = self.tm.as_ref().map_or(0.0, |t| t.shift[1]);
        let mut c_prev = self.tm.as_ref().map_or(0.0, |t| t.pos[1]);
        let mut at = path(0.0);
        let mut ends = Vec::new();
        chord_ends(&path, arc, &mut ends);
        for u in ends {
            let q = path(u);
            let r = q.x.hypot(q.y);
            let z = z0 + (z_end - z0) * u;
            // The angle nearest the last C (the same point, unwrapped); on the axis C stays.
            let c = if r < AXIS_MM {
                c_prev
            } else {
                let mut c = c_zero - q.y.atan2(q.x).to_degrees();
                c += 360.0 * ((c_prev - c) / 360.0).round();
                c
            };
            if at.x.hypot(at.y) < AXIS_MM && (c - c_prev).abs() > 1e-9 {
                // Leaving the axis: C turns there first, as on the control.
                let mut e = extra;
                e[1] = c;
                self.push_chord(b, P2::new(0.0, self.programmed().y), e, 0.0, f);
            }
            let mut e = extra;
            e[1] = c;
            let chord = (q.x - at.x).hypot(q.y - at.y).hypot(z - self.programmed().y);
            self.push_chord(b, P2::new(r, z), e, chord, f);
            c_prev = c;
            at = q;
        }
    }
}

/// A point this near the spindle axis (mm) is on it: its angle is the one C already has.
const AXIS_MM: f64 = 1e-9;

/// The path fractions (ascending, the last 1) where the chords of a polar move end: each chord
/// at most [`CHORD_MM`] long, at most [`CHORD_DEG`] of C where it stays [`ANGLE_FROM_MM`] or more
/// from the axis, and its X–C line — the radius and the angle each linear along it, which is how
/// the control moves — within [`CHORD_TOL_MM`] of the programmed contour. Pieces are halved until
/// they pass; a piece at most `CHORD_TOL_MM` long always passes (its X–C line stays within a few
/// tolerances of it, even through the axis). So the count follows the geometry: the length, the
/// turn of C away from the axis, and near the axis the tolerance (a few dozen chords where a line
/// passes through it), never the angle there; at most [`MAX_CHORDS`] in all.
fn chord_ends(path: &dyn Fn(f64) -> P2, arc: Option<(P2, f64)>, out: &mut Vec<f64>) {
    // The path's length, and how far an arc piece strays from its chord per unit of fraction².
    let (len, radius, sweep) = match arc {
        Some((c, sweep)) => {
            let p = path(0.0);
            let r = (p.x - c.x).hypot(p.y - c.y);
            (r * sweep.abs(), r, sweep.abs())
        }
        None => {
            let (a, b) = (path(0.0), path(1.0));
            ((b.x - a.x).hypot(b.y - a.y), 0.0, 0.0)
        }
    };
    // First, pieces no longer than a chord may be (as many as the cap allows), then each halved
    // as it needs, within what the cap leaves.
    let n0 = ((len / CHORD_MM).ceil().max(1.0) as usize).min(MAX_CHORDS / 2);
    let mut stack: Vec<(f64, f64, P2, P2)> = Vec::new();
    for k in 0..n0 {
        let (u0, u1) = (k as f64 / n0 as f64, (k + 1) as f64 / n0 as f64);
        stack.clear();
        stack.push((u0, u1, path(u0), path(u1)));
        while let Some((u0, u1, q0, q1)) = stack.pop() {
            let room = MAX_CHORDS.saturating_sub(out.len() + stack.len() + (n0 - k));
            let parts = match chord_split(q0, q1, radius * (1.0 - (sweep * (u1 - u0) / 2.0).cos())) {
                Some(parts) if room > 1 => parts.min(room),
                _ => {
                    out.push(u1);
                    continue;
                }
            };
            // The parts wait last first, so that they leave in order.
            let mut q_hi = q1;
            for j in (0..parts).rev() {
                let ua = u0 + (u1 - u0) * j as f64 / parts as f64;
                let qa = if j == 0 { q0 } else { path(ua) };
                let ub = u0 + (u1 - u0) * (j + 1) as f64 / parts as f64;
                stack.push((ua, ub, qa, q_hi));
                q_hi = qa;
            }
        }
    }
}

/// `None` when the chord from `q0` to `q1` of a path passes (see [`chord_ends`]), else into how
/// many equal parts to cut its piece (2 to 64; a part may need cutting again); `sag` is how far
/// the path itself strays from the segment `q0`–`q1`.
fn chord_split(q0: P2, q1: P2, sag: f64) -> Option<usize> {
    let len = (q1.x - q0.x).hypot(q1.y - q0.y);
    if len <= CHORD_TOL_MM {
        return None;
    }
    let (r0, r1) = (q0.x.hypot(q0.y), q1.x.hypot(q1.y));
    let (mut a0, mut a1) = (q0.y.atan2(q0.x), q1.y.atan2(q1.x));
    // From or to the axis the chord is radial (C turns on the axis, not along the chord).
    if r0 < AXIS_MM {
        a0 = a1;
    }
    if r1 < AXIS_MM {
        a1 = a0;
    }
    let tau = std::f64::consts::TAU;
    let mut da = a1 - a0;
    da -= tau * (da / tau).round();
    let mut need = len / CHORD_MM;
    if r0.min(r1) >= ANGLE_FROM_MM {
        need = need.max(da.abs().to_degrees() / CHORD_DEG);
    }
    // The X–C line at a quarter, the half and three quarters, against the segment: its
    // distance shrinks with the square of the chord's length.
    let (dx, dy) = (q1.x - q0.x, q1.y - q0.y);
    let dev = [0.25, 0.5, 0.75]
        .iter()
        .map(|&t| {
            let (r, a) = (r0 + (r1 - r0) * t, a0 + da * t);
            let (px, py) = (r * a.cos() - q0.x, r * a.sin() - q0.y);
            let s = ((px * dx + py * dy) / (len * len)).clamp(0.0, 1.0);
            (px - s * dx).hypot(py - s * dy)
        })
        .fold(0.0f64, f64::max);
    need = need.max(((dev + sag) / CHORD_TOL_MM).sqrt());
    if need <= 1.0 {
        return None;
    }
    Some((need.ceil() as usize).clamp(2, 64))
}

impl Run<'_> {
    /// The motion of a block in a contour mode (polar or cylindrical interpolation): `Some(ccw)`
    /// for an arc, `None` for a line, with the feed per minute; a rapid is an alarm, any other
    /// motion or a feed per revolution is not modelled (findings at the block).
    pub(crate) fn contour_motion(&mut self, b: &Block, mode: &str, cancel: &str) -> Option<(Option<bool>, f64)> {
        let ccw = match self.modal.motion.unwrap_or(Motion::Line) {
            Motion::Line => None,
            Motion::ArcCcw => Some(true),
            Motion::ArcCw => Some(false),
            Motion::Rapid => {
                self.error(
                    b,
                    None,
                    format!("G0 in {mode}: a control alarms here (cancel it with {cancel} first)"),
                );
                return None;
            }
            _ => {
                self.unsupported(b, None, format!("only G1, G2 and G3 move in {mode}"), true);
                return None;
            }
        };
        let Feed::PerMinute(f) = self.feed(b)? else {
            self.unsupported(
                b,
                None,
                format!("a feed per revolution in {mode} is not modelled: give G98 (per minute)"),
                true,
            );
            return None;
        };
        Some((ccw, f))
    }

    /// One chord of a contour mode: a line to `to` (x a radius, z) with the extra axes at
    /// `extra`, timed as the control runs it — `chord` mm of the contour at `f` mm/min. (The
    /// motion module times a feed by its linear travel, or with none by its rotary travel in
    /// °/min: the feed given to it is scaled so that either takes the chord's time.)
    pub(crate) fn push_chord(&mut self, b: &Block, to: P2, extra: super::ExtraAxes, chord: f64, f: f64) {
        let from = self.programmed();
        let c_prev = self.tm.as_ref().map_or(0.0, |t| t.pos[1]);
        let lin = (to.x - from.x).hypot(to.y - from.y);
        let fk = if chord < 1e-12 {
            f
        } else if lin > 1e-9 {
            f * lin / chord
        } else {
            f * (extra[1] - c_prev).abs() / chord
        };
        self.set_pending(extra, None);
        self.push_move(b, MoveKind::Line, from, to, Feed::PerMinute(fk.max(1e-6)));
    }
}

/// A contour's path in its plane as a function of its fraction: the segment `ps`–`pe`, or the
/// arc from `ps` about `centre` through `sweep` radians.
pub(crate) fn contour_path(ps: P2, pe: P2, arc: Option<(P2, f64)>) -> Box<dyn Fn(f64) -> P2> {
    match arc {
        None => Box::new(move |u| P2::new(ps.x + (pe.x - ps.x) * u, ps.y + (pe.y - ps.y) * u)),
        Some((c, sweep)) => {
            let (r, a0) = ((ps.x - c.x).hypot(ps.y - c.y), (ps.y - c.y).atan2(ps.x - c.x));
            Box::new(move |u| {
                let a = a0 + sweep * u;
                P2::new(c.x + r * a.cos(), c.y + r * a.sin())
            })
        }
    }
}
