//! The turn-round between two operations (docs/job.md, "Operations"): the operator opens the
//! chuck, takes the part out, turns it end for end (or not) and clamps it again, standing where
//! the job says. In the model that is a map of z alone, `z ↦ ±z + shift` — the part is a solid of
//! revolution, so nothing else changes — applied to the part's outline (a job's `[stock] from`)
//! or to the in-process stock column by column (the checker, at an operation's start).
//!
//! On the dexel stock the map is exact: the columns keep their width and their material, only
//! their order (reversed when the part is turned round) and their place along z change, so the
//! turned part holds every radius the program left, to the bit, and a face the program cut on a
//! column's edge stays on one.

use super::DexelStock;
use crate::geom::P2;

/// Where the part stands after the turn-round, in the spindle frame (z 0 at the jaw faces).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stand {
    /// Its front face (its largest z) at this z.
    Front(f64),
    /// Held this long in the jaws: its back end (its smallest z) at `z = -grip`.
    Grip(f64),
    /// Where it stood (no shift): a part re-clamped as it was, with other jaws.
    Stay,
}

/// `z ↦ z + shift`, or `z ↦ −z + shift` when the part is turned round.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockTransform {
    /// Turned end for end: z mirrored.
    pub reverse: bool,
    /// Added after the mirror, mm.
    pub shift: f64,
}

impl StockTransform {
    /// Nothing moves.
    pub const IDENTITY: StockTransform = StockTransform {
        reverse: false,
        shift: 0.0,
    };

    /// The transform that takes a part spanning `lo ..= hi` in z (its material), mirrored when
    /// `reverse`, to where `stand` says.
    pub fn placing(lo: f64, hi: f64, reverse: bool, stand: Stand) -> StockTransform {
        let (a, b) = if reverse { (-hi, -lo) } else { (lo, hi) };
        let shift = match stand {
            Stand::Front(front) => front - b,
            Stand::Grip(grip) => -grip - a,
            Stand::Stay => 0.0,
        };
        StockTransform { reverse, shift }
    }

    /// Where the point at `z` goes.
    pub fn z(&self, z: f64) -> f64 {
        if self.reverse {
            self.shift - z
        } else {
            z + self.shift
        }
    }

    /// An outline `[x, z]` mapped point by point (its order reversed when mirrored, so that it
    /// keeps its turning sense).
    pub fn outline(&self, pts: &[P2]) -> Vec<P2> {
        let mut out: Vec<P2> = pts.iter().map(|p| P2::new(p.x, self.z(p.y))).collect();
        if self.reverse {
            out.reverse();
        }
        out
    }

    /// The stock's material mapped: a stock of the columns from its first to its last column
    /// with material (the empty ones beyond dropped), in reverse order when mirrored, each
    /// column as it was; same column width. A stock with no material gives one empty column.
    pub fn stock(&self, s: &DexelStock) -> DexelStock {
        let h = s.column_width();
        let Some((a, b)) = s.material_columns() else {
            return DexelStock::from_columns(self.z(s.extent().0), h, Vec::new());
        };
        let z0 = s.extent().0;
        let (lo, hi) = (z0 + a as f64 * h, z0 + (b + 1) as f64 * h);
        let cols: Vec<Vec<(f64, f64)>> = if self.reverse {
            (a..=b).rev().map(|j| s.column_now(j).to_vec()).collect()
        } else {
            (a..=b).map(|j| s.column_now(j).to_vec()).collect()
        };
        let start = if self.reverse { self.z(hi) } else { self.z(lo) };
        DexelStock::from_columns(start, h, cols)
    }
}

/// The z range of a stock's material: from the first edge of its first column with material to
/// the last edge of its last (None: no material left).
pub fn material_extent(s: &DexelStock) -> Option<(f64, f64)> {
    let (a, b) = s.material_columns()?;
    let (z0, h) = (s.extent().0, s.column_width());
    Some((z0 + a as f64 * h, z0 + (b + 1) as f64 * h))
}

/// The part the operator takes out of the chuck, and whether a part-off made it: after a
/// part-off (an empty column with material on both sides), the piece cut off — the material
/// beyond the last such column, toward `+z` (`DexelStock::split_off_beyond`); the bar left in
/// the jaws is not the part. Without one, the whole stock. None when no material is left.
pub fn the_part(stock: &DexelStock) -> Option<(DexelStock, bool)> {
    stock.material_columns()?;
    let mut rest = stock.clone();
    rest.end_move();
    Some(match rest.split_off_beyond() {
        Some(piece) => (piece, true),
        None => (rest, false),
    })
}

/// The largest radius of material, for the stock's box (0 for none).
pub fn max_radius(s: &DexelStock) -> f64 {
    (0..s.columns())
        .filter_map(|j| s.column_now(j).last().map(|iv| iv.1))
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Columns of 1 mm: the material of each, front to back as given.
    fn stock(z0: f64, cols: &[&[(f64, f64)]]) -> DexelStock {
        DexelStock::from_columns(z0, 1.0, cols.iter().map(|c| c.to_vec()).collect())
    }

    fn columns(s: &DexelStock) -> Vec<Vec<(f64, f64)>> {
        (0..s.columns()).map(|j| s.column_now(j).to_vec()).collect()
    }

    #[test]
    fn turning_a_stepped_part_round_mirrors_its_columns_about_the_new_front() {
        // z 0..5: a shoulder Ø20 for two columns, Ø30 for two, then a bored Ø40 column; the
        // first column empty (a face cut back), so the material runs z 1..5.
        let s = stock(
            0.0,
            &[&[], &[(0.0, 10.0)], &[(0.0, 10.0)], &[(0.0, 15.0)], &[(4.0, 20.0)]],
        );
        // Turned round with its front (old back end, z 1) at z 30: z ↦ 31 − z.
        let t = StockTransform::placing(1.0, 5.0, true, Stand::Front(30.0));
        assert_eq!(
            t,
            StockTransform {
                reverse: true,
                shift: 31.0
            }
        );
        let r = t.stock(&s);
        // By hand: the columns z 26..27 (old 4..5, bored), 27..28 (old 3..4), 28..29 and
        // 29..30 (old 2..3 and 1..2).
        assert_eq!(r.extent(), (26.0, 30.0));
        assert_eq!(
            columns(&r),
            vec![
                vec![(4.0, 20.0)],
                vec![(0.0, 15.0)],
                vec![(0.0, 10.0)],
                vec![(0.0, 10.0)]
            ]
        );
        assert_eq!(material_extent(&r), Some((26.0, 30.0)));
        assert!(r.holds(19.0, 26.5) && !r.holds(2.0, 26.5) && r.holds(14.0, 27.5) && !r.holds(11.0, 29.5));
        // Gripped 3 mm instead: the back end (old z 5) at z -3, z ↦ 2 − z.
        let g = StockTransform::placing(1.0, 5.0, true, Stand::Grip(3.0));
        assert_eq!(g.shift, 2.0);
        assert_eq!(g.stock(&s).extent(), (-3.0, 1.0));
        // Not turned round, pulled out 10 mm: the same columns in the same order.
        let p = StockTransform::placing(1.0, 5.0, false, Stand::Front(15.0));
        let moved = p.stock(&s);
        assert_eq!(moved.extent(), (11.0, 15.0));
        assert_eq!(columns(&moved)[0], vec![(0.0, 10.0)]);
        assert_eq!(columns(&moved)[3], vec![(4.0, 20.0)]);
    }

    #[test]
    fn an_outline_turned_round_keeps_its_sense_and_lands_where_it_is_told() {
        let pts = [
            P2::new(0.0, -10.0),
            P2::new(20.0, -10.0),
            P2::new(20.0, 30.0),
            P2::new(0.0, 30.0),
        ];
        let t = StockTransform::placing(-10.0, 30.0, true, Stand::Grip(12.0));
        let out = t.outline(&pts);
        assert_eq!(
            out,
            vec![
                P2::new(0.0, -12.0),
                P2::new(20.0, -12.0),
                P2::new(20.0, 28.0),
                P2::new(0.0, 28.0)
            ]
        );
        let poly = crate::geom::Polygon::new(&out).unwrap();
        assert!(poly.area() > 0.0);
        assert_eq!(StockTransform::IDENTITY.outline(&pts), pts.to_vec());
    }

    #[test]
    fn the_part_is_the_piece_cut_off_after_a_part_off_else_the_whole_stock() {
        let whole = stock(0.0, &[&[(0.0, 10.0)], &[(0.0, 10.0)], &[(0.0, 8.0)]]);
        let (p, parted) = the_part(&whole).unwrap();
        assert!(!parted);
        assert_eq!(material_extent(&p), Some((0.0, 3.0)));
        let parted_off = stock(0.0, &[&[(0.0, 10.0)], &[], &[(0.0, 8.0)], &[(0.0, 9.0)]]);
        let (p, parted) = the_part(&parted_off).unwrap();
        assert!(parted);
        assert_eq!(material_extent(&p), Some((2.0, 4.0)));
        assert_eq!(max_radius(&p), 9.0);
        assert!(the_part(&stock(0.0, &[&[], &[]])).is_none());
    }
}
