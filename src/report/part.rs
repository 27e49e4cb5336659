//! The final part as a job fragment for the next operation (`--stock-out part.toml`); its
//! drawing (`--stock-out part.svg`) is `part_svg`.

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
