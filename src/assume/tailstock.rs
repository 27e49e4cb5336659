//! Whether the tailstock is in use (docs/assume.md, "The tailstock"): on a machine whose setup
//! is an example, the tailstock stays in use when the program calls for it (its M code, a
//! comment naming it) or turns a part too slender to stand without it; otherwise it is read as
//! not in use.

use super::reading::{Reading, SegKind};
use super::words::{numbered, split_comment};
use super::{set, Assumed, Assumption};
use crate::machine::{MAction, Machine};

/// A part this many times longer than its diameter needs the tailstock.
pub const SLENDER: f64 = 4.0;

/// Words of a comment that name the tailstock.
const WORDS: [&str; 7] = [
    "TAILSTOCK",
    "TAIL STOCK",
    "LIVE CENTER",
    "LIVE CENTRE",
    "QUILL",
    "REITSTOCK",
    "PINOLE",
];

/// Why the program needs the tailstock, if it does: the evidence and its line.
fn called_for(r: &Reading, machine: &Machine, diameter: f64) -> Option<(String, u32)> {
    for (i, line) in r.lines.iter().enumerate() {
        let (code, comment) = split_comment(&line);
        let n = i as u32 + 1;
        for m in numbered(&code, 'M') {
            let action = u16::try_from(m).ok().and_then(|c| machine.mcodes.action(c));
            if matches!(action, Some(MAction::TailstockAdvance)) {
                return Some((format!("M{m} advances it (line {n})"), n));
            }
        }
        let c = comment.to_uppercase();
        if let Some(w) = WORDS.iter().find(|w| c.contains(*w)) {
            return Some((format!("a comment names the {} (line {n})", w.to_lowercase()), n));
        }
    }
    let deepest = r
        .segs
        .iter()
        .filter(|s| s.kind == SegKind::Feed)
        .min_by(|a, b| a.b[1].min(a.a[1]).total_cmp(&b.b[1].min(b.a[1])))?;
    let depth = -deepest.a[1].min(deepest.b[1]);
    (diameter > 0.0 && depth > SLENDER * diameter).then(|| {
        (
            format!(
                "the part is turned {} mm long (line {}), over {SLENDER} times its diameter",
                crate::machine::num((depth * 10.0).round() / 10.0),
                deepest.line
            ),
            deepest.line,
        )
    })
}

/// Read whether the tailstock is in use; after [`super::bar::assume`] (it reads the bar).
pub fn assume(r: &Reading, file: &str, machine: &Machine, out: &mut Assumed) {
    if machine.tailstock.is_none() || !machine.assume_setup {
        return;
    }
    let stock = out.layer.stock.as_ref().map(|s| (s.value.diameter, s.value.front));
    let diameter = stock.map_or(machine.stock.as_ref().map_or(0.0, |s| s.diameter), |s| s.0);
    match called_for(r, machine, diameter) {
        Some((why, line)) => {
            // In use: with an assumed bar, its centre at the bar's face.
            if let Some((_, Some(front))) = stock {
                out.layer.tailstock_in_use = Some(set(true, file, line, "tailstock.in_use"));
                out.layer.tailstock_z = Some(set(front, file, line, "tailstock.z"));
                out.notes.push(Assumption {
                    key: "tailstock".into(),
                    value: "tailstock in use at the bar's face".into(),
                    reason: why,
                    line,
                    kept: false,
                });
            } else {
                out.notes.push(Assumption {
                    key: "tailstock".into(),
                    value: "tailstock as the machine file sets it".into(),
                    reason: why,
                    line,
                    kept: true,
                });
            }
        }
        None if machine.tailstock_advanced => {
            out.layer.tailstock_in_use = Some(set(false, file, 0, "tailstock.in_use"));
            out.notes.push(Assumption {
                key: "tailstock".into(),
                value: "no tailstock".into(),
                reason: "the program never calls for the tailstock (no M code or comment names it) and the part is short enough to stand in the chuck".into(),
                line: 0,
                kept: false,
            });
        }
        None => {}
    }
}
