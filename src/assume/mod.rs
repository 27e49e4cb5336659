//! The setup read from the program (docs/assume.md): when a program has no job, latheguard
//! reads its bar, program zero and tools from the program itself, the way a setter reads a
//! program before loading the bar, and says what it assumed and why.
//!
//! [`assume`] interprets the program once on the machine (its moves in program coordinates,
//! [`reading::Reading`]), reads the bar and program zero from what the program cuts and how it
//! approaches ([`bar`]), and each station's tool from its comment and what it does ([`tools`]).
//! The result is an ordinary job [`Layer`] (labelled [`LABEL`]) laid under every job layer a
//! user writes, so a job always wins, key by key; and one [`Assumption`] per value, with its
//! reason and the program line it rests on.
//!
//! Where the program gives no evidence, the machine file's setup stays. A machine file's
//! `[stock]`, `[setup]` and `[[tools]]` are the shop's truth unless it says `[setup] assume =
//! true` (an example setup: the built-in machine's); then the program's evidence replaces each
//! value it contradicts, and a value it agrees with stays.
//!
//! The invariant (docs/assume.md, "What an assumption never hides"): the bar is never assumed
//! smaller than the largest diameter the program cuts at feed, so a rapid into the bar at the
//! approach is still found; a tube is assumed only when the first tool that cuts works inside,
//! so a boring bar entering a bore no earlier move made is still found.

pub mod bar;
pub mod reading;
pub mod tools;

use crate::job::{Layer, Place, Set};
use crate::machine::Machine;

/// The label of the assumed layer (what `setup` and the reports name it by).
pub const LABEL: &str = "assumed from the program";

/// One value read from the program: the job key it sets, the value in words, why, and the
/// program line it rests on (0: no single line).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Assumption {
    /// The job key: `stock`, `stock.stick_out`, `program_zero_z`, `tools.3`.
    pub key: String,
    /// The value in words: `bar Ø50 × 90`, `T03 boring bar`.
    pub value: String,
    /// Why: `the first roughing pass cuts at X48. (line 12); rounded up to a stock size`.
    pub reason: String,
    /// 1-based program line of the evidence; 0 when it rests on no single line.
    pub line: u32,
    /// The machine file's value agrees with the program and stays (nothing is laid over it).
    pub kept: bool,
}

/// What [`assume`] read: the layer to lay under the user's job layers, and each value it sets
/// (and each machine value it kept) in words.
#[derive(Clone, Debug, Default)]
pub struct Assumed {
    pub layer: Layer,
    pub notes: Vec<Assumption>,
}

impl Assumed {
    /// One line for the text report, the values assumed (not those kept): `bar Ø50 × 90 mm,
    /// 60 mm out of the jaws, T03 boring bar`. Empty when nothing was assumed.
    pub fn summary(&self) -> String {
        self.notes
            .iter()
            .filter(|n| !n.kept)
            .map(|n| n.value.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Nothing was assumed: every value is the machine file's.
    pub fn is_empty(&self) -> bool {
        self.notes.iter().all(|n| n.kept)
    }
}

/// Where an assumed value was read: the program, its line, the job key it sets.
pub(crate) fn place(file: &str, line: u32, key: &str) -> Place {
    Place {
        file: file.to_string(),
        line,
        col: 1,
        key: key.to_string(),
    }
}

pub(crate) fn set<T>(value: T, file: &str, line: u32, key: &str) -> Set<T> {
    Set {
        value,
        at: place(file, line, key),
        layer: LABEL.to_string(),
    }
}

/// Read the setup of `src` (shown as `file`) on `machine`: the assumed layer and its notes.
/// Empty when the program gives no evidence or the machine's setup is not to be replaced.
pub fn assume(src: &[u8], file: &str, machine: &Machine) -> Assumed {
    let r = reading::Reading::of(src, machine);
    let mut out = Assumed {
        layer: Layer::new(LABEL),
        notes: Vec::new(),
    };
    let face = bar::assume(&r, file, machine, &mut out);
    tools::assume(&r, file, machine, face, &mut out);
    out
}
