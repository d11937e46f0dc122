//! `camsim montecarlo`: many actual cams, in parallel, reproducible bit for bit. The
//! command line and its outputs; the study is [`crate::study::montecarlo`] (measured by
//! [`crate::study::montecarlo::measure()`]), its histograms [`crate::plot::montecarlo`].

use std::io::Write;
use std::path::PathBuf;

use anyhow::{bail, Result};

pub use crate::args::{OutputArgs, StudyArgs};
use crate::output::{AtomicDir, AtomicFile, DirTarget, Plan};
use crate::plot::montecarlo::PLOT_FILES;
pub use crate::study::montecarlo::MonteCarloOutcome as Outcome;
pub use crate::study::montecarlo::*;
use crate::units::Units;

mod options;

pub use options::{Args, MergeArgs, Sub};

/// Runs what `args` ask for (a study, a shard or a merge) and writes its files (the
/// figures in `units`).
pub fn execute(args: &Args, units: Units) -> Result<Outcome> {
    if let Some(Sub::Merge(m)) = &args.merge {
        return merge(&m.files, &m.output, units).map(|r| Outcome::Study(Box::new(r)));
    }
    args.study.actual.refuse_actual_flag("montecarlo")?;
    let study = args
        .study
        .study()?
        .with_levels(args.two_level, args.study.scene.follower.is_some())?;
    let scene: Vec<PathBuf> = args.study.scene.scene.iter().cloned().collect();
    let (out_file, plot_target) = outputs(
        &args.output,
        ("scene file", &scene),
        args.out.as_ref(),
        args.shard,
    )?;
    let spec = Spec {
        study,
        shard: args.shard,
        threads: threads(args.threads),
        allow_long: args.allow_long,
    };
    let measured = crate::study::montecarlo::measure(&spec)?;
    let plots = match (plot_target, &measured.summary) {
        (Some(t), Some(_)) => Some(figures(t, &measured, units)?),
        _ => None,
    };
    if let Some(mut f) = out_file {
        serde_json::to_writer(&mut f, &measured.shard_file()?)?;
        f.write_all(b"\n")?;
        f.commit()?;
    }
    if let Some(p) = plots {
        p.commit()?;
    }
    Ok(measured.report(args.out.clone().unwrap_or_default()))
}

/// Every output checked before any sample runs: the inputs (`what`, `files`), the `--out`
/// file, its temporary already open (a name the file system refuses fails now, not after
/// the whole study), and the `--plot` directory.
fn outputs(
    out: &OutputArgs,
    (what, files): (&str, &[PathBuf]),
    file: Option<&PathBuf>,
    shard: Option<Shard>,
) -> Result<(Option<AtomicFile>, Option<DirTarget>)> {
    let mut plan = Plan::new(out.force);
    for f in files {
        plan.input(what, f);
    }
    let out_target = file.map(|p| plan.file("--out", p)).transpose()?;
    if out.plot.is_some() && shard.is_some() {
        bail!("--plot draws a whole study: give it to `merge`, not to a shard")
    }
    let plot = out.plot.as_ref();
    let plot_target = plot
        .map(|d| plan.dir("--plot", d, &PLOT_FILES))
        .transpose()?;
    Ok((out_target.map(|t| t.open()).transpose()?, plot_target))
}

/// Draws the study's histograms into `target`'s temporary directory, in `units` (the
/// caller commits it).
fn figures(target: DirTarget, m: &Measured, units: Units) -> Result<AtomicDir> {
    let mut dir = target.open()?;
    for (file, fig) in crate::plot::montecarlo::figures(&m.stats, m.revolution, units) {
        crate::figure::draw(&mut dir, file, &fig, units)?;
    }
    Ok(dir)
}

/// Merges shard files into the result of their study (every sample exactly once),
/// drawing its histograms (`--plot`, in `units`).
pub fn merge(files: &[PathBuf], out: &OutputArgs, units: Units) -> Result<MonteCarloReport> {
    let (_, plot_target) = outputs(out, ("shard file", files), None, None)?;
    let measured = crate::study::montecarlo::merge(files)?;
    if let Some(t) = plot_target {
        figures(t, &measured, units)?.commit()?;
    }
    measured.study_report()
}

/// Runs the command.
pub fn run(args: Args, units: Units) -> Result<()> {
    let json = match &args.merge {
        Some(Sub::Merge(m)) => m.output.json,
        None => args.output.json,
    };
    match execute(&args, units)? {
        Outcome::Study(r) => crate::report::print(r.as_ref(), json, units),
        Outcome::Shard(r) => crate::report::print(&r, json, units),
    }
}
