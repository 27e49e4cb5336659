//! The milled stock's surface as a closed triangle mesh (binary STL, and the 3D pictures' part).
//!
//! The surface of what every grid calls material (`Stock::contains`), so a face grid's pocket or
//! hole is in it as much as the cylindrical grid's flats: a lattice of points over the stock's
//! box (one cell of air around it), each cube split into six tetrahedra along its main diagonal
//! (the same split in every cube, so neighbours share their faces' triangles), and in each
//! tetrahedron whose corners are partly material the piece of surface between them (marching
//! tetrahedra). Each vertex lies on a lattice edge at the material's boundary, found by
//! bisection with `contains` (so a pocket floor is at its depth, not at a lattice level). Every
//! edge is shared by two triangles running it in opposite directions; the triangles face out.
//!
//! **Plain stretches are merged**: the lattice is fine (`h`) across the axis but along z it has
//! levels only where the stock changes — around a column of the cylindrical grid that differs
//! from its neighbour, and over the box of every face grid's cuts — and at the ends; a turned
//! stretch no tool milled is one slab of long triangles.
//!
//! **Flat faces across the axis are one polygon each** (`flat_faces.rs`): a bar's end, a face with
//! a slot in it, a pocket's floor, re-triangulated through their outline points only.

use nalgebra::Vector3;
use std::collections::HashMap;

use super::flat_faces::{self, FlatFaces};
use super::{Shape, Stock};

/// Most triangles written: the STL reader's own cap, so the file reads back as a machine part.
pub const MAX_TRIANGLES: usize = crate::kin::stl::MAX_STL_TRIANGLES;

/// Lattice cells across the stock's width for `--stock-out` (at least the grids' spacing).
pub const STL_CELLS_ACROSS: usize = 100;

/// A closed surface: vertices and counter-clockwise (seen from outside) triangles.
#[derive(Clone, Debug, Default)]
pub struct Surface {
    pub vertices: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// What writing the flat faces across the axis as one polygon each did (`flat_faces.rs`).
    pub flat: FlatFaces,
}

impl Surface {
    /// As binary STL (coordinates as `f32`).
    pub fn stl(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(84 + 50 * self.triangles.len());
        out.extend_from_slice(&[0u8; 80]);
        out.extend_from_slice(&(self.triangles.len() as u32).to_le_bytes());
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| Vector3::from(self.vertices[i as usize]));
            let n = (b - a).cross(&(c - a));
            let n = if n.norm() > 0.0 { n.normalize() } else { n };
            for p in [n, a, b, c] {
                for x in p.iter() {
                    // + 0.0: −0.0 and 0.0 are one vertex.
                    out.extend_from_slice(&((*x as f32) + 0.0).to_le_bytes());
                }
            }
            out.extend_from_slice(&0u16.to_le_bytes());
        }
        out
    }

    /// The enclosed volume (divergence theorem).
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| Vector3::from(self.vertices[i as usize]));
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }
}

/// The stock's box.
fn bounds(s: &Stock) -> Option<(Vector3<f64>, Vector3<f64>)> {
    match &s.shape {
        Shape::Block { min, max } => Some((*min, *max)),
        Shape::Turned => {
            let c = s.cyl.as_ref()?;
            let r = c.col_max.iter().copied().fold(0.0, f64::max);
            if r <= 0.0 || c.nz == 0 {
                return None;
            }
            Some((
                Vector3::new(-r, -r, c.z0),
                Vector3::new(r, r, c.z0 + c.dz * c.nz as f64),
            ))
        }
    }
}

/// The z ranges where the stock changes along z (the lattice is dense there).
fn busy(s: &Stock, h: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    if let Some(c) = &s.cyl {
        for j in 1..c.nz {
            let same = c.inner[j - 1] == c.inner[j] && c.col_max[j - 1] == c.col_max[j] && c.same_nodes(j - 1, j);
            if !same {
                let z = c.z0 + c.dz * j as f64;
                out.push((z - h, z + h));
            }
        }
    }
    for f in &s.faces {
        if let Some((a, b)) = f.touched {
            out.push((a.z - h, b.z + h));
        }
    }
    out
}

/// Lattice levels from `lo` to `hi` at spacing `h`, one outside each end; with `keep`, only the
/// levels it keeps (and the first and last inside).
fn levels(lo: f64, hi: f64, h: f64, keep: impl Fn(f64) -> bool) -> Vec<f64> {
    // An odd offset: no level lands on a round coordinate (the axis, a column boundary).
    let start = lo - 0.6180339887 * h;
    let n = ((hi - start) / h).ceil() as usize + 1;
    let inside: Vec<f64> = (1..n).map(|k| start + k as f64 * h).filter(|&x| x < hi).collect();
    let mut out = vec![start];
    for (k, &x) in inside.iter().enumerate() {
        if k == 0 || k + 1 == inside.len() || keep(x) {
            out.push(x);
        }
    }
    out.push(hi + 0.3819660113 * h);
    out
}

/// How far a point of a flat face may lie from its plane, in lattice spacings: well above the
/// bisection's error (1/32768 of a lattice edge), far below anything the grids resolve.
pub const PLANE_TOL: f64 = 1e-3;

/// The surface of the stock with about `cells` lattice cells across its width (never finer than
/// its grids resolve), its flat faces across the axis written as one polygon each (their points
/// left where the bisection put them: the pictures' part); `None` for a stock with no material
/// box or a surface past [`MAX_TRIANGLES`] at every spacing tried.
pub fn surface(s: &Stock, cells: usize) -> Option<Surface> {
    let (mut m, h) = lattice(s, cells)?;
    m.flat = flat_faces::merge(&mut m, PLANE_TOL * h, false);
    Some(m)
}

/// The lattice's surface as marching tetrahedra make it, and the lattice spacing.
pub(super) fn lattice(s: &Stock, cells: usize) -> Option<(Surface, f64)> {
    let (lo, hi) = bounds(s)?;
    let width = (hi.x - lo.x).max(hi.y - lo.y);
    let mut h = (width / cells.max(2) as f64).max(s.spacing());
    for _ in 0..8 {
        if let Some(m) = surface_at(s, lo, hi, h) {
            return Some((m, h));
        }
        h *= 1.5;
    }
    None
}

fn surface_at(s: &Stock, lo: Vector3<f64>, hi: Vector3<f64>, h: f64) -> Option<Surface> {
    let xs = levels(lo.x, hi.x, h, |_| true);
    let ys = levels(lo.y, hi.y, h, |_| true);
    let busy = busy(s, h);
    let zs = match s.shape {
        Shape::Turned => levels(lo.z, hi.z, h, |z| busy.iter().any(|&(a, b)| z >= a && z <= b)),
        Shape::Block { .. } => levels(lo.z, hi.z, h, |_| true),
    };
    let (nx, ny, nz) = (xs.len(), ys.len(), zs.len());
    let at = |ix: usize, iy: usize, iz: usize| Vector3::new(xs[ix], ys[iy], zs[iz]);
    let idx = |ix: usize, iy: usize, iz: usize| (iz * ny + iy) * nx + ix;
    let mut inside = vec![false; nx * ny * nz];
    for iz in 0..nz {
        for iy in 0..ny {
            for ix in 0..nx {
                inside[idx(ix, iy, iz)] = s.contains(at(ix, iy, iz));
            }
        }
    }
    let mut m = Surface::default();
    let mut verts: HashMap<(usize, usize), u32> = HashMap::new();
    // The boundary point on the edge from lattice point a (material) to b (air).
    let mut vertex = |a: usize, pa: Vector3<f64>, b: usize, pb: Vector3<f64>, m: &mut Surface| -> u32 {
        let key = (a.min(b), a.max(b));
        *verts.entry(key).or_insert_with(|| {
            let (mut t0, mut t1) = (0.0, 1.0);
            for _ in 0..14 {
                let t = 0.5 * (t0 + t1);
                if s.contains(pa + (pb - pa) * t) {
                    t0 = t;
                } else {
                    t1 = t;
                }
            }
            // Kept off the lattice points, so no two vertices meet.
            let t = (0.5 * (t0 + t1)).clamp(0.02, 0.98);
            let p = pa + (pb - pa) * t;
            m.vertices.push([p.x, p.y, p.z]);
            (m.vertices.len() - 1) as u32
        })
    };
    const PERMS: [[usize; 3]; 6] = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
    for iz in 0..nz - 1 {
        for iy in 0..ny - 1 {
            for ix in 0..nx - 1 {
                let corner = |b: usize| (ix + (b & 1), iy + ((b >> 1) & 1), iz + ((b >> 2) & 1));
                let ins: [bool; 8] = std::array::from_fn(|b| {
                    let (x, y, z) = corner(b);
                    inside[idx(x, y, z)]
                });
                if ins.iter().all(|&v| v == ins[0]) {
                    continue;
                }
                for p in PERMS {
                    let v1 = 1 << p[0];
                    let tet = [0usize, v1, v1 | (1 << p[1]), 7];
                    let (i_in, i_out): (Vec<usize>, Vec<usize>) = tet.iter().partition(|&&b| ins[b]);
                    if i_in.is_empty() || i_out.is_empty() {
                        continue;
                    }
                    let g = |b: usize| {
                        let (x, y, z) = corner(b);
                        (idx(x, y, z), at(x, y, z))
                    };
                    let mut e = |a: usize, b: usize, m: &mut Surface| {
                        let ((ga, pa), (gb, pb)) = (g(a), g(b));
                        vertex(ga, pa, gb, pb, m)
                    };
                    let poly: Vec<u32> = match (i_in.len(), i_out.len()) {
                        (1, _) => i_out.iter().map(|&o| e(i_in[0], o, &mut m)).collect(),
                        (_, 1) => i_in.iter().map(|&i| e(i, i_out[0], &mut m)).collect(),
                        _ => {
                            let (a, b, c, d) = (i_in[0], i_in[1], i_out[0], i_out[1]);
                            vec![e(a, c, &mut m), e(a, d, &mut m), e(b, d, &mut m), e(b, c, &mut m)]
                        }
                    };
                    // Face out: the polygon's normal toward the air corners.
                    let centre = |bs: &[usize]| bs.iter().map(|&b| g(b).1).sum::<Vector3<f64>>() / bs.len() as f64;
                    let dir = centre(&i_out) - centre(&i_in);
                    let pts: Vec<Vector3<f64>> = poly.iter().map(|&v| Vector3::from(m.vertices[v as usize])).collect();
                    let mut n = Vector3::zeros();
                    for k in 0..pts.len() {
                        n += pts[k].cross(&pts[(k + 1) % pts.len()]);
                    }
                    let mut poly = poly;
                    if n.dot(&dir) < 0.0 {
                        poly.reverse();
                    }
                    for k in 1..poly.len() - 1 {
                        m.triangles.push([poly[0], poly[k], poly[k + 1]]);
                    }
                    if m.triangles.len() > MAX_TRIANGLES {
                        return None;
                    }
                }
            }
        }
    }
    Some(m)
}

/// The stock's surface as binary STL (`--stock-out`): its flat faces across the axis written as
/// one polygon each, their points on the face's plane.
pub(super) fn stl(s: &Stock) -> Option<Vec<u8>> {
    let (mut m, h) = lattice(s, STL_CELLS_ACROSS)?;
    m.flat = flat_faces::merge(&mut m, PLANE_TOL * h, true);
    Some(m.stl())
}
