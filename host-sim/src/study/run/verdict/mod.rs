//! The verdict that opens `camsim run`: does contact hold, is the geometry sound, are the
//! loads within the material's allowable, is the spring clear of surge, did the
//! statistics settle. Every number carries its unit in its JSON key and its text.
//!
//! Each part is judged in its own module: contact, geometry, loads, spring, mass, drive,
//! margin and steady state, with the extremes the run watched ([`Watch`]) and the
//! warnings they raise; this module assembles them ([`judge`]) and writes the block's
//! text ([`text`]).

use anyhow::Result;
use serde::Serialize;

use super::RunReport;
use crate::sim::RunSpec;
use crate::units::Units;

mod contact;
mod drive;
mod geometry;
mod loads;
mod margin;
mod mass;
mod spring;
mod steady;
mod warnings;
mod watch;

pub use contact::{contact, ContactVerdict, JumpRow, Separation};
pub use drive::{drive, swing_warning, DriveVerdict};
pub use geometry::{geometry, GeometryVerdict};
pub use loads::{loads, LoadsVerdict, HP_LB_IN_PER_S, W_PER_LB_IN_PER_S};
pub use margin::{margin, MarginVerdict};
pub use mass::{mass, MassVerdict};
pub use spring::{key_hint, spring, spring_lines, spring_part_warnings, SpringVerdict};
pub use steady::{steady, SteadyVerdict};
pub use warnings::warnings;
pub use watch::Watch;

use contact::contact_lines;
use drive::drive_text;
use geometry::geometry_text;
use loads::loads_lines;
use margin::margin_text;
use mass::mass_text;

/// The limits a verdict judges against (`--allowable-stress`, `--pressure-angle-limit`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Limits {
    /// Allowable Hertz contact stress, psi.
    pub allowable_contact_stress_psi: f64,
    /// Largest pressure angle without a warning, degrees.
    pub pressure_angle_limit_deg: f64,
    /// Where the allowable comes from (the default's source, the scene, the option).
    #[serde(skip)]
    pub allowable_source: &'static str,
}

impl Limits {
    /// The reference limits, their source named in the output's family `units`.
    pub fn reference(units: Units) -> Self {
        Limits {
            allowable_contact_stress_psi: camsim_core::ALLOWABLE_CONTACT_STRESS_PSI,
            pressure_angle_limit_deg: camsim_core::PRESSURE_ANGLE_LIMIT_DEG,
            allowable_source: allowable_source(units),
        }
    }
}

/// Where an extreme occurred.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct At {
    /// Revolution, from 1.
    pub revolution: u32,
    /// Cam angle within it, degrees.
    pub cam_angle_deg: f64,
}

/// The verdict block.
#[derive(Clone, Debug, Serialize)]
pub struct Verdict {
    /// Contact.
    pub contact: ContactVerdict,
    /// Geometry.
    pub geometry: GeometryVerdict,
    /// Loads.
    pub loads: LoadsVerdict,
    /// The return spring.
    pub spring: SpringVerdict,
    /// The translating mass by its parts.
    pub mass: MassVerdict,
    /// The drive and the cam speed's swing.
    pub drive: DriveVerdict,
    /// The jump margin, when asked (`--margin`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_margin: Option<MarginVerdict>,
    /// Steady state (absent for a one-revolution run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady: Option<SteadyVerdict>,
    /// Every warning, one line each.
    pub warnings: Vec<String>,
}

/// The verdict of a finished run of `run` (its report so far, and the extremes `watch`
/// saw) against `limits`; with `margin` (`--margin`) also the jump-onset search on the
/// scene as it is (theoretical cam, static start).
pub fn judge(
    run: &RunSpec,
    report: &RunReport,
    watch: &Watch,
    limits: &Limits,
    margin: bool,
    units: Units,
) -> Result<Verdict> {
    let contact = contact(
        &run.design,
        &report.jumps,
        &report.periods,
        watch,
        run.revolutions,
    )?;
    let geometry = geometry(&run.design, limits)?;
    let loads = loads(watch, limits)?;
    let spring = spring(&run.design, run.spring.as_ref())?;
    let jump_margin = match margin {
        true => Some(self::margin(run, report.rpm)?),
        false => None,
    };
    let steady = steady(
        &report.per_period,
        &crate::sim::steady_checks(&report.per_period),
        units,
    );
    let mut warnings = warnings(
        &contact,
        &geometry,
        &loads,
        &spring,
        jump_margin.as_ref(),
        units,
    );
    let mass = mass(&run.design);
    let drive = drive(run, watch, units);
    warnings.extend(swing_warning(&drive));
    Ok(Verdict {
        contact,
        geometry,
        loads,
        spring,
        mass,
        drive,
        jump_margin,
        steady,
        warnings,
    })
}

/// The source of the default allowable contact stress.
pub const ALLOWABLE_SOURCE: &str = "through-hardened steel, 400 HB, 1e8 cycles: Buckingham's S_C = 0.4 H_B - 10 kpsi (Shigley); limits.allowable_contact_stress_psi (or _mpa) in the scene, or --allowable-stress PSI, to change";

/// [`ALLOWABLE_SOURCE`] in SI: Shigley's SI form of the same rule (0.4 kpsi = 2.76 MPa a
/// Brinell point, 10 kpsi = 68.9 MPa, which Shigley rounds to 70: 1034 MPa at 400 HB,
/// the 150 kpsi the default is), and the option in MPa as `--units si` reads it.
pub const ALLOWABLE_SOURCE_SI: &str = "through-hardened steel, 400 HB, 1e8 cycles: Buckingham's S_C = 2.76 H_B - 70 MPa (Shigley); limits.allowable_contact_stress_mpa (or _psi) in the scene, or --allowable-stress with its unit (1034MPa), to change";

/// The source of the default allowable contact stress in the output's family
/// (`--units`).
pub fn allowable_source(units: Units) -> &'static str {
    match units {
        crate::units::Units::Inch => ALLOWABLE_SOURCE,
        crate::units::Units::Si => ALLOWABLE_SOURCE_SI,
    }
}

/// Text of an [`At`].
pub fn at_text(a: &At) -> String {
    format!(
        "cam angle {:.1} deg of revolution {}",
        a.cam_angle_deg, a.revolution
    )
}

/// The verdict block as text.
pub fn text(v: &Verdict, units: Units) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let c = &v.contact;
    contact_lines(&mut out, c, units);
    let _ = writeln!(out, "{}", geometry_text(&v.geometry, units));
    loads_lines(&mut out, &v.loads, units);
    spring_lines(&mut out, &v.spring, units);
    let _ = writeln!(out, "{}", mass_text(&v.mass, units));
    let _ = writeln!(out, "{}", drive_text(&v.drive, c.revolutions));
    let _ = writeln!(out, "{}", margin_text(v.jump_margin.as_ref()));
    if let Some(st) = &v.steady {
        let _ = writeln!(out, "  steady:    {}", st.summary);
    }
    if v.warnings.is_empty() {
        let _ = writeln!(out, "  warnings:  none");
    } else {
        for w in &v.warnings {
            let _ = writeln!(out, "  WARNING:   {w}");
        }
    }
    out
}
