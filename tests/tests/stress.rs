//! Stability stress tests of England's method on the full cam model (issue 9): contact and
//! structural stiffness from 1/100 to 100 times the reference, cam speed from 100 to
//! 3000 rpm, rtol from 1e-2 to 1e-10, damping near zero, a return spring so weak the
//! follower leaves the cam every revolution, 50 revolutions of steady state, each with
//! England's original step control and with the PI controller and stiffness cap (and a
//! few in f32). Every case must either reach its last revolution with every state,
//! force and acceleration finite and bounded, or stop with a typed error (step budget,
//! step-size underflow, a stalled drive) within its step budget; none may hang or pass a
//! NaN on. Then the measured order of the error against the step size on the model:
//! 4 for RK4 and for England's propagated solution (two RK4 half steps; its error
//! estimate's fifth order is `tests/controller.rs`'s), against a reference from England
//! at rtol 1e-13.
//!
//! Measured numbers quoted in comments come from
//! `cargo test -p camsim-tests --test stress -- --nocapture`.

use std::ops::ControlFlow;
use std::sync::OnceLock;

use camsim::bench::methods::{run as run_method, Method};
use camsim::bench::sample::{Sampler, Samples};
use camsim_core::{
    solver_config, Design, England, EnglandConfig, Error, Merson, Real, RegulatedFull,
    RegulatedFullModel, Scene, SolverSettings, SolverStats, Start, StepControl, StiffnessCap,
    Tolerance, SCALED_CAP_FULL_RTOL,
};

mod common;
use common::loglog_slope;

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Attempted (double) steps allowed per revolution: about 40 times what the reference
/// needs at 500 rpm, so that a case that needs more ends with a typed error.
const BUDGET_PER_REV: u32 = 250_000;

/// What a run passed through.
#[derive(Debug, Default)]
struct Seen {
    /// The last revolution was completed.
    reached: bool,
    /// A node with a non-finite quantity (must never happen).
    non_finite: bool,
    /// The follower was off the cam at some node of revolution r (index r - 1).
    separated: Vec<bool>,
    /// Largest |displacement| of any DOF, in.
    max_pos: f64,
    /// Largest |velocity|, in/s.
    max_vel: f64,
    /// Largest contact force, lb.
    max_force: f64,
    /// Smallest and largest cam speed over ω0.
    min_speed: f64,
    max_speed: f64,
    /// Nodes seen.
    nodes: u64,
}

/// Runs `revolutions` revolutions of the full model from static equilibrium with
/// England's method in precision `T`, checking every node (midpoints and ends).
/// The integrator of a stress run: England's method under a step control, or Merson's
/// pair with the tolerance-scaled cap (the default's method at rtol >= 1e-7).
enum Integrator<T> {
    England(StepControl<T>),
    MersonCapped,
}

impl<T: Real> From<StepControl<T>> for Integrator<T> {
    fn from(c: StepControl<T>) -> Self {
        Integrator::England(c)
    }
}

fn stress_run<T: Real>(
    design: &Design<f64>,
    rtol: f64,
    atol: f64,
    integrator: impl Into<Integrator<T>>,
    revolutions: u32,
) -> (Result<SolverStats, Error>, Seen, u32) {
    let model = RegulatedFullModel::<T>::new(design.cast::<T>().unwrap()).expect("a valid design");
    let settings = SolverSettings {
        rtol: T::from_f64(rtol),
        atol: T::from_f64(atol),
        max_steps_per_rev: BUDGET_PER_REV,
        start: Start::Static,
        ..SolverSettings::reference()
    };
    let config = solver_config(&model, &settings, revolutions).unwrap();
    let budget = config.max_steps;
    let mut y = model.static_state();
    let w0 = design.omega0;
    let target = TWO_PI * f64::from(revolutions);
    let t_end = T::from_f64(4.0 * target / w0);
    let mut seen = Seen {
        separated: vec![false; revolutions as usize],
        min_speed: f64::INFINITY,
        ..Seen::default()
    };
    let mut observe = |t: T, y: &[T; RegulatedFull::N]| {
        let p = model.evaluate(t, y);
        seen.nodes += 1;
        let scalars = [
            p.theta_c,
            p.omega_c,
            p.omega_cp,
            p.omega_m,
            p.alpha_c,
            p.contact_force,
            p.torque_drive,
        ];
        let all = p
            .pos
            .iter()
            .chain(p.vel.iter())
            .chain(p.acc.iter())
            .chain(scalars.iter());
        if all.clone().any(|v| !v.is_finite()) {
            seen.non_finite = true;
            return ControlFlow::Break(());
        }
        let theta = p.theta_c.to_f64();
        seen.max_pos = p
            .pos
            .iter()
            .fold(seen.max_pos, |m, v| m.max(v.to_f64().abs()));
        seen.max_vel = p
            .vel
            .iter()
            .fold(seen.max_vel, |m, v| m.max(v.to_f64().abs()));
        seen.max_force = seen.max_force.max(p.contact_force.to_f64());
        let speed = p.omega_c.to_f64() / w0;
        seen.min_speed = seen.min_speed.min(speed);
        seen.max_speed = seen.max_speed.max(speed);
        if !p.in_contact {
            let rev = (theta / TWO_PI).floor().max(0.0) as usize;
            if let Some(s) = seen.separated.get_mut(rev) {
                *s = true;
            }
        }
        if theta >= target {
            seen.reached = true;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    };
    let r =
        match integrator.into() {
            Integrator::England(control) => England::with_control(config, control)
                .unwrap()
                .integrate(&model, T::ZERO, &mut y, t_end, &mut observe),
            Integrator::MersonCapped => {
                // A single step is half a double step (as a run's).
                let single = EnglandConfig {
                    h_init: config.h_init * T::HALF,
                    h_min: config.h_min * T::HALF,
                    h_max: config.h_max * T::HALF,
                    ..config
                };
                let cap = StiffnessCap::tolerance_scaled(T::from_f64(SCALED_CAP_FULL_RTOL));
                Merson::with_cap(single, cap).unwrap().integrate(
                    &model,
                    T::ZERO,
                    &mut y,
                    t_end,
                    |t, y, _| observe(t, y),
                )
            }
        };
    (r, seen, budget)
}

/// The contract of every case: finished with finite, bounded results within the budget,
/// or a typed error within it. Returns whether it finished.
fn check(case: &str, r: &Result<SolverStats, Error>, seen: &Seen, budget: u32) -> bool {
    assert!(
        !seen.non_finite,
        "{case}: a non-finite quantity reached the observer"
    );
    match r {
        Ok(s) => {
            assert!(seen.reached, "{case}: stopped early without an error");
            assert!(
                s.accepted + s.rejected <= budget,
                "{case}: over budget {s:?}"
            );
            // Bounded: the lift is 1.5 in and the cam turns 4π in 2 revolutions; a
            // solution that ran away would leave these bounds by orders of magnitude.
            assert!(seen.max_pos < 10.0, "{case}: |y| up to {}", seen.max_pos);
            assert!(seen.max_vel < 1e4, "{case}: |v| up to {}", seen.max_vel);
            assert!(seen.max_force < 1e5, "{case}: F_c up to {}", seen.max_force);
            assert!(
                seen.min_speed > 0.5 && seen.max_speed < 2.0,
                "{case}: cam speed {}-{} of ω0",
                seen.min_speed,
                seen.max_speed
            );
            eprintln!(
                "{case}: ok, {} steps, {} rejected, {} evaluations; |y| <= {:.3} in, |v| <= {:.1} in/s, F_c <= {:.1} lb, ω_c/ω0 {:.4}-{:.4}, separated {:?}",
                s.accepted, s.rejected, s.rhs_evals, seen.max_pos, seen.max_vel, seen.max_force,
                seen.min_speed, seen.max_speed, seen.separated
            );
            true
        }
        Err(e) => {
            match e {
                Error::StepBudgetExceeded { steps, .. } => {
                    assert!(
                        *steps <= budget,
                        "{case}: {steps} steps over the budget {budget}"
                    )
                }
                Error::StepSizeUnderflow { .. } | Error::NoConvergence { .. } => {}
                other => panic!("{case}: not a typed stop of the integration: {other}"),
            }
            eprintln!("{case}: typed error after {} nodes: {e}", seen.nodes);
            false
        }
    }
}

fn design(rpm: f64) -> Design<f64> {
    let mut d = Design::reference();
    d.set_speed_rpm(rpm).unwrap();
    d
}

/// A case under the three integrators a run can take on the full model: England's
/// classic and PI-capped controls, and Merson's capped pair (the default's).
fn both_controls(case: &str, d: &Design<f64>, rtol: f64, revolutions: u32) -> [bool; 3] {
    let mut out = [false; 3];
    for (k, (name, integrator)) in [
        (
            "classic",
            Integrator::England(StepControl::<f64>::classic()),
        ),
        ("pi_capped", Integrator::England(StepControl::pi_capped())),
        ("merson_capped", Integrator::MersonCapped),
    ]
    .into_iter()
    .enumerate()
    {
        let (r, seen, budget) = stress_run(d, rtol, 1e-3 * rtol, integrator, revolutions);
        out[k] = check(&format!("{case} [{name}]"), &r, &seen, budget);
    }
    out
}

const FACTORS: [f64; 4] = [0.01, 0.1, 10.0, 100.0];

#[test]
fn contact_stiffness_from_a_hundredth_to_a_hundred_times() {
    for f in FACTORS {
        let mut d = design(500.0);
        // K_h is proportional to the contact modulus (Eqs. V.10-V.11 at unit force).
        d.hertz.youngs_1 *= f;
        d.hertz.youngs_2 *= f;
        let done = both_controls(&format!("contact stiffness x{f}"), &d, 1e-6, 2);
        // Soft or stiff, a static start at 500 rpm is an ordinary run.
        assert_eq!(done, [true; 3], "contact x{f}");
    }
}

#[test]
fn structural_stiffness_from_a_hundredth_to_a_hundred_times() {
    for f in FACTORS {
        let mut d = design(500.0);
        d.k_vs *= f;
        d.k_hs *= f;
        d.k_rb *= f;
        d.k_s1 *= f;
        d.k_s2 *= f;
        d.youngs *= f;
        let done = both_controls(&format!("structural stiffness x{f}"), &d, 1e-6, 2);
        assert_eq!(done, [true; 3], "structure x{f}");
    }
}

#[test]
fn cam_speed_from_100_to_3000_rpm() {
    for rpm in [100.0, 300.0, 1000.0, 2000.0, 3000.0] {
        let done = both_controls(&format!("{rpm} rpm"), &design(rpm), 1e-6, 2);
        if rpm <= 300.0 {
            assert_eq!(done, [true; 3], "{rpm} rpm");
        }
    }
}

#[test]
fn relative_tolerance_from_1e_2_to_1e_10() {
    for rtol in [1e-2, 1e-4, 1e-6, 1e-8, 1e-10] {
        let done = both_controls(&format!("rtol {rtol:e}"), &design(500.0), rtol, 2);
        assert_eq!(done, [true; 3], "rtol {rtol}");
    }
}

#[test]
fn damping_near_zero() {
    let mut d = design(500.0);
    let tiny = 1e-6;
    d.c_vs *= tiny;
    d.c_hs *= tiny;
    d.c_cc *= tiny;
    d.c_mb *= tiny;
    d.c_s1 *= tiny;
    d.c_s2 *= tiny;
    d.damping_ratio_f1 *= tiny;
    d.contact_damping_ratio *= tiny;
    d.roller_bearing_damping_ratio *= tiny;
    d.mu = 0.0;
    let done = both_controls("damping x1e-6, no friction", &d, 1e-6, 2);
    assert_eq!(done, [true; 3]);
}

#[test]
fn a_spring_so_weak_the_follower_leaves_the_cam_every_revolution() {
    // 30 lb/in instead of 100: the preload falls to 15 lb and the onset speed to about
    // 902 rpm · √0.3 = 494 rpm (the onset goes with the square root of the spring's force
    // over the inertia force), at 500 rpm. (Far above the onset, at 1500-3000 rpm with the
    // reference spring, the follower flies up until the cantilever's free length e2 - y3
    // closes and K_hc = 3EI/(e2 - y3)³ diverges: the model leaves its range and the run
    // ends in a step-size underflow; a 10 lb/in spring at 500 rpm ends in one too.)
    let mut d = design(500.0);
    d.k_rs = 30.0;
    d.k_rs_modal = 30.0;
    for (name, integrator) in [
        (
            "classic",
            Integrator::England(StepControl::<f64>::classic()),
        ),
        ("pi_capped", Integrator::England(StepControl::pi_capped())),
        ("merson_capped", Integrator::MersonCapped),
    ] {
        let (r, seen, budget) = stress_run(&d, 1e-6, 1e-9, integrator, 3);
        let done = check(&format!("k_rs 30 lb/in [{name}]"), &r, &seen, budget);
        assert!(done, "{name}");
        assert_eq!(seen.separated, [true, true, true], "{name}");
    }
}

#[test]
fn single_precision_cases_finish_or_stop_typed() {
    for rpm in [100.0, 500.0, 3000.0] {
        for (name, integrator) in [
            (
                "classic",
                Integrator::England(StepControl::<f32>::classic()),
            ),
            ("pi_capped", Integrator::England(StepControl::pi_capped())),
            ("merson_capped", Integrator::MersonCapped),
        ] {
            let (r, seen, budget) = stress_run::<f32>(&design(rpm), 1e-4, 1e-7, integrator, 2);
            let done = check(
                &format!("f32 {rpm} rpm rtol 1e-4 [{name}]"),
                &r,
                &seen,
                budget,
            );
            if rpm == 500.0 {
                assert!(done, "f32 at 500 rpm");
            }
        }
    }
    // Below what f32 resolves: a typed error, soon (a budget of 20 000 steps).
    let mut d = design(500.0);
    d.set_speed_rpm(500.0).unwrap();
    let model = RegulatedFullModel::<f32>::new(d.cast().unwrap()).unwrap();
    let settings = SolverSettings {
        rtol: 1e-9f32,
        atol: 1e-12,
        max_steps_per_rev: 10_000,
        start: Start::Static,
        ..SolverSettings::reference()
    };
    let config = solver_config(&model, &settings, 2).unwrap();
    let mut solver = England::new(config).unwrap();
    let mut y = model.static_state();
    let r = solver.integrate(&model, 0.0, &mut y, 1.0, |_, _| ControlFlow::Continue(()));
    match r {
        Err(Error::StepBudgetExceeded { steps, .. }) => assert_eq!(steps, 20_000),
        Err(Error::StepSizeUnderflow { .. }) => {}
        other => panic!("f32 at rtol 1e-9: {other:?}"),
    }
}

#[test]
fn fifty_revolutions_reach_a_steady_state_without_drift() {
    // Per revolution: the smallest and largest contact force and the mean cam speed.
    let d = design(500.0);
    let model = RegulatedFullModel::<f64>::new(d.clone()).unwrap();
    let settings = SolverSettings {
        start: Start::Static,
        ..SolverSettings::reference()
    };
    let revolutions = 50u32;
    let config = solver_config(&model, &settings, revolutions).unwrap();
    let mut solver = England::with_control(config, StepControl::pi_capped()).unwrap();
    let mut y = model.static_state();
    let n = revolutions as usize;
    let (mut f_min, mut f_max) = (vec![f64::INFINITY; n], vec![0.0f64; n]);
    // Time the cam angle crosses 2π r, linear between the nodes around it (the cam speed
    // changes by 1e-9 of itself over a node spacing, so the interpolation is far finer
    // than the changes measured).
    let mut rev_start = vec![f64::NAN; n + 1];
    rev_start[0] = 0.0;
    let mut prev = (0.0f64, 0.0f64);
    let target = TWO_PI * f64::from(revolutions);
    let t_end = 4.0 * target / d.omega0;
    let stats = solver
        .integrate(&model, 0.0, &mut y, t_end, |t, y| {
            let p = model.evaluate(t, y);
            assert!(p.contact_force.is_finite() && p.theta_c.is_finite());
            let r = (p.theta_c / TWO_PI).floor() as usize;
            let crossing = |(t0, th0): (f64, f64)| {
                let th = TWO_PI * r as f64;
                t0 + (t - t0) * (th - th0) / (p.theta_c - th0)
            };
            if r >= n {
                rev_start[n] = crossing(prev);
                return ControlFlow::Break(());
            }
            if rev_start[r].is_nan() {
                rev_start[r] = crossing(prev);
            }
            prev = (t, p.theta_c);
            f_min[r] = f_min[r].min(p.contact_force);
            f_max[r] = f_max[r].max(p.contact_force);
            ControlFlow::Continue(())
        })
        .unwrap();
    let period: Vec<f64> = rev_start.windows(2).map(|w| w[1] - w[0]).collect();
    let nominal = TWO_PI / d.omega0;
    eprintln!(
        "periods {:?}",
        period.iter().map(|p| p / nominal - 1.0).collect::<Vec<_>>()
    );
    eprintln!(
        "50 revolutions: {} steps, {} rejected; F_c rev 2 {:.4}-{:.4}, rev 10 {:.4}-{:.4}, rev 50 {:.4}-{:.4} lb; period rev 2 {:.9}, rev 50 {:.9} s (nominal {:.9})",
        stats.accepted, stats.rejected, f_min[1], f_max[1], f_min[9], f_max[9], f_min[49], f_max[49],
        period[1], period[49], nominal
    );
    // The budget held and nothing ran away.
    assert!(stats.accepted + stats.rejected <= BUDGET_PER_REV * revolutions);
    // Steady state from revolution 10 on: every revolution's extreme forces and its
    // duration equal revolution 10's to within the solver's own tolerance level (the
    // node times differ from revolution to revolution, which moves a sampled extremum by
    // up to the force's change over a step: a few 1e-3 lb of a 100 lb swing).
    for r in 10..n {
        assert!(
            (f_min[r] - f_min[9]).abs() < 1e-2,
            "rev {}: F_min {} vs {}",
            r + 1,
            f_min[r],
            f_min[9]
        );
        assert!(
            (f_max[r] - f_max[9]).abs() < 1e-2,
            "rev {}: F_max {} vs {}",
            r + 1,
            f_max[r],
            f_max[9]
        );
        assert!(
            (period[r] / period[9] - 1.0).abs() < 1e-6,
            "rev {}: period {} vs {}",
            r + 1,
            period[r],
            period[9]
        );
    }
    // And the regulated drive holds the mean speed near its set point: the period is the
    // nominal one to within the motor law's steady droop (0.28 % at 500 rpm).
    assert!((period[49] / nominal - 1.0).abs() < 1e-2);
}

// ------------------------------------------------------------ order of the error

/// England at rtol 1e-13 (atol 1e-16 in), revolution 2 at 500 rpm, sampled every 0.5°
/// (`camsim bench`'s reference: Dormand-Prince at the same tolerance differs from it by
/// 4.8e-8 in/s² RMS in the load's acceleration).
fn reference() -> &'static Samples {
    static REF: OnceLock<Samples> = OnceLock::new();
    REF.get_or_init(|| {
        let m = RegulatedFullModel::<f64>::new(design(500.0)).unwrap();
        let mut s = Sampler::new(&m, 2, Some(2));
        let settings = SolverSettings {
            rtol: 1e-13,
            atol: 1e-16,
            start: Start::Static,
            ..SolverSettings::reference()
        };
        run_method(Method::England, &m, &settings, 2, &mut s).unwrap();
        s.samples
    })
}

/// RMS acceleration error of revolution 2 against the reference.
fn acc_error(s: &Samples) -> f64 {
    Samples::rms_diff(&s.acc, &reference().acc)
}

/// RK4 at `n` fixed steps per nominal revolution.
fn rk4_error(n: u32) -> f64 {
    let m = RegulatedFullModel::<f64>::new(design(500.0)).unwrap();
    let mut s = Sampler::new(&m, 2, Some(2));
    let settings = SolverSettings::reference();
    run_method(Method::Rk4 { steps_per_rev: n }, &m, &settings, 2, &mut s).unwrap();
    acc_error(&s.samples)
}

/// England at `n` fixed double steps per nominal revolution (h_min = h_max = h and a
/// tolerance no step can fail: nothing is rejected), sampled through its dense output.
fn england_fixed_error(n: u32) -> f64 {
    let m = RegulatedFullModel::<f64>::new(design(500.0)).unwrap();
    let h = TWO_PI / m.design().omega0 / f64::from(n);
    let config = EnglandConfig::<f64, { RegulatedFull::N }> {
        tol: Tolerance::scalar(0.5, 1e30),
        h_init: h,
        h_min: h,
        h_max: h,
        max_steps: 10 * n,
    };
    let mut solver = England::new(config).unwrap();
    let mut s = Sampler::new(&m, 2, Some(2));
    let mut y = m.static_state();
    let stats = solver
        .integrate_dense(&m, 0.0, &mut y, 3.0 * TWO_PI / m.design().omega0, |d| {
            s.feed(d)
        })
        .unwrap();
    assert_eq!(stats.rejected, 0);
    assert!(s.done && s.complete());
    acc_error(&s.samples)
}

#[test]
fn rk4_and_englands_propagated_solution_are_fourth_order_on_the_model() {
    // Steps per revolution above the fixed-step stability limits (RK4 about 15 200
    // steps, England about 7 600 double steps at 500 rpm: `camsim bench`), spaced by √2.
    let ns = [20_000u32, 28_284, 40_000];
    let h: Vec<f64> = ns.iter().map(|n| 1.0 / f64::from(*n)).collect();
    let rk4: Vec<f64> = ns.iter().map(|n| rk4_error(*n)).collect();
    let p_rk4 = loglog_slope(&h, &rk4);
    // England's double step h is two RK4 steps of h/2: the same steps per revolution
    // halved give the same error.
    let eng: Vec<f64> = ns.iter().map(|n| england_fixed_error(n / 2)).collect();
    let p_eng = loglog_slope(&h, &eng);
    eprintln!("RK4 errors {rk4:?}: order {p_rk4:.3}; England (double steps n/2) {eng:?}: order {p_eng:.3}");
    // Every error far above the reference's own (4.8e-8 in/s² against Dormand-Prince).
    assert!(rk4.iter().chain(&eng).all(|e| *e > 2e-6));
    assert!((p_rk4 - 4.0).abs() < 0.25, "RK4 order {p_rk4}");
    assert!((p_eng - 4.0).abs() < 0.25, "England order {p_eng}");
    for (a, b) in rk4.iter().zip(&eng) {
        assert!((a / b - 1.0).abs() < 0.05, "RK4 {a} against England {b}");
    }
}
