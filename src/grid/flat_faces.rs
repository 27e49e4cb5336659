//! Flat faces across the axis as one polygon each: the lattice's small triangles of a plane
//! `z = const` (a bar's end, a face, a pocket's floor) replaced by a triangulation of the face's
//! outline and holes through their points only.
//!
//! A face is a maximal set of triangles that lie in one plane across the axis (every vertex within
//! `tol` of it), face the same way (+z or −z) and meet edge to edge. Its outline is the set of
//! its edges whose other triangle is not in the face; every outline point is kept, collinear ones
//! included, so the triangles around the face still share their edges with it and the surface
//! stays closed. The outline is triangulated by a constrained Delaunay triangulation (`spade`,
//! exact predicates) in the plane: the outline's edges as constraints, the triangles inside the
//! outline (an odd number of constraints crossed from outside) kept. For the STL the face's
//! points are then put on its plane (they lie on it only to the bisection's tolerance).
//!
//! A face is left as it was (and counted) when the result could not be proved right: an outline
//! that touches itself at a point, two outline points at the same place, an outline edge through
//! another point, a triangle of no area, outline edges other than the face's own, a triangle
//! count other than a polygon's (points + 2 × holes − 2), or a new inside edge that some other
//! triangle already uses. Nothing here panics; a surface with an edge run twice the same way (not
//! a closed surface) is returned untouched.

use std::collections::{HashMap, HashSet};

use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::mesh::Surface;

/// What the merge did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FlatFaces {
    /// Faces written as one polygon each.
    pub merged: usize,
    /// Faces left as the lattice made them: their outline could not be triangulated safely.
    pub kept: usize,
    /// Faces already as few triangles as their outline allows (nothing to gain).
    pub small: usize,
    /// Triangles before the merge.
    pub triangles_before: usize,
}

/// A face found: its triangles and which way it faces (+z: `up`).
struct Face {
    tris: Vec<usize>,
    up: bool,
}

/// Merges every flat face across the axis of a closed surface (see the module's text); `tol` is
/// how far from its plane a face's point may lie (mm); with `snap`, the points of a merged face
/// are put on its plane (for the STL; the pictures keep them where the bisection found them, so
/// that a part touching the face draws as it did).
pub fn merge(m: &mut Surface, tol: f64, snap: bool) -> FlatFaces {
    let mut out = FlatFaces {
        triangles_before: m.triangles.len(),
        ..FlatFaces::default()
    };
    if tol.is_nan() || tol <= 0.0 || m.triangles.iter().flatten().any(|&v| v as usize >= m.vertices.len()) {
        return out;
    }
    // Each directed edge → its triangle; a surface with an edge run twice the same way is not
    // closed: leave it.
    let Some(edges) = Edges::new(m) else { return out };
    let (faces, face_of) = find_faces(m, &edges, tol);
    if faces.is_empty() {
        return out;
    }
    // The inside edges of the faces merged so far: a new inside edge must be none of them (nor
    // an edge of the surface outside its own face).
    let mut new_edges: HashSet<(u32, u32)> = HashSet::new();
    let mut gone = vec![false; m.triangles.len()];
    let mut added: Vec<[u32; 3]> = Vec::new();
    for (id, f) in faces.iter().enumerate() {
        let here = Here {
            edges: &edges,
            face_of: &face_of,
            id,
            new_edges: &new_edges,
        };
        match triangulate(m, f, &here) {
            Ok((tris, z)) => {
                for &i in &f.tris {
                    gone[i] = true;
                }
                for t in &tris {
                    for k in 0..3 {
                        let (a, b) = (t[k], t[(k + 1) % 3]);
                        new_edges.insert((a.min(b), a.max(b)));
                    }
                    for &v in t {
                        if snap {
                            m.vertices[v as usize][2] = z;
                        }
                    }
                }
                added.extend(tris);
                out.merged += 1;
            }
            Err(Left::Small) => out.small += 1,
            Err(Left::Unsafe) => out.kept += 1,
        }
    }
    if out.merged == 0 {
        return out;
    }
    let mut tris: Vec<[u32; 3]> = m
        .triangles
        .iter()
        .zip(&gone)
        .filter(|(_, &g)| !g)
        .map(|(t, _)| *t)
        .collect();
    tris.extend(added);
    m.triangles = tris;
    compact(m);
    out
}

/// The surface's directed edges by their first point (sorted by their second), each with its
/// triangle: an edge's triangle is found without hashing.
struct Edges {
    start: Vec<usize>,
    to: Vec<(u32, usize)>,
}

impl Edges {
    /// `None` if some edge is run twice the same way.
    fn new(m: &Surface) -> Option<Edges> {
        let mut start = vec![0usize; m.vertices.len() + 1];
        for t in &m.triangles {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..m.vertices.len() {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut to = vec![(0u32, 0usize); start[m.vertices.len()]];
        for (i, t) in m.triangles.iter().enumerate() {
            for k in 0..3 {
                let a = t[k] as usize;
                to[fill[a]] = (t[(k + 1) % 3], i);
                fill[a] += 1;
            }
        }
        for v in 0..m.vertices.len() {
            let out = &mut to[start[v]..start[v + 1]];
            out.sort_unstable();
            if out.windows(2).any(|w| w[0].0 == w[1].0) {
                return None;
            }
        }
        Some(Edges { start, to })
    }

    /// The triangle that runs the edge from `a` to `b`.
    fn owner(&self, a: u32, b: u32) -> Option<usize> {
        let out = &self.to[self.start[a as usize]..self.start[a as usize + 1]];
        out.binary_search_by_key(&b, |e| e.0).ok().map(|k| out[k].1)
    }
}

/// What a face's triangulation is checked against: the surface's edges, which face each triangle
/// belongs to, this face's number, the inside edges of the faces merged before it.
struct Here<'a> {
    edges: &'a Edges,
    face_of: &'a [usize],
    id: usize,
    new_edges: &'a HashSet<(u32, u32)>,
}

impl Here<'_> {
    fn mine(&self, tri: Option<usize>) -> bool {
        tri.is_some_and(|i| self.face_of[i] == self.id)
    }

    /// Whether a new inside edge between `a` and `b` is one no other triangle has: an edge of the
    /// surface only if both its triangles are this face's, and none a face merged before made.
    fn free(&self, a: u32, b: u32) -> bool {
        let (ab, ba) = (self.edges.owner(a, b), self.edges.owner(b, a));
        let old_ok = (ab.is_none() && ba.is_none()) || (self.mine(ab) && self.mine(ba));
        old_ok && !self.new_edges.contains(&(a.min(b), a.max(b)))
    }
}

/// The faces across the axis of more than one triangle, and each triangle's face (`usize::MAX`:
/// none).
fn find_faces(m: &Surface, edges: &Edges, tol: f64) -> (Vec<Face>, Vec<usize>) {
    let p = |v: u32| m.vertices[v as usize];
    // Per triangle: its mean z and which way it faces, if it lies in a plane across the axis.
    let flat: Vec<Option<(f64, bool)>> = m
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(p);
            let (lo, hi) = (a[2].min(b[2]).min(c[2]), a[2].max(b[2]).max(c[2]));
            if (hi - lo).is_nan() || hi - lo > tol {
                return None;
            }
            let o = robust::orient2d(xy(a), xy(b), xy(c));
            (o != 0.0).then_some(((a[2] + b[2] + c[2]) / 3.0, o > 0.0))
        })
        .collect();
    let mut seen = vec![false; m.triangles.len()];
    let mut face_of = vec![usize::MAX; m.triangles.len()];
    let mut faces = Vec::new();
    for start in 0..m.triangles.len() {
        let Some((_, up)) = flat[start] else { continue };
        if seen[start] {
            continue;
        }
        seen[start] = true;
        let mut tris = vec![start];
        let mut k = 0;
        while k < tris.len() {
            let i = tris[k];
            k += 1;
            let (zi, _) = flat[i].unwrap_or_default();
            let t = m.triangles[i];
            for e in 0..3 {
                let Some(j) = edges.owner(t[(e + 1) % 3], t[e]) else {
                    continue;
                };
                if seen[j] {
                    continue;
                }
                if let Some((zj, uj)) = flat[j] {
                    if uj == up && (zj - zi).abs() <= tol {
                        seen[j] = true;
                        tris.push(j);
                    }
                }
            }
        }
        if tris.len() > 1 {
            for &i in &tris {
                face_of[i] = faces.len();
            }
            faces.push(Face { tris, up });
        }
    }
    (faces, face_of)
}

fn xy(p: [f64; 3]) -> robust::Coord<f64> {
    robust::Coord { x: p[0], y: p[1] }
}

/// Why a face is left as it was.
enum Left {
    /// It has no more triangles than its outline needs.
    Small,
    /// Its outline could not be triangulated safely.
    Unsafe,
}

/// The face's triangles through its outline points only, facing as the face did, and its plane's
/// z.
fn triangulate(m: &Surface, f: &Face, here: &Here) -> Result<(Vec<[u32; 3]>, f64), Left> {
    // The outline, directed as the face runs it.
    let mut outline: Vec<(u32, u32)> = Vec::new();
    for &i in &f.tris {
        let t = m.triangles[i];
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if !here.mine(here.edges.owner(b, a)) {
                outline.push((a, b));
            }
        }
    }
    // One edge out of every outline point: loops that never touch.
    let mut next: HashMap<u32, u32> = HashMap::with_capacity(outline.len());
    for &(a, b) in &outline {
        if next.insert(a, b).is_some() {
            return Err(Left::Unsafe);
        }
    }
    let loops = count_loops(&next).ok_or(Left::Unsafe)?;
    let points = next.len();
    // A polygon with holes through its outline points only: points + 2 × holes − 2 triangles.
    let want = points + 2 * loops - 4;
    if want >= f.tris.len() {
        return Err(Left::Small);
    }
    // In the order of the points' numbers: the same file from the same stock on every run.
    let mut order: Vec<u32> = next.keys().copied().collect();
    order.sort_unstable();
    let z = order.iter().map(|&v| m.vertices[v as usize][2]).sum::<f64>() / points as f64;

    let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> = ConstrainedDelaunayTriangulation::new();
    let mut handle = HashMap::with_capacity(points);
    let mut vertex_of = Vec::with_capacity(points);
    for &v in &order {
        let p = m.vertices[v as usize];
        let h = cdt.insert(Point2::new(p[0], p[1])).map_err(|_| Left::Unsafe)?;
        if h.index() != vertex_of.len() {
            return Err(Left::Unsafe); // Two outline points at one place.
        }
        vertex_of.push(v);
        handle.insert(v, h);
    }
    for &(a, b) in &outline {
        let (ha, hb) = (handle[&a], handle[&b]);
        let made = cdt.try_add_constraint(ha, hb);
        // Exactly the edge from a to b: not split at a point on it, not crossing another.
        if made.len() != 1 {
            return Err(Left::Unsafe);
        }
        let e = cdt.directed_edge(made[0]);
        let ends = [e.from().fix(), e.to().fix()];
        if ends != [ha, hb] && ends != [hb, ha] {
            return Err(Left::Unsafe);
        }
    }
    let inside = inside_faces(&cdt).ok_or(Left::Unsafe)?;
    let mut tris = Vec::with_capacity(want);
    for face in cdt.inner_faces() {
        if !inside[face.fix().index()] {
            continue;
        }
        let [a, b, c] = face.vertices().map(|v| vertex_of[v.fix().index()]);
        let o = robust::orient2d(
            xy(m.vertices[a as usize]),
            xy(m.vertices[b as usize]),
            xy(m.vertices[c as usize]),
        );
        if o == 0.0 {
            return Err(Left::Unsafe);
        }
        tris.push(if (o > 0.0) == f.up { [a, b, c] } else { [a, c, b] });
    }
    if tris.len() != want {
        return Err(Left::Unsafe);
    }
    // The new triangles' own outline is the face's, edge for edge and the same way round, and
    // their inside edges are new to the surface.
    let mut dir: HashSet<(u32, u32)> = HashSet::with_capacity(3 * tris.len());
    for t in &tris {
        for k in 0..3 {
            if !dir.insert((t[k], t[(k + 1) % 3])) {
                return Err(Left::Unsafe);
            }
        }
    }
    let mut rim = 0;
    for &(a, b) in &dir {
        if dir.contains(&(b, a)) {
            if !here.free(a, b) {
                return Err(Left::Unsafe);
            }
        } else {
            rim += 1;
        }
    }
    if rim != outline.len() || outline.iter().any(|e| !dir.contains(e)) {
        return Err(Left::Unsafe);
    }
    Ok((tris, z))
}

/// How many loops the outline's edges make, each point with one edge in and one out; `None` if
/// some point has no edge in.
fn count_loops(next: &HashMap<u32, u32>) -> Option<usize> {
    let mut done: HashSet<u32> = HashSet::with_capacity(next.len());
    let mut loops = 0;
    for &start in next.keys() {
        if done.contains(&start) {
            continue;
        }
        loops += 1;
        let mut v = start;
        loop {
            if !done.insert(v) {
                // Back at a point already walked: only the start closes a loop.
                if v != start {
                    return None;
                }
                break;
            }
            v = *next.get(&v)?;
        }
    }
    Some(loops)
}

/// Which faces of the triangulation lie inside the outline, by face index: crossing a constraint
/// edge steps in or out; `None` if the constraints do not bound regions consistently.
fn inside_faces(cdt: &ConstrainedDelaunayTriangulation<Point2<f64>>) -> Option<Vec<bool>> {
    let n = cdt.num_all_faces();
    let outer = cdt.outer_face().fix().index();
    // Each face's neighbours across its edges, and whether that edge is a constraint.
    let mut next: Vec<Vec<(usize, bool)>> = vec![Vec::new(); n];
    for face in cdt.inner_faces() {
        let i = face.fix().index();
        for e in face.adjacent_edges() {
            let j = e.rev().face().fix().index();
            let cross = e.as_undirected().data().is_constraint_edge();
            if i >= n || j >= n {
                return None;
            }
            next[i].push((j, cross));
            if j == outer {
                next[outer].push((i, cross));
            }
        }
    }
    let mut side: Vec<Option<bool>> = vec![None; n];
    side[outer] = Some(false);
    let mut stack = vec![outer];
    while let Some(i) = stack.pop() {
        let s = side[i]?;
        for &(j, cross) in &next[i] {
            let want = s ^ cross;
            match side[j] {
                Some(have) if have != want => return None,
                Some(_) => {}
                None => {
                    side[j] = Some(want);
                    stack.push(j);
                }
            }
        }
    }
    side.into_iter().collect()
}

/// Drops the points no triangle uses any more.
fn compact(m: &mut Surface) {
    let mut new_index = vec![u32::MAX; m.vertices.len()];
    let mut vertices = Vec::with_capacity(m.vertices.len());
    for t in &mut m.triangles {
        for v in t.iter_mut() {
            let slot = &mut new_index[*v as usize];
            if *slot == u32::MAX {
                *slot = vertices.len() as u32;
                vertices.push(m.vertices[*v as usize]);
            }
            *v = *slot;
        }
    }
    m.vertices = vertices;
}
