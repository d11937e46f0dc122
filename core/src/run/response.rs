//! Streaming outputs of a simulation: samples, per-period statistics, jumps, timing.
//!
//! Nothing is stored per sample: an [`Observer`] receives each [`Sample`] as the
//! solver produces it (the midpoint and end point of every accepted double step)
//! and accumulates what it needs. [`ResponseStats`] accumulates the thesis's
//! per-period metrics (VI.4, docs/MODEL.md §3.17): RMS deviation of the follower output from
//! the theoretical response, average and extreme torque, contact force and stress,
//! AORD of each angular velocity, and jump intervals. Time averages are
//! time-weighted (trapezoidal), so they do not depend on where the solver stepped.

use core::ops::ControlFlow;

use crate::run::method::{Method, RunSolver};
use crate::solve::england::Sampler;
use crate::{
    CamModel, EnglandConfig, Error, LiftProfile, ModelPoint, Real, Result, Scene, SegmentKind,
    SimFailure, SolverStats, StateMut, StateVar, StepRule, Tolerance, TransDof, TRANS_DOFS,
};

/// The theoretical response at a cam angle (VI.4, docs/MODEL.md §3.17: perfect profile, rigid system,
/// constant cam speed ω0): y = s(θ), v = s' ω0, a = s'' ω0².
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Theoretical<T> {
    /// Displacement, in.
    pub y: T,
    /// Velocity, in/s.
    pub v: T,
    /// Acceleration, in/s².
    pub a: T,
}

impl<T: Real> Theoretical<T> {
    /// The theoretical response for the commanded lift `l` at constant speed `w` (rad/s).
    pub fn of(l: &crate::FollowerLift<T>, w: T) -> Self {
        Theoretical {
            y: l.y,
            v: l.dy * w,
            a: l.d2y * w * w,
        }
    }
}

/// One output sample of a running simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample<T> {
    /// Every model quantity at this instant.
    pub point: ModelPoint<T>,
    /// Revolution, counted from 1.
    pub revolution: u32,
    /// Cam angle within the revolution, degrees in [0, 360).
    pub angle_deg: T,
    /// Index of the program segment (period) the cam angle is in.
    pub segment: usize,
    /// The theoretical response at this cam angle.
    pub theory: Theoretical<T>,
    /// Maximum Hertz contact stress, psi (0 when the observer does not need it or off contact).
    pub contact_stress: T,
}

/// How many numbers [`Sample::numbers`] gives.
pub const SAMPLE_NUMBERS: usize = 27 + 3 * TRANS_DOFS;

impl<T: Real> Sample<T> {
    /// Every number of the sample, in a fixed order, for checks that each one is finite:
    /// the point's scalars, the cam angle, the theoretical response, the contact stress,
    /// then the positions, velocities and accelerations. A surface radius of curvature
    /// of +inf, the documented value where the pitch curve is straight (an inflection of
    /// the profile; `CamGeometry::pitch_curvature_radius`), is given as 0.
    pub fn numbers(&self) -> [T; SAMPLE_NUMBERS] {
        let p = &self.point;
        let mut v = [T::ZERO; SAMPLE_NUMBERS];
        let scalars = [
            p.t,
            p.theta_c,
            p.theta_cp,
            p.theta_m,
            p.omega_c,
            p.omega_cp,
            p.omega_m,
            p.alpha_c,
            p.alpha_cp,
            p.alpha_m,
            p.lift.y,
            p.lift.dy,
            p.lift.d2y,
            p.lift.d3y,
            p.pressure_angle,
            p.k_h,
            if p.surface_radius == T::INFINITY {
                T::ZERO
            } else {
                p.surface_radius
            },
            p.contact_force,
            p.friction_follower,
            p.friction_cantilever,
            p.torque_out,
            p.torque_drive,
            self.angle_deg,
            self.theory.y,
            self.theory.v,
            self.theory.a,
            self.contact_stress,
        ];
        let all = scalars.iter().chain(&p.pos).chain(&p.vel).chain(&p.acc);
        for (slot, x) in v.iter_mut().zip(all) {
            *slot = *x;
        }
        v
    }
}

/// Receives each sample of a simulation.
pub trait Observer<T> {
    /// Whether this observer needs the Hertz contact stress (it costs a square root or two).
    fn needs_stress(&self) -> bool {
        true
    }
    /// Whether this observer reads the figures only outputs carry: the pressure angle and
    /// the surface radius of the point ([`ModelPoint::pressure_angle`],
    /// [`ModelPoint::surface_radius`]) and the theoretical response ([`Sample::theory`]).
    /// `false` lets [`simulate`] skip them (an `atan2`, the curvature and the motion law's
    /// closed form a sample): they are then 0 (the surface radius too where the lift is
    /// tabulated, docs/MODEL.md §3.21). Every other figure is the same either way.
    fn needs_outputs(&self) -> bool {
        true
    }
    /// Takes one sample; `Break` stops the simulation early.
    fn observe(&mut self, sample: &Sample<T>) -> ControlFlow<()>;
    /// Takes one sample at a point of a cam-angle grid ([`crate::simulate_on_grid`]), in
    /// time order with the solver's samples; `kind` tells what the point is. Ignored
    /// unless an observer overrides it.
    fn observe_grid(&mut self, sample: &Sample<T>, kind: GridPointKind) -> ControlFlow<()> {
        let _ = (sample, kind);
        ControlFlow::Continue(())
    }
}

/// What a point of a cam-angle grid is ([`Observer::observe_grid`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GridPointKind {
    /// A multiple of the grid's step (not a segment start).
    Step,
    /// The start of a program segment (a period; also a multiple of the step if the
    /// grid has one there): the sample ends the previous period and starts this one.
    SegmentStart,
    /// The end of the run (the last revolution's 360°): it closes the last period.
    End,
}

impl<T, F: FnMut(&Sample<T>) -> ControlFlow<()>> Observer<T> for F {
    fn observe(&mut self, sample: &Sample<T>) -> ControlFlow<()> {
        self(sample)
    }
}

/// Two observers fed from one simulation.
pub struct Both<'a, A, B>(pub &'a mut A, pub &'a mut B);

impl<T, A: Observer<T>, B: Observer<T>> Observer<T> for Both<'_, A, B> {
    fn needs_stress(&self) -> bool {
        self.0.needs_stress() || self.1.needs_stress()
    }
    fn needs_outputs(&self) -> bool {
        self.0.needs_outputs() || self.1.needs_outputs()
    }
    fn observe(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        let a = self.0.observe(s);
        let b = self.1.observe(s);
        if a.is_break() || b.is_break() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
    fn observe_grid(&mut self, s: &Sample<T>, kind: GridPointKind) -> ControlFlow<()> {
        let a = self.0.observe_grid(s, kind);
        let b = self.1.observe_grid(s, kind);
        if a.is_break() || b.is_break() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

/// Solver settings of a run: relative tolerance and an absolute tolerance in inches
/// that is scaled to every state component (see [`solver_config`]).
///
/// Scene keys (`[solver]`, [`crate::key::SOLVER_KEYS`]): `rtol`, `atol_in`,
/// `max_step_fraction_rev`, `max_steps_per_rev`, `start`, `step_control`; absent keys take
/// [`SolverSettings::reference`]'s values.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        deny_unknown_fields,
        default,
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct SolverSettings<T> {
    /// Relative tolerance.
    pub rtol: T,
    /// Absolute tolerance for displacements, in.
    #[cfg_attr(feature = "serde", serde(rename = "atol_in"))]
    pub atol: T,
    /// Largest double step as a fraction of one revolution at ω0 (keeps samples dense for
    /// statistics and plots).
    #[cfg_attr(feature = "serde", serde(rename = "max_step_fraction_rev"))]
    pub max_step_fraction: T,
    /// Step budget per revolution.
    pub max_steps_per_rev: u32,
    /// Where the simulation starts.
    pub start: Start,
    /// How England's method controls its step ([`StepRule`]; scene key `step_control`):
    /// the tolerance-scaled stiffness cap by default, `"thesis"` for the thesis's rule.
    /// Merson's pair is capped by the same rules but `"thesis"`.
    pub step_control: StepRule,
    /// The integration method ([`Method`]; scene key `method`).
    pub method: Method,
}

/// The initial state of a simulation (scene names `"thesis"`, `"static"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum Start {
    /// The thesis's (VI.1): every speed at ω0, everything else zero. The preload then acts
    /// on an unloaded chain, and the first revolution carries that start-up transient.
    #[default]
    Thesis,
    /// Static equilibrium on the base circle with the shafts twisted by the steady drag
    /// ([`CamModel::static_state`]).
    Static,
}

impl<T: Real> SolverSettings<T> {
    /// Defaults: rtol 1e-6, atol 1e-8 in, at most 1/2000 revolution per double step (1/4000
    /// per single step), [`Method::Auto`] (Merson's pair at this rtol: at equal
    /// acceleration error it needs 0.68×, 0.74× and 0.78× England's evaluations at rtol
    /// 1e-4, 1e-5 and 1e-6, docs/MODEL.md §3.16; England's method below 1e-6) with the
    /// tolerance-scaled stiffness cap ([`StepRule::ScaledCap`]).
    pub fn reference() -> Self {
        Self {
            rtol: T::from_f64(1e-6),
            atol: T::from_f64(1e-8),
            max_step_fraction: T::from_f64(1.0 / 2000.0),
            max_steps_per_rev: 2_000_000,
            start: Start::Thesis,
            step_control: StepRule::ScaledCap,
            method: Method::Auto,
        }
    }

    /// Checks the settings; errors name the scene key relative to `[solver]`
    /// ([`crate::key::RTOL`], ...): `rtol`, `atol_in` and `max_step_fraction_rev` positive
    /// and finite, then each within its plausibility range ([`crate::key::RANGES`],
    /// docs/MODEL.md §5.16: `rtol` 1e-13 to 0.1, `atol_in` 1e-15 to 1e-3 in,
    /// `max_step_fraction_rev` 1e-6 to 0.25, `max_steps_per_rev` 1 to 1e7).
    pub fn validate(&self) -> Result<()> {
        use crate::key;
        crate::positive(key::RTOL, self.rtol)?;
        crate::positive(key::ATOL, self.atol)?;
        crate::positive(key::MAX_STEP_FRACTION, self.max_step_fraction)?;
        key::RTOL_RANGE.check(key::RTOL, self.rtol)?;
        key::ATOL_RANGE.check(key::ATOL, self.atol)?;
        key::STEP_FRACTION.check(key::MAX_STEP_FRACTION, self.max_step_fraction)?;
        // A count: compared as an integer (the range's bounds are whole numbers).
        const MIN_STEPS: u32 = key::STEPS_PER_REV.min as u32;
        const MAX_STEPS: u32 = key::STEPS_PER_REV.max as u32;
        if !(MIN_STEPS..=MAX_STEPS).contains(&self.max_steps_per_rev) {
            return Err(crate::Error::InvalidParameter {
                field: key::MAX_STEPS_PER_REV,
                rule: key::STEPS_PER_REV.rule,
                value: f64::from(self.max_steps_per_rev),
            });
        }
        Ok(())
    }
}

impl<T: Real> Default for SolverSettings<T> {
    /// [`SolverSettings::reference`].
    fn default() -> Self {
        Self::reference()
    }
}

/// England solver configuration for a model. The scalar `atol` (inches) is mapped to
/// each component by its natural scale: angles and twists are compared as arc length at
/// the prime radius R_a (atol / R_a rad), velocities as displacement per radian of cam at
/// ω0 (atol ω0 / R_a rad/s, atol ω0 in/s).
pub fn solver_config<T: Real, S: Scene, const N: usize, P: LiftProfile<T>>(
    model: &CamModel<T, S, N, P>,
    s: &SolverSettings<T>,
    revolutions: u32,
) -> Result<EnglandConfig<T, N>> {
    crate::positive(crate::key::RTOL, s.rtol)?;
    crate::positive(crate::key::ATOL, s.atol)?;
    crate::positive(crate::key::MAX_STEP_FRACTION, s.max_step_fraction)?;
    let d = model.design();
    let w0 = d.omega0;
    let ra = d.geometry.prime_radius();
    let mut atol = [s.atol; N];
    let mut scaled = StateMut::<T, S, N>::new(&mut atol);
    for var in StateVar::ROTATIONAL {
        let a = match var {
            StateVar::CamAngle | StateVar::CouplingCamTwist | StateVar::MotorCouplingTwist => {
                s.atol / ra
            }
            _ => s.atol * w0 / ra,
        };
        scaled.set(var, a);
    }
    for dof in TransDof::ALL {
        scaled.set(StateVar::Position(dof), s.atol);
        scaled.set(StateVar::Velocity(dof), s.atol * w0);
    }
    let period = T::TWO * T::PI / w0;
    let h_max = period * s.max_step_fraction;
    Ok(EnglandConfig {
        tol: Tolerance::per_component(s.rtol, atol),
        h_init: h_max * T::from_f64(1e-3),
        h_min: period * T::from_f64(1e-13),
        h_max,
        max_steps: s.max_steps_per_rev.saturating_mul(revolutions.max(1)),
    })
}

/// Simulates `revolutions` cam revolutions from the initial state `settings.start` selects
/// (the thesis's VI.1 start or static equilibrium, docs/MODEL.md §5.11), feeding every
/// sample to `observer`. Returns the solver's statistics.
///
/// Every sample (the midpoint and the end of each accepted step) is checked against the
/// model's validity bounds first ([`CamModel::check_validity`], docs/MODEL.md §3.20): a
/// state outside them ends the run with [`Error::OutOfModel`] (the observer has seen
/// every sample before it). The solver's failures come back as
/// [`Error::SimulationFailed`] with the cam angle of the last accepted sample and the
/// quantity (not the state index) that became non-finite, or the scene key that raises
/// the step budget.
pub fn simulate<T: Real, S: Scene, const N: usize, P: LiftProfile<T>, O: Observer<T>>(
    model: &CamModel<T, S, N, P>,
    settings: &SolverSettings<T>,
    revolutions: u32,
    observer: &mut O,
) -> Result<SolverStats> {
    let RunStart {
        mut solver,
        mut run,
        t_end,
        mut y,
    } = RunState::start(model, settings, revolutions)?;
    // Each sample is formed from one of the solver's own evaluations of the model.
    let mut sampler = RunSampler {
        model,
        observer,
        run: &mut run,
        sample: Sample::default(),
        flags: (false, false),
    };
    let result = solver.integrate_shared(model, T::ZERO, &mut y, t_end, &mut sampler);
    run.finish(model, settings, result)
}

/// [`simulate`]'s samples from the solver's own evaluations of the model
/// ([`England::integrate_shared`](crate::England::integrate_shared)): the last point evaluated, with the outputs the observer
/// asked for.
struct RunSampler<'a, T: Real, S: Scene, const N: usize, P: LiftProfile<T>, O> {
    model: &'a CamModel<T, S, N, P>,
    observer: &'a mut O,
    run: &'a mut RunState<T>,
    /// The point last evaluated, in the sample [`Sampler::show`] completes in place (a
    /// model point is some 200 bytes; copying it into a new sample for each one shown
    /// cost the chip about 90 000 instructions a revolution).
    sample: Sample<T>,
    /// The observer's `(needs_stress, needs_outputs)` when it was evaluated.
    flags: (bool, bool),
}

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>, O: Observer<T>> Sampler<T, N>
    for RunSampler<'_, T, S, N, P, O>
{
    fn evaluate(&mut self, t: T, y: &[T; N], f: &mut [T; N]) {
        let (stress, outputs) = (self.observer.needs_stress(), self.observer.needs_outputs());
        self.flags = (stress, outputs);
        // The outputs only add to the point: the derivative is the right-hand side's.
        self.sample.point = self.model.evaluate_with(t, y, outputs || stress);
        self.model.derivative(&self.sample.point, f);
    }

    fn show(&mut self) -> ControlFlow<()> {
        let (stress, outputs) = self.flags;
        self.model
            .complete_sample(&mut self.sample, stress, outputs);
        self.run
            .take_sample(self.model, self.observer, &self.sample)
    }
}

/// What [`simulate`] and [`simulate_events`] share: the setup of a run, what each sample
/// passes through (the validity check, the end of the run, the observer) and how the
/// solver's failures are told.
pub(crate) struct RunState<T> {
    /// The cam angle that ends the run, rad.
    target: T,
    /// The run reached `target`.
    done: bool,
    /// The observer stopped the run.
    stopped: bool,
    /// Where the last accepted sample was (revolution, degrees, time), for the errors.
    last: (u32, T, T),
    /// The model left its valid range (docs/MODEL.md §3.20).
    left: Option<Error>,
}

/// What [`RunState::start`] sets up for a run.
pub(crate) struct RunStart<T, const N: usize> {
    /// The solver, configured from the settings.
    pub(crate) solver: RunSolver<T, N>,
    /// The run's state.
    pub(crate) run: RunState<T>,
    /// The end time: generous (four times the nominal), a stalled drive is an error.
    pub(crate) t_end: T,
    /// The initial state.
    pub(crate) y: [T; N],
}

impl<T: Real> RunState<T> {
    /// The solver, the run's state, the end time and the initial state of a run of
    /// `revolutions` revolutions.
    pub(crate) fn start<S: Scene, const N: usize, P: LiftProfile<T>>(
        model: &CamModel<T, S, N, P>,
        settings: &SolverSettings<T>,
        revolutions: u32,
    ) -> Result<RunStart<T, N>> {
        if revolutions == 0 {
            return Err(Error::InvalidParameter {
                field: "revolutions",
                rule: "must be at least 1",
                value: 0.0,
            });
        }
        let config = solver_config(model, settings, revolutions)?;
        // The solver's own names for what the settings derive (h_max, h_init, max_steps) are
        // not scene keys: name the key that sets each (unreachable with validated settings).
        let solver = RunSolver::new(settings.method, settings.step_control, config).map_err(
            |e| match e {
                Error::InvalidParameter { field, rule, value } => Error::InvalidParameter {
                    field: match field {
                        "max_steps" => crate::key::MAX_STEPS_PER_REV,
                        "rtol" => crate::key::RTOL,
                        "atol" => crate::key::ATOL,
                        _ => crate::key::MAX_STEP_FRACTION,
                    },
                    rule,
                    value,
                },
                other => other,
            },
        )?;
        let d = model.design();
        let target = T::TWO * T::PI * T::from_usize(revolutions as usize);
        // Generous end time: the drive may run slower than ω0; a stalled drive is an error.
        let t_end = T::from_f64(4.0) * target / d.omega0;
        let y = match settings.start {
            Start::Thesis => model.initial_state(),
            Start::Static => model.static_state(),
        };
        let run = RunState {
            target,
            done: false,
            stopped: false,
            last: (1, T::ZERO, T::ZERO),
            left: None,
        };
        Ok(RunStart {
            solver,
            run,
            t_end,
            y,
        })
    }

    /// One accepted sample at (t, y): checked against the model's validity bounds, then
    /// the end of the run, then the observer.
    pub(crate) fn take<S: Scene, const N: usize, P: LiftProfile<T>, O: Observer<T>>(
        &mut self,
        model: &CamModel<T, S, N, P>,
        observer: &mut O,
        t: T,
        y: &[T; N],
    ) -> ControlFlow<()> {
        let sample = model.sample_with(t, y, observer.needs_stress(), observer.needs_outputs());
        self.take_sample(model, observer, &sample)
    }

    /// [`RunState::take`] of a sample already formed (`model.sample_with(t, y, stress,
    /// outputs)` with the stress and outputs as the observer needs them).
    pub(crate) fn take_sample<S: Scene, const N: usize, P: LiftProfile<T>, O: Observer<T>>(
        &mut self,
        model: &CamModel<T, S, N, P>,
        observer: &mut O,
        sample: &Sample<T>,
    ) -> ControlFlow<()> {
        let t = sample.point.t;
        if let Err((limit, value, bound)) = model.check_validity(&sample.point) {
            self.left = Some(Error::OutOfModel {
                limit,
                value: value.to_f64(),
                bound: bound.to_f64(),
                revolution: sample.revolution,
                cam_deg: sample.angle_deg.to_f64(),
            });
            return ControlFlow::Break(());
        }
        self.last = (sample.revolution, sample.angle_deg, t);
        if sample.point.theta_c >= self.target {
            self.done = true;
            return ControlFlow::Break(());
        }
        let flow = observer.observe(sample);
        self.stopped = flow.is_break();
        flow
    }

    /// The cam angle that ends the run, rad.
    pub(crate) fn target(&self) -> T {
        self.target
    }

    /// An observer outside [`RunState::take`] stopped the run.
    pub(crate) fn stop(&mut self) {
        self.stopped = true;
    }

    /// The run's result: the solver's (`result`) unless the model left its range, with
    /// the solver's failures told by the cam angle of the last accepted sample and the
    /// quantity or scene key concerned; a run that neither reached its end nor was
    /// stopped has stalled.
    pub(crate) fn finish<S: Scene, const N: usize, P: LiftProfile<T>, R>(
        self,
        model: &CamModel<T, S, N, P>,
        settings: &SolverSettings<T>,
        result: Result<R>,
    ) -> Result<R> {
        if let Some(e) = self.left {
            return Err(e);
        }
        let (revolution, cam_deg, t_last) =
            (self.last.0, self.last.1.to_f64(), self.last.2.to_f64());
        let failed = |failure| Error::SimulationFailed {
            failure,
            revolution,
            cam_deg,
            t: t_last,
        };
        let out = result.map_err(|e| match e {
            Error::StepSizeUnderflow { h, .. } => failed(SimFailure::StepSizeUnderflow { h }),
            Error::NonFinite { component, .. } => failed(SimFailure::NonFinite {
                quantity: model.state_quantity(component),
            }),
            Error::StepBudgetExceeded { steps, .. } => failed(SimFailure::StepBudget {
                steps,
                per_revolution: settings.max_steps_per_rev,
            }),
            other => other,
        })?;
        if !self.done && !self.stopped {
            return Err(failed(SimFailure::Stalled));
        }
        Ok(out)
    }
}

/// The contact event function of a model (for [`England::integrate_events`](crate::England::integrate_events)): the
/// contact force before its clamp at zero, per unit cos φ,
/// `g = min(e, e + C_h · rate)` with `e = K_h (y + y1 - y2) + F_p` the elastic part and
/// `rate` the rate of approach (Eqs. V.19-V.20 with the contact damping of
/// docs/MODEL.md §3.9, [`crate::damped_contact_force`]). It is continuous, and `g > 0`
/// exactly when the model's [`ModelPoint::in_contact`] holds (up to rounding in the
/// approach, which the model forms as `y1 - q2`): the elastic part positive and the
/// damped force not pulling. One evaluation costs one [`CamModel::evaluate`].
#[derive(Clone, Copy, Debug)]
pub struct ContactEventFn<'a, T, S, const N: usize, P>(pub &'a CamModel<T, S, N, P>);

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>> ContactEventFn<'_, T, S, N, P> {
    /// `g` from an evaluated point of the model.
    pub fn of_point(&self, p: &ModelPoint<T>) -> T {
        let model = self.0;
        let approach = p.lift.y + p.position(TransDof::CamY) - p.position(TransDof::RollerY);
        let rate =
            p.lift.dy * p.omega_c + p.velocity(TransDof::CamY) - p.velocity(TransDof::RollerY);
        let e = p.k_h * approach + model.preload();
        let c_h = model.contact_damping(p.k_h);
        if c_h == T::ZERO {
            e
        } else {
            e.min(e + c_h * rate)
        }
    }
}

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>> crate::EventFunction<T, N>
    for ContactEventFn<'_, T, S, N, P>
{
    fn event(&self, t: T, y: &[T; N]) -> T {
        self.of_point(&self.0.evaluate(t, y))
    }
}

/// Contact-event location for [`simulate_events`] (opt-in; [`simulate`] never locates
/// events).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEventSettings<T> {
    /// Width of the final bracket of an event time, as a fraction of one revolution at
    /// ω0 (1e-9: 0.12 ns at 500 rpm).
    pub tol_fraction_rev: T,
}

impl<T: Real> Default for ContactEventSettings<T> {
    fn default() -> Self {
        Self {
            tol_fraction_rev: T::from_f64(1e-9),
        }
    }
}

/// A contact event of [`simulate_events`]: the follower leaves the cam
/// (`separation`) or comes back (recontact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent<T> {
    /// The located event ([`crate::Event`]: time, bracket, whether a step ends there).
    pub event: crate::Event<T>,
    /// True when contact is lost, false at recontact.
    pub separation: bool,
    /// The sample at the event (from the integrator's state there).
    pub sample: Sample<T>,
}

/// [`simulate`] with contact events located and the integration restarted at each
/// ([`England::integrate_events`](crate::England::integrate_events) with [`ContactEventFn`]): the observer receives the
/// midpoint and end of every accepted step (a restarted event's time is a step end)
/// and `on_event` each located contact loss and recontact. Validity checks, end of run
/// and errors as [`simulate`]. Returns the solver's and the event location's counters
/// (the evaluations of the event function, one model evaluation each, are in
/// [`crate::EventStats::event_evals`], not in [`SolverStats::rhs_evals`]).
pub fn simulate_events<T, S, const N: usize, P, O, E>(
    model: &CamModel<T, S, N, P>,
    settings: &SolverSettings<T>,
    events: &ContactEventSettings<T>,
    revolutions: u32,
    observer: &mut O,
    mut on_event: E,
) -> Result<(SolverStats, crate::EventStats)>
where
    T: Real,
    S: Scene,
    P: LiftProfile<T>,
    O: Observer<T>,
    E: FnMut(&ContactEvent<T>),
{
    // Event location runs on England's dense output, whatever the settings' method.
    let settings = &SolverSettings {
        method: Method::England,
        ..*settings
    };
    let RunStart {
        mut solver,
        mut run,
        t_end,
        mut y,
    } = RunState::start(model, settings, revolutions)?;
    let d = model.design();
    let ev_config = crate::EventConfig::new(events.tol_fraction_rev * T::TWO * T::PI / d.omega0);
    let gfn = ContactEventFn(model);
    // The start sample, as `simulate`'s observer sees it.
    let result =
        if run.take(model, observer, T::ZERO, &y).is_break() {
            Ok((solver.stats(), crate::EventStats::default()))
        } else {
            let stress = observer.needs_stress();
            solver.england()?.integrate_events(
                model,
                &gfn,
                &ev_config,
                T::ZERO,
                &mut y,
                t_end,
                |r| match r {
                    crate::Report::Step(dense) => {
                        let [_, y1, y2] = dense.nodes();
                        if run.take(model, observer, dense.t_mid(), y1).is_break() {
                            return ControlFlow::Break(());
                        }
                        run.take(model, observer, dense.t_end(), y2)
                    }
                    crate::Report::Event(event, y) => {
                        on_event(&ContactEvent {
                            event,
                            separation: !event.rising,
                            sample: model.sample(event.t, y, stress),
                        });
                        ControlFlow::Continue(())
                    }
                },
            )
        };
    run.finish(model, settings, result)
}

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>> CamModel<T, S, N, P> {
    /// The theoretical response at cam angle `theta` (rad) at the design's ω0.
    pub fn theoretical(&self, theta: T) -> Theoretical<T> {
        let w = self.design().omega0;
        Theoretical::of(&self.design().program.follower(theta), w)
    }

    /// A full output sample at (t, y); `stress` computes the Hertz contact stress.
    pub fn sample(&self, t: T, y: &[T; N], stress: bool) -> Sample<T> {
        self.sample_with(t, y, stress, true)
    }

    /// [`Self::sample`]; `outputs = false` (and no stress) skips what only some observers
    /// read ([`Observer::needs_outputs`]): the pressure angle, the surface radius where the
    /// lift is tabulated, and the theoretical response, left at 0.
    pub fn sample_with(&self, t: T, y: &[T; N], stress: bool, outputs: bool) -> Sample<T> {
        self.sample_of(self.evaluate_with(t, y, outputs || stress), stress, outputs)
    }

    /// [`Self::sample_with`] of the point `p` already evaluated (with the outputs if
    /// `outputs || stress`).
    pub(crate) fn sample_of(&self, p: ModelPoint<T>, stress: bool, outputs: bool) -> Sample<T> {
        let mut sample = Sample {
            point: p,
            ..Sample::default()
        };
        self.complete_sample(&mut sample, stress, outputs);
        sample
    }

    /// [`Self::sample_of`] in place: the sample's fields beside its point (evaluated with
    /// the outputs if `outputs || stress`) from that point; the run's sampler keeps one
    /// sample and fills it without copying the point.
    pub(crate) fn complete_sample(&self, sample: &mut Sample<T>, stress: bool, outputs: bool) {
        let p = &sample.point;
        let outputs = outputs || stress;
        let d = self.design();
        let two_pi = T::TWO * T::PI;
        let turns = (p.theta_c / two_pi).floor();
        let within = p.theta_c - turns * two_pi;
        // The casts saturate (at u32::MAX, and NaN to 0) and so does the count, so a cam
        // angle beyond 2^32 turns (an absurd state) reads as the last revolution. `turns`
        // is a whole number: truncating it in `T` is the cast through `f64` without
        // software `f64` on the chip.
        let revolution = if turns >= T::ZERO {
            u32::try_from(turns.to_usize_trunc())
                .unwrap_or(u32::MAX)
                .saturating_add(1)
        } else {
            0
        };
        let w = d.omega0;
        // The perfect cam's response (VI.4), not the lift the roller rides on: on an
        // actual cam the deviation from it includes the profile's own error.
        let theory = if outputs {
            Theoretical::of(&d.program.follower(p.theta_c), w)
        } else {
            Theoretical::default()
        };
        let contact_stress = if stress && p.in_contact {
            // Roller diameter and the signed diameter of the cam surface at the contact.
            d.hertz.max_stress(
                p.contact_force,
                T::TWO * d.geometry.roller_radius,
                T::TWO * p.surface_radius,
            )
        } else {
            T::ZERO
        };
        let segment = d.program.segment_at(p.theta_c);
        sample.revolution = revolution;
        sample.angle_deg = within.to_degrees();
        sample.segment = segment;
        sample.theory = theory;
        sample.contact_stress = contact_stress;
    }
}

/// Per-period accumulators of one revolution's period (VI.4, docs/MODEL.md §3.17).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PeriodStats<T> {
    /// Time spent in the period, s.
    pub duration: T,
    /// Samples seen.
    pub samples: u32,
    sum_dy2: T,
    sum_dv2: T,
    sum_da2: T,
    sum_torque: T,
    sum_force: T,
    sum_rel_m: T,
    sum_rel_cp: T,
    sum_rel_c: T,
    /// Largest output torque on the cam, lb·in.
    pub torque_max: T,
    /// Smallest output torque on the cam, lb·in.
    pub torque_min: T,
    /// Largest contact force, lb.
    pub force_max: T,
    /// Smallest contact force, lb.
    pub force_min: T,
    /// Largest Hertz contact stress, psi.
    pub stress_max: T,
    /// Whether the follower left the cam in this period.
    pub jump: bool,
}

impl<T: Real> PeriodStats<T> {
    fn first(&mut self, s: &Sample<T>) {
        let p = &s.point;
        self.torque_max = p.torque_out;
        self.torque_min = p.torque_out;
        self.force_max = p.contact_force;
        self.force_min = p.contact_force;
        self.stress_max = s.contact_stress;
    }
    fn extremes(&mut self, s: &Sample<T>) {
        let p = &s.point;
        self.torque_max = self.torque_max.max(p.torque_out);
        self.torque_min = self.torque_min.min(p.torque_out);
        self.force_max = self.force_max.max(p.contact_force);
        self.force_min = self.force_min.min(p.contact_force);
        self.stress_max = self.stress_max.max(s.contact_stress);
        self.jump |= !p.in_contact;
    }
    #[inline]
    fn mean(&self, sum: T) -> T {
        if self.duration > T::ZERO {
            sum / self.duration
        } else {
            T::ZERO
        }
    }
    /// RMS deviation of the load displacement from the theoretical, in.
    pub fn rms_displacement(&self) -> T {
        self.mean(self.sum_dy2).sqrt()
    }
    /// RMS deviation of the load velocity from the theoretical, in/s.
    pub fn rms_velocity(&self) -> T {
        self.mean(self.sum_dv2).sqrt()
    }
    /// RMS deviation of the load acceleration from the theoretical, in/s².
    pub fn rms_acceleration(&self) -> T {
        self.mean(self.sum_da2).sqrt()
    }
    /// Time-averaged output torque on the cam, lb·in.
    pub fn torque_avg(&self) -> T {
        self.mean(self.sum_torque)
    }
    /// Time-averaged contact force, lb.
    pub fn force_avg(&self) -> T {
        self.mean(self.sum_force)
    }
    /// AORD of the motor speed: time average of (θ̇_m - ω_ref) / ω_ref.
    pub fn aord_motor(&self) -> T {
        self.mean(self.sum_rel_m)
    }
    /// AORD of the coupling speed.
    pub fn aord_coupling(&self) -> T {
        self.mean(self.sum_rel_cp)
    }
    /// AORD of the cam speed.
    pub fn aord_cam(&self) -> T {
        self.mean(self.sum_rel_c)
    }
}

/// A separation interval of the follower from the cam (Eq. V.20).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JumpInterval<T> {
    /// Revolution (from 1) of the onset.
    pub revolution: u32,
    /// Cam angle of the onset within that revolution, degrees.
    pub start_deg: T,
    /// Cam angle where contact resumed, degrees (may exceed 360 if it carries over).
    pub end_deg: T,
}

/// The per-period statistics of up to `R` revolutions of a program of up to `P`
/// periods, and up to `J` jump intervals.
#[derive(Clone, Debug)]
pub struct ResponseStats<T, const R: usize = 8, const P: usize = 8, const J: usize = 32> {
    periods: [[PeriodStats<T>; P]; R],
    jumps: heapless::Vec<JumpInterval<T>, J>,
    /// Jump intervals that did not fit in `J`.
    pub jumps_dropped: u32,
    omega_ref: T,
    prev: Option<Sample<T>>,
    open_jump: Option<(u32, T, T)>,
    revolutions_seen: u32,
}

impl<T: Real, const R: usize, const P: usize, const J: usize> ResponseStats<T, R, P, J> {
    /// Empty statistics; AORD is taken relative to `omega_ref` (rad/s).
    pub fn new(omega_ref: T) -> Self {
        Self {
            periods: [[PeriodStats::default(); P]; R],
            jumps: heapless::Vec::new(),
            jumps_dropped: 0,
            omega_ref,
            prev: None,
            open_jump: None,
            revolutions_seen: 0,
        }
    }

    /// Statistics of `revolution` (from 1) and `period` (segment index), if recorded.
    pub fn period(&self, revolution: u32, period: usize) -> Option<&PeriodStats<T>> {
        self.periods
            .get((revolution as usize).checked_sub(1)?)?
            .get(period)
    }

    /// Number of revolutions with samples (at most `R`).
    pub fn revolutions(&self) -> u32 {
        self.revolutions_seen
    }

    /// The recorded jump intervals (a jump still open at the end is closed at the last sample).
    pub fn jumps(&self) -> heapless::Vec<JumpInterval<T>, J> {
        let mut v = self.jumps.clone();
        if let (Some((rev, start, abs0)), Some(p)) = (self.open_jump, self.prev.as_ref()) {
            let end = start + (p.point.theta_c - abs0).to_degrees();
            if v.push(JumpInterval {
                revolution: rev,
                start_deg: start,
                end_deg: end,
            })
            .is_err()
            {
                // Full: the caller sees jumps_dropped.
            }
        }
        v
    }

    /// Sum over the periods of one revolution of the RMS acceleration deviation
    /// (the thesis's sensitivity index, VI.4.2).
    pub fn acceleration_rms_sum(&self, revolution: u32) -> T {
        let mut s = T::ZERO;
        if let Some(row) = self.periods.get((revolution as usize).saturating_sub(1)) {
            for p in row.iter().filter(|p| p.samples > 0) {
                s += p.rms_acceleration();
            }
        }
        s
    }
}

impl<T: Real, const R: usize, const P: usize, const J: usize> ResponseStats<T, R, P, J> {
    /// The cell of `revolution` (from 1) and `segment`, if recorded.
    fn cell_mut(&mut self, revolution: u32, segment: usize) -> Option<&mut PeriodStats<T>> {
        (revolution as usize)
            .checked_sub(1)
            .and_then(|r| self.periods.get_mut(r))
            .and_then(|row| row.get_mut(segment))
    }

    /// A sample enters its cell's extremes and count.
    fn enter(cell: &mut PeriodStats<T>, s: &Sample<T>) {
        if cell.samples == 0 {
            cell.first(s);
        }
        cell.extremes(s);
        cell.samples = cell.samples.saturating_add(1);
    }

    /// The trapezoidal time integrals from `q` to `s` into `cell`.
    fn integrate(cell: &mut PeriodStats<T>, q: &Sample<T>, s: &Sample<T>, w: T) {
        let p = &s.point;
        let dt = p.t - q.point.t;
        if dt > T::ZERO {
            let h = dt * T::HALF;
            let e = |a: &Sample<T>| {
                let pt = &a.point;
                (
                    (pt.load_displacement() - a.theory.y).sq(),
                    (pt.load_velocity() - a.theory.v).sq(),
                    (pt.load_acceleration() - a.theory.a).sq(),
                )
            };
            let (y0, v0, a0) = e(q);
            let (y1, v1, a1) = e(s);
            cell.duration += dt;
            cell.sum_dy2 += h * (y0 + y1);
            cell.sum_dv2 += h * (v0 + v1);
            cell.sum_da2 += h * (a0 + a1);
            cell.sum_torque += h * (q.point.torque_out + p.torque_out);
            cell.sum_force += h * (q.point.contact_force + p.contact_force);
            cell.sum_rel_m += h * ((q.point.omega_m + p.omega_m) / w - T::TWO);
            cell.sum_rel_cp += h * ((q.point.omega_cp + p.omega_cp) / w - T::TWO);
            cell.sum_rel_c += h * ((q.point.omega_c + p.omega_c) / w - T::TWO);
        }
    }
}

/// The statistics of the solver's samples: time integrals by the trapezoidal rule
/// between consecutive samples of one period, extremes over them. On a grid
/// ([`crate::simulate_on_grid`]) each period's first and last interval are closed too:
/// the sample at a segment start ([`GridPointKind::SegmentStart`]) ends the previous
/// period's integrals and starts this one's, and the run's end
/// ([`GridPointKind::End`]) closes the last; without the grid the pieces between a
/// period's last sample and the next period's first are left out (an error of the order
/// of one step per period, which does not fall with the tolerance).
impl<T: Real, const R: usize, const P: usize, const J: usize> Observer<T>
    for ResponseStats<T, R, P, J>
{
    fn observe(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        let p = &s.point;
        // Jump bookkeeping.
        match (self.open_jump, p.in_contact) {
            (None, false) => self.open_jump = Some((s.revolution, s.angle_deg, p.theta_c)),
            (Some((rev, start, abs0)), true) => {
                let end = start + (p.theta_c - abs0).to_degrees();
                if self
                    .jumps
                    .push(JumpInterval {
                        revolution: rev,
                        start_deg: start,
                        end_deg: end,
                    })
                    .is_err()
                {
                    self.jumps_dropped = self.jumps_dropped.saturating_add(1);
                }
                self.open_jump = None;
            }
            _ => {}
        }
        self.revolutions_seen = self.revolutions_seen.max(s.revolution.min(R as u32));
        let prev = self.prev;
        let w = self.omega_ref;
        if let Some(cell) = self.cell_mut(s.revolution, s.segment) {
            Self::enter(cell, s);
            // Trapezoidal time integrals from the previous sample when it is in the same cell.
            if let Some(q) = prev
                .as_ref()
                .filter(|q| q.revolution == s.revolution && q.segment == s.segment)
            {
                Self::integrate(cell, q, s, w);
            }
        }
        self.prev = Some(*s);
        ControlFlow::Continue(())
    }

    fn observe_grid(&mut self, s: &Sample<T>, kind: GridPointKind) -> ControlFlow<()> {
        if kind == GridPointKind::Step {
            return ControlFlow::Continue(());
        }
        let w = self.omega_ref;
        // The interval from the previous sample to this one lies in the previous one's
        // period (this sample is where that period ends).
        if let Some(q) = self.prev {
            if let Some(cell) = self.cell_mut(q.revolution, q.segment) {
                Self::integrate(cell, &q, s, w);
            }
        }
        if kind == GridPointKind::SegmentStart {
            if let Some(cell) = self.cell_mut(s.revolution, s.segment) {
                Self::enter(cell, s);
            }
        }
        self.prev = Some(*s);
        ControlFlow::Continue(())
    }
}

/// Names a program segment for reports: `dwell_low`, `rise`, `dwell_high`, `return`
/// for the four periods of a D-R-D-R program, else by kind.
pub fn period_name(kind: SegmentKind, level_before: bool) -> &'static str {
    match kind {
        SegmentKind::Dwell if level_before => "dwell_high",
        SegmentKind::Dwell => "dwell_low",
        SegmentKind::Rise(_) => "rise",
        SegmentKind::Return(_) => "return",
    }
}

#[cfg(test)]
mod run_error_tests {
    use super::*;
    use crate::{Design, ModelLimit, RegulatedFullModel, SimFailure};
    use std::string::ToString;

    #[test]
    fn the_revolution_count_saturates_instead_of_overflowing() {
        // Found by the core_rhs fuzz target: floor(θ/2π) as u32 + 1 overflowed past 2^32
        // turns. Revolution k + 1 holds θ in [2πk, 2π(k+1)).
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut y = m.static_state();
        let two_pi = 2.0 * core::f64::consts::PI;
        for (theta, rev) in [
            (0.5, 1),
            (two_pi * 3.5, 4),
            (-1.0, 0),
            (two_pi * 4.3e9, u32::MAX),
            (2.7e173, u32::MAX),
        ] {
            StateMut::<f64, crate::RegulatedFull, 22>::new(&mut y).set(StateVar::CamAngle, theta);
            assert_eq!(m.sample(0.0, &y, false).revolution, rev, "theta {theta}");
        }
    }

    #[test]
    fn a_thrown_follower_ends_the_run_with_the_cause_and_the_cam_angle() {
        // 1600 rpm, far above the onset (902 rpm): the follower leaves the cam on the rise
        // and flies into its slide bearing before the revolution ends.
        let mut d = Design::<f64>::reference();
        d.set_speed_rpm(1600.0).unwrap();
        let m = RegulatedFullModel::<f64>::new(d).unwrap();
        let mut s = SolverSettings::reference();
        s.start = Start::Static;
        let mut seen = 0u32;
        let mut count = |_: &Sample<f64>| {
            seen += 1;
            ControlFlow::Continue(())
        };
        let e = simulate(&m, &s, 2, &mut count).unwrap_err();
        let Error::OutOfModel {
            limit,
            value,
            bound,
            revolution,
            cam_deg,
        } = e
        else {
            panic!("{e:?}")
        };
        assert_eq!(limit, ModelLimit::CantileverLength);
        assert!(value < bound && bound == 0.375 && value > 0.3, "{value}");
        // On the rise (30-180 deg) or just after it, of revolution 1.
        assert_eq!(revolution, 1);
        assert!(cam_deg > 90.0 && cam_deg < 210.0, "{cam_deg}");
        assert!(seen > 100);
        let text = e.to_string();
        assert!(
            text.starts_with(&std::format!(
                "the model left its valid range at cam angle {cam_deg:.2} deg of revolution 1: cantilever length e2 - y3 = "
            )),
            "{text}"
        );
        assert!(text.contains("below its bound 3.750e-1 in"), "{text}");
        assert_eq!(e.summary(), "cantilever length e2 - y3");
    }

    #[test]
    fn a_spent_step_budget_names_the_key_that_raises_it() {
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let mut s = SolverSettings::reference();
        s.max_steps_per_rev = 50;
        let mut nothing = |_: &Sample<f64>| ControlFlow::Continue(());
        let e = simulate(&m, &s, 2, &mut nothing).unwrap_err();
        let Error::SimulationFailed {
            failure,
            revolution,
            cam_deg,
            t,
        } = e
        else {
            panic!("{e:?}")
        };
        // 50 a revolution over 2 revolutions: 100 steps, at most 1/2000 revolution each.
        assert_eq!(
            failure,
            SimFailure::StepBudget {
                steps: 100,
                per_revolution: 50
            }
        );
        assert_eq!(revolution, 1);
        assert!(
            cam_deg > 0.0 && cam_deg < 100.0 * 360.0 / 2000.0 + 1e-9,
            "{cam_deg}"
        );
        assert!(t > 0.0);
        let text = e.to_string();
        assert!(text.contains("(100 steps, 50 a revolution)"), "{text}");
        assert!(text.ends_with(": raise solver.max_steps_per_rev"), "{text}");
    }

    #[test]
    fn the_settings_refuse_values_outside_their_ranges_by_key() {
        let field = |s: SolverSettings<f64>| match s.validate() {
            Err(Error::InvalidParameter { field, .. }) => field,
            _ => "",
        };
        let r = SolverSettings::<f64>::reference();
        assert_eq!(field(r), "");
        assert_eq!(field(SolverSettings { rtol: 0.5, ..r }), "rtol");
        assert_eq!(field(SolverSettings { rtol: 1e-300, ..r }), "rtol");
        assert_eq!(field(SolverSettings { atol: 1.0, ..r }), "atol_in");
        assert_eq!(
            field(SolverSettings {
                max_step_fraction: 1e-9,
                ..r
            }),
            "max_step_fraction_rev"
        );
        assert_eq!(
            field(SolverSettings {
                max_steps_per_rev: 0,
                ..r
            }),
            "max_steps_per_rev"
        );
        assert_eq!(
            field(SolverSettings {
                max_steps_per_rev: u32::MAX,
                ..r
            }),
            "max_steps_per_rev"
        );
    }
}
