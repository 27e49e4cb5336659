//! The cylindrical grid's surface as a closed triangle mesh (binary STL).
//!
//! Vertices: each node's outer point `(R cos θ, R sin θ, z)` and, per column, the bore's ring
//! (or the axis point when there is no bore); the outer and inner surfaces are joined by rings at
//! both ends. Every edge is shared by exactly two triangles (columns whose material is gone
//! collapse to zero-area triangles, which keep the surface closed).

use super::CylGrid;

/// Most triangles written (a bound on the bytes: 50 per triangle).
const MAX_TRIANGLES: usize = 40_000_000;

pub(super) fn stl(c: &CylGrid) -> Option<Vec<u8>> {
    let (nth, nz) = (c.nth, c.nz);
    let tris = 4 * nth * nz + 4 * nth;
    if tris > MAX_TRIANGLES {
        return None;
    }
    let outer = |i: usize, j: usize| {
        let (th, r) = (c.theta(i % nth), c.radius(i % nth, j));
        [r * th.cos(), r * th.sin(), c.z(j)]
    };
    let inner = |i: usize, j: usize| {
        let (th, r) = (c.theta(i % nth), c.inner[j]);
        [r * th.cos(), r * th.sin(), c.z(j)]
    };
    let mut out = Vec::with_capacity(84 + 50 * tris);
    out.extend_from_slice(&[0u8; 80]);
    out.extend_from_slice(&0u32.to_le_bytes());
    let mut count = 0u32;
    let mut tri = |a: [f64; 3], b: [f64; 3], cc: [f64; 3]| {
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let v = [cc[0] - a[0], cc[1] - a[1], cc[2] - a[2]];
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let n = if l > 0.0 {
            [n[0] / l, n[1] / l, n[2] / l]
        } else {
            [0.0; 3]
        };
        for p in [n, a, b, cc] {
            for x in p {
                out.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        out.extend_from_slice(&0u16.to_le_bytes());
        count += 1;
    };
    for j in 0..nz.saturating_sub(1) {
        for i in 0..nth {
            // Outer surface, facing out (θ counter-clockwise, z up).
            tri(outer(i, j), outer(i + 1, j), outer(i + 1, j + 1));
            tri(outer(i, j), outer(i + 1, j + 1), outer(i, j + 1));
            // Inner surface, facing the axis.
            tri(inner(i, j), inner(i + 1, j + 1), inner(i + 1, j));
            tri(inner(i, j), inner(i, j + 1), inner(i + 1, j + 1));
        }
    }
    // End rings: at the first column facing −z, at the last facing +z.
    for i in 0..nth {
        tri(outer(i, 0), inner(i, 0), inner(i + 1, 0));
        tri(outer(i, 0), inner(i + 1, 0), outer(i + 1, 0));
        let j = nz - 1;
        tri(outer(i, j), outer(i + 1, j), inner(i + 1, j));
        tri(outer(i, j), inner(i + 1, j), inner(i, j));
    }
    out[80..84].copy_from_slice(&count.to_le_bytes());
    Some(out)
}
