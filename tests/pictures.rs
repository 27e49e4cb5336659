//! What the pictures of findings (`--svg`) must show to explain a crash (issue 14, item 4): the
//! dogleg as the machine moves it, an overtravel's limit and overshoot, program coordinates and
//! Z0, a contact marker, a detail panel that covers nothing, follow-ons drawn as follow-ons.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Check one program with `--svg` and return the picture whose name contains `name`.
fn picture(program: &str, machine: Option<&str>, name: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let mut cmd = Command::cargo_bin("latheguard").unwrap();
    cmd.current_dir(root())
        .args(["check", "--quiet", "--svg"])
        .arg(dir.path())
        .arg(program);
    if let Some(m) = machine {
        cmd.args(["-m", m]);
    }
    cmd.output().unwrap();
    let found = std::fs::read_dir(dir.path())
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.file_name().unwrap().to_string_lossy().contains(name));
    let p: &Path = found.as_deref().unwrap_or_else(|| panic!("no picture with {name}"));
    std::fs::read_to_string(p).unwrap()
}

/// The `points` of the first polyline drawn with `marker`, as (x, y) pairs.
fn polyline_with(svg: &str, marker: &str) -> Vec<(f64, f64)> {
    let line = svg
        .lines()
        .find(|l| l.starts_with("<polyline") && l.contains(marker))
        .unwrap_or_else(|| panic!("no polyline with {marker}"));
    let pts = line.split("points=\"").nth(1).unwrap().split('"').next().unwrap();
    pts.split(' ')
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// The number in attribute `name` of an SVG element line.
fn attr(line: &str, name: &str) -> f64 {
    line.split(&format!(" {name}=\""))
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_dogleg_rapid_is_drawn_as_the_machine_moves_it_beside_the_programmed_line() {
    let svg = picture("programs/crash_dogleg.nc", None, "L24.rapid_into_stock");
    let m = polyline_with(&svg, "arrow-machine");
    assert_eq!(m.len(), 3, "start, the corner where the first axis arrives, end: {m:?}");
    let ((x0, y0), (x1, y1), (x2, y2)) = (m[0], m[1], m[2]);
    let turn = (x1 - x0) * (y2 - y1) - (y1 - y0) * (x2 - x1);
    assert!(turn.abs() > 10.0, "the machine path bends: {m:?}");
    // X arrives first on this move: after the corner only Z moves (horizontal in the picture).
    assert!((y2 - y1).abs() < 0.5, "{m:?}");
    assert!(svg.contains("dogleg rapid as the machine moves"), "legend");
    assert!(
        polyline_with(&svg, "url(#arrow)").len() >= 2,
        "the programmed path is drawn too"
    );
}

#[test]
fn a_straight_rapid_has_no_second_path() {
    // A rapid along one axis follows its programmed line.
    let svg = picture("programs/crash_overtravel.nc", None, "overtravel");
    assert!(!svg.contains("arrow-machine)\""), "no machine path on a one-axis rapid");
}

#[test]
fn an_overtravel_shows_the_limit_line_and_the_overshoot() {
    let svg = picture("programs/crash_overtravel.nc", None, "overtravel");
    assert!(
        svg.contains("X travel limit of the turret reference point (radius = 300 mm): 110 mm beyond"),
        "{svg}"
    );
    assert!(svg.contains("travel limit, turret reference point"), "legend");
}

#[test]
fn pictures_carry_program_coordinates_and_the_program_zero() {
    let svg = picture("programs/crash_dogleg.nc", None, "L24.rapid_into_stock");
    assert!(svg.contains(">Z0 program zero (mm)</text>"), "Z0 mark");
    for tick in [">Z-20</text>", ">Z-40</text>", ">X50</text>", ">X0</text>"] {
        assert!(svg.contains(tick), "tick {tick}");
    }
}

#[test]
fn the_contact_is_ringed_and_the_detail_panel_lies_below_the_main_view() {
    let svg = picture("tests/fixtures/pictures/small_contact.nc", None, "L6.rapid_into_stock");
    assert!(svg.contains("detail ×"), "this contact is small enough for a detail");
    let plot = svg.lines().find(|l| l.contains(r##"fill="#fbfbfa""##)).unwrap();
    let bottom = attr(plot, "y") + attr(plot, "height");
    let frame = svg
        .lines()
        .find(|l| l.starts_with("<rect") && l.contains(r#"stroke-width="1.5""#))
        .expect("the detail's frame");
    assert!(attr(frame, "y") > bottom, "the detail covers nothing of the main view");
    assert!(
        svg.contains(r##"stroke="#e5151b" stroke-width="2.2""##),
        "the contact ring"
    );
}

#[test]
fn a_follow_on_contact_is_drawn_in_the_follow_on_colour() {
    // The same two parts still inside each other under another rule: a follow-on.
    let svg = picture(
        "tests/fixtures/follow-on/rapid_then_stopped_feed.nc",
        None,
        "L7.spindle_stopped.T01-insert.stock",
    );
    assert!(svg.contains("follow-on of the crash at line 6"), "caption");
    assert!(
        svg.contains(r##"fill="#f08c00" stroke="#f08c00" stroke-width="3""##),
        "overlap"
    );
    assert!(svg.contains("overlap (follow-on of an earlier crash)"), "legend");
    assert!(!svg.contains("overlap at first contact"));
}

/// A follow-on on a turn-mill machine names the crash it follows in the words that crash's own
/// finding uses ("the T09 holder", "the part in the sub-spindle's chuck"), in the text report
/// and on its picture; JSON keeps the machine file's ids. (Drawing this picture also once
/// indexed past the components known before the sub-spindle took the part.)
#[test]
fn a_follow_on_names_the_parent_crash_in_words_in_the_text_and_the_pictures() {
    let program = "programs/turn-mill/pick-off/crash_rapid_into_picked_part.nc";
    let out = Command::cargo_bin("latheguard")
        .unwrap()
        .current_dir(root())
        .args(["check", program])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains(
            "follow-on of the crash at line 33 between the T09 holder and the part in the sub-spindle's chuck"
        ),
        "{text}"
    );
    assert!(
        !text.contains("t9_holder") && !text.contains("part_in_sub_chuck"),
        "{text}"
    );
    let out = Command::cargo_bin("latheguard")
        .unwrap()
        .current_dir(root())
        .args(["check", "--format", "json", program])
        .output()
        .unwrap();
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let parents: Vec<&serde_json::Value> = json["files"][0]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|f| f.get("follow_on"))
        .collect();
    assert!(parents
        .iter()
        .any(|p| p["objects"] == serde_json::json!(["t9_holder", "part_in_sub_chuck"])));
    let svg = picture(program, None, "L34.collision.t9_holder");
    let message = svg.lines().find(|l| l.contains(r#"y="46""#)).expect("the message line");
    assert!(
        message.contains("the T09 holder hits the part in the sub-spindle")
            && message.ends_with("— follow-on of the crash at line 33</text>"),
        "{message}"
    );
    assert!(!svg.lines().take(8).any(|l| l.contains("t9_")), "no ids in the caption");
}
