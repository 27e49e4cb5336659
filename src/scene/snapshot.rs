//! What the working plane looks like at one moment: the data a picture of a finding needs.
//!
//! All points are spindle-frame `P2` (`x` = radius, signed; `y` = z). Revolved parts are given as
//! their outline in the half plane `x ≥ 0`: a drawing mirrors them about the axis.

use crate::geom::P2;
use crate::interp::ProgFrame;

/// The scene at first contact of a finding.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Snapshot {
    /// Revolved outlines (x ≥ 0).
    pub chuck: Option<Vec<P2>>,
    pub tailstock: Option<Vec<P2>>,
    /// The stock as it is at that moment: closed outlines in x ≥ 0.
    pub stock: Vec<Vec<P2>>,
    /// The turret body, posed, in the working plane.
    pub turret: Vec<P2>,
    /// The active tool, posed, in the working plane.
    pub insert: Vec<P2>,
    pub holder: Vec<P2>,
    /// Tools of the other stations in the radial section `(r ≥ 0, z)`, with labels ("T05 holder").
    pub others: Vec<(String, Vec<P2>)>,
    /// The programmed point's path around the moment (the move, and the one before).
    pub path: Vec<P2>,
    /// The programmed point as the machine drives it through the move, where that differs from
    /// the programmed line (a dogleg rapid: each axis at its own rate, so the path bends where
    /// the first axis arrives). Empty when the machine follows the programmed line.
    pub machine_path: Vec<P2>,
    /// How the move's program coordinates map onto the spindle frame (for ticks in program units
    /// and the program zero mark).
    pub frame: Option<ProgFrame>,
    /// An overtravel finding: the limit the turret reference point broke and by how much.
    pub travel: Option<Travel>,
    /// Programmed point at first contact.
    pub at: P2,
    /// The two parts involved, as closed outlines in the plane they were tested in; their
    /// intersection is the overlap to fill. Empty for findings with no geometry (overtravel).
    pub part_a: Vec<P2>,
    pub part_b: Vec<Vec<P2>>,
    /// Whether `part_a` was tested folded about the axis (a part in the working plane against a
    /// revolved part): the drawing then shows the obstacle on both sides.
    pub mirrored: bool,
}

/// The axis limit an overtravel finding broke, in the spindle frame of the turret reference
/// point (the point the machine's travel limits are given for).
#[derive(Clone, Debug, PartialEq)]
pub struct Travel {
    /// `'X'` or `'Z'`.
    pub axis: char,
    /// The limit broken: an `x` (radius) for X, a `z` for Z.
    pub limit: f64,
    /// The turret reference point through the move.
    pub reference_path: Vec<P2>,
    /// Where it is farthest beyond the limit, and how far.
    pub worst: P2,
    pub overshoot: f64,
}
