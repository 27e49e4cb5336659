//! The scene: the machine's parts posed in the working plane.
//!
//! Static, revolved parts (chuck, tailstock, the stock) are outlines in the half plane `x ≥ 0`;
//! their section through the working plane is the outline and its mirror about the axis.
//! Moving parts translate with the turret reference point `R`: the turret body (`R` + outline),
//! the active tool's insert and holder (`R + tip` + shape). Tools in the other stations sit on the
//! turret rotated about its axis, out of the working plane; they are mapped into the radial
//! section `(r, z)` (docs/checking.md), which is exact for collisions with revolved parts.

mod cleared;
pub mod section;
pub mod snapshot;
pub mod stock;
pub mod turn_round;

#[cfg(test)]
use crate::geom::P2;
use crate::geom::{Aabb, Polygon, V2};
use crate::machine::Machine;
use std::f64::consts::TAU;

pub use section::Section;
pub use snapshot::{Snapshot, Travel};
pub use stock::{DexelStock, StockHit, Swept, View, NO_SWEEP};
pub use turn_round::{Stand, StockTransform};

/// A revolved static part: its outline (x ≥ 0) and the mirror (x ≤ 0).
#[derive(Clone, Debug)]
pub struct Revolved {
    pub name: &'static str,
    pub outline: Polygon,
    pub mirror: Polygon,
    pub aabb: Aabb,
}

impl Revolved {
    pub fn new(name: &'static str, outline: Polygon) -> Revolved {
        let mirror = outline.mirrored_x();
        let aabb = outline.aabb().union(mirror.aabb());
        Revolved {
            name,
            outline,
            mirror,
            aabb,
        }
    }
}

/// A tool's shapes, relative to its programmed point.
#[derive(Clone, Debug)]
pub struct ToolShape {
    pub station: u32,
    /// "T03"
    pub label: String,
    pub tip: V2,
    pub insert: Polygon,
    /// Whether the insert is convex: its sweep along a chord is then one convex polygon
    /// ([`crate::geom::convex::sweep_convex`]).
    pub insert_convex: bool,
    pub holder: Polygon,
    /// What the boxes of their sections in another station need (`Scene::section_box`).
    pub insert_extent: section::Extent,
    pub holder_extent: section::Extent,
}

/// Everything the checker poses, built once per machine and tolerance.
#[derive(Clone, Debug)]
pub struct Scene {
    pub chuck: Option<Revolved>,
    pub tailstock: Option<Revolved>,
    /// The turret body relative to the reference point.
    pub turret: Polygon,
    pub turret_axis: f64,
    pub stations: u32,
    /// A gang-tool slide: every station stays in the working plane (angle 0).
    pub gang: bool,
    pub tools: Vec<ToolShape>,
    pub tolerance: f64,
    /// How far any point of the turret or of any tool, in any station, posed in the section,
    /// can lie from the turret reference point: `(x, z)` ([`Scene::reach_of`]).
    pub reach: (f64, f64),
    /// The sine and cosine of the angle of a station `k` stations from the active one, for `k`
    /// from `-trig_reach` to `trig_reach` ([`Scene::station_sin_cos`]).
    trig: Vec<(f64, f64)>,
    trig_reach: i64,
}

impl Scene {
    pub fn new(machine: &Machine, tolerance: f64) -> Scene {
        let tools: Vec<ToolShape> = machine
            .tools
            .iter()
            .map(|t| {
                let (insert, shift) = round_tip(&t.insert, t.nose_radius, tolerance);
                let holder = t.holder.translated(shift);
                let axis = machine.turret.axis;
                ToolShape {
                    station: t.station,
                    label: format!("T{:02}", t.station),
                    tip: t.tip.coords,
                    insert_extent: section::Extent::of(&insert, t.tip.coords, axis),
                    insert_convex: crate::geom::convex::is_convex(insert.points()),
                    holder_extent: section::Extent::of(&holder, t.tip.coords, axis),
                    insert,
                    holder,
                }
            })
            .collect();
        let reach = Scene::reach_of(&machine.turret.outline, machine.turret.axis, &tools);
        let trig_reach = machine
            .tools
            .iter()
            .map(|t| i64::from(t.station))
            .chain([i64::from(machine.turret.stations)])
            .max()
            .unwrap_or(0);
        let mut scene = Scene {
            reach,
            trig: Vec::new(),
            trig_reach,
            chuck: machine.chuck.clone().map(|p| Revolved::new("chuck", p)),
            tailstock: machine.tailstock.clone().map(|p| Revolved::new("tailstock", p)),
            turret: machine.turret.outline.clone(),
            turret_axis: machine.turret.axis,
            stations: machine.turret.stations,
            gang: machine.turret.kind == crate::machine::TurretKind::Gang,
            tools,
            tolerance,
        };
        scene.trig = (-trig_reach..=trig_reach)
            .map(|k| scene.angle_of_stations(k as f64).sin_cos())
            .collect();
        scene
    }

    /// The reach of the posed parts from the reference point `r`, in `x` and `z`: the turret's
    /// and a tool's points in the working plane lie `p` from `r`; another station's points lie
    /// at a radius `|(r.x, 0) + v|` from the spindle axis with `|v| <= |turret_axis| + |d|`
    /// (`d` the point's distance from the turret axis in its station's plane, as
    /// [`Scene::map_to_section`] maps it), so within `|turret_axis| + |d|` of `|r.x|`, and
    /// `z` from `r.y` exactly as in the plane.
    fn reach_of(turret: &Polygon, turret_axis: f64, tools: &[ToolShape]) -> (f64, f64) {
        let (mut rx, mut rz) = (0.0f64, 0.0f64);
        for p in turret.points() {
            rx = rx.max(p.x.abs());
            rz = rz.max(p.y.abs());
        }
        for t in tools {
            for q in t.insert.points().iter().chain(t.holder.points()) {
                let p = q + t.tip;
                rx = rx.max(p.x.abs()).max(turret_axis.abs() + (p.x - turret_axis).abs());
                rz = rz.max(p.y.abs());
            }
        }
        (rx, rz)
    }

    pub fn tool(&self, station: u32) -> Option<&ToolShape> {
        self.tools.iter().find(|t| t.station == station)
    }

    /// Angle of a station on the turret when `active` faces the spindle. On a gang slide every
    /// station is in the working plane: 0.
    pub fn station_angle(&self, station: u32, active: f64) -> f64 {
        self.angle_of_stations(station as f64 - active)
    }

    /// The angle of a station `k` stations from the active one (`k` may be a fraction during an
    /// index; a difference of two whole numbers is exact, so the table of
    /// [`Self::station_sin_cos`] holds `station_angle`'s values).
    fn angle_of_stations(&self, k: f64) -> f64 {
        if self.gang {
            return 0.0;
        }
        k * TAU / self.stations.max(1) as f64
    }

    /// The sine and cosine of [`Self::station_angle`] with a station active, from a table built
    /// once (bit for bit `station_angle(station, active as f64).sin_cos()`).
    pub fn station_sin_cos(&self, station: u32, active: u32) -> (f64, f64) {
        let k = i64::from(station) - i64::from(active);
        match usize::try_from(k + self.trig_reach).ok().and_then(|i| self.trig.get(i)) {
            Some(&sc) => sc,
            None => self.station_angle(station, active as f64).sin_cos(),
        }
    }

    /// The box of a shape's section at one reference point from every edge's two ends and its
    /// clamped closest approach to the spindle axis: the oracle of [`Scene::section_box`].
    #[cfg(test)]
    pub(crate) fn map_box_every_edge(&self, shape: &Polygon, tip: V2, r_ref: P2, angle: f64) -> Aabb {
        let (s, c) = angle.sin_cos();
        let axis_x = r_ref.x + self.turret_axis;
        let mut b = Aabb::empty();
        let pts = shape.points();
        let n = pts.len();
        for i in 0..n {
            let (a, e) = (pts[i], pts[(i + 1) % n]);
            for q in [a, e] {
                let p = q + tip;
                let d = p.x - self.turret_axis;
                let (x3, y3) = (axis_x + d * c, d * s);
                b.add(P2::new((x3 * x3 + y3 * y3).sqrt(), r_ref.y + p.y));
            }
            let (pa, pe) = (a + tip, e + tip);
            let (da, de) = (pa.x - self.turret_axis, pe.x - self.turret_axis);
            let (xa, ya) = (axis_x + da * c, da * s);
            let (xe, ye) = (axis_x + de * c, de * s);
            let (dx, dy) = (xe - xa, ye - ya);
            let len2 = dx * dx + dy * dy;
            if len2 > 0.0 {
                let t = (-(xa * dx + ya * dy) / len2).clamp(0.0, 1.0);
                let (x, y) = (xa + dx * t, ya + dy * t);
                b.add(P2::new((x * x + y * y).sqrt(), r_ref.y + pa.y + (pe.y - pa.y) * t));
            }
        }
        b
    }
}

/// Round the insert's tip corner (the vertex at the programmed point, or the one nearest to it)
/// with the nose radius, by chords within `tol` lying inside the true arc, and place the tool so
/// that the programmed point is the rounded nose's imaginary tip ([`imaginary_tip`]). Returns the
/// rounded insert in its place and the shift that placed it, which the holder takes too: insert
/// and holder are one rigid tool, set on the machine by where its nose touches.
fn round_tip(insert: &Polygon, radius: f64, tol: f64) -> (Polygon, V2) {
    let sharp = || (insert.clone(), V2::zeros());
    if radius <= 0.0 {
        return sharp();
    }
    let pts = insert.points();
    let n = pts.len();
    let (k, _) = pts
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p.coords.norm()))
        .fold((0, f64::INFINITY), |acc, x| if x.1 < acc.1 { x } else { acc });
    let (prev, cur, next) = (pts[(k + n - 1) % n], pts[k], pts[(k + 1) % n]);
    let u = (prev - cur).normalize();
    let v = (next - cur).normalize();
    let cos = u.dot(&v).clamp(-1.0, 1.0);
    let half = cos.acos() / 2.0;
    if !(half > 1e-6 && half < std::f64::consts::FRAC_PI_2 - 1e-6) {
        return sharp();
    }
    // Tangent points at distance radius / tan(half) along both edges.
    let d = radius / half.tan();
    if d >= (prev - cur).norm() * 0.5 || d >= (next - cur).norm() * 0.5 {
        return sharp();
    }
    let bis = (u + v).normalize();
    let center = cur + bis * (radius / half.sin());
    let t1 = cur + u * d;
    let t2 = cur + v * d;
    let a1 = (t1 - center).y.atan2((t1 - center).x);
    let a2 = (t2 - center).y.atan2((t2 - center).x);
    let mut sweep = a2 - a1;
    while sweep > std::f64::consts::PI {
        sweep -= TAU;
    }
    while sweep < -std::f64::consts::PI {
        sweep += TAU;
    }
    let step = 2.0 * (1.0 - tol.min(radius) / radius).acos().max(1e-3);
    let m = ((sweep.abs() / step).ceil() as usize).clamp(2, 64);
    let mut out = Vec::with_capacity(n + m);
    for (i, p) in pts.iter().enumerate() {
        if i == k {
            for j in 0..=m {
                let a = a1 + sweep * j as f64 / m as f64;
                out.push(center + V2::new(radius * a.cos(), radius * a.sin()));
            }
        } else {
            out.push(*p);
        }
    }
    let rounded = Polygon::new(&out).unwrap_or_else(|_| insert.clone());
    let shift = imaginary_tip(insert, &rounded);
    (rounded.translated(shift), shift)
}

/// Place a rounded insert so that the programmed point is its imaginary tool tip, as the tool is
/// set on a machine: the nose touches the lines through the programmed point parallel to the
/// axes, on the side the insert lies. An axis along which the sharp corner was not the insert's
/// extreme (a threading or grooving form symmetric about the tip) is left as it is. Returns the
/// shift that does it.
fn imaginary_tip(sharp: &Polygon, rounded: &Polygon) -> V2 {
    let (sb, rb) = (sharp.aabb(), rounded.aabb());
    let c = sharp.points().iter().fold(V2::zeros(), |a, p| a + p.coords) / sharp.points().len() as f64;
    let size = (sb.max.x - sb.min.x).max(sb.max.y - sb.min.y);
    let eps = 1e-9;
    let mut shift = V2::zeros();
    if c.x > 0.1 * size && sb.min.x.abs() < eps {
        shift.x = -rb.min.x;
    } else if c.x < -0.1 * size && sb.max.x.abs() < eps {
        shift.x = -rb.max.x;
    }
    if c.y > 0.1 * size && sb.min.y.abs() < eps {
        shift.y = -rb.min.y;
    } else if c.y < -0.1 * size && sb.max.y.abs() < eps {
        shift.y = -rb.max.y;
    }
    shift
}

#[cfg(test)]
mod section_box_tests {
    use super::*;

    /// A tool set by its rounded nose's imaginary tip moves whole: the holder keeps its place
    /// against the insert's edges (shifted only, the insert moved the holder would stand
    /// 0.18 mm ahead of T01's rake face and rub a bar's front corner the insert had left it).
    #[test]
    fn the_holder_moves_with_the_insert_when_the_nose_sets_the_tool() {
        let machine = crate::machine::Machine::builtin();
        let scene = Scene::new(&machine, 0.01);
        let mut shifted = 0;
        for t in &machine.tools {
            let st = scene.tool(t.station).unwrap();
            // The insert's vertex farthest from the nose is not rounded: it shows the shift.
            let far = |p: &[P2]| {
                *p.iter()
                    .max_by(|a, b| a.coords.norm().total_cmp(&b.coords.norm()))
                    .unwrap()
            };
            let shift = far(st.insert.points()) - far(t.insert.points());
            shifted += usize::from(shift.norm() > 1e-3);
            assert_eq!(st.holder.points().len(), t.holder.points().len());
            for (a, b) in st.holder.points().iter().zip(t.holder.points()) {
                assert!(
                    (a - (b + shift)).norm() < 1e-12,
                    "T{}: {a:?} against {b:?} + {shift:?}",
                    t.station
                );
            }
        }
        assert!(shifted >= 3, "only {shifted} tools set by a nose");
    }

    #[test]
    fn the_stations_sines_and_cosines_from_the_table_are_the_angles_bit_for_bit() {
        for name in ["generic-slant-bed", "haas-style-inch", "gang-tool", "twin-turret"] {
            let path = format!("machines/{name}.toml");
            let text = std::fs::read_to_string(&path).unwrap();
            let machine = crate::machine::from_toml(&text, &path).unwrap();
            let scene = Scene::new(&machine, 0.01);
            for station in 0..=machine.turret.stations + 3 {
                for active in 0..=machine.turret.stations + 3 {
                    let (s, c) = scene.station_angle(station, active as f64).sin_cos();
                    let (ts, tc) = scene.station_sin_cos(station, active);
                    assert_eq!(
                        (s.to_bits(), c.to_bits()),
                        (ts.to_bits(), tc.to_bits()),
                        "{name} {station} {active}"
                    );
                }
            }
        }
    }

    /// Random poses of every tool of the built-in machine (and its rounded inserts), turned to
    /// any angle: at one reference point the closed-form box is the box of every edge (within
    /// rounding) and holds every point of the section; over a reference box it holds the boxes at
    /// 24 reference points inside it, among them where a point of the tool passes over the
    /// spindle axis (its radius lower than at either end), which the boxes at the two ends of
    /// the move did not hold.
    #[test]
    fn the_section_box_is_every_edges_box_and_holds_the_section_over_a_move() {
        let machine = crate::machine::Machine::builtin();
        let scene = Scene::new(&machine, 0.01);
        let mut rnd = crate::test_util::unit_random(7u64);
        let (mut checked, mut dips) = (0, 0);
        for t in &scene.tools {
            for (shape, extent) in [(&t.holder, &t.holder_extent), (&t.insert, &t.insert_extent)] {
                for _ in 0..300 {
                    let angle = std::f64::consts::TAU * (rnd() - 0.5) * if rnd() < 0.2 { 0.0 } else { 1.0 };
                    let r_ref = P2::new(500.0 * rnd() - 250.0, 400.0 * rnd() - 200.0);
                    let one = scene.section_box(extent, &Aabb { min: r_ref, max: r_ref }, angle);
                    let slow = scene.map_box_every_edge(shape, t.tip, r_ref, angle);
                    let eps = 1e-9 * (1.0 + slow.max.x.abs() + slow.max.y.abs());
                    for (a, b) in [
                        (one.min.x, slow.min.x),
                        (one.min.y, slow.min.y),
                        (one.max.x, slow.max.x),
                        (one.max.y, slow.max.y),
                    ] {
                        assert!((a - b).abs() <= eps, "{one:?} against {slow:?}");
                    }
                    for p in scene
                        .map_to_section(shape, t.tip, r_ref, angle)
                        .iter()
                        .flat_map(|s| s.pieces())
                    {
                        for q in p.points() {
                            assert!(
                                q.x >= one.min.x - eps
                                    && q.x <= one.max.x + eps
                                    && q.y >= one.min.y - eps
                                    && q.y <= one.max.y + eps,
                                "{q:?} outside {one:?}"
                            );
                        }
                    }
                    // A move: a reference box, sometimes one that carries a point of the tool
                    // over the spindle axis.
                    let other = P2::new(500.0 * rnd() - 250.0, 400.0 * rnd() - 200.0);
                    let rb = Aabb::of_points(&[r_ref, other]);
                    let over = scene.section_box(extent, &rb, angle);
                    let ends = scene
                        .map_box_every_edge(shape, t.tip, rb.min, angle)
                        .union(&scene.map_box_every_edge(shape, t.tip, rb.max, angle));
                    for k in 0..24 {
                        let f = k as f64 / 23.0;
                        let at = P2::new(
                            rb.min.x + (rb.max.x - rb.min.x) * f,
                            rb.min.y + (rb.max.y - rb.min.y) * rnd(),
                        );
                        let b = scene.map_box_every_edge(shape, t.tip, at, angle);
                        assert!(
                            b.min.x >= over.min.x - eps
                                && b.max.x <= over.max.x + eps
                                && b.min.y >= over.min.y - eps
                                && b.max.y <= over.max.y + eps,
                            "{b:?} at {at:?} outside {over:?}"
                        );
                        dips += usize::from(b.min.x < ends.min.x - 1e-6);
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked >= 1000 && dips > 0, "{checked} poses, {dips} dips");
    }
}
