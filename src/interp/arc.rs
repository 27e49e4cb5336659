//! Arc geometry and the rs274ngc arc checks (docs/programs.md, "Arcs").
//!
//! Tolerances (rs274ngc): an I/K arc's start and end radius may differ by at most
//! 0.028284 mm (0.0028284 in), and by at most 0.1 % when the difference is over that, never over
//! 100 times that; an R arc whose half chord exceeds |R| by more than 0.00127 mm (0.00005 in) is an
//! error, by less it becomes a semicircle. Everything here is in mm; the caller converts the
//! tolerances of inch programs.

use super::MAX_COORD;
use crate::geom::P2;
use std::f64::consts::{PI, TAU};

/// The arc tolerances in mm for the program's units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcTolerance {
    /// Smallest radius, and how far an R arc may fall short of its chord.
    pub radius: f64,
    /// Largest start/end radius difference before the relative rule applies.
    pub spiral: f64,
}

impl ArcTolerance {
    pub const MM: ArcTolerance = ArcTolerance {
        radius: 0.00127,
        spiral: 0.028_284_271_247_461_9,
    };
    pub const INCH: ArcTolerance = ArcTolerance {
        radius: 0.00005 * 25.4,
        spiral: 0.002_828_427_124_746_19 * 25.4,
    };
}

#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArcError {
    #[error("zero-radius arc")]
    ZeroRadius,
    #[error("radius to end of arc ({end:.4} mm) differs from radius to start ({start:.4} mm) by {diff:.4} mm")]
    RadiusMismatch { start: f64, end: f64, diff: f64 },
    #[error("arc radius {radius:.4} mm is too small to reach the end point (half chord {half_chord:.4} mm)")]
    RadiusTooSmall { radius: f64, half_chord: f64 },
    #[error("an R arc cannot end where it starts")]
    StartEqualsEnd,
    #[error("arc geometry is not finite")]
    NotFinite,
    #[error("the arc's {what} is out of any range (beyond ±{max:e} mm)", max = super::MAX_COORD)]
    OutOfRange { what: &'static str },
}

/// Signed sweep (positive counter-clockwise) of an arc from `start` to `end` about `center`.
/// `turns` ≥ 1 is the number of times the arc passes the end angle (LinuxCNC P word).
pub fn arc_from_center(
    start: P2,
    end: P2,
    center: P2,
    ccw: bool,
    turns: u32,
    tol: ArcTolerance,
) -> Result<f64, ArcError> {
    if !(center.x.abs() <= MAX_COORD && center.y.abs() <= MAX_COORD) {
        return Err(ArcError::OutOfRange { what: "centre" });
    }
    let r0 = (start - center).norm();
    let r1 = (end - center).norm();
    if !(r0.is_finite() && r1.is_finite()) {
        return Err(ArcError::NotFinite);
    }
    if r0 < tol.radius || r1 < tol.radius {
        return Err(ArcError::ZeroRadius);
    }
    let diff = (r1 - r0).abs();
    let rel = diff / r0.max(r1);
    if diff > 100.0 * tol.spiral || (rel > 0.001 && diff > tol.spiral) {
        return Err(ArcError::RadiusMismatch {
            start: r0,
            end: r1,
            diff,
        });
    }
    Ok(sweep_between(start, end, center, ccw, turns))
}

fn sweep_between(start: P2, end: P2, center: P2, ccw: bool, turns: u32) -> f64 {
    let a0 = (start.y - center.y).atan2(start.x - center.x);
    let a1 = (end.y - center.y).atan2(end.x - center.x);
    let extra = TAU * (turns.max(1) - 1) as f64;
    if ccw {
        let mut d = (a1 - a0).rem_euclid(TAU);
        if d < 1e-12 || start == end {
            d = TAU;
        }
        d + extra
    } else {
        let mut d = (a0 - a1).rem_euclid(TAU);
        if d < 1e-12 || start == end {
            d = TAU;
        }
        -(d + extra)
    }
}

/// Centre and signed sweep of an R-format arc. `radius` < 0 asks for the arc over 180°.
pub fn arc_from_radius(
    start: P2,
    end: P2,
    radius: f64,
    ccw: bool,
    turns: u32,
    tol: ArcTolerance,
) -> Result<(P2, f64), ArcError> {
    if !radius.is_finite() {
        return Err(ArcError::NotFinite);
    }
    if radius.abs() > MAX_COORD {
        return Err(ArcError::OutOfRange { what: "radius" });
    }
    if start == end {
        return Err(ArcError::StartEqualsEnd);
    }
    let mut r = radius.abs();
    if r < tol.radius {
        return Err(ArcError::ZeroRadius);
    }
    let chord = end - start;
    let half = chord.norm() / 2.0;
    if half - r > tol.radius {
        return Err(ArcError::RadiusTooSmall {
            radius: r,
            half_chord: half,
        });
    }
    if r < half {
        r = half;
    }
    let mid = start + chord / 2.0;
    let d = (r * r - half * half).max(0.0).sqrt();
    let left = nalgebra::Vector2::new(-chord.y, chord.x) / (2.0 * half);
    // Counter-clockwise and at most 180°: the centre is to the left of start→end.
    let to_left = ccw == (radius > 0.0);
    let center = if to_left { mid + left * d } else { mid - left * d };
    if !(center.x.abs() <= MAX_COORD && center.y.abs() <= MAX_COORD) {
        return Err(ArcError::OutOfRange { what: "centre" });
    }
    let mut sweep = sweep_between(start, end, center, ccw, turns);
    let extra = TAU * (turns.max(1) - 1) as f64;
    if radius > 0.0 && sweep.abs() - extra > PI + 1e-6 {
        // The angles of the ends about a far centre differ by less than `sweep_between` tells
        // from a whole turn; an R arc of R > 0 turns at most 180°: its true sweep.
        let short = 2.0 * (half / r).min(1.0).asin();
        sweep = (short + extra).copysign(sweep);
    }
    Ok((center, sweep))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::p2;
    use std::f64::consts::PI;

    #[test]
    fn quarter_arcs_turn_the_right_way() {
        let s = arc_from_center(p2(1.0, 0.0), p2(0.0, 1.0), p2(0.0, 0.0), true, 1, ArcTolerance::MM).unwrap();
        assert!((s - PI / 2.0).abs() < 1e-12);
        let s = arc_from_center(p2(1.0, 0.0), p2(0.0, 1.0), p2(0.0, 0.0), false, 1, ArcTolerance::MM).unwrap();
        assert!((s + 3.0 * PI / 2.0).abs() < 1e-12);
    }

    #[test]
    fn full_circle_when_start_equals_end() {
        let s = arc_from_center(p2(1.0, 0.0), p2(1.0, 0.0), p2(0.0, 0.0), false, 1, ArcTolerance::MM).unwrap();
        assert!((s + TAU).abs() < 1e-12);
        let s = arc_from_center(p2(1.0, 0.0), p2(1.0, 0.0), p2(0.0, 0.0), true, 2, ArcTolerance::MM).unwrap();
        assert!((s - 2.0 * TAU).abs() < 1e-12);
    }

    #[test]
    fn negative_r_takes_the_long_way() {
        let (c, s) = arc_from_radius(p2(0.0, 0.0), p2(2.0, 0.0), 1.5, true, 1, ArcTolerance::MM).unwrap();
        assert!(s > 0.0 && s < PI, "{s}");
        let (c2, s2) = arc_from_radius(p2(0.0, 0.0), p2(2.0, 0.0), -1.5, true, 1, ArcTolerance::MM).unwrap();
        assert!(s2 > PI && s2 < TAU, "{s2}");
        assert!((c.x - 1.0).abs() < 1e-12 && (c2.x - 1.0).abs() < 1e-12);
        assert!((c.y + c2.y).abs() < 1e-12 && c.y != 0.0);
    }

    #[test]
    fn radius_tolerance_boundaries() {
        let t = ArcTolerance::MM;
        // half chord exceeds R by just under / over the tolerance
        assert!(arc_from_radius(p2(0.0, 0.0), p2(2.0, 0.0), 1.0 - 0.0012, true, 1, t).is_ok());
        assert!(arc_from_radius(p2(0.0, 0.0), p2(2.0, 0.0), 1.0 - 0.0013, true, 1, t).is_err());
    }

    #[test]
    fn a_radius_or_centre_past_the_range_is_an_error() {
        let t = ArcTolerance::MM;
        let (s, e) = (p2(50.0, 0.0), p2(50.0, -100.0));
        for r in [1e16, -1e16, 1e155, 1.0e12 + 1e6] {
            assert_eq!(
                arc_from_radius(s, e, r, true, 1, t),
                Err(ArcError::OutOfRange { what: "radius" }),
                "R{r}"
            );
        }
        assert_eq!(
            arc_from_center(s, s, p2(55.0, 1e40), true, 1, t),
            Err(ArcError::OutOfRange { what: "centre" })
        );
        assert_eq!(
            arc_from_center(s, e, p2(f64::NAN, 0.0), true, 1, t),
            Err(ArcError::OutOfRange { what: "centre" })
        );
    }

    #[test]
    fn a_short_r_arc_about_a_far_centre_stays_short() {
        // The ends' angles about the centre differ by ~1e-14: never a whole turn.
        let (s, e) = (p2(50.0, 0.0), p2(50.0, -0.001));
        for ccw in [true, false] {
            let (_, sw) = arc_from_radius(s, e, 1e11, ccw, 1, ArcTolerance::MM).unwrap();
            assert!(sw.abs() < 1e-12 && (sw > 0.0) == ccw, "{sw}");
            let (_, sw) = arc_from_radius(s, e, 1e11, ccw, 3, ArcTolerance::MM).unwrap();
            assert!((sw.abs() - 2.0 * TAU).abs() < 1e-9, "{sw}");
        }
    }
}
