//! The machine description: TOML (docs/machine.md) → a validated [`Machine`].
//!
//! All lengths are mm in the spindle frame: `x` is a radius (distance from the spindle axis, `+x`
//! toward the turret), `z` runs along the spindle axis with `z = 0` at the jaw faces.
//! Outlines are normalised [`Polygon`]s.

mod barrier;
mod gcodes;
mod load;
mod mcodes;
pub mod paths;
#[cfg(test)]
mod tests;
pub(crate) mod tool_entry;
pub use tool_entry::GeometryOffset;

use std::fmt::Write as _;

use crate::geom::{Polygon, P2};
pub mod auto;
pub mod jaws;
pub mod new;

pub use gcodes::{code_name as g_code_name, parse_code as parse_g_code, DrillingCycles, GAlias, GcodeTable};
pub use mcodes::{reserved as mcodes_reserved, MAction, McodeTable, ACTIONS as MCODE_ACTIONS, MAX_MCODE};

pub(crate) use load::{
    deserialize, deserialize_at, home_clashes, stock_clash, work_offset_doubt, work_offsets, Cx, Embedded, Num,
    Outline, Point, RawGrip, RawJawType, RawUnits, RawWorkOffsets, StockKey,
};
pub use load::{
    did_you_mean, from_toml, from_toml_with, schema, with_suggestion, MachineError, INDEX_TIME_RANGE, MAX_COORD_MM,
    MAX_OUTLINE_POINTS, MAX_RPM_RANGE, MAX_STATIONS, MAX_TEXT_BYTES, MAX_TOOLS, MAX_TOTAL_OUTLINE_POINTS,
    NOSE_RADIUS_RANGE, RAPID_RANGE, TOP_LEVEL,
};

/// The built-in machine's TOML, embedded in the binary.
pub const BUILTIN_TOML: &str = include_str!("../../machines/generic-slant-bed.toml");
pub const BUILTIN_NAME: &str = "machines/generic-slant-bed.toml";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Fanuc,
    Linuxcnc,
}

impl Dialect {
    /// The name used in machine files: `fanuc`, `linuxcnc`.
    pub fn as_str(self) -> &'static str {
        match self {
            Dialect::Fanuc => "fanuc",
            Dialect::Linuxcnc => "linuxcnc",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RapidMode {
    /// Each axis at its own rapid rate: the path bends.
    Dogleg,
    /// Both axes interpolated along the straight line.
    Linear,
}

impl RapidMode {
    /// The name used in machine files: `dogleg`, `linear`.
    pub fn as_str(self) -> &'static str {
        match self {
            RapidMode::Dogleg => "dogleg",
            RapidMode::Linear => "linear",
        }
    }
}

/// Fanuc: how a number without a decimal point is read for length words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecimalPoint {
    /// `X60` = 60 mm.
    Calculator,
    /// `X60` = 60 least increments (0.001 mm, 0.0001 in).
    Increment,
}

impl DecimalPoint {
    /// The name used in machine files: `calculator`, `increment`.
    pub fn as_str(self) -> &'static str {
        match self {
            DecimalPoint::Calculator => "calculator",
            DecimalPoint::Increment => "increment",
        }
    }
}

/// How the R word of the spindle-axis drilling cycles G81–G89 is read (`machine.drill_r`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrillR {
    /// Haas: R is the program Z of the R plane.
    Absolute,
    /// Fanuc (0i-TD and the lathe controls before it): R is the signed distance from the
    /// initial level (the Z where the cycle starts) to the R point.
    Incremental,
}

impl DrillR {
    /// The name used in machine files: `absolute`, `incremental`.
    pub fn as_str(self) -> &'static str {
        match self {
            DrillR::Absolute => "absolute",
            DrillR::Incremental => "incremental",
        }
    }
}

/// How a G71/G72 one-block `D` (the depth of cut) written without a decimal point is read
/// (`machine.g71_d`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum G71D {
    /// As written, in the program's unit (Haas: `D1.5` and `D1` are 1.5 mm and 1 mm).
    #[default]
    Length,
    /// Fanuc 0-TC, 10T, 15T: in the least input increment (`D1500` = 1.5 mm, 0.0001 in in
    /// inch); with a decimal point as written.
    Increment,
}

impl G71D {
    /// The name used in machine files: `length`, `increment`.
    pub fn as_str(self) -> &'static str {
        match self {
            G71D::Length => "length",
            G71D::Increment => "increment",
        }
    }
}

/// Fanuc lathe G-code system (Fanuc 0i-TD, B-64304EN): which codes name the box cycles and the
/// coordinate setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GcodeSystem {
    /// The lathe default: G90/G92/G94 box cycles, G50 coordinate setting and spindle clamp,
    /// G98/G99 feed per minute/revolution, U/W incremental.
    A,
    /// G77/G78/G79 box cycles, G92 coordinate setting and spindle clamp, G90/G91
    /// absolute/incremental, G94/G95 feed per minute/revolution.
    B,
}

impl GcodeSystem {
    /// The name used in machine files: `A`, `B`.
    pub fn as_str(self) -> &'static str {
        match self {
            GcodeSystem::A => "A",
            GcodeSystem::B => "B",
        }
    }
}

/// Where the turret stands relative to the spindle, seen by the operator: it decides how the
/// Fanuc/Haas tip-code chart (drawn with +X away from the operator) maps onto the spindle frame
/// (see docs/comp.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurretSide {
    /// Behind the spindle: +X points away from the operator, the manuals' charts as drawn.
    Rear,
    /// In front of the spindle: +X points toward the operator; the chart as the operator reads it
    /// is mirrored about the spindle axis.
    Front,
}

impl TurretSide {
    pub fn as_str(self) -> &'static str {
        match self {
            TurretSide::Rear => "rear",
            TurretSide::Front => "front",
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    /// mm/min
    pub rapid: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    pub diameter: f64,
    pub length: f64,
    /// z of the front face.
    pub front: f64,
    /// Inner diameter of a tube; 0 for a bar.
    pub bore: f64,
    /// A revolved outline (a casting, a forging, a part for its second operation) in the half
    /// plane x ≥ 0: the material is this outline, and `diameter`, `length`, `front` (with `bore`
    /// 0) are its bounding bar. None: a bar or tube.
    pub outline: Option<Polygon>,
    /// A prismatic block (a square bar in the jaws, milled on its faces: a job's `[stock]
    /// block`): `outline` is then its revolved envelope (docs/job.md, "A block").
    pub block: Option<Block>,
}

/// A block's section across the spindle axis, centred on it: `width` along x and `height`
/// along y with the spindle at C0 (the part's frame); its length and front are the stock's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Block {
    pub width: f64,
    pub height: f64,
}

impl Block {
    /// The radius of its corners: what it sweeps turning.
    pub fn circumscribed(&self) -> f64 {
        self.width.hypot(self.height) / 2.0
    }

    /// The radius of its nearer flats: where jaws closing on it grip.
    pub fn inscribed(&self) -> f64 {
        self.width.min(self.height) / 2.0
    }
}

/// The largest z of `chuck`'s material nearer the axis than `r` (its edges clipped at `r`):
/// where a part reaching out to `r` meets the chuck's front. None: nothing of it lies within `r`.
pub fn chuck_front_within(chuck: &Polygon, r: f64) -> Option<f64> {
    let pts = chuck.points();
    let n = pts.len();
    let mut best: Option<f64> = None;
    let mut take = |z: f64| best = Some(best.map_or(z, |b: f64| b.max(z)));
    for i in 0..n {
        let (p, q) = (pts[i], pts[(i + 1) % n]);
        if p.x < r {
            take(p.y);
        }
        if (p.x < r) != (q.x < r) && (q.x - p.x).abs() > 0.0 {
            take(p.y + (q.y - p.y) * (r - p.x) / (q.x - p.x));
        }
    }
    best
}

impl Stock {
    /// A bar (`bore` 0) or a tube.
    pub fn bar(diameter: f64, length: f64, front: f64, bore: f64) -> Stock {
        Stock {
            diameter,
            length,
            front,
            bore,
            outline: None,
            block: None,
        }
    }

    /// A block of `length` with its front face at `front`, held in `chuck`: its 2D model (the
    /// dexel stock's) is its revolved envelope — the corners' radius in front of where the chuck
    /// reaches within that radius (what the block sweeps turning), the nearer flats' radius
    /// behind it (where the jaws grip it) — and the block itself is kept for the milled stock.
    pub fn block(block: Block, length: f64, front: f64, chuck: Option<&Polygon>) -> Stock {
        let (rc, ri) = (block.circumscribed(), block.inscribed());
        let back = front - length;
        let grip = chuck
            .and_then(|c| chuck_front_within(c, rc))
            .map_or(back, |z| z.clamp(back, front));
        let p = |x: f64, z: f64| crate::geom::P2::new(x, z);
        let pts = if grip <= back {
            vec![p(0.0, back), p(rc, back), p(rc, front), p(0.0, front)]
        } else if grip >= front {
            vec![p(0.0, back), p(ri, back), p(ri, front), p(0.0, front)]
        } else {
            vec![
                p(0.0, back),
                p(ri, back),
                p(ri, grip),
                p(rc, grip),
                p(rc, front),
                p(0.0, front),
            ]
        };
        let outline = Polygon::new(&pts).ok();
        Stock {
            diameter: 2.0 * rc,
            length,
            front,
            bore: 0.0,
            outline,
            block: Some(block),
        }
    }

    /// A revolved outline (x ≥ 0), with its bounding bar.
    pub fn from_outline(outline: Polygon) -> Stock {
        let b = outline.aabb();
        Stock {
            diameter: 2.0 * b.max.x,
            length: b.max.y - b.min.y,
            front: b.max.y,
            bore: 0.0,
            outline: Some(outline),
            block: None,
        }
    }

    /// The stock's section in the half plane x ≥ 0 as `[x, z]` points (the outline, or the
    /// bar's rectangle): what a picture or `--stock-out` shows before any cut.
    pub fn section(&self) -> Vec<[f64; 2]> {
        match &self.outline {
            Some(o) => o.points().iter().map(|p| [p.x, p.y]).collect(),
            None => {
                let (z0, z1, r0, r1) = (
                    self.front - self.length,
                    self.front,
                    self.bore / 2.0,
                    self.diameter / 2.0,
                );
                vec![[r0, z0], [r1, z0], [r1, z1], [r0, z1]]
            }
        }
    }
}

/// How the tools are carried (`turret.type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TurretKind {
    /// A drum turret: the stations stand round an axis parallel to z, and a tool change turns the
    /// drum the short way round, swinging every tool through its arc (the index sweep).
    Drum,
    /// A gang-tool slide: every tool is clamped side by side on the cross slide, always in the
    /// working plane at its `tip` offset; a tool change (a T word) only changes which tool the
    /// program drives, nothing turns.
    Gang,
}

impl TurretKind {
    pub fn as_str(self) -> &'static str {
        match self {
            TurretKind::Drum => "drum",
            TurretKind::Gang => "gang",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Turret {
    /// Drum or gang slide.
    pub kind: TurretKind,
    pub stations: u32,
    pub start_station: u32,
    /// The turret's axis lies this far from the reference point in +x, parallel to z.
    pub axis: f64,
    /// Seconds per station indexed (a drum); seconds per tool change (a gang slide).
    pub index_time: f64,
    /// Relative to the turret reference point.
    pub outline: Polygon,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    pub station: u32,
    pub name: String,
    /// Programmed point relative to the turret reference point.
    pub tip: P2,
    /// Relative to the programmed point.
    pub insert: Polygon,
    /// Relative to the programmed point.
    pub holder: Polygon,
    pub nose_radius: f64,
    /// Imaginary-tip direction for nose-radius compensation, 0–9 (LinuxCNC orientation,
    /// Fanuc/Haas tip code T), as the machine file gives it; 0 when absent.
    pub tip_direction: u8,
    /// A milling tool built from its sizes (a job's `mill = { … }`): the milled stock's cutter
    /// and, on a machine with a kinematic tree, the station's 3D parts (`kin::station`).
    pub mill: Option<crate::tooling::milling::MillTool>,
    /// What the cutting part is, for the report's words ("the T04 drill").
    pub cutter: crate::tooling::Cutter,
}

/// How the chuck was given: the machine file's `[chuck]`, or a job's.
#[derive(Clone, Debug, PartialEq)]
pub enum ChuckForm {
    /// `outline`: drawn by hand (the machine file's, or a job's `chuck.outline`).
    Outline,
    /// `barrier`: Fanuc's chuck barrier parameters.
    Barrier,
    /// `body` and `[chuck.jaws]`: [`Machine::chuck`] is drawn from them, and a job's
    /// `[chuck.jaws]` (or its bar) sets the jaws over them.
    Jaws(jaws::Chuck),
}

/// The names of the work offsets a job or a machine file can give, in order: index 0 is G54.
pub const WORK_OFFSET_NAMES: [&str; 6] = ["G54", "G55", "G56", "G57", "G58", "G59"];

/// One work offset as the control's work offset page stores it (Fanuc 0i-TD and Haas lathes,
/// G54–G59; docs/machine.md, "Work offsets"), in mm: `z` is program zero's machine Z coordinate
/// (measured from machine zero, `axes.machine_zero`, as G53 is), `x` program X0's distance from
/// the spindle axis as a radius (0 on an ordinary setup: the X geometry offsets carry the
/// distance from machine zero to the axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkOffset {
    pub x: f64,
    pub z: f64,
}

/// Where an operation after the first begins (`[[operations]]`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OpStart {
    /// Before the words of the block at this file line (1-based), the first time it runs.
    Line(u32),
    /// At the `n`-th program stop the program makes (M0 or M1 as it runs, counted from 1), after
    /// the stop's block has run.
    Stop(u32),
    /// Before the words of the first block that selects this work offset (0: G54 … 5: G59).
    WorkOffset(u8),
}

/// The tailstock as an operation begins (`[[operations]] tailstock`).
#[derive(Clone, Debug, PartialEq)]
pub enum OpTailstock {
    /// As it stood: where it was, advanced or not.
    AsItStood,
    /// Not in use: no obstacle from the operation on (`in_use = false`).
    Out,
    /// This outline (the live centre's tip at the operation's `z`); advanced as the operation
    /// begins when `advance` (`in_use = true`), else as it stood.
    At { outline: Polygon, advance: bool },
}

/// One operation of a job after the first: where it starts, and how the part stands then.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    pub start: OpStart,
    /// The part turned end for end (z mirrored).
    pub reverse: bool,
    /// Where it then stands.
    pub stand: crate::scene::Stand,
    /// The jaws of this operation: its own `chuck.outline`, else the job's chuck.
    pub chuck: Option<Polygon>,
    /// G54's program zero from this operation on (the operator touched off the new face);
    /// `None`: as it was.
    pub program_zero_z: Option<f64>,
    /// The tailstock in this operation.
    pub tailstock: OpTailstock,
    /// Where the job gave it, for messages: `part.job.toml:12:1: operations[0]`.
    pub origin: String,
}

/// What depends on the dialect in a machine file with `dialect = "auto"`.
#[derive(Clone, Debug, PartialEq)]
pub struct DialectParts {
    pub diameter_mode: bool,
    pub decimal_point: DecimalPoint,
    pub gcode_system: GcodeSystem,
    pub mcodes: McodeTable,
}

/// Both dialects' settings of a machine with `dialect = "auto"`.
#[derive(Clone, Debug, PartialEq)]
pub struct AutoDialect {
    pub fanuc: DialectParts,
    pub linuxcnc: DialectParts,
}

/// A validated machine and its setup.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    pub name: String,
    pub dialect: Dialect,
    pub diameter_mode: bool,
    pub rapid: RapidMode,
    pub decimal_point: DecimalPoint,
    /// Fanuc G-code system (A unless the machine file says `gcode_system = "B"`).
    pub gcode_system: GcodeSystem,
    /// Which drilling cycles G83–G89 are (`machine.drilling_cycles`, default Haas's).
    pub drilling_cycles: DrillingCycles,
    /// How G81–G89's R is read on the spindle axis (`machine.drill_r`); `None`: the default of
    /// the drilling cycles, [`Machine::drill_r`].
    pub drill_r: Option<DrillR>,
    /// How a G71/G72 one-block `D` without a decimal point is read (`machine.g71_d`).
    pub g71_d: G71D,
    /// Builder G codes (`[gcodes]`): codes the control runs as standard ones, or ignores.
    pub gcodes: GcodeTable,
    /// Which side of the spindle the turret stands on (`machine.turret_side`, default rear).
    pub turret_side: TurretSide,
    /// The program starts in inch (G20) rather than mm (`machine.units = "inch"`).
    pub inch: bool,
    /// Contacts shallower than this are grazes, warnings (`machine.min_depth`; `None`: the
    /// default, [`crate::pipeline::DEFAULT_MIN_DEPTH_MM`]). Settings may override it.
    pub min_depth: Option<f64>,
    pub x: Axis,
    pub z: Axis,
    /// Turret reference point at program start and after a return home.
    pub home: P2,
    /// Turret reference point at machine zero (`axes.machine_zero`; default: `home`): G53
    /// positions are measured from it.
    pub machine_zero: P2,
    /// The 2nd, 3rd and 4th reference points (`axes.reference_points`, turret reference point,
    /// mm), where Fanuc G30 P2/P3/P4 returns; a point not given is home.
    pub reference_points: Vec<P2>,
    pub max_rpm: f64,
    /// The spindle turns forward at this speed from program start, as if M3 S… came before the
    /// first line (`spindle.start_rpm`: a manual lathe switched on by hand). None: stopped.
    pub start_rpm: Option<f64>,
    /// Revolved outline in the half plane x ≥ 0.
    pub chuck: Option<Polygon>,
    /// How `chuck` was given (None: no chuck); with body and jaws, their sizes.
    pub chuck_form: Option<ChuckForm>,
    pub tailstock: Option<Polygon>,
    /// The tailstock is advanced (an obstacle) at program start (`tailstock.advanced`, default
    /// true); its M codes (`[mcodes]` `tailstock_advance`/`tailstock_retract`) change it.
    pub tailstock_advanced: bool,
    /// What each M code does on this machine (`[mcodes]`, over the dialect's built-in table).
    pub mcodes: McodeTable,
    pub stock: Option<Stock>,
    /// Program Z0 of G54 (the program's zero at start) in the spindle frame.
    pub program_zero_z: f64,
    /// Work offsets G54–G59 as written (`setup.work_offsets`, a job's `[work_offsets]`); `None`:
    /// not given. When G54 is given, `program_zero_z` is its program zero
    /// (`machine_zero.z + z`); when not, G54 is `program_zero_z` on the spindle axis.
    pub work_offsets: [Option<WorkOffset>; 6],
    pub turret: Turret,
    /// Sorted by station.
    pub tools: Vec<Tool>,
    /// Manual tool changes of a job (`[[tool_changes]]`): `(line, station)`, sorted by line, at
    /// most one per line. Each time the block at that line runs, the operator has put the tool
    /// of that station in, as a T word would have switched to it, before the block's words.
    pub tool_changes: Vec<(u32, u32)>,
    /// A job's tool-number map (`[tool_numbers]`, docs/job.md "Tool numbers"): `(tool, station)`
    /// sorted by tool, one per tool. When it is not empty, a LinuxCNC-dialect T word (and
    /// `M61 Q`) names a tool of this map, which sits in that station; Fanuc T words ignore it.
    pub tool_numbers: Vec<(u32, u32)>,
    /// The operations of a job after the first (`[[operations]]`, docs/job.md "Operations"), in
    /// the order they start: at each, the operator turns the part round (or re-clamps it) and
    /// the program goes on with that part, standing where the operation says, in its jaws.
    pub operations: Vec<Operation>,
    /// `machine.dialect = "auto"`: the settings of each dialect, one of which
    /// [`Machine::with_dialect`] applies per program (the fields above hold Fanuc's).
    pub auto_dialect: Option<Box<AutoDialect>>,
    /// Values that were accepted but look like unit mistakes (`rapid = 1.0`), each as
    /// `file:line:col: key: message`, for `latheguard machine` to print. Empty for the shipped
    /// machines.
    pub warnings: Vec<String>,
    /// The kinematic tree of a turn-mill machine (`[kinematics]`; `crate::kin`), or
    /// `None` for a 2-axis lathe, which the 2D checker alone describes.
    pub kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
    /// `[setup] assume = true`: the stock, program zero and tools are an example setup that a
    /// program's own evidence replaces when the program has no job (`crate::assume`).
    pub assume_setup: bool,
    /// The carriers of paths 2, 3, … and the waiting M codes of a multi-path control
    /// (`[[paths]]`, `[sync]`; docs/paths.md). Empty on a one-path lathe.
    pub paths: paths::Paths,
}

impl Machine {
    /// The machine embedded in the binary.
    pub fn builtin() -> Machine {
        from_toml(BUILTIN_TOML, BUILTIN_NAME).expect("the built-in machine is valid")
    }

    /// This machine reading programs in dialect `d`: for a machine with `dialect = "auto"`, a
    /// copy with that dialect's settings (and no longer auto); otherwise None (use it as it is).
    pub fn with_dialect(&self, d: Dialect) -> Option<Machine> {
        let auto = self.auto_dialect.as_ref()?;
        let p = match d {
            Dialect::Fanuc => &auto.fanuc,
            Dialect::Linuxcnc => &auto.linuxcnc,
        };
        Some(Machine {
            dialect: d,
            diameter_mode: p.diameter_mode,
            decimal_point: p.decimal_point,
            gcode_system: p.gcode_system,
            mcodes: p.mcodes.clone(),
            auto_dialect: None,
            ..self.clone()
        })
    }

    /// How the spindle-axis drilling cycles read R: `machine.drill_r`, else incremental with
    /// Fanuc's drilling cycles (`drilling_cycles = "fanuc"`) and absolute with Haas's.
    pub fn drill_r(&self) -> DrillR {
        self.drill_r.unwrap_or(match self.drilling_cycles {
            DrillingCycles::Fanuc => DrillR::Incremental,
            DrillingCycles::Haas => DrillR::Absolute,
        })
    }

    /// Program zero of work offset `n` (0 = G54 … 5 = G59) in the spindle frame: the offset's
    /// Z from machine zero, its X from the spindle axis; G54 without a written offset is
    /// `program_zero_z` on the axis. `None`: offset `n` is not given.
    pub fn work_zero(&self, n: usize) -> Option<P2> {
        match (n, self.work_offsets.get(n).copied().flatten()) {
            (0, o) => Some(P2::new(o.map_or(0.0, |o| o.x), self.program_zero_z)),
            (_, Some(o)) => Some(P2::new(o.x, self.machine_zero.y + o.z)),
            (_, None) => None,
        }
    }

    /// Work offset `n` as the control's page would show it: the written one, else (G54 only)
    /// the one `program_zero_z` amounts to.
    pub fn work_offset(&self, n: usize) -> Option<WorkOffset> {
        let p = self.work_zero(n)?;
        Some(WorkOffset {
            x: p.x,
            z: p.y - self.machine_zero.y,
        })
    }

    /// Work offset `n` in words: `z -522 from machine zero: program zero at z 78` (and the x
    /// when it is not 0).
    pub fn work_offset_text(&self, n: usize) -> Option<String> {
        let (o, p) = (self.work_offset(n)?, self.work_zero(n)?);
        let mut t = format!("z {} from machine zero", num(o.z));
        if o.x != 0.0 {
            let _ = write!(t, ", x {} from the spindle axis", num(o.x));
        }
        let _ = write!(t, ": program zero at ");
        if p.x != 0.0 {
            let _ = write!(t, "x {}, ", num(p.x));
        }
        let _ = write!(t, "z {}", num(p.y));
        Some(t)
    }

    /// The chuck's body and jaws, when the chuck is given by them.
    pub fn chuck_jaws(&self) -> Option<&jaws::Chuck> {
        match &self.chuck_form {
            Some(ChuckForm::Jaws(c)) => Some(c),
            _ => None,
        }
    }

    pub fn tool(&self, station: u32) -> Option<&Tool> {
        self.tools.iter().find(|t| t.station == station)
    }

    /// The station tool number `tool` sits in by the job's `[tool_numbers]` map, if it is mapped.
    pub fn station_of_tool(&self, tool: u32) -> Option<u32> {
        self.tool_numbers
            .binary_search_by_key(&tool, |m| m.0)
            .ok()
            .map(|i| self.tool_numbers[i].1)
    }

    /// A human summary, several lines, for `latheguard machine FILE`: name, dialect and modes,
    /// axis limits, the parts present, stock, turret, and one line per tool with its station,
    /// name, tip, and the sizes (x × z, mm) of its insert and holder.
    pub fn describe(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "{}", self.name);
        let mut modes = format!(
            "{}, X words are {}, rapid {}",
            if self.auto_dialect.is_some() {
                "auto (chosen per program, docs/machine.md; fanuc's settings shown)"
            } else {
                self.dialect.as_str()
            },
            if self.diameter_mode { "diameters" } else { "radii" },
            match self.rapid {
                RapidMode::Dogleg => "dogleg (each axis at its own rate)",
                RapidMode::Linear => "linear (interpolated)",
            }
        );
        if self.dialect == Dialect::Fanuc {
            let _ = write!(
                modes,
                ", decimal point {}",
                match self.decimal_point {
                    DecimalPoint::Calculator => "calculator (X60 = 60 mm)",
                    DecimalPoint::Increment => "increment (X60 = 0.060 mm)",
                }
            );
            let _ = write!(modes, ", G-code system {}", self.gcode_system.as_str());
        }
        if self.inch {
            modes.push_str(", programs start in inch (G20)");
        }
        if self.turret_side == TurretSide::Front {
            modes.push_str(", turret in front (+X toward the operator)");
        }
        if self.drilling_cycles == DrillingCycles::Fanuc {
            modes.push_str(", drilling cycles Fanuc's live-tool face and side cycles");
        }
        if self.dialect == Dialect::Fanuc {
            if self.drill_r() == DrillR::Incremental {
                let _ = write!(modes, ", drilling R incremental (from the initial level)");
            }
            if self.g71_d == G71D::Increment {
                modes.push_str(", G71/G72 D without a point in increments (D1500 = 1.5 mm)");
            }
        }
        let _ = writeln!(s, "  dialect     {modes}");
        if !self.gcodes.is_empty() {
            let list: Vec<String> = self
                .gcodes
                .entries()
                .iter()
                .map(|&(c, a)| match a {
                    GAlias::As(t) => format!("{} as {}", g_code_name(c), g_code_name(t)),
                    GAlias::Ignore => format!("{} ignored", g_code_name(c)),
                })
                .collect();
            let _ = writeln!(s, "  G codes     {}", list.join(", "));
        }
        for (name, a) in [("x", &self.x), ("z", &self.z)] {
            let _ = writeln!(
                s,
                "  {name} axis      {} .. {} mm, rapid {} mm/min",
                num(a.min),
                num(a.max),
                num(a.rapid)
            );
        }
        let _ = writeln!(s, "  home        x {}, z {}", num(self.home.x), num(self.home.y));
        if self.machine_zero != self.home {
            let (x, z) = (self.machine_zero.x, self.machine_zero.y);
            let _ = writeln!(s, "  G53 zero    x {}, z {}", num(x), num(z));
        }
        match self.start_rpm {
            Some(r) => {
                let _ = writeln!(
                    s,
                    "  spindle     up to {} rpm, turning at {} rpm from program start",
                    num(self.max_rpm),
                    num(r)
                );
            }
            None => {
                let _ = writeln!(s, "  spindle     up to {} rpm", num(self.max_rpm));
            }
        }
        for (name, part) in [("chuck", &self.chuck), ("tailstock", &self.tailstock)] {
            let text = outline_text(part.as_ref());
            let state = if name == "tailstock" && part.is_some() {
                if self.tailstock_advanced {
                    ", advanced at start"
                } else {
                    ", retracted at start"
                }
            } else {
                ""
            };
            let _ = writeln!(s, "  {name:<11} {text}{state}");
            if let (true, Some(c)) = (name == "chuck", self.chuck_jaws()) {
                let _ = writeln!(s, "  jaws        {}", c.describe());
            }
        }
        let codes: Vec<String> = self
            .mcodes
            .entries()
            .iter()
            .filter(|(_, a)| *a != MAction::NoEffect)
            .map(|(c, a)| format!("M{c} {}", a.as_str()))
            .collect();
        let _ = writeln!(s, "  M codes     {}", codes.join(", "));
        let stock = match &self.stock {
            None => "none".to_string(),
            Some(Stock {
                block: Some(b),
                diameter,
                length,
                front,
                ..
            }) => format!(
                "block {} × {} × {} mm, z {} .. {} (envelope Ø{})",
                num(b.width),
                num(b.height),
                num(*length),
                num(front - length),
                num(*front),
                num(*diameter)
            ),
            Some(st) if st.outline.is_some() => format!(
                "revolved outline, Ø{} max × {} mm, z {} .. {}",
                num(st.diameter),
                num(st.length),
                num(st.front - st.length),
                num(st.front)
            ),
            Some(st) => {
                let kind = if st.bore > 0.0 {
                    format!("tube Ø{}/Ø{}", num(st.diameter), num(st.bore))
                } else {
                    format!("bar Ø{}", num(st.diameter))
                };
                format!(
                    "{kind} × {} mm, z {} .. {}",
                    num(st.length),
                    num(st.front - st.length),
                    num(st.front)
                )
            }
        };
        let _ = writeln!(s, "  stock       {stock}");
        let _ = writeln!(s, "  program Z0  z {}", num(self.program_zero_z));
        if self.work_offsets.iter().any(Option::is_some) {
            for (n, name) in WORK_OFFSET_NAMES.iter().enumerate() {
                if let Some(text) = self.work_offset_text(n) {
                    let _ = writeln!(s, "  {name}         {text}");
                }
            }
        }
        let t = &self.turret;
        let b = t.outline.aabb();
        let carrier = match t.kind {
            TurretKind::Drum => format!(
                "{} stations, starts at {}, axis {} mm in +x, {} s per station",
                t.stations,
                t.start_station,
                num(t.axis),
                num(t.index_time)
            ),
            TurretKind::Gang => format!(
                "gang slide, {} stations, starts at {}, {} s per tool change",
                t.stations,
                t.start_station,
                num(t.index_time)
            ),
        };
        let _ = writeln!(
            s,
            "  turret      {carrier}; outline x {} .. {}, z {} .. {}",
            num(b.min.x),
            num(b.max.x),
            num(b.min.y),
            num(b.max.y)
        );
        let _ = writeln!(s, "  tools       {}", self.tools.len());
        let size = |p: &Polygon| {
            let b = p.aabb();
            format!("{} × {} mm", num(b.max.x - b.min.x), num(b.max.y - b.min.y))
        };
        let rows: Vec<[String; 5]> = self
            .tools
            .iter()
            .map(|t| {
                [
                    format!("{:>2}", t.station),
                    t.name.clone(),
                    format!("tip [{}, {}]", num(t.tip.x), num(t.tip.y)),
                    format!("insert {}", size(&t.insert)),
                    format!("holder {}", size(&t.holder)),
                ]
            })
            .collect();
        let mut widths = [0usize; 5];
        for row in &rows {
            for (w, cell) in widths.iter_mut().zip(row) {
                *w = (*w).max(cell.chars().count());
            }
        }
        for (tool, row) in self.tools.iter().zip(&rows) {
            let mut line = String::from("   ");
            for (cell, w) in row.iter().zip(widths) {
                let _ = write!(line, " {cell}{} ", " ".repeat(w - cell.chars().count()));
            }
            if tool.nose_radius > 0.0 {
                let _ = write!(line, " nose r{}", num(tool.nose_radius));
            }
            if tool.tip_direction != 0 {
                let _ = write!(line, " tip {}", tool.tip_direction);
            }
            let _ = writeln!(s, "{}", line.trim_end());
        }
        for c in &self.paths.carriers {
            let _ = writeln!(
                s,
                "  path {}      {}{}: {} stations, {} tools; x {} .. {}, z {} .. {}",
                c.path,
                c.name,
                if c.opposite { " (across the spindle axis)" } else { "" },
                c.turret.stations,
                c.tools.len(),
                num(c.x.min),
                num(c.x.max),
                num(c.z.min),
                num(c.z.max)
            );
        }
        if let Some((a, b)) = self.paths.wait_mcodes {
            let _ = writeln!(s, "  waits       M{a} .. M{b} (the paths wait for each other)");
        }
        if let Some(k) = &self.kinematics {
            let axes: Vec<String> = k
                .axes
                .iter()
                .map(|a| match a.path {
                    1 => format!("{} {}", a.letter, a.name),
                    p => format!("{} {} (path {p})", a.letter, a.name),
                })
                .collect();
            let meshes = k
                .components
                .iter()
                .filter(|c| matches!(c.geometry, Some(crate::kin::Geometry::Mesh(_))))
                .count();
            let _ = writeln!(
                s,
                "  kinematics  axes {}; {} components ({} from STL files); {} never_touch pairs",
                axes.join(", "),
                k.components.len(),
                meshes,
                k.never_touch.len()
            );
        }
        s
    }
}

/// A length for people: at most three decimals, no trailing zeros, no `-0`.
/// An outline in one line for the human summaries (`latheguard machine`, `latheguard setup`): its
/// extent and its number of points, or `none`.
pub fn outline_text(p: Option<&Polygon>) -> String {
    match p {
        None => "none".to_string(),
        Some(p) => {
            let b = p.aabb();
            format!(
                "x {} .. {}, z {} .. {} ({} points)",
                num(b.min.x),
                num(b.max.x),
                num(b.min.y),
                num(b.max.y),
                p.points().len()
            )
        }
    }
}

/// A length for the human summaries: rounded to the µm, `0` without a sign.
pub fn num(v: f64) -> String {
    let r = (v * 1000.0).round() / 1000.0;
    if !r.is_finite() {
        format!("{v}")
    } else if r == 0.0 {
        "0".to_string()
    } else {
        format!("{r}")
    }
}
