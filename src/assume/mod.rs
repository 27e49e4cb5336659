//! The setup read from the program (docs/assume.md): when a program has no job, latheguard
//! reads its bar, program zero and tools from the program itself, the way a setter reads a
//! program before loading the bar, and says what it assumed and why.
//!
//! [`assume`] interprets the program once on the machine (its moves in program coordinates,
//! [`reading::Reading`]), reads the bar and program zero from what the program cuts and how it
//! approaches ([`bar`]), and each station's tool from its comment and what it does ([`tools`]).
//! The result is an ordinary job [`Layer`] (labelled [`LABEL`]), applied as a job is, and one
//! [`Assumption`] per value, with its reason and the program line it rests on. Only a program
//! with no job is read: a job, even of one key, says the setup is written down.
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
pub mod segs;
pub mod tailstock;
pub mod tools;
pub mod words;

use crate::job::{self, EffectiveJob, Layer, Place, Set};
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
    if crate::paths::is_multi_path(src, machine) {
        // Several paths drive several carriers: a tool read from one path's lines is not the
        // station of another's turret, and the bar is the machine file's (docs/paths.md).
        return out;
    }
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
    let weak_why = |why: &str| weak.iter().any(|w| why.contains(w));
    if d == machine.dialect || weak_why(&why) || speaks_linuxcnc(src, machine) {
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

/// On a LinuxCNC machine, a program that talks to the operator in LinuxCNC's own comments
/// (`(MSG, load tool 3)`, `(DEBUG, …)`, `(PRINT, …)`) is written for it, whatever program number
/// heads it: a Fanuc control shows no such message.
fn speaks_linuxcnc(src: &[u8], machine: &Machine) -> bool {
    machine.dialect == crate::machine::Dialect::Linuxcnc
        && String::from_utf8_lossy(src).lines().any(|l| {
            let (_, c) = words::split_comment(l);
            let c = c.to_ascii_uppercase();
            ["MSG,", "DEBUG,", "PRINT,"].iter().any(|k| c.starts_with(k))
        })
}

impl Assumption {
    /// The station of a `tools.N` note.
    pub fn station(&self) -> Option<u32> {
        self.key.strip_prefix("tools.").and_then(|s| s.parse().ok())
    }
}

/// What a program with no job is checked on: the machine with the setup read from it (and the
/// job that setup makes), or `None` when nothing was read or what was read does not fit the
/// machine; and the notes, each value with its reason (with a last note saying why, when it did
/// not fit).
pub struct Applied {
    pub machine: Option<(Machine, EffectiveJob)>,
    pub notes: Vec<Assumption>,
}

/// Read the setup of `src` (shown as `file`) on `machine`, a machine with no job applied, and
/// apply it (`job::apply`, validated as any job is).
pub fn apply(src: &[u8], file: &str, machine: &Machine) -> Applied {
    let a = assume(src, file, machine);
    if a.layer.is_empty() {
        return Applied {
            machine: None,
            notes: a.notes,
        };
    }
    let eff = EffectiveJob::merge([&a.layer]);
    match job::apply(machine, &eff) {
        Ok(m) => Applied {
            machine: Some((m, eff)),
            notes: a.notes,
        },
        Err(e) => {
            let mut notes = a.notes;
            notes.retain(|n| n.kept);
            notes.push(Assumption {
                key: "setup".into(),
                value: "the machine file's setup".into(),
                reason: format!(
                    "the setup read from the program does not fit the machine ({}): write a job",
                    e.message
                ),
                line: 0,
                kept: true,
            });
            Applied { machine: None, notes }
        }
    }
}

#[cfg(test)]
mod tests;
