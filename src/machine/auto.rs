//! `machine.dialect = "auto"`: which dialect a program is written in, read from its own signs.
//!
//! Each line is read once, outside comments (`( … )` and `;` to the end of the line), without
//! regard to case. A line counts for a dialect when it holds one of its signs:
//!
//! | dialect | signs |
//! |---|---|
//! | LinuxCNC | an o-word with a name (`o<name>`) or with a flow keyword (`o100 sub`, `o1 if`, `o2 while`, `call`, `endsub`, `return`, …); a named parameter (`#<name>`); `G7` or `G8` (diameter or radius mode) |
//! | Fanuc | a program number (`O1234` opening a line, no keyword after it); a four-digit T word (`T0101`: station and offset); `G50` with an `S` word (spindle clamp); `M98`/`M99`; macro B flow (`GOTO`, `WHILE [`, `DO1`, `END1`) |
//!
//! A `%` line counts for Fanuc too, but as one sign against a line's three: rs274ngc files may
//! also be wrapped in `%`. The dialect with the larger score (3 per line with a strong sign, 1 per
//! `%` line) is chosen; a tie, including a program with no sign at all, goes to Fanuc (the machine
//! file's other settings — diameter mode, decimal point, G-code system — are Fanuc's unless the
//! program shows otherwise). The reason names the first sign of the chosen dialect and its line.

use super::Dialect;

/// The dialect of a program and why: `("o-word `o<x> sub` at line 3")`.
pub fn detect(src: &[u8]) -> (Dialect, String) {
    let text = String::from_utf8_lossy(src);
    let (mut lc, mut fa) = (0u64, 0u64);
    let (mut first_lc, mut first_fa): (Option<String>, Option<String>) = (None, None);
    let mut first_percent: Option<String> = None;
    for (i, raw) in text.lines().enumerate() {
        let line = strip_comments(raw).to_ascii_lowercase();
        let line = line.trim();
        if line.is_empty() {
            continue;
        }
        let n = i + 1;
        if let Some(sign) = linuxcnc_sign(line) {
            lc += 3;
            first_lc.get_or_insert_with(|| format!("{sign} at line {n}"));
        }
        if let Some(sign) = fanuc_sign(line) {
            fa += 3;
            first_fa.get_or_insert_with(|| format!("{sign} at line {n}"));
        } else if line.starts_with('%') {
            fa += 1;
            first_percent.get_or_insert_with(|| format!("`%` at line {n}"));
        }
    }
    let first_fa = first_fa.or(first_percent);
    if lc > fa {
        (Dialect::Linuxcnc, format!("auto: {}", first_lc.unwrap_or_default()))
    } else if fa > 0 && fa >= lc {
        let why = if fa == lc {
            format!(
                "auto: as many signs of each, a tie goes to fanuc ({})",
                first_fa.unwrap_or_default()
            )
        } else {
            format!("auto: {}", first_fa.unwrap_or_default())
        };
        (Dialect::Fanuc, why)
    } else {
        (
            Dialect::Fanuc,
            "auto: no sign of either dialect, fanuc by default".to_string(),
        )
    }
}

fn strip_comments(line: &str) -> String {
    let mut out = String::with_capacity(line.len());
    let mut depth = 0u32;
    for c in line.chars() {
        match c {
            '(' => depth += 1,
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => break,
            c if depth == 0 => out.push(c),
            _ => {}
        }
    }
    out
}

const OWORD_KEYWORDS: [&str; 14] = [
    "sub",
    "endsub",
    "call",
    "if",
    "elseif",
    "else",
    "endif",
    "while",
    "endwhile",
    "do",
    "repeat",
    "endrepeat",
    "return",
    "break",
];

/// After an optional N number.
fn body(line: &str) -> &str {
    let l = line.trim_start();
    if let Some(rest) = l.strip_prefix('n') {
        let digits = rest.trim_start_matches(|c: char| c.is_ascii_digit() || c == ' ');
        if digits.len() < rest.len() {
            return digits;
        }
    }
    l
}

fn linuxcnc_sign(line: &str) -> Option<String> {
    let b = body(line);
    if let Some(rest) = b.strip_prefix('o') {
        if rest.trim_start().starts_with('<') {
            return Some("a named o-word".into());
        }
        let after = rest.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start();
        if after.len() < rest.len() {
            let word: String = after.chars().take_while(|c| c.is_ascii_alphabetic()).collect();
            if OWORD_KEYWORDS.contains(&word.as_str()) || word == "continue" {
                return Some(format!("an o-word `{word}`"));
            }
        }
    }
    if line.contains("#<") {
        return Some("a named parameter `#<…>`".into());
    }
    for (g, what) in [(7, "G7 (diameter mode)"), (8, "G8 (radius mode)")] {
        if g_words(line).any(|v| v == g) {
            return Some(what.into());
        }
    }
    None
}

fn fanuc_sign(line: &str) -> Option<String> {
    let b = body(line);
    if let Some(rest) = b.strip_prefix('o') {
        let after = rest.trim_start_matches(|c: char| c.is_ascii_digit());
        let word: String = after
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_alphabetic())
            .collect();
        if after.len() < rest.len() && !OWORD_KEYWORDS.contains(&word.as_str()) && word != "continue" {
            return Some("a program number `O…`".into());
        }
    }
    let bytes = line.as_bytes();
    for (i, &c) in bytes.iter().enumerate() {
        if c == b't' && (i == 0 || !bytes[i - 1].is_ascii_alphabetic()) {
            let digits = bytes[i + 1..].iter().take_while(|d| d.is_ascii_digit()).count();
            let next = bytes.get(i + 1 + digits);
            if digits == 4 && !next.is_some_and(|n| *n == b'.') {
                return Some("a four-digit T word (station and offset)".into());
            }
        }
    }
    if g_words(line).any(|v| v == 50) && line.contains('s') {
        return Some("G50 with an S word (spindle clamp)".into());
    }
    for (m, what) in [(98, "M98"), (99, "M99")] {
        if m_words(line).any(|v| v == m) {
            return Some(what.into());
        }
    }
    if line.contains("goto") || line.contains("while [") || line.contains("while[") {
        return Some("macro B flow (GOTO/WHILE)".into());
    }
    None
}

/// Whole-number values of the words with this letter (`g7` → 7; `g7.1` and `g70` are not 7).
fn words(line: &str, letter: u8) -> impl Iterator<Item = u32> + '_ {
    let b = line.as_bytes();
    (0..b.len()).filter_map(move |i| {
        if b[i] != letter || (i > 0 && b[i - 1].is_ascii_alphabetic()) {
            return None;
        }
        let rest = &b[i + 1..];
        let rest = &rest[rest.iter().take_while(|c| **c == b' ').count()..];
        let n = rest.iter().take_while(|c| c.is_ascii_digit()).count();
        if n == 0
            || n > 4
            || rest.get(n) == Some(&b'.') && rest.get(n + 1).is_some_and(|c| c.is_ascii_digit() && *c != b'0')
        {
            return None;
        }
        std::str::from_utf8(&rest[..n]).ok()?.parse().ok()
    })
}

fn g_words(line: &str) -> impl Iterator<Item = u32> + '_ {
    words(line, b'g')
}

fn m_words(line: &str) -> impl Iterator<Item = u32> + '_ {
    words(line, b'm')
}

#[cfg(test)]
mod tests {
    use super::*;

    fn d(s: &str) -> Dialect {
        detect(s.as_bytes()).0
    }

    #[test]
    fn linuxcnc_signs_choose_linuxcnc() {
        assert_eq!(d("o<turn> sub\nG0 X1\no<turn> endsub\nM2\n"), Dialect::Linuxcnc);
        assert_eq!(d("#<depth> = 2\nG1 X#<depth>\n"), Dialect::Linuxcnc);
        assert_eq!(d("G7 G18 G21\nG0 X10 Z2\nM2\n"), Dialect::Linuxcnc);
        assert_eq!(d("o100 while [#1 LT 3]\no100 endwhile\n"), Dialect::Linuxcnc);
        // lathe_pawn: `%` wrapped, G8 inside: the G8 outweighs the `%`.
        let (dl, why) = detect(b"%\nG8 G18 G21\nG0 X5 Z2\nM2\n%\n");
        assert_eq!(dl, Dialect::Linuxcnc);
        assert!(why.contains("G8") && why.contains("line 2"), "{why}");
    }

    #[test]
    fn fanuc_signs_choose_fanuc() {
        let haas = "%\nO58214\n(BORED PART)\nG18 G40 G80 G99\nG50 S1600\nG00 T101\nT0202\nM30\n%\n";
        let (dl, why) = detect(haas.as_bytes());
        assert_eq!(dl, Dialect::Fanuc);
        assert!(why.contains("program number") && why.contains("line 2"), "{why}");
        assert_eq!(detect(b"%\nG0 X1\n%\n").1, "auto: `%` at line 1");
        assert_eq!(d("G0 T0101\nG0 X50 Z2\n"), Dialect::Fanuc);
        assert_eq!(d("G50 S2000\n"), Dialect::Fanuc);
        assert_eq!(d("M98 P1000\n"), Dialect::Fanuc);
        assert_eq!(d("N10 IF [#1 GT 2] GOTO 20\n"), Dialect::Fanuc);
    }

    #[test]
    fn near_misses_are_no_signs() {
        // G70 and G76 are not G7, G80 is not G8, a comment says nothing, T1 has no offset digits.
        assert_eq!(
            detect(b"G70 P1 Q2\nG80\n(o<x> sub G7)\nT1 M6\n").1,
            "auto: no sign of either dialect, fanuc by default"
        );
        assert_eq!(d("G7.0\n"), Dialect::Linuxcnc);
    }

    #[test]
    fn a_tie_goes_to_fanuc_and_says_so() {
        let (dl, why) = detect(b"G7\nT0101\n");
        assert_eq!(dl, Dialect::Fanuc);
        assert!(why.contains("tie"), "{why}");
    }
}
