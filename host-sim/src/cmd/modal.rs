//! `camsim modal [--json]`: natural frequencies, normalised modes and modal stiffness of
//! the linearised rotational (Eq. VI.7) and translational (Eq. VI.6) systems of the
//! reference design (Section VI.2, Eqs. VI.2-VI.5).

use anyhow::Context;
use camsim_core::{modal_analysis, rotational_system, translational_system, ModalAnalysis};
use serde::Serialize;

// ---------------------------------------------------------------------------------------
// Reference values for the modal analysis.
// TEMPORARY: these move to `camsim_core::Design` (core/src/design.rs) when it lands on main;
// this block is then replaced by the design's fields.
// ---------------------------------------------------------------------------------------
/// Motor inertia I_m (lb·in·s², VI.1).
pub const I_M: f64 = 0.0291;
/// Coupling inertia I_cp (lb·in·s², VI.1).
pub const I_CP: f64 = 0.25;
/// Cam inertia I_c (lb·in·s², VI.1).
pub const I_C: f64 = 0.0102;
/// Motor-to-coupling shaft stiffness K_s1 (lb·in/rad, VI.1).
pub const K_S1: f64 = 2.0e5;
/// Coupling-to-cam shaft stiffness K_s2 (lb·in/rad, VI.1).
pub const K_S2: f64 = 2.0e5;
/// Roller mass M_r (lb·s²/in, VI.1, "M_T" in Eq. VI.6).
pub const M_R: f64 = 0.00013;
/// Follower mass M_f (lb·s²/in, VI.1).
pub const M_F: f64 = 0.007764;
/// Load mass M_l (lb·s²/in, NOTES.md: consistent with Eq. VI.6).
pub const M_L: f64 = 3.428e-3;
/// Roller-bearing stiffness K_rb (lb/in, VI.1).
pub const K_RB: f64 = 1.5e6;
/// Follower stiffness K_f at the nominal position (lb/in, NOTES.md).
pub const K_F: f64 = 1.265e6;
/// Return-spring stiffness for the modal analysis (lb/in, VI.2 uses 100; the dynamic
/// runs use 60).
pub const K_RS_MODAL: f64 = 100.0;
// ---------------------------------------------------------------------------------------

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
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
}

/// The reference-design values the analysis used.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ModalParameters {
    /// Motor inertia, lb·in·s².
    pub i_m: f64,
    /// Coupling inertia, lb·in·s².
    pub i_cp: f64,
    /// Cam inertia, lb·in·s².
    pub i_c: f64,
    /// Shaft stiffness motor-coupling, lb·in/rad.
    pub k_s1: f64,
    /// Shaft stiffness coupling-cam, lb·in/rad.
    pub k_s2: f64,
    /// Roller mass, lb·s²/in.
    pub m_r: f64,
    /// Follower mass, lb·s²/in.
    pub m_f: f64,
    /// Load mass, lb·s²/in.
    pub m_l: f64,
    /// Roller-bearing stiffness, lb/in.
    pub k_rb: f64,
    /// Follower stiffness, lb/in.
    pub k_f: f64,
    /// Return-spring stiffness of the modal analysis, lb/in.
    pub k_rs: f64,
}

fn system_modes(
    a: &ModalAnalysis<f64, 3>,
    coordinates: [&'static str; 3],
    stiffness_unit: &'static str,
    mass_unit: &'static str,
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
    }
}

/// Runs the modal analysis of both systems of the reference design (Section VI.2).
pub fn analyse() -> anyhow::Result<ModalReport> {
    let (k, m) = rotational_system(I_M, I_CP, I_C, K_S1, K_S2);
    let rot =
        modal_analysis(&k, &m).context("modal analysis of the rotational system (Eq. VI.7)")?;
    let (k, m) = translational_system(M_R, M_F, M_L, K_RB, K_F, K_RS_MODAL);
    let tra =
        modal_analysis(&k, &m).context("modal analysis of the translational system (Eq. VI.6)")?;
    let rotational = system_modes(
        &rot,
        ["theta_m", "theta_cp", "theta_c"],
        "lb*in/rad",
        "lb*in*s^2",
    );
    let translational = system_modes(
        &tra,
        ["y1 (roller)", "y2 (follower)", "y3 (load)"],
        "lb/in",
        "lb*s^2/in",
    );
    Ok(ModalReport {
        rotational_rad_s: rotational.omega_rad_s.clone(),
        translational_rad_s: translational.omega_rad_s.clone(),
        rotational_hz: rotational.hz.clone(),
        translational_hz: translational.hz.clone(),
        rotational,
        translational,
        parameters: ModalParameters {
            i_m: I_M,
            i_cp: I_CP,
            i_c: I_C,
            k_s1: K_S1,
            k_s2: K_S2,
            m_r: M_R,
            m_f: M_F,
            m_l: M_L,
            k_rb: K_RB,
            k_f: K_F,
            k_rs: K_RS_MODAL,
        },
    })
}

fn render_system(out: &mut String, title: &str, s: &SystemModes) {
    use std::fmt::Write;
    let _ = writeln!(out, "{title}");
    let _ = writeln!(
        out,
        "  mode  {:>14}  {:>12}  {:>14}  {:>14}  shape ({})",
        "omega rad/s",
        "f Hz",
        "k_modal",
        "m_modal",
        s.coordinates.join(", ")
    );
    for j in 0..s.omega_rad_s.len() {
        let shape: Vec<String> = s.modes[j].iter().map(|v| format!("{v:>10.6}")).collect();
        let rigid = if s.omega_rad_s[j] == 0.0 {
            "  (rigid body)"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  {:>4}  {:>14.3}  {:>12.3}  {:>14.6e}  {:>14.6e}  [{}]{rigid}",
            j + 1,
            s.omega_rad_s[j],
            s.hz[j],
            s.modal_stiffness[j],
            s.modal_mass[j],
            shape.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "  modal stiffness in {}, modal mass in {}; modes normalised to the first row (VI.4)",
        s.stiffness_unit, s.mass_unit
    );
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ModalReport) -> String {
    let mut out = String::new();
    render_system(
        &mut out,
        &format!("Rotational system (Eq. VI.7): I_m = {I_M}, I_cp = {I_CP}, I_c = {I_C} lb*in*s^2; K_s1 = {K_S1:e}, K_s2 = {K_S2:e} lb*in/rad"),
        &r.rotational,
    );
    out.push('\n');
    render_system(
        &mut out,
        &format!(
            "Translational system (Eq. VI.6): M_r = {M_R}, M_f = {M_F}, M_l = {M_L} lb*s^2/in; K_rb = {K_RB:e}, K_f = {K_F:e}, K_rs = {K_RS_MODAL} lb/in"
        ),
        &r.translational,
    );
    out
}

/// Runs the command.
pub fn run(args: Args) -> anyhow::Result<()> {
    let report = analyse()?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", render_table(&report));
    }
    Ok(())
}
