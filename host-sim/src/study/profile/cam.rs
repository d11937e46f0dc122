//! The cam's shape: its lift (the program plus the actual cam's deviation), the curves
//! offset from its pitch curve, sampled to a chordal error, and the surface's curvature.

use anyhow::Result;
use camsim_core::{Design, FollowerLift};

use super::{CurveReport, MAX_CURVE_POINTS};
use crate::export::{self, CurvePoint};
use crate::sim::HostDeviation;
use crate::units::{Length, Units};

/// Points inside every chord at which the chordal error is measured after sampling.
const CHECK_PER_CHORD: usize = 15;

/// A sampled curve: its name, its offset from the pitch curve (in) and its points in the
/// drawing's unit.
pub(super) type Curve = (&'static str, f64, Vec<CurvePoint>);

/// The cam to draw: the program, plus the actual cam's deviation.
pub(super) struct Cam {
    pub(super) design: Design<f64>,
    pub(super) dev: Option<HostDeviation>,
}

impl Cam {
    fn lift(&self, theta: f64) -> FollowerLift<f64> {
        let mut f = self.design.program.follower(theta);
        if let Some(d) = &self.dev {
            let e = d.deviation(theta);
            f.y += e.y;
            f.dy += e.dy;
            f.d2y += e.d2y;
            f.d3y += e.d3y;
        }
        f
    }

    /// The point at distance `d` (in) outward from the pitch curve, in the drawing unit
    /// (`scale` per inch).
    pub(super) fn offset(&self, theta: f64, d: f64, scale: f64) -> (f64, f64) {
        let f = self.lift(theta);
        let g = &self.design.geometry;
        let (x, y) = g.pitch_offset_point(theta, f.y, f.dy, d);
        (x * scale, y * scale)
    }

    /// The surface's smallest convex and concave radii of curvature over one revolution
    /// (Eq. V.12, 0.05° apart), in, and the last cam angle, deg, where the pitch curve's
    /// radius is below the roller's (undercut).
    pub(super) fn surface_curvature(&self) -> (Option<f64>, Option<f64>, Option<f64>) {
        let g = &self.design.geometry;
        let rr = g.roller_radius;
        let (mut convex, mut concave): (Option<f64>, Option<f64>) = (None, None);
        let mut undercut: Option<f64> = None;
        for k in 0..7200 {
            let th = (k as f64 * 0.05).to_radians();
            let f = self.lift(th);
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

    /// The surface, the pitch curve and (with a cutter radius `cutter_in`, in) the
    /// cutter's centre path, each sampled to within `bound` (drawing unit, `scale` per
    /// inch).
    pub(super) fn sampled_curves(
        &self,
        bound: f64,
        scale: f64,
        cutter_in: Option<f64>,
    ) -> Result<Vec<Curve>> {
        let rr = self.design.geometry.roller_radius;
        let sample = |d: f64| {
            export::adaptive(
                |t| self.offset(t, d, scale),
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

    /// Each curve's points, largest chordal error (measured inside every chord) and
    /// perimeter, in the drawing's `unit` (`scale` per inch).
    pub(super) fn curve_reports(
        &self,
        curves: &[Curve],
        scale: f64,
        unit: export::Units,
    ) -> Vec<CurveReport> {
        curves
            .iter()
            .map(|(name, d, pts)| CurveReport {
                name,
                points: pts.len(),
                max_chord_error: export::max_chord_error(
                    |t| self.offset(t, *d, scale),
                    pts,
                    CHECK_PER_CHORD,
                ),
                perimeter: perimeter(pts),
                unit,
            })
            .collect()
    }
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

/// What the shop must know before cutting: a cutter (radius `cutter_in`, in) larger than
/// the smallest concave surface radius (`concave`, in) gouges; an undercut (at cam angle
/// `undercut`, deg) cannot be followed by the roller. Lengths in `units`.
pub(super) fn machining_warnings(
    cutter_in: Option<f64>,
    concave: Option<f64>,
    undercut: Option<f64>,
    units: Units,
) -> Vec<String> {
    let mut warnings = Vec::new();
    if let (Some(c), Some(r)) = (cutter_in, concave) {
        if c > r {
            let (c, r) = (Length::inch(c), Length::inch(r));
            warnings.push(format!(
                "the cutter radius {:.6} {u} is larger than the smallest concave surface radius {:.6} {u}: \
                 it cannot cut the concave part without gouging",
                units.of(c),
                units.of(r),
                u = units.unit_of(c)
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
