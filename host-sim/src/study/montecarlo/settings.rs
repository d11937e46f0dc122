//! The settings that identify a study ([`StudySettings`]: a shard file carries them, the
//! report prints them) and how its actual cams are made ([`ProfileSettings`]).

use anyhow::Result;
use serde::{Deserialize, Serialize};

use crate::actual::{self, Cams};
use crate::units::Length;

/// The settings that make two runs the same study (a shard file carries them; the
/// merge refuses files whose settings differ in anything). Its tolerances are plain
/// inch numbers in the shard file (`L = f64`), [`Length`]s in the report
/// ([`StudySettings::measured`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudySettings<L = f64> {
    /// The camsim version that ran it.
    pub camsim_version: String,
    /// Number of samples of the whole study.
    pub samples: u64,
    /// Master seed.
    pub seed: u64,
    /// Revolutions simulated (the statistics are revolution 2's).
    pub revolutions: u32,
    /// The scene as a complete scene file (design, solver, DOFs).
    pub scene: String,
    /// How the actual cams are made.
    pub profile: ProfileSettings<L>,
    /// The two-level estimate's levels (absent: every cam on the one model of `scene`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub two_level: Option<TwoLevelSettings>,
    /// Why a study without `--follower` or `--two-level` runs one model rather than the
    /// default two-level estimate ([`super::Study::default_levels`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub one_model: Option<String>,
}

/// The levels of a two-level study (`--two-level n`): every cam on the reduced scene,
/// the first n on the full one (`scene`) as well.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoLevelSettings {
    /// n: the cams (samples 0 to n − 1) that run on the full model too.
    pub full_samples: u64,
    /// The reduced scene every cam runs on, as a complete scene file.
    pub reduced_scene: String,
}

/// How a study's actual cams are made (its tolerances plain inch numbers, `L = f64`, or
/// the report's [`Length`]s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileSettings<L = f64> {
    /// `thesis` or `envelope`.
    pub method: String,
    /// `sum12` or `polar`.
    pub normal: String,
    /// Cam profile tolerance, ± in.
    pub cam_tolerance_in: L,
    /// Roller radius tolerance, ± in.
    pub roller_tolerance_in: L,
    /// Eccentricity tolerance, ± in.
    pub eccentricity_tolerance_in: L,
    /// Profile points per revolution.
    pub intervals: usize,
    /// `given` (--interval-deg), `criteria` (IV.2.3's three, on the master seed) or
    /// `waviness FPR n (master seed's profile FPR m)` (--waviness-fpr).
    pub interval_source: String,
}

impl ProfileSettings {
    /// How `actual`'s cams are made, with the interval chosen for them
    /// ([`actual::intervals_for`]).
    pub fn of(actual: &Cams, interval: (usize, actual::IntervalSource)) -> Result<Self> {
        let tol = actual.tolerances()?;
        Ok(ProfileSettings {
            method: actual.profile_method.name().into(),
            normal: actual.normal.name().into(),
            cam_tolerance_in: tol.cam,
            roller_tolerance_in: tol.roller,
            eccentricity_tolerance_in: tol.eccentricity,
            intervals: interval.0,
            interval_source: interval.1.label(),
        })
    }

    /// These settings with their tolerances as [`Length`]s (the report's).
    pub fn measured(&self) -> ProfileSettings<Length> {
        ProfileSettings {
            method: self.method.clone(),
            normal: self.normal.clone(),
            cam_tolerance_in: Length::inch(self.cam_tolerance_in),
            roller_tolerance_in: Length::inch(self.roller_tolerance_in),
            eccentricity_tolerance_in: Length::inch(self.eccentricity_tolerance_in),
            intervals: self.intervals,
            interval_source: self.interval_source.clone(),
        }
    }
}

impl StudySettings {
    /// These settings with their tolerances as [`Length`]s (the report's).
    pub fn measured(&self) -> StudySettings<Length> {
        StudySettings {
            camsim_version: self.camsim_version.clone(),
            samples: self.samples,
            seed: self.seed,
            revolutions: self.revolutions,
            scene: self.scene.clone(),
            profile: self.profile.measured(),
            two_level: self.two_level.clone(),
            one_model: self.one_model.clone(),
        }
    }
}
