//! Walking the shared corpora (`../shared/corpus`, `../shared/corpus-extra`), for the tests that
//! read them.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// `../shared` beside the repository: the corpora, kept out of it.
pub fn shared() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared")
}

/// Every file below `dir` that `keep` accepts, depth first in directory order (an unreadable or
/// missing folder gives nothing).
pub fn walk(dir: &Path, keep: &dyn Fn(&Path) -> bool, out: &mut Vec<PathBuf>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if p.is_dir() {
            walk(&p, keep, out);
        } else if keep(&p) {
            out.push(p);
        }
    }
}

/// A corpus file that is a program, not the notes and tables beside the programs.
pub fn is_program(p: &Path) -> bool {
    let name = p.file_name().unwrap_or_default().to_string_lossy().to_lowercase();
    !(name == "expected" || name.ends_with(".md") || name.ends_with(".tbl") || name == "result")
}
