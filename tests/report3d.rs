//! Reports of 3D findings (issue 15): the three orthographic views (`report::views3`), the glTF
//! binary (`report::glb`) and the `--glb DIR` option.
//!
//! Meshes are built here (a box, a tessellated cylinder): converting machine geometry to meshes
//! is another module's job.

use crate::common;

use common::{latheguard, stderr};
use latheguard::finding::{Finding, Kind, Severity};
use latheguard::gate::FailOn;
use latheguard::kin::{Iso, Mesh};
use latheguard::pipeline::Settings;
use latheguard::report::scene3::{Part3, Role3, Snapshot3};
use latheguard::report::{glb, svg, views3, FileReport, Report};
use nalgebra::{Point3, Vector3};
use proptest::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;

/// A box from `min` to `max`, triangles counter-clockwise seen from outside.
fn cuboid(min: [f64; 3], max: [f64; 3]) -> Mesh {
    let mut vertices = Vec::new();
    for k in 0..8 {
        vertices.push(Point3::new(
            if k & 1 == 0 { min[0] } else { max[0] },
            if k & 2 == 0 { min[1] } else { max[1] },
            if k & 4 == 0 { min[2] } else { max[2] },
        ));
    }
    let quads = [
        [0, 2, 3, 1], // z min
        [4, 5, 7, 6], // z max
        [0, 1, 5, 4], // y min
        [2, 6, 7, 3], // y max
        [0, 4, 6, 2], // x min
        [1, 3, 7, 5], // x max
    ];
    let mut triangles = Vec::new();
    for q in quads {
        triangles.push([q[0], q[1], q[2]]);
        triangles.push([q[0], q[2], q[3]]);
    }
    Mesh { vertices, triangles }
}

/// A closed cylinder about the z axis from `z0` to `z1`, `n` sides.
fn cylinder(r: f64, z0: f64, z1: f64, n: u32) -> Mesh {
    let mut vertices = vec![Point3::new(0.0, 0.0, z0), Point3::new(0.0, 0.0, z1)];
    for i in 0..n {
        let a = 2.0 * PI * i as f64 / n as f64;
        vertices.push(Point3::new(r * a.cos(), r * a.sin(), z0));
        vertices.push(Point3::new(r * a.cos(), r * a.sin(), z1));
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        let (a0, a1) = (2 + 2 * i, 2 + 2 * ((i + 1) % n));
        let (b0, b1) = (a0 + 1, a1 + 1);
        triangles.push([a0, a1, b1]);
        triangles.push([a0, b1, b0]);
        triangles.push([0, a1, a0]);
        triangles.push([1, b0, b1]);
    }
    Mesh { vertices, triangles }
}

fn part(name: &str, mesh: Mesh, pose: Iso, role: Role3) -> Part3 {
    Part3 {
        name: name.into(),
        mesh: Arc::new(mesh),
        pose,
        role,
    }
}

/// A turn-mill scene: a holder on the turret runs into the sub-spindle's chuck, off the
/// working plane (y = 30); main chuck and bar stock stand on the left.
fn scene() -> Snapshot3 {
    // The radial drill points along −x: a cylinder about z turned onto the x axis.
    let drill_pose = Iso::new(Vector3::new(150.0, 30.0, 192.0), Vector3::y() * (-PI / 2.0));
    Snapshot3 {
        title: "rapid move drives the T05 holder into the sub chuck".into(),
        line: 42,
        time_s: Some(12.5),
        parts: vec![
            part(
                "main chuck",
                cylinder(100.0, -80.0, 0.0, 48),
                Iso::identity(),
                Role3::Fixed,
            ),
            part("stock", cylinder(25.0, 0.0, 90.0, 48), Iso::identity(), Role3::Stock),
            part(
                "turret",
                cuboid([0.0, -70.0, -50.0], [110.0, 70.0, 50.0]),
                Iso::translation(150.0, 0.0, 190.0),
                Role3::Moving,
            ),
            part(
                "T05 holder",
                cuboid([60.0, 10.0, 170.0], [150.0, 50.0, 215.0]),
                Iso::identity(),
                Role3::CollidingA,
            ),
            part("T05 drill", cylinder(6.0, 0.0, 120.0, 24), drill_pose, Role3::Moving),
            part(
                "sub chuck",
                cylinder(80.0, 205.0, 290.0, 48),
                Iso::identity(),
                Role3::CollidingB,
            ),
        ],
        contact: Some(Point3::new(70.0, 30.0, 205.0)),
    }
}

fn doc(svg: &str) -> roxmltree::Document<'_> {
    roxmltree::Document::parse(svg).expect("well-formed SVG")
}

/// Where pictures go when `REPORT3D_OUT` names a folder (to look at them; nothing is written
/// otherwise).
fn keep(name: &str, bytes: &[u8]) {
    if let Some(dir) = std::env::var_os("REPORT3D_OUT") {
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(std::path::Path::new(&dir).join(name), bytes).unwrap();
    }
}

#[test]
fn views_are_well_formed_with_three_labelled_views_a_legend_and_the_contact() {
    let s = scene();
    let out = views3::svg(&s);
    keep("scene.svg", out.as_bytes());
    let d = doc(&out);
    for id in ["view-xz", "view-xy", "view-yz"] {
        assert!(d.descendants().any(|n| n.attribute("id") == Some(id)), "no {id}");
    }
    let texts: Vec<String> = d
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.descendants().filter_map(|t| t.text()).collect::<String>())
        .collect();
    for label in ["XZ", "XY", "YZ"] {
        assert!(
            texts.iter().any(|t| t.starts_with(label) && t.contains("view")),
            "no label {label}: {texts:?}"
        );
    }
    let legend = d
        .descendants()
        .find(|n| n.attribute("class") == Some("legend"))
        .expect("a legend");
    let legend_text: String = legend.descendants().filter_map(|t| t.text()).collect();
    for name in ["T05 holder", "sub chuck", "first contact", "other moving parts"] {
        assert!(legend_text.contains(name), "{name} not in the legend: {legend_text}");
    }
    // The main chuck and the stock stand outside the box the views show: not in the legend.
    assert!(
        !legend_text.contains("fixed parts") && !legend_text.contains("stock"),
        "{legend_text}"
    );
    // The contact is ringed once in each view, inside that view's frame.
    let rings: Vec<_> = d
        .descendants()
        .filter(|n| n.attribute("class") == Some("contact"))
        .collect();
    assert_eq!(rings.len(), 3);
}

#[test]
fn views_are_deterministic() {
    let a = views3::svg(&scene());
    let b = views3::svg(&scene());
    assert_eq!(a, b);
    let g1 = glb::glb(&scene());
    let g2 = glb::glb(&scene());
    assert_eq!(g1, g2);
}

/// The points of the fill of the part named `name` in the view `view` (`"xz"`, `"xy"`, `"yz"`).
fn part_points(svg: &str, view: &str, name: &str) -> Vec<(f64, f64)> {
    let d = doc(svg);
    let v = d
        .descendants()
        .find(|n| n.attribute("id") == Some(&format!("view-{view}")[..]))
        .expect("the view");
    let Some(g) = v.children().find(|g| {
        g.attribute("class") == Some("part") && g.children().any(|t| t.has_tag_name("title") && t.text() == Some(name))
    }) else {
        return vec![];
    };
    let mut pts = vec![];
    for p in g.children().filter(|p| p.has_tag_name("path")) {
        let data = p.attribute("d").unwrap();
        for cmd in data.split(['M', 'L', 'Z']).filter(|c| !c.is_empty()) {
            let (x, y) = cmd.split_once(',').unwrap();
            pts.push((x.parse().unwrap(), y.parse().unwrap()));
        }
    }
    pts
}

fn centre(pts: &[(f64, f64)]) -> (f64, f64) {
    assert!(!pts.is_empty());
    let n = pts.len() as f64;
    (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    )
}

/// Cubes at the origin and off it along +x, +y and +z; the contact at the far corner, so that
/// the views show them all.
fn axes_scene() -> Snapshot3 {
    let cube = |name: &str, at: [f64; 3], role| {
        part(
            name,
            cuboid([-5.0, -5.0, -5.0], [5.0, 5.0, 5.0]),
            Iso::translation(at[0], at[1], at[2]),
            role,
        )
    };
    Snapshot3 {
        title: "axes".into(),
        line: 1,
        time_s: None,
        parts: vec![
            cube("origin", [0.0, 0.0, 0.0], Role3::CollidingA),
            cube("plus x", [60.0, 0.0, 0.0], Role3::Fixed),
            cube("plus y", [0.0, 60.0, 0.0], Role3::Fixed),
            cube("plus z", [0.0, 0.0, 60.0], Role3::CollidingB),
        ],
        contact: Some(Point3::new(65.0, 65.0, 65.0)),
    }
}

#[test]
fn each_view_draws_the_machine_axes_the_way_its_label_says() {
    let out = views3::svg(&axes_scene());
    keep("axes.svg", out.as_bytes());
    let c = |view: &str, name: &str| centre(&part_points(&out, view, name));
    // XZ, the lathe's view, looking along −Y: the cube on +y hides the one at the origin;
    // +z to the right, +x up (picture y runs down).
    assert!(part_points(&out, "xz", "origin").is_empty());
    let o = c("xz", "plus y");
    assert!(c("xz", "plus z").0 > o.0 + 50.0);
    assert!(c("xz", "plus x").1 < o.1 - 50.0);
    // XY, from the tailstock side (along −Z): +x up, +y to the left.
    assert!(part_points(&out, "xy", "origin").is_empty());
    let o = c("xy", "plus z");
    assert!(c("xy", "plus x").1 < o.1 - 50.0);
    assert!(c("xy", "plus y").0 < o.0 - 50.0);
    // YZ, from above (along −X): +z to the right, +y down.
    assert!(part_points(&out, "yz", "origin").is_empty());
    let o = c("yz", "plus x");
    assert!(c("yz", "plus z").0 > o.0 + 50.0);
    assert!(c("yz", "plus y").1 > o.1 + 50.0);
    // One scale: the same cube is as wide in every view.
    let width = |view: &str, name: &str| {
        let p = part_points(&out, view, name);
        let xs = p.iter().map(|q| q.0);
        xs.clone().fold(f64::MIN, f64::max) - xs.fold(f64::MAX, f64::min)
    };
    let (a, b, cc) = (width("xz", "plus y"), width("xy", "plus z"), width("yz", "plus x"));
    assert!(
        a > 20.0 && (a - b).abs() <= 1.5 && (a - cc).abs() <= 1.5,
        "{a} {b} {cc}"
    );
}

#[test]
fn a_part_behind_another_is_hidden_in_that_view_only() {
    // A small cube right behind a large plate as seen along −Y (the lathe's view), beside it
    // from above and from the end.
    let s = Snapshot3 {
        title: "hidden".into(),
        line: 1,
        time_s: None,
        parts: vec![
            part(
                "plate",
                cuboid([-40.0, 10.0, -40.0], [40.0, 14.0, 40.0]),
                Iso::identity(),
                Role3::CollidingA,
            ),
            part(
                "behind",
                cuboid([-5.0, -20.0, -5.0], [5.0, -10.0, 5.0]),
                Iso::identity(),
                Role3::Fixed,
            ),
        ],
        contact: Some(Point3::new(0.0, -20.0, 0.0)),
    };
    let out = views3::svg(&s);
    keep("hidden.svg", out.as_bytes());
    assert!(part_points(&out, "xz", "behind").is_empty());
    assert!(!part_points(&out, "xz", "plate").is_empty());
    assert!(!part_points(&out, "yz", "behind").is_empty());
    assert!(!part_points(&out, "xy", "behind").is_empty());
}

/// A sphere of about `n` triangles (latitude–longitude).
fn sphere(r: f64, n: usize) -> Mesh {
    let k = ((n / 2) as f64).sqrt().ceil() as u32;
    let mut vertices = vec![];
    for i in 0..=k {
        let th = PI * i as f64 / k as f64;
        for j in 0..k {
            let ph = 2.0 * PI * j as f64 / k as f64;
            vertices.push(Point3::new(
                r * th.sin() * ph.cos(),
                r * th.sin() * ph.sin(),
                r * th.cos(),
            ));
        }
    }
    let mut triangles = vec![];
    for i in 0..k {
        for j in 0..k {
            let a = i * k + j;
            let b = i * k + (j + 1) % k;
            let (c, d) = (a + k, b + k);
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    Mesh { vertices, triangles }
}

#[test]
fn views_of_a_million_triangle_part_stay_small() {
    let mut s = scene();
    let big = sphere(60.0, 1_000_000);
    assert!(big.triangles.len() >= 1_000_000);
    s.parts[5] = part("sub chuck", big, Iso::translation(0.0, 0.0, 260.0), Role3::CollidingB);
    let out = views3::svg(&s);
    keep("million.svg", out.as_bytes());
    doc(&out);
    // Bounded by the picture, not the mesh: a few hundred kilobytes at most.
    assert!(out.len() < 300_000, "{} bytes", out.len());
    assert!(!part_points(&out, "xz", "sub chuck").is_empty());
    let g = glb::glb(&s);
    // The binary carries the mesh as it is: 12 bytes a vertex, 12 an index triple.
    assert!(g.len() > 12_000_000);
    gltf::Gltf::from_slice(&g).expect("a valid glb");
}

/// Every node of a glTF document by name.
fn nodes(g: &gltf::Gltf) -> Vec<(String, gltf::Node<'_>)> {
    g.nodes().map(|n| (n.name().unwrap_or("").to_string(), n)).collect()
}

#[test]
fn the_glb_reads_back_with_every_part_its_pose_its_bounds_and_the_contact() {
    let s = scene();
    let bytes = glb::glb(&s);
    keep("scene.glb", &bytes);
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(u32::from_le_bytes(bytes[4..8].try_into().unwrap()), 2);
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    assert_eq!(bytes.len() % 4, 0);
    let g = gltf::Gltf::from_slice(&bytes).expect("a valid glb");
    let blob = g.blob.clone().expect("a BIN chunk");
    let buffers: Vec<_> = g.buffers().collect();
    assert_eq!(buffers.len(), 1);
    assert!(matches!(buffers[0].source(), gltf::buffer::Source::Bin));
    // The chunk is the buffer padded to 4 bytes.
    assert!(blob.len() >= buffers[0].length() && blob.len() < buffers[0].length() + 4);
    for v in g.views() {
        assert_eq!(v.offset() % 4, 0);
        assert!(v.offset() + v.length() <= buffers[0].length());
    }
    let ns = nodes(&g);
    // The root turns millimetres into metres and the machine frame into glTF's (z → +X, x → +Y).
    let scene = g.default_scene().expect("a default scene");
    let roots: Vec<_> = scene.nodes().collect();
    assert_eq!(roots.len(), 1);
    assert_eq!(roots[0].name(), Some(glb::ROOT_NAME));
    let m = roots[0].transform().matrix();
    assert_eq!((m[0][1], m[1][2], m[2][0]), (0.001, 0.001, 0.001));
    assert_eq!(roots[0].children().count(), s.parts.len() + 1);
    for p in &s.parts {
        let (_, n) = ns.iter().find(|(name, _)| name == &p.name).expect("a node per part");
        // The pose as the node's matrix.
        let m = n.transform().matrix();
        let want = p.pose.to_homogeneous();
        for c in 0..4 {
            for r in 0..4 {
                assert!((m[c][r] as f64 - want[(r, c)]).abs() < 1e-4, "{}", p.name);
            }
        }
        let mesh = n.mesh().expect("a mesh");
        let prim = mesh.primitives().next().unwrap();
        let pos = prim.get(&gltf::Semantic::Positions).unwrap();
        assert_eq!(pos.count(), p.mesh.vertices.len(), "{}", p.name);
        let reader = prim.reader(|_| Some(&blob[..]));
        let read: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for q in &read {
            for k in 0..3 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        let as_vec = |v: gltf::json::Value| -> Vec<f32> {
            v.as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap() as f32)
                .collect()
        };
        assert_eq!(as_vec(pos.min().unwrap()), lo.to_vec());
        assert_eq!(as_vec(pos.max().unwrap()), hi.to_vec());
        let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
        assert_eq!(idx.len(), 3 * p.mesh.triangles.len());
        // The triangles come back as they were (vertices in first-use order).
        for (t, got) in p.mesh.triangles.iter().zip(idx.chunks(3)) {
            for k in 0..3 {
                let want = p.mesh.vertices[t[k] as usize];
                let q = read[got[k] as usize];
                assert!((q[0] as f64 - want.x).abs() < 1e-3 && (q[2] as f64 - want.z).abs() < 1e-3);
            }
        }
        // A material per role, named after it.
        assert_eq!(prim.material().name(), Some(p.role.name()));
    }
    let (_, c) = ns
        .iter()
        .find(|(n, _)| n == glb::CONTACT_NAME)
        .expect("the contact marker");
    let (t, _, _) = c.transform().decomposed();
    assert_eq!(t, [70.0, 30.0, 205.0]);
    assert!(c.mesh().is_some());
}

#[test]
fn the_glb_leaves_bad_triangles_out_and_keeps_a_node_for_an_empty_part() {
    let bad = Mesh {
        vertices: vec![
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(10.0, 0.0, 0.0),
            Point3::new(0.0, 10.0, 0.0),
            Point3::new(f64::NAN, 0.0, 0.0),
            Point3::new(1e300, 0.0, 0.0),
        ],
        triangles: vec![[0, 1, 2], [0, 1, 3], [0, 1, 4], [0, 1, 99]],
    };
    let s = Snapshot3 {
        title: "bad".into(),
        line: 3,
        time_s: Some(f64::NAN),
        parts: vec![
            part("bad", bad, Iso::identity(), Role3::CollidingA),
            part("empty", Mesh::default(), Iso::identity(), Role3::CollidingB),
            part(
                "lost",
                cuboid([0.0; 3], [1.0; 3]),
                Iso::translation(f64::INFINITY, 0.0, 0.0),
                Role3::Fixed,
            ),
        ],
        contact: Some(Point3::new(f64::NAN, 0.0, 0.0)),
    };
    let bytes = glb::glb(&s);
    let g = gltf::Gltf::from_slice(&bytes).expect("a valid glb");
    let ns = nodes(&g);
    let (_, b) = ns.iter().find(|(n, _)| n == "bad").unwrap();
    let prim = b.mesh().unwrap().primitives().next().unwrap();
    assert_eq!(prim.indices().unwrap().count(), 3);
    assert_eq!(prim.get(&gltf::Semantic::Positions).unwrap().count(), 3);
    for name in ["empty", "lost"] {
        let (_, n) = ns.iter().find(|(x, _)| x == name).unwrap();
        assert!(n.mesh().is_none(), "{name}");
    }
    assert!(ns.iter().all(|(n, _)| n != glb::CONTACT_NAME));
    // And the views draw what can be drawn.
    let out = views3::svg(&s);
    doc(&out);
    // (Its one good triangle lies in z = 0: edge-on in the lathe's view, flat in the end view.)
    assert!(part_points(&out, "xz", "bad").is_empty());
    assert!(!part_points(&out, "xy", "bad").is_empty());
}

#[test]
fn an_empty_scene_still_gives_a_valid_picture_and_glb() {
    let s = Snapshot3 {
        title: String::new(),
        line: 0,
        time_s: None,
        parts: vec![],
        contact: None,
    };
    doc(&views3::svg(&s));
    let g = gltf::Gltf::from_slice(&glb::glb(&s)).expect("a valid glb");
    assert!(g.blob.is_none());
    assert_eq!(g.nodes().count(), 1);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Any mesh (wild coordinates, indices past the end, any pose) gives a well-formed picture
    /// and a glb the `gltf` crate reads, never a panic.
    #[test]
    fn any_mesh_gives_a_well_formed_picture_and_a_valid_glb(
        verts in prop::collection::vec(
            prop::array::uniform3(prop_oneof![
                -1e4..1e4f64,
                Just(0.0),
                Just(1e200),
                Just(-1e-300),
                Just(f64::NAN),
            ]),
            0..12,
        ),
        tris in prop::collection::vec(prop::array::uniform3(0u32..14), 0..20),
        t in prop::array::uniform3(-1e3..1e3f64),
        angle in -7.0..7.0f64,
        contact in prop::option::of(prop::array::uniform3(-1e3..1e3f64)),
    ) {
        let mesh = Mesh {
            vertices: verts.iter().map(|v| Point3::new(v[0], v[1], v[2])).collect(),
            triangles: tris,
        };
        let mesh = Arc::new(mesh);
        let s = Snapshot3 {
            title: "<&>\"".into(),
            line: 9,
            time_s: Some(1.0),
            parts: vec![
                Part3 { name: "a <b>".into(), mesh: mesh.clone(), pose: Iso::new(Vector3::from(t), Vector3::z() * angle), role: Role3::CollidingA },
                Part3 { name: "b & c".into(), mesh, pose: Iso::identity(), role: Role3::CollidingB },
            ],
            contact: contact.map(|c| Point3::new(c[0], c[1], c[2])),
        };
        let out = views3::svg(&s);
        prop_assert!(roxmltree::Document::parse(&out).is_ok());
        prop_assert!(out.len() < 400_000);
        let g = glb::glb(&s);
        prop_assert!(gltf::Gltf::from_slice(&g).is_ok());
    }
}

/// A report of one file whose one finding carries a 3D snapshot.
fn report_with_a_3d_finding() -> Report {
    let mut f = Finding::at(Kind::Collision, Severity::Error, 2, 0, "T05 holder hits the sub chuck");
    f.objects = vec!["T05 holder".into(), "sub chuck".into()];
    f.time_s = Some(12.5);
    (f.x, f.z) = (Some(100.0), Some(-35.25));
    f.snapshot3 = Some(Box::new(scene()));
    Report {
        machine: "turn-mill".into(),
        settings: Settings::default(),
        files: vec![FileReport {
            path: "progs/mill.nc".into(),
            findings: vec![f],
            source: b"G0 X100\nG0 Z205 Y30\n".to_vec(),
            ..FileReport::default()
        }],
        fail_on: FailOn::Error,
        docs_url: None,
    }
}

#[test]
fn a_finding_with_a_3d_snapshot_gets_three_views_and_a_glb_named_like_its_picture() {
    let r = report_with_a_3d_finding();
    let pics = svg::pictures(&r);
    assert_eq!(pics.len(), 1);
    assert_eq!(pics[0].name, "progs__mill.nc.L2.collision.T05-holder.sub-chuck.svg");
    keep("report.svg", pics[0].svg.as_bytes());
    let d = doc(&pics[0].svg);
    assert!(d.descendants().any(|n| n.attribute("id") == Some("view-xy")));
    // The caption has the place, the kind and the block's text.
    let text: String = d.descendants().filter_map(|n| n.text()).collect();
    assert!(text.contains("progs/mill.nc:2") && text.contains("error[collision]") && text.contains("G0 Z205 Y30"));
    // Where the program was, in program coordinates as the text report says it; the contact
    // point in the views' machine frame.
    assert!(text.contains("programmed point X100 Z-35.25"), "{text}");
    assert!(text.contains("(machine frame)"), "{text}");
    let gs = glb::files(&r);
    assert_eq!(gs.len(), 1);
    assert_eq!(gs[0].name, "progs__mill.nc.L2.collision.T05-holder.sub-chuck.glb");
    assert_eq!((gs[0].file, gs[0].finding), (0, 0));
    assert_eq!(gs[0].bytes, glb::glb(&scene()));
    // A finding of the working plane has no glb.
    let mut r2 = r.clone();
    r2.files[0].findings[0].snapshot3 = None;
    r2.files[0].findings[0].snapshot = Some(Box::default());
    assert!(glb::files(&r2).is_empty());
}

#[test]
fn the_glb_option_writes_and_says_nothing_for_findings_of_the_working_plane() {
    let dir = tempfile::tempdir().unwrap();
    let src = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("programs/crash_dogleg.nc");
    std::fs::copy(&src, dir.path().join("crash.nc")).unwrap();
    let o = latheguard(dir.path(), &["check", "crash.nc", "--glb", "scenes"]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!dir.path().join("scenes").exists());
    assert!(!stderr(&o).contains("scene"), "{}", stderr(&o));
    // Beside --svg, the pictures are written as before, and still no scene.
    let o = latheguard(dir.path(), &["check", "crash.nc", "--glb", "scenes", "--svg", "pics"]);
    assert_eq!(o.status.code(), Some(1));
    assert_eq!(std::fs::read_dir(dir.path().join("pics")).unwrap().count(), 1);
    assert!(!dir.path().join("scenes").exists());
}

#[test]
fn the_glb_option_is_in_the_help_the_readme_and_the_turn_mill_page() {
    let dir = tempfile::tempdir().unwrap();
    let help = common::stdout(&latheguard(dir.path(), &["check", "--help"]));
    assert!(help.contains("--glb <DIR>"), "{help}");
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let readme = std::fs::read_to_string(root.join("README.md")).unwrap();
    assert!(readme.contains("--glb <DIR>"));
    let page = std::fs::read_to_string(root.join("docs/turn-mill.md")).unwrap();
    assert!(page.starts_with("# Turn-mill machines"));
    assert!(page.contains("## Reports of 3D findings") && page.contains("--glb"));
}

#[test]
fn the_picture_on_the_turn_mill_page_is_what_the_views_draw_today() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/pictures/turn-mill-views.svg");
    let now = views3::svg(&scene());
    if std::env::var_os("REPORT3D_BLESS").is_some() {
        std::fs::write(&path, &now).unwrap();
    }
    let page = std::fs::read_to_string(&path).expect("docs/pictures/turn-mill-views.svg");
    assert!(page == now, "stale: run with REPORT3D_BLESS=1 to redraw it");
}

/// A box on the page: (left, top, right, bottom).
type PageBox = (f64, f64, f64, f64);

fn overlap(a: PageBox, b: PageBox) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Each contact ring's box as drawn: its circle and cross hair (±15 px), cut to its clip rect.
fn ring_boxes(d: &roxmltree::Document<'_>) -> Vec<PageBox> {
    let num = |n: roxmltree::Node<'_, '_>, a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    d.descendants()
        .filter(|n| n.attribute("class") == Some("contact"))
        .map(|g| {
            let c = g.children().find(|n| n.has_tag_name("circle")).unwrap();
            let (x, y) = (num(c, "cx"), num(c, "cy"));
            let mut b = (x - 15.0, y - 15.0, x + 15.0, y + 15.0);
            let clip = g.attribute("clip-path").expect("the ring is clipped");
            let id = clip.trim_start_matches("url(#").trim_end_matches(')');
            let rect = d
                .descendants()
                .find(|n| n.attribute("id") == Some(id))
                .and_then(|n| n.children().find(|c| c.has_tag_name("rect")))
                .expect("the clip's rect");
            let (l, t) = (num(rect, "x"), num(rect, "y"));
            let (r, bo) = (l + num(rect, "width"), t + num(rect, "height"));
            b = (b.0.max(l), b.1.max(t), b.2.min(r), b.3.min(bo));
            b
        })
        .collect()
}

/// The boxes of the caption's and the views' titles (text of 13 px and more, left-aligned):
/// about 0.62 of the font size a character, from the cap height to the descenders.
fn caption_boxes(d: &roxmltree::Document<'_>) -> Vec<(String, PageBox)> {
    d.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| {
            let size: f64 = n.attribute("font-size")?.parse().ok()?;
            if size < 13.0 || n.attribute("text-anchor").is_some() {
                return None;
            }
            let text: String = n.descendants().filter_map(|t| t.text()).collect();
            let x: f64 = n.attribute("x")?.parse().ok()?;
            let y: f64 = n.attribute("y")?.parse().ok()?;
            let w = 0.62 * size * text.chars().count() as f64;
            Some((text, (x, y - size, x + w, y + 0.3 * size)))
        })
        .collect()
}

fn assert_rings_clear_of_captions(svg: &str) {
    let d = doc(svg);
    let rings = ring_boxes(&d);
    assert!(rings.len() >= 3, "a ring in each view (and the detail's)");
    let captions = caption_boxes(&d);
    assert!(captions.len() >= 5, "the caption and three view titles: {captions:?}");
    for r in &rings {
        for (text, c) in &captions {
            assert!(!overlap(*r, *c), "the ring {r:?} covers {text:?} at {c:?}");
        }
    }
}

/// Two blocks meeting at one corner, the contact at the far corner of the larger: in the top
/// view it stands at the top left of the box the views show, next to the view's title and just
/// under the caption.
fn corner_scene() -> Snapshot3 {
    Snapshot3 {
        title: "the T05 holder hits the sub chuck at its corner".into(),
        line: 7,
        time_s: Some(1.0),
        parts: vec![
            part(
                "T05 holder",
                cuboid([0.0, 0.0, 0.0], [10.0, 10.0, 10.0]),
                Iso::identity(),
                Role3::CollidingA,
            ),
            part(
                "sub chuck",
                cuboid([-40.0, -40.0, -40.0], [0.0, 0.0, 0.0]),
                Iso::identity(),
                Role3::CollidingB,
            ),
        ],
        contact: Some(Point3::new(0.0, -40.0, -40.0)),
    }
}

#[test]
fn the_contact_ring_is_never_drawn_over_the_caption_or_a_view_title() {
    assert_rings_clear_of_captions(&views3::svg(&scene()));
    let sample = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/pictures/turn-mill-views.svg"),
    )
    .unwrap();
    assert_rings_clear_of_captions(&sample);
    let corner = views3::svg(&corner_scene());
    keep("corner.svg", corner.as_bytes());
    assert_rings_clear_of_captions(&corner);
}

/// The picture of one 3D finding of `depth` mm, the holder of the sample scene reaching `depth`
/// into the sub chuck.
fn picture_of_depth(depth: f64) -> String {
    let mut r = report_with_a_3d_finding();
    let mut s = scene();
    s.parts[3].mesh = Arc::new(cuboid([60.0, 10.0, 170.0], [150.0, 50.0, 205.0 + depth]));
    let f = &mut r.files[0].findings[0];
    f.depth_mm = Some(depth);
    f.snapshot3 = Some(Box::new(s));
    svg::pictures(&r).remove(0).svg
}

/// The (left, top, width, height) of the frame of the view with id `view-ID`'s clip.
fn frame_of(d: &roxmltree::Document<'_>, id: &str) -> Option<PageBox> {
    let rect = d
        .descendants()
        .find(|n| n.attribute("id") == Some(&format!("frame-{id}")))?
        .children()
        .find(|c| c.has_tag_name("rect"))?;
    let num = |a: &str| rect.attribute(a).unwrap().parse::<f64>().unwrap();
    Some((num("x"), num("y"), num("x") + num("width"), num("y") + num("height")))
}

#[test]
fn a_sliver_contact_gets_a_detail_panel_with_its_scale_and_a_deep_one_does_not() {
    let sliver = picture_of_depth(0.05);
    keep("sliver.svg", sliver.as_bytes());
    let d = doc(&sliver);
    let panel = frame_of(&d, "detail").expect("a 0.05 mm contact gets a detail panel");
    for view in ["xz", "xy", "yz"] {
        let frame = frame_of(&d, view).unwrap();
        assert!(!overlap(panel, frame), "the detail covers the {view} view");
    }
    assert!(d.descendants().any(|n| n.attribute("class") == Some("detail-region")));
    let text: String = d.descendants().filter_map(|n| n.text()).collect();
    let zoom: u32 = text
        .split("detail ×")
        .nth(1)
        .and_then(|t| t.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|z| z.parse().ok())
        .expect("the panel states its magnification");
    assert!(zoom >= 3, "×{zoom}");
    // The scale bar: the 0.05 mm depth spans many pixels in the panel.
    let bar = d
        .descendants()
        .find(|n| n.attribute("class") == Some("detail-scale"))
        .expect("the detail's scale bar");
    let path = bar.children().find(|n| n.has_tag_name("path")).unwrap();
    let xs: Vec<f64> = path
        .attribute("d")
        .unwrap()
        .split(['M', 'L'])
        .filter(|p| !p.is_empty())
        .map(|p| p.split(',').next().unwrap().parse().unwrap())
        .collect();
    let px = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    // (The page draws a text's white halo as a copy of it: the last copy is the text.)
    let label = bar.descendants().filter_map(|n| n.text()).next_back().unwrap();
    let len: f64 = label.trim_end_matches(" mm").parse().unwrap();
    assert!(
        0.05 * px / len >= 10.0,
        "0.05 mm is {} px in the detail",
        0.05 * px / len
    );
    assert_rings_clear_of_captions(&sliver);

    let deep = doc_has_detail(&picture_of_depth(8.0));
    assert!(!deep, "an 8 mm overlap is plain at the page's scale");
}

fn doc_has_detail(svg: &str) -> bool {
    frame_of(&doc(svg), "detail").is_some()
}

/// A part standing wholly between the viewer and the contact (a turret over a drill in its hole,
/// seen from above) is cut away in that view — drawn as a dotted outline, named under the views —
/// and drawn as usual in the views it does not hide the contact in.
#[test]
fn a_part_over_the_contact_is_cut_away_in_that_view_only() {
    let s = Snapshot3 {
        title: "cut away".into(),
        line: 1,
        time_s: None,
        parts: vec![
            part(
                "drill",
                cuboid([10.0, -4.0, -4.0], [40.0, 4.0, 4.0]),
                Iso::identity(),
                Role3::CollidingA,
            ),
            part(
                "stock",
                cuboid([-25.0, -25.0, -40.0], [12.0, 25.0, 40.0]),
                Iso::identity(),
                Role3::Stock,
            ),
            part(
                "turret",
                cuboid([40.0, -30.0, -30.0], [50.0, 30.0, 30.0]),
                Iso::identity(),
                Role3::Moving,
            ),
        ],
        contact: Some(Point3::new(12.0, 0.0, 0.0)),
    };
    let out = views3::svg(&s);
    keep("cut_away.svg", out.as_bytes());
    // From above (+X) the turret hid the drill: cut away, the drill shows.
    assert!(part_points(&out, "yz", "turret").is_empty());
    assert!(!part_points(&out, "yz", "drill").is_empty());
    let doc = roxmltree::Document::parse(&out).unwrap();
    let yz = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("view-yz"))
        .unwrap();
    assert!(yz.descendants().any(|n| n.attribute("class") == Some("cut-away")));
    assert!(out.contains("Cut away where it hid the contact (dotted outline): turret."));
    // From the side and the end it hides nothing: drawn.
    assert!(!part_points(&out, "xz", "turret").is_empty());
    assert!(!part_points(&out, "xy", "turret").is_empty());
}
