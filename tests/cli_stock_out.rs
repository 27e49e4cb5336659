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
