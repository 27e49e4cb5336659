//! Hostile input to the checker (issue 10): each of these once ran for hours or never ended.
//! The rule they hold: the work of a check is bounded by its input and settings — a move's
//! samples, probes and chords are capped, and a cap that would leave part of a move unchecked
//! says so with a finding.

use latheguard::finding::Kind;
use latheguard::machine::Machine;
use latheguard::pipeline::{self, Mode, Settings};

fn check(src: &str, settings: Settings) -> Vec<(u32, Kind, Vec<String>)> {
    pipeline::check(src.as_bytes(), &Machine::builtin(), &settings)
        .findings
        .into_iter()
        .map(|f| (f.line, f.kind, f.objects))
        .collect()
}

fn both_modes(src: &str) -> [Vec<(u32, Kind, Vec<String>)>; 2] {
    let step = Settings::default();
    let exact = Settings {
        mode: Mode::Exact,
        ..step
    };
    [check(src, step), check(src, exact)]
}

#[test]
fn a_feed_of_f0_00001_riding_the_bar_finishes_in_step_mode() {
    // 240,000 s of machine time with the holder touching the bar all along: 2.4e8 samples.
    let src = "G21 G18 G40 G97 G99\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X40. F0.2\nG1 Z-30. F0.00001\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
}

#[test]
fn a_feed_of_f0_00001_while_the_holder_is_buried_finishes() {
    // The holder ploughs through the bar for 300 mm of crawl: one long contact.
    let src = "G21 G18 G40 G97 G99\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X20. F0.2\nG1 Z-30. F0.00001\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
    assert!(
        step.iter()
            .any(|f| f.1 == Kind::Collision && f.2 == ["T01 holder", "stock"]),
        "{step:?}"
    );
}

#[test]
fn one_cutting_move_of_1e11_mm_finishes_in_both_modes() {
    let src = "G21 G18 G40 G97 G98\nT0101\nG97 S500 M3\nG0 X40. Z5.\nG1 Z-100000000000. F1000.\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
    assert!(step.iter().any(|f| f.1 == Kind::Collision), "into the chuck: {step:?}");
}

#[test]
fn a_full_circle_of_radius_1e9_through_the_bar_finishes_in_both_modes() {
    let src = "G21 G18 G40 G97 G98\nT0101\nG97 S500 M3\nG0 X60. Z5.\nG1 X46. F100.\nG2 X46. Z5. I-1000000000. K0 F1000.\nM30\n";
    let [step, exact] = both_modes(src);
    assert_eq!(step, exact);
}

#[test]
fn a_timestep_of_1e_9_ms_on_a_shipped_example_finishes() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/od_turning.nc")).unwrap();
    let tiny = Settings {
        dt_ms: 1e-9,
        ..Settings::default()
    };
    let exact = Settings {
        mode: Mode::Exact,
        ..Settings::default()
    };
    assert_eq!(check(&src, tiny), check(&src, exact));
}

#[test]
fn a_wide_clearance_at_a_fine_tolerance_finishes() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/facing.nc")).unwrap();
    let s = Settings {
        mode: Mode::Exact,
        clearance_mm: 100.0,
        tolerance_mm: 0.001,
        ..Settings::default()
    };
    let found = check(&src, s);
    assert!(found.iter().all(|f| f.1 == Kind::NearMiss), "{found:?}");
}

#[test]
fn a_program_that_uses_up_its_work_budget_says_where_the_check_stopped() {
    let src = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/programs/od_turning.nc")).unwrap();
    // The program takes 8 pair tests (most of its moves proven clear whole before sampling): a
    // budget of 3 runs out partway.
    let s = Settings {
        work_budget: 3,
        ..Settings::default()
    };
    let out = pipeline::check(src.as_bytes(), &Machine::builtin(), &s);
    let stop: Vec<_> = out
        .findings
        .iter()
        .filter(|f| f.message.contains("work budget"))
        .collect();
    assert_eq!(stop.len(), 1, "{:?}", out.findings);
    assert_eq!(stop[0].kind, Kind::Program);
    assert!(out.stats.pair_tests < 1_000, "{}", out.stats.pair_tests);
}

/// A machine file of `dir` with its STL files read beside it.
fn machine_in(text: &str, dir: std::path::PathBuf, name: &str) -> Machine {
    latheguard::machine::from_toml_with(text, name, &move |f: &str| {
        std::fs::read(dir.join(f)).map_err(|e| e.to_string())
    })
    .unwrap()
}

/// A hostile program of `tests/fixtures/hostile/`, checked on the machine its name says
/// (`lcnc_…`: the small LinuxCNC lathe, `tm_…`: the turn-mill machine, else the built-in one).
fn hostile(name: &str) -> pipeline::Outcome {
    hostile_with(name, Settings::default())
}

fn hostile_with(name: &str, settings: Settings) -> pipeline::Outcome {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read(root.join("tests/fixtures/hostile").join(name)).unwrap();
    pipeline::check(&src, &hostile_machine(name), &settings)
}

fn hostile_machine(name: &str) -> Machine {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let file = if name.starts_with("lcnc_") {
        "machines/linuxcnc-small-lathe.toml"
    } else if name.starts_with("tm_") {
        "machines/turn-mill.toml"
    } else {
        return Machine::builtin();
    };
    let path = root.join(file);
    let dir = path.parent().unwrap().to_path_buf();
    let text = std::fs::read_to_string(&path).unwrap();
    latheguard::machine::from_toml_with(&text, file, &move |n: &str| {
        std::fs::read(dir.join(n)).map_err(|e| e.to_string())
    })
    .unwrap()
}

fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// `never_touch = [["*", "*"]]` on the turn-mill machine (issue 26): every pair of components.
/// Once 400 s for the turn-mill examples (every pair queried on every move, and the turret
/// against its own housing stepped at the tolerance until its probe budget ran out). Now: parts
/// fixed to each other are tested once (the boring bar's insert in its bar: one finding), the
/// relative motion of a pair counts only the joints below their common ancestor (the drum and
/// its housing ride one slide: 0), and the 3D broad phase clears the rest without a query.
#[test]
fn never_touch_every_pair_on_the_turn_mill_machine_is_bounded_work() {
    let path = root().join("tests/fixtures/hostile/turn-mill-never-touch-all.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let all = machine_in(
        &text,
        path.parent().unwrap().to_path_buf(),
        "turn-mill-never-touch-all.toml",
    );
    let shipped_path = root().join("machines/turn-mill.toml");
    let shipped_text = std::fs::read_to_string(&shipped_path).unwrap();
    let shipped = machine_in(&shipped_text, root().join("machines"), "turn-mill.toml");
    let src = std::fs::read(root().join("programs/turn-mill/cross_drill.nc")).unwrap();
    for mode in [Mode::Step, Mode::Exact] {
        let s = Settings {
            mode,
            ..Settings::default()
        };
        let a = pipeline::check(&src, &all, &s);
        let b = pipeline::check(&src, &shipped, &s);
        // No probe budget ran out.
        assert!(
            !a.findings.iter().any(|f| f.kind == Kind::Program),
            "{mode:?}: {:?}",
            a.findings
        );
        // The one pair that overlaps by design, once: the insert seated in the boring bar.
        let rigid: Vec<_> = a.findings.iter().filter(|f| f.kind == Kind::Collision).collect();
        assert_eq!(rigid.len(), 1, "{mode:?}: {rigid:?}");
        assert_eq!(rigid[0].objects, ["t3_bar", "t3_insert"]);
        // Bounded: within a few times the shipped machine's 15 pair patterns (measured: 2,662
        // pair tests against 2,313; 228,949 and two unchecked moves before the pair bound).
        assert!(
            a.stats.pair_tests < 3 * b.stats.pair_tests,
            "{mode:?}: {} against {}",
            a.stats.pair_tests,
            b.stats.pair_tests
        );
    }
}

/// A chuck outline of 10,000 points (issue 26): its jaw tips rounded by 9,990 points. The 3D
/// turret index (`check/three/index.rs`) meets the chuck as a revolved mesh through its BVH: the
/// work of the index (its pair tests) does not grow with the outline's points.
#[test]
fn a_ten_thousand_point_chuck_outline_keeps_the_3d_index_check_bounded() {
    let path = root().join("machines/turn-mill.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    // The machine's chuck is given by its body and jaws; the same chuck as a fine outline
    // replaces both.
    let body = "body = { diameter = 210.0, bore = 50.0, face = -30.0, depth = 70.0 }";
    let jaws_at = text.find("[chuck.jaws]").unwrap();
    let jaws = &text[jaws_at..jaws_at + text[jaws_at..].find("\n\n").unwrap() + 1];
    assert!(text.contains(body));
    let mut pts = vec![
        [25.0, -100.0],
        [105.0, -100.0],
        [105.0, -30.0],
        [70.0, -30.0],
        [70.0, -12.0],
    ];
    let n = 9_990;
    for i in 1..n {
        let t = i as f64 / n as f64 * std::f64::consts::FRAC_PI_2;
        pts.push([45.0 + 25.0 * t.cos(), -12.0 + 12.0 * t.sin()]);
    }
    pts.extend([[45.0, 0.0], [25.0, 0.0]]);
    assert!(pts.len() >= 9_990 && pts.len() <= 10_000);
    let fine = format!(
        "outline = [{}]",
        pts.iter()
            .map(|p| format!("[{:.9}, {:.9}]", p[0], p[1]))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let dir = root().join("machines");
    let coarse_m = machine_in(&text, dir.clone(), "turn-mill.toml");
    let fine_m = machine_in(&text.replace(jaws, "").replace(body, &fine), dir, "turn-mill.toml");
    let plain = [
        [25.0, -100.0],
        [105.0, -100.0],
        [105.0, -30.0],
        [70.0, -30.0],
        [70.0, -12.0],
        [45.0, -12.0],
        [45.0, 0.0],
        [25.0, 0.0],
    ];
    let coarse: Vec<[f64; 2]> = coarse_m
        .chuck
        .as_ref()
        .unwrap()
        .points()
        .iter()
        .map(|p| [p.x, p.y])
        .collect();
    assert_eq!(coarse, plain);
    assert!(fine_m.chuck.as_ref().unwrap().points().len() > 9_000);
    let src = std::fs::read(root().join("programs/turn-mill/crash_y_index_into_tailstock.nc")).unwrap();
    let s = Settings::default();
    let a = pipeline::check(&src, &coarse_m, &s);
    let b = pipeline::check(&src, &fine_m, &s);
    let errs = |o: &pipeline::Outcome| {
        o.findings
            .iter()
            .filter(|f| f.severity == latheguard::finding::Severity::Error)
            .map(|f| (f.line, f.kind, f.objects.clone()))
            .collect::<Vec<_>>()
    };
    assert_eq!(errs(&a), errs(&b));
    assert!(
        b.stats.pair_tests <= 2 * a.stats.pair_tests,
        "{} against {}",
        b.stats.pair_tests,
        a.stats.pair_tests
    );
}

/// The `program` findings of an outcome whose message holds `words`, as their lines.
fn program_lines(out: &pipeline::Outcome, words: &str) -> Vec<u32> {
    out.findings
        .iter()
        .filter(|f| f.kind == Kind::Program && f.message.contains(words))
        .map(|f| f.line)
        .collect()
}

/// A hostile input past the range of moves: one `program` finding at `line`, and little work.
fn out_of_range_at(name: &str, line: u32) {
    let out = hostile(name);
    assert_eq!(
        program_lines(&out, "out of any range"),
        [line],
        "{name}: {:?}",
        out.findings
    );
    assert!(
        out.stats.pair_tests < 100_000,
        "{name}: {} pair tests",
        out.stats.pair_tests
    );
    assert!(out.stats.steps < 100_000, "{name}: {} steps", out.stats.steps);
}

#[test]
fn an_arc_radius_or_centre_past_the_range_is_a_program_error_and_ends() {
    // Each once hung the checker (R ≥ 1e16, a centre 1e20 or 1e40 away) or was accepted with a
    // NaN centre (R1e155): the range of plain moves (±1e12 mm) holds for R, I, K and the centre.
    for (name, line) in [
        ("arc_radius_1e16.nc", 7),
        ("arc_radius_1e155.nc", 7),
        ("arc_centre_k1e40.nc", 7),
        ("arc_centre_i1e20.nc", 7),
        ("lcnc_arc_radius_1e20.nc", 7),
    ] {
        out_of_range_at(name, line);
    }
}

#[test]
fn a_cycle_word_past_the_range_is_a_program_error_and_ends() {
    // The cycle's moves reach the words' points: each once hung the checker.
    for (name, line) in [
        ("cycle_g76_i1e40.nc", 7),
        ("cycle_g90_r1e20.nc", 6),
        ("cycle_g84_r1e20.nc", 7),
        ("lcnc_cycle_g84_r1e20.nc", 9),
        ("lcnc_cycle_g76_i1e20.nc", 8),
    ] {
        out_of_range_at(name, line);
    }
}

#[test]
fn a_loop_that_divides_by_zero_stops_at_the_alarm() {
    // Fanuc alarms (PS0112 "divided by zero") and LinuxCNC aborts: the run ends there, where it
    // once went on to the block budget (2 million blocks, 727k moves).
    for (name, line) in [
        ("macro_while_divides_by_zero.nc", 9),
        ("lcnc_owhile_divides_by_zero.nc", 8),
    ] {
        let out = hostile(name);
        assert_eq!(
            program_lines(&out, "division by zero"),
            [line],
            "{name}: {:?}",
            out.findings
        );
        assert!(out.stats.blocks < 20, "{name}: {} blocks", out.stats.blocks);
        assert!(out.stats.moves < 10, "{name}: {} moves", out.stats.moves);
    }
}

#[test]
fn c_turned_many_times_costs_what_one_or_two_turns_cost() {
    // The drill grooves the bar while C turns: once, ten times, 1e11 degrees. After a whole turn
    // with nothing else moving nothing new can happen: the milled grid is cut for one turn and
    // the 3D path follows at most two (it once cost 5 ms a degree: C36000 over 100 s).
    let one = hostile("tm_c_one_turn.nc").stats;
    let ten = hostile("tm_c_ten_turns.nc").stats;
    let huge = hostile("tm_c_1e11.nc").stats;
    assert!(one.grid_rays > 0, "the drill cuts: {one:?}");
    assert_eq!((ten.grid_rays, ten.pair_tests), (one.grid_rays, one.pair_tests));
    assert_eq!(huge.grid_rays, one.grid_rays);
    assert!(huge.pair_tests <= 2 * one.pair_tests, "{huge:?} against {one:?}");
}

#[test]
fn a_c_word_past_the_range_is_a_program_error() {
    let out = hostile("tm_c_past_the_range.nc");
    assert_eq!(program_lines(&out, "out of any range"), [11], "{:?}", out.findings);
}

#[test]
fn polar_chords_near_the_axis_follow_the_tolerance_not_the_angle() {
    // Line 11 of each: an 80 mm line through the axis (it made 11,520 chords), one passing
    // 0.5 mm from it (3,286), a 4e-7 mm move across it (11,520). About a chord a millimetre,
    // at most 1° of C each away from the axis, and a C turn at X0 where the line crosses it.
    for (name, most) in [
        ("tm_polar_through_the_axis.nc", 90),
        ("tm_polar_beside_the_axis.nc", 200),
        ("tm_polar_tiny_at_the_axis.nc", 2),
    ] {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let src = std::fs::read(root.join("tests/fixtures/hostile").join(name)).unwrap();
        let (_, run) = pipeline::interpret(&src, &hostile_machine(name));
        let chords = run.moves.iter().filter(|m| m.line == 11).count();
        assert!((1..=most).contains(&chords), "{name}: {chords} chords");
        assert!(
            run.findings
                .iter()
                .all(|f| f.severity != latheguard::finding::Severity::Error),
            "{name}: {:?}",
            run.findings
        );
    }
}

/// A G71 of 0.01 mm passes whose profile ran first (found by a campaign of random G71
/// programs): one pass's last sample, `k_end·dt`, rounded a hair below the move's end, the
/// sampler stepped past `k_end`, and the jump to the next pair's resume sample took it back:
/// step mode sampled the same instant forever. The sampler's index now only moves forward and
/// `k_end` is the move's end; the check's samples stay within one per dt of machine time.
#[test]
fn step_sampling_ends_when_the_last_sample_rounds_below_the_move_end() {
    let out = hostile("g71_passes_a_tolerance_apart.nc");
    let s = &out.stats;
    assert!(s.moves > 5_000, "{s:?}");
    let bound = s.machine_time_s / (Settings::default().dt_ms / 1000.0) + 2.0 * s.moves as f64;
    assert!((s.steps as f64) < bound, "{s:?}");
}

/// A G71 whose profile ran first as plain moves (from a campaign of random G71 programs): the
/// roughing passes drag the T01 holder through what the profile left, shallow, over most of each
/// pass — once 840 probes a move at the tolerance. Stretches proven in contact (or clear) are
/// stepped over by one query each: the same findings as probing every stretch, for well under
/// half the pair tests.
#[test]
fn a_holder_dragged_along_long_passes_is_stepped_over_by_proofs() {
    let proven = hostile_with("g71_profile_run_first_drags_the_holder.nc", Settings::default());
    let probed = hostile_with(
        "g71_profile_run_first_drags_the_holder.nc",
        Settings {
            prove_stretches: false,
            ..Settings::default()
        },
    );
    let facts = |o: &pipeline::Outcome| {
        o.findings
            .iter()
            .map(|f| (f.line, f.kind, f.objects.clone(), f.severity))
            .collect::<std::collections::BTreeSet<_>>()
    };
    assert!(
        proven.findings.iter().any(|f| f.kind == Kind::Collision),
        "{:?}",
        proven.findings
    );
    assert_eq!(facts(&proven), facts(&probed));
    assert!(
        2 * proven.stats.pair_tests < probed.stats.pair_tests,
        "{} pair tests proven against {} probed",
        proven.stats.pair_tests,
        probed.stats.pair_tests
    );
}

/// The bench's contact row in small: T01 fed back and forth along the bar with its holder
/// buried in it, a contact beginning and ending on every other move. Each stretch in contact is
/// proven with the probe at its end taken into the proof's depth (a contact deepening as the
/// holder enters is no deeper than its end), the first proof of a contact reaches to the end of
/// its move, a stretch that ends clear bounds where the contact ends, and each boundary is
/// found by a step of the clear end by its gap and a gallop from the touch it reaches: the same
/// findings as probing stretch by stretch, in about 20 queries a move (there were over a
/// hundred: probes and strides every half depth, and 40 bisections of each boundary).
#[test]
fn a_holder_buried_along_its_passes_is_proven_in_a_few_queries_a_move() {
    for mode in [Mode::Step, Mode::Exact] {
        let settings = Settings {
            mode,
            ..Settings::default()
        };
        let proven = hostile_with("holder_buried_back_and_forth.nc", settings);
        let probed = hostile_with(
            "holder_buried_back_and_forth.nc",
            Settings {
                prove_stretches: false,
                ..settings
            },
        );
        let facts = |o: &pipeline::Outcome| {
            o.findings
                .iter()
                .map(|f| (f.line, f.kind, f.objects.clone(), f.severity))
                .collect::<std::collections::BTreeSet<_>>()
        };
        let holder = proven
            .findings
            .iter()
            .filter(|f| f.kind == Kind::Collision && f.objects.first().is_some_and(|o| o.contains("holder")))
            .count();
        assert_eq!(holder, 20, "{:?}", proven.findings);
        assert_eq!(facts(&proven), facts(&probed), "{mode:?}");
        for (a, b) in proven.findings.iter().zip(&probed.findings) {
            let (da, db) = (a.depth_mm.unwrap_or(0.0), b.depth_mm.unwrap_or(0.0));
            assert!((da - db).abs() <= 0.5 * settings.tolerance_mm, "{a:?} against {b:?}");
        }
        let per_move = proven.stats.pair_tests as f64 / proven.stats.moves as f64;
        assert!(per_move < 32.0, "{mode:?}: {per_move:.1} pair tests a move");
    }
}

/// Step mode measures a pair in contact at a move's start, or during the move before, exactly
/// at once (`Checker::measure_likely_contacts`): it does not sample the approach that the
/// measure makes again. A holder buried along its passes then has exact mode's facts, bit for
/// bit, for about the pair tests exact mode spends.
#[test]
fn a_holder_buried_along_its_passes_costs_step_mode_what_it_costs_exact_mode() {
    let step = hostile_with("holder_buried_back_and_forth.nc", Settings::default());
    let exact = hostile_with(
        "holder_buried_back_and_forth.nc",
        Settings {
            mode: Mode::Exact,
            ..Settings::default()
        },
    );
    let facts = |o: &pipeline::Outcome| {
        o.findings
            .iter()
            .map(|f| {
                (
                    f.line,
                    f.kind,
                    f.objects.clone(),
                    f.time_s.map(f64::to_bits),
                    f.depth_mm.map(f64::to_bits),
                    f.end_line,
                )
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(facts(&step), facts(&exact));
    // Exact mode tests nothing of the sampler's; step mode at most about one a move beyond.
    assert!(
        step.stats.pair_tests <= exact.stats.pair_tests + step.stats.moves,
        "step mode {} pair tests, exact mode {}, {} moves",
        step.stats.pair_tests,
        exact.stats.pair_tests,
        step.stats.moves
    );
}

#[test]
fn a_macro_loop_that_marches_off_the_machine_costs_little_per_move() {
    // Found by the `check` fuzz target: a WHILE whose condition never changes while a counter
    // grows (no state repeats) runs to the block budget, 500,000 rapids each 10 mm farther past
    // the Z limit. Each is an over-travel at line 10 (one shown, the rest counted past the
    // finding cap, found by their first sample past the limit); far past every obstacle a move
    // poses no part at all (`Checker::out_of_reach`, tested in the library against the parts'
    // envelopes): no pair is even a candidate, and every pair counts as skipped.
    let out = hostile("macro_loop_marches_off_the_machine.nc");
    assert_eq!(out.stats.moves, 500_000, "{:?}", out.stats);
    let over: Vec<_> = out.findings.iter().filter(|f| f.kind == Kind::Overtravel).collect();
    assert!(
        !over.is_empty() && over.iter().all(|f| f.line == 10),
        "{:?}",
        out.findings
    );
    assert_eq!(out.stats.pair_tests, 0, "{:?}", out.stats);
}

#[test]
fn a_macro_loop_whose_condition_never_changes_stops_at_the_block_budget_it_is_given() {
    // Found by the `check` fuzz target: a WHILE on #2, which never changes, while the loop
    // calls a subroutine whose moves march on with #1. No state repeats, so the loop runs to the
    // block budget (2 million blocks, 1.2 s for the release binary); the fuzz targets give it a
    // tighter one (`Settings::max_blocks`), as they give the pair tests, and the run stops there
    // with the same finding.
    let stopped = |out: &pipeline::Outcome, blocks: u64| {
        let said = format!("stopped after executing {blocks} blocks");
        out.findings
            .iter()
            .any(|f| f.kind == Kind::Program && f.message.contains(&said))
    };
    let name = "macro_while_whose_condition_never_changes.nc";
    let out = hostile(name);
    assert!(stopped(&out, 2_000_000), "{:?}", out.findings);
    assert!(out.stats.blocks <= 2_000_100, "{:?}", out.stats);
    let bounded = hostile_with(
        name,
        Settings {
            max_blocks: Some(200_000),
            ..Settings::default()
        },
    );
    assert!(stopped(&bounded, 200_000), "{:?}", bounded.findings);
    assert!(bounded.stats.blocks <= 200_100, "{:?}", bounded.stats);
    assert!(
        bounded.stats.moves * 8 < out.stats.moves,
        "{:?} {:?}",
        bounded.stats,
        out.stats
    );
}

/// A circle of many turns (LinuxCNC's `P`) sweeps in its first turn all it ever sweeps: the
/// insert's chords stop there, and past them a look at the stock during the move is the stock
/// after the cut (a fuzz input of `P40` arcs took 1.3 s, and 1,000 turns 19 s, almost all of it
/// going through every turn's chords at each look). Its later turns leave the same part and the
/// same findings as two turns, in both modes.
#[test]
fn a_circle_of_many_turns_sweeps_what_its_first_turn_sweeps() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(root.join("tests/fixtures/hostile/arc_forty_turns_through_the_bar.nc")).unwrap();
    let m = Machine::builtin();
    for mode in [Mode::Step, Mode::Exact] {
        let s = Settings {
            mode,
            ..Settings::default()
        };
        let run = |turns: &str| pipeline::check(src.replace("P40", turns).as_bytes(), &m, &s);
        let (two, forty, thousand) = (run("P2"), run("P40"), run("P1000"));
        let key = |o: &pipeline::Outcome| {
            o.findings
                .iter()
                .map(|f| (f.line, f.kind, f.objects.clone()))
                .collect::<Vec<_>>()
        };
        // The same part to rounding (a turn's chords start at other fractions of the move).
        let same = |a: &pipeline::Outcome, b: &pipeline::Outcome| {
            a.stock.len() == b.stock.len()
                && a.stock.iter().zip(&b.stock).all(|(p, q)| {
                    p.len() == q.len()
                        && p.iter()
                            .zip(q)
                            .all(|(x, y)| (x[0] - y[0]).abs() < 1e-9 && (x[1] - y[1]).abs() < 1e-9)
                })
        };
        for (name, turns, o) in [("P40", 40, &forty), ("P1000", 1000, &thousand)] {
            assert_eq!(key(o), key(&two), "{mode:?} {name}");
            assert!(same(o, &two), "{mode:?} {name}: {:?} against {:?}", o.stock, two.stock);
            // The holder passes the part again each turn: its tests grow with the turns, no faster.
            assert!(
                o.stats.pair_tests <= turns * two.stats.pair_tests,
                "{mode:?} {name}: {:?} against {:?}",
                o.stats,
                two.stats
            );
        }
        // The circle cuts the bar: half of it (P1) leaves more.
        assert!(!same(&run("P1"), &two), "{mode:?}");
    }
}

#[test]
fn moves_that_stay_past_a_travel_limit_without_going_further_take_no_samples() {
    // 100,000 rapids at X700 (radius 350, past the X travel of 300), back and forth in Z: none
    // goes further past the limit than it starts, which the move's box proves, so none is
    // sampled (each took 256 samples before, the whole of a fuzz input's time). The move that
    // crosses the limit is found and sampled as before, in both modes.
    for mode in [Mode::Step, Mode::Exact] {
        let out = hostile_with(
            "loop_stays_past_the_x_travel.nc",
            Settings {
                mode,
                ..Settings::default()
            },
        );
        assert_eq!(out.stats.moves, 100_002, "{mode:?}: {:?}", out.stats);
        let over: Vec<_> = out
            .findings
            .iter()
            .filter(|f| f.kind == Kind::Overtravel)
            .map(|f| f.line)
            .collect();
        assert_eq!(over, [5], "{mode:?}: {:?}", out.findings);
        assert!(out.stats.travel_samples <= 2 * 256, "{mode:?}: {:?}", out.stats);
    }
}
