//! The verdict that opens `camsim run`: does contact hold, is the geometry sound, are the
//! loads within the material's allowable, is the spring clear of surge, did the
//! statistics settle. Every number carries its unit in its JSON key and its text.

use std::ops::ControlFlow;

use anyhow::Result;
use camsim_core::{Design, HelicalSpring, Observer, PeakScan, Sample, ScanEnds};
use camsim_scene_file::spring::SpringPart;
use serde::Serialize;

use crate::sim::{PeriodRow, SteadyCheck};
use crate::units::{Force, Length, Power, Stiffness, Stress, Torque, Units, Weight};

/// One horsepower, lb·in/s.
pub const HP_LB_IN_PER_S: f64 = 6600.0;
/// One lb·in/s in watts.
pub const W_PER_LB_IN_PER_S: f64 = 0.112_984_829;

/// The limits a verdict judges against (`--allowable-stress`, `--pressure-angle-limit`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Limits {
    /// Allowable Hertz contact stress, psi.
    pub allowable_contact_stress_psi: f64,
    /// Largest pressure angle without a warning, degrees.
    pub pressure_angle_limit_deg: f64,
    /// Where the allowable comes from (the default's source, the scene, the option).
    #[serde(skip)]
    pub allowable_source: &'static str,
}

impl Limits {
    /// The reference limits, their source named in the output's family `units`.
    pub fn reference(units: Units) -> Self {
        Limits {
            allowable_contact_stress_psi: camsim_core::ALLOWABLE_CONTACT_STRESS_PSI,
            pressure_angle_limit_deg: camsim_core::PRESSURE_ANGLE_LIMIT_DEG,
            allowable_source: allowable_source(units),
        }
    }
}

/// Where an extreme occurred.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct At {
    /// Revolution, from 1.
    pub revolution: u32,
    /// Cam angle within it, degrees.
    pub cam_angle_deg: f64,
}

/// The extremes of the steady revolutions, watched sample by sample.
#[derive(Clone, Debug)]
pub struct Watch {
    /// First revolution watched (2 when the run has two or more, else 1).
    pub from_revolution: u32,
    /// Smallest contact force in contact, lb, and where.
    pub min_force: Option<(f64, At)>,
    /// Largest |cam output torque|, lb·in (signed value), and where.
    pub peak_torque: Option<(f64, At)>,
    /// Largest motor power T_i ω_m, lb·in/s, and where.
    pub peak_power: Option<(f64, At)>,
    /// Largest Hertz stress, psi, and where.
    pub peak_stress: Option<(f64, At)>,
    /// Smallest and largest cam speed θ̇_c, rad/s.
    pub cam_speed: Option<(f64, f64)>,
}

impl Watch {
    /// A watch of the revolutions from `from_revolution` on.
    pub fn new(from_revolution: u32) -> Self {
        Watch {
            from_revolution,
            min_force: None,
            peak_torque: None,
            peak_power: None,
            peak_stress: None,
            cam_speed: None,
        }
    }

    /// The revolution a run of `revolutions` judges from: 2 (the thesis's steady state),
    /// or 1 for a one-revolution run.
    pub fn steady_from(revolutions: u32) -> u32 {
        if revolutions >= 2 {
            2
        } else {
            1
        }
    }
}

fn keep(slot: &mut Option<(f64, At)>, v: f64, at: At, better: impl Fn(f64, f64) -> bool) {
    if !v.is_finite() {
        return;
    }
    match slot {
        Some((old, _)) if !better(v, *old) => {}
        _ => *slot = Some((v, at)),
    }
}

impl Observer<f64> for Watch {
    fn needs_stress(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        if s.revolution < self.from_revolution {
            return ControlFlow::Continue(());
        }
        let at = At {
            revolution: s.revolution,
            cam_angle_deg: s.angle_deg,
        };
        let p = &s.point;
        if p.in_contact {
            keep(&mut self.min_force, p.contact_force, at, |a, b| a < b);
        }
        keep(&mut self.peak_torque, p.torque_out, at, |a, b| {
            a.abs() > b.abs()
        });
        keep(
            &mut self.peak_power,
            p.torque_drive * p.omega_m,
            at,
            |a, b| a > b,
        );
        keep(&mut self.peak_stress, s.contact_stress, at, |a, b| a > b);
        if p.omega_c.is_finite() {
            let (lo, hi) = self.cam_speed.unwrap_or((p.omega_c, p.omega_c));
            self.cam_speed = Some((lo.min(p.omega_c), hi.max(p.omega_c)));
        }
        ControlFlow::Continue(())
    }
}

/// One separation in the steady revolutions.
#[derive(Clone, Debug, Serialize)]
pub struct Separation {
    /// Revolution of the lift-off.
    pub revolution: u32,
    /// The period it starts in.
    pub period: String,
    /// Cam angle of the lift-off, degrees.
    pub from_deg: f64,
    /// Cam angle of the landing, degrees.
    pub to_deg: f64,
    /// Time off the cam, ms.
    pub duration_ms: f64,
}

/// Does contact hold.
#[derive(Clone, Debug, Serialize)]
pub struct ContactVerdict {
    /// True when the follower never leaves the cam in the judged revolutions.
    pub holds: bool,
    /// The revolutions judged (first, last).
    pub revolutions: [u32; 2],
    /// The separations in them (bursts of bounces merged per period).
    pub separations: Vec<Separation>,
    /// Cam angle off the cam in all of them, degrees.
    pub off_cam_deg: f64,
    /// Separations in revolution 1 before the judged ones (the start transient).
    pub start_transient_separations: usize,
    /// Smallest contact force while in contact, lb.
    pub min_contact_force_lb: Force,
    /// Where.
    pub min_contact_force_at: At,
    /// The period of the smallest contact force.
    pub min_contact_force_period: String,
}

/// The cam's shape.
#[derive(Clone, Debug, Serialize)]
pub struct GeometryVerdict {
    /// Largest |pressure angle| of the theoretical profile, degrees.
    pub max_pressure_angle_deg: f64,
    /// Cam angle where, degrees.
    pub max_pressure_angle_at_deg: f64,
    /// The limit judged against, degrees.
    pub pressure_angle_limit_deg: f64,
    /// Smallest radius of curvature of the pitch curve where it is convex, in.
    pub min_pitch_radius_in: Length,
    /// Cam angle where, degrees.
    pub min_pitch_radius_at_deg: f64,
    /// Undercut margin: that radius minus the roller radius (the cam surface's smallest
    /// convex radius), in; at or below 0 the roller cannot cut the profile.
    pub undercut_margin_in: Length,
}

/// Forces and power.
#[derive(Clone, Debug, Serialize)]
pub struct LoadsVerdict {
    /// Largest |output torque on the cam| T_o, lb·in (signed).
    pub peak_cam_torque_lb_in: Torque,
    /// Where.
    pub peak_cam_torque_at: At,
    /// Largest motor power T_i ω_m, hp.
    pub peak_motor_power_hp: Power,
    /// The same, W.
    pub peak_motor_power_w: f64,
    /// Where.
    pub peak_motor_power_at: At,
    /// Largest Hertz contact stress, psi.
    pub peak_contact_stress_psi: Stress,
    /// Where.
    pub peak_contact_stress_at: At,
    /// The allowable, psi.
    pub allowable_contact_stress_psi: Stress,
    /// Where the default allowable comes from.
    pub allowable_source: &'static str,
    /// Peak stress over the allowable.
    pub stress_ratio: f64,
}

/// The return spring: the part `[design.spring]` gives, or the wire-and-coil model's
/// spring of the rate (assumed: docs/MODEL.md §5.6).
#[derive(Clone, Debug, Serialize)]
pub struct SpringVerdict {
    /// Rate, lb/in.
    pub rate_lb_per_in: Stiffness,
    /// Mass the model uses, lb (weight).
    pub mass_lb: Weight,
    /// Whether the part is the scene's (`[design.spring]`) or assumed from the rate.
    pub given: bool,
    /// The wire: a named wire's title, or `explicit material values`.
    pub material: String,
    /// End type.
    pub ends: &'static str,
    /// Wire diameter d, in.
    pub wire_diameter_in: Length,
    /// Mean coil diameter D, in.
    pub mean_diameter_in: Length,
    /// Active coils.
    pub active_coils: f64,
    /// Total coils.
    pub total_coils: f64,
    /// Surge frequency, Hz.
    pub surge_hz: f64,
    /// Cam rotation frequency, Hz.
    pub cam_hz: f64,
    /// Surge over the cam frequency: the harmonic of the cam motion at the surge.
    pub surge_harmonic: f64,
    /// The least harmonic ratio accepted without a warning.
    pub least_harmonic: f64,
    /// Spring force at full compression (assembly compression plus the largest lift), lb.
    pub full_compression_force_lb: Force,
    /// Wahl-corrected shear stress at that force, psi.
    pub shear_stress_psi: Stress,
    /// The allowable shear stress, psi.
    pub allowable_shear_psi: Stress,
    /// Solid height, in.
    pub solid_height_in: Length,
    /// Compression at full lift (assembly compression plus the largest lift), in.
    pub full_compression_in: Length,
    /// Free length, in (absent: not given).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_length_in: Option<Length>,
    /// The least free length that is not solid at full compression: solid height plus
    /// the full compression, in.
    pub least_free_length_in: Length,
}

impl SpringVerdict {
    /// Whether the spring is solid (or beyond) at full compression: only with a free length.
    pub fn solid(&self) -> Option<bool> {
        self.free_length_in.map(|l| {
            l.in_inch() - self.full_compression_in.in_inch() <= self.solid_height_in.in_inch()
        })
    }
}

/// The follower train's translating mass by its parts (weights, lb), as the model has it
/// (docs/MODEL.md §5.1): the load takes what the rest leaves when a scene gives
/// `moving_mass_kg|lb`.
#[derive(Clone, Debug, Serialize)]
pub struct MassVerdict {
    /// The whole translating mass.
    pub moving_mass_lb: Weight,
    /// M_l, the load.
    pub load_mass_lb: Weight,
    /// ρ A (e1 + e2), the follower rod.
    pub rod_mass_lb: Weight,
    /// M_r, the roller.
    pub roller_mass_lb: Weight,
    /// A third of the return spring.
    pub spring_share_mass_lb: Weight,
}

/// Standard gravity, in/s² (a pound-mass is 1/g lb·s²/in).
const G: f64 = camsim_scene_file::units::G_IN_PER_S2;

/// The mass verdict of `design`.
pub fn mass(design: &Design<f64>) -> MassVerdict {
    let m = design.moving_mass();
    MassVerdict {
        moving_mass_lb: Weight::inch(m.total() * G),
        load_mass_lb: Weight::inch(m.load * G),
        rod_mass_lb: Weight::inch(m.rod * G),
        roller_mass_lb: Weight::inch(m.roller * G),
        spring_share_mass_lb: Weight::inch(m.spring_share * G),
    }
}

/// The drive and the cam speed it held over the judged revolutions.
#[derive(Clone, Debug, Serialize)]
pub struct DriveVerdict {
    /// The drive: `constant-cam-speed`, `constant-motor-speed`, `regulated` (the thesis's
    /// or a `[design.drive.regulated]` table) or `motor` (a `[design.drive.motor]` table).
    pub drive: &'static str,
    /// What it is, in words.
    pub description: String,
    /// The nominal cam speed ω0, rpm.
    pub nominal_rpm: f64,
    /// Smallest cam speed over the judged revolutions, rpm.
    pub min_cam_speed_rpm: f64,
    /// Largest cam speed over the judged revolutions, rpm.
    pub max_cam_speed_rpm: f64,
    /// The larger of the two deviations from nominal, percent.
    pub swing_percent: f64,
    /// The swing a constant-speed design assumes, percent
    /// ([`camsim_core::CAM_SPEED_SWING_LIMIT`]).
    pub swing_limit_percent: f64,
    /// The drive is given (the reference's, or one the scene names): a swing past the
    /// limit is then part of the result, not a warning. False when a scene names no
    /// drive and inherits the thesis's (docs/MODEL.md §5.17).
    pub given: bool,
}

/// The drive verdict of `spec` from the cam speeds `watch` saw.
pub fn drive(spec: &crate::sim::RunSpec, watch: &Watch, units: Units) -> DriveVerdict {
    use camsim_core::{rad_per_s_to_rpm, DriveLaw};
    let design = &spec.design;
    let w0 = design.omega0;
    let (lo, hi) = watch.cam_speed.unwrap_or((w0, w0));
    let (drive, description) = match design.drive {
        DriveLaw::ConstantCamSpeed => (
            "constant-cam-speed",
            "the cam turns at exactly the nominal speed (kinematic)".to_string(),
        ),
        DriveLaw::ConstantMotorSpeed => (
            "constant-motor-speed",
            "the motor held at the nominal speed; coupling and cam shafts twist".to_string(),
        ),
        DriveLaw::Regulated { k_p, t_max, .. } => (
            if spec.motor_table {
                "motor"
            } else {
                "regulated"
            },
            format!(
                "speed-regulated motor, gain {} {}, torque limit {} {} ({})",
                units.q(camsim_scene_file::units::GAIN, k_p, 1),
                units.symbol(camsim_scene_file::units::GAIN),
                units.q(crate::units::TORQUE, t_max, 1),
                units.symbol(crate::units::TORQUE),
                if spec.motor_table {
                    "the scene's [design.drive.motor]; what it does not give, the thesis's"
                } else if spec.drive_given {
                    "the thesis's motor unless [design.drive.regulated] or [design.drive.motor] says otherwise"
                } else {
                    "inherited: the scene names no drive, so it is the thesis's motor"
                }
            ),
        ),
    };
    DriveVerdict {
        drive,
        description,
        nominal_rpm: rad_per_s_to_rpm(w0),
        min_cam_speed_rpm: rad_per_s_to_rpm(lo),
        max_cam_speed_rpm: rad_per_s_to_rpm(hi),
        swing_percent: 100.0 * ((w0 - lo).max(hi - w0) / w0),
        swing_limit_percent: 100.0 * camsim_core::CAM_SPEED_SWING_LIMIT,
        given: spec.drive_given,
    }
}

/// The jump margin (`--margin`).
#[derive(Clone, Debug, Serialize)]
pub struct MarginVerdict {
    /// Lowest speed with steady-state separation, rpm (absent: none up to the search's top).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// Highest speed checked that holds contact, rpm.
    pub holds_at_rpm: f64,
    /// The onset over the operating speed, minus 1, in percent (absent without an onset).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_percent: Option<f64>,
    /// Bracket width of the onset, rpm.
    pub bracket_rpm: f64,
    /// Simulations the search ran (2 revolutions each, static start).
    pub simulations: u32,
}

/// Whether the statistics settled, in words.
#[derive(Clone, Debug, Serialize)]
pub struct SteadyVerdict {
    /// False only when the last revolutions' statistics really differ.
    pub settled: bool,
    /// What changed most, by how much, and what that means.
    pub summary: String,
}

/// The verdict block.
#[derive(Clone, Debug, Serialize)]
pub struct Verdict {
    /// Contact.
    pub contact: ContactVerdict,
    /// Geometry.
    pub geometry: GeometryVerdict,
    /// Loads.
    pub loads: LoadsVerdict,
    /// The return spring.
    pub spring: SpringVerdict,
    /// The translating mass by its parts.
    pub mass: MassVerdict,
    /// The drive and the cam speed's swing.
    pub drive: DriveVerdict,
    /// The jump margin, when asked (`--margin`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_margin: Option<MarginVerdict>,
    /// Steady state (absent for a one-revolution run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steady: Option<SteadyVerdict>,
    /// Every warning, one line each.
    pub warnings: Vec<String>,
}

/// The source of the default allowable contact stress.
pub const ALLOWABLE_SOURCE: &str = "through-hardened steel, 400 HB, 1e8 cycles: Buckingham's S_C = 0.4 H_B - 10 kpsi (Shigley); limits.allowable_contact_stress_psi (or _mpa) in the scene, or --allowable-stress PSI, to change";

/// [`ALLOWABLE_SOURCE`] in SI: Shigley's SI form of the same rule (0.4 kpsi = 2.76 MPa a
/// Brinell point, 10 kpsi = 68.9 MPa, which Shigley rounds to 70: 1034 MPa at 400 HB,
/// the 150 kpsi the default is), and the option in MPa as `--units si` reads it.
pub const ALLOWABLE_SOURCE_SI: &str = "through-hardened steel, 400 HB, 1e8 cycles: Buckingham's S_C = 2.76 H_B - 70 MPa (Shigley); limits.allowable_contact_stress_mpa (or _psi) in the scene, or --allowable-stress with its unit (1034MPa), to change";

/// The source of the default allowable contact stress in the output's family
/// (`--units`).
pub fn allowable_source(units: Units) -> &'static str {
    match units {
        crate::units::Units::Inch => ALLOWABLE_SOURCE,
        crate::units::Units::Si => ALLOWABLE_SOURCE_SI,
    }
}

/// Largest |pressure angle| of the theoretical profile (deg, at deg), smallest convex
/// pitch radius (in, at deg) and the undercut margin (in).
pub fn geometry(design: &Design<f64>, limits: &Limits) -> Result<GeometryVerdict> {
    let g = &design.geometry;
    let prog = &design.program;
    let n = 3600;
    let scan = PeakScan {
        start: 0.0,
        step: std::f64::consts::TAU / n as f64,
        points: n,
        ends: ScanEnds::Periodic,
        iterations: 60,
    };
    let phi = |th: f64| {
        let th = th.rem_euclid(std::f64::consts::TAU);
        let f = prog.follower(th);
        g.pressure_angle(f.y, f.dy).abs()
    };
    let peak = scan
        .maximize(phi)
        .ok_or_else(|| anyhow::anyhow!("no pressure angle could be evaluated"))?;
    let u = g.undercut(prog, n)?;
    let pitch = u.min_convex_surface_radius + g.roller_radius;
    Ok(GeometryVerdict {
        max_pressure_angle_deg: peak.value.to_degrees(),
        max_pressure_angle_at_deg: peak.at.rem_euclid(std::f64::consts::TAU).to_degrees(),
        pressure_angle_limit_deg: limits.pressure_angle_limit_deg,
        min_pitch_radius_in: Length::inch(pitch),
        min_pitch_radius_at_deg: u.min_convex_at.to_degrees(),
        undercut_margin_in: Length::inch(u.min_convex_surface_radius),
    })
}

/// The spring verdict of `design` at its speed: `part` (the scene's `[design.spring]`),
/// or the wire-and-coil model's spring of the design's rate.
pub fn spring(design: &Design<f64>, part: Option<&SpringPart>) -> Result<SpringVerdict> {
    let (coil, given, material, free_length) = match part {
        Some(p) => (
            p.coil,
            true,
            p.wire.map_or("explicit material values", |w| w.title),
            p.free_length,
        ),
        None => (
            HelicalSpring::of_rate(design.k_rs)?.part(),
            false,
            "VI.1's steel, music wire's allowable",
            None,
        ),
    };
    let cam_hz = camsim_core::rad_per_s_to_rpm(design.omega0) / 60.0;
    let compression = design.delta_rs + design.program.max_lift();
    let force = design.k_rs * compression;
    // The wire model's surge is the rate asked's (its quarter-turn coils differ a little).
    let surge_hz = match part {
        Some(_) => coil.surge_hz(),
        None => HelicalSpring::of_rate(design.k_rs)?.surge_hz,
    };
    Ok(SpringVerdict {
        rate_lb_per_in: Stiffness::inch(design.k_rs),
        mass_lb: Weight::inch(design.m_spring * camsim_core::GRAVITY_IN_PER_S2),
        given,
        material: material.to_string(),
        ends: coil.ends.name(),
        wire_diameter_in: Length::inch(coil.wire_diameter),
        mean_diameter_in: Length::inch(coil.mean_diameter),
        active_coils: coil.active_coils,
        total_coils: coil.total_coils(),
        surge_hz,
        cam_hz,
        surge_harmonic: surge_hz / cam_hz,
        least_harmonic: camsim_core::SURGE_HARMONIC_MARGIN,
        full_compression_force_lb: Force::inch(force),
        shear_stress_psi: Stress::inch(coil.shear_stress(force)),
        allowable_shear_psi: Stress::inch(coil.material.allowable_shear),
        solid_height_in: Length::inch(coil.solid_height()),
        full_compression_in: Length::inch(compression),
        free_length_in: free_length.map(Length::inch),
        least_free_length_in: Length::inch(coil.solid_height() + compression),
    })
}

/// What a run's steady-state comparison means to a designer. `rows` are the per-period
/// rows of every revolution; `checks` the comparison of each pair of consecutive
/// revolutions from the first, the last pair last.
///
/// The statistics have settled when the last revolution differs from the one before by at
/// most 1 % (of the statistic's largest magnitude over the periods), or when the change is
/// dying out fast enough that what remains after the last revolution is at most 1 %: with
/// the change before it `d1` and the last `d2`, a change that shrinks by `q = d2/d1` a
/// revolution leaves `d2 q / (1 - q)` to come. Separations in the last revolution make every
/// revolution different: not settled, and said so.
pub fn steady(rows: &[PeriodRow], checks: &[SteadyCheck], units: Units) -> Option<SteadyVerdict> {
    let last = checks.last()?;
    let rev = last.compared[1];
    let jumps_last = rows.iter().any(|r| r.revolution == rev && r.jump);
    let d2 = last.max_rel_change;
    let what = describe(rows, last, units);
    if jumps_last {
        return Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: the follower leaves the cam in revolution {rev}, so no two revolutions are alike; {what}"
            ),
        });
    }
    if d2 <= 0.01 {
        return Some(SteadyVerdict {
            settled: true,
            summary: format!("settled: {what}"),
        });
    }
    // The change before the last one, of the same statistic in the same period.
    let before = checks
        .len()
        .checked_sub(2)
        .and_then(|i| checks.get(i))
        .and_then(|c| change_of(rows, c.compared, &last.statistic));
    match before {
        Some(d1) if d1 > d2 => {
            let q = d2 / d1;
            let remaining = d2 * q / (1.0 - q);
            if remaining <= 0.01 {
                Some(SteadyVerdict {
                    settled: true,
                    summary: format!(
                        "settled: {what}; the change shrinks {:.1}-fold a revolution, so about {:.2} % more is to come",
                        1.0 / q,
                        100.0 * remaining
                    ),
                })
            } else {
                Some(SteadyVerdict {
                    settled: false,
                    summary: format!(
                        "NOT settled: {what}; it shrinks only {:.1}-fold a revolution, about {:.1} % more to come: run more revolutions (--revolutions)",
                        1.0 / q,
                        100.0 * remaining
                    ),
                })
            }
        }
        Some(_) => Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: {what}; the change does not shrink from one revolution to the next: run more revolutions (--revolutions), or the response is not periodic"
            ),
        }),
        None => Some(SteadyVerdict {
            settled: false,
            summary: format!(
                "NOT settled: {what}; with only these revolutions it cannot be told whether it is dying out: run more revolutions (--revolutions)"
            ),
        }),
    }
}

/// The designer's name of a statistic and its unit.
fn label(stat: &str) -> (&'static str, Option<camsim_scene_file::units::Unit>) {
    use crate::units as u;
    match stat {
        "rms_displacement" => ("displacement deviation RMS", Some(u::LENGTH)),
        "rms_velocity" => ("velocity deviation RMS", Some(u::SPEED)),
        "rms_acceleration" => ("acceleration deviation RMS", Some(u::ACCELERATION)),
        "torque_avg" => ("average cam torque", Some(u::TORQUE)),
        "contact_force_avg" => ("average contact force", Some(u::FORCE)),
        _ => ("statistic", None),
    }
}

fn value_of(r: &PeriodRow, stat: &str) -> Option<f64> {
    Some(match stat {
        "rms_displacement" => r.rms_displacement,
        "rms_velocity" => r.rms_velocity,
        "rms_acceleration" => r.rms_acceleration,
        "torque_avg" => r.torque_avg,
        "contact_force_avg" => r.contact_force_avg,
        _ => return None,
    })
}

/// The relative change of `statistic` ("period.name") between the revolutions `pair`,
/// on the scale [`crate::sim::steady_check`] uses (its largest magnitude over the periods of
/// both, or its floor).
fn change_of(rows: &[PeriodRow], pair: [u32; 2], statistic: &str) -> Option<f64> {
    let (period, stat) = statistic.split_once('.')?;
    let floor = crate::sim::steady_floor(stat)?;
    let scale = rows
        .iter()
        .filter(|r| r.revolution == pair[0] || r.revolution == pair[1])
        .filter_map(|r| value_of(r, stat))
        .map(f64::abs)
        .fold(floor, f64::max);
    let a = rows
        .iter()
        .find(|r| r.revolution == pair[0] && r.period == period)?;
    let b = rows
        .iter()
        .find(|r| r.revolution == pair[1] && r.period == period)?;
    Some((value_of(a, stat)? - value_of(b, stat)?).abs() / scale)
}

/// "the low dwell's acceleration deviation RMS went from 202 to 218 in/s^2 between
/// revolutions 2 and 3 (3.3 % of its largest value in any period)".
fn describe(rows: &[PeriodRow], c: &SteadyCheck, units: Units) -> String {
    let Some((period, stat)) = c.statistic.split_once('.') else {
        return format!(
            "revolutions {} and {} agree (largest change {:.2} %)",
            c.compared[0],
            c.compared[1],
            100.0 * c.max_rel_change
        );
    };
    let (name, unit) = label(stat);
    let get = |rev: u32| {
        rows.iter()
            .find(|r| r.revolution == rev && r.period == period)
            .and_then(|r| value_of(r, stat))
            .map(|x| unit.map_or(x, |u| units.value(u, x)))
    };
    let unit = unit.map_or("", |u| units.symbol(u));
    match (get(c.compared[0]), get(c.compared[1])) {
        (Some(a), Some(b)) => format!(
            "the largest change from revolution {} to {} is the {} of the {} period, {} to {} {unit} ({:.2} % of its largest value in any period)",
            c.compared[0],
            c.compared[1],
            name,
            period,
            short(a),
            short(b),
            100.0 * c.max_rel_change
        ),
        _ => format!(
            "revolutions {} and {} differ by {:.2} % at most",
            c.compared[0],
            c.compared[1],
            100.0 * c.max_rel_change
        ),
    }
}

/// A number with 4 significant digits, plain where that reads well.
fn short(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-2..1e5).contains(&a) {
        let digits = if a >= 1000.0 {
            0
        } else if a >= 100.0 {
            1
        } else if a >= 10.0 {
            2
        } else {
            3
        };
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

/// The spring's stress and solid-height warnings: the part's shear stress at full
/// compression over its allowable, the free length too short for full compression. An
/// assumed spring (a rate without `[design.spring]`) is not judged on them: its wire is
/// the model's assumption, not the designer's part.
pub fn spring_part_warnings(spring: &SpringVerdict, units: Units) -> Vec<String> {
    use crate::units as u;
    let mut w = Vec::new();
    if !spring.given {
        return w;
    }
    let su = units.symbol(u::STRESS);
    if spring.shear_stress_psi.in_inch() > spring.allowable_shear_psi.in_inch() {
        w.push(format!(
            "spring shear stress {} {su} at full compression ({} {fu}) exceeds the allowable {} {su} (design.spring): a thicker wire, a smaller coil or a softer spring",
            units.show(spring.shear_stress_psi, 0),
            units.show(spring.full_compression_force_lb, 1),
            units.show(spring.allowable_shear_psi, 0),
            fu = units.symbol(u::FORCE)
        ));
    }
    if spring.solid() == Some(true) {
        w.push(format!(
            "the spring is solid at full compression: free length {} {lu} less the compression {} {lu} is not above the solid height {} {lu} ({}: at least {} {lu})",
            units.q(u::LENGTH, spring.free_length_in.map_or(f64::NAN, Length::in_inch), 3),
            units.show(spring.full_compression_in, 3),
            units.show(spring.solid_height_in, 3),
            key_hint("design.spring.free_length", u::LENGTH, units),
            units.show(spring.least_free_length_in, 3),
            lu = units.symbol(u::LENGTH)
        ));
    }
    w
}

/// A scene key a hint names, in the output's unit family first and the other family's
/// suffix after it: `design.spring.free_length_mm or _in` under `--units si`.
pub fn key_hint(stem: &str, unit: camsim_scene_file::units::Unit, units: Units) -> String {
    let (first, other) = match units {
        crate::units::Units::Inch => (unit.inch, unit.si),
        crate::units::Units::Si => (unit.si, unit.inch),
    };
    format!("{stem}_{first} or _{other}")
}

/// The verdict's spring lines: rate, mass, coils and surge; the part (given, or assumed
/// from the rate); stress at full compression and the solid-height check.
pub fn spring_lines(out: &mut String, s: &SpringVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let (lu, su) = (units.symbol(u::LENGTH), units.symbol(u::STRESS));
    let _ = writeln!(
        out,
        "  spring:    {} {}, {:.2} active coils, {} {}; surge {:.0} Hz = {:.1} x the cam's {:.2} Hz",
        units.show(s.rate_lb_per_in, 1),
        units.symbol(u::STIFFNESS),
        s.active_coils,
        units.show(s.mass_lb, 4),
        units.symbol(u::WEIGHT),
        s.surge_hz,
        s.surge_harmonic,
        s.cam_hz
    );
    let part = format!(
        "wire {} {lu}, mean coil {} {lu}, {:.2} total coils, {} ends, {}",
        units.show(s.wire_diameter_in, 3),
        units.show(s.mean_diameter_in, 3),
        s.total_coils,
        s.ends,
        s.material
    );
    if s.given {
        let _ = writeln!(out, "             [design.spring]: {part}");
    } else {
        let _ = writeln!(
            out,
            "             assumed from the rate (no [design.spring]): {part}"
        );
    }
    // An assumed wire's stress and solid height are shown, not judged: say so on their
    // lines, beside the numbers a reader would otherwise take as a verdict.
    let assumed = if s.given {
        ""
    } else {
        " (the assumed wire's: not judged; give [design.spring], or camsim design spring for one)"
    };
    let _ = writeln!(
        out,
        "             at full compression {} {lu} ({} {}): shear stress {} {su} (Wahl), {:.0} % of the allowable {} {su}{assumed}",
        units.show(s.full_compression_in, 3),
        units.show(s.full_compression_force_lb, 1),
        units.symbol(u::FORCE),
        units.show(s.shear_stress_psi, 0),
        100.0 * s.shear_stress_psi.in_inch() / s.allowable_shear_psi.in_inch(),
        units.show(s.allowable_shear_psi, 0)
    );
    let solid = match s.free_length_in {
        Some(l) => format!(
            "free length {} {lu}: {} {lu} at full compression, {}",
            units.show(l, 3),
            units.q(u::LENGTH, l.in_inch() - s.full_compression_in.in_inch(), 3),
            if s.solid() == Some(true) {
                "SOLID"
            } else {
                "not solid"
            }
        ),
        None => format!(
            "free length not given ({}): at least {} {lu}",
            key_hint("design.spring.free_length", u::LENGTH, units),
            units.show(s.least_free_length_in, 3)
        ),
    };
    let _ = writeln!(
        out,
        "             solid height {} {lu}{}; {solid}",
        units.show(s.solid_height_in, 3),
        if s.given { "" } else { " (the assumed wire's)" }
    );
}

/// The warnings of a verdict (pressure angle, undercut, stress, surge, separation).
pub fn warnings(
    contact: &ContactVerdict,
    geometry: &GeometryVerdict,
    loads: &LoadsVerdict,
    spring: &SpringVerdict,
    margin: Option<&MarginVerdict>,
    units: Units,
) -> Vec<String> {
    use crate::units as u;
    let mut w = Vec::new();
    if !contact.holds {
        w.push(format!(
            "the follower leaves the cam {} time(s) in revolutions {}-{}, {:.2} deg of cam angle in all",
            contact.separations.len(),
            contact.revolutions[0],
            contact.revolutions[1],
            contact.off_cam_deg
        ));
    }
    if geometry.max_pressure_angle_deg > geometry.pressure_angle_limit_deg {
        w.push(format!(
            "pressure angle {:.1} deg at cam angle {:.1} deg exceeds the limit {:.1} deg (limits.pressure_angle_limit_deg, --pressure-angle-limit)",
            geometry.max_pressure_angle_deg,
            geometry.max_pressure_angle_at_deg,
            geometry.pressure_angle_limit_deg
        ));
    }
    if geometry.undercut_margin_in.in_inch() <= 0.0 {
        w.push(format!(
            "undercut: the pitch curve's radius {} {} at {:.1} deg is below the roller radius",
            units.show(geometry.min_pitch_radius_in, 4),
            units.symbol(u::LENGTH),
            geometry.min_pitch_radius_at_deg
        ));
    }
    if loads.stress_ratio > 1.0 {
        w.push(format!(
            "contact stress {} {su} exceeds the allowable {} {su} by {:.1} % (limits.allowable_contact_stress_{}, --allowable-stress)",
            units.show(loads.peak_contact_stress_psi, 0),
            units.show(loads.allowable_contact_stress_psi, 0),
            100.0 * (loads.stress_ratio - 1.0),
            units.key_suffix(u::STRESS),
            su = units.symbol(u::STRESS)
        ));
    }
    if spring.surge_harmonic < spring.least_harmonic {
        w.push(format!(
            "spring surge {:.0} Hz is only {:.1} times the cam's {:.2} Hz: harmonic {} of the cam motion excites it (keep the surge above the {:.0}th harmonic: a stiffer, lighter spring)",
            spring.surge_hz,
            spring.surge_harmonic,
            spring.cam_hz,
            spring.surge_harmonic.round().max(1.0),
            spring.least_harmonic
        ));
    }
    w.extend(spring_part_warnings(spring, units));
    if let Some(m) = margin {
        if let Some(p) = m.margin_percent {
            if p <= 0.0 {
                w.push(format!(
                    "the jump onset {:.1} rpm is at or below the operating speed",
                    m.jump_onset_rpm.unwrap_or(f64::NAN)
                ));
            }
        }
    }
    w
}

/// Text of an [`At`].
pub fn at_text(a: &At) -> String {
    format!(
        "cam angle {:.1} deg of revolution {}",
        a.cam_angle_deg, a.revolution
    )
}

/// The verdict block as text.
pub fn text(v: &Verdict, units: Units) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let c = &v.contact;
    contact_lines(&mut out, c, units);
    let _ = writeln!(out, "{}", geometry_text(&v.geometry, units));
    loads_lines(&mut out, &v.loads, units);
    spring_lines(&mut out, &v.spring, units);
    let _ = writeln!(out, "{}", mass_text(&v.mass, units));
    let _ = writeln!(out, "{}", drive_text(&v.drive, c.revolutions));
    let _ = writeln!(out, "{}", margin_text(v.jump_margin.as_ref()));
    if let Some(st) = &v.steady {
        let _ = writeln!(out, "  steady:    {}", st.summary);
    }
    if v.warnings.is_empty() {
        let _ = writeln!(out, "  warnings:  none");
    } else {
        for w in &v.warnings {
            let _ = writeln!(out, "  WARNING:   {w}");
        }
    }
    out
}

/// The verdict's heading and contact lines: whether contact holds and its smallest force,
/// or where the follower leaves the cam; the start transient's separations, not judged.
fn contact_lines(out: &mut String, c: &ContactVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "VERDICT (revolutions {}-{})",
        c.revolutions[0], c.revolutions[1]
    );
    if c.holds {
        let _ = writeln!(
            out,
            "  contact:   HOLDS; smallest contact force {} {} at {} ({})",
            units.show(c.min_contact_force_lb, 2),
            units.symbol(u::FORCE),
            at_text(&c.min_contact_force_at),
            c.min_contact_force_period
        );
    } else {
        let _ = writeln!(
            out,
            "  contact:   the follower LEAVES the cam ({:.2} deg of cam angle off it); smallest force in contact {} {} at {}",
            c.off_cam_deg,
            units.show(c.min_contact_force_lb, 2),
            units.symbol(u::FORCE),
            at_text(&c.min_contact_force_at)
        );
        for s in &c.separations {
            let _ = writeln!(
                out,
                "             revolution {}, {}: off from {:.2} to {:.2} deg, {:.3} ms",
                s.revolution, s.period, s.from_deg, s.to_deg, s.duration_ms
            );
        }
    }
    if c.start_transient_separations > 0 && c.revolutions[0] > 1 {
        let _ = writeln!(
            out,
            "             (revolution 1, the start transient, separated {} time(s): not judged)",
            c.start_transient_separations
        );
    }
}

/// The verdict's geometry line: the largest pressure angle and the pitch curve's smallest
/// radius with its undercut margin.
fn geometry_text(g: &GeometryVerdict, units: Units) -> String {
    use crate::units as u;
    format!(
        "  geometry:  largest pressure angle {:.2} deg at cam angle {:.1} deg (limit {:.0} deg); smallest pitch-curve radius {} {lu} at {:.1} deg, undercut margin {} {lu}",
        g.max_pressure_angle_deg,
        g.max_pressure_angle_at_deg,
        g.pressure_angle_limit_deg,
        units.show(g.min_pitch_radius_in, 4),
        g.min_pitch_radius_at_deg,
        units.show(g.undercut_margin_in, 4),
        lu = units.symbol(u::LENGTH)
    )
}

/// The verdict's loads lines: the peak cam torque and motor power, and the peak contact
/// stress against the allowable.
fn loads_lines(out: &mut String, l: &LoadsVerdict, units: Units) {
    use crate::units as u;
    use std::fmt::Write;
    let _ = writeln!(
        out,
        "  loads:     peak cam torque {} {} at {}; peak motor power {} at {}",
        units.show(l.peak_cam_torque_lb_in, 1),
        units.symbol(u::TORQUE),
        at_text(&l.peak_cam_torque_at),
        match units {
            u::Units::Inch => format!(
                "{:.3} hp ({:.0} W)",
                l.peak_motor_power_hp.in_inch(),
                l.peak_motor_power_w
            ),
            u::Units::Si => format!("{:.3} kW", l.peak_motor_power_w / 1000.0),
        },
        at_text(&l.peak_motor_power_at)
    );
    let _ = writeln!(
        out,
        "             peak contact stress {} {su} at {}: {:.0} % of the allowable {} {su} ({})",
        units.show(l.peak_contact_stress_psi, 0),
        at_text(&l.peak_contact_stress_at),
        100.0 * l.stress_ratio,
        units.show(l.allowable_contact_stress_psi, 0),
        l.allowable_source,
        su = units.symbol(u::STRESS)
    );
}

/// The verdict's margin line: the jump onset's margin over the operating speed, no jump up
/// to the search's limit, or not computed (`None`: no `--margin`).
fn margin_text(m: Option<&MarginVerdict>) -> String {
    let Some(m) = m else {
        return "  margin:    not computed (--margin: a search of about 15 two-revolution runs)"
            .to_string();
    };
    match (m.jump_onset_rpm, m.margin_percent) {
        (Some(j), Some(p)) => format!(
            "  margin:    jump onset {j:.1} rpm (contact holds at {:.1} rpm; bracket {:.1} rpm), {p:+.1} % over the operating speed; {} simulations",
            m.holds_at_rpm, m.bracket_rpm, m.simulations
        ),
        _ => format!(
            "  margin:    no jump up to {:.0} rpm; {} simulations",
            m.holds_at_rpm, m.simulations
        ),
    }
}

/// The verdict's mass line.
fn mass_text(m: &MassVerdict, units: Units) -> String {
    use crate::units as u;
    let q = |x: Weight| units.show(x, 4);
    format!(
        "  mass:      moving {} {w} = load {} + rod rho*A*(e1+e2) {} + roller {} + a third of the spring {}",
        q(m.moving_mass_lb),
        q(m.load_mass_lb),
        q(m.rod_mass_lb),
        q(m.roller_mass_lb),
        q(m.spring_share_mass_lb),
        w = units.symbol(u::WEIGHT)
    )
}

/// The verdict's drive line. A given drive's swing past the limit is stated there, as
/// part of the result (an inherited drive's is a warning: [`swing_warning`]).
fn drive_text(d: &DriveVerdict, revolutions: [u32; 2]) -> String {
    let limit = if d.given && d.swing_percent > d.swing_limit_percent {
        format!(
            "over the {:.0} % a constant-speed design assumes; the drive is given, so the result includes its speed variation",
            d.swing_limit_percent
        )
    } else {
        format!("limit {:.0} %", d.swing_limit_percent)
    };
    format!(
        "  drive:     {}: {}; cam speed {:.1} to {:.1} rpm over revolutions {}-{}, {:.2} % from the nominal {:.1} rpm ({limit})",
        d.drive,
        d.description,
        d.min_cam_speed_rpm,
        d.max_cam_speed_rpm,
        revolutions[0],
        revolutions[1],
        d.swing_percent,
        d.nominal_rpm,
    )
}

/// The warning on a cam speed that swings past the limit with a drive the scene did not
/// name (inherited from the reference), if it does.
pub fn swing_warning(d: &DriveVerdict) -> Option<String> {
    (!d.given && d.swing_percent > d.swing_limit_percent).then(|| {
        format!(
            "the cam speed swings {:.1} % from the nominal {:.1} rpm ({:.1} to {:.1} rpm; limit {:.0} %): the scene names no drive, so it inherits the thesis's regulated motor (tuned for 800 rpm), which does not hold the speed the kinematic design assumes: name the drive: a [design.drive.motor] table (inertia, shaft_stiffness, gain, torque_limit) for this machine, drive = \"thesis\" to keep this one, or drive = \"constant-cam-speed\" for the kinematic answer",
            d.swing_percent,
            d.nominal_rpm,
            d.min_cam_speed_rpm,
            d.max_cam_speed_rpm,
            d.swing_limit_percent,
        )
    })
}

/// The contact verdict from the run's jumps and watch.
pub fn contact(
    design: &Design<f64>,
    jumps: &[JumpRow],
    periods: &[&'static str],
    watch: &Watch,
    revolutions: u32,
) -> Result<ContactVerdict> {
    let rpm = camsim_core::rad_per_s_to_rpm(design.omega0);
    let from = watch.from_revolution;
    let mut separations: Vec<Separation> = Vec::new();
    let mut off = 0.0;
    let mut transient = 0;
    let ms_per_deg = 60_000.0 / (360.0 * rpm);
    let mut last_key: Option<(u32, usize)> = None;
    for j in jumps {
        if j.revolution < from {
            transient += 1;
            continue;
        }
        off += j.end_deg - j.start_deg;
        let period = periods.get(j.period).copied().unwrap_or("?").to_string();
        match separations.last_mut() {
            Some(s) if last_key == Some((j.revolution, j.period)) => {
                s.to_deg = j.end_deg;
                s.duration_ms += (j.end_deg - j.start_deg) * ms_per_deg;
            }
            _ => separations.push(Separation {
                revolution: j.revolution,
                period,
                from_deg: j.start_deg,
                to_deg: j.end_deg,
                duration_ms: (j.end_deg - j.start_deg) * ms_per_deg,
            }),
        }
        last_key = Some((j.revolution, j.period));
    }
    let (f, at) = watch.min_force.ok_or_else(|| {
        anyhow::anyhow!("the follower was never on the cam in the judged revolutions")
    })?;
    let seg = design.program.segment_at(at.cam_angle_deg.to_radians());
    Ok(ContactVerdict {
        holds: separations.is_empty(),
        revolutions: [from, revolutions],
        separations,
        off_cam_deg: off,
        start_transient_separations: transient,
        min_contact_force_lb: Force::inch(f),
        min_contact_force_at: at,
        min_contact_force_period: periods.get(seg).copied().unwrap_or("?").to_string(),
    })
}

/// The loads verdict from the watch.
pub fn loads(watch: &Watch, limits: &Limits) -> Result<LoadsVerdict> {
    let missing = || anyhow::anyhow!("no sample in the judged revolutions");
    let (t, t_at) = watch.peak_torque.ok_or_else(missing)?;
    let (p, p_at) = watch.peak_power.ok_or_else(missing)?;
    let (s, s_at) = watch.peak_stress.ok_or_else(missing)?;
    Ok(LoadsVerdict {
        peak_cam_torque_lb_in: Torque::inch(t),
        peak_cam_torque_at: t_at,
        peak_motor_power_hp: Power::inch(p / HP_LB_IN_PER_S),
        peak_motor_power_w: p * W_PER_LB_IN_PER_S,
        peak_motor_power_at: p_at,
        peak_contact_stress_psi: Stress::inch(s),
        peak_contact_stress_at: s_at,
        allowable_contact_stress_psi: Stress::inch(limits.allowable_contact_stress_psi),
        allowable_source: limits.allowable_source,
        stress_ratio: s / limits.allowable_contact_stress_psi,
    })
}

/// One separation interval (the JSON `jumps` entries).
#[derive(Clone, Debug, Serialize)]
pub struct JumpRow {
    /// Revolution of the onset, from 1.
    pub revolution: u32,
    /// Cam angle of the onset within that revolution, degrees.
    pub start_deg: f64,
    /// Cam angle of the landing, degrees (on the onset revolution's scale).
    pub end_deg: f64,
    /// Index of the period of the onset (text only).
    #[serde(skip)]
    pub period: usize,
}
