//! The verdict's warnings: pressure angle, undercut, contact stress, spring surge, the
//! spring part's stress and solid height, and a jump onset at or below the operating
//! speed.

use super::{
    spring_part_warnings, ContactVerdict, GeometryVerdict, LoadsVerdict, MarginVerdict,
    SpringVerdict,
};
use crate::units::Units;

/// The warnings of a verdict (pressure angle, undercut, stress, surge, separation).
pub fn warnings(
    contact: &ContactVerdict,
    geometry: &GeometryVerdict,
    loads: &LoadsVerdict,
    spring: &SpringVerdict,
    margin: Option<&MarginVerdict>,
    units: Units,
) -> Vec<String> {
    use crate::units as u;
    let mut w = Vec::new();
    if !contact.holds {
        w.push(format!(
            "the follower leaves the cam {} time(s) in revolutions {}-{}, {:.2} deg of cam angle in all",
            contact.separations.len(),
            contact.revolutions[0],
            contact.revolutions[1],
            contact.off_cam_deg
        ));
    }
    if geometry.max_pressure_angle_deg > geometry.pressure_angle_limit_deg {
        w.push(format!(
            "pressure angle {:.1} deg at cam angle {:.1} deg exceeds the limit {:.1} deg (limits.pressure_angle_limit_deg, --pressure-angle-limit)",
            geometry.max_pressure_angle_deg,
            geometry.max_pressure_angle_at_deg,
            geometry.pressure_angle_limit_deg
        ));
    }
    if geometry.undercut_margin_in.in_inch() <= 0.0 {
        w.push(format!(
            "undercut: the pitch curve's radius {} {} at {:.1} deg is below the roller radius",
            units.show(geometry.min_pitch_radius_in, 4),
            units.symbol(u::LENGTH),
            geometry.min_pitch_radius_at_deg
        ));
    }
    if loads.stress_ratio > 1.0 {
        w.push(format!(
            "contact stress {} {su} exceeds the allowable {} {su} by {:.1} % (limits.allowable_contact_stress_{}, --allowable-stress)",
            units.show(loads.peak_contact_stress_psi, 0),
            units.show(loads.allowable_contact_stress_psi, 0),
            100.0 * (loads.stress_ratio - 1.0),
            units.key_suffix(u::STRESS),
            su = units.symbol(u::STRESS)
        ));
    }
    if spring.surge_harmonic < spring.least_harmonic {
        w.push(format!(
            "spring surge {:.0} Hz is only {:.1} times the cam's {:.2} Hz: harmonic {} of the cam motion excites it (keep the surge above the {:.0}th harmonic: a stiffer, lighter spring)",
            spring.surge_hz,
            spring.surge_harmonic,
            spring.cam_hz,
            spring.surge_harmonic.round().max(1.0),
            spring.least_harmonic
        ));
    }
    w.extend(spring_part_warnings(spring, units));
    if let Some(m) = margin {
        if let Some(p) = m.margin_percent {
            if p <= 0.0 {
                w.push(format!(
                    "the jump onset {:.1} rpm is at or below the operating speed",
                    m.jump_onset_rpm.unwrap_or(f64::NAN)
                ));
            }
        }
    }
    w
}
