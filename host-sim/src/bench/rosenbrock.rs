//! A linearly implicit method for the bench, not bound by the explicit stability limit:
//! the Rosenbrock-W method ROS34PW2 of Rang and Angermann (BIT 45, 2005; 4 stages,
//! order 3, embedded order 2, stiffly accurate and L-stable), with the Jacobian by
//! forward differences and a dense LU with partial pivoting (N ≤ 22: plain arrays, no
//! dependency).
//!
//! One step of size `h` from `(t, y)` with `J ≈ ∂f/∂y` (a W-method keeps its order for
//! any `J`, so a Jacobian may be reused over several steps; the time derivative of `f`
//! is not needed, `J`'s missing t column being such an approximation):
//!
//! ```text
//! (I - h γ J) k_i = h f(t + c_i h, y + Σ_j a_ij k_j) + h J Σ_j g_ij k_j   (j < i)
//! y1 = y + Σ b_i k_i,   error estimate Σ (b_i - b̂_i) k_i   (local error ∝ h³)
//! ```
//!
//! Step-size control: the error ratio in England's max norm
//! (`|e_i| / (atol_i + rtol · max(|y_i|, |y1_i|))`), `h · clamp(0.9 err^(-1/3), 0.2, 5)`
//! (no growth right after a rejection); the Jacobian is recomputed every `jac_every`
//! accepted steps and after every rejection. Cost per accepted step: 3 evaluations (the
//! first stage's `f(t, y)` is the last step's end derivative) plus `N` per Jacobian, and
//! an LU factorisation of `I - h γ J` per attempt.

// The coefficients as published (20 digits; f64 rounds them).
#![allow(clippy::excessive_precision)]
// Dense linear algebra on small arrays reads best with indices.
#![allow(clippy::needless_range_loop)]

use std::ops::ControlFlow;

use anyhow::{bail, Result};
use camsim_core::{OdeSystem, Real};

/// γ of ROS34PW2.
pub const GAMMA: f64 = 4.358_665_215_084_590_0e-1;
/// Stage abscissae `c_i = Σ_j a_ij`.
pub const C: [f64; 4] = [
    0.0,
    8.717_330_430_169_180_1e-1,
    7.315_799_577_888_523_8e-1,
    1.0,
];
/// `a_ij` (strictly lower triangular).
pub const A: [[f64; 4]; 4] = [
    [0.0; 4],
    [8.717_330_430_169_180_1e-1, 0.0, 0.0, 0.0],
    [
        8.445_706_001_536_942_3e-1,
        -1.129_906_423_648_418_5e-1,
        0.0,
        0.0,
    ],
    [0.0, 0.0, 1.0, 0.0],
];
/// `g_ij` (strictly lower triangular; the diagonal is γ).
pub const G: [[f64; 4]; 4] = [
    [0.0; 4],
    [-8.717_330_430_169_180_1e-1, 0.0, 0.0, 0.0],
    [
        -9.033_805_701_304_408_2e-1,
        5.418_067_238_809_532_6e-2,
        0.0,
        0.0,
    ],
    [
        2.421_238_070_609_534_6e-1,
        -1.223_250_583_904_514_7,
        5.452_602_553_351_021_4e-1,
        0.0,
    ],
];
/// Weights of the third-order solution.
pub const B: [f64; 4] = [
    2.421_238_070_609_534_6e-1,
    -1.223_250_583_904_514_7,
    1.545_260_255_335_102_0,
    4.358_665_215_084_590_0e-1,
];
/// Weights of the embedded second-order solution.
pub const B_HAT: [f64; 4] = [
    3.781_090_314_581_936_9e-1,
    -9.604_229_221_242_317_8e-2,
    0.5,
    2.179_332_607_542_295_0e-1,
];

/// LU factorisation with partial pivoting of `m` in place (`P m = L U`, L unit lower);
/// `piv[k]` is the row swapped into row k. An error if a pivot is zero or not finite.
pub fn lu_factor<T: Real, const N: usize>(m: &mut [[T; N]; N], piv: &mut [usize; N]) -> Result<()> {
    for k in 0..N {
        let mut p = k;
        let mut best = m[k][k].abs();
        for (i, row) in m.iter().enumerate().skip(k + 1) {
            if row[k].abs() > best {
                best = row[k].abs();
                p = i;
            }
        }
        if !(best > T::ZERO && best.is_finite()) {
            bail!("singular or non-finite matrix at column {k}");
        }
        piv[k] = p;
        m.swap(k, p);
        let pivot = m[k][k];
        let row_k = m[k];
        for row in m.iter_mut().skip(k + 1) {
            let l = row[k] / pivot;
            row[k] = l;
            if l != T::ZERO {
                for j in k + 1..N {
                    row[j] -= l * row_k[j];
                }
            }
        }
    }
    Ok(())
}

/// Solves `m x = b` in place (`b` becomes `x`) from [`lu_factor`]'s output.
pub fn lu_solve<T: Real, const N: usize>(lu: &[[T; N]; N], piv: &[usize; N], b: &mut [T; N]) {
    for k in 0..N {
        b.swap(k, piv[k]);
    }
    for i in 0..N {
        let mut s = b[i];
        for j in 0..i {
            s -= lu[i][j] * b[j];
        }
        b[i] = s;
    }
    for i in (0..N).rev() {
        let mut s = b[i];
        for j in i + 1..N {
            s -= lu[i][j] * b[j];
        }
        b[i] = s / lu[i][i];
    }
}

/// `J[i][j] ≈ ∂f_i/∂y_j` at `(t, y)` by forward differences from `f0 = f(t, y)`, with
/// the increment `sqrt(ε) · max(|y_j|, scale_j)` (N evaluations).
pub fn jacobian<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    y: &[T; N],
    f0: &[T; N],
    scale: &[T; N],
    jac: &mut [[T; N]; N],
) {
    let sqrt_eps = T::EPSILON.sqrt();
    let mut yp = *y;
    let mut fp = [T::ZERO; N];
    for j in 0..N {
        let d = sqrt_eps * y[j].abs().max(scale[j]);
        let yj = y[j];
        yp[j] = yj + d;
        let d = yp[j] - yj; // exactly representable increment
        sys.rhs(t, &yp, &mut fp);
        yp[j] = yj;
        for i in 0..N {
            jac[i][j] = (fp[i] - f0[i]) / d;
        }
    }
}

/// Work buffers of one ROS34PW2 step.
pub struct Stepper<T, const N: usize> {
    /// The Jacobian in use.
    pub jac: [[T; N]; N],
    lu: [[T; N]; N],
    piv: [usize; N],
    k: [[T; N]; 4],
}

impl<T: Real, const N: usize> Default for Stepper<T, N> {
    fn default() -> Self {
        Self {
            jac: [[T::ZERO; N]; N],
            lu: [[T::ZERO; N]; N],
            piv: [0; N],
            k: [[T::ZERO; N]; 4],
        }
    }
}

impl<T: Real, const N: usize> Stepper<T, N> {
    /// One step of size `h` from `(t, y)` with `f0 = f(t, y)` and [`Self::jac`]: writes
    /// the third-order solution into `y1` and the error estimate into `err`
    /// (3 evaluations, one LU factorisation).
    #[allow(clippy::too_many_arguments)]
    pub fn step<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t: T,
        y: &[T; N],
        f0: &[T; N],
        h: T,
        y1: &mut [T; N],
        err: &mut [T; N],
    ) -> Result<()> {
        let hg = h * T::from_f64(GAMMA);
        for i in 0..N {
            for j in 0..N {
                self.lu[i][j] = -hg * self.jac[i][j];
            }
            self.lu[i][i] += T::ONE;
        }
        lu_factor(&mut self.lu, &mut self.piv)?;
        let mut arg = [T::ZERO; N];
        let mut f = [T::ZERO; N];
        let mut gk = [T::ZERO; N];
        for s in 0..4 {
            // f at the stage point.
            if s == 0 {
                f = *f0;
            } else {
                for (i, a) in arg.iter_mut().enumerate() {
                    let mut v = y[i];
                    for j in 0..s {
                        v += T::from_f64(A[s][j]) * self.k[j][i];
                    }
                    *a = v;
                }
                sys.rhs(t + T::from_f64(C[s]) * h, &arg, &mut f);
            }
            // rhs = h f + h J Σ g_sj k_j.
            let mut rhs = [T::ZERO; N];
            if s > 0 {
                for (i, g) in gk.iter_mut().enumerate() {
                    let mut v = T::ZERO;
                    for j in 0..s {
                        v += T::from_f64(G[s][j]) * self.k[j][i];
                    }
                    *g = v;
                }
                for (i, r) in rhs.iter_mut().enumerate() {
                    let mut v = T::ZERO;
                    for (jij, gj) in self.jac[i].iter().zip(gk.iter()) {
                        v += *jij * *gj;
                    }
                    *r = h * (f[i] + v);
                }
            } else {
                for (r, fi) in rhs.iter_mut().zip(f.iter()) {
                    *r = h * *fi;
                }
            }
            lu_solve(&self.lu, &self.piv, &mut rhs);
            self.k[s] = rhs;
        }
        for i in 0..N {
            let mut v = y[i];
            let mut e = T::ZERO;
            for s in 0..4 {
                v += T::from_f64(B[s]) * self.k[s][i];
                e += T::from_f64(B[s] - B_HAT[s]) * self.k[s][i];
            }
            y1[i] = v;
            err[i] = e;
        }
        if let Some(i) = y1.iter().position(|v| !v.is_finite()) {
            bail!(
                "Rosenbrock solution not finite at t = {:e} s (component {i})",
                t.to_f64()
            );
        }
        Ok(())
    }
}

/// Settings of [`integrate`].
#[derive(Clone, Copy, Debug)]
pub struct Config<T, const N: usize> {
    /// Relative tolerance.
    pub rtol: T,
    /// Absolute tolerance per component (also the Jacobian increments' floor).
    pub atol: [T; N],
    /// First step.
    pub h_init: T,
    /// Smallest step (a rejection below it is an error).
    pub h_min: T,
    /// Largest step.
    pub h_max: T,
    /// Accepted steps between Jacobians (1: every step).
    pub jac_every: u32,
    /// Budget of attempted steps.
    pub max_steps: u64,
}

/// Work of [`integrate`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Jacobians computed.
    pub jacobians: u64,
}

/// Integrates from `t0` to `t_end` with adaptive steps, calling `observer(t, y, f(t, y))`
/// at the start and at every accepted step end (`Break` stops, still `Ok`).
pub fn integrate<T, const N: usize, S, F>(
    sys: &S,
    t0: T,
    y: &mut [T; N],
    t_end: T,
    cfg: &Config<T, N>,
    mut observer: F,
) -> Result<Stats>
where
    T: Real,
    S: OdeSystem<T, N>,
    F: FnMut(T, &[T; N], &[T; N]) -> ControlFlow<()>,
{
    let mut st = Stepper::<T, N>::default();
    let mut stats = Stats::default();
    let mut f0 = [T::ZERO; N];
    sys.rhs(t0, y, &mut f0);
    if observer(t0, y, &f0).is_break() {
        return Ok(stats);
    }
    let scale = jacobian_scale(cfg);
    let mut t = t0;
    let mut h = cfg.h_init;
    let mut since_jac = cfg.jac_every; // a Jacobian at the first step
    let mut rejected_here = false;
    let mut y1 = [T::ZERO; N];
    let mut err = [T::ZERO; N];
    while t < t_end {
        if stats.accepted + stats.rejected >= cfg.max_steps {
            bail!(
                "Rosenbrock: step budget {} used up at t = {:e} s",
                cfg.max_steps,
                t.to_f64()
            );
        }
        if since_jac >= cfg.jac_every {
            jacobian(sys, t, y, &f0, &scale, &mut st.jac);
            stats.jacobians += 1;
            since_jac = 0;
        }
        let last = t + h >= t_end;
        let h_try = if last { t_end - t } else { h };
        st.step(sys, t, y, &f0, h_try, &mut y1, &mut err)?;
        let ratio = error_ratio(cfg, y, &y1, &err);
        let fac = step_factor(ratio);
        if ratio <= T::ONE {
            stats.accepted += 1;
            since_jac += 1;
            t = if last { t_end } else { t + h_try };
            *y = y1;
            sys.rhs(t, y, &mut f0);
            let cap = if rejected_here {
                T::ONE
            } else {
                T::from_f64(5.0)
            };
            h = (h_try * fac.clamp(T::from_f64(0.2), cap)).clamp(cfg.h_min, cfg.h_max);
            rejected_here = false;
            if observer(t, y, &f0).is_break() {
                break;
            }
        } else {
            stats.rejected += 1;
            if h_try <= cfg.h_min {
                bail!("Rosenbrock: step size underflow at t = {:e} s", t.to_f64());
            }
            h = (h_try * fac.clamp(T::from_f64(0.2), T::ONE)).max(cfg.h_min);
            rejected_here = true;
            since_jac = cfg.jac_every; // a fresh Jacobian for the retry
        }
    }
    Ok(stats)
}

/// The Jacobian's perturbation scale of each component: `atol_i / rtol`.
fn jacobian_scale<T: Real, const N: usize>(cfg: &Config<T, N>) -> [T; N] {
    let mut s = cfg.atol;
    for v in s.iter_mut() {
        *v /= cfg.rtol.max(T::EPSILON);
    }
    s
}

/// The step's error over its tolerance, largest component (at most 1: accepted).
fn error_ratio<T: Real, const N: usize>(
    cfg: &Config<T, N>,
    y: &[T; N],
    y1: &[T; N],
    err: &[T; N],
) -> T {
    let mut ratio = T::ZERO;
    for i in 0..N {
        let sc = cfg.atol[i] + cfg.rtol * y[i].abs().max(y1[i].abs());
        ratio = ratio.max(err[i].abs() / sc);
    }
    ratio
}

/// The next step over this one for an error `ratio` (third order: `0.9 ratio^(-1/3)`;
/// 5 at a zero error), before its clamps.
fn step_factor<T: Real>(ratio: T) -> T {
    if ratio > T::ZERO {
        T::from_f64(0.9) * ratio.powf(T::from_f64(-1.0 / 3.0))
    } else {
        T::from_f64(5.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x'' = -x as (x, v): smooth, closed form (cos t, -sin t).
    struct Oscillator;
    impl OdeSystem<f64, 2> for Oscillator {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            d[0] = y[1];
            d[1] = -y[0];
        }
    }

    /// A stiff linear system, y' = A y with eigenvalues -1 and -1e4 (A = V diag V⁻¹,
    /// V = [[1, 1], [1, -1]]): closed form y = e^{-t} c1 (1, 1) + e^{-1e4 t} c2 (1, -1).
    struct Stiff;
    impl OdeSystem<f64, 2> for Stiff {
        fn rhs(&self, _t: f64, y: &[f64; 2], d: &mut [f64; 2]) {
            // A = [[-(1+1e4)/2, (-1+1e4)/2], [(-1+1e4)/2, -(1+1e4)/2]].
            let (p, q) = (-(1.0 + 1e4) / 2.0, (-1.0 + 1e4) / 2.0);
            d[0] = p * y[0] + q * y[1];
            d[1] = q * y[0] + p * y[1];
        }
    }

    /// Global error at t_end with n fixed steps (Jacobian every step), and the largest
    /// local error estimate.
    fn fixed<S: OdeSystem<f64, 2>>(sys: &S, y0: [f64; 2], t_end: f64, n: u32) -> [f64; 2] {
        fixed_with(sys, y0, t_end, n, None)
    }

    /// [`fixed`] with an exact Jacobian if given (else forward differences).
    fn fixed_with<S: OdeSystem<f64, 2>>(
        sys: &S,
        y0: [f64; 2],
        t_end: f64,
        n: u32,
        exact_jac: Option<[[f64; 2]; 2]>,
    ) -> [f64; 2] {
        let mut st = Stepper::<f64, 2>::default();
        let mut y = y0;
        let h = t_end / f64::from(n);
        let mut f = [0.0; 2];
        let (mut y1, mut e) = ([0.0; 2], [0.0; 2]);
        for k in 0..n {
            let t = f64::from(k) * h;
            sys.rhs(t, &y, &mut f);
            match exact_jac {
                Some(j) => st.jac = j,
                None => jacobian(sys, t, &y, &f, &[1.0; 2], &mut st.jac),
            }
            st.step(sys, t, &y, &f, h, &mut y1, &mut e).unwrap();
            y = y1;
        }
        y
    }

    fn order(e1: f64, e2: f64) -> f64 {
        (e1 / e2).log2()
    }

    #[test]
    fn third_order_on_the_oscillator() {
        let err = |n| {
            let y = fixed(&Oscillator, [1.0, 0.0], 2.0, n);
            ((y[0] - 2f64.cos()).powi(2) + (y[1] + 2f64.sin()).powi(2)).sqrt()
        };
        let (e1, e2, e3) = (err(40), err(80), err(160));
        let (p1, p2) = (order(e1, e2), order(e2, e3));
        assert!(
            (2.85..3.15).contains(&p1) && (2.85..3.15).contains(&p2),
            "{e1:e} {e2:e} {e3:e}: {p1} {p2}"
        );
    }

    #[test]
    fn embedded_estimate_is_second_order_locally() {
        // One step from (1, 0): the estimate ∝ h³ (local error of the second-order solution).
        let est = |h: f64| {
            let mut st = Stepper::<f64, 2>::default();
            let y = [1.0, 0.0];
            let mut f = [0.0; 2];
            Oscillator.rhs(0.0, &y, &mut f);
            jacobian(&Oscillator, 0.0, &y, &f, &[1e-8; 2], &mut st.jac);
            let (mut y1, mut e) = ([0.0; 2], [0.0; 2]);
            st.step(&Oscillator, 0.0, &y, &f, h, &mut y1, &mut e)
                .unwrap();
            e[0].hypot(e[1])
        };
        let p = order(est(0.1), est(0.05));
        assert!((2.8..3.2).contains(&p), "{p}");
    }

    #[test]
    fn stiff_linear_system_third_order_at_steps_far_beyond_explicit_stability() {
        // c1 = 1, c2 = 1: y0 = (2, 0). Steps with h λ_stiff from -400 to -100 (an explicit
        // RK4 would need h < 2.8e-4 here); the stiff component is gone by the end, the
        // slow one converges at order 3 (L-stability: no order reduction in the stiff
        // part on a linear constant-coefficient problem). The exact Jacobian: forward
        // differences' error (~1e-4 absolute in J here) floors the error near 5e-10.
        let exact = |t: f64| {
            let s = (-t).exp();
            let f = (-1e4 * t).exp();
            [s + f, s - f]
        };
        let (p, q) = (-(1.0 + 1e4) / 2.0, (-1.0 + 1e4) / 2.0);
        let err = |n| {
            let y = fixed_with(&Stiff, [2.0, 0.0], 1.0, n, Some([[p, q], [q, p]]));
            let x = exact(1.0);
            (y[0] - x[0]).abs().max((y[1] - x[1]).abs())
        };
        let (e1, e2, e3) = (err(25), err(50), err(100));
        let (p1, p2) = (order(e1, e2), order(e2, e3));
        assert!(e1 < 1e-5, "{e1:e}");
        assert!(
            (2.7..3.3).contains(&p1) && (2.7..3.3).contains(&p2),
            "{e1:e} {e2:e} {e3:e}: {p1} {p2}"
        );
    }

    #[test]
    fn lu_solves_a_known_system() {
        let mut m = [[0.0, 2.0, 1.0], [1.0, 1.0, 0.0], [3.0, 0.0, 1.0]];
        let x = [1.0, -2.0, 3.0];
        let mut b = [0.0; 3];
        for i in 0..3 {
            b[i] = (0..3).map(|j| m[i][j] * x[j]).sum();
        }
        let mut piv = [0; 3];
        lu_factor(&mut m, &mut piv).unwrap();
        lu_solve(&m, &piv, &mut b);
        for i in 0..3 {
            assert!((b[i] - x[i]).abs() < 1e-14, "{b:?}");
        }
        let mut s = [[1.0, 2.0], [2.0, 4.0]];
        assert!(lu_factor(&mut s, &mut [0; 2]).is_err());
    }
}
