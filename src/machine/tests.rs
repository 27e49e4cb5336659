//! Tests of the machine loader: the shipped machines, the defaults, and that every class of bad
//! input is refused at the right line and key.

use super::*;
use crate::geom::p2;
use proptest::prelude::*;

const LINUXCNC_TOML: &str = include_str!("../../machines/linuxcnc-small-lathe.toml");

/// A small machine that leaves every optional key to its default.
const MINI: &str = r#"[machine]
name = "mini"

[axes]
x = { min = -10.0, max = 300.0, rapid = 20000.0 }
z = { min = -50.0, max = 600.0, rapid = 24000.0 }

[spindle]
max_rpm = 4000.0

[chuck]
outline = [[25, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0]]

[stock]
diameter = 50.0
length = 120.0
front = 80.0

[turret]
stations = 8
axis = 140.0
index_time = 0.5
outline = [[0, -35], [280, -35], [280, 35], [0, 35]]

[[tools]]
station = 1
name = "one"
tip = [-60.0, -12.0]
insert = [[0, 0], [12, 2], [14, 14], [2, 12]]
holder = [[5, 8], [60, 8], [60, 33], [8, 33]]

[[tools]]
station = 2
name = "two"
tip = [-58.0, -10.0]
insert = [[0, 0], [12, 2], [14, 14], [2, 12]]
holder = [[5, 8], [60, 8], [60, 33], [8, 33]]

[[tools]]
station = 3
name = "three"
tip = [-31.0, -90.0]
insert = [[0, 0], [-6, 0.5], [-6.5, 6.5], [-0.5, 6]]
holder = [[-15, 2], [-3, 2], [-3, 50], [-15, 50]]
"#;

fn load(text: &str) -> Result<Machine, MachineError> {
    from_toml(text, "test.toml")
}

#[track_caller]
fn refused(text: &str) -> MachineError {
    match load(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// `text` with the first `from` replaced by `to`.
#[track_caller]
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "{from:?} is not in the text");
    text.replacen(from, to, 1)
}

/// 1-based line of the first line containing `needle`.
#[track_caller]
fn line_of(text: &str, needle: &str) -> u32 {
    let i = text
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("{needle:?} not found"));
    i as u32 + 1
}

/// 1-based line of the `n`th (from 0) line equal to `needle` after trimming.
fn nth_line(text: &str, needle: &str, n: usize) -> u32 {
    let i = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == needle)
        .nth(n)
        .expect("line not found")
        .0;
    i as u32 + 1
}

#[track_caller]
fn assert_at(e: &MachineError, line: u32, key: &str) {
    assert_eq!((e.line, e.key.as_str()), (line, key), "wrong place for: {e}");
    assert_eq!(e.file, "test.toml");
    assert!(e.col >= 1, "no column: {e}");
}

/// Same vertices in the same cyclic order.
fn same_cycle(a: &Polygon, b: &Polygon) -> bool {
    let (a, b) = (a.points(), b.points());
    a.len() == b.len() && (0..a.len()).any(|k| (0..a.len()).all(|i| a[(i + k) % a.len()] == b[i]))
}

// --- the shipped machines -------------------------------------------------------------------

#[test]
fn builtin_machine_loads_with_eight_tools_in_stations_1_to_8() {
    let m = Machine::builtin();
    assert_eq!(m.name, "Generic 2-axis slant-bed lathe");
    assert_eq!(m.dialect, Dialect::Fanuc);
    assert!(m.diameter_mode);
    assert_eq!(m.rapid, RapidMode::Dogleg);
    assert_eq!(m.decimal_point, DecimalPoint::Calculator);
    assert_eq!(m.turret.stations, 8);
    assert_eq!(
        m.tools.iter().map(|t| t.station).collect::<Vec<_>>(),
        (1..=8).collect::<Vec<_>>()
    );
    assert_eq!(m.stock, Some(Stock::bar(50.0, 120.0, 80.0, 0.0)));
    assert_eq!(m.program_zero_z, 78.0);
    assert!(m.chuck.is_some());
    assert!(m.tailstock.is_none());
}

/// The examples of docs/machine.md quote these values; the built-in machine must keep them.
#[test]
fn builtin_machine_keeps_the_values_design_quotes() {
    let m = Machine::builtin();
    assert_eq!(
        (m.x, m.z),
        (
            Axis {
                min: -10.0,
                max: 300.0,
                rapid: 20000.0
            },
            Axis {
                min: -50.0,
                max: 600.0,
                rapid: 24000.0
            }
        )
    );
    assert_eq!(m.home, p2(300.0, 600.0));
    assert_eq!(m.max_rpm, 4000.0);
    assert_eq!(
        (m.turret.start_station, m.turret.axis, m.turret.index_time),
        (1, 140.0, 0.5)
    );
    let t1 = m.tool(1).unwrap();
    assert_eq!(
        (t1.name.as_str(), t1.tip, t1.nose_radius),
        ("OD rough CNMG 80", p2(-60.0, -12.0), 0.8)
    );
    let chuck = [
        [25, -100],
        [105, -100],
        [105, -30],
        [70, -30],
        [70, -12],
        [45, -12],
        [45, 0],
        [25, 0],
    ];
    let chuck = Polygon::new(&chuck.map(|[x, z]| p2(x as f64, z as f64))).unwrap();
    assert!(same_cycle(m.chuck.as_ref().unwrap(), &chuck));
}

/// The geometry other parts of latheguard rely on: the boring bar enters a 20 mm bore, the drill
/// is on the axis, and the long bar reaches far past every other tool.
#[test]
fn builtin_tools_have_the_promised_geometry() {
    let m = Machine::builtin();
    let bar = m.tool(3).unwrap();
    // Tip on the wall of a 20 mm bore (x = 10): the part of the tool within 60 mm of the tip
    // (inside the bore) stays within radius 10.
    for p in bar.holder.points().iter().chain(bar.insert.points()) {
        if p.y < 45.0 {
            assert!(
                (10.0 + p.x).abs() <= 10.0,
                "boring bar point {p:?} is outside a 20 mm bore"
            );
        }
    }
    let drill = m.tool(6).unwrap();
    let b = drill.insert.aabb();
    assert_eq!(
        (b.min.x, b.max.x, b.min.y),
        (-10.0, 10.0, 0.0),
        "a 20 mm drill pointing toward -z"
    );
    let reach = |t: &Tool| t.tip.y + t.insert.aabb().min.y.min(t.holder.aabb().min.y);
    let long = reach(m.tool(7).unwrap());
    for t in m.tools.iter().filter(|t| t.station != 7) {
        assert!(
            reach(t) > long + 50.0,
            "tool {} reaches as far as the long bar",
            t.station
        );
    }
}

#[test]
fn linuxcnc_machine_loads_in_radius_mode_with_a_tailstock() {
    let m = load(LINUXCNC_TOML).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.dialect, Dialect::Linuxcnc);
    assert!(!m.diameter_mode);
    assert_eq!(m.rapid, RapidMode::Linear);
    assert!(m.tailstock.is_some());
    assert_eq!(m.stock.as_ref().map(|s| s.diameter), Some(25.0));
    assert_eq!(m.turret.stations, 4);
    assert_eq!(m.tools.len(), 4);
}

#[test]
fn describe_names_the_machine_and_every_tool() {
    let m = Machine::builtin();
    let d = m.describe();
    assert!(d.starts_with("Generic 2-axis slant-bed lathe\n"), "{d}");
    for needle in [
        "fanuc",
        "diameters",
        "dogleg",
        "-10 .. 300",
        "-50 .. 600",
        "tailstock   none",
        "bar Ø50",
        "8 stations",
    ] {
        assert!(d.contains(needle), "{needle:?} missing from:\n{d}");
    }
    for t in &m.tools {
        assert!(
            d.lines()
                .any(|l| l.contains(&t.name) && l.trim_start().starts_with(&t.station.to_string())),
            "{}",
            t.name
        );
    }
    let d = load(LINUXCNC_TOML).unwrap().describe();
    assert!(
        d.contains("linuxcnc") && d.contains("radii") && d.contains("linear") && !d.contains("decimal point"),
        "{d}"
    );
}

// --- defaults --------------------------------------------------------------------------------

#[test]
fn defaults_fill_every_optional_key() {
    let m = load(MINI).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.dialect, Dialect::Fanuc);
    assert!(m.diameter_mode);
    assert_eq!(m.rapid, RapidMode::Dogleg);
    assert_eq!(m.decimal_point, DecimalPoint::Calculator);
    assert_eq!(m.home, p2(300.0, 600.0), "home defaults to both maxima");
    assert_eq!(m.stock.as_ref().unwrap().bore, 0.0);
    assert_eq!(m.program_zero_z, 80.0, "program Z0 defaults to the stock's front face");
    assert_eq!(m.turret.start_station, 1);
    assert!(m.tools.iter().all(|t| t.nose_radius == 0.0));
    assert!(m.tailstock.is_none());
}

#[test]
fn linuxcnc_defaults_to_radius_mode() {
    let m = load(&edit(
        MINI,
        "name = \"mini\"",
        "name = \"mini\"\ndialect = \"linuxcnc\"",
    ))
    .unwrap();
    assert!(!m.diameter_mode);
    let m = load(&edit(
        MINI,
        "name = \"mini\"",
        "name = \"mini\"\ndialect = \"linuxcnc\"\ndiameter_mode = true",
    ))
    .unwrap();
    assert!(m.diameter_mode);
}

#[test]
fn program_zero_defaults_to_the_jaw_faces_without_stock() {
    let text = edit(MINI, "[stock]\ndiameter = 50.0\nlength = 120.0\nfront = 80.0\n", "");
    let m = load(&text).unwrap();
    assert!(m.stock.is_none());
    assert_eq!(m.program_zero_z, 0.0);
}

#[test]
fn chuck_tailstock_and_stock_are_optional() {
    let text = edit(MINI, "[stock]\ndiameter = 50.0\nlength = 120.0\nfront = 80.0\n", "");
    let text = edit(&text, "[chuck]\n", "");
    let text = edit(
        &text,
        "outline = [[25, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0]]\n",
        "",
    );
    let m = load(&text).unwrap_or_else(|e| panic!("{e}"));
    assert!(m.chuck.is_none() && m.tailstock.is_none() && m.stock.is_none());
}

#[test]
fn tools_are_sorted_by_station() {
    let text = edit(MINI, "station = 1\n", "station = 7\n");
    let m = load(&text).unwrap();
    assert_eq!(m.tools.iter().map(|t| t.station).collect::<Vec<_>>(), [2, 3, 7]);
    assert_eq!(m.tool(7).unwrap().name, "one");
}

// --- outlines --------------------------------------------------------------------------------

#[test]
fn outline_winding_and_redundant_points_do_not_change_the_polygon() {
    let base = load(MINI).unwrap().chuck.unwrap();
    let forms = [
        // clockwise
        "[[25, 0], [45, 0], [45, -12], [70, -12], [70, -30], [105, -30], [105, -100], [25, -100]]",
        // clockwise, starting elsewhere, closed explicitly
        "[[70, -12], [70, -30], [105, -30], [105, -100], [25, -100], [25, 0], [45, 0], [45, -12], [70, -12]]",
        // duplicates and collinear points on edges
        "[[25, -100], [25, -100], [60, -100], [105, -100], [105, -60], [105, -30], [70, -30], [70, -30], [70, -12], [45, -12], [45, -6], [45, 0], [35, 0], [25, 0], [25, -50]]",
    ];
    for form in forms {
        let text = edit(
            MINI,
            "outline = [[25, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0]]",
            &format!("outline = {form}"),
        );
        let m = load(&text).unwrap_or_else(|e| panic!("{form}: {e}"));
        let chuck = m.chuck.unwrap();
        assert!(same_cycle(&chuck, &base), "{form} gave {:?}", chuck.points());
        assert!(chuck.area() > 0.0);
    }
}

#[test]
fn self_intersecting_chuck_outline_is_refused_at_its_key() {
    let text = edit(
        MINI,
        "[[25, -100], [105, -100], [105, -30]",
        "[[25, -100], [105, -30], [105, -100]",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "[[25, -100], [105, -30]"), "chuck.outline");
    assert!(e.message.contains("intersects itself"), "{e}");
    assert!(
        e.message.contains("point [0]") || e.message.contains("point [1]"),
        "{e}"
    );
}

#[test]
fn degenerate_holder_outline_is_refused_at_its_key() {
    let text = edit(
        MINI,
        "holder = [[-15, 2], [-3, 2], [-3, 50], [-15, 50]]",
        "holder = [[0, 0], [5, 5], [10, 10], [5, 5]]",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "holder = [[0, 0], [5, 5]"), "tools[2].holder");
    assert!(e.message.contains("fewer than 3"), "{e}");
}

#[test]
fn point_with_three_numbers_is_refused_at_its_index() {
    let text = edit(
        MINI,
        "[[0, -35], [280, -35], [280, 35], [0, 35]]",
        "[[0, -35], [280, -35, 1], [280, 35], [0, 35]]",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "[280, -35, 1]"), "turret.outline[1]");
    assert!(e.message.contains("expected 2 numbers, found 3"), "{e}");
}

#[test]
fn outline_of_20000_points_is_refused_before_it_is_normalised() {
    let pts: Vec<String> = (0..20_000)
        .map(|i| {
            let a = i as f64 / 20_000.0 * std::f64::consts::TAU;
            format!("[{}, {}]", 30.0 + 20.0 * a.cos(), 20.0 * a.sin())
        })
        .collect();
    let text = edit(
        MINI,
        "outline = [[0, -35], [280, -35], [280, 35], [0, 35]]",
        &format!("outline = [{}]", pts.join(", ")),
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "outline = [[50, 0]"), "turret.outline");
    assert!(e.message.contains("too many points: 20000"), "{e}");
}

#[test]
fn outlines_over_the_file_limit_are_refused() {
    // Three outlines of 7,000 points each: each under the outline limit, together over the file's.
    let circle = |n: usize| -> String {
        let pts: Vec<String> = (0..n)
            .map(|i| {
                let a = i as f64 / n as f64 * std::f64::consts::TAU;
                format!("[{}, {}]", 20.0 * a.cos(), 20.0 * a.sin())
            })
            .collect();
        format!("[{}]", pts.join(","))
    };
    let big = circle(7_000);
    let text = edit(
        MINI,
        "holder = [[5, 8], [60, 8], [60, 33], [8, 33]]",
        &format!("holder = {big}"),
    );
    let text = edit(
        &text,
        "holder = [[5, 8], [60, 8], [60, 33], [8, 33]]",
        &format!("holder = {big}"),
    );
    let text = edit(
        &text,
        "holder = [[-15, 2], [-3, 2], [-3, 50], [-15, 50]]",
        &format!("holder = {big}"),
    );
    let e = refused(&text);
    assert_eq!(e.key, "tools[2].holder", "{e}");
    assert!(e.message.contains("at most 20000 in all"), "{e}");
}

// --- each class of error, at its line and key -----------------------------------------------

#[test]
fn unknown_key_is_refused_at_its_line_and_key() {
    let text = edit(MINI, "front = 80.0\n", "front = 80.0\ncolour = \"red\"\n");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "colour"), "stock.colour");
    assert_eq!(e.col, 1);
    assert!(e.message.contains("unknown key `colour`"), "{e}");
}

#[test]
fn a_misspelt_key_or_value_gets_the_closest_one_as_a_suggestion() {
    let text = edit(MINI, "front = 80.0\n", "frnt = 80.0\n");
    let e = refused(&text);
    assert!(
        e.message.contains("unknown key `frnt`") && e.message.ends_with("did you mean `front`?"),
        "{e}"
    );
    // Nothing close: no suggestion.
    let text = edit(MINI, "front = 80.0\n", "front = 80.0\ncolour = \"red\"\n");
    assert!(!refused(&text).message.contains("did you mean"));
    assert_eq!(
        did_you_mean("unknown field `turet`, expected one of `machine`, `turret`, `tools`").as_deref(),
        Some("turret")
    );
    assert_eq!(
        did_you_mean("unknown variant `Fanuc`, expected `fanuc` or `linuxcnc`").as_deref(),
        Some("fanuc")
    );
    assert_eq!(
        did_you_mean("unknown variant `fanux`, expected `fanuc` or `linuxcnc`").as_deref(),
        Some("fanuc")
    );
    assert_eq!(did_you_mean("unknown field `x`, expected `z`").as_deref(), Some("z"));
    assert_eq!(did_you_mean("invalid type: string, expected an array"), None);
}

#[test]
fn unknown_key_in_an_inline_table_is_refused_at_its_key() {
    let text = edit(MINI, "rapid = 24000.0 }", "rapid = 24000.0, accel = 2 }");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "accel"), "axes.z.accel");
}

#[test]
fn unknown_table_is_refused_at_its_header() {
    let text = format!("{MINI}\n[coolant]\nflow = 3\n");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "[coolant]"), "coolant");
}

#[test]
fn unknown_key_in_the_third_tool_names_its_index() {
    let text = edit(MINI, "name = \"three\"\n", "name = \"three\"\nlength = 90\n");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "length = 90"), "tools[2].length");
}

#[test]
fn wrong_type_is_refused_at_its_line_and_key() {
    let text = edit(MINI, "diameter = 50.0", "diameter = \"fifty\"");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "diameter ="), "stock.diameter");
    assert_eq!(e.col, 12, "the column of the value");
    assert!(e.message.contains("expected a number"), "{e}");

    let text = edit(MINI, "holder = [[-15, 2], [-3, 2], [-3, 50], [-15, 50]]", "holder = 5");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "holder = 5"), "tools[2].holder");
    assert!(
        e.message
            .ends_with("expected a catalogue designation (a string) or an outline [[x, z], ...]"),
        "{e}"
    );

    let text = edit(MINI, "station = 2", "station = 2.5");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "station = 2.5"), "tools[1].station");

    let text = edit(MINI, "x = { min = -10.0,", "x = { min = true,");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "min = true"), "axes.x.min");
}

#[test]
fn unknown_dialect_is_refused_at_its_key() {
    let text = edit(MINI, "name = \"mini\"", "name = \"mini\"\ndialect = \"haas\"");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "haas"), "machine.dialect");
    assert!(e.message.contains("fanuc") && e.message.contains("linuxcnc"), "{e}");
}

#[test]
fn missing_key_is_refused_at_its_table() {
    let text = MINI.replacen("station = 2\n", "", 1);
    let e = refused(&text);
    assert_at(&e, nth_line(&text, "[[tools]]", 1), "tools[1].station");
    assert!(e.message.contains("missing required key `station`"), "{e}");

    let text = edit(MINI, "max = 300.0, ", "");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "x = {"), "axes.x.max");

    let text = edit(MINI, "[spindle]\nmax_rpm = 4000.0\n", "");
    let e = refused(&text);
    assert_at(&e, 1, "spindle");
}

#[test]
fn toml_syntax_error_is_refused_at_its_line_and_key() {
    let text = edit(MINI, "max_rpm = 4000.0", "max_rpm = 4000.0.0");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "max_rpm"), "spindle.max_rpm");
    assert!(e.message.starts_with("TOML syntax error"), "{e}");

    let text = edit(MINI, "max = 300.0, rapid", "max = 300.0 rapid");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "max = 300.0 rapid"), "axes.x");

    let text = edit(MINI, "name = \"two\"", "name = \"two");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "name = \"two"), "tools[1].name");

    let e = refused("[machine\nname = \"x\"\n");
    assert_eq!((e.line, e.key.as_str()), (1, "machine"), "{e}");

    let e = refused("= 3\n[machine]\nname = \"x\"\n");
    assert_eq!((e.line, e.key.as_str()), (1, TOP_LEVEL), "{e}");

    // A broken row of a multi-line outline is not a table header.
    let text = edit(
        MINI,
        "outline = [[0, -35], [280, -35], [280, 35], [0, 35]]",
        "outline = [\n  [0, -35],\n  [280 -35],\n  [280, 35],\n]",
    );
    let e = refused(&text);
    assert_eq!(e.line, line_of(&text, "[280 -35]"), "{e}");
    assert!(e.key.starts_with("turret.outline["), "{e}");
}

#[test]
fn duplicate_toml_key_is_refused_at_the_second() {
    let text = edit(MINI, "length = 120.0\n", "length = 120.0\nlength = 100.0\n");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "length = 100.0"), "stock.length");
    assert!(e.message.contains("duplicate key"), "{e}");

    let text = format!("{MINI}\n[stock]\nbore = 3\n");
    let e = refused(&text);
    assert_eq!(
        (e.line, e.key.as_str()),
        (nth_line(&text, "[stock]", 1), "stock"),
        "{e}"
    );
}

#[test]
fn negative_stock_diameter_is_refused() {
    let text = edit(MINI, "diameter = 50.0", "diameter = -50.0");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "diameter ="), "stock.diameter");
    assert!(e.message.contains("greater than 0"), "{e}");
}

#[test]
fn bore_not_smaller_than_diameter_is_refused() {
    for bore in ["50.0", "60"] {
        let text = edit(MINI, "front = 80.0\n", &format!("front = 80.0\nbore = {bore}\n"));
        let e = refused(&text);
        assert_at(&e, line_of(&text, "bore ="), "stock.bore");
        assert!(e.message.contains("smaller than the diameter"), "{e}");
    }
    let text = edit(MINI, "front = 80.0\n", "front = 80.0\nbore = -1\n");
    assert_at(&refused(&text), line_of(&text, "bore ="), "stock.bore");
    let text = edit(MINI, "front = 80.0\n", "front = 80.0\nbore = 20\n");
    assert_eq!(load(&text).unwrap().stock.unwrap().bore, 20.0);
}

#[test]
fn duplicate_station_is_refused_at_the_second_tool() {
    let text = edit(MINI, "station = 3", "station = 1");
    let e = refused(&text);
    assert_at(&e, nth_line(&text, "station = 1", 1), "tools[2].station");
    assert!(e.message.contains("already taken by tools[0]"), "{e}");
}

#[test]
fn station_out_of_range_is_refused() {
    for bad in ["9", "0"] {
        let text = edit(MINI, "station = 2", &format!("station = {bad}"));
        let e = refused(&text);
        assert_at(&e, line_of(&text, &format!("station = {bad}")), "tools[1].station");
        assert!(e.message.contains("stations 1 to 8"), "{e}");
    }
    let text = edit(MINI, "station = 2", "station = -2");
    assert_at(&refused(&text), line_of(&text, "station = -2"), "tools[1].station");
}

#[test]
fn turret_station_count_and_start_are_checked() {
    let text = edit(MINI, "stations = 8", "stations = 65");
    assert_at(&refused(&text), line_of(&text, "stations = 65"), "turret.stations");
    let text = edit(MINI, "stations = 8", "stations = 0");
    assert_at(&refused(&text), line_of(&text, "stations = 0"), "turret.stations");
    let text = edit(MINI, "stations = 8", "stations = 8\nstart_station = 9");
    assert_at(&refused(&text), line_of(&text, "start_station"), "turret.start_station");
    let text = edit(MINI, "index_time = 0.5", "index_time = -0.5");
    assert_at(&refused(&text), line_of(&text, "index_time"), "turret.index_time");
    let text = edit(MINI, "axis = 140.0", "axis = nan");
    assert_at(&refused(&text), line_of(&text, "axis = nan"), "turret.axis");
}

#[test]
fn turret_stations_errors_state_the_range_the_loader_accepts() {
    for bad in ["0", "-1", "65", "5000000000"] {
        let text = edit(MINI, "stations = 8", &format!("stations = {bad}"));
        let e = refused(&text);
        assert_at(&e, line_of(&text, "stations = "), "turret.stations");
        assert_eq!(e.message, format!("{bad} stations: a turret has 1 to {MAX_STATIONS}"));
    }
    let e = refused(&edit(MINI, "stations = 8", "stations = 4.5"));
    assert_eq!(e.message, "invalid type: floating point `4.5`, expected a whole number");
    for ok in [1, MAX_STATIONS] {
        // Only the turret's count is under test (with 1 station, the other tools are refused).
        if let Err(e) = load(&edit(MINI, "stations = 8", &format!("stations = {ok}"))) {
            assert!(!e.to_string().contains("turret.stations"), "{e}");
        }
    }
    let schema: serde_json::Value = serde_json::from_str(&schema()).unwrap();
    let s = &schema["$defs"]["RawTurret"]["properties"]["stations"];
    assert_eq!(
        (s["minimum"].as_u64(), s["maximum"].as_u64()),
        (Some(1), Some(u64::from(MAX_STATIONS)))
    );
}

#[test]
fn no_tools_is_refused() {
    let cut = MINI.find("[[tools]]").unwrap();
    let e = refused(&MINI[..cut]);
    assert_at(&e, 1, "tools");
    assert!(e.message.contains("missing tools"), "{e}");

    let text = format!("tools = []\n{}", &MINI[..cut]);
    let e = refused(&text);
    assert_at(&e, 1, "tools");
    assert!(e.message.contains("missing tools"), "{e}");
}

#[test]
fn too_many_tools_are_refused() {
    let cut = MINI.find("[[tools]]").unwrap();
    let mut text = MINI[..cut].to_string();
    for i in 0..300 {
        text.push_str(&format!("[[tools]]\nstation = {i}\nname = \"t\"\ntip = [0, 0]\ninsert = [[0, 0], [1, 0], [0, 1]]\nholder = [[0, 0], [1, 0], [0, 1]]\n"));
    }
    let e = refused(&text);
    assert_at(&e, nth_line(&text, "[[tools]]", 256), "tools[256]");
    assert!(e.message.contains("too many tools: 300"), "{e}");
}

#[test]
fn blank_names_are_refused() {
    let text = edit(MINI, "name = \"two\"", "name = \"  \"");
    assert_at(&refused(&text), line_of(&text, "name = \"  \""), "tools[1].name");
    let text = edit(MINI, "name = \"mini\"", "name = \"\"");
    assert_at(&refused(&text), 2, "machine.name");
}

#[test]
fn home_outside_limits_is_refused() {
    let text = edit(
        MINI,
        "rapid = 24000.0 }\n",
        "rapid = 24000.0 }\nhome = [301.0, 600.0]\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "home ="), "axes.home");
    assert!(e.message.contains("outside"), "{e}");
    let text = edit(MINI, "rapid = 24000.0 }\n", "rapid = 24000.0 }\nhome = [300.0, -51]\n");
    assert_at(&refused(&text), line_of(&text, "home ="), "axes.home");
    let text = edit(MINI, "rapid = 24000.0 }\n", "rapid = 24000.0 }\nhome = [200, 0]\n");
    assert_eq!(load(&text).unwrap().home, p2(200.0, 0.0));
}

#[test]
fn reference_points_are_at_most_three_inside_the_axis_limits() {
    let with = |pts: &str| {
        edit(
            MINI,
            "rapid = 24000.0 }\n",
            &format!("rapid = 24000.0 }}\nreference_points = {pts}\n"),
        )
    };
    let text = with("[[250, 500], [100, 0]]");
    assert_eq!(
        load(&text).unwrap().reference_points,
        vec![p2(250.0, 500.0), p2(100.0, 0.0)]
    );
    let text = with("[[1, 1], [2, 2], [3, 3], [4, 4]]");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "reference_points ="), "axes.reference_points");
    assert_eq!(
        e.message,
        "4 points: these are the 2nd, 3rd and 4th reference points (G30 P2 to P4), at most 3"
    );
    let text = with("[[1, 1], [301, 2]]");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "reference_points ="), "axes.reference_points[1]");
    assert_eq!(
        e.message,
        "the 3rd reference point [301, 2] lies outside the axis limits (x -10 .. 300, z -50 .. 600)"
    );
    assert!(e.also.is_empty(), "{e}");
}

#[test]
fn axis_limits_and_rates_are_checked() {
    let text = edit(MINI, "min = -10.0", "min = 300.0");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "x = {"), "axes.x.min");
    assert!(e.message.contains("less than max"), "{e}");
    let text = edit(MINI, "rapid = 24000.0", "rapid = 0");
    assert_at(&refused(&text), line_of(&text, "z = {"), "axes.z.rapid");
    let text = edit(MINI, "max = 600.0", "max = inf");
    assert_at(&refused(&text), line_of(&text, "z = {"), "axes.z.max");
}

#[test]
fn spindle_speed_and_nose_radius_are_checked() {
    let text = edit(MINI, "max_rpm = 4000.0", "max_rpm = 0");
    assert_at(&refused(&text), line_of(&text, "max_rpm"), "spindle.max_rpm");
    let text = edit(MINI, "name = \"two\"", "name = \"two\"\nnose_radius = -0.4");
    assert_at(&refused(&text), line_of(&text, "nose_radius"), "tools[1].nose_radius");
    let text = edit(MINI, "tip = [-58.0, -10.0]", "tip = [-58.0, inf]");
    assert_at(&refused(&text), line_of(&text, "inf]"), "tools[1].tip");
}

#[test]
fn increment_decimal_point_is_refused_for_linuxcnc() {
    let text = edit(
        MINI,
        "name = \"mini\"",
        "name = \"mini\"\ndialect = \"linuxcnc\"\ndecimal_point = \"increment\"",
    );
    assert_at(
        &refused(&text),
        line_of(&text, "decimal_point"),
        "machine.decimal_point",
    );
    let text = edit(
        MINI,
        "name = \"mini\"",
        "name = \"mini\"\ndecimal_point = \"increment\"",
    );
    assert_eq!(load(&text).unwrap().decimal_point, DecimalPoint::Increment);
}

#[test]
fn drill_r_follows_the_key_else_the_drilling_cycles() {
    use super::{DrillR, DrillingCycles, G71D};
    let m = load(MINI).unwrap();
    assert_eq!((m.drill_r(), m.g71_d), (DrillR::Absolute, G71D::Length));
    let fanuc_cycles = Machine {
        drilling_cycles: DrillingCycles::Fanuc,
        ..m.clone()
    };
    assert_eq!(fanuc_cycles.drill_r(), DrillR::Incremental);
    let with = |keys: &str| edit(MINI, "name = \"mini\"", &format!("name = \"mini\"\n{keys}"));
    let m = load(&with("drill_r = \"incremental\"\ng71_d = \"increment\"")).unwrap();
    assert_eq!((m.drill_r(), m.g71_d), (DrillR::Incremental, G71D::Increment));
    assert_eq!(Machine::builtin().drill_r(), DrillR::Incremental);
    // Fanuc's live-tool cycles measure R from the initial level; linuxcnc has its own rules.
    for keys in [
        "drilling_cycles = \"fanuc\"\ndrill_r = \"absolute\"",
        "dialect = \"linuxcnc\"\ndrill_r = \"absolute\"",
    ] {
        let text = with(keys);
        assert_at(&refused(&text), line_of(&text, "drill_r"), "machine.drill_r");
    }
    let text = with("dialect = \"linuxcnc\"\ng71_d = \"increment\"");
    assert_at(&refused(&text), line_of(&text, "g71_d"), "machine.g71_d");
}

#[test]
fn error_display_names_file_line_column_and_key() {
    let text = edit(MINI, "diameter = 50.0", "diameter = -5");
    let e = refused(&text);
    let line = line_of(&text, "diameter =");
    assert_eq!(
        e.to_string(),
        format!("test.toml:{line}:12: stock.diameter: must be greater than 0, not -5")
    );
}

// --- never a panic ---------------------------------------------------------------------------

#[track_caller]
fn check_error_shape(text: &str) {
    if let Err(e) = load(text) {
        assert!(e.line >= 1 && e.col >= 1, "{e}");
        assert!(!e.key.is_empty(), "{e}");
        let lines = crate::source::LineIndex::new(text.as_bytes()).line_count() as u32;
        assert!(e.line <= lines.max(1), "line {} of {lines}: {e}", e.line);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_text_never_panics(text in "\\PC*") {
        check_error_shape(&text);
    }

    #[test]
    fn toml_like_text_never_panics(text in "([\\[\\]{}=,.\"' \n#a-z0-9_-]|tools|outline|station|\\[\\[tools\\]\\]|inf|nan){0,200}") {
        check_error_shape(&text);
    }

    #[test]
    fn damaged_builtin_machine_never_panics(
        cut in 0usize..BUILTIN_TOML.len(),
        len in 0usize..12,
        insert in "([\\[\\]{}=,.\"' \n#0-9-]|inf|1e9|station|9){0,6}",
    ) {
        let mut text = BUILTIN_TOML.to_string();
        let end = (cut + len).min(text.len());
        if text.is_char_boundary(cut) && text.is_char_boundary(end) {
            text.replace_range(cut..end, &insert);
        }
        check_error_shape(&text);
    }
}

// --- hostile values: physical ranges, unit mistakes, home clearance, size -------------------

#[test]
fn shipped_machines_have_no_warnings() {
    assert!(Machine::builtin().warnings.is_empty());
    assert!(load(LINUXCNC_TOML).unwrap().warnings.is_empty());
    assert!(load(MINI).unwrap().warnings.is_empty());
}

#[test]
fn machine_values_that_never_finish_are_refused_with_their_range() {
    // Each of these was accepted and made every check endless or lost its results.
    let cases = [
        (
            "rapid = 20000.0",
            "rapid = 1e-300",
            "x = {",
            "axes.x.rapid",
            "1 to 1000000 mm/min",
        ),
        (
            "max_rpm = 4000.0",
            "max_rpm = 1e-300",
            "max_rpm",
            "spindle.max_rpm",
            "1 to 1000000 rpm",
        ),
        (
            "index_time = 0.5",
            "index_time = 1e300",
            "index_time",
            "turret.index_time",
            "0 to 60 s",
        ),
        (
            "tip = [-58.0, -10.0]",
            "tip = [1e300, 1e300]",
            "1e300",
            "tools[1].tip",
            "-100000 to 100000 mm",
        ),
        (
            "max_rpm = 4000.0",
            "max_rpm = 2e6",
            "max_rpm",
            "spindle.max_rpm",
            "1 to 1000000 rpm",
        ),
        (
            "index_time = 0.5",
            "index_time = -1",
            "index_time",
            "turret.index_time",
            "0 to 60 s",
        ),
        (
            "rapid = 24000.0",
            "rapid = 0",
            "z = {",
            "axes.z.rapid",
            "1 to 1000000 mm/min",
        ),
        (
            "diameter = 50.0",
            "diameter = 1e6",
            "diameter",
            "stock.diameter",
            "at most 100000 mm",
        ),
        (
            "front = 80.0",
            "front = -2e5",
            "front",
            "stock.front",
            "-100000 to 100000 mm",
        ),
        (
            "axis = 140.0",
            "axis = 1e9",
            "axis = ",
            "turret.axis",
            "-100000 to 100000 mm",
        ),
    ];
    for (from, to, at, key, range) in cases {
        let text = edit(MINI, from, to);
        let e = refused(&text);
        assert_at(&e, line_of(&text, at), key);
        assert!(
            e.message.contains("out of range") && e.message.contains(range),
            "{to}: {e}"
        );
    }
}

#[test]
fn chuck_outline_at_1e155_is_refused_not_silently_lost() {
    for big in ["1e155", "1e308"] {
        let text = edit(MINI, "[105, -100], [105, -30]", &format!("[{big}, -100], [{big}, -30]"));
        let e = refused(&text);
        assert_at(&e, line_of(&text, big), "chuck.outline[1]");
        assert!(e.message.contains("out of range"), "{e}");
    }
    // The largest coordinate allowed still loads.
    let text = edit(MINI, "[105, -100], [105, -30]", "[100000, -100], [100000, -30]");
    let text = edit(
        &text,
        "x = { min = -10.0, max = 300.0",
        "x = { min = -10.0, max = 100000.0",
    );
    assert_eq!(load(&text).unwrap().home, p2(1e5, 600.0));
}

#[test]
fn unit_mistakes_load_with_a_warning_naming_the_key() {
    let m = load(&edit(MINI, "rapid = 20000.0", "rapid = 1.0")).unwrap();
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    assert!(m.warnings[0].starts_with("test.toml:5:"), "{:?}", m.warnings);
    assert!(
        m.warnings[0].contains("axes.x.rapid") && m.warnings[0].contains("m/min"),
        "{:?}",
        m.warnings
    );
    let m = load(&edit(MINI, "max_rpm = 4000.0", "max_rpm = 50")).unwrap();
    assert!(
        m.warnings.iter().any(|w| w.contains("spindle.max_rpm")),
        "{:?}",
        m.warnings
    );
    let m = load(&edit(MINI, "index_time = 0.5", "index_time = 30")).unwrap();
    assert!(
        m.warnings.iter().any(|w| w.contains("turret.index_time")),
        "{:?}",
        m.warnings
    );
}

/// MINI with `home` moved next to the chuck and tool 1 reaching further toward the axis.
fn home_by_the_chuck(tip: &str) -> String {
    let text = edit(
        MINI,
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }",
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nhome = [110.0, -10.0]",
    );
    edit(&text, "tip = [-60.0, -12.0]", &format!("tip = {tip}"))
}

#[test]
fn tool_inside_the_chuck_at_home_is_refused_naming_the_tool() {
    // Clear of the chuck (holder and insert lie above z = 0)…
    load(&home_by_the_chuck("[-60.0, 20.0]")).unwrap();
    // …but with the tip 40 mm further in, the holder sits in the jaws.
    let text = home_by_the_chuck("[-100.0, -12.0]");
    let e = refused(&text);
    assert_at(
        &e,
        nth_line(&text, "holder = [[5, 8], [60, 8], [60, 33], [8, 33]]", 0),
        "tools[0].holder",
    );
    assert!(e.message.contains("chuck") && e.message.contains("station 1"), "{e}");
}

#[test]
fn turret_inside_the_chuck_at_home_is_refused() {
    let text = edit(
        MINI,
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }",
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nhome = [100.0, 100.0]",
    );
    // Turret x 100 .. 380, z 65 .. 135 is clear of the chuck (z ≤ 0): loads.
    load(&text).unwrap();
    let text = edit(&text, "home = [100.0, 100.0]", "home = [100.0, -10.0]");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "outline = [[0, -35]"), "turret.outline");
}

#[test]
fn a_tool_turned_out_of_the_plane_is_checked_at_home_too() {
    // Station 3 moved to station 5, half a turn from station 1 at start: it points back toward
    // the spindle across the turret axis (140 mm from the reference point). With its tip 380 mm
    // out, its bar comes within 23 .. 35 mm of the spindle axis, inside the chuck's section.
    let text = edit(
        MINI,
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }",
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nhome = [120.0, 40.0]",
    );
    load(&text).unwrap();
    let text = edit(&text, "station = 3", "station = 5");
    load(&text).unwrap();
    let far = edit(&text, "tip = [-31.0, -90.0]", "tip = [380.0, -60.0]");
    let e = refused(&far);
    // Both its parts reach in; each is reported, the insert first (it comes first in the file).
    let keys: Vec<&str> = e.all().map(|e| e.key.as_str()).collect();
    assert_eq!(keys, ["tools[2].insert", "tools[2].holder"], "{e}");
    assert!(
        e.all()
            .all(|e| e.message.contains("station 5") && e.message.contains("chuck")),
        "{e}"
    );
}

#[test]
fn a_machine_file_over_one_mebibyte_is_refused_before_parsing() {
    // 400,000 tools once took a 59 MB file through the whole parser before the tool limit.
    let mut text = MINI.to_string();
    let tool = "\n[[tools]]\nstation = 4\nname = \"x\"\ntip = [0, 0]\ninsert = [[0, 0], [1, 0], [0, 1]]\nholder = [[0, 0], [1, 0], [0, 1]]\n";
    while text.len() <= MAX_TEXT_BYTES {
        text.push_str(tool);
    }
    let t = std::time::Instant::now();
    let e = refused(&text);
    assert!(t.elapsed().as_secs_f64() < 0.5, "took {:?}", t.elapsed());
    assert_eq!((e.line, e.col, e.key.as_str()), (1, 1, TOP_LEVEL));
    assert!(e.message.contains("at most 1048576"), "{e}");
}

#[test]
fn gcode_system_defaults_to_a_and_b_is_fanuc_only() {
    assert_eq!(load(MINI).unwrap().gcode_system, GcodeSystem::A);
    let text = edit(MINI, "name = \"mini\"", "name = \"mini\"\ngcode_system = \"B\"");
    assert_eq!(load(&text).unwrap().gcode_system, GcodeSystem::B);
    let text = edit(MINI, "name = \"mini\"", "name = \"mini\"\ngcode_system = \"C\"");
    assert_at(&refused(&text), line_of(&text, "gcode_system"), "machine.gcode_system");
    let text = edit(
        MINI,
        "name = \"mini\"",
        "name = \"mini\"\ndialect = \"linuxcnc\"\ngcode_system = \"B\"",
    );
    assert_at(&refused(&text), line_of(&text, "gcode_system"), "machine.gcode_system");
}

// ---------------------------------------------------------------------------------------------
// Machine zero, the tailstock's start state and the M-code table.

#[test]
fn machine_zero_defaults_to_home_and_is_read_from_axes() {
    let m = load(MINI).unwrap();
    assert_eq!(m.machine_zero, m.home);
    let text = edit(
        MINI,
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\n",
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nmachine_zero = [250.0, 500.0]\n",
    );
    assert_eq!(load(&text).unwrap().machine_zero, p2(250.0, 500.0));
    let text = edit(
        MINI,
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\n",
        "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nmachine_zero = [250.0]\n",
    );
    assert_at(&refused(&text), line_of(&text, "machine_zero"), "axes.machine_zero");
}

#[test]
fn tailstock_starts_advanced_unless_the_file_says_retracted() {
    let m = from_toml(LINUXCNC_TOML, "l.toml").unwrap();
    assert!(m.tailstock.is_some() && m.tailstock_advanced);
    let text = LINUXCNC_TOML.replace("advanced = true ", "advanced = false");
    assert!(!from_toml(&text, "l.toml").unwrap().tailstock_advanced);
    let text = LINUXCNC_TOML.replace("advanced = true ", "advanced = 1");
    let no_key = LINUXCNC_TOML.replace("advanced = true ", "# none");
    assert!(from_toml(&no_key, "l.toml").unwrap().tailstock_advanced);
    let e = from_toml(&text, "l.toml").unwrap_err();
    assert_eq!(e.key, "tailstock.advanced", "{e}");
}

#[test]
fn mcodes_table_replaces_the_builtin_actions_it_names() {
    let m = load(MINI).unwrap();
    assert_eq!(m.mcodes, McodeTable::builtin(Dialect::Fanuc));
    let text = format!("{MINI}\n[mcodes]\ntailstock_advance = 21\ntailstock_retract = [22]\ncoolant_on = [8, 88]\n");
    let m = load(&text).unwrap();
    assert_eq!(m.mcodes.action(21), Some(MAction::TailstockAdvance));
    assert_eq!(m.mcodes.action(22), Some(MAction::TailstockRetract));
    assert_eq!(m.mcodes.action(88), Some(MAction::CoolantOn));
    assert_eq!(m.mcodes.action(7), None);
    assert_eq!(m.mcodes.action(3), Some(MAction::SpindleCw));
}

#[test]
fn bad_mcodes_are_refused_at_their_key() {
    for (entry, key, words) in [
        ("quill_out = 21", "mcodes.quill_out", "unknown M-code action"),
        ("chuck_open = 1000", "mcodes.chuck_open", "codes run from 0 to 999"),
        ("chuck_open = -1", "mcodes.chuck_open", "codes run from 0 to 999"),
        ("chuck_open = 98", "mcodes.chuck_open", "handled by the interpreter"),
        ("bar_feed = [6]", "mcodes.bar_feed", "handled by the interpreter"),
        (
            "chuck_open = 11\nchuck_close = [10, 11]",
            "mcodes.chuck_open",
            "already given",
        ),
        ("chuck_open = \"M11\"", "mcodes.chuck_open", "an M code number"),
    ] {
        let text = format!("{MINI}\n[mcodes]\n{entry}\n");
        let e = refused(&text);
        assert_eq!(e.key, key, "{entry}: {e}");
        assert!(e.message.contains(words), "{entry}: {e}");
        assert!(e.line > line_of(&text, "[mcodes]"), "{entry}: {e}");
    }
}

#[test]
fn tip_direction_is_a_whole_number_from_0_to_9() {
    let m = load(MINI).unwrap();
    assert!(
        m.tools.iter().all(|t| t.tip_direction == 0),
        "absent: 0 (the nose centre)"
    );
    let text = edit(
        MINI,
        "name = \"two\"",
        "name = \"two\"\nnose_radius = 0.4\ntip_direction = 3",
    );
    let m = load(&text).unwrap();
    assert_eq!(m.tools[1].tip_direction, 3);
    assert_eq!(m.tools[0].tip_direction, 0);
    for bad in ["10", "-1", "3.5", "\"3\""] {
        let text = edit(
            MINI,
            "name = \"two\"",
            &format!("name = \"two\"\ntip_direction = {bad}"),
        );
        assert_at(
            &refused(&text),
            line_of(&text, "tip_direction"),
            "tools[1].tip_direction",
        );
    }
}

#[test]
fn turret_side_is_rear_unless_the_file_says_front() {
    assert_eq!(load(MINI).unwrap().turret_side, super::TurretSide::Rear);
    let text = edit(MINI, "name = \"mini\"", "name = \"mini\"\nturret_side = \"front\"");
    assert_eq!(load(&text).unwrap().turret_side, super::TurretSide::Front);
    let text = edit(MINI, "name = \"mini\"", "name = \"mini\"\nturret_side = \"left\"");
    assert_at(&refused(&text), line_of(&text, "turret_side"), "machine.turret_side");
}

// ---------------------------------------------------------------------------------------------
// Every error at once, warnings for folds, a stock that fits the chuck.

#[test]
fn three_independent_mistakes_are_reported_together_in_file_order() {
    let text = edit(
        &edit(
            &edit(MINI, "min = -10.0, max = 300.0", "min = 400.0, max = 300.0"),
            "max_rpm = 4000.0",
            "max_rpm = 0.0",
        ),
        "station = 3",
        "station = 9",
    );
    let e = refused(&text);
    let all: Vec<&MachineError> = e.all().collect();
    assert_eq!(all.len(), 3, "{e}");
    assert_at(all[0], line_of(&text, "x = { min = 400.0"), "axes.x.min");
    assert_at(all[1], line_of(&text, "max_rpm = 0.0"), "spindle.max_rpm");
    assert_at(all[2], line_of(&text, "station = 9"), "tools[2].station");
    let shown = e.to_string();
    let lines: Vec<&str> = shown.lines().collect();
    assert_eq!(lines.len(), 3, "{shown}");
    assert!(lines[1].starts_with(&format!("test.toml:{}:", all[1].line)), "{shown}");
    assert!(
        lines[2].contains("tools[2].station: station 9 does not exist"),
        "{shown}"
    );
}

#[test]
fn a_single_mistake_is_one_error_with_nothing_else() {
    let e = refused(&edit(MINI, "max_rpm = 4000.0", "max_rpm = 0.0"));
    assert!(e.also.is_empty(), "{e}");
    assert_eq!(e.to_string().lines().count(), 1);
}

#[test]
fn a_refused_value_does_not_bring_errors_about_what_depends_on_it() {
    // A bad stations count: the tools' stations are not checked against it, the rest still is.
    let text = edit(
        &edit(MINI, "stations = 8", "stations = 0"),
        "index_time = 0.5",
        "index_time = -1.0",
    );
    let e = refused(&text);
    let keys: Vec<&str> = e.all().map(|e| e.key.as_str()).collect();
    assert_eq!(keys, ["turret.stations", "turret.index_time"], "{e}");
}

#[test]
fn a_syntax_error_still_stops_at_the_first_problem() {
    let text = edit(
        &edit(MINI, "max_rpm = 4000.0", "max_rpm = = 4000"),
        "stations = 8",
        "stations = 0",
    );
    let e = refused(&text);
    assert!(e.also.is_empty(), "{e}");
    assert!(e.message.contains("TOML syntax error"), "{e}");
}

#[test]
fn a_spike_in_an_outline_loads_with_a_warning_naming_the_key_and_point() {
    // Point [3] goes up to x 200 and straight back down: a spike.
    let text = edit(
        MINI,
        "outline = [[0, -35], [280, -35], [280, 35], [0, 35]]",
        "outline = [[0, -35], [280, -35], [280, 35], [100, 35], [100, 200], [100, 35], [0, 35]]",
    );
    let m = load(&text).unwrap();
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    let w = &m.warnings[0];
    let line = line_of(&text, "[100, 200]");
    assert!(w.starts_with(&format!("test.toml:{line}:")), "{w}");
    assert!(w.contains("turret.outline: point [4] [100, 200] is a spike"), "{w}");
    // The outline checked is the one without it.
    assert_eq!(m.turret.outline.points().len(), 4);
}

#[test]
fn a_zero_width_feature_in_an_outline_loads_with_a_warning() {
    // A zero-width T: up from [100, 35] to [100, 60], along to [120, 60], back, and back down.
    let text = edit(
        MINI,
        "outline = [[0, -35], [280, -35], [280, 35], [0, 35]]",
        "outline = [[0, -35], [280, -35], [280, 35], [100, 35], [100, 60], [120, 60], [100, 60], [100, 35], [0, 35]]",
    );
    let m = load(&text).unwrap();
    assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
    let w = &m.warnings[0];
    assert!(w.contains("turret.outline: points ["), "{w}");
    assert!(w.contains("zero-width feature"), "{w}");
    assert_eq!(m.turret.outline.points().len(), 4);
}

#[test]
fn collinear_and_repeated_points_bring_no_warning() {
    let text = edit(
        MINI,
        "outline = [[0, -35], [280, -35], [280, 35], [0, 35]]",
        "outline = [[0, -35], [140, -35], [280, -35], [280, -35], [280, 35], [0, 35], [0, -35]]",
    );
    assert!(load(&text).unwrap().warnings.is_empty());
}

#[test]
fn folds_finds_spikes_and_zero_width_runs() {
    let pts = |v: &[(f64, f64)]| v.iter().map(|&(x, z)| p2(x, z)).collect::<Vec<_>>();
    // A square with a spike at index 2.
    let f = super::load::folds(&pts(&[
        (0.0, 0.0),
        (10.0, 0.0),
        (10.0, -5.0),
        (10.0, 0.0),
        (10.0, 10.0),
        (0.0, 10.0),
    ]));
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].turns, [2]);
    // An edge that overshoots and comes back: the fold is at index 1.
    let f = super::load::folds(&pts(&[(0.0, 0.0), (12.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]));
    assert_eq!(f.len(), 1);
    assert_eq!(f[0].turns, [1]);
    // No fold in a plain square.
    assert!(super::load::folds(&pts(&[(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)])).is_empty());
}

#[test]
fn a_stock_wider_than_the_chuck_bore_is_refused_naming_the_diameter() {
    // The chuck's bore is 50 mm (x 25); a 60 mm bar overlaps the jaws.
    let text = edit(MINI, "diameter = 50.0", "diameter = 60.0");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "diameter = 60.0"), "stock.diameter");
    assert!(e.message.contains("overlaps the chuck by 5.000 mm"), "{e}");
}

#[test]
fn a_stock_that_reaches_into_a_closed_chuck_body_is_refused_naming_the_length() {
    // A chuck with no through bore behind z = -60: a 150 mm bar (back end at z = -70) runs into
    // the body whatever its diameter.
    let text = edit(
        &edit(
            MINI,
            "outline = [[25, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0]]",
            "outline = [[0, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0], [25, -60], [0, -60]]",
        ),
        "length = 120.0",
        "length = 150.0",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "length = 150.0"), "stock.length");
    assert!(e.message.contains("whatever its diameter"), "{e}");
    // The same chuck takes the 120 mm bar (back end at z = -40).
    let ok = edit(&text, "length = 150.0", "length = 120.0");
    load(&ok).unwrap();
}

#[test]
fn a_stock_gripped_at_the_jaw_faces_touches_and_loads() {
    // Exactly the bore: the jaws' faces touch the bar.
    let m = load(MINI).unwrap();
    assert_eq!(m.stock.as_ref().unwrap().diameter, 50.0);
    // A thinner bar and a tube load too.
    load(&edit(MINI, "diameter = 50.0", "diameter = 30.0")).unwrap();
    load(&edit(MINI, "front = 80.0", "front = 80.0\nbore = 20.0")).unwrap();
}

#[test]
fn stock_fit_is_judged_only_once_every_value_is_valid() {
    // A stock that does not fit is found after the values are valid; with a bad value elsewhere,
    // the value is reported (the fit is judged on a machine that loads).
    let text = edit(
        &edit(MINI, "diameter = 50.0", "diameter = 60.0"),
        "max_rpm = 4000.0",
        "max_rpm = 0.0",
    );
    let e = refused(&text);
    let keys: Vec<&str> = e.all().map(|e| e.key.as_str()).collect();
    assert_eq!(keys, ["spindle.max_rpm"], "{e}");
}

#[test]
fn every_shipped_and_test_machine_still_loads() {
    for dir in ["machines", "tests/machines"] {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(dir);
        for entry in std::fs::read_dir(&root).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().and_then(|e| e.to_str()) != Some("toml") {
                continue;
            }
            let text = std::fs::read_to_string(&path).unwrap();
            let name = path.display().to_string();
            // STL files of a [kinematics] section are read beside the machine file.
            let dir = root.clone();
            let read = move |n: &str| std::fs::read(dir.join(n)).map_err(|e| e.to_string());
            if let Err(e) = super::from_toml_with(&text, &name, &read) {
                panic!("{e}");
            }
        }
    }
}

#[test]
fn every_setup_problem_is_reported_together() {
    // The turret in the chuck at home and a bar wider than the chuck's bore: both, in file order.
    let text = edit(
        &edit(
            MINI,
            "z = { min = -50.0, max = 600.0, rapid = 24000.0 }",
            "z = { min = -50.0, max = 600.0, rapid = 24000.0 }\nhome = [100.0, -10.0]",
        ),
        "diameter = 50.0",
        "diameter = 60.0",
    );
    let e = refused(&text);
    let keys: Vec<&str> = e.all().map(|e| e.key.as_str()).collect();
    assert!(keys.len() >= 2, "{e}");
    assert_eq!(keys[0], "stock.diameter", "{e}");
    assert!(keys.contains(&"turret.outline"), "{e}");
    let lines: Vec<u32> = e.all().map(|e| e.line).collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "not in file order: {e}");
}

/// A gang slide turns nothing on a tool change: the built-in machine's index next to the chuck
/// (which swings the long boring bar of station 7 into it on a drum) is no index sweep on a gang
/// slide, takes one `index_time` however many stations apart, and every tool stays in the
/// working plane (so the long bar, standing 170 mm in front of the slide, meets the chuck on an
/// ordinary move before the T word).
#[test]
fn a_gang_tool_change_sweeps_nothing_and_takes_one_index_time() {
    let gang_toml = BUILTIN_TOML.replace("[turret]\n", "[turret]\ntype = \"gang\"\n");
    let gang = from_toml(&gang_toml, "gang").unwrap();
    assert_eq!(gang.turret.kind, TurretKind::Gang);
    let drum = Machine::builtin();
    assert_eq!(drum.turret.kind, TurretKind::Drum);
    let src = include_bytes!("../../programs/crash_index_long_tool.nc");
    let settings = crate::pipeline::Settings::default();
    let on_drum = crate::pipeline::check(src, &drum, &settings);
    let on_gang = crate::pipeline::check(src, &gang, &settings);
    let swings = |o: &crate::pipeline::Outcome| o.findings.iter().any(|f| f.message.starts_with("indexing"));
    assert!(swings(&on_drum), "{:#?}", on_drum.findings);
    assert!(!swings(&on_gang), "{:#?}", on_gang.findings);
    assert!(
        on_gang
            .findings
            .iter()
            .any(|f| f.line < 14 && f.message.contains("T07")),
        "{:#?}",
        on_gang.findings
    );
    let scene = crate::scene::Scene::new(&gang, 0.01);
    assert_eq!(scene.station_angle(5, 1.0), 0.0);
    // T01 → T07 is 2 stations the short way on the 8-station drum: 2 × 0.5 s; one change on a gang.
    let index = |m: &Machine| {
        let run = crate::pipeline::interpret(src, m).1;
        let tl = crate::motion::timeline(&run, m);
        tl.items
            .iter()
            .find(|t| {
                matches!(
                    run.moves[t.index].kind,
                    crate::interp::MoveKind::ToolChange { from: 1, to: 7 }
                )
            })
            .map(|t| t.duration)
            .unwrap()
    };
    assert_eq!(index(&drum), 1.0);
    assert_eq!(index(&gang), 0.5);
}

/// A drum turret without an axis is refused with the key named; a gang slide needs none.
#[test]
fn a_drum_turret_needs_its_axis_and_a_gang_slide_does_not() {
    let no_axis = MINI.replace("axis = 140.0\n", "");
    let e = from_toml(&no_axis, "m").unwrap_err();
    assert_eq!(e.key, "turret.axis", "{e}");
    let gang = no_axis.replace("[turret]\n", "[turret]\ntype = \"gang\"\n");
    assert!(from_toml(&gang, "m").is_ok());
}

// A revolved-outline stock and a spindle running from program start.

const FLANGE_STOCK: &str =
    "[stock]\noutline = [[0, -40], [20, -40], [20, 30], [40, 30], [40, 50], [15, 50], [15, 80], [0, 80]]\n";

#[test]
fn a_machine_stock_may_be_a_revolved_outline_with_its_bounding_bar() {
    let text = edit(
        MINI,
        "[stock]\ndiameter = 50.0\nlength = 120.0\nfront = 80.0\n",
        FLANGE_STOCK,
    );
    let m = load(&text).unwrap();
    let s = m.stock.as_ref().unwrap();
    assert_eq!((s.diameter, s.length, s.front, s.bore), (80.0, 120.0, 80.0, 0.0));
    assert_eq!(s.outline.as_ref().map(|o| o.points().len()), Some(8));
    assert_eq!(m.program_zero_z, 80.0);
    assert!(m
        .describe()
        .contains("stock       revolved outline, Ø80 max × 120 mm, z -40 .. 80"));
    assert_eq!(s.section().len(), 8);
}

#[test]
fn a_machine_stock_outline_is_refused_with_sizes_in_the_jaws_or_left_of_the_axis() {
    let both = edit(MINI, "[stock]\n", FLANGE_STOCK);
    let e = refused(&both);
    assert!(
        e.to_string().contains("stock.diameter: a stock with an `outline`"),
        "{e}"
    );
    let text = edit(
        MINI,
        "[stock]\ndiameter = 50.0\nlength = 120.0\nfront = 80.0\n",
        "[stock]\noutline = [[0, -40], [30, -40], [30, 50], [0, 50]]\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "outline = [[0, -40]"), "stock.outline");
    assert!(
        e.to_string()
            .contains("the stock outline (Ø60 max, z -40 .. 50) overlaps the chuck"),
        "{e}"
    );
    let text = edit(
        MINI,
        "[stock]\ndiameter = 50.0\nlength = 120.0\nfront = 80.0\n",
        "[stock]\noutline = [[-1, 0], [20, 0], [20, 50], [0, 50]]\n",
    );
    assert_at(&refused(&text), line_of(&text, "outline = [[-1"), "stock.outline[0]");
    // Without an outline, a bar needs all three sizes: the missing one is named at [stock].
    let text = edit(MINI, "length = 120.0\n", "");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "[stock]"), "stock.length");
}

#[test]
fn a_spindle_start_speed_is_read_and_may_not_exceed_max_rpm() {
    let m = load(&edit(
        MINI,
        "max_rpm = 4000.0\n",
        "max_rpm = 4000.0\nstart_rpm = 1200\n",
    ))
    .unwrap();
    assert_eq!(m.start_rpm, Some(1200.0));
    assert!(m.describe().contains("turning at 1200 rpm from program start"));
    assert_eq!(load(MINI).unwrap().start_rpm, None);
    let text = edit(MINI, "max_rpm = 4000.0\n", "max_rpm = 4000.0\nstart_rpm = 5000\n");
    let e = refused(&text);
    assert_at(&e, line_of(&text, "start_rpm"), "spindle.start_rpm");
    assert!(e.to_string().contains("faster than max_rpm = 4000"), "{e}");
}

/// The shipped machines whose chuck was a hand-drawn outline of a plain stepped jaw are given by
/// their body and jaws now (`[chuck] body`, `[chuck.jaws]`): the outline drawn from them is the
/// one they had, point for point (haas-style-inch.toml's jaws stand on the bore's edge rather
/// than on their grip, which the jaw shapes do not draw, and gang-tool.toml's is a collet: both
/// keep their outlines).
#[test]
fn converted_machines_draw_their_former_chuck_outline_point_for_point() {
    let builtin_outline = [
        [25.0, -100.0],
        [105.0, -100.0],
        [105.0, -30.0],
        [70.0, -30.0],
        [70.0, -12.0],
        [45.0, -12.0],
        [45.0, 0.0],
        [25.0, 0.0],
    ];
    let small_outline = [
        [12.5, -55.0],
        [50.0, -55.0],
        [50.0, -18.0],
        [34.0, -18.0],
        [34.0, -8.0],
        [22.0, -8.0],
        [22.0, 0.0],
        [12.5, 0.0],
    ];
    let turn_mill = include_str!("../../machines/turn-mill.toml");
    // The turn-mill machine's STL files do not matter here: its 2D sections are read first.
    let turn_mill_2d = &turn_mill[..turn_mill.find("\n[kinematics]").unwrap()];
    for (name, text, old) in [
        ("generic-slant-bed.toml", BUILTIN_TOML, &builtin_outline),
        ("linuxcnc-small-lathe.toml", LINUXCNC_TOML, &small_outline),
        ("turn-mill.toml", turn_mill_2d, &builtin_outline),
    ] {
        let m = load(text).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            matches!(m.chuck_form, Some(ChuckForm::Jaws(_))),
            "{name} gives its chuck by body and jaws"
        );
        let old: Vec<P2> = old.iter().map(|&[x, z]| p2(x, z)).collect();
        let drawn = m.chuck.as_ref().unwrap().points();
        assert_eq!(drawn, &old[..], "{name}: the chuck as drawn by hand");
        assert_eq!(drawn, Polygon::new(&old).unwrap().points(), "{name}");
        let c = m.chuck_jaws().unwrap();
        assert_eq!(c.faces(), 0.0, "{name}: the jaw faces at z 0");
    }
}

/// `[chuck] body` with `[chuck.jaws]`: each malformed value is an error at its line, column
/// and key; exactly one of outline, barrier, body and jaws.
#[test]
fn chuck_body_and_jaws_errors_name_file_line_column_and_key() {
    let chuck =
        "[chuck]\noutline = [[25, -100], [105, -100], [105, -30], [70, -30], [70, -12], [45, -12], [45, 0], [25, 0]]\n";
    let with = |new: &str| MINI.replace(chuck, new);
    let jaws = "[chuck]\nbody = { diameter = 210.0, bore = 50.0, face = -30.0, depth = 70.0 }\n\n[chuck.jaws]\ngrip_diameter = 50\ngrip_length = 12\nheight = 30\nwidth = 45\nstep = 20\n";
    let m = load(&with(jaws)).unwrap();
    assert_eq!(m.chuck, load(MINI).unwrap().chuck);
    let c = m.chuck_jaws().unwrap();
    assert_eq!(
        (c.jaws.grip, c.jaws.kind),
        (jaws::Grip::Outside, jaws::JawType::Hard),
        "grip and type default to outside and hard"
    );
    let first = |text: &str| {
        let e = load(text).unwrap_err();
        (e.line, e.col, e.key.clone(), e.message.clone())
    };
    // Lines: [chuck] is line 11 of MINI, body 12, [chuck.jaws] 14, grip_diameter 15 … step 19.
    // (replace, with, (line, column, key, message))
    type Case<'a> = (&'a str, &'a str, (u32, u32, &'a str, &'a str));
    let cases: [Case; 10] = [
        (
            "grip_length = 12",
            "grip_length = 31",
            (
                16,
                15,
                "chuck.jaws.grip_length",
                "the jaws grip for 31 mm but stand only 30 mm out of the chuck face",
            ),
        ),
        (
            "step = 20",
            "step = 46",
            (
                19,
                8,
                "chuck.jaws.step",
                "the gripping step (46 mm) is wider than the jaw (45 mm",
            ),
        ),
        (
            "width = 45",
            "width = -45",
            (18, 9, "chuck.jaws.width", "must be greater than 0, not -45"),
        ),
        (
            "grip_diameter = 50",
            "grip_diameter = 0",
            (15, 17, "chuck.jaws.grip_diameter", "must be greater than 0, not 0"),
        ),
        (
            "bore = 50.0",
            "bore = -1.0",
            (12, 35, "chuck.body.bore", "must not be negative, not -1"),
        ),
        (
            "bore = 50.0",
            "bore = 210.0",
            (
                12,
                35,
                "chuck.body.bore",
                "the bore (Ø210) must be smaller than the body (Ø210)",
            ),
        ),
        (
            "depth = 70.0",
            "depth = 0.0",
            (12, 63, "chuck.body.depth", "must be greater than 0, not 0"),
        ),
        (
            "grip_diameter = 50",
            "grip = \"inside\"\ngrip_diameter = 60",
            (
                19,
                9,
                "chuck.jaws.width",
                "jaws 45 mm wide opened in Ø60: they reach 15 mm past the spindle axis",
            ),
        ),
        (
            "grip_diameter = 50",
            "grip_diameter = 300",
            (
                15,
                17,
                "chuck.jaws.grip_diameter",
                "jaws gripping Ø300 stand at radius 150 .. 195 at the chuck face, off the body (radius 25 .. 105)",
            ),
        ),
        (
            "grip_diameter = 50",
            "type = \"medium\"\ngrip_diameter = 50",
            (
                15,
                8,
                "chuck.jaws.type",
                "unknown value `medium`, expected `hard` or `soft`",
            ),
        ),
    ];
    for (from, to, (line, col, key, message)) in cases {
        let text = with(&jaws.replace(from, to));
        let got = first(&text);
        assert_eq!((got.0, got.1, got.2.as_str()), (line, col, key), "{to}: {}", got.3);
        assert!(got.3.contains(message), "{to}: {}", got.3);
    }
    // Soft jaws: the seat must leave a wall, and must not reach past the axis.
    let soft = jaws.replace("grip_diameter = 50", "type = \"soft\"\ngrip_diameter = 50");
    assert_eq!(
        first(&with(&soft.replace("step = 20", "step = 45"))).2,
        "chuck.jaws.step"
    );
    let soft_small = soft.replace("grip_diameter = 50", "grip_diameter = 30");
    let e = first(&with(&soft_small.replace("step = 20", "step = 16")));
    assert_eq!(e.2, "chuck.jaws.step", "{}", e.3);
    assert!(e.3.contains("their seat reaches 1 mm past the spindle axis"), "{}", e.3);
    // Exactly one form.
    let both = with(&jaws.replace(
        "[chuck]\n",
        "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]\n",
    ));
    assert_eq!(first(&both).2, "chuck.outline");
    assert!(first(&both).3.contains("not both"));
    let no_jaws = with(&jaws[..jaws.find("\n\n[chuck.jaws]").unwrap() + 1]);
    let e = first(&no_jaws);
    assert_eq!((e.0, e.2.as_str()), (12, "chuck.jaws"), "{}", e.3);
    let no_body = with(&jaws.replace(
        "body = { diameter = 210.0, bore = 50.0, face = -30.0, depth = 70.0 }\n",
        "",
    ));
    assert_eq!(first(&no_body).2, "chuck.body");
    let missing = with(&jaws.replace("step = 20\n", ""));
    assert_eq!(first(&missing).2, "chuck.jaws.step");
    assert!(first(&missing).3.contains("missing required key `step`"));
}

#[test]
fn a_machine_file_maps_tool_numbers_to_stations() {
    let with = |map: &str| LINUXCNC_TOML.replacen("[turret]", &format!("[tool_numbers]\n{map}\n\n[turret]"), 1);
    let m = from_toml(&with("T12 = 1\nT7 = 4"), "m.toml").unwrap();
    assert_eq!(m.tool_numbers, vec![(7, 4), (12, 1)]);
    assert_eq!(m.station_of_tool(12), Some(1));
    let line = LINUXCNC_TOML[..LINUXCNC_TOML.find("[turret]").unwrap()].lines().count() + 3;
    let e = from_toml(&with("T12 = 1\nT7 = 5"), "m.toml").unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "m.toml:{line}:6: tool_numbers.T7: station 5 does not exist: the turret has stations 1 to 4"
        )),
        "{e}"
    );
    let e = from_toml(&with("T12 = 1\nX7 = 2"), "m.toml").unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "m.toml:{line}:1: tool_numbers.X7: `X7` is not a tool number: write T<tool> = <station>"
        )),
        "{e}"
    );
    // A job's entries go over the machine's, tool by tool.
    let job = crate::job::parse(
        "[tool_numbers]\nT7 = 2\nT3 = 3\n",
        "j.toml",
        ".",
        "j.toml",
        &mut |_: &str, r: &str| -> Result<(String, String), String> { Err(r.to_string()) },
    )
    .unwrap();
    let applied = crate::job::apply(&m, &crate::job::EffectiveJob::merge([&job])).unwrap();
    assert_eq!(applied.tool_numbers, vec![(3, 3), (7, 2), (12, 1)]);
}

/// MINI's second tool (station 2) as given.
const TWO: &str = "name = \"two\"\ntip = [-58.0, -10.0]\ninsert = [[0, 0], [12, 2], [14, 14], [2, 12]]\nholder = [[5, 8], [60, 8], [60, 33], [8, 33]]\n";

/// The tool a job builds from `entry` (a `[[tools]]` table's keys).
fn job_tool(entry: &str) -> Tool {
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no file {rel}")) };
    let layer = crate::job::parse(&format!("[[tools]]\n{entry}"), "j.toml", "/", "job", &mut no_files).unwrap();
    layer.tools[0].value.tool.clone()
}

#[test]
fn a_catalogue_tool_in_a_machine_file_is_the_tool_a_job_builds() {
    for keys in [
        "name = \"OD rough\"\ntip = [-58.0, -10.0]\ninsert = \"CNMG 120408\"\nholder = \"PCLNR 2525M12\"\n",
        "name = \"OD rough\"\ntip = [-58.0, -10.0]\ninsert = \"CNMG 120408\"\nholder = [[5, 8], [60, 8], [60, 33], [8, 33]]\nnose_radius = 0.4\n",
        "name = \"centre\"\ntip = [-58.0, -10.0]\ndrill = { diameter = 10, length = 40, point_angle = 118 }\n",
    ] {
        let m = load(&edit(MINI, TWO, keys)).unwrap_or_else(|e| panic!("{e}\n{keys}"));
        let t = m.tools.iter().find(|t| t.station == 2).unwrap();
        assert_eq!(*t, job_tool(&format!("station = 2\n{keys}")), "{keys}");
    }
    let m = load(&edit(
        MINI,
        TWO,
        "name = \"centre\"\ntip = [-58.0, -10.0]\ndrill = { diameter = 10, length = 40 }\n",
    ))
    .unwrap();
    assert_eq!(m.tools[1].cutter, crate::tooling::Cutter::Drill);
    assert_eq!(m.tools[1].nose_radius, 0.0);
    let m = load(&edit(
        MINI,
        TWO,
        "name = \"r\"\ntip = [-58.0, -10.0]\ninsert = \"CNMG 120408\"\nholder = \"PCLNR 2525M12\"\n",
    ))
    .unwrap();
    assert_eq!(
        (m.tools[1].nose_radius, m.tools[1].cutter),
        (0.8, crate::tooling::Cutter::Insert)
    );
}

#[test]
fn a_catalogue_tool_error_in_a_machine_file_names_file_line_column_and_key() {
    let text = edit(
        MINI,
        TWO,
        "name = \"r\"\ntip = [-58.0, -10.0]\ninsert = \"XYZW 1\"\nholder = \"PCLNR 2525M12\"\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "XYZW"), "tools[1].insert");
    assert_eq!(e.col, 10);
    assert!(
        e.message
            .starts_with("cannot build the tool from its catalogue description: "),
        "{e}"
    );

    let text = edit(
        MINI,
        TWO,
        "name = \"d\"\ntip = [-58.0, -10.0]\ndrill = { diameter = -1, length = 40 }\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "drill ="), "tools[1].drill.diameter");
    assert_eq!(e.message, "must be greater than 0, not -1");

    let text = edit(
        MINI,
        TWO,
        "name = \"d\"\ntip = [-58.0, -10.0]\ndrill = { diameter = 10, lenght = 40 }\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "drill ="), "tools[1].drill.lenght");
    assert!(e.message.contains("did you mean `length`?"), "{e}");

    let text = edit(
        MINI,
        TWO,
        "name = \"d\"\ntip = [-58.0, -10.0]\ninsert = \"  \"\nholder = \"PCLNR 2525M12\"\n",
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "insert = \"  \""), "tools[1].insert");
    assert_eq!(e.message, "the designation is empty");

    let text = edit(
        MINI,
        TWO,
        "name = \"d\"\ntip = [-58.0, -10.0]\nholder = [[5, 8], [60, 8], [60, 33], [8, 33]]\n",
    );
    let e = refused(&text);
    assert_at(&e, nth_line(&text, "[[tools]]", 1), "tools[1].insert");
    assert_eq!(
        e.message,
        "missing required key `insert`: give an outline, a catalogue designation or `drill`"
    );
}

#[test]
fn the_catalogue_tools_example_of_docs_machine_md_loads_as_a_job_builds_it() {
    let page = include_str!("../../docs/machine.md");
    let after = &page[page.find("#### Catalogue tools").unwrap()..];
    let block = &after[after.find("```toml\n").unwrap() + 8..];
    let block = &block[..block.find("```").unwrap()];
    let m = load(&format!("{MINI}\n{block}")).unwrap_or_else(|e| panic!("{e}"));
    for entry in block.split("[[tools]]\n").skip(1) {
        let want = job_tool(entry);
        let got = m.tools.iter().find(|t| t.station == want.station).unwrap();
        assert_eq!(*got, want);
    }
    assert_eq!(m.tools[4].cutter, crate::tooling::Cutter::Drill);
}

/// The built-in machine's T01 as it stands in the file (its `tip`).
const BUILTIN_T01_TIP: &str = "tip = [-60.0, -12.0]";
/// The same tool as the control's geometry page shows it: X −2 × (300 − 60) on diameter, Z 12.
const BUILTIN_T01_OFFSET: &str = "geometry_offset = { x = -480.0, z = 12.0 }";

#[test]
fn the_builtin_t01_written_as_its_geometry_offset_is_the_same_tool_as_its_tip() {
    let m = Machine::builtin();
    let text = edit(BUILTIN_TOML, BUILTIN_T01_TIP, BUILTIN_T01_OFFSET);
    let by_offset = load(&text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(by_offset.tools, m.tools);
    assert_eq!(by_offset.tools[0].tip, p2(-60.0, -12.0));
}

#[test]
fn a_geometry_offset_is_converted_with_the_machines_machine_zero_not_home() {
    // Machine zero 100 mm nearer the axis than home: the page's X is measured from there.
    let text = edit(
        BUILTIN_TOML,
        "home = [300.0, 600.0]",
        "home = [300.0, 600.0]\nmachine_zero = [200.0, 600.0]",
    );
    let text = edit(&text, BUILTIN_T01_TIP, "geometry_offset = { x = -280.0, z = 12.0 }");
    let m = load(&text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(m.tools[0].tip, p2(-60.0, -12.0));
}

#[test]
fn a_job_tool_given_by_its_geometry_offset_is_the_machine_files_tool() {
    let m = Machine::builtin();
    let t01 = BUILTIN_TOML.split("[[tools]]").nth(1).unwrap().trim();
    let entry = edit(t01, BUILTIN_T01_TIP, BUILTIN_T01_OFFSET);
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no file {rel}")) };
    let layer = crate::job::parse(&format!("[[tools]]\n{entry}\n"), "j.toml", "/", "job", &mut no_files)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(layer.tools[0].value.origin, "outlines, geometry offset X-480 Z12");
    let applied = crate::job::apply(&m, &crate::job::EffectiveJob::merge([&layer])).unwrap();
    assert_eq!(applied.tools, m.tools);
}

#[test]
fn tip_and_geometry_offset_together_are_an_error_naming_the_key() {
    let text = edit(
        BUILTIN_TOML,
        BUILTIN_T01_TIP,
        &format!("{BUILTIN_T01_TIP}\n{BUILTIN_T01_OFFSET}"),
    );
    let e = refused(&text);
    assert_at(&e, line_of(&text, "geometry_offset"), "tools[0].geometry_offset");
    assert!(e.message.contains("not both"), "{e}");
}

#[test]
fn a_tool_without_tip_or_geometry_offset_is_an_error_naming_both() {
    let text = edit(BUILTIN_TOML, &format!("{BUILTIN_T01_TIP}\n"), "");
    let e = refused(&text);
    assert_eq!(e.key, "tools[0].tip", "{e}");
    assert!(
        e.message.contains("missing required key `tip`") && e.message.contains("geometry_offset"),
        "{e}"
    );
}

#[test]
fn a_bad_geometry_offset_is_an_error_at_its_key() {
    for (value, key, says) in [
        (
            "{ x = -480.0 }",
            "tools[0].geometry_offset.z",
            "missing required key `z`",
        ),
        (
            "{ x = -480.0, z = 12.0, y = 1.0 }",
            "tools[0].geometry_offset.y",
            "unknown key `y`",
        ),
        ("{ x = \"-480\", z = 12.0 }", "tools[0].geometry_offset.x", "number"),
        (
            "{ x = -480.0, z = nan }",
            "tools[0].geometry_offset.z",
            "not a finite number",
        ),
        (
            "{ x = -480.0, z = 1e300 }",
            "tools[0].geometry_offset.z",
            "out of range",
        ),
        ("[-480.0, 12.0]", "tools[0].geometry_offset", "a table { x, z }"),
    ] {
        let text = edit(BUILTIN_TOML, BUILTIN_T01_TIP, &format!("geometry_offset = {value}"));
        let e = load(&text).err().unwrap_or_else(|| panic!("accepted {value}"));
        assert_eq!(
            (e.key.as_str(), e.line),
            (key, line_of(&text, "geometry_offset")),
            "{value}: {e}"
        );
        assert!(e.message.contains(says), "{value}: {e}");
    }
    // The same in a job: the job's key.
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no file {rel}")) };
    let e = crate::job::parse(
        "[[tools]]\nstation = 1\nname = \"t\"\ntip = [-60.0, -12.0]\ngeometry_offset = { x = -480.0, z = 12.0 }\ninsert = \"CNMG 120408\"\nholder = \"PCLNR 2525M12\"\n",
        "j.toml",
        "/",
        "job",
        &mut no_files,
    )
    .unwrap_err();
    assert_eq!((e.key.as_str(), e.line), ("tools[0].geometry_offset", 5), "{e}");
}
