//! Statistics shared by the studies: the one 95 % confidence interval of a
//! probability (`montecarlo`, `compare`, `tolerance-study`), and the streaming
//! statistics of a Monte Carlo study ([`stream`], [`study`], [`columns`]) and its
//! two-level estimate ([`two_level`]).

use serde::Serialize;

pub mod columns;
pub mod stream;
pub mod study;
pub mod two_level;

/// The standard normal quantile of 0.975 (a two-sided 95 % interval).
pub const Z95: f64 = 1.959_963_984_540_054;

/// How often something happened over `n` trials, with its 95 % Wilson score interval.
///
/// The Wilson interval (Wilson 1927) inverts the normal test of a binomial proportion:
/// unlike `p ± 1.96 √(p(1 − p)/n)` it stays inside [0, 1] and does not collapse to a
/// point at 0 of n or n of n (50 of 50 gives 0.929-1, 0 of 50 gives 0-0.071).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Probability {
    /// Trials where it happened.
    pub count: u64,
    /// Its fraction p = count / n (0 when n is 0).
    pub p: f64,
    /// Lower end of the 95 % Wilson interval.
    pub lo95: f64,
    /// Upper end of the 95 % Wilson interval.
    pub hi95: f64,
}

impl Probability {
    /// `count` of `n` (`count` is clamped to `n`; with `n = 0` nothing is known: p = 0
    /// and the interval is [0, 1]).
    pub fn of(count: u64, n: u64) -> Self {
        let count = count.min(n);
        let (lo95, hi95) = wilson95(count, n);
        Probability {
            count,
            p: if n == 0 { 0.0 } else { count as f64 / n as f64 },
            lo95,
            hi95,
        }
    }

    /// `p [lo, hi]` with `digits` decimals, as the reports print it.
    pub fn text(&self, digits: usize) -> String {
        format!(
            "{:.d$} [{:.d$}, {:.d$}]",
            self.p,
            self.lo95,
            self.hi95,
            d = digits
        )
    }
}

/// The 95 % Wilson score interval of `count` successes in `n` trials, (lo, hi) within
/// [0, 1]; exactly 0 below at `count = 0` and 1 above at `count = n`; [0, 1] for `n = 0`.
pub fn wilson95(count: u64, n: u64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let count = count.min(n);
    let nf = n as f64;
    let p = count as f64 / nf;
    let z2 = Z95 * Z95;
    let d = 1.0 + z2 / nf;
    let centre = (p + z2 / (2.0 * nf)) / d;
    let half = Z95 / d * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).sqrt();
    let lo = if count == 0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if count == n {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12
    }

    #[test]
    fn wilson_against_closed_forms_and_hand_values() {
        let z2 = Z95 * Z95;
        // n of n: [n/(n + z²), 1]; 0 of n: [0, z²/(n + z²)] (the score interval's
        // closed forms at the edges).
        assert!(close(wilson95(50, 50), (50.0 / (50.0 + z2), 1.0)));
        assert!(close(wilson95(0, 50), (0.0, z2 / (50.0 + z2))));
        // Hand-computed (Python, the textbook formula): 50/50 [0.928652, 1],
        // 0/50 [0, 0.071348], 5/50 [0.043476, 0.213602], 73/200 [0.301405, 0.433683].
        assert!(close(wilson95(50, 50), (0.9286524008666414, 1.0)));
        assert!(close(wilson95(0, 50), (0.0, 0.07134759913335872)));
        assert!(close(
            wilson95(5, 50),
            (0.04347576493189041, 0.21360231437479654)
        ));
        assert!(close(
            wilson95(73, 200),
            (0.301405264649268, 0.433682973472594)
        ));
        // Symmetry: k of n mirrors n − k of n.
        for n in [1u64, 7, 50, 1000] {
            for k in 0..=n.min(60) {
                let (a, b) = (wilson95(k, n), wilson95(n - k, n));
                assert!((a.0 - (1.0 - b.1)).abs() < 1e-12 && (a.1 - (1.0 - b.0)).abs() < 1e-12);
                let p = k as f64 / n as f64;
                assert!(a.0 <= p && p <= a.1, "{k}/{n}");
            }
        }
        // At p = 1/2 the width is z / √(n + z²): about 1/√n, 100× the trials a tenth
        // of the width as n grows.
        let w = |n: u64| {
            let (lo, hi) = wilson95(n / 2, n);
            hi - lo
        };
        for n in [2u64, 100, 10_000] {
            assert!((w(n) - Z95 / (n as f64 + z2).sqrt()).abs() < 1e-12, "{n}");
        }
        assert!((w(10_000) / w(1_000_000) - 10.0).abs() < 5e-3);
        // Nothing known from no trial.
        assert_eq!(wilson95(0, 0), (0.0, 1.0));
        let p = Probability::of(5, 50);
        assert_eq!((p.count, p.p), (5, 0.1));
        assert_eq!(p.text(3), "0.100 [0.043, 0.214]");
    }
}
