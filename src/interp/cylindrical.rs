//! Cylindrical interpolation: Fanuc G7.1 (G107 in system A naming) — a groove or a
//! cam track milled on the side of a turned part with a radial live tool, programmed on the
//! cylinder's surface unrolled (docs/turn-mill.md, "Cylindrical interpolation").
//!
//! `G7.1 C<r>` turns the mode on for a cylinder of radius r (mm; the C word of that block is the
//! radius, not a move), `G7.1 C0` turns it off. In the mode C words stay angles (degrees, as the
//! Fanuc 0i/16i/18i manuals' examples write them: a radius of 57.299 makes 1° one millimetre) and
//! the control converts them to lengths on the cylinder, s = r·C·π/180, so that Z and s form a
//! plane: G1 is a line in (Z, s) — the same as a line in Z and C, so it is one move — and F is the
//! feed along the unrolled path (the move is timed by its (Z, s) length at F). G2/G3 take R only
//! (I, J, K are refused, as the control refuses them) and turn in (Z, s): G3 counter-clockwise
//! with +Z to the right and +s up, G2 clockwise; an arc is made as chords of at most 1 mm. X
//! stays where it is (the tool on the cylinder) unless given. Not modelled: rapids in the mode (a `program` error: the control alarms).

use super::arc::arc_from_radius;
use super::flow::Run;
use super::letters::Letters;
use super::polar::contour_path;
use crate::gcode::Block;
use crate::geom::P2;

/// Longest chord of an arc, mm on the cylinder.
const CHORD_MM: f64 = 1.0;
/// Most chords one programmed arc makes.
const MAX_CHORDS: usize = 20_000;

impl Run<'_> {
    /// The cylinder's radius while cylindrical interpolation is on.
    pub(crate) fn cylindrical(&self) -> Option<f64> {
        self.tm.as_ref().and_then(|t| t.cylinder)
    }

    /// G7.1 C<r>: on for radius r; C0: off. The block's C word is taken here; `g40` is the
    /// block's G40 word, if any.
    pub(crate) fn cylindrical_code(&mut self, b: &Block, w: &mut Letters, at: u32, g40: Option<u32>) {
        let s = self.scale();
        let Some(r) = w.take(b'C') else {
            self.error(
                b,
                Some(at),
                "G7.1 needs C: the cylinder's radius, or C0 to cancel".into(),
            );
            return;
        };
        let has_c = self.tm.as_ref().is_some_and(|t| t.axes[1].is_some());
        if !has_c {
            self.unsupported(
                b,
                Some(at),
                "cylindrical interpolation needs a C axis: this machine has none (docs/turn-mill.md)".into(),
                true,
            );
            return;
        }
        if r == 0.0 {
            // Cutter compensation ends with the mode (`contour_comp_end`).
            let plane = super::contour_comp::Plane::Cylinder(self.cylindrical().unwrap_or(0.0));
            self.contour_comp_end(b, at, g40, plane);
            if let Some(tm) = self.tm.as_deref_mut() {
                tm.cylinder = None;
                tm.cylinder_prog = None;
            }
            return;
        }
        let r = r * s;
        if !(r.is_finite() && r > 0.0 && r <= 10_000.0) {
            self.error(
                b,
                w.at(b'C'),
                format!(
                    "G7.1 C{}: the cylinder's radius must be above 0 and at most 10 m",
                    r / s
                ),
            );
            return;
        }
        if self.comp.as_deref().is_some_and(|c| c.engaged()) {
            self.unsupported(
                b,
                Some(at),
                "cylindrical interpolation with nose-radius compensation on is not modelled: cancel it with G40 first"
                    .into(),
                true,
            );
            return;
        }
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.cylinder = Some(r);
        }
    }

    /// A motion block in the mode: G1 or G2/G3 (R) in the unrolled (Z, s) plane.
    pub(crate) fn cylindrical_motion(&mut self, b: &Block, w: &mut Letters, radius: f64) {
        let (named_z, named_c) = (w.peek(b'Z'), w.peek(b'C'));
        let Some(end) = self.target(b, w) else { return };
        let Some(extra) = self.extra_target(b, w, false) else {
            return;
        };
        let start = self.programmed();
        let c0 = self.tm.as_ref().map_or(0.0, |t| t.pos[1]);
        let k = radius * std::f64::consts::PI / 180.0;
        let Some((ccw, f)) = self.contour_motion(b, "cylindrical interpolation", "G7.1 C0") else {
            return;
        };
        // Under cutter compensation the tool stands off the programmed path: the block's
        // programmed start is the last programmed point, and what it does not name (or names
        // incrementally, W and H) is taken from there, not from where the tool is.
        let comp = self.contour_comp_engaged();
        let prog = self.tm.as_ref().and_then(|t| t.cylinder_prog).filter(|_| comp);
        let (z0, c_start) = prog.map_or((start.y, c0), |p| (p.x, p.y));
        let z1 = if named_z || prog.is_none() {
            end.y
        } else {
            z0 + (end.y - start.y)
        };
        let c1 = if named_c || prog.is_none() {
            extra[1]
        } else {
            c_start + (extra[1] - c0)
        };
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.cylinder_prog = comp.then_some(P2::new(z1, c1));
        }
        // (z, s) of the ends.
        let (ps, pe) = (P2::new(z0, c_start * k), P2::new(z1, c1 * k));
        let arc = match ccw {
            None => None,
            Some(ccw) => {
                if w.peek(b'I') || w.peek(b'J') || w.peek(b'K') {
                    self.error(b, None, "an arc in cylindrical interpolation takes R only".into());
                    w.use_all();
                    return;
                }
                let Some(r) = w.get(b'R') else {
                    self.error(b, None, "an arc in cylindrical interpolation needs R".into());
                    return;
                };
                let tol = self.arc_tolerance();
                match arc_from_radius(ps, pe, r * self.scale(), ccw, 1, tol) {
                    Ok(a) => Some(a),
                    Err(e) => {
                        self.error(b, None, format!("{e}"));
                        return;
                    }
                }
            }
        };
        if !self.contour_comp_route(b, ps, pe, arc, f, end.x) {
            self.cylindrical_chords(b, ps, pe, arc, end.x, f, extra, radius);
        }
    }

    /// The moves of one plane move from `ps` to `pe` ((z, s) on the unrolled cylinder of
    /// `radius`; a line, or the arc about a centre by a sweep, made as chords), X running from
    /// where it is to `x_end`, at `f` mm/min along the path; `extra` the other extra axes.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn cylindrical_chords(
        &mut self,
        b: &Block,
        ps: P2,
        pe: P2,
        arc: Option<(P2, f64)>,
        x_end: f64,
        f: f64,
        extra: super::ExtraAxes,
        radius: f64,
    ) {
        let k = radius * std::f64::consts::PI / 180.0;
        let x0 = self.programmed().x;
        let path = contour_path(ps, pe, arc);
        let (n, len) = match arc {
            None => (1, (pe.x - ps.x).hypot(pe.y - ps.y)),
            Some(_) => {
                let mut len = 0.0;
                let mut prev = path(0.0);
                for i in 1..=64 {
                    let q = path(i as f64 / 64.0);
                    len += (q.x - prev.x).hypot(q.y - prev.y);
                    prev = q;
                }
                (((len / CHORD_MM).ceil() as usize).clamp(1, MAX_CHORDS), len)
            }
        };
        let mut at = path(0.0);
        for i in 1..=n {
            let u = i as f64 / n as f64;
            let q = path(u);
            let to = P2::new(x0 + (x_end - x0) * u, q.x);
            let mut e = extra;
            e[1] = q.y / k;
            let chord = if n == 1 {
                len.hypot(x_end - x0)
            } else {
                (q.x - at.x).hypot(q.y - at.y).hypot((x_end - x0) / n as f64)
            };
            self.push_chord(b, to, e, chord, f);
            at = q;
        }
    }
}
