#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![doc = include_str!("../README.md")]

mod num;
pub use num::*;
mod error;
pub use error::*;

// Kinematics: Appendix A motion laws, cam programs, cam geometry (V.1-V.4, V.12, E.6).
mod motion;
pub use motion::*;
mod program;
pub use program::*;
mod geometry;
pub use geometry::*;

// Forces: Hertz contact and jump (V.9-V.11, V.19-V.20), return spring (V.17-V.18),
// slide-bearing friction (V.15-V.16).
mod contact;
pub use contact::*;
mod spring;
pub use spring::*;

// Numerics: England's adaptive Runge-Kutta (Appendix D), modal analysis (VI.2).
mod solver;
pub use solver::*;
mod modal;
pub use modal::*;
