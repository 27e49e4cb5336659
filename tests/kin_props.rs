//! The kinematic machine (issue 15): posing, the 2-axis mapping, the `[kinematics]` loader and
//! the shipped turn-mill machine.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use latheguard::kin::{Axis, AxisKind, Component, Geometry, Iso, Kinematics, Poser, Role};
use latheguard::machine::{self, Machine};
use nalgebra::{Point3, Translation3, Unit, UnitQuaternion, Vector3};
use proptest::prelude::*;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A machine file with its STL files read beside it.
fn load(rel: &str) -> Result<Machine, machine::MachineError> {
    let path = root().join(rel);
    let text = std::fs::read_to_string(&path).unwrap();
    let dir = path.parent().unwrap().to_path_buf();
    machine::from_toml_with(&text, rel, &move |name: &str| {
        std::fs::read(dir.join(name)).map_err(|e| e.to_string())
    })
}

fn mount(t: [f64; 3], r: [f64; 3]) -> Iso {
    Iso::from_parts(
        Translation3::new(t[0], t[1], t[2]),
        UnitQuaternion::from_euler_angles(r[0], r[1], r[2]),
    )
}

fn close(a: &Point3<f64>, b: &Point3<f64>) -> bool {
    (a - b).norm() <= 1e-9 * (1.0 + a.coords.norm())
}

fn comp(name: &str, parent: Option<usize>, mount: Iso, axis: Option<usize>) -> Component {
    Component {
        name: name.into(),
        parent,
        mount,
        axis,
        geometry: None,
        role: Role::Structure,
        station: None,
        label: None,
    }
}

fn v3() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-200.0..200.0f64)
}
fn angles() -> impl Strategy<Value = [f64; 3]> {
    prop::array::uniform3(-3.0..3.0f64)
}
fn unit() -> impl Strategy<Value = Unit<Vector3<f64>>> {
    prop::array::uniform3(-1.0..1.0f64)
        .prop_filter("not zero", |v| Vector3::from(*v).norm() > 0.1)
        .prop_map(|v| Unit::new_normalize(Vector3::from(v)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// child world = parent world · mount · joint, down a chain linear → rotary.
    #[test]
    fn pose_composes_parent_then_mount_then_joint(
        m1 in (v3(), angles()), m2 in (v3(), angles()), d1 in unit(), d2 in unit(),
        o in v3(), lin in -300.0..300.0f64, deg in -720.0..720.0f64, p in v3(),
    ) {
        let (m1, m2) = (mount(m1.0, m1.1), mount(m2.0, m2.1));
        let k = Kinematics {
            axes: vec![
                Axis { name: "l".into(), letter: 'Z', kind: AxisKind::Linear { dir: d1 }, zero: 0.0, travel: (-1e3, 1e3), rapid: 1e4, path: 1 },
                Axis { name: "r".into(), letter: 'C', kind: AxisKind::Rotary { origin: Point3::from(Vector3::from(o)), dir: d2 }, zero: 0.0, travel: (f64::NEG_INFINITY, f64::INFINITY), rapid: 1e4, path: 1 },
            ],
            components: vec![comp("a", None, m1, Some(0)), comp("b", Some(0), m2, Some(1))],
            never_touch: vec![],
        };
        let mut poser = Poser::new(&k);
        poser.pose(&k, &[lin, deg]);
        let p = Point3::from(Vector3::from(p));
        // By hand: the rotary joint about the line through o, then b's mount, the slide, a's mount.
        let rot = UnitQuaternion::from_axis_angle(&d2, deg.to_radians());
        let o = Point3::from(Vector3::from(o));
        let in_b = o + rot * (p - o);
        let in_a = m2 * in_b;
        let want = m1 * (in_a + d1.into_inner() * lin);
        prop_assert!(close(&(poser.world(1) * p), &want), "{} vs {}", poser.world(1) * p, want);
    }

    /// A rotary axis about a line off the origin keeps the points of that line where they are.
    #[test]
    fn rotary_axis_keeps_its_own_line_fixed(o in v3(), d in unit(), deg in -1000.0..1000.0f64, t in -500.0..500.0f64, m in (v3(), angles())) {
        let m = mount(m.0, m.1);
        let k = Kinematics {
            axes: vec![Axis { name: "c".into(), letter: 'C', kind: AxisKind::Rotary { origin: Point3::from(Vector3::from(o)), dir: d }, zero: 0.0, travel: (f64::NEG_INFINITY, f64::INFINITY), rapid: 1e4, path: 1 }],
            components: vec![comp("s", None, m, Some(0))],
            never_touch: vec![],
        };
        let mut poser = Poser::new(&k);
        let on_line = Point3::from(Vector3::from(o)) + d.into_inner() * t;
        let before = poser.world(0) * on_line;
        poser.pose(&k, &[deg]);
        prop_assert!(close(&(poser.world(0) * on_line), &before));
        // A point off the line moves (unless the angle is a whole turn).
        let off = on_line + d.into_inner().cross(&Vector3::new(0.3, -0.7, 0.5)).normalize() * 10.0;
        if (deg.rem_euclid(360.0)).min(360.0 - deg.rem_euclid(360.0)) > 1.0 {
            prop_assert!((poser.world(0) * off - m * off).norm() > 0.01);
        }
    }

    /// A 2-axis machine's tree puts the turret reference point and each tool's programmed point
    /// where the 2D model puts them: reference point + tip.
    #[test]
    fn lathe_tree_poses_turret_and_tips_as_the_2d_model(fx in 0.0..1.0f64, fz in 0.0..1.0f64) {
        let m = Machine::builtin();
        let k = Kinematics::from_lathe(&m);
        let (x, z) = (m.x.min + fx * (m.x.max - m.x.min), m.z.min + fz * (m.z.max - m.z.min));
        let mut poser = Poser::new(&k);
        let mut values = k.start_values();
        values[k.axis_by_letter('X').unwrap()] = x;
        values[k.axis_by_letter('Z').unwrap()] = z;
        poser.pose(&k, &values);
        let turret = k.component("turret").unwrap();
        prop_assert!(close(&(poser.world(turret) * Point3::origin()), &Point3::new(x, 0.0, z)));
        for t in &m.tools {
            let c = k.component(&format!("t{}_insert", t.station)).unwrap();
            let tip = poser.world(c) * Point3::origin();
            prop_assert!(close(&tip, &Point3::new(x + t.tip.x, 0.0, z + t.tip.y)), "T{}: {tip}", t.station);
            // The insert's outline points land at their 2D places too.
            let q = t.insert.points()[1];
            let world = poser.world(c) * Point3::new(q.x, 0.0, q.y);
            prop_assert!(close(&world, &Point3::new(x + t.tip.x + q.x, 0.0, z + t.tip.y + q.y)));
        }
    }

    /// Moving one axis re-poses exactly the components under it; the others keep their poses.
    #[test]
    fn only_the_subtrees_of_moved_axes_are_reposed(which in 0usize..6, v in -40.0..40.0f64) {
        let m = load("machines/turn-mill.toml").unwrap();
        let k = m.kinematics.clone().unwrap();
        let mut poser = Poser::new(&k);
        let before: Vec<Iso> = (0..k.components.len()).map(|c| *poser.world(c)).collect();
        let mut values = k.start_values();
        values[which] += v.max(0.5);
        if values[which] > k.axes[which].travel.1 {
            values[which] = k.axes[which].travel.1 - 1.0;
        }
        let n = poser.pose(&k, &values);
        let mut under = std::collections::BTreeSet::new();
        for (c, comp) in k.components.iter().enumerate() {
            if comp.axis == Some(which) {
                under.extend(k.subtree(c));
            }
        }
        prop_assert!(!under.is_empty());
        prop_assert_eq!(n, under.len());
        prop_assert_eq!(poser.last_reposed, under.len());
        for (c, was) in before.iter().enumerate() {
            if !under.contains(&c) {
                prop_assert_eq!(poser.world(c), was, "{} moved", k.components[c].name);
            }
        }
        // Posing the same values again re-poses nothing.
        prop_assert_eq!(poser.pose(&k, &values), 0);
    }
}

#[test]
fn turn_mill_loads_with_every_part_and_pairs() {
    let m = load("machines/turn-mill.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let k = m.kinematics.as_ref().unwrap();
    let letters: String = k.axes.iter().map(|a| a.letter).collect();
    assert_eq!(letters, "XZYCBA");
    assert_eq!(m.turret.stations, 12);
    let y = &k.axes[k.axis_by_letter('Y').unwrap()];
    assert_eq!(y.travel, (-50.0, 50.0));
    let meshes = k
        .components
        .iter()
        .filter(|c| matches!(c.geometry, Some(Geometry::Mesh(_))))
        .count();
    assert!(meshes >= 4, "{meshes} STL parts");
    // Parents first.
    for (i, c) in k.components.iter().enumerate() {
        assert!(c.parent.map_or(true, |p| p < i), "{}", c.name);
    }
    // The turret never touches the main chuck; the radial live drill's holder never touches the
    // live centre; no pair joins a tool to its own holder.
    let id = |n: &str| k.component(n).unwrap();
    let pair = |a: &str, b: &str| {
        let (a, b) = (id(a), id(b));
        k.never_touch.contains(&(a.min(b), a.max(b)))
    };
    assert!(pair("turret", "main_chuck"));
    assert!(pair("t8_live_block", "live_centre"));
    assert!(pair("t7_drill", "sub_chuck"));
    assert!(!pair("t7_drill", "t7_holder"));
    // Each STL file is small, and the ASCII one is ASCII.
    let dir = root().join("machines/turn-mill");
    let mut total = 0;
    for e in std::fs::read_dir(&dir).unwrap().flatten() {
        total += e.metadata().unwrap().len();
    }
    assert!(total < 300_000, "{total} bytes");
    assert!(std::fs::read(dir.join("turret.stl"))
        .unwrap()
        .starts_with(b"solid turret"));
    // The 2D path still reads it as a lathe: the tailstock is the parked sub-spindle's centre.
    assert!(m.tailstock.is_some() && m.chuck.is_some());
}

#[test]
fn turn_mill_tool_tips_match_their_2d_tips_at_home() {
    let m = load("machines/turn-mill.toml").unwrap();
    let k = m.kinematics.as_ref().unwrap();
    let poser = Poser::new(k);
    for t in &m.tools {
        let c = k.component(&format!("t{}_holder", t.station)).unwrap();
        let got = poser.world(c) * Point3::origin();
        let want = Point3::new(m.home.x + t.tip.x, 0.0, m.home.y + t.tip.y);
        assert!(close(&got, &want), "T{}: {got} vs {want}", t.station);
    }
    // The radial drill's point lies on its tip and its flutes run toward +x.
    let d = k.component("t8_drill").unwrap();
    let far = poser.world(d) * Point3::new(0.0, 0.0, 40.0);
    let tip = m.tool(8).unwrap().tip;
    assert!(
        close(&far, &Point3::new(m.home.x + tip.x + 40.0, 0.0, m.home.y + tip.y)),
        "{far}"
    );
}

#[test]
fn plain_from_toml_refuses_stl_geometry_clearly() {
    let text = std::fs::read_to_string(root().join("machines/turn-mill.toml")).unwrap();
    let e = machine::from_toml(&text, "turn-mill.toml").unwrap_err().to_string();
    assert!(e.contains(": kinematics.components[1].geometry.stl: cannot read \"turn-mill/headstock.stl\": an STL file is read relative to the machine file"), "{e}");
}

/// The turn-mill file with one text replaced, loaded with its STL files (or `stl` overrides).
fn variant(from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(root().join("machines/turn-mill.toml")).unwrap();
    assert!(text.contains(from), "{from}");
    let text = text.replacen(from, to, 1);
    let dir = root().join("machines");
    match machine::from_toml_with(&text, "tm.toml", &move |n: &str| {
        if n == "broken.stl" {
            return Ok(b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n".to_vec());
        }
        std::fs::read(Path::new(&dir).join(n)).map_err(|e| e.to_string())
    }) {
        Ok(_) => "ok".into(),
        Err(e) => e.to_string(),
    }
}

/// A component's `label` is a few words on one line, and the loaded component keeps it.
#[test]
fn a_component_label_is_one_short_line_and_is_kept() {
    let at = "label = \"sub-spindle's chuck\"";
    for (label, why) in [
        ("\"  \"", "must not be blank"),
        (
            "\"the chuck on the sub-spindle that faces the main spindle over there\"",
            "a label is a few words: at most 60 characters",
        ),
        (
            "\"sub\\tchuck\"",
            "a label is one line: no tabs, line breaks or other control characters",
        ),
    ] {
        let e = variant(at, &format!("label = {label}"));
        assert!(e.contains(&format!(".label: {why}")), "{label}: {e}");
        assert!(e.starts_with("tm.toml:"), "{e}");
    }
    let m = machine::from_toml_with(
        &std::fs::read_to_string(root().join("machines/turn-mill.toml")).unwrap(),
        "tm.toml",
        &|n: &str| std::fs::read(root().join("machines").join(n)).map_err(|e| e.to_string()),
    )
    .unwrap();
    let k = m.kinematics.as_ref().unwrap();
    let sub = &k.components[k.component("sub_chuck").unwrap()];
    assert_eq!(sub.label.as_deref(), Some("sub-spindle's chuck"));
    assert_eq!(k.components[k.component("main_chuck").unwrap()].label, None);
}

#[test]
fn load_errors_name_file_line_column_key() {
    let cases: &[(&str, &str, &str)] = &[
        (
            "name = \"z_slide\"\nparent = \"bed\"",
            "name = \"z_slide\"\nparent = \"nowhere\"",
            "kinematics.components[4].parent: no component is named \"nowhere\"",
        ),
        (
            "name = \"headstock\"\nparent = \"bed\"",
            "name = \"headstock\"\nparent = \"main_chuck\"",
            "kinematics.components[1].parent: the parents form a cycle: headstock → main_chuck → main_spindle",
        ),
        (
            "name = \"z_slide\"",
            "name = \"x_slide\"",
            "kinematics.components[5].name: component \"x_slide\" is already defined by kinematics.components[4]",
        ),
        (
            "letter = \"A\"",
            "letter = \"C\"",
            "kinematics.axes[5].letter: letter C already drives kinematics.axes[3] (\"c_main\"): a letter drives one axis",
        ),
        (
            "travel = [-50, 50]",
            "travel = [50, -50]",
            "kinematics.axes[2].travel: min = 50 must be less than max = -50",
        ),
        (
            "travel = [-10, 300]",
            "travel = [-10, 310]",
            "kinematics.axes[0].travel: travel [-10, 310] differs from axes.x (-10 .. 300): the two must be the same",
        ),
        (
            "letter = \"Y\"\ntype = \"linear\"",
            "letter = \"Y\"\ntype = \"rotary\"",
            "kinematics.axes[2].type: axis Y is linear: give type = \"linear\"",
        ),
        (
            "letter = \"Y\"",
            "letter = \"W\"",
            "kinematics.axes[2].letter: \"W\" is not an axis letter: give one of X, Z, Y, C, B, A",
        ),
        (
            "axis = \"c_sub\"",
            "axis = \"c_nowhere\"",
            "kinematics.components[32].axis: no axis is named \"c_nowhere\"",
        ),
        (
            "stl = \"turn-mill/turret.stl\"",
            "stl = \"broken.stl\"",
            "kinematics.components[7].geometry.stl: broken.stl:4: the file ends where `vertex` was expected",
        ),
        (
            "stl = \"turn-mill/turret.stl\"",
            "stl = \"turn-mill/missing.stl\"",
            "kinematics.components[7].geometry.stl: cannot read \"turn-mill/missing.stl\"",
        ),
        (
            "geometry = { box = { min = [60, -80, 35], max = [220, 80, 250] } }",
            "geometry = { box = { min = [60, -80, 35], max = [220, 80, 250] }, cylinder = { radius = 1, z0 = 0, z1 = 1 } }",
            "kinematics.components[8].geometry: give exactly one of stl, revolved, extruded, box, cylinder (found 2)",
        ),
        (
            "geometry = { revolved = \"chuck\" }",
            "geometry = { revolved = \"collet\" }",
            "kinematics.components[3].geometry.revolved: \"collet\": a named outline is \"chuck\" or \"tailstock\"",
        ),
        (
            "role = \"cutter\"\nstation = 9",
            "role = \"cutter\"\nstation = 13",
            "kinematics.components[29].station: station 13 does not exist: the turret has stations 1 to 12",
        ),
        (
            "[\"turret\", \"headstock\"],",
            "[\"turret\", \"role:spindle\"],",
            "kinematics.never_touch[2][1]: \"spindle\" is not a role: structure, chuck, tailstock, holder or cutter",
        ),
        (
            "[\"turret\", \"headstock\"],",
            "[\"turret\", \"turret\"],",
            "kinematics.never_touch[2]: a component cannot be paired with itself",
        ),
        (
            "mount = { translate = [-60, 0, -12] }",
            "mount = { translate = [-60, 0] }",
            "kinematics.components[9].mount.translate: expected 3 numbers [x, y, z], found 2",
        ),
    ];
    for (from, to, want) in cases {
        let got = variant(from, to);
        assert!(got.starts_with("tm.toml:"), "{got}");
        assert!(
            got.contains(want),
            "replacing {from:?} by {to:?}:\n got  {got}\n want {want}"
        );
    }
    // The line and column point at the value.
    let got = variant("travel = [-50, 50]", "travel = [50, -50]");
    let text = std::fs::read_to_string(root().join("machines/turn-mill.toml")).unwrap();
    let line = text.lines().position(|l| l == "travel = [-50, 50]").unwrap() + 1;
    assert!(got.starts_with(&format!("tm.toml:{line}:10: ")), "{got}");
}

#[test]
fn a_kinematic_x_axis_must_agree_with_the_2d_one() {
    let got = variant("direction = [1, 0, 0]", "direction = [0, 1, 0]");
    assert!(
        got.contains("kinematics.axes[0].direction: axis X moves along +x as the 2D axes do"),
        "{got}"
    );
    let got = variant(
        "travel = [-50, 600]\nrapid = 24000\n",
        "travel = [-50, 600]\nrapid = 25000\n",
    );
    assert!(
        got.contains("kinematics.axes[1].rapid: rapid 25000 differs from axes.z.rapid = 24000"),
        "{got}"
    );
}

#[test]
fn lathe_tree_pairs_tools_and_turret_with_chuck() {
    let m = Machine::builtin();
    let k = Kinematics::from_lathe(&m);
    let chuck = k.component("chuck").unwrap();
    let turret = k.component("turret").unwrap();
    assert!(k.never_touch.contains(&(chuck.min(turret), chuck.max(turret))));
    // Two per tool and the turret.
    assert_eq!(k.never_touch.len(), 2 * m.tools.len() + 1);
    assert!(k
        .components
        .iter()
        .all(|c| c.parent.map_or(true, |p| p < k.components.len())));
    let _ = Arc::new(k);
}

/// A cutter's end on a kinematic cylinder (`end = …`): the shapes load, and the grid cutter's
/// checks are said against the key (docs/machine.md, "[kinematics]").
#[test]
fn a_cutter_end_loads_and_its_bad_sizes_name_the_key() {
    let t11 = "geometry = { cylinder = { radius = 5, z0 = 0, z1 = 30 } }";
    let with = |end: &str| {
        variant(
            t11,
            &format!("geometry = {{ cylinder = {{ radius = 5, z0 = 0, z1 = 30, end = {end} }} }}"),
        )
    };
    for good in [
        "\"flat\"",
        "\"ball\"",
        "{ corner_radius = 1.5 }",
        "{ corner_radius = 5 }",
        "{ point_angle = 118 }",
    ] {
        assert_eq!(with(good), "ok", "{good}");
    }
    let cases = [
        ("{ corner_radius = 6 }", ".geometry.cylinder.end.corner_radius: corner radius 6 mm: must be above 0 and at most the radius 5"),
        ("{ corner_radius = 0 }", ".geometry.cylinder.end.corner_radius: corner radius 0 mm"),
        ("{ point_angle = 180 }", ".geometry.cylinder.end.point_angle: point angle 180°: must be between 0° and 180°"),
        ("{ point_angle = -5 }", ".geometry.cylinder.end.point_angle: point angle -5°"),
        ("\"round\"", ".geometry.cylinder.end: \"round\": an end is \"flat\", \"ball\", { corner_radius = r } or { point_angle = degrees }"),
    ];
    for (end, want) in cases {
        let got = with(end);
        assert!(got.contains(want), "{end}:\n got  {got}\n want {want}");
    }
    // A ball needs flutes at least its radius: z1 − z0 = 4 < 5.
    let got = variant(
        t11,
        "geometry = { cylinder = { radius = 5, z0 = 0, z1 = 4, end = \"ball\" } }",
    );
    assert!(
        got.contains(".geometry.cylinder.end: flute length 4 mm: a ball end needs at least its radius (the flutes are z1 − z0 = 4)"),
        "{got}"
    );
    // A table that is neither end.
    let got = with("{ radius = 2 }");
    assert!(got.contains(".geometry.cylinder.end"), "{got}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// A poser focused on a few components (the checker's probes ask about a pair and the part's
    /// frame) poses them, and every ancestor, exactly as the full poser does, along any run of
    /// axis values, and re-poses no other component.
    #[test]
    fn a_focused_poser_poses_its_parts_as_the_full_poser(
        runs in proptest::collection::vec(proptest::collection::vec(-300.0..300.0f64, 8), 1..6),
        picks in proptest::collection::vec(any::<prop::sample::Index>(), 1..3),
    ) {
        let m = load("machines/turn-mill.toml").unwrap();
        let k = m.kinematics.as_ref().unwrap();
        let parts: Vec<usize> = picks.iter().map(|i| i.index(k.components.len())).collect();
        let mut chain = vec![false; k.components.len()];
        for &c in &parts {
            let mut p = Some(c);
            while let Some(q) = p {
                chain[q] = true;
                p = k.components[q].parent;
            }
        }
        let mut full = Poser::new(k);
        let mut focused = Poser::focused(k, &parts);
        for values in &runs {
            let values: Vec<f64> = (0..k.axes.len()).map(|a| values.get(a).copied().unwrap_or(0.0)).collect();
            full.pose(k, &values);
            let n = focused.pose(k, &values);
            prop_assert!(n <= chain.iter().filter(|&&c| c).count());
            for c in (0..k.components.len()).filter(|&c| chain[c]) {
                prop_assert_eq!(full.world(c).to_homogeneous(), focused.world(c).to_homogeneous(), "component {}", c);
            }
        }
    }
}
