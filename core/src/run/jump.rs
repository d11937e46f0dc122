//! The jump rule, written once (docs/MODEL.md, the jump criterion): does the follower
//! leave the cam at this speed? [`JumpWatch`] watches the contact during a run and
//! [`jump_verdict`] turns the run's result and the watch into the answer. The CLI's
//! jump-speed search, the bench's onset search and the predictor's steady state
//! ([`crate::steady_state`]) all ask it.

use core::ops::ControlFlow;

use crate::{Observer, Real, Sample};

/// The first revolution in which a separation is a jump: revolution 1 carries the
/// start-up transient from the unloaded chain (docs/MODEL.md), so only a separation from
/// revolution 2 on is the steady-state jump.
pub const STEADY_FROM_REVOLUTION: u32 = 2;

/// Watches the contact of a run for [`jump_verdict`]: whether the follower left the cam at
/// all, and the cam angle of the first separation from [`STEADY_FROM_REVOLUTION`] on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct JumpWatch<T> {
    /// Cam angle of the first separation (revolution 1's transient too), rad.
    pub first_separation: Option<T>,
    /// Cam angle of the first separation in the steady state, rad.
    pub steady_separation: Option<T>,
}

impl<T: Copy> JumpWatch<T> {
    /// A watch that has seen no separation.
    pub fn new() -> Self {
        Self {
            first_separation: None,
            steady_separation: None,
        }
    }

    /// Notes one point of the run at cam angle `theta_c` (rad); `steady`: the point lies
    /// in revolution [`STEADY_FROM_REVOLUTION`] or later. `Break` at the first steady-state
    /// separation (the answer is known).
    pub fn note(&mut self, in_contact: bool, steady: bool, theta_c: T) -> ControlFlow<()> {
        if in_contact {
            return ControlFlow::Continue(());
        }
        self.first_separation.get_or_insert(theta_c);
        if steady {
            self.steady_separation.get_or_insert(theta_c);
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// Notes one sample of [`crate::simulate`] (its revolution decides `steady`).
    pub fn note_sample(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        let steady = s.revolution >= STEADY_FROM_REVOLUTION;
        self.note(s.point.in_contact, steady, s.point.theta_c)
    }

    /// The follower left the cam at some point of the run.
    pub fn separated(&self) -> bool {
        self.first_separation.is_some()
    }
}

/// An observer that only watches the contact; it stops the run at the answer.
impl<T: Real> Observer<T> for JumpWatch<T> {
    fn needs_stress(&self) -> bool {
        false
    }
    fn observe(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        self.note_sample(s)
    }
}

/// What a run says about the jump ([`jump_verdict`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JumpVerdict<T> {
    /// The follower held contact from revolution [`STEADY_FROM_REVOLUTION`] on.
    Holds,
    /// The follower left the cam in the steady state, first at this cam angle (rad).
    Separated {
        /// Cam angle of the first steady-state separation, rad.
        theta_c: T,
    },
    /// The run failed after the follower had left the cam (far above the onset the free
    /// flight and impact drive the model out of the range it represents: its validity
    /// check or the solver stops the run). The follower did not hold contact.
    FailedAfterSeparation {
        /// Cam angle of the first separation, rad.
        theta_c: T,
    },
}

impl<T> JumpVerdict<T> {
    /// The follower jumped (left the cam in the steady state, or the run failed after it
    /// left the cam).
    pub fn jumped(&self) -> bool {
        !matches!(self, JumpVerdict::Holds)
    }
}

/// The jump rule: a separation in revolution [`STEADY_FROM_REVOLUTION`] or later is a jump
/// (whatever the run's result); a run that fails after any separation is a jump; a run
/// that ends without a steady-state separation holds contact; a run that fails before any
/// separation is an error (`result`'s error, passed on).
pub fn jump_verdict<R, E, T: Copy>(
    result: core::result::Result<R, E>,
    watch: &JumpWatch<T>,
) -> core::result::Result<JumpVerdict<T>, E> {
    match (watch.steady_separation, watch.first_separation, result) {
        (Some(theta_c), _, _) => Ok(JumpVerdict::Separated { theta_c }),
        (None, _, Ok(_)) => Ok(JumpVerdict::Holds),
        (None, Some(theta_c), Err(_)) => Ok(JumpVerdict::FailedAfterSeparation { theta_c }),
        (None, None, Err(e)) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rule_in_its_four_cases() {
        let fail: core::result::Result<(), &str> = Err("solver");
        let ok: core::result::Result<(), &str> = Ok(());
        // No separation at all.
        let w = JumpWatch::<f64>::new();
        assert_eq!(jump_verdict(ok, &w), Ok(JumpVerdict::Holds));
        assert_eq!(jump_verdict(fail, &w), Err("solver"));
        // Separation in revolution 1 only: a run that ends holds, a failure is a jump.
        let mut w = JumpWatch::<f64>::new();
        assert_eq!(w.note(true, false, 0.5), ControlFlow::Continue(()));
        assert_eq!(w.note(false, false, 1.0), ControlFlow::Continue(()));
        assert_eq!(w.note(false, false, 1.5), ControlFlow::Continue(()));
        assert_eq!(w.first_separation, Some(1.0));
        assert_eq!(jump_verdict(ok, &w), Ok(JumpVerdict::Holds));
        assert_eq!(
            jump_verdict(fail, &w),
            Ok(JumpVerdict::FailedAfterSeparation { theta_c: 1.0 })
        );
        // A steady-state separation stops the run and is a jump either way.
        assert_eq!(w.note(true, true, 7.0), ControlFlow::Continue(()));
        assert_eq!(w.note(false, true, 7.5), ControlFlow::Break(()));
        assert_eq!(w.note(false, true, 8.0), ControlFlow::Break(()));
        let jumped = Ok(JumpVerdict::Separated { theta_c: 7.5 });
        assert_eq!(jump_verdict(ok, &w), jumped);
        assert_eq!(jump_verdict(fail, &w), jumped);
        assert_eq!(w.first_separation, Some(1.0));
        assert!(!JumpVerdict::<f64>::Holds.jumped());
        assert!(JumpVerdict::Separated { theta_c: 0.0 }.jumped());
        assert!(JumpVerdict::FailedAfterSeparation { theta_c: 0.0 }.jumped());
    }
}
