//! Scene files: every parameter of the model, the program and the solver in TOML,
//! with the units in the key names. Every key is optional and defaults to the
//! reference design (`camsim scene --default` prints them all); unknown keys are
//! refused, so a typo never passes silently.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use camsim_core::{
    CamGeometry, CamProgram, DriveLaw, HertzContact, MotionLaw, Segment, SegmentKind,
    SolverSettings, Start,
};
use serde::{Deserialize, Serialize};

use crate::sim::{Dofs, RunSpec};

/// `[run]`: what to simulate.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Revolutions to simulate (1-16).
    pub revolutions: Option<u32>,
    /// Cam speed (initial speeds and the drive's reference), rpm.
    pub rpm: Option<f64>,
    /// Keep the horizontal motion (x1, x2, x3).
    pub horizontal_motion: Option<bool>,
    /// Initial state: "thesis" (VI.1) or "static" (static equilibrium).
    pub start: Option<String>,
}

/// `[solver]`: England's adaptive Runge-Kutta.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSection {
    /// Relative tolerance.
    pub rtol: Option<f64>,
    /// Absolute tolerance for displacements, in (scaled to the other components).
    pub atol_in: Option<f64>,
    /// Largest double step, as a fraction of a revolution.
    pub max_step_fraction_rev: Option<f64>,
    /// Step budget per revolution.
    pub max_steps_per_rev: Option<u32>,
}

/// `[drive]`: the motor law.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSection {
    /// "regulated", "constant-motor-speed" or "constant-cam-speed".
    pub law: Option<String>,
    /// Regulated: feed-forward torque at the reference speed, lb·in.
    pub t_steady_lb_in: Option<f64>,
    /// Regulated: proportional gain, lb·in·s/rad.
    pub k_p_lb_in_s_per_rad: Option<f64>,
    /// Regulated: torque limit, lb·in.
    pub t_max_lb_in: Option<f64>,
}

/// `[rotational]`: motor, coupling, cam rotation (Eq. IV.1).
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RotationalSection {
    pub i_m_lb_in_s2: Option<f64>,
    pub i_cp_lb_in_s2: Option<f64>,
    pub i_c_lb_in_s2: Option<f64>,
    pub c_mb_lb_in_s: Option<f64>,
    pub c_s1_lb_in_s: Option<f64>,
    pub c_s2_lb_in_s: Option<f64>,
    pub c_cc_lb_in_s: Option<f64>,
    pub k_s1_lb_in_per_rad: Option<f64>,
    pub k_s2_lb_in_per_rad: Option<f64>,
}

/// `[cam]`: the cam disk and its shaft.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CamSection {
    pub base_radius_in: Option<f64>,
    pub thickness_in: Option<f64>,
    pub mass_lb_s2_per_in: Option<f64>,
    pub k_vs_lb_per_in: Option<f64>,
    pub c_vs_lb_s_per_in: Option<f64>,
    pub k_hs_lb_per_in: Option<f64>,
    pub c_hs_lb_s_per_in: Option<f64>,
    pub youngs_psi: Option<f64>,
    pub poisson: Option<f64>,
}

/// `[roller]`: the roller and its bearing.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RollerSection {
    pub radius_in: Option<f64>,
    pub mass_lb_s2_per_in: Option<f64>,
    pub k_rb_lb_per_in: Option<f64>,
    pub youngs_psi: Option<f64>,
    pub poisson: Option<f64>,
}

/// `[follower]`: the follower rod, its slide bearing and the load.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FollowerSection {
    pub density_lb_s2_per_in4: Option<f64>,
    pub youngs_psi: Option<f64>,
    pub area_in2: Option<f64>,
    pub second_moment_in4: Option<f64>,
    pub e1_in: Option<f64>,
    pub e2_in: Option<f64>,
    pub bearing_a_in: Option<f64>,
    pub bearing_b_in: Option<f64>,
    pub friction_coefficient: Option<f64>,
    pub friction_smoothing_in_per_s: Option<f64>,
    pub damping_ratio_f1: Option<f64>,
    pub load_mass_lb_s2_per_in: Option<f64>,
}

/// `[spring]`: the return spring.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringSection {
    pub rate_lb_per_in: Option<f64>,
    pub preload_length_in: Option<f64>,
    pub mass_lb_s2_per_in: Option<f64>,
    pub modal_rate_lb_per_in: Option<f64>,
}

/// One `[[program.segment]]`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSection {
    /// "dwell", "rise" or "return".
    pub kind: String,
    /// Motion law of a rise or return (names as in `camsim laws`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub law: Option<String>,
    pub start_deg: f64,
    pub end_deg: f64,
    /// Lift of a rise or return, in (0 or absent for a dwell).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lift_in: Option<f64>,
}

/// `[program]`: the cam's motion program over 360 degrees.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProgramSection {
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub segment: Vec<SegmentSection>,
}

/// A whole scene file.
#[derive(Debug, Default, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    #[serde(default)]
    pub run: RunSection,
    #[serde(default)]
    pub solver: SolverSection,
    #[serde(default)]
    pub drive: DriveSection,
    #[serde(default)]
    pub rotational: RotationalSection,
    #[serde(default)]
    pub cam: CamSection,
    #[serde(default)]
    pub roller: RollerSection,
    #[serde(default)]
    pub follower: FollowerSection,
    #[serde(default)]
    pub spring: SpringSection,
    #[serde(default)]
    pub program: ProgramSection,
}

/// Parses an initial-state name.
pub fn parse_start(s: &str, key: &str) -> Result<Start> {
    match s {
        "thesis" => Ok(Start::Thesis),
        "static" => Ok(Start::Static),
        other => bail!("{key} = {other:?}: must be \"thesis\" or \"static\""),
    }
}

/// Reads and validates a scene file.
pub fn load(path: &Path) -> Result<RunSpec> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read the scene file", path.display()))?;
    parse(&text).map_err(|e| anyhow!("{}: {e:#}", path.display()))
}

/// Parses and validates scene text (errors name the key and the rule, on one line).
pub fn parse(text: &str) -> Result<RunSpec> {
    let file: SceneFile = toml::from_str(text).map_err(|e| {
        let (line, col) = e.span().map(|s| line_col(text, s.start)).unwrap_or((0, 0));
        anyhow!(
            "line {line}, column {col}: {}",
            e.message().trim().replace('\n', " ")
        )
    })?;
    file.to_spec()
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Checks one number: finite, and positive or non-negative.
fn num(key: &str, v: Option<f64>, default: f64, rule: Rule) -> Result<f64> {
    let Some(x) = v else { return Ok(default) };
    let ok = match rule {
        Rule::Positive => x.is_finite() && x > 0.0,
        Rule::NonNegative => x.is_finite() && x >= 0.0,
        Rule::Finite => x.is_finite(),
    };
    if !ok {
        bail!("{key} = {x}: {}", rule.text());
    }
    Ok(x)
}

#[derive(Clone, Copy)]
enum Rule {
    Positive,
    NonNegative,
    Finite,
}
impl Rule {
    fn text(self) -> &'static str {
        match self {
            Rule::Positive => "must be positive and finite",
            Rule::NonNegative => "must be zero or positive and finite",
            Rule::Finite => "must be finite",
        }
    }
}

/// Core field names and the scene keys they come from (for core validation errors).
const KEY_OF_FIELD: &[(&str, &str)] = &[
    ("e2", "follower.e2_in"),
    ("e1", "follower.e1_in"),
    ("area", "follower.area_in2"),
    ("bearing_b", "follower.bearing_b_in"),
    ("k_rs", "spring.rate_lb_per_in"),
    ("delta_rs", "spring.preload_length_in"),
    ("r1", "roller.radius_in"),
    ("roller_radius", "roller.radius_in"),
    ("r2", "cam.base_radius_in"),
    ("drive.t_max", "drive.t_max_lb_in"),
    ("drive.k_p", "drive.k_p_lb_in_s_per_rad"),
];

fn core_err(e: camsim_core::Error) -> anyhow::Error {
    if let camsim_core::Error::InvalidParameter { field, rule, value } = e {
        if let Some((_, key)) = KEY_OF_FIELD.iter().find(|(f, _)| *f == field) {
            return anyhow!("{key} = {value}: {rule}");
        }
        if field.starts_with("segments[") {
            return anyhow!(
                "program.{} = {value}: {rule}",
                field.replace("segments", "segment")
            );
        }
    }
    anyhow!("{e}")
}

impl SceneFile {
    /// The reference design as a complete scene (every key present).
    pub fn reference() -> Self {
        let spec = RunSpec::reference();
        Self::from_spec(&spec)
    }

    /// A complete scene file describing `spec`.
    pub fn from_spec(spec: &RunSpec) -> Self {
        let d = &spec.design;
        let (law, t_steady, k_p, t_max) = match d.drive {
            DriveLaw::Regulated {
                t_steady,
                k_p,
                t_max,
                ..
            } => ("regulated", Some(t_steady), Some(k_p), Some(t_max)),
            DriveLaw::ConstantMotorSpeed => ("constant-motor-speed", None, None, None),
            DriveLaw::ConstantCamSpeed => ("constant-cam-speed", None, None, None),
        };
        let mut level = 0.0;
        let segment = d
            .program
            .segments()
            .iter()
            .map(|s| {
                let (kind, law) = match s.kind {
                    SegmentKind::Dwell => ("dwell", None),
                    SegmentKind::Rise(l) => ("rise", Some(l.name().to_string())),
                    SegmentKind::Return(l) => ("return", Some(l.name().to_string())),
                };
                match s.kind {
                    SegmentKind::Rise(_) => level += s.lift,
                    SegmentKind::Return(_) => level -= s.lift,
                    SegmentKind::Dwell => {}
                }
                SegmentSection {
                    kind: kind.into(),
                    law,
                    start_deg: s.start_deg,
                    end_deg: s.end_deg,
                    lift_in: (s.lift != 0.0).then_some(s.lift),
                }
            })
            .collect();
        SceneFile {
            run: RunSection {
                revolutions: Some(spec.revolutions),
                rpm: Some(camsim_core::rad_per_s_to_rpm(d.omega0)),
                horizontal_motion: Some(spec.dofs.horizontal),
                start: Some(
                    match spec.solver.start {
                        Start::Thesis => "thesis",
                        Start::Static => "static",
                    }
                    .into(),
                ),
            },
            solver: SolverSection {
                rtol: Some(spec.solver.rtol),
                atol_in: Some(spec.solver.atol),
                max_step_fraction_rev: Some(spec.solver.max_step_fraction),
                max_steps_per_rev: Some(spec.solver.max_steps_per_rev),
            },
            drive: DriveSection {
                law: Some(law.into()),
                t_steady_lb_in: t_steady,
                k_p_lb_in_s_per_rad: k_p,
                t_max_lb_in: t_max,
            },
            rotational: RotationalSection {
                i_m_lb_in_s2: Some(d.i_m),
                i_cp_lb_in_s2: Some(d.i_cp),
                i_c_lb_in_s2: Some(d.i_c),
                c_mb_lb_in_s: Some(d.c_mb),
                c_s1_lb_in_s: Some(d.c_s1),
                c_s2_lb_in_s: Some(d.c_s2),
                c_cc_lb_in_s: Some(d.c_cc),
                k_s1_lb_in_per_rad: Some(d.k_s1),
                k_s2_lb_in_per_rad: Some(d.k_s2),
            },
            cam: CamSection {
                base_radius_in: Some(d.geometry.base_radius),
                thickness_in: Some(d.geometry.thickness),
                mass_lb_s2_per_in: Some(d.m_c),
                k_vs_lb_per_in: Some(d.k_vs),
                c_vs_lb_s_per_in: Some(d.c_vs),
                k_hs_lb_per_in: Some(d.k_hs),
                c_hs_lb_s_per_in: Some(d.c_hs),
                youngs_psi: Some(d.hertz.youngs_2),
                poisson: Some(d.hertz.poisson_2),
            },
            roller: RollerSection {
                radius_in: Some(d.geometry.roller_radius),
                mass_lb_s2_per_in: Some(d.m_r),
                k_rb_lb_per_in: Some(d.k_rb),
                youngs_psi: Some(d.hertz.youngs_1),
                poisson: Some(d.hertz.poisson_1),
            },
            follower: FollowerSection {
                density_lb_s2_per_in4: Some(d.rho),
                youngs_psi: Some(d.youngs),
                area_in2: Some(d.area),
                second_moment_in4: Some(d.inertia_moment),
                e1_in: Some(d.e1),
                e2_in: Some(d.e2),
                bearing_a_in: Some(d.bearing_a),
                bearing_b_in: Some(d.bearing_b),
                friction_coefficient: Some(d.mu),
                friction_smoothing_in_per_s: Some(d.friction_smoothing),
                damping_ratio_f1: Some(d.damping_ratio_f1),
                load_mass_lb_s2_per_in: Some(d.m_l),
            },
            spring: SpringSection {
                rate_lb_per_in: Some(d.k_rs),
                preload_length_in: Some(d.delta_rs),
                mass_lb_s2_per_in: Some(d.m_spring),
                modal_rate_lb_per_in: Some(d.k_rs_modal),
            },
            program: ProgramSection { segment },
        }
    }

    /// Converts to a validated run specification (reference values for absent keys).
    pub fn to_spec(&self) -> Result<RunSpec> {
        use Rule::*;
        let r = RunSpec::reference();
        let d0 = &r.design;
        let mut d = d0.clone();
        let s = self;

        let revolutions = s.run.revolutions.unwrap_or(r.revolutions);
        if !(1..=16).contains(&revolutions) {
            bail!("run.revolutions = {revolutions}: must be between 1 and 16");
        }
        let horizontal = s.run.horizontal_motion.unwrap_or(true);
        let rpm = num("run.rpm", s.run.rpm, 800.0, Positive)?;

        let mut solver = SolverSettings::reference();
        solver.rtol = num("solver.rtol", s.solver.rtol, solver.rtol, Positive)?;
        if solver.rtol >= 1.0 {
            bail!("solver.rtol = {}: must be below 1", solver.rtol);
        }
        solver.atol = num("solver.atol_in", s.solver.atol_in, solver.atol, Positive)?;
        solver.max_step_fraction = num(
            "solver.max_step_fraction_rev",
            s.solver.max_step_fraction_rev,
            solver.max_step_fraction,
            Positive,
        )?;
        if solver.max_step_fraction > 0.25 {
            bail!(
                "solver.max_step_fraction_rev = {}: must be at most 0.25",
                solver.max_step_fraction
            );
        }
        if let Some(st) = s.run.start.as_deref() {
            solver.start = parse_start(st, "run.start")?;
        }
        if let Some(m) = s.solver.max_steps_per_rev {
            if m == 0 {
                bail!("solver.max_steps_per_rev = 0: must be at least 1");
            }
            solver.max_steps_per_rev = m;
        }

        let rt = &s.rotational;
        d.i_m = num("rotational.i_m_lb_in_s2", rt.i_m_lb_in_s2, d0.i_m, Positive)?;
        d.i_cp = num(
            "rotational.i_cp_lb_in_s2",
            rt.i_cp_lb_in_s2,
            d0.i_cp,
            Positive,
        )?;
        d.i_c = num("rotational.i_c_lb_in_s2", rt.i_c_lb_in_s2, d0.i_c, Positive)?;
        d.c_mb = num(
            "rotational.c_mb_lb_in_s",
            rt.c_mb_lb_in_s,
            d0.c_mb,
            NonNegative,
        )?;
        d.c_s1 = num(
            "rotational.c_s1_lb_in_s",
            rt.c_s1_lb_in_s,
            d0.c_s1,
            NonNegative,
        )?;
        d.c_s2 = num(
            "rotational.c_s2_lb_in_s",
            rt.c_s2_lb_in_s,
            d0.c_s2,
            NonNegative,
        )?;
        d.c_cc = num(
            "rotational.c_cc_lb_in_s",
            rt.c_cc_lb_in_s,
            d0.c_cc,
            NonNegative,
        )?;
        d.k_s1 = num(
            "rotational.k_s1_lb_in_per_rad",
            rt.k_s1_lb_in_per_rad,
            d0.k_s1,
            Positive,
        )?;
        d.k_s2 = num(
            "rotational.k_s2_lb_in_per_rad",
            rt.k_s2_lb_in_per_rad,
            d0.k_s2,
            Positive,
        )?;

        let c = &s.cam;
        let base_radius = num(
            "cam.base_radius_in",
            c.base_radius_in,
            d0.geometry.base_radius,
            Positive,
        )?;
        let thickness = num(
            "cam.thickness_in",
            c.thickness_in,
            d0.geometry.thickness,
            Positive,
        )?;
        d.m_c = num(
            "cam.mass_lb_s2_per_in",
            c.mass_lb_s2_per_in,
            d0.m_c,
            Positive,
        )?;
        d.k_vs = num("cam.k_vs_lb_per_in", c.k_vs_lb_per_in, d0.k_vs, Positive)?;
        d.c_vs = num(
            "cam.c_vs_lb_s_per_in",
            c.c_vs_lb_s_per_in,
            d0.c_vs,
            NonNegative,
        )?;
        d.k_hs = num("cam.k_hs_lb_per_in", c.k_hs_lb_per_in, d0.k_hs, Positive)?;
        d.c_hs = num(
            "cam.c_hs_lb_s_per_in",
            c.c_hs_lb_s_per_in,
            d0.c_hs,
            NonNegative,
        )?;
        let e_cam = num("cam.youngs_psi", c.youngs_psi, d0.hertz.youngs_2, Positive)?;
        let nu_cam = num("cam.poisson", c.poisson, d0.hertz.poisson_2, NonNegative)?;

        let ro = &s.roller;
        let roller_radius = num(
            "roller.radius_in",
            ro.radius_in,
            d0.geometry.roller_radius,
            Positive,
        )?;
        d.m_r = num(
            "roller.mass_lb_s2_per_in",
            ro.mass_lb_s2_per_in,
            d0.m_r,
            Positive,
        )?;
        d.k_rb = num(
            "roller.k_rb_lb_per_in",
            ro.k_rb_lb_per_in,
            d0.k_rb,
            Positive,
        )?;
        let e_rol = num(
            "roller.youngs_psi",
            ro.youngs_psi,
            d0.hertz.youngs_1,
            Positive,
        )?;
        let nu_rol = num(
            "roller.poisson",
            ro.poisson,
            d0.hertz.poisson_1,
            NonNegative,
        )?;
        for (k, nu) in [("cam.poisson", nu_cam), ("roller.poisson", nu_rol)] {
            if nu >= 0.5 {
                bail!("{k} = {nu}: must be below 0.5");
            }
        }
        d.geometry = CamGeometry::new(base_radius, roller_radius, thickness).map_err(core_err)?;
        d.hertz = HertzContact::new(e_rol, nu_rol, e_cam, nu_cam, thickness).map_err(core_err)?;

        let f = &s.follower;
        d.rho = num(
            "follower.density_lb_s2_per_in4",
            f.density_lb_s2_per_in4,
            d0.rho,
            Positive,
        )?;
        d.youngs = num("follower.youngs_psi", f.youngs_psi, d0.youngs, Positive)?;
        d.area = num("follower.area_in2", f.area_in2, d0.area, Positive)?;
        d.inertia_moment = num(
            "follower.second_moment_in4",
            f.second_moment_in4,
            d0.inertia_moment,
            Positive,
        )?;
        d.e1 = num("follower.e1_in", f.e1_in, d0.e1, Positive)?;
        d.e2 = num("follower.e2_in", f.e2_in, d0.e2, Positive)?;
        d.bearing_a = num(
            "follower.bearing_a_in",
            f.bearing_a_in,
            d0.bearing_a,
            NonNegative,
        )?;
        d.bearing_b = num(
            "follower.bearing_b_in",
            f.bearing_b_in,
            d0.bearing_b,
            Positive,
        )?;
        d.mu = num(
            "follower.friction_coefficient",
            f.friction_coefficient,
            d0.mu,
            NonNegative,
        )?;
        d.friction_smoothing = num(
            "follower.friction_smoothing_in_per_s",
            f.friction_smoothing_in_per_s,
            d0.friction_smoothing,
            Positive,
        )?;
        d.damping_ratio_f1 = num(
            "follower.damping_ratio_f1",
            f.damping_ratio_f1,
            d0.damping_ratio_f1,
            NonNegative,
        )?;
        d.m_l = num(
            "follower.load_mass_lb_s2_per_in",
            f.load_mass_lb_s2_per_in,
            d0.m_l,
            Positive,
        )?;

        let sp = &s.spring;
        d.k_rs = num(
            "spring.rate_lb_per_in",
            sp.rate_lb_per_in,
            d0.k_rs,
            Positive,
        )?;
        d.delta_rs = num(
            "spring.preload_length_in",
            sp.preload_length_in,
            d0.delta_rs,
            NonNegative,
        )?;
        d.m_spring = num(
            "spring.mass_lb_s2_per_in",
            sp.mass_lb_s2_per_in,
            d0.m_spring,
            NonNegative,
        )?;
        d.k_rs_modal = num(
            "spring.modal_rate_lb_per_in",
            sp.modal_rate_lb_per_in,
            d0.k_rs_modal,
            Positive,
        )?;

        if !s.program.segment.is_empty() {
            let mut segs = Vec::new();
            for (i, g) in s.program.segment.iter().enumerate() {
                let key = |k: &str| format!("program.segment[{i}].{k}");
                let law = |name: &Option<String>| -> Result<MotionLaw> {
                    let n = name.as_deref().ok_or_else(|| {
                        anyhow!("{}: a rise or return needs a motion law", key("law"))
                    })?;
                    MotionLaw::from_name(n)
                        .ok_or_else(|| anyhow!("{} = {n:?}: unknown motion law", key("law")))
                };
                let kind = match g.kind.as_str() {
                    "dwell" => SegmentKind::Dwell,
                    "rise" => SegmentKind::Rise(law(&g.law)?),
                    "return" => SegmentKind::Return(law(&g.law)?),
                    other => bail!(
                        "{} = {other:?}: must be \"dwell\", \"rise\" or \"return\"",
                        key("kind")
                    ),
                };
                for (k, v) in [("start_deg", g.start_deg), ("end_deg", g.end_deg)] {
                    if !v.is_finite() {
                        bail!("{} = {v}: must be finite", key(k));
                    }
                }
                let lift = match kind {
                    SegmentKind::Dwell => num(&key("lift_in"), g.lift_in, 0.0, Finite)?,
                    _ => num(
                        &key("lift_in"),
                        Some(g.lift_in.ok_or_else(|| {
                            anyhow!("{}: a rise or return needs a lift", key("lift_in"))
                        })?),
                        0.0,
                        Positive,
                    )?,
                };
                segs.push(Segment {
                    kind,
                    start_deg: g.start_deg,
                    end_deg: g.end_deg,
                    lift,
                });
            }
            if segs.len() > 8 {
                bail!("program.segment: {} segments, at most 8", segs.len());
            }
            d.program = CamProgram::new(&segs).map_err(core_err)?;
        }

        // Speed last: it moves the drive's reference (regulated feed-forward follows speed).
        d.omega0 = camsim_core::rpm_to_rad_per_s(rpm);
        let dr = &s.drive;
        d.drive = match dr.law.as_deref().unwrap_or("regulated") {
            "regulated" => {
                let base = DriveLaw::reference(d.omega0, d.c_mb, d.c_cc);
                let DriveLaw::Regulated {
                    t_steady,
                    k_p,
                    t_max,
                    ..
                } = base
                else {
                    bail!("drive.law: the reference drive is not regulated")
                };
                DriveLaw::Regulated {
                    omega_ref: d.omega0,
                    t_steady: num("drive.t_steady_lb_in", dr.t_steady_lb_in, t_steady, Finite)?,
                    k_p: num(
                        "drive.k_p_lb_in_s_per_rad",
                        dr.k_p_lb_in_s_per_rad,
                        k_p,
                        NonNegative,
                    )?,
                    t_max: num("drive.t_max_lb_in", dr.t_max_lb_in, t_max, Positive)?,
                }
            }
            other => {
                for (k, v) in [
                    ("drive.t_steady_lb_in", dr.t_steady_lb_in),
                    ("drive.k_p_lb_in_s_per_rad", dr.k_p_lb_in_s_per_rad),
                    ("drive.t_max_lb_in", dr.t_max_lb_in),
                ] {
                    if v.is_some() {
                        bail!("{k}: only a \"regulated\" drive takes it (drive.law = {other:?})");
                    }
                }
                match other {
                    "constant-motor-speed" => DriveLaw::ConstantMotorSpeed,
                    "constant-cam-speed" => DriveLaw::ConstantCamSpeed,
                    _ => bail!("drive.law = {other:?}: must be \"regulated\", \"constant-motor-speed\" or \"constant-cam-speed\""),
                }
            }
        };
        d.validate().map_err(core_err)?;
        Ok(RunSpec {
            design: d,
            dofs: Dofs { horizontal },
            solver,
            revolutions,
        })
    }
}

/// A complete scene file (TOML text) for `spec`.
pub fn spec_text(spec: &RunSpec) -> Result<String> {
    Ok(toml::to_string_pretty(&SceneFile::from_spec(spec))?)
}

/// The reference design as TOML text.
pub fn default_text() -> Result<String> {
    let body = toml::to_string_pretty(&SceneFile::reference())?;
    Ok(format!(
        "# camsim scene: the reference design of Kim (1982), VI.1, with the documented choices\n\
         # for what the thesis leaves out (core/src/design.rs). Units are in the key names\n\
         # (inch, pound-force, second). Every key is optional: absent keys take these values.\n\n{body}"
    ))
}

/// Rust source for the firmware: the scene as a `const` [`camsim_core::DesignRecord`]
/// named `SCENE` (every number printed with Rust's round-trip `f64` formatting).
pub fn rust_source(spec: &RunSpec, origin: &str) -> String {
    use std::fmt::Write;
    let r = spec.design.to_record();
    let mut o = String::new();
    let _ = writeln!(
        o,
        "// Generated by `camsim scene --rust {origin}`: the design compiled into the firmware."
    );
    let _ = writeln!(o, "// Do not edit; regenerate from the scene file.");
    let _ = writeln!(o, "/// The scene compiled in (from {origin}).");
    let _ = writeln!(
        o,
        "pub const SCENE: camsim_core::DesignRecord = camsim_core::DesignRecord {{"
    );
    let _ = write!(o, "    values: [");
    for (i, v) in r.values.iter().enumerate() {
        let _ = write!(o, "{}{v:?}_f64", if i == 0 { "" } else { ", " });
    }
    let _ = writeln!(o, "],");
    let drive = match r.drive {
        DriveLaw::ConstantCamSpeed => "camsim_core::DriveLaw::ConstantCamSpeed".to_string(),
        DriveLaw::ConstantMotorSpeed => "camsim_core::DriveLaw::ConstantMotorSpeed".to_string(),
        DriveLaw::Regulated { omega_ref, t_steady, k_p, t_max } => format!(
            "camsim_core::DriveLaw::Regulated {{ omega_ref: {omega_ref:?}_f64, t_steady: {t_steady:?}_f64, k_p: {k_p:?}_f64, t_max: {t_max:?}_f64 }}"
        ),
    };
    let _ = writeln!(o, "    drive: {drive},");
    let _ = writeln!(o, "    segments: [");
    for s in &r.segments {
        let kind = match s.kind {
            SegmentKind::Dwell => "camsim_core::SegmentKind::Dwell".to_string(),
            SegmentKind::Rise(l) => {
                format!("camsim_core::SegmentKind::Rise(camsim_core::MotionLaw::{l:?})")
            }
            SegmentKind::Return(l) => {
                format!("camsim_core::SegmentKind::Return(camsim_core::MotionLaw::{l:?})")
            }
        };
        let _ = writeln!(
            o,
            "        camsim_core::Segment {{ kind: {kind}, start_deg: {:?}_f64, end_deg: {:?}_f64, lift: {:?}_f64 }},",
            s.start_deg, s.end_deg, s.lift
        );
    }
    let _ = writeln!(o, "    ],");
    let _ = writeln!(o, "    segment_count: {},", r.segment_count);
    let _ = writeln!(o, "}};");
    o
}
