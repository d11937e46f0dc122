//! Issue 22: every method's error must follow its tolerance (or its step) down to the
//! reference's floor, on the reference design as `camsim bench` measures it (full 22-state
//! scene, 500 rpm, static start, 2 revolutions; RMS error of the load's acceleration over
//! revolution 2 at 720 cam angles, each method through its own continuous extension).
//!
//! The rule, derived from the methods' orders rather than from measured figures: over a
//! tolerance ladder one decade apart, an error-controlled method's error must fall by at
//! least [`PER_DECADE`] per decade (a method whose local error is controlled to `rtol`
//! has a global error proportional to `rtol`, or to `rtol^(4/5)` with England's
//! error-per-step control: 6.3x a decade; 3x leaves room for the step-size rule) until it
//! is below [`FLOOR`]; RK4 at a fixed step must fall by at least [`PER_HALVING`] per halving
//! of the step (fourth order: 16x).
//!
//! The reference is England at rtol 1e-12 (the bench's is 1e-13); at 1e-12 England and
//! Dormand-Prince agree to 2.8e-7 in/s² (docs/BENCHMARKS.md), so [`FLOOR`] is ten times that:
//! an error below it would measure the reference.
//!
//! England with error per step (classic and PI-capped, uncapped or with the full cap at
//! every rtol), Merson's pair with the full cap, and the thesis's rule on the default path
//! do not follow the rule: their steps in the dwells are held by stability and do not
//! shrink with rtol (issue 22: classic 2.56x, 1.70x, 1.25x a decade from rtol 1e-5 to
//! 1e-8). That is asserted as what it is, a plateau ([`assert_plateaus`]: the error falls,
//! but by less than [`PER_DECADE`] in some decade above the floor), so a change that
//! cures one of them fails its test and moves it to the converging cases. With error per
//! unit step over one revolution ([`per_revolution`]) both England controls converge.
//!
//! With the stiffness cap shrinking as `(rtol/1e-5)^(1/5)` below rtol 1e-5
//! ([`StiffnessCap::tolerance_scaled`]) England classic (capped) and PI-capped converge:
//! the steps held by stability then shrink with the tolerance too. The same controls with
//! the full cap at every rtol plateau ([`england_capped_full_cap_error_plateaus`]).
//!
//! The ladder stops at the first error below [`FLOOR`]: past it the error measures the
//! reference, and the tightest tolerances cost the most.

use anyhow::Result;
use camsim::bench::methods::{per_revolution, run, run_england, run_merson, Method};
use camsim::bench::sample::{Sampler, Samples};
use camsim::bench::{design_at, settings, MEASURED, REVOLUTIONS};
use camsim_core::Method as RunMethod;
use camsim_core::{
    CamModel, RegulatedFull, Scene, SolverSettings, Start, StepControl, StepRule, StiffnessCap,
    SCALED_CAP_FULL_RTOL,
};

type Model = CamModel<f64, RegulatedFull, { RegulatedFull::N }>;

/// Smallest fall of an adaptive method's error per decade of rtol.
const PER_DECADE: f64 = 3.0;
/// Smallest fall of RK4's error per halving of its fixed step.
const PER_HALVING: f64 = 8.0;
/// Errors below this (in/s²) are at the reference's floor.
const FLOOR: f64 = 3e-6;
/// The reference's rtol.
const REFERENCE_RTOL: f64 = 1e-12;
/// The tolerance ladder.
const RTOLS: [f64; 5] = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9];

fn acc(model: &Model, method: Method, rtol: f64) -> Result<Vec<f64>> {
    let mut s = Sampler::new(model, REVOLUTIONS, Some(MEASURED));
    run(method, model, &settings::<f64>(rtol), REVOLUTIONS, &mut s)?;
    anyhow::ensure!(
        s.complete(),
        "{} at {rtol:e}: samples missing",
        method.name()
    );
    Ok(s.samples.acc)
}

fn setup() -> Result<(Model, Vec<f64>)> {
    let model = Model::new(design_at(500.0)?)?;
    let reference = acc(&model, Method::England, REFERENCE_RTOL)?;
    Ok((model, reference))
}

/// Checks that each error falls by `factor` from the one before, until one is below
/// `FLOOR` (then every later one must stay below `FLOOR · factor`: at the floor the
/// error is the reference's).
fn assert_converges(what: &str, errs: &[(String, f64)], factor: f64) {
    let report: Vec<String> = errs.iter().map(|(k, e)| format!("{k}: {e:.3e}")).collect();
    for pair in errs.windows(2) {
        let [(k0, e0), (k1, e1)] = pair else { continue };
        assert!(
            e1.is_finite(),
            "{what}: error not finite at {k1} ({report:?})"
        );
        if *e0 < FLOOR {
            assert!(
                *e1 < FLOOR * factor,
                "{what}: error rose off the floor from {k0} to {k1} ({report:?})"
            );
        } else {
            assert!(
                *e1 <= *e0 / factor,
                "{what}: error fell only {:.2}x from {k0} to {k1}, less than {factor}x ({report:?})",
                e0 / e1
            );
        }
    }
}

/// Checks the plateau of issue 22: every error finite, none rising from one rtol to the
/// next (the error still falls, or stays), and at least one decade above `FLOOR` in which
/// it falls by less than `factor`.
fn assert_plateaus(what: &str, errs: &[(String, f64)], factor: f64) {
    let report: Vec<String> = errs.iter().map(|(k, e)| format!("{k}: {e:.3e}")).collect();
    let mut slow = 0;
    for pair in errs.windows(2) {
        let [(k0, e0), (k1, e1)] = pair else { continue };
        assert!(
            e1.is_finite(),
            "{what}: error not finite at {k1} ({report:?})"
        );
        assert!(
            e1 <= e0,
            "{what}: error rose from {k0} to {k1} ({report:?})"
        );
        if *e0 >= FLOOR && *e1 > *e0 / factor {
            slow += 1;
        }
    }
    assert!(
        slow > 0,
        "{what}: no plateau, the error fell at least {factor}x every decade ({report:?}): \
         it now converges; assert that instead"
    );
}

/// The errors over [`RTOLS`] of one way to run, up to the first below [`FLOOR`].
fn ladder(
    reference: &[f64],
    mut acc_at: impl FnMut(f64) -> Result<Vec<f64>>,
) -> Result<Vec<(String, f64)>> {
    let mut errs = Vec::new();
    for rtol in RTOLS {
        let e = Samples::rms_diff(&acc_at(rtol)?, reference);
        errs.push((format!("rtol {rtol:e}"), e));
        if e < FLOOR {
            break;
        }
    }
    Ok(errs)
}

/// The ladder of `method` against the reference.
fn adaptive_ladder(method: Method) -> Result<Vec<(String, f64)>> {
    let (model, reference) = setup()?;
    ladder(&reference, |rtol| acc(&model, method, rtol))
}

fn adaptive(method: Method) -> Result<()> {
    assert_converges(method.name(), &adaptive_ladder(method)?, PER_DECADE);
    Ok(())
}

/// `method`'s error plateaus ([`assert_plateaus`]).
fn adaptive_plateaus(method: Method) -> Result<()> {
    assert_plateaus(method.name(), &adaptive_ladder(method)?, PER_DECADE);
    Ok(())
}

/// England with `control` plus error per unit step over one revolution.
fn per_unit_step(name: &str, control: StepControl<f64>) -> Result<()> {
    let (model, reference) = setup()?;
    let control = StepControl {
        per_unit_step: Some(per_revolution(&model)),
        ..control
    };
    controlled(name, &model, &reference, control)
}

/// England with `control`'s stiffness cap shrinking as `(rtol/1e-5)^(1/5)` below 1e-5
/// ([`StiffnessCap::tolerance_scaled`], [`SCALED_CAP_FULL_RTOL`]).
fn scaled_cap(name: &str, control: StepControl<f64>) -> Result<()> {
    let (model, reference) = setup()?;
    let control = StepControl {
        stiffness_cap: Some(StiffnessCap::tolerance_scaled(SCALED_CAP_FULL_RTOL)),
        ..control
    };
    controlled(name, &model, &reference, control)
}

/// The ladder of England with `control` converges.
fn controlled(
    name: &str,
    model: &Model,
    reference: &[f64],
    control: StepControl<f64>,
) -> Result<()> {
    let errs = controlled_ladder(name, model, reference, control)?;
    assert_converges(name, &errs, PER_DECADE);
    Ok(())
}

/// The ladder of England with `control`.
fn controlled_ladder(
    name: &str,
    model: &Model,
    reference: &[f64],
    control: StepControl<f64>,
) -> Result<Vec<(String, f64)>> {
    ladder(reference, |rtol| {
        let mut s = Sampler::new(model, REVOLUTIONS, Some(MEASURED));
        run_england(model, &settings::<f64>(rtol), control, REVOLUTIONS, &mut s)?;
        anyhow::ensure!(s.complete(), "{name} at {rtol:e}: samples missing");
        Ok(s.samples.acc)
    })
}

/// Issue 22: England's error per step plateaus (1.7x and 1.25x a decade from rtol 1e-6
/// to 1e-8 when measured): its steps in the dwells are held by stability.
#[test]
fn england_error_plateaus() -> Result<()> {
    adaptive_plateaus(Method::England)
}

/// Issue 22: so does PI-capped England's (1.4x and 1.5x a decade from 1e-6 to 1e-8).
#[test]
fn england_pi_capped_error_plateaus() -> Result<()> {
    adaptive_plateaus(Method::EnglandPiCapped)
}

#[test]
fn england_per_unit_step_error_follows_rtol() -> Result<()> {
    per_unit_step("england_per_unit_step", StepControl::classic())
}

#[test]
fn england_pi_capped_per_unit_step_error_follows_rtol() -> Result<()> {
    per_unit_step("england_pi_capped_per_unit_step", StepControl::pi_capped())
}

#[test]
fn england_capped_tolerance_scaled_error_follows_rtol() -> Result<()> {
    scaled_cap("england_capped_scaled", StepControl::classic_capped())
}

#[test]
fn england_pi_capped_tolerance_scaled_error_follows_rtol() -> Result<()> {
    scaled_cap("england_pi_capped_scaled", StepControl::pi_capped())
}

/// The same controls with the cap at its full fraction at every rtol (`rtol_full`
/// `None`): the plateau of issue 22 (classic capped 2.31x, 1.92x, 1.27x a decade from
/// 1e-5 to 1e-8 when measured), which the scaled cap cures.
#[test]
fn england_capped_full_cap_error_plateaus() -> Result<()> {
    let (model, reference) = setup()?;
    let name = "england_capped_full_cap";
    let errs = controlled_ladder(name, &model, &reference, StepControl::classic_capped())?;
    assert_plateaus(name, &errs, PER_DECADE);
    Ok(())
}

/// The imaginary-axis method (Merson's 4(3) pair with its stiffness cap at its full
/// fraction) plateaus like England (5.18e-4, 2.58e-4, 8.43e-5, 6.56e-5, 3.60e-5 at rtol
/// 1e-5 to 1e-9 when measured).
#[test]
fn merson_capped_error_plateaus() -> Result<()> {
    adaptive_plateaus(Method::Merson { capped: true })
}

/// The same with the tolerance-scaled cap.
#[test]
fn merson_tolerance_scaled_error_follows_rtol() -> Result<()> {
    let (model, reference) = setup()?;
    let cap = StiffnessCap::tolerance_scaled(SCALED_CAP_FULL_RTOL);
    let errs = ladder(&reference, |rtol| {
        let mut s = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
        run_merson(
            &model,
            &settings::<f64>(rtol),
            Some(cap),
            REVOLUTIONS,
            &mut s,
        )?;
        anyhow::ensure!(s.complete(), "merson scaled at {rtol:e}: samples missing");
        Ok(s.samples.acc)
    })?;
    assert_converges("merson_4_3_scaled", &errs, PER_DECADE);
    Ok(())
}

#[test]
fn dormand_prince_error_follows_rtol() -> Result<()> {
    adaptive(Method::Dopri5)
}

#[test]
fn rk4_error_falls_at_fourth_order_with_its_step() -> Result<()> {
    let (model, reference) = setup()?;
    let mut errs = Vec::new();
    // From just above the fixed-step stability limit (15 177 steps a revolution).
    for steps_per_rev in [16_000, 32_000, 64_000] {
        let mut s = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
        run(
            Method::Rk4 { steps_per_rev },
            &model,
            &settings::<f64>(1e-6),
            REVOLUTIONS,
            &mut s,
        )?;
        errs.push((
            format!("T/{steps_per_rev}"),
            Samples::rms_diff(&s.samples.acc, &reference),
        ));
    }
    assert_converges("rk4_fixed", &errs, PER_HALVING);
    Ok(())
}

/// The rule itself: it passes a fourth-order fall, refuses a plateau, and accepts
/// anything once at the floor.
#[test]
fn the_rule_refuses_a_plateau_and_accepts_the_floor() {
    let e = |v: &[f64]| -> Vec<(String, f64)> {
        v.iter()
            .enumerate()
            .map(|(i, x)| (i.to_string(), *x))
            .collect()
    };
    assert_converges("falls", &e(&[1e-2, 1e-3, 1e-4]), PER_DECADE);
    assert_converges("to the floor", &e(&[1e-5, 1e-6, 2e-6, 1e-6]), PER_DECADE);
    let plateau = std::panic::catch_unwind(|| {
        assert_converges("plateau", &e(&[4.9e-4, 2.9e-4, 2.3e-4]), PER_DECADE)
    });
    assert!(plateau.is_err());
    // And its complement, the plateau check: it passes the plateau, refuses a fall.
    assert_plateaus("plateau", &e(&[4.9e-4, 2.9e-4, 2.3e-4]), PER_DECADE);
    let falls =
        std::panic::catch_unwind(|| assert_plateaus("falls", &e(&[1e-2, 1e-3, 1e-4]), PER_DECADE));
    assert!(falls.is_err());
    let rises = std::panic::catch_unwind(|| {
        assert_plateaus("rises", &e(&[1e-3, 2e-3, 1.9e-3]), PER_DECADE)
    });
    assert!(rises.is_err());
}

// ---------------------------------------------------------------------------------------
// The default path: `simulate_on_grid` (what `camsim run` calls) with
// `SolverSettings::reference()`'s step control, the tolerance-scaled stiffness cap
// (`StepRule::ScaledCap`, docs/MODEL.md §3.16). Same setup as above (500 rpm, static
// start, 2 revolutions, atol 1e-3 rtol, the load's acceleration every 0.5° of revolution
// 2), the reference the thesis's rule at rtol 1e-12 (atol 1e-15 in) on the same path.

/// The load's acceleration at every 0.5° grid step of revolution 2.
struct GridAcc(Vec<f64>);

impl camsim_core::Observer<f64> for GridAcc {
    fn needs_stress(&self) -> bool {
        false
    }
    fn needs_outputs(&self) -> bool {
        false
    }
    fn observe(&mut self, _: &camsim_core::Sample<f64>) -> std::ops::ControlFlow<()> {
        std::ops::ControlFlow::Continue(())
    }
    fn observe_grid(
        &mut self,
        s: &camsim_core::Sample<f64>,
        kind: camsim_core::GridPointKind,
    ) -> std::ops::ControlFlow<()> {
        if s.revolution == REVOLUTIONS && kind != camsim_core::GridPointKind::End {
            self.0.push(s.point.load_acceleration());
        }
        std::ops::ControlFlow::Continue(())
    }
}

/// The default path's acceleration samples at `rtol` (atol `1e-3 rtol`) with `method`
/// under `rule`.
fn default_path(
    model: &Model,
    rtol: f64,
    atol: f64,
    method: RunMethod,
    rule: StepRule,
) -> Result<Vec<f64>> {
    let settings = SolverSettings {
        rtol,
        atol,
        start: Start::Static,
        step_control: rule,
        method,
        ..SolverSettings::reference()
    };
    let mut obs = GridAcc(Vec::new());
    camsim_core::simulate_on_grid(
        model,
        &settings,
        REVOLUTIONS,
        camsim_core::AngleGrid::new(0.5)?,
        &mut obs,
    )?;
    anyhow::ensure!(obs.0.len() == 720, "{} samples at {rtol:e}", obs.0.len());
    Ok(obs.0)
}

/// The ladder `rtols` of the default path with `method` under `rule` against its
/// reference (England's method under the thesis's rule at [`REFERENCE_RTOL`]).
fn default_ladder(method: RunMethod, rule: StepRule, rtols: &[f64]) -> Result<Vec<(String, f64)>> {
    let model = Model::new(design_at(500.0)?)?;
    let thesis = (RunMethod::England, StepRule::Thesis);
    let reference = default_path(&model, REFERENCE_RTOL, 1e-15, thesis.0, thesis.1)?;
    let mut errs = Vec::new();
    for &rtol in rtols {
        let run = default_path(&model, rtol, 1e-3 * rtol, method, rule)?;
        let e = Samples::rms_diff(&run, &reference);
        errs.push((format!("rtol {rtol:e}"), e));
        if e < FLOOR {
            break;
        }
    }
    Ok(errs)
}

/// The default's method and rule (what `camsim run` uses unless the scene says
/// otherwise), and the chip's.
#[test]
fn the_default_is_merson_with_the_tolerance_scaled_cap() {
    let host = SolverSettings::<f64>::reference();
    assert_eq!(
        (host.method.resolve(host.rtol), host.step_control),
        (RunMethod::Merson, StepRule::ScaledCap)
    );
    // Merson where it wins by more than 15 % at equal error (rtol >= 1e-6), England
    // below.
    assert_eq!(host.method, RunMethod::Auto);
    assert_eq!(RunMethod::Auto.resolve(1e-6), RunMethod::Merson);
    assert_eq!(RunMethod::Auto.resolve(9.99e-7), RunMethod::England);
    let chip = camsim_chip::chip_solver_settings::<f32>();
    assert_eq!(
        (chip.method, chip.step_control),
        (RunMethod::England, StepRule::Thesis)
    );
}

/// Issue 22's "done when" on the default path: from rtol 1e-5 to 1e-8 the error falls at
/// least [`PER_DECADE`] a decade (or reaches [`FLOOR`]), for the default (Merson's pair)
/// and for England's method under the same rule. The longer ladder is
/// [`default_path_error_follows_rtol_to_1e_9`].
#[test]
fn default_path_error_follows_rtol() -> Result<()> {
    let rtols = [1e-5, 1e-6, 1e-7, 1e-8];
    let errs = default_ladder(RunMethod::Merson, StepRule::ScaledCap, &rtols)?;
    assert_converges("default (merson, scaled-cap)", &errs, PER_DECADE);
    let errs = default_ladder(RunMethod::England, StepRule::ScaledCap, &rtols)?;
    assert_converges("england, scaled-cap", &errs, PER_DECADE);
    Ok(())
}

/// [`default_path_error_follows_rtol`] on issue 22's whole ladder, and the PI variant.
#[test]
#[ignore = "long (rtol 1e-9 on the full model): run with --include-ignored"]
fn default_path_error_follows_rtol_to_1e_9() -> Result<()> {
    for rule in [StepRule::ScaledCap, StepRule::PiScaledCap] {
        let errs = default_ladder(RunMethod::England, rule, &RTOLS)?;
        assert_converges(rule.name(), &errs, PER_DECADE);
    }
    Ok(())
}

/// The thesis's rule (England uncapped), still selectable, on the same path: its error
/// plateaus (issue 22: its steps in the dwells are held by stability and do not shrink
/// with rtol).
#[test]
fn thesis_rule_error_plateaus() -> Result<()> {
    let errs = default_ladder(
        RunMethod::England,
        StepRule::Thesis,
        &[1e-5, 1e-6, 1e-7, 1e-8],
    )?;
    assert_plateaus("thesis", &errs, PER_DECADE);
    Ok(())
}
