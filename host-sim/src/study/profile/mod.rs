//! The cam as a drawing for the machine shop (`camsim profile`).
//!
//! For the inline translating roller follower: the pitch curve (the roller centre's path
//! in the cam frame), the cam surface (the pitch curve moved inwards by the roller
//! radius along its normal) and, with a cutter radius, the centre path of a cutter
//! (grinding wheel or end mill) of that radius cutting the surface from outside (the
//! surface moved outwards by the cutter radius). Each curve is sampled so that no chord
//! is farther than the chordal error bound from the curve ([`crate::export`]), for the
//! CSVs and the closed polylines of one DXF ([`Drawing::files`]). The surface's polar
//! radius is also written in the format `camsim run --measured` reads
//! ([`SURFACE_RADIUS_FILE`], in the drawing's unit: `radius_in` or `radius_mm`), so the
//! drawing can be simulated back. Every CSV starts with `#` lines and the DXF carries a
//! note giving the unit, the rotation direction and the 0° datum ([`conventions`]). With
//! the actual cam it is a simulated machined one ([`crate::actual::build_profile`],
//! sample 0 of the seed), to compare against a CMM measurement.
//!
//! The study takes a [`Spec`] and the output's unit family (the drawing's length unit)
//! and returns a [`Drawing`]: its [`ProfileReport`] (its text in `report.rs`) and the files'
//! contents; `camsim profile` (crate::cmd::profile) builds the spec from its arguments,
//! writes the files and prints the report.

use anyhow::Result;
use camsim_core::Design;

use crate::actual::Cams;
use crate::export;
use crate::units::{Length, Units};

mod cam;
mod files;
mod report;

use cam::Cam;
pub use files::{
    conventions, polar_rows, CUTTER_FILE, DXF_FILE, PITCH_FILE, SURFACE_FILE, SURFACE_RADIUS_FILE,
};
pub use report::{CurveReport, ProfileReport};

/// The default chordal error bound, in: 0.0001 in (2.5 µm), a fifth of the thesis's cam
/// profile tolerance (±0.0005 in, VI.1), so the drawing's chords add little to the
/// machining error it is meant to stay within.
pub const DEFAULT_CHORD_ERROR_IN: f64 = 1e-4;

/// The most points one curve may have: what a measured file may hold
/// ([`crate::measured::MAX_POINTS`]), so the surface reads back.
pub const MAX_CURVE_POINTS: usize = crate::measured::MAX_POINTS;

/// What to draw.
#[derive(Clone, Debug)]
pub struct Spec {
    /// The design (its program and geometry).
    pub design: Design<f64>,
    /// The actual cam's options (`actual.actual`: draw sample 0 of its seed instead of
    /// the theoretical cam).
    pub actual: Cams,
    /// Radius of the cutter whose centre path is also drawn, in.
    pub cutter_radius_in: Option<f64>,
    /// The largest distance of a chord from its curve, in.
    pub chord_error_in: f64,
    /// The CSVs' uniform step, deg (dividing 360), instead of the chordal sampling.
    pub every_deg: Option<f64>,
}

/// The drawing: its report and what its files are made from.
pub struct Drawing {
    /// What `camsim profile` reports (its `files` left empty: the command writes them).
    pub report: ProfileReport,
    cam: Cam,
    curves: Vec<cam::Curve>,
    unit: export::Units,
}

/// Computes the drawing of `spec` in the length unit of `units` (inch: in, SI: mm).
pub fn drawing(spec: &Spec, units: Units) -> Result<Drawing> {
    let design = spec.design.clone();
    let actual = if spec.actual.actual {
        Some(crate::actual::build_profile(&design, &spec.actual, 0)?)
    } else {
        None
    };
    let (dev, stats) = actual.map_or((None, None), |(d, s)| (Some(d), Some(s)));
    let cam = Cam { design, dev };
    let unit = export::Units::from(units);
    let scale = unit.per_inch();
    // The bound in the drawing's unit, as the curves are sampled in it.
    let bound = spec.chord_error_in * scale;
    let g = cam.design.geometry;
    let (convex, concave, undercut) = cam.surface_curvature();
    let warnings = cam::machining_warnings(spec.cutter_radius_in, concave, undercut, units);
    let curves = cam.sampled_curves(bound, scale, spec.cutter_radius_in)?;
    let report = ProfileReport {
        units: unit,
        cam: if stats.is_some() {
            "actual"
        } else {
            "theoretical"
        },
        chord_error_bound: Length::inch(spec.chord_error_in),
        base_radius: Length::inch(g.base_radius),
        roller_radius: Length::inch(g.roller_radius),
        cutter_radius: spec.cutter_radius_in.map(Length::inch),
        min_convex_surface_radius: convex.map(Length::inch),
        min_concave_surface_radius: concave.map(Length::inch),
        warnings,
        curves: cam.curve_reports(&curves, scale, unit),
        every_deg: spec.every_deg,
        actual: stats,
        files: Vec::new(),
    };
    Ok(Drawing {
        report,
        cam,
        curves,
        unit,
    })
}

impl Drawing {
    /// The design drawn.
    pub fn design(&self) -> &Design<f64> {
        &self.cam.design
    }

    /// The files of the drawing, (name, contents): the curves' CSVs (spaced by the
    /// report's `every_deg`, else by the chordal bound) and the DXF, each saying which
    /// cam it draws. Refused when the surface's polar angle does not grow around the cam
    /// (it cannot be written as a polar radius).
    pub fn files(&self) -> Result<Vec<(&'static str, String)>> {
        let r = &self.report;
        let what = match &r.actual {
            Some(s) => format!(
                "a simulated machined cam (camsim profile --actual, seed {}, sample {})",
                s.seed, s.sample
            ),
            None => "the theoretical cam".to_string(),
        };
        let step = match r.every_deg {
            Some(d) => files::Step::Every(d),
            None => files::Step::Chordal(r.chord_error_bound.in_inch() * self.unit.per_inch()),
        };
        let mut out = files::csv_files(&self.cam, &self.curves, step, self.unit, &what)?;
        let note = conventions(self.unit);
        let dxf = export::dxf(&files::dxf_layers(&self.curves), self.unit, &note);
        out.push((DXF_FILE, dxf));
        Ok(out)
    }
}
