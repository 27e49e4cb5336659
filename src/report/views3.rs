//! A picture of a 3D finding: three orthographic views of the scene at first contact, as SVG.
//!
//! The views share one scale and are laid out as a third-angle drawing: the lathe's own view
//! (XZ: `z` to the right, `x` up, as the 2D pictures draw the working plane, looking along −Y)
//! in the middle row; the end view (XY, looking along the spindle from the tailstock side, −Z)
//! to its right, sharing its rows; the top view (YZ, looking down from +X) above it, sharing its
//! columns. Each view is labelled with its axes; the first contact point is ringed in all three;
//! the legend names the two components that collide.
//!
//! Parts are drawn as filled silhouettes with hidden surfaces removed: every triangle is
//! rasterised into a depth buffer of one cell per picture unit, and the region each part wins is
//! traced back into outlines (three shades per part, after the facing of its triangles, so that
//! a cylinder reads as round and a box as a box). So the size of the SVG is bounded by the size
//! of the picture, not by the meshes: a million-triangle part costs no more bytes than a box.
//! The work is bounded too: at most [`MAX_RASTER_WORK`] cell tests per view (the two colliding
//! parts first), and at most [`MAX_POINTS_PER_VIEW`] outline points per view (shades are
//! dropped first, then the smallest outlines); the picture says when either cap cut something.
//!
//! Output is a pure function of the snapshot (fixed one-decimal coordinates, no hash order).

use super::scene3::{Box3, Role3, Snapshot3};
use super::svg::{self, document, esc, mm, n, nice, INK, OVERLAP};
use super::FileReport;
use crate::finding::{Finding, Severity};
use nalgebra::{Point3, Vector3};
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write;

/// Picture width, as the 2D pictures.
const WIDTH: f64 = 1000.0;
const MARGIN: f64 = 16.0;
/// Room above the views for the caption.
const HEAD: f64 = 104.0;
/// Room between views, for their labels.
const GAP: f64 = 34.0;
/// Total height of the views (both rows and the gap).
const MAX_VIEWS_H: f64 = 840.0;
/// Cell tests (pixels inside triangles' boxes) spent on one view at most.
pub const MAX_RASTER_WORK: u64 = 60_000_000;
/// Outline points written for one view at most.
pub const MAX_POINTS_PER_VIEW: usize = 40_000;
/// Shades of a part's fill: dark, middle, light (factors of its colour).
const SHADES: [f64; 3] = [0.74, 0.88, 1.0];

/// Which of the three views.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// z right, x up, looking along −Y.
    Xz,
    /// −y right, x up, looking along −Z (from the tailstock side).
    Xy,
    /// z right, −y up (+y down), looking along −X (from above).
    Yz,
}

impl Kind {
    /// (right, up, toward the viewer) of a machine point: a right-handed frame in each view.
    fn frame(self, p: &Point3<f64>) -> Vector3<f64> {
        match self {
            Kind::Xz => Vector3::new(p.z, p.x, p.y),
            Kind::Xy => Vector3::new(-p.y, p.x, p.z),
            Kind::Yz => Vector3::new(p.z, -p.y, p.x),
        }
    }

    fn label(self) -> &'static str {
        match self {
            Kind::Xz => "XZ  the lathe's view, looking along −Y   (→ +Z, ↑ +X)",
            Kind::Xy => "XY  end view, from the tailstock side   (→ −Y, ↑ +X)",
            Kind::Yz => "YZ  top view, looking down from +X   (→ +Z, ↓ +Y)",
        }
    }

    fn id(self) -> &'static str {
        match self {
            Kind::Xz => "xz",
            Kind::Xy => "xy",
            Kind::Yz => "yz",
        }
    }
}

/// One view: the world range it shows (in its own right/up coordinates) and where it stands.
struct View {
    kind: Kind,
    /// World right coordinate at the left edge, world up coordinate at the top edge.
    r0: f64,
    u1: f64,
    scale: f64,
    left: f64,
    top: f64,
    w: f64,
    h: f64,
    /// The depths the view shows (the region's extent along its line of sight): parts are cut
    /// there, so that a part far in front of the region (a tailstock, the turret) hides nothing.
    depth: (f64, f64),
    /// For the detail panel: how many times the views' scale it draws at (`None`: one of the
    /// three views).
    zoom: Option<u32>,
}

impl View {
    /// Picture coordinates of a machine point, and its depth (larger is nearer).
    fn project(&self, p: &Point3<f64>) -> (f64, f64, f64) {
        let f = self.kind.frame(p);
        (
            self.left + (f.x - self.r0) * self.scale,
            self.top + (self.u1 - f.y) * self.scale,
            f.z,
        )
    }
}

/// The region the views show: the two colliding parts near the contact, and the contact.
fn region(s: &Snapshot3) -> Box3 {
    let parts: Vec<Box3> = [Role3::CollidingA, Role3::CollidingB]
        .iter()
        .filter_map(|r| s.part(*r).and_then(|p| p.bounds()))
        .collect();
    let contact = s.contact();
    let mut core = Box3::empty();
    if let Some(small) = parts.iter().min_by(|a, b| a.size().total_cmp(&b.size())) {
        core.union(small);
    }
    if let Some(c) = contact {
        core.add(c);
    }
    if core.is_empty() {
        // Nothing collides that can be drawn: the whole scene.
        core = s.bounds();
    } else {
        // The larger part only near the contact: a chuck is much larger than what matters.
        let reach = (0.75 * core.size()).max(20.0);
        let d = Vector3::new(reach, reach, reach);
        let window = Box3 {
            min: core.min - d,
            max: core.max + d,
        };
        for p in &parts {
            let c = p.clip(&window);
            if !c.is_empty() {
                core.union(&c);
            }
        }
    }
    if core.is_empty() {
        core.add(Point3::new(-10.0, -10.0, -10.0));
        core.add(Point3::new(10.0, 10.0, 10.0));
    }
    // No view thinner than a third of the largest side, and a margin of 8 %.
    let big = core.size().max(1.0);
    let pad = 0.08 * big;
    for i in 0..3 {
        let (lo, hi) = (core.min[i], core.max[i]);
        let want = (hi - lo).max(big / 3.0);
        let mid = 0.5 * (lo + hi);
        core.min[i] = mid - want / 2.0 - pad;
        core.max[i] = mid + want / 2.0 + pad;
    }
    core
}

/// The three views of a region, one scale, centred on the page.
fn layout(b: &Box3) -> [View; 3] {
    let (dx, dy, dz) = (b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z);
    let scale = ((WIDTH - 2.0 * MARGIN - GAP) / (dz + dy)).min((MAX_VIEWS_H - GAP) / (dx + dy));
    let used = (dz + dy) * scale + GAP;
    let left = ((WIDTH - used) / 2.0).max(MARGIN);
    let top = HEAD + 18.0;
    let top_view = View {
        kind: Kind::Yz,
        r0: b.min.z,
        u1: -b.min.y,
        scale,
        left,
        top,
        w: dz * scale,
        h: dy * scale,
        depth: (b.min.x, b.max.x),
        zoom: None,
    };
    let main_top = top + dy * scale + GAP;
    let main = View {
        kind: Kind::Xz,
        r0: b.min.z,
        u1: b.max.x,
        scale,
        left,
        top: main_top,
        w: dz * scale,
        h: dx * scale,
        depth: (b.min.y, b.max.y),
        zoom: None,
    };
    let end = View {
        kind: Kind::Xy,
        r0: -b.max.y,
        u1: b.max.x,
        scale,
        left: left + dz * scale + GAP,
        top: main_top,
        w: dy * scale,
        h: dx * scale,
        depth: (b.min.z, b.max.z),
        zoom: None,
    };
    [main, end, top_view]
}

/// The depth buffer of one view: for each cell, the nearest part and the shade of its triangle.
struct Raster {
    w: usize,
    h: usize,
    /// Depths outside this are not drawn.
    clip: (f64, f64),
    /// Depths closer than this are one depth.
    tie: f64,
    depth: Vec<f64>,
    /// Part index + 1; 0 where nothing is drawn.
    part: Vec<u32>,
    shade: Vec<u8>,
    /// Triangles left out past [`MAX_RASTER_WORK`].
    skipped: u64,
}

/// The light, in a view's (right, up, toward the viewer) frame: from the upper left, in front.
fn light() -> Vector3<f64> {
    Vector3::new(-0.35, 0.55, 0.76).normalize()
}

/// The depth buffer of the parts `only` accepts (by index in the snapshot and role).
fn rasterise(v: &View, s: &Snapshot3, only: impl Fn(usize, Role3) -> bool) -> Raster {
    let w = (v.w.ceil() as usize).clamp(1, 4096);
    let h = (v.h.ceil() as usize).clamp(1, 4096);
    let mut r = Raster {
        w,
        h,
        clip: v.depth,
        tie: 1e-7 * (v.depth.1 - v.depth.0).abs().max(1.0),
        depth: vec![f64::NEG_INFINITY; w * h],
        part: vec![0; w * h],
        shade: vec![0; w * h],
        skipped: 0,
    };
    let mut work: u64 = 0;
    // The colliding parts first, so that the work cap never leaves them out.
    let mut order: Vec<usize> = (0..s.parts.len()).collect();
    order.sort_by_key(|&i| (s.parts[i].role, i));
    let l = light();
    // Cut faces: a cell where a part's surface is crossed an odd number of times in front of the
    // near face of the view's box has that box face inside the part (a closed mesh): it is drawn
    // there as the part's cut, so a part cut open by the box shows as a solid section, not as
    // the nothing its edge-on sides would leave.
    let mut parity = vec![false; w * h];
    let mut marked = vec![false; w * h];
    let mut touched: Vec<usize> = Vec::new();
    for &pi in &order {
        let part = &s.parts[pi];
        if !only(pi, part.role) {
            continue;
        }
        let id = pi as u32 + 1;
        for t in part.world_triangles() {
            if work > MAX_RASTER_WORK {
                r.skipped += 1;
                continue;
            }
            let q = t.map(|p| {
                let (x, y, d) = v.project(&p);
                (x - v.left, y - v.top, d)
            });
            let area = (q[1].0 - q[0].0) * (q[2].1 - q[0].1) - (q[2].0 - q[0].0) * (q[1].1 - q[0].1);
            // Edge-on (or not a number): nothing to fill.
            if area.is_nan() || area.abs() <= 1e-12 {
                continue;
            }
            // Facing of the triangle toward the light (either side: meshes may be inside out).
            let f = t.map(|p| v.kind.frame(&p));
            let nrm = (f[1] - f[0]).cross(&(f[2] - f[0]));
            let lit = if nrm.norm() > 0.0 {
                (nrm.normalize().dot(&l)).abs()
            } else {
                1.0
            };
            let shade = if lit < 0.45 {
                0
            } else if lit < 0.8 {
                1
            } else {
                2
            };
            let (minx, maxx) = (q[0].0.min(q[1].0).min(q[2].0), q[0].0.max(q[1].0).max(q[2].0));
            let (miny, maxy) = (q[0].1.min(q[1].1).min(q[2].1), q[0].1.max(q[1].1).max(q[2].1));
            if maxx < 0.0 || maxy < 0.0 || minx > w as f64 || miny > h as f64 {
                continue;
            }
            let i0 = (minx - 0.5).floor().max(0.0) as usize;
            let i1 = ((maxx - 0.5).ceil().max(0.0) as usize).min(w - 1);
            let j0 = (miny - 0.5).floor().max(0.0) as usize;
            let j1 = ((maxy - 0.5).ceil().max(0.0) as usize).min(h - 1);
            work += ((i1 + 1).saturating_sub(i0) * (j1 + 1).saturating_sub(j0)) as u64;
            let mut covered = false;
            let inv = 1.0 / area;
            for j in j0..=j1 {
                let py = j as f64 + 0.5;
                for i in i0..=i1 {
                    let px = i as f64 + 0.5;
                    // Barycentric weights of the cell centre.
                    let w0 = ((q[1].0 - px) * (q[2].1 - py) - (q[2].0 - px) * (q[1].1 - py)) * inv;
                    let w1 = ((q[2].0 - px) * (q[0].1 - py) - (q[0].0 - px) * (q[2].1 - py)) * inv;
                    let w2 = 1.0 - w0 - w1;
                    if w0 < -1e-9 || w1 < -1e-9 || w2 < -1e-9 {
                        continue;
                    }
                    covered = true;
                    let d = w0 * q[0].2 + w1 * q[1].2 + w2 * q[2].2;
                    // A crossing in front of the near face; the weights' edge rule (one edge
                    // shared by two triangles counts once) keeps the parity right on seams.
                    if d > r.clip.1 && w0 > 0.0 && w1 >= 0.0 && w2 >= 0.0 || d > r.clip.1 && w0 == 0.0 && w1 > 0.0 {
                        let k = j * w + i;
                        if !marked[k] {
                            marked[k] = true;
                            touched.push(k);
                        }
                        parity[k] = !parity[k];
                    }
                    r.put(i, j, d, id, shade);
                }
            }
            if !covered {
                // A triangle thinner than a cell still shows: its centre's cell.
                let cx = (q[0].0 + q[1].0 + q[2].0) / 3.0;
                let cy = (q[0].1 + q[1].1 + q[2].1) / 3.0;
                if cx >= 0.0 && cy >= 0.0 && cx < w as f64 && cy < h as f64 {
                    let d = (q[0].2 + q[1].2 + q[2].2) / 3.0;
                    r.put(cx as usize, cy as usize, d, id, shade);
                }
            }
        }
        for k in touched.drain(..) {
            marked[k] = false;
            if std::mem::take(&mut parity[k]) {
                r.put(k % w, k / w, r.clip.1, id, 0);
            }
        }
    }
    r
}

impl Raster {
    fn put(&mut self, i: usize, j: usize, d: f64, id: u32, shade: u8) {
        let k = j * self.w + i;
        // A face flush with one drawn before (the holder's top on the turret's underside)
        // leaves it in front: the parts are drawn colliding ones first, and no rounding noise
        // decides which of two coplanar faces shows.
        if d > self.depth[k] + self.tie && d >= self.clip.0 && d <= self.clip.1 {
            self.depth[k] = d;
            self.part[k] = id;
            self.shade[k] = shade;
        }
    }
}

/// A directed edge between two corners of the cell lattice.
type Edge = ((i32, i32), (i32, i32));
/// Closed outlines in a view's cell units.
type Loops = Vec<Vec<(f64, f64)>>;
/// A part's index, its silhouette and its shade bands (shade, outlines).
type PartOutlines = (usize, Loops, Vec<(u8, Loops)>);

/// Closed outlines of the regions of equal key (0: no region), on the lattice of cell corners,
/// each region on the right of its outlines as the picture's y runs down (so holes wind the
/// other way: fill them with the nonzero rule). Keyed by region key, in scan order.
fn trace(w: usize, h: usize, key: impl Fn(usize, usize) -> u32) -> BTreeMap<u32, Vec<Vec<(i32, i32)>>> {
    let mut edges: BTreeMap<u32, Vec<Edge>> = BTreeMap::new();
    let at = |i: isize, j: isize| -> u32 {
        if i < 0 || j < 0 || i >= w as isize || j >= h as isize {
            0
        } else {
            key(i as usize, j as usize)
        }
    };
    for j in 0..h as isize {
        for i in 0..w as isize {
            let k = at(i, j);
            if k == 0 {
                continue;
            }
            let (x, y) = (i as i32, j as i32);
            let e = edges.entry(k).or_default();
            if at(i, j - 1) != k {
                e.push(((x, y), (x + 1, y)));
            }
            if at(i + 1, j) != k {
                e.push(((x + 1, y), (x + 1, y + 1)));
            }
            if at(i, j + 1) != k {
                e.push(((x + 1, y + 1), (x, y + 1)));
            }
            if at(i - 1, j) != k {
                e.push(((x, y + 1), (x, y)));
            }
        }
    }
    let mut out = BTreeMap::new();
    for (k, es) in edges {
        let mut from: HashMap<(i32, i32), Vec<usize>> = HashMap::new();
        for (n, e) in es.iter().enumerate() {
            from.entry(e.0).or_default().push(n);
        }
        let mut used = vec![false; es.len()];
        let mut loops = Vec::new();
        for s in 0..es.len() {
            if used[s] {
                continue;
            }
            let start = es[s].0;
            let mut pts = vec![start];
            let mut cur = s;
            loop {
                used[cur] = true;
                let end = es[cur].1;
                if end == start {
                    break;
                }
                pts.push(end);
                // Every corner has as many edges in as out, so an unused one always leaves
                // (the lowest index: deterministic).
                match from.get(&end).and_then(|v| v.iter().copied().find(|&x| !used[x])) {
                    Some(nx) => cur = nx,
                    None => break,
                }
            }
            loops.push(pts);
        }
        out.insert(k, loops);
    }
    out
}

/// A closed outline with the corners that matter: collinear points gone, then Douglas–Peucker
/// within `tol` (turns the staircases of slanted edges into straight lines).
fn simplify(pts: &[(i32, i32)], tol: f64) -> Vec<(f64, f64)> {
    let p: Vec<(f64, f64)> = pts.iter().map(|&(x, y)| (x as f64, y as f64)).collect();
    if p.len() < 4 {
        return p;
    }
    // Split at the point farthest from the first, and simplify both open halves.
    let far = (1..p.len())
        .max_by(|&a, &b| d2(p[0], p[a]).total_cmp(&d2(p[0], p[b])).then(b.cmp(&a)))
        .unwrap_or(0);
    let mut keep = vec![false; p.len() + 1];
    keep[0] = true;
    keep[far] = true;
    keep[p.len()] = true;
    let closed: Vec<(f64, f64)> = p.iter().copied().chain(std::iter::once(p[0])).collect();
    dp(&closed, 0, far, tol, &mut keep);
    dp(&closed, far, p.len(), tol, &mut keep);
    (0..p.len()).filter(|&i| keep[i]).map(|i| p[i]).collect()
}

fn d2(a: (f64, f64), b: (f64, f64)) -> f64 {
    (a.0 - b.0).powi(2) + (a.1 - b.1).powi(2)
}

fn dp(p: &[(f64, f64)], a: usize, b: usize, tol: f64, keep: &mut [bool]) {
    // An explicit stack: an outline may have a few hundred thousand corners.
    let mut stack = vec![(a, b)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let (pa, pb) = (p[a], p[b]);
        let (dx, dy) = (pb.0 - pa.0, pb.1 - pa.1);
        let len = (dx * dx + dy * dy).sqrt();
        let mut best = (0.0, a);
        for (i, q) in p.iter().enumerate().take(b).skip(a + 1) {
            let d = if len > 0.0 {
                ((q.0 - pa.0) * dy - (q.1 - pa.1) * dx).abs() / len
            } else {
                d2(*q, pa).sqrt()
            };
            if d > best.0 {
                best = (d, i);
            }
        }
        if best.0 > tol {
            keep[best.1] = true;
            stack.push((a, best.1));
            stack.push((best.1, b));
        }
    }
}

/// Outlines of one view, ready to write: per part, its silhouette and its shade bands.
struct Outlines {
    /// (part index, silhouette loops, [(shade, loops)]), in part order.
    parts: Vec<PartOutlines>,
    /// Shades dropped to keep within [`MAX_POINTS_PER_VIEW`].
    flat: bool,
    /// Outlines dropped past [`MAX_POINTS_PER_VIEW`].
    dropped: usize,
}

const TOL: f64 = 0.6;

fn outlines(r: &Raster) -> Outlines {
    let sil = trace(r.w, r.h, |i, j| r.part[j * r.w + i]);
    let count = |m: &BTreeMap<u32, Vec<Vec<(f64, f64)>>>| m.values().flatten().map(Vec::len).sum::<usize>();
    let simp = |m: BTreeMap<u32, Vec<Vec<(i32, i32)>>>| -> BTreeMap<u32, Vec<Vec<(f64, f64)>>> {
        m.into_iter()
            .map(|(k, ls)| {
                (
                    k,
                    ls.iter().map(|l| simplify(l, TOL)).filter(|l| l.len() >= 3).collect(),
                )
            })
            .collect()
    };
    let mut sil = simp(sil);
    let mut total = count(&sil);
    // Shade bands: every shade but the middle one, drawn over the silhouette's middle shade.
    let bands = simp(trace(r.w, r.h, |i, j| {
        let k = j * r.w + i;
        let s = r.shade[k] as u32;
        if r.part[k] == 0 || s == 1 {
            0
        } else {
            r.part[k] * 4 + s
        }
    }));
    let band_points = count(&bands);
    let flat = total + band_points > MAX_POINTS_PER_VIEW;
    let bands = if flat { BTreeMap::new() } else { bands };
    total += if flat { 0 } else { band_points };
    let mut dropped = 0;
    if total > MAX_POINTS_PER_VIEW {
        // Keep the largest outlines (by points), dropping the rest: the picture says so.
        let mut all: Vec<(usize, u32, usize)> = sil
            .iter()
            .flat_map(|(k, ls)| ls.iter().enumerate().map(move |(i, l)| (l.len(), *k, i)))
            .collect();
        all.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut budget = MAX_POINTS_PER_VIEW;
        let mut keep: std::collections::BTreeSet<(u32, usize)> = Default::default();
        for (len, k, i) in all {
            if len <= budget {
                budget -= len;
                keep.insert((k, i));
            } else {
                dropped += 1;
            }
        }
        for (k, ls) in sil.iter_mut() {
            let mut i = 0;
            ls.retain(|_| {
                let kept = keep.contains(&(*k, i));
                i += 1;
                kept
            });
        }
    }
    let mut parts = Vec::new();
    for (k, ls) in sil {
        let pi = k as usize - 1;
        let b: Vec<(u8, Loops)> = [0u8, 2]
            .iter()
            .filter_map(|&s| bands.get(&(k * 4 + s as u32)).map(|l| (s, l.clone())))
            .collect();
        parts.push((pi, ls, b));
    }
    Outlines { parts, flat, dropped }
}

/// A colour scaled toward black by `f`.
fn shade_of(hex: &str, f: f64) -> String {
    let c = |i: usize| u8::from_str_radix(hex.get(i..i + 2).unwrap_or("80"), 16).unwrap_or(128) as f64;
    let (r, g, b) = (c(1), c(3), c(5));
    format!(
        "#{:02x}{:02x}{:02x}",
        (r * f).round() as u8,
        (g * f).round() as u8,
        (b * f).round() as u8
    )
}

fn path_data(v: &View, loops: &[Vec<(f64, f64)>]) -> String {
    let mut d = String::new();
    for l in loops {
        for (i, p) in l.iter().enumerate() {
            d.push(if i == 0 { 'M' } else { 'L' });
            d.push_str(&n(v.left + p.0));
            d.push(',');
            d.push_str(&n(v.top + p.1));
        }
        d.push('Z');
    }
    d
}

/// What one view cut to stay within its caps.
#[derive(Default)]
struct Cuts {
    skipped: u64,
    flat: bool,
    dropped: usize,
    /// The parts drawn (in any view), for the legend.
    drawn: std::collections::BTreeSet<usize>,
    /// The parts cut away in some view because they hid the contact, by name.
    cut_away: std::collections::BTreeSet<String>,
}

/// Cells around the contact's (this many picture units each way) looked at for a part that hides it.
const CONTACT_CELLS: i64 = 3;

/// The parts that hide the contact in a view: a part neither colliding nor the stock that wins a
/// cell around the contact's and stands wholly nearer the viewer than the contact (a turret over
/// a drill in its hole, seen from above). The view leaves them out and draws their outline dashed, so what
/// happens at the contact (the tool, the hole it stands in) shows.
fn hiding(v: &View, s: &Snapshot3, r: &Raster) -> Vec<usize> {
    let Some(c) = s.contact() else { return Vec::new() };
    let (x, y, d) = v.project(&c);
    let (ci, cj) = ((x - v.left).floor() as i64, (y - v.top).floor() as i64);
    let mut out = Vec::new();
    for j in cj - CONTACT_CELLS..=cj + CONTACT_CELLS {
        for i in ci - CONTACT_CELLS..=ci + CONTACT_CELLS {
            if i < 0 || j < 0 || i >= r.w as i64 || j >= r.h as i64 {
                continue;
            }
            let k = j as usize * r.w + i as usize;
            let Some(pi) = (r.part[k] as usize).checked_sub(1) else {
                continue;
            };
            if r.depth[k] <= d + r.tie || out.contains(&pi) {
                continue;
            }
            let Some(p) = s.parts.get(pi) else { continue };
            if matches!(p.role, Role3::Moving | Role3::Fixed) && wholly_in_front(v, p, d) {
                out.push(pi);
            }
        }
    }
    out.sort_unstable();
    out
}

/// Whether all of `p` (its box) stands nearer the viewer than the depth `d`: a part the contact
/// is neither in nor behind.
fn wholly_in_front(v: &View, p: &super::scene3::Part3, d: f64) -> bool {
    let Some(b) = p.bounds() else { return false };
    (0..8).all(|c| {
        let q = Point3::new(
            if c & 1 == 0 { b.min.x } else { b.max.x },
            if c & 2 == 0 { b.min.y } else { b.max.y },
            if c & 4 == 0 { b.min.z } else { b.max.z },
        );
        v.kind.frame(&q).z > d
    })
}

/// One view: frame, parts, spindle axis, contact ring, label.
fn view(o: &mut String, v: &View, s: &Snapshot3) -> Cuts {
    let all = rasterise(v, s, |_, _| true);
    let away = hiding(v, s, &all);
    let (r, away_loops) = if away.is_empty() {
        (all, Vec::new())
    } else {
        let alone = rasterise(v, s, |pi, _| away.contains(&pi));
        let loops: Vec<Vec<(f64, f64)>> = trace(alone.w, alone.h, |i, j| alone.part[j * alone.w + i])
            .into_values()
            .flatten()
            .map(|l| simplify(&l, TOL))
            .filter(|l| l.len() >= 3)
            .collect();
        (rasterise(v, s, |pi, _| !away.contains(&pi)), loops)
    };
    let ol = outlines(&r);
    // The colliding parts alone, each whole: their edges hidden behind other parts are drawn
    // dashed, as hidden edges are on a drawing.
    let mut hidden = Vec::new();
    let mut skipped = r.skipped;
    for role in [Role3::CollidingA, Role3::CollidingB] {
        let Some(pi) = s.parts.iter().position(|p| p.role == role) else {
            continue;
        };
        let alone = rasterise(v, s, |_, r| r == role);
        skipped += alone.skipped;
        let loops = trace(alone.w, alone.h, |i, j| alone.part[j * alone.w + i]);
        let loops: Vec<Vec<(f64, f64)>> = loops
            .into_values()
            .flatten()
            .map(|l| simplify(&l, TOL))
            .filter(|l| l.len() >= 3)
            .collect();
        let points: usize = loops.iter().map(Vec::len).sum();
        if points <= MAX_POINTS_PER_VIEW / 4 {
            hidden.push((pi, loops));
        }
    }
    let id = if v.zoom.is_some() { "detail" } else { v.kind.id() };
    let _ = writeln!(
        o,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#fbfbfa" stroke="#d0d7de"/>"##,
        n(v.left),
        n(v.top),
        n(v.w),
        n(v.h)
    );
    // A view narrower than its whole title (about 7 px a character at 13 px) keeps the title's
    // name and leaves out its axis directions, so that it does not run into the next view's.
    let zoomed;
    let label = match v.zoom {
        Some(z) => {
            zoomed = format!("XZ  detail ×{z}");
            zoomed.as_str()
        }
        None => v.kind.label(),
    };
    let rest = if label.chars().count() as f64 * 7.0 > v.w {
        label[2..].split("   (").next().unwrap_or(&label[2..])
    } else {
        &label[2..]
    };
    let _ = writeln!(
        o,
        r##"<text x="{}" y="{}" font-size="13" fill="{INK}"><tspan font-weight="bold">{}</tspan>{}</text>"##,
        n(v.left),
        n(v.top - 8.0),
        &label[..2],
        esc(rest)
    );
    let _ = writeln!(o, r#"<g id="view-{id}" stroke-linejoin="round" fill-rule="nonzero">"#);
    for (pi, sil, bands) in &ol.parts {
        let Some(part) = s.parts.get(*pi) else { continue };
        let (fill, _) = part.role.colours();
        // The part's name as its tooltip (and for tests to find it).
        let _ = writeln!(o, r#"<g class="part"><title>{}</title>"#, esc(&part.name));
        let _ = writeln!(
            o,
            r#"<path d="{}" fill="{}" stroke="none"/>"#,
            path_data(v, sil),
            shade_of(fill, SHADES[1])
        );
        for (sh, ls) in bands {
            let c = shade_of(fill, SHADES[*sh as usize]);
            let _ = writeln!(
                o,
                r#"<path d="{}" fill="{c}" stroke="{c}" stroke-width="0.6"/>"#,
                path_data(v, ls)
            );
        }
        let _ = writeln!(o, "</g>");
    }
    // Outlines over every fill, so that a part in front keeps its edge.
    for (pi, sil, _) in &ol.parts {
        let Some(part) = s.parts.get(*pi) else { continue };
        let (_, line) = part.role.colours();
        let width = if matches!(part.role, Role3::CollidingA | Role3::CollidingB) {
            "1.6"
        } else {
            "1"
        };
        let _ = writeln!(
            o,
            r#"<path d="{}" fill="none" stroke="{line}" stroke-width="{width}"/>"#,
            path_data(v, sil)
        );
    }
    if !away_loops.is_empty() {
        let line = s.parts.get(away[0]).map_or(INK, |p| p.role.colours().1);
        let _ = writeln!(
            o,
            r#"<path class="cut-away" d="{}" fill="none" stroke="{line}" stroke-width="1" stroke-dasharray="2 3"/>"#,
            path_data(v, &away_loops)
        );
    }
    for (pi, loops) in &hidden {
        let (_, line) = s.parts[*pi].role.colours();
        let _ = writeln!(
            o,
            r#"<path class="hidden-edge" d="{}" fill="none" stroke="{line}" stroke-width="1.2" stroke-dasharray="5 3"/>"#,
            path_data(v, loops)
        );
    }
    let _ = writeln!(o, "</g>");
    ticks(o, v);
    spindle_axis(o, v);
    if let Some(c) = s.contact() {
        let (x, y, _) = v.project(&c);
        // The ring is clipped to its view's frame: the views' labels and the caption stand
        // outside the frames, so the ring is never drawn over their text.
        let _ = writeln!(
            o,
            r#"<clipPath id="frame-{id}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
            n(v.left),
            n(v.top),
            n(v.w),
            n(v.h)
        );
        let _ = writeln!(
            o,
            r##"<g class="contact" clip-path="url(#frame-{id})"><circle cx="{x}" cy="{y}" r="10" fill="none" stroke="#ffffff" stroke-width="5" opacity="0.85"/><circle cx="{x}" cy="{y}" r="10" fill="none" stroke="{OVERLAP}" stroke-width="2.2"/><path d="M{a},{y}L{b},{y}M{x},{c}L{x},{d}" stroke="{OVERLAP}" stroke-width="1.4"/></g>"##,
            x = n(x),
            y = n(y),
            a = n(x - 15.0),
            b = n(x + 15.0),
            c = n(y - 15.0),
            d = n(y + 15.0)
        );
    }
    Cuts {
        cut_away: away
            .iter()
            .filter_map(|&pi| s.parts.get(pi))
            .map(|p| p.name.clone())
            .collect(),
        drawn: ol.parts.iter().map(|p| p.0).collect(),
        skipped,
        flat: ol.flat,
        dropped: ol.dropped,
    }
}

/// Machine coordinates along the bottom and left edges of a view (`Z200`, `X-40`, `Y30`).
fn ticks(o: &mut String, v: &View) {
    let step = nice(90.0 / v.scale);
    // The horizontal coordinate: z, or −y in the end view.
    let (letter, sign) = match v.kind {
        Kind::Xz | Kind::Yz => ('Z', 1.0),
        Kind::Xy => ('Y', -1.0),
    };
    let r1 = v.r0 + v.w / v.scale;
    let mut k = (v.r0 / step).ceil();
    let bottom = v.top + v.h;
    while k * step <= r1 && k.abs() < 1e6 {
        let x = v.left + (k * step - v.r0) * v.scale;
        if x > v.left + 14.0 && x < v.left + v.w - 14.0 {
            svg::bottom_tick(o, x, bottom, &format!("{letter}{}", mm(sign * k * step)));
        }
        k += 1.0;
    }
    // The vertical coordinate: x, or −y in the top view.
    let (letter, sign) = match v.kind {
        Kind::Xz | Kind::Xy => ('X', 1.0),
        Kind::Yz => ('Y', -1.0),
    };
    let u0 = v.u1 - v.h / v.scale;
    let mut k = (u0 / step).ceil();
    while k * step <= v.u1 && k.abs() < 1e6 {
        let y = v.top + (v.u1 - k * step) * v.scale;
        if y > v.top + 10.0 && y < bottom - 16.0 {
            svg::left_tick(o, v.left, y, &format!("{letter}{}", mm(sign * k * step)));
        }
        k += 1.0;
    }
}

/// The spindle axis (x = y = 0): a dash-dot centre line in the side and top views, a centre
/// cross in the end view; only where it crosses the view.
fn spindle_axis(o: &mut String, v: &View) {
    let (x, y, _) = v.project(&Point3::origin());
    let dash = r##"stroke="#1f2328" stroke-width="0.9" stroke-dasharray="18 4 3 4""##;
    let inside_y = y > v.top && y < v.top + v.h;
    let inside_x = x > v.left && x < v.left + v.w;
    match v.kind {
        Kind::Xz | Kind::Yz if inside_y => {
            let _ = writeln!(
                o,
                r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" {dash}/>"#,
                n(v.left),
                n(v.left + v.w),
                y = n(y)
            );
        }
        Kind::Xy if inside_x && inside_y => {
            let _ = writeln!(
                o,
                r#"<path d="M{},{y}L{},{y}M{x},{}L{x},{}" fill="none" {dash}/>"#,
                n(v.left),
                n(v.left + v.w),
                n(v.top),
                n(v.top + v.h),
                x = n(x),
                y = n(y)
            );
        }
        _ => {}
    }
}

/// The caption's lines: heading (place and kind), message, block, facts.
struct Caption {
    place: String,
    kind: Option<(String, &'static str)>,
    message: String,
    block: Option<(u32, String)>,
    facts: Vec<String>,
}

fn caption(o: &mut String, c: &Caption) {
    let m = n(MARGIN);
    let kind = c.kind.as_ref().map_or(String::new(), |(k, colour)| {
        format!(r#"  <tspan fill="{colour}" font-weight="bold">{}</tspan>"#, esc(k))
    });
    let _ = writeln!(
        o,
        r#"<text x="{m}" y="24" font-size="16" fill="{INK}"><tspan font-weight="bold">{}</tspan>{kind}</text>"#,
        esc(&cut(&c.place, 100))
    );
    let _ = writeln!(
        o,
        r#"<text x="{m}" y="46" font-size="15" fill="{INK}">{}</text>"#,
        esc(&cut(&c.message, 115))
    );
    if let Some((line, b)) = &c.block {
        let _ = writeln!(
            o,
            r#"<text x="{m}" y="68" font-size="13" font-family="DejaVu Sans Mono, Menlo, Consolas, monospace" fill="{INK}" xml:space="preserve">{line:>5} | {}</text>"#,
            esc(&cut(b, 112))
        );
    }
    let _ = writeln!(
        o,
        r##"<text x="{m}" y="90" font-size="13" fill="#57606a">first contact: {}</text>"##,
        esc(&cut(&c.facts.join("  ·  "), 130))
    );
}

fn cut(s: &str, max: usize) -> String {
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// The caption's figures: time, contact point and, with `names`, the colliding pair (a
/// finding's message already names it).
fn facts(s: &Snapshot3, names: bool) -> Vec<String> {
    let mut f = Vec::new();
    if let Some(t) = s.time_s.filter(|t| t.is_finite()) {
        f.push(format!("t = {t:.3} s"));
    }
    if let Some(c) = s.contact() {
        f.push(format!(
            "contact x {} y {} z {} (machine frame)",
            mm(c.x),
            mm(c.y),
            mm(c.z)
        ));
    }
    let pair: Vec<&str> = [Role3::CollidingA, Role3::CollidingB]
        .iter()
        .filter_map(|r| s.part(*r).map(|p| p.name.as_str()))
        .collect();
    if names && !pair.is_empty() {
        f.push(pair.join(" × "));
    }
    f
}

/// The three views of a snapshot, drawn alone: the caption is the snapshot's own title, line
/// and time.
pub fn svg(s: &Snapshot3) -> String {
    draw(
        s,
        &Caption {
            place: format!("line {}", s.line),
            kind: None,
            message: s.title.clone(),
            block: None,
            facts: facts(s, true),
        },
        None,
    )
}

/// The three views of a finding of a report's file, with the caption of the 2D pictures (place,
/// kind, message, the block's text).
pub(super) fn picture(file: &FileReport, f: &Finding, s: &Snapshot3, block: &str) -> String {
    let colour = if f.severity == Severity::Error {
        OVERLAP
    } else {
        "#9a6700"
    };
    // The message and the legend name the two parts: the line keeps room for the figures.
    let mut facts = facts(s, false);
    let mut at = 1.min(facts.len());
    if let Some(d) = f.depth_mm {
        facts.insert(at, format!("depth {} mm", mm(d)));
        at += 1;
    }
    // Where the program was, as the text report and the 2D pictures say it (X on diameter where
    // the program writes diameters); the contact point stays in the machine frame of the views.
    if let (Some(x), Some(z)) = (f.x, f.z) {
        facts.insert(at, format!("programmed point X{} Z{}", mm(x), mm(z)));
    }
    draw(
        s,
        &Caption {
            place: format!("{}:{}", file.path, f.line),
            kind: Some((format!("{}[{}]", f.severity.name(), f.kind), colour)),
            // A follow-on says whose crash it comes from, as the 2D pictures do.
            message: match f.follow_on_note() {
                Some(p) => format!("{} — {p}", f.message),
                None => f.message.clone(),
            },
            block: (!block.is_empty()).then(|| (f.line, block.to_string())),
            facts,
        },
        f.depth_mm,
    )
}

fn draw(s: &Snapshot3, c: &Caption, depth: Option<f64>) -> String {
    let region = region(s);
    let views = layout(&region);
    let mut o = String::new();
    let _ = writeln!(o, "<title>line {}: {}</title>", s.line, esc(&s.title));
    let _ = writeln!(o, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    caption(&mut o, c);
    let mut cuts = Cuts::default();
    for v in &views {
        let k = view(&mut o, v, s);
        cuts.skipped += k.skipped;
        cuts.flat |= k.flat;
        cuts.dropped += k.dropped;
        cuts.drawn.extend(k.drawn);
        cuts.cut_away.extend(k.cut_away);
    }
    if let Some(d) = detail(&views, s, depth) {
        // Where the detail is, in the lathe's view.
        let m = &views[0];
        let (x0, y0, _) = m.project(&Point3::new(d.u1, 0.0, d.r0));
        let _ = writeln!(
            o,
            r#"<rect class="detail-region" x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{INK}" stroke-width="1" stroke-dasharray="3 2"/>"#,
            n(x0),
            n(y0),
            n((d.w / d.scale * m.scale).max(2.0)),
            n((d.h / d.scale * m.scale).max(2.0))
        );
        let k = view(&mut o, &d, s);
        cuts.skipped += k.skipped;
        detail_scale(&mut o, &d);
    }
    let bottom = views.iter().map(|v| v.top + v.h).fold(0.0, f64::max);
    let bottom = footer(&mut o, &views[0], s, &cuts, bottom);
    document(&o, bottom)
}

/// How many pixels of the views' scale a contact's depth may span and still get a detail panel:
/// below this, the overlap is a sliver at the page's scale.
pub const DETAIL_BELOW_PX: f64 = 4.0;

/// The detail panel of a contact whose depth is a sliver at the views' scale: the lathe's view
/// (XZ) around the contact, magnified, in the corner of the page the third-angle layout leaves
/// empty (right of the top view, above the end view), so that it covers no view. `None` when
/// the depth is unknown or large enough to see.
fn detail(views: &[View; 3], s: &Snapshot3, depth: Option<f64>) -> Option<View> {
    let depth = depth.filter(|d| d.is_finite() && *d >= 0.0)?;
    let c = s.contact()?;
    let (main, end, top) = (&views[0], &views[1], &views[2]);
    if depth * main.scale >= DETAIL_BELOW_PX {
        return None;
    }
    let side = end.w.min(top.h) - 8.0;
    if side < 60.0 {
        return None;
    }
    // The region: about 12 depths across, at least 0.5 mm, and magnified 3 times at least.
    let across = (12.0 * depth).max(0.5).min(side / (3.0 * main.scale));
    let scale = side / across;
    let zoom = (scale / main.scale).round() as u32;
    let f = Kind::Xz.frame(&c);
    Some(View {
        kind: Kind::Xz,
        r0: f.x - across / 2.0,
        u1: f.y + across / 2.0,
        scale,
        left: end.left,
        top: top.top,
        w: side,
        h: side,
        depth: main.depth,
        zoom: Some(zoom),
    })
}

/// A scale bar in the detail panel's upper right corner, clear of its ticks (left and bottom
/// edges): its scale stated in mm.
fn detail_scale(o: &mut String, v: &View) {
    let len = nice(0.3 * v.w / v.scale);
    let px = len * v.scale;
    let (x1, y) = (v.left + v.w - 12.0, v.top + 24.0);
    let x0 = x1 - px;
    let _ = writeln!(
        o,
        r##"<g class="detail-scale"><path d="M{a},{b}L{a},{c}L{d},{c}L{d},{b}" fill="none" stroke="{INK}" stroke-width="1.5"/><text x="{e}" y="{f}" font-size="11" fill="{INK}" text-anchor="middle" stroke="#ffffff" stroke-width="3" paint-order="stroke">{g} mm</text></g>"##,
        a = n(x0),
        b = n(y - 5.0),
        c = n(y),
        d = n(x1),
        e = n((x0 + x1) / 2.0),
        f = n(y - 8.0),
        g = mm(len)
    );
}

/// Scale bar, legend and notes; returns the bottom of what it drew.
fn footer(o: &mut String, v: &View, s: &Snapshot3, cuts: &Cuts, below: f64) -> f64 {
    let y = below + 26.0;
    let left = MARGIN;
    let len = nice(160.0 / v.scale);
    let px = len * v.scale;
    let _ = writeln!(
        o,
        r#"<path d="M{a},{b}L{a},{c}L{d},{c}L{d},{b}" fill="none" stroke="{INK}" stroke-width="1.5"/><text x="{e}" y="{f}" font-size="12" fill="{INK}" text-anchor="middle">{g} mm</text>"#,
        a = n(left),
        b = n(y - 6.0),
        c = n(y),
        d = n(left + px),
        e = n(left + px / 2.0),
        f = n(y + 15.0),
        g = mm(len)
    );
    // Legend: the two components by name, then the other roles present, then the contact.
    let mut items: Vec<(String, &str, &str, bool)> = Vec::new();
    for role in Role3::ALL {
        let named = matches!(role, Role3::CollidingA | Role3::CollidingB);
        let (fill, line) = role.colours();
        if named {
            if let Some(p) = s.part(role) {
                items.push((p.name.clone(), fill, line, true));
            }
        } else if cuts
            .drawn
            .iter()
            .any(|&i| s.parts.get(i).is_some_and(|p| p.role == role))
        {
            let label = if role == Role3::Stock {
                "stock at that moment"
            } else {
                role.name()
            };
            items.push((label.to_string(), fill, line, false));
        }
    }
    let x_start = left + px.max(60.0) + 28.0;
    let x_end = WIDTH - MARGIN;
    let (mut lx, mut ly) = (x_start, y - 6.0);
    let mut place = |w: f64| -> (f64, f64) {
        if lx + w > x_end + 10.0 && lx > x_start {
            lx = x_start;
            ly += 20.0;
        }
        let at = (lx, ly);
        lx += w;
        at
    };
    let _ = writeln!(o, r#"<g class="legend">"#);
    for (label, fill, line, bold) in &items {
        let w = 21.0 + 7.2 * label.chars().count() as f64 + 16.0;
        let (x, yy) = place(w);
        let weight = if *bold { r#" font-weight="bold""# } else { "" };
        let _ = writeln!(
            o,
            r#"<rect x="{}" y="{}" width="16" height="11" fill="{fill}" stroke="{line}"/><text x="{}" y="{}" font-size="12" fill="{INK}"{weight}>{}</text>"#,
            n(x),
            n(yy - 10.0),
            n(x + 21.0),
            n(yy),
            esc(label)
        );
    }
    if s.contact().is_some() {
        let (x, yy) = place(21.0 + 7.2 * 13.0 + 16.0);
        let _ = writeln!(
            o,
            r#"<circle cx="{}" cy="{}" r="6" fill="none" stroke="{OVERLAP}" stroke-width="2"/><text x="{}" y="{}" font-size="12" fill="{INK}">first contact</text>"#,
            n(x + 8.0),
            n(yy - 4.5),
            n(x + 21.0),
            n(yy)
        );
    }
    let _ = writeln!(o, "</g>");
    let mut note_y = (y + 38.0).max(ly + 26.0);
    let mut notes = vec![
        "Orthographic views at first contact, one scale, machine frame in mm (z along the spindle, 0 at the jaw faces; x toward the turret).".to_string(),
        "Third-angle layout: the top view above the lathe's view, the end view to its right. The views show the box around the contact;".to_string(),
        "parts are cut at its faces. Dashed: edges of the colliding parts hidden behind other parts.".to_string(),
    ];
    if !cuts.cut_away.is_empty() {
        let names: Vec<&str> = cuts.cut_away.iter().map(String::as_str).collect();
        notes.push(format!(
            "Cut away where it hid the contact (dotted outline): {}.",
            cut(&names.join(", "), 120)
        ));
    }
    if cuts.skipped > 0 {
        notes.push(format!(
            "{} triangle{} left out of the views (at most {} cell tests a view; the colliding parts come first).",
            cuts.skipped,
            if cuts.skipped == 1 { "" } else { "s" },
            MAX_RASTER_WORK
        ));
    }
    if cuts.flat || cuts.dropped > 0 {
        notes.push(format!(
            "Outlines simplified to at most {MAX_POINTS_PER_VIEW} points a view{}.",
            if cuts.dropped > 0 {
                format!(
                    " ({} small outline{} left out)",
                    cuts.dropped,
                    if cuts.dropped == 1 { "" } else { "s" }
                )
            } else {
                " (shading left out)".to_string()
            }
        ));
    }
    for (i, t) in notes.iter().enumerate() {
        if i > 0 {
            note_y += 16.0;
        }
        let _ = writeln!(
            o,
            r##"<text x="{}" y="{}" font-size="11" fill="#57606a">{}</text>"##,
            n(left),
            n(note_y),
            esc(t)
        );
    }
    note_y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_traces_to_one_loop_of_four_corners() {
        let m = trace(4, 4, |i, j| u32::from((1..3).contains(&i) && (1..3).contains(&j)));
        let loops = &m[&1];
        assert_eq!(loops.len(), 1);
        let s = simplify(&loops[0], 0.6);
        assert_eq!(s.len(), 4, "{s:?}");
    }

    #[test]
    fn a_ring_traces_to_an_outer_loop_and_a_hole_wound_the_other_way() {
        let m = trace(5, 5, |i, j| u32::from(!(i == 2 && j == 2)));
        let loops = &m[&1];
        assert_eq!(loops.len(), 2);
        let area = |l: &Vec<(i32, i32)>| -> i64 {
            (0..l.len())
                .map(|k| {
                    let (a, b) = (l[k], l[(k + 1) % l.len()]);
                    a.0 as i64 * b.1 as i64 - b.0 as i64 * a.1 as i64
                })
                .sum()
        };
        assert_eq!(area(&loops[0]).signum(), -area(&loops[1]).signum());
        assert_eq!(area(&loops[0]).abs() + area(&loops[1]).abs(), 2 * (25 + 1));
    }

    #[test]
    fn shades_scale_a_colour_toward_black() {
        assert_eq!(shade_of("#ff8000", 0.5), "#804000");
        assert_eq!(shade_of("#123456", 1.0), "#123456");
    }

    #[test]
    fn the_three_view_frames_are_right_handed() {
        let (x, y, z) = (
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        );
        for k in [Kind::Xz, Kind::Xy, Kind::Yz] {
            let (a, b, c) = (k.frame(&x), k.frame(&y), k.frame(&z));
            // The machine frame's handedness is kept: det of the mapping is +1.
            let det = nalgebra::Matrix3::from_columns(&[a, b, c]).determinant();
            assert_eq!(det, 1.0, "{k:?}");
        }
    }
}
