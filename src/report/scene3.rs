//! The scene of a 3D finding at first contact (turn-mill): what its three orthographic views
//! (`views3`) and its glTF binary (`glb`) are drawn from.
//!
//! Every part is a triangle mesh in its own frame, posed in the machine frame by an isometry
//! (`kin::Iso`). Converting a component's geometry (revolved, extruded, boxes, cylinders) to a
//! mesh is the 3D path's job, not the reporters': they only read triangles. A mesh may be bad
//! (an index past its vertices, a vertex that is not finite or farther than [`MAX_COORD`] from
//! the origin): such triangles are left out of every picture, never a panic.

use crate::kin::{Iso, Mesh};
use nalgebra::Point3;
use std::sync::Arc;

/// No machine is a kilometre long: a vertex farther out (in mm, on any axis) is a bad vertex.
pub const MAX_COORD: f64 = 1e6;

/// Whether a point can be drawn: finite, within [`MAX_COORD`].
pub fn drawable(p: &Point3<f64>) -> bool {
    p.coords.iter().all(|v| v.abs() <= MAX_COORD)
}

/// What a part is in a finding's scene: it picks the part's colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Role3 {
    /// The first of the two components that collide (the finding's first object, usually the
    /// one that moves into the other).
    CollidingA,
    /// The second of the two components that collide.
    CollidingB,
    /// Any other part that moves with an axis (turret, other tools, a sub-spindle).
    Moving,
    /// Any other part that stands still (bed, headstock, main chuck).
    Fixed,
    /// The stock, as it is at that moment.
    Stock,
}

impl Role3 {
    /// The role of part `i` of a picture of the contact between parts `a` and `b`; `moved`: it
    /// moves with an axis.
    pub fn of(i: usize, (a, b): (usize, usize), moved: bool) -> Role3 {
        if i == a {
            Role3::CollidingA
        } else if i == b {
            Role3::CollidingB
        } else if moved {
            Role3::Moving
        } else {
            Role3::Fixed
        }
    }

    /// The word the legend and the glTF material use.
    pub fn name(self) -> &'static str {
        match self {
            Role3::CollidingA => "colliding (first)",
            Role3::CollidingB => "colliding (second)",
            Role3::Moving => "other moving parts",
            Role3::Fixed => "fixed parts",
            Role3::Stock => "stock",
        }
    }

    /// Fill and outline colours (`#rrggbb`), after the 2D pictures' palette.
    pub fn colours(self) -> (&'static str, &'static str) {
        match self {
            Role3::CollidingA => ("#f2b766", "#8a5a14"),
            Role3::CollidingB => ("#b58ad6", "#5b2f7d"),
            Role3::Moving => ("#e6e1d6", "#857b67"),
            Role3::Fixed => ("#8c96a0", "#3d444d"),
            Role3::Stock => ("#b7c9dd", "#5a7896"),
        }
    }

    /// Every role, in legend order.
    pub const ALL: [Role3; 5] = [
        Role3::CollidingA,
        Role3::CollidingB,
        Role3::Moving,
        Role3::Fixed,
        Role3::Stock,
    ];
}

/// One part of the scene: a mesh in its own frame and where it stands.
#[derive(Clone, Debug, PartialEq)]
pub struct Part3 {
    /// What a machinist calls the component (`"T05 drill"`, `"sub chuck"`: `kin::words`).
    pub name: String,
    pub mesh: Arc<Mesh>,
    /// The mesh's pose in the machine frame.
    pub pose: Iso,
    pub role: Role3,
}

impl Part3 {
    /// The triangles that can be drawn: every index within the vertices, every vertex
    /// [`drawable`] in its own frame and once posed. Yields the three posed corners.
    pub fn world_triangles(&self) -> impl Iterator<Item = [Point3<f64>; 3]> + '_ {
        let vs = &self.mesh.vertices;
        let pose = self.pose;
        self.mesh.triangles.iter().filter_map(move |t| {
            let a = vs.get(t[0] as usize)?;
            let b = vs.get(t[1] as usize)?;
            let c = vs.get(t[2] as usize)?;
            if !(drawable(a) && drawable(b) && drawable(c)) {
                return None;
            }
            let w = [pose * a, pose * b, pose * c];
            w.iter().all(drawable).then_some(w)
        })
    }

    /// The box around the part's drawable triangles, posed; `None` when it has none.
    pub fn bounds(&self) -> Option<Box3> {
        let mut b = Box3::empty();
        for t in self.world_triangles() {
            for p in t {
                b.add(p);
            }
        }
        (!b.is_empty()).then_some(b)
    }
}

/// A finding's scene at first contact, in 3D.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot3 {
    /// The finding's message (the caption's first line when the picture is drawn alone).
    pub title: String,
    /// The physical line of the finding.
    pub line: u32,
    /// Machine time at first contact, seconds from program start.
    pub time_s: Option<f64>,
    /// The parts, posed. At most one should have each colliding role.
    pub parts: Vec<Part3>,
    /// The first point of contact in the machine frame, when the check knows it.
    pub contact: Option<Point3<f64>>,
}

impl Snapshot3 {
    /// The part that has `role`, first found.
    pub fn part(&self, role: Role3) -> Option<&Part3> {
        self.parts.iter().find(|p| p.role == role)
    }

    /// The contact point, when it is [`drawable`].
    pub fn contact(&self) -> Option<Point3<f64>> {
        self.contact.filter(drawable)
    }

    /// The box around every drawable triangle and the contact point.
    pub fn bounds(&self) -> Box3 {
        let mut b = Box3::empty();
        for p in &self.parts {
            if let Some(pb) = p.bounds() {
                b.union(&pb);
            }
        }
        if let Some(c) = self.contact() {
            b.add(c);
        }
        b
    }
}

/// An axis-aligned box in the machine frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Box3 {
    pub min: Point3<f64>,
    pub max: Point3<f64>,
}

impl Box3 {
    pub fn empty() -> Box3 {
        Box3 {
            min: Point3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY),
            max: Point3::new(f64::NEG_INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY),
        }
    }

    pub fn is_empty(&self) -> bool {
        (0..3).any(|i| self.min[i] > self.max[i])
    }

    pub fn add(&mut self, p: Point3<f64>) {
        if p.coords.iter().all(|v| v.is_finite()) {
            self.min = self.min.inf(&p);
            self.max = self.max.sup(&p);
        }
    }

    pub fn union(&mut self, o: &Box3) {
        if !o.is_empty() {
            self.add(o.min);
            self.add(o.max);
        }
    }

    /// The part of this box inside `o` (may be empty).
    pub fn clip(&self, o: &Box3) -> Box3 {
        Box3 {
            min: self.min.sup(&o.min),
            max: self.max.inf(&o.max),
        }
    }

    /// The longest side (0 for an empty box).
    pub fn size(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            (self.max - self.min).max()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> Arc<Mesh> {
        Arc::new(Mesh {
            vertices: vec![
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 0.0, 0.0),
                Point3::new(0.0, 1.0, 0.0),
                Point3::new(f64::NAN, 0.0, 0.0),
            ],
            // One good triangle, one with a vertex past the end, one with a NaN vertex.
            triangles: vec![[0, 1, 2], [0, 1, 9], [0, 1, 3]],
        })
    }

    #[test]
    fn bad_triangles_are_left_out_of_the_drawable_ones() {
        let p = Part3 {
            name: "t".into(),
            mesh: tri(),
            pose: Iso::translation(10.0, 0.0, 0.0),
            role: Role3::Fixed,
        };
        let ts: Vec<_> = p.world_triangles().collect();
        assert_eq!(ts.len(), 1);
        assert_eq!(ts[0][1], Point3::new(11.0, 0.0, 0.0));
        let b = p.bounds().unwrap();
        assert_eq!((b.min.x, b.max.x, b.max.y), (10.0, 11.0, 1.0));
    }

    #[test]
    fn a_non_finite_contact_point_is_no_contact_point() {
        let s = Snapshot3 {
            title: String::new(),
            line: 1,
            time_s: None,
            parts: vec![],
            contact: Some(Point3::new(0.0, f64::INFINITY, 0.0)),
        };
        assert_eq!(s.contact(), None);
        assert!(s.bounds().is_empty());
    }
}
