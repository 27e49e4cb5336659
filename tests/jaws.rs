//! The chuck by its body and jaws (docs/machine.md, "The chuck as body and jaws"; docs/job.md,
//! "Jaws"): the outlines each jaw type and grip draws against points worked by hand, the docs'
//! examples, a job's jaws over the machine file's (merged key by key, closed on the job's bar), a
//! Ø30 bar on the built-in machine whose jaws now stand where a tool used to pass, every error
//! with its file, line, column and key, `setup`, the schemas and the turn-mill tree.

use crate::common;

use latheguard::finding::{Kind, Severity};
use latheguard::geom::{p2, Polygon, P2};
use latheguard::job::{self, EffectiveJob, Layer};
use latheguard::machine::jaws::{Body, Chuck, Grip, JawType, Jaws};
use latheguard::machine::{self, ChuckForm, Machine};
use latheguard::pipeline::{self, Settings};
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn pts(v: &[[f64; 2]]) -> Vec<P2> {
    v.iter().map(|&[x, z]| p2(x, z)).collect()
}

/// The built-in machine's body: Ø210, a Ø50 bore, its face at z -30, 70 deep.
const BODY: Body = Body {
    diameter: 210.0,
    bore: 50.0,
    face: -30.0,
    depth: 70.0,
};

fn chuck(grip: Grip, kind: JawType, [d, l, h, w, s]: [f64; 5]) -> Chuck {
    Chuck {
        body: BODY,
        jaws: Jaws {
            grip,
            kind,
            grip_diameter: d,
            grip_length: l,
            height: h,
            width: w,
            step: s,
        },
    }
}

/// Each outline below is worked by hand from the table of docs/machine.md: the body `25 .. 105`
/// from z -100 to -30, then the jaw's two layers (`a = grip_diameter / 2`), the outline running
/// up the outside and back down the inside from the body's inner back corner.
#[test]
fn each_jaw_type_and_grip_draws_the_outline_worked_by_hand() {
    let cases: [(&str, Chuck, Vec<P2>); 7] = [
        (
            // a = 25: lower 25 .. 70 (z -30 .. -12), step 25 .. 45 (z -12 .. 0).
            "hard, outside, the built-in machine's",
            chuck(Grip::Outside, JawType::Hard, [50.0, 12.0, 30.0, 45.0, 20.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [70.0, -30.0],
                [70.0, -12.0],
                [45.0, -12.0],
                [45.0, 0.0],
                [25.0, 0.0],
            ]),
        ),
        (
            // a = 15, inside the bore: lower 15 .. 60, step 15 .. 35; the jaws overhang the bore.
            "hard, outside, closed on Ø30",
            chuck(Grip::Outside, JawType::Hard, [30.0, 12.0, 30.0, 45.0, 20.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [60.0, -30.0],
                [60.0, -12.0],
                [35.0, -12.0],
                [35.0, 0.0],
                [15.0, 0.0],
                [15.0, -30.0],
                [25.0, -30.0],
            ]),
        ),
        (
            // a = 100: lower 100 .. 145 overhangs the body's 105; step 100 .. 120.
            "hard, outside, on Ø200: wider than the body",
            chuck(Grip::Outside, JawType::Hard, [200.0, 12.0, 30.0, 45.0, 20.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [145.0, -30.0],
                [145.0, -12.0],
                [120.0, -12.0],
                [120.0, 0.0],
                [100.0, 0.0],
                [100.0, -30.0],
                [25.0, -30.0],
            ]),
        ),
        (
            // grip_length = height: the step alone, 25 .. 45 from the face to z 0.
            "hard, outside, gripping its whole height",
            chuck(Grip::Outside, JawType::Hard, [50.0, 30.0, 30.0, 45.0, 20.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [45.0, -30.0],
                [45.0, 0.0],
                [25.0, 0.0],
            ]),
        ),
        (
            // a = 60: lower 20 .. 60 (z -30 .. -15), step 45 .. 60 (z -15 .. -5).
            "hard, inside",
            chuck(Grip::Inside, JawType::Hard, [120.0, 10.0, 25.0, 40.0, 15.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [60.0, -30.0],
                [60.0, -5.0],
                [45.0, -5.0],
                [45.0, -15.0],
                [20.0, -15.0],
                [20.0, -30.0],
                [25.0, -30.0],
            ]),
        ),
        (
            // a = 20: seat 15 .. 65 (z -30 .. -15), bored 20 .. 65 (z -15 .. 0).
            "soft, outside",
            chuck(Grip::Outside, JawType::Soft, [40.0, 15.0, 30.0, 50.0, 5.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [65.0, -30.0],
                [65.0, 0.0],
                [20.0, 0.0],
                [20.0, -15.0],
                [15.0, -15.0],
                [15.0, -30.0],
                [25.0, -30.0],
            ]),
        ),
        (
            // a = 50, faces at z -10: seat 26 .. 56 (z -30 .. -22), bored 26 .. 50 (z -22 .. -10).
            "soft, inside",
            chuck(Grip::Inside, JawType::Soft, [100.0, 12.0, 20.0, 30.0, 6.0]),
            pts(&[
                [25.0, -100.0],
                [105.0, -100.0],
                [105.0, -30.0],
                [56.0, -30.0],
                [56.0, -22.0],
                [50.0, -22.0],
                [50.0, -10.0],
                [26.0, -10.0],
                [26.0, -30.0],
                [25.0, -30.0],
            ]),
        ),
    ];
    for (name, c, want) in cases {
        let got = c.polygon().unwrap_or_else(|e| panic!("{name}: {e:?}"));
        assert_eq!(got.points(), &want[..], "{name}");
        // The hand-worked list is itself a valid outline in the same order.
        assert_eq!(got.points(), Polygon::new(&want).unwrap().points(), "{name}");
    }
}

/// The fenced TOML blocks of a page that hold `[chuck.jaws]`, each with the outline its
/// `# = outline [[…]]` comment gives (continued on `#` lines), if any.
fn jaws_blocks(page: &str) -> Vec<(String, Option<Vec<P2>>)> {
    let text = std::fs::read_to_string(root().join(page)).unwrap();
    let mut out = Vec::new();
    let mut block: Option<String> = None;
    for line in text.lines() {
        if line.starts_with("```toml") {
            block = Some(String::new());
        } else if line.starts_with("```") {
            if let Some(b) = block.take() {
                if b.contains("[chuck.jaws]") {
                    let outline = b.find("# = outline").map(|at| {
                        let tail: String = b[at + "# = outline".len()..]
                            .lines()
                            .map(|l| l.trim_start_matches('#').trim())
                            .collect::<Vec<_>>()
                            .join(" ");
                        let json = &tail[..tail.rfind("]]").unwrap() + 2];
                        let v: Vec<[f64; 2]> = serde_json::from_str(json).unwrap();
                        pts(&v)
                    });
                    out.push((b, outline));
                }
            }
        } else if let Some(b) = block.as_mut() {
            b.push_str(line);
            b.push('\n');
        }
    }
    out
}

/// The built-in machine with its `[chuck]` and `[chuck.jaws]` replaced by `chuck`, without its
/// Ø50 bar (the examples grip other parts).
fn builtin_with_chuck(chuck: &str) -> String {
    let t = machine::BUILTIN_TOML;
    let start = t.find("[chuck]").unwrap();
    let jaws = start + t[start..].find("[chuck.jaws]").unwrap();
    let end = jaws + t[jaws..].find("\n\n").unwrap();
    let t = format!("{}{chuck}{}", &t[..start], &t[end..]);
    let stock = t.find("[stock]").unwrap();
    let after = stock + t[stock..].find("\n\n").unwrap();
    format!("{}{}", &t[..stock], &t[after..])
}

#[test]
fn every_jaws_example_of_docs_machine_md_loads_and_draws_the_outline_its_comment_gives() {
    let blocks = jaws_blocks("docs/machine.md");
    assert_eq!(blocks.len(), 3, "the built-in's, soft outside, hard inside");
    for (toml, outline) in blocks {
        let m =
            machine::from_toml(&builtin_with_chuck(&toml), "docs/machine.md").unwrap_or_else(|e| panic!("{e}\n{toml}"));
        let want = outline.expect("each example gives its outline");
        assert_eq!(m.chuck.as_ref().unwrap().points(), &want[..], "{toml}");
    }
}

#[test]
fn every_jaws_example_of_docs_job_md_is_a_job_the_built_in_machine_takes() {
    let text = std::fs::read_to_string(root().join("docs/job.md")).unwrap();
    // The commented [chuck.jaws] of the keys example, uncommented.
    let at = text.find("# [chuck.jaws]").unwrap();
    let mut job = String::new();
    for line in text[at..].lines().take_while(|l| l.starts_with("# ")) {
        let l = line.trim_start_matches("# ");
        job.push_str(l.split("    #").next().unwrap().trim_end());
        job.push('\n');
    }
    assert!(
        job.contains("grip_diameter = 30.0") && job.contains("type = \"soft\""),
        "{job}"
    );
    // A Ø30 slug seated on the soft jaws' seat (z -5): the machine's Ø50 bar would not fit them.
    let slug = "[stock]\ndiameter = 30.0\nlength = 85.0\nstick_out = 80.0\n";
    let m = apply(&Machine::builtin(), &[("slug.job.toml", slug), ("keys.job.toml", &job)]).unwrap();
    let c = m.chuck_jaws().unwrap();
    assert_eq!(
        (c.jaws.kind, c.jaws.grip_diameter, c.jaws.step, c.faces()),
        (JawType::Soft, 30.0, 3.0, 10.0)
    );
    // The fixtures the page's shell examples run (tests/fixtures/docs).
    for f in ["face-groove.job.toml", "jaws-left-open.job.toml", "tall-jaws.job.toml"] {
        let t = std::fs::read_to_string(root().join("tests/fixtures/docs").join(f)).unwrap();
        apply(&Machine::builtin(), &[(f, &t)]).unwrap_or_else(|e| panic!("{f}: {e}"));
    }
}

/// `layers` (file name, text), lowest first, merged and applied to `m`.
fn apply(m: &Machine, layers: &[(&str, &str)]) -> Result<Machine, job::JobError> {
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no {rel}")) };
    let parsed: Vec<Layer> = layers
        .iter()
        .map(|(name, text)| job::parse(text, name, ".", name, &mut no_files))
        .collect::<Result<_, _>>()?;
    job::apply(m, &EffectiveJob::merge(&parsed))
}

fn jaws_of(m: &Machine) -> Jaws {
    m.chuck_jaws().unwrap().jaws
}

#[test]
fn a_jobs_jaws_lay_over_the_machines_key_by_key_and_close_on_its_bar() {
    let base = Machine::builtin();
    let builtin_jaws = jaws_of(&base);
    // A bar alone closes the jaws on it; nothing else changes.
    let bar = "[stock]\ndiameter = 30.0\nlength = 120.0\nstick_out = 80.0\n";
    let m = apply(&base, &[("bar.job.toml", bar)]).unwrap();
    assert_eq!(
        jaws_of(&m),
        Jaws {
            grip_diameter: 30.0,
            ..builtin_jaws
        }
    );
    assert_eq!(m.chuck.as_ref().unwrap().aabb().min.x, 15.0);
    // A layer's grip_diameter wins over the bar; the keys of two layers both apply.
    let m = apply(
        &base,
        &[
            ("bar.job.toml", bar),
            ("a.job.toml", "[chuck.jaws]\ngrip_length = 10.0\ngrip_diameter = 32.0\n"),
            ("b.job.toml", "[chuck.jaws]\nheight = 35.0\n"),
        ],
    )
    .unwrap();
    assert_eq!(
        jaws_of(&m),
        Jaws {
            grip_diameter: 32.0,
            grip_length: 10.0,
            height: 35.0,
            ..builtin_jaws
        }
    );
    assert_eq!(
        m.chuck.as_ref().unwrap().aabb().max.y,
        5.0,
        "the jaw faces at face + height"
    );
    assert_eq!(m.chuck_jaws().unwrap().body, base.chuck_jaws().unwrap().body);
    // The machine's frame, home and the bar's face stay: only the jaws moved.
    assert_eq!(
        (m.home, m.stock.as_ref().unwrap().front, m.program_zero_z),
        (base.home, 80.0, 80.0)
    );
    // A later chuck outline replaces the jaws; later jaws replace an earlier outline.
    let outline = "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]\n";
    let m = apply(&base, &[("bar.job.toml", bar), ("o.job.toml", outline)]).unwrap();
    assert_eq!(m.chuck_form, Some(ChuckForm::Outline));
    assert_eq!(m.chuck.as_ref().unwrap().points().len(), 4, "no jaws closed on the bar");
    let m = apply(
        &base,
        &[
            ("o.job.toml", outline),
            ("j.job.toml", "[chuck.jaws]\ngrip_diameter = 60.0\n"),
        ],
    )
    .unwrap();
    assert_eq!(jaws_of(&m).grip_diameter, 60.0);
    // An inside grip closes on a tube's bore; a revolved stock and no stock leave the jaws.
    let tube = "[stock]\ndiameter = 120.0\nbore = 100.0\nlength = 40.0\nstick_out = 30.0\n";
    let inside = "[chuck.jaws]\ngrip = \"inside\"\nwidth = 30.0\nstep = 10.0\ngrip_length = 10.0\nheight = 30.0\n";
    let m = apply(&base, &[("tube.job.toml", tube), ("in.job.toml", inside)]);
    // The tube (z -10 .. 30) is held on its bore for 10 mm, its back end on the jaws' lower layer.
    let m = m.unwrap();
    assert_eq!((jaws_of(&m).grip, jaws_of(&m).grip_diameter), (Grip::Inside, 100.0));
    let revolved = "[stock]\noutline = [[0, -12], [15, -12], [15, 41], [0, 41]]\n";
    let m = apply(&base, &[("r.job.toml", revolved)]);
    // The revolved blank reaches into the jaws drawn for Ø50 nowhere (radius 15 < 25).
    assert_eq!(jaws_of(&m.unwrap()), builtin_jaws);
    let m = apply(&base, &[("n.job.toml", "[stock]\nnone = true\n")]).unwrap();
    assert_eq!(jaws_of(&m), builtin_jaws);
}

/// The program of `tests/cases/jaws/`: a slim face-grooving blade fed at X36 (radius 18 .. 21)
/// to 6 mm past the jaw faces, on a Ø30 bar. With the jaws as the machine file draws them for
/// its Ø50 bar (radius 25 up), it passes between bar and jaws — the false green of a chuck that
/// did not follow the bar. Closed on the bar (radius 15 up), they stop it at line 7.
#[test]
fn a_30_mm_bar_on_the_built_in_machine_closes_the_jaws_where_a_tool_used_to_pass() {
    let dir = root().join("tests/cases/jaws");
    let job_text = std::fs::read_to_string(dir.join("bar30_groove_into_jaws.job.toml")).unwrap();
    let base = Machine::builtin();
    let closed = apply(&base, &[("bar30.job.toml", &job_text)]).unwrap();
    let open = apply(
        &base,
        &[
            ("bar30.job.toml", &job_text),
            ("open.job.toml", "[chuck.jaws]\ngrip_diameter = 50.0\n"),
        ],
    )
    .unwrap();
    let run = |name: &str, m: &Machine| {
        pipeline::check(&std::fs::read(dir.join(name)).unwrap(), m, &Settings::default()).findings
    };
    let crash = run("bar30_groove_into_jaws.nc", &closed);
    let errors: Vec<_> = crash.iter().filter(|f| f.severity == Severity::Error).collect();
    assert_eq!(errors.len(), 1, "{crash:#?}");
    let f = errors[0];
    assert_eq!((f.line, f.kind), (7, Kind::Collision));
    assert_eq!(f.objects, ["T03 insert", "chuck"]);
    assert!((f.depth_mm.unwrap() - 6.0).abs() < 1e-6, "{f:?}");
    assert!(
        run("bar30_groove_into_jaws.nc", &open).is_empty(),
        "the jaws left open: the old false green"
    );
    assert!(
        run("bar30_groove_clear.nc", &closed).is_empty(),
        "stopping 1 mm short is clean"
    );
    // The same from the command line, with the job beside the program.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(dir.join("bar30_groove_into_jaws.nc"), tmp.path().join("p.nc")).unwrap();
    std::fs::write(tmp.path().join("p.job.toml"), &job_text).unwrap();
    let o = common::latheguard(tmp.path(), &["check", "--no-timing", "p.nc"]);
    assert_eq!(o.status.code(), Some(1));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.starts_with("p.nc:7: error[collision]: the T03 insert hits the chuck (depth 6.000 mm"),
        "{text}"
    );
}

/// One job file's first error as `file:line:col: key: message` (the first line of its text).
fn job_error(m: &Machine, text: &str) -> String {
    apply(m, &[("part.job.toml", text)]).unwrap_err().to_string()
}

#[test]
fn every_jaws_error_of_a_job_names_its_file_line_column_and_key() {
    let base = Machine::builtin();
    let bar30 = "[stock]\ndiameter = 30.0\nlength = 120.0\nstick_out = 80.0\n";
    let cases: [(&str, &str); 11] = [
        (
            "[chuck.jaws]\ngrip_diameter = -4\n",
            "part.job.toml:2:17: chuck.jaws.grip_diameter: must be greater than 0, not -4",
        ),
        (
            "[chuck.jaws]\nheight = 0\n",
            "part.job.toml:2:10: chuck.jaws.height: must be greater than 0, not 0",
        ),
        (
            "[chuck.jaws]\ntype = \"medium\"\n",
            "part.job.toml:2:8: chuck.jaws.type: unknown value `medium`, expected `hard` or `soft`",
        ),
        (
            "[chuck.jaws]\ngrip = \"sideways\"\n",
            "part.job.toml:2:8: chuck.jaws.grip: unknown value `sideways`, expected `outside` or `inside`",
        ),
        (
            "[chuck.jaws]\nbody = 3\n",
            "part.job.toml:2:1: chuck.jaws.body: unknown key `body`, expected one of `grip`, `type`, `grip_diameter`, `grip_length`, `height`, `width`, `step`",
        ),
        (
            "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]\n[chuck.jaws]\nheight = 20\n",
            "part.job.toml:2:11: chuck.outline: give the chuck either as an `outline` or as `[chuck.jaws]` over the machine file's jaws, not both",
        ),
        (
            "[chuck.jaws]\ngrip_length = 40.0\n",
            "part.job.toml:2:15: chuck.jaws.grip_length: the jaws grip for 40 mm but stand only 30 mm out of the chuck face (chuck.jaws.height)",
        ),
        (
            "[chuck.jaws]\nstep = 50.0\n",
            "part.job.toml:2:8: chuck.jaws.step: the gripping step (50 mm) is wider than the jaw (45 mm, chuck.jaws.width)",
        ),
        (
            "[chuck.jaws]\ngrip = \"inside\"\n",
            "part.job.toml:2:8: chuck.jaws.grip: jaws 45 mm wide opened in Ø50: they reach 20 mm past the spindle axis (the machine file's chuck.jaws.width with this job's jaws)",
        ),
        (
            // Jaws closed on a bar as wide as the chuck stand off its body.
            "[stock]\ndiameter = 300.0\nlength = 60.0\nstick_out = 40.0\n",
            "part.job.toml:2:12: stock.diameter: jaws gripping Ø300 stand at radius 150 .. 195 at the chuck face, off the body (radius 25 .. 105): they must stand on it (the jaws close on the job's bar, Ø300; give chuck.jaws.grip_diameter for another grip)",
        ),
        (
            // The jaws held open narrower than the bar: the bar overlaps them.
            "[stock]\ndiameter = 30.0\nlength = 120.0\nstick_out = 80.0\n[chuck.jaws]\ngrip_diameter = 28.0\n",
            "part.job.toml:6:17: chuck.jaws.grip_diameter: the bar (Ø30, z -40 .. 80) overlaps the chuck by 1.000 mm: it is wider than the chuck's bore where it reaches (the jaws grip it where their faces touch it) (the jaws grip Ø28)",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(job_error(&base, text).lines().next().unwrap(), want, "{text}");
    }
    // A soft jaw seats the part: a bar that reaches past the seat is too long.
    let e = job_error(&base, &format!("{bar30}[chuck.jaws]\ntype = \"soft\"\nstep = 3.0\n"));
    assert_eq!(
        e,
        "part.job.toml:3:10: stock.length: the bar (Ø30, z -40 .. 80) overlaps the chuck by 3.000 mm: its back end reaches past the soft jaws' seat at z -12 (a part in soft jaws rests on it); make it at most 92 mm long or move stock.front"
    );
    // A [job] of latheguard.toml names the whole key path.
    let mut no_files = |_: &str, rel: &str| -> Result<(String, String), String> { Err(format!("no {rel}")) };
    let e = match job::parse_embedded(
        "[job.chuck.jaws]\nwidth = -1\n",
        "latheguard.toml",
        &["job"],
        ".",
        "latheguard.toml [job]",
        &mut no_files,
    ) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("a negative width is refused"),
    };
    assert_eq!(
        e,
        "latheguard.toml:2:9: job.chuck.jaws.width: must be greater than 0, not -1"
    );
}

/// The error lines docs/job.md quotes in its "Jaws" section, as the loader gives them.
#[test]
fn the_jaws_errors_docs_job_md_quotes_are_the_loaders() {
    let text = std::fs::read_to_string(root().join("docs/job.md")).unwrap();
    let section = &text[text.find("## Jaws: `[chuck.jaws]`").unwrap()..];
    let block = &section[section.find("```text\n").unwrap() + 8..];
    let quoted: Vec<&str> = block[..block.find("```").unwrap()].lines().collect();
    // The job's [chuck.jaws] at line 12, its grip_length at line 14 (eleven comment lines first).
    let job = format!(
        "{}[chuck.jaws]\ngrip_diameter = 30.0\ngrip_length = 40.0\n",
        "# a comment\n".repeat(11)
    );
    let haas = std::fs::read_to_string(root().join("machines/haas-style-inch.toml")).unwrap();
    let haas = machine::from_toml(&haas, "haas-style-inch.toml").unwrap();
    assert_eq!(haas.chuck_form, Some(ChuckForm::Outline));
    let got = [job_error(&haas, &job), job_error(&Machine::builtin(), &job)];
    let got: Vec<String> = got.iter().map(|e| format!("latheguard: {e}")).collect();
    assert_eq!(quoted, got);
}

#[test]
fn setup_and_machine_show_the_jaws_and_where_they_came_from() {
    let docs = root().join("tests/fixtures/docs");
    let tmp = tempfile::tempdir().unwrap();
    for f in ["face-groove.nc", "face-groove.job.toml", "tall-jaws.job.toml"] {
        std::fs::copy(docs.join(f), tmp.path().join(f)).unwrap();
    }
    let text = |args: &[&str]| {
        let o = common::latheguard(tmp.path(), args);
        assert_eq!(o.status.code(), Some(0), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let t = text(&["setup", "face-groove.nc"]);
    assert!(
        t.contains("\n  jaws          hard, outside grip on Ø30 for 12 mm, 30 mm high  [face-groove.job.toml]\n"),
        "{t}"
    );
    let t = text(&["setup", "--no-config", "--stock", "40x100@70", "face-groove.nc"]);
    assert!(
        t.contains("  jaws          hard, outside grip on Ø40 for 12 mm, 30 mm high  [command line]\n"),
        "the flag's bar is the job's: {t}"
    );
    std::fs::copy(docs.join("face-groove.nc"), tmp.path().join("plain.nc")).unwrap();
    let t = text(&[
        "setup",
        "-m",
        &root().join("machines/haas-style-inch.toml").display().to_string(),
        "plain.nc",
    ]);
    assert!(!t.contains("  jaws "), "no jaws line for an outline chuck: {t}");
    let j: serde_json::Value = serde_json::from_str(&text(&[
        "setup",
        "--format",
        "json",
        "--job",
        "tall-jaws.job.toml",
        "face-groove.nc",
    ]))
    .unwrap();
    assert_eq!(
        j["jaws"],
        serde_json::json!({
            "grip": "outside", "type": "soft", "grip_diameter": 30.0, "grip_length": 15.0,
            "height": 40.0, "width": 45.0, "step": 3.0, "faces_z": 10.0, "from": "tall-jaws.job.toml",
        })
    );
    assert_eq!(j["chuck"]["from"], "tall-jaws.job.toml");
    let t = text(&[
        "machine",
        &root().join("machines/generic-slant-bed.toml").display().to_string(),
    ]);
    assert!(
        t.contains("\n  jaws        hard, outside grip on Ø50 for 12 mm, 30 mm high; body Ø210, bore Ø50, face at z -30, 70 deep\n"),
        "{t}"
    );
}

#[test]
fn the_schemas_know_the_jaws_and_refuse_a_body_in_a_job() {
    let machine_schema: serde_json::Value = serde_json::from_str(&machine::schema()).unwrap();
    let v = jsonschema::validator_for(&machine_schema).unwrap();
    let doc =
        |t: &str| -> serde_json::Value { serde_json::to_value(toml::from_str::<toml::Value>(t).unwrap()).unwrap() };
    let builtin = doc(machine::BUILTIN_TOML);
    assert!(v.is_valid(&builtin));
    let mut bad = builtin.clone();
    bad["chuck"]["jaws"]["grip"] = "sideways".into();
    assert!(!v.is_valid(&bad), "an unknown grip");
    let mut bad = builtin.clone();
    bad["chuck"]["jaws"].as_object_mut().unwrap().remove("step");
    assert!(!v.is_valid(&bad), "a machine file's jaws need every size");
    let job_schema: serde_json::Value = serde_json::from_str(&job::schema()).unwrap();
    let v = jsonschema::validator_for(&job_schema).unwrap();
    assert!(v.is_valid(&doc("[chuck.jaws]\ngrip_diameter = 30.0\ntype = \"soft\"\n")));
    assert!(!v.is_valid(&doc("[chuck.jaws]\ngrip = \"sideways\"\n")));
    assert!(
        !v.is_valid(&doc(
            "[chuck]\nbody = { diameter = 210.0, face = -30.0, depth = 70.0 }\n"
        )),
        "the body is the machine's"
    );
    // The committed schemas are the generated ones (`machine --schema`, `schema job`).
    let committed = |f: &str| std::fs::read_to_string(root().join("machines").join(f)).unwrap();
    assert_eq!(committed("machine.schema.json"), machine::schema());
    assert_eq!(committed("job.schema.json"), job::schema());
}

/// On the turn-mill machine the 3D chuck is revolved from the 2D outline (`revolved =
/// "chuck"`): a job's jaws move it too, so the 3D path sees the jaws where the 2D path does.
#[test]
fn a_jobs_jaws_move_the_turn_mill_trees_chuck_too() {
    let dir = root().join("machines");
    let text = std::fs::read_to_string(dir.join("turn-mill.toml")).unwrap();
    let read = |n: &str| std::fs::read(dir.join(n)).map_err(|e| e.to_string());
    let base = machine::from_toml_with(&text, "turn-mill.toml", &read).unwrap();
    let revolved_chuck = |m: &Machine| -> Vec<P2> {
        let k = m.kinematics.as_ref().unwrap();
        let c = k.components.iter().find(|c| c.name == "main_chuck").unwrap();
        match &c.geometry {
            Some(latheguard::kin::Geometry::Revolved(p)) => p.clone(),
            g => panic!("{g:?}"),
        }
    };
    assert_eq!(revolved_chuck(&base), base.chuck.as_ref().unwrap().points());
    let m = apply(
        &base,
        &[(
            "bar.job.toml",
            "[stock]\ndiameter = 30.0\nlength = 120.0\nstick_out = 80.0\n",
        )],
    )
    .unwrap();
    assert_ne!(m.chuck, base.chuck);
    assert_eq!(revolved_chuck(&m), m.chuck.as_ref().unwrap().points());
}
