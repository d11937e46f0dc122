//! England's adaptive Runge-Kutta method (Appendix D, as corrected: docs/MODEL.md §3.16, §4.1):
//! the double step, its error estimate and step-size control, and integration with or without
//! the dense output (events: `events.rs`; the continuous extension: `dense.rs`).
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

use super::step_size::{StepController, Stepper};
use super::{Dense, OdeSystem, Tolerance};
use crate::{Error, Real, Result, StepControl};

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
    /// [`England::integrate`]). For [`rk4_integrate`](crate::rk4_integrate) it is `4 · steps`.
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
    pub(super) config: EnglandConfig<T, N>,
    pub(super) stats: SolverStats,
    // Stage buffers (each already multiplied by the half step s).
    pub(super) f0: [T; N],
    pub(super) k1: [T; N],
    pub(super) k2: [T; N],
    pub(super) k3: [T; N],
    pub(super) k4: [T; N],
    pub(super) k5: [T; N],
    pub(super) k6: [T; N],
    pub(super) k7: [T; N],
    /// k9, then reused for k8 after acceptance.
    pub(super) k9: [T; N],
    /// Argument of the stage being evaluated.
    pub(super) arg: [T; N],
    /// Step-size control: its rules ([`StepControl::classic`] by default) and state.
    pub(super) step: StepController<T, N>,
    /// Right-hand-side evaluations outside the `9 · accepted + 7 · rejected` of the steps.
    pub(super) aux_evals: u32,
}

/// One attempted double step: its sizes and times and its error ratio (accepted if at
/// most 1, or when its caller forces it: [`England::integrate_events`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Attempt<T> {
    /// Error ratio.
    pub(super) err: T,
    /// Sizes and times.
    pub(super) plan: Plan<T>,
}

/// The right-hand side and its evaluation counter: each [`Rhs::stage`] is one
/// evaluation.
struct Rhs<'a, S> {
    sys: &'a S,
    evals: &'a mut u32,
}

impl<S> Rhs<'_, S> {
    /// `out = scale · f(t, arg)`, counted and checked finite ([`stage`]).
    #[inline(always)]
    fn stage<T: Real, const N: usize>(
        &mut self,
        t: T,
        arg: &[T; N],
        scale: T,
        out: &mut [T; N],
    ) -> Result<()>
    where
        S: OdeSystem<T, N>,
    {
        stage(self.sys, t, arg, scale, out, self.evals)
    }
}

/// One of England's two half steps, of size `s` from `(t, base)` (`(t0, y0)` for the
/// first, `(t0 + s, y1)` for the second), written once and used for both: given its first
/// stage `ka = s f(t, base)` ([`Half::middle_stages`]: `kb`, `kc`; [`Half::last_stage`]:
/// `kd`; [`Half::end_point`]). Stages are `k1..k4` in the first half, `k5..k8` in the
/// second.
#[derive(Clone, Copy)]
struct Half<'a, T, const N: usize> {
    /// Start time.
    t: T,
    /// Half step.
    s: T,
    /// Start state.
    base: &'a [T; N],
}

impl<T: Real, const N: usize> Half<'_, T, N> {
    /// `kb = s f(t + s/2, base + ka/2)` and `kc = s f(t + s/2, base + (ka + kb)/4)`.
    #[inline(always)]
    fn middle_stages<S: OdeSystem<T, N>>(
        &self,
        f: &mut Rhs<'_, S>,
        ka: &[T; N],
        kb: &mut [T; N],
        kc: &mut [T; N],
        arg: &mut [T; N],
    ) -> Result<()> {
        let (s, a2, a3) = (self.s, T::from_f64(Tableau::A2), T::from_f64(Tableau::A3));
        for ((a, b), k1) in arg.iter_mut().zip(self.base.iter()).zip(ka.iter()) {
            *a = *b + a2 * *k1;
        }
        f.stage(self.t + s * T::from_f64(Tableau::C[1]), arg, s, kb)?;
        for (((a, b), k1), k2) in arg
            .iter_mut()
            .zip(self.base.iter())
            .zip(ka.iter())
            .zip(kb.iter())
        {
            *a = *b + a3 * (*k1 + *k2);
        }
        f.stage(self.t + s * T::from_f64(Tableau::C[2]), arg, s, kc)
    }

    /// `kd = s f(t_end, base - kb + 2 kc)`, at the half step's end time `t_end` (`t + s`,
    /// or the end time asked for on a last step).
    #[inline(always)]
    fn last_stage<S: OdeSystem<T, N>>(
        &self,
        f: &mut Rhs<'_, S>,
        t_end: T,
        (kb, kc): (&[T; N], &[T; N]),
        kd: &mut [T; N],
        arg: &mut [T; N],
    ) -> Result<()> {
        for (((a, b), k2), k3) in arg
            .iter_mut()
            .zip(self.base.iter())
            .zip(kb.iter())
            .zip(kc.iter())
        {
            *a = accumulated(*b, &Tableau::A4, [*k2, *k3]);
        }
        f.stage(t_end, arg, self.s, kd)
    }

    /// The end point `out = base + (ka + 4 kc + kd)/6`, checked finite (reported at
    /// `t_end`).
    #[inline(always)]
    fn end_point(&self, [ka, kc, kd]: [&[T; N]; 3], out: &mut [T; N], t_end: T) -> Result<()> {
        let b_scale = T::from_f64(Tableau::B_SCALE);
        for ((((o, b), k1), k3), k4) in out
            .iter_mut()
            .zip(self.base.iter())
            .zip(ka.iter())
            .zip(kc.iter())
            .zip(kd.iter())
        {
            *o = *b + b_scale * weighted(&Tableau::B, [*k1, *k3, *k4]);
        }
        match first_non_finite(out) {
            Some(i) => Err(Error::NonFinite {
                t: t_end.to_f64(),
                component: i,
            }),
            None => Ok(()),
        }
    }
}

/// England's tableau as data (the formulas of the module documentation): stage nodes,
/// the weights of each stage's argument, of the two half steps' updates, of `k9`'s
/// argument and of the error estimate `E`. Each combination is evaluated left to right as
/// `w_1 k_1 + w_2 k_2 + ...` ([`weighted`]), which for these weights is bit for bit the
/// original `-k1 - 96 k2 + ...` (a product with `-1` or a negative weight is exact
/// negation).
pub(super) struct Tableau;

impl Tableau {
    /// Stage nodes within a half step `s`, as fractions of `s`: `k1` at 0, `k2` and `k3`
    /// at `s/2`, `k4` at `s` (and `k5..k8` the same from the midpoint).
    pub(super) const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
    /// `k2`'s argument: `y0 + A2 k1`.
    pub(super) const A2: f64 = 0.5;
    /// `k3`'s argument: `y0 + A3 (k1 + k2)`.
    pub(super) const A3: f64 = 0.25;
    /// `k4`'s argument: `y0 + A4 · (k2, k3)`, i.e. `(y0 - k2) + 2 k3` (summed from `y0`).
    pub(super) const A4: [f64; 2] = [-1.0, 2.0];
    /// A half step's update: `y1 = y0 + B_SCALE · B · (k1, k3, k4)` (`k2` does not enter),
    /// i.e. `(k1 + 4 k3 + k4)/6`.
    pub(super) const B: [f64; 3] = [1.0, 4.0, 1.0];
    /// Factor of [`Tableau::B`].
    pub(super) const B_SCALE: f64 = 1.0 / 6.0;
    /// `k9`'s argument: `y0 + A9_SCALE · A9 · (k1, ..., k7)`.
    pub(super) const A9: [f64; 7] = [-1.0, -96.0, 92.0, -121.0, 144.0, 6.0, -12.0];
    /// Factor of [`Tableau::A9`].
    pub(super) const A9_SCALE: f64 = 1.0 / 6.0;
    /// The error estimate: `E = E_SCALE · E · (k1, k3, k4, k5, k7, k9)` (`k2`, `k6`, `k8`
    /// do not enter).
    pub(super) const E: [f64; 6] = [-1.0, 4.0, 17.0, -23.0, 4.0, -1.0];
    /// Factor of [`Tableau::E`].
    pub(super) const E_SCALE: f64 = 1.0 / 90.0;
}

/// The last step before an end time may stretch the planned size by at most this factor
/// (1 %) to land on it instead of leaving a sliver.
const STRETCH: f64 = 1.01;

/// `w_1 k_1 + w_2 k_2 + ...`, summed left to right starting from `w_1 k_1` (not from 0, which
/// would turn a `-0` into `+0`).
#[inline(always)]
fn weighted<T: Real, const M: usize>(w: &[f64; M], k: [T; M]) -> T {
    let mut terms = w.iter().zip(k);
    let Some((w1, k1)) = terms.next() else {
        return T::ZERO;
    };
    terms.fold(T::from_f64(*w1) * k1, |acc, (wi, ki)| {
        acc + T::from_f64(*wi) * ki
    })
}

/// `y + w_1 k_1 + w_2 k_2 + ...`, summed left to right from `y` (k4's argument
/// `y0 - k2 + 2 k3` is `(y0 - k2) + 2 k3`, not `y0 + (2 k3 - k2)`).
#[inline(always)]
fn accumulated<T: Real, const M: usize>(y: T, w: &[f64; M], k: [T; M]) -> T {
    w.iter()
        .zip(k)
        .fold(y, |acc, (wi, ki)| acc + T::from_f64(*wi) * ki)
}

/// The sizes and times of one attempted double step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plan<T> {
    /// Start time.
    t0: T,
    /// The size planned (the controller's, capped), before shortening near an end time.
    h_plan: T,
    /// This attempt's double step.
    h: T,
    /// Half step `h/2`.
    pub(super) s: T,
    /// Midpoint time `t0 + s`.
    pub(super) t_mid: T,
    /// End time (exactly the end time asked for on the last step).
    pub(super) t_end: T,
}

/// Checks the start of a step: `t0` finite, `t_end` finite and later, `y` finite.
pub(super) fn check_step_start<T: Real, const N: usize>(t0: T, t_end: T, y: &[T; N]) -> Result<()> {
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
    Ok(())
}

/// An observer of [`England::integrate_shared`] that forms its samples from the system's
/// own evaluations: at the start, at each midpoint (the second half step's first stage,
/// `k5 = s f(t_mid, y1)`, of every attempt) and at each end point (the next step's first
/// stage), so that no point shown is evaluated twice.
pub(crate) trait Sampler<T, const N: usize> {
    /// Writes `f(t, y)` into `f`, bit for bit as the system's
    /// [`rhs`](OdeSystem::rhs) would, and keeps what [`Sampler::show`] needs of the point.
    fn evaluate(&mut self, t: T, y: &[T; N], f: &mut [T; N]);
    /// Shows the point last evaluated; [`ControlFlow::Break`] stops the integration.
    fn show(&mut self) -> ControlFlow<()>;
}

/// Evaluates `out = scale · f(t, arg)` and checks that it is finite.
#[inline(always)]
pub(super) fn stage<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    arg: &[T; N],
    scale: T,
    out: &mut [T; N],
    evals: &mut u32,
) -> Result<()> {
    sys.rhs(t, arg, out);
    scaled_stage(t, scale, out, evals)
}

/// The rest of [`stage`] once `out = f(t, arg)`: counts the evaluation, scales `out` by
/// `scale` and checks that it is finite.
#[inline(always)]
fn scaled_stage<T: Real, const N: usize>(
    t: T,
    scale: T,
    out: &mut [T; N],
    evals: &mut u32,
) -> Result<()> {
    *evals = evals.saturating_add(1);
    // `x · 0` is NaN exactly for a non-finite x (±0 otherwise): one sum tells whether any
    // component is non-finite, without a test and branch per component.
    let mut probe = T::ZERO;
    for o in out.iter_mut() {
        *o *= scale;
        probe += *o * T::ZERO;
    }
    if probe.is_finite() {
        return Ok(());
    }
    Err(Error::NonFinite {
        t: t.to_f64(),
        component: first_non_finite(out).unwrap_or(0),
    })
}

/// Index of the first non-finite component, if any.
#[inline]
pub(super) fn first_non_finite<T: Real, const N: usize>(y: &[T; N]) -> Option<usize> {
    // One sum of `x · 0` (NaN exactly for a non-finite x) first: no test per component
    // unless one is non-finite.
    let mut probe = T::ZERO;
    for v in y {
        probe += *v * T::ZERO;
    }
    if probe.is_finite() {
        None
    } else {
        y.iter().position(|v| !v.is_finite())
    }
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
            step: StepController::new(Stepper::England, control, config.h_init),
            aux_evals: 0,
        })
    }

    /// The step-size control it was built with.
    pub fn control(&self) -> &StepControl<T> {
        self.step.rule()
    }

    /// The last spectral-radius estimate of the stiffness cap (`None` without a cap or
    /// before the first step).
    pub fn spectral_radius(&self) -> Option<T> {
        self.step.spectral_radius()
    }

    /// The current double-step cap of the stiffness cap (`None` without one).
    pub fn step_cap(&self) -> Option<T> {
        self.step.step_cap()
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
        self.step.refresh_stiffness();
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
        self.step.step_size()
    }

    /// Forgets the controller's history: the next step tries `h_init` (or Hairer's
    /// starting step, with [`StepControl::hairer_start`]) and the counters (and so the step
    /// budget) restart from zero; a PI rule forgets its previous error and the stiffness
    /// cap starts over from a fresh estimate.
    pub fn reset(&mut self) {
        self.step.reset(self.config.h_init);
        self.stats = SolverStats::default();
        self.aux_evals = 0;
    }

    /// Hairer's starting step and the stiffness estimate, when due, from `f0 = f(t0, y0)`
    /// ([`StepController::prepare`]), their evaluations counted as auxiliary.
    pub(super) fn prepare<S: OdeSystem<T, N>>(&mut self, sys: &S, t0: T, y: &[T; N]) -> Result<()> {
        let before = self.stats.rhs_evals;
        let evals = &mut self.stats.rhs_evals;
        self.step
            .prepare(sys, t0, y, &self.f0, &self.config, evals)?;
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
        check_step_start(*t, t_end, y)?;
        // f(t0, y0), shared by every attempt from this point.
        stage(sys, *t, y, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
        self.until_accepted(sys, t, y, t_end, mid, None)
            .map(|a| a.err)
    }

    /// [`England::step`] with `self.f0 = f(t, y)` already evaluated, each attempt's `k5`
    /// evaluated by `sampler` if given ([`England::integrate_shared`]); returns the
    /// accepted attempt.
    pub(super) fn until_accepted<'s, S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t: &mut T,
        y: &mut [T; N],
        t_end: T,
        mid: &mut (T, [T; N]),
        mut sampler: Option<&mut (dyn Sampler<T, N> + 's)>,
    ) -> Result<Attempt<T>> {
        self.step.begin_step();
        loop {
            let at = self.attempt(sys, *t, y, t_end, &mut mid.1, sampler.as_deref_mut())?;
            if at.err <= T::ONE {
                self.take(sys, &at, t, y, mid)?;
                return Ok(at);
            }
            self.reject(&at)?;
        }
    }

    /// One attempted double step from `(t0, y)` (`self.f0 = f(t0, y)`), to be taken
    /// ([`England::take`]) or rejected ([`England::reject`]) by the caller: the midpoint
    /// `y1`, `self.arg` the auxiliary end point ŷ2, `self.k5` and `self.k9` `s f` at those.
    pub(super) fn attempt<'s, S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t0: T,
        y: &[T; N],
        t_end: T,
        y1: &mut [T; N],
        sampler: Option<&mut (dyn Sampler<T, N> + 's)>,
    ) -> Result<Attempt<T>> {
        let steps = self.stats.accepted.saturating_add(self.stats.rejected);
        if steps >= self.config.max_steps {
            return Err(Error::StepBudgetExceeded {
                t: t0.to_f64(),
                steps,
            });
        }
        // Starting step and stiffness estimate when due (never with the classic control).
        if self.step.needs_preparation() {
            self.prepare(sys, t0, y)?;
        }
        let plan = self.plan(t0, t_end);
        self.first_half(sys, y, &plan, y1)?;
        self.second_half(sys, y, y1, &plan, sampler)?;
        let err = self.error_ratio(y, &plan)?;
        Ok(Attempt { err, plan })
    }

    /// Takes an attempt whatever its error: `(t, y)` to its end point, `mid.0` to its
    /// midpoint time (`mid.1` holds its midpoint), the controller's next size.
    pub(super) fn take<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        at: &Attempt<T>,
        t: &mut T,
        y: &mut [T; N],
        mid: &mut (T, [T; N]),
    ) -> Result<()> {
        self.accept(sys, &at.plan, at.err, &mid.1, y)?;
        mid.0 = at.plan.t_mid;
        *t = at.plan.t_end;
        Ok(())
    }
    /// This attempt's double step from `t0`: the planned size (capped), shortened to land
    /// on `t_end` when that is at most 1 % beyond it, or halving the rest when `t_end` is
    /// less than two steps away.
    fn plan(&self, t0: T, t_end: T) -> Plan<T> {
        let h_plan = self.step.propose(self.config.h_min);
        let remaining = t_end - t0;
        let (h, last) = if remaining <= h_plan * T::from_f64(STRETCH) {
            (remaining, true)
        } else if remaining < h_plan + h_plan {
            (remaining * T::HALF, false)
        } else {
            (h_plan, false)
        };
        let s = h * T::HALF;
        Plan {
            t0,
            h_plan,
            h,
            s,
            t_mid: t0 + s,
            t_end: if last { t_end } else { t0 + h },
        }
    }

    /// First half step from `(t0, y0)`: `k1..k4` and the midpoint `y1`.
    fn first_half<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        y: &[T; N],
        p: &Plan<T>,
        y1: &mut [T; N],
    ) -> Result<()> {
        let (t0, s) = (p.t0, p.s);
        for (k, f) in self.k1.iter_mut().zip(self.f0.iter()) {
            *k = s * *f;
        }
        if let Some(i) = first_non_finite(&self.k1) {
            return Err(Error::NonFinite {
                t: t0.to_f64(),
                component: i,
            });
        }
        let half = Half { t: t0, s, base: y };
        let mut f = Rhs {
            sys,
            evals: &mut self.stats.rhs_evals,
        };
        half.middle_stages(&mut f, &self.k1, &mut self.k2, &mut self.k3, &mut self.arg)?;
        // k4 at t0 + s · C[3] = t0 + s, the midpoint time.
        half.last_stage(
            &mut f,
            p.t_mid,
            (&self.k2, &self.k3),
            &mut self.k4,
            &mut self.arg,
        )?;
        half.end_point([&self.k1, &self.k3, &self.k4], y1, p.t_mid)
    }

    /// Second half step from the midpoint `y1` up to `k7`, then England's `k9` at the
    /// auxiliary end point ŷ2 (left in `self.arg`); `k8` and `y2` only if the attempt is
    /// taken ([`England::accept`]).
    fn second_half<'s, S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        y: &[T; N],
        y1: &[T; N],
        p: &Plan<T>,
        sampler: Option<&mut (dyn Sampler<T, N> + 's)>,
    ) -> Result<()> {
        let (s, t_mid) = (p.s, p.t_mid);
        match sampler {
            Some(sampler) => {
                sampler.evaluate(t_mid, y1, &mut self.k5);
                scaled_stage(t_mid, s, &mut self.k5, &mut self.stats.rhs_evals)?;
            }
            None => stage(sys, t_mid, y1, s, &mut self.k5, &mut self.stats.rhs_evals)?,
        }
        let half = Half {
            t: t_mid,
            s,
            base: y1,
        };
        let mut f = Rhs {
            sys,
            evals: &mut self.stats.rhs_evals,
        };
        half.middle_stages(&mut f, &self.k5, &mut self.k6, &mut self.k7, &mut self.arg)?;
        let a9_scale = T::from_f64(Tableau::A9_SCALE);
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
            let k = [*k1, *k2, *k3, *k4, *k5, *k6, *k7];
            *a = *y0 + a9_scale * weighted(&Tableau::A9, k);
        }
        f.stage(p.t_end, &self.arg, s, &mut self.k9)
    }
    /// The error ratio of the attempt from `E = (-k1 + 4k3 + 17k4 - 23k5 + 4k7 - k9)/90`:
    /// `max_i |E_i| / (atol_i + rtol · max(|y0_i|, |ŷ2_i|))`, per unit step if asked.
    fn error_ratio(&self, y: &[T; N], p: &Plan<T>) -> Result<T> {
        let rtol = self.config.tol.rtol;
        let e_scale = T::from_f64(Tableau::E_SCALE);
        let mut err = T::ZERO;
        // Non-finite components of E: one sum of `e · 0` (NaN exactly for a non-finite e),
        // looked into only when it is not finite.
        let mut probe = T::ZERO;
        let mut e_all = [T::ZERO; N];
        for ((((((((k1, k3), k4), k5), k7), k9), atol), y0), (a, e_out)) in self
            .k1
            .iter()
            .zip(self.k3.iter())
            .zip(self.k4.iter())
            .zip(self.k5.iter())
            .zip(self.k7.iter())
            .zip(self.k9.iter())
            .zip(self.config.tol.atol.iter())
            .zip(y.iter())
            .zip(self.arg.iter().zip(e_all.iter_mut()))
        {
            let e = e_scale * weighted(&Tableau::E, [*k1, *k3, *k4, *k5, *k7, *k9]);
            // max(|y0|, |ŷ2|) and the running max below as plain compares, without
            // `Real::max`'s NaN tests (about 200 instructions a step on the chip), and
            // with its values for every input: ŷ2 is y0 plus the stages, so a NaN y0
            // makes ŷ2 NaN too (both give |y0|), a NaN ŷ2 alone keeps |y0| (both), and
            // `err` starts at 0 and is never NaN, so a NaN `r` leaves it (both).
            let (ay0, aa) = (y0.abs(), a.abs());
            let scale = *atol + rtol * if aa > ay0 { aa } else { ay0 };
            probe += e * T::ZERO;
            *e_out = e;
            let e = e.abs();
            let r = if scale > T::ZERO {
                e / scale
            } else if e == T::ZERO {
                T::ZERO
            } else {
                T::INFINITY
            };
            if r > err {
                err = r;
            }
        }
        if !probe.is_finite() {
            return Err(Error::NonFinite {
                t: p.t_end.to_f64(),
                component: first_non_finite(&e_all).unwrap_or(0),
            });
        }
        Ok(self.step.judge(err, p.h, rtol))
    }

    /// An accepted attempt: `k8` (into the `k9` buffer) and the end point `y2` (in place
    /// of `y0`) by the second half step, the counters, and the next step's size from the
    /// controller (no growth right after a rejection from the same point).
    fn accept<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        p: &Plan<T>,
        err: T,
        y1: &[T; N],
        y: &mut [T; N],
    ) -> Result<()> {
        let half = Half {
            t: p.t_mid,
            s: p.s,
            base: y1,
        };
        let mut f = Rhs {
            sys,
            evals: &mut self.stats.rhs_evals,
        };
        half.last_stage(
            &mut f,
            p.t_end,
            (&self.k6, &self.k7),
            &mut self.k9,
            &mut self.arg,
        )?;
        // Restoring y0 on a non-finite y2 would need a copy on every step; report instead.
        half.end_point([&self.k5, &self.k7, &self.k9], y, p.t_end)?;
        self.stats.accepted = self.stats.accepted.saturating_add(1);
        let (h_min, h_max) = (self.config.h_min, self.config.h_max);
        self.step.accept(err, p.h, p.h_plan, h_min, h_max);
        Ok(())
    }

    /// Rejects an attempt: the counters, the smaller size of the retry (which will not
    /// grow the step on acceptance), and a new stiffness estimate when the cap may be
    /// stale. Fails at `h_min`.
    pub(super) fn reject(&mut self, at: &Attempt<T>) -> Result<()> {
        self.stats.rejected = self.stats.rejected.saturating_add(1);
        let (t0, err, h, h_min) = (at.plan.t0, at.err, at.plan.h, self.config.h_min);
        if h <= h_min {
            return Err(Error::StepSizeUnderflow {
                t: t0.to_f64(),
                h: h.to_f64(),
            });
        }
        self.step.reject(err, h, h_min);
        Ok(())
    }

    /// Resets the statistics for a new integration from (t0, y) to t_end and checks both
    /// ends and the state (shared by [`Self::integrate`] and [`Self::integrate_dense`]).
    pub(super) fn begin(&mut self, t0: T, y: &[T; N], t_end: T) -> Result<()> {
        self.stats = SolverStats::default();
        self.aux_evals = 0;
        self.step.begin();
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

    /// [`England::integrate`] for a [`Sampler`], an observer that forms its samples from
    /// the system's own evaluations: it is shown the same points in the same order (the
    /// start, each accepted step's midpoint and end point), each evaluated once, by the
    /// sampler: the midpoint is the accepted attempt's `k5` stage, the end point the next
    /// step's first stage. The points and the counters (`rhs_evals` counts those stages as
    /// before) are bit for bit those of [`England::integrate`] with an observer that
    /// evaluates the system at every point; the system is evaluated twice less per
    /// accepted step.
    pub(crate) fn integrate_shared<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        sampler: &mut dyn Sampler<T, N>,
    ) -> Result<SolverStats> {
        self.begin(t0, y, t_end)?;
        sampler.evaluate(t0, y, &mut self.f0);
        if sampler.show().is_break() {
            return Ok(self.stats);
        }
        let mut t = t0;
        let mut mid = (t0, [T::ZERO; N]);
        while t < t_end {
            // f(t, y) from the sampler: counted and checked as `stage` does.
            scaled_stage(t, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
            check_step_start(t, t_end, y)?;
            self.until_accepted(sys, &mut t, y, t_end, &mut mid, Some(&mut *sampler))?;
            if sampler.show().is_break() {
                // The caller stopped at the midpoint: leave y there.
                *y = mid.1;
                break;
            }
            sampler.evaluate(t, y, &mut self.f0);
            if sampler.show().is_break() {
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
            check_step_start(t, t_end, y)?;
            let s = self
                .until_accepted(sys, &mut t, y, t_end, &mut mid, None)?
                .plan
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
}

#[cfg(test)]
mod shared_tests {
    use super::*;
    use core::cell::Cell;

    /// A damped oscillator with a forcing term that depends on t, counting its evaluations.
    struct Forced {
        calls: Cell<u32>,
    }

    impl OdeSystem<f64, 2> for Forced {
        fn rhs(&self, t: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
            self.calls.set(self.calls.get() + 1);
            dydt[0] = y[1];
            dydt[1] = -400.0 * y[0] - 0.3 * y[1] + (3.0 * t).sin();
        }
    }

    /// Records every point shown, evaluating the system itself.
    struct Recorder<'a> {
        sys: &'a Forced,
        last: (f64, [f64; 2]),
        shown: [(f64, [f64; 2]); 4096],
        len: usize,
        stop_after: usize,
    }

    impl Sampler<f64, 2> for Recorder<'_> {
        fn evaluate(&mut self, t: f64, y: &[f64; 2], f: &mut [f64; 2]) {
            self.last = (t, *y);
            self.sys.rhs(t, y, f);
        }
        fn show(&mut self) -> ControlFlow<()> {
            if let Some(slot) = self.shown.get_mut(self.len) {
                *slot = self.last;
            }
            self.len += 1;
            if self.len >= self.stop_after {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        }
    }

    /// The one-sum test of `first_non_finite` (and the stages' and the error's): the
    /// largest, smallest and signed-zero components are finite; each of NaN, +inf and -inf
    /// is found at its index, the first of several.
    #[test]
    fn non_finite_components_are_found_by_index() {
        let finite = [f32::MAX, -f32::MAX, f32::MIN_POSITIVE * 0.5, -0.0, 0.0];
        assert_eq!(first_non_finite(&finite), None);
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for i in 0..5 {
                let mut y = finite;
                y[i] = bad;
                assert_eq!(first_non_finite(&y), Some(i), "{bad} at {i}");
                y[4] = f32::NAN;
                assert_eq!(first_non_finite(&y), Some(i), "{bad} at {i} and NaN at 4");
            }
        }
        let mut out = [1.0f32, 2.0, 3.0];
        let mut evals = 0;
        // 2 · MAX overflows to +inf in component 1 only.
        out[1] = f32::MAX;
        let r = scaled_stage(0.5f32, 2.0, &mut out, &mut evals);
        assert!(
            matches!(r, Err(Error::NonFinite { component: 1, .. })),
            "{r:?}"
        );
        assert_eq!(evals, 1);
    }

    fn solver() -> England<f64, 2> {
        England::new(EnglandConfig {
            tol: Tolerance::scalar(1e-6, 1e-9),
            h_init: 1e-3,
            h_min: 1e-12,
            h_max: 0.05,
            max_steps: 100_000,
        })
        .unwrap()
    }

    /// `integrate_shared` shows the points `integrate` shows, bit for bit, with the same
    /// counters, and evaluates the system exactly `2 · accepted` times less than
    /// `integrate` with an observer that evaluates it at every point shown (two per
    /// accepted step); stopping at a
    /// midpoint leaves `y` there in both.
    #[test]
    fn shared_evaluations_show_the_same_points_for_fewer_evaluations() {
        for stop_after in [usize::MAX, 7, 8] {
            let sys = Forced {
                calls: Cell::new(0),
            };
            let mut plain = [(0.0, [0.0; 2]); 4096];
            let mut n_plain = 0;
            let mut y_plain = [1.0, 0.0];
            let stats_plain = solver()
                .integrate(&sys, 0.0, &mut y_plain, 2.0, |t, y| {
                    let mut f = [0.0; 2];
                    sys.rhs(t, y, &mut f); // the observer's own evaluation
                    plain[n_plain] = (t, *y);
                    n_plain += 1;
                    if n_plain >= stop_after {
                        ControlFlow::Break(())
                    } else {
                        ControlFlow::Continue(())
                    }
                })
                .unwrap();
            let calls_plain = sys.calls.replace(0);

            let mut rec = Recorder {
                sys: &sys,
                last: (f64::NAN, [f64::NAN; 2]),
                shown: [(0.0, [0.0; 2]); 4096],
                len: 0,
                stop_after,
            };
            let mut y = [1.0, 0.0];
            let stats = solver()
                .integrate_shared(&sys, 0.0, &mut y, 2.0, &mut rec)
                .unwrap();
            let calls = sys.calls.get();

            assert_eq!(stats, stats_plain);
            if stop_after == usize::MAX {
                assert!(stats.rejected > 0 && stats.accepted > 20, "{stats:?}");
            }
            assert_eq!(rec.len, n_plain);
            for (a, b) in rec.shown.iter().zip(plain.iter()).take(n_plain) {
                assert_eq!(a.0.to_bits(), b.0.to_bits());
                assert_eq!(a.1.map(f64::to_bits), b.1.map(f64::to_bits));
            }
            assert_eq!(y.map(f64::to_bits), y_plain.map(f64::to_bits));
            // integrate: rhs_evals + one per point shown; shared: one per point evaluated
            // (the start, each attempt's k5 and each end point counted once).
            assert_eq!(calls_plain, stats.rhs_evals + n_plain as u32);
            // Both evaluate the last point shown (the shared run as the next step's first
            // stage, uncounted when there is no next step): two evaluations saved per
            // accepted step (its midpoint and its end point).
            let saved = calls_plain - calls;
            let expected = 2 * stats.accepted;
            assert_eq!(saved, expected, "stop_after {stop_after}: {stats:?}");
        }
    }
}
