//! `latheguard tools show` and `latheguard tools import` (docs/tools.md).

use crate::common;
use std::path::{Path, PathBuf};

use std::process::Output;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn run(args: &[&str]) -> Output {
    common::latheguard(root(), args)
}

fn out(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("latheguard-cli-tools-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn tools_show_prints_what_cnmg_in_pclnr_decodes_to() {
    let o = run(&["tools", "show", "CNMG 120408", "PCLNR 2525M12"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let s = out(&o);
    for line in [
        "  corner angle      80°",
        "  inscribed circle  12.7 mm",
        "  thickness         4.76 mm",
        "  nose radius       0.8 mm",
        "  style             L (κr 95°)",
        "  shank             25 × 25 mm (height × width)",
        "  length            150 mm",
        "  tip direction     3",
        "  extent            x 0 .. 150, z 0 .. 32 mm from the tip",
    ] {
        assert!(s.lines().any(|l| l == line), "{line:?} missing from:\n{s}");
    }
}

#[test]
fn tools_show_json_carries_both_outlines_and_the_tip_direction() {
    let o = run(&["tools", "show", "S20S-SCLCR09", "--format", "json"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let v: serde_json::Value = serde_json::from_str(&out(&o)).unwrap();
    assert_eq!(v["tip_direction"], 2);
    assert_eq!(v["holder_code"], "S20S-SCLCR09");
    assert_eq!(v["facts"]["insert"], "implied by the holder");
    assert_eq!(v["facts"]["length"], "250 mm");
    assert!(v["insert"]
        .as_array()
        .unwrap()
        .iter()
        .any(|p| p == &serde_json::json!([0.0, 0.0])));
    assert!(v["holder"].as_array().unwrap().len() >= 4);
}

#[test]
fn tools_show_draws_the_tool_as_svg() {
    let d = scratch("svg");
    let f = d.join("t.svg");
    let o = run(&["tools", "show", "--drill", "20,60", "--svg", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(out(&o).contains("point angle       118°"), "{}", out(&o));
    let svg = std::fs::read_to_string(&f).unwrap();
    assert!(svg.starts_with("<svg") && svg.matches("<polygon").count() == 2, "{svg}");
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn tools_show_names_the_position_of_an_unknown_letter_and_exits_2() {
    let o = run(&["tools", "show", "CNMG 120408", "PCLQR 2525M12"]);
    assert_eq!(o.status.code(), Some(2));
    let e = err(&o);
    assert!(
        e.contains("holder: \"PCLQR 2525M12\": position 4 (insert clearance) is 'Q'"),
        "{e}"
    );
    let o = run(&["tools", "show", "DNMG 150608", "PCLNR 2525M12"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err(&o).contains("shape C") && err(&o).contains("shape D"),
        "{}",
        err(&o)
    );
}

#[test]
fn tools_import_prints_the_lathe_comp_table_as_a_tool_library() {
    let tbl = root().join("tests/fixtures/tools/lathe-comp.tbl");
    let o = run(&["tools", "import", tbl.to_str().unwrap(), "--units", "inch"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let lib: toml::Table = toml::from_str(&out(&o)).unwrap();
    let tools = lib["tools"].as_array().unwrap();
    assert_eq!(tools.len(), 19);
    let t6 = tools[5].as_table().unwrap();
    assert_eq!(t6["id"].as_str(), Some("T6"));
    // X0.5 Z0.5 inches.
    assert_eq!(t6["tip"].as_array().unwrap()[0].as_float(), Some(12.7));
    assert_eq!(t6["tip_direction"].as_integer(), Some(6));
    assert_eq!(t6["nose_radius"].as_float(), Some(1.27));
}

#[test]
fn imported_tools_load_as_the_tools_of_a_machine_file() {
    let tbl = root().join("tests/fixtures/tools/shop.tbl");
    let o = run(&["tools", "import", tbl.to_str().unwrap(), "--units", "inch"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let lib = out(&o);
    assert!(lib.contains("name = \"OD rough CNMG\""), "{lib}");
    // The built-in machine without its tools, and the imported ones in stations 1-4.
    let m = std::fs::read_to_string(root().join("machines/generic-slant-bed.toml")).unwrap();
    let head = &m[..m.find("[[tools]]").unwrap()];
    let mut text = head.to_string();
    text.push_str(&lib.replace("id = \"T", "station = "));
    let text: String = text
        .lines()
        .map(|l| {
            if let Some(n) = l.strip_prefix("station = ") {
                format!("station = {}", n.trim_end_matches('"'))
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    let d = scratch("machine");
    let f = d.join("m.toml");
    std::fs::write(&f, text).unwrap();
    let o = run(&["machine", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(0), "{}\n{}", err(&o), out(&o));
    std::fs::remove_dir_all(d).ok();
}

#[test]
fn tools_import_reports_the_line_and_column_of_a_bad_word() {
    let d = scratch("bad");
    let f = d.join("bad.tbl");
    std::fs::write(&f, "T1 P1 X0 Z0\nT2 P2 X0 K5\n").unwrap();
    let o = run(&["tools", "import", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        err(&o).contains("bad.tbl:2:10: 'K' is not a tool table word"),
        "{}",
        err(&o)
    );
    std::fs::remove_dir_all(d).ok();
}
