//! One module per `camsim` subcommand.

pub mod bench;
pub mod compare;
pub mod contact;
pub mod design;
pub mod firmware_check;
pub mod jump_speed;
pub mod laws;
pub mod modal;
pub mod models;
pub mod montecarlo;
pub mod predict;
pub mod profile;
pub mod run;
pub mod scene;
pub mod sensitivity;
pub mod sweep;
pub mod tolerance_study;
pub mod waviness;
