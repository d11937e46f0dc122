//! Forces and power: the peak cam torque and motor power, and the peak Hertz contact
//! stress against the allowable.

use anyhow::Result;
use serde::Serialize;

use super::{at_text, At, Limits, Watch};
use crate::units::{Power, Stress, Torque, Units};

/// One horsepower, lb·in/s.
pub const HP_LB_IN_PER_S: f64 = 6600.0;

/// One lb·in/s in watts.
pub const W_PER_LB_IN_PER_S: f64 = 0.112_984_829;

/// Forces and power.
#[derive(Clone, Debug, Serialize)]
pub struct LoadsVerdict {
    /// Largest |output torque on the cam| T_o, lb·in (signed).
    pub peak_cam_torque_lb_in: Torque,
    /// Where.
    pub peak_cam_torque_at: At,
    /// Largest motor power T_i ω_m, hp.
    pub peak_motor_power_hp: Power,
    /// The same, W.
    pub peak_motor_power_w: f64,
    /// Where.
    pub peak_motor_power_at: At,
    /// Largest Hertz contact stress, psi.
    pub peak_contact_stress_psi: Stress,
    /// Where.
    pub peak_contact_stress_at: At,
    /// The allowable, psi.
    pub allowable_contact_stress_psi: Stress,
    /// Where the default allowable comes from.
    pub allowable_source: &'static str,
    /// Peak stress over the allowable.
    pub stress_ratio: f64,
}

/// The loads verdict from the watch.
pub fn loads(watch: &Watch, limits: &Limits) -> Result<LoadsVerdict> {
    let missing = || anyhow::anyhow!("no sample in the judged revolutions");
    let (t, t_at) = watch.peak_torque.ok_or_else(missing)?;
    let (p, p_at) = watch.peak_power.ok_or_else(missing)?;
    let (s, s_at) = watch.peak_stress.ok_or_else(missing)?;
    Ok(LoadsVerdict {
        peak_cam_torque_lb_in: Torque::inch(t),
        peak_cam_torque_at: t_at,
        peak_motor_power_hp: Power::inch(p / HP_LB_IN_PER_S),
        peak_motor_power_w: p * W_PER_LB_IN_PER_S,
        peak_motor_power_at: p_at,
        peak_contact_stress_psi: Stress::inch(s),
        peak_contact_stress_at: s_at,
        allowable_contact_stress_psi: Stress::inch(limits.allowable_contact_stress_psi),
        allowable_source: limits.allowable_source,
        stress_ratio: s / limits.allowable_contact_stress_psi,
    })
}

/// The verdict's loads lines: the peak cam torque and motor power, and the peak contact
/// stress against the allowable.
pub(super) fn loads_lines(out: &mut String, l: &LoadsVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "  loads:     peak cam torque {} {} at {}; peak motor power {} at {}",
        units.show(l.peak_cam_torque_lb_in, 1),
        units.symbol(u::TORQUE),
        at_text(&l.peak_cam_torque_at),
        match units {
            u::Units::Inch => format!(
                "{:.3} hp ({:.0} W)",
                l.peak_motor_power_hp.in_inch(),
                l.peak_motor_power_w
            ),
            u::Units::Si => format!("{:.3} kW", l.peak_motor_power_w / 1000.0),
        },
        at_text(&l.peak_motor_power_at)
    );
    let _ = writeln!(
        out,
        "             peak contact stress {} {su} at {}: {:.0} % of the allowable {} {su} ({})",
        units.show(l.peak_contact_stress_psi, 0),
        at_text(&l.peak_contact_stress_at),
        100.0 * l.stress_ratio,
        units.show(l.allowable_contact_stress_psi, 0),
        l.allowable_source,
        su = units.symbol(u::STRESS)
    );
}
