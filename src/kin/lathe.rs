//! A 2-axis lathe (the 2D model of a [`Machine`]) as a kinematic tree.
//!
//! ```text
//! bed (root)
//! ├── chuck            revolved chuck outline               role chuck
//! ├── tailstock        revolved tailstock outline           role tailstock
//! └── z_slide          axis Z (linear +z)
//!     └── x_slide      axis X (linear +x): its origin is the turret reference point
//!         └── turret   turret outline extruded              role structure
//!             └── t<station>_holder   mount: the tool's tip offset; holder extruded   role holder
//!                 └── t<station>_insert   insert extruded                              role cutter
//! ```
//!
//! The axis values are the turret reference point (X a radius), so the turret sits where the 2D
//! checker puts it and each tool's frame origin is its programmed point. Every tool is posed as
//! it stands when its station is active (in the working plane): a drum's index is not an axis of
//! the tree, and the 3D checker takes only the active station's tools (`Component::station`).
//!
//! The 2D outlines have no width; they are extruded along y, centred on the working plane: the
//! turret by its outline's x extent (a drum as wide as it is across), a holder or an insert by
//! the smaller side of its outline's box (a square shank, an insert as thick as it is small),
//! each at least [`MIN_HALF_WIDTH`].

use nalgebra::{Translation3, Unit, UnitQuaternion, Vector3};

use super::{Axis, AxisKind, Component, Geometry, Iso, Kinematics, Role};
use crate::geom::Polygon;
use crate::machine::Machine;

/// The thinnest half width of an extruded 2D outline, mm.
pub const MIN_HALF_WIDTH: f64 = 0.5;

fn half_width(p: &Polygon, across: bool) -> f64 {
    let b = p.aabb();
    let (w, h) = (b.max.x - b.min.x, b.max.y - b.min.y);
    let v = if across { w / 2.0 } else { w.min(h) / 2.0 };
    v.max(MIN_HALF_WIDTH)
}

fn extruded(p: &Polygon, across: bool) -> Geometry {
    Geometry::Extruded {
        outline: p.points().to_vec(),
        half_width: half_width(p, across),
    }
}

impl Kinematics {
    /// The tree of a 2-axis lathe: see the module documentation.
    pub fn from_lathe(m: &Machine) -> Kinematics {
        let linear = |name: &str, letter: char, dir: Vector3<f64>, a: &crate::machine::Axis, zero: f64| Axis {
            name: name.into(),
            letter,
            kind: AxisKind::Linear {
                dir: Unit::new_normalize(dir),
            },
            zero,
            travel: (a.min, a.max),
            rapid: a.rapid,
            path: 1,
        };
        let axes = vec![
            linear("x", 'X', Vector3::x(), &m.x, m.home.x),
            linear("z", 'Z', Vector3::z(), &m.z, m.home.y),
        ];
        let comp = |name: String, parent: Option<usize>, axis: Option<usize>, geometry, role| Component {
            name,
            parent,
            mount: Iso::identity(),
            axis,
            geometry,
            role,
            station: None,
            label: None,
        };
        let mut c = vec![comp("bed".into(), None, None, None, Role::Structure)];
        if let Some(ch) = &m.chuck {
            c.push(comp(
                "chuck".into(),
                Some(0),
                None,
                Some(Geometry::Revolved(ch.points().to_vec())),
                Role::Chuck,
            ));
        }
        if let Some(t) = &m.tailstock {
            c.push(comp(
                "tailstock".into(),
                Some(0),
                None,
                Some(Geometry::Revolved(t.points().to_vec())),
                Role::Tailstock,
            ));
        }
        let z = c.len();
        c.push(comp("z_slide".into(), Some(0), Some(1), None, Role::Structure));
        let x = c.len();
        c.push(comp("x_slide".into(), Some(z), Some(0), None, Role::Structure));
        let turret = c.len();
        c.push(comp(
            "turret".into(),
            Some(x),
            None,
            Some(extruded(&m.turret.outline, true)),
            Role::Structure,
        ));
        for t in &m.tools {
            let holder = c.len();
            c.push(Component {
                name: format!("t{}_holder", t.station),
                parent: Some(turret),
                mount: Iso::from_parts(Translation3::new(t.tip.x, 0.0, t.tip.y), UnitQuaternion::identity()),
                axis: None,
                geometry: Some(extruded(&t.holder, false)),
                role: Role::Holder,
                station: Some(t.station),
                label: None,
            });
            c.push(Component {
                name: format!("t{}_insert", t.station),
                parent: Some(holder),
                mount: Iso::identity(),
                axis: None,
                geometry: Some(extruded(&t.insert, false)),
                role: Role::Cutter,
                station: Some(t.station),
                label: None,
            });
        }
        let mut never_touch = Vec::new();
        for (i, a) in c.iter().enumerate() {
            if !matches!(a.role, Role::Chuck | Role::Tailstock) {
                continue;
            }
            for (j, b) in c.iter().enumerate() {
                if j == turret || matches!(b.role, Role::Holder | Role::Cutter) {
                    never_touch.push((i.min(j), i.max(j)));
                }
            }
        }
        never_touch.sort_unstable();
        Kinematics {
            axes,
            components: c,
            never_touch,
        }
    }
}
