//! Numerics: England's adaptive Runge-Kutta (Appendix D) with its step-size control, its
//! dense output and events, the classic RK4, and Merson's 4(3) pair for the imaginary axis.

pub(crate) mod controller;
pub(crate) mod dense;
pub(crate) mod england;
pub(crate) mod events;
pub(crate) mod imaginary;
pub(crate) mod rk4;
pub(crate) mod system;

pub(crate) use dense::Dense;
pub(crate) use england::England;
pub(crate) use system::{OdeSystem, Tolerance};
