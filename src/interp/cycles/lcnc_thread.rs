//! LinuxCNC spindle-synchronised cycles: G33.1 rigid tapping and G76 threading, as the LinuxCNC
//! G-code reference describes them ("G33.1 Rigid Tapping", "G76 Threading Cycle"); the pass
//! arithmetic is rs274ngc's, so the moves match `rs274 -g` (tests/rs274_reference.rs). See
//! docs/cycles-linuxcnc.md for the words and passes.

use super::common::{emit, rapid, MAX_PASSES};
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::flow::Run;
use crate::interp::letters::Letters;
use crate::interp::state::Motion;
use crate::interp::{Feed, MoveKind, SpindleDir};

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, at: u32) -> bool {
    let at = (at > 0).then_some(at);
    let name = if code == 331 { "G33.1" } else { "G76" };
    if run.spindle_dir == SpindleDir::Off {
        run.error(b, at, format!("{name} needs the spindle turning (M3 or M4)"));
        return true;
    }
    let before = run.reports;
    if code == 331 {
        rigid_tap(run, b, w);
    } else {
        g76(run, b, w, at);
    }
    // A refused cycle is not in force afterwards (rs274ngc stops the program there).
    run.modal.motion = (run.reports == before).then_some(Motion::Cycle(code));
    true
}

/// G33.1 X Z K (I): feed to the point at K per revolution, reverse the spindle, feed back to
/// where the tap started. I (the retract speed factor) changes no path.
fn rigid_tap(run: &mut Run<'_>, b: &Block, w: &mut Letters) {
    let s = run.scale();
    let Some(k) = w.get(b'K').filter(|k| *k > 0.0) else {
        run.error(b, w.at(b'K'), "G33.1 needs K, the thread pitch (positive)".into());
        return;
    };
    w.get(b'I');
    let start = run.programmed();
    let Some(end) = run.target(b, w) else { return };
    let f = Feed::PerRev(k * s);
    emit(run, b, MoveKind::Line, end, f, 0);
    emit(run, b, MoveKind::Line, start, f, 0);
}

/// G76 P Z I J R K Q H E L: threading passes from the drive line (the current point).
fn g76(run: &mut Run<'_>, b: &Block, w: &mut Letters, at: Option<u32>) {
    if !run.modal.plane_xz {
        run.error(b, at, "G76 runs in the XZ plane: select G18".into());
        return;
    }
    let s = run.scale();
    let word = |w: &mut Letters, l: u8| w.get(l);
    let (p, i, j, k) = (word(w, b'P'), word(w, b'I'), word(w, b'J'), word(w, b'K'));
    let (r, q, h, e, l) = (
        word(w, b'R'),
        word(w, b'Q'),
        word(w, b'H'),
        word(w, b'E'),
        word(w, b'L'),
    );
    let Some(pitch) = p.filter(|p| *p > 0.0) else {
        run.error(b, at, "G76 needs P, the thread pitch (positive)".into());
        return;
    };
    let (Some(i), Some(j), Some(k)) = (i, j, k) else {
        run.error(
            b,
            at,
            "G76 needs I (thread peak offset), J (first cut depth) and K (thread depth)".into(),
        );
        return;
    };
    if i == 0.0 {
        run.error(b, at, "in G76, I must not be 0".into());
        return;
    }
    if j <= 0.0 {
        run.error(b, at, "in G76, J must be greater than 0".into());
        return;
    }
    if k <= j {
        run.error(b, at, "in G76, K must be greater than J".into());
        return;
    }
    let start = run.programmed();
    let Some(end) = run.target(b, w) else { return };
    // I, J, K are radii in mm here (diameters in G7).
    let rad = |run: &Run<'_>, v: f64| run.to_radius(v) * s;
    let (i, j, k) = (rad(run, i), rad(run, j), rad(run, k));
    let boring = i > 0.0;
    let safe_x = start.x;
    let full_dia_depth = i.abs();
    let start_depth = i.abs() + j.abs();
    let cut_increment = j.abs();
    let thread_height = k.abs();
    let end_depth = k.abs() + i.abs();
    let pitch = pitch * s;
    let towards_plus = end.y > start.y;
    let mut angle = q.unwrap_or(0.0);
    if angle == -1.0 {
        angle = 0.0;
    }
    let mut angle = angle.to_radians();
    if towards_plus {
        angle = -angle;
    }
    let tan = angle.tan();
    let spring = h.unwrap_or(0.0).max(0.0);
    let degression = r.filter(|r| *r >= 1.0).unwrap_or(1.0);
    let mut taper = e.map_or(0.0, |e| (e * s).max(0.0));
    let taper_pitch = if taper > 0.0 {
        pitch * taper.hypot(thread_height) / taper
    } else {
        pitch
    };
    if towards_plus {
        taper = -taper;
    }
    let flags = l.unwrap_or(0.0).max(0.0) as i64;
    let (entry, exit) = (flags & 1 != 0, flags & 2 != 0);
    let target_z = end.y + k.abs() * tan;

    // The passes before the full depth: depth = I + J·n^(1/R).
    let mut depths = Vec::new();
    let mut depth = start_depth;
    let mut n = 1.0f64;
    while depth < end_depth {
        if depths.len() >= MAX_PASSES {
            run.error(
                b,
                at,
                format!("G76 makes more than {MAX_PASSES} passes (J too small for K); the cycle is not checked"),
            );
            return;
        }
        depths.push(depth);
        n += 1.0;
        depth = full_dia_depth + cut_increment * n.powf(1.0 / degression);
    }
    if spring > MAX_PASSES as f64 {
        run.error(b, at, format!("G76 H{spring}: more than {MAX_PASSES} spring passes"));
        return;
    }
    for _ in 0..(spring as usize + 1) {
        depths.push(end_depth);
    }
    let x_at = |d: f64| if boring { safe_x + d } else { safe_x - d };
    for d in depths {
        let zoff = (d - full_dia_depth) * tan;
        let z0 = start.y - zoff;
        let z1 = target_z - zoff;
        let back = x_at(d - end_depth);
        let crest = x_at(d - thread_height);
        rapid(run, b, P2::new(back, z0));
        if taper != 0.0 && entry {
            emit(run, b, MoveKind::Line, P2::new(crest, z0), Feed::PerRev(taper_pitch), 0);
            emit(
                run,
                b,
                MoveKind::Line,
                P2::new(x_at(d), z0 - taper),
                Feed::PerRev(taper_pitch),
                0,
            );
        } else {
            rapid(run, b, P2::new(x_at(d), z0));
        }
        if taper != 0.0 && exit {
            emit(
                run,
                b,
                MoveKind::Line,
                P2::new(x_at(d), z1 + taper),
                Feed::PerRev(pitch),
                0,
            );
            emit(run, b, MoveKind::Line, P2::new(crest, z1), Feed::PerRev(taper_pitch), 0);
        } else {
            emit(run, b, MoveKind::Line, P2::new(x_at(d), z1), Feed::PerRev(pitch), 0);
        }
        rapid(run, b, P2::new(back, z1));
    }
    rapid(run, b, end);
}

#[cfg(test)]
mod tests {
    use super::super::test_support::run;
    use crate::interp::{Feed, MoveKind};
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]
        /// G76 (external, no taper): the threading feeds run at the pitch along Z, each pass at
        /// least as deep as the one before, all between the first cut depth |I|+J and the full
        /// depth |I|+K from the drive line, with H + 1 passes at exactly the full depth and as
        /// many shallower passes as depths I + J·n^(1/R) short of it.
        #[test]
        fn g76_passes_deepen_to_the_full_depth(
            drive in 8.0f64..20.0,
            i in 0.1f64..2.0,
            j in 0.1f64..0.5,
            extra in 0.1f64..2.0,
            degression in 1.0f64..2.0,
            h in 0usize..4,
            q in prop::sample::select(vec![0.0f64, 29.5, 30.0]),
        ) {
            let k = j + extra;
            let src = format!(
                "G18 G8 G21 G90 G95\nT3 M6\nS600 M3\nG0 X{drive:.4} Z5\nG76 P1.5 Z-10 I-{i:.4} J{j:.4} K{k:.4} R{degression:.4} H{h} Q{q}\nM2\n"
            );
            let out = run(&src);
            prop_assert!(out.findings.is_empty(), "{:?}", out.findings);
            let (i, j, k) = ((i * 1e4).round() / 1e4, (j * 1e4).round() / 1e4, (k * 1e4).round() / 1e4);
            let drive = (drive * 1e4).round() / 1e4;
            let degression = (degression * 1e4).round() / 1e4;
            let feeds: Vec<_> = out
                .moves
                .iter()
                .filter(|m| m.line == 5 && m.kind == MoveKind::Line)
                .collect();
            let mut expected_passes = 0;
            let mut n = 1.0f64;
            let mut d = i + j;
            while d < i + k {
                expected_passes += 1;
                n += 1.0;
                d = i + j * n.powf(1.0 / degression);
            }
            prop_assert_eq!(feeds.len(), expected_passes + h + 1);
            let mut prev = 0.0;
            for (p, m) in feeds.iter().enumerate() {
                prop_assert_eq!(m.feed, Feed::PerRev(1.5));
                prop_assert!((m.start.x - m.end.x).abs() < 1e-9 && m.end.y < m.start.y);
                let depth = drive - m.end.x;
                prop_assert!(depth >= i + j - 1e-9 && depth <= i + k + 1e-9, "depth {depth}");
                prop_assert!(depth >= prev - 1e-9);
                if p >= expected_passes {
                    prop_assert!((depth - (i + k)).abs() < 1e-9);
                }
                prev = depth;
            }
        }
    }
}
