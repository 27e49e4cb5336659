//! Source text positions: byte spans and the physical line index.

/// A half-open byte range `[start, end)` in a program's source text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Span {
    pub start: u32,
    pub end: u32,
}

impl Span {
    pub fn new(start: usize, end: usize) -> Span {
        Span {
            start: start as u32,
            end: end as u32,
        }
    }

    pub fn range(self) -> std::ops::Range<usize> {
        self.start as usize..self.end as usize
    }
}

/// The physical lines of a text: `(start, end)` of each, the end without its terminator (LF,
/// CRLF or a lone CR). An empty text is one empty line; a terminator at the very end starts no
/// further line.
pub fn lines(src: &[u8]) -> Lines<'_> {
    Lines {
        src,
        next: 0,
        done: false,
    }
}

/// The physical lines of `src` from the line that starts at byte `start` on, as [`lines`] gives
/// them.
pub(crate) fn lines_from(src: &[u8], start: usize) -> Lines<'_> {
    Lines {
        src,
        next: start,
        done: start > src.len() || (start == src.len() && start != 0),
    }
}

/// The iterator of [`lines`].
pub struct Lines<'a> {
    src: &'a [u8],
    next: usize,
    done: bool,
}

impl Iterator for Lines<'_> {
    type Item = (usize, usize);

    #[inline]
    fn next(&mut self) -> Option<(usize, usize)> {
        if self.done {
            return None;
        }
        let (src, start) = (self.src, self.next);
        let end = line_end(src, start).unwrap_or(src.len());
        self.next = after_terminator(src, end);
        self.done = self.next >= src.len();
        Some((start, end))
    }
}

/// Where the line after the one ending at byte `end` (its terminator's first byte, or the end
/// of the text) starts: past its LF, CRLF or lone CR (past the text's end when none follows).
#[inline]
pub(crate) fn after_terminator(src: &[u8], end: usize) -> usize {
    let crlf = src.get(end) == Some(&b'\r') && src.get(end + 1) == Some(&b'\n');
    end + 1 + crlf as usize
}

/// Eight copies of a byte.
const fn splat(b: u8) -> u64 {
    0x0101_0101_0101_0101 * b as u64
}

/// 0x80 in each byte of `x` that is zero, 0 in the others (exact: no borrow between bytes).
#[inline(always)]
fn zero_bytes(x: u64) -> u64 {
    const M: u64 = splat(0x7F);
    !(((x & M) + M) | x | M)
}

/// The first LF or CR at or after `from`, eight bytes at a time (lines are short, so a search
/// that must be set up for each line would cost more than it saves).
#[inline]
fn line_end(src: &[u8], from: usize) -> Option<usize> {
    let mut i = from;
    while let Some(chunk) = src.get(i..i + 8) {
        let w = u64::from_le_bytes(chunk.try_into().unwrap_or([0; 8]));
        let hits = zero_bytes(w ^ splat(b'\n')) | zero_bytes(w ^ splat(b'\r'));
        if hits != 0 {
            return Some(i + (hits.trailing_zeros() / 8) as usize);
        }
        i += 8;
    }
    src[i..].iter().position(|&b| b == b'\n' || b == b'\r').map(|k| i + k)
}

/// The number of LF bytes.
pub(crate) fn count_lf(src: &[u8]) -> usize {
    let mut chunks = src.chunks_exact(8);
    let mut n = 0;
    for c in &mut chunks {
        let w = u64::from_le_bytes(c.try_into().unwrap_or([0; 8]));
        n += zero_bytes(w ^ splat(b'\n')).count_ones() as usize;
    }
    n + chunks.remainder().iter().filter(|&&b| b == b'\n').count()
}

/// Where each physical line starts. Lines end at LF, CRLF or a lone CR.
#[derive(Clone, Debug, Default)]
pub struct LineIndex {
    /// Byte offset of the first byte of each line; `starts[0] == 0`.
    starts: Vec<u32>,
    len: u32,
}

impl LineIndex {
    pub fn new(src: &[u8]) -> LineIndex {
        let mut starts = Vec::with_capacity(count_lf(src) + 1);
        starts.extend(lines(src).map(|(start, _)| start as u32));
        LineIndex::from_starts(starts, src.len())
    }

    /// The index of lines that start at `starts` (ascending, `starts[0] == 0`, no start at the
    /// end of the text) in a text of `len` bytes.
    pub(crate) fn from_starts(starts: Vec<u32>, len: usize) -> LineIndex {
        debug_assert!(starts.first() == Some(&0) && starts.windows(2).all(|w| w[0] < w[1]));
        LineIndex {
            starts,
            len: len as u32,
        }
    }

    pub fn line_count(&self) -> usize {
        self.starts.len()
    }

    /// 1-based line number of a byte offset.
    pub fn line_of(&self, offset: u32) -> u32 {
        match self.starts.binary_search(&offset) {
            Ok(i) => i as u32 + 1,
            Err(i) => i as u32,
        }
    }

    /// Byte range of a 1-based line, without its terminator.
    pub fn line_span(&self, src: &[u8], line: u32) -> Span {
        let i = (line.max(1) - 1) as usize;
        let start = self.starts.get(i).copied().unwrap_or(self.len) as usize;
        let mut end = self.starts.get(i + 1).map(|&s| s as usize).unwrap_or(src.len());
        while end > start && (src[end - 1] == b'\n' || src[end - 1] == b'\r') {
            end -= 1;
        }
        Span::new(start, end)
    }

    /// 1-based column, in characters, of a byte offset on its line.
    pub fn col_of(&self, src: &[u8], offset: u32) -> u32 {
        let line = self.line_of(offset);
        let start = self.starts[(line - 1) as usize] as usize;
        let end = (offset as usize).min(src.len());
        chars(&src[start.min(end)..end]) + 1
    }
}

/// Columns of offsets asked for one after another, each counted from the previous one on the same
/// line rather than from the line start: a line with many findings costs the distance the offsets
/// travel (one pass for offsets in order), not a count from the line start per finding.
#[derive(Clone, Copy, Debug)]
pub struct ColCursor {
    /// Start of the line of the last offset asked for (`u32::MAX`: none yet).
    line_start: u32,
    offset: u32,
    col: u32,
}

/// Characters (UTF-8 scalar starts; stray bytes count one each) in `text`.
fn chars(text: &[u8]) -> u32 {
    text.iter().filter(|&&b| (b & 0xC0) != 0x80).count() as u32
}

impl Default for ColCursor {
    /// A cursor on no line yet (the derived all-zero one would count columns on line 1 from 0).
    fn default() -> ColCursor {
        ColCursor::new()
    }
}

impl ColCursor {
    pub fn new() -> ColCursor {
        ColCursor {
            line_start: u32::MAX,
            offset: 0,
            col: 0,
        }
    }

    /// [`col_of`], counted from the last offset when it is on the same line (no line starts
    /// between them: the bytes between are looked at once).
    pub fn col_of(&mut self, src: &[u8], offset: u32) -> u32 {
        let offset = offset.min(src.len() as u32);
        let on_from_last = self.line_start != u32::MAX && offset >= self.offset;
        let (start, col) = match on_from_last.then(|| line_start_after(src, offset as usize, self.offset as usize)) {
            Some(None) => (
                self.line_start,
                self.col + chars(&src[self.offset as usize..offset as usize]),
            ),
            Some(Some(start)) => (start as u32, chars(&src[start..offset as usize]) + 1),
            None => {
                let start = line_start_after(src, offset as usize, 0).unwrap_or(0);
                (start as u32, chars(&src[start..offset as usize]) + 1)
            }
        };
        *self = ColCursor {
            line_start: start,
            offset,
            col,
        };
        col
    }
}

/// 1-based column, in characters, of byte `offset` on its line (as [`LineIndex::col_of`] counts
/// it), found by looking back from the offset to the line's start: no index of the lines needed.
pub fn col_of(src: &[u8], offset: u32) -> u32 {
    ColCursor::new().col_of(src, offset)
}

/// Where the line holding byte `offset` starts, as [`lines`] cuts the text, when that is after
/// byte `floor`: `None` when no line starts in `floor + 1 ..= offset`. A line starts after an LF,
/// and after a CR not followed by an LF; never at the end of the text (a terminator there starts
/// no further line).
fn line_start_after(src: &[u8], offset: usize, floor: usize) -> Option<usize> {
    let mut k = offset.min(src.len());
    while k > floor {
        let b = src[k - 1];
        if k < src.len() && (b == b'\n' || (b == b'\r' && src[k] != b'\n')) {
            return Some(k);
        }
        k -= 1;
    }
    None
}

#[cfg(test)]
mod tests {
    #[test]
    fn line_ends_are_found_at_every_offset_and_byte() {
        // The word-at-a-time search against the plain one, for terminators at every position of a
        // chunk and next to bytes that differ from them by one bit.
        for len in 0..40 {
            for at in 0..len {
                for term in [b'\n', b'\r'] {
                    for filler in [b'a', 0x0B, 0x0C, 0x8A, 0x8D, 0x00, 0xFF, b'\n' ^ 0x80] {
                        let mut src = vec![filler; len];
                        src[at] = term;
                        for from in 0..=at {
                            let want = src[from..]
                                .iter()
                                .position(|&b| b == b'\n' || b == b'\r')
                                .map(|k| from + k);
                            assert_eq!(super::line_end(&src, from), want, "len {len} at {at} from {from}");
                        }
                        let lf = src.iter().filter(|&&b| b == b'\n').count();
                        assert_eq!(super::count_lf(&src), lf);
                    }
                }
            }
        }
    }

    #[test]
    fn column_cursor_agrees_with_counting_from_the_line_start() {
        let texts = [
            "a\u{e9}b (\u{20ac}x) c\r\nxy\u{1F600}z\rq\n\u{e9}\u{e9}",
            "",
            "\n",
            "\r",
            "\r\n",
            "a\r\r\nb\n",
            "\n\nab\r\n\r\n",
            "x\ry\r",
        ];
        for text in texts {
            let src = text.as_bytes();
            let li = super::LineIndex::new(src);
            let mut cur = super::ColCursor::new();
            // Forward, backward, across lines, repeated and past the end.
            let n = src.len() as u32;
            let mut offsets: Vec<u32> = (0..=n + 2).collect();
            offsets.extend((0..=n).rev());
            offsets.extend([5, 5, 0, 17, 3, 20, 2, 1, 1, 0]);
            for o in offsets {
                let want = li.col_of(src, o.min(n));
                assert_eq!(cur.col_of(src, o), want, "{text:?} offset {o}");
                assert_eq!(super::col_of(src, o), want, "{text:?} offset {o}");
            }
        }
    }

    #[test]
    fn lines_and_the_index_agree_on_every_terminator() {
        for text in ["", "a", "a\n", "a\nb", "\n\n", "a\r\nb\rc\n", "\r", "\r\n", "a\r\r\nb"] {
            let src = text.as_bytes();
            let li = super::LineIndex::new(src);
            let spans: Vec<(usize, usize)> = super::lines(src).collect();
            assert_eq!(li.line_count(), spans.len(), "{text:?}");
            for (k, &(s, e)) in spans.iter().enumerate() {
                assert_eq!(li.line_span(src, k as u32 + 1), super::Span::new(s, e), "{text:?}");
            }
        }
    }
}
