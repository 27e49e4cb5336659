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

/// Where each physical line starts. Lines end at LF, CRLF or a lone CR.
#[derive(Clone, Debug, Default)]
pub struct LineIndex {
    /// Byte offset of the first byte of each line; `starts[0] == 0`.
    starts: Vec<u32>,
    len: u32,
}

impl LineIndex {
    pub fn new(src: &[u8]) -> LineIndex {
        let mut starts = vec![0u32];
        let mut i = 0;
        while i < src.len() {
            match src[i] {
                b'\n' => starts.push((i + 1) as u32),
                b'\r' => {
                    if src.get(i + 1) == Some(&b'\n') {
                        i += 1;
                    }
                    starts.push((i + 1) as u32);
                }
                _ => {}
            }
            i += 1;
        }
        if starts.len() > 1 && *starts.last().unwrap() as usize == src.len() {
            starts.pop();
        }
        LineIndex {
            starts,
            len: src.len() as u32,
        }
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
        let text = &src[start..end];
        // Count UTF-8 scalar starts; stray bytes count one each.
        text.iter().filter(|&&b| (b & 0xC0) != 0x80).count() as u32 + 1
    }
}
