//! `camsim predict [--f32] [--json] [--check-log FILE]`: the firmware's cam-timing and
//! jump predictor run on the host ([`crate::study::predict`], which holds the study, its
//! report and the report's text). This command reads the arguments into the study's
//! [`Spec`] (the scene file, the measured profile), then prints the report, or with
//! `--check-log` checks the firmware's decoded defmt log bit for bit against the host's
//! f32 run.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, bail, Result};

use camsim_chip::chip_design;
use camsim_core::Design;

use crate::measured::MeasuredProfile;

pub use crate::study::predict::*;

/// Command-line options of `camsim predict`.
#[derive(clap::Args, Debug, Default)]
pub struct Args {
    /// Compute in f32 like the firmware (default: f64).
    #[arg(long = "f32")]
    pub single: bool,
    /// Print JSON (with the raw f32 bit patterns under --f32).
    #[arg(long)]
    pub json: bool,
    /// Decoded defmt log of the firmware to check bit for bit (needs --f32; at most
    /// 16 MB read).
    #[arg(long, requires = "single")]
    pub check_log: Option<PathBuf>,
    /// Scene file compiled into the firmware (`CAMSIM_SCENE=FILE` at its build), positional
    /// like `run`'s; default: the reference design (`camsim_chip::chip_design`).
    #[arg(value_name = "SCENE")]
    pub scene_file: Option<PathBuf>,
    /// The scene file as an option (the same as the positional SCENE).
    #[arg(long, value_name = "SCENE", conflicts_with = "scene_file")]
    pub scene: Option<PathBuf>,
    /// Measured cam profile compiled into the firmware (`CAMSIM_PROFILE=FILE.csv` at its
    /// build; the CSV of `camsim run --measured`, at most 720 rows); default: the
    /// theoretical cam.
    #[arg(long)]
    pub measured: Option<PathBuf>,
}

/// Most bytes of a `--check-log` file read: 16 MB. The host checks 74 parity lines of
/// about 100 bytes; the decoded log of a firmware run around them (boot, timing and
/// defmt lines) is tens of kB, so the cap leaves two orders of magnitude and refuses a
/// device or a runaway capture instead of reading it without end.
pub const MAX_LOG_BYTES: u64 = 16_000_000;

/// The measured profile of `--measured FILE` on `design` (the scene's, in f64): `run
/// --measured`'s checks first (a profile it refuses is refused here with its reason, named
/// as the option as it names it), then the knots as the firmware's build reads them.
fn measured(path: &Path, design: &Design<f64>) -> Result<Measured> {
    crate::measured::load(path)?
        .profile(design)
        .map_err(|e| anyhow!("--measured {}: {e:#}", path.display()))?;
    let knots = ProfileKnots::load(path, design).map_err(|e| anyhow!("--measured {e:#}"))?;
    Ok(Measured {
        file: path.display().to_string(),
        knots,
    })
}

/// The study's spec from the arguments: the scene file (positional or `--scene`) read, the
/// measured profile read on its design.
pub fn spec(args: &Args) -> Result<Spec> {
    let scene_path = args.scene.as_ref().or(args.scene_file.as_ref());
    let scene = match scene_path {
        Some(p) => Some(crate::scene::load(p)?.design),
        None => None,
    };
    let measured = match &args.measured {
        Some(p) => {
            let design = scene.clone().unwrap_or_else(chip_design::<f64>);
            Some(measured(p, &design)?)
        }
        None => None,
    };
    Ok(Spec {
        single: args.single,
        scene_name: scene_path
            .map_or_else(|| REFERENCE_SCENE.to_string(), |p| p.display().to_string()),
        scene,
        measured,
    })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    if args.check_log.is_some() && !args.single {
        bail!("--check-log compares the firmware's f32 bits: add --f32");
    }
    let spec = spec(&args)?;
    if let Some(path) = &args.check_log {
        let host = host_parity(&spec)?;
        let log = camsim_scene_file::read_text(path, MAX_LOG_BYTES, "the firmware log")
            .map_err(|e| anyhow!("--check-log {e}"))?;
        let n = check_parity(&log, &host)?;
        return crate::report::out(&format!("parity OK: {n} lines (table, jump onset, interpolation checks, every reading of the scripted machine) bit-identical\n"));
    }
    crate::report::print(&report(&spec, units)?, args.json, units)
}
