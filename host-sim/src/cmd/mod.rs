//! One module per `camsim` subcommand.

pub mod contact;
pub mod laws;
pub mod modal;
