//! Statistics of one quantity over many samples in memory independent of their number,
//! and independent of the order they come in: exact sums, integer counts, the minimum and
//! maximum, and a histogram on a grid fixed before the study.
//!
//! - [`ExactSum`]: Shewchuk's non-overlapping partials (the sum held exactly, as Python's
//!   `math.fsum`), rounded once when read. The sum of any set of numbers is then the same
//!   bits whatever their order, grouping or split into shards.
//! - [`Stream`]: the count; the exact Σx and Σx² (each x² as the exact pair `hi + lo`,
//!   `lo = fma(x, x, −hi)`); the minimum and maximum; and the histogram. The variance is
//!   `Σ(x − m)² = Σx² − 2mΣx + nm²` with m the rounded mean, every product split exactly
//!   and summed exactly, so it is the two-pass sum of squares rounded once.
//! - The histogram's bins are those of the `f64` format cut to [`MANTISSA_BITS`] bits of
//!   mantissa: a bin holds the numbers that share sign, exponent and the top 10 mantissa
//!   bits, so its width is at most 2⁻¹⁰ of the numbers in it (0.098 %), at any magnitude,
//!   and no bound has to be guessed before the study. Each bin keeps its count and the
//!   smallest and largest value in it. An order statistic is read from its bin (linear
//!   between the bin's smallest and largest value by rank within the bin): exact when the
//!   bin holds one or two values or one distinct value, and otherwise within the bin, so
//!   within [`QUANTILE_RESOLUTION`] (2⁻¹⁰) of the true order statistic's magnitude.
//!   Percentiles are then type 7 (linear between the order statistics at rank (n − 1)p)
//!   of those order statistics.
//!
//! Memory: a bin for every occupied cell of the grid, at most 1 024 a factor of two of the
//! values' range (a column spread over 1-1000 has at most about 10 240 bins), never more
//! than the samples; it does not grow with the samples once the range is filled.

use std::collections::BTreeMap;

use anyhow::{ensure, Result};
use serde::{Deserialize, Serialize};

/// Mantissa bits a histogram bin keeps.
pub const MANTISSA_BITS: u32 = 10;
const SHIFT: u32 = 52 - MANTISSA_BITS;

/// How close a percentile is to the exact one: within this fraction of the larger
/// magnitude of the two order statistics it lies between (2⁻¹⁰ = 0.098 %: the bin's
/// width relative to its values).
pub const QUANTILE_RESOLUTION: f64 = 1.0 / 1024.0;

/// A sum held exactly (Shewchuk's partials: non-overlapping, increasing magnitude).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct ExactSum {
    partials: Vec<f64>,
}

/// `a · b` exactly as `hi + lo` (barring underflow).
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let hi = a * b;
    (hi, a.mul_add(b, -hi))
}

impl ExactSum {
    /// Adds `x` exactly (a non-finite `x` or an overflow makes the sum non-finite).
    pub fn add(&mut self, x: f64) {
        if !x.is_finite() || self.partials.iter().any(|p| !p.is_finite()) {
            self.partials = vec![x + self.partials.iter().sum::<f64>()];
            return;
        }
        let mut x = x;
        let mut kept = 0;
        for j in 0..self.partials.len() {
            let mut y = self.partials[j];
            if x.abs() < y.abs() {
                std::mem::swap(&mut x, &mut y);
            }
            let hi = x + y;
            let lo = y - (hi - x);
            if lo != 0.0 {
                self.partials[kept] = lo;
                kept += 1;
            }
            x = hi;
        }
        self.partials.truncate(kept);
        self.partials.push(x);
    }

    /// Adds another exact sum.
    pub fn add_sum(&mut self, other: &ExactSum) {
        for &p in &other.partials {
            self.add(p);
        }
    }

    /// The partials (exact sum = their sum).
    pub fn partials(&self) -> &[f64] {
        &self.partials
    }

    /// The exact sum rounded once to nearest (ties to even), as `math.fsum`.
    pub fn value(&self) -> f64 {
        let p = &self.partials;
        let Some(&last) = p.last() else {
            return 0.0;
        };
        if !last.is_finite() {
            return last;
        }
        let mut n = p.len() - 1;
        let mut hi = last;
        let mut lo = 0.0;
        while n > 0 {
            let x = hi;
            n -= 1;
            let y = p[n];
            hi = x + y;
            let yr = hi - x;
            lo = y - yr;
            if lo != 0.0 {
                break;
            }
        }
        // Half-way cases: the rest decides the direction of the rounding.
        if n > 0 && ((lo < 0.0 && p[n - 1] < 0.0) || (lo > 0.0 && p[n - 1] > 0.0)) {
            let y = lo * 2.0;
            let x = hi + y;
            if y == x - hi {
                hi = x;
            }
        }
        hi
    }
}

/// One histogram bin: how many values, the smallest and the largest.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bin {
    count: u64,
    lo: f64,
    hi: f64,
}

/// The bin of `x` (monotone in x; −0 and +0 share one).
fn key(x: f64) -> i64 {
    let a = (x.abs().to_bits() >> SHIFT) as i64;
    if x < 0.0 {
        -a - 1
    } else {
        a
    }
}

/// The middle of the interval of values whose [`key`] is `k` (inside it, monotone in k).
fn grid_mid(k: i64) -> f64 {
    let (a, sign) = if k < 0 { (-(k + 1), -1.0) } else { (k, 1.0) };
    let bits = (a as u64) << SHIFT | (1u64 << (SHIFT - 1));
    sign * f64::from_bits(bits)
}

/// The statistics of one quantity over samples (see the module).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stream {
    n: u64,
    sum: ExactSum,
    sum_sq: ExactSum,
    min: f64,
    max: f64,
    bins: BTreeMap<i64, Bin>,
}

/// Mean, standard deviation and percentiles of one statistic over the samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Moments {
    /// Mean.
    pub mean: f64,
    /// Sample standard deviation (n − 1; 0 for one sample).
    pub sd: f64,
    /// 5th percentile.
    pub p5: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
}

impl Moments {
    /// The moments of `values` (at least one, all finite).
    pub fn of(what: &str, values: &[f64]) -> Result<Self> {
        let mut s = Stream::default();
        for &v in values {
            s.add(what, v)?;
        }
        s.moments(what)
    }
}

impl Stream {
    /// Adds one sample's value (finite; −0 counts as +0).
    pub fn add(&mut self, what: &str, x: f64) -> Result<()> {
        ensure!(x.is_finite(), "{what}: a sample is {x}");
        let x = x + 0.0;
        if self.n == 0 {
            (self.min, self.max) = (x, x);
        } else {
            self.min = self.min.min(x);
            self.max = self.max.max(x);
        }
        self.n += 1;
        self.sum.add(x);
        let (hi, lo) = two_product(x, x);
        self.sum_sq.add(hi);
        self.sum_sq.add(lo);
        self.bins
            .entry(key(x))
            .and_modify(|b| {
                b.count += 1;
                b.lo = b.lo.min(x);
                b.hi = b.hi.max(x);
            })
            .or_insert(Bin {
                count: 1,
                lo: x,
                hi: x,
            });
        Ok(())
    }

    /// Adds another stream's samples (the result is the same as adding them one by one,
    /// in any order).
    pub fn merge(&mut self, other: &Stream) {
        if other.n == 0 {
            return;
        }
        if self.n == 0 {
            (self.min, self.max) = (other.min, other.max);
        } else {
            self.min = self.min.min(other.min);
            self.max = self.max.max(other.max);
        }
        self.n += other.n;
        self.sum.add_sum(&other.sum);
        self.sum_sq.add_sum(&other.sum_sq);
        for (k, b) in &other.bins {
            self.bins
                .entry(*k)
                .and_modify(|a| {
                    a.count += b.count;
                    a.lo = a.lo.min(b.lo);
                    a.hi = a.hi.max(b.hi);
                })
                .or_insert(*b);
        }
    }

    /// Samples added.
    pub fn count(&self) -> u64 {
        self.n
    }

    /// Histogram bins held (the memory: about 60 bytes each).
    pub fn bins(&self) -> usize {
        self.bins.len()
    }

    /// The smallest and largest value (None before the first).
    pub fn range(&self) -> Option<(f64, f64)> {
        (self.n > 0).then_some((self.min, self.max))
    }

    /// The mean, rounded once from the exact sum (0 before the first sample).
    pub fn mean(&self) -> f64 {
        if self.n == 0 {
            0.0
        } else {
            self.sum.value() / self.n as f64
        }
    }

    /// The order statistic of rank `r` (0 = the smallest) from its bin.
    fn order_statistic(&self, r: u64) -> f64 {
        let mut below = 0u64;
        for b in self.bins.values() {
            if r < below + b.count {
                let j = r - below;
                return if j == 0 {
                    b.lo
                } else if j + 1 == b.count {
                    b.hi
                } else {
                    b.lo + (b.hi - b.lo) * (j as f64 / (b.count - 1) as f64)
                };
            }
            below += b.count;
        }
        self.max
    }

    /// The percentile `p` (0..1): linear between the order statistics at rank
    /// (n − 1)p (type 7), each read from its bin (within [`QUANTILE_RESOLUTION`]).
    pub fn percentile(&self, p: f64) -> f64 {
        if self.n == 0 {
            return f64::NAN;
        }
        let h = (self.n - 1) as f64 * p;
        let lo = h.floor() as u64;
        let hi = (lo + 1).min(self.n - 1);
        let (a, b) = (self.order_statistic(lo), self.order_statistic(hi));
        a + (h - lo as f64) * (b - a)
    }

    /// The sample variance (n − 1; 0 for one sample): Σ(x − m)² summed exactly.
    pub fn variance(&self) -> f64 {
        if self.n < 2 {
            return 0.0;
        }
        let m = self.mean();
        let n = self.n as f64;
        let mut s = self.sum_sq.clone();
        for &p in self.sum.partials() {
            let (hi, lo) = two_product(-2.0 * m, p);
            s.add(hi);
            s.add(lo);
        }
        let (a, b) = two_product(m, m);
        for part in [a, b] {
            let (hi, lo) = two_product(n, part);
            s.add(hi);
            s.add(lo);
        }
        s.value().max(0.0) / (n - 1.0)
    }

    /// The moments (at least one sample; every statistic finite).
    pub fn moments(&self, what: &str) -> Result<Moments> {
        ensure!(self.n > 0, "{what}: no samples");
        let m = Moments {
            mean: self.mean(),
            sd: self.variance().sqrt(),
            p5: self.percentile(0.05),
            p50: self.percentile(0.50),
            p95: self.percentile(0.95),
            min: self.min,
            max: self.max,
        };
        for (k, v) in [
            ("mean", m.mean),
            ("sd", m.sd),
            ("p5", m.p5),
            ("p50", m.p50),
            ("p95", m.p95),
        ] {
            ensure!(v.is_finite(), "{what}: the {k} is {v}");
        }
        Ok(m)
    }

    /// Counts over `bins` equal bins spanning the values' range (a plot's histogram),
    /// as [`Stream::counts_over`]: (lo, hi, counts).
    pub fn display_bins(&self, bins: usize) -> (f64, f64, Vec<u32>) {
        let (mut lo, mut hi) = self.range().unwrap_or((0.0, 1.0));
        if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
            let half = if hi != 0.0 { 0.01 * hi.abs() } else { 0.5 };
            (lo, hi) = (lo - half, hi + half);
        }
        (lo, hi, self.counts_over(lo, hi, bins))
    }

    /// Counts over `bins` equal bins spanning `lo..hi` (values outside fall in the end
    /// bins), each histogram bin counted where the middle of its key's interval falls
    /// (a function of the key alone): the counts of two streams of the same quantity
    /// over the same `lo..hi` add up to those of their merge, so they can be stacked.
    pub fn counts_over(&self, lo: f64, hi: f64, bins: usize) -> Vec<u32> {
        let bins = bins.max(1);
        let mut counts = vec![0u32; bins];
        for (&key, b) in &self.bins {
            let mid = grid_mid(key);
            let k = (((mid - lo) / (hi - lo)) * bins as f64).floor().max(0.0) as usize;
            if let Some(c) = counts.get_mut(k.min(bins - 1)) {
                *c = c.saturating_add(u32::try_from(b.count).unwrap_or(u32::MAX));
            }
        }
        counts
    }

    /// Checks a stream read from a file: counts, bins in order and consistent with
    /// the range, finite partials.
    pub fn check(&self, what: &str) -> Result<()> {
        let total: u64 = self.bins.values().map(|b| b.count).sum();
        ensure!(
            total == self.n,
            "{what}: the histogram counts {total} samples, the stream {}",
            self.n
        );
        for (k, b) in &self.bins {
            ensure!(
                b.count > 0 && b.lo <= b.hi && key(b.lo) == *k && key(b.hi) == *k,
                "{what}: histogram bin {k} ({} values, {} to {}) is not one a run writes",
                b.count,
                b.lo,
                b.hi
            );
        }
        if self.n > 0 {
            let first = self.bins.values().next().map(|b| b.lo);
            let last = self.bins.values().next_back().map(|b| b.hi);
            ensure!(
                first == Some(self.min) && last == Some(self.max) && self.min <= self.max,
                "{what}: the minimum {} and maximum {} disagree with the histogram",
                self.min,
                self.max
            );
        }
        for p in self.sum.partials().iter().chain(self.sum_sq.partials()) {
            ensure!(p.is_finite(), "{what}: a partial sum is {p}");
        }
        let mean = self.mean();
        let slack = 1e-9 * self.min.abs().max(self.max.abs());
        ensure!(
            self.n == 0 || (self.min - slack <= mean && mean <= self.max + slack),
            "{what}: the mean {mean} lies outside the range {} to {}",
            self.min,
            self.max
        );
        Ok(())
    }
}

/// A stream as a file holds it (`bins`: [key, count, smallest, largest]).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct StreamRepr {
    n: u64,
    sum: ExactSum,
    sum_sq: ExactSum,
    min: Option<f64>,
    max: Option<f64>,
    bins: Vec<(i64, u64, f64, f64)>,
}

impl Serialize for Stream {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        StreamRepr {
            n: self.n,
            sum: self.sum.clone(),
            sum_sq: self.sum_sq.clone(),
            min: self.range().map(|r| r.0),
            max: self.range().map(|r| r.1),
            bins: self
                .bins
                .iter()
                .map(|(k, b)| (*k, b.count, b.lo, b.hi))
                .collect(),
        }
        .serialize(s)
    }
}

impl<'de> Deserialize<'de> for Stream {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error;
        let r = StreamRepr::deserialize(d)?;
        let mut bins = BTreeMap::new();
        for (k, count, lo, hi) in r.bins {
            if bins.insert(k, Bin { count, lo, hi }).is_some() {
                return Err(D::Error::custom(format!("histogram bin {k} twice")));
            }
        }
        let (min, max) = match (r.n, r.min, r.max) {
            (0, None, None) => (0.0, 0.0),
            (n, Some(a), Some(b)) if n > 0 => (a, b),
            _ => {
                return Err(D::Error::custom(
                    "min and max must be given when n > 0, and only then",
                ))
            }
        };
        Ok(Stream {
            n: r.n,
            sum: r.sum,
            sum_sq: r.sum_sq,
            min,
            max,
            bins,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic stream of uniform numbers in [0, 1) (SplitMix64).
    fn uniform(seed: u64, n: usize) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
                let mut z = s;
                z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                z ^= z >> 31;
                (z >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect()
    }

    #[test]
    fn exact_sums_do_not_depend_on_order() {
        // 1e16 + 1 - 1e16 is 1 exactly (a naive sum gives 0 or 2 by order).
        for order in [[1e16, 1.0, -1e16], [1.0, 1e16, -1e16], [1e16, -1e16, 1.0]] {
            let mut s = ExactSum::default();
            order.iter().for_each(|&x| s.add(x));
            assert_eq!(s.value(), 1.0);
        }
        // 0.1 ten times: the exact sum of the ten doubles rounds to 1.0 (fsum's example),
        // where the naive sum is 0.9999999999999999.
        let mut s = ExactSum::default();
        (0..10).for_each(|_| s.add(0.1));
        assert_eq!(s.value(), 1.0);
        assert_ne!((0..10).map(|_| 0.1).sum::<f64>(), 1.0);
        // Half-way: 1 + 2^-53 + 2^-106 rounds up (the tail decides), 1 + 2^-53 to even.
        let e = f64::EPSILON / 2.0;
        let mut s = ExactSum::default();
        [1.0, e, e * e].iter().for_each(|&x| s.add(x));
        assert_eq!(s.value(), 1.0 + f64::EPSILON);
        let mut s = ExactSum::default();
        [1.0, e].iter().for_each(|&x| s.add(x));
        assert_eq!(s.value(), 1.0);
        // Shuffled and split: the same bits.
        let v: Vec<f64> = uniform(3, 1000)
            .iter()
            .enumerate()
            .map(|(i, u)| (u - 0.5) * 10f64.powi((i % 9) as i32 - 4))
            .collect();
        let mut whole = ExactSum::default();
        v.iter().for_each(|&x| whole.add(x));
        let mut rev = ExactSum::default();
        v.iter().rev().for_each(|&x| rev.add(x));
        let (mut a, mut b) = (ExactSum::default(), ExactSum::default());
        v.iter().step_by(2).for_each(|&x| a.add(x));
        v.iter().skip(1).step_by(2).for_each(|&x| b.add(x));
        b.add_sum(&a);
        assert_eq!(whole.value().to_bits(), rev.value().to_bits());
        assert_eq!(whole.value().to_bits(), b.value().to_bits());
    }

    #[test]
    fn moments_against_closed_forms() {
        // 1..101: mean 51, variance n(n + 1)/12 = 858.5, type-7 percentiles 6, 51, 96
        // (one value a bin: exact).
        let v: Vec<f64> = (1..=101).map(f64::from).collect();
        let m = Moments::of("x", &v).unwrap();
        assert_eq!((m.mean, m.p5, m.p50, m.p95), (51.0, 6.0, 51.0, 96.0));
        assert_eq!(m.sd, 858.5f64.sqrt());
        // A large offset: the sd of 1e9 + (1..101) is the same (no cancellation).
        let off: Vec<f64> = v.iter().map(|x| 1e9 + x).collect();
        assert_eq!(Moments::of("x", &off).unwrap().sd, 858.5f64.sqrt());
        // Constant values: sd exactly 0.
        assert_eq!(Moments::of("x", &[0.1; 7]).unwrap().sd, 0.0);
        let m = Moments::of("x", &[-0.0, 0.0]).unwrap();
        assert_eq!(m.min.to_bits(), 0.0f64.to_bits());
        assert!(Moments::of("x", &[]).is_err());
        assert!(Moments::of("x", &[1.0, f64::NAN]).is_err());
    }

    /// The type-7 percentile of sorted values.
    fn exact(sorted: &[f64], p: f64) -> f64 {
        let h = (sorted.len() - 1) as f64 * p;
        let lo = h.floor() as usize;
        let hi = (lo + 1).min(sorted.len() - 1);
        sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
    }

    #[test]
    fn percentiles_within_the_stated_resolution_of_the_order_statistics() {
        // Exponential (-ln u, over 1e-16..37) and a normal-ish sum of uniforms shifted
        // across zero, 200 000 samples each: many values a bin.
        let u = uniform(11, 200_000);
        let expo: Vec<f64> = u.iter().map(|u| -(1.0 - u).ln()).collect();
        let w = uniform(12, 600_000);
        let centred: Vec<f64> = w.chunks(3).map(|c| c.iter().sum::<f64>() - 1.2).collect();
        for (name, v) in [("exponential", expo), ("centred", centred)] {
            let mut s = Stream::default();
            v.iter().for_each(|&x| s.add(name, x).unwrap());
            let mut sorted = v.clone();
            sorted.sort_by(f64::total_cmp);
            let mut worst = 0.0f64;
            for p in [0.001, 0.05, 0.25, 0.5, 0.75, 0.95, 0.999] {
                let (got, want) = (s.percentile(p), exact(&sorted, p));
                let h = (sorted.len() - 1) as f64 * p;
                let scale = sorted[h.floor() as usize]
                    .abs()
                    .max(sorted[(h.floor() as usize + 1).min(sorted.len() - 1)].abs());
                let rel = (got - want).abs() / scale;
                assert!(rel <= QUANTILE_RESOLUTION, "{name} p{p}: {got} vs {want}");
                worst = worst.max(rel);
            }
            // The bins are not so wide that the test cannot fail: some error shows.
            assert!(worst > 0.0, "{name}");
            // Memory: bins, not samples.
            assert!(
                s.bins() < 30_000 && s.bins() < v.len() / 6,
                "{name}: {}",
                s.bins()
            );
            // The exact moments.
            let mean = v.iter().sum::<f64>() / v.len() as f64;
            assert!((s.mean() - mean).abs() <= 1e-12 * mean.abs().max(1.0));
        }
    }

    #[test]
    fn stacked_counts_add_up_to_the_whole_and_fall_in_their_bins() {
        // 0.5, 1.5, .. 99.5 over 0..100 in 10 bins: 10 a bin (each value 0.5 from an
        // edge, its key's interval 2^-10 of it wide).
        let mut s = Stream::default();
        (0..100).for_each(|i| s.add("x", f64::from(i) + 0.5).unwrap());
        assert_eq!(s.counts_over(0.0, 100.0, 10), vec![10; 10]);
        // The "jumped" part (an arbitrary third) and the rest, counted over the whole's
        // range, add up to the whole's histogram bin by bin.
        let v: Vec<f64> = uniform(9, 2000)
            .iter()
            .map(|u| -4.0 + 9.0 * u * u)
            .collect();
        let [mut whole, mut part, mut rest] = <[Stream; 3]>::default();
        for (i, &x) in v.iter().enumerate() {
            whole.add("x", x).unwrap();
            if i % 3 == 0 {
                part.add("x", x).unwrap()
            } else {
                rest.add("x", x).unwrap()
            }
        }
        let (lo, hi, all) = whole.display_bins(17);
        let (a, b) = (part.counts_over(lo, hi, 17), rest.counts_over(lo, hi, 17));
        let sum: Vec<u32> = a.iter().zip(&b).map(|(x, y)| x + y).collect();
        assert_eq!(sum, all);
        assert_eq!(a.iter().sum::<u32>(), 667);
    }

    #[test]
    fn merged_streams_equal_the_whole_bit_for_bit_and_round_trip() {
        let v: Vec<f64> = uniform(5, 3000).iter().map(|u| 3.0 + 1e-3 * u).collect();
        let whole = {
            let mut s = Stream::default();
            v.iter().for_each(|&x| s.add("x", x).unwrap());
            s
        };
        for k in [1usize, 2, 3, 7] {
            let mut parts = vec![Stream::default(); k];
            for (i, &x) in v.iter().enumerate().rev() {
                parts[i % k].add("x", x).unwrap();
            }
            let mut m = Stream::default();
            for p in parts.iter().rev() {
                let text = serde_json::to_string(p).unwrap();
                let back: Stream = serde_json::from_str(&text).unwrap();
                back.check("x").unwrap();
                m.merge(&back);
            }
            let a = serde_json::to_string(&m.moments("x").unwrap()).unwrap();
            let b = serde_json::to_string(&whole.moments("x").unwrap()).unwrap();
            assert_eq!(a, b, "{k} parts");
            assert_eq!(m.display_bins(20), whole.display_bins(20));
        }
        // An edited count does not pass the check.
        let text = serde_json::to_string(&whole)
            .unwrap()
            .replacen("\"n\":3000", "\"n\":3001", 1);
        let back: Stream = serde_json::from_str(&text).unwrap();
        assert!(back.check("x").is_err());
    }

    /// The histogram of a merge, counted over any range, is the sum of its parts'
    /// counted over the same range (the jumped/held stacking of the plots), even where
    /// a part's values sit at the edge of a display bin.
    #[test]
    fn counts_over_add_up_over_a_merge() {
        let (mut all, mut a, mut b) = (Stream::default(), Stream::default(), Stream::default());
        for i in 0..1000 {
            // Values crowding the display-bin edges of 0..10 in 10 bins.
            let x = f64::from(i % 11) + if i % 2 == 0 { 1e-4 } else { -1e-4 } - 0.0;
            all.add("x", x).unwrap();
            if i % 3 == 0 {
                a.add("x", x).unwrap()
            } else {
                b.add("x", x).unwrap()
            }
        }
        let (lo, hi, total) = all.display_bins(10);
        let (ca, cb) = (a.counts_over(lo, hi, 10), b.counts_over(lo, hi, 10));
        let sum: Vec<u32> = ca.iter().zip(&cb).map(|(x, y)| x + y).collect();
        assert_eq!(sum, total);
        assert_eq!(total.iter().sum::<u32>(), 1000);
    }

    /// A key's grid middle lies in that key's bin.
    #[test]
    fn grid_mid_is_in_its_bin() {
        for x in [0.0, 1e-300, 0.3, 1.0, 2.5, 1e5, -0.3, -1.0, -7e4] {
            assert_eq!(key(grid_mid(key(x))), key(x), "{x}");
        }
    }
}
