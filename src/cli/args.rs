//! The argument grammar (clap derive).

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

#[derive(Parser, Debug)]
#[command(
    name = "latheguard",
    version,
    about = "Finds the lines of a CNC lathe program that would crash the machine"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand, Debug)]
pub enum Command {
    /// Check programs, or folders walked for NC files.
    Check(CheckArgs),
    /// Print the interpreted motion, one move a line.
    Moves(MovesArgs),
    /// Validate and describe a machine file.
    Machine(MachineArgs),
    /// The cost-of-accuracy table: exact mode against step mode at several timesteps and tolerances.
    Accuracy(AccuracyArgs),
}

#[derive(Args, Debug)]
pub struct AccuracyArgs {
    pub program: PathBuf,
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// Report format.
    #[arg(long, value_enum, default_value_t = FormatArg::Text)]
    pub format: FormatArg,
    /// Also write a plot of run time against missed collisions (SVG).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<PathBuf>,
    /// Runs of each setting; the median time is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(usize))]
    pub repeats: usize,
    /// Clearance for near misses, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = non_negative)]
    pub clearance: f64,
}

#[derive(Args, Debug)]
pub struct CheckArgs {
    /// Programs, or folders walked for NC files.
    #[arg(required_unless_present = "explain")]
    pub paths: Vec<PathBuf>,
    /// Print the documentation of a finding kind (collision, rapid_into_stock, …) and exit.
    #[arg(long, value_name = "KIND")]
    pub explain: Option<String>,
    /// Machine description (default: the built-in machine).
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    /// How moves are checked.
    #[arg(long, value_enum, default_value_t = ModeArg::Step)]
    pub mode: ModeArg,
    /// Timestep in milliseconds of machine time (step mode).
    #[arg(long, value_name = "MS", default_value_t = 1.0, value_parser = positive)]
    pub dt: f64,
    /// How far curves may be replaced by chords, in mm.
    #[arg(long, value_name = "MM", default_value_t = 0.01, value_parser = positive)]
    pub tolerance: f64,
    /// Report parts closer than this as near misses, in mm.
    #[arg(long, value_name = "MM", default_value_t = 0.0, value_parser = non_negative)]
    pub clearance: f64,
    /// Report format.
    #[arg(long, value_enum, default_value_t = FormatArg::Text)]
    pub format: FormatArg,
    /// Write the report here instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Files checked in parallel (default: all cores).
    #[arg(short, long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Only errors and the summary line.
    #[arg(short, long)]
    pub quiet: bool,
}

#[derive(Args, Debug)]
pub struct MovesArgs {
    pub program: PathBuf,
    #[arg(short, long, value_name = "FILE")]
    pub machine: Option<PathBuf>,
    #[arg(long, value_enum, default_value_t = MovesFormat::Canon)]
    pub format: MovesFormat,
}

#[derive(Args, Debug)]
pub struct MachineArgs {
    pub file: PathBuf,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum ModeArg {
    Step,
    Exact,
}

#[derive(Clone, Copy, Debug, ValueEnum, PartialEq, Eq)]
pub enum FormatArg {
    Text,
    Json,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MovesFormat {
    Canon,
    Json,
}

fn positive(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(format!("`{s}` must be a finite number greater than 0"))
    }
}

fn non_negative(s: &str) -> Result<f64, String> {
    let v: f64 = s.parse().map_err(|_| format!("`{s}` is not a number"))?;
    if v.is_finite() && v >= 0.0 {
        Ok(v)
    } else {
        Err(format!("`{s}` must be a finite number, 0 or more"))
    }
}
