#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![doc = include_str!("../README.md")]

mod num;
pub use num::*;
// One-dimensional searches (peak scan, jump-onset bracketing and bisection).
mod search;
pub use search::*;
mod error;
pub use error::*;
// Scene keys: the serde names of the design's parameters and the names errors use.
mod keys;
pub use keys::key;

// Kinematics: Appendix A motion laws, cam programs, cam geometry (V.1-V.4, V.12, E.6).
mod motion;
pub use motion::*;
mod program;
pub use program::*;
mod geometry;
pub use geometry::*;

// Forces: Hertz contact and jump (V.9-V.11, V.19-V.20) with the damping at the roller
// (V.13), return spring (V.17-V.18), slide-bearing friction (V.15-V.16).
mod contact;
pub use contact::*;
mod spring;
pub use spring::*;

// Numerics: England's adaptive Runge-Kutta (Appendix D) and its step-size control,
// modal analysis (VI.2).
mod solver;
pub use solver::*;
mod controller;
pub use controller::*;
mod modal;
pub use modal::*;

// The eleven-degree-of-freedom model (Eqs. IV.1-IV.3): the reference design of VI.1,
// the motor law, the scenes (state layouts fixed at compile time), the model itself and
// its streaming per-period responses.
mod design;
pub use design::*;
mod drive;
pub use drive::*;
mod scene;
pub use scene::*;
mod quasistatic;
pub use quasistatic::*;
mod dynamics;
pub use dynamics::*;
mod response;
pub use response::*;

// The cam-timing and jump predictor: what a machine feeds it (implemented by the
// firmware's board modules), the alarm, the steady-state observer and the boot-time table.
mod predict;
pub use predict::*;

// Stochastic profile (IV.2, Appendices B, C, E): random numbers, cubic splines,
// waviness (FPR, VI.4.1), the actual cam contour and follower lift.
mod random;
pub use random::*;
mod spline;
pub use spline::*;
mod waviness;
pub use waviness::*;
mod profile;
pub use profile::*;
// The exact envelope of the roller circle on an actual contour (beyond the thesis).
mod envelope;
pub use envelope::*;
// The lift the model's roller rides on: the program, or the program plus a deviation.
mod lift;
pub use lift::*;

// Cam speed from a once-per-revolution index pulse: captured timer counts to rpm, with
// bounce rejection, timeout and range check (fed by the firmware's board adapters).
mod index_pulse;
pub use index_pulse::*;
