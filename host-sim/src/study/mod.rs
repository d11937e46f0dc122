//! The studies as a library: each computes its report from a scene and options, with no
//! command-line parsing (the thin `cmd` module of each parses, prints and writes files).

pub mod coil_spring;
pub mod compare;
pub mod contact;
pub mod design;
pub mod firmware_check;
pub mod jump_speed;
/// `jump-speed --actual` (now [`jump_speed::actual`]), at its former path.
pub use jump_speed::actual as jump_speed_actual;
pub mod laws;
pub mod modal;
pub mod models;
pub mod montecarlo;
pub mod predict;
pub mod profile;
pub mod run;
pub mod sensitivity;
pub mod sweep;
pub mod tolerance;
pub mod waviness;

/// A local pool of `threads` worker threads (at least one) for a study's independent runs,
/// each with a 16 MB stack (a sample's profile, three arrays of 3601 f64, is built on the
/// stack). The results never depend on the thread count: every study collects by index.
pub fn pool(threads: usize) -> anyhow::Result<rayon::ThreadPool> {
    use anyhow::Context;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .stack_size(16 << 20)
        .build()
        .context("cannot start the worker threads")
}
