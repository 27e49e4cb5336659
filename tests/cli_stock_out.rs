//! `check --stock-out FILE.svg` draws the final part section of one program.

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
