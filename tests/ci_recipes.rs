//! The install recipes (docs/ci.md) hold together: the GitHub Action (`action.yml`), the
//! workflows of `.github/workflows/`, the GitLab template (`ci/gitlab/`) and the YAML of
//! docs/ci.md validate against the schemas their platforms publish (SchemaStore's and GitLab's,
//! vendored in `tests/fixtures/schemas/` with their licences); the pre-commit manifest has the
//! shape pre-commit reads (its `files` pattern against the default extensions: docs_examples.rs); and the action's installer takes a release binary when the release has
//! one and otherwise leaves the build to the action.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn yaml(path: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    yaml_text(&text, &path.display().to_string())
}

fn yaml_text(text: &str, what: &str) -> serde_json::Value {
    serde_yaml_ng::from_str(text).unwrap_or_else(|e| panic!("{what}: not YAML: {e}"))
}

fn validator(schema: &str) -> jsonschema::Validator {
    let path = root().join("tests/fixtures/schemas").join(schema);
    let schema: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    jsonschema::validator_for(&schema).unwrap()
}

fn assert_valid(v: &jsonschema::Validator, doc: &serde_json::Value, what: &str) {
    let errors: Vec<String> = v
        .iter_errors(doc)
        .map(|e| format!("{e} at {}", e.instance_path))
        .collect();
    assert!(errors.is_empty(), "{what}: {errors:#?}");
}

/// The fenced `yaml` blocks of a Markdown page: (line, text).
fn yaml_blocks(page: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(page).unwrap();
    let mut out = Vec::new();
    let mut current: Option<(usize, String)> = None;
    for (i, line) in text.lines().enumerate() {
        match (&mut current, line.trim_start()) {
            (None, l) if l.starts_with("```yaml") => current = Some((i + 1, String::new())),
            (Some(_), l) if l.starts_with("```") => out.push(current.take().unwrap()),
            (Some((_, t)), _) => {
                t.push_str(line);
                t.push('\n');
            }
            _ => {}
        }
    }
    out
}

#[test]
fn the_action_the_workflows_and_the_gitlab_template_validate_against_their_schemas() {
    let action = validator("github-actions.json");
    let workflow = validator("github-workflows.json");
    let gitlab = validator("gitlab-ci.json");
    assert_valid(&action, &yaml(&root().join("action.yml")), "action.yml");
    let mut workflows = 0;
    for e in std::fs::read_dir(root().join(".github/workflows")).unwrap().flatten() {
        assert_valid(&workflow, &yaml(&e.path()), &e.path().display().to_string());
        workflows += 1;
    }
    assert!(workflows >= 2, "the release and ci workflows");
    let template = yaml(&root().join("ci/gitlab/latheguard.gitlab-ci.yml"));
    assert_valid(&gitlab, &template, "ci/gitlab/latheguard.gitlab-ci.yml");
    // The template's job is hidden (a user extends it) and hands GitLab both reports.
    let job = &template[".latheguard"];
    assert_eq!(job["artifacts"]["reports"]["junit"], "latheguard.xml");
    assert_eq!(job["artifacts"]["reports"]["codequality"], "gl-code-quality.json");

    // And the schemas do catch a broken file.
    let mut broken = yaml(&root().join("action.yml"));
    broken["runs"]["using"] = "python".into();
    assert!(!action.is_valid(&broken));
    let mut broken = yaml(&root().join(".github/workflows/release.yml"));
    broken["jobs"]["build"]["steps"] = "not a list".into();
    assert!(!workflow.is_valid(&broken));
}

#[test]
fn every_complete_yaml_recipe_of_the_ci_page_validates() {
    let workflow = validator("github-workflows.json");
    let gitlab = validator("gitlab-ci.json");
    let page = root().join("docs/ci.md");
    let (mut github, mut gl) = (0, 0);
    for (line, text) in yaml_blocks(&page) {
        let what = format!("docs/ci.md:{line}");
        let mut doc = yaml_text(&text, &what);
        if doc.get("jobs").is_some() {
            // A recipe that shows only the jobs of a workflow is validated as a whole one.
            if doc.get("on").is_none() {
                doc["on"] = "push".into();
            }
            assert_valid(&workflow, &doc, &what);
            github += 1;
        } else if doc.get("include").is_some()
            || doc.as_object().is_some_and(|o| {
                o.values()
                    .any(|j| j.get("script").is_some() || j.get("extends").is_some())
            })
        {
            assert_valid(&gitlab, &doc, &what);
            gl += 1;
        } else if doc.get("repos").is_some() {
            // A .pre-commit-config.yaml: the hook this repository defines, at a tag.
            let hooks = &doc["repos"][0]["hooks"];
            assert!(
                hooks.as_array().is_some_and(|h| h
                    .iter()
                    .all(|h| h["id"].as_str().is_some_and(|id| id.starts_with("latheguard")))),
                "{what}"
            );
        } else {
            // A list of steps to paste into a job: each step runs or uses something.
            let steps = doc
                .as_array()
                .unwrap_or_else(|| panic!("{what}: neither a workflow, a GitLab file nor steps"));
            assert!(
                steps.iter().all(|s| s.get("run").is_some() || s.get("uses").is_some()),
                "{what}"
            );
        }
    }
    assert!(
        github >= 2 && gl >= 2,
        "the page's GitHub ({github}) and GitLab ({gl}) recipes"
    );
}

#[test]
fn the_pre_commit_manifest_has_the_hooks_the_docs_name() {
    let hooks = yaml(&root().join(".pre-commit-hooks.yaml"));
    let hooks = hooks.as_array().expect("a list of hooks");
    let ids: Vec<&str> = hooks.iter().map(|h| h["id"].as_str().unwrap()).collect();
    assert_eq!(ids, ["latheguard", "latheguard-system"]);
    let ci = std::fs::read_to_string(root().join("docs/ci.md")).unwrap();
    for h in hooks {
        for key in ["id", "name", "entry", "language", "files"] {
            assert!(h[key].as_str().is_some_and(|v| !v.is_empty()), "{key} of {h}");
        }
        assert!(["rust", "system"].contains(&h["language"].as_str().unwrap()));
        assert!(h["entry"].as_str().unwrap().starts_with("latheguard check"));
        assert!(
            ci.contains(&format!("id: {}", h["id"].as_str().unwrap())),
            "docs/ci.md shows hook {}",
            h["id"]
        );
    }
}

#[test]
fn the_action_documents_every_input_and_output() {
    let action = yaml(&root().join("action.yml"));
    let ci = std::fs::read_to_string(root().join("docs/ci.md")).unwrap();
    for section in ["inputs", "outputs"] {
        for name in action[section].as_object().unwrap().keys() {
            assert!(
                ci.contains(&format!("`{name}`")),
                "docs/ci.md says nothing of the action's {section} `{name}`"
            );
        }
    }
}

/// Runs the action's installer with a runner's environment; returns what it wrote to
/// GITHUB_OUTPUT and GITHUB_PATH.
fn install(dir: &Path, env: &[(&str, &str)]) -> (String, String) {
    let output = dir.join("output");
    let path = dir.join("path");
    let _ = std::fs::remove_file(&output);
    let _ = std::fs::remove_file(&path);
    let temp = dir.join("runner-temp");
    std::fs::create_dir_all(&temp).unwrap();
    let mut cmd = Command::new("bash");
    cmd.arg(root().join("ci/action/install.sh"))
        .env("RUNNER_TEMP", &temp)
        .env("GITHUB_OUTPUT", &output)
        .env("GITHUB_PATH", &path)
        .env("GITHUB_ACTION_PATH", root())
        .env_remove("GITHUB_ACTION_REF")
        .env_remove("LATHEGUARD_VERSION");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    (
        std::fs::read_to_string(&output).unwrap_or_default(),
        std::fs::read_to_string(&path).unwrap_or_default(),
    )
}

#[test]
fn the_action_installs_the_release_binary_when_there_is_one_else_builds() {
    let dir = tempfile::tempdir().unwrap();
    // A release folder laid out as GitHub serves one: TAG/latheguard-TAG-TARGET.tar.gz.
    let releases = dir.path().join("releases");
    let pkg = releases.join("pkg/latheguard-v9.9.9-x86_64-unknown-linux-gnu");
    std::fs::create_dir_all(&pkg).unwrap();
    std::fs::write(pkg.join("latheguard"), "#!/bin/sh\necho latheguard 9.9.9\n").unwrap();
    std::fs::create_dir_all(releases.join("v9.9.9")).unwrap();
    let tar = Command::new("tar")
        .arg("-czf")
        .arg(releases.join("v9.9.9/latheguard-v9.9.9-x86_64-unknown-linux-gnu.tar.gz"))
        .arg("-C")
        .arg(releases.join("pkg"))
        .arg("latheguard-v9.9.9-x86_64-unknown-linux-gnu")
        .status()
        .unwrap();
    assert!(tar.success());
    let base = format!("file://{}", releases.display());
    let linux = [
        ("RUNNER_OS", "Linux"),
        ("RUNNER_ARCH", "X64"),
        ("LATHEGUARD_RELEASES", base.as_str()),
    ];

    // The tag the action is used at has a binary for this runner: it is installed.
    let mut env = linux.to_vec();
    env.push(("GITHUB_ACTION_REF", "v9.9.9"));
    let (out, path) = install(dir.path(), &env);
    assert!(
        out.contains("installed-from=release") && out.contains("version=v9.9.9"),
        "{out}"
    );
    let bin = PathBuf::from(path.trim()).join("latheguard");
    let ran = Command::new(&bin).output().unwrap();
    assert_eq!(String::from_utf8_lossy(&ran.stdout), "latheguard 9.9.9\n");

    // A release without this runner's binary, a branch, a runner with no binaries: source.
    let mut env = linux.to_vec();
    env.push(("LATHEGUARD_VERSION", "v1.0.0"));
    let (out, path) = install(dir.path(), &env);
    assert!(out.contains("installed-from=source") && path.is_empty(), "{out}");
    let mut env = linux.to_vec();
    env.push(("GITHUB_ACTION_REF", "main"));
    let (out, _) = install(dir.path(), &env);
    assert!(out.contains("installed-from=source"), "{out}");
    let (out, _) = install(
        dir.path(),
        &[
            ("RUNNER_OS", "FreeBSD"),
            ("RUNNER_ARCH", "X64"),
            ("LATHEGUARD_VERSION", "v9.9.9"),
            ("LATHEGUARD_RELEASES", base.as_str()),
        ],
    );
    assert!(out.contains("installed-from=source"), "{out}");
    // Every run names a cache key for the build from source.
    assert!(
        out.lines().any(|l| l.starts_with("cache-key=latheguard-FreeBSD-X64-")),
        "{out}"
    );
}
