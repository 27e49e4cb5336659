//! The whole scene and program shifted by 1e7 mm along the spindle axis give the same findings:
//! every computation that matters is done relative to a local origin.

use latheguard::geom::{Polygon, P2};
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};

const SHIFT: f64 = 1e7;

fn shifted(p: &Polygon) -> Polygon {
    let pts: Vec<P2> = p.points().iter().map(|q| P2::new(q.x, q.y + SHIFT)).collect();
    Polygon::new(&pts).unwrap()
}

fn shifted_machine() -> Machine {
    let mut m = Machine::builtin();
    m.chuck = m.chuck.as_ref().map(shifted);
    m.tailstock = m.tailstock.as_ref().map(shifted);
    if let Some(s) = m.stock.as_mut() {
        s.front += SHIFT;
    }
    m.program_zero_z += SHIFT;
    m.z.min += SHIFT;
    m.z.max += SHIFT;
    m.home.y += SHIFT;
    m
}

/// (line, end line, kind, objects, time, x, z), times and coordinates in units of 1e-4.
type Row = (u32, u32, String, Vec<String>, i64, i64, i64);

fn summary(src: &[u8], m: &Machine, mode: Mode) -> Vec<Row> {
    let s = Settings {
        mode,
        ..Settings::default()
    };
    let q = |v: Option<f64>| (v.unwrap_or(0.0) * 1e4).round() as i64; // 0.1 um, 0.1 ms
    pipeline::check(src, m, &s)
        .findings
        .into_iter()
        .map(|f| {
            (
                f.line,
                f.end_line,
                f.kind.name().to_string(),
                f.objects,
                q(f.time_s),
                q(f.x),
                q(f.z),
            )
        })
        .collect()
}

#[test]
fn every_program_gives_identical_findings_when_shifted_by_1e7_mm() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/programs");
    let base = Machine::builtin();
    let far = shifted_machine();
    let mut files: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().map(|e| e.path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "nc"));
    files.sort();
    let mut crashes = 0;
    for f in &files {
        let src = std::fs::read(f).unwrap();
        for mode in [Mode::Step, Mode::Exact] {
            let a = summary(&src, &base, mode);
            let b = summary(&src, &far, mode);
            crashes += a.len();
            assert_eq!(a, b, "{} ({mode:?}) differs when shifted by {SHIFT} mm", f.display());
        }
    }
    assert!(crashes >= 10, "the programs should crash somewhere: {crashes} findings");
}
