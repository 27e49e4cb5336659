//! The final part: a drawing of the stock's section at the end of a program (`--stock-out
//! part.svg`), or the part as a job fragment for the next operation (`--stock-out part.toml`).

use crate::pipeline::FinalPart;
use std::fmt::Write;

/// The part as a job fragment: `[stock] outline = [...]` with comments saying which program made
/// it and what it is, for the next operation's job to read with `[stock] from` (docs/job.md,
/// "Operations"). Coordinates are rounded to the µm/1000 (six decimals), as the JSON report's.
pub fn part_toml(program: &str, part: &FinalPart) -> String {
    let mut s = String::new();
    let (mut zmin, mut zmax, mut rmax) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for p in &part.outline {
        zmin = zmin.min(p[1]);
        zmax = zmax.max(p[1]);
        rmax = rmax.max(p[0]);
    }
    let one_line = program.replace(['\n', '\r'], " ");
    let _ = writeln!(s, "# The part made by {one_line} (latheguard check --stock-out).");
    let _ = writeln!(
        s,
        "# Spindle frame of that check, mm: x a radius, z from the jaw faces; Ø{} max, z {} .. {}.",
        crate::machine::num(2.0 * rmax),
        crate::machine::num(zmin),
        crate::machine::num(zmax)
    );
    if part.parted_off {
        let _ = writeln!(
            s,
            "# The piece the part-off cut off; the bar left in the jaws is not written."
        );
    } else {
        let _ = writeln!(s, "# The whole stock (no part-off).");
    }
    if part.pieces_left_out > 0 {
        let _ = writeln!(
            s,
            "# Its largest piece of material; {} smaller piece(s) of it are left out.",
            part.pieces_left_out
        );
    }
    let _ = writeln!(
        s,
        "# The next operation's job reads it with `[stock] from = \"FILE\"` (turned round: `reverse = true`\n# and `grip` or `front`; docs/job.md, \"Operations\")."
    );
    let _ = writeln!(s, "[stock]");
    let _ = writeln!(s, "outline = [");
    for chunk in part.outline.chunks(6) {
        let pts: Vec<String> = chunk
            .iter()
            .map(|p| format!("[{}, {}]", short(p[0]), short(p[1])))
            .collect();
        let _ = writeln!(s, "  {},", pts.join(", "));
    }
    let _ = writeln!(s, "]");
    s
}

/// A coordinate with at most six decimals, `-0` as `0`, always with a decimal point (TOML floats).
fn short(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    let r = if r == 0.0 { 0.0 } else { r };
    let t = format!("{r}");
    if t.contains(['.', 'e', 'E']) {
        t
    } else {
        format!("{t}.0")
    }
}

/// An SVG of the part's section: the outlines (`[x, z]`, x ≥ 0) mirrored about the spindle axis,
/// z to the right, a centre line, a scale bar and a caption.
pub fn part_svg(title: &str, outlines: &[Vec<[f64; 2]>]) -> String {
    let (w, h, margin, head) = (900.0, 520.0, 40.0, 50.0);
    let (mut zmin, mut zmax, mut rmax) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    for o in outlines {
        for p in o {
            zmin = zmin.min(p[1]);
            zmax = zmax.max(p[1]);
            rmax = rmax.max(p[0]);
        }
    }
    if !zmin.is_finite() {
        (zmin, zmax, rmax) = (0.0, 1.0, 1.0);
    }
    let (pw, ph) = (w - 2.0 * margin, h - head - 2.0 * margin);
    let scale = (pw / (zmax - zmin).max(1e-9)).min(ph / (2.0 * rmax).max(1e-9));
    let cx = margin + (pw - (zmax - zmin) * scale) / 2.0;
    let cy = head + margin + ph / 2.0;
    let x = |z: f64| cx + (z - zmin) * scale;
    let y = |r: f64| cy - r * scale;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="13">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(
        s,
        r#"<text x="{margin}" y="26" font-size="16" font-weight="bold">{}</text>"#,
        esc(title)
    );
    let _ = writeln!(
        s,
        r##"<text x="{margin}" y="44" fill="#555">final part section: z to the right (0 at the jaw faces), x up, both sides of the spindle axis</text>"##
    );
    for side in [1.0, -1.0] {
        for o in outlines {
            let d: Vec<String> = o
                .iter()
                .map(|p| format!("{:.2},{:.2}", x(p[1]), y(side * p[0])))
                .collect();
            let _ = writeln!(
                s,
                r##"<polygon points="{}" fill="#b7c9dd" stroke="#5a7896" stroke-width="1"/>"##,
                d.join(" ")
            );
        }
    }
    let _ = writeln!(
        s,
        r##"<line x1="{:.2}" y1="{cy:.2}" x2="{:.2}" y2="{cy:.2}" stroke="#333" stroke-dasharray="12 3 2 3"/>"##,
        margin,
        w - margin
    );
    let bar = nice((zmax - zmin) / 5.0);
    let (bx, by) = (margin, h - 14.0);
    let _ = writeln!(
        s,
        r##"<line x1="{bx}" y1="{by}" x2="{:.2}" y2="{by}" stroke="#333" stroke-width="2"/><text x="{:.2}" y="{:.2}">{bar} mm</text>"##,
        bx + bar * scale,
        bx + bar * scale + 6.0,
        by + 4.0
    );
    s.push_str("</svg>\n");
    s
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
}
