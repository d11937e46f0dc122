//! `--plot DIR` (placeholder until the plots land).

use anyhow::Result;
use camsim_core::{JumpInterval, Sample};

/// What the plots need from each sample.
#[derive(Default)]
pub struct PlotData {}

impl PlotData {
    /// Takes one sample.
    pub fn push(&mut self, _s: &Sample<f64>) {}
}

/// Writes every plot into `dir`.
pub fn write_all(
    _dir: &std::path::Path,
    _data: &PlotData,
    _jumps: &[JumpInterval<f64>],
) -> Result<()> {
    anyhow::bail!("--plot: not available yet")
}
