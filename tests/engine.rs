//! The checker on programs: data-driven cases, depths, fidelity of the modes, hostile inputs,
//! turn-mill machines.
//!
//! One test binary of a few (`autotests = false` in Cargo.toml): each file beside this one is a
//! module here, so the library is linked once per group, not once per file.

mod cases;
mod depth;
mod depth_cases;
mod fidelity;
mod hostile_check;
mod hostile_read;
mod live_drilling;
mod milling_tools;
mod polar;
mod robustness;
mod shifted;
mod turn_mill;
mod turn_mill_bhead;

/// With `autotests = false`, a new file in `tests/` runs only once a test binary names it: this
/// fails until it does (or until a new binary is declared in Cargo.toml).
#[test]
fn every_test_file_is_a_module_of_a_declared_test_binary() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let manifest = std::fs::read_to_string(dir.join("../Cargo.toml")).unwrap();
    let roots: Vec<String> = manifest
        .lines()
        .filter_map(|l| l.trim().strip_prefix("path = \"tests/"))
        .filter_map(|l| l.strip_suffix('"'))
        .map(str::to_string)
        .collect();
    assert!(roots.len() >= 4, "test binaries declared in Cargo.toml: {roots:?}");
    let declared: String = roots
        .iter()
        .map(|r| std::fs::read_to_string(dir.join(r)).unwrap())
        .collect();
    let mut missing = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        let Some(stem) = name.strip_suffix(".rs") else { continue };
        if !roots.contains(&name) && !declared.contains(&format!("\nmod {stem};")) {
            missing.push(name);
        }
    }
    assert!(
        missing.is_empty(),
        "test files no test binary declares as a module: {missing:?}"
    );
}
