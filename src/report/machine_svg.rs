//! A drawing of a machine at home, as SVG (`latheguard machine FILE --svg OUT`, the pictures of
//! docs/machines/).
//!
//! The main view is the working plane as the finding pictures draw it (`svg.rs`: chuck on the
//! left, `+z` to the right, `x` up, revolved parts on both sides of the dash-dot centre line): the
//! chuck, the stock as set up, the tailstock, the turret at home with the start station's tool in
//! the working plane, the travel of the turret reference point as a dashed box with its two
//! dimensions, and home marked. The other stations: on a gang slide they stand in the working
//! plane, each drawn and named there; on a drum they are turned out of the plane, drawn dashed
//! where they cut the radial section, and an end view of the drum below (seen from the tailstock)
//! names every station at its angle, with the radial reach of its tool.
//!
//! Output is a pure function of the machine and the title: identical runs give identical files.

use std::fmt::Write;

use super::svg::{
    area, document, esc, footer, mm, n, scene, Bounds, Labels, Legend, MachineLegend, Marks, View, CHUCK_LINE,
    HOLDER_LINE, INK, LIMIT_LINE, OTHER_LINE, PATH_LINE, STOCK_FILL, STOCK_LINE, TURRET_FILL, TURRET_LINE,
};
use crate::geom::{p2, Polygon, P2};
use crate::machine::{Machine, TurretKind};
use crate::scene::{Scene, Snapshot};

/// Side of the drum's end view, px.
const END_VIEW: f64 = 380.0;

fn moved(p: &Polygon, by: P2) -> Vec<P2> {
    p.points().iter().map(|q| p2(q.x + by.x, q.y + by.y)).collect()
}

/// The SVG drawing of `m` at home; `title` names it (the machine file's path).
pub fn machine_drawing(m: &Machine, title: &str) -> String {
    let home = m.home;
    let gang = m.turret.kind == TurretKind::Gang;
    let start = m.turret.start_station;
    let scene_parts = Scene::new(m, 0.05);
    let mut s = Snapshot {
        chuck: m.chuck.as_ref().map(|c| c.points().to_vec()),
        tailstock: m.tailstock.as_ref().map(|t| t.points().to_vec()),
        turret: moved(&m.turret.outline, home),
        at: home,
        ..Snapshot::default()
    };
    if let Some(st) = &m.stock {
        let (r0, r1) = (st.bore / 2.0, st.diameter / 2.0);
        s.stock.push(vec![
            p2(r0, st.front - st.length),
            p2(r1, st.front - st.length),
            p2(r1, st.front),
            p2(r0, st.front),
        ]);
    }
    // The tools: the start station's in the working plane; the others in plane (gang) or in the
    // radial section (drum).
    let mut in_plane: Vec<(String, Vec<P2>)> = Vec::new();
    for t in &m.tools {
        let at = p2(home.x + t.tip.x, home.y + t.tip.y);
        if t.station == start {
            s.holder = moved(&t.holder, at);
            s.insert = moved(&t.insert, at);
            s.at = at;
        } else if gang {
            let mut both = moved(&t.holder, at);
            both.extend(moved(&t.insert, at));
            s.others.push((format!("T{:02}", t.station), moved(&t.holder, at)));
            s.others.push((format!("T{:02}", t.station), moved(&t.insert, at)));
            in_plane.push((format!("T{:02}", t.station), both));
        } else {
            let angle = scene_parts.station_angle(t.station, start as f64);
            for shape in [&t.holder, &t.insert] {
                if let Some(sec) = scene_parts.map_to_section(shape, t.tip.coords, home, angle) {
                    for p in sec.pieces() {
                        s.others.push((format!("T{:02}", t.station), p.points().to_vec()));
                    }
                }
            }
        }
    }

    // The region: every part and the travel box.
    let mut b = Bounds::empty();
    for p in [&s.chuck, &s.tailstock].into_iter().flatten() {
        b.add_all(p, true);
    }
    for p in &s.stock {
        b.add_all(p, true);
    }
    b.add_all(&s.turret, false);
    b.add_all(&s.holder, false);
    b.add_all(&s.insert, false);
    for (_, p) in &s.others {
        b.add_all(p, false);
    }
    let (x0, x1, z0, z1) = (m.x.min, m.x.max, m.z.min, m.z.max);
    b.add(p2(x0, z0));
    b.add(p2(x1, z1));
    let head = 104.0;
    let mut v = View::fit(&b);
    // Room at the top for the caption (View::fit puts the plot below HEAD of svg.rs, 104 px).
    v.top = head;

    let mut o = String::new();
    let _ = writeln!(o, "<title>{}: {}</title>", esc(title), esc(&m.name));
    let _ = writeln!(o, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
    let _ = writeln!(
        o,
        r#"<defs><marker id="dim" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="8" markerHeight="8" orient="auto-start-reverse"><path d="M0,1L10,5L0,9Z" fill="{LIMIT_LINE}"/></marker></defs>"#
    );
    caption(&mut o, m, title);
    let marks = Marks {
        follow_on: false,
        at: None,
    };
    scene(&mut o, &v, &s, &marks, None, "machine");
    let mut l = Labels {
        v: &v,
        taken: Vec::new(),
    };
    travel_box(&mut o, &mut l, m);
    home_mark(&mut o, &mut l, m, s.at);

    // Names: the tools first (they are the smallest), then the big parts.
    let mirror = |p: &[P2]| -> Vec<Vec<P2>> { vec![p.iter().map(|q| P2::new(-q.x, q.y)).collect(), p.to_vec()] };
    if let Some(t) = m.tool(start) {
        let active = format!("T{:02} {}", t.station, t.name);
        let mut both = s.holder.clone();
        both.extend(s.insert.iter().copied());
        if !label(&mut o, &mut l, vec![s.holder.clone()], &active, HOLDER_LINE, true) {
            leader(&mut o, &v, &mut l, &both, &active, HOLDER_LINE);
        }
    }
    if gang {
        for (name, pts) in &in_plane {
            if !label(&mut o, &mut l, vec![pts.clone()], name, OTHER_LINE, true) {
                leader(&mut o, &v, &mut l, pts, name, OTHER_LINE);
            }
        }
    }
    if let Some(c) = &s.chuck {
        label(&mut o, &mut l, mirror(c), "chuck", CHUCK_LINE, false);
    }
    if let Some(t) = &s.tailstock {
        let what = if m.tailstock_advanced {
            "tailstock (advanced)"
        } else {
            "tailstock where advanced (retracted at start)"
        };
        if !label(&mut o, &mut l, mirror(t), what, CHUCK_LINE, false) {
            label(&mut o, &mut l, mirror(t), "tailstock", CHUCK_LINE, false);
        }
    }
    if let Some(st) = s.stock.iter().max_by(|a, b| area(a).total_cmp(&area(b))) {
        label(&mut o, &mut l, mirror(st), "stock", STOCK_LINE, false);
    }
    label(&mut o, &mut l, vec![s.turret.clone()], "turret", TURRET_LINE, false);

    let mut below = v.top + v.h;
    if !gang {
        below = end_view(&mut o, m, below + 16.0);
    }
    let legend = Legend {
        carriers: false,
        overlap: false,
        swept: false,
        follow_on: false,
        machine: Some(MachineLegend {
            others: if gang {
                "other stations, in the working plane"
            } else {
                "other stations, radial section"
            },
        }),
    };
    let bottom = footer(&mut o, &v, &s, &legend, below);
    document(&o, bottom)
}

/// A name inside its part, where it fits; false when it does not.
fn label(o: &mut String, l: &mut Labels<'_>, polys: Vec<Vec<P2>>, text: &str, color: &str, bold: bool) -> bool {
    let size = 13.0;
    let Some((x, y)) = l.place(&polys, text, size) else {
        return false;
    };
    let weight = if bold { r#" font-weight="bold""# } else { "" };
    let _ = writeln!(
        o,
        r##"<text x="{}" y="{}" font-size="{size}" fill="{color}"{weight} text-anchor="middle" stroke="#ffffff" stroke-width="3" stroke-opacity="0.8" paint-order="stroke">{}</text>"##,
        n(x),
        n(y),
        esc(text)
    );
    true
}

/// A name beside a part too small to hold it, with a leader line to the part.
fn leader(o: &mut String, v: &View, l: &mut Labels<'_>, pts: &[P2], text: &str, color: &str) {
    let mut b = Bounds::empty();
    b.add_all(pts, false);
    if b.zmin > b.zmax {
        return;
    }
    let size = 13.0;
    let w = 0.62 * size * text.chars().count() as f64;
    let (px, py) = (v.sx(b.zmin), v.sy((b.xmin + b.xmax) / 2.0));
    // Try left of the part, then lower, until the box is free.
    let mut y = py;
    for _ in 0..12 {
        let (x0, x1) = (px - 24.0 - w, px - 24.0);
        let clash = l
            .taken
            .iter()
            .any(|&(a0, b0, a1, b1)| x1 > a0 && x0 < a1 && y + 4.0 > b0 && y - size < b1);
        if !clash && x0 > v.left {
            l.taken.push((x0, y - size, x1, y + 4.0));
            let _ = writeln!(
                o,
                r##"<path d="M{},{}L{},{}" stroke="{color}" stroke-width="0.8" fill="none"/><text x="{}" y="{}" font-size="{size}" font-weight="bold" fill="{color}" text-anchor="end" stroke="#ffffff" stroke-width="3" stroke-opacity="0.8" paint-order="stroke">{}</text>"##,
                n(x1 + 2.0),
                n(y - 4.0),
                n(px),
                n(py),
                n(x1),
                n(y),
                esc(text)
            );
            return;
        }
        y += size + 4.0;
    }
}

fn caption(o: &mut String, m: &Machine, title: &str) {
    let kind = match m.turret.kind {
        TurretKind::Drum => format!("{}-station drum turret", m.turret.stations),
        TurretKind::Gang => format!("gang slide, {} stations", m.turret.stations),
    };
    let dialect = if m.auto_dialect.is_some() {
        "auto"
    } else {
        m.dialect.as_str()
    };
    let _ = writeln!(
        o,
        r#"<text x="16" y="30" font-size="20" font-weight="bold" fill="{INK}">{}</text>"#,
        esc(&m.name)
    );
    let mut line = format!(
        "{title} · {dialect}{} · {kind} · {} tools · spindle max {} rpm",
        if m.inch { ", inch programs" } else { "" },
        m.tools.len(),
        mm(m.max_rpm)
    );
    if let Some(st) = &m.stock {
        let _ = write!(line, " · stock Ø{} × {}", mm(st.diameter), mm(st.length));
        if st.bore > 0.0 {
            let _ = write!(line, " (bore Ø{})", mm(st.bore));
        }
    }
    let _ = writeln!(
        o,
        r#"<text x="16" y="54" font-size="13" fill="{INK}">{}</text>"#,
        esc(&line)
    );
    let _ = writeln!(
        o,
        r#"<text x="16" y="74" font-size="13" fill="{INK}">At home: turret reference point X{} Z{} (radius, mm, machine frame: z = 0 at the jaw faces), station {} in the working plane; program Z0 at z {}.</text>"#,
        mm(m.home.x),
        mm(m.home.y),
        m.turret.start_station,
        mm(m.program_zero_z)
    );
}

/// The travel of the turret reference point: a dashed box with a dimension along each axis.
fn travel_box(o: &mut String, lb: &mut Labels<'_>, m: &Machine) {
    let v = lb.v;
    let (x0, x1, z0, z1) = (m.x.min, m.x.max, m.z.min, m.z.max);
    let (l, r, t, b) = (v.sx(z0), v.sx(z1), v.sy(x1), v.sy(x0));
    let _ = writeln!(
        o,
        r#"<rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="{LIMIT_LINE}" stroke-width="1.2" stroke-dasharray="6 4"/>"#,
        n(l),
        n(t),
        n(r - l),
        n(b - t)
    );
    // Z: above the box, inside the plot.
    let yd = (t - 14.0).max(v.top + 18.0);
    let zt = format!("Z travel {} mm: z {} .. {}", mm(z1 - z0), mm(z0), mm(z1));
    let half = 0.31 * 12.0 * zt.chars().count() as f64;
    lb.taken
        .push(((l + r) / 2.0 - half, yd - 18.0, (l + r) / 2.0 + half, yd + 2.0));
    let _ = writeln!(
        o,
        r##"<path d="M{l},{yd}L{r},{yd}" stroke="{LIMIT_LINE}" stroke-width="1" marker-start="url(#dim)" marker-end="url(#dim)"/><text x="{}" y="{}" font-size="12" fill="{LIMIT_LINE}" text-anchor="middle" stroke="#ffffff" stroke-width="3" paint-order="stroke">{}</text>"##,
        n((l + r) / 2.0),
        n(yd - 4.0),
        esc(&zt),
        l = n(l),
        r = n(r),
        yd = n(yd)
    );
    // X: right of the box (left of it when the box reaches the plot's right edge).
    let right = r + 70.0 < v.left + v.w;
    let xd = if right { r + 14.0 } else { l - 14.0 };
    let _ = writeln!(
        o,
        r##"<path d="M{xd},{t}L{xd},{b}" stroke="{LIMIT_LINE}" stroke-width="1" marker-start="url(#dim)" marker-end="url(#dim)"/><text transform="translate({},{}) rotate(-90)" font-size="12" fill="{LIMIT_LINE}" text-anchor="middle" stroke="#ffffff" stroke-width="3" paint-order="stroke">X travel {} mm (radius): x {} .. {}</text>"##,
        n(if right { xd + 14.0 } else { xd - 6.0 }),
        n((t + b) / 2.0),
        mm(x1 - x0),
        mm(x0),
        mm(x1),
        xd = n(xd),
        t = n(t),
        b = n(b)
    );
}

/// Home: the turret reference point, a cross in a circle, and the programmed point of the start
/// station's tool.
fn home_mark(o: &mut String, lb: &mut Labels<'_>, m: &Machine, tip: P2) {
    let v = lb.v;
    let (x, y) = (v.sx(m.home.y), v.sy(m.home.x));
    lb.taken.push((x - 50.0, y - 24.0, x + 8.0, y + 8.0));
    let _ = writeln!(
        o,
        r##"<circle cx="{x}" cy="{y}" r="6" fill="#ffffff" stroke="{LIMIT_LINE}" stroke-width="2"/><path d="M{a},{y}L{b},{y}M{x},{c}L{x},{d}" stroke="{LIMIT_LINE}" stroke-width="1.5"/><text x="{tx}" y="{ty}" font-size="12" font-weight="bold" fill="{LIMIT_LINE}" text-anchor="end" stroke="#ffffff" stroke-width="3" paint-order="stroke">home</text>"##,
        x = n(x),
        y = n(y),
        a = n(x - 9.0),
        b = n(x + 9.0),
        c = n(y - 9.0),
        d = n(y + 9.0),
        tx = n(x - 10.0),
        ty = n(y - 10.0)
    );
    let _ = writeln!(
        o,
        r##"<circle cx="{}" cy="{}" r="3.5" fill="#ffffff" stroke="{PATH_LINE}" stroke-width="2"/>"##,
        n(v.sx(tip.y)),
        n(v.sy(tip.x))
    );
}

/// The drum seen from the tailstock (looking toward `-z`): the spindle axis and the stock, the
/// drum's axis, and each station at its angle with the radial reach of its tool (from the
/// drum's axis, the nearest and farthest points of holder and insert), named. Returns the bottom.
fn end_view(o: &mut String, m: &Machine, top: f64) -> f64 {
    let left = 16.0;
    let size = END_VIEW;
    // The turret axis is `axis` above the reference point; at home the spindle axis is `home.x`
    // below the reference point.
    let axis_r = m.turret.axis;
    let reach = m
        .tools
        .iter()
        .flat_map(|t| {
            t.holder
                .points()
                .iter()
                .chain(t.insert.points())
                .map(move |p| (p.x + t.tip.x - axis_r).abs())
        })
        .fold(axis_r.abs(), f64::max);
    let spindle_d = m.home.x + axis_r; // spindle axis from the drum's axis, along -x
    let span = reach.max(1.0) * 1.4;
    let scale = (size / 2.0) / span;
    let (cx, cy) = (left + size / 2.0, top + size / 2.0 + 8.0);
    let _ = writeln!(
        o,
        r##"<rect x="{}" y="{}" width="{}" height="{}" fill="#fbfbfa" stroke="#d0d7de"/><text x="{}" y="{}" font-size="12" font-weight="bold" fill="{INK}">End view of the drum, seen from the tailstock (+X up): each station at its angle, start station toward the spindle</text>"##,
        n(left),
        n(top + 8.0),
        n(size),
        n(size),
        n(left),
        n(top + 2.0)
    );
    // The drum's rim through the reference point.
    let _ = writeln!(
        o,
        r#"<circle cx="{}" cy="{}" r="{}" fill="{TURRET_FILL}" stroke="{TURRET_LINE}" stroke-width="1.2"/>"#,
        n(cx),
        n(cy),
        n(axis_r.abs() * scale)
    );
    let _ = writeln!(
        o,
        r#"<path d="M{},{cy}L{},{cy}M{cx},{}L{cx},{}" stroke="{INK}" stroke-width="0.8" stroke-dasharray="10 3 2 3"/>"#,
        n(cx - 12.0),
        n(cx + 12.0),
        n(cy - 12.0),
        n(cy + 12.0),
        cx = n(cx),
        cy = n(cy)
    );
    // Where the spindle axis is (below, toward -x), when it is inside the panel.
    let sy = cy + spindle_d * scale;
    if sy < top + 8.0 + size - 6.0 {
        let r = m.stock.as_ref().map_or(3.0 / scale, |s| s.diameter / 2.0);
        let _ = writeln!(
            o,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{STOCK_FILL}" stroke="{STOCK_LINE}"/><text x="{}" y="{}" font-size="11" fill="{STOCK_LINE}">spindle axis</text>"#,
            n(cx),
            n(sy),
            n((r * scale).max(2.0)),
            n(cx + (r * scale).max(2.0) + 4.0),
            n(sy + 4.0)
        );
    } else {
        let _ = writeln!(
            o,
            r#"<text x="{}" y="{}" font-size="11" fill="{STOCK_LINE}">spindle axis {} mm below the drum's axis ↓</text>"#,
            n(left + 6.0),
            n(top + size + 2.0),
            mm(spindle_d)
        );
    }
    let stations = m.turret.stations.max(1);
    let start = m.turret.start_station as f64;
    for k in 1..=stations {
        // Station k stands (k − start) steps round from the working plane; the working plane's
        // tools point toward the spindle (down in this view). Counter-clockwise seen from the
        // tailstock for increasing station numbers.
        let a = (k as f64 - start) * std::f64::consts::TAU / stations as f64;
        let (dx, dy) = (a.sin(), a.cos()); // unit vector from the drum axis toward the station
        let tool = m.tool(k);
        let (near, far) = tool.map_or((axis_r, axis_r), |t| {
            let ds = t
                .holder
                .points()
                .iter()
                .chain(t.insert.points())
                .map(|p| axis_r - (p.x + t.tip.x));
            ds.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)))
        });
        let near = near.max(0.0);
        let p = |r: f64| (cx + dx * r * scale, cy + dy * r * scale);
        let (ax, ay) = p(near);
        let (bx, by) = p(far.max(near));
        let color = if tool.is_none() {
            "#8c959f"
        } else if k as f64 == start {
            HOLDER_LINE
        } else {
            OTHER_LINE
        };
        if tool.is_some() {
            let _ = writeln!(
                o,
                r#"<path d="M{},{}L{},{}" stroke="{color}" stroke-width="7" stroke-linecap="butt" opacity="0.85"/>"#,
                n(ax),
                n(ay),
                n(bx),
                n(by)
            );
        }
        let (lx, ly) = p(far.max(axis_r) + 14.0 / scale);
        let name = tool.map_or(format!("T{k:02} (empty)"), |_| format!("T{k:02}"));
        let anchor = if dx > 0.3 {
            "start"
        } else if dx < -0.3 {
            "end"
        } else {
            "middle"
        };
        let _ = writeln!(
            o,
            r##"<text x="{}" y="{}" font-size="12" font-weight="bold" fill="{color}" text-anchor="{anchor}" stroke="#fbfbfa" stroke-width="3" paint-order="stroke">{}</text>"##,
            n(lx),
            n(ly + 4.0),
            esc(&name)
        );
    }
    // The station list beside the end view: every tool's name and reach.
    let tx = left + size + 24.0;
    let mut y = top + 30.0;
    let _ = writeln!(
        o,
        r#"<text x="{}" y="{}" font-size="12" font-weight="bold" fill="{INK}">Station  tool  (tip from the turret reference point, mm)</text>"#,
        n(tx),
        n(y)
    );
    for t in &m.tools {
        y += 18.0;
        let _ = writeln!(
            o,
            r#"<text x="{}" y="{}" font-size="12" fill="{INK}">T{:02}  {}  (X{} Z{})</text>"#,
            n(tx),
            n(y),
            t.station,
            esc(&t.name),
            mm(t.tip.x),
            mm(t.tip.y)
        );
    }
    let _ = writeln!(
        o,
        r#"<text x="{}" y="{}" font-size="11" fill="{INK}">The end view has its own scale; the scale bar below is the main view's.</text>"#,
        n(tx),
        n(y + 24.0)
    );
    top + 8.0 + size
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn machine_drawing_names_every_station_and_the_travel() {
        let m = Machine::builtin();
        let svg = machine_drawing(&m, "machines/generic-slant-bed.toml");
        for k in 1..=8 {
            assert!(svg.contains(&format!(">T{k:02}")), "station {k} is named");
        }
        assert!(svg.contains("Z travel 650 mm: z -50 .. 600"), "{svg}");
        assert!(svg.contains("X travel 310 mm (radius): x -10 .. 300"));
        assert!(svg.contains(">home<"));
        assert_eq!(
            svg,
            machine_drawing(&m, "machines/generic-slant-bed.toml"),
            "deterministic"
        );
    }
}
