use super::*;
use crate::machine::Machine;

fn no_files(_: &str, rel: &str) -> Result<(String, String), String> {
    Err(format!("no file {rel}"))
}

fn layer(text: &str, label: &str) -> Result<Layer, JobError> {
    parse(text, "part.job.toml", "/shop", label, &mut no_files)
}

fn err(text: &str) -> String {
    layer(text, "job").unwrap_err().to_string()
}

const TOOL: &str = "station = 2\nname = \"OD finish\"\ntip = [-50.0, -10.0]\n\
    insert = [[0.0, 0.0], [4.0, 2.0], [4.0, 8.0], [0.0, 6.0]]\n\
    holder = [[4.0, 2.0], [30.0, 2.0], [30.0, 20.0], [4.0, 20.0]]\n";

#[test]
fn a_full_job_file_reads_into_one_layer() {
    let l = layer(
        &format!(
            "units = \"inch\"\ndialect = \"linuxcnc\"\nprogram_zero_z = 70\n\n[stock]\ndiameter = 40\nlength = 100\nstick_out = 60\nbore = 10\n\n\
             [tailstock]\nin_use = false\n\n[[tools]]\n{TOOL}nose_radius = 0.4\ntip_direction = 3\n"
        ),
        "part.job.toml",
    )
    .unwrap();
    assert!(l.units_inch.as_ref().unwrap().value);
    assert_eq!(l.dialect.as_ref().unwrap().value, DialectChoice::Linuxcnc);
    assert_eq!(l.program_zero_z.as_ref().unwrap().value, 70.0);
    let s = &l.stock.as_ref().unwrap().value;
    assert_eq!((s.diameter, s.length, s.front, s.bore), (40.0, 100.0, Some(60.0), 10.0));
    assert!(!l.tailstock_in_use.as_ref().unwrap().value);
    let t = &l.tools[0].value;
    assert_eq!((t.tool.station, t.tool.nose_radius, t.tool.tip_direction), (2, 0.4, 3));
    assert_eq!(t.origin, "outlines");
    assert_eq!(l.tools[0].at.key, "tools[0]");
    assert_eq!(l.files, vec!["part.job.toml".to_string()]);
}

#[test]
fn front_is_accepted_for_stick_out_but_not_both() {
    let l = layer("[stock]\ndiameter = 40\nlength = 100\nfront = 60\n", "j").unwrap();
    assert_eq!(l.stock.unwrap().value.front, Some(60.0));
    assert!(
        err("[stock]\ndiameter = 40\nlength = 100\nfront = 60\nstick_out = 60\n")
            .starts_with("part.job.toml:4:9: stock.front: give `stick_out` or `front`")
    );
}

#[test]
fn errors_name_file_line_column_and_key() {
    assert!(err("units = \"mm\"\nstok = 1\n").starts_with("part.job.toml:2:1: stok: unknown key `stok`"));
    assert!(err("[stock]\ndiameter = -4\nlength = 10\nstick_out = 5\n")
        .starts_with("part.job.toml:2:12: stock.diameter: must be greater than 0"));
    assert!(err("[stock]\ndiameter = 4\nlength = 10\n")
        .starts_with("part.job.toml:1:1: stock.stick_out: missing required key"));
    assert!(
        err("[[tools]]\nstation = 99\nname = \"x\"\n").starts_with("part.job.toml:2:11: tools[0].station: station 99")
    );
    assert!(err("[tailstock]\nin_use = 1\n").starts_with("part.job.toml:2:10: tailstock.in_use: invalid type"));
    assert!(err("dialect = \"heidenhain\"\n").contains("dialect: unknown value `heidenhain`"));
    assert!(err("[stock]\noutline = [[0, 0], [10, 0], [10, 5]]\nlength = 5\n")
        .starts_with("part.job.toml:3:10: stock.length: a stock with an `outline` takes its sizes from it"));
    assert!(err(&format!("[[tools]]\n{TOOL}[[tools]]\n{TOOL}"))
        .contains("tools[1].station: station 2 is already given by tools[0]"));
}

#[test]
fn a_tool_without_an_outline_says_which_key_is_missing() {
    let e = err("[[tools]]\nstation = 3\nname = \"x\"\ntip = [0, 0]\nholder = [[0,0],[1,0],[1,1]]\n");
    assert!(
        e.starts_with("part.job.toml:2:11: tools[0].insert: missing required key `insert`"),
        "{e}"
    );
}

#[test]
fn a_catalogue_tool_error_is_a_job_error_naming_the_key() {
    // X is no ISO 1832 shape letter.
    let e = err(
        "[[tools]]\nstation = 3\nname = \"x\"\ntip = [0, 0]\ninsert = \"XNMG 120408\"\nholder = \"PCLNR 2525M12\"\n",
    );
    assert!(
        e.starts_with("part.job.toml:5:10: tools[0].insert: cannot build the tool from its catalogue description"),
        "{e}"
    );
}

#[test]
fn use_takes_a_library_entry_and_the_entry_keys_win() {
    let lib = "[[tools]]\nid = \"T-FIN\"\nname = \"Finisher\"\ntip = [-50.0, -10.0]\nnose_radius = 0.8\n\
               insert = [[0.0, 0.0], [4.0, 2.0], [4.0, 8.0], [0.0, 6.0]]\n\
               holder = [[4.0, 2.0], [30.0, 2.0], [30.0, 20.0], [4.0, 20.0]]\n";
    let mut read = |base: &str, rel: &str| -> Result<(String, String), String> {
        assert_eq!((base, rel), ("/shop", "tools.toml"));
        Ok(("tools.toml".into(), lib.into()))
    };
    let l = parse(
        "tool_library = \"tools.toml\"\n[[tools]]\nstation = 4\nuse = \"T-FIN\"\nnose_radius = 0.4\n",
        "part.job.toml",
        "/shop",
        "j",
        &mut read,
    )
    .unwrap();
    let t = &l.tools[0].value;
    assert_eq!(
        (t.tool.name.as_str(), t.tool.nose_radius, t.tool.station),
        ("Finisher", 0.4, 4)
    );
    assert_eq!(t.origin, "use T-FIN (tools.toml)");
    assert_eq!(l.files, vec!["part.job.toml".to_string(), "tools.toml".to_string()]);
    let e = parse(
        "tool_library = \"tools.toml\"\n[[tools]]\nstation = 4\nuse = \"T-NONE\"\n",
        "part.job.toml",
        "/shop",
        "j",
        &mut read,
    )
    .unwrap_err();
    assert!(e
        .to_string()
        .starts_with("part.job.toml:4:7: tools[0].use: tools.toml has no tool with id = \"T-NONE\""));
    let e = err("[[tools]]\nstation = 4\nuse = \"T\"\n");
    assert!(
        e.contains("tools[0].use: `use` takes an entry of the job's tool library"),
        "{e}"
    );
    let e = err("tool_library = \"nope.toml\"\n[[tools]]\nstation = 4\nuse = \"T\"\n");
    assert!(
        e.starts_with("part.job.toml:1:16: tool_library: cannot read nope.toml: no file nope.toml"),
        "{e}"
    );
}

#[test]
fn an_inline_job_in_a_configuration_names_its_whole_key_path() {
    let cfg = "machine = \"m.toml\"\n[[override]]\nglob = \"*.nc\"\n[override.job.stock]\ndiameter = 0\nlength = 1\nstick_out = 1\n";
    let e = parse_embedded(
        cfg,
        "latheguard.toml",
        &["override", "0", "job"],
        "/",
        "l",
        &mut no_files,
    )
    .err()
    .unwrap();
    assert!(
        e.to_string()
            .starts_with("latheguard.toml:5:12: override[0].job.stock.diameter: must be greater than 0"),
        "{e}"
    );
    let cfg = "job = \"a.job.toml\"\n";
    match parse_embedded(cfg, "latheguard.toml", &["job"], "/", "l", &mut no_files).unwrap() {
        Some(Embedded::File { name, at }) => {
            assert_eq!(name, "a.job.toml");
            assert_eq!((at.line, at.col, at.key.as_str()), (1, 7, "job"));
        }
        _ => panic!("a file"),
    }
    assert!(
        parse_embedded("mode = \"step\"\n", "c", &["job"], "/", "l", &mut no_files)
            .unwrap()
            .is_none()
    );
}

#[test]
fn later_layers_win_key_by_key_and_tools_station_by_station() {
    let a = layer(&format!("units = \"inch\"\nprogram_zero_z = 5\n[[tools]]\n{TOOL}"), "a").unwrap();
    let b = layer(
        &format!(
            "units = \"mm\"\n[[tools]]\n{}",
            TOOL.replace("OD finish", "other").replace("station = 2", "station = 3")
        ),
        "b",
    )
    .unwrap();
    let j = EffectiveJob::merge([&a, &b]);
    assert_eq!(j.layers, vec!["a", "b"]);
    assert!(!j.units_inch.as_ref().unwrap().value);
    assert_eq!(j.units_inch.as_ref().unwrap().layer, "b");
    assert_eq!(j.program_zero_z.as_ref().unwrap().layer, "a");
    let stations: Vec<_> = j
        .tools
        .iter()
        .map(|t| (t.value.tool.station, t.layer.as_str()))
        .collect();
    assert_eq!(stations, vec![(2, "a"), (3, "b")]);
    let c = layer(&format!("[[tools]]\n{}", TOOL.replace("OD finish", "again")), "c").unwrap();
    let j = EffectiveJob::merge([&a, &b, &c]);
    assert_eq!(j.tools[0].value.tool.name, "again");
}

#[test]
fn apply_sets_the_machine_and_validates_it() {
    let m = Machine::builtin();
    let l = layer(
        "units = \"inch\"\n[stock]\ndiameter = 30\nlength = 60\nstick_out = 50\n",
        "j",
    )
    .unwrap();
    let out = apply(&m, &EffectiveJob::merge([&l])).unwrap();
    assert!(out.inch);
    let s = out.stock.as_ref().unwrap();
    assert_eq!((s.diameter, s.length, s.front), (30.0, 60.0, 50.0));
    assert_eq!(out.program_zero_z, 50.0, "program zero follows the job's stock front");
    // The machine's other parts are unchanged.
    assert_eq!(out.tools, m.tools);

    // A bar wider than the jaws' bore where it reaches into the chuck is the job's stock.diameter.
    let l = layer("[stock]\ndiameter = 60\nlength = 120\nstick_out = 50\n", "j").unwrap();
    let e = apply(&m, &EffectiveJob::merge([&l])).unwrap_err().to_string();
    assert!(e.starts_with("part.job.toml:2:12: stock.diameter: the bar"), "{e}");
    // A thin long bar passes through the spindle bore.
    let l = layer("[stock]\ndiameter = 30\nlength = 600\nstick_out = 50\n", "j").unwrap();
    assert!(apply(&m, &EffectiveJob::merge([&l])).is_ok());
    // A chuck of this job that the machine's bar does not fit: the job's chuck.outline.
    let l = layer("[chuck]\nouter = 1\n", "j");
    assert!(l.is_err());
    let l = layer("[chuck]\noutline = [[10, -100], [105, -100], [105, 0], [10, 0]]\n", "j").unwrap();
    let e = apply(&m, &EffectiveJob::merge([&l])).unwrap_err().to_string();
    assert!(e.starts_with("part.job.toml:1:1: chuck.outline: the bar"), "{e}");

    // A station the turret lacks.
    let l = layer(
        &format!("[[tools]]\n{}", TOOL.replace("station = 2", "station = 40")),
        "j",
    )
    .unwrap();
    let e = apply(&m, &EffectiveJob::merge([&l])).unwrap_err().to_string();
    assert!(e.contains("tools[0].station: station 40 does not exist"), "{e}");

    // A tool that overlaps the chuck at home (a holder reaching from x 250 down to the jaws).
    let huge = "station = 1\nname = \"huge\"\ntip = [-50.0, -10.0]\ninsert = [[0,0],[1,0],[1,1]]\n\
                holder = [[-200.0, 0.0], [-190.0, 0.0], [-190.0, -700.0], [-200.0, -700.0]]\n";
    let l = layer(&format!("[[tools]]\n{huge}"), "j").unwrap();
    let e = apply(&m, &EffectiveJob::merge([&l])).unwrap_err().to_string();
    assert!(e.contains("tools[0].holder: at home"), "{e}");
}

#[test]
fn tailstock_not_in_use_removes_it_and_in_use_needs_one() {
    let m = crate::machine::from_toml(include_str!("../../machines/linuxcnc-small-lathe.toml"), "m").unwrap();
    assert!(m.tailstock.is_some());
    let off = layer("[tailstock]\nin_use = false\n", "j").unwrap();
    let out = apply(&m, &EffectiveJob::merge([&off])).unwrap();
    assert!(out.tailstock.is_none());
    let on = layer("[tailstock]\nin_use = true\n", "j").unwrap();
    let mut bare = m.clone();
    bare.tailstock = None;
    let e = apply(&bare, &EffectiveJob::merge([&on])).unwrap_err().to_string();
    assert!(
        e.starts_with("part.job.toml:2:10: tailstock.in_use: the machine has no tailstock"),
        "{e}"
    );
}

#[test]
fn a_dialect_change_takes_the_new_dialects_defaults() {
    let m = Machine::builtin();
    assert_eq!(m.dialect, Dialect::Fanuc);
    let l = layer("dialect = \"linuxcnc\"\n", "j").unwrap();
    let out = apply(&m, &EffectiveJob::merge([&l])).unwrap();
    assert_eq!(out.dialect, Dialect::Linuxcnc);
    assert!(!out.diameter_mode);
    assert_eq!(out.mcodes, McodeTable::builtin(Dialect::Linuxcnc));
}

#[test]
fn stock_flag_reads_diameter_length_stick_out_and_bore() {
    assert_eq!(parse_stock_flag("50x120@80"), Ok((50.0, 120.0, Some(80.0), 0.0)));
    assert_eq!(parse_stock_flag("50/20X120"), Ok((50.0, 120.0, None, 20.0)));
    assert!(parse_stock_flag("50").is_err());
    assert!(parse_stock_flag("0x10").is_err());
    assert!(parse_stock_flag("20/20x10").is_err());
    assert!(parse_stock_flag("nanx10").is_err());
    let l = flags_layer(Some("30x60"), Some(true), None).unwrap();
    let out = apply(&Machine::builtin(), &EffectiveJob::merge([&l])).unwrap();
    assert_eq!(out.stock.unwrap().front, Machine::builtin().stock.unwrap().front);
}

#[test]
fn a_catalogue_tool_builds_from_its_iso_codes() {
    let l = layer(
        "[[tools]]\nstation = 3\nname = \"OD rough\"\ntip = [-60, -12]\ninsert = \"CNMG 120408\"\nholder = \"PCLNR 2525M12\"\n",
        "job",
    );
    assert!(l.is_ok(), "{:?}", l.err().map(|e| e.to_string()));
}

const FLANGE: &str =
    "[stock]\noutline = [[0, -40], [20, -40], [20, 30], [40, 30], [40, 50], [15, 50], [15, 80], [0, 80]]\n";

#[test]
fn an_outline_stock_reads_into_its_bounding_bar_and_applies_as_an_outline() {
    let l = layer(FLANGE, "j").unwrap();
    let s = &l.stock.as_ref().unwrap().value;
    assert!(s.outline.is_some() && !s.none);
    assert_eq!((s.diameter, s.length, s.front, s.bore), (80.0, 120.0, Some(80.0), 0.0));
    let out = apply(&Machine::builtin(), &EffectiveJob::merge([&l])).unwrap();
    let st = out.stock.as_ref().unwrap();
    assert_eq!(st.outline.as_ref().map(|o| o.points().len()), Some(8));
    assert_eq!(out.program_zero_z, 80.0, "program zero follows the outline's front");
    // An outline reaching into the jaws is the job's stock.outline.
    let l = layer("[stock]\noutline = [[0, -40], [30, -40], [30, 50], [0, 50]]\n", "j").unwrap();
    let e = apply(&Machine::builtin(), &EffectiveJob::merge([&l]))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("part.job.toml:2:11: stock.outline: the stock outline"),
        "{e}"
    );
}

#[test]
fn an_outline_stock_is_refused_with_sizes_a_negative_radius_or_a_bad_shape() {
    let e = err("[stock]\ndiameter = 40\noutline = [[0, 0], [10, 0], [10, 5], [0, 5]]\n");
    assert!(
        e.starts_with("part.job.toml:2:12: stock.diameter: a stock with an `outline`"),
        "{e}"
    );
    let e = err("[stock]\noutline = [[0, 0], [10, 0], [10, 5], [-3, 5]]\n");
    assert!(
        e.starts_with("part.job.toml:2:38: stock.outline[3]: a stock outline is the revolved section"),
        "{e}"
    );
    let e = err("[stock]\noutline = [[0, 0], [10, 5], [10, 0], [0, 5]]\n");
    assert!(e.contains("stock.outline: invalid outline"), "{e}");
}

#[test]
fn a_job_with_no_stock_removes_the_machines_and_keeps_its_program_zero() {
    let l = layer("[stock]\nnone = true\n", "j").unwrap();
    assert!(l.stock.as_ref().unwrap().value.none);
    let m = Machine::builtin();
    let out = apply(&m, &EffectiveJob::merge([&l])).unwrap();
    assert!(out.stock.is_none());
    assert_eq!(out.program_zero_z, m.program_zero_z);
    // A later layer's stock replaces "none" as a whole, and "none" a lower layer's bar.
    let bar = layer("[stock]\ndiameter = 30\nlength = 60\nstick_out = 50\n", "j").unwrap();
    assert!(apply(&m, &EffectiveJob::merge([&l, &bar])).unwrap().stock.is_some());
    assert!(apply(&m, &EffectiveJob::merge([&bar, &l])).unwrap().stock.is_none());
    let e = err("[stock]\nnone = true\nlength = 3\n");
    assert!(
        e.starts_with("part.job.toml:3:10: stock.length: `none = true` means no stock"),
        "{e}"
    );
    let e = err("[stock]\nnone = false\n");
    assert!(
        e.starts_with("part.job.toml:2:8: stock.none: `none = false` says nothing"),
        "{e}"
    );
}

#[test]
fn a_spindle_start_speed_is_checked_against_the_machine_and_zero_stops_it() {
    let m = Machine::builtin();
    let l = layer("[spindle]\nstart_rpm = 800\n", "j").unwrap();
    assert_eq!(apply(&m, &EffectiveJob::merge([&l])).unwrap().start_rpm, Some(800.0));
    let fast = layer("[spindle]\nstart_rpm = 5000\n", "j").unwrap();
    let e = apply(&m, &EffectiveJob::merge([&fast])).unwrap_err().to_string();
    assert!(
        e.starts_with("part.job.toml:2:13: spindle.start_rpm: start_rpm = 5000 is faster"),
        "{e}"
    );
    let mut on = m.clone();
    on.start_rpm = Some(500.0);
    let stop = layer("[spindle]\nstart_rpm = 0\n", "j").unwrap();
    assert_eq!(apply(&on, &EffectiveJob::merge([&stop])).unwrap().start_rpm, None);
    assert!(err("[spindle]\nstart_rpm = -5\n").starts_with("part.job.toml:2:13: spindle.start_rpm:"));
}

#[test]
fn manual_tool_changes_are_sorted_one_per_line_and_later_layers_win_by_line() {
    let a = layer(
        "[[tool_changes]]\nline = 20\nstation = 3\n[[tool_changes]]\nline = 8\nstation = 2\nnote = \"M0\"\n",
        "a",
    )
    .unwrap();
    let b = layer("[[tool_changes]]\nline = 20\nstation = 4\n", "b").unwrap();
    let j = EffectiveJob::merge([&a, &b]);
    let v: Vec<(u32, u32)> = j.tool_changes.iter().map(|c| c.value).collect();
    assert_eq!(v, vec![(8, 2), (20, 4)]);
    let out = apply(&Machine::builtin(), &j).unwrap();
    assert_eq!(out.tool_changes, vec![(8, 2), (20, 4)]);
    let e = err("[[tool_changes]]\nline = 8\nstation = 2\n[[tool_changes]]\nline = 8\nstation = 3\n");
    assert!(
        e.starts_with("part.job.toml:5:8: tool_changes[1].line: line 8 already has a tool change"),
        "{e}"
    );
    let e = err("[[tool_changes]]\nline = 0\nstation = 2\n");
    assert!(
        e.starts_with("part.job.toml:2:8: tool_changes[0].line: 0 is not a line"),
        "{e}"
    );
    let e = err("[[tool_changes]]\nline = 3\n");
    assert!(
        e.contains("tool_changes[0].station: missing required key `station`"),
        "{e}"
    );
    let l = layer("[[tool_changes]]\nline = 3\nstation = 9\n", "j").unwrap();
    let e = apply(&Machine::builtin(), &EffectiveJob::merge([&l]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("tool_changes[0].station: station 9 holds no tool"), "{e}");
}

#[test]
fn a_tailstock_z_moves_its_tip_there_and_diameter_mode_is_set() {
    let m = crate::machine::from_toml(include_str!("../../machines/linuxcnc-small-lathe.toml"), "m").unwrap();
    let before = *m.tailstock.as_ref().unwrap().aabb();
    let l = layer("diameter_mode = true\n[tailstock]\nz = 150\n", "j").unwrap();
    let out = apply(&m, &EffectiveJob::merge([&l])).unwrap();
    let after = out.tailstock.as_ref().unwrap().aabb();
    assert_eq!(after.min.y, 150.0);
    assert_eq!(
        after.max.y - after.min.y,
        before.max.y - before.min.y,
        "moved, not stretched"
    );
    assert_eq!((after.min.x, after.max.x), (before.min.x, before.max.x));
    assert!(out.diameter_mode && !m.diameter_mode);
    let e = apply(&Machine::builtin(), &EffectiveJob::merge([&l]))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("part.job.toml:3:5: tailstock.z: the machine has no tailstock to move"),
        "{e}"
    );
}

#[test]
fn work_offsets_read_as_the_control_stores_them_and_g55_is_placed_from_machine_zero() {
    let l = layer(
        "[work_offsets]\nG55 = { z = -560.0 }\nG59 = { x = 1.5, z = -300 }\n",
        "job",
    )
    .unwrap();
    let g55 = l.work_offsets[1].as_ref().unwrap();
    assert_eq!(g55.value, WorkOffset { x: 0.0, z: -560.0 });
    assert_eq!(
        (g55.at.key.as_str(), g55.at.line, g55.at.col),
        ("work_offsets.G55", 2, 7)
    );
    assert!(l.work_offsets[0].is_none() && l.work_offsets[2].is_none());
    let m = Machine::builtin();
    let out = apply(&m, &EffectiveJob::merge([&l])).unwrap();
    // Machine zero is home (z 600) on the built-in machine: 600 - 560 = z 40.
    assert_eq!(out.work_zero(1), Some(crate::geom::P2::new(0.0, 40.0)));
    assert_eq!(out.work_zero(5), Some(crate::geom::P2::new(1.5, 300.0)));
    assert_eq!(out.work_zero(2), None);
    // G54 not written: program_zero_z, unchanged.
    assert_eq!(out.program_zero_z, m.program_zero_z);
    assert_eq!(out.work_zero(0), Some(crate::geom::P2::new(0.0, 78.0)));
    assert_eq!(out.work_offset(0), Some(WorkOffset { x: 0.0, z: -522.0 }));
}

#[test]
fn g54_is_program_zero_so_a_layer_gives_it_or_program_zero_z_and_the_later_layer_wins() {
    let e = err("program_zero_z = 70\n[work_offsets]\nG54 = { z = -530 }\n");
    assert!(
        e.starts_with("part.job.toml:1:18: program_zero_z: program zero is given twice: by program_zero_z and by work_offsets.G54"),
        "{e}"
    );
    let g54 = layer("[work_offsets]\nG54 = { z = -520 }\n", "a").unwrap();
    let pz = layer("program_zero_z = 70\n", "b").unwrap();
    let m = Machine::builtin();
    let out = apply(&m, &EffectiveJob::merge([&pz, &g54])).unwrap();
    assert_eq!(out.program_zero_z, 80.0, "G54 Z -520 from machine zero z 600");
    assert_eq!(out.work_offsets[0], Some(WorkOffset { x: 0.0, z: -520.0 }));
    let out = apply(&m, &EffectiveJob::merge([&g54, &pz])).unwrap();
    assert_eq!(out.program_zero_z, 70.0);
    assert_eq!(
        out.work_offsets[0], None,
        "program_zero_z replaced the earlier layer's G54"
    );
    // A job's stock without either takes program zero from the stock's face, as before.
    let st = layer("[stock]\ndiameter = 40\nlength = 100\nstick_out = 60\n", "c").unwrap();
    let out = apply(&m, &EffectiveJob::merge([&g54, &st])).unwrap();
    assert_eq!(
        out.program_zero_z, 80.0,
        "G54 of a lower layer still stands over the stock's face"
    );
    let out = apply(&m, &EffectiveJob::merge([&st])).unwrap();
    assert_eq!(out.program_zero_z, 60.0);
}

#[test]
fn bad_work_offsets_name_file_line_column_and_key() {
    let e = err("[work_offsets]\nG60 = { z = 0 }\n");
    assert!(e.starts_with("part.job.toml:2:1: work_offsets"), "{e}");
    assert!(e.contains("G60"), "{e}");
    let e = err("[work_offsets]\nG55 = { z = 1e9 }\n");
    assert!(e.starts_with("part.job.toml:2:13: work_offsets.G55.z: "), "{e}");
    let e = err("[work_offsets]\nG55 = { x = nan, z = 0 }\n");
    assert!(e.starts_with("part.job.toml:2:13: work_offsets.G55.x: "), "{e}");
    let e = err("[work_offsets]\nG55 = { x = 0 }\n");
    assert!(
        e.starts_with("part.job.toml:2:7: work_offsets.G55.z: missing required key `z`"),
        "{e}"
    );
    let e = err("[work_offsets]\nG55 = -560\n");
    assert!(e.contains("work_offsets.G55") && e.contains("a table { x, z }"), "{e}");
}

#[test]
fn a_work_offset_outside_the_z_travel_is_a_warning_naming_its_key() {
    // Built-in: z travel -50 .. 600, machine zero z 600: machine Z -650 .. 0.
    let l = layer("[work_offsets]\nG55 = { z = 560 }\nG56 = { z = -560 }\n", "job").unwrap();
    let m = Machine::builtin();
    let j = EffectiveJob::merge([&l]);
    let w = warnings(&m, &j);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("part.job.toml:2:7: work_offsets.G55: program zero at machine Z 560 lies outside the Z travel (machine Z -650 .. 0"),
        "{w:?}"
    );
    assert!(apply(&m, &j).is_ok(), "a warning, not an error");
}

// ---------------------------------------------------------------------------------------------
// [tool_numbers]

const TBL: &str = "T12 P3 X-0.5 Z-1.0 D0.8 I85 J25 Q2 ;OD rough\nT5 P4 X-0.4 Z-2.5 D0.4 I265 J205 Q3 ;boring bar\n";

fn with_table(tbl: &'static str) -> impl FnMut(&str, &str) -> Result<(String, String), String> {
    move |_: &str, rel: &str| Ok((rel.to_string(), tbl.to_string()))
}

fn tn_layer(text: &str, tbl: &'static str) -> Result<Layer, JobError> {
    parse(text, "part.job.toml", "/shop", "part.job.toml", &mut with_table(tbl))
}

fn tn_apply(text: &str, tbl: &'static str) -> Result<Machine, JobError> {
    let l = tn_layer(text, tbl)?;
    apply(&Machine::builtin(), &EffectiveJob::merge([&l]))
}

#[test]
fn tool_numbers_map_tools_to_stations_and_explicit_entries_win_over_the_table() {
    let m = tn_apply("[tool_numbers]\nT12 = 3\nT7 = 2\n", TBL).unwrap();
    assert_eq!(m.tool_numbers, vec![(7, 2), (12, 3)]);
    assert_eq!(
        (m.station_of_tool(12), m.station_of_tool(7), m.station_of_tool(8)),
        (Some(3), Some(2), None)
    );
    // The machine's tools stay: explicit entries carry no shape.
    assert_eq!(m.tools, Machine::builtin().tools);

    let m = tn_apply(
        "tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\nT5 = 6\n",
        TBL,
    )
    .unwrap();
    assert_eq!(m.tool_numbers, vec![(5, 6), (12, 3)]);
    // Each table tool's shape goes to its station: T12 to its pocket 3, T5 where T5 = 6 puts it.
    assert_eq!(m.tool(3).unwrap().name, "OD rough");
    assert_eq!(m.tool(6).unwrap().name, "boring bar");
    assert_eq!(m.tool(6).unwrap().tip, crate::geom::p2(-0.4, -2.5));
    // A [[tools]] entry of the job describes its station over the table.
    let m = tn_apply(
        &format!(
            "tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\n\n[[tools]]\n{}",
            TOOL.replace("station = 2", "station = 3")
        ),
        TBL,
    )
    .unwrap();
    assert_eq!(m.tool(3).unwrap().name, "OD finish");
    assert_eq!(m.station_of_tool(12), Some(3));
}

/// A LinuxCNC tool table is in the machine's units: an inch table's offsets and nose radius were
/// taken as mm (T5's as 0.4 mm from the reference point instead of 10.16 mm).
#[test]
fn an_inch_tool_table_is_read_in_inches_by_the_jobs_units_or_tool_table_units() {
    let table = "tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\nT5 = 6\n";
    let tip = |head: &str| match tn_apply(&format!("{head}{table}"), TBL) {
        Ok(m) => (m.tool(6).unwrap().tip, m.tool(6).unwrap().nose_radius),
        Err(e) => panic!("{head}: {e}"),
    };
    let mm = tip("");
    let inch = tip("units = \"inch\"\n");
    assert_eq!(inch.0, crate::geom::p2(-0.4 * 25.4, -2.5 * 25.4));
    assert!((inch.1 - 25.4 * mm.1).abs() < 1e-9, "{inch:?} {mm:?}");
    assert_eq!(tip("tool_table_units = \"inch\"\n"), inch);
    // The table's own units win over the program's.
    assert_eq!(tip("units = \"inch\"\ntool_table_units = \"mm\"\n"), mm);
    match tn_apply("tool_table_units = \"inch\"\n", TBL) {
        Err(e) => assert_eq!(
            e.to_string(),
            "part.job.toml:1:20: tool_table_units: `tool_table_units` says the units of the job's tool table: give `tool_table = \"FILE.tbl\"` too"
        ),
        Ok(_) => panic!("tool_table_units alone"),
    }
}

#[test]
fn tool_numbers_merge_tool_by_tool() {
    let a = tn_layer("[tool_numbers]\nT12 = 3\nT7 = 2\n", TBL).unwrap();
    let b = tn_layer("[tool_numbers]\nT7 = 5\n", TBL).unwrap();
    let m = apply(&Machine::builtin(), &EffectiveJob::merge([&a, &b])).unwrap();
    assert_eq!(m.tool_numbers, vec![(7, 5), (12, 3)]);
}

#[test]
fn tool_numbers_errors_name_file_line_column_and_key() {
    let e = |text: &str| match tn_apply(text, TBL) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("{text}: no error"),
    };
    assert_eq!(
        e("[tool_numbers]\nT12 = 9\n"),
        "part.job.toml:2:7: tool_numbers.T12: T12: station 9 does not exist (tool_numbers.T12 = 9): the turret of Generic 2-axis slant-bed lathe has stations 1 to 8"
    );
    assert_eq!(
        e("[tool_numbers]\nT12 = 0\n"),
        "part.job.toml:2:7: tool_numbers.T12: station 0 does not exist: stations run from 1 to 64"
    );
    assert_eq!(
        e("[tool_numbers]\nX12 = 1\n"),
        "part.job.toml:2:1: tool_numbers.X12: `X12` is not a tool number: write T<tool> = <station> (T12 = 3, tools 1 to 99999) or from_table = true"
    );
    assert_eq!(
        e("[tool_numbers]\nfrom_table = true\n"),
        "part.job.toml:2:14: tool_numbers.from_table: `from_table` takes the tools of the job's tool table: give `tool_table = \"FILE.tbl\"`"
    );
    assert_eq!(
        e("tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\nT5 = 3\n"),
        "part.job.toml:4:6: tool_numbers.T5: T5 and T12 are both in station 3 and both have a shape in the tool table: map one of them elsewhere (tool_numbers.T5 = STATION)"
    );
    let zero = "T3 P0 X0 Z0 D0.4 Q2 ;in the spindle\n";
    assert_eq!(
        match tn_apply("tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\n", zero) {
            Err(e) => e.to_string(),
            Ok(_) => panic!(),
        },
        "part.job.toml:3:14: tool_numbers.from_table: lathe.tbl: T3 is in pocket 0, which is no turret station: give its station with tool_numbers.T3 = STATION"
    );
    // An explicit entry gives the pocket-0 tool its station.
    let m = match tn_apply(
        "tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\nT3 = 2\n",
        zero,
    ) {
        Ok(m) => m,
        Err(e) => panic!("{e}"),
    };
    assert_eq!(m.station_of_tool(3), Some(2));
    let far = "T4 P12 X0 Z0 D0.4 Q2\n";
    assert_eq!(
        match tn_apply("tool_table = \"lathe.tbl\"\n[tool_numbers]\nfrom_table = true\n", far) {
            Err(e) => e.to_string(),
            Ok(_) => panic!(),
        },
        "part.job.toml:3:14: tool_numbers.from_table: T4: station 12 does not exist (lathe.tbl puts T4 in pocket 12): the turret of Generic 2-axis slant-bed lathe has stations 1 to 8"
    );
}

/// A block (`[stock] block = { width, height }`): its corners' diameter is the stock's, the
/// jaws close on its nearer flats, and the 2D model is its revolved envelope — the corners'
/// radius in front of the jaw faces (z 0 on the built-in machine), the flats' behind.
#[test]
fn a_block_stock_applies_as_its_envelope_with_the_jaws_closed_on_its_flats() {
    let text = "[stock]\nblock = { width = 40, height = 30 }\nlength = 100\nstick_out = 60\n";
    let l = layer(text, "j").unwrap();
    let s = &l.stock.as_ref().unwrap().value;
    assert_eq!(
        s.block,
        Some(machine::Block {
            width: 40.0,
            height: 30.0
        })
    );
    // hypot(40, 30) = 50.
    assert_eq!((s.diameter, s.length, s.front), (50.0, 100.0, Some(60.0)));
    let out = apply(&Machine::builtin(), &EffectiveJob::merge([&l])).unwrap();
    let st = out.stock.as_ref().unwrap();
    assert_eq!(st.block, s.block);
    let pts: Vec<(f64, f64)> = st
        .outline
        .as_ref()
        .unwrap()
        .points()
        .iter()
        .map(|p| (p.x, p.y))
        .collect();
    let mut want = vec![
        (0.0, -40.0),
        (15.0, -40.0),
        (15.0, 0.0),
        (25.0, 0.0),
        (25.0, 60.0),
        (0.0, 60.0),
    ];
    want.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let mut got = pts.clone();
    got.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(got, want, "{pts:?}");
    assert_eq!(out.chuck_jaws().unwrap().jaws.grip_diameter, 30.0);
    assert_eq!(out.program_zero_z, 60.0);
}

#[test]
fn a_block_stock_is_refused_with_a_bar_size_a_bad_size_or_jaws_that_do_not_hold_it() {
    let base = "length = 100\nstick_out = 60\n";
    for (extra, want) in [
        (
            "block = { width = 40, height = 30 }\ndiameter = 50\n",
            "part.job.toml:3:12: stock.diameter: a block takes its section from `block = { width, height }`",
        ),
        (
            "block = { width = 40, height = 30 }\nbore = 10\n",
            "part.job.toml:3:8: stock.bore: a block takes its section",
        ),
        (
            "block = { width = 0, height = 30 }\n",
            "part.job.toml:2:19: stock.block.width: must be greater than 0",
        ),
        (
            "block = { width = 40, height = -3 }\n",
            "stock.block.height: must be greater than 0",
        ),
        ("block = { width = 40 }\n", "stock.block"),
        ("block = { width = 40, height = 30, depth = 2 }\n", "unknown"),
    ] {
        let e = err(&format!("[stock]\n{extra}{base}"));
        assert!(e.contains(want), "{extra}: {e}");
    }
    let e = err("[stock]\nblock = { width = 40, height = 30 }\nnone = true\n");
    assert!(e.contains("stock.block: `none = true` means no stock"), "{e}");
    // Jaws set to another diameter stand off the block's flats (or would close inside it).
    for (grip, how) in [(40.0, "stand off its flats"), (20.0, "")] {
        let l = layer(
            &format!("[stock]\nblock = {{ width = 40, height = 30 }}\n{base}\n[chuck.jaws]\ngrip_diameter = {grip}\n"),
            "j",
        )
        .unwrap();
        let e = apply(&Machine::builtin(), &EffectiveJob::merge([&l]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("stock.block: "), "{grip}: {e}");
        assert!(e.contains(how), "{grip}: {e}");
    }
}
