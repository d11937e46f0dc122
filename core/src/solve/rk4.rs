//! The classic fixed-step fourth-order Runge-Kutta method (the left column of Appendix D),
//! for comparison with England's.

use core::ops::ControlFlow;

use super::england::first_non_finite;
use super::OdeSystem;
use crate::{Error, Real, Result, SolverStats};

/// One classic fourth-order Runge-Kutta step of size `h` from `(t, y)`, in place (the
/// left column of Appendix D); 4 right-hand-side evaluations, no error control.
pub fn rk4_step<T: Real, const N: usize, S: OdeSystem<T, N>>(sys: &S, t: T, y: &mut [T; N], h: T) {
    let mut k1 = [T::ZERO; N];
    sys.rhs(t, y, &mut k1);
    rk4_step_from(sys, t, y, &k1, h);
}

/// [`rk4_step`] with its first stage `k1 = f(t, y)` given (3 evaluations): for a caller
/// that already has the derivative at the step's start (an interpolant between step ends,
/// a sampler), bit for bit the same arithmetic.
pub fn rk4_step_from<T: Real, const N: usize, S: OdeSystem<T, N>>(
    sys: &S,
    t: T,
    y: &mut [T; N],
    k1: &[T; N],
    h: T,
) {
    let half = h * T::HALF;
    let mut k = *k1;
    let mut acc = [T::ZERO; N];
    let mut arg = [T::ZERO; N];
    // acc += w k; arg = y + c k.
    let stage = |arg: &mut [T; N], acc: &mut [T; N], k: &[T; N], w: T, c: T, y: &[T; N]| {
        for (((a, s), yi), ki) in arg
            .iter_mut()
            .zip(acc.iter_mut())
            .zip(y.iter())
            .zip(k.iter())
        {
            *s += w * *ki;
            *a = *yi + c * *ki;
        }
    };
    stage(&mut arg, &mut acc, &k, T::ONE, half, y);
    sys.rhs(t + half, &arg, &mut k);
    stage(&mut arg, &mut acc, &k, T::TWO, half, y);
    sys.rhs(t + half, &arg, &mut k);
    stage(&mut arg, &mut acc, &k, T::TWO, h, y);
    sys.rhs(t + h, &arg, &mut k);
    let h6 = h * T::from_f64(1.0 / 6.0);
    for ((yi, s), ki) in y.iter_mut().zip(acc.iter()).zip(k.iter()) {
        *yi += h6 * (*s + *ki);
    }
}

/// Integrates from `t0` to `t_end` in `steps` equal classic Runge-Kutta steps, calling
/// `observer(t, &y)` at the start and after every step ([`ControlFlow::Break`] stops
/// early, still `Ok`); for comparison with [`England`](crate::England).
pub fn rk4_integrate<
    T: Real,
    const N: usize,
    S: OdeSystem<T, N>,
    F: FnMut(T, &[T; N]) -> ControlFlow<()>,
>(
    sys: &S,
    t0: T,
    y: &mut [T; N],
    t_end: T,
    steps: u32,
    mut observer: F,
) -> Result<SolverStats> {
    if !t0.is_finite() {
        return Err(Error::InvalidParameter {
            field: "t0",
            rule: "must be finite",
            value: t0.to_f64(),
        });
    }
    if !(t_end.is_finite() && t_end >= t0) {
        return Err(Error::InvalidParameter {
            field: "t_end",
            rule: "must be finite and not before t0",
            value: t_end.to_f64(),
        });
    }
    if steps == 0 {
        return Err(Error::InvalidParameter {
            field: "steps",
            rule: "must be positive",
            value: 0.0,
        });
    }
    if let Some(i) = first_non_finite(y) {
        return Err(Error::NonFinite {
            t: t0.to_f64(),
            component: i,
        });
    }
    let mut stats = SolverStats::default();
    if observer(t0, y).is_break() {
        return Ok(stats);
    }
    let span = t_end - t0;
    let n = T::from_usize(steps as usize);
    let h = span / n;
    for i in 0..steps {
        // Times from the index, not by accumulation, so the last one is exactly t_end.
        let t = t0 + span * (T::from_usize(i as usize) / n);
        rk4_step(sys, t, y, h);
        stats.accepted += 1;
        stats.rhs_evals = stats.rhs_evals.saturating_add(4);
        let t_next = if i + 1 == steps {
            t_end
        } else {
            t0 + span * (T::from_usize(i as usize + 1) / n)
        };
        if let Some(c) = first_non_finite(y) {
            return Err(Error::NonFinite {
                t: t_next.to_f64(),
                component: c,
            });
        }
        if observer(t_next, y).is_break() {
            break;
        }
    }
    Ok(stats)
}
