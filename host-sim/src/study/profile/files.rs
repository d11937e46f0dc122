//! The drawing's files: the curves' CSVs (the surface's polar radius in the format
//! `camsim run --measured` reads, its Cartesian points, the pitch curve, the cutter's
//! path) and the DXF's layers, every file with the drawing's conventions.

use anyhow::{bail, Result};

use super::cam::{Cam, Curve};
use crate::export::{CurvePoint, Layer, Units};

/// The surface's polar radius (the format of `run --measured`).
pub const SURFACE_RADIUS_FILE: &str = "surface_radius.csv";
/// The surface's Cartesian points.
pub const SURFACE_FILE: &str = "surface.csv";
/// The pitch curve.
pub const PITCH_FILE: &str = "pitch.csv";
/// The cutter-centre path (with a cutter radius).
pub const CUTTER_FILE: &str = "cutter.csv";
/// The drawing.
pub const DXF_FILE: &str = "cam.dxf";

/// The drawing's conventions, one line each (the DXF's note, the CSVs' `#` lines): the
/// unit, which way the cam turns and where angle 0 is. The cam-fixed frame is that of
/// [`camsim_core::CamGeometry::pitch_point`] (docs/MODEL.md §1.2): the roller centre at cam angle θ
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
pub(super) enum Step {
    /// The drawing's own points: chords within this bound, in the drawing unit.
    Chordal(f64),
    /// Every this many degrees (dividing 360: `--every-deg`).
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

/// The CSV files (name, text) of the sampled `curves` of `cam` (the drawing of `what`),
/// spaced by `step`, in `units`.
pub(super) fn csv_files(
    cam: &Cam,
    curves: &[Curve],
    step: Step,
    units: Units,
    what: &str,
) -> Result<Vec<(&'static str, String)>> {
    let (u, scale) = (units.name(), units.per_inch());
    let comment: String = conventions(units)
        .iter()
        .map(|l| format!("# {l}\n"))
        .collect();
    let points = |(_, d, pts): &Curve| match step {
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

/// The DXF's layers: the surface (white), the pitch curve (red) and the cutter path (blue).
pub(super) fn dxf_layers(curves: &[Curve]) -> Vec<Layer<'_>> {
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
