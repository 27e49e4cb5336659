//! Executing one block: words → modal changes and moves, in rs274ngc's order of execution.

use super::arc::{arc_from_center, arc_from_radius, ArcTolerance};
use super::comp;
use super::flow::Run;
use super::state::Motion;
use super::{Feed, Move, MoveKind, MoveState, ProgFrame, Spindle, SpindleDir, SpindleSpeed, MAX_COORD};
use crate::finding::{Finding, Kind, Severity};
use crate::gcode::Block;
use crate::geom::{P2, V2};
use crate::machine::{DecimalPoint, Dialect, GcodeSystem};

/// Most G or M codes one block may hold.
const MAX_CODES: usize = 16;

/// `Run::selected` after a LinuxCNC T word for a tool number the job's `[tool_numbers]` lacks:
/// no station (past any turret's), so the M6 that follows leaves the moves unchecked.
pub(crate) const UNMAPPED: u32 = u32::MAX;

/// Every G code (×10) some dialect knows; its index is its bit in [`Words::gbits`].
pub(super) const KNOWN_G: [u16; 82] = [
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
/// code this file asks about is in the list).
#[inline(always)]
const fn gb(code: u16) -> u128 {
    if code < 1000 && G_INDEX[code as usize] != 255 {
        1u128 << G_INDEX[code as usize]
    } else {
        0
    }
}

/// G7/G8, G20/G21, G90/G91, G90.1/G91.1: the codes that change how values read.
const UNIT_AND_DISTANCE_CODES: u128 = gb(70) | gb(80) | gb(200) | gb(210) | gb(900) | gb(910) | gb(901) | gb(911);
/// G93/G94/G95, G98/G99: the feed modes.
const FEED_MODE_CODES: u128 = gb(930) | gb(940) | gb(950) | gb(980) | gb(990);

/// G96/G97: constant surface speed on and off.
const SPINDLE_CODES: u128 = gb(960) | gb(970);
/// Plane, nose-radius compensation, length offsets, work offsets, path mode.
const PLANE_COMP_OFFSET_CODES: u128 = gb(170)
    | gb(180)
    | gb(190)
    | gb(400)
    | gb(410)
    | gb(420)
    | gb(411)
    | gb(421)
    | gb(430)
    | gb(431)
    | gb(540)
    | gb(550)
    | gb(560)
    | gb(570)
    | gb(580)
    | gb(590)
    | gb(640);
/// Non-modal codes that use the axis words themselves: G28, G30, G10, G50, G52, G92.
const NONMODAL_CODES: u128 =
    gb(280) | gb(281) | gb(300) | gb(301) | gb(100) | gb(500) | gb(520) | gb(920) | gb(921) | gb(922);

/// The motion codes of a plain block (see [`Run::plain_block`]).
const PLAIN_MOTION_CODES: u128 = gb(0) | gb(10) | gb(20) | gb(30);
/// The letters of a plain block.
const PLAIN_LETTERS: u32 = bit(b'F') | bit(b'I') | bit(b'K') | bit(b'R') | bit(b'X') | bit(b'Z');

/// The evaluated words of one block.
pub(super) struct Words {
    val: [f64; 26],
    /// Bit per letter: present.
    has: u32,
    /// Bit per letter: written with a decimal point.
    point: u32,
    /// Byte offset of each letter's word, for columns.
    at: [u32; 26],
    /// G codes ×10 (G33.1 → 331) with their offsets, in block order.
    g: [(u16, u32); MAX_CODES],
    ng: usize,
    m: [(u16, u32); MAX_CODES],
    nm: usize,
    /// Bit per known G code present (see [`gb`]).
    gbits: u128,
    /// Bit per M code below 128 present.
    mbits: u128,
    /// Bits of letters some code used.
    used: u32,
}

/// A point within ±[`MAX_COORD`] mm on both axes (false for NaN).
#[inline]
pub(crate) fn in_range(p: P2) -> bool {
    p.x.abs() <= MAX_COORD && p.y.abs() <= MAX_COORD
}

const fn bit(letter: u8) -> u32 {
    1 << (letter - b'A')
}

impl Words {
    pub(super) fn new() -> Words {
        Words {
            val: [0.0; 26],
            has: 0,
            point: 0,
            at: [0; 26],
            g: [(0, 0); MAX_CODES],
            ng: 0,
            m: [(0, 0); MAX_CODES],
            nm: 0,
            gbits: 0,
            mbits: 0,
            used: 0,
        }
    }

    /// Empty again: only the masks and counts (a letter's value is read only when its bit is set).
    fn clear(&mut self) {
        self.has = 0;
        self.point = 0;
        self.used = 0;
        self.ng = 0;
        self.nm = 0;
        self.gbits = 0;
        self.mbits = 0;
    }

    pub(super) fn get(&mut self, letter: u8) -> Option<f64> {
        let b = bit(letter);
        if self.has & b != 0 {
            self.used |= b;
            Some(self.val[(letter - b'A') as usize])
        } else {
            None
        }
    }

    /// The letter's value, the word then gone from the block for every later reader (used).
    pub(super) fn take(&mut self, letter: u8) -> Option<f64> {
        let v = self.get(letter);
        self.has &= !bit(letter);
        v
    }

    /// Every word of the block counted as used (a block refused as a whole).
    pub(super) fn use_all(&mut self) {
        self.used = self.has;
    }

    /// The offset of the G code's word, also for codes outside [`KNOWN_G`] (G112, G113).
    pub(super) fn find_g(&self, code: u16) -> Option<u32> {
        self.g[..self.ng].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The letter's word was written with a decimal point.
    pub(super) fn has_point(&self, letter: u8) -> bool {
        self.point & bit(letter) != 0
    }

    pub(super) fn peek(&self, letter: u8) -> bool {
        self.has & bit(letter) != 0
    }

    pub(super) fn at(&self, letter: u8) -> Option<u32> {
        self.peek(letter).then(|| self.at[(letter - b'A') as usize])
    }

    /// The G code (×10) is in the block.
    #[inline(always)]
    fn g(&self, code: u16) -> bool {
        self.gbits & gb(code) != 0
    }

    /// Any of the G codes whose bits are in `mask`.
    #[inline(always)]
    fn any_g(&self, mask: u128) -> bool {
        self.gbits & mask != 0
    }

    /// The M code is in the block.
    #[inline(always)]
    fn m(&self, code: u16) -> bool {
        code < 128 && self.mbits & (1u128 << code) != 0
    }

    /// The offset of the G code's word, when it is in the block.
    pub(super) fn has_g(&self, code: u16) -> Option<u32> {
        if !self.g(code) {
            return None;
        }
        self.g[..self.ng].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The offset of the M code's word, when it is in the block.
    pub(super) fn has_m(&self, code: u16) -> Option<u32> {
        if !self.m(code) {
            return None;
        }
        self.m[..self.nm].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    /// The M codes of the block with their offsets, in block order.
    pub(super) fn m_codes(&self) -> &[(u16, u32)] {
        &self.m[..self.nm]
    }

    pub(super) fn axis_words(&self) -> bool {
        self.has & (bit(b'X') | bit(b'Z') | bit(b'U') | bit(b'W')) != 0
    }
}

/// The tip of the tool in a station (zero for an empty station).
pub(super) fn tip_of(machine: &crate::machine::Machine, station: u32) -> V2 {
    machine.tool(station).map_or(V2::zeros(), |t| t.tip.coords)
}

/// Modal group of a G code (×10) in a dialect; `None` for codes the dialect does not know.
fn g_group(code: u16, d: Dialect, sys_b: bool, axis_words: bool) -> Option<u8> {
    let fanuc = d == Dialect::Fanuc;
    // Fanuc G-code system A: G90/G92/G94 with axis words are the box cycles (system B: G77–G79).
    let box_a = fanuc && !sys_b;
    Some(match code {
        800 if fanuc => 9, // cancels the canned cycles; not in group 01 (`G0 G80 X… Z…` is legal)
        770 | 780 | 790 if fanuc && sys_b => 1,
        0 | 10 | 20 | 30 | 330 | 800 => 1,
        320 if fanuc => 1,
        331 | 760 | 700 | 710 | 720 | 711 | 712 | 721 | 722 | 730 | 740 | 750 => 1,
        810..=890 if code % 10 == 0 => 1,
        170 | 180 | 190 => 2,
        900 | 910 if !(box_a && axis_words) => 3,
        900 | 920 | 940 if box_a => 1, // Fanuc system A box cycles (with axis words)
        901 | 911 if !fanuc => 4,
        930 | 940 | 950 if !fanuc => 5,
        940 | 950 if fanuc => 5,
        980 | 990 if box_a => 5,
        980 | 990 => 10,
        200 | 210 => 6,
        400 | 410 | 420 | 411 | 421 => 7,
        430 | 431 | 490 if !fanuc => 8,
        540 | 550 | 560 | 570 | 580 | 590 => 12,
        610 | 611 | 640 => 13,
        960 | 970 => 14,
        70 | 80 if !fanuc => 15,
        40 | 280 | 281 | 300 | 301 | 530 | 100 => 0,
        500 if fanuc => 0,
        520 | 921 | 922 | 923 if !fanuc => 0,
        // Polar coordinate interpolation G12.1/G13.1 (G112/G113 in system A): Fanuc group 21.
        121 | 131 | 1120 | 1130 if fanuc => 21,
        // Cylindrical interpolation G7.1 (G107): group 21 too.
        71 | 1070 if fanuc => 21,
        920 => 0,
        _ => return None,
    })
}

fn g_name(code: u16) -> String {
    crate::machine::g_code_name(code)
}

/// The dialect runs the G code (×10) in some G-code system (the codes a machine file's
/// `[gcodes]` may name as what a builder code runs as).
pub(crate) fn models_g(code: u16, d: Dialect) -> bool {
    g_group(code, d, false, true).is_some() || g_group(code, d, true, true).is_some()
}

fn m_group(code: u16) -> u8 {
    match code {
        0 | 1 | 2 | 30 | 60 => 4,
        6 => 6,
        3..=5 => 7,
        7..=9 => 8,
        48..=53 => 9,
        98 | 99 => 10,
        70..=73 => 11,
        _ => 20 + (code % 200) as u8 % 200,
    }
}

impl Run<'_> {
    /// How far an arc's radii may differ at its ends, for the program's units.
    pub(crate) fn arc_tolerance(&self) -> ArcTolerance {
        if self.modal.inch {
            ArcTolerance::INCH
        } else {
            ArcTolerance::MM
        }
    }

    /// mm per program unit.
    pub(crate) fn scale(&self) -> f64 {
        if self.modal.inch {
            25.4
        } else {
            1.0
        }
    }

    /// The active tool's tip relative to the turret reference point.
    pub(crate) fn tip(&self) -> V2 {
        self.tip
    }

    pub(crate) fn origin(&self) -> P2 {
        self.base_origin + self.shift
    }

    pub(crate) fn frame(&self) -> ProgFrame {
        ProgFrame {
            origin: self.origin(),
            scale: self.scale(),
            diameter: self.modal.diameter,
        }
    }

    /// The programmed point (tool tip), spindle frame.
    pub(crate) fn programmed(&self) -> P2 {
        self.reference + self.tip()
    }

    /// The programmed point in program coordinates (X as the program writes it).
    pub(crate) fn program_position(&self) -> (f64, f64) {
        self.frame().to_program(self.programmed())
    }

    fn spindle(&self) -> Spindle {
        let max = self.machine.max_rpm;
        let clamp = self.modal.css_clamp.map_or(max, |c| c.min(max));
        let speed = if self.modal.spindle_css {
            // Surface speed: m/min, or ft/min in inch mode.
            let v = if self.modal.inch {
                self.modal.s * 0.3048
            } else {
                self.modal.s
            };
            SpindleSpeed::Css {
                m_per_min: v,
                max_rpm: clamp,
            }
        } else {
            SpindleSpeed::Rpm(self.modal.s.min(max))
        };
        Spindle {
            dir: self.spindle_dir,
            speed,
        }
    }

    pub(super) fn push_move(&mut self, b: &Block, kind: MoveKind, start: P2, end: P2, feed: Feed) {
        let center = match kind {
            MoveKind::Arc { center, .. } => center,
            _ => start,
        };
        if (!(in_range(start) && in_range(end) && in_range(center)) || self.out_of_range.is_some())
            && self.move_out_of_range(b, start, end, center)
        {
            return;
        }
        if matches!(kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }) {
            self.reference = end - self.tip();
        }
        let state = MoveState {
            spindle: self.spindle(),
            frame: self.frame(),
            tailstock_advanced: self.devices.tailstock_advanced,
            tool_unknown: self.devices.tool_unknown,
            sub_chuck_closed: self.devices.sub_chuck_closed,
        };
        if self.states.last() != Some(&state) {
            self.states.push(state);
        }
        let m = Move {
            kind,
            line: b.line,
            n: b.n(),
            profile_line: 0,
            start,
            end,
            tip: self.tip(),
            station: self.station,
            feed,
            state: (self.states.len() - 1) as u32,
        };
        if self.modal.spindle_css && feed != Feed::Rapid && self.spindle_dir != SpindleDir::Off {
            self.css_above_max_rpm(b, &m, &state.spindle);
        }
        if self.tm.is_none() {
            match self.comp.as_deref_mut() {
                Some(c) if c.engaged() => self.compensate(b, m),
                _ => self.moves.push(m),
            }
            return;
        }
        let first = self.moves.len();
        match self.comp.as_deref_mut() {
            Some(c) if c.engaged() => self.compensate(b, m),
            _ => self.moves.push(m),
        }
        let count = self.moves.len().saturating_sub(first);
        self.record_extra(kind, first, count);
    }

    /// Whether a move of block `b` is refused: it goes out of range (a word of a cycle, a
    /// computed point), or an earlier move of the block did. The first is reported at the block;
    /// no later move of the block is made (a cycle stops at its first such move).
    #[cold]
    fn move_out_of_range(&mut self, b: &Block, start: P2, end: P2, center: P2) -> bool {
        let key = b as *const Block as usize;
        if self.out_of_range == Some(key) {
            return true;
        }
        if in_range(start) && in_range(end) && in_range(center) {
            return false;
        }
        self.out_of_range = Some(key);
        self.error(
            b,
            None,
            format!(
                "a move of this block goes out of any range (a coordinate beyond ±{MAX_COORD:e} mm, or not a number): \
                 it is not made, nor the rest of the block's moves"
            ),
        );
        true
    }

    /// A move through nose-radius compensation (src/interp/comp.rs). An error of the control
    /// is a `program` finding at the move's line; compensation then stops and the move is made
    /// as programmed from where the tool is.
    #[cold]
    fn compensate(&mut self, b: &Block, m: Move) {
        let Some(c) = self.comp.as_deref_mut() else {
            self.moves.push(m);
            return;
        };
        if let Err(msg) = c.take(m, &mut self.moves) {
            c.abandon(&mut self.moves);
            let _ = c.take(m, &mut self.moves);
            self.error(
                b,
                None,
                format!("{msg}; nose radius compensation stops here and the rest is checked as programmed"),
            );
        }
    }

    /// Let the moves that nose-radius compensation still holds out (the program ended).
    pub(super) fn comp_flush(&mut self) {
        if let Some(c) = self.comp.as_deref_mut() {
            c.flush(&mut self.moves);
        }
    }

    /// G40: compensation off (the next move leaves the offset).
    fn comp_off(&mut self, b: &Block, at: u32) {
        if self.contour_comp_engaged() {
            self.contour_comp_off(b, at);
            return;
        }
        if self.comp.is_none() && self.cycles.profile_comp.is_none() {
            return;
        }
        self.comp_word(b, at, comp::Word::Off);
    }

    /// A G41/G42/G40 word to the compensation stage, or, while a Fanuc stock-removal cycle reads
    /// its profile, to the cycle (`cycles::ProfileComp`): roughing drops it, G70 has it replayed
    /// at its move (`run_cycle`).
    fn comp_word(&mut self, b: &Block, at: u32, word: comp::Word) {
        if let Some(words) = self.cycles.profile_comp.as_mut() {
            words.push(super::cycles::ProfileComp {
                at: self.moves.len(),
                word,
            });
            return;
        }
        let c = self.comp.get_or_insert_with(Default::default);
        if let Err(msg) = c.word(word, &mut self.moves) {
            self.error(b, Some(at), msg);
        }
    }

    /// G41/G42 (the radius and tip direction of the tool: the active one, or LinuxCNC's D
    /// tool), LinuxCNC G41.1/G42.1 (D the diameter, L the tip direction).
    fn comp_on(&mut self, b: &Block, w: &mut Words, code: u16, at: u32) {
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let side = if code == 410 || code == 411 {
            comp::Side::Left
        } else {
            comp::Side::Right
        };
        let (radius, dir) = if code == 411 || code == 421 {
            let d = w.get(b'D');
            let l = w.get(b'L');
            let Some(d) = d else {
                self.error(b, Some(at), format!("{} needs D, the tool diameter", g_name(code)));
                return;
            };
            let dir = match l {
                None => 0,
                Some(l) if l.fract() == 0.0 && (0.0..=9.0).contains(&l) => l as u8,
                Some(l) => {
                    self.error(
                        b,
                        w.at(b'L'),
                        format!("L{l}: the tip direction must be a whole number from 0 to 9"),
                    );
                    return;
                }
            };
            (d / 2.0 * self.scale(), dir)
        } else {
            let station = if !fanuc && w.peek(b'D') {
                let d = w.get(b'D').unwrap_or(0.0);
                if d.fract() != 0.0 || d < 0.0 {
                    self.error(
                        b,
                        w.at(b'D'),
                        format!("D{d}: {} takes a tool number in D", g_name(code)),
                    );
                    return;
                }
                if d > 0.0 && self.machine.tool(d as u32).is_none() {
                    self.error(
                        b,
                        w.at(b'D'),
                        format!("D{d}: the machine file has no tool {d} to take the nose radius from"),
                    );
                    return;
                }
                d as u32
            } else {
                self.station
            };
            let tool = self.machine.tool(station);
            (tool.map_or(0.0, |t| t.nose_radius), tool.map_or(0, |t| t.tip_direction))
        };
        if matches!(code, 410 | 420) {
            // In a contour mode the contour is offset in the mode's plane before the transform
            // (`contour_comp.rs`).
            let plane = if self.polar_on() {
                Some(super::contour_comp::Plane::Polar)
            } else {
                self.cylindrical().map(super::contour_comp::Plane::Cylinder)
            };
            if let Some(plane) = plane {
                self.contour_comp_on(b, code == 410, &g_name(code), at, plane);
                return;
            }
        }
        if !self.modal.plane_xz && dir != 0 && dir != 9 {
            self.error(
                b,
                Some(at),
                format!("{} with a lathe tip direction needs the XZ plane (G18)", g_name(code)),
            );
            return;
        }
        let style = if fanuc { comp::Style::Fanuc } else { comp::Style::Rs274 };
        let tip = comp::tip_vector(dir, radius.abs(), fanuc, self.machine.turret_side);
        // (Fanuc switches sides or tools without G40: a new start-up from where the tool is.)
        let word = comp::Word::On {
            side,
            radius,
            tip,
            style,
            unit: self.scale(),
        };
        self.comp_word(b, at, word);
    }

    /// A canned cycle with nose-radius compensation standing aside while it expands (its
    /// profile machinery reads and rewrites the moves it made). A G70 finishing pass is then
    /// compensated like any path; roughing and other cycles run on the programmed profile, and
    /// compensation starts again with the next move (docs/comp.md).
    fn run_cycle(&mut self, b: &Block, w: &mut Words, code: u16, at: u32) -> bool {
        if code == 700 && self.machine.dialect == Dialect::Fanuc {
            return self.fanuc_g70(b, w, at);
        }
        let Some(mut comp) = self.comp.take() else {
            return super::cycles::run(self, b, w, code, at);
        };
        if comp.is_on()
            && self.machine.dialect == Dialect::Linuxcnc
            && matches!(code, 710..=712 | 720..=722 | 810..=890)
        {
            // rs274ngc refuses G71/G72 and the drilling cycles while compensation is on.
            self.comp = Some(comp);
            self.error(
                b,
                Some(at),
                format!(
                    "{} cannot run with nose radius compensation on: cancel it with G40 first",
                    g_name(code)
                ),
            );
            self.modal.motion = None;
            return true;
        }
        // rs274 keeps the moves that wait for their corner across a G70: its first move settles it.
        let lcnc_g70 = code == 700 && self.machine.dialect == Dialect::Linuxcnc && comp.offsets();
        if !lcnc_g70 {
            comp.flush(&mut self.moves);
        }
        let m0 = self.moves.len();
        if lcnc_g70 {
            self.cycles.lcnc_g70_comp = Some(Default::default());
        }
        let ran = super::cycles::run(self, b, w, code, at);
        // Where rs274 read the profile, as an index into the cycle's moves.
        let read = self
            .cycles
            .lcnc_g70_comp
            .take()
            .and_then(|c| c.read)
            .and_then(|(i, p)| i.checked_sub(m0).map(|k| (k, p)));
        if !comp.is_on() && ran && m0 < self.moves.len() {
            // After G40 the cycle's first move starts where compensation left the tool.
            if let Some(p) = comp.take_resume() {
                let first = &mut self.moves[m0];
                if matches!(first.kind, MoveKind::Rapid | MoveKind::Line) {
                    first.start = p;
                }
            }
        }
        if comp.is_on() && ran && m0 < self.moves.len() {
            if code == 700 {
                self.replay_through_comp(b, &mut comp, m0, read, &[]);
            } else {
                if let Some(p) = comp.last_out() {
                    let first = &mut self.moves[m0];
                    if matches!(first.kind, MoveKind::Rapid | MoveKind::Line) {
                        first.start = p;
                    }
                }
                comp.restart();
            }
        }
        self.comp = Some(comp);
        ran
    }

    /// Fanuc G70: the profile blocks and the way back to the start point run through
    /// compensation as plain blocks would: what waits for its corner (a start-up block just
    /// before the G70) is settled by the cycle's first move, and the profile's own G41/G42/G40
    /// act before the moves of their blocks. Compensation is then as the profile left it.
    fn fanuc_g70(&mut self, b: &Block, w: &mut Words, at: u32) -> bool {
        let comp = self.comp.take();
        let m0 = self.moves.len();
        let ran = super::cycles::run(self, b, w, 700, at);
        let words = std::mem::take(&mut self.cycles.g70_comp);
        let mut comp = match comp {
            Some(c) => c,
            None if words.is_empty() => return ran,
            None => Box::default(),
        };
        self.replay_through_comp(b, &mut comp, m0, None, &words);
        self.comp = Some(comp);
        ran
    }

    /// Hand the moves a cycle made from `m0` on to compensation, with rs274's reading of the
    /// profile (`read`: the index of the move it comes before, and the profile's last point)
    /// and the profile's G41/G42/G40 (`words`, at absolute move indices) taken where they fall.
    /// An error of the control is one finding at the cycle's line; compensation stops there.
    fn replay_through_comp(
        &mut self,
        b: &Block,
        comp: &mut comp::Comp,
        m0: usize,
        read: Option<(usize, P2)>,
        words: &[super::cycles::ProfileComp],
    ) {
        let made: Vec<Move> = self.moves.drain(m0..).collect();
        let mut failed = None;
        let mut words = words.iter().peekable();
        let word = |comp: &mut comp::Comp, w: comp::Word, out: &mut Vec<Move>, failed: &mut Option<String>| {
            if failed.is_none() {
                *failed = comp.word(w, out).err();
            }
        };
        for (k, m) in made.into_iter().enumerate() {
            while let Some(pw) = words.next_if(|pw| pw.at <= m0 + k) {
                word(comp, pw.word, &mut self.moves, &mut failed);
            }
            if let Some((_, p)) = read.filter(|&(i, _)| i == k) {
                comp.profile_read(p);
            }
            if failed.is_none() {
                if let Err(msg) = comp.take(m, &mut self.moves) {
                    comp.abandon(&mut self.moves);
                    failed = Some(msg);
                    let _ = comp.take(m, &mut self.moves);
                }
            } else {
                let _ = comp.take(m, &mut self.moves);
            }
        }
        for pw in words {
            word(comp, pw.word, &mut self.moves, &mut failed);
        }
        if let Some(msg) = failed {
            self.error(
                b,
                None,
                format!("{msg}; nose radius compensation stops here and the rest is checked as programmed"),
            );
        }
    }

    /// A feed move under constant surface speed that would need more than the machine's
    /// `max_rpm` somewhere (near the axis) while the program set no lower limit (Fanuc G50 S,
    /// LinuxCNC G96 D): the control holds the spindle at `max_rpm`; a warning at the move's line.
    #[cold]
    fn css_above_max_rpm(&mut self, b: &Block, m: &Move, spindle: &Spindle) {
        let max = self.machine.max_rpm;
        if self.modal.css_clamp.is_some_and(|c| c <= max) {
            return;
        }
        let SpindleSpeed::Css { m_per_min, .. } = spindle.speed else {
            return;
        };
        if m_per_min.is_nan() || m_per_min <= 0.0 {
            return; // no speed at all: the timing reports that move
        }
        // The smallest radius on the move (an arc is sampled; a sign change means the axis).
        let mut r_min = f64::INFINITY;
        let mut prev_x = m.start.x;
        let pieces = if matches!(m.kind, MoveKind::Arc { .. }) { 32 } else { 1 };
        for k in 0..=pieces {
            let x = m.point_at(k as f64 / pieces as f64).x;
            r_min = if prev_x * x <= 0.0 { 0.0 } else { r_min.min(x.abs()) };
            prev_x = x;
        }
        let needed = m_per_min * 1000.0 / (2.0 * std::f64::consts::PI * r_min);
        if needed <= max {
            return;
        }
        let msg = format!(
            "constant surface speed S{} needs more than the machine's max_rpm ({} rpm) on this move: the spindle is held at {} rpm (set a lower limit with {})",
            self.modal.s,
            max,
            max,
            if self.machine.dialect == Dialect::Fanuc { "G50 S" } else { "G96 D" }
        );
        self.warn_once(b, None, msg);
    }

    /// A `program` warning, unless the same one was just reported for this line (a line in a
    /// loop would repeat it on every pass).
    pub(crate) fn warn_once(&mut self, b: &Block, col_offset: Option<u32>, msg: String) {
        let col = col_offset.map_or(0, |o| self.prog.lines.col_of(self.src, o));
        let repeat = self
            .findings
            .iter()
            .rev()
            .take(8)
            .any(|f| f.line == b.line && f.col == col && f.message == msg);
        // A warning does not refuse the move, so it is kept apart from `report` (and its
        // refusal count), under the same cap.
        if !repeat && self.findings.len() < crate::finding::MAX_FINDINGS {
            self.findings
                .push(Finding::at(Kind::Program, Severity::Warning, b.line, col, msg).with_n(b.n()));
        }
    }

    /// Read the words of a block. `None` when a value could not be evaluated (already reported).
    fn read_words(&mut self, b: &Block, w: &mut Words) -> bool {
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let increment = fanuc && self.machine.decimal_point == DecimalPoint::Increment;
        let mut ok = true;
        for word in self.prog.words_of(b) {
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

    /// Execute one block that is not an o-word.
    pub(crate) fn execute(&mut self, b: &Block) {
        let ops = self.ops_pending();
        if ops {
            self.operation_before(b);
        }
        if !self.machine.tool_changes.is_empty() {
            self.manual_tool_change(b);
        }
        if let Some(tm) = self.tm.as_deref_mut() {
            tm.pending = None;
        }
        // The group-01 motion in force as this block begins (set by any path, the plain-block
        // one too): what a Fanuc G80 gives back.
        if let Some(m) = self.modal.motion.filter(|m| !m.is_drilling()) {
            self.modal.group1 = Some(m);
        }
        // One word table serves every block (see `Words::clear`).
        let mut w = self.words.take().unwrap_or_else(|| Box::new(Words::new()));
        w.clear();
        let stops = self.stops_made();
        self.execute_words(b, &mut w);
        self.words = Some(w);
        if ops && self.stops_made() != stops {
            self.operation_after(b, stops);
        }
    }

    fn execute_words(&mut self, b: &Block, w: &mut Words) {
        if !self.read_words(b, w) {
            return;
        }
        // Parameter assignments: evaluate every right side first, then assign.
        let assigns = self.prog.assigns_of(b);
        if !assigns.is_empty() {
            let mut vals = Vec::with_capacity(assigns.len());
            for a in assigns {
                match self.eval_assign(a.value) {
                    Ok(v) => vals.push((a.target, v, a.span.start)),
                    Err(m) => {
                        self.eval_error(b, Some(a.span.start), m);
                        return;
                    }
                }
            }
            for (t, v, at) in vals {
                if let Err(m) = self.assign(t, v) {
                    self.eval_error(b, Some(at), m);
                    return;
                }
            }
        }
        if w.ng == 0 && w.nm == 0 && w.has == 0 {
            return;
        }
        let plain_codes = w.ng == 0 || (w.ng == 1 && w.any_g(PLAIN_MOTION_CODES));
        if self.plain_blocks_fast && plain_codes && w.nm == 0 && w.has & !PLAIN_LETTERS == 0 && assigns.is_empty() {
            self.plain_block(b, w);
            return;
        }
        let d = self.machine.dialect;
        let fanuc = d == Dialect::Fanuc;
        let sys_b = fanuc && self.machine.gcode_system == GcodeSystem::B;
        if fanuc && w.ng > 0 {
            // G7.1's C word is the cylinder's radius, not a move (`cylindrical.rs`).
            if let Some(at) = w.find_g(71).or(w.find_g(1070)) {
                self.cylindrical_code(b, w, at);
            }
        }
        let axis = w.axis_words() || self.extra_words(w);

        // Modal group conflicts and unknown codes.
        let mut seen: [Option<u16>; 32] = [None; 32];
        let mut unknown = false;
        // The motion code of the block (modal group 1), if any.
        let mut motion_code: Option<(u16, u32)> = None;
        for &(code, at) in &w.g[..w.ng] {
            match g_group(code, d, sys_b, axis) {
                Some(grp) => {
                    if grp == 1 && motion_code.is_none() {
                        motion_code = Some((code, at));
                    }
                    if grp != 0 {
                        if let Some(prev) = seen[grp as usize] {
                            if prev != code {
                                self.error(
                                    b,
                                    Some(at),
                                    format!(
                                        "{} and {} are in the same modal group ({grp})",
                                        g_name(prev),
                                        g_name(code)
                                    ),
                                );
                                return;
                            }
                        }
                        seen[grp as usize] = Some(code);
                    }
                }
                None => {
                    let dialect = if fanuc { "fanuc" } else { "linuxcnc" };
                    self.unsupported(
                        b,
                        Some(at),
                        format!("{} is not a {dialect} code latheguard models", g_name(code)),
                        true,
                    );
                    unknown = true;
                }
            }
        }
        for i in 0..w.nm {
            let (code, at) = w.m[i];
            let grp = m_group(code);
            if grp >= 20 {
                continue;
            }
            let clash = w.m[..i]
                .iter()
                .find(|&&(prev, _)| m_group(prev) == grp && prev != code && !(grp == 8 && prev != 9 && code != 9));
            if let Some(&(prev, _)) = clash {
                self.error(b, Some(at), format!("M{prev} and M{code} are in the same modal group"));
                return;
            }
        }
        if w.nm > 4 {
            self.error(b, None, "more than four M codes in one block".into());
            return;
        }
        if unknown {
            // Run what we know, but the unknown code's words are not checked for use.
            w.used = w.has;
        }

        // 1. Lathe diameter/radius mode and units come first: they govern how values read.
        if w.any_g(UNIT_AND_DISTANCE_CODES) {
            if !fanuc {
                if w.g(70) {
                    self.modal.diameter = true;
                }
                if w.g(80) {
                    self.modal.diameter = false;
                }
            }
            if w.g(200) {
                self.modal.inch = true;
            }
            if w.g(210) {
                self.modal.inch = false;
            }
            if w.g(900) && !(fanuc && !sys_b && axis) {
                self.modal.incremental = false;
            }
            if w.g(910) && !(fanuc && !sys_b && axis) {
                self.modal.incremental = true;
            }
            if !fanuc {
                if w.g(901) {
                    self.modal.arc_incremental = false;
                }
                if w.g(911) {
                    self.modal.arc_incremental = true;
                }
            }
        }

        // 2. Feed mode and feed.
        if w.any_g(FEED_MODE_CODES) {
            if fanuc {
                // System A: G98/G99 (G94/G95 without axis words); system B: G94/G95.
                if (w.g(980) && !sys_b) || (w.g(940) && (sys_b || !axis)) {
                    self.modal.feed_per_rev = false;
                }
                if (w.g(990) && !sys_b) || (w.g(950) && (sys_b || !axis)) {
                    self.modal.feed_per_rev = true;
                }
                if sys_b && (w.g(980) || w.g(990)) {
                    // System B: G98/G99 choose the drilling cycles' return level.
                    self.cycles.return_r = w.g(990);
                }
            } else {
                if w.g(940) {
                    self.modal.feed_per_rev = false;
                }
                if w.g(950) {
                    self.modal.feed_per_rev = true;
                }
                // G98/G99: where a LinuxCNC drilling cycle retracts to.
                if w.g(980) || w.g(990) {
                    self.cycles.lcnc.retract_to_old_z = w.g(980);
                }
                if let Some(at) = w.has_g(930) {
                    self.unsupported(b, Some(at), "G93 inverse-time feed is not modelled".into(), false);
                }
            }
        }
        let thread_lead_f = fanuc && (w.g(320) || w.g(330));
        if !thread_lead_f {
            self.feed_word(b, w);
        }

        // 3. Spindle speed: S is a clamp with G50/G92 (Fanuc) and D with G96 (LinuxCNC).
        if w.peek(b'S') || w.any_g(SPINDLE_CODES) {
            let clamp_block = fanuc && (w.g(500) || w.g(920)) && !axis;
            // `S2000 M13`: the S is the live tool's speed, not the main spindle's.
            let live_s = self.live_start_takes_s(w);
            if let Some(s) = w.peek(b'S').then(|| w.get(b'S')).flatten() {
                if !s.is_finite() {
                    self.error(b, w.at(b'S'), format!("spindle speed S{s} is not a finite number"));
                } else if s < 0.0 {
                    self.error(b, w.at(b'S'), format!("negative spindle speed S{s}"));
                } else if clamp_block {
                    self.modal.css_clamp = Some(s);
                } else if !live_s {
                    self.modal.s = s;
                }
            }
            if w.g(960) {
                self.modal.spindle_css = true;
                if !fanuc {
                    if let Some(dv) = w.get(b'D') {
                        self.modal.css_clamp = Some(dv);
                    }
                }
            }
            if w.g(970) {
                self.modal.spindle_css = false;
            }
            // A speed in rpm above the machine's limit: the control holds it at max_rpm.
            let max = self.machine.max_rpm;
            if w.peek(b'S') && !clamp_block && !live_s && !self.modal.spindle_css && self.modal.s > max {
                let msg = format!(
                    "spindle speed S{} is above the machine's max_rpm ({max} rpm): the spindle runs at {max} rpm",
                    self.modal.s
                );
                self.warn_once(b, w.at(b'S'), msg);
            }
        }

        // 4. Tool selection and change.
        if w.peek(b'T') || w.nm > 0 {
            if let Some(t) = w.get(b'T') {
                self.tool_word(b, t, w.at(b'T'), fanuc);
            }
            if let Some(at) = w.has_m(6) {
                if fanuc {
                    // Fanuc lathes index at the T word; M6 has nothing left to do.
                } else {
                    if let Some(t) = self.selected {
                        self.change_tool(b, t, Some(at));
                    }
                }
            }
        }

        // 5. Spindle, coolant, tailstock, chuck…: by the machine's M-code table (mcodes.rs).
        let mut ends = false;
        if w.nm > 0 {
            ends = self.m_codes(b, w);
            if w.m(70) || w.m(73) {
                if w.m(73) {
                    let m = self.modal.clone();
                    match self.frames.last_mut() {
                        Some(f) => f.autorestore = Some(m),
                        None => self.saved_modal = Some(m),
                    }
                } else {
                    self.saved_modal = Some(self.modal.clone());
                }
            }
            if w.m(71) {
                self.saved_modal = None;
            }
            if let Some(at) = w.has_m(72) {
                match self.saved_modal.clone() {
                    Some(m) => self.modal = m,
                    None => self.error(b, Some(at), "M72 without a state saved by M70".into()),
                }
            }
        }

        // 6. Dwell. On Fanuc lathes the X, U or P word of a G4 block is the dwell time and never
        // an axis word: such a block does not move (a Z or W there has no use and is reported).
        // LinuxCNC reads the time from P only; its axis words go to the modal motion, as in
        // rs274ngc.
        let mut dwell_took_axes = false;
        if w.g(40) {
            self.dwell(b, w, fanuc);
            dwell_took_axes = fanuc;
        }

        // 7. Plane, compensation, length offsets, coordinate systems, path mode.
        // LinuxCNC lathe programs select G17 to drill along Z (src/interp/cycles/lcnc_drill.rs).
        // A machine with a Y axis has all three planes.
        let has_y = self.has_y_axis();
        let g17_ok = !fanuc || has_y;
        let plane_error_here = !has_y && ((w.g(170) && !g17_ok) || w.g(190));
        if fanuc && w.ng > 0 {
            // Polar coordinate interpolation (`polar.rs`).
            if let Some(at) = w.find_g(121).or(w.find_g(1120)) {
                self.polar_start(b, at);
            }
            if let Some(at) = w.find_g(131).or(w.find_g(1130)) {
                self.polar_stop(b, at, w.has_g(400));
            }
        }
        if w.any_g(PLANE_COMP_OFFSET_CODES) {
            let refused = if has_y {
                None
            } else if g17_ok {
                w.has_g(190)
            } else {
                w.has_g(170).or(w.has_g(190))
            };
            if let Some(at) = refused {
                self.error(b, Some(at), "only the XZ plane (G18) exists on a 2-axis lathe".into());
                self.modal.plane_xz = false;
                self.modal.plane_xy = false;
            } else if w.g(170) && self.modal.plane_xz && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                // rs274ngc refuses a change of plane while compensation is on.
                self.error(
                    b,
                    w.has_g(170),
                    "G17 cannot change the plane with nose radius compensation on: cancel it with G40 first".into(),
                );
            } else if w.g(190)
                && has_y
                && !self.modal.plane_xy
                && self.modal.plane_xz
                && self.comp.as_ref().is_some_and(|c| c.is_on())
            {
                self.error(
                    b,
                    w.has_g(190),
                    "G19 cannot change the plane with nose radius compensation on: cancel it with G40 first".into(),
                );
            } else if w.g(170) {
                self.modal.plane_xz = false;
                self.modal.plane_xy = true;
            } else if w.g(190) {
                self.modal.plane_xz = false;
                self.modal.plane_xy = false;
            }
            if w.g(180) {
                self.modal.plane_xz = true;
                self.modal.plane_xy = false;
            }
            if let Some(at) = w.has_g(400) {
                self.comp_off(b, at);
            }
            for code in [410u16, 420, 411, 421] {
                if let Some(at) = w.has_g(code) {
                    self.comp_on(b, w, code, at);
                }
            }
            if w.g(430) {
                w.get(b'H');
            }
            if let Some(at) = w.has_g(431) {
                self.unsupported(
                    b,
                    Some(at),
                    "G43.1 dynamic tool length offset is not modelled".into(),
                    true,
                );
            }
            for code in [540u16, 550, 560, 570, 580, 590] {
                if let Some(at) = w.has_g(code) {
                    self.select_work_offset(b, code, at);
                }
            }
            if w.g(640) {
                w.get(b'P');
                w.get(b'Q');
            }
        }

        // 8. Non-modal coordinate codes and returns home.
        let mut axes_used_by_nonmodal = dwell_took_axes;
        if w.any_g(NONMODAL_CODES) {
            if w.g(280) {
                if !fanuc && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                    // rs274ngc refuses G28 while compensation is on.
                    self.error(
                        b,
                        w.has_g(280),
                        "G28 cannot run with nose radius compensation on: cancel it with G40 first".into(),
                    );
                    w.used = w.has;
                } else {
                    self.home_return(b, w);
                }
                axes_used_by_nonmodal = true;
            }
            if w.g(300) {
                if !fanuc && self.comp.as_ref().is_some_and(|c| c.is_on()) {
                    // rs274ngc refuses G30 while compensation is on, as G28.
                    self.error(
                        b,
                        w.has_g(300),
                        "G30 cannot run with nose radius compensation on: cancel it with G40 first".into(),
                    );
                    w.used = w.has;
                } else {
                    self.reference_return(b, w, fanuc);
                }
                axes_used_by_nonmodal = true;
            }
            if let Some(at) = w.has_g(281).or(w.has_g(301)).or(w.has_g(100)) {
                let code = [281u16, 301, 100]
                    .into_iter()
                    .find(|&c| w.has_g(c).is_some())
                    .unwrap_or(281);
                self.unsupported(b, Some(at), format!("{} is not modelled", g_name(code)), false);
                w.used = w.has;
                axes_used_by_nonmodal = true;
            }
            if fanuc && w.g(500) && axis {
                self.set_origin(b, w);
                axes_used_by_nonmodal = true;
            }
            if sys_b && w.g(920) && axis {
                // G-code system B: G92 is the coordinate setting (G50 of system A).
                self.set_origin(b, w);
                axes_used_by_nonmodal = true;
            }
            if !fanuc {
                if w.g(920) {
                    self.set_origin(b, w);
                    axes_used_by_nonmodal = true;
                }
                if w.g(921) || w.g(922) {
                    self.shift = V2::zeros();
                    self.extra_clear_shift();
                }
                if w.g(520) {
                    let x = w.get(b'X').map(|x| self.to_radius(x)).unwrap_or(0.0) * self.scale();
                    let z = w.get(b'Z').unwrap_or(0.0) * self.scale();
                    self.shift = V2::new(x, z);
                    self.extra_set_origin(w, true);
                    axes_used_by_nonmodal = true;
                }
            }
        }

        // 9. Motion.
        if let Some((code, at)) = motion_code {
            match code {
                0 => self.modal.motion = Some(Motion::Rapid),
                10 => self.modal.motion = Some(Motion::Line),
                20 => self.modal.motion = Some(Motion::ArcCw),
                30 => self.modal.motion = Some(Motion::ArcCcw),
                320 | 330 => self.modal.motion = Some(Motion::Thread),
                800 => self.modal.motion = None,
                // Canned cycles latheguard expands (src/interp/cycles): the cycle sets the modes.
                _ if self.run_cycle(b, w, code, at) => return,
                _ => {
                    let what = match code {
                        700..=760 => "lathe canned cycle",
                        810..=890 => "drilling cycle",
                        900 | 920 | 940 => "turning/threading/facing box cycle",
                        331 => "rigid tapping",
                        _ => "motion code",
                    };
                    self.unsupported(
                        b,
                        Some(at),
                        format!(
                            "{} ({what}) is not modelled yet: its moves are not checked",
                            g_name(code)
                        ),
                        true,
                    );
                    self.modal.motion = None;
                    return;
                }
            }
        }
        if fanuc && motion_code.is_none() && w.g(800) {
            // Fanuc G80 (group 9 here) cancels the drilling cycle only: the group-01 motion it
            // ran over (G0 or G1, usually) is in force again, so `X… Z…` after it moves.
            // A box cycle (G90/G92/G94) ends with no motion mode, as before.
            self.modal.motion = match self.modal.motion {
                Some(m) if m.is_drilling() => self.modal.group1.filter(|g| !matches!(g, Motion::Cycle(_))),
                Some(Motion::Cycle(_)) => None,
                m => m,
            };
        }
        let g53 = w.has_g(530);
        if unknown && axis {
            // An unknown code may be the one that uses the axis words: do not guess a motion.
        } else if (axis || w.peek(b'Y')) && !axes_used_by_nonmodal {
            // (`axis` counts the machine's extra-axis words.)
            let before = self.reports;
            self.motion(b, w, g53.is_some(), plane_error_here);
            if self.reports > before {
                // The move was refused: its words are accounted for by that finding.
                w.used = w.has;
            } else if self.cycles.profile_corners.is_some() && (w.peek(b'A') || w.peek(b'C')) {
                // A LinuxCNC G7x profile: A and C round or bevel the corner after this move.
                super::cycles::lcnc_rough::corner_words(self, b, w);
            }
        } else if let Some(at) = g53 {
            // A G53 block with no axis word: Fanuc runs it as a one-shot with nothing to move
            // (posts write it alone before a tool change); rs274ngc refuses it (G53 needs G0 or
            // G1, and a motion needs an axis word).
            if !axis && !fanuc {
                self.error(b, Some(at), "G53 without axis words".into());
            }
        }

        // 10. Program flow.
        if w.m(98) {
            let p = w.get(b'P');
            let l = w.get(b'L');
            self.check_unused(b, w);
            self.m98(b, p, l, w.has_m(98));
            return;
        }
        if w.m(99) {
            let p = w.peek(b'P').then(|| w.at(b'P'));
            let p = p.map(|at| (w.get(b'P').unwrap_or(0.0), at));
            self.check_unused(b, w);
            self.m99(b, p);
            return;
        }
        self.check_unused(b, w);
        if ends {
            self.stopped = true;
        }
    }

    /// The F word: the feed rate from here on.
    fn feed_word(&mut self, b: &Block, w: &mut Words) {
        if let Some(f) = w.get(b'F') {
            if f < 0.0 {
                self.error(b, w.at(b'F'), format!("negative feed F{f}"));
            } else {
                self.modal.feed = f;
            }
        }
    }

    /// A block of the commonest kind: at most one of G0–G3, and only X, Z, F, I, K, R words (no M
    /// code, no assignment). What [`Run::execute_words`] would do with it, without the steps that
    /// have nothing to do for it (tests run both ways and compare).
    fn plain_block(&mut self, b: &Block, w: &mut Words) {
        self.feed_word(b, w);
        if w.ng == 1 {
            self.modal.motion = Some(match w.g[0].0 {
                0 => Motion::Rapid,
                10 => Motion::Line,
                20 => Motion::ArcCw,
                _ => Motion::ArcCcw,
            });
        }
        if w.axis_words() {
            let before = self.reports;
            self.motion(b, w, false, false);
            if self.reports > before {
                w.used = w.has;
            }
        }
        self.check_unused(b, w);
    }

    #[inline]
    pub(super) fn check_unused(&mut self, b: &Block, w: &Words) {
        let unused = w.has & !w.used;
        if unused != 0 {
            self.report_unused(b, w, unused);
        }
    }

    #[cold]
    fn report_unused(&mut self, b: &Block, w: &Words, unused: u32) {
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

    /// X as a radius in program units.
    pub(crate) fn to_radius(&self, x: f64) -> f64 {
        if self.modal.diameter {
            x / 2.0
        } else {
            x
        }
    }

    fn tool_word(&mut self, b: &Block, t: f64, at: Option<u32>, fanuc: bool) {
        if t < 0.0 || t.fract() != 0.0 || t > 9999.0 {
            // The control changes to some tool here, which one latheguard cannot tell: the moves
            // until the next tool change are not checked (as after a T for an unknown station).
            self.error(
                b,
                at,
                format!("T{t} is not a tool number; the moves until the next tool change are not checked"),
            );
            self.devices.tool_unknown = true;
            return;
        }
        let t = t as u32;
        // Fanuc T0101 / T101: station in front of the last two digits (offset number); T1..T99:
        // the station itself. LinuxCNC: the tool number is the station, unless the job maps tool
        // numbers to stations (`[tool_numbers]`: the tool table's pockets).
        let station = if fanuc && t >= 100 {
            t / 100
        } else if !fanuc && t != 0 && !self.machine.tool_numbers.is_empty() {
            match self.machine.station_of_tool(t) {
                Some(s) => s,
                None => {
                    self.unmapped_tool(b, t, at);
                    return;
                }
            }
        } else {
            t
        };
        if station == 0 {
            // T0 / T0000: cancel the offset, keep the station (no index).
            return;
        }
        if station > self.machine.turret.stations || self.machine.tool(station).is_none() {
            self.unknown_tool(b, t, station, at, fanuc);
        }
        if fanuc {
            self.change_tool(b, station, at);
        } else {
            self.selected = Some(station);
        }
    }

    fn change_tool(&mut self, b: &Block, station: u32, _at: Option<u32>) {
        // A station the turret lacks cannot be indexed to; one the machine file has no tool for
        // can. Either way the moves that follow are not checked (`tool_unknown`, see
        // `unknown_tool`) until the next change to a described tool; the index to an empty
        // station is checked, the one out of it is not (the turret's place was unknown).
        let known = self.machine.tool(station).is_some();
        if station == self.station || station > self.machine.turret.stations {
            self.devices.tool_unknown = !known;
            return;
        }
        let from = self.station;
        self.station = station;
        self.tip = tip_of(self.machine, station);
        // The reference point stays; the programmed point becomes the new tool's tip.
        let end = self.programmed();
        self.push_move(b, MoveKind::ToolChange { from, to: station }, end, end, Feed::Rapid);
        self.devices.tool_unknown = !known;
    }

    /// A job's manual tool change at this block's line (`[[tool_changes]]`): the operator has put
    /// the tool of that station in, as a T word would switch to it, before the block runs.
    #[cold]
    fn manual_tool_change(&mut self, b: &Block) {
        let changes = &self.machine.tool_changes;
        if let Ok(i) = changes.binary_search_by_key(&b.line, |c| c.0) {
            let station = changes[i].1;
            self.change_tool(b, station, None);
        }
    }

    /// A LinuxCNC `T` for a tool number the job's `[tool_numbers]` map lacks: a `program`
    /// finding at the T word; the M6 that follows changes to a tool latheguard does not know
    /// (`UNMAPPED`), so the moves until the next tool change are not checked.
    #[cold]
    fn unmapped_tool(&mut self, b: &Block, t: u32, at: Option<u32>) {
        self.error(
            b,
            at,
            format!(
                "T{t}: tool {t} is in no station: add tool_numbers.T{t} = STATION to the job (or list it in its tool_table); the moves after M6 until the next tool change are not checked"
            ),
        );
        self.selected = Some(UNMAPPED);
    }

    /// A `T` for a station the turret lacks or the machine file has no tool in: a `program`
    /// finding at the T word. What follows is not checked as if another tool were there.
    #[cold]
    fn unknown_tool(&mut self, b: &Block, t: u32, station: u32, at: Option<u32>, fanuc: bool) {
        let stations = self.machine.turret.stations;
        let with: Vec<String> = self.machine.tools.iter().map(|t| t.station.to_string()).collect();
        let what = if station > stations {
            format!("the turret has no station {station} (it has 1 to {stations}; a control refuses it)")
        } else {
            format!(
                "the machine file has no tool in station {station} (stations with tools: {})",
                with.join(", ")
            )
        };
        let when = if fanuc { "" } else { " after M6" };
        self.error(
            b,
            at,
            format!(
                "T{t}: {what}; the moves{when} until the next tool change are not checked: where the turret is depends on that tool's offsets"
            ),
        );
    }

    fn dwell(&mut self, b: &Block, w: &mut Words, fanuc: bool) {
        let seconds = if fanuc {
            // P in milliseconds (seconds when written with a decimal point, as Haas reads it);
            // X or U in seconds. Each of them is the dwell here, never an axis word.
            let given = [b'P', b'X', b'U'].into_iter().filter(|&l| w.peek(l)).count();
            let p = w.peek(b'P').then(|| w.get(b'P')).flatten();
            let x = w.peek(b'X').then(|| w.get(b'X')).flatten();
            let u = w.peek(b'U').then(|| w.get(b'U')).flatten();
            if given > 1 {
                self.error(
                    b,
                    w.has_g(40),
                    "G4 takes one dwell time: P (ms), X or U (s), not several".into(),
                );
                return;
            }
            if let Some(p) = p {
                if w.point & bit(b'P') != 0 {
                    p
                } else {
                    p / 1000.0
                }
            } else if let Some(x) = x.or(u) {
                x
            } else {
                self.error(b, w.has_g(40), "G4 needs P (ms), X or U (s)".into());
                return;
            }
        } else {
            match w.get(b'P') {
                Some(p) => p,
                None => {
                    self.error(b, w.has_g(40), "G4 needs P, the dwell in seconds".into());
                    return;
                }
            }
        };
        if seconds < 0.0 {
            self.error(b, w.has_g(40), format!("negative dwell {seconds} s"));
            return;
        }
        let p = self.programmed();
        self.push_move(b, MoveKind::Dwell { seconds }, p, p, Feed::Rapid);
    }

    /// Target programmed point of the axis words (X/Z absolute or incremental, U/W incremental).
    pub(crate) fn target(&mut self, b: &Block, w: &mut Words) -> Option<P2> {
        let cur = self.programmed();
        let origin = self.origin();
        let s = self.scale();
        // U and W are incremental X and Z on Fanuc, and in a LinuxCNC G70-G72 profile (LinuxCNC's
        // own `g71-endless-loop_2` test: `W-5` then `U0.5`); elsewhere LinuxCNC's U and W are axes.
        let incremental_uw = self.machine.dialect == Dialect::Fanuc || self.cycles.profile_corners.is_some();
        let mut x = cur.x;
        let mut z = cur.y;
        let (xw, uw) = (w.peek(b'X'), incremental_uw && w.peek(b'U'));
        let (zw, ww) = (w.peek(b'Z'), incremental_uw && w.peek(b'W'));
        if xw && uw {
            self.error(b, w.at(b'U'), "X and U in one block".into());
            return None;
        }
        if zw && ww {
            self.error(b, w.at(b'W'), "Z and W in one block".into());
            return None;
        }
        if let Some(v) = w.get(b'X') {
            let r = self.to_radius(v) * s;
            x = if self.modal.incremental {
                cur.x + r
            } else {
                origin.x + r
            };
        }
        if uw {
            let v = w.get(b'U').unwrap_or(0.0);
            x = cur.x + self.to_radius(v) * s;
        }
        if let Some(v) = w.get(b'Z') {
            z = if self.modal.incremental {
                cur.y + v * s
            } else {
                origin.y + v * s
            };
        }
        if ww {
            z = cur.y + w.get(b'W').unwrap_or(0.0) * s;
        }
        if let Some(y) = (!self.has_y_axis()).then(|| w.get(b'Y')).flatten() {
            if y != 0.0 {
                self.error(b, w.at(b'Y'), format!("Y{y}: this lathe has no Y axis"));
                return None;
            }
            // rs274ngc reads Y on any machine and a lathe without a Y joint does not move for
            // it: Y0 is simply where it is. A Fanuc 2-axis control has no Y address at all.
            if !self.y_reported && self.machine.dialect != Dialect::Linuxcnc {
                self.y_reported = true;
                self.unsupported(
                    b,
                    w.at(b'Y'),
                    "Y0: a 2-axis lathe has no Y axis; Y0 words are ignored (reported once)".into(),
                    false,
                );
            }
        }
        if !in_range(P2::new(x, z)) {
            self.error(b, None, "the target point is out of any range".into());
            return None;
        }
        Some(P2::new(x, z))
    }

    fn motion(&mut self, b: &Block, w: &mut Words, g53: bool, plane_error_here: bool) {
        if self.polar_on() && !g53 {
            self.polar_motion(b, w);
            return;
        }
        if let Some(r) = self.cylindrical().filter(|_| !g53) {
            self.cylindrical_motion(b, w, r);
            return;
        }
        if let (Some(Motion::Cycle(code)), false) = (self.modal.motion, g53) {
            // A later block of a modal cycle: the cycle again with the new words.
            if super::cycles::repeat(self, b, w, code) {
                return;
            }
        }
        let Some(mut end) = self.target(b, w) else {
            return;
        };
        let Some(extra_end) = self.extra_end(b, w, g53) else {
            return;
        };
        let start = self.programmed();
        if g53 {
            // G53: machine coordinates: the turret reference point goes to machine zero
            // (`axes.machine_zero`, by default home as on Fanuc and Haas lathes) + the values.
            let tip = self.tip();
            let home = self.machine.machine_zero;
            let s = self.scale();
            let mut r = self.reference;
            if let Some(v) = w.peek(b'X').then(|| self.val(w, b'X')) {
                r.x = home.x + self.to_radius(v) * s;
            }
            if let Some(v) = w.peek(b'Z').then(|| self.val(w, b'Z')) {
                r.y = home.y + v * s;
            }
            end = r + tip;
        }
        let straight = !matches!(self.modal.motion, Some(Motion::ArcCw | Motion::ArcCcw));
        let has_y = self.has_y_axis();
        if let Some(e) = extra_end {
            self.set_pending(e, None);
        }
        if self.modal.plane_xy && !straight && !has_y {
            self.unsupported(
                b,
                None,
                "an arc in the XY plane (G17) leaves the lathe's XZ plane and is not modelled: select G18".into(),
                true,
            );
            w.used = w.has;
            return;
        }
        if !self.modal.plane_xz && !self.modal.plane_xy && !has_y {
            if !plane_error_here {
                self.error(b, None, "motion in the G17/G19 plane is not checked: select G18".into());
            } else {
                w.used = w.has;
            }
            return;
        }
        let motion = match self.modal.motion {
            Some(m) => m,
            None => {
                if !self.motion_reported {
                    self.motion_reported = true;
                    self.error(
                        b,
                        None,
                        "axis words but no motion mode in force (no G0/G1 given yet, or G80); assuming G1 from here"
                            .into(),
                    );
                }
                self.modal.motion = Some(Motion::Line);
                Motion::Line
            }
        };
        let motion = if g53 && motion != Motion::Line {
            Motion::Rapid
        } else {
            motion
        };
        match motion {
            // A cycle its family declined (reported there), or a G53 block under a cycle: no move.
            Motion::Cycle(_) => {}
            Motion::Rapid => {
                self.push_move(b, MoveKind::Rapid, start, end, Feed::Rapid);
            }
            Motion::Line => {
                let Some(feed) = self.feed(b) else { return };
                self.push_move(b, MoveKind::Line, start, end, feed);
            }
            Motion::Thread => {
                let fanuc = self.machine.dialect == Dialect::Fanuc;
                let lead = if fanuc {
                    w.get(b'F').or(w.get(b'E'))
                } else {
                    w.get(b'K')
                };
                let Some(lead) = lead.filter(|l| *l > 0.0) else {
                    self.error(
                        b,
                        None,
                        format!("threading move needs its lead ({} word)", if fanuc { "F" } else { "K" }),
                    );
                    return;
                };
                self.push_move(b, MoveKind::Line, start, end, Feed::PerRev(lead * self.scale()));
            }
            Motion::ArcCw | Motion::ArcCcw => {
                // G2 turns from +X toward +Z: counter-clockwise in (x right, z up).
                let ccw = motion == Motion::ArcCw;
                let Some(feed) = self.feed(b) else { return };
                let turns = match w.get(b'P') {
                    Some(p) if p >= 1.0 && p.fract() == 0.0 && p <= 1000.0 => p as u32,
                    Some(p) => {
                        self.error(
                            b,
                            w.at(b'P'),
                            format!("P{p}: the number of turns must be a whole number from 1 to 1000"),
                        );
                        return;
                    }
                    None => 1,
                };
                if has_y && !self.modal.plane_xz {
                    let e = extra_end.unwrap_or([0.0; 4]);
                    self.plane_arc(b, w, motion, start, end, e, feed, turns);
                    return;
                }
                let tol = self.arc_tolerance();
                let s = self.scale();
                let has_r = w.peek(b'R');
                let has_ik = w.peek(b'I') || w.peek(b'K');
                if has_r && has_ik {
                    self.error(b, w.at(b'R'), "an arc takes R or I/K, not both".into());
                    return;
                }
                if w.peek(b'J') {
                    return; // reported as unused
                }
                let result = if has_r {
                    let r = w.get(b'R').unwrap_or(0.0) * s;
                    arc_from_radius(start, end, r, ccw, turns, tol)
                } else if has_ik {
                    let i = w.get(b'I').unwrap_or(0.0) * s;
                    let k = w.get(b'K').unwrap_or(0.0) * s;
                    let center = if self.modal.arc_incremental {
                        P2::new(start.x + i, start.y + k)
                    } else {
                        let o = self.origin();
                        P2::new(o.x + i, o.y + k)
                    };
                    arc_from_center(start, end, center, ccw, turns, tol).map(|sw| (center, sw))
                } else {
                    self.error(b, None, "an arc needs R or I/K".into());
                    return;
                };
                match result {
                    Ok((center, sweep)) => self.push_move(b, MoveKind::Arc { center, sweep }, start, end, feed),
                    Err(e) => self.error(b, None, e.to_string()),
                }
            }
        }
    }

    fn val(&self, w: &mut Words, letter: u8) -> f64 {
        w.get(letter).unwrap_or(0.0)
    }

    /// The feed of a cutting move now, or a finding at the block's line.
    pub(super) fn feed(&mut self, b: &Block) -> Option<Feed> {
        self.feed_or(b, || "feed move without a feed rate (no F word in force)".into())
    }

    /// [`Self::feed`] with the finding's message given by `missing`.
    pub(crate) fn feed_or(&mut self, b: &Block, missing: impl FnOnce() -> String) -> Option<Feed> {
        if self.modal.feed <= 0.0 {
            self.error(b, None, missing());
            return None;
        }
        let f = self.modal.feed * self.scale();
        Some(if self.modal.feed_per_rev {
            Feed::PerRev(f)
        } else {
            Feed::PerMinute(f)
        })
    }

    /// G28: through the intermediate point given by the axis words to home, for the axes named
    /// (all axes when none is named).
    fn home_return(&mut self, b: &Block, w: &mut Words) {
        let home = self.machine.home;
        self.return_through(b, w, home);
    }

    /// G30: as G28, to another point. Fanuc: the 2nd, 3rd or 4th reference point (`P2` when no P
    /// word; `axes.reference_points`, home for a point the machine file does not give).
    /// LinuxCNC: the point in parameters #5181 (X) and #5183 (Z), machine coordinates (as G53
    /// reads them: from `axes.machine_zero`), X a radius, in the machine's native units, as
    /// rs274ngc keeps them.
    fn reference_return(&mut self, b: &Block, w: &mut Words, fanuc: bool) {
        let target = if fanuc {
            let at = w.at(b'P');
            let p = w.get(b'P').unwrap_or(2.0);
            let n = if p.fract() == 0.0 && (2.0..=4.0).contains(&p) {
                p as usize
            } else {
                self.error(
                    b,
                    at,
                    format!("G30 P{p}: the reference point is P2, P3 or P4 (the 2nd to 4th)"),
                );
                w.used = w.has;
                return;
            };
            self.machine
                .reference_points
                .get(n - 2)
                .copied()
                .unwrap_or(self.machine.home)
        } else {
            // rs274ngc keeps the point in the machine's native units: inch on a machine that
            // starts programs in inch (rs274 without an INI file is one), mm otherwise.
            let unit = if self.machine.inch { 25.4 } else { 1.0 };
            let param = |n: usize| self.params.numbered.get(n).copied().unwrap_or(0.0) * unit;
            let zero = self.machine.machine_zero;
            crate::geom::p2(zero.x + param(5181), zero.y + param(5183))
        };
        self.return_through(b, w, target);
    }

    /// G28/G30: a rapid to the intermediate point given by the axis words, then a rapid that
    /// takes the turret reference point to `target` on the axes named (all axes when none is
    /// named).
    fn return_through(&mut self, b: &Block, w: &mut Words, target: P2) {
        let named_x = w.peek(b'X') || w.peek(b'U');
        let named_z = w.peek(b'Z') || w.peek(b'W');
        let named_extra = self.extra_named(w);
        let any_extra = named_extra.iter().any(|&n| n);
        let start = self.programmed();
        let Some(mid) = self.target(b, w) else { return };
        let extra_start = self.tm.as_deref().map(|t| t.pos);
        let Some(extra_mid) = self.extra_end(b, w, false) else {
            return;
        };
        if mid != start || extra_mid != extra_start {
            if let Some(e) = extra_mid {
                self.set_pending(e, None);
            }
            self.push_move(b, MoveKind::Rapid, start, mid, Feed::Rapid);
        }
        let (hx, hz) = if named_x || named_z || any_extra {
            (named_x, named_z)
        } else {
            (true, true)
        };
        // The extra axes named (all of them when no axis is named) go to their home: the axis
        // value they start the program at.
        let extra_end = extra_mid.map(|mut e| {
            let all = !(named_x || named_z || any_extra);
            if let Some(kin) = self.machine.kinematics.as_deref() {
                for k in 0..4 {
                    if all || named_extra[k] {
                        if let Some(a) = kin.axis_by_letter(super::EXTRA_LETTERS[k]) {
                            e[k] = kin.axes[a].zero;
                        }
                    }
                }
            }
            e
        });
        let tip = self.tip();
        let mut r = mid - tip;
        if hx {
            r.x = target.x;
        }
        if hz {
            r.y = target.y;
        }
        let end = r + tip;
        if end != mid || extra_end != extra_mid {
            if let Some(e) = extra_end {
                self.set_pending(e, None);
            }
            self.push_move(b, MoveKind::Rapid, mid, end, Feed::Rapid);
        }
        self.reference = r;
    }

    /// G54–G59: the work offset `code` names becomes program zero for what follows (the
    /// machine's or the job's `work_offsets`; G54 without one is `program_zero_z`). A G50/G92
    /// or G52 shift stays in force over it, as both controls shift every work coordinate system
    /// by it. An offset that is not given leaves program zero where it is, as an `unsupported`
    /// error that names the key to write.
    fn select_work_offset(&mut self, b: &Block, code: u16, at: u32) {
        let n = usize::from((code - 540) / 10);
        let zero = match n {
            0 => self.g54_zero().or(self.machine.work_zero(0)),
            _ => self.machine.work_zero(n),
        };
        match zero {
            Some(p) => {
                self.base_origin = p;
                self.coord_system = n as u8;
            }
            None => {
                let name = g_name(code);
                self.unsupported(
                    b,
                    Some(at),
                    format!(
                        "{name}: the work offset {name} is not given, so program zero stays where it was: write it in the job as `[work_offsets] {name} = {{ z = … }}` (the control's work offset page: Z from machine zero, mm) or in the machine file's [setup.work_offsets]"
                    ),
                    true,
                );
            }
        }
    }

    /// Fanuc G50 X Z / LinuxCNC G92 X Z: the current point gets the given program coordinates.
    fn set_origin(&mut self, b: &Block, w: &mut Words) {
        let cur = self.programmed();
        let s = self.scale();
        let mut origin = self.origin();
        if let Some(x) = w.get(b'X') {
            origin.x = cur.x - self.to_radius(x) * s;
        }
        if let Some(z) = w.get(b'Z') {
            origin.y = cur.y - z * s;
        }
        let _ = b;
        self.shift = origin - self.base_origin;
        self.extra_set_origin(w, false);
    }
}
