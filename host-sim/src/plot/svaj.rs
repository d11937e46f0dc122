//! The SVAJ plot of a cam program (`profile --plot`): lift, velocity, acceleration
//! and jerk against cam angle at the design's speed.

use anyhow::Result;

use super::axis::{angle_panel, AngleAxis};
use super::run::PlotData;
use super::{SECOND, SIMULATED, SVAJ_PLOT_SIZE, THEORY, THIRD};
use crate::figure::{self, Axis, Figure, Series};
use crate::output::AtomicDir;
use crate::units::Units;

/// Points of the SVAJ plot over one revolution (0.05°).
const SVAJ_SAMPLES: usize = 7200;

/// The SVAJ figure of `design`'s program (DYNACAM's S, V, A, J diagram): lift,
/// velocity, acceleration and jerk against cam angle, the derivatives in time at the
/// design's speed ω0 (v = ω dy/dθ, a = ω² d²y/dθ², j = ω³ d³y/dθ³), the segment
/// boundaries marked.
fn svaj_figure(design: &camsim_core::Design<f64>) -> Figure {
    let w = design.omega0;
    let rpm = camsim_core::rad_per_s_to_rpm(w);
    let mut axis_data = PlotData::default();
    let (mut s, mut v, mut a, mut j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..=SVAJ_SAMPLES {
        let deg = k as f64 * 360.0 / SVAJ_SAMPLES as f64;
        let f = design.program.follower(deg.to_radians());
        axis_data.angle_deg.push(deg);
        s.push(f.y);
        v.push(f.dy * w);
        a.push(f.d2y * w * w);
        j.push(f.d3y * w * w * w);
    }
    axis_data.period_starts_deg = design
        .program
        .segments()
        .iter()
        .map(|g| g.start_deg)
        .filter(|d| *d > 0.0 && *d < 360.0)
        .collect();
    let mut axis = AngleAxis::new(&axis_data, &[]);
    axis.run = false;
    let xs = &axis_data.angle_deg;
    use crate::units::{ACCELERATION, JERK};
    use camsim_scene_file::units::{LENGTH, SPEED};
    let panel = |title: String, label: &str, values: &[f64], c, unit, last| {
        let curve = Series::of(label, xs, values, figure::Stroke::solid(c, 2));
        angle_panel(&axis, Axis::of(&title, unit), vec![curve], last)
    };
    Figure::new(
        format!("SVAJ of the cam program at {rpm:.0} rpm (grey lines: segment boundaries)"),
        SVAJ_PLOT_SIZE,
        vec![
            panel("lift s".into(), "lift s", &s, SIMULATED, LENGTH, false),
            panel(
                format!("velocity v at {rpm:.0} rpm"),
                "velocity v",
                &v,
                SECOND,
                SPEED,
                false,
            ),
            panel(
                format!("acceleration a at {rpm:.0} rpm"),
                "acceleration a",
                &a,
                THEORY,
                ACCELERATION,
                false,
            ),
            panel(
                format!("jerk j at {rpm:.0} rpm"),
                "jerk j",
                &j,
                THIRD,
                JERK,
                true,
            ),
        ],
    )
}

/// Draws the SVAJ plot of `design`'s program as `file` into `out`.
pub fn draw_svaj(
    out: &mut AtomicDir,
    design: &camsim_core::Design<f64>,
    file: &'static str,
    units: Units,
) -> Result<()> {
    figure::draw(out, file, &svaj_figure(design), units)
}
