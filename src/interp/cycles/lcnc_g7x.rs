//! The passes of LinuxCNC's G70/G71/G72 the way rs274ngc computes them, written from the
//! semantics of its `interp_g7x.cc` (read, not copied; see docs/cycles-linuxcnc.md).
//!
//! Points are complex numbers `z + i·x` in program units (rs274's tolerances are in program
//! units). The profile is first brought into a canonical frame (a quarter turn for G72, then
//! mirrored so that it runs toward −re and climbs toward +im, judged by its ends), offset in
//! steps, and the passes are computed there; every output point is mapped back.
//!
//! The roughing passes are those of the reference rs274 (2023); where they never end (that
//! version loops for ever), those of newer LinuxCNC, which fixed the loops ([`Rules`]).

use nalgebra::Complex;

pub(super) type C = Complex<f64>;

const TOL: f64 = 1e-6;
const J: C = Complex { re: 0.0, im: 1.0 };

/// A piece of the path: a line, or an arc about its centre (`ccw`: G3 in the z + i·x plane).
#[derive(Clone, Copy, Debug)]
pub(super) struct Piece {
    pub s: C,
    pub e: C,
    pub arc: Option<(C, bool)>,
    pub line: u32,
}

/// One output move in program coordinates (z + i·x).
#[derive(Clone, Copy, Debug)]
pub(super) enum Cmd {
    Rapid(C),
    Feed(C),
    Arc { ccw: bool, center: C, end: C },
}

fn dist(a: C, b: C) -> f64 {
    (a - b).norm()
}

/// `dist(a, b) >= m` known without the `hypot`: one coordinate's difference alone reaches `m`
/// (and neither is NaN). `hypot` is faithfully rounded, so it never returns less than the
/// larger of its two arguments. `false`: not known this way.
fn surely_reaches(a: C, b: C, m: f64) -> bool {
    let d = a - b;
    let (x, y) = (d.re.abs(), d.im.abs());
    !x.is_nan() && !y.is_nan() && x.max(y) >= m
}

impl Piece {
    fn offset(&mut self, d: f64) {
        let by = match self.arc {
            None => dist(self.s, self.e),
            Some((c, _)) => dist(self.s, c),
        };
        self.offset_by(d, by);
    }
    /// [`Piece::offset`] with the length it divides by known: a line's chord, an arc's radius
    /// at its start (the second of [`Piece::lengths`], found for its size a moment before: the
    /// same `hypot` of the same points, so the same bits).
    fn offset_by(&mut self, d: f64, by: f64) {
        match self.arc {
            None => {
                let n = J * d * (self.s - self.e) / by;
                self.s += n;
                self.e += n;
            }
            Some((c, ccw)) => {
                let r = by;
                let k = (r + if ccw { d } else { -d }) / r;
                self.s = (self.s - c) * k + c;
                self.e = (self.e - c) * k + c;
            }
        }
    }
    /// `self.size() >= m`, mostly without a `hypot` ([`surely_reaches`]); where that does not
    /// tell, the size itself (NaNs and all).
    fn size_at_least(&self, m: f64) -> bool {
        let sure = match self.arc {
            None => surely_reaches(self.s, self.e, m),
            Some((c, _)) => surely_reaches(self.s, self.e, m) && surely_reaches(self.s, c, m),
        };
        sure || self.size() >= m
    }
    /// The chord from start to end and the length an offset divides by (an arc's radius at its
    /// start, a line's chord again): what [`Piece::size`] and [`Piece::offset`] measure.
    fn lengths(&self) -> (f64, f64) {
        match self.arc {
            None => {
                let chord = dist(self.s, self.e);
                (chord, chord)
            }
            Some((c, _)) => (dist(self.s, self.e), dist(self.s, c)),
        }
    }
    /// [`Piece::size`] from its [`Piece::lengths`].
    fn size_of(&self, (chord, radius): (f64, f64)) -> f64 {
        match self.arc {
            None => chord,
            Some(_) => chord.min(radius),
        }
    }
    fn size(&self) -> f64 {
        self.size_of(self.lengths())
    }
    fn monotonic(&self) -> bool {
        match self.arc {
            None => (self.e - self.s).re <= 1e-3,
            Some((c, ccw)) => {
                let (entry, exit, dz) = ((self.s - c).im, (self.e - c).im, (self.e - self.s).re);
                if ccw {
                    entry >= -1e-3 && exit >= -1e-3 && dz <= -1e-3
                } else {
                    entry <= 1e-3 && exit <= 1e-3 && dz <= -1e-3
                }
            }
        }
    }
    fn map(&mut self, f: impl Fn(C) -> C, mirror: bool) {
        self.s = f(self.s);
        self.e = f(self.e);
        if let Some((c, ccw)) = self.arc {
            self.arc = Some((f(c), ccw != mirror));
        }
    }
    fn on_arc(&self, p: C) -> bool {
        let Some((c, ccw)) = self.arc else { return false };
        let a = ((self.s - c).conj() * (p - c)).im;
        let b = ((self.e - c).conj() * (p - c)).im;
        if ccw {
            a >= -TOL && b <= TOL
        } else {
            a <= TOL && b >= -TOL
        }
    }
    /// The re of each point where the piece meets im = x.
    fn level(&self, x: f64) -> Levels {
        let mut out = Levels::default();
        match self.arc {
            None => {
                if self.s.im.min(self.e.im) > x + TOL || self.s.im.max(self.e.im) < x - TOL {
                    return out;
                }
                if (self.s.im - self.e.im).abs() < TOL {
                    out.push(self.s.re);
                    out.push(self.e.re);
                } else {
                    out.push((x - self.s.im) / (self.e.im - self.s.im) * (self.e.re - self.s.re) + self.s.re);
                }
            }
            Some((c, _)) => {
                let r = dist(self.s, c);
                let q = -(x - r - c.im) * (x + r - c.im);
                if q < -TOL {
                    return out;
                }
                let q = q.max(0.0).sqrt();
                for re in [c.re + q, c.re - q] {
                    if self.on_arc(C::new(re, x)) {
                        out.push(re);
                    }
                }
            }
        }
        out
    }
}

/// The points where a piece meets a level: at most two (a line's ends when it lies on the level,
/// or an arc's two crossings), held in place rather than allocated, read as a slice.
#[derive(Clone, Copy, Debug, Default)]
struct Levels {
    v: [f64; 2],
    n: usize,
}

impl Levels {
    fn push(&mut self, re: f64) {
        self.v[self.n] = re;
        self.n += 1;
    }
}

impl std::ops::Deref for Levels {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.v[..self.n]
    }
}

/// Where the passes' output goes, with the point rs274's machine is at.
/// Room the moves of one cycle are given at once (a typical cycle makes 40–80; the vector
/// grows past it by doubling).
const CMDS_AT_ONCE: usize = 128;

struct Out {
    flip: u8,
    at: C,
    cmds: Vec<(Cmd, u32)>,
    cap: usize,
}

impl Out {
    fn back(&self, p: C) -> C {
        match self.flip {
            1 => -p.conj(),
            2 => p.conj(),
            3 => -p,
            4 => J * p,
            5 => (J * p).conj(),
            6 => -(J * p).conj(),
            7 => -J * p,
            _ => p,
        }
    }
    fn push(&mut self, c: Cmd, line: u32) -> Result<(), String> {
        if self.cmds.len() >= self.cap {
            return Err(format!("{ENDLESS} (more than {} moves)", self.cap));
        }
        self.cmds.push((c, line));
        Ok(())
    }
    fn rapid(&mut self, p: C) -> Result<(), String> {
        self.at = p;
        self.push(Cmd::Rapid(self.back(p)), 0)
    }
    fn feed(&mut self, p: C, line: u32) -> Result<(), String> {
        self.at = p;
        self.push(Cmd::Feed(self.back(p)), line)
    }
    fn arc(&mut self, ccw: bool, center: C, end: C, line: u32, unit_tol: f64) -> Result<(), String> {
        // rs274 drops an arc that ends where the machine is (within its equality tolerance).
        if (end.re - self.at.re).abs() < unit_tol && (end.im - self.at.im).abs() < unit_tol {
            return Ok(());
        }
        self.at = end;
        let mirror = matches!(self.flip, 1 | 2 | 5 | 6);
        let c = Cmd::Arc {
            ccw: ccw != mirror,
            center: self.back(center),
            end: self.back(end),
        };
        self.push(c, line)
    }
}

/// The path being cut: `v[0]` runs from the start point to the profile's first point.
#[derive(Clone)]
struct Path {
    v: Vec<Piece>,
    flip: u8,
}

impl Path {
    fn rotate(&mut self) {
        for p in &mut self.v {
            p.map(|q| -q * J, false);
        }
        self.flip ^= 4;
    }
    /// Mirrored so that the profile runs toward −re and climbs toward +im, by its ends.
    fn swap(&mut self) {
        let (f, l) = (self.v[0].e, self.v[self.v.len() - 1].e);
        if (f - l).im > 0.0 {
            for p in &mut self.v {
                p.map(|q| q.conj(), true);
            }
            self.flip ^= 2;
        }
        if (f - l).re < 0.0 {
            for p in &mut self.v {
                p.map(|q| -q.conj(), true);
            }
            self.flip ^= 1;
        }
    }
    fn drop_tiny(&mut self) {
        self.v.retain(|p| p.size_at_least(1e-3));
    }
    fn monotonic(&mut self) -> Result<(), String> {
        let f = &mut self.v[0];
        if (f.e - f.s).re > 0.0 {
            f.s.re = f.e.re;
        }
        if self.v.iter().all(Piece::monotonic) {
            Ok(())
        } else {
            Err("the profile is not monotonic (rs274: \"Not monotonic\")".into())
        }
    }

    /// Cut p's end and n's start where they meet.
    fn join(p: &mut Piece, n: &mut Piece) -> Result<(), String> {
        let x = match (p.arc, n.arc) {
            (None, None) => {
                let rot = (n.s - n.e).conj() / dist(n.s, n.e);
                let (ps, pe) = ((p.s - n.e) * rot, (p.e - n.e) * rot);
                if (ps - pe).im == 0.0 {
                    return Err(
                        "the offset meets two parallel lines (rs274: \"Cannot intersect parallel lines\")".into(),
                    );
                }
                let f = ps.im / (ps - pe).im;
                (ps + (pe - ps) * f) / rot + n.e
            }
            (Some((c, _)), None) | (None, Some((c, _))) => {
                // (`surely_reaches`: no `hypot` where a coordinate alone is TOL apart.)
                if !surely_reaches(n.s, p.e, TOL) && dist(n.s, p.e) < TOL {
                    return Ok(());
                }
                // The line's carrier against the arc's circle, the meeting nearest n's start.
                let (ls, le, on) = if p.arc.is_some() {
                    (n.s, n.e, p.e)
                } else {
                    (p.s, p.e, n.e)
                };
                let rot = (ls - le).conj() / dist(ls, le);
                let (pe, pc) = ((on - le) * rot, (c - le) * rot);
                let b = (pc - pe).norm_sqr() - pc.im * pc.im;
                let b = if b < 0.0 { 0.0 } else { b.sqrt() };
                let s1 = C::new(pc.re + b, 0.0) / rot + le;
                let s2 = C::new(pc.re - b, 0.0) / rot + le;
                if dist(n.s, s1) < dist(n.s, s2) {
                    s1
                } else {
                    s2
                }
            }
            (Some((cp, _)), Some((cn, _))) => {
                let a = dist(n.s, cn);
                let b = dist(p.s, cp);
                let c = dist(cn, cp);
                if c == 0.0 || a == 0.0 {
                    return Err("two arcs of the offset share their centre".into());
                }
                let cos = (c * c + a * a - b * b) / 2.0 / a / c;
                let rot = C::new(cos, (1.0 - (cos * cos).min(1.0)).sqrt());
                rot * (cp - cn) / c * a + cn
            }
        };
        p.e = x;
        n.s = x;
        Ok(())
    }

    /// The profile (all but `v[0]`) offset by `distance` toward the start point's side, in steps.
    fn add_distance(&mut self, distance: f64) -> Result<(), String> {
        let f = self.v[0];
        let last_s = self.v[self.v.len() - 1].s;
        let angle = (f.e - f.s) / (last_s - f.s);
        let distance = if angle.im < 0.0 { -distance } else { distance };
        let mut v: Vec<Piece> = self.v[1..].to_vec();
        let mut cur = 0.0;
        let mut rounds = 0u32;
        let mut lengths: Vec<(f64, f64)> = Vec::with_capacity(v.len() + 8);
        while cur != distance {
            rounds += 1;
            if rounds > 100_000 || v.is_empty() {
                return Err("the offset of the profile vanishes".into());
            }
            // Each piece's lengths once: its size here and its offset below.
            lengths.clear();
            lengths.extend(v.iter().map(Piece::lengths));
            let mut step = v
                .iter()
                .zip(&lengths)
                .map(|(p, &l)| p.size_of(l) / 2.0)
                .fold(1e9, f64::min);
            step = step.min((distance - cur).abs());
            if distance < 0.0 {
                step = -step;
            }
            if !step.is_finite() || step == 0.0 {
                return Err("the offset of the profile vanishes".into());
            }
            for (p, &l) in v.iter_mut().zip(&lengths) {
                p.offset_by(step, l.1);
            }
            v.retain(|p| p.size_at_least(1e-3));
            let mut k = 0;
            while k + 1 < v.len() {
                if (v[k].e - v[k + 1].s).re > 1e-2 {
                    let (mut a, mut b) = (v[k], v[k + 1]);
                    a.offset(-step);
                    b.offset(-step);
                    let center = (a.e + b.s) / 2.0;
                    let arc = Piece {
                        s: v[k].e,
                        e: v[k + 1].s,
                        arc: Some((center, distance > 0.0)),
                        line: v[k + 1].line,
                    };
                    v.insert(k + 1, arc);
                    k += 1;
                }
                k += 1;
            }
            let mut k = 0;
            let mut guard = 0usize;
            while k + 1 < v.len() {
                guard += 1;
                if guard > 10_000_000 {
                    return Err("the offset of the profile does not settle".into());
                }
                if !v[k].monotonic() {
                    if k == 0 {
                        return Err("the offset of the profile runs backward at its start".into());
                    }
                    if v[k].size() < v[k - 1].size() {
                        v.remove(k);
                    } else {
                        v.remove(k - 1);
                    }
                    k = 0;
                    if v.len() < 2 {
                        break;
                    }
                }
                if !v[k].size_at_least(1e-3) {
                    v.remove(k);
                    k = 1;
                    continue;
                }
                let (l, r) = v.split_at_mut(k + 1);
                Self::join(&mut l[k], &mut r[0])?;
                k += 1;
            }
            cur += step;
        }
        if v.is_empty() {
            return Err("the offset of the profile vanishes".into());
        }
        for k in 1..v.len() {
            let mid = (v[k - 1].e + v[k].s) / 2.0;
            v[k - 1].e = mid;
            v[k].s = mid;
        }
        let mut f = f;
        f.e = v[0].s;
        v.insert(0, f);
        self.v = v;
        Ok(())
    }
}

/// The settings of one roughing run.
struct Rough {
    /// The pocket scan of LinuxCNC since 2024 (see [`Rules`]).
    newer: bool,
    delta: f64,
    escape: C,
    unit_tol: f64,
    starts: Vec<C>,
}

impl Rough {
    /// A line or arc of the path followed downward (toward −im) from `at` to level `x`; `Ok(true)`
    /// when the piece does not dive.
    fn dive(&self, p: &Piece, at: &mut C, x: f64, out: &mut Out, fast: bool) -> Result<bool, String> {
        match p.arc {
            None => {
                if p.s.im <= p.e.im + TOL {
                    return Ok(true);
                }
                let to = if x < p.e.im {
                    p.e
                } else {
                    let is = p.level(x);
                    let Some(&z) = is.first() else {
                        return Err("x too large in straight dive".into());
                    };
                    C::new(z, x)
                };
                if fast {
                    out.rapid(to)?;
                } else {
                    out.feed(to, p.line)?;
                }
                *at = to;
                Ok(false)
            }
            Some((c, ccw)) => {
                if dist(*at, p.e) < TOL || (*at - p.e).re <= TOL {
                    *at = p.e;
                    return Ok(false);
                }
                let mut is = p.level(x);
                if is.is_empty() {
                    is = p.level(x - TOL);
                }
                if ccw {
                    if at.re - TOL > c.re {
                        return Ok(true);
                    }
                    let to = match is.last() {
                        Some(&z) if z <= c.re => C::new(z, x),
                        _ => p.e,
                    };
                    out.arc(ccw, c, to, p.line, self.unit_tol)?;
                    *at = to;
                } else {
                    if at.re <= c.re {
                        return Ok(true);
                    }
                    match is.first() {
                        None => {
                            out.arc(ccw, c, p.e, p.line, self.unit_tol)?;
                            *at = p.e;
                        }
                        Some(&z) if z < c.re => {}
                        Some(&z) => {
                            let to = C::new(z, x);
                            out.arc(ccw, c, to, p.line, self.unit_tol)?;
                            *at = to;
                        }
                    }
                }
                Ok(false)
            }
        }
    }

    /// The piece followed upward from `at`; `true` when the climb stops here (a pocket follows).
    fn climb(&self, p: &Piece, at: &mut C, out: &mut Out) -> Result<bool, String> {
        match p.arc {
            None => {
                if p.e.im + TOL < p.s.im {
                    return Ok(true);
                }
                if dist(*at, p.s) > TOL {
                    return Err("the final pass leaves the profile (rs274: \"How did we get here?\")".into());
                }
                out.feed(p.e, p.line)?;
                *at = p.e;
                Ok(false)
            }
            Some((c, ccw)) => {
                if !ccw {
                    if at.re > c.re {
                        return Ok(true);
                    }
                    if dist(*at, p.e) > 1e-3 {
                        out.arc(ccw, c, p.e, p.line, self.unit_tol)?;
                    }
                    *at = p.e;
                    Ok(false)
                } else {
                    if at.re < c.re {
                        return Ok(true);
                    }
                    let to = Self::top(p, c);
                    if dist(*at, to) > 1e-3 {
                        out.arc(ccw, c, to, p.line, self.unit_tol)?;
                    }
                    *at = to;
                    Ok(true)
                }
            }
        }
    }

    /// A G3 arc's end, or its top when it falls away past the top.
    fn top(p: &Piece, c: C) -> C {
        if p.e.re < c.re {
            C::new(c.re, c.im + dist(p.s, c))
        } else {
            p.e
        }
    }

    /// G7x.1's final pass: the climbing parts of the piece from the level of `at`.
    fn climb_only(&self, p: &Piece, at: &mut C, out: &mut Out) -> Result<(), String> {
        let is = p.level(at.im);
        match p.arc {
            None => {
                if p.e.im < p.s.im {
                    return Ok(());
                }
                let Some(&z) = is.first() else { return Ok(()) };
                at.re = z;
                out.feed(*at, p.line)?;
                out.feed(p.e, p.line)?;
                *at = p.e;
            }
            Some((c, ccw)) => {
                if is.is_empty() {
                    return Ok(());
                }
                if !ccw {
                    let z = is[is.len() - 1];
                    if z > c.re {
                        return Ok(());
                    }
                    at.re = z;
                    out.feed(*at, p.line)?;
                    if dist(*at, p.e) > 1e-3 {
                        out.arc(ccw, c, p.e, p.line, self.unit_tol)?;
                    }
                    *at = p.e;
                } else {
                    let z = is[0];
                    if z < c.re {
                        return Ok(());
                    }
                    at.re = z;
                    out.feed(*at, p.line)?;
                    let to = Self::top(p, c);
                    if dist(*at, to) > 1e-3 {
                        out.arc(ccw, c, to, p.line, self.unit_tol)?;
                    }
                    *at = to;
                }
            }
        }
        Ok(())
    }

    /// The passes from `at` along the path from piece `p` on (rs274's `pocket`, its recursion a
    /// loop). `cycle`: 0 all pockets, 1 none (final pass bridges them), 2 only after the first.
    fn pockets(&mut self, v: &[Piece], mut cycle: u8, mut at: C, mut p: usize, out: &mut Out) -> Result<(), String> {
        let mut rounds = 0usize;
        'pocket: loop {
            let mut x = self.starts[self.starts.len() - 1].im;
            if cycle == 2 {
                while p < v.len() {
                    if self.dive(&v[p], &mut at, -1e9, out, p == 0)? {
                        break;
                    }
                    p += 1;
                }
                cycle = 3;
            }
            while p < v.len() {
                rounds += 1;
                if rounds > out.cap {
                    return Err(format!("{ENDLESS} (more than {} passes)", out.cap));
                }
                while x - TOL > at.im {
                    x -= self.delta;
                }
                if self.dive(&v[p], &mut at, x, out, p == 0)? {
                    if cycle == 1 {
                        for q in &v[p..] {
                            self.climb_only(q, &mut at, out)?;
                        }
                        return Ok(());
                    }
                    while p < v.len() {
                        if self.climb(&v[p], &mut at, out)? {
                            if cycle == 3 {
                                if at.im > self.starts[self.starts.len() - 1].im && self.starts.len() > 1 {
                                    self.starts.pop();
                                }
                                if self.starts.len() == 1 {
                                    self.starts.push(at);
                                }
                            }
                            continue 'pocket;
                        }
                        p += 1;
                    }
                    return Ok(());
                }
                // Newer LinuxCNC: after the last piece followed down nothing is left to cut
                // toward, and a dive that ended exactly at its piece's end goes on from the next
                // piece (the scan from there finds its own end point and takes no level: the
                // reference rs274 repeats it for ever).
                if self.newer && p + 1 == v.len() {
                    return Ok(());
                }
                if (at.im - x).abs() > TOL || (self.newer && v[p].e == at) {
                    p += 1;
                    continue;
                }
                for (ip, seg) in v.iter().enumerate().skip(p) {
                    let is = seg.level(at.im);
                    if is.is_empty() {
                        continue;
                    }
                    let z = if ip != p { is[0] } else { is[is.len() - 1] };
                    let d = (z - at.re).abs();
                    if z - TOL > at.re {
                        continue;
                    }
                    if d < TOL {
                        if p == ip {
                            continue;
                        } else if dist(at, seg.s) < TOL {
                            p = ip;
                            break;
                        } else {
                            x -= self.delta;
                            break;
                        }
                    }
                    let mut dest = C::new(z, at.im);
                    out.feed(dest, seg.line)?;
                    let scale = (d / 2.0 / self.escape.re).min(1.0);
                    dest += self.escape * scale;
                    out.rapid(dest)?;
                    out.rapid(at - (self.escape * scale).conj())?;
                    if p == 0 {
                        out.rapid(at)?;
                    } else {
                        out.feed(at, 0)?;
                    }
                    x -= self.delta;
                    break;
                }
            }
            return Ok(());
        }
    }
}

/// Newer LinuxCNC (since late 2023), before any turn or mirror: when the entry runs toward the profile
/// and the profile ends on the entry's far side of the start point's level (X for G71, Z for
/// G72), with its last piece moving along the passes, a line from its end back to that level
/// closes it. The orientation is then judged with that line: a profile that dips back toward
/// the start point's side at its end is still roughed from the start point's side.
fn close_to_start_level(v: &mut Vec<Piece>, facing: bool, start: C) {
    let (first, last) = (v[0], v[v.len() - 1]);
    let (dfront, dback) = (first.e - first.s, last.e - last.s);
    let (along, across, gap) = if facing {
        (dback.im, dfront.re, start.re - last.e.re)
    } else {
        (dback.re, dfront.im, start.im - last.e.im)
    };
    if along.abs() > 0.0 && across * gap < 0.0 {
        let e = if facing {
            C::new(start.re, last.e.im)
        } else {
            C::new(last.e.re, start.im)
        };
        v.push(Piece {
            s: last.e,
            e,
            arc: None,
            line: 0,
        });
    }
}

/// Which LinuxCNC computes the passes: the reference rs274 (2023), or LinuxCNC since its fixes
/// of 2023-2026 for profiles on which the reference never ends.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Rules {
    Reference,
    Newer,
}

/// The start of the message of passes that do not end (the reference rs274 loops for ever).
const ENDLESS: &str = "the passes do not come to an end";

/// G71 (`facing` false) or G72 roughing from `start` along `v` (v[0] from the start point to
/// the profile's first point). `cycle` 0, 1 or 2 for G7x, G7x.1, G7x.2. The passes are the
/// reference rs274's; where those never end (the reference loops for ever), they are the ones
/// LinuxCNC computes since it fixed those loops (docs/cycles-linuxcnc.md).
#[allow(clippy::too_many_arguments)]
pub(super) fn rough(
    v: Vec<Piece>,
    facing: bool,
    cycle: u8,
    start: C,
    d: f64,
    i: f64,
    r: f64,
    cap: usize,
) -> Result<Vec<(Cmd, u32)>, String> {
    match rough_by(v.clone(), facing, cycle, start, (d, i, r), cap, Rules::Reference) {
        Err(e) if e.starts_with(ENDLESS) => rough_by(v, facing, cycle, start, (d, i, r), cap, Rules::Newer)
            .map_err(|e| format!("{e}, in the reference rs274 and in newer LinuxCNC")),
        done => done,
    }
}

/// [`rough`] by one set of rules; D, I and R as a triple.
fn rough_by(
    v: Vec<Piece>,
    facing: bool,
    cycle: u8,
    start: C,
    (d, i, r): (f64, f64, f64),
    cap: usize,
    rules: Rules,
) -> Result<Vec<(Cmd, u32)>, String> {
    if v.len() < 2 {
        return Err("the profile makes no move".into());
    }
    let mut path = Path { v, flip: 0 };
    path.v[0].s = start;
    if rules == Rules::Newer {
        close_to_start_level(&mut path.v, facing, start);
    }
    if facing {
        path.rotate();
    }
    path.swap();
    path.drop_tiny();
    if path.v.len() < 2 {
        return Err("the profile makes no move".into());
    }
    path.monotonic()?;
    path.add_distance(d)?;
    let mut out = Out {
        flip: path.flip,
        at: path.v[0].s,
        cmds: Vec::with_capacity(cap.min(CMDS_AT_ONCE)),
        cap,
    };
    let mut rough = Rough {
        newer: rules == Rules::Newer,
        delta: i.max(2.0 * TOL),
        escape: C::new(r, r),
        unit_tol: 1e-4,
        starts: vec![path.v[0].s],
    };
    let s0 = path.v[0].s;
    out.rapid(s0)?;
    let last = path.v[path.v.len() - 1];
    if last.e.im < s0.im {
        path.v.push(Piece {
            s: last.e,
            e: C::new(last.e.re, s0.im),
            arc: None,
            line: 0,
        });
    }
    rough.pockets(&path.v, cycle, s0, 0, &mut out)?;
    Ok(out.cmds)
}

/// G70 finishing: `passes` passes from distance `d` down to `e`.
pub(super) fn finish(
    v: Vec<Piece>,
    start: C,
    d: f64,
    e: f64,
    passes: u32,
    cap: usize,
) -> Result<Vec<(Cmd, u32)>, String> {
    if v.len() < 2 {
        return Err("the profile makes no move".into());
    }
    let mut this = Path { v, flip: 0 };
    this.v[0].s = start;
    let mut probe = Path {
        v: this.v[1..].to_vec(),
        flip: 0,
    };
    probe.swap();
    if !probe.v.iter().all(Piece::monotonic) {
        probe.rotate();
        probe.swap();
    }
    probe.monotonic()?;
    if probe.flip & 4 != 0 {
        this.rotate();
    }
    this.swap();
    this.drop_tiny();
    if this.v.len() < 2 {
        return Err("the profile makes no move".into());
    }
    this.monotonic()?;
    let mut out = Out {
        flip: this.flip,
        at: this.v[0].s,
        cmds: Vec::with_capacity(cap.min(CMDS_AT_ONCE)),
        cap,
    };
    for pass in (1..=passes).rev() {
        let distance = f64::from(pass - 1) * (d - e) / f64::from(passes) + e;
        let mut path = this.clone();
        path.add_distance(distance)?;
        out.rapid(path.v[0].s)?;
        out.rapid(path.v[0].e)?;
        for p in &path.v[1..] {
            match p.arc {
                None => out.feed(p.e, p.line)?,
                Some((c, ccw)) => out.arc(ccw, c, p.e, p.line, 1e-4)?,
            }
        }
    }
    Ok(out.cmds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Coordinates near the cycle's 1e-3 size limit, far from it, and not numbers at all.
    fn coord() -> impl Strategy<Value = f64> {
        prop_oneof![
            -0.003f64..0.003,
            -100.0f64..100.0,
            Just(f64::NAN),
            Just(f64::INFINITY),
            Just(0.0),
            Just(1e-3),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(5000))]

        /// The size test without `hypot` decides as the size itself, NaNs and infinities too.
        #[test]
        fn a_piece_is_at_least_a_size_exactly_when_its_size_says_so(
            s in (coord(), coord()),
            e in (coord(), coord()),
            c in proptest::option::of((coord(), coord())),
            ccw: bool,
        ) {
            let p = Piece {
                s: C::new(s.0, s.1),
                e: C::new(e.0, e.1),
                arc: c.map(|c| (C::new(c.0, c.1), ccw)),
                line: 1,
            };
            prop_assert_eq!(p.size_at_least(1e-3), p.size() >= 1e-3, "{:?}", p);
        }
    }

    fn line(a: (f64, f64), b: (f64, f64)) -> Piece {
        Piece {
            s: C::new(a.0, a.1),
            e: C::new(b.0, b.1),
            arc: None,
            line: 1,
        }
    }

    #[test]
    fn a_profile_starting_at_the_start_point_is_offset_to_the_side_rs274_takes() {
        // From the start point (z 0, x 25) the profile falls to x 5 along −z; its first move
        // goes nowhere. The rs274 of the reference prints the floor offset by D1 at x 4 (G8,
        // `G71 Q100 X25 Z0 D1 I1 R0.5`), ending with a feed to z −40.
        let v = vec![
            line((0.0, 25.0), (0.0, 25.0)),
            line((0.0, 25.0), (-10.0, 20.0)),
            line((-10.0, 20.0), (-10.0, 5.0)),
            line((-10.0, 5.0), (-40.0, 5.0)),
        ];
        let cmds = rough(v, false, 0, C::new(0.0, 25.0), 1.0, 1.0, 0.5, 10_000).unwrap();
        let Some((Cmd::Feed(last), _)) = cmds.last() else {
            panic!("{cmds:?}")
        };
        assert!((*last - C::new(-40.0, 4.0)).norm() < 1e-9, "{last:?}");
        assert_eq!(cmds.len(), 5, "{cmds:?}");
    }

    /// LinuxCNC's g71-endless-loop profile (G8): X10 from Z0 to Z-14, down to X3, up to X7 at
    /// Z-22, ending below the start point's level X15.
    fn step_then_deep_pocket() -> Vec<Piece> {
        vec![
            line((0.0, 15.0), (0.0, 10.0)),
            line((0.0, 10.0), (-14.0, 10.0)),
            line((-14.0, 10.0), (-14.0, 3.0)),
            line((-14.0, 3.0), (-22.0, 7.0)),
        ]
    }

    #[test]
    fn the_reference_rules_never_end_on_a_deep_pocket_after_a_step() {
        // rs274's endless G71.2 (LinuxCNC's g71-endless-loop test): stopped at the cap.
        let v = step_then_deep_pocket();
        let r = rough_by(
            v,
            false,
            2,
            C::new(0.0, 15.0),
            (0.04, 0.5, 1.0),
            5_000,
            Rules::Reference,
        );
        assert!(r.is_err_and(|e| e.starts_with(ENDLESS)));
    }

    #[test]
    fn passes_the_reference_never_ends_are_the_newer_linuxcnc_ones() {
        // The G71.2 of g71-endless-loop as LinuxCNC master prints it (its `expected` file): the
        // profile closed by a line up to X15 at Z-22 is roughed from outside, D 0.04: the first
        // pocket level X9.54 under the step at X10.04, the last pass at X3.54 stopping on the
        // offset slope, then the final climb along it (X3.0647 Z-14.04 to X7.0247 Z-21.96) and
        // up the closing line to X15.
        let v = step_then_deep_pocket();
        let cmds = rough(v, false, 2, C::new(0.0, 15.0), 0.04, 0.5, 1.0, 5_000).unwrap();
        let feeds: Vec<C> = cmds
            .iter()
            .filter_map(|(c, _)| match c {
                Cmd::Feed(p) => Some(*p),
                _ => None,
            })
            .collect();
        let near = |a: C, z: f64, x: f64| (a - C::new(z, x)).norm() < 1e-4;
        let n = feeds.len();
        assert!(near(feeds[n - 1], -21.96, 15.0), "{:?}", feeds[n - 1]);
        assert!(near(feeds[n - 2], -21.96, 7.0247), "{:?}", feeds[n - 2]);
        assert!(near(feeds[n - 3], -14.04, 3.0647), "{:?}", feeds[n - 3]);
        assert!(feeds.iter().any(|p| near(*p, -14.04, 9.54)));
        assert!(feeds.iter().all(|p| p.im > 3.0 - 1e-9));
    }

    #[test]
    fn where_the_reference_ends_its_passes_stand() {
        // The G71.1 of the same profile ends in the reference rs274 (mirrored by its ends, as a
        // bore): those passes stay, though newer LinuxCNC closes the profile and roughs it from
        // outside.
        let v = step_then_deep_pocket();
        let start = C::new(0.0, 15.0);
        let ours = rough(v.clone(), false, 1, start, 0.04, 0.5, 1.0, 5_000).unwrap();
        let reference = rough_by(v.clone(), false, 1, start, (0.04, 0.5, 1.0), 5_000, Rules::Reference).unwrap();
        let newer = rough_by(v, false, 1, start, (0.04, 0.5, 1.0), 5_000, Rules::Newer).unwrap();
        assert_eq!(format!("{ours:?}"), format!("{reference:?}"));
        assert_ne!(format!("{ours:?}"), format!("{newer:?}"));
    }

    #[test]
    fn an_arc_ending_where_the_tool_is_is_left_out() {
        let mut out = Out {
            flip: 0,
            at: C::new(1.0, 1.0),
            cmds: Vec::new(),
            cap: 10,
        };
        out.arc(true, C::new(0.0, 0.0), C::new(1.00005, 1.0), 1, 1e-4).unwrap();
        assert!(out.cmds.is_empty());
        out.arc(true, C::new(0.0, 0.0), C::new(1.0002, 1.0), 1, 1e-4).unwrap();
        assert_eq!(out.cmds.len(), 1);
    }
}
