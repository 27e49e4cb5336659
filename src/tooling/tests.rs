//! The decoders against catalogue values (docs/tools.md), their errors, the `.tbl` reader, and
//! a property test over every tool the decoders build.

use super::holder::{self, AnyHolder, Body};
use super::insert::{self, Insert, Pitch};
use super::*;
use crate::geom::{locate, Location};
use proptest::prelude::*;

fn spec(insert: Option<&str>, holder: Option<&str>) -> CatalogueSpec {
    CatalogueSpec {
        insert: insert.map(String::from),
        holder: holder.map(String::from),
        drill: None,
    }
}

fn turning(code: &str) -> insert::Iso1832 {
    match insert::parse(code) {
        Ok(Insert::Turning(i)) => i,
        other => panic!("{code}: {other:?}"),
    }
}

fn turning_holder(code: &str) -> holder::Holder {
    match holder::parse(code) {
        Ok(AnyHolder::Turning(h)) => h,
        other => panic!("{code}: {other:?}"),
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

fn insert_err(code: &str) -> String {
    match insert::parse(code) {
        Err(e) => e,
        Ok(i) => panic!("{code} was read as {i:?}"),
    }
}

fn build_err(i: Option<&str>, h: Option<&str>) -> CatalogueError {
    match build(&spec(i, h)) {
        Err(e) => e,
        Ok(t) => panic!("{i:?} {h:?} built {}", t.summary),
    }
}

/// The angle of the edge from `a` to `b`, degrees from +x toward +z.
fn angle(a: P2, b: P2) -> f64 {
    (b.y - a.y).atan2(b.x - a.x).to_degrees()
}

/// The two edges of the insert at the tip (the vertex at the origin), as angles.
fn tip_edges(p: &Polygon) -> (f64, f64) {
    let pts = p.points();
    let n = pts.len();
    let k = pts
        .iter()
        .position(|q| q.x == 0.0 && q.y == 0.0)
        .expect("a vertex at the tip");
    (angle(pts[k], pts[(k + 1) % n]), angle(pts[k], pts[(k + n - 1) % n]))
}

#[test]
fn cnmg_120408_is_80_degree_rhombic_12_7_ic_4_76_thick_r0_8() {
    let i = turning("CNMG 120408");
    assert_eq!(i.shape.angle, 80.0);
    assert_eq!(i.clearance, 0.0);
    assert!(close(i.ic, 12.7, 1e-9));
    assert!(close(i.edge, 12.896, 0.001), "{}", i.edge);
    assert!(close(i.thickness, 4.76, 1e-9));
    assert!(close(i.nose_radius, 0.8, 1e-9));
    assert!(!i.inch);
    // Without the space, and with a chip breaker suffix, the same numbers.
    let j = turning("cnmg120408-PM 4325");
    assert_eq!((j.ic, j.thickness, j.nose_radius), (i.ic, i.thickness, i.nose_radius));
    assert_eq!(j.suffix, "-PM 4325");
}

#[test]
fn catalogue_inserts_decode_to_their_documented_sizes() {
    // (code, corner angle, IC, thickness, nose radius, clearance)
    let cases = [
        ("DNMG 150608", 55.0, 12.7, 6.35, 0.8, 0.0),
        ("VNMG 160404", 35.0, 9.525, 4.76, 0.4, 0.0),
        ("VBMT 160404", 35.0, 9.525, 4.76, 0.4, 5.0),
        ("CCMT 09T304", 80.0, 9.525, 3.97, 0.4, 7.0),
        ("TNMG 160408", 60.0, 9.525, 4.76, 0.8, 0.0),
        ("TCMT 110204", 60.0, 6.35, 2.38, 0.4, 7.0),
        ("SNMG 120408", 90.0, 12.7, 4.76, 0.8, 0.0),
        ("WNMG 080408", 80.0, 12.7, 4.76, 0.8, 0.0),
        ("DCMT 11T304", 55.0, 9.525, 3.97, 0.4, 7.0),
        ("RCMT 1204M0", 360.0, 12.0, 4.76, 0.0, 7.0),
        ("SPMR 120304", 90.0, 12.7, 3.18, 0.4, 11.0),
    ];
    for (code, a, ic, t, r, c) in cases {
        let i = turning(code);
        assert_eq!(i.shape.angle, a, "{code}");
        assert!(close(i.ic, ic, 1e-9), "{code}: IC {}", i.ic);
        assert!(close(i.thickness, t, 1e-9), "{code}: thickness {}", i.thickness);
        assert!(close(i.nose_radius, r, 1e-9), "{code}: r {}", i.nose_radius);
        assert_eq!(i.clearance, c, "{code}");
    }
}

#[test]
fn inch_cnmg_432_is_half_inch_ic_three_sixteenths_thick_one_thirty_second_nose() {
    let i = turning("CNMG 432");
    assert!(i.inch);
    assert!(close(i.ic, 12.7, 1e-9));
    assert!(close(i.thickness, 4.7625, 1e-9));
    assert!(close(i.nose_radius, 0.79375, 1e-9));
    // It fits the metric holder for size 12 C inserts.
    assert!(build(&spec(Some("CNMG 432"), Some("PCLNR 2525M12"))).is_ok());
}

#[test]
fn unknown_insert_letters_say_which_position_and_what_is_accepted() {
    let e = insert_err("QNMG 120408");
    assert!(
        e.contains("position 1 (shape)") && e.contains("'Q'") && e.contains("C D E"),
        "{e}"
    );
    let e = insert_err("CZMG 120408");
    assert!(e.contains("position 2 (normal clearance)") && e.contains("N P"), "{e}");
    let e = insert_err("CNZG 120408");
    assert!(e.contains("position 3 (tolerance class)"), "{e}");
    let e = insert_err("CNMZ 120408");
    assert!(e.contains("position 4 (type"), "{e}");
    let e = insert_err("CNMG 128808");
    assert!(e.contains("thickness") && e.contains("\"88\""), "{e}");
    let e = insert_err("CNMG 12040X");
    assert!(e.contains("nose radius"), "{e}");
    let e = insert_err("CNMG 0604 80");
    assert!(e.contains("size"), "{e}");
    let e = insert_err("CNMG 060464");
    assert!(e.contains("does not fit"), "{e}");
    assert!(insert_err("CN").contains("ends before position 3"));
    assert!(insert_err("").contains("empty"));
    assert!(insert_err(&"C".repeat(200)).contains("longer than"));
}

#[test]
fn threading_inserts_decode_size_side_hand_pitch_and_angle() {
    let t = match insert::parse("16ER 1.5 ISO") {
        Ok(Insert::Threading(t)) => t,
        o => panic!("{o:?}"),
    };
    assert_eq!((t.size, t.internal, t.hand, t.angle), (16, false, 'R', 60.0));
    assert!(close(t.ic, 9.525, 1e-9));
    assert_eq!(t.pitch, Pitch::Mm(1.5));
    assert!(close(t.nose_radius, 0.1875, 1e-9));
    let t = match insert::parse("16IL AG60") {
        Ok(Insert::Threading(t)) => t,
        o => panic!("{o:?}"),
    };
    assert_eq!((t.internal, t.hand, t.angle), (true, 'L', 60.0));
    assert_eq!(t.pitch, Pitch::Range("AG", 0.5, 3.0));
    let t = match insert::parse("22ER 11W") {
        Ok(Insert::Threading(t)) => t,
        o => panic!("{o:?}"),
    };
    assert_eq!((t.angle, t.pitch.clone()), (55.0, Pitch::Tpi(11.0)));
    assert!(insert_err("16XR 1.5ISO").contains("E I"));
    assert!(insert_err("16EX 1.5ISO").contains("R L"));
    assert!(insert_err("17ER 1.5ISO").contains("11 16 22 27"));
    assert!(insert_err("16ER 1.5ACME").contains("profile"));
    assert!(insert_err("16ER ZZ60").contains("range"));
}

#[test]
fn groove_form_reads_width_depth_radius_and_side() {
    let g = match insert::parse("GROOVE 3x20 R0.2") {
        Ok(Insert::Groove(g)) => g,
        o => panic!("{o:?}"),
    };
    assert_eq!((g.width, g.depth, g.nose_radius, g.internal), (3.0, 20.0, 0.2, false));
    assert!(matches!(insert::parse("groove 2.5x12 int"), Ok(Insert::Groove(g)) if g.internal));
    assert!(insert_err("GROOVE 3").contains("<width>x<depth>"));
    assert!(insert_err("GROOVE 0x20").contains("width"));
    assert!(insert_err("GROOVE 3x20 R2").contains("half the width"));
    assert!(insert_err("GROOVE 3x20 FOO").contains("does not take"));
}

#[test]
fn pclnr_2525m12_is_95_degrees_25_by_25_150_mm_for_size_12_c_inserts() {
    let h = turning_holder("PCLNR 2525M12");
    assert_eq!(h.clamping, 'P');
    assert_eq!(h.shape.letter, 'C');
    assert_eq!((h.style.letter, h.style.kappa), ('L', 95.0));
    assert_eq!((h.clearance_letter, h.hand), ('N', 'R'));
    assert_eq!(
        h.body,
        Body::Shank {
            height: 25.0,
            width: 25.0,
            length: 150.0
        }
    );
    assert!(close(h.ic, 12.7, 1e-9));
    let h = turning_holder("DDJNR 2020K15");
    assert_eq!((h.style.kappa, h.shape.angle), (93.0, 55.0));
    assert_eq!(
        h.body,
        Body::Shank {
            height: 20.0,
            width: 20.0,
            length: 125.0
        }
    );
    assert!(close(h.ic, 12.7, 1e-9));
    let h = turning_holder("MVJNL2525M16");
    assert_eq!((h.hand, h.style.kappa), ('L', 93.0));
    assert!(close(h.ic, 9.525, 1e-9));
}

#[test]
fn boring_bars_decode_kind_diameter_length_and_insert() {
    let h = turning_holder("S20S-SCLCR09");
    assert_eq!(
        h.body,
        Body::Bar {
            kind: 'S',
            diameter: 20.0,
            length: 250.0
        }
    );
    assert_eq!(
        (h.clamping, h.shape.letter, h.style.kappa, h.clearance, h.hand),
        ('S', 'C', 95.0, 7.0, 'R')
    );
    assert!(close(h.ic, 9.525, 1e-9));
    let h = turning_holder("A16R-SDUCR07");
    assert_eq!(
        h.body,
        Body::Bar {
            kind: 'A',
            diameter: 16.0,
            length: 200.0
        }
    );
    assert_eq!((h.shape.letter, h.style.kappa), ('D', 93.0));
    assert!(close(h.ic, 6.35, 1e-9));
}

#[test]
fn unknown_holder_letters_say_which_position_and_what_is_accepted() {
    let e = |c: &str| holder::parse(c).expect_err(c);
    assert!(e("XCLNR 2525M12").contains("position 1 (clamping)"));
    assert!(e("PQLNR 2525M12").contains("position 2 (insert shape)"));
    let m = e("PCZNR 2525M12");
    assert!(m.contains("position 3 (style)") && m.contains("L M N"), "{m}");
    assert!(e("PCLZR 2525M12").contains("position 4 (insert clearance)"));
    assert!(e("PCLNX 2525M12").contains("position 5 (hand)"));
    assert!(e("PCLNR 25X5M12").contains("shank width"));
    assert!(e("PCLNR 2525Z12").contains("position 10 (length)"));
    assert!(e("PCLNR 2525M1").contains("insert size"));
    assert!(e("PCLNR 2525M12Z").contains("position 13"));
    assert!(e("X20S-SCLCR09").contains("bar kind"));
}

#[test]
fn built_pclnr_with_cnmg_is_a_95_degree_tip_3_tool_like_the_machine_file_t01() {
    let t = build(&spec(Some("CNMG 120408"), Some("PCLNR 2525M12"))).unwrap();
    assert_eq!(t.tip_direction, 3);
    assert_eq!(t.nose_radius, 0.8);
    let (a, b) = tip_edges(&t.insert);
    // The main edge backs off 5° from the radius (95°), the trailing edge runs 5° off the axis.
    assert!(close(a, 5.0, 1e-6) && close(b, 85.0, 1e-6), "{a} {b}");
    // The shank: x up to 150, z 7 .. 32 (f = 32 for a 25 mm shank).
    let hb = t.holder.aabb();
    assert!(close(hb.max.x, 150.0, 1e-9) && close(hb.max.y, 32.0, 1e-9), "{hb:?}");
    let hp = t.holder.points();
    assert!(
        hp.contains(&P2::new(150.0, 7.0)) && hp.contains(&P2::new(150.0, 32.0)),
        "{hp:?}"
    );
    // Behind the insert the holder is its seat, a little inside it.
    assert!(close(hb.min.y, 1.943, 0.001) && close(hb.min.x, 1.943, 0.001), "{hb:?}");
    assert!(
        t.summary.contains("80° rhombic") && t.summary.contains("95°"),
        "{}",
        t.summary
    );
}

#[test]
fn left_hand_and_boring_tools_mirror_the_right_hand_tool() {
    let r = build(&spec(Some("VNMG 160404"), Some("MVJNR 2525M16"))).unwrap();
    let l = build(&spec(Some("VNMG 160404"), Some("MVJNL 2525M16"))).unwrap();
    assert_eq!((r.tip_direction, l.tip_direction), (3, 4));
    let (a, b) = tip_edges(&r.insert);
    assert!(close(a, 3.0, 1e-6) && close(b, 38.0, 1e-6), "{a} {b}");
    assert!(close(l.insert.aabb().min.y, -r.insert.aabb().max.y, 1e-9));
    let bar = build(&spec(Some("CCMT 09T304"), Some("S20S-SCLCR09"))).unwrap();
    assert_eq!(bar.tip_direction, 2);
    let b = bar.holder.aabb();
    // The bar lies on the -x side of the tip, 13 mm from the tip to its axis, along +z.
    assert!(
        close(b.min.x, -23.0, 1e-9) && close(b.max.x, -1.4572, 0.01) && close(b.max.y, 250.0, 1e-9),
        "{b:?}"
    );
    let left_bar = build(&spec(Some("CCMT 09T304"), Some("S20S-SCLCL09"))).unwrap();
    assert_eq!(left_bar.tip_direction, 1);
}

#[test]
fn holder_and_insert_must_agree_in_shape_clearance_and_size() {
    let e = build_err(Some("DNMG 150608"), Some("PCLNR 2525M12"));
    assert_eq!(e.key, "holder");
    assert!(
        e.message.contains("shape C") && e.message.contains("shape D"),
        "{}",
        e.message
    );
    let e = build_err(Some("CCMT 120408"), Some("PCLNR 2525M12"));
    assert!(e.message.contains("clearance"), "{}", e.message);
    let e = build_err(Some("CNMG 090308"), Some("PCLNR 2525M12"));
    assert!(e.message.contains("size 12"), "{}", e.message);
    let e = build_err(Some("SNMG 120408"), Some("PSLNR 2525M12"));
    assert!(e.message.contains("no clearance"), "{}", e.message);
    let e = build_err(Some("CNMG 120408"), Some("PCLNN 2525M12"));
    assert!(e.message.contains("hand N"), "{}", e.message);
    let e = build_err(Some("16ER 1.5ISO"), Some("PCLNR 2525M12"));
    assert!(e.message.contains("threading holder"), "{}", e.message);
    let e = build_err(Some("16ER 1.5ISO"), Some("SIR 0020P16"));
    assert!(e.message.contains("internal"), "{}", e.message);
    let e = build_err(Some("QNMG 120408"), None);
    assert_eq!(e.key, "insert");
    assert!(e.message.starts_with("\"QNMG 120408\": position 1"), "{}", e.message);
    let e = build_err(None, None);
    assert!(e.message.contains("nothing to build"));
}

#[test]
fn an_insert_alone_or_a_holder_alone_builds_with_the_documented_defaults() {
    let t = build(&spec(Some("DNMG 150608"), None)).unwrap();
    assert_eq!(t.tip_direction, 3);
    assert!(t.summary.contains("93°"), "{}", t.summary);
    let d = decode(&spec(None, Some("PCLNR 2525M12"))).unwrap();
    assert_eq!(d.tool.nose_radius, 0.8);
    assert_eq!(d.facts[0], ("insert", "implied by the holder".to_string()));
    let t = build(&spec(None, Some("SER 2525M16"))).unwrap();
    assert_eq!(t.tip_direction, 8);
    let t = build(&spec(Some("16IR 1.5ISO"), Some("SIR 0020P16"))).unwrap();
    assert_eq!(t.tip_direction, 6);
    let t = build(&spec(Some("GROOVE 3x20 R0.2"), None)).unwrap();
    assert_eq!((t.tip_direction, t.nose_radius), (3, 0.2));
    // The groove insert's chuck-side face runs along +x from the tip, 3 wide at its mouth.
    assert!(close(t.insert.aabb().max.y, 3.0, 1e-9) && close(t.insert.aabb().max.x, 21.0, 1e-9));
}

#[test]
fn drills_point_at_the_tip_and_flute_back_their_length() {
    let d = DrillSpec {
        diameter: 20.0,
        length: 60.0,
        point_angle: None,
    };
    let t = build(&CatalogueSpec {
        drill: Some(d.clone()),
        ..CatalogueSpec::default()
    })
    .unwrap();
    let b = t.insert.aabb();
    assert_eq!((b.min.x, b.max.x, b.min.y, b.max.y), (-10.0, 10.0, 0.0, 60.0));
    // 118°: the point is r / tan 59° = 6.01 mm long.
    assert!(t
        .insert
        .points()
        .iter()
        .any(|p| close(p.x, 10.0, 1e-9) && close(p.y, 6.0086, 1e-3)));
    assert_eq!(t.tip_direction, 0);
    let flat = DrillSpec {
        point_angle: Some(180.0),
        ..d.clone()
    };
    let t = build(&CatalogueSpec {
        drill: Some(flat),
        ..CatalogueSpec::default()
    })
    .unwrap();
    assert_eq!(locate(P2::new(0.0, 0.0), &t.insert), Location::Boundary);
    for bad in [
        DrillSpec {
            diameter: 0.0,
            ..d.clone()
        },
        DrillSpec {
            length: f64::NAN,
            ..d.clone()
        },
        DrillSpec {
            point_angle: Some(30.0),
            ..d.clone()
        },
        DrillSpec {
            length: 2.0,
            ..d.clone()
        },
    ] {
        let e = build(&CatalogueSpec {
            drill: Some(bad.clone()),
            ..CatalogueSpec::default()
        })
        .expect_err("bad drill");
        assert_eq!(e.key, "drill", "{bad:?}");
    }
    let e = build(&CatalogueSpec {
        drill: Some(d),
        insert: Some("CNMG 120408".into()),
        holder: None,
    })
    .expect_err("drill and insert");
    assert!(e.message.contains("alone"));
}

const LATHE_COMP_TBL: &str = include_str!("../../tests/fixtures/tools/lathe-comp.tbl");

#[test]
fn lathe_comp_tool_table_reads_19_tools_with_their_angles_and_orientations() {
    let tools = tbl::parse(LATHE_COMP_TBL).unwrap();
    assert_eq!(tools.len(), 19);
    assert_eq!(
        tools[0],
        tbl::TblTool {
            tool: 1,
            pocket: 1,
            x: 0.0,
            z: 0.0,
            diameter: 0.1,
            front_angle: 95.0,
            back_angle: 155.0,
            orientation: 1,
            comment: String::new(),
        }
    );
    assert_eq!((tools[5].x, tools[5].z), (0.5, 0.5));
    assert_eq!((tools[6].front_angle, tools[6].back_angle), (-30.0, 30.0));
    for (k, t) in tools.iter().enumerate() {
        assert_eq!(t.tool as usize, k + 1);
        assert_eq!(t.orientation as usize, (k + 1) % 10);
        let built = tbl::shape(&t.in_mm(true)).unwrap();
        assert_eq!(built.tip_direction, t.orientation);
        assert!(close(built.nose_radius, t.diameter * 25.4 / 2.0, 1e-9));
        assert_ne!(
            locate(P2::new(0.0, 0.0), &built.insert),
            Location::Outside,
            "T{}",
            t.tool
        );
        assert_eq!(
            locate(P2::new(0.0, 0.0), &built.holder),
            Location::Outside,
            "T{}",
            t.tool
        );
    }
}

/// A table line's generic holder ends near the turret, not through it: lined up on the insert's
/// centroid, a 93° finishing tool's bar had to start 107 mm back to stay behind its leading edge
/// (187 mm in all), so that on a drum turret the tool of the opposite station reached through the
/// spindle axis into the bar (a false collision of a tool that never moves near the part).
#[test]
fn tbl_holder_of_a_93_degree_tool_ends_within_a_turret_of_its_tip() {
    for line in [
        "T21 P2 X-40 Z-10 D0.4 I93 J58 Q2",
        "T12 P1 X-40 Z-8 D0.8 I85 J25 Q2",
        "T13 P3 X-13 Z-70 D0.4 I265 J205 Q3",
        "T5 P5 D0.8 I95 J35 Q2",
        "T6 P6 D0.8 I-5 J-55 Q1",
    ] {
        let t = &tbl::parse(line).unwrap()[0];
        let b = tbl::shape(t).unwrap();
        let far = b.holder.points().iter().map(|p| p.coords.norm()).fold(0.0, f64::max);
        assert!(far <= 110.0, "{line}: the holder reaches {far} mm from the tip");
        assert_eq!(locate(P2::new(0.0, 0.0), &b.holder), Location::Outside, "{line}");
    }
}

#[test]
fn tbl_orientation_2_is_an_od_tool_whose_insert_lies_toward_plus_x_and_plus_z() {
    let t = &tbl::parse("T2 P2 Z0.0 X0.0 D0.1 I85.0 J25.0 Q2;").unwrap()[0];
    let b = tbl::shape(t).unwrap();
    let (a, c) = tip_edges(&b.insert);
    // I = 85° from +Z toward +X is 5° from +x; J = 25° is 65° from +x.
    assert!(close(a, 5.0, 1e-6) && close(c, 65.0, 1e-6), "{a} {c}");
    assert_eq!(tbl::fanuc_tip(2), 3);
}

#[test]
fn tbl_words_come_in_any_order_with_comments_blank_lines_and_no_spaces() {
    let text = "; a table\n\n  q3 d0.8 T7 z-12.5 x-60;OD rough\r\nT8P3X1Z2\nT9 Y5 A1;\n";
    let tools = tbl::parse(text).unwrap();
    assert_eq!(tools.len(), 3);
    assert_eq!(
        (tools[0].tool, tools[0].pocket, tools[0].x, tools[0].z),
        (7, 7, -60.0, -12.5)
    );
    assert_eq!((tools[0].orientation, tools[0].diameter), (3, 0.8));
    assert_eq!(tools[0].comment, "OD rough");
    assert_eq!(
        (tools[1].tool, tools[1].pocket, tools[1].x, tools[1].z),
        (8, 3, 1.0, 2.0)
    );
    assert_eq!(tools[0].in_mm(true).tip(), [-60.0 * 25.4, -12.5 * 25.4]);
}

#[test]
fn tbl_errors_carry_line_and_column() {
    let e = |text: &str| tbl::parse(text).expect_err(text);
    let x = e("T1 P1\nT2 P2 K4\n");
    assert_eq!((x.line, x.col), (2, 7));
    assert!(x.message.contains("not a tool table word"), "{}", x.message);
    let x = e("T1 X1 X2");
    assert_eq!((x.line, x.col, x.message.contains("twice")), (1, 7, true));
    let x = e("P1 X2");
    assert_eq!((x.line, x.col), (1, 1));
    assert!(x.message.contains("no T word"));
    let x = e("T1\nT1");
    assert_eq!((x.line, x.col), (2, 1));
    assert!(x.message.contains("already"));
    let x = e("T1 Q12");
    assert_eq!((x.line, x.col), (1, 5));
    assert!(x.message.contains("0 to 9"), "{}", x.message);
    let x = e("T1.5");
    assert_eq!((x.line, x.col), (1, 2));
    let x = e("T1 Zabc");
    assert!(x.message.contains("needs a number"), "{}", x.message);
    let x = e("T1 Z1-2-3");
    assert!(x.message.contains("not a number"), "{}", x.message);
    let x = e("T1 D-1");
    assert!(x.message.contains("negative"));
    let x = e("T1 Z1e9");
    assert_eq!(
        (x.col, x.message.contains("not a tool table word")),
        (6, true),
        "{}",
        x.message
    );
    let x = e("T1 Z1,5");
    assert_eq!((x.col, x.message.contains("cannot follow")), (6, true), "{}", x.message);
    let x = e("T1 é");
    assert_eq!((x.line, x.col), (1, 4));
    let bad = tbl::shape(&tbl::TblTool {
        tool: 4,
        front_angle: 10.0,
        back_angle: 190.0,
        orientation: 2,
        ..tbl::TblTool::default()
    })
    .expect_err("180° insert");
    assert!(bad.message.starts_with("T4:"), "{}", bad.message);
}

/// Every tool: valid outlines, the insert holds the tip (on its outline), the holder does not,
/// and the holder leaves the two cutting edges free near the tip.
fn assert_sound(t: &BuiltTool, what: &str) {
    let o = P2::new(0.0, 0.0);
    assert_ne!(
        locate(o, &t.insert),
        Location::Outside,
        "{what}: the insert does not hold the tip"
    );
    assert_eq!(
        locate(o, &t.holder),
        Location::Outside,
        "{what}: the holder covers the tip"
    );
    assert!(t.insert.area() > 0.0 && t.holder.area() > 0.0, "{what}");
    assert!(t.tip_direction <= 9 && t.nose_radius >= 0.0, "{what}");
    // Points a little way along each insert edge from the tip are not inside the holder.
    let pts = t.insert.points();
    let n = pts.len();
    if let Some(k) = pts.iter().position(|q| *q == o) {
        for nb in [pts[(k + 1) % n], pts[(k + n - 1) % n]] {
            let q = P2::new(nb.x * 0.3, nb.y * 0.3);
            assert_ne!(
                locate(q, &t.holder),
                Location::Inside,
                "{what}: the holder covers an edge at {q:?}"
            );
        }
    }
    // Re-normalising the outlines changes nothing: they are valid kernel polygons.
    assert_eq!(Polygon::new(t.insert.points()).as_ref(), Ok(&t.insert), "{what}");
    assert_eq!(Polygon::new(t.holder.points()).as_ref(), Ok(&t.holder), "{what}");
}

fn shape_letter() -> impl Strategy<Value = char> {
    prop::sample::select(vec![
        'A', 'B', 'C', 'D', 'E', 'H', 'K', 'M', 'O', 'P', 'R', 'S', 'T', 'V', 'W',
    ])
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn every_built_turning_tool_has_valid_outlines_and_its_insert_holds_the_tip(
        shape in shape_letter(),
        clear in prop::sample::select(vec!['N', 'C', 'P', 'B']),
        size in prop::sample::select(vec![6u32, 9, 11, 12, 15, 16, 19, 22]),
        nose in prop::sample::select(vec!["00", "02", "04", "08", "12"]),
        style in prop::sample::select(holder::STYLES.iter().map(|s| s.0).collect::<Vec<_>>()),
        hand in prop::sample::select(vec!['R', 'L', 'N']),
        bar in any::<bool>(),
        alone in 0u8..3,
    ) {
        let ins = format!("{shape}{clear}MG {size:02}04{nose}");
        let hol = if bar {
            format!("S20S-P{shape}{style}{clear}{hand}{size:02}")
        } else {
            format!("P{shape}{style}{clear}{hand} 2525M{size:02}")
        };
        let s = match alone {
            0 => spec(Some(&ins), Some(&hol)),
            1 => spec(Some(&ins), None),
            _ => spec(None, Some(&hol)),
        };
        // Some combinations are refused (no clearance, a nose too big): never a panic, and
        // whatever is built is sound.
        if let Ok(t) = build(&s) {
            assert_sound(&t, &format!("{s:?}"));
        }
    }

    #[test]
    fn every_tbl_line_shapes_into_valid_outlines_whose_insert_holds_the_tip(
        i in -360.0f64..360.0,
        j in -360.0f64..360.0,
        d in 0.0f64..10.0,
        q in 0u8..10,
    ) {
        let t = tbl::TblTool { tool: 1, diameter: d, front_angle: i, back_angle: j, orientation: q, ..tbl::TblTool::default() };
        if let Ok(b) = tbl::shape(&t) {
            assert_sound(&b, &format!("{t:?}"));
        }
    }

    #[test]
    fn every_drill_threading_and_groove_tool_is_sound(
        dia in 0.5f64..100.0,
        len in 1.0f64..300.0,
        pa in 60.0f64..=180.0,
        w in 0.5f64..10.0,
        depth in 1.0f64..50.0,
        internal in any::<bool>(),
        size in prop::sample::select(vec![11u32, 16, 22, 27]),
    ) {
        let d = DrillSpec { diameter: dia, length: len, point_angle: Some(pa) };
        if let Ok(t) = build(&CatalogueSpec { drill: Some(d), ..CatalogueSpec::default() }) {
            assert_sound(&t, "drill");
        }
        let g = format!("GROOVE {w}x{depth}{}", if internal { " INT" } else { "" });
        assert_sound(&build(&spec(Some(&g), None)).unwrap(), &g);
        let th = format!("{size}{}R 1.5ISO", if internal { 'I' } else { 'E' });
        assert_sound(&build(&spec(Some(&th), None)).unwrap(), &th);
    }

    #[test]
    fn decoders_never_panic_on_arbitrary_codes(code in "\\PC{0,80}") {
        let _ = build(&spec(Some(&code), None));
        let _ = build(&spec(None, Some(&code)));
        let _ = tbl::parse(&code);
    }
}

/// A report names a drill "the T04 drill", a tap "the T05 tap", an end mill "the T11 mill": by
/// how the tool was built, or for a tool drawn by its outlines, by the words of its name.
#[test]
fn a_tools_cutter_is_named_by_how_it_was_built_or_by_its_name() {
    use super::Cutter;
    for (name, want) in [
        ("Drill 0.53 in", Cutter::Drill),
        ("centre drill", Cutter::Drill),
        ("U-drill D25", Cutter::Drill),
        ("M8 tap", Cutter::Tap),
        ("End mill D10", Cutter::Mill),
        ("OD turn DCMT 55", Cutter::Insert),
        ("Boring bar D10 min bore 13", Cutter::Insert),
        ("Drillmaster grooving", Cutter::Insert),
        ("parting", Cutter::Insert),
    ] {
        assert_eq!(Cutter::from_name(name), want, "{name}");
    }
    let d = DrillSpec {
        diameter: 10.0,
        length: 60.0,
        point_angle: None,
    };
    let built = build(&CatalogueSpec {
        drill: Some(d),
        ..CatalogueSpec::default()
    })
    .unwrap();
    assert_eq!(built.cutter.word(), "drill");
    assert_eq!(build(&spec(Some("CNMG 120408"), None)).unwrap().cutter, Cutter::Insert);
}
