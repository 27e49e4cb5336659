//! The drawings of the shipped machines in docs/machines/ (`latheguard machine FILE --svg OUT`,
//! shown in docs/machine.md) are current: each equals what the code draws from its machine file
//! now. Run with `UPDATE_EXPECT=1` to rewrite them (then render them, look at them and review
//! the diff).

use latheguard::machine;
use latheguard::report::machine_svg::machine_drawing;
use std::path::PathBuf;

const SHIPPED: &[&str] = &[
    "generic-slant-bed",
    "haas-style-inch",
    "gang-tool",
    "linuxcnc-small-lathe",
    "turn-mill",
];

#[test]
fn docs_machine_drawings_are_current() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut stale = Vec::new();
    for name in SHIPPED {
        let file = format!("machines/{name}.toml");
        let text = std::fs::read_to_string(root.join(&file)).unwrap();
        let dir = root.join("machines");
        let m = machine::from_toml_with(&text, &file, &|n: &str| {
            std::fs::read(dir.join(n)).map_err(|e| e.to_string())
        })
        .unwrap();
        let svg = machine_drawing(&m, &file);
        let out = root.join(format!("docs/machines/{name}.svg"));
        if std::env::var_os("UPDATE_EXPECT").is_some() {
            std::fs::write(&out, &svg).unwrap();
            continue;
        }
        let committed = std::fs::read_to_string(&out).unwrap_or_default();
        if committed != svg {
            stale.push(out.display().to_string());
        }
    }
    assert!(
        stale.is_empty(),
        "stale machine drawings (run `UPDATE_EXPECT=1 cargo test --test all machine_drawings::`): {stale:?}"
    );
}

#[test]
fn every_shipped_machine_is_documented_with_its_drawing() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let doc = std::fs::read_to_string(root.join("docs/machine.md")).unwrap();
    for name in SHIPPED {
        assert!(
            doc.contains(&format!("machines/{name}.svg")),
            "docs/machine.md shows {name}.svg"
        );
    }
}
