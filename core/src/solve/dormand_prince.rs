//! Dormand and Prince's 5(4) pair ("DOPRI5"), for runs whose step is held by accuracy,
//! not stability (the chip's: at rtol 1e-2 its step is several times the stability
//! limit).
//!
//! Source: J. R. Dormand and P. J. Prince, "A family of embedded Runge-Kutta formulae",
//! *J. Comput. Appl. Math.* 6 (1980) 19-26; tableau as given by Hairer, Nørsett and
//! Wanner, *Solving Ordinary Differential Equations I* (2nd ed., Springer 1993), §II.5,
//! Table 5.2:
//!
//! ```text
//!    0  |
//!   1/5 | 1/5
//!  3/10 | 3/40        9/40
//!   4/5 | 44/45      -56/15       32/9
//!   8/9 | 19372/6561 -25360/2187  64448/6561 -212/729
//!    1  | 9017/3168  -355/33      46732/5247  49/176  -5103/18656
//!    1  | 35/384      0           500/1113    125/192 -2187/6784    11/84
//! ------+--------------------------------------------------------------------------
//!    b  | 35/384      0           500/1113    125/192 -2187/6784    11/84     0      order 5
//!    b̂  | 5179/57600  0           7571/16695  393/640 -92097/339200 187/2100  1/40   order 4
//! ```
//!
//! The last stage is evaluated at the solution `y1` (its row is `b`): first same as last,
//! so an accepted step costs 6 evaluations, and its end point's derivative (the next
//! step's first stage, the sample a run takes there) is that stage. The solution is
//! propagated at order 5 (local extrapolation), the error estimated at order 4: the
//! step-size controller is Hairer's PI with `alpha = 0.17`, `beta = 0.04` (DOPRI5's
//! defaults), safety 0.9, factors in `[0.2, 10]`.
//!
//! Why this pair for the chip: the chip's step is held by accuracy at several times the
//! stability limit, so what counts is the error per evaluation, not the reach along the
//! imaginary axis (where DOPRI5 reaches only 0.997, against England's 2·2√2 per double
//! step; [`crate::Merson`] is the pair for that case). Measured in `camsim bench --quick`
//! (docs/BENCHMARKS.md).

use crate::{EnglandConfig, Pair, PairTableau, Real, Result};

/// Stages of the pair (the last one first-same-as-last).
pub const DP_STAGES: usize = 7;

/// Dormand and Prince's 5(4) pair (see the module documentation for its source).
pub const DORMAND_PRINCE: PairTableau<DP_STAGES> = PairTableau {
    a: [
        [0.0; 7],
        [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
        [
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
            0.0,
            0.0,
            0.0,
        ],
        [
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
            0.0,
            0.0,
        ],
        [
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
            0.0,
        ],
    ],
    b: [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    b_hat: [
        5179.0 / 57600.0,
        0.0,
        7571.0 / 16695.0,
        393.0 / 640.0,
        -92097.0 / 339200.0,
        187.0 / 2100.0,
        1.0 / 40.0,
    ],
    c: [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    order: 5,
    embedded_order: 4,
    fsal: true,
    imaginary_boundary: DP_IMAGINARY_BOUNDARY,
    pi: (0.17, 0.04),
};

/// Where DOPRI5's stability region first leaves the imaginary axis, `|hλ|`.
pub const DP_IMAGINARY_BOUNDARY: f64 = 0.997_189;

/// Dormand and Prince's adaptive pair for `N` equations ([`Pair`] with [`DORMAND_PRINCE`]).
pub type DormandPrince<T, const N: usize> = Pair<T, N, DP_STAGES>;

impl<T: Real, const N: usize> Pair<T, N, DP_STAGES> {
    /// Dormand and Prince's pair with `config` (single-step sizes). Errors as
    /// [`Pair::with_tableau`].
    pub fn dormand_prince(config: EnglandConfig<T, N>) -> Result<Self> {
        Self::with_tableau(&DORMAND_PRINCE, config)
    }
}

#[cfg(test)]
#[allow(clippy::indexing_slicing, clippy::unwrap_used, clippy::panic)]
mod tests {
    use super::*;
    use crate::{OdeSystem, Tolerance};
    use core::ops::ControlFlow;

    const S: usize = DP_STAGES;

    fn dot(w: &[f64; S], g: impl Fn(usize) -> f64) -> f64 {
        (0..S).map(|i| w[i] * g(i)).sum()
    }

    fn a_times(v: &[f64; S]) -> [f64; S] {
        let t = &DORMAND_PRINCE;
        core::array::from_fn(|i| (0..S).map(|j| t.a[i][j] * v[j]).sum())
    }

    #[test]
    fn rows_sum_to_nodes_fsal_and_the_quadrature_orders() {
        let t = &DORMAND_PRINCE;
        for i in 0..S {
            assert!(
                (t.a[i].iter().sum::<f64>() - t.c[i]).abs() < 1e-14,
                "row {i}"
            );
            assert!(t.a[i][i..].iter().all(|a| *a == 0.0), "explicit");
        }
        // First same as last: the last row is b, at c = 1, and b's last weight is 0.
        assert_eq!(t.a[S - 1], t.b);
        assert_eq!((t.c[S - 1], t.b[S - 1]), (1.0, 0.0));
        // Quadrature conditions Σ b_i c_i^(q-1) = 1/q: up to q = 5 for b, 4 for b̂ (and b̂
        // fails q = 5).
        for q in 1..=5 {
            let rb = dot(&t.b, |i| t.c[i].powi(q - 1)) - 1.0 / f64::from(q);
            assert!(rb.abs() < 1e-14, "b, q = {q}: {rb}");
            let rh = dot(&t.b_hat, |i| t.c[i].powi(q - 1)) - 1.0 / f64::from(q);
            if q <= 4 {
                assert!(rh.abs() < 1e-14, "b̂, q = {q}: {rh}");
            } else {
                assert!(rh.abs() > 1e-6, "b̂ is of order 4 only");
            }
        }
        // The linear conditions b A^(k-1) 1 = 1/k!: the stability polynomial is
        // Σ z^k/k! to k = 5, then z⁶/600 (Hairer-Nørsett-Wanner §IV.2).
        let mut v = [1.0; S];
        let mut fact = 1.0;
        for k in 1..=6 {
            fact *= f64::from(k);
            let got = dot(&t.b, |i| v[i]);
            let want = if k <= 5 { 1.0 / fact } else { 1.0 / 600.0 };
            assert!((got - want).abs() < 1e-15, "z^{k}: {got} against {want}");
            v = a_times(&v);
        }
    }

    /// A nonlinear scalar problem with a known solution: `y' = 1 + y²`, `y(0) = 0`,
    /// `y = tan t`.
    struct Tan;
    impl OdeSystem<f64, 1> for Tan {
        fn rhs(&self, _t: f64, y: &[f64; 1], d: &mut [f64; 1]) {
            d[0] = 1.0 + y[0] * y[0];
        }
    }

    /// A time-dependent problem (every node `c_i` counts): `y' = y cos t`, `y(0) = 1`,
    /// `y = exp(sin t)`.
    struct ExpSin;
    impl OdeSystem<f64, 1> for ExpSin {
        fn rhs(&self, t: f64, y: &[f64; 1], d: &mut [f64; 1]) {
            d[0] = y[0] * t.cos();
        }
    }

    fn fixed_tan(h: f64, n: u32) -> (f64, crate::SolverStats) {
        fixed(&Tan, 0.0, f64::tan, h, n)
    }

    fn fixed(
        sys: &impl OdeSystem<f64, 1>,
        y0: f64,
        exact: fn(f64) -> f64,
        h: f64,
        n: u32,
    ) -> (f64, crate::SolverStats) {
        let cfg = EnglandConfig {
            tol: Tolerance::scalar(0.0, 1e300),
            h_init: h,
            h_min: h,
            h_max: h,
            max_steps: 10 * n,
        };
        let mut m = DormandPrince::dormand_prince(cfg).unwrap();
        let mut y = [y0];
        let t_end = h * f64::from(n);
        let st = m
            .integrate(sys, 0.0, &mut y, t_end, |_, _, _| ControlFlow::Continue(()))
            .unwrap();
        ((y[0] - exact(t_end)).abs(), st)
    }

    #[test]
    fn converges_at_order_5_on_a_nonlinear_problem_with_six_evaluations_a_step() {
        let exact = |t: f64| t.sin().exp();
        // Over t in [0, 4]: the observed order rises to 5 as h falls (4.6, 4.85, ...).
        let (e1, _) = fixed(&ExpSin, 1.0, exact, 0.1, 40);
        let (e2, _) = fixed(&ExpSin, 1.0, exact, 0.05, 80);
        let (e3, _) = fixed(&ExpSin, 1.0, exact, 0.025, 160);
        let (p1, p2) = ((e1 / e2).log2(), (e2 / e3).log2());
        assert!(
            p1 < p2 && (p2 - 5.0).abs() < 0.15,
            "orders {p1} {p2}: {e1:e} {e2:e} {e3:e}"
        );
        let (_, s1) = fixed_tan(0.05, 20);
        assert_eq!(s1.accepted, 20);
        // FSAL: the first evaluation, then 6 a step.
        assert_eq!(s1.rhs_evals, 1 + 6 * 20);
    }

    #[test]
    fn adaptive_run_meets_its_tolerance_and_counts_its_evaluations() {
        crate::solve::pair::testing::meets_its_tolerance(&DORMAND_PRINCE, 6, 6);
    }

    #[test]
    fn the_dense_extension_is_exact_at_the_ends_and_third_order_between() {
        // Fixed steps on tan: the cubic Hermite's error at mid-step falls ~16x per halving.
        let mut worst = [0.0f64; 2];
        for (slot, h) in worst.iter_mut().zip([0.05, 0.025]) {
            let cfg = EnglandConfig {
                tol: Tolerance::scalar(0.0, 1e300),
                h_init: h,
                h_min: h,
                h_max: h,
                max_steps: 1000,
            };
            let mut m = DormandPrince::dormand_prince(cfg).unwrap();
            let mut y = [0.0];
            let mut out = [0.0];
            m.integrate_dense(&Tan, 0.0, &mut y, 1.0, |d| {
                d.eval(d.t_end(), &mut out);
                assert_eq!(out[0].to_bits(), d.nodes()[2][0].to_bits());
                let tm = 0.5 * (d.t_start() + d.t_end());
                d.eval(tm, &mut out);
                *slot = slot.max((out[0] - tm.tan()).abs());
                ControlFlow::Continue(())
            })
            .unwrap();
        }
        let p = (worst[0] / worst[1]).log2();
        assert!((p - 4.0).abs() < 0.3, "local order {p}: {worst:?}");
    }

    /// `y' = y²`, `y(0) = 1`: `y = 1/(1 - t)` blows up at t = 1.
    struct BlowUp;
    impl OdeSystem<f32, 1> for BlowUp {
        fn rhs(&self, _t: f32, y: &[f32; 1], d: &mut [f32; 1]) {
            d[0] = y[0] * y[0];
        }
    }

    #[test]
    fn a_blow_up_is_a_typed_error_never_a_non_finite_success() {
        // In f32 the solution overflows well before the step would underflow: every
        // pair must stop with an error, and no node it shows may be non-finite.
        let cfg = EnglandConfig {
            tol: Tolerance::scalar(1e-3f32, 1e-6),
            h_init: 1e-3,
            h_min: 1e-30,
            h_max: 0.1,
            max_steps: 100_000,
        };
        let finite = core::cell::Cell::new(true);
        let node = |_: f32, y: &[f32; 1], f: &[f32; 1]| {
            finite.set(finite.get() && y[0].is_finite() && f[0].is_finite());
            ControlFlow::Continue(())
        };
        let mut y = [1.0f32];
        let dp = DormandPrince::dormand_prince(cfg)
            .unwrap()
            .integrate(&BlowUp, 0.0, &mut y, 2.0, node);
        assert!(dp.is_err(), "{dp:?}");
        let mut y = [1.0f32];
        let merson = crate::Merson::new(cfg)
            .unwrap()
            .integrate(&BlowUp, 0.0, &mut y, 2.0, node);
        assert!(merson.is_err(), "{merson:?}");
        assert!(finite.get());
        // A solution that overflows while every stage stays finite (y' = 1e38 from 2e38):
        // the error estimate is 0, the scale infinite; the step must still not pass.
        let mut y = [2e38f32];
        let r = DormandPrince::dormand_prince(cfg)
            .unwrap()
            .integrate(&Drift, 0.0, &mut y, 10.0, node);
        assert!(r.is_err() && finite.get(), "{r:?} {y:?}");
    }

    /// `y' = 1e38`: stages as finite as the slope, the solution overflowing f32.
    struct Drift;
    impl OdeSystem<f32, 1> for Drift {
        fn rhs(&self, _t: f32, _y: &[f32; 1], d: &mut [f32; 1]) {
            d[0] = 1e38;
        }
    }

    #[test]
    fn reaches_0_997_on_the_imaginary_axis() {
        // |R(iy)| of the stability polynomial, R = Σ_{k<=5} z^k/k! + z⁶/600.
        let p = [
            1.0,
            1.0,
            0.5,
            1.0 / 6.0,
            1.0 / 24.0,
            1.0 / 120.0,
            1.0 / 600.0,
        ];
        let modulus = |y: f64| crate::solve::pair::testing::imaginary_modulus(&p, y);
        let b = DP_IMAGINARY_BOUNDARY;
        assert!(modulus(0.999 * b) <= 1.0 && modulus(0.5 * b) <= 1.0);
        assert!(modulus(1.001 * b) > 1.0);
    }
}
