//! Tests of the geometry kernel: data-driven cases, property tests, sweeps.

mod cases;
mod props;
mod sweeps;
mod util;
