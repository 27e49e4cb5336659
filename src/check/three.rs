//! The 3D path (turn-mill): the moves of a turn-mill machine that leave the lathe's working plane,
//! checked on the machine's kinematic tree (`kin`) with 3D queries (`collide3`).
//!
//! Which path a move takes ([`Three::route`]): the 2D section checker is exact for a lathe in
//! its working plane, so a move stays on it while every extra axis is where the 2D model assumes
//! (Y at its start value, the sub-spindle's B and A at theirs, no G17/G19 arc) and the part turns
//! (or, positioned as a C axis, is cut only on the spindle axis: X = 0). A move whose tool leaves
//! that plane is checked here, and only here ([`Route::Space`]): every `never_touch` pair of the
//! machine file, and the turret, the holders and the cutters against the in-process stock — the
//! tools of every station: the other stations' stand at their angle on the drum, posed with the
//! index axis held there ([`Carousel`]); parts fixed to each other are tested once. A move whose tool
//! stays in the plane while the sub-spindle's side does not ([`Route::Hybrid`]) is checked by
//! both: the 2D sections for the tools against the main chuck and the stock, this path for the
//! component pairs, the sub-spindle's chuck and centre against the stock, and the pieces it holds
//! after a part-off (`transfer.rs`).
//!
//! Rules: a pair of components that overlaps by more than `TOUCH_EPS` is a `collision`; the
//! cutter in the stock is `rapid_into_stock` in a rapid, `spindle_stopped` in a feed with neither
//! the main spindle nor a live tool turning, machining otherwise. The dexel stock is revolved, so
//! only a turning spindle's cuts are taken from it; a live tool's cut with the spindle positioned
//! leaves it as it is (the milled stock is `three/mill.rs`). What that cut removed is kept as a
//! **plunge**: the straight line the cutter fed along, at its C angle. Moves of that cutter back
//! along the line, at the same C, are in its own hole and not judged against the stock; any other
//! motion with the cutter still in the part (a C index, a Y or Z move sideways) is judged against
//! the uncut stock — which is what such a move does to a real part: drags the tool through it.
//!
//! Each pair is followed along the move by conservative advancement with a proven motion bound
//! (`collide3::motion`): never a step longer than the proven gap, in both modes, so a move
//! never tunnels. The axis values along a move: X and Z are the turret reference point as the 2D
//! model times it (`motion::reference_at`: dogleg rapids too), the extra axes go linearly over the
//! move's time, a G17/G19 arc follows `interp::position3`.

mod index;
pub(super) mod mill;
mod near;
mod slide;
pub(super) mod transfer;

use std::sync::Arc;

use nalgebra::Point3;

use super::episodes::Contact;
use super::Checker;
use crate::collide3::{self, Hit, Shape3};
use crate::collide3::{bound_from, Advance, Path as _, MAX_PROBES};
use crate::finding::Kind;
use crate::geom::TOUCH_EPS;
use crate::interp::{ExtraMove, Move, MoveKind};
use crate::kin::{AxisId, CompId, Geometry, Kinematics, Poser, Role};
use crate::motion::{self, Timed};
use crate::report::scene3::{Part3, Role3, Snapshot3};

/// Episode keys of the 3D path: above every 2D key.
const KEY_BASE: u64 = 1 << 48;
/// The stock as the second member of a pair.
const STOCK: usize = usize::MAX;
/// Samples after first contact at which the depth of a 3D contact is measured (also by the
/// carriers' 3D check, `paths/cross3.rs`).
pub(crate) const DEPTH_SAMPLES: u32 = 16;
/// The shortest stretch a part sliding along the stock is proven clear over (`slide.rs`), in
/// the advancement's shortest steps.
const SLIDE_STEPS: f64 = 16.0;

/// The path that checks a move ([`Three::route`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Route {
    /// The 2D sections alone: the lathe in its working plane.
    Plane,
    /// The tool in the working plane, the sub-spindle's side not: the 2D sections check the
    /// tools against the main chuck and the stock (and cut it); the 3D path checks the
    /// component pairs, the sub-spindle's chucks and pieces.
    Hybrid,
    /// The 3D path alone.
    Space,
}

/// How the tree poses the tools of the stations that are not active (`Three::set_turret`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Carousel {
    /// A drum: station `s` stands turned `(s − active)·360°/n` about the index axis added to the
    /// carrier (`index.rs`), as the 2D model's `Scene::station_angle` has it.
    Drum { ix: index::IndexAxis, n: u32 },
    /// A gang slide: every tool stands where the file poses it.
    InPlace,
    /// A carrier that a program axis moves (a B head) or a tree without stations: the file poses
    /// only the active station's tools, and only they are checked.
    ActiveOnly,
}

/// What a live tool has cut with the spindle positioned: the line its cutter fed along.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plunge {
    cutter: CompId,
    /// C (the main spindle's angle) during the cut.
    c: f64,
    /// The turret reference point (x, y, z) where the feed began and where it reached.
    a: [f64; 3],
    b: [f64; 3],
}

/// The 3D side of the checker: the tree, its collision shapes, the last poses.
pub(super) struct Three {
    kin: Arc<Kinematics>,
    shapes: Vec<Option<Shape3>>,
    /// Cylinders and boxes as parry's primitives (exact, and cast in closed form) for the milled
    /// stock's ray queries (`mill.rs`); `None`: the mesh serves.
    grid_shapes: Vec<Option<Shape3>>,
    ax_x: Option<AxisId>,
    ax_z: Option<AxisId>,
    /// The kinematic axis of each of `interp::EXTRA_LETTERS` (Y, C, B, A).
    ax_extra: [Option<AxisId>; 4],
    start: Vec<f64>,
    /// The turret's index axis, once a T word on this path needed it (`index.rs`).
    index: Option<index::IndexAxis>,
    /// Per extra axis: it carries a tool (the Y slide, a B head) rather than the sub-spindle's
    /// side of the machine (its slide and its C axis).
    tool_axis: [bool; 4],
    /// The chucks the sub-spindle's axes carry: the 2D sections have them only as the
    /// tailstock outline at their start values (`transfer.rs`).
    sub_chucks: Vec<CompId>,
    /// The chucks and centres the sub-spindle's axes carry: checked against the stock.
    sub_parts: Vec<CompId>,
    /// The pieces the sub-spindle holds after a part-off (components added to the tree, always
    /// its last ones: `transfer.rs`).
    pieces: Vec<CompId>,
    /// The sub chuck's clamp and what it holds (`transfer.rs`).
    transfer: transfer::Transfer,
    /// The component the C axis turns: the part's frame (`mill.rs`).
    main_spindle: Option<CompId>,
    /// How the tools of the stations that are not active stand on an ordinary move.
    carousel: Carousel,
    /// Per component: the station of its tool (its own or its nearest ancestor's `station`).
    /// A component added during the run (the part a sub-spindle takes) has no entry: no station.
    station_of: Vec<Option<u32>>,
    /// The 3D path ran on at least one move (`stats.effects` says "3d").
    pub ran: bool,
}

impl Three {
    pub fn new(kin: Arc<Kinematics>, tolerance: f64) -> Three {
        let shapes: Vec<Option<Shape3>> = kin
            .components
            .iter()
            .map(|c| c.geometry.as_ref().and_then(|g| Shape3::meshed(g, tolerance)))
            .collect();
        let grid_shapes = kin
            .components
            .iter()
            .map(|c| match &c.geometry {
                Some(g @ (Geometry::Cylinder { .. } | Geometry::Cuboid { .. })) => Shape3::from_geometry(g, tolerance),
                _ => None,
            })
            .collect();
        let letter = |c| kin.axis_by_letter(c);
        let mut ax_extra = [None; 4];
        for (i, l) in crate::interp::EXTRA_LETTERS.iter().enumerate() {
            ax_extra[i] = letter(*l);
        }
        let moved_by = |c: CompId, a: AxisId| {
            let mut p = Some(c);
            while let Some(q) = p {
                if kin.components[q].axis == Some(a) {
                    return true;
                }
                p = kin.components[q].parent;
            }
            false
        };
        let tools: Vec<CompId> = (0..kin.components.len())
            .filter(|&i| matches!(kin.components[i].role, Role::Holder | Role::Cutter) || carried_by_x(&kin, i))
            .collect();
        let mut tool_axis = [false; 4];
        for (k, a) in ax_extra.iter().enumerate() {
            // C turns the part; every other extra axis is the tool's unless it moves no tool.
            tool_axis[k] = a.is_some_and(|a| k != 1 && tools.iter().any(|&t| moved_by(t, a)));
        }
        let sub_parts: Vec<CompId> = (0..kin.components.len())
            .filter(|&i| matches!(kin.components[i].role, Role::Chuck | Role::Tailstock) && shapes[i].is_some())
            .filter(|&i| {
                ax_extra
                    .iter()
                    .enumerate()
                    .any(|(k, a)| k != 1 && !tool_axis[k] && a.is_some_and(|a| moved_by(i, a)))
            })
            .collect();
        let sub_chucks = sub_parts
            .iter()
            .copied()
            .filter(|&i| kin.components[i].role == Role::Chuck)
            .collect();
        let mut station_of: Vec<Option<u32>> = Vec::with_capacity(kin.components.len());
        for c in &kin.components {
            let own = c
                .station
                .or_else(|| c.parent.and_then(|p| station_of.get(p).copied().flatten()));
            station_of.push(own);
        }
        Three {
            carousel: Carousel::ActiveOnly,
            station_of,
            tool_axis,
            sub_chucks,
            sub_parts,
            pieces: Vec::new(),
            transfer: transfer::Transfer::default(),
            main_spindle: ax_extra[1].and_then(|a| kin.components.iter().position(|c| c.axis == Some(a))),
            ax_x: letter('X'),
            ax_z: letter('Z'),
            ax_extra,
            start: kin.start_values(),
            index: None,
            shapes,
            grid_shapes,
            kin,
            ran: false,
        }
    }

    /// Which path checks this move (see the module docs): `tailstock_in` is whether the 2D
    /// tailstock (the parked sub-spindle's outline on a turn-mill) is in the scene.
    pub fn route(&self, m: &Move, e: Option<&ExtraMove>, spindle_turns: bool, tailstock_in: bool) -> Route {
        let mut sub_moved = false;
        if let Some(e) = e {
            if e.arc.is_some() {
                return Route::Space;
            }
            // Y, B and A where the 2D model has them (their start values); C is free while the
            // part is revolved — and it is: the stock and the chuck are revolved outlines.
            for k in [0usize, 2, 3] {
                if let Some(a) = self.ax_extra[k] {
                    let z = self.start[a];
                    if e.start[k] != z || e.end[k] != z {
                        if self.tool_axis[k] {
                            return Route::Space;
                        }
                        sub_moved = true;
                    }
                }
            }
            // A positioned spindle is cut as a revolved part only on its axis.
            let cuts_positioned = e.c_mode || !spindle_turns;
            if cuts_positioned && e.live_rpm > 0.0 && (m.start.x != 0.0 || m.end.x != 0.0) {
                return Route::Space;
            }
        }
        // The tool is in the working plane, but the sub-spindle's side is not where the 2D
        // tailstock outline has it (moved, holding a piece, or that outline is out of the scene
        // while its chuck is still there).
        if sub_moved || !self.pieces.is_empty() || (!tailstock_in && !self.sub_chucks.is_empty()) {
            Route::Hybrid
        } else {
            Route::Plane
        }
    }

    /// The axis values at time fraction `u` of the move.
    fn values(&self, m: &Move, e: Option<&ExtraMove>, item: &Timed, u: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.start);
        self.tree_axes().values(m, e, item, u, out);
    }

    /// Per axis, a bound of how fast its value changes per unit of the time fraction `u`.
    fn rates(&self, m: &Move, e: Option<&ExtraMove>, item: &Timed) -> Vec<f64> {
        let mut r = vec![0.0; self.start.len()];
        self.tree_axes().rates(m, e, item, &mut r);
        r
    }

    /// The program's axes on the tree.
    fn tree_axes(&self) -> motion::TreeAxes {
        motion::TreeAxes {
            x: self.ax_x,
            z: self.ax_z,
            extra: self.ax_extra,
        }
    }

    /// The components that take part in this move: every tool of every station (the others
    /// posed at their station's angle, [`Three::index_of`]) unless the carrier cannot pose them
    /// ([`Carousel::ActiveOnly`]), and the tailstock's parts only while it is in (as in 2D).
    fn present(&self, active: u32, tailstock_in: bool) -> Vec<bool> {
        let k = &self.kin;
        let all = self.carousel != Carousel::ActiveOnly;
        let mut on = vec![true; k.components.len()];
        for (i, c) in k.components.iter().enumerate() {
            let station = all || c.station.map_or(true, |s| s == active);
            let own = station && (tailstock_in || c.role != Role::Tailstock);
            let parent = c.parent.map_or(true, |p| on[p]);
            on[i] = own && parent;
        }
        on
    }

    /// Set how the stations that are not active stand (the 2D model's turret: a gang slide or a
    /// drum of `stations` about `turret_axis`). A drum gets its index axis now (`index.rs`), at
    /// value 0 on every move of the file's pose; a carrier a program axis moves has none.
    pub fn set_turret(&mut self, gang: bool, turret_axis: f64, stations: u32) {
        if !self.kin.components.iter().any(|c| c.station.is_some()) {
            return;
        }
        self.carousel = if gang {
            Carousel::InPlace
        } else {
            match self.index_axis(turret_axis) {
                Some(ix) => Carousel::Drum { ix, n: stations.max(1) },
                None => Carousel::ActiveOnly,
            }
        };
    }

    /// The index axis value that poses component `c` on a move made with station `active`:
    /// `None` where the file's pose is the one (the active station, parts of no station, a
    /// gang slide).
    fn index_of(&self, c: usize, active: u32) -> Option<(AxisId, f64)> {
        let Carousel::Drum { ix, n } = self.carousel else {
            return None;
        };
        let s = self.station_of.get(c).copied().flatten()?;
        if s == active || !(c == ix.carrier || self.kin.is_ancestor(ix.carrier, c)) {
            return None;
        }
        Some((ix.axis, (s as f64 - active as f64) * 360.0 / n as f64))
    }

    /// Whether two components are fixed to each other: no joint (a program axis or the turret's
    /// index) lies between them, so their relative pose never changes and one test decides them
    /// for the whole program.
    fn rigid(&self, a: usize, b: usize) -> bool {
        let joint = |c: usize| {
            let mut p = Some(c);
            while let Some(q) = p {
                if self.kin.components[q].axis.is_some() {
                    return Some(q);
                }
                p = self.kin.components[q].parent;
            }
            None
        };
        joint(a) == joint(b)
    }
}

/// A pair's follower along the move: positions and bounds at any `u`.
#[derive(Clone)]
struct Follow<'a> {
    three: &'a Three,
    m: &'a Move,
    e: Option<&'a ExtraMove>,
    item: &'a Timed,
    rates: Vec<f64>,
    /// The turret's index axis held at a station's angle (the pair's tool is of a station that
    /// is not active): it does not move during the move.
    index: Option<(AxisId, f64)>,
}

impl collide3::Path for Follow<'_> {
    fn at(&self, u: f64, out: &mut Vec<f64>) {
        self.three.values(self.m, self.e, self.item, u, out);
        if let Some((a, v)) = self.index {
            if let Some(x) = out.get_mut(a) {
                *x = v;
            }
        }
    }

    /// Each axis at most its rate: linear in `u1 - u0`.
    fn deltas(&self, u0: f64, u1: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend(self.rates.iter().map(|r| r * (u1 - u0)));
    }
}

impl Checker<'_> {
    /// Check one move on the 3D path (the caller decided it leaves the working plane).
    /// `hybrid`: the 2D sections check the tools against the main chuck and the stock (see
    /// [`Route::Hybrid`]); this path the rest.
    pub(super) fn three_move(&mut self, m: &Move, e: Option<&ExtraMove>, item: &Timed, hybrid: bool) {
        let Some(three) = self.three.take() else { return };
        match e.and_then(|e| first_turns(m, e, item)) {
            Some((e1, item1)) => {
                // The travel limits see the whole move; the parts, the turns that pose them all.
                self.extra_overtravel(&three, m, e, item);
                self.three_move_with(&three, m, Some(&e1), &item1, hybrid, false);
            }
            None => self.three_move_with(&three, m, e, item, hybrid, true),
        }
        self.three = Some(three);
    }

    fn three_move_with(
        &mut self,
        three: &Three,
        m: &Move,
        e: Option<&ExtraMove>,
        item: &Timed,
        hybrid: bool,
        overtravel: bool,
    ) {
        if overtravel {
            self.extra_overtravel(three, m, e, item);
        }
        let k = &three.kin;
        let active = m.station;
        let on = three.present(active, self.tailstock_in);
        let follow = Follow {
            three,
            m,
            e,
            item,
            rates: three.rates(m, e, item),
            index: None,
        };
        // One follower per station that is not active: its tools stand at the station's angle.
        let mut follows: Vec<Follow> = vec![follow.clone()];
        let mut follow_of = |c: usize| -> usize {
            let Some(ix) = three.index_of(c, active) else { return 0 };
            if let Some(j) = follows.iter().position(|f| f.index == Some(ix)) {
                return j;
            }
            follows.push(Follow {
                index: Some(ix),
                ..follow.clone()
            });
            follows.len() - 1
        };
        let rapid = m.kind == MoveKind::Rapid;
        let spindle_turns = self.spindle().is_on() && !e.is_some_and(|e| e.c_mode);
        let live = e.is_some_and(|e| e.live_rpm > 0.0);
        let cutter_rule = if rapid {
            Some(Kind::RapidIntoStock)
        } else if !spindle_turns && !live {
            Some(Kind::SpindleStopped)
        } else {
            None
        };
        // Each pair with the follower that poses it: the tools of a station that is not active
        // at that station's angle (a pair has at most one side on the turret: two parts fixed to
        // each other are `rigid`, decided once).
        let mut pairs: Vec<(CompId, usize, Kind, usize)> = Vec::new();
        let mut rigid: Vec<(CompId, CompId)> = Vec::new();
        let mut to_mill: Vec<CompId> = Vec::new();
        for &(a, b) in &k.never_touch {
            if on[a] && on[b] && three.shapes[a].is_some() && three.shapes[b].is_some() {
                if three.rigid(a, b) {
                    rigid.push((a, b));
                } else {
                    let fa = follow_of(a);
                    let fi = if fa == 0 { follow_of(b) } else { fa };
                    // The active cutter rapiding into a part the sub-spindle holds drives a tool
                    // into material, as into the bar: rapid_into_stock, not a collision.
                    let cutter_into_piece = |c: CompId, p: CompId| {
                        k.components[c].role == Role::Cutter
                            && three.station_of.get(c).copied().flatten().map_or(true, |s| s == active)
                            && three.pieces.contains(&p)
                    };
                    let kind = if rapid && (cutter_into_piece(a, b) || cutter_into_piece(b, a)) {
                        Kind::RapidIntoStock
                    } else {
                        Kind::Collision
                    };
                    pairs.push((a, b, kind, fi));
                }
            }
        }
        if self.machine.stock.is_some() {
            // The sub-spindle's chuck (its jaws over the bar), a centre it carries (driven into
            // the bar) and the pieces it holds.
            for &i in three.sub_parts.iter().chain(&three.pieces) {
                if on[i] && three.shapes[i].is_some() {
                    pairs.push((i, STOCK, Kind::Collision, 0));
                }
            }
        }
        if self.machine.stock.is_some() && !hybrid {
            for (i, c) in k.components.iter().enumerate() {
                if !on[i] || three.shapes[i].is_none() {
                    continue;
                }
                if !carried_by_x(k, i) {
                    continue;
                }
                let fi = follow_of(i);
                if three.station_of.get(i).copied().flatten().is_some_and(|s| s != active) {
                    // A tool of another station (holder or cutter) in the stock: a collision,
                    // as the 2D path's other stations.
                    pairs.push((i, STOCK, Kind::Collision, fi));
                    continue;
                }
                if c.role == Role::Cutter {
                    if let Some(rule) = cutter_rule {
                        if !self.in_own_plunge(three, i, m, e, item) {
                            pairs.push((i, STOCK, rule, fi));
                        }
                    }
                    if live && !rapid && !spindle_turns {
                        if self.grid_cutter(three, i).is_some() {
                            // Milled into the grid after the pairs (`mill.rs`).
                            to_mill.push(i);
                        } else {
                            self.record_plunge(three, i, m, e, item);
                        }
                    }
                } else {
                    pairs.push((i, STOCK, Kind::Collision, fi));
                }
            }
        }
        let mut keys: Vec<u64> = pairs.iter().map(|&(a, b, kind, _)| pair_key(a, b, kind)).collect();
        // Near misses (`near.rs`): the component pairs, as the 2D path's parts against the chuck
        // and the tailstock; never the stock.
        let clearance = self.settings.clearance_mm;
        let near_pairs: Vec<(CompId, CompId, usize)> = if clearance > 0.0 {
            pairs
                .iter()
                .filter(|&&(_, b, _, _)| b != STOCK)
                .map(|&(a, b, _, fi)| (a, b, fi))
                .collect()
        } else {
            Vec::new()
        };
        keys.extend(near_pairs.iter().map(|&(a, b, _)| pair_key(a, b, Kind::NearMiss)));
        self.episodes
            .close_except(|key| key == u64::MAX || key < KEY_BASE || keys.contains(&key));
        self.rigid_pairs(three, &follow, m, item, &rigid);
        for &(a, b, fi) in &near_pairs {
            self.near_misses(three, &follows[fi], m, item, a, b);
        }
        // The component pairs' gaps at the end of the previous move, when that was the move just
        // before this one on this path (the parts then start where they stood).
        let known = match self.gap3.take() {
            Some((i, g)) if i + 1 == item.index => g,
            _ => Vec::new(),
        };
        let mut gaps: PairGaps = Vec::new();
        for (&(a, b, kind, fi), &key) in pairs.iter().zip(&keys) {
            let follow = &follows[fi];
            let res = if b == STOCK {
                self.stock_advance(three, follow, Some(follow), a)
            } else {
                let start = known.iter().find(|(p, _)| *p == (a, b)).map_or(0.0, |g| g.1);
                let (adv, end, n) = pair_advance(three, follow, a, b, self.settings.tolerance_mm, start);
                gaps.push(((a, b), end));
                (adv, n)
            };
            // A pair the broad phase clears (no query) is a skipped test, as a 2D pair whose
            // envelopes never meet.
            if res.1 == 0 {
                self.stats.pair_tests_skipped += 1;
            }
            self.stats.pair_tests += res.1;
            match res.0 {
                Advance::Clear => self.episodes.clear(key),
                Advance::Unchecked { u } => {
                    let t = item.t0 + u * item.duration;
                    self.budget.push((
                        m.line,
                        format!("the 3D check of {} stopped after {MAX_PROBES} probes at {t:.3} s: the rest of this move is unchecked", self.names(k, a, b)),
                    ));
                }
                Advance::Contact { u, hit } => {
                    let t = item.t0 + u * item.duration;
                    if self.episodes.is_open(key) {
                        self.episodes.extend(key, m.line, t, hit.depth, false);
                    } else {
                        let c = self.contact3(three, follow, m, a, b, kind, u, hit, t);
                        self.episodes.contact(key, c);
                    }
                    // The depth over the rest of the move, and whether contact lasts to its end.
                    let mut still = false;
                    for j in 1..=DEPTH_SAMPLES {
                        let uu = u + (1.0 - u) * j as f64 / DEPTH_SAMPLES as f64;
                        self.stats.pair_tests += 1;
                        match self.probe3_sample(three, follow, (a, b), uu, key) {
                            Some(h) => {
                                self.episodes
                                    .extend(key, m.line, item.t0 + uu * item.duration, h.depth, false);
                                still = j == DEPTH_SAMPLES;
                            }
                            None => still = false,
                        }
                    }
                    if !still {
                        self.episodes.clear(key);
                    }
                }
            }
        }
        self.gap3 = Some((item.index, gaps));
        for c in to_mill {
            if !self.mill_cut(three, c, m, e, item) {
                self.record_plunge(three, c, m, e, item);
            }
        }
        self.end_plunge(three, &follow);
    }

    /// Pairs of parts fixed to each other (`Three::rigid`: two tools on the turret, a holder's
    /// block and its drill): their relative pose never changes, so one overlap test, at the first
    /// move that checks them, decides them for the whole program. An overlap is one `collision`.
    fn rigid_pairs(&mut self, three: &Three, f: &Follow, m: &Move, item: &Timed, pairs: &[(CompId, CompId)]) {
        if pairs.iter().all(|p| self.rigid3.contains(p)) {
            return;
        }
        let mut vals = Vec::new();
        f.at(0.0, &mut vals);
        let tol = self.settings.tolerance_mm;
        for &(a, b) in pairs {
            if !self.rigid3.insert((a, b)) {
                continue;
            }
            let (Some(sa), Some(sb)) = (three.shapes[a].as_ref(), three.shapes[b].as_ref()) else {
                continue;
            };
            let pa = three.pose_of(a, m.station, &vals);
            let pb = three.pose_of(b, m.station, &vals);
            self.stats.pair_tests += 1;
            let Some(hit) = collide3::overlap(sa, &pa, sb, &pb, 2.0 * tol) else {
                continue;
            };
            let key = pair_key(a, b, Kind::Collision);
            let fa = Follow {
                index: three.index_of(a, m.station),
                ..f.clone()
            };
            let mut c = self.contact3(three, &fa, m, a, b, Kind::Collision, 0.0, hit, item.t0);
            c.message = format!(
                "{}: they are fixed to each other, so they overlap wherever the machine stands",
                c.message
            );
            if let Some(s) = c.snapshot3.as_mut() {
                s.title = c.message.clone();
            }
            self.episodes.contact(key, c);
            self.episodes.clear(key);
        }
    }

    /// Near misses of the pair `(a, b)` along the move (`near.rs`), as episodes.
    fn near_misses(&mut self, three: &Three, f: &Follow, m: &Move, item: &Timed, a: CompId, b: CompId) {
        let (Some(sa), Some(sb)) = (three.shapes[a].as_ref(), three.shapes[b].as_ref()) else {
            return;
        };
        let tol = self.settings.tolerance_mm;
        let c = self.settings.clearance_mm;
        // As the 2D exact scan: steps of at least min(tolerance, C/2) once in or near the band.
        let scan = near::scan(&three.kin, (a, sa), (b, sb), f, c, 2.0 * tol, tol.min(c / 2.0));
        self.stats.pair_tests += scan.probes;
        let key = pair_key(a, b, Kind::NearMiss);
        let time = |u: f64| item.t0 + u * item.duration;
        let mut first = true;
        for s in &scan.spans {
            let continues = first && s.u0 == 0.0 && self.episodes.is_open(key);
            first = false;
            if !continues {
                // A new episode: a band that left off in the previous move and did not go on
                // at this one's start ended there.
                self.episodes.clear(key);
                let mut vals = Vec::new();
                f.at(s.u0, &mut vals);
                let mut poser = Poser::new(&three.kin);
                poser.pose(&three.kin, &vals);
                let (pa, pb) = (*poser.world(a), *poser.world(b));
                let point = collide3::closest_point(sa, &pa, sb, &pb, c)
                    .unwrap_or_else(|| nalgebra::center(&(pa * sa.sphere().center), &(pb * sb.sphere().center)));
                let hit = Hit { depth: s.gap, point };
                let contact = self.contact3(three, f, m, a, b, Kind::NearMiss, s.u0, hit, time(s.u0));
                self.episodes.contact(key, contact);
            }
            self.episodes.extend(key, m.line, time(s.u_min), s.gap, true);
            self.episodes.extend(key, m.line, time(s.u1), s.gap, true);
            if !s.to_end {
                self.episodes.clear(key);
            }
        }
        if scan.spans.is_empty() {
            // Never within the clearance: an episode of the previous move ended with it.
            self.episodes.clear(key);
        }
        if let Some(u) = scan.unchecked {
            self.budget.push((
                m.line,
                format!(
                    "the near-miss scan of {} stopped after {MAX_PROBES} probes at {:.3} s: the rest of this move is unchecked",
                    self.names(&three.kin, a, b),
                    time(u)
                ),
            ));
        }
    }

    /// The cutter of a plunge that is out of the part at the end of the move has left its hole.
    fn end_plunge(&mut self, three: &Three, f: &dyn collide3::Path) {
        let Some(p) = self.plunge3 else { return };
        if self.probe3(three, f, p.cutter, STOCK, 1.0, None).is_none() {
            self.plunge3 = None;
        }
    }

    /// [`Checker::probe3`] for a later sample of contact `key`: the stock (with a milled grid) or
    /// the other part is asked how deep only beyond the contact's deepest so far
    /// (`mill::Ask::DeepestBeyond`, `collide3::overlap_beyond`), as a depth no deeper leaves the
    /// contact's deepest as it is.
    fn probe3_sample(
        &mut self,
        three: &Three,
        f: &dyn collide3::Path,
        (a, b): (CompId, usize),
        u: f64,
        key: u64,
    ) -> Option<Hit> {
        let floor = self.episodes.max_depth(key);
        self.probe3(three, f, a, b, u, floor)
    }

    /// Overlap of pair (a, b) at fraction `u` (b may be the stock); with `floor`, asked how deep
    /// only beyond it (the stock: `mill::Ask::DeepestBeyond`; a pair: `collide3::overlap_beyond`).
    fn probe3(
        &mut self,
        three: &Three,
        f: &dyn collide3::Path,
        a: CompId,
        b: usize,
        u: f64,
        floor: Option<f64>,
    ) -> Option<Hit> {
        let k = &three.kin;
        let mut vals = Vec::new();
        f.at(u, &mut vals);
        // The pair and the part's frame only.
        let pair = [a, b];
        let mut poser = three.poser_with_part(if b == STOCK { &pair[..1] } else { &pair });
        poser.pose(k, &vals);
        let sa = three.shapes[a].as_ref()?;
        if b == STOCK {
            self.ensure_stock()?;
            let stock = self.stock.as_mut()?;
            let ask = floor.map_or(mill::Ask::Deepest, mill::Ask::DeepestBeyond);
            mill::stock_hit(self.mill.as_ref(), stock, &three.posed(a, sa, &poser), ask)
        } else {
            let (pa, sb, pb) = (poser.world(a), three.shapes[b].as_ref()?, poser.world(b));
            match floor {
                Some(floor) => collide3::overlap_beyond(sa, pa, sb, pb, TOUCH_EPS, floor),
                None => collide3::overlap(sa, pa, sb, pb, TOUCH_EPS),
            }
        }
    }

    /// Conservative advancement of a component against the stock (see `collide3::motion`).
    /// `follow`: the move's follower, when `f` is one (the proofs of `slide.rs` read its path).
    fn stock_advance(
        &mut self,
        three: &Three,
        f: &dyn collide3::Path,
        follow: Option<&Follow>,
        a: CompId,
    ) -> (Advance, u64) {
        let k = &three.kin;
        let Some(sa) = three.shapes[a].as_ref() else {
            return (Advance::Clear, 0);
        };
        let min_step = self.settings.tolerance_mm.max(collide3::MIN_STEP_MM);
        let Some(b) = self.stock_box else {
            return (Advance::Clear, 0);
        };
        let raw = (b.min.y, b.max.y, b.max.x.max(-b.min.x));
        if self.ensure_stock().is_none() {
            return (Advance::Clear, 0);
        }
        let Some(stock) = self.stock.as_mut() else {
            return (Advance::Clear, 0);
        };
        let mill = self.mill.as_ref();
        // Against the milled stock, contacts up to its touch depth are touches: a step of that
        // much can step over nothing that counts.
        let min_step = mill.map_or(min_step, |m| min_step.max(m.touch()));
        // Only the component and the part's frame are asked for.
        let mut poser = three.poser_with_part(&[a]);
        let mut vals = Vec::new();
        f.at(0.0, &mut vals);
        poser.pose(k, &vals);
        // As the 2D check's conservative advancement: never a step longer than the proven gap,
        // at least the tolerance (a contact it could step over is shallower than that).
        let mut rates = Vec::new();
        f.deltas(0.0, 1.0, &mut rates);
        let rate = bound_from(k, &poser, a, &sa.sphere(), &rates);
        let (mut u, mut prev, mut probes) = (0.0f64, 0.0f64, 0u64);
        // A contact deeper than a touch of the component, posed as `poser` says, with the stock.
        let hit_at =
            |poser: &Poser, stock: &mut _| mill::stock_hit(mill, stock, &three.posed(a, sa, poser), mill::Ask::Any);
        // The gap is sought within a few mm: its cost grows with the columns the window spans.
        let window = rate.min(5.0) + 1.0;
        let mut slide = slide::Slide::new(SLIDE_STEPS * min_step / rate);
        loop {
            probes += 1;
            if probes > MAX_PROBES {
                return (Advance::Unchecked { u }, probes);
            }
            f.at(u, &mut vals);
            poser.pose(k, &vals);
            // Quick reject: the part's bounding sphere against the raw stock's cylinder (the
            // stock only loses material) bounds the gap from below at no cost.
            let sph = sa.sphere();
            let c = poser.world(a) * sph.center;
            let (zr0, zr1, rr) = raw;
            let radial = (c.x.hypot(c.y) - sph.radius - rr).max(0.0);
            let axial = (zr0 - (c.z + sph.radius)).max(c.z - sph.radius - zr1).max(0.0);
            let quick = radial.max(axial);
            if quick > 0.0 {
                if u == 0.0 && quick > rate {
                    // Out of the raw stock's reach over the whole move: the broad phase.
                    return (Advance::Clear, 0);
                }
                if u >= 1.0 || rate == 0.0 {
                    return (Advance::Clear, probes);
                }
                prev = u;
                let next = (u + quick.max(min_step) / rate).min(1.0);
                u = if next > u { next } else { (u + f64::EPSILON).min(1.0) };
                continue;
            }
            if let Some(h) = hit_at(&poser, stock) {
                if u == 0.0 {
                    return (Advance::Contact { u, hit: h }, probes);
                }
                let (mut lo, mut hi, mut best) = (prev, u, h);
                while hi - lo > 1e-9 {
                    probes += 1;
                    let mid = lo + (hi - lo) / 2.0;
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    f.at(mid, &mut vals);
                    poser.pose(k, &vals);
                    match hit_at(&poser, stock) {
                        Some(h) => (hi, best) = (mid, h),
                        None => lo = mid,
                    }
                }
                return (Advance::Contact { u: hi, hit: best }, probes);
            }
            if u >= 1.0 || rate == 0.0 {
                return (Advance::Clear, probes);
            }
            let gap = mill::stock_gap(mill, stock, &three.posed(a, sa, &poser), window);
            if !rate.is_finite() || gap.is_nan() {
                return (Advance::Unchecked { u }, probes);
            }
            prev = u;
            let step = gap.max(min_step) / rate;
            // Sliding along the dexel stock: a stretch proven clear in one query (`slide.rs`). The
            // dexel stock holds all the material: a stretch clear of it is clear of the milled
            // stock too.
            if let Some(f) = follow {
                if let Some(end) = slide.skip(three, f, a, sa, stock, u, step) {
                    u = end;
                    continue;
                }
            }
            let next = (u + step).min(1.0);
            u = if next > u { next } else { (u + f64::EPSILON).min(1.0) };
        }
    }

    /// The finding's facts at first contact, and its picture when asked for.
    #[allow(clippy::too_many_arguments)]
    fn contact3(
        &mut self,
        three: &Three,
        f: &dyn collide3::Path,
        m: &Move,
        a: CompId,
        b: usize,
        kind: Kind,
        u: f64,
        hit: Hit,
        t: f64,
    ) -> Contact {
        let k = &three.kin;
        // The JSON report's objects are the machine file's ids; the message is in words.
        let id = |c: usize| {
            if c == STOCK {
                "stock".to_string()
            } else {
                k.components[c].name.clone()
            }
        };
        let (a_, b_) = mover_first(k, a, b);
        let (an, bn) = (id(a_), id(b_));
        let (aw, bw) = (self.words3(k, a_), self.words3(k, b_));
        let message = match kind {
            Kind::RapidIntoStock if b == STOCK => format!("rapid move drives the {aw} into the stock"),
            Kind::RapidIntoStock => format!("rapid move drives the {aw} into the {bw}"),
            Kind::SpindleStopped => format!("the {aw} cuts the stock with neither the spindle nor a live tool turning"),
            Kind::NearMiss => format!(
                "the {aw} passes within {:.3} mm of the {bw}",
                self.settings.clearance_mm
            ),
            _ => format!("the {aw} hits the {bw}"),
        };
        let mut vals = Vec::new();
        f.at(u, &mut vals);
        let tip = nalgebra::Vector2::new(m.tip.x, m.tip.y);
        let xi = three.ax_x.map_or(0.0, |i| vals[i]);
        let zi = three.ax_z.map_or(0.0, |i| vals[i]);
        let (x, z) = self.frame().to_program(crate::geom::P2::new(xi, zi) + tip);
        let snapshot3 = self
            .settings
            .snapshots
            .then(|| Box::new(self.scene3(three, &vals, m, a, b, &message, t, hit.point)));
        Contact {
            kind,
            objects: [an, bn],
            words: Some([aw, bw]),
            line: m.line,
            n: m.n,
            profile_line: m.profile_line,
            time: t,
            x,
            z,
            depth: Some(hit.depth),
            message,
            snapshot: None,
            snapshot3,
        }
    }

    /// What a machinist calls component `c` (or the stock) in a message, without article:
    /// [`words`](crate::kin::words::words) with the cutter of the machine's tool in its station.
    pub(super) fn words3(&self, k: &Kinematics, c: usize) -> String {
        if c == STOCK {
            return "stock".into();
        }
        let comp = &k.components[c];
        let cutter = comp
            .station
            .and_then(|s| self.machine.tools.iter().find(|t| t.station == s))
            .map(|t| t.cutter);
        crate::kin::words::words(comp, cutter)
    }

    /// A pair in words: "the T08 drill and the stock".
    pub(super) fn names(&self, k: &Kinematics, a: CompId, b: usize) -> String {
        format!("the {} and the {}", self.words3(k, a), self.words3(k, b))
    }

    /// The posed scene for a picture.
    #[allow(clippy::too_many_arguments)]
    fn scene3(
        &mut self,
        three: &Three,
        vals: &[f64],
        m: &Move,
        a: CompId,
        b: usize,
        title: &str,
        t: f64,
        point: Point3<f64>,
    ) -> Snapshot3 {
        let k = &three.kin;
        let mut poser = Poser::new(k);
        poser.pose(k, vals);
        let moved = moved_flags(k, vals, &three.start);
        let on = three.present(m.station, self.tailstock_in);
        // An index sweep draws the pair as it swings and the active station's tools; any other
        // move every station's tools, each at its station's angle.
        let sweep = matches!(m.kind, MoveKind::ToolChange { .. });
        let drum = match three.carousel {
            Carousel::Drum { ix, .. } if !sweep => Some(ix.axis),
            _ => None,
        };
        let mut posers: Vec<(u64, Poser)> = Vec::new();
        let mut parts = Vec::new();
        for i in 0..k.components.len() {
            let other = three
                .station_of
                .get(i)
                .copied()
                .flatten()
                .is_some_and(|s| s != m.station);
            // The pair itself always (a tool of another station swung by an index).
            if (!on[i] || (sweep && other)) && i != a && i != b {
                continue;
            }
            let pose = match drum {
                Some(ax) => {
                    let v = three.index_of(i, m.station).map_or(0.0, |x| x.1);
                    let j = match posers.iter().position(|p| p.0 == v.to_bits()) {
                        Some(j) => j,
                        None => {
                            let mut vv = vals.to_vec();
                            if let Some(x) = vv.get_mut(ax) {
                                *x = v;
                            }
                            let mut p = Poser::new(k);
                            p.pose(k, &vv);
                            posers.push((v.to_bits(), p));
                            posers.len() - 1
                        }
                    };
                    *posers[j].1.world(i)
                }
                None => *poser.world(i),
            };
            let Some(mesh) = three.mesh(i, self.settings.tolerance_mm) else {
                continue;
            };
            let role = Role3::of(i, (a, b), moved[i]);
            parts.push(Part3 {
                name: self.words3(k, i),
                mesh,
                pose,
                role,
            });
        }
        let stock_role = if b == STOCK { Role3::CollidingB } else { Role3::Stock };
        // A milled part is drawn as both its models hold it now (holes, flats and pockets in it).
        let milled = match (self.mill.as_ref(), self.stock.as_ref()) {
            (Some(mill), Some(d)) => mill.picture_mesh(d),
            _ => None,
        };
        if let Some(mesh) = milled {
            parts.push(Part3 {
                name: "stock".into(),
                mesh: Arc::new(mesh),
                pose: three.part_pose(&poser),
                role: stock_role,
            });
        } else if let Some(stock) = self.stock.as_ref() {
            for outline in stock.outlines(1e-9) {
                let pts: Vec<crate::geom::P2> =
                    outline.iter().map(|p| crate::geom::P2::new(p[0].abs(), p[1])).collect();
                if let Ok(mesh) = crate::kin::shape::revolved(&pts, self.settings.tolerance_mm.max(0.05)) {
                    parts.push(Part3 {
                        name: "stock".into(),
                        mesh: Arc::new(mesh),
                        pose: crate::kin::Iso::identity(),
                        role: stock_role,
                    });
                }
            }
        }
        Snapshot3 {
            title: title.to_string(),
            line: m.line,
            time_s: Some(t),
            parts,
            contact: Some(point),
        }
    }

    /// Whether this cutter's move runs back along the line of its own plunge (see the module docs).
    fn in_own_plunge(&self, three: &Three, cutter: CompId, m: &Move, e: Option<&ExtraMove>, item: &Timed) -> bool {
        let Some(p) = self.plunge3 else { return false };
        if p.cutter != cutter {
            return false;
        }
        let c_at = |ex: &[f64; 4]| ex[1];
        if let Some(e) = e {
            if c_at(&e.start) != p.c || c_at(&e.end) != p.c || e.arc.is_some() {
                return false;
            }
        }
        let s = ref3(three, m, e, item, 0.0);
        let f = ref3(three, m, e, item, 1.0);
        on_line(&p, s) && on_line(&p, f) && matches!(m.kind, MoveKind::Rapid | MoveKind::Line)
    }

    fn record_plunge(&mut self, three: &Three, cutter: CompId, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let c = e.map_or(0.0, |e| e.end[1]);
        let s = ref3(three, m, e, item, 0.0);
        let f = ref3(three, m, e, item, 1.0);
        let same_c = e.is_some_and(|e| e.start[1] == e.end[1]);
        let plunge = match self.plunge3 {
            Some(p) if p.cutter == cutter && p.c == c && on_line(&p, s) && on_line(&p, f) => {
                // Deeper along the same line: keep the end farthest from where it began.
                let far = if dist(p.a, f) > dist(p.a, p.b) { f } else { p.b };
                Some(Plunge { b: far, ..p })
            }
            _ if same_c && matches!(m.kind, MoveKind::Line) => Some(Plunge { cutter, c, a: s, b: f }),
            _ => None,
        };
        self.plunge3 = plunge;
    }

    /// Overtravel of the extra axes (X and Z are the 2D check's).
    fn extra_overtravel(&mut self, three: &Three, m: &Move, e: Option<&ExtraMove>, item: &Timed) {
        let Some(e) = e else { return };
        let k = &three.kin;
        let mut vals = Vec::new();
        for (slot, a) in three.ax_extra.iter().enumerate() {
            let Some(a) = *a else { continue };
            let (lo, hi) = k.axes[a].travel;
            let mut worst: Option<(f64, f64)> = None;
            let n = if e.arc.is_some() { 64 } else { 1 };
            // As for X and Z: a move over-travels when it goes past a limit farther than it
            // already was at its start (one finding per such move).
            let mut base = 0.0f64;
            for j in 0..=n {
                let u = j as f64 / n as f64;
                three.values(m, Some(e), item, u, &mut vals);
                let v = vals[a];
                let over = (lo - v).max(v - hi);
                if j == 0 {
                    base = over.max(0.0);
                    continue;
                }
                if over > base + 1e-9 && worst.map_or(true, |w: (f64, f64)| over > w.1) {
                    worst = Some((u, over));
                }
            }
            let Some((u, over)) = worst else { continue };
            let key = KEY_BASE - 1 - slot as u64;
            if self.episodes.is_open(key) {
                continue;
            }
            let name = &k.axes[a].name;
            let letter = k.axes[a].letter;
            let t = item.t0 + u * item.duration;
            let (x, z) = self.frame().to_program(m.end);
            let message = format!("axis {name} ({letter}) goes {over:.3} past its travel [{lo}, {hi}]");
            self.episodes.contact(
                key,
                Contact {
                    kind: Kind::Overtravel,
                    objects: [format!("{letter} axis"), "travel limit".into()],
                    words: None,
                    line: m.line,
                    n: m.n,
                    profile_line: m.profile_line,
                    time: t,
                    x,
                    z,
                    depth: Some(over),
                    message,
                    snapshot: None,
                    snapshot3: None,
                },
            );
            self.episodes.clear(key);
        }
    }
}

impl Three {
    /// Component `c`'s pose with the axes at `vals` and the turret's index at `c`'s station's
    /// angle for a move made with station `active` (0: the file's pose).
    fn pose_of(&self, c: CompId, active: u32, vals: &[f64]) -> crate::kin::Iso {
        let mut v = vals.to_vec();
        if let Carousel::Drum { ix, .. } = self.carousel {
            if let Some(x) = v.get_mut(ix.axis) {
                *x = self.index_of(c, active).map_or(0.0, |i| i.1);
            }
        }
        let mut poser = Poser::new(&self.kin);
        poser.pose(&self.kin, &v);
        *poser.world(c)
    }

    /// A component's mesh for pictures (built when a picture is asked for).
    fn mesh(&self, i: CompId, tol: f64) -> Option<Arc<crate::kin::Mesh>> {
        let g = self.kin.components[i].geometry.as_ref()?;
        crate::kin::shape::mesh_of(g, tol.max(0.05)).ok().map(Arc::new)
    }
}

/// A move that only turns the main spindle (C) through more than a turn, everything else
/// standing still, poses every part during its first turn as it ever will: after it, nothing new
/// can happen. Its prefix in time that turns C by one turn and the part of a turn that brings C
/// to the move's end modulo 360° (so the parts end where the whole move leaves them): the move
/// the 3D path checks in its place, at a cost independent of the number of turns. `None` for
/// any other move.
fn first_turns(m: &Move, e: &ExtraMove, item: &Timed) -> Option<(ExtraMove, Timed)> {
    let dc = e.end[1] - e.start[1];
    if !only_c_turns(m, e) || dc.is_nan() || dc.abs() <= 720.0 {
        return None;
    }
    let turn = (360.0 + dc.abs().rem_euclid(360.0)).copysign(dc);
    let mut e1 = *e;
    e1.end[1] = e.start[1] + turn;
    let item1 = Timed {
        duration: item.duration * (turn / dc),
        ..item.clone()
    };
    Some((e1, item1))
}

/// The move turns C and nothing else moves: X, Z, Y, B and A stand, no arc.
pub(super) fn only_c_turns(m: &Move, e: &ExtraMove) -> bool {
    m.start == m.end && e.arc.is_none() && [0usize, 2, 3].iter().all(|&k| e.start[k] == e.end[k])
}

/// Per component: an axis on its way from the root is off its start value.
fn moved_flags(k: &Kinematics, vals: &[f64], start: &[f64]) -> Vec<bool> {
    let mut out = vec![false; k.components.len()];
    for (i, c) in k.components.iter().enumerate() {
        let own = c.axis.is_some_and(|a| vals.get(a) != start.get(a));
        out[i] = own || c.parent.is_some_and(|p| out[p]);
    }
    out
}

/// The turret reference point (x, y, z) at fraction `u`.
fn ref3(three: &Three, m: &Move, e: Option<&ExtraMove>, item: &Timed, u: f64) -> [f64; 3] {
    let mut v = Vec::new();
    three.values(m, e, item, u, &mut v);
    let g = |a: Option<AxisId>| a.map_or(0.0, |a| v[a]);
    [g(three.ax_x), g(three.ax_extra[0]), g(three.ax_z)]
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// `p` lies on the plunge's line (within 1e-6 mm), on the side where it began or beyond its end.
fn on_line(pl: &Plunge, p: [f64; 3]) -> bool {
    let d = [pl.b[0] - pl.a[0], pl.b[1] - pl.a[1], pl.b[2] - pl.a[2]];
    let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    if len < 1e-9 {
        return dist(pl.a, p) < 1e-6;
    }
    let w = [p[0] - pl.a[0], p[1] - pl.a[1], p[2] - pl.a[2]];
    let along = (w[0] * d[0] + w[1] * d[1] + w[2] * d[2]) / len;
    let off2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] - along * along;
    // Any point before the deepest one: the cutter's way out of its hole is along the line.
    off2.max(0.0).sqrt() < 1e-6 && along <= len + 1e-6
}

/// Whether the X slide carries component `i` (the turret, its housing, the tools).
fn carried_by_x(k: &Kinematics, i: CompId) -> bool {
    let mut p = Some(i);
    while let Some(q) = p {
        if k.components[q].axis.is_some_and(|a| k.axes[a].letter == 'X') {
            return true;
        }
        p = k.components[q].parent;
    }
    false
}

/// The pair with the part that moves into the other first, as in the 2D findings.
fn mover_first(k: &Kinematics, a: CompId, b: usize) -> (usize, usize) {
    if b != STOCK && !carried_by_x(k, a) && carried_by_x(k, b) {
        (b, a)
    } else {
        (a, b)
    }
}

fn pair_key(a: CompId, b: usize, kind: Kind) -> u64 {
    let b = if b == STOCK { 0xFFFF } else { b as u64 & 0xFFFF };
    KEY_BASE | ((a as u64 & 0xFFFF) << 24) | (b << 8) | kind as u64
}

/// Conservative advancement of a pair of components.
/// Lower bounds of component pairs' gaps, by pair (`Checker::gap3`).
pub(super) type PairGaps = Vec<((CompId, usize), f64)>;

/// A component pair along the move: the advance, a lower bound of the pair's gap at the move's
/// end (0 when unknown), and the probes it cost. `start_gap` is a known lower bound of the gap
/// at the move's start (0: none).
fn pair_advance(three: &Three, f: &Follow, a: CompId, b: CompId, tol: f64, start_gap: f64) -> (Advance, f64, u64) {
    let k = &three.kin;
    let (Some(sa), Some(sb)) = (three.shapes[a].as_ref(), three.shapes[b].as_ref()) else {
        return (Advance::Clear, 0.0, 0);
    };
    // Overlaps count from twice the tolerance: the meshes of revolved parts and cylinders stand
    // up to the tolerance proud of their true surfaces (circumscribed), so two touching parts may
    // overlap that much as meshes alone (a drill sliding along a jaw's radius). Steps as the 2D
    // check's advancement: never longer than the proven gap, at least the tolerance.
    // Where the pair slides past each other at a small gap, stretches are proven clear by the
    // hull of one part's poses relative to the other (`slide::pair_proven`).
    let mut prove = |u0, u1| slide::pair_proven(three, f, (a, sa), (b, sb), u0, u1);
    collide3::first_contact_proving(k, (a, sa), (b, sb), f, 2.0 * tol, tol, start_gap, Some(&mut prove))
}
