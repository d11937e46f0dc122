//! Numerics: England's adaptive Runge-Kutta (Appendix D), its dense output, events and
//! RK4, and its step-size control.

pub(crate) mod controller;
pub(crate) mod solver;
