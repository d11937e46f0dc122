//! Typed errors: every failure names what was wrong and the rule it broke.

use core::fmt;

/// Every way a camsim-core computation can refuse or fail.
///
/// Values are widened to `f64` only here, on the error path, so the messages carry
/// the offending number whatever the precision of the computation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Error {
    /// A parameter broke a rule (`field` names it, `rule` states the limit).
    InvalidParameter {
        /// Name of the parameter: its scene key (for example `"spring_rate_lb_per_in"`,
        /// `"program.segment[2].end_deg"`; see [`crate::key`]).
        field: &'static str,
        /// The rule it must satisfy (for example `"must be positive and finite"`).
        rule: &'static str,
        /// The value given.
        value: f64,
    },
    /// A key that does not fit the others (a rise or return without a motion law, a
    /// law on a dwell): `field` names it, `rule` says what fits.
    Inconsistent {
        /// Name of the parameter, as in scene files (for example `"program.segment[1].law"`).
        field: &'static str,
        /// What the other keys require of it.
        rule: &'static str,
    },
    /// A fixed-capacity buffer is too small for the input.
    Capacity {
        /// What did not fit.
        what: &'static str,
        /// Its compile-time capacity.
        capacity: usize,
    },
    /// The adaptive step size fell below its floor.
    StepSizeUnderflow {
        /// Time reached.
        t: f64,
        /// Step size that was still too large for the tolerance.
        h: f64,
    },
    /// The state or its derivative became NaN or infinite.
    NonFinite {
        /// Time reached.
        t: f64,
        /// Index of the first offending state component.
        component: usize,
    },
    /// The integrator used up its step budget before reaching the end time.
    StepBudgetExceeded {
        /// Time reached.
        t: f64,
        /// Steps taken (accepted plus rejected).
        steps: u32,
    },
    /// An iterative algorithm (for example the Jacobi eigensolver) did not converge.
    NoConvergence {
        /// Which algorithm.
        what: &'static str,
        /// Iterations spent.
        iterations: u32,
    },
    /// A matrix that must be positive definite is not.
    NotPositiveDefinite {
        /// Which matrix.
        what: &'static str,
    },
    /// A simulation reached a state outside what the model represents (docs/MODEL.md
    /// §3.20): the run ends there instead of integrating on into a state whose numbers
    /// mean nothing.
    OutOfModel {
        /// Which bound was crossed (the physical quantity and why it is bounded).
        limit: ModelLimit,
        /// The quantity's value.
        value: f64,
        /// Its bound (an upper bound of a magnitude, or a lower bound: see [`ModelLimit`]).
        bound: f64,
        /// Revolution of the state, from 1.
        revolution: u32,
        /// Cam angle of the state within its revolution, degrees.
        cam_deg: f64,
    },
    /// A simulation's solver could not continue, at a cam angle.
    SimulationFailed {
        /// Why.
        failure: SimFailure,
        /// Revolution of the last accepted state, from 1.
        revolution: u32,
        /// Cam angle of the last accepted state within its revolution, degrees.
        cam_deg: f64,
        /// Time of the last accepted state, s.
        t: f64,
    },
}

/// A bound of what the eleven-degree-of-freedom model represents, checked on every
/// accepted state of a simulation (docs/MODEL.md §3.20; the bounds follow from the
/// design: [`crate::ValidityBounds`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelLimit {
    /// The contact penetration y + y1 - y2 above r_min / 100 (r_min the smaller of the
    /// roller and base radii): beyond Hertz's small-contact theory.
    Penetration,
    /// The cantilever e2 - y3 shorter than the roller radius: the roller reaches the
    /// slide bearing (the follower was thrown off the cam).
    CantileverLength,
    /// The follower e1 + y3 between load and slide bearing shorter than the roller
    /// radius: the follower was driven down through its bearing.
    FollowerLength,
    /// An elastic deflection (named) above r_r / 10: the linear supports and the contact
    /// geometry at the undeflected positions no longer hold.
    Deflection(&'static str),
    /// A shaft twist (named) above 0.1 rad: beyond linear torsion.
    Twist(&'static str),
    /// The cam speed at or below zero: the cam stopped or turned backwards.
    CamSpeed,
}

impl ModelLimit {
    /// The quantity, its unit, whether the bound is a lower one (else an upper bound of
    /// the magnitude) and what crossing it means.
    pub fn describe(&self) -> (&'static str, &'static str, bool, &'static str) {
        match *self {
            ModelLimit::Penetration => (
                "contact penetration y + y1 - y2",
                "in",
                false,
                "beyond Hertz's small-contact theory",
            ),
            ModelLimit::CantileverLength => (
                "cantilever length e2 - y3",
                "in",
                true,
                "the roller reaches the slide bearing: the follower was thrown off the cam",
            ),
            ModelLimit::FollowerLength => (
                "follower length e1 + y3",
                "in",
                true,
                "the follower was driven down through its slide bearing",
            ),
            ModelLimit::Deflection(what) => (
                what,
                "in",
                false,
                "beyond the small deflections of the linear supports and the contact geometry",
            ),
            ModelLimit::Twist(what) => (what, "rad", false, "beyond linear torsion"),
            ModelLimit::CamSpeed => (
                "cam speed",
                "rad/s",
                true,
                "the cam stopped or turned backwards: the drive stalled",
            ),
        }
    }
}

/// Why a simulation's solver could not continue ([`Error::SimulationFailed`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SimFailure {
    /// The step size fell to its floor (a fixed fraction of a revolution) and was still
    /// rejected.
    StepSizeUnderflow {
        /// The rejected double step, s.
        h: f64,
    },
    /// A quantity of the state or its rate became NaN or infinite.
    NonFinite {
        /// The quantity (`"load y5 velocity"`).
        quantity: &'static str,
    },
    /// The step budget ran out.
    StepBudget {
        /// Steps taken (accepted and rejected).
        steps: u32,
        /// The budget per revolution, the scene key `solver.max_steps_per_rev`.
        per_revolution: u32,
    },
    /// The cam did not turn far enough within four times the nominal time.
    Stalled,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Error::InvalidParameter { field, rule, value } => {
                // Plain digits, or an exponent where they would run long (1e-300).
                let a = if value < 0.0 { -value } else { value };
                if value == 0.0 || !value.is_finite() || (1e-5..1e16).contains(&a) {
                    write!(f, "{field} = {value}: {rule}")
                } else {
                    write!(f, "{field} = {value:e}: {rule}")
                }
            }
            Error::Inconsistent { field, rule } => write!(f, "{field}: {rule}"),
            Error::Capacity { what, capacity } => {
                write!(f, "{what}: more than the capacity of {capacity}")
            }
            Error::StepSizeUnderflow { t, h } => write!(
                f,
                "step size underflow at t = {t:e} s (h = {h:e} s): the solution changes faster than the smallest step follows"
            ),
            Error::NonFinite { t, component } => {
                write!(f, "state component {component} became non-finite at t = {t:e} s")
            }
            Error::StepBudgetExceeded { t, steps } => {
                write!(f, "step budget of {steps} steps used up at t = {t:e} s")
            }
            Error::NoConvergence { what, iterations } => {
                write!(f, "{what} did not converge in {iterations} iterations")
            }
            Error::NotPositiveDefinite { what } => {
                write!(f, "{what} is not positive definite")
            }
            Error::OutOfModel {
                limit,
                value,
                bound,
                revolution,
                cam_deg,
            } => {
                let (what, unit, lower, why) = limit.describe();
                write!(
                    f,
                    "the model left its valid range at cam angle {cam_deg:.2} deg of revolution {revolution}: {what} = {value:.3e} {unit}, {} its bound {bound:.3e} {unit} ({why})",
                    if lower { "below" } else { "beyond" }
                )
            }
            Error::SimulationFailed {
                failure,
                revolution,
                cam_deg,
                t,
            } => {
                let at = |f: &mut fmt::Formatter<'_>| {
                    write!(
                        f,
                        "at cam angle {cam_deg:.2} deg of revolution {revolution} (t = {t:.6e} s)"
                    )
                };
                match failure {
                    SimFailure::StepSizeUnderflow { h } => {
                        write!(f, "the solver could not continue ")?;
                        at(f)?;
                        write!(
                            f,
                            ": its step fell to {h:.3e} s, its floor (1e-13 of a revolution), and was still rejected: the state changes faster than any step follows"
                        )
                    }
                    SimFailure::NonFinite { quantity } => {
                        write!(f, "the {quantity} became NaN or infinite ")?;
                        at(f)
                    }
                    SimFailure::StepBudget {
                        steps,
                        per_revolution,
                    } => {
                        write!(f, "the step budget ({steps} steps, {per_revolution} a revolution) ran out ")?;
                        at(f)?;
                        write!(f, ": raise solver.max_steps_per_rev")
                    }
                    SimFailure::Stalled => {
                        write!(f, "the cam did not finish its revolutions in four times the nominal time: the drive stalled; last state ")?;
                        at(f)
                    }
                }
            }
        }
    }
}

impl Error {
    /// A short name of the error (no formatting: for logs that cannot afford
    /// `core::fmt`): the key of a parameter, the quantity of a model limit, or the kind.
    pub fn summary(&self) -> &'static str {
        match *self {
            Error::InvalidParameter { field, .. } | Error::Inconsistent { field, .. } => field,
            Error::Capacity { what, .. }
            | Error::NoConvergence { what, .. }
            | Error::NotPositiveDefinite { what } => what,
            Error::StepSizeUnderflow { .. } => "step size underflow",
            Error::NonFinite { .. } => "non-finite state",
            Error::StepBudgetExceeded { .. } => "step budget exceeded",
            Error::OutOfModel { limit, .. } => limit.describe().0,
            Error::SimulationFailed { failure, .. } => match failure {
                SimFailure::StepSizeUnderflow { .. } => "step size underflow",
                SimFailure::NonFinite { quantity } => quantity,
                SimFailure::StepBudget { .. } => "step budget exceeded",
                SimFailure::Stalled => "drive stalled",
            },
        }
    }
}

#[cfg(feature = "std")]
extern crate std;
#[cfg(feature = "std")]
impl std::error::Error for Error {}

/// Result with camsim's [`Error`].
pub type Result<T> = core::result::Result<T, Error>;

/// Checks that `value` is finite and strictly positive.
#[inline]
pub fn positive<T: crate::Real>(field: &'static str, value: T) -> Result<T> {
    if value.is_finite() && value > T::ZERO {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            field,
            rule: "must be positive and finite",
            value: value.to_f64(),
        })
    }
}

/// Checks that `value` is finite and not negative.
#[inline]
pub fn non_negative<T: crate::Real>(field: &'static str, value: T) -> Result<T> {
    if value.is_finite() && value >= T::ZERO {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            field,
            rule: "must be zero or positive and finite",
            value: value.to_f64(),
        })
    }
}

/// Checks that `value` is finite.
#[inline]
pub fn finite<T: crate::Real>(field: &'static str, value: T) -> Result<T> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::InvalidParameter {
            field,
            rule: "must be finite",
            value: value.to_f64(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_print_plain_or_with_an_exponent_when_long() {
        let e = |value: f64| {
            Error::InvalidParameter {
                field: "k",
                rule: "r",
                value,
            }
            .to_string()
        };
        assert_eq!(e(-1.0), "k = -1: r");
        assert_eq!(e(0.375), "k = 0.375: r");
        assert_eq!(e(1.5e6), "k = 1500000: r");
        assert_eq!(e(1e-300), "k = 1e-300: r");
        assert_eq!(e(-2.5e20), "k = -2.5e20: r");
        assert_eq!(e(f64::NAN), "k = NaN: r");
        assert_eq!(e(f64::NEG_INFINITY), "k = -inf: r");
        let i = Error::Inconsistent {
            field: "program.segment[1].law",
            rule: "a dwell takes no motion law",
        };
        assert_eq!(
            i.to_string(),
            "program.segment[1].law: a dwell takes no motion law"
        );
    }
}
