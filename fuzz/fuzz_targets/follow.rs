//! Live samples: any bytes, read as sample lines (JSON or CSV by the first line, a period when
//! the first byte is odd) and followed on the built-in lathe, the two-path twin-turret lathe or
//! the two-path milling head with a lower turret in 3D (by the second byte), never panic the
//! reader or the follower, and every line's work is a move's.
#![no_main]

use latheguard::follow::{lathes, Follower, Format};
use latheguard::machine::{self, Machine};
use latheguard::pipeline::Settings;
use libfuzzer_sys::fuzz_target;
use std::sync::OnceLock;

/// Most lines read of one input: a stream's cost is per line, and this bounds an input's.
const MAX_LINES: usize = 256;

fn machines() -> &'static [Machine; 3] {
    static M: OnceLock<[Machine; 3]> = OnceLock::new();
    M.get_or_init(|| {
        let twin = machine::from_toml(include_str!("../../machines/twin-turret.toml"), "twin-turret.toml")
            .expect("the shipped twin-turret machine loads");
        let head = machine::from_toml(include_str!("../../machines/mill-turn-head.toml"), "mill-turn-head.toml")
            .expect("the shipped mill-turn-head machine loads");
        [Machine::builtin(), twin, head]
    })
}

fuzz_target!(|data: &[u8]| {
    let (flags, rest) = match data {
        [a, b, rest @ ..] => ((*a, *b), rest),
        _ => return,
    };
    let m = &machines()[usize::from(flags.1 % 3)];
    let lathes = lathes(m);
    let settings = Settings {
        tolerance_mm: 0.05,
        ..Settings::default()
    };
    let mut f = Follower::new(m, &lathes, &settings);
    let mut reader = f.reader(Format::Auto);
    if flags.0 & 1 == 1 {
        reader = reader.with_period(0.001);
    }
    let text = String::from_utf8_lossy(rest);
    for (i, line) in text.lines().take(MAX_LINES).enumerate() {
        let at = i as u64 + 1;
        if let Ok(Some(s)) = reader.read(at, line) {
            let _ = f.push(at, &s, reader.period());
        }
        let _ = f.findings();
    }
    let _ = f.finish();
});
