//! The machine description: TOML (DESIGN §3) → a validated [`Machine`].
//!
//! All lengths are mm in the spindle frame: `x` is a radius (distance from the spindle axis, `+x`
//! toward the turret), `z` runs along the spindle axis with `z = 0` at the jaw faces.
//! Outlines are normalised [`Polygon`]s.

mod load;

use crate::geom::{Polygon, P2};

pub use load::{from_toml, MachineError};

/// The built-in machine's TOML, embedded in the binary.
pub const BUILTIN_TOML: &str = include_str!("../../machines/generic-slant-bed.toml");
pub const BUILTIN_NAME: &str = "machines/generic-slant-bed.toml";

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dialect {
    Fanuc,
    Linuxcnc,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RapidMode {
    /// Each axis at its own rapid rate: the path bends.
    Dogleg,
    /// Both axes interpolated along the straight line.
    Linear,
}

/// Fanuc: how a number without a decimal point is read for length words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecimalPoint {
    /// `X60` = 60 mm.
    Calculator,
    /// `X60` = 60 least increments (0.001 mm, 0.0001 in).
    Increment,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    pub min: f64,
    pub max: f64,
    /// mm/min
    pub rapid: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Stock {
    pub diameter: f64,
    pub length: f64,
    /// z of the front face.
    pub front: f64,
    /// Inner diameter of a tube; 0 for a bar.
    pub bore: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Turret {
    pub stations: u32,
    pub start_station: u32,
    /// The turret's axis lies this far from the reference point in +x, parallel to z.
    pub axis: f64,
    /// Seconds per station indexed.
    pub index_time: f64,
    /// Relative to the turret reference point.
    pub outline: Polygon,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Tool {
    pub station: u32,
    pub name: String,
    /// Programmed point relative to the turret reference point.
    pub tip: P2,
    /// Relative to the programmed point.
    pub insert: Polygon,
    /// Relative to the programmed point.
    pub holder: Polygon,
    pub nose_radius: f64,
}

/// A validated machine and its setup.
#[derive(Clone, Debug, PartialEq)]
pub struct Machine {
    pub name: String,
    pub dialect: Dialect,
    pub diameter_mode: bool,
    pub rapid: RapidMode,
    pub decimal_point: DecimalPoint,
    pub x: Axis,
    pub z: Axis,
    /// Turret reference point at program start and after a return home.
    pub home: P2,
    pub max_rpm: f64,
    /// Revolved outline in the half plane x ≥ 0.
    pub chuck: Option<Polygon>,
    pub tailstock: Option<Polygon>,
    pub stock: Option<Stock>,
    pub program_zero_z: f64,
    pub turret: Turret,
    /// Sorted by station.
    pub tools: Vec<Tool>,
}

impl Machine {
    /// The machine embedded in the binary.
    pub fn builtin() -> Machine {
        from_toml(BUILTIN_TOML, BUILTIN_NAME).expect("the built-in machine is valid")
    }

    pub fn tool(&self, station: u32) -> Option<&Tool> {
        self.tools.iter().find(|t| t.station == station)
    }
}
