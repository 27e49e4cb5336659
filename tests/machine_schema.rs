//! The JSON Schema of machine files (`latheguard machine --schema`, kept in
//! `machines/machine.schema.json` for editors): current, and valid for every shipped machine.

use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn toml_as_json(p: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(p).unwrap();
    let v: toml::Value = toml::from_str(&text).unwrap();
    serde_json::to_value(v).unwrap()
}

#[test]
fn the_committed_schema_is_the_generated_one() {
    let committed = std::fs::read_to_string(root().join("machines/machine.schema.json")).unwrap();
    assert_eq!(
        committed,
        latheguard::machine::schema(),
        "run `cargo run -- machine --schema > machines/machine.schema.json`"
    );
}

#[test]
fn every_shipped_and_test_machine_file_validates_and_a_typo_does_not() {
    let schema: serde_json::Value = serde_json::from_str(&latheguard::machine::schema()).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let mut files = Vec::new();
    for dir in ["machines", "tests/machines", "tests/fixtures/tree/machines"] {
        for e in std::fs::read_dir(root().join(dir)).unwrap().flatten() {
            if e.path().extension().is_some_and(|x| x == "toml") {
                files.push(e.path());
            }
        }
    }
    assert!(files.len() >= 5, "{files:?}");
    for f in &files {
        let doc = toml_as_json(f);
        // Only files the loader accepts must validate (tests/machines holds some broken on purpose).
        let loads = latheguard::machine::from_toml(&std::fs::read_to_string(f).unwrap(), "m").is_ok();
        let errors: Vec<String> = validator
            .iter_errors(&doc)
            .map(|e| format!("{e} at {}", e.instance_path))
            .collect();
        if loads {
            assert!(errors.is_empty(), "{}: {errors:#?}", f.display());
        }
    }
    let mut doc = toml_as_json(&root().join("machines/generic-slant-bed.toml"));
    doc["spindle"]["max_rmp"] = 4000.into();
    assert!(!validator.is_valid(&doc), "an unknown key is refused");
    let mut doc = toml_as_json(&root().join("machines/generic-slant-bed.toml"));
    doc["machine"]["dialect"] = "heidenhain".into();
    assert!(!validator.is_valid(&doc), "an unknown dialect is refused");
    let mut doc = toml_as_json(&root().join("machines/generic-slant-bed.toml"));
    doc["axes"].as_object_mut().unwrap().remove("x");
    assert!(!validator.is_valid(&doc), "a missing required key is refused");
}

#[test]
fn the_configuration_schema_is_current_and_every_fixture_configuration_validates() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_latheguard"))
        .args(["schema", "config"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let generated = String::from_utf8(out.stdout).unwrap();
    let committed = std::fs::read_to_string(root().join("machines/config.schema.json")).unwrap();
    assert_eq!(
        committed, generated,
        "run `cargo run -- schema config > machines/config.schema.json`"
    );
    let schema: serde_json::Value = serde_json::from_str(&generated).unwrap();
    let validator = jsonschema::validator_for(&schema).unwrap();
    let mut n = 0;
    for cell in ["", "cell-b", "cell-c"] {
        let doc = toml_as_json(&root().join("tests/fixtures/tree").join(cell).join("latheguard.toml"));
        let errors: Vec<String> = validator.iter_errors(&doc).map(|e| e.to_string()).collect();
        assert!(errors.is_empty(), "{cell}: {errors:#?}");
        n += 1;
    }
    assert_eq!(n, 3);
    let doc: serde_json::Value = serde_json::json!({"clerance": 0.2});
    assert!(!validator.is_valid(&doc), "a typo is refused");
    let doc: serde_json::Value = serde_json::json!({"mode": "fast"});
    assert!(!validator.is_valid(&doc), "an unknown mode is refused");
}

/// Every machine under `machines/` loads without warnings, and the four realistic lathes of issue
/// 13 are there with the traits each one is shipped for.
#[test]
fn every_shipped_machine_loads_clean_with_its_defining_traits() {
    use latheguard::machine::{from_toml_with, Dialect, MAction, TurretKind};
    let load = |name: &str| {
        let text = std::fs::read_to_string(root().join("machines").join(name)).unwrap();
        // STL files of a [kinematics] section are read beside the machine file.
        let read = |n: &str| std::fs::read(root().join("machines").join(n)).map_err(|e| e.to_string());
        let m = from_toml_with(&text, name, &read).unwrap_or_else(|e| panic!("{e}"));
        assert!(m.warnings.is_empty(), "{name}: {:?}", m.warnings);
        m
    };
    let mut n = 0;
    for e in std::fs::read_dir(root().join("machines")).unwrap().flatten() {
        if e.path().extension().is_some_and(|x| x == "toml") {
            load(e.file_name().to_str().unwrap());
            n += 1;
        }
    }
    assert!(n >= 4, "{n} shipped machines");
    let slant = load("generic-slant-bed.toml");
    assert_eq!((slant.dialect, slant.turret.kind), (Dialect::Fanuc, TurretKind::Drum));
    let haas = load("haas-style-inch.toml");
    assert!(haas.inch, "programs start in G20");
    assert!(haas.tailstock.is_some() && !haas.tailstock_advanced);
    assert_eq!(haas.mcodes.action(21), Some(MAction::TailstockAdvance));
    assert_eq!(haas.mcodes.action(22), Some(MAction::TailstockRetract));
    assert_eq!(haas.mcodes.action(10), Some(MAction::ChuckClose));
    assert_eq!(haas.mcodes.action(11), Some(MAction::ChuckOpen));
    let gang = load("gang-tool.toml");
    assert_eq!(gang.turret.kind, TurretKind::Gang);
    let small = load("linuxcnc-small-lathe.toml");
    assert_eq!(small.dialect, Dialect::Linuxcnc);
    // Home is out of the tailstock's reach: the turret's outline at home ends short of the
    // tailstock's nearest point in z.
    let ts = small.tailstock.as_ref().unwrap().aabb();
    let post = small.turret.outline.aabb();
    assert!(
        small.home.y + post.max.y < ts.min.y,
        "the tool post at home reaches the tailstock"
    );
    assert!(
        small.z.max + post.max.y < ts.min.y,
        "the Z travel reaches the tailstock"
    );
}

/// Every key path of the machine file's JSON Schema (`machine.name`, `axes.x.min`,
/// `tools.station`, …) is named in `docs/machine.md`, in backquotes.
#[test]
fn every_key_of_the_machine_schema_is_documented_in_docs_machine_md() {
    let schema: serde_json::Value = serde_json::from_str(&latheguard::machine::schema()).unwrap();
    let doc = std::fs::read_to_string(root().join("docs/machine.md")).unwrap();
    fn resolve<'a>(schema: &'a serde_json::Value, v: &'a serde_json::Value) -> &'a serde_json::Value {
        let mut v = v;
        loop {
            if let Some(r) = v.get("$ref").and_then(|r| r.as_str()) {
                let name = r.rsplit('/').next().unwrap();
                v = &schema["$defs"][name];
            } else if let Some(any) = v.get("anyOf").and_then(|a| a.as_array()) {
                match any.iter().find(|x| x.get("type") != Some(&"null".into())) {
                    Some(x) => v = x,
                    None => return v,
                }
            } else if v.get("type") == Some(&"array".into()) && v["items"].is_object() {
                v = &v["items"];
            } else {
                return v;
            }
        }
    }
    fn walk(schema: &serde_json::Value, v: &serde_json::Value, path: &str, out: &mut Vec<String>) {
        let v = resolve(schema, v);
        if let Some(props) = v.get("properties").and_then(|p| p.as_object()) {
            for (k, sub) in props {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                out.push(p.clone());
                walk(schema, sub, &p, out);
            }
        }
    }
    let mut keys = Vec::new();
    walk(&schema, &schema, "", &mut keys);
    assert!(keys.len() > 30, "{keys:?}");
    let missing: Vec<&String> = keys
        .iter()
        .filter(|k| {
            // A table is documented by its keys (`axes.x` as `axes.x`, `mcodes` as `[mcodes]`).
            !doc.contains(&format!("`{k}`")) && !doc.contains(&format!("`[{k}]`")) && !doc.contains(&format!("`{k}`,"))
        })
        .collect();
    assert!(missing.is_empty(), "not in docs/machine.md: {missing:?}");
}
