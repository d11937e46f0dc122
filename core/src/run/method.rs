//! The integration method of a run ([`Method`], scene key `[solver] method`) and the one
//! solver a run holds ([`RunSolver`]): England's method (the thesis's), Merson's 4(3) pair
//! (for the imaginary axis) or Dormand and Prince's 5(4) pair (for accuracy-limited runs).

use core::ops::ControlFlow;

use crate::solve::england::Sampler;
use crate::{Dense, England, EnglandConfig, Error, OdeSystem, Real, Result, SolverStats, StepRule};
#[cfg(feature = "pairs")]
use crate::{DormandPrince, Merson, StiffnessCap, SCALED_CAP_FULL_RTOL};

/// The tightest rtol at which [`Method::Auto`] takes Merson's pair: at rtol 1e-4, 1e-5 and
/// 1e-6 Merson needs 0.68×, 0.74× and 0.78× England's evaluations at equal acceleration
/// error, at 1e-7 and 1e-8 0.87× and 0.90× (docs/MODEL.md §3.16), so below 1e-6 it does
/// not win by the 15 % a default needs (issue 21), and England's method, which also takes
/// the thesis start's impact at rtol 1e-12 where Merson's step underflows, runs there. A
/// chosen value, from that measurement.
pub const AUTO_MERSON_MIN_RTOL: f64 = 1e-6;

/// How a run integrates the model (scene key `[solver] method`, option `--method`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "kebab-case")
)]
pub enum Method {
    /// The default: Merson's pair at rtol >= [`AUTO_MERSON_MIN_RTOL`], where it wins, and
    /// England's method at tighter tolerances ([`Method::resolve`]).
    #[default]
    Auto,
    /// England's double step (the thesis's "modified Runge-Kutta", Appendix D), its step
    /// controlled by [`SolverSettings::step_control`](crate::SolverSettings::step_control).
    England,
    /// Merson's 4(3) pair ([`crate::MERSON`]): √12 along the imaginary axis in five
    /// evaluations. With a capped [`StepRule`] its step is capped at the stiffness limit
    /// as England's (tolerance-scaled below rtol 1e-5); with `"thesis"` it is not.
    Merson,
    /// Dormand and Prince's 5(4) pair ([`crate::DORMAND_PRINCE`]): order 5 in six
    /// evaluations, for a step held by accuracy; no stiffness cap.
    DormandPrince,
}

impl Method {
    /// Every method, in the order the documentation lists them.
    pub const ALL: [Method; 4] = [
        Method::Auto,
        Method::England,
        Method::Merson,
        Method::DormandPrince,
    ];

    /// The scene file's name: `"auto"`, `"england"`, `"merson"`, `"dormand-prince"`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::England => "england",
            Method::Merson => "merson",
            Method::DormandPrince => "dormand-prince",
        }
    }

    /// The method of a scene file's name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// The method that runs at `rtol`: [`Method::Auto`]'s choice, any other as it is.
    /// Without the feature `pairs`, [`Method::Auto`] is always England's method.
    ///
    /// ```
    /// # #[cfg(feature = "pairs")] {
    /// use camsim_core::Method;
    /// assert_eq!(Method::Auto.resolve(1e-6), Method::Merson);
    /// assert_eq!(Method::Auto.resolve(1e-7), Method::England);
    /// assert_eq!(Method::DormandPrince.resolve(1e-8), Method::DormandPrince);
    /// # }
    /// ```
    pub fn resolve(self, rtol: f64) -> Method {
        match self {
            Method::Auto if cfg!(feature = "pairs") && rtol >= AUTO_MERSON_MIN_RTOL => {
                Method::Merson
            }
            Method::Auto => Method::England,
            other => other,
        }
    }
}

/// The solver of one run, built from its settings.
#[derive(Clone, Debug)]
pub(crate) enum RunSolver<T, const N: usize> {
    /// England's method.
    England(England<T, N>),
    /// Merson's pair.
    #[cfg(feature = "pairs")]
    Merson(Merson<T, N>),
    /// Dormand and Prince's pair.
    #[cfg(feature = "pairs")]
    DormandPrince(DormandPrince<T, N>),
}

impl<T: Real, const N: usize> RunSolver<T, N> {
    /// The solver of `method` on `config` (England's double-step sizes; a pair's single
    /// step is half of one, so that its samples are as dense; the budget counts each
    /// method's own steps), England's step controlled by `rule`.
    pub(crate) fn new(method: Method, rule: StepRule, config: EnglandConfig<T, N>) -> Result<Self> {
        #[cfg(feature = "pairs")]
        let single = EnglandConfig {
            h_init: config.h_init * T::HALF,
            h_min: config.h_min * T::HALF,
            h_max: config.h_max * T::HALF,
            ..config
        };
        Ok(match method.resolve(config.tol.rtol.to_f64()) {
            Method::Auto | Method::England => {
                RunSolver::England(England::with_control(config, rule.control())?)
            }
            #[cfg(feature = "pairs")]
            Method::Merson => RunSolver::Merson(match rule {
                StepRule::Thesis => Merson::new(single)?,
                StepRule::ScaledCap | StepRule::PiScaledCap => Merson::with_cap(
                    single,
                    StiffnessCap::tolerance_scaled(T::from_f64(SCALED_CAP_FULL_RTOL)),
                )?,
            }),
            #[cfg(feature = "pairs")]
            Method::DormandPrince => {
                RunSolver::DormandPrince(DormandPrince::dormand_prince(single)?)
            }
            #[cfg(not(feature = "pairs"))]
            Method::Merson | Method::DormandPrince => return Err(Error::InvalidParameter {
                field: crate::key::METHOD,
                rule:
                    "this build has England's method only (camsim-core's feature \"pairs\" is off)",
                value: f64::NAN,
            }),
        })
    }

    /// The counters of the last integration.
    pub(crate) fn stats(&self) -> SolverStats {
        match self {
            RunSolver::England(s) => s.stats(),
            #[cfg(feature = "pairs")]
            RunSolver::Merson(s) => s.stats(),
            #[cfg(feature = "pairs")]
            RunSolver::DormandPrince(s) => s.stats(),
        }
    }

    /// England's solver, for what only it provides (event location); an error naming
    /// the setting otherwise.
    pub(crate) fn england(&mut self) -> Result<&mut England<T, N>> {
        #[allow(unreachable_patterns)]
        match self {
            RunSolver::England(s) => Ok(s),
            _ => Err(Error::InvalidParameter {
                field: crate::key::METHOD,
                rule: "contact-event location runs on England's dense output: set method = \"england\"",
                value: f64::NAN,
            }),
        }
    }

    /// Integrates with `sampler` evaluating and shown every sample: the start, then the
    /// midpoint and end of each England double step, or the end of each pair step.
    pub(crate) fn integrate_shared<S: OdeSystem<T, N>>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        sampler: &mut dyn Sampler<T, N>,
    ) -> Result<SolverStats> {
        match self {
            RunSolver::England(s) => s.integrate_shared(sys, t0, y, t_end, sampler),
            #[cfg(feature = "pairs")]
            RunSolver::Merson(s) => s.integrate_shared(sys, t0, y, t_end, sampler),
            #[cfg(feature = "pairs")]
            RunSolver::DormandPrince(s) => s.integrate_shared(sys, t0, y, t_end, sampler),
        }
    }

    /// Integrates with `observer` given each accepted step's continuous extension.
    pub(crate) fn integrate_dense<S, F>(
        &mut self,
        sys: &S,
        t0: T,
        y: &mut [T; N],
        t_end: T,
        observer: F,
    ) -> Result<SolverStats>
    where
        S: OdeSystem<T, N>,
        F: FnMut(&Dense<'_, T, N>) -> ControlFlow<()>,
    {
        match self {
            RunSolver::England(s) => s.integrate_dense(sys, t0, y, t_end, observer),
            #[cfg(feature = "pairs")]
            RunSolver::Merson(s) => s.integrate_dense(sys, t0, y, t_end, observer),
            #[cfg(feature = "pairs")]
            RunSolver::DormandPrince(s) => s.integrate_dense(sys, t0, y, t_end, observer),
        }
    }
}
