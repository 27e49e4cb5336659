//! The interpreted motion as the reference interpreter prints it (`rs274 -g`): one canonical call
//! a line, so the two can be compared line by line.
//!
//! Positions are in program units relative to program zero, X always a radius (as rs274 prints
//! them); in G18 `ARC_FEED`'s first coordinate is Z and its second X, and its rotation is +turns
//! for G3 and −turns for G2.

use super::{Interpretation, MoveKind, ProgFrame};
use std::f64::consts::TAU;
use std::fmt::Write;

/// One line per move: `STRAIGHT_TRAVERSE`, `STRAIGHT_FEED`, `ARC_FEED`, `DWELL`, `CHANGE_TOOL`.
pub fn write(run: &Interpretation, out: &mut String) {
    out.reserve(run.moves.len() * 64);
    for m in &run.moves {
        let f = run.frame(m);
        let (x, z) = radius_coords(f, m.end);
        let _ = write!(out, "{:>5} ", m.line);
        match m.kind {
            MoveKind::Rapid | MoveKind::Line => {
                out.push_str(if m.kind == MoveKind::Rapid {
                    "STRAIGHT_TRAVERSE("
                } else {
                    "STRAIGHT_FEED("
                });
                f4(out, x);
                out.push_str(", 0.0000, ");
                f4(out, z);
                out.push_str(", 0.0000, 0.0000, 0.0000)\n");
            }
            MoveKind::Arc { center, sweep } => {
                let (cx, cz) = radius_coords(f, center);
                let turns = (sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i64;
                let rotation = if sweep > 0.0 { -turns } else { turns };
                out.push_str("ARC_FEED(");
                for v in [z, x, cz, cx] {
                    f4(out, v);
                    out.push_str(", ");
                }
                let _ = writeln!(out, "{rotation}, 0.0000, 0.0000, 0.0000, 0.0000)");
            }
            MoveKind::Dwell { seconds } => {
                out.push_str("DWELL(");
                f4(out, seconds);
                out.push_str(")\n");
            }
            MoveKind::ToolChange { to, .. } => {
                let _ = writeln!(out, "CHANGE_TOOL({to})");
            }
        }
    }
}

/// Append `v` with four decimals, as `%.4f` prints it (but a value that rounds to zero prints as
/// `0.0000`, never `-0.0000`), without the
/// standard library's exact float formatting, which dominates the cost of printing long runs.
fn f4(out: &mut String, v: f64) {
    let scaled = (v * 1e4).round();
    if !scaled.is_finite() || scaled.abs() >= 9e15 {
        let _ = write!(out, "{v:.4}");
        return;
    }
    let n = scaled as i64;
    if n < 0 {
        out.push('-');
    }
    let a = n.unsigned_abs();
    let _ = write!(out, "{}.{:04}", a / 10_000, a % 10_000);
}

/// Program coordinates with X as a radius.
fn radius_coords(f: &ProgFrame, p: crate::geom::P2) -> (f64, f64) {
    ((p.x - f.origin.x) / f.scale, (p.y - f.origin.y) / f.scale)
}

#[cfg(test)]
mod tests {
    #[test]
    fn four_decimals_match_printf_style() {
        for (v, want) in [
            (0.0, "0.0000"),
            (-0.00004, "0.0000"),
            (-0.00006, "-0.0001"),
            (12.34566, "12.3457"),
            (-25.4, "-25.4000"),
            (1e6, "1000000.0000"),
        ] {
            let mut s = String::new();
            super::f4(&mut s, v);
            assert_eq!(s, want, "{v}");
        }
    }
}
