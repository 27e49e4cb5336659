//! Modal groups: the group of each G code per dialect (and G-code system) and of each M code,
//! and the check that opens the order of execution: two codes of one group in a block are a
//! `program` finding and the block is not run; a code the dialect does not model is an
//! `unsupported` finding and the rest of the block runs.

use super::flow::Run;
use super::order::Cx;
use super::words::Words;
use crate::gcode::Block;
use crate::machine::{Dialect, GcodeSystem};

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

pub(crate) fn g_name(code: u16) -> String {
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
    /// Before step 1: the modal-group conflicts and the unknown codes of the block, and what the
    /// steps share ([`Cx`]). `None` when the block is refused (reported).
    pub(crate) fn check_modal_groups(&mut self, b: &Block, w: &mut Words) -> Option<Cx> {
        let d = self.machine.dialect;
        let fanuc = d == Dialect::Fanuc;
        let sys_b = fanuc && self.machine.gcode_system == GcodeSystem::B;
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
                                return None;
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
                return None;
            }
        }
        if w.nm > 4 {
            self.error(b, None, "more than four M codes in one block".into());
            return None;
        }
        if unknown {
            // Run what we know, but the unknown code's words are not checked for use.
            w.used = w.has;
        }
        Some(Cx {
            fanuc,
            sys_b,
            axis,
            unknown,
            motion_code,
            ends: false,
            axes_taken: false,
            plane_error_here: false,
        })
    }
}
