//! Seeded, reproducible random numbers for the stochastic profile (IV.2, Appendix B).
//!
//! The generator is Marsaglia's xorshift128 (`rand_xorshift::XorShiftRng`, period
//! 2¹²⁸ − 1): 16 bytes of state, a few integer instructions a draw, `no_std`.
//!
//! # Seeds (stable: changing any of this changes every stored study)
//!
//! * A `u64` seed `s` is expanded to the generator's 16-byte seed by [`splitmix64`]:
//!   the first two outputs of SplitMix64 started from state `s`, each written
//!   little-endian (bytes 0-7, then 8-15). This is done here, not by
//!   `SeedableRng::seed_from_u64`, so the expansion cannot change with `rand_core`.
//!   (An all-zero 16-byte seed, which xorshift cannot use, is replaced by
//!   `rand_xorshift` with `0x0BAD_5EED` words; SplitMix64 never produces two zero
//!   outputs in a row from any state, so a `u64` seed never reaches that case.)
//! * Sample `i` of a study with master seed `m` uses the seed
//!   [`sample_seed`]`(m, i)` = the `i`-th output (counting from 0) of SplitMix64
//!   started from state `m`, that is `mix(m + (i + 1)·γ)` with
//!   `γ = 0x9E37_79B9_7F4A_7C15` (wrapping). It depends only on `(m, i)`, never on
//!   which other samples were drawn or in which order.
//!
//! # Deviates
//!
//! * [`RandomStream::uniform`]: in the open interval (0, 1), never 0 or 1, symmetric
//!   about 1/2: `(2k + 1)/2²⁴` for `f32` (k uniform over 2²³ values, from the top 23
//!   bits of one 32-bit draw, exact in `f32`) and `(2k + 1)/2⁵³` for `f64` (k over 2⁵²,
//!   from the top 52 bits of one 64-bit draw, exact in `f64`). Only integer-to-float
//!   conversions and multiplications by powers of two in `T`: no `f64` arithmetic for
//!   `f32`.
//! * [`NormalMethod::SumOfTwelve`] (Appendix B, Eq. B-2): `Y = Σ₁¹² Xᵢ − 6` with uniform
//!   `Xᵢ`. Mean 0, variance 12 · 1/12 = 1, kurtosis 3 − 6/(5·12) = 2.9 (the Irwin-Hall
//!   distribution), and `|Y| ≤ 6` always: the tails are cut at ±6σ exactly.
//! * [`NormalMethod::Polar`] (Marsaglia's polar form of Box-Muller): exact normal
//!   deviates. `u = 2U₁ − 1`, `v = 2U₂ − 1` (never 0), `s = u² + v²`, rejected unless
//!   `s < 1` (probability π/4 of acceptance); then `u f`, `v f` with
//!   `f = √(−2 ln s / s)`; the second of each pair is kept for the next call. No
//!   trigonometry; the logarithm is libm's in the precision of `T` whatever the
//!   `micromath` feature (its approximate `ln` would bias the variance by several
//!   percent). Since `s ≥ 2·2⁻⁴⁶` (`f32`) or `2·2⁻¹⁰⁴` (`f64`), `|Y| ≤ √(−2 ln s)`:
//!   7.9 in `f32`, 12 in `f64`. The rejection loop stops after 64 tries (all
//!   rejected with probability 0.215⁶⁴ ≈ 10⁻⁴³) and then returns 0.
//! * [`RandomStream::gaussian`] applies Eq. B-3, `μ + σY`.

use crate::Real;
use rand_core::{Rng, SeedableRng};
use rand_xorshift::XorShiftRng;

/// SplitMix64's increment γ (the golden ratio in 64-bit fixed point).
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// SplitMix64's output function (Steele, Lea & Flood 2014; Vigna's constants).
#[inline]
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// One step of SplitMix64: advances `state` by γ and returns the mixed new state.
///
/// From state 0 the outputs are `0xE220A8397B1DCDAF`, `0x6E789E6AA1B965F4`,
/// `0x06C45D188009454F`, ... (the reference sequence).
#[inline]
pub fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(GAMMA);
    mix64(*state)
}

/// The seed of sample `index` of a study with seed `master`: the `index`-th output
/// (from 0) of SplitMix64 started at `master`, computed directly in O(1).
///
/// Stable forever: a study's sample `i` can be regenerated alone, in any order.
#[inline]
pub fn sample_seed(master: u64, index: u64) -> u64 {
    mix64(master.wrapping_add(index.wrapping_add(1).wrapping_mul(GAMMA)))
}

/// `ln x` by libm in `T`'s own precision (`logf` for `f32`, `log` for `f64`), never
/// micromath's approximation.
#[inline(always)]
fn ln_libm<T: Real>(x: T) -> T {
    use core::any::Any;
    let a: &dyn Any = &x;
    if let Some(&v) = a.downcast_ref::<f32>() {
        let r = libm::logf(v);
        if let Some(&t) = (&r as &dyn Any).downcast_ref::<T>() {
            return t;
        }
    } else if let Some(&v) = a.downcast_ref::<f64>() {
        let r = libm::log(v);
        if let Some(&t) = (&r as &dyn Any).downcast_ref::<T>() {
            return t;
        }
    }
    x.ln()
}

/// How [`RandomStream::normal`] makes a standard normal deviate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalMethod {
    /// Appendix B, Eq. B-2: the sum of 12 uniforms minus 6 (the thesis's choice).
    /// Mean 0, variance 1, kurtosis 2.9, bounded by ±6 exactly.
    #[default]
    SumOfTwelve,
    /// Marsaglia's polar method: exactly normal (to the resolution of the uniforms),
    /// two deviates per accepted pair.
    Polar,
}

/// A seeded stream of uniform and normal deviates in `T` (see the module docs for
/// the seeding rules and the distributions).
#[derive(Clone, Debug, PartialEq)]
pub struct RandomStream<T> {
    rng: XorShiftRng,
    method: NormalMethod,
    /// The polar method's second deviate of the last pair, not yet returned.
    spare: Option<T>,
}

impl<T: Real> RandomStream<T> {
    /// A stream from a `u64` seed (expanded by SplitMix64, see the module docs).
    pub fn new(seed: u64, method: NormalMethod) -> Self {
        let mut state = seed;
        let (a, b) = (splitmix64(&mut state), splitmix64(&mut state));
        let mut bytes = [0u8; 16];
        for (dst, src) in bytes
            .iter_mut()
            .zip(a.to_le_bytes().into_iter().chain(b.to_le_bytes()))
        {
            *dst = src;
        }
        Self::from_seed_bytes(bytes, method)
    }

    /// A stream from the generator's own 16-byte seed: the four xorshift128 state
    /// words `x, y, z, w`, each little-endian (all zero is replaced by `0x0BAD_5EED`
    /// words).
    pub fn from_seed_bytes(seed: [u8; 16], method: NormalMethod) -> Self {
        RandomStream {
            rng: XorShiftRng::from_seed(seed),
            method,
            spare: None,
        }
    }

    /// The stream of sample `index` of a study with seed `master`:
    /// `RandomStream::new(sample_seed(master, index), method)`.
    pub fn for_sample(master: u64, index: u64, method: NormalMethod) -> Self {
        Self::new(sample_seed(master, index), method)
    }

    /// The normal method [`RandomStream::normal`] uses.
    pub fn method(&self) -> NormalMethod {
        self.method
    }

    /// The next 32 raw bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.rng.next_u32()
    }

    /// The next 64 raw bits (two 32-bit draws, the first in the low half).
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.rng.next_u64()
    }

    /// A uniform deviate in the open interval (0, 1).
    #[inline]
    pub fn uniform(&mut self) -> T {
        if T::EPSILON > T::from_f64(1e-10) {
            // Single precision: an odd 24-bit integer times 2⁻²⁴.
            let m = (self.next_u32() >> 8) | 1;
            T::from_usize(m as usize) * T::from_f64(1.0 / 16_777_216.0)
        } else {
            // Double precision: an odd 53-bit integer times 2⁻⁵³, assembled from two
            // 32-bit halves (usize is 32 bits on the chip), exact in f64.
            let m = (self.next_u64() >> 11) | 1;
            let hi = T::from_usize((m >> 32) as usize);
            let lo = T::from_usize((m & 0xFFFF_FFFF) as usize);
            (hi * T::from_f64(4_294_967_296.0) + lo) * T::from_f64(1.0 / 9_007_199_254_740_992.0)
        }
    }

    /// A standard normal deviate by the stream's method.
    #[inline]
    pub fn normal(&mut self) -> T {
        self.normal_with(self.method)
    }

    /// A standard normal deviate by `method`.
    pub fn normal_with(&mut self, method: NormalMethod) -> T {
        match method {
            NormalMethod::SumOfTwelve => {
                let mut sum = T::ZERO;
                for _ in 0..12 {
                    sum += self.uniform();
                }
                sum - T::from_i32(6)
            }
            NormalMethod::Polar => {
                if let Some(z) = self.spare.take() {
                    return z;
                }
                for _ in 0..64 {
                    let u = T::TWO * self.uniform() - T::ONE;
                    let v = T::TWO * self.uniform() - T::ONE;
                    let s = u * u + v * v;
                    if s < T::ONE {
                        let f = (-T::TWO * ln_libm(s) / s).sqrt();
                        self.spare = Some(v * f);
                        return u * f;
                    }
                }
                T::ZERO
            }
        }
    }

    /// A normal deviate with mean `mean` and standard deviation `sigma` (Eq. B-3).
    #[inline]
    pub fn gaussian(&mut self, mean: T, sigma: T) -> T {
        mean + sigma * self.normal()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_reference_sequence() {
        // The published SplitMix64 outputs from state 0.
        let mut s = 0u64;
        assert_eq!(splitmix64(&mut s), 0xE220_A839_7B1D_CDAF);
        assert_eq!(splitmix64(&mut s), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(splitmix64(&mut s), 0x06C4_5D18_8009_454F);
        // sample_seed(m, i) is the i-th output from m, whatever m.
        for m in [0u64, 1, 42, u64::MAX] {
            let mut s = m;
            for i in 0..100 {
                assert_eq!(sample_seed(m, i), splitmix64(&mut s));
            }
        }
    }

    #[test]
    fn xorshift128_reference_sequence() {
        // Marsaglia (2003), xor128 with x, y, z, w = 123456789, 362436069, 521288629,
        // 88675123: the first outputs are 3701687786, 458299110, 2500872618.
        let mut seed = [0u8; 16];
        for (k, w) in [123_456_789u32, 362_436_069, 521_288_629, 88_675_123]
            .iter()
            .enumerate()
        {
            seed[4 * k..4 * k + 4].copy_from_slice(&w.to_le_bytes());
        }
        let mut r = RandomStream::<f64>::from_seed_bytes(seed, NormalMethod::SumOfTwelve);
        assert_eq!(r.next_u32(), 3_701_687_786);
        assert_eq!(r.next_u32(), 458_299_110);
        assert_eq!(r.next_u32(), 2_500_872_618);
    }

    #[test]
    fn same_seed_same_sequence_and_order_free_derivation() {
        for method in [NormalMethod::SumOfTwelve, NormalMethod::Polar] {
            let mut a = RandomStream::<f64>::new(7, method);
            let mut b = RandomStream::<f64>::new(7, method);
            let mut c = RandomStream::<f64>::new(8, method);
            let mut differ = 0;
            for _ in 0..1000 {
                let (x, y, z) = (a.normal(), b.normal(), c.normal());
                assert_eq!(x.to_bits(), y.to_bits());
                differ += usize::from(x != z);
            }
            assert!(differ > 990);
        }
        // Sample 5's stream is the same whether samples 0..5 were drawn first, in
        // reverse, or not at all.
        let first: [f32; 8] = {
            let mut r = RandomStream::<f32>::for_sample(99, 5, NormalMethod::Polar);
            core::array::from_fn(|_| r.normal())
        };
        for i in (0..10).rev() {
            let mut r = RandomStream::<f32>::for_sample(99, i, NormalMethod::Polar);
            let _ = r.normal();
        }
        let mut r = RandomStream::<f32>::for_sample(99, 5, NormalMethod::Polar);
        let again: [f32; 8] = core::array::from_fn(|_| r.normal());
        assert_eq!(first, again);
        assert_eq!(
            RandomStream::<f32>::for_sample(99, 5, NormalMethod::Polar),
            RandomStream::<f32>::new(sample_seed(99, 5), NormalMethod::Polar)
        );
    }

    #[test]
    fn uniform_is_open_and_exact() {
        // f32: odd multiples of 2^-24; f64: odd multiples of 2^-53; never 0 or 1.
        let mut r = RandomStream::<f32>::new(1, NormalMethod::SumOfTwelve);
        let (mut lo, mut hi) = (1.0f32, 0.0f32);
        for _ in 0..100_000 {
            let u = r.uniform();
            assert!(u > 0.0 && u < 1.0);
            let k = u * 16_777_216.0;
            assert_eq!(k, k.floor());
            assert_eq!(k as u32 % 2, 1);
            lo = lo.min(u);
            hi = hi.max(u);
        }
        assert!(lo < 1e-4 && hi > 1.0 - 1e-4);
        let mut r = RandomStream::<f64>::new(1, NormalMethod::SumOfTwelve);
        for _ in 0..100_000 {
            let u = r.uniform();
            assert!(u > 0.0 && u < 1.0);
            let k = u * 9_007_199_254_740_992.0;
            assert_eq!(k, k.floor());
            assert_eq!(k as u64 % 2, 1);
        }
    }

    /// Sample moments of `n` deviates: mean, variance, fourth central moment over
    /// variance squared (kurtosis), fraction with |z| > 2, largest |z|.
    fn moments<T: Real>(r: &mut RandomStream<T>, n: usize) -> (f64, f64, f64, f64, f64) {
        let (mut s1, mut s2, mut s4, mut tail, mut max) = (0.0, 0.0, 0.0, 0usize, 0.0f64);
        for _ in 0..n {
            let z = r.normal().to_f64();
            s1 += z;
            s2 += z * z;
            s4 += z * z * z * z;
            tail += usize::from(z.abs() > 2.0);
            max = max.max(z.abs());
        }
        let nf = n as f64;
        let m = s1 / nf;
        (m, s2 / nf - m * m, s4 / nf, tail as f64 / nf, max)
    }

    #[test]
    fn normal_moments_within_five_standard_errors() {
        // For n independent deviates of a distribution with mean 0, variance 1 and
        // fourth moment μ4 the standard errors are: mean 1/√n, variance √((μ4 − 1)/n),
        // fourth moment √((μ8 − μ4²)/n), tail fraction √(p(1 − p)/n); every check allows
        // 5 of them. Normal: μ4 = 3, μ8 = 105, P(|z| > 2) = erfc(√2) = 0.0455003.
        // Sum of 12 uniforms (centred Irwin-Hall): cumulants κ4 = 12·(−1/120) = −0.1, so
        // μ4 = 3 + κ4 = 2.9; its μ8 is below the normal's 105, which is used (a looser
        // bound); P(|z| > 2) = 2 P(S > 8) = 0.0445512 from the Irwin-Hall CDF. Both
        // the kurtosis (0.1 apart, 10 standard errors) and the tail (4.5 apart) tell the
        // two methods apart.
        let n = 1_000_000usize;
        let nf = n as f64;
        let irwin_hall_tail = 2.0 * irwin_hall_upper(12, 8.0);
        assert!(
            (irwin_hall_tail - 0.044_551_166).abs() < 1e-8,
            "{irwin_hall_tail}"
        );
        for (method, mu4, p2) in [
            (NormalMethod::Polar, 3.0, 0.045_500_263_896_358_4),
            (NormalMethod::SumOfTwelve, 2.9, irwin_hall_tail),
        ] {
            for precision in 0..2 {
                let (m, v, k, tail, max) = if precision == 0 {
                    moments(&mut RandomStream::<f64>::new(2024, method), n)
                } else {
                    moments(&mut RandomStream::<f32>::new(2024, method), n)
                };
                let se_m = 1.0 / nf.sqrt();
                let se_v = ((mu4 - 1.0) / nf).sqrt();
                let se_k = ((105.0 - mu4 * mu4) / nf).sqrt();
                let se_t = (p2 * (1.0 - p2) / nf).sqrt();
                let what = (method, precision);
                assert!(m.abs() < 5.0 * se_m, "{what:?} mean {m}");
                assert!((v - 1.0).abs() < 5.0 * se_v, "{what:?} variance {v}");
                assert!((k - mu4).abs() < 5.0 * se_k, "{what:?} kurtosis {k}");
                assert!((tail - p2).abs() < 5.0 * se_t, "{what:?} tail {tail}");
                if method == NormalMethod::SumOfTwelve {
                    // Bounded at 6 always; P(|z| > 5) = 2 P(S > 11) = 2/12! ≈ 4e-9.
                    assert!(max <= 6.0, "{what:?} bounded at 6: {max}");
                } else {
                    // 10⁶ normal deviates exceed 4.5 with probability 1 − 1e-3; the
                    // open uniforms bound them at √(2·103 ln 2) = 11.95.
                    assert!(max > 4.5 && max < 11.95, "{what:?} {max}");
                }
            }
        }
    }

    /// P(S > x) for S the sum of `k` uniforms on (0, 1) (Irwin-Hall):
    /// `1 − (1/k!) Σ_{j ≤ x} (−1)^j C(k, j) (x − j)^k`.
    fn irwin_hall_upper(k: u32, x: f64) -> f64 {
        let mut fact = 1.0;
        for i in 1..=k {
            fact *= i as f64;
        }
        let mut cdf = 0.0;
        let mut binom = 1.0;
        for j in 0..=k {
            if (j as f64) < x {
                let sign = if j % 2 == 0 { 1.0 } else { -1.0 };
                cdf += sign * binom * (x - j as f64).powi(k as i32);
            }
            binom = binom * (k - j) as f64 / (j + 1) as f64;
        }
        1.0 - cdf / fact
    }

    #[test]
    fn gaussian_applies_mean_and_sigma() {
        let mut a = RandomStream::<f64>::new(3, NormalMethod::Polar);
        let mut b = RandomStream::<f64>::new(3, NormalMethod::Polar);
        for _ in 0..100 {
            let z = a.normal();
            assert_eq!(b.gaussian(2.0, 0.5), 2.0 + 0.5 * z);
        }
        // Zero sigma gives the mean exactly.
        assert_eq!(a.gaussian(1.25, 0.0), 1.25);
    }
}
