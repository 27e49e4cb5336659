//! A block's words as the order of execution reads them: its G and M codes (with a bit per known
//! code, so a converter asks "is G41 here" in one test) and its letter words
//! ([`Letters`], plain data, what the converters and the cycles read); reading them from the
//! parsed block (values evaluated, Fanuc's least input increment applied, a builder's own G code
//! numbers mapped); and the finding for a letter word no code used.

use super::flow::Run;
use super::letters::{bit, Letters};
use crate::gcode::{Block, BlockRef};
use crate::machine::{DecimalPoint, Dialect};

/// Most G or M codes one block may hold.
pub(crate) const MAX_CODES: usize = 16;

/// Every G code (×10) some dialect knows; its index is its bit in [`Words::gbits`].
pub(crate) const KNOWN_G: [u16; 82] = [
    0, 10, 20, 30, 330, 800, 320, 331, 760, 700, 710, 720, 711, 712, 721, 722, 730, 740, 750, 810, 820, 830, 840, 850,
    860, 870, 880, 890, 170, 180, 190, 900, 910, 920, 940, 901, 911, 930, 950, 980, 990, 200, 210, 400, 410, 420, 411,
    421, 430, 431, 490, 540, 550, 560, 570, 580, 590, 610, 611, 640, 960, 970, 70, 80, 40, 280, 281, 300, 301, 530,
    100, 500, 520, 921, 922, 923, 770, 780, 790, 121, 131, 71,
];

/// Bit index of each G code below 1000 in [`KNOWN_G`]; 255 for the others.
const G_INDEX: [u8; 1000] = {
    let mut t = [255u8; 1000];
    let mut i = 0;
    while i < KNOWN_G.len() {
        t[KNOWN_G[i] as usize] = i as u8;
        i += 1;
    }
    t
};

/// The bit of a known G code (×10); 0 for a code outside [`KNOWN_G`] (a test checks that every
/// code the order of execution and its converters ask about is in the list).
#[inline(always)]
pub(crate) const fn gb(code: u16) -> u128 {
    if code < 1000 && G_INDEX[code as usize] != 255 {
        1u128 << G_INDEX[code as usize]
    } else {
        0
    }
}

/// The evaluated words of one block.
pub(crate) struct Words {
    /// The letter words (every word but G and M).
    pub letters: Letters,
    /// G codes ×10 (G33.1 → 331) with their offsets, in block order.
    pub g: [(u16, u32); MAX_CODES],
    pub ng: usize,
    pub m: [(u16, u32); MAX_CODES],
    pub nm: usize,
    /// Bit per known G code present (see [`gb`]).
    gbits: u128,
    /// Bit per M code below 128 present.
    mbits: u128,
}

/// A block's words read as its letter words (`w.get(b'X')`, `w.peek(b'F')`, …).
impl std::ops::Deref for Words {
    type Target = Letters;
    #[inline(always)]
    fn deref(&self) -> &Letters {
        &self.letters
    }
}

impl std::ops::DerefMut for Words {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut Letters {
        &mut self.letters
    }
}

impl Words {
    pub(crate) fn new() -> Words {
        Words {
            letters: Letters::new(),
            g: [(0, 0); MAX_CODES],
            ng: 0,
            m: [(0, 0); MAX_CODES],
            nm: 0,
            gbits: 0,
            mbits: 0,
        }
    }

    /// Empty again: only the masks and counts (a letter's value is read only when its bit is set).
    pub(crate) fn clear(&mut self) {
        self.letters.clear();
        self.ng = 0;
        self.nm = 0;
        self.gbits = 0;
        self.mbits = 0;
    }

    /// No word at all (codes or letters).
    pub(crate) fn is_empty(&self) -> bool {
        self.ng == 0 && self.nm == 0 && self.letters.has == 0
    }

    /// The offset of the G code's word, also for codes outside [`KNOWN_G`] (G112, G113).
    pub(crate) fn find_g(&self, code: u16) -> Option<u32> {
        self.g[..self.ng].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The G code (×10) is in the block.
    #[inline(always)]
    pub(crate) fn g(&self, code: u16) -> bool {
        self.gbits & gb(code) != 0
    }

    /// Any of the G codes whose bits are in `mask`.
    #[inline(always)]
    pub(crate) fn any_g(&self, mask: u128) -> bool {
        self.gbits & mask != 0
    }

    /// The M code is in the block.
    #[inline(always)]
    pub(crate) fn m(&self, code: u16) -> bool {
        code < 128 && self.mbits & (1u128 << code) != 0
    }

    /// The offset of the G code's word, when it is in the block.
    pub(crate) fn has_g(&self, code: u16) -> Option<u32> {
        if !self.g(code) {
            return None;
        }
        self.g[..self.ng].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The offset of the M code's word, when it is in the block.
    pub(crate) fn has_m(&self, code: u16) -> Option<u32> {
        if !self.m(code) {
            return None;
        }
        self.m[..self.nm].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The M codes of the block with their offsets, in block order.
    pub(crate) fn m_codes(&self) -> &[(u16, u32)] {
        &self.m[..self.nm]
    }
}

impl Run<'_> {
    /// Read the words of a block. `None` when a value could not be evaluated (already reported).
    pub(crate) fn read_words(&mut self, b: &BlockRef, w: &mut Words) -> bool {
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let increment = fanuc && self.machine.decimal_point == DecimalPoint::Increment;
        let mut ok = true;
        for word in b.words() {
            let v = match self.word_value(word.value()) {
                Ok(Some(v)) => v,
                Ok(None) => continue, // Fanuc: a vacant value leaves the word out
                Err(m) => {
                    self.eval_error(b, Some(word.at), m);
                    ok = false;
                    continue;
                }
            };
            let letter = word.letter;
            if !letter.is_ascii_uppercase() {
                ok = false;
                continue;
            }
            let at = word.at;
            match letter {
                b'G' | b'M' => {
                    let scaled = v * 10.0;
                    let code = scaled.round();
                    if (scaled - code).abs() > 1e-6 || !(0.0..=9999.0).contains(&code) {
                        self.error(
                            b,
                            Some(at),
                            format!("{}{v}: a code number has at most one decimal", letter as char),
                        );
                        ok = false;
                        continue;
                    }
                    let code = code as u16;
                    if letter == b'M' && code % 10 != 0 {
                        self.unsupported(b, Some(at), format!("M{v} is not a code latheguard knows"), false);
                        continue;
                    }
                    let (list, n) = if letter == b'G' {
                        (&mut w.g, &mut w.ng)
                    } else {
                        (&mut w.m, &mut w.nm)
                    };
                    if *n == MAX_CODES {
                        self.error(
                            b,
                            Some(at),
                            format!("more than {MAX_CODES} {} codes in one block", letter as char),
                        );
                        ok = false;
                        continue;
                    }
                    let code = if letter == b'M' { code / 10 } else { code };
                    // A builder's own number for a code (`[gcodes]`): the code it runs as, or
                    // a mode switch that moves nothing.
                    let code = match (letter, self.machine.gcodes.get(code)) {
                        (b'G', Some(crate::machine::GAlias::As(c))) => c,
                        (b'G', Some(crate::machine::GAlias::Ignore)) => continue,
                        _ => code,
                    };
                    list[*n] = (code, at);
                    *n += 1;
                    if letter == b'G' {
                        w.gbits |= gb(code);
                    } else if code < 128 {
                        w.mbits |= 1u128 << code;
                    }
                }
                _ => {
                    let bit = bit(letter);
                    if w.has & bit != 0 {
                        self.error(b, Some(at), format!("{} word given twice in one block", letter as char));
                        ok = false;
                        continue;
                    }
                    let mut v = v;
                    // A value from an expression (Fanuc: a variable) is in mm or inches, never scaled.
                    let plain = matches!(word.value(), crate::gcode::Value::Num(_));
                    if increment
                        && plain
                        && !word.has_point
                        && (matches!(letter, b'X' | b'Z' | b'U' | b'W' | b'I' | b'K' | b'R')
                            || (self.tm.is_some() && matches!(letter, b'Y' | b'V' | b'C' | b'H' | b'B' | b'A' | b'J')))
                    {
                        v *= if self.modal.inch { 0.0001 } else { 0.001 };
                    }
                    w.has |= bit;
                    if word.has_point {
                        w.point |= bit;
                    }
                    w.val[(letter - b'A') as usize] = v;
                    w.at[(letter - b'A') as usize] = at;
                }
            }
        }
        ok
    }

    #[inline]
    pub(crate) fn check_unused(&mut self, b: &Block, w: &Letters) {
        let unused = w.has & !w.used;
        if unused != 0 {
            self.report_unused(b, w, unused);
        }
    }

    #[cold]
    fn report_unused(&mut self, b: &Block, w: &Letters, unused: u32) {
        for i in 0..26u8 {
            if unused & (1 << i) != 0 {
                let letter = (b'A' + i) as char;
                let why = match letter {
                    'I' | 'K' => "an arc center needs G2 or G3",
                    'J' => "J is the Y offset of an arc; a lathe works in XZ (G18)",
                    'R' => "R is an arc radius or a cycle value",
                    'A' | 'B' | 'C' | 'V' if self.tm.is_none() => "this machine has no such axis",
                    'A' | 'B' | 'C' | 'V' | 'Y' if self.tm.is_some() => {
                        "this machine has no such axis, or no code in this block moves it"
                    }
                    'P' | 'Q' | 'L' | 'E' | 'D' | 'H' => "no code in this block takes it",
                    _ => "no code in this block uses it",
                };
                self.error(
                    b,
                    Some(w.at[i as usize]),
                    format!("{letter} word has no use here: {why}"),
                );
            }
        }
    }
}
