//! A multi-path program's paths, from one file: `$1`, `$2`, … lines start each path's lines
//! (the single-file form of Fanuc multi-path and Swiss-type CAM output). Each path is handed on
//! as a copy of the whole source with every other line blanked, so its blocks keep the file's
//! lines, columns and byte offsets: a finding of path 2 points at its line of the file.

/// A line that starts a path: `$n`, blanks around it and an optional comment after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Marker {
    pub path: u32,
    /// Its 1-based line.
    pub line: u32,
    /// The byte offset of the `$`.
    pub at: u32,
}

/// The paths of a source.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Split {
    /// Every marker, in order.
    pub markers: Vec<Marker>,
    /// Per path that has lines (sorted by path): its copy of the source. The lines before the
    /// first marker (`%`, the program number, comments) are in every path's copy.
    pub paths: Vec<(u32, Vec<u8>)>,
}

/// The largest path number a marker may give.
pub const MAX_PATH_NUMBER: u32 = 9;

/// The path a line starts, if it is a marker: `$` and one digit 1–9 first (after blanks), then
/// only blanks, a `( … )` or a `;` comment.
fn marker_of(line: &[u8]) -> Option<(u32, usize)> {
    let start = line.iter().position(|&c| c != b' ' && c != b'\t')?;
    let rest = &line[start..];
    if rest.first() != Some(&b'$') {
        return None;
    }
    let d = *rest.get(1)?;
    if !(b'1'..=b'9').contains(&d) {
        return None;
    }
    let tail = &rest[2..];
    let tail = &tail[tail
        .iter()
        .position(|&c| c != b' ' && c != b'\t' && c != b'\r')
        .unwrap_or(tail.len())..];
    if tail.is_empty() || tail[0] == b'(' || tail[0] == b';' {
        Some(((d - b'0') as u32, start))
    } else {
        None
    }
}

/// The paths of `src`; `None` when it has no marker (a one-path program).
pub fn split(src: &[u8]) -> Option<Split> {
    // Most programs have no marker: find that out without allocating (a long program is never
    // held twice for nothing).
    // A marker holds a `$`: a file without one (a `memchr` away) has none.
    if !src.contains(&b'$')
        || !src
            .split(|&c| c == b'\n' || c == b'\r')
            .any(|line| marker_of(line).is_some())
    {
        return None;
    }
    // Lines: [start, end) without the line break.
    let mut lines: Vec<(usize, usize)> = Vec::new();
    let mut s = 0;
    let mut i = 0;
    while i < src.len() {
        match src[i] {
            b'\n' => {
                lines.push((s, i));
                s = i + 1;
            }
            b'\r' => {
                lines.push((s, i));
                if src.get(i + 1) == Some(&b'\n') {
                    i += 1;
                }
                s = i + 1;
            }
            _ => {}
        }
        i += 1;
    }
    if s < src.len() {
        lines.push((s, src.len()));
    }
    // Which path each line belongs to: 0 = every path (before the first marker), u32::MAX = a
    // marker line (in none).
    let mut owner = Vec::with_capacity(lines.len());
    let mut markers = Vec::new();
    let mut current = 0u32;
    for (k, &(a, b)) in lines.iter().enumerate() {
        match marker_of(&src[a..b]) {
            Some((p, off)) => {
                markers.push(Marker {
                    path: p,
                    line: k as u32 + 1,
                    at: (a + off) as u32,
                });
                current = p;
                owner.push(u32::MAX);
            }
            None => owner.push(current),
        }
    }
    if markers.is_empty() {
        return None;
    }
    let mut numbers: Vec<u32> = markers.iter().map(|m| m.path).collect();
    numbers.sort_unstable();
    numbers.dedup();
    let paths = numbers
        .into_iter()
        .map(|p| {
            let mut text = src.to_vec();
            for (&(a, b), &o) in lines.iter().zip(&owner) {
                if o != 0 && o != p {
                    text[a..b].fill(b' ');
                }
            }
            (p, text)
        })
        .collect();
    Some(Split { markers, paths })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_without_markers_is_one_path() {
        assert_eq!(split(b"G0 X10\n$ not a marker\nM30\n"), None);
        assert_eq!(split(b"G0 X10\n$10\n"), None);
    }

    #[test]
    fn each_path_keeps_the_header_and_its_own_lines_at_their_offsets() {
        let src = b"%\nO100\n$1 (UPPER)\nG0 X1\r\n$2\nG0 X2\n$1\nM30\n";
        let s = split(src).unwrap();
        assert_eq!(
            s.markers.iter().map(|m| (m.path, m.line)).collect::<Vec<_>>(),
            vec![(1, 3), (2, 5), (1, 7)]
        );
        assert_eq!(s.paths.len(), 2);
        let one = std::str::from_utf8(&s.paths[0].1).unwrap();
        let two = std::str::from_utf8(&s.paths[1].1).unwrap();
        assert_eq!(one.len(), src.len());
        assert_eq!(two.len(), src.len());
        assert_eq!(one, "%\nO100\n          \nG0 X1\r\n  \n     \n  \nM30\n");
        assert_eq!(two, "%\nO100\n          \n     \r\n  \nG0 X2\n  \n   \n");
    }
}
