//! Appendix A: the twelve standard follower motion laws in closed form.
//!
//! Every law is normalized to a unit rise over a unit angle: `u = θ/β` in `[0, 1]`,
//! `s(0) = 0`, `s(1) = 1`, and [`LawValue`] holds `s` and its first three derivatives
//! with respect to `u`. A rise of `h` over `β` radians is `y = h s(θ/β)`,
//! `dy/dθ = h v/β`, `d²y/dθ² = h a/β²`, `d³y/dθ³ = h j/β³`.
//!
//! The thesis prints only the first half of the symmetric piecewise laws (and some of
//! their coefficients are OCR-damaged); here every piecewise law is built from its
//! acceleration profile and completed by point symmetry `s(1-u) = 1 - s(u)`:
//!
//! * trapezoidal: linear ramps over `[0, 1/8]`, `[3/8, 5/8]`, `[7/8, 1]`, flats between;
//!   `s(1/2) = 1/2` gives the peak `A = 16/3` (the printed `-10θ/3β` of the second
//!   interval is `-θ/3β`);
//! * modified trapezoidal: the ramps are quarter/half sine waves of period `1/2`;
//!   `s(1/2) = 1/2` gives `A = 8π/(π+2) = 4.888124`, jerk peak `4πA = 61.425977`;
//! * modified sine: quarter sine of period `1/2` on `[0, 1/8]`, then a sine of period
//!   `3/2` on `[1/8, 7/8]`, peak `A = 4π²/(π+4)`.

use crate::Real;

/// One of the standard follower motion laws of Appendix A (A.1-A.4).
///
/// With the `serde` feature a law is (de)serialized by its [`MotionLaw::name`] (the
/// variant index in non-self-describing formats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MotionLaw {
    /// A.1-1 straight line (constant velocity): `s = u`. The acceleration and jerk
    /// impulses at the ends are not representable; `a = j = 0` is reported.
    #[cfg_attr(feature = "serde", serde(rename = "straight-line"))]
    StraightLine,
    /// A.1-2 parabolic (constant acceleration ±4, jump at `u = 1/2`).
    #[cfg_attr(feature = "serde", serde(rename = "parabolic"))]
    Parabolic,
    /// A.1-3 cubic No. 1 (constant jerk 24, acceleration jump ±12 at `u = 1/2`).
    #[cfg_attr(feature = "serde", serde(rename = "cubic-1"))]
    Cubic1,
    /// A.1-4 cubic No. 2 (the 2-3 polynomial, `s = 3u² - 2u³`).
    #[cfg_attr(feature = "serde", serde(rename = "cubic-2"))]
    Cubic2,
    /// A.2-1 simple harmonic motion (crank curve).
    #[cfg_attr(feature = "serde", serde(rename = "shm"))]
    SimpleHarmonic,
    /// A.2-2 double harmonic (not symmetric: it decelerates harder than it starts).
    #[cfg_attr(feature = "serde", serde(rename = "double-harmonic"))]
    DoubleHarmonic,
    /// A.2-3 cycloidal (sine acceleration).
    #[cfg_attr(feature = "serde", serde(rename = "cycloidal"))]
    Cycloidal,
    /// A.3-1 trapezoidal acceleration.
    #[cfg_attr(feature = "serde", serde(rename = "trapezoidal"))]
    Trapezoidal,
    /// A.3-2 modified trapezoidal acceleration.
    #[cfg_attr(feature = "serde", serde(rename = "modified-trapezoidal"))]
    ModifiedTrapezoidal,
    /// A.2-4 modified sine.
    #[cfg_attr(feature = "serde", serde(rename = "modified-sine"))]
    ModifiedSine,
    /// A.4-2 3-4-5 polynomial.
    #[cfg_attr(feature = "serde", serde(rename = "3-4-5"))]
    Poly345,
    /// A.4-3 4-5-6-7 polynomial.
    #[cfg_attr(feature = "serde", serde(rename = "4-5-6-7"))]
    Poly4567,
}

/// A normalized motion law at one point: `s(u)` and its derivatives with respect to `u`
/// (Appendix A with `h = 1`, `β = 1`, `ω = 1`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LawValue<T> {
    /// Displacement, 0 at `u = 0` and 1 at `u = 1`.
    pub s: T,
    /// Velocity coefficient `ds/du`.
    pub v: T,
    /// Acceleration coefficient `d²s/du²`.
    pub a: T,
    /// Jerk coefficient `d³s/du³`.
    pub j: T,
}

/// The exact ratio `n/d` in `T` (folds to a literal for a concrete `T`).
#[inline(always)]
fn q<T: Real>(n: i32, d: i32) -> T {
    T::from_i32(n) / T::from_i32(d)
}

impl MotionLaw {
    /// Every law, in the order of Appendix A's figures as listed by `camsim laws`.
    pub const ALL: [MotionLaw; 12] = [
        MotionLaw::StraightLine,
        MotionLaw::Parabolic,
        MotionLaw::Cubic1,
        MotionLaw::Cubic2,
        MotionLaw::SimpleHarmonic,
        MotionLaw::DoubleHarmonic,
        MotionLaw::Cycloidal,
        MotionLaw::Trapezoidal,
        MotionLaw::ModifiedTrapezoidal,
        MotionLaw::ModifiedSine,
        MotionLaw::Poly345,
        MotionLaw::Poly4567,
    ];

    /// The law's name as used in scene files and by `camsim laws`.
    pub fn name(self) -> &'static str {
        match self {
            MotionLaw::StraightLine => "straight-line",
            MotionLaw::Parabolic => "parabolic",
            MotionLaw::Cubic1 => "cubic-1",
            MotionLaw::Cubic2 => "cubic-2",
            MotionLaw::SimpleHarmonic => "shm",
            MotionLaw::DoubleHarmonic => "double-harmonic",
            MotionLaw::Cycloidal => "cycloidal",
            MotionLaw::Trapezoidal => "trapezoidal",
            MotionLaw::ModifiedTrapezoidal => "modified-trapezoidal",
            MotionLaw::ModifiedSine => "modified-sine",
            MotionLaw::Poly345 => "3-4-5",
            MotionLaw::Poly4567 => "4-5-6-7",
        }
    }

    /// The law named `s` (exactly as [`MotionLaw::name`] spells it, ASCII case ignored).
    pub fn from_name(s: &str) -> Option<MotionLaw> {
        Self::ALL
            .iter()
            .copied()
            .find(|l| l.name().eq_ignore_ascii_case(s))
    }

    /// True if the law is point-symmetric about its midpoint: `s(1-u) = 1 - s(u)`
    /// (all but the double harmonic).
    pub fn is_symmetric(self) -> bool {
        !matches!(self, MotionLaw::DoubleHarmonic)
    }

    /// The law at `u` (clamped to `[0, 1]`; NaN reads as 0): Appendix A, normalized.
    ///
    /// At an acceleration jump (parabolic, cubic No. 1 at `u = 1/2`) the value of the
    /// second half is returned.
    #[inline]
    pub fn eval<T: Real>(self, u: T) -> LawValue<T> {
        let u = u.clamp(T::ZERO, T::ONE);
        let pi = T::PI;
        match self {
            MotionLaw::StraightLine => LawValue {
                s: u,
                v: T::ONE,
                a: T::ZERO,
                j: T::ZERO,
            },
            // The trigonometric laws use half angles (1 - cos x = 2 sin²(x/2)) so that
            // s and v keep their relative accuracy near u = 0 in single precision.
            MotionLaw::SimpleHarmonic => {
                let (sh, ch) = (T::HALF * pi * u).sin_cos();
                let (sn, cs) = (T::TWO * sh * ch, ch * ch - sh * sh);
                let half = T::HALF;
                LawValue {
                    s: sh * sh,
                    v: half * pi * sn,
                    a: half * pi * pi * cs,
                    j: -half * pi * pi * pi * sn,
                }
            }
            MotionLaw::DoubleHarmonic => {
                let (sh, ch) = (T::HALF * pi * u).sin_cos();
                let (s1, c1) = (T::TWO * sh * ch, ch * ch - sh * sh);
                let (s2, c2) = (T::TWO * s1 * c1, c1 * c1 - s1 * s1);
                let half = T::HALF;
                LawValue {
                    // (1/2)[(1 - cos πu) - (1/4)(1 - cos 2πu)]
                    s: sh * sh - q::<T>(1, 4) * s1 * s1,
                    v: half * pi * (s1 - half * s2),
                    a: half * pi * pi * (c1 - c2),
                    j: half * pi * pi * pi * (T::TWO * s2 - s1),
                }
            }
            MotionLaw::Cycloidal => {
                let two_pi = T::TWO * pi;
                let (sh, ch) = (pi * u).sin_cos();
                let (sn, cs) = (T::TWO * sh * ch, ch * ch - sh * sh);
                LawValue {
                    s: u - sn / two_pi,
                    v: T::TWO * sh * sh,
                    a: two_pi * sn,
                    j: two_pi * two_pi * cs,
                }
            }
            // Point-symmetric laws: the first half, mirrored (this also keeps s(u) near
            // u = 1 free of the polynomials' cancellation in single precision).
            MotionLaw::Parabolic
            | MotionLaw::Cubic1
            | MotionLaw::Cubic2
            | MotionLaw::Poly345
            | MotionLaw::Poly4567
            | MotionLaw::Trapezoidal
            | MotionLaw::ModifiedTrapezoidal
            | MotionLaw::ModifiedSine => {
                if u < T::HALF {
                    self.first_half(u)
                } else {
                    // Point symmetry: s(u) = 1 - s(1-u), v even, a odd, j even.
                    let m = self.first_half(T::ONE - u);
                    LawValue {
                        s: T::ONE - m.s,
                        v: m.v,
                        a: -m.a,
                        j: m.j,
                    }
                }
            }
        }
    }

    /// First half (`u` in `[0, 1/2]`) of the point-symmetric laws evaluated by mirroring.
    #[inline]
    fn first_half<T: Real>(self, u: T) -> LawValue<T> {
        let pi = T::PI;
        match self {
            MotionLaw::Cubic2 => LawValue {
                s: u * u * (T::from_i32(3) - T::TWO * u),
                v: T::from_i32(6) * u * (T::ONE - u),
                a: T::from_i32(6) * (T::ONE - T::TWO * u),
                j: T::from_i32(-12),
            },
            MotionLaw::Poly345 => {
                let w = T::ONE - u;
                LawValue {
                    s: u * u * u * (T::from_i32(10) - T::from_i32(15) * u + T::from_i32(6) * u * u),
                    v: T::from_i32(30) * (u * w).sq(),
                    a: T::from_i32(60) * u * w * (w - u),
                    j: T::from_i32(60) * (T::ONE - T::from_i32(6) * u * w),
                }
            }
            MotionLaw::Poly4567 => {
                let w = T::ONE - u;
                let p = u * w;
                let u2 = u * u;
                LawValue {
                    s: u2
                        * u2
                        * (T::from_i32(35) - T::from_i32(84) * u + T::from_i32(70) * u2
                            - T::from_i32(20) * u2 * u),
                    v: T::from_i32(140) * p * p * p,
                    a: T::from_i32(420) * p * p * (w - u),
                    j: T::from_i32(840) * p * (T::ONE - T::from_i32(5) * p),
                }
            }
            MotionLaw::Parabolic => LawValue {
                s: T::TWO * u * u,
                v: T::from_i32(4) * u,
                a: T::from_i32(4),
                j: T::ZERO,
            },
            MotionLaw::Cubic1 => LawValue {
                s: T::from_i32(4) * u * u * u,
                v: T::from_i32(12) * u * u,
                a: T::from_i32(24) * u,
                j: T::from_i32(24),
            },
            MotionLaw::Trapezoidal => trapezoidal_first_half(u),
            MotionLaw::ModifiedTrapezoidal => modified_trapezoidal_first_half(u),
            MotionLaw::ModifiedSine => {
                let d = pi + T::from_i32(4);
                let k = T::from_i32(4) * pi;
                if u < q::<T>(1, 8) {
                    let (sn, cs) = (k * u).sin_cos();
                    LawValue {
                        s: (k * u - sn) / (T::from_i32(4) * d),
                        v: pi * (T::ONE - cs) / d,
                        a: T::from_i32(4) * pi * pi * sn / d,
                        j: T::from_i32(16) * pi * pi * pi * cs / d,
                    }
                } else {
                    let (sn, cs) = (k * u / T::from_i32(3) - pi / T::from_i32(6)).sin_cos();
                    LawValue {
                        s: (k * u - T::from_i32(9) * cs + T::from_i32(8)) / (T::from_i32(4) * d),
                        v: pi * (T::ONE + T::from_i32(3) * sn) / d,
                        a: T::from_i32(4) * pi * pi * cs / d,
                        j: -T::from_i32(16) * pi * pi * pi * sn / (T::from_i32(3) * d),
                    }
                }
            }
            // Evaluated directly by `eval`, never reached from there; well-defined anyway.
            _ => self.eval(u),
        }
    }
}

/// The trapezoidal law's first half (`u` in `[0, 1/2]`): the acceleration ramps up
/// linearly over the first eighth, holds, and ramps down to 0 at `u = 1/2`.
#[inline]
fn trapezoidal_first_half<T: Real>(u: T) -> LawValue<T> {
    // Peak acceleration from s(1/2) = 3A/32 = 1/2.
    let a_pk = q::<T>(16, 3);
    let eighth = q::<T>(1, 8);
    let three_eighths = q::<T>(3, 8);
    if u < eighth {
        // Linear ramp a = 8A u.
        let k = T::from_i32(8) * a_pk;
        LawValue {
            s: k * u * u * u / T::from_i32(6),
            v: k * u * u * T::HALF,
            a: k * u,
            j: k,
        }
    } else if u < three_eighths {
        // Constant a = A from s = A/384, v = A/16 at u = 1/8.
        let w = u - eighth;
        LawValue {
            s: a_pk * (q::<T>(1, 384) + w / T::from_i32(16) + T::HALF * w * w),
            v: a_pk * (q::<T>(1, 16) + w),
            a: a_pk,
            j: T::ZERO,
        }
    } else {
        // Ramp down a = A (1 - 8w) from s = 19A/384, v = 5A/16 at u = 3/8.
        let w = u - three_eighths;
        let k = T::from_i32(8) * a_pk;
        LawValue {
            s: a_pk * q::<T>(19, 384) + a_pk * q::<T>(5, 16) * w + a_pk * T::HALF * w * w
                - k * w * w * w / T::from_i32(6),
            v: a_pk * q::<T>(5, 16) + a_pk * w - k * T::HALF * w * w,
            a: a_pk - k * w,
            j: -k,
        }
    }
}

/// The modified trapezoidal law's first half (`u` in `[0, 1/2]`): a quarter sine wave
/// of acceleration over the first eighth, the constant peak, and a quarter cosine wave
/// down to 0 at `u = 1/2`.
#[inline]
fn modified_trapezoidal_first_half<T: Real>(u: T) -> LawValue<T> {
    let pi = T::PI;
    // a = A sin(4πu) on [0,1/8], A on [1/8,3/8], A cos(4π(u-3/8)) on [3/8,1/2];
    // s(1/2) = A (π+2)/(16π) = 1/2 gives A = 8π/(π+2).
    let k = T::from_i32(4) * pi;
    let a_pk = T::from_i32(8) * pi / (pi + T::TWO);
    let eighth = q::<T>(1, 8);
    let three_eighths = q::<T>(3, 8);
    let c = a_pk / k;
    // s and v at u = 1/8.
    let s1 = c * (eighth - T::ONE / k);
    if u < eighth {
        let (sn, cs) = (k * u).sin_cos();
        LawValue {
            s: c * (u - sn / k),
            v: c * (T::ONE - cs),
            a: a_pk * sn,
            j: a_pk * k * cs,
        }
    } else if u < three_eighths {
        let w = u - eighth;
        LawValue {
            s: s1 + c * w + T::HALF * a_pk * w * w,
            v: c + a_pk * w,
            a: a_pk,
            j: T::ZERO,
        }
    } else {
        let w = u - three_eighths;
        let quarter = q::<T>(1, 4);
        let v2 = c + a_pk * quarter;
        let s2 = s1 + c * quarter + a_pk * q::<T>(1, 32);
        let (sn, cs) = (k * w).sin_cos();
        LawValue {
            s: s2 + v2 * w + c / k * (T::ONE - cs),
            v: v2 + c * sn,
            a: a_pk * cs,
            j: -a_pk * k * sn,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    /// Internal junctions of each law (where the closed form switches pieces).
    fn junctions(law: MotionLaw) -> &'static [f64] {
        match law {
            MotionLaw::Parabolic | MotionLaw::Cubic1 => &[0.5],
            MotionLaw::Trapezoidal | MotionLaw::ModifiedTrapezoidal => {
                &[0.125, 0.375, 0.5, 0.625, 0.875]
            }
            MotionLaw::ModifiedSine => &[0.125, 0.5, 0.875],
            _ => &[0.5],
        }
    }

    /// Highest derivative (1 = v, 2 = a, 3 = j) the law keeps continuous inside (0,1).
    fn continuous_order(law: MotionLaw) -> u32 {
        match law {
            MotionLaw::Parabolic | MotionLaw::Cubic1 => 1,
            MotionLaw::Trapezoidal => 2,
            _ => 3,
        }
    }

    /// Laws that claim zero acceleration at both ends.
    fn zero_end_acceleration(law: MotionLaw) -> bool {
        matches!(
            law,
            MotionLaw::Cubic1
                | MotionLaw::Cycloidal
                | MotionLaw::Trapezoidal
                | MotionLaw::ModifiedTrapezoidal
                | MotionLaw::ModifiedSine
                | MotionLaw::Poly345
                | MotionLaw::Poly4567
        )
    }

    fn e(law: MotionLaw, u: f64) -> LawValue<f64> {
        law.eval(u)
    }

    #[test]
    fn names_round_trip_and_are_distinct() {
        for (i, l) in MotionLaw::ALL.iter().enumerate() {
            assert_eq!(MotionLaw::from_name(l.name()), Some(*l));
            for m in &MotionLaw::ALL[i + 1..] {
                assert_ne!(l.name(), m.name());
                assert_ne!(l, m);
            }
        }
        assert_eq!(
            MotionLaw::from_name("Modified-Sine"),
            Some(MotionLaw::ModifiedSine)
        );
        assert_eq!(MotionLaw::from_name("sine"), None);
    }

    #[test]
    fn end_values() {
        for law in MotionLaw::ALL {
            let (a, b) = (e(law, 0.0), e(law, 1.0));
            assert!(a.s.abs() < 1e-15, "{law:?} s(0) = {}", a.s);
            assert!((b.s - 1.0).abs() < 1e-14, "{law:?} s(1) = {}", b.s);
            if law != MotionLaw::StraightLine {
                assert!(
                    a.v.abs() < 1e-14 && b.v.abs() < 1e-13,
                    "{law:?} v ends {} {}",
                    a.v,
                    b.v
                );
            }
            if zero_end_acceleration(law) {
                assert!(
                    a.a.abs() < 1e-12 && b.a.abs() < 1e-12,
                    "{law:?} a ends {} {}",
                    a.a,
                    b.a
                );
            }
        }
        // The 4-5-6-7 polynomial also starts and ends without jerk.
        assert_eq!(e(MotionLaw::Poly4567, 0.0).j, 0.0);
        assert_eq!(e(MotionLaw::Poly4567, 1.0).j, 0.0);
        // Clamping outside [0, 1], NaN reads as 0.
        assert_eq!(e(MotionLaw::Cycloidal, -3.0), e(MotionLaw::Cycloidal, 0.0));
        assert_eq!(e(MotionLaw::Cycloidal, 7.0), e(MotionLaw::Cycloidal, 1.0));
        assert_eq!(e(MotionLaw::Poly345, f64::NAN), e(MotionLaw::Poly345, 0.0));
    }

    #[test]
    fn continuity_at_junctions() {
        let d = 1e-9;
        for law in MotionLaw::ALL {
            for &u in junctions(law) {
                let (l, r) = (e(law, u - d), e(law, u + d));
                // Across 2d the value moves by at most |next derivative| * 2d.
                let tol = |next: f64| 2.0 * d * (next.abs() + 1.0) * 1.5 + 1e-12;
                assert!((l.s - r.s).abs() < tol(l.v), "{law:?} s jumps at {u}");
                assert!(
                    (l.v - r.v).abs() < tol(l.a.abs().max(r.a.abs())),
                    "{law:?} v jumps at {u}"
                );
                if continuous_order(law) >= 2 {
                    assert!(
                        (l.a - r.a).abs() < tol(l.j.abs().max(r.j.abs())),
                        "{law:?} a jumps at {u}"
                    );
                }
                if continuous_order(law) >= 3 {
                    assert!(
                        (l.j - r.j).abs() < 1e-5,
                        "{law:?} j jumps at {u}: {} {}",
                        l.j,
                        r.j
                    );
                }
            }
        }
        // The jumps the laws do have are where they should be.
        let p = (
            e(MotionLaw::Parabolic, 0.5 - d),
            e(MotionLaw::Parabolic, 0.5 + d),
        );
        assert!((p.0.a - 4.0).abs() < 1e-12 && (p.1.a + 4.0).abs() < 1e-12);
        let c = (e(MotionLaw::Cubic1, 0.5 - d), e(MotionLaw::Cubic1, 0.5 + d));
        assert!((c.0.a - 12.0).abs() < 1e-6 && (c.1.a + 12.0).abs() < 1e-6);
        let t = (
            e(MotionLaw::Trapezoidal, 0.125 - d),
            e(MotionLaw::Trapezoidal, 0.125 + d),
        );
        assert!((t.0.j - 128.0 / 3.0).abs() < 1e-9 && t.1.j == 0.0);
    }

    #[test]
    fn derivatives_match_central_differences() {
        let h = 1e-5;
        let n = 997;
        for law in MotionLaw::ALL {
            for k in 0..n {
                let u = (k as f64 + 0.5) / n as f64;
                // Skip points whose stencil straddles a junction.
                if junctions(law).iter().any(|&x| (x - u).abs() < 2.0 * h) {
                    continue;
                }
                let (m, p, c) = (e(law, u - h), e(law, u + h), e(law, u));
                let fd = |a: f64, b: f64| (b - a) / (2.0 * h);
                // Truncation error h²/6 |f'''|: scale the tolerance with the law's size.
                let tol = |scale: f64| 1e-6 * (1.0 + scale);
                assert!(
                    (fd(m.s, p.s) - c.v).abs() < tol(c.v.abs()),
                    "{law:?} v at {u}"
                );
                assert!(
                    (fd(m.v, p.v) - c.a).abs() < tol(c.a.abs() + 10.0),
                    "{law:?} a at {u}"
                );
                assert!(
                    (fd(m.a, p.a) - c.j).abs() < tol(c.j.abs() + 100.0),
                    "{law:?} j at {u}"
                );
            }
        }
    }

    #[test]
    fn point_symmetry() {
        for law in MotionLaw::ALL {
            let mut worst: f64 = 0.0;
            for k in 0..=1000 {
                let u = k as f64 / 1000.0;
                worst = worst.max((e(law, 1.0 - u).s - (1.0 - e(law, u).s)).abs());
            }
            if law.is_symmetric() {
                assert!(worst < 1e-13, "{law:?} asymmetric by {worst}");
            } else {
                assert!(worst > 0.1, "{law:?} unexpectedly symmetric");
            }
        }
    }

    /// Extremes of one coefficient over a dense grid plus golden-section refinement
    /// (keeping the best point seen: at a jump the supremum is a one-sided limit).
    fn extreme(law: MotionLaw, f: fn(LawValue<f64>) -> f64, sign: f64) -> f64 {
        let n = 8 * 2048;
        let scan = crate::PeakScan {
            start: 0.0,
            step: 1.0 / n as f64,
            points: n + 1,
            ends: crate::ScanEnds::Clamped,
            iterations: 80,
        };
        let best = scan.maximize(|u| sign * f(e(law, u))).map(|p| p.value);
        sign * best.unwrap_or(f64::NEG_INFINITY)
    }

    fn peaks(law: MotionLaw) -> [f64; 5] {
        [
            extreme(law, |x| x.v, 1.0),
            extreme(law, |x| x.a, 1.0),
            extreme(law, |x| x.a, -1.0),
            extreme(law, |x| x.j, 1.0),
            extreme(law, |x| x.j, -1.0),
        ]
    }

    fn check(law: MotionLaw, want: [f64; 5]) {
        let got = peaks(law);
        for (i, (g, w)) in got.iter().zip(want).enumerate() {
            assert!(
                (g - w).abs() < 1e-8 * (1.0 + w.abs()),
                "{law:?} coefficient {i}: got {g}, want {w}"
            );
        }
    }

    #[test]
    fn peak_coefficients_match_closed_forms() {
        let s3 = 3f64.sqrt();
        let s5 = 5f64.sqrt();
        check(MotionLaw::StraightLine, [1.0, 0.0, 0.0, 0.0, 0.0]);
        check(MotionLaw::Parabolic, [2.0, 4.0, -4.0, 0.0, 0.0]);
        check(MotionLaw::Cubic1, [3.0, 12.0, -12.0, 24.0, 24.0]);
        check(MotionLaw::Cubic2, [1.5, 6.0, -6.0, -12.0, -12.0]);
        check(
            MotionLaw::SimpleHarmonic,
            [
                PI / 2.0,
                PI * PI / 2.0,
                -PI * PI / 2.0,
                0.0,
                -PI.powi(3) / 2.0,
            ],
        );
        // Double harmonic: v' = 0 at cos(πu) = -1/2, a' = 0 at cos(πu) = 1/4, j' = 0 at
        // 8c² - c - 4 = 0 (c = cos πu), where j = (π³/2) sin(πu) (4c - 1).
        let jdh = |c: f64| PI.powi(3) / 2.0 * (1.0 - c * c).sqrt() * (4.0 * c - 1.0);
        let r129 = 129f64.sqrt();
        check(
            MotionLaw::DoubleHarmonic,
            [
                3.0 * s3 * PI / 8.0,
                9.0 * PI * PI / 16.0,
                -PI * PI,
                jdh((1.0 + r129) / 16.0),
                jdh((1.0 - r129) / 16.0),
            ],
        );
        check(
            MotionLaw::Cycloidal,
            [2.0, 2.0 * PI, -2.0 * PI, 4.0 * PI * PI, -4.0 * PI * PI],
        );
        check(
            MotionLaw::Trapezoidal,
            [2.0, 16.0 / 3.0, -16.0 / 3.0, 128.0 / 3.0, -128.0 / 3.0],
        );
        let amt = 8.0 * PI / (PI + 2.0);
        check(
            MotionLaw::ModifiedTrapezoidal,
            [2.0, amt, -amt, 4.0 * PI * amt, -4.0 * PI * amt],
        );
        let ms = PI + 4.0;
        check(
            MotionLaw::ModifiedSine,
            [
                4.0 * PI / ms,
                4.0 * PI * PI / ms,
                -4.0 * PI * PI / ms,
                16.0 * PI.powi(3) / ms,
                -16.0 * PI.powi(3) / (3.0 * ms),
            ],
        );
        // 3-4-5: a' = 0 at u = 1/2 - √3/6 where u(1-u) = 1/6; j = 60(1 - 6u(1-u)).
        check(
            MotionLaw::Poly345,
            [1.875, 10.0 / s3, -10.0 / s3, 60.0, -30.0],
        );
        // 4-5-6-7: a' = 0 at u(1-u) = 1/5; j = 840 p (1 - 5p) with p = u(1-u) in [0, 1/4].
        check(
            MotionLaw::Poly4567,
            [
                140.0 / 64.0,
                84.0 * s5 / 25.0,
                -84.0 * s5 / 25.0,
                42.0,
                -52.5,
            ],
        );
    }

    #[test]
    fn derived_constants_match_the_thesis_print() {
        // Appendix A.3-2 prints these to 7 digits; they follow from A = 8π/(π+2).
        let a = 8.0 * PI / (PI + 2.0);
        assert!((a - 4.888124).abs() < 5e-7);
        assert!((4.0 * PI * a - 61.425977).abs() < 5e-6);
        assert!((a / (16.0 * PI) - 0.0972461).abs() < 5e-8);
        assert!((a / (4.0 * PI) - 0.3889845).abs() < 5e-8);
        // Second interval y = h(2.444 u² - 0.222 u + 0.007234).
        let m = e(MotionLaw::ModifiedTrapezoidal, 0.25);
        let printed = 2.444062 * 0.0625 - 0.2220315 * 0.25 + 0.007234;
        assert!((m.s - printed).abs() < 1e-6, "{} vs {printed}", m.s);
        // Trapezoidal third interval as printed (this one survived the OCR).
        for u in [0.4, 0.45, 0.5] {
            let t = e(MotionLaw::Trapezoidal, u);
            let p = 7.0 / 18.0 - 10.0 / 3.0 * u + 32.0 / 3.0 * u * u - 64.0 / 9.0 * u * u * u;
            assert!((t.s - p).abs() < 1e-14);
        }
        // Modified sine second interval as printed.
        let u: f64 = 0.3;
        let x = 4.0 * PI * u / 3.0 - PI / 6.0;
        let p = (4.0 * PI * u - 9.0 * x.cos() + 8.0) / (4.0 * (PI + 4.0));
        assert!((e(MotionLaw::ModifiedSine, u).s - p).abs() < 1e-15);
    }

    /// f32 against f64 (micromath's approximate f32 functions are not held to this).
    #[cfg(not(feature = "micromath"))]
    #[test]
    fn single_precision_agrees() {
        for law in MotionLaw::ALL {
            for k in 0..=64 {
                let u = k as f64 / 64.0;
                let (d, f) = (law.eval(u), law.eval(u as f32));
                let scale = 1.0 + d.j.abs();
                assert!((d.s - f.s as f64).abs() < 1e-6, "{law:?} s at {u}");
                assert!((d.v - f.v as f64).abs() < 1e-5, "{law:?} v at {u}");
                assert!(
                    (d.a - f.a as f64).abs() < 1e-5 * (1.0 + d.a.abs()),
                    "{law:?} a at {u}"
                );
                assert!((d.j - f.j as f64).abs() < 1e-5 * scale, "{law:?} j at {u}");
            }
        }
    }
}
