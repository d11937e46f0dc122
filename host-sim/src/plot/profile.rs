//! The profile deviation plot of an actual or measured cam (`run --plot` and
//! `profile --plot` with `--actual`): the lift deviation and its slope over one
//! revolution.

use anyhow::Result;

use super::axis::{angle_panel, AngleAxis};
use super::run::PlotData;
use super::{FOLLOWER_PLOT_SIZE, SECOND, SIMULATED};
use crate::figure::{self, Axis, Figure, Series};
use crate::output::AtomicDir;
use crate::sim::HostDeviation;
use crate::units::Units;

/// The file of the profile deviation plot (actual and measured cams).
pub const PROFILE_FILE: &str = "profile_deviation.png";

/// Points of the profile plot over one revolution (0.05°).
const PROFILE_SAMPLES: usize = 7200;

/// The profile deviation figure: the lift deviation `e(θ)` over one revolution and,
/// below it, its slope `de/dθ` (whose local extrema FPR counts), with the run's period
/// starts of the first revolution (`periods`) marked.
fn profile_figure(dev: &HostDeviation, periods: Vec<f64>) -> Figure {
    let step = 360.0 / PROFILE_SAMPLES as f64;
    let mut axis_data = PlotData::default();
    let (mut e, mut de) = (Vec::new(), Vec::new());
    for k in 0..=PROFILE_SAMPLES {
        let deg = k as f64 * step;
        let p = dev.deviation(deg.to_radians());
        axis_data.angle_deg.push(deg);
        e.push(p.y);
        de.push(p.dy);
    }
    axis_data.period_starts_deg = periods;
    let axis = AngleAxis::new(&axis_data, &[]);
    let xs = &axis_data.angle_deg;
    let e = Series::of("e(θ)", xs, &e, figure::Stroke::solid(SIMULATED, 1));
    let de = Series::of(
        "de/dθ (FPR counts its extrema)",
        xs,
        &de,
        figure::Stroke::solid(SECOND, 1),
    );
    use camsim_scene_file::units::LENGTH;
    Figure::new(
        "Profile deviation of the actual cam (lift − program)",
        FOLLOWER_PLOT_SIZE,
        vec![
            angle_panel(&axis, Axis::of("lift deviation e", LENGTH), vec![e], false),
            angle_panel(
                &axis,
                Axis::of("de/dθ", crate::units::LENGTH_PER_RAD),
                vec![de],
                true,
            ),
        ],
    )
}

/// Draws the profile deviation plot ([`PROFILE_FILE`]) into `out`; `data` gives the
/// period starts of the run's first revolution.
pub fn draw_profile(
    out: &mut AtomicDir,
    data: &PlotData,
    dev: &HostDeviation,
    units: Units,
) -> Result<()> {
    let periods = data
        .period_starts_deg
        .iter()
        .copied()
        .filter(|p| *p > 0.0 && *p < 360.0)
        .collect();
    figure::draw(out, PROFILE_FILE, &profile_figure(dev, periods), units)
}
