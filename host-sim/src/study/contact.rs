//! The Hertz contact of `camsim contact`: stiffness (Eqs. V.9-V.11), contact width and
//! maximum Hertz stress of a roller on a base circle at one force.

use anyhow::{bail, Context};
use camsim_core::HertzContact;
use serde::Serialize;

use crate::report::Report;
use crate::units::{Force, Length, Stiffness, Stress, Units};

/// Reference roller diameter d1 (in, VI.1).
pub const ROLLER_DIAMETER_IN: f64 = 0.75;
/// Reference base-circle diameter d2 (in, VI.1).
pub const BASE_CIRCLE_DIAMETER_IN: f64 = 3.0;
/// Reference cam thickness t (in, docs/MODEL.md §5.5).
pub const CAM_THICKNESS_IN: f64 = 0.25;

/// Contact quantities of the reference pair at one force.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactReport {
    /// Roller radius r1, in.
    pub roller_radius_in: Length,
    /// Base-circle radius r2, in.
    pub base_radius_in: Length,
    /// Contact length (cam thickness) t, in.
    pub thickness_in: Length,
    /// The force F (lb).
    pub force_lb: Force,
    /// K_h of Eq. V.11 (band width at 1 lb), lb/in.
    pub k_h_lb_per_in: Stiffness,
    /// Secant stiffness F / H with the band at F, lb/in.
    pub k_h_at_force_lb_per_in: Stiffness,
    /// Contact width w at F (Eq. V.9), in.
    pub contact_width_in: Length,
    /// Maximum Hertz pressure 2F/(pi b t) at F, psi.
    pub max_stress_psi: Stress,
}

/// The rule a force must satisfy, as printed in the error.
const FORCE_RULE: &str = "--force must be a positive, finite number of pounds";

/// Computes the report for the reference steel roller (d1 = 0.75 in) on the base
/// circle (d2 = 3.0 in), t = 0.25 in, E = 30e6 psi, nu = 0.295.
pub fn compute(force: f64) -> anyhow::Result<ContactReport> {
    let hertz = HertzContact::<f64>::steel(CAM_THICKNESS_IN);
    let (r1, r2) = (ROLLER_DIAMETER_IN / 2.0, BASE_CIRCLE_DIAMETER_IN / 2.0);
    compute_for(force, &hertz, r1, r2)
}

/// The report for the roller of radius `r1` on the base circle of radius `r2` (in) with
/// the materials and thickness of `hertz` (a scene's `design.hertz` and geometry).
pub fn compute_for(
    force: f64,
    hertz: &HertzContact<f64>,
    r1: f64,
    r2: f64,
) -> anyhow::Result<ContactReport> {
    if !(force.is_finite() && force > 0.0) {
        bail!("{FORCE_RULE} (got {force})");
    }
    if force < crate::args::MIN_FORCE_LB {
        bail!(
            "--force {force:e}: must be at least {:e} lb (smaller forces underflow the contact band)",
            crate::args::MIN_FORCE_LB
        );
    }
    if force > crate::args::max_force_lb() {
        bail!("--force {force:e}: {}", crate::args::force_range_rule());
    }
    let k_h = hertz
        .stiffness(r1, r2)
        .context("unit-force Hertz stiffness")?;
    let k_at = hertz
        .stiffness_at(force, r1, r2)
        .map_err(|e| match e {
            // The core names the radii by their symbols (r1, r2): say which they are here.
            camsim_core::Error::InvalidParameter { rule, .. } => anyhow::anyhow!(
                "--force {force:e}: the Hertz stiffness of the reference pair (roller radius {r1} in, base circle radius {r2} in) at this force: {rule} (the force is beyond Hertz's theory for this pair)"
            ),
            other => anyhow::anyhow!("--force {force:e}: {other}"),
        })?;
    Ok(ContactReport {
        roller_radius_in: Length::inch(r1),
        base_radius_in: Length::inch(r2),
        thickness_in: Length::inch(hertz.thickness),
        force_lb: Force::inch(force),
        k_h_lb_per_in: Stiffness::inch(k_h),
        k_h_at_force_lb_per_in: Stiffness::inch(k_at),
        contact_width_in: Length::inch(hertz.width(force, 2.0 * r1, 2.0 * r2)),
        max_stress_psi: Stress::inch(hertz.max_stress(force, 2.0 * r1, 2.0 * r2)),
    })
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ContactReport, units: Units) -> String {
    use crate::units as u;
    let (l, f, k, st) = (
        units.symbol(u::LENGTH),
        units.symbol(u::FORCE),
        units.symbol(u::STIFFNESS),
        units.symbol(u::STRESS),
    );
    // V.11's K_h is the stiffness at a unit force: 1 lb (4.448 N in SI).
    let unit_force = match units {
        Units::Inch => "K_h (V.11, unit force)",
        Units::Si => "K_h (V.11, F = 1 lbf)",
    };
    format!(
        "Hertz contact, roller d1 = {} {l} on base circle d2 = {} {l}, t = {} {l}\n\
         force                      {:>14.6} {f}\n\
         {unit_force:<27}{:>14.6e} {k}\n\
         K_h at force (F/H)         {:>14.6e} {k}\n\
         contact width w (V.9)      {:>14.6e} {l}\n\
         max Hertz stress 2F/(pi b t) {:>12.6e} {st}",
        units.given(u::LENGTH, 2.0 * r.roller_radius_in.in_inch()),
        units.given(u::LENGTH, 2.0 * r.base_radius_in.in_inch()),
        units.given(u::LENGTH, r.thickness_in.in_inch()),
        units.of(r.force_lb),
        units.of(r.k_h_lb_per_in),
        units.of(r.k_h_at_force_lb_per_in),
        units.of(r.contact_width_in),
        units.of(r.max_stress_psi)
    )
}

impl Report for ContactReport {
    fn text(&self, units: Units) -> String {
        render_table(self, units) + "\n"
    }
}
