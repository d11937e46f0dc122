//! `camsim run`: simulate a scene (the built-in reference design by default) and
//! print the per-period table of every revolution, the jumps, the solver statistics
//! and the run time ([`RunReport`]); optionally every sample as CSV and the plots. The
//! study is [`crate::study::run`]; this command reads the arguments into its [`Spec`],
//! plans and writes the files, and prints the report.

use std::path::PathBuf;

use anyhow::Result;

use crate::args::ActualArgs;
use crate::args::OutputArgs;
pub use crate::args::{spec_from, CsvArgs, SceneArgs, VerdictArgs};
use crate::csv::CsvRows;
use crate::output::{AtomicDir, AtomicFile, DirTarget, FileTarget, Plan};
use crate::plot;
pub use crate::study::run::*;
use crate::units::Units;

/// Command-line options of `camsim run`.
#[derive(clap::Args, Debug, Clone, Default)]
#[command(mut_arg("plot", |a| a.help("Write PNG plots against cam angle into DIR (created if missing; its parent must exist; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --csv and --plot files")))]
pub struct Args {
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Revolutions to simulate, 1-16 (default 3, or the scene's).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::whole_u32::<1, 16>)]
    pub revolutions: Option<u32>,
    /// The response as CSV (`--csv` and its options).
    #[command(flatten)]
    pub rows: CsvArgs,
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
    Ok(Spec {
        limits: args.verdict.limits(&run.limits, units),
        run,
        cam,
        margin: args.verdict.margin,
        scene_file: args.scene.scene.as_ref().map(|p| p.display().to_string()),
        grid: args.rows.grid()?,
        plot: args.output.plot.is_some(),
    })
}

/// The files `args` asks for, checked before the run (a refusal touches no file) and told
/// which files the run reads (no output overwrites them): `--csv`, refused when its rows
/// would pass `--max-csv-mb`, and `--plot`'s directory (with the profile's figure for an
/// actual or measured cam).
fn targets(args: &Args, spec: &Spec) -> Result<(Option<FileTarget>, Option<DirTarget>)> {
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene.scene {
        plan.input("scene file", p);
    }
    if let Some(p) = &args.measured {
        plan.input("--measured", p);
    }
    let csv = match &args.rows.csv {
        Some(p) => Some(plan.file("--csv", p)?.limit(
            args.rows.expected_bytes(&spec.run, &spec.grid),
            args.rows.max_bytes(),
            "--max-csv-mb N",
        )?),
        None => None,
    };
    let plots = match &args.output.plot {
        Some(dir) if !matches!(spec.cam, Cam::Theoretical) => {
            Some(plan.dir("--plot", dir, &plot::FILES_WITH_PROFILE)?)
        }
        Some(dir) => {
            Some(plan.dir_replacing("--plot", dir, &plot::FILES, &[plot::PROFILE_FILE])?)
        }
        None => None,
    };
    Ok((csv, plots))
}

/// Runs the simulation `args` asks for and writes its outputs: every output is checked
/// before the simulation (a refusal touches no file), written to temporaries during it,
/// and committed only when all succeeded (and the report is finite).
pub fn report(args: &Args, units: Units) -> Result<RunReport> {
    let spec = spec(args, units)?;
    let (csv_target, plot_target) = targets(args, &spec)?;
    let mut rows = CsvRows::open(csv_target, args.rows.csv_every_step, units)?;
    let run = report_observed(&spec, units, &mut rows)?;
    let csv_file = rows.finish()?;
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
    commit(&mut report, csv_file, plots)?;
    Ok(report)
}

/// Commits the files written, the CSV first, and lists them in `report`.
fn commit(report: &mut RunReport, csv: Option<AtomicFile>, plots: Option<AtomicDir>) -> Result<()> {
    if let Some(f) = csv {
        let path = f.target().display().to_string();
        f.commit()?;
        report.files.push(path);
    }
    if let Some(p) = plots {
        let done = p.commit()?;
        (report.files).extend(done.written.iter().map(|f| f.display().to_string()));
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    crate::report::print(&report(&args, units)?, args.output.json, units)
}
