//! A program as [`super::assume`] reads it: its moves in program coordinates (mm, `r` the
//! radius, `z` from program zero), each with its line and station, and its source lines.

use crate::interp::{Feed, MoveKind};
use crate::machine::Machine;
use std::borrow::Cow;

pub use super::segs::Segs;

/// What a move is, for reading the setup.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SegKind {
    Rapid,
    /// G1, G2/G3 and the passes of cycles, at feed.
    Feed,
}

/// A straight piece of a move (arcs come as several chords), in program coordinates: `a` and
/// `b` are `[r, z]` in mm, `r` the distance from the spindle axis, `z` from program zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seg {
    pub line: u32,
    pub station: u32,
    pub kind: SegKind,
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// The feed per revolution, when the move has one (a thread's lead is larger than any
    /// turning feed).
    pub per_rev: Option<f64>,
    /// mm per program unit (1, or 25.4 under G20), for writing evidence as the program does.
    pub scale: f64,
    /// X words are diameters.
    pub diameter: bool,
    /// A roughing or finishing cycle (G70–G73) made the move: its passes start wherever the
    /// cycle's start point is, often in the air.
    pub cycle: bool,
    /// The move follows a cycle's profile (the finished shape).
    pub profile: bool,
}

impl Seg {
    /// The X word that would reach radius `r` (mm), as the program writes it.
    pub fn x_word(&self, r: f64) -> f64 {
        let x = r / self.scale;
        if self.diameter {
            2.0 * x
        } else {
            x
        }
    }

    /// The Z word of `z` (mm from program zero), as the program writes it.
    pub fn z_word(&self, z: f64) -> f64 {
        z / self.scale
    }
}

/// Blocks a window of the program holds while it is read for its setup: a quarter of what the
/// check holds (the reading runs the program once and keeps none of its blocks, so its windows
/// are read again only where the program jumps back more than 8 of them).
const READ_WINDOW: usize = crate::gcode::WINDOW_BLOCKS / 4;

/// Moves the interpreter hands the reading at a time.
const READ_CHUNK: usize = 256;

/// Chords an arc is read as.
const ARC_CHORDS: usize = 8;

/// The program read once on its machine.
#[derive(Clone, Debug, Default)]
pub struct Reading<'s> {
    /// Its segments in order, packed ([`Segs`]).
    pub segs: Segs,
    /// The spindle turns during some move (an M3 or M4 took effect): without it the program
    /// is a dry run or a test of the control, and no bar is assumed.
    pub spindle_runs: bool,
    /// The source, line by line (lossy UTF-8), index 0 = line 1.
    pub lines: Lines<'s>,
}

/// A program's source as lines: the source itself and where every [`LINE_MARK`]th line starts
/// (4 bytes per 64 lines; a line is found from the mark before it and made text, lossy UTF-8,
/// when it is asked for).
#[derive(Clone, Debug, Default)]
pub struct Lines<'s> {
    src: &'s [u8],
    /// Where lines `0, LINE_MARK, 2·LINE_MARK, …` start in `src`; a line ends at the next `\n`
    /// (its `\r` before that left out) or at the end of the source.
    marks: Vec<u32>,
    len: usize,
}

/// Every how many lines [`Lines`] keeps where one starts.
const LINE_MARK: usize = 64;

impl<'s> Lines<'s> {
    /// The lines of `src` as [`str::lines`] cuts its lossy UTF-8 text. A source past 4 GiB
    /// keeps its first 4 GiB of lines (the programs read are far smaller).
    pub fn of(src: &'s [u8]) -> Lines<'s> {
        let mut marks = Vec::new();
        let mut len = 0usize;
        let mut at = 0usize;
        while at < src.len() {
            let Ok(a) = u32::try_from(at) else { break };
            if len % LINE_MARK == 0 {
                marks.push(a);
            }
            len += 1;
            at = next_line(src, at);
        }
        Lines { src, marks, len }
    }

    /// Line `i` (0-based).
    pub fn get(&self, i: usize) -> Option<Cow<'s, str>> {
        if i >= self.len {
            return None;
        }
        let mut at = *self.marks.get(i / LINE_MARK)? as usize;
        for _ in 0..i % LINE_MARK {
            at = next_line(self.src, at);
        }
        Some(self.text(at))
    }

    /// The line starting at byte `at`.
    fn text(&self, at: usize) -> Cow<'s, str> {
        let mut line = &self.src[at..next_line(self.src, at)];
        // `\n` or `\r\n` ends a line; a `\r` alone stays in it.
        if let Some(l) = line.strip_suffix(b"\n") {
            line = l.strip_suffix(b"\r").unwrap_or(l);
        }
        String::from_utf8_lossy(line)
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Every line in order (read on from each one's end, not found from a mark).
    pub fn iter(&self) -> impl Iterator<Item = Cow<'s, str>> + '_ {
        let mut at = 0usize;
        (0..self.len).map(move |_| {
            let line = self.text(at);
            at = next_line(self.src, at);
            line
        })
    }

    /// Bytes held beside the source.
    fn held_bytes(&self) -> usize {
        self.marks.capacity() * std::mem::size_of::<u32>()
    }
}

/// Where the line after the one starting at `at` starts (the end of the source after the last).
fn next_line(src: &[u8], at: usize) -> usize {
    match src[at..].iter().position(|&b| b == b'\n') {
        Some(k) => at + k + 1,
        None => src.len(),
    }
}

impl<'s> Reading<'s> {
    /// Interpret `src` on `machine` (as `check` reads it: the machine's dialect, or the one the
    /// program's signs choose) and keep its moves in program coordinates.
    pub fn of(src: &'s [u8], machine: &Machine) -> Reading<'s> {
        let lines = Lines::of(src);
        // The 1-based lines that hold a G70–G73 word, a bit each.
        let mut cycle_lines = LineSet::with_lines(lines.len());
        for (i, l) in lines.iter().enumerate() {
            let code = super::words::code_of(&l);
            if super::words::g_codes(&code)
                .iter()
                .any(|g| [700, 710, 720, 730].contains(g))
            {
                cycle_lines.insert(i as u32 + 1);
            }
        }
        let mut segs = Segs::new();
        // The moves are read as the interpreter makes them, and dropped: only the segments stay.
        let (machine, _) = crate::pipeline::resolve(src, machine);
        let machine = machine.as_ref();
        let prog = crate::pipeline::read_by(src, machine, READ_WINDOW);
        // In chunks of a few hundred moves: the reading keeps none of them, so a larger chunk
        // only holds more memory (4096 moves hold 1 MB).
        let run = crate::interp::interpret_streaming_by(&prog, src, machine, READ_CHUNK, |c| {
            for m in c.moves {
                read_move(m, &c.states[m.state as usize].frame, &cycle_lines, &mut segs);
            }
        });
        drop(prog);
        let spindle_runs = run.states.iter().any(|s| s.spindle.is_on());
        Reading {
            segs,
            spindle_runs,
            lines,
        }
    }

    /// Bytes the reading holds beside the source: its packed segments and its line starts (the
    /// memory a long program's setup reading costs; the source is the caller's).
    pub fn held_bytes(&self) -> usize {
        self.segs.packed_bytes() + self.lines.held_bytes()
    }

    /// The text of 1-based `line` ("" past the end).
    pub fn line(&self, line: u32) -> Cow<'s, str> {
        self.lines
            .get(line.saturating_sub(1) as usize)
            .unwrap_or(Cow::Borrowed(""))
    }
}

/// A set of 1-based line numbers of a program, a bit a line (a long program's per-line facts
/// in an eighth of the bytes a `Vec<bool>` takes).
#[derive(Clone, Debug, Default)]
pub struct LineSet(Vec<u64>);

impl LineSet {
    /// An empty set of the lines `1..=n`.
    pub fn with_lines(n: usize) -> LineSet {
        LineSet(vec![0; n / 64 + 1])
    }

    /// Adds `line` (a line past the set's lines is left out).
    pub fn insert(&mut self, line: u32) {
        if let Some(w) = self.0.get_mut(line as usize / 64) {
            *w |= 1 << (line % 64);
        }
    }

    pub fn contains(&self, line: u32) -> bool {
        self.0
            .get(line as usize / 64)
            .is_some_and(|w| w >> (line % 64) & 1 == 1)
    }
}

/// The segments of one move `m` in `frame`, appended to `segs`; `cycle_lines` holds the 1-based
/// lines with a G70–G73 word.
fn read_move(m: &crate::interp::Move, frame: &crate::interp::ProgFrame, cycle_lines: &LineSet, segs: &mut Segs) {
    // A tool working beyond the axis (negative X) is read as its mirror image: the bar
    // is the same on both sides.
    let side = if m.start.x + m.end.x < 2.0 * frame.origin.x - 1e-9 {
        -1.0
    } else {
        1.0
    };
    let to = |p: crate::geom::P2| [side * (p.x - frame.origin.x), p.y - frame.origin.y];
    let kind = match m.kind {
        MoveKind::Rapid => SegKind::Rapid,
        MoveKind::Line | MoveKind::Arc { .. } => SegKind::Feed,
        _ => return,
    };
    let cycle = cycle_lines.contains(m.line);
    let per_rev = match m.feed {
        Feed::PerRev(f) => Some(f),
        _ => None,
    };
    let mut push = |a: [f64; 2], b: [f64; 2]| {
        segs.push(Seg {
            line: m.line,
            station: m.station,
            kind,
            a,
            b,
            per_rev,
            scale: frame.scale,
            diameter: frame.diameter,
            cycle,
            profile: m.profile_line != 0,
        })
    };
    match m.kind {
        MoveKind::Arc { center, sweep } => {
            let (s, e) = (m.start - center, m.end - center);
            let (r0, r1) = (s.norm(), e.norm());
            let a0 = s.y.atan2(s.x);
            let at = |t: f64| {
                let r = r0 + t * (r1 - r0);
                let a = a0 + t * sweep;
                to(center + crate::geom::V2::new(r * a.cos(), r * a.sin()))
            };
            let mut prev = to(m.start);
            for k in 1..=ARC_CHORDS {
                let p = if k == ARC_CHORDS {
                    to(m.end)
                } else {
                    at(k as f64 / ARC_CHORDS as f64)
                };
                push(prev, p);
                prev = p;
            }
        }
        _ => push(to(m.start), to(m.end)),
    }
}
