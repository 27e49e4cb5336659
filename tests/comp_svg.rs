//! `docs/comp-od.svg`, the picture in docs/comp.md: one OD profile as programmed, the path of the
//! nose centre with G42 (Fanuc start-up and corners, on the
//! comp test lathe, tool 4: tip 3, r 0.8), and the imaginary tip the control drives, with the nose
//! drawn at the end of every move. The test fails when the picture is out of date;
//! `UPDATE_EXPECT=1` rewrites it.

use latheguard::geom::P2;
use latheguard::interp::{Interpretation, MoveKind};
use latheguard::pipeline;
use std::fmt::Write;
use std::path::PathBuf;

const PROFILE: &str = "G99 G97 S500 M3\nF0.2\nT0404\nG0 X30 Z5\nG42 G1 X20 Z1\nZ-10\nX30 Z-15\nG2 X40 Z-20 R5\nG1 Z-30\nX50\nG40 G0 X60 Z5\nM30\n";
const R: f64 = 0.8;

fn interpret(text: &str) -> Interpretation {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let path = root.join("tests/machines/comp-fanuc-rear.toml");
    let m = latheguard::machine::from_toml(&std::fs::read_to_string(&path).unwrap(), "comp-fanuc-rear").unwrap();
    pipeline::interpret(text.as_bytes(), &m).1
}

/// Points along the feed moves (rapids left out), spindle frame.
fn feed_path(run: &Interpretation, shift: (f64, f64)) -> Vec<Vec<P2>> {
    let mut runs: Vec<Vec<P2>> = Vec::new();
    let mut open = false;
    for m in &run.moves {
        match m.kind {
            MoveKind::Line | MoveKind::Arc { .. } => {
                if !open {
                    runs.push(vec![m.start]);
                    open = true;
                }
                let n = if matches!(m.kind, MoveKind::Arc { .. }) { 24 } else { 1 };
                let cur = runs.last_mut().unwrap();
                for k in 1..=n {
                    cur.push(m.point_at(k as f64 / n as f64));
                }
            }
            _ => open = false,
        }
    }
    for r in &mut runs {
        for p in r.iter_mut() {
            *p = P2::new(p.x + shift.0, p.y + shift.1);
        }
    }
    runs
}

fn svg() -> String {
    let programmed = interpret(&PROFILE.replace("G42 ", "").replace("G40 ", ""));
    let comp = interpret(PROFILE);
    let (z0, z1, x0, x1, s) = (-34.0, 6.0, 7.0, 27.0, 24.0);
    let px = |p: P2| ((p.y - z0) * s, (x1 - p.x) * s);
    let (w, h) = ((z1 - z0) * s, (x1 - x0) * s);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w:.0}\" height=\"{h:.0}\" viewBox=\"0 0 {w:.0} {h:.0}\" font-family=\"sans-serif\" font-size=\"13\">"
    );
    let _ = writeln!(out, "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>");
    let poly = |out: &mut String, runs: &[Vec<P2>], style: &str| {
        for r in runs {
            let pts: Vec<String> = r
                .iter()
                .map(|p| {
                    let (a, b) = px(*p);
                    format!("{a:.2},{b:.2}")
                })
                .collect();
            let _ = writeln!(out, "<polyline fill=\"none\" {style} points=\"{}\"/>", pts.join(" "));
        }
    };
    poly(
        &mut out,
        &feed_path(&programmed, (0.0, 0.0)),
        "stroke=\"black\" stroke-width=\"2\"",
    );
    // Tip 3: the nose centre is the controlled point + (r, r).
    poly(
        &mut out,
        &feed_path(&comp, (R, R)),
        "stroke=\"#1f6fd1\" stroke-width=\"1.5\" stroke-dasharray=\"6 4\"",
    );
    poly(
        &mut out,
        &feed_path(&comp, (0.0, 0.0)),
        "stroke=\"#d1331f\" stroke-width=\"1.5\"",
    );
    for m in comp
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MoveKind::Line | MoveKind::Arc { .. }))
    {
        let (a, b) = px(P2::new(m.end.x + R, m.end.y + R));
        let _ = writeln!(
            out,
            "<circle cx=\"{a:.2}\" cy=\"{b:.2}\" r=\"{:.2}\" fill=\"none\" stroke=\"#1f6fd1\" stroke-width=\"0.8\"/>",
            R * s
        );
    }
    let legend = [
        ("black", "programmed profile (X20 Z1 … X50 Z-30)"),
        (
            "#1f6fd1",
            "nose centre with G42, r 0.8 (circles: the nose at each move's end)",
        ),
        (
            "#d1331f",
            "imaginary tip, tip code 3: the controlled point latheguard checks",
        ),
    ];
    for (i, (c, t)) in legend.iter().enumerate() {
        let y = h - 84.0 + 18.0 * i as f64;
        let _ = writeln!(
            out,
            "<line x1=\"10\" y1=\"{y:.0}\" x2=\"40\" y2=\"{y:.0}\" stroke=\"{c}\" stroke-width=\"2\"/><text x=\"46\" y=\"{:.0}\">{t}</text>",
            y + 4.0
        );
    }
    let _ = writeln!(
        out,
        "<text x=\"10\" y=\"{:.0}\">+Z →   (+X up, radius in mm; Fanuc, rear turret)</text>",
        h - 10.0
    );
    out.push_str("</svg>\n");
    out
}

#[test]
fn comp_picture_in_the_docs_is_current() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/comp-od.svg");
    let got = svg();
    assert!(got.matches("<polyline").count() >= 3, "a path is missing:\n{got}");
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::write(&path, &got).unwrap();
        return;
    }
    let want = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        want == got,
        "docs/comp-od.svg is out of date: run with UPDATE_EXPECT=1 and review it"
    );
}
