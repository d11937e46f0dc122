//! A run's plots (`camsim run --plot DIR`): the samples' columns ([`PlotData`]), the
//! follower output figures (simulated over theoretical, the deviation below) and the
//! pressure angle, drive train, contact and torque figures.

use anyhow::Result;
use camsim_core::{JumpInterval, Sample};
use camsim_scene_file::units::Unit;

use super::axis::{angle_panel, AngleAxis};
use super::profile::{draw_profile, PROFILE_FILE};
use super::{FOLLOWER_PLOT_SIZE, PLOT_SIZE, SECOND, SIMULATED, THEORY, THIRD};
use crate::figure::{self, Axis, Figure, Series};
use crate::output::AtomicDir;
use crate::sim::HostDeviation;
use crate::units::Units;

/// What the plots need from each sample of a run: one column per quantity, in the
/// units of the plots (angles in degrees).
#[derive(Clone, Debug, Default)]
pub struct PlotData {
    /// Continuous cam angle θ_c, degrees (360 per revolution from the start).
    pub angle_deg: Vec<f64>,
    /// Follower (load) displacement, in.
    pub y: Vec<f64>,
    /// Theoretical displacement, in.
    pub y_theory: Vec<f64>,
    /// Follower (load) velocity, in/s.
    pub v: Vec<f64>,
    /// Theoretical velocity, in/s.
    pub v_theory: Vec<f64>,
    /// Follower (load) acceleration, in/s².
    pub a: Vec<f64>,
    /// Theoretical acceleration, in/s².
    pub a_theory: Vec<f64>,
    /// Pressure angle φ, degrees.
    pub pressure_angle_deg: Vec<f64>,
    /// Motor speed θ̇_m, rad/s.
    pub omega_m: Vec<f64>,
    /// Coupling speed θ̇_cp, rad/s.
    pub omega_cp: Vec<f64>,
    /// Cam speed θ̇_c, rad/s.
    pub omega_c: Vec<f64>,
    /// Contact force F_c (Eq. V.19), lb.
    pub contact_force: Vec<f64>,
    /// Maximum Hertz contact stress, psi.
    pub contact_stress: Vec<f64>,
    /// Output torque on the cam T_o (Eq. IV.1), lb·in.
    pub torque_out: Vec<f64>,
    /// Torque delivered by the drive, lb·in.
    pub torque_drive: Vec<f64>,
    /// Whether the follower touches the cam (false while it jumps, Eq. V.20).
    pub in_contact: Vec<bool>,
    /// Continuous cam angles, degrees, where a new program period (segment) begins.
    pub period_starts_deg: Vec<f64>,
    last_period: Option<(u32, usize)>,
}

impl PlotData {
    /// Records one sample of a run.
    pub fn push(&mut self, s: &Sample<f64>) {
        let p = &s.point;
        let angle = p.theta_c.to_degrees();
        let period = (s.revolution, s.segment);
        if self.last_period.is_some_and(|q| q != period) {
            self.period_starts_deg.push(angle);
        }
        self.last_period = Some(period);
        self.angle_deg.push(angle);
        self.y.push(p.load_displacement());
        self.y_theory.push(s.theory.y);
        self.v.push(p.load_velocity());
        self.v_theory.push(s.theory.v);
        self.a.push(p.load_acceleration());
        self.a_theory.push(s.theory.a);
        self.pressure_angle_deg.push(p.pressure_angle.to_degrees());
        self.omega_m.push(p.omega_m);
        self.omega_cp.push(p.omega_cp);
        self.omega_c.push(p.omega_c);
        self.contact_force.push(p.contact_force);
        self.contact_stress.push(s.contact_stress);
        self.torque_out.push(p.torque_out);
        self.torque_drive.push(p.torque_drive);
        self.in_contact.push(p.in_contact);
    }

    /// The intervals (continuous cam angle, degrees) where the samples show the follower
    /// off the cam: from the first sample off contact to the first one back on (or the
    /// last sample).
    pub fn off_cam_intervals(&self) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        let mut start = None;
        let mut last = None;
        for (&x, &on) in self.angle_deg.iter().zip(&self.in_contact) {
            match (start, on) {
                (None, false) => start = Some(x),
                (Some(a), true) => {
                    out.push((a, x));
                    start = None;
                }
                _ => {}
            }
            last = Some(x);
        }
        if let (Some(a), Some(b)) = (start, last) {
            out.push((a, b));
        }
        out
    }

    /// Number of recorded samples.
    pub fn len(&self) -> usize {
        self.angle_deg.len()
    }

    /// Whether no sample was recorded.
    pub fn is_empty(&self) -> bool {
        self.angle_deg.is_empty()
    }
}

/// One run plot: its file and its figure.
pub(super) type RunFigure = (&'static str, Figure);

/// A follower output figure: simulated over theoretical, and their difference below.
fn follower_figure(
    axis: &AngleAxis,
    xs: &[f64],
    (title, quantity, unit): (&str, &str, Unit),
    sim: &[f64],
    theory: &[f64],
) -> Figure {
    let dev: Vec<f64> = sim.iter().zip(theory).map(|(s, t)| s - t).collect();
    let curves = vec![
        Series::of("simulated", xs, sim, figure::Stroke::solid(SIMULATED, 2)),
        Series::of(
            "theoretical (rigid system at ω₀)",
            xs,
            theory,
            figure::Stroke::dashed(THEORY, 2),
        ),
    ];
    let deviation = vec![Series::of(
        "simulated − theoretical",
        xs,
        &dev,
        figure::Stroke::solid(SIMULATED, 1),
    )];
    let mut fig = Figure::new(
        title,
        FOLLOWER_PLOT_SIZE,
        vec![
            angle_panel(axis, Axis::of(quantity, unit), curves, false),
            angle_panel(axis, Axis::of("deviation", unit), deviation, true),
        ],
    );
    fig.row_weights = vec![3, 2];
    fig
}

/// A one-panel figure against cam angle.
fn single(axis: &AngleAxis, title: &str, y: Axis, curves: Vec<Series>) -> Figure {
    Figure::new(title, PLOT_SIZE, vec![angle_panel(axis, y, curves, true)])
}

/// Every figure `draw_all` writes, in order, with its file; the values in the inch
/// family, each axis naming its quantity.
pub(super) fn figures(d: &PlotData, axis: &AngleAxis) -> Vec<RunFigure> {
    use crate::units::ACCELERATION;
    use camsim_scene_file::units::{LENGTH, SPEED};
    let xs = &d.angle_deg;
    let follower = |title, q: &str, u, sim: &[f64], th: &[f64]| {
        follower_figure(axis, xs, (title, q, u), sim, th)
    };
    let mut v = vec![
        (
            FILES[0],
            follower(
                "Follower (load) displacement",
                "displacement y",
                LENGTH,
                &d.y,
                &d.y_theory,
            ),
        ),
        (
            FILES[1],
            follower(
                "Follower (load) velocity",
                "velocity",
                SPEED,
                &d.v,
                &d.v_theory,
            ),
        ),
        (
            FILES[2],
            follower(
                "Follower (load) acceleration",
                "acceleration",
                ACCELERATION,
                &d.a,
                &d.a_theory,
            ),
        ),
    ];
    v.extend(FILES.iter().skip(3).copied().zip(drive_figures(d, axis)));
    v
}

/// The pressure angle, drive train, contact and torque figures, in [`FILES`]' order.
fn drive_figures(d: &PlotData, axis: &AngleAxis) -> Vec<Figure> {
    use crate::units::FORCE;
    use camsim_scene_file::units::{STRESS, TORQUE};
    let s = |label: &str, v: &[f64], c, w| {
        Series::of(label, &d.angle_deg, v, figure::Stroke::solid(c, w))
    };
    let one = |title, y, curves| single(axis, title, y, curves);
    vec![
        one(
            "Pressure angle φ",
            Axis::plain("pressure angle φ", "deg"),
            vec![s("φ", &d.pressure_angle_deg, SIMULATED, 2)],
        ),
        one(
            "Angular velocities of the drive train",
            Axis::plain("angular velocity", "rad/s"),
            vec![
                s("motor", &d.omega_m, SECOND, 4),
                s("coupling", &d.omega_cp, THIRD, 2),
                s("cam", &d.omega_c, SIMULATED, 1),
            ],
        ),
        one(
            "Cam-follower contact force F_c",
            Axis::of("contact force Fc", FORCE),
            vec![s("F_c", &d.contact_force, SIMULATED, 2)],
        ),
        one(
            "Maximum Hertz contact stress",
            Axis::of("contact stress", STRESS),
            vec![s("stress", &d.contact_stress, SIMULATED, 2)],
        ),
        one(
            "Cam torque",
            Axis::of("torque", TORQUE),
            vec![
                s("output torque T_o", &d.torque_out, SIMULATED, 2),
                s("drive torque", &d.torque_drive, SECOND, 2),
            ],
        ),
    ]
}

/// The files `--plot DIR` writes, in the order they are drawn.
pub const FILES: [&str; 8] = [
    "displacement.png",
    "velocity.png",
    "acceleration.png",
    "pressure_angle.png",
    "angular_velocity.png",
    "contact_force.png",
    "contact_stress.png",
    "torque.png",
];

/// The files `--plot DIR` writes for an actual or measured cam: [`FILES`] and
/// [`PROFILE_FILE`].
pub const FILES_WITH_PROFILE: [&str; 9] = [
    FILES[0],
    FILES[1],
    FILES[2],
    FILES[3],
    FILES[4],
    FILES[5],
    FILES[6],
    FILES[7],
    PROFILE_FILE,
];

/// Draws every plot of a run ([`FILES`]) as PNG into the directory output `out` (each
/// file to its temporary: the caller commits `out`).
pub fn draw_all(
    out: &mut AtomicDir,
    data: &PlotData,
    jumps: &[JumpInterval<f64>],
    units: Units,
) -> Result<()> {
    let axis = AngleAxis::new(data, jumps);
    for (file, fig) in figures(data, &axis) {
        figure::draw(out, file, &fig, units)?;
    }
    Ok(())
}

/// Draws a run's figures ([`FILES`]) and, for an actual or measured cam, its profile's
/// ([`PROFILE_FILE`]) into `out`, returned for the caller to commit.
pub fn draw_run(
    mut out: AtomicDir,
    data: &PlotData,
    jumps: &[JumpInterval<f64>],
    profile: Option<&HostDeviation>,
    units: Units,
) -> Result<AtomicDir> {
    draw_all(&mut out, data, jumps, units)?;
    if let Some(dev) = profile {
        draw_profile(&mut out, data, dev, units)?;
    }
    Ok(out)
}

#[cfg(test)]
mod pixels;
#[cfg(test)]
pub(super) mod tests;
