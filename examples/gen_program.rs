//! Benchmark program generator: writes a long, realistic, valid lathe program.
//!
//! ```text
//! cargo run --release --example gen_program -- --lines 100000 --dialect linuxcnc > p.ngc
//! cargo run --release --example gen_program -- --lines 100000 --dialect fanuc --seed 7 > p.nc
//! ```
//!
//! Options: `--lines N` (about N lines, default 100000), `--dialect linuxcnc|fanuc` (default
//! linuxcnc), `--seed S` (default 1). The output is a pure function of the options: the random
//! choices come from a 64-bit LCG (no `rand`), all geometry is computed in integer micrometres,
//! so the same options always give the same bytes.
//!
//! What the program does: a 50 mm bar (radius 25), program Z0 at the faced front, stock front at
//! Z2. After a metric, XZ-plane, absolute header and a spindle start it machines "parts" one after
//! another (as a bar-fed production run would), each with a new random stepped OD profile:
//!   * facing passes at Z1 and Z0 (bar radius 25 to 0.8 mm past the axis, so no pip is left);
//!   * roughing passes along Z at falling levels (G0 approach at Z2, G1 along Z, G1 45-degree
//!     pull-off, G0 retract to Z2), stopping short of each shoulder by a finishing allowance;
//!   * a finishing pass along the profile: front chamfer or corner radius, concave shoulder
//!     fillets (G2, quarter circles), convex shoulder corners (G3) or chamfers, and shallow
//!     circular grooves (G2 with both I and K non-zero, built from Pythagorean triples).
//!
//! Arcs are in I/K (centre, incremental, radius values) format; start and end radius are exactly
//! equal (integer micrometre geometry), so rs274ngc's radius checks always pass. Comments and N
//! numbers appear now and then; the tool is changed rarely (every few parts, alternating the OD tools T1 and T2).
//! All positions stay within X (radius) 0..25 mm and Z -70..2 mm; tool changes happen at X25 Z2
//! (radius 25, i.e. X50. on Fanuc).
//!
//! Dialects:
//!   * `linuxcnc`: `G18 G21 G90 G8 G40 G95` (G8: X words are radii, which is also how rs274 prints
//!     X), tool change `T2 M6`, ends with `M30`. Accepted by LinuxCNC's `rs274 -g`.
//!   * `fanuc`: `%` / `O1000` framing, `G18 G21 G40 G97 G99` (no G90: on a Fanuc lathe, G-code
//!     system A, G90 is the OD turning cycle; X/Z are absolute anyway), X words are *diameters*
//!     with a decimal point (`X37.5`, `X50.`), arc I/K stay radius values, tool change `T0202`,
//!     ends with `M30` and `%`.

use std::io::{self, BufWriter, Write};
use std::process::ExitCode;

/// Micrometres: all geometry is integer so arc radii are exact.
type Um = i64;

const STOCK_R: Um = 25_000;
const Z_CLEAR: Um = 2_000;
const Z_MIN: Um = -70_000;
const MAX_PROFILE_R: Um = 21_000;
const ALLOW_X: Um = 200; // finishing allowance left by roughing, radius
const ALLOW_Z: Um = 200; // finishing allowance left by roughing, along Z

#[derive(Clone, Copy, PartialEq)]
enum Dialect {
    LinuxCnc,
    Fanuc,
}

/// Knuth's MMIX LCG; the high bits are used.
struct Lcg(u64);

impl Lcg {
    fn new(seed: u64) -> Self {
        let mut l = Lcg(seed ^ 0x5DEE_CE66_D1CE_4E5B);
        l.next();
        l.next();
        l
    }
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
    /// Uniform in lo..=hi.
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        if hi <= lo {
            return lo;
        }
        lo + (self.next() % ((hi - lo + 1) as u64)) as i64
    }
    /// Uniform in lo..=hi, a multiple of `step`.
    fn stepped(&mut self, lo: Um, hi: Um, step: Um) -> Um {
        let lo_s = (lo + step - 1).div_euclid(step);
        let hi_s = hi.div_euclid(step);
        self.range(lo_s, hi_s.max(lo_s)) * step
    }
    /// True with probability num/den.
    fn chance(&mut self, num: u64, den: u64) -> bool {
        self.next() % den < num
    }
}

struct Out<W: Write> {
    w: W,
    dialect: Dialect,
    lines: usize,
    n_next: u32,
}

impl<W: Write> Out<W> {
    fn line(&mut self, s: &str) -> io::Result<()> {
        self.lines += 1;
        self.w.write_all(s.as_bytes())?;
        self.w.write_all(b"\n")
    }
    /// A block with an N number in front.
    fn numbered(&mut self, s: &str) -> io::Result<()> {
        let n = self.n_next;
        self.n_next = if self.n_next >= 99_980 { 10 } else { self.n_next + 10 };
        self.line(&format!("N{n} {s}"))
    }
    /// A length (Z, I, K, or an X already converted) in mm.
    fn num(&self, v: Um) -> String {
        let sign = if v < 0 { "-" } else { "" };
        let a = v.unsigned_abs();
        let (int, frac) = (a / 1000, a % 1000);
        let mut f = format!("{frac:03}");
        while f.ends_with('0') {
            f.pop();
        }
        match (self.dialect, f.is_empty()) {
            (Dialect::Fanuc, true) => format!("{sign}{int}."),
            (Dialect::LinuxCnc, true) => format!("{sign}{int}"),
            _ => format!("{sign}{int}.{f}"),
        }
    }
    /// An X word value: radius on LinuxCNC (G8), diameter on Fanuc.
    fn x(&self, r: Um) -> String {
        match self.dialect {
            Dialect::LinuxCnc => self.num(r),
            Dialect::Fanuc => self.num(2 * r),
        }
    }
    fn feed(&self, f: Um) -> String {
        // feed per revolution, in micrometres/rev -> mm/rev
        let s = self.num(f);
        s.trim_end_matches('.').to_string()
    }
}

/// One cylindrical section of the profile: radius `r` from the previous shoulder to `z_end`.
struct Section {
    r: Um,
    z_end: Um,
    /// Concave fillet radius where this section meets the next, larger one (0: sharp).
    fillet: Um,
    /// Top corner of the shoulder after this section: 0 sharp, >0 convex radius, <0 chamfer.
    corner: Um,
    /// Optional circular groove in the middle of the section: (a, b) with a^2 + b^2 = c^2;
    /// centre a above the surface, half width b, radius c, depth c - a.
    groove: Option<(Um, Um)>,
}

struct Profile {
    /// Front edge at Z0: >0 convex radius, <0 chamfer, 0 sharp.
    front: Um,
    sections: Vec<Section>,
}

fn make_profile(rng: &mut Lcg) -> Profile {
    // Pythagorean triples (a, b): groove depth is c - a, half width b.
    const TRIPLES: [(Um, Um, Um); 5] = [(4, 3, 5), (12, 5, 13), (24, 7, 25), (3, 4, 5), (15, 8, 17)];
    let n = rng.range(2, 5) as usize;
    let mut rs = Vec::with_capacity(n);
    let mut r = rng.stepped(6_000, 13_000, 50);
    rs.push(r);
    for _ in 1..n {
        r += rng.stepped(1_500, 4_000, 50);
        if r > MAX_PROFILE_R {
            break;
        }
        rs.push(r);
    }
    let n = rs.len();
    let total = rng.stepped(20_000 + 6_000 * n as Um, 65_000.min(-Z_MIN - 2_000), 500);
    // split the length into sections of at least 6 mm
    let mut lens = vec![6_000; n];
    let mut rest = total - 6_000 * n as Um;
    while rest > 0 {
        let i = rng.range(0, n as i64 - 1) as usize;
        let d = rest.min(rng.stepped(500, 8_000, 500));
        lens[i] += d;
        rest -= d;
    }
    let front = match rng.range(0, 2) {
        0 => 0,
        1 => rng.stepped(500, 1_500, 250),
        _ => -rng.stepped(500, 1_500, 250),
    };
    let mut sections = Vec::with_capacity(n);
    let mut z = 0;
    for i in 0..n {
        z -= lens[i];
        let mut s = Section {
            r: rs[i],
            z_end: z,
            fillet: 0,
            corner: 0,
            groove: None,
        };
        if i + 1 < n {
            let h = rs[i + 1] - rs[i];
            if rng.chance(2, 3) {
                s.fillet = rng.stepped(250, (h / 3).min(1_500), 250);
            }
            if rng.chance(2, 3) {
                let c = rng.stepped(250, (h / 3).min(1_000), 250);
                s.corner = if rng.chance(1, 2) { c } else { -c };
            }
        }
        sections.push(s);
    }
    // grooves where a section has room: usable length between the features at both ends
    let mut start_z = -front.abs();
    for sec in &mut sections {
        let end_z = sec.z_end + sec.fillet;
        let room = start_z - end_z;
        if room >= 8_000 && sec.r >= 5_000 && rng.chance(1, 2) {
            let (a, b, c) = TRIPLES[rng.range(0, TRIPLES.len() as i64 - 1) as usize];
            let scale = rng.stepped(250, 1_000, 250);
            let depth = (c - a) * scale;
            let width = 2 * b * scale;
            if width + 3_000 <= room && depth <= 2_000 {
                sec.groove = Some((a * scale, b * scale));
            }
        }
        start_z = sec.z_end - sec.corner.abs();
    }
    Profile { front, sections }
}

struct Gen<W: Write> {
    o: Out<W>,
    rng: Lcg,
    seed: u64,
    target: usize,
    tool: u32,
    part: u32,
    rpm: u32,
}

impl<W: Write> Gen<W> {
    fn new(w: W, dialect: Dialect, target: usize, seed: u64) -> Gen<W> {
        Gen {
            o: Out {
                w,
                dialect,
                lines: 0,
                n_next: 10,
            },
            rng: Lcg::new(seed),
            seed,
            target,
            tool: 1,
            part: 0,
            rpm: 1200,
        }
    }

    fn say(&mut self, comment: &str) -> io::Result<()> {
        self.o.line(&format!("({comment})"))
    }

    fn rapid_xz(&mut self, r: Um, z: Um) -> io::Result<()> {
        let s = format!("G0 X{} Z{}", self.o.x(r), self.o.num(z));
        self.o.line(&s)
    }

    fn spindle_on(&mut self) -> io::Result<()> {
        let s = match self.o.dialect {
            Dialect::LinuxCnc => format!("S{} M3", self.rpm),
            Dialect::Fanuc => format!("G97 S{} M3", self.rpm),
        };
        self.o.line(&s)
    }

    fn tool_change(&mut self, t: u32) -> io::Result<()> {
        self.tool = t;
        let (x, z) = (self.o.x(STOCK_R), self.o.num(Z_CLEAR));
        self.o.numbered(&format!("G0 X{x} Z{z}"))?;
        match self.o.dialect {
            Dialect::LinuxCnc => self.o.line(&format!("T{t} M6"))?,
            Dialect::Fanuc => self.o.line(&format!("T{t:02}{t:02}"))?,
        }
        self.rpm = self.rng.range(10, 20) as u32 * 100;
        self.spindle_on()
    }

    fn lines_left(&self) -> usize {
        self.target.saturating_sub(self.o.lines)
    }

    fn header(&mut self) -> io::Result<()> {
        let seed_note = format!("SEED {}", self.seed);
        match self.o.dialect {
            Dialect::LinuxCnc => {
                self.say(&format!("LATHEGUARD BENCHMARK PROGRAM, LINUXCNC, {seed_note}"))?;
                self.say("50 MM BAR, X IS A RADIUS - G8, Z0 AT THE FACED FRONT")?;
                self.o.line("G18 G21 G90 G8 G40 G95")?;
            }
            Dialect::Fanuc => {
                self.o.line("%")?;
                self.o
                    .line(&format!("O1000 (LATHEGUARD BENCHMARK, FANUC, {seed_note})"))?;
                self.say("50 MM BAR, X IS A DIAMETER, Z0 AT THE FACED FRONT")?;
                self.o.line("G18 G21 G40 G97 G99")?;
            }
        }
        self.tool_change(1)?;
        self.o.line("M8")
    }

    fn footer(&mut self) -> io::Result<()> {
        self.say("END OF RUN")?;
        let (x, z) = (self.o.x(STOCK_R), self.o.num(Z_CLEAR));
        self.o.numbered(&format!("G0 X{x} Z{z}"))?;
        self.o.line("M9")?;
        self.o.line("M5")?;
        self.o.line("M30")?;
        if self.o.dialect == Dialect::Fanuc {
            self.o.line("%")?;
        }
        Ok(())
    }

    /// Facing from the bar radius to the axis at Z1, then Z0.
    fn face(&mut self) -> io::Result<()> {
        self.say("FACE")?;
        let f = self.rng.stepped(150, 250, 10);
        for z in [1_000, 0] {
            self.rapid_xz(STOCK_R, Z_CLEAR)?;
            let s = format!("G1 Z{} F{}", self.o.num(z), self.o.feed(f));
            self.o.line(&s)?;
            let s = format!("G1 X{}", self.o.x(-800));
            self.o.line(&s)?;
            let s = format!("G0 Z{}", self.o.num(Z_CLEAR));
            self.o.line(&s)?;
        }
        Ok(())
    }

    /// Roughing along Z at falling levels. Returns false if the line budget ran out.
    fn rough(&mut self, p: &Profile) -> io::Result<bool> {
        self.say("ROUGH OD")?;
        let doc = self.rng.stepped(1_000, 2_500, 100);
        let f = self.rng.stepped(200, 350, 10);
        let lowest = p.sections[0].r + ALLOW_X;
        let mut level = STOCK_R;
        let mut first = true;
        while level > lowest {
            if self.lines_left() < 40 {
                return Ok(false);
            }
            level = (level - doc).max(lowest);
            // the pass ends before the first section whose radius (plus allowance) reaches level
            let mut z_end = p.sections[0].z_end;
            for s in &p.sections {
                if s.r + ALLOW_X > level {
                    break;
                }
                z_end = s.z_end;
            }
            let z_stop = z_end + ALLOW_Z;
            let s = format!("G0 X{}", self.o.x(level));
            if first || self.rng.chance(1, 8) {
                self.o.numbered(&s)?;
            } else {
                self.o.line(&s)?;
            }
            let s = if first {
                first = false;
                format!("G1 Z{} F{}", self.o.num(z_stop), self.o.feed(f))
            } else {
                format!("G1 Z{}", self.o.num(z_stop))
            };
            self.o.line(&s)?;
            let s = format!("G1 X{} Z{}", self.o.x(level + 500), self.o.num(z_stop + 500));
            self.o.line(&s)?;
            let s = format!("G0 Z{}", self.o.num(Z_CLEAR));
            self.o.line(&s)?;
        }
        Ok(true)
    }

    fn finish(&mut self, p: &Profile) -> io::Result<()> {
        self.say("FINISH PROFILE")?;
        let f = self.rng.stepped(80, 150, 10);
        let r0 = p.sections[0].r;
        let e = p.front.abs();
        let s = format!("G0 X{}", self.o.x(r0 - e));
        self.o.numbered(&s)?;
        let s = format!("G1 Z{} F{}", self.o.num(0), self.o.feed(f));
        self.o.line(&s)?;
        if p.front > 0 {
            // convex front radius: from (Z0, r0-e) around centre (Z-e, r0-e) to (Z-e, r0)
            let s = format!(
                "G3 X{} Z{} I{} K{}",
                self.o.x(r0),
                self.o.num(-e),
                self.o.num(0),
                self.o.num(-e)
            );
            self.o.line(&s)?;
        } else if p.front < 0 {
            let s = format!("G1 X{} Z{}", self.o.x(r0), self.o.num(-e));
            self.o.line(&s)?;
        }
        for i in 0..p.sections.len() {
            let sec = &p.sections[i];
            if let Some((a, b)) = sec.groove {
                // concave circular groove centred in the section's free length
                let start = if i == 0 {
                    -e
                } else {
                    p.sections[i - 1].z_end - p.sections[i - 1].corner.abs()
                };
                let end = sec.z_end + sec.fillet;
                let zg = (start + end) / 2 + b;
                let zg = zg - zg.rem_euclid(10); // stay on a 0.01 mm grid
                let s = format!("G1 Z{}", self.o.num(zg));
                self.o.line(&s)?;
                let s = format!(
                    "G2 X{} Z{} I{} K{}",
                    self.o.x(sec.r),
                    self.o.num(zg - 2 * b),
                    self.o.num(a),
                    self.o.num(-b)
                );
                self.o.line(&s)?;
            }
            let Some(next) = p.sections.get(i + 1) else {
                let s = format!("G1 Z{}", self.o.num(sec.z_end));
                self.o.line(&s)?;
                break;
            };
            if sec.fillet > 0 {
                let fl = sec.fillet;
                let s = format!("G1 Z{}", self.o.num(sec.z_end + fl));
                self.o.line(&s)?;
                let s = format!(
                    "G2 X{} Z{} I{} K{}",
                    self.o.x(sec.r + fl),
                    self.o.num(sec.z_end),
                    self.o.num(fl),
                    self.o.num(0)
                );
                self.o.line(&s)?;
            } else {
                let s = format!("G1 Z{}", self.o.num(sec.z_end));
                self.o.line(&s)?;
            }
            let c = sec.corner;
            if c > 0 {
                let s = format!("G1 X{}", self.o.x(next.r - c));
                self.o.line(&s)?;
                let s = format!(
                    "G3 X{} Z{} I{} K{}",
                    self.o.x(next.r),
                    self.o.num(sec.z_end - c),
                    self.o.num(0),
                    self.o.num(-c)
                );
                self.o.line(&s)?;
            } else if c < 0 {
                let s = format!("G1 X{}", self.o.x(next.r + c));
                self.o.line(&s)?;
                let s = format!("G1 X{} Z{}", self.o.x(next.r), self.o.num(sec.z_end + c));
                self.o.line(&s)?;
            } else {
                let s = format!("G1 X{}", self.o.x(next.r));
                self.o.line(&s)?;
            }
        }
        // up the last face to the bar radius, then back out along the (roughed) OD
        let s = format!("G1 X{}", self.o.x(STOCK_R));
        self.o.line(&s)?;
        let s = format!("G0 Z{}", self.o.num(Z_CLEAR));
        self.o.line(&s)
    }

    fn run(&mut self) -> io::Result<()> {
        self.header()?;
        loop {
            // a part needs at most ~25 roughing passes * 4 + finishing ~40 + facing 10 lines
            if self.lines_left() < 40 {
                break;
            }
            self.part += 1;
            if self.part > 1 && self.rng.chance(1, 6) {
                let t = self.tool % 2 + 1;
                self.say("TOOL CHANGE")?;
                self.tool_change(t)?;
            }
            self.say(&format!("PART {}", self.part))?;
            let p = make_profile(&mut self.rng);
            self.face()?;
            if !self.rough(&p)? {
                break;
            }
            self.finish(&p)?;
        }
        self.footer()
    }
}

fn usage() -> ExitCode {
    eprintln!("usage: gen_program [--lines N] [--dialect linuxcnc|fanuc] [--seed S]");
    ExitCode::from(2)
}

fn main() -> ExitCode {
    let mut lines: usize = 100_000;
    let mut dialect = Dialect::LinuxCnc;
    let mut seed: u64 = 1;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = match a.as_str() {
            "-h" | "--help" => {
                usage();
                return ExitCode::SUCCESS;
            }
            "--lines" | "--dialect" | "--seed" => match args.next() {
                Some(v) => v,
                None => return usage(),
            },
            _ => return usage(),
        };
        match a.as_str() {
            "--lines" => match v.parse() {
                Ok(n) => lines = n,
                Err(_) => return usage(),
            },
            "--seed" => match v.parse() {
                Ok(s) => seed = s,
                Err(_) => return usage(),
            },
            _ => {
                dialect = match v.as_str() {
                    "linuxcnc" => Dialect::LinuxCnc,
                    "fanuc" => Dialect::Fanuc,
                    _ => return usage(),
                }
            }
        }
    }
    let stdout = io::stdout();
    let mut g = Gen::new(BufWriter::new(stdout.lock()), dialect, lines, seed);
    let r = g.run().and_then(|_| g.o.w.flush());
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if e.kind() == io::ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gen_program: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The generator as a function, for the benchmarks (which include this file with `#[path]`).
#[allow(dead_code)]
pub fn generate(lines: usize, fanuc: bool, seed: u64) -> Vec<u8> {
    let mut buf = Vec::new();
    {
        let dialect = if fanuc { Dialect::Fanuc } else { Dialect::LinuxCnc };
        let mut g = Gen::new(BufWriter::new(&mut buf), dialect, lines, seed);
        let _ = g.run().and_then(|_| g.o.w.flush());
    }
    buf
}
