//! Explicit embedded Runge-Kutta pairs as data ([`PairTableau`]) and one adaptive
//! integrator for any of them ([`Pair`]): Merson's 4(3) pair for the imaginary axis
//! ([`crate::MERSON`], [`crate::Merson`]) and Dormand and Prince's 5(4) pair for
//! accuracy-limited runs ([`crate::DORMAND_PRINCE`], [`crate::DormandPrince`]).
//!
//! One step of size `h` from `(t, y)` with `k_1 = f(t, y)`:
//! `k_i = f(t + c_i h, y + h Σ_{j<i} a_ij k_j)`, the solution `y1 = y + h Σ b_i k_i`, the
//! embedded `ŷ1 = y + h Σ b̂_i k_i`, and the error ratio
//! `err = max_i |y1_i - ŷ1_i| / (atol_i + rtol · max(|y_i|, |y1_i|))` (England's norm,
//! docs/MODEL.md §3.16), accepted if `err <= 1`. The next step comes from Hairer's PI
//! controller with the pair's exponents, clamped to `[h_min, h_max]`, and optionally
//! capped at a fraction of the stability boundary over the Jacobian's spectral radius
//! ([`StiffnessCap`], tolerance-scaled as England's).
//!
//! The end point's derivative `f(t1, y1)` is the next step's `k_1`: a pair that is
//! "first same as last" (FSAL: its last stage is evaluated at `y1`, as Dormand-Prince's)
//! gets it from that stage; any other (Merson's) evaluates it once after acceptance. So a
//! step costs `S − 1` evaluations with FSAL and `S` without, and a rejection `S − 1`.
//!
//! Dense output: the cubic Hermite interpolant on the step's ends ([`Dense::cubic`], third
//! order between the nodes, exact at them).

use core::ops::ControlFlow;

use crate::solve::england::{first_non_finite, Sampler};
use crate::solve::step_size::{StepController, Stepper};
use crate::{
    Dense, EnglandConfig, Error, OdeSystem, PiSettings, Real, Result, SolverStats, StepControl,
    StiffnessCap,
};

/// An explicit embedded Runge-Kutta pair of `S` stages as data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairTableau<const S: usize> {
    /// Stage coefficients `a[i][j]`, `j < i`.
    pub a: [[f64; S]; S],
    /// Weights of the propagated solution.
    pub b: [f64; S],
    /// Weights of the embedded solution (for the error estimate only).
    pub b_hat: [f64; S],
    /// Nodes.
    pub c: [f64; S],
    /// Order of `b`.
    pub order: u32,
    /// Order of `b̂`.
    pub embedded_order: u32,
    /// The last stage is `f(t + h, y1)` (`c = 1`, its row of `a` is `b`): first same as last.
    pub fsal: bool,
    /// The stability region's reach along the imaginary axis, `|hλ|` (what the stiffness
    /// cap scales).
    pub imaginary_boundary: f64,
    /// Hairer's PI exponents `(alpha, beta)` for this pair's estimate.
    pub pi: (f64, f64),
}

impl<const S: usize> PairTableau<S> {
    /// Hairer's PI settings with this pair's exponents: safety 0.9, factors in
    /// `[0.2, 10]` (no growth right after a rejection).
    pub fn pi_settings<T: Real>(&self) -> PiSettings<T> {
        PiSettings::new(
            T::from_f64(self.pi.0),
            T::from_f64(self.pi.1),
            T::from_f64(0.9),
            T::from_f64(0.2),
            T::from_f64(10.0),
        )
    }
}

/// The adaptive integrator of an embedded pair for `N` equations (no allocation;
/// reusable): [`crate::Merson`] and [`crate::DormandPrince`] are its two instances.
#[derive(Clone, Debug)]
pub struct Pair<T, const N: usize, const S: usize> {
    tab: &'static PairTableau<S>,
    config: EnglandConfig<T, N>,
    cap: Option<StiffnessCap<T>>,
    k: [[T; N]; S],
    stats: SolverStats,
}

/// Checks a pair's configuration: tolerances, step sizes.
fn check_config<T: Real, const N: usize>(c: &EnglandConfig<T, N>) -> Result<()> {
    let bad = |field: &'static str, rule: &'static str, v: T| {
        Err(Error::InvalidParameter {
            field,
            rule,
            value: v.to_f64(),
        })
    };
    if !(c.tol.rtol.is_finite() && c.tol.rtol >= T::ZERO) {
        return bad("rtol", "must be finite and non-negative", c.tol.rtol);
    }
    if let Some(a) = c
        .tol
        .atol
        .iter()
        .find(|a| !(a.is_finite() && **a > T::ZERO))
    {
        return bad("atol", "must be positive and finite", *a);
    }
    for (field, v) in [("h_init", c.h_init), ("h_min", c.h_min), ("h_max", c.h_max)] {
        if !(v.is_finite() && v > T::ZERO) {
            return bad(field, "must be positive and finite", v);
        }
    }
    if c.h_min > c.h_max {
        return bad("h_min", "must not exceed h_max", c.h_min);
    }
    Ok(())
}

impl<T: Real, const N: usize, const S: usize> Pair<T, N, S> {
    /// A solver of the pair `tab` with `config` (single-step sizes). Errors: a negative or
    /// non-finite tolerance, a non-positive or non-finite step size, `h_min > h_max`.
    pub fn with_tableau(tab: &'static PairTableau<S>, config: EnglandConfig<T, N>) -> Result<Self> {
        check_config(&config)?;
        Ok(Self {
            tab,
            config,
            cap: None,
            k: [[T::ZERO; N]; S],
            stats: SolverStats::default(),
        })
    }

    /// As [`Pair::with_tableau`], the step also capped by the stiffness estimate with
    /// `cap`'s fraction, refresh interval, power-iteration settings and tolerance scaling
    /// ([`StiffnessCap::rtol_full`]); its `boundary` is replaced by the pair's
    /// [`PairTableau::imaginary_boundary`].
    pub fn with_tableau_and_cap(
        tab: &'static PairTableau<S>,
        config: EnglandConfig<T, N>,
        cap: StiffnessCap<T>,
    ) -> Result<Self> {
        let mut s = Self::with_tableau(tab, config)?;
        if !(cap.fraction > T::ZERO && cap.fraction <= T::ONE) {
            return Err(Error::InvalidParameter {
                field: "cap.fraction",
                rule: "must lie in (0, 1]",
                value: cap.fraction.to_f64(),
            });
        }
        if let Some(r0) = cap.rtol_full {
            if !(r0.is_finite() && r0 > T::ZERO) {
                return Err(Error::InvalidParameter {
                    field: "cap.rtol_full",
                    rule: "must be positive and finite",
                    value: r0.to_f64(),
                });
            }
        }
        s.cap = Some(StiffnessCap {
            boundary: T::from_f64(tab.imaginary_boundary),
            ..cap
        });
        Ok(s)
    }

    /// The step control of one integration: Hairer's PI controller with the pair's
    /// exponents and the stiffness cap if any, from the configured first step.
    fn step_controller(&self) -> StepController<T, N> {
        let rule = StepControl {
            pi: Some(self.tab.pi_settings::<T>()),
            hairer_start: false,
            stiffness_cap: self.cap,
            per_unit_step: None,
        };
        let cfg = &self.config;
        let h_init = cfg.h_init.min(cfg.h_max).max(cfg.h_min);
        StepController::new(Stepper::Pair, rule, h_init)
    }

    /// The pair's tableau.
    pub fn tableau(&self) -> &'static PairTableau<S> {
        self.tab
    }

    /// The configuration.
    pub fn config(&self) -> &EnglandConfig<T, N> {
        &self.config
    }

    /// The counters of the last (or current) integration.
    pub fn stats(&self) -> SolverStats {
        self.stats
    }

    /// Integrates `y` from `t0` to `t_end`, calling `node(t, y, f)` at the start and at
    /// every accepted step end (`f = f(t, y)`, as the Hermite interpolant needs);
    /// `ControlFlow::Break` stops the run early (not an error). Errors: a non-finite
    /// state or derivative, the step below `h_min`, the step budget used up.
    pub fn integrate<Sys, F>(
        &mut self,
        sys: &Sys,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut node: F,
    ) -> Result<SolverStats>
    where
        Sys: OdeSystem<T, N>,
        F: FnMut(T, &[T; N], &[T; N]) -> ControlFlow<()>,
    {
        self.integrate_shared(sys, t0, y, t_end, &mut Direct::new(sys, t0, &mut node))
    }

    /// [`Pair::integrate`] for a [`Sampler`], which evaluates the system at every step end
    /// itself (the next step's first stage, or an FSAL pair's last stage of each attempt)
    /// and is shown the start and each accepted end.
    pub(crate) fn integrate_shared<Sys: OdeSystem<T, N>>(
        &mut self,
        sys: &Sys,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        sampler: &mut dyn Sampler<T, N>,
    ) -> Result<SolverStats> {
        self.walk(sys, t0, y, t_end, sampler, |_, _, _, _, _, _| {
            ControlFlow::Continue(())
        })
    }

    /// Integrates from `t0` to `t_end` calling `observer(&dense)` once per accepted step
    /// with its continuous extension ([`Dense::cubic`]), in time order;
    /// [`ControlFlow::Break`] stops early (still `Ok`, `y` at the end of that step). No
    /// call if `t_end == t0`.
    pub fn integrate_dense<Sys, F>(
        &mut self,
        sys: &Sys,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut observer: F,
    ) -> Result<SolverStats>
    where
        Sys: OdeSystem<T, N>,
        F: FnMut(&Dense<'_, T, N>) -> ControlFlow<()>,
    {
        let mut none = |_: T, _: &[T; N], _: &[T; N]| ControlFlow::Continue(());
        let mut s = Direct::new(sys, t0, &mut none);
        let mut failed = None;
        let stats =
            self.walk(
                sys,
                t0,
                y,
                t_end,
                &mut s,
                |ta, ya, fa, tb, yb, fb| match Dense::cubic([ta, tb], [ya, yb], [fa, fb]) {
                    Ok(d) => observer(&d),
                    Err(e) => {
                        failed = Some(e);
                        ControlFlow::Break(())
                    }
                },
            )?;
        match failed {
            Some(e) => Err(e),
            None => Ok(stats),
        }
    }

    /// The integration loop: `sampler` evaluates and shows the points, `step_done` sees
    /// each accepted step's ends `(t0, y0, f0, t1, y1, f1)` before the end is shown.
    fn walk<Sys, G>(
        &mut self,
        sys: &Sys,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        sampler: &mut dyn Sampler<T, N>,
        mut step_done: G,
    ) -> Result<SolverStats>
    where
        Sys: OdeSystem<T, N>,
        G: FnMut(T, &[T; N], &[T; N], T, &[T; N], &[T; N]) -> ControlFlow<()>,
    {
        self.stats = SolverStats::default();
        if !(t0.is_finite() && t_end.is_finite() && t_end >= t0) {
            return Err(Error::InvalidParameter {
                field: "t_end",
                rule: "must be finite and not before t0",
                value: t_end.to_f64(),
            });
        }
        let cfg = self.config;
        let mut ctl = self.step_controller();
        let mut t = t0;
        let mut f0 = [T::ZERO; N];
        sampler.evaluate(t, y, &mut f0);
        self.count_checked(t, y, &f0)?;
        if sampler.show().is_break() {
            return Ok(self.stats);
        }
        let mut y1 = [T::ZERO; N];
        let mut f1 = [T::ZERO; N];
        while t < t_end {
            let steps = self.stats.accepted.saturating_add(self.stats.rejected);
            if steps >= cfg.max_steps {
                return Err(Error::StepBudgetExceeded {
                    t: t.to_f64(),
                    steps,
                });
            }
            if ctl.needs_preparation() {
                ctl.prepare(sys, t, y, &f0, &cfg, &mut self.stats.rhs_evals)?;
            }
            let h = ctl.propose(cfg.h_min);
            // Land on t_end: stretch by at most 1 %, or take the short last step.
            let rest = t_end - t;
            let last = h * T::from_f64(1.01) >= rest;
            let hs = if last { rest } else { h };
            let t1 = if last { t_end } else { t + hs };
            let err = self.attempt(sys, t, y, &f0, hs, t1, &mut y1, &mut f1, sampler)?;
            if err <= T::ONE {
                // After a last step the next size is not used.
                ctl.accept(err, hs, h, cfg.h_min, cfg.h_max);
                if !self.tab.fsal {
                    sampler.evaluate(t1, &y1, &mut f1);
                    self.count_checked(t1, &y1, &f1)?;
                }
                self.stats.accepted = self.stats.accepted.saturating_add(1);
                let flow = step_done(t, y, &f0, t1, &y1, &f1);
                *y = y1;
                f0 = f1;
                t = t1;
                if flow.is_break() || sampler.show().is_break() {
                    break;
                }
            } else {
                self.stats.rejected = self.stats.rejected.saturating_add(1);
                if hs <= cfg.h_min {
                    return Err(Error::StepSizeUnderflow {
                        t: t.to_f64(),
                        h: hs.to_f64(),
                    });
                }
                ctl.reject(err, hs, cfg.h_min);
            }
        }
        Ok(self.stats)
    }

    /// Counts one evaluation at `(t, y)` and checks that `y` and `f` are finite.
    fn count_checked(&mut self, t: T, y: &[T; N], f: &[T; N]) -> Result<()> {
        self.stats.rhs_evals = self.stats.rhs_evals.saturating_add(1);
        match first_non_finite(y).or_else(|| first_non_finite(f)) {
            Some(i) => Err(Error::NonFinite {
                t: t.to_f64(),
                component: i,
            }),
            None => Ok(()),
        }
    }

    /// One attempt of `hs` from `(t, y)` with `f0 = f(t, y)`: the stages into `k`, the
    /// solution into `y1` (and, for an FSAL pair, `f(t1, y1)` into `f1`, by `sampler`);
    /// returns the error ratio (infinite where a stage is not finite, so that the step is
    /// rejected).
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn attempt<Sys: OdeSystem<T, N>>(
        &mut self,
        sys: &Sys,
        t: T,
        y: &[T; N],
        f0: &[T; N],
        hs: T,
        t1: T,
        y1: &mut [T; N],
        f1: &mut [T; N],
        sampler: &mut dyn Sampler<T, N>,
    ) -> Result<T> {
        let tab = self.tab;
        let mut arg = [T::ZERO; N];
        if let Some(k0) = self.k.first_mut() {
            *k0 = *f0;
        }
        // The stages before an FSAL pair's last.
        let explicit = if tab.fsal { S.saturating_sub(1) } else { S };
        for i in 1..explicit {
            let (done, todo) = self.k.split_at_mut(i);
            let (Some(ai), Some(ci), Some(ki)) = (tab.a.get(i), tab.c.get(i), todo.first_mut())
            else {
                continue;
            };
            combine(y, hs, ai, done, &mut arg);
            sys.rhs(t + T::from_f64(*ci) * hs, &arg, ki);
            self.stats.rhs_evals = self.stats.rhs_evals.saturating_add(1);
        }
        combine(y, hs, &tab.b, self.k.get(..explicit).unwrap_or(&[]), y1);
        if tab.fsal {
            sampler.evaluate(t1, y1, f1);
            self.stats.rhs_evals = self.stats.rhs_evals.saturating_add(1);
            if let Some(last) = self.k.last_mut() {
                *last = *f1;
            }
        }
        // Error ratio: e = h Σ (b_i - b̂_i) k_i, the sum first, one stage at a time.
        let mut e = [T::ZERO; N];
        for ((bi, bh), ki) in tab.b.iter().zip(tab.b_hat.iter()).zip(self.k.iter()) {
            let d = *bi - *bh;
            if d != 0.0 {
                let c = T::from_f64(d);
                for (en, kn) in e.iter_mut().zip(ki.iter()) {
                    *en += c * *kn;
                }
            }
        }
        for en in e.iter_mut() {
            *en *= hs;
        }
        // A non-finite solution rejects the step (its scale would be infinite, its ratio 0).
        if first_non_finite(y1).is_some() {
            return Ok(T::INFINITY);
        }
        let cfg = &self.config;
        let mut err = T::ZERO;
        for (((en, y1n), y0n), atol) in e
            .iter()
            .zip(y1.iter())
            .zip(y.iter())
            .zip(cfg.tol.atol.iter())
        {
            let scale = *atol + cfg.tol.rtol * y0n.abs().max(y1n.abs());
            let r = en.abs() / scale;
            // A non-finite stage rejects the step.
            err = if r.is_finite() {
                err.max(r)
            } else {
                T::INFINITY
            };
        }
        Ok(err)
    }
}

/// `out = y + h Σ_j w_j k_j` over the stages given (zero weights skipped): the weighted sum
/// of the stages first, one stage at a time (a vector update per stage, no index per
/// component), then one addition to `y`, so that in f32 the solution is rounded once per
/// step at its own scale, not once per stage.
#[inline(always)]
fn combine<T: Real, const N: usize, const S: usize>(
    y: &[T; N],
    h: T,
    w: &[f64; S],
    k: &[[T; N]],
    out: &mut [T; N],
) {
    let mut acc = [T::ZERO; N];
    for (wj, kj) in w.iter().zip(k.iter()) {
        if *wj != 0.0 {
            let c = T::from_f64(*wj);
            for (a, kn) in acc.iter_mut().zip(kj.iter()) {
                *a += c * *kn;
            }
        }
    }
    for ((o, yn), a) in out.iter_mut().zip(y.iter()).zip(acc.iter()) {
        *o = *yn + h * *a;
    }
}

/// A [`Sampler`] that evaluates the system itself and shows each point to a closure
/// `node(t, y, f)` ([`Pair::integrate`]).
struct Direct<'a, Sys, T, const N: usize, F> {
    sys: &'a Sys,
    t: T,
    y: [T; N],
    f: [T; N],
    node: &'a mut F,
}

impl<'a, Sys, T: Real, const N: usize, F> Direct<'a, Sys, T, N, F> {
    /// A sampler of `sys` showing each point to `node`.
    fn new(sys: &'a Sys, t0: T, node: &'a mut F) -> Self {
        Self {
            sys,
            t: t0,
            y: [T::ZERO; N],
            f: [T::ZERO; N],
            node,
        }
    }
}

impl<Sys, T, const N: usize, F> Sampler<T, N> for Direct<'_, Sys, T, N, F>
where
    Sys: OdeSystem<T, N>,
    T: Real,
    F: FnMut(T, &[T; N], &[T; N]) -> ControlFlow<()>,
{
    fn evaluate(&mut self, t: T, y: &[T; N], f: &mut [T; N]) {
        self.sys.rhs(t, y, f);
        self.t = t;
        self.y = *y;
        self.f = *f;
    }

    fn show(&mut self) -> ControlFlow<()> {
        (self.node)(self.t, &self.y, &self.f)
    }
}

/// What the pairs' tests share.
#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::panic)]
pub(super) mod testing {
    use super::*;
    use crate::Tolerance;

    /// `|R(iy)|` of the stability polynomial with coefficients `p` (of `z⁰, z¹, ...`).
    pub(in crate::solve) fn imaginary_modulus(p: &[f64], y: f64) -> f64 {
        let (mut re, mut im) = (0.0, 0.0);
        for (k, ck) in p.iter().enumerate() {
            // (iy)^k = y^k i^k
            let yk = ck * y.powi(k as i32);
            match k % 4 {
                0 => re += yk,
                1 => im += yk,
                2 => re -= yk,
                _ => im -= yk,
            }
        }
        (re * re + im * im).sqrt()
    }

    /// `x'' = -x`, `(x, v) = (cos t, -sin t)`.
    pub(in crate::solve) struct Oscillator;
    impl OdeSystem<f64, 2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = y[1];
            d[1] = -y[0];
        }
    }

    /// An adaptive run of `tab` on the oscillator over 10 s at rtol 1e-4, 1e-6, 1e-8: the
    /// global error within 100 rtol, and the evaluations `1 + per_accepted · accepted +
    /// per_rejected · rejected`.
    pub(in crate::solve) fn meets_its_tolerance<const S: usize>(
        tab: &'static PairTableau<S>,
        per_accepted: u32,
        per_rejected: u32,
    ) {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let cfg = EnglandConfig {
                tol: Tolerance::scalar(rtol, rtol),
                h_init: 1e-3,
                h_min: 1e-12,
                h_max: 1.0,
                max_steps: 1_000_000,
            };
            let mut m = Pair::<f64, 2, S>::with_tableau(tab, cfg).unwrap();
            let mut y = [1.0, 0.0];
            let st = m
                .integrate(&Oscillator, 0.0, &mut y, 10.0, |_, _, _| {
                    ControlFlow::Continue(())
                })
                .unwrap();
            let e = (y[0] - 10f64.cos()).abs().max((y[1] + 10f64.sin()).abs());
            // Global error within a modest multiple of the tolerance times the span.
            assert!(e < 10.0 * 10.0 * rtol, "rtol {rtol}: {e:e}");
            let evals = 1 + per_accepted * st.accepted + per_rejected * st.rejected;
            assert_eq!(st.rhs_evals, evals, "rtol {rtol}");
        }
    }
}
