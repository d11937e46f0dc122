//! The spectral radius of a system's Jacobian, estimated by power iteration with
//! finite-difference products: what the stiffness cap ([`StiffnessCap`](crate::StiffnessCap)) limits the step
//! by when the system does not report it ([`OdeSystem::spectral_radius`]).

use crate::{Error, OdeSystem, Real, Result, Tolerance};

/// `x > 0` (false for NaN).
#[inline]
fn positive<T: Real>(x: T) -> bool {
    x > T::ZERO
}

/// Euclidean norm.
#[inline]
fn norm2<T: Real, const N: usize>(v: &[T; N]) -> T {
    v.iter().fold(T::ZERO, |a, x| a + *x * *x).sqrt()
}

/// Dot product.
#[inline]
fn dot<T: Real, const N: usize>(a: &[T; N], b: &[T; N]) -> T {
    a.iter()
        .zip(b.iter())
        .fold(T::ZERO, |s, (x, y)| s + *x * *y)
}

/// A fixed, well-mixed start vector (no structure that a test matrix could be orthogonal to).
fn seed<T: Real, const N: usize>(v: &mut [T; N]) {
    for (i, x) in v.iter_mut().enumerate() {
        let h = (i as u32)
            .wrapping_add(1)
            .wrapping_mul(2_654_435_761)
            .rotate_right(13)
            % 1000;
        *x = T::from_usize(h as usize) * T::from_f64(1e-3) - T::from_f64(0.4999);
    }
}

/// Spectral-radius estimate of the Jacobian `J = ∂f/∂y` at `(t, y)` (`f_y = f(t, y)`)
/// by power iteration with finite-difference products, for [`StiffnessCap`](crate::StiffnessCap).
///
/// It works on `D⁻¹ J D` (same eigenvalues) with `D = diag(atol_i + rtol |y_i|)`, so that
/// components of different units are comparable; a product is
/// `D⁻¹ (f(y + ε D u) - f(y)) / ε` with `ε = √eps · max(1, ‖D⁻¹ y‖∞)` (one evaluation).
/// A real matrix's dominant eigenvalues may be a complex pair (an oscillation), for which
/// the plain ratio `‖J u‖/‖u‖` never settles; so every iteration fits the two-term
/// projects `J` on `span{u, J u}` (Arnoldi with two vectors, orthonormalised: no extra
/// evaluation, since `J (J u)` is the next iterate anyway) and takes the larger modulus of
/// the two Ritz values, which is exact once `u` lies in the invariant subspace of a
/// dominant real eigenvalue or complex pair; when `u` and `J u` are numerically parallel
/// it uses `√(‖J u‖ ‖J² u‖)` for unit `u` instead.
///
/// `v` is the start vector and returns the last iterate, both in the original coordinates
/// (pass it back for a warm start; a zero or non-finite `v` is replaced by a fixed seed). Stops when the estimate changes
/// by at most `rel_tol` relatively and the subspace's relative residual
/// `‖J w - P J w‖/‖J w‖` (`P` the projection on `span{u, J u}`, `w = J u/‖J u‖`) is at most
/// `rel_tol` too (the Ritz value's error is about that residual), or after
/// `max_iterations` iterations (at least 1), returning the last estimate.
///
/// Accuracy: the products are finite differences, whose rounding is about
/// `eps |f| / |J δ|` relative. In the tolerance scaling a stiff oscillator's iterates
/// alternate between position- and velocity-dominated vectors whose images differ by
/// `(ρ/ω_scale)²`, so the small images carry more noise: a 3-mass system with a
/// 2.5e5 rad/s mode in the cam model's scaling is estimated to 3e-4. A Jacobian that is
/// extremely non-normal in the tolerance scaling (images 1e12 apart) defeats it; an
/// underestimate only loosens the cap. A system that knows its stiffest eigenvalue should
/// report it through [`OdeSystem::spectral_radius`]. Costs `1 + iterations` evaluations, added to `evals`.
#[allow(clippy::too_many_arguments)]
pub fn spectral_radius<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    y: &[T; N],
    f_y: &[T; N],
    tol: &Tolerance<T, N>,
    v: &mut [T; N],
    max_iterations: u32,
    rel_tol: T,
    evals: &mut u32,
) -> Result<T> {
    if N == 0 {
        return Ok(T::ZERO);
    }
    let (d, eps) = difference_scales(tol, y);

    let mut arg = [T::ZERO; N];
    let mut fz = [T::ZERO; N];
    // out = D⁻¹ (f(y + ε D u) - f(y)) / ε
    let mut jv = |u: &[T; N], out: &mut [T; N]| -> Result<()> {
        for (((a, yi), di), ui) in arg.iter_mut().zip(y.iter()).zip(d.iter()).zip(u.iter()) {
            *a = *yi + eps * *di * *ui;
        }
        sys.rhs(t, &arg, &mut fz);
        *evals = evals.saturating_add(1);
        for (i, (((o, f1), f0), di)) in out
            .iter_mut()
            .zip(fz.iter())
            .zip(f_y.iter())
            .zip(d.iter())
            .enumerate()
        {
            *o = (*f1 - *f0) / (eps * *di);
            if !o.is_finite() {
                return Err(Error::NonFinite {
                    t: t.to_f64(),
                    component: i,
                });
            }
        }
        Ok(())
    };

    let mut u = start_vector(v, &d);
    let mut w = [T::ZERO; N];
    jv(&u, &mut w)?;
    let mut nw = norm2(&w);
    if !positive(nw) {
        store(v, &u, &d);
        return Ok(T::ZERO);
    }
    // Below this sine of the angle between u and J u the pair is numerically one
    // direction (finite-difference noise ~√eps would dominate the 2x2 projection).
    let s_min = T::EPSILON.sqrt() * T::from_f64(1000.0);
    let mut rho = nw;
    let mut rho_prev = T::NAN;
    let mut z = [T::ZERO; N];
    let mut r = [T::ZERO; N];
    let mut jq2 = [T::ZERO; N];
    for it in 0..max_iterations.max(1) {
        for x in w.iter_mut() {
            *x /= nw;
        }
        // Now w = J u / ‖J u‖ (unit); z = J w.
        jv(&w, &mut z)?;
        let nz = norm2(&z);
        // Orthonormal basis (u, q2) of span{u, J u}: r = w - c u, q2 = r / ‖r‖.
        let c = dot(&u, &w);
        for ((ri, wi), ui) in r.iter_mut().zip(w.iter()).zip(u.iter()) {
            *ri = *wi - c * *ui;
        }
        let s = norm2(&r);
        // Relative residual of span{u, J u} as an invariant subspace (0 in the
        // one-direction case, which only the change of the estimate judges).
        let mut residual = T::ZERO;
        rho = if s > s_min {
            let (modulus, res) = ritz_modulus(&u, &w, &z, (nw, nz), c, s, &mut r, &mut jq2);
            residual = res;
            modulus
        } else {
            // One direction: |λ| from two successive ratios (also right for a purely
            // imaginary pair seen in a non-normal scaling, where one ratio alone swings).
            (nw * nz).sqrt()
        };
        u = w;
        w = z;
        nw = nz;
        // Two estimates that agree can still both be off (the change may pause while
        // the subspace is not yet invariant); the residual is what tracks the error.
        let done = it > 0 && (rho - rho_prev).abs() <= rel_tol * rho && residual <= rel_tol;
        rho_prev = rho;
        if done || !positive(nw) {
            break;
        }
    }
    store(v, &u, &d);
    Ok(rho)
}

/// The power iteration's start in the scaled coordinates: the last vector `v` as
/// `D⁻¹ v`, normalised (a fixed seed if it is zero or not finite). `v` is kept in the
/// original coordinates, so that a change of D (with y) between two estimates does not
/// turn a converged eigenvector into a contaminated start.
fn start_vector<T: Real, const N: usize>(v: &[T; N], d: &[T; N]) -> [T; N] {
    let mut u = [T::ZERO; N];
    for ((a, b), di) in u.iter_mut().zip(v.iter()).zip(d.iter()) {
        *a = *b / *di;
    }
    let mut nu = norm2(&u);
    if !(nu > T::ZERO && nu.is_finite()) {
        seed(&mut u);
        nu = norm2(&u);
    }
    for a in u.iter_mut() {
        *a /= nu;
    }
    u
}

/// The scales `D_i` of [`spectral_radius`]'s products and their difference step
/// `ε = √eps · max(1, ‖D⁻¹ y‖∞)`; a zero scale (atol_i = 0 at y_i = 0) borrows the
/// largest other one.
fn difference_scales<T: Real, const N: usize>(tol: &Tolerance<T, N>, y: &[T; N]) -> ([T; N], T) {
    let mut d = [T::ZERO; N];
    let mut d_max = T::ZERO;
    for (i, (di, yi)) in d.iter_mut().zip(y.iter()).enumerate() {
        *di = tol.scale(i, *yi);
        d_max = d_max.max(*di);
    }
    if !(d_max > T::ZERO && d_max.is_finite()) {
        d_max = T::ONE;
    }
    let mut y_scaled = T::ONE;
    for (di, yi) in d.iter_mut().zip(y.iter()) {
        if !positive(*di) {
            *di = d_max;
        }
        y_scaled = y_scaled.max(yi.abs() / *di);
    }
    (d, T::EPSILON.sqrt() * y_scaled)
}

/// One Rayleigh-Ritz step of [`spectral_radius`]: `J` projected on `span{u, J u}`
/// (`u` unit, `w = J u/‖J u‖`, `z = J w`, `norms = (‖J u‖, ‖z‖)`, `c = u·w`, `s = ‖r‖`
/// for `r = w − c u`, which becomes `q2 = r/s`), as `H = Qᵀ J Q` with `J u = ‖J u‖ w`
/// and `J q2 = (z − c ‖J u‖ w)/s`. Returns the larger modulus of `H`'s two eigenvalues
/// and the subspace's relative residual `‖z − (u·z) u − (q2·z) q2‖/‖z‖`; `jq2` is
/// scratch.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn ritz_modulus<T: Real, const N: usize>(
    u: &[T; N],
    w: &[T; N],
    z: &[T; N],
    norms: (T, T),
    c: T,
    s: T,
    r: &mut [T; N],
    jq2: &mut [T; N],
) -> (T, T) {
    let (nw, nz) = norms;
    for (((j, zi), wi), ri) in jq2.iter_mut().zip(z.iter()).zip(w.iter()).zip(r.iter_mut()) {
        *j = (*zi - c * nw * *wi) / s;
        *ri /= s;
    }
    let h11 = nw * c;
    let h21 = nw * s;
    let h12 = dot(u, jq2);
    let h22 = dot(r, jq2);
    // z - (u·z) u - (q2·z) q2, reusing jq2 as scratch.
    let (uz, qz) = (dot(u, z), dot(r, z));
    for (((j, zi), ui), qi) in jq2.iter_mut().zip(z.iter()).zip(u.iter()).zip(r.iter()) {
        *j = *zi - uz * *ui - qz * *qi;
    }
    let residual = norm2(jq2) / nz;
    let tr = h11 + h22;
    let det = h11 * h22 - h12 * h21;
    let disc = tr * tr - T::from_f64(4.0) * det;
    let modulus = if disc >= T::ZERO {
        T::HALF * (tr.abs() + disc.sqrt())
    } else {
        det.sqrt()
    };
    (modulus, residual)
}

/// `v = D u`, normalised to a largest entry of 1 (a direction in the original coordinates).
fn store<T: Real, const N: usize>(v: &mut [T; N], u: &[T; N], d: &[T; N]) {
    let mut big = T::ZERO;
    for ((a, b), di) in v.iter_mut().zip(u.iter()).zip(d.iter()) {
        *a = *b * *di;
        big = big.max(a.abs());
    }
    if positive(big) && big.is_finite() {
        for a in v.iter_mut() {
            *a /= big;
        }
    }
}
