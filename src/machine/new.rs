//! `latheguard machine new`: a commented starter machine file from a few answers.
//!
//! Every answer has a default (a small Fanuc slant-bed lathe); the file written is a valid
//! machine file for every combination of answers within their ranges ([`NewSpec::check`]), with
//! one OD tool (and a parting tool) to edit, a chuck given by its body and hard jaws from the chuck
//! size, jaw height and bar capacity, and a bar of 80 % of the bar capacity (the jaws closed on it).

use std::fmt::Write as _;

/// The answers. Lengths in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct NewSpec {
    pub name: String,
    /// Chuck outside diameter, 80 ..= 1000 mm (default 210).
    pub chuck_diameter: f64,
    /// How far the jaws stand out of the chuck face, 5 ..= 100 mm (default 30).
    pub jaw_height: f64,
    /// The largest bar through the spindle, 5 ..= chuck diameter / 2 (default 52).
    pub bar_capacity: f64,
    /// Stations, 1 ..= 24 (default 8 on a drum, 4 on a gang slide).
    pub stations: u32,
    /// A gang slide instead of a drum turret.
    pub gang: bool,
    /// Travel of the turret reference point, mm: X (radius) 100 ..= 2000 (default 300), Z
    /// 100 ..= 5000 (default 600).
    pub x_travel: f64,
    pub z_travel: f64,
    /// `"fanuc"`, `"linuxcnc"` or `"auto"` (default fanuc).
    pub dialect: String,
    /// Program units at start, `"mm"` or `"inch"` (default mm).
    pub inch: bool,
}

impl Default for NewSpec {
    fn default() -> NewSpec {
        NewSpec {
            name: "My lathe".into(),
            chuck_diameter: 210.0,
            jaw_height: 30.0,
            bar_capacity: 52.0,
            stations: 8,
            gang: false,
            x_travel: 300.0,
            z_travel: 600.0,
            dialect: "fanuc".into(),
            inch: false,
        }
    }
}

impl NewSpec {
    /// The answers' ranges: the first answer out of range, as `--flag: message`.
    pub fn check(&self) -> Result<(), String> {
        let within = |flag: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(format!("--{flag}: {v} is out of range: must be from {lo} to {hi} mm"))
            }
        };
        within("chuck-diameter", self.chuck_diameter, 80.0, 1000.0)?;
        within("jaw-height", self.jaw_height, 5.0, 100.0)?;
        within("bar-capacity", self.bar_capacity, 5.0, self.chuck_diameter / 2.0)?;
        within("x-travel", self.x_travel, 100.0, 2000.0)?;
        within("z-travel", self.z_travel, 100.0, 5000.0)?;
        if !(1..=24).contains(&self.stations) {
            return Err(format!(
                "--stations: {} is out of range: must be from 1 to 24",
                self.stations
            ));
        }
        if !["fanuc", "linuxcnc", "auto"].contains(&self.dialect.as_str()) {
            return Err(format!("--dialect: {:?} is not fanuc, linuxcnc or auto", self.dialect));
        }
        if self.name.trim().is_empty() || self.name.contains(['"', '\\', '\n', '\r']) {
            return Err("--name: give a name without quotes, backslashes or line breaks".into());
        }
        Ok(())
    }
}

fn n(x: f64) -> String {
    let r = (x * 1000.0).round() / 1000.0;
    if r == r.trunc() {
        format!("{r:.1}")
    } else {
        format!("{r}")
    }
}

/// The starter file's text.
pub fn starter(s: &NewSpec) -> String {
    let big_r = s.chuck_diameter / 2.0;
    let bore = s.bar_capacity / 2.0;
    let stock_d = (s.bar_capacity * 0.8 * 10.0).round() / 10.0;
    let rs = stock_d / 2.0;
    let h = s.jaw_height;
    let body = (s.chuck_diameter * 0.5).max(40.0);
    let jaw_out = (bore + (big_r - bore) * 0.6).max(rs + 5.0);
    let front = (stock_d * 1.5).clamp(20.0, 150.0);
    let length = front + h + 20.0;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "# {} — a starter machine file written by `latheguard machine new`.",
        s.name
    );
    let _ = writeln!(
        o,
        "# Every key is described in docs/machine.md. Measure your lathe and edit: the chuck, the"
    );
    let _ = writeln!(
        o,
        "# turret and the tools below are drawn from the answers given, not from your machine."
    );
    let _ = writeln!(o, "#");
    let _ = writeln!(
        o,
        "# Frames: z along the spindle axis, z = 0 at the jaw faces, +z toward the tailstock; x = radius,"
    );
    let _ = writeln!(
        o,
        "# +x from the spindle axis toward the turret. Points are [x, z] in mm (also for inch programs).\n"
    );
    let _ = writeln!(o, "[machine]\nname = \"{}\"\ndialect = \"{}\"", s.name, s.dialect);
    if s.inch {
        let _ = writeln!(o, "units = \"inch\"             # programs start in G20");
    }
    let _ = writeln!(
        o,
        "rapid = \"dogleg\"           # \"linear\" if the control interpolates rapids\n"
    );
    // Axes: the reference point's travel; the tools reach 50 mm in -x of it on a drum.
    let (x_min, x_max) = if s.gang {
        let last = 10.0 + 80.0 * (s.stations - 1) as f64;
        (-(last + 10.0), s.x_travel - last - 10.0)
    } else {
        (-10.0, s.x_travel - 10.0)
    };
    // Home is at x max: the tools there must clear the chuck (its radius and 120 mm for them).
    let asked = x_max;
    let x_max = x_max.max(big_r + 120.0);
    let z_min = -h - 10.0;
    let z_max = z_min + s.z_travel;
    let _ = writeln!(
        o,
        "[axes]\n# The turret reference point's travel and rapid rates (mm/min)."
    );
    if x_max > asked {
        let _ = writeln!(
            o,
            "# x max is {} here, not {} as --x-travel {} gives: home is at x max, and the tools there must\n# clear the Ø{} chuck (its radius and 120 mm). Measure your lathe's travel and home and edit.",
            n(x_max),
            n(asked),
            n(s.x_travel),
            n(s.chuck_diameter)
        );
    }
    let _ = writeln!(o, "x = {{ min = {}, max = {}, rapid = 20000.0 }}", n(x_min), n(x_max));
    let _ = writeln!(o, "z = {{ min = {}, max = {}, rapid = 24000.0 }}", n(z_min), n(z_max));
    let _ = writeln!(o, "home = [{}, {}]\n", n(x_max), n(z_max));
    let _ = writeln!(o, "[spindle]\nmax_rpm = 4000.0\n");
    let width = jaw_out - rs;
    let step = ((width * 0.5) * 10.0).round() / 10.0;
    let _ = writeln!(
        o,
        "[chuck]\n# Ø{} mm chuck, {} mm spindle bore, its face at z -{}; the jaws stand {} mm out of it (their\n# faces at z 0) and close on the bar. A job's bar closes them on its diameter (docs/job.md).",
        n(s.chuck_diameter),
        n(s.bar_capacity),
        n(h),
        n(h)
    );
    let _ = writeln!(
        o,
        "body = {{ diameter = {}, bore = {}, face = {}, depth = {} }}\n",
        n(s.chuck_diameter),
        n(s.bar_capacity),
        n(-h),
        n(body)
    );
    let _ = writeln!(o, "[chuck.jaws]");
    for (key, value, note) in [
        ("grip", "\"outside\"".to_string(), "\"inside\": the jaws open in a bore"),
        (
            "type",
            "\"hard\"".to_string(),
            "\"soft\": bored to the grip, the part seated behind it",
        ),
        ("grip_diameter", n(stock_d), "the diameter held"),
        (
            "grip_length",
            n(h.min(12.0)),
            "how long they hold it, back from their faces",
        ),
        ("height", n(h), "how far they stand out of the chuck face"),
        ("width", n(width), "a jaw's radial extent"),
        ("step", n(step), "the gripping step at the jaw tip, radially"),
    ] {
        let _ = writeln!(o, "{:<26}# {note}", format!("{key} = {value}"));
    }
    o.push('\n');
    let _ = writeln!(o, "# [tailstock]\n# outline = [[0, 300], [10, 315], [30, 315], [30, 900], [0, 900]]   # where it stands when advanced\n# advanced = false\n");
    let _ = writeln!(o, "# [mcodes]\n# tailstock_advance = 21\n# tailstock_retract = 22\n");
    let _ = writeln!(
        o,
        "[stock]\n# A Ø{} bar (80 % of the bar capacity), {} mm out of the jaws.\ndiameter = {}\nlength = {}\nfront = {}\n",
        n(stock_d),
        n(front),
        n(stock_d),
        n(length),
        n(front)
    );
    let _ = writeln!(o, "[setup]\nprogram_zero_z = {}     # Z0 on the bar's face\n", n(front));
    if s.gang {
        let width = 80.0 * s.stations as f64 + 20.0;
        let _ = writeln!(
            o,
            "[turret]\n# A gang slide: the tools stand side by side, 80 mm apart in x, in the working plane; the"
        );
        let _ = writeln!(
            o,
            "# reference point is the spindle-side end of the row, level with the tips; the plate is behind them."
        );
        let _ = writeln!(
            o,
            "type = \"gang\"\nstations = {}\nstart_station = 1\nindex_time = 0.0",
            s.stations
        );
        let _ = writeln!(
            o,
            "outline = [[0, 70], [{w}, 70], [{w}, 110], [0, 110]]\n",
            w = n(width)
        );
        let _ = writeln!(o, "# T1: OD turning, 55° insert, 12 mm shank along z.");
        let _ = writeln!(o, "[[tools]]\nstation = 1\nname = \"OD turn\"\ntip = [10.0, 0.0]");
        let _ = writeln!(o, "insert = [[0, 0], [11, 0.6], [16.8, 9.9], [5.8, 9.3]]\nholder = [[8, 1.5], [20, 1.5], [20, 70], [8, 70], [8, 12.8]]\nnose_radius = 0.4\ntip_direction = 3");
        if s.stations >= 2 {
            let _ = writeln!(o, "\n# T2: parting blade, 2 mm insert.");
            let _ = writeln!(
                o,
                "[[tools]]\nstation = 2\nname = \"Parting blade 2 mm\"\ntip = [90.0, 0.0]"
            );
            let _ = writeln!(o, "insert = [[0, 0], [4, 0.1], [4, 1.9], [0, 2]]\nholder = [[3, 0.15], [22, 0.15], [22, -6], [32, -6], [32, 70], [22, 70], [22, 1.85], [3, 1.85]]\nnose_radius = 0.1");
        }
    } else {
        let axis = (big_r * 0.8).max(100.0);
        let _ = writeln!(
            o,
            "[turret]\n# A drum turret: the reference point is the rim nearest the spindle axis, halfway through the"
        );
        let _ = writeln!(o, "# drum's 60 mm; the drum is {} mm across.", n(2.0 * axis));
        let _ = writeln!(
            o,
            "type = \"drum\"\nstations = {}\nstart_station = 1\naxis = {}\nindex_time = 0.5",
            s.stations,
            n(axis)
        );
        let _ = writeln!(
            o,
            "outline = [[0, -30], [{d}, -30], [{d}, 30], [0, 30]]\n",
            d = n(2.0 * axis)
        );
        let _ = writeln!(o, "# T1: OD turning, 80° insert, 25 mm shank standing on the rim.");
        let _ = writeln!(o, "[[tools]]\nstation = 1\nname = \"OD turn\"\ntip = [-50.0, -10.0]");
        let _ = writeln!(o, "insert = [[0, 0], [12, 2], [14, 14], [2, 12]]\nholder = [[5, 8], [50, 8], [50, 28], [8, 28]]\nnose_radius = 0.8\ntip_direction = 3");
        if s.stations >= 2 {
            let _ = writeln!(o, "\n# T2: parting blade, 2.5 mm insert.");
            let _ = writeln!(
                o,
                "[[tools]]\nstation = 2\nname = \"Parting blade 2.5 mm\"\ntip = [-50.0, -4.0]"
            );
            let _ = writeln!(o, "insert = [[0, 0], [5, 0.1], [5, 2.4], [0, 2.5]]\nholder = [[4, 0.2], [35, 0.2], [35, -8], [50, -8], [50, 17], [35, 17], [35, 2.3], [4, 2.3]]\nnose_radius = 0.2");
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every combination of the answers at their extremes and defaults loads clean.
    #[test]
    fn every_combination_of_answers_gives_a_machine_file_that_loads() {
        let mut n_ok = 0;
        for chuck in [80.0, 210.0, 1000.0] {
            for jaw in [5.0, 30.0, 100.0] {
                for bar_f in [0.0, 0.5, 1.0] {
                    for stations in [1, 2, 8, 24] {
                        for gang in [false, true] {
                            for (xt, zt) in [(100.0, 100.0), (300.0, 600.0), (2000.0, 5000.0)] {
                                for dialect in ["fanuc", "linuxcnc", "auto"] {
                                    let spec = NewSpec {
                                        chuck_diameter: chuck,
                                        jaw_height: jaw,
                                        bar_capacity: 5.0 + bar_f * (chuck / 2.0 - 5.0),
                                        stations,
                                        gang,
                                        x_travel: xt,
                                        z_travel: zt,
                                        dialect: dialect.into(),
                                        inch: stations % 2 == 0,
                                        ..NewSpec::default()
                                    };
                                    spec.check().unwrap();
                                    let text = starter(&spec);
                                    let m = crate::machine::from_toml(&text, "new.toml")
                                        .unwrap_or_else(|e| panic!("{spec:?}\n{e}\n{text}"));
                                    assert!(m.warnings.is_empty(), "{spec:?}: {:?}", m.warnings);
                                    n_ok += 1;
                                }
                            }
                        }
                    }
                }
            }
        }
        assert_eq!(n_ok, 3 * 3 * 3 * 4 * 2 * 3 * 3);
    }

    #[test]
    fn answers_out_of_range_are_refused_with_their_flag() {
        let bad = NewSpec {
            bar_capacity: 200.0,
            ..NewSpec::default()
        };
        assert!(bad.check().unwrap_err().starts_with("--bar-capacity"));
        let bad = NewSpec {
            stations: 0,
            ..NewSpec::default()
        };
        assert!(bad.check().unwrap_err().starts_with("--stations"));
    }

    #[test]
    fn an_x_travel_too_short_for_home_to_clear_the_chuck_is_raised_and_the_file_says_why() {
        // 205 mm of travel puts x max at 195, inside the 210 mm chuck's radius + 120.
        let short = NewSpec {
            x_travel: 205.0,
            ..NewSpec::default()
        };
        let text = starter(&short);
        assert!(text.contains("x = { min = -10.0, max = 225.0,"), "{text}");
        assert!(
            text.contains("# x max is 225.0 here, not 195.0 as --x-travel 205.0 gives"),
            "{text}"
        );
        // Travel enough: as asked, and no such note.
        let text = starter(&NewSpec::default());
        assert!(text.contains("max = 290.0,") && !text.contains("x max is"), "{text}");
    }
}
