//! `camsim scene`: print the reference design as a scene file, or check a scene file.

use std::path::PathBuf;

use anyhow::Result;

/// Command-line options of `camsim scene`.
#[derive(clap::Args, Debug)]
#[command(group(clap::ArgGroup::new("what").required(true).args(["default", "check"])))]
pub struct Args {
    /// Print the reference design as a complete scene file.
    #[arg(long, conflicts_with = "check")]
    pub default: bool,
    /// Validate a scene file and print it back complete (every key, defaults filled in).
    #[arg(long, value_name = "FILE")]
    pub check: Option<PathBuf>,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    if let Some(p) = args.check {
        let spec = crate::scene::load(&p)?;
        return crate::report::out(&crate::scene::spec_text(&spec)?);
    }
    if !args.default {
        anyhow::bail!("camsim scene: give --default (print the reference scene) or --check FILE");
    }
    crate::report::out(&crate::scene::default_text()?)
}
