use super::insert::{self, Insert, Pitch};
use super::*;
use crate::geom::{locate, Location};

fn spec(insert: Option<&str>, holder: Option<&str>) -> CatalogueSpec {
    CatalogueSpec {
        insert: insert.map(String::from),
        holder: holder.map(String::from),
        drill: None,
    }
}

fn turning(code: &str) -> insert::Iso1832 {
    match insert::parse(code) {
        Ok(Insert::Turning(i)) => i,
        other => panic!("{code}: {other:?}"),
    }
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn debug_print() {
    for (i, h) in [("CNMG 120408", "PCLNR 2525M12"), ("VNMG160404", "MVJNL 2525M16"), ("CCMT 09T304", "S20S-SCLCR09")] {
        let d = decode(&spec(Some(i), Some(h))).unwrap();
        eprintln!("{i} {h}: {:?}\n{:?}\n{:?}", d.tool.insert.points(), d.tool.holder.points(), d.facts);
    }
}
