//! The histograms of a Monte Carlo study (`camsim montecarlo --plot DIR`), drawn from
//! the streamed statistics' histograms.

use anyhow::Result;

use super::study::{histograms_binned, Binned};
use crate::output::AtomicDir;
use crate::study::montecarlo::report::label;
use crate::study::montecarlo::{StudyStats, COLUMNS, REVOLUTION_COLUMNS};

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["histograms.png", "period_histograms.png"];

/// Draws the histograms of a study's statistics into `dir` (from each stream's
/// histogram: counts of samples, the bins of each panel equal over its range).
pub fn draw(dir: &mut AtomicDir, stats: &StudyStats, revolution: u32) -> Result<()> {
    let n = stats.samples;
    let bins = ((n as f64).sqrt().ceil() as usize).clamp(5, 50);
    let mut panels: Vec<(String, Binned)> = REVOLUTION_COLUMNS
        .iter()
        .zip(&stats.whole_revolution)
        .map(|(c, s)| {
            (
                format!("revolution {revolution}: {}", label(c)),
                s.display_bins(bins),
            )
        })
        .collect();
    panels.push(("profile FPR".into(), stats.fpr.display_bins(bins)));
    panels.push((
        "profile rms lift deviation, in".into(),
        stats.rms_deviation_in.display_bins(bins),
    ));
    histograms_binned(
        dir,
        PLOT_FILES[0],
        &format!(
            "{n} actual cams: revolution {revolution}, {} with a jump",
            stats.jumps
        ),
        &panels,
        4,
    )?;
    let mut panels = Vec::new();
    for col in [
        "rms_acceleration",
        "contact_force_min",
        "torque_max",
        "contact_stress_max",
    ] {
        let c = COLUMNS.iter().position(|x| *x == col);
        for p in &stats.periods {
            if let Some(s) = c.and_then(|c| p.columns.get(c)) {
                panels.push((
                    format!("{}: {}", p.period, label(col)),
                    s.display_bins(bins),
                ));
            }
        }
    }
    histograms_binned(
        dir,
        PLOT_FILES[1],
        &format!("{n} actual cams: revolution {revolution} by period"),
        &panels,
        stats.periods.len().max(1),
    )
}
