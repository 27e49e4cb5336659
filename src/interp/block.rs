//! Executing one block: words → modal changes and moves, in rs274ngc's order of execution.

use super::arc::{arc_from_center, arc_from_radius, ArcTolerance};
use super::flow::Run;
use super::state::Motion;
use super::{Feed, Move, MoveKind, ProgFrame, Spindle, SpindleDir, SpindleSpeed};
use crate::gcode::Block;
use crate::geom::{P2, V2};
use crate::machine::{DecimalPoint, Dialect};

/// Most G or M codes one block may hold.
const MAX_CODES: usize = 16;

/// The evaluated words of one block.
struct Words {
    val: [f64; 26],
    /// Bit per letter: present.
    has: u32,
    /// Bit per letter: written with a decimal point.
    point: u32,
    /// Byte offset of each letter's word, for columns.
    at: [u32; 26],
    /// G codes ×10 (G33.1 → 331) with their offsets.
    g: [(u16, u32); MAX_CODES],
    ng: usize,
    m: [(u16, u32); MAX_CODES],
    nm: usize,
    /// Bits of letters some code used.
    used: u32,
}

const fn bit(letter: u8) -> u32 {
    1 << (letter - b'A')
}

impl Words {
    fn get(&mut self, letter: u8) -> Option<f64> {
        let b = bit(letter);
        if self.has & b != 0 {
            self.used |= b;
            Some(self.val[(letter - b'A') as usize])
        } else {
            None
        }
    }

    fn peek(&self, letter: u8) -> bool {
        self.has & bit(letter) != 0
    }

    fn at(&self, letter: u8) -> Option<u32> {
        self.peek(letter).then(|| self.at[(letter - b'A') as usize])
    }

    fn has_g(&self, code: u16) -> Option<u32> {
        self.g[..self.ng].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    fn has_m(&self, code: u16) -> Option<u32> {
        self.m[..self.nm].iter().find(|(c, _)| *c == code).map(|&(_, a)| a)
    }

    fn axis_words(&self) -> bool {
        self.has & (bit(b'X') | bit(b'Z') | bit(b'U') | bit(b'W')) != 0
    }
}

/// Modal group of a G code (×10) in a dialect; `None` for codes the dialect does not know.
fn g_group(code: u16, d: Dialect, axis_words: bool) -> Option<u8> {
    let fanuc = d == Dialect::Fanuc;
    Some(match code {
        0 | 10 | 20 | 30 | 330 | 800 => 1,
        320 if fanuc => 1,
        331 | 760 | 700 | 710 | 720 | 711 | 712 | 721 | 722 | 730 | 740 | 750 => 1,
        810..=890 if code % 10 == 0 => 1,
        170 | 180 | 190 => 2,
        900 | 910 if !(fanuc && axis_words) => 3,
        900 | 920 | 940 if fanuc => 1, // Fanuc system A box cycles (with axis words)
        901 | 911 if !fanuc => 4,
        930 | 940 | 950 if !fanuc => 5,
        940 | 950 if fanuc => 5,
        980 | 990 if fanuc => 5,
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
        920 => 0,
        _ => return None,
    })
}

fn g_name(code: u16) -> String {
    if code % 10 == 0 {
        format!("G{}", code / 10)
    } else {
        format!("G{}.{}", code / 10, code % 10)
    }
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
    /// mm per program unit.
    pub(crate) fn scale(&self) -> f64 {
        if self.modal.inch {
            25.4
        } else {
            1.0
        }
    }

    pub(crate) fn tip(&self) -> V2 {
        self.machine.tool(self.station).map_or(V2::zeros(), |t| t.tip.coords)
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

    fn push_move(&mut self, b: &Block, kind: MoveKind, start: P2, end: P2, feed: Feed) {
        if matches!(kind, MoveKind::Rapid | MoveKind::Line | MoveKind::Arc { .. }) {
            self.reference = end - self.tip();
        }
        self.moves.push(Move {
            kind,
            line: b.line,
            n: b.n,
            start,
            end,
            tip: self.tip(),
            station: self.station,
            feed,
            spindle: self.spindle(),
            frame: self.frame(),
        });
    }

    /// Read the words of a block. `None` when a value could not be evaluated (already reported).
    fn read_words(&mut self, b: &Block) -> Option<Words> {
        let mut w = Words {
            val: [0.0; 26],
            has: 0,
            point: 0,
            at: [0; 26],
            g: [(0, 0); MAX_CODES],
            ng: 0,
            m: [(0, 0); MAX_CODES],
            nm: 0,
            used: 0,
        };
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let increment = fanuc && self.machine.decimal_point == DecimalPoint::Increment;
        let mut ok = true;
        for word in self.prog.words_of(b) {
            let v = match self.value(word.value) {
                Ok(v) => v,
                Err(m) => {
                    self.error(b, Some(word.span.start), m);
                    ok = false;
                    continue;
                }
            };
            let letter = word.letter;
            if !letter.is_ascii_uppercase() {
                ok = false;
                continue;
            }
            let at = word.span.start;
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
                    list[*n] = (code, at);
                    *n += 1;
                }
                _ => {
                    let bit = bit(letter);
                    if w.has & bit != 0 {
                        self.error(b, Some(at), format!("{} word given twice in one block", letter as char));
                        ok = false;
                        continue;
                    }
                    let mut v = v;
                    if increment && !word.has_point && matches!(letter, b'X' | b'Z' | b'U' | b'W' | b'I' | b'K' | b'R')
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
        ok.then_some(w)
    }

    /// Execute one block that is not an o-word.
    pub(crate) fn execute(&mut self, b: &Block) {
        let Some(mut w) = self.read_words(b) else {
            return;
        };
        // Parameter assignments: evaluate every right side first, then assign.
        let assigns = self.prog.assigns_of(b);
        if !assigns.is_empty() {
            let mut vals = Vec::with_capacity(assigns.len());
            for a in assigns {
                match self.eval(a.value) {
                    Ok(v) => vals.push((a.target, v, a.span.start)),
                    Err(m) => {
                        self.error(b, Some(a.span.start), m);
                        return;
                    }
                }
            }
            for (t, v, at) in vals {
                if let Err(m) = self.assign(t, v) {
                    self.error(b, Some(at), m);
                }
            }
        }
        if w.ng == 0 && w.nm == 0 && w.has == 0 {
            return;
        }
        let d = self.machine.dialect;
        let fanuc = d == Dialect::Fanuc;
        let axis = w.axis_words();

        // Modal group conflicts and unknown codes.
        let mut seen: [Option<u16>; 32] = [None; 32];
        let mut unknown = false;
        for &(code, at) in &w.g[..w.ng] {
            match g_group(code, d, axis) {
                Some(grp) => {
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
        if !fanuc {
            if w.has_g(70).is_some() {
                self.modal.diameter = true;
            }
            if w.has_g(80).is_some() {
                self.modal.diameter = false;
            }
        }
        if w.has_g(200).is_some() {
            self.modal.inch = true;
        }
        if w.has_g(210).is_some() {
            self.modal.inch = false;
        }
        if w.has_g(900).is_some() && !(fanuc && axis) {
            self.modal.incremental = false;
        }
        if w.has_g(910).is_some() && !(fanuc && axis) {
            self.modal.incremental = true;
        }
        if !fanuc {
            if w.has_g(901).is_some() {
                self.modal.arc_incremental = false;
            }
            if w.has_g(911).is_some() {
                self.modal.arc_incremental = true;
            }
        }

        // 2. Feed mode and feed.
        if fanuc {
            if w.has_g(980).is_some() || (w.has_g(940).is_some() && !axis) {
                self.modal.feed_per_rev = false;
            }
            if w.has_g(990).is_some() || (w.has_g(950).is_some() && !axis) {
                self.modal.feed_per_rev = true;
            }
        } else {
            if w.has_g(940).is_some() {
                self.modal.feed_per_rev = false;
            }
            if w.has_g(950).is_some() {
                self.modal.feed_per_rev = true;
            }
            if let Some(at) = w.has_g(930) {
                self.unsupported(b, Some(at), "G93 inverse-time feed is not modelled".into(), false);
            }
        }
        let thread_lead_f = fanuc && (w.has_g(320).is_some() || w.has_g(330).is_some());
        if !thread_lead_f {
            if let Some(f) = w.get(b'F') {
                if f < 0.0 {
                    self.error(b, w.at(b'F'), format!("negative feed F{f}"));
                } else {
                    self.modal.feed = f;
                }
            }
        }

        // 3. Spindle speed: S is a clamp with G50/G92 (Fanuc) and D with G96 (LinuxCNC).
        let clamp_block = fanuc && (w.has_g(500).is_some() || w.has_g(920).is_some()) && !axis;
        if let Some(s) = w.peek(b'S').then(|| w.get(b'S')).flatten() {
            if s < 0.0 {
                self.error(b, w.at(b'S'), format!("negative spindle speed S{s}"));
            } else if clamp_block {
                self.modal.css_clamp = Some(s);
            } else {
                self.modal.s = s;
            }
        }
        if w.has_g(960).is_some() {
            self.modal.spindle_css = true;
            if !fanuc {
                if let Some(dv) = w.get(b'D') {
                    self.modal.css_clamp = Some(dv);
                }
            }
        }
        if w.has_g(970).is_some() {
            self.modal.spindle_css = false;
        }

        // 4. Tool selection and change.
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

        // 5. Spindle and coolant.
        if w.has_m(3).is_some() {
            self.spindle_dir = SpindleDir::Cw;
        }
        if w.has_m(4).is_some() {
            self.spindle_dir = SpindleDir::Ccw;
        }
        if w.has_m(5).is_some() {
            self.spindle_dir = SpindleDir::Off;
        }
        for &(code, at) in &w.m[..w.nm] {
            match code {
                0..=9 | 30 | 48..=53 | 98 | 99 | 70..=73 => {}
                41..=44 if fanuc => {}       // gear range: no geometric effect
                60 | 62..=68 if !fanuc => {} // pallet/IO: no geometric effect
                21 | 22 if fanuc => self.unsupported(
                    b,
                    Some(at),
                    format!("M{code} moves the tailstock; latheguard keeps it where the machine file puts it"),
                    true,
                ),
                _ => self.unsupported(b, Some(at), format!("M{code} is not a code latheguard models"), false),
            }
        }
        if w.has_m(70).is_some() || w.has_m(73).is_some() {
            if w.has_m(73).is_some() {
                let m = self.modal.clone();
                match self.frames.last_mut() {
                    Some(f) => f.autorestore = Some(m),
                    None => self.saved_modal = Some(m),
                }
            } else {
                self.saved_modal = Some(self.modal.clone());
            }
        }
        if w.has_m(71).is_some() {
            self.saved_modal = None;
        }
        if let Some(at) = w.has_m(72) {
            match self.saved_modal.clone() {
                Some(m) => self.modal = m,
                None => self.error(b, Some(at), "M72 without a state saved by M70".into()),
            }
        }

        // 6. Dwell.
        if w.has_g(40).is_some() {
            self.dwell(b, &mut w, fanuc);
        }

        // 7. Plane, compensation, length offsets, coordinate systems, path mode.
        let plane_error_here = w.has_g(170).is_some() || w.has_g(190).is_some();
        if let Some(at) = w.has_g(170).or(w.has_g(190)) {
            self.error(b, Some(at), "only the XZ plane (G18) exists on a 2-axis lathe".into());
            self.modal.plane_xz = false;
        }
        if w.has_g(180).is_some() {
            self.modal.plane_xz = true;
        }
        for code in [410u16, 420, 411, 421] {
            if let Some(at) = w.has_g(code) {
                if code > 420 || code == 411 {
                    w.get(b'D');
                    w.get(b'L');
                }
                self.unsupported(
                    b,
                    Some(at),
                    format!(
                        "{}: tool nose radius compensation is not modelled; the uncompensated path is checked",
                        g_name(code)
                    ),
                    false,
                );
            }
        }
        if w.has_g(430).is_some() {
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
        for code in [550u16, 560, 570, 580, 590] {
            if let Some(at) = w.has_g(code) {
                self.unsupported(
                    b,
                    Some(at),
                    format!("{}: work offsets other than G54 are not in the machine file; program zero stays at setup.program_zero_z", g_name(code)),
                    true,
                );
            }
        }
        if w.has_g(640).is_some() {
            w.get(b'P');
            w.get(b'Q');
        }

        // 8. Non-modal coordinate codes and returns home.
        if !fanuc && w.has_g(980).is_some() | w.has_g(990).is_some() {
            // LinuxCNC canned-cycle return level: no effect without canned cycles.
        }
        let mut axes_used_by_nonmodal = false;
        if w.has_g(280).is_some() {
            self.home_return(b, &mut w);
            axes_used_by_nonmodal = true;
        }
        if let Some(at) = w.has_g(300).or(w.has_g(281)).or(w.has_g(301)).or(w.has_g(100)) {
            let code = [300u16, 281, 301, 100]
                .into_iter()
                .find(|&c| w.has_g(c).is_some())
                .unwrap_or(300);
            self.unsupported(b, Some(at), format!("{} is not modelled", g_name(code)), code == 300);
            w.used = w.has;
            axes_used_by_nonmodal = true;
        }
        if fanuc && w.has_g(500).is_some() && axis {
            self.set_origin(b, &mut w);
            axes_used_by_nonmodal = true;
        }
        if fanuc && w.has_g(920).is_some() && axis {
            self.unsupported(
                b,
                w.has_g(920),
                "G92 with axis words (a thread cycle or coordinate setting) is not modelled".into(),
                true,
            );
            w.used = w.has;
            axes_used_by_nonmodal = true;
        }
        if !fanuc {
            if w.has_g(920).is_some() {
                self.set_origin(b, &mut w);
                axes_used_by_nonmodal = true;
            }
            if w.has_g(921).is_some() || w.has_g(922).is_some() {
                self.shift = V2::zeros();
            }
            if w.has_g(520).is_some() {
                let x = w.get(b'X').map(|x| self.to_radius(x)).unwrap_or(0.0) * self.scale();
                let z = w.get(b'Z').unwrap_or(0.0) * self.scale();
                self.shift = V2::new(x, z);
                axes_used_by_nonmodal = true;
            }
        }

        // 9. Motion.
        let motion_code = w.g[..w.ng]
            .iter()
            .map(|&(c, a)| (c, a))
            .find(|&(c, _)| g_group(c, d, axis) == Some(1));
        if let Some((code, at)) = motion_code {
            match code {
                0 => self.modal.motion = Some(Motion::Rapid),
                10 => self.modal.motion = Some(Motion::Line),
                20 => self.modal.motion = Some(Motion::ArcCw),
                30 => self.modal.motion = Some(Motion::ArcCcw),
                320 | 330 => self.modal.motion = Some(Motion::Thread),
                800 => self.modal.motion = None,
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
        let g53 = w.has_g(530);
        if unknown && axis {
            // An unknown code may be the one that uses the axis words: do not guess a motion.
        } else if (axis || w.peek(b'Y')) && !axes_used_by_nonmodal {
            let before = self.findings.len();
            self.motion(b, &mut w, g53.is_some(), plane_error_here);
            if self.findings.len() > before {
                // The move was refused: its words are accounted for by that finding.
                w.used = w.has;
            }
        } else if let Some(at) = g53 {
            if !axis {
                self.error(b, Some(at), "G53 without axis words".into());
            }
        }

        // 10. Program flow.
        if w.has_m(98).is_some() {
            let p = w.get(b'P');
            let l = w.get(b'L');
            self.check_unused(b, &w);
            self.m98(b, p, l, w.has_m(98));
            return;
        }
        if w.has_m(99).is_some() {
            if w.peek(b'P') {
                self.unsupported(
                    b,
                    w.at(b'P'),
                    "M99 P (return to a sequence number) is not modelled".into(),
                    true,
                );
                w.get(b'P');
            }
            self.check_unused(b, &w);
            self.m99(b);
            return;
        }
        self.check_unused(b, &w);
        if w.has_m(2).is_some() || w.has_m(30).is_some() {
            self.stopped = true;
        }
    }

    fn check_unused(&mut self, b: &Block, w: &Words) {
        let unused = w.has & !w.used;
        if unused == 0 {
            return;
        }
        for i in 0..26u8 {
            if unused & (1 << i) != 0 {
                let letter = (b'A' + i) as char;
                let why = match letter {
                    'I' | 'K' => "an arc center needs G2 or G3",
                    'J' => "J is the Y offset of an arc; a lathe works in XZ (G18)",
                    'R' => "R is an arc radius or a cycle value",
                    'A' | 'B' | 'C' | 'V' => "this machine has no such axis",
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
    fn to_radius(&self, x: f64) -> f64 {
        if self.modal.diameter {
            x / 2.0
        } else {
            x
        }
    }

    fn tool_word(&mut self, b: &Block, t: f64, at: Option<u32>, fanuc: bool) {
        if t < 0.0 || t.fract() != 0.0 || t > 9999.0 {
            self.error(b, at, format!("T{t} is not a tool number"));
            return;
        }
        let t = t as u32;
        // Fanuc T0101 / T101: station in front of the last two digits (offset number); T1..T99:
        // the station itself. LinuxCNC: the tool number is the station.
        let station = if fanuc && t >= 100 { t / 100 } else { t };
        if station == 0 {
            // T0 / T0000: cancel the offset, keep the station (no index).
            return;
        }
        if station > self.machine.turret.stations || self.machine.tool(station).is_none() {
            self.error(
                b,
                at,
                format!(
                    "T{t}: the machine has no tool in station {station} (stations with tools: {})",
                    self.machine
                        .tools
                        .iter()
                        .map(|t| t.station.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            );
            return;
        }
        if fanuc {
            self.change_tool(b, station, at);
        } else {
            self.selected = Some(station);
        }
    }

    fn change_tool(&mut self, b: &Block, station: u32, _at: Option<u32>) {
        if station == self.station {
            return;
        }
        let from = self.station;
        self.station = station;
        // The reference point stays; the programmed point becomes the new tool's tip.
        let end = self.programmed();
        self.push_move(b, MoveKind::ToolChange { from, to: station }, end, end, Feed::Rapid);
    }

    fn dwell(&mut self, b: &Block, w: &mut Words, fanuc: bool) {
        let seconds = if fanuc {
            // P in milliseconds (seconds when written with a decimal point, as Haas reads it);
            // X or U in seconds.
            if let Some(p) = w.peek(b'P').then(|| w.get(b'P')).flatten() {
                if w.point & bit(b'P') != 0 {
                    p
                } else {
                    p / 1000.0
                }
            } else if let Some(x) = w.get(b'X').or_else(|| w.get(b'U')) {
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
    fn target(&mut self, b: &Block, w: &mut Words) -> Option<P2> {
        let cur = self.programmed();
        let origin = self.origin();
        let s = self.scale();
        let fanuc = self.machine.dialect == Dialect::Fanuc;
        let mut x = cur.x;
        let mut z = cur.y;
        let (xw, uw) = (w.peek(b'X'), fanuc && w.peek(b'U'));
        let (zw, ww) = (w.peek(b'Z'), fanuc && w.peek(b'W'));
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
        if let Some(y) = w.get(b'Y') {
            if y != 0.0 {
                self.error(b, w.at(b'Y'), format!("Y{y}: this lathe has no Y axis"));
                return None;
            }
            if !self.y_reported {
                self.y_reported = true;
                self.unsupported(
                    b,
                    w.at(b'Y'),
                    "Y0: a 2-axis lathe has no Y axis; Y0 words are ignored (reported once)".into(),
                    false,
                );
            }
        }
        if !(x.is_finite() && z.is_finite()) || x.abs() > 1e12 || z.abs() > 1e12 {
            self.error(b, None, "the target point is out of any range".into());
            return None;
        }
        Some(P2::new(x, z))
    }

    fn motion(&mut self, b: &Block, w: &mut Words, g53: bool, plane_error_here: bool) {
        let Some(mut end) = self.target(b, w) else {
            return;
        };
        let start = self.programmed();
        if g53 {
            // G53: machine coordinates, with machine zero at the home position (as on Fanuc and
            // Haas lathes): the turret reference point goes to home + the given values.
            let tip = self.tip();
            let home = self.machine.home;
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
        if !self.modal.plane_xz {
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
            Motion::Rapid => {
                self.push_move(b, MoveKind::Rapid, start, end, Feed::Rapid);
            }
            Motion::Line => {
                let Some(feed) = self.feed(b, w) else { return };
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
                let Some(feed) = self.feed(b, w) else { return };
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
                let tol = if self.modal.inch {
                    ArcTolerance::INCH
                } else {
                    ArcTolerance::MM
                };
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

    fn feed(&mut self, b: &Block, _w: &mut Words) -> Option<Feed> {
        if self.modal.feed <= 0.0 {
            self.error(b, None, "feed move without a feed rate (no F word in force)".into());
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
        let named_x = w.peek(b'X') || w.peek(b'U');
        let named_z = w.peek(b'Z') || w.peek(b'W');
        let start = self.programmed();
        let Some(mid) = self.target(b, w) else { return };
        if mid != start {
            self.push_move(b, MoveKind::Rapid, start, mid, Feed::Rapid);
        }
        let (hx, hz) = if named_x || named_z {
            (named_x, named_z)
        } else {
            (true, true)
        };
        let tip = self.tip();
        let mut r = mid - tip;
        if hx {
            r.x = self.machine.home.x;
        }
        if hz {
            r.y = self.machine.home.y;
        }
        let end = r + tip;
        if end != mid {
            self.push_move(b, MoveKind::Rapid, mid, end, Feed::Rapid);
        }
        self.reference = r;
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
    }
}
