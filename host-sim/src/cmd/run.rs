//! `camsim run`: simulate a scene (the built-in reference design by default) and
//! print the per-period table of every revolution, the jumps, the solver statistics
//! and the run time ([`RunReport`]); optionally every sample as CSV and the plots.

use std::path::PathBuf;

use anyhow::Result;
use serde::Serialize;

use crate::actual::{ActualArgs, ProfileStats};
use crate::args::{self, megabytes, OutputArgs};
pub use crate::args::{spec_from, SceneArgs};
use crate::csv::{self, CsvOut};
use crate::measured::{MeasuredProfile, MeasuredStats};
use crate::output::{FileTarget, Plan};
use crate::plot;
use crate::report::{sorted_pretty_json, Report};
use crate::sim::{self, PeriodRow, RunSpec, SteadyCheck};
pub use crate::verdict::JumpRow;

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

/// What the verdict that opens `camsim run` judges against.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct VerdictArgs {
    /// Allowable Hertz contact stress, psi, or with its unit (1034MPa), 1 000 to
    /// 1 000 000 psi (default: the scene's limits.allowable_contact_stress_psi or _mpa,
    /// else 150 000 psi = 1034 MPa: through-hardened steel at 400 HB, 1e8 cycles,
    /// Buckingham's S_C = 0.4 H_B - 10 kpsi = 2.76 H_B - 70 MPa as Shigley gives it).
    #[arg(long, value_name = "PSI", allow_hyphen_values = true, value_parser = args::allowable_stress)]
    pub allowable_stress: Option<f64>,
    /// Largest pressure angle without a warning, degrees (default: the scene's
    /// limits.pressure_angle_limit_deg, else 30, the usual limit for a translating
    /// follower; 0-90).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = args::pressure_angle_limit)]
    pub pressure_angle_limit: Option<f64>,
    /// Also find the jump onset and the margin to it (a bisection of about 15
    /// two-revolution runs from the static start, as `camsim jump-speed`).
    #[arg(long)]
    pub margin: bool,
}

impl VerdictArgs {
    /// The limits asked for, the scene's (`[limits]`, or the defaults) otherwise.
    pub fn limits(&self, scene: &camsim_scene_file::Limits) -> crate::verdict::Limits {
        crate::verdict::Limits {
            // The option is read in psi (its parser converts a value given in MPa).
            allowable_contact_stress_psi: self
                .allowable_stress
                .unwrap_or(scene.allowable_contact_stress_psi),
            pressure_angle_limit_deg: self
                .pressure_angle_limit
                .unwrap_or(scene.pressure_angle_limit_deg),
            allowable_source: if self.allowable_stress.is_some() {
                "--allowable-stress"
            } else if scene.allowable_contact_stress_psi
                != camsim_core::ALLOWABLE_CONTACT_STRESS_PSI
            {
                "the scene's [limits]"
            } else {
                crate::verdict::allowable_source()
            },
        }
    }
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

/// What an actual or measured cam's profile is (the JSON `profile`).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ProfileReport {
    /// `--actual`: drawn from tolerances.
    Actual(ProfileStats),
    /// `--measured FILE`.
    Measured(MeasuredStats),
}

impl ProfileReport {
    /// The waviness frequency per revolution.
    pub fn fpr(&self) -> usize {
        match self {
            ProfileReport::Actual(s) => s.fpr,
            ProfileReport::Measured(s) => s.fpr,
        }
    }
}

/// Everything `camsim run` prints (`--json`: keys sorted, as before the report was a
/// struct; `wall_ms` is a timing; `fpr` and `profile` only for an actual or measured cam).
#[derive(Clone, Debug, Serialize)]
pub struct RunReport {
    /// The camsim that ran it (its version).
    pub camsim_version: &'static str,
    /// The scene file given (absent: the built-in reference design).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene_file: Option<String>,
    /// The scene that ran, as a scene file (TOML; the options that override it applied):
    /// `camsim run` on this text reproduces the run (set by [`report`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// The verdict: contact, geometry, loads, spring, margin, steady state, warnings
    /// (set by [`report`]; absent from a bare [`RunReport::new`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub verdict: Option<crate::verdict::Verdict>,
    /// Waviness frequency per revolution of the profile (VI.4.1; actual and measured
    /// cams only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fpr: Option<usize>,
    /// The actual or measured profile (None: the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileReport>,
    /// Per-period statistics of every revolution.
    pub per_period: Vec<PeriodRow>,
    /// Every recorded separation interval.
    pub jumps: Vec<JumpRow>,
    /// Accepted (double) steps.
    pub steps: u32,
    /// Rejected (double) steps.
    pub rejected_steps: u32,
    /// Right-hand-side evaluations.
    pub rhs_evals: u32,
    /// Separation intervals not recorded (past the statistics' capacity).
    pub jumps_dropped: u32,
    /// The last two revolutions compared (absent with one revolution).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady_state: Option<SteadyCheck>,
    /// Wall-clock time of the simulation, ms.
    pub wall_ms: f64,
    /// The preload F_p, lb.
    pub preload_lb: f64,
    /// Cam speed ω0, rpm.
    pub rpm: f64,
    /// Revolutions simulated.
    pub revolutions: u32,
    /// Degrees of freedom of the scene (text only).
    #[serde(skip)]
    pub dofs: usize,
    /// Solver relative tolerance (text only).
    #[serde(skip)]
    pub rtol: f64,
    /// The integration method (`solver.method`; text only, the JSON's scene has it).
    #[serde(skip)]
    pub method: &'static str,
    /// Solver absolute tolerance, in (text only).
    #[serde(skip)]
    pub atol_in: f64,
    /// The name of each period of the program (text only).
    #[serde(skip)]
    pub periods: Vec<&'static str>,
    /// The files the run wrote (--csv, the plots of --plot; absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub files: Vec<String>,
}

impl RunReport {
    /// The report of a finished run of `spec`.
    pub fn new(spec: &RunSpec, result: &sim::RunResult) -> Self {
        let per_period = sim::period_rows(&spec.design, &result.stats);
        let steady_state = sim::steady_check(&per_period);
        let jumps = result
            .stats
            .jumps()
            .iter()
            .map(|j| JumpRow {
                revolution: j.revolution,
                start_deg: j.start_deg,
                end_deg: j.end_deg,
                period: spec.design.program.segment_at(j.start_deg.to_radians()),
            })
            .collect();
        RunReport {
            camsim_version: env!("CARGO_PKG_VERSION"),
            scene_file: None,
            scene: None,
            verdict: None,
            fpr: None,
            profile: None,
            per_period,
            jumps,
            steps: result.solver.accepted,
            rejected_steps: result.solver.rejected,
            rhs_evals: result.solver.rhs_evals,
            jumps_dropped: result.stats.jumps_dropped,
            steady_state,
            wall_ms: result.wall_ms,
            preload_lb: result.preload,
            rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
            revolutions: spec.revolutions,
            dofs: result.scene.dofs,
            rtol: spec.solver.rtol,
            method: spec.solver.method.resolve(spec.solver.rtol).name(),
            atol_in: spec.solver.atol,
            periods: sim::period_names(&spec.design),
            files: Vec::new(),
        }
    }
}

/// Runs the simulation `args` asks for and writes its outputs: every output is checked
/// before the simulation (a refusal touches no file), written to temporaries during it,
/// and committed only when all succeeded.
/// Attaches the cam's measured (`--measured`) or as-cut (`--actual`) profile to
/// `spec`, if one was asked for, and returns its report.
fn attach_profile(spec: &mut RunSpec, args: &Args) -> Result<Option<ProfileReport>> {
    args.actual.ensure_actual_if_options()?;
    let profile = if let Some(path) = &args.measured {
        let (dev, stats) = crate::measured::load(path)?
            .profile(&spec.design)
            .map_err(|e| anyhow::anyhow!("--measured {}: {e:#}", path.display()))?;
        Some((dev, ProfileReport::Measured(stats)))
    } else if args.actual.actual {
        let (dev, stats) = crate::actual::build_profile(&spec.design, &args.actual, 0)?;
        Some((dev, ProfileReport::Actual(stats)))
    } else {
        None
    };
    let profile_report = profile.as_ref().map(|p| p.1.clone());
    spec.profile = profile.map(|p| std::sync::Arc::new(p.0));
    Ok(profile_report)
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

/// `--csv`'s target, refused before the run when its rows (on the cam-angle `grid`, else
/// estimated from the solver's steps) would pass `--max-csv-mb`.
fn csv_target(
    plan: &mut Plan,
    args: &Args,
    spec: &RunSpec,
    grid: Option<&camsim_core::AngleGrid<f64>>,
) -> Result<Option<FileTarget>> {
    let Some(p) = &args.csv else {
        return Ok(None);
    };
    let bytes = match grid {
        Some(g) => csv::rows_bytes(csv::grid_rows(spec, g)),
        None => csv::estimated_bytes(spec),
    };
    let limit = args.max_csv_mb.saturating_mul(1_000_000);
    Ok(Some(plan.file("--csv", p)?.limit(
        bytes,
        limit,
        "--max-csv-mb N",
    )?))
}

pub fn report(args: &Args) -> Result<RunReport> {
    let mut spec = spec_from(&args.scene)?;
    if let Some(n) = args.revolutions {
        spec.revolutions = n;
    }
    let profile_report = attach_profile(&mut spec, args)?;
    let mut plan = input_plan(args);
    // The grid's step was checked by the option's parser.
    let grid = match args.csv_every_step {
        false => Some(camsim_core::AngleGrid::new(args.csv_every_deg)?),
        true => None,
    };
    let csv_target = csv_target(&mut plan, args, &spec, grid.as_ref())?;
    let plot_target = match &args.output.plot {
        Some(dir) if spec.profile.is_some() => {
            Some(plan.dir("--plot", dir, &plot::FILES_WITH_PROFILE)?)
        }
        Some(dir) => {
            Some(plan.dir_replacing("--plot", dir, &plot::FILES, &[plot::PROFILE_FILE])?)
        }
        None => None,
    };
    let mut csv_out = match csv_target {
        Some(t) => Some(CsvOut::new(t.open()?)),
        None => None,
    };
    let mut plot_data = plot_target.as_ref().map(|_| plot::PlotData::default());
    let mut watch =
        crate::verdict::Watch::new(crate::verdict::Watch::steady_from(spec.revolutions));
    let result = {
        let every_step = args.csv_every_step;
        let mut obs = RunObserver {
            watch: &mut watch,
            plot: plot_data.as_mut(),
            csv: csv_out.as_mut(),
            every_step,
        };
        let grid = grid.unwrap_or_else(camsim_core::AngleGrid::segment_starts);
        sim::run_on_grid(&spec, &mut obs, grid)?
    };
    let csv_file = csv_out.map(CsvOut::into_file).transpose()?;
    let plots = match (plot_target, plot_data) {
        (Some(t), Some(data)) => {
            let mut out = t.open()?;
            plot::draw_all(&mut out, &data, &result.stats.jumps())?;
            if let Some(dev) = &spec.profile {
                plot::draw_profile(&mut out, &data, dev)?;
            }
            Some(out)
        }
        _ => None,
    };
    // A result with a number that is not finite is no success: refused before any
    // output is committed (the temporaries go with it).
    let mut report = RunReport::new(&spec, &result);
    report.fpr = profile_report.as_ref().map(ProfileReport::fpr);
    report.profile = profile_report;
    report.verdict = Some(verdict(&spec, &report, &watch, &args.verdict)?);
    report.scene_file = args.scene.scene.as_ref().map(|p| p.display().to_string());
    report.scene = Some(crate::scene::spec_text(&spec)?);
    crate::report::ensure_finite(&report)?;
    crate::report::ensure_physical(&report)?;
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

/// What `camsim run` watches during the simulation: the verdict's watch and the plots on
/// the solver's samples, the CSV on the solver's samples (--csv-every-step) or on the
/// cam-angle grid.
struct RunObserver<'a> {
    watch: &'a mut crate::verdict::Watch,
    plot: Option<&'a mut plot::PlotData>,
    csv: Option<&'a mut CsvOut>,
    every_step: bool,
}

impl camsim_core::Observer<f64> for RunObserver<'_> {
    fn observe(&mut self, s: &camsim_core::Sample<f64>) -> std::ops::ControlFlow<()> {
        let _ = self.watch.observe(s);
        if let Some(p) = self.plot.as_mut() {
            p.push(s);
        }
        match self.csv.as_mut().filter(|_| self.every_step) {
            Some(c) => c.row(s),
            None => std::ops::ControlFlow::Continue(()),
        }
    }
    fn observe_grid(
        &mut self,
        s: &camsim_core::Sample<f64>,
        _: camsim_core::GridPointKind,
    ) -> std::ops::ControlFlow<()> {
        match self.csv.as_mut().filter(|_| !self.every_step) {
            Some(c) => c.row(s),
            None => std::ops::ControlFlow::Continue(()),
        }
    }
}

/// The verdict of a finished run (`--margin`: the jump-onset search on the scene as it
/// is, theoretical cam, static start).
fn verdict(
    spec: &RunSpec,
    report: &RunReport,
    watch: &crate::verdict::Watch,
    args: &VerdictArgs,
) -> Result<crate::verdict::Verdict> {
    use crate::verdict as v;
    let limits = args.limits(&spec.limits);
    let contact = v::contact(
        &spec.design,
        &report.jumps,
        &report.periods,
        watch,
        spec.revolutions,
    )?;
    let geometry = v::geometry(&spec.design, &limits)?;
    let loads = v::loads(watch, &limits)?;
    let spring = v::spring(&spec.design, spec.spring.as_ref())?;
    let jump_margin = if args.margin {
        let mut s = spec.clone();
        s.solver.start = camsim_core::Start::Static;
        let rpm = report.rpm;
        let r = crate::study::jump_speed::find(&s, 1.0, crate::study::jump_speed::MAX_RPM)?;
        Some(v::MarginVerdict {
            jump_onset_rpm: r.jump_rpm,
            holds_at_rpm: r.no_jump_rpm,
            margin_percent: r.jump_rpm.map(|j| 100.0 * (j / rpm - 1.0)),
            bracket_rpm: r.jump_rpm.map_or(0.0, |j| j - r.no_jump_rpm),
            simulations: r.simulations,
        })
    } else {
        None
    };
    let steady = v::steady(&report.per_period, &sim::steady_checks(&report.per_period));
    let mut warnings = v::warnings(&contact, &geometry, &loads, &spring, jump_margin.as_ref());
    let mass = v::mass(&spec.design);
    let drive = v::drive(spec, watch);
    warnings.extend(v::swing_warning(&drive));
    Ok(v::Verdict {
        contact,
        geometry,
        loads,
        spring,
        mass,
        drive,
        jump_margin,
        steady,
        warnings,
    })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args)?, args.output.json, units)
}

/// The separations of one period of one revolution, as the text report sums them up.
struct JumpBurst {
    /// Revolution, from 1.
    revolution: u32,
    /// Index of the period in the program.
    period: usize,
    /// Separation intervals.
    intervals: usize,
    /// Cam angle of the first separation, degrees.
    first_onset_deg: f64,
    /// Cam angle of the last landing, degrees.
    last_landing_deg: f64,
    /// Degrees of cam angle off the cam, summed over the intervals.
    off_cam_deg: f64,
}

impl Report for RunReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self, _units: crate::units::Units) -> String {
        let mut out = String::new();
        self.write_heading(&mut out);
        if let Some(p) = &self.profile {
            p.write_lines(&mut out);
        }
        self.write_periods(&mut out);
        self.write_jumps(&mut out);
        self.write_steady_state(&mut out);
        self.write_solver(&mut out);
        out
    }
}

impl ProfileReport {
    /// The actual or measured cam's lines: what it is, its lift deviation and (measured)
    /// its waviness.
    fn write_lines(&self, out: &mut String) {
        use std::fmt::Write;
        match self {
            ProfileReport::Actual(p) => write_actual_cam(p, out),
            ProfileReport::Measured(p) => {
                let _ = writeln!(
                    out,
                    "measured cam: column {}, {} points, {} deviation knots",
                    p.column.name(),
                    p.points,
                    p.deviation_knots
                );
            }
        }
        let _ = writeln!(out, "{}", self.deviation_line());
        if let ProfileReport::Measured(p) = self {
            let w = crate::measured::MeasuredWaviness::of(p);
            let _ = writeln!(out, "{}", w.line(crate::units::current()));
        }
    }

    /// The lift deviation's line: RMS, mean and largest |e|, RMS of d²e/dθ², and the FPR.
    fn deviation_line(&self) -> String {
        use crate::units::{symbol, value, LENGTH, LENGTH_PER_RAD2};
        let (rms, mean, max, curv, fpr) = match self {
            ProfileReport::Actual(p) => (
                p.rms_deviation_in,
                p.mean_deviation_in,
                p.max_abs_deviation_in,
                p.rms_curvature_in_per_rad2,
                p.fpr,
            ),
            ProfileReport::Measured(p) => (
                p.rms_deviation_in,
                p.mean_deviation_in,
                p.max_abs_deviation_in,
                p.rms_curvature_in_per_rad2,
                p.fpr,
            ),
        };
        let (l, lu) = (|x| value(LENGTH, x), symbol(LENGTH));
        format!(
            "  lift deviation: rms {:.3e} {lu}, mean {:.3e} {lu}, max |e| {:.3e} {lu}, rms d2e/dtheta2 {:.3e} {}; FPR {fpr}",
            l(rms), l(mean), l(max), value(LENGTH_PER_RAD2, curv), symbol(LENGTH_PER_RAD2)
        )
    }
}

/// An actual cam's lines: how it was drawn (method, seed, tolerances, intervals) and,
/// for the envelope method, the roller and the rotation centre it was cut with.
fn write_actual_cam(p: &ProfileStats, out: &mut String) {
    use crate::units::{given, symbol, value, LENGTH};
    use std::fmt::Write;
    let lu = symbol(LENGTH);
    let _ = writeln!(
        out,
        "actual cam: {} method, seed {}, sample {}, {} normals; tolerances cam {} {lu}, roller {} {lu}, eccentricity {} {lu}; {} points every {:.4} deg ({})",
        p.method.name(), p.seed, p.sample, p.normal.name(), given(LENGTH, p.cam_tolerance_in),
        given(LENGTH, p.roller_tolerance_in), given(LENGTH, p.eccentricity_tolerance_in),
        p.intervals, p.interval_deg, p.interval_source.label(),
    );
    if let (Some(r), Some(c)) = (p.roller_radius_in, p.centre_offset_in) {
        let _ = writeln!(
            out,
            "  envelope: roller radius {} {lu}, rotation centre offset ({:.2e}, {:.2e}) {lu}, {} deviation knots",
            crate::units::q(LENGTH, r, 6), value(LENGTH, c[0]), value(LENGTH, c[1]), p.deviation_knots
        );
    }
}

impl RunReport {
    /// The first line (revolutions, speed, model, preload) and the verdict.
    fn write_heading(&self, out: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "camsim run: {} revolutions at {:.1} rpm, {} DOF model, preload F_p = {} {}",
            self.revolutions,
            self.rpm,
            self.dofs,
            crate::units::q(crate::units::FORCE, self.preload_lb, 3),
            crate::units::symbol(crate::units::FORCE)
        );
        if let Some(v) = &self.verdict {
            let _ = writeln!(out, "{}", crate::verdict::text(v));
        }
    }

    /// The units line, then each revolution's per-period table, then a blank line.
    fn write_periods(&self, out: &mut String) {
        use crate::units::{self as u, q};
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "units: {}, {}, s; torque {}; stress {}; AORD = mean (omega - omega0)/omega0",
            u::symbol(u::LENGTH),
            u::symbol(u::FORCE),
            u::symbol(u::TORQUE),
            u::symbol(u::STRESS)
        );
        let mut last_rev = 0;
        for r in &self.per_period {
            if r.revolution != last_rev {
                last_rev = r.revolution;
                let transient = if r.revolution == 1 {
                    " (transient)"
                } else {
                    ""
                };
                let _ = writeln!(out, "\nrevolution {}{transient}", r.revolution);
                let _ = writeln!(
                    out,
                    "{:<11} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>10} {:>10} {:>10} {:>5}",
                    "period", "rms_y", "rms_v", "rms_a", "T_avg", "T_max", "T_min", "Fc_min", "Fc_max", "Fc_avg",
                    "stress", "aord_m", "aord_cp", "aord_c", "jump"
                );
            }
            // Torques and forces print as 0.00, not -0.00, where they round to zero.
            let (t, f) = (|x| q(u::TORQUE, x, 2), |x| q(u::FORCE, x, 2));
            let _ = writeln!(
                out,
                "{:<11} {:>10.3e} {:>10.3e} {:>10.3e} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>10.3e} {:>10.3e} {:>10.3e} {:>5}",
                r.period, u::value(u::LENGTH, r.rms_displacement), u::value(u::SPEED, r.rms_velocity),
                u::value(u::ACCELERATION, r.rms_acceleration), t(r.torque_avg), t(r.torque_max),
                t(r.torque_min), f(r.contact_force_min), f(r.contact_force_max), f(r.contact_force_avg),
                q(u::STRESS, r.contact_stress_max, 0),
                r.aord_motor, r.aord_coupling, r.aord_cam, if r.jump { "yes" } else { "no" }
            );
        }
        let _ = writeln!(out);
    }

    /// The steady-state line: the verdict's when it judged one, else the comparison of
    /// the last two revolutions (none with one revolution).
    fn write_steady_state(&self, out: &mut String) {
        use std::fmt::Write;
        match (&self.verdict, &self.steady_state) {
            (
                Some(crate::verdict::Verdict {
                    steady: Some(st), ..
                }),
                _,
            ) => {
                let _ = writeln!(out, "steady state: {}", st.summary);
            }
            (_, Some(c)) => {
                let _ = writeln!(
                    out,
                    "steady state: revolution {} vs {}: largest relative change of the per-period statistics {:.2e} ({})",
                    c.compared[1], c.compared[0], c.max_rel_change, c.statistic
                );
            }
            _ => {}
        }
    }

    /// The solver's line (method, tolerances, work), the run time and the files written.
    fn write_solver(&self, out: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "solver: {} adaptive RK, rtol {:e}, atol {:e} {}: {} steps, {} rejected, {} rhs evaluations",
            method_title(self.method), self.rtol, crate::units::given(crate::units::LENGTH, self.atol_in), crate::units::symbol(crate::units::LENGTH), self.steps, self.rejected_steps, self.rhs_evals
        );
        let _ = writeln!(out, "run time: {:.1} ms", self.wall_ms);
        for f in &self.files {
            let _ = writeln!(out, "wrote {f}");
        }
    }
}

impl RunReport {
    /// The jumps' lines: none, or one summary line per burst of separations.
    fn write_jumps(&self, out: &mut String) {
        use std::fmt::Write;
        if self.jumps.is_empty() {
            let _ = writeln!(out, "jumps: none (the follower stays on the cam)");
        } else {
            // Separations come in bursts (the roller bounces after landing): summarise each
            // revolution and period; --json and --csv keep every interval.
            let _ = writeln!(
                out,
                "jumps: {} separation intervals (every one in --json)",
                self.jumps.len()
            );
            let mut groups: Vec<JumpBurst> = Vec::new();
            for j in &self.jumps {
                match groups.last_mut() {
                    Some(g) if g.revolution == j.revolution && g.period == j.period => {
                        g.intervals += 1;
                        g.last_landing_deg = j.end_deg;
                        g.off_cam_deg += j.end_deg - j.start_deg;
                    }
                    _ => groups.push(JumpBurst {
                        revolution: j.revolution,
                        period: j.period,
                        intervals: 1,
                        first_onset_deg: j.start_deg,
                        last_landing_deg: j.end_deg,
                        off_cam_deg: j.end_deg - j.start_deg,
                    }),
                }
            }
            for g in groups {
                let _ = writeln!(
                out,
                "  revolution {}, {:<10}: {:>4} intervals from {:7.2} to {:7.2} deg, {:6.2} deg off the cam",
                g.revolution,
                self.periods.get(g.period).copied().unwrap_or("?"),
                g.intervals,
                g.first_onset_deg,
                g.last_landing_deg,
                g.off_cam_deg
            );
            }
            if self.jumps_dropped > 0 {
                let _ = writeln!(
                    out,
                    "  ({} more intervals not recorded)",
                    self.jumps_dropped
                );
            }
        }
    }
}

/// The solver line's name of a method (`solver.method`): "England" as before.
fn method_title(name: &str) -> &str {
    match name {
        "england" => "England",
        "merson" => "Merson 4(3)",
        "dormand-prince" => "Dormand-Prince 5(4)",
        other => other,
    }
}
