//! Polar coordinate interpolation G12.1/G13.1 (G112/G113) on the turn-mill machine (issue 16;
//! docs/turn-mill.md, "Polar coordinate interpolation"): the chords it makes lie on the
//! programmed Cartesian path, the hand-worked points are where they should be, and the control's
//! alarms are findings.

use std::process::Command;

const HEX: &str = "tests/fixtures/polar/hex_g12_1.nc";

fn run(args: &[&str], stdin: Option<&str>) -> (String, String, Option<i32>) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_latheguard"));
    c.current_dir(env!("CARGO_MANIFEST_DIR")).args(args);
    let out = match stdin {
        Some(text) => {
            use std::io::Write;
            let mut child = c
                .stdin(std::process::Stdio::piped())
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap();
            child.stdin.take().unwrap().write_all(text.as_bytes()).unwrap();
            child.wait_with_output().unwrap()
        }
        None => c.output().unwrap(),
    };
    (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
        out.status.code(),
    )
}

/// The feed moves' (line, x radius, z, c degrees) from the canonical output.
fn feeds(program: &str) -> Vec<(u32, f64, f64, f64)> {
    let (out, err, _) = run(
        &[
            "moves",
            "--machine",
            "machines/turn-mill.toml",
            "--format",
            "canon",
            program,
        ],
        None,
    );
    let mut v = Vec::new();
    for l in out.lines() {
        let l = l.trim();
        let Some((line, rest)) = l.split_once(' ') else {
            continue;
        };
        let Some(args) = rest.strip_prefix("STRAIGHT_FEED(") else {
            continue;
        };
        let n: Vec<f64> = args
            .trim_end_matches(')')
            .split(',')
            .map(|s| s.trim().parse().unwrap())
            .collect();
        v.push((line.parse().unwrap(), n[0], n[2], n[5]));
    }
    assert!(!v.is_empty(), "{err}");
    v
}

/// Worked by hand: the hex's corners (radius 40/2 / cos 30° = 23.094 at 30°, 90°, …) come at C
/// −30°, −90°, −150° … (the part turned by minus the corner's angle), and every chord's end, turned
/// back into the plane (x = X cos(−C), c = X sin(−C)), lies on its programmed side within the
/// canonical output's 1e-4 rounding.
#[test]
fn a_g12_1_hex_runs_on_its_sides_and_through_its_corners() {
    let f = feeds(HEX);
    let corners = [
        (13, 30.0),
        (14, 90.0),
        (15, 150.0),
        (16, 210.0),
        (17, 270.0),
        (18, 330.0),
    ];
    for (line, deg) in corners {
        let last = f.iter().rfind(|m| m.0 == line).unwrap();
        assert!((last.1 - 23.094).abs() < 1e-3, "line {line}: {last:?}");
        let c = (-last.3).rem_euclid(360.0);
        assert!(
            (c - deg).abs() < 1e-3,
            "line {line}: C {} for a corner at {deg}°",
            last.3
        );
    }
    // The sides: |point − its projection on the side| ≤ 1e-3 (rounding of X and C to 1e-4).
    let corner = |deg: f64| {
        let a = deg.to_radians();
        (23.094011 * a.cos(), 23.094011 * a.sin())
    };
    for (line, deg) in corners.iter().skip(1) {
        let (p, q) = (corner(deg - 60.0), corner(*deg));
        for m in f.iter().filter(|m| m.0 == *line) {
            let a = (-m.3).to_radians();
            let (x, c) = (m.1 * a.cos(), m.1 * a.sin());
            let (dx, dc) = (q.0 - p.0, q.1 - p.1);
            let t = ((x - p.0) * dx + (c - p.1) * dc) / (dx * dx + dc * dc);
            assert!((-1e-6..=1.0 + 1e-6).contains(&t), "line {line}: {m:?}");
            let d = ((x - p.0 - t * dx).powi(2) + (c - p.1 - t * dc).powi(2)).sqrt();
            assert!(d < 1e-3, "line {line}: {m:?} is {d} off its side");
        }
    }
    // C never jumps: at most 1° between consecutive chords of the mode.
    for w in f
        .windows(2)
        .filter(|w| (12..=19).contains(&w[0].0) && (12..=19).contains(&w[1].0))
    {
        assert!((w[1].3 - w[0].3).abs() <= 1.0 + 1e-9, "{w:?}");
    }
}

/// G112/G113 (Fanuc's system A names) are the same mode.
#[test]
fn g112_and_g113_are_g12_1_and_g13_1() {
    let hex = std::fs::read_to_string(format!("{}/{HEX}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let dir = std::env::temp_dir().join(format!("lg-polar-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("g112.nc");
    std::fs::write(&p, hex.replace("G12.1", "G112").replace("G13.1", "G113")).unwrap();
    assert_eq!(feeds(p.to_str().unwrap()), feeds(HEX));
    let _ = std::fs::remove_dir_all(&dir);
}

/// An arc in the mode: G2 with I/J about (15, 0), radius 5: every chord end 5 from the centre.
#[test]
fn a_g12_1_arc_keeps_its_radius_about_its_centre() {
    let text = "G21 G18 G40 G97 G98\nG28 U0 W0\nT1111\nM154\nG28 H0\nM133 P3000\nG0 X40. Z2. C0.\nG1 Z-1. F200.\nG12.1\nG1 X40. C0. F300.\nG2 X40. C0. I-5. J0.\nG13.1\nG1 Z2.\nM135\nM155\nM30\n";
    let dir = std::env::temp_dir().join(format!("lg-polar-arc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("arc.nc");
    std::fs::write(&p, text).unwrap();
    let f = feeds(p.to_str().unwrap());
    let arc: Vec<_> = f.iter().filter(|m| m.0 == 11).collect();
    assert!(arc.len() >= 31, "{}", arc.len());
    for m in arc {
        let a = (-m.3).to_radians();
        let (x, c) = (m.1 * a.cos(), m.1 * a.sin());
        let d = (x - 15.0).hypot(c);
        assert!((d - 5.0).abs() < 1e-3, "{m:?}: {d}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_rapid_in_the_mode_and_the_mode_without_a_c_axis_are_findings() {
    let hex = std::fs::read_to_string(format!("{}/{HEX}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let rapid = hex.replace("G1 X40. C11.547", "G0 X40. C11.547");
    let rapid = format!("{}\nM30\n", &rapid[..rapid.find("G0 X40. C11.547").unwrap() + 15]);
    let (out, _, code) = run(&["check", "--machine", "machines/turn-mill.toml", "-"], Some(&rapid));
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains(":13:") && out.contains("G0 in polar coordinate interpolation"),
        "{out}"
    );
    // The built-in 2-axis lathe has no C axis.
    let (out, _, code) = run(&["check", "-"], Some("G21 G18\nG12.1\nG13.1\nM30\n"));
    assert_eq!(code, Some(1), "{out}");
    assert!(
        out.contains("error[unsupported]") && out.contains("needs a C axis"),
        "{out}"
    );
}

const SLOT: &str = "tests/fixtures/polar/slot_g7_1.nc";

/// G7.1 on a 25 mm cylinder: a line in C is one move (a line in Z and C is a line on the
/// unrolled surface); the arc's chords lie on a circle of radius 25 in (Z, s = 25·C·π/180), at
/// most 1 mm apart, from Z-20 C90 to Z-30 C180; G7.1 C0 ends the mode.
#[test]
fn a_g7_1_slot_keeps_c_in_degrees_and_its_arc_on_the_unrolled_circle() {
    let f = feeds(SLOT);
    let line: Vec<_> = f.iter().filter(|m| m.0 == 14).collect();
    assert_eq!(line.len(), 1);
    assert!((line[0].3 - 90.0).abs() < 1e-9 && (line[0].2 + 20.0).abs() < 1e-9);
    let k = 25.0 * std::f64::consts::PI / 180.0;
    let arc: Vec<(f64, f64)> = f.iter().filter(|m| m.0 == 15).map(|m| (m.2, m.3 * k)).collect();
    let mut pts = vec![(-20.0, 90.0 * k)];
    pts.extend(arc.iter().copied());
    let (a, b, c) = (pts[0], pts[pts.len() / 2], *pts.last().unwrap());
    assert!((c.0 + 30.0).abs() < 1e-4 && (c.1 / k - 180.0).abs() < 1e-3, "{c:?}");
    // The circumcentre of the first, middle and last points.
    let d = 2.0 * (a.0 * (b.1 - c.1) + b.0 * (c.1 - a.1) + c.0 * (a.1 - b.1));
    let sq = |p: (f64, f64)| p.0 * p.0 + p.1 * p.1;
    let ux = (sq(a) * (b.1 - c.1) + sq(b) * (c.1 - a.1) + sq(c) * (a.1 - b.1)) / d;
    let uy = (sq(a) * (c.0 - b.0) + sq(b) * (a.0 - c.0) + sq(c) * (b.0 - a.0)) / d;
    for w in pts.windows(2) {
        assert!((w[1].0 - w[0].0).hypot(w[1].1 - w[0].1) <= 1.0 + 1e-3, "{w:?}");
    }
    for p in &pts {
        let r = (p.0 - ux).hypot(p.1 - uy);
        assert!((r - 25.0).abs() < 2e-3, "{p:?}: {r}");
    }
    // After G7.1 C0, C is the rotary axis again and X moves as programmed.
    let last = f.last().unwrap();
    assert!(
        (last.1 - 30.0).abs() < 1e-9 && (last.3 - 360.0).abs() < 1e-9,
        "{last:?}"
    );
}

#[test]
fn g7_1_without_its_radius_and_a_rapid_in_the_mode_are_findings() {
    // The fixture up to the line in question (the milling after it is not what is tested).
    let slot = std::fs::read_to_string(format!("{}/{SLOT}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let upto = |text: &str, last: &str| {
        let end = text.find(last).unwrap() + last.len();
        format!("{}\nM30\n", &text[..end])
    };
    let (out, _, code) = run(
        &["check", "--machine", "machines/turn-mill.toml", "-"],
        Some(&upto(&slot.replace("G7.1 C25.", "G7.1"), "\nG7.1")),
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("G7.1 needs C"), "{out}");
    let (out, _, code) = run(
        &["check", "--machine", "machines/turn-mill.toml", "-"],
        Some(&upto(&slot.replace("G1 C90. F300.", "G0 C90."), "\nG0 C90.")),
    );
    assert_eq!(code, Some(1), "{out}");
    assert!(out.contains("G0 in cylindrical interpolation"), "{out}");
}

/// G41 in the mode (tests/fixtures/polar/hex_g41.nc): the programmed flats are the hex's (40
/// across), the control offsets the cutter's centre by its radius, 5 (the T11 end mill's
/// cylinder in the machine's tree), to the left of the path. The path runs counter-clockwise,
/// so the centre runs on the hex inset by 5: 30 across flats, every point of lines 13–19 with
/// its largest projection on the six flat normals at 15 (a corner inset by 5 / cos 30°, at
/// 17.32 from the centre), line 13 on x = 15 from the entry below the hex. The start-up block (line 12) ends normal to the next block's start,
/// the block before G40 normal to its own end, and the G40 block returns to the programmed X80.
#[test]
fn g41_in_the_mode_offsets_the_contour_before_the_transform() {
    let f = feeds("tests/fixtures/polar/hex_g41.nc");
    let plane = |m: &(u32, f64, f64, f64)| {
        let a = (-m.3).to_radians();
        (m.1 * a.cos(), m.1 * a.sin())
    };
    let apothem = |(x, c): (f64, f64)| {
        (0..6)
            .map(|k| {
                let a = (k as f64 * 60.0).to_radians();
                x * a.cos() + c * a.sin()
            })
            .fold(f64::MIN, f64::max)
    };
    // Line 13 climbs the flat from the entry below the hex (C-15): on x = 15 all the way.
    for m in f.iter().filter(|m| m.0 == 13) {
        assert!((plane(m).0 - 15.0).abs() < 1e-3, "{m:?}");
    }
    let on_inset: Vec<_> = f.iter().filter(|m| (14..=19).contains(&m.0)).collect();
    assert!(on_inset.len() > 100, "{}", on_inset.len());
    for m in &on_inset {
        let a = apothem(plane(m));
        assert!((a - 15.0).abs() < 1e-3, "{m:?}: {a}");
    }
    let end_of = |line: u32| plane(f.iter().rfind(|m| m.0 == line).unwrap());
    let close = |p: (f64, f64), q: (f64, f64)| (p.0 - q.0).abs() < 1e-3 && (p.1 - q.1).abs() < 1e-3;
    assert!(close(end_of(12), (15.0, -15.0)), "{:?}", end_of(12));
    assert!(close(end_of(14), (0.0, 17.3205)), "{:?}", end_of(14));
    assert!(close(end_of(19), (15.0, 0.0)), "{:?}", end_of(19));
    assert!(close(end_of(20), (40.0, 0.0)), "{:?}", end_of(20));
    // G42 puts the centre outside: the same contour with the flats at 25.
    let text = std::fs::read_to_string(format!(
        "{}/tests/fixtures/polar/hex_g41.nc",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let dir = std::env::temp_dir().join(format!("lg-polar-g42-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("g42.nc");
    std::fs::write(&p, text.replace("G41 G1", "G42 G1")).unwrap();
    let g = feeds(p.to_str().unwrap());
    for m in g.iter().filter(|m| m.0 == 13) {
        assert!((plane(m).0 - 25.0).abs() < 1e-3, "{m:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The mode cancelled with compensation on is the control's alarm; a tool whose radius
/// latheguard does not know (T11 with no milling sizes, no nose radius and, here, no cylinder
/// cutter in the tree) is `unsupported`.
#[test]
fn g13_1_with_compensation_on_and_an_unknown_radius_are_findings() {
    let text = std::fs::read_to_string(format!(
        "{}/tests/fixtures/polar/hex_g41.nc",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let dir = std::env::temp_dir().join(format!("lg-polar-g13-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let read = |name: &str, text: String| {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        run(
            &[
                "moves",
                "--machine",
                "machines/turn-mill.toml",
                "--format",
                "canon",
                p.to_str().unwrap(),
            ],
            None,
        )
        .1
    };
    let err = read("no_g40.nc", text.replace("G40 G1 X80. C0.", "G1 X80. C0."));
    assert!(
        err.contains(":21:") && err.contains("cancelled with cutter compensation on"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    // The machine without T11's cutter cylinder in its tree: no radius to offset by.
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("machines/turn-mill.toml");
    let base = path.parent().unwrap().to_path_buf();
    let mut m = latheguard::machine::from_toml_with(
        &std::fs::read_to_string(&path).unwrap(),
        "machines/turn-mill.toml",
        &move |name: &str| std::fs::read(base.join(name)).map_err(|e| e.to_string()),
    )
    .unwrap();
    let mut k = (**m.kinematics.as_ref().unwrap()).clone();
    for c in &mut k.components {
        if c.station == Some(11) && c.role == latheguard::kin::Role::Cutter {
            c.geometry = None;
        }
    }
    m.kinematics = Some(std::sync::Arc::new(k));
    let (_, i) = latheguard::pipeline::interpret(text.as_bytes(), &m);
    let f: Vec<_> = i
        .findings
        .iter()
        .filter(|f| f.message.contains("the cutter's radius is unknown"))
        .collect();
    assert_eq!(f.len(), 1, "{:?}", i.findings);
    assert_eq!(f[0].line, 12);
}

/// G41 in cylindrical interpolation (tests/fixtures/polar/slot_wall_g7_1_g41.nc): the wall is
/// programmed on Z-20 with C rising; seen from the tool (Z to the right, the unrolled C up) the
/// D12 end mill's centre runs left of it, on Z-26 (G42: Z-14), from the start-up block's end at
/// C90 to C180; the G40 block returns to the programmed Z-20 at C200.
#[test]
fn g41_in_g7_1_offsets_the_unrolled_contour() {
    let wall = "tests/fixtures/polar/slot_wall_g7_1_g41.nc";
    let f = feeds(wall);
    let at = |line: u32| *f.iter().rfind(|m| m.0 == line).unwrap();
    for (line, z, c) in [(13, -26.0, 90.0), (14, -26.0, 180.0), (15, -20.0, 200.0)] {
        let m = at(line);
        assert!((m.2 - z).abs() < 1e-9 && (m.3 - c).abs() < 1e-9, "line {line}: {m:?}");
    }
    let text = std::fs::read_to_string(format!("{}/{wall}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let dir = std::env::temp_dir().join(format!("lg-cyl-g42-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("g42.nc");
    std::fs::write(&p, text.replace("G41 G1", "G42 G1")).unwrap();
    let g = feeds(p.to_str().unwrap());
    let m = g.iter().rfind(|m| m.0 == 14).unwrap();
    assert!((m.2 + 14.0).abs() < 1e-9, "{m:?}");
    let q = dir.join("no_g40.nc");
    std::fs::write(&q, text.replace("G40 G1 C200.", "G1 C200.")).unwrap();
    let (_, err, _) = run(
        &[
            "moves",
            "--machine",
            "machines/turn-mill.toml",
            "--format",
            "canon",
            q.to_str().unwrap(),
        ],
        None,
    );
    assert!(
        err.contains(":16:") && err.contains("cancelled with cutter compensation on"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 29: a G12.1 face pocket through the spindle axis
/// (tests/fixtures/polar/face_pocket_through_axis.nc: three passes across the Ø50 bar's face
/// 20 mm apart, 4 mm deep, the middle one through the axis with its C turn there) is clean and
/// its milled stock's work is bounded: near the axis every chord's sweep spans every angle of
/// the cylindrical grid, and the cuts cast 22,735,867 rays when each ray under a chord was cast
/// at every height, each face node under it every chord and each chord of the C turn on the axis
/// again (3.2 s); now about 1.16 million (0.64 s). The bound counts rays, not seconds.
#[test]
fn a_g12_1_face_pocket_through_the_axis_is_clean_and_casts_few_rays() {
    let (out, err, code) = run(
        &[
            "check",
            "--machine",
            "machines/turn-mill.toml",
            "--format",
            "json",
            "tests/fixtures/polar/face_pocket_through_axis.nc",
        ],
        None,
    );
    assert_eq!(code, Some(0), "{out}{err}");
    let json: serde_json::Value = serde_json::from_str(&out).unwrap();
    let file = &json["files"][0];
    assert_eq!(file["status"], "clean", "{file}");
    let stats = &file["stats"];
    assert!(
        stats["effects"].as_array().unwrap().iter().any(|e| e == "grid_stock"),
        "the pocket mills the bar: {stats}"
    );
    let rays = stats["grid_rays"].as_u64().unwrap();
    assert!(
        (100_000..3_000_000).contains(&rays),
        "{rays} rays cast (22,735,867 before issue 29)"
    );
}
