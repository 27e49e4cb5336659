//! Reports of 3D findings (issue 15): the three orthographic views (`report::views3`), the glTF
//! binary (`report::glb`) and the `--glb DIR` option.
//!
//! Meshes are built here (a box, a tessellated cylinder): converting machine geometry to meshes
//! is another module's job.

mod common;

use latheguard::finding::{Finding, Kind, Severity};
use latheguard::kin::{Iso, Mesh};
use latheguard::report::scene3::{Part3, Role3, Snapshot3};
use latheguard::report::{glb, svg, views3, FileReport, Report};
use nalgebra::{Point3, Vector3};
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
    for name in [
        "T05 holder",
        "sub chuck",
        "first contact",
        "fixed parts",
        "stock at that moment",
    ] {
        assert!(legend_text.contains(name), "{name} not in the legend: {legend_text}");
    }
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
