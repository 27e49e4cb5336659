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
    let manifest = std::fs::read_to_string(root().join(".pre-commit-hooks.yaml")).unwrap();
    let yaml = manifest
        .split("files: (?i)\\.(")
        .nth(1)
        .and_then(|p| p.split(')').next())
        .expect("the hooks' files pattern in .pre-commit-hooks.yaml");
    let mut yaml: Vec<&str> = yaml.split('|').collect();
    yaml.sort();
    assert_eq!(yaml, want, "the pre-commit hooks' files pattern");
}

/// The pages a reader of the repository sees: the README, ARCHITECTURE.md and every page of
/// `docs/` and `docs/findings/`.
fn pages() -> Vec<PathBuf> {
    let mut pages = vec![root().join("README.md"), root().join("ARCHITECTURE.md")];
    for dir in ["docs", "docs/findings"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "md") {
                pages.push(e.path());
            }
        }
    }
    pages.sort();
    pages
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The anchors GitHub gives a page's headings: lower case, letters, digits, `-` and `_` kept,
/// spaces made `-`, everything else dropped; a repeated heading gets `-1`, `-2`, ….
fn anchors(text: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut seen = std::collections::HashMap::<String, usize>::new();
    let mut in_block = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block || !line.starts_with('#') {
            continue;
        }
        let title = line.trim_start_matches('#').trim();
        let slug: String = title
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let n = seen.entry(slug.clone()).or_insert(0);
        out.push(if *n == 0 { slug } else { format!("{slug}-{n}") });
        *n += 1;
    }
    out
}

/// The targets of the Markdown links and images of `text` outside fenced blocks and code spans.
fn link_targets(text: &str) -> Vec<(usize, String)> {
    let mut out = Vec::new();
    let mut in_block = false;
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            in_block = !in_block;
            continue;
        }
        if in_block {
            continue;
        }
        // Drop code spans: a `](` inside backquotes is not a link.
        let plain: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push((i + 1, after[..end].trim().to_string()));
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_relative_link_of_the_readme_and_the_docs_points_to_a_file_that_exists() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        for (line, target) in link_targets(&text) {
            if target.contains("://") || target.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = match target.split_once('#') {
                Some((f, a)) => (f, Some(a)),
                None => (target.as_str(), None),
            };
            let path = if file.is_empty() {
                page.clone()
            } else {
                page.parent().unwrap().join(file)
            };
            checked += 1;
            if !path.exists() {
                broken.push(format!("{name}:{line}: {target}: no such file"));
                continue;
            }
            if let Some(a) = anchor {
                if path.extension().is_some_and(|x| x == "md") {
                    let there = std::fs::read_to_string(&path).unwrap();
                    if !anchors(&there).iter().any(|h| h == a) {
                        broken.push(format!("{name}:{line}: {target}: no heading with that anchor"));
                    }
                }
            }
        }
    }
    assert!(checked >= 20, "found only {checked} relative links");
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

#[test]
fn the_docs_stand_on_their_own_and_the_readme_stays_short() {
    // The team's design brief and the corpora live beside the repository, not in it: no page a
    // reader of a clone sees may send them there. The corpora's place is explained once, for
    // the tests, in docs/testing.md.
    let mut found = Vec::new();
    for page in pages() {
        let text = std::fs::read_to_string(&page).unwrap();
        let name = page.strip_prefix(root()).unwrap().display().to_string();
        for (i, line) in text.lines().enumerate() {
            let shared_ok = name == "docs/testing.md";
            if line.contains("DESIGN") || (!shared_ok && line.contains("../shared")) {
                found.push(format!("{name}:{}: {line}", i + 1));
            }
        }
    }
    let mut sources = Vec::new();
    rust_files(&root().join("src"), &mut sources);
    sources.sort();
    for file in sources {
        let text = std::fs::read_to_string(&file).unwrap();
        let name = file.strip_prefix(root()).unwrap().display().to_string();
        for (i, line) in text.lines().enumerate() {
            let comment = line.trim_start().starts_with("//");
            if comment && (line.contains("DESIGN") || line.contains("../shared")) {
                found.push(format!("{name}:{}: {line}", i + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "references outside the repository:\n{}",
        found.join("\n")
    );

    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 200,
        "README.md has {lines} lines: keep it at most 200 (details go to docs/)"
    );
}

#[test]
fn the_link_helpers_read_what_github_renders() {
    assert_eq!(
        anchors("# A\n## `dialect = \"auto\"`\n```\n# not a heading\n```\n## Editor support: JSON Schema\n## A\n"),
        ["a", "dialect--auto", "editor-support-json-schema", "a-1"]
    );
    let links = link_targets("see [x](a.md#b) and ![p](pic.svg), not `[y](z.md)`\n```\n[q](r.md)\n```\n");
    assert_eq!(links, [(1, "a.md#b".to_string()), (1, "pic.svg".to_string())]);
}
