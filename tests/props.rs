//! Property tests: the checker's and the interpreter's pieces against slow, obviously right oracles.
//!
//! One test binary of a few (`autotests = false` in Cargo.toml): each file beside this one is a
//! module here, so the library is linked once per group, not once per file.

mod comp_props;
mod cycles2_props;
mod cycles_props;
mod exact_props;
mod follow_on_props;
mod gap_props;
mod kin_props;
mod stock_instant_props;
mod stock_props;
