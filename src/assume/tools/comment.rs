//! What a program's comments say of a station's tool: `T0303 (BORING BAR)`, `(T3 BORE)` on the
//! line before, `N30 T0101 (OD ROUGH)`, LinuxCNC `T3 M6 (drill 10mm)`, and a tool list at the
//! head of the program (`(T6 DRILL 20)`).

use crate::assume::words::{code_of, split_comment};
use std::collections::BTreeMap;

use super::super::reading::Reading;
use super::ToolKind;

/// A comment that names a tool kind.
#[derive(Clone, Debug, PartialEq)]
pub struct Said {
    pub kind: ToolKind,
    /// It says the tool works inside (`ID`, `INT`, `INTERNAL`, `BORE`).
    pub internal: bool,
    /// A size it gives, mm: a drill's or tap's diameter, a boring bar's, a groove's width.
    pub size: Option<f64>,
    /// The comment as written, trimmed.
    pub text: String,
    /// 1-based line of the comment.
    pub line: u32,
}

/// The words of a text, upper case, split at anything not a letter or digit (`U-DRILL` → `U`,
/// `DRILL`).
fn words(up: &str) -> Vec<&str> {
    up.split(|c: char| !c.is_alphanumeric())
        .filter(|w| !w.is_empty())
        .collect()
}

/// The tool kind a comment names, and whether it says the tool works inside.
pub fn kind_of(text: &str) -> Option<(ToolKind, bool)> {
    let up = text.to_uppercase();
    let w = words(&up);
    let has = |p: &str| w.iter().any(|x| x.starts_with(p));
    let is = |p: &str| w.contains(&p);
    // German setters write compounds (`Innengewinde`, `Aussendrehen`): a part of a word counts.
    let inner = |p: &str| w.iter().any(|x| x.contains(p));
    let pair = |a: &str, b: &str| w.windows(2).any(|p| p[0] == a && p[1] == b);
    let internal =
        is("ID") || is("INT") || has("INTERNAL") || has("BOR") || inner("INNEN") || has("AUSDREH") || has("BOHRSTANG");
    // German: Bohrer, Bohren, Zentrierbohrer (a drill); Bohrstange (a boring bar); Gewindebohrer
    // (a tap).
    let bohr_drill = w.iter().any(|x| {
        (x.starts_with("BOHR") && !x.starts_with("BOHRSTANG") && !x.starts_with("BOHRUNG"))
            || (x.ends_with("BOHRER") && !x.contains("GEWINDE"))
    }) || has("ZENTRIER");
    let parting = is("CUTOFF")
        || is("PARTOFF")
        || has("PARTING")
        || pair("CUT", "OFF")
        || inner("ABSTECH")
        || w.iter().enumerate().any(|(i, x)| {
            *x == "PART"
                && w.get(i + 1).map_or(true, |n| {
                    ["OFF", "TOOL", "BLADE", "INSERT"].contains(n) || n.starts_with(|c: char| c.is_ascii_digit())
                })
        });
    let turning = has("ROUGH")
        || has("FINISH")
        || has("TURN")
        || is("OD")
        || has("PROFIL")
        || is("CONTOUR")
        || inner("AUSSENDREH")
        || has("SCHRUPP")
        || has("SCHLICHT")
        || has("DREH");
    let kind = if has("DRILL") || is("SPOT") || bohr_drill {
        ToolKind::Drilling
    } else if is("TAP") || is("TAPS") || is("TAPPING") || inner("GEWINDEBOHR") {
        ToolKind::Tapping
    } else if has("THREAD") || is("THD") || is("THRD") || inner("GEWINDE") {
        ToolKind::Threading
    } else if has("GROOV") || inner("EINSTECH") {
        ToolKind::Grooving
    } else if parting {
        ToolKind::Parting
    } else if has("BOR") || is("ID") || inner("INNENDREH") || has("AUSDREH") || has("BOHRSTANG") || has("AUSBOHR") {
        ToolKind::Boring
    } else if (has("FACE") || has("FACING") || inner("PLANDREH")) && !turning {
        ToolKind::Facing
    } else if turning {
        ToolKind::OdTurning
    } else {
        return None;
    };
    Some((kind, internal))
}

/// A size the comment gives, mm (`scale`: mm per program unit, for a number without its unit):
/// `Ø12`, `D=10`, `D16`, `DIA 20`, `M10` (a tap), `W3` (a groove), `10MM`, and for a drill or
/// tap a bare number (`DRILL 10`); a boring bar's only as `D16`, `Ø16` or `BAR 16` (`BORES FROM
/// 16 MM` is the bore). `None` when it gives none, or none in 0 < size ≤ 200 mm.
pub fn size_of(text: &str, kind: ToolKind, scale: f64) -> Option<f64> {
    let up: Vec<char> = text.to_uppercase().chars().collect();
    let mut strong = None;
    let mut with_unit = None;
    let mut bare = None;
    let mut i = 0;
    while i < up.len() {
        let starts = up[i].is_ascii_digit() || (up[i] == '.' && up.get(i + 1).is_some_and(|c| c.is_ascii_digit()));
        if !starts || (i > 0 && (up[i - 1].is_ascii_digit() || up[i - 1] == '.')) {
            i += 1;
            continue;
        }
        let mut j = i;
        while j < up.len() && (up[j].is_ascii_digit() || up[j] == '.') {
            j += 1;
        }
        let s: String = up[i..j].iter().collect();
        let v = s.parse::<f64>().ok().filter(|v| v.is_finite());
        // The word just before (letters, skipping spaces, `=` and `:`), and whether it touches.
        let mut k = i;
        while k > 0 && matches!(up[k - 1], ' ' | '=' | ':') {
            k -= 1;
        }
        let touches = k == i || up[k..i].iter().all(|c| *c == '=');
        let mut b = k;
        while b > 0 && up[b - 1].is_alphabetic() {
            b -= 1;
        }
        let before: String = up[b..k].iter().collect();
        let mut a = j;
        while a < up.len() && up[a] == ' ' {
            a += 1;
        }
        let mut e = a;
        while e < up.len() && (up[e].is_alphabetic() || up[e] == '"') {
            e += 1;
        }
        let after: String = up[a..e].iter().collect();
        i = j;
        let Some(v) = v else { continue };
        let unit = match after.as_str() {
            "MM" => 1.0,
            "IN" | "INCH" | "\"" => 25.4,
            _ => scale,
        };
        let mm = v * unit;
        let strong_word = match before.as_str() {
            "Ø" | "⌀" | "DIA" | "DIAM" | "DIAMETER" => true,
            "D" | "W" => touches,
            "M" => touches && kind == ToolKind::Tapping,
            _ => false,
        };
        if strong_word || (kind == ToolKind::Boring && before == "BAR") {
            strong = strong.or(Some(mm));
        } else if kind == ToolKind::Boring {
            // `BORES FROM 16 MM` is the bore, not the bar: a bar's size is written `D16`.
        } else if matches!(after.as_str(), "MM" | "IN" | "INCH" | "\"")
            && !["T", "N", "R", "F", "S"].contains(&before.as_str())
        {
            with_unit = with_unit.or(Some(mm));
        } else if matches!(kind, ToolKind::Drilling | ToolKind::Tapping)
            && (before.is_empty() || words(&before).iter().any(|w| w.starts_with("DRILL") || *w == "TAP"))
            && !after.starts_with("DEG")
            && !up[j..].first().is_some_and(|c| *c == '°')
        {
            bare = bare.or(Some(mm));
        }
    }
    strong.or(with_unit).or(bare).filter(|v| *v > 0.0 && *v <= 200.0)
}

/// The number of the first T word in a line's code (`T0303`, `T3`), or `None`.
fn t_word(code: &str) -> Option<String> {
    let up: Vec<char> = code.to_uppercase().chars().collect();
    for (i, c) in up.iter().enumerate() {
        if *c != 'T' || (i > 0 && up[i - 1].is_alphabetic()) {
            continue;
        }
        let digits: String = up[i + 1..].iter().take_while(|c| c.is_ascii_digit()).collect();
        if !digits.is_empty() {
            return Some(digits);
        }
    }
    None
}

/// The station a T number names: Fanuc's first two digits of four (`T0303` → 3), the first of
/// three (`T303` → 3), else the number itself (`T3`, LinuxCNC's tool number).
pub fn station_of(digits: &str) -> Option<u32> {
    let lead = match digits.len() {
        4 => &digits[..2],
        3 => &digits[..1],
        1 | 2 => digits,
        _ => return None,
    };
    lead.parse().ok()
}

/// What the comments say, by station: the comment on a T word's line, else on a comment-only
/// line just before or after it, else the first CAM step heading (a comment-only line starting
/// `STEP`) that names a tool before the next T word, each at the station the program's moves run
/// at that line or the next move (the segments are authoritative); then a comment-only line that starts with
/// `T<n>` (a tool list) for a station no T word's comment named.
pub fn read(r: &Reading, scale: f64) -> BTreeMap<u32, Said> {
    // Each line is split into code and comment when it is looked at (a long program's lines
    // are not all held split).
    let part = |i: usize| r.lines.get(i).map(|l| split_comment(&l));
    let comment_only = |i: usize| part(i).and_then(|(code, comment)| only_comment(&code, comment));
    let said = |text: &str, i: usize| -> Option<Said> {
        let (kind, internal) = kind_of(text)?;
        Some(Said {
            kind,
            internal,
            size: size_of(text, kind, scale),
            text: text.trim().to_string(),
            line: i as u32 + 1,
        })
    };
    let mut out = BTreeMap::new();
    let t_lines: Vec<usize> = r
        .lines
        .iter()
        .enumerate()
        .filter(|(_, l)| t_word(&code_of(l)).is_some())
        .map(|(i, _)| i)
        .collect();
    // The moves up to the next T word run with each one's tool: the station of the first move
    // at a line from the T word's on, before the next T word's (by line; of the moves at that
    // line, the first run), found in one walk of the segments.
    let starts: Vec<u32> = t_lines.iter().map(|&i| i as u32 + 1).collect();
    let mut first: Vec<Option<(u32, u32)>> = vec![None; starts.len()];
    for s in r.segs.iter() {
        let Some(k) = starts.partition_point(|&a| a <= s.line).checked_sub(1) else {
            continue;
        };
        if first[k].map_or(true, |(line, _)| s.line < line) {
            first[k] = Some((s.line, s.station));
        }
    }
    for (k, &i) in t_lines.iter().enumerate() {
        let Some((code, comment)) = part(i) else { continue };
        let Some(digits) = t_word(&code) else { continue };
        let until = t_lines.get(k + 1).map_or(u32::MAX, |&n| n as u32 + 1);
        // None: its own number.
        let Some(station) = first[k].map(|(_, s)| s).or_else(|| station_of(&digits)) else {
            continue;
        };
        // A comment-only line next to it, unless it names another tool (`(T3 BORE)`), or
        // stands just before the next T word (then it is that one's).
        let next_to = |j: usize| {
            let c = comment_only(j)?;
            let other = t_word(&c).and_then(|d| station_of(&d)).is_some_and(|n| n != station);
            (!other).then(|| said(&c, j)).flatten()
        };
        let t_next = part(i + 2).is_some_and(|(code, _)| t_word(&code).is_some());
        let found = said(&comment, i)
            .or_else(|| i.checked_sub(1).and_then(next_to))
            .or_else(|| if t_next { None } else { next_to(i + 1) });
        // Else a CAM step heading (`(STEP: 5. Abspanen Ausdrehen …)`) while the tool is in use.
        let step = || {
            (i + 1..(until as usize - 1).min(r.lines.len())).find_map(|j| {
                let c = comment_only(j)?;
                c.trim_start()
                    .to_uppercase()
                    .starts_with("STEP")
                    .then(|| said(&c, j))
                    .flatten()
            })
        };
        if let Some(s) = found.or_else(step) {
            out.entry(station).or_insert(s);
        }
    }
    for (i, l) in r.lines.iter().enumerate() {
        let (code, comment) = split_comment(&l);
        let Some(c) = only_comment(&code, comment) else {
            continue;
        };
        let listed = t_word(&c)
            .filter(|_| c.trim_start().to_uppercase().starts_with('T'))
            .map(|d| (d, c.as_str()));
        let Some((digits, text)) = listed.or_else(|| described(&c)) else {
            continue;
        };
        if let (Some(station), Some(s)) = (station_of(&digits), said(text, i)) {
            out.entry(station).or_insert(s);
        }
    }
    out
}

/// The comment of a line that holds nothing else (an N number aside).
fn only_comment(code: &str, comment: String) -> Option<String> {
    let code = code
        .trim()
        .trim_start_matches(['N', 'n'])
        .trim_start_matches(|c: char| c.is_ascii_digit());
    (code.trim().is_empty() && !comment.is_empty()).then_some(comment)
}

/// A tool named inside a longer comment, as CAM systems write a step's tool: `(Step 4: turn |
/// T2: CCMT Aussendrehen)` → the digits `2` and `CCMT Aussendrehen` (up to the next `|`). The
/// T stands at the comment's start or after a space, `|` or `,`, and a colon follows its number.
fn described(c: &str) -> Option<(String, &str)> {
    let b = c.as_bytes();
    for (k, ch) in c.char_indices() {
        if !(ch == 'T' || ch == 't') || (k > 0 && !matches!(b[k - 1], b' ' | b'|' | b',')) {
            continue;
        }
        let digits: String = c[k + 1..].chars().take_while(|d| d.is_ascii_digit()).collect();
        let after = k + 1 + digits.len();
        if digits.is_empty() || b.get(after) != Some(&b':') {
            continue;
        }
        let rest = &c[after + 1..];
        let text = rest.split('|').next().unwrap_or(rest).trim();
        return (!text.is_empty()).then_some((digits, text));
    }
    None
}
