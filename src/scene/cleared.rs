//! The last few regions a cut took off the dexel stock (ARCHITECTURE.md, "A cut that retraces
//! a cut"): a spring pass over the same path, a tool fed back and forth over its own groove,
//! a cycle's passes repeated over the same chord sweep the very polygon cut before, and cutting
//! it again walks every column under it to take off nothing.
//!
//! A cut subtracts from each column the polygon's span at the column's centre. Once it has, no
//! column has material inside that span, and the stock never gains material; the same polygon
//! again, vertex for vertex, has the same spans with the same arithmetic, so its cut changes no
//! column: leaving it out is bit for bit what making it gives. Only an equal polygon counts: one
//! merely held by a region cut before (the same chord run the other way, computed from its other
//! end) may differ in its spans by rounding, and a column whose centre lies on its edge may then
//! go either way.

use crate::geom::P2;

/// How many regions are remembered: a pass run back and forth needs two; a non-convex insert
/// cuts a quad per edge and its end pose along each chord.
const KEPT: usize = 8;

/// Regions (rings of points) already cut off the stock.
#[derive(Clone, Debug, Default)]
pub(super) struct Cleared {
    rings: Vec<Vec<P2>>,
    /// The slot the next region takes once `rings` is full (the oldest).
    next: usize,
}

impl Cleared {
    /// Whether `pts` is a region already cut, vertex for vertex (its cut takes off nothing).
    pub(super) fn holds(&self, pts: &[P2]) -> bool {
        self.rings.iter().any(|q| q.as_slice() == pts)
    }

    /// Whether `pts` was cut before (as [`Self::holds`]); when not, it is remembered, as the
    /// region about to be cut. One pass over the remembered regions for each cut.
    pub(super) fn seen_or_remember(&mut self, pts: &[P2]) -> bool {
        if self.holds(pts) {
            return true;
        }
        if pts.is_empty() {
            return false;
        }
        if self.rings.len() < KEPT {
            self.rings.push(pts.to_vec());
        } else {
            self.rings[self.next].clear();
            self.rings[self.next].extend_from_slice(pts);
            self.next = (self.next + 1) % KEPT;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, z: f64, s: f64) -> Vec<P2> {
        vec![
            P2::new(x, z),
            P2::new(x + s, z),
            P2::new(x + s, z + s),
            P2::new(x, z + s),
        ]
    }

    #[test]
    fn only_a_region_equal_to_one_cut_is_held() {
        let mut c = Cleared::default();
        assert!(!c.seen_or_remember(&square(10.0, 0.0, 5.0)));
        assert!(c.holds(&square(10.0, 0.0, 5.0)));
        // Inside it, or the same points from another vertex: not the same spans by the same
        // arithmetic, so not held.
        assert!(!c.holds(&square(11.0, 1.0, 2.0)));
        let mut turned = square(10.0, 0.0, 5.0);
        turned.rotate_left(1);
        assert!(!c.holds(&turned));
        assert!(!c.holds(&square(10.0, 0.0, 5.0 + 1e-15)));
    }

    #[test]
    fn only_the_last_few_regions_are_remembered() {
        let mut c = Cleared::default();
        for k in 0..=KEPT {
            c.seen_or_remember(&square(10.0 * k as f64, 0.0, 1.0));
        }
        assert!(!c.holds(&square(0.0, 0.0, 1.0)), "the oldest is forgotten");
        for k in 1..=KEPT {
            assert!(c.holds(&square(10.0 * k as f64, 0.0, 1.0)));
        }
    }
}
