//! The return spring: series stiffness and preload (Eqs. V.17-V.18) and the share of
//! the spring's own mass that joins the follower (Appendix F.1).

use crate::{Real, Result};

/// Stiffness of springs in series, `1 / sum(1/k_i)` (lb/in); with K_rb, K_h and K_vs
/// it is the total equivalent stiffness K_t of Eq. V.17.
///
/// An infinite element is rigid (adds no compliance); any zero element gives 0; an
/// empty slice gives `+inf` (nothing to deflect). A negative or NaN element is not a
/// stiffness and gives NaN.
pub fn series_stiffness<T: Real>(k: &[T]) -> T {
    let mut compliance = T::ZERO;
    for &ki in k {
        if ki > T::ZERO {
            compliance += T::ONE / ki;
        } else if ki == T::ZERO {
            return T::ZERO;
        } else {
            return T::from_f64(f64::NAN);
        }
    }
    if compliance > T::ZERO {
        T::ONE / compliance
    } else {
        T::INFINITY
    }
}

/// Return-spring preload and the deflection of the series K_rb, K_h, K_vs (Eq. V.18).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Preload<T> {
    /// Preload F_p (lb).
    pub force: T,
    /// Compression Delta of the series K_rb, K_h, K_vs after installing the spring (in).
    pub compression: T,
}

/// Return-spring preload, Eq. V.18: `Delta = K_rs delta_rs / (K_t + K_rs)`,
/// `F_p = K_t Delta = K_rs (delta_rs - Delta)`.
///
/// `k_t` is the series stiffness of K_rb, K_h, K_vs ([`series_stiffness`]), `k_rs` the
/// return-spring rate, `delta_rs` its assembly compression.
/// Errors: `k_t` not positive and finite; `k_rs` or `delta_rs` negative or not finite.
pub fn return_spring_preload<T: Real>(k_t: T, k_rs: T, delta_rs: T) -> Result<Preload<T>> {
    crate::positive("k_t", k_t)?;
    crate::non_negative("k_rs", k_rs)?;
    crate::non_negative("delta_rs", delta_rs)?;
    // k_t > 0, so the denominator is positive.
    let compression = k_rs * delta_rs / (k_t + k_rs);
    Ok(Preload {
        force: k_t * compression,
        compression,
    })
}

/// Share of a coil spring's mass that moves with its free end: one third of it
/// (Appendix F.1; lb s^2/in).
#[inline]
pub fn spring_effective_mass<T: Real>(spring_mass: T) -> T {
    spring_mass / T::from_f64(3.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Error, HertzContact};

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    #[test]
    fn series_matches_the_printed_three_spring_formula() {
        let (krb, kh, kvs) = (1.5e6, 6.45e6, 1.48e6);
        let printed = krb * kh * kvs / (kh * kvs + krb * kvs + krb * kh);
        assert!(rel(series_stiffness(&[krb, kh, kvs]), printed) < 1e-14);
        assert_eq!(series_stiffness(&[4.0, 4.0]), 2.0);
        assert_eq!(series_stiffness(&[8.0f32]), 8.0);
        assert_eq!(series_stiffness(&[3.0, f64::INFINITY]), 3.0);
        assert_eq!(series_stiffness(&[3.0, 0.0]), 0.0);
        assert_eq!(series_stiffness::<f64>(&[]), f64::INFINITY);
        assert!(series_stiffness(&[3.0, -1.0]).is_nan());
        assert!(series_stiffness(&[f64::NAN, 1.0]).is_nan());
    }

    #[test]
    fn preload_limits() {
        // K_t >> K_rs: all of delta_rs stays in the return spring, F_p -> K_rs delta_rs.
        let p = return_spring_preload(1.0e9, 60.0, 0.5).unwrap();
        assert!(rel(p.force, 30.0) < 1e-7);
        assert!(rel(p.compression, 30.0 / 1.0e9) < 1e-6);
        // Equal stiffnesses: the compression splits in half.
        let p = return_spring_preload(100.0, 100.0, 0.5).unwrap();
        assert_eq!(p.compression, 0.25);
        assert_eq!(p.force, 25.0);
        // Both expressions of V.17 agree.
        let p = return_spring_preload(667_853.75, 60.0, 0.5).unwrap();
        assert!(rel(p.force, 60.0 * (0.5 - p.compression)) < 1e-12);
        // No return spring, no preload.
        assert_eq!(return_spring_preload(1.0e6, 0.0, 0.5).unwrap().force, 0.0);
    }

    /// VI.1 data: K_rb = 1.5e6, K_vs = 1.48e6, K_h at unit force on the base circle,
    /// K_rs = 60, delta_rs = 0.5. 40-digit reference: K_t = 667853.7487,
    /// F_p = 29.99730504 lb, Delta = 4.4915979e-5 in.
    #[test]
    fn reference_preload() {
        let kh = HertzContact::steel(0.25).stiffness(0.375, 1.5).unwrap();
        let kt = series_stiffness(&[1.5e6, kh, 1.48e6]);
        assert!(rel(kt, 667_853.748_680_766) < 1e-12, "{kt}");
        let p = return_spring_preload(kt, 60.0, 0.5).unwrap();
        assert!(rel(p.force, 29.997_305_041_251_875) < 1e-13, "{p:?}");
        assert!(
            rel(p.compression, 4.491_597_913_541_185e-5) < 1e-12,
            "{p:?}"
        );
    }

    #[test]
    fn preload_errors_name_the_field() {
        let field = |r: Result<Preload<f64>>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            other => panic!("expected an error, got {other:?}"),
        };
        assert_eq!(field(return_spring_preload(0.0, 60.0, 0.5)), "k_t");
        assert_eq!(
            field(return_spring_preload(f64::INFINITY, 60.0, 0.5)),
            "k_t"
        );
        assert_eq!(field(return_spring_preload(1.0e6, -60.0, 0.5)), "k_rs");
        assert_eq!(
            field(return_spring_preload(1.0e6, 60.0, f64::NAN)),
            "delta_rs"
        );
    }

    #[test]
    fn effective_mass_is_a_third() {
        assert!(rel(spring_effective_mass(0.0003), 0.0001) < 1e-15);
        assert_eq!(spring_effective_mass(3.0f32), 1.0);
    }
}
