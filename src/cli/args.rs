//! The argument grammar (clap derive).

use clap::{Args, Parser, Subcommand, ValueEnum};
use latheguard::finding::Kind;
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "latheguard",
    version,
    about = "Finds the lines of a CNC lathe program that would crash the machine",
    after_help = EXIT_AND_ENVIRONMENT
)]
pub struct Cli {
    /// When to colour the report: auto (a terminal without NO_COLOR), always, never.
    #[arg(long, value_enum, global = true, default_value_t = ColorArg::Auto, value_name = "WHEN")]
    pub color: ColorArg,
    #[command(subcommand)]
    pub command: Command,
}

/// The exit statuses and environment variables, under `--help` and in the man pages.
pub const EXIT_AND_ENVIRONMENT: &str = "\
Exit status:
  0  no finding fails the run (no error; with --fail-on warning, no warning either)
  1  at least one finding fails the run (suppressed and --ignore'd findings never do)
  2  latheguard could not run: bad arguments, a named path that does not exist, an unreadable
     or invalid machine file or latheguard.toml, a report that cannot be written

Environment:
  NO_COLOR             set and not empty: no colours with --color auto
  CI                   set: no progress bar
  LATHEGUARD_DOCS_URL  the address of the published finding pages KIND.md (SARIF helpUri)";

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Check programs, or folders walked for NC files.
    #[command(after_help = EXIT_AND_ENVIRONMENT)]
    Check(Box<CheckArgs>),
    /// Print the interpreted motion, one move a line.
    Moves(MovesArgs),
    /// Check a machine's live axis positions as they come, one sample a line (docs/follow.md).
    Follow(Box<FollowArgs>),
    /// Validate and describe a machine file.
    Machine(MachineArgs),
    /// Tools from their catalogue names (ISO inserts, holders, boring bars), LinuxCNC tool tables.
    Tools(ToolsArgs),
    /// The cost-of-accuracy table: exact mode against step mode at several timesteps and tolerances.
    Accuracy(AccuracyArgs),
    /// The effective machine and job of a program: each layer that applied, stock, program zero,
    /// chuck, tailstock, tools by station.
    Setup(Box<SetupArgs>),
    /// Print the JSON Schema of machine files, job files or latheguard.toml, for editors.
    Schema(SchemaArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(CompletionsArgs),
    /// Write the man pages (latheguard.1, latheguard-check.1, …).
    Man(ManArgs),
}

#[derive(Args, Debug)]
pub struct AccuracyArgs {
    /// The NC program to check at every setting.
    pub program: PathBuf,
    /// Machine description (default: the built-in machine; latheguard.toml is not read here).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// Report format.
    #[arg(long, value_enum, default_value_t = TableFormat::Text)]
    pub format: TableFormat,
    /// Also write a plot of run time against missed collisions (SVG).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Runs of each setting, 1 to 100; the median time is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=MAX_REPEATS))]
    pub repeats: u16,
    /// Leave the run times out (`-` in the table, 0 in JSON) so that the output is the same on
    /// every run and machine: for tests and documentation.
    #[arg(long)]
    pub no_timing: bool,
    /// Clearance for near misses, 0 to 10 mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = clearance)]
    pub clearance: f64,
    /// Contacts shallower than this are grazes (warnings), 0 to 1 mm [default: the machine's
    /// min_depth, else 0.1].
    #[arg(long, value_name = "MM", value_parser = min_depth)]
    pub min_depth: Option<f64>,
    #[command(flatten)]
    pub job: JobArgs,
}

/// The job of a run (docs/job.md): over the machine, `latheguard.toml` and the file beside the
/// program.
#[derive(Args, Debug, Clone, Default)]
pub struct JobArgs {
    /// A job file (stock, program zero, jaws, tailstock, tools) over every other job layer.
    #[arg(long, value_name = "FILE")]
    pub job: Option<PathBuf>,
    /// The stock, mm: DIAxLEN[@STICKOUT] (50x120@80), a tube DIA/BORExLEN[@STICKOUT].
    #[arg(long, value_name = "DIAxLEN[@STICKOUT]")]
    pub stock: Option<String>,
    /// A file of [[tools]] tables by station (as in a job file) over every other layer.
    #[arg(long, value_name = "FILE.toml")]
    pub tools: Option<PathBuf>,
    /// The program's units at program start.
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// z of program Z0 from the jaw faces, mm.
    #[arg(long, value_name = "Z", allow_hyphen_values = true, value_parser = program_zero)]
    pub program_zero: Option<f64>,
    /// Do not read the bar, program zero and tools from the program: the machine file's setup
    /// and the job's only (docs/assume.md).
    #[arg(long)]
    pub no_assume: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum UnitsArg {
    Mm,
    Inch,
}

#[derive(Args, Debug)]
pub struct SetupArgs {
    pub program: PathBuf,
    /// Machine description (default: from latheguard.toml, else the built-in machine).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    #[command(flatten)]
    pub job: JobArgs,
    /// Ignore latheguard.toml files.
    #[arg(long)]
    pub no_config: bool,
    #[arg(long, value_enum, default_value_t = TableFormat::Text)]
    pub format: TableFormat,
}

/// Formats of the accuracy table.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum TableFormat {
    Text,
    Json,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// Programs, or folders walked for NC files; `-` reads one program from standard input
    /// [default: `.`; `-` with --stdin-filename].
    pub paths: Vec<PathBuf>,
    /// Print the documentation of a finding kind, by name or code (collision, LG02, …), and exit.
    #[arg(long, value_name = "KIND")]
    pub explain: Option<String>,
    /// Report only these finding kinds, by name or code, comma-separated (rapid_into_stock,LG01).
    #[arg(long, value_name = "KIND,…", value_delimiter = ',', value_parser = kind)]
    pub select: Option<Vec<Kind>>,
    /// Never report these finding kinds, by name or code, comma-separated; wins over --select and
    /// adds to latheguard.toml's `ignore`.
    #[arg(long, value_name = "KIND,…", value_delimiter = ',', value_parser = kind)]
    pub ignore: Option<Vec<Kind>>,
    /// Report these finding kinds too, over --select and latheguard.toml's `select` and `ignore`.
    #[arg(long, value_name = "KIND,…", value_delimiter = ',', value_parser = kind)]
    pub extend_select: Option<Vec<Kind>>,
    /// The least severity that fails the run (exit 1) [default: error].
    #[arg(long, value_enum, value_name = "SEVERITY")]
    pub fail_on: Option<FailOnArg>,
    /// Print how many findings of each kind there are, instead of the findings.
    #[arg(long)]
    pub statistics: bool,
    /// Machine description (default: from latheguard.toml, else the built-in machine).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// How moves are checked [default: step].
    #[arg(long, value_enum)]
    pub mode: Option<ModeArg>,
    /// Timestep in milliseconds of machine time, step mode, 0.001 to 1000 [default: 1].
    #[arg(long, value_name = "MS", value_parser = dt)]
    pub dt: Option<f64>,
    /// How far curves may be replaced by chords, 0.001 to 1 mm [default: 0.01].
    #[arg(long, value_name = "MM", value_parser = tolerance)]
    pub tolerance: Option<f64>,
    /// Report parts closer than this as near misses, 0 to 10 mm [default: 0].
    #[arg(long, value_name = "MM", value_parser = clearance)]
    pub clearance: Option<f64>,
    /// Contacts shallower than this are grazes (warnings), 0 to 1 mm [default: the machine's
    /// min_depth, else 0.1].
    #[arg(long, value_name = "MM", value_parser = min_depth)]
    pub min_depth: Option<f64>,
    /// Report format (also --output-format).
    #[arg(long, alias = "output-format", value_enum, default_value_t = FormatArg::Text)]
    pub format: FormatArg,
    /// Write the report here instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Write a picture (SVG) of the working plane at each finding into this folder.
    #[arg(long, value_name = "DIR")]
    pub svg: Option<PathBuf>,
    /// Write the posed 3D scene (glTF binary, .glb) at each finding of a turn-mill machine's 3D
    /// check into this folder; findings of the working plane have none.
    #[arg(long, value_name = "DIR")]
    pub glb: Option<PathBuf>,
    /// Write the final part (the stock at the end) of the one program checked: its section with its
    /// main dimensions as SVG, with a .stl name the part as an STL mesh (milled features
    /// included), with a .toml name the part as a job fragment ([stock] outline) for the next
    /// operation's `[stock] from`.
    #[arg(long, value_name = "FILE.svg|FILE.stl|FILE.toml")]
    pub stock_out: Option<PathBuf>,
    /// Files checked in parallel, 1 to 256, never more than the files [default: all cores].
    #[arg(short, long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=MAX_JOBS))]
    pub jobs: Option<u16>,
    /// Extensions taken as NC programs when walking folders, comma-separated (a .txt found in a
    /// folder only when its first lines read as G-code) [default: nc,ngc,tap,cnc,mpf,eia,gcode,txt].
    #[arg(long, value_name = "EXT,…", value_delimiter = ',', value_parser = extension)]
    pub ext: Option<Vec<String>>,
    /// Check only the I-th of N equal parts of the files (1-based), to split a batch over runners.
    #[arg(long, value_name = "I/N", value_parser = shard)]
    pub shard: Option<Shard>,
    /// Ignore latheguard.toml files.
    #[arg(long, conflicts_with = "config")]
    pub no_config: bool,
    /// Use this file as the latheguard.toml of every program instead of looking for the nearest
    /// one (paths in it are relative to its folder).
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Print what applies to a program (the first of PATH, else of the paths checked) and where
    /// each value came from, then exit.
    #[arg(long, value_name = "PATH", num_args = 0..=1, default_missing_value = "")]
    pub show_settings: Option<String>,
    /// The name of the program read from standard input (`-`): latheguard.toml, the job file
    /// beside it and per-file-ignores are looked up as for this path, and reports name it.
    #[arg(long, value_name = "NAME")]
    pub stdin_filename: Option<PathBuf>,
    /// Leave run times out of the report (JSON elapsed_ms is 0, no JUnit times): byte-identical
    /// output from run to run.
    #[arg(long)]
    pub no_timing: bool,
    /// Only errors and the summary line; no progress bar.
    #[arg(short, long)]
    pub quiet: bool,
    #[command(flatten)]
    pub job: JobArgs,
}

#[derive(Args, Debug)]
pub struct MovesArgs {
    /// The NC program to interpret.
    pub program: PathBuf,
    /// Machine description (default: the built-in machine; latheguard.toml is not read here).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// Output: rs274-style canonical calls, a JSON array of the moves, or the samples a
    /// control would report every --dt (JSON lines, the input of `latheguard follow`).
    #[arg(long, value_enum, default_value_t = MovesFormat::Canon)]
    pub format: MovesFormat,
    /// With --format samples: ms of machine time between samples (besides one at every move's
    /// end), 0.001 to 1000.
    #[arg(long, value_name = "MS", default_value_t = 1.0, value_parser = dt)]
    pub dt: f64,
    /// The path whose moves to print, on a multi-path machine or of a file with `$1`/`$2` lines:
    /// its lines, on its carrier (1 to 9; default 1).
    #[arg(long, value_name = "N", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=9))]
    pub path: u32,
    #[command(flatten)]
    pub job: JobArgs,
}

#[derive(Args, Debug)]
pub struct FollowArgs {
    /// Where the samples come from: a file, `-` (standard input, the default), `tcp:HOST:PORT`
    /// (connect and read), or `unix:PATH` (a Unix socket).
    pub source: Option<String>,
    /// Machine description (default: the built-in machine).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// A job file (stock, jaws, tailstock, tools) over the machine file.
    #[arg(long, value_name = "FILE")]
    pub job: Option<PathBuf>,
    /// Check with the setup `check` gives this program (its latheguard.toml's machine and
    /// settings, the job beside it); the program itself is not read.
    #[arg(long, value_name = "FILE")]
    pub program: Option<PathBuf>,
    /// How the samples are written: JSON lines, CSV with a header, or auto (JSON when the first
    /// sample starts with `{`).
    #[arg(long, value_enum, default_value_t = SamplesFormat::Auto)]
    pub samples: SamplesFormat,
    /// Seconds between samples that give no time `t` (a fixed-rate feed such as halsampler's).
    #[arg(long, value_name = "S", value_parser = period)]
    pub period: Option<f64>,
    /// Findings as text lines, or one JSON object a line.
    #[arg(long, value_enum, default_value_t = FollowFormat::Text)]
    pub format: FollowFormat,
    /// Warn of parts closer than this without touching, 0 to 10 mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = clearance)]
    pub clearance: f64,
    /// Contacts shallower than this are grazes (warnings), 0 to 1 mm [default: the machine's
    /// min_depth, else 0.1].
    #[arg(long, value_name = "MM", value_parser = min_depth)]
    pub min_depth: Option<f64>,
    /// Exact mode's tolerance and the stock's resolution, mm.
    #[arg(long, value_name = "MM", value_parser = tolerance)]
    pub tolerance: Option<f64>,
    /// At the end, the samples taken and the processing time per sample (median, 99th
    /// percentile, maximum) on standard error (with --format json, also a last `summary` record).
    #[arg(long)]
    pub stats: bool,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum SamplesFormat {
    Auto,
    Json,
    Csv,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum FollowFormat {
    Text,
    Json,
}

fn period(s: &str) -> Result<f64, String> {
    in_range(s, (1e-6, 3600.0))
}

#[derive(Args, Debug)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct MachineArgs {
    #[command(subcommand)]
    pub new: Option<MachineCommand>,
    #[arg(required_unless_present = "schema")]
    pub file: Option<PathBuf>,
    /// Print the JSON Schema of machine files (for editors that complete and validate TOML) and exit.
    #[arg(long)]
    pub schema: bool,
    /// Also draw the machine at home (chuck, stock, tailstock, turret, every tool at its station,
    /// the travel) as SVG into this file (docs/machine.md).
    #[arg(long, value_name = "FILE.svg")]
    pub svg: Option<PathBuf>,
}

#[derive(clap::Subcommand, Debug)]
pub enum MachineCommand {
    /// Write a commented starter machine file from a few answers (docs/machine.md).
    New(MachineNewArgs),
}

#[derive(Args, Debug)]
pub struct MachineNewArgs {
    /// Write to this file (default: standard output); an existing file only with --force.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Overwrite FILE if it exists.
    #[arg(long)]
    pub force: bool,
    /// The machine's name.
    #[arg(long, default_value = "My lathe")]
    pub name: String,
    /// Chuck outside diameter, mm (80 to 1000).
    #[arg(long, default_value_t = 210.0)]
    pub chuck_diameter: f64,
    /// How far the jaws stand out of the chuck face, mm (5 to 100).
    #[arg(long, default_value_t = 30.0)]
    pub jaw_height: f64,
    /// The largest bar through the spindle, mm (5 to half the chuck diameter).
    #[arg(long, default_value_t = 52.0)]
    pub bar_capacity: f64,
    /// Turret stations (1 to 24) [default: 8 on a drum, 4 on a gang slide].
    #[arg(long)]
    pub stations: Option<u32>,
    /// The tool carrier.
    #[arg(long = "type", value_parser = ["drum", "gang"], default_value = "drum")]
    pub kind: String,
    /// X travel (radius) of the turret, mm (100 to 2000).
    #[arg(long, default_value_t = 300.0)]
    pub x_travel: f64,
    /// Z travel of the turret, mm (100 to 5000).
    #[arg(long, default_value_t = 600.0)]
    pub z_travel: f64,
    /// How programs are read.
    #[arg(long, value_parser = ["fanuc", "linuxcnc", "auto"], default_value = "fanuc")]
    pub dialect: String,
    /// Program units at program start.
    #[arg(long, value_parser = ["mm", "inch"], default_value = "mm")]
    pub units: String,
}

#[derive(Args, Debug)]
pub struct ToolsArgs {
    #[command(subcommand)]
    pub command: ToolsCommand,
}

#[derive(Subcommand, Debug)]
pub enum ToolsCommand {
    /// What an insert and holder designation decode to: shape, angles, sizes, nose radius, tip
    /// direction, the outlines' extents.
    Show(ToolsShowArgs),
    /// Print a LinuxCNC tool table (.tbl) as a tool library ([[tools]] entries, TOML).
    Import(ToolsImportArgs),
}

#[derive(Args, Debug)]
pub struct ToolsShowArgs {
    /// An insert (`CNMG 120408`, `16ER 1.5ISO`, `GROOVE 3x20`) or a holder alone (`PCLNR 2525M12`,
    /// `S20S-SCLCR09`); quote codes with spaces.
    #[arg(required_unless_present = "drill")]
    pub code: Option<String>,
    /// The holder or boring bar for the insert CODE.
    pub holder: Option<String>,
    /// A drill instead: diameter and flute length in mm, point angle in degrees (118 if left out).
    #[arg(long, value_name = "D,LENGTH[,ANGLE]", conflicts_with_all = ["code", "holder"])]
    pub drill: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = TableFormat::Text)]
    pub format: TableFormat,
    /// Also draw the tool's outlines (SVG).
    #[arg(long, value_name = "FILE.svg")]
    pub svg: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct ToolsImportArgs {
    /// The LinuxCNC tool table.
    pub file: PathBuf,
    /// The table's length unit (X, Z, D); the library is written in mm.
    #[arg(long, value_enum, default_value_t = TblUnits::Mm)]
    pub units: TblUnits,
}

/// Length units of a tool table.
#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum TblUnits {
    Mm,
    Inch,
}

#[derive(Args, Debug)]
pub struct SchemaArgs {
    /// Which file's schema.
    #[arg(value_enum)]
    pub of: SchemaOf,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum SchemaOf {
    /// A machine file (also `latheguard machine --schema`; `machines/machine.schema.json`).
    Machine,
    /// A `latheguard.toml` configuration file (`machines/config.schema.json`).
    Config,
    /// A job file (`machines/job.schema.json`, docs/job.md).
    Job,
}

#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell to complete for.
    #[arg(value_enum)]
    pub shell: clap_complete::Shell,
}

#[derive(Args, Debug)]
pub struct ManArgs {
    /// Folder to write one page per command into; without it, latheguard.1 goes to standard output.
    #[arg(value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ModeArg {
    Step,
    Exact,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum FormatArg {
    Text,
    Json,
    Junit,
    Sarif,
    /// GitHub Actions workflow commands (annotations).
    Github,
    /// GitLab Code Quality JSON.
    Gitlab,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum FailOnArg {
    Error,
    Warning,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum ColorArg {
    Auto,
    Always,
    Never,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MovesFormat {
    Canon,
    Json,
    Samples,
}

/// `--shard I/N`: the I-th (1-based) of N parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

fn shard(s: &str) -> Result<Shard, String> {
    let bad = || format!("`{s}` is not a shard: write I/N with 1 ≤ I ≤ N, e.g. 2/3");
    let (i, n) = s.split_once('/').ok_or_else(bad)?;
    let index: usize = i.trim().parse().map_err(|_| bad())?;
    let count: usize = n.trim().parse().map_err(|_| bad())?;
    if index >= 1 && index <= count {
        Ok(Shard { index, count })
    } else {
        Err(bad())
    }
}

fn kind(s: &str) -> Result<Kind, String> {
    latheguard::gate::kind_by_name_or_code(s).ok_or_else(|| {
        let all: Vec<String> = Kind::ALL
            .iter()
            .map(|&k| format!("{} ({})", k.name(), latheguard::finding::code(k)))
            .collect();
        format!("`{s}` is not a finding kind; the kinds are: {}", all.join(", "))
    })
}

fn extension(s: &str) -> Result<String, String> {
    let e = s.trim().trim_start_matches('.');
    if e.is_empty() || e.contains(['/', '\\']) {
        Err(format!("`{s}` is not a file extension"))
    } else {
        Ok(e.to_string())
    }
}

/// `--jobs` above this is refused: each job is a thread.
pub const MAX_JOBS: i64 = 256;
/// `accuracy --repeats` above this is refused.
pub const MAX_REPEATS: i64 = 100;
/// The ranges of the numeric settings (command line and `latheguard.toml`): below the smallest
/// timestep or tolerance a check's work grows without bound; a wider clearance makes every part
/// a near miss of every other and costs exact mode minutes.
pub const DT_MS: (f64, f64) = (1e-3, 1000.0);
pub const TOLERANCE_MM: (f64, f64) = (1e-3, 1.0);
pub const CLEARANCE_MM: (f64, f64) = (0.0, 10.0);

/// Why `v` is outside `lo ..= hi` (NaN and infinities included), if it is.
pub fn out_of_range(v: f64, (lo, hi): (f64, f64)) -> Option<String> {
    if v.is_finite() && v >= lo && v <= hi {
        None
    } else {
        Some(format!("must be a number from {lo} to {hi}, not {v}"))
    }
}

fn in_range(s: &str, range: (f64, f64)) -> Result<f64, String> {
    let v: f64 = s.trim().parse().map_err(|_| format!("`{s}` is not a number"))?;
    match out_of_range(v, range) {
        None => Ok(v),
        Some(why) => Err(why),
    }
}

fn dt(s: &str) -> Result<f64, String> {
    in_range(s, DT_MS)
}

fn tolerance(s: &str) -> Result<f64, String> {
    in_range(s, TOLERANCE_MM)
}

fn program_zero(s: &str) -> Result<f64, String> {
    in_range(
        s,
        (-latheguard::machine::MAX_COORD_MM, latheguard::machine::MAX_COORD_MM),
    )
}

fn clearance(s: &str) -> Result<f64, String> {
    in_range(s, CLEARANCE_MM)
}

fn min_depth(s: &str) -> Result<f64, String> {
    in_range(s, latheguard::pipeline::MIN_DEPTH_MM)
}
