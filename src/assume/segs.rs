//! The segments of a [`super::reading::Reading`], held packed: a few bytes a segment instead of
//! the 72 of a [`Seg`], every value given back bit for bit.
//!
//! A long program's reading is millions of segments (an arc is 8), and the setup rules walk
//! them several times, looking one or two segments back and forward. Most of a segment repeats
//! the one before it: it starts where the last one ended, at the same station, in the same
//! mode, on the next line, and one of its end's coordinates is its start's or one met a few
//! segments ago (a retract plane, a pass's radius). So each segment is written as what differs:
//! a two-byte header of flags (one byte when the pair was met before and still holds its slot in a
//! table of 64), then only the
//! fields the flags do not give. A coordinate that is none of those it may repeat is written as
//! the shortest of: an XOR with its reference, a whole number of 1e-4 mm less its reference's (a
//! word's decimals, 2–3 bytes), the difference of its bits from where the two segments before
//! it lead (an arc's chords: the next chord turns as the last one did, a byte or two), or its 8
//! bytes. Every [`CHECKPOINT`]th segment is written whole (nothing taken from earlier ones), so
//! a walk can start there; [`Segs::get`] and [`Segs::iter_from`] decode from the checkpoint
//! before.
//!
//! Invariant: decoding gives exactly the segments pushed, in order (`f64`s by their bits); the
//! property tests below hold it against a `Vec<Seg>` on random runs and on arcs' chords.

use super::reading::{Seg, SegKind};

/// Every this many segments one is written whole: a seek decodes at most this many. (A
/// segment written whole takes about 40 bytes against 7: every 64th cost the 1M-line program
/// 0.74 MB more than every 128th, in the same time; every 256th saved 0.4 MB more, but each
/// seek of the rules, a station's next move after a tool change, a boring pass's way out,
/// decodes twice as far again.)
const CHECKPOINT: usize = 128;

/// Recent values of one coordinate a segment's end may repeat.
const RECENT: usize = 4;

/// Recent modes (feed per revolution and scale) a segment may repeat: a rapid's and a feed's
/// alternate.
const MODES: usize = 3;

// Header, first byte.
const FEED: u8 = 1;
const DIAMETER: u8 = 1 << 1;
const CYCLE: u8 = 1 << 2;
const PROFILE: u8 = 1 << 3;
/// The segment starts where the one before ended (bit for bit).
const JOINED: u8 = 1 << 4;
const SAME_STATION: u8 = 1 << 5;
/// The segment's line is the one after the segment before's (a program read line by line).
const NEXT_LINE: u8 = 1 << 6;
const SAME_LINE: u8 = 1 << 7;
/// A first byte with both line flags (which never go together) stands for both header bytes:
/// its low six bits are the slot of the pair in the table of header pairs met ([`Headers`]). A
/// program's segments mostly repeat a few headers (a rapid, a feed, a chord, a retract).
const REPEAT: u8 = SAME_LINE | NEXT_LINE;

/// Slots of the table of header pairs.
const HEADERS: usize = 64;

/// The header pairs met, each in the slot its bits hash to (the last one met there): a pair is
/// found or replaced in one look, so packing and decoding cost the same whatever the table holds.
#[derive(Clone, Copy, Debug)]
struct Headers([Option<(u8, u8)>; HEADERS]);

impl Default for Headers {
    fn default() -> Headers {
        Headers([None; HEADERS])
    }
}

impl Headers {
    fn slot(pair: (u8, u8)) -> usize {
        // Fibonacci hashing of the two bytes into 6 bits.
        ((u32::from(pair.0) << 8 | u32::from(pair.1)).wrapping_mul(0x9E37_79B1) >> 26) as usize
    }
}

// Header, second byte: a tag for each end coordinate (r in bits 0–2, z in bits 3–5) and one for
// the mode (bits 6–7); a third byte, when the segment does not start where the one before ended,
// tags its start's coordinates. A coordinate is written against a reference: the start's for
// the end, the end before for the start.
/// The coordinate is its reference.
const SAME: u8 = 0;
/// The coordinate is its prediction from the two segments before ([`predict`], an arc's chords):
/// the difference of their bits, zigzag and varint (a byte or two on a circle). (The recent value
/// at place 1, the newest, is the reference: the position the tool is at.)
const PREDICTED: u8 = 1;
// 2..=RECENT: the coordinate is the recent value at that place (1 the newest).
/// Its bits differ from the reference's in the low 16 only: those written (2 bytes).
const XOR2: u8 = 5;
/// A whole number of 1e-4 mm ([`DECIMAL_UNITS`] a mm; divided by the unit's count per mm it gives its bits
/// back): that number less the reference's nearest whole number of units, zigzag and varint
/// (2–3 bytes for a program's coordinates, whose words have a few decimals).
const DECIMAL: u8 = 6;
/// Written in full.
const LITERAL: u8 = 7;

/// Units per mm of a [`DECIMAL`] coordinate: 1e-4 mm (a diameter word's 3 decimals halved).
const DECIMAL_UNITS: f64 = 1e4;

/// `v` as a whole number of 1e-4 mm, when dividing that number back gives `v`'s bits.
fn decimal_of(v: u64) -> Option<i64> {
    let f = f64::from_bits(v);
    let q = (f * DECIMAL_UNITS).round();
    // Whole numbers to 2^53 are exact in an f64 (and the division is correctly rounded); the
    // number as the decoder makes it must give the bits back (-0 comes back as +0: written whole).
    let q = (q.abs() < 9e15).then_some(q as i64)?;
    ((q as f64 / DECIMAL_UNITS).to_bits() == v).then_some(q)
}

/// The nearest whole number of 1e-4 mm to a reference (0 for none, or one too large to be a
/// coordinate): what a [`DECIMAL`] coordinate is written against.
fn decimal_ref(reference: Option<u64>) -> i64 {
    let q = reference.map_or(0.0, |r| (f64::from_bits(r) * DECIMAL_UNITS).round());
    if q.abs() < 9e15 {
        q as i64
    } else {
        0
    }
}
/// 0..MODES: the mode is the recent one at that place (0 the newest); this: written in full.
const NEW_MODE: u8 = 3;

/// The segments, packed.
#[derive(Clone, Debug, Default)]
pub struct Segs {
    bytes: Pages,
    /// Byte offset of every [`CHECKPOINT`]th segment.
    marks: Vec<usize>,
    len: usize,
    /// What the next segment is written against.
    last: Context,
}

/// Bytes in pages of [`PAGE`]: a store that grows by a page, never by copying what it holds, so
/// what a long program's reading holds is its bytes and at most one page more (a `Vec` doubling
/// holds up to twice its bytes, and three times while it copies).
#[derive(Clone, Debug, Default)]
struct Pages {
    pages: Vec<Box<[u8]>>,
    len: usize,
}

/// Bytes a page.
const PAGE: usize = 1 << 18;

impl Pages {
    fn len(&self) -> usize {
        self.len
    }

    fn push(&mut self, b: u8) {
        let (page, at) = (self.len / PAGE, self.len % PAGE);
        if page == self.pages.len() {
            self.pages.push(vec![0u8; PAGE].into_boxed_slice());
        }
        self.pages[page][at] = b;
        self.len += 1;
    }

    fn extend_from_slice(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.push(b);
        }
    }

    fn get(&self, at: usize) -> u8 {
        self.pages[at / PAGE][at % PAGE]
    }
}

/// What a segment is written against: the segment before it and the recent values of each
/// end coordinate. Empty at a checkpoint.
#[derive(Clone, Debug, Default)]
struct Context {
    prev: Option<Seg>,
    /// The segment before `prev`.
    prev2: Option<Seg>,
    recent: [Recent<u64, RECENT>; 2],
    modes: Recent<Mode, MODES>,
    /// The two header bytes of segments met.
    headers: Headers,
}

/// A segment's feed per revolution and scale, by their bits.
type Mode = (Option<u64>, u64);

fn mode_of(per_rev: Option<f64>, scale: f64) -> Mode {
    (opt_bits(per_rev), scale.to_bits())
}

/// The most recent distinct values of one kind, newest first.
#[derive(Clone, Copy, Debug)]
struct Recent<T, const N: usize> {
    vals: [T; N],
    n: u8,
}

impl<T: Copy + Default, const N: usize> Default for Recent<T, N> {
    fn default() -> Self {
        Recent {
            vals: [T::default(); N],
            n: 0,
        }
    }
}

impl<T: Copy + PartialEq, const N: usize> Recent<T, N> {
    fn find(&self, v: T) -> Option<usize> {
        self.vals[..self.n as usize].iter().position(|&w| w == v)
    }

    /// `v` becomes the newest (moved from its place, or pushed in, the oldest falling out).
    fn touch(&mut self, v: T) {
        let at = self.find(v).unwrap_or_else(|| {
            if (self.n as usize) < N {
                self.n += 1;
            }
            self.n as usize - 1
        });
        self.vals.copy_within(0..at, 1);
        self.vals[0] = v;
    }
}

impl Segs {
    pub fn new() -> Segs {
        Segs::default()
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bytes held (for tests and the memory figures).
    pub fn packed_bytes(&self) -> usize {
        self.bytes.len() + self.marks.len() * std::mem::size_of::<usize>()
    }

    pub fn push(&mut self, s: Seg) {
        if self.len % CHECKPOINT == 0 {
            self.marks.push(self.bytes.len());
            self.last = Context::default();
        }
        let ctx = &mut self.last;
        let out = &mut self.bytes;
        let mut h0 = 0u8;
        if s.kind == SegKind::Feed {
            h0 |= FEED;
        }
        if s.diameter {
            h0 |= DIAMETER;
        }
        if s.cycle {
            h0 |= CYCLE;
        }
        if s.profile {
            h0 |= PROFILE;
        }
        let p = ctx.prev;
        let joined = p.is_some_and(|p| bits2(p.b) == bits2(s.a));
        if joined {
            h0 |= JOINED;
        }
        if p.is_some_and(|p| p.station == s.station) {
            h0 |= SAME_STATION;
        }
        let mode = mode_of(s.per_rev, s.scale);
        let tm = ctx.modes.find(mode).map_or(NEW_MODE, |i| i as u8);
        if p.is_some_and(|p| p.line == s.line) {
            h0 |= SAME_LINE;
        } else if p.is_some_and(|p| p.line.checked_add(1) == Some(s.line)) {
            h0 |= NEXT_LINE;
        }
        // Each coordinate's tag against its reference and the recent values, in this order
        // (the start's r and z, then the end's): the decoder keeps the recent values the same
        // way.
        let predicted = if joined { predict(ctx.prev2, ctx.prev) } else { None };
        let mut payload = [(SAME, 0u64); 4];
        for (n, k) in [(0, 0), (1, 1), (2, 0), (3, 1)] {
            let (v, reference) = if n < 2 {
                if joined {
                    continue;
                }
                (s.a[k].to_bits(), p.map(|p| p.b[k].to_bits()))
            } else {
                (s.b[k].to_bits(), Some(s.a[k].to_bits()))
            };
            let guess = if n < 2 { None } else { predicted.map(|g| g[k]) };
            payload[n] = tag_of(v, reference, guess, &mut ctx.recent[k]);
        }
        let h1 = payload[2].0 | payload[3].0 << 3 | tm << 6;
        let slot = Headers::slot((h0, h1));
        if ctx.headers.0[slot] == Some((h0, h1)) {
            out.push(REPEAT | slot as u8);
        } else {
            out.push(h0);
            out.push(h1);
            ctx.headers.0[slot] = Some((h0, h1));
        }
        if !joined {
            out.push(payload[0].0 | payload[1].0 << 3);
        }
        if h0 & (SAME_LINE | NEXT_LINE) == 0 {
            let d = i64::from(s.line) - p.map_or(0, |p| i64::from(p.line));
            varint(out, zigzag(d));
        }
        if h0 & SAME_STATION == 0 {
            varint(out, u64::from(s.station));
        }
        ctx.modes.touch(mode);
        if tm == NEW_MODE {
            match s.per_rev {
                Some(f) => {
                    out.push(1);
                    out.extend_from_slice(&f.to_le_bytes());
                }
                None => out.push(0),
            }
            out.extend_from_slice(&s.scale.to_le_bytes());
        }
        for (t, x) in payload {
            match t {
                XOR2 => out.extend_from_slice(&(x as u16).to_le_bytes()),
                DECIMAL | PREDICTED => varint(out, x),
                LITERAL => out.extend_from_slice(&x.to_le_bytes()),
                _ => {}
            }
        }
        ctx.prev2 = ctx.prev.replace(s);
        self.len += 1;
    }

    /// Every segment in order.
    pub fn iter(&self) -> Iter<'_> {
        Iter {
            segs: self,
            at: 0,
            index: 0,
            ctx: Context::default(),
        }
    }

    /// The segments from index `i` on (none past the end).
    pub fn iter_from(&self, i: usize) -> Iter<'_> {
        let mark = i / CHECKPOINT;
        let mut it = match self.marks.get(mark) {
            Some(&at) => Iter {
                segs: self,
                at,
                index: mark * CHECKPOINT,
                ctx: Context::default(),
            },
            None => Iter {
                segs: self,
                at: self.bytes.len(),
                index: self.len,
                ctx: Context::default(),
            },
        };
        while it.index < i.min(self.len) {
            it.next();
        }
        it
    }

    /// Segment `i`.
    pub fn get(&self, i: usize) -> Option<Seg> {
        self.iter_from(i).next()
    }

    pub fn first(&self) -> Option<Seg> {
        self.iter().next()
    }

    /// Each segment with the one before it and a walk of those after it (to look ahead).
    pub fn walk(&self) -> Walk<'_> {
        let mut it = self.iter();
        let ahead = it.next();
        Walk { it, prev: None, ahead }
    }
}

/// The tag of a coordinate's bits `v` against its reference, its prediction (`guess`, the bits
/// [`predict`] gives) and the recent values (which it then joins), and what is written for it:
/// the shortest of the XOR with the reference, the zigzag difference of whole units or of the
/// prediction's bits, and the bits.
fn tag_of(v: u64, reference: Option<u64>, guess: Option<u64>, recent: &mut Recent<u64, RECENT>) -> (u8, u64) {
    if reference == Some(v) {
        return (SAME, 0);
    }
    let out = match recent.find(v) {
        // Place 1 is the reference (see `PREDICTED`), and tag 1 the prediction.
        Some(i) if i > 0 => (i as u8 + 1, 0),
        _ => {
            let mut best = (LITERAL, v, 8);
            let mut offer = |tag: u8, x: u64, len: usize| {
                if len < best.2 {
                    best = (tag, x, len);
                }
            };
            if let Some(x) = reference.map(|r| r ^ v).filter(|x| x >> 16 == 0) {
                offer(XOR2, x, 2);
            }
            if let Some(q) = decimal_of(v) {
                let x = zigzag(q.wrapping_sub(decimal_ref(reference)));
                offer(DECIMAL, x, varint_len(x));
            }
            if let Some(g) = guess {
                let x = zigzag((v as i64).wrapping_sub(g as i64));
                offer(PREDICTED, x, varint_len(x));
            }
            (best.0, best.1)
        }
    };
    recent.touch(v);
    out
}

/// Where a segment joined to `prev` would end if it turned from `prev` as `prev` turned from
/// `prev2` (the same turn and the same change of length: on an arc read as equal chords, the next
/// chord), as the bits of its `[r, z]`; `None` unless `prev` starts where `prev2` ends and the
/// guess is finite. Encoder and decoder compute it from the same bits, so it is the same guess.
fn predict(prev2: Option<Seg>, prev: Option<Seg>) -> Option<[u64; 2]> {
    let (p2, p) = (prev2?, prev?);
    if bits2(p2.b) != bits2(p.a) {
        return None;
    }
    let v1 = [p2.b[0] - p2.a[0], p2.b[1] - p2.a[1]];
    let v2 = [p.b[0] - p.a[0], p.b[1] - p.a[1]];
    let d = v1[0] * v1[0] + v1[1] * v1[1];
    // v2 / v1 as complex numbers: the turn and the change of length from one to the next.
    let wr = (v2[0] * v1[0] + v2[1] * v1[1]) / d;
    let wi = (v2[1] * v1[0] - v2[0] * v1[1]) / d;
    let g = [p.b[0] + (v2[0] * wr - v2[1] * wi), p.b[1] + (v2[0] * wi + v2[1] * wr)];
    (g[0].is_finite() && g[1].is_finite()).then(|| bits2(g))
}

/// Bytes of `v` as a varint.
fn varint_len(v: u64) -> usize {
    (64 - v.leading_zeros() as usize).max(1).div_ceil(7)
}

fn bits2(p: [f64; 2]) -> [u64; 2] {
    [p[0].to_bits(), p[1].to_bits()]
}

fn opt_bits(f: Option<f64>) -> Option<u64> {
    f.map(f64::to_bits)
}

fn zigzag(d: i64) -> u64 {
    ((d << 1) ^ (d >> 63)) as u64
}

fn unzigzag(v: u64) -> i64 {
    (v >> 1) as i64 ^ -((v & 1) as i64)
}

fn varint(out: &mut Pages, mut v: u64) {
    while v >= 0x80 {
        out.push(v as u8 | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

/// The segments in order, decoded as they come (cheap to clone: a clone walks on from here).
#[derive(Clone, Debug)]
pub struct Iter<'a> {
    segs: &'a Segs,
    at: usize,
    index: usize,
    ctx: Context,
}

impl Iter<'_> {
    fn byte(&mut self) -> u8 {
        let b = self.segs.bytes.get(self.at);
        self.at += 1;
        b
    }

    fn f64(&mut self) -> f64 {
        let mut b = [0u8; 8];
        for x in &mut b {
            *x = self.byte();
        }
        f64::from_le_bytes(b)
    }

    /// A coordinate of axis `k` written with tag `t` against `reference` (see [`tag_of`]).
    fn coordinate(&mut self, t: u8, reference: Option<u64>, guess: Option<u64>, k: usize) -> f64 {
        let v = match t {
            SAME => return f64::from_bits(reference.unwrap_or(0)),
            XOR2 => {
                let x = u16::from_le_bytes([self.byte(), self.byte()]);
                reference.unwrap_or(0) ^ u64::from(x)
            }
            PREDICTED => {
                let g = guess.unwrap_or(0) as i64;
                g.wrapping_add(unzigzag(self.varint())) as u64
            }
            DECIMAL => {
                let q = decimal_ref(reference).wrapping_add(unzigzag(self.varint()));
                (q as f64 / DECIMAL_UNITS).to_bits()
            }
            LITERAL => self.f64().to_bits(),
            i => self.ctx.recent[k].vals[i as usize - 1],
        };
        self.ctx.recent[k].touch(v);
        f64::from_bits(v)
    }

    fn varint(&mut self) -> u64 {
        let (mut v, mut shift) = (0u64, 0);
        loop {
            let b = self.byte();
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return v;
            }
            shift += 7;
        }
    }
}

impl Iterator for Iter<'_> {
    type Item = Seg;

    fn next(&mut self) -> Option<Seg> {
        if self.index >= self.segs.len {
            return None;
        }
        if self.index % CHECKPOINT == 0 {
            self.ctx = Context::default();
        }
        let p = self.ctx.prev;
        let first = self.byte();
        let (h0, h1) = if first & REPEAT == REPEAT {
            self.ctx.headers.0[(first & !REPEAT) as usize].unwrap_or_default()
        } else {
            let pair = (first, self.byte());
            self.ctx.headers.0[Headers::slot(pair)] = Some(pair);
            pair
        };
        let joined = p.filter(|_| h0 & JOINED != 0);
        let h2 = if joined.is_some() { 0 } else { self.byte() };
        let line = if h0 & SAME_LINE != 0 {
            p.map_or(0, |p| p.line)
        } else if h0 & NEXT_LINE != 0 {
            p.map_or(0, |p| p.line + 1)
        } else {
            let d = unzigzag(self.varint());
            (p.map_or(0, |p| i64::from(p.line)) + d) as u32
        };
        let station = match p {
            Some(p) if h0 & SAME_STATION != 0 => p.station,
            _ => self.varint() as u32,
        };
        let tm = h1 >> 6;
        let (per_rev, scale) = if tm == NEW_MODE {
            let per_rev = (self.byte() == 1).then(|| self.f64());
            (per_rev, self.f64())
        } else {
            let (f, scale) = self.ctx.modes.vals[tm as usize];
            (f.map(f64::from_bits), f64::from_bits(scale))
        };
        self.ctx.modes.touch(mode_of(per_rev, scale));
        let mut a = joined.map_or([0.0; 2], |p| p.b);
        if joined.is_none() {
            for (k, t) in [(0, h2 & 7), (1, (h2 >> 3) & 7)] {
                a[k] = self.coordinate(t, p.map(|p| p.b[k].to_bits()), None, k);
            }
        }
        let mut b = a;
        // Worked out only when an end coordinate is written as its prediction.
        let predicted = [h1 & 7, (h1 >> 3) & 7].contains(&PREDICTED);
        let guess = joined
            .filter(|_| predicted)
            .and_then(|_| predict(self.ctx.prev2, self.ctx.prev));
        for (k, t) in [(0, h1 & 7), (1, (h1 >> 3) & 7)] {
            b[k] = self.coordinate(t, Some(a[k].to_bits()), guess.map(|g| g[k]), k);
        }
        let s = Seg {
            line,
            station,
            kind: if h0 & FEED != 0 { SegKind::Feed } else { SegKind::Rapid },
            a,
            b,
            per_rev,
            scale,
            diameter: h0 & DIAMETER != 0,
            cycle: h0 & CYCLE != 0,
            profile: h0 & PROFILE != 0,
        };
        self.ctx.prev2 = self.ctx.prev.replace(s);
        self.index += 1;
        Some(s)
    }
}

/// One step of [`Segs::walk`]: a segment with the ones just before and after it.
pub struct Step<'a> {
    pub index: usize,
    pub prev: Option<Seg>,
    pub seg: Seg,
    pub next: Option<Seg>,
    segs: &'a Segs,
}

impl<'a> Step<'a> {
    /// The segments after this one (a walk of its own, from the checkpoint before them).
    pub fn rest(&self) -> Iter<'a> {
        self.segs.iter_from(self.index + 1)
    }

    /// The first segment after this one that satisfies `f` (the next one looked at first).
    pub fn find_after(&self, f: impl Fn(&Seg) -> bool) -> Option<Seg> {
        match self.next {
            Some(n) if f(&n) => Some(n),
            Some(_) => self.rest().skip(1).find(|n| f(n)),
            None => None,
        }
    }
}

/// See [`Segs::walk`]: decodes each segment once, one ahead.
pub struct Walk<'a> {
    it: Iter<'a>,
    prev: Option<Seg>,
    /// The segment the next step is about, decoded.
    ahead: Option<Seg>,
}

impl<'a> Iterator for Walk<'a> {
    type Item = Step<'a>;

    fn next(&mut self) -> Option<Step<'a>> {
        let index = self.it.index.checked_sub(1)?;
        let seg = self.ahead?;
        self.ahead = self.it.next();
        let prev = self.prev.replace(seg);
        Some(Step {
            index,
            prev,
            seg,
            next: self.ahead,
            segs: self.it.segs,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn bits(s: &Seg) -> impl PartialEq + std::fmt::Debug {
        (
            s.line,
            s.station,
            s.kind,
            bits2(s.a),
            bits2(s.b),
            opt_bits(s.per_rev),
            s.scale.to_bits(),
            (s.diameter, s.cycle, s.profile),
        )
    }

    fn packed(segs: &[Seg]) -> Segs {
        let mut out = Segs::new();
        for s in segs {
            out.push(*s);
        }
        out
    }

    fn same(got: &[Seg], want: &[Seg]) {
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(want) {
            assert_eq!(bits(g), bits(w));
        }
    }

    /// A value drawn mostly from a few that repeat (as a program's planes and radii do), some
    /// odd ones (signed zeros, NaN, infinities, subnormals) and any other.
    fn value() -> impl Strategy<Value = f64> {
        prop_oneof![
            4 => prop::sample::select(vec![0.0, 2.0, 25.0, 24.5, -30.0, 52.01]),
            // Words with a few decimals (a diameter's halved), a few ulps off them (an offset
            // added and taken away), and whole units past where an f64 holds them exactly.
            3 => (-20_000_000i64..20_000_000).prop_map(|q| q as f64 / 1e4),
            1 => ((-20_000_000i64..20_000_000), -3i64..=3)
                .prop_map(|(q, ulps)| f64::from_bits(((q as f64 / 1e4).to_bits() as i64 + ulps) as u64)),
            1 => prop::sample::select(vec![9.007e11, -9.007e11, 1e12, 4.5e15, 0.00005, -0.00005, 1e-300]),
            1 => prop::sample::select(vec![-0.0, f64::NAN, f64::INFINITY, -f64::INFINITY, 5e-324, f64::MAX]),
            2 => any::<f64>(),
        ]
    }

    /// Segments with their runs: each joined to the one before or not, one end coordinate its
    /// start's or not; lines forward, back (a subprogram, a loop) and far.
    fn run() -> impl Strategy<Value = Vec<Seg>> {
        let one = (
            (any::<bool>(), 0u8..4, value(), value(), value(), value()),
            (
                prop_oneof![Just(0i64), Just(1), -3i64..3, Just(1 << 40), Just(-(1 << 40))],
                0u32..3,
                any::<bool>(),
            ),
            (
                prop::option::of(prop::sample::select(vec![0.2, 1.5])),
                prop::sample::select(vec![1.0, 25.4]),
            ),
            (any::<bool>(), any::<bool>(), any::<bool>(), any::<bool>()),
        );
        prop::collection::vec(one, 0..300).prop_map(|v| {
            let mut out: Vec<Seg> = Vec::new();
            let mut line = 1u32;
            for ((joined, keep, ar, az, br, bz), (dl, station, big_station), (per_rev, scale), flags) in v {
                line = (i64::from(line) + dl).clamp(0, i64::from(u32::MAX)) as u32;
                let a = match out.last() {
                    Some(p) if joined => p.b,
                    _ => [ar, az],
                };
                let b = match keep {
                    0 => [a[0], bz],
                    1 => [br, a[1]],
                    _ => [br, bz],
                };
                out.push(Seg {
                    line,
                    station: if big_station { u32::MAX - station } else { station },
                    kind: if flags.0 { SegKind::Feed } else { SegKind::Rapid },
                    a,
                    b,
                    per_rev,
                    scale,
                    diameter: flags.1,
                    cycle: flags.2,
                    profile: flags.3,
                });
            }
            out
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// Packed segments give back every segment bit for bit: in order, from any index, one
        /// by one, and walked with the one before and after each.
        #[test]
        fn packed_segments_decode_to_what_was_pushed(want in run()) {
            let segs = packed(&want);
            prop_assert_eq!(segs.len(), want.len());
            same(&segs.iter().collect::<Vec<_>>(), &want);
            for i in (0..=want.len() + 1).step_by(7).chain([want.len().saturating_sub(1), 63, 64, 65, 128]) {
                same(&segs.iter_from(i).collect::<Vec<_>>(), &want[i.min(want.len())..]);
                match (segs.get(i), want.get(i)) {
                    (Some(g), Some(w)) => prop_assert_eq!(bits(&g), bits(w)),
                    (g, w) => prop_assert_eq!(g.is_some(), w.is_some()),
                }
            }
            for st in segs.walk() {
                let i = st.index;
                prop_assert_eq!(bits(&st.seg), bits(&want[i]));
                prop_assert_eq!(st.prev.map(|p| bits(&p)), i.checked_sub(1).map(|k| bits(&want[k])));
                prop_assert_eq!(st.next.map(|n| bits(&n)), want.get(i + 1).map(bits));
                same(&st.rest().collect::<Vec<_>>(), &want[i + 1..]);
                let f = |n: &Seg| n.station == st.seg.station;
                prop_assert_eq!(st.find_after(f).map(|n| bits(&n)), want[i + 1..].iter().find(|n| f(n)).map(bits));
            }
        }
    }

    /// Arcs read as chords (as `reading::read_move` reads them: circles and spirals, any centre,
    /// radius and sweep, some mirrored), between straight moves.
    fn arcs() -> impl Strategy<Value = Vec<Seg>> {
        let arc = (
            (-200.0f64..200.0, -300.0f64..300.0),
            (0.01f64..150.0, prop_oneof![Just(0.0), -5.0f64..5.0]),
            (-3.2f64..3.2, prop_oneof![-6.3f64..6.3, Just(std::f64::consts::PI)]),
            any::<bool>(),
        );
        prop::collection::vec(arc, 1..12).prop_map(|v| {
            let mut out: Vec<Seg> = Vec::new();
            for (n, ((cx, cz), (r0, dr), (a0, sweep), mirror)) in v.into_iter().enumerate() {
                let side = if mirror { -1.0 } else { 1.0 };
                let at = |t: f64| {
                    let (r, a) = (r0 + t * dr, a0 + t * sweep);
                    [side * (cx + r * a.cos()), cz + r * a.sin()]
                };
                let seg = |line: u32, a: [f64; 2], b: [f64; 2]| Seg {
                    line,
                    station: 1,
                    kind: SegKind::Feed,
                    a,
                    b,
                    per_rev: Some(0.2),
                    scale: 1.0,
                    diameter: true,
                    cycle: false,
                    profile: false,
                };
                let line = 2 * n as u32 + 1;
                // A straight move to the arc's start, then its chords.
                let from = out.last().map_or([0.0, 0.0], |s| s.b);
                out.push(seg(line, from, at(0.0)));
                for k in 1..=8 {
                    out.push(seg(line + 1, at((k - 1) as f64 / 8.0), at(k as f64 / 8.0)));
                }
            }
            out
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// Chords of arcs come back bit for bit, in order and from any index.
        #[test]
        fn the_chords_of_arcs_decode_to_what_was_pushed(want in arcs()) {
            let segs = packed(&want);
            same(&segs.iter().collect::<Vec<_>>(), &want);
            for i in (0..want.len()).step_by(5) {
                same(&segs.iter_from(i).collect::<Vec<_>>(), &want[i..]);
            }
        }
    }

    /// A circle's chords pack small: past the first two of an arc, each chord's end is its
    /// prediction less a few ulps (16 bytes written whole).
    #[test]
    fn the_chords_of_a_circle_are_packed_as_their_predictions() {
        let mut segs = Segs::new();
        let at = |t: f64| {
            let a = 0.3 + t * 1.7;
            [12.5 + 23.0 * a.cos(), -40.0 + 23.0 * a.sin()]
        };
        let n = 8;
        for k in 1..=n {
            segs.push(Seg {
                line: 7,
                station: 1,
                kind: SegKind::Feed,
                a: at((k - 1) as f64 / n as f64),
                b: at(k as f64 / n as f64),
                per_rev: None,
                scale: 1.0,
                diameter: false,
                cycle: false,
                profile: false,
            });
        }
        let whole = 2 + 1 + 1 + 1 + 1 + 8 + 32; // the first: header, start tags, line, station, mode, coordinates
        let rest = segs.packed_bytes() - std::mem::size_of::<usize>() - whole;
        // The second chord: its end's two coordinates whole (18 bytes with its header); the six
        // after it: a header and two short differences each.
        assert!(rest <= 18 + 6 * 5, "{rest} bytes for the chords after the first");
    }

    /// A turning program's segments pack into a fraction of their size (the point of packing).
    #[test]
    fn a_turning_programs_segments_pack_small() {
        // Roughing passes: in at the pass's diameter, along Z, out, back to the start plane.
        let mut src = String::from("G21 G18 G99\nT0101\nG97 S800 M3\n");
        for k in 0..200 {
            let d = 50.0 - 0.4 * f64::from(k % 50);
            src += &format!("G0 X{d:.3} Z2.\nG1 Z-30. F0.25\nX{:.3}\nG0 Z2.\n", d + 1.0);
        }
        src += "M30\n";
        let src = src.into_bytes();
        let m = crate::machine::Machine::builtin();
        let r = super::super::reading::Reading::of(&src, &m);
        assert!(r.segs.len() >= 800, "{} segments", r.segs.len());
        let per = r.segs.packed_bytes() as f64 / r.segs.len() as f64;
        assert!(per < 10.5, "{per:.1} bytes a segment");
    }
}
