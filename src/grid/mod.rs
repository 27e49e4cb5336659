//! The milled stock (matrix grids, docs/grid-stock.md): what live tools leave on a part.
//!
//! A [`Stock`] is the raw solid cut down by grids of nodes, each node a ray into the material
//! along which the material's boundary is held:
//! - a turned part: the **cylindrical grid** ([`CylGrid`]: `R(θ, z)` from the spindle axis, with
//!   the bore `r_in(z)`) and a **face grid** over its front face ([`FaceGrid`]: the depth `d(x, y)`
//!   removed along −z);
//! - a block: a face grid on each of its six faces.
//!
//! A point is material when every grid says so. A cut ([`Sweep`]: a [`Cutter`] moved along a
//! line with its axis fixed) changes a node only where the swept solid reaches its ray at the
//! material's boundary, from outside: the ray's new boundary is where it leaves the sweep (the
//! ray meets a convex swept solid in one interval, found exactly: `sweep.rs`). Only the nodes
//! under the sweep's bounding box are visited, so the cost of a cut depends on the cutter and
//! the grid's density, never on how many cuts came before.
//!
//! Limits, all on the conservative side (the grid never holds less material than the part):
//! a void no ray reaches from its grid's outside (a cross hole's far wall seen along a ray at
//! another angle, a pocket's undercut) stays material; a bore is one inner radius per `z` (inner
//! grooves are filled); curved cutter ends other than a ball are stacks of inscribed discs (at
//! most the tolerance narrower). No I/O, no panics; sizes are capped ([`MAX_NODES`]).

mod cutter;
mod cyl;
mod face;
mod flat_faces;
mod mesh;
mod sweep;

pub use cutter::{Cutter, CutterKind, Sweep};
pub use cyl::CylGrid;
pub(crate) use face::samples_within;
pub use face::FaceGrid;
pub use flat_faces::FlatFaces;
pub use mesh::{Surface, STL_CELLS_ACROSS};

use nalgebra::Vector3;

/// Most nodes of one stock (all its grids).
pub const MAX_NODES: usize = 16_000_000;
/// Most side grids (face grids across a cutter axis no other grid looks along).
pub const MAX_SIDE_GRIDS: usize = 12;

/// `x.floor()`, bit for bit, without a call: on the baseline x86-64 target `f64::floor` is a
/// library function, and the grids' point tests take one or two a point (millions a program).
/// Below 2^52 in magnitude the conversion to an integer truncates exactly, and a truncation that
/// rounded up (a negative non-integer) is one more than the floor; the sign is the argument's
/// (`-0.0` stays `-0.0`, and `-0.5` truncates to `-0.0` before the step down). Beyond that (whole
/// numbers already, infinities) and for NaN, `f64::floor` itself.
#[inline(always)]
pub(crate) fn floor(x: f64) -> f64 {
    if x.abs() < 4_503_599_627_370_496.0 {
        let t = (x as i64 as f64).copysign(x);
        if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// `x.ceil()`, bit for bit, without a call ([`floor`]): the ceiling is minus the floor of minus
/// the argument, both exact operations, the signed zeros included (`ceil(-0.5)` is `-0.0`, minus
/// `floor(0.5)`).
#[inline(always)]
pub(crate) fn ceil(x: f64) -> f64 {
    -floor(-x)
}

/// A stock that could not be built.
#[derive(Clone, Debug, PartialEq)]
pub struct GridError(pub String);

impl std::fmt::Display for GridError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// A run of cuts with nothing else changing the stock between them ([`Stock::cut_in_run`]): the
/// last sweep when it changed nothing.
#[derive(Debug, Default)]
pub struct CutRun {
    idle: Option<Sweep>,
}

/// What the stock's shape is, for its volume and mesh.
#[derive(Clone, Debug)]
enum Shape {
    Turned,
    Block { min: Vector3<f64>, max: Vector3<f64> },
}

/// The milled stock: its grids.
#[derive(Clone, Debug)]
pub struct Stock {
    shape: Shape,
    pub cyl: Option<CylGrid>,
    pub faces: Vec<FaceGrid>,
    /// The tolerance cutters' curved ends are stacked to.
    pub tolerance: f64,
}

/// Node spacing for a tolerance over an area, coarsened until `budget` nodes cover it.
fn spacing(tol: f64, area: f64, budget: usize) -> f64 {
    let s = tol.max(1e-3);
    let min = (area / budget as f64).sqrt();
    s.max(min)
}

impl Stock {
    /// A turned part from its revolved profile: `profile(z) → (r_in, r_out)` (`None`: no
    /// material) over `z_lo .. z_hi`, radii at most `r_max`. Nodes are spaced at most `tol`
    /// apart (on the outer radius) unless that would pass [`MAX_NODES`]: then as fine as the
    /// cap allows (`spacing()` says which).
    pub fn turned(
        z_lo: f64,
        z_hi: f64,
        r_max: f64,
        tol: f64,
        profile: impl Fn(f64) -> Option<(f64, f64)>,
    ) -> Result<Stock, GridError> {
        if !(z_lo.is_finite() && z_hi.is_finite() && z_hi > z_lo && r_max.is_finite() && r_max > 0.0) {
            return Err(GridError(format!(
                "no turned stock from z {z_lo} to {z_hi} with radius {r_max}"
            )));
        }
        let len = z_hi - z_lo;
        let circ = std::f64::consts::TAU * r_max;
        let face_area = (2.0 * r_max) * (2.0 * r_max);
        // Half the nodes for the cylinder and the face; the rest for side grids.
        let s = spacing(tol, circ * len + 2.0 * face_area, MAX_NODES / 2);
        let nz = ((len / s).ceil() as usize).max(1);
        let nth = ((circ / s).ceil() as usize).max(8);
        let nf = ((2.0 * r_max / s).ceil() as usize).max(2);
        if nz.saturating_mul(nth).saturating_add(nf * nf) > MAX_NODES {
            return Err(GridError(format!(
                "a turned stock of {len} mm by radius {r_max} mm needs more than {MAX_NODES} nodes"
            )));
        }
        let cyl = CylGrid::new(z_lo, len / nz as f64, nz, nth, &profile);
        // The front face's grid: material along −z begins where the profile first holds the
        // node's radius, searched column by column from the front.
        let df = 2.0 * r_max / nf as f64;
        let origin = Vector3::new(-r_max, r_max, z_hi);
        let (dzc, z0) = (cyl.dz, cyl.z0);
        let cols: Vec<Option<(f64, f64)>> = (0..nz).map(|j| profile(z0 + (j as f64 + 0.5) * dzc)).collect();
        // Beyond every column's outer radius no ray meets material: no search.
        let r_top = cols.iter().flatten().map(|c| c.1).fold(0.0, f64::max);
        // Per block of columns, the least inner and the largest outer radius: a radius outside
        // them is held by none of its columns.
        const BLOCK: usize = 64;
        let blocks: Vec<(f64, f64)> = cols
            .chunks(BLOCK)
            .map(|c| {
                c.iter()
                    .flatten()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &(ri, ro)| {
                        (lo.min(ri), hi.max(ro))
                    })
            })
            .collect();
        let face = FaceGrid::flat(origin, Vector3::x(), -Vector3::y(), (df, df), (nf, nf), len).with_start(|u, v| {
            // e_v = −y so that e_u × e_v = −z (inward from the front face).
            let (x, y) = (-r_max + u, r_max - v);
            let rho = x.hypot(y);
            if rho > r_top {
                return None;
            }
            // The frontmost column holding the radius, blocks that cannot hold it passed over.
            (0..blocks.len()).rev().find_map(|b| {
                let (lo, hi) = blocks[b];
                if !(rho >= lo && rho <= hi) {
                    return None;
                }
                (b * BLOCK..((b + 1) * BLOCK).min(nz)).rev().find_map(|j| {
                    cols[j]
                        .filter(|&(ri, ro)| rho >= ri && rho <= ro)
                        .map(|_| z_hi - (z0 + (j as f64 + 1.0) * dzc))
                })
            })
        });
        Ok(Stock {
            shape: Shape::Turned,
            cyl: Some(cyl),
            faces: vec![face],
            tolerance: tol,
        })
    }

    /// A block from `min` to `max` with an `n × n` grid on each face.
    pub fn block(min: Vector3<f64>, max: Vector3<f64>, n: usize, tol: f64) -> Result<Stock, GridError> {
        let size = max - min;
        if !(size.iter().all(|x| x.is_finite() && *x > 0.0))
            || n == 0
            || n.saturating_mul(n).saturating_mul(6) > MAX_NODES
        {
            return Err(GridError(format!(
                "no block from {min:?} to {max:?} with {n}×{n} grids"
            )));
        }
        let mut faces = Vec::with_capacity(6);
        // For each axis k, the faces at min (inward +k) and at max (inward −k).
        for k in 0..3 {
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            let e = |i: usize| Vector3::ith(i, 1.0);
            for at_max in [false, true] {
                // e_u × e_v must be the inward normal.
                let (eu, ev) = if at_max { (e(b), e(a)) } else { (e(a), e(b)) };
                let mut origin = min;
                if at_max {
                    origin[k] = max[k];
                }
                let (lu, lv) = (size.dot(&eu), size.dot(&ev));
                faces.push(FaceGrid::flat(
                    origin,
                    eu,
                    ev,
                    (lu / n as f64, lv / n as f64),
                    (n, n),
                    size[k],
                ));
            }
        }
        Ok(Stock {
            shape: Shape::Block { min, max },
            cyl: None,
            faces,
            tolerance: tol,
        })
    }

    /// Apply a sweep to every grid. Returns the volume the grids lost (mm³; summed over the
    /// grids, so where two grids see the same material it counts twice: any removal above zero
    /// means the cutter cut). A cutter whose axis no grid looks along gets a face grid across
    /// it first (a **side grid**, up to [`MAX_SIDE_GRIDS`]), so that the hole it drills is seen
    /// from where it enters.
    pub fn cut(&mut self, sw: &Sweep) -> f64 {
        self.ensure_side_grid(sw);
        self.run(sw, true, true)
    }

    /// [`Stock::cut`] with every ray cast: none of the cylindrical grid's answered from the memo
    /// of its column's neighbour ([`CylGrid::cut`]), none of a face grid's left by its known exit
    /// ([`FaceGrid::cut`]): their oracle.
    #[cfg(test)]
    pub(crate) fn cut_casting_every_ray(&mut self, sw: &Sweep) -> f64 {
        self.ensure_side_grid(sw);
        self.run(sw, true, false)
    }

    /// [`Stock::cut`] for one of a run of cuts that nothing else changes the stock between (the
    /// chords of one move): a sweep bit for bit the run's last one ([`Sweep::same_bits`]) when
    /// that one changed nothing (removed nothing, added no side grid) is not applied. The stock
    /// is then as it was when that same sweep left it unchanged, and a cut is a function of the
    /// stock and the sweep: it would change nothing again (a C turn at the spindle axis, the
    /// cutter's tip on it, repeats one sweep for every chord of the turn). Returns what the cut
    /// removed, 0 for one left out (what it would have returned).
    pub fn cut_in_run(&mut self, sw: &Sweep, run: &mut CutRun) -> f64 {
        if run.idle.as_ref().is_some_and(|last| last.same_bits(sw)) {
            return 0.0;
        }
        let grids = self.faces.len();
        let removed = self.cut(sw);
        run.idle = (removed == 0.0 && self.faces.len() == grids).then(|| sw.clone());
        removed
    }

    /// What the sweep would remove (mm³), without applying it.
    pub fn would_remove(&mut self, sw: &Sweep) -> f64 {
        self.ensure_side_grid(sw);
        self.run(sw, false, true)
    }

    /// The rays the cuts (and measures) of this stock have cast into its grids: the work of its
    /// cuts, whatever their size (`stats.grid_rays`).
    pub fn rays(&self) -> u64 {
        self.cyl.as_ref().map_or(0, |c| c.rays) + self.faces.iter().map(|f| f.rays).sum::<u64>()
    }

    fn run(&mut self, sw: &Sweep, apply: bool, memo: bool) -> f64 {
        let step = self.air_step();
        let mut v = 0.0;
        if let Some(mut c) = self.cyl.take() {
            v += c
                .cut_nodes(sw, &|p| !self.contains_except(p, None), step, apply, memo)
                .0;
            self.cyl = Some(c);
        }
        for k in 0..self.faces.len() {
            let mut f = std::mem::replace(&mut self.faces[k], FaceGrid::empty());
            // Outside the cylindrical grid's reach every other grid's point is air.
            let span = |o: Vector3<f64>, u: Vector3<f64>, a: f64, b: f64| match &self.cyl {
                Some(c) => c.may_hold(o, u, a, b),
                None => Some((a, b)),
            };
            v += f.cut_nodes(sw, &|p| !self.contains_except(p, Some(k)), &span, step, apply, memo);
            self.faces[k] = f;
        }
        v
    }

    /// The sampling step of the air checks: the finest grid spacing.
    fn air_step(&self) -> f64 {
        let mut s = self.tolerance.max(1e-3);
        if let Some(c) = &self.cyl {
            s = s.max(c.dz.min(1.0));
        }
        s
    }

    /// A side grid across the sweep's axis (inward −axis) when the cutter feeds along its axis
    /// (a drill, a plunge: at least half its motion along it), unless a grid already looks along
    /// it. A cutter moving sideways is seen by the grids that look across it.
    fn ensure_side_grid(&mut self, sw: &Sweep) {
        let along = sw.v.dot(&sw.axis).abs();
        if sw.v.norm() < 1e-9 || along < 0.5 * sw.v.norm() {
            return;
        }
        let n = -sw.axis;
        if self.faces.iter().any(|f| f.n.dot(&n) > 1.0 - 1e-9) || self.faces.len() >= MAX_SIDE_GRIDS + 6 {
            return;
        }
        // The stock's box.
        let (lo, hi) = match &self.shape {
            Shape::Block { min, max } => (*min, *max),
            Shape::Turned => {
                let Some(c) = &self.cyl else { return };
                let r = c.col_max.iter().copied().fold(0.0, f64::max);
                (
                    Vector3::new(-r, -r, c.z0),
                    Vector3::new(r, r, c.z0 + c.dz * c.nz as f64),
                )
            }
        };
        let ref_dir = if n.z.abs() < 0.9 { Vector3::z() } else { Vector3::x() };
        let ev = (ref_dir - n * n.dot(&ref_dir)).normalize();
        let eu = ev.cross(&n);
        let mut a = [f64::INFINITY; 3];
        let mut b = [f64::NEG_INFINITY; 3];
        for k in 0..8 {
            let c = Vector3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            for (i, e) in [eu, ev, n].iter().enumerate() {
                a[i] = a[i].min(c.dot(e));
                b[i] = b[i].max(c.dot(e));
            }
        }
        let (lu, lv) = (b[0] - a[0], b[1] - a[1]);
        let used: usize =
            self.cyl.as_ref().map_or(0, |c| c.nodes()) + self.faces.iter().map(|f| f.d.len()).sum::<usize>();
        let budget = MAX_NODES.saturating_sub(used);
        if budget < 4 {
            return;
        }
        // No finer than the stock's own grids (their spacing sets what the stock resolves).
        let s = spacing(self.tolerance, lu * lv, budget).max(self.spacing());
        let (nu, nv) = (((lu / s).ceil() as usize).max(1), ((lv / s).ceil() as usize).max(1));
        if nu * nv > budget {
            return;
        }
        let origin = a[0] * eu + a[1] * ev + a[2] * n;
        self.faces.push(FaceGrid::flat(
            origin,
            eu,
            ev,
            (lu / nu as f64, lv / nv as f64),
            (nu, nv),
            b[2] - a[2],
        ));
    }

    /// Material by every grid but face grid `skip` (`None`: but the cylindrical grid).
    fn contains_except(&self, p: Vector3<f64>, skip: Option<usize>) -> bool {
        if let Shape::Block { min, max } = &self.shape {
            if (0..3).any(|k| p[k] < min[k] || p[k] > max[k]) {
                return false;
            }
        }
        if skip.is_some() {
            if let Some(c) = &self.cyl {
                if !c.contains(p) {
                    return false;
                }
            }
        } else if let Shape::Turned = self.shape {
            // The cylindrical grid is the turned part's outline: outside its columns, air.
            if let Some(c) = &self.cyl {
                if p.z < c.z0 || p.z > c.z0 + c.dz * c.nz as f64 {
                    return false;
                }
            }
        }
        self.faces
            .iter()
            .enumerate()
            .all(|(k, f)| Some(k) == skip || f.contains(p))
    }

    /// Whether a point is material: inside every grid's material.
    pub fn contains(&self, p: Vector3<f64>) -> bool {
        if let Shape::Block { min, max } = &self.shape {
            if (0..3).any(|k| p[k] < min[k] || p[k] > max[k]) {
                return false;
            }
        }
        self.cyl.as_ref().map_or(true, |c| c.contains(p)) && self.faces.iter().all(|f| f.contains(p))
    }

    /// The volume of material (mm³). A turned part: the cylindrical grid's wedges, each ray cut
    /// back where the face grid holds no material (sampled at the face grid's spacing). A block:
    /// its volume less what each face lost (exact while no two faces' cuts meet).
    pub fn volume(&self) -> f64 {
        match &self.shape {
            Shape::Block { min, max } => {
                let s = max - min;
                s.x * s.y * s.z - self.faces.iter().map(FaceGrid::removed).sum::<f64>()
            }
            Shape::Turned => {
                let Some(c) = self.cyl.as_ref() else { return 0.0 };
                let boxes: Vec<(Vector3<f64>, Vector3<f64>)> = self.faces.iter().filter_map(|f| f.touched).collect();
                let dth = std::f64::consts::TAU / c.nth as f64;
                let step = self.faces.iter().map(|f| f.du.min(f.dv)).fold(c.dz, f64::min).max(1e-3);
                let mut v = 0.0;
                for j in 0..c.nz {
                    let z = c.z(j);
                    let ri = c.inner[j];
                    let near: Vec<&(Vector3<f64>, Vector3<f64>)> =
                        boxes.iter().filter(|(a, b)| z >= a.z && z <= b.z).collect();
                    for i in 0..c.nth {
                        let r = c.radius(i, j);
                        if r <= ri {
                            continue;
                        }
                        let th = c.theta(i);
                        let (cs, sn) = (th.cos(), th.sin());
                        // Does the ray's segment pass through a box some face grid cut in?
                        let hit = near.iter().any(|(a, b)| {
                            let (x0, x1) = (ri * cs, r * cs);
                            let (y0, y1) = (ri * sn, r * sn);
                            x0.max(x1) >= a.x && x0.min(x1) <= b.x && y0.max(y1) >= a.y && y0.min(y1) <= b.y
                        });
                        if !hit {
                            v += (r * r - ri * ri) / 2.0;
                            continue;
                        }
                        let n = ((r - ri) / step).ceil().max(1.0) as usize;
                        let dr = (r - ri) / n as f64;
                        for k in 0..n {
                            let rho = ri + (k as f64 + 0.5) * dr;
                            let p = Vector3::new(rho * cs, rho * sn, z);
                            if self.faces.iter().all(|f| f.contains(p)) {
                                v += rho * dr;
                            }
                        }
                    }
                }
                v * dth * c.dz
            }
        }
    }

    /// The part as a closed triangle mesh in binary STL: the surface of what every grid calls
    /// material (`mesh.rs`), face grids' pockets and holes included.
    pub fn stl(&self) -> Option<Vec<u8>> {
        mesh::stl(self)
    }

    /// The part's closed surface with about `cells` lattice cells across its width (a coarser
    /// one for pictures; `--stock-out` takes [`mesh::STL_CELLS_ACROSS`]).
    pub fn surface(&self, cells: usize) -> Option<Surface> {
        mesh::surface(self, cells)
    }

    /// The coarsest node spacing of the stock's grids (mm): what it resolves.
    pub fn spacing(&self) -> f64 {
        let mut s = self.tolerance;
        if let Some(c) = &self.cyl {
            let r = c.col_max.iter().copied().fold(0.0, f64::max);
            s = s.max(c.dz).max(std::f64::consts::TAU * r / c.nth as f64);
        }
        for f in &self.faces {
            if f.nu > 0 {
                s = s.max(f.du).max(f.dv);
            }
        }
        s
    }

    /// Bytes the grids hold.
    pub fn bytes(&self) -> usize {
        self.cyl.as_ref().map_or(0, CylGrid::bytes) + self.faces.iter().map(FaceGrid::bytes).sum::<usize>()
    }
}

#[cfg(test)]
mod flat_tests;
#[cfg(test)]
mod tests;
