//! `design spring`: the smallest return-spring rate (at the scene's preload length; its mass
//! follows the rate by the wire-and-coil model, core's `HelicalSpring`) that holds contact
//! with a margin: on the theoretical cam, contact in steady state at `(1 + margin/100)`
//! times the operating speed ([`crate::sim::jumps_at`], the jump predicate of
//! `camsim jump-speed`); on actual cams, the upper end of the 95 % Wilson interval of
//! P(jump) at the operating speed at most the limit (the Monte Carlo of `camsim
//! montecarlo`, on the quasi-static-cantilever follower that docs/RESULTS.md "Reduced
//! scenes" shows adequate on actual cams). With a preload search, the shortest preload
//! length at the rate held. The search doubles from [`START_RATE`], then bisects to the
//! resolution. Then the spring to build: the lightest standard part that passes.

use std::time::Instant;

use anyhow::{bail, Result};
use camsim_core::{Onset, OnsetSearch, Start};
use serde::Serialize;

use super::{check_search_time, describe, p_jump_on_actual_cams, p_max_and_samples, search_steps};
use crate::actual::{intervals_for, Cams};
use crate::args::{spec_from, SceneArgs};
use crate::report::Report;
use crate::sim::{self, RunSpec};
use crate::stats::Probability;
use crate::study::coil_spring::{candidates, CoilChoice, CoilQuery, Rejections};
use crate::study::montecarlo::{threads, ProfileSettings};
use crate::units::{self, Force, Length, Stiffness, Stress, Units, Weight};

/// What `design spring` is asked.
#[derive(Clone, Debug)]
pub struct SpringSpec {
    /// The scene and its overrides (the operating speed is its rpm).
    pub scene: SceneArgs,
    /// Speed margin on the theoretical cam, percent.
    pub margin: f64,
    /// The actual cams (judged on them when `actual.actual`).
    pub actual: Cams,
    /// Largest acceptable P(jump) (its upper 95 % Wilson bound), on actual cams.
    pub p_max: f64,
    /// Actual cams per rate (None: the fewest that can pass).
    pub samples: Option<u64>,
    /// Worker threads (None: every core). The answer does not depend on it.
    pub threads: Option<u32>,
    /// The unit family of the report's lines.
    pub units: Units,
    /// Bracket width the rate search stops at, lb/in.
    pub resolution: f64,
    /// Largest rate searched, lb/in.
    pub max_rate: f64,
    /// Search the preload length δ_rs instead of the rate.
    pub preload: bool,
    /// Largest preload length searched, in.
    pub max_preload_length: f64,
    /// CI's quick mode: coarse brackets, and on actual cams a limit at least
    /// [`super::QUICK_P_MAX`].
    pub quick: bool,
}

/// The preload search's first length, in: a tenth of the reference's 0.5 in.
pub const START_PRELOAD_LENGTH: f64 = 0.05;

/// The default largest preload length, in: 20 times the reference's 0.5 in, beyond any
/// compression the reference spring's coils could take.
pub const MAX_PRELOAD_LENGTH: f64 = 10.0;

/// The preload search's bracket width, in (0.1 in the quick mode).
pub const PRELOAD_RESOLUTION: f64 = 0.005;

/// The search's first rate, lb/in.
pub const START_RATE: f64 = 10.0;

/// The default largest rate, lb/in: the reference wire's stiffest spring of two active
/// coils (G d⁴ / (8 D³ · 2) = 274 lb/in) is well below it.
pub const MAX_RATE: f64 = 1000.0;

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
    /// Rates tried (lb/in; with --preload lengths, in) in order, each with whether it
    /// passed. Its JSON key names the unit (`rates_tried_lb_per_in`,
    /// `preload_lengths_tried_in`, or their SI names).
    #[serde(skip)]
    pub tried: Vec<(f64, bool)>,
    /// The spring to build: wire, coil and coils that pass every check of the verdict.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub part: Option<PartReport>,
    /// Model runs of the search (each of 2 revolutions), and of the onset check.
    pub model_runs: u64,
    /// Wall time, s.
    pub wall_s: f64,
}

/// The spring `design spring` answers with ([`crate::study::coil_spring`]).
#[derive(Clone, Debug, Serialize)]
pub struct PartReport {
    /// The spring.
    pub spring: CoilReport,
    /// The wire (`chrome-silicon wire, ASTM A401`).
    pub wire: String,
    /// The wire's scene name.
    pub material: &'static str,
    /// End type.
    pub ends: &'static str,
    /// The rule that binds: the one closest to its limit (`limit_rule`), or contact when
    /// the rate had to be raised for it.
    pub binding: String,
    /// The rule of stress, surge and coil count closest to its limit.
    pub limit_rule: String,
    /// `limit_rule`'s use of its limit, percent.
    pub binding_percent: f64,
    /// Candidates each rule turned away.
    pub rejected: Rejections,
    /// Whether contact was checked with this spring's own rate and mass (a simulation);
    /// with --actual it is judged at the rate found, with the wire model's mass.
    pub contact_checked: bool,
    /// The preload length the part is built and judged at, in: the scene's, or with
    /// --preload the length found (raised with the part when its own mass asked for more).
    pub preload_length_in: Length,
}

/// A candidate spring and its checks ([`CoilChoice`]) as the report gives them, each
/// dimensional value a measure.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CoilReport {
    /// Wire diameter.
    pub wire_diameter_in: Length,
    /// Mean coil diameter.
    pub mean_diameter_in: Length,
    /// Spring index D/d.
    pub index: f64,
    /// Active coils.
    pub active_coils: f64,
    /// Total coils.
    pub total_coils: f64,
    /// Rate.
    pub rate_lb_per_in: Stiffness,
    /// Mass (a weight).
    pub mass_lb: Weight,
    /// Surge, Hz.
    pub surge_hz: f64,
    /// Surge over the cam frequency.
    pub surge_harmonic: f64,
    /// Wahl stress at full compression.
    pub shear_stress_psi: Stress,
    /// The wire's allowable.
    pub allowable_shear_psi: Stress,
    /// Solid height.
    pub solid_height_in: Length,
    /// Free length.
    pub free_length_in: Length,
    /// Length at full compression.
    pub full_compression_length_in: Length,
}

impl From<CoilChoice> for CoilReport {
    fn from(c: CoilChoice) -> Self {
        Self {
            wire_diameter_in: c.wire_diameter_in.into(),
            mean_diameter_in: c.mean_diameter_in.into(),
            index: c.index,
            active_coils: c.active_coils,
            total_coils: c.total_coils,
            rate_lb_per_in: c.rate_lb_per_in.into(),
            mass_lb: c.mass_lb.into(),
            surge_hz: c.surge_hz,
            surge_harmonic: c.surge_harmonic,
            shear_stress_psi: c.shear_stress_psi.into(),
            allowable_shear_psi: c.allowable_shear_psi.into(),
            solid_height_in: c.solid_height_in.into(),
            free_length_in: c.free_length_in.into(),
            full_compression_length_in: c.full_compression_length_in.into(),
        }
    }
}

/// The candidates' contact checks a search runs at most before it gives up.
const MAX_PART_CHECKS: usize = 12;

/// The spring to build for `spec` at its rate and preload length: the lightest standard
/// candidate that passes stress and surge and, with `at_rpm`, holds contact at that speed
/// with its own rate and mass. Returns it and the spec with its rate and mass.
fn choose_part(
    spec: &RunSpec,
    at_rpm: Option<f64>,
    runs: &mut u64,
    units: Units,
) -> Result<(PartReport, RunSpec)> {
    let part = spec.spring.as_ref();
    let wire = part
        .and_then(|p| p.wire)
        .unwrap_or(camsim_core::ASSUMED_SPRING_WIRE);
    let q = CoilQuery {
        rate: spec.design.k_rs,
        full_compression: spec.design.delta_rs + spec.design.program.max_lift(),
        cam_hz: camsim_core::rad_per_s_to_rpm(spec.design.omega0) / 60.0,
        wire,
        ends: part.map_or(camsim_core::CoilEnds::SquaredGround, |p| p.coil.ends),
        fixed: part.map(|p| (p.coil.wire_diameter, p.coil.mean_diameter)),
    };
    let (found, rejected) = candidates(&q);
    let lu = units.symbol(units::LENGTH);
    if found.is_empty() {
        bail!(
            "no {} spring of {} {} passes: of the wire and coil sizes tried, {} need fewer than {} active coils, {} exceed the allowable stress at full compression ({} {lu}), {} surge below {} x the cam's {:.2} Hz: a longer preload length with a softer spring, a gentler program or a lower speed",
            wire.title,
            units.q(units::STIFFNESS, q.rate, 1),
            units.symbol(units::STIFFNESS),
            rejected.too_stiff,
            crate::study::coil_spring::MIN_ACTIVE_COILS,
            rejected.stress,
            units.q(units::LENGTH, q.full_compression, 3),
            rejected.surge,
            camsim_core::SURGE_HARMONIC_MARGIN,
            q.cam_hz
        );
    }
    let (c, s) = lightest_in_contact(spec, &found, at_rpm, runs)?;
    let (rule, use_) = c.binding(&q);
    let mut s = s;
    s.spring = Some(camsim_scene_file::spring::SpringPart {
        coil: c.coil(&q),
        wire: Some(wire),
        free_length: Some(c.free_length_in),
    });
    Ok((
        PartReport {
            spring: c.into(),
            wire: wire.title.to_string(),
            material: wire.name,
            ends: q.ends.name(),
            binding: rule.to_string(),
            limit_rule: rule.to_string(),
            binding_percent: 100.0 * use_,
            rejected,
            contact_checked: at_rpm.is_some(),
            preload_length_in: Length::inch(s.design.delta_rs),
        },
        s,
    ))
}

/// The lightest of the first springs `found` that holds contact at `at_rpm` (counting the
/// runs; any passes without a speed), with the spec carrying its rate and mass.
fn lightest_in_contact(
    spec: &RunSpec,
    found: &[CoilChoice],
    at_rpm: Option<f64>,
    runs: &mut u64,
) -> Result<(CoilChoice, RunSpec)> {
    let with = |c: &CoilChoice| {
        let mut s = spec.clone();
        s.design.k_rs = c.rate_lb_per_in;
        s.design.m_spring = c.mass_lb / camsim_core::GRAVITY_IN_PER_S2;
        s
    };
    let mut chosen = None;
    for c in found.iter().take(MAX_PART_CHECKS) {
        let s = with(c);
        let ok = match at_rpm {
            Some(rpm) => {
                *runs += 1;
                !sim::jumps_at(&s, rpm)?
            }
            None => true,
        };
        if ok {
            chosen = Some((*c, s));
            break;
        }
    }
    let Some(chosen) = chosen else {
        return Err(NoPartHoldsContact(MAX_PART_CHECKS.min(found.len())).into());
    };
    Ok(chosen)
}

/// None of the lightest springs that pass stress and surge holds contact with its own
/// mass (their count): [`choose_part_holding_contact`] then asks for a stiffer rate.
#[derive(Debug)]
struct NoPartHoldsContact(usize);

impl std::fmt::Display for NoPartHoldsContact {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "none of the {} lightest springs that pass stress and surge holds contact with its own mass, up to {} % above the rate found: a larger --margin on the rate, or a lighter program",
            self.0,
            ((1.0 + RATE_RAISE).powi(MAX_RATE_RAISES) * 100.0 - 100.0).round()
        )
    }
}

impl std::error::Error for NoPartHoldsContact {}

/// How much [`choose_part_holding_contact`] raises the rate each time no buildable spring
/// of it holds contact with its own mass (a real spring is heavier than the massless
/// search assumed, so its rate must be a little higher), and how many times at most.
const RATE_RAISE: f64 = 0.05;
const MAX_RATE_RAISES: i32 = 10;

/// [`choose_part`] on `spec_at(rate)` (the searched value, `what`: the rate, or the
/// preload length at the rate held), raised by [`RATE_RAISE`] while no buildable spring of
/// it holds contact at `at_rpm` with its own mass; the part's binding rule says so when
/// it was raised.
fn choose_part_holding_contact(
    spec_at: &dyn Fn(f64) -> Result<RunSpec>,
    rate: f64,
    what: &str,
    at_rpm: f64,
    runs: &mut u64,
    units: Units,
) -> Result<(PartReport, RunSpec)> {
    let (mut asked, mut raises) = (rate, 0);
    loop {
        match choose_part(&spec_at(asked)?, Some(at_rpm), runs, units) {
            Ok((mut part, chosen)) => {
                if raises > 0 {
                    part.binding = format!(
                        "contact with the spring's own mass (the {what} raised {:.0} % above the one found, in {} step(s) of {:.0} %)",
                        (asked / rate - 1.0) * 100.0,
                        raises,
                        RATE_RAISE * 100.0
                    );
                }
                return Ok((part, chosen));
            }
            Err(e) if e.is::<NoPartHoldsContact>() && raises < MAX_RATE_RAISES => {
                asked *= 1.0 + RATE_RAISE;
                raises += 1;
            }
            Err(e) => return Err(e),
        }
    }
}

/// (start, max, resolution) of `design spring`'s search: over the rate, or over the
/// preload length with --preload.
fn spring_search_range(args: &SpringSpec) -> Result<(f64, f64, f64)> {
    Ok(if args.preload {
        let res = if args.quick { 0.1 } else { PRELOAD_RESOLUTION };
        if args.max_preload_length <= START_PRELOAD_LENGTH {
            bail!(
                "--max-preload-length {}: must be above the search's first length {START_PRELOAD_LENGTH} in",
                args.max_preload_length
            );
        }
        (START_PRELOAD_LENGTH, args.max_preload_length, res)
    } else {
        let res = if args.quick {
            args.resolution.max(10.0)
        } else {
            args.resolution
        };
        if args.max_rate <= START_RATE {
            bail!(
                "--max-rate {}: must be above the search's first rate {START_RATE} lb/in",
                args.max_rate
            );
        }
        (START_RATE, args.max_rate, res)
    })
}

/// The spring search.
pub fn spring(args: &SpringSpec) -> Result<SpringReport> {
    let t0 = Instant::now();
    let mut spec = spec_from(&args.scene)?;
    spec.solver.start = Start::Static;
    spec.revolutions = 2;
    let range = spring_search_range(args)?;
    args.actual.ensure_actual_if_options()?;
    let report = if args.actual.actual {
        spring_on_actual_cams(args, &spec, range, t0)?
    } else {
        spring_on_theoretical_cam(args, &spec, range, t0)?
    };
    crate::report::ensure_finite(&report)?;
    Ok(report)
}

/// What `design spring` varies: the rate (at the preload length), or with --preload the
/// preload length (at the rate held).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Searched {
    /// The spring rate, lb/in.
    #[serde(rename = "spring rate")]
    Rate,
    /// The preload length δ_rs, in.
    #[serde(rename = "preload length")]
    PreloadLength,
}

impl Searched {
    fn of(preload: bool) -> Self {
        if preload {
            Searched::PreloadLength
        } else {
            Searched::Rate
        }
    }

    /// Its name and unit: `spring rate` lb/in or `preload length` in.
    fn words(self) -> (&'static str, &'static str) {
        match self {
            Searched::PreloadLength => ("preload length", "in"),
            Searched::Rate => ("spring rate", "lb/in"),
        }
    }
}

impl PartialEq<&str> for Searched {
    fn eq(&self, other: &&str) -> bool {
        self.words().0 == *other
    }
}

/// A spring search's answer: the passing value of what it searched (lb/in or in) and the
/// failing value below it (absent: the first value tried passed).
#[derive(Clone, Copy, Debug)]
struct Answer {
    searched: Searched,
    value: f64,
    failing: Option<f64>,
}

impl Answer {
    /// The bracket width, in the answer's unit (0 when the first value tried passed).
    fn bracket(self) -> f64 {
        self.failing.map_or(0.0, |b| self.value - b)
    }
}

/// What a spring search found, before the answer's spring is worked out.
struct Found {
    answer: Answer,
    criterion: String,
    model: String,
    tried: Vec<(f64, bool)>,
    part: PartReport,
    model_runs: u64,
}

/// `base` with the searched value `x`: its rate (its mass following it by the wire model),
/// or its preload length at the rate held; validated.
fn with_value(base: &RunSpec, x: f64, preload: bool) -> Result<RunSpec> {
    let mut s = base.clone();
    if preload {
        s.design.delta_rs = x;
    } else {
        s.design.set_spring_rate(x)?;
    }
    s.design
        .validate()
        .map_err(|e| camsim_scene_file::refusal("design", e))?;
    Ok(s)
}

/// The report of a search's answer on `spec` (the rate or the preload length in their own
/// fields, the other held at the scene's), with the answer's spring ([`spring_of_answer`]);
/// what only one criterion gives is absent.
fn answered(found: Found, spec: &RunSpec, t0: Instant) -> Result<SpringReport> {
    let Found {
        answer,
        criterion,
        model,
        tried,
        part,
        model_runs,
    } = found;
    let spring = spring_of_answer(spec, answer, &part)?;
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
        tried,
        part: Some(part),
        model_runs,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// `design spring --actual`: the search on P(jump) over the same actual cams at every
/// value, then the part at the answer (judged at the rate found).
fn spring_on_actual_cams(
    args: &SpringSpec,
    spec: &RunSpec,
    (start, max, resolution): (f64, f64, f64),
    t0: Instant,
) -> Result<SpringReport> {
    let (what, unit) = Searched::of(args.preload).words();
    let mc = crate::study::montecarlo::monte_carlo_model(spec);
    let (p_max, n) = p_max_and_samples(args.p_max, args.quick, args.samples)?;
    let actual = args.actual.resolve(&mc.design)?;
    let nthreads = threads(args.threads);
    let steps = search_steps(start, max, resolution);
    check_search_time(
        &with_value(&mc, start, args.preload)?,
        &actual,
        n,
        steps,
        nthreads,
    )?;
    let (mut tried, mut runs, mut last_p) = (Vec::new(), 0, None);
    let onset = OnsetSearch::new(start, Some(2.0), max, resolution)?.find(|k| -> Result<bool> {
        let s = with_value(&mc, k, args.preload)?;
        let p = p_jump_on_actual_cams(&s, &actual, n, nthreads, &mut runs)
            .map_err(|e| e.context(format!("{what} {k} {unit}")))?;
        let ok = p.hi95 <= p_max;
        if ok {
            last_p = Some((k, p));
        }
        tried.push((k, ok));
        Ok(ok)
    })?;
    let ans = answer(onset, max, args.preload, "P(jump) above --p-max")?;
    let (part, _) = choose_part(
        &with_value(spec, ans.value, args.preload)?,
        None,
        &mut runs,
        args.units,
    )?;
    let criterion = format!(
        "upper 95 % Wilson bound of P(jump) in revolution 2 at {:.1} rpm over {n} actual cams (seed {}) at most {p_max}",
        camsim_core::rad_per_s_to_rpm(spec.design.omega0),
        actual.seed()
    );
    Ok(SpringReport {
        p_jump: last_p.filter(|(k, _)| *k == ans.value).map(|(_, p)| p),
        samples: Some(n),
        seed: Some(actual.seed()),
        profile: Some(ProfileSettings::of(
            &actual,
            intervals_for(&mc.design, &actual)?,
        )?),
        ..answered(
            Found {
                answer: ans,
                criterion,
                model: describe(&mc, args.units),
                tried,
                part,
                model_runs: runs,
            },
            spec,
            t0,
        )?
    })
}

/// `design spring` on the theoretical cam: the search on steady-state contact at the
/// margin's speed, the part that holds it with its own rate and mass, and that part's own
/// jump onset (the margin it really has).
fn spring_on_theoretical_cam(
    args: &SpringSpec,
    spec: &RunSpec,
    (start, max, resolution): (f64, f64, f64),
    t0: Instant,
) -> Result<SpringReport> {
    let op_rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    let at_rpm = op_rpm * (1.0 + args.margin / 100.0);
    camsim_core::key::SPEED_RPM
        .check(camsim_core::key::RPM, at_rpm)
        .map_err(|e| anyhow::anyhow!("--margin {}: {e}", args.margin))?;
    let (mut tried, mut runs) = (Vec::new(), 0);
    let onset = OnsetSearch::new(start, Some(2.0), max, resolution)?.find(|k| -> Result<bool> {
        let s = with_value(spec, k, args.preload)?;
        runs += 1;
        let ok = !sim::jumps_at(&s, at_rpm)?;
        tried.push((k, ok));
        Ok(ok)
    })?;
    let ans = answer(onset, max, args.preload, "separates")?;
    let at = |x: f64| with_value(spec, x, args.preload); // contact with its own mass
    let what = ans.searched.words().0;
    let (part, chosen) =
        choose_part_holding_contact(&at, ans.value, what, at_rpm, &mut runs, args.units)?;
    let js = crate::study::jump_speed::find(&chosen, 1.0, crate::study::jump_speed::MAX_RPM)?;
    runs += u64::from(js.simulations);
    let criterion = format!(
        "steady-state contact (revolution 2, static start) at {at_rpm:.1} rpm = {op_rpm:.1} rpm + {} %, theoretical cam",
        args.margin
    );
    Ok(SpringReport {
        checked_at_rpm: Some(at_rpm),
        jump_onset_rpm: js.jump_rpm,
        jump_onset_bracket_rpm: js.jump_rpm.map(|j| j - js.no_jump_rpm),
        ..answered(
            Found {
                answer: ans,
                criterion,
                model: describe(spec, args.units),
                tried,
                part,
                model_runs: runs,
            },
            spec,
            t0,
        )?
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

/// The passing value (rate or preload length) and the failing one below it from the
/// search's outcome.
fn answer(onset: Onset<f64>, max: f64, preload: bool, fails: &str) -> Result<Answer> {
    let searched = Searched::of(preload);
    match onset {
        Onset::AtStart(k) => Ok(Answer {
            searched,
            value: k,
            failing: None,
        }),
        Onset::Bracketed { below, at } => Ok(Answer {
            searched,
            value: at,
            failing: Some(below),
        }),
        Onset::Beyond(_) if preload => bail!(
            "no preload length up to --max-preload-length {max} in passes (the follower {fails} at every length tried): a stiffer spring, a gentler program or a lower speed"
        ),
        Onset::Beyond(_) => bail!(
            "no spring up to --max-rate {max} lb/in passes (the follower {fails} at every rate tried): a larger preload length, a gentler program or a lower speed"
        ),
    }
}

impl Report for SpringReport {
    fn json(&self) -> serde_json::Result<String> {
        // The tried values under a key that names their unit (`--units` converts it).
        let mut v = serde_json::to_value(self)?;
        let key = if self.searched == Searched::PreloadLength {
            "preload_lengths_tried_in"
        } else {
            "rates_tried_lb_per_in"
        };
        if let Some(o) = v.as_object_mut() {
            o.insert(key.into(), serde_json::to_value(&self.tried)?);
        }
        crate::report::sorted_pretty_json(&v)
    }
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        spring_headline(self, &mut out, units);
        let _ = writeln!(out, "  criterion: {}", self.criterion);
        if let (Some(j), Some(b)) = (self.jump_onset_rpm, self.jump_onset_bracket_rpm) {
            let _ = writeln!(
                out,
                "  check: its jump onset is {j:.1} rpm (bracket {b:.1} rpm), {:+.1} % over {:.1} rpm",
                100.0 * (j / self.operating_rpm - 1.0),
                self.operating_rpm
            );
        }
        if let (Some(p), Some(n)) = (&self.p_jump, self.samples) {
            let _ = writeln!(
                out,
                "  P(jump) at the chosen rate: {} of {n}: {} (95 % Wilson)",
                p.count,
                p.text(4)
            );
        }
        if let Some(p) = &self.part {
            part_lines(&mut out, p, units);
            if self.searched == Searched::PreloadLength {
                let _ = writeln!(
                    out,
                    "    and in [design]: spring_preload_length_{} = {}",
                    units.key_suffix(units::LENGTH),
                    units.show(p.preload_length_in, 4)
                );
            }
        }
        let _ = writeln!(out, "  model: {}", self.model);
        let tried: Vec<String> = self
            .tried
            .iter()
            .map(|(k, ok)| {
                if self.searched == Searched::PreloadLength {
                    format!(
                        "{}{}",
                        units.q(units::LENGTH, *k, 3),
                        if *ok { "+" } else { "-" }
                    )
                } else {
                    format!(
                        "{}{}",
                        units.q(units::STIFFNESS, *k, 1),
                        if *ok { "+" } else { "-" }
                    )
                }
            })
            .collect();
        if self.searched == Searched::PreloadLength {
            let _ = writeln!(
                out,
                "  preload lengths tried ({}, + passes): {}",
                units.symbol(units::LENGTH),
                tried.join(" ")
            );
        } else {
            let _ = writeln!(
                out,
                "  rates tried ({}, + passes): {}",
                units.symbol(units::STIFFNESS),
                tried.join(" ")
            );
        }
        let _ = writeln!(
            out,
            "  {} model runs of 2 revolutions, {:.1} s",
            self.model_runs, self.wall_s
        );
        out
    }
}

/// The first lines of the spring search's text: the answer and its bracket. The rate it
/// gives is the built spring's own (its wire, coil and coils: the `[design.spring]` lines
/// below), beside the least rate the search found.
fn spring_headline(r: &SpringReport, out: &mut String, units: Units) {
    use std::fmt::Write;
    let ku = units.symbol(units::STIFFNESS);
    let rate = r
        .part
        .as_ref()
        .map_or(r.spring_rate_lb_per_in, |p| p.spring.rate_lb_per_in);
    if r.searched == Searched::PreloadLength {
        let _ = writeln!(
            out,
            "camsim design spring --preload: preload length {} {lu} at the rate held, {} {ku} {}",
            units.show(r.preload_length_in, 3),
            units.show(rate, 1),
            spring_summary(r, units),
            lu = units.symbol(units::LENGTH),
        );
        preload_bracket_line(r, out, units);
        return;
    }
    let found = match &r.part {
        Some(_) => format!(
            "; the least rate the search found: {} {ku}",
            units.show(r.spring_rate_lb_per_in, 1)
        ),
        None => String::new(),
    };
    let _ = writeln!(
        out,
        "camsim design spring: {} {ku} at preload length {} {} {}{found}",
        units.show(rate, 1),
        units.given(units::LENGTH, r.preload_length_in.in_inch()),
        units.symbol(units::LENGTH),
        spring_summary(r, units),
    );
    let _ = match r.failing_rate_lb_per_in {
        Some(b) => writeln!(
            out,
            "  bracket: fails at {} {ku}, passes at {} {ku} (width {} {ku})",
            units.show(b, 1),
            units.show(r.spring_rate_lb_per_in, 1),
            units.show(r.bracket_lb_per_in, 2),
        ),
        None => writeln!(
            out,
            "  the first rate tried passes: any rate up to it may do"
        ),
    };
}

/// The answer's spring in brackets: its preload, coils, mass and surge.
fn spring_summary(r: &SpringReport, units: Units) -> String {
    format!(
        "(preload {} {}; {:.2} active coils, {} {}, surge {:.0} Hz)",
        units.show(r.preload_lb, 2),
        units.symbol(units::FORCE),
        r.active_coils,
        units.show(r.spring_mass_lb, 4),
        units.symbol(units::WEIGHT),
        r.surge_hz,
    )
}

/// The preload search's bracket line.
fn preload_bracket_line(r: &SpringReport, out: &mut String, units: Units) {
    use std::fmt::Write;
    let lu = units.symbol(units::LENGTH);
    let _ = match (r.failing_preload_length_in, r.preload_bracket_in) {
        (Some(b), Some(w)) => writeln!(
            out,
            "  searched: the preload length; bracket: fails at {} {lu}, passes at {} {lu} (width {} {lu})",
            units.show(b, 3),
            units.show(Length::inch(b.in_inch() + w.in_inch()), 3),
            units.show(w, 3),
        ),
        _ => writeln!(
            out,
            "  searched: the preload length; the first length tried passes: any length up to it may do"
        ),
    };
}

/// The binding rule as the part's text gives it: `binding` at `percent` of its limit; or,
/// when contact bound (`binding` is not `limit_rule`: the rate was raised until a buildable
/// spring held contact with its own mass, and `binding` says by how much), the part's
/// own stress and surge use of their limits, percent.
fn binding_text(p: &PartReport) -> String {
    if p.binding == p.limit_rule {
        return format!("{} ({:.0} % of its limit)", p.binding, p.binding_percent);
    }
    let c = &p.spring;
    format!(
        "{}; the part's stress at {:.0} % and surge at {:.0} % of their limits",
        p.binding,
        100.0 * c.shear_stress_psi.in_inch() / c.allowable_shear_psi.in_inch(),
        100.0 * camsim_core::SURGE_HARMONIC_MARGIN / c.surge_harmonic
    )
}

/// The spring to build: the part, its checks, the rule that binds, and the
/// `[design.spring]` lines that describe it in the output's family.
fn part_lines(out: &mut String, p: &PartReport, units: Units) {
    use std::fmt::Write;
    let c = &p.spring;
    let (lu, su) = (units.symbol(units::LENGTH), units.symbol(units::STRESS));
    let _ = writeln!(
        out,
        "  spring to build: {}, wire {} {lu}, mean coil {} {lu} (index {:.1}), {:.2} active / {:.2} total coils, {} ends; rate {} {}, {} {}",
        p.wire,
        units.show(c.wire_diameter_in, 3),
        units.show(c.mean_diameter_in, 3),
        c.index,
        c.active_coils,
        c.total_coils,
        p.ends,
        units.show(c.rate_lb_per_in, 1),
        units.symbol(units::STIFFNESS),
        units.show(c.mass_lb, 4),
        units.symbol(units::WEIGHT)
    );
    let _ = writeln!(
        out,
        "    checks: stress {} {su} at full compression, {:.0} % of the allowable {} {su}; surge {:.0} Hz = {:.1} x the cam (least {:.0}); free length {} {lu}, {} {lu} at full compression above the solid {} {lu}; contact {}",
        units.show(c.shear_stress_psi, 0),
        100.0 * c.shear_stress_psi.in_inch() / c.allowable_shear_psi.in_inch(),
        units.show(c.allowable_shear_psi, 0),
        c.surge_hz,
        c.surge_harmonic,
        camsim_core::SURGE_HARMONIC_MARGIN,
        units.show(c.free_length_in, 3),
        units.show(c.full_compression_length_in, 3),
        units.show(c.solid_height_in, 3),
        if p.contact_checked {
            "checked with its own rate and mass"
        } else {
            "judged at the rate found, with the wire model's mass"
        }
    );
    let _ = writeln!(
        out,
        "    binding: {}; turned away: {} too stiff for {} coils, {} over the stress, {} low surge",
        binding_text(p),
        p.rejected.too_stiff,
        crate::study::coil_spring::MIN_ACTIVE_COILS,
        p.rejected.stress,
        p.rejected.surge
    );
    let k = units.key_suffix(units::LENGTH);
    let _ = writeln!(
        out,
        "    as a scene (these lines in place of the spring rate):\n      [design.spring]\n      wire_diameter_{k} = {}\n      mean_diameter_{k} = {}\n      active_coils = {}\n      ends = \"{}\"\n      material = \"{}\"\n      free_length_{k} = {}",
        scene_length(c.wire_diameter_in.in_inch(), units),
        scene_length(c.mean_diameter_in.in_inch(), units),
        c.active_coils,
        p.ends,
        p.material,
        units.show(c.free_length_in, 4)
    );
}

/// A wire or coil diameter for the scene lines, to 6 significant digits in the output's
/// family: the standard wires are millimetre sizes, so an inch scene needs more than 4
/// decimals for the part it reads back to be the part printed (5.6 mm is 0.220472 in;
/// 0.2205 in would read back as a 0.221 in wire).
fn scene_length(inch: f64, units: Units) -> f64 {
    let v = units.value(units::LENGTH, inch);
    format!("{v:.5e}").parse().unwrap_or(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The binding text (issue 30): a part bound by contact after a raised rate gives its
    /// own stress and surge use (here 500/1000 psi and a surge harmonic of twice the
    /// least), not the stale use of the rule before the raise; an unraised part gives its
    /// rule's.
    #[test]
    fn a_raised_rates_binding_text_gives_the_parts_own_figures() {
        let c: CoilReport = crate::study::coil_spring::CoilChoice {
            wire_diameter_in: 0.1,
            mean_diameter_in: 1.0,
            index: 10.0,
            active_coils: 8.0,
            total_coils: 10.0,
            rate_lb_per_in: 20.0,
            mass_lb: 0.1,
            surge_hz: 100.0,
            surge_harmonic: 2.0 * camsim_core::SURGE_HARMONIC_MARGIN,
            shear_stress_psi: 500.0,
            allowable_shear_psi: 1000.0,
            solid_height_in: 1.0,
            free_length_in: 3.0,
            full_compression_length_in: 2.0,
        }
        .into();
        let mut p = PartReport {
            spring: c,
            wire: "music wire".into(),
            material: "music-wire",
            ends: "squared-ground",
            binding: "contact with the spring's own mass (the rate raised 10 % above the one found, in 2 step(s) of 5 %)".into(),
            limit_rule: "contact (the rate asked)".into(),
            binding_percent: 99.0,
            rejected: Rejections::default(),
            contact_checked: true,
            preload_length_in: Length::inch(0.5),
        };
        let t = binding_text(&p);
        assert!(
            t.ends_with("; the part's stress at 50 % and surge at 50 % of their limits"),
            "{t}"
        );
        assert!(!t.contains("99"), "{t}");
        p.binding = "stress".into();
        p.limit_rule = "stress".into();
        p.binding_percent = 87.0;
        assert_eq!(binding_text(&p), "stress (87 % of its limit)");
    }
}
