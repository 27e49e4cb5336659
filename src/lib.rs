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
