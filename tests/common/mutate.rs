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

use latheguard::geom::{Polygon, P2};
use latheguard::interp::{Interpretation, Move, MoveKind};
use latheguard::machine::{Machine, Tool, TurretKind};
use latheguard::pipeline;
use std::collections::{BTreeMap, BTreeSet};

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
    /// The rapid that approaches a canned cycle moved into the bar.
    CycleApproachIntoStock,
    /// A canned cycle's profile block moved into the chuck (its Z past the jaw face).
    CycleProfileIntoChuck,
    /// A long boring bar put in the station a T word indexes to, where the turret reference
    /// point is close enough to the chuck that the bar ends in the jaws (a machine mutation).
    LongToolAtIndex,
}

impl MutKind {
    pub const ALL: [MutKind; 8] = [
        MutKind::RapidIntoStock,
        MutKind::RetractIntoPart,
        MutKind::ZPastJawFace,
        MutKind::G0ForG1,
        MutKind::SpindleStopBeforeCut,
        MutKind::CycleApproachIntoStock,
        MutKind::CycleProfileIntoChuck,
        MutKind::LongToolAtIndex,
    ];

    pub fn name(self) -> &'static str {
        match self {
            MutKind::RapidIntoStock => "rapid_target_into_stock",
            MutKind::RetractIntoPart => "retract_into_part",
            MutKind::ZPastJawFace => "z_past_jaw_face",
            MutKind::G0ForG1 => "g0_for_g1",
            MutKind::SpindleStopBeforeCut => "spindle_stop_before_cut",
            MutKind::CycleApproachIntoStock => "cycle_approach_into_stock",
            MutKind::CycleProfileIntoChuck => "cycle_profile_into_chuck",
            MutKind::LongToolAtIndex => "long_tool_at_index",
        }
    }
}

/// How a mutant's text differs from its program's (1-based lines).
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// The program is kept (a machine mutation).
    Keep,
    /// The line replaced.
    Replace(usize, String),
    /// A line inserted before the line.
    Insert(usize, String),
}

/// What reading the mutant back must show (see [`verify`]); checked when the mutant is made
/// ([`Mutants::realise`]), so that only the mutants a run samples are read back.
#[derive(Clone, Debug)]
struct Expect {
    k: usize,
    line: usize,
    end: P2,
    kind: Option<MoveKind>,
    spindle_on: Option<bool>,
}

/// One crashing variant of a program, described; [`Mutants::realise`] makes (and proves) it.
#[derive(Clone, Debug)]
pub struct Mutant {
    pub kind: MutKind,
    pub edit: Edit,
    /// The 1-based line (of the mutant) where the crash must be reported.
    pub line: u32,
    /// The 1-based line of the original program that was mutated.
    pub original_line: u32,
    /// Other lines (of the mutant) where a report also counts: a canned cycle's lines, when
    /// its profile block was mutated.
    pub also: Vec<u32>,
    /// The machine to check the mutant on, when the mutation is of the machine (the program is
    /// then unchanged).
    pub machine: Option<Machine>,
    /// `None`: already proved.
    expect: Option<Expect>,
}

/// The mutants of one program on one machine, with what proves them.
pub struct Mutants<'a> {
    o: Oracle<'a>,
    text: String,
    pub list: Vec<Mutant>,
}

impl Mutants<'_> {
    /// The mutant's text, when reading it back proves it (else `None`: dropped, never counted).
    pub fn realise(&self, m: &Mutant) -> Option<Vec<u8>> {
        let mut lines: Vec<&str> = self.text.split('\n').collect();
        match &m.edit {
            Edit::Keep => {}
            Edit::Replace(l, s) => lines[l - 1] = s,
            Edit::Insert(l, s) => lines.insert(l - 1, s),
        }
        let src = lines.join("\n").into_bytes();
        match &m.expect {
            None => Some(src),
            Some(e) => verify(&src, self.o.machine, &self.o, e.k, e.line, e.end, e.kind, e.spindle_on).then_some(src),
        }
    }

    /// The program's text as the mutants are made of it (not UTF-8 bytes read as U+FFFD).
    pub fn text(&self) -> &str {
        &self.text
    }
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

/// Every mutant of `src` on `machine` the oracle can prove (each still read back when made:
/// [`Mutants::realise`]), each kind in line order.
pub fn mutants<'a>(src: &[u8], machine: &'a Machine) -> Mutants<'a> {
    // Bytes that are not UTF-8 (a Latin-1 comment) are read as U+FFFD: the text the mutants
    // are made of. A lone CR ends a line for the reader, not for `split('\n')`: such files are
    // left alone.
    let text = String::from_utf8_lossy(src).to_string();
    let b = text.as_bytes();
    if (0..b.len()).any(|i| b[i] == b'\r' && b.get(i + 1) != Some(&b'\n')) {
        return Mutants {
            o: Oracle::new(src, machine),
            text,
            list: Vec::new(),
        };
    }
    let src = text.as_bytes();
    let lines: Vec<&str> = text.split('\n').collect();
    let o = Oracle::new(src, machine);
    let moves = &o.run.moves;
    let mut out = Vec::new();
    // Lines that run a canned cycle: a move along a profile, or three moves or more of which one
    // feeds (a G28's legs are rapids).
    let mut per_line: BTreeMap<u32, (usize, bool)> = BTreeMap::new();
    for m in moves {
        let e = per_line.entry(m.line).or_default();
        e.0 += 1;
        e.1 |= m.profile_line != 0;
        e.1 |= matches!(m.kind, MoveKind::Line | MoveKind::Arc { .. }) && e.0 >= 3;
    }
    let cycle_line = |line: u32| per_line.get(&line).is_some_and(|e| e.1);
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
                // The rapid right before a canned cycle's first move: the cycle's approach.
                let approach = moves.get(k + 1).is_some_and(|n| n.line != m.line && cycle_line(n.line));
                let kind = if approach {
                    MutKind::CycleApproachIntoStock
                } else {
                    MutKind::RapidIntoStock
                };
                if let Some(t) = cands.clone().find(|&t| o.in_material(t, k)) {
                    out.extend(retarget(kind, &lines, l, &p, frame, t, k));
                }
                if retract {
                    // A retract turned back into the part: from where the cut ended, down by d.
                    let s = m.start;
                    let cands = [MARGIN + 0.5, 3.0, 5.0]
                        .iter()
                        .flat_map(|&d| [P2::new(s.x - d, s.y), P2::new(s.x, s.y - d)]);
                    if let Some(t) = cands.clone().find(|&t| o.in_material(t, k)) {
                        out.extend(retarget(MutKind::RetractIntoPart, &lines, l, &p, frame, t, k));
                    }
                }
            }
            MoveKind::Line => {
                let axis = (m.end.x - m.start.x).abs() < 1e-9 || (m.end.y - m.start.y).abs() < 1e-9;
                let cuts = (1..10).any(|i| o.in_material(m.start + (m.end - m.start) * (i as f64 / 10.0), k));
                if cuts && axis {
                    if let Some((gs, ge, 1)) = p.g {
                        let nl = format!("{}G0{}", &lines[l - 1][..gs], &lines[l - 1][ge..]);
                        out.push(Mutant {
                            kind: MutKind::G0ForG1,
                            edit: Edit::Replace(l, nl),
                            line: l as u32,
                            original_line: l as u32,
                            also: Vec::new(),
                            machine: None,
                            expect: Some(Expect {
                                k,
                                line: l,
                                end: m.end,
                                kind: Some(MoveKind::Rapid),
                                spindle_on: None,
                            }),
                        });
                    }
                }
                if cuts {
                    out.push(Mutant {
                        kind: MutKind::SpindleStopBeforeCut,
                        edit: Edit::Insert(l, "M5 (SEEDED: SPINDLE STOP)".into()),
                        line: l as u32 + 1,
                        original_line: l as u32,
                        also: Vec::new(),
                        machine: None,
                        expect: Some(Expect {
                            k,
                            line: l + 1,
                            end: m.end,
                            kind: None,
                            spindle_on: Some(false),
                        }),
                    });
                }
            }
            _ => {}
        }
        // A Z past the jaw face (z = 0), at the move's radius or further out, into the jaws.
        if matches!(m.kind, MoveKind::Rapid | MoveKind::Line) && p.z.is_some() {
            let z = -(MARGIN + 0.5);
            let cands = (0..16).map(|i| P2::new(m.end.x + 5.0 * i as f64, z));
            if let Some(t) = cands.clone().find(|&t| o.in_chuck(t)) {
                out.extend(retarget(MutKind::ZPastJawFace, &lines, l, &p, frame, t, k));
            }
        }
    }
    out.extend(profile_mutants(&lines, machine, &o));
    out.extend(long_tool_mutants(src, machine, &o));
    Mutants {
        o,
        text: text.clone(),
        list: out,
    }
}

/// A canned cycle's profile block with its end moved past the jaw face, into the chuck (z =
/// −(MARGIN + 0.5), at the block's radius or up to 75 mm further out). Proved by reading the
/// mutant back: some move the cycle makes (at the cycle's line, or along that profile block)
/// ends with the tip inside the chuck, with a known tool; the moves before the cycle are the
/// original's. Detected at the cycle's line or the profile block's.
fn profile_mutants(lines: &[&str], machine: &Machine, o: &Oracle<'_>) -> Vec<Mutant> {
    let moves = &o.run.moves;
    // Profile block → the lines of the cycles that follow it.
    let mut blocks: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
    for m in moves.iter().filter(|m| m.profile_line != 0) {
        blocks.entry(m.profile_line).or_default().insert(m.line);
    }
    let mut out = Vec::new();
    for (lp, cycles) in blocks {
        let l = lp as usize;
        if l == 0 || l > lines.len() {
            continue;
        }
        let Some(p) = plain(lines[l - 1]) else { continue };
        let Some(m) = moves.iter().find(|m| m.profile_line == lp) else {
            continue;
        };
        let state = &o.run.states[m.state as usize];
        if state.tool_unknown {
            continue;
        }
        let z = -(MARGIN + 0.5);
        let Some(t) = (0..16)
            .map(|i| P2::new(m.end.x.abs() + 5.0 * i as f64, z))
            .find(|&t| o.in_chuck(t))
        else {
            continue;
        };
        let code = rewrite(lines[l - 1], &p, state.frame, t);
        let mut new = lines.to_vec();
        new[l - 1] = &code;
        let src = new.join("\n").into_bytes();
        let ours = |n: &Move| cycles.contains(&n.line) || n.line == lp || n.profile_line == lp;
        // The first move of the cycle (or of the profile block run as ordinary lines).
        let Some(k0) = moves.iter().position(&ours) else {
            continue;
        };
        let (_, run) = pipeline::interpret(&src, machine);
        if run.moves.len() <= k0 {
            continue;
        }
        let same = moves[..k0]
            .iter()
            .zip(&run.moves[..k0])
            .all(|(a, b)| (a.start - b.start).norm() < 1e-6 && (a.end - b.end).norm() < 1e-6);
        let into = run.moves[k0..]
            .iter()
            .any(|n| ours(n) && !run.states[n.state as usize].tool_unknown && o.in_chuck(n.end));
        if same && into {
            out.push(Mutant {
                kind: MutKind::CycleProfileIntoChuck,
                edit: Edit::Replace(l, code.clone()),
                expect: None,
                line: lp,
                original_line: lp,
                also: cycles.into_iter().collect(),
                machine: None,
            });
        }
    }
    out
}

/// The long boring bar put in `base`'s station: `extra` mm longer toward the chuck than the
/// tool it replaces, a 16 mm shank from its tip back to the turret, a 4 mm insert at the tip.
pub fn long_tool(base: &Tool, extra: f64) -> Option<Tool> {
    let rect = |x0: f64, x1: f64, z0: f64, z1: f64| {
        Polygon::new(&[P2::new(x0, z0), P2::new(x1, z0), P2::new(x1, z1), P2::new(x0, z1)]).ok()
    };
    Some(Tool {
        station: base.station,
        name: format!("seeded long boring bar ({extra} mm longer)"),
        tip: P2::new(base.tip.x, base.tip.y - extra),
        insert: rect(0.0, 4.0, 0.0, 4.0)?,
        holder: rect(0.0, SHANK, 2.0, extra + 40.0)?,
        nose_radius: 0.4,
        tip_direction: base.tip_direction,
        mill: None,
        cutter: latheguard::tooling::Cutter::Insert,
    })
}

/// The long tool's shank width, mm.
const SHANK: f64 = 16.0;

/// Smallest distance from the spindle axis of the points `(a + d·c, d·s)` for `a` in [a0, a1]
/// (where the turret axis is) and `d` in [d0, d1] (a point's distance from the turret axis, in
/// its station's plane turned by the angle whose cosine and sine are c, s). The squared
/// distance is convex in (a, d); minimised over `a` in closed form, over `d` by ternary search.
pub fn min_radius(a0: f64, a1: f64, d0: f64, d1: f64, c: f64, s: f64) -> f64 {
    let g = |d: f64| {
        let a = (-c * d).clamp(a0, a1);
        ((a + c * d).powi(2) + (s * d).powi(2)).sqrt()
    };
    let (mut lo, mut hi) = (d0, d1);
    for _ in 0..100 {
        let m1 = lo + (hi - lo) / 3.0;
        let m2 = hi - (hi - lo) / 3.0;
        if g(m1) <= g(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    g((lo + hi) / 2.0).min(g(d0)).min(g(d1))
}

/// Angle of `station` when the turret stands at (fractional) station `active`, by the drum's
/// geometry: stations evenly spaced round the turret axis.
fn angle(station: u32, active: f64, n: u32) -> f64 {
    (station as f64 - active) * std::f64::consts::TAU / n.max(1) as f64
}

/// The long tool in `station` stays clear of the raw bar's box, the chuck's and the
/// tailstock's (advanced or not) during every move before move `k`: for each move, the box of
/// the turret reference point (the path's box; an arc by its whole circle) and the angles the
/// station takes (fixed, or every angle an index sweeps, the short way round; both ways on a
/// tie), a lower bound on the tool's distance from the spindle axis against the obstacles' outer
/// radius wherever their z ranges meet.
fn clear_before(o: &Oracle<'_>, tool: &Tool, k: usize) -> bool {
    let machine = o.machine;
    let n = machine.turret.stations;
    let axis = machine.turret.axis;
    let mut obstacles: Vec<(f64, f64, f64)> = Vec::new(); // (r max, z min, z max)
    if let Some(s) = &machine.stock {
        obstacles.push((s.diameter / 2.0, s.front - s.length, s.front));
    }
    for poly in [&machine.chuck, &machine.tailstock].into_iter().flatten() {
        let b = poly.aabb();
        obstacles.push((b.max.x.max(-b.min.x), b.min.y, b.max.y));
    }
    let pts: Vec<P2> = tool
        .holder
        .points()
        .iter()
        .chain(tool.insert.points())
        .copied()
        .collect();
    let px = |f: fn(f64, f64) -> f64, init: f64| pts.iter().map(|p| p.x + tool.tip.x).fold(init, f);
    let pz = |f: fn(f64, f64) -> f64, init: f64| pts.iter().map(|p| p.y + tool.tip.y).fold(init, f);
    let (d0, d1) = (px(f64::min, f64::MAX) - axis, px(f64::max, f64::MIN) - axis);
    let (z0, z1) = (pz(f64::min, f64::MAX), pz(f64::max, f64::MIN));
    let reach = d0.abs().max(d1.abs());
    const GAP: f64 = 0.5;
    for m in &o.run.moves[..k] {
        let (rs, re) = (m.start - m.tip, m.end - m.tip);
        let (mut x0, mut x1) = (rs.x.min(re.x), rs.x.max(re.x));
        let (mut zz0, mut zz1) = (rs.y.min(re.y), rs.y.max(re.y));
        if let MoveKind::Arc { center, .. } = m.kind {
            let r = (m.start - center).norm().max((m.end - center).norm());
            let c = center - m.tip;
            x0 = x0.min(c.x - r);
            x1 = x1.max(c.x + r);
            zz0 = zz0.min(c.y - r);
            zz1 = zz1.max(c.y + r);
        }
        let (tz0, tz1) = (zz0 + z0, zz1 + z1);
        let near: Vec<f64> = obstacles
            .iter()
            .filter(|(_, oz0, oz1)| tz0 <= oz1 + GAP && *oz0 - GAP <= tz1)
            .map(|o| o.0)
            .collect();
        if near.is_empty() {
            continue;
        }
        let rmax = near.iter().copied().fold(f64::MIN, f64::max);
        // The angles: [from, to] in stations, the short way round; both ways on a tie.
        let (a, b) = match m.kind {
            MoveKind::ToolChange { from, to } if from != to => {
                let nn = n.max(1) as i64;
                let fwd = ((to as i64 - from as i64) % nn + nn) % nn;
                if 2 * fwd == nn {
                    (0.0, n as f64)
                } else if fwd < nn - fwd {
                    (from as f64, from as f64 + fwd as f64)
                } else {
                    (from as f64 - (nn - fwd) as f64, from as f64)
                }
            }
            _ => (m.station as f64, m.station as f64),
        };
        let span = (b - a).abs() * std::f64::consts::TAU / n.max(1) as f64;
        let step = 0.01;
        let samples = (span / step).ceil().max(0.0) as usize;
        let slack = reach * step / 2.0 + 1e-6;
        for i in 0..=samples {
            let u = if samples == 0 { 0.0 } else { i as f64 / samples as f64 };
            let th = angle(tool.station, a + (b - a) * u, n);
            let (s, c) = th.sin_cos();
            let r = min_radius(x0 + axis, x1 + axis, d0, d1, c, s) - if samples == 0 { 1e-6 } else { slack };
            if r <= rmax + GAP {
                return false;
            }
        }
    }
    true
}

/// Machine mutants: for each T word that indexes a drum turret to a station the program has not
/// used before (nor started in), the station's tool replaced by [`long_tool`] (60, 100, 150 or
/// 200 mm longer: the first that works). Proved by posing the bar where the index leaves it (the
/// station in the working plane, at angle 0 whichever way the drum turns, the reference point
/// where the T word finds it): a point of the shank's centre line whose ±`MARGIN` grid lies
/// inside the chuck outline; and by [`clear_before`]: the bar touches nothing before the T word.
/// Read back with the new machine: the moves up to the T word are the original's. Detected at
/// the T word's line.
fn long_tool_mutants(src: &[u8], machine: &Machine, o: &Oracle<'_>) -> Vec<Mutant> {
    if machine.turret.kind != TurretKind::Drum || machine.chuck.is_none() {
        return Vec::new();
    }
    let moves = &o.run.moves;
    let mut out = Vec::new();
    for (k, m) in moves.iter().enumerate() {
        let MoveKind::ToolChange { from, to } = m.kind else {
            continue;
        };
        if from == to || to == machine.turret.start_station {
            continue;
        }
        let used = moves[..k]
            .iter()
            .any(|e| e.station == to || matches!(e.kind, MoveKind::ToolChange { from: f, .. } if f == to));
        if used || o.run.states[m.state as usize].tool_unknown {
            continue;
        }
        let Some(base) = machine.tool(to) else { continue };
        let r = m.start - m.tip;
        for extra in [60.0, 100.0, 150.0, 200.0] {
            let Some(tool) = long_tool(base, extra) else { continue };
            let steps = ((extra + 38.0 - 2.0 * MARGIN) / 1.0) as usize;
            let x = r.x + tool.tip.x + SHANK / 2.0;
            let hits = (0..=steps).any(|i| {
                let z = r.y + tool.tip.y + 2.0 + MARGIN + i as f64;
                o.in_chuck(P2::new(x, z))
            });
            if !hits || !clear_before(o, &tool, k) {
                continue;
            }
            let mut mm = machine.clone();
            for t in mm.tools.iter_mut().filter(|t| t.station == to) {
                *t = tool.clone();
            }
            let (_, run) = pipeline::interpret(src, &mm);
            let same = run.moves.len() > k
                && moves[..=k].iter().zip(&run.moves[..=k]).all(|(a, b)| {
                    (a.start - a.tip - (b.start - b.tip)).norm() < 1e-6
                        && (a.end - a.tip - (b.end - b.tip)).norm() < 1e-6
                        && a.kind == b.kind
                        && a.line == b.line
                });
            if same {
                out.push(Mutant {
                    kind: MutKind::LongToolAtIndex,
                    edit: Edit::Keep,
                    expect: None,
                    line: m.line,
                    original_line: m.line,
                    also: Vec::new(),
                    machine: Some(mm),
                });
            }
            break;
        }
    }
    out
}

/// The line rewritten so that its move ends at `t` (spindle frame), to be verified.
#[allow(clippy::too_many_arguments)]
fn retarget(
    kind: MutKind,
    lines: &[&str],
    l: usize,
    p: &Plain,
    frame: latheguard::interp::ProgFrame,
    t: P2,
    k: usize,
) -> Option<Mutant> {
    Some(Mutant {
        kind,
        edit: Edit::Replace(l, rewrite(lines[l - 1], p, frame, t)),
        line: l as u32,
        original_line: l as u32,
        also: Vec::new(),
        machine: None,
        expect: Some(Expect {
            k,
            line: l,
            end: t,
            kind: None,
            spindle_on: None,
        }),
    })
}

/// `line` with its move's end rewritten to `t` (spindle frame): X and Z words replaced (or
/// added), the rest of the code kept, a trailing comment replaced by a mark, a CR kept.
fn rewrite(line: &str, p: &Plain, frame: latheguard::interp::ProgFrame, t: P2) -> String {
    let (px, pz) = frame.to_program(t);
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
    code.push_str(line[at..p.end].trim_end_matches('\r'));
    if p.x.is_none() {
        code.push_str(&format!(" X{px:.4}"));
    }
    if p.z.is_none() {
        code.push_str(&format!(" Z{pz:.4}"));
    }
    code.push_str(" (SEEDED CRASH)");
    if line.ends_with('\r') {
        code.push('\r');
    }
    code
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
