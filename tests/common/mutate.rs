//! Seeded crashes (mutation testing, `docs/mutation.md`): take a clean program and its machine,
//! rewrite one line so that the program crashes there by construction, and say where.
//!
//! Every mutant is proved a crash by a small oracle of its own, written for this file and sharing
//! nothing with the checker under test:
//! - the stock at a moment is bounded by the raw bar less the box each earlier move's insert could
//!   have swept (the box of the move's path, arcs by their whole circle, grown by the box of the
//!   station's insert outline): a point whose ±`MARGIN` box lies inside the raw bar and meets none
//!   of those boxes is surely still material;
//! - the chuck is the machine file's outline, tested with a point-in-polygon of this file's own.
//!
//! The interpreter is used only to learn where the program's moves go (the programmed tip in the
//! spindle frame), and each mutant is read back through it to confirm that the mutated line now
//! moves where the mutation meant and that nothing before it changed; a mutant that fails that
//! is dropped, never counted.

use latheguard::geom::P2;
use latheguard::interp::{Interpretation, MoveKind};
use latheguard::machine::Machine;
use latheguard::pipeline;

/// How deep inside material (or the chuck) a mutated point lies on every side, mm.
pub const MARGIN: f64 = 1.5;

/// The mutation kinds, in table order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum MutKind {
    /// A rapid's target moved into the stock.
    RapidIntoStock,
    /// A retract after a cut turned back into the part.
    RetractIntoPart,
    /// A move's Z taken past the jaw face, into the jaws.
    ZPastJawFace,
    /// G0 written where a G1 cut was.
    G0ForG1,
    /// A spindle stop (M5) put before a cut.
    SpindleStopBeforeCut,
}

impl MutKind {
    pub const ALL: [MutKind; 5] = [
        MutKind::RapidIntoStock,
        MutKind::RetractIntoPart,
        MutKind::ZPastJawFace,
        MutKind::G0ForG1,
        MutKind::SpindleStopBeforeCut,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MutKind::RapidIntoStock => "rapid_target_into_stock",
            MutKind::RetractIntoPart => "retract_into_part",
            MutKind::ZPastJawFace => "z_past_jaw_face",
            MutKind::G0ForG1 => "g0_for_g1",
            MutKind::SpindleStopBeforeCut => "spindle_stop_before_cut",
        }
    }
}

/// One crashing variant of a program.
#[derive(Clone, Debug)]
pub struct Mutant {
    pub kind: MutKind,
    pub src: Vec<u8>,
    /// The 1-based line (of the mutant) where the crash must be reported.
    pub line: u32,
    /// The 1-based line of the original program that was mutated.
    pub original_line: u32,
}

/// A plain motion line: an optional N word, at most one of G0/G00/G1/G01, X and/or Z, F, and
/// nothing else (comments aside). Returns the byte ranges of the X and Z numbers and of the G word.
struct Plain {
    g: Option<(usize, usize, u8)>,
    x: Option<(usize, usize)>,
    z: Option<(usize, usize)>,
    /// Where the code ends (before a comment).
    end: usize,
}

fn plain(line: &str) -> Option<Plain> {
    let b = line.as_bytes();
    let mut i = 0;
    let mut p = Plain {
        g: None,
        x: None,
        z: None,
        end: b.len(),
    };
    while i < b.len() {
        let c = b[i].to_ascii_uppercase();
        match c {
            b' ' | b'\t' | b'\r' => i += 1,
            b'(' | b';' => {
                p.end = i;
                // Only a trailing comment is allowed.
                let rest = &line[i..];
                if c == b'(' && rest.find(')').is_some_and(|e| !rest[e + 1..].trim().is_empty()) {
                    return None;
                }
                break;
            }
            b'N' | b'G' | b'X' | b'Z' | b'F' => {
                let s = i + 1;
                let mut e = s;
                while e < b.len() && (b[e].is_ascii_digit() || b[e] == b'.' || b[e] == b'-' || b[e] == b'+') {
                    e += 1;
                }
                let num = &line[s..e];
                let v: f64 = num.parse().ok()?;
                match c {
                    b'G' => {
                        if p.g.is_some() || !num.chars().all(|ch| ch.is_ascii_digit()) {
                            return None;
                        }
                        let g = match v as i64 {
                            0 => 0,
                            1 => 1,
                            _ => return None,
                        };
                        p.g = Some((i, e, g));
                    }
                    b'X' if p.x.is_none() => p.x = Some((s, e)),
                    b'Z' if p.z.is_none() => p.z = Some((s, e)),
                    b'N' | b'F' => {}
                    _ => return None,
                }
                i = e;
            }
            _ => return None,
        }
    }
    (p.x.is_some() || p.z.is_some()).then_some(p)
}

/// Axis-aligned box.
#[derive(Clone, Copy, Debug)]
struct Bx {
    x0: f64,
    x1: f64,
    z0: f64,
    z1: f64,
}

impl Bx {
    fn around(p: P2, m: f64) -> Bx {
        Bx {
            x0: p.x - m,
            x1: p.x + m,
            z0: p.y - m,
            z1: p.y + m,
        }
    }
    fn meets(&self, o: &Bx) -> bool {
        self.x0 <= o.x1 && o.x0 <= self.x1 && self.z0 <= o.z1 && o.z0 <= self.z1
    }
}

/// What the oracle knows about one program on one machine.
pub struct Oracle<'a> {
    machine: &'a Machine,
    run: Interpretation,
    /// Per move: the box its insert could sweep.
    swept: Vec<Bx>,
}

/// Point in polygon (even-odd), the machine file's own points.
fn inside(poly: &[P2], p: P2) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + n - 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            c = !c;
        }
    }
    c
}

impl<'a> Oracle<'a> {
    pub fn new(src: &[u8], machine: &'a Machine) -> Oracle<'a> {
        let (_, run) = pipeline::interpret(src, machine);
        let swept = run
            .moves
            .iter()
            .map(|m| {
                let (mut x0, mut x1) = (m.start.x.min(m.end.x), m.start.x.max(m.end.x));
                let (mut z0, mut z1) = (m.start.y.min(m.end.y), m.start.y.max(m.end.y));
                if let MoveKind::Arc { center, .. } = m.kind {
                    let r = (m.start - center).norm().max((m.end - center).norm());
                    x0 = x0.min(center.x - r);
                    x1 = x1.max(center.x + r);
                    z0 = z0.min(center.y - r);
                    z1 = z1.max(center.y + r);
                }
                // The insert's outline around the programmed point (an unknown tool: 100 mm).
                let (a, b, c, d) = match machine.tool(m.station) {
                    Some(t) => {
                        let pts = t.insert.points();
                        let f = |g: fn(&P2) -> f64, min: bool| {
                            pts.iter().map(g).fold(if min { f64::MAX } else { f64::MIN }, |acc, v| {
                                if min {
                                    acc.min(v)
                                } else {
                                    acc.max(v)
                                }
                            })
                        };
                        (f(|p| p.x, true), f(|p| p.x, false), f(|p| p.y, true), f(|p| p.y, false))
                    }
                    None => (-100.0, 100.0, -100.0, 100.0),
                };
                Bx {
                    x0: x0 + a,
                    x1: x1 + b,
                    z0: z0 + c,
                    z1: z1 + d,
                }
            })
            .collect();
        Oracle { machine, run, swept }
    }

    /// The tip at `p` lies at least [`MARGIN`] inside material on every side, by the stock as it
    /// is before move `k` (raw bar less every earlier move's swept box).
    fn in_material(&self, p: P2, k: usize) -> bool {
        let Some(s) = &self.machine.stock else { return false };
        let b = Bx::around(p, MARGIN);
        let (rb, rr) = (s.bore / 2.0, s.diameter / 2.0);
        if b.x0 < rb || b.x1 > rr || b.z0 < s.front - s.length || b.z1 > s.front {
            return false;
        }
        self.swept[..k].iter().all(|w| !w.meets(&b))
    }

    /// The point at `p`, and a grid of points within [`MARGIN`] of it, lie inside the chuck.
    fn in_chuck(&self, p: P2) -> bool {
        let Some(ch) = &self.machine.chuck else { return false };
        let pts = ch.points();
        (-2..=2).all(|i| {
            (-2..=2).all(|j| {
                let q = P2::new(p.x + MARGIN * i as f64 / 2.0, p.y + MARGIN * j as f64 / 2.0);
                inside(pts, q)
            })
        })
    }
}

/// Every mutant of `src` on `machine` the oracle can prove, each kind in line order.
pub fn mutants(src: &[u8], machine: &Machine) -> Vec<Mutant> {
    let Ok(text) = std::str::from_utf8(src) else {
        return Vec::new();
    };
    let lines: Vec<&str> = text.split('\n').collect();
    let o = Oracle::new(src, machine);
    let moves = &o.run.moves;
    let mut out = Vec::new();
    // Moves by line: only lines that make exactly one move of their own (no cycle, no profile).
    for (k, m) in moves.iter().enumerate() {
        let l = m.line as usize;
        if l == 0 || l > lines.len() || m.profile_line != 0 {
            continue;
        }
        if moves.iter().filter(|n| n.line == m.line).count() != 1 {
            continue;
        }
        let state = &o.run.states[m.state as usize];
        if state.tool_unknown || !state.spindle.is_on() {
            continue;
        }
        let Some(p) = plain(lines[l - 1]) else { continue };
        let frame = state.frame;
        match m.kind {
            MoveKind::Rapid => {
                // A rapid's target moved into the stock: the nearest candidate below or behind
                // the programmed target that the oracle proves is material.
                let e = m.end;
                let cands = [3.0, 5.0, 8.0, 12.0]
                    .iter()
                    .flat_map(|&d| [P2::new(e.x - d, e.y), P2::new(e.x, e.y - d), P2::new(e.x - d, e.y - d)]);
                let prev_cut = k > 0 && matches!(moves[k - 1].kind, MoveKind::Line | MoveKind::Arc { .. });
                let retract = prev_cut && m.end.x > m.start.x + 1e-6;
                if let Some(t) = cands.clone().find(|&t| o.in_material(t, k)) {
                    out.extend(retarget(
                        MutKind::RapidIntoStock,
                        &lines,
                        l,
                        &p,
                        frame,
                        t,
                        &o,
                        k,
                        machine,
                    ));
                }
                if retract {
                    // A retract turned back into the part: from where the cut ended, down by d.
                    let s = m.start;
                    let cands = [MARGIN + 0.5, 3.0, 5.0]
                        .iter()
                        .flat_map(|&d| [P2::new(s.x - d, s.y), P2::new(s.x, s.y - d)]);
                    if let Some(t) = cands.clone().find(|&t| o.in_material(t, k)) {
                        out.extend(retarget(
                            MutKind::RetractIntoPart,
                            &lines,
                            l,
                            &p,
                            frame,
                            t,
                            &o,
                            k,
                            machine,
                        ));
                    }
                }
            }
            MoveKind::Line => {
                let axis = (m.end.x - m.start.x).abs() < 1e-9 || (m.end.y - m.start.y).abs() < 1e-9;
                let cuts = (1..10).any(|i| o.in_material(m.start + (m.end - m.start) * (i as f64 / 10.0), k));
                if cuts && axis {
                    if let Some((gs, ge, 1)) = p.g {
                        let mut new = lines.clone();
                        let nl = format!("{}G0{}", &lines[l - 1][..gs], &lines[l - 1][ge..]);
                        new[l - 1] = &nl;
                        let src = new.join("\n").into_bytes();
                        if verify(&src, machine, &o, k, l, m.end, Some(MoveKind::Rapid), None) {
                            out.push(Mutant {
                                kind: MutKind::G0ForG1,
                                src,
                                line: l as u32,
                                original_line: l as u32,
                            });
                        }
                    }
                }
                if cuts {
                    let mut new: Vec<&str> = lines.clone();
                    new.insert(l - 1, "M5 (SEEDED: SPINDLE STOP)");
                    let src = new.join("\n").into_bytes();
                    if verify(&src, machine, &o, k, l + 1, m.end, None, Some(false)) {
                        out.push(Mutant {
                            kind: MutKind::SpindleStopBeforeCut,
                            src,
                            line: l as u32 + 1,
                            original_line: l as u32,
                        });
                    }
                }
            }
            _ => {}
        }
        // A Z past the jaw face (z = 0), at the move's radius or further out, into the jaws.
        if matches!(m.kind, MoveKind::Rapid | MoveKind::Line) && p.z.is_some() {
            let z = -(MARGIN + 0.5);
            let cands = (0..16).map(|i| P2::new(m.end.x + 5.0 * i as f64, z));
            if let Some(t) = cands.clone().find(|&t| o.in_chuck(t)) {
                out.extend(retarget(MutKind::ZPastJawFace, &lines, l, &p, frame, t, &o, k, machine));
            }
        }
    }
    out
}

/// The line rewritten so that its move ends at `t` (spindle frame), verified.
#[allow(clippy::too_many_arguments)]
fn retarget(
    kind: MutKind,
    lines: &[&str],
    l: usize,
    p: &Plain,
    frame: latheguard::interp::ProgFrame,
    t: P2,
    o: &Oracle<'_>,
    k: usize,
    machine: &Machine,
) -> Option<Mutant> {
    let (px, pz) = frame.to_program(t);
    let line = lines[l - 1];
    // Rebuild the code part: X and Z words replaced (or added), the rest kept.
    let mut code = String::new();
    let mut spans: Vec<(usize, usize, String)> = Vec::new();
    if let Some((s, e)) = p.x {
        spans.push((s, e, format!("{px:.4}")));
    }
    if let Some((s, e)) = p.z {
        spans.push((s, e, format!("{pz:.4}")));
    }
    spans.sort_by_key(|s| s.0);
    let mut at = 0;
    for (s, e, v) in &spans {
        code.push_str(&line[at..*s]);
        code.push_str(v);
        at = *e;
    }
    code.push_str(&line[at..p.end]);
    if p.x.is_none() {
        code.push_str(&format!(" X{px:.4}"));
    }
    if p.z.is_none() {
        code.push_str(&format!(" Z{pz:.4}"));
    }
    code.push_str(" (SEEDED CRASH)");
    let mut new = lines.to_vec();
    new[l - 1] = &code;
    let src = new.join("\n").into_bytes();
    verify(&src, machine, o, k, l, t, None, None).then_some(Mutant {
        kind,
        src,
        line: l as u32,
        original_line: l as u32,
    })
}

/// Read the mutant back: the moves before move `k` are the original's, and the move at `line`
/// ends at `end` (and is of `kind`, with the spindle `spindle_on`, when given).
#[allow(clippy::too_many_arguments)]
fn verify(
    src: &[u8],
    machine: &Machine,
    o: &Oracle<'_>,
    k: usize,
    line: usize,
    end: P2,
    kind: Option<MoveKind>,
    spindle_on: Option<bool>,
) -> bool {
    let (_, run) = pipeline::interpret(src, machine);
    if run.moves.len() <= k {
        return false;
    }
    let same = o.run.moves[..k]
        .iter()
        .zip(&run.moves[..k])
        .all(|(a, b)| (a.start - b.start).norm() < 1e-6 && (a.end - b.end).norm() < 1e-6);
    let m = &run.moves[k];
    same && m.line as usize == line
        && (m.end - end).norm() < 1e-3
        && kind.map_or(true, |kd| m.kind == kd)
        && spindle_on.map_or(true, |on| run.states[m.state as usize].spindle.is_on() == on)
}

/// At most `n` of `v`, evenly spaced (deterministic).
pub fn sample<T: Clone>(v: &[T], n: usize) -> Vec<T> {
    if v.len() <= n {
        return v.to_vec();
    }
    (0..n).map(|i| v[i * v.len() / n].clone()).collect()
}
