//! Helpers for the tests that run the `latheguard` binary on a copy of `tests/fixtures/tree`.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's root (the crate's manifest folder).
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A machine file of the repository (`machines/twin-turret.toml`), with its STL parts beside it.
pub fn repo_machine(rel: &str) -> latheguard::machine::Machine {
    let path = root().join(rel);
    let dir = path.parent().unwrap().to_path_buf();
    let text = std::fs::read_to_string(&path).unwrap();
    latheguard::machine::from_toml_with(&text, rel, &move |name: &str| {
        std::fs::read(dir.join(name)).map_err(|e| e.to_string())
    })
    .unwrap()
}

pub fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let target = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &target);
        } else {
            std::fs::copy(e.path(), &target).unwrap();
        }
    }
}

/// A copy of the fixture tree in a fresh temporary folder, with what git cannot keep: a link to
/// nothing (an unreadable program), a `.gitignore`d folder and a hidden folder with a crashing
/// program each, and a `.latheguardignore`d file.
pub struct Tree {
    pub dir: tempfile::TempDir,
}

impl Tree {
    pub fn new() -> Tree {
        let dir = tempfile::Builder::new().prefix("latheguard-tree").tempdir().unwrap();
        copy_dir(&fixtures().join("tree"), dir.path());
        let root = dir.path();
        std::os::unix::fs::symlink("no-such-program.nc", root.join("cell-a/unreadable.nc")).unwrap();
        let crash = std::fs::read(root.join("cell-a/crash_holder.nc")).unwrap();
        std::fs::write(root.join("cell-a/.gitignore"), "scratch/\n").unwrap();
        std::fs::create_dir_all(root.join("cell-a/scratch")).unwrap();
        std::fs::write(root.join("cell-a/scratch/ignored.nc"), &crash).unwrap();
        std::fs::create_dir_all(root.join(".hidden")).unwrap();
        std::fs::write(root.join(".hidden/ignored.nc"), &crash).unwrap();
        std::fs::write(root.join(".latheguardignore"), "cell-c/old-*.ngc\n").unwrap();
        std::fs::write(root.join("cell-c/old-crash.ngc"), &crash).unwrap();
        Tree { dir }
    }

    pub fn path(&self) -> &Path {
        self.dir.path()
    }

    /// `latheguard ARGS` run in the tree's folder.
    pub fn run(&self, args: &[&str]) -> Output {
        latheguard(self.path(), args)
    }
}

pub fn latheguard(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(args)
        .current_dir(cwd)
        .env_remove("NO_COLOR")
        .env_remove("LATHEGUARD_DOCS_URL")
        .env("CI", "true")
        .output()
        .unwrap()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn json(o: &Output) -> serde_json::Value {
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("not JSON ({e}): {}", stdout(o)))
}
