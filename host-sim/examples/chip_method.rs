//! The chip's integration method at equal error: for England's method and the two pairs
//! (`camsim_core::Method`) at a ladder of rtol, the chip's f32 model (its scene, its lift
//! table, the chip's other settings) against a reference (England in f64 at rtol 1e-10 on
//! the closed-form lift): the error
//! of the smallest contact force at 800 and 900 rpm and of the largest timing error, the
//! prediction table's jump onset, and the right-hand-side evaluations of one revolution
//! at 800 and 950 rpm from static equilibrium (what `budget`'s `model chip` lines count
//! on the chip). docs/FIRMWARE.md quotes its output.
//!
//! `cargo run --release -p camsim --example chip_method [-- rtol...]` (default 1e-2 3e-3
//! 1e-3 3e-4 1e-4).

use std::ops::ControlFlow;

use anyhow::Result;
use camsim_chip::{chip_design, chip_solver_settings, ChipConfig, ChipModel, ChipTable};
use camsim_core::{simulate, Method, Observer, Sample, SolverSettings, StepRule};

struct Nothing;

impl Observer<f32> for Nothing {
    fn needs_stress(&self) -> bool {
        false
    }
    fn needs_outputs(&self) -> bool {
        false
    }
    fn observe(&mut self, _: &Sample<f32>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// Evaluations of one revolution at `rpm` from static equilibrium.
fn revolution_evals(settings: &SolverSettings<f32>, rpm: f32) -> Result<u32> {
    let mut d = chip_design::<f32>();
    d.set_speed_rpm(rpm)?;
    let model = ChipModel::<f32>::new(d)?;
    Ok(simulate(&model, settings, 1, &mut Nothing)?.rhs_evals)
}

fn main() -> Result<()> {
    let rtols: Vec<f64> = {
        let a: Vec<String> = std::env::args().skip(1).collect();
        if a.is_empty() {
            vec![1e-2, 3e-3, 1e-3, 3e-4, 1e-4]
        } else {
            a.iter().map(|x| x.parse()).collect::<Result<_, _>>()?
        }
    };
    let rpms = [800.0, 900.0];
    let d64 = chip_design::<f64>();
    let reference = SolverSettings {
        rtol: 1e-10,
        atol: 1e-13,
        method: Method::England,
        step_control: StepRule::Thesis,
        ..chip_solver_settings::<f64>()
    };
    let rc = ChipConfig::new(&d64).with_settings(reference);
    let ref_ss = rpms.map(|r| rc.steady_state(r));
    let ref_onset = rc.prediction_table()?.jump_rpm;
    println!("reference: England f64 rtol 1e-10; onset {ref_onset:?} rpm");
    for (r, s) in rpms.iter().zip(&ref_ss) {
        let s = s.as_ref().map_err(|e| anyhow::anyhow!("{e}"))?;
        println!(
            "  {r} rpm: smallest contact force {:.4} lb",
            s.min_contact_force
        );
    }
    println!(
        "{:>15} {:>7} {:>11} {:>11} {:>11} {:>11} {:>9} {:>9}",
        "method",
        "rtol",
        "dFc800 lb",
        "dFc900 lb",
        "dtiming deg",
        "donset rpm",
        "evals800",
        "evals950"
    );
    let d32 = chip_design::<f32>();
    for method in [Method::England, Method::Merson, Method::DormandPrince] {
        for &rtol in &rtols {
            let s = SolverSettings {
                rtol: rtol as f32,
                method,
                ..chip_solver_settings::<f32>()
            };
            // On the chip's lift table, as the firmware and `predict --f32` (set
            // CHIP_METHOD_THEORETICAL=1 for the closed-form lift).
            let mut table = Box::new(ChipTable::<f32>::EMPTY);
            let theoretical = ChipConfig::new(&d32).with_settings(s);
            let tabled = theoretical.tabulate(&mut table)?;
            let closed_form = std::env::var("CHIP_METHOD_THEORETICAL").is_ok();
            let steady = |r: f32| {
                if closed_form {
                    theoretical.steady_state(r)
                } else {
                    tabled.steady_state(r)
                }
            };
            let mut dfc = [0.0f64; 2];
            let mut dt = 0.0f64;
            for ((slot, r), rs) in dfc.iter_mut().zip(rpms).zip(&ref_ss) {
                let (Ok(a), Ok(b)) = (steady(r as f32), rs) else {
                    continue;
                };
                *slot = (f64::from(a.min_contact_force) - b.min_contact_force).abs();
                for (x, y) in a.timing_deg.iter().zip(b.timing_deg.iter()) {
                    if x.is_finite() && y.is_finite() {
                        dt = dt.max((f64::from(*x) - y).abs());
                    }
                }
            }
            let onset = if closed_form {
                theoretical.prediction_table()?.jump_rpm
            } else {
                tabled.prediction_table()?.jump_rpm
            };
            let don = match (onset, ref_onset) {
                (Some(a), Some(b)) => format!("{:+.2}", f64::from(a) - b),
                _ => "-".into(),
            };
            println!(
                "{:>15} {:>7.0e} {:>11.4} {:>11.4} {:>11.5} {:>11} {:>9} {:>9}",
                method.name(),
                rtol,
                dfc[0],
                dfc[1],
                dt,
                don,
                revolution_evals(&s, 800.0)?,
                revolution_evals(&s, 950.0)?,
            );
        }
    }
    Ok(())
}
