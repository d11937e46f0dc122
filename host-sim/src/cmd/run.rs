//! `camsim run`: simulate a scene (the built-in reference design by default) and
//! print the per-period table of every revolution, the jumps, the solver statistics
//! and the run time ([`RunReport`]); optionally every sample as CSV and the plots. The
//! study is [`crate::study::run`]; this command reads the arguments into its [`Spec`],
//! plans and writes the files, and prints the report.

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::AngleGrid;

use crate::args::ActualArgs;
pub use crate::args::VerdictArgs;
use crate::args::{self, megabytes, OutputArgs};
pub use crate::args::{spec_from, SceneArgs};
use crate::csv::{self, CsvOut};
use crate::output::{FileTarget, Plan};
use crate::plot;
pub use crate::study::run::*;
use crate::units::Units;

/// The default of `--csv-every-deg`: a row every half degree of cam angle.
pub const DEFAULT_CSV_EVERY_DEG: f64 = 0.5;

/// `--csv-every-deg`: a grid step the core's [`camsim_core::AngleGrid`] accepts.
fn csv_every_deg(s: &str) -> Result<f64, String> {
    let x = args::positive_finite(s)?;
    match camsim_core::AngleGrid::new(x) {
        Ok(_) => Ok(x),
        Err(_) => Err("must be between 3.6e-4 and 360 degrees".into()),
    }
}

/// The default of `--max-csv-mb`: 1000 MB = 1 GB.
pub const DEFAULT_MAX_CSV_MB: u64 = 1000;

/// Command-line options of `camsim run`.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("plot", |a| a.help("Write PNG plots against cam angle into DIR (created if missing; its parent must exist; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --csv and --plot files")))]
pub struct Args {
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Revolutions to simulate, 1-16 (default 3, or the scene's).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::whole_u32::<1, 16>)]
    pub revolutions: Option<u32>,
    /// Write the response to FILE as CSV: one row every --csv-every-deg degrees of cam
    /// angle (written whole at the end of a successful run; an existing FILE needs --force).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// --csv's row spacing, degrees of cam angle (3.6e-4 to 360; default 0.5), plus a row
    /// at every segment's start; taken from the solver's continuous output, as accurate as
    /// its steps.
    #[arg(long, value_name = "DEG", default_value_t = DEFAULT_CSV_EVERY_DEG, allow_hyphen_values = true, value_parser = csv_every_deg, conflicts_with = "csv_every_step")]
    pub csv_every_deg: f64,
    /// --csv gets one row per solver sample (the midpoint and end of every step: uneven,
    /// and hundreds of times larger than the default grid) instead of the angle grid.
    #[arg(long)]
    pub csv_every_step: bool,
    /// Largest --csv file, MB (10^6 bytes; the default is 1 GB). The size is estimated
    /// before the run (about 850 B a row; the grid's rows are counted, --csv-every-step's
    /// estimated from the tolerance) and a larger one is refused; a run that writes more
    /// stops with an error and leaves no file.
    #[arg(long, value_name = "MB", default_value_t = DEFAULT_MAX_CSV_MB, allow_hyphen_values = true, value_parser = megabytes)]
    pub max_csv_mb: u64,
    /// An actual cam drawn from tolerances (`--actual` and its options).
    #[command(flatten)]
    pub actual: ActualArgs,
    /// Simulate a measured profile: a CSV with the header `angle_deg,deviation_in`
    /// (lift deviation), `angle_deg,lift_in` (lift) or `angle_deg,radius_in` (cam
    /// surface polar radius, followed by the roller's exact envelope); see docs/COMMANDS.md.
    #[arg(long, value_name = "FILE.csv", conflicts_with = "actual")]
    pub measured: Option<PathBuf>,
    /// The verdict's limits and its jump margin.
    #[command(flatten)]
    pub verdict: VerdictArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

impl Default for Args {
    fn default() -> Self {
        Args {
            actual: ActualArgs::default(),
            measured: None,
            scene: SceneArgs::default(),
            revolutions: None,
            csv: None,
            csv_every_deg: DEFAULT_CSV_EVERY_DEG,
            csv_every_step: false,
            max_csv_mb: DEFAULT_MAX_CSV_MB,
            output: OutputArgs::default(),
            verdict: VerdictArgs::default(),
        }
    }
}

/// The study's spec of `args`: the scene, its revolutions, the cam (a measured profile
/// is read here), the verdict's limits and the samples the outputs need.
pub fn spec(args: &Args, units: Units) -> Result<Spec> {
    args.actual.ensure_actual_if_options()?;
    let mut run = spec_from(&args.scene)?;
    if let Some(n) = args.revolutions {
        run.revolutions = n;
    }
    let cam = if let Some(path) = &args.measured {
        Cam::Measured {
            profile: crate::measured::load(path)?,
            name: format!("--measured {}", path.display()),
        }
    } else if args.actual.actual {
        Cam::Actual(args.actual.cams())
    } else {
        Cam::Theoretical
    };
    // The grid's step was checked by the option's parser.
    let grid = match args.csv_every_step {
        false => AngleGrid::new(args.csv_every_deg)?,
        true => AngleGrid::segment_starts(),
    };
    Ok(Spec {
        limits: args.verdict.limits(&run.limits, units),
        run,
        cam,
        margin: args.verdict.margin,
        scene_file: args.scene.scene.as_ref().map(|p| p.display().to_string()),
        grid,
        plot: args.output.plot.is_some(),
    })
}

/// The output plan, told which files the run reads (so no output overwrites them).
fn input_plan(args: &Args) -> Plan {
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene.scene {
        plan.input("scene file", p);
    }
    if let Some(p) = &args.measured {
        plan.input("--measured", p);
    }
    plan
}

/// `--csv`'s target, refused before the run when its rows (on the cam-angle grid, else
/// estimated from the solver's steps) would pass `--max-csv-mb`.
fn csv_target(plan: &mut Plan, args: &Args, spec: &Spec) -> Result<Option<FileTarget>> {
    let Some(p) = &args.csv else {
        return Ok(None);
    };
    let bytes = match args.csv_every_step {
        false => csv::rows_bytes(csv::grid_rows(&spec.run, &spec.grid)),
        true => csv::estimated_bytes(&spec.run),
    };
    let limit = args.max_csv_mb.saturating_mul(1_000_000);
    Ok(Some(plan.file("--csv", p)?.limit(
        bytes,
        limit,
        "--max-csv-mb N",
    )?))
}

/// `--plot`'s directory (with the profile's figure for an actual or measured cam).
fn plot_target(
    plan: &mut Plan,
    args: &Args,
    cam: &Cam,
) -> Result<Option<crate::output::DirTarget>> {
    Ok(match &args.output.plot {
        Some(dir) if !matches!(cam, Cam::Theoretical) => {
            Some(plan.dir("--plot", dir, &plot::FILES_WITH_PROFILE)?)
        }
        Some(dir) => {
            Some(plan.dir_replacing("--plot", dir, &plot::FILES, &[plot::PROFILE_FILE])?)
        }
        None => None,
    })
}

/// Runs the simulation `args` asks for and writes its outputs: every output is checked
/// before the simulation (a refusal touches no file), written to temporaries during it,
/// and committed only when all succeeded (and the report is finite).
pub fn report(args: &Args, units: Units) -> Result<RunReport> {
    let spec = spec(args, units)?;
    let mut plan = input_plan(args);
    let csv_target = csv_target(&mut plan, args, &spec)?;
    let plot_target = plot_target(&mut plan, args, &spec.cam)?;
    let mut rows = csv::CsvRows {
        csv: csv_target
            .map(|t| t.open().map(|f| CsvOut::new(f, units)))
            .transpose()?,
        every_step: args.csv_every_step,
    };
    let run = report_observed(&spec, units, &mut rows)?;
    let csv_file = rows.csv.map(CsvOut::into_file).transpose()?;
    let plots = match (plot_target, &run.plot) {
        (Some(t), Some(data)) => Some(plot::draw_run(
            t.open()?,
            data,
            &run.jumps,
            run.profile.as_deref(),
            units,
        )?),
        _ => None,
    };
    let mut report = run.report;
    if let Some(f) = csv_file {
        let path = f.target().display().to_string();
        f.commit()?;
        report.files.push(path);
    }
    if let Some(p) = plots {
        let done = p.commit()?;
        (report.files).extend(done.written.iter().map(|f| f.display().to_string()));
    }
    Ok(report)
}

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    crate::report::print(&report(&args, units)?, args.output.json, units)
}
