//! Fanuc / Haas stock removal: G71 (turning), G72 (facing), G73 (pattern repeat), G70
//! (finishing). See docs/cycles.md for the words, the passes and which manual each rule follows.

use super::common::{self, emit, feed, rapid, Seg, Traced, MAX_PASSES};
use crate::gcode::Block;
use crate::geom::{P2, V2};
use crate::interp::flow::Run;
use crate::interp::letters::Letters;
use crate::interp::{Feed, MoveKind};

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

pub(super) fn run(run: &mut Run<'_>, b: &Block, w: &mut Letters, code: u16, _at: u32) -> bool {
    match code {
        700 => g70(run, b, w),
        710 => g71_g72(run, b, w, Axes { facing: false }),
        720 => g71_g72(run, b, w, Axes { facing: true }),
        730 => g73(run, b, w),
        _ => return false,
    }
    true
}

/// The finishing allowance (Δu/2, Δw) in mm: U (diameter) or Haas I (radius), W or Haas K.
fn allowance(run: &Run<'_>, w: &mut Letters) -> V2 {
    let s = run.scale();
    let x = match w.get(b'I') {
        Some(i) => i * s,
        None => run.to_radius(w.get(b'U').unwrap_or(0.0)) * s,
    };
    let z = w.get(b'K').or_else(|| w.get(b'W')).unwrap_or(0.0) * s;
    V2::new(x, z)
}

/// Most a depth, retract, allowance or relief may be, mm: anything larger is a typing error, and
/// it would put the passes out of any machine's range.
const MAX_CYCLE_VALUE_MM: f64 = 10_000.0;

/// The cycle's lengths are finite and within [`MAX_CYCLE_VALUE_MM`]; else a finding at its line.
fn in_range(run: &mut Run<'_>, b: &Block, name: &str, values: &[f64]) -> bool {
    if values.iter().all(|v| v.is_finite() && v.abs() <= MAX_CYCLE_VALUE_MM) {
        return true;
    }
    run.error(
        b,
        None,
        format!("{name}: a depth, retract, allowance or relief beyond {MAX_CYCLE_VALUE_MM} mm"),
    );
    false
}

fn here(run: &Run<'_>) -> usize {
    run.pc.saturating_sub(1)
}

fn g71_g72(run: &mut Run<'_>, b: &Block, w: &mut Letters, ax: Axes) {
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
    let at = here(run);
    common::skip_profile(run, at, q);
    let mem = if ax.facing { run.cycles.g72 } else { run.cycles.g71 };
    // One-block D: as written (Haas), or on the old Fanuc controls (0-TC, 10T, 15T: `g71_d =
    // "increment"`) in the least input increment unless written with a decimal point.
    let d_word = if run.machine.g71_d == crate::machine::G71D::Increment {
        super::least(run, w, b'D')
    } else {
        w.get(b'D').map(|d| d * s)
    };
    let depth = d_word.or(mem.map(|m| m.0));
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
    if !in_range(run, b, name, &[depth, retract, off.x, off.y]) {
        return;
    }
    let Some(f) = feed(run, b, name) else { return };
    let a = run.programmed();
    let Some(t) = common::trace(run, b, at, p, q, name, false) else {
        return;
    };
    common::resume_after(run, at, t.q);
    rough(run, b, &t, a, off, depth, retract.abs(), f, ax, name);
}

/// Check the profile runs one way along the passes (both types) and in the stepping axis (type
/// I; type II may have pockets). The finding names the first profile block that turns back.
#[allow(clippy::too_many_arguments)]
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
        for p in samples(sgm, 16).into_iter().skip(1) {
            let (dd, da) = (ax.dep(p) - ax.dep(prev), ax.along(p) - ax.along(prev));
            let (dep_axis, along_axis) = if ax.facing { ("Z", "X") } else { ("X", "Z") };
            if dird * dd < -1e-6 && !type2 {
                run.error(
                    b,
                    None,
                    format!(
                        "{name} type I: the profile's {dep_axis} must move one way only, and line {} turns back",
                        sgm.line
                    ),
                );
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

/// The points of a segment at fractions 0, 1/n, …, 1 (n ≥ 1): its ends as `point_at` gives them,
/// an arc's inner points by turning one direction step by step (one sine and cosine per arc
/// rather than per point; they agree with `point_at` to a few units in the last place).
fn samples(s: &Seg, n: usize) -> Vec<P2> {
    let mut out = Vec::with_capacity(n + 1);
    out.push(s.point_at(0.0));
    if let MoveKind::Arc { center, sweep } = s.kind {
        let a = s.start - center;
        let (r0, r1) = (a.norm(), (s.end - center).norm());
        if r0 > 0.0 {
            let (sd, cd) = (sweep / n as f64).sin_cos();
            let mut dir = a / r0;
            for k in 1..n {
                dir = V2::new(dir.x * cd - dir.y * sd, dir.x * sd + dir.y * cd);
                let r = r0 + (r1 - r0) * (k as f64 / n as f64);
                out.push(center + dir * r);
            }
        } else {
            out.extend((1..n).map(|k| s.point_at(k as f64 / n as f64)));
        }
    } else {
        out.extend((1..n).map(|k| s.point_at(k as f64 / n as f64)));
    }
    out.push(s.point_at(1.0));
    out
}

/// A piece of the profile short enough that it crosses a level at most once in practice: a
/// line is one piece, an arc one piece per 1/64 turn. Its ends' stepping coordinates are
/// computed once per cycle, so a pass level is tested against them without trigonometry.
#[derive(Clone, Copy, Debug)]
struct Piece {
    seg: usize,
    t0: f64,
    t1: f64,
    /// The stepping coordinate at t0 and at t1.
    d0: f64,
    d1: f64,
}

fn pieces(segs: &[Seg], ax: Axes) -> Vec<Piece> {
    let mut out = Vec::new();
    for (i, s) in segs.iter().enumerate() {
        let n = match s.kind {
            MoveKind::Arc { sweep, .. } => {
                ((sweep.abs() / (std::f64::consts::TAU / 64.0)).ceil() as usize).clamp(1, 64)
            }
            _ => 1,
        };
        let pts = samples(s, n);
        let mut d0 = ax.dep(pts[0]);
        for k in 0..n {
            let t1 = (k + 1) as f64 / n as f64;
            let d1 = ax.dep(pts[k + 1]);
            out.push(Piece {
                seg: i,
                t0: k as f64 / n as f64,
                t1,
                d0,
                d1,
            });
            d0 = d1;
        }
    }
    out
}

/// Where an arc piece (t0..t1, its ends on either side of the level) meets the stepping
/// coordinate `level`: in closed form on the circle (an arccosine), then Newton steps when the
/// arc's start and end radii differ (the path interpolates its radius, see `path_point`).
fn arc_crossing(s: &Seg, center: P2, sweep: f64, t0: f64, t1: f64, level: f64, ax: Axes) -> f64 {
    let a = s.start - center;
    let (r0, r1) = (a.norm(), (s.end - center).norm());
    let a0 = a.y.atan2(a.x);
    let cd = ax.dep(center);
    // dep(θ) = cd + r·cos(θ − φ): φ is 0 when stepping in X, π/2 in Z.
    let phi = if ax.facing { std::f64::consts::FRAC_PI_2 } else { 0.0 };
    let radius = |t: f64| r0 + (r1 - r0) * t;
    if sweep.abs() < 1e-300 || r0.max(r1) < 1e-300 {
        return t1;
    }
    let tm = 0.5 * (t0 + t1);
    let base = ((level - cd) / radius(tm)).clamp(-1.0, 1.0).acos();
    let period = std::f64::consts::TAU / sweep.abs();
    let mut best = (f64::INFINITY, tm);
    for th in [phi + base, phi - base] {
        let raw = (th - a0) / sweep;
        let t = raw + ((tm - raw) / period).round() * period;
        let miss = (t0 - t).max(t - t1).max(0.0);
        if miss < best.0 {
            best = (miss, t);
        }
    }
    let mut t = best.1.clamp(t0, t1);
    if (r1 - r0).abs() > 1e-12 {
        for _ in 0..4 {
            let th = a0 + sweep * t - phi;
            let (sn, cs) = th.sin_cos();
            let g = cd + radius(t) * cs - level;
            let dg = (r1 - r0) * cs - radius(t) * sn * sweep;
            if dg.abs() < 1e-300 {
                break;
            }
            let next = (t - g / dg).clamp(t0, t1);
            if (next - t).abs() < 1e-16 {
                break;
            }
            t = next;
        }
    }
    t
}

/// One stretch of a level where the profile lies beyond it (material to cut): from `from` to
/// `to` along the pass; `from` is `None` for the stretch open toward the start point.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Stretch {
    from: Option<f64>,
    to: f64,
    /// The profile line where the stretch ends.
    line: u32,
}

/// The stretches of level `level` into `out` (cleared first): where the offset profile lies
/// deeper than the level, in the order a pass meets them. A type I profile has one, open toward
/// the start point; a type II profile one more per pocket. A line meets the level in one
/// division, an arc in an arccosine ([`arc_crossing`]).
fn stretches(segs: &[Seg], pieces: &[Piece], level: f64, dird: f64, ax: Axes, out: &mut Vec<Stretch>) {
    out.clear();
    let f = |d: f64| dird * (d - level);
    let Some(first) = segs.first() else { return };
    let mut inside = f(ax.dep(first.start)) < 0.0;
    let mut from: Option<f64> = None;
    for pc in pieces {
        let (f0, f1) = (f(pc.d0), f(pc.d1));
        let flips = if inside { f1 >= 0.0 } else { f1 < 0.0 };
        if !flips {
            continue;
        }
        let s = &segs[pc.seg];
        let (t0, t1) = (pc.t0, pc.t1);
        let t = match s.kind {
            MoveKind::Arc { center, sweep } => arc_crossing(s, center, sweep, t0, t1, level, ax),
            _ if (f1 - f0).abs() > 0.0 => t0 + (t1 - t0) * (-f0 / (f1 - f0)).clamp(0.0, 1.0),
            _ => t1,
        };
        let at = ax.along(s.point_at(t));
        if inside {
            out.push(Stretch {
                from,
                to: at,
                line: s.line,
            });
        } else {
            from = Some(at);
        }
        inside = !inside;
    }
    if inside {
        let last = segs.last().unwrap_or(first);
        out.push(Stretch {
            from,
            to: ax.along(last.end),
            line: last.line,
        });
    }
}

/// Most (pass level × profile piece) tests one cycle may spend.
const MAX_LEVEL_WORK: f64 = 2e7;

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
    let pcs = pieces(&prof, ax);
    // The deepest point of the profile (type II: a pocket may lie deeper than its first point).
    let mut deepest = dird * ax.dep(first);
    for pc in &pcs {
        deepest = deepest.min(dird * pc.d1);
    }
    for sgm in &prof {
        if let MoveKind::Arc { .. } = sgm.kind {
            for p in &samples(sgm, 8)[1..8] {
                deepest = deepest.min(dird * ax.dep(*p));
            }
        }
    }
    let infeed = |run: &mut Run<'_>, b: &Block, to: P2| match t.approach.map(|s| s.kind) {
        Some(MoveKind::Line) => emit(run, b, MoveKind::Line, to, f, t.approach.map_or(0, |s| s.line)),
        _ => rapid(run, b, to),
    };
    let span = dird * ax.dep(a) - deepest;
    let passes = if span > 1e-9 { (span / depth - 1e-9).ceil() } else { 0.0 };
    if passes > MAX_PASSES as f64 || passes * pcs.len() as f64 > MAX_LEVEL_WORK {
        run.error(
            b,
            None,
            format!(
                "{name}: a depth of cut of {depth} mm over {span:.3} mm makes too many passes (at most {MAX_PASSES})"
            ),
        );
        return;
    }
    let (a0, d0) = (ax.along(a), ax.dep(a));
    let m0 = run.moves.len();
    let mut sts = Vec::new();
    for k in 1..passes as usize {
        if common::too_many_moves(run, b, m0, name) {
            return;
        }
        let level = d0 - dird * depth * k as f64;
        let above = d0 - dird * depth * (k - 1) as f64;
        stretches(&prof, &pcs, level, dird, ax, &mut sts);
        for &st in &sts {
            let len = dira * (st.to - st.from.unwrap_or(a0));
            if len <= 1e-9 {
                continue;
            }
            let slide = e.min(len);
            match st.from {
                None => {
                    // Open toward the start point: in at the start's Z, as type I.
                    infeed(run, b, ax.pt(level, a0));
                    emit(run, b, MoveKind::Line, ax.pt(level, st.to), f, st.line);
                    rapid(run, b, ax.pt(level + dird * e, st.to - dira * slide));
                    rapid(run, b, ax.pt(level + dird * e, a0));
                }
                Some(from) => {
                    // A pocket: over it at the start level, down to the level above (cleared by
                    // the pass before), feed down to this level, along, and out the same way.
                    let here = run.programmed();
                    rapid(run, b, ax.pt(d0, ax.along(here)));
                    rapid(run, b, ax.pt(d0, from));
                    rapid(run, b, ax.pt(above, from));
                    emit(run, b, MoveKind::Line, ax.pt(level, from), f, st.line);
                    emit(run, b, MoveKind::Line, ax.pt(level, st.to), f, st.line);
                    rapid(run, b, ax.pt(level + dird * e, st.to - dira * slide));
                    rapid(run, b, ax.pt(d0, st.to - dira * slide));
                    rapid(run, b, a);
                }
            }
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
fn g70(run: &mut Run<'_>, b: &Block, w: &mut Letters) {
    let Some(p) = w.get(b'P') else {
        run.error(b, None, "G70 needs P and Q, the profile's first and last blocks".into());
        return;
    };
    let Some(q) = w.get(b'Q') else {
        run.error(b, w.at(b'P'), "G70 P… needs Q, the profile's last block".into());
        return;
    };
    let at = here(run);
    // After G70 the control reads the block after it (the profile is normally before it, with
    // its roughing cycle), so nothing is skipped.
    // Haas programs often repeat G71's U W D in G70: the control ignores them.
    for l in [b'U', b'W', b'D', b'I', b'K'] {
        w.get(l);
    }
    let a = run.programmed();
    let Some(t) = common::trace(run, b, at, p, q, "G70", true) else {
        return;
    };
    let first = t.approach.map_or(a, |s| s.end);
    let dird = sign(a.x - first.x, 1.0);
    return_to(run, b, a, dird, Axes { facing: false });
}

/// G73: the profile repeated d times, shifted by the relief (Δi, Δk) on the first pass and by
/// nothing but the allowance on the last.
fn g73(run: &mut Run<'_>, b: &Block, w: &mut Letters) {
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
    let at = here(run);
    common::skip_profile(run, at, q);
    let (mut ri, mut rk, mut n) = run.cycles.g73.unwrap_or((0.0, 0.0, 1.0));
    // Haas one-block form: I, K relief (radius, Z), D passes; U W allowance.
    let off = {
        let x = run.to_radius(w.get(b'U').unwrap_or(0.0)) * run.scale();
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
    if !in_range(run, b, "G73", &[ri, rk, off.x, off.y]) {
        return;
    }
    let Some(f) = feed(run, b, "G73") else { return };
    let a = run.programmed();
    let Some(t) = common::trace(run, b, at, p, q, "G73", false) else {
        return;
    };
    common::resume_after(run, at, t.q);
    let first = t.approach.map_or(a, |s| s.end);
    let dird = sign(a.x - first.x, 1.0);
    let n = n as usize;
    let m0 = run.moves.len();
    for k in 1..=n {
        if common::too_many_moves(run, b, m0, "G73") {
            return;
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The crossings as they were first written: each piece's ends evaluated on the path, and an
    /// arc's crossing found by 60 bisection steps. The slow oracle for [`stretches`].
    fn stretches_by_bisection(segs: &[Seg], level: f64, dird: f64, ax: Axes) -> Vec<Stretch> {
        let f = |p: P2| dird * (ax.dep(p) - level);
        let mut out = Vec::new();
        let Some(first) = segs.first() else { return out };
        let mut inside = f(first.start) < 0.0;
        let mut from: Option<f64> = None;
        for pc in pieces(segs, ax) {
            let (s, t0, t1) = (&segs[pc.seg], pc.t0, pc.t1);
            let (p0, p1) = (s.point_at(t0), s.point_at(t1));
            let (f0, f1) = (f(p0), f(p1));
            let flips = if inside { f1 >= 0.0 } else { f1 < 0.0 };
            if !flips {
                continue;
            }
            let t = match s.kind {
                MoveKind::Arc { .. } => {
                    let (mut lo, mut hi) = (t0, t1);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if (f(s.point_at(mid)) < 0.0) == (f0 < 0.0) {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    hi
                }
                _ if (f1 - f0).abs() > 0.0 => t0 + (t1 - t0) * (-f0 / (f1 - f0)).clamp(0.0, 1.0),
                _ => t1,
            };
            let at = ax.along(s.point_at(t));
            if inside {
                out.push(Stretch {
                    from,
                    to: at,
                    line: s.line,
                });
            } else {
                from = Some(at);
            }
            inside = !inside;
        }
        if inside {
            let last = segs.last().unwrap_or(first);
            out.push(Stretch {
                from,
                to: ax.along(last.end),
                line: last.line,
            });
        }
        out
    }

    /// A random profile in the XZ plane: lines and arcs (either way, up to a half turn, the end
    /// radius off by up to `skew` as the interpreter tolerates), chained end to start.
    fn profile() -> impl Strategy<Value = Vec<Seg>> {
        let step = (0u8..3, 0.1f64..8.0, -8.0f64..8.0, 0.1f64..3.1, -1e-3f64..1e-3);
        (proptest::collection::vec(step, 1..9), -5.0f64..5.0).prop_map(|(steps, x0)| {
            let mut p = P2::new(x0, 0.0);
            let mut out = Vec::new();
            for (k, (kind, a, b, ang, skew)) in steps.into_iter().enumerate() {
                let line = k as u32 + 10;
                if kind == 0 {
                    let end = p + V2::new(b, -a);
                    out.push(Seg {
                        kind: MoveKind::Line,
                        start: p,
                        end,
                        line,
                    });
                    p = end;
                } else {
                    // An arc of radius a about a centre at angle b from p, sweeping ±ang.
                    let sweep = if kind == 1 { ang } else { -ang };
                    let center = p + V2::new(b.cos(), b.sin()) * a;
                    let s0 = (p - center).y.atan2((p - center).x);
                    let r1 = a + skew;
                    let end = center + V2::new((s0 + sweep).cos(), (s0 + sweep).sin()) * r1;
                    out.push(Seg {
                        kind: MoveKind::Arc { center, sweep },
                        start: p,
                        end,
                        line,
                    });
                    p = end;
                }
            }
            out
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(2000))]

        /// The closed-form crossings give the stretches the bisection gave, on random profiles
        /// of lines and arcs, for levels through and beside them, stepping either way in X or Z.
        #[test]
        fn closed_form_crossings_match_the_bisection(
            segs in profile(),
            frac in -0.1f64..1.1,
            dird in prop_oneof![Just(1.0), Just(-1.0)],
            facing in any::<bool>(),
        ) {
            let ax = Axes { facing };
            let pcs = pieces(&segs, ax);
            let lo = pcs.iter().map(|p| p.d0.min(p.d1)).fold(f64::MAX, f64::min);
            let hi = pcs.iter().map(|p| p.d0.max(p.d1)).fold(f64::MIN, f64::max);
            let level = lo + (hi - lo) * frac;
            let mut fast = Vec::new();
            stretches(&segs, &pcs, level, dird, ax, &mut fast);
            let slow = stretches_by_bisection(&segs, level, dird, ax);
            prop_assert_eq!(fast.len(), slow.len(), "{:?} vs {:?}", fast, slow);
            // A spiral arc (start and end radii differ: the small spiral rs274ngc tolerates) near
            // a level that grazes its extreme is ill-conditioned for both methods: a level error
            // of a few nm moves the crossing by up to a micron along the level there. Circles
            // agree to 1e-9.
            let spiral = segs.iter().any(|s| match s.kind {
                MoveKind::Arc { center, .. } => ((s.start - center).norm() - (s.end - center).norm()).abs() > 1e-12,
                _ => false,
            });
            let tol = if spiral { 1e-6 } else { 1e-9 };
            for (a, b) in fast.iter().zip(&slow) {
                prop_assert_eq!(a.line, b.line);
                prop_assert_eq!(a.from.is_some(), b.from.is_some());
                let d = (a.to - b.to).abs().max((a.from.unwrap_or(0.0) - b.from.unwrap_or(0.0)).abs());
                prop_assert!(d < tol, "{:?} vs {:?}", fast, slow);
            }
        }
    }

    proptest! {
        /// An arc's samples by turning one direction agree with `point_at` at every fraction.
        #[test]
        fn arc_samples_by_rotation_agree_with_point_at(segs in profile(), n in 1usize..65) {
            for s in &segs {
                let pts = samples(s, n);
                prop_assert_eq!(pts.len(), n + 1);
                for (k, p) in pts.iter().enumerate() {
                    let q = s.point_at(k as f64 / n as f64);
                    prop_assert!((p - q).norm() < 1e-12, "{:?} at {}/{}: {:?} vs {:?}", s, k, n, p, q);
                }
            }
        }
    }

    #[test]
    fn a_level_meets_a_quarter_arc_where_the_circle_says() {
        // Clockwise quarter circle of radius 5 about (10, -30): from (15, -30) to (10, -35).
        let s = Seg {
            kind: MoveKind::Arc {
                center: P2::new(10.0, -30.0),
                sweep: -std::f64::consts::FRAC_PI_2,
            },
            start: P2::new(15.0, -30.0),
            end: P2::new(10.0, -35.0),
            line: 7,
        };
        let ax = Axes { facing: false };
        let pcs = pieces(std::slice::from_ref(&s), ax);
        let mut out = Vec::new();
        // Stepping down in X from above: material where X > 13 runs from the start to where
        // X = 13 on the arc, z = -30 - sqrt(25 - 9) = -34.
        stretches(std::slice::from_ref(&s), &pcs, 13.0, -1.0, ax, &mut out);
        assert_eq!(out.len(), 1, "{out:?}");
        assert!((out[0].to - -34.0).abs() < 1e-12, "{out:?}");
        assert_eq!(out[0].line, 7);
    }
}
