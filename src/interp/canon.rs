//! The interpreted motion as the reference interpreter prints it (`rs274 -g`): one canonical call
//! a line, so the two can be compared line by line.
//!
//! Positions are in program units relative to program zero, X always a radius (as rs274 prints
//! them); in G18 `ARC_FEED`'s first coordinate is Z and its second X, and its rotation is +turns
//! for G3 and −turns for G2.
//!
//! A move with an extra-axis entry ([`super::ExtraMove`], turn-mill machines) prints its real Y,
//! A, B and C where rs274 prints them (Y in program units, A/B/C as the axis values less their
//! program zero, never scaled), and an arc in G17 or G19 prints as rs274 does: G17
//! `ARC_FEED(x, y, cx, cy, rotation, z, a, b, c)`, G19 `ARC_FEED(y, z, cy, cz, rotation, x, a,
//! b, c)`, rotation +turns for G3 and −turns for G2.

use super::{ExtraMove, Interpretation, Move, MoveKind, MoveState, Plane, ProgFrame};
use std::f64::consts::TAU;
use std::io::Write;

/// One line per move: `STRAIGHT_TRAVERSE`, `STRAIGHT_FEED`, `ARC_FEED`, `DWELL`, `CHANGE_TOOL`
/// (and `COMMENT` where a job's operation starts).
/// The lines are gathered [`OUT_BYTES`] at a time and written on, so a long run streams without a
/// copy of the whole output in memory.
pub fn write<W: Write>(run: &Interpretation, sink: &mut W) -> std::io::Result<()> {
    let whole = super::Chunk {
        first: 0,
        moves: &run.moves,
        states: &run.states,
        extra: &run.extra,
    };
    write_chunk(whole, sink)
}

/// [`write`] for the moves of a chunk of a streaming run ([`super::interpret_streaming`]), with
/// their extra axes.
pub fn write_chunk<W: Write>(c: super::Chunk<'_>, sink: &mut W) -> std::io::Result<()> {
    if c.extra.is_empty() {
        return write_moves(c.moves, c.states, sink);
    }
    let mut out = Vec::with_capacity(OUT_BYTES + 512);
    let mut d = Decimals::new();
    let mut next = c.extra.iter().peekable();
    for (i, m) in c.moves.iter().enumerate() {
        let i = c.first + i;
        while next.peek().is_some_and(|e| (e.index as usize) < i) {
            next.next();
        }
        let e = next.peek().filter(|e| e.index as usize == i).copied();
        one_move_extra(&c.states[m.state as usize].frame, m, e, &mut d, &mut out);
        if out.len() >= OUT_BYTES {
            sink.write_all(&out)?;
            out.clear();
        }
    }
    sink.write_all(&out)
}

/// How many bytes of lines are gathered before they are written on (one write of many lines
/// costs less than a write a line, and the buffer stays small). As large as the `BufWriter`
/// `moves` writes through, which then hands such a write on without copying it.
const OUT_BYTES: usize = 1 << 16;

/// [`write`] for a run of moves and the states they refer to (a chunk of a streaming run,
/// [`super::interpret_streaming`]).
pub fn write_moves<W: Write>(moves: &[Move], states: &[MoveState], sink: &mut W) -> std::io::Result<()> {
    let mut out = Vec::with_capacity(OUT_BYTES + 512);
    let mut d = Decimals::new();
    for m in moves {
        one_move_extra(&states[m.state as usize].frame, m, None, &mut d, &mut out);
        if out.len() >= OUT_BYTES {
            sink.write_all(&out)?;
            out.clear();
        }
    }
    sink.write_all(&out)
}

/// Y, A, B, C of a move's end in program units (0 without an entry).
fn extra_coords(f: &ProgFrame, e: Option<&ExtraMove>) -> [f64; 4] {
    match e {
        Some(e) => [
            (e.end[0] - e.origin[0]) / f.scale,
            e.end[3] - e.origin[3],
            e.end[2] - e.origin[2],
            e.end[1] - e.origin[1],
        ],
        None => [0.0; 4],
    }
}

/// The arguments of an `ARC_FEED` after its opening parenthesis, as rs274 prints them: the end
/// and centre in the plane, the signed turns, the third axis and A, B, C.
fn arc_args(out: &mut Vec<u8>, d: &mut Decimals, plane: [f64; 4], rotation: i64, rest: [f64; 4]) {
    for v in plane {
        d.put(out, v);
        out.extend_from_slice(b", ");
    }
    if rotation < 0 {
        out.push(b'-');
    }
    push_uint(out, rotation.unsigned_abs(), 1, b'0');
    for v in rest {
        out.extend_from_slice(b", ");
        d.put(out, v);
    }
    out.extend_from_slice(b")\n");
}

fn one_move_extra(f: &ProgFrame, m: &Move, e: Option<&ExtraMove>, d: &mut Decimals, out: &mut Vec<u8>) {
    let [y, a, b, c] = extra_coords(f, e);
    if let Some(arc) = e.and_then(|e| e.arc) {
        let (x, z) = radius_coords(f, m.end);
        push_uint(out, m.line as u64, 5, b' ');
        out.extend_from_slice(b" ARC_FEED(");
        // The arc's centre in program units of the plane's two coordinates.
        let (o0, o1) = match arc.plane {
            Plane::Xy => (f.origin.x, e.map_or(0.0, |e| e.origin[0])),
            _ => (e.map_or(0.0, |e| e.origin[0]), f.origin.y),
        };
        let c0 = (arc.center[0] - o0) / f.scale;
        let c1 = (arc.center[1] - o1) / f.scale;
        let (e0, e1, third) = match arc.plane {
            Plane::Xy => (x, y, z),
            _ => (y, z, x),
        };
        let turns = (arc.sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i64;
        arc_args(
            out,
            d,
            [e0, e1, c0, c1],
            if arc.sweep < 0.0 { -turns } else { turns },
            [third, a, b, c],
        );
        return;
    }
    let (x, z) = radius_coords(f, m.end);
    push_uint(out, m.line as u64, 5, b' ');
    out.push(b' ');
    match m.kind {
        MoveKind::Rapid | MoveKind::Line => {
            out.extend_from_slice(if m.kind == MoveKind::Rapid {
                b"STRAIGHT_TRAVERSE("
            } else {
                b"STRAIGHT_FEED("
            });
            if e.is_none() {
                // No extra axis: Y, A, B and C are zero, written as `f4` writes zero.
                d.put(out, x);
                out.extend_from_slice(b", 0.0000, ");
                d.put(out, z);
                out.extend_from_slice(b", 0.0000, 0.0000, 0.0000)\n");
                return;
            }
            for v in [x, y, z, a, b] {
                d.put(out, v);
                out.extend_from_slice(b", ");
            }
            d.put(out, c);
            out.extend_from_slice(b")\n");
        }
        MoveKind::Arc { center, sweep } => {
            let (cx, cz) = radius_coords(f, center);
            let turns = (sweep.abs() / TAU - 1e-9).ceil().max(1.0) as i64;
            let rotation = if sweep > 0.0 { -turns } else { turns };
            out.extend_from_slice(b"ARC_FEED(");
            arc_args(out, d, [z, x, cz, cx], rotation, [y, a, b, c]);
        }
        MoveKind::Dwell { seconds } => {
            out.extend_from_slice(b"DWELL(");
            f4(out, seconds);
            out.extend_from_slice(b")\n");
        }
        MoveKind::ToolChange { to, .. } => {
            out.extend_from_slice(b"CHANGE_TOOL(");
            push_uint(out, to as u64, 1, b'0');
            out.extend_from_slice(b")\n");
        }
        MoveKind::Operation { op } => {
            // Not an rs274 call: the job's turn-round, as a comment (rs274 prints `COMMENT`).
            out.extend_from_slice(b"COMMENT(\"latheguard: operation ");
            push_uint(out, u64::from(op) + 2, 1, b'0');
            out.extend_from_slice(b" starts: the part turned round or re-clamped (job operations[");
            push_uint(out, u64::from(op), 1, b'0');
            out.extend_from_slice(b"])\")\n");
        }
        MoveKind::Wait { code, paths } => {
            // Not an rs274 call: a multi-path control's wait, as a comment.
            out.extend_from_slice(b"COMMENT(\"latheguard: waits at M");
            push_uint(out, u64::from(code), 1, b'0');
            out.extend_from_slice(b" for paths");
            for p in 1..=8u8 {
                if paths & (1 << (p - 1)) != 0 {
                    out.push(b' ');
                    push_uint(out, u64::from(p), 1, b'0');
                }
            }
            out.extend_from_slice(b"\")\n");
        }
    }
}

/// The text of the values written lately, by their bits: a lathe program's coordinates repeat
/// (the retract plane, the bar's radius, a pass's level, the X a feed along Z keeps), and a
/// value found here is copied instead of written again. A slot holds the last value whose bits
/// hash to it, so what it gives is what [`f4`] wrote for the same bits.
struct Decimals {
    bits: [u64; DECIMAL_SLOTS],
    /// The text in the first `len` bytes (0: the slot is empty).
    text: [[u8; 24]; DECIMAL_SLOTS],
    len: [u8; DECIMAL_SLOTS],
}

const DECIMAL_SLOTS: usize = 256;

impl Decimals {
    fn new() -> Decimals {
        Decimals {
            bits: [0; DECIMAL_SLOTS],
            text: [[0; 24]; DECIMAL_SLOTS],
            len: [0; DECIMAL_SLOTS],
        }
    }

    /// Append `v` as [`f4`] does.
    #[inline]
    fn put(&mut self, out: &mut Vec<u8>, v: f64) {
        let bits = v.to_bits();
        let k = (bits.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 56) as usize;
        let start = out.len();
        let len = self.len[k] as usize;
        if len != 0 && self.bits[k] == bits {
            // A fixed-size append and a cut, as in `f4` (no `memcpy` call for a few bytes).
            out.extend_from_slice(&self.text[k]);
            out.truncate(start + len);
            return;
        }
        f4(out, v);
        let written = &out[start..];
        if written.len() <= 24 {
            self.text[k][..written.len()].copy_from_slice(written);
            self.len[k] = written.len() as u8;
            self.bits[k] = bits;
        }
    }
}

/// Append `v` with four decimals, as `%.4f` prints it (but a value that rounds to zero prints as
/// `0.0000`, never `-0.0000`), without the standard library's formatting machinery, which would
/// cost more than the rest of the canonical output together.
fn f4(out: &mut Vec<u8>, v: f64) {
    let r = v * 1e4;
    // Most coordinates of a lathe program's moves are Y, A, B and C at zero.
    if r.abs() < 0.5 {
        out.extend_from_slice(b"0.0000");
        return;
    }
    // Rounded half away from zero, as `f64::round` does (without its call): `r` less its
    // integer part is exact, so comparing it with one half decides as `round` would.
    let n = if r.abs() < 9e15 {
        let t = r as i64;
        let f = r - t as f64;
        t + i64::from(f >= 0.5) - i64::from(f <= -0.5)
    } else {
        i64::MAX
    };
    if n.unsigned_abs() >= 9_000_000_000_000_000 {
        let _ = write!(out, "{v:.4}");
        return;
    }
    let a = n.unsigned_abs();
    let (int, frac) = (a / 10_000, (a % 10_000) as usize);
    // At most 22 bytes: a sign, 16 digits, the point and 4 decimals. A fixed-size append is a few
    // stores (a copy of the few bytes written would be a call to `memcpy` per number), and the
    // tail is cut off after.
    let start = out.len();
    out.extend_from_slice(&[0u8; 24]);
    let buf = &mut out[start..];
    let mut i = usize::from(n < 0);
    buf[0] = b'-';
    let digits = match int {
        0..=9 => 1,
        10..=99 => 2,
        100..=999 => 3,
        1000..=9999 => 4,
        _ => {
            let mut d = 5;
            while d < 20 && int >= 10u64.pow(d as u32) {
                d += 1;
            }
            d
        }
    };
    // The integer's digits two at a time from its last, then the four decimals.
    let mut x = int;
    let mut k = i + digits;
    while x >= 10 {
        let pair = (x % 100) as usize * 2;
        buf[k - 2..k].copy_from_slice(&PAIRS[pair..pair + 2]);
        k -= 2;
        x /= 100;
    }
    if k > i {
        buf[k - 1] = b'0' + x as u8;
    }
    i += digits;
    buf[i] = b'.';
    let (hi, lo) = (frac / 100 * 2, frac % 100 * 2);
    buf[i + 1..i + 3].copy_from_slice(&PAIRS[hi..hi + 2]);
    buf[i + 3..i + 5].copy_from_slice(&PAIRS[lo..lo + 2]);
    out.truncate(start + i + 5);
}

/// "00" to "99", for writing numbers two digits at a time.
const PAIRS: &[u8; 200] = b"0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Append `a` in decimal, filled on the left with `fill` to `width` characters.
fn push_uint(out: &mut Vec<u8>, a: u64, width: usize, fill: u8) {
    let mut buf = [0u8; 24];
    let i = put_uint(&mut buf, 24, a, width, fill);
    out.extend_from_slice(&buf[i..]);
}

/// Write `a` in decimal into `buf` so that it ends before `end`, filled on the left with `fill`
/// to `width` characters (at most `end`); returns where it starts.
fn put_uint(buf: &mut [u8], end: usize, mut a: u64, width: usize, fill: u8) -> usize {
    let mut i = end;
    // Two digits at a time while at least three are left, then the last one or two.
    while a >= 100 {
        let pair = (a % 100) as usize * 2;
        buf[i - 2..i].copy_from_slice(&PAIRS[pair..pair + 2]);
        i -= 2;
        a /= 100;
    }
    if a >= 10 {
        let pair = a as usize * 2;
        buf[i - 2..i].copy_from_slice(&PAIRS[pair..pair + 2]);
        i -= 2;
    } else {
        i -= 1;
        buf[i] = b'0' + a as u8;
    }
    while end - i < width.min(end) {
        i -= 1;
        buf[i] = fill;
    }
    i
}

/// Program coordinates with X as a radius.
fn radius_coords(f: &ProgFrame, p: crate::geom::P2) -> (f64, f64) {
    ((p.x - f.origin.x) / f.scale, (p.y - f.origin.y) / f.scale)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    /// The plain way: round, then `{}` of the integer and four decimals (what `f4` did before
    /// it wrote its digits two at a time).
    fn f4_plain(v: f64) -> String {
        let scaled = (v * 1e4).round();
        if !scaled.is_finite() || scaled.abs() >= 9e15 {
            return format!("{v:.4}");
        }
        let n = scaled as i64;
        let a = n.unsigned_abs();
        let sign = if n < 0 { "-" } else { "" };
        format!("{sign}{}.{:04}", a / 10_000, a % 10_000)
    }

    proptest! {
        /// Four decimals as the plain way writes them: any value, values near a half of the last
        /// decimal, near every width, and past the integer range.
        #[test]
        fn four_decimals_are_the_plain_ways(
            v in prop_oneof![
                any::<f64>(),
                (-1e6f64..1e6),
                (-100_000_000i64..100_000_000).prop_map(|k| (k as f64 + 0.5) * 1e-4),
                (0u32..19, -1.0f64..1.0).prop_map(|(k, f)| 10f64.powi(k as i32) * (1.0 + f * 1e-12)),
                Just(9e11), Just(-9e11), Just(8.99999999999999e11), Just(f64::NAN), Just(-0.0),
            ]
        ) {
            let mut s = b"X".to_vec();
            super::f4(&mut s, v);
            prop_assert_eq!(String::from_utf8(s).unwrap(), format!("X{}", f4_plain(v)));
        }

        /// The values written lately give the text `f4` writes, whatever came before: values
        /// repeated, values one bit apart, and more values than the table has slots, so that
        /// slots are taken over.
        #[test]
        fn a_value_written_again_is_written_as_f4_writes_it(
            picks in proptest::collection::vec((0usize..600, 0u8..3), 1..3000),
        ) {
            let base: Vec<f64> = (0..600).map(|k| (k as f64 - 300.0) * 0.37 + 1e-3 * k as f64).collect();
            let mut d = super::Decimals::new();
            let mut cached = Vec::new();
            let mut plain = Vec::new();
            for (k, nudge) in picks {
                let v = match nudge {
                    0 => base[k],
                    1 => f64::from_bits(base[k].to_bits() + 1),
                    _ => -base[k],
                };
                d.put(&mut cached, v);
                super::f4(&mut plain, v);
                cached.push(b' ');
                plain.push(b' ');
            }
            prop_assert_eq!(String::from_utf8(cached).unwrap(), String::from_utf8(plain).unwrap());
        }
    }

    #[test]
    fn four_decimals_match_printf_style() {
        for (v, want) in [
            (0.0, "0.0000"),
            (-0.00004, "0.0000"),
            (-0.00006, "-0.0001"),
            (12.34566, "12.3457"),
            (-25.4, "-25.4000"),
            (1e6, "1000000.0000"),
        ] {
            let mut s = Vec::new();
            super::f4(&mut s, v);
            assert_eq!(String::from_utf8(s).unwrap(), want, "{v}");
        }
    }

    /// Every number below 200,000, every power of ten and its neighbours, and the largest,
    /// against the standard library's formatting, plain and padded.
    #[test]
    fn integers_are_the_standard_decimals() {
        let mut values: Vec<u64> = (0..200_000).collect();
        for k in 0..20 {
            let p = 10u64.pow(k);
            values.extend([p - 1, p, p + 1]);
        }
        values.push(u64::MAX);
        let mut s = Vec::new();
        for a in values {
            s.clear();
            super::push_uint(&mut s, a, 1, b'0');
            assert_eq!(std::str::from_utf8(&s).unwrap(), a.to_string());
            // After other text, which stays as it was.
            s.clear();
            s.extend_from_slice(b"N=");
            super::push_uint(&mut s, a, 6, b'0');
            assert_eq!(std::str::from_utf8(&s).unwrap(), format!("N={a:06}"));
        }
    }

    /// Every count of integer digits, both signs, appended after other text: as `{:.4}` prints.
    #[test]
    fn four_decimals_of_every_width_follow_what_came_before() {
        let mut s = b"X".to_vec();
        let mut want = String::from("X");
        for k in 0..12 {
            let p = 10f64.powi(k);
            for v in [p - 0.00031, p, p + 0.12342, 9.87653 * p] {
                for v in [v, -v] {
                    super::f4(&mut s, v);
                    s.push(b' ');
                    want.push_str(&format!("{v:.4} "));
                }
            }
        }
        assert_eq!(std::str::from_utf8(&s).unwrap(), want);
    }

    /// Four decimals as `{:.4}` prints them, for values whose fifth decimal is far from a tie.
    #[test]
    fn four_decimals_are_the_standard_formatting_away_from_ties() {
        let mut s = Vec::new();
        for k in -300_000i64..300_000 {
            let v = k as f64 * 0.00731 + 0.000_012;
            s.clear();
            super::f4(&mut s, v);
            let want = format!("{v:.4}");
            let want = if want == "-0.0000" { "0.0000".to_string() } else { want };
            assert_eq!(std::str::from_utf8(&s).unwrap(), want, "{v}");
        }
    }

    #[test]
    fn integers_pad_as_printf_does() {
        for (a, width, fill, want) in [
            (0u64, 1, b'0', "0"),
            (7, 4, b'0', "0007"),
            (12345, 4, b'0', "12345"),
            (42, 5, b' ', "   42"),
            (123456, 5, b' ', "123456"),
            (u64::MAX, 1, b'0', "18446744073709551615"),
        ] {
            let mut s = Vec::new();
            super::push_uint(&mut s, a, width, fill);
            let s = String::from_utf8(s).unwrap();
            assert_eq!(s, want);
            assert_eq!(
                s,
                if fill == b' ' {
                    format!("{a:>width$}")
                } else {
                    format!("{a:0width$}")
                }
            );
        }
    }
}
