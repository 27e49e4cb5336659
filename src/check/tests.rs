//! What step mode guarantees against exact mode, and what a file past its finding cap costs.

use super::*;
use crate::finding::{Severity, MAX_FINDINGS};
use crate::pipeline::{self, Mode, Settings};

/// The checker's findings for `src` on the built-in machine, in report order.
fn run(src: &str, settings: &Settings, cap: usize) -> CheckResult {
    let machine = Machine::builtin();
    let (_, interp) = pipeline::interpret(src.as_bytes(), &machine);
    let mut out = check_capped(&interp, &machine, settings, cap);
    crate::finding::sort_findings(&mut out.findings);
    out
}

fn settings(mode: Mode, dt_ms: f64) -> Settings {
    Settings {
        mode,
        dt_ms,
        ..Settings::default()
    }
}

#[test]
fn a_rapid_grazing_the_bar_corner_between_samples_is_found_in_step_mode() {
    // The rapid of N70 dips 19 µm into the corner of the bar for a fraction of a millisecond:
    // no sample of 1 ms (0.3 mm of travel) or coarser lands in the contact. The gaps proven at
    // the samples on either side do not cover the way between them, so step mode measures the
    // pair over the move as exact mode does, and reports the same finding with the same facts.
    let src = include_str!("../../programs/crash_rapid_grazes_bar_corner.nc");
    let facts = |f: &Finding| {
        (
            f.line,
            f.kind,
            f.objects.clone(),
            f.severity,
            f.depth_mm,
            f.time_s,
            f.end_time_s,
        )
    };
    let exact = run(src, &settings(Mode::Exact, 1.0), MAX_FINDINGS);
    assert_eq!(exact.findings.len(), 1, "{:?}", exact.findings);
    assert_eq!(
        (exact.findings[0].line, exact.findings[0].kind),
        (12, Kind::RapidIntoStock)
    );
    for dt in [0.5, 1.0, 2.0, 5.0, 10.0] {
        let step = run(src, &settings(Mode::Step, dt), MAX_FINDINGS);
        let got: Vec<_> = step.findings.iter().map(facts).collect();
        assert_eq!(got, vec![facts(&exact.findings[0])], "dt {dt} ms");
    }
}

#[test]
fn an_insert_sliding_out_along_the_faces_it_cut_is_proven_clear_without_exact_measure() {
    // A grooving insert leaves its groove between the walls it cut, a facing insert backs off
    // the face it cut: a gap of 0 at every sample, which no proven gap covers. The hull of its
    // poses over the stretch does (and over longer stretches ahead), so no pair is handed to
    // exact mode's conservative advancement.
    for src in [
        include_str!("../../programs/grooving.nc"),
        include_str!("../../programs/facing.nc"),
    ] {
        let step = run(src, &settings(Mode::Step, 1.0), MAX_FINDINGS);
        assert!(step.findings.is_empty(), "{:?}", step.findings);
        assert_eq!(step.stats.refined, 0, "no pair needed exact mode's measure");
    }
}

/// Every program of `programs/` and `tests/cases/` (sorted), then the named files of
/// `tests/fixtures/hostile/`.
fn repository_programs(hostile: &[&str]) -> Vec<std::path::PathBuf> {
    fn nc_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
        let Ok(rd) = std::fs::read_dir(dir) else { return };
        let mut entries: Vec<_> = rd.flatten().map(|e| e.path()).collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                nc_files(&p, out);
            } else if p.extension().is_some_and(|e| e == "nc" || e == "ngc") {
                out.push(p);
            }
        }
    }
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    nc_files(&root.join("programs"), &mut files);
    nc_files(&root.join("tests/cases"), &mut files);
    files.extend(hostile.iter().map(|f| root.join("tests/fixtures/hostile").join(f)));
    files
}

/// The measure's shortcuts change no finding: a probe answered again (where a move starts in
/// contact at the pose the last one ended at, against the same material) and a move proven
/// buried no deeper than its contact already was. Every program and case of the repository and
/// the hostile fixtures that bury the holder give the same findings, fact for fact, with them
/// and without, in both modes. Not vacuous: the holder buried all along its passes is proven
/// move by move (with fewer pair tests), and the one that leaves the bar on every return pass
/// has the probe at each return's start answered again.
#[test]
fn the_measures_shortcuts_change_no_finding_on_any_program_or_case() {
    let files = repository_programs(&[
        "g71_profile_run_first_drags_the_holder.nc",
        "holder_buried_back_and_forth.nc",
        "holder_buried_all_along.nc",
    ]);
    let mut differ = Vec::new();
    let mut taken = std::collections::BTreeMap::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap_or_default();
        for mode in [Mode::Exact, Mode::Step] {
            exact::shortcuts::set_off(true);
            let plain = run(&src, &settings(mode, 1.0), MAX_FINDINGS);
            exact::shortcuts::set_off(false);
            let short = run(&src, &settings(mode, 1.0), MAX_FINDINGS);
            let name = f.file_name().unwrap_or_default().to_string_lossy().to_string();
            taken.insert(format!("{name} {mode:?}"), exact::shortcuts::counts());
            if format!("{:?}", plain.findings) != format!("{:?}", short.findings) {
                differ.push(format!("{}: {mode:?}", f.display()));
            }
            if name == "holder_buried_all_along.nc" {
                assert!(
                    short.stats.pair_tests < plain.stats.pair_tests,
                    "{mode:?}: {} pair tests with the shortcuts, {} without",
                    short.stats.pair_tests,
                    plain.stats.pair_tests
                );
            }
        }
    }
    exact::shortcuts::set_off(false);
    assert!(differ.is_empty(), "{differ:#?}");
    for mode in [Mode::Exact, Mode::Step] {
        // 40 moves in the bar: all but the first proven buried, none of them probed.
        let (_, buried) = taken[&format!("holder_buried_all_along.nc {mode:?}")];
        assert!(buried >= 35, "{mode:?}: {buried} moves proven buried");
        // Each return pass starts in contact where the pass before ended.
        let (recalled, _) = taken[&format!("holder_buried_back_and_forth.nc {mode:?}")];
        assert!(recalled >= 30, "{mode:?}: {recalled} recalled");
    }
}

/// `n` rapids into the bar and back out, every third one only grazing its front corner.
fn crashing_rapids(n: usize) -> String {
    let mut s = String::from("G21 G18 G99\nT0101\nG97 S800 M3\nG0 X60 Z2\n");
    for i in 0..n {
        if i % 3 == 2 {
            // The graze of programs/crash_rapid_grazes_bar_corner.nc.
            s += "G0 X48 Z3.67\nZ2.67\nX52 Z0.67\nX60 Z2\n";
        } else {
            s += "G0 X40 Z-5\nG0 X60 Z2\n";
        }
    }
    s + "M30\n"
}

#[test]
fn contacts_past_the_finding_cap_are_counted_alike_and_cost_less_to_measure() {
    let src = crashing_rapids(90);
    let cap = 20;
    for mode in [Mode::Step, Mode::Exact] {
        let s = settings(mode, 1.0);
        let whole = run(&src, &s, MAX_FINDINGS);
        let capped = run(&src, &s, cap);
        assert!(whole.findings.len() > 3 * cap, "{}", whole.findings.len());
        // The same findings: the ones a report shows (the first `cap` in report order) with
        // every fact, the others as the count and lines the report gives, and as crashes in
        // progress or grazes (which decide what follows on from them).
        let shown = |f: &Finding| {
            (
                f.line,
                f.end_line,
                f.kind,
                f.objects.clone(),
                f.severity,
                f.depth_mm,
                f.time_s,
                f.end_time_s,
                f.follow_on.as_ref().map(|p| p.line),
            )
        };
        let counted = |f: &Finding| {
            (
                f.line,
                f.end_line,
                f.kind,
                f.objects.clone(),
                f.severity,
                f.follow_on.is_some(),
            )
        };
        let first = |r: &CheckResult| r.findings[..cap].iter().map(shown).collect::<Vec<_>>();
        assert_eq!(first(&capped), first(&whole), "{mode:?}");
        let all = |r: &CheckResult| r.findings.iter().map(counted).collect::<Vec<_>>();
        assert_eq!(all(&capped), all(&whole), "{mode:?}");
        assert!(whole.findings.iter().any(|f| f.severity == Severity::Warning));
        // What the last half of the rapids costs (all past the cap): well under what measuring
        // them fully costs (under half of it before stretches in contact were proven by one
        // query, which made the full measure cheaper too; now 54 %).
        let half = crashing_rapids(45);
        let w = whole.stats.pair_tests - run(&half, &s, MAX_FINDINGS).stats.pair_tests;
        let c = capped.stats.pair_tests - run(&half, &s, cap).stats.pair_tests;
        assert!(
            5 * c < 3 * w,
            "{mode:?}: {c} pair tests past the cap against {w} measured fully"
        );
    }
}

#[test]
fn strides_in_contact_step_over_no_separation_on_any_program_or_case() {
    // Every stride conservative advancement takes in contact (longer than the tolerance) is
    // probed every half tolerance: none may find the pair apart, on every program and case of
    // the repository and the hostile holder-dragging G71, in both modes, on the built-in
    // machine (the scenes differ from the cases' own machines; the strides are what is tested).
    let files = repository_programs(&["g71_profile_run_first_drags_the_holder.nc"]);
    assert!(files.len() > 100, "{}", files.len());
    let mut strides = 0;
    let mut misses = Vec::new();
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap_or_default();
        for mode in [Mode::Exact, Mode::Step] {
            exact::stride_audit::on();
            run(&src, &settings(mode, 1.0), MAX_FINDINGS);
            let audit = exact::stride_audit::take();
            strides += audit.strides;
            for (s, c) in audit.misses {
                misses.push(format!(
                    "{}: {mode:?}: a stride of {s:.3} mm apart after {c:.3} mm",
                    f.display()
                ));
            }
        }
    }
    assert!(misses.is_empty(), "{misses:#?}");
    // Not vacuous: buried holders and inserts stride in contact many times over.
    assert!(strides > 1000, "only {strides} strides in contact audited");
}

/// Every contact boundary `refine` finds by stepping the clear end by proven gaps and galloping
/// from a touch lies where plain bisection of the same bracket lands, within 2^-30 of the
/// bracket, on the programs and cases of the repository, the hostile holder-dragging G71 and the
/// holder buried along its passes, in both modes. (Not to the unit of 2^-40: where an insert
/// slides along a face its overlap flickers about the touch tolerance at the level of rounding,
/// and the two land on flickers 9 units apart, 1e-13 mm.) A gap stepped past the boundary would
/// put them a gap apart. The shortcut is taken: the buried holder's boundaries cost a few probes
/// (`tests/hostile_check.rs`, its pair tests a move).
#[test]
fn contact_boundaries_lie_where_plain_bisection_puts_them() {
    let files = repository_programs(&[
        "g71_profile_run_first_drags_the_holder.nc",
        "holder_buried_back_and_forth.nc",
    ]);
    let (mut boundaries, mut far) = (0usize, Vec::new());
    for f in &files {
        let src = std::fs::read_to_string(f).unwrap_or_default();
        for mode in [Mode::Exact, Mode::Step] {
            exact::refine_audit::on();
            run(&src, &settings(mode, 1.0), MAX_FINDINGS);
            for apart in exact::refine_audit::take() {
                boundaries += 1;
                if apart > 1024.0 {
                    far.push(format!("{}: {mode:?}: {apart:.1} units apart", f.display()));
                }
            }
        }
    }
    assert!(far.is_empty(), "{far:#?}");
    assert!(boundaries > 500, "only {boundaries} boundaries audited");
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(400))]

    /// A move judged out of reach of every obstacle (`Checker::out_of_reach`, which spares the
    /// per-part envelopes) is one where no part's envelope — every station's tools, the turret —
    /// meets any obstacle's box: the skip never drops a pair the broad phase would keep.
    #[test]
    fn a_move_out_of_reach_has_no_part_envelope_near_an_obstacle(
        x0 in -2000.0f64..2000.0, z0 in -2000.0f64..2000.0,
        dx in 0.0f64..300.0, dz in 0.0f64..300.0,
        active in 1u32..=8,
        margin in 0.0f64..5.0,
    ) {
        let machine = Machine::builtin();
        let settings = Settings::default();
        let mut c = checker(&machine, &settings, false);
        c.ensure_stock();
        let rb = crate::geom::Aabb { min: P2::new(x0, z0), max: P2::new(x0 + dx, z0 + dz) };
        if c.out_of_reach(&rb, margin) {
            for p in c.parts(active) {
                let Some(pb) = c.envelope(p, &rb, active) else { continue };
                for o in OBSTACLES {
                    if let Some(ob) = c.obstacle_box(o) {
                        proptest::prop_assert!(!pb.meets(&ob, margin), "{p:?} against {o:?} at {rb:?}");
                    }
                }
            }
        }
    }
}

#[test]
fn a_move_beside_the_chuck_is_in_reach_and_one_far_past_the_travel_is_not() {
    let machine = Machine::builtin();
    let c = checker(&machine, &Settings::default(), false);
    let near = crate::geom::Aabb {
        min: P2::new(20.0, 5.0),
        max: P2::new(30.0, 10.0),
    };
    let far = crate::geom::Aabb {
        min: P2::new(20.0, 1e6),
        max: P2::new(30.0, 1e6 + 10.0),
    };
    assert!(!c.out_of_reach(&near, 0.0));
    assert!(c.out_of_reach(&far, 0.0));
}

#[test]
fn over_travels_past_the_finding_cap_on_one_line_are_counted_alike() {
    // One line of a macro loop runs the turret farther past the Z limit on every pass, and rapids
    // into the bar between: every over-travel is a finding at that line. Past the cap, those that
    // begin after every finding made so far are found by their first sample past the limit and
    // not measured; the report's first `cap` findings keep every fact, the rest count alike.
    let src = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X60 Z2\n#1 = 0\nWHILE [#1 LT 60] DO1\n#1 = #1 + 1\n\
               G0 Z[400 + #1 * 10]\nG0 X40 Z-5\nG0 X60 Z2\nEND1\nM30\n";
    let cap = 25;
    for mode in [Mode::Step, Mode::Exact] {
        let s = settings(mode, 1.0);
        let whole = run(src, &s, MAX_FINDINGS);
        let capped = run(src, &s, cap);
        let over = whole.findings.iter().filter(|f| f.kind == Kind::Overtravel).count();
        assert!(
            over >= 40 && whole.findings.len() > 2 * cap,
            "{over} of {}",
            whole.findings.len()
        );
        let shown = |f: &Finding| (f.line, f.kind, f.objects.clone(), f.severity, f.depth_mm, f.time_s);
        let counted = |f: &Finding| (f.line, f.kind, f.objects.clone(), f.severity);
        let first = |r: &CheckResult| r.findings[..cap].iter().map(shown).collect::<Vec<_>>();
        assert_eq!(first(&capped), first(&whole), "{mode:?}");
        let all = |r: &CheckResult| r.findings.iter().map(counted).collect::<Vec<_>>();
        assert_eq!(all(&capped), all(&whole), "{mode:?}");
        // Not vacuous: the over-travels left out were found without their facts.
        let differ = capped
            .findings
            .iter()
            .zip(&whole.findings)
            .filter(|(a, b)| a.time_s != b.time_s)
            .count();
        assert!(differ > 0, "{mode:?}: no over-travel past the cap went unmeasured");
    }
}
