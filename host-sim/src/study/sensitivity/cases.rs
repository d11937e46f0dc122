//! The group study of VI.4.3: every mass, every damper, every structural stiffness changed
//! together ([`Group`], [`scaled`]), each case run on the theoretical and the actual cam.

use std::sync::Arc;

use anyhow::{Context, Result};
use camsim_core::{key, Design, DriveLaw};
use rayon::prelude::*;
use serde::Serialize;

use super::outputs::{outputs_or_left_range, Outputs};
use crate::sim::{self, RunSpec};

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

/// The baseline and every case of `changes` on both cams (`dev` the actual cam's
/// deviation), in the study's order: (baselines, cases, cases that left the model's
/// valid range). Fails when no case has an answer ([`all_failed`]).
pub fn run_cases(
    spec: &RunSpec,
    dev: &Arc<sim::HostDeviation>,
    changes: &[i32],
    threads: usize,
) -> Result<(Vec<Case>, Vec<Case>, Vec<NotWorkableCase>)> {
    // Every job: (group or None for the baseline, change %, actual cam?).
    let mut jobs: Vec<(Option<Group>, i32, bool)> = vec![(None, 0, false), (None, 0, true)];
    for g in Group::ALL {
        for &c in changes {
            for actual in [false, true] {
                jobs.push((Some(g), c, actual));
            }
        }
    }
    let pool = crate::study::pool(threads)?;
    let results: Vec<Result<CaseOutcome>> = pool.install(|| {
        jobs.par_iter()
            .map(|&(g, c, actual)| run_case(spec, dev, g, c, actual))
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
    Ok((all, cases, not_workable))
}
