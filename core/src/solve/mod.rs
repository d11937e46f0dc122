//! Numerics: England's adaptive Runge-Kutta (Appendix D) with its step-size control, its
//! dense output and events, and the classic RK4.

pub(crate) mod controller;
pub(crate) mod dense;
pub(crate) mod england;
pub(crate) mod events;
pub(crate) mod rk4;
pub(crate) mod system;

pub(crate) use dense::Dense;
pub(crate) use england::England;
pub(crate) use system::{OdeSystem, Tolerance};
