//! The histograms of a Monte Carlo study (`camsim montecarlo --plot DIR`).

use anyhow::Result;

use super::study::histograms;
use crate::output::AtomicDir;
use crate::study::montecarlo::report::label;
use crate::study::montecarlo::summary::{revolution_value, REVOLUTION_COLUMNS};
use crate::study::montecarlo::SampleRecord;

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["histograms.png", "period_histograms.png"];

/// Draws the histograms of a study's records into `dir`.
pub fn draw(dir: &mut AtomicDir, records: &[SampleRecord], revolution: u32) -> Result<()> {
    let n = records.len();
    let mut panels: Vec<(String, Vec<f64>)> = REVOLUTION_COLUMNS
        .iter()
        .map(|c| {
            (
                format!("revolution {revolution}: {}", label(c)),
                records.iter().map(|r| revolution_value(r, c)).collect(),
            )
        })
        .collect();
    panels.push((
        "profile FPR".into(),
        records.iter().map(|r| r.fpr as f64).collect(),
    ));
    panels.push((
        "profile rms lift deviation, in".into(),
        records.iter().map(|r| r.rms_deviation_in).collect(),
    ));
    let jumps = records.iter().filter(|r| r.jump()).count();
    histograms(
        dir,
        PLOT_FILES[0],
        &format!("{n} actual cams: revolution {revolution}, {jumps} with a jump"),
        &panels,
        4,
    )?;
    let mut panels = Vec::new();
    let names: Vec<String> = records
        .first()
        .map(|r| r.periods.iter().map(|p| p.period.clone()).collect())
        .unwrap_or_default();
    for col in [
        "rms_acceleration",
        "contact_force_min",
        "torque_max",
        "contact_stress_max",
    ] {
        for (k, name) in names.iter().enumerate() {
            panels.push((
                format!("{name}: {}", label(col)),
                records
                    .iter()
                    .filter_map(|r| r.periods.get(k).and_then(|p| p.get(col)))
                    .collect(),
            ));
        }
    }
    histograms(
        dir,
        PLOT_FILES[1],
        &format!("{n} actual cams: revolution {revolution} by period"),
        &panels,
        names.len().max(1),
    )
}
