//! `camsim modal [--json]`: natural frequencies, normalised modes and modal stiffness of
//! the linearised rotational (Eq. VI.7) and translational (Eq. VI.6) systems of the
//! reference design (Section VI.2, Eqs. VI.2-VI.5).
//!
//! The parameters come from [`Design::reference`]: the follower's M_f and K_f at its
//! nominal position (y3 = 0) and the modal analysis's return-spring rate `k_rs_modal`
//! (VI.2's 100 lb/in, the same as the dynamic model's `k_rs` in the reference design,
//! docs/MODEL.md §6.1).

use anyhow::Context;
use camsim_core::{modal_analysis, rotational_system, translational_system, Design, ModalAnalysis};
use serde::Serialize;

use crate::report::Report;
use crate::units::{self, UnitKind as Unit};

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML, see `camsim scene --default`): its masses, stiffnesses and
    /// `design.spring_modal_rate_lb_per_in`; the reference design if omitted.
    #[arg(value_name = "SCENE")]
    pub scene: Option<std::path::PathBuf>,
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
}

/// The reference-design values the analysis used (in JSON each key with its unit, the
/// thesis's symbol first: `i_c_lb_in_s2`, `k_f_lb_per_in`, converted by `--units`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ModalParameters {
    /// Motor inertia, lb·in·s².
    #[serde(rename = "i_m_lb_in_s2")]
    pub i_m: f64,
    /// Coupling inertia, lb·in·s².
    #[serde(rename = "i_cp_lb_in_s2")]
    pub i_cp: f64,
    /// Cam inertia, lb·in·s².
    #[serde(rename = "i_c_lb_in_s2")]
    pub i_c: f64,
    /// Shaft stiffness motor-coupling, lb·in/rad.
    #[serde(rename = "k_s1_lb_in_per_rad")]
    pub k_s1: f64,
    /// Shaft stiffness coupling-cam, lb·in/rad.
    #[serde(rename = "k_s2_lb_in_per_rad")]
    pub k_s2: f64,
    /// Roller mass, lb·s²/in.
    #[serde(rename = "m_r_lb_s2_per_in")]
    pub m_r: f64,
    /// Follower mass, lb·s²/in.
    #[serde(rename = "m_f_lb_s2_per_in")]
    pub m_f: f64,
    /// Load mass, lb·s²/in.
    #[serde(rename = "m_l_lb_s2_per_in")]
    pub m_l: f64,
    /// Roller-bearing stiffness, lb/in.
    #[serde(rename = "k_rb_lb_per_in")]
    pub k_rb: f64,
    /// Follower stiffness, lb/in.
    #[serde(rename = "k_f_lb_per_in")]
    pub k_f: f64,
    /// Return-spring stiffness of the modal analysis, lb/in.
    #[serde(rename = "k_rs_lb_per_in")]
    pub k_rs: f64,
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
        i_m: d.i_m,
        i_cp: d.i_cp,
        i_c: d.i_c,
        k_s1: d.k_s1,
        k_s2: d.k_s2,
        m_r: d.m_r,
        m_f: d.m_f(0.0),
        m_l: d.m_l,
        k_rb: d.k_rb,
        k_f: d.k_f(0.0),
        k_rs: d.k_rs_modal,
    }
}

/// Runs the modal analysis of both systems of the reference design (Section VI.2).
pub fn analyse() -> anyhow::Result<ModalReport> {
    analyse_with(reference_parameters()?)
}

/// Runs the modal analysis of both systems for the given parameters (Section VI.2).
pub fn analyse_with(p: ModalParameters) -> anyhow::Result<ModalReport> {
    let (k, m) = rotational_system(p.i_m, p.i_cp, p.i_c, p.k_s1, p.k_s2);
    let rot =
        modal_analysis(&k, &m).context("modal analysis of the rotational system (Eq. VI.7)")?;
    let (k, m) = translational_system(p.m_r, p.m_f, p.m_l, p.k_rb, p.k_f, p.k_rs);
    let tra =
        modal_analysis(&k, &m).context("modal analysis of the translational system (Eq. VI.6)")?;
    let rotational = system_modes(
        &rot,
        ["theta_m", "theta_cp", "theta_c"],
        (units::TORSIONAL_STIFFNESS, "lb*in/rad"),
        (units::INERTIA, "lb*in*s^2"),
    );
    let translational = system_modes(
        &tra,
        ["y1 (roller)", "y2 (follower)", "y3 (load)"],
        (units::STIFFNESS, "lb/in"),
        (units::MASS, "lb*s^2/in"),
    );
    Ok(ModalReport {
        rotational_rad_s: rotational.omega_rad_s.clone(),
        translational_rad_s: translational.omega_rad_s.clone(),
        rotational_hz: rotational.hz.clone(),
        translational_hz: translational.hz.clone(),
        rotational,
        translational,
        parameters: p,
    })
}

impl SystemModes {
    /// A unit's label in the output's family: this report's own in inch.
    fn label(&self, unit: Unit, inch: &'static str) -> &'static str {
        match units::current() {
            units::Units::Inch => inch,
            units::Units::Si => unit.si_symbol,
        }
    }
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
            units::value(s.stiffness, s.modal_stiffness[j]),
            units::value(s.mass, s.modal_mass[j]),
            shape.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "  modal stiffness in {}, modal mass in {}; modes normalised to the first row (VI.4)",
        s.label(s.stiffness, s.stiffness_unit),
        s.label(s.mass, s.mass_unit)
    );
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ModalReport) -> String {
    let p = &r.parameters;
    // The scene's values: as given in inch; in SI to 5 significant digits (`0.0102` lb
    // in s^2 is `1.1524e-3` kg m^2).
    let conv = |u: Unit, x: f64| match units::current() {
        units::Units::Inch => format!("{x}"),
        units::Units::Si => format!("{:.4e}", units::value(u, x)),
    };
    let (i, k) = (
        |x| conv(units::INERTIA, x),
        |x| conv(units::TORSIONAL_STIFFNESS, x),
    );
    let (m, ks) = (|x| conv(units::MASS, x), |x| conv(units::STIFFNESS, x));
    // The stiffnesses print as `{:e}` in inch (`2e5`).
    let sci = |x: f64, f: &dyn Fn(f64) -> String| match units::current() {
        units::Units::Inch => format!("{x:e}"),
        units::Units::Si => f(x),
    };
    let mut out = String::new();
    render_system(
        &mut out,
        &format!(
            "Rotational system (Eq. VI.7): I_m = {}, I_cp = {}, I_c = {} {}; K_s1 = {}, K_s2 = {} {}",
            i(p.i_m),
            i(p.i_cp),
            i(p.i_c),
            r.rotational.label(units::INERTIA, "lb*in*s^2"),
            sci(p.k_s1, &k),
            sci(p.k_s2, &k),
            r.rotational.label(units::TORSIONAL_STIFFNESS, "lb*in/rad")
        ),
        &r.rotational,
    );
    out.push('\n');
    render_system(
        &mut out,
        &format!(
            "Translational system (Eq. VI.6): M_r = {}, M_f = {}, M_l = {} {}; K_rb = {}, K_f = {:.6e}, K_rs = {} {}",
            m(p.m_r),
            match units::current() {
                units::Units::Inch => format!("{:.6}", p.m_f),
                units::Units::Si => m(p.m_f),
            },
            m(p.m_l),
            r.translational.label(units::MASS, "lb*s^2/in"),
            sci(p.k_rb, &ks),
            units::value(units::STIFFNESS, p.k_f),
            ks(p.k_rs),
            r.translational.label(units::STIFFNESS, "lb/in")
        ),
        &r.translational,
    );
    out
}

impl Report for ModalReport {
    fn text(&self, _units: crate::units::Units) -> String {
        render_table(self)
    }
    /// The struct's JSON with the modal stiffness and mass under keys that carry their
    /// system's unit (`modal_stiffness_lb_in_per_rad`, `modal_mass_lb_s2_per_in`), which
    /// `--units` converts as every other key; the unit strings in the output's family.
    fn json(&self) -> serde_json::Result<String> {
        let mut v = serde_json::to_value(self)?;
        for (name, s) in [
            ("rotational", &self.rotational),
            ("translational", &self.translational),
        ] {
            if let Some(o) = v.get_mut(name).and_then(|x| x.as_object_mut()) {
                for (key, unit, label) in [
                    ("modal_stiffness", s.stiffness, s.stiffness_unit),
                    ("modal_mass", s.mass, s.mass_unit),
                ] {
                    if let Some(x) = o.remove(key) {
                        o.insert(format!("{key}_{}", unit.inch), x);
                    }
                    o.insert(
                        format!("{}_unit", key.trim_start_matches("modal_")),
                        serde_json::Value::from(s.label(unit, label)),
                    );
                }
            }
        }
        serde_json::to_string_pretty(&v)
    }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> anyhow::Result<()> {
    let report = match &args.scene {
        Some(p) => analyse_with(parameters(&crate::scene::load(p)?.design))?,
        None => analyse()?,
    };
    crate::report::print(&report, args.json, units)
}
