//! Tools from their catalogue names: ISO 1832 insert designations (`CNMG 120408`), ISO 5608
//! holder designations (`PCLNR 2525M12`), ISO 6261 boring bars (`S20S-SCLCR09`), grooving and
//! threading inserts, drills by diameter and length; and LinuxCNC tool tables (`.tbl`).
//!
//! The outlines built here are in the frame of a machine file's `[[tools]]` entry: relative to
//! the programmed point (the tool tip, at the origin), `x` = radius direction (+x toward the
//! turret), `z` along the spindle axis (+z toward the tailstock). Pure functions: no I/O.
//!
//! (Interface fixed first so that the job module can build against it; the decoders fill it in.)

use crate::geom::Polygon;

pub mod tbl;

/// A drill given by its sizes (no ISO code): it points toward the chuck (-z) on the spindle axis.
#[derive(Clone, Debug, PartialEq)]
pub struct DrillSpec {
    /// mm, > 0.
    pub diameter: f64,
    /// Flute (cutting) length, mm, > 0.
    pub length: f64,
    /// Point angle in degrees (118 when not given; 180 for a flat-bottom drill).
    pub point_angle: Option<f64>,
}

/// What a tool entry gives in catalogue form. At least one of the three is given; `insert` and
/// `holder` go together for turning tools (a holder alone implies its insert's shape and size).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CatalogueSpec {
    /// ISO 1832 insert designation, e.g. `"CNMG 120408"`, `"VNMG160404"`, `"16ER 1.5ISO"`.
    pub insert: Option<String>,
    /// ISO 5608 holder (`"PCLNR 2525M12"`) or ISO 6261 boring bar (`"S20S-SCLCR09"`).
    pub holder: Option<String>,
    pub drill: Option<DrillSpec>,
}

/// The geometry a catalogue tool stands for, in a `[[tools]]` entry's frame.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltTool {
    /// The cutting part: may cut stock at feed.
    pub insert: Polygon,
    /// Everything behind it up to the turret: must never touch.
    pub holder: Polygon,
    pub nose_radius: f64,
    /// Imaginary-tip direction 0–9 (docs/comp.md), as a rear-turret Fanuc chart reads it.
    pub tip_direction: u8,
    /// One line for `latheguard setup`: what the codes were read as (`80° rhombic, 12.9 mm
    /// IC, r0.8, 95° right-hand holder, 25 × 25 shank, 150 mm`).
    pub summary: String,
}

/// A designation that cannot be used: which of `insert`, `holder`, `drill` and why.
#[derive(Clone, Debug, PartialEq)]
pub struct CatalogueError {
    /// `"insert"`, `"holder"` or `"drill"`.
    pub key: &'static str,
    pub message: String,
}

/// Decode the designations and build the tool's outlines.
pub fn build(spec: &CatalogueSpec) -> Result<BuiltTool, CatalogueError> {
    let key = if spec.insert.is_some() {
        "insert"
    } else if spec.holder.is_some() {
        "holder"
    } else {
        "drill"
    };
    Err(CatalogueError {
        key,
        message: "catalogue tools are not built yet".into(),
    })
}
