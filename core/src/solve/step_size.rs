//! The step-size controller of England's method and of the embedded pairs: one type,
//! [`StepController`], that owns the rules of step control as data and all the state they
//! need, behind one interface.
//!
//! - The rules are data ([`StepControl`], built from a run's [`StepRule`](crate::StepRule)
//!   by name): the factor rule (England's classic `0.9 err^(-1/5)`, or Gustafsson's PI
//!   with [`PiSettings`]), the first step (`h_init` or Hairer's, [`initial_step`]), the
//!   stiffness cap as an optional limit ([`StiffnessCap`](crate::StiffnessCap),
//!   tolerance-scaled or not) and error per unit step as an optional judge of the error
//!   ([`PerUnitStep`](crate::PerUnitStep)).
//! - The state is the next step, whether the next attempt retries a rejected one, the PI
//!   rule's previous error, the stiffness estimate (cap, spectral radius, its age, whether
//!   one is due, the power iteration's vector) and whether Hairer's first step is due.
//! - The interface is the cycle of one attempt: [`StepController::prepare`] (the
//!   estimates that are due), [`StepController::propose`] (the size to try),
//!   [`StepController::judge`] (the error ratio the step is accepted by), then
//!   [`StepController::accept`] or [`StepController::reject`] (the next size).
//!
//! The integrator keeps what is its own: the landing on an end time, the stages, the
//! counters and the step budget. What differs between England's double step and a pair's
//! single step is the [`Stepper`] the controller is built for.

use crate::{
    spectral_radius, EnglandConfig, Error, OdeSystem, PiSettings, Real, Result, StepControl,
    Tolerance,
};

/// England's rule (`StepControl::pi` `None`): safety factor 0.9.
const CLASSIC_SAFETY: f64 = 0.9;
/// England's rule: exponent `-1/5` of the error ratio (local error ∝ `h^5`).
const CLASSIC_EXPONENT: f64 = -0.2;
/// England's rule: smallest step-size factor.
const CLASSIC_FAC_MIN: f64 = 0.2;
/// England's rule: largest step-size factor.
const CLASSIC_FAC_MAX: f64 = 5.0;

/// A rejected step of at least this fraction of the stiffness cap counts as rejected at
/// the cap, so the cap's estimate may be stale: a step planned at the cap is the cap up to
/// rounding, or slightly shorter where it lands on an end time; the same 1 % as
/// England's stretch of a last step.
const AT_CAP: f64 = 0.99;

/// A rejection this many refresh intervals ([`StiffnessCap::refresh_every`](crate::StiffnessCap))
/// after the last stiffness estimate asks for a new one whatever the step: periodic
/// estimates run only while the step is within a factor 2 of the cap, so a stiffness
/// that grew past the cap while the step was held lower would otherwise go unseen. Four
/// intervals keep such estimates rare (at most one per four intervals of rejections).
const STALE_AFTER_REFRESHES: u32 = 4;

/// The integrator a [`StepController`] controls: where the stiffness cap's scale and
/// schedule differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Stepper {
    /// England's double step: two half steps, each within the stability boundary, so the
    /// cap is `2 · fraction · boundary / ρ`. The estimate is renewed every
    /// `refresh_every` accepted steps only while the step is within a factor 2 of the cap,
    /// and after a rejection that suggests it is stale; the next step is capped as soon as
    /// it is planned.
    England,
    /// An embedded pair's single step (the pair's own boundary): the cap is
    /// `fraction · boundary / ρ`, renewed every `refresh_every` accepted steps, applied
    /// when the step is proposed.
    #[cfg_attr(not(feature = "pairs"), allow(dead_code))]
    Pair,
}

impl Stepper {
    /// Steps of the boundary's method in one step: 2 half steps for England, 1 for a pair.
    fn steps<T: Real>(self) -> T {
        match self {
            Stepper::England => T::TWO,
            Stepper::Pair => T::ONE,
        }
    }
}

/// The stiffness cap's state: the cap and the estimate it comes from (its age and whether
/// a new one is due are [`StepController`]'s, beside its flags: one padded group, not
/// two, so the solver is no larger than before).
#[derive(Clone, Debug)]
struct Stiffness<T, const N: usize> {
    /// Double-step cap from the last estimate (`T::MAX`: none).
    h_cap: T,
    /// Last spectral-radius estimate (NaN: none yet).
    rho: T,
    /// Power-iteration vector, kept for a warm start.
    v: [T; N],
}

impl<T: Real, const N: usize> Stiffness<T, N> {
    /// No estimate yet.
    fn fresh() -> Self {
        Self {
            h_cap: T::MAX,
            rho: T::NAN,
            v: [T::ZERO; N],
        }
    }
}

/// The step-size controller: the rules ([`StepControl`]) and their state (module
/// documentation). Sizes are the integrator's steps (England's double steps).
#[derive(Clone, Debug)]
pub(crate) struct StepController<T, const N: usize> {
    /// The integrator whose steps it controls.
    stepper: Stepper,
    /// The rules (a PI factor rule keeps its previous error in it).
    rule: StepControl<T>,
    /// Next double-step size to try (before the cap).
    h: T,
    /// The PI rule's error ratio of the last accepted step, floored (1 before the first:
    /// "on target"); unused by England's rule.
    err_prev: T,
    /// The next attempt retries a rejected one from the same point (its acceptance must
    /// not grow the step).
    retry: bool,
    /// The stiffness cap's state (unused without a cap).
    stiffness: Stiffness<T, N>,
    /// Accepted steps since the last stiffness estimate.
    since_estimate: u32,
    /// A stiffness estimate is due at the next step.
    estimate_due: bool,
    /// Hairer's starting step is due at the next step.
    initial_due: bool,
}

impl<T: Real, const N: usize> StepController<T, N> {
    /// A controller of `stepper`'s steps with `rule` whose first step is `h_init`.
    pub(crate) fn new(stepper: Stepper, rule: StepControl<T>, h_init: T) -> Self {
        Self {
            stepper,
            rule,
            h: h_init,
            err_prev: T::ONE,
            retry: false,
            stiffness: Stiffness::fresh(),
            since_estimate: 0,
            estimate_due: true,
            initial_due: rule.hairer_start,
        }
    }

    /// The rules.
    pub(crate) fn rule(&self) -> &StepControl<T> {
        &self.rule
    }

    /// The next double-step size it will propose (before the cap).
    pub(crate) fn step_size(&self) -> T {
        self.h
    }

    /// The last spectral-radius estimate (`None` without a cap or before the first).
    pub(crate) fn spectral_radius(&self) -> Option<T> {
        let rho = self.stiffness.rho;
        (!rho.is_nan()).then_some(rho)
    }

    /// The current double-step cap (`None` without one).
    pub(crate) fn step_cap(&self) -> Option<T> {
        let h_cap = self.stiffness.h_cap;
        (self.rule.stiffness_cap.is_some() && h_cap < T::MAX).then_some(h_cap)
    }

    /// Asks for a new stiffness estimate at the next step.
    pub(crate) fn refresh_stiffness(&mut self) {
        self.estimate_due = true;
    }

    /// Forgets everything: the next step is `h_init` (or Hairer's), a PI rule forgets its
    /// previous error and the cap starts over from a fresh estimate.
    pub(crate) fn reset(&mut self, h_init: T) {
        self.h = h_init;
        self.err_prev = T::ONE;
        self.stiffness = Stiffness::fresh();
        self.since_estimate = 0;
        self.estimate_due = true;
        self.initial_due = self.rule.hairer_start;
        self.retry = false;
    }

    /// A new integration: a stiffness estimate is due and no attempt is a retry.
    pub(crate) fn begin(&mut self) {
        self.estimate_due = true;
        self.retry = false;
    }

    /// A new step from a new point: its first attempt is not a retry.
    pub(crate) fn begin_step(&mut self) {
        self.retry = false;
    }

    /// After an event: forget the history (a PI rule's previous error, the stiffness
    /// estimate) and propose `h` next (clamped to `[h_min, h_max]`).
    pub(crate) fn restart(&mut self, h: T, h_min: T, h_max: T) {
        self.err_prev = T::ONE;
        self.estimate_due = true;
        self.since_estimate = 0;
        self.h = h.clamp(h_min, h_max);
    }

    /// Sets the next size (an integrator aiming at a point: an event's bracket).
    pub(crate) fn set_step_size(&mut self, h: T) {
        self.h = h;
    }

    /// Whether [`StepController::prepare`] has anything to do (never with the classic
    /// rules).
    pub(crate) fn needs_preparation(&self) -> bool {
        self.rule.stiffness_cap.is_some() || self.initial_due
    }

    /// The stiffness estimate and Hairer's starting step, when due, at `(t0, y)` with
    /// `f0 = f(t0, y)`; their evaluations are added to `evals`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn prepare<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t0: T,
        y: &[T; N],
        f0: &[T; N],
        config: &EnglandConfig<T, N>,
        evals: &mut u32,
    ) -> Result<()> {
        if let Some(cap) = self.rule.stiffness_cap {
            let st = &mut self.stiffness;
            // England: periodic estimates only while the cap may bind (the planned step
            // within a factor 2 of it); rejections ask for one through `estimate_due`.
            let near_cap = match self.stepper {
                Stepper::England => self.h >= T::HALF * st.h_cap,
                Stepper::Pair => true,
            };
            let periodic = self.since_estimate >= cap.refresh_every.max(1) && near_cap;
            if self.estimate_due || periodic {
                let rho = match sys.spectral_radius(t0, y) {
                    Some(r) if r.is_finite() && r >= T::ZERO => r,
                    _ if cap.max_iterations > 0 => spectral_radius(
                        sys,
                        t0,
                        y,
                        f0,
                        &config.tol,
                        &mut st.v,
                        cap.max_iterations,
                        cap.rel_tol,
                        evals,
                    )?,
                    _ => T::NAN,
                };
                st.rho = rho;
                st.h_cap = cap.step_cap_at(rho, config.tol.rtol, self.stepper.steps());
                self.since_estimate = 0;
                self.estimate_due = false;
            }
        }
        if self.initial_due {
            self.initial_due = false;
            let h = initial_step(sys, t0, y, f0, &config.tol, 4, config.h_max, evals)?;
            self.h = h.clamp(config.h_min, config.h_max);
        }
        Ok(())
    }

    /// The double step to try: the next size, capped (never below `h_min`).
    pub(crate) fn propose(&self, h_min: T) -> T {
        if self.rule.stiffness_cap.is_some() {
            self.h.min(self.stiffness.h_cap).max(h_min)
        } else {
            self.h
        }
    }

    /// The error ratio a double step `h` with per-step ratio `err` is judged by at
    /// relative tolerance `rtol`: `err`, or per unit step ([`PerUnitStep::ratio`](crate::PerUnitStep::ratio)).
    pub(crate) fn judge(&self, err: T, h: T, rtol: T) -> T {
        match &self.rule.per_unit_step {
            Some(u) => u.ratio(err, h, rtol),
            None => err,
        }
    }

    /// An attempt of size `h` (proposed `h_plan`, shortened when `h < h_plan`) taken with
    /// error ratio `err`: the next size from the factor rule (no growth right after a
    /// rejection), within `[h_min, h_max]` and the cap.
    pub(crate) fn accept(&mut self, err: T, h: T, h_plan: T, h_min: T, h_max: T) {
        let after_rejection = core::mem::replace(&mut self.retry, false);
        let (fac, fac_unbounded) = self.accept_factor(err, after_rejection);
        let mut h_next = h * fac;
        if h < h_plan {
            // A step shortened to meet t_end says nothing against the planned size.
            let h_ok = if fac_unbounded >= h_plan / h {
                h_plan
            } else {
                h * fac_unbounded
            };
            h_next = h_next.max(h_ok);
        }
        self.h = h_next.clamp(h_min, h_max);
        if self.rule.stiffness_cap.is_some() {
            self.since_estimate = self.since_estimate.saturating_add(1);
            if self.stepper == Stepper::England {
                self.h = self.h.min(self.stiffness.h_cap).max(h_min);
            }
        }
    }

    /// An attempt of size `h` rejected with error ratio `err`: the smaller size of the
    /// retry (at least `h_min`; its acceptance will not grow the step), and a new
    /// stiffness estimate when the cap may be stale.
    pub(crate) fn reject(&mut self, err: T, h: T, h_min: T) {
        let fac = self.reject_factor(err);
        let cap = self
            .rule
            .stiffness_cap
            .filter(|_| self.stepper == Stepper::England);
        if let Some(cap) = &cap {
            // Rejected at the cap, or near it long after the last estimate, or very long
            // after it (the stiffness may have grown past the cap): it may be stale.
            let (k, since, h_cap) = (cap.refresh_every, self.since_estimate, self.stiffness.h_cap);
            if h >= T::from_f64(AT_CAP) * h_cap
                || (since >= k && h >= T::HALF * h_cap)
                || since >= k.saturating_mul(STALE_AFTER_REFRESHES)
            {
                self.estimate_due = true;
            }
        }
        self.h = (h * fac).max(h_min);
        self.retry = true;
    }

    /// `(clamped factor, factor before the clamp)` of the next step after an accepted step
    /// with error ratio `err`, both at most 1 after a rejection (the second tells a step
    /// shortened to meet an end time whether the planned size would have passed). The PI
    /// rule remembers `err`.
    fn accept_factor(&mut self, err: T, after_rejection: bool) -> (T, T) {
        let (raw, fac_min, fac_max) = match &self.rule.pi {
            None => (
                classic_factor(err),
                T::from_f64(CLASSIC_FAC_MIN),
                T::from_f64(CLASSIC_FAC_MAX),
            ),
            Some(pi) => {
                let raw = pi_factor(pi, err) * self.err_prev.powf(pi.beta);
                self.err_prev = err.max(pi.err_floor);
                (raw, pi.fac_min, pi.fac_max)
            }
        };
        if after_rejection {
            (raw.clamp(fac_min, T::ONE), raw.min(T::ONE))
        } else {
            (raw.clamp(fac_min, fac_max), raw)
        }
    }

    /// The factor (at most 1) of the retry of a step rejected with error ratio `err > 1`;
    /// the PI rule's memory is left alone.
    fn reject_factor(&self, err: T) -> T {
        match &self.rule.pi {
            None => classic_factor(err).clamp(T::from_f64(CLASSIC_FAC_MIN), T::ONE),
            // err > 1 (or +inf, giving fac_min); the floor only guards a misuse with err = 0.
            Some(pi) => pi_factor(pi, err).clamp(pi.fac_min, T::ONE),
        }
    }
}

/// England's raw factor `0.9 err^(-1/5)` (`T::MAX` for a zero error; 0 for `+inf`).
fn classic_factor<T: Real>(err: T) -> T {
    if err > T::ZERO {
        T::from_f64(CLASSIC_SAFETY) * err.powf(T::from_f64(CLASSIC_EXPONENT))
    } else {
        T::MAX
    }
}

/// The PI rule's raw factor without its memory, `safety · max(err, err_floor)^(-alpha)`
/// (after an accepted step it is multiplied by `err_prev^beta`).
fn pi_factor<T: Real>(pi: &PiSettings<T>, err: T) -> T {
    pi.safety * err.max(pi.err_floor).powf(-pi.alpha)
}

/// Hairer's starting step (Hairer, Nørsett & Wanner, *Solving ODEs I*, II.4) for a method
/// of order `order` (England: 4), from `f0 = f(t0, y0)` and one explicit Euler step
/// (one right-hand-side evaluation, counted in `evals`):
///
/// 1. `d0 = ‖y0‖`, `d1 = ‖f0‖` (max norm weighted by `atol_i + rtol |y0_i|`; components
///    with a zero weight are left out);
/// 2. `h0 = 0.01 d0/d1`, or `1e-6` if either is below `1e-5`;
/// 3. `d2 = ‖f(t0 + h0, y0 + h0 f0) - f0‖ / h0`;
/// 4. `h1 = (0.01 / max(d1, d2))^(1/(order+1))`, or `max(1e-6, 1e-3 h0)` if that maximum
///    is below `1e-15`;
/// 5. `h = min(100 h0, h1, h_max)`.
#[allow(clippy::too_many_arguments)]
pub fn initial_step<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t0: T,
    y0: &[T; N],
    f0: &[T; N],
    tol: &Tolerance<T, N>,
    order: u32,
    h_max: T,
    evals: &mut u32,
) -> Result<T> {
    let mut d0 = T::ZERO;
    let mut d1 = T::ZERO;
    for (i, (y, f)) in y0.iter().zip(f0.iter()).enumerate() {
        let sc = tol.scale(i, *y);
        if sc > T::ZERO {
            d0 = d0.max(y.abs() / sc);
            d1 = d1.max(f.abs() / sc);
        }
    }
    let small = T::from_f64(1e-5);
    let mut h0 = if d0 < small || d1 < small {
        T::from_f64(1e-6)
    } else {
        T::from_f64(0.01) * d0 / d1
    };
    if h_max.is_finite() && h_max > T::ZERO {
        h0 = h0.min(h_max);
    }
    let mut y1 = [T::ZERO; N];
    for ((a, y), f) in y1.iter_mut().zip(y0.iter()).zip(f0.iter()) {
        *a = *y + h0 * *f;
    }
    let mut f1 = [T::ZERO; N];
    sys.rhs(t0 + h0, &y1, &mut f1);
    *evals = evals.saturating_add(1);
    let mut d2 = T::ZERO;
    for (i, ((a, b), y)) in f1.iter().zip(f0.iter()).zip(y0.iter()).enumerate() {
        if !a.is_finite() {
            return Err(Error::NonFinite {
                t: (t0 + h0).to_f64(),
                component: i,
            });
        }
        let sc = tol.scale(i, *y);
        if sc > T::ZERO {
            d2 = d2.max((*a - *b).abs() / sc);
        }
    }
    d2 /= h0;
    let m = d1.max(d2);
    let h1 = if m <= T::from_f64(1e-15) {
        (h0 * T::from_f64(1e-3)).max(T::from_f64(1e-6))
    } else {
        (T::from_f64(0.01) / m).powf(T::ONE / T::from_usize(order as usize + 1))
    };
    let mut h = (T::from_f64(100.0) * h0).min(h1);
    if h_max.is_finite() && h_max > T::ZERO {
        h = h.min(h_max);
    }
    Ok(h)
}

#[cfg(test)]
mod tests {
    use super::{StepController, Stepper};
    use crate::{PiSettings, StepControl, StiffnessCap};

    /// Step bounds wide enough never to bind.
    const H_MIN: f64 = 1e-300;
    const H_MAX: f64 = 1e300;

    /// The factor of the next step after accepting a unit step with error ratio `err`.
    fn accepted(c: &mut StepController<f64, 1>, err: f64) -> f64 {
        c.set_step_size(1.0);
        c.accept(err, 1.0, 1.0, H_MIN, H_MAX);
        c.step_size()
    }

    /// The factor of the retry after rejecting a unit step with error ratio `err`.
    fn rejected(c: &mut StepController<f64, 1>, err: f64) -> f64 {
        c.reject(err, 1.0, H_MIN);
        c.step_size()
    }

    /// A controller with the PI rule `pi` and nothing else.
    fn pi_rule(pi: PiSettings<f64>) -> StepController<f64, 1> {
        let control = StepControl {
            pi: Some(pi),
            ..StepControl::classic()
        };
        StepController::new(Stepper::England, control, 1.0)
    }

    /// With `err = C h^5` the PI rule's accepted steps settle where
    /// `safety · e^(-alpha) · e^(beta) = 1`, i.e. `e* = safety^(1/(alpha - beta))`
    /// `= 0.9^(1/0.06) = 0.1725` for Hairer's settings, and the rule remembers that error.
    #[test]
    fn the_pi_rule_settles_where_its_factor_is_one() {
        let pi = PiSettings::<f64>::hairer();
        assert!((pi.alpha - 0.14).abs() < 1e-15 && (pi.beta - 0.08).abs() < 1e-15);
        let mut c = pi_rule(pi);
        c.set_step_size(0.01);
        let mut err = 0.0;
        for _ in 0..400 {
            let h = c.step_size();
            err = 3.0e4 * h.powi(5);
            assert!(err <= 1.0);
            c.accept(err, h, h, H_MIN, H_MAX);
        }
        let target = 0.9f64.powf(1.0 / (0.14 - 0.08));
        assert!((err / target - 1.0).abs() < 1e-6, "{err} vs {target}");
        assert_eq!(c.err_prev, err);
    }

    /// The error floor 1e-4 bounds growth from a zero error to `0.9 · 1e4^0.14 = 3.27`
    /// (then `0.9 · 1e4^0.06 = 1.57` per step); a lower floor meets `fac_max`; no increase
    /// right after a rejection; a rejection's factor is `0.9 err^(-0.14)` down to
    /// `fac_min` and leaves the memory alone.
    #[test]
    fn the_pi_rule_is_bounded_by_its_floor_and_factors() {
        let mut c = pi_rule(PiSettings::hairer());
        assert!((accepted(&mut c, 0.0) - 0.9 * 1e4f64.powf(0.14)).abs() < 1e-12);
        assert!((accepted(&mut c, 0.0) - 0.9 * 1e4f64.powf(0.06)).abs() < 1e-12);
        let retry = rejected(&mut c, 2.0);
        c.accept(1e-8, retry, retry, H_MIN, H_MAX);
        assert_eq!(c.step_size(), retry);
        let mut c = pi_rule(PiSettings {
            err_floor: 1e-12,
            ..PiSettings::hairer()
        });
        assert_eq!(accepted(&mut c, 0.0), 10.0);
        let mut c = pi_rule(PiSettings::hairer());
        assert_eq!(rejected(&mut c, f64::INFINITY), 0.2);
        assert!((rejected(&mut c, 1.5) - 0.9 * 1.5f64.powf(-0.14)).abs() < 1e-15);
        assert_eq!(c.err_prev, 1.0, "a rejection leaves the memory alone");
    }

    /// England's double step is two RK4 half steps, each within the boundary, so its cap
    /// is exactly twice a single step's: `2 · 0.95 · 2√2 / ρ` against `0.95 · 2√2 / ρ`.
    #[test]
    fn a_double_step_is_capped_at_two_single_steps() {
        let cap = StiffnessCap::<f64>::new();
        let rho = 2.5e5;
        let single = cap.step_cap_at(rho, 1e-6, Stepper::Pair.steps());
        let double = cap.step_cap_at(rho, 1e-6, Stepper::England.steps());
        assert_eq!(double, 2.0 * single);
        let expected = 0.95 * 2.0 * core::f64::consts::SQRT_2 / rho;
        assert!(
            (single - expected).abs() <= 1e-15 * expected,
            "{single} {expected}"
        );
        assert_eq!(double, cap.h_cap_at(rho, 1e-6));
    }

    /// England's rule: after an accepted step with error ratio `err` the next step is
    /// `h · 0.9 err^(-1/5)`; after a rejection `h · 0.9 err^(-1/5)` too (at most 1), and
    /// the retry's acceptance does not grow the step whatever its error.
    #[test]
    fn the_classic_rule_grows_shrinks_and_holds_after_a_retry() {
        let (h_min, h_max, h) = (1e-9, 1.0, 1e-3);
        let mut c = StepController::<f64, 2>::new(Stepper::England, StepControl::classic(), h);
        assert_eq!(c.propose(h_min), h);
        c.accept(0.5, h, h, h_min, h_max);
        let grown = h * 0.9 * 0.5f64.powf(-0.2);
        assert!((c.step_size() - grown).abs() <= 1e-15 * grown);
        c.reject(2.0, h, h_min);
        let shrunk = h * 0.9 * 2.0f64.powf(-0.2);
        assert!((c.step_size() - shrunk).abs() <= 1e-15 * shrunk);
        let retry = c.step_size();
        c.accept(1e-6, retry, retry, h_min, h_max);
        assert_eq!(c.step_size(), retry);
        // The next accepted step from a new point may grow again (at most 5 times).
        c.begin_step();
        c.accept(1e-6, retry, retry, h_min, h_max);
        assert_eq!(c.step_size(), 5.0 * retry);
    }

    /// A proposal never exceeds the cap nor falls below `h_min`; without a cap it is the
    /// next size itself.
    #[test]
    fn a_proposal_is_within_the_cap_and_h_min() {
        let mut c = StepController::<f64, 2>::new(Stepper::Pair, StepControl::classic(), 0.5);
        assert_eq!(c.propose(1e-3), 0.5);
        let control = StepControl::classic_capped();
        c = StepController::new(Stepper::Pair, control, 0.5);
        c.stiffness.h_cap = 0.1;
        assert_eq!(c.propose(1e-3), 0.1);
        assert_eq!(c.propose(0.2), 0.2);
    }
}
