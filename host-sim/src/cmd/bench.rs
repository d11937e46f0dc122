//! `camsim bench`: run time against error. Runs the reference design at a ladder of
//! solver tolerances and with the reduced scenes, and reports for each the wall time,
//! the solver's work and the error of the steady-state statistics (revolution 2)
//! against a tight-tolerance run of the full model.

use std::time::Instant;

use anyhow::Result;
use camsim_core::{DriveLaw, Start};
use serde::Serialize;

use crate::report::{sorted_pretty_json, Report};
use crate::sim::{self, Dofs, Nothing, RunSpec};

/// Command-line options of `camsim bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Cam speed, rpm (500: the reference holds contact, so the statistics converge;
    /// at 800 it jumps and the impacts make them chaotic).
    #[arg(long, default_value_t = 500.0, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: f64,
    /// Repetitions of each timing, 1-100 (the fastest is reported).
    #[arg(long, default_value_t = 3, allow_hyphen_values = true, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeat: u32,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

/// Revolutions every bench run simulates.
const REVOLUTIONS: u32 = 2;
/// Tolerances of the reference run, (rtol, atol in).
const REFERENCE_TOL: (f64, f64) = (1e-10, 1e-12);

/// Everything `camsim bench` prints (`--json`: keys sorted, as before the report was a
/// struct; `wall_ms` and `ns_per_rhs` are timings).
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Revolutions of every run.
    pub revolutions: u32,
    /// The tolerances of the reference run.
    pub reference: Tolerances,
    /// One row per scene and tolerance.
    pub rows: Vec<BenchRow>,
    /// Fixed memory of a simulation (no heap in the core).
    pub memory: Memory,
    /// Repetitions of each timing (text only).
    #[serde(skip)]
    pub repeat: u32,
}

/// Solver tolerances.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance of displacements, in.
    pub atol_in: f64,
}

/// One scene at one tolerance against the reference run.
#[derive(Clone, Debug, Serialize)]
pub struct BenchRow {
    /// What ran.
    pub scene: String,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance of displacements, in.
    pub atol_in: f64,
    /// Fastest wall time of the repetitions, ms.
    pub wall_ms: f64,
    /// Accepted steps.
    pub steps: u32,
    /// Rejected steps.
    pub rejected: u32,
    /// Right-hand-side evaluations.
    pub rhs_evals: u32,
    /// Wall time per right-hand-side evaluation, ns.
    pub ns_per_rhs: f64,
    /// Largest relative error of the revolution-2 statistics against the reference.
    pub max_rel_error: f64,
    /// Error of the smallest contact force, lb.
    pub force_min_error_lb: f64,
    /// Error of the RMS acceleration deviation summed over the periods, in/s².
    pub acc_rms_sum_error: f64,
}

/// What each part of a simulation occupies, bytes.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct Memory {
    /// The full model, f64, 22 states.
    pub model_f64_22_bytes: usize,
    /// England's solver, f64, 22 states.
    pub solver_f64_22_bytes: usize,
    /// The chip's model, f32, 16 states.
    pub model_f32_16_bytes: usize,
    /// England's solver, f32, 16 states.
    pub solver_f32_16_bytes: usize,
    /// The host's per-period statistics.
    pub stats_host_bytes: usize,
    /// One sample, f64.
    pub sample_f64_bytes: usize,
}

impl Memory {
    /// The sizes of this build.
    pub fn of_this_build() -> Self {
        use std::mem::size_of;
        Memory {
            model_f64_22_bytes: size_of::<camsim_core::RegulatedFullModel<f64>>(),
            solver_f64_22_bytes: size_of::<
                camsim_core::England<
                    f64,
                    { <camsim_core::RegulatedFull as camsim_core::Scene>::N },
                >,
            >(),
            model_f32_16_bytes: size_of::<camsim_chip::ChipModel<f32>>(),
            solver_f32_16_bytes: size_of::<camsim_core::England<f32, { camsim_chip::CHIP_STATES }>>(
            ),
            stats_host_bytes: size_of::<sim::Stats>(),
            sample_f64_bytes: size_of::<camsim_core::Sample<f64>>(),
        }
    }
}

fn stats_vector(spec: &RunSpec, r: &sim::RunResult) -> Vec<f64> {
    sim::period_rows(&spec.design, &r.stats)
        .iter()
        .filter(|p| p.revolution == 2)
        .flat_map(|p| {
            [
                p.rms_displacement,
                p.rms_velocity,
                p.rms_acceleration,
                p.contact_force_avg,
                p.contact_force_min,
                p.contact_force_max,
            ]
        })
        .collect()
}

fn timed(spec: &RunSpec, repeat: u32) -> Result<(sim::RunResult, f64)> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let t0 = Instant::now();
        let r = sim::run(spec, &mut Nothing)?;
        best = best.min(t0.elapsed().as_secs_f64() * 1e3);
        last = Some(r);
    }
    Ok((last.ok_or_else(|| anyhow::anyhow!("no run"))?, best))
}

/// Runs the bench (`rpm` positive and finite, each timing the best of `repeat`).
pub fn measure(rpm: f64, repeat: u32) -> Result<BenchReport> {
    let mut base = RunSpec::reference();
    base.revolutions = REVOLUTIONS;
    base.solver.start = Start::Static;
    base.design.set_speed_rpm(rpm)?;
    let mut reference = base.clone();
    (reference.solver.rtol, reference.solver.atol) = REFERENCE_TOL;
    let (ref_run, _) = timed(&reference, 1)?;
    let ref_stats = stats_vector(&reference, &ref_run);
    let ref_fmin = ref_stats
        .iter()
        .skip(4)
        .step_by(6)
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let ref_acc: f64 = ref_stats.iter().skip(2).step_by(6).sum();

    let mut cases: Vec<(String, RunSpec)> = Vec::new();
    for (rtol, atol) in [
        (1e-3, 1e-6),
        (1e-4, 1e-7),
        (1e-5, 1e-8),
        (1e-6, 1e-8),
        (1e-7, 1e-9),
        (1e-8, 1e-10),
    ] {
        let mut s = base.clone();
        s.solver.rtol = rtol;
        s.solver.atol = atol;
        cases.push(("full 11-DOF (22 states)".into(), s));
    }
    let mut v = base.clone();
    v.dofs = Dofs { horizontal: false };
    cases.push(("vertical, regulated drive (16 states)".into(), v.clone()));
    let mut m = v.clone();
    m.design.drive = DriveLaw::ConstantMotorSpeed;
    cases.push(("vertical, constant motor speed (15 states)".into(), m));
    let mut c = v.clone();
    c.design.drive = DriveLaw::ConstantCamSpeed;
    cases.push(("vertical, constant cam speed (10 states)".into(), c));

    let mut rows = Vec::new();
    for (name, spec) in &cases {
        let (r, wall_ms) = timed(spec, repeat)?;
        let st = stats_vector(spec, &r);
        let max_rel_error = st
            .iter()
            .zip(&ref_stats)
            .map(|(a, b)| (a - b).abs() / b.abs().max(1e-3))
            .fold(0.0, f64::max);
        let fmin = st
            .iter()
            .skip(4)
            .step_by(6)
            .cloned()
            .fold(f64::INFINITY, f64::min);
        let acc: f64 = st.iter().skip(2).step_by(6).sum();
        rows.push(BenchRow {
            scene: name.clone(),
            rtol: spec.solver.rtol,
            atol_in: spec.solver.atol,
            wall_ms,
            steps: r.solver.accepted,
            rejected: r.solver.rejected,
            rhs_evals: r.solver.rhs_evals,
            ns_per_rhs: wall_ms * 1e6 / f64::from(r.solver.rhs_evals.max(1)),
            max_rel_error,
            force_min_error_lb: (fmin - ref_fmin).abs(),
            acc_rms_sum_error: (acc - ref_acc).abs(),
        });
    }
    Ok(BenchReport {
        rpm,
        revolutions: REVOLUTIONS,
        reference: Tolerances {
            rtol: REFERENCE_TOL.0,
            atol_in: REFERENCE_TOL.1,
        },
        rows,
        memory: Memory::of_this_build(),
        repeat,
    })
}

impl Report for BenchReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "camsim bench: reference design at {} rpm, {} revolutions from static equilibrium; errors of the\n\
             revolution-2 statistics against the full model at rtol {:e}, atol {:e} in (best of {} runs)",
            self.rpm, self.revolutions, self.reference.rtol, self.reference.atol_in, self.repeat
        );
        let _ = writeln!(
            s,
            "{:<42} {:>7} {:>7} {:>9} {:>8} {:>9} {:>8} {:>11} {:>10} {:>10}",
            "scene",
            "rtol",
            "atol",
            "wall ms",
            "steps",
            "rhs",
            "ns/rhs",
            "max rel err",
            "Fmin err",
            "acc err"
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "{:<42} {:>7.0e} {:>7.0e} {:>9.1} {:>8} {:>9} {:>8.0} {:>11.2e} {:>10.2e} {:>10.2e}",
                r.scene,
                r.rtol,
                r.atol_in,
                r.wall_ms,
                r.steps,
                r.rhs_evals,
                r.ns_per_rhs,
                r.max_rel_error,
                r.force_min_error_lb,
                r.acc_rms_sum_error
            );
        }
        let m = &self.memory;
        let _ = writeln!(
            s,
            "memory (fixed, no heap in the core): model {} B and England solver {} B (f64, 22 states); \
             model {} B and solver {} B (f32, 16 states, the chip's); host statistics {} B",
            m.model_f64_22_bytes,
            m.solver_f64_22_bytes,
            m.model_f32_16_bytes,
            m.solver_f32_16_bytes,
            m.stats_host_bytes
        );
        s
    }
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    crate::report::print(&measure(args.rpm, args.repeat)?, args.json)
}
