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
//! Dense output: Merson gives none; [`hermite`] (and [`crate::Dense::cubic`], what
//! [`crate::Pair::integrate_dense`] passes) is the cubic Hermite interpolant on the step
//! ends `(t0, y0, f0)`, `(t1, y1, f1)` (third order between the nodes, exact at them). The
//! bench samples every method without its own interpolant through the quintic Hermite
//! through three consecutive step ends instead.
//!
//! Step-size control: `err = max_i |y1_i - ŷ1_i| / (atol_i + rtol · max(|y0_i|, |y1_i|))`
//! (England's norm, docs/MODEL.md §3.16), accepted if `err <= 1`. The next step is set by
//! Hairer's PI controller ([`PiSettings`]) with the exponents for an estimate of local
//! order 4 (`alpha = 0.7/4`, `beta = 0.4/4`; safety 0.9, factors in `[0.2, 10]`, no
//! growth right after a rejection: the PI-capped England's settings with 5 replaced by 4),
//! clamped to `[h_min, h_max]`. Optionally ([`Merson::with_cap`](crate::Pair::with_cap)) the step is also capped
//! at `fraction · √12 / ρ`, `ρ` the Jacobian's spectral radius by power iteration
//! ([`spectral_radius`], [`StiffnessCap`]'s settings with the boundary √12), so that at
//! loose tolerances the step sits just inside the stability limit instead of being found
//! there by rejections.

use crate::{EnglandConfig, Pair, PairTableau, PiSettings, Real, Result, StiffnessCap};

/// Stages of the pair.
pub const STAGES: usize = 5;

/// Merson's 4(3) pair (see the module documentation for its source).
pub const MERSON: PairTableau<STAGES> = PairTableau {
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
    fsal: false,
    imaginary_boundary: IMAGINARY_BOUNDARY,
    pi: (0.7 / 4.0, 0.4 / 4.0),
};

/// Merson's imaginary-axis stability boundary, `|hλ|` (√12).
pub const IMAGINARY_BOUNDARY: f64 = 3.464_101_615_137_754_6;

/// Hairer's PI settings for an estimate of local order 4 (see the module documentation).
pub fn merson_pi<T: Real>() -> PiSettings<T> {
    MERSON.pi_settings()
}

/// Merson's adaptive pair for `N` equations ([`Pair`] with [`MERSON`]).
pub type Merson<T, const N: usize> = Pair<T, N, STAGES>;

impl<T: Real, const N: usize> Pair<T, N, STAGES> {
    /// Merson's pair with `config` (step sizes are single-step sizes here). Errors: a
    /// negative or non-finite tolerance, a non-positive or non-finite step size,
    /// `h_min > h_max`.
    pub fn new(config: EnglandConfig<T, N>) -> Result<Self> {
        Self::with_tableau(&MERSON, config)
    }

    /// As [`Merson::new`](Pair::new), the step also capped by the stiffness estimate
    /// ([`Pair::with_tableau_and_cap`]: the boundary is Merson's √12).
    pub fn with_cap(config: EnglandConfig<T, N>, cap: StiffnessCap<T>) -> Result<Self> {
        Self::with_tableau_and_cap(&MERSON, config, cap)
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
    use crate::{EnglandConfig, Error, OdeSystem, Tolerance};
    use core::ops::ControlFlow;

    /// `sum_i w_i g(i)`.
    fn dot(w: &[f64; STAGES], g: impl Fn(usize) -> f64) -> f64 {
        (0..STAGES).map(|i| w[i] * g(i)).sum()
    }

    fn ac(t: &PairTableau<STAGES>, p: i32) -> [f64; STAGES] {
        core::array::from_fn(|i| (0..STAGES).map(|j| t.a[i][j] * t.c[j].powi(p)).sum())
    }

    /// The eight conditions of order 4 for weights `w` (Butcher), as residuals.
    fn order4_residuals(t: &PairTableau<STAGES>, w: &[f64; STAGES]) -> [f64; 8] {
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
    fn stability_poly(t: &PairTableau<STAGES>, w: &[f64; STAGES]) -> [f64; 6] {
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
        let modulus = |y: f64| crate::solve::pair::testing::imaginary_modulus(p, y);
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

    use crate::solve::pair::testing::Oscillator;

    fn fixed(h: f64, n: u32) -> (f64, crate::SolverStats) {
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
        crate::solve::pair::testing::meets_its_tolerance(&MERSON, 5, 4);
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
