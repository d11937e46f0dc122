//! The modal analysis of Section VI.2 (Eqs. VI.2-VI.5): natural frequencies, normalised
//! modes and modal stiffness of the linearised rotational (Eq. VI.7) and translational
//! (Eq. VI.6) systems of a design.
//!
//! The parameters come from the design ([`Design::reference`] without a scene): the
//! follower's M_f and K_f at its nominal position (y3 = 0) and the modal analysis's
//! return-spring rate `k_rs_modal` (VI.2's 100 lb/in, the same as the dynamic model's
//! `k_rs` in the reference design, docs/MODEL.md §6.1). The study takes a [`Spec`] and
//! returns a [`ModalReport`] (its text in [`text`]); `camsim modal`
//! (crate::cmd::modal) builds the spec from its arguments and prints the report.

use anyhow::Context;
use camsim_core::{modal_analysis, rotational_system, translational_system, Design, ModalAnalysis};
use serde::Serialize;

use crate::units::{Inertia, Mass, Stiffness, TorsionalStiffness, UnitKind as Unit, Units};

pub mod text;

pub use text::render_table;

/// What the study analyses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    /// The design's values that enter Eqs. VI.6 and VI.7 ([`parameters`]).
    pub parameters: ModalParameters,
}

/// The modal analysis of both systems ([`analyse_with`]), its JSON's unit names in
/// `units`.
pub fn report(spec: &Spec, units: Units) -> anyhow::Result<ModalReport> {
    Ok(ModalReport {
        json_units: units,
        ..analyse_with(spec.parameters)?
    })
}

/// Modal results of one system.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SystemModes {
    /// Names of the coordinates, in matrix order.
    pub coordinates: Vec<&'static str>,
    /// Angular natural frequencies ω, rad/s, ascending (Eq. VI.3); rigid-body modes are 0.
    pub omega_rad_s: Vec<f64>,
    /// Natural frequencies f = ω / 2π, Hz.
    pub hz: Vec<f64>,
    /// Mode shapes: `modes[j][i]` is coordinate `i` of mode `j` (a column of P, Eq. VI.4),
    /// normalised so that coordinate `normalized_by[j]` (the first, as in VI.4) is 1.
    pub modes: Vec<Vec<f64>>,
    /// Row set to 1 in each mode (0 unless the first entry of that mode is ~0).
    pub normalized_by: Vec<usize>,
    /// Modal stiffness diag(Pᵀ K P) (Eq. VI.5), lb/in or lb·in/rad; 0 for a rigid mode.
    pub modal_stiffness: Vec<f64>,
    /// Modal mass diag(Pᵀ M P), lb·s²/in or lb·in·s².
    pub modal_mass: Vec<f64>,
    /// Unit of the modal stiffness.
    pub stiffness_unit: &'static str,
    /// Unit of the modal mass.
    pub mass_unit: &'static str,
    /// The modal stiffness's unit (the JSON key's suffix and the SI conversion).
    #[serde(skip)]
    pub stiffness: Unit,
    /// The modal mass's unit.
    #[serde(skip)]
    pub mass: Unit,
}

/// Everything `camsim modal` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModalReport {
    /// Rotational ω, rad/s, ascending (first entry is the rigid-body mode, 0).
    pub rotational_rad_s: Vec<f64>,
    /// Translational ω, rad/s, ascending.
    pub translational_rad_s: Vec<f64>,
    /// Rotational natural frequencies, Hz.
    pub rotational_hz: Vec<f64>,
    /// Translational natural frequencies, Hz.
    pub translational_hz: Vec<f64>,
    /// Rotational system (Eq. VI.7): motor, coupling, cam.
    pub rotational: SystemModes,
    /// Translational system (Eq. VI.6): roller, follower, load.
    pub translational: SystemModes,
    /// The parameters used (inch, pound-force, second, radian).
    pub parameters: ModalParameters,
    /// The family of the JSON's unit names (`stiffness_unit`, `mass_unit`): the JSON is
    /// written without the output's family, so the report carries it ([`report`]).
    #[serde(skip)]
    pub json_units: Units,
}

/// The reference-design values the analysis used (in JSON each key with its unit, the
/// thesis's symbol first: `i_c_lb_in_s2`, `k_f_lb_per_in`, converted by `--units`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ModalParameters {
    /// Motor inertia, lb·in·s².
    #[serde(rename = "i_m_lb_in_s2")]
    pub i_m: Inertia,
    /// Coupling inertia, lb·in·s².
    #[serde(rename = "i_cp_lb_in_s2")]
    pub i_cp: Inertia,
    /// Cam inertia, lb·in·s².
    #[serde(rename = "i_c_lb_in_s2")]
    pub i_c: Inertia,
    /// Shaft stiffness motor-coupling, lb·in/rad.
    #[serde(rename = "k_s1_lb_in_per_rad")]
    pub k_s1: TorsionalStiffness,
    /// Shaft stiffness coupling-cam, lb·in/rad.
    #[serde(rename = "k_s2_lb_in_per_rad")]
    pub k_s2: TorsionalStiffness,
    /// Roller mass, lb·s²/in.
    #[serde(rename = "m_r_lb_s2_per_in")]
    pub m_r: Mass,
    /// Follower mass, lb·s²/in.
    #[serde(rename = "m_f_lb_s2_per_in")]
    pub m_f: Mass,
    /// Load mass, lb·s²/in.
    #[serde(rename = "m_l_lb_s2_per_in")]
    pub m_l: Mass,
    /// Roller-bearing stiffness, lb/in.
    #[serde(rename = "k_rb_lb_per_in")]
    pub k_rb: Stiffness,
    /// Follower stiffness, lb/in.
    #[serde(rename = "k_f_lb_per_in")]
    pub k_f: Stiffness,
    /// Return-spring stiffness of the modal analysis, lb/in.
    #[serde(rename = "k_rs_lb_per_in")]
    pub k_rs: Stiffness,
}

fn system_modes(
    a: &ModalAnalysis<f64, 3>,
    coordinates: [&'static str; 3],
    (stiffness, stiffness_unit): (Unit, &'static str),
    (mass, mass_unit): (Unit, &'static str),
) -> SystemModes {
    SystemModes {
        coordinates: coordinates.to_vec(),
        omega_rad_s: a.omega.to_vec(),
        hz: a
            .omega
            .iter()
            .map(|w| w / (2.0 * std::f64::consts::PI))
            .collect(),
        modes: (0..3)
            .map(|j| a.modes.iter().map(|row| row[j]).collect())
            .collect(),
        normalized_by: a.normalized_by.to_vec(),
        modal_stiffness: a.modal_stiffness.to_vec(),
        modal_mass: a.modal_mass.to_vec(),
        stiffness_unit,
        mass_unit,
        stiffness,
        mass,
    }
}

/// The reference design's values that enter Eqs. VI.6 and VI.7.
pub fn reference_parameters() -> anyhow::Result<ModalParameters> {
    let d = Design::<f64>::reference();
    d.validate().context("reference design")?;
    Ok(parameters(&d))
}

/// A design's values that enter Eqs. VI.6 and VI.7 (the follower at y3 = 0, the modal
/// analysis's return-spring rate `k_rs_modal`).
pub fn parameters(d: &Design<f64>) -> ModalParameters {
    ModalParameters {
        i_m: Inertia::inch(d.i_m),
        i_cp: Inertia::inch(d.i_cp),
        i_c: Inertia::inch(d.i_c),
        k_s1: TorsionalStiffness::inch(d.k_s1),
        k_s2: TorsionalStiffness::inch(d.k_s2),
        m_r: Mass::inch(d.m_r),
        m_f: Mass::inch(d.m_f(0.0)),
        m_l: Mass::inch(d.m_l),
        k_rb: Stiffness::inch(d.k_rb),
        k_f: Stiffness::inch(d.k_f(0.0)),
        k_rs: Stiffness::inch(d.k_rs_modal),
    }
}

/// Runs the modal analysis of both systems of the reference design (Section VI.2).
pub fn analyse() -> anyhow::Result<ModalReport> {
    analyse_with(reference_parameters()?)
}

/// Runs the modal analysis of both systems for the given parameters (Section VI.2).
pub fn analyse_with(p: ModalParameters) -> anyhow::Result<ModalReport> {
    let (k, m) = rotational_system(
        p.i_m.in_inch(),
        p.i_cp.in_inch(),
        p.i_c.in_inch(),
        p.k_s1.in_inch(),
        p.k_s2.in_inch(),
    );
    let rot =
        modal_analysis(&k, &m).context("modal analysis of the rotational system (Eq. VI.7)")?;
    let (k, m) = translational_system(
        p.m_r.in_inch(),
        p.m_f.in_inch(),
        p.m_l.in_inch(),
        p.k_rb.in_inch(),
        p.k_f.in_inch(),
        p.k_rs.in_inch(),
    );
    let tra =
        modal_analysis(&k, &m).context("modal analysis of the translational system (Eq. VI.6)")?;
    let rotational = system_modes(
        &rot,
        ["theta_m", "theta_cp", "theta_c"],
        (crate::units::TORSIONAL_STIFFNESS, "lb*in/rad"),
        (crate::units::INERTIA, "lb*in*s^2"),
    );
    let translational = system_modes(
        &tra,
        ["y1 (roller)", "y2 (follower)", "y3 (load)"],
        (crate::units::STIFFNESS, "lb/in"),
        (crate::units::MASS, "lb*s^2/in"),
    );
    Ok(ModalReport {
        rotational_rad_s: rotational.omega_rad_s.clone(),
        translational_rad_s: translational.omega_rad_s.clone(),
        rotational_hz: rotational.hz.clone(),
        translational_hz: translational.hz.clone(),
        rotational,
        translational,
        parameters: p,
        json_units: Units::Inch,
    })
}
