//! Milling cutters as unions of convex pieces about their axis (heights from the tip).

use nalgebra::Vector3;

use super::sweep::{basis_across, ray_ball, Across};

/// Largest cutter diameter or length (mm).
pub const MAX_SIZE_MM: f64 = 1000.0;

/// The shape of a cutter's cutting part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CutterKind {
    /// A flat end mill: a cylinder.
    Flat,
    /// A ball end mill: a hemisphere under a cylinder.
    Ball,
    /// A bull-nose end mill: a flat end with corners of this radius.
    Bull { corner_radius: f64 },
    /// A drill: a cone of this included angle (degrees) under a cylinder.
    Drill { point_angle_deg: f64 },
    /// A tap of this pitch: as a cylinder of its minor diameter (ISO metric: D − 1.0825·P), the
    /// hole the drill left; the thread itself is not modelled.
    Tap { pitch: f64 },
}

/// A cutter: its shape, diameter and the length of its cutting part (flute length).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutter {
    pub kind: CutterKind,
    pub diameter: f64,
    pub flute_length: f64,
}

/// A convex piece of a cutter in its own frame (height `h` along the axis from the tip).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Piece {
    /// A cylinder of radius `r` from height `h0` to `h1`.
    Disc { r: f64, h0: f64, h1: f64 },
    /// A ball of radius `r` centred at height `h`.
    Ball { r: f64, h: f64 },
}

impl Cutter {
    /// A checked cutter: sizes positive and at most [`MAX_SIZE_MM`], a corner radius at most the
    /// radius, a point angle in (0°, 180°), a pitch below the diameter.
    pub fn new(kind: CutterKind, diameter: f64, flute_length: f64) -> Result<Cutter, String> {
        let ok = |x: f64| x.is_finite() && x > 0.0 && x <= MAX_SIZE_MM;
        if !ok(diameter) {
            return Err(format!(
                "diameter {diameter} mm: must be above 0 and at most {MAX_SIZE_MM}"
            ));
        }
        if !ok(flute_length) {
            return Err(format!(
                "flute length {flute_length} mm: must be above 0 and at most {MAX_SIZE_MM}"
            ));
        }
        match kind {
            CutterKind::Bull { corner_radius } if !(corner_radius > 0.0 && corner_radius <= diameter / 2.0) => {
                return Err(format!(
                    "corner radius {corner_radius} mm: must be above 0 and at most the radius {}",
                    diameter / 2.0
                ));
            }
            CutterKind::Drill { point_angle_deg } if !(point_angle_deg > 0.0 && point_angle_deg < 180.0) => {
                return Err(format!("point angle {point_angle_deg}°: must be between 0° and 180°"));
            }
            CutterKind::Tap { pitch } if !(pitch > 0.0 && 1.0825 * pitch < diameter) => {
                return Err(format!("pitch {pitch} mm: must be above 0 and leave a minor diameter"));
            }
            CutterKind::Ball if flute_length < diameter / 2.0 => {
                return Err(format!(
                    "flute length {flute_length} mm: a ball end needs at least its radius"
                ));
            }
            _ => {}
        }
        Ok(Cutter {
            kind,
            diameter,
            flute_length,
        })
    }

    /// The cutter's pieces. Curved ends that are not a ball (a bull nose's corners, a drill's
    /// cone) are stacks of discs inscribed in them, each at most `tol` narrower than the true
    /// profile over its height: the pieces never hold more than the cutter does.
    pub(crate) fn pieces(&self, tol: f64) -> Vec<Piece> {
        let r = self.diameter / 2.0;
        let l = self.flute_length;
        let tol = tol.max(1e-4);
        let mut out = Vec::new();
        // Inscribed discs under a profile radius(h) increasing from h = 0 to h = top.
        let stack = |out: &mut Vec<Piece>, top: f64, radius: &dyn Fn(f64) -> f64| {
            let n = ((radius(top) - radius(0.0)) / tol).ceil().clamp(1.0, 4096.0) as usize;
            for i in 0..n {
                let (h0, h1) = (top * i as f64 / n as f64, top * (i + 1) as f64 / n as f64);
                let rr = radius(h0);
                if rr > 0.0 {
                    out.push(Piece::Disc { r: rr, h0, h1 });
                }
            }
        };
        match self.kind {
            CutterKind::Flat => out.push(Piece::Disc { r, h0: 0.0, h1: l }),
            CutterKind::Ball => {
                out.push(Piece::Ball { r, h: r });
                out.push(Piece::Disc { r, h0: r, h1: l });
            }
            CutterKind::Bull { corner_radius: rc } => {
                let rc = rc.min(l);
                stack(&mut out, rc, &|h: f64| {
                    r - rc + (rc * rc - (rc - h) * (rc - h)).max(0.0).sqrt()
                });
                if l > rc {
                    out.push(Piece::Disc { r, h0: rc, h1: l });
                }
            }
            CutterKind::Drill { point_angle_deg } => {
                let k = (point_angle_deg.to_radians() / 2.0).tan();
                let tip = (r / k).min(l);
                stack(&mut out, tip, &|h: f64| (h * k).min(r));
                if l > tip {
                    out.push(Piece::Disc { r, h0: tip, h1: l });
                }
            }
            CutterKind::Tap { pitch } => out.push(Piece::Disc {
                r: (self.diameter - 1.0825 * pitch) / 2.0,
                h0: 0.0,
                h1: l,
            }),
        }
        out
    }

    /// The cutter's radius at height `h` above its tip (0 outside its cutting part): the true
    /// profile, for oracles and drawings.
    pub fn radius_at(&self, h: f64) -> f64 {
        let r = self.diameter / 2.0;
        if !(0.0..=self.flute_length).contains(&h) {
            return 0.0;
        }
        match self.kind {
            CutterKind::Flat => r,
            CutterKind::Ball => {
                if h >= r {
                    r
                } else {
                    (r * r - (r - h) * (r - h)).max(0.0).sqrt()
                }
            }
            CutterKind::Bull { corner_radius: rc } => {
                if h >= rc {
                    r
                } else {
                    r - rc + (rc * rc - (rc - h) * (rc - h)).max(0.0).sqrt()
                }
            }
            CutterKind::Drill { point_angle_deg } => (h * (point_angle_deg.to_radians() / 2.0).tan()).min(r),
            CutterKind::Tap { pitch } => (self.diameter - 1.0825 * pitch) / 2.0,
        }
    }
}

/// One ray's answer kept for the rays that share its key ([`Sweep::ray_memo`]).
pub(crate) type RayMemo = Option<([u64; 8], Option<(f64, f64)>)>;

/// A cutter moved along a straight line with its axis fixed: the tip from `p0` to `p0 + v`,
/// the axis `axis` (unit, from the tip toward the shank). The swept solid has no direction, and
/// the segment is kept from its lesser end (by x, then y, then z): a move and the move that
/// retraces it (a drill's plunge and its retract) are one sweep, bit for bit, and their rays'
/// answers are the same numbers (`FaceGrid`'s retrace).
#[derive(Clone, Debug)]
pub struct Sweep {
    pub(crate) pieces: Vec<Piece>,
    pub p0: Vector3<f64>,
    pub v: Vector3<f64>,
    pub axis: Vector3<f64>,
    /// A basis of the plane across the axis.
    across: (Vector3<f64>, Vector3<f64>),
    /// The cutter's radius and flute length: every piece lies within `radius` of the segment
    /// from the tip to `length` up the axis.
    radius: f64,
    length: f64,
    /// The box holding the swept solid.
    pub min: Vector3<f64>,
    pub max: Vector3<f64>,
}

impl Sweep {
    /// `None` when the axis is not a direction.
    pub fn new(cutter: &Cutter, axis: Vector3<f64>, p0: Vector3<f64>, p1: Vector3<f64>, tol: f64) -> Option<Sweep> {
        let n = axis.norm();
        if !(n.is_finite() && n > 1e-12 && p0.iter().chain(p1.iter()).all(|x| x.is_finite())) {
            return None;
        }
        let axis = axis / n;
        let (p0, p1) = if crate::geom::after(p0.into(), p1.into()) {
            (p1, p0)
        } else {
            (p0, p1)
        };
        let r = cutter.diameter / 2.0;
        let l = cutter.flute_length;
        let mut min = Vector3::repeat(f64::INFINITY);
        let mut max = Vector3::repeat(f64::NEG_INFINITY);
        for p in [p0, p1] {
            for h in [0.0, l] {
                let c = p + h * axis;
                // A disc of radius r across the axis reaches r·√(1 − a_i²) along each axis.
                for i in 0..3 {
                    let reach = r * (1.0 - axis[i] * axis[i]).max(0.0).sqrt();
                    min[i] = min[i].min(c[i] - reach);
                    max[i] = max[i].max(c[i] + reach);
                }
            }
        }
        let pieces = Self::widest_first(cutter.pieces(tol));
        Some(Sweep {
            pieces,
            radius: r,
            length: l,
            p0,
            v: p1 - p0,
            axis,
            across: basis_across(axis),
            min,
            max,
        })
    }

    /// The swept solid seen along z: inside the quadrilateral of these corners (the cutter's
    /// axis segment at the move's two ends) grown by [`Sweep::reach`].
    pub(crate) fn corners_xy(&self) -> [(f64, f64); 4] {
        let top = self.length * self.axis;
        [self.p0, self.p0 + top, self.p0 + self.v + top, self.p0 + self.v].map(|c| (c.x, c.y))
    }

    /// How far the solid reaches from its axis segment.
    pub(crate) fn reach(&self) -> f64 {
        self.radius
    }

    /// The pieces in the order [`Sweep::ray`] reads them best: the one reaching highest (the
    /// shank), the one reaching lowest (the tip), then the widest first, so that the interval of
    /// the first two or three holds what the many thin discs of a stacked end could add.
    fn widest_first(mut pieces: Vec<Piece>) -> Vec<Piece> {
        let top = |p: &Piece| match *p {
            Piece::Disc { h1, .. } => h1,
            Piece::Ball { r, h } => h + r,
        };
        let bottom = |p: &Piece| match *p {
            Piece::Disc { h0, .. } => h0,
            Piece::Ball { r, h } => h - r,
        };
        let radius = |p: &Piece| match *p {
            Piece::Disc { r, .. } | Piece::Ball { r, .. } => r,
        };
        pieces.sort_by(|a, b| radius(b).total_cmp(&radius(a)));
        if let Some(i) = (0..pieces.len()).max_by(|&i, &j| top(&pieces[i]).total_cmp(&top(&pieces[j]))) {
            let p = pieces.remove(i);
            pieces.insert(0, p);
        }
        if pieces.len() > 2 {
            if let Some(i) = (1..pieces.len()).min_by(|&i, &j| bottom(&pieces[i]).total_cmp(&bottom(&pieces[j]))) {
                let p = pieces.remove(i);
                pieces.insert(1, p);
            }
        }
        pieces
    }

    /// The interval of `t ∈ [t0, t1]` where the ray `o + t·u` is inside the swept solid.
    pub fn ray(&self, o: Vector3<f64>, u: Vector3<f64>, t0: f64, t1: f64) -> Option<(f64, f64)> {
        self.ray_across(&self.across_of(o, u), o, u, t0, t1)
    }

    /// The ray `o + t·u` in the sweep's frame ([`Across`]): what [`Sweep::ray_across`] and
    /// [`Sweep::exit_along_axis`] take, worked out once for both.
    pub(crate) fn across_of(&self, o: Vector3<f64>, u: Vector3<f64>) -> Across {
        Across::new(o, u, self.p0, self.v, self.axis, self.across)
    }

    /// Whether `other` is this sweep, every number bit for bit (a cut is a function of the stock
    /// and these numbers).
    pub fn same_bits(&self, other: &Sweep) -> bool {
        let piece = |p: &Piece| match *p {
            Piece::Disc { r, h0, h1 } => [0.0, r, h0, h1].map(f64::to_bits),
            Piece::Ball { r, h } => [1.0, r, h, 0.0].map(f64::to_bits),
        };
        let v3 = |v: &Vector3<f64>| [v.x, v.y, v.z].map(f64::to_bits);
        let numbers = |s: &Sweep| {
            [s.p0, s.v, s.axis, s.across.0, s.across.1, s.min, s.max]
                .iter()
                .flat_map(v3)
                .chain([s.radius, s.length].map(f64::to_bits))
                .collect::<Vec<u64>>()
        };
        self.pieces.len() == other.pieces.len()
            && self.pieces.iter().zip(&other.pieces).all(|(a, b)| piece(a) == piece(b))
            && numbers(self) == numbers(other)
    }

    /// For a sweep of one disc piece (a flat end mill, a tap) moved square to its axis and a ray
    /// along that axis: the `t` at which the ray leaves the sweep whenever [`Sweep::ray`] (to
    /// `t1`) says it meets it ([`Across::exit_along_axis`]); `None` for any other sweep or ray.
    pub(crate) fn exit_along_axis(&self, across: &Across, t1: f64) -> Option<f64> {
        let [Piece::Disc { h0, h1, .. }] = self.pieces.as_slice() else {
            return None;
        };
        across.exit_along_axis((*h0, *h1), t1)
    }

    /// Whether the cutter is one disc piece (a flat end mill, a tap): the sweeps whose rays
    /// [`Sweep::ray_memo`] can answer from its memo.
    pub(crate) fn one_disc(&self) -> bool {
        matches!(self.pieces.as_slice(), [Piece::Disc { .. }])
    }

    /// [`Sweep::ray`], the answer taken from `memo` when it holds the answer of a ray with the
    /// same [`Across::level_key`] (a sweep of one disc piece: a flat end mill, a tap), bit for
    /// bit what casting it gives; a ray cast with a key is kept in `memo`. Also whether the ray
    /// was cast.
    pub(crate) fn ray_memo(
        &self,
        o: Vector3<f64>,
        u: Vector3<f64>,
        t0: f64,
        t1: f64,
        memo: &mut RayMemo,
    ) -> (Option<(f64, f64)>, bool) {
        let across = self.across_of(o, u);
        let key = match self.pieces.as_slice() {
            [Piece::Disc { h0, h1, .. }] => across.level_key((*h0, *h1), (t0, t1)),
            _ => None,
        };
        if let (Some(k), Some((mk, answer))) = (key, memo.as_ref()) {
            if k == *mk {
                return (*answer, false);
            }
        }
        let answer = self.ray_across(&across, o, u, t0, t1);
        if let Some(k) = key {
            *memo = Some((k, answer));
        }
        (answer, true)
    }

    /// [`Sweep::ray`] of the ray whose [`Sweep::across_of`] is `across`.
    pub(crate) fn ray_across(
        &self,
        across: &Across,
        o: Vector3<f64>,
        u: Vector3<f64>,
        t0: f64,
        t1: f64,
    ) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        // A stacked end (more pieces than a shank and an end) lies inside the cutter's
        // cylinder: a ray that misses it misses every piece.
        if self.pieces.len() > 2 {
            let whole = (0.0, self.length);
            across.disc_bound((t0, t1), self.radius, whole)?;
            across.disc((t0, t1), self.radius, whole)?;
        }
        for p in &self.pieces {
            let iv = match *p {
                // A lone piece in closed form: its bound would cost what its interval does (and
                // holds it: a bound that misses is an interval that misses).
                Piece::Disc { r, h0, h1 } if self.pieces.len() == 1 && across.closed_form() => {
                    across.disc((t0, t1), r, (h0, h1))
                }
                Piece::Disc { r, h0, h1 } => {
                    // A piece whose outer bound lies within the interval so far cannot widen it:
                    // the union's interval is the same without its exact (costly) interval.
                    match across.disc_bound((t0, t1), r, (h0, h1)) {
                        None => continue,
                        Some((a, b)) if a >= lo && b <= hi => continue,
                        Some(_) => across.disc((t0, t1), r, (h0, h1)),
                    }
                }
                Piece::Ball { r, h } => ray_ball(o, u, (t0, t1), self.p0 + h * self.axis, self.v, r),
            };
            if let Some((a, b)) = iv {
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// The same as [`Sweep::ray`], every piece measured exactly (the oracle of its skips).
    #[cfg(test)]
    pub(crate) fn ray_every_piece(&self, o: Vector3<f64>, u: Vector3<f64>, t0: f64, t1: f64) -> Option<(f64, f64)> {
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for p in &self.pieces {
            let iv = match *p {
                Piece::Disc { r, h0, h1 } => {
                    super::sweep::ray_disc(o, u, (t0, t1), self.p0, self.v, self.axis, r, (h0, h1))
                }
                Piece::Ball { r, h } => ray_ball(o, u, (t0, t1), self.p0 + h * self.axis, self.v, r),
            };
            if let Some((a, b)) = iv {
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// Whether a point is inside the swept solid (the pieces: for oracles).
    pub fn contains(&self, x: Vector3<f64>) -> bool {
        // A zero-length ray through the point.
        self.ray(x, Vector3::x(), 0.0, 0.0).is_some()
    }
}
