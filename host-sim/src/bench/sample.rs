//! What every bench run measures, the same way for every method: the load's displacement
//! and acceleration and the contact force at fixed cam angles (every 0.5° of the sampled
//! revolution), read from a continuous extension of the steps (England's own dense
//! output, or the quintic Hermite interpolant through three consecutive step ends for the
//! methods that give values and derivatives at step ends), and the right-hand-side
//! evaluations, counted at the right-hand side itself.

use std::cell::Cell;
use std::ops::ControlFlow;

use camsim_core::{CamModel, Dense, JumpWatch, OdeSystem, Real, Scene, STEADY_FROM_REVOLUTION};

/// Samples per revolution (every 0.5° of cam angle).
pub const SAMPLES_PER_REV: usize = 720;

/// A right-hand side that counts its evaluations (every method's work is counted here,
/// whatever the method's own counters say).
#[derive(Debug)]
pub struct Counted<'a, M> {
    inner: &'a M,
    evals: Cell<u64>,
}

impl<'a, M> Counted<'a, M> {
    /// Wraps `inner`, count 0.
    pub fn new(inner: &'a M) -> Self {
        Self {
            inner,
            evals: Cell::new(0),
        }
    }

    /// Evaluations so far.
    pub fn evals(&self) -> u64 {
        self.evals.get()
    }

    /// The wrapped system.
    pub fn inner(&self) -> &'a M {
        self.inner
    }
}

impl<T: Real, const N: usize, M: OdeSystem<T, N>> OdeSystem<T, N> for Counted<'_, M> {
    #[inline]
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]) {
        self.evals.set(self.evals.get() + 1);
        self.inner.rhs(t, y, dydt);
    }

    fn spectral_radius(&self, t: T, y: &[T; N]) -> Option<T> {
        self.inner.spectral_radius(t, y)
    }
}

/// The sampled quantities of one run, in `f64` whatever the run's precision.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Samples {
    /// Time of each sample, s.
    pub t: Vec<f64>,
    /// Load displacement y5 (absolute), in.
    pub disp: Vec<f64>,
    /// Load acceleration, in/s².
    pub acc: Vec<f64>,
    /// Contact force F_c, lb (0 off the cam).
    pub force: Vec<f64>,
    /// The state at each sample (kept only when asked: the reference's, for the
    /// Jacobians of the stability limit).
    pub states: Vec<Vec<f64>>,
}

impl Samples {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.disp.len()
    }

    /// No samples.
    pub fn is_empty(&self) -> bool {
        self.disp.is_empty()
    }

    /// Smallest sampled contact force, lb.
    pub fn force_min(&self) -> f64 {
        self.force.iter().copied().fold(f64::INFINITY, f64::min)
    }

    /// RMS of `a - b` over the samples both have (NaN if either is empty).
    pub fn rms_diff(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len().min(b.len());
        if n == 0 {
            return f64::NAN;
        }
        let s: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
        (s / n as f64).sqrt()
    }

    /// RMS of a signal.
    pub fn rms(a: &[f64]) -> f64 {
        if a.is_empty() {
            return f64::NAN;
        }
        (a.iter().map(|x| x * x).sum::<f64>() / a.len() as f64).sqrt()
    }
}

/// Collects [`Samples`] at the cam angles `2π (r - 1) + k · 2π/720` of revolution `r`
/// from the continuous extensions it is fed in time order, and says when a run has
/// reached its last revolution's end (`2π · revolutions`).
#[derive(Debug)]
pub struct Sampler<'m, T, S, const N: usize> {
    model: &'m CamModel<T, S, N>,
    /// First sampled angle, rad (f64: each target is rounded to `T` once).
    theta0: f64,
    /// Samples wanted (0: none).
    wanted: usize,
    next: usize,
    theta_stop: T,
    keep_states: bool,
    /// Check the contact at the nodes the caller passes to [`Sampler::watch`].
    watch_contact: bool,
    /// What was sampled.
    pub samples: Samples,
    /// The run reached `2π · revolutions`.
    pub done: bool,
    /// Start of the steady state ([`STEADY_FROM_REVOLUTION`]'s start), rad.
    theta_steady: f64,
    /// The contact at the watched nodes, for the jump rule ([`camsim_core::jump_verdict`]).
    pub jump_watch: JumpWatch<T>,
    /// A sample could not be placed (a non-finite interpolant or cam angle).
    pub bad_sample: bool,
}

impl<'m, T: Real, S: Scene, const N: usize> Sampler<'m, T, S, N> {
    /// A sampler for a run of `revolutions` revolutions that samples revolution
    /// `sampled` (None: only watches the end).
    pub fn new(model: &'m CamModel<T, S, N>, revolutions: u32, sampled: Option<u32>) -> Self {
        let two_pi = 2.0 * std::f64::consts::PI;
        let (theta0, wanted) = match sampled {
            Some(r) if r >= 1 && r <= revolutions => (two_pi * f64::from(r - 1), SAMPLES_PER_REV),
            _ => (0.0, 0),
        };
        Self {
            model,
            theta0,
            wanted,
            next: 0,
            theta_stop: T::from_f64(two_pi * f64::from(revolutions)),
            keep_states: false,
            watch_contact: false,
            samples: Samples::default(),
            done: false,
            theta_steady: two_pi * f64::from(STEADY_FROM_REVOLUTION - 1),
            jump_watch: JumpWatch::new(),
            bad_sample: false,
        }
    }

    /// Also keep the state at every sample.
    pub fn keep_states(mut self) -> Self {
        self.keep_states = true;
        self
    }

    /// Check the contact at the nodes passed to [`Sampler::watch`] (the jump search).
    pub fn watch_contact(mut self) -> Self {
        self.watch_contact = true;
        self
    }

    /// The model sampled.
    pub fn model(&self) -> &'m CamModel<T, S, N> {
        self.model
    }

    /// Target angle of sample `k`, rad.
    fn target(&self, k: usize) -> T {
        let step = 2.0 * std::f64::consts::PI / SAMPLES_PER_REV as f64;
        T::from_f64(self.theta0 + step * k as f64)
    }

    /// Every sample was taken.
    pub fn complete(&self) -> bool {
        self.next >= self.wanted
    }

    /// Checks the contact at a node of the solution (only with [`Sampler::watch_contact`]);
    /// `Break` once the follower is off the cam in the steady state
    /// ([`STEADY_FROM_REVOLUTION`] or later).
    pub fn watch(&mut self, t: T, y: &[T; N]) -> ControlFlow<()> {
        if !self.watch_contact {
            return ControlFlow::Continue(());
        }
        let p = self.model.evaluate(t, y);
        let steady = p.theta_c.to_f64() >= self.theta_steady;
        self.jump_watch.note(p.in_contact, steady, p.theta_c)
    }

    /// Takes every sample whose angle the interpolant `d` reaches (the samples before
    /// were taken from earlier interpolants); `Break` when its end reaches the last
    /// revolution's end.
    pub fn feed(&mut self, d: &Dense<'_, T, N>) -> ControlFlow<()> {
        let [y0, _, y2] = d.nodes();
        let (t0, t2) = (d.t_start(), d.t_end());
        let th0 = self.model.cam_angle(t0, y0);
        let th2 = self.model.cam_angle(t2, y2);
        if !(th0.is_finite() && th2.is_finite()) {
            self.bad_sample = true;
            return ControlFlow::Break(());
        }
        let mut y = [T::ZERO; N];
        while self.next < self.wanted {
            let target = self.target(self.next);
            if target > th2 {
                break;
            }
            let t = self.locate(d, target, th0, th2, &mut y);
            if !t.is_finite() {
                self.bad_sample = true;
                return ControlFlow::Break(());
            }
            let p = self.model.evaluate(t, &y);
            let s = &mut self.samples;
            s.t.push(t.to_f64());
            s.disp.push(p.load_displacement().to_f64());
            s.acc.push(p.load_acceleration().to_f64());
            s.force.push(p.contact_force.to_f64());
            if self.keep_states {
                s.states.push(y.iter().map(|v| v.to_f64()).collect());
            }
            self.next += 1;
        }
        if th2 >= self.theta_stop {
            self.done = true;
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// The time at which the interpolant's cam angle is `target` (Newton's method on
    /// θ_c(t) with θ̇_c from the interpolated state, from the linear guess between the
    /// interpolant's ends, kept within them); leaves the state there in `y`.
    fn locate(&self, d: &Dense<'_, T, N>, target: T, th0: T, th2: T, y: &mut [T; N]) -> T {
        let (t0, t2) = (d.t_start(), d.t_end());
        let w0 = self.model.design().omega0;
        let mut t = if th2 > th0 {
            t0 + (t2 - t0) * ((target - th0) / (th2 - th0))
        } else {
            t2
        };
        t = t.max(t0).min(t2);
        for _ in 0..16 {
            d.eval(t, y);
            let th = self.model.cam_angle(t, y);
            let w = self.model.state(y).cam_speed().unwrap_or(w0);
            if !(w > T::ZERO && th.is_finite()) {
                break;
            }
            let tn = (t + (target - th) / w).max(t0).min(t2);
            let moved = (tn - t).abs();
            t = tn;
            if moved <= T::from_f64(4.0) * T::EPSILON * t.abs() {
                break;
            }
        }
        d.eval(t, y);
        t
    }
}

/// The quintic Hermite interpolant through three consecutive step ends with their
/// derivatives ([`Dense`]) for methods without England's midpoints: fed one node
/// `(t, y, f(t, y))` at a time, it passes the interpolant over the last three nodes to a
/// [`Sampler`], which samples only the angles past the ones it has (so each angle is
/// read on the last of the three intervals that reach it, never extrapolated).
#[derive(Debug)]
pub struct NodeHermite<T, const N: usize> {
    t: [T; 3],
    y: [[T; N]; 3],
    f: [[T; N]; 3],
    count: usize,
}

impl<T: Real, const N: usize> Default for NodeHermite<T, N> {
    fn default() -> Self {
        Self {
            t: [T::ZERO; 3],
            y: [[T::ZERO; N]; 3],
            f: [[T::ZERO; N]; 3],
            count: 0,
        }
    }
}

impl<T: Real, const N: usize> NodeHermite<T, N> {
    /// Adds the node `(t, y, f)` and feeds the interpolant over the last three to
    /// `sampler` (once there are three); `Break` when the sampler is done or a node is
    /// not later than the one before.
    pub fn push<S: Scene>(
        &mut self,
        sampler: &mut Sampler<'_, T, S, N>,
        t: T,
        y: &[T; N],
        f: &[T; N],
    ) -> ControlFlow<()> {
        // Shift the window left (3 small arrays; the cost is that of one RHS at most).
        self.t = [self.t[1], self.t[2], t];
        self.y = [self.y[1], self.y[2], *y];
        self.f = [self.f[1], self.f[2], *f];
        self.count += 1;
        if sampler.watch(t, y).is_break() {
            return ControlFlow::Break(());
        }
        if self.count < 3 {
            return ControlFlow::Continue(());
        }
        let [y0, y1, y2] = &self.y;
        let [f0, f1, f2] = &self.f;
        match Dense::new(self.t, [y0, y1, y2], [f0, f1, f2]) {
            Ok(d) => sampler.feed(&d),
            Err(_) => {
                sampler.bad_sample = true;
                ControlFlow::Break(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::methods::{run, Method};
    use crate::bench::settings;
    use camsim_core::{Design, RegulatedFull, RegulatedFullModel};

    /// Every sample sits at its cam angle (the Newton iteration on the interpolant
    /// converged) and the run stops at the end of revolution 2.
    fn samples_at_their_angles(method: Method) {
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut s = Sampler::new(&m, 2, Some(2)).keep_states();
        run(method, &m, &settings(1e-6), 2, &mut s).unwrap();
        assert!(s.done && s.complete());
        assert_eq!(s.samples.len(), SAMPLES_PER_REV);
        let two_pi = 2.0 * std::f64::consts::PI;
        for (k, (t, y)) in s.samples.t.iter().zip(&s.samples.states).enumerate() {
            let y: [f64; RegulatedFull::N] = y.as_slice().try_into().unwrap();
            let theta = m.cam_angle(*t, &y);
            let target = two_pi * (1.0 + k as f64 / SAMPLES_PER_REV as f64);
            assert!(
                (theta - target).abs() < 1e-13 * target,
                "{method:?} sample {k}: {theta} against {target}"
            );
        }
        assert!(s.samples.t.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn england_dense_samples_sit_at_their_angles() {
        samples_at_their_angles(Method::England);
    }

    #[test]
    fn hermite_samples_of_rk4_and_dopri5_sit_at_their_angles() {
        samples_at_their_angles(Method::Rk4 {
            steps_per_rev: 20_000,
        });
        samples_at_their_angles(Method::Dopri5);
    }

    #[test]
    fn counted_evaluations_are_englands_own_count() {
        // England's dense output costs 9 per accepted and 7 per rejected double step
        // plus the end point's derivative (England::integrate_dense's documentation).
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut s = Sampler::new(&m, 1, None);
        let w = run(Method::England, &m, &settings(1e-4), 1, &mut s).unwrap();
        assert!(w.rejected > 0 && w.accepted > 1000, "{w:?}");
        assert_eq!(w.evals, 9 * w.accepted + 7 * w.rejected + 1);
        // RK4: 4 per step plus the first node's derivative.
        let mut s = Sampler::new(&m, 1, None);
        let w = run(
            Method::Rk4 {
                steps_per_rev: 17_000,
            },
            &m,
            &settings(1e-4),
            1,
            &mut s,
        )
        .unwrap();
        assert_eq!(w.evals, 4 * w.accepted + 1);
        assert!(w.accepted >= 17_000 && w.accepted < 17_100, "{w:?}");
    }

    #[test]
    fn two_methods_and_two_interpolants_agree_far_below_the_benchs_errors() {
        // England at rtol 1e-10 through its dense output against RK4 at 4x its fixed-step
        // limit through the node Hermite: the bench measures errors of 1e-5 to 1e1 in/s²
        // at these settings' neighbours, so both must agree to well below 1e-4.
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut a = Sampler::new(&m, 2, Some(2));
        run(Method::England, &m, &settings(1e-10), 2, &mut a).unwrap();
        let mut b = Sampler::new(&m, 2, Some(2));
        run(
            Method::Rk4 {
                steps_per_rev: 60_800,
            },
            &m,
            &settings(1e-10),
            2,
            &mut b,
        )
        .unwrap();
        let acc = Samples::rms_diff(&a.samples.acc, &b.samples.acc);
        let disp = Samples::rms_diff(&a.samples.disp, &b.samples.disp);
        assert!(acc < 5e-5, "{acc}");
        assert!(disp < 1e-12, "{disp}");
        // And the signal itself is large: 2.6e3 in/s² RMS.
        assert!(Samples::rms(&a.samples.acc) > 1e3);
    }

    #[test]
    fn watch_stops_at_a_separation_in_the_sampled_revolution() {
        // Far above the jump onset (about 902 rpm) the follower leaves the cam.
        let mut d = Design::reference();
        d.set_speed_rpm(1200.0).unwrap();
        let m = RegulatedFullModel::<f64>::new(d).unwrap();
        let mut s = Sampler::new(&m, 2, Some(2)).watch_contact();
        let _ = run(Method::England, &m, &settings(1e-6), 2, &mut s);
        assert!(s.jump_watch.separated() && s.jump_watch.steady_separation.is_some());
        // At 500 rpm it never does.
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut s = Sampler::new(&m, 2, Some(2)).watch_contact();
        run(Method::England, &m, &settings(1e-6), 2, &mut s).unwrap();
        assert!(!s.jump_watch.separated() && s.done);
    }
}
