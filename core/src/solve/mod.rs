//! Numerics: England's adaptive Runge-Kutta (Appendix D), its dense output, events and
//! RK4, and its step-size control; Merson's 4(3) pair for the imaginary axis.

pub(crate) mod controller;
pub(crate) mod imaginary;
pub(crate) mod solver;
