//! The kinematic machine (pose transforms from servo-axis values): a tree of components, each posed in its parent's
//! frame by a fixed mount and at most one servo axis, with a geometry of its own.
//!
//! Frames: the machine frame extends the spindle frame of the 2D checker to 3D: `z` along the
//! spindle axis (0 at the main chuck's jaw faces, + toward the tailstock), `x` in the working
//! plane (+ toward the turret), `y = z × x` (right-handed). Lengths are mm, rotary axis values
//! degrees. Linear axis values are the positions the 2D checker uses: X and Z are the turret
//! reference point in the spindle frame (x as a radius), so a 2-axis machine's poses equal the
//! 2D model's.
//!
//! Two models, as in the pose-transform method: the **initial model** is each component's mount and geometry in its own
//! frame (never changed after loading); the **real-time model** is each component's world pose,
//! which [`Poser::pose`] recomputes only for the components whose own axis, or an ancestor's,
//! changed value since the last call.

use nalgebra::{Isometry3, Point3, Translation3, Unit, UnitQuaternion, Vector3};
use std::sync::Arc;

use crate::geom::P2;

pub mod lathe;
pub mod load;
pub mod shape;
pub mod station;
pub mod stl;
pub mod words;

pub type Iso = Isometry3<f64>;

/// Index of a component in [`Kinematics::components`].
pub type CompId = usize;
/// Index of an axis in [`Kinematics::axes`].
pub type AxisId = usize;

/// How an axis moves the component it drives, in the parent's frame (after the mount).
#[derive(Clone, Debug, PartialEq)]
pub enum AxisKind {
    /// Translation by `value` mm along `dir`.
    Linear { dir: Unit<Vector3<f64>> },
    /// Rotation by `value` degrees about the line through `origin` along `dir` (right hand).
    Rotary {
        origin: Point3<f64>,
        dir: Unit<Vector3<f64>>,
    },
}

/// A servo axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Axis {
    /// The machine file's name for it (`"x"`, `"sub_z"`, `"c1"`).
    pub name: String,
    /// The address letter that drives it in a program (`'X'`, `'Y'`, `'C'`, `'B'`, …).
    pub letter: char,
    pub kind: AxisKind,
    /// Value at program start.
    pub zero: f64,
    /// Travel (min, max): mm or degrees. A rotary axis without limits has (-inf, inf).
    pub travel: (f64, f64),
    /// Rapid rate: mm/min or degrees/min.
    pub rapid: f64,
    /// The program path whose lines drive it (1 on a one-path machine; `[[paths]]`,
    /// docs/paths.md): its letter is that path's.
    pub path: u32,
}

/// A component's geometry in its own frame.
#[derive(Clone, Debug, PartialEq)]
pub enum Geometry {
    /// A triangle mesh (from an STL file, or built from a primitive).
    Mesh(Arc<Mesh>),
    /// An outline in (r = `P2::x` ≥ 0, z = `P2::y`) revolved about the component's z axis.
    Revolved(Vec<P2>),
    /// An outline in the component's (x, z) plane (`P2::x` = x, `P2::y` = z), extruded along y
    /// from `-half_width` to `+half_width`.
    Extruded { outline: Vec<P2>, half_width: f64 },
    /// A box from `min` to `max`.
    Cuboid { min: Point3<f64>, max: Point3<f64> },
    /// A cylinder about the component's z axis from `z0` to `z1`.
    Cylinder { radius: f64, z0: f64, z1: f64 },
    /// A milling cutter about the component's z axis: its point at `z0`, its flutes up to `z1`
    /// (`z0 < z1`), of this radius, with this end (a ball, a bull nose's corners, a drill's
    /// cone; `cylinder = { …, end = … }` in a machine file, or a job's `mill`). Its mesh is the
    /// true profile circumscribed ([`shape::cutter_outline`] revolved); the milled stock cuts with
    /// the true shape (`grid::Cutter`).
    Cutter {
        end: crate::grid::CutterKind,
        radius: f64,
        z0: f64,
        z1: f64,
    },
}

/// A triangle mesh: counter-clockwise triangles seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub vertices: Vec<Point3<f64>>,
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// The enclosed volume by the divergence theorem (positive for a closed mesh whose triangles
    /// run counter-clockwise seen from outside).
    pub fn volume(&self) -> f64 {
        let mut v = 0.0;
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize].coords);
            v += a.dot(&b.cross(&c));
        }
        v / 6.0
    }

    /// The mesh with every triangle's winding reversed.
    pub fn flipped(mut self) -> Mesh {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        self
    }
}

/// What a component is to the checker (which rules apply to its pairs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Machine structure: bed, slides, housings, turret body, spindle noses.
    Structure,
    /// A chuck (body and jaws) or a collet on a spindle.
    Chuck,
    Tailstock,
    /// A tool holder (static or live).
    Holder,
    /// The cutting part of a tool (insert, drill, end mill): it may cut the stock.
    Cutter,
}

/// A component of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Component {
    pub name: String,
    /// Parents come before their children in [`Kinematics::components`].
    pub parent: Option<CompId>,
    /// Placement in the parent's frame, before the axis moves it.
    pub mount: Iso,
    pub axis: Option<AxisId>,
    pub geometry: Option<Geometry>,
    pub role: Role,
    /// For a tool: the turret station it sits in.
    pub station: Option<u32>,
    /// What a machinist calls it in a report (the machine file's `label`), when given; else
    /// [`words::words`] derives it from the name, role and station.
    pub label: Option<String>,
}

/// The whole tree and the pairs that must never touch.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Kinematics {
    pub axes: Vec<Axis>,
    /// Topologically ordered: every parent index is smaller than its children's.
    pub components: Vec<Component>,
    /// Pairs of components whose geometries must never overlap (`a < b`).
    pub never_touch: Vec<(CompId, CompId)>,
}

impl Kinematics {
    /// This tree with every component revolved from the machine's chuck outline `old`
    /// (`revolved = "chuck"` in the machine file) revolved from `new` instead: the chuck a job
    /// sets up (its jaws, or its chuck outline). None when no component is revolved from `old`.
    pub fn with_chuck(&self, old: &[P2], new: &[P2]) -> Option<Kinematics> {
        let mut k = self.clone();
        let mut changed = false;
        for c in &mut k.components {
            if let Some(Geometry::Revolved(pts)) = &mut c.geometry {
                if pts.as_slice() == old {
                    *pts = new.to_vec();
                    changed = true;
                }
            }
        }
        changed.then_some(k)
    }

    /// The axis a program letter drives, if the machine has one.
    pub fn axis_by_letter(&self, letter: char) -> Option<AxisId> {
        self.axes.iter().position(|a| a.letter == letter)
    }

    /// Whether `a` is a proper ancestor of `c`.
    pub fn is_ancestor(&self, a: CompId, c: CompId) -> bool {
        let mut p = self.components.get(c).and_then(|c| c.parent);
        // Parents come first, so the walk ends within `c` steps.
        while let Some(x) = p {
            if x == a {
                return true;
            }
            p = self.components.get(x).and_then(|c| c.parent);
        }
        false
    }

    /// The component named `name`.
    pub fn component(&self, name: &str) -> Option<CompId> {
        self.components.iter().position(|c| c.name == name)
    }

    /// Per component, the paths whose axes carry it, as a bit mask (bit `p` for path `p`): its
    /// own axis's and every ancestor's, except a **spindle's** turning (a rotary axis about the
    /// spindle axis, the machine frame's z line, where the tree's start pose has it: C or A).
    /// A spindle turns its chuck about itself, which the 2D sections treat as revolved: the
    /// chuck belongs to no carrier and every path sees it (at its start angle when another path
    /// drives it). 0 for a part fixed to the machine frame.
    pub fn path_masks(&self) -> Vec<u32> {
        let poser = Poser::new(self);
        let mut out: Vec<u32> = Vec::with_capacity(self.components.len());
        for (i, c) in self.components.iter().enumerate() {
            let mut mask = c.parent.filter(|&p| p < i).map_or(0, |p| out[p]);
            if let Some(a) = c.axis.and_then(|a| self.axes.get(a)) {
                let spindle = match &a.kind {
                    AxisKind::Rotary { origin, dir } => {
                        let frame = c.parent.map_or(Iso::identity(), |p| *poser.world(p)) * c.mount;
                        let (o, d) = (frame * origin, frame.rotation * dir.into_inner());
                        o.x.abs() < 1e-9 && o.y.abs() < 1e-9 && d.x.abs() < 1e-9 && d.y.abs() < 1e-9
                    }
                    AxisKind::Linear { .. } => false,
                };
                if !spindle {
                    mask |= 1 << a.path.min(31);
                }
            }
            out.push(mask);
        }
        out
    }

    /// Whether the axes of more than one path drive this tree (a machine with two tool carriers
    /// in 3D, docs/paths.md).
    pub fn is_multi_path(&self) -> bool {
        self.axes.iter().any(|a| a.path != 1)
    }

    /// The never-touch pairs whose two parts are moved by the axes of more than one path
    /// together: no path's own check sees them (`for_path` leaves one of the two out); the
    /// carriers' check over the machine's one clock does (`paths::cross3`).
    pub fn cross_pairs(&self) -> Vec<(CompId, CompId)> {
        let masks = self.path_masks();
        self.never_touch
            .iter()
            .copied()
            .filter(|&(a, b)| (masks[a] | masks[b]).count_ones() > 1)
            .collect()
    }

    /// The tree path `p`'s own check runs on: the parts that only path `p`'s axes carry (or none,
    /// [`Kinematics::path_masks`]),
    /// the other paths' letters taken off their axes (their values stay at their start), and the
    /// never-touch pairs among the parts kept. Every pair this leaves out is moved by two paths'
    /// axes: [`Kinematics::cross_pairs`]. On a one-path tree, path 1's view is the tree.
    pub fn for_path(&self, p: u32) -> Kinematics {
        let own = 1u32 << p.min(31);
        let keep: Vec<bool> = self.path_masks().iter().map(|m| m & !own == 0).collect();
        let mut new_id = vec![usize::MAX; self.components.len()];
        let mut components = Vec::new();
        for (i, c) in self.components.iter().enumerate() {
            if !keep[i] {
                continue;
            }
            // A kept part's parent is kept: it is moved by no more paths than its child.
            let mut c = c.clone();
            c.parent = c.parent.map(|q| new_id[q]).filter(|&q| q != usize::MAX);
            new_id[i] = components.len();
            components.push(c);
        }
        let axes = self
            .axes
            .iter()
            .map(|a| {
                let mut a = a.clone();
                if a.path != p {
                    a.letter = '\0';
                }
                a
            })
            .collect();
        let never_touch = self
            .never_touch
            .iter()
            .filter(|&&(a, b)| keep[a] && keep[b])
            .map(|&(a, b)| {
                let (x, y) = (new_id[a], new_id[b]);
                (x.min(y), x.max(y))
            })
            .collect();
        Kinematics {
            axes,
            components,
            never_touch,
        }
    }

    /// `c` and every component below it.
    pub fn subtree(&self, c: CompId) -> Vec<CompId> {
        (0..self.components.len())
            .filter(|&x| x == c || self.is_ancestor(c, x))
            .collect()
    }

    /// Every axis at its program-start value.
    pub fn start_values(&self) -> Vec<f64> {
        self.axes.iter().map(|a| a.zero).collect()
    }

    /// The motion of one component relative to its parent for an axis value.
    fn joint(&self, c: &Component, values: &[f64]) -> Iso {
        let Some(a) = c.axis else {
            return Iso::identity();
        };
        let v = values.get(a).copied().unwrap_or(0.0);
        match &self.axes[a].kind {
            AxisKind::Linear { dir } => {
                Iso::from_parts(Translation3::from(dir.into_inner() * v), UnitQuaternion::identity())
            }
            AxisKind::Rotary { origin, dir } => {
                let rot = UnitQuaternion::from_axis_angle(dir, v.to_radians());
                let o = origin.coords;
                // Rotate about the line through `origin`: translate to it, rotate, translate back.
                Iso::from_parts(Translation3::from(o - rot * o), rot)
            }
        }
    }
}

/// The real-time model: every component's world pose for the last axis values.
#[derive(Clone, Debug)]
pub struct Poser {
    values: Vec<f64>,
    world: Vec<Iso>,
    /// How many components were re-posed by the last [`Poser::pose`] (for stats and tests).
    pub last_reposed: usize,
    /// The components kept posed ([`Poser::focused`]): these and their ancestors; `None`: all.
    only: Option<Vec<bool>>,
    /// Per axis, whether the last [`Poser::pose`] changed it; per component, whether it was
    /// re-posed (kept between calls: posing is a checker's inner loop).
    changed: Vec<bool>,
    dirty: Vec<bool>,
}

impl Poser {
    /// Poses every component at the axes' start values.
    pub fn new(k: &Kinematics) -> Poser {
        let values = k.start_values();
        let mut p = Poser {
            values: values.clone(),
            world: vec![Iso::identity(); k.components.len()],
            last_reposed: 0,
            only: None,
            changed: Vec::new(),
            dirty: Vec::new(),
        };
        p.repose(k, true);
        p
    }

    /// A poser that keeps only `parts` and their ancestors posed (a query about a few parts of a
    /// large tree: a check's probes move the turret, whose every tool a full pose would place).
    /// [`Poser::world`] of any other component is not kept up to date.
    pub fn focused(k: &Kinematics, parts: &[CompId]) -> Poser {
        let mut only = vec![false; k.components.len()];
        for &c in parts {
            let mut p = Some(c);
            while let Some(q) = p.filter(|&q| q < only.len() && !only[q]) {
                only[q] = true;
                p = k.components[q].parent;
            }
        }
        let mut p = Poser {
            values: k.start_values(),
            world: vec![Iso::identity(); k.components.len()],
            last_reposed: 0,
            only: Some(only),
            changed: Vec::new(),
            dirty: Vec::new(),
        };
        p.repose(k, true);
        p
    }

    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// A component's world pose.
    pub fn world(&self, c: CompId) -> &Iso {
        debug_assert!(self.only.as_ref().map_or(true, |o| o[c]), "component {c} is not posed");
        &self.world[c]
    }

    /// Poses the tree at `values` (one per axis), re-posing only the components whose axis or an
    /// ancestor's axis changed. Returns how many were re-posed.
    pub fn pose(&mut self, k: &Kinematics, values: &[f64]) -> usize {
        self.changed.clear();
        for (a, v) in self.values.iter_mut().enumerate() {
            let new = values.get(a).copied().unwrap_or(0.0);
            self.changed.push(new != *v);
            *v = new;
        }
        self.repose(k, false)
    }

    /// Re-pose the components whose axis or an ancestor's changed (`self.changed`), or all.
    fn repose(&mut self, k: &Kinematics, all: bool) -> usize {
        let mut dirty = std::mem::take(&mut self.dirty);
        dirty.clear();
        dirty.resize(k.components.len(), false);
        let changed = &self.changed;
        let mut n = 0;
        for (i, c) in k.components.iter().enumerate() {
            if self.only.as_ref().is_some_and(|o| !o[i]) {
                continue;
            }
            let own = || c.axis.is_some_and(|a| changed.get(a).copied().unwrap_or(true));
            let inherited = c.parent.is_some_and(|p| dirty[p]);
            if !(all || inherited || own()) {
                continue;
            }
            dirty[i] = true;
            n += 1;
            let parent = c.parent.map_or(Iso::identity(), |p| self.world[p]);
            self.world[i] = parent * c.mount * k.joint(c, &self.values);
        }
        self.dirty = dirty;
        self.last_reposed = n;
        n
    }
}
