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
pub mod numbers;
pub mod reading;
pub mod tailstock;
pub mod tools;
pub mod words;

use crate::job::{self, EffectiveJob, JobError, Layer, Place, Set};
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
        summary(&self.notes)
    }

    /// Nothing was assumed: every value is the machine file's.
    pub fn is_empty(&self) -> bool {
        self.notes.iter().all(|n| n.kept)
    }
}

/// The values of `notes` that were assumed (not kept), in one line: `bar Ø50 × 90 mm, 60 mm
/// out of the jaws, T03 boring bar`. Empty when nothing was assumed.
pub fn summary(notes: &[Assumption]) -> String {
    notes
        .iter()
        .filter(|n| !n.kept)
        .map(|n| n.value.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The sentence the reports give a file whose setup was read from the program.
pub fn sentence(notes: &[Assumption]) -> Option<String> {
    let s = summary(notes);
    (!s.is_empty())
        .then(|| format!("setup read from the program: {s}; write a job to fix it (`latheguard setup` shows why)"))
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
    let mut out = Assumed {
        layer: Layer::new(LABEL),
        notes: Vec::new(),
    };
    let switched = dialect(src, file, machine, &mut out);
    let machine = switched.as_ref().unwrap_or(machine);
    let numbered = numbers::assume(src, file, machine, &mut out);
    let machine = numbered.as_ref().unwrap_or(machine);
    let r = reading::Reading::of(src, machine);
    if r.segs.is_empty() {
        // No move reaches the machine: nothing to read, and nothing to check.
        return Assumed {
            layer: Layer::new(LABEL),
            notes: Vec::new(),
        };
    }
    let face = bar::assume(&r, file, machine, &mut out);
    tailstock::assume(&r, file, machine, &mut out);
    tools::assume(&r, file, machine, face, &mut out);
    out
}

/// On a machine whose setup is an example and whose dialect is fixed: the program's own
/// dialect when its signs say so (`machine::auto`). Returns the machine switched to it.
fn dialect(src: &[u8], file: &str, machine: &Machine, out: &mut Assumed) -> Option<Machine> {
    if !machine.assume_setup || machine.auto_dialect.is_some() {
        return None;
    }
    let (d, why) = crate::machine::auto::detect(src);
    // M98/M99 are signs of Fanuc, but LinuxCNC runs them too: not enough to switch on.
    let weak = ["no sign", "tie", "M98", "M99", "`%`"];
    if d == machine.dialect || weak.iter().any(|w| why.contains(w)) {
        return None;
    }
    let choice = match d {
        crate::machine::Dialect::Fanuc => job::DialectChoice::Fanuc,
        crate::machine::Dialect::Linuxcnc => job::DialectChoice::Linuxcnc,
    };
    let mut layer = Layer::new(LABEL);
    layer.dialect = Some(set(choice, file, 0, "dialect"));
    let m = job::apply(machine, &EffectiveJob::merge([&layer])).ok()?;
    out.layer.dialect = layer.dialect;
    out.notes.push(Assumption {
        key: "dialect".into(),
        value: format!("{} dialect", d.as_str()),
        reason: format!("the program is written for it: {}", why.trim_start_matches("auto: ")),
        line: 0,
        kept: false,
    });
    Some(m)
}

impl Assumed {
    /// Drop what a user's layer sets: the bar and program zero go together (a layer that sets
    /// the stock, program zero or G54 takes both), a tool goes with its station.
    pub fn under(mut self, layers: &[&Layer]) -> Assumed {
        let zero_or_stock = layers
            .iter()
            .any(|l| l.stock.is_some() || l.program_zero_z.is_some() || l.work_offsets[0].is_some());
        if zero_or_stock {
            self.layer.stock = None;
            self.layer.program_zero_z = None;
            self.notes.retain(|n| !n.key.starts_with("stock"));
        }
        if layers.iter().any(|l| l.dialect.is_some()) {
            self.layer.dialect = None;
            self.notes.retain(|n| n.key != "dialect");
        }
        if layers
            .iter()
            .any(|l| !l.tool_numbers.is_empty() || l.tool_numbers_table.is_some())
        {
            self.layer.tool_numbers.clear();
            self.notes.retain(|n| n.key != "tool_numbers");
        }
        if layers
            .iter()
            .any(|l| l.tailstock_in_use.is_some() || l.tailstock_z.is_some())
        {
            self.layer.tailstock_in_use = None;
            self.layer.tailstock_z = None;
            self.notes.retain(|n| n.key != "tailstock");
        }
        let stations: Vec<u32> = layers
            .iter()
            .flat_map(|l| l.tools.iter().map(|t| t.value.tool.station))
            .collect();
        self.layer.tools.retain(|t| !stations.contains(&t.value.tool.station));
        self.notes
            .retain(|n| n.station().map_or(true, |s| !stations.contains(&s)));
        self
    }
}

impl Assumption {
    /// The station of a `tools.N` note.
    pub fn station(&self) -> Option<u32> {
        self.key.strip_prefix("tools.").and_then(|s| s.parse().ok())
    }
}

/// The machine the assumed setup gives, and the job it was merged into; or why it does not fit.
pub type Applied = Result<(Machine, EffectiveJob), JobError>;

/// The machine `src` runs on when its setup is read from it: the assumed layer under the
/// user's `layers` (lowest first), applied to `base`. `machine` is `base` with the user's
/// layers applied (what the check runs without an assumption); the program is read on it.
/// `None` when nothing is assumed; `Err` when the assumed setup does not fit the machine (the
/// notes then say so, and the check runs on `machine`).
pub fn apply(
    src: &[u8],
    file: &str,
    base: &Machine,
    machine: &Machine,
    layers: &[&Layer],
) -> (Assumed, Option<Applied>) {
    let a = assume(src, file, machine).under(layers);
    if a.layer.is_empty() {
        return (a, None);
    }
    let eff = EffectiveJob::merge(std::iter::once(&a.layer).chain(layers.iter().copied()));
    let got = job::apply(base, &eff).map(|m| (m, eff));
    (a, Some(got))
}

#[cfg(test)]
mod tests;
