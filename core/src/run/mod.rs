//! A run of the model: solver settings, the simulation loop and its streaming per-period
//! statistics (VI.4), and the one-dimensional searches over runs (peak scan, jump-onset
//! bracketing and bisection).

pub(crate) mod grid;
pub(crate) mod jump;
pub(crate) mod method;
pub(crate) mod response;
pub(crate) mod search;
