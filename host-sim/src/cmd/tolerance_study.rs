//! `camsim tolerance-study`: the grid of VI.4.1 (Table VI.2 varies both the tolerance
//! and the waviness) on the thesis's more stable program (4-5-6-7 rise, modified
//! trapezoidal return; `scenes/stable-4567-rise.toml`): the cam and roller tolerances at
//! 0.2, 1 and 5 times VI.1's (cam ±0.0001, ±0.0005, ±0.0025 in, the roller's at 1/5 of
//! it; the eccentricity kept at VI.1's ±0.001 in), by the waviness (FPR 17, 39 and 57,
//! the thesis's cams; `--waviness-fpr`), or by given intervals (`--interval-deg`). Each
//! cell is a small Monte Carlo study ([`crate::study::montecarlo`]) whose samples use the
//! same master seed in every cell (common random numbers), reported as the mean of
//! revolution 2's time responses (RMS deviations) and inertial responses per period,
//! with the probability of a jump and its 95 % interval. A theoretical-cam row (no
//! tolerance) comes first; `--plot DIR` draws the grid as heat maps.

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::{MotionLaw, SegmentKind};
use serde::Serialize;

use crate::actual::{ActualArgs, NormalArg};
use crate::args::OutputArgs;
use crate::report::Report;
use crate::sim::RunSpec;
use crate::study::montecarlo::{self, Columns, Moments, Probability, Study, StudyStats, Summary};
use crate::units;
use camsim_scene_file::units::Unit;

/// The factors on VI.1's cam and roller tolerances (±0.0005 and ±0.0001 in) of the
/// grid's rows, largest first: cam ±0.0025, ±0.0005, ±0.0001 in.
pub const TOLERANCE_FACTORS: [f64; 3] = [5.0, 1.0, 0.2];
/// The default waviness axis: the thesis's cams (VI.4.1, Table VI.2): FPR 17 (its
/// study cams), 39 (a rougher one) and 57 (at ±0.0025/±0.0005 in).
pub const WAVINESS_FPR: [u32; 3] = [17, 39, 57];
/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["tolerance_grid.png", "tolerance_response.png"];

/// Command-line options of `camsim tolerance-study`.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("plot", |a| a.help("Write the grid as heat maps (P(jump) with its interval, acceleration RMS) and P(jump), smallest contact force and largest contact stress against the tolerance (p5, p50, p95) into DIR (tolerance_grid.png, tolerance_response.png)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Scene file (default: the thesis's more stable program, the reference design with
    /// a 4-5-6-7 rise and a modified trapezoidal return).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default: the scene's, 800).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Actual cams per cell (default 8; 1 with --quick).
    #[arg(long, value_parser = crate::args::whole_u64::<1, 100_000>)]
    pub samples: Option<u64>,
    /// The waviness axis, FPR (default 17,39,57; FPR 2n is a single harmonic of n
    /// undulations a revolution): each cell's interval is the one whose profile, drawn
    /// from the master seed at the cell's tolerances, has the FPR nearest.
    #[arg(long, value_name = "N", value_delimiter = ',', value_parser = crate::args::whole_u32::<2, 2000>, conflicts_with = "interval_deg")]
    pub waviness_fpr: Vec<u32>,
    /// Profile point intervals, degrees, instead of the waviness axis (each a whole
    /// number of intervals a revolution).
    #[arg(long, value_name = "DEG", value_delimiter = ',', value_parser = crate::actual::interval_deg)]
    pub interval_deg: Vec<f64>,
    /// Camshaft-bearing and eccentricity tolerance, ± in (kept at VI.1's 0.001 in every
    /// cell), or with its unit (mm).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub eccentricity_tolerance: Option<f64>,
    /// Master seed (the same in every cell).
    #[arg(long, value_parser = crate::args::seed)]
    pub seed: Option<u64>,
    /// Normal deviates.
    #[arg(long, value_enum, default_value_t = NormalArg::Sum12)]
    pub normal: NormalArg,
    /// Quick mode: one cam per cell, the vertical scene.
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// One cell of the grid.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    /// Cam profile tolerance, ± in.
    pub cam_tolerance_in: f64,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance_in: f64,
    /// Eccentricity tolerance, ± in.
    pub eccentricity_tolerance_in: f64,
    /// The waviness asked for, FPR (absent for the theoretical cam and given intervals).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_fpr: Option<u32>,
    /// Profile point interval, degrees (absent for the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interval_deg: Option<f64>,
    /// The waviness achieved: mean FPR of the cell's cams (absent for the theoretical
    /// cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fpr: Option<f64>,
    /// Revolution 2's acceleration RMS summed over the periods, mean over the cams,
    /// in/s² (absent when no cam has statistics: each left the model's valid range).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub acc_rms_sum_in_per_s2: Option<f64>,
    /// Why the cell is not workable: every cam left the model's valid range with the
    /// follower on the cam (docs/MODEL.md §3.20; the first cam's reason). A cell whose
    /// cams jumped and then left it is workable: P(jump) = 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_workable: Option<String>,
    /// The cell's Monte Carlo result (revolution 2).
    pub summary: Summary,
}

impl Cell {
    /// The profiles' waviness (FPR).
    pub fn fpr_moments(&self) -> Option<&Moments> {
        self.summary.profile.get("fpr")
    }
}

/// What `camsim tolerance-study` prints.
#[derive(Clone, Debug, Serialize)]
pub struct ToleranceReport {
    /// The program's laws, rise and return.
    pub program: [String; 2],
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Actual cams per cell.
    pub samples_per_cell: u64,
    /// Master seed.
    pub seed: u64,
    /// Whether the vertical scene ran (--quick).
    pub quick: bool,
    /// The theoretical cam (no tolerance).
    pub theoretical: Cell,
    /// The grid, by cam tolerance (largest first), then waviness (the axis's order).
    pub cells: Vec<Cell>,
    /// Cells a row (the waviness axis's length).
    pub columns: usize,
    /// Wall-clock time, s.
    pub wall_s: f64,
}

fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => {
            let mut s = RunSpec::reference();
            s.design.program = camsim_core::CamProgram::with_laws(
                MotionLaw::Poly4567,
                MotionLaw::ModifiedTrapezoidal,
            );
            s
        }
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r)?;
    }
    spec.revolutions = montecarlo::REVOLUTION;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    spec.design.validate()?;
    Ok(spec)
}

fn law_of(spec: &RunSpec, rise: bool) -> String {
    spec.design
        .program
        .segments()
        .iter()
        .find_map(|s| match (s.kind, rise) {
            (SegmentKind::Rise(l), true) | (SegmentKind::Return(l), false) => Some(l.name()),
            _ => None,
        })
        .unwrap_or("none")
        .to_string()
}

/// The waviness axis: (FPR asked, interval given) per column.
fn waviness_axis(args: &Args) -> Vec<(Option<u32>, Option<f64>)> {
    if !args.interval_deg.is_empty() {
        args.interval_deg.iter().map(|&d| (None, Some(d))).collect()
    } else if !args.waviness_fpr.is_empty() {
        args.waviness_fpr.iter().map(|&f| (Some(f), None)).collect()
    } else {
        WAVINESS_FPR.iter().map(|&f| (Some(f), None)).collect()
    }
}

/// Runs the grid.
pub fn report(args: &Args) -> Result<ToleranceReport> {
    let t0 = std::time::Instant::now();
    let spec = base_spec(args)?;
    let samples = args.samples.unwrap_or(if args.quick { 1 } else { 8 });
    let threads = montecarlo::threads(args.threads);
    let mut plan = crate::output::Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let axis = waviness_axis(args);
    let reference = camsim_core::Tolerances::<f64>::reference();
    let ecc = args
        .eccentricity_tolerance
        .unwrap_or(reference.eccentricity);
    let cell = |cam: f64,
                roller: f64,
                ecc: f64,
                fpr: Option<u32>,
                interval: Option<f64>|
     -> Result<Cell> {
        let actual = ActualArgs {
            actual: true,
            cam_tolerance: Some(cam),
            roller_tolerance: Some(roller),
            eccentricity_tolerance: Some(ecc),
            interval_deg: interval,
            waviness_fpr: fpr.into_iter().collect(),
            seed: args.seed,
            normal: args.normal,
            ..ActualArgs::default()
        };
        let theoretical = cam == 0.0 && roller == 0.0 && ecc == 0.0;
        let n = if theoretical { 1 } else { samples };
        let study = Study::from_spec(spec.clone(), &actual, n)?;
        // Samples that leave the model's range are counted (jumps or not workable).
        let stats = study.run_stats(montecarlo::Shard::WHOLE, threads, false)?;
        let (summary, not_workable) = cell_summary(&stats, study.revolution())?;
        let acc = summary.whole_revolution.get("acc_rms_sum").map(|m| m.mean);
        Ok(Cell {
            cam_tolerance_in: cam,
            roller_tolerance_in: roller,
            eccentricity_tolerance_in: ecc,
            target_fpr: if theoretical { None } else { fpr },
            interval_deg: (!theoretical).then(|| 360.0 / study.settings.profile.intervals as f64),
            fpr: if theoretical {
                None
            } else {
                summary.profile.get("fpr").map(|m| m.mean)
            },
            acc_rms_sum_in_per_s2: acc,
            not_workable,
            summary,
        })
    };
    // The theoretical cam, then every cell's actual cams.
    let bar = crate::study_limits::progress_bar(
        1 + (TOLERANCE_FACTORS.len() * axis.len()) as u64 * samples,
        true,
        "{elapsed_precise} [{bar:40}] {pos}/{len} runs, {per_sec}, eta {eta}",
    );
    let theoretical = cell(0.0, 0.0, 0.0, None, Some(10.0))?;
    bar.inc(1);
    let mut cells = Vec::new();
    for k in TOLERANCE_FACTORS {
        for &(fpr, iv) in &axis {
            let (cam, roller) = (k * reference.cam, k * reference.roller);
            cells.push(cell(cam, roller, ecc, fpr, iv)?);
            bar.inc(samples);
        }
    }
    bar.finish_and_clear();
    some_cell_workable(&theoretical, &cells)?;
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        let (cols, units) = (axis.len(), crate::units::current());
        let fig = crate::plot::tolerance::grid(&theoretical, &cells, cols, samples);
        crate::figure::draw(&mut dir, PLOT_FILES[0], &fig, units)?;
        let fig = crate::plot::tolerance::response(&theoretical, &cells, cols, samples);
        crate::figure::draw(&mut dir, PLOT_FILES[1], &fig, units)?;
        dir.commit()?;
    }
    Ok(ToleranceReport {
        program: [law_of(&spec, true), law_of(&spec, false)],
        rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        samples_per_cell: samples,
        seed: args.seed.unwrap_or(crate::actual::DEFAULT_SEED),
        quick: args.quick,
        theoretical,
        columns: cells.len() / TOLERANCE_FACTORS.len(),
        cells,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// Fails when no cell is workable (every cam of every cell left the model's valid range
/// with the follower on the cam), with the theoretical cam's reason.
fn some_cell_workable(theoretical: &Cell, cells: &[Cell]) -> Result<()> {
    let all = std::iter::once(theoretical).chain(cells);
    if let Some(why) = all
        .map(|c| c.not_workable.as_ref())
        .collect::<Option<Vec<_>>>()
    {
        anyhow::bail!(
            "no cell is workable: in every one each cam left the model's valid range with the follower on the cam (theoretical cam: {})",
            why.first().map_or("", |w| w.as_str())
        );
    }
    Ok(())
}

/// A cell's statistics, and why it is not workable when every cam left the model's
/// valid range with the follower on the cam (then an empty summary with the count).
pub fn cell_summary(stats: &StudyStats, revolution: u32) -> Result<(Summary, Option<String>)> {
    if stats.samples + stats.left_range_jumps > 0 {
        return Ok((stats.summary(revolution)?, None));
    }
    let why = stats
        .first_not_workable
        .as_ref()
        .map_or("no cam ran".to_string(), |(i, r)| {
            format!("sample {i}: {r}")
        });
    let summary = Summary {
        samples: 0,
        revolution,
        periods: Vec::new(),
        whole_revolution: Columns(Vec::new()),
        jump: Probability::of(0, 0),
        profile: Columns(Vec::new()),
        steps: None,
        left_range_jumps: 0,
        not_workable: stats.not_workable,
        not_workable_reason: Some(why.clone()),
    };
    Ok((summary, Some(why)))
}

/// A cell's profiles: the waviness achieved and the RMS lift deviation (none when no
/// cam has statistics).
fn profile_text(c: &Cell) -> String {
    let p = &c.summary.profile;
    match (p.get("fpr"), p.get("rms_deviation_in")) {
        (Some(f), Some(d)) => format!(
            ": FPR {:.1} (sd {:.1}), rms lift deviation {:.3e} {}",
            f.mean,
            f.sd,
            units::value(units::LENGTH, d.mean),
            units::symbol(units::LENGTH)
        ),
        _ => String::new(),
    }
}

/// A cell's acceleration RMS sum in the report's unit, or why it has none.
fn acc_text(c: &Cell) -> String {
    match (&c.not_workable, c.acc_rms_sum_in_per_s2) {
        (Some(_), _) => "not workable".into(),
        (None, None) => "no statistics".into(),
        (None, Some(a)) => units::q(units::ACCELERATION, a, 0).to_string(),
    }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args)?, args.output.json, units)
}

/// The columns of the per-cell table: (column, header, unit, decimals in inch; `None`:
/// scientific with three).
const TABLE: [(&str, &str, Unit, Option<usize>); 9] = [
    ("rms_displacement", "rms_y", units::LENGTH, None),
    ("rms_velocity", "rms_v", units::SPEED, None),
    ("rms_acceleration", "rms_a", units::ACCELERATION, None),
    ("torque_avg", "T_avg", units::TORQUE, Some(2)),
    ("torque_max", "T_max", units::TORQUE, Some(2)),
    ("torque_min", "T_min", units::TORQUE, Some(2)),
    ("contact_force_min", "Fc_min", units::FORCE, Some(2)),
    ("contact_force_max", "Fc_max", units::FORCE, Some(2)),
    ("contact_stress_max", "stress", units::STRESS, Some(0)),
];

fn cell_text(out: &mut String, title: &str, c: &Cell) {
    use std::fmt::Write;
    let s = &c.summary;
    let _ = writeln!(out, "{title}");
    if let Some(why) = &c.not_workable {
        let _ = writeln!(
            out,
            "  not workable: each of its {} cams left the model's valid range with the follower on the cam (docs/MODEL.md §3.20; first: {why})",
            s.not_workable
        );
        return;
    }
    if s.samples == 0 {
        let _ = writeln!(
            out,
            "  jump anywhere {} of {}: p = {} (95 % Wilson interval); no statistics: every cam jumped and then left the model's valid range (docs/MODEL.md §3.20)",
            s.jump.count,
            s.left_range_jumps,
            s.jump.text(3)
        );
        return;
    }
    let _ = write!(out, "  {:<11}", "period");
    for (_, h, _, _) in TABLE {
        let _ = write!(out, " {:>10}", h);
    }
    let _ = writeln!(out, " {:>7}", "P(jump)");
    for p in &s.periods {
        let _ = write!(out, "  {:<11}", p.period);
        for (col, _, unit, decimals) in TABLE {
            let m = p.columns.get(col).map_or(f64::NAN, |m| m.mean);
            match decimals {
                None => {
                    let _ = write!(out, " {:>10.3e}", units::value(unit, m));
                }
                Some(d) => {
                    let _ = write!(out, " {:>10}", units::q(unit, m, d));
                }
            }
        }
        let _ = writeln!(out, " {:>7.3}", p.jump.p);
    }
    let acc = s.whole_revolution.get("acc_rms_sum");
    let _ = writeln!(
        out,
        "  sum of rms_a {:.4e} {} (sd {:.2e}), jump anywhere {} of {}: p = {} (95 % Wilson interval)",
        units::value(units::ACCELERATION, acc.map_or(0.0, |m| m.mean)),
        units::label(units::ACCELERATION, "in/s2"),
        units::value(units::ACCELERATION, acc.map_or(0.0, |m| m.sd)),
        s.jump.count,
        s.samples + s.left_range_jumps,
        s.jump.text(3)
    );
    if s.left_range_jumps + s.not_workable > 0 {
        let _ = writeln!(
            out,
            "  left the model's valid range: {} cams after the follower separated (jumps, without statistics), {} with the follower on the cam (not workable, excluded)",
            s.left_range_jumps, s.not_workable
        );
    }
}

impl Report for ToleranceReport {
    fn text(&self, _units: crate::units::Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "camsim tolerance-study (VI.4.1): {} rise, {} return at {:.1} rpm, {} model; revolution 2, mean of {} actual \
             cams per cell (seed {}, the same deviates in every cell)",
            self.program[0],
            self.program[1],
            self.rpm,
            if self.quick { "vertical (--quick)" } else { "full 11-DOF" },
            self.samples_per_cell,
            self.seed
        );
        let _ = writeln!(
            out,
            "units: rms_y {}, rms_v {}, rms_a {}, torque {}, force {}, stress {}\n",
            units::symbol(units::LENGTH),
            units::symbol(units::SPEED),
            units::label(units::ACCELERATION, "in/s2"),
            units::symbol(units::TORQUE),
            units::symbol(units::FORCE),
            units::symbol(units::STRESS)
        );
        cell_text(
            &mut out,
            "theoretical cam (no tolerance)",
            &self.theoretical,
        );
        for c in &self.cells {
            let _ = writeln!(out);
            cell_text(
                &mut out,
                &format!(
                    "cam ±{} {lu}, roller ±{} {lu}, eccentricity ±{} {lu}, {}interval {:.4} deg{}",
                    units::given(units::LENGTH, c.cam_tolerance_in),
                    units::given(units::LENGTH, c.roller_tolerance_in),
                    units::given(units::LENGTH, c.eccentricity_tolerance_in),
                    c.target_fpr
                        .map_or(String::new(), |f| format!("waviness asked FPR {f}, ")),
                    c.interval_deg.unwrap_or(0.0),
                    profile_text(c),
                    lu = units::symbol(units::LENGTH)
                ),
                c,
            );
        }
        grid_text(&mut out, self);
        let _ = writeln!(out, "\nrun time: {:.1} s", self.wall_s);
        out
    }
}

/// The heading of column `j` of the grid (`cols` cells a row): the waviness asked (or
/// the interval) and the range of the FPR achieved (mean of each cell's cams) down it.
pub(crate) fn column_label(cells: &[Cell], cols: usize, j: usize) -> String {
    let (lo, hi) = cells
        .iter()
        .skip(j)
        .step_by(cols.max(1))
        .filter_map(|c| c.fpr)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    let got = if !lo.is_finite() {
        "none with statistics".to_string()
    } else if hi - lo < 0.05 {
        format!("{lo:.1}")
    } else {
        format!("{lo:.1}-{hi:.1}")
    };
    match cells.get(j) {
        Some(Cell {
            target_fpr: Some(f),
            ..
        }) => format!("FPR {f} ({got})"),
        Some(c) => format!("{} deg (FPR {got})", c.interval_deg.unwrap_or(0.0)),
        None => String::new(),
    }
}

/// The summary grid: P(jump) with its interval and the acceleration RMS, a row per
/// tolerance, a column per waviness.
fn grid_text(out: &mut String, r: &ToleranceReport) {
    use std::fmt::Write;
    let cols = r.columns.max(1);
    let _ = writeln!(
        out,
        "\nthe grid (revolution 2, {} cams a cell): P(jump) [95 % Wilson interval]; acceleration RMS summed over the periods, {} \
         (theoretical cam: {}, {}); columns: waviness asked (FPR achieved, mean)",
        r.samples_per_cell,
        units::label(units::ACCELERATION, "in/s2"),
        acc_text(&r.theoretical),
        if r.theoretical.summary.jump.count > 0 { "jumps" } else { "no jump" }
    );
    let _ = write!(out, "{:<28}", "cam / roller tolerance");
    for j in 0..cols.min(r.cells.len()) {
        let _ = write!(out, " {:>32}", column_label(&r.cells, cols, j));
    }
    let _ = writeln!(out);
    for row in r.cells.chunks(cols) {
        let Some(first) = row.first() else { continue };
        let _ = write!(
            out,
            "{:<28}",
            format!(
                "±{} / ±{} {}",
                units::given(units::LENGTH, first.cam_tolerance_in),
                units::given(units::LENGTH, first.roller_tolerance_in),
                units::symbol(units::LENGTH)
            )
        );
        for c in row {
            let _ = write!(
                out,
                " {:>32}",
                match c.not_workable {
                    Some(_) => "not workable".to_string(),
                    None => format!("{}; {}", c.summary.jump.text(2), acc_text(c)),
                }
            );
        }
        let _ = writeln!(out);
    }
}
