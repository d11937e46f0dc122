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
                "step size underflow at t = {t:e} s (h = {h:e} s): tolerance too tight or the system too stiff"
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
