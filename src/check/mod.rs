//! The checks (docs/checking.md): which parts may never touch which, and what an overlap means.
//!
//! Moving parts: the turret body, the active tool's holder and insert, and the tools of the other
//! stations. Obstacles: the chuck, the tailstock and the (in-process) stock. Rules:
//! - holder, turret and other stations against chuck, tailstock or stock: `collision`;
//! - the insert against chuck or tailstock: `collision`;
//! - the insert in the stock: `rapid_into_stock` in a rapid (`rapid_scrape`, a warning, when it is
//!   only the wedge the preceding feed's edge left, see [`scrape`]), `spindle_stopped` in a feed
//!   with the spindle stopped, machining otherwise (the stock loses what the insert sweeps);
//! - any of those pairs closer than `--clearance` without touching: `near_miss` (a warning);
//! - the turret reference point outside the axis limits: `overtravel`.
//!
//! One finding per episode and pair (see [`episodes`]). Per move, each pair's motion envelope
//! (the part's box swept over the move) is tested against the obstacle's box first; pairs whose
//! envelopes never meet cost nothing, and a move with no such pair is not sampled at all.

pub mod episodes;
mod exact;
mod scrape;
mod stream;
#[cfg(test)]
mod tests;
mod three;
mod turn_round;

use crate::finding::{Finding, Kind, Severity};
use crate::geom::convex::sweep_convex;
use crate::geom::{self, Aabb, Polygon, P2, V2};
use crate::interp::{ExtraMove, Interpretation, Move, MoveKind, MoveState, ProgFrame, Spindle};
use crate::machine::Machine;
use crate::motion::{self, Timed};
use crate::pipeline::{Mode, Settings, Stats};
use crate::scene::{DexelStock, Revolved, Scene, Section, Snapshot, StockHit, Swept, Travel, View, NO_SWEEP};

use episodes::{Contact, Episodes};
pub use stream::{takes_3d, takes_3d_depends_on_run, Stream};
pub(crate) use three::DEPTH_SAMPLES as DEPTH_SAMPLES_3D;

/// A moving part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    Turret,
    Holder,
    Insert,
    /// A tool in another station, out of the working plane.
    OtherHolder(u32),
    OtherInsert(u32),
}

/// A static, revolved obstacle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Obstacle {
    Chuck,
    Tailstock,
    Stock,
}

const OBSTACLES: [Obstacle; 3] = [Obstacle::Chuck, Obstacle::Tailstock, Obstacle::Stock];

/// Most samples step mode takes along one move; longer moves are checked as in exact mode.
pub const MAX_STEP_SAMPLES: u64 = 200_000;

/// Inside an open episode against the stock, the full depth is computed at every this many
/// samples; the others only confirm that the contact goes on.
const FULL_DEPTH_EVERY: u64 = 16;

/// How much of the way between two samples step mode may leave unproven against a polygon
/// obstacle (chuck, tailstock): at every instant of a stretch whose bounds cover all but this,
/// the part is clear or a translation by half of it clears it, and the depth of an overlap
/// (`geom::overlap`) never exceeds the translation that clears it: a touch (`geom::TOUCH_EPS`),
/// not a collision (see [`Checker::sample`]). Against the stock none: its depth is the radial
/// overlap in one column, which a part barely across a column's centre can have in full.
const SLACK: f64 = 2.0 * geom::TOUCH_EPS;

/// Episode key of a pair and rule. Tools are keyed by station, whatever station is active, so a
/// contact that goes on through a turret index stays one episode.
fn key(part: Part, active: u32, obs: Obstacle, kind: Kind) -> u64 {
    let p = match part {
        Part::Turret => 0,
        Part::Holder => 1 + 2 * active as u64,
        Part::Insert => 2 + 2 * active as u64,
        Part::OtherHolder(s) => 1 + 2 * s as u64,
        Part::OtherInsert(s) => 2 + 2 * s as u64,
    };
    (p << 16) | ((obs as u64) << 8) | kind as u64
}

/// What a check found and what it cost.
pub struct CheckResult {
    pub findings: Vec<Finding>,
    pub stats: Stats,
    /// The stock at the end, when the program reached it.
    pub stock: Option<DexelStock>,
    /// With `Settings::part_mesh`: the final part as binary STL.
    pub part_stl: Option<Vec<u8>>,
    /// With [`Stream::share_cuts`]'s `record`: each cutting move's index and the polygons its
    /// insert swept (what it took off the stock), for the other paths of a multi-path program.
    pub cuts: Vec<Cut>,
}

/// What one feed move took off the stock: the move's index and what it removed.
pub type Cut = (usize, Removed);

/// What a move removed, for the other paths of a multi-path program.
#[derive(Clone, Debug)]
pub enum Removed {
    /// The polygons the insert swept (the working plane, folded about the axis as the dexel stock
    /// is).
    Turned(Vec<Vec<crate::geom::P2>>),
    /// The sweeps a milling cutter made through the milled stock (the part's frame).
    Milled(Vec<crate::grid::Sweep>),
}

/// The checker reads a program one move at a time (`stream.rs`): of the run it sees only the
/// move being checked, its state and extra-axis entry (`now`), and the two moves behind it that
/// a rule looks back at (`behind`).
struct Checker<'a> {
    now: Now,
    behind: Behind,
    machine: &'a Machine,
    scene: Scene,
    settings: Settings,
    stock: Option<DexelStock>,
    /// Box of the raw stock, both halves of the section.
    stock_box: Option<Aabb>,
    episodes: Episodes,
    stats: Stats,
    cut_any: bool,
    /// Record each cut in `cuts` (`Stream::share_cuts`).
    record_cuts: bool,
    cuts: Vec<Cut>,
    /// The index in the run of the move being checked (a milled cut's, for `cuts`).
    move_index: usize,
    indexed: bool,
    others_tested: bool,
    /// The buffers of the last whole cut's swept region, reused by the next (`Checker::cut`).
    cut_buf: Swept,
    /// The feed move whose cut is under way, if any: stock queries see the stock as it is at the
    /// path fraction `instant` of that move.
    cutting: Option<Cutting>,
    /// The buffers of the last cutting move, reused by the next.
    spare: Option<Cutting>,
    instant: f64,
    /// Stock queries see the stock as it was before the cutting move (the insert's own
    /// spindle-stopped test).
    pre_move: bool,
    /// The source line of the move being checked.
    current_line: u32,
    /// The index of the last feed move whose cut changed the stock's journal (`scrape.rs`).
    last_cut: Option<usize>,
    /// Per pair key, the index of the last move whose exact measure found it in contact (step
    /// mode measures a pair in contact during the previous move exactly at once, see
    /// [`Checker::measure_likely_contacts`]).
    contact_moves: Vec<(u64, usize)>,
    /// The last two probes of conservative advancement whose answers can be named (see
    /// [`exact::ProbeKey`]), newest first: a move in contact at its end is probed at the same
    /// pose when the next move starts.
    last_probes: [Option<(exact::ProbeKey, Result<f64, f64>)>; 2],
    /// The pair (part, obstacle, station) and move index of the last move proven buried no
    /// deeper than its contact already was (`Checker::buried_no_deeper`): the next move of that
    /// pair is likely buried too, and is tried in the order that costs least when it is.
    buried: Option<(Part, Obstacle, u32, usize)>,
    /// Moves whose check ran out of its work budget: (line, message).
    budget: Vec<(u32, String)>,
    /// Moves step mode checked as exact mode does because they had too many samples.
    long_moves: bool,
    /// The tailstock is advanced during the move being checked: only then is it an obstacle.
    tailstock_in: bool,
    /// The 3D path of a machine with a kinematic tree (`three.rs`); `None` on a 2-axis lathe.
    three: Option<three::Three>,
    /// A live tool's plunge into the positioned part (`three.rs`).
    plunge3: Option<three::Plunge>,
    /// The milled stock once a live cutter milled the positioned part (`three/mill.rs`).
    mill: Option<three::mill::Mill>,
    /// Lower bounds of the 3D component pairs' gaps at the end of move `.0` (`three.rs`).
    gap3: Option<(usize, three::PairGaps)>,
    /// The pairs of parts fixed to each other already tested (`three.rs`, `rigid_pairs`).
    rigid3: std::collections::BTreeSet<(usize, usize)>,
    /// A job's operation began: the part was turned round (`turn_round.rs`).
    turned: bool,
}

/// The move being checked, with what it refers to.
struct Now {
    m: Move,
    state: MoveState,
    extra: Option<ExtraMove>,
}

/// The moves behind the one being checked that the checker looks back at.
#[derive(Default)]
struct Behind {
    /// The move just before it (a snapshot draws its path).
    prev: Option<Move>,
    /// The last move before it that is no dwell, and its index (the feed a rapid follows,
    /// `scrape.rs`).
    motion: Option<(usize, Move)>,
}

/// A feed move whose cut is under way (see [`DexelStock::begin_move`]).
#[derive(Default)]
struct Cutting {
    index: usize,
    /// Its station (the insert that cuts).
    station: u32,
    /// Its programmed path as chords: (path fraction, point) at each vertex.
    path: Vec<(f64, P2)>,
    /// The chords (index of their first vertex) whose sweep can reach the raw stock.
    kept: Vec<usize>,
    /// The path fraction `swept` was built for (NaN: none yet).
    f: f64,
    /// The insert's swept region from the move's start to fraction `f`.
    swept: Swept,
}

impl Cutting {
    /// The stock as a query sees it during this move: cut up to the instant, or as it was before
    /// the move (`pre_move`: the insert's own spindle-stopped test).
    fn view(&self, pre_move: bool) -> View<'_> {
        if pre_move {
            return View::Instant(&NO_SWEEP);
        }
        // Past the path's last vertex the region swept so far is the whole cut's (the same
        // polygons `Checker::cut` took off, with the same arithmetic): the stock as it is now,
        // without going through the polygons column by column at every query (a circle of many
        // turns is past it after its first, `Checker::chords`).
        if self.path.last().is_some_and(|&(u, _)| self.f >= u) {
            return View::Now;
        }
        View::Instant(&self.swept)
    }
}

/// Check a program's moves on a machine, the whole run at once (the streamed check,
/// [`Stream`], fed every move in one chunk: what `pipeline::check` gets from the interpreter
/// chunk by chunk).
pub fn check(run: &Interpretation, machine: &Machine, settings: &Settings) -> CheckResult {
    check_capped(run, machine, settings, crate::finding::MAX_FINDINGS)
}

/// [`check`] of one path of a multi-path program whose stock the paths share
/// ([`Stream::share_cuts`]): `foreign` the other paths' cuts, each before the move it precedes;
/// with `record`, this path's own cuts in [`CheckResult::cuts`].
pub fn check_sharing(
    run: &Interpretation,
    machine: &Machine,
    settings: &Settings,
    foreign: Vec<Cut>,
    record: bool,
) -> CheckResult {
    run_stream(
        run,
        machine,
        settings,
        crate::finding::MAX_FINDINGS,
        Some((foreign, record)),
    )
}

/// [`check`] for a report that keeps the first `cap` findings of a file in line order: a contact
/// certainly left out is counted but measured only as far as the findings shown depend on it
/// (`exact::Measure::Coarse`).
fn check_capped(run: &Interpretation, machine: &Machine, settings: &Settings, cap: usize) -> CheckResult {
    run_stream(run, machine, settings, cap, None)
}

/// A whole run through one [`Stream`], sharing the stock as [`check_sharing`] says when `share`.
fn run_stream(
    run: &Interpretation,
    machine: &Machine,
    settings: &Settings,
    cap: usize,
    share: Option<(Vec<Cut>, bool)>,
) -> CheckResult {
    // Another path's milling is taken off the milled stock, which only the 3D path has: a path
    // that shares it is checked on that path.
    let milled = share
        .as_ref()
        .is_some_and(|(f, _)| f.iter().any(|c| matches!(c.1, Removed::Milled(_))));
    let three = takes_3d(
        machine,
        !run.extra.is_empty() || milled,
        run.states.iter().any(|s| !s.tailstock_advanced),
    );
    let mut s = Stream::new(machine, settings, three, cap);
    if let Some((foreign, record)) = share {
        s.share_cuts(foreign, record);
    }
    s.feed(crate::interp::Chunk {
        first: 0,
        moves: &run.moves,
        states: &run.states,
        extra: &run.extra,
    });
    s.finish()
}

/// What the checker takes a move to be in before its first move (never read: `Now` is set
/// before each move is checked).
const NO_MOVE: Now = Now {
    m: Move {
        kind: MoveKind::Dwell { seconds: 0.0 },
        line: 0,
        n: None,
        profile_line: 0,
        start: P2::new(0.0, 0.0),
        end: P2::new(0.0, 0.0),
        tip: V2::new(0.0, 0.0),
        station: 0,
        feed: crate::interp::Feed::Rapid,
        state: 0,
    },
    state: MoveState {
        spindle: Spindle {
            dir: crate::interp::SpindleDir::Off,
            speed: crate::interp::SpindleSpeed::Rpm(0.0),
        },
        frame: ProgFrame {
            origin: P2::new(0.0, 0.0),
            scale: 1.0,
            diameter: false,
        },
        tailstock_advanced: false,
        tool_unknown: false,
        sub_chuck_closed: false,
    },
    extra: None,
};

/// A checker on `machine`, before its first move; with the 3D path when `three` (see
/// [`takes_3d`]) and the machine has a kinematic tree.
fn checker<'a>(machine: &'a Machine, settings: &Settings, three: bool) -> Checker<'a> {
    let scene = Scene::new(machine, settings.tolerance_mm);
    let turret = (scene.gang, scene.turret_axis, scene.stations);
    let stock_box = machine.stock.as_ref().map(|s| Aabb {
        min: P2::new(-s.diameter / 2.0, s.front - s.length),
        max: P2::new(s.diameter / 2.0, s.front),
    });
    let mut c = Checker {
        now: NO_MOVE,
        behind: Behind::default(),
        machine,
        scene,
        settings: *settings,
        stock: None,
        stock_box,
        episodes: Episodes::default(),
        stats: Stats::default(),
        cut_any: false,
        record_cuts: false,
        cuts: Vec::new(),
        move_index: 0,
        indexed: false,
        others_tested: false,
        cut_buf: Swept::default(),
        cutting: None,
        spare: None,
        instant: 1.0,
        pre_move: false,
        current_line: 0,
        budget: Vec::new(),
        last_cut: None,
        contact_moves: Vec::new(),
        last_probes: [None; 2],
        buried: None,
        long_moves: false,
        tailstock_in: machine.tailstock_advanced,
        three: machine.kinematics.as_ref().filter(|_| three).map(|k| {
            let mut t = three::Three::new(k.clone(), settings.tolerance_mm);
            t.set_turret(turret.0, turret.1, turret.2);
            t
        }),
        plunge3: None,
        mill: None,
        gap3: None,
        rigid3: std::collections::BTreeSet::new(),
        turned: false,
    };
    // A block is milled from the start: its grids are the block, its dexel stock the envelope.
    if let Some(s) = machine
        .stock
        .as_ref()
        .filter(|s| s.block.is_some() && c.three.is_some())
    {
        c.ensure_stock();
        c.mill = three::mill::Mill::block(s, settings.tolerance_mm);
    }
    c
}

impl Checker<'_> {
    fn obstacle(&self, o: Obstacle) -> Option<&Revolved> {
        match o {
            Obstacle::Chuck => self.scene.chuck.as_ref(),
            Obstacle::Tailstock => self.scene.tailstock.as_ref().filter(|_| self.tailstock_in),
            Obstacle::Stock => None,
        }
    }

    /// Whether no part posed anywhere along a move whose reference point stays in `rb` can come
    /// within `margin` of any obstacle's box (both halves of the section): the parts' reach
    /// ([`Scene::reach`]) from `rb` misses every obstacle in `z`, or keeps farther from the
    /// spindle axis than every obstacle reaches.
    fn out_of_reach(&self, rb: &Aabb, margin: f64) -> bool {
        let (rx, rz) = self.scene.reach;
        let near_r = if rb.min.x <= 0.0 && rb.max.x >= 0.0 {
            0.0
        } else {
            rb.min.x.abs().min(rb.max.x.abs())
        };
        OBSTACLES.iter().filter_map(|&o| self.obstacle_box(o)).all(|ob| {
            let r_obs = ob.min.x.abs().max(ob.max.x.abs());
            rb.min.y - rz > ob.max.y + margin || rb.max.y + rz < ob.min.y - margin || near_r - rx > r_obs + margin
        })
    }

    fn obstacle_box(&self, o: Obstacle) -> Option<Aabb> {
        match o {
            Obstacle::Stock => self.stock_box,
            _ => self.obstacle(o).map(|r| r.aabb),
        }
    }

    fn ensure_stock(&mut self) -> Option<&mut DexelStock> {
        if self.stock.is_none() {
            let s = self.machine.stock.as_ref()?;
            self.stock = Some(match &s.outline {
                Some(o) => DexelStock::from_outline(o.points(), self.settings.tolerance_mm),
                None => DexelStock::new(s.diameter, s.bore, s.length, s.front, self.settings.tolerance_mm),
            });
        }
        self.stock.as_mut()
    }

    /// The tailstock against the raw stock and the chuck, once, at program start (`line`: the
    /// program's first move's, else 1).
    fn static_pairs(&mut self, line: u32) {
        let Some(ts) = self.obstacle(Obstacle::Tailstock).cloned() else {
            return;
        };
        if let Some(ch) = self.scene.chuck.clone() {
            if let Some(d) = geom::overlap(&ts.outline, &ch.outline) {
                self.setup_overlap(line, "chuck", d);
            }
        }
        if self.machine.stock.is_some() {
            let pts = ts.outline.points().to_vec();
            if let Some(hit) = self.ensure_stock().and_then(|s| s.overlap(&pts, geom::TOUCH_EPS)) {
                self.setup_overlap(line, "stock", hit.depth);
            }
        }
    }

    /// A collision of the tailstock with `other` in the setup, before anything moves.
    fn setup_overlap(&mut self, line: u32, other: &str, depth: f64) {
        let mut f = Finding::at(
            Kind::Collision,
            Severity::Error,
            line,
            0,
            format!("the tailstock overlaps the {other} in the setup"),
        );
        f.objects = vec!["tailstock".into(), other.into()];
        f.depth_mm = Some(depth);
        f.time_s = Some(0.0);
        f.operation = (self.episodes.operation > 0).then_some(self.episodes.operation);
        self.episodes.findings.push(f);
    }

    fn parts(&self, active: u32) -> Vec<Part> {
        let mut v = vec![Part::Turret];
        if self.scene.tool(active).is_some() {
            v.push(Part::Holder);
            v.push(Part::Insert);
        }
        for t in &self.scene.tools {
            if t.station != active {
                v.push(Part::OtherHolder(t.station));
                v.push(Part::OtherInsert(t.station));
            }
        }
        v
    }

    /// What the cutting part of the tool in `station` is called ("insert", "drill", …).
    fn cutter_word(&self, station: u32) -> &'static str {
        self.machine
            .tools
            .iter()
            .find(|t| t.station == station)
            .map_or("insert", |t| t.cutter.word())
    }

    fn name(&self, part: Part, active: u32) -> String {
        match part {
            Part::Turret => "turret".into(),
            Part::Holder => format!("T{active:02} holder"),
            Part::Insert => format!("T{active:02} {}", self.cutter_word(active)),
            Part::OtherHolder(s) => format!("T{s:02} holder"),
            Part::OtherInsert(s) => format!("T{s:02} {}", self.cutter_word(s)),
        }
    }

    /// The part's polygon when the reference point is at `r`, and whether it lies in the working
    /// plane (else it is already in the radial section).
    fn pose(&self, part: Part, r: P2, active: f64) -> Option<(Section, bool)> {
        let whole = |p: Polygon| Some((Section::Whole(p), true));
        match part {
            Part::Turret => whole(self.scene.turret.translated(r.coords)),
            Part::Holder | Part::Insert => {
                let t = self.scene.tool(active.round() as u32)?;
                let shape = if part == Part::Holder { &t.holder } else { &t.insert };
                whole(shape.translated(r.coords + t.tip))
            }
            Part::OtherHolder(s) | Part::OtherInsert(s) => {
                let t = self.scene.tool(s)?;
                let shape = if matches!(part, Part::OtherHolder(_)) {
                    &t.holder
                } else {
                    &t.insert
                };
                let angle = self.scene.station_angle(s, active);
                self.scene.map_to_section(shape, t.tip, r, angle).map(|p| (p, false))
            }
        }
    }

    /// Box of a part over a move whose reference point stays in `rb`.
    fn envelope(&self, part: Part, rb: &Aabb, active: u32) -> Option<Aabb> {
        match part {
            Part::Turret => Some(minkowski(self.scene.turret.aabb(), rb)),
            Part::Holder | Part::Insert => {
                let t = self.scene.tool(active)?;
                let shape = if part == Part::Holder { &t.holder } else { &t.insert };
                Some(minkowski(&shape.aabb().translate(t.tip), rb))
            }
            Part::OtherHolder(_) | Part::OtherInsert(_) => {
                // The box of the sections at every reference point in `rb` (`Scene::section_box`).
                let (station, holder) = match part {
                    Part::OtherHolder(s) => (s, true),
                    _ => (
                        match part {
                            Part::OtherInsert(s) => s,
                            _ => 0,
                        },
                        false,
                    ),
                };
                let t = self.scene.tool(station)?;
                let extent = if holder { &t.holder_extent } else { &t.insert_extent };
                let turned = self.scene.station_sin_cos(station, active);
                Some(self.scene.section_box_turned(extent, rb, turned))
            }
        }
    }

    /// Overlap depth (> TOUCH_EPS) or gap (< clearance) of a posed part with an obstacle.
    fn test(&mut self, part: &Section, in_plane: bool, obs: Obstacle) -> (Option<f64>, Option<f64>) {
        self.test_with(part, in_plane, obs, false)
    }

    /// [`Self::test_one`] of each piece of a posed part: the deepest overlap, else the nearest
    /// gap (the pieces together are the part).
    fn test_with(&mut self, part: &Section, in_plane: bool, obs: Obstacle, quick: bool) -> (Option<f64>, Option<f64>) {
        let (mut depth, mut gap): (Option<f64>, Option<f64>) = (None, None);
        for poly in part.pieces() {
            let (d, g) = self.test_one(poly, in_plane, obs, quick);
            depth = match (depth, d) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            };
            gap = match (gap, g) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
        }
        if depth.is_some() {
            gap = None;
        }
        (depth, gap)
    }

    /// With `quick`, a stock test stops at the first column that proves an overlap (used inside
    /// an open episode, where only its continuation is in question; its depth is then a lower
    /// bound, and the full depth is computed every [`FULL_DEPTH_EVERY`] samples).
    fn test_one(&mut self, poly: &Polygon, in_plane: bool, obs: Obstacle, quick: bool) -> (Option<f64>, Option<f64>) {
        self.stats.pair_tests += 1;
        let clearance = self.settings.clearance_mm;
        match obs {
            Obstacle::Stock => (
                self.stock_overlap(poly.points(), geom::TOUCH_EPS, quick)
                    .map(|h| h.depth),
                None,
            ),
            _ => {
                let Some(rev) = self.obstacle(obs) else {
                    return (None, None);
                };
                let mut depth = geom::overlap(poly, &rev.outline);
                if in_plane {
                    if let Some(d) = geom::overlap(poly, &rev.mirror) {
                        depth = Some(depth.map_or(d, |e: f64| e.max(d)));
                    }
                }
                if depth.is_some() || clearance <= 0.0 {
                    return (depth, None);
                }
                let mut gap = geom::distance(poly, &rev.outline);
                if in_plane {
                    gap = gap.min(geom::distance(poly, &rev.mirror));
                }
                (None, (gap < clearance).then_some(gap))
            }
        }
    }

    /// Check move `m` (`item`: its timing), with the state it refers to and its extra-axis
    /// entry.
    fn one_move(&mut self, m: &Move, state: &MoveState, e: Option<&ExtraMove>, item: &Timed) {
        self.now = Now {
            m: *m,
            state: *state,
            extra: e.copied(),
        };
        self.current_line = m.line;
        if let MoveKind::Operation { op } = m.kind {
            // Whatever tool the turret holds, the operator turns the part round.
            self.turn_round(m, item, op as usize);
            return;
        }
        if state.tool_unknown {
            // The station holds no tool the machine file describes: the turret's place is unknown
            // (the interpreter reported it at the T word).
            return;
        }
        self.tailstock_in = state.tailstock_advanced;
        self.overtravel(m, item);
        if self.three.is_some() {
            self.transfer_before(m, e, item);
            let turns = state.spindle.is_on() && !e.is_some_and(|e| e.c_mode);
            let motion = matches!(m.kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. });
            let Some(t) = self.three.as_mut() else { return };
            let mut route = t.route(m, e, turns, self.tailstock_in);
            // A cutter inside its own non-revolved cut leaves the 2D model on every move; so does
            // every move while a milled part stands still (the 2D model sees it revolved: a
            // spinning part sweeps its revolved outline, a standing one does not).
            if self.plunge3.is_some() || (self.mill.is_some() && !turns) {
                route = three::Route::Space;
            }
            if route != three::Route::Plane {
                t.ran = true;
            }
            match (route, m.kind) {
                (three::Route::Space, MoveKind::ToolChange { from, to }) => {
                    // A T word out of the working plane swings the turret in 3D (three/index.rs).
                    self.three_index(m, e, item, from, to);
                    self.plunge3 = None;
                    return;
                }
                (three::Route::Space, _) if motion => {
                    self.three_move(m, e, item, false);
                    self.transfer_after(m, e, item);
                    return;
                }
                (three::Route::Hybrid, MoveKind::ToolChange { from, to }) => {
                    // The swing of the turret near the sub-spindle's side is a 3D question.
                    self.three_index(m, e, item, from, to);
                    self.plunge3 = None;
                    return;
                }
                (three::Route::Hybrid, _) if motion => {
                    // The 2D sections without their tailstock outline (the sub-spindle's side
                    // is the 3D path's), then the 3D pairs.
                    self.tailstock_in = false;
                    self.motion(m, item);
                    self.tailstock_in = state.tailstock_advanced;
                    self.three_move(m, e, item, true);
                    self.transfer_after(m, e, item);
                    return;
                }
                _ => {}
            }
        }
        match m.kind {
            MoveKind::ToolChange { from, to } => {
                self.plunge3 = None;
                self.index_sweep(m, item, from, to)
            }
            MoveKind::Dwell { .. } => {
                // Nothing moves: contacts in progress stay as they are.
                self.stats.steps += self.samples_in(item.t0, item.t1());
            }
            // A multi-path wait: this path stands while another moves (`crate::paths` checks
            // the carriers against each other over the paths' common time).
            MoveKind::Wait { .. } => {}
            _ => self.motion(m, item),
        }
        if self.three.is_some() {
            self.transfer_after(m, e, item);
        }
    }

    /// Samples of a move: every multiple of dt in [t0, t1), and the end pose (where the control
    /// stops at the programmed point) when it is not one of them.
    fn samples_in(&self, t0: f64, t1: f64) -> u64 {
        let dt = self.settings.dt_ms / 1000.0;
        let k0 = (t0 / dt - 1e-9).ceil().max(0.0);
        let k1 = (t1 / dt - 1e-9).ceil().max(0.0);
        (k1 - k0).max(0.0) as u64 + 1
    }

    /// A live tool turns during the move being checked (`ExtraMove::live_rpm`): its cutter
    /// cutting with the main spindle stopped is then no `spindle_stopped`.
    fn live_tool_turns(&self) -> bool {
        self.now.extra.is_some_and(|e| e.live_rpm > 0.0)
    }

    /// The spindle during the move being checked.
    fn spindle(&self) -> &Spindle {
        &self.now.state.spindle
    }

    /// How to turn the points of the move being checked back into program coordinates.
    fn frame(&self) -> &ProgFrame {
        &self.now.state.frame
    }

    fn motion(&mut self, m: &Move, item: &Timed) {
        let active = m.station;
        let rb = motion::reference_box(m, item);
        let rapid = m.kind == MoveKind::Rapid;
        let feed = !rapid;
        let insert_rule = if rapid {
            Some(Kind::RapidIntoStock)
        } else if !self.spindle().is_on() && !self.live_tool_turns() {
            Some(Kind::SpindleStopped)
        } else {
            None
        };
        let margin = self.settings.clearance_mm + 1e-6;
        let parts = self.parts(active);
        let mut cands: Vec<(Part, Obstacle)> = Vec::new();
        let mut insert_box = None;
        // Every part out of reach of every obstacle (a move far outside the machine): no part's
        // envelope could meet one, so none is computed.
        let parts = if self.out_of_reach(&rb, margin) {
            Vec::new()
        } else {
            parts
        };
        for &p in &parts {
            let Some(pb) = self.envelope(p, &rb, active) else {
                continue;
            };
            if p == Part::Insert {
                insert_box = Some(pb);
            }
            for o in OBSTACLES {
                if p == Part::Insert && o == Obstacle::Stock && insert_rule.is_none() {
                    continue;
                }
                if let Some(ob) = self.obstacle_box(o) {
                    let mg = if o == Obstacle::Stock { 1e-6 } else { margin };
                    if pb.meets(&ob, mg) {
                        cands.push((p, o));
                    }
                }
            }
        }
        let total_pairs = parts.len() as u64 * 3;
        let samples = self.samples_in(item.t0, item.t1());
        if self.settings.mode == Mode::Step {
            self.stats.steps += samples;
        }

        // Pairs that cannot touch during this move end their episodes.
        let live: Vec<u64> = cands.iter().flat_map(|&(p, o)| pair_keys(p, active, o)).collect();
        self.episodes.close_except(|k| k == OVERTRAVEL_KEY || live.contains(&k));
        let cuts = feed && insert_box.zip(self.stock_box).is_some_and(|(a, b)| a.meets(&b, 1e-6));
        if cuts {
            // The whole cut is applied now, but every stock query of this move sees the stock as
            // it is at that instant: the material before the move less what the insert has swept
            // up to then (ARCHITECTURE.md, "The stock at the instant").
            if let Some(s) = self.ensure_stock() {
                s.begin_move();
            }
            self.last_cut = Some(item.index);
            let mut c = self.spare.take().unwrap_or_default();
            c.index = item.index;
            c.station = m.station;
            c.f = f64::NAN;
            self.chords(m, &mut c);
            self.cutting = Some(c);
            self.cut();
        }
        if cuts && insert_rule == Some(Kind::SpindleStopped) {
            // The insert meets the material as it was before this move.
            let first: Vec<_> = cands
                .iter()
                .copied()
                .filter(|c| *c == (Part::Insert, Obstacle::Stock))
                .collect();
            self.pre_move = true;
            self.check_pairs(m, item, samples, &first, active, insert_rule);
            self.pre_move = false;
            cands.retain(|c| *c != (Part::Insert, Obstacle::Stock));
        }
        self.stats.pair_tests_skipped += (total_pairs - cands.len() as u64) * samples;
        let first_finding = self.episodes.findings.len();
        if !cands.is_empty() {
            self.check_pairs(m, item, samples, &cands, active, insert_rule);
        }
        if rapid && cands.contains(&(Part::Insert, Obstacle::Stock)) {
            self.mark_scrape(m, item, active, first_finding);
        }
        if cuts {
            if let Some(s) = self.stock.as_mut() {
                s.end_move();
            }
            self.spare = self.cutting.take();
        }
    }

    /// Rebuild the swept region of the cutting move for the current `instant` when it changed.
    fn refresh_swept(&mut self) {
        // A move whose cut took nothing off (a retrace, `DexelStock::cut`) has the stock at
        // every instant as it is now: no instant view reads the swept region.
        if self.stock.as_ref().is_some_and(|s| !s.move_changed_any()) {
            return;
        }
        let f = self.instant;
        let Some(mut c) = self.cutting.take() else { return };
        if c.f != f {
            let mut swept = std::mem::take(&mut c.swept);
            self.swept_until(&c, f, &mut swept);
            c.swept = swept;
            c.f = f;
        }
        self.cutting = Some(c);
    }

    /// Check the candidate pairs of a move of `samples` step-mode samples.
    #[allow(clippy::too_many_arguments)]
    fn check_pairs(
        &mut self,
        m: &Move,
        item: &Timed,
        samples: u64,
        cands: &[(Part, Obstacle)],
        active: u32,
        rule: Option<Kind>,
    ) {
        match self.settings.mode {
            // A move with more samples than the cap (a tiny dt, a crawl of F0.00001, a move of
            // 1e11 mm) is checked as exact mode checks it: never less than sampling would find,
            // with work bounded by its path instead of its time.
            Mode::Step if samples > MAX_STEP_SAMPLES => {
                self.long_moves = true;
                self.exact(m, item, cands, active, rule)
            }
            Mode::Step => self.sample(m, item, cands, active, rule),
            Mode::Exact => self.exact(m, item, cands, active, rule),
        }
    }

    /// Fixed-timestep sampling of the candidate pairs over one move.
    ///
    /// The samples are every multiple of dt (and the move's end); between two samples the sampler
    /// proves the pair clear or hands it to exact mode's measure, so that step mode misses no
    /// contact exact mode finds (ARCHITECTURE.md, "What step mode guarantees"). Per pair:
    ///
    /// 1. Bounds. Let the pair be proven clear by `ga` at time `ta` (reference point `ra`) and by
    ///    `gb` at `tb` (`rb`), and let `L` bound how far the reference point travels from `ta` to
    ///    `tb` — exactly the chord on a line, the two legs on a dogleg, `vmax·(tb − ta)` on an
    ///    arc. A part translates with the reference point (another station's section moves no
    ///    more than it does), so its distance to a fixed obstacle changes no faster than the
    ///    reference point moves: at any `t` in between it is at least `ga − L(ta, t)` and at
    ///    least `gb − L(t, tb)`, whose sum is `ga + gb − L`. If `ga + gb ≥ L`, the larger of the
    ///    two is never negative: the part at most touches. Against a polygon obstacle `L` may
    ///    exceed the sum by [`SLACK`]: the part is then never more than `TOUCH_EPS` in, and an
    ///    overlap's depth never exceeds the translation that clears it. The stock of a cutting
    ///    move is not fixed: it only loses material as the move goes on, so a bound at `ta`
    ///    against the stock then holds for every later instant (the stock then is a subset), but
    ///    a bound at `tb` says nothing about material the insert removes before `tb`: for those
    ///    pairs `gb` counts 0, and a test at the move's start gives the first stretch its `ga`.
    ///    Each test is made at the last sample the previous bound still covers, so a part that
    ///    heads straight at an obstacle is proven by the bound alone.
    /// 2. Hulls. A stretch the bounds leave open is tested as one ([`Self::stretch_clear`]): the
    ///    convex hull of the part's poses at the corners of the path holds every pose between,
    ///    so a hull that overlaps nothing proves it (a part touching what it slides along: an
    ///    insert leaving the groove or the shoulder it cut). A sliding part is then proven twice
    ///    as far ahead after each success, and the samples there are skipped: they are clear.
    /// 3. Exact measure. A stretch neither proves goes to exact mode's measure of the pair over
    ///    the whole move ([`Self::follow_exact`]), once: whatever contacts exact mode finds for
    ///    the pair in this move, step mode reports with the same facts; if it finds none, there
    ///    is nothing left for step mode to miss in this move.
    ///
    /// Samples skipped because their pair is proven clear are exactly the proven stretches (and
    /// never inside the clearance band of a near miss), so skips change nothing.
    fn sample(&mut self, m: &Move, item: &Timed, cands: &[(Part, Obstacle)], active: u32, insert_rule: Option<Kind>) {
        if cands.is_empty() {
            return;
        }
        let dt = self.settings.dt_ms / 1000.0;
        let mut k = (item.t0 / dt - 1e-9).ceil().max(0.0) as u64;
        let t1 = item.t1();
        let clearance = self.settings.clearance_mm;
        let mut posed: Vec<(Part, Option<(Section, bool)>)> = Vec::new();
        // How far the reference point can travel between two instants of the move: exactly, along
        // a line or a dogleg's legs; at most vmax·Δt on an arc.
        let vmax = motion::max_speed(m, item);
        let travel = |ta: f64, ra: P2, tb: f64, rb: P2| -> f64 {
            match motion::polyline_between(m, item, ta - item.t0, tb - item.t0) {
                Some(bend) => {
                    let len = bend.map_or((rb - ra).norm(), |c| (c - ra).norm() + (rb - c).norm());
                    len * (1.0 + 1e-12) + 1e-12
                }
                None if vmax.is_finite() => vmax * (tb - ta).max(0.0),
                None => f64::INFINITY,
            }
        };
        // Per pair: its bound holds only forward in time (the stock while a cutting move changes
        // it; not for the insert's own spindle-stopped test, which sees the stock before the move).
        let forward_only: Vec<bool> = cands
            .iter()
            .map(|&(_, o)| o == Obstacle::Stock && self.cutting.is_some() && !self.pre_move)
            .collect();
        // Per pair: its last clear test (time, reference point, proven gap). The move's start
        // with a gap of 0 proves nothing: the first stretch is proven by the first test's bound
        // alone (looking back), or by a test at the start for the forward-only pairs.
        let r_start = motion::reference_at(m, item, 0.0);
        let mut proven: Vec<(f64, P2, f64)> = vec![(item.t0, r_start, 0.0); cands.len()];
        let mut start_pass = forward_only.iter().any(|&f| f);
        // Per pair: the first sample that can need a test. With a bound on the speed it is known
        // from the proven gap; when every pair is provably clear, jump straight to the earliest.
        // `u64::MAX`: nothing to sample (its contacts in this move were measured exactly, see
        // `follow_exact`, or the whole move is proven clear).
        let mut resume: Vec<u64> = vec![0; cands.len()];
        // Per pair: whether its contacts were handed to `follow_exact`.
        let mut tried: Vec<bool> = vec![false; cands.len()];
        // Per pair: how many samples ahead the next hull of a sliding part reaches.
        let mut ahead: Vec<u64> = vec![2; cands.len()];
        let k_end = (t1 / dt - 1e-9).ceil().max(0.0) as u64;
        let r_end = motion::reference_at(m, item, t1 - item.t0);
        let whole = (r_start, r_end, travel(item.t0, r_start, t1, r_end));
        self.prove_whole_move(m, item, cands, (active, insert_rule), whole, &mut resume);
        self.measure_likely_contacts(m, item, cands, (active, insert_rule), &mut resume, &mut tried);
        let mut last = false;
        while !last {
            let at_start = start_pass;
            let t = if at_start {
                item.t0
            } else {
                let next = resume.iter().copied().min().unwrap_or(0);
                if next > k && k < k_end {
                    let jump = next.min(k_end);
                    self.stats.pair_tests_skipped += (jump - k) * cands.len() as u64;
                    k = jump;
                }
                let mut t = k as f64 * dt;
                // Sample `k_end` is the move's end, whatever the rounding of `k_end·dt` against
                // `t1` (a jump must never take `k` back, or the loop would never end).
                if k >= k_end || t >= t1 - 1e-12 {
                    t = t1;
                    last = true;
                }
                t
            };
            // The first sample after this one.
            let next_k = if at_start { k } else { k + 1 };

            let r = motion::reference_at(m, item, t - item.t0);
            let instant = motion::fraction_at(item, t - item.t0);
            self.instant = instant;
            posed.clear();
            for (ci, &(p, o)) in cands.iter().enumerate() {
                // Measured exactly, or proven clear for the whole move: nothing to sample.
                if resume[ci] == u64::MAX || (at_start && !forward_only[ci]) {
                    continue;
                }
                if !at_start {
                    if k < resume[ci] {
                        self.stats.pair_tests_skipped += 1;
                        continue;
                    }
                    // Along a line or a dogleg the way travelled is known exactly (tighter than
                    // vmax·Δt): a sample still within the proven gap (less the clearance band)
                    // needs no test when the next sample is within it too.
                    let (ta, ra, ga) = proven[ci];
                    let d = travel(ta, ra, t, r);
                    if d < ga - clearance && (last || d + vmax * dt < ga) {
                        self.stats.pair_tests_skipped += 1;
                        continue;
                    }
                }
                let idx = match posed.iter().position(|(q, _)| *q == p) {
                    Some(i) => i,
                    None => {
                        if matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_)) {
                            self.others_tested = true;
                        }
                        posed.push((p, self.pose(p, r, active as f64)));
                        posed.len() - 1
                    }
                };
                let Some((poly, in_plane)) = posed[idx].1.clone() else {
                    continue;
                };
                let Some(kind) = rule(p, o, insert_rule) else { continue };
                let hit_key = key(p, active, o, kind);
                let near_key = key(p, active, o, Kind::NearMiss);
                let quick = k % FULL_DEPTH_EVERY != 0 && self.episodes.is_open(hit_key);
                let (depth, gap) = self.test_with(&poly, in_plane, o, quick);
                // Clear: the proven gap now (a lower bound; the distance itself in the clearance
                // band of a polygon obstacle).
                let g = match (depth, gap) {
                    (Some(_), _) => None,
                    (None, Some(g)) => Some(g),
                    (None, None) => Some(self.gap_lower_bound(&poly, in_plane, o)),
                };
                // The stretch since the last clear test was proven by the hull of the part's
                // poses (see `stretch_clear`): the part slides along what it touches.
                let mut slides = false;
                if let Some(g) = g {
                    // Can a contact hide between the last clear test and this one? (The test at
                    // the move's start has no stretch before it.)
                    let (ta, ra, ga) = proven[ci];
                    let back = if forward_only[ci] { 0.0 } else { g };
                    let way = travel(ta, ra, t, r);
                    let slack = if o == Obstacle::Stock { 0.0 } else { SLACK };
                    if !tried[ci] && !at_start && ga + back < way - slack {
                        slides = self.stretch_clear(p, o, active, (ta, ra), (t, r), way, item);
                        self.instant = instant;
                        if !slides {
                            tried[ci] = true;
                            self.stats.refined += 1;
                            let found = self.follow_exact(m, item, p, o, active, insert_rule);
                            self.instant = instant;
                            if found {
                                resume[ci] = u64::MAX;
                                continue;
                            }
                        }
                    }
                    proven[ci] = (t, r, g);
                }
                match (depth, gap) {
                    (Some(d), _) => {
                        self.episodes.clear(near_key);
                        // Found by sampling; measured exactly (start, end, depth), so that the
                        // facts of a contact do not depend on dt and a long contact costs what
                        // it costs in exact mode.
                        if !tried[ci] && {
                            tried[ci] = true;
                            let found = self.follow_exact(m, item, p, o, active, insert_rule);
                            self.instant = instant;
                            found
                        } {
                            resume[ci] = u64::MAX;
                            continue;
                        }
                        // A quick test's depth is one column's, not the part's: it only says
                        // the contact goes on.
                        let d = if quick { 0.0 } else { d };
                        if self.episodes.extend(hit_key, m.line, t, d, false) {
                            continue;
                        }
                        let mut c = self.contact(m, r, p, o, kind, Some(d), t, active);
                        if self.settings.snapshots && !self.episodes.is_open(hit_key) {
                            c.snapshot = Some(Box::new(self.snapshot(m, item, r, active, &poly, Some(o), in_plane)));
                        }
                        self.episodes.contact(hit_key, c);
                    }
                    (None, Some(g)) => {
                        self.episodes.clear(hit_key);
                        resume[ci] = next_k;
                        if self.episodes.extend(near_key, m.line, t, g, true) {
                            continue;
                        }
                        let mut c = self.contact(m, r, p, o, Kind::NearMiss, Some(g), t, active);

                        if self.settings.snapshots && !self.episodes.is_open(near_key) {
                            c.snapshot = Some(Box::new(self.snapshot(m, item, r, active, &poly, Some(o), in_plane)));
                        }
                        self.episodes.contact(near_key, c);
                    }
                    (None, None) => {
                        self.episodes.clear(hit_key);
                        self.episodes.clear(near_key);
                        let g = proven[ci].2;
                        // The first sample the part can reach `d` from here: samples before it
                        // travel less (vmax·(j·dt − t) < d).
                        let first_at = |d: f64| -> u64 {
                            let x = ((t + d / vmax) / dt).ceil();
                            if x.is_finite() {
                                x.clamp(0.0, 1e15) as u64
                            } else {
                                u64::MAX / 4
                            }
                        };
                        let s = g - clearance;
                        resume[ci] = if s > 0.0 && !last {
                            // Outside the clearance band until the part can have travelled s;
                            // tested again at the last sample the bound still covers (the next
                            // test's own bound then proves the stretch after it).
                            first_at(s).min(first_at(g).saturating_sub(1)).max(next_k)
                        } else {
                            next_k
                        };
                        // A part sliding along what it touches: prove the way ahead by hulls,
                        // twice as far after each success (a sample inside a proven stretch is
                        // clear, and the stock has no near misses to sample).
                        if slides && !last && (o == Obstacle::Stock || clearance <= 0.0) {
                            let j = k.saturating_add(ahead[ci]).min(k_end);
                            if j >= resume[ci] {
                                let tj = if j == k_end { t1 } else { j as f64 * dt };
                                let rj = motion::reference_at(m, item, tj - item.t0);
                                let way = travel(t, r, tj, rj);
                                if self.stretch_clear(p, o, active, (t, r), (tj, rj), way, item) {
                                    proven[ci] = (tj, rj, 0.0);
                                    resume[ci] = j + 1;
                                    ahead[ci] = ahead[ci].saturating_mul(2).min(1 << 40);
                                } else {
                                    ahead[ci] = (ahead[ci] / 4).max(1);
                                }
                                self.instant = instant;
                            }
                        }
                    }
                }
            }
            if at_start {
                start_pass = false;
            } else {
                k += 1;
            }
        }
    }

    /// Before sampling a straight move (or a dogleg): each pair against the stock whose part's
    /// hull over the whole move overlaps nothing ([`Self::stretch_clear`], the stock at the
    /// move's start) is clear at every sample, so it is closed as every clear sample would close
    /// it (its contact and near-miss episodes end) and left out of the sampling (`resume` past
    /// the last sample). The findings are the sampler's: only the pair tests differ.
    /// `(r0, r1, way)`: the reference point at the move's start and end and the way between
    /// (the sampler's `travel`).
    fn prove_whole_move(
        &mut self,
        m: &Move,
        item: &Timed,
        cands: &[(Part, Obstacle)],
        (active, insert_rule): (u32, Option<Kind>),
        (r0, r1, way): (P2, P2, f64),
        resume: &mut [u64],
    ) {
        let (t0, t1) = (item.t0, item.t1());
        // On an arc the hull would be a square around the whole move.
        if !self.settings.prove_stretches || motion::polyline_between(m, item, 0.0, t1 - t0).is_none() {
            return;
        }
        for (ci, &(p, o)) in cands.iter().enumerate() {
            let Some(kind) = rule(p, o, insert_rule) else { continue };
            if o != Obstacle::Stock || matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_)) {
                continue;
            }
            // In contact at the previous move's end, so at this one's start (the same pose,
            // the same stock): its hull, which holds that pose, cannot be clear.
            if self.episodes.is_open(key(p, active, o, kind)) {
                continue;
            }
            if self.stretch_clear(p, o, active, (t0, r0), (t1, r1), way, item) {
                self.episodes.clear(key(p, active, o, kind));
                self.episodes.clear(key(p, active, o, Kind::NearMiss));
                resume[ci] = u64::MAX;
            }
        }
    }

    /// Step mode: the stock pairs likely in contact during this move are measured exactly at
    /// once ([`Self::follow_exact`]), instead of after an approach by samples that the measure
    /// then repeats. Likely: in contact at the move's start (its episode is open: the previous
    /// move ended in contact, and this one starts at the same pose against the same stock), or
    /// found in contact by the previous move's measure (a holder buried in the bar across a
    /// roughing cycle enters and leaves it on every pass).
    ///
    /// What the measure finds does not depend on when it is taken: it looks at the whole move,
    /// at the stock as it is at each instant, and settles the pair's episode itself (extended
    /// from a contact at the move's start, else closed). Before the contact a stock pair's
    /// samples only close that episode (a stock pair has no near miss). So this saves the
    /// approach's tests and changes no finding; a pair the measure finds clear goes on being
    /// sampled, as one whose measure found nothing does after a contact sample.
    fn measure_likely_contacts(
        &mut self,
        m: &Move,
        item: &Timed,
        cands: &[(Part, Obstacle)],
        (active, insert_rule): (u32, Option<Kind>),
        resume: &mut [u64],
        tried: &mut [bool],
    ) {
        for (ci, &(p, o)) in cands.iter().enumerate() {
            if o != Obstacle::Stock || resume[ci] == u64::MAX {
                continue;
            }
            let Some(kind) = rule(p, o, insert_rule) else { continue };
            let k = key(p, active, o, kind);
            let before = item.index.checked_sub(1);
            let likely =
                self.episodes.is_open(k) || self.contact_moves.iter().any(|&(kk, at)| kk == k && Some(at) == before);
            if !likely {
                continue;
            }
            tried[ci] = true;
            let instant = self.instant;
            if self.follow_exact(m, item, p, o, active, insert_rule) {
                resume[ci] = u64::MAX;
            }
            self.instant = instant;
        }
    }

    /// The exact measure of pair `key` found it in contact during move `index`.
    fn contact_in_move(&mut self, key: u64, index: usize) {
        match self.contact_moves.iter_mut().find(|(k, _)| *k == key) {
            Some(e) => e.1 = index,
            None => self.contact_moves.push((key, index)),
        }
    }

    /// Whether pair `(p, o)` is clear over a whole stretch of a move, the reference point going
    /// from `ra` (at time `ta`) to `rb` (at `tb`) and travelling at most `way`: the part is tested
    /// once, as the convex hull of its poses at the corners of a convex region holding the
    /// reference point's path — the ends (and a dogleg's bend between them) on a line or a
    /// dogleg; on an arc the square of half-width `way`/2 around the ends' midpoint (a point
    /// whose distances to the two ends sum to at most `way` is within `way`/2 of it). Every pose
    /// in between lies inside that hull, so a hull that overlaps nothing proves the stretch:
    /// against the stock, no column's radial overlap exceeds `TOUCH_EPS`/2 (a part inside the
    /// hull overlaps each column no more than the hull does), seen at `ta` (the stock then holds
    /// all the material of later instants); against the chuck or the tailstock, the hull's
    /// interior meets neither half of the outline. A part touching what it slides along (an
    /// insert leaving the shoulder it has just cut) is proven clear by one query instead of
    /// being followed by conservative advancement. Another station's section changes shape as it
    /// moves, so its stretches are never proven this way.
    #[allow(clippy::too_many_arguments)]
    fn stretch_clear(
        &mut self,
        p: Part,
        o: Obstacle,
        active: u32,
        (ta, ra): (f64, P2),
        (tb, rb): (f64, P2),
        way: f64,
        item: &Timed,
    ) -> bool {
        if matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_)) {
            return false;
        }
        let Some((Section::Whole(poly), in_plane)) = self.pose(p, ra, active as f64) else {
            return false;
        };
        let m = &self.now.m;
        let corners: Vec<V2> = match motion::polyline_between(m, item, ta - item.t0, tb - item.t0) {
            Some(None) => vec![V2::zeros(), rb - ra],
            Some(Some(c)) => vec![V2::zeros(), c - ra, rb - ra],
            None if way.is_finite() => {
                let (mid, h) = (0.5 * (rb - ra), 0.5 * way);
                vec![
                    mid + V2::new(-h, -h),
                    mid + V2::new(h, -h),
                    mid + V2::new(h, h),
                    mid + V2::new(-h, h),
                ]
            }
            None => return false,
        };
        let Ok(hull) = Polygon::new(&crate::tooling::outline::hull_of_translates(
            poly.points(),
            false,
            &corners,
        )) else {
            return false;
        };
        self.stats.pair_tests += 1;
        match o {
            Obstacle::Stock => {
                self.instant = motion::fraction_at(item, ta - item.t0);
                self.stock_overlap(hull.points(), 0.5 * geom::TOUCH_EPS, true).is_none()
            }
            _ => self.obstacle(o).is_some_and(|rev| {
                let meets = |b: &Polygon| geom::interiors_overlap(&hull, b);
                !meets(&rev.outline) && (!in_plane || !meets(&rev.mirror))
            }),
        }
    }

    /// A part's overlap with the stock as the current query sees it: at `self.instant` of the
    /// cutting move under way, or before it for the insert's own spindle-stopped test (see
    /// [`DexelStock::overlap_view`]); none when there is no stock.
    fn stock_overlap(&mut self, pts: &[P2], eps: f64, first_only: bool) -> Option<StockHit> {
        self.ensure_stock();
        self.refresh_swept();
        let (Some(stock), cutting) = (self.stock.as_mut(), self.cutting.as_ref()) else {
            return None;
        };
        let view = cutting.map_or(View::Now, |c| c.view(self.pre_move));
        stock.overlap_view(pts, eps, first_only, view)
    }

    /// A proven lower bound of the distance between a posed part and an obstacle it is clear of.
    /// Against the stock, the bound is to the stock as the current query sees it (at the instant
    /// of the cutting move under way, or before it for the insert's own spindle-stopped test):
    /// it holds for every later instant of the move too, since the stock only loses material
    /// (ARCHITECTURE.md, "The stock at the instant").
    fn gap_lower_bound(&mut self, part: &Section, in_plane: bool, o: Obstacle) -> f64 {
        // The least of the pieces' bounds; a NaN (no bound) stays one, as a whole part's does.
        let mut least = f64::INFINITY;
        for poly in part.pieces() {
            let g = self.gap_lower_bound_one(poly, in_plane, o);
            if g.is_nan() || g < least {
                least = g;
            }
            if least.is_nan() {
                break;
            }
        }
        least
    }

    fn gap_lower_bound_one(&mut self, poly: &Polygon, in_plane: bool, o: Obstacle) -> f64 {
        match o {
            Obstacle::Stock => {
                self.refresh_swept();
                let (Some(stock), cutting) = (self.stock.as_mut(), self.cutting.as_ref()) else {
                    return f64::INFINITY;
                };
                let view = cutting.map_or(View::Now, |c| c.view(self.pre_move));
                stock.gap_bound_view(poly.points(), 10.0, view)
            }
            _ => self.obstacle(o).map_or(f64::INFINITY, |rev| {
                let g = geom::distance(poly, &rev.outline);
                if in_plane {
                    g.min(geom::distance(poly, &rev.mirror))
                } else {
                    g
                }
            }),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn contact(
        &self,
        m: &Move,
        r: P2,
        p: Part,
        o: Obstacle,
        kind: Kind,
        depth: Option<f64>,
        t: f64,
        active: u32,
    ) -> Contact {
        let a = self.name(p, active);
        let b = obstacle_name(o);
        let message = match kind {
            Kind::RapidIntoStock => format!("rapid move drives the {a} into the stock"),
            Kind::SpindleStopped => format!("the {a} cuts the stock with the spindle stopped"),
            Kind::NearMiss => format!("the {a} passes within {:.3} mm of the {b}", self.settings.clearance_mm),
            _ => {
                let other = if matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_)) {
                    " (a tool in another station)"
                } else {
                    ""
                };
                format!("the {a}{other} hits the {b}")
            }
        };
        let (x, z) = self.frame().to_program(r + m.tip);
        let snapshot = None;
        Contact {
            kind,

            objects: [a, b.to_string()],
            words: None,
            line: m.line,
            n: m.n,
            profile_line: m.profile_line,
            time: t,
            x,
            z,
            depth,
            message,
            snapshot,
            snapshot3: None,
        }
    }

    /// The scene when the reference point is at `r` (for pictures of findings).
    /// The piece of a posed part a picture shows as the part in contact: the whole part, or of a
    /// folded one (`Section::Folded`) the piece deepest in what it meets (`meets`: the obstacle's
    /// outlines as the picture draws them, the stock at that instant included), else the nearest.
    fn shown_piece<'a>(part: &'a Section, meets: &[Vec<P2>]) -> &'a Polygon {
        let pieces = part.pieces();
        if pieces.len() == 1 {
            return &pieces[0];
        }
        let outlines: Vec<Polygon> = meets.iter().filter_map(|o| Polygon::new(o).ok()).collect();
        let key = |p: &Polygon| {
            outlines
                .iter()
                .map(|o| geom::overlap(p, o).unwrap_or_else(|| -geom::distance(p, o)))
                .fold(f64::NEG_INFINITY, f64::max)
        };
        pieces
            .iter()
            .map(|p| (key(p), p))
            .fold(None, |best: Option<(f64, &Polygon)>, (k, p)| match best {
                Some((bk, _)) if bk >= k => best,
                _ => Some((k, p)),
            })
            .map_or(&pieces[0], |(_, p)| p)
    }

    #[allow(clippy::too_many_arguments)]
    fn snapshot(
        &self,
        m: &Move,
        item: &Timed,
        r: P2,
        active: u32,
        part: &Section,
        obstacle: Option<Obstacle>,
        in_plane: bool,
    ) -> Snapshot {
        let pts = |p: &Polygon| p.points().to_vec();
        // The stock as it is at this instant of a cutting move.
        let instant = self
            .stock
            .as_ref()
            .zip(self.cutting.as_ref())
            .map(|(s, c)| s.view_copy(c.view(self.pre_move)));
        let stock: Vec<Vec<P2>> = instant
            .as_ref()
            .or(self.stock.as_ref())
            .map(|s| {
                s.outlines(self.settings.tolerance_mm)
                    .into_iter()
                    .map(|o| o.into_iter().map(|[x, z]| P2::new(x, z)).collect())
                    .collect()
            })
            .unwrap_or_else(|| {
                self.machine
                    .stock
                    .as_ref()
                    .map(|s| vec![s.section().into_iter().map(|[x, z]| P2::new(x, z)).collect()])
                    .unwrap_or_default()
            });
        let tool = self.scene.tool(active);
        let posed = |shape: &Polygon, tip: V2| shape.translated(r.coords + tip).points().to_vec();
        let mut others = Vec::new();
        for t in &self.scene.tools {
            if t.station == active {
                continue;
            }
            let angle = self.scene.station_angle(t.station, active as f64);
            for (what, shape) in [("holder", &t.holder), ("insert", &t.insert)] {
                if let Some(sec) = self.scene.map_to_section(shape, t.tip, r, angle) {
                    for p in sec.pieces() {
                        others.push((format!("{} {what}", t.label), pts(p)));
                    }
                }
            }
        }
        let mut path = Vec::new();
        if let Some(prev) = &self.behind.prev {
            path.extend((0..=24).map(|k| prev.point_at(k as f64 / 24.0)));
        }
        path.extend((0..=48).map(|k| m.point_at(k as f64 / 48.0)));
        let part_b = match obstacle {
            Some(Obstacle::Stock) => stock.clone(),
            Some(o) => self.obstacle(o).map(|rv| vec![pts(&rv.outline)]).unwrap_or_default(),
            None => Vec::new(),
        };
        // A dogleg rapid bends where its first axis arrives: draw it as the machine moves.
        let machine_path = motion::machine_path(m, item);
        Snapshot {
            chuck: self.scene.chuck.as_ref().map(|c| pts(&c.outline)),
            tailstock: self.obstacle(Obstacle::Tailstock).map(|c| pts(&c.outline)), // drawn while advanced
            stock,
            turret: posed(&self.scene.turret, V2::zeros()),
            insert: tool.map(|t| posed(&t.insert, t.tip)).unwrap_or_default(),
            holder: tool.map(|t| posed(&t.holder, t.tip)).unwrap_or_default(),
            others,
            path,
            machine_path,
            frame: Some(*self.frame()),
            travel: None,
            at: r + m.tip,
            part_a: pts(Self::shown_piece(part, &part_b)),
            part_b,
            mirrored: in_plane,
        }
    }

    /// Remove what the insert sweeps in a feed move (its chords are in `self.cutting`).
    fn cut(&mut self) {
        let Some(c) = self.cutting.take() else { return };
        let mut swept = std::mem::take(&mut self.cut_buf);
        self.swept_until(&c, 1.0, &mut swept);
        self.cutting = Some(c);
        let Some(stock) = self.ensure_stock() else {
            self.cut_buf = swept;
            return;
        };
        let mut any = false;
        for p in swept.to_cut() {
            any |= stock.cut(p);
        }
        self.cut_any |= any;
        if self.record_cuts {
            let index = self.cutting.as_ref().map_or(0, |c| c.index);
            self.cuts
                .push((index, Removed::Turned(swept.to_cut().map(<[_]>::to_vec).collect())));
        }
        self.cut_buf = swept;
    }

    /// Take off the stock what another path cut (`Stream::share_cuts`), between two moves: what
    /// it turned off the dexel stock, what it milled off the milled stock (built from the dexel
    /// stock first if this path has not milled yet; a path checked in the working plane only has
    /// none, and the pipeline checks a path that shares milled cuts on its 3D path).
    fn cut_foreign(&mut self, removed: &Removed) {
        let polygons = match removed {
            Removed::Turned(p) => p,
            Removed::Milled(sweeps) => {
                self.mill_foreign(sweeps);
                return;
            }
        };
        let Some(stock) = self.ensure_stock() else {
            return;
        };
        stock.end_move();
        let mut any = false;
        for p in polygons {
            any |= stock.cut(p);
        }
        self.cut_any |= any;
    }

    /// The programmed path of a feed move as chords within the tolerance (arcs; a line is one
    /// chord), and which chords the insert's sweep along them can bring near the raw stock.
    fn chords(&self, m: &Move, c: &mut Cutting) {
        c.path.clear();
        c.kept.clear();
        let tol = self.settings.tolerance_mm;
        c.path.push((0.0, m.start));
        if let MoveKind::Arc { center, sweep } = m.kind {
            let (r0, r1) = ((m.start - center).norm(), (m.end - center).norm());
            let r = r0.max(r1).max(tol);
            let step = 2.0 * (1.0 - (tol / r).min(1.0)).acos().max(1e-4);
            // A circle of more than one turn (LinuxCNC's `P` turns) sweeps in its first turn all
            // the region it ever sweeps: its later turns pass the same points again. Its chords
            // stop there (at that fraction of the move: from then on the region swept so far is
            // the whole of it). A spiral's later turns are at other radii: all of them.
            let turns = sweep.abs() / std::f64::consts::TAU;
            let circle = (r0 - r1).abs() <= 1e-9 * r;
            let u_end = if turns > 1.0 && circle { 1.0 / turns } else { 1.0 };
            let n = ((sweep.abs() * u_end / step).ceil() as usize).clamp(1, 100_000);
            for j in 1..n {
                let u = u_end * j as f64 / n as f64;
                c.path.push((u, m.point_at(u)));
            }
            c.path.push((u_end, m.point_at(u_end)));
        } else {
            c.path.push((1.0, m.end));
        }
        let (Some(tool), Some(sb)) = (self.scene.tool(m.station), self.stock_box) else {
            return;
        };
        let ib = tool.insert.aabb();
        for j in 0..c.path.len() - 1 {
            let (a, b) = (c.path[j].1, c.path[j + 1].1);
            let lo = P2::new(a.x.min(b.x) + ib.min.x, a.y.min(b.y) + ib.min.y);
            let hi = P2::new(a.x.max(b.x) + ib.max.x, a.y.max(b.y) + ib.max.y);
            if (Aabb { min: lo, max: hi }).meets(&sb, 1e-6) {
                c.kept.push(j);
            }
        }
    }

    /// The region the insert sweeps from the start of a feed move to path fraction `f`: the
    /// insert at the start, each edge swept along every chord of the path, and the insert at
    /// each chord's end (the point at f on the chord holding f). Chords whose sweep cannot reach
    /// the raw stock are left out: they remove nothing. With `f` = 1 this is exactly what
    /// [`Self::cut`] removes, so the stock "at the end of the move" is the stock after it.
    fn swept_until(&self, c: &Cutting, f: f64, out: &mut Swept) {
        out.clear();
        let Some(tool) = self.scene.tool(c.station) else {
            return;
        };
        let insert = tool.insert.points();
        let f = if f.is_nan() { 1.0 } else { f.clamp(0.0, 1.0) };
        let posed = |p: P2| insert.iter().map(move |q| p + q.coords);
        out.push(posed(c.path[0].1));
        for &j in &c.kept {
            let (u0, a) = c.path[j];
            let (u1, b) = c.path[j + 1];
            if u0 >= f {
                break;
            }
            // Partway along a chord, the point on the chord (for a line, the point on the move):
            // then the swept region only grows with f, exactly, which the gap bounds rely on
            // (ARCHITECTURE.md, "The stock at the instant"). On an arc it is within the
            // tolerance of the insert's pose, as the chords of the whole cut are.
            let end = if u1 <= f {
                b
            } else {
                a + (b - a) * ((f - u0) / (u1 - u0))
            };
            let d: V2 = end - a;
            // A convex insert sweeps one convex polygon along the chord: its two poses joined
            // at the points that lead and trail across the chord. Otherwise (or should the
            // edges' sides not split in two runs), each edge's quad and the end pose.
            if tool.insert_convex && out.push_with(|poly| sweep_convex(insert, a, d, poly)) {
                // The first chord's sweep holds the pose it starts from, pushed first.
                if j == 0 {
                    out.cover_first();
                }
                continue;
            }
            let n = insert.len();
            for i in 0..n {
                let (p, q) = (a + insert[i].coords, a + insert[(i + 1) % n].coords);
                out.push([p, q, q + d, p + d]);
            }
            out.push(posed(end));
        }
    }

    /// Every tool's sweep while the turret indexes, at the T word's line.
    fn index_sweep(&mut self, m: &Move, item: &Timed, from: u32, to: u32) {
        self.indexed = true;
        let n = self.scene.stations;
        let dir = motion::index_direction(from, to, n);
        // A gang slide turns nothing: its tools stand where they stood.
        if dir == 0 || self.scene.gang {
            return;
        }
        let r = m.ref_start();
        let tools: Vec<_> = self.scene.tools.iter().map(|t| (t.station, t.tip)).collect();
        let tol = self.settings.tolerance_mm;
        for (station, tip) in tools {
            let t = self.scene.tool(station).unwrap();
            let shapes = [
                (Part::OtherHolder(station), t.holder.clone(), t.holder_extent),
                (Part::OtherInsert(station), t.insert.clone(), t.insert_extent),
            ];
            for (part, shape, extent) in shapes {
                // Farthest point from the turret axis sets the angular step.
                let rho = shape
                    .points()
                    .iter()
                    .map(|q| ((q.x + tip.x - self.scene.turret_axis).powi(2)).sqrt())
                    .fold(0.0f64, f64::max)
                    .max(1.0);
                let c = r.x + self.scene.turret_axis;
                let zb = shape.aabb().translate(tip + r.coords);
                let env = Aabb {
                    min: P2::new((c - rho).abs().min(0.0f64.max(c - rho)), zb.min.y),
                    max: P2::new(c + rho, zb.max.y),
                };
                let near: Vec<Obstacle> = OBSTACLES
                    .into_iter()
                    .filter(|&o| self.obstacle_box(o).is_some_and(|b| env.meets(&b, 1e-6)))
                    .collect();
                if near.is_empty() {
                    continue;
                }
                let span = (dir.unsigned_abs() as f64) * std::f64::consts::TAU / n as f64;
                let step = (8.0 * tol / rho).sqrt().max(1e-4);
                let k = ((span / step).ceil() as usize).clamp(2, 100_000);
                for j in 0..=k {
                    let u = j as f64 / k as f64;
                    let active = from as f64 + dir as f64 * u;
                    let angle = self.scene.station_angle(station, active);
                    // The section's box first (no polygon built): an obstacle whose box it does
                    // not meet cannot overlap the section, so that pair is clear at this angle
                    // without a test, and a sample clear of every near obstacle maps nothing.
                    let bx = self.scene.section_box(&extent, &Aabb { min: r, max: r }, angle);
                    let mut meets = [false; OBSTACLES.len()];
                    for (i, &o) in near.iter().enumerate() {
                        meets[i] = self.obstacle_box(o).is_some_and(|b| bx.meets(&b, 1e-6));
                    }
                    let mut poly = None;
                    if meets.iter().any(|&m| m) {
                        poly = self.scene.map_to_section(&shape, tip, r, angle);
                        if poly.is_none() {
                            continue;
                        }
                    }
                    self.others_tested = true;
                    for (i, &o) in near.iter().enumerate() {
                        let kk = key(part, from, o, Kind::Collision);
                        let depth = match &poly {
                            Some(poly) if meets[i] => self.test(poly, false, o).0,
                            _ => None,
                        };
                        match depth {
                            Some(d) => {
                                let time = item.t0 + item.duration * u;
                                let mut c = self.contact(m, r, part, o, Kind::Collision, Some(d), time, from);
                                c.message = format!(
                                    "indexing T{from:02} → T{to:02} swings the {} into the {}",
                                    c.objects[0], c.objects[1]
                                );
                                if let (true, false, Some(poly)) =
                                    (self.settings.snapshots, self.episodes.is_open(kk), &poly)
                                {
                                    let s = self.snapshot(m, item, r, from, poly, Some(o), false);
                                    c.snapshot = Some(Box::new(s));
                                }
                                self.episodes.contact(kk, c);
                            }
                            None => self.episodes.clear(kk),
                        }
                    }
                }
            }
        }
    }

    /// The turret reference point against the axis limits, on the exact path. Each move that
    /// takes it past a limit farther than it already was at the move's start is an over-travel
    /// of its own (a finding per move, never an episode across moves: a suppression of one line's
    /// over-travel must not hide the next line's); a move that starts out of travel and comes
    /// back, or stays as far out, commands nothing new and is not one.
    fn overtravel(&mut self, m: &Move, item: &Timed) {
        let ax = (self.machine.x, self.machine.z);
        // How far the point is past each limit: X min, X max, Z min, Z max.
        let past = |p: P2| -> [f64; 4] {
            [ax.0.min - p.x, p.x - ax.0.max, ax.1.min - p.y, p.y - ax.1.max].map(|e| e.max(0.0))
        };
        let rb = motion::reference_box(m, item);
        let corners = [rb.min, rb.max, P2::new(rb.min.x, rb.max.y), P2::new(rb.max.x, rb.min.y)];
        if corners.iter().all(|&p| past(p).iter().all(|&e| e <= 1e-9)) {
            return;
        }
        let at = |u: f64| motion::reference_at(m, item, u * item.duration);
        let base = past(at(0.0));
        // Every point of the move lies in its box: when no corner of the box is further past a
        // limit than the start, no sample below can be (a move that stays past a limit without
        // going further, as a loop marching off the machine makes thousands of, costs nothing).
        let worst = past(rb.min).into_iter().zip(past(rb.max)).map(|(a, b)| a.max(b));
        if worst.zip(base).all(|(w, b)| w - b <= 1e-9) {
            return;
        }
        // How far beyond its start the move goes past a limit, and which limit.
        let beyond = |p: P2| -> (f64, usize) {
            let e = past(p);
            (0..4)
                .map(|i| (e[i] - base[i], i))
                .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
        };
        // Scan, then bisect the first sample past the start's state. A finding certainly left
        // out of the report (past the file's finding cap) only counts: the scan stops at its
        // first sample past the limit, which it is found by alike, and its facts are not sought.
        let n = 256;
        let left_out = !self.settings.snapshots && self.episodes.left_out_at(m.line, item.t0);
        let mut first = None;
        let mut depth: f64 = 0.0;
        for j in 1..=n {
            self.stats.travel_samples += 1;
            let u = j as f64 / n as f64;
            let (e, i) = beyond(at(u));
            if e > 1e-9 {
                depth = depth.max(past(at(u))[i]);
                first.get_or_insert(j);
                if left_out {
                    break;
                }
            }
        }
        let Some(j) = first else { return };
        let (mut lo, mut hi) = ((j - 1) as f64 / n as f64, j as f64 / n as f64);
        for _ in 0..if left_out { 0 } else { 50 } {
            let mid = 0.5 * (lo + hi);
            if beyond(at(mid)).0 > 1e-9 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let r = at(hi);
        let axis = if beyond(at(j as f64 / n as f64)).1 < 2 {
            "X"
        } else {
            "Z"
        };
        let (x, z) = self.frame().to_program(r + m.tip);
        let mut c = Contact {
            kind: Kind::Overtravel,
            objects: ["turret".into(), format!("{axis} travel")],
            words: None,
            line: m.line,
            n: m.n,
            profile_line: m.profile_line,
            time: item.t0 + hi * item.duration,
            x,
            z,
            depth: Some(depth),
            message: format!("the turret reference point leaves the {axis} travel limits"),
            snapshot: None,
            snapshot3: None,
        };
        if self.settings.snapshots {
            let turret = Section::Whole(self.scene.turret.translated(r.coords));
            let mut s = self.snapshot(m, item, r, m.station, &turret, None, true);
            s.travel = Some(travel_facts(axis, &ax, at));
            c.snapshot = Some(Box::new(s));
        }
        self.episodes.contact(OVERTRAVEL_KEY, c);
        self.episodes.clear(OVERTRAVEL_KEY);
    }
}

/// The episode key of an over-travel of X or Z (one finding per move, closed at once).
const OVERTRAVEL_KEY: u64 = u64::MAX;

/// Where the turret reference point (`at(u)` along the move, `u` in 0..=1) is farthest beyond
/// the broken limit of `axis`, sampled finely enough for a picture.
fn travel_facts(axis: &str, ax: &(crate::machine::Axis, crate::machine::Axis), at: impl Fn(f64) -> P2) -> Travel {
    let x_axis = axis == "X";
    let (a, get): (crate::machine::Axis, fn(P2) -> f64) = if x_axis { (ax.0, |p| p.x) } else { (ax.1, |p| p.y) };
    let (mut worst, mut over, mut limit) = (at(0.0), f64::NEG_INFINITY, a.max);
    for p in (0..=256).map(|k| at(k as f64 / 256.0)) {
        let (below, above) = (a.min - get(p), get(p) - a.max);
        if below > over {
            (worst, over, limit) = (p, below, a.min);
        }
        if above > over {
            (worst, over, limit) = (p, above, a.max);
        }
    }
    Travel {
        axis: if x_axis { 'X' } else { 'Z' },
        limit,
        reference_path: (0..=64).map(|k| at(k as f64 / 64.0)).collect(),
        worst,
        overshoot: over.max(0.0),
    }
}

/// The rule a contact of a pair breaks: `collision`, or for the insert in the stock the move's
/// rule (`None` while machining).
fn rule(p: Part, o: Obstacle, insert_rule: Option<Kind>) -> Option<Kind> {
    if p == Part::Insert && o == Obstacle::Stock {
        insert_rule
    } else {
        Some(Kind::Collision)
    }
}

fn pair_keys(p: Part, active: u32, o: Obstacle) -> [u64; 4] {
    [
        Kind::Collision,
        Kind::NearMiss,
        Kind::RapidIntoStock,
        Kind::SpindleStopped,
    ]
    .map(|k| key(p, active, o, k))
}

fn obstacle_name(o: Obstacle) -> &'static str {
    match o {
        Obstacle::Chuck => "chuck",
        Obstacle::Tailstock => "tailstock",
        Obstacle::Stock => "stock",
    }
}

/// Box of a shape box swept over a box of reference points.
fn minkowski(shape: &Aabb, refs: &Aabb) -> Aabb {
    Aabb {
        min: P2::new(shape.min.x + refs.min.x, shape.min.y + refs.min.y),
        max: P2::new(shape.max.x + refs.max.x, shape.max.y + refs.max.y),
    }
}
