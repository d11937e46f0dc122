//! A study ready to run ([`Study`]: the scene, the actual cams and the settings) and its
//! models: the scene's one model, or the two levels of the two-level estimate (every cam
//! on the reduced model of the design searches, [`monte_carlo_model`], a subsample on the
//! full model too).

use anyhow::Result;
use camsim_core::{DriveLaw, FollowerModel};

use super::{measured_revolution, ProfileSettings, StudySettings, TwoLevelSettings};
use crate::actual::{self, Cams};
use crate::sim::RunSpec;

/// The fewest full-model cams of a default two-level study.
pub const MIN_FULL_SAMPLES: u64 = 30;

/// The default subsample of a two-level study of `samples` cams (docs/MODEL.md §9.7):
/// a tenth of the cams, at least [`MIN_FULL_SAMPLES`], at most all of them.
pub fn default_full_samples(samples: u64) -> u64 {
    samples.div_ceil(10).max(MIN_FULL_SAMPLES).min(samples)
}

/// A study ready to run: the scene, and the actual-cam options with the interval
/// fixed once (so no sample repeats the interval choice).
#[derive(Clone, Debug)]
pub struct Study {
    /// The scene (its `profile` is set per sample).
    pub spec: RunSpec,
    /// The actual-cam options, the interval resolved (`resolved` set).
    pub actual: Cams,
    /// What identifies the study.
    pub settings: StudySettings,
    /// The reduced scene of a two-level study (`spec` is then its full one).
    pub reduced: Option<RunSpec>,
}

impl Study {
    /// A study of `samples` actual cams made by `actual` on the scene `spec`.
    pub fn from_spec(spec: RunSpec, actual: &Cams, samples: u64) -> Result<Self> {
        anyhow::ensure!(
            spec.revolutions >= 1,
            "a study needs at least one revolution"
        );
        anyhow::ensure!(samples >= 1, "--samples must be at least 1");
        let (intervals, source) = actual::intervals_for(&spec.design, actual)?;
        let profile = ProfileSettings::of(actual, (intervals, source))?;
        let mut fixed = actual.clone();
        fixed.actual = true;
        fixed.resolved = Some((intervals, source));
        let settings = StudySettings {
            camsim_version: env!("CARGO_PKG_VERSION").to_string(),
            samples,
            seed: actual.seed(),
            revolutions: spec.revolutions,
            scene: crate::scene::spec_text(&spec)?,
            profile,
            two_level: None,
            one_model: None,
        };
        Ok(Study {
            spec,
            actual: fixed,
            settings,
            reduced: None,
        })
    }

    /// The two-level study of this one (`--two-level n`): every cam on the Monte Carlo
    /// model of the design searches ([`monte_carlo_model`]), samples 0 to n − 1 on this
    /// study's full scene as well.
    pub fn two_level(mut self, n: u64) -> Result<Self> {
        let samples = self.settings.samples;
        anyhow::ensure!(
            self.spec.dofs.follower == FollowerModel::Full,
            "--two-level {n}: the scene's follower is {}: the two-level estimate pairs the full follower with a reduced one (drop --follower, or the scene's run.follower)",
            self.spec.dofs.follower.name()
        );
        anyhow::ensure!(
            matches!(self.spec.design.drive, DriveLaw::Regulated { .. }),
            "--two-level {n}: the reduced followers are built for the regulated drive only (drop --constant-cam-speed, or the scene's constant drive)"
        );
        anyhow::ensure!(
            (2..=samples).contains(&n),
            "--two-level {n}: the full-model cams must be at least 2 and at most --samples ({samples})"
        );
        let reduced = monte_carlo_model(&self.spec);
        self.settings.two_level = Some(TwoLevelSettings {
            full_samples: n,
            reduced_scene: crate::scene::spec_text(&reduced)?,
        });
        self.reduced = Some(reduced);
        Ok(self)
    }

    /// The study montecarlo runs when neither `--follower` nor `--two-level` is given:
    /// the two-level estimate with [`default_full_samples`] cams on the full model, or,
    /// where it cannot run, the scene's one model with the reason in `one_model`.
    pub fn default_levels(mut self) -> Result<Self> {
        let samples = self.settings.samples;
        let why = if self.spec.dofs.follower != FollowerModel::Full {
            format!(
                "the scene's run.follower ({})",
                self.spec.dofs.follower.name()
            )
        } else if !matches!(self.spec.design.drive, DriveLaw::Regulated { .. }) {
            "the full model alone: the reduced followers need the regulated drive (constant cam speed given)".to_string()
        } else if samples < 2 {
            "the full model alone: the two-level estimate needs at least 2 cams".to_string()
        } else {
            return self.two_level(default_full_samples(samples));
        };
        self.settings.one_model = Some(why);
        Ok(self)
    }

    /// The study's models: `two_level` N cams on the full model too (`Some(0)`: the full
    /// model alone), else one model if `one_model` (the follower given), else the
    /// default two-level estimate ([`Study::default_levels`]).
    pub fn with_levels(mut self, two_level: Option<u64>, one_model: bool) -> Result<Study> {
        match two_level {
            Some(0) => {
                self.settings.one_model = Some("the full model alone (--two-level 0)".into());
                Ok(self)
            }
            Some(n) => self.two_level(n),
            None if one_model => Ok(self),
            None => self.default_levels(),
        }
    }

    /// n of a two-level study (0 in a study of one model).
    pub fn full_samples(&self) -> u64 {
        self.settings
            .two_level
            .as_ref()
            .map_or(0, |t| t.full_samples)
    }

    /// The revolution the study measures ([`measured_revolution`]).
    pub fn revolution(&self) -> u32 {
        measured_revolution(self.spec.revolutions)
    }
}

/// The Monte Carlo model of the design searches: the quasi-static cantilever, vertical
/// (docs/RESULTS.md "Reduced scenes": adequate for P(jump) on actual cams), at rtol 1e-4.
pub fn monte_carlo_model(spec: &RunSpec) -> RunSpec {
    let mut mc = spec.clone();
    mc.dofs.horizontal = false;
    mc.dofs.follower = FollowerModel::QuasiStaticCantilever;
    mc.solver.rtol = 1e-4;
    mc.solver.atol = 1e-8;
    mc.solver.max_step_fraction = 0.01;
    mc
}
