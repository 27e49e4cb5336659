//! Stable fingerprints of findings, for CI systems that track a finding from run to run (GitLab
//! Code Quality `fingerprint`, SARIF `partialFingerprints`).
//!
//! A fingerprint hashes what a finding *is*, not where the file happens to put it: the path, the
//! kind, the parts involved, the text of its source line (blanks squeezed), and its rank among the
//! findings of the file with those same four. A line inserted above a crash leaves the crash's
//! fingerprint as it was; editing the crashing line, or the crash changing parts, gives a new one.
//! Times, depths and line numbers are left out (they move with every edit above). The hash is
//! FNV-1a over the fields, twice with two offset bases, printed as 32 hex digits.

use super::FileReport;
use crate::finding::Finding;
use crate::source::LineIndex;
use std::collections::HashMap;

const PRIME: u64 = 0x0000_0100_0000_01b3;

fn fnv(seed: u64, parts: &[&[u8]]) -> u64 {
    let mut h = seed;
    for p in parts {
        for &b in *p {
            h ^= u64::from(b);
            h = h.wrapping_mul(PRIME);
        }
        // A separator no field can hold, so ("ab","c") and ("a","bc") differ.
        h ^= 0xff;
        h = h.wrapping_mul(PRIME);
    }
    h
}

/// The fingerprint of something said about a whole file (`what`, such as `no_motion`).
pub fn file_fingerprint(path: &str, what: &str) -> String {
    let a = fnv(0xcbf2_9ce4_8422_2325, &[path.as_bytes(), what.as_bytes()]);
    let b = fnv(0x6c62_272e_07bb_0142, &[path.as_bytes(), what.as_bytes()]);
    format!("{a:016x}{b:016x}")
}

/// The fingerprints of a file's findings, in the order of `findings`.
pub fn fingerprints(file: &FileReport, findings: &[&Finding]) -> Vec<String> {
    let lines = (!file.source.is_empty()).then(|| LineIndex::new(&file.source));
    let mut rank: HashMap<u64, u32> = HashMap::new();
    findings
        .iter()
        .map(|f| {
            let text = lines
                .as_ref()
                .filter(|li| f.line >= 1 && (f.line as usize) <= li.line_count())
                .map(|li| {
                    let raw = String::from_utf8_lossy(&file.source[li.line_span(&file.source, f.line).range()]);
                    raw.split_whitespace().collect::<Vec<_>>().join(" ")
                })
                .unwrap_or_default();
            let objects = f.objects.join("\u{1f}");
            let parts: [&[u8]; 4] = [
                file.path.as_bytes(),
                f.kind.name().as_bytes(),
                objects.as_bytes(),
                text.as_bytes(),
            ];
            let key = fnv(0xcbf2_9ce4_8422_2325, &parts);
            let n = rank.entry(key).or_insert(0);
            *n += 1;
            let nth = n.to_le_bytes();
            let a = fnv(0xcbf2_9ce4_8422_2325, &[&key.to_le_bytes(), &nth]);
            let b = fnv(0x6c62_272e_07bb_0142, &[&key.to_le_bytes(), &nth]);
            format!("{a:016x}{b:016x}")
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::finding::{Kind, Severity};

    fn file(src: &str, findings: Vec<Finding>) -> FileReport {
        FileReport {
            path: "cell/p.nc".into(),
            findings,
            source: src.as_bytes().to_vec(),
            ..FileReport::default()
        }
    }

    fn crash(line: u32) -> Finding {
        let mut f = Finding::at(Kind::Collision, Severity::Error, line, 0, "hit");
        f.objects = vec!["T01 holder".into(), "chuck".into()];
        f
    }

    #[test]
    fn a_line_inserted_above_keeps_the_fingerprint_and_an_edit_of_the_line_changes_it() {
        let a = file("G0 X1\nG1 Z-120.\n", vec![crash(2)]);
        let b = file("(new comment)\nG0 X1\nG1 Z-120.\n", vec![crash(3)]);
        let c = file("G0 X1\nG1 Z-121.\n", vec![crash(2)]);
        let fp = |f: &FileReport| fingerprints(f, &f.findings.iter().collect::<Vec<_>>());
        assert_eq!(fp(&a), fp(&b));
        assert_ne!(fp(&a), fp(&c));
        assert_eq!(fp(&a)[0].len(), 32);
    }

    #[test]
    fn identical_findings_in_one_file_get_different_fingerprints() {
        let a = file("G1 Z-120.\nG1 Z-120.\n", vec![crash(1), crash(2)]);
        let fp = fingerprints(&a, &a.findings.iter().collect::<Vec<_>>());
        assert_ne!(fp[0], fp[1]);
    }
}
