//! The chuck by what it is made of: a body and the jaws that grip the part (`[chuck] body = { … }`
//! and `[chuck.jaws]`; docs/machine.md, "The chuck as body and jaws", has the drawing).
//!
//! The three (or more) jaws are discrete blocks, but the spindle turns them: what a tool in the
//! working plane can hit is their *revolved envelope*, the half section swept by every jaw. So a
//! jaw here is its half section in `[x, z]` (x the radius), and the chuck is the union of the
//! body's section and the jaws' section: one simple outline, as a hand-drawn `outline` is.
//!
//! - The body: a ring `bore / 2 ..= diameter / 2` in x, from the chuck face (`z = face`) back
//!   `depth` toward `-z`.
//! - The jaws stand `height` out of the face, so their faces are at `z = face + height`. They
//!   grip `grip_diameter` for `grip_length` back from their faces. `grip = "outside"`: the jaws
//!   close on an outer diameter and lie outward of it; `"inside"`: they open in a bore and lie
//!   inward of it. `width` is a jaw's whole radial extent.
//! - Hard jaws (`type = "hard"`): a `width × height` block with its gripping step at the tip. The
//!   step is `step` wide (radially) and `grip_length` long; the rest of the jaw stands
//!   `grip_length` back from the step's face. The gripping face runs flush down to the chuck
//!   face, so the part rests against nothing (a bar goes on into the spindle bore).
//! - Soft jaws (`type = "soft"`): a `width × height` block bored to the grip diameter for
//!   `grip_length`; behind the bore the jaw reaches `step` past the grip diameter (toward the
//!   axis for an outside grip, away from it for an inside grip): the seat the part rests against.
//!
//! In numbers, with `a = grip_diameter / 2`, `F = face`, `H = height`, `L = grip_length`, `W =
//! width`, `S = step`, each jaw is two stacked layers, a lower one `[F, F + H − L]` and the
//! gripping one `[F + H − L, F + H]` (the lower one is left out when `L = H`):
//!
//! | jaws | lower layer, x | gripping layer, x |
//! |---|---|---|
//! | hard, outside | `a ..= a + W` | `a ..= a + S` |
//! | hard, inside | `a − W ..= a` | `a − S ..= a` |
//! | soft, outside | `a − S ..= a − S + W` | `a ..= a − S + W` |
//! | soft, inside | `a + S − W ..= a + S` | `a + S − W ..= a` |
//!
//! The outline runs up the outer side of the body and the layers and back down their inner side,
//! starting at the body's inner back corner: the built-in machine's hand-drawn outline, point for
//! point. Values are checked here for how they fit together (a grip longer than the jaw, a step
//! wider than it, jaws that reach past the spindle axis or do not stand on the body); each error
//! names the keys it is about, the first the one to change.

use crate::geom::{p2, Polygon, P2};

/// How the jaws hold the part.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grip {
    /// The jaws close on an outer diameter (a bar, a shaft): they lie outward of it.
    Outside,
    /// The jaws open in a bore (a ring, a tube): they lie inward of it.
    Inside,
}

impl Grip {
    /// The name used in machine and job files: `outside`, `inside`.
    pub fn as_str(self) -> &'static str {
        match self {
            Grip::Outside => "outside",
            Grip::Inside => "inside",
        }
    }
}

/// What the jaws are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JawType {
    /// Hardened stepped jaws: the gripping step at the jaw's tip.
    Hard,
    /// Soft (machinable) jaws bored to the part, with a seat behind the bore.
    Soft,
}

impl JawType {
    /// The name used in machine and job files: `hard`, `soft`.
    pub fn as_str(self) -> &'static str {
        match self {
            JawType::Hard => "hard",
            JawType::Soft => "soft",
        }
    }
}

/// `[chuck] body`: mm, `face` a z in the spindle frame, the others lengths.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    pub diameter: f64,
    /// The through bore's diameter (0: none).
    pub bore: f64,
    /// The z of the chuck face.
    pub face: f64,
    /// How far the body reaches back from its face (toward `-z`).
    pub depth: f64,
}

/// `[chuck.jaws]`: mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jaws {
    pub grip: Grip,
    pub kind: JawType,
    /// The diameter held: the part's outer diameter (outside grip) or its bore (inside grip).
    pub grip_diameter: f64,
    /// How long (along z, back from the jaw faces) the jaws hold the part.
    pub grip_length: f64,
    /// How far the jaws stand out of the chuck face.
    pub height: f64,
    /// A jaw's whole radial extent.
    pub width: f64,
    /// Hard jaws: the gripping step's radial width; soft jaws: how far the seat reaches past the
    /// grip diameter.
    pub step: f64,
}

/// The chuck as its body and its jaws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chuck {
    pub body: Body,
    pub jaws: Jaws,
}

/// Values that give no chuck: the keys they are about (relative to `chuck.`, the first the one
/// to change: `jaws.grip_length`, `body.bore`) and why.
#[derive(Clone, Debug, PartialEq)]
pub struct JawError {
    pub keys: Vec<&'static str>,
    pub message: String,
}

fn fail<T>(keys: &[&'static str], message: String) -> Result<T, JawError> {
    Err(JawError {
        keys: keys.to_vec(),
        message,
    })
}

/// A length for messages: at most three decimals.
fn mm(v: f64) -> String {
    super::num(v)
}

impl Jaws {
    /// The jaw faces' z on a body whose face is at `face`.
    pub fn faces(&self, face: f64) -> f64 {
        face + self.height
    }

    /// One line for people: `hard, outside grip on Ø30 for 12 mm, 30 mm high`.
    pub fn describe(&self) -> String {
        format!(
            "{}, {} grip on Ø{} for {} mm, {} mm high",
            self.kind.as_str(),
            self.grip.as_str(),
            mm(self.grip_diameter),
            mm(self.grip_length),
            mm(self.height)
        )
    }

    /// The jaw's layers `(x0, x1, z0, z1)` from the chuck face up, each `x0 < x1`, `z0 < z1`.
    /// The sizes must already fit together ([`Chuck::outline`] checks them).
    fn layers(&self, face: f64) -> Vec<(f64, f64, f64, f64)> {
        let Jaws {
            grip,
            kind,
            grip_diameter,
            grip_length: l,
            height: h,
            width: w,
            step: s,
        } = *self;
        let a = grip_diameter / 2.0;
        let ((l0, l1), (u0, u1)) = match (kind, grip) {
            (JawType::Hard, Grip::Outside) => ((a, a + w), (a, a + s)),
            (JawType::Hard, Grip::Inside) => ((a - w, a), (a - s, a)),
            (JawType::Soft, Grip::Outside) => ((a - s, a - s + w), (a, a - s + w)),
            (JawType::Soft, Grip::Inside) => ((a + s - w, a + s), (a + s - w, a)),
        };
        let (zf, zs, zt) = (face, face + h - l, face + h);
        let mut out = Vec::with_capacity(2);
        if zs > zf {
            out.push((l0, l1, zf, zs));
        }
        out.push((u0, u1, zs, zt));
        out
    }
}

impl Chuck {
    /// The jaw faces' z (`face + height`): z 0 for the machine file's own jaws when its frame has
    /// z 0 at the jaw faces; a job's taller or shorter jaws move them, not the frame.
    pub fn faces(&self) -> f64 {
        self.jaws.faces(self.body.face)
    }

    /// The jaws in one line ([`Jaws::describe`]), with where their faces stand when that is not
    /// z 0: `hard, outside grip on Ø30 for 12 mm, 40 mm high, faces at z 10`.
    pub fn describe_jaws(&self) -> String {
        let mut s = self.jaws.describe();
        if self.faces() != 0.0 {
            s.push_str(&format!(", faces at z {}", mm(self.faces())));
        }
        s
    }

    /// [`Chuck::describe_jaws`] and the body: `…; body Ø210, bore Ø50, face at z -30, 70 deep`.
    pub fn describe(&self) -> String {
        let b = &self.body;
        format!(
            "{}; body Ø{}, bore Ø{}, face at z {}, {} deep",
            self.describe_jaws(),
            mm(b.diameter),
            mm(b.bore),
            mm(b.face),
            mm(b.depth)
        )
    }

    /// The chuck's half section in the spindle frame (`[x, z]`, mm): the body and the revolved
    /// envelope of the jaws, as one outline. Every value must be positive (the bore may be 0);
    /// this checks how they fit together.
    pub fn outline(&self) -> Result<Vec<P2>, JawError> {
        let Body {
            diameter,
            bore,
            face,
            depth,
        } = self.body;
        let j = self.jaws;
        for (key, v) in [
            ("body.diameter", diameter),
            ("body.depth", depth),
            ("jaws.grip_diameter", j.grip_diameter),
            ("jaws.grip_length", j.grip_length),
            ("jaws.height", j.height),
            ("jaws.width", j.width),
            ("jaws.step", j.step),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return fail(&[key], format!("must be greater than 0, not {}", mm(v)));
            }
        }
        if !(bore.is_finite() && bore >= 0.0) {
            return fail(&["body.bore"], format!("must not be negative, not {}", mm(bore)));
        }
        if bore >= diameter {
            return fail(
                &["body.bore", "body.diameter"],
                format!(
                    "the bore (Ø{}) must be smaller than the body (Ø{})",
                    mm(bore),
                    mm(diameter)
                ),
            );
        }
        if j.grip_length > j.height {
            return fail(
                &["jaws.grip_length", "jaws.height"],
                format!(
                    "the jaws grip for {} mm but stand only {} mm out of the chuck face (chuck.jaws.height)",
                    mm(j.grip_length),
                    mm(j.height)
                ),
            );
        }
        match j.kind {
            JawType::Hard if j.step > j.width => {
                return fail(
                    &["jaws.step", "jaws.width"],
                    format!(
                        "the gripping step ({} mm) is wider than the jaw ({} mm, chuck.jaws.width)",
                        mm(j.step),
                        mm(j.width)
                    ),
                )
            }
            JawType::Soft if j.step >= j.width => {
                return fail(
                    &["jaws.step", "jaws.width"],
                    format!(
                        "the seat reaches {} mm past the grip, as far as the jaw is wide ({} mm, chuck.jaws.width) or farther: no jaw is left around the bored grip",
                        mm(j.step),
                        mm(j.width)
                    ),
                )
            }
            _ => {}
        }
        let layers = j.layers(face);
        let inner = layers.iter().map(|l| l.0).fold(f64::INFINITY, f64::min);
        if inner < 0.0 {
            let (keys, what): (&[&'static str], &str) = match (j.kind, j.grip) {
                (JawType::Soft, Grip::Outside) => (&["jaws.step", "jaws.grip_diameter"], "their seat reaches"),
                _ => (&["jaws.width", "jaws.grip_diameter"], "they reach"),
            };
            return fail(
                keys,
                format!(
                    "jaws {} mm wide {} Ø{}: {what} {} mm past the spindle axis",
                    mm(j.width),
                    match j.grip {
                        Grip::Outside => "closed on",
                        Grip::Inside => "opened in",
                    },
                    mm(j.grip_diameter),
                    mm(-inner)
                ),
            );
        }
        let (b0, b1) = (bore / 2.0, diameter / 2.0);
        let (x0, x1, _, _) = layers[0];
        if x1 <= b0 || x0 >= b1 {
            return fail(
                &["jaws.grip_diameter", "jaws.width", "body.diameter", "body.bore"],
                format!(
                    "jaws gripping Ø{} stand at radius {} .. {} at the chuck face, off the body (radius {} .. {}): they must stand on it",
                    mm(j.grip_diameter),
                    mm(x0),
                    mm(x1),
                    mm(b0),
                    mm(b1)
                ),
            );
        }
        let mut stack = Vec::with_capacity(3);
        stack.push((b0, b1, face - depth, face));
        stack.extend(layers);
        // Up the outer side from the body's inner back corner, then down the inner side.
        let mut pts = vec![p2(b0, face - depth)];
        for &(_, x1, z0, z1) in &stack {
            pts.push(p2(x1, z0));
            pts.push(p2(x1, z1));
        }
        for &(x0, _, z0, z1) in stack.iter().rev() {
            pts.push(p2(x0, z1));
            pts.push(p2(x0, z0));
        }
        pts.pop();
        Ok(pts)
    }

    /// [`Chuck::outline`] as a normalised polygon (repeated and collinear points dropped), every
    /// point within ±[`MAX_COORD_MM`](super::MAX_COORD_MM) (else an error on `body.face`).
    pub fn polygon(&self) -> Result<Polygon, JawError> {
        let pts = self.outline()?;
        let max = super::MAX_COORD_MM;
        if let Some(q) = pts.iter().find(|q| q.x.abs() > max || q.y.abs() > max) {
            return fail(
                &["body.face"],
                format!(
                    "the chuck reaches [{}, {}]: coordinates must be from {} to {} mm",
                    mm(q.x),
                    mm(q.y),
                    mm(-max),
                    mm(max)
                ),
            );
        }
        Polygon::new(&pts).map_err(|e| JawError {
            keys: vec!["jaws"],
            message: format!("the body and the jaws give no outline: {e}"),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(v: &[[f64; 2]]) -> Vec<P2> {
        v.iter().map(|&[x, z]| p2(x, z)).collect()
    }

    /// The built-in machine's chuck: a Ø210 body with a Ø50 bore, face at z -30, 70 deep; hard
    /// jaws 30 high and 45 wide gripping Ø50 for 12 mm on a 20 mm step.
    pub(crate) const BUILTIN: Chuck = Chuck {
        body: Body {
            diameter: 210.0,
            bore: 50.0,
            face: -30.0,
            depth: 70.0,
        },
        jaws: Jaws {
            grip: Grip::Outside,
            kind: JawType::Hard,
            grip_diameter: 50.0,
            grip_length: 12.0,
            height: 30.0,
            width: 45.0,
            step: 20.0,
        },
    };

    fn with(f: impl FnOnce(&mut Jaws)) -> Chuck {
        let mut c = BUILTIN;
        f(&mut c.jaws);
        c
    }

    #[test]
    fn the_builtin_chuck_is_its_hand_drawn_outline() {
        let drawn = pts(&[
            [25.0, -100.0],
            [105.0, -100.0],
            [105.0, -30.0],
            [70.0, -30.0],
            [70.0, -12.0],
            [45.0, -12.0],
            [45.0, 0.0],
            [25.0, 0.0],
        ]);
        assert_eq!(
            BUILTIN.polygon().unwrap().points(),
            Polygon::new(&drawn).unwrap().points()
        );
        assert_eq!(BUILTIN.polygon().unwrap().points(), &drawn[..]);
    }

    #[test]
    fn a_validation_error_names_its_keys() {
        let e = with(|j| j.grip_length = 31.0).outline().unwrap_err();
        assert_eq!(e.keys[0], "jaws.grip_length");
        let e = with(|j| j.step = 46.0).outline().unwrap_err();
        assert_eq!(e.keys[0], "jaws.step");
        let e = with(|j| {
            j.grip = Grip::Inside;
            j.grip_diameter = 60.0
        })
        .outline()
        .unwrap_err();
        assert_eq!(e.keys[0], "jaws.width");
        assert!(e.message.contains("15 mm past the spindle axis"), "{}", e.message);
    }
}
