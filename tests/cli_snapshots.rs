//! Snapshots (insta) of every report format over the fixture tree, and of one picture.
//! Run `cargo insta review` (or set `INSTA_UPDATE=always`) after a deliberate change, and read
//! the diff.

use crate::common;

use common::{stdout, Tree};

fn report(t: &Tree, format: &str) -> String {
    let out = t.run(&["check", "--no-timing", "--format", format, "."]);
    assert_eq!(out.status.code(), Some(1));
    stdout(&out)
}

#[test]
fn text_report() {
    insta::assert_snapshot!(report(&Tree::new(), "text"));
}

#[test]
fn json_report() {
    insta::assert_snapshot!(report(&Tree::new(), "json"));
}

#[test]
fn junit_report() {
    insta::assert_snapshot!(report(&Tree::new(), "junit"));
}

#[test]
fn sarif_report() {
    insta::assert_snapshot!(report(&Tree::new(), "sarif"));
}

#[test]
fn picture_of_a_holder_hitting_the_chuck() {
    let t = Tree::new();
    let out = t.run(&["check", "--quiet", "--svg", "pictures", "cell-a/crash_holder.nc"]);
    assert_eq!(out.status.code(), Some(1));
    let svg = std::fs::read_to_string(
        t.path()
            .join("pictures/cell-a__crash_holder.nc.L10.collision.T01-holder.chuck.svg"),
    )
    .unwrap();
    insta::assert_snapshot!(svg);
}

#[test]
fn github_report() {
    insta::assert_snapshot!(report(&Tree::new(), "github"));
}

#[test]
fn gitlab_report() {
    insta::assert_snapshot!(report(&Tree::new(), "gitlab"));
}
