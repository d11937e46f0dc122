//! The drive and the cam speed it held over the judged revolutions: stated on the drive
//! line for a given drive, warned for one the scene inherits.

use serde::Serialize;

use super::Watch;
use crate::units::Units;

/// The drive and the cam speed it held over the judged revolutions.
#[derive(Clone, Debug, Serialize)]
pub struct DriveVerdict {
    /// The drive: `constant-cam-speed`, `constant-motor-speed`, `regulated` (the thesis's
    /// or a `[design.drive.regulated]` table) or `motor` (a `[design.drive.motor]` table).
    pub drive: &'static str,
    /// What it is, in words.
    pub description: String,
    /// The nominal cam speed ω0, rpm.
    pub nominal_rpm: f64,
    /// Smallest cam speed over the judged revolutions, rpm.
    pub min_cam_speed_rpm: f64,
    /// Largest cam speed over the judged revolutions, rpm.
    pub max_cam_speed_rpm: f64,
    /// The larger of the two deviations from nominal, percent.
    pub swing_percent: f64,
    /// The swing a constant-speed design assumes, percent
    /// ([`camsim_core::CAM_SPEED_SWING_LIMIT`]).
    pub swing_limit_percent: f64,
    /// The drive is given (the reference's, or one the scene names): a swing past the
    /// limit is then part of the result, not a warning. False when a scene names no
    /// drive and inherits the thesis's (docs/MODEL.md §5.17).
    pub given: bool,
}

/// The drive verdict of `spec` from the cam speeds `watch` saw.
pub fn drive(spec: &crate::sim::RunSpec, watch: &Watch, units: Units) -> DriveVerdict {
    use camsim_core::{rad_per_s_to_rpm, DriveLaw};
    let design = &spec.design;
    let w0 = design.omega0;
    let (lo, hi) = watch.cam_speed.unwrap_or((w0, w0));
    let (drive, description) = match design.drive {
        DriveLaw::ConstantCamSpeed => (
            "constant-cam-speed",
            "the cam turns at exactly the nominal speed (kinematic)".to_string(),
        ),
        DriveLaw::ConstantMotorSpeed => (
            "constant-motor-speed",
            "the motor held at the nominal speed; coupling and cam shafts twist".to_string(),
        ),
        DriveLaw::Regulated { k_p, t_max, .. } => (
            if spec.motor_table {
                "motor"
            } else {
                "regulated"
            },
            format!(
                "speed-regulated motor, gain {} {}, torque limit {} {} ({})",
                units.q(camsim_scene_file::units::GAIN, k_p, 1),
                units.symbol(camsim_scene_file::units::GAIN),
                units.q(crate::units::TORQUE, t_max, 1),
                units.symbol(crate::units::TORQUE),
                if spec.motor_table {
                    "the scene's [design.drive.motor]; what it does not give, the thesis's"
                } else if spec.drive_given {
                    "the thesis's motor unless [design.drive.regulated] or [design.drive.motor] says otherwise"
                } else {
                    "inherited: the scene names no drive, so it is the thesis's motor"
                }
            ),
        ),
    };
    DriveVerdict {
        drive,
        description,
        nominal_rpm: rad_per_s_to_rpm(w0),
        min_cam_speed_rpm: rad_per_s_to_rpm(lo),
        max_cam_speed_rpm: rad_per_s_to_rpm(hi),
        swing_percent: 100.0 * ((w0 - lo).max(hi - w0) / w0),
        swing_limit_percent: 100.0 * camsim_core::CAM_SPEED_SWING_LIMIT,
        given: spec.drive_given,
    }
}

/// The verdict's drive line. A given drive's swing past the limit is stated there, as
/// part of the result (an inherited drive's is a warning: [`swing_warning`]).
pub(super) fn drive_text(d: &DriveVerdict, revolutions: [u32; 2]) -> String {
    let limit = if d.given && d.swing_percent > d.swing_limit_percent {
        format!(
            "over the {:.0} % a constant-speed design assumes; the drive is given, so the result includes its speed variation",
            d.swing_limit_percent
        )
    } else {
        format!("limit {:.0} %", d.swing_limit_percent)
    };
    format!(
        "  drive:     {}: {}; cam speed {:.1} to {:.1} rpm over revolutions {}-{}, {:.2} % from the nominal {:.1} rpm ({limit})",
        d.drive,
        d.description,
        d.min_cam_speed_rpm,
        d.max_cam_speed_rpm,
        revolutions[0],
        revolutions[1],
        d.swing_percent,
        d.nominal_rpm,
    )
}

/// The warning on a cam speed that swings past the limit with a drive the scene did not
/// name (inherited from the reference), if it does.
pub fn swing_warning(d: &DriveVerdict) -> Option<String> {
    (!d.given && d.swing_percent > d.swing_limit_percent).then(|| {
        format!(
            "the cam speed swings {:.1} % from the nominal {:.1} rpm ({:.1} to {:.1} rpm; limit {:.0} %): the scene names no drive, so it inherits the thesis's regulated motor (tuned for 800 rpm), which does not hold the speed the kinematic design assumes: name the drive: a [design.drive.motor] table (inertia, shaft_stiffness, gain, torque_limit) for this machine, drive = \"thesis\" to keep this one, or drive = \"constant-cam-speed\" for the kinematic answer",
            d.swing_percent,
            d.nominal_rpm,
            d.min_cam_speed_rpm,
            d.max_cam_speed_rpm,
            d.swing_limit_percent,
        )
    })
}
