//! Machine files: arbitrary text never panics the TOML loader and its validation.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = latheguard::machine::from_toml(text, "fuzz.toml");
    }
});
