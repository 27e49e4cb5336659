//! The shoulder scrape: a rapid retract that rubs the wedge the tool's own edge just left.
//!
//! A turning tool whose leading edge leans back from the feed (a 95° or 93° holder: the edge
//! runs a few degrees past square to the feed) leaves the shoulder it turns up to at that lean:
//! a thin wedge of material under the edge. A rapid straight out of the cut (`G1 Z-30.` then
//! `G0 X52.`) drags the edge over that wedge: real contact, a few tenths of a millimetre deep,
//! and no crash. Such a contact is reported as `rapid_scrape` (a warning) instead of
//! `rapid_into_stock` when every one of these holds (docs/findings/rapid_scrape.md):
//!
//! 1. the rapid directly follows (dwells aside) a feed move of the same tool that cut material;
//! 2. the insert is in the material from the rapid's start: its contact begins within
//!    [`START_MM`] of travel and is one interval that ends before the rapid does;
//! 3. throughout that interval, the insert meets material only in columns the feed's cut
//!    changed, the holder meets none, the rapid has moved away from the surface the feed's path
//!    traced (its displacement points to the insert's side of the feed's last direction), and
//!    the depth stays within the lean bound: at most `s·tan(LEAN_DEG) + 2h` after a travel `s`
//!    (`h` the stock's column width) and never more than [`MAX_MM`].
//!
//! A rapid into material the feed did not cut (a groove's wall, the uncut bar beyond the
//! shoulder), a dive back into the diameter just turned, a contact that begins later in the
//! rapid or goes deeper than an edge's lean allows stays `rapid_into_stock`. The test is a walk
//! of the rapid at the stock's column width, independent of the check mode, so step and exact
//! mode classify a contact alike.

use super::{Checker, Part};
use crate::finding::{Kind, Severity};
use crate::geom::{self, Polygon, P2, V2};
use crate::interp::{Move, MoveKind};
use crate::motion::{self, Timed};
use crate::scene::{Section, StockHit};

/// The largest edge lean whose wedge counts as a scrape, degrees (a 107.5° holder leans 17.5°).
pub const LEAN_DEG: f64 = 20.0;
/// The deepest scrape, mm: deeper, the rapid cuts, whatever the angle.
pub const MAX_MM: f64 = 1.0;
/// The contact must begin within this travel from the rapid's start, mm (an edge leaning 1° is
/// a column width into the wedge after 0.6 mm at the finest column width of 0.01 mm).
const START_MM: f64 = 1.0;
/// The contact must end within this travel from the rapid's start, mm.
const WALK_MM: f64 = 25.0;
/// Most positions the walk tests.
const MAX_STEPS: usize = 100_000;
/// The walk's step, in stock column widths.
const STEP_COLUMNS: f64 = 4.0;
/// Bisections measuring the wedge's thickness at each step (2^-8 of the bound).
const THICKNESS_STEPS: usize = 8;

impl Checker<'_> {
    /// After rapid `m` was checked: turn the `rapid_into_stock` finding of the active insert that
    /// began in this move (among the findings from `first` on) into a `rapid_scrape` warning when
    /// the contact is the scrape of the wedge the preceding feed left (module docs).
    pub(super) fn mark_scrape(&mut self, m: &Move, item: &Timed, active: u32, first: usize) {
        let insert = self.name(Part::Insert, active);
        // The first contact of the insert in this move (a later one is never the scrape).
        let found = self.episodes.findings[first..]
            .iter()
            .enumerate()
            .filter(|(_, f)| {
                f.kind == Kind::RapidIntoStock
                    && f.line == m.line
                    && f.objects.first() == Some(&insert)
                    && f.time_s.is_some_and(|t| t >= item.t0 - 1e-9)
            })
            .min_by(|a, b| a.1.time_s.unwrap_or(0.0).total_cmp(&b.1.time_s.unwrap_or(0.0)));
        let Some((i, _)) = found else {
            return;
        };
        let i = first + i;
        let Some((end, feed_line, thickness)) = self.scrape_walk(m, item, active) else {
            return;
        };
        let f = &mut self.episodes.findings[i];
        if f.end_time_s.is_some_and(|t| t > end + 1e-9) {
            // The episode lasted past the walk's contact: it holds more than the scrape.
            return;
        }
        f.kind = Kind::RapidScrape;
        f.severity = Severity::Warning;
        f.depth_mm = Some(thickness);
        f.message =
            format!("rapid retract: the {insert} scrapes the wedge its own edge left in the cut of line {feed_line}");
    }

    /// The walk of the module docs: `Some((time the contact ends, line of the feed, thickest
    /// wedge))` when the active insert's contact with the stock in rapid `m` is a scrape.
    fn scrape_walk(&mut self, m: &Move, item: &Timed, active: u32) -> Option<(f64, u32, f64)> {
        // 1. The feed this rapid follows, which made the last cut.
        let (feed_index, feed) = self.behind.motion?;
        debug_assert!(feed_index < item.index);
        let feed = &feed;
        if !matches!(feed.kind, MoveKind::Line | MoveKind::Arc { .. })
            || feed.station != m.station
            || self.last_cut != Some(feed_index)
        {
            return None;
        }
        // The side of the feed's path the insert stands on at its end: the rapid must move to it.
        let tangent = feed.point_at(1.0) - feed.point_at(1.0 - 1e-6);
        let tool = self.scene.tool(active)?;
        let pts = tool.insert.points();
        let body = pts.iter().fold(V2::zeros(), |a, p| a + p.coords) / pts.len() as f64;
        // Each edge's inward normal: the directions that pull the insert off what it rubs.
        let inward: Vec<V2> = tool
            .insert
            .edges()
            .filter_map(|(a, b)| {
                let n = V2::new(a.y - b.y, b.x - a.x).try_normalize(1e-12)?;
                Some(if (body - a.coords).dot(&n) >= 0.0 { n } else { -n })
            })
            .collect();
        let normal = V2::new(-tangent.y, tangent.x).try_normalize(1e-15)?;
        let side = normal.dot(&body);
        if side.abs() < 1e-9 * body.norm().max(1.0) {
            return None;
        }
        let normal = normal * side.signum();
        // 2–3. Walk the rapid.
        let h = self.stock.as_ref()?.column_width();
        let ds = STEP_COLUMNS * h;
        let lean = LEAN_DEG.to_radians().tan();
        let vmax = motion::max_speed(m, item);
        let duration = item.duration;
        if !(vmax.is_finite() && vmax > 0.0 && duration > 0.0) {
            return None;
        }
        let dt = ds / vmax;
        let steps = ((duration / dt).ceil() as usize).min(MAX_STEPS);
        let r0 = motion::reference_at(m, item, 0.0);
        let mut began = false;
        let mut thickest: f64 = 0.0;
        for k in 1..=steps {
            let t = (k as f64 * dt).min(duration);
            let r = motion::reference_at(m, item, t);
            let d = r - r0;
            let s = d.norm();
            if s > WALK_MM {
                return None;
            }
            let (Section::Whole(poly), _) = self.pose(Part::Insert, r, active as f64)? else {
                return None;
            };
            let Some(hit) = self.overlap_now(&poly, V2::zeros(), false) else {
                if began {
                    return Some((item.t0 + t, feed.line, thickest));
                }
                continue;
            };
            if !began && s > START_MM {
                return None;
            }
            began = true;
            if d.dot(&normal) <= 0.0 || !self.stock.as_ref()?.last_move_changed(hit.cols.0, hit.cols.1) {
                return None;
            }
            let (Section::Whole(holder), _) = self.pose(Part::Holder, r, active as f64)? else {
                return None;
            };
            if self.overlap_now(&holder, V2::zeros(), true).is_some() {
                return None;
            }
            // The wedge's thickness: the least pull along an edge's inward normal that clears it.
            let bound = (s * lean + 2.0 * h).min(MAX_MM);
            let mut thinnest = f64::INFINITY;
            for &w in &inward {
                if self.overlap_now(&poly, w * bound, true).is_some() {
                    continue;
                }
                let (mut lo, mut hi) = (0.0, bound.min(thinnest));
                if self.overlap_now(&poly, w * hi, true).is_some() {
                    continue;
                }
                for _ in 0..THICKNESS_STEPS {
                    let mid = 0.5 * (lo + hi);
                    if self.overlap_now(&poly, w * mid, true).is_some() {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                thinnest = thinnest.min(hi);
            }
            if !thinnest.is_finite() {
                return None;
            }
            thickest = thickest.max(thinnest);
        }
        // In contact at the rapid's end (or the walk ran out of steps): not a scrape.
        None
    }

    /// A posed part's overlap with the stock (as it is now: a rapid cuts nothing), the part
    /// moved by `shift`.
    fn overlap_now(&mut self, poly: &Polygon, shift: V2, first_only: bool) -> Option<StockHit> {
        let moved: Vec<P2> = poly.points().iter().map(|p| p + shift).collect();
        self.stock_overlap(&moved, geom::TOUCH_EPS, first_only)
    }
}
