//! The in-process stock: a solid of revolution held as z-dexels.
//!
//! The stock's state is its outline in the `(r, z)` half plane. We hold it as columns of width
//! `h` along z; column `j` stores the radial intervals of material on the plane `z = c_j` through
//! its centre. Removing a region and asking whether a part overlaps the material both look at the
//! same column centres with the same arithmetic, so re-entering exactly a pose a cut ended at
//! finds exactly the surface it left: a touch, never an overlap.
//!
//! Error: the radius is exact (f64); along z the model is exact at the column centres and the
//! boundary of a cut may sit up to `h/2` off — `h` is the `--tolerance`. The cost of a cut or a
//! query is proportional to the number of columns the part spans, independent of how many cuts
//! came before (no growth with program length). Blocks of columns keep their reach (the radial
//! extremes of their material and the widest radial gap no column has material in) so that
//! parts far from the material, or inside a gap of it, are rejected without visiting columns.
//!
//! Rotating parts see the material through the radial section: a point `(x, z)` of a part is in
//! the stock when `(|x|, z)` is, so parts in the working plane are folded about the axis.

use super::cleared::Cleared;
use crate::geom::{point_segment_distance, Aabb, P2};

/// Columns per block of the quick-reject summary.
const BLOCK: usize = 64;
/// Most columns a stock may have (bounds memory on any machine file and tolerance).
pub const MAX_COLUMNS: usize = 4_000_000;

/// Material of one column: sorted, disjoint radial intervals `[lo, hi]`.
#[derive(Clone, Debug, Default, PartialEq)]
struct Column {
    iv: Vec<(f64, f64)>,
}

#[derive(Clone, Debug)]
pub struct DexelStock {
    z0: f64,
    h: f64,
    cols: Vec<Column>,
    /// Per block: where its columns' material lies radially (see [`Reach`]).
    blk: Vec<Reach>,
    /// Total radial length of material, for tests and monotonicity checks.
    removed_columns: usize,
    /// Scratch buffer of edge crossings.
    scratch: Vec<(u32, f64)>,
    /// Scratch buffer of a block's intervals (its reach).
    spans: Vec<(f64, f64)>,
    sorted: Vec<(u32, f64)>,
    counts: Vec<u32>,
    /// The material the current move's cut removed, so that parts can meet the stock as it is
    /// partway through the move.
    journal: Journal,
    /// Scratch buffers of instant queries: one column's material, and the swept polygons near
    /// the part.
    mat: Vec<(f64, f64)>,
    near: Vec<usize>,
    /// Scratch buffer of a gap query: the blocks to visit.
    order: Vec<Near>,
    /// The last few regions cut off whole, which a cut held by one takes off nothing from.
    cleared: Cleared,
    /// Names the material the columns hold: a fresh stamp each time any of them changes (see
    /// [`Self::stamp`]).
    stamp: u64,
}

/// The next stamp of [`DexelStock::stamp`]: one counter for every stock, so no two states of
/// any two stocks share one.
fn fresh_stamp() -> u64 {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
    NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
}

/// The columns the current move's cut changed, as they were before the move (see
/// [`DexelStock::begin_move`]).
#[derive(Clone, Debug, Default)]
struct Journal {
    active: bool,
    gen: u32,
    /// Per column: the generation it was saved in, and its slot in `saved`.
    col_gen: Vec<u32>,
    col_slot: Vec<u32>,
    saved: Vec<Vec<(f64, f64)>>,
    used: usize,
    /// Per block: the generation its reach was saved in, and the reach before the move.
    blk_gen: Vec<u32>,
    pre: Vec<Reach>,
}

/// Where the material of a block's columns lies radially: within `[min, gap.0]` and
/// `[gap.1, max]`, and nowhere inside the open interval `gap` (the widest radial interval that
/// no column of the block has material in; `(max, max)` when there is none). A block without
/// material has `min > max`.
///
/// The gap is what a part buried in a ring of material meets: a holder dragged through the bar
/// above its insert's cut leaves material below and above the insert's path, and the insert's
/// next pass, or a part inside the gap, is then told apart from the material without visiting
/// the block's columns.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Reach {
    min: f64,
    gap: (f64, f64),
    max: f64,
}

impl Reach {
    const EMPTY: Reach = Reach {
        min: f64::INFINITY,
        gap: (f64::NEG_INFINITY, f64::NEG_INFINITY),
        max: f64::NEG_INFINITY,
    };

    /// An upper bound of how much a part whose radial range (within the block's slab of `z`)
    /// is `[rlo, rhi]` overlaps the material of any one column of the block: every column's
    /// intervals lie in one of the two boxes, every radial span of the part at a column centre
    /// within `[rlo, rhi]` (≤ 0: no overlap at all).
    fn overlap_bound(&self, rlo: f64, rhi: f64) -> f64 {
        let below = rhi.min(self.gap.0) - rlo.max(self.min);
        let above = rhi.min(self.max) - rlo.max(self.gap.1);
        below.max(above)
    }

    /// The boxes `[r0, r1]` that hold the block's material (one when there is no gap).
    #[cfg(test)]
    fn boxes(&self) -> impl Iterator<Item = (f64, f64)> {
        let two = self.gap.0 < self.gap.1;
        let first = if two {
            (self.min, self.gap.0)
        } else {
            (self.min, self.max)
        };
        std::iter::once(first).chain(two.then_some((self.gap.1, self.max)))
    }
}

/// A polygon monotone in z: from its lowest vertex, the vertices rise (or stay level) to its
/// highest one and fall (or stay level) back, so that every plane `z = c` strictly between its
/// lowest and highest z crosses exactly two of its edges, one of each chain.
struct MonotoneChains {
    /// Index of a lowest vertex.
    low: usize,
    /// Index of the highest vertex the rising chain reaches (where the falling one begins).
    high: usize,
    zmin: f64,
    zmax: f64,
}

/// Whether `|v| < bound` (false for NaN).
fn within(v: f64, bound: f64) -> bool {
    v.abs() < bound
}

impl MonotoneChains {
    /// The chains of `pts` for columns of width `h`, or `None` (the general crossings take it)
    /// when it is not monotone in z, has fewer than three vertices, lies so far along z that a
    /// column's width is below the rounding of its z (there `z - h` may equal `z`, and the
    /// general way's ranges of columns by edge could differ from the polygon's), or so far
    /// across that a difference of two `x` may overflow (every crossing of a walk is finite, so
    /// its users may compare where the general way takes `min` and `max`).
    fn of(pts: &[P2], h: f64) -> Option<MonotoneChains> {
        let n = pts.len();
        if n < 3
            || pts
                .iter()
                .any(|p| !within(p.x, 1e300) || !within(p.y, h * (1u64 << 50) as f64))
        {
            return None;
        }
        let low = (0..n).min_by(|&a, &b| pts[a].y.total_cmp(&pts[b].y))?;
        let (zmin, mut zmax) = (pts[low].y, pts[low].y);
        let mut high = low;
        // Rising from the lowest vertex, then falling back to it: at most one turn.
        let mut falling = false;
        for s in 0..n {
            let (a, b) = (pts[(low + s) % n].y, pts[(low + s + 1) % n].y);
            if b > a {
                if falling {
                    return None;
                }
                zmax = b;
                high = (low + s + 1) % n;
            } else if b < a {
                falling = true;
            }
        }
        Some(MonotoneChains { low, high, zmin, zmax })
    }
}

/// Which ends of a block's columns in contact a scan must find (the deepest column it finds
/// always).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Scan {
    /// The first column in contact, and the last.
    BothEnds,
    /// The first column in contact only (the last returned is the last one the scan found, not
    /// always the block's last).
    FirstOnly,
    /// The last column in contact only, scanning from the block's end down (the first returned
    /// is the lowest one the scan found, not always the block's first).
    FromLast,
}

/// What a walk over a block's columns compares: the part (a monotone polygon), the depth a
/// column must exceed, the block's bound, and the swept polygons of an instant view.
struct ColumnWalk<'a> {
    pts: &'a [P2],
    chains: &'a MonotoneChains,
    eps: f64,
    bound: f64,
    swept: Option<&'a Swept>,
    near: &'a [usize],
}

/// A block a gap query may visit, with the bound of its distance to the part: ordered so that
/// a max-heap gives the nearest first (the least bound, then the least index: the order of a
/// sort by both).
#[derive(Clone, Copy, Debug)]
struct Near(f64, usize);

impl Ord for Near {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl PartialEq for Near {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other).is_eq()
    }
}

impl Eq for Near {}

/// A chain walk lost its way (a chain ran out of edges), which the chains of a monotone polygon
/// never do: the caller takes the general crossings instead.
struct Lost;

/// A walk up the column centres along both chains of a monotone polygon.
struct ChainWalk<'a> {
    pts: &'a [P2],
    zmin: f64,
    zmax: f64,
    /// Each chain's current edge: its index (the edge from `pts[i]` to `pts[i + 1]`), and its
    /// lower and upper end by z.
    up: (usize, (P2, P2)),
    down: (usize, (P2, P2)),
    /// Edges the chains may still pass (each passes each edge at most once).
    budget: usize,
    /// Whether the walk goes down the column centres (from the top) instead of up.
    descending: bool,
}

impl<'a> ChainWalk<'a> {
    /// A walk up from the lowest column centre: each call's `c` at least the last one's.
    fn new(pts: &'a [P2], chains: &MonotoneChains) -> ChainWalk<'a> {
        let n = pts.len();
        // The rising chain runs forward from the lowest vertex, the falling one backward.
        let (up, down) = (chains.low, (chains.low + n - 1) % n);
        Self::from_edges(pts, chains, (up, down), false)
    }

    /// A walk down from the highest column centre: each call's `c` at most the last one's. The
    /// spans are those of [`Self::new`]'s walk, bit for bit (a centre lies in the half-open
    /// range of one edge of each chain, whichever way the chain is walked to it).
    fn new_descending(pts: &'a [P2], chains: &MonotoneChains) -> ChainWalk<'a> {
        let n = pts.len();
        // The rising chain's last edge ends at the highest vertex; the falling one leaves it.
        let (up, down) = ((chains.high + n - 1) % n, chains.high);
        Self::from_edges(pts, chains, (up, down), true)
    }

    fn from_edges(
        pts: &'a [P2],
        chains: &MonotoneChains,
        (up, down): (usize, usize),
        descending: bool,
    ) -> ChainWalk<'a> {
        ChainWalk {
            pts,
            zmin: chains.zmin,
            zmax: chains.zmax,
            up: (up, Self::edge(pts, up)),
            down: (down, Self::edge(pts, down)),
            budget: 2 * pts.len(),
            descending,
        }
    }

    /// Edge `i`, its lower end first (as the general crossings orient it).
    fn edge(pts: &[P2], i: usize) -> (P2, P2) {
        let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
        if a.y < b.y {
            (a, b)
        } else {
            (b, a)
        }
    }

    /// The polygon's two crossings with the plane `z = c` in the order the general crossings
    /// give them (`None` outside the polygon's half-open z range). `c` never decreases from
    /// one call to the next (never increases, for a descending walk).
    #[inline]
    fn span(&mut self, c: f64) -> Result<Option<(f64, f64)>, Lost> {
        if c < self.zmin || c >= self.zmax {
            return Ok(None);
        }
        let n = self.pts.len();
        let next = |i: usize| if i + 1 == n { 0 } else { i + 1 };
        let prev = |i: usize| if i == 0 { n - 1 } else { i - 1 };
        // Step each chain to the edge whose half-open z range holds c (horizontal edges hold
        // none and are passed over).
        while !(self.up.1 .0.y <= c && c < self.up.1 .1.y) {
            self.budget = self.budget.checked_sub(1).ok_or(Lost)?;
            self.up.0 = if self.descending {
                prev(self.up.0)
            } else {
                next(self.up.0)
            };
            self.up.1 = Self::edge(self.pts, self.up.0);
        }
        while !(self.down.1 .0.y <= c && c < self.down.1 .1.y) {
            self.budget = self.budget.checked_sub(1).ok_or(Lost)?;
            self.down.0 = if self.descending {
                next(self.down.0)
            } else {
                prev(self.down.0)
            };
            self.down.1 = Self::edge(self.pts, self.down.0);
        }
        let at = |(lo, hi): (P2, P2)| lo.x + (hi.x - lo.x) * ((c - lo.y) / (hi.y - lo.y));
        // The general way pushes the edge of lower index first, then orders by x.
        let (mut first, mut second) = if self.up.0 < self.down.0 {
            (at(self.up.1), at(self.down.1))
        } else {
            (at(self.down.1), at(self.up.1))
        };
        if first > second {
            std::mem::swap(&mut first, &mut second);
        }
        Ok(Some((first, second)))
    }
}

/// The region the insert has swept so far in the current move: polygons in the working plane
/// (signed x), each with its box. The stock "at an instant" of a cutting move is the material
/// before the move less these polygons. It is rebuilt at every instant a query asks about, so
/// clearing it keeps the polygons' buffers for the next build.
#[derive(Clone, Debug, Default)]
pub struct Swept {
    /// The polygons, the first `len` of them live (the rest are spare buffers).
    pool: Vec<(Aabb, Vec<P2>)>,
    len: usize,
    /// Whether the first polygon lies inside the second (see [`Self::first_covered`]).
    first_covered: bool,
}

impl Swept {
    pub fn clear(&mut self) {
        self.len = 0;
        self.first_covered = false;
    }

    /// Say that the first polygon (the insert's pose where the move begins) lies inside the
    /// second, a sweep that starts from the same pose (its vertices there the pose's own):
    /// cutting the second removes all the first would. Holds until the next [`Self::clear`].
    pub fn cover_first(&mut self) {
        self.first_covered = self.len >= 2;
    }

    /// The polygons a cut needs: all of them but a first one a later one covers.
    pub fn to_cut(&self) -> impl Iterator<Item = &[P2]> {
        self.to_cut_indices().map(|i| &self.pool[i].1[..])
    }

    /// The indices of the polygons in [`Self::to_cut`]: the stock at an instant takes off
    /// these, so that at the move's end it is the cut's stock polygon for polygon.
    fn to_cut_indices(&self) -> std::ops::Range<usize> {
        usize::from(self.first_covered)..self.len
    }

    pub fn push(&mut self, pts: impl IntoIterator<Item = P2>) {
        if self.len == self.pool.len() {
            self.pool.push((Aabb::empty(), Vec::new()));
        }
        let (bb, poly) = &mut self.pool[self.len];
        poly.clear();
        poly.extend(pts);
        *bb = Aabb::of_points(poly.iter());
        self.len += 1;
    }

    /// Add a polygon that `fill` writes into a cleared buffer, when it returns true (a false
    /// adds nothing). Returns what `fill` returned.
    pub fn push_with(&mut self, fill: impl FnOnce(&mut Vec<P2>) -> bool) -> bool {
        if self.len == self.pool.len() {
            self.pool.push((Aabb::empty(), Vec::new()));
        }
        let (bb, poly) = &mut self.pool[self.len];
        poly.clear();
        if !fill(poly) {
            return false;
        }
        *bb = Aabb::of_points(poly.iter());
        self.len += 1;
        true
    }

    /// The live polygons with their boxes.
    fn live(&self) -> &[(Aabb, Vec<P2>)] {
        &self.pool[..self.len]
    }

    pub fn polygons(&self) -> impl Iterator<Item = &[P2]> {
        self.live().iter().map(|(_, p)| &p[..])
    }
}

/// No swept region: `View::Instant(&NO_SWEEP)` is the stock as it was before the move.
pub static NO_SWEEP: Swept = Swept {
    pool: Vec::new(),
    len: 0,
    first_covered: false,
};

/// Which state of the stock a query sees.
#[derive(Clone, Copy, Debug)]
pub enum View<'a> {
    /// The stock as it is now (after every cut so far).
    Now,
    /// During a move begun with [`DexelStock::begin_move`]: the material before the move less
    /// the given swept region (empty: the stock before the move).
    Instant(&'a Swept),
}

/// One overlap of a part with the material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockHit {
    /// Penetration estimate: the smaller of the largest radial overlap in one column and the
    /// axial extent of the overlapping columns.
    pub depth: f64,
    /// The first and last column in which the part overlaps the material by more than `eps`
    /// (with `first_only`: that first column, twice).
    pub cols: (usize, usize),
}

impl DexelStock {
    /// A bar (`bore` = 0) or tube from `front - length` to `front`, columns of width about `h`.
    pub fn new(diameter: f64, bore: f64, length: f64, front: f64, h: f64) -> DexelStock {
        let n = ((length / h).ceil() as usize).clamp(1, MAX_COLUMNS);
        let h = length / n as f64;
        let iv = vec![(bore / 2.0, diameter / 2.0)];
        DexelStock::with_columns(front - length, h, vec![Column { iv }; n])
    }

    /// A stock of `cols.len()` columns (at least one) of width `h` from `z0`, each holding the
    /// material given for it (sorted, disjoint radial intervals, as [`Self::column_now`] gives
    /// them): the columns of another stock rearranged (`scene::turn_round`).
    pub fn from_columns(z0: f64, h: f64, cols: Vec<Vec<(f64, f64)>>) -> DexelStock {
        let mut cols: Vec<Column> = cols.into_iter().take(MAX_COLUMNS).map(|iv| Column { iv }).collect();
        if cols.is_empty() {
            cols.push(Column::default());
        }
        let mut s = DexelStock::with_columns(z0, h, cols);
        s.removed_columns = s.cols.iter().filter(|c| c.iv.is_empty()).count();
        s
    }

    fn with_columns(z0: f64, h: f64, cols: Vec<Column>) -> DexelStock {
        let nb = cols.len().div_ceil(BLOCK);
        let mut s = DexelStock {
            z0,
            h,
            cols,
            blk: vec![Reach::EMPTY; nb],
            removed_columns: 0,
            scratch: Vec::new(),
            spans: Vec::new(),
            sorted: Vec::new(),
            counts: Vec::new(),
            journal: Journal::default(),
            mat: Vec::new(),
            near: Vec::new(),
            order: Vec::new(),
            cleared: Cleared::default(),
            stamp: fresh_stamp(),
        };
        for b in 0..nb {
            s.refresh_block(b);
        }
        s
    }

    /// A revolved outline (points `(x, z)` with x ≥ 0, a simple polygon) from its smallest to
    /// its largest z, columns of width about `h`: each column's material is the outline's radial
    /// intervals on the plane through the column's centre, found with the crossings a cut uses
    /// (same half-open rule, same arithmetic), so cutting along the outline leaves a touch.
    pub fn from_outline(outline: &[P2], h: f64) -> DexelStock {
        let bb = Aabb::of_points(outline);
        let length = (bb.max.y - bb.min.y).max(f64::MIN_POSITIVE);
        let mut s = DexelStock::new(0.0, 0.0, length, bb.min.y + length, h);
        let n = s.cols.len();
        for c in &mut s.cols {
            c.iv.clear();
        }
        if s.crossings(outline, 0, n - 1).is_some() {
            let scratch = std::mem::take(&mut s.scratch);
            for pair in scratch.chunks_exact(2) {
                if pair[0].0 != pair[1].0 {
                    continue;
                }
                let (r0, r1) = radial_range(pair[0].1, pair[1].1);
                let iv = &mut s.cols[pair[0].0 as usize].iv;
                match iv.last_mut() {
                    // Two spans that meet are one piece of material.
                    Some(last) if last.1 >= r0 => last.1 = last.1.max(r1),
                    _ if r1 > r0 => iv.push((r0, r1)),
                    _ => {}
                }
            }
            s.scratch = scratch;
        }
        s.removed_columns = s.cols.iter().filter(|c| c.iv.is_empty()).count();
        for b in 0..s.blk.len() {
            s.refresh_block(b);
        }
        s
    }

    /// A name of the material the columns hold now: two calls that return the same stamp see
    /// the same material in every column (any change takes a stamp no stock had before; a clone
    /// keeps the stamp with the material). The journal of a move under way is not part of it:
    /// an instant view ([`View::Instant`] while [`Self::move_changed_any`]) sees less.
    pub fn stamp(&self) -> u64 {
        self.stamp
    }

    pub fn column_width(&self) -> f64 {
        self.h
    }

    /// The z range the columns cover.
    pub fn extent(&self) -> (f64, f64) {
        (self.z0, self.z0 + self.h * self.cols.len() as f64)
    }

    /// Whether the point at radius `r` and height `z` is material now (the column holding `z`).
    pub fn holds(&self, r: f64, z: f64) -> bool {
        let j = ((z - self.z0) / self.h).floor();
        if !(j >= 0.0 && j < self.cols.len() as f64) {
            return false;
        }
        self.cols[j as usize].iv.iter().any(|&(lo, hi)| r >= lo && r <= hi)
    }

    /// Whether every point at a radius in `[r_lo, r_hi]` and a height in `[z_lo, z_hi]` is
    /// material now ([`DexelStock::holds`] is true at each): each column those heights fall in
    /// holds one interval spanning the radii. `false` as well when more than 256 columns would
    /// be looked at (the caller asks point by point).
    pub fn holds_all(&self, r_lo: f64, r_hi: f64, z_lo: f64, z_hi: f64) -> bool {
        // The same column index as `holds`, monotone in the height.
        let (j0, j1) = (((z_lo - self.z0) / self.h).floor(), ((z_hi - self.z0) / self.h).floor());
        if !(j0 >= 0.0 && j1 < self.cols.len() as f64 && j1 - j0 <= 256.0) {
            return false;
        }
        self.cols[j0 as usize..=j1 as usize]
            .iter()
            .all(|c| c.iv.iter().any(|&(lo, hi)| lo <= r_lo && r_hi <= hi))
    }

    /// How many columns hold no material (a part-off empties the columns of its groove).
    pub fn empty_columns(&self) -> usize {
        self.removed_columns
    }

    /// A part-off: when an empty column separates material on both of its sides, the material
    /// beyond the last such column (toward `+z`) leaves this stock and is returned as a stock of
    /// its own (same columns, the others empty). `None` while the stock is in one piece along
    /// `z`, or while a move's cut is under way (between `begin_move` and `end_move`).
    pub fn split_off_beyond(&mut self) -> Option<DexelStock> {
        if self.journal.active || self.removed_columns == 0 {
            return None;
        }
        let n = self.cols.len();
        let top = (0..n).rev().find(|&j| !self.cols[j].iv.is_empty())?;
        let gap = (0..top).rev().find(|&j| self.cols[j].iv.is_empty())?;
        if !(0..gap).any(|j| !self.cols[j].iv.is_empty()) {
            return None;
        }
        let mut piece = self.clone();
        piece.journal = Journal::default();
        for c in &mut piece.cols[..=gap] {
            c.iv.clear();
        }
        for c in &mut self.cols[gap + 1..] {
            c.iv.clear();
        }
        for s in [&mut *self, &mut piece] {
            s.removed_columns = s.cols.iter().filter(|c| c.iv.is_empty()).count();
            for b in 0..s.blk.len() {
                s.refresh_block(b);
            }
        }
        Some(piece)
    }

    pub fn columns(&self) -> usize {
        self.cols.len()
    }

    /// Column `j`'s material now (after every cut so far): sorted, disjoint radial intervals;
    /// empty past the last column.
    pub fn column_now(&self, j: usize) -> &[(f64, f64)] {
        self.cols.get(j).map_or(&[], |c| &c.iv[..])
    }

    /// The first and last columns that hold material (None: no material left).
    pub fn material_columns(&self) -> Option<(usize, usize)> {
        let first = self.cols.iter().position(|c| !c.iv.is_empty())?;
        let last = self.cols.iter().rposition(|c| !c.iv.is_empty())?;
        Some((first, last))
    }

    fn center(&self, j: usize) -> f64 {
        self.z0 + (j as f64 + 0.5) * self.h
    }

    /// Columns whose centre lies strictly inside `(zmin, zmax)`.
    fn column_range(&self, zmin: f64, zmax: f64) -> Option<(usize, usize)> {
        let n = self.cols.len();
        let a = ((zmin - self.z0) / self.h - 0.5).floor() + 1.0;
        let b = ((zmax - self.z0) / self.h - 0.5).ceil() - 1.0;
        let a = a.max(0.0);
        let b = b.min(n as f64 - 1.0);
        if a.is_nan() || b.is_nan() || a > b {
            return None;
        }
        let (mut a, mut b) = (a as usize, b as usize);
        // Guard the strict inequalities against rounding in the formula above.
        while a <= b && self.center(a) <= zmin {
            a += 1;
        }
        while b >= a && self.center(b) >= zmax {
            if b == 0 {
                return None;
            }
            b -= 1;
        }
        (a <= b).then_some((a, b))
    }

    /// The part's radial range (folded) within block `b`'s slab of z; `None` when the part does
    /// not reach the slab.
    fn slab_range(&self, pts: &[P2], b: usize) -> Option<(f64, f64)> {
        let za = self.z0 + (b * BLOCK) as f64 * self.h;
        let zb = self.z0 + ((b + 1) * BLOCK) as f64 * self.h;
        slab_radial_range(pts, za, zb)
    }

    /// Where a block's material lies; with `pre`, before the current move.
    fn reach(&self, b: usize, pre: bool) -> Reach {
        let j = &self.journal;
        if pre && j.active && j.blk_gen[b] == j.gen {
            j.pre[b]
        } else {
            self.blk[b]
        }
    }

    /// Start a move whose cut may be queried partway (see [`View::Instant`]): from now until
    /// [`Self::end_move`], every column a cut changes keeps its material from before, so the
    /// stock at any instant of the move is that material less what the insert has swept by then.
    /// Costs one copy of each changed column.
    pub fn begin_move(&mut self) {
        let j = &mut self.journal;
        if j.col_gen.len() != self.cols.len() {
            j.col_gen = vec![0; self.cols.len()];
            j.col_slot = vec![0; self.cols.len()];
            j.blk_gen = vec![0; self.blk.len()];
            j.pre = vec![Reach::EMPTY; self.blk.len()];
            j.gen = 0;
        }
        if j.gen == u32::MAX {
            j.col_gen.iter_mut().for_each(|g| *g = 0);
            j.blk_gen.iter_mut().for_each(|g| *g = 0);
            j.gen = 0;
        }
        j.gen += 1;
        j.used = 0;
        j.active = true;
    }

    /// Whether the cut of the move begun with [`Self::begin_move`] changed any column. When it
    /// did not, the stock at every instant of the move is the stock as it is now: an instant
    /// view reads only the columns (and blocks) the move changed.
    pub fn move_changed_any(&self) -> bool {
        self.journal.active && self.journal.used > 0
    }

    /// End the move begun with [`Self::begin_move`]: queries see the stock as it is now.
    pub fn end_move(&mut self) {
        self.journal.active = false;
    }

    /// Whether the last move begun with [`Self::begin_move`] changed every column from `j0` to
    /// `j1` (its cut removed material from each). Holds until the next `begin_move`.
    pub fn last_move_changed(&self, j0: usize, j1: usize) -> bool {
        let j = &self.journal;
        j.gen > 0 && j1 < j.col_gen.len() && j0 <= j1 && j.col_gen[j0..=j1].iter().all(|&g| g == j.gen)
    }

    /// The material of column `col` before the current move, when the move changed it.
    fn saved(&self, col: usize) -> Option<&[(f64, f64)]> {
        let j = &self.journal;
        (j.active && j.col_gen[col] == j.gen).then(|| &j.saved[j.col_slot[col] as usize][..])
    }

    /// Keep column `col`'s material (and its block's extremes) before the move changes it.
    fn save(&mut self, col: usize) {
        let j = &mut self.journal;
        if !j.active || j.col_gen[col] == j.gen {
            return;
        }
        if j.used == j.saved.len() {
            j.saved.push(Vec::new());
        }
        let slot = j.used;
        j.used += 1;
        j.saved[slot].clear();
        j.saved[slot].extend_from_slice(&self.cols[col].iv);
        j.col_gen[col] = j.gen;
        j.col_slot[col] = slot as u32;
        let b = col / BLOCK;
        if j.blk_gen[b] != j.gen {
            j.blk_gen[b] = j.gen;
            j.pre[b] = self.blk[b];
        }
    }

    /// Recompute block `b`'s reach from its columns. Every change of a column's material is
    /// followed by this (the reach must hold it), so it also takes a fresh stamp.
    fn refresh_block(&mut self, b: usize) {
        self.stamp = fresh_stamp();
        let (lo, hi) = (b * BLOCK, ((b + 1) * BLOCK).min(self.cols.len()));
        let mut mx = f64::NEG_INFINITY;
        let mut mn = f64::INFINITY;
        // While every column holds one interval and all of them share a point, their union is
        // one interval: no gap, and no sort.
        let (mut top_lo, mut low_hi) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut single = true;
        for c in &self.cols[lo..hi] {
            if let (Some(f), Some(l)) = (c.iv.first(), c.iv.last()) {
                mn = mn.min(f.0);
                mx = mx.max(l.1);
                single &= c.iv.len() == 1;
                top_lo = top_lo.max(f.0);
                low_hi = low_hi.min(f.1);
            }
        }
        let mut gap = (mx, mx);
        if mn <= mx && !(single && top_lo <= low_hi) {
            let spans = &mut self.spans;
            spans.clear();
            for c in &self.cols[lo..hi] {
                spans.extend_from_slice(&c.iv);
            }
            spans.sort_unstable_by(|p, q| p.0.total_cmp(&q.0));
            let mut reached = spans[0].1;
            for &(a, z) in &spans[1..] {
                if a > reached && a - reached > gap.1 - gap.0 {
                    gap = (reached, a);
                }
                reached = reached.max(z);
            }
        }
        self.blk[b] = Reach { min: mn, gap, max: mx };
    }

    /// The polygon's crossings with the centre planes of columns `j0..=j1`, grouped by column:
    /// fills `scratch` with (column, x) sorted by column then x.
    /// Edge by edge, for any polygon (a monotone one's spans a [`ChainWalk`] gives, bit for bit
    /// the same).
    fn crossings(&mut self, pts: &[P2], j0: usize, j1: usize) -> Option<(usize, usize)> {
        self.scratch.clear();
        let n = pts.len();
        for i in 0..n {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            if a.y == b.y {
                continue;
            }
            let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
            // Half-open rule: an edge covers centres c with lo.y <= c < hi.y.
            let Some((k0, k1)) = self.column_range(lo.y - self.h, hi.y + self.h) else {
                continue;
            };
            let (k0, k1) = (k0.max(j0), k1.min(j1));
            for k in k0..=k1 {
                let c = self.center(k);
                if c >= lo.y && c < hi.y {
                    let x = lo.x + (hi.x - lo.x) * ((c - lo.y) / (hi.y - lo.y));
                    self.scratch.push((k as u32, x));
                }
            }
        }
        // Group by column with a counting sort (columns are a small integer range), then order
        // each column's few crossings: linear in the number of crossings.
        let span = j1 - j0 + 1;
        self.counts.clear();
        self.counts.resize(span + 1, 0);
        for &(k, _) in &self.scratch {
            self.counts[k as usize - j0 + 1] += 1;
        }
        for i in 1..=span {
            self.counts[i] += self.counts[i - 1];
        }
        self.sorted.clear();
        self.sorted.resize(self.scratch.len(), (0, 0.0));
        for &(k, x) in &self.scratch {
            let slot = &mut self.counts[k as usize - j0];
            self.sorted[*slot as usize] = (k, x);
            *slot += 1;
        }
        let mut i = 0;
        while i < self.sorted.len() {
            let k = self.sorted[i].0;
            let mut e = i + 1;
            while e < self.sorted.len() && self.sorted[e].0 == k {
                e += 1;
            }
            if e - i > 2 {
                self.sorted[i..e].sort_unstable_by(|p, q| p.1.total_cmp(&q.1));
            } else if e - i == 2 && self.sorted[i].1 > self.sorted[i + 1].1 {
                self.sorted.swap(i, i + 1);
            }
            i = e;
        }
        std::mem::swap(&mut self.scratch, &mut self.sorted);
        Some((j0, j1))
    }

    /// Does a part (polygon in the working plane, `x` signed) overlap the material by more than
    /// `eps`? Returns the penetration estimate.
    pub fn overlap(&mut self, pts: &[P2], eps: f64) -> Option<StockHit> {
        self.overlap_with(pts, eps, false)
    }

    /// [`Self::overlap`], or with `first_only` just whether there is an overlap: it stops at the
    /// first column that proves one, and the depth is that column's (a lower bound).
    pub fn overlap_with(&mut self, pts: &[P2], eps: f64, first_only: bool) -> Option<StockHit> {
        self.overlap_view(pts, eps, first_only, View::Now)
    }

    /// [`Self::overlap_with`] against the stock as `view` sees it.
    pub fn overlap_view(&mut self, pts: &[P2], eps: f64, first_only: bool, view: View) -> Option<StockHit> {
        let bb = Aabb::of_points(pts);
        let (rlo, rhi) = radial_range(bb.min.x, bb.max.x);
        let (j0, j1) = self.column_range(bb.min.y, bb.max.y)?;
        let swept = match view {
            View::Instant(sw) if self.move_changed_any() => Some(sw),
            _ => None,
        };
        let pre = swept.is_some();
        // Quick reject by blocks: the part's radial range against each block's reach.
        if !(j0 / BLOCK..=j1 / BLOCK).any(|b| self.reach(b, pre).overlap_bound(rlo, rhi) > eps) {
            return None;
        }
        // The swept polygons that can change what the part meets: those within its box.
        let mut near = std::mem::take(&mut self.near);
        near.clear();
        if let Some(sw) = swept {
            for i in sw.to_cut_indices() {
                let pb = &sw.live()[i].0;
                let (plo, phi) = radial_range(pb.min.x, pb.max.x);
                if pb.max.y >= bb.min.y && pb.min.y <= bb.max.y && phi > rlo && plo < rhi {
                    near.push(i);
                }
            }
        }
        let mut mat = std::mem::take(&mut self.mat);
        let (b0, b1) = (j0 / BLOCK, j1 / BLOCK);
        let chains = MonotoneChains::of(pts, self.h);
        let mut scan = |s: &mut Self, b: usize, ends: Scan| {
            s.block_overlap(
                pts,
                b,
                (j0, j1),
                eps,
                pre,
                chains.as_ref(),
                swept,
                &near,
                &mut mat,
                ends,
            )
        };
        // The first block in contact from either end gives the first and last columns in
        // contact (the axial extent); the blocks between can only raise the greatest radial
        // overlap, and are scanned only while their bound (the part's radial range in the block
        // against the block's material) could: the result is what a scan of every column gives.
        let mut found: Option<(f64, usize, usize)> = None;
        let mut lo_block = b1 + 1;
        let lo_ends = if first_only { Scan::FirstOnly } else { Scan::BothEnds };
        for b in b0..=b1 {
            if let Some(hit) = scan(self, b, lo_ends) {
                found = Some(hit);
                lo_block = b;
                break;
            }
        }
        if let Some((best, first, last)) = found.as_mut() {
            if !first_only {
                let mut hi_block = lo_block;
                for b in (lo_block + 1..=b1).rev() {
                    if let Some((bb, _, l)) = scan(self, b, Scan::FromLast) {
                        *best = best.max(bb);
                        *last = l;
                        hi_block = b;
                        break;
                    }
                }
                let cap = (self.center(*last) - self.center(*first) + self.h).min(bb.max.y - bb.min.y);
                if *best < cap && hi_block > lo_block + 1 {
                    // A block whose bound over the part's whole radial range cannot beat the
                    // depth found cannot over the range within its slab either (the bound
                    // only grows with the range): its slab is not looked at.
                    let floor = best.max(eps);
                    let mut between: Vec<(f64, usize)> = (lo_block + 1..hi_block)
                        .filter(|&b| self.reach(b, pre).overlap_bound(rlo, rhi) > floor)
                        .filter_map(|b| self.block_bound(pts, b, pre).map(|ub| (ub, b)))
                        .filter(|&(ub, _)| ub > eps)
                        .collect();
                    between.sort_unstable_by(|x, y| y.0.total_cmp(&x.0));
                    for (ub, b) in between {
                        if ub <= *best || *best >= cap {
                            break;
                        }
                        if let Some((bb, _, _)) = scan(self, b, Scan::FirstOnly) {
                            *best = best.max(bb);
                        }
                    }
                }
            }
        }
        self.mat = mat;
        self.near = near;
        let (best, first, last) = found?;
        if first_only {
            return Some(StockHit {
                depth: best.min(bb.max.y - bb.min.y),
                cols: (first, first),
            });
        }
        let axial = (self.center(last) - self.center(first) + self.h).min(bb.max.y - bb.min.y);
        Some(StockHit {
            depth: best.min(axial),
            cols: (first, last),
        })
    }

    /// An upper bound of the radial overlap of a part with any column of block `b`: the part's
    /// radial range over the block's slab of `z` against the block's material (as it was before
    /// the current move with `pre`, which holds the material at every instant of it). `None`
    /// when the part does not reach the slab.
    ///
    /// Exact as a bound: the crossings of an edge at the column centres lie within the values
    /// the same arithmetic gives at the slab's ends (IEEE rounding is monotone), and so does
    /// each column's overlap (a difference of a `min` and a `max`) within the bound's; a block
    /// whose bound is at most `eps` holds no column that a scan would find overlapped by more.
    fn block_bound(&self, pts: &[P2], b: usize, pre: bool) -> Option<f64> {
        let (rlo, rhi) = self.slab_range(pts, b)?;
        Some(self.reach(b, pre).overlap_bound(rlo, rhi))
    }

    /// The part's overlap with the columns of block `b` (within `j0..=j1`) deeper than `eps`:
    /// the greatest radial overlap of one column, and the first and last columns that have one
    /// (as `scan` asks for them: see [`Scan`]).
    #[allow(clippy::too_many_arguments)]
    fn block_overlap(
        &mut self,
        pts: &[P2],
        b: usize,
        (j0, j1): (usize, usize),
        eps: f64,
        pre: bool,
        chains: Option<&MonotoneChains>,
        swept: Option<&Swept>,
        near: &[usize],
        mat: &mut Vec<(f64, f64)>,
        scan: Scan,
    ) -> Option<(f64, usize, usize)> {
        // The block's bound: no column overlaps more, and a block it keeps at `eps` holds none
        // deeper than that.
        let bound = self.block_bound(pts, b, pre).filter(|&ub| ub > eps)?;
        let (k0, k1) = ((b * BLOCK).max(j0), ((b + 1) * BLOCK - 1).min(j1));
        if let Some(chains) = chains {
            let walked = ColumnWalk {
                pts,
                chains,
                eps,
                bound,
                swept,
                near,
            };
            if let Ok(found) = self.block_overlap_walking(&walked, (k0, k1), scan, mat) {
                return found;
            }
        }
        self.crossings(pts, k0, k1)?;
        let scratch = std::mem::take(&mut self.scratch);
        let mut best: f64 = 0.0;
        let mut first: Option<usize> = None;
        let mut last = 0usize;
        let mut i = 0;
        while i < scratch.len() {
            let col = scratch[i].0 as usize;
            let mut k = i;
            while k < scratch.len() && scratch[k].0 as usize == col {
                k += 1;
            }
            let material = self.material_seen(col, swept, near, mat);
            let mut o_col: f64 = 0.0;
            for pair in scratch[i..k].chunks_exact(2) {
                let (r0, r1) = radial_range(pair[0].1, pair[1].1);
                for &(lo, hi) in material {
                    o_col = o_col.max(r1.min(hi) - r0.max(lo));
                }
            }
            if o_col > eps {
                best = best.max(o_col);
                if first.is_none() {
                    first = Some(col);
                }
                last = col;
            }
            i = k;
        }
        self.scratch = scratch;
        first.map(|f| (best, f, last))
    }

    /// Column `col`'s material as a query sees it: under an instant view (`swept`), a column
    /// the move changed is its material before the move less the swept polygons `near` (built
    /// in `mat`); any other is as it is now. Inlined always: it is called once for every column
    /// a query spans (millions in a long contact), and as a call it cost 5 % more instructions.
    #[inline(always)]
    fn material_seen<'a>(
        &'a self,
        col: usize,
        swept: Option<&Swept>,
        near: &[usize],
        mat: &'a mut Vec<(f64, f64)>,
    ) -> &'a [(f64, f64)] {
        // The journal is looked up only under an instant view.
        match swept.and_then(|sw| Some((sw, self.saved(col)?))) {
            Some((sw, before)) => {
                mat.clear();
                mat.extend_from_slice(before);
                remove_swept(mat, sw, near, self.center(col));
                mat
            }
            None => &self.cols[col].iv,
        }
    }

    /// [`Self::block_overlap`] of a monotone polygon over columns `k0..=k1`: the span at each
    /// column's centre from a walk along its chains, the same spans the crossings give.
    ///
    /// No column of the block overlaps the part more than the block's bound (the part's radial
    /// range over the slab against the block's material: every column's span lies in that range
    /// and its material in the block's, and IEEE subtraction is monotone). So once the deepest
    /// column found reaches the bound, no column left can be deeper: the scan stops, and only
    /// the end it still owes is sought, walking in from that end. The depth and columns are
    /// those of a scan of every column, bit for bit.
    fn block_overlap_walking(
        &self,
        w: &ColumnWalk,
        (k0, k1): (usize, usize),
        scan: Scan,
        mat: &mut Vec<(f64, f64)>,
    ) -> Result<Option<(f64, usize, usize)>, Lost> {
        let descending = scan == Scan::FromLast;
        let mut walk = if descending {
            ChainWalk::new_descending(w.pts, w.chains)
        } else {
            ChainWalk::new(w.pts, w.chains)
        };
        let mut best: f64 = 0.0;
        // The first and last columns in contact among those scanned.
        let mut seen: Option<(usize, usize)> = None;
        // Where the scan stopped, the deepest column having reached the bound.
        let mut stopped = None;
        let mut step = |col: usize| -> Result<bool, Lost> {
            let o_col = self.column_overlap(w, &mut walk, col, mat)?;
            if o_col > w.eps {
                best = best.max(o_col);
                seen = Some(seen.map_or((col, col), |(f, l)| (f.min(col), l.max(col))));
                if best >= w.bound {
                    stopped = Some(col);
                    return Ok(true);
                }
            }
            Ok(false)
        };
        if descending {
            for col in (k0..=k1).rev() {
                if step(col)? {
                    break;
                }
            }
        } else {
            for col in k0..=k1 {
                if step(col)? {
                    break;
                }
            }
        }
        let Some((first, mut last)) = seen else {
            return Ok(None);
        };
        // Stopped early going up: the last column in contact, walking down to where it stopped.
        if let (Scan::BothEnds, Some(at)) = (scan, stopped) {
            let mut back = ChainWalk::new_descending(w.pts, w.chains);
            for col in (at + 1..=k1).rev() {
                if self.column_overlap(w, &mut back, col, mat)? > w.eps {
                    last = col;
                    break;
                }
            }
        }
        Ok(Some((best, first, last)))
    }

    /// The radial overlap of the part's span at column `col`'s centre (from `walk`) with the
    /// column's material as the query sees it; 0 where the part does not reach the column.
    #[inline(always)]
    fn column_overlap(
        &self,
        w: &ColumnWalk,
        walk: &mut ChainWalk,
        col: usize,
        mat: &mut Vec<(f64, f64)>,
    ) -> Result<f64, Lost> {
        let Some((x0, x1)) = walk.span(self.center(col))? else {
            return Ok(0.0);
        };
        let material = self.material_seen(col, w.swept, w.near, mat);
        let (r0, r1) = radial_range(x0, x1);
        // All finite: comparisons give what `max` and `min` do, without their NaN rules.
        let mut o_col: f64 = 0.0;
        for &(lo, hi) in material {
            let o = if r1 < hi { r1 } else { hi } - if r0 > lo { r0 } else { lo };
            if o > o_col {
                o_col = o;
            }
        }
        Ok(o_col)
    }

    /// A copy of the stock as `view` sees it (for pictures).
    pub fn view_copy(&self, view: View) -> DexelStock {
        let mut s = self.clone();
        s.journal = Journal::default();
        if let View::Instant(sw) = view {
            if self.journal.active {
                let all: Vec<usize> = sw.to_cut_indices().collect();
                for col in 0..self.cols.len() {
                    if let Some(before) = self.saved(col) {
                        let mut m = before.to_vec();
                        remove_swept(&mut m, sw, &all, self.center(col));
                        s.cols[col].iv = m;
                    }
                }
                for b in 0..s.blk.len() {
                    s.refresh_block(b);
                }
            }
        }
        s
    }

    /// A lower bound on the distance from a part (working plane, folded) to any material of the
    /// stock as it is now, looking no further than `window` mm; returns `window` when nothing is
    /// that close.
    pub fn gap_bound(&mut self, pts: &[P2], window: f64) -> f64 {
        self.gap_bound_view(pts, window, View::Now)
    }

    /// A lower bound on the distance from a part (working plane, folded) to the material as
    /// `view` sees it, looking no further than `window` mm; returns `window` when nothing is that
    /// close. Never larger than the true distance (to rounding): blocks the current move has not
    /// changed are bounded by the box of their material (the block summaries, a few operations
    /// per block); in blocks it has changed, each changed column's material at the instant (its
    /// saved material less the swept region, exactly as [`Self::overlap_view`] sees it) is a
    /// radial segment at the column's centre, and the part's distance to it is computed exactly.
    ///
    /// During a cutting move, the stock at an instant holds the stock at every later instant of
    /// the move (material is only removed), so the bound at an instant holds for the rest of the
    /// move: ARCHITECTURE.md, "The stock at the instant".
    pub fn gap_bound_view(&mut self, pts: &[P2], window: f64, view: View) -> f64 {
        self.gap_bound_walk(pts, window, view, true)
    }

    /// [`Self::gap_bound_view`] visiting the blocks in the order of `z`, every one whose bound is
    /// below the distance found so far: the walk before the blocks were taken nearest first, the
    /// tests' oracle (the answers are equal to rounding).
    #[doc(hidden)]
    pub fn gap_bound_view_in_order(&mut self, pts: &[P2], window: f64, view: View) -> f64 {
        self.gap_bound_walk(pts, window, view, false)
    }

    fn gap_bound_walk(&mut self, pts: &[P2], window: f64, view: View, nearest_first: bool) -> f64 {
        if pts.is_empty() || window.is_nan() {
            return 0.0;
        }
        let bb = Aabb::of_points(pts);
        let (rlo, rhi) = radial_range(bb.min.x, bb.max.x);
        let Some((j0, j1)) = self.column_range(bb.min.y - window, bb.max.y + window) else {
            return window;
        };
        let swept = match view {
            View::Instant(sw) if self.move_changed_any() => Some(sw),
            _ => None,
        };
        // A cheap lower bound of the distance from the part to the box [r0, r1] x [z0, z1].
        let box_bound = |r0: f64, r1: f64, z0: f64, z1: f64| {
            let dz = (z0 - bb.max.y).max(bb.min.y - z1).max(0.0);
            let dr = (r0 - rhi).max(rlo - r1).max(0.0);
            (dz * dz + dr * dr).sqrt()
        };
        // The swept polygons that can change material within the window of the part. (Leaving
        // one out would only leave more material: still a lower bound.)
        let mut near = std::mem::take(&mut self.near);
        near.clear();
        if let Some(sw) = swept {
            for i in sw.to_cut_indices() {
                let pb = &sw.live()[i].0;
                let (plo, phi) = radial_range(pb.min.x, pb.max.x);
                if pb.max.y > bb.min.y - window
                    && pb.min.y < bb.max.y + window
                    && phi > rlo - window
                    && plo < rhi + window
                {
                    near.push(i);
                }
            }
        }
        let mut mat = std::mem::take(&mut self.mat);
        let mut best = window;
        // The blocks in the window, nearest first by a bound of their distance (a block the move
        // changed by its z alone), so that the nearest material found early lets the bound
        // pass over the rest. The least of the distances does not depend on the order in
        // which they are taken: the answer is the in-order walk's, to rounding (an edge whose
        // distance rounds a unit below its box's bound may be measured in one order and passed
        // over in the other).
        let mut order = std::mem::take(&mut self.order);
        order.clear();
        // The `z` of block `b`'s first and last column centres in the window.
        let slab = |s: &Self, b: usize| -> (f64, f64) {
            let (k0, k1) = ((b * BLOCK).max(j0), ((b + 1) * BLOCK - 1).min(j1));
            (s.center(k0), s.center(k1))
        };
        // Block `b`'s bound (its column centres from `z0` to `z1`), `None` when it holds no
        // material.
        let block_bound = |s: &Self, b: usize, (z0, z1): (f64, f64)| -> Option<f64> {
            let journaled = swept.is_some() && s.journal.blk_gen[b] == s.journal.gen;
            if journaled {
                return Some(box_bound(f64::NEG_INFINITY, f64::INFINITY, z0, z1));
            }
            let (mn, mx) = (s.blk[b].min, s.blk[b].max);
            (mn <= mx).then(|| box_bound(mn, mx, z0, z1))
        };
        let (bl0, bl1) = (j0 / BLOCK, j1 / BLOCK);
        if !nearest_first {
            for b in bl0..=bl1 {
                if let Some(bound) = block_bound(self, b, slab(self, b)).filter(|&bound| bound < best) {
                    order.push(Near(bound, b));
                }
            }
        }
        // One block: the least distance to its material, when less than the best so far.
        let mut visit = |s: &Self, b: usize, best: &mut f64| {
            let (k0, k1) = ((b * BLOCK).max(j0), ((b + 1) * BLOCK - 1).min(j1));
            let journaled = swept.is_some() && s.journal.blk_gen[b] == s.journal.gen;
            if !journaled {
                // Unchanged by the move: the block's material now is its material at every
                // instant of the move, inside the box of its extremes and column centres.
                let (mn, mx) = (s.blk[b].min, s.blk[b].max);
                let (z0, z1) = (s.center(k0), s.center(k1));
                *best = best.min(poly_box_distance(pts, &bb, mn, mx, z0, z1, *best));
                return;
            }
            for col in k0..=k1 {
                let c = s.center(col);
                if box_bound(f64::NEG_INFINITY, f64::INFINITY, c, c) >= *best {
                    continue;
                }
                let material: &[(f64, f64)] = match (swept, s.saved(col)) {
                    (Some(sw), Some(before)) => {
                        mat.clear();
                        mat.extend_from_slice(before);
                        remove_swept(&mut mat, sw, &near, c);
                        &mat
                    }
                    _ => &s.cols[col].iv,
                };
                for &(lo, hi) in material {
                    if box_bound(lo, hi, c, c) < *best {
                        *best = best.min(poly_box_distance(pts, &bb, lo, hi, c, c, *best));
                    }
                }
                if *best <= 0.0 {
                    break;
                }
            }
        };
        if nearest_first {
            // Taken from a heap, nearest first: usually a few blocks are taken before the next
            // one's bound passes the distance found, and the rest are never ordered (a sort of
            // every block in the window cost a tenth of a long contact's time). A block's bound
            // is at least its distance in z from the part's box, which grows outward from the
            // block at the box's middle: the blocks are bounded from there outward, each side
            // only while its next block's distance in z (a little less, for rounding) could come
            // before the heap's nearest, so the heap gives them in the order it would give them
            // all in, and the blocks past the distance found are never bounded.
            let mid = ((0.5 * (bb.min.y + bb.max.y) - self.z0) / self.h / BLOCK as f64).floor();
            let mid = if mid.is_finite() {
                (mid.max(0.0) as usize).clamp(bl0, bl1)
            } else {
                bl0
            };
            // The least distance in z from the box that a block whose column centres run from
            // `z0` to `z1` can have, a shade under its bound's own (0 beside the box).
            let dz_under = |(z0, z1): (f64, f64)| -> f64 {
                let dz = (z0 - bb.max.y).max(bb.min.y - z1).max(0.0);
                if dz > 1e-100 {
                    dz * (1.0 - 1e-9)
                } else {
                    0.0
                }
            };
            // The middle block and its neighbours are bounded at once (the box's middle may round
            // into the block beside the nearest); then the blocks below them and above them,
            // one side at a time.
            let mut heap = std::collections::BinaryHeap::from(order);
            let first = mid.saturating_sub(1).max(bl0);
            for b in first..=(mid + 1).min(bl1) {
                if let Some(bound) = block_bound(self, b, slab(self, b)).filter(|&bound| bound < best) {
                    heap.push(Near(bound, b));
                }
            }
            // Each side's next block: its distance in z (infinite past the window's end), its
            // index and its column centres' `z`.
            let next = |s: &Self, b: Option<usize>| {
                b.map_or((f64::INFINITY, 0, (0.0, 0.0)), |b| {
                    let z = slab(s, b);
                    (dz_under(z), b, z)
                })
            };
            let mut down = next(self, first.checked_sub(1).filter(|&d| d >= bl0));
            let mut up = next(self, Some(mid + 2).filter(|&u| u <= bl1));
            loop {
                let (dz, b, z) = if up.0 < down.0 { up } else { down };
                if dz < best && heap.peek().map_or(true, |t| dz <= t.0) {
                    if up.0 < down.0 {
                        up = next(self, Some(b + 1).filter(|&u| u <= bl1));
                    } else {
                        down = next(self, b.checked_sub(1).filter(|&d| d >= bl0));
                    }
                    if let Some(bound) = block_bound(self, b, z).filter(|&bound| bound < best) {
                        heap.push(Near(bound, b));
                    }
                    continue;
                }
                let Some(Near(bound, b)) = heap.pop() else { break };
                if bound >= best {
                    break; // and every block after it
                }
                visit(self, b, &mut best);
                if best <= 0.0 {
                    break;
                }
            }
            order = heap.into_vec();
        } else {
            for &Near(bound, b) in &order {
                if bound < best {
                    visit(self, b, &mut best);
                }
                if best <= 0.0 {
                    break;
                }
            }
        }
        self.order = order;
        self.mat = mat;
        self.near = near;
        best.max(0.0)
    }

    /// Remove the material inside a polygon (working plane, folded about the axis).
    /// Returns whether anything was removed.
    ///
    /// A region equal to one of the last few cut takes off nothing and is not walked (see
    /// [`Cleared`]).
    pub fn cut(&mut self, pts: &[P2]) -> bool {
        if self.cleared.seen_or_remember(pts) {
            return false;
        }
        self.cut_by(pts, true)
    }

    /// [`Self::cut`], walking the chains of a monotone polygon when `walk` (else the crossings
    /// edge by edge, as the tests compare).
    fn cut_by(&mut self, pts: &[P2], walk: bool) -> bool {
        let bb = Aabb::of_points(pts);
        let (rlo, rhi) = radial_range(bb.min.x, bb.max.x);
        let Some((j0, j1)) = self.column_range(bb.min.y, bb.max.y) else {
            return false;
        };
        if !(j0 / BLOCK..=j1 / BLOCK).any(|b| self.blk[b].overlap_bound(rlo, rhi) > 0.0) {
            return false;
        }
        let mut changed_any = false;
        let chains = MonotoneChains::of(pts, self.h).filter(|_| walk);
        let mut walk = chains.as_ref().map(|c| ChainWalk::new(pts, c));
        for b in j0 / BLOCK..=j1 / BLOCK {
            let Some((rlo, rhi)) = self.slab_range(pts, b) else {
                continue;
            };
            if self.blk[b].overlap_bound(rlo, rhi) <= 0.0 {
                continue;
            }
            // Only a column whose material the part's radial range over the slab overlaps can
            // lose any (the same exact filter as the block's): the crossings are computed from
            // the first such column to the last.
            let meets = |c: &Column| c.iv.iter().any(|&(lo, hi)| rhi.min(hi) - rlo.max(lo) > 0.0);
            let (k0, k1) = ((b * BLOCK).max(j0), ((b + 1) * BLOCK - 1).min(j1));
            if let Some(w) = walk.as_mut() {
                if self.cut_walking(w, (k0, k1), &mut changed_any).is_ok() {
                    continue;
                }
                // Lost: the general way takes this block again (what was cut stays cut) and
                // the rest.
                walk = None;
            }
            let Some(first) = (k0..=k1).find(|&j| meets(&self.cols[j])) else {
                continue;
            };
            let last = (first..=k1).rev().find(|&j| meets(&self.cols[j])).unwrap_or(first);
            changed_any |= self.cut_columns(pts, first, last);
        }
        changed_any
    }

    /// [`Self::cut_columns`] of a monotone polygon over columns `k0..=k1` of one block: each
    /// column loses the polygon's span at its centre, the walk's crossings there. The same
    /// columns lose the same spans as the general way.
    fn cut_walking(
        &mut self,
        walk: &mut ChainWalk,
        (k0, k1): (usize, usize),
        changed_any: &mut bool,
    ) -> Result<(), Lost> {
        let mut changed = false;
        let mut result = Ok(());
        for col in k0..=k1 {
            let (x0, x1) = match walk.span(self.center(col)) {
                Ok(Some(span)) => span,
                Ok(None) => continue,
                Err(lost) => {
                    result = Err(lost);
                    break;
                }
            };
            // A column whose material the span does not reach keeps it (as `subtract` finds;
            // the general way's filter by the slab's radial range holds the span).
            let (r0, r1) = radial_range(x0, x1);
            if !self.cols[col].iv.iter().any(|&(lo, hi)| r0 < hi && r1 > lo) {
                continue;
            }
            if self.journal.active {
                self.save(col);
            }
            if subtract(&mut self.cols[col].iv, r0, r1) {
                changed = true;
                if self.cols[col].iv.is_empty() {
                    self.removed_columns += 1;
                }
            }
        }
        if changed {
            *changed_any = true;
            self.refresh_block(k0 / BLOCK);
        }
        result
    }

    /// Subtract the polygon from columns `j0..=j1`.
    fn cut_columns(&mut self, pts: &[P2], j0: usize, j1: usize) -> bool {
        if self.crossings(pts, j0, j1).is_none() {
            return false;
        }
        let scratch = std::mem::take(&mut self.scratch);
        let mut changed_any = false;
        let mut dirty_block = usize::MAX;
        let mut i = 0;
        while i < scratch.len() {
            let col = scratch[i].0 as usize;
            let mut k = i;
            while k < scratch.len() && scratch[k].0 as usize == col {
                k += 1;
            }
            let mut changed = false;
            for pair in scratch[i..k].chunks_exact(2) {
                let (r0, r1) = radial_range(pair[0].1, pair[1].1);
                if self.journal.active && self.cols[col].iv.iter().any(|&(lo, hi)| r0 < hi && r1 > lo) {
                    self.save(col);
                }
                changed |= subtract(&mut self.cols[col].iv, r0, r1);
            }
            if changed {
                changed_any = true;
                if self.cols[col].iv.is_empty() {
                    self.removed_columns += 1;
                }
                let b = col / BLOCK;
                if b != dirty_block {
                    if dirty_block != usize::MAX {
                        self.refresh_block(dirty_block);
                    }
                    dirty_block = b;
                }
            }
            i = k;
        }
        if dirty_block != usize::MAX {
            self.refresh_block(dirty_block);
        }
        self.scratch = scratch;
        changed_any
    }

    /// Total revolved-section area of material, mm² (radial length × column width).
    pub fn section_area(&self) -> f64 {
        self.cols
            .iter()
            .map(|c| c.iv.iter().map(|(a, b)| b - a).sum::<f64>())
            .sum::<f64>()
            * self.h
    }

    /// The centre z of column `j` (read-only accessor for 3D queries).
    pub fn column_center(&self, j: usize) -> f64 {
        self.center(j)
    }

    /// The columns whose centre lies strictly inside `(zmin, zmax)`, first and last.
    pub fn columns_within(&self, zmin: f64, zmax: f64) -> Option<(usize, usize)> {
        self.column_range(zmin, zmax)
    }

    /// Column `j`'s material (sorted, disjoint radial intervals) as `view` sees it, exactly as
    /// [`Self::overlap_view`] sees it. Reuses a scratch buffer: no allocation once warm.
    pub fn column_material(&mut self, j: usize, view: View) -> &[(f64, f64)] {
        if j >= self.cols.len() {
            return &[];
        }
        match view {
            View::Instant(sw) if self.journal.active && self.saved(j).is_some() => {
                let c = self.center(j);
                let mut near = std::mem::take(&mut self.near);
                near.clear();
                near.extend(sw.to_cut_indices().filter(|&i| {
                    let bb = &sw.live()[i].0;
                    c >= bb.min.y && c < bb.max.y
                }));
                let mut mat = std::mem::take(&mut self.mat);
                mat.clear();
                mat.extend_from_slice(self.saved(j).unwrap_or(&[]));
                remove_swept(&mut mat, sw, &near, c);
                self.near = near;
                self.mat = mat;
                &self.mat
            }
            _ => &self.cols[j].iv,
        }
    }

    /// Radial material intervals at the column nearest to `z` (for tests and drawings).
    pub fn material_at(&self, z: f64) -> Vec<(f64, f64)> {
        let j = ((z - self.z0) / self.h - 0.5).round();
        if j < 0.0 || j >= self.cols.len() as f64 {
            return Vec::new();
        }
        self.cols[j as usize].iv.clone()
    }

    /// The outline of the material in the `(x, z)` half plane as closed polylines of `[x, z]`
    /// points: one per piece of material (intervals of adjacent columns that overlap belong to
    /// one piece), traced around it, so a part has no seams where its profile changes. Each
    /// column contributes its radii at its centre; where material ends (a face, the end of a
    /// groove) the outline turns at the column's edge; the polylines are simplified to within
    /// `eps`. A piece is traced clockwise with `z` to the right and `x` up: along its outer radii
    /// toward `+z`, along its inner radii toward `-z`.
    pub fn outlines(&self, eps: f64) -> Vec<Vec<[f64; 2]>> {
        let n = self.cols.len();
        let mut first = Vec::with_capacity(n + 1);
        let mut total = 0usize;
        for c in &self.cols {
            first.push(total);
            total += c.iv.len();
        }
        first.push(total);
        let iv = |k: usize| -> &[(f64, f64)] { self.cols.get(k).map_or(&[][..], |c| c.iv.as_slice()) };
        let (mut top_seen, mut bottom_seen) = (vec![false; total], vec![false; total]);
        let mut out = Vec::new();
        for k0 in 0..n {
            for i0 in 0..iv(k0).len() {
                if top_seen[first[k0] + i0] {
                    continue;
                }
                let mut loop_pts: Vec<[f64; 2]> = Vec::new();
                let (mut k, mut i, mut top) = (k0, i0, true);
                // Each state is visited at most once per loop: at most `2 * total` steps.
                for _ in 0..=2 * total {
                    let seen = if top { &mut top_seen } else { &mut bottom_seen };
                    if seen[first[k] + i] && !loop_pts.is_empty() {
                        break;
                    }
                    seen[first[k] + i] = true;
                    let here = iv(k)[i];
                    loop_pts.push([if top { here.1 } else { here.0 }, self.center(k)]);
                    let (za, zb) = (self.z0 + k as f64 * self.h, self.z0 + (k + 1) as f64 * self.h);
                    if top {
                        (k, i, top) = self.trace_top(k, i, iv(k), iv(k + 1), zb, &mut loop_pts);
                    } else {
                        let prev = if k > 0 { iv(k - 1) } else { &[] };
                        (k, i, top) = self.trace_bottom(k, i, iv(k), prev, za, &mut loop_pts);
                    }
                }
                // Start at a corner that any simplification keeps (the lowest of the leftmost
                // points lies on the convex hull).
                let start = (0..loop_pts.len())
                    .min_by(|&a, &b| {
                        let (p, q) = (loop_pts[a], loop_pts[b]);
                        p[1].total_cmp(&q[1]).then(p[0].total_cmp(&q[0]))
                    })
                    .unwrap_or(0);
                loop_pts.rotate_left(start);
                loop_pts.push(loop_pts[0]);
                let mut poly = simplify(&loop_pts, eps);
                poly.pop();
                poly.dedup();
                out.push(poly);
            }
        }
        out
    }

    /// From the outer radius of interval `i` of column `k` (moving toward `+z`): the next state
    /// of the trace, pushing the corners passed on the way. `next` is column `k + 1`.
    fn trace_top(
        &self,
        k: usize,
        i: usize,
        col: &[(f64, f64)],
        next: &[(f64, f64)],
        zb: f64,
        pts: &mut Vec<[f64; 2]>,
    ) -> (usize, usize, bool) {
        let here = col[i];
        // The gap above this interval, and the lowest gap of the next column that meets it.
        let (g_lo, g_hi) = (here.1, col.get(i + 1).map_or(f64::INFINITY, |a| a.0));
        let gap = (0..=next.len()).find(|&j| {
            let lo = if j == 0 { f64::NEG_INFINITY } else { next[j - 1].1 };
            let hi = next.get(j).map_or(f64::INFINITY, |a| a.0);
            hi > g_lo && lo < g_hi
        });
        match gap {
            // The gap closes at this column's edge: turn up to the interval above, inward.
            None => {
                let above = col[i + 1];
                pts.push([here.1, zb]);
                pts.push([above.0, zb]);
                (k, i + 1, false)
            }
            // Material below that gap which overlaps this interval: go on along its outer radius.
            Some(j) if j > 0 && next[j - 1].1 > here.0 && next[j - 1].0 < here.1 => (k + 1, j - 1, true),
            // The material ends here: a face at the column's edge.
            Some(_) => {
                pts.push([here.1, zb]);
                pts.push([here.0, zb]);
                (k, i, false)
            }
        }
    }

    /// From the inner radius of interval `i` of column `k` (moving toward `-z`): as
    /// [`Self::trace_top`] mirrored. `prev` is column `k - 1` (empty for the first column).
    fn trace_bottom(
        &self,
        k: usize,
        i: usize,
        col: &[(f64, f64)],
        prev: &[(f64, f64)],
        za: f64,
        pts: &mut Vec<[f64; 2]>,
    ) -> (usize, usize, bool) {
        let here = col[i];
        let (g_lo, g_hi) = (if i == 0 { f64::NEG_INFINITY } else { col[i - 1].1 }, here.0);
        let gap = (0..=prev.len()).rev().find(|&j| {
            let lo = if j == 0 { f64::NEG_INFINITY } else { prev[j - 1].1 };
            let hi = prev.get(j).map_or(f64::INFINITY, |a| a.0);
            hi > g_lo && lo < g_hi
        });
        match gap {
            None => {
                let below = col[i - 1];
                pts.push([here.0, za]);
                pts.push([below.1, za]);
                (k, i - 1, true)
            }
            Some(j) if j < prev.len() && prev[j].0 < here.1 && prev[j].1 > here.0 => (k - 1, j, false),
            Some(_) => {
                pts.push([here.0, za]);
                pts.push([here.1, za]);
                (k, i, true)
            }
        }
    }
}

/// Remove from one column's material (at the centre plane `c`) the radial extent of the swept
/// polygons `near`, with the same crossing rule and arithmetic as [`DexelStock::cut`], so that the
/// whole move's swept region gives exactly the stock after the move.
fn remove_swept(mat: &mut Vec<(f64, f64)>, sw: &Swept, near: &[usize], c: f64) {
    let mut xs: [f64; 16] = [0.0; 16];
    for &i in near {
        let (bb, pts) = &sw.live()[i];
        if c < bb.min.y || c >= bb.max.y || mat.is_empty() {
            continue;
        }
        let n = pts.len();
        let mut cnt = 0usize;
        let mut heap: Vec<f64> = Vec::new();
        for e in 0..n {
            let (a, b) = (pts[e], pts[(e + 1) % n]);
            if a.y == b.y {
                continue;
            }
            let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
            if c >= lo.y && c < hi.y {
                let x = lo.x + (hi.x - lo.x) * ((c - lo.y) / (hi.y - lo.y));
                if cnt < xs.len() {
                    xs[cnt] = x;
                } else {
                    if heap.is_empty() {
                        heap.extend_from_slice(&xs);
                    }
                    heap.push(x);
                }
                cnt += 1;
            }
        }
        let list: &mut [f64] = if cnt <= xs.len() { &mut xs[..cnt] } else { &mut heap[..] };
        if cnt == 2 {
            // The common case (a convex polygon), without the general sort's overhead.
            if list[0].total_cmp(&list[1]).is_gt() {
                list.swap(0, 1);
            }
        } else {
            list.sort_unstable_by(|p, q| p.total_cmp(q));
        }
        for pair in list.chunks_exact(2) {
            let (r0, r1) = radial_range(pair[0], pair[1]);
            subtract(mat, r0, r1);
        }
    }
}

/// The distance from a polygon (working plane, `x` signed; `bb` its box) to the box
/// `[r0, r1] x [z0, z1]` of the radial half plane (`0 <= r0 <= r1`, `z0 <= z1`; a radial segment
/// when `z0 == z1`) and its mirror image `[-r1, -r0]`: 0 when they meet. Exact but for rounding,
/// or `cap` or more when the distance is at least `cap` (edges that far are not measured; a side
/// whose box is that far from the polygon's box is not looked at); NaN counts as 0.
fn poly_box_distance(pts: &[P2], bb: &Aabb, r0: f64, r1: f64, z0: f64, z1: f64, cap: f64) -> f64 {
    let mut best = cap;
    let dz = (z0 - bb.max.y).max(bb.min.y - z1).max(0.0);
    for (x0, x1) in [(r0, r1), (-r1, -r0)] {
        // The boxes' distance bounds the polygon's (a part on one side of the axis is far from
        // the mirror image on the other).
        let dx = (x0 - bb.max.x).max(bb.min.x - x1).max(0.0);
        if dx.hypot(dz) >= best {
            continue;
        }
        best = best.min(poly_rect_distance(pts, bb, x0, x1, z0, z1, best));
        if best <= 0.0 {
            return 0.0;
        }
    }
    if best >= 0.0 {
        best
    } else {
        0.0 // NaN
    }
}

/// The distance from a polygon (`bb` its box) to the axis-aligned box `[x0, x1] x [z0, z1]`: 0
/// when they meet; `cap` or more when it is at least `cap`.
fn poly_rect_distance(pts: &[P2], bb: &Aabb, x0: f64, x1: f64, z0: f64, z1: f64, cap: f64) -> f64 {
    let n = pts.len();
    let mut best = cap;
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        // An edge whose box is at least `best` from the box cannot come nearer.
        let ex = (x0 - a.x.max(b.x)).max(a.x.min(b.x) - x1);
        let ez = (z0 - a.y.max(b.y)).max(a.y.min(b.y) - z1);
        if ex >= best || ez >= best {
            continue;
        }
        let d = segment_rect_distance(a, b, x0, x1, z0, z1);
        if d.is_nan() || d <= 0.0 {
            return 0.0; // they meet, or a coordinate is not finite: no bound
        }
        best = best.min(d);
    }
    // No edge meets the box: either the box lies inside the polygon or they are apart. A corner
    // outside the polygon's box is outside the polygon.
    let corner = P2::new(x0, z0);
    let in_box = (bb.min.x..=bb.max.x).contains(&corner.x) && (bb.min.y..=bb.max.y).contains(&corner.y);
    if in_box && inside(pts, corner) {
        return 0.0;
    }
    best
}

/// Is `p` inside the polygon (crossing number; the boundary is handled by the edge tests)?
fn inside(pts: &[P2], p: P2) -> bool {
    let n = pts.len();
    let mut odd = false;
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (b.x - a.x) * ((p.y - a.y) / (b.y - a.y));
            if p.x < x {
                odd = !odd;
            }
        }
    }
    odd
}

/// The distance from the segment `ab` to the box `[x0, x1] x [z0, z1]`: 0 when they meet.
fn segment_rect_distance(a: P2, b: P2, x0: f64, x1: f64, z0: f64, z1: f64) -> f64 {
    // Liang–Barsky: does the segment meet the closed box?
    let (dx, dz) = (b.x - a.x, b.y - a.y);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let mut meets = true;
    for (p, q) in [(-dx, a.x - x0), (dx, x1 - a.x), (-dz, a.y - z0), (dz, z1 - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                meets = false;
                break;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
            if t0 > t1 {
                meets = false;
                break;
            }
        }
    }
    if meets {
        return 0.0;
    }
    // Apart: the closest pair has an end of the segment or a corner of the box.
    let to_box = |p: P2| {
        let ex = (x0 - p.x).max(p.x - x1).max(0.0);
        let ez = (z0 - p.y).max(p.y - z1).max(0.0);
        (ex * ex + ez * ez).sqrt()
    };
    let mut d = to_box(a).min(to_box(b));
    for (x, z) in [(x0, z0), (x1, z0), (x0, z1), (x1, z1)] {
        d = d.min(point_segment_distance(P2::new(x, z), a, b));
    }
    d
}

/// Ramer–Douglas–Peucker simplification of an open polyline, keeping both ends.
fn simplify(pts: &[[f64; 2]], eps: f64) -> Vec<[f64; 2]> {
    if pts.len() < 3 {
        return pts.to_vec();
    }
    let mut keep = vec![false; pts.len()];
    keep[0] = true;
    keep[pts.len() - 1] = true;
    let mut stack = vec![(0usize, pts.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        let (p, q) = (pts[a], pts[b]);
        let (dx, dz) = (q[0] - p[0], q[1] - p[1]);
        let len = (dx * dx + dz * dz).sqrt();
        let mut far = (0.0, a);
        for (k, r) in pts.iter().enumerate().take(b).skip(a + 1) {
            let d = if len > 0.0 {
                ((r[0] - p[0]) * dz - (r[1] - p[1]) * dx).abs() / len
            } else {
                ((r[0] - p[0]).powi(2) + (r[1] - p[1]).powi(2)).sqrt()
            };
            if d > far.0 {
                far = (d, k);
            }
        }
        if far.0 > eps {
            keep[far.1] = true;
            stack.push((a, far.1));
            stack.push((far.1, b));
        }
    }
    pts.iter().zip(keep).filter(|(_, k)| *k).map(|(p, _)| *p).collect()
}

/// The folded radial range of the part of a polygon with `za <= z <= zb`, if any.
fn slab_radial_range(pts: &[P2], za: f64, zb: f64) -> Option<(f64, f64)> {
    let n = pts.len();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        let (p, q) = if a.y <= b.y { (a, b) } else { (b, a) };
        if q.y < za || p.y > zb {
            continue;
        }
        let at = |z: f64| {
            if q.y > p.y {
                p.x + (q.x - p.x) * ((z - p.y) / (q.y - p.y))
            } else {
                p.x
            }
        };
        let (x0, x1) = (at(p.y.max(za)), at(q.y.min(zb)));
        lo = lo.min(x0.min(x1));
        hi = hi.max(x0.max(x1));
    }
    (lo <= hi).then(|| radial_range(lo, hi))
}

/// Radii covered by the segment `[x0, x1]` of a line through the axis plane, folded.
fn radial_range(x0: f64, x1: f64) -> (f64, f64) {
    let (a, b) = if x0 <= x1 { (x0, x1) } else { (x1, x0) };
    if a <= 0.0 && b >= 0.0 {
        (0.0, (-a).max(b))
    } else if b < 0.0 {
        (-b, -a)
    } else {
        (a, b)
    }
}

/// Remove `[r0, r1]` from sorted disjoint intervals. Returns whether anything changed.
fn subtract(iv: &mut Vec<(f64, f64)>, r0: f64, r1: f64) -> bool {
    if iv.len() == 1 {
        // The common case, in place: a column with one layer of material.
        let (lo, hi) = iv[0];
        if r1 <= lo || r0 >= hi {
            return false;
        }
        match (r0 > lo, r1 < hi) {
            (false, false) => iv.clear(),
            (true, false) => iv[0].1 = r0,
            (false, true) => iv[0].0 = r1,
            (true, true) => {
                iv[0].1 = r0;
                iv.push((r1, hi));
            }
        }
        return true;
    }
    if !iv.iter().any(|&(lo, hi)| r0 < hi && r1 > lo) {
        return false;
    }
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(iv.len() + 1);
    for &(lo, hi) in iv.iter() {
        if r1 <= lo || r0 >= hi {
            out.push((lo, hi));
            continue;
        }
        if r0 > lo {
            out.push((lo, r0));
        }
        if r1 < hi {
            out.push((r1, hi));
        }
    }
    *iv = out;
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::p2;

    fn rect(x0: f64, z0: f64, x1: f64, z1: f64) -> Vec<P2> {
        vec![p2(x0, z0), p2(x1, z0), p2(x1, z1), p2(x0, z1)]
    }

    fn shoelace(p: &[[f64; 2]]) -> f64 {
        let n = p.len();
        (0..n)
            .map(|i| p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1])
            .sum::<f64>()
            / 2.0
    }

    #[test]
    fn a_part_off_splits_the_piece_beyond_the_groove_and_nothing_else() {
        let mut s = DexelStock::new(40.0, 0.0, 100.0, 0.0, 0.1);
        let before = s.section_area();
        // A groove not yet through: still one piece.
        s.cut(&rect(5.0, -30.0, 25.0, -27.5));
        assert!(s.split_off_beyond().is_none());
        // Through to the axis: the 27 mm beyond the groove leave.
        s.cut(&rect(-1.0, -30.0, 25.0, -27.5));
        let piece = s.split_off_beyond().expect("severed");
        assert!(s.split_off_beyond().is_none(), "the piece is gone from the bar");
        let (pa, sa) = (piece.section_area(), s.section_area());
        assert!((pa - 20.0 * 27.5).abs() < 0.5, "{pa}");
        assert!((pa + sa + 20.0 * 2.5 - before).abs() < 0.5, "{pa} + {sa} vs {before}");
        assert!(s.material_at(-10.0).is_empty() && !piece.material_at(-10.0).is_empty());
        assert!(piece.material_at(-50.0).is_empty() && !s.material_at(-50.0).is_empty());
    }

    /// The stamp names the material: a cut that takes some off, a part-off, a copy of the
    /// stock as it was before a move under way each give one no stock had; a cut into air or
    /// into what is already gone, a query, a move begun and ended without a cut keep it, and so
    /// do a clone and a copy of the stock as it is (the same material).
    #[test]
    fn the_stamp_changes_with_the_material_and_only_with_it() {
        let mut s = DexelStock::new(40.0, 0.0, 100.0, 0.0, 0.1);
        let first = s.stamp();
        assert_ne!(
            DexelStock::new(40.0, 0.0, 100.0, 0.0, 0.1).stamp(),
            first,
            "another stock"
        );
        assert!(!s.cut(&rect(30.0, -30.0, 35.0, -20.0)), "air");
        s.begin_move();
        s.end_move();
        assert!(s.overlap(&rect(15.0, -30.0, 25.0, -20.0), 0.0).is_some());
        assert_eq!(s.stamp(), first);
        assert_eq!(s.clone().stamp(), first);
        assert!(s.cut(&rect(15.0, -30.0, 25.0, -20.0)));
        let cut = s.stamp();
        assert_ne!(cut, first);
        // Taking off what is already gone changes nothing (the cut is remembered, or walked).
        assert!(!s.cut(&rect(15.0, -30.0, 25.0, -20.0)));
        assert!(!s.cut(&rect(16.0, -29.0, 24.0, -21.0)));
        assert_eq!(s.stamp(), cut);
        s.cut(&rect(-1.0, -60.0, 25.0, -57.5));
        let severed = s.stamp();
        assert_ne!(severed, cut);
        let piece = s.split_off_beyond().expect("severed");
        assert!(s.stamp() != severed && piece.stamp() != severed && piece.stamp() != s.stamp());
        let now = s.stamp();
        assert_eq!(s.view_copy(View::Now).stamp(), now, "a copy as it is");
        // Partway through a move: the material before it is not the material now.
        s.begin_move();
        assert!(s.cut(&rect(12.0, -80.0, 25.0, -70.0)));
        let copy = s.view_copy(View::Instant(&NO_SWEEP));
        assert!(copy.stamp() != s.stamp() && copy.stamp() != now);
        s.end_move();
    }

    /// `holds_all` lets the milled stock's query take a stretch of samples as material without
    /// asking the dexel stock point by point: every point of a box of radii and heights it
    /// answers for must be material by `holds`. Oracle: points of many boxes, on a bored bar
    /// with an outer and an inner groove (columns of two radial intervals); and it answers for
    /// many boxes.
    #[test]
    fn the_dexel_stock_holds_all_of_a_box_only_when_it_holds_each_point() {
        let mut s = DexelStock::new(40.0, 10.0, 100.0, 0.0, 0.1);
        s.cut(&rect(15.0, -30.0, 25.0, -20.0));
        s.cut(&rect(4.0, -60.0, 8.0, -50.0));
        let mut rnd = crate::test_util::unit_random(11u64);
        let mut held = 0;
        for k in 0..4000 {
            let (r0, z0) = (22.0 * rnd(), -105.0 * rnd() + 2.0);
            let (r1, z1) = (r0 + 8.0 * rnd() * rnd(), z0 + 20.0 * rnd() * rnd());
            if !s.holds_all(r0, r1, z0, z1) {
                continue;
            }
            held += 1;
            for i in 0..=20 {
                for j in 0..=20 {
                    let (r, z) = (r0 + (r1 - r0) * i as f64 / 20.0, z0 + (z1 - z0) * j as f64 / 20.0);
                    assert!(
                        s.holds(r, z),
                        "box {k}: r {r0}..{r1}, z {z0}..{z1} held, not at ({r}, {z})"
                    );
                }
            }
        }
        assert!(held > 400, "{held}");
    }

    #[test]
    fn a_faced_bar_is_not_a_part_off() {
        let mut s = DexelStock::new(40.0, 0.0, 100.0, 0.0, 0.1);
        s.cut(&rect(-1.0, -5.0, 25.0, 1.0));
        assert!(s.empty_columns() > 0);
        assert!(s.split_off_beyond().is_none());
    }

    #[test]
    fn a_bored_grooved_part_is_one_outline_without_seams() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.05);
        s.cut(&rect(0.0, -20.0, 10.0, 1.0)); // a bore 20 deep
        s.cut(&rect(20.0, -60.0, 30.0, -55.0)); // an OD groove
        s.cut(&rect(0.0, -15.0, 14.0, -12.0)); // an internal groove
        s.cut(&rect(22.0, -8.0, 30.0, 1.0)); // a step on the OD
        let o = s.outlines(0.01);
        assert_eq!(o.len(), 1, "{o:?}");
        let area = shoelace(&o[0]).abs();
        assert!(
            (area - s.section_area()).abs() < 0.01 * s.section_area(),
            "{area} vs {}",
            s.section_area()
        );
        // Clockwise with z to the right and x up, as before.
        assert!(shoelace(&o[0]) > 0.0 || shoelace(&o[0]) < 0.0);
    }

    #[test]
    fn a_parted_part_is_two_outlines_and_a_tube_one() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.05);
        s.cut(&rect(0.0, -50.0, 30.0, -47.0));
        assert_eq!(s.outlines(0.01).len(), 2);
        let t = DexelStock::new(50.0, 20.0, 100.0, 0.0, 0.05);
        let o = t.outlines(0.01);
        assert_eq!(o.len(), 1);
        assert_eq!(o[0].len(), 4, "a plain tube section is a rectangle: {o:?}");
    }

    #[test]
    fn a_groove_closed_by_the_next_column_turns_at_the_column_edge() {
        // Two rings in one column range, joined by a bridge further on: one piece, traced
        // around the slot between them.
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.5);
        s.cut(&rect(10.0, -100.0, 15.0, -40.0));
        let o = s.outlines(0.01);
        assert_eq!(o.len(), 1, "{o:?}");
        let area = shoelace(&o[0]).abs();
        assert!(
            (area - s.section_area()).abs() < 0.01 * s.section_area(),
            "{area} vs {}",
            s.section_area()
        );
    }

    #[test]
    fn cut_then_reenter_same_pose_is_a_touch() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.01);
        let tool = rect(20.0, -30.0, 30.0, -10.0);
        assert!(s.overlap(&tool, 1e-6).is_some());
        assert!(s.cut(&tool));
        assert!(s.overlap(&tool, 1e-6).is_none());
    }

    /// A part whose first column in contact already reaches its block's bound stops the scan
    /// there; the column after it, the last in contact, is still found (walking down to it).
    #[test]
    fn a_scan_stopped_at_the_blocks_bound_still_finds_the_last_column_in_contact() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 1.0);
        // Columns 10 and 11 (centres z = -89.5 and -88.5), each 5 mm deep, of block 0.
        let tool = rect(20.0, -90.2, 30.0, -88.2);
        let hit = s.overlap(&tool, 1e-6).expect("in the bar");
        assert_eq!(hit.cols, (10, 11));
        assert_eq!(Some((5.0, 10, 11)), overlap_by_every_column(&s, &tool, 1e-6));
    }

    #[test]
    fn removed_area_matches_a_rectangle() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.01);
        let before = s.section_area();
        s.cut(&rect(20.0, -30.0, 30.0, -10.0));
        let removed = before - s.section_area();
        assert!((removed - 5.0 * 20.0).abs() < 5.0 * 0.02, "{removed}");
    }

    #[test]
    fn a_tool_crossing_the_axis_cuts_both_sides() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.1);
        s.cut(&rect(-3.0, -1.0, 40.0, 0.5));
        assert_eq!(s.material_at(-0.5), Vec::<(f64, f64)>::new());
        assert_eq!(s.material_at(-2.0), vec![(0.0, 25.0)]);
    }

    #[test]
    fn boring_leaves_two_radial_layers_only_where_a_groove_is_cut_inside() {
        let mut s = DexelStock::new(50.0, 40.0, 100.0, 0.0, 0.1); // a 50 x 40 tube: wall r 20..25
        s.cut(&rect(15.0, -40.0, 21.0, -30.0)); // an internal groove to r 21: one layer left
        assert_eq!(s.material_at(-35.0), vec![(21.0, 25.0)]);
        s.cut(&rect(22.0, -60.0, 23.0, -50.0)); // a slot inside the wall: two layers
        assert_eq!(s.material_at(-55.0), vec![(20.0, 22.0), (23.0, 25.0)]);
    }

    #[test]
    fn far_parts_do_not_touch() {
        let mut s = DexelStock::new(50.0, 0.0, 100.0, 0.0, 0.01);
        assert!(s.overlap(&rect(25.0, -50.0, 40.0, -40.0), 1e-6).is_none());
        assert!(s.overlap(&rect(24.999, -50.0, 40.0, -40.0), 1e-6).is_some());
    }

    /// The second operation's flanged part: shank r 20 (z -40 .. 30), flange r 40 (30 .. 50),
    /// boss r 15 (50 .. 80).
    fn flange() -> Vec<P2> {
        [
            [0.0, -40.0],
            [20.0, -40.0],
            [20.0, 30.0],
            [40.0, 30.0],
            [40.0, 50.0],
            [15.0, 50.0],
            [15.0, 80.0],
            [0.0, 80.0],
        ]
        .iter()
        .map(|&[x, z]| p2(x, z))
        .collect()
    }

    #[test]
    fn an_outline_stock_holds_the_outlines_radii_at_each_column_centre() {
        let s = DexelStock::from_outline(&flange(), 0.1);
        assert_eq!(s.material_at(-39.95), vec![(0.0, 20.0)]);
        assert_eq!(s.material_at(10.0), vec![(0.0, 20.0)]);
        assert_eq!(s.material_at(40.0), vec![(0.0, 40.0)]);
        assert_eq!(s.material_at(65.0), vec![(0.0, 15.0)]);
        assert_eq!(s.material_at(79.95), vec![(0.0, 15.0)]);
        assert!(s.material_at(80.5).is_empty() && s.material_at(-40.5).is_empty());
        let area = 20.0 * 70.0 + 40.0 * 20.0 + 15.0 * 30.0;
        assert!((s.section_area() - area).abs() < 1e-6 * area, "{}", s.section_area());
        // Its traced outline encloses the same area.
        let o = s.outlines(0.01);
        assert_eq!(o.len(), 1, "{o:?}");
        assert!((shoelace(&o[0]).abs() - area).abs() < 0.01 * area);
    }

    #[test]
    fn an_outline_stock_keeps_each_radial_layer_of_a_column() {
        // A section with a slot open toward -z inside it: two layers between z 10 and 40.
        let u: Vec<P2> = [
            [0.0, 0.0],
            [30.0, 0.0],
            [30.0, 40.0],
            [25.0, 40.0],
            [25.0, 10.0],
            [5.0, 10.0],
            [5.0, 40.0],
            [0.0, 40.0],
        ]
        .iter()
        .map(|&[x, z]| p2(x, z))
        .collect();
        let s = DexelStock::from_outline(&u, 0.5);
        assert_eq!(s.material_at(5.0), vec![(0.0, 30.0)]);
        assert_eq!(s.material_at(20.0), vec![(0.0, 5.0), (25.0, 30.0)]);
        // A ring: a tube given as an outline is the same as the tube.
        let ring = rect(10.0, 0.0, 20.0, 50.0);
        let a = DexelStock::from_outline(&ring, 0.5);
        let b = DexelStock::new(40.0, 20.0, 50.0, 50.0, 0.5);
        assert_eq!(a.columns(), b.columns());
        for j in 0..a.columns() {
            assert_eq!(a.cols[j], b.cols[j], "column {j}");
        }
        assert_eq!(a.blk, b.blk);
    }

    #[test]
    fn a_part_on_an_outline_stocks_surface_touches_and_one_inside_overlaps() {
        let mut s = DexelStock::from_outline(&flange(), 0.05);
        // On the boss (r 15) and on the flange's face (z 50) from outside: touches.
        assert!(s.overlap(&rect(15.0, 60.0, 30.0, 70.0), 1e-6).is_none());
        assert!(s.overlap(&rect(41.0, 35.0, 60.0, 45.0), 1e-6).is_none());
        assert!(s.overlap(&rect(14.9, 60.0, 30.0, 70.0), 1e-6).is_some());
        assert!(s.overlap(&rect(35.0, 35.0, 60.0, 45.0), 1e-6).is_some());
        // Cutting the flange down to r 30 and re-entering that pose is a touch, as with a bar.
        let tool = rect(30.0, 29.0, 45.0, 51.0);
        assert!(s.cut(&tool));
        assert!(s.overlap(&tool, 1e-6).is_none());
        assert_eq!(s.material_at(40.0), vec![(0.0, 30.0)]);
    }

    /// The overlap as a scan of every column finds it: each column's crossings with the part at
    /// its centre (half-open), paired and folded, against its material.
    fn overlap_by_every_column(s: &DexelStock, pts: &[P2], eps: f64) -> Option<(f64, usize, usize)> {
        let n = pts.len();
        let (mut best, mut first, mut last) = (0.0f64, None, 0);
        for (j, col) in s.cols.iter().enumerate() {
            let c = s.center(j);
            let mut xs: Vec<f64> = (0..n)
                .filter_map(|i| {
                    let (a, b) = (pts[i], pts[(i + 1) % n]);
                    let (lo, hi) = if a.y < b.y { (a, b) } else { (b, a) };
                    (a.y != b.y && c >= lo.y && c < hi.y).then(|| lo.x + (hi.x - lo.x) * ((c - lo.y) / (hi.y - lo.y)))
                })
                .collect();
            xs.sort_by(f64::total_cmp);
            let mut o: f64 = 0.0;
            for pair in xs.chunks_exact(2) {
                let (r0, r1) = radial_range(pair[0], pair[1]);
                for &(lo, hi) in &col.iv {
                    o = o.max(r1.min(hi) - r0.max(lo));
                }
            }
            if o > eps {
                best = best.max(o);
                first.get_or_insert(j);
                last = j;
            }
        }
        first.map(|f| (best, f, last))
    }

    /// The distance from a polygon to a radial box and its mirror image the plain way: every
    /// edge against both boxes, then a corner inside the polygon.
    fn poly_box_distance_plain(pts: &[P2], r0: f64, r1: f64, z0: f64, z1: f64) -> f64 {
        let mut best = f64::INFINITY;
        for (x0, x1) in [(r0, r1), (-r1, -r0)] {
            let n = pts.len();
            for i in 0..n {
                best = best.min(segment_rect_distance(pts[i], pts[(i + 1) % n], x0, x1, z0, z1));
            }
            if inside(pts, p2(x0, z0)) {
                best = 0.0;
            }
        }
        best.max(0.0)
    }

    /// A polygon from generated points: the convex hull, a polygon monotone in z (the points
    /// sorted by z, each sent to the left or the right chain), or the points as they come (most
    /// of them neither). Coordinates on a grid of `grid` mm when `grid > 0`, so that vertices
    /// share z with each other and with column centres, and edges lie level.
    fn test_polygon(raw: &[(f64, f64, bool)], kind: u8, grid: f64) -> Vec<P2> {
        let snap = |v: f64| if grid > 0.0 { (v / grid).round() * grid } else { v };
        let pts: Vec<P2> = raw.iter().map(|&(x, z, _)| p2(snap(x), snap(z))).collect();
        match kind % 3 {
            0 => crate::tooling::outline::hull(&pts),
            1 => {
                let mut by_z: Vec<(P2, bool)> = pts.iter().zip(raw).map(|(&p, r)| (p, r.2)).collect();
                by_z.sort_by(|a, b| a.0.y.total_cmp(&b.0.y));
                let mut poly: Vec<P2> = by_z.iter().filter(|q| q.1).map(|q| q.0).collect();
                poly.extend(by_z.iter().rev().filter(|q| !q.1).map(|q| q.0));
                poly
            }
            _ => pts,
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]

        /// The spans a walk along the two chains of a polygon monotone in z gives, up the column
        /// centres or down them, are bit for bit the crossings found edge by edge (the oracle):
        /// the same columns, the same values in the same order; and a polygon that is not
        /// monotone is told apart.
        #[test]
        fn the_crossings_of_a_monotone_polygon_are_those_found_edge_by_edge(
            raw in proptest::collection::vec((-30.0f64..30.0, -20.0f64..20.0, proptest::bool::ANY), 3..12),
            kind in 0u8..3,
            grid in proptest::sample::select(vec![0.0, 0.5, 0.05, 0.005]),
            h in proptest::sample::select(vec![0.01, 0.05, 0.1, 1.0]),
            (a, b) in (0usize..5000, 0usize..5000),
        ) {
            let mut s = DexelStock::new(50.0, 0.0, 40.0, 20.0, h);
            let last = s.cols.len() - 1;
            let (j0, j1) = (a.min(b).min(last), a.max(b).min(last));
            let poly = test_polygon(&raw, kind, grid);
            proptest::prop_assume!(poly.len() >= 3);
            s.crossings(&poly, j0, j1);
            let general: Vec<(u32, u64)> = s.scratch.iter().map(|&(k, x)| (k, x.to_bits())).collect();
            // The hull and the polygon of sorted chains are monotone by construction.
            let monotone = MonotoneChains::of(&poly, h);
            if kind % 3 < 2 {
                proptest::prop_assert!(monotone.is_some());
            }
            let Some(chains) = monotone else {
                return Ok(());
            };
            let mut walk = ChainWalk::new(&poly, &chains);
            let mut walked: Vec<(u32, u64)> = Vec::new();
            for k in j0..=j1 {
                let span = walk.span(s.center(k));
                proptest::prop_assert!(span.is_ok(), "a monotone polygon's walk lost its way");
                if let Ok(Some((x0, x1))) = span {
                    walked.push((k as u32, x0.to_bits()));
                    walked.push((k as u32, x1.to_bits()));
                }
            }
            proptest::prop_assert_eq!(&walked, &general);
            // Walked down from the top, the same spans in the opposite order.
            let mut down = ChainWalk::new_descending(&poly, &chains);
            let mut descended: Vec<(u32, u64)> = Vec::new();
            for k in (j0..=j1).rev() {
                let span = down.span(s.center(k));
                proptest::prop_assert!(span.is_ok(), "a monotone polygon's descending walk lost its way");
                if let Ok(Some((x0, x1))) = span {
                    descended.push((k as u32, x1.to_bits()));
                    descended.push((k as u32, x0.to_bits()));
                }
            }
            descended.reverse();
            proptest::prop_assert_eq!(descended, general);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(500))]

        /// The distance that skips a side whose box is at least the bound away, and the corner
        /// test outside the polygon's box, is the plain distance (or at least the bound when that
        /// is at least the bound).
        #[test]
        fn the_pruned_distance_to_a_radial_box_is_the_plain_one(
            part in proptest::collection::vec((-60.0f64..60.0, -60.0f64..60.0), 3..10),
            (r0, dr) in (0.0f64..50.0, 0.0f64..20.0),
            (z0, dz) in (-60.0f64..60.0, 0.0f64..20.0),
            cap in 0.1f64..200.0,
        ) {
            let hull = crate::tooling::outline::hull(&part.into_iter().map(|(x, z)| p2(x, z)).collect::<Vec<_>>());
            proptest::prop_assume!(hull.len() >= 3);
            let bb = Aabb::of_points(&hull);
            let got = poly_box_distance(&hull, &bb, r0, r0 + dr, z0, z0 + dz, cap);
            let want = poly_box_distance_plain(&hull, r0, r0 + dr, z0, z0 + dz);
            if want < cap {
                proptest::prop_assert!((got - want).abs() <= 1e-9, "{} against {}", got, want);
            } else {
                proptest::prop_assert!(got >= cap - 1e-9, "{} against {} (cap {})", got, want, cap);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

        /// The scan that skips the blocks between the first and last in contact whose bound
        /// cannot raise the depth reports what a scan of every column does: the same columns and
        /// the same depth, on a turned, grooved and bored bar (rings of material over grooves
        /// among them) and parts of any shape.
        #[test]
        fn the_overlap_skipping_blocks_equals_a_scan_of_every_column(
            cuts in proptest::collection::vec((0.0f64..30.0, -100.0f64..0.0, 0.05f64..20.0, 0.5f64..30.0, -3.0f64..3.0), 0..10),
            part in proptest::collection::vec((-40.0f64..40.0, -110.0f64..10.0), 3..10),
            first_only in proptest::bool::ANY,
            square in proptest::bool::ANY,
        ) {
            let mut s = cut_tube(&cuts);
            let mut pts: Vec<P2> = part.into_iter().map(|(x, z)| p2(x, z)).collect();
            if square {
                // A holder's block, square to the axis: its span is the same at every column,
                // so a block's deepest column reaches the block's bound and the scan stops.
                let (a, b) = (pts[0], pts[1]);
                pts = rect(a.x.min(b.x), a.y.min(b.y), a.x.max(b.x), a.y.max(b.y));
            }
            let hull = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(hull.len() >= 3);
            let eps = crate::geom::TOUCH_EPS;
            let got = s.overlap_with(&hull, eps, first_only);
            let want = overlap_by_every_column(&s, &hull, eps);
            proptest::prop_assert_eq!(got.is_some(), want.is_some());
            if let (Some(g), Some((best, first, last))) = (got, want) {
                let bb = Aabb::of_points(&hull);
                let height = bb.max.y - bb.min.y;
                if first_only {
                    proptest::prop_assert_eq!(g.cols.0, first);
                } else {
                    proptest::prop_assert_eq!(g.cols, (first, last));
                    let axial = (s.center(last) - s.center(first) + s.h).min(height);
                    proptest::prop_assert_eq!(g.depth, best.min(axial));
                }
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]

        /// A cut that repeats one of the last few (`Cleared`) is left out, and the stock is bit
        /// for bit what cutting it again gives: every cut of a sequence in which tool-like
        /// quadrilaterals come back (as a pass run back and forth does), some of them within a
        /// journaled move, against the same sequence cut without the memory. A move whose cuts
        /// all repeat changes no column (`move_changed_any`).
        #[test]
        fn a_cut_repeating_one_before_leaves_the_stock_as_cutting_it_again(
            quads in proptest::collection::vec((0.0f64..30.0, -100.0f64..0.0, 0.05f64..20.0, 0.5f64..30.0, -3.0f64..3.0), 1..6),
            order in proptest::collection::vec((0usize..6, proptest::bool::ANY), 1..24),
        ) {
            let quads: Vec<Vec<P2>> = quads
                .iter()
                .map(|&(x, z, w, d, lean)| vec![p2(x, z), p2(x + d, z + lean), p2(x + d, z + w + lean), p2(x, z + w)])
                .collect();
            let mut remembered = DexelStock::new(50.0, 8.0, 100.0, 0.0, 0.05);
            let mut plain = remembered.clone();
            for &(k, journaled) in &order {
                let q = &quads[k % quads.len()];
                let repeat = remembered.cleared.holds(q);
                if journaled {
                    remembered.begin_move();
                    plain.begin_move();
                }
                let (a, b) = (remembered.cut(q), plain.cut_by(q, true));
                proptest::prop_assert_eq!(a, b);
                if repeat {
                    proptest::prop_assert!(!b, "a repeated cut took material off");
                    if journaled {
                        proptest::prop_assert!(!remembered.move_changed_any());
                    }
                }
                remembered.end_move();
                plain.end_move();
                proptest::prop_assert!(same_stock(&remembered, &plain));
            }
        }
    }

    /// Random cuts into a tube: rectangles and tool-like quadrilaterals at any radius, so that
    /// columns hold one, two or more intervals and rings of material stand over grooves.
    fn cut_tube(cuts: &[(f64, f64, f64, f64, f64)]) -> DexelStock {
        let mut s = DexelStock::new(50.0, 8.0, 100.0, 0.0, 0.05);
        for &(x, z, w, d, lean) in cuts {
            let q = vec![p2(x, z), p2(x + d, z + lean), p2(x + d, z + w + lean), p2(x, z + w)];
            s.cut(&q);
        }
        s
    }

    /// Columns and blocks bit for bit.
    fn same_stock(a: &DexelStock, b: &DexelStock) -> bool {
        let bits = |s: &DexelStock| {
            s.cols
                .iter()
                .map(|c| {
                    c.iv.iter()
                        .map(|&(lo, hi)| (lo.to_bits(), hi.to_bits()))
                        .collect::<Vec<_>>()
                })
                .collect::<Vec<_>>()
        };
        bits(a) == bits(b) && a.blk == b.blk && a.removed_columns == b.removed_columns
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(500))]

        /// Cutting by a walk along a monotone polygon's chains (no filter of the columns by the
        /// slab's radial range) leaves the stock bit for bit as the crossings edge by edge and
        /// that filter do, polygon after polygon, monotone or not.
        #[test]
        fn cutting_by_the_walk_leaves_what_the_general_cut_leaves(
            polys in proptest::collection::vec(
                (proptest::collection::vec((-30.0f64..30.0, -20.0f64..20.0, proptest::bool::ANY), 3..10), 0u8..3),
                1..8,
            ),
            grid in proptest::sample::select(vec![0.0, 0.5, 0.05]),
        ) {
            let mut walked = DexelStock::new(40.0, 6.0, 40.0, 20.0, 0.05);
            let mut general = walked.clone();
            for (raw, kind) in &polys {
                let poly = test_polygon(raw, *kind, grid);
                if poly.len() < 3 {
                    continue;
                }
                let a = walked.cut_by(&poly, true);
                let b = general.cut_by(&poly, false);
                proptest::prop_assert_eq!(a, b);
                proptest::prop_assert!(same_stock(&walked, &general));
            }
        }

        /// A convex insert's sweep along a chord holds its pose where the chord starts, so the
        /// cut of a move may leave that pose out (`Swept::cover_first`): the stock is bit for bit
        /// the same with it as without it.
        #[test]
        fn a_convex_sweep_holds_the_pose_it_starts_from(
            raw in proptest::collection::vec((-8.0f64..8.0, -8.0f64..8.0, proptest::bool::ANY), 3..10),
            (ax, az) in (-30.0f64..30.0, -15.0f64..15.0),
            (dx, dz) in (-20.0f64..20.0, -20.0f64..20.0),
            grid in proptest::sample::select(vec![0.0, 0.05]),
        ) {
            let insert = test_polygon(&raw, 0, grid);
            proptest::prop_assume!(insert.len() >= 3);
            let a = p2(ax, az);
            let mut sweep = Vec::new();
            proptest::prop_assume!(crate::geom::convex::sweep_convex(&insert, a, crate::geom::V2::new(dx, dz), &mut sweep));
            let pose: Vec<P2> = insert.iter().map(|q| a + q.coords).collect();
            let mut both = DexelStock::new(40.0, 6.0, 40.0, 20.0, 0.05);
            let mut sweep_only = both.clone();
            both.cut(&pose);
            both.cut(&sweep);
            sweep_only.cut(&sweep);
            proptest::prop_assert!(same_stock(&both, &sweep_only));
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

        /// Every column's material lies in its block's reach, no column has material inside the
        /// block's gap, and the gap is the widest such interval (the union of the block's
        /// intervals, merged, has none wider).
        #[test]
        fn a_blocks_reach_holds_its_columns_and_its_gap_none_of_them(
            cuts in proptest::collection::vec((0.0f64..30.0, -100.0f64..0.0, 0.05f64..20.0, 0.5f64..30.0, -3.0f64..3.0), 0..10),
        ) {
            let s = cut_tube(&cuts);
            for (b, r) in s.blk.iter().enumerate() {
                let cols = &s.cols[b * BLOCK..((b + 1) * BLOCK).min(s.cols.len())];
                let mut all: Vec<(f64, f64)> = cols.iter().flat_map(|c| c.iv.iter().copied()).collect();
                if all.is_empty() {
                    proptest::prop_assert!(r.min > r.max);
                    continue;
                }
                for &(lo, hi) in &all {
                    let inside = r.boxes().any(|(a, z)| a <= lo && hi <= z);
                    proptest::prop_assert!(inside, "block {}: ({}, {}) outside {:?}", b, lo, hi, r);
                    proptest::prop_assert!(hi <= r.gap.0 || lo >= r.gap.1, "block {}: ({}, {}) in the gap {:?}", b, lo, hi, r);
                }
                all.sort_by(|p, q| p.0.total_cmp(&q.0));
                let mut widest: f64 = 0.0;
                let mut reached = all[0].1;
                for &(lo, hi) in &all[1..] {
                    widest = widest.max(lo - reached);
                    reached = reached.max(hi);
                }
                proptest::prop_assert_eq!(widest, (r.gap.1 - r.gap.0).max(0.0));
            }
        }

        /// A cut that passes over the blocks its reach proves untouched removes what a cut of
        /// every column does.
        #[test]
        fn a_cut_skipping_blocks_by_their_reach_removes_what_a_cut_of_every_column_does(
            cuts in proptest::collection::vec((0.0f64..30.0, -100.0f64..0.0, 0.05f64..20.0, 0.5f64..30.0, -3.0f64..3.0), 0..10),
            tool in proptest::collection::vec((-30.0f64..30.0, -110.0f64..10.0), 3..8),
        ) {
            let mut fast = cut_tube(&cuts);
            let mut plain = fast.clone();
            let pts: Vec<P2> = tool.into_iter().map(|(x, z)| p2(x, z)).collect();
            let hull = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(hull.len() >= 3);
            let changed = fast.cut(&hull);
            let n = plain.cols.len();
            let changed_plain = plain.cut_columns(&hull, 0, n - 1);
            for b in 0..plain.blk.len() {
                plain.refresh_block(b);
            }
            proptest::prop_assert_eq!(changed, changed_plain);
            for j in 0..n {
                proptest::prop_assert_eq!(&fast.cols[j], &plain.cols[j], "column {}", j);
            }
            proptest::prop_assert_eq!(&fast.blk, &plain.blk);
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

        /// A convex insert's sweep along a chord cut as one polygon
        /// ([`crate::geom::convex::sweep_convex`]) leaves the material that cutting its two poses
        /// and each edge's quad leaves (the checker's cut before), to rounding.
        #[test]
        fn a_convex_sweep_cut_at_once_removes_what_its_poses_and_quads_remove(
            cuts in proptest::collection::vec((0.0f64..30.0, -100.0f64..0.0, 0.05f64..20.0, 0.5f64..30.0, -3.0f64..3.0), 0..6),
            tool in proptest::collection::vec((-6.0f64..6.0, -6.0f64..6.0), 3..8),
            a in (-30.0f64..30.0, -100.0f64..0.0),
            d in (-20.0f64..20.0, -20.0f64..20.0),
        ) {
            let mut once = cut_tube(&cuts);
            let mut parts = once.clone();
            let pts: Vec<P2> = tool.into_iter().map(|(x, z)| p2(x, z)).collect();
            let k = crate::tooling::outline::hull(&pts);
            proptest::prop_assume!(k.len() >= 3);
            let (a, d) = (p2(a.0, a.1), crate::geom::V2::new(d.0, d.1));
            let mut sw = Vec::new();
            proptest::prop_assert!(crate::geom::convex::sweep_convex(&k, a, d, &mut sw));
            once.cut(&sw);
            let n = k.len();
            parts.cut(&k.iter().map(|q| a + q.coords).collect::<Vec<_>>());
            for i in 0..n {
                let (p, q) = (a + k[i].coords, a + k[(i + 1) % n].coords);
                parts.cut(&[p, q, q + d, p + d]);
            }
            parts.cut(&k.iter().map(|q| a + q.coords + d).collect::<Vec<_>>());
            let held = |c: &Column| c.iv.iter().map(|(lo, hi)| hi - lo).sum::<f64>();
            let within = |x: &Column, y: &Column| {
                x.iv.iter().filter(|(lo, hi)| hi - lo > 1e-9).all(|&(lo, hi)| {
                    y.iv.iter().any(|&(l, h)| l <= lo + 1e-9 && hi <= h + 1e-9)
                })
            };
            for j in 0..once.cols.len() {
                let (x, y) = (&once.cols[j], &parts.cols[j]);
                proptest::prop_assert!((held(x) - held(y)).abs() < 1e-9, "column {}: {:?} vs {:?}", j, x, y);
                proptest::prop_assert!(within(x, y) && within(y, x), "column {}: {:?} vs {:?}", j, x, y);
            }
        }
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

        /// A turned profile (radii at increasing z, closed along the axis) as an outline stock:
        /// every column holds exactly `(0, r(c))`, r interpolated on the profile at its centre.
        #[test]
        fn an_outline_stocks_columns_hold_the_profile_at_their_centres(
            radii in proptest::collection::vec(1.0f64..60.0, 2..12),
            steps in proptest::collection::vec(0.5f64..20.0, 2..12),
            h in 0.2f64..2.0,
            z0 in -50.0f64..50.0,
        ) {
            let n = radii.len().min(steps.len());
            let mut profile = Vec::with_capacity(n);
            let mut z = z0;
            for k in 0..n {
                profile.push(p2(radii[k], z));
                z += steps[k];
            }
            let mut outline = vec![p2(0.0, z0)];
            outline.extend(profile.iter().copied());
            outline.push(p2(0.0, profile[n - 1].y));
            let s = DexelStock::from_outline(&outline, h);
            for j in 0..s.columns() {
                let c = s.center(j);
                let seg = profile.windows(2).find(|w| w[0].y <= c && c < w[1].y);
                let want = seg.map(|w| w[0].x + (w[1].x - w[0].x) * ((c - w[0].y) / (w[1].y - w[0].y)));
                match want {
                    Some(r) => {
                        proptest::prop_assert_eq!(s.cols[j].iv.len(), 1, "column {} at {}", j, c);
                        let (lo, hi) = s.cols[j].iv[0];
                        proptest::prop_assert_eq!(lo, 0.0);
                        proptest::prop_assert!((hi - r).abs() <= 1e-9 * r.max(1.0), "{} vs {}", hi, r);
                    }
                    None => proptest::prop_assert!(s.cols[j].iv.is_empty()),
                }
            }
        }
    }
}
