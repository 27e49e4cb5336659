//! Fanuc / Haas stock removal: G71 (turning), G72 (facing), G73 (pattern repeat), G70
//! (finishing). See docs/cycles.md for the words, the passes and which manual each rule follows.

use super::common::{self, emit, feed, rapid, Seg, Traced, MAX_PASSES};
use crate::gcode::Block;
use crate::geom::{P2, V2};
use crate::interp::block::Words;
use crate::interp::flow::Run;
use crate::interp::{Feed, MoveKind};
use crate::machine::Dialect;

/// Retract e when no `G71 U R` / `G72 W R` block set one (Haas: setting 73), mm.
const DEFAULT_RETRACT_MM: f64 = 0.5;

/// Which way the passes run: G71 cuts along Z and steps in X, G72 the reverse.
#[derive(Clone, Copy)]
struct Axes {
    /// Steps in Z (G72) rather than in X (G71).
    facing: bool,
}

impl Axes {
    /// The stepping ("depth") coordinate.
    fn dep(self, p: P2) -> f64 {
        if self.facing {
            p.y
        } else {
            p.x
        }
    }
    /// The coordinate a pass runs along.
    fn along(self, p: P2) -> f64 {
        if self.facing {
            p.x
        } else {
            p.y
        }
    }
    fn pt(self, dep: f64, along: f64) -> P2 {
        if self.facing {
            P2::new(along, dep)
        } else {
            P2::new(dep, along)
        }
    }
}

fn sign(v: f64, default: f64) -> f64 {
    if v > 1e-9 {
        1.0
    } else if v < -1e-9 {
        -1.0
    } else {
        default
    }
}

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Words, code: u16, _at: u32) -> bool {
    if run.machine.dialect != Dialect::Fanuc {
        return false; // LinuxCNC G70–G72 (o-word profiles) and G73 (drilling) are not here yet
    }
    match code {
        700 => g70(run, b, w),
        710 => g71_g72(run, b, w, Axes { facing: false }),
        720 => g71_g72(run, b, w, Axes { facing: true }),
        730 => g73(run, b, w),
        _ => return false,
    }
    true
}

/// X as a radius in mm (a diameter in diameter mode).
fn radius_mm(run: &Run<'_>, v: f64) -> f64 {
    let r = if run.modal.diameter { v / 2.0 } else { v };
    r * run.scale()
}

/// The finishing allowance (Δu/2, Δw) in mm: U (diameter) or Haas I (radius), W or Haas K.
fn allowance(run: &Run<'_>, w: &mut Words) -> V2 {
    let s = run.scale();
    let x = match w.get(b'I') {
        Some(i) => i * s,
        None => radius_mm(run, w.get(b'U').unwrap_or(0.0)),
    };
    let z = w.get(b'K').or_else(|| w.get(b'W')).unwrap_or(0.0) * s;
    V2::new(x, z)
}

fn here(run: &Run<'_>) -> usize {
    run.pc.saturating_sub(1)
}

fn g71_g72(run: &mut Run<'_>, b: &Block, w: &mut Words, ax: Axes) {
    let name = if ax.facing { "G72" } else { "G71" };
    let s = run.scale();
    if !w.peek(b'P') {
        // First block of the two-block form: G71 U(Δd) R(e) / G72 W(Δd) R(e).
        let d = w.get(if ax.facing { b'W' } else { b'U' });
        let e = w.get(b'R');
        let mem = if ax.facing {
            &mut run.cycles.g72
        } else {
            &mut run.cycles.g71
        };
        let (d0, e0) = mem.unwrap_or((0.0, DEFAULT_RETRACT_MM));
        *mem = Some((d.map_or(d0, |d| d * s), e.map_or(e0, |e| e * s)));
        return;
    }
    let p = w.get(b'P').unwrap_or(0.0);
    let Some(q) = w.get(b'Q') else {
        run.error(b, w.at(b'P'), format!("{name} P… needs Q, the profile's last block"));
        return;
    };
    let mem = if ax.facing { run.cycles.g72 } else { run.cycles.g71 };
    let depth = match w.get(b'D') {
        Some(d) => Some(d * s),
        None => mem.map(|m| m.0),
    };
    let retract = w
        .get(b'R')
        .map(|r| r * s)
        .or(mem.map(|m| m.1))
        .unwrap_or(DEFAULT_RETRACT_MM);
    let off = allowance(run, w);
    let Some(depth) = depth.filter(|d| *d > 0.0) else {
        run.error(
            b,
            None,
            format!(
                "{name} needs a positive depth of cut: a {name} {}(Δd) R(e) block before it, or D in this block",
                if ax.facing { "W" } else { "U" }
            ),
        );
        return;
    };
    let Some(f) = feed(run, b, name) else { return };
    let a = run.programmed();
    let at = here(run);
    let Some(t) = common::trace(run, b, at, p, q, name, false) else {
        return;
    };
    common::resume_after(run, at, t.q);
    rough(run, b, &t, a, off, depth, retract.abs(), f, ax, name);
}

/// Check the profile runs one way on both axes (type I, and type II without pockets). The
/// finding names the first profile block that turns back.
fn monotone(
    run: &mut Run<'_>,
    b: &Block,
    segs: &[Seg],
    dird: f64,
    dira: f64,
    ax: Axes,
    type2: bool,
    name: &str,
) -> bool {
    for sgm in segs {
        let mut prev = sgm.start;
        for k in 1..=16 {
            let p = sgm.point_at(k as f64 / 16.0);
            let (dd, da) = (ax.dep(p) - ax.dep(prev), ax.along(p) - ax.along(prev));
            let (dep_axis, along_axis) = if ax.facing { ("Z", "X") } else { ("X", "Z") };
            if dird * dd < -1e-6 {
                if type2 {
                    run.unsupported(
                        b,
                        None,
                        format!("{name} type II with a pocket (line {}: {dep_axis} turns back) is not modelled yet: its moves are not checked", sgm.line),
                        true,
                    );
                } else {
                    run.error(
                        b,
                        None,
                        format!(
                            "{name} type I: the profile's {dep_axis} must move one way only, and line {} turns back",
                            sgm.line
                        ),
                    );
                }
                return false;
            }
            if dira * da < -1e-6 {
                run.error(
                    b,
                    None,
                    format!(
                        "{name}: the profile's {along_axis} must move one way only, and line {} turns back",
                        sgm.line
                    ),
                );
                return false;
            }
            prev = p;
        }
    }
    true
}

/// Where a pass at stepping level `level` meets the profile: the first point along it that
/// reaches the level (the profile runs one way, so there is one), or its end.
fn crossing(segs: &[Seg], level: f64, dird: f64, ax: Axes) -> (f64, u32) {
    let reached = |p: P2| dird * (ax.dep(p) - level) >= 0.0;
    for sgm in segs {
        if !reached(sgm.end) {
            continue;
        }
        if reached(sgm.start) {
            return (ax.along(sgm.start), sgm.line);
        }
        let t = match sgm.kind {
            MoveKind::Arc { .. } => {
                let (mut lo, mut hi) = (0.0, 1.0);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if reached(sgm.point_at(mid)) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                hi
            }
            _ => (level - ax.dep(sgm.start)) / (ax.dep(sgm.end) - ax.dep(sgm.start)),
        };
        return (ax.along(sgm.point_at(t)), sgm.line);
    }
    segs.last().map_or((0.0, 0), |s| (ax.along(s.end), s.line))
}

#[allow(clippy::too_many_arguments)]
fn rough(run: &mut Run<'_>, b: &Block, t: &Traced, a: P2, off: V2, depth: f64, e: f64, f: Feed, ax: Axes, name: &str) {
    let first = t.approach.map_or(a, |s| s.end) + off;
    let prof: Vec<Seg> = t.segs.iter().map(|s| s.shifted(off)).collect();
    let last = prof.last().map_or(first, |s| s.end);
    let dird = sign(ax.dep(a) - ax.dep(first), 1.0);
    let dira = sign(ax.along(last) - ax.along(first), -1.0);
    if !monotone(run, b, &prof, dird, dira, ax, t.p_names_both, name) {
        return;
    }
    let infeed = |run: &mut Run<'_>, b: &Block, to: P2| match t.approach.map(|s| s.kind) {
        Some(MoveKind::Line) => emit(run, b, MoveKind::Line, to, f, t.approach.map_or(0, |s| s.line)),
        _ => rapid(run, b, to),
    };
    let span = dird * (ax.dep(a) - ax.dep(first));
    let passes = if span > 1e-9 { (span / depth - 1e-9).ceil() } else { 0.0 };
    if passes > MAX_PASSES as f64 {
        run.error(
            b,
            None,
            format!("{name}: a depth of cut of {depth} mm over {span:.3} mm makes more than {MAX_PASSES} passes"),
        );
        return;
    }
    let a0 = ax.along(a);
    for k in 1..passes as usize {
        let level = ax.dep(a) - dird * depth * k as f64;
        infeed(run, b, ax.pt(level, a0));
        let (end, line) = crossing(&prof, level, dird, ax);
        if dira * (end - a0) > 1e-9 {
            emit(run, b, MoveKind::Line, ax.pt(level, end), f, line);
            rapid(run, b, ax.pt(level + dird * e, end - dira * e));
            rapid(run, b, ax.pt(level + dird * e, a0));
        }
    }
    // The last pass follows the profile offset by the allowance.
    infeed(run, b, first);
    for sgm in &prof {
        common::follow(run, b, sgm, f);
    }
    return_to(run, b, a, dird, ax);
}

/// Back to the start point at rapid, one axis at a time: first along the pass direction when
/// the tool is already outside the start level, else first back to the start level.
fn return_to(run: &mut Run<'_>, b: &Block, a: P2, dird: f64, ax: Axes) {
    let here = run.programmed();
    if dird * (ax.dep(here) - ax.dep(a)) >= -1e-9 {
        rapid(run, b, ax.pt(ax.dep(here), ax.along(a)));
    } else {
        rapid(run, b, ax.pt(ax.dep(a), ax.along(here)));
    }
    rapid(run, b, a);
}

/// G70 P Q: the profile as programmed, with its own F, S and T, then back to the start point.
fn g70(run: &mut Run<'_>, b: &Block, w: &mut Words) {
    let Some(p) = w.get(b'P') else {
        run.error(b, None, "G70 needs P and Q, the profile's first and last blocks".into());
        return;
    };
    let Some(q) = w.get(b'Q') else {
        run.error(b, w.at(b'P'), "G70 P… needs Q, the profile's last block".into());
        return;
    };
    // Haas programs often repeat G71's U W D in G70: the control ignores them.
    for l in [b'U', b'W', b'D', b'I', b'K'] {
        w.get(l);
    }
    let a = run.programmed();
    let at = here(run);
    let Some(t) = common::trace(run, b, at, p, q, "G70", true) else {
        return;
    };
    common::resume_after(run, at, t.q);
    let first = t.approach.map_or(a, |s| s.end);
    let dird = sign(a.x - first.x, 1.0);
    return_to(run, b, a, dird, Axes { facing: false });
}

/// G73: the profile repeated d times, shifted by the relief (Δi, Δk) on the first pass and by
/// nothing but the allowance on the last.
fn g73(run: &mut Run<'_>, b: &Block, w: &mut Words) {
    let s = run.scale();
    if !w.peek(b'P') {
        // G73 U(Δi) W(Δk) R(d)
        let (i0, k0, d0) = run.cycles.g73.unwrap_or((0.0, 0.0, 1.0));
        let i = w.get(b'U').map_or(i0, |u| u * s);
        let k = w.get(b'W').map_or(k0, |v| v * s);
        let d = w.get(b'R').unwrap_or(d0);
        run.cycles.g73 = Some((i, k, d));
        return;
    }
    let p = w.get(b'P').unwrap_or(0.0);
    let Some(q) = w.get(b'Q') else {
        run.error(b, w.at(b'P'), "G73 P… needs Q, the profile's last block".into());
        return;
    };
    let (mut ri, mut rk, mut n) = run.cycles.g73.unwrap_or((0.0, 0.0, 1.0));
    // Haas one-block form: I, K relief (radius, Z), D passes; U W allowance.
    let off = {
        let x = radius_mm(run, w.get(b'U').unwrap_or(0.0));
        let z = w.get(b'W').unwrap_or(0.0) * s;
        V2::new(x, z)
    };
    if let Some(i) = w.get(b'I') {
        ri = i * s;
    }
    if let Some(k) = w.get(b'K') {
        rk = k * s;
    }
    if let Some(d) = w.get(b'D') {
        n = d;
    }
    if !(n >= 1.0 && n.fract() == 0.0 && n <= MAX_PASSES as f64) {
        run.error(
            b,
            None,
            format!("G73: the number of passes must be a whole number from 1 to {MAX_PASSES}, not {n}"),
        );
        return;
    }
    let Some(f) = feed(run, b, "G73") else { return };
    let a = run.programmed();
    let at = here(run);
    let Some(t) = common::trace(run, b, at, p, q, "G73", false) else {
        return;
    };
    common::resume_after(run, at, t.q);
    let first = t.approach.map_or(a, |s| s.end);
    let dird = sign(a.x - first.x, 1.0);
    let n = n as usize;
    for k in 1..=n {
        let frac = if n == 1 { 0.0 } else { (n - k) as f64 / (n - 1) as f64 };
        let shift = off + V2::new(ri, rk) * frac;
        let to = first + shift;
        match t.approach.map(|s| s.kind) {
            Some(MoveKind::Line) => emit(run, b, MoveKind::Line, to, f, t.approach.map_or(0, |s| s.line)),
            _ => rapid(run, b, to),
        }
        for sgm in &t.segs {
            common::follow(run, b, &sgm.shifted(shift), f);
        }
        return_to(run, b, a, dird, Axes { facing: false });
    }
}
