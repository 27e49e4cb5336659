//! G76 multiple threading cycle.
//!
//! Two-block form (Fanuc 0i-TD B-64304EN, "multiple repetitive cycle", G76):
//! `G76 P(m)(r)(a) Q(Δdmin) R(d)` sets the finishing repetitions m, the chamfer-out r (in 0.1
//! lead), the tool angle a, the least cut Δdmin and the finishing allowance d; they stay until the
//! next such block. `G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L)` cuts: thread height k, first depth Δd,
//! taper i (radius, start minus end), lead L. P(k), Q(Δd) and Q(Δdmin) are in the least input
//! increment (0.001 mm, 0.0001 in) unless written with a decimal point.
//!
//! One-block form (Haas lathe operator's manual, G76): `G76 X(U) Z(W) K D F [A] [I] [P]`: K the
//! thread height, D the first depth, A the tool angle (default 0: radial infeed), I the taper, Q the
//! thread start angle (no effect on the path), F (or E) the lead,
//! P the infeed method (1 single edge, constant area, the default; 2 both edges, constant area;
//! 3 single edge, constant depth; 4 both edges, constant depth).
//!
//! Passes: depth Δd·√n for pass n (constant area; Δd·n for constant depth), an increment never
//! below Δdmin, roughing up to k − d; then m finishing passes at k. With single-edge infeed each
//! pass is shifted back along the cut by (k − depth)·tan(a/2) so that the tool follows one flank.
//! Each pass: a rapid from the start point to the pass start, the thread move (spindle
//! synchronised, feed per revolution = lead), with r > 0 a 45° chamfer-out of length r·L/10 at
//! its end, the rapid out in X to the start X and the rapid back to the start point.

use super::super::flow::Run;
use super::super::{Feed, MoveKind};
use super::box_::go;
use crate::gcode::Block;
use crate::geom::P2;
use crate::interp::letters::Letters;

/// Passes one cycle may make; more is a `program` finding (a tiny Δd with no Δdmin).
pub(crate) const MAX_PASSES: usize = 10_000;

/// The first-block words of the two-block G76.
#[derive(Clone, Copy, Debug)]
pub(crate) struct G76Params {
    /// Finishing passes m.
    pub m: u32,
    /// Chamfer-out r, in tenths of the lead.
    pub r: u32,
    /// Tool angle a, degrees.
    pub a: f64,
    /// Least depth increment Δdmin, mm.
    pub dmin: f64,
    /// Finishing allowance d, mm.
    pub d: f64,
}

impl Default for G76Params {
    /// What a control holds before any first block: one finishing pass, no chamfer, 60°, no
    /// least increment, no allowance.
    fn default() -> Self {
        G76Params {
            m: 1,
            r: 0,
            a: 60.0,
            dmin: 0.0,
            d: 0.0,
        }
    }
}

pub(super) fn g76(run: &mut Run<'_>, b: &Block, w: &mut Letters, at: u32) -> bool {
    let axis = w.peek(b'X') || w.peek(b'Z') || w.peek(b'U') || w.peek(b'W');
    if !axis {
        first_block(run, b, w, at);
    } else if w.peek(b'K') || w.peek(b'D') {
        haas(run, b, w, at);
    } else {
        second_block(run, b, w, at);
    }
    run.check_unused(b, w);
    true
}

fn first_block(run: &mut Run<'_>, b: &Block, w: &mut Letters, at: u32) {
    let mut g = run.cycles.g76;
    if let Some(p) = w.get(b'P') {
        if !(0.0..=999_999.0).contains(&p) || p.fract() != 0.0 {
            run.error(
                b,
                w.at(b'P'),
                format!("G76 P{p}: P is six digits mmrraa (repetitions, chamfer, angle)"),
            );
            return;
        }
        let p = p as u32;
        let (m, r, a) = (p / 10_000, (p / 100) % 100, p % 100);
        if m == 0 || !matches!(a, 0 | 29 | 30 | 55 | 60 | 80) {
            run.error(
                b,
                w.at(b'P'),
                format!("G76 P{p:06}: repetitions m must be 1–99 and the angle a one of 80, 60, 55, 30, 29, 0"),
            );
            return;
        }
        g.m = m;
        g.r = r;
        g.a = f64::from(a);
    }
    if let Some(q) = super::least(run, w, b'Q') {
        if q < 0.0 {
            run.error(b, w.at(b'Q'), "G76 Q (least depth of cut) must not be negative".into());
            return;
        }
        g.dmin = q;
    }
    if let Some(r) = w.get(b'R') {
        if r < 0.0 {
            run.error(b, w.at(b'R'), "G76 R (finishing allowance) must not be negative".into());
            return;
        }
        g.d = r * run.scale();
    }
    if !(w.peek(b'P') || w.peek(b'Q') || w.peek(b'R')) {
        run.error(
            b,
            Some(at),
            "G76 needs P, Q, R (first block) or X/Z with P, Q, F (second block)".into(),
        );
    }
    run.cycles.g76 = g;
}

/// The cut of one thread: everything a pass list needs.
struct Cut {
    end: P2,
    taper: f64,
    height: f64,
    first: f64,
    dmin: f64,
    allowance: f64,
    finish_passes: u32,
    angle_deg: f64,
    flank: bool,
    constant_depth: bool,
    chamfer: f64,
    lead: f64,
}

fn second_block(run: &mut Run<'_>, b: &Block, w: &mut Letters, _at: u32) {
    let g = run.cycles.g76;
    let Some(end) = run.target(b, w) else { return };
    let taper = w.get(b'R').unwrap_or(0.0) * run.scale();
    let (Some(k), Some(dd)) = (super::least(run, w, b'P'), super::least(run, w, b'Q')) else {
        run.error(
            b,
            None,
            "G76 second block needs P (thread height) and Q (first depth of cut)".into(),
        );
        return;
    };
    let Some(lead) = lead(run, b, w) else { return };
    let cut = Cut {
        end,
        taper,
        height: k,
        first: dd,
        dmin: g.dmin,
        allowance: g.d,
        finish_passes: g.m,
        angle_deg: g.a,
        flank: true,
        constant_depth: false,
        chamfer: f64::from(g.r) * 0.1 * lead,
        lead,
    };
    passes(run, b, &cut);
}

fn haas(run: &mut Run<'_>, b: &Block, w: &mut Letters, _at: u32) {
    let Some(end) = run.target(b, w) else { return };
    let s = run.scale();
    let taper = w.get(b'I').unwrap_or(0.0) * s;
    let (Some(k), Some(dd)) = (w.get(b'K'), w.get(b'D')) else {
        run.error(
            b,
            None,
            "G76 (one-block form) needs K (thread height) and D (first depth of cut)".into(),
        );
        return;
    };
    let angle = w.get(b'A').unwrap_or(0.0);
    if !(0.0..=120.0).contains(&angle) {
        run.error(
            b,
            w.at(b'A'),
            format!("G76 A{angle}: the tool angle is 0 to 120 degrees"),
        );
        return;
    }
    // Q: the thread start angle (where on the circle the thread begins): no effect on the path.
    w.get(b'Q');
    let method = w.get(b'P').unwrap_or(1.0);
    if !matches!(method as i64, 1..=4) || method.fract() != 0.0 {
        run.error(
            b,
            w.at(b'P'),
            format!("G76 P{method}: the infeed method is 1, 2, 3 or 4"),
        );
        return;
    }
    let method = method as u32;
    let Some(lead) = lead(run, b, w) else { return };
    let cut = Cut {
        end,
        taper,
        height: k * s,
        first: dd * s,
        dmin: 0.0,
        allowance: 0.0,
        finish_passes: 0,
        angle_deg: angle,
        flank: method == 1 || method == 3,
        constant_depth: method >= 3,
        chamfer: 0.0,
        lead,
    };
    passes(run, b, &cut);
}

/// The lead in mm: F of the block (also the modal F, as on the control), or the modal F.
fn lead(run: &mut Run<'_>, b: &Block, w: &mut Letters) -> Option<f64> {
    let f = w.get(b'F').or_else(|| w.get(b'E')).unwrap_or(run.modal.feed);
    if f.is_nan() || f <= 0.0 {
        run.error(b, None, "G76 needs the thread lead (F word)".into());
        return None;
    }
    Some(f * run.scale())
}

/// The depths of the passes (from the thread's crest), roughing then finishing; `None` when
/// there would be more than [`MAX_PASSES`].
pub(super) fn depths(
    height: f64,
    first: f64,
    dmin: f64,
    allowance: f64,
    finish: u32,
    constant_depth: bool,
) -> Option<Vec<f64>> {
    let rough = height - allowance;
    let mut out = Vec::new();
    let mut prev = 0.0f64;
    let mut n = 1.0f64;
    while prev < rough {
        let mut d = if constant_depth { prev + first } else { first * n.sqrt() };
        if d - prev < dmin {
            d = prev + dmin;
        }
        if d >= rough - 1e-9 || d <= prev {
            d = rough;
        }
        out.push(d);
        if out.len() > MAX_PASSES {
            return None;
        }
        prev = d;
        n += 1.0;
    }
    for _ in 0..finish {
        out.push(height);
    }
    Some(out)
}

fn passes(run: &mut Run<'_>, b: &Block, c: &Cut) {
    let s = run.programmed();
    let e = c.end;
    let sx = (s.x - e.x).signum();
    let dz = (e.y - s.y).signum();
    if s.x == e.x || s.y == e.y {
        run.error(
            b,
            None,
            "G76: the end point must differ from the start point in both X and Z (start X is the clearance)".into(),
        );
        return;
    }
    let valid = c.height > 0.0 && c.first > 0.0 && c.allowance < c.height && c.lead.is_finite();
    if !valid {
        run.error(
            b,
            None,
            format!(
                "G76: thread height {} and first depth {} must be positive and the allowance {} below the height",
                c.height, c.first, c.allowance
            ),
        );
        return;
    }
    let Some(depths) = depths(
        c.height,
        c.first,
        c.dmin,
        c.allowance,
        c.finish_passes,
        c.constant_depth,
    ) else {
        run.error(b, None, format!("G76 would make more than {MAX_PASSES} passes"));
        return;
    };
    if !super::charge(run, b, depths.len() as u64 * 5) {
        return;
    }
    let tan = if c.flank {
        (c.angle_deg.to_radians() / 2.0).tan()
    } else {
        0.0
    };
    let feed = Feed::PerRev(c.lead);
    for d in depths {
        let left = c.height - d;
        let off = -dz * left * tan;
        let x_end = e.x + sx * left;
        let p1 = P2::new(x_end + c.taper, s.y + off);
        let p3 = P2::new(x_end, e.y + off);
        go(run, b, MoveKind::Rapid, s, p1, Feed::Rapid);
        let out = if c.chamfer > 0.0 {
            // Straight thread up to the chamfer, then out at 45° over its length.
            let len = (p3.y - p1.y).abs();
            let ch = c.chamfer.min(len);
            let t = 1.0 - ch / len;
            let p2 = P2::new(p1.x + (p3.x - p1.x) * t, p3.y - dz * ch);
            let p4 = P2::new(p2.x + sx * ch, p3.y);
            go(run, b, MoveKind::Line, p1, p2, feed);
            go(run, b, MoveKind::Line, p2, p4, feed);
            p4
        } else {
            go(run, b, MoveKind::Line, p1, p3, feed);
            p3
        };
        let back = P2::new(s.x, out.y);
        go(run, b, MoveKind::Rapid, out, back, Feed::Rapid);
        go(run, b, MoveKind::Rapid, back, s, Feed::Rapid);
    }
}
