//! Cylindrical interpolation (issue 16): Fanuc G7.1 (G107 in system A naming) — a groove or a
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
//! stays where it is (the tool on the cylinder) unless given. Not modelled: compensation in the
//! mode (`unsupported`), rapids in the mode (a `program` error: the control alarms).

use super::arc::{arc_from_radius, ArcTolerance};
use super::block::Words;
use super::flow::Run;
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

    /// G7.1 C<r>: on for radius r; C0: off. The block's C word is taken here.
    pub(crate) fn cylindrical_code(&mut self, b: &Block, w: &mut Words, at: u32) {
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
            if let Some(tm) = self.tm.as_deref_mut() {
                tm.cylinder = None;
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
    pub(crate) fn cylindrical_motion(&mut self, b: &Block, w: &mut Words, radius: f64) {
        let Some(end) = self.target(b, w) else { return };
        let Some(extra) = self.extra_target(b, w, false) else {
            return;
        };
        let start = self.programmed();
        let c0 = self.tm.as_ref().map_or(0.0, |t| t.pos[1]);
        let c1 = extra[1];
        let k = radius * std::f64::consts::PI / 180.0;
        let Some((ccw, f)) = self.contour_motion(b, "cylindrical interpolation", "G7.1 C0") else {
            return;
        };
        // (z, s) of the ends.
        let (ps, pe) = (P2::new(start.y, c0 * k), P2::new(end.y, c1 * k));
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
                let tol = if self.modal.inch {
                    ArcTolerance::INCH
                } else {
                    ArcTolerance::MM
                };
                match arc_from_radius(ps, pe, r * self.scale(), ccw, 1, tol) {
                    Ok(a) => Some(a),
                    Err(e) => {
                        self.error(b, None, format!("{e}"));
                        return;
                    }
                }
            }
        };
        let path = contour_path(ps, pe, arc);
        let (n, len) = match ccw {
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
        let x0 = start.x;
        let mut at = path(0.0);
        for i in 1..=n {
            let u = i as f64 / n as f64;
            let q = path(u);
            let to = P2::new(x0 + (end.x - x0) * u, q.x);
            let mut e = extra;
            e[1] = q.y / k;
            let chord = if n == 1 {
                len.hypot(end.x - x0)
            } else {
                (q.x - at.x).hypot(q.y - at.y).hypot((end.x - x0) / n as f64)
            };
            self.push_chord(b, to, e, chord, f);
            at = q;
        }
    }
}
