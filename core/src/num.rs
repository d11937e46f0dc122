//! The one numeric trait every module is generic over.
//!
//! `f64` always uses libm. `f32` uses libm too, or micromath's fast approximations
//! with the `micromath` feature. Constants enter generic code through
//! [`Real::from_f64`], which is `#[inline(always)]` so that `T::from_f64(0.5)`
//! folds to an `f32` literal on the firmware: no double-precision arithmetic is
//! ever executed for an `f32` instantiation.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// A real scalar (`f32` or `f64`) with the elementary functions camsim needs.
pub trait Real:
    Copy
    + Default
    + Debug
    + Display
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Send
    + Sync
    + 'static
{
    /// 0
    const ZERO: Self;
    /// 1
    const ONE: Self;
    /// 2
    const TWO: Self;
    /// 1/2
    const HALF: Self;
    /// π
    const PI: Self;
    /// Machine epsilon.
    const EPSILON: Self;
    /// Largest finite value.
    const MAX: Self;
    /// Smallest positive normal value.
    const MIN_POSITIVE: Self;
    /// Infinity.
    const INFINITY: Self;
    /// Not a number (marks a value that could not be measured).
    const NAN: Self;
    /// Where `tanh` rounds to exactly 1 in this precision: for `x` above it
    /// `1 - 2/(exp(2x) + 1)` is 1 (the friction's smooth sign skips its `exp` there).
    const TANH_SATURATES: Self;

    /// Converts an `f64` constant (rounds for `f32`).
    fn from_f64(x: f64) -> Self;
    /// Converts a small integer exactly.
    fn from_i32(i: i32) -> Self;
    /// Converts a count (exact below 2^24 for `f32`).
    fn from_usize(n: usize) -> Self;
    /// Widens to `f64` (for reports and errors only, never in hot paths).
    fn to_f64(self) -> f64;
    /// Truncates towards zero to a `usize` (Rust's saturating cast: negative and NaN
    /// give 0, too large gives `usize::MAX`); one instruction on the chip, no `f64`.
    fn to_usize_trunc(self) -> usize;
    /// Converts to another precision through `f64`, `U::from_f64(self.to_f64())`: exact
    /// when widening, rounded to nearest when narrowing to `f32`. How a design changes
    /// precision ([`Design::cast`](crate::Design::cast)); not for hot paths.
    #[inline]
    fn cast<U: Real>(self) -> U {
        U::from_f64(self.to_f64())
    }

    /// Square root.
    fn sqrt(self) -> Self;
    /// Cube root.
    fn cbrt(self) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Sine and cosine together.
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// Tangent.
    fn tan(self) -> Self;
    /// Arc sine.
    fn asin(self) -> Self;
    /// Arc cosine.
    fn acos(self) -> Self;
    /// Arc tangent.
    fn atan(self) -> Self;
    /// Four-quadrant arc tangent of `self / x`.
    fn atan2(self, x: Self) -> Self;
    /// e^self.
    fn exp(self) -> Self;
    /// Natural logarithm.
    fn ln(self) -> Self;
    /// self^n for an integer exponent.
    fn powi(self, n: i32) -> Self;
    /// self^p.
    fn powf(self, p: Self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Largest integer not above self.
    fn floor(self) -> Self;
    /// sqrt(self² + y²) without undue overflow.
    fn hypot(self, y: Self) -> Self;
    /// True unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// True if NaN.
    fn is_nan(self) -> bool;

    /// The larger of two values (NaN-ignoring, like `f64::max`).
    #[inline(always)]
    fn max(self, o: Self) -> Self {
        if self >= o || o.is_nan() {
            self
        } else {
            o
        }
    }
    /// The smaller of two values (NaN-ignoring, like `f64::min`).
    #[inline(always)]
    fn min(self, o: Self) -> Self {
        if self <= o || o.is_nan() {
            self
        } else {
            o
        }
    }
    /// self clamped to `[lo, hi]`.
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
    /// Square.
    #[inline(always)]
    fn sq(self) -> Self {
        self * self
    }
    /// Degrees to radians.
    #[inline(always)]
    fn to_radians(self) -> Self {
        self * (Self::PI / Self::from_f64(180.0))
    }
    /// Radians to degrees.
    #[inline(always)]
    fn to_degrees(self) -> Self {
        self * (Self::from_f64(180.0) / Self::PI)
    }
}

/// Methods of [`Real`] that call one function with `self` (and the other arguments) each:
/// `name(args) => path;` becomes `#[inline(always)] fn name(self, args) -> Self { path(self, args) }`.
macro_rules! delegate_math {
    ($($name:ident($($arg:ident),*) => $f:path;)*) => {
        $(
            #[inline(always)]
            fn $name(self $(, $arg: Self)*) -> Self {
                $f(self $(, $arg)*)
            }
        )*
    };
}

macro_rules! real_common {
    ($t:ty, $m:ident) => {
        const ZERO: Self = 0.0;
        const ONE: Self = 1.0;
        const TWO: Self = 2.0;
        const HALF: Self = 0.5;
        const PI: Self = core::$m::consts::PI;
        const EPSILON: Self = <$t>::EPSILON;
        const MAX: Self = <$t>::MAX;
        const MIN_POSITIVE: Self = <$t>::MIN_POSITIVE;
        const INFINITY: Self = <$t>::INFINITY;
        const NAN: Self = <$t>::NAN;
        // 1 - 2/(exp(2x) + 1) rounds to exactly 1 above: 2/exp(2x) is then below a
        // quarter of EPSILON, under half the spacing of the numbers just below 1
        // (f32: exp(19) = 1.8e8, 2/1.8e8 = 1.1e-8 < 3.0e-8; f64: exp(39) = 8.7e16,
        // 2.3e-17 < 5.6e-17).
        const TANH_SATURATES: Self = if <$t>::EPSILON > 1e-10 { 9.5 } else { 19.5 };

        #[inline(always)]
        fn from_f64(x: f64) -> Self {
            x as $t
        }
        #[inline(always)]
        fn from_i32(i: i32) -> Self {
            i as $t
        }
        #[inline(always)]
        fn from_usize(n: usize) -> Self {
            n as $t
        }
        #[inline(always)]
        fn to_f64(self) -> f64 {
            self as f64
        }
        #[inline(always)]
        fn to_usize_trunc(self) -> usize {
            self as usize
        }
        #[inline(always)]
        fn abs(self) -> Self {
            // The sign bit cleared: one instruction (vabs on the chip), no branch; the same
            // value as a compare-and-negate for every number, +0 for -0.
            <$t>::abs(self)
        }
        #[inline(always)]
        fn is_finite(self) -> bool {
            <$t>::is_finite(self)
        }
        #[inline(always)]
        fn is_nan(self) -> bool {
            <$t>::is_nan(self)
        }
        #[inline(always)]
        fn powi(self, n: i32) -> Self {
            let mut base = if n < 0 { 1.0 / self } else { self };
            let mut e = n.unsigned_abs();
            let mut acc: $t = 1.0;
            while e > 0 {
                if e & 1 == 1 {
                    acc *= base;
                }
                base *= base;
                e >>= 1;
            }
            acc
        }
    };
}

impl Real for f64 {
    real_common!(f64, f64);
    delegate_math! {
        sqrt() => libm::sqrt;
        cbrt() => libm::cbrt;
        sin() => libm::sin;
        cos() => libm::cos;
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        libm::sincos(self)
    }
    delegate_math! {
        tan() => libm::tan;
        asin() => libm::asin;
        acos() => libm::acos;
        atan() => libm::atan;
        atan2(x) => libm::atan2;
        exp() => libm::exp;
        ln() => libm::log;
        powf(p) => libm::pow;
        floor() => libm::floor;
        hypot(y) => libm::hypot;
    }
}

#[cfg(not(feature = "micromath"))]
impl Real for f32 {
    real_common!(f32, f32);
    delegate_math! {
        sqrt() => libm::sqrtf;
        cbrt() => libm::cbrtf;
    }
    #[inline(always)]
    fn sin(self) -> Self {
        sin_cos_f32(self).0
    }
    #[inline(always)]
    fn cos(self) -> Self {
        sin_cos_f32(self).1
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        sin_cos_f32(self)
    }
    delegate_math! {
        tan() => libm::tanf;
        asin() => libm::asinf;
        acos() => libm::acosf;
        atan() => libm::atanf;
        atan2(x) => libm::atan2f;
        exp() => libm::expf;
        ln() => libm::logf;
        powf(p) => libm::powf;
        floor() => libm::floorf;
        hypot(y) => libm::hypotf;
    }
}

/// Cam speed in rpm to angular speed in rad/s, computed as `(rpm · π) / 30` in `T`
/// (that order: the firmware's f32 numbers and the host's agree bit for bit only if
/// both sides round the same products).
#[inline(always)]
pub fn rpm_to_rad_per_s<T: Real>(rpm: T) -> T {
    rpm * T::PI / T::from_f64(30.0)
}

/// Angular speed in rad/s to rpm, computed as `(ω · 30) / π` in `T`.
#[inline(always)]
pub fn rad_per_s_to_rpm<T: Real>(rad_per_s: T) -> T {
    rad_per_s * T::from_f64(30.0) / T::PI
}

/// Single-precision sine and cosine computed in single precision.
///
/// libm's `sinf`/`cosf` evaluate in `f64`: on the Cortex-M4F's single-precision FPU that
/// is software double arithmetic (its cost is measured in docs/FIRMWARE.md).
/// This is Cephes' `sinf`/`cosf` (S. L. Moshier): reduction by π/4 in three parts
/// (Cody-Waite, exact for |x| < 8192) and minimax polynomials on [-π/4, π/4]; peak error
/// within 2 ulp (tested against `f64` below). Larger arguments go through
/// [`sin_cos_f32_large`]; infinite and NaN arguments give NaN.
#[cfg(not(feature = "micromath"))]
#[inline(never)] // one copy: inlining it at every call site costs the chip's flash
fn sin_cos_f32(x: f32) -> (f32, f32) {
    let ax = if x < 0.0 { -x } else { x };
    if ax.is_nan() || ax >= 8192.0 {
        return sin_cos_f32_large(x);
    }
    const FOPI: f32 = 1.273_239_5; // 4/π
    const DP1: f32 = 0.785_156_25;
    const DP2: f32 = 2.418_756_5e-4;
    const DP3: f32 = 3.774_895e-8;
    let mut j = (ax * FOPI) as u32; // truncation toward zero, ax >= 0
    if j & 1 == 1 {
        j += 1;
    }
    let y = j as f32;
    let j = j & 7;
    let z = ((ax - y * DP1) - y * DP2) - y * DP3;
    let zz = z * z;
    let sp = ((-1.951_529_6e-4 * zz + 8.332_161e-3) * zz - 1.666_665_5e-1) * zz * z + z;
    let cp =
        ((2.443_315_7e-5 * zz - 1.388_731_6e-3) * zz + 4.166_664_6e-2) * zz * zz - 0.5 * zz + 1.0;
    // j is even: 0, 2, 4 or 6 (octant pairs): rotate by multiples of π/2.
    let (s, c) = match j {
        0 => (sp, cp),
        2 => (cp, -sp),
        4 => (-sp, -cp),
        _ => (-cp, sp),
    };
    if x < 0.0 {
        (-s, c)
    } else {
        (s, c)
    }
}

/// Sine and cosine for |x| >= 8192 (and NaN, ±∞, which give NaN): the argument is reduced
/// by the exact remainder (`fmodf`, exact in IEEE arithmetic) modulo τ rounded to `f32`
/// (6.283 185 5, 1.748e-7 above τ), and the reduced angle, below 6.29, takes the
/// polynomial path. The angle used is then `x - n·τ_f32 = x - n·τ - n·1.748e-7` with
/// `n <= |x|/τ`: it lies within |x|·2.78e-8 of x, less than half of x's own `f32` spacing
/// (at least |x|·2^-24 = |x|·5.96e-8), so within the rounding that x already carries. This
/// replaces libm's `sincosf` (Payne-Hanek reduction and `f64` kernels, 7.5 KB of the chip's
/// flash with software double arithmetic); no cam angle reaches it.
#[cfg(not(feature = "micromath"))]
#[cold]
#[inline(never)]
fn sin_cos_f32_large(x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    sin_cos_f32(libm::fmodf(x, core::f32::consts::TAU))
}

#[cfg(feature = "micromath")]
impl Real for f32 {
    real_common!(f32, f32);
    #[inline(always)]
    fn sqrt(self) -> Self {
        // The M4F has a hardware square root; micromath's is an approximation.
        libm::sqrtf(self)
    }
    delegate_math! {
        cbrt() => libm::cbrtf;
        sin() => micromath::F32Ext::sin;
        cos() => micromath::F32Ext::cos;
        tan() => micromath::F32Ext::tan;
        asin() => micromath::F32Ext::asin;
        acos() => micromath::F32Ext::acos;
        atan() => micromath::F32Ext::atan;
        atan2(x) => micromath::F32Ext::atan2;
    }
    #[inline(always)]
    fn exp(self) -> Self {
        // micromath's exp returns NaN for arguments in [88.7233, 89.416] (and its debug
        // build panics there) instead of overflowing: past ln(f32::MAX) = 88.722839 the
        // result is +inf, as libm's. `coulomb_friction`'s tanh reaches such arguments.
        if self >= 88.722_84 {
            f32::INFINITY
        } else {
            micromath::F32Ext::exp(self)
        }
    }
    delegate_math! {
        ln() => micromath::F32Ext::ln;
        powf(p) => micromath::F32Ext::powf;
        floor() => micromath::F32Ext::floor;
        hypot(y) => micromath::F32Ext::hypot;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rpm_conversions_are_the_hand_formulas_and_invert() {
        use core::f64::consts::PI;
        // 60 rpm is one revolution per second: 2π rad/s.
        assert!((rpm_to_rad_per_s(60.0f64) - 2.0 * PI).abs() < 1e-15);
        assert!((rad_per_s_to_rpm(2.0 * PI) - 60.0f64).abs() < 1e-12);
        for rpm in [0.1f64, 1.0, 300.0, 697.65625, 800.0, 20000.0] {
            // Bit for bit the formulas the code used before (same operation order).
            assert_eq!(rpm_to_rad_per_s(rpm).to_bits(), (rpm * PI / 30.0).to_bits());
            let w = rpm * PI / 30.0;
            assert_eq!(rad_per_s_to_rpm(w).to_bits(), (w * 30.0 / PI).to_bits());
            assert!((rad_per_s_to_rpm(rpm_to_rad_per_s(rpm)) / rpm - 1.0).abs() < 1e-15);
            let r = rpm as f32;
            let pi = core::f32::consts::PI;
            assert_eq!(rpm_to_rad_per_s(r).to_bits(), (r * pi / 30.0).to_bits());
        }
    }

    fn generic_identity<T: Real>(x: T) -> T {
        let (s, c) = x.sin_cos();
        s.sq() + c.sq()
    }

    #[test]
    fn single_precision_exp_overflows_to_infinity_never_nan() {
        // Just below ln(f32::MAX) = 88.722839 the result is finite, from there on +inf
        // (micromath's own exp gave NaN on [88.7233, 89.416]).
        assert!(Real::exp(88.722_83f32).is_finite());
        let mut x = 88.0f32;
        while x < 100.0 {
            let e = Real::exp(x);
            assert!(!e.is_nan(), "exp({x}) is NaN");
            assert!(e.is_finite() || x >= 88.722_84, "exp({x}) = {e}");
            x += 1e-4;
        }
        assert_eq!(Real::exp(f32::INFINITY), f32::INFINITY);
        assert_eq!(Real::exp(-200.0f32), 0.0);
    }

    #[test]
    fn pythagoras_both_precisions() {
        assert!((generic_identity(0.7f64) - 1.0).abs() < 1e-15);
        // micromath's sin/cos are approximations (about 1e-3 relative).
        let f32_tol = if cfg!(feature = "micromath") {
            1e-2
        } else {
            1e-6
        };
        assert!((generic_identity(0.7f32) - 1.0).abs() < f32_tol);
    }

    #[cfg(not(feature = "micromath"))]
    #[test]
    fn single_precision_sin_cos_within_two_ulp() {
        // Dense sweep over the arguments the laws use (|x| < 8π) and beyond, against f64.
        let mut worst = 0.0f64;
        let mut x = -100.0f32;
        while x < 100.0 {
            let (s, c) = super::sin_cos_f32(x);
            let (s64, c64) = (x as f64).sin_cos();
            for (a, b) in [(s as f64, s64), (c as f64, c64)] {
                // Error in units of the f32 spacing at the exact value (floor: near zero,
                // the absolute error of the reduced argument).
                let ulp = (b.abs().max(1e-3) as f32).to_bits();
                let spacing = f32::from_bits(ulp + 1) as f64 - f32::from_bits(ulp) as f64;
                worst = worst.max((a - b).abs() / spacing);
            }
            x += 0.000_731;
        }
        assert!(worst <= 2.0, "worst error {worst} ulp");
        // Exact points and the non-finite arguments.
        assert_eq!(super::sin_cos_f32(0.0), (0.0, 1.0));
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            let (s, c) = super::sin_cos_f32(bad);
            assert!(s.is_nan() && c.is_nan(), "{bad}");
        }
    }

    #[cfg(not(feature = "micromath"))]
    #[test]
    fn large_arguments_within_half_their_own_spacing() {
        // |x| >= 8192: the angle used is within |x|·(τ_f32 - τ)/τ of x (the remainder is
        // exact), under half of x's f32 spacing; sin and cos are 1-Lipschitz, so the error
        // against f64 is at most that shift plus the polynomial path's 2 ulp of 1.
        let shift_per_x =
            (core::f32::consts::TAU as f64 - core::f64::consts::TAU) / core::f64::consts::TAU;
        let mut x = 8192.0f32;
        let mut checked = 0;
        while x.is_finite() {
            for arg in [x, -x, f32::from_bits(x.to_bits() + 12_345)] {
                let (s, c) = super::sin_cos_f32(arg);
                let (s64, c64) = (arg as f64).sin_cos();
                let spacing = f32::from_bits(arg.abs().to_bits() + 1) as f64 - arg.abs() as f64;
                let bound = arg.abs() as f64 * shift_per_x + 2.0 * f32::EPSILON as f64;
                assert!(bound < 0.5 * spacing + 2.0 * f32::EPSILON as f64, "{arg}");
                assert!(
                    (s as f64 - s64).abs() <= bound,
                    "sin {arg}: {s} against {s64}"
                );
                assert!(
                    (c as f64 - c64).abs() <= bound,
                    "cos {arg}: {c} against {c64}"
                );
                assert!((s * s + c * c - 1.0).abs() < 1e-6, "{arg}");
                checked += 1;
            }
            x *= 1.37;
        }
        assert!(checked > 200);
        let (s, c) = super::sin_cos_f32(f32::MAX);
        assert!(s.is_finite() && c.is_finite());
    }

    #[test]
    fn powi_matches_repeated_multiplication() {
        assert_eq!(2.0f64.powi(10), 1024.0);
        assert_eq!(2.0f64.powi(-2), 0.25);
        assert_eq!(3.0f32.powi(0), 1.0);
    }

    #[test]
    fn degrees_round_trip() {
        let d = 123.0f64;
        assert!((d.to_radians().to_degrees() - d).abs() < 1e-12);
    }

    #[test]
    fn max_min_ignore_nan() {
        assert_eq!(1.0f64.max(f64::NAN), 1.0);
        assert_eq!(f64::NAN.min(2.0), 2.0);
    }
}
