//! The camsim harness as a library: every command is a module of [`cmd`], so the
//! integration tests can call the same code the binary runs, and [`cli`] is the binary.

pub mod actual;
pub mod args;
pub mod bench;
pub mod cli;
pub mod cmd;
pub mod csv;
pub mod export;
pub mod figure;
pub mod firmware_log;
pub mod measured;
pub mod output;
pub mod plot;
pub mod report;
pub mod scene;
pub mod shard;
pub mod sim;
pub mod stats;
pub mod study;
pub mod study_limits;
pub mod units;

/// `camsim run`'s verdict ([`study::run::verdict`]), at the path its callers use.
pub use study::run::verdict;
