//! `camsim scene`: print the reference design as a scene file, or check a scene file.

use std::path::PathBuf;

use anyhow::Result;

/// Command-line options of `camsim scene`.
#[derive(clap::Args, Debug)]
#[command(group(clap::ArgGroup::new("what").required(true).args(["default", "check"])))]
pub struct Args {
    /// Print the reference design as a complete scene file (with `--units si`, its keys
    /// in SI: `base_radius_mm`, `spring_rate_n_per_mm`, ...).
    #[arg(long, conflicts_with = "check")]
    pub default: bool,
    /// Validate a scene file and print it back complete (every key, defaults filled in;
    /// with `--units si`, its keys in SI).
    #[arg(long, value_name = "FILE")]
    pub check: Option<PathBuf>,
    /// Print the scene as JSON (the file's tables as objects, every key with its unit;
    /// `--units si` converts them) instead of TOML.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let text = if let Some(p) = &args.check {
        let spec = crate::scene::load(p)?;
        crate::scene::spec_text(&spec)?
    } else if args.default {
        crate::scene::default_text()?
    } else {
        anyhow::bail!("camsim scene: give --default (print the reference scene) or --check FILE");
    };
    if args.json {
        return crate::report::out(&format!("{}\n", json(&text)?));
    }
    match crate::units::current() {
        crate::units::Units::Inch => crate::report::out(&text),
        // The same scene with its keys in SI (`base_radius_mm`, ...): it reads back to
        // the same design.
        crate::units::Units::Si if args.default => {
            crate::report::out(&crate::scene::default_text_si()?)
        }
        crate::units::Units::Si => crate::report::out(&crate::scene::in_si(&text)),
    }
}

/// A scene file's text as JSON: its tables as objects, its arrays of tables as arrays,
/// every key in the unit family of `--units` ([`crate::units`]).
pub fn json(text: &str) -> Result<String> {
    let doc: toml::Table = toml::from_str(text)
        .map_err(|e| anyhow::anyhow!("the scene as written does not read back: {e}"))?;
    let value = crate::units::convert(serde_json::to_value(&doc)?, crate::units::current());
    Ok(serde_json::to_string_pretty(&value)?)
}
