//! The cam's shape: the largest pressure angle of the theoretical profile and the pitch
//! curve's smallest convex radius with its undercut margin.

use anyhow::Result;
use camsim_core::{Design, PeakScan, ScanEnds};
use serde::Serialize;

use super::Limits;
use crate::units::{Length, Units};

/// The cam's shape.
#[derive(Clone, Debug, Serialize)]
pub struct GeometryVerdict {
    /// Largest |pressure angle| of the theoretical profile, degrees.
    pub max_pressure_angle_deg: f64,
    /// Cam angle where, degrees.
    pub max_pressure_angle_at_deg: f64,
    /// The limit judged against, degrees.
    pub pressure_angle_limit_deg: f64,
    /// Smallest radius of curvature of the pitch curve where it is convex, in.
    pub min_pitch_radius_in: Length,
    /// Cam angle where, degrees.
    pub min_pitch_radius_at_deg: f64,
    /// Undercut margin: that radius minus the roller radius (the cam surface's smallest
    /// convex radius), in; at or below 0 the roller cannot cut the profile.
    pub undercut_margin_in: Length,
}

/// Largest |pressure angle| of the theoretical profile (deg, at deg), smallest convex
/// pitch radius (in, at deg) and the undercut margin (in).
pub fn geometry(design: &Design<f64>, limits: &Limits) -> Result<GeometryVerdict> {
    let g = &design.geometry;
    let prog = &design.program;
    let n = 3600;
    let scan = PeakScan {
        start: 0.0,
        step: std::f64::consts::TAU / n as f64,
        points: n,
        ends: ScanEnds::Periodic,
        iterations: 60,
    };
    let phi = |th: f64| {
        let th = th.rem_euclid(std::f64::consts::TAU);
        let f = prog.follower(th);
        g.pressure_angle(f.y, f.dy).abs()
    };
    let peak = scan
        .maximize(phi)
        .ok_or_else(|| anyhow::anyhow!("no pressure angle could be evaluated"))?;
    let u = g.undercut(prog, n)?;
    let pitch = u.min_convex_surface_radius + g.roller_radius;
    Ok(GeometryVerdict {
        max_pressure_angle_deg: peak.value.to_degrees(),
        max_pressure_angle_at_deg: peak.at.rem_euclid(std::f64::consts::TAU).to_degrees(),
        pressure_angle_limit_deg: limits.pressure_angle_limit_deg,
        min_pitch_radius_in: Length::inch(pitch),
        min_pitch_radius_at_deg: u.min_convex_at.to_degrees(),
        undercut_margin_in: Length::inch(u.min_convex_surface_radius),
    })
}

/// The verdict's geometry line: the largest pressure angle and the pitch curve's smallest
/// radius with its undercut margin.
pub(super) fn geometry_text(g: &GeometryVerdict, units: Units) -> String {
    use crate::units as u;
    format!(
        "  geometry:  largest pressure angle {:.2} deg at cam angle {:.1} deg (limit {:.0} deg); smallest pitch-curve radius {} {lu} at {:.1} deg, undercut margin {} {lu}",
        g.max_pressure_angle_deg,
        g.max_pressure_angle_at_deg,
        g.pressure_angle_limit_deg,
        units.show(g.min_pitch_radius_in, 4),
        g.min_pitch_radius_at_deg,
        units.show(g.undercut_margin_in, 4),
        lu = units.symbol(u::LENGTH)
    )
}
