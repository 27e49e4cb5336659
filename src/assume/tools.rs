//! Each station's tool, read from its comment and from what it does (docs/assume.md, "Tools").

use super::reading::Reading;
use super::Assumed;
use crate::machine::Machine;

/// Read the tool of each station the program uses; `face` is the bar's raw front face in
/// program Z (mm). Adds the assumed tools to `out.layer.tools` and a note for each station.
pub fn assume(_r: &Reading, _file: &str, _machine: &Machine, _face: f64, _out: &mut Assumed) {}
