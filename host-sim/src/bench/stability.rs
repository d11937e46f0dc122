//! The stability limit of each method on the model, from the eigenvalues of the model's
//! own Jacobian along the reference solution.
//!
//! At each sample of the reference the Jacobian `∂f/∂y` is formed by central differences
//! (in coordinates scaled by each component's magnitude, which leaves the eigenvalues
//! unchanged and the matrix balanced) and all its eigenvalues come from nalgebra's real
//! Schur decomposition. A method with stability function `R` is stable for an eigenvalue
//! `λ` at step `h` when `|R(hλ)| ≤ 1`; along the ray of `λ` that holds up to the first exit
//! `r(arg λ)` of the stability region, so the step limit there is `min over λ of
//! r(arg λ)/|λ|`. England's double step is two RK4 steps, so its limit is twice RK4's.
//! Integrated over the revolution, `∫ dt / h_limit(t)` is the fewest steps a method that
//! always ran exactly at its limit would take; a fixed step must stay below the smallest
//! limit of the revolution.

use anyhow::{anyhow, Result};
use camsim_core::{solver_config, spectral_radius, CamModel, OdeSystem, Scene, SolverSettings};
use nalgebra::{Complex, DMatrix, Schur};
use serde::Serialize;

/// An explicit method's stability function.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Classic RK4: `1 + z + z²/2 + z³/6 + z⁴/24`.
    Rk4,
    /// Dormand-Prince 5(4) (the fifth-order solution): RK4's plus `z⁵/120 + z⁶/600`.
    Dopri5,
    /// Merson's 4(3) pair: RK4's plus `z⁵/144` (√12 on the imaginary axis).
    Merson,
}

impl Scheme {
    /// `R(z)`.
    pub fn amplification(&self, z: Complex<f64>) -> Complex<f64> {
        let coef: &[f64] = match self {
            Scheme::Rk4 => &[1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0],
            Scheme::Dopri5 => &[
                1.0,
                1.0,
                1.0 / 2.0,
                1.0 / 6.0,
                1.0 / 24.0,
                1.0 / 120.0,
                1.0 / 600.0,
            ],
            Scheme::Merson => &[1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 144.0],
        };
        coef.iter().rev().fold(Complex::new(0.0, 0.0), |acc, c| {
            acc * z + Complex::new(*c, 0.0)
        })
    }

    /// The first `r > 0` at which `|R(r · dir)|` exceeds `1 + 1e-9` (`dir` a unit
    /// complex number; a growth below 1e-9 per step is rounding, and harmless over the
    /// 1e4 steps of a revolution): scanned in steps of 1e-3, then bisected. Infinity if
    /// none below 10.
    pub fn ray_limit(&self, dir: Complex<f64>) -> f64 {
        let unstable = |r: f64| self.amplification(dir * r).norm() > 1.0 + 1e-9;
        let dr = 1e-3;
        let mut r = dr;
        while r < 10.0 {
            if unstable(r) {
                let (mut lo, mut hi) = (r - dr, r);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    if unstable(mid) {
                        hi = mid;
                    } else {
                        lo = mid;
                    }
                }
                return lo;
            }
            r += dr;
        }
        f64::INFINITY
    }

    /// The largest stable step for the eigenvalues `eig` (an eigenvalue with a positive
    /// real part is growth of the problem itself: only its imaginary part is counted).
    pub fn step_limit(&self, eig: &[Complex<f64>]) -> f64 {
        let rho = eig.iter().map(|l| l.norm()).fold(0.0, f64::max);
        let mut h = f64::INFINITY;
        for l in eig {
            let l = if l.re > 0.0 {
                Complex::new(0.0, l.im.abs())
            } else {
                *l
            };
            let m = l.norm();
            // The slow eigenvalues cannot bind (the stiffest one binds at ~3/ρ).
            if m <= 0.05 * rho || m == 0.0 {
                continue;
            }
            h = h.min(self.ray_limit(l / m) / m);
        }
        h
    }
}

/// The Jacobian `∂f/∂y` at `(t, y)` by central differences, returned as `D⁻¹ J D`
/// (`D = diag(scale)`: the same eigenvalues, comparable entries); component `c` is
/// perturbed by `±1e-6 · scale_c`.
pub fn scaled_jacobian<S: Scene, const N: usize>(
    model: &CamModel<f64, S, N>,
    t: f64,
    y: &[f64; N],
    scale: &[f64; N],
) -> DMatrix<f64> {
    let mut j = DMatrix::<f64>::zeros(N, N);
    let (mut fp, mut fm) = ([0.0; N], [0.0; N]);
    for c in 0..N {
        let d = 1e-6 * scale[c];
        let (mut yp, mut ym) = (*y, *y);
        yp[c] += d;
        ym[c] -= d;
        let d2 = yp[c] - ym[c];
        model.rhs(t, &yp, &mut fp);
        model.rhs(t, &ym, &mut fm);
        for r in 0..N {
            j[(r, c)] = (fp[r] - fm[r]) / d2 * scale[c] / scale[r];
        }
    }
    j
}

/// The eigenvalues of a square matrix (real Schur decomposition).
pub fn eigenvalues(m: DMatrix<f64>) -> Result<Vec<Complex<f64>>> {
    let schur = Schur::try_new(m, f64::EPSILON, 100_000)
        .ok_or_else(|| anyhow!("the Schur decomposition of the Jacobian did not converge"))?;
    Ok(schur.complex_eigenvalues().iter().copied().collect())
}

/// The stability analysis along the reference's sampled revolution.
#[derive(Clone, Debug, Serialize)]
pub struct StabilityLimit {
    /// Jacobians analysed (samples of the revolution).
    pub points: usize,
    /// Smallest and largest spectral radius over the revolution, 1/s.
    pub rho_min: f64,
    /// Largest spectral radius, 1/s.
    pub rho_max: f64,
    /// Damping ratio `-Re λ / |λ|` of the stiffest eigenvalue where ρ is largest.
    pub stiffest_damping_ratio: f64,
    /// The stiffest eigenvalue where ρ is largest, (Re, Im), 1/s.
    pub stiffest_eigenvalue: [f64; 2],
    /// Fewest England double steps per revolution (always at its limit).
    pub england_double_steps_per_rev: f64,
    /// Fewest RK4 steps per revolution at a variable step.
    pub rk4_steps_per_rev: f64,
    /// Fewest RK4 steps per nominal revolution at a fixed step (the smallest limit).
    pub rk4_fixed_steps_per_rev: f64,
    /// Fewest Dormand-Prince steps per revolution.
    pub dopri5_steps_per_rev: f64,
    /// Fewest Merson 4(3) steps per revolution.
    pub merson_steps_per_rev: f64,
    /// Merson's stability boundary on the imaginary axis (√12).
    pub merson_imaginary_boundary: f64,
    /// RK4's stability boundary on the imaginary axis, `|hλ|` (2√2).
    pub rk4_imaginary_boundary: f64,
    /// Dormand-Prince's on the imaginary axis.
    pub dopri5_imaginary_boundary: f64,
    /// RK4's and Dormand-Prince's boundaries along the stiffest eigenvalue's ray.
    pub rk4_boundary_at_stiffest: f64,
    /// Dormand-Prince's boundary along the stiffest eigenvalue's ray.
    pub dopri5_boundary_at_stiffest: f64,
    /// The stiffness cap's power-iteration estimate (England with `pi_capped`, the
    /// solver's default tolerance scaling) over the eigenvalues' ρ: smallest ratio.
    pub power_over_eig_min: f64,
    /// Median ratio.
    pub power_over_eig_median: f64,
    /// Largest ratio.
    pub power_over_eig_max: f64,
}

/// Analyses the Jacobian at every `stride`-th sample (times `t`, states `states`) of
/// `model`'s sampled revolution. `settings` gives the tolerance scaling of the power
/// iteration (as the stiffness cap runs it).
pub fn analyse<S: Scene, const N: usize>(
    model: &CamModel<f64, S, N>,
    settings: &SolverSettings<f64>,
    t: &[f64],
    states: &[Vec<f64>],
    stride: usize,
) -> Result<StabilityLimit> {
    let config = solver_config(model, settings, 1)?;
    // Scale of each component: its magnitude, at least 1e3 atol_i (a position 1e-5 in).
    let typical: Vec<f64> = config.tol.atol.iter().map(|a| 1e3 * a).collect();
    let stride = stride.max(1);
    let n = t.len().min(states.len());
    anyhow::ensure!(
        n >= 2,
        "too few reference samples for the stability analysis"
    );
    let mut tally = Tally::default();
    let mut v = [0.0; N];
    let mut k = 0;
    while k < n {
        let next = (k + stride).min(n - 1);
        // The time this point stands for: to the next analysed point (the last one: the
        // spacing before it).
        let dt = if next > k {
            t[next] - t[k]
        } else {
            t[k] - t[k - stride.min(k)]
        };
        let y = state_at::<N>(&states[k]);
        let eig = eigenvalues_at(model, t[k], &y, &typical)?;
        let rho = tally.add(&eig, dt);
        let mut f = [0.0; N];
        model.rhs(t[k], &y, &mut f);
        let mut evals = 0;
        let p = spectral_radius(
            model,
            t[k],
            &y,
            &f,
            &config.tol,
            &mut v,
            20,
            1e-3,
            &mut evals,
        )?;
        tally.ratios.push(p / rho);
        if next == k {
            break;
        }
        k = next;
    }
    let revolution_time = t[n - 1] - t[0];
    // The sums cover t[0]..t[n-1] plus the last point's share: per revolution.
    let covered = revolution_time + (t[n - 1] - t[n - 1 - stride.min(n - 1)]);
    let period = 2.0 * std::f64::consts::PI / model.design().omega0;
    Ok(tally.limit(period, period / covered))
}

/// A reference sample's state as the model's array (missing components 0).
fn state_at<const N: usize>(state: &[f64]) -> [f64; N] {
    let mut y = [0.0; N];
    for (a, b) in y.iter_mut().zip(state) {
        *a = *b;
    }
    y
}

/// The eigenvalues of the model's Jacobian at `(t, y)`, in coordinates scaled by each
/// component's magnitude (at least `typical`).
fn eigenvalues_at<S: Scene, const N: usize>(
    model: &CamModel<f64, S, N>,
    t: f64,
    y: &[f64; N],
    typical: &[f64],
) -> Result<Vec<Complex<f64>>> {
    let mut scale = [0.0; N];
    for ((s, yi), ty) in scale.iter_mut().zip(y.iter()).zip(typical) {
        *s = yi.abs().max(*ty);
    }
    eigenvalues(scaled_jacobian(model, t, y, &scale))
}

/// The running sums and extremes of the analysed points.
struct Tally {
    sum_england: f64,
    sum_rk4: f64,
    sum_dopri: f64,
    sum_merson: f64,
    h_rk4_min: f64,
    rho_min: f64,
    rho_max: f64,
    stiffest: Complex<f64>,
    /// Power-iteration estimate over ρ at each point.
    ratios: Vec<f64>,
    points: usize,
}

impl Default for Tally {
    fn default() -> Self {
        Tally {
            sum_england: 0.0,
            sum_rk4: 0.0,
            sum_dopri: 0.0,
            sum_merson: 0.0,
            h_rk4_min: f64::INFINITY,
            rho_min: f64::INFINITY,
            rho_max: 0.0,
            stiffest: Complex::new(0.0, 0.0),
            ratios: Vec::new(),
            points: 0,
        }
    }
}

impl Tally {
    /// Counts a point with eigenvalues `eig` standing for `dt` seconds: its spectral
    /// radius (returned) and each method's steps over `dt` at its limit.
    fn add(&mut self, eig: &[Complex<f64>], dt: f64) -> f64 {
        let top = eig
            .iter()
            .copied()
            .max_by(|a, b| a.norm().total_cmp(&b.norm()))
            .unwrap_or_default();
        let rho = top.norm();
        self.rho_min = self.rho_min.min(rho);
        if rho > self.rho_max {
            self.rho_max = rho;
            self.stiffest = top;
        }
        let h_rk4 = Scheme::Rk4.step_limit(eig);
        let h_dopri = Scheme::Dopri5.step_limit(eig);
        self.h_rk4_min = self.h_rk4_min.min(h_rk4);
        self.sum_rk4 += dt / h_rk4;
        self.sum_england += dt / (2.0 * h_rk4);
        self.sum_dopri += dt / h_dopri;
        self.sum_merson += dt / Scheme::Merson.step_limit(eig);
        self.points += 1;
        rho
    }

    /// The analysis: the sums scaled by `per_rev` (a revolution's `period`, s, over the
    /// time they cover), the fixed step's count over a revolution, the boundaries.
    fn limit(mut self, period: f64, per_rev: f64) -> StabilityLimit {
        let stiffest = self.stiffest;
        let ratios = &mut self.ratios;
        ratios.sort_by(f64::total_cmp);
        let dir = if stiffest.norm() > 0.0 {
            stiffest / stiffest.norm()
        } else {
            Complex::new(0.0, 1.0)
        };
        StabilityLimit {
            points: self.points,
            rho_min: self.rho_min,
            rho_max: self.rho_max,
            stiffest_damping_ratio: -stiffest.re / stiffest.norm(),
            stiffest_eigenvalue: [stiffest.re, stiffest.im],
            england_double_steps_per_rev: self.sum_england * per_rev,
            rk4_steps_per_rev: self.sum_rk4 * per_rev,
            rk4_fixed_steps_per_rev: period / self.h_rk4_min,
            dopri5_steps_per_rev: self.sum_dopri * per_rev,
            merson_steps_per_rev: self.sum_merson * per_rev,
            merson_imaginary_boundary: Scheme::Merson.ray_limit(Complex::new(0.0, 1.0)),
            rk4_imaginary_boundary: Scheme::Rk4.ray_limit(Complex::new(0.0, 1.0)),
            dopri5_imaginary_boundary: Scheme::Dopri5.ray_limit(Complex::new(0.0, 1.0)),
            rk4_boundary_at_stiffest: Scheme::Rk4.ray_limit(dir),
            dopri5_boundary_at_stiffest: Scheme::Dopri5.ray_limit(dir),
            power_over_eig_min: ratios.first().copied().unwrap_or(f64::NAN),
            power_over_eig_median: ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN),
            power_over_eig_max: ratios.last().copied().unwrap_or(f64::NAN),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_boundaries_are_the_known_ones() {
        // Imaginary axis: |R(iy)|² = 1 - y⁶/72 + y⁸/576, so 2√2; negative real axis 2.785.
        let im = Scheme::Rk4.ray_limit(Complex::new(0.0, 1.0));
        assert!((im - 8f64.sqrt()).abs() < 1e-6, "{im}");
        let re = Scheme::Rk4.ray_limit(Complex::new(-1.0, 0.0));
        assert!((re - 2.785).abs() < 1e-3, "{re}");
    }

    #[test]
    fn dopri5_boundary_on_the_negative_real_axis() {
        // Hairer-Wanner's figure: about 3.3 on the negative real axis.
        let re = Scheme::Dopri5.ray_limit(Complex::new(-1.0, 0.0));
        assert!((re - 3.31).abs() < 0.02, "{re}");
    }

    #[test]
    fn eigenvalues_of_a_damped_oscillator() {
        // x'' + 2ζω x' + ω² x = 0: λ = -ζω ± iω√(1-ζ²).
        let (w, z) = (2.5e5, 0.05);
        let m = DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -w * w, -2.0 * z * w]);
        let e = eigenvalues(m).unwrap();
        for l in e {
            assert!((l.re + z * w).abs() < 1e-6 * w, "{l}");
            assert!(
                (l.im.abs() - w * (1.0 - z * z).sqrt()).abs() < 1e-6 * w,
                "{l}"
            );
        }
    }
}

#[cfg(test)]
mod model_tests {
    use super::*;
    use crate::bench::methods::{run, Method};
    use crate::bench::sample::Sampler;
    use camsim_core::{Design, RegulatedFullModel, Start};

    #[test]
    fn the_jacobians_eigenvalues_and_the_caps_power_iteration_agree_on_the_model() {
        // Two independent estimates of the spectral radius along revolution 2: nalgebra's
        // Schur decomposition of a central-difference Jacobian, and the stiffness cap's
        // Arnoldi-type power iteration on one-sided products (cold-started 24 samples
        // apart here, so within a few per cent; the bench's neighbouring samples agree to 1 %).
        // The reference design (800 rpm).
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let s = SolverSettings {
            rtol: 1e-8,
            atol: 1e-11,
            start: Start::Static,
            ..SolverSettings::reference()
        };
        let mut sampler = Sampler::new(&m, 2, Some(2)).keep_states();
        run(Method::England, &m, &s, 2, &mut sampler).unwrap();
        let l = analyse(
            &m,
            &SolverSettings::reference(),
            &sampler.samples.t,
            &sampler.samples.states,
            24,
        )
        .unwrap();
        assert_eq!(l.points, 31);
        assert!(
            l.power_over_eig_min > 0.97 && l.power_over_eig_max < 1.03,
            "{l:?}"
        );
        // The stiffest mode is lightly damped (almost on the imaginary axis) ...
        assert!(l.stiffest_damping_ratio > 0.0 && l.stiffest_damping_ratio < 0.05);
        // ... so the boundaries along it are close to the imaginary axis's for RK4, and
        // England's double step is two RK4 steps: half RK4's steps at a variable step.
        assert!((l.rk4_boundary_at_stiffest / 8f64.sqrt() - 1.0).abs() < 0.02);
        assert!((l.rk4_steps_per_rev / l.england_double_steps_per_rev - 2.0).abs() < 1e-12);
        // A fixed step must be below the smallest limit: more steps than a variable one.
        assert!(l.rk4_fixed_steps_per_rev > l.rk4_steps_per_rev);
        // ρ between the smallest and the largest bound the fixed and variable limits.
        let period = 2.0 * std::f64::consts::PI / m.design().omega0;
        let boundary = l.rk4_boundary_at_stiffest;
        assert!(l.rk4_fixed_steps_per_rev <= 1.02 * period * l.rho_max / boundary);
        assert!(l.rk4_steps_per_rev >= 0.98 * period * l.rho_min / 8f64.sqrt());
    }
}
