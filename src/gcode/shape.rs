//! Whether a line is a plain line, decided without reading it.
//!
//! The first reading of a long program keeps only its first windows (`window.rs`); the blocks of
//! the windows after them are dropped and read again when the interpreter reaches them. What
//! the first reading must learn of a dropped window is how many blocks it holds and what its
//! lines add to the whole program (syntax findings, comments, expressions, names). A plain line
//! ([`Reader::read_plain_line`](super::lexer): an optional N number, then words whose values are
//! plain numbers) adds nothing but its block, so for those windows it is enough to know that a
//! line is plain and whether it makes a block (a line of blanks makes none). [`plain_shape`]
//! decides both with one table lookup per byte; every other line is read as usual.
//!
//! The automaton follows the fast reader rule for rule: blanks, then an optional `N` with 1 to
//! 18 digits, then words: a letter other than N and O (either case), an optional `-`, digits
//! with at most one point and 1 to 15 digits in all; after an N number or a value, blanks may
//! follow but not a digit or a point (`X1 0.5` is `X10.5`, which the general reader reads). A
//! unit test holds it to the fast reader on every line of a small alphabet up to a length and
//! on random lines.

/// What a byte is to the automaton.
#[derive(Clone, Copy)]
enum Class {
    Blank,
    Digit,
    Point,
    Minus,
    /// A letter that starts a word (not N or O).
    Letter,
    N,
    O,
    Other,
}

const fn class(b: u8) -> Class {
    match b {
        b' ' | b'\t' => Class::Blank,
        b'0'..=b'9' => Class::Digit,
        b'.' => Class::Point,
        b'-' => Class::Minus,
        b'N' | b'n' => Class::N,
        b'O' | b'o' => Class::O,
        b'A'..=b'Z' | b'a'..=b'z' => Class::Letter,
        _ => Class::Other,
    }
}

// States. A number's state counts its digits so far, which is how the automaton holds the
// limits of 18 digits for N and 15 for a value.
/// Blanks at the start of the line.
const START: u8 = 0;
/// After `N` and k digits: `N_DIGITS + k`, k = 0..=18.
const N_DIGITS: u8 = 1;
/// Blanks after an N number.
const N_BLANKS: u8 = 20;
/// After a word's letter.
const LETTER: u8 = 21;
/// After a word's letter and `-`.
const MINUS: u8 = 22;
/// k digits of a value and no point: `INT + k - 1`, k = 1..=15.
const INT: u8 = 23;
/// A point and k digits of a value in all: `FRAC + k`, k = 0..=15.
const FRAC: u8 = 38;
/// Blanks after a value.
const BLANKS: u8 = 54;
/// Not a plain line (absorbing).
const NO: u8 = 55;
const STATES: usize = 56;

/// The next state of `s` on a byte of class `c`.
const fn step(s: u8, c: Class) -> u8 {
    use Class::*;
    if s == START {
        match c {
            Blank => START,
            N => N_DIGITS,
            Letter => LETTER,
            _ => NO,
        }
    } else if s >= N_DIGITS && s <= N_DIGITS + 18 {
        let k = s - N_DIGITS;
        match c {
            Digit if k < 18 => s + 1,
            Blank if k >= 1 => N_BLANKS,
            Letter if k >= 1 => LETTER,
            _ => NO,
        }
    } else if s == N_BLANKS || s == BLANKS {
        match c {
            Blank => s,
            Letter => LETTER,
            _ => NO,
        }
    } else if s == LETTER {
        match c {
            Minus => MINUS,
            Digit => INT,
            Point => FRAC,
            _ => NO,
        }
    } else if s == MINUS {
        match c {
            Digit => INT,
            Point => FRAC,
            _ => NO,
        }
    } else if s >= INT && s < INT + 15 {
        let k = s - INT + 1;
        match c {
            Digit if k < 15 => s + 1,
            Point => FRAC + k,
            Blank => BLANKS,
            Letter => LETTER,
            _ => NO,
        }
    } else if s >= FRAC && s <= FRAC + 15 {
        let k = s - FRAC;
        match c {
            Digit if k < 15 => s + 1,
            Blank if k >= 1 => BLANKS,
            Letter if k >= 1 => LETTER,
            _ => NO,
        }
    } else {
        NO
    }
}

/// The automaton by state and byte: 256 rows, so that no state a byte leads to is out of the
/// table (the rows past the last state are never reached, and say NO).
static NEXT: [[u8; 256]; 256] = {
    let mut t = [[NO; 256]; 256];
    let mut s = 0;
    while s < STATES {
        let mut b = 0;
        while b < 256 {
            t[s][b] = step(s as u8, class(b as u8));
            b += 1;
        }
        s += 1;
    }
    t
};

/// Whether a line is plain as the fast reader reads it, and if so whether it makes a block
/// (`Some(false)`: blanks only). `None`: the line is not plain (the general reader decides it).
#[inline]
pub(super) fn plain_shape(line: &[u8]) -> Option<bool> {
    let mut s = START;
    for &b in line {
        s = NEXT[s as usize][b as usize];
    }
    // A line ends well after blanks, an N number or a value with digits.
    match s {
        START => Some(false),
        N_BLANKS | BLANKS => Some(true),
        _ if (N_DIGITS + 1..=N_DIGITS + 18).contains(&s) => Some(true),
        _ if (INT..INT + 15).contains(&s) => Some(true),
        _ if (FRAC + 1..=FRAC + 15).contains(&s) => Some(true),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::plain_shape;
    use crate::gcode::lexer::fast_reading;

    #[test]
    fn the_shape_of_a_line_is_what_the_fast_reader_makes_of_it() {
        // Every line of up to five bytes over bytes of each class and their neighbours.
        let alphabet = b" \t09.-+GxNnOo(#e\xC3/";
        let mut line = Vec::new();
        let mut lines = 0;
        for len in 0..=5u32 {
            for mut code in 0..alphabet.len().pow(len) {
                line.clear();
                for _ in 0..len {
                    line.push(alphabet[code % alphabet.len()]);
                    code /= alphabet.len();
                }
                assert_eq!(
                    plain_shape(&line),
                    fast_reading(&line),
                    "{:?}",
                    String::from_utf8_lossy(&line)
                );
                lines += 1;
            }
        }
        assert!(lines > 2_000_000);
        // Numbers at and past their limits: 15 digits of a value, 18 of an N number, with the
        // point anywhere, and what may follow them.
        for digits in 0..=20 {
            for point in 0..=digits + 1 {
                for (head, tail) in [
                    ("X", ""),
                    ("x-", " G1"),
                    ("N", " X1"),
                    ("N", ""),
                    ("G1 Z", " 5"),
                    ("Z", "."),
                ] {
                    let mut l = head.as_bytes().to_vec();
                    for k in 0..digits {
                        if k == point {
                            l.push(b'.');
                        }
                        l.push(b'0' + (k % 10) as u8);
                    }
                    if point == digits {
                        l.push(b'.');
                    }
                    l.extend_from_slice(tail.as_bytes());
                    assert_eq!(plain_shape(&l), fast_reading(&l), "{:?}", String::from_utf8_lossy(&l));
                }
            }
        }
    }
}
