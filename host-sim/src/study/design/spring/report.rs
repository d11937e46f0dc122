//! `design spring`'s report: what was checked at the answer, and the answer's spring.

use std::time::Instant;

use anyhow::Result;
use serde::Serialize;

use super::part::PartReport;
use super::search::{with_value, Answer};
use super::Searched;
use crate::sim::RunSpec;
use crate::stats::Probability;
use crate::study::montecarlo::ProfileSettings;
use crate::units::{Force, Kind, Length, Measure, Stiffness, Weight};

/// What was checked at the chosen rate.
#[derive(Clone, Debug, Serialize)]
pub struct SpringReport {
    /// What the search varied: `spring rate` (at the preload length) or `preload length`
    /// (at the rate, with --preload).
    pub searched: Searched,
    /// The smallest rate found that passes, lb/in (with --preload: the rate held).
    pub spring_rate_lb_per_in: Stiffness,
    /// The largest rate tried that fails, lb/in (absent: the first rate tried passed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing_rate_lb_per_in: Option<Stiffness>,
    /// Bracket width, lb/in (the answer is within it of the true smallest rate; 0 with
    /// --preload, where the rate is held).
    pub bracket_lb_per_in: Stiffness,
    /// With --preload: the longest preload length tried that fails, in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failing_preload_length_in: Option<Length>,
    /// With --preload: the bracket width, in.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload_bracket_in: Option<Length>,
    /// The spring's preload at assembly, lb.
    pub preload_lb: Force,
    /// Preload length, in.
    pub preload_length_in: Length,
    /// Its mass by the wire-and-coil model, lb.
    pub spring_mass_lb: Weight,
    /// Its active coils.
    pub active_coils: f64,
    /// Its surge frequency, Hz.
    pub surge_hz: f64,
    /// Operating speed, rpm.
    pub operating_rpm: f64,
    /// The criterion, in words.
    pub criterion: String,
    /// Theoretical cam: the speed contact was required at, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub checked_at_rpm: Option<f64>,
    /// Theoretical cam: the jump onset of the chosen spring, rpm (a second search).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// Its bracket, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_bracket_rpm: Option<f64>,
    /// Actual cams: P(jump) at the chosen rate with its 95 % interval.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p_jump: Option<Probability>,
    /// Actual cams: samples per rate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples: Option<u64>,
    /// Actual cams: the master seed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Actual cams: how they are made (method, normal deviates, tolerances, interval).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileSettings>,
    /// Which model produced the answer.
    pub model: String,
    /// The rates tried in order, each with whether it passed (absent with --preload).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rates_tried_lb_per_in: Option<Vec<(Stiffness, bool)>>,
    /// With --preload: the preload lengths tried in order, each with whether it passed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preload_lengths_tried_in: Option<Vec<(Length, bool)>>,
    /// The spring to build: wire, coil and coils that pass every check of the verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<PartReport>,
    /// Model runs of the search (each of 2 revolutions), and of the onset check.
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}
/// What a spring search found, before the answer's spring is worked out.
pub(super) struct Found {
    pub(super) answer: Answer,
    pub(super) criterion: String,
    pub(super) model: String,
    pub(super) tried: Vec<(f64, bool)>,
    pub(super) part: PartReport,
    pub(super) model_runs: u64,
}
/// The report of a search's answer on `spec` (the rate or the preload length in their own
/// fields, the other held at the scene's), with the answer's spring ([`spring_of_answer`]);
/// what only one criterion gives is absent.
pub(super) fn answered(found: Found, spec: &RunSpec, t0: Instant) -> Result<SpringReport> {
    let Found {
        answer,
        criterion,
        model,
        tried,
        part,
        model_runs,
    } = found;
    let spring = spring_of_answer(spec, answer, &part)?;
    let (rates_tried, lengths_tried) = match answer.searched {
        Searched::Rate => (Some(measured(&tried)), None),
        Searched::PreloadLength => (None, Some(measured(&tried))),
    };
    let (rate, failing_rate, bracket, failing_length, length_bracket) = match answer.searched {
        Searched::Rate => (
            answer.value,
            answer.failing.map(Stiffness::inch),
            answer.bracket(),
            None,
            None,
        ),
        Searched::PreloadLength => (
            spec.design.k_rs,
            None,
            0.0,
            answer.failing.map(Length::inch),
            Some(Length::inch(answer.bracket())),
        ),
    };
    Ok(SpringReport {
        searched: answer.searched,
        spring_rate_lb_per_in: Stiffness::inch(rate),
        failing_rate_lb_per_in: failing_rate,
        bracket_lb_per_in: Stiffness::inch(bracket),
        failing_preload_length_in: failing_length,
        preload_bracket_in: length_bracket,
        preload_lb: Force::inch(spring.preload_lb),
        preload_length_in: Length::inch(spring.preload_length_in),
        spring_mass_lb: Weight::inch(spring.mass_lb),
        active_coils: spring.active_coils,
        surge_hz: spring.surge_hz,
        operating_rpm: camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        criterion,
        checked_at_rpm: None,
        jump_onset_rpm: None,
        jump_onset_bracket_rpm: None,
        p_jump: None,
        samples: None,
        seed: None,
        profile: None,
        model,
        rates_tried_lb_per_in: rates_tried,
        preload_lengths_tried_in: lengths_tried,
        part: Some(part),
        model_runs,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}
/// The spring of a search's answer: its preload, and the part's own preload length, mass,
/// coils and surge.
struct AnswerSpring {
    preload_lb: f64,
    preload_length_in: f64,
    mass_lb: f64,
    active_coils: f64,
    surge_hz: f64,
}

/// The answer's spring: `spec` at the answer (validated), built as `part` (its own rate and
/// preload length), and its preload.
fn spring_of_answer(spec: &RunSpec, answer: Answer, part: &PartReport) -> Result<AnswerSpring> {
    let mut chosen = with_value(
        spec,
        answer.value,
        answer.searched == Searched::PreloadLength,
    )?;
    chosen.design.k_rs = part.spring.rate_lb_per_in.in_inch();
    chosen.design.delta_rs = part.preload_length_in.in_inch();
    Ok(AnswerSpring {
        preload_lb: chosen.design.preload()?,
        preload_length_in: part.preload_length_in.in_inch(),
        mass_lb: part.spring.mass_lb.in_inch(),
        active_coils: part.spring.active_coils,
        surge_hz: part.spring.surge_hz,
    })
}

/// The values a search tried (inch family), each with whether it passed, as measures.
fn measured<K: Kind>(tried: &[(f64, bool)]) -> Vec<(Measure<K>, bool)> {
    tried
        .iter()
        .map(|&(x, ok)| (Measure::inch(x), ok))
        .collect()
}
