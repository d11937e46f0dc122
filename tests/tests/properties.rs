//! Properties over random inputs (proptest): the core returns finite results or a typed
//! error, never panics and never takes more steps than its budget.
//!
//! - Random valid scenes: the reference design perturbed within plausible ranges (masses,
//!   stiffnesses, damping, friction, spring, geometry, speed, program timing and laws),
//!   each of the ten scenes (f64, and the chip's scene in f32), simulated for a fraction
//!   of a revolution on a small step budget.
//! - Random ODEs through England: damped oscillators against their closed form, linear
//!   systems whose norm cannot grow (skew-symmetric plus a non-positive diagonal) against
//!   that bound, arbitrary linear systems and a blow-up (`y' = y²`) for finite-or-typed-error.
//!
//! Case counts are set per property so that the whole file runs in well under a minute on
//! two cores (`cargo test -p camsim-tests --test properties`); `PROPTEST_CASES` overrides
//! them all for a longer run.

use std::ops::ControlFlow;

use camsim_core::{
    simulate, CamModel, CamProgram, Design, DriveKind, DriveLaw, England, EnglandConfig, Error,
    MotionLaw, OdeSystem, Real, Sample, Scene, SceneId, SceneVisitor, Segment, SegmentKind,
    SolverSettings, SolverStats, Start, Tolerance,
};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Cases per property, unless `PROPTEST_CASES` asks for another number.
fn cases(default: u32) -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default);
    ProptestConfig {
        cases,
        // A rejected design (undercut, e2 below the lift) is a local reject; allow plenty.
        max_local_rejects: 100_000,
        max_global_rejects: 100_000,
        // A failure prints its minimal input; a regression test is written by hand.
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

// ------------------------------------------------------------------- random scenes

/// One random scene: a perturbed reference design and how to run it.
#[derive(Clone, Debug)]
struct RandomScene {
    design: Design<f64>,
    scene: SceneId,
    start: Start,
    rtol: f64,
    /// Fraction of a revolution to simulate.
    fraction: f64,
    /// Step budget (the whole budget, since a fraction of one revolution is simulated).
    budget: u32,
}

/// A factor in [1/spread, spread], uniform in its logarithm.
fn factor(spread: f64) -> impl Strategy<Value = f64> {
    (-1.0f64..=1.0).prop_map(move |u| spread.powf(u))
}

/// A cam program D-R-D-R closing at 360 deg with random timing, lift and laws.
fn program() -> impl Strategy<Value = CamProgram<f64>> {
    let law = prop::sample::select(MotionLaw::ALL.to_vec());
    (
        5.0f64..60.0,
        100.0f64..180.0,
        5.0f64..60.0,
        0.3f64..1.5,
        law.clone(),
        law,
    )
        .prop_filter_map("program refused", |(d1, rise, d2, lift, r, ret)| {
            let a = d1;
            let b = a + rise;
            let c = b + d2;
            if c >= 300.0 {
                return None;
            }
            let seg = |kind, start_deg, end_deg, lift| Segment {
                kind,
                start_deg,
                end_deg,
                lift,
            };
            CamProgram::new(&[
                seg(SegmentKind::Dwell, 0.0, a, 0.0),
                seg(SegmentKind::Rise(r), a, b, lift),
                seg(SegmentKind::Dwell, b, c, 0.0),
                seg(SegmentKind::Return(ret), c, 360.0, lift),
            ])
            .ok()
        })
}

prop_compose! {
    /// The reference design with every parameter moved within a plausible range.
    fn design()(
        inertia in prop::array::uniform3(factor(2.0)),
        shaft in prop::array::uniform4(factor(2.0)),
        drag in prop::array::uniform3(factor(2.0)),
        cam in prop::array::uniform3(factor(2.0)),
        roller in prop::array::uniform2(factor(2.0)),
        follower in prop::array::uniform3(factor(1.5)),
        ratios in prop::array::uniform3(0.0f64..0.1),
        mu in 0.0f64..0.2,
        smoothing in 0.001f64..0.1,
        spring in (40.0f64..300.0, 0.2f64..1.0, factor(2.0)),
        radii in (1.2f64..3.0, 0.2f64..0.6),
        levers in (1.6f64..3.0, 1.0f64..3.0, 2.0f64..5.0),
        rpm in 200.0f64..1100.0,
        program in program(),
    ) -> Design<f64> {
        let mut d = Design::<f64>::reference();
        d.i_m *= inertia[0];
        d.i_cp *= inertia[1];
        d.i_c *= inertia[2];
        d.k_s1 *= shaft[0];
        d.k_s2 *= shaft[1];
        d.c_s1 *= shaft[2];
        d.c_s2 *= shaft[3];
        d.c_mb *= drag[0];
        d.c_cc *= drag[1];
        d.c_vs *= drag[2];
        d.c_hs *= drag[2];
        d.m_c *= cam[0];
        d.k_vs *= cam[1];
        d.k_hs *= cam[2];
        d.m_r *= roller[0];
        d.k_rb *= roller[1];
        d.m_l *= follower[0];
        d.e1 *= follower[1];
        d.area *= follower[2];
        d.inertia_moment *= follower[2] * follower[2];
        d.roller_bearing_damping_ratio = ratios[0];
        d.contact_damping_ratio = ratios[1];
        d.damping_ratio_f1 = ratios[2];
        d.mu = mu;
        d.friction_smoothing = smoothing;
        d.k_rs = spring.0;
        d.k_rs_modal = spring.0;
        d.delta_rs = spring.1;
        d.m_spring *= spring.2;
        d.geometry.base_radius = radii.0;
        d.geometry.roller_radius = radii.1;
        d.e2 = levers.0;
        d.bearing_a = levers.1;
        d.bearing_b = levers.2;
        d.program = program;
        // Speed last: the regulated drive from the (perturbed) drags at this speed.
        d.set_speed_rpm(rpm).expect("a positive speed");
        d.drive = DriveLaw::reference(d.omega0, d.c_mb, d.c_cc);
        d
    }
}

prop_compose! {
    fn random_scene()(
        design in design(),
        scene in prop::sample::select(SceneId::ALL.to_vec()),
        start in prop::sample::select(vec![Start::Thesis, Start::Static]),
        rtol in prop::sample::select(vec![1e-4, 1e-5, 1e-6]),
        fraction in 0.05f64..0.3,
        // Mostly enough for the fraction (about 6000 double steps a revolution for the
        // reference), sometimes far too little.
        budget in prop_oneof![3 => 4000u32..20_000, 1 => 20u32..2000],
    ) -> RandomScene {
        let mut design = design;
        design.drive = match scene.drive() {
            DriveKind::Regulated => design.drive,
            DriveKind::ConstantMotorSpeed => DriveLaw::ConstantMotorSpeed,
            DriveKind::ConstantCamSpeed => DriveLaw::ConstantCamSpeed,
        };
        RandomScene { design, scene, start, rtol, fraction, budget }
    }
}

/// How a run of a valid scene ended (all three are allowed by [`check_run`]; the share
/// of completed runs is checked by `most_valid_scenes_with_a_fair_budget_complete`).
#[derive(Debug, PartialEq)]
enum Outcome {
    /// The fraction of a revolution was simulated, every sample finite.
    Completed,
    /// The step budget ran out (a typed error).
    BudgetExceeded,
    /// Another typed run-time error.
    Failed(String),
}

/// What a run of a valid scene may end with: success with every sample finite and the
/// budget kept, or one of the run-time errors (never a refused parameter: the design was
/// validated, the settings are valid).
fn check_run<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
    r: &RandomScene,
) -> Result<Outcome, TestCaseError> {
    let settings = SolverSettings {
        rtol: T::from_f64(r.rtol),
        start: r.start,
        max_steps_per_rev: r.budget,
        ..SolverSettings::reference()
    };
    let stop = T::from_f64(r.fraction * TWO_PI);
    let mut samples = 0usize;
    let mut bad: Option<(f64, usize)> = None;
    let mut observer = |s: &Sample<T>| {
        samples += 1;
        if let Some(i) = s.numbers().iter().position(|x| !x.is_finite()) {
            bad = Some((s.point.t.to_f64(), i));
            return ControlFlow::Break(());
        }
        if s.point.theta_c >= stop {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let result: Result<SolverStats, Error> = simulate(model, &settings, 1, &mut observer);
    match result {
        Ok(stats) => {
            prop_assert!(bad.is_none(), "non-finite sample (t, index): {bad:?}");
            prop_assert!(samples > 1);
            let steps = stats.accepted + stats.rejected;
            prop_assert!(
                steps <= r.budget,
                "{steps} steps on a budget of {}",
                r.budget
            );
            // The default method's count (Merson's pair): the start, 5 per accepted step
            // (4 stages and the end point's derivative), 4 per rejected one, plus the
            // default control's stiffness estimates (at most 1 + 20 power iterations
            // each: one at the start and one every 25 accepted steps).
            let merson = 1 + 5 * stats.accepted + 4 * stats.rejected;
            let estimates = 1 + stats.accepted / 25;
            prop_assert!(stats.rhs_evals > merson);
            prop_assert!(stats.rhs_evals <= merson + 21 * estimates);
            Ok(Outcome::Completed)
        }
        Err(Error::StepBudgetExceeded { steps, .. }) => {
            prop_assert!(
                steps <= r.budget,
                "{steps} steps on a budget of {}",
                r.budget
            );
            Ok(Outcome::BudgetExceeded)
        }
        Err(e @ (Error::InvalidParameter { .. } | Error::Inconsistent { .. })) => Err(
            TestCaseError::fail(format!("a validated scene was refused: {e}")),
        ),
        // Run-time failures are typed errors (step size, non-finite state, a stalled drive,
        // or whatever the model's own validity checks report).
        Err(e) => Ok(Outcome::Failed(e.to_string())),
    }
}

fn run_scene(r: &RandomScene) -> Result<Outcome, TestCaseError> {
    struct Run<'a>(&'a RandomScene);
    impl SceneVisitor for Run<'_> {
        type Output = Result<Outcome, TestCaseError>;
        fn visit<S: Scene, const N: usize>(self) -> Self::Output {
            let m = CamModel::<f64, S, N>::new(self.0.design.clone())
                .map_err(|e| TestCaseError::fail(format!("model of a valid design: {e}")))?;
            check_run(&m, self.0)
        }
    }
    r.scene.visit(Run(r))
}

proptest! {
    #![proptest_config(cases(1024))]

    /// Random valid scenes in f64, each of the ten scenes: finite or a typed error, within
    /// the budget.
    #[test]
    fn random_valid_scenes_run_finite_or_fail_typed(r in random_scene()) {
        prop_assume!(r.design.validate().is_ok());
        run_scene(&r)?;
    }
}

/// The property above accepts any typed error, so a solver that failed on every scene
/// would pass it. Here the same random scenes (a fixed seed, so the count is
/// reproducible), each with a fair budget (20 000 double steps for at most 0.3 of a
/// revolution, over three times what the reference design needs at rtol 1e-6), must
/// mostly complete: at least 95 % of 200 (all 200 do today), and none may end out of
/// budget.
#[test]
fn most_valid_scenes_with_a_fair_budget_complete() {
    most_complete_with_a_fair_budget("f64", |r| {
        if r.design.validate().is_err() {
            return Ok(None);
        }
        run_scene(r).map(Some)
    });
}

/// Draws the random scenes of a fixed seed, each with a fair budget (20 000 double
/// steps), until 200 are valid (`run` returns `None` for one that is not), and checks
/// that at least 95 % of them complete and none ends out of budget.
fn most_complete_with_a_fair_budget(
    what: &str,
    mut run: impl FnMut(&mut RandomScene) -> Result<Option<Outcome>, TestCaseError>,
) {
    use proptest::strategy::ValueTree;
    use proptest::test_runner::{RngAlgorithm, TestRng, TestRunner};
    let mut runner =
        TestRunner::new_with_rng(cases(200), TestRng::deterministic_rng(RngAlgorithm::ChaCha));
    let (mut valid, mut completed, mut failures) = (0usize, 0usize, Vec::new());
    while valid < 200 {
        let mut r = random_scene().new_tree(&mut runner).unwrap().current();
        r.budget = 20_000;
        let Some(outcome) = run(&mut r).unwrap_or_else(|e| panic!("{e}: {r:?}")) else {
            continue;
        };
        valid += 1;
        match outcome {
            Outcome::Completed => completed += 1,
            Outcome::BudgetExceeded => panic!("{what}: out of a fair budget: {r:?}"),
            Outcome::Failed(e) => failures.push(e),
        }
    }
    eprintln!("{what}: {completed} of {valid} completed; failures: {failures:?}");
    assert!(
        completed * 20 >= valid * 19,
        "{what}: {completed} of {valid} valid scenes completed; failures: {failures:?}"
    );
}

proptest! {
    #![proptest_config(cases(256))]

    /// The chip's scene (`camsim_chip::ChipModel`: regulated drive, the quasi-static rod)
    /// in f32, from a random design narrowed as the firmware narrows it.
    #[test]
    fn random_valid_scenes_in_f32_run_finite_or_fail_typed(r in random_scene()) {
        let mut r = r;
        let Some(m) = chip_model(&mut r)? else {
            return Err(TestCaseError::reject("not a valid chip scene in f32"));
        };
        check_run(&m, &r)?;
    }
}

/// Narrows a random scene as the firmware narrows it (the chip's scene, the regulated
/// drive, rtol at least 1e-5) and builds its f32 model: `None` if the design is not
/// valid, in f64 or in f32.
fn chip_model(r: &mut RandomScene) -> Result<Option<camsim_chip::ChipModel<f32>>, TestCaseError> {
    r.scene = SceneId::RegulatedQsRod;
    r.design.drive = DriveLaw::reference(r.design.omega0, r.design.c_mb, r.design.c_cc);
    r.rtol = r.rtol.max(1e-5);
    if r.design.validate().is_err() {
        return Ok(None);
    }
    let Ok(d32) = r.design.cast::<f32>() else {
        return Ok(None);
    };
    if d32.validate().is_err() {
        return Ok(None);
    }
    camsim_chip::ChipModel::<f32>::new(d32)
        .map(Some)
        .map_err(|e| TestCaseError::fail(format!("model of a valid design: {e}")))
}

/// The f32 property above accepts any typed error too, so it would pass if every f32 run
/// failed. Here the same random scenes narrowed to the chip's (a fixed seed), each with
/// the fair budget of [`most_valid_scenes_with_a_fair_budget_complete`], must mostly
/// complete in f32: the same rule, at least 95 % of 200, and none out of budget.
#[test]
fn most_valid_f32_chip_scenes_with_a_fair_budget_complete() {
    most_complete_with_a_fair_budget("f32", |r| match chip_model(r)? {
        Some(m) => check_run(&m, r).map(Some),
        None => Ok(None),
    });
}

// ----------------------------------------------------------------------- random ODEs

/// x'' + 2 ζ ω x' + ω² x = 0 as (x, v).
struct Oscillator {
    omega: f64,
    zeta: f64,
}

impl OdeSystem<f64, 2> for Oscillator {
    fn rhs(&self, _t: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
        let [x, v] = *y;
        *dydt = [
            v,
            -2.0 * self.zeta * self.omega * v - self.omega * self.omega * x,
        ];
    }
}

impl Oscillator {
    /// The closed form x(t) from x(0) = x0, x'(0) = v0 (under-, critically and over-damped).
    fn exact(&self, x0: f64, v0: f64, t: f64) -> f64 {
        let (w, z) = (self.omega, self.zeta);
        let decay = (-z * w * t).exp();
        if (z - 1.0).abs() < 1e-9 {
            // x = (x0 + (v0 + w x0) t) e^{-w t}
            (x0 + (v0 + w * x0) * t) * decay
        } else if z < 1.0 {
            let wd = w * (1.0 - z * z).sqrt();
            decay * (x0 * (wd * t).cos() + (v0 + z * w * x0) / wd * (wd * t).sin())
        } else {
            let s = w * (z * z - 1.0).sqrt();
            decay * (x0 * (s * t).cosh() + (v0 + z * w * x0) / s * (s * t).sinh())
        }
    }
}

/// y' = A y.
struct Linear<const N: usize>([[f64; N]; N]);

impl<const N: usize> OdeSystem<f64, N> for Linear<N> {
    fn rhs(&self, _t: f64, y: &[f64; N], dydt: &mut [f64; N]) {
        for (d, row) in dydt.iter_mut().zip(&self.0) {
            *d = row.iter().zip(y).map(|(a, b)| a * b).sum();
        }
    }
}

/// y' = y² (y = y0 / (1 - y0 t): infinite at t = 1/y0).
struct BlowUp;

impl OdeSystem<f64, 1> for BlowUp {
    fn rhs(&self, _t: f64, y: &[f64; 1], dydt: &mut [f64; 1]) {
        dydt[0] = y[0] * y[0];
    }
}

fn solver<const N: usize>(rtol: f64, atol: f64, h_max: f64, budget: u32) -> England<f64, N> {
    England::new(EnglandConfig {
        tol: Tolerance::scalar(rtol, atol),
        h_init: h_max * 1e-3,
        h_min: h_max * 1e-14,
        h_max,
        max_steps: budget,
    })
    .expect("a valid configuration")
}

/// The budget kept, and England's evaluation count, on success or on budget failure.
fn check_budget(result: &Result<SolverStats, Error>, budget: u32) -> Result<(), TestCaseError> {
    match result {
        Ok(s) => {
            prop_assert!(s.accepted + s.rejected <= budget);
            prop_assert_eq!(s.rhs_evals, 9 * s.accepted + 7 * s.rejected);
        }
        Err(Error::StepBudgetExceeded { steps, .. }) => prop_assert!(*steps <= budget),
        Err(Error::InvalidParameter { field, .. }) => {
            return Err(TestCaseError::fail(format!("valid input refused: {field}")));
        }
        Err(_) => {}
    }
    Ok(())
}

proptest! {
    #![proptest_config(cases(1024))]

    /// Damped oscillators against their closed form. The flow never grows the energy norm
    /// |(x, v/ω)| (d/dt (ω²x² + v²) = -4ζω v² <= 0), so the global error is at most the sum
    /// of the local ones: per accepted double step atol + rtol |x| <= 2 rtol s on x and
    /// atol + rtol |v| <= rtol s (1 + ω) on v, s = max(|x0|, |v0|/ω) the amplitude scale
    /// (atol = rtol s): in the energy norm (3 + 1/ω) rtol s a step.
    #[test]
    fn oscillators_match_their_closed_form(
        omega in 0.1f64..2000.0,
        zeta in prop_oneof![Just(0.0), Just(1.0), 0.0f64..3.0],
        x0 in -10.0f64..10.0,
        v0 in -10.0f64..10.0,
        periods in 0.1f64..3.0,
        rtol in prop::sample::select(vec![1e-4, 1e-6, 1e-8, 1e-10]),
        budget in 1u32..20_000,
    ) {
        let sys = Oscillator { omega, zeta };
        let t_end = periods * TWO_PI / omega;
        let scale = x0.abs().max(v0.abs() / omega).max(1e-3);
        let atol = rtol * scale;
        let mut s = solver::<2>(rtol, atol, t_end / 4.0, budget);
        let mut y = [x0, v0];
        let result = s.integrate(&sys, 0.0, &mut y, t_end, |_, _| ControlFlow::Continue(()));
        check_budget(&result, budget)?;
        if result.is_ok() {
            prop_assert!(y.iter().all(|v| v.is_finite()));
            let steps = f64::from(result.map(|s| s.accepted).unwrap_or(0) + 1);
            let bound = steps * (3.0 + 1.0 / omega) * rtol * scale;
            let exact = sys.exact(x0, v0, t_end);
            let err = (y[0] - exact).abs();
            prop_assert!(
                err <= bound,
                "x({t_end}) = {} vs exact {exact}: error {err:e}, bound {bound:e}",
                y[0]
            );
        }
    }

    /// y' = (S + D) y, S skew-symmetric and D a non-positive diagonal: d|y|²/dt = 2 yᵀ D y
    /// <= 0, so |y| never grows and with D = 0 it is conserved, up to the sum of the local
    /// errors (the flow does not amplify them): per accepted double step at most
    /// atol + rtol |y| <= 2 rtol |y0| on each of 4 components, 4 rtol |y0| in norm.
    #[test]
    fn dissipative_linear_systems_never_grow(
        upper in prop::array::uniform6(-50.0f64..50.0),
        diag in prop::array::uniform4(prop_oneof![Just(0.0), -50.0f64..0.0]),
        y0 in prop::array::uniform4(-5.0f64..5.0),
        t_end in 0.01f64..2.0,
        rtol in prop::sample::select(vec![1e-5, 1e-7, 1e-9]),
    ) {
        // Upper triangle of S in row order: (0,1) (0,2) (0,3) (1,2) (1,3) (2,3).
        let pairs = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)];
        let mut a = [[0.0; 4]; 4];
        for (i, d) in diag.iter().enumerate() {
            a[i][i] = *d;
        }
        for (&(i, j), &u) in pairs.iter().zip(&upper) {
            a[i][j] = u;
            a[j][i] = -u;
        }
        let norm = |y: &[f64; 4]| y.iter().map(|v| v * v).sum::<f64>().sqrt();
        let n0 = norm(&y0);
        prop_assume!(n0 > 1e-3);
        let budget = 50_000;
        let mut s = solver::<4>(rtol, rtol * n0, t_end, budget);
        let mut y = y0;
        let mut grew = 0.0f64;
        let mut steps = 0.0;
        let result = s.integrate(&Linear(a), 0.0, &mut y, t_end, |_, y| {
            // Relative to the bound of the steps taken so far (two calls a double step).
            grew = grew.max((norm(y) / n0 - 1.0) / (4.0 * rtol * (steps / 2.0 + 1.0)));
            steps += 1.0;
            ControlFlow::Continue(())
        });
        check_budget(&result, budget)?;
        let Ok(stats) = result else {
            return Err(TestCaseError::fail(format!("{result:?}")));
        };
        prop_assert!(grew <= 1.0, "|y| grew by {grew} x its bound (rtol {rtol:e})");
        if diag.iter().all(|d| *d == 0.0) {
            let drift = (norm(&y) / n0 - 1.0).abs();
            let bound = 4.0 * rtol * f64::from(stats.accepted + 1);
            prop_assert!(drift <= bound, "|y| drifted by {drift:e}, bound {bound:e}");
        }
    }

    /// Arbitrary linear systems (growing ones too), arbitrary tolerances and budgets:
    /// finite on success, a typed error otherwise, never beyond the budget.
    #[test]
    fn arbitrary_linear_systems_end_finite_or_typed(
        a in prop::array::uniform4(prop::array::uniform4(-1.0f64..1.0)),
        magnitude in -2.0f64..3.0,
        y0 in prop::array::uniform4(-1e3f64..1e3),
        t_end in 0.0f64..10.0,
        rtol in 1e-12f64..0.5,
        atol in 1e-12f64..1.0,
        budget in 1u32..3000,
    ) {
        // Entries up to 10^magnitude: from slow to overflowing within t_end.
        let a = a.map(|row| row.map(|v| v * 10f64.powf(magnitude)));
        let mut s = solver::<4>(rtol, atol, t_end.max(1e-6), budget);
        let mut y = y0;
        let mut seen_non_finite = false;
        let result = s.integrate(&Linear(a), 0.0, &mut y, t_end, |_, y| {
            seen_non_finite |= y.iter().any(|v| !v.is_finite());
            ControlFlow::Continue(())
        });
        check_budget(&result, budget)?;
        if result.is_ok() {
            prop_assert!(!seen_non_finite && y.iter().all(|v| v.is_finite()), "{y:?}");
        }
    }

    /// y' = y² past its blow-up at t = 1/y0: never `Ok` with a non-finite state or through
    /// the singularity. Well before it (y0 t <= 0.9, where a perturbation grows at most
    /// (y/y0)² = 100 times) a success matches y0 / (1 - y0 t) to 1e-4.
    #[test]
    fn blow_up_is_a_typed_error(
        y0 in 0.1f64..10.0,
        past in 0.5f64..3.0,
        budget in 1u32..5000,
    ) {
        let t_end = past / y0;
        let mut s = solver::<1>(1e-8, 1e-10, t_end / 8.0, budget);
        let mut y = [y0];
        let result = s.integrate(&BlowUp, 0.0, &mut y, t_end, |_, _| ControlFlow::Continue(()));
        check_budget(&result, budget)?;
        if past >= 1.0 {
            prop_assert!(result.is_err(), "integrated through the singularity: {y:?}");
        }
        if result.is_ok() {
            prop_assert!(y[0].is_finite());
        }
        if result.is_ok() && past <= 0.9 {
            let exact = y0 / (1.0 - y0 * t_end);
            prop_assert!(
                (y[0] - exact).abs() <= 1e-4 * exact.abs(),
                "{} vs {exact}",
                y[0]
            );
        }
    }
}
