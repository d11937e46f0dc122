//! What the method comparison reports: each law's measures on the theoretical and on
//! the actual cam ([`CamStudy`], per period [`LawPeriod`]), its values and ranks in every
//! ranked column ([`Ranks`]), the laws not workable, and the study's settings
//! ([`CompareReport`]). Its text is in [`super::text`].

use serde::{Serialize, Serializer};

use crate::actual::{self, ProfileStats};
use crate::units::{Acceleration, Force, Stress, Torque};

/// An inch-family acceleration sum (in/s²) serialized as an [`Acceleration`]: its key
/// names its unit and converts (`sensitivity_in_per_s2`, `sensitivity_mm_per_s2`).
fn acceleration<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    Acceleration::inch(*v).serialize(s)
}

/// The ranked columns' values ([`LawStudy::values`]) as JSON, each with its quantity.
#[derive(Serialize)]
struct RankValues {
    sensitivity_to_flexibility: Acceleration,
    sensitivity_to_tolerance: Acceleration,
    shock_index: f64,
    torque_avg: Torque,
    torque_max: Torque,
    contact_force_min: Force,
    contact_force_max: Force,
    contact_stress_max: Stress,
    overall: f64,
}

/// [`LawStudy::values`] serialized as [`RankValues`].
fn rank_values<S: Serializer>(v: &Ranks<f64>, s: S) -> Result<S::Ok, S::Error> {
    RankValues {
        sensitivity_to_flexibility: v.sensitivity_to_flexibility.into(),
        sensitivity_to_tolerance: v.sensitivity_to_tolerance.into(),
        shock_index: v.shock_index,
        torque_avg: v.torque_avg.into(),
        torque_max: v.torque_max.into(),
        contact_force_min: v.contact_force_min.into(),
        contact_force_max: v.contact_force_max.into(),
        contact_stress_max: v.contact_stress_max.into(),
        overall: v.overall,
    }
    .serialize(s)
}

/// One period of one cam: cycle I and cycle II acceleration RMS, cycle II's inertial
/// responses and jump.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawPeriod {
    /// Period name.
    pub period: String,
    /// Acceleration RMS deviation from the theoretical (perfect, rigid) response in
    /// cycle I (revolution 1).
    pub acc_rms_cycle1: Acceleration,
    /// The same in cycle II (revolution 2).
    pub acc_rms_cycle2: Acceleration,
    /// Cycle II: average output torque.
    pub torque_avg: Torque,
    /// Cycle II: largest output torque.
    pub torque_max: Torque,
    /// Cycle II: smallest output torque.
    pub torque_min: Torque,
    /// Cycle II: smallest contact force.
    pub contact_force_min: Force,
    /// Cycle II: largest contact force.
    pub contact_force_max: Force,
    /// Cycle II: largest Hertz stress.
    pub contact_stress_max: Stress,
    /// Cycle II: whether the follower separated.
    pub jump: bool,
}

/// One law on one cam (docs/MODEL.md §9).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CamStudy {
    /// Every period.
    pub per_period: Vec<LawPeriod>,
    /// Σ over the periods of the cycle-II acceleration RMS, in/s² (on the theoretical
    /// cam: the sensitivity to flexibility).
    #[serde(serialize_with = "acceleration")]
    pub sensitivity: f64,
    /// Σ over the rises and returns of (RMS_I − RMS_II)/RMS_I (VI.4.2).
    pub shock_index: f64,
    /// Cycle II: average output torque over the rise(s) (the largest).
    pub torque_avg_rise: Torque,
    /// Cycle II: average output torque over the return(s) (the most negative: the
    /// power fed back).
    pub torque_avg_return: Torque,
    /// Cycle II: largest |output torque|.
    pub torque_max: Torque,
    /// Cycle II: smallest contact force.
    pub contact_force_min: Force,
    /// Cycle II: largest contact force.
    pub contact_force_max: Force,
    /// Cycle II: largest Hertz stress.
    pub contact_stress_max: Stress,
    /// Cycle II: whether the follower separated anywhere.
    pub jump: bool,
    /// Accepted solver steps.
    pub steps: u32,
}

/// The actual cam's study of one law.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ActualStudy {
    /// The same measures as on the theoretical cam.
    #[serde(flatten)]
    pub cam: CamStudy,
    /// Sensitivity to tolerance: the actual cam's Σ cycle-II acceleration RMS minus the
    /// theoretical cam's, in/s².
    #[serde(serialize_with = "acceleration")]
    pub sensitivity_to_tolerance: f64,
    /// The actual cam's profile.
    pub profile: ProfileStats,
}

/// One law's study.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawStudy {
    /// The law's name (as `camsim laws` prints it).
    pub name: String,
    /// On the theoretical cam (flexibility alone).
    pub flexibility: CamStudy,
    /// On the actual cam (flexibility and tolerance).
    pub actual: ActualStudy,
    /// The actual cam separates during a rise of cycle II.
    pub jump_rise: bool,
    /// The actual cam separates during a return of cycle II.
    pub jump_return: bool,
    /// The value of every ranked column ([`super::RANKED`]), in the inch family (in JSON
    /// each with its quantity: `sensitivity_to_flexibility_in_per_s2`, `torque_avg_lb_in`).
    #[serde(serialize_with = "rank_values")]
    pub values: Ranks<f64>,
    /// The law's rank (1 best) in every ranked column, and overall (the laws that hold
    /// contact on the theoretical cam first, then by the sum of the ranks).
    pub ranks: Ranks<usize>,
}

/// One value per ranked column ([`super::RANKED`]) and an overall one.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Ranks<T> {
    /// Sensitivity to flexibility.
    pub sensitivity_to_flexibility: T,
    /// Sensitivity to tolerance.
    pub sensitivity_to_tolerance: T,
    /// Shock index.
    pub shock_index: T,
    /// Average torque of the rise.
    pub torque_avg: T,
    /// Largest |torque|.
    pub torque_max: T,
    /// Smallest contact force (larger is better).
    pub contact_force_min: T,
    /// Largest contact force.
    pub contact_force_max: T,
    /// Largest contact stress.
    pub contact_stress_max: T,
    /// Overall: the rank (ranks) or the sum of the ranks above (values).
    pub overall: T,
}

impl<T: Copy> Ranks<T> {
    /// The value of column `name` ([`super::RANKED`] or `overall`).
    pub fn get(&self, name: &str) -> Option<T> {
        Some(match name {
            "sensitivity_to_flexibility" => self.sensitivity_to_flexibility,
            "sensitivity_to_tolerance" => self.sensitivity_to_tolerance,
            "shock_index" => self.shock_index,
            "torque_avg" => self.torque_avg,
            "torque_max" => self.torque_max,
            "contact_force_min" => self.contact_force_min,
            "contact_force_max" => self.contact_force_max,
            "contact_stress_max" => self.contact_stress_max,
            "overall" => self.overall,
            _ => return None,
        })
    }

    pub(super) fn set(&mut self, name: &str, v: T) {
        match name {
            "sensitivity_to_flexibility" => self.sensitivity_to_flexibility = v,
            "sensitivity_to_tolerance" => self.sensitivity_to_tolerance = v,
            "shock_index" => self.shock_index = v,
            "torque_avg" => self.torque_avg = v,
            "torque_max" => self.torque_max = v,
            "contact_force_min" => self.contact_force_min = v,
            "contact_force_max" => self.contact_force_max = v,
            "contact_stress_max" => self.contact_stress_max = v,
            _ => self.overall = v,
        }
    }
}

/// A law whose run left the model's valid range (docs/MODEL.md §3.20): not ranked.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NotWorkable {
    /// The law's name (as `camsim laws` prints it).
    pub name: String,
    /// The cam whose run left the range: `theoretical` or `actual`.
    pub cam: String,
    /// Why: the core's error (the quantity, its value, the bound, the cam angle).
    pub reason: String,
}

/// What `camsim compare` prints.
#[derive(Clone, Debug, Serialize)]
pub struct CompareReport {
    /// Every workable law, in the order of `camsim laws`.
    pub laws: Vec<LawStudy>,
    /// The laws not workable (their run left the model's valid range), in the same order.
    pub not_workable: Vec<NotWorkable>,
    /// Cam speed, rpm.
    pub rpm: f64,
    /// Whether the vertical scene ran (--quick).
    pub quick: bool,
    /// Master seed of the actual cam (sample 0).
    pub seed: u64,
    /// Profile intervals per revolution (the same for every law).
    pub intervals: usize,
    /// How the interval was set (by default the waviness, FPR 17).
    pub interval_source: actual::IntervalSource,
    /// Wall-clock time, s.
    pub wall_s: f64,
}
