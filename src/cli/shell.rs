//! Shell integration: completion scripts and man pages, generated from the clap grammar.

use super::args::{Cli, CompletionsArgs, ManArgs};
use super::{emit, Trouble, EXIT_CLEAN};
use clap::CommandFactory;

/// `latheguard completions SHELL`: the script on standard output.
pub fn completions(a: CompletionsArgs) -> Result<u8, Trouble> {
    let mut cmd = Cli::command();
    let mut out = Vec::new();
    clap_complete::generate(a.shell, &mut cmd, "latheguard", &mut out);
    emit(None, &String::from_utf8_lossy(&out))?;
    Ok(EXIT_CLEAN)
}

/// `latheguard man [DIR]`: latheguard.1 on standard output, or one page per command in DIR.
pub fn man(a: ManArgs) -> Result<u8, Trouble> {
    let cmd = Cli::command();
    match a.dir {
        None => {
            let mut out = Vec::new();
            clap_mangen::Man::new(cmd)
                .render(&mut out)
                .map_err(|e| format!("cannot render the man page: {e}"))?;
            emit(None, &String::from_utf8_lossy(&out))?;
        }
        Some(dir) => {
            std::fs::create_dir_all(&dir)
                .map_err(|e| format!("{}: cannot create folder: {}", super::shown(&dir), super::plain(&e)))?;
            clap_mangen::generate_to(cmd, &dir)
                .map_err(|e| format!("{}: cannot write man pages: {}", super::shown(&dir), super::plain(&e)))?;
        }
    }
    Ok(EXIT_CLEAN)
}
