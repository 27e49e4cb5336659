//! Which files a `check` covers: the paths given, and NC files found in folders given.
//!
//! Folders are walked with the `ignore` crate, as git sees them: `.gitignore` (in a repository or
//! not), `.git/info/exclude`, `.ignore` and `.latheguardignore` files are honoured, and hidden
//! files and folders are skipped. The user's global git excludes are not read, so the same tree
//! gives the same files on every machine. Symbolic links to files are taken; links to folders
//! are not followed. FIFOs, sockets and devices found in a folder are skipped (a path named on the
//! command line is always taken; reading it then says why it cannot be read).

use std::path::{Component, Path, PathBuf};

/// File extensions taken as NC programs when walking a folder (case-insensitive).
pub const NC_EXTENSIONS: &[&str] = &["nc", "ngc", "tap", "cnc", "mpf", "eia", "gcode", "txt"];

/// A file to check, or a path that could not be listed (reported as a finding for that path).
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Entry {
    pub path: PathBuf,
    /// Why the path could not be listed, when it could not.
    pub problem: Option<String>,
}

/// Files named directly are always checked; folders are walked for files with one of `exts`.
/// The result is sorted by path (component-wise) and has no duplicates.
pub fn collect(paths: &[PathBuf], exts: &[String]) -> Vec<Entry> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            walk(p, exts, &mut out);
        } else {
            out.push(Entry {
                path: tidy(p),
                problem: None,
            });
        }
    }
    out.sort();
    out.dedup_by(|a, b| a.path == b.path);
    out
}

fn walk(root: &Path, exts: &[String], out: &mut Vec<Entry>) {
    let walker = ignore::WalkBuilder::new(root)
        .standard_filters(true)
        .require_git(false)
        .git_global(false)
        .add_custom_ignore_filename(".latheguardignore")
        .follow_links(false)
        .build();
    for item in walker {
        match item {
            Ok(e) => {
                let Some(ft) = e.file_type() else { continue };
                // A link is taken when it names a regular file, or names nothing (reading it then
                // says why). FIFOs, sockets and devices, and links to them, are skipped: opening a
                // FIFO would wait for a writer.
                let file =
                    ft.is_file() || (ft.is_symlink() && std::fs::metadata(e.path()).map_or(true, |m| m.is_file()));
                // A `.toml` file (a job, a machine, a configuration) is never a program, whatever --ext says.
                let toml = has_extension(e.path(), &["toml".to_string()]);
                if file && !toml && has_extension(e.path(), exts) && (!is_txt(e.path()) || looks_like_gcode(e.path())) {
                    out.push(Entry {
                        path: tidy(e.path()),
                        problem: None,
                    });
                }
            }
            Err(err) => {
                if let Some(path) = error_path(&err) {
                    out.push(Entry {
                        path: tidy(&path),
                        problem: Some(format!("cannot list: {}", error_cause(&err))),
                    });
                }
            }
        }
    }
}

fn error_path(e: &ignore::Error) -> Option<PathBuf> {
    match e {
        ignore::Error::WithPath { path, .. } => Some(path.clone()),
        ignore::Error::WithDepth { err, .. } | ignore::Error::WithLineNumber { err, .. } => error_path(err),
        ignore::Error::Partial(errs) => errs.iter().find_map(error_path),
        _ => None,
    }
}

fn error_cause(e: &ignore::Error) -> String {
    match e {
        ignore::Error::WithPath { err, .. }
        | ignore::Error::WithDepth { err, .. }
        | ignore::Error::WithLineNumber { err, .. } => error_cause(err),
        other => other.to_string(),
    }
}

/// The path as reports show it: `./` components dropped.
pub fn tidy(p: &Path) -> PathBuf {
    let t: PathBuf = p.components().filter(|c| *c != Component::CurDir).collect();
    if t.as_os_str().is_empty() {
        p.to_path_buf()
    } else {
        t
    }
}

fn is_txt(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("txt"))
}

/// Whether a `.txt` file found in a folder reads as G-code, from its first 4 KiB: most of its
/// first lines (at least half of those with text, and at least one) begin as NC blocks do — `%`,
/// `(`, `;`, `/`, `#`, `:` or `O`, `N`, `G`, `M`, `T`, `X`, `Z` … followed by a number. Notes,
/// logs and READMEs next to programs are then not read as programs. A `.txt` named on the command
/// line is always checked.
fn looks_like_gcode(p: &Path) -> bool {
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    let Ok(f) = std::fs::File::open(p) else {
        return true; // reading it will say why it cannot be read
    };
    if f.take(4096).read_to_end(&mut head).is_err() {
        return true;
    }
    looks_like_gcode_text(&String::from_utf8_lossy(&head))
}

fn looks_like_gcode_text(text: &str) -> bool {
    let (mut nc, mut all) = (0, 0);
    for line in text.lines().map(str::trim).filter(|l| !l.is_empty()).take(40) {
        all += 1;
        let mut c = line.chars();
        let first = c.next().unwrap_or(' ');
        let second = c.find(|c| *c != ' ').unwrap_or(' ');
        let block = matches!(first, '%' | '(' | ';' | '/' | '#' | ':')
            || (first.is_ascii_alphabetic()
                && (second.is_ascii_digit() || matches!(second, '-' | '+' | '.' | '#' | '[')));
        if block {
            nc += 1;
        }
    }
    nc > 0 && nc * 2 >= all
}

pub fn has_extension(p: &Path, exts: &[String]) -> bool {
    p.extension()
        .is_some_and(|e| exts.iter().any(|x| e.eq_ignore_ascii_case(x.as_str())))
}

/// Keep the `index`-th (1-based) of `count` parts: file k of the sorted list goes to part
/// `k mod count + 1`, so the parts differ in size by at most one file.
pub fn shard<T>(files: Vec<T>, index: usize, count: usize) -> Vec<T> {
    files
        .into_iter()
        .enumerate()
        .filter(|(k, _)| k % count == index - 1)
        .map(|(_, f)| f)
        .collect()
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_txt_is_taken_as_a_program_only_when_it_reads_as_g_code() {
        let yes = [
            "%\nO0001\nG21 G99\nG0 X50. Z5.\nM30\n",
            "(part 12)\nN10 G0 X1\nN20 G1 Z-5 F0.1\n",
            "g0 x1\nz2\n",
        ];
        let no = [
            "Setup notes for op 20\nUse soft jaws bored to 49.8\n",
            "",
            "TODO: check the G71 depth\nthen ask Bob\n",
        ];
        for t in yes {
            assert!(super::looks_like_gcode_text(t), "{t:?}");
        }
        for t in no {
            assert!(!super::looks_like_gcode_text(t), "{t:?}");
        }
    }
}
