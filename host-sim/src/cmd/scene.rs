//! `camsim scene`: print the reference design as a scene file, or check a scene file.

use std::path::PathBuf;

use anyhow::Result;

pub use crate::scene::template::new_template;
use crate::units::Units;

/// Command-line options of `camsim scene`.
#[derive(clap::Args, Debug)]
#[command(group(clap::ArgGroup::new("what").required(true).args(["default", "check", "new"])))]
pub struct Args {
    /// Print the reference design as a complete scene file (with `--units si`, its keys
    /// in SI: `base_radius_mm`, `spring_rate_n_per_mm`, ...).
    #[arg(long, conflicts_with = "check")]
    pub default: bool,
    /// Print a short template of what a designer must decide (program, base and roller
    /// radius, cam width, rpm, moving mass, spring, drive, follower rod), each key with a
    /// one-line comment (with `--units si`, in mm, kg and N/mm): save it, edit it, then `scene
    /// --check FILE` and `run FILE`.
    #[arg(long, conflicts_with_all = ["check", "default", "json"])]
    pub new: bool,
    /// Validate a scene file, list as comments where each value comes from (taken from
    /// the file, derived and from what, inherited from the reference design, grouped:
    /// drive, follower rod and bearings, cam width and materials, masses), and print it
    /// back complete (every key, defaults filled in). Both in the file's unit family: an
    /// SI file's (keys in mm, N, kg) in SI whatever --units says, an inch file's in
    /// inch unless --units si.
    #[arg(long, value_name = "FILE")]
    pub check: Option<PathBuf>,
    /// Print the scene as JSON (the file's tables as objects, every key with its unit;
    /// `--units si` converts them) instead of TOML.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::out(&output(&args, units)?)
}

/// What the command prints, `units` being `--units`.
pub fn output(args: &Args, units: Units) -> Result<String> {
    if args.new {
        return Ok(new_template(units));
    }
    let mut listing = String::new();
    let mut units = units;
    let spec = if let Some(p) = &args.check {
        let spec = crate::scene::load(p)?;
        let file =
            camsim_scene_file::read_text(p, camsim_scene_file::MAX_SCENE_BYTES, "the scene file")?;
        // An SI file is listed and printed back in SI: never an inch key for a value
        // the user wrote in mm, N or kg.
        if crate::scene::file_family(&file)? == Some(Units::Si) {
            units = Units::Si;
        }
        listing = crate::scene::listing(&file, &spec, units)?;
        spec
    } else if args.default {
        crate::sim::RunSpec::reference()
    } else {
        anyhow::bail!("camsim scene: give --default (print the reference scene) or --check FILE");
    };
    if args.json {
        let text = crate::scene::spec_text(&spec)?;
        return Ok(format!("{}\n", json(&text, units)?));
    }
    if !listing.is_empty() {
        listing.push('\n');
    }
    // In SI, the same scene with its keys in SI (`base_radius_mm`, ...): it reads back
    // to the same design.
    let scene = match units {
        Units::Inch if args.default => crate::scene::default_text()?,
        Units::Inch => crate::scene::spec_text(&spec)?,
        Units::Si if args.default => crate::scene::default_text_si()?,
        Units::Si => crate::scene::spec_text_si(&spec)?,
    };
    Ok(listing + &scene)
}

/// A scene file's text as JSON: its tables as objects, its arrays of tables as arrays,
/// every key in the unit family `units` ([`crate::units`]).
pub fn json(text: &str, units: Units) -> Result<String> {
    let doc: toml::Table = toml::from_str(text)
        .map_err(|e| anyhow::anyhow!("the scene as written does not read back: {e}"))?;
    let value = crate::units::convert(serde_json::to_value(&doc)?, units);
    Ok(serde_json::to_string_pretty(&value)?)
}
