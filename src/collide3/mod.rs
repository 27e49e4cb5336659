//! 3D collision queries for turn-mill machines: shapes from `kin` geometry, pair
//! overlap with depth and distance (`parry3d-f64`), meshes against the revolved in-process stock,
//! a proven motion bound, and conservative advancement along a move.
//!
//! Frames and units are `kin`'s (machine frame, mm). Poses are nalgebra [`Iso`] at the boundary and
//! converted to parry's glam poses inside.
//!
//! **Accuracy.** `overlap` is exact for whether triangles cross (parry's triangle tests, f64) and
//! for containment of closed meshes (a point of each connected component tested against the other
//! solid; parry's pseudo-normal point containment). The depth is parry's `contact` penetration
//! (GJK/EPA, to about 1e-9 mm) of the deepest crossing pair of convex parts (two triangles, a
//! triangle and a primitive): a local depth and a lower bound of the solids' penetration depth
//! (separating the solids separates every pair of their parts; two boxes crossing by 0.5 mm may
//! report 0.2, the deepest triangle pair); for containment, a lower bound: the distance from the
//! contained component's test point to the container's surface. `distance` is parry's closest
//! distance between the two boundaries (branch and bound, GJK to about 1e-9 mm) below 10 mm and a
//! lower bound at least 31/32 of it beyond (`distance_bound`: a bound at least 1/2 of it at any
//! distance, the advancement's), and 0
//! when the solids overlap by any amount (crossing or containment). Two meshes are answered by
//! one walk of both their trees (`pairs.rs`), measuring the pairs of triangles as parry does.

mod grid;
mod memo;
mod motion;
mod pairs;
mod stock;
mod tess;
#[cfg(test)]
mod tests;

pub use grid::{dexel_clears_grid, grid_clear, grid_overlap, grid_overlap_beyond};
pub use motion::{
    bound_from, first_contact, first_contact_from, first_contact_proving, geometry_sphere, motion_bound, pair_bound,
    Advance, LinearPath, Path, Stretches, MAX_PROBES, MIN_STEP_MM,
};
pub use stock::{stock_gap, stock_hull_depth, stock_overlap};
pub use tess::uv_sphere;

use nalgebra::Point3;
use parry3d_f64::math::{Pose, Rotation, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{ConvexPolyhedron, Cuboid, Cylinder, Shape, TriMesh, TriMeshFlags};

use crate::geom::P2;
use crate::kin::{shape, Geometry, Iso};

/// A nalgebra isometry as a parry pose.
pub fn to_pose(iso: &Iso) -> Pose {
    let t = iso.translation.vector;
    let q = iso.rotation.quaternion();
    Pose::from_parts(Vector::new(t.x, t.y, t.z), Rotation::from_xyzw(q.i, q.j, q.k, q.w))
}

/// A nalgebra point as a parry vector.
pub fn to_vec(p: &Point3<f64>) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// A parry vector as a nalgebra point.
pub fn to_point(v: Vector) -> Point3<f64> {
    Point3::new(v.x, v.y, v.z)
}

/// One overlap of two solids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Penetration depth, mm (see the module docs for its accuracy).
    pub depth: f64,
    /// A point of the overlap, machine frame.
    pub point: Point3<f64>,
}

/// A convex part and its placement in the component's frame.
pub struct Convex {
    /// Unique for the life of the process (`memo`).
    id: u64,
    shape: Box<dyn Shape>,
    local: Pose,
    /// A point strictly inside, component frame.
    inner: Vector,
    /// A closed triangle surface holding the solid, component frame (for the stock query).
    surf: (Vec<Vector>, Vec<[u32; 3]>),
}

/// A closed triangle mesh with its BVH and pseudo-normals (point containment).
pub struct MeshShape {
    /// Unique for the life of the process (`memo`).
    id: u64,
    mesh: TriMesh,
    /// One vertex per connected component (containment tests).
    reps: Vec<Vector>,
    /// The tree of the pair walks (`pairs`), built on the first.
    tree: pairs::LazyTree,
}

/// The collision shape of one component.
pub enum Shape3 {
    Mesh(Box<MeshShape>),
    Convex(Convex),
}

/// A bounding sphere of a shape in its component's frame (centre, radius).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    pub center: Point3<f64>,
    pub radius: f64,
}

impl Shape3 {
    /// The shape of a geometry; revolved outlines are meshed to within `tol` mm (circumscribed,
    /// never smaller than the solid). `None` for a geometry with no volume or non-finite numbers.
    pub fn from_geometry(g: &Geometry, tol: f64) -> Option<Shape3> {
        match g {
            Geometry::Mesh(m) => Shape3::from_mesh(m),
            Geometry::Revolved(outline) => Shape3::from_mesh(&shape::revolved(outline, tol).ok()?),
            Geometry::Cutter { .. } => Shape3::from_mesh(&shape::mesh_of(g, tol).ok()?),
            Geometry::Extruded { outline, half_width } => {
                let hw = *half_width;
                if crate::geom::convex::is_convex(outline) {
                    return Shape3::hull(outline, hw);
                }
                match shape::extruded(outline, hw) {
                    Ok(m) => Shape3::from_mesh(&m),
                    // Not a simple polygon: its convex hull holds it.
                    Err(_) => Shape3::hull(outline, hw),
                }
            }
            Geometry::Cuboid { min, max } => {
                let (a, b) = (to_vec(min), to_vec(max));
                let half = (b - a) * 0.5;
                if !positive(half.x.min(half.y).min(half.z)) || !half.is_finite() {
                    return None;
                }
                let c = (a + b) * 0.5;
                let cub = Cuboid::new(half);
                let (v, t) = cub.to_trimesh();
                let surf = (v.into_iter().map(|p| p + c).collect(), t);
                Some(Shape3::Convex(Convex {
                    id: memo::next_id(),
                    shape: Box::new(cub),
                    local: Pose::from_translation(c),
                    inner: c,
                    surf,
                }))
            }
            Geometry::Cylinder { radius, z0, z1 } => {
                let (lo, hi) = (z0.min(*z1), z0.max(*z1));
                let hh = (hi - lo) / 2.0;
                if !positive(radius.min(hh)) || !radius.is_finite() || !hh.is_finite() {
                    return None;
                }
                let c = Vector::new(0.0, 0.0, (lo + hi) / 2.0);
                // parry's cylinder axis is y: turn it onto z (a quarter turn about x).
                let rot = Rotation::from_rotation_x(std::f64::consts::FRAC_PI_2);
                let m = shape::cylinder(*radius, lo, hi, tol).ok()?;
                let surf = (m.vertices.iter().map(to_vec).collect(), m.triangles);
                Some(Shape3::Convex(Convex {
                    id: memo::next_id(),
                    shape: Box::new(Cylinder::new(hh, *radius)),
                    local: Pose::from_parts(c, rot),
                    inner: c,
                    surf,
                }))
            }
        }
    }

    /// A geometry as a triangle mesh whatever its kind (`kin::shape`: revolved outlines and
    /// cylinders circumscribed), for callers that pose many queries: parry's mesh–mesh queries
    /// are many times faster than its mesh–primitive ones (docs/turn-mill.md, "3D collision").
    pub fn meshed(g: &Geometry, tol: f64) -> Option<Shape3> {
        match g {
            Geometry::Mesh(_) => Shape3::from_geometry(g, tol),
            _ => Shape3::from_mesh(&shape::mesh_of(g, tol).ok()?),
        }
    }

    fn from_mesh(m: &crate::kin::Mesh) -> Option<Shape3> {
        Shape3::mesh(m.vertices.iter().map(to_vec).collect(), m.triangles.clone())
    }

    /// A mesh from vertices and triangles: duplicate vertices merged, degenerate triangles
    /// dropped, topology and pseudo-normals computed (point containment of a closed, outward
    /// oriented mesh).
    pub fn mesh(v: Vec<Vector>, t: Vec<[u32; 3]>) -> Option<Shape3> {
        if t.is_empty() || v.iter().any(|p| !p.is_finite()) || t.iter().flatten().any(|&i| i as usize >= v.len()) {
            return None;
        }
        let flags = TriMeshFlags::MERGE_DUPLICATE_VERTICES
            | TriMeshFlags::DELETE_DEGENERATE_TRIANGLES
            | TriMeshFlags::HALF_EDGE_TOPOLOGY
            | TriMeshFlags::ORIENTED;
        let mesh = TriMesh::with_flags(v, t, flags).ok()?;
        if mesh.num_triangles() == 0 {
            return None;
        }
        let reps = component_reps(mesh.vertices(), mesh.indices());
        Some(Shape3::Mesh(Box::new(MeshShape {
            id: memo::next_id(),
            mesh,
            reps,
            tree: pairs::LazyTree::default(),
        })))
    }

    fn hull(outline: &[P2], hw: f64) -> Option<Shape3> {
        if !positive(hw) || !hw.is_finite() {
            return None;
        }
        let pts: Vec<Vector> = outline
            .iter()
            .flat_map(|p| [Vector::new(p.x, -hw, p.y), Vector::new(p.x, hw, p.y)])
            .collect();
        if pts.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let shape = ConvexPolyhedron::from_convex_hull(&pts)?;
        let inner = pts.iter().fold(Vector::ZERO, |a, &p| a + p) / pts.len() as f64;
        let surf = shape.to_trimesh();
        Some(Shape3::Convex(Convex {
            id: memo::next_id(),
            shape: Box::new(shape),
            local: Pose::IDENTITY,
            inner,
            surf,
        }))
    }

    /// The shape's id: unique for the life of the process (`memo`).
    fn id(&self) -> u64 {
        match self {
            Shape3::Mesh(m) => m.id,
            Shape3::Convex(c) => c.id,
        }
    }

    /// Whether the shape is one of parry's convex primitives (not a mesh).
    pub fn is_convex(&self) -> bool {
        matches!(self, Shape3::Convex(_))
    }

    /// The stretch `[t0, t1]` (within `[lo, hi]`) of the line `o + t·u` (world frame; `u` a unit
    /// vector) inside a cylinder or box primitive posed at `pose`, in closed form: `Some(None)`
    /// when it misses, `None` when the shape is neither.
    pub fn line_interval(&self, pose: &Pose, o: Vector, u: Vector, lo: f64, hi: f64) -> Option<Option<(f64, f64)>> {
        let Shape3::Convex(c) = self else { return None };
        let pos = *pose * c.local;
        let (lo_p, lu) = (pos.inverse_transform_point(o), pos.inverse_transform_vector(u));
        let (mut t0, mut t1) = (lo, hi);
        // One slab per bounded local axis.
        let mut slab = |p: f64, d: f64, h: f64| {
            if d.abs() < 1e-300 {
                if p.abs() > h {
                    t1 = f64::NEG_INFINITY;
                }
            } else {
                let (a, b) = ((-h - p) / d, (h - p) / d);
                t0 = t0.max(a.min(b));
                t1 = t1.min(a.max(b));
            }
        };
        if let Some(cyl) = c.shape.as_cylinder() {
            // parry's cylinder: axis y, |y| ≤ half height, x² + z² ≤ r².
            slab(lo_p.y, lu.y, cyl.half_height);
            let a = lu.x * lu.x + lu.z * lu.z;
            let b = lo_p.x * lu.x + lo_p.z * lu.z;
            let cc = lo_p.x * lo_p.x + lo_p.z * lo_p.z - cyl.radius * cyl.radius;
            if a < 1e-300 {
                if cc > 0.0 {
                    return Some(None);
                }
            } else {
                let disc = b * b - a * cc;
                if disc < 0.0 {
                    return Some(None);
                }
                let q = disc.sqrt();
                t0 = t0.max((-b - q) / a);
                t1 = t1.min((-b + q) / a);
            }
        } else if let Some(cub) = c.shape.as_cuboid() {
            let h = cub.half_extents;
            slab(lo_p.x, lu.x, h.x);
            slab(lo_p.y, lu.y, h.y);
            slab(lo_p.z, lu.z, h.z);
        } else {
            return None;
        }
        Some((t1 > t0).then_some((t0, t1)))
    }

    /// Number of triangles (0 for a primitive).
    pub fn triangles(&self) -> usize {
        match self {
            Shape3::Mesh(m) => m.mesh.num_triangles(),
            Shape3::Convex(_) => 0,
        }
    }

    /// The parry shape and its pose in the world for a component pose.
    fn parts<'a>(&'a self, pose: &Pose) -> (&'a dyn Shape, Pose) {
        match self {
            Shape3::Mesh(m) => (&m.mesh, *pose),
            Shape3::Convex(c) => (&*c.shape, *pose * c.local),
        }
    }

    /// A point of each connected part (component frame): a vertex of a mesh's part, the
    /// centre of a primitive.
    fn reps(&self) -> &[Vector] {
        match self {
            Shape3::Mesh(m) => &m.reps,
            Shape3::Convex(c) => std::slice::from_ref(&c.inner),
        }
    }

    /// A sphere holding the shape, component frame.
    pub fn sphere(&self) -> Sphere {
        let aabb = self.local_box();
        let center = (aabb.mins + aabb.maxs) * 0.5;
        Sphere {
            center: to_point(center),
            radius: ((aabb.maxs - aabb.mins) * 0.5).length(),
        }
    }

    /// The box holding the shape, component frame.
    pub fn local_box(&self) -> parry3d_f64::bounding_volume::Aabb {
        match self {
            Shape3::Mesh(m) => m.mesh.local_aabb(),
            Shape3::Convex(c) => c.shape.compute_aabb(&c.local),
        }
    }

    /// A closed triangle surface holding the solid, component frame.
    fn surface(&self) -> (&[Vector], &[[u32; 3]]) {
        match self {
            Shape3::Mesh(m) => (m.mesh.vertices(), m.mesh.indices()),
            Shape3::Convex(c) => (&c.surf.0, &c.surf.1),
        }
    }

    /// The solid holds the world point (shape posed at `pose`).
    fn contains(&self, pose: &Pose, p: Vector) -> bool {
        // A point beyond the shape's own box, by far more than rounding, is outside the solid
        // (which the box holds): answered without projecting it onto the surface.
        let (b, q) = (self.local_box(), pose.inverse_transform_point(p));
        let margin = 1e-7 + 1e-12 * (b.mins.abs().max(b.maxs.abs()).max_element() + q.abs().max_element());
        if (q.cmplt(b.mins - margin) | q.cmpgt(b.maxs + margin)).any() {
            return false;
        }
        let (s, pos) = self.parts(pose);
        s.contains_point(&pos, p)
    }

    /// Distance from a world point to the shape's boundary.
    fn depth_of(&self, pose: &Pose, p: Vector) -> f64 {
        let (s, pos) = self.parts(pose);
        let proj = s.project_point(&pos, p, false);
        (proj.point - p).length()
    }

    /// The triangle mesh, when the shape is one (for the stock query).
    pub fn as_trimesh(&self) -> Option<&TriMesh> {
        match self {
            Shape3::Mesh(m) => Some(&m.mesh),
            Shape3::Convex(_) => None,
        }
    }
}

/// `x > 0` (false for NaN).
pub(crate) fn positive(x: f64) -> bool {
    x > 0.0
}

/// One vertex index per connected component of the triangles (union-find).
fn component_reps(v: &[Vector], t: &[[u32; 3]]) -> Vec<Vector> {
    let mut parent: Vec<u32> = (0..v.len() as u32).collect();
    fn find(p: &mut [u32], mut i: u32) -> u32 {
        while p[i as usize] != i {
            p[i as usize] = p[p[i as usize] as usize];
            i = p[i as usize];
        }
        i
    }
    for tr in t {
        let a = find(&mut parent, tr[0]);
        for &k in &tr[1..] {
            let b = find(&mut parent, k);
            if a != b {
                parent[b as usize] = a;
            }
        }
    }
    let mut seen = vec![false; v.len()];
    let mut reps = Vec::new();
    for tr in t {
        let r = find(&mut parent, tr[0]) as usize;
        if !seen[r] {
            seen[r] = true;
            reps.push(v[tr[0] as usize]);
        }
    }
    reps
}

/// Do the solids of `a` (posed at `pa`) and `b` overlap by more than `eps`? Triangles crossing
/// and one solid wholly inside the other both count; touching (depth ≤ `eps`) does not. The
/// one entry point: dispatches by the pair's kinds.
pub fn overlap(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> Option<Hit> {
    overlap_touch(a, pa, b, pb, eps).0
}

/// [`overlap`], and whether the shapes' parts were found touching or crossing at any depth
/// (then [`distance`] is 0: the advancement needs no distance query).
pub fn overlap_touch(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> (Option<Hit>, bool) {
    let key = memo::Key::new(memo::Query::OverlapTouch, (a.id(), pa), (b.id(), pb), eps);
    match memo::answer(key, || {
        let (hit, touch) = overlap_touch_computed(a, pa, b, pb, eps);
        memo::Answer::OverlapTouch(hit, touch)
    }) {
        memo::Answer::OverlapTouch(hit, touch) => (hit, touch),
        memo::Answer::Distance(_) => unreachable!("an overlap question keyed as a distance"),
    }
}

/// [`overlap_touch`]'s answer when it is held (`memo`), for the lighter questions below.
fn overlap_held(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> Option<(Option<Hit>, bool)> {
    let key = memo::Key::new(memo::Query::OverlapTouch, (a.id(), pa), (b.id(), pb), eps);
    match memo::held(&key)? {
        memo::Answer::OverlapTouch(hit, touch) => Some((hit, touch)),
        memo::Answer::Distance(_) => None,
    }
}

/// Whether [`overlap`] finds an overlap deeper than `eps`: its answer when held (`memo`), else
/// decided with the least measuring (`pairs::Ask::Over`): the same answer.
pub fn overlaps(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> bool {
    if let Some((hit, _)) = overlap_held(a, pa, b, pb, eps) {
        return hit.is_some();
    }
    let ask = pairs::Ask::Over {
        eps,
        floor: f64::INFINITY,
    };
    overlap_asked(a, &to_pose(pa), b, &to_pose(pb), eps, ask).0.is_some()
}

/// [`overlap_touch`] without the depth and point of the hit: whether it finds an overlap deeper
/// than `eps`, and whether it finds the parts touching (its answer when held, `memo`).
pub fn touches(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> (bool, bool) {
    if let Some((hit, touch)) = overlap_held(a, pa, b, pb, eps) {
        return (hit.is_some(), touch);
    }
    let (hit, touch) = overlap_asked(a, &to_pose(pa), b, &to_pose(pb), eps, pairs::Ask::Touch { eps });
    (hit.is_some(), touch)
}

/// How much deeper than a contact's deepest so far (its floor) a later sample must reach to be
/// measured as deeper (mm), by [`overlap_beyond`] and [`grid_overlap_beyond`]: far below what
/// the reports print (four significant digits), what the milled grid resolves (a node spacing)
/// and what sampling the rest of a move at 16 points after its first contact misses, and above the
/// margins the searches skip by (EPA's depths are trusted to 1e-6 mm, a ray's depth bound has a
/// few 1e-7 mm on a machine's scale). A contact held at one depth (a block pressed flat against
/// the part's face, a holder resting on a jaw) has every ray or pair of triangles along the
/// face tie the floor within those margins; with the floor exact, each was measured to prove
/// it no deeper (on the NL1500Y sample, 64 samples of 750 rays each, and 46k of the 78k EPA
/// runs of the pairs' samples). A deepest depth can then come out short by at most this.
pub const BEYOND_MM: f64 = 2e-6;

/// [`overlap`] where only a depth beyond `floor` (by more than [`BEYOND_MM`]) counts: `None`
/// exactly when [`overlap`] is; else [`overlap`]'s hit when its depth is beyond
/// `floor + BEYOND_MM`, and when not, a hit no deeper than that (a contact's later depth
/// samples, which keep the deepest).
pub fn overlap_beyond(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64, floor: f64) -> Option<Hit> {
    if let Some((hit, _)) = overlap_held(a, pa, b, pb, eps) {
        return hit;
    }
    let floor = floor + BEYOND_MM;
    overlap_asked(a, &to_pose(pa), b, &to_pose(pb), eps, pairs::Ask::Over { eps, floor }).0
}

/// [`overlap_touch`] computed (not taken from the answers held, `memo`).
fn overlap_touch_computed(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, eps: f64) -> (Option<Hit>, bool) {
    overlap_asked(a, &to_pose(pa), b, &to_pose(pb), eps, pairs::Ask::Deepest)
}

/// The overlap of two shapes by their kinds, measured as `ask` needs (`pairs::Ask`; the
/// touching flag with `Deepest` and `Touch`).
fn overlap_asked(a: &Shape3, pa: &Pose, b: &Shape3, pb: &Pose, eps: f64, ask: pairs::Ask) -> (Option<Hit>, bool) {
    match (a, b) {
        (Shape3::Mesh(_), Shape3::Mesh(_)) => mesh_mesh(a, pa, b, pb, eps, ask),
        (Shape3::Mesh(_), Shape3::Convex(_)) => mesh_convex(a, pa, b, pb, eps),
        (Shape3::Convex(_), Shape3::Mesh(_)) => mesh_convex(b, pb, a, pa, eps),
        (Shape3::Convex(_), Shape3::Convex(_)) => convex_convex(a, pa, b, pb, eps),
    }
}

/// Meshes: crossing triangles (parry's BVH against BVH), then containment both ways. parry's
/// contact between two composite shapes depends on their order (of the triangle pairs deep
/// enough it keeps the one its traversal meets best, which need not be the same pair the other
/// way round): the pair is taken in one order, by the poses' positions, so that a query and its
/// mirror give the same depth.
fn mesh_mesh(a: &Shape3, pa: &Pose, b: &Shape3, pb: &Pose, eps: f64, ask: pairs::Ask) -> (Option<Hit>, bool) {
    let key = |p: &Pose| [p.translation.x, p.translation.y, p.translation.z];
    if crate::geom::after(key(pa), key(pb)) {
        return mesh_mesh(b, pb, a, pa, eps, ask);
    }
    let (hit, touch) = crossing(a, pa, b, pb, eps, ask);
    let hit = hit
        .or_else(|| contained(a, pa, b, pb, eps))
        .or_else(|| contained(b, pb, a, pa, eps));
    (hit, touch)
}

/// A mesh and a convex primitive: crossing (triangles against the primitive), then containment.
fn mesh_convex(m: &Shape3, pm: &Pose, c: &Shape3, pc: &Pose, eps: f64) -> (Option<Hit>, bool) {
    let (hit, touch) = crossing(m, pm, c, pc, eps, pairs::Ask::Deepest);
    let hit = hit
        .or_else(|| contained(m, pm, c, pc, eps))
        .or_else(|| contained(c, pc, m, pm, eps));
    (hit, touch)
}

/// Two convex primitives: GJK/EPA sees the solids, containment included.
fn convex_convex(a: &Shape3, pa: &Pose, b: &Shape3, pb: &Pose, eps: f64) -> (Option<Hit>, bool) {
    crossing(a, pa, b, pb, eps, pairs::Ask::Deepest)
}

/// parry's deepest contact between the two shapes' parts, when deeper than `eps`; and whether
/// parry found the parts touching or crossing at all (a contact at distance ≤ 0). Two meshes
/// are measured as `ask` needs (`pairs`); other pairs by parry's own query.
fn crossing(a: &Shape3, pa: &Pose, b: &Shape3, pb: &Pose, eps: f64, ask: pairs::Ask) -> (Option<Hit>, bool) {
    let contact = if let (Shape3::Mesh(ma), Shape3::Mesh(mb)) = (a, b) {
        pairs::mesh_contact(&ma.mesh, &mb.mesh, pa, pb, ask)
    } else {
        let (sa, qa) = a.parts(pa);
        let (sb, qb) = b.parts(pb);
        query::contact(&qa, sa, &qb, sb, 0.0).ok().flatten()
    };
    let Some(c) = contact else {
        return (None, false);
    };
    let depth = -c.dist;
    let hit = (depth > eps).then(|| Hit {
        depth,
        point: to_point((c.point1 + c.point2) * 0.5),
    });
    (hit, c.dist <= 0.0)
}

/// Is `inner` wholly inside `outer` (one test point per connected part), deeper than `eps`?
/// Called only when no triangles cross, so a part with one point inside is inside whole.
fn contained(inner: &Shape3, pi: &Pose, outer: &Shape3, po: &Pose, eps: f64) -> Option<Hit> {
    inner.reps().iter().find_map(|&r| {
        let p = *pi * r;
        if !outer.contains(po, p) {
            return None;
        }
        let depth = outer.depth_of(po, p);
        (depth > eps).then(|| Hit {
            depth,
            point: to_point(p),
        })
    })
}

/// The box of a shape posed at `pose`, world frame: the posed box of its own frame's box (its
/// centre moved, its half extents through the rotation's absolute values), holding the solid.
pub fn world_box(s: &Shape3, pose: &Iso) -> (Point3<f64>, Point3<f64>) {
    let b = s.local_box();
    let c = to_point((b.mins + b.maxs) * 0.5);
    let h = (b.maxs - b.mins) * 0.5;
    let r = pose.rotation.to_rotation_matrix();
    let m = r.matrix();
    let wc = pose * c;
    let e = |i: usize| m[(i, 0)].abs() * h.x + m[(i, 1)].abs() * h.y + m[(i, 2)].abs() * h.z;
    let ext = nalgebra::Vector3::new(e(0), e(1), e(2));
    (wc - ext, wc + ext)
}

/// A lower bound of the distance between two posed solids at no query's cost: the distance
/// between their world boxes ([`world_box`]) or between their bounding spheres, whichever is
/// larger (0 when both meet). The broad phase of [`first_contact_from`].
pub fn box_gap(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso) -> f64 {
    let (a0, a1) = world_box(a, pa);
    let (b0, b1) = world_box(b, pb);
    let mut d2 = 0.0;
    for i in 0..3 {
        let g = (a0[i] - b1[i]).max(b0[i] - a1[i]).max(0.0);
        d2 += g * g;
    }
    let (sa, sb) = (a.sphere(), b.sphere());
    let spheres = ((pa * sa.center) - (pb * sb.center)).norm() - sa.radius - sb.radius;
    let g = d2.sqrt().max(spheres).max(0.0);
    if g.is_finite() {
        g
    } else {
        0.0
    }
}

/// A point midway between the closest points of the two boundaries when they are less than
/// `within` apart (for the pictures of near misses); `None` when farther or when parry has no
/// answer for the pair.
pub fn closest_point(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, within: f64) -> Option<Point3<f64>> {
    let (pa, pb) = (to_pose(pa), to_pose(pb));
    let (sa, qa) = a.parts(&pa);
    let (sb, qb) = b.parts(&pb);
    let c = query::contact(&qa, sa, &qb, sb, within.max(0.0)).ok().flatten()?;
    Some(to_point((c.point1 + c.point2) * 0.5))
}

/// Whether the two solids stay more than `margin` apart while each translates linearly from its
/// pose at `t = 0` to its pose at `t = 1` (`a` from `pa0` to `pa1`, `b` from `pb0` to `pb1`; each
/// pair of poses with the same rotation): parry's shape cast of the boundaries finds no impact
/// within `margin`, and neither solid holds a point of each connected part of the other at the
/// start (boundaries that never meet keep what holds what). False when parry has no answer.
pub fn swept_clear(a: &Shape3, (pa0, pa1): (&Iso, &Iso), b: &Shape3, (pb0, pb1): (&Iso, &Iso), margin: f64) -> bool {
    let (qa0, qb0) = (to_pose(pa0), to_pose(pb0));
    let (sa, qa) = a.parts(&qa0);
    let (sb, qb) = b.parts(&qb0);
    let vel = |p0: &Iso, p1: &Iso| {
        let d = p1.translation.vector - p0.translation.vector;
        Vector::new(d.x, d.y, d.z)
    };
    let (va, vb) = (vel(pa0, pa1), vel(pb0, pb1));
    if !(va.is_finite() && vb.is_finite()) {
        return false;
    }
    let options = query::ShapeCastOptions {
        max_time_of_impact: 1.0,
        target_distance: margin,
        // Parts that overlap at the start are an impact even while they move apart.
        stop_at_penetration: true,
        compute_impact_geometry_on_penetration: false,
    };
    match query::cast_shapes(&qa, va, sa, &qb, vb, sb, options) {
        Ok(None) => {}
        _ => return false,
    }
    let inside = |x: &Shape3, px: &Pose, y: &Shape3, py: &Pose| x.reps().iter().any(|&r| y.contains(py, *px * r));
    !inside(a, &qa0, b, &qb0) && !inside(b, &qb0, a, &qa0)
}

/// Distance between the two solids (0 when they overlap, containment included), mm: parry's
/// closest distance between their boundaries, exact below [`EXACT_BELOW`] (the near-miss
/// clearances), beyond it a lower bound at least `1 − 1/32` of it (`pairs::SLACK`). A lower
/// bound for skips to within GJK's accuracy.
pub fn distance(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso) -> f64 {
    distance_asked(a, pa, b, pb, EXACT_BELOW)
}

/// A lower bound of [`distance`], at least `1 − 1/2` of it at any distance
/// (`pairs::ADVANCE_SLACK`): what conservative advancement needs.
pub fn distance_bound(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso) -> f64 {
    distance_asked(a, pa, b, pb, 0.0)
}

/// The slack of a distance measured exactly below `exact_below`: [`distance`]'s beyond its
/// exact range, [`distance_bound`]'s (exact nowhere) at any distance.
fn slack_of(exact_below: f64) -> f64 {
    if exact_below > 0.0 {
        pairs::SLACK
    } else {
        pairs::ADVANCE_SLACK
    }
}

/// Distances below this are measured exactly by [`distance`] (the near-miss clearance is at
/// most 10 mm).
pub const EXACT_BELOW: f64 = 10.0;

fn distance_asked(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, exact_below: f64) -> f64 {
    let key = memo::Key::new(memo::Query::Distance, (a.id(), pa), (b.id(), pb), exact_below);
    match memo::answer(key, || {
        memo::Answer::Distance(distance_computed(a, pa, b, pb, exact_below))
    }) {
        memo::Answer::Distance(d) => d,
        memo::Answer::OverlapTouch(..) => unreachable!("a distance question keyed as an overlap"),
    }
}

/// [`distance_asked`] computed (not taken from the answers held, `memo`).
fn distance_computed(a: &Shape3, pa: &Iso, b: &Shape3, pb: &Iso, exact_below: f64) -> f64 {
    let (pa, pb) = (to_pose(pa), to_pose(pb));
    let d = if let (Shape3::Mesh(ma), Shape3::Mesh(mb)) = (a, b) {
        // parry's distance (exact below `exact_below`), by one walk of both trees (`pairs`).
        let (ta, tb) = (ma.tree.get(&ma.mesh), mb.tree.get(&mb.mesh));
        let slack = slack_of(exact_below);
        pairs::mesh_distance((&ma.mesh, ta), (&mb.mesh, tb), &pa.inv_mul(&pb), exact_below, slack)
    } else {
        let (sa, qa) = a.parts(&pa);
        let (sb, qb) = b.parts(&pb);
        match query::distance(&qa, sa, &qb, sb) {
            Ok(d) => d.distance,
            Err(_) => return 0.0,
        }
    };
    if d > 0.0 {
        // Separate boundaries: the solids are apart unless one holds the other.
        let inside = |x: &Shape3, px: &Pose, y: &Shape3, py: &Pose| x.reps().iter().any(|&r| y.contains(py, *px * r));
        if inside(a, &pa, b, &pb) || inside(b, &pb, a, &pa) {
            return 0.0;
        }
    }
    if d.is_nan() {
        0.0
    } else {
        d.max(0.0)
    }
}
