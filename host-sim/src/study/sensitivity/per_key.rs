//! `--per-key`: every design key's elasticity d ln(output) / d ln(key) by central
//! differences ([`key_scaled`], [`per_key`]), ranked by the jump onset's.

use anyhow::{anyhow, Context, Result};
use camsim_core::{key, Design, Start};
use rayon::prelude::*;
use serde::Serialize;

use super::outputs::{outputs_or_left_range, Outputs};
use super::KEY_STEP;
use crate::sim::RunSpec;
use crate::study::montecarlo::LeftRange;

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

/// The elasticities of one key.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct KeyElasticity {
    /// The scene key.
    pub key: &'static str,
    /// What it is.
    pub description: &'static str,
    /// Its value in the scene.
    pub value: f64,
    /// d ln(output) / d ln(key) of each output of [`OUTPUTS`](super::OUTPUTS) (absent where an output is
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

/// d ln(output) / d ln(key) for each output (absent where not defined). Elasticities have
/// no unit: their JSON keys name the output without one, so no unit family converts them.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Elasticities {
    /// Of the RMS displacement deviation.
    #[serde(
        rename = "rms_displacement_deviation",
        skip_serializing_if = "Option::is_none"
    )]
    pub rms_displacement_in: Option<f64>,
    /// Of the RMS velocity deviation.
    #[serde(
        rename = "rms_velocity_deviation",
        skip_serializing_if = "Option::is_none"
    )]
    pub rms_velocity_in_per_s: Option<f64>,
    /// Of the RMS acceleration deviation.
    #[serde(
        rename = "rms_acceleration_deviation",
        skip_serializing_if = "Option::is_none"
    )]
    pub rms_acceleration_in_per_s2: Option<f64>,
    /// Of the RMS cam-speed deviation.
    #[serde(
        rename = "rms_cam_speed_deviation",
        skip_serializing_if = "Option::is_none"
    )]
    pub rms_angular_velocity_rad_per_s: Option<f64>,
    /// Of the average contact stress.
    #[serde(
        rename = "contact_stress_average",
        skip_serializing_if = "Option::is_none"
    )]
    pub contact_stress_avg_psi: Option<f64>,
    /// Of the jump-onset speed (absent when either side has no onset up to 10 000 rpm).
    #[serde(rename = "jump_onset_speed", skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
}

impl Elasticities {
    /// The six, in [`OUTPUTS`](super::OUTPUTS)' order and the onset last.
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
