//! `camsim scene`: print the reference design as a scene file, or check a scene file.

use std::path::PathBuf;

use anyhow::Result;

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
    /// radius, cam width, rpm, moving mass, spring, drive), each key with a one-line
    /// comment (with `--units si`, in mm, kg and N/mm): save it, edit it, then `scene
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
pub fn run(args: Args) -> Result<()> {
    crate::report::out(&output(&args, crate::units::current())?)
}

/// What the command prints, `units` being `--units`.
pub fn output(args: &Args, units: Units) -> Result<String> {
    if args.new {
        return Ok(match units {
            Units::Inch => NEW_INCH,
            Units::Si => NEW_SI,
        }
        .to_string());
    }
    let mut listing = String::new();
    let mut units = units;
    let text = if let Some(p) = &args.check {
        let spec = crate::scene::load(p)?;
        let file =
            camsim_scene_file::read_text(p, camsim_scene_file::MAX_SCENE_BYTES, "the scene file")?;
        // An SI file is listed and printed back in SI: never an inch key for a value
        // the user wrote in mm, N or kg.
        if crate::scene::file_family(&file)? == Some(Units::Si) {
            units = Units::Si;
        }
        listing = crate::scene::listing(&file, &spec, units)?;
        crate::scene::spec_text(&spec)?
    } else if args.default {
        crate::scene::default_text()?
    } else {
        anyhow::bail!("camsim scene: give --default (print the reference scene) or --check FILE");
    };
    if args.json {
        return Ok(format!("{}\n", json_in(&text, units)?));
    }
    if !listing.is_empty() {
        listing.push('\n');
    }
    let scene = match units {
        Units::Inch => text,
        // The same scene with its keys in SI (`base_radius_mm`, ...): it reads back to
        // the same design.
        Units::Si if args.default => crate::scene::default_text_si()?,
        Units::Si => crate::scene::in_si(&text),
    };
    Ok(listing + &scene)
}

/// A scene file's text as JSON: its tables as objects, its arrays of tables as arrays,
/// every key in the unit family of `--units` ([`crate::units`]).
pub fn json(text: &str) -> Result<String> {
    json_in(text, crate::units::current())
}

/// [`json`] in the unit family `units`.
fn json_in(text: &str, units: Units) -> Result<String> {
    let doc: toml::Table = toml::from_str(text)
        .map_err(|e| anyhow::anyhow!("the scene as written does not read back: {e}"))?;
    let value = crate::units::convert(serde_json::to_value(&doc)?, units);
    Ok(serde_json::to_string_pretty(&value)?)
}

/// `scene --new`'s template in the inch family: a machine of the reference's size at
/// 300 rpm with a lighter 0.75 in rise and return.
pub const NEW_INCH: &str = r#"# A cam machine in a designer's terms (camsim scene --new): decide each value, then
# `camsim scene --check FILE` (everything the model takes from elsewhere) and `camsim run FILE`.
# Every key not here is the reference design's (docs/MODEL.md section 5).

[run]
rpm = 300.0  # cam speed, rpm

[design]
moving_mass_lb = 4.5  # all that translates: load, follower rod, roller and a third of the spring, lb
spring_rate_lb_per_in = 60.0  # return spring rate
spring_preload_length_in = 1.0  # how far the spring is compressed with the roller on the base circle
drive = "constant-cam-speed"  # the cam turns at exactly rpm; or "thesis" (its regulated 1.75 hp motor), or a [design.drive.motor] table (inertia, shaft_stiffness, gain, torque_limit)

[design.geometry]
base_radius_in = 2.5  # base circle radius
roller_radius_in = 0.5  # roller radius
thickness_in = 0.375  # cam width (its mass)

[design.hertz]
contact_length_in = 0.375  # cam width in contact with the roller (sets the contact stress)

[[design.program.segment]]  # rise over 120 deg from 0 deg (the roller on the base circle)
kind = "rise"
law = "modified-sine"  # camsim laws lists the motion laws
start_deg = 0.0
end_deg = 120.0
lift_in = 0.75  # lift of this segment

[[design.program.segment]]  # dwell at full lift
kind = "dwell"
start_deg = 120.0
end_deg = 180.0

[[design.program.segment]]  # return over 120 deg
kind = "return"
law = "modified-sine"  # the return's motion law
start_deg = 180.0
end_deg = 300.0
lift_in = 0.75  # the returns undo the rises

[[design.program.segment]]  # dwell on the base circle
kind = "dwell"
start_deg = 300.0
end_deg = 360.0
"#;

/// `scene --new`'s template in SI (`--units si`): [`NEW_INCH`]'s machine in round mm, kg
/// and N/mm.
pub const NEW_SI: &str = r#"# A cam machine in a designer's terms (camsim scene --new --units si): decide each value, then
# `camsim scene --check FILE` (everything the model takes from elsewhere) and `camsim run FILE`.
# Every key not here is the reference design's (docs/MODEL.md section 5).

[run]
rpm = 300.0  # cam speed, rpm

[design]
moving_mass_kg = 2.0  # all that translates: load, follower rod, roller and a third of the spring, kg
spring_rate_n_per_mm = 10.0  # return spring rate
spring_preload_length_mm = 25.0  # how far the spring is compressed with the roller on the base circle
drive = "constant-cam-speed"  # the cam turns at exactly rpm; or "thesis" (its regulated 1.75 hp motor), or a [design.drive.motor] table (inertia, shaft_stiffness, gain, torque_limit)

[design.geometry]
base_radius_mm = 60.0  # base circle radius
roller_radius_mm = 12.5  # roller radius
thickness_mm = 10.0  # cam width (its mass)

[design.hertz]
contact_length_mm = 10.0  # cam width in contact with the roller (sets the contact stress)

[[design.program.segment]]  # rise over 120 deg from 0 deg (the roller on the base circle)
kind = "rise"
law = "modified-sine"  # camsim laws lists the motion laws
start_deg = 0.0
end_deg = 120.0
lift_mm = 20.0  # lift of this segment

[[design.program.segment]]  # dwell at full lift
kind = "dwell"
start_deg = 120.0
end_deg = 180.0

[[design.program.segment]]  # return over 120 deg
kind = "return"
law = "modified-sine"  # the return's motion law
start_deg = 180.0
end_deg = 300.0
lift_mm = 20.0  # the returns undo the rises

[[design.program.segment]]  # dwell on the base circle
kind = "dwell"
start_deg = 300.0
end_deg = 360.0
"#;
