//! The words of a program's source as the assumption reads them: each line's code without its
//! comments, the comments, and the numbered words of a letter (T, M).

/// A line's code and its comment text (`( … )` and `;` to the end; several comments joined by
/// a space, trimmed).
pub fn split_comment(line: &str) -> (String, String) {
    if !line.contains(['(', ';']) {
        return (line.to_string(), String::new());
    }
    split_comment_of_chars(line)
}

/// [`split_comment`] of any line, char by char.
fn split_comment_of_chars(line: &str) -> (String, String) {
    let (mut code, mut comment) = (String::new(), String::new());
    let mut depth = 0u32;
    for (k, ch) in line.char_indices() {
        match ch {
            '(' => {
                depth += 1;
                if depth == 1 && !comment.is_empty() {
                    comment.push(' ');
                }
            }
            ')' if depth > 0 => depth -= 1,
            ';' if depth == 0 => {
                comment.push(' ');
                comment.push_str(&line[k + 1..]);
                break;
            }
            _ if depth > 0 => comment.push(ch),
            _ => code.push(ch),
        }
    }
    (code, comment.trim().to_string())
}

/// A line's code without its comments (as [`split_comment`] gives it; the line itself when it
/// has none, most lines of a long program).
pub fn code_of(line: &str) -> std::borrow::Cow<'_, str> {
    if line.contains(['(', ';']) {
        std::borrow::Cow::Owned(split_comment(line).0)
    } else {
        std::borrow::Cow::Borrowed(line)
    }
}

/// The G codes of a line of code, in tenths (`G33.1` → 331, `G71` → 710), each under G100.
pub fn g_codes(code: &str) -> Vec<u32> {
    let mut out = Vec::new();
    if code.is_ascii() {
        // The same reading on bytes (an ASCII line's upper case is its bytes' upper case).
        let b = code.as_bytes();
        for (i, c) in b.iter().enumerate() {
            if !c.eq_ignore_ascii_case(&b'G') || (i > 0 && b[i - 1].is_ascii_alphabetic()) {
                continue;
            }
            let len = b[i + 1..]
                .iter()
                .take_while(|c| c.is_ascii_digit() || **c == b'.')
                .count();
            if let Ok(v) = code[i + 1..i + 1 + len].parse::<f64>() {
                if v.is_finite() && (0.0..1000.0).contains(&v) {
                    out.push((v * 10.0).round() as u32);
                }
            }
        }
        return out;
    }
    g_codes_of_chars(code)
}

/// [`g_codes`] of any text, read char by char in upper case.
fn g_codes_of_chars(code: &str) -> Vec<u32> {
    let mut out = Vec::new();
    let up: Vec<char> = code.to_uppercase().chars().collect();
    for (i, c) in up.iter().enumerate() {
        if *c != 'G' || (i > 0 && up[i - 1].is_alphabetic()) {
            continue;
        }
        let n: String = up[i + 1..]
            .iter()
            .take_while(|c| c.is_ascii_digit() || **c == '.')
            .collect();
        if let Ok(v) = n.parse::<f64>() {
            if v.is_finite() && (0.0..1000.0).contains(&v) {
                out.push((v * 10.0).round() as u32);
            }
        }
    }
    out
}

/// The values of the words of `letter` in a line of code (outside comments): `T0303` → 303,
/// `M6` → 6. Letters inside a name (`#<tool>`, `o<turn>`) and words with no digits (`T#1`) are
/// not words. At most 9 digits.
pub fn numbered(code: &str, letter: char) -> Vec<u32> {
    let chars: Vec<char> = code.chars().collect();
    let mut out = Vec::new();
    let mut in_name = false;
    let mut k = 0;
    while k < chars.len() {
        let c = chars[k];
        if c == '<' {
            in_name = true;
        } else if c == '>' {
            in_name = false;
        } else if !in_name && c.eq_ignore_ascii_case(&letter) && (k == 0 || !chars[k - 1].is_ascii_alphabetic()) {
            let mut j = k + 1;
            while j < chars.len() && chars[j] == ' ' {
                j += 1;
            }
            let start = j;
            while j < chars.len() && chars[j].is_ascii_digit() {
                j += 1;
            }
            // A word's digits end at a letter, a space or the line's end (`G00T0202`); a
            // decimal point makes it another word (`G71.1`).
            let decimal = j < chars.len() && chars[j] == '.';
            if j > start && j - start <= 9 && !decimal {
                let digits: String = chars[start..j].iter().collect();
                if let Ok(v) = digits.parse() {
                    out.push(v);
                }
            }
            k = j.max(k + 1);
            continue;
        }
        k += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// The shortcuts for what most lines are (ASCII, no comment) read as the general way.
        #[test]
        fn shortcuts_read_lines_as_the_general_way(line in "[GgXZ0-9. ;()Nß]{0,16}") {
            prop_assert_eq!(split_comment(&line), split_comment_of_chars(&line));
            prop_assert_eq!(code_of(&line).into_owned(), split_comment_of_chars(&line).0);
            prop_assert_eq!(g_codes(&line), g_codes_of_chars(&line));
        }
    }

    #[test]
    fn t_words_outside_names_and_comments_are_read() {
        let (code, comment) = split_comment("N30 T0303 (BORING BAR) ; more");
        assert_eq!(numbered(&code, 'T'), vec![303]);
        assert!(comment.contains("BORING BAR") && comment.contains("more"));
        assert_eq!(numbered("o<turn> call [1]", 'T'), Vec::<u32>::new());
        assert_eq!(numbered("#<tool> = 3 T#<tool> M6", 'T'), Vec::<u32>::new());
        assert_eq!(numbered("t7 m6", 'M'), vec![6]);
        assert_eq!(numbered("G0 X1 T 12M6", 'T'), vec![12]);
    }
}
