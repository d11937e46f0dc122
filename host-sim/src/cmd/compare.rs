//! `camsim compare`: the study of VI.4.2. Every motion law (the same law for every
//! rise and return, the scene otherwise unchanged) runs on the theoretical cam with
//! the system's flexibility, and on one actual cam (sample 0 of `--seed`, the same
//! interval for every law); cycle I (revolution 1, from the thesis's start) and cycle
//! II (revolution 2) are measured as docs/MODEL.md §9 defines, and every law is ranked
//! in every column.
//!
//! The runs are independent and run in parallel; each is deterministic, so the
//! result does not depend on `--threads`.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::{anyhow, Context, Result};
use camsim_core::{MotionLaw, Sample, SegmentKind, Start};
use rayon::prelude::*;
use serde::Serialize;

use crate::actual::{self, ActualArgs, ProfileStats};
use crate::args::OutputArgs;
use crate::output::{AtomicDir, Plan};
use crate::report::Report;
use crate::sim::{self, PeriodRow, RunSpec};
use camsim_scene_file::units::Unit;

use crate::units;

/// Command-line options of `camsim compare`.
#[derive(clap::Args, Debug, Clone, Default)]
#[command(mut_arg("actual", |a| a.hide(true)))]
#[command(mut_arg("plot", |a| a.help("Write PNG plots (the rankings, and the responses of a few laws) into DIR")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Scene file whose program's rises and returns take each law in turn (the
    /// reference design if omitted).
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default: the scene's, 800 for the reference).
    #[arg(long, allow_negative_numbers = true, value_parser = crate::args::rpm)]
    pub rpm: Option<f64>,
    /// Quick mode for CI: the vertical scene (the horizontal motion does not feed back
    /// into the vertical chain or the drive; docs/MODEL.md §9).
    #[arg(long)]
    pub quick: bool,
    /// Worker threads (default: every core). The result does not depend on it.
    #[arg(long, value_parser = crate::args::whole_u32::<1, 1024>)]
    pub threads: Option<u32>,
    /// The actual cam (sample 0 of --seed): always run beside the theoretical one.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// One period of one cam: cycle I and cycle II acceleration RMS, cycle II's inertial
/// responses and jump.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LawPeriod {
    /// Period name.
    pub period: String,
    /// Acceleration RMS deviation from the theoretical (perfect, rigid) response in
    /// cycle I (revolution 1), in/s².
    pub acc_rms_cycle1: f64,
    /// The same in cycle II (revolution 2), in/s².
    pub acc_rms_cycle2: f64,
    /// Cycle II: average output torque, lb·in.
    pub torque_avg: f64,
    /// Cycle II: largest output torque, lb·in.
    pub torque_max: f64,
    /// Cycle II: smallest output torque, lb·in.
    pub torque_min: f64,
    /// Cycle II: smallest contact force, lb.
    pub contact_force_min: f64,
    /// Cycle II: largest contact force, lb.
    pub contact_force_max: f64,
    /// Cycle II: largest Hertz stress, psi.
    pub contact_stress_max: f64,
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
    pub sensitivity: f64,
    /// Σ over the rises and returns of (RMS_I − RMS_II)/RMS_I (VI.4.2).
    pub shock_index: f64,
    /// Cycle II: average output torque over the rise(s) (the largest), lb·in.
    pub torque_avg_rise: f64,
    /// Cycle II: average output torque over the return(s) (the most negative: the
    /// power fed back), lb·in.
    pub torque_avg_return: f64,
    /// Cycle II: largest |output torque|, lb·in.
    pub torque_max: f64,
    /// Cycle II: smallest contact force, lb.
    pub contact_force_min: f64,
    /// Cycle II: largest contact force, lb.
    pub contact_force_max: f64,
    /// Cycle II: largest Hertz stress, psi.
    pub contact_stress_max: f64,
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
    pub sensitivity_to_tolerance: f64,
    /// The actual cam's profile.
    pub profile: ProfileStats,
}

/// The columns every law is ranked in, and whether a smaller value ranks better.
pub const RANKED: [(&str, bool); 8] = [
    ("sensitivity_to_flexibility", true),
    ("sensitivity_to_tolerance", true),
    ("shock_index", true),
    ("torque_avg", true),
    ("torque_max", true),
    ("contact_force_min", false),
    ("contact_force_max", true),
    ("contact_stress_max", true),
];

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
    /// The value of every ranked column ([`RANKED`]).
    pub values: Ranks<f64>,
    /// The law's rank (1 best) in every ranked column, and overall (the laws that hold
    /// contact on the theoretical cam first, then by the sum of the ranks).
    pub ranks: Ranks<usize>,
}

/// One value per ranked column ([`RANKED`]) and an overall one.
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
    /// The value of column `name` ([`RANKED`] or `overall`).
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

    fn set(&mut self, name: &str, v: T) {
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

/// Ranks `values` (one per law) from 1: ascending when `smaller_better`, else
/// descending; ties keep the laws' order, so the ranks are always a permutation.
pub fn rank(values: &[f64], smaller_better: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| {
        let o = values[a].total_cmp(&values[b]);
        let o = if smaller_better { o } else { o.reverse() };
        o.then(a.cmp(&b))
    });
    let mut ranks = vec![0; values.len()];
    for (r, &i) in order.iter().enumerate() {
        ranks[i] = r + 1;
    }
    ranks
}

/// The scene with `law` for every rise and return.
fn with_law(base: &RunSpec, law: MotionLaw) -> Result<RunSpec> {
    let mut spec = base.clone();
    let mut segs: Vec<_> = spec.design.program.segments().to_vec();
    for s in &mut segs {
        match &mut s.kind {
            SegmentKind::Rise(l) | SegmentKind::Return(l) => *l = law,
            SegmentKind::Dwell => {}
        }
    }
    spec.design.program = camsim_core::CamProgram::new(&segs)?;
    spec.design.validate()?;
    Ok(spec)
}

/// The kind of each segment of the program (rise, return or dwell), in the order of its
/// periods.
fn segment_kinds(spec: &RunSpec) -> Vec<SegmentKind> {
    spec.design
        .program
        .segments()
        .iter()
        .map(|s| s.kind)
        .collect()
}

/// The measures of one run's revolutions 1 and 2.
fn cam_study(spec: &RunSpec, rows: &[PeriodRow], steps: u32) -> Result<CamStudy> {
    let names = sim::period_names(&spec.design);
    let kinds = segment_kinds(spec);
    let row = |rev: u32, k: usize| {
        rows.iter()
            .filter(|r| r.revolution == rev)
            .nth(k)
            .filter(|r| r.period == names[k])
            .ok_or_else(|| anyhow!("revolution {rev} has no {} period", names[k]))
    };
    let mut per_period = Vec::new();
    let (mut sens, mut shock) = (0.0, 0.0);
    let (mut t_rise, mut t_return) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut t_max, mut f_min, mut f_max, mut s_max) =
        (0.0f64, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let mut jump = false;
    for (k, name) in names.iter().enumerate() {
        let (one, two) = (row(1, k)?, row(2, k)?);
        sens += two.rms_acceleration;
        match kinds[k] {
            SegmentKind::Rise(_) => {
                shock += (one.rms_acceleration - two.rms_acceleration) / one.rms_acceleration;
                t_rise = t_rise.max(two.torque_avg);
            }
            SegmentKind::Return(_) => {
                shock += (one.rms_acceleration - two.rms_acceleration) / one.rms_acceleration;
                t_return = t_return.min(two.torque_avg);
            }
            SegmentKind::Dwell => {}
        }
        t_max = t_max.max(two.torque_max.abs()).max(two.torque_min.abs());
        f_min = f_min.min(two.contact_force_min);
        f_max = f_max.max(two.contact_force_max);
        s_max = s_max.max(two.contact_stress_max);
        jump |= two.jump;
        per_period.push(LawPeriod {
            period: name.to_string(),
            acc_rms_cycle1: one.rms_acceleration,
            acc_rms_cycle2: two.rms_acceleration,
            torque_avg: two.torque_avg,
            torque_max: two.torque_max,
            torque_min: two.torque_min,
            contact_force_min: two.contact_force_min,
            contact_force_max: two.contact_force_max,
            contact_stress_max: two.contact_stress_max,
            jump: two.jump,
        });
    }
    let s = CamStudy {
        per_period,
        sensitivity: sens,
        shock_index: shock,
        torque_avg_rise: t_rise,
        torque_avg_return: t_return,
        torque_max: t_max,
        contact_force_min: f_min,
        contact_force_max: f_max,
        contact_stress_max: s_max,
        jump,
        steps,
    };
    for (what, v) in [
        ("sensitivity", s.sensitivity),
        ("shock index", s.shock_index),
        ("rise torque", s.torque_avg_rise),
        ("return torque", s.torque_avg_return),
        ("largest torque", s.torque_max),
        ("smallest contact force", s.contact_force_min),
        ("largest contact force", s.contact_force_max),
        ("largest contact stress", s.contact_stress_max),
    ] {
        anyhow::ensure!(v.is_finite(), "the {what} is {v}");
    }
    Ok(s)
}

/// Simulates `spec` (two revolutions) and measures it.
fn simulate(spec: &RunSpec) -> Result<CamStudy> {
    let r = sim::run(spec, &mut sim::Nothing)?;
    cam_study(
        spec,
        &sim::period_rows(&spec.design, &r.stats),
        r.solver.accepted,
    )
}

/// The scene every law starts from.
fn base_spec(args: &Args) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r)?;
    }
    // Cycle I is measured from the thesis's start (its start-up shock).
    spec.solver.start = Start::Thesis;
    spec.revolutions = 2;
    if args.quick {
        spec.dofs.horizontal = false;
    }
    Ok(spec)
}

/// Runs the study `args` ask for (the plots too, if asked).
pub fn report(args: &Args) -> Result<CompareReport> {
    args.actual.refuse_actual_flag("compare")?;
    let t0 = std::time::Instant::now();
    let base = base_spec(args)?;
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene {
        plan.input("scene file", p);
    }
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &PLOT_FILES)?),
        None => None,
    };
    // One interval for every law: the one the scene's own program gets.
    let mut actual_args = args.actual.resolve(&base.design)?;
    actual_args.actual = true;
    let (intervals, interval_source) = actual::intervals_for(&base.design, &actual_args)?;
    let specs: Vec<(MotionLaw, RunSpec)> = MotionLaw::ALL
        .iter()
        .map(|&l| with_law(&base, l).map(|s| (l, s)))
        .collect::<Result<_>>()?;
    let results = run_every_law(&specs, &actual_args, args.threads)?;
    let (mut laws, not_workable) = law_studies(&base, &specs, results)?;
    anyhow::ensure!(
        !laws.is_empty(),
        "no law is workable: every law's run left the model's valid range (first: {} on the {} cam: {})",
        not_workable.first().map_or("", |n: &NotWorkable| n.name.as_str()),
        not_workable.first().map_or("", |n| n.cam.as_str()),
        not_workable.first().map_or("", |n| n.reason.as_str())
    );
    fill_ranks(&mut laws);
    let rpm = camsim_core::rad_per_s_to_rpm(base.design.omega0);
    if let Some(t) = plot_target {
        let mut dir = t.open()?;
        draw(&mut dir, &laws, &not_workable, &base, &actual_args)?;
        dir.commit()?;
    }
    Ok(CompareReport {
        laws,
        not_workable,
        rpm,
        quick: args.quick,
        seed: args.actual.seed(),
        intervals,
        interval_source,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// Every law's run on the theoretical and on the actual cam (sample 0 of `actual_args`),
/// in parallel on `threads`, in order: law 0 theoretical, law 0 actual, law 1 ...
fn run_every_law(
    specs: &[(MotionLaw, RunSpec)],
    actual_args: &ActualArgs,
    threads: Option<u32>,
) -> Result<Vec<Job>> {
    // Every (law, cam) pair, in order: law 0 theoretical, law 0 actual, law 1 ...
    let jobs: Vec<(usize, bool)> = (0..specs.len())
        .flat_map(|i| [(i, false), (i, true)])
        .collect();
    let pool = crate::study::pool(crate::study::montecarlo::threads(threads))?;
    let bar = crate::study_limits::progress_bar(
        jobs.len() as u64,
        true,
        "{elapsed_precise} [{bar:40}] {pos}/{len} runs (every law, theoretical and actual), eta {eta}",
    );
    let results: Vec<Job> = pool.install(|| {
        jobs.par_iter()
            .map(|&(i, is_actual)| {
                let (law, spec) = &specs[i];
                let run = || -> Job {
                    if !is_actual {
                        return Ok((simulate(spec)?, None));
                    }
                    let (dev, stats) = actual::build_profile(&spec.design, actual_args, 0)?;
                    let mut s = spec.clone();
                    s.profile = Some(Arc::new(dev));
                    Ok((simulate(&s)?, Some(stats)))
                };
                let r = run().with_context(|| {
                    format!(
                        "{} on the {} cam",
                        law.name(),
                        if is_actual { "actual" } else { "theoretical" }
                    )
                });
                bar.inc(1);
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    Ok(results)
}

/// The studies of the workable laws, and the laws whose run on either cam left the
/// model's valid range, from the runs in [`run_every_law`]'s order.
fn law_studies(
    base: &RunSpec,
    specs: &[(MotionLaw, RunSpec)],
    results: Vec<Job>,
) -> Result<(Vec<LawStudy>, Vec<NotWorkable>)> {
    let mut it = results.into_iter();
    let mut laws = Vec::new();
    let mut not_workable = Vec::new();
    for (law, _) in specs {
        let flex = it.next().ok_or_else(|| anyhow!("missing run"))?;
        let cam = it.next().ok_or_else(|| anyhow!("missing run"))?;
        let ((flex, _), (cam, profile)) = match workable(law.name(), flex, cam)? {
            Ok(pair) => pair,
            Err(n) => {
                not_workable.push(n);
                continue;
            }
        };
        let profile = profile.ok_or_else(|| anyhow!("missing profile"))?;
        laws.push(law_study(base, *law, flex, cam, profile)?);
    }
    Ok((laws, not_workable))
}

/// One workable law's study: its runs on the theoretical and the actual cam, the
/// periods it jumps in, and the values it is ranked by.
fn law_study(
    base: &RunSpec,
    law: MotionLaw,
    flex: CamStudy,
    cam: CamStudy,
    profile: ProfileStats,
) -> Result<LawStudy> {
    let names = sim::period_names(&base.design);
    let kinds = segment_kinds(base);
    let jump_in = |rise: bool| {
        cam.per_period.iter().zip(&kinds).any(|(p, k)| {
            p.jump
                && matches!(
                    (k, rise),
                    (SegmentKind::Rise(_), true) | (SegmentKind::Return(_), false)
                )
        })
    };
    debug_assert_eq!(names.len(), cam.per_period.len());
    let sensitivity_to_tolerance = cam.sensitivity - flex.sensitivity;
    anyhow::ensure!(
        sensitivity_to_tolerance.is_finite(),
        "{}: the sensitivity to tolerance is not finite",
        law.name()
    );
    let values = Ranks {
        sensitivity_to_flexibility: flex.sensitivity,
        sensitivity_to_tolerance,
        shock_index: flex.shock_index,
        torque_avg: flex.torque_avg_rise,
        torque_max: flex.torque_max,
        contact_force_min: flex.contact_force_min,
        contact_force_max: flex.contact_force_max,
        contact_stress_max: flex.contact_stress_max,
        overall: 0.0,
    };
    Ok(LawStudy {
        name: law.name().to_string(),
        jump_rise: jump_in(true),
        jump_return: jump_in(false),
        flexibility: flex,
        actual: ActualStudy {
            cam,
            sensitivity_to_tolerance,
            profile,
        },
        values,
        ranks: Ranks::default(),
    })
}

/// One run's study, and the actual cam's profile.
type Run = (CamStudy, Option<ProfileStats>);
type Job = Result<Run>;

/// One law's two runs (theoretical, actual): both, or the law not workable when a run
/// left the model's valid range (the theoretical cam's reason first). Any other failure
/// is an error.
fn workable(
    law: &str,
    flex: Job,
    cam: Job,
) -> Result<std::result::Result<(Run, Run), NotWorkable>> {
    let not = |which: &str, e: anyhow::Error| {
        if !crate::study::sweep::out_of_model(&e) {
            return Err(e);
        }
        Ok(Err(NotWorkable {
            name: law.to_string(),
            cam: which.to_string(),
            reason: format!("{}", e.root_cause()),
        }))
    };
    match (flex, cam) {
        (Ok(f), Ok(c)) => Ok(Ok((f, c))),
        (Err(e), _) => not("theoretical", e),
        (_, Err(e)) => not("actual", e),
    }
}

/// Ranks every law in every column of [`RANKED`], then overall: the laws that hold
/// contact on the theoretical cam in cycle II before those that separate, each group by
/// the sum of its ranks (ties in the laws' order).
pub fn fill_ranks(laws: &mut [LawStudy]) {
    let mut sums = vec![0.0; laws.len()];
    for (col, smaller) in RANKED {
        let v: Vec<f64> = laws
            .iter()
            .map(|l| l.values.get(col).unwrap_or(f64::NAN))
            .collect();
        for (i, r) in rank(&v, smaller).into_iter().enumerate() {
            laws[i].ranks.set(col, r);
            sums[i] += r as f64;
        }
    }
    // The sum is at most 8 · 12 = 96: a separating law's key is above every other's.
    let keys: Vec<f64> = laws
        .iter()
        .zip(&sums)
        .map(|(l, s)| s + if l.flexibility.jump { 1000.0 } else { 0.0 })
        .collect();
    for (i, r) in rank(&keys, true).into_iter().enumerate() {
        laws[i].values.overall = sums[i];
        laws[i].ranks.overall = r;
    }
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args)?, args.output.json, units)
}

/// Column headers of the ranking table.
pub(crate) const HEADERS: [(&str, &str); 9] = [
    ("sensitivity_to_flexibility", "S_flex"),
    ("sensitivity_to_tolerance", "S_tol"),
    ("shock_index", "shock"),
    ("torque_avg", "T_avg"),
    ("torque_max", "T_max"),
    ("contact_force_min", "Fc_min"),
    ("contact_force_max", "Fc_max"),
    ("contact_stress_max", "stress"),
    ("overall", "overall"),
];

impl Report for CompareReport {
    fn text(&self, _units: crate::units::Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        self.write_heading(&mut out);
        self.write_acceleration(&mut out);
        self.write_inertial(&mut out);
        self.write_ranks(&mut out);
        not_workable_text(&mut out, &self.not_workable);
        let _ = writeln!(out, "\nrun time: {:.2} s", self.wall_s);
        out
    }
}

impl CompareReport {
    /// The first lines: the study (speed, model, cycles), the actual cam it drew and the
    /// units of the tables.
    fn write_heading(&self, out: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "camsim compare: every motion law for rise and return at {:.1} rpm, {} model; cycle I = revolution 1 \
             (thesis start), cycle II = revolution 2",
            self.rpm,
            if self.quick { "vertical (--quick)" } else { "full 11-DOF" }
        );
        if let Some(l) = self.laws.first() {
            let p = &l.actual.profile;
            let _ = writeln!(
                out,
                "actual cam: sample 0 of seed {}, tolerances cam {} / roller {} / eccentricity {} {}, {} intervals ({:.4} deg, {}); FPR {}",
                self.seed,
                units::given(units::LENGTH, p.cam_tolerance_in),
                units::given(units::LENGTH, p.roller_tolerance_in),
                units::given(units::LENGTH, p.eccentricity_tolerance_in),
                units::symbol(units::LENGTH),
                p.intervals, p.interval_deg,
                self.interval_source.label(),
                {
                    let (lo, hi) = self.laws.iter().fold((usize::MAX, 0), |(a, b), l| {
                        (a.min(l.actual.profile.fpr), b.max(l.actual.profile.fpr))
                    });
                    if lo == hi { format!("{lo}") } else { format!("{lo}-{hi} (by law)") }
                }
            );
        }
        let _ = writeln!(
            out,
            "units: acceleration RMS {}, torque {}, force {}, stress {} (docs/MODEL.md §9 defines each measure)\n",
            units::label(units::ACCELERATION, "in/s2"),
            units::symbol(units::TORQUE),
            units::symbol(units::FORCE),
            units::symbol(units::STRESS)
        );
    }

    /// The acceleration RMS of each law's periods, cycles I and II, on the theoretical
    /// cam and on the actual one, with its sensitivity, shock index and jumps.
    fn write_acceleration(&self, out: &mut String) {
        use std::fmt::Write;
        let periods: Vec<String> = self
            .laws
            .first()
            .map(|l| {
                l.flexibility
                    .per_period
                    .iter()
                    .map(|p| p.period.clone())
                    .collect()
            })
            .unwrap_or_default();
        for (title, actual) in [
            ("theoretical cam (flexibility alone): acceleration RMS per period, cycle I / cycle II", false),
            ("actual cam (flexibility and tolerance): acceleration RMS per period, cycle I / cycle II", true),
        ] {
            let _ = writeln!(out, "{title}");
            let _ = write!(out, "{:<21}", "law");
            for p in &periods {
                let _ = write!(out, " {:>21}", p);
            }
            let _ = writeln!(
                out,
                " {:>10} {:>7} {:>6}",
                if actual { "S_act" } else { "S_flex" },
                "shock",
                "jumps"
            );
            for l in &self.laws {
                let c = if actual { &l.actual.cam } else { &l.flexibility };
                let _ = write!(out, "{:<21}", l.name);
                for p in &c.per_period {
                    let _ = write!(
                        out,
                        " {:>10}/{:<10}",
                        units::q(units::ACCELERATION, p.acc_rms_cycle1, 1),
                        units::q(units::ACCELERATION, p.acc_rms_cycle2, 1)
                    );
                }
                let jumps: String = c
                    .per_period
                    .iter()
                    .map(|p| if p.jump { 'J' } else { '-' })
                    .collect();
                let _ = writeln!(
                    out,
                    " {:>10} {:>7.3} {:>6}",
                    units::q(units::ACCELERATION, c.sensitivity, 1),
                    c.shock_index,
                    jumps
                );
            }
            let _ = writeln!(out);
        }
    }

    /// The ranks of each law on every measure and overall, best first, with its jumps.
    fn write_ranks(&self, out: &mut String) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "ranks (1 = best; S_tol and the jumps on the actual cam, the rest on the theoretical cam; Fc_min larger is better;\n\
             overall: the laws holding contact on the theoretical cam first, then by the sum of the ranks)"
        );
        let _ = write!(out, "{:<21}", "law");
        for (_, h) in HEADERS {
            let _ = write!(out, " {:>7}", h);
        }
        let _ = writeln!(out, " {:>11}", "jump r/ret");
        let mut order: Vec<&LawStudy> = self.laws.iter().collect();
        order.sort_by_key(|l| l.ranks.overall);
        for l in order {
            let _ = write!(out, "{:<21}", l.name);
            for (c, _) in HEADERS {
                let _ = write!(out, " {:>7}", l.ranks.get(c).unwrap_or(0));
            }
            let yn = |b: bool| if b { "yes" } else { "no" };
            let _ = writeln!(
                out,
                " {:>11}",
                format!("{}/{}", yn(l.jump_rise), yn(l.jump_return))
            );
        }
    }
    /// The inertial responses' tables, cycle II, on the theoretical and the actual cam.
    fn write_inertial(&self, out: &mut String) {
        use std::fmt::Write;
        for (title, actual) in [
            ("inertial responses, cycle II, theoretical cam", false),
            ("inertial responses, cycle II, actual cam", true),
        ] {
            let _ = writeln!(out, "{title}");
            let _ = writeln!(
                out,
                "{:<21} {:>9} {:>9} {:>9} {:>8} {:>8} {:>9}",
                "law", "T_avg_r", "T_avg_ret", "|T|_max", "Fc_min", "Fc_max", "stress"
            );
            for l in &self.laws {
                let c = if actual {
                    &l.actual.cam
                } else {
                    &l.flexibility
                };
                let _ = writeln!(
                    out,
                    "{:<21} {:>9} {:>9} {:>9} {:>8} {:>8} {:>9}",
                    l.name,
                    units::q(units::TORQUE, c.torque_avg_rise, 2),
                    units::q(units::TORQUE, c.torque_avg_return, 2),
                    units::q(units::TORQUE, c.torque_max, 2),
                    units::q(units::FORCE, c.contact_force_min, 2),
                    units::q(units::FORCE, c.contact_force_max, 2),
                    units::q(units::STRESS, c.contact_stress_max, 0)
                );
            }
            let _ = writeln!(out);
        }
    }
}

/// The laws not ranked, each with the reason its run stopped.
fn not_workable_text(out: &mut String, laws: &[NotWorkable]) {
    use std::fmt::Write;
    if laws.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nnot workable (the run left the model's valid range, docs/MODEL.md §3.20; not ranked):"
    );
    for n in laws {
        let _ = writeln!(out, "{:<21} on the {} cam: {}", n.name, n.cam, n.reason);
    }
}

/// The plots `--plot DIR` writes.
pub const PLOT_FILES: [&str; 2] = ["rankings.png", "responses.png"];

/// Revolution-2 samples of one run: (cam angle in degrees, acceleration deviation,
/// contact force).
pub(crate) type Trace = Vec<(f64, f64, f64)>;

fn trace(spec: &RunSpec) -> Result<Trace> {
    let mut out = Vec::new();
    let mut obs = |s: &Sample<f64>| {
        if s.revolution == 2 {
            out.push((
                s.angle_deg,
                s.point.load_acceleration() - s.theory.a,
                s.point.contact_force,
            ));
        }
        std::ops::ControlFlow::Continue(())
    };
    sim::run(spec, &mut obs)?;
    Ok(out)
}

/// A ranked column's quantity and unit on a plot axis (`None`: dimensionless), and
/// which way is better.
pub(crate) fn rank_axis(col: &str) -> (&'static str, Option<Unit>, &'static str) {
    use crate::units::{ACCELERATION, FORCE};
    use camsim_scene_file::units::{STRESS, TORQUE};
    match col {
        "sensitivity_to_flexibility" => (
            "Σ acceleration RMS, theoretical cam",
            Some(ACCELERATION),
            "smaller is better",
        ),
        "sensitivity_to_tolerance" => (
            "Σ acceleration RMS, actual − theoretical",
            Some(ACCELERATION),
            "smaller is better",
        ),
        "shock_index" => ("Σ (RMS_I − RMS_II) / RMS_I", None, "smaller is better"),
        "torque_avg" => (
            "average torque over the rise",
            Some(TORQUE),
            "smaller is better",
        ),
        "torque_max" => ("largest |torque|", Some(TORQUE), "smaller is better"),
        "contact_force_min" => ("smallest contact force", Some(FORCE), "larger is better"),
        "contact_force_max" => ("largest contact force", Some(FORCE), "smaller is better"),
        "contact_stress_max" => ("largest contact stress", Some(STRESS), "smaller is better"),
        _ => (
            "sum of the ranks",
            None,
            "holding contact first, then smaller",
        ),
    }
}

/// The laws whose responses `compare --plot` draws (the two best overall and the
/// reference program's two), each on the theoretical cam and on one actual cam.
fn response_traces(
    laws: &[LawStudy],
    base: &RunSpec,
    actual: &ActualArgs,
) -> Result<Vec<(String, Trace, Trace)>> {
    let mut picks: Vec<usize> = Vec::new();
    let by_rank = |r: usize| laws.iter().position(|l| l.ranks.overall == r);
    for i in [by_rank(1), by_rank(2)].into_iter().flatten().chain(
        ["modified-trapezoidal", "4-5-6-7"]
            .iter()
            .filter_map(|n| laws.iter().position(|l| l.name == *n)),
    ) {
        if !picks.contains(&i) {
            picks.push(i);
        }
    }
    let mut traces = Vec::new();
    for &i in &picks {
        let law = MotionLaw::from_name(&laws[i].name).ok_or_else(|| anyhow!("unknown law"))?;
        let spec = with_law(base, law)?;
        let theo = trace(&spec)?;
        let (dev, _) = actual::build_profile(&spec.design, actual, 0)?;
        let mut s = spec.clone();
        s.profile = Some(Arc::new(dev));
        traces.push((laws[i].name.clone(), theo, trace(&s)?));
    }
    Ok(traces)
}

/// Draws [`PLOT_FILES`]: the rankings, then the responses of the laws
/// [`response_traces`] picks.
fn draw(
    dir: &mut AtomicDir,
    laws: &[LawStudy],
    not_workable: &[NotWorkable],
    base: &RunSpec,
    actual: &ActualArgs,
) -> Result<()> {
    use crate::plot::compare::{rankings, responses};
    let units = units::current();
    crate::figure::draw(dir, PLOT_FILES[0], &rankings(laws, not_workable), units)?;
    let traces = response_traces(laws, base, actual)?;
    crate::figure::draw(dir, PLOT_FILES[1], &responses(&traces), units)
}
