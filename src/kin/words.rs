//! What a machinist calls a component of the kinematic machine in a finding's message and a
//! picture's legend: "T08 drill", "T08 live block", "main chuck", not the machine file's ids
//! `t8_drill`, `t8_live_block`, `main_chuck` (the JSON report's `objects` keep the ids).

use super::{Component, Role};
use crate::tooling::Cutter;

/// The words for `c`, without an article (a message writes "the T08 drill hits the main chuck"):
///
/// - its `label` when the machine file gives one;
/// - a tool's part by its station: the cutting part as the station's tool is called (`cutter`,
///   the 2D tool's [`Cutter`] when the machine has a tool there: "T08 drill"), any other part by
///   its name without the `t8_` prefix ("T08 live block");
/// - anything else by its name, underscores read as spaces ("main chuck", "live centre").
pub fn words(c: &Component, cutter: Option<Cutter>) -> String {
    if let Some(label) = c.label.as_deref().map(str::trim).filter(|l| !l.is_empty()) {
        return label.to_string();
    }
    let spaced = |s: &str| s.split('_').filter(|w| !w.is_empty()).collect::<Vec<_>>().join(" ");
    let Some(station) = c.station else {
        return spaced(&c.name);
    };
    let rest = without_station(&c.name, station);
    let part = match (c.role, cutter) {
        (Role::Cutter, Some(cutter)) => cutter.word().to_string(),
        (Role::Cutter, None) => Cutter::from_name(&c.name).word().to_string(),
        _ if rest.is_empty() => "holder".to_string(),
        _ => spaced(rest),
    };
    format!("T{station:02} {part}")
}

/// `name` without its station prefix (`t8_`, `T08_`, `t08-`), or all of it when it has none.
fn without_station(name: &str, station: u32) -> &str {
    let Some(rest) = name.strip_prefix(['t', 'T']) else {
        return name;
    };
    let digits = rest.len() - rest.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    if digits == 0 || rest[..digits].parse::<u32>().ok() != Some(station) {
        return name;
    }
    match rest[digits..].strip_prefix(['_', '-']) {
        Some(r) => r,
        None if digits == rest.len() => "",
        None => name,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn comp(name: &str, role: Role, station: Option<u32>, label: Option<&str>) -> Component {
        Component {
            name: name.into(),
            parent: None,
            mount: super::super::Iso::identity(),
            axis: None,
            geometry: None,
            role,
            station,
            label: label.map(str::to_string),
        }
    }

    #[test]
    fn a_tool_part_is_named_by_its_station_and_the_cutter_by_the_station_tool() {
        let drill = comp("t8_drill", Role::Cutter, Some(8), None);
        assert_eq!(words(&drill, Some(Cutter::Drill)), "T08 drill");
        assert_eq!(words(&drill, None), "T08 drill");
        let cutter = comp("t12_cutter", Role::Cutter, Some(12), None);
        assert_eq!(words(&cutter, Some(Cutter::Mill)), "T12 mill");
        assert_eq!(words(&cutter, None), "T12 insert");
        let block = comp("t8_live_block", Role::Holder, Some(8), None);
        assert_eq!(words(&block, Some(Cutter::Drill)), "T08 live block");
        assert_eq!(
            words(&comp("T08-holder", Role::Holder, Some(8), None), None),
            "T08 holder"
        );
        assert_eq!(words(&comp("t8", Role::Holder, Some(8), None), None), "T08 holder");
        // A prefix of another station is part of the name.
        assert_eq!(
            words(&comp("t3_block", Role::Holder, Some(8), None), None),
            "T08 t3 block"
        );
        assert_eq!(
            words(&comp("head_nose", Role::Holder, Some(1), None), None),
            "T01 head nose"
        );
    }

    #[test]
    fn other_parts_are_named_by_their_name_in_words_or_their_label() {
        assert_eq!(words(&comp("main_chuck", Role::Chuck, None, None), None), "main chuck");
        assert_eq!(
            words(&comp("live_centre", Role::Tailstock, None, None), None),
            "live centre"
        );
        let sub = comp("sub_chuck", Role::Chuck, None, Some("sub-spindle's chuck"));
        assert_eq!(words(&sub, None), "sub-spindle's chuck");
        let blank = comp("turret", Role::Structure, None, Some("  "));
        assert_eq!(words(&blank, None), "turret");
        let labelled_tool = comp("t8_drill", Role::Cutter, Some(8), Some("long drill"));
        assert_eq!(words(&labelled_tool, Some(Cutter::Drill)), "long drill");
    }
}
