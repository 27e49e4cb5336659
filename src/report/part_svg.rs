//! The final part as a drawing (`--stock-out part.svg`): its section mirrored about the spindle
//! axis, z to the right, with the main dimensions a machinist's drawing gives (`part_dims`): each
//! step's diameter and the bore's as vertical dimension lines whose labels stand above the part in
//! staggered rows (no two labels overlap, no leader crosses a label), and below it the z of each
//! shoulder and of each bore's end measured from the front face, one row each, the overall length
//! last. Labels carry a white halo drawn as its own element (`svg::split_halos`), so every
//! renderer shows them.
//!
//! Output is a pure function of its input: identical runs give identical files.

use std::fmt::Write;

use super::part_dims::Dims;
use super::svg::{split_halos, HALO, INK, STOCK_FILL, STOCK_LINE};
use crate::pipeline::FinalPart;

const WIDTH: f64 = 900.0;
/// Left and right margin, px: a length's label may stand beside its line there, and a diameter's
/// label stands to the right of its leader.
const MARGIN: f64 = 60.0;
const MARGIN_RIGHT: f64 = 120.0;
/// From a diameter's leader to its label, px.
const LABEL_GAP: f64 = 3.0;
/// Height of the title and the caption, px.
const HEAD: f64 = 66.0;
/// The tallest the part's section is drawn, px.
const MAX_SECTION: f64 = 320.0;
/// Rows of the diameters' labels above the part and of the lengths below it, px apart.
const TOP_ROW: f64 = 17.0;
const LENGTH_ROW: f64 = 20.0;
/// Dimension lines and their labels.
const DIM: &str = "#24292f";
const FONT: f64 = 12.0;

/// The drawing of the final part: `outlines` every piece of material (`[x, z]`, x ≥ 0), `part`
/// the one dimensioned (the part the next operation takes, `pipeline::FinalPart`); `title` names
/// the program.
pub fn part_svg(title: &str, outlines: &[Vec<[f64; 2]>], part: Option<&FinalPart>) -> String {
    let (mut zmin, mut zmax, mut rmax) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for p in outlines.iter().flatten() {
        zmin = zmin.min(p[1]);
        zmax = zmax.max(p[1]);
        rmax = rmax.max(p[0]);
    }
    if !zmin.is_finite() || zmax - zmin < 1e-9 {
        (zmin, zmax, rmax) = (0.0, 1.0, 1.0);
    }
    let rmax = rmax.max(1e-6);
    let pw = WIDTH - MARGIN - MARGIN_RIGHT;
    let scale = (pw / (zmax - zmin)).min(MAX_SECTION / (2.0 * rmax));
    let x0 = MARGIN + (pw - (zmax - zmin) * scale) / 2.0;
    let px = |z: f64| x0 + (z - zmin) * scale;
    let dims = part.and_then(|p| Dims::of(&p.outline).map(|d| (p, d)));

    // Above the part: the diameters' labels in rows, placed before anything is drawn (the rows
    // set where the part stands).
    let diameters = dims.as_ref().map_or_else(Vec::new, |(_, d)| diameter_marks(d));
    let widths: Vec<f64> = diameters.iter().map(|m| text_width(&m.text)).collect();
    let xs: Vec<f64> = diameters.iter().map(|m| px(m.z)).collect();
    let rows = stagger(&xs, &widths);
    let top_rows = rows.iter().map(|r| r + 1).max().unwrap_or(0) as f64;
    let top = HEAD + 8.0 + top_rows * TOP_ROW + 6.0;
    let cy = top + rmax * scale;
    let py = |r: f64| cy - r * scale;
    let bottom = py(-rmax);
    let lengths = dims
        .as_ref()
        .map_or_else(Vec::new, |(p, d)| length_marks(d, &p.outline));
    // The lengths' rows: the first clear of the part's lowest edge.
    let row_y = |i: usize| bottom + 22.0 + i as f64 * LENGTH_ROW;
    let h = (row_y(lengths.len()) + 24.0).ceil();

    let mut o = String::new();
    let _ = writeln!(o, r#"<rect width="{WIDTH}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        o,
        r#"<text x="{MARGIN}" y="26" font-size="16" font-weight="bold" fill="{INK}">{}</text>"#,
        esc(title)
    );
    let which = match part {
        Some(p) if p.parted_off => "the piece the part-off cut off is dimensioned; ",
        _ => "",
    };
    let _ = writeln!(
        o,
        r##"<text x="{MARGIN}" y="44" font-size="13" fill="#57606a">final part section, mm: z to the right, both sides of the spindle axis; {which}Ø diameters,</text>"##
    );
    let _ = writeln!(
        o,
        r##"<text x="{MARGIN}" y="60" font-size="13" fill="#57606a">lengths below the part from its front face (right) to each shoulder and to the end of each bore</text>"##
    );
    for side in [1.0, -1.0] {
        for piece in outlines {
            let d: Vec<String> = piece
                .iter()
                .map(|p| format!("{:.2},{:.2}", px(p[1]), py(side * p[0])))
                .collect();
            let _ = writeln!(
                o,
                r#"<polygon points="{}" fill="{STOCK_FILL}" stroke="{STOCK_LINE}" stroke-width="1"/>"#,
                d.join(" ")
            );
        }
    }
    let _ = writeln!(
        o,
        r##"<line x1="{:.2}" y1="{cy:.2}" x2="{:.2}" y2="{cy:.2}" stroke="#333" stroke-width="0.8" stroke-dasharray="12 3 2 3"/>"##,
        MARGIN / 2.0,
        WIDTH - MARGIN_RIGHT + MARGIN / 2.0
    );
    for ((m, &row), (&x, &w)) in diameters.iter().zip(&rows).zip(xs.iter().zip(&widths)) {
        let base = top - 6.0 - row as f64 * TOP_ROW;
        let (ya, yb) = (py(m.r), py(-m.r));
        // The dimension line across the section, its leader up to the label's row and a
        // landing under the label.
        let _ = writeln!(
            o,
            r#"<path d="M{x:.2},{yb:.2}L{x:.2},{:.2}L{:.2},{:.2}" stroke="{DIM}" stroke-width="0.8" fill="none"/>{}{}"#,
            base + 3.0,
            x + LABEL_GAP + w,
            base + 3.0,
            arrow(x, ya, -1.0),
            arrow(x, yb, 1.0),
        );
        let _ = writeln!(
            o,
            r#"<text x="{:.2}" y="{base:.2}" font-size="{FONT}" fill="{DIM}" {HALO}>{}</text>"#,
            x + LABEL_GAP,
            esc(&m.text)
        );
    }
    if let Some((p, d)) = &dims {
        let front = px(d.zmax);
        let _ = writeln!(
            o,
            r#"<path d="M{front:.2},{:.2}L{front:.2},{:.2}" stroke="{DIM}" stroke-width="0.6"/>"#,
            py(-d.outer_at(&p.outline, d.zmax)) + 3.0,
            row_y(lengths.len().saturating_sub(1)) + 5.0
        );
        for (i, l) in lengths.iter().enumerate() {
            let y = row_y(i);
            let x = px(l.z);
            let _ = writeln!(
                o,
                r#"<path d="M{x:.2},{:.2}L{x:.2},{:.2}M{x:.2},{y:.2}L{front:.2},{y:.2}" stroke="{DIM}" stroke-width="0.6"/>{}{}"#,
                py(-l.from_r) + 3.0,
                y + 5.0,
                arrow_h(x, y, -1.0),
                arrow_h(front, y, 1.0),
            );
            let w = text_width(&l.text);
            let (tx, anchor) = if w + 8.0 <= front - x {
                ((x + front) / 2.0, "middle")
            } else if x - 5.0 - w >= 4.0 {
                (x - 5.0, "end")
            } else {
                (front + 5.0, "start")
            };
            let _ = writeln!(
                o,
                r#"<text x="{tx:.2}" y="{:.2}" font-size="{FONT}" fill="{DIM}" text-anchor="{anchor}" {HALO}>{}</text>"#,
                y - 4.0,
                esc(&l.text)
            );
        }
    }
    let bar = nice((zmax - zmin) / 5.0);
    let (bx, by) = (MARGIN, h - 14.0);
    let _ = writeln!(
        o,
        r#"<line x1="{bx}" y1="{by}" x2="{:.2}" y2="{by}" stroke="{INK}" stroke-width="2"/><text x="{:.2}" y="{:.2}" font-size="12" fill="{INK}">{bar} mm</text>"#,
        bx + bar * scale,
        bx + bar * scale + 6.0,
        by + 4.0
    );
    let mut svg = format!(
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{h}" viewBox="0 0 {WIDTH} {h}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">"#
    );
    svg.push('\n');
    svg.push_str(&split_halos(&o));
    svg.push_str("</svg>\n");
    svg
}

/// A diameter to draw: a vertical dimension line across the section at `z`, between `±r`.
struct Mark {
    z: f64,
    r: f64,
    text: String,
}

/// The diameters: each step's in the middle of the step, each bore step's a third of the way in
/// (clear of an outer step's line over the same stretch), and the largest diameter where the
/// outline reaches it when no step has it (a part that is largest on a taper or a radius).
fn diameter_marks(d: &Dims) -> Vec<Mark> {
    let mut marks: Vec<Mark> = d
        .steps
        .iter()
        .map(|s| Mark {
            z: 0.5 * (s.z0 + s.z1),
            r: s.r,
            text: format!("Ø{}", fmt(2.0 * s.r)),
        })
        .collect();
    if !d.steps.iter().any(|s| (s.r - d.rmax).abs() <= 1e-3) {
        marks.push(Mark {
            z: d.rmax_at,
            r: d.rmax,
            text: format!("Ø{} max", fmt(2.0 * d.rmax)),
        });
    }
    marks.extend(d.bores.iter().map(|s| Mark {
        z: s.z0 + (s.z1 - s.z0) / 3.0,
        r: s.r,
        text: format!("Ø{} bore", fmt(2.0 * s.r)),
    }));
    marks.sort_by(|a, b| a.z.total_cmp(&b.z));
    marks
}

/// A length below the part: from the front face to `z`, the extension line at `z` starting at
/// the radius `from_r`.
struct Length {
    z: f64,
    from_r: f64,
    text: String,
}

/// The shoulders' and the bores' ends' distances from the front face, shortest first (nearest
/// the part), one per distance, then the overall length.
fn length_marks(d: &Dims, outline: &[[f64; 2]]) -> Vec<Length> {
    let mut out: Vec<Length> = d
        .shoulders
        .iter()
        .map(|&z| (z, d.outer_at(outline, z)))
        .chain(d.bores.iter().filter(|b| b.z0 > d.zmin + 0.05).map(|b| (b.z0, b.r)))
        .map(|(z, from_r)| Length {
            z,
            from_r,
            text: fmt(d.zmax - z),
        })
        .collect();
    out.sort_by(|a, b| b.z.total_cmp(&a.z));
    out.dedup_by(|a, b| a.text == b.text);
    out.retain(|l| l.z > d.zmin + 1e-6);
    out.push(Length {
        z: d.zmin,
        from_r: d.outer_at(outline, d.zmin),
        text: fmt(d.zmax - d.zmin),
    });
    out
}

/// The row of each label (0 nearest the part). A label stands to the right of its leader, which
/// rises straight from the part at `xs[i]`; `widths[i]` is its width. Taken from right to left,
/// each gets the lowest row where it overlaps no label of that row and no leader of a higher row
/// crosses it; labels of lower rows stand to its right, so its own leader crosses none of them
/// (two leaders at one x: the later label goes higher).
fn stagger(xs: &[f64], widths: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..xs.len()).collect();
    order.sort_by(|&a, &b| xs[b].total_cmp(&xs[a]).then(a.cmp(&b)));
    let mut rows = vec![0; xs.len()];
    let mut placed: Vec<(f64, f64, usize)> = Vec::new(); // (left, right, row) of each label's box
    for i in order {
        let (l, r) = (xs[i] - 2.0, xs[i] + LABEL_GAP + widths[i] + 2.0);
        let row = (0..=placed.len())
            .find(|&k| {
                placed.iter().all(|&(pl, pr, pk)| {
                    let same_row = pk == k && pl < r && l < pr;
                    // A higher row's leader (at its box's left) through this box.
                    let crossed = pk > k && l <= pl + 2.0 && pl + 2.0 <= r;
                    // This leader through a lower row's box.
                    let crosses = pk < k && pl <= xs[i] && xs[i] <= pr;
                    !same_row && !crossed && !crosses
                })
            })
            .unwrap_or(placed.len());
        placed.push((l, r, row));
        rows[i] = row;
    }
    rows
}

/// A text's width at [`FONT`], px (DejaVu Sans's digits are 0.64 em; a little over).
fn text_width(t: &str) -> f64 {
    t.chars().count() as f64 * FONT * 0.66
}

/// An arrowhead on a vertical line, its tip at `(x, y)`, pointing up (`dir` −1) or down (+1).
fn arrow(x: f64, y: f64, dir: f64) -> String {
    let b = y - dir * 7.0;
    format!(
        r#"<path d="M{x:.2},{y:.2}L{:.2},{b:.2}L{:.2},{b:.2}Z" fill="{DIM}"/>"#,
        x - 2.5,
        x + 2.5
    )
}

/// An arrowhead on a horizontal line, its tip at `(x, y)`, pointing left (`dir` −1) or right.
fn arrow_h(x: f64, y: f64, dir: f64) -> String {
    let b = x - dir * 7.0;
    format!(
        r#"<path d="M{x:.2},{y:.2}L{b:.2},{:.2}L{b:.2},{:.2}Z" fill="{DIM}"/>"#,
        y - 2.5,
        y + 2.5
    )
}

/// A length or diameter to the hundredth of a millimetre, without trailing zeros.
fn fmt(v: f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    if r == 0.0 {
        "0".to_string()
    } else {
        format!("{r}")
    }
}

fn nice(v: f64) -> f64 {
    let p = 10f64.powf(v.max(1e-6).log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * p)
        .find(|c| *c >= v)
        .unwrap_or(10.0 * p)
}

/// Text for XML: markup escaped, control characters (not allowed in XML 1.0) as spaces.
fn esc(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn od_turned() -> FinalPart {
        FinalPart {
            outline: vec![
                [0.0, -40.0],
                [25.0, -40.0],
                [25.0, 37.995],
                [20.388299, 38.005],
                [20.110382, 38.125],
                [20.0, 38.425],
                [20.0, 77.325],
                [19.779347, 78.0],
                [0.0, 78.0],
            ],
            ..FinalPart::default()
        }
    }

    /// The letters of each label (its second element: the first is its halo).
    fn labels(svg: &str) -> Vec<String> {
        let doc = roxmltree::Document::parse(svg).unwrap();
        doc.descendants()
            .filter(|n| n.has_tag_name("text") && n.attribute("stroke").is_none())
            .filter_map(|n| n.text().map(str::to_string))
            .collect()
    }

    #[test]
    fn a_turned_bar_is_drawn_with_its_diameters_its_shoulder_and_its_length() {
        let part = od_turned();
        let svg = part_svg("od_turning.nc", std::slice::from_ref(&part.outline), Some(&part));
        let l = labels(&svg);
        for want in ["Ø40", "Ø50", "40", "118"] {
            assert!(l.iter().any(|t| t == want), "{want} not in {l:?}");
        }
        assert!(!svg.contains("paint-order"), "halos are elements of their own");
        assert_eq!(svg.matches("<polygon").count(), 2);
        // Every halo is followed by its letters.
        let halos = svg.matches(r##"stroke-linejoin="round""##).count();
        assert_eq!(halos, 4, "{svg}");
    }

    #[test]
    fn labels_in_one_row_never_overlap_and_leaders_cross_none() {
        // Twelve labels 10 px apart, 40 px wide: they need several rows.
        let xs: Vec<f64> = (0..12).map(|i| 100.0 + 10.0 * i as f64).collect();
        let ws = vec![40.0; 12];
        let rows = stagger(&xs, &ws);
        let boxed = |i: usize| (xs[i], xs[i] + LABEL_GAP + ws[i]);
        for i in 0..12 {
            for j in 0..12 {
                if i == j {
                    continue;
                }
                let ((li, ri), (lj, rj)) = (boxed(i), boxed(j));
                if rows[i] == rows[j] {
                    assert!(ri <= lj || rj <= li, "{i} and {j} overlap: {rows:?}");
                }
                if rows[j] > rows[i] {
                    // j's leader passes through i's row: not through i's label.
                    assert!(xs[j] < li || xs[j] > ri, "{j}'s leader crosses {i}: {rows:?}");
                }
            }
        }
        assert!(*rows.iter().max().unwrap() < 12);
        // Labels far apart share the row next to the part.
        assert_eq!(stagger(&[100.0, 300.0, 500.0], &[40.0; 3]), vec![0, 0, 0]);
    }

    #[test]
    fn no_part_draws_the_section_alone() {
        let svg = part_svg("p.nc", &[], None);
        assert!(roxmltree::Document::parse(&svg).is_ok());
        assert!(labels(&svg).iter().all(|t| !t.starts_with('Ø')));
    }
}
