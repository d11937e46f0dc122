//! Waviness frequency per revolution, FPR (VI.4.1, Fig. VI.14).
//!
//! The thesis counts "the curve portions between the inflection points" of the
//! follower displacement over one cam revolution, found as the local maxima and minima
//! of the velocity (the first derivative). Here FPR is the number of local extrema of a
//! sampled signal over one revolution, normally the follower velocity or its deviation
//! from the theoretical velocity; any sampled periodic signal works.
//!
//! # Counting rule
//!
//! With a threshold `δ ≥ 0` (the noise level), a turning point is counted when the
//! signal, after it, moves more than `δ` back the other way (hysteresis, "zig-zag"):
//!
//! * a maximum is the highest value since the last counted minimum, confirmed once the
//!   signal falls more than `δ` below it; a minimum likewise;
//! * a flat stretch (equal samples) is one extremum if the signal turns around across
//!   it and none if it goes on in the same direction; with `δ = 0`, every strict
//!   change of direction counts;
//! * ripples whose peak-to-valley height is at most `δ` are not counted.
//!
//! A revolution is periodic: the scan starts at the first sample holding the global
//! maximum and goes once around, so the count does not depend on where the samples
//! start and is always even (maxima and minima alternate). A signal whose whole range
//! is at most `δ` has 0. [`count_extrema_open`] counts an open (non-periodic) record,
//! leaving out its two ends.

use crate::{non_negative, Error, Real, Result};

/// Direction of the hysteresis scan.
#[derive(Clone, Copy, PartialEq)]
enum Dir {
    /// Not yet known (open records only).
    Unknown,
    /// Looking for a maximum.
    Rising,
    /// Looking for a minimum.
    Falling,
}

fn non_finite(index: usize) -> Error {
    Error::InvalidParameter {
        field: "waviness samples",
        rule: "must be finite (value: the first offending index)",
        value: index as f64,
    }
}

/// The hysteresis scan over `len` values from `get`: returns the number of
/// confirmed turning points and the final direction.
fn scan<T: Real>(len: usize, delta: T, start: Dir, first: T, get: impl Fn(usize) -> T) -> usize {
    let (mut dir, mut hi, mut lo, mut count) = (start, first, first, 0usize);
    for k in 0..len {
        let v = get(k);
        match dir {
            Dir::Unknown => {
                hi = hi.max(v);
                lo = lo.min(v);
                if v - lo > delta {
                    dir = Dir::Rising;
                    hi = v;
                } else if hi - v > delta {
                    dir = Dir::Falling;
                    lo = v;
                }
            }
            Dir::Rising => {
                if v > hi {
                    hi = v;
                } else if hi - v > delta {
                    count += 1;
                    dir = Dir::Falling;
                    lo = v;
                }
            }
            Dir::Falling => {
                if v < lo {
                    lo = v;
                } else if v - lo > delta {
                    count += 1;
                    dir = Dir::Rising;
                    hi = v;
                }
            }
        }
    }
    count
}

/// FPR of `n` samples over one revolution given by `sample(k)`, `k < n` (evaluated
/// twice each, nothing stored): the number of local extrema of the periodic signal
/// under the module's counting rule with threshold `threshold`.
pub fn waviness_fpr_of<T: Real>(
    n: usize,
    threshold: T,
    sample: impl Fn(usize) -> T,
) -> Result<usize> {
    let delta = non_negative("waviness threshold", threshold)?;
    // The first global maximum, the minimum, and finiteness.
    let (mut k_max, mut max, mut min) = (0usize, -T::INFINITY, T::INFINITY);
    for k in 0..n {
        let v = sample(k);
        if !v.is_finite() {
            return Err(non_finite(k));
        }
        if v > max {
            max = v;
            k_max = k;
        }
        min = min.min(v);
    }
    if n < 2 || max - min <= delta {
        return Ok(0);
    }
    // Once around from the maximum back to it: the turning points confirmed on the
    // way, plus the maximum itself.
    let turns = scan(n, delta, Dir::Falling, max, |j| sample((k_max + 1 + j) % n));
    Ok(turns + 1)
}

/// FPR of one revolution of samples (see [`waviness_fpr_of`]).
pub fn waviness_fpr<T: Real>(samples: &[T], threshold: T) -> Result<usize> {
    waviness_fpr_of(samples.len(), threshold, |k| {
        samples.get(k).copied().unwrap_or(T::ZERO)
    })
}

/// Local extrema strictly inside an open (non-periodic) record, by the same rule:
/// the ends are not extrema; the first direction is taken once the signal has moved
/// more than `threshold` from its running range.
pub fn count_extrema_open<T: Real>(samples: &[T], threshold: T) -> Result<usize> {
    let delta = non_negative("waviness threshold", threshold)?;
    if let Some(k) = samples.iter().position(|v| !v.is_finite()) {
        return Err(non_finite(k));
    }
    let Some(&first) = samples.first() else {
        return Ok(0);
    };
    Ok(scan(samples.len(), delta, Dir::Unknown, first, |k| {
        samples.get(k).copied().unwrap_or(T::ZERO)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CamProgram;
    use core::f64::consts::PI;

    fn sampled<const N: usize>(f: impl Fn(f64) -> f64) -> [f64; N] {
        core::array::from_fn(|k| f(2.0 * PI * k as f64 / N as f64))
    }

    #[test]
    fn harmonic_plus_third_harmonic_closed_form() {
        // v = sin θ + c sin 3θ: v' = cos θ + 3c cos 3θ = cos θ (1 − 9c + 12c cos²θ), zero
        // at cos θ = 0 (2 points) and, for c > 1/9, at cos²θ = (9c − 1)/(12c) < 1 (4
        // more). So FPR = 2 for 0 ≤ c < 1/9 and 6 for c > 1/9. At c = 0.2 the extra
        // extrema are v(π/2) = 1 − c = 0.8 and v at sin²θ = 2/3, sin 3θ = sin θ/3:
        // √(2/3)(1 + c/3) = 0.870930: a ripple 0.070930 high.
        for c in [0.0, 0.05, 0.1] {
            let v = sampled::<3600>(|t| t.sin() + c * (3.0 * t).sin());
            assert_eq!(waviness_fpr(&v, 0.0).unwrap(), 2, "c = {c}");
        }
        let v = sampled::<3600>(|t| t.sin() + 0.2 * (3.0 * t).sin());
        let ripple = (2.0f64 / 3.0).sqrt() * (1.0 + 0.2 / 3.0) - 0.8;
        assert!((ripple - 0.070_930).abs() < 1e-6);
        assert_eq!(waviness_fpr(&v, 0.0).unwrap(), 6);
        assert_eq!(waviness_fpr(&v, 0.9 * ripple).unwrap(), 6);
        assert_eq!(waviness_fpr(&v, 1.1 * ripple).unwrap(), 2);
        // Any starting sample gives the same count.
        for shift in [1, 900, 1777, 3599] {
            let w: [f64; 3600] = core::array::from_fn(|k| v[(k + shift) % 3600]);
            assert_eq!(waviness_fpr(&w, 0.0).unwrap(), 6, "shift {shift}");
        }
    }

    #[test]
    fn cam_velocity_plus_waviness() {
        // The reference program's velocity dy/dθ has one maximum (rise) and one
        // minimum (return): FPR 2; the dwells are flat at 0 between a fall and a
        // further fall (or a rise and a further rise), so they add nothing.
        let p = CamProgram::<f64>::reference();
        let n = 7200;
        let v = |k: usize| p.follower(2.0 * PI * k as f64 / n as f64).dy;
        assert_eq!(waviness_fpr_of(n, 1e-12, v).unwrap(), 2);
        // Waviness a sin(kθ) on the lift adds a k cos(kθ) to the velocity; its
        // deviation from the theoretical velocity has exactly 2k extrema.
        let (a, k) = (1e-4, 36.0);
        let dev = |j: usize| a * k * (k * 2.0 * PI * j as f64 / n as f64).cos();
        assert_eq!(waviness_fpr_of(n, 0.0, dev).unwrap(), 72);
        // On the full velocity v = y' + a k cos kθ, v' = y'' − a k² sin kθ. If
        // a k² > max|y''| =: A, v' has opposite signs at the 2k peaks of sin kθ; away
        // from them (|sin kθ| ≤ A/(a k²)), |cos kθ| ≥ √(1 − (A/ak²)²) =: c, and if
        // a k³ c > max|y'''| then v'' keeps one sign there: exactly one zero of v' between
        // neighbouring peaks, 2k extrema in all (the law's own two merge into them).
        let (a, k) = (2e-3, 36.0);
        let (mut amax, mut jmax) = (0.0f64, 0.0f64);
        for j in 0..n {
            let f = p.follower(2.0 * PI * j as f64 / n as f64);
            amax = amax.max(f.d2y.abs());
            jmax = jmax.max(f.d3y.abs());
        }
        assert!(a * k * k > amax, "{amax}");
        assert!(a * k * k * k * (1.0 - (amax / (a * k * k)).powi(2)).sqrt() > jmax);
        let total = |j: usize| {
            let t = 2.0 * PI * j as f64 / n as f64;
            p.follower(t).dy + a * k * (k * t).cos()
        };
        assert_eq!(waviness_fpr_of(n, 0.0, total).unwrap(), 72);
        // Below that amplitude the law's curvature swallows waviness extrema where it
        // is steepest.
        let a = 0.5 * amax / (k * k);
        let weak = |j: usize| {
            let t = 2.0 * PI * j as f64 / n as f64;
            p.follower(t).dy + a * k * (k * t).cos()
        };
        assert!(waviness_fpr_of(n, 0.0, weak).unwrap() < 72);
    }

    #[test]
    fn flat_stretches_and_noise() {
        // A plateau at the top and one at the bottom: one maximum, one minimum.
        assert_eq!(
            waviness_fpr(&[0.0, 1.0, 1.0, 1.0, 0.0, -1.0, -1.0, 0.0], 0.0).unwrap(),
            2
        );
        // A plateau on the way up is no extremum.
        assert_eq!(
            waviness_fpr(&[0.0, 1.0, 1.0, 2.0, 3.0, 2.0, 1.0, 0.5], 0.0).unwrap(),
            2
        );
        // Constant, empty, single sample: no extrema.
        assert_eq!(waviness_fpr(&[2.0; 10], 0.0).unwrap(), 0);
        assert_eq!(waviness_fpr::<f64>(&[], 0.0).unwrap(), 0);
        assert_eq!(waviness_fpr(&[1.0], 0.0).unwrap(), 0);
        // Two samples around a revolution: a maximum and a minimum.
        assert_eq!(waviness_fpr(&[0.0, 1.0], 0.0).unwrap(), 2);
        // Alternating noise of height 0.01 on a sinusoid: counted at δ = 0, not at
        // δ = 0.05 (the noise swings by at most 0.02 peak to valley).
        let v = sampled::<1000>(|t| t.sin());
        let noisy: [f64; 1000] =
            core::array::from_fn(|k| v[k] + if k % 2 == 0 { 0.01 } else { -0.01 });
        assert!(waviness_fpr(&noisy, 0.0).unwrap() > 100);
        assert_eq!(waviness_fpr(&noisy, 0.05).unwrap(), 2);
        // Bad input is an error, not a panic.
        assert!(waviness_fpr(&[0.0, f64::NAN, 1.0], 0.0).is_err());
        assert!(waviness_fpr(&[0.0, 1.0], -1.0).is_err());
        assert!(waviness_fpr(&[0.0, 1.0], f64::NAN).is_err());
        // f32 works the same.
        let v32 = sampled::<720>(|t| t.sin() + 0.2 * (3.0 * t).sin()).map(|x| x as f32);
        assert_eq!(waviness_fpr(&v32, 0.0f32).unwrap(), 6);
    }

    #[test]
    fn open_records_leave_out_their_ends() {
        // sin over (0, 2π): one maximum, one minimum inside.
        let v = sampled::<1000>(|t| t.sin());
        assert_eq!(count_extrema_open(&v, 0.0).unwrap(), 2);
        // A monotone ramp, with a flat step: none.
        assert_eq!(count_extrema_open(&[0.0, 1.0, 1.0, 2.0], 0.0).unwrap(), 0);
        // Falls first, then rises: one minimum.
        assert_eq!(
            count_extrema_open(&[3.0, 2.0, 1.0, 2.0, 3.0], 0.0).unwrap(),
            1
        );
        // The first dip below the threshold is not a minimum.
        assert_eq!(
            count_extrema_open(&[1.0, 0.95, 2.0, 3.0, 1.0], 0.1).unwrap(),
            1
        );
        assert_eq!(count_extrema_open::<f64>(&[], 0.0).unwrap(), 0);
        assert!(count_extrema_open(&[0.0, f64::INFINITY], 0.0).is_err());
    }
}
