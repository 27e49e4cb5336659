//! Command-line front end (DESIGN §6). Exit status: 0 no error finding, 1 at least one, 2 when
//! latheguard could not run (bad arguments, unreadable or invalid machine file).

mod accuracy;
mod args;
mod check;
mod config;
mod moves;
mod shell;
mod walk;

use args::{Cli, Command};
use clap::Parser;
use latheguard::machine::{self, Machine};
use std::process::ExitCode;

/// Exit status: the run found no error.
pub const EXIT_CLEAN: u8 = 0;
/// Exit status: at least one finding of severity error.
pub const EXIT_FINDINGS: u8 = 1;
/// Exit status: latheguard could not run.
pub const EXIT_TROUBLE: u8 = 2;

pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { EXIT_TROUBLE } else { EXIT_CLEAN };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let code = match run(cli) {
        Ok(code) => code,
        Err(msg) => {
            eprintln!("latheguard: {msg}");
            EXIT_TROUBLE
        }
    };
    ExitCode::from(code)
}

/// A failure that stops latheguard (exit 2), as a message.
pub type Trouble = String;

fn run(cli: Cli) -> Result<u8, Trouble> {
    match cli.command {
        Command::Check(a) => check::run(a, cli.color),
        Command::Moves(a) => moves::run(a),
        Command::Accuracy(a) => accuracy::run(a),

        Command::Machine(a) => {
            let m = load_machine(Some(&a.file))?;
            print!("{}", m.describe());
            Ok(EXIT_CLEAN)
        }
        Command::Completions(a) => shell::completions(a),
        Command::Man(a) => shell::man(a),
    }
}

/// The machine of `-m FILE`, or the built-in one.
pub fn load_machine(path: Option<&std::path::Path>) -> Result<Machine, Trouble> {
    match path {
        None => Ok(Machine::builtin()),
        Some(p) => {
            let text =
                std::fs::read_to_string(p).map_err(|e| format!("{}: cannot read machine file: {e}", p.display()))?;
            machine::from_toml(&text, &p.display().to_string()).map_err(|e| e.to_string())
        }
    }
}

/// Write to `-o FILE` or standard output.
pub fn emit(output: Option<&std::path::Path>, text: &str) -> Result<(), Trouble> {
    use std::io::Write;
    match output {
        Some(p) => std::fs::write(p, text).map_err(|e| format!("{}: cannot write report: {e}", p.display())),
        None => {
            let mut out = std::io::stdout().lock();
            match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
                Ok(()) => Ok(()),
                // A closed pipe (`latheguard … | head`) is not a failure of the check.
                Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(format!("cannot write to standard output: {e}")),
            }
        }
    }
}

/// An I/O error without the OS error number, which differs between systems.
pub fn plain(e: &std::io::Error) -> String {
    let s = e.to_string();
    match s.find(" (os error") {
        Some(i) => s[..i].to_string(),
        None => s,
    }
}
