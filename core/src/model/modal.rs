//! Modal analysis of the linearised rotational and translational systems (Section VI.2,
//! Eqs. VI.2-VI.7) with a small fixed-size symmetric generalized eigensolver.
//!
//! The free undamped system `M x'' + K x = 0` (Eq. VI.2) has modes `x = φ sin(ω t)` with
//! `K φ = ω² M φ`. [`generalized_eigen`] reduces this to a standard symmetric problem with
//! the Cholesky factor of `M` (`M = L Lᵀ`, `A = L⁻¹ K L⁻ᵀ`) and diagonalises `A` by cyclic
//! Jacobi rotations, which are accurate for small matrices whatever their conditioning
//! (the translational system mixes 100 lb/in and 1.5e6 lb/in springs).

// Indices come from iterators (rows, `zip`, `enumerate`); the few entries picked by
// position are read with `get`, whose `None` cannot happen for indices below N.

use crate::{Error, Real, Result};

/// Cyclic sweeps allowed before [`Error::NoConvergence`]; Jacobi converges quadratically,
/// so a handful suffice for the small matrices of Section VI.2.
const JACOBI_MAX_SWEEPS: u32 = 64;

/// The transpose of `a` (the columns of a matrix are the rows of its transpose).
fn transpose<T: Copy, const N: usize>(a: &[[T; N]; N]) -> [[T; N]; N] {
    let mut t = *a;
    for (i, row) in a.iter().enumerate() {
        // t[j][i] = a[i][j] for every j.
        for (&v, t_row) in row.iter().zip(t.iter_mut()) {
            if let Some(x) = t_row.get_mut(i) {
                *x = v;
            }
        }
    }
    t
}

/// Entry `(i, j)` of `a`, if it has one.
fn entry<T: Copy, const N: usize>(a: &[[T; N]; N], i: usize, j: usize) -> Option<T> {
    a.get(i).and_then(|row| row.get(j)).copied()
}

/// Entries `p` and `q` of `s`, both mutable (`None` unless `p < q < s.len()`).
fn pair_mut<T>(s: &mut [T], p: usize, q: usize) -> Option<(&mut T, &mut T)> {
    let (lo, hi) = s.split_at_mut_checked(q)?;
    Some((lo.get_mut(p)?, hi.first_mut()?))
}

/// Swaps entries `i < j` of `s` (nothing otherwise).
fn swap_entries<T>(s: &mut [T], i: usize, j: usize) {
    if let Some((a, b)) = pair_mut(s, i, j) {
        core::mem::swap(a, b);
    }
}

/// Index of the smallest of `x[i..]` (the first one on ties; `i` if it is out of range).
fn argmin_from<T: Real>(x: &[T], i: usize) -> usize {
    let Some(&first) = x.get(i) else {
        return i;
    };
    let (mut best, mut best_v) = (i, first);
    for (j, &v) in x.iter().enumerate().skip(i + 1) {
        if v < best_v {
            best = j;
            best_v = v;
        }
    }
    best
}

/// Checks that a matrix is finite and symmetric (relative to its largest entry).
fn check_symmetric<T: Real, const N: usize>(a: &[[T; N]; N], field: &'static str) -> Result<T> {
    let mut amax = T::ZERO;
    for row in a.iter() {
        for &v in row.iter() {
            if !v.is_finite() {
                return Err(Error::InvalidParameter {
                    field,
                    rule: "every entry must be finite",
                    value: v.to_f64(),
                });
            }
            amax = amax.max(v.abs());
        }
    }
    let tol = T::from_f64(64.0) * T::EPSILON * amax;
    let at = transpose(a);
    for (i, (row, row_t)) in a.iter().zip(at.iter()).enumerate() {
        // a[i][j] - a[j][i] for j > i.
        for (&aij, &aji) in row.iter().zip(row_t.iter()).skip(i + 1) {
            let d = aij - aji;
            if d.abs() > tol {
                return Err(Error::InvalidParameter {
                    field,
                    rule: "must be symmetric",
                    value: d.to_f64(),
                });
            }
        }
    }
    Ok(amax)
}

/// Lower Cholesky factor `L` of a symmetric positive-definite `m` (`m = L Lᵀ`), row by
/// row (row `i` needs only the rows above it; the first pivot that fails is the same as
/// column by column, and every entry is the same sum in the same order).
fn cholesky<T: Real, const N: usize>(m: &[[T; N]; N]) -> Result<[[T; N]; N]> {
    let mut l = [[T::ZERO; N]; N];
    let rel = T::from_usize(N) * T::EPSILON;
    for (i, m_row) in m.iter().enumerate() {
        let Some((done, rest)) = l.split_at_mut_checked(i) else {
            break;
        };
        let Some(l_row) = rest.first_mut() else {
            break;
        };
        // l[i][j] = (m[i][j] - Σ_{k<j} l[i][k] l[j][k]) / l[j][j], j < i.
        for (j, (l_j, &mij)) in done.iter().zip(m_row.iter()).enumerate() {
            let mut v = mij;
            for (lik, ljk) in l_row.iter().zip(l_j.iter()).take(j) {
                v -= *lik * *ljk;
            }
            if let (Some(&ljj), Some(lij)) = (l_j.get(j), l_row.get_mut(j)) {
                *lij = v / ljj;
            }
        }
        let Some(&mii) = m_row.get(i) else {
            break;
        };
        let mut d = mii;
        for lik in l_row.iter().take(i) {
            d -= lik.sq();
        }
        // A pivot lost to rounding (relative to its diagonal entry) is singular in practice.
        if !(d.is_finite() && d > rel * mii.abs()) {
            return Err(Error::NotPositiveDefinite {
                what: "mass matrix m",
            });
        }
        if let Some(lii) = l_row.get_mut(i) {
            *lii = d.sqrt();
        }
    }
    Ok(l)
}

/// Solves `L x = b` in place (forward substitution; `L` from [`cholesky`]).
fn forward<T: Real, const N: usize>(l: &[[T; N]; N], x: &mut [T; N]) {
    for (i, l_row) in l.iter().enumerate() {
        let Some((done, rest)) = x.split_at_mut_checked(i) else {
            return;
        };
        let Some(xi) = rest.first_mut() else {
            return;
        };
        let mut v = *xi;
        for (lik, xk) in l_row.iter().zip(done.iter()) {
            v -= *lik * *xk;
        }
        // Diagonal is positive (checked by `cholesky`).
        if let Some(&lii) = l_row.get(i) {
            *xi = v / lii;
        }
    }
}

/// Solves `Lᵀ x = b` in place given `lt = Lᵀ` (back substitution).
fn backward<T: Real, const N: usize>(lt: &[[T; N]; N], x: &mut [T; N]) {
    for (i, lt_row) in lt.iter().enumerate().rev() {
        let Some((head, later)) = x.split_at_mut_checked(i + 1) else {
            return;
        };
        let Some(xi) = head.last_mut() else {
            return;
        };
        let mut v = *xi;
        for (lki, xk) in lt_row.iter().skip(i + 1).zip(later.iter()) {
            v -= *lki * *xk;
        }
        if let Some(&lii) = lt_row.get(i) {
            *xi = v / lii;
        }
    }
}

/// Applies the rotation `(c, s)` to columns `p < q` of `a`.
fn rotate_columns<T: Real, const N: usize>(a: &mut [[T; N]; N], p: usize, q: usize, c: T, s: T) {
    for row in a.iter_mut() {
        if let Some((kp, kq)) = pair_mut(row, p, q) {
            let (x, y) = (*kp, *kq);
            *kp = c * x - s * y;
            *kq = s * x + c * y;
        }
    }
}

/// Cyclic Jacobi diagonalisation of the symmetric `a` (overwritten by its eigenvalues on
/// the diagonal); `v` accumulates the rotations (eigenvectors as columns).
fn jacobi<T: Real, const N: usize>(
    a: &mut [[T; N]; N],
    v: &mut [[T; N]; N],
    max_sweeps: u32,
) -> Result<()> {
    for (i, row) in v.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = if i == j { T::ONE } else { T::ZERO };
        }
    }
    let mut norm2 = T::ZERO;
    for row in a.iter() {
        for &x in row.iter() {
            norm2 += x.sq();
        }
    }
    let target = (T::from_usize(4 * N) * T::EPSILON).sq() * norm2;
    // Beyond this |theta|, sqrt(theta^2 + 1) = |theta| to working precision.
    let big_theta = T::ONE / T::EPSILON;
    let mut sweeps = 0;
    loop {
        let mut off = T::ZERO;
        for (p, row) in a.iter().enumerate() {
            for x in row.iter().skip(p + 1) {
                off += x.sq();
            }
        }
        if off <= target || off == T::ZERO {
            return Ok(());
        }
        if !off.is_finite() || sweeps >= max_sweeps {
            return Err(Error::NoConvergence {
                what: "Jacobi eigensolver",
                iterations: sweeps,
            });
        }
        sweeps += 1;
        for p in 0..N {
            for q in (p + 1)..N {
                let (Some(apq), Some(app), Some(aqq)) =
                    (entry(a, p, q), entry(a, p, p), entry(a, q, q))
                else {
                    continue;
                };
                if apq == T::ZERO {
                    continue;
                }
                // Rotation zeroing a[p][q] (Golub & Van Loan, sym.Schur2). Only sqrt is used
                // (exact on every build; micromath's hypot is an approximation), with the
                // large-theta limit taken explicitly so theta^2 cannot overflow.
                let theta = (aqq - app) / (T::TWO * apq);
                let t = if theta.abs() > big_theta {
                    T::HALF / theta
                } else {
                    let r = T::ONE / (theta.abs() + (theta.sq() + T::ONE).sqrt());
                    if theta < T::ZERO {
                        -r
                    } else {
                        r
                    }
                };
                let c = T::ONE / (t.sq() + T::ONE).sqrt();
                let s = t * c;
                rotate_columns(a, p, q, c, s);
                if let Some((row_p, row_q)) = pair_mut(a, p, q) {
                    for (apk, aqk) in row_p.iter_mut().zip(row_q.iter_mut()) {
                        let (x, y) = (*apk, *aqk);
                        *apk = c * x - s * y;
                        *aqk = s * x + c * y;
                    }
                    if let (Some(x), Some(y)) = (row_p.get_mut(q), row_q.get_mut(p)) {
                        *x = T::ZERO;
                        *y = T::ZERO;
                    }
                }
                rotate_columns(v, p, q, c, s);
            }
        }
    }
}

/// Solves the symmetric generalized eigenproblem `K φ = ω² M φ` of Eq. VI.2: returns the
/// eigenvalues `ω²` in ascending order and the `M`-orthonormal eigenvectors as columns
/// (`vectors[i][j]` is component `i` of mode `j`, `Φᵀ M Φ = I`, `Φᵀ K Φ = diag(ω²)`).
///
/// Cholesky of `M` ([`Error::NotPositiveDefinite`]) then cyclic Jacobi on `L⁻¹ K L⁻ᵀ`
/// ([`Error::NoConvergence`] after 64 sweeps); non-finite or asymmetric input is
/// [`Error::InvalidParameter`] naming `k` or `m`. Eigenvalues are returned as computed
/// (a rigid-body mode may come out as a tiny positive or negative number).
pub fn generalized_eigen<T: Real, const N: usize>(
    k: &[[T; N]; N],
    m: &[[T; N]; N],
) -> Result<([T; N], [[T; N]; N])> {
    check_symmetric(k, "k")?;
    check_symmetric(m, "m")?;
    let l = cholesky(m)?;
    // A = L⁻¹ K L⁻ᵀ = L⁻¹ (L⁻¹ K)ᵀ since K is symmetric: L⁻¹ applied to the columns of K,
    // then to the columns of the transpose of that. A matrix's columns are the rows of
    // its transpose, so the solves run on rows: b_t = (L⁻¹ K)ᵀ, then a_t = (L⁻¹ b_t)ᵀ.
    let mut b_t = transpose(k);
    for row in b_t.iter_mut() {
        forward(&l, row);
    }
    let mut a_t = transpose(&b_t);
    for row in a_t.iter_mut() {
        forward(&l, row);
    }
    let mut a = transpose(&a_t);
    for (i, (row, row_t)) in a.iter_mut().zip(a_t.iter()).enumerate() {
        for (j, (aij, &aji)) in row.iter_mut().zip(row_t.iter()).enumerate() {
            if i != j {
                *aij = T::HALF * (*aij + aji);
            }
        }
    }
    let mut z = [[T::ZERO; N]; N];
    jacobi(&mut a, &mut z, JACOBI_MAX_SWEEPS)?;
    // Eigenvectors of the original problem: Φ = L⁻ᵀ Z, column by column (rows of z_t).
    let l_t = transpose(&l);
    let mut z_t = transpose(&z);
    for row in z_t.iter_mut() {
        backward(&l_t, row);
    }

    let mut lambda = [T::ZERO; N];
    for (i, (lam, row)) in lambda.iter_mut().zip(a.iter()).enumerate() {
        if let Some(&d) = row.get(i) {
            *lam = d;
        }
    }
    // Selection sort, ascending, swapping the eigenvectors along.
    for i in 0..N {
        let best = argmin_from(&lambda, i);
        if best != i {
            swap_entries(&mut lambda, i, best);
            swap_entries(&mut z_t, i, best);
        }
    }
    Ok((lambda, transpose(&z_t)))
}

/// Natural frequencies, normalised modes and modal stiffness of `M x'' + K x = 0`
/// (Section VI.2, Eqs. VI.2-VI.5).
#[derive(Clone, Copy, Debug)]
pub struct ModalAnalysis<T, const N: usize> {
    /// Angular natural frequencies ω (rad/s), ascending (Eq. VI.3); a rigid-body mode
    /// (Pᵀ K P within rounding of 0, see [`modal_analysis`]) is reported as exactly 0.
    pub omega: [T; N],
    /// Modal matrix P (Eq. VI.4): mode `j` is column `j` (`modes[i][j]`), normalised so
    /// its first row is 1 as in VI.4. If a mode's first entry is ~0 (below √ε times its
    /// largest-magnitude entry) it is normalised by its largest-magnitude entry instead;
    /// [`ModalAnalysis::normalized_by`] says which row was used.
    pub modes: [[T; N]; N],
    /// Modal stiffness, the diagonal of Pᵀ K P (Eq. VI.5); 0 for a rigid-body mode.
    pub modal_stiffness: [T; N],
    /// Modal mass, the diagonal of Pᵀ M P (so ω² = modal_stiffness / modal_mass).
    pub modal_mass: [T; N],
    /// Row whose entry is 1 in each mode column (0 unless that entry was ~0).
    pub normalized_by: [usize; N],
}

/// Modal analysis of the free undamped system `M x'' + K x = 0` (Section VI.2): ω from
/// Eq. VI.3, the modal matrix normalised to its first row (Eq. VI.4) and the modal
/// stiffness diag(Pᵀ K P) (Eq. VI.5).
///
/// ω² of each mode is taken as the Rayleigh quotient `pᵀKp / pᵀMp` of its computed
/// vector (equal to the eigenvalue in exact arithmetic, but second-order accurate in the
/// vector's error). A mode is rigid-body (ω = 0, modal stiffness 0) when `|pᵀKp|` is within
/// rounding of zero: at most `N·ε·|p|ᵀ|K||p|` (the rounding bound of that sum). This
/// separates a true rigid mode from a very soft one even in `f32`: the translational
/// system's 94 rad/s mode, held by the 100 lb/in spring among 1e6 lb/in springs, has
/// `|pᵀKp| ≈ 76 ε(f32)·|p|ᵀ|K||p|`, while computed rigid modes come out below 1e-3 ε. `K` must be positive semi-definite (a negative ω² beyond
/// rounding is [`Error::InvalidParameter`] on `k`); errors of [`generalized_eigen`] pass
/// through.
pub fn modal_analysis<T: Real, const N: usize>(
    k: &[[T; N]; N],
    m: &[[T; N]; N],
) -> Result<ModalAnalysis<T, N>> {
    let (_lambda, phi) = generalized_eigen(k, m)?;
    let small = T::EPSILON.sqrt();
    let rigid_rel = T::from_usize(N) * T::EPSILON;

    // Mode j is row j of the transposes.
    let phi_t = transpose(&phi);
    let mut modes_t = phi_t;
    let mut omega = [T::ZERO; N];
    let mut modal_stiffness = [T::ZERO; N];
    let mut modal_mass = [T::ZERO; N];
    let mut normalized_by = [0; N];
    for (((((raw, p), om), ks), ms), by) in phi_t
        .iter()
        .zip(modes_t.iter_mut())
        .zip(omega.iter_mut())
        .zip(modal_stiffness.iter_mut())
        .zip(modal_mass.iter_mut())
        .zip(normalized_by.iter_mut())
    {
        // Normalise the mode by its first entry, or by its largest if that is ~0.
        let mut big = 0;
        let mut big_abs = T::ZERO;
        for (i, x) in raw.iter().enumerate() {
            let a = x.abs();
            if a > big_abs {
                big_abs = a;
                big = i;
            }
        }
        let row = match raw.first() {
            Some(first) if first.abs() > small * big_abs => 0,
            _ => big,
        };
        let pivot = raw.get(row).copied().unwrap_or(T::ZERO);
        if !(pivot.is_finite() && pivot != T::ZERO) {
            // Unreachable for an M-orthonormal vector; keep the no-panic promise anyway.
            return Err(Error::NoConvergence {
                what: "modal normalisation",
                iterations: 0,
            });
        }
        for (x, &r) in p.iter_mut().zip(raw.iter()) {
            *x = r / pivot;
        }
        *by = row;
        let p: &[T; N] = p;

        // Eq. VI.5: diag(Pᵀ K P) and diag(Pᵀ M P), with the rounding scale |p|ᵀ|K||p|.
        let (mut pk, mut pm, mut pk_abs) = (T::ZERO, T::ZERO, T::ZERO);
        for ((k_row, m_row), &pr) in k.iter().zip(m.iter()).zip(p.iter()) {
            let (mut kr, mut mr, mut kr_abs) = (T::ZERO, T::ZERO, T::ZERO);
            for ((&krc, &mrc), &pc) in k_row.iter().zip(m_row.iter()).zip(p.iter()) {
                kr += krc * pc;
                kr_abs += krc.abs() * pc.abs();
                mr += mrc * pc;
            }
            pk += pr * kr;
            pk_abs += pr.abs() * kr_abs;
            pm += pr * mr;
        }
        if !(pm.is_finite() && pm > T::ZERO) {
            return Err(Error::NotPositiveDefinite {
                what: "mass matrix m",
            });
        }
        let rigid = pk.abs() <= rigid_rel * pk_abs;
        if !rigid && pk < T::ZERO {
            return Err(Error::InvalidParameter {
                field: "k",
                rule: "must be positive semi-definite (a mode has negative omega^2)",
                value: (pk / pm).to_f64(),
            });
        }
        *om = if rigid { T::ZERO } else { (pk / pm).sqrt() };
        *ks = if rigid { T::ZERO } else { pk };
        *ms = pm;
    }
    // Keep ω ascending (rounding could swap nearly equal frequencies).
    for i in 0..N {
        let best = argmin_from(&omega, i);
        if best != i {
            swap_entries(&mut omega, i, best);
            swap_entries(&mut modal_stiffness, i, best);
            swap_entries(&mut modal_mass, i, best);
            swap_entries(&mut normalized_by, i, best);
            swap_entries(&mut modes_t, i, best);
        }
    }
    Ok(ModalAnalysis {
        omega,
        modes: transpose(&modes_t),
        modal_stiffness,
        modal_mass,
        normalized_by,
    })
}

/// Stiffness and inertia matrices `(K, M)` of the rotational system, Eq. VI.7: motor
/// `I_m`, coupling `I_cp` and cam `I_c` (lb·in·s²) joined by the shafts `K_s1`, `K_s2`
/// (lb·in/rad); coordinates (θ_m, θ_cp, θ_c). Free at both ends, so it has a rigid mode.
pub fn rotational_system<T: Real>(
    i_m: T,
    i_cp: T,
    i_c: T,
    k_s1: T,
    k_s2: T,
) -> ([[T; 3]; 3], [[T; 3]; 3]) {
    let z = T::ZERO;
    let k = [
        [k_s1, -k_s1, z],
        [-k_s1, k_s1 + k_s2, -k_s2],
        [z, -k_s2, k_s2],
    ];
    let m = [[i_m, z, z], [z, i_cp, z], [z, z, i_c]];
    (k, m)
}

/// Stiffness and mass matrices `(K, M)` of the three-degree-of-freedom translational
/// system, Eq. VI.6 (Fig. VI.3): roller `M_r`, follower `M_f` and load `M_l` (lb·s²/in);
/// roller bearing `K_rb`, follower `K_f` and return spring `K_rs` (lb/in); coordinates
/// (y1, y2, y3).
pub fn translational_system<T: Real>(
    m_r: T,
    m_f: T,
    m_l: T,
    k_rb: T,
    k_f: T,
    k_rs: T,
) -> ([[T; 3]; 3], [[T; 3]; 3]) {
    let z = T::ZERO;
    let k = [
        [k_rb, -k_rb, z],
        [-k_rb, k_rb + k_f + k_rs, -k_f],
        [z, -k_f, k_f],
    ];
    let m = [[m_r, z, z], [z, m_f, z], [z, z, m_l]];
    (k, m)
}

#[cfg(test)]
mod tests {
    // Matrix test code reads best with explicit indices over 0..N.
    #![allow(clippy::needless_range_loop)]
    use super::*;

    fn matmul<const N: usize>(a: &[[f64; N]; N], b: &[[f64; N]; N]) -> [[f64; N]; N] {
        let mut c = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                for k in 0..N {
                    c[i][j] += a[i][k] * b[k][j];
                }
            }
        }
        c
    }
    fn transpose<const N: usize>(a: &[[f64; N]; N]) -> [[f64; N]; N] {
        let mut t = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                t[j][i] = a[i][j];
            }
        }
        t
    }

    /// Grounded two-mass chain: k1 (ground-m1), k2 (m1-m2).
    fn chain(m1: f64, m2: f64, k1: f64, k2: f64) -> ([[f64; 2]; 2], [[f64; 2]; 2]) {
        ([[k1 + k2, -k2], [-k2, k2]], [[m1, 0.0], [0.0, m2]])
    }

    #[test]
    fn equal_two_mass_chain_has_golden_ratio_modes() {
        // m = k = 1: omega^2 = (3 -+ sqrt5)/2, x2/x1 = phi and -1/phi (phi = golden ratio).
        let (k, m) = chain(1.0, 1.0, 1.0, 1.0);
        let r = modal_analysis(&k, &m).unwrap();
        let s5 = 5f64.sqrt();
        let golden = (1.0 + s5) / 2.0;
        assert!((r.omega[0] - ((3.0 - s5) / 2.0).sqrt()).abs() < 1e-14);
        assert!((r.omega[1] - ((3.0 + s5) / 2.0).sqrt()).abs() < 1e-14);
        assert_eq!(r.modes[0], [1.0, 1.0]);
        assert!((r.modes[1][0] - golden).abs() < 1e-13);
        assert!((r.modes[1][1] + 1.0 / golden).abs() < 1e-13);
        assert_eq!(r.normalized_by, [0, 0]);
    }

    #[test]
    fn unequal_two_mass_chain_matches_the_characteristic_quadratic() {
        // m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0; x2/x1 = k2 / (k2 - w^2 m2).
        let (m1, m2, k1, k2) = (2.0, 0.5, 3.0e4, 1.0e4);
        let (k, m) = chain(m1, m2, k1, k2);
        let b = m1 * k2 + m2 * (k1 + k2);
        let disc = (b * b - 4.0 * m1 * m2 * k1 * k2).sqrt();
        let w2 = [(b - disc) / (2.0 * m1 * m2), (b + disc) / (2.0 * m1 * m2)];
        let r = modal_analysis(&k, &m).unwrap();
        for j in 0..2 {
            assert!((r.omega[j] / w2[j].sqrt() - 1.0).abs() < 1e-13, "mode {j}");
            let ratio = k2 / (k2 - w2[j] * m2);
            assert!((r.modes[1][j] / ratio - 1.0).abs() < 1e-12, "mode {j}");
            // Eq. VI.5 with first-row normalisation: k_j = w_j^2 (m1 + m2 ratio^2).
            let kj = w2[j] * (m1 + m2 * ratio * ratio);
            assert!((r.modal_stiffness[j] / kj - 1.0).abs() < 1e-12, "mode {j}");
        }
    }

    #[test]
    fn eigenvectors_are_m_orthonormal_and_k_orthogonal() {
        let (k, m) = translational_system(0.00013, 0.007764, 3.428e-3, 1.5e6, 1.265e6, 100.0);
        let (lam, phi) = generalized_eigen(&k, &m).unwrap();
        let ptmp = matmul(&transpose(&phi), &matmul(&m, &phi));
        let ptkp = matmul(&transpose(&phi), &matmul(&k, &phi));
        for i in 0..3 {
            for j in 0..3 {
                let want = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (ptmp[i][j] - want).abs() < 1e-12,
                    "PtMP[{i}][{j}] = {}",
                    ptmp[i][j]
                );
                let want = if i == j { lam[i] } else { 0.0 };
                assert!(
                    (ptkp[i][j] - want).abs() < 1e-9 * lam[2],
                    "PtKP[{i}][{j}] = {}",
                    ptkp[i][j]
                );
            }
        }
        assert!(lam[0] < lam[1] && lam[1] < lam[2]);
        // The trace of M^-1 K is the sum of the eigenvalues.
        let tr = k[0][0] / m[0][0] + k[1][1] / m[1][1] + k[2][2] / m[2][2];
        assert!(((lam[0] + lam[1] + lam[2]) / tr - 1.0).abs() < 1e-12);
        // Product = det K / det M.
        let det_k =
            k[0][0] * (k[1][1] * k[2][2] - k[1][2] * k[2][1]) - k[0][1] * (k[1][0] * k[2][2]);
        let det_m = m[0][0] * m[1][1] * m[2][2];
        assert!((lam[0] * lam[1] * lam[2] / (det_k / det_m) - 1.0).abs() < 1e-8);
    }

    #[test]
    fn rotational_system_has_a_rigid_mode_at_zero() {
        let (k, m) = rotational_system(0.0291, 0.25, 0.0102, 2e5, 2e5);
        let r = modal_analysis(&k, &m).unwrap();
        assert_eq!(r.omega[0], 0.0);
        assert_eq!(r.modal_stiffness[0], 0.0);
        for i in 0..3 {
            assert!(
                (r.modes[i][0] - 1.0).abs() < 1e-9,
                "rigid mode is a uniform rotation"
            );
        }
        // Modal mass of the rigid mode: total inertia.
        assert!((r.modal_mass[0] - (0.0291 + 0.25 + 0.0102)).abs() < 1e-9);
        assert!(r.omega[1] > 0.0);
    }

    #[test]
    fn non_first_row_normalisation_when_the_first_entry_vanishes() {
        // Decoupled system: the second mode moves only the second coordinate, so its first
        // entry is 0 and it is normalised by its largest entry (row 1).
        let k = [[1.0, 0.0], [0.0, 4.0]];
        let m = [[1.0, 0.0], [0.0, 1.0]];
        let r = modal_analysis(&k, &m).unwrap();
        assert_eq!(r.omega, [1.0, 2.0]);
        assert_eq!(r.normalized_by, [0, 1]);
        assert_eq!(r.modes[1][1], 1.0);
        assert_eq!(r.modes[0][1], 0.0);
    }

    #[test]
    fn bad_input_is_typed() {
        let m = [[1.0, 0.0], [0.0, 1.0]];
        let asym = [[2.0, -1.0], [-1.1, 1.0]];
        assert!(matches!(
            generalized_eigen(&asym, &m),
            Err(Error::InvalidParameter { field: "k", .. })
        ));
        let nan = [[2.0, f64::NAN], [f64::NAN, 1.0]];
        assert!(matches!(
            generalized_eigen(&m, &nan),
            Err(Error::InvalidParameter { field: "m", .. })
        ));
        let k = [[2.0, -1.0], [-1.0, 1.0]];
        let singular = [[1.0, 1.0], [1.0, 1.0]];
        assert!(matches!(
            generalized_eigen(&k, &singular),
            Err(Error::NotPositiveDefinite { .. })
        ));
        let negative = [[1.0, 0.0], [0.0, -1.0]];
        assert!(matches!(
            generalized_eigen(&k, &negative),
            Err(Error::NotPositiveDefinite { .. })
        ));
        let indefinite = [[1.0, 0.0], [0.0, -1.0]];
        assert!(matches!(
            modal_analysis(&indefinite, &m),
            Err(Error::InvalidParameter { field: "k", .. })
        ));
    }

    #[test]
    fn jacobi_reports_no_convergence_when_out_of_sweeps() {
        let mut a = [
            [4.0, 1.0, 0.5, 0.2],
            [1.0, 3.0, 0.7, 0.1],
            [0.5, 0.7, 2.0, 0.3],
            [0.2, 0.1, 0.3, 1.0],
        ];
        let mut v = [[0.0; 4]; 4];
        assert!(matches!(
            jacobi(&mut a, &mut v, 1),
            Err(Error::NoConvergence {
                what: "Jacobi eigensolver",
                iterations: 1
            })
        ));
        let mut a = [
            [4.0, 1.0, 0.5, 0.2],
            [1.0, 3.0, 0.7, 0.1],
            [0.5, 0.7, 2.0, 0.3],
            [0.2, 0.1, 0.3, 1.0],
        ];
        let a0 = a;
        jacobi(&mut a, &mut v, JACOBI_MAX_SWEEPS).unwrap();
        // A V = V diag(a): every column is an eigenvector.
        let av = matmul(&a0, &v);
        for i in 0..4 {
            for j in 0..4 {
                assert!((av[i][j] - v[i][j] * a[j][j]).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn single_and_double_precision_agree() {
        let (k, m) = translational_system(0.00013, 0.007764, 3.428e-3, 1.5e6, 1.265e6, 100.0);
        let (k32, m32) =
            translational_system(0.00013f32, 0.007764, 3.428e-3, 1.5e6, 1.265e6, 100.0);
        let r = modal_analysis(&k, &m).unwrap();
        let r32 = modal_analysis(&k32, &m32).unwrap();
        for j in 0..3 {
            assert!(
                (f64::from(r32.omega[j]) / r.omega[j] - 1.0).abs() < 1e-5,
                "mode {j}"
            );
            assert!(
                (f64::from(r32.modal_stiffness[j]) / r.modal_stiffness[j] - 1.0).abs() < 1e-4,
                "mode {j}"
            );
            for i in 0..3 {
                assert!(
                    (f64::from(r32.modes[i][j]) - r.modes[i][j]).abs()
                        < 1e-5 * r.modes[i][j].abs().max(1.0)
                );
            }
        }
        // The soft 94 rad/s mode (K_rs = 100 lb/in among 1e6 lb/in springs) is not taken
        // for a rigid one in f32 ...
        assert!(
            r32.omega[0] > 93.9 && r32.omega[0] < 94.1,
            "{}",
            r32.omega[0]
        );
        // ... while without the return spring the follower chain is free: a rigid mode.
        let (k32, m32) = translational_system(0.00013f32, 0.007764, 3.428e-3, 1.5e6, 1.265e6, 0.0);
        let free = modal_analysis(&k32, &m32).unwrap();
        assert_eq!(free.omega[0], 0.0);
        assert!(free.omega[1] > 2.0e4);
        // Rotational system in f32: rigid mode at 0, the others as in f64.
        let (k, m) = rotational_system(0.0291, 0.25, 0.0102, 2e5, 2e5);
        let (k32, m32) = rotational_system(0.0291f32, 0.25, 0.0102, 2e5, 2e5);
        let (r, r32) = (
            modal_analysis(&k, &m).unwrap(),
            modal_analysis(&k32, &m32).unwrap(),
        );
        assert_eq!(r32.omega[0], 0.0);
        for j in 1..3 {
            assert!(
                (f64::from(r32.omega[j]) / r.omega[j] - 1.0).abs() < 1e-5,
                "mode {j}"
            );
        }
    }

    #[test]
    fn a_very_soft_mode_is_not_rigid() {
        // Two equal masses joined by a stiff spring, grounded by a spring 1e8 times softer:
        // omega_1^2 = k_soft / (2 m) exactly in the limit (the pair moves as one).
        let (m1, k_stiff, k_soft) = (1.0, 1.0e8, 1.0);
        let k = [[k_stiff + k_soft, -k_stiff], [-k_stiff, k_stiff]];
        let m = [[m1, 0.0], [0.0, m1]];
        let r = modal_analysis(&k, &m).unwrap();
        assert!(
            (r.omega[0] / (k_soft / (2.0 * m1)).sqrt() - 1.0).abs() < 1e-7,
            "{}",
            r.omega[0]
        );
    }

    #[test]
    fn eleven_mass_chain_matches_the_closed_form() {
        // Fixed-fixed chain of n = 11 masses m and springs k, with unequal masses scaled out:
        // M = 2 I, K tridiagonal (2k, -k): omega_j = 2 sqrt(k/m) sin(j pi / (2 (n + 1))).
        const N: usize = 11;
        let (m, k) = (2.0, 3.0e4);
        let mut kk = [[0.0; N]; N];
        let mut mm = [[0.0; N]; N];
        for i in 0..N {
            kk[i][i] = 2.0 * k;
            mm[i][i] = m;
            if i + 1 < N {
                kk[i][i + 1] = -k;
                kk[i + 1][i] = -k;
            }
        }
        let r = modal_analysis(&kk, &mm).unwrap();
        for j in 0..N {
            let want = 2.0
                * (k / m).sqrt()
                * ((j as f64 + 1.0) * core::f64::consts::PI / (2.0 * (N as f64 + 1.0))).sin();
            assert!(
                (r.omega[j] / want - 1.0).abs() < 1e-12,
                "mode {j}: {} vs {want}",
                r.omega[j]
            );
            // Mode shape sin(i (j+1) pi / (n+1)), normalised to its first entry.
            let s1 = ((j as f64 + 1.0) * core::f64::consts::PI / (N as f64 + 1.0)).sin();
            for i in 0..N {
                let si = ((i as f64 + 1.0) * (j as f64 + 1.0) * core::f64::consts::PI
                    / (N as f64 + 1.0))
                    .sin();
                assert!((r.modes[i][j] - si / s1).abs() < 1e-9, "mode {j} row {i}");
            }
        }
    }
}
