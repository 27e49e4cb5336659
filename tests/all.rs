//! Every integration test of latheguard, in one test binary (`autotests = false` in Cargo.toml):
//! each file beside this one is a module here, so the library is linked once, not once per file.
//! The command line (`cli_*`, `docs_examples`, `pictures`, …), property tests against oracles
//! (`*_props`), data-driven cases, hostile inputs and turn-mill machines, and the real programs of
//! the corpora (`corpus*`, `mutation`, `rs274_reference`). Run one file's tests with
//! `cargo test --test all cases::`.

#[path = "common/case_machine.rs"]
mod case_machine;
mod common;
#[path = "common/corpus_job.rs"]
mod corpus_job;
#[path = "common/files.rs"]
mod files;
#[path = "common/mutate.rs"]
mod mutate;

mod assumed_setups;
mod cases;
mod ci_recipes;
mod cli_batch;
mod cli_gate;
mod cli_gate_config;
mod cli_graze;
mod cli_hostile;
mod cli_job;
mod cli_machine_file;
mod cli_snapshots;
mod cli_stock_out;
mod cli_tools;
mod comp_props;
mod comp_svg;
mod corpus;
mod corpus_setups;
mod cycle_comp;
mod cycles2_props;
mod cycles_props;
mod depth;
mod depth_cases;
mod docs_examples;
mod exact_props;
mod fidelity;
mod follow;
mod follow_on_props;
mod gap_props;
mod hostile_check;
mod hostile_read;
mod jaws;
mod kin_props;
mod live_drilling;
mod machine_drawings;
mod machine_schema;
mod milling_tools;
mod mutation;
mod operations;
mod paths;
mod paths3d;
mod pictures;
mod polar;
mod render_png;
mod report3d;
mod robustness;
mod rs274_reference;
mod scrape;
mod shifted;
mod stock_instant_props;
mod stock_props;
mod streamed;
mod turn_mill;
mod turn_mill_bhead;
mod work_offsets;

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
    assert_eq!(roots, ["all.rs"], "test binaries declared in Cargo.toml");
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
