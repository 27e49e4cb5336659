//! Command-line front end (docs/cli.md). Exit status: 0 no error finding, 1 at least one, 2 when
//! latheguard could not run (bad arguments, unreadable or invalid machine file, an output that
//! cannot be written). Nothing here prints with `print!`/`println!` (they panic on a closed pipe
//! or a full disk): standard output goes through [`emit`], standard error through [`say`].

mod accuracy;
mod args;
mod check;
mod config;
mod follow;
mod moves;
mod setup;
mod shell;
mod tools;
mod walk;

use args::{Cli, Command};
use clap::Parser;
use latheguard::machine::{self, Machine};
use latheguard::report::terminal_safe;
use std::io::{ErrorKind, Read, Write};
use std::path::Path;
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
            // `--help | head`: a closed pipe is no failure; a full disk is.
            if let Err(err) = e.print() {
                if err.kind() != ErrorKind::BrokenPipe && !e.use_stderr() {
                    say(&format!("cannot write to standard output: {}", plain(&err)));
                    return ExitCode::from(EXIT_TROUBLE);
                }
            }
            return ExitCode::from(code);
        }
    };
    let code = match run(cli) {
        Ok(code) => code,
        Err(msg) => {
            say(&msg);
            EXIT_TROUBLE
        }
    };
    ExitCode::from(code)
}

/// A failure that stops latheguard (exit 2), as a message.
pub type Trouble = String;

fn run(cli: Cli) -> Result<u8, Trouble> {
    match cli.command {
        Command::Check(a) => check::run(*a, cli.color),
        Command::Moves(a) => moves::run(a),
        Command::Follow(a) => follow::run(*a),
        Command::Accuracy(a) => accuracy::run(a),
        Command::Setup(a) => setup::run(*a),

        Command::Machine(args::MachineArgs {
            new: Some(args::MachineCommand::New(a)),
            ..
        }) => machine_new(a),
        Command::Machine(a) => {
            let Some(file) = a.file.filter(|_| !a.schema) else {
                emit(None, &machine::schema())?;
                return Ok(EXIT_CLEAN);
            };
            let m = load_machine(Some(&file))?;
            if let Some(out) = &a.svg {
                let title = file.display().to_string();
                emit(Some(out), &latheguard::report::machine_svg::machine_drawing(&m, &title))?;
            }
            // Names in a machine file may hold control characters: never raw to a terminal.
            emit(None, &safe_lines(&m.describe()))?;
            Ok(EXIT_CLEAN)
        }
        Command::Schema(a) => {
            emit(
                None,
                &match a.of {
                    args::SchemaOf::Machine => machine::schema(),
                    args::SchemaOf::Config => config::schema(),
                    args::SchemaOf::Job => latheguard::job::schema(),
                },
            )?;
            Ok(EXIT_CLEAN)
        }
        Command::Tools(a) => tools::run(a),
        Command::Completions(a) => shell::completions(a),
        Command::Man(a) => shell::man(a),
    }
}

/// `latheguard machine new`: the starter file to `-o FILE` (never over an existing one without
/// `--force`) or standard output.
fn machine_new(a: args::MachineNewArgs) -> Result<u8, Trouble> {
    let gang = a.kind == "gang";
    let spec = machine::new::NewSpec {
        name: a.name,
        chuck_diameter: a.chuck_diameter,
        jaw_height: a.jaw_height,
        bar_capacity: a.bar_capacity,
        stations: a.stations.unwrap_or(if gang { 4 } else { 8 }),
        gang,
        x_travel: a.x_travel,
        z_travel: a.z_travel,
        dialect: a.dialect,
        inch: a.units == "inch",
    };
    spec.check()?;
    let text = machine::new::starter(&spec);
    match a.output {
        None => emit(None, &text)?,
        Some(path) => {
            if path.exists() && !a.force {
                return Err(format!("{} exists: give --force to overwrite it", shown(&path)));
            }
            std::fs::write(&path, text).map_err(|e| format!("{}: cannot write: {}", shown(&path), plain(&e)))?;
        }
    }
    Ok(EXIT_CLEAN)
}

/// Machine files larger than this are not read (exit 2).
pub const MAX_MACHINE_BYTES: u64 = 4 << 20;
/// `latheguard.toml` files larger than this are not read (exit 2).
pub const MAX_CONFIG_BYTES: u64 = 1 << 20;
/// Programs larger than this are not read (a finding of the file for `check`, exit 2 for
/// `moves` and `accuracy`).
pub const MAX_PROGRAM_BYTES: u64 = 256 << 20;

/// The machine of `-m FILE`, or the built-in one.
pub fn load_machine(path: Option<&Path>) -> Result<Machine, Trouble> {
    match path {
        None => Ok(Machine::builtin()),
        Some(p) => {
            let shown = shown(p);
            let text =
                read_text(p, MAX_MACHINE_BYTES).map_err(|why| format!("{shown}: cannot read machine file: {why}"))?;
            let m = parse_machine(&text, &shown, p).map_err(|e| error_lines(&e))?;
            warn_machine(&m);
            Ok(m)
        }
    }
}

/// A machine file's text → the machine, reading the STL files its `[kinematics]` names from the
/// folder of `path` (each at most `latheguard::kin::stl::MAX_STL_BYTES`).
pub fn parse_machine(text: &str, shown: &str, path: &Path) -> Result<Machine, machine::MachineError> {
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let resolve = move |name: &str| -> Result<Vec<u8>, String> {
        read_capped(&dir.join(name), latheguard::kin::stl::MAX_STL_BYTES as u64)
    };
    machine::from_toml_with(text, shown, &resolve)
}

/// Every problem of a machine file on a line of its own, each with the `latheguard:` that [`say`]
/// puts before the first.
pub fn error_lines(e: &machine::MachineError) -> String {
    e.to_string().replace('\n', "\nlatheguard: ")
}

/// A machine file's values that load but look like unit mistakes, on standard error.
pub fn warn_machine(m: &Machine) {
    for w in &m.warnings {
        say(&format!("warning: {w}"));
    }
}

/// The bytes of a file, at most `cap` of them, or why they cannot be had (a message without
/// the path). Only regular files are read: a FIFO, a socket or a device (`/dev/zero`) is refused
/// from its metadata before it is opened, so reading never blocks and never runs on without end;
/// the opened file is asked again in case it was swapped in between.
pub fn read_capped(path: &Path, cap: u64) -> Result<Vec<u8>, String> {
    let meta = std::fs::metadata(path).map_err(|e| plain(&e))?;
    regular(&meta, cap)?;
    let file = std::fs::File::open(path).map_err(|e| plain(&e))?;
    let meta = file.metadata().map_err(|e| plain(&e))?;
    regular(&meta, cap)?;
    let mut bytes = Vec::with_capacity(meta.len().min(cap) as usize);
    file.take(cap + 1).read_to_end(&mut bytes).map_err(|e| plain(&e))?;
    if bytes.len() as u64 > cap {
        return Err(format!("it is larger than the {} latheguard reads", mib(cap)));
    }
    Ok(bytes)
}

/// A text file read with [`read_capped`].
pub fn read_text(path: &Path, cap: u64) -> Result<String, String> {
    String::from_utf8(read_capped(path, cap)?).map_err(|_| "it is not UTF-8 text".to_string())
}

fn regular(meta: &std::fs::Metadata, cap: u64) -> Result<(), String> {
    let ft = meta.file_type();
    if ft.is_dir() {
        return Err("it is a folder".into());
    }
    if !ft.is_file() {
        #[cfg(unix)]
        {
            use std::os::unix::fs::FileTypeExt;
            let what = if ft.is_fifo() {
                "a FIFO (named pipe)"
            } else if ft.is_char_device() || ft.is_block_device() {
                "a device"
            } else if ft.is_socket() {
                "a socket"
            } else {
                "a special file"
            };
            return Err(format!("it is {what}, not a regular file"));
        }
        #[cfg(not(unix))]
        return Err("it is not a regular file".into());
    }
    if meta.len() > cap {
        return Err(format!(
            "it is {} bytes, larger than the {} latheguard reads",
            meta.len(),
            mib(cap)
        ));
    }
    Ok(())
}

fn mib(bytes: u64) -> String {
    format!("{} MiB", bytes >> 20)
}

/// A path as messages show it: control and bidi characters escaped (`\x1b`, `\n`, `\u{202e}`).
pub fn shown(p: &Path) -> String {
    terminal_safe(&p.display().to_string()).into_owned()
}

/// Each line of a text made safe for a terminal; the line breaks themselves are kept.
pub fn safe_lines(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, line) in text.split('\n').enumerate() {
        if i > 0 {
            out.push('\n');
        }
        out.push_str(&terminal_safe(line));
    }
    out
}

/// `latheguard: MESSAGE` on standard error, each line made safe for a terminal. A standard error
/// that cannot be written (closed, a full disk) is ignored: there is nowhere left to say it.
pub fn say(msg: &str) {
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "latheguard: {}", safe_lines(msg));
}

/// Write to `-o FILE` or standard output. A closed pipe on standard output (`latheguard … | head`)
/// is not a failure: the run ends with its usual exit status. Any other write error (a full
/// disk) is trouble (exit 2).
pub fn emit(output: Option<&Path>, text: &str) -> Result<(), Trouble> {
    match output {
        Some(p) => std::fs::write(p, text).map_err(|e| format!("{}: cannot write report: {}", shown(p), plain(&e))),
        None => {
            let mut out = std::io::stdout().lock();
            match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
                Ok(()) => Ok(()),
                Err(e) if e.kind() == ErrorKind::BrokenPipe => Ok(()),
                Err(e) => Err(format!("cannot write to standard output: {}", plain(&e))),
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
