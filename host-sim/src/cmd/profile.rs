//! `camsim profile [SCENE] --out DIR`: the cam as a drawing for the machine shop
//! ([`crate::study::profile`], which holds the study, its report and the report's text,
//! and makes the files' contents). This command reads the arguments into the study's
//! [`Spec`], writes the drawing's files (`--out`: CSVs and a DXF, in the length unit of
//! `--units`) and the program's SVAJ diagram (`--plot DIR`: `svaj.png`), and prints the
//! report.

use std::path::PathBuf;

use anyhow::Result;

use crate::args::ActualArgs;
use crate::args::{positive_length, spec_from, OutputArgs, SceneArgs};
use crate::output::Plan;
pub use crate::study::profile::*;

/// The SVAJ plot (`--plot`).
pub const SVAJ_FILE: &str = "svaj.png";

/// `--every-deg`: a positive step, degrees, that divides 360 into 4 to
/// [`MAX_CURVE_POINTS`] steps (so the rows close the revolution and read back).
pub fn every_deg(s: &str) -> Result<f64, String> {
    let d: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("\"{s}\" is not a number of degrees"))?;
    let steps = 360.0 / d;
    let n = steps.round();
    if !(d.is_finite() && d > 0.0) {
        return Err("must be a positive number of degrees".into());
    }
    if (steps - n).abs() > 1e-9 * n {
        return Err(format!(
            "must divide 360 so that the last step ends at 360 = 0 deg \
             (360/{d} = {steps:.4} steps); e.g. 0.5, 1, 2, 5 or 10"
        ));
    }
    if n < 4.0 || n > MAX_CURVE_POINTS as f64 {
        return Err(format!(
            "must divide 360 into 4 to {MAX_CURVE_POINTS} steps (360/{d} = {n} steps): \
             a step from {:.1} to 90 deg",
            360.0 / MAX_CURVE_POINTS as f64
        ));
    }
    Ok(d)
}

/// Command-line options.
#[derive(clap::Args, Debug, Clone)]
#[command(mut_arg("json", |a| a.help("Print JSON instead of a table")))]
#[command(mut_arg("plot", |a| a.help("Draw the program's lift, velocity, acceleration and jerk against cam angle (svaj.png) into DIR")))]
#[command(mut_arg("force", |a| a.help("Replace existing files in --out and --plot")))]
pub struct Args {
    /// The scene and its overrides (`--rpm` sets the speed of the SVAJ plot).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Write the drawing into DIR: cam.dxf, surface.csv, surface_radius.csv (the format
    /// of `run --measured`), pitch.csv and, with --cutter-radius, cutter.csv.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Radius of the cutter (grinding wheel or end mill), in, or with its unit (6mm):
    /// also write its centre path.
    #[arg(long, value_name = "IN", allow_hyphen_values = true, value_parser = positive_length)]
    pub cutter_radius: Option<f64>,
    /// Largest distance of a chord from the curve, in, or with its unit (0.002mm)
    /// (default 0.0001 in = 0.00254 mm: a fifth of the thesis's cam tolerance).
    #[arg(long, value_name = "IN", allow_hyphen_values = true, value_parser = positive_length)]
    pub chord_error: Option<f64>,
    /// Write the CSVs at a uniform step of DEG degrees instead of the chordal sampling:
    /// surface.csv, pitch.csv and cutter.csv every DEG of cam angle, surface_radius.csv
    /// every DEG of polar angle (as a rotary table or CMM reads the cam). DEG must divide
    /// 360 (0.5, 1, 2, 5 ...) into 4 to 3600 steps: the last step ends at 360 = 0 deg,
    /// the first row. The DXF keeps the chordal sampling (its chords stay within
    /// --chord-error).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, value_parser = every_deg)]
    pub every_deg: Option<f64>,
    /// A simulated machined cam (`--actual` and its options) instead of the theoretical.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Computes the drawing in the length unit of `units` (inch: in; si: mm) and writes
/// what `args` asks for.
pub fn report(args: &Args, units: crate::units::Units) -> Result<ProfileReport> {
    let run = spec_from(&args.scene)?;
    args.actual.ensure_actual_if_options()?;
    let spec = Spec {
        design: run.design,
        actual: args.actual.cams(),
        cutter_radius_in: args.cutter_radius,
        // The options are read in inch (their parser converts a value given in mm).
        chord_error_in: args.chord_error.unwrap_or(DEFAULT_CHORD_ERROR_IN),
        every_deg: args.every_deg,
    };
    let mut drawing = drawing(&spec, units)?;
    // Nothing is written for a result with a non-finite number.
    crate::report::ensure_finite(&drawing.report)?;
    drawing.report.files = write_outputs(args, &drawing, units)?;
    Ok(drawing.report)
}

/// Writes `--out`'s drawing and `--plot`'s SVAJ diagram (both checked before either is
/// written); the paths written.
fn write_outputs(
    args: &Args,
    drawing: &Drawing,
    units: crate::units::Units,
) -> Result<Vec<String>> {
    let mut files = Vec::new();
    let mut plan = Plan::new(args.output.force);
    if let Some(p) = &args.scene.scene {
        plan.input("scene file", p);
    }
    let mut names = vec![SURFACE_RADIUS_FILE, SURFACE_FILE, PITCH_FILE, DXF_FILE];
    if args.cutter_radius.is_some() {
        names.push(CUTTER_FILE);
    }
    let out_target = match &args.out {
        // Replaced as a whole: a cutter path of an earlier design does not stay.
        Some(dir) => Some(plan.dir_replacing("--out", dir, &names, &[CUTTER_FILE])?),
        None => None,
    };
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &[SVAJ_FILE])?),
        None => None,
    };
    if let Some(t) = out_target {
        let contents = drawing.files()?;
        let mut out = t.open()?;
        for (file, text) in contents {
            out.write(file, text.as_bytes())?;
        }
        let done = out.commit()?;
        files.extend(done.written.iter().map(|p| p.display().to_string()));
    }
    if let Some(t) = plot_target {
        let mut out = t.open()?;
        crate::plot::draw_svaj(&mut out, drawing.design(), SVAJ_FILE, units)?;
        let dir = out.dir().to_path_buf();
        out.commit()?;
        files.push(dir.join(SVAJ_FILE).display().to_string());
    }
    Ok(files)
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args, units)?, args.output.json, units)
}
