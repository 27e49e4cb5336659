//! Fanuc's chuck and tailstock barrier parameters as a way to give the chuck and tailstock
//! outlines (`[chuck] barrier = { … }`, `[tailstock] barrier = { … }`; docs/machine.md, "Fanuc
//! barrier parameters", has the drawing).
//!
//! The parameters are those of the "chuck and tail stock barrier" of the Fanuc Series 0i-C
//! (parameter manual B-64120EN, parameters 1330–1348) and 21i-B (B-63610EN): the chuck as one jaw
//! (TY, CX, CZ, L, W, L1, W1), the tailstock as three coaxial cylinders with a hole at its front
//! (TZ, L, D, L1, D1, L2, D2, D3). CX, CZ and TZ are in the *workpiece* coordinate system, CX as a
//! diameter; D, D1, D2, D3 are diameters; W and W1 radii. Everything here is in mm; the machine
//! file's `setup.program_zero_z` places the workpiece zero in the spindle frame.
//!
//! What the manuals give as text is the meaning of each symbol; the shape is their figure. Our
//! reading of it, which the docs draw:
//!
//! - Chuck, point A = (CX, CZ) is the corner of the jaw where it meets the workpiece: on the
//!   gripping surface, at the jaw's front face. The jaw is L long (z) and W wide (radially); the
//!   step that holds the work, at A, is L1 long and W1 wide, and the rest of the jaw stands back
//!   L1 from A's face: the jaw's front at A is a step of W1 × L1 standing proud of the rest.
//!   TY = 1 (holds on the outer surface): the jaw lies outward of A (`+x`); TY = 0 (holds on the
//!   inner surface, gripping a bore from inside): inward (`-x`).
//! - Tailstock, point B = (0, TZ) is the front of the tailstock on the spindle axis. From B toward
//!   `+z`: L long at Ø D, then L1 long at Ø D1, then L2 long at Ø D2; the first section has a hole
//!   of Ø D3 through it (the quill's bore, where a centre or the part's end sits).

use crate::geom::{p2, P2};

/// `[chuck] barrier`: mm, CX a diameter, CX/CZ in the workpiece coordinate system.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChuckBarrier {
    /// 0: the jaws hold the part on its inner surface; 1: on its outer surface.
    pub ty: u8,
    pub cx: f64,
    pub cz: f64,
    pub l: f64,
    pub w: f64,
    pub l1: f64,
    pub w1: f64,
}

/// `[tailstock] barrier`: mm, TZ in the workpiece coordinate system, D… diameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TailstockBarrier {
    pub tz: f64,
    pub l: f64,
    pub d: f64,
    pub l1: f64,
    pub d1: f64,
    pub l2: f64,
    pub d2: f64,
    pub d3: f64,
}

/// A barrier whose values give no outline: the key (`l1`, `w`…) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct BarrierError {
    pub key: &'static str,
    pub message: String,
}

fn fail<T>(key: &'static str, message: String) -> Result<T, BarrierError> {
    Err(BarrierError { key, message })
}

impl ChuckBarrier {
    /// The jaw's half section in the spindle frame (`[x, z]`, mm), program Z0 at
    /// `program_zero_z`. Lengths must be positive, the step no larger than the jaw, and a jaw
    /// that holds a bore must not reach across the spindle axis.
    pub fn outline(&self, program_zero_z: f64) -> Result<Vec<P2>, BarrierError> {
        let &ChuckBarrier {
            ty,
            cx,
            cz,
            l,
            w,
            l1,
            w1,
        } = self;
        if ty > 1 {
            return fail(
                "ty",
                format!("TY is 0 (holds on the inner surface) or 1 (on the outer surface), not {ty}"),
            );
        }
        if cx < 0.0 {
            return fail("cx", format!("CX is a diameter: it must not be negative, not {cx}"));
        }
        if l1 > l {
            return fail(
                "l1",
                format!("the holding step (L1 = {l1}) is longer than the jaw (L = {l})"),
            );
        }
        if w1 > w {
            return fail(
                "w1",
                format!("the holding step (W1 = {w1}) is wider than the jaw (W = {w})"),
            );
        }
        let ax = cx / 2.0;
        let az = program_zero_z + cz;
        // +1: the jaw lies outward of A (holds the outer surface); -1: inward.
        let s = if ty == 1 { 1.0 } else { -1.0 };
        if ty == 0 && ax - w < 0.0 {
            return fail(
                "w",
                format!(
                    "a jaw {w} wide (radius) holding a bore of Ø{cx} (CX) reaches {} past the spindle axis",
                    w - ax
                ),
            );
        }
        Ok(vec![
            p2(ax, az),
            p2(ax + s * w1, az),
            p2(ax + s * w1, az - l1),
            p2(ax + s * w, az - l1),
            p2(ax + s * w, az - l),
            p2(ax, az - l),
        ])
    }
}

impl TailstockBarrier {
    /// The tailstock's half section in the spindle frame (`[x, z]`, mm), program Z0 at
    /// `program_zero_z`. Lengths and diameters must be positive and the hole narrower than the
    /// section it runs through.
    pub fn outline(&self, program_zero_z: f64) -> Result<Vec<P2>, BarrierError> {
        let &TailstockBarrier {
            tz,
            l,
            d,
            l1,
            d1,
            l2,
            d2,
            d3,
        } = self;
        if d3 >= d {
            return fail(
                "d3",
                format!("the hole (D3 = Ø{d3}) must be narrower than the front section (D = Ø{d})"),
            );
        }
        let bz = program_zero_z + tz;
        let (z1, z2, z3) = (bz + l, bz + l + l1, bz + l + l1 + l2);
        let mut pts = Vec::with_capacity(10);
        if d3 > 0.0 {
            pts.push(p2(0.0, z1));
            pts.push(p2(d3 / 2.0, z1));
            pts.push(p2(d3 / 2.0, bz));
        } else {
            pts.push(p2(0.0, bz));
        }
        pts.extend([
            p2(d / 2.0, bz),
            p2(d / 2.0, z1),
            p2(d1 / 2.0, z1),
            p2(d1 / 2.0, z2),
            p2(d2 / 2.0, z2),
            p2(d2 / 2.0, z3),
            p2(0.0, z3),
        ]);
        Ok(pts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[(f64, f64)]) -> Vec<P2> {
        v.iter().map(|&(x, z)| p2(x, z)).collect()
    }

    // The worked example of docs/machine.md: a jaw 40 long and 30 wide with a 12 × 8 holding
    // step, gripping Ø50 at Z-3 (program Z0 78 mm in front of the jaw faces).
    const JAW: ChuckBarrier = ChuckBarrier {
        ty: 1,
        cx: 50.0,
        cz: -3.0,
        l: 40.0,
        w: 30.0,
        l1: 12.0,
        w1: 8.0,
    };

    #[test]
    fn chuck_barrier_ty1_jaw_lies_outward_of_point_a() {
        let o = JAW.outline(78.0).unwrap();
        assert_eq!(
            o,
            pts(&[
                (25.0, 75.0),
                (33.0, 75.0),
                (33.0, 63.0),
                (55.0, 63.0),
                (55.0, 35.0),
                (25.0, 35.0)
            ])
        );
    }

    #[test]
    fn chuck_barrier_ty0_jaw_lies_inward_of_point_a() {
        let b = ChuckBarrier {
            ty: 0,
            cx: 120.0,
            ..JAW
        };
        let o = b.outline(78.0).unwrap();
        assert_eq!(
            o,
            pts(&[
                (60.0, 75.0),
                (52.0, 75.0),
                (52.0, 63.0),
                (30.0, 63.0),
                (30.0, 35.0),
                (60.0, 35.0)
            ])
        );
    }

    #[test]
    fn chuck_barrier_refuses_what_gives_no_jaw() {
        let key = |b: ChuckBarrier| b.outline(0.0).unwrap_err().key;
        assert_eq!(key(ChuckBarrier { ty: 2, ..JAW }), "ty");
        assert_eq!(key(ChuckBarrier { cx: -1.0, ..JAW }), "cx");
        assert_eq!(key(ChuckBarrier { l1: 41.0, ..JAW }), "l1");
        assert_eq!(key(ChuckBarrier { w1: 31.0, ..JAW }), "w1");
        // A bore of Ø50 held by a jaw 30 wide: it would cross the axis.
        assert_eq!(key(ChuckBarrier { ty: 0, ..JAW }), "w");
        assert!(
            ChuckBarrier { ty: 0, cx: 60.0, ..JAW }.outline(0.0).is_ok(),
            "exactly on the axis is fine"
        );
    }

    const TAIL: TailstockBarrier = TailstockBarrier {
        tz: 150.0,
        l: 20.0,
        d: 30.0,
        l1: 60.0,
        d1: 50.0,
        l2: 100.0,
        d2: 120.0,
        d3: 12.0,
    };

    #[test]
    fn tailstock_barrier_sections_run_from_point_b_toward_plus_z() {
        let o = TAIL.outline(78.0).unwrap();
        assert_eq!(
            o,
            pts(&[
                (0.0, 248.0),
                (6.0, 248.0),
                (6.0, 228.0),
                (15.0, 228.0),
                (15.0, 248.0),
                (25.0, 248.0),
                (25.0, 308.0),
                (60.0, 308.0),
                (60.0, 408.0),
                (0.0, 408.0)
            ])
        );
    }

    #[test]
    fn tailstock_barrier_without_a_hole_starts_on_the_axis() {
        let o = TailstockBarrier { d3: 0.0, ..TAIL }.outline(0.0).unwrap();
        assert_eq!(o[0], p2(0.0, 150.0));
        assert_eq!(o[1], p2(15.0, 150.0));
        assert_eq!(o.len(), 8);
    }

    #[test]
    fn tailstock_barrier_hole_must_be_narrower_than_the_front() {
        let e = TailstockBarrier { d3: 30.0, ..TAIL }.outline(0.0).unwrap_err();
        assert_eq!(e.key, "d3");
    }

    /// The built-in machine with its `[chuck]` and `[chuck.jaws]` tables replaced by `chuck`.
    fn builtin_with(chuck: &str, tail: &str) -> String {
        let t = crate::machine::BUILTIN_TOML;
        let start = t.find("[chuck]").unwrap();
        let jaws = start + t[start..].find("[chuck.jaws]").unwrap();
        let end = jaws + t[jaws..].find("\n\n").unwrap();
        format!("{}{chuck}\n{tail}{}", &t[..start], &t[end..])
    }

    #[test]
    fn machine_file_chuck_barrier_gives_the_chuck_outline() {
        // The built-in's program Z0 is 78: the jaw of JAW, in the spindle frame.
        let toml = builtin_with(
            "[chuck]\nbarrier = { ty = 1, cx = 50, cz = -3, l = 40, w = 30, l1 = 12, w1 = 8 }",
            "",
        );
        let m = crate::machine::from_toml(&toml, "m.toml").unwrap();
        let want = crate::geom::Polygon::new(&JAW.outline(78.0).unwrap()).unwrap();
        assert_eq!(m.chuck, Some(want));
    }

    #[test]
    fn machine_file_tailstock_barrier_gives_the_tailstock_outline() {
        let toml = builtin_with(
            "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]",
            "[tailstock]\nadvanced = false\nbarrier = { tz = 150, l = 20, d = 30, l1 = 60, d1 = 50, l2 = 100, d2 = 120, d3 = 12 }\n",
        );
        let m = crate::machine::from_toml(&toml, "m.toml").unwrap();
        let want = crate::geom::Polygon::new(&TAIL.outline(78.0).unwrap()).unwrap();
        assert_eq!(m.tailstock, Some(want));
    }

    #[test]
    fn machine_file_barrier_errors_name_the_key() {
        let err = |chuck: &str, tail: &str| {
            crate::machine::from_toml(&builtin_with(chuck, tail), "m.toml")
                .unwrap_err()
                .to_string()
        };
        let e = err(
            "[chuck]\nbarrier = { ty = 1, cx = 50, cz = -3, l = 40, w = 30, l1 = 41, w1 = 8 }",
            "",
        );
        assert!(e.contains("chuck.barrier.l1"), "{e}");
        let e = err(
            "[chuck]\nbarrier = { ty = 3, cx = 50, cz = -3, l = 40, w = 30, l1 = 12, w1 = 8 }",
            "",
        );
        assert!(e.contains("chuck.barrier.ty"), "{e}");
        let e = err(
            "[chuck]\nbarrier = { ty = 1, cx = 50, cz = -3, l = -40, w = 30, l1 = 12, w1 = 8 }",
            "",
        );
        assert!(e.contains("chuck.barrier.l:"), "{e}");
        let e = err(
            "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]\nbarrier = { ty = 1, cx = 50, cz = -3, l = 40, w = 30, l1 = 12, w1 = 8 }",
            "",
        );
        assert!(e.contains("not both"), "{e}");
        let e = err(
            "[chuck]\noutline = [[25, -100], [105, -100], [105, 0], [25, 0]]",
            "[tailstock]\nbarrier = { tz = 150, l = 20, d = 30, l1 = 60, d1 = 50, l2 = 100, d2 = 120, d3 = 40 }\n",
        );
        assert!(e.contains("tailstock.barrier.d3"), "{e}");
        let e = err(
            "[chuck]\nbarrier = { ty = 1, cx = 50, cz = -3, l = 40, w = 30, l1 = 12, w1 = 8, q = 1 }",
            "",
        );
        assert!(e.contains("q"), "{e}");
    }
}
