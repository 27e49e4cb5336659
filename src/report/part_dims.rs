//! The main dimensions of a turned part, read from its section (`pipeline::FinalPart::outline`,
//! closed `[x, z]` points in the half plane x ≥ 0), as a machinist's drawing shows them: the
//! overall length, the largest diameter, each step's diameter, the z of each shoulder measured from
//! the front face (the part's largest z), and the diameters of a bore (`report::part_svg` draws
//! them).
//!
//! The section is read as two profiles along z — the outer radius and, where the material starts
//! off the axis, the bore's — each a list of stretches between the outline's distinct z values,
//! on which the radius is linear. A step is a run of stretches at one radius at least
//! [`MIN_STEP`] long (shorter ones — a nose radius's fillet, a chamfer, a groove narrower than a
//! tool — belong to the shoulder between two steps); at most [`MAX_STEPS`] outer steps and
//! [`MAX_BORES`] bore steps are kept (the longest). A shoulder is where the radius falls or rises
//! most steeply between two kept steps (a taper: its middle).

/// A step shorter than this (mm) is not dimensioned: it belongs to the shoulder beside it.
pub const MIN_STEP: f64 = 0.5;
/// At most this many outer steps are dimensioned (the longest).
pub const MAX_STEPS: usize = 12;
/// At most this many bore steps are dimensioned (the longest).
pub const MAX_BORES: usize = 4;
/// Two radii within this (mm) are one radius.
const SAME_R: f64 = 1e-3;

/// A run of the profile at one radius: `z0 < z1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    pub z0: f64,
    pub z1: f64,
    pub r: f64,
}

/// What the drawing dimensions.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dims {
    /// The part's extent along z: its back end and its front face.
    pub zmin: f64,
    pub zmax: f64,
    /// Its largest radius, and a z where the outline reaches it.
    pub rmax: f64,
    pub rmax_at: f64,
    /// The outer steps, in z order.
    pub steps: Vec<Step>,
    /// The z of the shoulder between each two consecutive steps (`steps.len() - 1` of them).
    pub shoulders: Vec<f64>,
    /// The bore's steps, in z order (empty for a solid part).
    pub bores: Vec<Step>,
}

/// An edge of the outline from its lower z to its higher, `[x, z]` ends.
type Edge = ([f64; 2], [f64; 2]);

/// A stretch of a profile between two z values, the radius linear on it.
#[derive(Clone, Copy, Debug)]
struct Stretch {
    z0: f64,
    z1: f64,
    r0: f64,
    r1: f64,
}

impl Dims {
    /// The dimensions of the part whose section is `outline`; `None` for fewer than three points,
    /// a point not finite, or no extent along z.
    pub fn of(outline: &[[f64; 2]]) -> Option<Dims> {
        if outline.len() < 3 || outline.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return None;
        }
        let (outer, inner) = profiles(outline);
        let (first, last) = (outer.first()?, outer.last()?);
        let (zmin, zmax) = (first.z0, last.z1);
        let (mut rmax, mut rmax_at) = (f64::NEG_INFINITY, zmin);
        for s in &outer {
            for (r, z) in [(s.r0, s.z0), (s.r1, s.z1)] {
                if r > rmax {
                    (rmax, rmax_at) = (r, z);
                }
            }
        }
        let (steps, bores) = (runs(&outer, MAX_STEPS), runs(&inner, MAX_BORES));
        let shoulders = steps.windows(2).map(|w| shoulder(&outer, w[0].z1, w[1].z0)).collect();
        Some(Dims {
            zmin,
            zmax,
            rmax,
            rmax_at,
            steps,
            shoulders,
            bores,
        })
    }

    /// The outer radius of `outline` (the one these dimensions were read from) at `z`: the largest
    /// the profile reaches there (at a face perpendicular to the axis, the larger side).
    pub fn outer_at(&self, outline: &[[f64; 2]], z: f64) -> f64 {
        let (outer, _) = profiles(outline);
        outer
            .iter()
            .filter(|s| s.z0 - 1e-9 <= z && z <= s.z1 + 1e-9)
            .map(|s| {
                let t = if s.z1 > s.z0 {
                    ((z - s.z0) / (s.z1 - s.z0)).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                s.r0 + t * (s.r1 - s.r0)
            })
            .fold(0.0, f64::max)
    }
}

/// The outer and the bore profile of a closed outline: for each stretch between two consecutive
/// distinct z values of its points, the largest and (where the material starts off the axis) the
/// smallest radius at which an edge crosses it. A sweep over the edges sorted by z: each edge
/// is looked at on the stretches it spans only.
fn profiles(outline: &[[f64; 2]]) -> (Vec<Stretch>, Vec<Stretch>) {
    let n = outline.len();
    let mut zs: Vec<f64> = outline.iter().map(|p| p[1]).collect();
    zs.sort_by(f64::total_cmp);
    zs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    // Edges that span some z (not perpendicular to the axis), by their lower z.
    let mut edges: Vec<Edge> = (0..n)
        .map(|i| (outline[i], outline[(i + 1) % n]))
        .filter(|(a, b)| (a[1] - b[1]).abs() >= 1e-9)
        .map(|(a, b)| if a[1] < b[1] { (a, b) } else { (b, a) })
        .collect();
    edges.sort_by(|a, b| a.0[1].total_cmp(&b.0[1]));
    let (mut outer, mut inner) = (Vec::new(), Vec::new());
    let (mut next, mut active): (usize, Vec<Edge>) = (0, Vec::new());
    let at = |e: &Edge, z: f64| {
        let t = ((z - e.0[1]) / (e.1[1] - e.0[1])).clamp(0.0, 1.0);
        e.0[0] + t * (e.1[0] - e.0[0])
    };
    for w in zs.windows(2) {
        let (z0, z1) = (w[0], w[1]);
        let zm = 0.5 * (z0 + z1);
        while next < edges.len() && edges[next].0[1] < zm {
            active.push(edges[next]);
            next += 1;
        }
        active.retain(|e| e.1[1] > zm);
        if active.len() < 2 {
            continue;
        }
        let (mut lo, mut hi) = (&active[0], &active[0]);
        for e in &active[1..] {
            if at(e, zm) < at(lo, zm) {
                lo = e;
            }
            if at(e, zm) > at(hi, zm) {
                hi = e;
            }
        }
        outer.push(Stretch {
            z0,
            z1,
            r0: at(hi, z0),
            r1: at(hi, z1),
        });
        if at(lo, zm) > 1e-6 {
            inner.push(Stretch {
                z0,
                z1,
                r0: at(lo, z0),
                r1: at(lo, z1),
            });
        }
    }
    (outer, inner)
}

/// The runs of a profile at one radius at least [`MIN_STEP`] long, the `keep` longest, in z order.
/// Runs at one radius (within [`SAME_R`]) parted only by shorter stretches are one step.
fn runs(profile: &[Stretch], keep: usize) -> Vec<Step> {
    let mut runs: Vec<Step> = Vec::new();
    let mut cur: Option<Step> = None;
    for s in profile {
        let flat = (s.r1 - s.r0).abs() <= SAME_R;
        match (&mut cur, flat) {
            (Some(c), true) if (s.r0 - c.r).abs() <= SAME_R && (s.z0 - c.z1).abs() < 1e-9 => c.z1 = s.z1,
            _ => {
                if let Some(c) = cur.take() {
                    runs.push(c);
                }
                if flat {
                    cur = Some(Step {
                        z0: s.z0,
                        z1: s.z1,
                        r: s.r0.max(s.r1),
                    });
                }
            }
        }
    }
    runs.extend(cur);
    runs.retain(|s| s.z1 - s.z0 >= MIN_STEP);
    // One radius either side of a short stretch (a scratch of the model, a column's step): one step.
    let mut merged: Vec<Step> = Vec::new();
    for s in runs {
        match merged.last_mut() {
            Some(m) if (m.r - s.r).abs() <= SAME_R && s.z0 - m.z1 < MIN_STEP => m.z1 = s.z1,
            _ => merged.push(s),
        }
    }
    if merged.len() > keep {
        merged.sort_by(|a, b| (b.z1 - b.z0).total_cmp(&(a.z1 - a.z0)));
        merged.truncate(keep);
        merged.sort_by(|a, b| a.z0.total_cmp(&b.z0));
    }
    merged
}

/// The z of the shoulder between a step ending at `za` and the next starting at `zb`: where the
/// radius changes most between them — a jump between two stretches (a face perpendicular to the
/// axis, also at either step's own end) or the middle of a stretch steeper than 45° (a face one
/// column long) — or the middle of `za..zb` when nothing there is steeper (a taper).
fn shoulder(profile: &[Stretch], za: f64, zb: f64) -> f64 {
    let first = profile.partition_point(|s| s.z1 <= za + 1e-9);
    let last = profile.partition_point(|s| s.z0 < zb - 1e-9);
    let mut best: Option<(f64, f64)> = None; // (change of radius, z)
    let mut offer = |change: f64, z: f64| {
        if change > SAME_R && best.map_or(true, |b| change > b.0) {
            best = Some((change, z));
        }
    };
    for s in &profile[first..last.max(first)] {
        if (s.r1 - s.r0).abs() >= s.z1 - s.z0 {
            offer((s.r1 - s.r0).abs(), 0.5 * (s.z0 + s.z1));
        }
    }
    // Jumps between consecutive stretches, from the one ending at `za` to the one starting at `zb`.
    for i in first.max(1)..(last + 1).min(profile.len()) {
        let (p, s) = (&profile[i - 1], &profile[i]);
        if (s.z0 - p.z1).abs() < 1e-9 {
            offer((s.r0 - p.r1).abs(), s.z0);
        }
    }
    best.map_or(0.5 * (za + zb), |b| b.1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Ø50 bar from z −40 to 78 turned to Ø40 over its last 40 mm, with a 0.4 mm nose radius's
    /// fillet at the shoulder and a 1 mm chamfer at the front, traced as the dexel stock traces it
    /// (column centres 0.01 mm apart).
    fn od_turned() -> Vec<[f64; 2]> {
        vec![
            [0.0, -40.0],
            [25.0, -40.0],
            [25.0, 37.995],
            [20.388299, 38.005],
            [20.241586, 38.035],
            [20.110382, 38.125],
            [20.027343, 38.255],
            [20.0, 38.425],
            [20.0, 77.325],
            [19.779347, 78.0],
            [0.0, 78.0],
        ]
    }

    #[test]
    fn a_turned_bar_has_two_steps_and_its_shoulder_40_mm_from_the_face() {
        let d = Dims::of(&od_turned()).unwrap();
        assert_eq!((d.zmin, d.zmax, d.rmax), (-40.0, 78.0, 25.0));
        assert_eq!(d.steps.len(), 2, "{:?}", d.steps);
        assert_eq!((d.steps[0].r, d.steps[1].r), (25.0, 20.0));
        assert_eq!(d.shoulders.len(), 1);
        assert!((d.zmax - d.shoulders[0] - 40.0).abs() < 1e-9, "{:?}", d.shoulders);
        assert!(d.bores.is_empty());
    }

    #[test]
    fn a_bore_is_its_own_profile_and_short_runs_are_no_steps() {
        // Ø50 bar bored Ø23 to 24.6 deep from the face at 78, a drill's cone beyond; a 0.2 mm
        // land at Ø46 between Ø50 and Ø40 is part of the shoulder, which stands at its larger
        // face (Ø46 down to Ø40).
        let outline = vec![
            [0.0, 0.0],
            [25.0, 0.0],
            [25.0, 30.0],
            [23.0, 30.0],
            [23.0, 30.2],
            [20.0, 30.2],
            [20.0, 78.0],
            [11.5, 78.0],
            [11.5, 53.4],
            [10.0, 53.0],
            [0.0, 48.0],
        ];
        let d = Dims::of(&outline).unwrap();
        assert_eq!(d.steps.iter().map(|s| s.r).collect::<Vec<_>>(), vec![25.0, 20.0]);
        assert_eq!(d.shoulders, vec![30.2]);
        assert_eq!(d.bores.len(), 1);
        assert_eq!(
            d.bores[0],
            Step {
                z0: 53.4,
                z1: 78.0,
                r: 11.5
            }
        );
    }

    #[test]
    fn many_steps_keep_the_longest_and_bad_outlines_give_none() {
        // 30 steps, each 1 mm long except every third one 2 mm.
        let mut top = Vec::new();
        let mut z = 0.0;
        for i in 0..30 {
            let len = if i % 3 == 0 { 2.0 } else { 1.0 };
            let r = 10.0 + (i % 2) as f64;
            top.push([r, z]);
            top.push([r, z + len]);
            z += len;
        }
        let mut outline = vec![[0.0, 0.0]];
        outline.extend(top);
        outline.push([0.0, z]);
        let d = Dims::of(&outline).unwrap();
        assert_eq!(d.steps.len(), MAX_STEPS);
        assert!(d.steps.iter().filter(|s| s.z1 - s.z0 > 1.5).count() == 10);
        assert_eq!(d.shoulders.len(), MAX_STEPS - 1);
        assert!(Dims::of(&[[0.0, 0.0], [1.0, 0.0]]).is_none());
        assert!(Dims::of(&[[0.0, 0.0], [1.0, 0.0], [f64::NAN, 1.0]]).is_none());
        assert!(Dims::of(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).is_none());
    }
}
