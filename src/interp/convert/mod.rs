//! The converters of the order of execution (`order.rs`): one small function per step, each in
//! a module by subject, each touching only its modal group's state. The order itself, the table
//! of steps and where it comes from, is in `order.rs`.

mod coords;
mod cycle;
mod dwell;
mod feed;
mod flow;
mod m_codes;
mod motion;
mod plane;
mod spindle;
mod tool;
mod units;

pub(crate) use tool::{tip_of, UNMAPPED};
