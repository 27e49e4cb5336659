//! The carriers of a multi-path turn-mill against each other in 3D, over the machine's one time:
//! a milling head on its X/Y/Z slides and B swivel and a lower turret on its own slides, or two
//! turrets, each path's axes driving its part of the kinematic tree.
//!
//! **Which pairs.** A `never_touch` pair whose two parts are carried by the axes of two paths
//! together ([`Kinematics::cross_pairs`]: the head against the lower turret, the head against a
//! sub-spindle that path 2's slide moves) is checked here and nowhere else: each path's own check
//! runs on the parts its own axes carry ([`Kinematics::for_path`]). The stock is not this
//! check's: each path's own check meets the stock the paths share (`paths/mod.rs`).
//!
//! **The poses.** The machine's time is cut at every start and end of a move of any path; within
//! one piece every path is in one move, or standing. Each path's axes take the values its own
//! check gives them at that instant (X and Z the turret reference point as `motion` times it,
//! dogleg rapids too, the extra axes linearly over the move, a G17/G19 arc along
//! `interp::position3`), shifted by the path's waits (`sync.rs`). The tools of a carrier that a
//! program axis swivels (a B head) are posed only for the active tool (the others sit in the
//! magazine, out of the working space); a drum turret's every station stands at its angle
//! `(s − active)·360°/n` about the turret axis, turning while it indexes, each station on an
//! index joint of its own added to this check's copy of the tree (the machine file's tree is not
//! changed) — as `check/three/index.rs` turns one drum.
//!
//! **The search.** Each pair is followed along each piece by conservative advancement with the
//! proven motion bound of `collide3::motion` (the pair's relative motion over a step at most the
//! bound of its axes' travel), so no contact is stepped over by more than the `--tolerance`: the
//! same guarantee as every other 3D check. An overlap deeper than the tolerance is a
//! `collision`, reported once per contact at the line of each of the two paths (a path standing
//! still, at the line it stands at), each naming the other's, its depth the deepest of a few
//! instants while it lasts.

use std::collections::HashMap;

use nalgebra::{Point3, Unit, Vector3};

use crate::collide3::{self, Advance, Path, Shape3};
use crate::finding::{Finding, Kind, Severity};
use crate::interp::{MoveKind, EXTRA_LETTERS};
use crate::kin::{Axis, AxisId, AxisKind, CompId, Kinematics, Poser};
use crate::machine::Machine;
use crate::motion;
use crate::report::scene3::{Part3, Role3, Snapshot3};

/// Probes the search spends on one program before it gives up with a finding (the working-plane
/// search's budget).
pub use super::cross::MAX_PROBES;
/// Instants after first contact at which a contact's depth is measured (as the 3D check's).
use crate::check::DEPTH_SAMPLES_3D as DEPTH_SAMPLES;

/// One path, as this check sees it: the carriage of the working-plane check (its side is the
/// tree's business here).
pub use super::cross::Carriage as Lane3;

/// How a lane's stations stand in this check's tree.
#[derive(Clone, Debug, PartialEq)]
enum Stations {
    /// No tool of the tree is this path's, or a gang slide: every part where the file poses it.
    InPlace,
    /// A carrier a program axis moves (a B head): only the active tool is there.
    ActiveOnly,
    /// A drum: each station's top parts on an index joint, the drum itself on one.
    Drum {
        body: AxisId,
        station_axes: Vec<(u32, AxisId)>,
        step_deg: f64,
    },
}

/// A lane's axes in the tree and its timing in machine time.
struct Track<'a> {
    lane: &'a Lane3<'a>,
    axes: motion::TreeAxes,
    stations: Stations,
    /// The machine-time start and end of each timed move.
    spans: Vec<(f64, f64)>,
    starts: Vec<f64>,
}

/// Where a lane is at an instant.
#[derive(Clone, Copy, Debug)]
struct At {
    /// The timed move under way or last finished; `None` before the first.
    item: Option<usize>,
    /// Under way (not standing after it).
    moving: bool,
    /// Fraction of the move done.
    u: f64,
}

impl Track<'_> {
    fn at(&self, t: f64) -> At {
        let k = self.starts.partition_point(|&s| s <= t);
        if k == 0 {
            return At {
                item: None,
                moving: false,
                u: 0.0,
            };
        }
        let i = k - 1;
        let (g0, g1) = self.spans[i];
        if t < g1 && g1 > g0 {
            At {
                item: Some(i),
                moving: true,
                u: ((t - g0) / (g1 - g0)).clamp(0.0, 1.0),
            }
        } else {
            At {
                item: Some(i),
                moving: false,
                u: 1.0,
            }
        }
    }

    /// The source line and block number the lane is at.
    fn line(&self, at: At) -> (u32, Option<u64>) {
        let moves = &self.lane.run.moves;
        match at.item {
            Some(i) => {
                let m = &moves[self.lane.timeline.items[i].index];
                (m.line, m.n)
            }
            None => moves.first().map_or((1, None), |m| (m.line, m.n)),
        }
    }

    /// The active station, fractional while a drum indexes; and the two stations of a tool change.
    fn station(&self, at: At) -> (f64, Option<(u32, u32)>) {
        let moves = &self.lane.run.moves;
        let n = self.lane.machine.turret.stations;
        match at.item {
            None => {
                let s = moves
                    .first()
                    .map_or(self.lane.machine.turret.start_station, |m| match m.kind {
                        MoveKind::ToolChange { from, .. } => from,
                        _ => m.station,
                    });
                (s as f64, None)
            }
            Some(i) => {
                let m = &moves[self.lane.timeline.items[i].index];
                match m.kind {
                    MoveKind::ToolChange { from, to } if at.moving => {
                        let dir = motion::index_direction(from, to, n) as f64;
                        (from as f64 + dir * at.u, Some((from, to)))
                    }
                    _ => (m.station as f64, None),
                }
            }
        }
    }

    /// Write this lane's axis values at `at` into `out`.
    fn values(&self, at: At, out: &mut [f64]) {
        let run = self.lane.run;
        if let Some(i) = at.item {
            let it = &self.lane.timeline.items[i];
            self.axes
                .values(&run.moves[it.index], run.extra_of(it.index), it, at.u, out);
        } else if let Some(m) = run.moves.first() {
            let r = m.ref_start();
            for (a, v) in [(self.axes.x, r.x), (self.axes.z, r.y)] {
                if let Some(a) = a {
                    out[a] = v;
                }
            }
        }
        if let Stations::Drum {
            body,
            station_axes,
            step_deg,
        } = &self.stations
        {
            let (active, change) = self.station(at);
            for &(s, a) in station_axes {
                out[a] = (s as f64 - active) * step_deg;
            }
            out[*body] = change.map_or(0.0, |(from, _)| (from as f64 - active) * step_deg);
        }
    }

    /// Per axis of this lane, a bound of its speed (per second) at `at`.
    fn rates(&self, at: At, out: &mut [f64]) {
        let Some(i) = at.item.filter(|_| at.moving) else { return };
        let run = self.lane.run;
        let it = &self.lane.timeline.items[i];
        let m = &run.moves[it.index];
        if it.duration <= 0.0 {
            return;
        }
        // The tree's rates over the whole move, per second.
        let mut whole = vec![0.0; out.len()];
        self.axes.rates(m, run.extra_of(it.index), it, &mut whole);
        for (o, w) in out.iter_mut().zip(whole) {
            if w != 0.0 {
                *o = w / it.duration;
            }
        }
        if let (
            Stations::Drum {
                body,
                station_axes,
                step_deg,
            },
            MoveKind::ToolChange { from, to },
        ) = (&self.stations, m.kind)
        {
            let dir = motion::index_direction(from, to, self.lane.machine.turret.stations) as f64;
            let w = dir.abs() * step_deg / it.duration;
            out[*body] = w;
            for &(_, a) in station_axes {
                out[a] = w;
            }
        }
    }

    /// Whether a part of this lane's station `s` is in the working space at `at`.
    fn present(&self, s: u32, at: At) -> bool {
        if self.stations != Stations::ActiveOnly {
            return true;
        }
        let (active, change) = self.station(at);
        change.map_or(active.round() as u32 == s, |(a, b)| s == a || s == b)
    }
}

/// The axis values of every lane over one piece of machine time.
struct Piece<'a> {
    tracks: &'a [Track<'a>],
    start: &'a [f64],
    t0: f64,
    t1: f64,
}

impl Path for Piece<'_> {
    fn at(&self, u: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(self.start);
        // Within the piece no lane changes moves: each is placed by its state at the piece's
        // middle, at the instant `t`.
        let t = self.t0 + (self.t1 - self.t0) * u;
        let mid = (self.t0 + self.t1) / 2.0;
        for tr in self.tracks {
            let mut at = tr.at(mid);
            if at.moving {
                let (g0, g1) = tr.spans[at.item.unwrap_or(0)];
                at.u = ((t - g0) / (g1 - g0)).clamp(0.0, 1.0);
            }
            tr.values(at, out);
        }
    }

    fn deltas(&self, u0: f64, u1: f64, out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.start.len(), 0.0);
        let mid = (self.t0 + self.t1) / 2.0;
        for tr in self.tracks {
            tr.rates(tr.at(mid), out);
        }
        let dt = (u1 - u0) * (self.t1 - self.t0);
        for v in out.iter_mut() {
            *v *= dt;
        }
    }
}

/// The nearest common ancestor of `comps`.
fn common_ancestor(k: &Kinematics, comps: &[CompId]) -> Option<CompId> {
    let first = *comps.first()?;
    let mut chain = Vec::new();
    let mut p = Some(first);
    while let Some(x) = p {
        chain.push(x);
        p = k.components[x].parent;
    }
    chain
        .into_iter()
        .find(|&a| comps.iter().all(|&c| c == a || k.is_ancestor(a, c)))
}

/// Give lane `path`'s drum its index joints in `k` (see the module docs); how its stations stand.
fn stations_of(k: &mut Kinematics, masks: &[u32], path: u32, machine: &Machine) -> Stations {
    let own = 1u32 << path.min(31);
    let tools: Vec<CompId> = (0..k.components.len())
        .filter(|&c| k.components[c].station.is_some())
        .filter(|&c| masks[c] == own || (masks[c] == 0 && path == 1))
        .collect();
    if tools.is_empty() || machine.turret.kind == crate::machine::TurretKind::Gang {
        return Stations::InPlace;
    }
    let Some(carrier) = common_ancestor(k, &tools) else {
        return Stations::ActiveOnly;
    };
    // A program axis on the carrier or between it and a tool: not a drum this check can turn.
    let axis_between = tools.iter().any(|&c| {
        let mut p = Some(c);
        while let Some(x) = p {
            if k.components[x].axis.is_some() {
                return true;
            }
            if x == carrier {
                break;
            }
            p = k.components[x].parent;
        }
        false
    });
    if axis_between {
        return Stations::ActiveOnly;
    }
    let poser = Poser::new(k);
    let frame_of = |k: &Kinematics, c: CompId| {
        k.components[c]
            .parent
            .map_or(crate::kin::Iso::identity(), |p| *poser.world(p))
            * k.components[c].mount
    };
    // The turret axis: parallel to z through `[turret] axis` along +x from the carrier's parent's
    // origin (where the reference point is), as `check/three/index.rs` has it.
    let parent_frame = k.components[carrier]
        .parent
        .map_or(crate::kin::Iso::identity(), |p| *poser.world(p));
    let origin_w = parent_frame * Point3::new(machine.turret.axis, 0.0, 0.0);
    let dir_w = parent_frame.rotation * Vector3::z();
    let add = |k: &mut Kinematics, c: CompId, name: String| -> AxisId {
        let inv = frame_of(k, c).inverse();
        let a = k.axes.len();
        k.axes.push(Axis {
            name,
            letter: '\0',
            kind: AxisKind::Rotary {
                origin: inv * origin_w,
                dir: Unit::new_normalize(inv.rotation * dir_w),
            },
            zero: 0.0,
            travel: (f64::NEG_INFINITY, f64::INFINITY),
            rapid: 0.0,
            path,
        });
        k.components[c].axis = Some(a);
        a
    };
    let body = add(k, carrier, format!("path{path}_index"));
    let mut station_axes = Vec::new();
    for &c in &tools {
        let s = k.components[c].station.unwrap_or(0);
        let top = k.components[c]
            .parent
            .map_or(true, |p| k.components[p].station != Some(s));
        if top {
            let a = add(k, c, format!("path{path}_station{s}"));
            station_axes.push((s, a));
        }
    }
    Stations::Drum {
        body,
        station_axes,
        step_deg: 360.0 / machine.turret.stations.max(1) as f64,
    }
}

/// An open contact: the findings it gave (indices into the output).
struct Open {
    /// Each finding's index and the path whose line it is at.
    findings: Vec<(usize, u32)>,
}

/// What tells one crash between carriers from another: the path a finding is at and the line
/// of every path of the pair when the contact began.
type CrashKey = (u32, Vec<u32>);

/// What of the whole machine this check poses that does not change with the program: the tree
/// with the drums' index joints, which parts each path's axes carry, the pairs between carriers
/// and their shapes, and each path's axes and stations in the tree. Built once per machine (a
/// stream of samples checks many short spans against the same rig).
pub struct Rig {
    k: Kinematics,
    masks: Vec<u32>,
    start: Vec<f64>,
    pairs: Vec<(CompId, CompId)>,
    shapes: Vec<Option<Shape3>>,
    /// Per path (in the order given): its number, its axes in the tree, its stations.
    lanes: Vec<(u32, motion::TreeAxes, Stations)>,
}

impl Rig {
    /// `kin` is the whole machine's tree, `paths` each path's number and lathe
    /// ([`Machine::for_path`]).
    pub fn new(kin: &Kinematics, paths: &[(u32, &Machine)], tolerance: f64) -> Rig {
        let masks = kin.path_masks();
        let mut k = kin.clone();
        let lanes = paths
            .iter()
            .map(|&(path, machine)| {
                let letter = |c: char| kin.axes.iter().position(|a| a.path == path && a.letter == c);
                let mut extra = [None; 4];
                for (i, c) in EXTRA_LETTERS.iter().enumerate() {
                    extra[i] = letter(*c);
                }
                let axes = motion::TreeAxes {
                    x: letter('X'),
                    z: letter('Z'),
                    extra,
                };
                (path, axes, stations_of(&mut k, &masks, path, machine))
            })
            .collect();
        let shapes: Vec<Option<Shape3>> = k
            .components
            .iter()
            .map(|c| c.geometry.as_ref().and_then(|g| Shape3::meshed(g, tolerance)))
            .collect();
        let pairs = kin
            .cross_pairs()
            .into_iter()
            .filter(|&(a, b)| shapes[a].is_some() && shapes[b].is_some())
            .collect();
        Rig {
            start: k.start_values(),
            k,
            masks,
            pairs,
            shapes,
            lanes,
        }
    }
}

/// The whole machine as this check poses it over a program's time: the [`Rig`] and each path's
/// moves in the machine's clock. Public for the tests' oracle (`tests/paths.rs` samples it
/// densely where [`check`] advances).
pub struct Carriers<'a> {
    rig: Rig,
    tracks: Vec<Track<'a>>,
}

impl<'a> Carriers<'a> {
    /// `kin` is the whole machine's tree, `lanes` its paths as timed.
    pub fn new(kin: &Kinematics, lanes: &'a [Lane3<'a>], tolerance: f64) -> Carriers<'a> {
        let paths: Vec<(u32, &Machine)> = lanes.iter().map(|l| (l.path, l.machine)).collect();
        Carriers::with_rig(Rig::new(kin, &paths, tolerance), lanes)
    }

    /// `lanes` (the rig's paths, in its order) posed on `rig`.
    pub fn with_rig(rig: Rig, lanes: &'a [Lane3<'a>]) -> Carriers<'a> {
        let tracks = lanes
            .iter()
            .zip(&rig.lanes)
            .map(|(l, (path, axes, stations))| {
                debug_assert_eq!(l.path, *path);
                let spans: Vec<(f64, f64)> = l
                    .timeline
                    .items
                    .iter()
                    .map(|it| {
                        let g = l.schedule.global(it.index, it.t0);
                        (g, g + it.duration)
                    })
                    .collect();
                Track {
                    lane: l,
                    axes: *axes,
                    stations: stations.clone(),
                    starts: spans.iter().map(|s| s.0).collect(),
                    spans,
                }
            })
            .collect();
        Carriers { rig, tracks }
    }

    /// The rig back, for the next span's lanes.
    pub fn into_rig(self) -> Rig {
        self.rig
    }

    /// The tree with the drums' index joints (the machine file's components, same indices).
    pub fn tree(&self) -> &Kinematics {
        &self.rig.k
    }

    /// The never-touch pairs between parts two paths' axes carry.
    pub fn pairs(&self) -> &[(CompId, CompId)] {
        &self.rig.pairs
    }

    /// A component's collision shape.
    pub fn shape(&self, c: CompId) -> Option<&Shape3> {
        self.rig.shapes.get(c).and_then(Option::as_ref)
    }

    /// The last instant any path moves.
    pub fn end(&self) -> f64 {
        self.tracks
            .iter()
            .flat_map(|t| t.spans.iter().map(|s| s.1))
            .fold(0.0, f64::max)
    }

    /// Every axis value of [`Carriers::tree`] at machine time `t`.
    pub fn values_at(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.rig.start);
        for tr in &self.tracks {
            tr.values(tr.at(t), out);
        }
    }

    /// Whether component `c` is in the working space at `t` (a head's tool only while it is the
    /// active one).
    pub fn present(&self, c: CompId, t: f64) -> bool {
        let Some(s) = self.rig.k.components[c].station else {
            return true;
        };
        let Some(p) = self.owner(c) else { return true };
        self.tracks
            .iter()
            .find(|tr| tr.lane.path == p)
            .map_or(true, |tr| tr.present(s, tr.at(t)))
    }

    /// The machine posed at `t` for a finding's picture: every part in the working space, the
    /// pair `(a, b)` marked, the parts away from their start poses drawn as moving.
    pub fn picture(&self, (a, b): (CompId, CompId), t: f64, point: Point3<f64>, tolerance: f64) -> Snapshot3 {
        let k = &self.rig.k;
        let mut vals = Vec::new();
        self.values_at(t, &mut vals);
        let mut poser = Poser::new(k);
        poser.pose(k, &vals);
        let mut parts = Vec::new();
        // A part moved when its own axis or an ancestor's is away from its start value.
        let mut moved = vec![false; k.components.len()];
        for (i, c) in k.components.iter().enumerate() {
            let own = c.axis.is_some_and(|x| vals.get(x) != self.rig.start.get(x));
            moved[i] = own || c.parent.is_some_and(|p| p < i && moved[p]);
            if !self.present(i, t) {
                continue;
            }
            let Some(mesh) = c
                .geometry
                .as_ref()
                .and_then(|g| crate::kin::shape::mesh_of(g, tolerance.max(0.05)).ok())
            else {
                continue;
            };
            let role = Role3::of(i, (a, b), moved[i]);
            let cutter = c
                .station
                .zip(self.owner(i))
                .and_then(|(s, p)| {
                    let tr = self.tracks.iter().find(|tr| tr.lane.path == p)?;
                    tr.lane.machine.tools.iter().find(|tool| tool.station == s)
                })
                .map(|tool| tool.cutter);
            parts.push(Part3 {
                name: crate::kin::words::words(c, cutter),
                mesh: std::sync::Arc::new(mesh),
                pose: *poser.world(i),
                role,
            });
        }
        Snapshot3 {
            title: String::new(),
            line: 0,
            time_s: Some(t),
            parts,
            contact: Some(point),
        }
    }

    /// The path whose axes carry `c` (the lowest, for a part two carry).
    fn owner(&self, c: CompId) -> Option<u32> {
        let m = self.rig.masks[c];
        (m != 0).then(|| m.trailing_zeros())
    }
}

/// The carriers' contacts over the machine's time (see the module docs). `kin` is the whole
/// machine's tree; `stop`: nothing past this machine time (a deadlock). Returns the findings and
/// the probes spent.
pub fn check(
    kin: &Kinematics,
    lanes: &[Lane3],
    tolerance: f64,
    stop: Option<f64>,
    snapshots: bool,
) -> (Vec<Finding>, u64) {
    let paths: Vec<(u32, &Machine)> = lanes.iter().map(|l| (l.path, l.machine)).collect();
    let mut search = Search::new(kin, &paths, tolerance, snapshots);
    let end = lanes
        .iter()
        .flat_map(|l| {
            l.timeline
                .items
                .iter()
                .map(|it| l.schedule.global(it.index, it.t0) + it.duration)
        })
        .fold(0.0, f64::max)
        .min(stop.unwrap_or(f64::INFINITY));
    search.run(lanes, 0.0, end, MAX_PROBES);
    search.finish()
}

/// The search of [`check`], resumable: [`Search::run`] follows every pair over one span of
/// machine time and keeps the contacts still open for the next, so a stream of short spans
/// (`latheguard follow`: each sample interval one span, its moves the lanes) finds what one run
/// over their union finds.
pub struct Search {
    /// `None` only while a run holds it.
    rig: Option<Rig>,
    open: HashMap<(CompId, CompId), Open>,
    /// Per finding: its line and the other paths' lines it names (how a crash is told apart).
    keys: Vec<Option<CrashKey>>,
    findings: Vec<Finding>,
    probes: u64,
    tolerance: f64,
    snapshots: bool,
}

impl Search {
    /// A search of the carriers of `paths` (each path's number and lathe, in the order the
    /// lanes of every run come in) on the whole machine's tree `kin`.
    pub fn new(kin: &Kinematics, paths: &[(u32, &Machine)], tolerance: f64, snapshots: bool) -> Search {
        Search {
            rig: Some(Rig::new(kin, paths, tolerance)),
            open: HashMap::new(),
            keys: Vec::new(),
            findings: Vec::new(),
            probes: 0,
            tolerance,
            snapshots,
        }
    }

    /// Follow every pair from machine time `from` to `end`, spending at most `budget` probes
    /// (past them an `unsupported` warning says the rest is unchecked, and the run ends).
    pub fn run(&mut self, lanes: &[Lane3], from: f64, end: f64, budget: u64) {
        let Some(rig) = self.rig.take() else { return };
        let cx = Carriers::with_rig(rig, lanes);
        self.pieces(&cx, from, end, budget);
        self.rig = Some(cx.into_rig());
    }

    /// The findings taken so far, when no contact is open (none can still grow or be joined):
    /// for a stream with no end. Taken here, they are not in [`Search::finish`]'s.
    pub fn take_final(&mut self) -> Vec<Finding> {
        if self.open.is_empty() {
            self.keys.clear();
            std::mem::take(&mut self.findings)
        } else {
            Vec::new()
        }
    }

    /// Every finding not taken yet, open or not, and no contact open any more: for a search run
    /// again over another stretch (`follow`'s look back over a turret index).
    pub fn take_all(&mut self) -> Vec<Finding> {
        self.open.clear();
        self.keys.clear();
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

    fn pieces(&mut self, cx: &Carriers, from: f64, end: f64, budget: u64) {
        let tol = self.tolerance.max(1e-4);
        let tolerance = self.tolerance;
        let snapshots = self.snapshots;
        let Rig {
            k,
            masks,
            start,
            pairs,
            shapes,
            ..
        } = &cx.rig;
        let tracks = &cx.tracks;
        let Search {
            open,
            keys,
            findings,
            probes,
            ..
        } = self;
        let mut spent = 0u64;
        if pairs.is_empty() {
            return;
        }
        let mut cuts: Vec<f64> = tracks
            .iter()
            .flat_map(|t| t.spans.iter().flat_map(|s| [s.0, s.1]))
            .chain([from, end])
            .filter(|t| t.is_finite() && *t >= from && *t <= end)
            .collect();
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() <= 1e-12);
        let pieces: Vec<(f64, f64)> = if cuts.len() < 2 {
            vec![(from, from)]
        } else {
            cuts.windows(2).map(|w| (w[0], w[1])).collect()
        };
        for (t0, t1) in pieces {
            let mid = (t0 + t1) / 2.0;
            let piece = Piece { tracks, start, t0, t1 };
            for &(a, b) in pairs {
                // A tool in the magazine of a head is not in the working space.
                if !cx.present(a, mid) || !cx.present(b, mid) {
                    open.remove(&(a, b));
                    continue;
                }
                let (sa, sb) = (shapes[a].as_ref().unwrap(), shapes[b].as_ref().unwrap());
                let (adv, _, used) = collide3::first_contact_from(k, (a, sa), (b, sb), &piece, 2.0 * tol, tol, 0.0);
                *probes += used;
                spent += used;
                match adv {
                    Advance::Clear => {
                        open.remove(&(a, b));
                    }
                    Advance::Unchecked { u } => {
                        keys.push(None);
                        findings.push(Finding::at(
                        Kind::Unsupported,
                        Severity::Warning,
                        1,
                        0,
                        format!(
                            "the 3D check of the carriers against each other stopped after {} probes at {:.3} s: the rest of that move is unchecked",
                            collide3::MAX_PROBES,
                            t0 + u * (t1 - t0)
                        ),
                    ));
                    }
                    Advance::Contact { u, hit } => {
                        // The deepest of a few instants from first contact to the piece's end, and
                        // whether it lasts into the next piece.
                        let mut depth = hit.depth;
                        let mut lasts = false;
                        let t = t0 + u * (t1 - t0);
                        // The last instant seen in contact.
                        let mut last_in = t;
                        let mut poser = Poser::new(k);
                        let mut vals = Vec::new();
                        for i in 1..=DEPTH_SAMPLES {
                            let v = u + (1.0 - u) * i as f64 / DEPTH_SAMPLES as f64;
                            piece.at(v, &mut vals);
                            poser.pose(k, &vals);
                            let h = collide3::overlap(sa, poser.world(a), sb, poser.world(b), 2.0 * tol);
                            *probes += 1;
                            spent += 1;
                            if let Some(h) = &h {
                                depth = depth.max(h.depth);
                                last_in = t0 + v * (t1 - t0);
                            }
                            if i == DEPTH_SAMPLES {
                                lasts = h.is_some();
                            }
                        }
                        if u <= 1e-9 && open.contains_key(&(a, b)) {
                            // The same contact goes on from the piece before.
                            for &(f, path) in &open[&(a, b)].findings {
                                let fd: &mut Finding = &mut findings[f];
                                fd.depth_mm = Some(fd.depth_mm.unwrap_or(0.0).max(depth));
                                fd.end_time_s = Some(fd.end_time_s.unwrap_or(last_in).max(last_in));
                                if let Some(tr) = tracks.iter().find(|tr| tr.lane.path == path) {
                                    fd.end_line = fd.end_line.max(tr.line(tr.at(mid)).0);
                                }
                            }
                        } else {
                            // Another pair of the same two carriers meeting at the same lines (the
                            // holder after the insert) is the same crash: its findings take the
                            // deeper depth, not a finding of their own.
                            let mut made = report(k, tracks, masks, (a, b), t, depth);
                            let picture = snapshots.then(|| cx.picture((a, b), t, hit.point, tolerance));
                            for (f, _) in &mut made {
                                f.end_time_s = Some(last_in);
                                if let Some(p) = &picture {
                                    let mut p = p.clone();
                                    p.title = f.message.clone();
                                    p.line = f.line;
                                    f.snapshot3 = Some(Box::new(p));
                                }
                            }
                            let mut at = Vec::new();
                            for (f, key) in made {
                                let path = key.0;
                                match keys.iter().position(|k| k.as_ref() == Some(&key)) {
                                    Some(i) => {
                                        let g = &mut findings[i];
                                        let most = |a: Option<f64>, b: Option<f64>| match (a, b) {
                                            (Some(a), Some(b)) => Some(a.max(b)),
                                            (a, b) => a.or(b),
                                        };
                                        let (deepest, last) =
                                            (most(g.depth_mm, f.depth_mm), most(g.end_time_s, f.end_time_s));
                                        let end_line = g.end_line.max(f.end_line);
                                        // The contact that came first tells the crash.
                                        if f.time_s < g.time_s {
                                            *g = f;
                                        }
                                        g.depth_mm = deepest;
                                        g.end_time_s = last;
                                        g.end_line = end_line;
                                        at.push((i, path));
                                    }
                                    None => {
                                        at.push((findings.len(), path));
                                        findings.push(f);
                                        keys.push(Some(key));
                                    }
                                }
                            }
                            open.insert((a, b), Open { findings: at });
                        }
                        if !lasts {
                            open.remove(&(a, b));
                        }
                    }
                }
                if spent > budget {
                    findings.push(Finding::at(
                    Kind::Unsupported,
                    Severity::Warning,
                    1,
                    0,
                    format!(
                        "the 3D check of the carriers against each other stopped after {budget} probes at {t0:.3} s: the rest, to {end:.3} s, is unchecked"
                    ),
                ));
                    return;
                }
            }
        }
    }
}

/// The findings of a contact that begins at `t`: one at the line of each path whose axes carry
/// one of the two parts, naming the other path's line; each with its [`CrashKey`].
fn report(
    k: &Kinematics,
    tracks: &[Track],
    masks: &[u32],
    (a, b): (CompId, CompId),
    t: f64,
    depth: f64,
) -> Vec<(Finding, CrashKey)> {
    let paths = masks[a] | masks[b];
    let in_pair: Vec<&Track> = tracks
        .iter()
        .filter(|t| paths & (1 << t.lane.path.min(31)) != 0)
        .collect();
    let owner = |c: CompId| (masks[c] != 0).then(|| masks[c].trailing_zeros());
    let words = |c: CompId| {
        let comp = &k.components[c];
        let lane = owner(c).and_then(|p| tracks.iter().find(|t| t.lane.path == p));
        let cutter = comp
            .station
            .zip(lane)
            .and_then(|(s, l)| l.lane.machine.tools.iter().find(|t| t.station == s))
            .map(|t| t.cutter);
        let w = crate::kin::words::words(comp, cutter);
        match (comp.station, lane) {
            (Some(_), Some(l)) => format!("{} on the {}", w, l.lane.name),
            _ => w,
        }
    };
    let lines: Vec<u32> = in_pair.iter().map(|tr| tr.line(tr.at(t)).0).collect();
    let mut out = Vec::new();
    for tr in in_pair.iter().copied() {
        let p = tr.lane.path;
        // This path's part first.
        let (mine, other) = if owner(a) == Some(p) { (a, b) } else { (b, a) };
        let at = tr.at(t);
        let (line, n) = tr.line(at);
        let others: Vec<String> = in_pair
            .iter()
            .filter(|o| o.lane.path != p)
            .map(|o| format!("path {} at line {}", o.lane.path, o.line(o.at(t)).0))
            .collect();
        let mut f = Finding::at(
            Kind::Collision,
            Severity::Error,
            line,
            0,
            format!("the {} hits the {} ({})", words(mine), words(other), others.join(", ")),
        )
        .with_n(n);
        let path_of = |c: CompId| owner(c).unwrap_or(p);
        f.objects = vec![
            format!("path{}:{}", p, k.components[mine].name),
            format!("path{}:{}", path_of(other), k.components[other].name),
        ];
        f.time_s = Some(t);
        f.end_time_s = Some(t);
        f.depth_mm = Some(depth);
        if let Some(i) = at.item {
            let m = &tr.lane.run.moves[tr.lane.timeline.items[i].index];
            let it = &tr.lane.timeline.items[i];
            let r = motion::reference_at(m, it, at.u * it.duration);
            let q = tr.lane.run.frame(m).to_program(r + m.tip);
            f.x = Some(q.0);
            f.z = Some(q.1);
        }
        out.push((f, (p, lines.clone())));
    }
    out
}
