//! True depth (DESIGN §4): a finding's `depth_mm` is the deepest penetration of the whole episode,
//! the same in step mode at any timestep and in exact mode, within the tolerance.

use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};

/// (line, kind, objects, time, depth) of a finding.
type Facts = (u32, String, Vec<String>, Option<f64>, Option<f64>);

fn facts(src: &[u8], s: Settings) -> Vec<Facts> {
    pipeline::check(src, &Machine::builtin(), &s)
        .findings
        .into_iter()
        .map(|f| (f.line, f.kind.to_string(), f.objects, f.time_s, f.depth_mm))
        .collect()
}

fn settings() -> Vec<(String, Settings)> {
    let mut v: Vec<(String, Settings)> = [0.1, 1.0, 10.0]
        .into_iter()
        .map(|dt| {
            (
                format!("step dt={dt}"),
                Settings {
                    dt_ms: dt,
                    ..Settings::default()
                },
            )
        })
        .collect();
    v.push((
        "exact".into(),
        Settings {
            mode: Mode::Exact,
            ..Settings::default()
        },
    ));
    v
}

#[test]
fn an_arc_dipping_into_the_jaw_face_is_deepest_mid_move_in_every_mode() {
    // The tip travels an arc of R10.3 about (r 35, z 10) in the machine frame, from r 26.93 to
    // r 43.07 at z 3.6: its lowest point, halfway, is 0.3 mm below the jaw face (z = 0), where
    // the T01 insert's tip corner is its lowest point. Depth 0.3 at mid-move, nowhere else.
    let src = b"G21 G18 G40 G97 G99\nT0101\nG97 S500 M3\nG0 X53.86 Z-60.\nG1 Z-74.4 F0.2\n\
G2 X86.14 Z-74.4 R10.3 F0.1\nG1 Z-60.\nG0 X200.\nM30\n";
    for (name, s) in settings() {
        let f = facts(src, s);
        assert_eq!(f.len(), 1, "{name}: {f:?}");
        assert_eq!(
            (f[0].0, &f[0].2[..]),
            (6, &["T01 insert".to_string(), "chuck".to_string()][..])
        );
        let d = f[0].4.unwrap();
        assert!((d - 0.3).abs() <= 0.01, "{name}: depth {d}, true 0.3");
    }
}

#[test]
fn every_crash_example_has_the_same_depth_and_time_at_any_timestep_and_in_exact_mode() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/programs");
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("crash_") && p.extension().unwrap() == "nc")
        .collect();
    names.sort();
    assert!(names.len() >= 6);
    for p in names {
        let src = std::fs::read(&p).unwrap();
        let all = settings();
        let base = facts(&src, all[all.len() - 1].1);
        assert!(!base.is_empty(), "{}", p.display());
        for (name, s) in &all {
            let got = facts(&src, *s);
            assert_eq!(
                got.len(),
                base.len(),
                "{} {name}: {got:?} vs exact {base:?}",
                p.display()
            );
            for (g, b) in got.iter().zip(&base) {
                assert_eq!((g.0, &g.1, &g.2), (b.0, &b.1, &b.2), "{} {name}", p.display());
                let (dg, db) = (g.4.unwrap(), b.4.unwrap());
                assert!(
                    (dg - db).abs() <= 0.01,
                    "{} {name}: depth {dg} vs exact {db}",
                    p.display()
                );
                let (tg, tb) = (g.3.unwrap(), b.3.unwrap());
                assert!(
                    (tg - tb).abs() <= 1e-3,
                    "{} {name}: time {tg} vs exact {tb}",
                    p.display()
                );
            }
        }
    }
}
