//! LinuxCNC drilling cycles G73, G74, G81–G86, G89 in the XY plane (G17): on a
//! lathe they drill along Z, the spindle axis, at the X the block names (usually X0). The
//! words, passes and retract rules follow the LinuxCNC G-code reference ("G73 Drilling Cycle
//! with Chip Breaking", "G74 Left-hand Tapping", "G81 Drilling Cycle", "G82", "G83 Peck
//! Drilling", "G84 Right-hand Tapping", "G85", "G86", "G89",
//! "G98 / G99 Canned Cycle Return Level"); docs/cycles-linuxcnc.md has the details.
//!
//! In G18 (the lathe's own plane) these cycles drill along Y, which a 2-axis lathe does not
//! have: refused with a finding. G87/G88 (back boring, manual retract) are not modelled
//! (`unsupported`).

use super::common::{emit, feed, rapid, MAX_PASSES};
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::flow::Run;
use crate::interp::letters::Letters;
use crate::interp::state::Motion;
use crate::interp::{Feed, MoveKind, SpindleDir};

/// What LinuxCNC keeps between cycle blocks (rs274ngc's `cycle_*` settings).
#[derive(Default, Debug)]
pub(crate) struct LcncMemory {
    /// G98 (retract to the initial level) rather than G99 (to the R plane). rs274ngc leaves the
    /// retract mode at its first value, the R plane, until a program says otherwise.
    pub retract_to_old_z: bool,
    /// Initial level (spindle-frame z, mm) of the current series of drilling cycles.
    pub initial_z: f64,
    /// R, Z (as written, program units), P (s) and Q (program units) of the last cycle block.
    pub r: f64,
    pub z: f64,
    pub p: f64,
    pub q: f64,
}

/// The retract above each peck of G73/G83 when the block has no D: LinuxCNC's default of
/// 0.010 inch (0.254 mm), used when no INI file sets `G73_PECK_CLEARANCE` / `G83_PECK_CLEARANCE`.
const PECK_CLEARANCE_MM: f64 = 0.254;

fn is_drill(code: u16) -> bool {
    code == 730 || (810..=890).contains(&code)
}

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    let name = format!("G{}", code / 10);
    let at = (at > 0).then_some(at);
    if matches!(code, 870 | 880) {
        let what = if code == 870 {
            "G87 back boring"
        } else {
            "G88 boring with a manual retract"
        };
        run.unsupported(
            b,
            at,
            format!("{what} is not modelled yet: its moves are not checked"),
            true,
        );
        run.modal.motion = None;
        return true;
    }
    if code == 740 || code == 840 {
        // Right-hand tapping (G84) needs the spindle turning forward (M3), left-hand (G74) in
        // reverse (M4).
        let need = if code == 840 { SpindleDir::Cw } else { SpindleDir::Ccw };
        if run.spindle_dir != need {
            let m = if code == 840 { "M3" } else { "M4" };
            run.error(b, at, format!("{name} taps with the spindle turning {m}"));
            run.modal.motion = None;
            return true;
        }
    }
    if !run.modal.plane_xy {
        run.error(
            b,
            at,
            format!(
                "{name} in the XZ plane (G18) drills along Y, which a 2-axis lathe does not have: select G17 to drill along Z"
            ),
        );
        run.modal.motion = None;
        return true;
    }
    let same = run.modal.motion == Some(Motion::Cycle(code));
    let series = matches!(run.modal.motion, Some(Motion::Cycle(c)) if is_drill(c));
    let before = run.reports;
    drill(run, b, w, code, &name, same, series);
    // A refused cycle is not in force afterwards (rs274ngc stops the program there).
    run.modal.motion = (run.reports == before).then_some(Motion::Cycle(code));
    true
}

fn drill(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, name: &str, same: bool, series: bool) {
    let s = run.scale();
    let o = run.origin();
    let cur = run.programmed();
    // Words: X (and Y, which must stay 0), Z, R, L, P (G82, G86, G89), Q (G73, G83).
    let x = w.get(b'X');
    if let Some(y) = w.get(b'Y') {
        if y != 0.0 {
            run.error(b, w.at(b'Y'), format!("Y{y}: this lathe has no Y axis"));
            return;
        }
    }
    let z = match w.get(b'Z') {
        Some(z) => z,
        None if same => run.cycles.lcnc.z,
        None => {
            run.error(
                b,
                None,
                format!("{name} needs Z (the bottom of the hole) when it starts"),
            );
            return;
        }
    };
    let r_word = match w.get(b'R') {
        Some(r) => r,
        None if same => run.cycles.lcnc.r,
        None => {
            run.error(b, None, format!("{name} needs R (the retract plane) when it starts"));
            return;
        }
    };
    let l = match w.get(b'L') {
        None => 1,
        Some(l) if l >= 1.0 && l.fract() == 0.0 && l <= MAX_PASSES as f64 => l as usize,
        Some(l) => {
            run.error(
                b,
                w.at(b'L'),
                format!("{name} L{l}: the repeat count must be a whole number from 1 to {MAX_PASSES}"),
            );
            return;
        }
    };
    let p = match (code, w.get(b'P')) {
        (820 | 860 | 890 | 740 | 840, Some(p)) => p,
        // G74/G84: the dwell at the bottom is optional; rs274ngc keeps the last one.
        (740 | 840, None) => run.cycles.lcnc.p,
        (820 | 860 | 890, None) if same => run.cycles.lcnc.p,
        (820 | 860 | 890, None) => {
            run.error(b, None, format!("{name} needs P (the dwell at the bottom, seconds)"));
            return;
        }
        (_, p) => p.unwrap_or(0.0),
    };
    if p < 0.0 {
        run.error(b, w.at(b'P'), format!("{name}: negative dwell P{p}"));
        return;
    }
    let q = match (code, w.get(b'Q')) {
        (730 | 830, Some(q)) => q,
        (730 | 830, None) if same => run.cycles.lcnc.q,
        (730 | 830, None) => {
            run.error(b, None, format!("{name} needs Q (the peck depth)"));
            return;
        }
        (_, q) => q.unwrap_or(0.0),
    };
    if matches!(code, 730 | 830) && q <= 0.0 {
        run.error(b, w.at(b'Q'), format!("{name}: the peck depth Q must be positive"));
        return;
    }
    // G73/G83 D: the retract above each peck (program units), else the default clearance.
    let clearance = match code {
        730 | 830 => w.get(b'D').map_or(PECK_CLEARANCE_MM, |d| d * s),
        _ => PECK_CLEARANCE_MM,
    };
    let Some(f) = feed(run, b, name) else { return };

    // The initial level: where the first cycle of a series found the tool.
    let old_z = if series {
        run.cycles.lcnc.initial_z
    } else {
        run.cycles.lcnc.initial_z = cur.y;
        cur.y
    };
    let (mut xa, x_step, r, bottom) = if run.modal.incremental {
        let step = x.map_or(0.0, |x| run.to_radius(x) * s);
        let r = old_z + r_word * s;
        (cur.x, step, r, r + z * s)
    } else {
        let xa = x.map_or(cur.x, |x| o.x + run.to_radius(x) * s);
        (xa, 0.0, o.y + r_word * s, o.y + z * s)
    };
    if r < bottom - 1e-9 {
        run.error(
            b,
            None,
            format!("{name}: the R plane lies below the bottom Z of the hole"),
        );
        return;
    }
    {
        let m = &mut run.cycles.lcnc;
        m.z = z;
        m.r = r_word;
        m.p = p;
        m.q = q;
    }
    let pecks = if matches!(code, 730 | 830) {
        ((r - bottom) / (q * s)).ceil()
    } else {
        1.0
    };
    if !(pecks.is_finite() && pecks * l as f64 <= MAX_PASSES as f64) {
        run.error(
            b,
            w.at(b'Q'),
            format!("{name} makes more than {MAX_PASSES} pecks; the cycle is not checked"),
        );
        return;
    }
    // Below the R plane: up to it first, along Z.
    let (mut z_now, mut old) = (cur.y, old_z);
    if old < r {
        rapid(run, b, P2::new(cur.x, r));
        old = r;
        z_now = r;
    }
    let clear = if run.cycles.lcnc.retract_to_old_z { old } else { r };
    let delta = q * s;
    for repeat in 0..l {
        xa += x_step;
        if repeat == 0 && z_now > r {
            rapid(run, b, P2::new(xa, z_now));
            rapid(run, b, P2::new(xa, r));
        } else {
            rapid(run, b, P2::new(xa, clear));
            if clear > r {
                rapid(run, b, P2::new(xa, r));
            }
        }
        let at = |z: f64| P2::new(xa, z);
        match code {
            730 | 830 => {
                let mut d = r - delta;
                while d > bottom {
                    emit(run, b, MoveKind::Line, at(d), f, 0);
                    if code == 830 {
                        rapid(run, b, at(r));
                    }
                    rapid(run, b, at(d + clearance));
                    d -= delta;
                }
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                rapid(run, b, at(clear));
            }
            810 => {
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                rapid(run, b, at(clear));
            }
            820 => {
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                dwell(run, b, p);
                rapid(run, b, at(clear));
            }
            850 => {
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                emit(run, b, MoveKind::Line, at(r), f, 0);
                rapid(run, b, at(clear));
            }
            860 => {
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                dwell(run, b, p);
                // The spindle stops for the rapid out and starts again in its direction.
                let dir = run.spindle_dir;
                run.spindle_dir = SpindleDir::Off;
                rapid(run, b, at(clear));
                run.spindle_dir = dir;
            }
            740 | 840 => {
                // Tapping: feed in, reverse the spindle, dwell, feed out, forward again.
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                let dir = run.spindle_dir;
                run.spindle_dir = if dir == SpindleDir::Cw {
                    SpindleDir::Ccw
                } else {
                    SpindleDir::Cw
                };
                dwell(run, b, p);
                emit(run, b, MoveKind::Line, at(clear), f, 0);
                run.spindle_dir = dir;
            }
            _ => {
                // G89: dwell at the bottom, feed out.
                emit(run, b, MoveKind::Line, at(bottom), f, 0);
                dwell(run, b, p);
                emit(run, b, MoveKind::Line, at(clear), f, 0);
            }
        }
    }
}

fn dwell(run: &mut Run<'_>, b: &Block, seconds: f64) {
    if seconds > 0.0 {
        let p = run.programmed();
        run.push_move(b, MoveKind::Dwell { seconds }, p, p, Feed::Rapid);
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::{lathe, run};
    use crate::interp::MoveKind;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// Every drilling cycle stays on its X, never goes below the bottom of the hole nor above
        /// the higher of the initial level and R, reaches the bottom exactly, and ends at the
        /// clear level (R under G99, the higher of the initial level and R under G98); peck
        /// feeds are at most Q plus the peck clearance long.
        #[test]
        fn drilling_stays_between_the_bottom_and_the_clear_level(
            code in prop::sample::select(vec![73u16, 81, 82, 83, 85, 86, 89]),
            start in 5.0f64..40.0,
            r in 2.0f64..30.0,
            depth in 0.5f64..20.0,
            q in 0.3f64..6.0,
            x in -3.0f64..3.0,
            g98 in any::<bool>(),
        ) {
            let round = |v: f64| (v * 1e4).round() / 1e4;
            let (start, r, q, x) = (round(start), round(r), round(q), round(x));
            let bottom = round(r - depth);
            let src = format!(
                "G18 G8 G21 G90 G95\nT1 M6\nS800 M3\nG0 X{x:.4} Z{start:.4}\nG17\nF0.1\n{} G{code} X{x:.4} Z{bottom:.4} R{r:.4} Q{q:.4} P0.2\nG80\nM2\n",
                if g98 { "G98" } else { "G99" },
            );
            let out = run(&src);
            prop_assert!(out.findings.is_empty(), "{:?}", out.findings);
            let z0 = lathe().program_zero_z;
            let cyc: Vec<_> = out.moves.iter().filter(|m| m.line == 7).collect();
            prop_assert!(!cyc.is_empty());
            let top = start.max(r);
            let clear = if g98 { top } else { r };
            let mut deepest = f64::INFINITY;
            for m in &cyc {
                let (zs, ze) = (m.start.y - z0, m.end.y - z0);
                prop_assert!((m.end.x - x).abs() < 1e-9, "off the X: {:?}", m);
                prop_assert!(ze >= bottom - 1e-9 && ze <= top + 1e-9, "z {ze} outside [{bottom}, {top}]");
                deepest = deepest.min(ze);
                if matches!(code, 73 | 83) && m.kind == MoveKind::Line && ze < zs {
                    prop_assert!(zs - ze <= q + 0.254 + 1e-9, "a peck of {}", zs - ze);
                }
            }
            prop_assert!((deepest - bottom).abs() < 1e-9);
            let last = cyc.last().unwrap();
            prop_assert!((last.end.y - z0 - clear).abs() < 1e-9, "ends at {} not {clear}", last.end.y - z0);
        }
    }
}
