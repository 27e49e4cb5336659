//! `check --stock-out FILE` writes the final part of one program: its drawing with its main
//! dimensions (`.svg`), its surface (`.stl`).

use std::process::Command;

#[test]
fn stock_out_draws_the_turned_part_of_one_program() {
    let dir = std::env::temp_dir().join(format!("lg-stock-out-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("part.svg");
    let root = env!("CARGO_MANIFEST_DIR");
    let st = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["check", "-q", &format!("{root}/programs/od_turning.nc"), "--stock-out"])
        .arg(&out)
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(0));
    let svg = std::fs::read_to_string(&out).unwrap();
    // One outline, drawn on both sides of the axis; the finished 40 mm diameter is at r = 20.
    assert_eq!(svg.matches("<polygon").count(), 2);
    assert!(svg.contains("od_turning.nc"));
    // Its dimensions: the Ø50 bar turned to Ø40 over 40 mm from the front face, 118 mm overall
    // (from the faced front at z 78 back to the bar's end at −40 in the jaws); each label's halo
    // is an element of its own.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let labels: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("stroke").is_none())
        .filter_map(|n| n.text())
        .collect();
    for want in ["Ø50", "Ø40", "40", "118"] {
        assert!(labels.contains(&want), "{want} is not a label: {labels:?}");
    }
    assert!(!svg.contains("paint-order"));
    // docs/checking.md shows this drawing: it is what the binary draws today
    // (`PART_SVG_BLESS=1` redraws it, after looking at it).
    let page = dir.join("page.svg");
    let st = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .current_dir(root)
        .args(["check", "-q", "programs/od_turning.nc", "--stock-out"])
        .arg(&page)
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(0));
    let now = std::fs::read_to_string(&page).unwrap();
    let shown = std::path::Path::new(root).join("docs/pictures/od_turning.part.svg");
    if std::env::var_os("PART_SVG_BLESS").is_some() {
        std::fs::write(&shown, &now).unwrap();
    }
    let was = std::fs::read_to_string(&shown).expect("docs/pictures/od_turning.part.svg");
    assert!(was == now, "stale: run with PART_SVG_BLESS=1 to redraw it");
    let two = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args([
            "check",
            "-q",
            &format!("{root}/programs/od_turning.nc"),
            &format!("{root}/programs/facing.nc"),
            "--stock-out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(two.status.code(), Some(2), "{}", String::from_utf8_lossy(&two.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--stock-out FILE.stl` writes the part as binary STL: a turned part is its section revolved,
/// closed, and its volume that of the finished part.
#[test]
fn stock_out_stl_writes_the_turned_part_as_a_closed_mesh() {
    let dir = std::env::temp_dir().join(format!("lg-stock-out-stl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("part.STL");
    let root = env!("CARGO_MANIFEST_DIR");
    let st = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["check", "-q", &format!("{root}/programs/od_turning.nc"), "--stock-out"])
        .arg(&out)
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(0));
    let bytes = std::fs::read(&out).unwrap();
    let mesh = latheguard::kin::stl::read_stl(&bytes, "part.STL").expect("a closed STL");
    // The same part as the JSON report's section, revolved (Pappus over each outline).
    let json = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args([
            "check",
            "-q",
            "--format",
            "json",
            &format!("{root}/programs/od_turning.nc"),
        ])
        .output()
        .unwrap();
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let mut want = 0.0;
    for o in doc["files"][0]["stock"].as_array().unwrap() {
        let p: Vec<(f64, f64)> = o
            .as_array()
            .unwrap()
            .iter()
            .map(|q| (q[0].as_f64().unwrap(), q[1].as_f64().unwrap()))
            .collect();
        let mut v = 0.0;
        for k in 0..p.len() {
            let ((x0, z0), (x1, z1)) = (p[k], p[(k + 1) % p.len()]);
            v += (x0 * x0 + x0 * x1 + x1 * x1) * (z1 - z0);
        }
        want += (std::f64::consts::PI * v / 3.0).abs();
    }
    let got = mesh.volume();
    assert!(want > 1e4 && (got - want).abs() < 0.01 * want, "{got} against {want}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The highest point of a mesh's surface straight above `(x, y)` (a ray cast along −z).
fn top_at(mesh: &latheguard::kin::Mesh, x: f64, y: f64) -> Option<f64> {
    let mut top: Option<f64> = None;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let d = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
        if d == 0.0 {
            continue;
        }
        let l1 = ((b.y - c.y) * (x - c.x) + (c.x - b.x) * (y - c.y)) / d;
        let l2 = ((c.y - a.y) * (x - c.x) + (a.x - c.x) * (y - c.y)) / d;
        let l3 = 1.0 - l1 - l2;
        if l1 >= 0.0 && l2 >= 0.0 && l3 >= 0.0 {
            let z = l1 * a.z + l2 * b.z + l3 * c.z;
            top = Some(top.map_or(z, |t: f64| t.max(z)));
        }
    }
    top
}

/// A slot an axial end mill cut into the front face of the turn-mill example's Ø50 × 120 bar is
/// in the STL at its depth (3 mm below program zero, the face 2 mm above it), the file reads back
/// as a machine part, its plain stretches are merged and its flat faces across the axis (both
/// ends, the slot's floor) are one polygon each: 46,318 triangles where the lattice made 167,172
/// (and one per node pair of the grids would be about 792,000).
#[test]
fn stock_out_stl_holds_a_face_slot_at_its_depth() {
    let dir = std::env::temp_dir().join(format!("lg-stock-out-slot-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("part.stl");
    let root = env!("CARGO_MANIFEST_DIR");
    let st = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args([
            "check",
            "-q",
            &format!("{root}/programs/turn-mill/milling/crash_rapid_into_pocket_floor.nc"),
            "--stock-out",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert_eq!(st.code(), Some(1));
    let bytes = std::fs::read(&out).unwrap();
    let mesh = latheguard::kin::stl::read_stl(&bytes, "part.stl").expect("a closed STL");
    let n = mesh.triangles.len();
    eprintln!("the Ø50 × 120 bar with a face slot: {n} triangles");
    assert!(n < 60_000, "{n} triangles");
    // Program zero is at 78 on the part (machines/turn-mill.toml), the bar's face at 80; the slot
    // runs along Y at X10 (Ø10 mill, Y−8 to Y8): its floor at Z−3.
    for (x, y, want) in [
        (10.0, 0.0, 75.0),
        (10.0, 6.0, 75.0),
        (-10.0, 0.0, 80.0),
        (10.0, -16.0, 80.0),
        (0.0, 0.0, 80.0),
    ] {
        let got = top_at(&mesh, x, y).unwrap();
        assert!((got - want).abs() < 0.05, "at ({x}, {y}): {got} against {want}");
    }
    // Ø50: nothing above the face beyond the bar's round.
    assert!(top_at(&mesh, 25.5, 0.0).is_none());
    let _ = std::fs::remove_dir_all(&dir);
}
