//! What `camsim profile` reports, and its text.

use std::fmt::Write;

use serde::ser::{Serialize, SerializeStruct, Serializer};

use crate::actual::ProfileStats;
use crate::export::Units as DrawingUnit;
use crate::report::Report;
use crate::units::measure::kind;
use crate::units::{Length, MeasureIn, Units, LENGTH};

/// One sampled curve (the JSON `curves` entries). Its chordal error and perimeter are
/// measured on the drawing's own points, so they are numbers in the drawing's `unit`,
/// held in it in JSON ([`MeasureIn`]: `perimeter_mm`).
#[derive(Clone, Debug)]
pub struct CurveReport {
    /// "surface", "pitch" or "cutter".
    pub name: &'static str,
    /// Points (the polyline's vertices).
    pub points: usize,
    /// The largest distance of the curve from its chords, measured after sampling, in
    /// `unit`.
    pub max_chord_error: f64,
    /// The polyline's length, in `unit`.
    pub perimeter: f64,
    /// The drawing's length unit.
    pub unit: DrawingUnit,
}

impl Serialize for CurveReport {
    /// The lengths as measured, in the drawing's unit, keyed by it (`max_chord_error_in`,
    /// `perimeter_mm`).
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let family = match self.unit {
            DrawingUnit::In => Units::Inch,
            DrawingUnit::Mm => Units::Si,
        };
        let length = |v: f64| MeasureIn::<kind::Length>::new(v, family);
        let mut m = s.serialize_struct("CurveReport", 4)?;
        m.serialize_field("name", self.name)?;
        m.serialize_field("points", &self.points)?;
        m.serialize_field("max_chord_error", &length(self.max_chord_error))?;
        m.serialize_field("perimeter", &length(self.perimeter))?;
        m.end()
    }
}

/// What `camsim profile` reports.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ProfileReport {
    /// Length unit of the files and of the curves' lengths.
    pub units: DrawingUnit,
    /// "theoretical" or "actual".
    pub cam: &'static str,
    /// The chordal error bound.
    pub chord_error_bound: Length,
    /// Base-circle radius.
    pub base_radius: Length,
    /// Roller radius.
    pub roller_radius: Length,
    /// Cutter radius (with a cutter).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cutter_radius: Option<Length>,
    /// Smallest radius of curvature of the cam surface where it is convex.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_convex_surface_radius: Option<Length>,
    /// Smallest |radius of curvature| of the cam surface where it is concave (None:
    /// convex everywhere).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_concave_surface_radius: Option<Length>,
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
    fn text(&self, units: Units) -> String {
        let u = units.symbol(LENGTH);
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Cam drawing ({} cam): base circle radius {:.6} {u}, roller radius {:.6} {u}{}",
            self.cam,
            units.of(self.base_radius),
            units.of(self.roller_radius),
            self.cutter_radius.map_or(String::new(), |c| format!(
                ", cutter radius {:.6} {u}",
                units.of(c)
            ))
        );
        if let Some(a) = &self.actual {
            let _ = writeln!(
                s,
                "  actual cam: seed {}, sample {}, method {}, RMS lift deviation {:.3e} {u}",
                a.seed,
                a.sample,
                a.method.name(),
                units.value(LENGTH, a.rms_deviation_in.in_inch())
            );
        }
        let _ = writeln!(
            s,
            "  chordal error bound {:.3e} {u}",
            units.of(self.chord_error_bound)
        );
        self.curve_table(&mut s);
        self.curvature_lines(&mut s, units);
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

impl ProfileReport {
    /// The curves' points, chordal errors and perimeters, in the drawing's unit.
    fn curve_table(&self, s: &mut String) {
        let u = self.units.name();
        let _ = writeln!(
            s,
            "  {:<8} {:>7} {:>18} {:>16}",
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
    }

    /// The surface's smallest convex and concave radii of curvature.
    fn curvature_lines(&self, s: &mut String, units: Units) {
        let u = units.symbol(LENGTH);
        if let Some(r) = self.min_convex_surface_radius {
            let _ = writeln!(
                s,
                "  smallest convex surface radius of curvature {:.6} {u}",
                units.of(r)
            );
        }
        match self.min_concave_surface_radius {
            Some(r) => {
                let _ = writeln!(
                    s,
                    "  smallest concave surface radius of curvature {:.6} {u}",
                    units.of(r)
                );
            }
            None => {
                let _ = writeln!(s, "  the surface is convex everywhere");
            }
        }
    }
}
