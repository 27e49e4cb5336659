//! The `latheguard` binary: parse arguments, read files, run the library, pick a reporter, set
//! the exit code. Everything else lives in the library.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
