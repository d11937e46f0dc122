//! The spring to build: the lightest standard wire and coil ([`crate::study::coil_spring`])
//! that passes stress and surge and holds contact with its own rate and mass, its rate
//! raised when none does; and the part as the report gives it.

use anyhow::{bail, Result};
use serde::Serialize;

use crate::sim::{self, RunSpec};
use crate::study::coil_spring::{candidates, CoilChoice, CoilQuery, Rejections};
use crate::units::{self, Length, Stiffness, Stress, Units, Weight};

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
pub(super) fn choose_part(
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
pub(super) fn choose_part_holding_contact(
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
