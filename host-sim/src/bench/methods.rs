//! The methods the bench compares, all on the same right-hand side
//! ([`CamModel`]'s, through [`Counted`]), from the same static start, to the same end
//! (the first step end at or past `2π · revolutions` of cam angle), sampled the same way
//! ([`Sampler`]):
//! - England's method with the thesis's rule, uncapped ([`StepControl::classic`], the
//!   `"thesis"` step control);
//! - England's method as `camsim run --method england` runs it (the default method is
//!   `auto`: Merson's pair at `rtol >= 1e-6`): the thesis's rule with the
//!   tolerance-scaled stiffness cap ([`StepRule::ScaledCap`], `"scaled-cap"`);
//! - England's method with the PI controller, Hairer's starting step and the stiffness
//!   cap ([`StepControl::pi_capped`]);
//! - classic RK4 at a fixed step (a whole number of steps per nominal revolution), the
//!   `camsim_core::rk4_step_from`, the core's RK4 from a given first stage;
//! - Dormand and Prince's 5(4) pair with Hairer's PI controller as the `ode_solvers` crate
//!   implements it, on the same per-component tolerances (the state is scaled so that the
//!   crate's scalar absolute tolerance is each component's own), the crate's stiffness
//!   test off (it would stop the run: the problem is stiff by design) and its sparse
//!   output (no work spent on its own dense output; the bench interpolates);
//! - Merson's 4(3) pair ([`camsim_core::Merson`]), built for the imaginary axis (√12 of
//!   stability there over 5 evaluations a step), with Hairer's PI controller, without and
//!   with the stiffness cap (0.95 of √12 over the spectral radius), on the same tolerances as England
//!   (single-step sizes: England's double-step `h_init`, `h_min`, `h_max` halved), its
//!   step ends sampled through the quintic Hermite like RK4's.

use std::ops::ControlFlow;

use anyhow::{anyhow, bail, Result};
use camsim_core::{
    rk4_step_from, solver_config, CamModel, England, EnglandConfig, Merson, OdeSystem, Real, Scene,
    SolverSettings, StepControl, StepRule, StiffnessCap,
};
use ode_solvers::dop_shared::{FloatNumber, OutputType, System};
use ode_solvers::{Dopri5, SVector};

use super::sample::{Counted, NodeHermite, Sampler};

/// One method of the comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// England's method with its original step-size rule (`camsim run --method england
    /// --step-control thesis`).
    England,
    /// England's method as `camsim run --method england` runs it ([`StepRule::ScaledCap`]): the
    /// original rule with the stiffness cap scaled with the tolerance.
    EnglandScaledCap,
    /// England's method with the PI controller, Hairer's first step and the stiffness cap.
    EnglandPiCapped,
    /// Classic RK4 at a fixed step: this many steps per nominal revolution (2π/ω0).
    Rk4 {
        /// Steps per nominal revolution.
        steps_per_rev: u32,
    },
    /// Dormand-Prince 5(4) from `ode_solvers`.
    Dopri5,
    /// Merson's 4(3) pair ([`camsim_core::MERSON`]), for the imaginary axis, with Hairer's
    /// PI controller; `capped`: also the stiffness cap at 0.95 of √12 over the spectral
    /// radius.
    Merson {
        /// The stiffness cap on.
        capped: bool,
    },
    /// The linearly implicit Rosenbrock-W method ROS34PW2 ([`super::rosenbrock`]), its
    /// Jacobian by forward differences every `jac_every` accepted steps.
    Rosenbrock {
        /// Accepted steps between Jacobians.
        jac_every: u32,
    },
}

impl Method {
    /// The name in reports and JSON (`england`, `england_scaled_cap`, `england_pi_capped`, `rk4_fixed`,
    /// `dopri5_ode_solvers`, `merson_4_3`, `merson_4_3_capped`, `rosenbrock_ros34pw2` with a Jacobian every step,
    /// `rosenbrock_ros34pw2_j10` every 10 steps, `rosenbrock_ros34pw2_jn` otherwise).
    pub fn name(&self) -> &'static str {
        match self {
            Method::England => "england",
            Method::EnglandScaledCap => "england_scaled_cap",
            Method::EnglandPiCapped => "england_pi_capped",
            Method::Rk4 { .. } => "rk4_fixed",
            Method::Dopri5 => "dopri5_ode_solvers",
            Method::Merson { capped: false } => "merson_4_3",
            Method::Merson { capped: true } => "merson_4_3_capped",
            Method::Rosenbrock { jac_every: 1 } => "rosenbrock_ros34pw2",
            Method::Rosenbrock { jac_every: 10 } => "rosenbrock_ros34pw2_j10",
            Method::Rosenbrock { .. } => "rosenbrock_ros34pw2_jn",
        }
    }

    /// Whether the method has a tolerance (RK4 at a fixed step has none).
    pub fn adaptive(&self) -> bool {
        !matches!(self, Method::Rk4 { .. })
    }
}

/// The work of one run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Work {
    /// Accepted steps (England: double steps).
    pub accepted: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations, counted at the right-hand side (everything: the
    /// steps, starting-step and stiffness estimates, the end-point derivatives the
    /// interpolants need).
    pub evals: u64,
}

impl Work {
    /// `self - earlier` (the work between two points of the same run).
    pub fn since(&self, earlier: &Work) -> Work {
        Work {
            accepted: self.accepted.saturating_sub(earlier.accepted),
            rejected: self.rejected.saturating_sub(earlier.rejected),
            evals: self.evals.saturating_sub(earlier.evals),
        }
    }
}

/// A generous end time for `revolutions` (the drive may run slower than ω0; the sampler
/// stops the run at the cam angle): 4 nominal periods per revolution, like `simulate`.
fn end_time<T: Real>(omega0: T, revolutions: u32) -> T {
    T::from_f64(4.0 * 2.0 * std::f64::consts::PI * f64::from(revolutions)) / omega0
}

/// Runs `method` from the model's static state for `revolutions` revolutions with the
/// tolerances of `settings` (rtol; atol in inches, per component as `solver_config`
/// scales it; the largest step), feeding `sampler`. Returns the work; an error if the
/// method failed (the sampler keeps what it saw before).
pub fn run<T, S, const N: usize>(
    method: Method,
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work>
where
    T: Real + FloatNumber,
    S: Scene,
    f64: From<T>,
{
    let work = match method {
        Method::England => england(
            model,
            settings,
            StepControl::classic(),
            revolutions,
            sampler,
        )?,
        Method::EnglandScaledCap => england(
            model,
            settings,
            StepRule::ScaledCap.control(),
            revolutions,
            sampler,
        )?,
        Method::EnglandPiCapped => england(
            model,
            settings,
            StepControl::pi_capped(),
            revolutions,
            sampler,
        )?,
        Method::Rk4 { steps_per_rev } => rk4(model, steps_per_rev, revolutions, sampler)?,
        Method::Dopri5 => dopri5(model, settings, revolutions, sampler)?,
        Method::Merson { capped } => run_merson(
            model,
            settings,
            capped.then(StiffnessCap::new),
            revolutions,
            sampler,
        )?,
        Method::Rosenbrock { jac_every } => {
            rosenbrock(model, settings, jac_every, revolutions, sampler)?
        }
    };
    if sampler.bad_sample {
        bail!("a sample could not be placed (non-finite solution)");
    }
    if !sampler.done && sampler.jump_watch.steady_separation.is_none() {
        bail!("the run ended before the cam turned {revolutions} revolutions");
    }
    Ok(work)
}

/// Error per unit step with one revolution at ω0 as the reference double step: the local
/// errors England may make over a revolution add up to at most one tolerance, whatever
/// its steps (issue 22; [`camsim_core::PerUnitStep`]).
pub fn per_revolution<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
) -> camsim_core::PerUnitStep<T> {
    camsim_core::PerUnitStep::new(T::TWO * T::PI / model.design().omega0)
}

/// [`run`] for England's method with any step control (for example with
/// [`camsim_core::PerUnitStep`]), with the same checks.
pub fn run_england<T, S, const N: usize>(
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    control: StepControl<T>,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work>
where
    T: Real + FloatNumber,
    S: Scene,
    f64: From<T>,
{
    let work = england(model, settings, control, revolutions, sampler)?;
    if sampler.bad_sample {
        bail!("a sample could not be placed (non-finite solution)");
    }
    if !sampler.done && sampler.jump_watch.steady_separation.is_none() {
        bail!("the run ended before the cam turned {revolutions} revolutions");
    }
    Ok(work)
}

/// England's method with `control`, sampled through its dense output.
fn england<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    control: StepControl<T>,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work> {
    let config = solver_config(model, settings, revolutions)?;
    let sys = Counted::new(model);
    let mut solver = England::with_control(config, control)?;
    let mut y = model.static_state();
    let t_end = end_time(model.design().omega0, revolutions);
    let r = solver.integrate_dense(&sys, T::ZERO, &mut y, t_end, |d| {
        let [_, y1, y2] = d.nodes();
        if sampler.watch(d.t_mid(), y1).is_break() || sampler.watch(d.t_end(), y2).is_break() {
            return ControlFlow::Break(());
        }
        sampler.feed(d)
    });
    let stats = r?;
    Ok(Work {
        accepted: u64::from(stats.accepted),
        rejected: u64::from(stats.rejected),
        evals: sys.evals(),
    })
}

/// Merson's 4(3) pair on England's tolerances (rtol, per-component atol) and step bounds
/// halved (England's are double steps), its step ends (with `f`, the next step's first
/// stage, so free) through the quintic Hermite sampler; `cap`: its stiffness cap (`None`:
/// uncapped). [`run`] with [`Method::Merson`] adds the checks of a complete run.
pub fn run_merson<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    cap: Option<StiffnessCap<T>>,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work> {
    let config = solver_config(model, settings, revolutions)?;
    let single = EnglandConfig {
        h_init: config.h_init * T::HALF,
        h_min: config.h_min * T::HALF,
        h_max: config.h_max * T::HALF,
        // England's budget counts double steps.
        max_steps: config.max_steps.saturating_mul(2),
        ..config
    };
    let sys = Counted::new(model);
    let mut solver = match cap {
        Some(cap) => Merson::with_cap(single, cap)?,
        None => Merson::new(single)?,
    };
    let mut y = model.static_state();
    let t_end = end_time(model.design().omega0, revolutions);
    let mut nodes = NodeHermite::default();
    let stats = solver.integrate(&sys, T::ZERO, &mut y, t_end, |t, y, f| {
        nodes.push(sampler, t, y, f)
    })?;
    Ok(Work {
        accepted: u64::from(stats.accepted),
        rejected: u64::from(stats.rejected),
        evals: sys.evals(),
    })
}

/// ROS34PW2 on the same tolerances (rtol, per-component atol, largest step) as England,
/// sampled through the quintic Hermite interpolant of its step ends like RK4; the
/// evaluations counted include the Jacobians' columns.
fn rosenbrock<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    jac_every: u32,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work> {
    let config = solver_config(model, settings, revolutions)?;
    let sys = Counted::new(model);
    let cfg = super::rosenbrock::Config {
        rtol: config.tol.rtol,
        atol: config.tol.atol,
        h_init: config.h_init,
        h_min: config.h_min,
        h_max: config.h_max,
        jac_every: jac_every.max(1),
        max_steps: u64::from(config.max_steps),
    };
    let mut y = model.static_state();
    let t_end = end_time(model.design().omega0, revolutions);
    let mut nodes = NodeHermite::default();
    let stats = super::rosenbrock::integrate(&sys, T::ZERO, &mut y, t_end, &cfg, |t, y, f| {
        nodes.push(sampler, t, y, f)
    })?;
    Ok(Work {
        accepted: stats.accepted,
        rejected: stats.rejected,
        evals: sys.evals(),
    })
}

/// Classic RK4 at `steps_per_rev` steps per nominal revolution; the step ends with
/// `f(t, y)` (the next step's first stage) feed the Hermite sampler, so the cost is
/// `4 · steps + 1` evaluations.
fn rk4<T: Real, S: Scene, const N: usize>(
    model: &CamModel<T, S, N>,
    steps_per_rev: u32,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work> {
    if steps_per_rev == 0 {
        bail!("steps per revolution must be positive");
    }
    let sys = Counted::new(model);
    let period = T::TWO * T::PI / model.design().omega0;
    let h = period / T::from_usize(steps_per_rev as usize);
    // A stalled drive must not loop forever: 4 nominal periods per revolution at most.
    let max_steps = u64::from(steps_per_rev) * u64::from(revolutions) * 4;
    let mut y = model.static_state();
    let mut f = [T::ZERO; N];
    sys.rhs(T::ZERO, &y, &mut f);
    let mut nodes = NodeHermite::default();
    let mut steps = 0u64;
    if nodes.push(sampler, T::ZERO, &y, &f).is_continue() {
        loop {
            if steps >= max_steps {
                bail!("RK4 took {steps} steps without finishing the revolutions");
            }
            let t = h * T::from_usize(steps as usize);
            rk4_step_from(&sys, t, &mut y, &f, h);
            steps += 1;
            let t1 = h * T::from_usize(steps as usize);
            sys.rhs(t1, &y, &mut f);
            if let Some(i) = y.iter().chain(f.iter()).position(|v| !v.is_finite()) {
                bail!(
                    "RK4 solution not finite at t = {:e} s (component {})",
                    t1.to_f64(),
                    i % N
                );
            }
            if nodes.push(sampler, t1, &y, &f).is_break() {
                break;
            }
        }
    }
    Ok(Work {
        accepted: steps,
        rejected: 0,
        evals: sys.evals(),
    })
}

/// The model as `ode_solvers` sees it: the state scaled component by component,
/// `z_i = y_i / d_i` with `d_i = atol_i / atol`, so that the crate's scalar absolute
/// tolerance `atol` is each component's own `atol_i`.
struct Peer<'a, 's, 'm, T, S, const N: usize> {
    sys: &'a Counted<'a, CamModel<T, S, N>>,
    d: [T; N],
    sampler: &'s mut Sampler<'m, T, S, N>,
    nodes: NodeHermite<T, N>,
    /// The sampler asked to stop (or the crate stopped for another reason).
    stop: bool,
}

impl<T: Real, S: Scene, const N: usize> Peer<'_, '_, '_, T, S, N> {
    fn unscale(&self, z: &SVector<T, N>) -> [T; N] {
        let mut y = [T::ZERO; N];
        for ((yi, zi), di) in y.iter_mut().zip(z.iter()).zip(self.d.iter()) {
            *yi = *zi * *di;
        }
        y
    }
}

impl<T, S, const N: usize> System<T, SVector<T, N>> for Peer<'_, '_, '_, T, S, N>
where
    T: Real + FloatNumber,
    S: Scene,
{
    fn system(&self, x: T, z: &SVector<T, N>, dz: &mut SVector<T, N>) {
        let y = self.unscale(z);
        let mut f = [T::ZERO; N];
        self.sys.rhs(x, &y, &mut f);
        for ((o, fi), di) in dz.iter_mut().zip(f.iter()).zip(self.d.iter()) {
            *o = *fi / *di;
        }
    }

    fn solout(&mut self, x: T, z: &SVector<T, N>, dz: &SVector<T, N>) -> bool {
        let y = self.unscale(z);
        let f = self.unscale(dz);
        self.stop = self.nodes.push(self.sampler, x, &y, &f).is_break();
        self.stop
    }
}

/// Dormand-Prince 5(4) from `ode_solvers` with Hairer's settings (safety 0.9, PI
/// `beta` 0.04, step factors in [0.2, 10], Hairer's first step), the same rtol, per-component
/// atol and largest step as England, and a step budget.
fn dopri5<T, S, const N: usize>(
    model: &CamModel<T, S, N>,
    settings: &SolverSettings<T>,
    revolutions: u32,
    sampler: &mut Sampler<'_, T, S, N>,
) -> Result<Work>
where
    T: Real + FloatNumber,
    S: Scene,
    f64: From<T>,
{
    let config = solver_config(model, settings, revolutions)?;
    let atol = settings.atol;
    let mut d = [T::ONE; N];
    for (di, a) in d.iter_mut().zip(config.tol.atol.iter()) {
        *di = *a / atol;
    }
    let sys = Counted::new(model);
    let y0 = model.static_state();
    let mut z0 = SVector::<T, N>::zeros();
    for ((z, y), di) in z0.iter_mut().zip(y0.iter()).zip(d.iter()) {
        *z = *y / *di;
    }
    // f(t0, y0) for the first node (the crate evaluates it too; this one is counted).
    let mut f0 = [T::ZERO; N];
    sys.rhs(T::ZERO, &y0, &mut f0);
    let mut nodes = NodeHermite::default();
    if nodes.push(sampler, T::ZERO, &y0, &f0).is_break() {
        return Ok(Work {
            evals: sys.evals(),
            ..Work::default()
        });
    }
    let peer = Peer {
        sys: &sys,
        d,
        sampler,
        nodes,
        stop: false,
    };
    let t_end = end_time(model.design().omega0, revolutions);
    let n_max = config.max_steps;
    let mut stepper = Dopri5::from_param(
        peer,
        T::ZERO,
        t_end,
        t_end,
        z0,
        settings.rtol,
        atol,
        <T as Real>::from_f64(0.9),
        <T as Real>::from_f64(0.04),
        <T as Real>::from_f64(0.2),
        <T as Real>::from_f64(10.0),
        config.h_max,
        T::ZERO,
        n_max,
        // The stiffness test runs every n_stiff accepted steps: never.
        u32::MAX,
        OutputType::Sparse,
    );
    let r = stepper.integrate();
    drop(stepper);
    let stats = r.map_err(|e| anyhow!("dopri5 (ode_solvers): {e}"))?;
    Ok(Work {
        accepted: u64::from(stats.accepted_steps),
        rejected: u64::from(stats.rejected_steps),
        evals: sys.evals(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit oscillator `x'' = -x` for the peer's order.
    struct Oscillator;
    impl System<f64, SVector<f64, 2>> for Oscillator {
        fn system(&self, _x: f64, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>) {
            dy[0] = y[1];
            dy[1] = -y[0];
        }
    }

    #[test]
    fn the_peers_dormand_prince_is_fifth_order() {
        // ode_solvers' Dopri5 at a fixed step (first and largest step h, a tolerance no
        // step fails) over [0, 10] on x'' = -x from (1, 0): the error of x(10) against
        // cos 10 falls as h^5. (On the cam model the steps its stability allows leave
        // its error dominated by the stiff mode's treatment near the boundary, flat at
        // 4e-7 to 9e-7 in/s² from 24 500 to 40 000 steps per revolution: no order shows.)
        let err = |n: u32| {
            let h = 10.0 / f64::from(n);
            let mut s = Dopri5::from_param(
                Oscillator,
                0.0,
                10.0,
                10.0,
                SVector::<f64, 2>::new(1.0, 0.0),
                1.0,
                1e30,
                0.9,
                0.04,
                0.2,
                10.0,
                h,
                h,
                100_000,
                u32::MAX,
                OutputType::Sparse,
            );
            let st = s.integrate().unwrap();
            assert_eq!(st.accepted_steps, n);
            assert_eq!(st.rejected_steps, 0);
            let y = s.y_out().last().unwrap();
            (y[0] - 10f64.cos()).abs()
        };
        let (e1, e2) = (err(100), err(200));
        let p = (e1 / e2).log2();
        assert!((p - 5.0).abs() < 0.1, "order {p}: {e1:e}, {e2:e}");
    }
}
