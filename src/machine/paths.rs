//! `[[paths]]` and `[sync]`: the tool carriers of a multi-path control (a twin-turret lathe: the
//! upper turret run by path 1, the lower by path 2) and the M codes at which the paths wait for
//! each other (docs/paths.md).
//!
//! Path 1 is the machine file's own `[axes]`, `[turret]` and `[[tools]]`. Each `[[paths]]` entry
//! is one more carrier with the same three keys, read by the same functions (its errors name
//! `paths[i].…`), standing across the spindle axis from path 1's turret unless it says
//! `side = "same"`. Everything else — spindle, chuck, tailstock, stock, setup, M and G codes,
//! dialect — is the machine's, shared by every path. [`Machine::for_path`] is the lathe a path's
//! program runs on: the machine with that path's carrier.

use std::borrow::Cow;

use schemars::JsonSchema;
use serde::Deserialize;
use toml::Spanned;

use super::load::{axes_of, clear_at_home, tools_given, tools_of, turret_of, Cx, RawAxes, RawTool, RawTurret};
use super::{Machine, MachineError, Tool, Turret};
use crate::geom::P2;

/// At most this many paths (the machine's own and three more).
pub const MAX_PATHS: usize = 4;

/// One `[[paths]]` entry.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawPath {
    /// What reports call this carrier ("lower turret").
    #[schemars(with = "String")]
    name: Spanned<String>,
    /// Where the carrier stands: `"opposite"` (default) across the spindle axis from path 1's
    /// turret, its +X pointing the other way; `"same"` on path 1's side.
    side: Option<RawSide>,
    axes: RawAxes,
    turret: RawTurret,
    #[schemars(with = "Vec<RawTool>")]
    tools: Spanned<Vec<Spanned<RawTool>>>,
}

#[derive(Deserialize, JsonSchema, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "lowercase", expecting = "\"opposite\" or \"same\"")]
enum RawSide {
    Opposite,
    Same,
}

/// `[sync]`: how the paths meet.
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, expecting = "a table")]
pub(super) struct RawSync {
    /// The waiting M codes, `[first, last]` (default `[100, 999]`).
    #[schemars(with = "Option<[u32; 2]>")]
    wait_mcodes: Option<Spanned<Vec<i64>>>,
    /// What reports call path 1's carrier, the machine's own `[turret]` (default "turret of
    /// path 1"; "milling head").
    #[schemars(with = "Option<String>")]
    first: Option<Spanned<String>>,
}

/// The tool carrier of one path after the first: what replaces the machine's axes, turret and
/// tools when that path's program runs.
#[derive(Clone, Debug, PartialEq)]
pub struct Carrier {
    /// The path's number, from 2.
    pub path: u32,
    pub name: String,
    /// It stands across the spindle axis from path 1's turret (its +X the other way).
    pub opposite: bool,
    pub x: super::Axis,
    pub z: super::Axis,
    pub home: P2,
    pub machine_zero: P2,
    pub reference_points: Vec<P2>,
    pub turret: Turret,
    pub tools: Vec<Tool>,
}

/// The paths of a machine: the carriers after the first and the waiting M codes.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Paths {
    pub carriers: Vec<Carrier>,
    /// The waiting M codes, `first ..= last`; `None` on a one-path machine.
    pub wait_mcodes: Option<(u16, u16)>,
    /// How many paths the whole machine has (kept by [`Machine::for_path`], whose lathe has no
    /// further carriers: a wait without `P` still names them all).
    pub total: u32,
    /// What reports call path 1's carrier (`[sync] first`).
    pub first: String,
}

impl Paths {
    /// How many paths the machine runs (1 without `[[paths]]`).
    pub fn count(&self) -> usize {
        (1 + self.carriers.len()).max(self.total as usize)
    }

    /// Whether `code` is a waiting M code of this machine.
    pub fn is_wait(&self, code: u16) -> bool {
        self.wait_mcodes.is_some_and(|(a, b)| (a..=b).contains(&code))
    }
}

impl Machine {
    /// The lathe path `path` (from 1) runs on: this machine with that path's carrier (its axes,
    /// turret and tools); path 1 is the machine itself. `None` for a path the machine does not
    /// have.
    pub fn for_path(&self, path: u32) -> Option<Cow<'_, Machine>> {
        if self.paths.carriers.is_empty() {
            return (path == 1).then_some(Cow::Borrowed(self));
        }
        let c = self.paths.carriers.iter().find(|c| c.path == path);
        if path != 1 && c.is_none() {
            return None;
        }
        let mut m = self.clone();
        // The lathe of one path: its waits stay waiting M codes, it has no further carriers;
        // its kinematic tree has the parts its own axes move (`Kinematics::for_path`).
        m.paths.carriers.clear();
        if let Some(k) = &self.kinematics {
            m.kinematics = Some(std::sync::Arc::new(k.for_path(path)));
        }
        let Some(c) = c else {
            return Some(Cow::Owned(m));
        };
        m.x = c.x;
        m.z = c.z;
        m.home = c.home;
        m.machine_zero = c.machine_zero;
        m.reference_points = c.reference_points.clone();
        m.turret = c.turret.clone();
        m.tools = c.tools.clone();
        m.tool_changes.clear();
        m.tool_numbers.clear();
        // The work offsets and program zero are the machine's: the part is the same for every
        // path.
        Some(Cow::Owned(m))
    }
}

/// Read `[[paths]]` and `[sync]` once the machine's own sections are valid (`base`).
pub(super) fn paths_of(
    cx: &Cx<'_>,
    raw: Option<Spanned<Vec<Spanned<RawPath>>>>,
    sync: Option<Spanned<RawSync>>,
    base: &Machine,
    mcodes_given: &[i64],
) -> Result<Paths, MachineError> {
    let Some(raw) = raw else {
        if let Some(s) = sync {
            return Err(cx.err(
                s.span(),
                "sync",
                "[sync] without [[paths]]: a one-path machine has nothing to wait for",
            ));
        }
        return Ok(Paths::default());
    };
    let span = raw.span();
    let raw = raw.into_inner();
    if raw.is_empty() {
        return Err(cx.err(
            span,
            "paths",
            "paths is empty: give one [[paths]] table per path after the first, or none",
        ));
    }
    if raw.len() + 1 > MAX_PATHS {
        return Err(cx.err(
            raw[MAX_PATHS - 1].span(),
            format!("paths[{}]", MAX_PATHS - 1),
            format!(
                "{} paths: a machine file may describe at most {MAX_PATHS}",
                raw.len() + 1
            ),
        ));
    }
    let wait_mcodes = match sync.as_ref().and_then(|s| s.get_ref().wait_mcodes.as_ref()) {
        None => (100, 999),
        Some(w) => match w.get_ref().as_slice() {
            &[a, b] if (0..=9999).contains(&a) && (a..=9999).contains(&b) => (a as u16, b as u16),
            _ => {
                return Err(cx.err(
                    w.span(),
                    "sync.wait_mcodes",
                    "wait_mcodes is [first, last]: two M code numbers, 0 to 9999, the first not above the last",
                ))
            }
        },
    };
    if let Some(code) =
        (wait_mcodes.0..=wait_mcodes.1).find(|&c| mcodes_given.contains(&i64::from(c)) || super::mcodes_reserved(c))
    {
        return Err(cx.err(
            sync.as_ref().map_or(span.clone(), |s| s.span()),
            "sync.wait_mcodes",
            format!(
                "the waiting M codes M{} to M{} include M{code}, which the machine file's [mcodes] or the control gives another meaning (the waiting codes take precedence over the dialect's built-in table, not over [mcodes])",
                wait_mcodes.0, wait_mcodes.1
            ),
        ));
    }
    let mut carriers = Vec::new();
    for (i, entry) in raw.into_iter().enumerate() {
        let e = entry.into_inner();
        let prefix = format!("paths[{i}].");
        let carrier = cx.prefixed(&prefix, || {
            let ax = axes_of(cx, &e.axes);
            let (stations, turret) = turret_of(cx, &e.turret);
            let tools = tools_given(cx, Some(e.tools))?;
            let out = tools_of(cx, &tools, stations, ax.machine_zero);
            if let Some(err) = cx.kept() {
                return Err(err);
            }
            let (Some(x), Some(z), Some(home), Some(machine_zero), Some(reference_points), Some(turret)) =
                (ax.x, ax.z, ax.home, ax.machine_zero, ax.reference_points, turret)
            else {
                return Err(cx.err(0..0, "", "invalid path"));
            };
            let carrier = Carrier {
                path: i as u32 + 2,
                name: e.name.get_ref().trim().to_string(),
                opposite: e.side != Some(RawSide::Same),
                x,
                z,
                home,
                machine_zero,
                reference_points,
                turret,
                tools: out,
            };
            // Its tools clear the chuck and the tailstock where the carrier stands at home.
            let view = Machine {
                x,
                z,
                home,
                machine_zero,
                turret: carrier.turret.clone(),
                tools: carrier.tools.clone(),
                ..base.clone()
            };
            clear_at_home(cx, &view, &e.turret.outline, &tools);
            match cx.kept() {
                Some(err) => Err(err),
                None => Ok(carrier),
            }
        })?;
        if carrier.name.is_empty() {
            return Err(cx.err(
                e.name.span(),
                format!("{prefix}name"),
                "name is blank: say what the carrier is (\"lower turret\")",
            ));
        }
        carriers.push(carrier);
    }
    let first = match sync.as_ref().and_then(|s| s.get_ref().first.as_ref()) {
        None => "turret of path 1".to_string(),
        Some(n) if n.get_ref().trim().is_empty() => {
            return Err(cx.err(
                n.span(),
                "sync.first",
                "first is blank: say what path 1's carrier is (\"milling head\")",
            ))
        }
        Some(n) => n.get_ref().trim().to_string(),
    };
    Ok(Paths {
        total: 1 + carriers.len() as u32,
        carriers,
        wait_mcodes: Some(wait_mcodes),
        first,
    })
}
