//! England's adaptive Runge-Kutta (Appendix D) and the classic RK4 against closed-form
//! solutions: convergence order, the error estimate, tolerance proportionality, typed
//! errors and the exact cost formula.

use core::ops::ControlFlow;

use camsim_core::{
    rk4_integrate, England, EnglandConfig, Error, OdeSystem, Real, SolverStats, Tolerance,
};

mod common;
use common::loglog_slope;

/// y' = -y + sin t; exact y(t) = C e^{-t} + (sin t - cos t)/2.
struct Forced;
impl<T: Real> OdeSystem<T, 1> for Forced {
    fn rhs(&self, t: T, y: &[T; 1], dydt: &mut [T; 1]) {
        dydt[0] = -y[0] + t.sin();
    }
}
fn forced_exact(t0: f64, y0: f64, t: f64) -> f64 {
    let c = (y0 - 0.5 * (t0.sin() - t0.cos())) * t0.exp();
    c * (-t).exp() + 0.5 * (t.sin() - t.cos())
}

/// x'' = -w^2 x as (x, v).
struct Oscillator {
    w: f64,
}
impl OdeSystem<f64, 2> for Oscillator {
    fn rhs(&self, _t: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
        dydt[0] = y[1];
        dydt[1] = -self.w * self.w * y[0];
    }
}
impl OdeSystem<f32, 2> for Oscillator {
    fn rhs(&self, _t: f32, y: &[f32; 2], dydt: &mut [f32; 2]) {
        dydt[0] = y[1];
        dydt[1] = -(self.w * self.w) as f32 * y[0];
    }
}

/// Counts its own calls, to check the solver's bookkeeping independently.
struct Counting<'a, S> {
    inner: S,
    calls: &'a core::cell::Cell<u32>,
}
impl<S: OdeSystem<f64, 1>> OdeSystem<f64, 1> for Counting<'_, S> {
    fn rhs(&self, t: f64, y: &[f64; 1], dydt: &mut [f64; 1]) {
        self.calls.set(self.calls.get() + 1);
        self.inner.rhs(t, y, dydt);
    }
}

fn cfg<const N: usize>(
    rtol: f64,
    atol: f64,
    h_init: f64,
    h_min: f64,
    h_max: f64,
    max_steps: u32,
) -> EnglandConfig<f64, N> {
    EnglandConfig {
        tol: Tolerance::scalar(rtol, atol),
        h_init,
        h_min,
        h_max,
        max_steps,
    }
}

/// England with every step accepted at exactly h (h_min = h_max, a tolerance it always meets).
fn fixed_england(h: f64) -> England<f64, 1> {
    England::new(cfg(0.0, 1e6, h, h, h, 1_000_000)).unwrap()
}

#[test]
fn fixed_step_global_error_is_fourth_order_for_england_and_rk4() {
    let (t0, y0, t_end) = (0.0, 1.0, 8.0);
    let exact = forced_exact(t0, y0, t_end);
    // Dyadic steps divide [0, 8] exactly: 4 halvings. (On [0, 2] this problem is
    // pre-asymptotic at h = 1/4: the global error changes sign near h = 1/2.)
    let hs = [0.25, 0.125, 0.0625, 0.03125, 0.015625];
    let mut e_eng = Vec::new();
    let mut e_rk4 = Vec::new();
    for &h in &hs {
        let mut solver = fixed_england(h);
        let mut y = [y0];
        let stats = solver
            .integrate(&Forced, t0, &mut y, t_end, |_, _| ControlFlow::Continue(()))
            .unwrap();
        assert_eq!(stats.rejected, 0);
        assert_eq!(
            stats.accepted,
            (t_end / h).round() as u32,
            "fixed step h = {h}"
        );
        e_eng.push((y[0] - exact).abs());

        let mut y = [y0];
        let steps = (t_end / h).round() as u32;
        let st = rk4_integrate(&Forced, t0, &mut y, t_end, steps, |_, _| {
            ControlFlow::Continue(())
        })
        .unwrap();
        assert_eq!(
            st,
            SolverStats {
                accepted: steps,
                rejected: 0,
                rhs_evals: 4 * steps
            }
        );
        e_rk4.push((y[0] - exact).abs());
    }
    let p_eng = loglog_slope(&hs, &e_eng);
    let p_rk4 = loglog_slope(&hs, &e_rk4);
    assert!(
        (3.7..=4.3).contains(&p_eng),
        "England order {p_eng}, errors {e_eng:?}"
    );
    assert!(
        (3.7..=4.3).contains(&p_rk4),
        "RK4 order {p_rk4}, errors {e_rk4:?}"
    );
    // Each halving divides the error by about 16.
    for w in e_eng.windows(2).chain(e_rk4.windows(2)) {
        let r = w[0] / w[1];
        assert!((12.0..=20.0).contains(&r), "halving ratio {r}");
    }
}

#[test]
fn fixed_step_oscillator_is_fourth_order() {
    // A second problem (a system of two) so a coupling bug cannot hide in a scalar test.
    let sys = Oscillator { w: 2.0 };
    let t_end = 4.0;
    let hs = [0.25, 0.125, 0.0625, 0.03125, 0.015625];
    let mut errs = Vec::new();
    for &h in &hs {
        let mut solver = England::<f64, 2>::new(cfg(0.0, 1e6, h, h, h, 1_000_000)).unwrap();
        let mut y = [1.0, 0.0];
        solver
            .integrate(&sys, 0.0, &mut y, t_end, |_, _| ControlFlow::Continue(()))
            .unwrap();
        let ex = [(2.0 * t_end).cos(), -2.0 * (2.0 * t_end).sin()];
        errs.push((y[0] - ex[0]).abs().max((y[1] - ex[1]).abs()));
    }
    let p = loglog_slope(&hs, &errs);
    assert!((3.7..=4.3).contains(&p), "order {p}, errors {errs:?}");
}

#[test]
fn error_estimate_tracks_true_local_error_of_the_double_step() {
    // With rtol = 0 and atol = 1 the returned error ratio is |E| itself.
    let (t0, y0) = (0.3, 1.0);
    let mut last_ratio = 0.0;
    for &h in &[0.4, 0.2, 0.1, 0.05, 0.025, 0.0125] {
        let mut solver = England::<f64, 1>::new(cfg(0.0, 1.0, h, h, h, 10)).unwrap();
        let mut t = t0;
        let mut y = [y0];
        let mut mid = (0.0, [0.0]);
        let e = solver
            .step(&Forced, &mut t, &mut y, t0 + 10.0, &mut mid)
            .unwrap();
        assert_eq!(t, t0 + h);
        assert!((mid.0 - (t0 + 0.5 * h)).abs() < 1e-15);
        let true_local = (y[0] - forced_exact(t0, y0, t0 + h)).abs();
        let ratio = e / true_local;
        assert!(
            (0.5..=2.0).contains(&ratio),
            "h = {h}: |E| = {e:e}, true {true_local:e}, ratio {ratio}"
        );
        // The midpoint is a plain RK half step: its error is ~32x smaller than the double step's.
        let mid_err = (mid.1[0] - forced_exact(t0, y0, mid.0)).abs();
        assert!(mid_err < true_local, "h = {h}");
        last_ratio = ratio;
    }
    // And the estimate becomes asymptotically exact (ratio -> 1 as h -> 0).
    assert!(
        (0.95..=1.05).contains(&last_ratio),
        "ratio at the smallest h: {last_ratio}"
    );
}

#[test]
fn tolerance_sweep_reduces_global_error_monotonically() {
    let (t0, y0, t_end) = (0.0, 1.0, 10.0);
    let mut prev = f64::INFINITY;
    let mut prev_evals = 0;
    let (mut tols, mut worsts) = (Vec::new(), Vec::new());
    for p in 3..=9 {
        let tol = 10f64.powi(-p);
        let mut solver =
            England::<f64, 1>::new(cfg(tol, tol, 0.1, 1e-12, 10.0, 1_000_000)).unwrap();
        let mut y = [y0];
        let mut worst: f64 = 0.0;
        let stats = solver
            .integrate(&Forced, t0, &mut y, t_end, |t, y| {
                worst = worst.max((y[0] - forced_exact(t0, y0, t)).abs());
                ControlFlow::Continue(())
            })
            .unwrap();
        assert!(
            worst < prev,
            "tol {tol:e}: worst error {worst:e} not below {prev:e}"
        );
        // Within a modest factor of the tolerance (measured: 0.8x at 1e-3 .. 10x at 1e-9).
        assert!(worst <= 20.0 * tol, "tol {tol:e}: worst error {worst:e}");
        assert!(
            stats.rhs_evals > prev_evals,
            "tighter tolerance must cost more"
        );
        prev = worst;
        prev_evals = stats.rhs_evals;
        tols.push(tol);
        worsts.push(worst);
    }
    // Error-per-step control of a 4th-order result: local error ~ h^5 = tol, so the global
    // error ~ h^4 ~ tol^(4/5). The fitted exponent must be close to 0.8.
    let q = loglog_slope(&tols, &worsts);
    assert!(
        (0.7..=0.9).contains(&q),
        "global error ~ tol^{q}, errors {worsts:?}"
    );
}

#[test]
fn rhs_count_is_nine_per_accepted_and_seven_per_rejected_step() {
    let calls = core::cell::Cell::new(0);
    let sys = Counting {
        inner: Forced,
        calls: &calls,
    };
    // A first step far too large forces rejections.
    let mut solver = England::<f64, 1>::new(cfg(1e-8, 1e-8, 5.0, 1e-9, 5.0, 100_000)).unwrap();
    let mut y = [1.0];
    let stats = solver
        .integrate(&sys, 0.0, &mut y, 10.0, |_, _| ControlFlow::Continue(()))
        .unwrap();
    assert!(stats.rejected > 0, "{stats:?}");
    assert_eq!(stats.rhs_evals, calls.get());
    assert_eq!(
        stats.rhs_evals,
        9 * stats.accepted + 7 * stats.rejected,
        "{stats:?}"
    );
    assert_eq!(solver.stats(), stats);
}

#[test]
fn observer_sees_midpoints_and_end_points_in_order_and_lands_on_t_end() {
    let mut solver = England::<f64, 1>::new(cfg(1e-6, 1e-6, 0.3, 1e-9, 0.7, 100_000)).unwrap();
    let mut y = [1.0];
    let mut times = Vec::new();
    let stats = solver
        .integrate(&Forced, 0.0, &mut y, 3.3, |t, y| {
            assert!((y[0] - forced_exact(0.0, 1.0, t)).abs() < 1e-5);
            times.push(t);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(times.len() as u32, 1 + 2 * stats.accepted);
    assert_eq!(times.first(), Some(&0.0));
    assert_eq!(times.last(), Some(&3.3), "must land exactly on t_end");
    assert!(times.windows(2).all(|w| w[1] > w[0]));
    // Midpoints sit halfway between end points.
    for w in times.windows(3).step_by(2) {
        assert!((w[1] - 0.5 * (w[0] + w[2])).abs() < 1e-12);
    }
    assert!(times
        .windows(2)
        .all(|w| w[1] - w[0] <= 0.5 * 0.7 * 1.01 + 1e-12));

    // Break stops early and leaves y at the point observed.
    let mut solver = England::<f64, 1>::new(cfg(1e-6, 1e-6, 0.3, 1e-9, 0.7, 100_000)).unwrap();
    let mut y = [1.0];
    let mut seen = 0;
    let mut last = (0.0, 0.0);
    solver
        .integrate(&Forced, 0.0, &mut y, 3.3, |t, y| {
            seen += 1;
            last = (t, y[0]);
            if seen == 4 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        })
        .unwrap();
    assert_eq!(seen, 4);
    assert_eq!(y[0], last.1);
    assert!(last.0 < 3.3);
}

#[test]
fn step_never_passes_t_end_and_keeps_its_step_size_after_a_short_last_step() {
    let mut solver = England::<f64, 1>::new(cfg(1e-6, 1e-6, 0.01, 1e-9, 1.0, 100_000)).unwrap();
    let (mut t, mut y, mut mid) = (0.0, [1.0], (0.0, [0.0]));
    // Step to a series of close sample times, as a streaming caller does.
    for k in 1..=200 {
        let t_end = k as f64 * 0.05;
        while t < t_end {
            solver
                .step(&Forced, &mut t, &mut y, t_end, &mut mid)
                .unwrap();
            assert!(t <= t_end);
        }
        assert_eq!(t, t_end);
    }
    assert!((y[0] - forced_exact(0.0, 1.0, 10.0)).abs() < 1e-5);
    // Short steps forced by the sample times must not ratchet the step size down:
    // the solver keeps proposing steps at least as long as the sample interval.
    assert!(
        solver.step_size() >= 0.05,
        "step size {}",
        solver.step_size()
    );
    // step with nothing to do is an error, not a silent no-op.
    assert!(matches!(
        solver.step(&Forced, &mut t.clone(), &mut y, t, &mut mid),
        Err(Error::InvalidParameter { field: "t_end", .. })
    ));
}

#[test]
fn stiff_problem_exhausts_the_step_budget() {
    struct Stiff;
    impl OdeSystem<f64, 1> for Stiff {
        fn rhs(&self, t: f64, y: &[f64; 1], dydt: &mut [f64; 1]) {
            dydt[0] = -1e6 * (y[0] - t.cos());
        }
    }
    let mut solver = England::<f64, 1>::new(cfg(1e-6, 1e-6, 1e-3, 1e-12, 1.0, 50)).unwrap();
    let mut y = [1.0];
    match solver.integrate(&Stiff, 0.0, &mut y, 1.0, |_, _| ControlFlow::Continue(())) {
        Err(Error::StepBudgetExceeded { t, steps }) => {
            assert_eq!(steps, 50);
            assert!(t < 1.0);
        }
        other => panic!("expected StepBudgetExceeded, got {other:?}"),
    }
    assert_eq!(solver.stats().accepted + solver.stats().rejected, 50);
}

#[test]
fn nan_right_hand_side_is_non_finite_with_its_component() {
    struct Bad;
    impl OdeSystem<f64, 3> for Bad {
        fn rhs(&self, t: f64, y: &[f64; 3], dydt: &mut [f64; 3]) {
            dydt[0] = -y[0];
            dydt[1] = -y[1];
            dydt[2] = if t > 0.5 { f64::NAN } else { 1.0 };
        }
    }
    let mut solver = England::<f64, 3>::new(cfg(1e-6, 1e-6, 0.1, 1e-9, 0.1, 1000)).unwrap();
    let mut y = [1.0; 3];
    match solver.integrate(&Bad, 0.0, &mut y, 1.0, |_, _| ControlFlow::Continue(())) {
        Err(Error::NonFinite { t, component }) => {
            assert_eq!(component, 2);
            assert!(t > 0.5 && t <= 0.6 + 1e-12, "t = {t}");
        }
        other => panic!("expected NonFinite, got {other:?}"),
    }
    // A non-finite initial state is refused before any step.
    let mut y = [1.0, f64::INFINITY, 0.0];
    assert!(matches!(
        solver.integrate(&Bad, 0.0, &mut y, 1.0, |_, _| ControlFlow::Continue(())),
        Err(Error::NonFinite { component: 1, .. })
    ));
}

#[test]
fn tight_tolerance_with_large_h_min_underflows() {
    let mut solver = England::<f64, 1>::new(cfg(1e-14, 1e-14, 0.5, 0.5, 1.0, 1000)).unwrap();
    let mut y = [1.0];
    match solver.integrate(&Forced, 0.0, &mut y, 10.0, |_, _| ControlFlow::Continue(())) {
        Err(Error::StepSizeUnderflow { t, h }) => {
            assert_eq!(t, 0.0);
            assert_eq!(h, 0.5);
        }
        other => panic!("expected StepSizeUnderflow, got {other:?}"),
    }
}

#[test]
fn bad_configuration_names_the_field() {
    let good = cfg::<1>(1e-6, 1e-6, 0.1, 1e-6, 1.0, 100);
    assert!(England::new(good).is_ok());
    let field = |c: EnglandConfig<f64, 1>| match England::new(c) {
        Err(Error::InvalidParameter { field, .. }) => field,
        other => panic!("expected InvalidParameter, got {other:?}"),
    };
    assert_eq!(
        field(EnglandConfig {
            tol: Tolerance::scalar(-1.0, 1e-6),
            ..good
        }),
        "rtol"
    );
    assert_eq!(
        field(EnglandConfig {
            tol: Tolerance::scalar(f64::NAN, 1e-6),
            ..good
        }),
        "rtol"
    );
    assert_eq!(
        field(EnglandConfig {
            tol: Tolerance::scalar(1e-6, -1e-6),
            ..good
        }),
        "atol"
    );
    assert_eq!(
        field(EnglandConfig {
            tol: Tolerance::scalar(0.0, 0.0),
            ..good
        }),
        "atol"
    );
    assert_eq!(
        field(EnglandConfig {
            h_min: 0.0,
            h_init: 0.0,
            ..good
        }),
        "h_min"
    );
    assert_eq!(
        field(EnglandConfig {
            h_max: 1e-7,
            ..good
        }),
        "h_max"
    );
    assert_eq!(
        field(EnglandConfig {
            h_init: 2.0,
            ..good
        }),
        "h_init"
    );
    assert_eq!(
        field(EnglandConfig {
            h_init: 1e-7,
            ..good
        }),
        "h_init"
    );
    assert_eq!(
        field(EnglandConfig {
            max_steps: 0,
            ..good
        }),
        "max_steps"
    );
    // Per-component tolerances: one zero atol is fine with rtol > 0.
    let per = EnglandConfig {
        tol: Tolerance::per_component(1e-6, [0.0, 1e-3]),
        h_init: 0.1,
        h_min: 1e-6,
        h_max: 1.0,
        max_steps: 10,
    };
    assert!(England::<f64, 2>::new(per).is_ok());
    // Integration interval.
    let mut s = England::new(good).unwrap();
    let mut y = [1.0];
    assert!(matches!(
        s.integrate(&Forced, 1.0, &mut y, 0.0, |_, _| ControlFlow::Continue(())),
        Err(Error::InvalidParameter { field: "t_end", .. })
    ));
    assert!(matches!(
        rk4_integrate(&Forced, 0.0, &mut y, 1.0, 0, |_, _| ControlFlow::Continue(
            ()
        )),
        Err(Error::InvalidParameter { field: "steps", .. })
    ));
}

#[test]
fn single_precision_works_and_agrees_with_double() {
    let sys = Oscillator { w: 3.0 };
    let c32 = EnglandConfig {
        tol: Tolerance::scalar(1e-5f32, 1e-5),
        h_init: 0.05,
        h_min: 1e-6,
        h_max: 1.0,
        max_steps: 100_000,
    };
    let mut s32 = England::<f32, 2>::new(c32).unwrap();
    let mut y32 = [1.0f32, 0.0];
    let st32 = s32
        .integrate(&sys, 0.0, &mut y32, 2.0, |_, _| ControlFlow::Continue(()))
        .unwrap();
    let mut s64 = England::<f64, 2>::new(cfg(1e-5, 1e-5, 0.05, 1e-6, 1.0, 100_000)).unwrap();
    let mut y64 = [1.0f64, 0.0];
    let st64 = s64
        .integrate(&sys, 0.0, &mut y64, 2.0, |_, _| ControlFlow::Continue(()))
        .unwrap();
    let ex = (6.0f64).cos();
    assert!((f64::from(y32[0]) - ex).abs() < 1e-3, "f32 {}", y32[0]);
    assert!((y64[0] - ex).abs() < 1e-3, "f64 {}", y64[0]);
    assert!((f64::from(y32[0]) - y64[0]).abs() < 1e-3);
    // The same controller on the same problem takes (nearly) the same steps.
    assert!(
        st32.accepted.abs_diff(st64.accepted) <= 2,
        "{st32:?} vs {st64:?}"
    );
}

/// Fixed-fixed chain of 11 unit masses and springs (22 states, the size of the thesis's
/// model): x_i'' = x_{i-1} - 2 x_i + x_{i+1}.
struct Chain11;
impl OdeSystem<f64, 22> for Chain11 {
    fn rhs(&self, _t: f64, y: &[f64; 22], dydt: &mut [f64; 22]) {
        for i in 0..11 {
            let left = if i == 0 { 0.0 } else { y[i - 1] };
            let right = if i == 10 { 0.0 } else { y[i + 1] };
            dydt[i] = y[11 + i];
            dydt[11 + i] = left - 2.0 * y[i] + right;
        }
    }
}

#[test]
fn twenty_two_state_chain_follows_its_exact_normal_mode() {
    // Started in normal mode j, the chain moves as x_i(t) = sin(i j pi / 12) cos(w_j t),
    // w_j = 2 sin(j pi / 24).
    let j = 3.0;
    let shape = |i: usize| ((i as f64 + 1.0) * j * std::f64::consts::PI / 12.0).sin();
    let w = 2.0 * (j * std::f64::consts::PI / 24.0).sin();
    let mut y = [0.0; 22];
    for (i, yi) in y.iter_mut().take(11).enumerate() {
        *yi = shape(i);
    }
    let mut solver = England::<f64, 22>::new(cfg(1e-9, 1e-9, 0.1, 1e-9, 2.0, 1_000_000)).unwrap();
    let mut worst: f64 = 0.0;
    let stats = solver
        .integrate(&Chain11, 0.0, &mut y, 20.0, |t, y| {
            for i in 0..11 {
                worst = worst.max((y[i] - shape(i) * (w * t).cos()).abs());
                worst = worst.max((y[11 + i] + shape(i) * w * (w * t).sin()).abs());
            }
            ControlFlow::Continue(())
        })
        .unwrap();
    // Global error ~ tol^(4/5) over about 2.4 periods (measured 2e-7).
    assert!(
        worst < 1e-6,
        "worst deviation from the exact mode {worst:e}"
    );
    assert_eq!(stats.rhs_evals, 9 * stats.accepted + 7 * stats.rejected);
}
