//! Drills by their sizes: diameter, flute length, point angle.

use super::outline::polygon;
use super::{finish, fmt_mm, Decoded, DrillSpec};
use crate::geom::P2;

/// Largest drill diameter read, mm.
pub const MAX_DIAMETER: f64 = 500.0;
/// Longest flute read, mm.
pub const MAX_LENGTH: f64 = 2000.0;

/// The drill on the spindle axis, its point at the programmed point and its flutes toward +z
/// (it drills toward the chuck): the insert is the fluted part with its point, the holder a
/// shank of the same diameter behind it, max(3 D, 30 mm) long.
pub fn build(d: &DrillSpec) -> Result<Decoded, String> {
    if !(d.diameter.is_finite() && d.diameter > 0.0 && d.diameter <= MAX_DIAMETER) {
        return Err(format!(
            "diameter is {}; expected 0 < diameter <= {MAX_DIAMETER} mm",
            d.diameter
        ));
    }
    if !(d.length.is_finite() && d.length > 0.0 && d.length <= MAX_LENGTH) {
        return Err(format!(
            "length is {}; expected 0 < length <= {MAX_LENGTH} mm",
            d.length
        ));
    }
    let angle = d.point_angle.unwrap_or(118.0);
    if !(angle.is_finite() && (60.0..=180.0).contains(&angle)) {
        return Err(format!("point_angle is {angle}; expected 60 to 180 degrees"));
    }
    let r = d.diameter / 2.0;
    let point = r / (angle / 2.0).to_radians().tan();
    if point >= d.length {
        return Err(format!(
            "the point ({} mm long at {}°) is longer than the flutes ({} mm)",
            fmt_mm(point),
            fmt_mm(angle),
            fmt_mm(d.length)
        ));
    }
    let ins = [
        P2::new(0.0, 0.0),
        P2::new(r, point),
        P2::new(r, d.length),
        P2::new(-r, d.length),
        P2::new(-r, point),
    ];
    let shank = (3.0 * d.diameter).max(30.0);
    let hold = [
        P2::new(-r, d.length),
        P2::new(r, d.length),
        P2::new(r, d.length + shank),
        P2::new(-r, d.length + shank),
    ];
    let insert = polygon("drill", &ins)?;
    let holder = polygon("drill shank", &hold)?;
    let facts = vec![
        ("kind", "drill, on the spindle axis, pointing toward the chuck".into()),
        ("diameter", format!("{} mm", fmt_mm(d.diameter))),
        ("flute length", format!("{} mm", fmt_mm(d.length))),
        ("point angle", format!("{}°", fmt_mm(angle))),
        ("shank", format!("Ø{} mm, {} mm", fmt_mm(d.diameter), fmt_mm(shank))),
        ("tip direction", "0".into()),
    ];
    let summary = format!(
        "drill Ø{}, {} mm flutes, {}° point",
        fmt_mm(d.diameter),
        fmt_mm(d.length),
        fmt_mm(angle)
    );
    Ok(finish(insert, holder, 0.0, 0, summary, facts))
}
