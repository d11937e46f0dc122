//! Running the core's model from the host: dispatch to the run's scene type (the one
//! list of scenes the host runs, [`with_model`]), collect statistics, samples for CSV
//! and plots, and time the run.

use std::ops::ControlFlow;
use std::time::Instant;

use anyhow::{bail, Context, Result};
use camsim_core::{
    jump_verdict, period_name, simulate, simulate_on_grid, AngleGrid, Both, CamModel, Design,
    DeviatedLift, DofSet, FollowerModel, JumpWatch, LiftProfile, Observer, ResponseStats, Sample,
    Scene, SceneId, SceneVisitor, SegmentKind, SolverSettings, SolverStats,
};
use std::sync::Arc;

use crate::units::{Acceleration, Force, Length, Speed, Stress, Torque};

/// Knots of the host's actual-cam deviation spline: one revolution at down to 0.1°.
pub const PROFILE_KNOTS: usize = 3601;

/// An actual cam on the host: the program plus a deviation spline (see camsim-core's
/// `lift` module).
pub type HostDeviation = DeviatedLift<f64, PROFILE_KNOTS>;
use serde::Serialize;

/// Which parts of the model a run keeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Dofs {
    /// Keep the horizontal motion (x1, x2, x3).
    pub horizontal: bool,
    /// The follower's model (full, or a reduced one with quasi-static DOFs).
    pub follower: FollowerModel,
}

impl Dofs {
    /// The translational DOFs kept.
    pub fn set(self) -> DofSet {
        if self.horizontal {
            DofSet::ALL
        } else {
            DofSet::VERTICAL
        }
    }
}

/// Everything a simulation needs.
#[derive(Clone, Debug)]
pub struct RunSpec {
    /// The model's parameters.
    pub design: Design<f64>,
    /// Which DOFs to keep.
    pub dofs: Dofs,
    /// Solver settings.
    pub solver: SolverSettings<f64>,
    /// Revolutions to simulate.
    pub revolutions: u32,
    /// The actual cam's deviation from the program (None: the theoretical cam).
    pub profile: Option<Arc<HostDeviation>>,
    /// What the verdict judges against: the scene's `[limits]` (the defaults without
    /// one); `run --allowable-stress` and `--pressure-angle-limit` override them.
    pub limits: camsim_scene_file::Limits,
    /// The return spring as a part (`[design.spring]`; None: the wire-and-coil model's
    /// spring of the design's rate). `--spring-rate` drops it.
    pub spring: Option<camsim_scene_file::spring::SpringPart>,
    /// The scene gave its drive as a `[design.drive.motor]` table: the drive's messages
    /// name that table.
    pub motor_table: bool,
    /// The drive is given (the reference design's, the thesis's measured machine, or one
    /// the scene names); false when a scene names none and inherits it: the verdict then
    /// warns on a cam-speed swing past the limit (docs/MODEL.md §5.17).
    pub drive_given: bool,
}

impl RunSpec {
    /// The reference design, all DOFs, default solver settings, 3 revolutions.
    pub fn reference() -> Self {
        Self {
            design: Design::reference(),
            dofs: Dofs {
                horizontal: true,
                follower: FollowerModel::Full,
            },
            solver: SolverSettings::reference(),
            revolutions: 3,
            profile: None,
            limits: camsim_scene_file::Limits::default(),
            spring: None,
            motor_table: false,
            drive_given: true,
        }
    }
}

/// Why a regulated drive may stall, for the refusal of a run whose cam stopped: the
/// torque the return spring alone asks of the cam, K_rs (δ_rs + y) y'(θ) at its largest
/// over the program (quasi-static: no inertia, no friction), against the drive's torque
/// limit. None for the ideal drives (they cannot stall).
pub fn stall_hint(design: &Design<f64>) -> Option<String> {
    let camsim_core::DriveLaw::Regulated { t_max, .. } = design.drive else {
        return None;
    };
    let n = 3600;
    let (mut peak, mut at) = (0.0_f64, 0.0_f64);
    for i in 0..n {
        let th = std::f64::consts::TAU * f64::from(i) / f64::from(n);
        let l = design.program.follower(th);
        let t = design.k_rs * (design.delta_rs + l.y) * l.dy;
        if t > peak {
            (peak, at) = (t, th.to_degrees());
        }
    }
    let spring = format!(
        "the return spring (K_rs = {} lb/in: --spring-rate, design.spring_rate_lb_per_in) alone takes up to {peak:.0} lb in of cam torque (at {at:.1} deg, K_rs (delta_rs + y) dy/dtheta)",
        design.k_rs
    );
    let drive = format!(
        "the drive's torque limit of {t_max:.0} lb in (design.drive.regulated.t_max_lb_in, or torque_limit_lb_in of [design.drive.motor])"
    );
    Some(if peak > t_max {
        format!("{spring}, more than {drive}: a softer spring or a stronger drive")
    } else {
        format!(
            "{spring}, {:.0} % of {drive}; with the follower's inertia and friction the drive runs out: a softer spring, a lower speed or a stronger drive",
            100.0 * peak / t_max
        )
    })
}

/// What a caller does with the model of a run's scene ([`with_model`] builds it).
pub trait ModelTask {
    /// What the task returns.
    type Output;
    /// Runs the task on the model of scene `S` (`N = S::N`) riding on the lift `P`.
    fn run<S: Scene, const N: usize, P: LiftProfile<f64>>(
        self,
        model: &CamModel<f64, S, N, P>,
    ) -> Result<Self::Output>;
}

/// Builds the model of `spec`'s scene (its drive kind and DOFs) and runs `task` on it.
///
/// The scene comes from camsim-core's one list (`SceneId`, defined with the scene types
/// by `scenes!`): a new scene needs nothing here.
pub fn with_model<K: ModelTask>(spec: &RunSpec, task: K) -> Result<K::Output> {
    struct Build<'a, K> {
        spec: &'a RunSpec,
        task: K,
    }
    impl<K: ModelTask> SceneVisitor for Build<'_, K> {
        type Output = Result<K::Output>;
        fn visit<S: Scene, const N: usize>(self) -> Self::Output {
            let design = self.spec.design.clone();
            match &self.spec.profile {
                Some(profile) => self.task.run(&CamModel::<f64, S, N, _>::with_profile(
                    design,
                    profile.as_ref(),
                )?),
                None => self.task.run(&CamModel::<f64, S, N>::new(design)?),
            }
        }
    }
    let drive = spec.design.drive.kind();
    let dofs = spec.dofs.set();
    let quasi = spec.dofs.follower.quasi_static();
    if let Some(id) = SceneId::find(drive, dofs, quasi) {
        return id.visit(Build { spec, task });
    }
    if spec.dofs.follower != FollowerModel::Full {
        if spec.dofs.horizontal {
            bail!(
                "follower {}: a reduced follower needs the vertical scene (no horizontal motion)",
                spec.dofs.follower.name()
            );
        }
        bail!(
            "follower {}: reduced followers are built for the regulated drive only (this design's drive is {drive:?})",
            spec.dofs.follower.name()
        );
    }
    bail!("no scene with a {drive:?} drive and {} DOFs", dofs.name())
}

/// The scene of a run: its degrees of freedom and state length.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneSize {
    /// Degrees of freedom (11 for the full model).
    pub dofs: usize,
    /// State length.
    pub states: usize,
}

/// Statistics of a run (up to 16 revolutions of up to 8 periods, 1024 jump intervals).
pub type Stats = ResponseStats<f64, 16, 8, 1024>;

/// The outcome of one simulation.
pub struct RunResult {
    /// Per-period statistics.
    pub stats: Stats,
    /// Solver counters.
    pub solver: SolverStats,
    /// Wall-clock time of the simulation, ms.
    pub wall_ms: f64,
    /// The preload F_p, lb.
    pub preload: f64,
    /// The scene that ran.
    pub scene: SceneSize,
}

/// Runs a simulation, feeding `extra` every sample too.
pub fn run<O: Observer<f64>>(spec: &RunSpec, extra: &mut O) -> Result<RunResult> {
    run_on_grid(spec, extra, AngleGrid::segment_starts())
}

/// [`run`] with `extra` fed the samples on the cam-angle grid `grid` as well
/// ([`Observer::observe_grid`]). The statistics close each period at its segment start
/// (every grid has them), whatever else the grid holds; the steps, the statistics and
/// `extra`'s solver samples do not depend on `grid`.
pub fn run_on_grid<O: Observer<f64>>(
    spec: &RunSpec,
    extra: &mut O,
    grid: AngleGrid<f64>,
) -> Result<RunResult> {
    anyhow::ensure!(
        (1..=16).contains(&spec.revolutions),
        "revolutions = {}: must be between 1 and 16",
        spec.revolutions
    );
    struct Simulate<'a, O> {
        spec: &'a RunSpec,
        stats: &'a mut Stats,
        extra: &'a mut O,
        grid: AngleGrid<f64>,
    }
    impl<O: Observer<f64>> ModelTask for Simulate<'_, O> {
        type Output = (SolverStats, f64, SceneSize);
        fn run<S: Scene, const N: usize, P: LiftProfile<f64>>(
            self,
            m: &CamModel<f64, S, N, P>,
        ) -> Result<Self::Output> {
            let spec = self.spec;
            let s = simulate_on_grid(
                m,
                &spec.solver,
                spec.revolutions,
                self.grid,
                &mut Both(self.stats, self.extra),
            )
            .map_err(|e| {
                let stalled = matches!(
                    e,
                    camsim_core::Error::OutOfModel {
                        limit: camsim_core::ModelLimit::CamSpeed,
                        ..
                    } | camsim_core::Error::SimulationFailed {
                        failure: camsim_core::SimFailure::Stalled,
                        ..
                    }
                );
                match stall_hint(&spec.design).filter(|_| stalled) {
                    Some(hint) => anyhow::anyhow!("simulation failed: {e}. Why: {hint}"),
                    None => anyhow::Error::new(e).context("simulation failed"),
                }
            })?;
            let l = S::LAYOUT;
            let size = SceneSize {
                dofs: l.degrees_of_freedom(),
                states: l.states(),
            };
            Ok((s, m.preload(), size))
        }
    }
    let mut stats = Stats::new(spec.design.omega0);
    let t0 = Instant::now();
    let (solver, preload, scene) = with_model(
        spec,
        Simulate {
            spec,
            stats: &mut stats,
            extra,
            grid,
        },
    )?;
    let wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    Ok(RunResult {
        stats,
        solver,
        wall_ms,
        preload,
        scene,
    })
}

/// An observer that does nothing.
pub struct Nothing;
impl Observer<f64> for Nothing {
    fn needs_stress(&self) -> bool {
        false
    }
    fn observe(&mut self, _: &Sample<f64>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// The name of each period of the design's program (dwell_low, rise, dwell_high, return).
pub fn period_names(design: &Design<f64>) -> Vec<&'static str> {
    let mut level = 0.0;
    design
        .program
        .segments()
        .iter()
        .map(|s| {
            let n = period_name(s.kind, level > 0.0);
            match s.kind {
                SegmentKind::Rise(_) => level += s.lift,
                SegmentKind::Return(_) => level -= s.lift,
                SegmentKind::Dwell => {}
            }
            n
        })
        .collect()
}

/// One row of the per-period table (the JSON `per_period` entries; each measure's key
/// names its unit, `rms_displacement_in`, `contact_force_min_lb`).
#[derive(Clone, Debug, Serialize)]
pub struct PeriodRow {
    /// Revolution from 1.
    pub revolution: u32,
    /// Period name.
    pub period: &'static str,
    /// RMS displacement deviation, in.
    pub rms_displacement: Length,
    /// RMS velocity deviation, in/s.
    pub rms_velocity: Speed,
    /// RMS acceleration deviation, in/s².
    pub rms_acceleration: Acceleration,
    /// Average output torque, lb·in.
    pub torque_avg: Torque,
    /// Largest output torque, lb·in.
    pub torque_max: Torque,
    /// Smallest output torque, lb·in.
    pub torque_min: Torque,
    /// Smallest contact force, lb.
    pub contact_force_min: Force,
    /// Largest contact force, lb.
    pub contact_force_max: Force,
    /// Average contact force, lb.
    pub contact_force_avg: Force,
    /// Largest Hertz stress, psi.
    pub contact_stress_max: Stress,
    /// AORD of the motor speed.
    pub aord_motor: f64,
    /// AORD of the coupling speed.
    pub aord_coupling: f64,
    /// AORD of the cam speed.
    pub aord_cam: f64,
    /// Whether the follower jumped in this period.
    pub jump: bool,
}

/// The per-period rows of every revolution.
pub fn period_rows(design: &Design<f64>, stats: &Stats) -> Vec<PeriodRow> {
    let names = period_names(design);
    let mut rows = Vec::new();
    for rev in 1..=stats.revolutions() {
        for (i, name) in names.iter().enumerate() {
            if let Some(p) = stats.period(rev, i).filter(|p| p.samples > 0) {
                rows.push(PeriodRow {
                    revolution: rev,
                    period: name,
                    rms_displacement: Length::inch(p.rms_displacement()),
                    rms_velocity: Speed::inch(p.rms_velocity()),
                    rms_acceleration: Acceleration::inch(p.rms_acceleration()),
                    torque_avg: Torque::inch(p.torque_avg()),
                    torque_max: Torque::inch(p.torque_max),
                    torque_min: Torque::inch(p.torque_min),
                    contact_force_min: Force::inch(p.force_min),
                    contact_force_max: Force::inch(p.force_max),
                    contact_force_avg: Force::inch(p.force_avg()),
                    contact_stress_max: Stress::inch(p.stress_max),
                    aord_motor: p.aord_motor(),
                    aord_coupling: p.aord_coupling(),
                    aord_cam: p.aord_cam(),
                    jump: p.jump,
                });
            }
        }
    }
    rows
}

/// Whether the follower separates from the cam in steady state (revolution >= 2) at `rpm`.
/// A simulation that fails after the follower has left the cam counts as separating; one
/// that fails with the follower on the cam is an error.
///
/// "Fails" includes the model leaving its valid range ([`camsim_core::Error::OutOfModel`],
/// docs/MODEL.md §3.20): far above the onset the follower leaves the cam in revolution 1
/// and is thrown into its slide bearing, or lands with a penetration Hertz's theory does
/// not cover; that is separation. The same error before any separation (a shaft twisted
/// beyond linear torsion with the follower on the cam, say) ends the search: the model
/// cannot say whether the follower would separate there.
pub fn jumps_at(spec: &RunSpec, rpm: f64) -> Result<bool> {
    let mut s = spec.clone();
    s.design.set_speed_rpm(rpm)?;
    struct Run<'a>(&'a RunSpec, f64);
    impl ModelTask for Run<'_> {
        type Output = bool;
        fn run<S: Scene, const N: usize, P: LiftProfile<f64>>(
            self,
            m: &CamModel<f64, S, N, P>,
        ) -> Result<bool> {
            let (s, rpm) = (self.0, self.1);
            // Only the contact flag on: no statistics, no contact stress. The rule is
            // core's (docs/MODEL.md): a failure after any separation is a jump.
            let mut watch = JumpWatch::new();
            let run = simulate(m, &s.solver, s.revolutions.max(2), &mut watch);
            jump_verdict(run, &watch)
                .map(|v| v.jumped())
                .with_context(|| format!("simulation at {rpm:.1} rpm failed"))
        }
    }
    with_model(&s, Run(&s, rpm))
}

/// How far the last revolution differs from the one before: the largest change of a
/// per-period statistic (RMS deviations, average torque and contact force), relative to
/// that statistic's largest magnitude over the periods of both revolutions.
#[derive(Clone, Debug, Serialize)]
pub struct SteadyCheck {
    /// The two revolutions compared.
    pub compared: [u32; 2],
    /// Largest relative change.
    pub max_rel_change: f64,
    /// Which statistic (period.name).
    pub statistic: String,
}

/// Compares the last two revolutions of a run (None with fewer than two).
pub fn steady_check(rows: &[PeriodRow]) -> Option<SteadyCheck> {
    let last = rows.iter().map(|r| r.revolution).max()?;
    if last < 2 {
        return None;
    }
    Some(steady_check_between(rows, [last - 1, last]))
}

/// The comparison of every pair of consecutive revolutions of a run, the first pair first
/// (empty with fewer than two revolutions).
pub fn steady_checks(rows: &[PeriodRow]) -> Vec<SteadyCheck> {
    let last = rows.iter().map(|r| r.revolution).max().unwrap_or(0);
    (2..=last)
        .map(|b| steady_check_between(rows, [b - 1, b]))
        .collect()
}

/// The statistics the steady-state check compares, each with the floor of its scale.
type Stat = fn(&PeriodRow) -> f64;
const STEADY_STATS: [(&str, Stat, f64); 5] = [
    ("rms_displacement", |r| r.rms_displacement.in_inch(), 1e-6),
    ("rms_velocity", |r| r.rms_velocity.in_inch(), 1e-3),
    ("rms_acceleration", |r| r.rms_acceleration.in_inch(), 1.0),
    ("torque_avg", |r| r.torque_avg.in_inch(), 1e-2),
    ("contact_force_avg", |r| r.contact_force_avg.in_inch(), 1e-2),
];

/// The floor of the scale of a statistic the steady-state check compares (its name as in
/// [`SteadyCheck::statistic`] after the period), or None for another name.
pub fn steady_floor(stat: &str) -> Option<f64> {
    STEADY_STATS
        .iter()
        .find(|(n, _, _)| *n == stat)
        .map(|(_, _, f)| *f)
}

/// Compares revolution `pair[1]` with `pair[0]`.
pub fn steady_check_between(rows: &[PeriodRow], pair: [u32; 2]) -> SteadyCheck {
    let [first, last] = pair;
    let mut worst = SteadyCheck {
        compared: pair,
        max_rel_change: 0.0,
        statistic: String::new(),
    };
    // Each statistic's change is measured against its largest magnitude over the periods
    // of the two revolutions (the scale the solver's absolute error lives on), so a period
    // where a statistic is tiny (a dwell's velocity deviation) does not read as unsteady.
    let both = || {
        rows.iter()
            .filter(move |r| r.revolution == last || r.revolution == first)
    };
    for (name, get, floor) in STEADY_STATS {
        let scale = both().map(|r| get(r).abs()).fold(floor, f64::max);
        for b in rows.iter().filter(|r| r.revolution == last) {
            let Some(a) = rows
                .iter()
                .find(|r| r.revolution == first && r.period == b.period)
            else {
                continue;
            };
            let rel = (get(a) - get(b)).abs() / scale;
            if rel > worst.max_rel_change {
                worst.max_rel_change = rel;
                worst.statistic = format!("{}.{name}", b.period);
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(revolution: u32, period: &'static str, rms_velocity: f64) -> PeriodRow {
        PeriodRow {
            revolution,
            period,
            rms_displacement: Length::default(),
            rms_velocity: Speed::inch(rms_velocity),
            rms_acceleration: Acceleration::default(),
            torque_avg: Torque::default(),
            torque_max: Torque::default(),
            torque_min: Torque::default(),
            contact_force_min: Force::default(),
            contact_force_max: Force::default(),
            contact_force_avg: Force::default(),
            contact_stress_max: Stress::default(),
            aord_motor: 0.0,
            aord_coupling: 0.0,
            aord_cam: 0.0,
            jump: false,
        }
    }

    #[test]
    fn steady_check_scales_each_statistic_by_its_largest_period() {
        // A dwell's velocity deviation 0.01 -> 0.02 in/s next to a rise's steady 2 in/s:
        // the change is 0.01 against a scale of 2, i.e. 5e-3.
        let rows = [
            row(1, "dwell", 0.01),
            row(1, "rise", 2.0),
            row(2, "dwell", 0.02),
            row(2, "rise", 2.0),
        ];
        let c = steady_check(&rows).unwrap();
        assert_eq!(c.compared, [1, 2]);
        assert!(
            (c.max_rel_change - 0.005).abs() < 1e-15,
            "{}",
            c.max_rel_change
        );
        assert_eq!(c.statistic, "dwell.rms_velocity");
        // The rise itself changing by 10 % is 10 % of the scale (2.2).
        let rows = [row(1, "rise", 2.0), row(2, "rise", 2.2)];
        let c = steady_check(&rows).unwrap();
        assert!((c.max_rel_change - 0.2 / 2.2).abs() < 1e-15);
    }
}
