//! Every shell example of the README, of `docs/*.md` and of the finding pages `docs/findings/*.md`
//! runs, and prints what the page says.
//!
//! An example is a fenced block whose first line starts with `$ `: each `$ ` line is a command,
//! the lines after it (up to the next `$ ` line) are its expected output (standard output, then
//! standard error). Commands run with `sh` in a fresh folder holding copies of `programs/`,
//! `machines/` and the files of `tests/fixtures/docs/`, with this build's `latheguard` first on the
//! `PATH`. In the expected output a line `...` (blanks around it allowed) stands for any number
//! of lines, and a line ending in `...` for any line that starts with the text before it.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

struct Example {
    page: String,
    line: usize,
    command: String,
    expected: Vec<String>,
}

fn examples(page: &Path) -> Vec<Example> {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page.strip_prefix(root()).unwrap().display().to_string();
    let mut out = Vec::new();
    let mut in_block = false;
    let mut block_is_shell = false;
    let mut first = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            first = in_block;
            block_is_shell = false;
            continue;
        }
        if !in_block {
            continue;
        }
        if first {
            block_is_shell = line.starts_with("$ ");
            first = false;
        }
        if !block_is_shell {
            continue;
        }
        if let Some(cmd) = line.strip_prefix("$ ") {
            out.push(Example {
                page: name.clone(),
                line: i + 1,
                command: cmd.to_string(),
                expected: Vec::new(),
            });
        } else if let Some(e) = out.last_mut() {
            e.expected.push(line.to_string());
        }
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap().flatten() {
        let t = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &t);
        } else {
            std::fs::copy(e.path(), &t).unwrap();
        }
    }
}

/// Whether `actual` lines match `expected` lines with `...` wildcards.
fn matches(expected: &[String], actual: &[&str]) -> bool {
    let Some((e, rest)) = expected.split_first() else {
        return actual.is_empty();
    };
    let e_trim = e.trim();
    if e_trim == "..." {
        return (0..=actual.len()).any(|k| matches(rest, &actual[k..]));
    }
    let Some((a, arest)) = actual.split_first() else {
        return false;
    };
    let ok = match e.strip_suffix("...") {
        Some(prefix) => a.starts_with(prefix.trim_end_matches('…')),
        None => a.trim_end() == e.trim_end(),
    };
    ok && matches(rest, arest)
}

#[test]
fn every_shell_example_of_the_readme_and_the_docs_prints_what_the_page_says() {
    let mut pages = vec![root().join("README.md")];
    for dir in ["docs", "docs/findings"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "md") {
                pages.push(e.path());
            }
        }
    }
    pages.sort();
    let exe = PathBuf::from(env!("CARGO_BIN_EXE_latheguard"));
    let path = format!(
        "{}:{}",
        exe.parent().unwrap().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let mut ran = 0;
    let mut failures = Vec::new();
    for page in &pages {
        for ex in examples(page) {
            let dir = tempfile::tempdir().unwrap();
            copy_dir(&root().join("programs"), &dir.path().join("programs"));
            copy_dir(&root().join("machines"), &dir.path().join("machines"));
            copy_dir(&root().join("tests/fixtures/docs"), dir.path());
            let out = Command::new("sh")
                .arg("-c")
                .arg(&ex.command)
                .current_dir(dir.path())
                .env("PATH", &path)
                .env("NO_COLOR", "1")
                .env("CI", "true")
                .output()
                .unwrap();
            let text = format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
            let actual: Vec<&str> = text.lines().collect();
            if !matches(&ex.expected, &actual) {
                failures.push(format!(
                    "{}:{}: `{}` printed:\n{text}\nthe page says:\n{}",
                    ex.page,
                    ex.line,
                    ex.command,
                    ex.expected.join("\n")
                ));
            }
            ran += 1;
        }
    }
    assert!(ran >= 6, "found only {ran} examples");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

#[test]
fn the_wildcards_match_as_documented() {
    let e = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(matches(&e(&["a", "...", "z"]), &["a", "b", "c", "z"]));
    assert!(matches(&e(&["a", "...", "z"]), &["a", "z"]));
    assert!(!matches(&e(&["a", "z"]), &["a", "b", "z"]));
    assert!(matches(&e(&["x: 1; ..."]), &["x: 1; and more"]));
    assert!(!matches(&e(&["x: 1; ..."]), &["x: 2; and more"]));
}

#[test]
fn the_pre_commit_recipes_name_every_default_extension_but_txt() {
    let help = Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["check", "--help"])
        .output()
        .unwrap();
    let help = String::from_utf8_lossy(&help.stdout).to_string();
    let list = help
        .split("[default: ")
        .find(|p| p.starts_with("nc,"))
        .and_then(|p| p.split(']').next())
        .expect("the default extensions in --help")
        .replace(['\n', ' '], "");
    let mut want: Vec<&str> = list.split(',').filter(|e| *e != "txt").collect();
    want.sort();
    let ci = std::fs::read_to_string(root().join("docs/ci.md")).unwrap();
    let mut hook: Vec<&str> = ci
        .split(":(icase)*.")
        .skip(1)
        .map(|p| p.split('\'').next().unwrap())
        .collect();
    hook.sort();
    assert_eq!(hook, want, "the git hook's pathspecs");
    let yaml = ci
        .split("files: '(?i)\\.(")
        .nth(1)
        .and_then(|p| p.split(')').next())
        .unwrap();
    let mut yaml: Vec<&str> = yaml.split('|').collect();
    yaml.sort();
    assert_eq!(yaml, want, "the pre-commit framework's files pattern");
}
