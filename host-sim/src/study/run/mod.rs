//! `camsim run` as a study: one simulation of a scene (the theoretical cam, an actual
//! cam drawn from tolerances or a measured one) with its verdict ([`verdict`]),
//! per-period table, jumps and solver statistics.
//!
//! The study takes a typed [`Spec`] and the output's unit family and returns a
//! [`RunReport`] (its text in [`text`]); [`report_observed`] also hands every sample to
//! the caller's observer (the command's `--csv`) and keeps the samples the run's figures
//! need ([`crate::plot`]). `camsim run` (crate::cmd::run) builds the spec from its
//! arguments, writes the files and prints the report.

use std::ops::ControlFlow;
use std::sync::Arc;

use anyhow::Result;
use camsim_core::{AngleGrid, GridPointKind, JumpInterval, Observer, Sample};

use crate::actual::Cams;
use crate::measured::MeasuredProfile;
use crate::plot::PlotData;
use crate::sim::{self, HostDeviation, RunSpec};
use crate::units::Units;
use verdict::{self as v, Watch};

pub mod report;
pub mod text;
pub mod verdict;

pub use report::*;

/// The cam the study runs.
pub enum Cam {
    /// The theoretical profile.
    Theoretical,
    /// An actual cam, sample 0 of the tolerances' seed (`--actual`).
    Actual(Cams),
    /// A measured profile (`--measured FILE`), named as its errors name it.
    Measured {
        /// The profile as read.
        profile: crate::measured::Measured,
        /// How errors name it (`--measured FILE`).
        name: String,
    },
}

/// What the study runs.
pub struct Spec {
    /// The scene, its revolutions resolved (the profile is attached by the study).
    pub run: RunSpec,
    /// The cam.
    pub cam: Cam,
    /// What the verdict judges against.
    pub limits: v::Limits,
    /// Also find the jump onset and the margin to it (`--margin`).
    pub margin: bool,
    /// The scene file given (None: the built-in reference design).
    pub scene_file: Option<String>,
    /// The cam-angle grid the observer of [`report_observed`] is given samples on.
    pub grid: AngleGrid<f64>,
    /// Keep the samples the run's figures need ([`Simulated::plot`]).
    pub plot: bool,
}

/// A finished run: its report, and what its figures need.
pub struct Simulated {
    /// The report (checked finite and physical; no files listed yet).
    pub report: RunReport,
    /// The samples of the figures (with [`Spec::plot`]).
    pub plot: Option<PlotData>,
    /// The run's separation intervals (for the figures).
    pub jumps: Vec<JumpInterval<f64>>,
    /// The actual or measured cam's lift deviation (for its figure).
    pub profile: Option<Arc<HostDeviation>>,
}

/// Runs the study.
pub fn report(spec: &Spec, units: Units) -> Result<RunReport> {
    Ok(report_observed(spec, units, &mut NoRows)?.report)
}

/// Runs the study, `rows` observing every sample (and every point of [`Spec::grid`]).
/// A result with a number that is not finite is an error.
pub fn report_observed<O: Observer<f64>>(
    spec: &Spec,
    units: Units,
    rows: &mut O,
) -> Result<Simulated> {
    let mut run = spec.run.clone();
    let profile_report = attach_profile(&mut run, &spec.cam)?;
    let mut plot = spec.plot.then(PlotData::default);
    let mut watch = Watch::new(Watch::steady_from(run.revolutions));
    let result = {
        let mut obs = RunObserver {
            watch: &mut watch,
            plot: plot.as_mut(),
            rows,
        };
        sim::run_on_grid(&run, &mut obs, spec.grid)?
    };
    let mut report = RunReport::new(&run, &result);
    report.fpr = profile_report.as_ref().map(ProfileReport::fpr);
    report.profile = profile_report;
    report.verdict = Some(v::judge(
        &run,
        &report,
        &watch,
        &spec.limits,
        spec.margin,
        units,
    )?);
    report.scene_file = spec.scene_file.clone();
    report.scene = Some(crate::scene::spec_text(&run)?);
    crate::report::ensure_finite(&report)?;
    crate::report::ensure_physical(&report)?;
    Ok(Simulated {
        report,
        plot,
        jumps: result.stats.jumps().to_vec(),
        profile: run.profile,
    })
}

/// Attaches the cam's measured or actual profile to `run`, if the spec asks for one, and
/// returns its report.
fn attach_profile(run: &mut RunSpec, cam: &Cam) -> Result<Option<ProfileReport>> {
    let profile = match cam {
        Cam::Theoretical => None,
        Cam::Measured { profile, name } => {
            let (dev, stats) = profile
                .profile(&run.design)
                .map_err(|e| anyhow::anyhow!("{name}: {e:#}"))?;
            Some((dev, ProfileReport::Measured(stats)))
        }
        Cam::Actual(actual) => {
            let (dev, stats) = crate::actual::build_profile(&run.design, actual, 0)?;
            Some((dev, ProfileReport::Actual(stats)))
        }
    };
    let profile_report = profile.as_ref().map(|p| p.1.clone());
    run.profile = profile.map(|p| Arc::new(p.0));
    Ok(profile_report)
}

/// No rows: [`report`]'s observer.
struct NoRows;

impl Observer<f64> for NoRows {
    fn observe(&mut self, _: &Sample<f64>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// What the run watches: the verdict's watch and the figures on the solver's samples,
/// and the caller's observer on the samples and the grid.
struct RunObserver<'a, O> {
    watch: &'a mut Watch,
    plot: Option<&'a mut PlotData>,
    rows: &'a mut O,
}

impl<O: Observer<f64>> Observer<f64> for RunObserver<'_, O> {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        let _ = self.watch.observe(s);
        if let Some(p) = self.plot.as_mut() {
            p.push(s);
        }
        self.rows.observe(s)
    }
    fn observe_grid(&mut self, s: &Sample<f64>, kind: GridPointKind) -> ControlFlow<()> {
        self.rows.observe_grid(s, kind)
    }
}
