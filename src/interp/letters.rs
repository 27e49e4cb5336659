//! The letter words of one block (every word but G and M) as plain data: each letter's value,
//! whether it is present, written with a decimal point, where it stands, and whether some code
//! used it. The modal converters (`convert/`), the motion helpers and the canned cycles
//! (`cycles/`) read a block through this and nothing else of it; the G and M codes stay with
//! the block's [`Words`](super::words::Words), which only the order of execution reads.
//!
//! Reading a letter marks it used; a letter present and never used is a `program` finding at the
//! end of the block (`Run::check_unused`).

/// The bit of a letter in the masks of [`Letters`].
pub(crate) const fn bit(letter: u8) -> u32 {
    1 << (letter - b'A')
}

/// The letter words of one block.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Letters {
    /// Each letter's value (read only when its bit in `has` is set).
    pub val: [f64; 26],
    /// Bit per letter: present.
    pub has: u32,
    /// Bit per letter: written with a decimal point.
    pub point: u32,
    /// Byte offset of each letter's word, for columns.
    pub at: [u32; 26],
    /// Bits of letters some code used.
    pub used: u32,
}

impl Letters {
    pub(crate) const fn new() -> Letters {
        Letters {
            val: [0.0; 26],
            has: 0,
            point: 0,
            at: [0; 26],
            used: 0,
        }
    }

    /// Empty again: only the masks (a letter's value is read only when its bit is set).
    pub(crate) fn clear(&mut self) {
        self.has = 0;
        self.point = 0;
        self.used = 0;
    }

    /// The letter's value, the word then used.
    #[inline]
    pub(crate) fn get(&mut self, letter: u8) -> Option<f64> {
        let b = bit(letter);
        if self.has & b != 0 {
            self.used |= b;
            Some(self.val[(letter - b'A') as usize])
        } else {
            None
        }
    }

    /// The letter's value, the word then gone from the block for every later reader (used).
    pub(crate) fn take(&mut self, letter: u8) -> Option<f64> {
        let v = self.get(letter);
        self.has &= !bit(letter);
        v
    }

    /// Every word of the block counted as used (a block refused as a whole).
    pub(crate) fn use_all(&mut self) {
        self.used = self.has;
    }

    /// The letter's word was written with a decimal point.
    pub(crate) fn has_point(&self, letter: u8) -> bool {
        self.point & bit(letter) != 0
    }

    /// The letter is in the block (not marked used).
    #[inline]
    pub(crate) fn peek(&self, letter: u8) -> bool {
        self.has & bit(letter) != 0
    }

    /// The offset of the letter's word, when it is in the block.
    pub(crate) fn at(&self, letter: u8) -> Option<u32> {
        self.peek(letter).then(|| self.at[(letter - b'A') as usize])
    }

    /// Any of X, Z, U, W.
    #[inline]
    pub(crate) fn axis_words(&self) -> bool {
        self.has & (bit(b'X') | bit(b'Z') | bit(b'U') | bit(b'W')) != 0
    }
}
