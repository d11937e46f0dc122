//! The output argument group: `--json`, `--plot DIR` and `--force`, one declaration for
//! every command that prints a report and draws plots (a command words its own `--plot`
//! and `--force` help with `#[command(mut_arg(...))]`).

use std::path::PathBuf;

/// What a command prints and draws.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct OutputArgs {
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Write PNG plots into DIR (created if missing; existing plots need --force).
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
    /// Replace existing output files.
    #[arg(long)]
    pub force: bool,
}
