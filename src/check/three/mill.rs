//! Milling on the lathe: the milled stock (`grid`) on the 3D path.
//!
//! - **Hand-over.** The dexel stock is the model while the part is only turned. At the first feed
//!   of a live cutter with the spindle positioned (what was kept as a *plunge* before the milled stock), the grid
//!   stock is built from the dexel stock's columns as they are then (`grid::Stock::turned`: each
//!   column's innermost and outermost radius), and `stats.effects` says `grid_stock`.
//! - **Material** from then on is what both hold: the grid's (milled) and the dexel stock's
//!   (turned after the hand-over). The 2D path keeps the dexel stock alone: it holds at least the
//!   part's material, so the 2D checks stay on the safe side.
//! - **Cuts.** A live cutter whose geometry is a cylinder (its tip at its `z0` end, its axis its
//!   frame's z) feeding with the live tool turning and the spindle positioned sweeps the grid: the
//!   move in the part's frame (the main spindle turned by C), chords of C whose sagitta at the
//!   stock's outer radius is at most half a node spacing, ½° to 10° (or 1/64 of an out-of-plane
//!   arc), each chord with the cutter's axis at its start; C turning alone past a whole turn is cut
//!   for one turn (it sweeps nothing more after it). The sweep is applied
//!   after the move's pairs are checked: the move's other parts meet the stock as it was before it
//!   (never a missed crash; a holder that follows its own cutter into the hole it cuts in the same
//!   move would be judged against the uncut stock). Other cutters keep their plunge lines.
//! - **Queries.** A component against the stock: the dexel stock's query first (it holds all the
//!   material, so no overlap there is no overlap at all), then `collide3::grid_overlap` against
//!   the grid, points kept where the dexel stock also holds them. The gap for advancement stays
//!   the dexel stock's lower bound.

use nalgebra::Vector3;

use super::Three;
use crate::check::Checker;
use crate::collide3::{grid_clear, grid_overlap, grid_overlap_beyond, stock_overlap, Hit, Shape3};
use crate::geom::TOUCH_EPS;
use crate::grid::{CutRun, Cutter, CutterKind, CylGrid, Stock, Sweep};
use crate::interp::{ExtraMove, Move};
use crate::kin::{CompId, Geometry, Iso, Poser};
use crate::motion::Timed;
use crate::scene::{DexelStock, View};

/// The grid's node spacing never goes below this (mm): a finer `--tolerance` leaves the milled
/// stock here (the node budget of a bar).
pub const MIN_SPACING_MM: f64 = 0.05;

/// Lattice cells across the part in a 3D picture's mesh of the milled stock (`--stock-out`
/// takes `grid::STL_CELLS_ACROSS`).
pub const PICTURE_CELLS: usize = 80;

/// The milled stock of a check.
pub(in crate::check) struct Mill {
    pub stock: Stock,
}

impl Mill {
    /// Contacts with the milled stock up to this depth are touches: a milled wall stands up to a
    /// node spacing off the cutter's true surface, and meshes stand up to the tolerance proud.
    pub fn touch(&self) -> f64 {
        2.0 * self.stock.spacing()
    }

    /// The milled stock turned down to the dexel stock's columns (the turning after the
    /// hand-over): the part as both models hold it.
    fn turned_down(&self, d: &DexelStock) -> Stock {
        let mut s = self.stock.clone();
        if s.cyl.is_none() {
            // A block: the turning is the dexel stock's, each column's radii whatever the angle
            // (eight rays a column hold it).
            let (z0, z1) = d.extent();
            let nz = d.columns().max(1);
            s.cyl = Some(CylGrid::new(z0, (z1 - z0) / nz as f64, nz, 8, |z| {
                let m = d.material_at(z);
                Some((m.first()?.0, m.last()?.1))
            }));
            return s;
        }
        if let Some(c) = s.cyl.as_mut() {
            for j in 0..c.nz {
                let z = c.z(j);
                let m = d.material_at(z);
                let (ri, ro) = (m.first().map_or(0.0, |p| p.0), m.last().map_or(0.0, |p| p.1));
                c.turn(z - c.dz / 4.0, z + c.dz / 4.0, ro);
                c.inner[j] = c.inner[j].max(ri.min(c.col_max[j]));
            }
        }
        s
    }

    /// The final part as binary STL: the surface of what every grid holds (face pockets and
    /// holes included), turned down to the dexel stock.
    fn part_stl(&self, d: &DexelStock) -> Option<Vec<u8>> {
        self.turned_down(d).stl()
    }

    /// The part as it is now, for a 3D picture: the same surface on a coarser lattice
    /// ([`PICTURE_CELLS`] across), in the part's frame.
    pub(super) fn picture_mesh(&self, d: &DexelStock) -> Option<crate::kin::Mesh> {
        let surf = self.turned_down(d).surface(PICTURE_CELLS)?;
        Some(crate::kin::Mesh {
            vertices: surf.vertices.iter().map(|p| nalgebra::Point3::from(*p)).collect(),
            triangles: surf.triangles,
        })
    }

    /// The milled stock of a block (a job's `[stock] block`): the block itself in the part's
    /// frame (`width` along x, `height` along y at C0, centred on the spindle axis), built before
    /// the first move: no hand-over. Its six faces are `n × n` nodes, `n` the longest side over
    /// the spacing, at most what keeps the faces within half of `grid::MAX_NODES` (the rest for
    /// side grids). `None` for a stock that is no block.
    pub fn block(s: &crate::machine::Stock, tol: f64) -> Option<Mill> {
        let b = s.block?;
        let min = Vector3::new(-b.width / 2.0, -b.height / 2.0, s.front - s.length);
        let max = Vector3::new(b.width / 2.0, b.height / 2.0, s.front);
        let spacing = tol.max(MIN_SPACING_MM);
        let cap = ((crate::grid::MAX_NODES / 12) as f64).sqrt().floor() as usize;
        let longest = b.width.max(b.height).max(s.length);
        let n = ((longest / spacing).ceil() as usize).clamp(2, cap);
        let stock = Stock::block(min, max, n, spacing).ok()?;
        Some(Mill { stock })
    }

    /// The grid stock of the dexel stock as it is now.
    fn from_dexel(d: &DexelStock, tol: f64) -> Option<Mill> {
        let (z0, z1) = d.extent();
        let n = d.columns();
        let mut r_max = 0.0f64;
        for j in 0..n {
            let z = z0 + (j as f64 + 0.5) * d.column_width();
            if let Some(&(_, hi)) = d.material_at(z).last() {
                r_max = r_max.max(hi);
            }
        }
        if r_max <= 0.0 {
            return None;
        }
        let stock = Stock::turned(z0, z1, r_max, tol.max(MIN_SPACING_MM), |z| {
            let m = d.material_at(z);
            Some((m.first()?.0, m.last()?.1))
        })
        .ok()?;
        Some(Mill { stock })
    }
}

/// A component posed for the stock's queries: its shape, the shape the milled grid is queried
/// with (its primitive when it has one), where it is, and where the part is.
pub(super) struct Posed<'s> {
    pub sa: &'s Shape3,
    pub sg: &'s Shape3,
    pub pose: &'s Iso,
    pub part: Iso,
}

/// A component against the stock. With a milled grid: its quick proof of a clear box first (the
/// cheap answer inside a hole the cutter made), then the grid, its material cut down to the
/// dexel stock's (which turning after the hand-over cuts). Without: the dexel stock (always how
/// deep). `ask`: what the grid is asked.
pub(super) fn stock_hit(mill: Option<&Mill>, dexel: &mut DexelStock, c: &Posed<'_>, ask: Ask) -> Option<Hit> {
    let Some(m) = mill else {
        return stock_overlap(c.sa, c.pose, dexel, View::Now, TOUCH_EPS);
    };
    if grid_clear(c.sg, c.pose, &c.part, &m.stock, 0.0) {
        return None;
    }
    // The dexel stock holds all the material: a part that reaches into none of it on any
    // column's plane has no grid contact either (`collide3::dexel_clears_grid`).
    if crate::collide3::dexel_clears_grid(c.sa, c.pose, dexel, m.touch()) {
        return None;
    }
    let (sg, pose, part, grid, eps) = (c.sg, c.pose, &c.part, &m.stock, m.touch());
    match ask {
        Ask::Any => grid_overlap(sg, pose, part, grid, eps, Some(dexel), true),
        Ask::Deepest => grid_overlap(sg, pose, part, grid, eps, Some(dexel), false),
        Ask::DeepestBeyond(floor) => grid_overlap_beyond(sg, pose, part, grid, eps, Some(dexel), floor),
    }
}

/// What [`stock_hit`] asks of the milled stock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Ask {
    /// Whether there is a contact, not how deep it goes (the advancement's probes).
    Any,
    /// How deep the contact goes: its deepest point.
    Deepest,
    /// How deep, only where deeper than this many mm (a contact's later samples, whose depths
    /// only raise the deepest so far): the deepest point when it lies deeper (by more than
    /// `collide3::BEYOND_MM`), else any contact (a hit no deeper), else none
    /// (`collide3::grid_overlap_beyond`).
    DeepestBeyond(f64),
}

/// A lower bound of the distance from a component to the stock, looking no further than
/// `window` mm. With a milled grid: the largest of a few margins at which the component's box
/// holds no grid material, less a node spacing (`grid_clear`); when the box is clear only at
/// its own size, 0 (the caller steps by the touch depth). Without: the dexel stock's bound.
pub(super) fn stock_gap(mill: Option<&Mill>, dexel: &mut DexelStock, c: &Posed<'_>, window: f64) -> f64 {
    let Some(m) = mill else {
        return crate::collide3::stock_gap(c.sa, c.pose, dexel, View::Now, window);
    };
    let s = m.stock.spacing();
    let mut margin = window;
    while margin > 2.0 * s {
        if grid_clear(c.sg, c.pose, &c.part, &m.stock, margin) {
            return margin - s;
        }
        margin /= 4.0;
    }
    0.0
}

impl Three {
    /// The shape of component `a` for the milled stock's queries: its primitive when it is a
    /// cylinder or a box, else its mesh `sa` (also for the pieces added to the tree later).
    pub(super) fn grid_shape<'s>(&'s self, a: CompId, sa: &'s Shape3) -> &'s Shape3 {
        self.grid_shapes.get(a).and_then(Option::as_ref).unwrap_or(sa)
    }

    /// A poser that keeps `parts`, their ancestors and the part's frame posed
    /// ([`Poser::focused`]): what a probe of a few parts against each other or the stock reads.
    pub(super) fn poser_with_part(&self, parts: &[CompId]) -> Poser {
        let mut all = parts.to_vec();
        all.extend(self.main_spindle);
        Poser::focused(&self.kin, &all)
    }

    /// The part's frame: the pose of the component the C axis turns (identity without one).
    pub(super) fn part_pose(&self, poser: &Poser) -> Iso {
        self.main_spindle.map_or(Iso::identity(), |c| *poser.world(c))
    }

    /// Component `a` (shape `sa`) as `poser` poses it, for the stock's queries.
    pub(super) fn posed<'s>(&'s self, a: CompId, sa: &'s Shape3, poser: &'s Poser) -> Posed<'s> {
        Posed {
            sa,
            sg: self.grid_shape(a, sa),
            pose: poser.world(a),
            part: self.part_pose(poser),
        }
    }
}

impl Checker<'_> {
    /// The final part as binary STL: the milled stock when the program milled, else the dexel
    /// stock's section (or the raw stock's) revolved.
    pub(in crate::check) fn part_stl(&self) -> Option<Vec<u8>> {
        let tol = self.settings.tolerance_mm;
        if let (Some(m), Some(d)) = (&self.mill, &self.stock) {
            return m.part_stl(d);
        }
        let outlines = match (&self.stock, &self.machine.stock) {
            (Some(d), _) => d.outlines(tol),
            (None, Some(s)) => vec![s.section()],
            (None, None) => return None,
        };
        let mut mesh = crate::kin::Mesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        // A revolved outline's mesh circumscribes it within the tolerance (kin::shape).
        let tol = tol.max(0.01);
        for o in outlines {
            let pts: Vec<crate::geom::P2> = o.iter().map(|p| crate::geom::P2::new(p[0], p[1])).collect();
            let Ok(part) = crate::kin::shape::revolved(&pts, tol) else {
                continue;
            };
            let base = mesh.vertices.len() as u32;
            mesh.vertices.extend(part.vertices);
            mesh.triangles
                .extend(part.triangles.iter().map(|t| t.map(|i| i + base)));
        }
        if mesh.triangles.is_empty() {
            return None;
        }
        Some(crate::kin::stl::write_stl(&mesh, "latheguard part", false))
    }

    /// The milled stock's cutter of a cutter component, with the z range of its frame it spans
    /// (its point at the low end): a job's milling tool (`mill = { … }`, built by
    /// `kin::station` with its point at z = 0 and its flutes along +z), else a cutter geometry
    /// (`cylinder = { …, end = … }`: a ball, bull-nose or drill-point end) or a cylinder taken
    /// as a flat end mill, its point at `z0`. `None`: the component mills nothing (it keeps a plunge line).
    pub(super) fn grid_cutter(&self, three: &Three, cutter: CompId) -> Option<(Cutter, f64, f64)> {
        let c = &three.kin.components[cutter];
        if let Some(mt) = c.station.and_then(|s| self.machine.tool(s)).and_then(|t| t.mill) {
            let tool = Cutter::new(mt.grid_kind(), mt.diameter, mt.flute_length).ok()?;
            return Some((tool, 0.0, mt.flute_length));
        }
        let (kind, radius, z0, z1) = match c.geometry.as_ref()? {
            Geometry::Cylinder { radius, z0, z1 } => (CutterKind::Flat, *radius, *z0, *z1),
            Geometry::Cutter { end, radius, z0, z1 } => (*end, *radius, *z0, *z1),
            _ => return None,
        };
        let tool = Cutter::new(kind, 2.0 * radius, (z1 - z0).abs()).ok()?;
        Some((tool, z0, z1))
    }

    /// Sweep the grid with `cutter`'s move; false when the cutter is not a cylinder (the caller
    /// keeps a plunge line instead).
    pub(super) fn mill_cut(
        &mut self,
        three: &Three,
        cutter: CompId,
        m: &Move,
        e: Option<&ExtraMove>,
        item: &Timed,
    ) -> bool {
        let Some((tool, z0, z1)) = self.grid_cutter(three, cutter) else {
            return false;
        };
        let tol = self.settings.tolerance_mm;
        if !self.ensure_mill() {
            return false;
        }
        let mut c_turns = e.map_or(0.0, |e| (e.end[1] - e.start[1]).abs());
        // C alone turning past a whole turn sweeps in its first turn all it ever sweeps.
        let mut u_end = 1.0;
        if c_turns > 360.0 && e.is_some_and(|e| super::only_c_turns(m, e)) {
            u_end = 360.0 / c_turns;
            c_turns = 360.0;
        }
        // Chords of the turn: a chord strays inside the cutter's true arc by its sagitta, at
        // most half a node spacing at the stock's outer radius (within what the grid resolves;
        // outside the arc the chord removes less, never more).
        let Some(mill) = self.mill.as_ref() else { return false };
        let r_out = mill
            .stock
            .cyl
            .as_ref()
            .map_or(1.0, |c| c.col_max.iter().copied().fold(1.0, f64::max));
        let half = (mill.stock.spacing() / 2.0 / r_out).min(1.0);
        let step_deg = (2.0 * (1.0 - half).acos().to_degrees()).clamp(0.5, 10.0);
        let n = if e.is_some_and(|e| e.arc.is_some()) {
            64
        } else {
            ((c_turns / step_deg).ceil() as usize).clamp(1, 720)
        };
        let mut poser = three.poser_with_part(&[cutter]);
        let mut vals = Vec::new();
        let mut at = |u: f64| {
            three.values(m, e, item, u, &mut vals);
            poser.pose(&three.kin, &vals);
            let local = three.part_pose(&poser).inverse() * poser.world(cutter);
            let tip = (local * nalgebra::Point3::new(0.0, 0.0, z0.min(z1))).coords;
            let axis = local.rotation * Vector3::z() * if z1 >= z0 { 1.0 } else { -1.0 };
            (tip, axis)
        };
        let Some(mill) = self.mill.as_mut() else { return false };
        let (mut tip, mut axis) = at(0.0);
        let mut made = Vec::new();
        let mut run = CutRun::default();
        for k in 1..=n {
            let (t1, a1) = at(u_end * k as f64 / n as f64);
            if let Some(sw) = Sweep::new(&tool, axis, tip, t1, tol.max(MIN_SPACING_MM)) {
                mill.stock.cut_in_run(&sw, &mut run);
                if self.record_cuts {
                    made.push(sw);
                }
            }
            (tip, axis) = (t1, a1);
        }
        if !made.is_empty() {
            self.cuts.push((self.move_index, crate::check::Removed::Milled(made)));
        }
        true
    }

    /// The milled stock, built from the dexel stock as it is now the first time something mills:
    /// whether there is one.
    fn ensure_mill(&mut self) -> bool {
        if self.mill.is_none() {
            let tol = self.settings.tolerance_mm;
            let Some(d) = self.ensure_stock() else { return false };
            self.mill = Mill::from_dexel(d, tol);
        }
        self.mill.is_some()
    }

    /// Another path's milling (`Stream::share_cuts`): its sweeps taken off the milled stock,
    /// which is built from the dexel stock as it is now when this path has not milled yet.
    pub(in crate::check) fn mill_foreign(&mut self, sweeps: &[Sweep]) {
        if self.three.is_none() || !self.ensure_mill() {
            return;
        }
        if let Some(mill) = self.mill.as_mut() {
            let mut run = CutRun::default();
            for sw in sweeps {
                mill.stock.cut_in_run(sw, &mut run);
            }
        }
    }
}
