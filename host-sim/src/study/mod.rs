//! The studies as a library: each computes its report from a scene and options, with no
//! command-line parsing (the thin `cmd` module of each parses, prints and writes files).

pub mod contact;
pub mod jump_speed;
pub mod jump_speed_actual;
pub mod montecarlo;
