//! Reading samples (docs/follow.md, "Samples"): one a line, JSON lines or CSV with a header,
//! every bad value a [`SampleError`] with its line and column. No I/O: the caller hands over
//! each line's text.

use std::fmt;

/// The axes a sample may name, in the order of [`Sample::axes`]: X and Z (the turret reference
/// point in machine coordinates, mm, X a radius), then the extra axes of
/// [`crate::interp::EXTRA_LETTERS`] (Y mm, C B A degrees; B is a linear slide on the shipped
/// turn-mill machine, in mm).
pub const AXES: [char; 6] = ['X', 'Z', 'Y', 'C', 'B', 'A'];

/// Longest line read, bytes: past it a line is an error and is not parsed.
pub const MAX_LINE: usize = 4096;

/// Most columns a CSV header may name.
pub const MAX_COLUMNS: usize = 32;

/// How the machine moves over the interval that ends at a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// At the rapid rate (G0): an insert entering material is a `rapid_into_stock`.
    Rapid,
    /// At a feed (G1, G2, G3, threading, probing): an insert in material cuts it.
    Feed,
}

/// The main spindle's direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpindleDir {
    Off,
    Cw,
    Ccw,
}

/// Most paths a sample may name: a key's path is one digit, as a `$` line's (docs/paths.md).
pub const MAX_PATHS: usize = 9;

/// One path's tool carrier in a sample: path 1's keys are `X`, `tool`, …; path `p`'s the same
/// with `p` after them (`X2`, `tool2`), docs/follow.md.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carrier {
    /// Values of the [`AXES`], in that order.
    pub axes: [Option<f64>; 6],
    /// The turret station facing the spindle.
    pub tool: Option<u32>,
    pub motion: Option<Motion>,
    /// The program line the control reports (LinuxCNC `motion.program-line`).
    pub line: Option<u32>,
    /// The live tool's speed, rev/min (0: stopped).
    pub live_rpm: Option<f64>,
}

/// One sample as read: every field but the time may be absent, and then keeps its value from
/// the sample before (docs/follow.md).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Sample {
    /// Seconds; `None` only when the reader was given a period ([`Reader::with_period`]).
    pub t: Option<f64>,
    /// Each path's carrier, path 1 first, as far as the highest path the sample names.
    pub carriers: Vec<Carrier>,
    pub spindle: Option<SpindleDir>,
    /// The main spindle is a positioned C axis.
    pub c_axis: Option<bool>,
    /// The tailstock is advanced.
    pub tailstock: Option<bool>,
    /// The sub-spindle's chuck is clamped.
    pub sub_chuck: Option<bool>,
}

impl Sample {
    /// Path `path`'s carrier (from 1), if the sample names any key of it.
    pub fn carrier(&self, path: usize) -> Option<&Carrier> {
        self.carriers.get(path.wrapping_sub(1))
    }

    /// Path `path`'s carrier, made when the sample had none of its keys yet.
    pub fn carrier_mut(&mut self, path: usize) -> &mut Carrier {
        let i = path.clamp(1, MAX_PATHS) - 1;
        if self.carriers.len() <= i {
            self.carriers.resize(i + 1, Carrier::default());
        }
        &mut self.carriers[i]
    }
}

/// A line that is no sample, with where.
#[derive(Clone, Debug, PartialEq)]
pub struct SampleError {
    /// 1-based line of the source.
    pub line: u64,
    /// 1-based column in characters, 0 for the whole line.
    pub col: u32,
    pub message: String,
}

impl fmt::Display for SampleError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.col > 0 {
            write!(f, "{}:{}: {}", self.line, self.col, self.message)
        } else {
            write!(f, "{}: {}", self.line, self.message)
        }
    }
}

/// The format of a source of samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// One JSON object a line.
    Json,
    /// A header naming the columns, then one sample a line, separated by commas (or, when the
    /// header has no comma, by spaces and tabs: `halsampler`'s output).
    Csv,
    /// JSON when the first line that is not blank or a comment starts with `{`, else CSV.
    Auto,
}

/// Which field a key or column names; a carrier's fields with their path (from 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Field {
    T,
    Axis(usize, usize),
    Tool(usize),
    Spindle,
    Motion(usize),
    Line(usize),
    CAxis,
    LiveRpm(usize),
    Tailstock,
    SubChuck,
    /// A column the sample does not read (CSV: `-` or a name starting with `_`).
    Skip,
}

const KEYS: &str = "t, X, Z, Y, C, B, A, tool, spindle, motion, line, c_axis, live_rpm, tailstock, sub_chuck (a carrier's keys with its path after them for path 2 on: X2, tool2)";

/// What a sample may name on one machine: per path (path 1 first), the [`AXES`] its carrier
/// has and its turret's stations.
#[derive(Clone, Debug, PartialEq)]
pub struct Layout {
    pub paths: Vec<([bool; 6], u32)>,
}

impl Default for Layout {
    /// Any axis, any station, every path.
    fn default() -> Layout {
        Layout {
            paths: vec![([true; 6], u32::MAX); MAX_PATHS],
        }
    }
}

impl Layout {
    fn stations(&self, path: usize) -> u32 {
        self.paths.get(path - 1).map_or(0, |p| p.1)
    }
}

/// A key a carrier's path may follow: `tool`, `motion`, `line`, `live_rpm` and the axes.
fn is_carrier_key(base: &str) -> bool {
    matches!(base, "tool" | "motion" | "line" | "live_rpm")
        || (base.len() == 1 && base.chars().all(|c| AXES.contains(&c)))
}

fn field(name: &str, layout: &Layout) -> Result<Field, String> {
    match name {
        "t" => return Ok(Field::T),
        "spindle" => return Ok(Field::Spindle),
        "c_axis" => return Ok(Field::CAxis),
        "tailstock" => return Ok(Field::Tailstock),
        "sub_chuck" => return Ok(Field::SubChuck),
        "-" => return Ok(Field::Skip),
        n if n.starts_with('_') => return Ok(Field::Skip),
        _ => {}
    }
    // A carrier's key, with its path's digit after it (none: path 1).
    let (base, path) = match name.as_bytes().last() {
        Some(d @ b'1'..=b'9') if is_carrier_key(&name[..name.len() - 1]) => {
            (&name[..name.len() - 1], usize::from(d - b'0'))
        }
        _ => (name, 1),
    };
    let carrier = |f: Field| -> Result<Field, String> {
        if path > layout.paths.len() {
            let n = layout.paths.len();
            return Err(format!(
                "`{name}` is path {path}'s, but the machine has {n} path{}",
                if n == 1 { "" } else { "s" }
            ));
        }
        Ok(f)
    };
    match base {
        "tool" => return carrier(Field::Tool(path)),
        "motion" => return carrier(Field::Motion(path)),
        "line" => return carrier(Field::Line(path)),
        "live_rpm" => return carrier(Field::LiveRpm(path)),
        _ => {}
    }
    let mut c = base.chars();
    match (c.next(), c.next()) {
        (Some(a), None) if a.is_ascii_alphabetic() => match AXES.iter().position(|&x| x == a) {
            Some(k) => {
                let f = carrier(Field::Axis(path, k))?;
                if layout.paths[path - 1].0[k] {
                    Ok(f)
                } else if path == 1 {
                    Err(format!("the machine has no {name} axis"))
                } else {
                    Err(format!("path {path}'s carrier has no {a} axis (`{name}`)"))
                }
            }
            None if AXES.contains(&a.to_ascii_uppercase()) => Err(format!(
                "unknown axis `{name}`: axes are upper case ({})",
                a.to_ascii_uppercase()
            )),
            None => Err(format!("unknown axis `{name}`: the axes are X, Z, Y, C, B and A")),
        },
        _ => Err(format!("unknown key `{}`: the keys are {KEYS}", shorten(name))),
    }
}

fn shorten(s: &str) -> String {
    if s.chars().count() > 40 {
        let mut t: String = s.chars().take(40).collect();
        t.push('…');
        t
    } else {
        s.to_string()
    }
}

/// A value as text (CSV) or JSON, read into its field.
enum Value<'a> {
    Text(&'a str),
    Json(&'a serde_json::Value),
}

impl Value<'_> {
    fn show(&self) -> String {
        match self {
            Value::Text(s) => shorten(s),
            Value::Json(v) => shorten(&v.to_string()),
        }
    }

    fn number(&self) -> Option<f64> {
        match self {
            Value::Text(s) => s.trim().parse::<f64>().ok(),
            Value::Json(v) => v.as_f64(),
        }
        .filter(|v| v.is_finite())
    }

    fn word(&self) -> Option<&str> {
        match self {
            Value::Text(s) => Some(s.trim()),
            Value::Json(v) => v.as_str(),
        }
    }

    fn boolean(&self) -> Option<bool> {
        if let Value::Json(serde_json::Value::Bool(b)) = self {
            return Some(*b);
        }
        match self.word() {
            Some("true" | "1" | "on" | "in" | "closed") => Some(true),
            Some("false" | "0" | "off" | "out" | "open") => Some(false),
            _ => self.number().filter(|v| *v == 0.0 || *v == 1.0).map(|v| v == 1.0),
        }
    }
}

/// Largest axis value accepted, mm or degrees ([`crate::interp::MAX_COORD`]).
const MAX_VALUE: f64 = crate::interp::MAX_COORD;

fn set(s: &mut Sample, f: Field, v: &Value<'_>, layout: &Layout) -> Result<(), String> {
    let bad = |what: &str| format!("`{}` is not {what}", v.show());
    match f {
        Field::T => {
            let t = v.number().ok_or_else(|| bad("a time in seconds"))?;
            if !(0.0..=1e12).contains(&t) {
                return Err(format!("time {t} s is out of range (0 to 1e12 s)"));
            }
            s.t = Some(t);
        }
        Field::Axis(p, k) => {
            let x = v.number().ok_or_else(|| bad("a number"))?;
            if x.abs() > MAX_VALUE {
                return Err(format!("{} {x} is out of range (±1e12)", AXES[k]));
            }
            s.carrier_mut(p).axes[k] = Some(x);
        }
        Field::Tool(p) => {
            let x = v.number().ok_or_else(|| bad("a station number"))?;
            let stations = layout.stations(p);
            if x.fract() != 0.0 || !(1.0..=f64::from(stations)).contains(&x) {
                return Err(format!("tool `{}`: the turret has stations 1 to {stations}", v.show()));
            }
            s.carrier_mut(p).tool = Some(x as u32);
        }
        Field::Spindle => {
            s.spindle = Some(match v.word() {
                Some("cw" | "CW" | "M3" | "m3") => SpindleDir::Cw,
                Some("ccw" | "CCW" | "M4" | "m4") => SpindleDir::Ccw,
                Some("off" | "OFF" | "M5" | "m5") => SpindleDir::Off,
                _ => match v.number() {
                    Some(x) if x > 0.0 => SpindleDir::Cw,
                    Some(x) if x < 0.0 => SpindleDir::Ccw,
                    Some(_) => SpindleDir::Off,
                    None => return Err(bad("a spindle state (cw, ccw, off, or a signed speed)")),
                },
            })
        }
        Field::Motion(p) => {
            let last = s.carrier(p).and_then(|c| c.motion);
            s.carrier_mut(p).motion = match v.word() {
                Some("rapid" | "G0" | "g0") => Some(Motion::Rapid),
                Some("feed" | "G1" | "g1") => Some(Motion::Feed),
                // LinuxCNC's motion.motion-type: 1 traverse; 2 feed, 3 arc, 5 probing; 0 (no
                // motion), 4 (tool change) and 6 (rotary index) say nothing new.
                _ => match v.number().filter(|x| x.fract() == 0.0).map(|x| x as i64) {
                    Some(1) => Some(Motion::Rapid),
                    Some(2 | 3 | 5) => Some(Motion::Feed),
                    Some(0 | 4 | 6) => last,
                    _ => return Err(bad("a motion (rapid, feed, or LinuxCNC's motion-type 0 to 6)")),
                },
            }
        }
        Field::Line(p) => {
            let x = v.number().ok_or_else(|| bad("a line number"))?;
            if x.fract() != 0.0 || !(0.0..=4e9).contains(&x) {
                return Err(bad("a line number"));
            }
            // LinuxCNC reports 0 (or -1) before the program runs: no line.
            s.carrier_mut(p).line = (x >= 1.0).then_some(x as u32);
        }
        Field::CAxis => s.c_axis = Some(v.boolean().ok_or_else(|| bad("true or false"))?),
        Field::LiveRpm(p) => {
            let x = v.number().ok_or_else(|| bad("a speed in rev/min"))?;
            s.carrier_mut(p).live_rpm = Some(x.abs().min(1e9));
        }
        Field::Tailstock => s.tailstock = Some(v.boolean().ok_or_else(|| bad("in or out (true or false)"))?),
        Field::SubChuck => s.sub_chuck = Some(v.boolean().ok_or_else(|| bad("closed or open (true or false)"))?),
        Field::Skip => {}
    }
    Ok(())
}

/// Reads a source's lines as samples, in order.
#[derive(Clone, Debug)]
pub struct Reader {
    format: Format,
    /// CSV: the header's fields, and whether columns are separated by commas.
    columns: Option<(Vec<Field>, bool)>,
    period: Option<f64>,
    /// What the machine's samples may name.
    layout: Layout,
}

impl Reader {
    pub fn new(format: Format) -> Reader {
        Reader {
            format,
            columns: None,
            period: None,
            layout: Layout::default(),
        }
    }

    /// Samples of a machine with the paths, axes and stations of `layout`: another path, axis
    /// or station is an error at its column.
    pub fn for_machine(mut self, layout: Layout) -> Reader {
        self.layout = layout;
        self
    }

    /// Samples without a time are `period` seconds after the sample before (the first at 0):
    /// for feeds that sample at a fixed rate and give no clock (`halsampler`).
    pub fn with_period(mut self, period: f64) -> Reader {
        self.period = Some(period);
        self
    }

    /// The format, once the first line decided it ([`Format::Auto`] before).
    pub fn format(&self) -> Format {
        self.format
    }

    /// Read line `line` (1-based) of the source: a sample, `None` for a blank line, a comment
    /// (`#`) or the CSV header, or an error that names the line and column.
    pub fn read(&mut self, line: u64, text: &str) -> Result<Option<Sample>, SampleError> {
        let err = |col: usize, message: String| SampleError {
            line,
            col: col as u32,
            message,
        };
        if text.len() > MAX_LINE {
            return Err(err(0, format!("the line is longer than {MAX_LINE} bytes")));
        }
        let text = text.strip_suffix('\r').unwrap_or(text);
        let trimmed = text.trim_start();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            return Ok(None);
        }
        if self.format == Format::Auto {
            self.format = if trimmed.starts_with('{') {
                Format::Json
            } else {
                Format::Csv
            };
        }
        let sample = match self.format {
            Format::Json => json_sample(text, &self.layout).map_err(|(c, m)| err(c, m))?,
            _ => match &self.columns {
                None => {
                    self.columns = Some(header(text, &self.layout).map_err(|(c, m)| err(c, m))?);
                    return Ok(None);
                }
                Some((cols, comma)) => csv_sample(text, cols, *comma, &self.layout).map_err(|(c, m)| err(c, m))?,
            },
        };
        if sample.t.is_none() && self.period.is_none() {
            return Err(err(0, "the sample has no time `t` (or give --period)".into()));
        }
        Ok(Some(sample))
    }

    /// The period of [`Reader::with_period`].
    pub fn period(&self) -> Option<f64> {
        self.period
    }
}

/// The 1-based column (in characters) of byte `at` of `text`.
fn column(text: &str, at: usize) -> usize {
    text.get(..at).map_or(0, |s| s.chars().count()) + 1
}

fn json_sample(text: &str, layout: &Layout) -> Result<Sample, (usize, String)> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| {
        let msg = e.to_string();
        // serde_json's message ends with " at line L column C": the column is ours.
        let msg = msg.split(" at line ").next().unwrap_or(&msg).to_string();
        (e.column(), format!("not a JSON sample: {msg}"))
    })?;
    let serde_json::Value::Object(map) = value else {
        return Err((1, "a JSON sample is an object: {\"t\": …, \"X\": …}".into()));
    };
    let mut s = Sample::default();
    for (k, v) in &map {
        // The key's place on the line, for the column (its first appearance as a JSON string).
        let at = text.find(&format!("\"{k}\"")).map_or(0, |b| column(text, b));
        let f = field(k, layout).map_err(|m| (at, m))?;
        if v.is_null() {
            continue;
        }
        set(&mut s, f, &Value::Json(v), layout).map_err(|m| (at, format!("{k}: {m}")))?;
    }
    Ok(s)
}

fn split(text: &str, comma: bool) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    if comma {
        let mut start = 0;
        for (i, c) in text.char_indices() {
            if c == ',' {
                out.push((start, &text[start..i]));
                start = i + 1;
            }
        }
        out.push((start, &text[start..]));
    } else {
        let mut start = None;
        for (i, c) in text.char_indices() {
            match (c == ' ' || c == '\t', start) {
                (true, Some(s)) => {
                    out.push((s, &text[s..i]));
                    start = None;
                }
                (false, None) => start = Some(i),
                _ => {}
            }
        }
        if let Some(s) = start {
            out.push((s, &text[s..]));
        }
    }
    out
}

fn header(text: &str, layout: &Layout) -> Result<(Vec<Field>, bool), (usize, String)> {
    let comma = text.contains(',');
    let mut fields = Vec::new();
    for (at, name) in split(text, comma) {
        let lead = name.len() - name.trim_start().len();
        let f = field(name.trim(), layout).map_err(|m| (column(text, at + lead), format!("in the CSV header: {m}")))?;
        if f != Field::Skip && fields.contains(&f) {
            return Err((column(text, at + lead), format!("`{}` is named twice", name.trim())));
        }
        fields.push(f);
    }
    if fields.len() > MAX_COLUMNS {
        return Err((0, format!("the CSV header names more than {MAX_COLUMNS} columns")));
    }
    Ok((fields, comma))
}

fn csv_sample(text: &str, cols: &[Field], comma: bool, layout: &Layout) -> Result<Sample, (usize, String)> {
    let cells = split(text, comma);
    if cells.len() != cols.len() {
        return Err((
            0,
            format!("{} values where the header names {} columns", cells.len(), cols.len()),
        ));
    }
    let mut s = Sample::default();
    for ((at, cell), &f) in cells.iter().zip(cols) {
        if cell.trim().is_empty() {
            continue;
        }
        let lead = cell.len() - cell.trim_start().len();
        set(&mut s, f, &Value::Text(cell), layout).map_err(|m| (column(text, at + lead), m))?;
    }
    Ok(s)
}
