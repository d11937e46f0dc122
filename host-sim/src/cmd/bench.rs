//! `camsim bench`: run time against error. Runs the reference design at a ladder of
//! solver tolerances and with the reduced scenes, and reports for each the wall time,
//! the solver's work and the error of the steady-state statistics (revolution 2)
//! against a tight-tolerance run of the full model.

use std::time::Instant;

use anyhow::Result;
use camsim_core::{DriveLaw, Start};
use serde::Serialize;
use serde_json::json;

use crate::sim::{self, Dofs, Nothing, RunSpec};

/// Command-line options of `camsim bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Cam speed, rpm (500: the reference holds contact, so the statistics converge;
    /// at 800 it jumps and the impacts make them chaotic).
    #[arg(long, default_value_t = 500.0)]
    pub rpm: f64,
    /// Repetitions of each timing (the fastest is reported).
    #[arg(long, default_value_t = 3)]
    pub repeat: u32,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

#[derive(Serialize)]
struct Row {
    scene: String,
    rtol: f64,
    atol_in: f64,
    wall_ms: f64,
    steps: u32,
    rejected: u32,
    rhs_evals: u32,
    ns_per_rhs: f64,
    /// Largest relative error of the revolution-2 statistics against the reference.
    max_rel_error: f64,
    /// Error of the smallest contact force, lb.
    force_min_error_lb: f64,
    /// Error of the RMS acceleration deviation summed over the periods, in/s².
    acc_rms_sum_error: f64,
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

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    anyhow::ensure!(
        args.rpm.is_finite() && args.rpm > 0.0,
        "--rpm {}: must be positive and finite",
        args.rpm
    );
    let mut base = RunSpec::reference();
    base.revolutions = 2;
    base.solver.start = Start::Static;
    base.design.set_speed_rpm(args.rpm)?;
    let mut reference = base.clone();
    reference.solver.rtol = 1e-10;
    reference.solver.atol = 1e-12;
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
        let (r, wall_ms) = timed(spec, args.repeat)?;
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
        rows.push(Row {
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
    // Fixed memory of a simulation (no heap in the core): what each part occupies.
    let memory = json!({
        "model_f64_22_bytes": std::mem::size_of::<camsim_core::RegulatedFullModel<f64>>(),
        "solver_f64_22_bytes": std::mem::size_of::<camsim_core::England<f64, { <camsim_core::RegulatedFull as camsim_core::Scene>::N }>>(),
        "model_f32_16_bytes": std::mem::size_of::<camsim_chip::ChipModel<f32>>(),
        "solver_f32_16_bytes": std::mem::size_of::<camsim_core::England<f32, { camsim_chip::CHIP_STATES }>>(),
        "stats_host_bytes": std::mem::size_of::<sim::Stats>(),
        "sample_f64_bytes": std::mem::size_of::<camsim_core::Sample<f64>>(),
    });
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(
                &json!({"rpm": args.rpm, "revolutions": 2, "reference": {"rtol": 1e-10, "atol_in": 1e-12}, "rows": rows, "memory": memory})
            )?
        );
        return Ok(());
    }
    println!(
        "camsim bench: reference design at {} rpm, 2 revolutions from static equilibrium; errors of the\n\
         revolution-2 statistics against the full model at rtol 1e-10, atol 1e-12 in (best of {} runs)",
        args.rpm, args.repeat
    );
    println!(
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
    for r in &rows {
        println!(
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
    println!(
        "memory (fixed, no heap in the core): model {} B and England solver {} B (f64, 22 states); \
         model {} B and solver {} B (f32, 16 states, the chip's); host statistics {} B",
        memory["model_f64_22_bytes"], memory["solver_f64_22_bytes"], memory["model_f32_16_bytes"],
        memory["solver_f32_16_bytes"], memory["stats_host_bytes"]
    );
    Ok(())
}
