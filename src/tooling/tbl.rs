//! LinuxCNC tool tables (`.tbl`): one tool a line, `T<n> P<pocket> X Z D I J Q ;comment`.

/// One line of a tool table, as written (lengths in the table's units, angles in degrees).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TblTool {
    pub tool: u32,
    pub pocket: u32,
    /// X offset (LinuxCNC lathe tables give it as written; see the decoder's docs for its sense).
    pub x: f64,
    pub z: f64,
    /// Tool diameter (D): twice the nose radius for a lathe tool.
    pub diameter: f64,
    /// Front angle I, back angle J (degrees), orientation Q (0–9).
    pub front_angle: f64,
    pub back_angle: f64,
    pub orientation: u8,
    pub comment: String,
}

/// A table that cannot be read: 1-based line and column, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct TblError {
    pub line: usize,
    pub col: usize,
    pub message: String,
}

/// Read a tool table.
pub fn parse(_text: &str) -> Result<Vec<TblTool>, TblError> {
    Err(TblError {
        line: 1,
        col: 1,
        message: "tool tables are not read yet".into(),
    })
}

/// The outlines a table line stands for (insert from the front and back angles and the nose
/// radius, a generic holder behind it).
pub fn shape(t: &TblTool) -> Result<super::BuiltTool, super::CatalogueError> {
    let _ = t;
    Err(super::CatalogueError {
        key: "insert",
        message: "tool tables are not shaped yet".into(),
    })
}
