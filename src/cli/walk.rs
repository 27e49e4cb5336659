//! Which files a `check` covers: the paths given, and NC files found in folders given.

use std::path::{Path, PathBuf};

/// File extensions taken as NC programs when walking a folder (case-insensitive).
pub const NC_EXTENSIONS: &[&str] = &["nc", "ngc", "tap", "cnc", "mpf", "eia", "gcode", "txt"];

/// Files named directly are always checked; folders are walked recursively for NC files.
/// The result is sorted by path and has no duplicates. A path that cannot be listed is kept, so
/// that reading it reports the problem as a finding for that path.
pub fn collect(paths: &[PathBuf]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            walk(p, &mut out, 0);
        } else {
            out.push(p.clone());
        }
    }
    out.sort();
    out.dedup();
    out
}

fn walk(dir: &Path, out: &mut Vec<PathBuf>, depth: usize) {
    if depth > 64 {
        return;
    }
    let Ok(rd) = std::fs::read_dir(dir) else {
        out.push(dir.to_path_buf());
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        let Ok(ft) = e.file_type() else { continue };
        if ft.is_dir() {
            if !p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.')) {
                walk(&p, out, depth + 1);
            }
        } else if is_nc(&p) {
            out.push(p);
        }
    }
}

pub fn is_nc(p: &Path) -> bool {
    p.extension()
        .is_some_and(|e| NC_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}
