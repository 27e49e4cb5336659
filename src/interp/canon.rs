//! The interpreted motion as the reference interpreter prints it (`rs274 -g`): one canonical call
//! a line, so the two can be compared line by line.
//!
//! Positions are in program units relative to program zero, X always a radius (as rs274 prints
//! them); in G18 `ARC_FEED`'s first coordinate is Z and its second X, and its rotation is +turns
//! for G3 and −turns for G2.

use super::{Move, MoveKind};
use std::f64::consts::TAU;
use std::fmt::Write;

/// One line per move: `STRAIGHT_TRAVERSE`, `STRAIGHT_FEED`, `ARC_FEED`, `DWELL`, `CHANGE_TOOL`.
pub fn write(moves: &[Move], out: &mut String) {
    for m in moves {
        let f = &m.frame;
        let (x, z) = radius_coords(m, m.end);
        match m.kind {
            MoveKind::Rapid => {
                let _ = writeln!(
                    out,
                    "{:>5} STRAIGHT_TRAVERSE({x:.4}, 0.0000, {z:.4}, 0.0000, 0.0000, 0.0000)",
                    m.line
                );
            }
            MoveKind::Line => {
                let _ = writeln!(
                    out,
                    "{:>5} STRAIGHT_FEED({x:.4}, 0.0000, {z:.4}, 0.0000, 0.0000, 0.0000)",
                    m.line
                );
            }
            MoveKind::Arc { center, sweep } => {
                let (cx, cz) = radius_coords(m, center);
                let turns = (sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i64;
                let rotation = if sweep > 0.0 { -turns } else { turns };
                let _ = writeln!(
                    out,
                    "{:>5} ARC_FEED({z:.4}, {x:.4}, {cz:.4}, {cx:.4}, {rotation}, 0.0000, 0.0000, 0.0000, 0.0000)",
                    m.line
                );
            }
            MoveKind::Dwell { seconds } => {
                let _ = writeln!(out, "{:>5} DWELL({seconds:.4})", m.line);
            }
            MoveKind::ToolChange { to, .. } => {
                let _ = writeln!(out, "{:>5} CHANGE_TOOL({to})", m.line);
            }
        }
        let _ = f;
    }
}

/// Program coordinates with X as a radius.
fn radius_coords(m: &Move, p: crate::geom::P2) -> (f64, f64) {
    let f = &m.frame;
    ((p.x - f.origin.x) / f.scale, (p.y - f.origin.y) / f.scale)
}
