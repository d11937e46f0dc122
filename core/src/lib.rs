#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![doc = include_str!("../README.md")]

mod num;
pub use num::*;
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

// Numerics: England's adaptive Runge-Kutta (Appendix D), modal analysis (VI.2).
mod solver;
pub use solver::*;
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
mod dynamics;
pub use dynamics::*;
mod response;
pub use response::*;

// What a machine feeds the predictor (implemented by the firmware's board modules).
mod machine;
pub use machine::*;
