//! Real programs from others (`../shared/corpus`, `../shared/corpus-extra`): read, checked with
//! their jobs, mutated with injected crashes, and compared with LinuxCNC's reference output.
//!
//! One test binary of a few (`autotests = false` in Cargo.toml): each file beside this one is a
//! module here, so the library is linked once per group, not once per file.

#[path = "common/corpus_job.rs"]
mod corpus_job;
#[path = "common/files.rs"]
mod files;
#[path = "common/mutate.rs"]
mod mutate;

mod corpus;
mod corpus_setups;
mod mutation;
mod rs274_reference;
