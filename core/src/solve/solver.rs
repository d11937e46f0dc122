//! England's adaptive Runge-Kutta method (Appendix D, as corrected: docs/MODEL.md §3.16, §4.1) and a
//! classic fixed-step fourth-order Runge-Kutta for comparison.
//!
//! England's scheme (R. England, *Computer Journal* 12, 1969) takes a *double step*
//! `h = 2s` as two fourth-order Runge-Kutta half steps of size `s`, each with stages
//! chosen so that one extra derivative evaluation (`k9`) yields a fifth-order estimate
//! of the local error of the double step:
//!
//! ```text
//! k1 = s f(t0,        y0)
//! k2 = s f(t0 + s/2,  y0 + k1/2)
//! k3 = s f(t0 + s/2,  y0 + (k1 + k2)/4)
//! k4 = s f(t0 + s,    y0 - k2 + 2 k3)
//! y1 = y0 + (k1 + 4 k3 + k4)/6                      (midpoint, t0 + s)
//! k5..k8: the same from (t0 + s, y1)
//! y2 = y1 + (k5 + 4 k7 + k8)/6                      (end point, t0 + 2s)
//! k9 = s f(t0 + 2s, y0 + (-k1 - 96 k2 + 92 k3 - 121 k4 + 144 k5 + 6 k6 - 12 k7)/6)
//! E  = (-k1 + 4 k3 + 17 k4 - 23 k5 + 4 k7 - k9)/90  (≈ y(t0 + 2s) - y2)
//! ```
//!
//! `k8` does not enter `E`, so a rejected double step stops after `k7` and `k9`, and a
//! retry from the same point reuses `f(t0, y0)`. The cost is therefore exactly
//! `9 · accepted + 7 · rejected` right-hand-side evaluations (see [`SolverStats`]).
//!
//! All step sizes in [`EnglandConfig`] and [`England::step_size`] are *double*-step
//! sizes `h`: one accepted step advances time by `h`, with the midpoint at `h/2`.
//!
//! Opt-in extras (the defaults reproduce the original solver bit for bit):
//! - [`England::with_control`] takes a [`StepControl`]: a PI step-size controller,
//!   Hairer's starting step, and a cap on the step from the stiffest eigenvalue
//!   ([`StiffnessCap`](crate::StiffnessCap)), for problems whose step is held by stability
//!   rather than accuracy.
//! - [`England::integrate_dense`] passes each accepted step's continuous extension
//!   [`Dense`] (a quintic Hermite interpolant, globally as accurate as the steps).

use core::ops::ControlFlow;

use crate::{
    initial_step, spectral_radius, Controller, Error, InitialStep, Real, Result, StepControl,
};

/// A system of first-order ordinary differential equations `dy/dt = f(t, y)` with
/// `N` components, as integrated by [`England`] and [`rk4_integrate`].
pub trait OdeSystem<T: Real, const N: usize> {
    /// dy/dt = f(t, y): writes the derivative of every component into `dydt`.
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]);

    /// An estimate of the spectral radius of the Jacobian `∂f/∂y` at `(t, y)` (the
    /// modulus of the stiffest eigenvalue, 1/s), if the system knows one; used only by
    /// [`StiffnessCap`](crate::StiffnessCap) (which otherwise estimates it by power
    /// iteration). The default knows none.
    fn spectral_radius(&self, t: T, y: &[T; N]) -> Option<T> {
        let _ = (t, y);
        None
    }
}

/// Error tolerance of [`England`]: component `i` of a double step is accepted when
/// `|E_i| <= atol_i + rtol · max(|y_i(t0)|, |ŷ2_i|)`, ŷ2 England's auxiliary end-point
/// estimate (Appendix D's "absolute error + relative error · y"; docs/MODEL.md §3.16).
#[derive(Clone, Copy, Debug)]
pub struct Tolerance<T, const N: usize> {
    /// Relative tolerance (dimensionless), shared by all components.
    pub rtol: T,
    /// Absolute tolerance per component, in that component's units.
    pub atol: [T; N],
}

impl<T: Real, const N: usize> Tolerance<T, N> {
    /// The same absolute tolerance for every component.
    pub fn scalar(rtol: T, atol: T) -> Self {
        Self {
            rtol,
            atol: [atol; N],
        }
    }

    /// One absolute tolerance per component (for states of different units).
    pub fn per_component(rtol: T, atol: [T; N]) -> Self {
        Self { rtol, atol }
    }
}

/// Settings of [`England`]; every step size is a double-step size (time advanced by one
/// accepted step).
#[derive(Clone, Copy, Debug)]
pub struct EnglandConfig<T, const N: usize> {
    /// Error tolerance of each double step.
    pub tol: Tolerance<T, N>,
    /// First double-step size tried.
    pub h_init: T,
    /// Smallest double-step size allowed; a rejection at this size is
    /// [`Error::StepSizeUnderflow`]. (Only the last step before an end time may be shorter.)
    pub h_min: T,
    /// Largest double-step size allowed (the last step before an end time may stretch it
    /// by at most 1 % to land on the end time instead of leaving a sliver).
    pub h_max: T,
    /// Budget of attempted double steps (accepted plus rejected) since the last
    /// [`England::integrate`] or [`England::reset`]; using it up is
    /// [`Error::StepBudgetExceeded`].
    pub max_steps: u32,
}

/// Work counters of an integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SolverStats {
    /// Accepted (double) steps.
    pub accepted: u32,
    /// Rejected (double) steps.
    pub rejected: u32,
    /// Right-hand-side evaluations. For [`England`] this is exactly
    /// `9 · accepted + 7 · rejected` after a successful run: an accepted double step costs
    /// `k1..k9`; a rejected one `k2..k7` and `k9` (it stops before `k8`, and the retry
    /// from the same point reuses `f(t0, y0)`), plus the [`England::auxiliary_evals`] of
    /// an opt-in step control or dense output (zero with [`England::new`] and
    /// [`England::integrate`]). For [`rk4_integrate`] it is `4 · steps`.
    pub rhs_evals: u32,
}

/// England's adaptive Runge-Kutta integrator (the thesis's "modified Runge-Kutta
/// algorithm", Appendix D) for a system of `N` first-order equations.
///
/// It keeps its stage buffers and its step-size controller between calls, so one
/// instance can be reused for many integrations (or stepped indefinitely with
/// [`England::step`]) without allocating.
///
/// Error control per double step of size `h` (the scale uses the start value and
/// England's auxiliary end-point estimate `ŷ2`, the argument of `k9`, because `y2`
/// itself needs `k8`, which is evaluated only after acceptance):
///
/// `err = max_i |E_i| / (atol_i + rtol · max(|y0_i|, |ŷ2_i|))`, accepted if `err <= 1`;
/// the next size is `h · clamp(0.9 · err^(-1/5), 0.2, 5)` (no growth right after a
/// rejection), clamped to `[h_min, h_max]`.
///
/// # Example: your own ODE
///
/// A unit harmonic oscillator `x'' = -x` as the first-order system `(x, v)`; its energy
/// `(x² + v²)/2` must stay at its initial value 1/2.
///
/// ```
/// use core::ops::ControlFlow;
/// use camsim_core::{England, EnglandConfig, OdeSystem, Tolerance};
///
/// struct Oscillator;
/// impl OdeSystem<f64, 2> for Oscillator {
///     fn rhs(&self, _t: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
///         dydt[0] = y[1];
///         dydt[1] = -y[0];
///     }
/// }
///
/// let mut solver = England::new(EnglandConfig {
///     tol: Tolerance::scalar(1e-10, 1e-10),
///     h_init: 0.1,
///     h_min: 1e-9,
///     h_max: 1.0,
///     max_steps: 100_000,
/// })?;
/// let mut y = [1.0, 0.0];
/// let mut worst_energy_error: f64 = 0.0;
/// let stats = solver.integrate(&Oscillator, 0.0, &mut y, 10.0, |_t, y| {
///     let energy = 0.5 * (y[0] * y[0] + y[1] * y[1]);
///     worst_energy_error = worst_energy_error.max((energy - 0.5).abs());
///     ControlFlow::Continue(())
/// })?;
/// assert!(worst_energy_error < 1e-8, "energy drift {worst_energy_error}");
/// // Global error grows like tol^(4/5) times the interval (error per step is controlled).
/// assert!((y[0] - 10.0f64.cos()).abs() < 1e-7);
/// assert_eq!(stats.rhs_evals, 9 * stats.accepted + 7 * stats.rejected);
/// # Ok::<(), camsim_core::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct England<T, const N: usize> {
    config: EnglandConfig<T, N>,
    /// Next double-step size to try.
    h: T,
    stats: SolverStats,
    // Stage buffers (each already multiplied by the half step s).
    f0: [T; N],
    k1: [T; N],
    k2: [T; N],
    k3: [T; N],
    k4: [T; N],
    k5: [T; N],
    k6: [T; N],
    k7: [T; N],
    /// k9, then reused for k8 after acceptance.
    k9: [T; N],
    /// Argument of the stage being evaluated.
    arg: [T; N],
    /// Step-size control beyond the configuration ([`StepControl::classic`] by default).
    control: StepControl<T>,
    /// Double-step cap from the last stiffness estimate (`T::MAX`: none).
    h_cap: T,
    /// Last spectral-radius estimate (NaN: none yet).
    rho: T,
    /// Accepted steps since the last stiffness estimate.
    since_estimate: u32,
    /// A stiffness estimate is due at the next step.
    estimate_due: bool,
    /// Hairer's starting step is due at the next step.
    initial_due: bool,
    /// Right-hand-side evaluations outside the `9 · accepted + 7 · rejected` of the steps.
    aux_evals: u32,
    /// Power-iteration vector, kept for a warm start.
    power_v: [T; N],
}

/// One attempted double step of [`England::step_impl`].
#[derive(Clone, Copy, Debug)]
struct Attempt<T> {
    /// Error ratio.
    err: T,
    /// Half step.
    s: T,
    /// End time of the attempt.
    t_end: T,
    /// Accepted (else rejected, with `once`).
    accepted: bool,
}

/// Evaluates `out = scale · f(t, arg)` and checks that it is finite.
#[inline(always)]
fn stage<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    arg: &[T; N],
    scale: T,
    out: &mut [T; N],
    evals: &mut u32,
) -> Result<()> {
    sys.rhs(t, arg, out);
    *evals = evals.saturating_add(1);
    for (i, o) in out.iter_mut().enumerate() {
        *o *= scale;
        if !o.is_finite() {
            return Err(Error::NonFinite {
                t: t.to_f64(),
                component: i,
            });
        }
    }
    Ok(())
}

/// Index of the first non-finite component, if any.
#[inline]
fn first_non_finite<T: Real, const N: usize>(y: &[T; N]) -> Option<usize> {
    y.iter().position(|v| !v.is_finite())
}

impl<T: Real, const N: usize> England<T, N> {
    /// Checks the configuration and builds a solver whose first double step is `h_init`,
    /// with England's original step-size rule ([`StepControl::classic`]).
    pub fn new(config: EnglandConfig<T, N>) -> Result<Self> {
        Self::with_control(config, StepControl::classic())
    }

    /// Like [`England::new`] with the given step-size control (PI controller, Hairer's
    /// starting step, stiffness cap); `StepControl::classic()` is exactly [`England::new`].
    ///
    /// ```
    /// use camsim_core::{England, EnglandConfig, StepControl, Tolerance};
    /// let config = EnglandConfig::<f64, 2> {
    ///     tol: Tolerance::scalar(1e-8, 1e-8),
    ///     h_init: 1e-3,
    ///     h_min: 1e-12,
    ///     h_max: 0.1,
    ///     max_steps: 1_000_000,
    /// };
    /// let solver = England::with_control(config, StepControl::pi_capped())?;
    /// # Ok::<(), camsim_core::Error>(())
    /// ```
    pub fn with_control(config: EnglandConfig<T, N>, control: StepControl<T>) -> Result<Self> {
        control.validate()?;
        let tol = config.tol;
        if !(tol.rtol.is_finite() && tol.rtol >= T::ZERO) {
            return Err(Error::InvalidParameter {
                field: "rtol",
                rule: "must be zero or positive and finite",
                value: tol.rtol.to_f64(),
            });
        }
        for &a in tol.atol.iter() {
            if !(a.is_finite() && a >= T::ZERO) {
                return Err(Error::InvalidParameter {
                    field: "atol",
                    rule: "must be zero or positive and finite",
                    value: a.to_f64(),
                });
            }
            if a == T::ZERO && tol.rtol == T::ZERO {
                return Err(Error::InvalidParameter {
                    field: "atol",
                    rule: "atol and rtol must not both be zero",
                    value: 0.0,
                });
            }
        }
        if !(config.h_min.is_finite() && config.h_min > T::ZERO) {
            return Err(Error::InvalidParameter {
                field: "h_min",
                rule: "must be positive and finite",
                value: config.h_min.to_f64(),
            });
        }
        if !(config.h_max.is_finite() && config.h_max >= config.h_min) {
            return Err(Error::InvalidParameter {
                field: "h_max",
                rule: "must be finite and at least h_min",
                value: config.h_max.to_f64(),
            });
        }
        if !(config.h_init >= config.h_min && config.h_init <= config.h_max) {
            return Err(Error::InvalidParameter {
                field: "h_init",
                rule: "must lie within [h_min, h_max]",
                value: config.h_init.to_f64(),
            });
        }
        if config.max_steps == 0 {
            return Err(Error::InvalidParameter {
                field: "max_steps",
                rule: "must be positive",
                value: 0.0,
            });
        }
        let z = [T::ZERO; N];
        Ok(Self {
            config,
            h: config.h_init,
            stats: SolverStats::default(),
            f0: z,
            k1: z,
            k2: z,
            k3: z,
            k4: z,
            k5: z,
            k6: z,
            k7: z,
            k9: z,
            arg: z,
            control,
            h_cap: T::MAX,
            rho: T::NAN,
            since_estimate: 0,
            estimate_due: true,
            initial_due: control.initial_step == InitialStep::Hairer,
            aux_evals: 0,
            power_v: z,
        })
    }

    /// The step-size control it was built with.
    pub fn control(&self) -> &StepControl<T> {
        &self.control
    }

    /// The last spectral-radius estimate of the stiffness cap (`None` without a cap or
    /// before the first step).
    pub fn spectral_radius(&self) -> Option<T> {
        if self.rho.is_nan() {
            None
        } else {
            Some(self.rho)
        }
    }

    /// The current double-step cap of the stiffness cap (`None` without one).
    pub fn step_cap(&self) -> Option<T> {
        if self.control.stiffness_cap.is_some() && self.h_cap < T::MAX {
            Some(self.h_cap)
        } else {
            None
        }
    }

    /// Right-hand-side evaluations since the counters were last reset that are not part of
    /// the `9 · accepted + 7 · rejected` of the steps themselves (included in
    /// [`SolverStats::rhs_evals`]): Hairer's starting step (1), stiffness estimates
    /// (1 + iterations each) and the end-point derivative of [`England::integrate_dense`] (1).
    /// Zero with [`StepControl::classic`] and [`England::integrate`].
    pub fn auxiliary_evals(&self) -> u32 {
        self.aux_evals
    }

    /// Asks for a new stiffness estimate at the next step (after the caller changed the
    /// system, for example); no effect without a [`StiffnessCap`](crate::StiffnessCap).
    pub fn refresh_stiffness(&mut self) {
        self.estimate_due = true;
    }

    /// The configuration it was built with.
    pub fn config(&self) -> &EnglandConfig<T, N> {
        &self.config
    }

    /// Work counters since the last [`England::integrate`] started (or [`England::reset`]).
    pub fn stats(&self) -> SolverStats {
        self.stats
    }

    /// The next double-step size it will try.
    pub fn step_size(&self) -> T {
        self.h
    }

    /// Forgets the controller's history: the next step tries `h_init` (or Hairer's
    /// starting step, with [`InitialStep::Hairer`]) and the counters (and so the step
    /// budget) restart from zero; a PI controller forgets its previous error and the
    /// stiffness cap starts over from a fresh estimate.
    pub fn reset(&mut self) {
        self.h = self.config.h_init;
        self.stats = SolverStats::default();
        self.aux_evals = 0;
        if let Controller::Pi(pi) = &mut self.control.controller {
            pi.reset();
        }
        self.h_cap = T::MAX;
        self.rho = T::NAN;
        self.since_estimate = 0;
        self.estimate_due = true;
        self.initial_due = self.control.initial_step == InitialStep::Hairer;
        self.power_v = [T::ZERO; N];
    }

    /// Hairer's starting step and the stiffness estimate, when due, from `f0 = f(t0, y0)`.
    fn prepare<S: OdeSystem<T, N>>(&mut self, sys: &S, t0: T, y: &[T; N]) -> Result<()> {
        let before = self.stats.rhs_evals;
        if let Some(cap) = self.control.stiffness_cap {
            // Periodic estimates only while the cap may bind (the planned step within a
            // factor 2 of it); rejections ask for one through `estimate_due`.
            let periodic =
                self.since_estimate >= cap.refresh_every && self.h >= T::HALF * self.h_cap;
            if self.estimate_due || periodic {
                let rho = match sys.spectral_radius(t0, y) {
                    Some(r) if r.is_finite() && r >= T::ZERO => r,
                    _ if cap.max_iterations > 0 => spectral_radius(
                        sys,
                        t0,
                        y,
                        &self.f0,
                        &self.config.tol,
                        &mut self.power_v,
                        cap.max_iterations,
                        cap.rel_tol,
                        &mut self.stats.rhs_evals,
                    )?,
                    _ => T::NAN,
                };
                self.rho = rho;
                self.h_cap = cap.h_cap(rho);
                self.since_estimate = 0;
                self.estimate_due = false;
            }
        }
        if self.initial_due {
            self.initial_due = false;
            let h = initial_step(
                sys,
                t0,
                y,
                &self.f0,
                &self.config.tol,
                4,
                self.config.h_max,
                &mut self.stats.rhs_evals,
            )?;
            self.h = h.clamp(self.config.h_min, self.config.h_max);
        }
        self.aux_evals = self
            .aux_evals
            .saturating_add(self.stats.rhs_evals.saturating_sub(before));
        Ok(())
    }

    /// Advances one accepted double step (retrying rejected ones), never past `t_end`;
    /// returns the midpoint `(t + s, y1)` through `mid` and leaves `(t, y)` at the end point;
    /// returns the error ratio `err <= 1` of the accepted step.
    ///
    /// The step is shortened to land exactly on `t_end` when that is at most 1 % beyond the
    /// next step; if `t_end` is less than two steps away the remaining interval is halved
    /// instead of leaving a sliver. Counters accumulate across calls (the budget
    /// `max_steps` applies to them; see [`England::reset`]). On error, `(t, y)` are left
    /// at the start of the failed step and `mid` is unspecified.
    pub fn step<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t: &mut T,
        y: &mut [T; N],
        t_end: T,
        mid: &mut (T, [T; N]),
    ) -> Result<T> {
        self.step_impl(sys, t, y, t_end, mid, false, false, false, false)
            .map(|a| a.err)
    }

    /// [`England::step`]; `f0_ready`: `self.f0` already holds `f(t, y)`; `once`: return
    /// after a rejected attempt too (`(t, y)` unchanged, `mid` its midpoint, `self.arg`
    /// its auxiliary end point ŷ2, `self.k5` and `self.k9` `s f` at those, `self.h` the
    /// size of the retry). Returns the attempt's error ratio, half step, end time and
    /// whether it was accepted. `once` with `once_rejected`: an earlier attempt from the
    /// same point was rejected (the retry then does not grow the step, as within one call).
    /// `force`: accept whatever the error (a step across a located event of at most a
    /// couple of event tolerances, whose error the event's bracket bounds, not the step).
    #[allow(clippy::too_many_arguments)]
    fn step_impl<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t: &mut T,
        y: &mut [T; N],
        t_end: T,
        mid: &mut (T, [T; N]),
        f0_ready: bool,
        once: bool,
        once_rejected: bool,
        force: bool,
    ) -> Result<Attempt<T>> {
        let t0 = *t;
        if !t0.is_finite() {
            return Err(Error::InvalidParameter {
                field: "t",
                rule: "must be finite",
                value: t0.to_f64(),
            });
        }
        if !(t_end.is_finite() && t_end > t0) {
            return Err(Error::InvalidParameter {
                field: "t_end",
                rule: "must be finite and later than the current time",
                value: t_end.to_f64(),
            });
        }
        if let Some(i) = first_non_finite(y) {
            return Err(Error::NonFinite {
                t: t0.to_f64(),
                component: i,
            });
        }
        // f(t0, y0), shared by every attempt from this point.
        if !f0_ready {
            stage(sys, t0, y, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
        }
        let capped = self.control.stiffness_cap.is_some();

        let (h_min, h_max, max_steps, rtol) = (
            self.config.h_min,
            self.config.h_max,
            self.config.max_steps,
            self.config.tol.rtol,
        );
        let c90 = T::from_f64(1.0 / 90.0);
        let sixth = T::from_f64(1.0 / 6.0);
        let quarter = T::from_f64(0.25);
        let safety = T::from_f64(0.9);
        let neg_fifth = T::from_f64(-0.2);
        let fac_min = T::from_f64(0.2);
        let fac_max = T::from_f64(5.0);
        let stretch = T::from_f64(1.01);
        let mut rejected_here = once && once_rejected;

        loop {
            let steps = self.stats.accepted.saturating_add(self.stats.rejected);
            if steps >= max_steps {
                return Err(Error::StepBudgetExceeded {
                    t: t0.to_f64(),
                    steps,
                });
            }

            // Starting step and stiffness estimate when due (never with the classic control).
            if capped || self.initial_due {
                self.prepare(sys, t0, y)?;
            }

            // Choose this attempt's double step h, shortened near t_end.
            let h_plan = if capped {
                self.h.min(self.h_cap).max(h_min)
            } else {
                self.h
            };
            let remaining = t_end - t0;
            let (h, last) = if remaining <= h_plan * stretch {
                (remaining, true)
            } else if remaining < h_plan + h_plan {
                (remaining * T::HALF, false)
            } else {
                (h_plan, false)
            };
            let clipped = h < h_plan;
            let s = h * T::HALF;
            let s2 = s * T::HALF;
            let t_mid = t0 + s;
            let t_end_step = if last { t_end } else { t0 + h };

            // First half step: k1..k4 and y1 (written straight into `mid`).
            for (i, (k, f)) in self.k1.iter_mut().zip(self.f0.iter()).enumerate() {
                *k = s * *f;
                if !k.is_finite() {
                    return Err(Error::NonFinite {
                        t: t0.to_f64(),
                        component: i,
                    });
                }
            }
            for ((a, y0), k1) in self.arg.iter_mut().zip(y.iter()).zip(self.k1.iter()) {
                *a = *y0 + T::HALF * *k1;
            }
            stage(
                sys,
                t0 + s2,
                &self.arg,
                s,
                &mut self.k2,
                &mut self.stats.rhs_evals,
            )?;
            for (((a, y0), k1), k2) in self
                .arg
                .iter_mut()
                .zip(y.iter())
                .zip(self.k1.iter())
                .zip(self.k2.iter())
            {
                *a = *y0 + quarter * (*k1 + *k2);
            }
            stage(
                sys,
                t0 + s2,
                &self.arg,
                s,
                &mut self.k3,
                &mut self.stats.rhs_evals,
            )?;
            for (((a, y0), k2), k3) in self
                .arg
                .iter_mut()
                .zip(y.iter())
                .zip(self.k2.iter())
                .zip(self.k3.iter())
            {
                *a = *y0 - *k2 + T::TWO * *k3;
            }
            stage(
                sys,
                t_mid,
                &self.arg,
                s,
                &mut self.k4,
                &mut self.stats.rhs_evals,
            )?;
            let y1 = &mut mid.1;
            for ((((m, y0), k1), k3), k4) in y1
                .iter_mut()
                .zip(y.iter())
                .zip(self.k1.iter())
                .zip(self.k3.iter())
                .zip(self.k4.iter())
            {
                *m = *y0 + sixth * (*k1 + T::from_f64(4.0) * *k3 + *k4);
            }
            if let Some(i) = first_non_finite(y1) {
                return Err(Error::NonFinite {
                    t: t_mid.to_f64(),
                    component: i,
                });
            }

            // Second half step up to k7, then England's k9.
            stage(sys, t_mid, y1, s, &mut self.k5, &mut self.stats.rhs_evals)?;
            for ((a, m), k5) in self.arg.iter_mut().zip(y1.iter()).zip(self.k5.iter()) {
                *a = *m + T::HALF * *k5;
            }
            stage(
                sys,
                t_mid + s2,
                &self.arg,
                s,
                &mut self.k6,
                &mut self.stats.rhs_evals,
            )?;
            for (((a, m), k5), k6) in self
                .arg
                .iter_mut()
                .zip(y1.iter())
                .zip(self.k5.iter())
                .zip(self.k6.iter())
            {
                *a = *m + quarter * (*k5 + *k6);
            }
            stage(
                sys,
                t_mid + s2,
                &self.arg,
                s,
                &mut self.k7,
                &mut self.stats.rhs_evals,
            )?;
            // Nine arrays of length N in step (zipped: no index, no bounds check).
            for ((((((((a, y0), k1), k2), k3), k4), k5), k6), k7) in self
                .arg
                .iter_mut()
                .zip(y.iter())
                .zip(self.k1.iter())
                .zip(self.k2.iter())
                .zip(self.k3.iter())
                .zip(self.k4.iter())
                .zip(self.k5.iter())
                .zip(self.k6.iter())
                .zip(self.k7.iter())
            {
                *a = *y0
                    + sixth
                        * (-*k1 - T::from_f64(96.0) * *k2 + T::from_f64(92.0) * *k3
                            - T::from_f64(121.0) * *k4
                            + T::from_f64(144.0) * *k5
                            + T::from_f64(6.0) * *k6
                            - T::from_f64(12.0) * *k7);
            }
            stage(
                sys,
                t_end_step,
                &self.arg,
                s,
                &mut self.k9,
                &mut self.stats.rhs_evals,
            )?;

            // Error ratio from E = (-k1 + 4k3 + 17k4 - 23k5 + 4k7 - k9)/90.
            let mut err = T::ZERO;
            for (i, ((((((((k1, k3), k4), k5), k7), k9), atol), y0), a)) in self
                .k1
                .iter()
                .zip(self.k3.iter())
                .zip(self.k4.iter())
                .zip(self.k5.iter())
                .zip(self.k7.iter())
                .zip(self.k9.iter())
                .zip(self.config.tol.atol.iter())
                .zip(y.iter())
                .zip(self.arg.iter())
                .enumerate()
            {
                let e = c90
                    * (-*k1 + T::from_f64(4.0) * *k3 + T::from_f64(17.0) * *k4
                        - T::from_f64(23.0) * *k5
                        + T::from_f64(4.0) * *k7
                        - *k9);
                let scale = *atol + rtol * y0.abs().max(a.abs());
                if !e.is_finite() {
                    return Err(Error::NonFinite {
                        t: t_end_step.to_f64(),
                        component: i,
                    });
                }
                let e = e.abs();
                let r = if scale > T::ZERO {
                    e / scale
                } else if e == T::ZERO {
                    T::ZERO
                } else {
                    T::INFINITY
                };
                err = err.max(r);
            }
            if let Some(p) = &self.control.per_unit_step {
                err = p.ratio(err, h, rtol);
            }
            // err^(-1/5) step factor (k's are finite, so err is not NaN; it may be +inf).
            let fac_raw = if err > T::ZERO {
                safety * err.powf(neg_fifth)
            } else {
                T::MAX
            };

            if err <= T::ONE || force {
                // Accepted: k8 (into the k9 buffer) and y2 (in place of y0).
                for (((a, m), k6), k7) in self
                    .arg
                    .iter_mut()
                    .zip(mid.1.iter())
                    .zip(self.k6.iter())
                    .zip(self.k7.iter())
                {
                    *a = *m - *k6 + T::TWO * *k7;
                }
                stage(
                    sys,
                    t_end_step,
                    &self.arg,
                    s,
                    &mut self.k9,
                    &mut self.stats.rhs_evals,
                )?;
                for ((((y2, m), k5), k7), k8) in y
                    .iter_mut()
                    .zip(mid.1.iter())
                    .zip(self.k5.iter())
                    .zip(self.k7.iter())
                    .zip(self.k9.iter())
                {
                    *y2 = *m + sixth * (*k5 + T::from_f64(4.0) * *k7 + *k8);
                }
                if let Some(i) = first_non_finite(y) {
                    // Restoring y0 would need a copy on every step; report instead.
                    return Err(Error::NonFinite {
                        t: t_end_step.to_f64(),
                        component: i,
                    });
                }
                self.stats.accepted = self.stats.accepted.saturating_add(1);
                mid.0 = t_mid;
                *t = t_end_step;

                let (fac, fac_unbounded) = match &mut self.control.controller {
                    Controller::Classic => {
                        let fac_cap = if rejected_here { T::ONE } else { fac_max };
                        let fac_unbounded = if rejected_here {
                            fac_raw.min(T::ONE)
                        } else {
                            fac_raw
                        };
                        (fac_raw.clamp(fac_min, fac_cap), fac_unbounded)
                    }
                    Controller::Pi(pi) => pi.accept_raw(err, rejected_here),
                };
                let mut h_next = h * fac;
                if clipped {
                    // A step shortened to meet t_end says nothing against the planned size.
                    let h_ok = if fac_unbounded >= h_plan / h {
                        h_plan
                    } else {
                        h * fac_unbounded
                    };
                    h_next = h_next.max(h_ok);
                }
                self.h = h_next.clamp(h_min, h_max);
                if capped {
                    self.since_estimate = self.since_estimate.saturating_add(1);
                    self.h = self.h.min(self.h_cap).max(h_min);
                }
                return Ok(Attempt {
                    err,
                    s,
                    t_end: t_end_step,
                    accepted: true,
                });
            }

            // Rejected: shrink and retry from the same point.
            self.stats.rejected = self.stats.rejected.saturating_add(1);
            if h <= h_min {
                return Err(Error::StepSizeUnderflow {
                    t: t0.to_f64(),
                    h: h.to_f64(),
                });
            }
            rejected_here = true;
            let fac = match &mut self.control.controller {
                Controller::Classic => fac_raw.clamp(fac_min, T::ONE),
                Controller::Pi(pi) => pi.reject(err),
            };
            if let Some(cap) = &self.control.stiffness_cap {
                // Rejected at the cap, or near it long after the last estimate, or very long
                // after it (the stiffness may have grown past the cap): it may be stale.
                let k = cap.refresh_every;
                let since = self.since_estimate;
                if h >= T::from_f64(0.99) * self.h_cap
                    || (since >= k && h >= T::HALF * self.h_cap)
                    || since >= k.saturating_mul(4)
                {
                    self.estimate_due = true;
                }
            }
            self.h = (h * fac).max(h_min);
            if once {
                return Ok(Attempt {
                    err,
                    s,
                    t_end: t_end_step,
                    accepted: false,
                });
            }
        }
    }

    /// Resets the statistics for a new integration from (t0, y) to t_end and checks both
    /// ends and the state (shared by [`Self::integrate`] and [`Self::integrate_dense`]).
    fn begin(&mut self, t0: T, y: &[T; N], t_end: T) -> Result<()> {
        self.stats = SolverStats::default();
        self.aux_evals = 0;
        self.estimate_due = true;
        if !t0.is_finite() {
            return Err(Error::InvalidParameter {
                field: "t0",
                rule: "must be finite",
                value: t0.to_f64(),
            });
        }
        if !(t_end.is_finite() && t_end >= t0) {
            return Err(Error::InvalidParameter {
                field: "t_end",
                rule: "must be finite and not before t0",
                value: t_end.to_f64(),
            });
        }
        if let Some(i) = first_non_finite(y) {
            return Err(Error::NonFinite {
                t: t0.to_f64(),
                component: i,
            });
        }
        Ok(())
    }
    /// Integrates from `t0` to `t_end`, calling `observer(t, &y)` at the start, at every
    /// midpoint and end point of each accepted double step (in time order); the observer
    /// returns [`ControlFlow::Break`] to stop early (still `Ok`). Starts from the current
    /// [`England::step_size`] (`h_init` for a new solver), resets the counters and returns
    /// those of this run; `y` is left at the last point reached.
    pub fn integrate<S: OdeSystem<T, N>, F: FnMut(T, &[T; N]) -> ControlFlow<()>>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut observer: F,
    ) -> Result<SolverStats> {
        self.begin(t0, y, t_end)?;
        if observer(t0, y).is_break() {
            return Ok(self.stats);
        }
        let mut t = t0;
        let mut mid = (t0, [T::ZERO; N]);
        while t < t_end {
            self.step(sys, &mut t, y, t_end, &mut mid)?;
            if observer(mid.0, &mid.1).is_break() {
                // The caller stopped at the midpoint: leave y there.
                *y = mid.1;
                break;
            }
            if observer(t, y).is_break() {
                break;
            }
        }
        Ok(self.stats)
    }

    /// Integrates from `t0` to `t_end` like [`England::integrate`], calling
    /// `observer(&dense)` once per accepted double step with its continuous extension
    /// [`Dense`], which evaluates the solution anywhere in the step (in time order; the
    /// observer returns [`ControlFlow::Break`] to stop early, still `Ok`, with `y` at the
    /// end of that step). No call if `t_end == t0`. Starts from the current
    /// [`England::step_size`], resets the counters and returns those of this run.
    ///
    /// The points `y` passes through are bit for bit those of [`England::integrate`]; the
    /// extension needs `f` at each step's end, which is the next step's first stage, so
    /// the only extra cost is one evaluation at the very end:
    /// `rhs_evals = 9 · accepted + 7 · rejected + 1` (plus the
    /// [`England::auxiliary_evals`] of the step control).
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use camsim_core::{England, EnglandConfig, OdeSystem, Tolerance};
    ///
    /// struct Decay;
    /// impl OdeSystem<f64, 1> for Decay {
    ///     fn rhs(&self, _t: f64, y: &[f64; 1], dydt: &mut [f64; 1]) {
    ///         dydt[0] = -y[0];
    ///     }
    /// }
    /// let mut solver = England::new(EnglandConfig {
    ///     tol: Tolerance::scalar(1e-9, 1e-12),
    ///     h_init: 0.01,
    ///     h_min: 1e-9,
    ///     h_max: 0.5,
    ///     max_steps: 100_000,
    /// })?;
    /// // Sample on a uniform grid, independent of the steps taken.
    /// let mut next = 0.0;
    /// let mut worst: f64 = 0.0;
    /// let mut out = [0.0];
    /// solver.integrate_dense(&Decay, 0.0, &mut [1.0], 3.0, |d| {
    ///     while next <= d.t_end() {
    ///         d.eval(next, &mut out);
    ///         worst = worst.max((out[0] - (-next).exp()).abs());
    ///         next += 0.01;
    ///     }
    ///     ControlFlow::Continue(())
    /// })?;
    /// assert!(next > 3.0 && worst < 1e-8, "{worst}");
    /// # Ok::<(), camsim_core::Error>(())
    /// ```
    pub fn integrate_dense<S, F>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut observer: F,
    ) -> Result<SolverStats>
    where
        S: OdeSystem<T, N>,
        F: FnMut(&Dense<'_, T, N>) -> ControlFlow<()>,
    {
        self.begin(t0, y, t_end)?;
        if t_end == t0 {
            return Ok(self.stats);
        }
        stage(sys, t0, y, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
        let mut t = t0;
        let mut mid = (t0, [T::ZERO; N]);
        let mut f1 = [T::ZERO; N];
        let mut f2 = [T::ZERO; N];
        while t < t_end {
            let t_start = t;
            let y0 = *y;
            let f0 = self.f0;
            let s = self
                .step_impl(sys, &mut t, y, t_end, &mut mid, true, false, false, false)?
                .s;
            // f(t1, y1) = k5 / s; f(t2, y2) is the next step's f(t0, y0).
            for (a, k5) in f1.iter_mut().zip(self.k5.iter()) {
                *a = *k5 / s;
            }
            stage(sys, t, y, T::ONE, &mut f2, &mut self.stats.rhs_evals)?;
            self.f0 = f2;
            let dense = Dense::new([t_start, mid.0, t], [&y0, &mid.1, y], [&f0, &f1, &f2])?;
            if observer(&dense).is_break() {
                // f(t, y) was evaluated for a next step that will not come.
                self.aux_evals = self.aux_evals.saturating_add(1);
                return Ok(self.stats);
            }
        }
        self.aux_evals = self.aux_evals.saturating_add(1);
        Ok(self.stats)
    }

    /// Integrates from `t0` to `t_end` like [`England::integrate_dense`], and locates the
    /// changes of side of the event function `event` (`g > 0` against `g <= 0`) and
    /// restarts the integration there (opt-in; [`England::integrate`] and
    /// [`England::integrate_dense`] are unchanged by it).
    ///
    /// After each accepted step `g` is evaluated at its end (one evaluation of `g` per
    /// step; a pair of crossings within one step goes unseen). When the side changed,
    /// the root is located on the step's quintic Hermite extension ([`Dense`]) to within
    /// [`EventConfig::tol_t`] by the Illinois method (bisection when it stalls); the
    /// step is then discarded (its evaluations stay counted) and the solution
    /// re-integrated from the step's start to the new-side end `b` of the final
    /// bracket, so that a step ends exactly at the event and the next one starts on the
    /// new side, with the controller's history forgotten (a PI controller's previous
    /// error; a fresh stiffness estimate; the next step tries the size planned before
    /// the crossing step). The observer gets [`Report::Step`] for every accepted step
    /// (never for a discarded one) and [`Report::Event`] for each event after the step
    /// that ends at it; [`ControlFlow::Break`] stops early (still `Ok`).
    ///
    /// A rejected attempt whose auxiliary end point ŷ2 lies on the other side is
    /// treated alike (its root located on the interpolant of `y0`, `y1`, `ŷ2` with
    /// `f0`, `k5/s`, `k9/s`) and the next attempt aimed at the root, instead of letting
    /// the error test close in on a jump of `f`. An attempt that ends within `tol_t`
    /// past the event, or spans at most `2.5 tol_t` across it, is accepted whatever its
    /// error estimate (its error is the event bracket's). A crossing step whose root
    /// lies within `tol_t` of its end is kept and the event reported at its end
    /// (restarted); within `tol_t` of its start, or after 4 discards in a row from one
    /// point, it is kept and the event reported at the located time from the
    /// interpolant (not restarted). Returns the solver's counters and the event
    /// counters: `rhs_evals = 9 · accepted + 7 · rejected + 9 · discarded + 1` (plus the
    /// step control's own), the discarded steps' 9 each and the final 1 also in
    /// [`England::auxiliary_evals`]. The evaluations of `g` are counted apart
    /// ([`EventStats::event_evals`]).
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use camsim_core::{England, EnglandConfig, EventConfig, EventFunction, OdeSystem, Report, Tolerance};
    ///
    /// // x' = 1 from x = -1: g = x changes side at t = 1.
    /// struct Ramp;
    /// impl OdeSystem<f64, 1> for Ramp {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1], dydt: &mut [f64; 1]) {
    ///         dydt[0] = 1.0;
    ///     }
    /// }
    /// impl EventFunction<f64, 1> for Ramp {
    ///     fn event(&self, _t: f64, y: &[f64; 1]) -> f64 {
    ///         y[0]
    ///     }
    /// }
    /// let mut solver = England::new(EnglandConfig {
    ///     tol: Tolerance::scalar(1e-9, 1e-12),
    ///     h_init: 0.3,
    ///     h_min: 1e-12,
    ///     h_max: 0.3,
    ///     max_steps: 1000,
    /// })?;
    /// let mut found = Vec::new();
    /// let (_, ev) = solver.integrate_events(&Ramp, &Ramp, &EventConfig::new(1e-12), 0.0, &mut [-1.0], 2.0, |r| {
    ///     if let Report::Event(e, _) = r {
    ///         found.push(e);
    ///     }
    ///     ControlFlow::Continue(())
    /// })?;
    /// assert_eq!(ev.events, 1);
    /// assert!(found[0].rising && (found[0].t - 1.0).abs() <= 1e-12);
    /// # Ok::<(), camsim_core::Error>(())
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn integrate_events<S, E, F>(
        &mut self,
        sys: &S,
        event: &E,
        config: &EventConfig<T>,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut observer: F,
    ) -> Result<(SolverStats, EventStats)>
    where
        S: OdeSystem<T, N>,
        E: EventFunction<T, N>,
        F: FnMut(Report<'_, T, N>) -> ControlFlow<()>,
    {
        config.validate()?;
        self.begin(t0, y, t_end)?;
        let mut ev = EventStats::default();
        if t_end == t0 {
            return Ok((self.stats, ev));
        }
        stage(sys, t0, y, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
        let mut g_prev = event.event(t0, y);
        ev.event_evals = ev.event_evals.saturating_add(1);
        let mut t = t0;
        let mut mid = (t0, [T::ZERO; N]);
        let mut f1 = [T::ZERO; N];
        let mut f2 = [T::ZERO; N];
        let mut y_ev = [T::ZERO; N];
        // An event time being integrated to (the new-side end of a located bracket),
        // with the event found there.
        let mut target: Option<T> = None;
        // The step size planned before the approach to an event began (restored after it).
        let mut h_keep: Option<T> = None;
        // The last attempt was rejected (the retry from the same point must not grow).
        let mut rejected = false;
        // Steps discarded in a row from the same point (bounded: then the step is kept).
        let mut discards = 0u32;
        // Force the next attempt (to `target`) through the error test.
        let mut force_next = false;
        let two_tol = T::TWO * config.tol_t;
        // Two tolerances with room for the rounding of t + 2 tol - t.
        let force_width = T::from_f64(2.5) * config.tol_t;
        while t < t_end {
            let t_start = t;
            let y0 = *y;
            let f0 = self.f0;
            let h_before = self.h;
            let stop = target.map_or(t_end, |b| b.min(t_end));
            // The step across the event, accepted as is: the target lies within two
            // tolerances, or a rejected attempt ended within one past the event.
            let force = target.is_some() && (force_next || stop - t_start <= force_width);
            force_next = false;
            let at = self.step_impl(sys, &mut t, y, stop, &mut mid, true, true, rejected, force)?;
            let s = at.s;
            rejected = !at.accepted;
            if !at.accepted {
                // A rejected attempt: did g change side by its (auxiliary) end? Then the
                // rejection is probably the event's; aim the next attempt at it instead
                // of letting the error control close in on it.
                let g_try = event.event(at.t_end, &self.arg);
                ev.event_evals = ev.event_evals.saturating_add(1);
                if side(g_try) != side(g_prev) && s > T::ZERO {
                    for (a, k5) in f1.iter_mut().zip(self.k5.iter()) {
                        *a = *k5 / s;
                    }
                    for (a, k9) in f2.iter_mut().zip(self.k9.iter()) {
                        *a = *k9 / s;
                    }
                    let y_try = self.arg;
                    let dense = Dense::new(
                        [t_start, t_start + s, at.t_end],
                        [&y0, &mid.1, &y_try],
                        [&f0, &f1, &f2],
                    )?;
                    let (a, mut b) = locate(
                        event,
                        &dense,
                        t_start,
                        g_prev,
                        at.t_end,
                        g_try,
                        config,
                        &mut ev.event_evals,
                    );
                    if at.t_end - a <= config.tol_t {
                        // The attempt ends within a tolerance past the event: its error is
                        // the event's (a jump in f it straddles), not the step's; retry it
                        // as is and accept it.
                        force_next = true;
                        b = at.t_end;
                    } else if target.is_some() {
                        // Aimed at an estimate and rejected again: at least halve.
                        b = b.min(t_start + T::HALF * (at.t_end - t_start));
                    }
                    let b = b.max(t_start + two_tol);
                    h_keep.get_or_insert(h_before);
                    target = Some(b);
                    self.h = self.h.max(b - t_start);
                }
                continue;
            }
            for (a, k5) in f1.iter_mut().zip(self.k5.iter()) {
                *a = *k5 / s;
            }
            stage(sys, t, y, T::ONE, &mut f2, &mut self.stats.rhs_evals)?;
            let g = event.event(t, y);
            ev.event_evals = ev.event_evals.saturating_add(1);
            let crossed = side(g) != side(g_prev);
            if target.is_some_and(|b| t >= b) || crossed {
                target = None;
            }

            if crossed {
                let dense = Dense::new([t_start, mid.0, t], [&y0, &mid.1, y], [&f0, &f1, &f2])?;
                let (a, b) = locate(
                    event,
                    &dense,
                    t_start,
                    g_prev,
                    t,
                    g,
                    config,
                    &mut ev.event_evals,
                );
                let at_end = t - b <= config.tol_t;
                let mut found = Event {
                    t: b,
                    bracket: b - a,
                    rising: side(g),
                    restarted: false,
                };
                if !at_end && b - t_start > config.tol_t && discards < 4 {
                    // Discard the step and re-integrate from its start to b.
                    discards += 1;
                    ev.discarded_steps = ev.discarded_steps.saturating_add(1);
                    self.stats.accepted = self.stats.accepted.saturating_sub(1);
                    // Its accepted attempt: k2..k9 (f0 was ready) and f at its end.
                    self.aux_evals = self.aux_evals.saturating_add(9);
                    t = t_start;
                    *y = y0;
                    self.f0 = f0;
                    h_keep.get_or_insert(h_before);
                    self.h = h_before.max(b - t_start);
                    target = Some(b.max(t_start + two_tol));
                    continue;
                }
                // The root lies at an end of the step (or the discards ran out): keep it.
                discards = 0;
                self.f0 = f2;
                g_prev = g;
                if at_end {
                    found.t = t;
                    found.restarted = true;
                    y_ev = *y;
                } else {
                    dense.eval(b, &mut y_ev);
                }
                if observer(Report::Step(&dense)).is_break() {
                    self.aux_evals = self.aux_evals.saturating_add(1);
                    return Ok((self.stats, ev));
                }
                ev.events = ev.events.saturating_add(1);
                self.restart_after_event(h_keep.take().unwrap_or(h_before));
                if observer(Report::Event(found, &y_ev)).is_break() {
                    self.aux_evals = self.aux_evals.saturating_add(1);
                    return Ok((self.stats, ev));
                }
                continue;
            }
            discards = 0;

            self.f0 = f2;
            g_prev = g;
            let dense = Dense::new([t_start, mid.0, t], [&y0, &mid.1, y], [&f0, &f1, &f2])?;
            if observer(Report::Step(&dense)).is_break() {
                self.aux_evals = self.aux_evals.saturating_add(1);
                return Ok((self.stats, ev));
            }
        }
        self.aux_evals = self.aux_evals.saturating_add(1);
        Ok((self.stats, ev))
    }

    /// After an event: forget the controller's history (a PI controller's previous
    /// error, the stiffness estimate) and plan the next step at `h` (the size planned
    /// before the step that crossed the event).
    fn restart_after_event(&mut self, h: T) {
        if let Controller::Pi(pi) = &mut self.control.controller {
            pi.reset();
        }
        self.estimate_due = true;
        self.since_estimate = 0;
        self.h = h.clamp(self.config.h_min, self.config.h_max);
    }
}

/// A scalar event function `g(t, y)` for [`England::integrate_events`]: an event is a
/// change of the *side* of `g` (`g > 0` against `g <= 0`), for example a contact force
/// before it is clamped at zero (positive in contact, zero or negative apart). `g` should
/// be continuous in `(t, y)`; its root is located on the step's continuous extension.
pub trait EventFunction<T, const N: usize> {
    /// The event function at `(t, y)`.
    fn event(&self, t: T, y: &[T; N]) -> T;
}

/// Settings of [`England::integrate_events`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventConfig<T> {
    /// Width of the final bracket of an event time (s): the located time is the end of a
    /// bracket `[a, b]` with `b - a <= tol_t`, `g(a)` on the old side and `g(b)` on the
    /// new side (both on the interpolant). Must be positive and finite.
    pub tol_t: T,
    /// Most evaluations of `g` per located root (Illinois steps; the bracket halves at
    /// least every third step). 0 is refused.
    pub max_iterations: u32,
}

impl<T: Real> EventConfig<T> {
    /// `tol_t`, at most 100 evaluations of `g` per event.
    pub fn new(tol_t: T) -> Self {
        Self {
            tol_t,
            max_iterations: 100,
        }
    }

    fn validate(&self) -> Result<()> {
        if !(self.tol_t.is_finite() && self.tol_t > T::ZERO) {
            return Err(Error::InvalidParameter {
                field: "tol_t",
                rule: "must be positive and finite",
                value: self.tol_t.to_f64(),
            });
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidParameter {
                field: "max_iterations",
                rule: "must be positive",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// One located event of [`England::integrate_events`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event<T> {
    /// The located time (the new-side end of the final bracket).
    pub t: T,
    /// Width of the final bracket (s), at most [`EventConfig::tol_t`] unless the
    /// iteration budget ran out.
    pub bracket: T,
    /// `true`: `g` went from `<= 0` to `> 0` (contact made); `false`: from `> 0` to `<= 0`.
    pub rising: bool,
    /// Whether a step of the integrator ends at `t` (within `tol_t` after the root) and
    /// the next starts on the new side; `false` when the root lay within `tol_t` of the
    /// crossing step's start or the discards ran out (`t` and the state reported are
    /// then the interpolant's).
    pub restarted: bool,
}

/// Work of the event location of one [`England::integrate_events`] run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventStats {
    /// Events reported.
    pub events: u32,
    /// Evaluations of `g` (at every step end, and in the root searches).
    pub event_evals: u32,
    /// Accepted steps that crossed an event and were discarded (their evaluations are
    /// in [`SolverStats::rhs_evals`] and [`England::auxiliary_evals`], not in
    /// [`SolverStats::accepted`]).
    pub discarded_steps: u32,
}

/// What [`England::integrate_events`] passes its observer, in time order.
#[derive(Clone, Copy, Debug)]
pub enum Report<'a, T, const N: usize> {
    /// An accepted step with its continuous extension.
    Step(&'a Dense<'a, T, N>),
    /// A located event, with the state at `event.t` (the integrator's own state when
    /// `event.restarted`, else the interpolant's).
    Event(Event<T>, &'a [T; N]),
}

/// The side of an event function's value: `g > 0` (NaN counts as not).
#[inline]
fn side<T: Real>(g: T) -> bool {
    g > T::ZERO
}

/// Locates the change of side of `g` along `dense` in `[a, b]` (`ga`, `gb` on different
/// sides) by the Illinois method, falling back to bisection when it stalls; returns the
/// final bracket `(a, b)`, `b` on `gb`'s side.
#[allow(clippy::too_many_arguments)]
fn locate<T: Real, const N: usize, E: EventFunction<T, N>>(
    event: &E,
    dense: &Dense<'_, T, N>,
    mut a: T,
    mut ga: T,
    mut b: T,
    mut gb: T,
    cfg: &EventConfig<T>,
    evals: &mut u32,
) -> (T, T) {
    let side_a = side(ga);
    let mut y = [T::ZERO; N];
    // Which end was kept last (Illinois halves its g when kept twice), and how long since
    // the bracket last shrank to half.
    let mut kept: i8 = 0;
    let mut since_halving = 0u32;
    let mut width_at_halving = b - a;
    for _ in 0..cfg.max_iterations {
        let width = b - a;
        if width <= cfg.tol_t {
            break;
        }
        let mid = a + T::HALF * width;
        let mut c = if since_halving >= 3 {
            mid
        } else {
            // Secant through the (modified) ends.
            let denom = gb - ga;
            let c = b - gb * (width / denom);
            if c.is_finite() && c > a && c < b {
                c
            } else {
                mid
            }
        };
        // Keep c at least a fraction of tol_t inside, so a converged side moves too.
        let margin = T::from_f64(0.25) * cfg.tol_t;
        if width > T::TWO * margin {
            c = c.clamp(a + margin, b - margin);
        }
        if !(c > a && c < b) {
            break;
        }
        dense.eval(c, &mut y);
        let gc = event.event(c, &y);
        *evals = evals.saturating_add(1);
        if side(gc) == side_a {
            a = c;
            ga = gc;
            if kept == 1 {
                gb *= T::HALF;
            }
            kept = 1;
        } else {
            b = c;
            gb = gc;
            if kept == -1 {
                ga *= T::HALF;
            }
            kept = -1;
        }
        if !(ga.is_finite() && gb.is_finite()) {
            // A non-finite g: plain bisection from here.
            since_halving = 3;
            ga = if side_a { T::ONE } else { -T::ONE };
            gb = -ga;
        }
        if b - a <= T::HALF * width_at_halving {
            width_at_halving = b - a;
            since_halving = 0;
        } else {
            since_halving += 1;
        }
    }
    (a, b)
}

/// The continuous extension of one accepted double step of [`England`] (its dense
/// output, passed by [`England::integrate_dense`]): the quintic Hermite interpolant of the
/// start `(t0, y0)`, midpoint `(t1, y1)` and end `(t2, y2)` of the step and of the
/// derivatives `f(t_j, y_j)` at all three.
///
/// Why quintic: it uses only what the solver has anyway (`f(t0, y0)` is `k1/s`,
/// `f(t1, y1)` is `k5/s`, `f(t2, y2)` is the next step's first stage), its interpolation
/// error `y⁽⁶⁾(ξ) ((t-t0)(t-t1)(t-t2))² / 720` is `O(h⁶)`, one order below the
/// `O(h⁵)` local error of the nodes themselves, so between the nodes the output is as
/// accurate as at them (globally fourth order, like the solver); and it matches `f` at
/// every node, so it is continuously differentiable across steps. A quartic from
/// `y0, y1, y2, f0, f1` would save only the one final evaluation, with an `O(h⁵)`
/// interpolation error and a kink at every step end.
///
/// It reproduces `y0`, `y1`, `y2` exactly (bit for bit) at `t0`, `t1`, `t2`. Outside
/// `[t0, t2]` it extrapolates (no error; accuracy degrades quickly).
#[derive(Clone, Copy, Debug)]
pub struct Dense<'a, T, const N: usize> {
    t: [T; 3],
    y: [&'a [T; N]; 3],
    f: [&'a [T; N]; 3],
    /// L_j'(t_j) of the quadratic Lagrange basis.
    c: [T; 3],
}

impl<'a, T: Real, const N: usize> Dense<'a, T, N> {
    /// The interpolant of `y[j]` with derivative `f[j]` at times `t[j]`; the times must
    /// be finite and strictly increasing (they need not be equally spaced).
    pub fn new(t: [T; 3], y: [&'a [T; N]; 3], f: [&'a [T; N]; 3]) -> Result<Self> {
        let [t0, t1, t2] = t;
        if !(t0.is_finite() && t1.is_finite() && t2.is_finite() && t0 < t1 && t1 < t2) {
            return Err(Error::InvalidParameter {
                field: "t",
                rule: "dense-output nodes must be finite and strictly increasing (a step below the resolution of t?)",
                value: t1.to_f64(),
            });
        }
        let c = [
            T::ONE / (t0 - t1) + T::ONE / (t0 - t2),
            T::ONE / (t1 - t0) + T::ONE / (t1 - t2),
            T::ONE / (t2 - t0) + T::ONE / (t2 - t1),
        ];
        Ok(Self { t, y, f, c })
    }

    /// Start time of the step.
    pub fn t_start(&self) -> T {
        self.t[0]
    }

    /// Midpoint time of the step.
    pub fn t_mid(&self) -> T {
        self.t[1]
    }

    /// End time of the step.
    pub fn t_end(&self) -> T {
        self.t[2]
    }

    /// State at the start, midpoint and end.
    pub fn nodes(&self) -> [&'a [T; N]; 3] {
        self.y
    }

    /// Derivative `f(t_j, y_j)` at the start, midpoint and end.
    pub fn derivatives(&self) -> [&'a [T; N]; 3] {
        self.f
    }

    /// Weights `[H0, H1, H2, K0, K1, K2]` of the values and derivatives at `t`:
    /// `L_j` the quadratic Lagrange basis, `H_j = (1 - 2 L_j'(t_j)(t - t_j)) L_j²`,
    /// `K_j = (t - t_j) L_j²`. Each `L_j` is a product of ratios that is exactly 1 at
    /// `t_j` and exactly 0 at the other nodes, so the nodes are reproduced exactly.
    fn weights(&self, t: T) -> [T; 6] {
        let [t0, t1, t2] = self.t;
        let a = [t - t0, t - t1, t - t2];
        let [a0, a1, a2] = a;
        let l = [
            (a1 / (t0 - t1)) * (a2 / (t0 - t2)),
            (a0 / (t1 - t0)) * (a2 / (t1 - t2)),
            (a0 / (t2 - t0)) * (a1 / (t2 - t1)),
        ];
        // (H_j, K_j) of node j.
        let hk = |lj: T, aj: T, cj: T| {
            let l2 = lj * lj;
            ((T::ONE - T::TWO * cj * aj) * l2, aj * l2)
        };
        let [l0, l1, l2] = l;
        let [c0, c1, c2] = self.c;
        let (h0, k0) = hk(l0, a0, c0);
        let (h1, k1) = hk(l1, a1, c1);
        let (h2, k2) = hk(l2, a2, c2);
        [h0, h1, h2, k0, k1, k2]
    }

    /// The interpolated state at `t`.
    pub fn eval(&self, t: T, out: &mut [T; N]) {
        combine(self.weights(t), self.y, self.f, out);
    }

    /// The interpolated derivative `dy/dt` at `t` (continuous across steps; equal to
    /// `f(t_j, y_j)` at the nodes up to rounding).
    pub fn eval_derivative(&self, t: T, out: &mut [T; N]) {
        // d/dt of the weights: with a_j = t - t_j, L_j = (a_k/(t_j-t_k))(a_m/(t_j-t_m)),
        // L_j' = a_m/((t_j-t_k)(t_j-t_m)) + a_k/((t_j-t_k)(t_j-t_m)).
        let [t0, t1, t2] = self.t;
        let a = [t - t0, t - t1, t - t2];
        let den = [
            (t0 - t1) * (t0 - t2),
            (t1 - t0) * (t1 - t2),
            (t2 - t0) * (t2 - t1),
        ];
        // (H_j', K_j') of node j, whose other two nodes are k and m.
        let dhk = |aj: T, ak: T, am: T, den_j: T, cj: T| {
            let l = ak * am / den_j;
            let dl = (ak + am) / den_j;
            // H_j' = -2 c_j L² + (1 - 2 c_j a_j) 2 L L';  K_j' = L² + a_j 2 L L'.
            (
                -T::TWO * cj * l * l + (T::ONE - T::TWO * cj * aj) * T::TWO * l * dl,
                l * l + aj * T::TWO * l * dl,
            )
        };
        let [a0, a1, a2] = a;
        let [den0, den1, den2] = den;
        let [c0, c1, c2] = self.c;
        let (dh0, dk0) = dhk(a0, a1, a2, den0, c0);
        let (dh1, dk1) = dhk(a1, a0, a2, den1, c1);
        let (dh2, dk2) = dhk(a2, a0, a1, den2, c2);
        combine([dh0, dh1, dh2, dk0, dk1, dk2], self.y, self.f, out);
    }
}

/// `out = w0 y0 + w1 y1 + w2 y2 + (w3 f0 + w4 f1 + w5 f2)`, component by component: the
/// value or derivative of [`Dense`] from its weights.
fn combine<T: Real, const N: usize>(w: [T; 6], y: [&[T; N]; 3], f: [&[T; N]; 3], out: &mut [T; N]) {
    let [w0, w1, w2, w3, w4, w5] = w;
    let [y0, y1, y2] = y;
    let [f0, f1, f2] = f;
    for ((((((o, y0), y1), y2), f0), f1), f2) in out
        .iter_mut()
        .zip(y0.iter())
        .zip(y1.iter())
        .zip(y2.iter())
        .zip(f0.iter())
        .zip(f1.iter())
        .zip(f2.iter())
    {
        *o = w0 * *y0 + w1 * *y1 + w2 * *y2 + (w3 * *f0 + w4 * *f1 + w5 * *f2);
    }
}

/// One classic fourth-order Runge-Kutta step of size `h` from `(t, y)`, in place (the
/// left column of Appendix D); 4 right-hand-side evaluations, no error control.
pub fn rk4_step<T: Real, const N: usize, S: OdeSystem<T, N>>(sys: &S, t: T, y: &mut [T; N], h: T) {
    let mut k1 = [T::ZERO; N];
    sys.rhs(t, y, &mut k1);
    rk4_step_from(sys, t, y, &k1, h);
}

/// [`rk4_step`] with its first stage `k1 = f(t, y)` given (3 evaluations): for a caller
/// that already has the derivative at the step's start (an interpolant between step ends,
/// a sampler), bit for bit the same arithmetic.
pub fn rk4_step_from<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    y: &mut [T; N],
    k1: &[T; N],
    h: T,
) {
    let half = h * T::HALF;
    let mut k = *k1;
    let mut acc = [T::ZERO; N];
    let mut arg = [T::ZERO; N];
    // acc += w k; arg = y + c k.
    let stage = |arg: &mut [T; N], acc: &mut [T; N], k: &[T; N], w: T, c: T, y: &[T; N]| {
        for (((a, s), yi), ki) in arg
            .iter_mut()
            .zip(acc.iter_mut())
            .zip(y.iter())
            .zip(k.iter())
        {
            *s += w * *ki;
            *a = *yi + c * *ki;
        }
    };
    stage(&mut arg, &mut acc, &k, T::ONE, half, y);
    sys.rhs(t + half, &arg, &mut k);
    stage(&mut arg, &mut acc, &k, T::TWO, half, y);
    sys.rhs(t + half, &arg, &mut k);
    stage(&mut arg, &mut acc, &k, T::TWO, h, y);
    sys.rhs(t + h, &arg, &mut k);
    let h6 = h * T::from_f64(1.0 / 6.0);
    for ((yi, s), ki) in y.iter_mut().zip(acc.iter()).zip(k.iter()) {
        *yi += h6 * (*s + *ki);
    }
}

/// Integrates from `t0` to `t_end` in `steps` equal classic Runge-Kutta steps, calling
/// `observer(t, &y)` at the start and after every step ([`ControlFlow::Break`] stops
/// early, still `Ok`); for comparison with [`England`].
pub fn rk4_integrate<
    T: Real,
    const N: usize,
    S: OdeSystem<T, N>,
    F: FnMut(T, &[T; N]) -> ControlFlow<()>,
>(
    sys: &S,
    t0: T,
    y: &mut [T; N],
    t_end: T,
    steps: u32,
    mut observer: F,
) -> Result<SolverStats> {
    if !t0.is_finite() {
        return Err(Error::InvalidParameter {
            field: "t0",
            rule: "must be finite",
            value: t0.to_f64(),
        });
    }
    if !(t_end.is_finite() && t_end >= t0) {
        return Err(Error::InvalidParameter {
            field: "t_end",
            rule: "must be finite and not before t0",
            value: t_end.to_f64(),
        });
    }
    if steps == 0 {
        return Err(Error::InvalidParameter {
            field: "steps",
            rule: "must be positive",
            value: 0.0,
        });
    }
    if let Some(i) = first_non_finite(y) {
        return Err(Error::NonFinite {
            t: t0.to_f64(),
            component: i,
        });
    }
    let mut stats = SolverStats::default();
    if observer(t0, y).is_break() {
        return Ok(stats);
    }
    let span = t_end - t0;
    let n = T::from_usize(steps as usize);
    let h = span / n;
    for i in 0..steps {
        // Times from the index, not by accumulation, so the last one is exactly t_end.
        let t = t0 + span * (T::from_usize(i as usize) / n);
        rk4_step(sys, t, y, h);
        stats.accepted += 1;
        stats.rhs_evals = stats.rhs_evals.saturating_add(4);
        let t_next = if i + 1 == steps {
            t_end
        } else {
            t0 + span * (T::from_usize(i as usize + 1) / n)
        };
        if let Some(c) = first_non_finite(y) {
            return Err(Error::NonFinite {
                t: t_next.to_f64(),
                component: c,
            });
        }
        if observer(t_next, y).is_break() {
            break;
        }
    }
    Ok(stats)
}
