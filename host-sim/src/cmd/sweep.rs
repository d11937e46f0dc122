//! `camsim sweep --rpm FROM:TO:N`: the operating map (the study is
//! [`crate::study::sweep`]; this parses, prints and writes the files).

use std::io::Write;
use std::path::PathBuf;

use anyhow::Result;

use crate::args::ActualArgs;
use crate::args::SceneArgs;
use crate::args::{self, Law};
use crate::output::Plan;
use crate::study::sweep::{self, RpmGrid, Sweep};

/// Command-line options of `camsim sweep`.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("json", |a| a.help("Print JSON")))]
#[command(mut_arg("plot", |a| a.help("Write the plot (sweep.png) into DIR (created if missing; its parent must exist)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --csv and --plot files")))]
pub struct Args {
    /// The speeds: N equally spaced cam speeds from FROM to TO, rpm (e.g. 300:1200:19).
    #[arg(long, value_name = "FROM:TO:N", allow_hyphen_values = true, value_parser = sweep::parse_rpm_grid)]
    pub rpm: RpmGrid,
    /// Scene file (TOML, see `camsim scene --default`); the reference design if omitted.
    /// Its speed is the operating speed marked on the plot.
    pub scene: Option<PathBuf>,
    /// Motion law of the rise(s) (names as in `camsim laws`).
    #[arg(long = "rise", value_name = "LAW", ignore_case = true)]
    pub rise: Option<Law>,
    /// Motion law of the return(s).
    #[arg(long = "return", value_name = "LAW", ignore_case = true)]
    pub ret: Option<Law>,
    /// Return spring rate K_rs, lb/in (0.01-1e6), or with its unit (17.5N/mm).
    #[arg(long, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = args::spring_rate)]
    pub spring_rate: Option<f64>,
    /// Spring length compressed at assembly δ_rs, in (0-100), or with its unit (12.7mm).
    #[arg(long, value_name = "IN", allow_hyphen_values = true, value_parser = args::preload_length)]
    pub preload_length: Option<f64>,
    /// Solver relative tolerance of the theoretical cam's runs (1e-13 to 0.1).
    #[arg(long, allow_hyphen_values = true, value_parser = args::rtol)]
    pub rtol: Option<f64>,
    /// Step control of the theoretical cam's runs (default "scaled-cap"; "thesis": the
    /// thesis's rule, uncapped).
    #[arg(long, value_enum, value_name = "CONTROL")]
    pub step_control: Option<args::StepControlArg>,
    /// The theoretical cam's follower model (default: the scene's, the full chain).
    #[arg(long, value_enum, value_name = "MODEL")]
    pub follower: Option<args::FollowerArg>,
    /// Machined cams too (`--actual` and its options): P(jump) and the band of every
    /// quantity over --samples cams a speed, on the quasi-static-cantilever follower.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// With --actual: actual cams a speed, the same at every speed (default 100).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 100_000>)]
    pub samples: Option<u64>,
    /// Worker threads (default: every core); the result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// Write one row per speed to FILE.csv (units in the header's names).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: crate::args::OutputArgs,
}

/// The plot `--plot DIR` writes.
pub const PLOT_FILES: [&str; 1] = ["sweep.png"];

/// The sweep `args` describe.
pub fn sweep_of(args: &Args) -> Result<Sweep> {
    let scene = SceneArgs {
        scene: args.scene.clone(),
        rise: args.rise,
        ret: args.ret,
        spring_rate: args.spring_rate,
        preload_length: args.preload_length,
        // The steady state `camsim jump-speed` judges.
        start: Some(args::StartArg::Static),
        rtol: args.rtol,
        step_control: args.step_control,
        follower: args.follower,
        ..SceneArgs::default()
    };
    let spec = crate::args::spec_from(&scene)?;
    anyhow::ensure!(
        args.actual.actual || (!args.actual.any_profile_option() && args.samples.is_none()),
        "the profile options (--cam-tolerance, --seed, --samples, ...) need --actual"
    );
    Ok(Sweep {
        spec,
        grid: args.rpm,
        actual: args.actual.actual.then(|| {
            (
                args.actual.cams(),
                args.samples.unwrap_or(sweep::DEFAULT_SAMPLES),
            )
        }),
        threads: crate::study::montecarlo::threads(args.threads),
        progress: true,
    })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let sw = sweep_of(&args)?;
    // Every output checked before any run.
    let mut plan = Plan::new(args.output.force);
    let csv_target = match &args.csv {
        Some(p) => Some(plan.file("--csv", p)?),
        None => None,
    };
    let plot_target = match &args.output.plot {
        Some(d) => Some(plan.dir("--plot", d, &PLOT_FILES)?),
        None => None,
    };
    let report = sweep::run(&sw, units)?;
    let mut plot = match plot_target {
        Some(t) => {
            let mut dir = t.open()?;
            let fig = crate::plot::sweep::figure(&report);
            crate::figure::draw(&mut dir, PLOT_FILES[0], &fig, units)?;
            Some(dir)
        }
        None => None,
    };
    if let Some(t) = csv_target {
        let mut f = t.open()?;
        {
            let mut w = csv::Writer::from_writer(&mut f);
            w.write_record(sweep::csv_header(report.actual.is_some(), units))?;
            for row in sweep::csv_rows(&report, units) {
                w.write_record(row)?;
            }
            w.flush()?;
        }
        f.flush()?;
        f.commit()?;
    }
    if let Some(p) = plot.take() {
        p.commit()?;
    }
    crate::report::print(&report, args.output.json, units)
}
