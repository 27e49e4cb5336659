//! A program's blocks held a window at a time.
//!
//! A long program's blocks and words would be most of the memory a check takes (a `Block` per
//! line, a `Word` per word: about seven bytes for each byte of source). So [`Program`] keeps
//! them only for a few windows of [`WINDOW_BLOCKS`] consecutive blocks and reads a window again
//! from the source when it is asked for after it left the cache. What stays for the whole
//! program is what the reader finds once and the interpreter looks up anywhere: the syntax
//! findings, the comments, the expressions, the names and the line index, and one [`Mark`] per
//! window (where its lines start and where its expressions' ids start).
//!
//! Why a window read again is the window read first: the reader reads each line on its own (no
//! state crosses a line end but the name table and the expression arena's length), so a window
//! read again from its first line, with the name table of the whole program and its expressions
//! numbered from the window's first id, gives the same blocks, words, assignments and ids. Its
//! findings, comments and expressions are the first reading's and are dropped (the unit tests
//! hold every window of a program read one block at a time equal to a whole reading).
//!
//! A program of at most `CACHED_WINDOWS` windows (32k blocks) is read once and kept whole. A
//! flow that jumps among more windows than that, again and again, reads each window again at
//! most a few times: past twice the number of windows, every window read is kept.

use super::{lexer, Assign, Block, NameId, Program, Word};
use std::cell::{Cell, RefCell};
use std::collections::HashMap;
use std::rc::Rc;

/// Blocks per window.
pub const WINDOW_BLOCKS: usize = 4096;

/// Windows kept at once.
pub(super) const CACHED_WINDOWS: usize = 8;

/// Consecutive blocks with their words and assignments (the blocks' ranges index these).
#[derive(Debug, Default)]
pub struct Window {
    /// The program index of `blocks[0]`.
    pub(super) first: usize,
    pub(super) blocks: Vec<Block>,
    pub(super) words: Vec<Word>,
    pub(super) assigns: Vec<Assign>,
}

impl Window {
    fn holds(&self, i: usize) -> bool {
        i.wrapping_sub(self.first) < self.blocks.len()
    }
}

/// Where a window starts.
#[derive(Clone, Copy, Debug)]
pub(super) struct Mark {
    /// The program index of its first block.
    pub first_block: usize,
    /// The physical line its reading starts at (the line after the previous window's last block).
    pub line: u32,
    /// The byte that line starts at (the end of the source when no line follows).
    pub start: u32,
    /// The id its first expression takes.
    pub expr_base: u32,
    /// Some block of it has assignments, an O-word, a message or a macro statement
    /// ([`Block::rare`]).
    pub rare: bool,
}

/// The windows of a program and the few it holds.
#[derive(Debug, Default)]
pub(super) struct Store {
    /// Blocks in the program.
    pub len: usize,
    pub marks: Vec<Mark>,
    /// How the program was read (a window is read again the same way).
    pub macro_b: bool,
    pub plain_lines_fast: bool,
    /// The whole program's name table, for reading a window again.
    pub interned: RefCell<HashMap<String, NameId>>,
    /// The windows held, most recently used first.
    pub cache: RefCell<Vec<Rc<Window>>>,
    /// Windows read again since the first reading.
    pub rereads: Cell<u64>,
    /// Of those, the ones [`Program::block`] read (a flow's jumps; not the whole-program walks,
    /// which read each window once each).
    pub jumps: Cell<u64>,
}

/// A block of a program, with its words and assignments: it keeps its window alive, so it
/// stays valid whatever else of the program is read meanwhile. Derefs to [`Block`].
#[derive(Clone)]
pub struct BlockRef {
    win: Rc<Window>,
    k: usize,
}

impl std::ops::Deref for BlockRef {
    type Target = Block;

    #[inline]
    fn deref(&self) -> &Block {
        &self.win.blocks[self.k]
    }
}

impl std::fmt::Debug for BlockRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        (**self).fmt(f)
    }
}

impl BlockRef {
    /// Its index in the program.
    pub fn index(&self) -> usize {
        self.win.first + self.k
    }

    /// Its words, in source order.
    #[inline]
    pub fn words(&self) -> &[Word] {
        let r = &self.win.blocks[self.k].words;
        &self.win.words[r.start as usize..r.end as usize]
    }

    /// Its parameter assignments, in source order.
    pub fn assigns(&self) -> &[Assign] {
        let r = self.win.blocks[self.k].assigns();
        &self.win.assigns[r.start as usize..r.end as usize]
    }
}

impl Program<'_> {
    /// The number of blocks.
    pub fn len(&self) -> usize {
        self.store.len
    }

    pub fn is_empty(&self) -> bool {
        self.store.len == 0
    }

    /// Block `i` (panics past the end, as indexing does).
    #[inline]
    pub fn block(&self, i: usize) -> BlockRef {
        assert!(i < self.store.len, "block {i} of {}", self.store.len);
        let mut cache = self.store.cache.borrow_mut();
        if let Some(w) = cache.first().filter(|w| w.holds(i)) {
            return BlockRef {
                win: w.clone(),
                k: i - w.first,
            };
        }
        let win = match cache.iter().position(|w| w.holds(i)) {
            Some(p) => {
                cache[..=p].rotate_right(1);
                cache[0].clone()
            }
            None => {
                self.store.jumps.set(self.store.jumps.get() + 1);
                // A flow that keeps jumping among more windows than the cache holds would read
                // a window for every block it runs: once the windows read again for its blocks
                // outnumber the program's windows twice over, every window read stays (the
                // program whole, as it was before windows), so the reading never costs more
                // than a few readings of the program.
                let evict = self.store.jumps.get() <= 2 * self.store.marks.len() as u64 + 16;
                // The window that leaves the cache lends its buffers to the one read, when no
                // block of it is still in use: memory already touched instead of fresh pages.
                // (While windows are evicted the cache never holds more than it may: it grows
                // past that only once they no longer are, and `jumps` never goes down.)
                debug_assert!(!evict || cache.len() <= CACHED_WINDOWS);
                let spare = if evict && cache.len() >= CACHED_WINDOWS {
                    cache.pop().and_then(|w| Rc::try_unwrap(w).ok())
                } else {
                    None
                };
                let w = Rc::new(self.read_window(self.window_of(i), spare));
                cache.insert(0, w.clone());
                w
            }
        };
        BlockRef { k: i - win.first, win }
    }

    /// Every block in order. Windows not held are read for the walk and not kept (a scan of the
    /// whole program does not push out the windows a run is working in).
    pub fn blocks(&self) -> impl Iterator<Item = BlockRef> + '_ {
        (0..self.store.marks.len()).flat_map(move |k| self.window_blocks(k))
    }

    /// Every block with assignments, an O-word, a message or a macro statement ([`Block::rare`]),
    /// in order: [`Program::blocks`] with the windows that hold none of them skipped unread.
    pub fn rare_blocks(&self) -> impl Iterator<Item = BlockRef> + '_ {
        let windows = (0..self.store.marks.len()).filter(|&k| self.store.marks[k].rare);
        windows
            .flat_map(move |k| self.window_blocks(k))
            .filter(|b| b.rare.is_some())
    }

    /// The blocks of window `k`, read for the walk if it is not held.
    fn window_blocks(&self, k: usize) -> impl Iterator<Item = BlockRef> {
        let first = self.store.marks[k].first_block;
        let held = self.store.cache.borrow().iter().find(|w| w.first == first).cloned();
        let win = held.unwrap_or_else(|| Rc::new(self.read_window(k, None)));
        (0..win.blocks.len()).map(move |j| BlockRef { win: win.clone(), k: j })
    }

    /// The block of a physical line, if the line has one.
    pub fn block_at_line(&self, line: u32) -> Option<BlockRef> {
        // The window whose reading starts at or before the line, then the block in it.
        let k = self.store.marks.partition_point(|m| m.line <= line).checked_sub(1)?;
        let m = self.store.marks[k];
        let end = self.store.marks.get(k + 1).map_or(self.store.len, |n| n.first_block);
        let (mut lo, mut hi) = (m.first_block, end);
        while lo < hi {
            let mid = (lo + hi) / 2;
            if self.block(mid).line < line {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        (lo < end).then(|| self.block(lo)).filter(|b| b.line == line)
    }

    /// Windows read again from the source since the first reading (what jumping about a long
    /// program costs; tests bound it).
    pub fn windows_reread(&self) -> u64 {
        self.store.rereads.get()
    }

    fn window_of(&self, i: usize) -> usize {
        self.store.marks.partition_point(|m| m.first_block <= i) - 1
    }

    /// Window `k` read again from the source.
    /// Window `k` read again, into the buffers of `spare` when given.
    fn read_window(&self, k: usize, spare: Option<Window>) -> Window {
        self.store.rereads.set(self.store.rereads.get() + 1);
        let m = self.store.marks[k];
        let end = self.store.marks.get(k + 1).map_or(self.store.len, |n| n.first_block);
        let mut interned = self.store.interned.borrow_mut();
        lexer::reread(self, m, end - m.first_block, &mut interned, spare)
    }
}
