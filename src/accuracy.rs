//! The cost of accuracy (docs/checking.md): one program in exact mode and in step mode at several
//! timesteps and tolerances, with what each setting costs and what it misses.
//!
//! Exact mode at a tolerance is the reference for the step runs at that tolerance. A reference
//! finding (collision, rapid_into_stock, spindle_stopped) is *found* by a step run when that run
//! reports the same kind and parts in an episode whose lines overlap it; otherwise it is
//! *missed*. *Lag* is how far the turret reference point travelled (straight-line distance)
//! between the true first contact and the step run's first detection.

use crate::finding::{Finding, Kind};
use crate::machine::Machine;
use crate::motion::{self, Timeline};
use crate::pipeline::{self, Mode, Settings};
use serde::Serialize;
use std::fmt::Write;
use std::time::Instant;

/// Timesteps of the table, ms.
pub const DTS: [f64; 6] = [10.0, 5.0, 2.0, 1.0, 0.5, 0.1];
/// Tolerances of the table, mm.
pub const TOLERANCES: [f64; 3] = [0.1, 0.01, 0.001];

/// One setting's result.
#[derive(Clone, Debug, Serialize)]
pub struct Row {
    pub mode: Mode,
    /// ms; `None` for exact mode.
    pub dt_ms: Option<f64>,
    pub tolerance_mm: f64,
    /// Median wall time of the check, ms.
    pub run_ms: f64,
    pub findings: usize,
    /// Collision-type findings of this run.
    pub collisions: usize,
    /// Reference collisions this run did not find (0 for exact mode).
    pub missed: usize,
    /// Largest travel between true first contact and detection, mm.
    pub max_lag_mm: f64,
    pub steps: u64,
}

fn is_crash(k: Kind) -> bool {
    matches!(k, Kind::Collision | Kind::RapidIntoStock | Kind::SpindleStopped)
}

fn timed(src: &[u8], machine: &Machine, s: &Settings, repeats: usize) -> (pipeline::Outcome, f64) {
    let mut times = Vec::with_capacity(repeats);
    let mut out = None;
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let o = pipeline::check(src, machine, s);
        times.push(t.elapsed().as_secs_f64() * 1000.0);
        out = Some(o);
    }
    times.sort_by(f64::total_cmp);
    (out.unwrap(), times[times.len() / 2])
}

/// Run the whole table. `repeats` runs of each setting give its median time.
pub fn run(src: &[u8], machine: &Machine, clearance_mm: f64, min_depth_mm: Option<f64>, repeats: usize) -> Vec<Row> {
    let (prog, interp) = pipeline::interpret(src, machine);
    let _ = prog;
    let timeline = motion::timeline(&interp, machine);
    let mut rows = Vec::new();
    for &tol in &TOLERANCES {
        let base = Settings {
            mode: Mode::Exact,
            dt_ms: 1.0,
            tolerance_mm: tol,
            clearance_mm,
            min_depth_mm,
            snapshots: false,
            part_mesh: false,
            ..Settings::default()
        };
        let (exact, ms) = timed(src, machine, &base, repeats);
        let reference: Vec<&Finding> = exact.findings.iter().filter(|f| is_crash(f.kind)).collect();
        rows.push(Row {
            mode: Mode::Exact,
            dt_ms: None,
            tolerance_mm: tol,
            run_ms: ms,
            findings: exact.findings.len(),
            collisions: reference.len(),
            missed: 0,
            max_lag_mm: 0.0,
            steps: exact.stats.steps,
        });
        for &dt in &DTS {
            let s = Settings {
                mode: Mode::Step,
                dt_ms: dt,
                ..base
            };
            let (out, ms) = timed(src, machine, &s, repeats);
            let mine: Vec<&Finding> = out.findings.iter().filter(|f| is_crash(f.kind)).collect();
            let mut missed = 0;
            let mut lag: f64 = 0.0;
            for r in &reference {
                let hit = mine
                    .iter()
                    .filter(|f| {
                        f.kind == r.kind && f.objects == r.objects && f.line <= r.end_line && r.line <= f.end_line
                    })
                    .min_by(|a, b| a.time_s.unwrap_or(0.0).total_cmp(&b.time_s.unwrap_or(0.0)));
                match hit {
                    None => missed += 1,
                    Some(f) => {
                        let (t0, t1) = (r.time_s.unwrap_or(0.0), f.time_s.unwrap_or(0.0));
                        lag = lag.max(travel(&interp.moves, &timeline, t0, t1));
                    }
                }
            }
            rows.push(Row {
                mode: Mode::Step,
                dt_ms: Some(dt),
                tolerance_mm: tol,
                run_ms: ms,
                findings: out.findings.len(),
                collisions: mine.len(),
                missed,
                max_lag_mm: lag,
                steps: out.stats.steps,
            });
        }
    }
    rows
}

/// Straight-line distance between the turret reference point at two times.
fn travel(moves: &[crate::interp::Move], tl: &Timeline, a: f64, b: f64) -> f64 {
    let at = |t: f64| {
        let i = tl
            .items
            .partition_point(|it| it.t1() < t)
            .min(tl.items.len().saturating_sub(1));
        tl.items
            .get(i)
            .map(|it| motion::reference_at(&moves[it.index], it, t - it.t0))
    };
    match (at(a), at(b)) {
        (Some(p), Some(q)) => (q - p).norm(),
        _ => 0.0,
    }
}

/// The table as text; without `timing` the run-time column shows `-`.
pub fn table(rows: &[Row], timing: bool) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<6} {:>8} {:>10} {:>10} {:>9} {:>10} {:>7} {:>10} {:>10}",
        "mode", "dt ms", "tol mm", "run ms", "findings", "collisions", "missed", "lag mm", "steps"
    );
    for r in rows {
        let mode = match r.mode {
            Mode::Exact => "exact",
            Mode::Step => "step",
        };
        let dt = r.dt_ms.map_or("-".to_string(), |d| format!("{d}"));
        let run = if timing {
            format!("{:.2}", r.run_ms)
        } else {
            "-".to_string()
        };
        let _ = writeln!(
            s,
            "{:<6} {:>8} {:>10} {:>10} {:>9} {:>10} {:>7} {:>10.3} {:>10}",
            mode, dt, r.tolerance_mm, run, r.findings, r.collisions, r.missed, r.max_lag_mm, r.steps
        );
    }
    s
}

/// A plot of run time (log scale) against missed collisions, one point per setting, as SVG.
pub fn plot_svg(rows: &[Row], title: &str) -> String {
    let (w, h, ml, mr, mt, mb) = (720.0, 440.0, 70.0, 170.0, 40.0, 50.0);
    let pw = w - ml - mr;
    let ph = h - mt - mb;
    let tmin = rows.iter().map(|r| r.run_ms).fold(f64::INFINITY, f64::min).max(1e-3);
    let tmax = rows.iter().map(|r| r.run_ms).fold(0.0f64, f64::max).max(tmin * 10.0);
    let (l0, l1) = (tmin.log10().floor(), tmax.log10().ceil());
    let mmax = rows.iter().map(|r| r.missed).max().unwrap_or(0).max(1) as f64;
    let x = |t: f64| ml + (t.max(1e-3).log10() - l0) / (l1 - l0) * pw;
    let y = |m: f64| mt + ph - m / mmax * ph;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(s, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    let _ = writeln!(s, r#"<text x="{ml}" y="24" font-size="15">{}</text>"#, escape(title));
    let _ = writeln!(
        s,
        r##"<rect x="{ml}" y="{mt}" width="{pw}" height="{ph}" fill="none" stroke="#444"/>"##
    );
    let mut d = l0;
    while d <= l1 + 1e-9 {
        let xx = x(10f64.powf(d));
        let _ = writeln!(
            s,
            r##"<line x1="{xx:.1}" y1="{mt}" x2="{xx:.1}" y2="{:.1}" stroke="#ddd"/>"##,
            mt + ph
        );
        let _ = writeln!(
            s,
            r#"<text x="{xx:.1}" y="{:.1}" text-anchor="middle">{}</text>"#,
            mt + ph + 16.0,
            fmt_ms(10f64.powf(d))
        );
        d += 1.0;
    }
    for m in 0..=(mmax as usize) {
        let yy = y(m as f64);
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" text-anchor="end">{m}</text>"#,
            ml - 6.0,
            yy + 4.0
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">run time, ms (log)</text>"#,
        ml + pw / 2.0,
        h - 10.0
    );
    let _ = writeln!(
        s,
        r#"<text x="16" y="{:.1}" transform="rotate(-90 16 {:.1})" text-anchor="middle">collisions missed vs exact</text>"#,
        mt + ph / 2.0,
        mt + ph / 2.0
    );
    let colors = ["#d62728", "#1f77b4", "#2ca02c"];
    let mut labels: Vec<PlotLabel> = Vec::new();
    for (ti, &tol) in TOLERANCES.iter().enumerate() {
        let c = colors[ti % 3];
        for r in rows.iter().filter(|r| r.tolerance_mm == tol) {
            let (px, py) = (x(r.run_ms), y(r.missed as f64));
            match r.mode {
                Mode::Exact => {
                    let _ = writeln!(
                        s,
                        r#"<rect x="{:.1}" y="{:.1}" width="10" height="10" fill="{c}"/>"#,
                        px - 5.0,
                        py - 5.0
                    );
                }
                Mode::Step => {
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{px:.1}" cy="{py:.1}" r="4.5" fill="none" stroke="{c}" stroke-width="2"/>"#
                    );
                    // Points of one tolerance that coincide on the plot share one label.
                    let text = r.dt_ms.map_or(String::new(), |d| format!("{d}"));
                    match labels
                        .iter_mut()
                        .find(|l: &&mut PlotLabel| l.color == c && (l.px - px).abs() < 4.0 && (l.py - py).abs() < 4.0)
                    {
                        Some(l) => {
                            l.text.push_str(", ");
                            l.text.push_str(&text);
                        }
                        None => labels.push(PlotLabel { px, py, text, color: c }),
                    }
                }
            }
        }
        let ly = mt + 14.0 + ti as f64 * 18.0;
        let lx = ml + pw + 16.0;
        let _ = writeln!(
            s,
            r#"<circle cx="{lx}" cy="{ly}" r="4.5" fill="none" stroke="{c}" stroke-width="2"/>"#
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}">step, tol {tol} mm</text>"#,
            lx + 10.0,
            ly + 4.0
        );
    }
    let ly = mt + 14.0 + 3.0 * 18.0;
    let lx = ml + pw + 16.0;
    let _ = writeln!(
        s,
        r##"<rect x="{}" y="{}" width="10" height="10" fill="#444"/>"##,
        lx - 5.0,
        ly - 5.0
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}">exact (by colour)</text>"#,
        lx + 10.0,
        ly + 4.0
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" font-size="10">labels: dt in ms</text>"#,
        lx - 5.0,
        ly + 24.0
    );
    place_labels(&mut s, &labels, mt);
    s.push_str("</svg>\n");
    s
}

/// A label of step-mode points (their dt values) at a point of the plot.
struct PlotLabel {
    px: f64,
    py: f64,
    text: String,
    color: &'static str,
}

/// Write the labels, each at the first of several spots beside its point (above right, then
/// higher, then below) whose box stays below the plot's top edge `top` (the title is above it)
/// and overlaps no label placed before it.
fn place_labels(s: &mut String, labels: &[PlotLabel], top: f64) {
    let mut taken: Vec<(f64, f64, f64, f64)> = Vec::new();
    for l in labels {
        let w = 5.4 * l.text.chars().count() as f64;
        let h = 10.0;
        let spots = (0..6)
            .map(|k| (l.px + 6.0, l.py - 5.0 - 11.0 * k as f64))
            .chain((1..4).map(|k| (l.px + 6.0, l.py + 4.0 + 11.0 * k as f64)));
        let free = |&(x, y): &(f64, f64)| {
            y - h >= top + 2.0
                && taken
                    .iter()
                    .all(|&(a, b, c, d)| x + w + 4.0 < a || x > c + 4.0 || y < b || y - h > d)
        };
        let spot = spots.clone().find(free).unwrap_or((l.px + 6.0, l.py - 5.0));
        taken.push((spot.0, spot.1 - h, spot.0 + w, spot.1));
        let _ = writeln!(
            s,
            r#"<text x="{:.1}" y="{:.1}" font-size="9" fill="{}">{}</text>"#,
            spot.0,
            spot.1,
            l.color,
            escape(&l.text)
        );
    }
}

fn fmt_ms(v: f64) -> String {
    if v >= 1.0 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

#[cfg(test)]
mod plot_tests {
    use super::*;

    /// (x, y) of each `<text>` written.
    fn spots(s: &str) -> Vec<(f64, f64)> {
        s.lines()
            .map(|l| {
                let num = |k: &str| -> f64 { l.split(k).nth(1).unwrap().split('"').next().unwrap().parse().unwrap() };
                (num(" x=\""), num(" y=\""))
            })
            .collect()
    }

    #[test]
    fn labels_of_points_that_coincide_do_not_overlap_and_stay_below_the_title() {
        let labels: Vec<PlotLabel> = ["#d62728", "#1f77b4", "#2ca02c"]
            .iter()
            .map(|&color| PlotLabel {
                px: 200.0,
                py: 60.0,
                text: "10, 5, 2".into(),
                color,
            })
            .collect();
        let mut s = String::new();
        place_labels(&mut s, &labels, 50.0);
        let p = spots(&s);
        assert_eq!(p.len(), 3);
        for i in 0..3 {
            assert!(p[i].1 - 10.0 >= 52.0, "below the plot's top: {p:?}");
            for j in 0..i {
                assert!(
                    (p[i].1 - p[j].1).abs() >= 10.0 || (p[i].0 - p[j].0).abs() >= 40.0,
                    "{p:?}"
                );
            }
        }
    }
}
