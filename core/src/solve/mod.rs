//! Numerics: England's adaptive Runge-Kutta (Appendix D) with its step-size control, its
//! dense output and events, the classic RK4, and embedded pairs as data
//! (Merson's 4(3) for the imaginary axis, Dormand-Prince's 5(4) for accuracy-limited runs).

pub(crate) mod dense;
#[cfg(feature = "pairs")]
pub(crate) mod dormand_prince;
pub(crate) mod england;
pub(crate) mod events;
#[cfg(feature = "pairs")]
pub(crate) mod imaginary;
#[cfg(feature = "pairs")]
pub(crate) mod pair;
pub(crate) mod rk4;
pub(crate) mod spectral_radius;
pub(crate) mod step_control;
pub(crate) mod step_size;
pub(crate) mod system;

pub(crate) use dense::Dense;
pub(crate) use england::England;
pub(crate) use system::{OdeSystem, Tolerance};
