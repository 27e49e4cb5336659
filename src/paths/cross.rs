//! The carriers of a multi-path machine against each other, in the working plane, over the
//! machine's one time.
//!
//! Each path's carrier is posed at its turret reference point (as the path's own check times
//! it, shifted by its waits: `sync.rs`) with its parts: the turret outline and every station's
//! holder and insert. A drum's other stations are turned out of the working plane; they are
//! drawn **projected** onto it (a point `d` from the turret axis at angle `a` lands `d·cos a`
//! from it), and while a drum indexes, every station at every angle is inside the box
//! `axis ± reach` (`reach` the farthest tool point from the turret axis). Two bodies that meet in
//! space meet in their projections, so this never misses a contact between carriers; it may
//! report two that pass each other at different heights (`y`) — docs/paths.md says where that
//! matters. A carrier across the spindle axis from path 1's turret (`opposite`) has its x
//! mirrored.
//!
//! The search is conservative advancement: at each probe the least distance between the two
//! carriers' parts, and a step no longer than that distance (at least the tolerance) at the sum
//! of the two reference points' greatest speeds, never past a move's start or end on either
//! path; a path standing still (a wait, a dwell, its program ended) moves nothing.

use std::collections::HashMap;

use crate::finding::{Finding, Kind, Severity};
use crate::geom::{query, Polygon, P2, TOUCH_EPS};
use crate::interp::{Interpretation, MoveKind};
use crate::machine::Machine;
use crate::motion::{self, Timeline};
use crate::scene::Scene;

use super::sync::Schedule;

/// Probes the search spends on one program before it gives up with a finding.
pub const MAX_PROBES: u64 = 2_000_000;

/// One path, as the cross check sees it.
pub struct Carriage<'a> {
    pub path: u32,
    /// What reports call its carrier ("upper turret").
    pub name: String,
    /// The lathe the path runs on ([`Machine::for_path`]).
    pub machine: &'a Machine,
    pub run: &'a Interpretation,
    pub timeline: &'a Timeline,
    pub schedule: &'a Schedule,
    /// Across the spindle axis from path 1's turret: x mirrored.
    pub opposite: bool,
}

/// A part of a carrier, relative to its reference point, in its own frame.
#[derive(Clone, Debug)]
struct Part {
    /// "turret", "T03 insert", "T03 holder", "the turret's stations indexing".
    label: String,
    poly: Polygon,
}

/// The pose of a carriage at an instant.
#[derive(Clone, Copy, Debug)]
struct Pose {
    /// The turret reference point.
    r: P2,
    /// The active station, or the index envelope while indexing (`None`).
    station: Option<u32>,
    /// Upper bound of the reference point's speed until `until` (mm/s).
    speed: f64,
    /// The next instant at which the speed bound or the parts change.
    until: f64,
    line: u32,
    n: Option<u64>,
    /// The programmed point in program coordinates (X as the program writes it).
    prog: Option<(f64, f64)>,
}

impl Carriage<'_> {
    /// The machine-time interval of move `k`.
    fn span_of(&self, k: usize) -> (f64, f64) {
        let it = &self.timeline.items[k];
        let g = self.schedule.global(it.index, it.t0);
        (g, g + it.duration)
    }

    /// Where the carriage stands at machine time `t`.
    fn pose(&self, t: f64, starts: &[f64]) -> Pose {
        let items = &self.timeline.items;
        let moves = &self.run.moves;
        // The last move that has started.
        let k = starts.partition_point(|&s| s <= t);
        if k == 0 {
            // Before its first move: at home with its start station.
            let until = starts.first().copied().unwrap_or(f64::INFINITY);
            let m0 = moves.first();
            return Pose {
                r: m0.map_or(self.machine.home, |m| m.ref_start()),
                station: Some(m0.map_or(self.machine.turret.start_station, |m| {
                    if let MoveKind::ToolChange { from, .. } = m.kind {
                        from
                    } else {
                        m.station
                    }
                })),
                speed: 0.0,
                until,
                line: m0.map_or(1, |m| m.line),
                n: None,
                prog: m0.map(|m| self.run.frame(m).to_program(m.start)),
            };
        }
        let i = k - 1;
        let it = &items[i];
        let m = &moves[it.index];
        let (g0, g1) = self.span_of(i);
        let next = starts.get(k).copied().unwrap_or(f64::INFINITY);
        if t < g1 {
            let indexing = matches!(m.kind, MoveKind::ToolChange { .. }) && it.duration > 0.0;
            let r = motion::reference_at(m, it, t - g0);
            Pose {
                r,
                prog: Some(self.run.frame(m).to_program(r + m.tip)),
                station: if indexing { None } else { Some(m.station) },
                speed: motion::max_speed(m, it).min(1e12),
                until: g1,
                line: m.line,
                n: m.n,
            }
        } else {
            // Standing at the move's end: a wait, or after the program's end.
            Pose {
                r: m.ref_end(),
                prog: Some(self.run.frame(m).to_program(m.end)),
                station: Some(m.station),
                speed: 0.0,
                until: next,
                line: m.line,
                n: m.n,
            }
        }
    }

    /// The carrier's parts with `station` active (or indexing: `None`), relative to the
    /// reference point, in the working plane with this carrier's x sign. `scene`: the parts as
    /// the path's own check poses them (its turret, its tools with their rounded noses, each
    /// station's angle on the drum).
    fn parts(&self, scene: &Scene, station: Option<u32>) -> Vec<Part> {
        let axis = scene.turret_axis;
        let mut out = vec![Part {
            label: "turret".to_string(),
            poly: scene.turret.clone(),
        }];
        match station {
            Some(active) => {
                for tool in &scene.tools {
                    // Projected onto the working plane; never flatter than 1e-3 of its width, so a
                    // station at 90° is a sliver around its line, not a line.
                    let c = scene.station_angle(tool.station, f64::from(active)).cos();
                    let c = if c.abs() < 1e-3 { 1e-3f64.copysign(c) } else { c };
                    for (what, shape) in [("insert", &tool.insert), ("holder", &tool.holder)] {
                        let pts: Vec<P2> = shape
                            .points()
                            .iter()
                            .map(|q| {
                                let p = q + tool.tip;
                                P2::new(axis + (p.x - axis) * c, p.y)
                            })
                            .collect();
                        if let Ok(poly) = Polygon::new(&pts) {
                            out.push(Part {
                                label: format!("{} {what}", tool.label),
                                poly,
                            });
                        }
                    }
                }
            }
            None => {
                // Every station at every angle: the box around the turret axis.
                let (mut reach, mut zlo, mut zhi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
                for tool in &scene.tools {
                    for q in tool.insert.points().iter().chain(tool.holder.points()) {
                        let p = q + tool.tip;
                        reach = reach.max((p.x - axis).abs());
                        zlo = zlo.min(p.y);
                        zhi = zhi.max(p.y);
                    }
                }
                if zlo < zhi {
                    let b = [
                        P2::new(axis - reach, zlo),
                        P2::new(axis + reach, zlo),
                        P2::new(axis + reach, zhi),
                        P2::new(axis - reach, zhi),
                    ];
                    if let Ok(poly) = Polygon::new(&b) {
                        out.push(Part {
                            label: "tools indexing".to_string(),
                            poly,
                        });
                    }
                }
            }
        }
        if self.opposite {
            for p in &mut out {
                p.poly = p.poly.mirrored_x();
            }
        }
        out
    }
}

/// The parts of a carriage posed at `r` (its x sign applied).
fn posed(parts: &[Part], r: P2, opposite: bool) -> Vec<(usize, Polygon)> {
    let v = if opposite { P2::new(-r.x, r.y) } else { r };
    parts
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p.poly.translated(v.coords)))
        .collect()
}

/// The carriers' contacts: for each pair of paths, each time their parts come to overlap, one
/// `collision` finding at each path's line. `stop`: nothing past this machine time (a
/// deadlock). Returns the findings and the probes spent.
pub fn check(carriages: &[Carriage], tolerance: f64, stop: Option<f64>) -> (Vec<Finding>, u64) {
    let end = carriages
        .iter()
        .map(|c| (0..c.timeline.items.len()).map(|k| c.span_of(k).1).fold(0.0, f64::max))
        .fold(0.0, f64::max)
        .min(stop.unwrap_or(f64::INFINITY));
    let machines: Vec<&Machine> = carriages.iter().map(|c| c.machine).collect();
    let mut search = Search::new(&machines, tolerance, true);
    search.run(carriages, 0.0, end, MAX_PROBES);
    search.finish()
}

/// The search of [`check`], resumable: [`Search::run`] follows every pair of carriers over one
/// span of machine time and keeps the contacts still open for the next span, so a stream of
/// short spans (`latheguard follow`, each sample interval one span) finds what one run over
/// their union finds.
pub struct Search {
    /// Each carriage's parts as its own check poses them.
    scenes: Vec<Scene>,
    /// Each carriage's parts by active station (`None`: indexing).
    cache: Vec<HashMap<Option<u32>, Vec<Part>>>,
    /// Per pair of carriages `(a, b)`, `a < b`, in contact: its two findings' indices.
    open: HashMap<(usize, usize), [usize; 2]>,
    findings: Vec<Finding>,
    probes: u64,
    tol: f64,
    snapshots: bool,
}

impl Search {
    /// A search of the carriers of `machines` (each path's lathe, in the order of the carriages
    /// of every [`Search::run`]); `snapshots`: a picture for each contact.
    pub fn new(machines: &[&Machine], tolerance: f64, snapshots: bool) -> Search {
        Search {
            scenes: machines.iter().map(|m| Scene::new(m, tolerance)).collect(),
            cache: machines.iter().map(|_| HashMap::new()).collect(),
            open: HashMap::new(),
            findings: Vec::new(),
            probes: 0,
            tol: tolerance.max(1e-4),
            snapshots,
        }
    }

    /// Follow every pair of carriers from machine time `from` to `end`, spending at most
    /// `budget` probes (past them an `unsupported` warning says the rest of the span is
    /// unchecked, and the run ends).
    pub fn run(&mut self, carriages: &[Carriage], from: f64, end: f64, budget: u64) {
        let starts: Vec<Vec<f64>> = carriages
            .iter()
            .map(|c| (0..c.timeline.items.len()).map(|k| c.span_of(k).0).collect())
            .collect();
        let tol = self.tol;
        let mut spent = 0u64;
        for a in 0..carriages.len() {
            for b in a + 1..carriages.len() {
                let (ca, cb) = (&carriages[a], &carriages[b]);
                let mut t = from;
                loop {
                    spent += 1;
                    self.probes += 1;
                    if spent > budget {
                        self.findings.push(Finding::at(
                            Kind::Unsupported,
                            Severity::Warning,
                            1,
                            0,
                            format!(
                                "the check of the {} against the {} stopped after {budget} probes at {t:.3} s: the rest, to {end:.3} s, is unchecked",
                                ca.name, cb.name
                            ),
                        ));
                        return;
                    }
                    let pa = ca.pose(t, &starts[a]);
                    let pb = cb.pose(t, &starts[b]);
                    for (k, c, p) in [(a, ca, &pa), (b, cb, &pb)] {
                        if !self.cache[k].contains_key(&p.station) {
                            let parts = c.parts(&self.scenes[k], p.station);
                            self.cache[k].insert(p.station, parts);
                        }
                    }
                    let (parts_a, parts_b) = (&self.cache[a][&pa.station], &self.cache[b][&pb.station]);
                    let qa = posed(parts_a, pa.r, ca.opposite);
                    let qb = posed(parts_b, pb.r, cb.opposite);
                    let mut gap = f64::INFINITY;
                    let mut hit: Option<(usize, usize, f64)> = None;
                    for (i, x) in &qa {
                        for (j, y) in &qb {
                            // Boxes apart by more than the gap so far cannot lower it.
                            if box_gap(x, y) > gap {
                                continue;
                            }
                            let d = query::distance(x, y);
                            if d <= 0.0 {
                                let depth = query::penetration_depth(x, y);
                                if depth > TOUCH_EPS && hit.map_or(true, |h| depth > h.2) {
                                    hit = Some((*i, *j, depth));
                                }
                            }
                            gap = gap.min(d);
                        }
                    }
                    match (hit, self.open.get(&(a, b))) {
                        (Some((i, j, depth)), None) => {
                            let (la, lb) = (&parts_a[i].label, &parts_b[j].label);
                            let side_a = Side {
                                scene: &self.scenes[a],
                                parts: parts_a,
                                posed: &qa,
                                hit: i,
                                starts: &starts[a],
                            };
                            let side_b = Side {
                                scene: &self.scenes[b],
                                parts: parts_b,
                                posed: &qb,
                                hit: j,
                                starts: &starts[b],
                            };
                            let sides = [
                                (ca, cb, pa, pb, la, lb, &side_a, &side_b),
                                (cb, ca, pb, pa, lb, la, &side_b, &side_a),
                            ];
                            let first = self.findings.len();
                            for (me, other, pm, po, lm, lo, sm, so) in sides {
                                let mut f = Finding::at(
                                    Kind::Collision,
                                    Severity::Error,
                                    pm.line,
                                    0,
                                    format!(
                                        "the {lm} on the {} hits the {lo} on the {} (path {} at line {})",
                                        me.name, other.name, other.path, po.line
                                    ),
                                )
                                .with_n(pm.n);
                                f.objects =
                                    vec![format!("path{}:{}", me.path, lm), format!("path{}:{}", other.path, lo)];
                                f.time_s = Some(t);
                                f.end_time_s = Some(t);
                                f.depth_mm = Some(depth);
                                f.x = pm.prog.map(|p| p.0);
                                f.z = pm.prog.map(|p| p.1);
                                if self.snapshots {
                                    f.snapshot = Some(Box::new(picture(t, (me, &pm, sm), (other, so))));
                                }
                                self.findings.push(f);
                            }
                            self.open.insert((a, b), [first, first + 1]);
                        }
                        (Some((_, _, depth)), Some(&at)) => {
                            // The same contact goes on: its two findings keep the deepest overlap
                            // and the last instant and line.
                            for (k, p) in at.into_iter().zip([pa, pb]) {
                                let f = &mut self.findings[k];
                                f.depth_mm = Some(f.depth_mm.unwrap_or(0.0).max(depth));
                                f.end_time_s = Some(t);
                                f.end_line = f.end_line.max(p.line);
                            }
                        }
                        (None, _) => {
                            self.open.remove(&(a, b));
                        }
                    }
                    if t >= end {
                        break;
                    }
                    let speed = pa.speed + pb.speed;
                    let until = pa.until.min(pb.until).min(end);
                    let step = if speed > 0.0 {
                        gap.max(tol) / speed
                    } else {
                        f64::INFINITY
                    };
                    let next = (t + step).min(until);
                    // Always go forward: past an instant that equals `t` (two moves starting
                    // together).
                    t = if next > t {
                        next
                    } else {
                        next_after(t, &starts[a], &starts[b], end)
                    };
                }
            }
        }
    }

    /// The findings whose contact has ended, when no contact is open (none can still grow):
    /// for a stream with no end. Taken here, they are not in [`Search::finish`]'s.
    pub fn take_final(&mut self) -> Vec<Finding> {
        if self.open.is_empty() {
            std::mem::take(&mut self.findings)
        } else {
            Vec::new()
        }
    }

    /// Every finding not taken yet, open or not, and no contact open any more: for a search run
    /// again over another stretch (`follow`'s look back over a turret index).
    pub fn take_all(&mut self) -> Vec<Finding> {
        self.open.clear();
        std::mem::take(&mut self.findings)
    }

    /// The line and parts of each finding not taken yet.
    pub fn held(&self) -> impl Iterator<Item = (u32, &[String])> {
        self.findings.iter().map(|f| (f.line, f.objects.as_slice()))
    }

    /// Every finding not taken yet, and the probes spent.
    pub fn finish(self) -> (Vec<Finding>, u64) {
        (self.findings, self.probes)
    }
}

/// One carrier at a contact: its scene, its parts, the parts posed, and the one that hit.
struct Side<'s> {
    scene: &'s Scene,
    parts: &'s [Part],
    posed: &'s [(usize, Polygon)],
    hit: usize,
    /// The machine time each of its moves starts at.
    starts: &'s [f64],
}

/// The picture of a contact between two carriers, drawn from `me`'s path: its turret and active
/// tool where they are, its other stations and the other carrier's parts as outlines labelled
/// with their path, the two parts that meet filled, and the chuck. The stock is not drawn: each
/// path's own check holds it, not this one.
fn picture(t: f64, (me, pm, sm): (&Carriage, &Pose, &Side), (other, so): (&Carriage, &Side)) -> crate::scene::Snapshot {
    let pts = |p: &Polygon| p.points().to_vec();
    let sign = if me.opposite { -1.0 } else { 1.0 };
    // The programmed path of the move under way (or the last one), as the path's own pictures
    // draw it.
    let mirror = |p: P2| P2::new(sign * p.x, p.y);
    let k = sm.starts.partition_point(|&s| s <= t);
    let current = k
        .checked_sub(1)
        .and_then(|i| me.timeline.items.get(i))
        .and_then(|it| Some((it, me.run.moves.get(it.index)?)));
    let path: Vec<P2> = current
        .map(|(_, m)| (0..=48).map(|q| mirror(m.point_at(f64::from(q) / 48.0))).collect())
        .unwrap_or_default();
    // A dogleg rapid bends where its first axis arrives: drawn as the machine moves it.
    let machine_path = current.map_or_else(Vec::new, |(it, m)| {
        motion::machine_path(m, it).into_iter().map(mirror).collect()
    });
    let tool = pm.station.and_then(|s| sm.scene.tool(s));
    let label_of = |what: &str| tool.map(|t| format!("{} {what}", t.label));
    let find = |what: &str| {
        let l = label_of(what)?;
        sm.parts.iter().position(|p| p.label == l).map(|k| pts(&sm.posed[k].1))
    };
    let mut others = Vec::new();
    for (k, (_, poly)) in sm.posed.iter().enumerate() {
        let l = &sm.parts[k].label;
        if k == 0 || label_of("insert").as_ref() == Some(l) || label_of("holder").as_ref() == Some(l) {
            continue;
        }
        others.push((l.clone(), pts(poly)));
    }
    for (k, (_, poly)) in so.posed.iter().enumerate() {
        others.push((format!("{}: {}", other.name, so.parts[k].label), pts(poly)));
    }
    let at = match tool {
        Some(t) => P2::new(sign * (pm.r.x + t.tip.x), pm.r.y + t.tip.y),
        None => P2::new(sign * pm.r.x, pm.r.y),
    };
    crate::scene::Snapshot {
        chuck: sm.scene.chuck.as_ref().map(|c| pts(&c.outline)),
        turret: pts(&sm.posed[0].1),
        insert: find("insert").unwrap_or_default(),
        holder: find("holder").unwrap_or_default(),
        others,
        at,
        part_a: pts(&sm.posed[sm.hit].1),
        part_b: vec![pts(&so.posed[so.hit].1)],
        path,
        machine_path,
        ..Default::default()
    }
}

/// The first move start on either path after `t` (or `end`).
fn next_after(t: f64, a: &[f64], b: &[f64], end: f64) -> f64 {
    let na = a.get(a.partition_point(|&s| s <= t)).copied().unwrap_or(f64::INFINITY);
    let nb = b.get(b.partition_point(|&s| s <= t)).copied().unwrap_or(f64::INFINITY);
    na.min(nb).min(end).max(t + 1e-9)
}

/// The distance between the boxes of two polygons (0 when they meet): a lower bound of theirs.
fn box_gap(a: &Polygon, b: &Polygon) -> f64 {
    let (p, q) = (a.aabb(), b.aabb());
    let dx = (q.min.x - p.max.x).max(p.min.x - q.max.x).max(0.0);
    let dy = (q.min.y - p.max.y).max(p.min.y - q.max.y).max(0.0);
    dx.hypot(dy)
}
