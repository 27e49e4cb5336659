//! latheguard: verifies CNC lathe programs against a machine description.
//!
//! The library does no file I/O and never panics on any input. See `ARCHITECTURE.md` for the
//! pipeline: [`gcode`] → [`interp`] → [`motion`] → [`scene`] → [`check`] → [`report`].

pub mod accuracy;
pub mod assume;
pub mod check;
pub mod collide3;
pub mod finding;
pub mod follow;
pub mod gate;
pub mod gcode;
pub mod geom;
pub mod grid;
pub mod interp;
pub mod job;
pub mod kin;
pub mod machine;
pub mod motion;
pub mod paths;
pub mod pipeline;
pub mod report;
pub mod scene;
pub mod source;
pub mod tooling;

/// Helpers the unit tests share.
#[cfg(test)]
pub(crate) mod test_util {
    /// Numbers in [0, 1) from `seed`, the same on every platform and run (a 64-bit linear
    /// congruential generator's top 53 bits): random cases a test can name by their seed.
    pub fn unit_random(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}
