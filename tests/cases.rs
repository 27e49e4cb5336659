//! Data-driven tests: every `*.nc` / `*.ngc` under `tests/cases/` and `programs/` is checked, and
//! its findings must equal the `.expected` file beside it.
//!
//! Expected-file format: one finding a line,
//! `LINE[:COL] KIND[ OBJECT, OBJECT][ follow-on of LINE| graze]`, sorted as latheguard reports them (by
//! line, then time); `# …` lines are comments. A case's first line may set options in a comment: `(test-case: machine=linuxcnc-small-lathe mode=exact dt=0.5 tolerance=0.01 clearance=0.2 min_depth=0.05)`
//! (named so that it does not look like a setting of the command, which reads only
//! `(latheguard: allow … -- reason)` comments);
//! `modes=step,exact` runs both modes and prefixes each expected line with the mode.
//! A case with a job beside it (`NAME.job.toml` for `NAME.nc`, as `latheguard check` reads it) is
//! checked with that job applied to its machine.
//! Cases under `tests/cases/{interp,comp,macro,cycles,cycles_lcnc,ops}/` also pin their interpreted motion in a `.moves` file
//! (`latheguard moves --format canon`).
//! Run with `UPDATE_EXPECT=1` to rewrite the expected files from the current output (then review
//! the diff: a test that is updated blindly proves nothing).

use crate::case_machine::{case_machine, with_case_job};
use latheguard::finding::{Kind, Severity};
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};
use std::fmt::Write;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn cases(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            // A folder with its own latheguard.toml is written for another machine
            // (programs/turn-mill: tests/turn_mill.rs checks it there).
            if !p.join("latheguard.toml").exists() {
                cases(&p, out);
            }
        } else if matches!(p.extension().and_then(|e| e.to_str()), Some("nc" | "ngc")) {
            out.push(p);
        }
    }
}

fn options(src: &[u8]) -> (Machine, Settings, Vec<Mode>) {
    let first = src.split(|&b| b == b'\n').next().unwrap_or(&[]);
    let first = String::from_utf8_lossy(first);
    let mut machine = Machine::builtin();
    let mut s = Settings::default();
    let mut modes = Vec::new();
    assert!(
        !first.contains("(latheguard: machine") && !first.contains("(latheguard: mode"),
        "case options are written `(test-case: …)` now: {first}"
    );
    if let Some(rest) = first.split("test-case:").nth(1) {
        for kv in rest.trim_end_matches([')', '\r', ' ']).split_whitespace() {
            let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
            match k {
                "machine" => machine = case_machine(&root(), v),
                // A machine with the extra axes of issue 15 (the kinematics given by hand until
                // machine files describe them): Y linear, C rotary, B linear, A rotary.
                "kin" if v == "turnmill" => {
                    machine.kinematics = Some(std::sync::Arc::new(turn_mill_kinematics()));
                }
                "mode" => s.mode = if v == "exact" { Mode::Exact } else { Mode::Step },
                "modes" => {
                    modes = v
                        .split(',')
                        .map(|m| if m == "exact" { Mode::Exact } else { Mode::Step })
                        .collect()
                }
                "dt" => s.dt_ms = v.parse().unwrap(),
                "tolerance" => s.tolerance_mm = v.parse().unwrap(),
                "clearance" => s.clearance_mm = v.parse().unwrap(),
                "min_depth" => s.min_depth_mm = Some(v.parse().unwrap()),
                other => panic!("unknown case option {other}"),
            }
        }
    }
    (machine, s, modes)
}

pub(crate) fn turn_mill_kinematics() -> latheguard::kin::Kinematics {
    use latheguard::kin::{Axis, AxisKind, Kinematics};
    use nalgebra::{Point3, Vector3};
    let axis = |name: &str, letter: char, linear: bool, dir: Vector3<f64>, rapid: f64| Axis {
        name: name.into(),
        letter,
        kind: if linear {
            AxisKind::Linear {
                dir: nalgebra::Unit::new_normalize(dir),
            }
        } else {
            AxisKind::Rotary {
                origin: Point3::origin(),
                dir: nalgebra::Unit::new_normalize(dir),
            }
        },
        zero: 0.0,
        travel: if linear {
            (-1000.0, 1000.0)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        },
        rapid,
        path: 1,
    };
    Kinematics {
        axes: vec![
            axis("x", 'X', true, Vector3::x(), 12000.0),
            axis("z", 'Z', true, Vector3::z(), 16000.0),
            axis("y", 'Y', true, Vector3::y(), 6000.0),
            axis("c", 'C', false, Vector3::z(), 36000.0),
            axis("sub_z", 'B', true, Vector3::z(), 12000.0),
            axis("a", 'A', false, Vector3::x(), 18000.0),
        ],
        ..Default::default()
    }
}

fn render(src: &[u8], machine: &Machine, settings: &Settings) -> String {
    let out = pipeline::check(src, machine, settings);
    let mut s = String::new();
    for f in &out.findings {
        let col = if f.col > 0 {
            format!(":{}", f.col)
        } else {
            String::new()
        };
        let objects = if f.objects.is_empty() {
            String::new()
        } else {
            format!(" {}", f.objects.join(", "))
        };
        let follow = match &f.follow_on {
            Some(p) => format!(" follow-on of {}", p.line),
            // A contact reported as a warning on its own: a graze (below min_depth).
            None if f.severity == Severity::Warning && f.depth_mm.is_some() && f.kind != Kind::RapidScrape => {
                " graze".to_string()
            }
            None => String::new(),
        };
        let _ = writeln!(s, "{}{col} {}{objects}{follow}", f.line, f.kind);
    }
    s
}

fn strip(expected: &str) -> String {
    expected
        .lines()
        .filter(|l| !l.trim_start().starts_with('#') && !l.trim().is_empty())
        .map(|l| format!("{}\n", l.trim_end()))
        .collect()
}

#[test]
fn every_case_reports_exactly_its_expected_findings() {
    let mut files = Vec::new();
    cases(&root().join("tests/cases"), &mut files);
    cases(&root().join("programs"), &mut files);
    files.sort();
    assert!(files.len() >= 10, "too few cases found: {}", files.len());
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let mut failures = Vec::new();
    for f in &files {
        let src = std::fs::read(f).unwrap();
        let (machine, settings, modes) = options(&src);
        let machine = with_case_job(machine, f);
        let got = if modes.is_empty() {
            render(&src, &machine, &settings)
        } else {
            // One block of findings per mode, each line prefixed by the mode.
            let mut all = String::new();
            for mode in modes {
                let name = if mode == Mode::Exact { "exact" } else { "step" };
                let s = Settings { mode, ..settings };
                for line in render(&src, &machine, &s).lines() {
                    all += &format!("{name}: {line}\n");
                }
            }
            all
        };
        let exp_path = f.with_extension("expected");
        let exp_text = std::fs::read_to_string(&exp_path).unwrap_or_default();
        // Cases in some folders also pin the interpreted motion (canonical calls).
        if f.components().any(|c| pins_moves(c.as_os_str())) {
            let (_, run) = pipeline::interpret(&src, &machine);
            let mut canon = Vec::new();
            latheguard::interp::canon::write(&run, &mut canon).unwrap();
            let canon = String::from_utf8(canon).unwrap();
            let moves_path = f.with_extension("moves");
            if update {
                std::fs::write(&moves_path, &canon).unwrap();
            } else if std::fs::read_to_string(&moves_path).unwrap_or_default() != canon {
                failures.push(format!(
                    "{}: moves differ from {}:\n{canon}",
                    f.display(),
                    moves_path.display()
                ));
            }
        }
        if update {
            let header: String = exp_text
                .lines()
                .filter(|l| l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect();
            std::fs::write(&exp_path, format!("{header}{got}")).unwrap();
            continue;
        }
        if strip(&exp_text) != got {
            failures.push(format!(
                "{}\n--- expected ({})\n{}--- got\n{}",
                f.display(),
                exp_path.display(),
                strip(&exp_text),
                got
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} cases differ:\n\n{}",
        failures.len(),
        files.len(),
        failures.join("\n")
    );
}

/// Cases in these folders also pin their interpreted motion in a `.moves` file.
fn pins_moves(dir: &std::ffi::OsStr) -> bool {
    ["interp", "comp", "macro", "cycles", "cycles_lcnc", "ops"]
        .iter()
        .any(|d| dir == *d)
}
