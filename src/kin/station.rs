//! A station's 3D parts from a milling tool given by its sizes (docs/tools.md,
//! "Milling tools"): a job's `mill = { … }` on a machine with a kinematic tree.
//!
//! Where a station's tool sits in the tree: the station's components (those with its `station`)
//! hang under the turret; the cutter changes with the tool, the driven unit (the live holder
//! block, the frames) stays on the turret. So the station's **cutter** components (role
//! `cutter`, and anything under them) leave the tree, and the new tool's parts come in under the
//! parent of the station's top component (on the shipped machine: `turret`), posed at the tool's
//! programmed point as the shipped machine poses its live tools: a radial tool turned a quarter
//! about +y (its axis along +x), an axial one as it is (its axis along +z). A station with no
//! components takes the parent of another station's top component. The new parts never touch
//! what the station's parts of the same role never touch (or, for a station without them, what
//! the other stations' parts of that role never touch).

use nalgebra::{Translation3, UnitQuaternion, Vector3};

use super::{CompId, Component, Geometry, Iso, Kinematics, Role};
use crate::geom::P2;
use crate::tooling::milling::{Live, MillTool};

/// The names the new parts take (`t{station}_…`).
const PARTS: [&str; 4] = ["live", "cutter", "shank", "holder"];

/// The tree with station `station`'s cutter replaced by the milling tool `m` whose programmed
/// point is `tip` (`[x, z]` from the turret reference point). `None` when the tree has no
/// station to hang it from (no component carries a station).
pub fn fit(k: &Kinematics, station: u32, tip: P2, m: &MillTool) -> Option<Kinematics> {
    let n = k.components.len();
    // A job's tools are path 1's (docs/paths.md): on a tree several paths drive, another
    // carrier's station of the same number is not this one.
    let masks = k.path_masks();
    let ours = |c: CompId| masks[c] & !(1 << 1) == 0;
    let top_of = |mut c: CompId| {
        while let Some(p) = k.components[c].parent {
            if k.components[p].station != k.components[c].station {
                break;
            }
            c = p;
        }
        c
    };
    let first = (0..n)
        .find(|&c| k.components[c].station == Some(station) && ours(c))
        .or_else(|| (0..n).find(|&c| k.components[c].station.is_some() && ours(c)))?;
    let anchor = top_of(first);
    let parent = k.components[anchor].parent?;
    // The station's cutters and everything under them leave.
    let mut gone = vec![false; n];
    for c in 0..n {
        let comp = &k.components[c];
        gone[c] = (comp.station == Some(station) && comp.role == Role::Cutter && ours(c))
            || comp.parent.is_some_and(|p| gone[p]);
    }
    // Partners by role: of this station's parts, else of every station's.
    let partners = |role: Role, own: bool| -> Vec<CompId> {
        let mut out: Vec<CompId> = Vec::new();
        for &(a, b) in &k.never_touch {
            for (x, y) in [(a, b), (b, a)] {
                let c = &k.components[x];
                let fits = c.role == role && c.station.is_some() && ours(x) && (!own || c.station == Some(station));
                if fits && !gone[y] && k.components[y].station.is_none() && !out.contains(&y) {
                    out.push(y);
                }
            }
        }
        out
    };
    let with = |role: Role| {
        let own = partners(role, true);
        if own.is_empty() {
            partners(role, false)
        } else {
            own
        }
    };
    let (cut_partners, hold_partners) = (with(Role::Cutter), with(Role::Holder));
    // The kept components, renumbered (parents stay before children).
    let mut map = vec![None; n];
    let mut comps: Vec<Component> = Vec::with_capacity(n + PARTS.len());
    for c in 0..n {
        if gone[c] {
            continue;
        }
        let mut comp = k.components[c].clone();
        comp.parent = comp.parent.and_then(|p| map[p]);
        map[c] = Some(comps.len());
        comps.push(comp);
    }
    let parent = map[parent]?;
    let taken: Vec<String> = comps.iter().map(|c| c.name.clone()).collect();
    let name = |part: &str| {
        let base = format!("t{station}_{part}");
        if taken.contains(&base) {
            format!("{base}_job")
        } else {
            base
        }
    };
    let turn = match m.live {
        Live::Radial => UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f64::consts::FRAC_PI_2),
        Live::Axial => UnitQuaternion::identity(),
    };
    let frame = comps.len();
    let part = |name: String, parent: Option<CompId>, mount: Iso, geometry: Option<Geometry>, role: Role| Component {
        name,
        parent,
        mount,
        axis: None,
        geometry,
        role,
        station: Some(station),
        label: None,
    };
    comps.push(part(
        name(PARTS[0]),
        Some(parent),
        Iso::from_parts(Translation3::new(tip.x, 0.0, tip.y), turn),
        None,
        Role::Holder,
    ));
    let (fl, so) = (m.flute_length, m.stick_out);
    // The true end (its mesh circumscribes it); a flat end, a tap and a flat-bottomed drill are
    // cylinders.
    let cutter = match m.grid_kind() {
        crate::grid::CutterKind::Flat | crate::grid::CutterKind::Tap { .. } => Geometry::Cylinder {
            radius: m.diameter / 2.0,
            z0: 0.0,
            z1: fl,
        },
        end => Geometry::Cutter {
            end,
            radius: m.diameter / 2.0,
            z0: 0.0,
            z1: fl,
        },
    };
    let id = Iso::identity();
    let mut new = vec![(comps.len(), Role::Cutter)];
    comps.push(part(name(PARTS[1]), Some(frame), id, Some(cutter), Role::Cutter));
    if so > fl {
        new.push((comps.len(), Role::Holder));
        let g = Geometry::Cylinder {
            radius: m.shank / 2.0,
            z0: fl,
            z1: so,
        };
        comps.push(part(name(PARTS[2]), Some(frame), id, Some(g), Role::Holder));
    }
    new.push((comps.len(), Role::Holder));
    let g = Geometry::Cylinder {
        radius: m.holder_diameter / 2.0,
        z0: so,
        z1: so + m.holder_length,
    };
    comps.push(part(name(PARTS[3]), Some(frame), id, Some(g), Role::Holder));
    let mut pairs: Vec<(CompId, CompId)> = k
        .never_touch
        .iter()
        .filter_map(|&(a, b)| Some((map[a]?, map[b]?)))
        .collect();
    for (c, role) in new {
        let with = if role == Role::Cutter {
            &cut_partners
        } else {
            &hold_partners
        };
        for &p in with {
            if let Some(p) = map[p] {
                pairs.push((p.min(c), p.max(c)));
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    Some(Kinematics {
        axes: k.axes.clone(),
        components: comps,
        never_touch: pairs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tooling::milling::{build, MillSpec};

    fn turn_mill() -> crate::machine::Machine {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("machines/turn-mill.toml");
        let dir = path.parent().unwrap().to_path_buf();
        let text = std::fs::read_to_string(&path).unwrap();
        crate::machine::from_toml_with(&text, "turn-mill.toml", &move |n: &str| {
            std::fs::read(dir.join(n)).map_err(|e| e.to_string())
        })
        .unwrap()
    }

    fn drill() -> MillTool {
        let s = MillSpec {
            kind: "drill".into(),
            diameter: 8.0,
            flute_length: 40.0,
            stick_out: 50.0,
            corner_radius: None,
            point_angle: None,
            pitch: None,
            shank: None,
            holder_diameter: 35.0,
            holder_length: 25.0,
            live: Live::Radial,
        };
        build(&s).unwrap().1
    }

    /// Station 12's end mill leaves; the drill, its shank and its holder come in under the
    /// turret at the new point, never touching what the old cutter and holders never touched;
    /// the live block (the driven unit) stays.
    #[test]
    fn a_milling_tool_replaces_the_station_cutter_and_keeps_its_pairs() {
        let m = turn_mill();
        let k = m.kinematics.as_ref().unwrap();
        let f = fit(k, 12, P2::new(-130.0, 0.0), &drill()).unwrap();
        let id = |n: &str| f.component(n).unwrap_or_else(|| panic!("{n}"));
        assert!(f.component("t12_mill").is_none());
        assert!(f.component("t12_live_block").is_some());
        let (cut, chuck) = (id("t12_cutter"), id("main_chuck"));
        assert_eq!(f.components[cut].role, Role::Cutter);
        assert_eq!(f.components[cut].station, Some(12));
        assert!(
            f.never_touch.contains(&(cut.min(chuck), cut.max(chuck))),
            "{:?}",
            f.never_touch
        );
        let hold = id("t12_holder_job");
        assert!(f.never_touch.contains(&(hold.min(chuck), hold.max(chuck))));
        // Parents first; the frame under the turret at the point, turned a quarter about +y.
        for (i, c) in f.components.iter().enumerate() {
            assert!(c.parent.is_none_or(|p| p < i), "{}", c.name);
        }
        let frame = f.components[cut].parent.unwrap();
        assert_eq!(f.components[frame].parent, Some(id("turret")));
        let tip = f.components[frame].mount * nalgebra::Point3::origin();
        assert!((tip - nalgebra::Point3::new(-130.0, 0.0, 0.0)).norm() < 1e-12);
        let axis = f.components[frame].mount.rotation * Vector3::z();
        assert!((axis - Vector3::x()).norm() < 1e-12);
        // Every pair of the machine's not about its old cutter is still there (by names).
        let name = |k: &Kinematics, c: CompId| k.components[c].name.clone();
        let have: Vec<(String, String)> = f.never_touch.iter().map(|&(a, b)| (name(&f, a), name(&f, b))).collect();
        for &(a, b) in &k.never_touch {
            if name(k, a) != "t12_mill" && name(k, b) != "t12_mill" {
                assert!(
                    have.contains(&(name(k, a), name(k, b))),
                    "{} × {}",
                    name(k, a),
                    name(k, b)
                );
            }
        }
    }
}
