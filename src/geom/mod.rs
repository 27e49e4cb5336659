//! The 2D geometry kernel of the section checker.
//!
//! Coordinates: a point's `x` is the machine x (radius, toward the turret) and its `y` is the
//! machine z (along the spindle axis). All lengths are mm.
//!
//! * [`polygon`]: simple polygons, normalised to counter-clockwise; the exact orientation
//!   predicate.
//! * [`query`]: static queries — point location, distances, whether two parts overlap and how
//!   deep ([`overlap`], [`distance`]).
//! * [`sweep`]: continuous first contact of a translating part along a line or a circular path
//!   ([`sweep_line`], [`sweep_arc`]).
//!
//! Topology (touching or not, inside or not) is decided with exact predicates; lengths are
//! computed relative to a local origin so that results do not depend on where the parts are.

pub mod convex;
pub mod polygon;
pub mod query;
pub mod sweep;

#[cfg(test)]
mod tests;

pub use polygon::{orient, segments_meet, Polygon, PolygonError};
pub use query::{
    distance, interiors_overlap, locate, overlap, penetration_depth, point_segment_distance, segment_distance, Location,
};
pub use sweep::{sweep_arc, sweep_arc_episodes, sweep_line, sweep_line_episodes, Contact};

/// A point of the working plane: `x` = radius, `y` = z.
pub type P2 = nalgebra::Point2<f64>;
/// A displacement in the working plane.
pub type V2 = nalgebra::Vector2<f64>;

/// Build a point from machine `[x, z]`.
pub fn p2(x: f64, z: f64) -> P2 {
    P2::new(x, z)
}

/// Whether the point `a` comes after `b` in the total order of their coordinates taken in turn
/// (`f64::total_cmp` on x, then y, then z): an order that does not depend on which was given
/// first (a pair of parts asked either way round, a segment given from either end).
pub fn after(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| x.total_cmp(y))
        .find(|o| o.is_ne())
        .is_some_and(|o| o.is_gt())
}

/// Golden-section search for the largest value of `f` on `[lo, hi]`, stopping when the bracket is
/// no wider than `width` or after `steps` steps. Returns the better point of the last bracket and
/// the largest value met on the way (every evaluation counts: where `f` has more than one peak
/// there, a lower bound of its maximum).
pub fn golden_section_max(lo: f64, hi: f64, width: f64, steps: usize, mut f: impl FnMut(f64) -> f64) -> (f64, f64) {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut a, mut b) = (lo, hi);
    let mut x1 = b - g * (b - a);
    let mut x2 = a + g * (b - a);
    let mut f1 = f(x1);
    let mut f2 = f(x2);
    let mut best = f1.max(f2);
    for _ in 0..steps {
        if b - a <= width {
            break;
        }
        if f1 >= f2 {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = b - g * (b - a);
            f1 = f(x1);
            best = best.max(f1);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = a + g * (b - a);
            f2 = f(x2);
            best = best.max(f2);
        }
    }
    (if f1 >= f2 { x1 } else { x2 }, best)
}

/// Two parts collide when they overlap by more than this (docs/checking.md).
pub const TOUCH_EPS: f64 = 1e-6;

/// Axis-aligned bounding box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: P2,
    pub max: P2,
}

impl Aabb {
    pub fn empty() -> Aabb {
        Aabb {
            min: P2::new(f64::INFINITY, f64::INFINITY),
            max: P2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        }
    }

    pub fn of_points<'a>(pts: impl IntoIterator<Item = &'a P2>) -> Aabb {
        let mut b = Aabb::empty();
        for p in pts {
            b.add(*p);
        }
        b
    }

    pub fn add(&mut self, p: P2) {
        self.min.x = self.min.x.min(p.x);
        self.min.y = self.min.y.min(p.y);
        self.max.x = self.max.x.max(p.x);
        self.max.y = self.max.y.max(p.y);
    }

    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: P2::new(self.min.x.min(o.min.x), self.min.y.min(o.min.y)),
            max: P2::new(self.max.x.max(o.max.x), self.max.y.max(o.max.y)),
        }
    }

    pub fn translate(&self, v: V2) -> Aabb {
        Aabb {
            min: self.min + v,
            max: self.max + v,
        }
    }

    pub fn inflate(&self, d: f64) -> Aabb {
        Aabb {
            min: P2::new(self.min.x - d, self.min.y - d),
            max: P2::new(self.max.x + d, self.max.y + d),
        }
    }

    /// Overlap with a margin: boxes closer than `margin` count as meeting.
    pub fn meets(&self, o: &Aabb, margin: f64) -> bool {
        self.min.x <= o.max.x + margin
            && o.min.x <= self.max.x + margin
            && self.min.y <= o.max.y + margin
            && o.min.y <= self.max.y + margin
    }

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y
    }
}
