//! The follow-on rule and suppressions against an oracle that knows nothing of episodes.
//!
//! Random contact timelines of a few part pairs (each sample: which pairs are inside each other,
//! under which rule, how deep) and single-move over-travels are fed to the checker's episode
//! bookkeeping as the checker feeds it (a contact extends or opens the pair's episode of that
//! rule; a clear test closes the pair's episodes), then graze and follow-on marking and the gate
//! with random `allow` comments. The oracle reads the timeline alone: every stretch of samples in
//! which a pair stays in contact is one crash, an error at the line where the stretch begins,
//! whatever other pairs or over-travels do meanwhile; every over-travel is an error at its line;
//! an error leaves the failing set only when a suppression names its own kind on its own line.

use latheguard::check::episodes::{self, Contact, Episodes};
use latheguard::finding::{Kind, Severity};
use latheguard::gate::{self, Rules, Suppressions};
use proptest::prelude::*;

/// The pairs of the timelines: (moving part, obstacle).
const PAIRS: [(&str, &str); 4] = [
    ("T01 insert", "stock"),
    ("T01 holder", "chuck"),
    ("turret", "chuck"),
    ("T02 holder", "stock"),
];

/// One sample: per pair, `None` (clear) or the rule and the depth.
type Sample = [Option<(Kind, f64)>; 4];

fn rule() -> impl Strategy<Value = Kind> {
    prop_oneof![
        Just(Kind::Collision),
        Just(Kind::RapidIntoStock),
        Just(Kind::SpindleStopped)
    ]
}

fn one() -> impl Strategy<Value = Option<(Kind, f64)>> {
    prop::option::weighted(0.45, (rule(), 0.2f64..5.0))
}

fn sample() -> impl Strategy<Value = Sample> {
    [one(), one(), one(), one()]
}

fn contact(kind: Kind, objects: [&str; 2], line: u32, time: f64, depth: f64) -> Contact {
    Contact {
        kind,
        objects: objects.map(str::to_string),
        words: None,
        line,
        n: None,
        profile_line: 0,
        time,
        x: 0.0,
        z: 0.0,
        depth: Some(depth),
        message: format!("{} {} {}", kind, objects[0], objects[1]),
        snapshot: None,
        snapshot3: None,
    }
}

fn key(pair: usize, kind: Kind) -> u64 {
    (pair as u64) << 8 | kind as u64
}

const RULES: [Kind; 3] = [Kind::Collision, Kind::RapidIntoStock, Kind::SpindleStopped];

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn every_contact_stretch_and_overtravel_is_an_error_at_its_line_and_suppressions_remove_only_their_own(
        samples in prop::collection::vec(sample(), 1..40),
        // Which samples are also an over-travel of the move they belong to.
        overtravel in prop::collection::vec(prop::bool::weighted(0.15), 40),
        // Each sample starts a new line with this chance (else it is on the line before).
        new_line in prop::collection::vec(prop::bool::weighted(0.6), 40),
        // Allow comments: (line, kind index) pairs.
        allows in prop::collection::vec((1u32..45, 0usize..4), 0..6),
    ) {
        // Lines of the samples.
        let mut lines = Vec::with_capacity(samples.len());
        let mut line = 1u32;
        for (i, _) in samples.iter().enumerate() {
            if i > 0 && new_line[i] {
                line += 1;
            }
            lines.push(line);
        }

        // The checker's bookkeeping.
        let mut ep = Episodes::default();
        for (i, s) in samples.iter().enumerate() {
            let t = i as f64;
            for (p, c) in s.iter().enumerate() {
                match c {
                    Some((kind, depth)) => {
                        // Under another rule than the sample before, the pair has not separated:
                        // the earlier rule's contact lasted until this instant (as exact
                        // measurement finds it, at the boundary of the two moves).
                        if let Some(Some((before, _))) = i.checked_sub(1).map(|j| samples[j][p]) {
                            if before != *kind {
                                ep.lasts_until(key(p, before), t);
                            }
                        }
                        let k = key(p, *kind);
                        if !ep.extend(k, lines[i], t, *depth, false) {
                            let (a, b) = PAIRS[p];
                            ep.contact(k, contact(*kind, [a, b], lines[i], t, *depth));
                        }
                    }
                    None => {
                        for r in RULES {
                            ep.clear(key(p, r));
                        }
                    }
                }
            }
            if overtravel[i] {
                ep.contact(u64::MAX, contact(Kind::Overtravel, ["turret", "X travel"], lines[i], t, 1.0));
                ep.clear(u64::MAX);
            }
        }
        ep.close_all();
        let mut findings = std::mem::take(&mut ep.findings);
        episodes::mark_grazes(&mut findings, 0.1);
        episodes::mark_follow_ons(&mut findings);
        latheguard::finding::sort_findings(&mut findings);

        // Suppressions as comments in a program of as many lines.
        let kinds = [Kind::Collision, Kind::RapidIntoStock, Kind::SpindleStopped, Kind::Overtravel];
        let mut src = String::new();
        for l in 1..=45u32 {
            src.push_str(&format!("G0 X{l}"));
            for &(al, ki) in &allows {
                if al == l {
                    src.push_str(&format!(" (latheguard: allow {} -- why)", kinds[ki]));
                }
            }
            src.push('\n');
        }
        let (sup, problems) = Suppressions::read(src.as_bytes());
        prop_assert!(problems.is_empty());
        let gated = gate::apply(findings.clone(), &Rules::default(), &sup, Vec::new());
        let allowed = |line: u32, kind: Kind| allows.iter().any(|&(l, k)| l == line && kinds[k] == kind);

        // The oracle: stretches of contact per pair, from the timeline alone.
        let mut expected: Vec<(u32, Kind, [String; 2])> = Vec::new();
        for (p, (a, b)) in PAIRS.iter().enumerate() {
            for i in 0..samples.len() {
                let Some((kind, _)) = samples[i][p] else { continue };
                if i > 0 && samples[i - 1][p].is_some() {
                    continue; // the stretch began earlier
                }
                expected.push((lines[i], kind, [a.to_string(), b.to_string()]));
            }
        }
        for i in 0..samples.len() {
            if overtravel[i] {
                expected.push((lines[i], Kind::Overtravel, ["turret".into(), "X travel".into()]));
            }
        }

        // Every stretch and over-travel: an error of its pair at its line, before the gate…
        let errors: Vec<(u32, Kind, [String; 2])> = findings
            .iter()
            .filter(|f| f.severity == Severity::Error)
            .map(|f| (f.line, f.kind, [f.objects[0].clone(), f.objects[1].clone()]))
            .collect();
        let mut want = expected.clone();
        want.sort();
        let mut got = errors.clone();
        got.sort();
        prop_assert_eq!(&got, &want, "errors against the oracle's stretches");

        // …and after it, every one not named by an allow on its own line and kind still fails;
        // each one suppressed is named so.
        for (line, kind, objects) in &expected {
            let failing = gated.findings.iter().any(|f| {
                f.severity == Severity::Error && f.line == *line && f.kind == *kind && f.objects[..] == objects[..]
            });
            let suppressed = gated
                .suppressed
                .iter()
                .any(|s| s.finding.line == *line && s.finding.kind == *kind && s.finding.objects[..] == objects[..]);
            if allowed(*line, *kind) {
                prop_assert!(suppressed && !failing, "{line} {kind} {objects:?} should be suppressed");
            } else {
                prop_assert!(failing, "{line} {kind} {objects:?} hidden by the gate");
            }
        }
        // Warnings (follow-ons) name an earlier crash of the same two parts still in progress.
        for f in findings.iter().filter(|f| f.follow_on.is_some()) {
            let parent = f.follow_on.as_ref().unwrap();
            let mut a = parent.objects.clone();
            let mut b = f.objects.clone();
            a.sort();
            b.sort();
            prop_assert_eq!(a, b);
        }
    }
}
