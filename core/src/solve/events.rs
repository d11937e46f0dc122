//! Events on England's dense output ([`England::integrate_events`]): a change of side of
//! an event function located by the Illinois method on the step's continuous extension,
//! the step discarded and re-integrated to end at the event.

use core::ops::ControlFlow;

use super::england::{check_step_start, stage, Attempt};
use super::{Dense, England, OdeSystem};
use crate::{Error, Real, Result, SolverStats};

impl<T: Real, const N: usize> England<T, N> {
    /// Integrates from `t0` to `t_end` like [`England::integrate_dense`], and locates the
    /// changes of side of the event function `event` (`g > 0` against `g <= 0`) and
    /// restarts the integration there (opt-in; [`England::integrate`] and
    /// [`England::integrate_dense`] are unchanged by it).
    ///
    /// After each accepted step `g` is evaluated at its end (one evaluation of `g` per
    /// step; a pair of crossings within one step goes unseen). When the side changed,
    /// the root is located on the step's quintic Hermite extension ([`Dense`]) to within
    /// [`EventConfig::tol_t`] by the Illinois method (bisection when it stalls); the
    /// step is then discarded (its evaluations stay counted) and the solution
    /// re-integrated from the step's start to the new-side end `b` of the final
    /// bracket, so that a step ends exactly at the event and the next one starts on the
    /// new side, with the controller's history forgotten (a PI controller's previous
    /// error; a fresh stiffness estimate; the next step tries the size planned before
    /// the crossing step). The observer gets [`Report::Step`] for every accepted step
    /// (never for a discarded one) and [`Report::Event`] for each event after the step
    /// that ends at it; [`ControlFlow::Break`] stops early (still `Ok`).
    ///
    /// A rejected attempt whose auxiliary end point ŷ2 lies on the other side is
    /// treated alike (its root located on the interpolant of `y0`, `y1`, `ŷ2` with
    /// `f0`, `k5/s`, `k9/s`) and the next attempt aimed at the root, instead of letting
    /// the error test close in on a jump of `f`. An attempt that ends within `tol_t`
    /// past the event, or spans at most `2.5 tol_t` across it, is accepted whatever its
    /// error estimate (its error is the event bracket's). A crossing step whose root
    /// lies within `tol_t` of its end is kept and the event reported at its end
    /// (restarted); within `tol_t` of its start, or after 4 discards in a row from one
    /// point, it is kept and the event reported at the located time from the
    /// interpolant (not restarted). Returns the solver's counters and the event
    /// counters: `rhs_evals = 9 · accepted + 7 · rejected + 9 · discarded + 1` (plus the
    /// step control's own), the discarded steps' 9 each and the final 1 also in
    /// [`England::auxiliary_evals`]. The evaluations of `g` are counted apart
    /// ([`EventStats::event_evals`]).
    ///
    /// ```
    /// use core::ops::ControlFlow;
    /// use camsim_core::{England, EnglandConfig, EventConfig, EventFunction, OdeSystem, Report, Tolerance};
    ///
    /// // x' = 1 from x = -1: g = x changes side at t = 1.
    /// struct Ramp;
    /// impl OdeSystem<f64, 1> for Ramp {
    ///     fn rhs(&self, _t: f64, _y: &[f64; 1], dydt: &mut [f64; 1]) {
    ///         dydt[0] = 1.0;
    ///     }
    /// }
    /// impl EventFunction<f64, 1> for Ramp {
    ///     fn event(&self, _t: f64, y: &[f64; 1]) -> f64 {
    ///         y[0]
    ///     }
    /// }
    /// let mut solver = England::new(EnglandConfig {
    ///     tol: Tolerance::scalar(1e-9, 1e-12),
    ///     h_init: 0.3,
    ///     h_min: 1e-12,
    ///     h_max: 0.3,
    ///     max_steps: 1000,
    /// })?;
    /// let mut found = Vec::new();
    /// let (_, ev) = solver.integrate_events(&Ramp, &Ramp, &EventConfig::new(1e-12), 0.0, &mut [-1.0], 2.0, |r| {
    ///     if let Report::Event(e, _) = r {
    ///         found.push(e);
    ///     }
    ///     ControlFlow::Continue(())
    /// })?;
    /// assert_eq!(ev.events, 1);
    /// assert!(found[0].rising && (found[0].t - 1.0).abs() <= 1e-12);
    /// # Ok::<(), camsim_core::Error>(())
    /// ```
    #[allow(clippy::too_many_arguments)]
    pub fn integrate_events<S, E, F>(
        &mut self,
        sys: &S,
        event: &E,
        config: &EventConfig<T>,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        mut observer: F,
    ) -> Result<(SolverStats, EventStats)>
    where
        S: OdeSystem<T, N>,
        E: EventFunction<T, N>,
        F: FnMut(Report<'_, T, N>) -> ControlFlow<()>,
    {
        config.validate()?;
        self.begin(t0, y, t_end)?;
        if t_end == t0 {
            return Ok((self.stats, EventStats::default()));
        }
        stage(sys, t0, y, T::ONE, &mut self.f0, &mut self.stats.rhs_evals)?;
        let mut w = EventWalk::new(config, t0, t_end, event.event(t0, y));
        while w.t < t_end {
            let start = StepStart {
                t: w.t,
                y0: *y,
                f0: self.f0,
                h_before: self.step.step_size(),
            };
            let Some(s) = self.event_attempt(sys, event, &start, &mut w, y)? else {
                continue;
            };
            if self
                .event_step(sys, event, &start, s, &mut w, y, &mut observer)?
                .is_break()
            {
                break;
            }
        }
        Ok(self.end_events(w.ev))
    }

    /// One attempt of [`England::integrate_events`] from `start`, to the event target if
    /// one is aimed at; returns the half step of an attempt taken, `None` after a
    /// rejection (aimed at the root when `g` changed side by the attempt's end).
    fn event_attempt<S: OdeSystem<T, N>, E: EventFunction<T, N>>(
        &mut self,
        sys: &S,
        event: &E,
        start: &StepStart<T, N>,
        w: &mut EventWalk<'_, T, N>,
        y: &mut [T; N],
    ) -> Result<Option<T>> {
        let ap = &mut w.ap;
        let stop = ap.target.map_or(w.t_end, |b| b.min(w.t_end));
        // The step across the event, taken as is: the target lies within two
        // tolerances, or a rejected attempt ended within one past the event.
        let force = ap.target.is_some() && (ap.force_next || stop - start.t <= ap.force_width);
        ap.force_next = false;
        check_step_start(start.t, stop, y)?;
        let at = self.attempt(sys, start.t, y, stop, &mut w.mid.1, None)?;
        if at.err <= T::ONE || force {
            self.take(sys, &at, &mut w.t, y, &mut w.mid)?;
            return Ok(Some(at.plan.s));
        }
        self.reject(&at)?;
        let g_prev = w.g_prev;
        self.aim_at_crossing(
            event, w.config, start, &w.mid.1, &at, g_prev, &mut w.ap, &mut w.ev,
        )?;
        Ok(None)
    }

    /// After a step from `start` of half step `s` was taken: its continuous extension and
    /// `g` at its end; a step that did not cross is shown, one that crossed is discarded
    /// (`(t, y)` back at its start, aimed at the root) or kept with its event
    /// ([`England::keep_event`]).
    #[allow(clippy::too_many_arguments)]
    fn event_step<S, E, F>(
        &mut self,
        sys: &S,
        event: &E,
        start: &StepStart<T, N>,
        s: T,
        w: &mut EventWalk<'_, T, N>,
        y: &mut [T; N],
        observer: &mut F,
    ) -> Result<ControlFlow<()>>
    where
        S: OdeSystem<T, N>,
        E: EventFunction<T, N>,
        F: FnMut(Report<'_, T, N>) -> ControlFlow<()>,
    {
        for (a, k5) in w.f1.iter_mut().zip(self.k5.iter()) {
            *a = *k5 / s;
        }
        let t = w.t;
        stage(sys, t, y, T::ONE, &mut w.f2, &mut self.stats.rhs_evals)?;
        let g = event.event(t, y);
        w.ev.event_evals = w.ev.event_evals.saturating_add(1);
        let crossed = side(g) != side(w.g_prev);
        if w.ap.target.is_some_and(|b| t >= b) || crossed {
            w.ap.target = None;
        }
        let (y0, f0) = (&start.y0, &start.f0);
        let dense = Dense::new([start.t, w.mid.0, t], [y0, &w.mid.1, y], [f0, &w.f1, &w.f2])?;
        if !crossed {
            w.ap.discards = 0;
            self.f0 = w.f2;
            w.g_prev = g;
            return Ok(observer(Report::Step(&dense)));
        }
        let evals = &mut w.ev.event_evals;
        let (a, b) = locate(event, &dense, start.t, w.g_prev, t, g, w.config, evals);
        let tol_t = w.config.tol_t;
        let at_end = t - b <= tol_t;
        if !at_end && b - start.t > tol_t && w.ap.discards < MAX_DISCARDS {
            // Discard the step and re-integrate from its start to b.
            self.discard_step(start, b, &mut w.ap, &mut w.ev);
            w.t = start.t;
            *y = start.y0;
            return Ok(ControlFlow::Continue(()));
        }
        let found = Event {
            t: if at_end { t } else { b },
            bracket: b - a,
            rising: side(g),
            restarted: at_end,
        };
        if at_end {
            w.y_ev = *y;
        } else {
            dense.eval(b, &mut w.y_ev);
        }
        // The root lies at an end of the step (or the discards ran out): keep it.
        w.ap.discards = 0;
        self.f0 = w.f2;
        w.g_prev = g;
        if observer(Report::Step(&dense)).is_break() {
            return Ok(ControlFlow::Break(()));
        }
        self.keep_event(start, found, w, observer)
    }

    /// Counts and reports an event kept at the end of a step from `start`, and restarts
    /// the step-size control there.
    fn keep_event<F>(
        &mut self,
        start: &StepStart<T, N>,
        found: Event<T>,
        w: &mut EventWalk<'_, T, N>,
        observer: &mut F,
    ) -> Result<ControlFlow<()>>
    where
        F: FnMut(Report<'_, T, N>) -> ControlFlow<()>,
    {
        w.ev.events = w.ev.events.saturating_add(1);
        self.restart_after_event(w.ap.h_keep.take().unwrap_or(start.h_before));
        Ok(observer(Report::Event(found, &w.y_ev)))
    }

    /// The counters at the end of [`England::integrate_events`]: its final evaluation of
    /// `f` (for a next step that does not come) counted as auxiliary.
    fn end_events(&mut self, ev: EventStats) -> (SolverStats, EventStats) {
        self.aux_evals = self.aux_evals.saturating_add(1);
        (self.stats, ev)
    }

    /// After a rejected attempt from `start` (midpoint `y1`): did `g` change side by its
    /// auxiliary end ŷ2 (`self.arg`)? Then the rejection is probably the event's: aim the
    /// next attempt at the root, located on the interpolant of `y0`, `y1`, `ŷ2` with
    /// `f0`, `k5/s`, `k9/s`, instead of letting the error control close in on it.
    #[allow(clippy::too_many_arguments)]
    fn aim_at_crossing<E: EventFunction<T, N>>(
        &mut self,
        event: &E,
        config: &EventConfig<T>,
        start: &StepStart<T, N>,
        y1: &[T; N],
        at: &Attempt<T>,
        g_prev: T,
        ap: &mut Approach<T>,
        ev: &mut EventStats,
    ) -> Result<()> {
        let (s, t_end) = (at.plan.s, at.plan.t_end);
        let g_try = event.event(t_end, &self.arg);
        ev.event_evals = ev.event_evals.saturating_add(1);
        let crossed = side(g_try) != side(g_prev) && s > T::ZERO;
        if !crossed {
            return Ok(());
        }
        let mut f1 = [T::ZERO; N];
        let mut f2 = [T::ZERO; N];
        for (a, k5) in f1.iter_mut().zip(self.k5.iter()) {
            *a = *k5 / s;
        }
        for (a, k9) in f2.iter_mut().zip(self.k9.iter()) {
            *a = *k9 / s;
        }
        let y_try = self.arg;
        let t_start = start.t;
        let dense = Dense::new(
            [t_start, t_start + s, t_end],
            [&start.y0, y1, &y_try],
            [&start.f0, &f1, &f2],
        )?;
        let (a, mut b) = locate(
            event,
            &dense,
            t_start,
            g_prev,
            t_end,
            g_try,
            config,
            &mut ev.event_evals,
        );
        if t_end - a <= config.tol_t {
            // The attempt ends within a tolerance past the event: its error is the
            // event's (a jump in f it straddles), not the step's; retry it as is and
            // accept it.
            ap.force_next = true;
            b = t_end;
        } else if ap.target.is_some() {
            // Aimed at an estimate and rejected again: at least halve.
            b = b.min(t_start + T::HALF * (t_end - t_start));
        }
        let b = b.max(t_start + ap.two_tol);
        ap.h_keep.get_or_insert(start.h_before);
        ap.target = Some(b);
        let h = self.step.step_size().max(b - t_start);
        self.step.set_step_size(h);
        Ok(())
    }

    /// Discards an accepted step from `start` that crossed an event at `b` (its
    /// evaluations stay counted) and aims the re-integration at `b`; the caller puts
    /// `(t, y)` back at the start.
    fn discard_step(
        &mut self,
        start: &StepStart<T, N>,
        b: T,
        ap: &mut Approach<T>,
        ev: &mut EventStats,
    ) {
        ap.discards += 1;
        ev.discarded_steps = ev.discarded_steps.saturating_add(1);
        self.stats.accepted = self.stats.accepted.saturating_sub(1);
        // Its accepted attempt: k2..k9 (f0 was ready) and f at its end.
        self.aux_evals = self.aux_evals.saturating_add(9);
        self.f0 = start.f0;
        ap.h_keep.get_or_insert(start.h_before);
        self.step.set_step_size(start.h_before.max(b - start.t));
        ap.target = Some(b.max(start.t + ap.two_tol));
    }

    /// After an event: forget the controller's history (a PI controller's previous
    /// error, the stiffness estimate) and plan the next step at `h` (the size planned
    /// before the step that crossed the event).
    fn restart_after_event(&mut self, h: T) {
        self.step.restart(h, self.config.h_min, self.config.h_max);
    }
}

/// A scalar event function `g(t, y)` for [`England::integrate_events`]: an event is a
/// change of the *side* of `g` (`g > 0` against `g <= 0`), for example a contact force
/// before it is clamped at zero (positive in contact, zero or negative apart). `g` should
/// be continuous in `(t, y)`; its root is located on the step's continuous extension.
pub trait EventFunction<T, const N: usize> {
    /// The event function at `(t, y)`.
    fn event(&self, t: T, y: &[T; N]) -> T;
}

/// Settings of [`England::integrate_events`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventConfig<T> {
    /// Width of the final bracket of an event time (s): the located time is the end of a
    /// bracket `[a, b]` with `b - a <= tol_t`, `g(a)` on the old side and `g(b)` on the
    /// new side (both on the interpolant). Must be positive and finite.
    pub tol_t: T,
    /// Most evaluations of `g` per located root (Illinois steps; the bracket halves at
    /// least every third step). 0 is refused.
    pub max_iterations: u32,
}

impl<T: Real> EventConfig<T> {
    /// `tol_t`, at most 100 evaluations of `g` per event.
    pub fn new(tol_t: T) -> Self {
        Self {
            tol_t,
            max_iterations: 100,
        }
    }

    fn validate(&self) -> Result<()> {
        if !(self.tol_t.is_finite() && self.tol_t > T::ZERO) {
            return Err(Error::InvalidParameter {
                field: "tol_t",
                rule: "must be positive and finite",
                value: self.tol_t.to_f64(),
            });
        }
        if self.max_iterations == 0 {
            return Err(Error::InvalidParameter {
                field: "max_iterations",
                rule: "must be positive",
                value: 0.0,
            });
        }
        Ok(())
    }
}

/// The state of one [`England::integrate_events`] run between its steps.
struct EventWalk<'c, T, const N: usize> {
    /// The settings.
    config: &'c EventConfig<T>,
    /// End time.
    t_end: T,
    /// Time reached.
    t: T,
    /// The last attempt's midpoint.
    mid: (T, [T; N]),
    /// `g` at the time reached.
    g_prev: T,
    /// The approach to an event.
    ap: Approach<T>,
    /// Counters.
    ev: EventStats,
    /// `f` at the step's midpoint and end (for its continuous extension).
    f1: [T; N],
    f2: [T; N],
    /// The state at the last event.
    y_ev: [T; N],
}

impl<'c, T: Real, const N: usize> EventWalk<'c, T, N> {
    /// At `t0` with `g(t0, y0) = g0` (counted), no approach under way.
    fn new(config: &'c EventConfig<T>, t0: T, t_end: T, g0: T) -> Self {
        let ev = EventStats {
            event_evals: 1,
            ..EventStats::default()
        };
        Self {
            config,
            t_end,
            t: t0,
            mid: (t0, [T::ZERO; N]),
            g_prev: g0,
            ap: Approach::new(config),
            ev,
            f1: [T::ZERO; N],
            f2: [T::ZERO; N],
            y_ev: [T::ZERO; N],
        }
    }
}
/// Accepted steps discarded in a row from the same point before the next is kept with
/// its event on the interpolant: each discard re-integrates to the located root, which
/// normally ends the next step within `tol_t` of it; a root that keeps moving (an event
/// function that is discontinuous along the re-integration) would otherwise repeat the
/// step forever. Four leave room for the usual one or two.
const MAX_DISCARDS: u32 = 4;

/// Illinois steps without the bracket halving after which the root search bisects: the
/// Illinois method converges superlinearly but can stall on one end; three is the
/// [`EventConfig::max_iterations`] promise that the bracket halves at least every third
/// evaluation.
const BISECT_AFTER: u32 = 3;

/// Where an attempt of [`England::integrate_events`] starts.
struct StepStart<T, const N: usize> {
    /// Time.
    t: T,
    /// State.
    y0: [T; N],
    /// `f(t, y0)`.
    f0: [T; N],
    /// The step size planned at the start.
    h_before: T,
}

/// The state of [`England::integrate_events`]'s approach to an event, kept between
/// attempts.
struct Approach<T> {
    /// An event time being integrated to (the new-side end of a located bracket).
    target: Option<T>,
    /// The step size planned before the approach to an event began (restored after it).
    h_keep: Option<T>,
    /// Steps discarded in a row from the same point (bounded: then the step is kept).
    discards: u32,
    /// Force the next attempt (to `target`) through the error test.
    force_next: bool,
    /// Two event tolerances: the shortest step aimed at an event.
    two_tol: T,
    /// Two tolerances with room for the rounding of `t + 2 tol - t`: an attempt to the
    /// target at most this long is accepted whatever its error.
    force_width: T,
}

impl<T: Real> Approach<T> {
    /// No approach under way.
    fn new(config: &EventConfig<T>) -> Self {
        Self {
            target: None,
            h_keep: None,
            discards: 0,
            force_next: false,
            two_tol: T::TWO * config.tol_t,
            force_width: T::from_f64(2.5) * config.tol_t,
        }
    }
}

/// One located event of [`England::integrate_events`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event<T> {
    /// The located time (the new-side end of the final bracket).
    pub t: T,
    /// Width of the final bracket (s), at most [`EventConfig::tol_t`] unless the
    /// iteration budget ran out.
    pub bracket: T,
    /// `true`: `g` went from `<= 0` to `> 0` (contact made); `false`: from `> 0` to `<= 0`.
    pub rising: bool,
    /// Whether a step of the integrator ends at `t` (within `tol_t` after the root) and
    /// the next starts on the new side; `false` when the root lay within `tol_t` of the
    /// crossing step's start or the discards ran out (`t` and the state reported are
    /// then the interpolant's).
    pub restarted: bool,
}

/// Work of the event location of one [`England::integrate_events`] run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventStats {
    /// Events reported.
    pub events: u32,
    /// Evaluations of `g` (at every step end, and in the root searches).
    pub event_evals: u32,
    /// Accepted steps that crossed an event and were discarded (their evaluations are
    /// in [`SolverStats::rhs_evals`] and [`England::auxiliary_evals`], not in
    /// [`SolverStats::accepted`]).
    pub discarded_steps: u32,
}

/// What [`England::integrate_events`] passes its observer, in time order.
#[derive(Clone, Copy, Debug)]
pub enum Report<'a, T, const N: usize> {
    /// An accepted step with its continuous extension.
    Step(&'a Dense<'a, T, N>),
    /// A located event, with the state at `event.t` (the integrator's own state when
    /// `event.restarted`, else the interpolant's).
    Event(Event<T>, &'a [T; N]),
}

/// The side of an event function's value: `g > 0` (NaN counts as not).
#[inline]
fn side<T: Real>(g: T) -> bool {
    g > T::ZERO
}

/// Locates the change of side of `g` along `dense` in `[a, b]` (`ga`, `gb` on different
/// sides) by the Illinois method, falling back to bisection when it stalls; returns the
/// final bracket `(a, b)`, `b` on `gb`'s side.
#[allow(clippy::too_many_arguments)]
fn locate<T: Real, const N: usize, E: EventFunction<T, N>>(
    event: &E,
    dense: &Dense<'_, T, N>,
    mut a: T,
    mut ga: T,
    mut b: T,
    mut gb: T,
    cfg: &EventConfig<T>,
    evals: &mut u32,
) -> (T, T) {
    let side_a = side(ga);
    let mut y = [T::ZERO; N];
    // Which end was kept last (Illinois halves its g when kept twice), and how long since
    // the bracket last shrank to half.
    let mut kept: i8 = 0;
    let mut since_halving = 0u32;
    let mut width_at_halving = b - a;
    for _ in 0..cfg.max_iterations {
        let width = b - a;
        if width <= cfg.tol_t {
            break;
        }
        let mid = a + T::HALF * width;
        let mut c = if since_halving >= BISECT_AFTER {
            mid
        } else {
            // Secant through the (modified) ends.
            let denom = gb - ga;
            let c = b - gb * (width / denom);
            if c.is_finite() && c > a && c < b {
                c
            } else {
                mid
            }
        };
        // Keep c at least a fraction of tol_t inside, so a converged side moves too.
        let margin = T::from_f64(0.25) * cfg.tol_t;
        if width > T::TWO * margin {
            c = c.clamp(a + margin, b - margin);
        }
        if !(c > a && c < b) {
            break;
        }
        dense.eval(c, &mut y);
        let gc = event.event(c, &y);
        *evals = evals.saturating_add(1);
        if side(gc) == side_a {
            a = c;
            ga = gc;
            if kept == 1 {
                gb *= T::HALF;
            }
            kept = 1;
        } else {
            b = c;
            gb = gc;
            if kept == -1 {
                ga *= T::HALF;
            }
            kept = -1;
        }
        if !(ga.is_finite() && gb.is_finite()) {
            // A non-finite g: plain bisection from here.
            since_halving = BISECT_AFTER;
            ga = if side_a { T::ONE } else { -T::ONE };
            gb = -ga;
        }
        if b - a <= T::HALF * width_at_halving {
            width_at_halving = b - a;
            since_halving = 0;
        } else {
            since_halving += 1;
        }
    }
    (a, b)
}
