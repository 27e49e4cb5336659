//! The turret index on the 3D path: a T word while the machine is out of its working plane
//! (Y, B or A off their start values, a live cutter in its own non-revolved cut, any condition
//! that sends a move to the 3D path) swings the turret's tools in 3D, checked by conservative
//! advancement with the rotary motion bound.
//!
//! **The index axis.** The drum's index is not an axis a program drives, and a machine file's tree
//! need not have one: its tools are posed as they stand when their station faces the spindle. The
//! checker adds one: the **carrier** is the nearest common ancestor of every component with a
//! `station` (the shipped machine's `turret`). The file's schema gives every axis a program
//! letter, so a tree never holds the index itself: the checker gives the carrier a rotary joint
//! of its own, in memory (the machine file is not changed), about the
//! line parallel to z through `[turret] axis` mm along +x from the carrier's parent's origin — the
//! 2D model's turret axis, with the reference point at that origin (the Y slide's, on the shipped
//! machine). Value 0 is the pose of the file, so every other move is posed exactly as before.
//!
//! **Angles.** As the 2D model's `Scene::station_angle`: while the active station goes from `from`
//! to `to` the short way (`motion::index_direction`), station `s` stands turned
//! `(s − a)·360°/n` about +z from the working position, `a` the (fractional) active station. The
//! 2D model folds the sign away (it maps into the radial section); in 3D it matters as soon as the
//! turret is off the spindle's centre line, which is what this module is for. A station's tools
//! are swept with the index axis at that angle; the carrier's own geometry (the drum) with the
//! angle it has turned since the T word.
//!
//! **Pairs.** Each `never_touch` pair of a swept component with one outside the carrier (chucks,
//! the tailstock, the sub-spindle), and each swept component against the in-process stock: all
//! `collision`, at the T word's line, "indexing T01 → T08 swings … into …", as the 2D sweep says.
//! A T word with everything at its start values never comes here: the 2D index sweep checks it,
//! exactly as before.

use std::sync::Arc;

use nalgebra::{Point3, Unit, Vector3};

use super::{pair_key, Three, STOCK};
use crate::collide3::{self, Advance, Path, MAX_PROBES};
use crate::finding::Kind;
use crate::interp::{ExtraMove, Move};
use crate::kin::{Axis, AxisId, AxisKind, CompId, Kinematics};
use crate::motion::{self, Timed};

/// The index axis of a tree, once found or added.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct IndexAxis {
    pub axis: AxisId,
    pub carrier: CompId,
}

/// The axis values of a move with the index axis going linearly between two values.
struct IndexPath {
    base: Vec<f64>,
    axis: AxisId,
    v0: f64,
    v1: f64,
}

impl Path for IndexPath {
    fn at(&self, u: f64, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.base);
        out[self.axis] = self.v0 + (self.v1 - self.v0) * u;
    }

    fn deltas(&self, u0: f64, u1: f64, out: &mut Vec<f64>) {
        out.clear();
        out.resize(self.base.len(), 0.0);
        out[self.axis] = (self.v1 - self.v0).abs() * (u1 - u0);
    }
}

/// The nearest common ancestor of every component with a station (or `None` without any).
pub(crate) fn carrier(k: &Kinematics) -> Option<CompId> {
    let chain = |c: CompId| {
        let mut v = vec![c];
        let mut p = k.components[c].parent;
        while let Some(q) = p {
            v.push(q);
            p = k.components[q].parent;
        }
        v
    };
    let mut common: Option<Vec<CompId>> = None;
    for (i, c) in k.components.iter().enumerate() {
        if c.station.is_none() {
            continue;
        }
        // Ancestors proper: a tool's own component is never the carrier of the others.
        let anc: Vec<CompId> = chain(i).into_iter().skip(1).collect();
        common = Some(match common {
            None => anc,
            Some(prev) => prev.into_iter().filter(|x| anc.contains(x)).collect(),
        });
    }
    // Chains run from the component up: the first common entry is the nearest.
    common.and_then(|c| c.first().copied())
}

/// Whether component `c` is `top` or lies under it.
fn under(k: &Kinematics, top: CompId, c: CompId) -> bool {
    c == top || k.is_ancestor(top, c)
}

impl Three {
    /// Add the index axis to the carrier (see the module docs), once. `None`: the tree has no tools
    /// by station, or a program axis already moves the carrier (a milling head's B swivel): the T
    /// word is then swept in 2D.
    pub(super) fn index_axis(&mut self, turret_axis: f64) -> Option<IndexAxis> {
        if let Some(ix) = self.index {
            return Some(ix);
        }
        let carrier = carrier(&self.kin)?;
        let c = &self.kin.components[carrier];
        if c.axis.is_some() {
            // A program letter drives it (a B head's swivel): not the drum's index.
            return None;
        }
        // The joint's line is in the carrier's parent frame after its mount.
        let inv = c.mount.inverse();
        let origin = inv * Point3::new(turret_axis, 0.0, 0.0);
        let dir = Unit::new_normalize(inv.rotation * Vector3::z());
        let mut k: Kinematics = (*self.kin).clone();
        let axis = k.axes.len();
        k.axes.push(Axis {
            name: "turret_index".into(),
            // No program letter drives it.
            letter: '\0',
            kind: AxisKind::Rotary { origin, dir },
            zero: 0.0,
            travel: (f64::NEG_INFINITY, f64::INFINITY),
            rapid: 0.0,
            path: 1,
        });
        k.components[carrier].axis = Some(axis);
        self.kin = Arc::new(k);
        self.start.push(0.0);
        let ix = IndexAxis { axis, carrier };
        self.index = Some(ix);
        Some(ix)
    }
}

impl super::Checker<'_> {
    /// A T word on the 3D path (the caller decided the machine is out of its working plane).
    /// Falls back to the 2D sweep when the tree has no turret to turn.
    pub(in crate::check) fn three_index(&mut self, m: &Move, e: Option<&ExtraMove>, item: &Timed, from: u32, to: u32) {
        let n = self.scene.stations;
        let dir = motion::index_direction(from, to, n);
        if dir == 0 || self.scene.gang {
            return;
        }
        let Some(mut three) = self.three.take() else { return };
        let Some(ix) = three.index_axis(self.scene.turret_axis) else {
            self.three = Some(three);
            self.index_sweep(m, item, from, to);
            return;
        };
        self.indexed = true;
        self.three_index_with(&three, ix, m, e, item, (from, to, dir, n));
        self.three = Some(three);
    }

    fn three_index_with(
        &mut self,
        three: &Three,
        ix: IndexAxis,
        m: &Move,
        e: Option<&ExtraMove>,
        item: &Timed,
        (from, to, dir, n): (u32, u32, i64, u32),
    ) {
        let k = three.kin.clone();
        let mut base = Vec::new();
        three.values(m, e, item, 0.0, &mut base);
        let zero = three.start[ix.axis];
        let step_deg = 360.0 / n.max(1) as f64;
        // Groups of swept components with their index values over the T word: each station's
        // tools, and the carrier's own parts (no station) by the angle turned so far.
        let mut groups: Vec<(Option<u32>, f64, f64)> = vec![(None, zero, zero - dir as f64 * step_deg)];
        let mut stations: Vec<u32> = k
            .components
            .iter()
            .enumerate()
            .filter(|(i, c)| c.station.is_some() && under(&k, ix.carrier, *i))
            .filter_map(|(_, c)| c.station)
            .collect();
        stations.sort_unstable();
        stations.dedup();
        for s in stations {
            let angle = |a: f64| zero + (s as f64 - a) * step_deg;
            groups.push((Some(s), angle(from as f64), angle(from as f64 + dir as f64)));
        }
        let stock = self.machine.stock.is_some();
        let tol = self.settings.tolerance_mm;
        for (station, v0, v1) in groups {
            let swept: Vec<CompId> = (0..k.components.len())
                .filter(|&i| under(&k, ix.carrier, i) && three.shapes[i].is_some())
                .filter(|&i| k.components[i].station == station)
                .collect();
            if swept.is_empty() {
                continue;
            }
            let path = IndexPath {
                base: base.clone(),
                axis: ix.axis,
                v0,
                v1,
            };
            let mut pairs: Vec<(CompId, usize)> = Vec::new();
            for &(a, b) in &k.never_touch {
                for (x, y) in [(a, b), (b, a)] {
                    if swept.contains(&x) && !under(&k, ix.carrier, y) && three.shapes[y].is_some() {
                        pairs.push((x, y));
                    }
                }
            }
            if stock {
                pairs.extend(swept.iter().map(|&x| (x, STOCK)));
            }
            for (a, b) in pairs {
                let res = if b == STOCK {
                    self.stock_advance(three, &path, None, a)
                } else {
                    let (sa, sb) = (three.shapes[a].as_ref().unwrap(), three.shapes[b].as_ref().unwrap());
                    let (adv, _, probes) =
                        collide3::first_contact_from(&k, (a, sa), (b, sb), &path, 2.0 * tol, tol, 0.0);
                    (adv, probes)
                };
                if res.1 == 0 {
                    self.stats.pair_tests_skipped += 1;
                }
                self.stats.pair_tests += res.1;
                match res.0 {
                    Advance::Clear => {}
                    Advance::Unchecked { u } => {
                        let t = item.t0 + u * item.duration;
                        self.budget.push((
                            m.line,
                            format!(
                                "the 3D check of {} while indexing stopped after {MAX_PROBES} probes at {t:.3} s: the rest of the index is unchecked",
                                self.names(&k, a, b)
                            ),
                        ));
                    }
                    Advance::Contact { u, hit } => {
                        let key = pair_key(a, b, Kind::Collision);
                        let t = item.t0 + u * item.duration;
                        if self.episodes.is_open(key) {
                            self.episodes.extend(key, m.line, t, hit.depth, false);
                        } else {
                            let mut c = self.contact3(three, &path, m, a, b, Kind::Collision, u, hit, t);
                            let (x, y) = super::mover_first(&k, a, b);
                            c.message = format!(
                                "indexing T{from:02} → T{to:02} swings the {} into the {}",
                                self.words3(&k, x),
                                self.words3(&k, y)
                            );
                            if let Some(s) = c.snapshot3.as_mut() {
                                s.title = c.message.clone();
                            }
                            self.episodes.contact(key, c);
                        }
                        // The deepest point of the swing, at a few instants after first contact.
                        for j in 1..=super::DEPTH_SAMPLES {
                            let uu = u + (1.0 - u) * j as f64 / super::DEPTH_SAMPLES as f64;
                            self.stats.pair_tests += 1;
                            if let Some(h) = self.probe3_sample(three, &path, (a, b), uu, key) {
                                self.episodes
                                    .extend(key, m.line, item.t0 + uu * item.duration, h.depth, false);
                            }
                        }
                        self.episodes.clear(key);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn turn_mill_kin() -> Kinematics {
        let root = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"));
        let path = root.join("machines/turn-mill.toml");
        let dir = path.parent().unwrap().to_path_buf();
        let text = std::fs::read_to_string(&path).unwrap();
        let m = crate::machine::from_toml_with(&text, "turn-mill.toml", &move |name: &str| {
            std::fs::read(dir.join(name)).map_err(|e| e.to_string())
        })
        .unwrap();
        (*m.kinematics.unwrap()).clone()
    }

    #[test]
    fn the_carrier_of_the_shipped_machine_is_its_turret() {
        let k = turn_mill_kin();
        let c = carrier(&k).unwrap();
        assert_eq!(k.components[c].name, "turret");
    }

    #[test]
    fn a_tree_without_stations_has_no_carrier() {
        let mut k = turn_mill_kin();
        for c in &mut k.components {
            c.station = None;
        }
        assert_eq!(carrier(&k), None);
    }

    #[test]
    fn the_added_index_axis_turns_a_tool_about_the_2d_turret_axis() {
        let k = turn_mill_kin();
        let mut three = Three::new(Arc::new(k), 0.05);
        let ix = three.index_axis(140.0).unwrap();
        let k = three.kin.clone();
        let drill = k.component("t8_drill").unwrap();
        let mut poser = crate::kin::Poser::new(&k);
        let mut v = three.start.clone();
        // Reference point at x 100, y 20: the turret axis at x 240, y 20.
        v[k.axis_by_letter('X').unwrap()] = 100.0;
        v[k.axis_by_letter('Y').unwrap()] = 20.0;
        v[k.axis_by_letter('Z').unwrap()] = 0.0;
        poser.pose(&k, &v);
        let p0 = poser.world(drill) * Point3::origin();
        assert!((p0 - Point3::new(-10.0, 20.0, 0.0)).norm() < 1e-9, "{p0}");
        // A quarter turn about +z: the point 250 mm in -x of the axis goes to 250 mm in -y.
        v[ix.axis] = 90.0;
        poser.pose(&k, &v);
        let p1 = poser.world(drill) * Point3::origin();
        assert!((p1 - Point3::new(240.0, 20.0 - 250.0, 0.0)).norm() < 1e-9, "{p1}");
        // Value 0 poses everything as the file does.
        v[ix.axis] = 0.0;
        poser.pose(&k, &v);
        assert!((poser.world(drill) * Point3::origin() - p0).norm() < 1e-12);
    }
}
