//! The verdict's argument group (`camsim run`): the limits it judges against and whether
//! it searches the jump onset.

use crate::units::Units;

/// What the verdict that opens `camsim run` judges against.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct VerdictArgs {
    /// Allowable Hertz contact stress, psi, or with its unit (1034MPa), 1 000 to
    /// 1 000 000 psi (default: the scene's limits.allowable_contact_stress_psi or _mpa,
    /// else 150 000 psi = 1034 MPa: through-hardened steel at 400 HB, 1e8 cycles,
    /// Buckingham's S_C = 0.4 H_B - 10 kpsi = 2.76 H_B - 70 MPa as Shigley gives it).
    #[arg(long, value_name = "PSI", allow_hyphen_values = true, value_parser = super::allowable_stress)]
    pub allowable_stress: Option<f64>,
    /// Largest pressure angle without a warning, degrees (default: the scene's
    /// limits.pressure_angle_limit_deg, else 30, the usual limit for a translating
    /// follower; 0-90).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = super::pressure_angle_limit)]
    pub pressure_angle_limit: Option<f64>,
    /// Also find the jump onset and the margin to it (a bisection of about 15
    /// two-revolution runs from the static start, as `camsim jump-speed`).
    #[arg(long)]
    pub margin: bool,
}

impl VerdictArgs {
    /// The limits asked for, the scene's (`[limits]`, or the defaults) otherwise.
    pub fn limits(
        &self,
        scene: &camsim_scene_file::Limits,
        units: Units,
    ) -> crate::verdict::Limits {
        crate::verdict::Limits {
            // The option is read in psi (its parser converts a value given in MPa).
            allowable_contact_stress_psi: self
                .allowable_stress
                .unwrap_or(scene.allowable_contact_stress_psi),
            pressure_angle_limit_deg: self
                .pressure_angle_limit
                .unwrap_or(scene.pressure_angle_limit_deg),
            allowable_source: if self.allowable_stress.is_some() {
                "--allowable-stress"
            } else if scene.allowable_contact_stress_psi
                != camsim_core::ALLOWABLE_CONTACT_STRESS_PSI
            {
                "the scene's [limits]"
            } else {
                crate::verdict::allowable_source(units)
            },
        }
    }
}
