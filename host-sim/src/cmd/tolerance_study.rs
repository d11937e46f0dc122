//! `camsim tolerance-study`: the grid of VI.4.1 on the thesis's more stable program
//! (4-5-6-7 rise, modified trapezoidal return; `scenes/stable-4567-rise.toml`): the cam
//! profile tolerance at 0.0025, 0.0005 and 0.0001 in with the roller's at 1/5 of it,
//! and the waviness (FPR) set through the profile point interval. Each cell is a small
//! Monte Carlo study ([`crate::cmd::montecarlo`]) whose samples use the same master
//! seed in every cell (common random numbers: two cells with the same interval draw
//! the same normal deviates, scaled by their tolerance band), reported as the mean of
//! revolution 2's time responses (RMS deviations) and inertial responses per period,
//! with the probability of a jump. A theoretical-cam row (no tolerance) comes first.

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::{MotionLaw, SegmentKind};
use serde::Serialize;

use crate::actual::{ActualArgs, NormalArg};
use crate::cmd::montecarlo::{self, Moments, Study, Summary};
use crate::report::Report;
use crate::sim::RunSpec;

/// The cam profile tolerances of the grid (± in); the roller's is 1/5 of each.
pub const CAM_TOLERANCES: [f64; 3] = [0.0025, 0.0005, 0.0001];
/// The default profile point intervals (degrees): about 10, 28 and 57 waves a
/// revolution (FPR ≈ 0.8 per interval, camsim-core's profile tests).
pub const INTERVALS_DEG: [f64; 3] = [30.0, 10.0, 5.0];

/// Command-line options of `camsim tolerance-study`.
#[derive(clap::Args, Debug, Clone)]
pub struct Args {
    /// Scene file (default: the thesis's more stable program, the reference design with
    /// a 4-5-6-7 rise and a modified trapezoidal return).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default: the scene's, 800).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Actual cams per cell (default 8; 1 with --quick).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub samples: Option<u64>,
    /// Profile point intervals, degrees (each a whole number of intervals a
    /// revolution; default 30,10,5).
    #[arg(long, value_name = "DEG", value_delimiter = ',', value_parser = crate::actual::interval_deg)]
    pub interval_deg: Vec<f64>,
    /// Camshaft-bearing and eccentricity tolerance, ± in (kept at VI.1's 0.001 in every
    /// cell).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub eccentricity_tolerance: Option<f64>,
    /// Master seed (the same in every cell).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Normal deviates.
    #[arg(long, value_enum, default_value_t = NormalArg::Sum12)]
    pub normal: NormalArg,
    /// Quick mode: one cam per cell, the vertical scene.
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
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
    /// Profile point interval, degrees (none for the theoretical cam).
    pub interval_deg: Option<f64>,
    /// The cell's Monte Carlo result (revolution 2).
    pub summary: Summary,
}

impl Cell {
    /// The profiles' waviness (FPR).
    pub fn fpr(&self) -> Option<&Moments> {
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
    /// The grid, by cam tolerance (largest first), then interval.
    pub cells: Vec<Cell>,
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

/// Runs the grid.
pub fn report(args: &Args) -> Result<ToleranceReport> {
    let t0 = std::time::Instant::now();
    let spec = base_spec(args)?;
    let samples = args.samples.unwrap_or(if args.quick { 1 } else { 8 });
    let threads = montecarlo::threads(args.threads);
    let intervals: Vec<f64> = if args.interval_deg.is_empty() {
        INTERVALS_DEG.to_vec()
    } else {
        args.interval_deg.clone()
    };
    let ecc = args.eccentricity_tolerance.unwrap_or(0.001);
    let cell = |cam: f64, roller: f64, ecc: f64, interval: f64| -> Result<Summary> {
        let actual = ActualArgs {
            actual: true,
            cam_tolerance: Some(cam),
            roller_tolerance: Some(roller),
            eccentricity_tolerance: Some(ecc),
            interval_deg: Some(interval),
            seed: args.seed,
            normal: args.normal,
            ..ActualArgs::default()
        };
        let n = if cam == 0.0 && roller == 0.0 && ecc == 0.0 {
            1
        } else {
            samples
        };
        let study = Study::from_spec(spec.clone(), &actual, n)?;
        let indices: Vec<u64> = (0..n).collect();
        montecarlo::summarize(&study.run(&indices, threads, false)?, study.revolution())
    };
    let theoretical = Cell {
        cam_tolerance_in: 0.0,
        roller_tolerance_in: 0.0,
        eccentricity_tolerance_in: 0.0,
        interval_deg: None,
        summary: cell(0.0, 0.0, 0.0, 10.0)?,
    };
    let mut cells = Vec::new();
    for cam in CAM_TOLERANCES {
        for &iv in &intervals {
            let roller = cam / 5.0;
            cells.push(Cell {
                cam_tolerance_in: cam,
                roller_tolerance_in: roller,
                eccentricity_tolerance_in: ecc,
                interval_deg: Some(iv),
                summary: cell(cam, roller, ecc, iv)?,
            });
        }
    }
    Ok(ToleranceReport {
        program: [law_of(&spec, true), law_of(&spec, false)],
        rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        samples_per_cell: samples,
        seed: args.seed.unwrap_or(crate::actual::DEFAULT_SEED),
        quick: args.quick,
        theoretical,
        cells,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    crate::report::print(&report(&args)?, args.json)
}

/// The columns of the per-cell table: (column, header).
const TABLE: [(&str, &str); 9] = [
    ("rms_displacement", "rms_y"),
    ("rms_velocity", "rms_v"),
    ("rms_acceleration", "rms_a"),
    ("torque_avg", "T_avg"),
    ("torque_max", "T_max"),
    ("torque_min", "T_min"),
    ("contact_force_min", "Fc_min"),
    ("contact_force_max", "Fc_max"),
    ("contact_stress_max", "stress"),
];

fn cell_text(out: &mut String, title: &str, c: &Cell) {
    use std::fmt::Write;
    let s = &c.summary;
    let _ = writeln!(out, "{title}");
    let _ = write!(out, "  {:<11}", "period");
    for (_, h) in TABLE {
        let _ = write!(out, " {:>10}", h);
    }
    let _ = writeln!(out, " {:>7}", "P(jump)");
    for p in &s.periods {
        let _ = write!(out, "  {:<11}", p.period);
        for (col, _) in TABLE {
            let m = p.columns.get(col).map_or(f64::NAN, |m| m.mean);
            if col.starts_with("rms") {
                let _ = write!(out, " {:>10.3e}", m);
            } else if col == "contact_stress_max" {
                let _ = write!(out, " {:>10.0}", m);
            } else {
                let _ = write!(out, " {:>10.2}", m);
            }
        }
        let _ = writeln!(out, " {:>7.3}", p.jump.p);
    }
    let acc = s.whole_revolution.get("acc_rms_sum");
    let _ = writeln!(
        out,
        "  sum of rms_a {:.4e} in/s2 (sd {:.2e}), jump anywhere p = {:.3} ± {:.3}",
        acc.map_or(f64::NAN, |m| m.mean),
        acc.map_or(f64::NAN, |m| m.sd),
        s.jump.p,
        s.jump.se
    );
}

impl Report for ToleranceReport {
    fn text(&self) -> String {
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
            "units: rms_y in, rms_v in/s, rms_a in/s2, torque lb in, force lb, stress psi\n"
        );
        cell_text(
            &mut out,
            "theoretical cam (no tolerance)",
            &self.theoretical,
        );
        for c in &self.cells {
            let fpr = c.fpr();
            let _ = writeln!(out);
            cell_text(
                &mut out,
                &format!(
                    "cam ±{} in, roller ±{} in, eccentricity ±{} in, interval {} deg: FPR {:.1} (sd {:.1}), rms lift deviation {:.3e} in",
                    c.cam_tolerance_in,
                    c.roller_tolerance_in,
                    c.eccentricity_tolerance_in,
                    c.interval_deg.unwrap_or(0.0),
                    fpr.map_or(f64::NAN, |m| m.mean),
                    fpr.map_or(f64::NAN, |m| m.sd),
                    c.summary
                        .profile
                        .get("rms_deviation_in")
                        .map_or(f64::NAN, |m| m.mean)
                ),
                c,
            );
        }
        let _ = writeln!(out, "\nrun time: {:.1} s", self.wall_s);
        out
    }
}
