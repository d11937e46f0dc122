//! `camsim profile [SCENE] --out DIR`: the cam as a drawing for the machine shop.
//!
//! For the inline translating roller follower: the pitch curve (the roller centre's path
//! in the cam frame), the cam surface (the pitch curve moved inwards by the roller
//! radius along its normal) and, with `--cutter-radius`, the centre path of a cutter
//! (grinding wheel or end mill) of that radius cutting the surface from outside (the
//! surface moved outwards by the cutter radius). Each curve is sampled so that no
//! chord is farther than `--chord-error` from the curve ([`crate::export`]), and written
//! as CSV and as closed polylines of one DXF. The surface's polar radius is also written
//! in the format `camsim run --measured` reads (`surface_radius.csv`, in the drawing's
//! unit: `radius_in` or `radius_mm`), so the drawing can be simulated back. Every CSV
//! starts with `#` lines and the DXF carries a note giving the unit, the rotation
//! direction and the 0° datum ([`conventions`]). With `--actual` the cam is a simulated machined one
//! ([`crate::actual::build_profile`], sample 0 of `--seed`), to compare against a CMM
//! measurement. `--plot DIR` draws the program's SVAJ diagram (`svaj.png`).

use std::path::PathBuf;

use anyhow::{bail, Result};
use camsim_core::{CamGeometry, FollowerLift};
use serde::Serialize;

use crate::actual::{ActualArgs, ProfileStats};
use crate::args::{positive_length, spec_from, OutputArgs, SceneArgs};
use crate::export::{self, CurvePoint, Layer, Units};
use crate::output::{AtomicDir, Plan};
use crate::report::Report;
use crate::sim::HostDeviation;

/// The default `--chord-error`, in: 0.0001 in (2.5 µm), a fifth of the thesis's cam
/// profile tolerance (±0.0005 in, VI.1), so the drawing's chords add little to the
/// machining error it is meant to stay within.
pub const DEFAULT_CHORD_ERROR_IN: f64 = 1e-4;

/// The most points one curve may have: what a measured file may hold
/// ([`crate::measured::MAX_POINTS`]), so the surface reads back.
pub const MAX_CURVE_POINTS: usize = crate::measured::MAX_POINTS;

/// Points inside every chord at which the chordal error is measured after sampling.
const CHECK_PER_CHORD: usize = 15;

/// The files `--out` writes.
pub const SURFACE_RADIUS_FILE: &str = "surface_radius.csv";
/// The surface's Cartesian points.
pub const SURFACE_FILE: &str = "surface.csv";
/// The pitch curve.
pub const PITCH_FILE: &str = "pitch.csv";
/// The cutter-centre path (with `--cutter-radius`).
pub const CUTTER_FILE: &str = "cutter.csv";
/// The drawing.
pub const DXF_FILE: &str = "cam.dxf";
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
    /// Length unit of the DXF, of every CSV and of the report: the global `--units`
    /// (inch: in; si: mm). Set by the command line, not an option here.
    #[arg(skip)]
    pub units: Units,
    /// A simulated machined cam (`--actual` and its options) instead of the theoretical.
    #[command(flatten)]
    pub actual: ActualArgs,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// One sampled curve (the JSON `curves` entries).
#[derive(Clone, Debug, Serialize)]
pub struct CurveReport {
    /// "surface", "pitch" or "cutter".
    pub name: &'static str,
    /// Points (the polyline's vertices).
    pub points: usize,
    /// The largest distance of the curve from its chords, measured after sampling, in
    /// `units`.
    pub max_chord_error: f64,
    /// The polyline's length, in `units`.
    pub perimeter: f64,
}

/// What `camsim profile` reports.
#[derive(Clone, Debug, Serialize)]
pub struct ProfileReport {
    /// Length unit of every length below and of the files.
    pub units: Units,
    /// "theoretical" or "actual".
    pub cam: &'static str,
    /// The chordal error bound, in `units`.
    pub chord_error_bound: f64,
    /// Base-circle radius, in `units`.
    pub base_radius: f64,
    /// Roller radius, in `units`.
    pub roller_radius: f64,
    /// Cutter radius, in `units` (with --cutter-radius).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutter_radius: Option<f64>,
    /// Smallest radius of curvature of the cam surface where it is convex, in `units`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_convex_surface_radius: Option<f64>,
    /// Smallest |radius of curvature| of the cam surface where it is concave, in
    /// `units` (None: convex everywhere).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_concave_surface_radius: Option<f64>,
    /// Warnings for the shop: a cutter that cannot cut a concave part.
    pub warnings: Vec<String>,
    /// The sampled curves (the DXF's polylines; the CSVs' too without `every_deg`).
    pub curves: Vec<CurveReport>,
    /// The CSVs' uniform angle step, deg (`--every-deg`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub every_deg: Option<f64>,
    /// The actual cam's profile (with --actual).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub actual: Option<ProfileStats>,
    /// The files written (with --out and --plot).
    pub files: Vec<String>,
}

impl Report for ProfileReport {
    /// Every length key with the drawing's unit (`base_radius_mm`), which `--units`
    /// chose: the values are in it already.
    fn json(&self) -> serde_json::Result<String> {
        const LENGTHS: [&str; 8] = [
            "chord_error_bound",
            "base_radius",
            "roller_radius",
            "cutter_radius",
            "min_convex_surface_radius",
            "min_concave_surface_radius",
            "max_chord_error",
            "perimeter",
        ];
        fn suffix(v: serde_json::Value, u: &str) -> serde_json::Value {
            use serde_json::Value;
            match v {
                Value::Object(o) => Value::Object(
                    o.into_iter()
                        .map(|(k, v)| {
                            let k = if LENGTHS.contains(&k.as_str()) {
                                format!("{k}_{u}")
                            } else {
                                k
                            };
                            (k, suffix(v, u))
                        })
                        .collect(),
                ),
                Value::Array(a) => Value::Array(a.into_iter().map(|v| suffix(v, u)).collect()),
                v => v,
            }
        }
        serde_json::to_string_pretty(&suffix(serde_json::to_value(self)?, self.units.name()))
    }

    fn text(&self, _units: crate::units::Units) -> String {
        use std::fmt::Write;
        let u = self.units.name();
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Cam drawing ({} cam): base circle radius {:.6} {u}, roller radius {:.6} {u}{}",
            self.cam,
            self.base_radius,
            self.roller_radius,
            self.cutter_radius
                .map_or(String::new(), |c| format!(", cutter radius {c:.6} {u}"))
        );
        if let Some(a) = &self.actual {
            let _ = writeln!(
                s,
                "  actual cam: seed {}, sample {}, method {}, RMS lift deviation {:.3e} in",
                a.seed,
                a.sample,
                a.method.name(),
                a.rms_deviation_in
            );
        }
        let _ = writeln!(
            s,
            "  chordal error bound {:.3e} {u}\n  {:<8} {:>7} {:>18} {:>16}",
            self.chord_error_bound,
            "curve",
            "points",
            format!("max chord err {u}"),
            format!("perimeter {u}")
        );
        for c in &self.curves {
            let _ = writeln!(
                s,
                "  {:<8} {:>7} {:>18.3e} {:>16.6}",
                c.name, c.points, c.max_chord_error, c.perimeter
            );
        }
        if let Some(r) = self.min_convex_surface_radius {
            let _ = writeln!(
                s,
                "  smallest convex surface radius of curvature {r:.6} {u}"
            );
        }
        match self.min_concave_surface_radius {
            Some(r) => {
                let _ = writeln!(
                    s,
                    "  smallest concave surface radius of curvature {r:.6} {u}"
                );
            }
            None => {
                let _ = writeln!(s, "  the surface is convex everywhere");
            }
        }
        if let Some(d) = self.every_deg {
            let _ = writeln!(
                s,
                "  the CSVs every {d} deg ({} rows; surface_radius.csv by polar angle), \
                 the DXF by the chordal error bound",
                (360.0 / d).round()
            );
        }
        for w in &self.warnings {
            let _ = writeln!(s, "  warning: {w}");
        }
        for f in &self.files {
            let _ = writeln!(s, "  wrote {f}");
        }
        s
    }
}

/// The lift of the cam to draw: the program, plus the actual cam's deviation.
struct Cam<'a> {
    design: &'a camsim_core::Design<f64>,
    dev: Option<&'a HostDeviation>,
}

impl Cam<'_> {
    fn lift(&self, theta: f64) -> FollowerLift<f64> {
        let mut f = self.design.program.follower(theta);
        if let Some(d) = self.dev {
            let e = d.deviation(theta);
            f.y += e.y;
            f.dy += e.dy;
            f.d2y += e.d2y;
            f.d3y += e.d3y;
        }
        f
    }

    fn geometry(&self) -> &CamGeometry<f64> {
        &self.design.geometry
    }

    /// The point at distance `d` (in) outward from the pitch curve, in the drawing unit.
    fn offset(&self, theta: f64, d: f64, scale: f64) -> (f64, f64) {
        let f = self.lift(theta);
        let (x, y) = self.geometry().pitch_offset_point(theta, f.y, f.dy, d);
        (x * scale, y * scale)
    }
}

/// The drawing's conventions, one line each (the DXF's note, the CSVs' `#` lines): the
/// unit, which way the cam turns and where angle 0 is. The cam-fixed frame is that of
/// [`CamGeometry::pitch_point`] (docs/MODEL.md §1.2): the roller centre at cam angle θ
/// sits at (R_a + y)(sin θ, cos θ), so the point under the follower (fixed on +y) at cam
/// angle θ was at θ clockwise from +y: the cam turns counterclockwise as drawn.
pub fn conventions(units: Units) -> [String; 3] {
    let (u, long) = match units {
        Units::In => ("in", "inches"),
        Units::Mm => ("mm", "millimetres"),
    };
    [
        format!(
            "Units: lengths in {long} ({u}), angles in degrees; rotation centre at the origin."
        ),
        "Rotation: the cam turns counterclockwise as drawn (x right, y up, seen from +z), \
         the follower on the +y axis."
            .to_string(),
        "0 deg datum: the +y axis, the follower axis at cam angle 0 (the lift program's start); \
         cam and polar angles grow clockwise as drawn."
            .to_string(),
    ]
}

/// Polyline length of a closed curve.
fn perimeter(p: &[CurvePoint]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            (b.x - a.x).hypot(b.y - a.y)
        })
        .sum()
}

/// The surface points as `run --measured` reads them: polar angle (deg, in [0, 360),
/// increasing) and radius (in), from points in the drawing unit.
pub fn polar_rows(points: &[CurvePoint], per_inch: f64) -> Result<Vec<(f64, f64)>> {
    let mut rows: Vec<(f64, f64)> = points
        .iter()
        .map(|p| {
            // The frame of CamGeometry::surface_point: angle 0 on +y, growing towards +x.
            let a = p.x.atan2(p.y).to_degrees().rem_euclid(360.0);
            (if a >= 360.0 { 0.0 } else { a }, p.x.hypot(p.y) / per_inch)
        })
        .collect();
    // Rotate so the smallest polar angle comes first; the order must then increase.
    let first = rows
        .iter()
        .enumerate()
        .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0))
        .map_or(0, |(i, _)| i);
    rows.rotate_left(first);
    for w in rows.windows(2) {
        if w[1].0 <= w[0].0 {
            bail!(
                "the cam surface's polar angle does not grow around the cam (at {:.4} deg): \
                 it cannot be written as a polar radius",
                w[0].0
            );
        }
    }
    Ok(rows)
}

/// How the CSVs' rows are spaced.
#[derive(Clone, Copy, Debug)]
enum Step {
    /// The drawing's own points: chords within this bound, in the drawing unit.
    Chordal(f64),
    /// Every this many degrees (dividing 360, [`every_deg`]).
    Every(f64),
}

/// The closed curve `curve` at the `n` cam angles 2πk/n, k = 0..n.
fn uniform(curve: impl Fn(f64) -> (f64, f64), n: usize) -> Result<Vec<CurvePoint>> {
    (0..n)
        .map(|k| {
            let theta = std::f64::consts::TAU * k as f64 / n as f64;
            let (x, y) = curve(theta);
            if !(x.is_finite() && y.is_finite()) {
                bail!(
                    "the curve has a non-finite point at cam angle {:.3} deg",
                    theta.to_degrees()
                );
            }
            Ok(CurvePoint { theta, x, y })
        })
        .collect()
}

/// The surface `curve` (cam angle to point, the drawing unit) at the `n` polar angles
/// 360k/n deg: (polar angle deg, radius). The surface point lies off the pitch point
/// (at polar angle θ) by the roller radius along the normal, less than 90° away
/// in polar angle, so the cam angle of polar angle φ lies in (φ - 90°, φ + 90°), found
/// by bisection (the polar angle grows with the cam angle: [`polar_rows`] checked it).
fn polar_uniform(curve: impl Fn(f64) -> (f64, f64), n: usize) -> Vec<(f64, f64)> {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    (0..n)
        .map(|k| {
            let phi = TAU * k as f64 / n as f64;
            // The polar angle's signed offset from φ, in (-π, π].
            let off = |t: f64| {
                let (x, y) = curve(t.rem_euclid(TAU));
                let d = (x.atan2(y) - phi).rem_euclid(TAU);
                if d > PI {
                    d - TAU
                } else {
                    d
                }
            };
            let (mut lo, mut hi) = (phi - FRAC_PI_2, phi + FRAC_PI_2);
            for _ in 0..64 {
                let mid = 0.5 * (lo + hi);
                if off(mid) < 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let (x, y) = curve((0.5 * (lo + hi)).rem_euclid(TAU));
            (phi.to_degrees(), x.hypot(y))
        })
        .collect()
}

/// The CSV files (name, text) of the sampled `curves` (name, offset from the pitch curve
/// in in, points), spaced by `step`, in `units` (`scale` per inch).
fn csv_files(
    cam: &Cam,
    curves: &[(&'static str, f64, Vec<CurvePoint>)],
    step: Step,
    units: Units,
    what: &str,
    scale: f64,
) -> Result<Vec<(&'static str, String)>> {
    let u = units.name();
    let comment: String = conventions(units)
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    let points = |(_, d, pts): &(&str, f64, Vec<CurvePoint>)| match step {
        Step::Chordal(_) => Ok(pts.clone()),
        Step::Every(deg) => uniform(|t| cam.offset(t, *d, scale), (360.0 / deg).round() as usize),
    };
    let Some(surface) = curves.first() else {
        bail!("no cam surface was sampled");
    };
    // Refused here when the surface's polar angle does not grow (an undercut cam).
    let chordal_rows = polar_rows(&surface.2, 1.0)?;
    let (rows, spacing) = match step {
        Step::Chordal(bound) => (chordal_rows, format!("Chordal error bound {bound:e} {u}.")),
        Step::Every(deg) => (
            polar_uniform(
                |t| cam.offset(t, surface.1, scale),
                (360.0 / deg).round() as usize,
            ),
            format!("Every {deg} deg of polar angle."),
        ),
    };
    let mut radius = format!(
        "# camsim profile: cam surface polar radius of {what}, from the rotation centre.\n\
         {comment}# {spacing} Read back by: camsim run --measured {SURFACE_RADIUS_FILE}\n\
         angle_deg,radius_{u}\n"
    );
    for (a, r) in rows {
        radius.push_str(&format!("{a:.9},{r:.10}\n"));
    }
    let mut files = vec![(SURFACE_RADIUS_FILE, radius)];
    let mut s = format!("{comment}cam_angle_deg,x_{u},y_{u},polar_angle_deg,radius_{u}\n");
    for p in points(surface)? {
        let a = p.x.atan2(p.y).to_degrees().rem_euclid(360.0);
        s.push_str(&format!(
            "{:.9},{:.10},{:.10},{a:.9},{:.10}\n",
            p.theta.to_degrees(),
            p.x,
            p.y,
            p.x.hypot(p.y)
        ));
    }
    files.push((SURFACE_FILE, s));
    for (name, file) in [("pitch", PITCH_FILE), ("cutter", CUTTER_FILE)] {
        if let Some(c) = curves.iter().find(|c| c.0 == name) {
            let mut s = format!("{comment}cam_angle_deg,x_{u},y_{u}\n");
            for p in points(c)? {
                s.push_str(&format!(
                    "{:.9},{:.10},{:.10}\n",
                    p.theta.to_degrees(),
                    p.x,
                    p.y
                ));
            }
            files.push((file, s));
        }
    }
    Ok(files)
}

/// The surface's smallest convex and concave radii of curvature over one revolution
/// (Eq. V.12, 0.05° apart), and the last cam angle, deg, where the pitch curve's radius
/// is below the roller's (undercut).
fn surface_curvature(
    cam: &Cam,
    g: &camsim_core::CamGeometry<f64>,
) -> (Option<f64>, Option<f64>, Option<f64>) {
    let rr = g.roller_radius;
    let (mut convex, mut concave): (Option<f64>, Option<f64>) = (None, None);
    let mut undercut: Option<f64> = None;
    for k in 0..7200 {
        let th = (k as f64 * 0.05).to_radians();
        let f = cam.lift(th);
        let rho_pitch = g.pitch_curvature_radius(f.y, f.dy, f.d2y);
        if rho_pitch > 0.0 && rho_pitch <= rr {
            undercut = Some(th.to_degrees());
        } else if rho_pitch > rr {
            let r = rho_pitch - rr;
            convex = Some(convex.map_or(r, |c| c.min(r)));
        } else if rho_pitch < 0.0 {
            let r = rr - rho_pitch;
            concave = Some(concave.map_or(r, |c| c.min(r)));
        }
    }
    (convex, concave, undercut)
}

/// A sampled curve: its name, its offset from the pitch curve (in) and its points in the
/// drawing's unit.
type Curve = (&'static str, f64, Vec<CurvePoint>);

/// Computes the drawing and writes what `args` asks for.
pub fn report(args: &Args) -> Result<ProfileReport> {
    let spec = spec_from(&args.scene)?;
    let design = &spec.design;
    args.actual.ensure_actual_if_options()?;
    let actual = if args.actual.actual {
        Some(crate::actual::build_profile(design, &args.actual, 0)?)
    } else {
        None
    };
    let cam = Cam {
        design,
        dev: actual.as_ref().map(|a| &a.0),
    };
    let scale = args.units.per_inch();
    // The options are read in inch (their parser converts a value given in mm).
    let bound = args.chord_error.unwrap_or(DEFAULT_CHORD_ERROR_IN) * scale;
    let g = design.geometry;
    let (convex, concave, undercut) = surface_curvature(&cam, &g);
    let warnings = machining_warnings(args, concave, undercut);
    let curves = sampled_curves(&cam, bound, scale, args.cutter_radius)?;
    let mut report = ProfileReport {
        units: args.units,
        cam: if actual.is_some() {
            "actual"
        } else {
            "theoretical"
        },
        chord_error_bound: bound,
        base_radius: g.base_radius * scale,
        roller_radius: g.roller_radius * scale,
        cutter_radius: args.cutter_radius.map(|c| c * scale),
        min_convex_surface_radius: convex.map(|r| r * scale),
        min_concave_surface_radius: concave.map(|r| r * scale),
        warnings,
        curves: curve_reports(&cam, &curves, scale),
        every_deg: args.every_deg,
        actual: actual.as_ref().map(|a| a.1.clone()),
        files: Vec::new(),
    };
    // Nothing is written for a result with a non-finite number.
    crate::report::ensure_finite(&report)?;
    let stats = actual.as_ref().map(|a| &a.1);
    report.files = write_outputs(args, &cam, &curves, stats, bound)?;
    Ok(report)
}

/// What the shop must know before cutting: a cutter larger than the smallest concave
/// surface radius (`concave`, in) gouges; an undercut (at cam angle `undercut`, deg) cannot
/// be followed by the roller.
fn machining_warnings(args: &Args, concave: Option<f64>, undercut: Option<f64>) -> Vec<String> {
    let scale = args.units.per_inch();
    let mut warnings = Vec::new();
    if let (Some(c), Some(r)) = (args.cutter_radius, concave) {
        if c > r {
            warnings.push(format!(
                "the cutter radius {:.6} {u} is larger than the smallest concave surface radius {:.6} {u}: \
                 it cannot cut the concave part without gouging",
                c * scale,
                r * scale,
                u = args.units.name()
            ));
        }
    }
    if let Some(a) = undercut {
        warnings.push(format!(
            "the cam is undercut near cam angle {a:.2} deg: the pitch curve's radius of curvature is below the roller radius"
        ));
    }
    warnings
}

/// The surface, the pitch curve and (with a cutter radius `cutter_in`, in) the cutter's
/// centre path, each sampled to within `bound` (drawing unit, `scale` per inch).
fn sampled_curves(cam: &Cam, bound: f64, scale: f64, cutter_in: Option<f64>) -> Result<Vec<Curve>> {
    let rr = cam.geometry().roller_radius;
    let sample = |d: f64| {
        export::adaptive(
            |t| cam.offset(t, d, scale),
            bound,
            MAX_CURVE_POINTS,
            "--chord-error",
        )
    };
    let mut curves = vec![("surface", -rr, sample(-rr)?), ("pitch", 0.0, sample(0.0)?)];
    if let Some(c) = cutter_in {
        curves.push(("cutter", c - rr, sample(c - rr)?));
    }
    Ok(curves)
}

/// Each curve's points, largest chordal error (measured inside every chord) and perimeter.
fn curve_reports(cam: &Cam, curves: &[Curve], scale: f64) -> Vec<CurveReport> {
    curves
        .iter()
        .map(|(name, d, pts)| CurveReport {
            name,
            points: pts.len(),
            max_chord_error: export::max_chord_error(
                |t| cam.offset(t, *d, scale),
                pts,
                CHECK_PER_CHORD,
            ),
            perimeter: perimeter(pts),
        })
        .collect()
}

/// Writes `--out`'s drawing and `--plot`'s SVAJ diagram (both checked before either is
/// written); the paths written.
fn write_outputs(
    args: &Args,
    cam: &Cam,
    curves: &[Curve],
    stats: Option<&ProfileStats>,
    bound: f64,
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
        let mut out = t.open()?;
        write_drawing(&mut out, args, cam, curves, stats, bound)?;
        let done = out.commit()?;
        files.extend(done.written.iter().map(|p| p.display().to_string()));
    }
    if let Some(t) = plot_target {
        let mut out = t.open()?;
        crate::plot::draw_svaj(&mut out, cam.design, SVAJ_FILE, crate::units::current())?;
        let dir = out.dir().to_path_buf();
        out.commit()?;
        files.push(dir.join(SVAJ_FILE).display().to_string());
    }
    Ok(files)
}

/// The drawing into `out`: the curves' CSV files (spaced by `--every-deg`, else by the
/// chordal `bound`) and the DXF, each saying which cam it draws.
fn write_drawing(
    out: &mut AtomicDir,
    args: &Args,
    cam: &Cam,
    curves: &[Curve],
    stats: Option<&ProfileStats>,
    bound: f64,
) -> Result<()> {
    let what = match stats {
        Some(s) => format!(
            "a simulated machined cam (camsim profile --actual, seed {}, sample {})",
            s.seed, s.sample
        ),
        None => "the theoretical cam".to_string(),
    };
    let step = match args.every_deg {
        Some(d) => Step::Every(d),
        None => Step::Chordal(bound),
    };
    let scale = args.units.per_inch();
    for (file, text) in csv_files(cam, curves, step, args.units, &what, scale)? {
        out.write(file, text.as_bytes())?;
    }
    let note = conventions(args.units);
    out.write(
        DXF_FILE,
        export::dxf(&dxf_layers(curves), args.units, &note).as_bytes(),
    )
}

/// The DXF's layers: the surface (white), the pitch curve (red) and the cutter path (blue).
fn dxf_layers(curves: &[Curve]) -> Vec<Layer<'_>> {
    curves
        .iter()
        .map(|(name, _, pts)| Layer {
            name: match *name {
                "surface" => "SURFACE",
                "pitch" => "PITCH",
                _ => "CUTTER",
            },
            color: match *name {
                "surface" => 7,
                "pitch" => 1,
                _ => 5,
            },
            points: pts,
        })
        .collect()
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    crate::report::print(&report(&args)?, args.output.json, units)
}
