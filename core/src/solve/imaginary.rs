//! An explicit Runge-Kutta pair of order 4 for the imaginary axis: Merson's 4(3) pair.
//!
//! Source: R. H. Merson, "An operational method for the study of integration processes",
//! *Proc. Symp. Data Processing*, Weapons Research Establishment, Salisbury, Australia,
//! 1957, pp. 110-125; tableau as given by Hairer, Nørsett and Wanner, *Solving Ordinary
//! Differential Equations I* (2nd ed., Springer 1993), §II.4, Table 4.1 ("Merson 4(5)"):
//!
//! ```text
//!   0  |
//!  1/3 | 1/3
//!  1/3 | 1/6   1/6
//!  1/2 | 1/8   0     3/8
//!   1  | 1/2   0    -3/2   2
//! -----+-----------------------------
//!   b  | 1/6   0     0     2/3   1/6     order 4
//!   b̂  | 1/10  0     3/10  2/5   1/5     order 3 (order 5 on linear problems)
//! ```
//!
//! Why this pair: the stiffest modes of the cam model are nearly imaginary, so the step
//! is set by how far the stability region reaches along the imaginary axis. Merson's
//! stability polynomial is `R(z) = 1 + z + z²/2 + z³/6 + z⁴/24 + z⁵/144`, and
//! `|R(iy)| <= 1` for `|y| <= √12 = 3.464`: the largest interval of any five-stage
//! method of order 4 (the fifth-degree coefficient is the family's only freedom, and
//! 1/144 maximises the interval: tested below). Per evaluation that is 0.693 (the step's
//! last stage point `f(t1, y1)` is not a stage, but it is the next step's first stage, so
//! a step costs 5 evaluations), against England's 0.514 (11 evaluations per double step
//! of `2 · 2√2`) and classic RK4's 0.707 without any error estimate.
//!
//! Dense output: Merson gives none; [`hermite`] is the cubic Hermite interpolant on the
//! step ends `(t0, y0, f0)`, `(t1, y1, f1)` (third order between the nodes, exact at
//! them). The bench samples every method without its own interpolant through the quintic
//! Hermite through three consecutive step ends instead.
//!
//! Step-size control: `err = max_i |y1_i - ŷ1_i| / (atol_i + rtol · max(|y0_i|, |y1_i|))`
//! (England's norm, docs/MODEL.md §3.16), accepted if `err <= 1`. The next step is set by
//! Hairer's PI controller ([`PiController`]) with the exponents for an estimate of local
//! order 4 (`alpha = 0.7/4`, `beta = 0.4/4`; safety 0.9, factors in `[0.2, 10]`, no
//! growth right after a rejection: the PI-capped England's settings with 5 replaced by 4),
//! clamped to `[h_min, h_max]`. Optionally ([`Merson::with_cap`]) the step is also capped
//! at `fraction · √12 / ρ`, `ρ` the Jacobian's spectral radius by power iteration
//! ([`spectral_radius`], [`StiffnessCap`]'s settings with the boundary √12), so that at
//! loose tolerances the step sits just inside the stability limit instead of being found
//! there by rejections.

use core::ops::ControlFlow;

use crate::{
    spectral_radius, EnglandConfig, Error, OdeSystem, PiController, Real, Result, StiffnessCap,
};

/// Stages of the pair.
pub const STAGES: usize = 5;

/// An explicit Runge-Kutta pair as data: `A` (strictly lower triangular), `b` (the
/// propagated solution), `b̂` (the embedded estimate), `c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairTableau {
    /// Stage coefficients `a[i][j]`, `j < i`.
    pub a: [[f64; STAGES]; STAGES],
    /// Weights of the solution (order 4).
    pub b: [f64; STAGES],
    /// Weights of the embedded solution (order 3).
    pub b_hat: [f64; STAGES],
    /// Nodes.
    pub c: [f64; STAGES],
    /// Order of `b`.
    pub order: u32,
    /// Order of `b̂`.
    pub embedded_order: u32,
}

/// Merson's 4(3) pair (see the module documentation for its source).
pub const MERSON: PairTableau = PairTableau {
    a: [
        [0.0, 0.0, 0.0, 0.0, 0.0],
        [1.0 / 3.0, 0.0, 0.0, 0.0, 0.0],
        [1.0 / 6.0, 1.0 / 6.0, 0.0, 0.0, 0.0],
        [1.0 / 8.0, 0.0, 3.0 / 8.0, 0.0, 0.0],
        [1.0 / 2.0, 0.0, -3.0 / 2.0, 2.0, 0.0],
    ],
    b: [1.0 / 6.0, 0.0, 0.0, 2.0 / 3.0, 1.0 / 6.0],
    b_hat: [1.0 / 10.0, 0.0, 3.0 / 10.0, 2.0 / 5.0, 1.0 / 5.0],
    c: [0.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 2.0, 1.0],
    order: 4,
    embedded_order: 3,
};

/// Merson's imaginary-axis stability boundary, `|hλ|` (√12).
pub const IMAGINARY_BOUNDARY: f64 = 3.464_101_615_137_754_6;

/// Hairer's PI controller for an estimate of local order 4 (see the module documentation).
pub fn merson_pi<T: Real>() -> PiController<T> {
    PiController::new(
        T::from_f64(0.7 / 4.0),
        T::from_f64(0.4 / 4.0),
        T::from_f64(0.9),
        T::from_f64(0.2),
        T::from_f64(10.0),
    )
}

/// Work counters of [`Merson::integrate`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MersonStats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations: `1 + 5 · accepted + 4 · rejected` (the first stage of
    /// a step is the previous step's end derivative, and a retry reuses it), plus the
    /// stiffness cap's power iterations.
    pub rhs_evals: u64,
}

/// Merson's adaptive pair for `N` equations (no allocation; reusable).
#[derive(Clone, Debug)]
pub struct Merson<T, const N: usize> {
    config: EnglandConfig<T, N>,
    cap: Option<StiffnessCap<T>>,
    k: [[T; N]; STAGES],
}

impl<T: Real, const N: usize> Merson<T, N> {
    /// A solver with `config` (step sizes are single-step sizes here). Errors: a
    /// non-positive or non-finite tolerance or step size, `h_min > h_max`.
    pub fn new(config: EnglandConfig<T, N>) -> Result<Self> {
        let bad = |field: &'static str, rule: &'static str, v: T| {
            Err(Error::InvalidParameter {
                field,
                rule,
                value: v.to_f64(),
            })
        };
        let c = &config;
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
        Ok(Self {
            config,
            cap: None,
            k: [[T::ZERO; N]; STAGES],
        })
    }

    /// As [`Merson::new`], the step also capped by the stiffness estimate with `cap`'s
    /// fraction, refresh interval and power-iteration settings (its `boundary` is replaced
    /// by Merson's √12), and its tolerance scaling ([`StiffnessCap::rtol_full`]: the
    /// fraction shrinks as `(rtol / rtol_full)^(1/5)` below `rtol_full`, issue 22).
    pub fn with_cap(config: EnglandConfig<T, N>, cap: StiffnessCap<T>) -> Result<Self> {
        let mut s = Self::new(config)?;
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
            boundary: T::from_f64(IMAGINARY_BOUNDARY),
            ..cap
        });
        Ok(s)
    }

    /// Integrates `y` from `t0` to `t_end`, calling `node(t, y, f)` at the start and at
    /// every accepted step end (`f = f(t, y)`, as the Hermite interpolant needs);
    /// `ControlFlow::Break` stops the run early (not an error). Errors: a non-finite
    /// state or derivative, the step below `h_min`, the step budget used up.
    pub fn integrate<S, F>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut node: F,
    ) -> Result<MersonStats>
    where
        S: OdeSystem<T, N>,
        F: FnMut(T, &[T; N], &[T; N]) -> ControlFlow<()>,
    {
        let cfg = self.config;
        let mut stats = MersonStats::default();
        let mut ctl = merson_pi::<T>();
        let mut after_reject = false;
        let mut h_cap = T::INFINITY;
        let mut since_cap = u32::MAX;
        let mut v = [T::ZERO; N];
        let mut t = t0;
        let mut f0 = [T::ZERO; N];
        sys.rhs(t, y, &mut f0);
        stats.rhs_evals += 1;
        check_finite(t, y, &f0)?;
        if node(t, y, &f0).is_break() {
            return Ok(stats);
        }
        let mut h = cfg.h_init.min(cfg.h_max).max(cfg.h_min);
        let mut ys = [T::ZERO; N];
        let mut y1 = [T::ZERO; N];
        let tab = &MERSON;
        while t < t_end {
            if stats.accepted + stats.rejected >= u64::from(cfg.max_steps) {
                return Err(Error::StepBudgetExceeded {
                    t: t.to_f64(),
                    steps: cfg.max_steps,
                });
            }
            if let Some(cap) = &self.cap {
                if since_cap >= cap.refresh_every.max(1) {
                    let mut evals = 0u32;
                    let rho = spectral_radius(
                        sys,
                        t,
                        y,
                        &f0,
                        &cfg.tol,
                        &mut v,
                        cap.max_iterations,
                        cap.rel_tol,
                        &mut evals,
                    )?;
                    stats.rhs_evals += u64::from(evals);
                    h_cap = if rho > T::ZERO && rho.is_finite() {
                        cap.fraction_at(cfg.tol.rtol) * cap.boundary / rho
                    } else {
                        T::INFINITY
                    };
                    since_cap = 0;
                }
                h = h.min(h_cap).max(cfg.h_min);
            }
            // Land on t_end: stretch by at most 1 %, or take the short last step.
            let rest = t_end - t;
            let last = h >= rest || h * T::from_f64(1.01) >= rest;
            let hs = if last { rest } else { h };
            if let Some(k0) = self.k.first_mut() {
                *k0 = f0;
            }
            for i in 1..STAGES {
                let (done, todo) = self.k.split_at_mut(i);
                let (Some(ai), Some(ci), Some(ki)) = (tab.a.get(i), tab.c.get(i), todo.first_mut())
                else {
                    continue;
                };
                for (n, yn) in ys.iter_mut().enumerate() {
                    let mut s = T::ZERO;
                    for (aij, kj) in ai.iter().zip(done.iter()) {
                        s += T::from_f64(*aij) * kj.get(n).copied().unwrap_or(T::ZERO);
                    }
                    *yn = y.get(n).copied().unwrap_or(T::ZERO) + hs * s;
                }
                sys.rhs(t + T::from_f64(*ci) * hs, &ys, ki);
                stats.rhs_evals += 1;
            }
            // Solution and error norm.
            let mut err = T::ZERO;
            for (n, y1n) in y1.iter_mut().enumerate() {
                let (mut s, mut e) = (T::ZERO, T::ZERO);
                for ((bi, bh), ki) in tab.b.iter().zip(tab.b_hat.iter()).zip(self.k.iter()) {
                    let kn = ki.get(n).copied().unwrap_or(T::ZERO);
                    s += T::from_f64(*bi) * kn;
                    e += T::from_f64(*bi - *bh) * kn;
                }
                let y0n = y.get(n).copied().unwrap_or(T::ZERO);
                *y1n = y0n + hs * s;
                let atol = cfg.tol.atol.get(n).copied().unwrap_or(T::ONE);
                let scale = atol + cfg.tol.rtol * y0n.abs().max(y1n.abs());
                let r = (hs * e).abs() / scale;
                // NaN propagates as a rejection below.
                err = if r.is_finite() {
                    err.max(r)
                } else {
                    T::INFINITY
                };
            }
            if err <= T::ONE {
                let factor = ctl.accept(err, after_reject);
                after_reject = false;
                since_cap = since_cap.saturating_add(1);
                let t1 = if last { t_end } else { t + hs };
                sys.rhs(t1, &y1, &mut f0);
                stats.rhs_evals += 1;
                check_finite(t1, &y1, &f0)?;
                *y = y1;
                t = t1;
                stats.accepted += 1;
                if node(t, y, &f0).is_break() {
                    return Ok(stats);
                }
                if !last {
                    h = (hs * factor).min(cfg.h_max).max(cfg.h_min);
                }
            } else {
                let factor = ctl.reject(err);
                after_reject = true;
                stats.rejected += 1;
                if hs <= cfg.h_min {
                    return Err(Error::StepSizeUnderflow {
                        t: t.to_f64(),
                        h: hs.to_f64(),
                    });
                }
                h = (hs * factor).max(cfg.h_min);
            }
        }
        Ok(stats)
    }
}

fn check_finite<T: Real, const N: usize>(t: T, y: &[T; N], f: &[T; N]) -> Result<()> {
    match y.iter().chain(f.iter()).position(|v| !v.is_finite()) {
        Some(i) => Err(Error::NonFinite {
            t: t.to_f64(),
            component: i % N.max(1),
        }),
        None => Ok(()),
    }
}

/// The cubic Hermite interpolant on one step, `(t0, y0, f0)` to `(t1, y1, f1)`, at `t`
/// (Merson's dense output: third order between the nodes, exact at them). A step of zero or non-finite
/// length gives `y0`.
#[allow(clippy::too_many_arguments)]
pub fn hermite<T: Real, const N: usize>(
    t0: T,
    y0: &[T; N],
    f0: &[T; N],
    t1: T,
    y1: &[T; N],
    f1: &[T; N],
    t: T,
    out: &mut [T; N],
) {
    let h = t1 - t0;
    if h == T::ZERO || !h.is_finite() {
        *out = *y0;
        return;
    }
    let s = (t - t0) / h;
    let s2 = s * s;
    let s3 = s2 * s;
    let three = T::from_f64(3.0);
    let h00 = T::TWO * s3 - three * s2 + T::ONE;
    let h10 = s3 - T::TWO * s2 + s;
    let h01 = three * s2 - T::TWO * s3;
    let h11 = s3 - s2;
    for ((((o, a), da), b), db) in out
        .iter_mut()
        .zip(y0.iter())
        .zip(f0.iter())
        .zip(y1.iter())
        .zip(f1.iter())
    {
        *o = h00 * *a + h10 * h * *da + h01 * *b + h11 * h * *db;
    }
}

#[cfg(test)]
#[allow(clippy::indexing_slicing, clippy::unwrap_used, clippy::panic)]
mod tests {
    use super::*;
    use crate::Tolerance;

    /// `sum_i w_i g(i)`.
    fn dot(w: &[f64; STAGES], g: impl Fn(usize) -> f64) -> f64 {
        (0..STAGES).map(|i| w[i] * g(i)).sum()
    }

    fn ac(t: &PairTableau, p: i32) -> [f64; STAGES] {
        core::array::from_fn(|i| (0..STAGES).map(|j| t.a[i][j] * t.c[j].powi(p)).sum())
    }

    /// The eight conditions of order 4 for weights `w` (Butcher), as residuals.
    fn order4_residuals(t: &PairTableau, w: &[f64; STAGES]) -> [f64; 8] {
        let c = t.c;
        let ac1 = ac(t, 1);
        let ac2 = ac(t, 2);
        let aac: [f64; STAGES] =
            core::array::from_fn(|i| (0..STAGES).map(|j| t.a[i][j] * ac1[j]).sum());
        [
            dot(w, |_| 1.0) - 1.0,
            dot(w, |i| c[i]) - 0.5,
            dot(w, |i| c[i] * c[i]) - 1.0 / 3.0,
            dot(w, |i| ac1[i]) - 1.0 / 6.0,
            dot(w, |i| c[i].powi(3)) - 0.25,
            dot(w, |i| c[i] * ac1[i]) - 1.0 / 8.0,
            dot(w, |i| ac2[i]) - 1.0 / 12.0,
            dot(w, |i| aac[i]) - 1.0 / 24.0,
        ]
    }

    #[test]
    fn merson_rows_sum_to_nodes_and_b_has_order_4_and_b_hat_order_3_only() {
        let t = MERSON;
        for i in 0..STAGES {
            assert!((t.a[i].iter().sum::<f64>() - t.c[i]).abs() < 1e-15);
            assert!(t.a[i][i..].iter().all(|a| *a == 0.0), "explicit");
        }
        for r in order4_residuals(&t, &t.b) {
            assert!(r.abs() < 1e-12, "{r}");
        }
        let rh = order4_residuals(&t, &t.b_hat);
        assert!(rh[..4].iter().all(|r| r.abs() < 1e-12), "{rh:?}");
        // Not of order 4: b̂·c³ = 47/180, not 1/4.
        assert!((rh[4] - (47.0 / 180.0 - 0.25)).abs() < 1e-12, "{rh:?}");
    }

    /// Coefficients `b A^(k-1) 1`, k = 0..=5, of the stability polynomial of weights `w`.
    fn stability_poly(t: &PairTableau, w: &[f64; STAGES]) -> [f64; 6] {
        let mut v = [1.0; STAGES];
        let mut out = [1.0; 6];
        for o in out.iter_mut().skip(1) {
            *o = dot(w, |i| v[i]);
            v = core::array::from_fn(|i| (0..STAGES).map(|j| t.a[i][j] * v[j]).sum());
        }
        out
    }

    /// Largest y with |R(iy')| <= 1 for all y' in (0, y], by scan and bisection.
    fn imaginary_limit(p: &[f64; 6]) -> f64 {
        let modulus = |y: f64| {
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
        };
        let mut y = 1e-3;
        while y < 20.0 && modulus(y) <= 1.0 + 1e-13 {
            y += 1e-3;
        }
        let (mut lo, mut hi) = (y - 1e-3, y);
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            if modulus(m) <= 1.0 + 1e-13 {
                lo = m;
            } else {
                hi = m;
            }
        }
        lo
    }

    #[test]
    fn merson_reaches_root_12_on_the_imaginary_axis_the_best_of_its_family() {
        let p = stability_poly(&MERSON, &MERSON.b);
        let expect = [1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 144.0];
        for (a, e) in p.iter().zip(expect) {
            assert!((a - e).abs() < 1e-15, "{p:?}");
        }
        let lim = imaginary_limit(&p);
        assert!((lim - 12f64.sqrt()).abs() < 1e-6, "{lim}");
        // Classic RK4 (z⁵ coefficient 0) reaches 2√2.
        let mut rk4 = expect;
        rk4[5] = 0.0;
        assert!((imaginary_limit(&rk4) - 8f64.sqrt()).abs() < 1e-6);
        // No other fifth-degree coefficient of an order-4 five-stage method does better.
        for g in 1..400 {
            let mut q = expect;
            q[5] = f64::from(g) * 2.5e-5;
            assert!(imaginary_limit(&q) <= lim + 1e-9, "{}", q[5]);
        }
        // The embedded weights are of order 5 on linear problems (z⁵/120).
        let ph = stability_poly(&MERSON, &MERSON.b_hat);
        assert!((ph[5] - 1.0 / 120.0).abs() < 1e-15);
    }

    struct Oscillator;
    impl OdeSystem<f64, 2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = y[1];
            d[1] = -y[0];
        }
    }

    fn fixed(h: f64, n: u32) -> (f64, MersonStats) {
        // A tolerance no step fails: a fixed step h.
        let cfg = EnglandConfig {
            tol: Tolerance::scalar(0.0, 1e300),
            h_init: h,
            h_min: h,
            h_max: h,
            max_steps: 10 * n,
        };
        let mut m = Merson::new(cfg).unwrap();
        let mut y = [1.0, 0.0];
        let st = m
            .integrate(&Oscillator, 0.0, &mut y, h * f64::from(n), |_, _, _| {
                ControlFlow::Continue(())
            })
            .unwrap();
        (
            ((y[0] - (h * f64::from(n)).cos()).powi(2) + (y[1] + (h * f64::from(n)).sin()).powi(2))
                .sqrt(),
            st,
        )
    }

    #[test]
    fn merson_converges_at_order_4_on_the_oscillator() {
        let (e1, s1) = fixed(0.1, 100);
        let (e2, _) = fixed(0.05, 200);
        let p = (e1 / e2).log2();
        assert!((p - 4.0).abs() < 0.1, "order {p}: {e1:e} {e2:e}");
        assert_eq!(s1.accepted, 100);
        assert_eq!(s1.rhs_evals, 1 + 5 * 100);
    }

    #[test]
    fn merson_is_stable_just_inside_root_12_and_unstable_just_outside() {
        // |R(ih)| for the oscillator over many steps: bounded at h = 0.99·√12, growing at
        // 1.01·√12.
        let lim = 12f64.sqrt();
        let (e_in, _) = fixed(0.99 * lim, 1000);
        let (e_out, _) = fixed(1.01 * lim, 1000);
        assert!(e_in < 2.5, "{e_in}");
        assert!(e_out > 10.0, "{e_out}");
    }

    #[test]
    fn adaptive_run_meets_its_tolerance_and_counts_its_evaluations() {
        for rtol in [1e-4, 1e-6, 1e-8] {
            let cfg = EnglandConfig {
                tol: Tolerance::scalar(rtol, rtol),
                h_init: 1e-3,
                h_min: 1e-12,
                h_max: 1.0,
                max_steps: 1_000_000,
            };
            let mut m = Merson::new(cfg).unwrap();
            let mut y = [1.0, 0.0];
            let st = m
                .integrate(&Oscillator, 0.0, &mut y, 10.0, |_, _, _| {
                    ControlFlow::Continue(())
                })
                .unwrap();
            let e = (y[0] - 10f64.cos()).abs().max((y[1] + 10f64.sin()).abs());
            // Global error within a modest multiple of the tolerance times the span.
            assert!(e < 10.0 * 10.0 * rtol, "rtol {rtol}: {e:e}");
            assert_eq!(st.rhs_evals, 1 + 5 * st.accepted + 4 * st.rejected);
        }
    }

    /// A stiff oscillator `x'' = -ω² x`, ω = 1000 rad/s.
    struct Stiff;
    impl OdeSystem<f64, 2> for Stiff {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = y[1];
            d[1] = -1e6 * y[0];
        }
    }

    #[test]
    fn the_cap_holds_the_step_at_its_fraction_of_root_12_over_omega() {
        // A loose tolerance: accuracy would allow far longer steps than stability, so the
        // capped run takes ω T / (0.95 √12) = 303.9 steps over T = 1 s, and none fails.
        let cfg = EnglandConfig {
            tol: Tolerance::scalar(1e-1, 1e-1),
            h_init: 1e-4,
            h_min: 1e-12,
            h_max: 1.0,
            max_steps: 1_000_000,
        };
        let mut m = Merson::with_cap(cfg, StiffnessCap::new()).unwrap();
        let mut y = [1e-3, 0.0];
        let st = m
            .integrate(
                &Stiff,
                0.0,
                &mut y,
                1.0,
                |_, _, _| ControlFlow::Continue(()),
            )
            .unwrap();
        let expect = 1e3 / (0.95 * 12f64.sqrt());
        assert!(
            (st.accepted as f64) >= expect && (st.accepted as f64) < 1.1 * expect,
            "{st:?} against {expect}"
        );
        assert!(st.rejected <= 3, "{st:?}");
        // The solution stays bounded (stable): |x| <= the amplitude 1e-3.
        assert!(y[0].abs() <= 1.0001e-3, "{y:?}");
    }

    #[test]
    fn hermite_is_exact_for_cubics_and_at_the_nodes() {
        // y = t³ - t: y' = 3t² - 1.
        let y = |t: f64| [t * t * t - t];
        let f = |t: f64| [3.0 * t * t - 1.0];
        let mut o = [0.0];
        for t in [0.3, 0.7, 1.0, 1.4] {
            hermite(0.3, &y(0.3), &f(0.3), 1.4, &y(1.4), &f(1.4), t, &mut o);
            assert!((o[0] - y(t)[0]).abs() < 1e-14);
        }
    }

    #[test]
    fn bad_settings_are_typed_errors() {
        let ok = EnglandConfig {
            tol: Tolerance::scalar(1e-6, 1e-9),
            h_init: 1e-3,
            h_min: 1e-9,
            h_max: 1.0,
            max_steps: 10,
        };
        assert!(Merson::<f64, 2>::new(ok).is_ok());
        let mut c = ok;
        c.h_min = 2.0;
        assert!(matches!(
            Merson::<f64, 2>::new(c),
            Err(Error::InvalidParameter { field: "h_min", .. })
        ));
        let mut c = ok;
        c.tol.atol = [f64::NAN, 1.0];
        assert!(Merson::<f64, 2>::new(c).is_err());
        // Budget.
        let mut m = Merson::new(ok).unwrap();
        let mut y = [1.0, 0.0];
        let r = m.integrate(&Oscillator, 0.0, &mut y, 100.0, |_, _, _| {
            ControlFlow::Continue(())
        });
        assert!(matches!(r, Err(Error::StepBudgetExceeded { .. })));
    }
}
