//! The lift the roller rides on: the theoretical program, or the program plus a profile
//! deviation (an actual, machined or measured cam; docs/MODEL.md §8).
//!
//! The dynamic model ([`crate::CamModel`]) asks its [`LiftProfile`] for the follower lift
//! `y(θ)`, `dy/dθ`, `d²y/dθ²` wherever the equations use the program (the contact
//! approach, the pressure angle, the surface curvature in the Hertz stiffness, the output
//! torque and the relative coordinates). [`TheoreticalLift`] is the program itself, at no
//! cost; [`DeviatedLift`] (`actual/deviation.rs`) adds a periodic spline of the deviation
//! `e(θ)`:
//!
//! ```text
//! y_actual(θ) = y(θ) + e(θ),  dy_actual/dθ = y'(θ) + e'(θ),  …
//! ```
//!
//! Keeping the program's closed form and splining only the deviation means a zero
//! deviation gives back the theoretical cam exactly (not a spline through its points),
//! and the motion law's own discontinuities in acceleration stay where they are.
//!
//! ```
//! use camsim_core::{CamProgram, DeviatedLift, LiftProfile};
//! let program = CamProgram::<f64>::reference();
//! // 0.001 in of once-per-revolution runout, sampled every 10 degrees.
//! let n = 36;
//! let step = 2.0 * core::f64::consts::PI / n as f64;
//! let dev = DeviatedLift::<f64, 64>::uniform(step, n, |k| 1e-3 * (k as f64 * step).cos()).unwrap();
//! let l = dev.follower(&program, 0.0);
//! assert!((l.y - (program.follower(0.0).y + 1e-3)).abs() < 1e-12);
//! ```

use crate::{CamProgram, ContactTerms, FollowerLift, Real};

/// Where the dynamic model takes the follower lift from.
pub trait LiftProfile<T: Real> {
    /// The lift and its cam-angle derivatives at `theta` (rad, any real) for `program`.
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T>;

    /// [`Self::follower`] and, where the profile tabulates them ([`crate::LiftTable`]),
    /// the Hertz contact stiffness and the pressure angle's inverse hypotenuse
    /// ([`ContactTerms`]); `None` leaves them to the closed forms (the model's Eqs.
    /// V.9-V.12 at the lift's curvature, and a square root).
    #[inline(always)]
    fn follower_and_contact<const K: usize>(
        &self,
        program: &CamProgram<T, K>,
        theta: T,
    ) -> (FollowerLift<T>, Option<ContactTerms<T>>) {
        (self.follower(program, theta), None)
    }
}

/// The theoretical cam: the program's closed-form lift (the default of every model).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TheoreticalLift;

impl<T: Real> LiftProfile<T> for TheoreticalLift {
    #[inline(always)]
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T> {
        program.follower(theta)
    }
}

impl<T: Real, L: LiftProfile<T>> LiftProfile<T> for &L {
    #[inline(always)]
    fn follower<const K: usize>(&self, program: &CamProgram<T, K>, theta: T) -> FollowerLift<T> {
        (**self).follower(program, theta)
    }
    #[inline(always)]
    fn follower_and_contact<const K: usize>(
        &self,
        program: &CamProgram<T, K>,
        theta: T,
    ) -> (FollowerLift<T>, Option<ContactTerms<T>>) {
        (**self).follower_and_contact(program, theta)
    }
}
