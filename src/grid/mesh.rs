//! The cylindrical grid's surface as a closed triangle mesh (binary STL).
//!
//! Vertices: each node's outer point `(R cos θ, R sin θ, z)` and, per column, the bore's ring
//! (or the axis point when there is no bore); the outer and inner surfaces are joined by rings at
//! both ends. Every edge is shared by exactly two triangles; a triangle two of whose corners are
//! one point (the bore's ring of a solid bar is the axis point) is left out, and the surface
//! stays closed through that point. A grid whose surface would
//! take more than [`MAX_TRIANGLES`] is written over blocks of k × k nodes, each block's least
//! radius and greatest bore (what was cut shows; a feature narrower than a block may shrink).

use super::CylGrid;

/// Most triangles written: the STL reader's own cap, so the file reads back as a machine part.
pub const MAX_TRIANGLES: usize = crate::kin::stl::MAX_STL_TRIANGLES;

pub(super) fn stl(c: &CylGrid) -> Option<Vec<u8>> {
    if c.nth == 0 || c.nz == 0 {
        return None;
    }
    let tris = |k: usize| {
        let (a, b) = (c.nth.div_ceil(k), c.nz.div_ceil(k));
        4 * a * b + 4 * a
    };
    let mut k = 1;
    while tris(k) > MAX_TRIANGLES {
        k += 1;
    }
    let (nth, nz) = (c.nth.div_ceil(k), c.nz.div_ceil(k));
    // Block (i, j): nodes k·i .. k·i + k − 1 in θ, k·j .. in z.
    let span = |b: usize, n: usize| (b * k, ((b + 1) * k).min(n));
    let mut rr = vec![0.0; nth * nz];
    let mut bore = vec![0.0f64; nz];
    let mut zs = vec![0.0; nz];
    for j in 0..nz {
        let (z0, z1) = span(j, c.nz);
        bore[j] = (z0..z1).map(|jj| c.inner[jj]).fold(0.0, f64::max);
        zs[j] = (c.z(z0) + c.z(z1 - 1)) / 2.0;
        for i in 0..nth {
            let (i0, i1) = span(i, c.nth);
            let mut r = f64::INFINITY;
            for jj in z0..z1 {
                for ii in i0..i1 {
                    r = r.min(c.radius(ii, jj));
                }
            }
            rr[j * nth + i] = r.max(bore[j]);
        }
    }
    let theta = |i: usize| {
        let (i0, i1) = span(i % nth, c.nth);
        (c.theta(i0) + c.theta(i1 - 1)) / 2.0
    };
    let tris = 4 * nth * nz + 4 * nth;
    let outer = |i: usize, j: usize| {
        let (th, r) = (theta(i), rr[j * nth + i % nth]);
        [r * th.cos(), r * th.sin(), zs[j]]
    };
    let inner = |i: usize, j: usize| {
        let (th, r) = (theta(i), bore[j]);
        [r * th.cos(), r * th.sin(), zs[j]]
    };
    let mut out = Vec::with_capacity(84 + 50 * tris);
    out.extend_from_slice(&[0u8; 80]);
    out.extend_from_slice(&0u32.to_le_bytes());
    let mut count = 0u32;
    let mut tri = |a: [f64; 3], b: [f64; 3], cc: [f64; 3]| {
        // Two corners the same point as written (the axis with no bore, a column cut away): no
        // triangle; the ones around it still close the surface at that point.
        let f = |p: [f64; 3]| p.map(|x| x as f32);
        if f(a) == f(b) || f(b) == f(cc) || f(a) == f(cc) {
            return;
        }
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
                // + 0.0: the axis point's −0.0 and 0.0 are one vertex.
                out.extend_from_slice(&((x as f32) + 0.0).to_le_bytes());
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
