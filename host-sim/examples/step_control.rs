//! The step controls and methods a run can choose (`[solver] step_control`,
//! `camsim_core::StepRule`; `[solver] method`, `camsim_core::Method`) on the default path, `simulate_on_grid` as `camsim run` calls it: for each control and
//! rtol, the right-hand-side evaluations and the RMS error of the load's acceleration over
//! the last revolution at every 0.5° against a reference run (the thesis's rule at rtol
//! 1e-12, atol 1e-15 in). docs/MODEL.md §3.16 and docs/BENCHMARKS.md quote its output.
//!
//! `cargo run --release -p camsim --example step_control -- RPM REVOLUTIONS START [rtol...]`
//! (START `thesis` or `static`; rtol 1e-4 1e-6 1e-8 by default). The absolute tolerance is
//! the default run's 1e-8 in; `STEP_ATOL_SCALED=1` takes `1e-3 · rtol` instead (the bench's
//! rule, so that rtol alone sets the error).

use std::ops::ControlFlow;

use anyhow::Result;
use camsim_core::{
    simulate_on_grid, AngleGrid, CamModel, Design, GridPointKind, Method, Observer, RegulatedFull,
    Sample, Scene, SolverSettings, Start, StepRule,
};

type Model = CamModel<f64, RegulatedFull, { RegulatedFull::N }>;

/// The load's acceleration at every grid step of revolution `last`.
struct Acc {
    last: u32,
    acc: Vec<f64>,
}

impl Observer<f64> for Acc {
    fn needs_stress(&self) -> bool {
        false
    }
    fn needs_outputs(&self) -> bool {
        false
    }
    fn observe(&mut self, _: &Sample<f64>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
    fn observe_grid(&mut self, s: &Sample<f64>, kind: GridPointKind) -> ControlFlow<()> {
        if s.revolution == self.last && kind != GridPointKind::End {
            self.acc.push(s.point.load_acceleration());
        }
        ControlFlow::Continue(())
    }
}

fn run(model: &Model, s: &SolverSettings<f64>, revs: u32) -> Result<(Vec<f64>, u64)> {
    let mut obs = Acc {
        last: revs,
        acc: Vec::new(),
    };
    let st = simulate_on_grid(model, s, revs, AngleGrid::new(0.5)?, &mut obs)?;
    Ok((obs.acc, u64::from(st.rhs_evals)))
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rpm: f64 = args.first().map_or(Ok(800.0), |a| a.parse())?;
    let revs: u32 = args.get(1).map_or(Ok(3), |a| a.parse())?;
    let start = match args.get(2).map(String::as_str) {
        Some("static") => Start::Static,
        _ => Start::Thesis,
    };
    let rtols: Vec<f64> = if args.len() > 3 {
        args[3..]
            .iter()
            .map(|a| a.parse())
            .collect::<Result<_, _>>()?
    } else {
        vec![1e-4, 1e-6, 1e-8]
    };
    let scaled_atol = std::env::var("STEP_ATOL_SCALED").is_ok();
    let mut design = Design::<f64>::reference();
    design.set_speed_rpm(rpm)?;
    let model = Model::new(design)?;
    let base = SolverSettings {
        start,
        ..SolverSettings::reference()
    };
    let reference = SolverSettings {
        rtol: 1e-12,
        atol: 1e-15,
        step_control: StepRule::Thesis,
        method: Method::England,
        ..base
    };
    let (r, r_evals) = run(&model, &reference, revs)?;
    println!(
        "{rpm} rpm, {revs} revolutions, {start:?} start, atol {}; reference (thesis, rtol 1e-12): {r_evals} evals, {} points, acc RMS {:.4e}",
        if scaled_atol { "1e-3 rtol" } else { "1e-8 in" },
        r.len(),
        (r.iter().map(|a| a * a).sum::<f64>() / r.len() as f64).sqrt()
    );
    // England under each step rule, then the two pairs under the default rule (Merson
    // capped, Dormand-Prince never).
    let runs = StepRule::ALL.iter().map(|r| (Method::England, *r)).chain([
        (Method::Merson, StepRule::ScaledCap),
        (Method::DormandPrince, StepRule::ScaledCap),
    ]);
    for (method, rule) in runs {
        let name = match method {
            Method::England => rule.name(),
            other => other.name(),
        };
        for &rtol in &rtols {
            let s = SolverSettings {
                rtol,
                atol: if scaled_atol { 1e-3 * rtol } else { base.atol },
                step_control: rule,
                method,
                ..base
            };
            let (a, evals) = run(&model, &s, revs)?;
            anyhow::ensure!(a.len() == r.len(), "{} points, want {}", a.len(), r.len());
            let err = (a.iter().zip(&r).map(|(x, y)| (x - y).powi(2)).sum::<f64>()
                / r.len() as f64)
                .sqrt();
            println!("{name:>14} rtol {rtol:e}: evals {evals:>8} acc err {err:.3e} in/s^2");
        }
    }
    Ok(())
}
