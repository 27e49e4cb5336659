//! Exact mode (docs/checking.md): every move checked as a continuous motion.
//!
//! Between turret indexes the parts only translate, so the first contact of a part with a
//! polygon obstacle (chuck, tailstock) along a straight piece or a circular arc is computed
//! exactly by the kernel's sweeps ([`geom::sweep_line_episodes`], [`geom::sweep_arc_episodes`]).
//! A dogleg rapid is two straight pieces. A spiral arc (end radius within rs274ngc's tolerance of
//! the start radius) is swept as the circle through its start.
//!
//! Two kinds of pairs are not rigid polygon pairs: the in-process stock (a dexel field, exact to
//! its own resolution, the tolerance) and tools of other stations (their radial section changes
//! shape as the turret moves in x). Those are checked by conservative advancement: the part moves
//! by the larger of the tolerance and a proven lower bound of its distance to the obstacle, so
//! nothing deeper than the tolerance is stepped over, and the first and last contact of each
//! episode are refined by bisection.

use super::*;
use crate::motion::Path;

/// Farthest look-ahead of the stock's gap bound, mm.
const GAP_WINDOW: f64 = 20.0;
/// Bisection steps refining a sampled contact boundary (2^-40 of a step).
const REFINE: usize = 40;
/// Most steps by a proven gap from the clear end of a contact boundary before its bisection.
const GAP_STEPS: usize = 1;
/// Probes galloping from a touch toward a contact boundary (1 and 4 units of the resolution
/// past it: where a touch is no boundary, a holder sliding along a face, each is one probe lost).
const GALLOP: usize = 2;
/// Golden-section steps seeking the deepest point of a contact interval.
const PEAK_STEPS: usize = 24;
/// The first stretch (in tolerances) conservative advancement tries to prove in contact ahead
/// of a probe in contact; it doubles after each proof and shrinks after a failure.
const CONTACT_AHEAD: f64 = 8.0;
/// Longest stretch of a piece whose motion envelope is tested as one, mm.
const SPAN_MM: f64 = 50.0;
/// Most probes conservative advancement (or the near-miss scan) spends on one pair along one
/// move; past it the rest of the move is reported unchecked (ARCHITECTURE.md, bounded work).
pub(super) const MAX_PROBES: u64 = 1_000_000;

/// The deepest probe of a contact interval under conservative advancement, and the probes
/// before and after it.
#[derive(Clone, Copy, Default)]
struct Peak {
    before: f64,
    at: f64,
    after: Option<f64>,
    depth: f64,
    /// A stretch `(a, b)` of the contact and a bound of every pose's depth along it (from the
    /// last proof of a stretch in contact).
    bound: Option<(f64, f64, f64)>,
}

impl Peak {
    /// A probe at `u` (the one before it at `prev`) found depth `d` (0: clear).
    fn probe(&mut self, prev: f64, u: f64, d: f64) {
        if d > self.depth {
            *self = Peak {
                before: prev,
                at: u,
                after: None,
                depth: d,
                bound: self.bound,
            };
        } else if self.after.is_none() && u > self.at {
            self.after = Some(u);
        }
    }
}

#[derive(Clone, Copy)]
enum Shape {
    Line { from: P2, d: V2 },
    Arc { center: P2, start: P2, sweep: f64 },
}

#[derive(Clone, Copy)]
enum TimeMap<'a> {
    /// Time goes linearly from the first to the second value along the piece.
    Linear(f64, f64),
    /// `table[k]` is the path fraction at time `k/(n) · duration` (CSS feeds).
    Table(&'a [f64], f64),
}

/// A stretch of a move along which the reference point follows one line or arc.
#[derive(Clone, Copy)]
struct Piece<'a> {
    shape: Shape,
    time: TimeMap<'a>,
}

impl Piece<'_> {
    fn at(&self, u: f64) -> P2 {
        match self.shape {
            Shape::Line { from, d } => from + d * u,
            Shape::Arc { center, start, sweep } => {
                let v = start - center;
                let (s, c) = (sweep * u).sin_cos();
                center + V2::new(v.x * c - v.y * s, v.x * s + v.y * c)
            }
        }
    }

    /// A box holding the piece between fractions `a` and `b`.
    fn box_between(&self, a: f64, b: f64) -> Aabb {
        let mut bx = Aabb::of_points(&[self.at(a), self.at(b)]);
        if let Shape::Arc { center, start, sweep } = self.shape {
            let r = (start - center).norm();
            let half = 0.5 * (sweep * (b - a)).abs();
            // The arc leaves its chord by at most its sagitta (the whole radius past a half turn).
            let pad = if half < std::f64::consts::FRAC_PI_2 {
                r * (1.0 - half.cos())
            } else {
                r
            };
            bx = bx.inflate(pad + 1e-9 * r.max(1.0));
        }
        bx
    }

    fn length(&self) -> f64 {
        match self.shape {
            Shape::Line { d, .. } => d.norm(),
            Shape::Arc { center, start, sweep } => (start - center).norm() * sweep.abs(),
        }
    }

    /// Seconds from the start of the move at path fraction `u`.
    fn time(&self, u: f64) -> f64 {
        match self.time {
            TimeMap::Linear(a, b) => a + (b - a) * u,
            TimeMap::Table(table, duration) => {
                let n = table.len() - 1;
                let k = table.partition_point(|&f| f < u).clamp(1, n);
                let (f0, f1) = (table[k - 1], table[k]);
                let frac = if f1 > f0 {
                    ((u - f0) / (f1 - f0)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (k as f64 - 1.0 + frac) / n as f64 * duration
            }
        }
    }
}

fn pieces<'a>(m: &Move, item: &'a Timed) -> Vec<Piece<'a>> {
    let dur = item.duration;
    let time = match &item.path {
        Path::Varying { table } => TimeMap::Table(table, dur),
        _ => TimeMap::Linear(0.0, dur),
    };
    match &item.path {
        Path::Still(_) => Vec::new(),
        Path::Line { from, to } => vec![Piece {
            shape: Shape::Line {
                from: *from,
                d: to - from,
            },
            time,
        }],
        Path::Dogleg { from, to, tx, tz } => {
            let (tx, tz) = (*tx, *tz);
            let d = to - from;
            let t1 = tx.min(tz);
            let t2 = tx.max(tz);
            let mid = P2::new(
                from.x + d.x * if tx > 0.0 { (t1 / tx).min(1.0) } else { 1.0 },
                from.y + d.y * if tz > 0.0 { (t1 / tz).min(1.0) } else { 1.0 },
            );
            let mut v = Vec::new();
            if t1 > 0.0 {
                v.push(Piece {
                    shape: Shape::Line {
                        from: *from,
                        d: mid - from,
                    },
                    time: TimeMap::Linear(0.0, t1),
                });
            }
            if t2 > t1 {
                v.push(Piece {
                    shape: Shape::Line { from: mid, d: to - mid },
                    time: TimeMap::Linear(t1, t2),
                });
            }
            v
        }
        Path::Uniform | Path::Varying { .. } => match m.kind {
            MoveKind::Arc { center, sweep } => {
                vec![Piece {
                    shape: Shape::Arc {
                        center: center - m.tip,
                        start: m.ref_start(),
                        sweep,
                    },
                    time,
                }]
            }
            _ => vec![Piece {
                shape: Shape::Line {
                    from: m.ref_start(),
                    d: m.ref_end() - m.ref_start(),
                },
                time,
            }],
        },
    }
}

/// What a stretch ahead of conservative advancement is proven to be (see
/// [`Checker::stretch_proven`]).
#[derive(Clone, Copy)]
enum Proof {
    /// Clear of the stock throughout.
    Clear,
    /// In contact throughout, and nowhere deeper than `cap`.
    Contact { cap: f64 },
}

/// What [`Checker::prove_ahead`] found of a stretch ahead.
#[derive(Clone, Copy)]
enum Ahead {
    /// Proven; for a stretch in contact, the probe at its end and the bound of every pose's
    /// depth along the stretch.
    Proven(Option<(Result<f64, f64>, f64)>),
    /// The stretch in contact ends clear: the part is clear at every instant of the stretch
    /// within this distance (mm) of its end, 0 when nothing is known.
    EndsClear(f64),
    /// Not proven.
    Failed,
    /// Not tried (no stretch left short of where the contact ends).
    Skipped,
}

/// How closely conservative advancement measures the contacts it finds.
#[derive(Clone, Copy)]
enum Measure {
    /// Start and end refined by bisection, the deepest point sought (what a report shows).
    Full,
    /// The contact is certainly left out of the report (the file's finding cap): it still counts,
    /// and the findings shown may depend on it only as a crash in progress when they begin
    /// (`episodes::mark_follow_ons`) — they begin on other lines, so in other moves. So its start
    /// is its first probe in contact; its end is refined only when it comes within 1e-8 s of the
    /// move's end (`duration`); its depth is sought only while the probes leave it a graze (below
    /// `min_depth`). How many contacts there are does not change: they are told apart by the
    /// probes between them, which are the same.
    Coarse { duration: f64, min_depth: f64 },
}

/// A probe's question, as far as its answer depends on it (see [`Checker::probe_key`]): the
/// part and the station it is posed for, the reference point (its bits: the pose is computed
/// from them), and the stock's material ([`crate::scene::DexelStock::stamp`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct ProbeKey {
    p: Part,
    active: u32,
    at: (u64, u64),
    stamp: u64,
}

/// A contact interval found in one move: times in seconds from the move's start.
struct Interval {
    t0: f64,
    t1: f64,
    depth: f64,
    /// Reference point at first contact.
    at: P2,
    /// Path fraction of the piece at first contact.
    u: f64,
}

impl Checker<'_> {
    /// Check the candidate pairs of one move continuously.
    pub(super) fn exact(
        &mut self,
        m: &Move,
        item: &Timed,
        cands: &[(Part, Obstacle)],
        active: u32,
        insert_rule: Option<Kind>,
    ) {
        let pieces = pieces(m, item);
        if pieces.is_empty() {
            return;
        }
        for &(p, o) in cands {
            self.exact_pair(m, item, &pieces, p, o, active, insert_rule, false);
            if self.settings.clearance_mm > 0.0 && o != Obstacle::Stock {
                self.exact_near_miss(m, item, &pieces, p, o, active);
            }
        }
    }

    /// Step mode found pair `(p, o)` in contact during this move: measure its contacts over the
    /// whole move as exact mode does, so that where a contact begins and ends and how deep it
    /// goes do not depend on the timestep. Returns false when the exact measure finds no contact
    /// (a contact thinner than the tolerance, which conservative advancement may step over):
    /// the sampler then keeps the sample's own contact.
    pub(super) fn follow_exact(
        &mut self,
        m: &Move,
        item: &Timed,
        p: Part,
        o: Obstacle,
        active: u32,
        insert_rule: Option<Kind>,
    ) -> bool {
        let pieces = pieces(m, item);
        !pieces.is_empty() && self.exact_pair(m, item, &pieces, p, o, active, insert_rule, true)
    }

    /// The contact episodes of one pair over one move. Returns whether it found any.
    /// `in_contact`: a sample of step mode found the pair in contact during the move.
    #[allow(clippy::too_many_arguments)]
    fn exact_pair(
        &mut self,
        m: &Move,
        item: &Timed,
        pieces: &[Piece],
        p: Part,
        o: Obstacle,
        active: u32,
        insert_rule: Option<Kind>,
        in_contact: bool,
    ) -> bool {
        let dur = item.duration;
        let Some(kind) = rule(p, o, insert_rule) else {
            return false;
        };
        let k = key(p, active, o, kind);
        // A contact that begins on this line now is certainly left out of the report (the file's
        // finding cap), and so is the open episode this move may continue: it is counted, its
        // facts are never shown, so it is measured only as far as the findings that are shown
        // depend on it (see `Measure::Coarse`).
        let coarse =
            self.episodes.left_out(m.line) && self.episodes.open_line(k).map_or(true, |l| self.episodes.left_out(l));
        let measure = if coarse {
            Measure::Coarse {
                duration: dur,
                min_depth: self.settings.min_depth(self.machine),
            }
        } else {
            Measure::Full
        };
        let rigid = o != Obstacle::Stock && !matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_));
        // In contact at the previous move's end, so at this one's start (the same pose, the same
        // stock): its first piece holds a contact.
        let open_at_start = self.episodes.is_open(k);
        let mut found: Vec<Interval> = Vec::new();
        for (i, piece) in pieces.iter().enumerate() {
            if rigid {
                self.swept(p, o, piece, active, &mut found);
            } else {
                // A move of one piece found in contact is in contact somewhere on it.
                let sure = (in_contact && pieces.len() == 1) || (open_at_start && i == 0);
                // The depth the contact going on from the previous move has reached: a first
                // piece buried no deeper than that all along adds nothing to measure.
                let floor = match self.episodes.max_depth(k) {
                    Some(d) if open_at_start && pieces.len() == 1 => d,
                    _ => 0.0,
                };
                self.advanced(p, o, piece, active, measure, (sure, floor), &mut found);
            }
        }
        found.sort_by(|a, b| a.t0.total_cmp(&b.t0));
        // Merge touching intervals (from the two halves of a revolved part, or two pieces).
        let mut merged: Vec<Interval> = Vec::new();
        for iv in found {
            match merged.last_mut() {
                Some(last) if iv.t0 <= last.t1 + 1e-12 => {
                    last.t1 = last.t1.max(iv.t1);
                    last.depth = last.depth.max(iv.depth);
                }
                _ => merged.push(iv),
            }
        }
        if merged.is_empty() {
            self.episodes.clear(k);
            return false;
        }
        self.contact_in_move(k, item.index);
        for iv in merged {
            if iv.t0 > 1e-12 {
                self.episodes.clear(k); // a contact from the previous move ended at its end
            }
            // A contact going on from the previous move extends its episode: no finding to build
            // (its name, message and picture are the episode's first contact's).
            let near_miss = kind == Kind::NearMiss;
            if !self.episodes.extend(k, m.line, item.t0 + iv.t0, iv.depth, near_miss) {
                let mut c = self.contact(m, iv.at, p, o, kind, Some(iv.depth), item.t0 + iv.t0, active);
                if self.settings.snapshots && !coarse {
                    self.instant = iv.u;
                    self.refresh_swept();
                    if let Some((poly, in_plane)) = self.pose(p, iv.at, active as f64) {
                        c.snapshot = Some(Box::new(self.snapshot(
                            m,
                            item,
                            iv.at,
                            active,
                            &poly,
                            Some(o),
                            in_plane,
                        )));
                    }
                }
                self.episodes.contact(k, c);
            }
            self.episodes.lasts_until(k, item.t0 + iv.t1);
            if iv.t1 < dur - 1e-12 {
                self.episodes.clear(k);
            }
        }
        true
    }

    /// Exact sweeps of a rigid part against a polygon obstacle (both halves of its section).
    fn swept(&mut self, p: Part, o: Obstacle, piece: &Piece, active: u32, out: &mut Vec<Interval>) {
        // A rigid part is posed whole (only another station's tool may fold).
        let Some((Section::Whole(a), _)) = self.pose(p, piece.at(0.0), active as f64) else {
            return;
        };
        let Some(rev) = self.obstacle(o) else { return };
        let halves = [rev.outline.clone(), rev.mirror.clone()];
        for b in &halves {
            self.stats.pair_tests += 1;
            let eps = match piece.shape {
                Shape::Line { d, .. } => geom::sweep_line_episodes(&a, b, d),
                Shape::Arc { center, start, sweep } => geom::sweep_arc_episodes(&a, b, center, start, sweep),
            };
            for e in eps {
                out.push(Interval {
                    t0: piece.time(e.t_start),
                    t1: piece.time(e.t_end),
                    depth: e.max_depth,
                    at: piece.at(e.t_start),
                    u: e.t_start,
                });
            }
        }
    }

    /// Depth of a pair at path fraction `u` of a piece, or the gap when clear (a lower bound).
    /// The stock is seen as it is at that instant of the move. A probe that repeats one of the
    /// last two exactly ([`ProbeKey`]) gives its answer again without a query.
    fn probe(&mut self, p: Part, o: Obstacle, piece: &Piece, u: f64, active: u32) -> Result<f64, f64> {
        let memo = self.probe_key(p, o, piece.at(u), active);
        if let Some(res) = memo.and_then(|k| self.recalled(k)) {
            self.instant = u;
            return res;
        }
        let res = self.probe_now(p, o, piece, u, active);
        if let Some(k) = memo {
            self.remember(k, res);
        }
        res
    }

    /// Whether a pair is in contact at path fraction `u` of a piece (the stock's scan stops at
    /// the first column in contact), else the gap [`Self::probe`] gives there (and remembers).
    fn touches_at(&mut self, p: Part, o: Obstacle, piece: &Piece, u: f64, active: u32) -> Result<(), f64> {
        let memo = self.probe_key(p, o, piece.at(u), active);
        if let Some(res) = memo.and_then(|k| self.recalled(k)) {
            self.instant = u;
            return res.map(|_| ());
        }
        let Some((poly, in_plane)) = self.posed_at(p, piece, u, active) else {
            return Err(f64::INFINITY);
        };
        if self.test_with(&poly, in_plane, o, true).0.is_some() {
            return Ok(());
        }
        // No column in contact: what a full probe finds too (it scans for the same columns).
        let gap = self.gap_lower_bound(&poly, in_plane, o).min(GAP_WINDOW);
        if let Some(k) = memo {
            self.remember(k, Err(gap));
        }
        Err(gap)
    }

    /// The answer of a probe made before with the same key (see [`ProbeKey`]).
    fn recalled(&self, k: ProbeKey) -> Option<Result<f64, f64>> {
        let found = self
            .last_probes
            .iter()
            .flatten()
            .find(|(kk, _)| *kk == k)
            .map(|&(_, r)| r);
        #[cfg(test)]
        if found.is_some() {
            shortcuts::taken(true);
        }
        found
    }

    /// Keep a probe's answer, in place of the older of the two kept.
    fn remember(&mut self, k: ProbeKey, res: Result<f64, f64>) {
        self.last_probes.swap(0, 1);
        self.last_probes[0] = Some((k, res));
    }

    /// [`Self::probe`] made now, with its queries.
    fn probe_now(&mut self, p: Part, o: Obstacle, piece: &Piece, u: f64, active: u32) -> Result<f64, f64> {
        let Some((poly, in_plane)) = self.posed_at(p, piece, u, active) else {
            return Err(f64::INFINITY);
        };
        let (depth, _) = self.test(&poly, in_plane, o);
        if let Some(d) = depth {
            return Ok(d);
        }
        Err(self.gap_lower_bound(&poly, in_plane, o).min(GAP_WINDOW))
    }

    /// What names a probe's answer, where one can be named: a rigid part (the turret, or the
    /// active tool's holder or insert: its pose is its shape moved to the reference point) against
    /// the stock while the stock's material stands still (the current move cuts none of it, so
    /// every instant of the move sees the columns as they are, and the stamp names them). Two
    /// probes with the same key pose the same shape at the same point against the same
    /// material, with the same arithmetic: the same answer.
    fn probe_key(&self, p: Part, o: Obstacle, at: P2, active: u32) -> Option<ProbeKey> {
        #[cfg(test)]
        if shortcuts::off() {
            return None;
        }
        if o != Obstacle::Stock || !matches!(p, Part::Turret | Part::Holder | Part::Insert) {
            return None;
        }
        let stock = self.stock.as_ref()?;
        if stock.move_changed_any() {
            return None;
        }
        Some(ProbeKey {
            p,
            active,
            at: (at.x.to_bits(), at.y.to_bits()),
            stamp: stock.stamp(),
        })
    }

    /// Whether a pair is in contact at path fraction `u` of a piece (as [`Self::probe`] finds it,
    /// without measuring how deep: the stock's scan stops at the first column in contact).
    fn probe_hit(&mut self, p: Part, o: Obstacle, piece: &Piece, u: f64, active: u32) -> bool {
        let Some((poly, in_plane)) = self.posed_at(p, piece, u, active) else {
            return false;
        };
        self.test_with(&poly, in_plane, o, true).0.is_some()
    }

    /// The part posed at path fraction `u` of a piece, the stock's instant set to it.
    fn posed_at(&mut self, p: Part, piece: &Piece, u: f64, active: u32) -> Option<(Section, bool)> {
        self.instant = u;
        let posed = self.pose(p, piece.at(u), active as f64)?;
        if matches!(p, Part::OtherHolder(_) | Part::OtherInsert(_)) {
            self.others_tested = true;
        }
        Some(posed)
    }

    /// Conservative advancement along a piece: steps of at least the tolerance, and as long as
    /// the proven gap allows; contact boundaries refined by bisection. `in_contact`: the pair is
    /// known to be in contact somewhere on the piece. `floor`: the depth the pair's contact going
    /// on from the previous move has reached (0: none goes on), see [`Self::buried_no_deeper`].
    #[allow(clippy::too_many_arguments)]
    fn advanced(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        measure: Measure,
        (in_contact, floor): (bool, f64),
        out: &mut Vec<Interval>,
    ) {
        if let Some(bound) = self.buried_no_deeper(p, o, piece, active, floor) {
            out.push(Interval {
                t0: piece.time(0.0),
                t1: piece.time(1.0),
                depth: bound,
                at: piece.at(0.0),
                u: 0.0,
            });
            return;
        }
        let mut probes = 0u64;
        let spans = self.spans(p, o, piece, active);
        // The contact lies in one of the spans (elsewhere the part cannot reach the obstacle):
        // when there is only one, it cannot be proven clear whole, and is not tried.
        let try_whole = !(in_contact && spans.len() == 1);
        for (a, b) in spans {
            if !self.advanced_span(p, o, piece, active, measure, (a, b), try_whole, out, &mut probes) {
                return;
            }
        }
    }

    /// The stretches `[a, b]` of a piece along which the part's motion envelope can meet the
    /// obstacle's box; the rest of the piece is provably clear and costs nothing (a move of
    /// 1e11 mm, an arc of radius 1e9 mm, mostly far from everything).
    fn spans(&self, p: Part, o: Obstacle, piece: &Piece, active: u32) -> Vec<(f64, f64)> {
        let Some(ob) = self.obstacle_box(o) else {
            return Vec::new();
        };
        let margin = self.settings.clearance_mm + 1e-6;
        let len = piece.length();
        let mut out: Vec<(f64, f64)> = Vec::new();
        let mut stack = vec![(0.0f64, 1.0f64, 0u32)];
        while let Some((a, b, depth)) = stack.pop() {
            let rb = piece.box_between(a, b);
            let meets = self.envelope(p, &rb, active).is_some_and(|e| e.meets(&ob, margin));
            if !meets {
                continue;
            }
            if (b - a) * len > SPAN_MM && depth < 48 {
                let mid = 0.5 * (a + b);
                stack.push((mid, b, depth + 1));
                stack.push((a, mid, depth + 1));
                continue;
            }
            match out.last_mut() {
                Some(last) if last.1 >= a => last.1 = b,
                _ => out.push((a, b)),
            }
        }
        out
    }

    /// Conservative advancement from `a` to `b` of a piece. Returns false when the probe budget
    /// ran out (the rest of the move is then unchecked, and a finding says so). `try_whole`:
    /// whether to try first to prove the whole stretch clear at once.
    #[allow(clippy::too_many_arguments)]
    fn advanced_span(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        measure: Measure,
        (a, b): (f64, f64),
        try_whole: bool,
        out: &mut Vec<Interval>,
        probes: &mut u64,
    ) -> bool {
        let len = piece.length();
        let step = self.settings.tolerance_mm;
        let mut u = a;
        let mut prev_u = a;
        let mut open: Option<Interval> = None;
        // The deepest probe of the open interval and its neighbours (where the peak is sought).
        let mut peak = Peak::default();
        // How far ahead (mm) the next proof of a stretch in contact reaches.
        let mut ahead = CONTACT_AHEAD * step;
        // Proofs of a stretch in contact that failed in a row, and how many probes in contact
        // are still to pass before the next attempt: 1, 3, 7, … after one, two, three failures
        // (a contact whose depth is its axial extent fails each proof, as the stretch's hull
        // overstates that extent; an attempt costs a probe and two stock queries).
        let (mut failed, mut wait) = (0u32, 0u32);
        // The probe at `u` when a proof of the stretch up to it already made it.
        let mut known: Option<Result<f64, f64>> = None;
        // A path fraction the open contact ends before (a proof ahead found the part clear
        // there at every instant since).
        let mut ends_by = f64::INFINITY;
        // Where the rest of the span is proven clear from: a proof ahead that reached the span's
        // end found the part clear there, and every pose within that clear pose's gap of it is
        // clear at every instant since the proof's stretch began (see `gap_since`). Kept once
        // the contact has ended: past it, the rest of the span holds nothing.
        let mut clear_from = f64::INFINITY;
        // The gap the probe at `prev_u` proved (NaN: it was in contact, or none).
        let mut prev_gap = f64::NAN;
        // Most pieces pass the material at a distance, or slide along it: the hull of their
        // poses proves the whole of them clear before any probe. Whether the rest of the piece
        // was tried as one clear stretch since the last contact ended (a failed try costs one
        // stock query, so it is tried once from the start and once after each contact).
        // (Where the stretch is known to hold a contact the try would fail: it is taken as
        // made.)
        let mut tried_rest = self.settings.prove_stretches && len > 0.0 && b > a;
        if tried_rest && try_whole && self.stretch_proven(p, o, piece, active, (a, b), Proof::Clear).is_some() {
            *probes += 1;
            return true;
        }
        loop {
            *probes += 1;
            if *probes > MAX_PROBES {
                self.out_of_budget(p, o, active);
                if let Some(mut iv) = open.take() {
                    iv.t1 = piece.time(u);
                    out.push(iv);
                }
                return false;
            }
            let res = match known.take() {
                Some(r) => r,
                None => self.probe(p, o, piece, u, active),
            };
            match res {
                Ok(d) => {
                    peak.probe(prev_u, u, d);
                    match &mut open {
                        Some(iv) => iv.depth = iv.depth.max(d),
                        None => {
                            let u0 = match measure {
                                _ if u <= a => a,
                                Measure::Full => self.refine(p, o, piece, active, prev_u, u, true, prev_gap),
                                // The first probe in contact: the start only orders this contact
                                // among others of its own move, all left out too.
                                Measure::Coarse { .. } => u,
                            };
                            ends_by = f64::INFINITY;
                            // The first proof of a new contact tries the rest of the span: a
                            // part buried along its move is proven at once, and one leaving the
                            // material on the way tells where it is clear (`Ahead::EndsClear`).
                            ahead = ahead.max((b - u) * len);
                            open = Some(Interval {
                                t0: piece.time(u0),
                                t1: piece.time(u),
                                depth: d,
                                at: piece.at(u0),
                                u: u0,
                            });
                        }
                    }
                }
                Err(_) => {
                    if let Some(mut iv) = open.take() {
                        tried_rest = false;
                        ends_by = f64::INFINITY;
                        peak.probe(prev_u, u, 0.0);
                        let u1 = match measure {
                            // Ends (before this clear probe) well before the move does: no
                            // contact shown can begin while it lasts (those begin on other
                            // lines, in other moves). The last probe in contact stands for the
                            // end: it never merges with a contact after it.
                            Measure::Coarse { duration, .. } if piece.time(u) < duration - 1e-8 => prev_u,
                            _ => self.refine(p, o, piece, active, prev_u, u, false, res.err().unwrap_or(f64::NAN)),
                        };
                        iv.t1 = piece.time(u1);
                        iv.depth = self.final_depth(p, o, piece, active, measure, iv.depth, &peak);
                        peak = Peak::default();
                        out.push(iv);
                    }
                }
            }
            if u >= b || len <= 0.0 {
                break;
            }
            // Clear: as far as the proven gap allows. In contact: only the episode's end matters
            // (refined by bisection), so stride as far as the contact is proven to last (see
            // `contact_stride`); the deepest point is then sought between the neighbours of the
            // deepest probe.
            let advance = match res {
                Err(gap) if open.is_none() => gap.max(step),
                // Half a depth no longer than the tolerance but for rounding is the tolerance
                // (no stride to prove: see `contact_stride`).
                Ok(d) if 0.5 * d.min(GAP_WINDOW) <= step * (1.0 + 1e-9) => step,
                Ok(d) => 0.5 * d.min(GAP_WINDOW),
                _ => step,
            };
            // Clear past where the rest of the span was proven clear: nothing is left to find.
            if matches!((res, &open), (Err(_), None)) && u >= clear_from {
                break;
            }
            // A stretch ahead proven clear throughout (a part sliding along what it touches),
            // or in contact throughout and no deeper than the contact already is (within half
            // the tolerance), holds nothing a probe could add: step over it, and try twice as
            // far the next time.
            if matches!((res, &open), (Err(_), None))
                && !tried_rest
                && self.settings.prove_stretches
                && (b - u) * len > 2.0 * advance
            {
                tried_rest = true;
                if self.stretch_proven(p, o, piece, active, (u, b), Proof::Clear).is_some() {
                    *probes += 1;
                    break;
                }
            }
            // Touching where a whole gap's step took the part (the gap before was all of the
            // way there): it met the material head on and nearly always goes on into it, so a
            // stretch ahead is not tried as clear (a part sliding along a face has a gap of 0
            // before too, and is tried). Only the cost depends on it: where such a try would
            // have succeeded, the probes that follow find the same (on the corpus, 25 more pair
            // tests in two programs of 69).
            let head_on = res == Err(0.0) && prev_gap > 0.0 && (u - prev_u) * len >= prev_gap;
            let proof = match (res, &open) {
                _ if !self.settings.prove_stretches => None,
                (Ok(_), Some(_)) if wait > 0 => {
                    wait -= 1;
                    None
                }
                (Ok(_), Some(iv)) => Some(Proof::Contact {
                    cap: iv.depth.max(peak.depth) + 0.5 * step,
                }),
                (Err(_), None) if advance < 0.5 * ahead && !head_on => Some(Proof::Clear),
                _ => None,
            };
            if let Some(proof) = proof {
                ahead = ahead.max(2.0 * advance);
                let mut to = (u + ahead / len).min(b);
                if let Proof::Contact { .. } = proof {
                    to = to.min(ends_by - 1.5 * step / len);
                }
                let found = if to > u {
                    self.prove_ahead(p, o, piece, active, (u, to), proof, probes)
                } else {
                    Ahead::Skipped
                };
                match found {
                    Ahead::Skipped => {}
                    Ahead::Proven(at_to) => {
                        *probes += 1;
                        ahead *= 2.0;
                        failed = 0;
                        if let Some((_, bound)) = at_to {
                            peak.bound = Some((u, to, bound));
                        }
                        prev_u = u;
                        u = to;
                        known = at_to.map(|(r, _)| r);
                        prev_gap = res.err().unwrap_or(f64::NAN);
                        continue;
                    }
                    // The contact ends before the part comes within `g` of where it is clear:
                    // the next proof reaches to a tolerance and a half short of that (where a
                    // column's centre is still in the part), no further.
                    Ahead::EndsClear(g) if g > 0.0 => {
                        ends_by = ends_by.min(to - g / len);
                        if to >= b {
                            clear_from = clear_from.min(to - g / len);
                        }
                        known = Some(res);
                        continue;
                    }
                    _ => {
                        ahead = (0.25 * ahead).max(CONTACT_AHEAD * step);
                        if let Proof::Contact { .. } = proof {
                            failed = (failed + 1).min(6);
                            wait = (1 << failed) - 1;
                        }
                    }
                }
            }
            let advance = match res {
                Ok(_) if advance > step => {
                    let s = self.contact_stride(p, o, piece, active, (u, b), advance);
                    #[cfg(test)]
                    self.audit_stride(p, o, piece, active, (u, b), s);
                    s
                }
                _ => advance,
            };

            prev_u = u;
            prev_gap = res.err().unwrap_or(f64::NAN);
            u = (u + advance / len).min(b);
            // In contact, and the step would pass where the contact is known to have ended: the
            // next probe is there instead (a shorter step), the boundary's clear end.
            if res.is_ok() && open.is_some() && prev_u < ends_by && ends_by < u {
                u = ends_by;
            }
        }
        if let Some(mut iv) = open {
            iv.t1 = piece.time(b);
            iv.depth = self.final_depth(p, o, piece, active, measure, iv.depth, &peak);
            out.push(iv);
        }
        true
    }

    /// Whether a stretch `[a, b]` of a straight piece holds nothing a probe of the part against
    /// the stock could add (only the turret, holder and insert: they translate along the piece,
    /// by `δ` from their pose at `a`):
    ///
    /// - [`Proof::Clear`]: the convex hull of the poses at `a` and `b` holds every pose between,
    ///   and overlaps no column of the stock as it is at `a` (the most material of the stretch:
    ///   a cutting move only removes it) by more than half the touch tolerance, so no pose does
    ///   (as [`Checker::stretch_clear`] proves a stretch between two samples).
    /// - [`Proof::Contact`]: in contact throughout — for a convex piece `K` of the part, every
    ///   pose holds `K ∩ (K + δ)`, so when that region overlaps the stock as it is at `b` (the
    ///   least material), every pose overlaps the stock at its own instant at least as much —
    ///   and nowhere deeper than `cap`: the hull's depth against the stock at `a` bounds every
    ///   pose's (a column's radial overlap and the axial extent of the overlapping columns only
    ///   grow with the part).
    ///
    /// Returns, when proven, that bound of every pose's depth along the stretch (0 for a clear
    /// one).
    fn stretch_proven(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (a, b): (f64, f64),
        proof: Proof,
    ) -> Option<f64> {
        let (pose_a, d) = self.stretch_motion(p, o, piece, active, (a, b))?;
        // One query for a clear stretch; two for one in contact (counted whether or not the
        // first one already fails).
        self.stats.pair_tests += if let Proof::Contact { .. } = proof { 2 } else { 1 };
        let hull = stretch_hull(&pose_a, d);
        let cap = match proof {
            Proof::Clear => {
                self.instant = a;
                return self
                    .stock_overlap(&hull, 0.5 * geom::TOUCH_EPS, true)
                    .is_none()
                    .then_some(0.0);
            }
            Proof::Contact { cap } => cap,
        };
        // The bound first: it is what fails while a contact deepens (its depth the axial
        // extent, which the hull overstates).
        let bound = self.hull_depth(&hull, a);
        if bound > cap {
            return None;
        }
        self.held_throughout(&pose_a, d, b).then_some(bound)
    }

    /// Whether a part translating by `d` from `pose_a` along a stretch that ends at fraction `b`
    /// is in contact with the stock at every instant of it: a convex piece `K` of the part is
    /// held by every pose as `K ∩ (K + δ)`, and that region overlaps the stock as it is at `b`
    /// (the least material of the stretch). See [`Self::stretch_proven`].
    fn held_throughout(&mut self, pose_a: &Polygon, d: V2, b: f64) -> bool {
        self.instant = b;
        geom::convex::convex_pieces(pose_a.points()).iter().any(|k| {
            let moved: Vec<P2> = k.iter().map(|q| q + d).collect();
            let common = geom::convex::clip_convex(k, &moved);
            common.len() >= 3 && self.stock_overlap(&common, geom::TOUCH_EPS, true).is_some()
        })
    }

    /// A first piece of a move (the whole move, straight) along which the pair's contact going
    /// on from the previous move goes on to the end and is nowhere deeper than `floor`, the
    /// depth that contact has already reached: then this move adds nothing to the contact's
    /// facts but its end (the depth shown is the deepest of the whole contact), and the bound
    /// of the depth is returned (at most `floor`), to stand for the depth. `None` when that is
    /// not proven; the measure then goes on as usual, and finds what it would have.
    ///
    /// Three queries, each what a proof ahead of conservative advancement makes: a probe at the
    /// end that only asks whether it is in contact (stopping at the first column in contact;
    /// when it is clear, its gap is what a probe there gives, and is kept for the measure that
    /// follows); the hull of the poses against the stock at the start, whose depth bounds every
    /// pose's; the region every pose holds against the stock at the end (contact throughout).
    /// Right after a move of the pair proven so, two: the held region (which holds the end's
    /// contact too) and the hull.
    /// Contact throughout is what the measure's probes would find everywhere (no separation, so
    /// one contact from the start to the end), and no pose deeper than the hull, so no probe nor
    /// search deeper than `floor`: the facts the measure would give.
    fn buried_no_deeper(&mut self, p: Part, o: Obstacle, piece: &Piece, active: u32, floor: f64) -> Option<f64> {
        #[cfg(test)]
        if shortcuts::off() {
            return None;
        }
        if floor.is_nan() || floor <= 0.0 || !self.settings.prove_stretches {
            return None;
        }
        let (pose_a, d) = self.stretch_motion(p, o, piece, active, (0.0, 1.0))?;
        // After a move proven so, the region held throughout first: it proves the end in
        // contact too, and only the move where the contact ends pays for it. Else the end
        // first: where the contact ends in this move, its gap serves the measure.
        let index = self.move_index;
        let after_buried = self.buried == Some((p, o, active, index.wrapping_sub(1)));
        self.stats.pair_tests += 2;
        if after_buried {
            if !self.held_throughout(&pose_a, d, 1.0) {
                return None;
            }
        } else if self.touches_at(p, o, piece, 1.0, active).is_err() {
            return None;
        }
        let bound = self.hull_depth(&stretch_hull(&pose_a, d), 0.0);
        let proven = bound <= floor && (after_buried || self.held_throughout(&pose_a, d, 1.0));
        if !proven {
            return None;
        }
        #[cfg(test)]
        shortcuts::taken(false);
        self.buried = Some((p, o, active, index));
        Some(bound)
    }

    /// [`Self::stretch_proven`] of the stretch `[u, to]`; for one in contact, the probe at `to`
    /// first, which the proof then takes as part of the contact: a stretch that ends clear is
    /// not in contact throughout, and one whose end is in contact may be as deep inside as that
    /// end is (a contact deepening along the stretch is proven no deeper than its end within
    /// half the tolerance, and the end's depth is the contact's from then on).
    #[allow(clippy::too_many_arguments)]
    fn prove_ahead(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (u, to): (f64, f64),
        proof: Proof,
        probes: &mut u64,
    ) -> Ahead {
        let Proof::Contact { cap } = proof else {
            return match self.stretch_proven(p, o, piece, active, (u, to), proof) {
                Some(_) => Ahead::Proven(None),
                None => Ahead::Failed,
            };
        };
        // Only where a proof can be made at all (else the probe would be spent for nothing).
        if !stretch_provable(p, o, piece) || to <= u {
            return Ahead::Failed;
        }
        *probes += 1;
        let at_to = self.probe(p, o, piece, to, active);
        let d_to = match at_to {
            Ok(d_to) => d_to,
            Err(g_to) => {
                let moved = (to - u) * piece.length();
                return Ahead::EndsClear(self.gap_since(p, o, piece, active, (u, to), moved, g_to));
            }
        };
        let cap = cap.max(d_to + 0.5 * self.settings.tolerance_mm);
        match self.stretch_proven(p, o, piece, active, (u, to), Proof::Contact { cap }) {
            Some(bound) => Ahead::Proven(Some((at_to, bound))),
            None => Ahead::Failed,
        }
    }

    /// How far before `to` (mm along a straight piece) the part is surely clear at every
    /// instant from `u` on: the gap of its pose at `to` against the stock as it is at `u` (the
    /// most material from then on). A pose within that distance of the pose at `to` is nearer
    /// to it than the gap, so clear of that material. 0 when nothing is known; at most `moved`
    /// (the stretch's length). `probed`: the gap a probe at `to` found (against the stock at
    /// `to`), which is that gap while the material stands still (the stock at `u` is then the
    /// stock at `to`) unless the probe's window capped it.
    #[allow(clippy::too_many_arguments)]
    fn gap_since(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (u, to): (f64, f64),
        moved: f64,
        probed: f64,
    ) -> f64 {
        let g = if probed < GAP_WINDOW && self.material_stands_still(o) {
            probed
        } else {
            let Some((posed, in_plane)) = self.pose(p, piece.at(to), active as f64) else {
                return 0.0;
            };
            self.instant = u;
            self.gap_lower_bound(&posed, in_plane, o)
        };
        if g.is_finite() && g > 0.0 {
            g.min(moved)
        } else {
            0.0
        }
    }

    /// The part's pose at `a` and how it moves to `b` along a stretch of a straight piece, for
    /// the proofs over a stretch against the stock: the turret, holder and insert only (they
    /// translate along the piece, whole); `None` for any other pair, piece or stretch.
    fn stretch_motion(
        &self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (a, b): (f64, f64),
    ) -> Option<(Polygon, V2)> {
        if !stretch_provable(p, o, piece) || b <= a {
            return None;
        }
        let Some((Section::Whole(pose_a), _)) = self.pose(p, piece.at(a), active as f64) else {
            return None;
        };
        Some((pose_a, piece.at(b) - piece.at(a)))
    }

    /// A bound of the depth of every pose of the part against the stock along a stretch
    /// `[a, b]` of a straight piece (the turret, holder and insert only): the depth of the hull
    /// of its poses at `a` and `b` against the stock as it is at `a` (see
    /// [`Self::stretch_proven`]). `None` where no such bound is known.
    fn stretch_depth_bound(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (a, b): (f64, f64),
    ) -> Option<f64> {
        let (pose_a, d) = self.stretch_motion(p, o, piece, active, (a, b))?;
        let hull = stretch_hull(&pose_a, d);
        self.stats.pair_tests += 1;
        Some(self.hull_depth(&hull, a))
    }

    /// The depth of the hull of a stretch's poses against the stock as it is at `a` (the most
    /// material of the stretch): the bound of [`Self::stretch_depth_bound`] and of a stretch
    /// proven in contact. 0 when it does not touch.
    fn hull_depth(&mut self, hull: &[P2], a: f64) -> f64 {
        self.instant = a;
        self.stock_overlap(hull, geom::TOUCH_EPS, false)
            .map_or(0.0, |h| h.depth)
    }

    /// How far (mm along the piece, at most `want`, at least the tolerance) a part in contact at
    /// fraction `u` stays in contact for certain, so that a stride of that much steps over no
    /// separation (one would end the contact and make what follows a contact of its own: never
    /// a follow-on). `want` is half the contact's depth:
    ///
    /// Conservative advancement only follows the pairs the exact sweeps do not (the turret,
    /// holder and insert against the chuck and tailstock are swept): pairs with the stock, whose
    /// depth is a column measure and not a translation bound, and tools of other stations, whose
    /// section changes shape with the reference point's `x`. So the stride is the longest one
    /// from `want`, halving down to the tolerance, over which a region every pose holds still
    /// meets the obstacle as it is at the stride's end (the least material): `K ∩ (K + δ)` of a
    /// convex piece `K` along a straight piece; along an arc `K` eroded by the stride's length
    /// (no point moves farther); for another station's section, eroded by that plus twice the
    /// tolerance its chords keep to the true section (a point's radius from the spindle axis
    /// moves no more than the reference point's `x` does).
    ///
    /// Below the tolerance the stride is the tolerance: a separation shorter than that may be
    /// stepped over (ARCHITECTURE.md, "Exact mode").
    fn contact_stride(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (u, b): (f64, f64),
        want: f64,
    ) -> f64 {
        let step = self.settings.tolerance_mm;
        let rigid = matches!(p, Part::Turret | Part::Holder | Part::Insert);
        let len = piece.length();
        let Some((pose, in_plane)) = self.pose(p, piece.at(u), active as f64) else {
            return step;
        };
        // The convex pieces of every piece of the section (a folded one has several).
        let pieces: Vec<Vec<P2>> = pose
            .pieces()
            .iter()
            .flat_map(|q| geom::convex::convex_pieces(q.points()))
            .collect();
        let mut s = want;
        while s > step {
            let to = (u + s / len).min(b);
            let d = piece.at(to) - piece.at(u);
            let moved = (to - u) * len;
            let region = |k: &Vec<P2>| -> Vec<P2> {
                match piece.shape {
                    Shape::Line { .. } if rigid => {
                        let shifted: Vec<P2> = k.iter().map(|q| q + d).collect();
                        geom::convex::clip_convex(k, &shifted)
                    }
                    _ if rigid => geom::convex::erode_convex(k, moved),
                    _ => geom::convex::erode_convex(k, moved + 2.0 * step),
                }
            };
            self.instant = to;
            let held = pieces.iter().any(|k| {
                let r = region(k);
                r.len() >= 3
                    && Polygon::new(&r)
                        .is_ok_and(|poly| self.test_with(&Section::Whole(poly), in_plane, o, true).0.is_some())
            });
            if held {
                return s;
            }
            s *= 0.5;
        }
        step
    }

    /// With [`stride_audit::on`], probes every half tolerance along a stride in contact and
    /// records it when it stepped over a separation (the slow, obviously right oracle of
    /// `contact_stride`).
    #[cfg(test)]
    fn audit_stride(&mut self, p: Part, o: Obstacle, piece: &Piece, active: u32, (u, b): (f64, f64), s: f64) {
        // A stride of the tolerance is the resolution itself (what may step over a separation).
        if !stride_audit::enabled() || s <= self.settings.tolerance_mm * (1.0 + 1e-9) {
            return;
        }
        let (saved_stats, saved_instant) = (self.stats.clone(), self.instant);
        let len = piece.length();
        let to = (u + s / len).min(b);
        let n = ((to - u) * len / (0.5 * self.settings.tolerance_mm)).ceil().max(1.0) as usize;
        // A separation stepped over: apart somewhere inside the stride, in contact at its end
        // (a stride that ends past the contact's end is what the boundary's bisection refines).
        let at_end = self.probe_hit(p, o, piece, to, active);
        let clear: Vec<f64> = (1..n)
            .map(|k| u + (to - u) * k as f64 / n as f64)
            .filter(|&v| !self.probe_hit(p, o, piece, v, active))
            .collect();
        stride_audit::record(s, clear.first().filter(|_| at_end).map(|v| (v - u) * len));
        self.stats = saved_stats;
        self.instant = saved_instant;
    }

    /// The depth of a contact interval whose probes found `probed` at the deepest: sought
    /// between the deepest probe's neighbours, unless the contact is left out of the report and
    /// the probes already show it is no graze (then its depth only says that it is a crash in
    /// progress, which a later contact may follow on from).
    #[allow(clippy::too_many_arguments)]
    fn final_depth(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        measure: Measure,
        probed: f64,
        peak: &Peak,
    ) -> f64 {
        match measure {
            Measure::Coarse { min_depth, .. } if probed >= min_depth => probed,
            _ => probed.max(self.peak_depth(p, o, piece, active, peak)),
        }
    }

    /// The largest depth a golden-section search finds between the neighbours of the deepest
    /// probe of an interval: the true peak within the tolerance when the depth is unimodal
    /// there, a lower bound otherwise.
    fn peak_depth(&mut self, p: Part, o: Obstacle, piece: &Piece, active: u32, peak: &Peak) -> f64 {
        let (a, b) = (peak.before, peak.after.unwrap_or(peak.at));
        let best = peak.depth;
        let len = piece.length();
        if b <= a || len <= 0.0 {
            return best;
        }
        // The deepest probe is the peak when nothing between its neighbours can be deeper: the
        // search could only find what the bound allows, and keeps the deeper of the two. A proof
        // of a stretch holding both neighbours bounds them already (the hull of a part of the
        // stretch lies in the stretch's hull, and the stock at a later instant in the stock at
        // an earlier one: the depth only grows with either).
        if peak
            .bound
            .is_some_and(|(pa, pb, bound)| pa <= a && b <= pb && bound <= best)
        {
            return best;
        }
        if self
            .stretch_depth_bound(p, o, piece, active, (a, b))
            .is_some_and(|bound| bound <= best)
        {
            return best;
        }
        let width = 0.5 * self.settings.tolerance_mm / len;
        let (_, found) = crate::geom::golden_section_max(a, b, width, PEAK_STEPS, |u| {
            self.probe(p, o, piece, u, active).unwrap_or(0.0)
        });
        best.max(found)
    }

    /// The boundary between `a` (one state) and `b` (the other) on a piece: the first fraction in
    /// contact when `entering`, the last one in contact otherwise, within 2^-40 of `b - a`.
    ///
    /// `clear_gap` is a proven gap of the part at the clear end (`a` when entering, `b`
    /// otherwise; NaN when none): every pose nearer to it than that along the piece is clear
    /// (forward in time always, the stock only losing material; backward only while the
    /// obstacle's material stands still, [`Self::material_stands_still`]). The clear end first
    /// steps toward the contact by such gaps, a probe each; where it touches (a gap of 0: an
    /// exact gap took it onto the material, as advancement does to a face it approaches
    /// square), the boundary is usually at once beyond it: one probe at the resolution's
    /// distance settles it. What is left is bisected.
    #[allow(clippy::too_many_arguments)]
    fn refine(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        a: f64,
        b: f64,
        entering: bool,
        clear_gap: f64,
    ) -> f64 {
        let width = (b - a) / (1u64 << REFINE) as f64;
        let len = piece.length();
        // The clear end, the contact end, and the way from one to the other.
        let (mut c, mut k) = if entering { (a, b) } else { (b, a) };
        let toward = if entering { 1.0 } else { -1.0 };
        let usable = entering || self.material_stands_still(o);
        let mut g = if usable { clear_gap } else { f64::NAN };
        let mut stepped = false;
        for _ in 0..GAP_STEPS {
            if !(g > 0.0 && g.is_finite() && len > 0.0) {
                break;
            }
            let next = c + toward * g / len;
            if (k - next) * toward <= width {
                break;
            }
            stepped = true;
            match self.probe(p, o, piece, next, active) {
                Err(gap) => {
                    c = next;
                    g = gap;
                }
                // Rounding put the pose just past the gap in contact: a tighter bracket.
                Ok(_) => {
                    k = next;
                    g = f64::NAN;
                }
            }
        }
        // Touching where the steps ended (an exact gap took the part onto the material): the
        // boundary is usually a few units of rounding beyond. Gallop there by fours.
        if g == 0.0 {
            let mut ahead = width;
            for _ in 0..GALLOP {
                let t = c + toward * ahead;
                if (k - t) * toward <= 0.0 {
                    break;
                }
                stepped = true;
                if self.probe_hit(p, o, piece, t, active) {
                    k = t;
                    break;
                }
                c = t;
                ahead *= 4.0;
            }
        }
        let bracket = if entering { (c, k) } else { (k, c) };
        let found = self.bisect(
            p,
            o,
            piece,
            active,
            bracket,
            entering,
            if stepped { width } else { 0.0 },
        );
        #[cfg(test)]
        self.audit_refine(p, o, piece, active, (a, b), entering, found);
        found
    }

    /// Bisection of a bracket `(lo, hi)` of a contact boundary (`lo` in the state before it):
    /// 40 halvings, fewer once it is no wider than `until` or its ends are adjacent doubles (a
    /// probe at either end gives what it gave). The first fraction in contact when `entering`,
    /// the last one in contact otherwise.
    #[allow(clippy::too_many_arguments)]
    fn bisect(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (mut lo, mut hi): (f64, f64),
        entering: bool,
        until: f64,
    ) -> f64 {
        for _ in 0..REFINE {
            let mid = 0.5 * (lo + hi);
            if hi - lo <= until || mid <= lo || mid >= hi {
                break;
            }
            if self.probe_hit(p, o, piece, mid, active) == entering {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        if entering {
            hi
        } else {
            lo
        }
    }

    /// With [`refine_audit::on`], bisects the bracket `[a, b]` of [`Self::refine`] 40 times as
    /// it did before its gap steps and gallop (the slow, plain oracle), and records how far
    /// apart the two boundaries are in units of the resolution (2^-40 of the bracket, or a unit
    /// of rounding where that is coarser).
    #[cfg(test)]
    #[allow(clippy::too_many_arguments)]
    fn audit_refine(
        &mut self,
        p: Part,
        o: Obstacle,
        piece: &Piece,
        active: u32,
        (a, b): (f64, f64),
        entering: bool,
        found: f64,
    ) {
        if !refine_audit::enabled() {
            return;
        }
        let (saved_stats, saved_instant) = (self.stats.clone(), self.instant);
        let plain = self.bisect(p, o, piece, active, (a, b), entering, 0.0);
        // The resolution, or the spacing of doubles there when that is coarser (a bracket
        // near 1 of 1e-4 has its 2^-40 below one unit of rounding).
        let unit = ((b - a) / (1u64 << REFINE) as f64).max(f64::EPSILON * plain.abs());
        refine_audit::record((found - plain).abs() / unit.max(f64::MIN_POSITIVE));
        self.stats = saved_stats;
        self.instant = saved_instant;
    }

    /// Whether an obstacle's material is the same at every instant of the current move (so a
    /// gap proven at one instant holds backward too): a polygon obstacle; the stock when the
    /// move's cut changed no column (or the move cuts nothing).
    fn material_stands_still(&self, o: Obstacle) -> bool {
        o != Obstacle::Stock || !self.stock.as_ref().is_some_and(|s| s.move_changed_any())
    }

    /// Near misses in exact mode: the gap sampled every tolerance along the move.
    fn exact_near_miss(&mut self, m: &Move, item: &Timed, pieces: &[Piece], p: Part, o: Obstacle, active: u32) {
        let k = key(p, active, o, Kind::NearMiss);
        let c = self.settings.clearance_mm;
        let step = self.settings.tolerance_mm.min(c / 2.0);
        let mut probes = 0u64;
        for piece in pieces {
            let len = piece.length();
            for (a, b) in self.spans(p, o, piece, active) {
                let mut u = a;
                loop {
                    probes += 1;
                    if probes > MAX_PROBES {
                        self.out_of_budget(p, o, active);
                        return;
                    }
                    let r = piece.at(u);
                    let res = self.probe(p, o, piece, u, active);
                    match res {
                        Err(g) if g < c => {
                            let t = item.t0 + piece.time(u);
                            if !self.episodes.extend(k, m.line, t, g, true) {
                                let mut contact = self.contact(m, r, p, o, Kind::NearMiss, Some(g), t, active);
                                if self.settings.snapshots {
                                    if let Some((poly, in_plane)) = self.pose(p, r, active as f64) {
                                        let s = self.snapshot(m, item, r, active, &poly, Some(o), in_plane);
                                        contact.snapshot = Some(Box::new(s));
                                    }
                                }
                                self.episodes.contact(k, contact);
                            }
                        }
                        Ok(_) | Err(_) => self.episodes.clear(k),
                    }
                    if u >= b || len <= 0.0 {
                        break;
                    }
                    // The gap changes no faster than the part moves (and the stock only
                    // shrinks): outside the clearance band it proves no near miss for g - c,
                    // inside it proves the near miss goes on for c - g.
                    let advance = match res {
                        Err(g) if g.is_finite() => (g - c).abs().max(step),
                        _ => step,
                    };
                    u = (u + advance / len).min(b);
                }
            }
        }
    }
}

impl Checker<'_> {
    /// The probe budget of one pair along the current move ran out: say so at the move's line.
    fn out_of_budget(&mut self, p: Part, o: Obstacle, active: u32) {
        let line = self.current_line;
        let a = self.name(p, active);
        let b = obstacle_name(o);
        let message = format!(
            "latheguard stopped checking the {a} against the {b} along this move after {MAX_PROBES} probes: \
             the rest of the move is unchecked (a larger --tolerance checks it)"
        );
        self.budget.push((line, message));
    }
}

/// Whether a part's stretches against an obstacle along a piece can be proven at once
/// ([`Checker::stretch_motion`]): the turret, holder and insert (they translate whole) against
/// the stock, along a straight piece.
fn stretch_provable(p: Part, o: Obstacle, piece: &Piece) -> bool {
    o == Obstacle::Stock
        && matches!(p, Part::Turret | Part::Holder | Part::Insert)
        && matches!(piece.shape, Shape::Line { .. })
}

/// The convex hull of a pose and of the pose moved by `d`: it holds every pose between.
fn stretch_hull(pose: &Polygon, d: V2) -> Vec<P2> {
    crate::tooling::outline::hull_of_translates(pose.points(), true, &[d])
}

/// The shortcuts of the measure that must change no finding — a probe answered again
/// ([`Checker::probe`]) and a move proven buried no deeper than its contact already was
/// ([`Checker::buried_no_deeper`]) — turned off for a thread, for tests that compare them with
/// the plain measure, and counted where taken.
#[cfg(test)]
pub(super) mod shortcuts {
    use std::cell::Cell;

    thread_local! {
        static OFF: Cell<bool> = const { Cell::new(false) };
        static TAKEN: Cell<(u64, u64)> = const { Cell::new((0, 0)) };
    }

    /// Turn the shortcuts off (or on again) for this thread, and zero the counts.
    pub fn set_off(off: bool) {
        OFF.with(|o| o.set(off));
        TAKEN.with(|t| t.set((0, 0)));
    }

    pub(super) fn off() -> bool {
        OFF.with(|o| o.get())
    }

    /// A probe answered again (`recalled`), else a move proven buried no deeper.
    pub(super) fn taken(recalled: bool) {
        TAKEN.with(|t| {
            let (a, b) = t.get();
            t.set(if recalled { (a + 1, b) } else { (a, b + 1) });
        });
    }

    /// How many probes were answered again, and how many moves proven buried, since `set_off`.
    pub fn counts() -> (u64, u64) {
        TAKEN.with(|t| t.get())
    }
}

/// The audit of contact boundaries against plain bisection, for tests: off unless a test turns
/// it on for its thread.
#[cfg(test)]
pub(super) mod refine_audit {
    use std::cell::RefCell;

    thread_local! {
        static AUDIT: RefCell<Option<Vec<f64>>> = const { RefCell::new(None) };
    }

    pub fn on() {
        AUDIT.with(|a| *a.borrow_mut() = Some(Vec::new()));
    }

    /// How far each boundary found lay from plain bisection's, in units of the resolution.
    pub fn take() -> Vec<f64> {
        AUDIT.with(|a| a.borrow_mut().take().unwrap_or_default())
    }

    pub(super) fn enabled() -> bool {
        AUDIT.with(|a| a.borrow().is_some())
    }

    pub(super) fn record(apart: f64) {
        AUDIT.with(|a| {
            if let Some(v) = a.borrow_mut().as_mut() {
                v.push(apart);
            }
        });
    }
}

/// The audit of strides in contact, for tests: off unless a test turns it on for its thread.
#[cfg(test)]
pub(super) mod stride_audit {
    use std::cell::RefCell;

    #[derive(Default, Debug, Clone)]
    pub struct Audit {
        pub on: bool,
        /// Strides longer than the tolerance taken in contact.
        pub strides: u64,
        /// `(stride, first clear point along it)` of each stride that stepped over a separation.
        pub misses: Vec<(f64, f64)>,
    }

    thread_local! {
        static AUDIT: RefCell<Audit> = RefCell::new(Audit::default());
    }

    pub fn on() {
        AUDIT.with(|a| {
            *a.borrow_mut() = Audit {
                on: true,
                ..Audit::default()
            }
        });
    }

    pub fn take() -> Audit {
        AUDIT.with(|a| std::mem::take(&mut *a.borrow_mut()))
    }

    pub(super) fn enabled() -> bool {
        AUDIT.with(|a| a.borrow().on)
    }

    pub(super) fn record(stride: f64, clear_at: Option<f64>) {
        AUDIT.with(|a| {
            let mut a = a.borrow_mut();
            a.strides += 1;
            if let Some(c) = clear_at {
                a.misses.push((stride, c));
            }
        });
    }
}
