//! `camsim sensitivity`: the sensitivity study of VI.4.3 (Tables VI.11-VI.12) and, beyond
//! the thesis, every design key's elasticity.
//!
//! Three groups of dynamic characteristics ([`Group`]) are each changed together by
//! −30, −10, +10 and +30 % ([`scaled`], the one place that says what a group holds;
//! docs/MODEL.md §11), on the theoretical cam and on one actual cam (sample 0 of the
//! master seed, built once by [`crate::actual::build_profile`] from the baseline design:
//! the groups touch neither the program nor the geometry, so every case rides on the
//! same profile). Each case reports, over the whole of revolution 2 ([`Outputs`]), the
//! RMS of the load's displacement, velocity and acceleration deviations from the
//! theoretical response, the RMS of the cam's angular-velocity deviation from ω0, the
//! time-averaged contact stress, and whether the follower separated.
//!
//! `--per-key` ([`per_key`]): d ln(output) / d ln(key) by central differences at ±1 %
//! of every numeric design key ([`key_scaled`]) on the five outputs (theoretical cam)
//! and on the jump-onset speed ([`crate::study::jump_speed::find`]), ranked by the
//! onset's.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{anyhow, Context, Result};
use camsim_core::{jump_verdict, key, Both, Design, DriveLaw, JumpWatch, Observer, Sample, Start};
use rayon::prelude::*;
use serde::Serialize;

use crate::actual::{self, ActualArgs, ProfileStats};
use crate::args::OutputArgs;
use crate::output::Plan;
use crate::report::Report;
use crate::sim::{self, RunSpec};
use crate::study::montecarlo::LeftRange;

/// The changes of every group, % (VI.4.3).
pub const CHANGES_PCT: [i32; 4] = [-30, -10, 10, 30];
/// The changes of `--quick`, %.
pub const QUICK_CHANGES_PCT: [i32; 2] = [-30, 30];
/// The relative step of `--per-key`'s central differences (±1 %).
pub const KEY_STEP: f64 = 0.01;
/// Resolution of `--per-key`'s jump-onset searches, rpm (`--quick`: [`QUICK_ONSET_RESOLUTION_RPM`]).
/// At a 900 rpm onset and ±1 % steps it resolves an elasticity to 0.01 / 900 / 0.02 ≈ 6e-4.
pub const ONSET_RESOLUTION_RPM: f64 = 0.01;
/// `--quick`'s onset resolution, rpm.
pub const QUICK_ONSET_RESOLUTION_RPM: f64 = 1.0;
/// The revolution the study measures (the thesis's steady state, as the other studies).
pub const REVOLUTION: u32 = 2;
/// The plot `--plot DIR` writes.
pub const PLOT_FILES: [&str; 1] = ["sensitivity.png"];

/// Command-line options of `camsim sensitivity`.
#[derive(clap::Args, Debug, Clone, Default)]
#[command(mut_arg("actual", |a| a.hide(true)))]
#[command(mut_arg("plot", |a| a.help("Write a tornado-style bar chart (sensitivity.png) into DIR")))]
#[command(mut_arg("force", |a| a.help("Replace an existing --plot file")))]
pub struct Args {
    /// Scene file (the reference design if omitted).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm, 1-10 000 (default: the scene's, 800 for the reference).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Quick mode for CI: the vertical scene, changes of ±30 % only, and with --per-key
    /// a 1 rpm onset resolution.
    #[arg(long)]
    pub quick: bool,
    /// Also every design key's elasticity (d ln output / d ln key, central differences
    /// at ±1 %) on the five outputs and on the jump-onset speed, ranked (theoretical cam).
    #[arg(long)]
    pub per_key: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cam (sample 0 of --seed): both cams always run.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// A group of dynamic characteristics changed together (VI.4.3).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Group {
    /// Every mass and polar moment of inertia.
    Mass,
    /// Every damper.
    Damping,
    /// Every structural stiffness (not the return spring, not the Hertz contact).
    Stiffness,
}

impl Group {
    /// The three groups, in the thesis's order.
    pub const ALL: [Group; 3] = [Group::Mass, Group::Damping, Group::Stiffness];

    /// The name reports use.
    pub fn name(self) -> &'static str {
        match self {
            Group::Mass => "mass",
            Group::Damping => "damping",
            Group::Stiffness => "stiffness",
        }
    }

    /// The scene keys [`scaled`] multiplies (the drive's feed-forward only with the
    /// regulated drive).
    pub fn keys(self) -> &'static [&'static str] {
        match self {
            Group::Mass => &MASS_KEYS,
            Group::Damping => &DAMPING_KEYS,
            Group::Stiffness => &STIFFNESS_KEYS,
        }
    }
}

/// The mass group: motor, coupling, cam, cam and shaft, roller, follower rod density
/// (its two masses M_f and M_fc), load, return spring.
pub const MASS_KEYS: [&str; 8] = [
    key::I_M,
    key::I_CP,
    key::I_C,
    key::M_C,
    key::M_R,
    key::RHO,
    key::M_L,
    key::M_SPRING,
];
/// The damping group: the rotational and shaft dampers, the follower's structural
/// damping ratio, the contact and roller-bearing damping ratios, and the regulated
/// drive's feed-forward torque, which is the steady drag (C_mb + C_cc) ω_ref by
/// definition ([`DriveLaw::reference`]) and so moves with C_mb and C_cc (the cam keeps
/// its speed instead of slowing by the extra drag over the drive's gain).
pub const DAMPING_KEYS: [&str; 10] = [
    key::C_MB,
    key::C_S1,
    key::C_S2,
    key::C_CC,
    key::C_VS,
    key::C_HS,
    key::DAMPING_RATIO_F1,
    key::CONTACT_DAMPING_RATIO,
    key::ROLLER_BEARING_DAMPING_RATIO,
    key::DRIVE_T_STEADY,
];
/// The stiffness group: both shafts, the cam shaft's supports (vertical and horizontal),
/// the roller bearing, the follower rod's Young's modulus (K_f, K_vc, K_hc).
pub const STIFFNESS_KEYS: [&str; 6] = [
    key::K_S1,
    key::K_S2,
    key::K_VS,
    key::K_HS,
    key::K_RB,
    key::YOUNGS,
];

/// `design` with every parameter of `group` multiplied by `factor` (1.1 for +10 %) and
/// nothing else changed ([`Group::keys`]; docs/MODEL.md §11).
///
/// Damping enters three coefficients through ratios, C = 2 ξ sqrt(K M) (C_f1, C_h,
/// C_rb): the damping group scales the ratios, so those coefficients scale with it; the
/// mass and stiffness groups keep the ratios (the fraction of critical damping), so those
/// coefficients follow sqrt(K M). The return spring's mass is a key of its own (its
/// default comes from the wire, [`camsim_core::SPRING_MASS`]) and is scaled as a mass;
/// its rate and the Hertz moduli are not in any group. The preload F_p depends on K_rb
/// and K_vs (Eq. V.18), so the stiffness group moves it slightly (as it would on a
/// stiffer machine assembled with the same spring compression).
pub fn scaled(design: &Design<f64>, group: Group, factor: f64) -> Design<f64> {
    let mut d = design.clone();
    match group {
        Group::Mass => {
            for x in [
                &mut d.i_m,
                &mut d.i_cp,
                &mut d.i_c,
                &mut d.m_c,
                &mut d.m_r,
                &mut d.rho,
                &mut d.m_l,
                &mut d.m_spring,
            ] {
                *x *= factor;
            }
        }
        Group::Damping => {
            for x in [
                &mut d.c_mb,
                &mut d.c_s1,
                &mut d.c_s2,
                &mut d.c_cc,
                &mut d.c_vs,
                &mut d.c_hs,
                &mut d.damping_ratio_f1,
                &mut d.contact_damping_ratio,
                &mut d.roller_bearing_damping_ratio,
            ] {
                *x *= factor;
            }
            if let DriveLaw::Regulated { t_steady, .. } = &mut d.drive {
                *t_steady *= factor;
            }
        }
        Group::Stiffness => {
            for x in [
                &mut d.k_s1,
                &mut d.k_s2,
                &mut d.k_vs,
                &mut d.k_hs,
                &mut d.k_rb,
                &mut d.youngs,
            ] {
                *x *= factor;
            }
        }
    }
    d
}

/// `design` with the numeric scene key `name` ([`key::DESIGN_KEYS`], dotted for the
/// sub-tables: `geometry.base_radius_in`) multiplied by `factor`, checked
/// ([`Design::validate`]). The key is reached through the design's own serialization,
/// so every scene key works without a list of fields here.
pub fn key_scaled(design: &Design<f64>, name: &str, factor: f64) -> Result<Design<f64>> {
    let mut v = serde_json::to_value(design)?;
    let mut at = &mut v;
    for part in name.split('.') {
        at = at
            .get_mut(part)
            .ok_or_else(|| anyhow!("key {name}: not a key of this design"))?;
    }
    let x = at
        .as_f64()
        .ok_or_else(|| anyhow!("key {name}: not a number"))?;
    *at = serde_json::Value::from(x * factor);
    let d: Design<f64> = serde_json::from_value(v).with_context(|| format!("key {name}"))?;
    d.validate()
        .with_context(|| format!("key {name} times {factor}"))?;
    Ok(d)
}

/// The study's outputs over the whole of one revolution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outputs {
    /// RMS of the load's displacement deviation from the theoretical response, in.
    pub rms_displacement_in: f64,
    /// RMS of the load's velocity deviation, in/s.
    pub rms_velocity_in_per_s: f64,
    /// RMS of the load's acceleration deviation, in/s².
    pub rms_acceleration_in_per_s2: f64,
    /// RMS of the cam's angular-velocity deviation from ω0, rad/s.
    pub rms_angular_velocity_rad_per_s: f64,
    /// Time average of the largest Hertz contact stress, psi (0 while separated).
    pub contact_stress_avg_psi: f64,
    /// Whether the follower left the cam in the revolution.
    pub jump: bool,
}

/// The names of the five numeric outputs, in [`Outputs::values`]'s order, with the
/// text table's header and unit.
pub const OUTPUTS: [(&str, &str, &str); 5] = [
    ("rms_displacement_in", "rms y", "in"),
    ("rms_velocity_in_per_s", "rms v", "in/s"),
    ("rms_acceleration_in_per_s2", "rms a", "in/s2"),
    ("rms_angular_velocity_rad_per_s", "rms w_cam", "rad/s"),
    ("contact_stress_avg_psi", "avg stress", "psi"),
];

impl Outputs {
    /// The five numbers, in [`OUTPUTS`]' order.
    pub fn values(&self) -> [f64; 5] {
        [
            self.rms_displacement_in,
            self.rms_velocity_in_per_s,
            self.rms_acceleration_in_per_s2,
            self.rms_angular_velocity_rad_per_s,
            self.contact_stress_avg_psi,
        ]
    }
}

/// Whole-revolution RMS from per-period RMS values over their own spans:
/// sqrt(Σ dᵢ rmsᵢ² / Σ dᵢ) for `(duration dᵢ, rmsᵢ)` pairs (each period's mean square
/// is its integral over its duration, so the revolution's integral is the sum of
/// dᵢ rmsᵢ²). 0 for no duration.
pub fn combine_rms(periods: &[(f64, f64)]) -> f64 {
    let (num, den) = periods.iter().fold((0.0, 0.0), |(n, d), &(dur, rms)| {
        (n + dur * rms * rms, d + dur)
    });
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}

/// Time integrals over one revolution, trapezoidal between consecutive samples that both
/// lie in it (as the per-period statistics, but across the period boundaries too): the
/// cam-speed deviation and the contact stress, which the per-period statistics do not
/// keep, and the three load deviations (to check [`combine_rms`] against).
#[derive(Clone, Debug, Default)]
pub struct RevolutionIntegrals {
    /// The revolution (from 1).
    pub revolution: u32,
    /// ω0, rad/s.
    pub omega0: f64,
    /// Time covered, s.
    pub duration: f64,
    /// ∫ (y − y_th)² dt, ∫ (v − v_th)² dt, ∫ (a − a_th)² dt, ∫ (ω_c − ω0)² dt, ∫ σ dt.
    pub sums: [f64; 5],
    prev: Option<(f64, [f64; 5])>,
}

impl RevolutionIntegrals {
    /// Empty integrals of `revolution` about the speed `omega0`.
    pub fn new(revolution: u32, omega0: f64) -> Self {
        Self {
            revolution,
            omega0,
            ..Self::default()
        }
    }

    /// RMS (the first four) or mean (the stress) over the time covered.
    pub fn means(&self) -> [f64; 5] {
        let m = |s: f64| {
            if self.duration > 0.0 {
                s / self.duration
            } else {
                0.0
            }
        };
        let [y, v, a, w, s] = self.sums;
        [m(y).sqrt(), m(v).sqrt(), m(a).sqrt(), m(w).sqrt(), m(s)]
    }
}

impl Observer<f64> for RevolutionIntegrals {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        if s.revolution != self.revolution {
            self.prev = None;
            return ControlFlow::Continue(());
        }
        let p = &s.point;
        let f = [
            (p.load_displacement() - s.theory.y).powi(2),
            (p.load_velocity() - s.theory.v).powi(2),
            (p.load_acceleration() - s.theory.a).powi(2),
            (p.omega_c - self.omega0).powi(2),
            s.contact_stress,
        ];
        if let Some((t0, f0)) = self.prev {
            let dt = p.t - t0;
            if dt > 0.0 {
                self.duration += dt;
                for ((sum, a), b) in self.sums.iter_mut().zip(f0).zip(f) {
                    *sum += 0.5 * dt * (a + b);
                }
            }
        }
        self.prev = Some((p.t, f));
        ControlFlow::Continue(())
    }
}

/// Simulates `spec` (its `revolutions` set to [`REVOLUTION`]) and returns revolution 2's
/// outputs: the three load deviations from the per-period statistics ([`combine_rms`]),
/// the cam-speed deviation and the stress from [`RevolutionIntegrals`], and the jump
/// from the periods' flags.
pub fn outputs(spec: &RunSpec) -> Result<Outputs> {
    outputs_or_left_range(spec)?.map_err(|l| anyhow!(l.reason))
}

/// [`outputs`], or how the run left the model's valid range (docs/MODEL.md §3.20):
/// after a separation (a jump, the rule of `camsim jump-speed`) or with the follower on
/// the cam. Any other failure is an error.
pub fn outputs_or_left_range(spec: &RunSpec) -> Result<std::result::Result<Outputs, LeftRange>> {
    let mut s = spec.clone();
    s.revolutions = REVOLUTION;
    let mut integrals = RevolutionIntegrals::new(REVOLUTION, s.design.omega0);
    let mut watch = JumpWatch::<f64>::new();
    let r = match sim::run(&s, &mut Both(&mut integrals, &mut watch)) {
        Ok(r) => r,
        Err(e) => {
            let separated = jump_verdict::<(), (), f64>(Err(()), &watch).is_ok();
            if !crate::study::sweep::out_of_model(&e) {
                return Err(e);
            }
            let reason = format!("{}", e.root_cause());
            return Ok(Err(LeftRange { separated, reason }));
        }
    };
    let periods: Vec<_> = (0..s.design.program.segments().len())
        .filter_map(|i| r.stats.period(REVOLUTION, i))
        .filter(|p| p.samples > 0)
        .collect();
    anyhow::ensure!(
        !periods.is_empty(),
        "revolution {REVOLUTION} has no samples"
    );
    let combine = |f: fn(&camsim_core::PeriodStats<f64>) -> f64| {
        combine_rms(
            &periods
                .iter()
                .map(|p| (p.duration, f(p)))
                .collect::<Vec<_>>(),
        )
    };
    let m = integrals.means();
    let out = Outputs {
        rms_displacement_in: combine(|p| p.rms_displacement()),
        rms_velocity_in_per_s: combine(|p| p.rms_velocity()),
        rms_acceleration_in_per_s2: combine(|p| p.rms_acceleration()),
        rms_angular_velocity_rad_per_s: m[3],
        contact_stress_avg_psi: m[4],
        jump: periods.iter().any(|p| p.jump),
    };
    for ((name, _, _), v) in OUTPUTS.iter().zip(out.values()) {
        anyhow::ensure!(v.is_finite(), "{name} is {v}");
    }
    Ok(Ok(out))
}

/// A case whose run left the model's valid range (docs/MODEL.md §3.20): reported with its
/// reason, not in the table.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NotWorkableCase {
    /// "mass", "damping", "stiffness" or "baseline".
    pub group: &'static str,
    /// The group's change, %.
    pub change_pct: i32,
    /// "theoretical" or "actual".
    pub cam: &'static str,
    /// Whether the follower had separated before the run left the range: the case then
    /// jumps (the rule of `camsim jump-speed`), only its outputs are unknown.
    pub jump: bool,
    /// The core's error (the quantity, its value, the bound, the cam angle).
    pub reason: String,
}

impl NotWorkableCase {
    /// The case in words (`stiffness -30 % on the actual cam`).
    pub fn name(&self) -> String {
        if self.group == "baseline" {
            format!("baseline on the {} cam", self.cam)
        } else {
            format!(
                "{} {:+} % on the {} cam",
                self.group, self.change_pct, self.cam
            )
        }
    }

    /// What the case is, in words: a jump whose outputs are unknown, or not workable.
    pub fn verdict(&self) -> &'static str {
        if self.jump {
            "jumps, then the model left its valid range (a jump, docs/MODEL.md §3.20; no outputs)"
        } else {
            "not workable: the model left its valid range with the follower on the cam"
        }
    }
}

/// One case of the study (a baseline has group "baseline" and change 0).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    /// "mass", "damping", "stiffness" or "baseline".
    pub group: &'static str,
    /// The group's change, %.
    pub change_pct: i32,
    /// "theoretical" or "actual".
    pub cam: &'static str,
    /// Revolution 2's outputs.
    #[serde(flatten)]
    pub outputs: Outputs,
}

/// The elasticities of one key.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KeyElasticity {
    /// The scene key.
    pub key: &'static str,
    /// What it is.
    pub description: &'static str,
    /// Its value in the scene.
    pub value: f64,
    /// d ln(output) / d ln(key) of each output of [`OUTPUTS`] (absent where an output is
    /// 0 on either side, and all absent when the key is not workable).
    pub elasticity: Elasticities,
    /// Why the key has no elasticities: a perturbed design left the model's valid range
    /// (docs/MODEL.md §3.20).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_workable: Option<KeyNotWorkable>,
}

/// A key whose perturbed design left the model's valid range (docs/MODEL.md §3.20), or
/// that the design check refused (the same bounds on the static design): no elasticity.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KeyNotWorkable {
    /// The factor on the key's value (1 ± [`KEY_STEP`]).
    pub factor: f64,
    /// Whether the follower had separated first (a jump at that design, whose outputs
    /// are unknown).
    pub jump: bool,
    /// The core's error (the quantity, its value, the bound, the cam angle; or the key,
    /// its value and the rule).
    pub reason: String,
}

impl KeyNotWorkable {
    /// The row's text: `not workable at x0.99: reason`.
    pub fn text(&self) -> String {
        let what = if self.jump {
            "jumps, then the model left its valid range"
        } else {
            "not workable"
        };
        format!("{what} at x{}: {}", self.factor, self.reason)
    }
}

/// d ln(output) / d ln(key) for each output (absent where not defined).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Elasticities {
    /// Of the RMS displacement deviation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_displacement_in: Option<f64>,
    /// Of the RMS velocity deviation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_velocity_in_per_s: Option<f64>,
    /// Of the RMS acceleration deviation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_acceleration_in_per_s2: Option<f64>,
    /// Of the RMS cam-speed deviation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rms_angular_velocity_rad_per_s: Option<f64>,
    /// Of the average contact stress.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_stress_avg_psi: Option<f64>,
    /// Of the jump-onset speed (absent when either side has no onset up to 10 000 rpm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
}

impl Elasticities {
    /// The six, in [`OUTPUTS`]' order and the onset last.
    pub fn values(&self) -> [Option<f64>; 6] {
        [
            self.rms_displacement_in,
            self.rms_velocity_in_per_s,
            self.rms_acceleration_in_per_s2,
            self.rms_angular_velocity_rad_per_s,
            self.contact_stress_avg_psi,
            self.jump_onset_rpm,
        ]
    }
}

/// d ln f / d ln x from f at x (1 + h) and x (1 − h): (ln f₊ − ln f₋) / (ln(1 + h) −
/// ln(1 − h)), exact for a power law f = c xᵖ; None unless both values are positive and
/// finite.
pub fn elasticity(f_plus: f64, f_minus: f64, h: f64) -> Option<f64> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    (ok(f_plus) && ok(f_minus) && h > 0.0 && h < 1.0)
        .then(|| (f_plus.ln() - f_minus.ln()) / ((1.0 + h).ln() - (1.0 - h).ln()))
}

/// The keys `--per-key` perturbs: every numeric design key but the speed (ω0 and the
/// drive's reference speed: the operating point, which the onset search moves itself),
/// keys at 0 (no logarithmic derivative: the coupling's free play), and the modal
/// analysis's spring rate (not in the dynamic model), with its value in `design`.
pub fn per_key_keys(design: &Design<f64>) -> Result<Vec<(&'static str, &'static str, f64)>> {
    let v = serde_json::to_value(design)?;
    let mut out = Vec::new();
    for &(name, what) in key::DESIGN_KEYS {
        if [key::OMEGA0, key::DRIVE_OMEGA_REF, key::K_RS_MODAL].contains(&name) {
            continue;
        }
        let mut at = Some(&v);
        for part in name.split('.') {
            at = at.and_then(|x| x.get(part));
        }
        // The regulated drive's keys are absent with another drive.
        let Some(x) = at.and_then(|x| x.as_f64()) else {
            continue;
        };
        if x != 0.0 {
            out.push((name, what, x));
        }
    }
    Ok(out)
}

/// The jump-onset speed of `spec`'s design, rpm (None: none up to 10 000 rpm), from the
/// static start as `camsim jump-speed`.
pub fn onset_rpm(spec: &RunSpec, resolution: f64) -> Result<Option<f64>> {
    let mut s = spec.clone();
    s.solver.start = Start::Static;
    Ok(crate::study::jump_speed::find(&s, resolution, crate::study::jump_speed::MAX_RPM)?.jump_rpm)
}

/// `--per-key`'s result.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PerKey {
    /// The relative step of the central differences.
    pub step: f64,
    /// Resolution of the onset searches, rpm.
    pub onset_resolution_rpm: f64,
    /// The baseline's jump-onset speed, rpm (absent: none up to 10 000 rpm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_jump_onset_rpm: Option<f64>,
    /// Every key, by |elasticity of the onset| (largest first; keys without one last),
    /// ties by the largest |elasticity| of the other outputs.
    pub keys: Vec<KeyElasticity>,
}

/// What one `--per-key` job computes: the outputs and the onset at one perturbed design.
pub type KeyPoint = (Outputs, Option<f64>);

/// One `--per-key` job's outcome: its [`KeyPoint`], or how the design left the model's
/// valid range.
pub type KeyOutcome = std::result::Result<KeyPoint, LeftRange>;

/// `--per-key` on the theoretical cam of `spec`: [`per_key_with`] with the study's
/// outputs and the jump-onset speed to `resolution` rpm.
pub fn per_key(spec: &RunSpec, resolution: f64, threads: usize, progress: bool) -> Result<PerKey> {
    let base_onset = onset_rpm(spec, resolution)?;
    let keys = per_key_with(&spec.design, threads, progress, |d| {
        let mut s = spec.clone();
        s.design = d.clone();
        let out = match outputs_or_left_range(&s)? {
            Ok(out) => out,
            Err(l) => return Ok(Err(l)),
        };
        match onset_rpm(&s, resolution) {
            Ok(onset) => Ok(Ok((out, onset))),
            // The search met a speed where the run left the range on the cam.
            Err(e) if crate::study::sweep::out_of_model(&e) => Ok(Err(LeftRange {
                separated: false,
                reason: format!("in the onset search: {}", e.root_cause()),
            })),
            Err(e) => Err(e),
        }
    })?;
    Ok(PerKey {
        step: KEY_STEP,
        onset_resolution_rpm: resolution,
        baseline_jump_onset_rpm: base_onset,
        keys,
    })
}

/// Every key of [`per_key_keys`] at ±[`KEY_STEP`] ([`key_scaled`]), `eval` (the outputs
/// and the onset of a design, or how it left the model's valid range) on each, in
/// parallel on `threads` threads and collected by key, so the result does not depend on
/// the thread count; the elasticities ranked by the onset's magnitude (keys without one
/// last), ties by the largest of the others. A key whose perturbed design left the range,
/// or is refused by the design check, has none, with its reason ([`KeyNotWorkable`]);
/// the study fails only when no key has one.
pub fn per_key_with(
    design: &Design<f64>,
    threads: usize,
    progress: bool,
    eval: impl Fn(&Design<f64>) -> Result<KeyOutcome> + Sync,
) -> Result<Vec<KeyElasticity>> {
    let keys = per_key_keys(design)?;
    let jobs: Vec<(usize, f64)> = (0..keys.len())
        .flat_map(|i| [(i, 1.0 + KEY_STEP), (i, 1.0 - KEY_STEP)])
        .collect();
    let pool = crate::study::pool(threads)?;
    let bar = crate::study_limits::progress_bar(
        jobs.len() as u64,
        progress,
        "{elapsed_precise} [{bar:40}] {pos}/{len} perturbed designs, eta {eta}",
    );
    let results: Vec<Result<KeyOutcome>> = pool.install(|| {
        jobs.par_iter()
            .map(|&(i, f)| {
                let r = key_job(design, keys[i].0, f, &eval);
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut points = Vec::with_capacity(results.len());
    for r in results {
        points.push(r?);
    }
    let mut out: Vec<KeyElasticity> = keys
        .iter()
        .zip(points.chunks_exact(2))
        .map(|(&(name, what, value), pm)| key_row(name, what, value, &pm[0], &pm[1]))
        .collect();
    rank_keys(&mut out);
    if let Some(n) = out
        .iter()
        .map(|k| k.not_workable.as_ref())
        .collect::<Option<Vec<_>>>()
    {
        let first = out.first().map_or(String::new(), |k| k.key.to_string());
        anyhow::bail!(
            "no key is workable: at every key's ±{} % the model left its valid range (first: {first} {})",
            KEY_STEP * 100.0,
            n.first().map_or(String::new(), |n| n.text())
        );
    }
    Ok(out)
}

/// One `--per-key` job: `eval` at `name` times `factor`. A factor the design check
/// refuses (a bound of docs/MODEL.md §3.20 on the static design, as the cantilever's
/// length) is an outcome with its reason, as a run that left the range.
fn key_job(
    design: &Design<f64>,
    name: &str,
    factor: f64,
    eval: &(impl Fn(&Design<f64>) -> Result<KeyOutcome> + Sync),
) -> Result<KeyOutcome> {
    let refused = |e: &anyhow::Error| {
        e.chain().any(|c| {
            matches!(
                c.downcast_ref::<camsim_core::Error>(),
                Some(camsim_core::Error::InvalidParameter { .. })
            )
        })
    };
    match key_scaled(design, name, factor) {
        Ok(d) => eval(&d).with_context(|| format!("key {name} times {factor}")),
        Err(e) if refused(&e) => Ok(Err(LeftRange {
            separated: false,
            reason: format!("the design check refuses it: {}", e.root_cause()),
        })),
        Err(e) => Err(e),
    }
}

/// A key's row from its +/− outcomes: the elasticities, or none and why.
fn key_row(
    key: &'static str,
    description: &'static str,
    value: f64,
    plus: &KeyOutcome,
    minus: &KeyOutcome,
) -> KeyElasticity {
    let (p, m) = match (plus, minus) {
        (Ok(p), Ok(m)) => (p, m),
        (Err(l), _) | (_, Err(l)) => {
            let factor = if plus.is_err() {
                1.0 + KEY_STEP
            } else {
                1.0 - KEY_STEP
            };
            return KeyElasticity {
                key,
                description,
                value,
                elasticity: Elasticities::default(),
                not_workable: Some(KeyNotWorkable {
                    factor,
                    jump: l.separated,
                    reason: l.reason.clone(),
                }),
            };
        }
    };
    let e = |a: f64, b: f64| elasticity(a, b, KEY_STEP);
    let (pv, mv) = (p.0.values(), m.0.values());
    KeyElasticity {
        key,
        description,
        value,
        elasticity: Elasticities {
            rms_displacement_in: e(pv[0], mv[0]),
            rms_velocity_in_per_s: e(pv[1], mv[1]),
            rms_acceleration_in_per_s2: e(pv[2], mv[2]),
            rms_angular_velocity_rad_per_s: e(pv[3], mv[3]),
            contact_stress_avg_psi: e(pv[4], mv[4]),
            jump_onset_rpm: match (p.1, m.1) {
                (Some(a), Some(b)) => e(a, b),
                _ => None,
            },
        },
        not_workable: None,
    }
}

/// Ranks the keys by |elasticity of the onset| (keys without one last), ties by the
/// largest |elasticity| of the others; the not-workable keys (none) last, in key order.
fn rank_keys(out: &mut [KeyElasticity]) {
    let onset = |k: &KeyElasticity| k.elasticity.jump_onset_rpm.map_or(-1.0, f64::abs);
    let rest = |k: &KeyElasticity| {
        k.elasticity.values()[..5]
            .iter()
            .flatten()
            .fold(0.0f64, |a, b| a.max(b.abs()))
    };
    out.sort_by(|a, b| {
        (a.not_workable.is_some())
            .cmp(&b.not_workable.is_some())
            .then(onset(b).total_cmp(&onset(a)))
            .then(rest(b).total_cmp(&rest(a)))
    });
}

/// What `camsim sensitivity` prints.
#[derive(Clone, Debug, Serialize)]
pub struct SensitivityReport {
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Whether the vertical scene ran (--quick).
    pub quick: bool,
    /// The revolution measured.
    pub revolution: u32,
    /// The actual cam (sample 0 of the master seed).
    pub actual_profile: ProfileStats,
    /// The baseline on each cam (change 0).
    pub baseline: Vec<Case>,
    /// Every group, change and cam whose run stayed in the model's valid range.
    pub cases: Vec<Case>,
    /// The cases whose run left the model's valid range (docs/MODEL.md §3.20), in the
    /// study's order: each a jump (the follower had separated first) or not workable.
    pub not_workable: Vec<NotWorkableCase>,
    /// `--per-key`'s elasticities.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_key: Option<PerKey>,
    /// Wall-clock time, s.
    pub wall_s: f64,
}

fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r).map_err(|e| match e {
            camsim_core::Error::InvalidParameter { rule, .. } => anyhow!("--rpm {r}: {rule}"),
            other => other.into(),
        })?;
    }
    spec.revolutions = REVOLUTION;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    spec.design.validate()?;
    Ok(spec)
}

/// The study's error when no case has an answer: every run left the model's valid range
/// with the follower on the cam. A case that separated first is a jump, an answer (as a
/// Monte Carlo sample is).
pub fn all_failed(cases: &[Case], not_workable: &[NotWorkableCase]) -> Result<()> {
    match not_workable.first() {
        Some(n) if cases.is_empty() && not_workable.iter().all(|n| !n.jump) => anyhow::bail!(
            "no case is workable: every run left the model's valid range with the follower on the cam (first: {}: {})",
            n.name(),
            n.reason
        ),
        _ => Ok(()),
    }
}

/// One case: `spec` with group `g` changed by `c` %, on the theoretical cam or (`actual`)
/// on `dev`.
fn run_case(
    spec: &RunSpec,
    dev: &Arc<sim::HostDeviation>,
    g: Option<Group>,
    c: i32,
    actual: bool,
) -> Result<CaseOutcome> {
    let mut s = spec.clone();
    if let Some(g) = g {
        s.design = scaled(&spec.design, g, 1.0 + f64::from(c) / 100.0);
        s.design
            .validate()
            .with_context(|| format!("the {} group changed by {c:+} %", g.name()))?;
    }
    if actual {
        s.profile = Some(dev.clone());
    }
    let cam = if actual { "actual" } else { "theoretical" };
    let group = g.map_or("baseline", Group::name);
    let out = outputs_or_left_range(&s).with_context(|| format!("{cam} cam, {group} {c:+} %"))?;
    Ok(match out {
        Ok(outputs) => Ok(Case {
            group,
            change_pct: c,
            cam,
            outputs,
        }),
        Err(l) => Err(NotWorkableCase {
            group,
            change_pct: c,
            cam,
            jump: l.separated,
            reason: l.reason,
        }),
    })
}

/// A case's outcome: its outputs, or how it left the model's valid range.
type CaseOutcome = std::result::Result<Case, NotWorkableCase>;

/// Runs the study.
pub fn report(args: &Args) -> Result<SensitivityReport> {
    args.actual.refuse_actual_flag("sensitivity")?;
    let t0 = std::time::Instant::now();
    let spec = base_spec(args)?;
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    let mut actual_args = args.actual.clone();
    actual_args.actual = true;
    let (dev, profile) = actual::build_profile(&spec.design, &actual_args, 0)?;
    let dev = Arc::new(dev);
    let changes: &[i32] = if args.quick {
        &QUICK_CHANGES_PCT
    } else {
        &CHANGES_PCT
    };
    // Every job: (group or None for the baseline, change %, actual cam?).
    let mut jobs: Vec<(Option<Group>, i32, bool)> = vec![(None, 0, false), (None, 0, true)];
    for g in Group::ALL {
        for &c in changes {
            for actual in [false, true] {
                jobs.push((Some(g), c, actual));
            }
        }
    }
    let threads = crate::study::montecarlo::threads(args.threads);
    let pool = crate::study::pool(threads)?;
    let results: Vec<Result<CaseOutcome>> = pool.install(|| {
        jobs.par_iter()
            .map(|&(g, c, actual)| run_case(&spec, &dev, g, c, actual))
            .collect()
    });
    let (mut all, mut not_workable) = (Vec::new(), Vec::new());
    for r in results {
        match r? {
            Ok(c) => all.push(c),
            Err(n) => not_workable.push(n),
        }
    }
    all_failed(&all, &not_workable)?;
    let cases = all.split_off(all.iter().take_while(|c| c.group == "baseline").count());
    let per_key = if args.per_key {
        let res = if args.quick {
            QUICK_ONSET_RESOLUTION_RPM
        } else {
            ONSET_RESOLUTION_RPM
        };
        Some(per_key(&spec, res, threads, true)?)
    } else {
        None
    };
    let report = SensitivityReport {
        rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        quick: args.quick,
        revolution: REVOLUTION,
        actual_profile: profile,
        baseline: all,
        cases,
        not_workable,
        per_key,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    if let Some(t) = plot_target {
        crate::report::ensure_finite(&report)?;
        let mut dir = t.open()?;
        let fig = crate::plot::sensitivity::figure(&report);
        crate::figure::draw(&mut dir, PLOT_FILES[0], &fig, crate::units::current())?;
        dir.commit()?;
    }
    Ok(report)
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    crate::report::print(&report(&args)?, args.output.json)
}

/// A change in % to one decimal with its sign, `0.0` without one when it rounds to zero
/// (`-0.0%` read as a decrease where there is none to the printed digit).
fn signed_pct_1(d: f64) -> String {
    let text = format!("{d:+.1}");
    if text == "+0.0" || text == "-0.0" {
        "0.0".to_string()
    } else {
        text
    }
}

/// The change of `v` from `base`, % (None when the baseline is 0).
pub(crate) fn pct(v: f64, base: f64) -> Option<f64> {
    (base != 0.0).then(|| 100.0 * (v / base - 1.0))
}

/// An output's value as a designer reads it: stress in whole psi, others with four
/// significant digits, in plain notation from 0.001 up.
/// The unit of output `i` of [`OUTPUTS`] (`None`: the cam speed's rad/s, the same in
/// either family).
pub(crate) fn output_unit(i: usize) -> Option<camsim_scene_file::units::Unit> {
    use crate::units::{ACCELERATION, LENGTH, SPEED, STRESS};
    match i {
        0 => Some(LENGTH),
        1 => Some(SPEED),
        2 => Some(ACCELERATION),
        4 => Some(STRESS),
        _ => None,
    }
}

/// The unit label of output `i` in the output's family (`--units`): the table's own
/// (`in/s2`) in inch.
fn output_label(i: usize) -> &'static str {
    let inch = OUTPUTS.get(i).map_or("", |o| o.2);
    output_unit(i).map_or(inch, |u| crate::units::label(u, inch))
}

/// Output `i`'s value `v` (inch family) in the output's family: four significant
/// digits; the stress to the psi in inch (to 0.01 MPa in SI).
pub(crate) fn fmt_value(i: usize, v: f64) -> String {
    let unit = output_unit(i);
    let v = unit.map_or(v, |u| crate::units::value(u, v));
    if i == 4 {
        let d = unit.map_or(0, |u| crate::units::decimals(u, 0));
        return format!("{v:.d$}");
    }
    if v.abs() >= 1e4 {
        return format!("{v:.0}");
    }
    if v == 0.0 {
        return "0".to_string();
    }
    if v.abs() < 1e-3 {
        return format!("{v:.3e}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// A cam's table rows of the cases that left the model's valid range, and a note when its
/// baseline did (`has_baseline` false).
fn left_range_rows(out: &mut String, cases: &[NotWorkableCase], cam: &str, has_baseline: bool) {
    use std::fmt::Write;
    for n in cases.iter().filter(|n| n.cam == cam) {
        let change = format!("{:+}", n.change_pct);
        let _ = writeln!(out, "  {:<10} {change:>5}%  {}", n.group, n.verdict());
    }
    if !has_baseline {
        let _ = writeln!(
            out,
            "  (its baseline left the model's valid range: the changes are not computed against it)"
        );
    }
}

/// The cases that left the model's valid range, each with the core's reason.
fn left_range_text(out: &mut String, cases: &[NotWorkableCase]) {
    use std::fmt::Write;
    if cases.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nleft the model's valid range (docs/MODEL.md §3.20; after a separation the case is a jump, as in `camsim jump-speed`):"
    );
    for n in cases {
        let _ = writeln!(out, "  {}: {}", n.name(), n.reason);
    }
}

impl Report for SensitivityReport {
    fn text(&self) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let p = &self.actual_profile;
        let _ = writeln!(
            out,
            "camsim sensitivity (VI.4.3): every mass, every damper, every structural stiffness changed together, \
             at {:.1} rpm, {} model; revolution {} whole",
            self.rpm,
            if self.quick { "vertical (--quick)" } else { "full 11-DOF" },
            self.revolution
        );
        let _ = writeln!(
            out,
            "actual cam: sample 0 of seed {}, tolerances cam {} / roller {} / eccentricity {} {}, {} intervals \
             ({:.2} deg, {}), FPR {}; the same cam in every case",
            p.seed,
            crate::units::given(crate::units::LENGTH, p.cam_tolerance_in),
            crate::units::given(crate::units::LENGTH, p.roller_tolerance_in),
            crate::units::given(crate::units::LENGTH, p.eccentricity_tolerance_in),
            crate::units::symbol(crate::units::LENGTH),
            p.intervals,
            p.interval_deg,
            p.interval_source.name(),
            p.fpr
        );
        let _ = writeln!(
            out,
            "outputs: RMS deviations of the load from the theoretical response (displacement {}, velocity {}, \
             acceleration {}), RMS deviation of the cam speed from its nominal (rad/s), time-averaged Hertz \
             stress ({}); each case's value, then its change from the baseline",
            output_label(0),
            output_label(1),
            output_label(2),
            output_label(4)
        );
        for cam in ["theoretical", "actual"] {
            let b = self.baseline.iter().find(|c| c.cam == cam);
            let _ = writeln!(out, "\n{cam} cam");
            let _ = write!(out, "  {:<10} {:>6}", "group", "change");
            for (i, (_, h, _)) in OUTPUTS.iter().enumerate() {
                let _ = write!(out, " {:>19}", format!("{h} ({})", output_label(i)));
            }
            let _ = writeln!(out, "  jump");
            let row = |out: &mut String, c: &Case| {
                let _ = write!(
                    out,
                    "  {:<10} {:>5}%",
                    c.group,
                    format!("{:+}", c.change_pct)
                );
                let base = b.map_or([f64::NAN; 5], |b| b.outputs.values());
                for (i, (v, bv)) in c.outputs.values().into_iter().zip(base).enumerate() {
                    let cell = if c.group == "baseline" || bv.is_nan() {
                        fmt_value(i, v)
                    } else {
                        match pct(v, bv) {
                            Some(d) => format!("{} {:>6}%", fmt_value(i, v), signed_pct_1(d)),
                            None => fmt_value(i, v),
                        }
                    };
                    let _ = write!(out, " {cell:>19}");
                }
                let _ = writeln!(out, "  {}", if c.outputs.jump { "yes" } else { "no" });
            };
            if let Some(b) = b {
                row(&mut out, b);
            }
            for c in self.cases.iter().filter(|c| c.cam == cam) {
                row(&mut out, c);
            }
            left_range_rows(&mut out, &self.not_workable, cam, b.is_some());
        }
        left_range_text(&mut out, &self.not_workable);
        if let Some(pk) = &self.per_key {
            per_key_table(&mut out, pk);
        }
        let _ = writeln!(out, "\nrun time: {:.1} s", self.wall_s);
        out
    }
}

/// `--per-key`'s table: each key's elasticities, ranked, a not-workable key on a line of
/// its own.
fn per_key_table(out: &mut String, pk: &PerKey) {
    use std::fmt::Write;
    let _ = writeln!(
            out,
            "\nelasticity d ln(output) / d ln(key), central differences at ±{} % on the theoretical cam; \
             jump onset {} (static start, resolution {} rpm); ranked by |onset elasticity|",
            pk.step * 100.0,
            pk.baseline_jump_onset_rpm
                .map_or("none up to 10 000 rpm".to_string(), |r| format!("{r:.2} rpm")),
            pk.onset_resolution_rpm
        );
    let _ = write!(out, "  {:>4} {:<42}", "rank", "key");
    for (_, h, _) in OUTPUTS {
        let _ = write!(out, " {h:>10}");
    }
    let _ = writeln!(out, " {:>10}", "onset");
    for (i, k) in pk.keys.iter().enumerate() {
        // The key under its name in the output's family (an elasticity is the
        // same in either).
        let key = crate::units::key_in(k.key, crate::units::current()).0;
        if let Some(n) = &k.not_workable {
            let _ = writeln!(out, "  {:>4} {key:<42} {}", "-", n.text());
            continue;
        }
        let _ = write!(out, "  {:>4} {:<42}", i + 1, key);
        for v in k.elasticity.values() {
            match v {
                Some(v) => {
                    let _ = write!(out, " {v:>10.4}");
                }
                None => {
                    let _ = write!(out, " {:>10}", "-");
                }
            }
        }
        let _ = writeln!(out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use camsim_core::{modal_analysis, rotational_system};
    use std::collections::BTreeMap;

    /// A change that rounds to zero reads 0.0 with no sign; any other keeps its sign.
    /// Only cases that left the range with the follower on the cam fail; one case with
    /// outputs, or one that jumped first, is an answer.
    #[test]
    fn a_study_fails_only_when_every_case_failed_without_a_separation() {
        let nw = |jump| NotWorkableCase {
            group: "mass",
            change_pct: -30,
            cam: "actual",
            jump,
            reason: "the model left its valid range at cam angle 1 deg".into(),
        };
        let e = all_failed(&[], &[nw(false), nw(false)]).unwrap_err();
        assert!(
            format!("{e}").contains("no case is workable")
                && format!("{e}").contains("mass -30 % on the actual cam"),
            "{e}"
        );
        assert!(all_failed(&[], &[nw(false), nw(true)]).is_ok());
        assert!(all_failed(&[], &[]).is_ok());
        let case = Case {
            group: "baseline",
            change_pct: 0,
            cam: "theoretical",
            outputs: Outputs {
                rms_displacement_in: 0.0,
                rms_velocity_in_per_s: 0.0,
                rms_acceleration_in_per_s2: 0.0,
                rms_angular_velocity_rad_per_s: 0.0,
                contact_stress_avg_psi: 0.0,
                jump: false,
            },
        };
        assert!(all_failed(&[case], &[nw(false)]).is_ok());
    }

    #[test]
    fn a_change_that_rounds_to_zero_has_no_sign() {
        assert_eq!(signed_pct_1(-0.04), "0.0");
        assert_eq!(signed_pct_1(0.049), "0.0");
        assert_eq!(signed_pct_1(0.0), "0.0");
        assert_eq!(signed_pct_1(-0.06), "-0.1");
        assert_eq!(signed_pct_1(39.6), "+39.6");
        assert_eq!(signed_pct_1(-0.2), "-0.2");
    }

    /// Every numeric leaf of a design's serialization, by dotted key.
    fn leaves(d: &Design<f64>) -> BTreeMap<String, f64> {
        fn walk(v: &serde_json::Value, path: &str, out: &mut BTreeMap<String, f64>) {
            match v {
                serde_json::Value::Object(o) => {
                    for (k, x) in o {
                        let p = if path.is_empty() {
                            k.clone()
                        } else {
                            format!("{path}.{k}")
                        };
                        walk(x, &p, out);
                    }
                }
                serde_json::Value::Array(a) => {
                    for (i, x) in a.iter().enumerate() {
                        walk(x, &format!("{path}[{i}]"), out);
                    }
                }
                serde_json::Value::Number(n) => {
                    out.insert(path.to_string(), n.as_f64().unwrap());
                }
                _ => {}
            }
        }
        let mut out = BTreeMap::new();
        walk(&serde_json::to_value(d).unwrap(), "", &mut out);
        out
    }

    /// The keys whose value differs between two designs, with the ratio new / old.
    fn changed(a: &Design<f64>, b: &Design<f64>) -> BTreeMap<String, f64> {
        let (la, lb) = (leaves(a), leaves(b));
        assert_eq!(la.keys().collect::<Vec<_>>(), lb.keys().collect::<Vec<_>>());
        la.iter()
            .filter(|(k, v)| lb[*k] != **v)
            .map(|(k, v)| (k.clone(), lb[k] / v))
            .collect()
    }

    #[test]
    fn each_group_moves_exactly_its_listed_parameters() {
        let d = Design::<f64>::reference();
        let f = 1.37;
        for g in Group::ALL {
            let s = scaled(&d, g, f);
            s.validate().unwrap();
            let c = changed(&d, &s);
            let mut want: Vec<&str> = g.keys().to_vec();
            want.sort_unstable();
            assert_eq!(
                c.keys().map(String::as_str).collect::<Vec<_>>(),
                want,
                "{g:?}"
            );
            for (k, r) in &c {
                assert!((r - f).abs() < 1e-15, "{g:?} {k}: ratio {r}");
            }
            // Neither the return spring nor the Hertz contact nor the program moves.
            assert_eq!(
                (s.k_rs, s.delta_rs, s.k_rs_modal),
                (d.k_rs, d.delta_rs, d.k_rs_modal)
            );
            assert_eq!(s.hertz, d.hertz);
            assert_eq!(s.geometry, d.geometry);
            assert_eq!(s.program, d.program);
            // A change of 0 is the baseline exactly.
            assert_eq!(scaled(&d, g, 1.0), d);
        }
        // Without the regulated drive the damping group has no feed-forward to move.
        let mut ideal = d.clone();
        ideal.drive = DriveLaw::ConstantCamSpeed;
        let c = changed(&ideal, &scaled(&ideal, Group::Damping, f));
        assert_eq!(c.len(), DAMPING_KEYS.len() - 1);
        assert!(!c.contains_key(key::DRIVE_T_STEADY));
        // The groups do not overlap.
        let mut all: Vec<&str> = Group::ALL.iter().flat_map(|g| g.keys().to_vec()).collect();
        all.sort_unstable();
        let n = all.len();
        all.dedup();
        assert_eq!(all.len(), n);
    }

    /// The rotational system (Eq. VI.7) is made of the groups' parameters alone: masses
    /// times λ divide its natural frequencies by sqrt(λ); masses and stiffnesses times λ
    /// leave them; stiffnesses times λ multiply them by sqrt(λ).
    #[test]
    fn natural_frequencies_scale_as_sqrt_of_stiffness_over_mass() {
        let omegas = |d: &Design<f64>| {
            let (k, m) = rotational_system(d.i_m, d.i_cp, d.i_c, d.k_s1, d.k_s2);
            modal_analysis(&k, &m).unwrap().omega
        };
        let d = Design::<f64>::reference();
        let w = omegas(&d);
        assert!(w[0].abs() < 1e-6 * w[2] && w[1] > 0.0, "{w:?}");
        for lambda in [0.7, 1.3] {
            let m = scaled(&d, Group::Mass, lambda);
            let mk = scaled(&m, Group::Stiffness, lambda);
            let k = scaled(&d, Group::Stiffness, lambda);
            for (got, want) in [
                (omegas(&m), 1.0 / lambda.sqrt()),
                (omegas(&mk), 1.0),
                (omegas(&k), lambda.sqrt()),
            ] {
                for i in 1..3 {
                    let r = got[i] / w[i];
                    assert!(
                        (r - want).abs() < 1e-12,
                        "lambda {lambda}: mode {i} ratio {r}, want {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn elasticity_is_exact_for_a_power_law_and_undefined_at_zero() {
        for p in [-2.5, -1.0, 0.0, 0.5, 3.0] {
            let f = |x: f64| 7.0 * x.powf(p);
            let x = 3.3;
            let e = elasticity(f(x * 1.01), f(x * 0.99), 0.01).unwrap();
            assert!((e - p).abs() < 1e-10, "{p}: {e}");
        }
        assert_eq!(elasticity(0.0, 1.0, 0.01), None);
        assert_eq!(elasticity(1.0, f64::NAN, 0.01), None);
        assert_eq!(elasticity(1.0, 1.0, 0.0), None);
    }

    /// The preload F_p = K_t K_rs δ_rs / (K_t + K_rs) (Eq. V.18) through the per-key
    /// perturbation: its elasticity on δ_rs is 1, on K_rs K_t / (K_t + K_rs), on K_rb
    /// (K_t / K_rb)·K_rs / (K_t + K_rs), to the central difference's O(h²).
    #[test]
    fn preload_elasticities_match_their_closed_forms() {
        let d = Design::<f64>::reference();
        let fp = |name: &str, f: f64| key_scaled(&d, name, f).unwrap().preload().unwrap();
        let e = |name: &str| elasticity(fp(name, 1.01), fp(name, 0.99), 0.01).unwrap();
        let k_h = d.k_h_base().unwrap();
        let k_t = 1.0 / (1.0 / d.k_rb + 1.0 / k_h + 1.0 / d.k_vs);
        assert!((e(key::DELTA_RS) - 1.0).abs() < 1e-12);
        let want = k_t / (k_t + d.k_rs);
        assert!(
            (e(key::K_RS) - want).abs() < 1e-5,
            "{} {want}",
            e(key::K_RS)
        );
        let want = (k_t / d.k_rb) * d.k_rs / (k_t + d.k_rs);
        assert!(
            (e(key::K_RB) - want).abs() < 1e-5 * want.max(1e-3),
            "{} {want}",
            e(key::K_RB)
        );
    }

    #[test]
    fn every_per_key_key_moves_one_number_by_its_factor() {
        let d = Design::<f64>::reference();
        let keys = per_key_keys(&d).unwrap();
        // Every design key but ω0, the drive's reference speed, the modal spring rate
        // and the free play (0).
        assert_eq!(keys.len(), key::DESIGN_KEYS.len() - 4);
        for (name, _, value) in keys {
            let s = key_scaled(&d, name, 1.01).unwrap();
            let c = changed(&d, &s);
            assert_eq!(c.len(), 1, "{name}: {c:?}");
            let (k, r) = c.iter().next().unwrap();
            assert_eq!(k, name);
            assert!((r - 1.01).abs() < 1e-15);
            assert_eq!(leaves(&d)[name], value);
        }
        assert!(key_scaled(&d, "no_such_key", 1.01).is_err());
        assert!(key_scaled(&d, key::K_RB, -1.0).is_err());
    }

    #[test]
    fn combined_rms_is_the_duration_weighted_mean_square() {
        // (1 s at RMS 3, 3 s at RMS 1): sqrt((9 + 3) / 4).
        assert!((combine_rms(&[(1.0, 3.0), (3.0, 1.0)]) - 3f64.sqrt()).abs() < 1e-15);
        assert_eq!(combine_rms(&[]), 0.0);
    }

    /// Revolution 2's RMS deviations combined from the per-period statistics equal the
    /// same integrals taken directly over the revolution (which also cover the few steps
    /// that straddle a period boundary, a few of some thousands).
    #[test]
    fn combined_rms_matches_the_direct_integral_of_the_revolution() {
        let mut spec = RunSpec::reference();
        spec.dofs.horizontal = false;
        let out = outputs(&spec).unwrap();
        let mut s = spec.clone();
        s.revolutions = REVOLUTION;
        let mut direct = RevolutionIntegrals::new(REVOLUTION, s.design.omega0);
        sim::run(&s, &mut direct).unwrap();
        let m = direct.means();
        let period = 2.0 * std::f64::consts::PI / s.design.omega0;
        assert!(
            (direct.duration / period - 1.0).abs() < 0.05,
            "{}",
            direct.duration
        );
        for (i, v) in out.values()[..3].iter().enumerate() {
            assert!(
                (v / m[i] - 1.0).abs() < 2e-3,
                "output {i}: {v} against {}",
                m[i]
            );
        }
        // The cam's speed deviation and stress come from the direct integrals.
        assert_eq!(out.rms_angular_velocity_rad_per_s, m[3]);
        assert_eq!(out.contact_stress_avg_psi, m[4]);
        // On the base circle the stress is tens of thousands of psi: a positive average
        // below the largest per-period stress.
        assert!(out.contact_stress_avg_psi > 1e4 && out.contact_stress_avg_psi < 3e5);
        // The same run again: the same numbers (the baseline is a change of 0).
        assert_eq!(outputs(&spec).unwrap(), out);
    }

    /// `--per-key`'s bookkeeping on a model whose outputs are power laws of the keys:
    /// each elasticity is its exponent, whatever the thread count, and the ranking
    /// follows the onset's magnitude.
    #[test]
    fn per_key_recovers_the_exponents_of_a_power_law_model_and_ranks_by_the_onset() {
        let eval = |d: &Design<f64>| -> Result<KeyOutcome> {
            let out = Outputs {
                rms_displacement_in: d.k_rs.powf(0.5) * d.m_l.powf(-2.0),
                rms_velocity_in_per_s: d.rho.powf(1.5),
                rms_acceleration_in_per_s2: 3.0,
                rms_angular_velocity_rad_per_s: d.k_s1.powf(-0.25),
                contact_stress_avg_psi: d.hertz.youngs_1.powf(0.5),
                jump: false,
            };
            // No onset when the roller is light (a key without one ranks last).
            let onset =
                (d.m_r >= 0.00013).then(|| 900.0 * (d.k_rs / d.rho).sqrt() * d.e1.powf(0.1));
            Ok(Ok((out, onset)))
        };
        let d = Design::<f64>::reference();
        let one = per_key_with(&d, 1, false, eval).unwrap();
        let two = per_key_with(&d, 2, false, eval).unwrap();
        assert_eq!(one, two);
        assert_eq!(one.len(), per_key_keys(&d).unwrap().len());
        let get = |k: &str| one.iter().find(|x| x.key == k).unwrap().elasticity.clone();
        let close = |a: Option<f64>, b: f64| (a.unwrap() - b).abs() < 1e-9;
        assert!(close(get(key::K_RS).rms_displacement_in, 0.5));
        assert!(close(get(key::M_L).rms_displacement_in, -2.0));
        assert!(close(get(key::RHO).rms_velocity_in_per_s, 1.5));
        assert!(close(get(key::K_S1).rms_angular_velocity_rad_per_s, -0.25));
        assert!(close(get(key::ROLLER_YOUNGS).contact_stress_avg_psi, 0.5));
        assert!(close(get(key::K_RS).jump_onset_rpm, 0.5));
        assert!(close(get(key::RHO).jump_onset_rpm, -0.5));
        assert!(close(get(key::E1).jump_onset_rpm, 0.1));
        assert!(close(get(key::C_MB).jump_onset_rpm, 0.0));
        assert!(close(get(key::C_MB).rms_acceleration_in_per_s2, 0.0));
        // The roller's mass at −1 % has no onset: no elasticity, ranked last.
        assert_eq!(get(key::M_R).jump_onset_rpm, None);
        assert_eq!(one.last().unwrap().key, key::M_R);
        // Ranked by |onset|: ρ and K_rs tie at 0.5, ρ first by its larger other
        // elasticity (1.5 against K_rs's 0.5), then e1 (0.1).
        let top: Vec<&str> = one.iter().take(3).map(|k| k.key).collect();
        assert_eq!(top, [key::RHO, key::K_RS, key::E1]);
        // A failing evaluation names the key.
        let e = per_key_with(&d, 1, false, |_| -> Result<KeyOutcome> {
            anyhow::bail!("boom")
        })
        .unwrap_err();
        assert!(format!("{e:#}").contains("times 1.01: boom"), "{e:#}");
    }

    /// A key whose perturbed design leaves the model's valid range (docs/MODEL.md
    /// §3.20) has no elasticity and says why, at which factor and whether it jumped
    /// first; so does one the design check refuses at −1 % (a cantilever 1.885 in long
    /// clears the roller at full lift by 0.01 in, 0.99 of it by −0.009 in); they rank
    /// last; the others keep their exponents; only a study of no workable key fails.
    /// The reference with a cantilever 0.01 in longer than the roller's reach at full lift.
    fn design_at_the_edge() -> Design<f64> {
        let mut d = Design::<f64>::reference();
        d.e2 = d.program.max_lift() + d.geometry.roller_radius + 0.01;
        d.validate().unwrap();
        d
    }

    /// A stand-in study of known exponents: a softer k_s2 than `base`'s leaves the range,
    /// a heavier load jumps and then leaves it; the others give rms y ∝ k_rs^0.5 and an
    /// onset ∝ rho^-0.5.
    fn stand_in(base: &Design<f64>, d: &Design<f64>) -> Result<KeyOutcome> {
        let (k_s2, m_l) = (base.k_s2, base.m_l);
        {
            if d.k_s2 < k_s2 {
                return Ok(Err(LeftRange {
                    separated: false,
                    reason: "twist beyond its bound".into(),
                }));
            }
            if d.m_l > m_l {
                return Ok(Err(LeftRange {
                    separated: true,
                    reason: "thrown off".into(),
                }));
            }
            let out = Outputs {
                rms_displacement_in: d.k_rs.powf(0.5),
                rms_velocity_in_per_s: 1.0,
                rms_acceleration_in_per_s2: 1.0,
                rms_angular_velocity_rad_per_s: 1.0,
                contact_stress_avg_psi: 1.0,
                jump: false,
            };
            Ok(Ok((out, Some(900.0 * d.rho.powf(-0.5)))))
        }
    }

    #[test]
    fn per_key_reports_keys_that_leave_the_range_and_goes_on() {
        let d = design_at_the_edge();
        let keys = per_key_with(&d, 2, false, |x| stand_in(&d, x)).unwrap();
        assert_eq!(keys.len(), per_key_keys(&d).unwrap().len());
        let row = |k: &str| keys.iter().find(|x| x.key == k).unwrap();
        let nw = |k: &str| row(k).not_workable.clone().unwrap();
        assert_eq!((nw(key::K_S2).factor, nw(key::K_S2).jump), (0.99, false));
        assert_eq!(nw(key::K_S2).reason, "twist beyond its bound");
        assert_eq!((nw(key::M_L).factor, nw(key::M_L).jump), (1.01, true));
        let e2 = nw(key::E2);
        assert_eq!((e2.factor, e2.jump), (0.99, false));
        assert!(
            e2.reason.contains("design check refuses") && e2.reason.contains(key::E2),
            "{}",
            e2.reason
        );
        assert_eq!(
            nw(key::K_S2).text(),
            "not workable at x0.99: twist beyond its bound"
        );
        assert!(nw(key::M_L)
            .text()
            .starts_with("jumps, then the model left"));
        for k in [key::K_S2, key::M_L, key::E2] {
            assert_eq!(row(k).elasticity, Elasticities::default(), "{k}");
        }
        let n = keys.len();
        let mut last: Vec<&str> = keys[n - 3..].iter().map(|k| k.key).collect();
        last.sort_unstable();
        let mut want = [key::K_S2, key::M_L, key::E2];
        want.sort_unstable();
        assert_eq!(last, want);
        assert!((row(key::K_RS).elasticity.rms_displacement_in.unwrap() - 0.5).abs() < 1e-9);
        assert!((row(key::RHO).elasticity.jump_onset_rpm.unwrap() + 0.5).abs() < 1e-9);
        assert_eq!(keys[0].key, key::RHO);
        // JSON: no elasticity numbers, the reason beside them.
        let j = serde_json::to_value(row(key::K_S2)).unwrap();
        assert_eq!(j["elasticity"], serde_json::json!({}));
        assert_eq!(j["not_workable"]["reason"], "twist beyond its bound");
        assert!(serde_json::to_value(row(key::K_RS))
            .unwrap()
            .get("not_workable")
            .is_none());
    }

    /// Every key out of range: the study fails, naming why.
    #[test]
    fn per_key_with_no_workable_key_fails_naming_why() {
        let d = design_at_the_edge();
        let e = per_key_with(&d, 1, false, |_| -> Result<KeyOutcome> {
            Ok(Err(LeftRange {
                separated: false,
                reason: "stalled".into(),
            }))
        })
        .unwrap_err();
        let msg = format!("{e:#}");
        assert!(
            msg.contains("no key is workable") && msg.contains("stalled"),
            "{msg}"
        );
    }
}
