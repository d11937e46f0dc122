//! One module per `camsim` subcommand.

pub mod bench;
pub mod compare;
pub mod contact;
pub mod design;
pub mod jump_speed;
pub mod laws;
pub mod modal;
pub mod montecarlo;
pub mod predict;
pub mod run;
pub mod scene;
pub mod scenes;
pub mod sensitivity;
pub mod tolerance_study;
pub mod waviness;
