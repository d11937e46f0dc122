//! One-dimensional searches shared by the whole project, each with a bounded loop:
//! [`PeakScan`] (grid scan, then golden section) for the largest value of a function.

use crate::Real;

/// Whether a [`PeakScan`]'s refinement may leave the scanned grid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScanEnds {
    /// The grid spans a closed interval: the refinement stays between its first and last point.
    Clamped,
    /// The function is periodic and the grid covers one period: the refinement around an
    /// end point may cross it (the caller wraps the argument if it needs one in range).
    Periodic,
}

/// The largest value found by a [`PeakScan`] and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak<T> {
    /// Argument of the best value seen.
    pub at: T,
    /// The best value seen.
    pub value: T,
}

/// Maximisation of `f` over `points` grid points `start + k·step` (`k < points`), refined
/// by golden section between the best point's neighbours for at most `iterations` steps.
///
/// The best value *seen* is kept, not the bracket's end value, so a maximum at a kink,
/// a junction or a one-sided limit at a jump is never lost. The refinement stops early
/// once the bracket no longer changes (the remaining iterations would repeat the last one
/// exactly), so a generous `iterations` costs nothing at the precision's resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeakScan<T> {
    /// First grid point.
    pub start: T,
    /// Grid spacing (positive).
    pub step: T,
    /// Number of grid points.
    pub points: usize,
    /// Whether the refinement may leave the grid.
    pub ends: ScanEnds,
    /// Most golden-section steps.
    pub iterations: u32,
}

/// 1/φ = (√5 − 1)/2, the golden-section ratio.
const INV_GOLDEN: f64 = 0.618_033_988_749_894_9;

impl<T: Real> PeakScan<T> {
    /// The largest value of `f` (a pure function: called again at the same argument it
    /// must return the same value). `None` when no grid value exceeds −∞ (no points,
    /// or `f` is −∞ or NaN everywhere on the grid).
    pub fn maximize(&self, f: impl Fn(T) -> T) -> Option<Peak<T>> {
        let (mut best_x, mut best) = (self.start, -T::INFINITY);
        for k in 0..self.points {
            let x = self.start + T::from_usize(k) * self.step;
            let y = f(x);
            if y > best {
                best = y;
                best_x = x;
            }
        }
        if best == -T::INFINITY || best.is_nan() {
            return None;
        }
        let (mut a, mut b) = (best_x - self.step, best_x + self.step);
        if self.ends == ScanEnds::Clamped {
            let last = self.start + T::from_usize(self.points.saturating_sub(1)) * self.step;
            a = a.max(self.start);
            b = b.min(last);
        }
        let r = T::from_f64(INV_GOLDEN);
        for _ in 0..self.iterations {
            let (c, d) = (b - r * (b - a), a + r * (b - a));
            let (fc, fd) = (f(c), f(d));
            if fc > best {
                best = fc;
                best_x = c;
            }
            if fd > best {
                best = fd;
                best_x = d;
            }
            let (a0, b0) = (a, b);
            if fc > fd {
                b = d;
            } else {
                a = c;
            }
            if a == a0 && b == b0 {
                break;
            }
        }
        Some(Peak {
            at: best_x,
            value: best,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_scan(points: usize, iterations: u32) -> PeakScan<f64> {
        PeakScan {
            start: 0.0,
            step: 1.0 / (points - 1) as f64,
            points,
            ends: ScanEnds::Clamped,
            iterations,
        }
    }

    #[test]
    fn smooth_maximum_between_grid_points_is_refined() {
        // -(x - 0.3141)^2 + 2 has its maximum 2 at 0.3141, off the 11-point grid.
        let p = unit_scan(11, 100)
            .maximize(|x| 2.0 - (x - 0.3141) * (x - 0.3141))
            .unwrap();
        assert!((p.at - 0.3141).abs() < 1e-7, "{p:?}");
        assert!((p.value - 2.0).abs() < 1e-14);
        // Without refinement: the best grid point, 0.3, and its value.
        let g = unit_scan(11, 0)
            .maximize(|x| 2.0 - (x - 0.3141) * (x - 0.3141))
            .unwrap();
        assert_eq!(g.at, 0.30000000000000004); // 3 * 0.1
        assert!((g.value - (2.0 - 0.0141f64 * 0.0141)).abs() < 1e-15);
    }

    #[test]
    fn one_sided_limit_at_a_jump_is_approached() {
        // f = x below 0.55, -1 above: the supremum 0.55 is never attained.
        let p = unit_scan(11, 200)
            .maximize(|x| if x < 0.55 { x } else { -1.0 })
            .unwrap();
        assert!(p.value < 0.55 && p.value > 0.55 - 1e-12, "{p:?}");
    }

    #[test]
    fn clamped_stays_in_the_interval_and_periodic_may_leave_it() {
        // Increasing on [0, 1]: the maximum is the end point, never beyond it.
        let p = unit_scan(5, 100).maximize(|x| x).unwrap();
        assert_eq!((p.at, p.value), (1.0, 1.0));
        // cos(2πx) over one period with a grid offset: the peak at x = 0 is refined on
        // both sides of the grid's start, so the maximiser may be slightly negative.
        let tau = 2.0 * core::f64::consts::PI;
        let s = PeakScan {
            start: 0.0,
            step: 1.0 / 7.0,
            points: 7,
            ends: ScanEnds::Periodic,
            iterations: 100,
        };
        let p = s.maximize(|x| (tau * (x - 1e-3)).cos()).unwrap();
        assert!((p.at - 1e-3).abs() < 1e-7 && (p.value - 1.0).abs() < 1e-14);
        let q = s.maximize(|x| (tau * (x + 1e-3)).cos()).unwrap();
        assert!((q.at + 1e-3).abs() < 1e-7, "{q:?}");
    }

    #[test]
    fn nothing_to_maximise_is_none_and_never_panics() {
        assert_eq!(unit_scan(2, 10).maximize(|_| f64::NEG_INFINITY), None);
        assert_eq!(unit_scan(2, 10).maximize(|_| f64::NAN), None);
        let empty = PeakScan {
            points: 0,
            ..unit_scan(2, 10)
        };
        assert_eq!(empty.maximize(|x| x), None);
        let nan_step = PeakScan {
            step: f64::NAN,
            ..unit_scan(3, 10)
        };
        assert_eq!(nan_step.maximize(|x| x), None);
    }

    #[test]
    fn refinement_stops_once_the_bracket_is_fixed() {
        // A billion allowed steps: the bracket reaches its fixed point after a few dozen,
        // and the result is the one of a run with exactly as many steps as needed.
        let calls = core::cell::Cell::new(0u64);
        let f = |x: f64| {
            calls.set(calls.get() + 1);
            2.0 - (x - 0.3141) * (x - 0.3141)
        };
        let long = unit_scan(11, 1_000_000_000).maximize(f).unwrap();
        let used = calls.get() - 11;
        assert!(used < 400, "{used} evaluations");
        let exact = unit_scan(11, (used / 2) as u32).maximize(f).unwrap();
        assert_eq!(long, exact);
    }

    #[test]
    fn f32_scan_reaches_single_precision() {
        let s = PeakScan {
            start: 0.0f32,
            step: 0.125,
            points: 9,
            ends: ScanEnds::Clamped,
            iterations: 40,
        };
        let p = s.maximize(|x| 1.0 - (x - 0.7) * (x - 0.7)).unwrap();
        assert!(
            (p.at - 0.7).abs() < 1e-3 && (p.value - 1.0).abs() < 1e-6,
            "{p:?}"
        );
    }
}
