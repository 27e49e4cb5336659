//! The command-line tests: they run the `latheguard` binary on copies of `tests/fixtures` and read
//! its reports, pictures, schemas and exit codes; every example of the README and docs.
//!
//! One test binary of a few (`autotests = false` in Cargo.toml): each file beside this one is a
//! module here, so the library is linked once per group, not once per file.

mod common;

mod cli_batch;
mod cli_gate;
mod cli_graze;
mod cli_hostile;
mod cli_job;
mod cli_machine_file;
mod cli_snapshots;
mod cli_stock_out;
mod cli_tools;
mod comp_svg;
mod docs_examples;
mod machine_drawings;
mod machine_schema;
mod pictures;
mod report3d;
