//! One-dimensional searches shared by the whole project, each with a bounded loop:
//! [`PeakScan`] (grid scan, then golden section) for the largest value of a function, and
//! [`OnsetSearch`] (bracketing by growth, then bisection) for where a monotone predicate
//! such as "the follower jumps at this speed" first holds.

use crate::{positive, Error, Real, Result};

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

/// What an [`OnsetSearch`] found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Onset<T> {
    /// The predicate already holds at the bracket start (this argument).
    AtStart(T),
    /// The predicate is false at `below` and holds at `at`: the onset lies in
    /// `(below, at]`, and `at − below` is at most the resolution unless no float lies
    /// between them or the bisection reached [`OnsetSearch::MAX_BISECTIONS`].
    Bracketed {
        /// Largest argument tried where the predicate is false.
        below: T,
        /// Smallest argument tried where it holds.
        at: T,
    },
    /// The predicate is false at every argument tried, the last being this one (the
    /// search's `max`).
    Beyond(T),
}

impl<T: Copy> Onset<T> {
    /// The smallest argument found where the predicate holds, if any.
    pub fn at(&self) -> Option<T> {
        match *self {
            Onset::AtStart(x) => Some(x),
            Onset::Bracketed { at, .. } => Some(at),
            Onset::Beyond(_) => None,
        }
    }
}

/// Search for the onset of a monotone predicate `holds(x)` (false below some `x*`, true
/// from it on; e.g. "the follower separates at `x` rpm"): from the bracket `start`, the
/// upper end grows by the factor `growth` (2: doubling) until the predicate holds or
/// `max` is reached (without growth, `max` is tried at once), then bisection narrows the
/// bracket to `resolution`.
///
/// Every loop is bounded: the growth stops at `max` or after [`Self::MAX_GROWTH_STEPS`];
/// the bisection stops at the resolution, when the midpoint equals an end (the floats
/// between the ends are exhausted: a resolution below the numbers' spacing still ends), or
/// after [`Self::MAX_BISECTIONS`] halvings. The predicate's errors end the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnsetSearch<T> {
    start: T,
    growth: Option<T>,
    max: T,
    resolution: T,
}

impl<T: Real> OnsetSearch<T> {
    /// Most halvings of the bracket (more than enough to exhaust any `f64` bracket between
    /// numbers within a factor 2^100 of each other).
    pub const MAX_BISECTIONS: u32 = 256;
    /// Most growth steps before the upper end jumps to `max`.
    pub const MAX_GROWTH_STEPS: u32 = 64;

    /// A search from `start` (positive, finite) up to `max` (finite, above `start`),
    /// growing the bracket by `growth` (finite, above 1) or going straight to `max`
    /// (`None`), to `resolution` (positive, finite).
    pub fn new(start: T, growth: Option<T>, max: T, resolution: T) -> Result<Self> {
        positive("start", start)?;
        positive("resolution", resolution)?;
        if !(max.is_finite() && max > start) {
            return Err(Error::InvalidParameter {
                field: "max",
                rule: "must be finite and above the bracket start",
                value: max.to_f64(),
            });
        }
        if let Some(g) = growth {
            if !(g.is_finite() && g > T::ONE) {
                return Err(Error::InvalidParameter {
                    field: "growth",
                    rule: "must be finite and above 1",
                    value: g.to_f64(),
                });
            }
        }
        Ok(Self {
            start,
            growth,
            max,
            resolution,
        })
    }

    /// The full search: tries `start`, then grows the bracket and bisects.
    pub fn find<E>(
        &self,
        mut holds: impl FnMut(T) -> core::result::Result<bool, E>,
    ) -> core::result::Result<Onset<T>, E> {
        if holds(self.start)? {
            return Ok(Onset::AtStart(self.start));
        }
        self.find_above(holds)
    }

    /// The search when the predicate is already known to be false at `start` (it is not
    /// tried again).
    pub fn find_above<E>(
        &self,
        mut holds: impl FnMut(T) -> core::result::Result<bool, E>,
    ) -> core::result::Result<Onset<T>, E> {
        let mut lo = self.start;
        let mut steps = 0;
        loop {
            let next = match self.growth {
                Some(g) if steps < Self::MAX_GROWTH_STEPS => lo * g,
                _ => self.max,
            };
            if next < self.max {
                if holds(next)? {
                    return self.bisect(lo, next, holds);
                }
                lo = next;
                steps += 1;
                continue;
            }
            // Reached (or passed, or lost to NaN) the limit: try the limit itself.
            if holds(self.max)? {
                return self.bisect(lo, self.max, holds);
            }
            return Ok(Onset::Beyond(self.max));
        }
    }

    /// Bisection of a known bracket: the predicate is false at `below` and holds at `at`
    /// (neither is tried).
    pub fn bisect<E>(
        &self,
        below: T,
        at: T,
        mut holds: impl FnMut(T) -> core::result::Result<bool, E>,
    ) -> core::result::Result<Onset<T>, E> {
        let (mut lo, mut hi) = (below, at);
        for _ in 0..Self::MAX_BISECTIONS {
            // At the resolution (or NaN): done.
            if (hi - lo).partial_cmp(&self.resolution) != Some(core::cmp::Ordering::Greater) {
                break;
            }
            let mid = (lo + hi) * T::HALF;
            // No float strictly between the ends: the bracket cannot narrow further.
            if mid <= lo || mid >= hi || mid.is_nan() {
                break;
            }
            if holds(mid)? {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Ok(Onset::Bracketed { below: lo, at: hi })
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

    /// A step at `x_star`, counting its calls.
    fn step(
        x_star: f64,
        calls: &mut u32,
    ) -> impl FnMut(f64) -> core::result::Result<bool, ()> + '_ {
        move |x| {
            *calls += 1;
            Ok(x >= x_star)
        }
    }

    #[test]
    fn onset_of_a_step_is_bracketed_to_the_resolution() {
        let s = OnsetSearch::new(50.0, Some(2.0), 20000.0, 1.0).unwrap();
        for x_star in [51.0, 99.9, 100.0, 698.4, 12345.678, 19999.5, 20000.0] {
            let mut n = 0;
            let Onset::Bracketed { below, at } = s.find(step(x_star, &mut n)).unwrap() else {
                panic!("{x_star}: not bracketed")
            };
            assert!(below < x_star && x_star <= at, "{x_star}: ({below}, {at}]");
            assert!(at - below <= 1.0, "{x_star}: width {}", at - below);
            // Doubling to the first power-of-two multiple of 50 at or above x*, then
            // halving that bracket down to the resolution.
            let mut hi: f64 = 100.0;
            let mut tries = 2; // start, 100
            while hi < x_star {
                hi = (2.0 * hi).min(20000.0);
                tries += 1;
            }
            let width = if hi >= 20000.0 && x_star > 12800.0 {
                20000.0 - 12800.0
            } else {
                hi / 2.0
            };
            tries += (width.log2()).ceil() as u32;
            assert_eq!(n, tries, "{x_star}: calls");
        }
    }

    #[test]
    fn resolution_below_the_float_spacing_ends() {
        // Near 698 the f64 spacing is 1.1e-13: a resolution of 1e-13 (or 0's neighbour)
        // cannot be met; the bisection ends when the ends are adjacent floats.
        for res in [1e-13, f64::MIN_POSITIVE] {
            let s = OnsetSearch::new(50.0, Some(2.0), 20000.0, res).unwrap();
            let mut n = 0;
            let r = s.find(step(698.4, &mut n)).unwrap();
            let Onset::Bracketed { below, at } = r else {
                panic!("{r:?}")
            };
            assert!(below < 698.4 && 698.4 <= at);
            assert_eq!(at, 698.4); // the onset itself is a float: found exactly
            assert_eq!(below, f64::from_bits(698.4f64.to_bits() - 1));
            assert!(n < 80, "{n} calls");
        }
        // f32 too.
        let s = OnsetSearch::new(50.0f32, Some(2.0), 1000.0, 1e-13).unwrap();
        let r = s.find(|x: f32| Ok::<_, ()>(x >= 697.7)).unwrap();
        let Onset::Bracketed { below, at } = r else {
            panic!("{r:?}")
        };
        assert_eq!((below.to_bits() + 1, at), (at.to_bits(), 697.7f32));
    }

    #[test]
    fn onset_outcomes_and_errors() {
        let s = OnsetSearch::new(50.0, Some(2.0), 1000.0, 1.0).unwrap();
        let mut n = 0;
        assert_eq!(s.find(step(10.0, &mut n)), Ok(Onset::AtStart(50.0)));
        assert_eq!(n, 1);
        let mut n = 0;
        // 100, 200, 400, 800, then 1000 (= max): no onset.
        assert_eq!(s.find_above(step(1e9, &mut n)), Ok(Onset::Beyond(1000.0)));
        assert_eq!(n, 5);
        // Without growth the search goes straight to max.
        let direct = OnsetSearch::new(800.0, None, 1000.0, 1.0).unwrap();
        let mut n = 0;
        let r = direct.find_above(step(900.0, &mut n)).unwrap();
        assert_eq!(r.at(), Some(900.0)); // 1000, 900 (jumps), 850, 875, ... all halvings
        assert_eq!(n, 1 + 8);
        // The predicate's error ends the search.
        let mut k = 0;
        let failing = |x: f64| {
            k += 1;
            if x > 300.0 {
                Err("diverged")
            } else {
                Ok(false)
            }
        };
        assert_eq!(s.find(failing), Err("diverged"));
        assert_eq!(k, 4); // 50, 100, 200, then 400 fails
                          // Invalid searches are refused by name.
        let field = |r: Result<OnsetSearch<f64>>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            _ => "",
        };
        assert_eq!(field(OnsetSearch::new(0.0, None, 1.0, 1.0)), "start");
        assert_eq!(field(OnsetSearch::new(1.0, None, 1.0, 1.0)), "max");
        assert_eq!(
            field(OnsetSearch::new(1.0, None, f64::INFINITY, 1.0)),
            "max"
        );
        assert_eq!(field(OnsetSearch::new(1.0, None, 2.0, 0.0)), "resolution");
        assert_eq!(field(OnsetSearch::new(1.0, Some(1.0), 2.0, 1.0)), "growth");
        assert_eq!(
            field(OnsetSearch::new(1.0, Some(f64::NAN), 2.0, 1.0)),
            "growth"
        );
    }

    #[test]
    fn tiny_growth_is_capped() {
        // Growth by 1 + 1e-15 would take ages to reach max: after MAX_GROWTH_STEPS the
        // upper end jumps to max.
        let s = OnsetSearch::new(1.0, Some(1.0 + 1e-15), 1000.0, 1.0).unwrap();
        let mut n = 0;
        let r = s.find(step(500.0, &mut n)).unwrap();
        assert!(
            matches!(r, Onset::Bracketed { below, at } if below < 500.0 && at >= 500.0 && at - below <= 1.0)
        );
        assert_eq!(n, 1 + OnsetSearch::<f64>::MAX_GROWTH_STEPS + 1 + 10);
    }
}
