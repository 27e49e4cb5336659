//! A picture of each finding: the working plane at first contact, as SVG.
//!
//! The drawing follows the lathe drawing habits of a machinist: `z` runs left to right (chuck on
//! the left, `+z` toward the tailstock), `x` upward, the spindle axis is a dash-dot centre line,
//! and revolved bodies (chuck, tailstock, stock) are drawn on both sides of it. The turret and
//! the active tool stand in the working plane above the axis; tools of the other stations are
//! drawn dashed where they cut the radial section (at their distance from the axis). The overlap
//! of the two parts that collide is filled solid red (orange for a follow-on of an earlier
//! crash): one part clipped by the other, ringed so that a sliver is found at a glance. A dogleg
//! rapid is drawn twice: the programmed line and the path the machine drives (each axis at its
//! own rate). An overtravel shows the broken travel limit of the turret reference point, its
//! path and the overshoot. Ticks along the plot's edges are program coordinates (X as written)
//! with the program zero Z0 marked. A small contact gets a detail panel below the main view (it
//! never covers it). A caption gives file, line, block text, time and depth; a scale bar and a
//! legend finish it.
//!
//! Output is a pure function of the finding: coordinates are written with one decimal in
//! picture units, so two runs give identical files.

use super::{FileReport, Report};
use crate::finding::{Finding, Severity};
use crate::geom::P2;
use crate::scene::Snapshot;
use crate::source::LineIndex;
use std::fmt::Write;

/// Picture width, in SVG user units (px).
const WIDTH: f64 = 1000.0;
/// Height of the plot area is kept within these.
const MIN_PLOT_H: f64 = 420.0;
const MAX_PLOT_H: f64 = 760.0;
/// Room above the plot for the caption, and below it for the legend and scale.
const HEAD: f64 = 104.0;
const MARGIN: f64 = 16.0;

pub(super) const INK: &str = "#1f2328";
pub(super) const CHUCK_FILL: &str = "#8c96a0";
pub(super) const CHUCK_LINE: &str = "#3d444d";
pub(super) const STOCK_FILL: &str = "#b7c9dd";
pub(super) const STOCK_LINE: &str = "#5a7896";
pub(super) const TURRET_FILL: &str = "#e6e1d6";
pub(super) const TURRET_LINE: &str = "#857b67";
pub(super) const HOLDER_FILL: &str = "#f2b766";
pub(super) const HOLDER_LINE: &str = "#8a5a14";
pub(super) const INSERT_FILL: &str = "#d9c53f";
pub(super) const INSERT_LINE: &str = "#6b5d00";
pub(super) const OTHER_LINE: &str = "#7a5ea8";
pub(super) const PATH_LINE: &str = "#1f6feb";
pub(super) const OVERLAP: &str = "#e5151b";
/// A follow-on contact's overlap: it exists because of an earlier crash.
pub(super) const FOLLOW_ON: &str = "#f08c00";
/// The programmed point as the machine drives it (a dogleg rapid).
pub(super) const MACHINE_LINE: &str = "#8250df";
/// A travel limit and the turret reference point beyond it.
pub(super) const LIMIT_LINE: &str = "#cf222e";
/// Size of the detail panel drawn below the main view.
const DETAIL_W: f64 = 460.0;
const DETAIL_H: f64 = 280.0;

/// Every picture of a batch: `(file name, SVG)`, in report order. File names are made from the
/// program's path, the line, the kind and the parts, and are unique within the batch.
pub fn pictures(r: &Report) -> Vec<Picture> {
    let mut out = Vec::new();
    let mut used = std::collections::HashSet::new();
    for (fi, f) in r.files.iter().enumerate() {
        // One line index per file (not per picture: a big file with many pictures).
        let mut lines = None;
        for (xi, x) in f.findings.iter().enumerate() {
            // A finding of the 3D path is drawn as three views (`views3`), the others as the
            // working plane.
            if x.snapshot.is_none() && x.snapshot3.is_none() {
                continue;
            }
            let li = lines.get_or_insert_with(|| LineIndex::new(&f.source));
            let base = name(&f.path, x);
            let mut file = format!("{base}.svg");
            let mut k = 2;
            while !used.insert(file.clone()) {
                file = format!("{base}.{k}.svg");
                k += 1;
            }
            let block = block_text(f, li, x.line);
            let svg = match (x.snapshot3.as_deref(), x.snapshot.as_deref()) {
                (Some(s3), _) => super::views3::picture(f, x, s3, &block),
                (None, Some(snap)) => picture(f, x, snap, &block),
                (None, None) => continue,
            };
            out.push(Picture {
                file: fi,
                finding: xi,
                svg,
                name: file,
            });
        }
    }
    out
}

/// One picture: which file and finding of the report it shows, its file name, its SVG text.
pub struct Picture {
    pub file: usize,
    pub finding: usize,
    pub name: String,
    pub svg: String,
}

/// `programs__crash.nc.L10.collision.T01-holder.chuck`: safe on every file system.
pub(super) fn name(path: &str, f: &Finding) -> String {
    let parts: Vec<String> = path
        .split(['/', '\\'])
        .filter(|c| !c.is_empty() && *c != ".")
        .map(|c| if c == ".." { "up".to_string() } else { slug(c) })
        .collect();
    let mut s = parts.join("__");
    let _ = write!(s, ".L{}.{}", f.line, f.kind);
    for o in &f.objects {
        s.push('.');
        s.push_str(&slug(o));
    }
    s
}

fn slug(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '+') {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// One decimal, never `-0.0`.
pub(super) fn n(v: f64) -> String {
    let s = format!("{v:.1}");
    if s == "-0.0" {
        "0.0".into()
    } else {
        s
    }
}

/// A length in mm for people: up to three decimals, no trailing zeros.
pub(super) fn mm(v: f64) -> String {
    super::text::fmt_num(v)
}

pub(super) fn esc(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c if (c as u32) < 0x20 => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// World (spindle frame: `x` radius up, `y` = z right) to picture units.
pub(super) struct View {
    pub zmin: f64,
    pub xmax: f64,
    pub scale: f64,
    pub left: f64,
    pub top: f64,
    pub w: f64,
    pub h: f64,
}

impl View {
    pub(super) fn fit(bx: &Bounds) -> View {
        let plot_w = WIDTH - 2.0 * MARGIN;
        let (mut zmin, mut zmax, mut xmin, mut xmax) = (bx.zmin, bx.zmax, bx.xmin, bx.xmax);
        // A margin of 8 % around the region of interest.
        let pad = 0.08 * (zmax - zmin).max(xmax - xmin).max(1.0);
        zmin -= pad;
        zmax += pad;
        xmin -= pad;
        xmax += pad;
        let mut scale = plot_w / (zmax - zmin);
        let mut h = (xmax - xmin) * scale;
        if h > MAX_PLOT_H {
            // Tall region: fit the height, widen the z range around its middle.
            scale = MAX_PLOT_H / (xmax - xmin);
            let extra = plot_w / scale - (zmax - zmin);
            zmin -= extra / 2.0;
            h = MAX_PLOT_H;
        } else if h < MIN_PLOT_H {
            let extra = MIN_PLOT_H / scale - (xmax - xmin);
            xmax += extra / 2.0;
            h = MIN_PLOT_H;
        }
        View {
            zmin,
            xmax,
            scale,
            left: MARGIN,
            top: HEAD,
            w: plot_w,
            h,
        }
    }

    pub(super) fn sx(&self, z: f64) -> f64 {
        self.left + (z - self.zmin) * self.scale
    }

    pub(super) fn sy(&self, x: f64) -> f64 {
        self.top + (self.xmax - x) * self.scale
    }

    fn pt(&self, p: P2) -> String {
        format!("{},{}", n(self.sx(p.y)), n(self.sy(p.x)))
    }

    /// Closed outlines as path data; `mirror` adds each one reflected about the axis.
    fn path(&self, polys: &[&[P2]], mirror: bool) -> String {
        let mut d = String::new();
        for poly in polys {
            for flip in [false, true] {
                if flip && !mirror {
                    continue;
                }
                for (i, p) in poly.iter().enumerate() {
                    let q = if flip { P2::new(-p.x, p.y) } else { *p };
                    d.push(if i == 0 { 'M' } else { 'L' });
                    d.push_str(&self.pt(q));
                }
                if !poly.is_empty() {
                    d.push('Z');
                }
            }
        }
        d
    }

    /// World coordinates of the plot area's corners.
    fn world(&self) -> Bounds {
        Bounds {
            zmin: self.zmin,
            zmax: self.zmin + self.w / self.scale,
            xmin: self.xmax - self.h / self.scale,
            xmax: self.xmax,
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Bounds {
    pub zmin: f64,
    pub zmax: f64,
    pub xmin: f64,
    pub xmax: f64,
}

impl Bounds {
    pub(super) fn empty() -> Bounds {
        Bounds {
            zmin: f64::INFINITY,
            zmax: f64::NEG_INFINITY,
            xmin: f64::INFINITY,
            xmax: f64::NEG_INFINITY,
        }
    }

    pub(super) fn add(&mut self, p: P2) {
        if p.x.is_finite() && p.y.is_finite() {
            self.zmin = self.zmin.min(p.y);
            self.zmax = self.zmax.max(p.y);
            self.xmin = self.xmin.min(p.x);
            self.xmax = self.xmax.max(p.x);
        }
    }

    pub(super) fn add_all(&mut self, pts: &[P2], mirror: bool) {
        for p in pts {
            self.add(*p);
            if mirror {
                self.add(P2::new(-p.x, p.y));
            }
        }
    }

    fn is_empty(&self) -> bool {
        self.zmin > self.zmax
    }

    fn clip(&self, o: &Bounds) -> Bounds {
        Bounds {
            zmin: self.zmin.max(o.zmin),
            zmax: self.zmax.min(o.zmax),
            xmin: self.xmin.max(o.xmin),
            xmax: self.xmax.min(o.xmax),
        }
    }
}

fn bounds_of(pts: &[P2]) -> Bounds {
    let mut b = Bounds::empty();
    b.add_all(pts, false);
    b
}

/// The region a picture shows: the parts in contact, the active tool, the path around the
/// moment, the stock on both sides of the axis, the obstacle near the contact, and the axis.
fn region(s: &Snapshot) -> Bounds {
    let mut b = Bounds::empty();
    b.add_all(&s.part_a, false);
    b.add_all(&s.insert, false);
    b.add_all(&s.holder, false);
    // The path near the contact only: the move before may come from far away.
    let tool = {
        let mut t = bounds_of(&s.holder);
        t.add_all(&s.insert, false);
        t.add_all(&s.part_a, false);
        t
    };
    let near_r = if tool.is_empty() {
        60.0
    } else {
        (1.5 * (tool.zmax - tool.zmin).max(tool.xmax - tool.xmin)).max(60.0)
    };
    for p in &s.path {
        if (p - s.at).norm() <= near_r {
            b.add(*p);
        }
    }
    for p in &s.machine_path {
        if (p - s.at).norm() <= near_r {
            b.add(*p);
        }
    }
    if let Some(t) = &s.travel {
        b.add(t.worst);
        b.add(if t.axis == 'Z' {
            P2::new(t.worst.x, t.limit)
        } else {
            P2::new(t.limit, t.worst.y)
        });
    }
    b.add(s.at);
    for st in &s.stock {
        b.add_all(st, true);
    }
    // The obstacle only near the contact: a chuck is much larger than what matters.
    let mut near = bounds_of(&s.part_a);
    near.add(s.at);
    let reach = 0.5 * (near.zmax - near.zmin).max(near.xmax - near.xmin).max(20.0);
    let window = Bounds {
        zmin: near.zmin - reach,
        zmax: near.zmax + reach,
        xmin: near.xmin - reach,
        xmax: near.xmax + reach,
    };
    for pb in &s.part_b {
        let c = bounds_of(pb).clip(&window);
        if c.zmin <= c.zmax && c.xmin <= c.xmax {
            b.add(P2::new(c.xmin, c.zmin));
            b.add(P2::new(c.xmax, c.zmax));
        }
    }
    if b.is_empty() {
        b.add(P2::new(0.0, 0.0));
        b.add(P2::new(10.0, 10.0));
    }
    // Always the spindle axis.
    b.add(P2::new(0.0, b.zmin));
    b
}

/// The white halo that keeps a label readable over drawn parts.
pub(super) const HALO: &str = r##"stroke="#ffffff" stroke-width="3" paint-order="stroke""##;

/// A coordinate tick on a view's bottom edge at `x`, with its label (`Z200`).
pub(super) fn bottom_tick(o: &mut String, x: f64, bottom: f64, label: &str) {
    let _ = writeln!(
        o,
        r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#57606a" stroke-width="1"/><text x="{x}" y="{}" font-size="10" fill="#57606a" text-anchor="middle" {HALO}>{label}</text>"##,
        n(bottom),
        n(bottom - 6.0),
        n(bottom - 9.0),
        x = n(x)
    );
}

/// A coordinate tick on a view's left edge at `y`, with its label (`X40`).
pub(super) fn left_tick(o: &mut String, left: f64, y: f64, label: &str) {
    let _ = writeln!(
        o,
        r##"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="#57606a" stroke-width="1"/><text x="{}" y="{}" font-size="10" fill="#57606a" {HALO}>{label}</text>"##,
        n(left),
        n(left + 6.0),
        n(left + 8.0),
        n(y + 3.5),
        y = n(y)
    );
}

/// 1, 2 or 5 times a power of ten, near `target`.
pub(super) fn nice(target: f64) -> f64 {
    let p = 10f64.powf(target.max(1e-6).log10().floor());
    for m in [1.0, 2.0, 5.0] {
        if m * p >= target * 0.75 {
            return m * p;
        }
    }
    10.0 * p
}

/// The block's source text, for the caption.
fn block_text(f: &FileReport, li: &LineIndex, line: u32) -> String {
    if f.source.is_empty() || line == 0 {
        return String::new();
    }
    if line as usize > li.line_count() {
        return String::new();
    }
    String::from_utf8_lossy(&f.source[li.line_span(&f.source, line).range()])
        .trim()
        .to_string()
}

/// At most `max` characters, with an ellipsis at the end where cut.
fn fit_text(s: &str, max: usize) -> String {
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let mut t: String = s.chars().take(max.saturating_sub(1)).collect();
        t.push('…');
        t
    }
}

/// At most `max` characters, cut in the middle (for paths).
fn fit_middle(s: &str, max: usize) -> String {
    let n = s.chars().count();
    if n <= max {
        return s.to_string();
    }
    let keep = max.saturating_sub(1);
    let head: String = s.chars().take(keep / 3).collect();
    let tail: String = s.chars().skip(n - (keep - keep / 3)).collect();
    format!("{head}…{tail}")
}

fn cross(o: P2, a: P2, b: P2) -> f64 {
    (a.y - o.y) * (b.x - o.x) - (a.x - o.x) * (b.y - o.y)
}

/// The same polygon, counter-clockwise in the picture (z right, x up).
fn ccw(mut p: Vec<P2>) -> Vec<P2> {
    let mut a = 0.0;
    for i in 0..p.len() {
        let (u, w) = (p[i], p[(i + 1) % p.len()]);
        a += u.y * w.x - w.y * u.x;
    }
    if a < 0.0 {
        p.reverse();
    }
    p
}

/// What the colliding part would go through in the rest of its move, had the machine not
/// stopped: the part swept along the path from the first contact to the end of the move, as
/// polygons of one winding (their union, filled nonzero, is the swept region). Only for parts
/// that move in the working plane by translation; `None` for the others (index sweeps, tools of
/// other stations).
fn sweep(s: &Snapshot) -> Option<Vec<Vec<P2>>> {
    if !s.mirrored || s.part_a.len() < 3 || s.part_b.is_empty() || s.path.len() < 2 {
        return None;
    }
    // The path segment the contact lies on (the last one, when several touch it).
    let mut best = (f64::INFINITY, 0);
    for i in 0..s.path.len() - 1 {
        let d = seg_dist(s.at, s.path[i], s.path[i + 1]);
        if d <= best.0 + 1e-9 {
            best = (d, i);
        }
    }
    if best.0 > 1e-3 {
        return None;
    }
    let mut rest = vec![s.at];
    for &p in &s.path[best.1 + 1..] {
        if (p - *rest.last()?).norm() > 1e-9 {
            rest.push(p);
        }
    }
    // Merge nearly straight runs: a line move is one segment.
    let mut pts = vec![rest[0]];
    for i in 1..rest.len() {
        if i + 1 < rest.len() {
            let (a, b, c) = (*pts.last()?, rest[i], rest[i + 1]);
            let chord = (c - a).norm();
            if chord > 0.0 && (cross(a, b, c) / chord).abs() < 0.02 {
                continue;
            }
        }
        pts.push(rest[i]);
    }
    if pts.len() < 2 {
        return None;
    }
    let shape = ccw(s.part_a.clone());
    let at = |d: crate::geom::V2| -> Vec<P2> { shape.iter().map(|p| p + d).collect() };
    let mut out = vec![];
    for w in pts.windows(2) {
        let (d0, d1) = (w[0] - s.at, w[1] - s.at);
        out.push(at(d1));
        for i in 0..shape.len() {
            let (u, v) = (shape[i], shape[(i + 1) % shape.len()]);
            let quad = vec![u + d0, v + d0, v + d1, u + d1];
            if cross(quad[0], quad[1], quad[2]).abs() + cross(quad[0], quad[2], quad[3]).abs() > 1e-12 {
                out.push(ccw(quad));
            }
        }
    }
    Some(out)
}

fn seg_dist(p: P2, a: P2, b: P2) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 {
        ((p - a).dot(&ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p - (a + ab * t)).norm()
}

fn inside(p: P2, poly: &[P2]) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.x > p.x) != (b.x > p.x) && p.y < a.y + (p.x - a.x) / (b.x - a.x) * (b.y - a.y) {
            c = !c;
        }
    }
    c
}

fn edge_dist(p: P2, poly: &[P2]) -> f64 {
    (0..poly.len())
        .map(|i| seg_dist(p, poly[i], poly[(i + 1) % poly.len()]))
        .fold(f64::INFINITY, f64::min)
}

/// Where labels go: inside their part, as far from its edges, the plot's border and the labels
/// already placed as a grid search finds.
pub(super) struct Labels<'v> {
    pub v: &'v View,
    /// Boxes taken, in picture units: (x0, y0, x1, y1).
    pub taken: Vec<(f64, f64, f64, f64)>,
}

impl Labels<'_> {
    pub(super) fn place(&mut self, polys: &[Vec<P2>], text: &str, size: f64) -> Option<(f64, f64)> {
        let v = self.v;
        let world = v.world();
        let half_w = 0.3 * size * text.chars().count() as f64;
        let mut best: Option<(f64, f64, f64)> = None;
        for poly in polys {
            let b = bounds_of(poly).clip(&world);
            // Too small to carry its name.
            if !(b.zmin < b.zmax && b.xmin < b.xmax) || (b.zmax - b.zmin) * v.scale < 1.2 * half_w {
                continue;
            }
            const K: usize = 24;
            for i in 0..=K {
                for j in 0..=K {
                    let p = P2::new(
                        b.xmin + (b.xmax - b.xmin) * i as f64 / K as f64,
                        b.zmin + (b.zmax - b.zmin) * j as f64 / K as f64,
                    );
                    if !inside(p, poly) {
                        continue;
                    }
                    let (x, y) = (v.sx(p.y), v.sy(p.x));
                    let border = (x - half_w - v.left)
                        .min(v.left + v.w - x - half_w)
                        .min(y - size - v.top)
                        .min(v.top + v.h - y - 4.0);
                    let score = (edge_dist(p, poly) * v.scale).min(border + size);
                    let clash = self
                        .taken
                        .iter()
                        .any(|&(x0, y0, x1, y1)| x + half_w > x0 && x - half_w < x1 && y > y0 && y - size < y1);
                    if clash || border < 0.0 {
                        continue;
                    }
                    if best.map_or(true, |(s, _, _)| score > s + 1e-9) {
                        best = Some((score, x, y + 0.35 * size));
                    }
                }
            }
        }
        let (score, x, y) = best?;
        if score < 0.5 * size {
            return None;
        }
        self.taken.push((x - half_w, y - size, x + half_w, y + 2.0));
        Some((x, y))
    }
}

/// The SVG of one finding whose source block text is `block`.
fn picture(file: &FileReport, f: &Finding, s: &Snapshot, block: &str) -> String {
    let v = View::fit(&region(s));
    let swept = sweep(s);
    // A near miss has no overlap to show: its parts stay apart.
    let has_overlap = s.part_a.len() >= 3 && !s.part_b.is_empty() && f.kind != crate::finding::Kind::NearMiss;
    let mut o = String::new();
    let _ = writeln!(o, "<title>{}:{}: {}</title>", esc(&file.path), f.line, esc(&f.message));
    let _ = writeln!(o, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    let _ = writeln!(
        o,
        r#"<defs><marker id="arrow" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse"><path d="M0,0L10,5L0,10Z" fill="{PATH_LINE}"/></marker><marker id="arrow-machine" viewBox="0 0 10 10" refX="9" refY="5" markerWidth="7" markerHeight="7" orient="auto-start-reverse"><path d="M0,0L10,5L0,10Z" fill="{MACHINE_LINE}"/></marker></defs>"#
    );
    caption(&mut o, file, f, block);
    scene(&mut o, &v, s, &Marks::of(f), swept.as_deref(), "main");
    if let Some(frame) = &s.frame {
        program_ticks(&mut o, &v, frame);
    }
    labels(&mut o, &v, s, f);
    if has_overlap {
        if let Some(core) = contact_core(s, swept.as_deref()) {
            contact_marker(&mut o, &v, &core);
        }
    }
    let mut below = v.top + v.h;
    if let Some(d) = detail(&v, s, swept.as_deref()) {
        below = d.view.top + d.view.h;
        // Where the detail is, in the main view.
        let _ = writeln!(
            o,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{INK}" stroke-width="1" stroke-dasharray="3 2"/>"#,
            n(v.sx(d.region.zmin)),
            n(v.sy(d.region.xmax)),
            n((d.region.zmax - d.region.zmin) * v.scale),
            n((d.region.xmax - d.region.xmin) * v.scale)
        );
        let _ = writeln!(
            o,
            r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#ffffff" stroke="{INK}" stroke-width="1.5"/>"##,
            n(d.view.left - 1.0),
            n(d.view.top - 1.0),
            n(d.view.w + 2.0),
            n(d.view.h + 2.0)
        );
        scene(&mut o, &d.view, s, &Marks::of(f), swept.as_deref(), "detail");
        let _ = writeln!(
            o,
            r##"<text x="{}" y="{}" font-size="12" font-weight="bold" fill="{INK}" stroke="#ffffff" stroke-width="3" paint-order="stroke">detail ×{}</text>"##,
            n(d.view.left + 6.0),
            n(d.view.top + 16.0),
            d.zoom
        );
    }
    let legend = Legend {
        overlap: has_overlap,
        swept: swept.is_some() && has_overlap,
        follow_on: f.follow_on.is_some(),
        // Both objects a path's part (`path1:T03 holder`): two carriers met.
        carriers: f.objects.len() == 2 && f.objects.iter().all(|o| o.starts_with("path") && o.contains(':')),
        machine: None,
    };
    let bottom = footer(&mut o, &v, s, &legend, below);
    document(&o, bottom)
}

/// The SVG document around a picture's body `o`, whose drawing ends at `bottom`.
pub(super) fn document(o: &str, bottom: f64) -> String {
    let h = n(bottom + 10.0);
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#,
        w = n(WIDTH),
    );
    svg.push('\n');
    svg.push_str(&split_halos(o));
    svg.push_str("</svg>\n");
    svg
}

/// Every label drawn with a halo (`stroke="…" … paint-order="stroke"`: the outline under the
/// letters) as two elements: the halo (its stroke and fill in the halo's colour) and then the
/// letters on top. `paint-order` is not read by every renderer (cairosvg paints the stroke over
/// the fill: white letters on white), two elements are.
pub(super) fn split_halos(body: &str) -> String {
    let mut out = String::with_capacity(body.len() + body.len() / 4);
    let mut rest = body;
    while let Some(i) = rest.find("<text ") {
        out.push_str(&rest[..i]);
        rest = &rest[i..];
        let (Some(open_end), Some(close)) = (rest.find('>'), rest.find("</text>")) else {
            break;
        };
        let tag = &rest[..open_end];
        if !tag.contains(r#"paint-order="stroke""#) || close < open_end {
            out.push_str(&rest[..open_end + 1]);
            rest = &rest[open_end + 1..];
            continue;
        }
        let content = &rest[open_end + 1..close];
        let attrs = attributes(&tag["<text ".len()..]);
        let get = |name: &str| attrs.iter().find(|(k, _)| *k == name).map(|(_, v)| *v);
        let halo = get("stroke").unwrap_or("#ffffff");
        let common: String = attrs
            .iter()
            .filter(|(k, _)| {
                !matches!(
                    *k,
                    "fill" | "stroke" | "stroke-width" | "stroke-opacity" | "paint-order"
                )
            })
            .map(|(k, v)| format!(r#" {k}="{v}""#))
            .collect();
        let opacity = get("stroke-opacity").map_or(String::new(), |o| format!(r#" opacity="{o}""#));
        out.push_str(&format!(
            r#"<text{common} fill="{halo}" stroke="{halo}" stroke-width="{}" stroke-linejoin="round"{opacity}>{content}</text>"#,
            get("stroke-width").unwrap_or("3")
        ));
        out.push_str(&format!(
            r#"<text{common} fill="{}">{content}</text>"#,
            get("fill").unwrap_or("#000000")
        ));
        rest = &rest[close + "</text>".len()..];
    }
    out.push_str(rest);
    out
}

/// `name="value"` pairs of a tag's attribute text, in order (values hold no quotes: they are
/// escaped with [`esc`]).
fn attributes(s: &str) -> Vec<(&str, &str)> {
    let mut out = Vec::new();
    let mut rest = s.trim_end_matches('/');
    while let Some(eq) = rest.find("=\"") {
        let name = rest[..eq].trim();
        let after = &rest[eq + 2..];
        let Some(end) = after.find('"') else { break };
        out.push((name, &after[..end]));
        rest = &after[end + 1..];
    }
    out
}

/// An enlarged view of the contact, for contacts too small to see in the main view.
struct Detail {
    view: View,
    /// The world region shown.
    region: Bounds,
    zoom: u32,
}

fn detail(main: &View, s: &Snapshot, swept: Option<&[Vec<P2>]>) -> Option<Detail> {
    if s.part_a.len() < 3 || s.part_b.is_empty() {
        return None;
    }
    let mut core = contact_core(s, swept).unwrap_or_else(Bounds::empty);
    core.add(s.at);
    let span = (core.zmax - core.zmin).max(core.xmax - core.xmin).max(3.0);
    let world = main.world();
    if span > 0.12 * (world.zmax - world.zmin) {
        return None;
    }
    // The detail is a panel of its own below the main view, so that it never covers any of it.
    let (iw, ih) = (DETAIL_W, DETAIL_H);
    let (left, top) = (main.left, main.top + main.h + 14.0);
    // The region, centred on the contact, with the inset's aspect.
    let c = P2::new((core.xmin + core.xmax) / 2.0, (core.zmin + core.zmax) / 2.0);
    let half_z = (1.6 * span).max(1.6 * span * iw / ih) / 2.0;
    let half_x = half_z * ih / iw;
    let region = Bounds {
        zmin: c.y - half_z,
        zmax: c.y + half_z,
        xmin: c.x - half_x,
        xmax: c.x + half_x,
    };
    let scale = iw / (2.0 * half_z);
    let zoom = (scale / main.scale).round() as u32;
    if zoom < 3 {
        return None;
    }
    Some(Detail {
        view: View {
            zmin: region.zmin,
            xmax: region.xmax,
            scale,
            left,
            top,
            w: iw,
            h: ih,
        },
        region,
        zoom,
    })
}

/// Where the two parts meet: the box of the moving part (and of what the rest of the move
/// sweeps) within the box of the obstacle. `None` when they do not meet.
fn contact_core(s: &Snapshot, swept: Option<&[Vec<P2>]>) -> Option<Bounds> {
    if s.part_a.len() < 3 || s.part_b.is_empty() {
        return None;
    }
    let mut b = Bounds::empty();
    for pb in &s.part_b {
        b.add_all(pb, s.mirrored);
    }
    let mut core = bounds_of(&s.part_a).clip(&b);
    if let Some(sw) = swept {
        let mut sb = Bounds::empty();
        for p in sw {
            sb.add_all(p, false);
        }
        let c = sb.clip(&b);
        if c.zmin <= c.zmax && c.xmin <= c.xmax {
            core.add(P2::new(c.xmin, c.zmin));
            core.add(P2::new(c.xmax, c.zmax));
        }
    }
    (core.zmin <= core.zmax && core.xmin <= core.xmax).then_some(core)
}

/// A ring around the place of contact, so that a sliver of overlap is found at a glance.
fn contact_marker(o: &mut String, v: &View, core: &Bounds) {
    let (cx, cy) = (v.sx((core.zmin + core.zmax) / 2.0), v.sy((core.xmin + core.xmax) / 2.0));
    let half = 0.5 * ((core.zmax - core.zmin).powi(2) + (core.xmax - core.xmin).powi(2)).sqrt() * v.scale;
    let r = (half + 7.0).clamp(14.0, 0.25 * v.w);
    let _ = writeln!(
        o,
        r##"<circle cx="{}" cy="{}" r="{}" fill="none" stroke="#ffffff" stroke-width="5" opacity="0.8"/><circle cx="{}" cy="{}" r="{}" fill="none" stroke="{OVERLAP}" stroke-width="2.2"/>"##,
        n(cx),
        n(cy),
        n(r),
        n(cx),
        n(cy),
        n(r)
    );
}

/// Ticks in program coordinates along the bottom and left edges of the plot (Z as written, X as
/// written: a diameter in diameter mode), and the program zero (Z0) as a thin line.
fn program_ticks(o: &mut String, v: &View, frame: &crate::interp::ProgFrame) {
    if frame.scale.is_nan() || frame.scale <= 0.0 {
        return;
    }
    let w = v.world();
    let unit = if frame.scale > 1.5 { "in" } else { "mm" };
    let halo = HALO;
    // Z along the bottom edge.
    let (z0, z1) = (
        (w.zmin - frame.origin.y) / frame.scale,
        (w.zmax - frame.origin.y) / frame.scale,
    );
    let step = nice((z1 - z0) / 8.0);
    let bottom = v.top + v.h;
    let mut k = (z0 / step).ceil();
    while k * step <= z1 && k.abs() < 1e6 {
        let zp = k * step;
        let sx = v.sx(frame.origin.y + zp * frame.scale);
        if sx < v.left + 18.0 || sx > v.left + v.w - 18.0 {
            k += 1.0;
            continue;
        }
        bottom_tick(o, sx, bottom, &format!("Z{}", mm(zp)));
        k += 1.0;
    }
    // X along the left edge, as the program writes it.
    let xs = if frame.diameter { 2.0 } else { 1.0 };
    let (x0, x1) = (
        xs * (w.xmin - frame.origin.x) / frame.scale,
        xs * (w.xmax - frame.origin.x) / frame.scale,
    );
    let step = nice((x1 - x0) / 6.0);
    let mut k = (x0 / step).ceil();
    while k * step <= x1 && k.abs() < 1e6 {
        let xp = k * step;
        let sy = v.sy(frame.origin.x + xp / xs * frame.scale);
        if sy > v.top + 8.0 && sy < bottom - 14.0 {
            left_tick(o, v.left, sy, &format!("X{}", mm(xp)));
        }
        k += 1.0;
    }
    // Program zero, its label on the side with room.
    let zx = v.sx(frame.origin.y);
    if zx > v.left + 1.0 && zx < v.left + v.w - 1.0 {
        let right = zx < v.left + v.w - 160.0;
        let _ = writeln!(
            o,
            r##"<line x1="{x}" y1="{}" x2="{x}" y2="{}" stroke="#57606a" stroke-width="0.8" stroke-dasharray="2 3"/><text x="{}" y="{}" font-size="11" font-weight="bold" fill="#57606a" text-anchor="{}" {halo}>Z0 program zero ({unit})</text>"##,
            n(v.top),
            n(bottom),
            n(if right { zx + 4.0 } else { zx - 4.0 }),
            n(v.top + 13.0),
            if right { "start" } else { "end" },
            x = n(zx)
        );
    }
}

/// The scene in one view: every part, the overlap, the axis and the path, clipped to the view.
/// What of a finding the drawing of a scene shows besides the snapshot.
pub(super) struct Marks {
    /// The overlap is a follow-on of an earlier crash (orange, not red).
    pub follow_on: bool,
    /// The programmed point as the program writes it (`X… Z…` beside its circle).
    pub at: Option<(f64, f64)>,
}

impl Marks {
    fn of(f: &Finding) -> Marks {
        Marks {
            follow_on: f.follow_on.is_some(),
            at: f.x.zip(f.z),
        }
    }
}

/// The parts of a snapshot (chuck, tailstock, stock, turret, tools), the overlap, the paths and
/// the programmed point, clipped to the view's plot area.
pub(super) fn scene(o: &mut String, v: &View, s: &Snapshot, f: &Marks, swept: Option<&[Vec<P2>]>, id: &str) {
    let part_b: Vec<&[P2]> = s.part_b.iter().map(|p| p.as_slice()).collect();
    let has_overlap = s.part_a.len() >= 3 && !part_b.is_empty();
    let overlap = if f.follow_on { FOLLOW_ON } else { OVERLAP };
    let _ = writeln!(o, "<defs>");
    let _ = writeln!(
        o,
        r#"<clipPath id="plot-{id}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath>"#,
        n(v.left),
        n(v.top),
        n(v.w),
        n(v.h)
    );
    if has_overlap {
        let _ = writeln!(
            o,
            r#"<clipPath id="part-b-{id}"><path clip-rule="nonzero" d="{}"/></clipPath>"#,
            v.path(&part_b, s.mirrored)
        );
    }
    let _ = writeln!(o, "</defs>");
    let _ = writeln!(
        o,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#fbfbfa" stroke="#d0d7de"/>"##,
        n(v.left),
        n(v.top),
        n(v.w),
        n(v.h)
    );
    let _ = writeln!(o, r#"<g clip-path="url(#plot-{id})" stroke-linejoin="round">"#);
    let poly = |o: &mut String, pts: &[&[P2]], mirror: bool, fill: &str, line: &str, extra: &str| {
        if pts.iter().all(|p| p.is_empty()) {
            return;
        }
        let width = if extra.contains("stroke-width") {
            ""
        } else {
            r#" stroke-width="1.2""#
        };
        let _ = writeln!(
            o,
            r#"<path d="{}" fill="{fill}" stroke="{line}"{width}{extra}/>"#,
            v.path(pts, mirror)
        );
    };
    if let Some(c) = &s.chuck {
        poly(o, &[c], true, CHUCK_FILL, CHUCK_LINE, "");
    }
    if let Some(t) = &s.tailstock {
        poly(o, &[t], true, CHUCK_FILL, CHUCK_LINE, "");
    }
    let stock: Vec<&[P2]> = s.stock.iter().map(|p| p.as_slice()).collect();
    poly(o, &stock, true, STOCK_FILL, STOCK_FILL, r#" stroke-width="0.6""#);
    poly(o, &[&s.turret], false, TURRET_FILL, TURRET_LINE, "");
    for (_, p) in &s.others {
        poly(o, &[p], false, "none", OTHER_LINE, r#" stroke-dasharray="5 3""#);
    }
    poly(o, &[&s.holder], false, HOLDER_FILL, HOLDER_LINE, "");
    poly(o, &[&s.insert], false, INSERT_FILL, INSERT_LINE, "");

    // Spindle axis: dash-dot centre line.
    let ya = v.sy(0.0);
    let _ = writeln!(
        o,
        r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="{INK}" stroke-width="0.9" stroke-dasharray="18 4 3 4"/>"#,
        n(v.left),
        n(v.left + v.w),
        y = n(ya)
    );

    if has_overlap {
        if let Some(sw) = swept {
            let polys: Vec<&[P2]> = sw.iter().map(|p| p.as_slice()).collect();
            let _ = writeln!(
                o,
                r#"<path d="{}" fill="{overlap}" fill-opacity="0.3" fill-rule="nonzero" stroke="none" clip-path="url(#part-b-{id})"/>"#,
                v.path(&polys, false)
            );
        }
        // The overlap at first contact: part a inside part b, filled, with its edge drawn
        // thick so that a sliver still shows.
        let _ = writeln!(
            o,
            r#"<path d="{d}" fill="{overlap}" stroke="{overlap}" stroke-width="3" clip-path="url(#part-b-{id})"/>"#,
            d = v.path(&[&s.part_a], false)
        );
    }
    // The colliding part, when it is not the active tool (turret, another station's tool).
    let is_tool = s.part_a == s.holder || s.part_a == s.insert;
    if s.part_a.len() >= 3 && !is_tool {
        poly(
            o,
            &[&s.part_a],
            false,
            "none",
            OVERLAP,
            r#" stroke-dasharray="7 3" stroke-width="1.6""#,
        );
    }

    // The path of the programmed point, with its direction. A move that does not move the
    // programmed point (a station change, a dwell) adds nothing to draw.
    let mut path: Vec<P2> = Vec::new();
    for &p in &s.path {
        if path.last().map_or(true, |q: &P2| (p - q).norm() > 1e-9) {
            path.push(p);
        }
    }
    let stationary = s.path.len() >= 2 && (s.path[s.path.len() - 1] - s.path[s.path.len() - 2]).norm() <= 1e-9;
    if stationary {
        path.pop();
    }
    if path.len() >= 2 {
        let pts: Vec<String> = path.iter().map(|p| v.pt(*p)).collect();
        let _ = writeln!(
            o,
            r#"<polyline points="{}" fill="none" stroke="{PATH_LINE}" stroke-width="1.6" marker-end="url(#arrow)"/>"#,
            pts.join(" ")
        );
    }
    if s.machine_path.len() >= 2 {
        let pts: Vec<String> = s.machine_path.iter().map(|p| v.pt(*p)).collect();
        let _ = writeln!(
            o,
            r#"<polyline points="{}" fill="none" stroke="{MACHINE_LINE}" stroke-width="2.2" stroke-dasharray="8 3" marker-end="url(#arrow-machine)"/>"#,
            pts.join(" ")
        );
    }
    if let Some(t) = &s.travel {
        travel(o, v, t);
    }
    let (cx, cy) = (v.sx(s.at.y), v.sy(s.at.x));
    let _ = writeln!(
        o,
        r##"<circle cx="{x}" cy="{y}" r="4" fill="#ffffff" stroke="{PATH_LINE}" stroke-width="2"/>"##,
        x = n(cx),
        y = n(cy)
    );
    if let Some((px, pz)) = f.at {
        // The programmed point, as the program writes it.
        let right = cx < v.left + v.w - 140.0;
        let _ = writeln!(
            o,
            r##"<text x="{}" y="{}" font-size="12" fill="{PATH_LINE}" text-anchor="{}" stroke="#ffffff" stroke-width="3" paint-order="stroke">X{} Z{}</text>"##,
            n(if right { cx + 8.0 } else { cx - 8.0 }),
            n(cy - 8.0),
            if right { "start" } else { "end" },
            mm(px),
            mm(pz)
        );
    }
    let _ = writeln!(o, "</g>");
}

/// An overtravel: the broken limit of the turret reference point, its path through the move and
/// the point farthest beyond the limit, with the overshoot.
fn travel(o: &mut String, v: &View, t: &crate::scene::Travel) {
    let (x1, y1, x2, y2) = if t.axis == 'Z' {
        let x = v.sx(t.limit);
        (x, v.top, x, v.top + v.h)
    } else {
        let y = v.sy(t.limit);
        (v.left, y, v.left + v.w, y)
    };
    let _ = writeln!(
        o,
        r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{LIMIT_LINE}" stroke-width="2" stroke-dasharray="10 4"/>"#,
        n(x1),
        n(y1),
        n(x2),
        n(y2)
    );
    let pts: Vec<String> = t.reference_path.iter().map(|p| v.pt(*p)).collect();
    let _ = writeln!(
        o,
        r#"<polyline points="{}" fill="none" stroke="{LIMIT_LINE}" stroke-width="1.4"/>"#,
        pts.join(" ")
    );
    let (wx, wy) = (v.sx(t.worst.y), v.sy(t.worst.x));
    // From the limit to the worst point: the overshoot.
    let (fx, fy) = if t.axis == 'Z' {
        (v.sx(t.limit), wy)
    } else {
        (wx, v.sy(t.limit))
    };
    let _ = writeln!(
        o,
        r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{LIMIT_LINE}" stroke-width="3"/><circle cx="{}" cy="{}" r="4" fill="{LIMIT_LINE}"/>"#,
        n(fx),
        n(fy),
        n(wx),
        n(wy),
        n(wx),
        n(wy)
    );
    let label = format!(
        "{} travel limit of the turret reference point ({} = {} mm): {} mm beyond",
        t.axis,
        if t.axis == 'Z' { "z" } else { "radius" },
        mm(t.limit),
        mm(t.overshoot)
    );
    let right = wx < v.left + v.w / 2.0;
    let ty = (wy - 10.0).clamp(v.top + 14.0, v.top + v.h - 6.0);
    let _ = writeln!(
        o,
        r##"<text x="{}" y="{}" font-size="12" font-weight="bold" fill="{LIMIT_LINE}" text-anchor="{}" stroke="#ffffff" stroke-width="3" paint-order="stroke">{}</text>"##,
        n(if right { wx + 8.0 } else { wx - 8.0 }),
        n(ty),
        if right { "start" } else { "end" },
        esc(&label)
    );
}

/// Caption: where (file, line), what, the block, and the facts at first contact.
fn caption(o: &mut String, file: &FileReport, f: &Finding, block: &str) {
    let sev_color = if f.severity == Severity::Error {
        OVERLAP
    } else {
        "#9a6700"
    };
    let head = format!("{}[{}]", f.severity.name(), f.kind);
    let place = fit_middle(&format!("{}:{}", file.path, f.line), 110 - head.chars().count());
    let m = n(MARGIN);
    let _ = writeln!(
        o,
        r#"<text x="{m}" y="24" font-size="16" fill="{INK}"><tspan font-weight="bold">{}</tspan>  <tspan fill="{sev_color}" font-weight="bold">{}</tspan></text>"#,
        esc(&place),
        esc(&head),
    );
    // A follow-on says whose crash it comes from on the message line, where it is read first.
    let message = match f.follow_on_note() {
        Some(p) => format!("{} — {p}", f.message),
        None => f.message.clone(),
    };
    let message = match f.profile_line {
        Some(p) => format!("{message} (profile line {p})"),
        None => message,
    };
    let _ = writeln!(
        o,
        r#"<text x="{m}" y="46" font-size="15" fill="{INK}">{}</text>"#,
        esc(&fit_text(&message, 115))
    );
    if !block.is_empty() {
        let _ = writeln!(
            o,
            r#"<text x="{m}" y="68" font-size="13" font-family="DejaVu Sans Mono, Menlo, Consolas, monospace" fill="{INK}" xml:space="preserve">{:>5} | {}</text>"#,
            f.line,
            esc(&fit_text(block, 112))
        );
    }
    let mut facts = Vec::new();
    if let Some(t) = f.time_s {
        facts.push(format!("t = {t:.3} s"));
    }
    if let Some(d) = f.depth_mm {
        facts.push(format!("depth {} mm", mm(d)));
    }
    if let (Some(x), Some(z)) = (f.x, f.z) {
        facts.push(format!("programmed point X{} Z{}", mm(x), mm(z)));
    }
    if f.end_line != f.line {
        facts.push(format!("lines {}–{}", f.line, f.end_line));
    }
    if let Some(nn) = f.n {
        facts.push(format!("N{nn}"));
    }
    if !f.objects.is_empty() {
        facts.push(f.parts_in_words().join(" × "));
    }
    let _ = writeln!(
        o,
        r##"<text x="{m}" y="90" font-size="13" fill="#57606a">first contact: {}</text>"##,
        esc(&fit_text(&facts.join("   "), 130))
    );
}

/// Names on the parts, placed inside them where there is room.
fn labels(o: &mut String, v: &View, s: &Snapshot, f: &Finding) {
    let mut l = Labels { v, taken: Vec::new() };
    let put = |o: &mut String, l: &mut Labels, polys: Vec<Vec<P2>>, text: &str, color: &str, bold: bool| {
        let size = 13.0;
        if let Some((x, y)) = l.place(&polys, text, size) {
            let weight = if bold { r#" font-weight="bold""# } else { "" };
            let _ = writeln!(
                o,
                r##"<text x="{}" y="{}" font-size="{size}" fill="{color}"{weight} text-anchor="middle" stroke="#ffffff" stroke-width="3" stroke-opacity="0.8" paint-order="stroke">{}</text>"##,
                n(x),
                n(y),
                esc(text)
            );
        }
    };
    let mirror = |p: &[P2]| -> Vec<Vec<P2>> { vec![p.iter().map(|q| P2::new(-q.x, q.y)).collect(), p.to_vec()] };
    // The active tool's station, when the finding is about it (not about another station's tool).
    let other = s.others.iter().any(|(label, _)| f.objects.contains(label));
    let station = f
        .objects
        .iter()
        .find_map(|o| o.split_whitespace().next().filter(|w| w.starts_with('T')))
        .filter(|_| !other);
    let holder = station.map_or("holder".to_string(), |t| format!("{t} holder"));
    // The colliding part of another station first: it is the one to find.
    for (label, p) in &s.others {
        if f.objects.iter().any(|o| o == label) {
            put(o, &mut l, vec![s.part_a.clone(), p.clone()], label, OVERLAP, true);
        }
    }
    put(o, &mut l, vec![s.holder.clone()], &holder, HOLDER_LINE, false);
    put(o, &mut l, vec![s.insert.clone()], "insert", INSERT_LINE, false);
    if let Some(c) = &s.chuck {
        put(o, &mut l, mirror(c), "chuck", CHUCK_LINE, false);
    }
    if let Some(t) = &s.tailstock {
        put(o, &mut l, mirror(t), "tailstock", CHUCK_LINE, false);
    }
    if let Some(st) = s.stock.iter().max_by(|a, b| area(a).total_cmp(&area(b))) {
        put(o, &mut l, mirror(st), "stock", STOCK_LINE, false);
    }
    put(o, &mut l, vec![s.turret.clone()], "turret", TURRET_LINE, false);
}

pub(super) fn area(p: &[P2]) -> f64 {
    let mut a = 0.0;
    for i in 0..p.len() {
        let (u, w) = (p[i], p[(i + 1) % p.len()]);
        a += u.y * w.x - w.y * u.x;
    }
    (a / 2.0).abs()
}

/// Scale bar, axis directions and the legend.
/// Returns the bottom of what it drew.
/// What the legend lists beyond the parts.
pub(super) struct Legend {
    pub overlap: bool,
    pub swept: bool,
    pub follow_on: bool,
    /// A contact between two paths' carriers: the dashed outlines are the other carrier's parts
    /// and this one's other stations, in the working plane.
    pub carriers: bool,
    /// A machine drawing (`latheguard machine --svg`) rather than a finding's picture: the stock
    /// as set up, the other stations named for the turret type, no path.
    pub machine: Option<MachineLegend>,
}

/// The legend of a machine drawing.
pub(super) struct MachineLegend {
    /// How the other stations are drawn: "other stations, radial section" (a drum) or "other
    /// stations, in the working plane" (a gang slide).
    pub others: &'static str,
}

pub(super) fn footer(o: &mut String, v: &View, s: &Snapshot, legend: &Legend, below: f64) -> f64 {
    let y = below + 24.0;
    // Scale bar: a round length near a sixth of the width.
    let len = nice(v.w / v.scale / 6.0);
    let px = len * v.scale;
    let x0 = v.left;
    let _ = writeln!(
        o,
        r#"<path d="M{a},{b}L{a},{c}L{d},{c}L{d},{b}" fill="none" stroke="{INK}" stroke-width="1.5"/>"#,
        a = n(x0),
        b = n(y - 6.0),
        c = n(y),
        d = n(x0 + px)
    );
    let _ = writeln!(
        o,
        r#"<text x="{}" y="{}" font-size="12" fill="{INK}" text-anchor="middle">{} mm</text>"#,
        n(x0 + px / 2.0),
        n(y + 15.0),
        mm(len)
    );
    // Axis directions.
    let ax = x0 + px.max(60.0) + 24.0;
    let _ = writeln!(
        o,
        r#"<path d="M{a},{y0}L{b},{y0}M{a},{y0}L{a},{c}" stroke="{INK}" stroke-width="1.3" fill="none"/><text x="{d}" y="{y1}" font-size="12" fill="{INK}">+Z</text><text x="{e}" y="{f}" font-size="12" fill="{INK}">+X</text>"#,
        a = n(ax),
        b = n(ax + 28.0),
        c = n(y - 22.0),
        d = n(ax + 31.0),
        e = n(ax + 4.0),
        f = n(y - 13.0),
        y0 = n(y),
        y1 = n(y + 4.0)
    );
    // Legend, in rows.
    let mut items: Vec<(&str, &str, &str, &str)> = Vec::new();
    if s.chuck.is_some() || s.tailstock.is_some() {
        items.push(("chuck, tailstock", CHUCK_FILL, CHUCK_LINE, ""));
    }
    if !s.stock.is_empty() {
        let what = if legend.machine.is_some() {
            "stock as set up"
        } else {
            "stock at that moment"
        };
        items.push((what, STOCK_FILL, STOCK_FILL, ""));
    }
    items.push(("turret", TURRET_FILL, TURRET_LINE, ""));
    items.push(("holder", HOLDER_FILL, HOLDER_LINE, ""));
    items.push(("insert", INSERT_FILL, INSERT_LINE, ""));
    if !s.others.is_empty() {
        items.push((
            match (&legend.machine, legend.carriers) {
                (Some(m), _) => m.others,
                (None, true) => "other carrier, other stations (working plane)",
                (None, false) => "other stations, radial section",
            },
            "none",
            OTHER_LINE,
            r#" stroke-dasharray="4 2""#,
        ));
    }
    if legend.machine.is_none() {
        items.push(("programmed path", "none", PATH_LINE, ""));
    } else {
        items.push(("travel of the turret reference point", "none", LIMIT_LINE, ""));
    }
    if s.machine_path.len() >= 2 {
        items.push(("dogleg rapid as the machine moves", "none", MACHINE_LINE, ""));
    }
    if s.travel.is_some() {
        items.push(("travel limit, turret reference point", "none", LIMIT_LINE, ""));
    }
    if legend.overlap {
        if legend.follow_on {
            items.push(("overlap (follow-on of an earlier crash)", FOLLOW_ON, FOLLOW_ON, ""));
        } else {
            items.push(("overlap at first contact", OVERLAP, OVERLAP, ""));
        }
        if legend.swept {
            items.push(("swept by the rest of the move", "#f5a3a5", "#f5a3a5", ""));
        }
    }
    let x_start = ax + 64.0;
    let x_end = v.left + v.w;
    let (mut lx, mut ly) = (x_start, y - 6.0);
    for (label, fill, line, extra) in items {
        let w = 21.0 + 6.8 * label.chars().count() as f64 + 14.0;
        if lx + w > x_end + 10.0 && lx > x_start {
            lx = x_start;
            ly += 18.0;
        }
        if fill == "none" && extra.is_empty() {
            let dash = if line == PATH_LINE {
                ""
            } else {
                r#" stroke-dasharray="6 2""#
            };
            let _ = writeln!(
                o,
                r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="{line}" stroke-width="2"{dash}/>"#,
                n(lx),
                n(ly - 4.0),
                n(lx + 16.0),
                n(ly - 4.0)
            );
        } else {
            let _ = writeln!(
                o,
                r#"<rect x="{}" y="{}" width="16" height="11" fill="{fill}" stroke="{line}"{extra}/>"#,
                n(lx),
                n(ly - 10.0)
            );
        }
        let _ = writeln!(
            o,
            r#"<text x="{}" y="{}" font-size="12" fill="{INK}">{}</text>"#,
            n(lx + 21.0),
            n(ly),
            esc(label)
        );
        lx += w;
    }
    let note_y = (y + 36.0).max(ly + 24.0);
    let _ = writeln!(
        o,
        r##"<text x="{}" y="{}" font-size="11" fill="#57606a">Section through the spindle axis, machine frame (z = 0 at the jaw faces); revolved parts are drawn on both sides of the centre line. latheguard {}</text>"##,
        n(v.left),
        n(note_y),
        env!("CARGO_PKG_VERSION"),
    );
    note_y
}

#[cfg(test)]
mod halo_tests {
    use super::split_halos;

    #[test]
    fn a_haloed_label_becomes_its_halo_then_its_letters() {
        let body = r##"<path d="M0,0"/><text x="1" y="2" font-size="12" fill="#b42318" text-anchor="end" stroke="#ffffff" stroke-width="3" stroke-opacity="0.8" paint-order="stroke">X10 &amp; Z5</text><text x="3" y="4" fill="#000">plain</text>"##;
        assert_eq!(
            split_halos(body),
            r##"<path d="M0,0"/><text x="1" y="2" font-size="12" text-anchor="end" fill="#ffffff" stroke="#ffffff" stroke-width="3" stroke-linejoin="round" opacity="0.8">X10 &amp; Z5</text><text x="1" y="2" font-size="12" text-anchor="end" fill="#b42318">X10 &amp; Z5</text><text x="3" y="4" fill="#000">plain</text>"##
        );
        // Nothing else changes, and no paint-order is left anywhere.
        assert_eq!(split_halos("<g><rect/></g>"), "<g><rect/></g>");
        let rotated = r##"<text transform="translate(5,6) rotate(-90)" fill="#333" stroke="#fbfbfa" stroke-width="3" paint-order="stroke">X travel</text>"##;
        let out = split_halos(rotated);
        assert!(
            !out.contains("paint-order") && out.matches("rotate(-90)").count() == 2,
            "{out}"
        );
    }
}
