//! The cam as a drawing (`camsim profile`): closed curves sampled to a chordal error
//! bound, written as CSV and as an ASCII DXF.
//!
//! # Sampling
//!
//! A curve `P(θ)`, θ over one revolution, is cut into chords: 72 equal intervals
//! (5°), each halved while a point of the curve at a quarter, the half or three
//! quarters of the interval lies farther than the bound from its chord. The bound is
//! then checked independently ([`max_chord_error`], 15 points inside every chord, the middle one among them): the
//! reported chordal error is that measured one. On a circle of radius ρ a chord of
//! length L has the sagitta `ρ - sqrt(ρ² - L²/4) ≈ L²/(8ρ)`, so the points needed
//! grow as `1/sqrt(bound)`.
//!
//! # DXF
//!
//! AutoCAD R12 ASCII DXF (AC1009) written here, not by a crate: the one crate
//! maintained for writing DXF, `dxf` 0.6.2, brings a second `image` (0.25, with its
//! default codecs) beside the one the plots use, `chrono`, `uuid`, `num` and a
//! code-generating build script, for output that is a few dozen group codes. Each curve
//! is a closed `POLYLINE` (flag 70 = 1) of 2D `VERTEX` entities on its own layer; the
//! header carries `$INSUNITS` (1 inch, 4 millimetre) and `$MEASUREMENT` (0 imperial,
//! 1 metric), and the extents.

use std::fmt::Write as _;

use anyhow::{bail, Result};

/// A point of a sampled curve: its parameter (cam angle, rad) and position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// The parameter: cam angle, rad, in [0, 2π).
    pub theta: f64,
    /// x (the curve's length unit).
    pub x: f64,
    /// y (the curve's length unit).
    pub y: f64,
}

/// Equal intervals the sampling starts from (5°).
pub const START_INTERVALS: usize = 72;
/// Smallest parameter interval the sampling halves, rad (a bound beyond reach at a
/// corner of the curve stops here; the measured error then says so).
const MIN_INTERVAL: f64 = 1e-7;

/// Distance from `p` to the segment `a`-`b`.
fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

/// The points of the closed curve `curve` over θ in [0, 2π) whose chords stay within
/// `bound` of the curve (see the module docs), at most `max_points` of them. Refused
/// (naming `option`) when the bound needs more points, or when the curve has a
/// non-finite point.
pub fn adaptive(
    curve: impl Fn(f64) -> (f64, f64),
    bound: f64,
    max_points: usize,
    option: &str,
) -> Result<Vec<CurvePoint>> {
    let tau = std::f64::consts::TAU;
    let mut out: Vec<CurvePoint> = Vec::new();
    for k in 0..START_INTERVALS {
        let a = tau * k as f64 / START_INTERVALS as f64;
        let b = tau * (k + 1) as f64 / START_INTERVALS as f64;
        // Depth-first, left half first: points come out in order.
        let mut stack = vec![(a, b)];
        while let Some((a, b)) = stack.pop() {
            let (pa, pb) = (curve(a), curve(b));
            let inner = [0.25, 0.5, 0.75].map(|f| curve(a + f * (b - a)));
            for p in [pa, pb].iter().chain(&inner) {
                if !(p.0.is_finite() && p.1.is_finite()) {
                    bail!(
                        "the curve has a non-finite point near cam angle {:.3} deg",
                        a.to_degrees()
                    );
                }
            }
            let err = inner
                .iter()
                .map(|p| to_segment(*p, pa, pb))
                .fold(0.0, f64::max);
            if err > bound && b - a > MIN_INTERVAL {
                let m = 0.5 * (a + b);
                stack.push((m, b));
                stack.push((a, m));
            } else {
                out.push(CurvePoint {
                    theta: a,
                    x: pa.0,
                    y: pa.1,
                });
                if out.len() > max_points {
                    bail!(
                        "{option} {bound:e}: needs more than {max_points} points on one curve; \
                         must be larger (the points of one revolution a measured file may have)"
                    );
                }
            }
        }
    }
    Ok(out)
}

/// The largest distance of `curve` from the closed polygon `points` (its chords,
/// the last back to the first), from `per_chord` points inside each chord's interval.
pub fn max_chord_error(
    curve: impl Fn(f64) -> (f64, f64),
    points: &[CurvePoint],
    per_chord: usize,
) -> f64 {
    let n = points.len();
    let mut worst: f64 = 0.0;
    for (i, p) in points.iter().enumerate() {
        let q = points[(i + 1) % n];
        let tb = if i + 1 == n {
            q.theta + std::f64::consts::TAU
        } else {
            q.theta
        };
        for j in 1..=per_chord {
            let t = p.theta + (tb - p.theta) * j as f64 / (per_chord + 1) as f64;
            worst = worst.max(to_segment(curve(t), (p.x, p.y), (q.x, q.y)));
        }
    }
    worst
}

/// A length unit of the drawing (`--units inch` draws in inches, `--units si` in
/// millimetres).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    /// Inches (the model's unit).
    #[default]
    In,
    /// Millimetres (25.4 per inch).
    Mm,
}

impl From<crate::units::Units> for Units {
    fn from(u: crate::units::Units) -> Self {
        match u {
            crate::units::Units::Inch => Units::In,
            crate::units::Units::Si => Units::Mm,
        }
    }
}

impl Units {
    /// Units per inch.
    pub fn per_inch(self) -> f64 {
        match self {
            Units::In => 1.0,
            Units::Mm => 25.4,
        }
    }

    /// The suffix of a column name (`x_in`, `x_mm`).
    pub fn name(self) -> &'static str {
        match self {
            Units::In => "in",
            Units::Mm => "mm",
        }
    }

    /// DXF `$INSUNITS`: 1 inch, 4 millimetre.
    pub fn insunits(self) -> u8 {
        match self {
            Units::In => 1,
            Units::Mm => 4,
        }
    }

    /// DXF `$MEASUREMENT`: 0 imperial, 1 metric.
    pub fn measurement(self) -> u8 {
        match self {
            Units::In => 0,
            Units::Mm => 1,
        }
    }
}

/// One closed curve of a drawing, its points in the drawing's unit.
#[derive(Clone, Debug)]
pub struct Layer<'a> {
    /// Layer name (upper case, letters, digits and `_`).
    pub name: &'static str,
    /// AutoCAD colour index.
    pub color: u8,
    /// The points, in order; the polyline closes back to the first.
    pub points: &'a [CurvePoint],
}

fn pair(out: &mut String, code: u16, value: impl std::fmt::Display) {
    let _ = write!(out, "{code:>3}\n{value}\n");
}

/// The R12 ASCII DXF of `layers` (each a closed polyline) with the unit in the header,
/// a `POINT` at the rotation centre on layer `CENTRE` and `note`'s lines as `TEXT`
/// entities on layer `0` below the drawing.
pub fn dxf(layers: &[Layer], units: Units, note: &[String]) -> String {
    let mut s = String::new();
    let (mut lo, mut hi) = ((0.0f64, 0.0f64), (0.0f64, 0.0f64));
    for p in layers.iter().flat_map(|l| l.points) {
        lo = (lo.0.min(p.x), lo.1.min(p.y));
        hi = (hi.0.max(p.x), hi.1.max(p.y));
    }
    // The note's text height: a fortieth of the drawing's height, lines 1.5 apart.
    let height = (hi.1 - lo.1) / 40.0;
    let text_top = lo.1 - 2.0 * height;
    lo.1 = text_top - 1.5 * height * note.len() as f64;
    pair(
        &mut s,
        999,
        "camsim profile: cam drawing, rotation centre at the origin",
    );
    dxf_header(&mut s, units, lo, hi);
    dxf_tables(&mut s, layers);
    dxf_entities(&mut s, layers, note, (lo.0, text_top, height));
    pair(&mut s, 0, "EOF");
    s
}

/// The DXF's HEADER section: the version, the unit and the drawing's extent.
fn dxf_header(s: &mut String, units: Units, lo: (f64, f64), hi: (f64, f64)) {
    pair(s, 0, "SECTION");
    pair(s, 2, "HEADER");
    pair(s, 9, "$ACADVER");
    pair(s, 1, "AC1009");
    pair(s, 9, "$INSUNITS");
    pair(s, 70, units.insunits());
    pair(s, 9, "$MEASUREMENT");
    pair(s, 70, units.measurement());
    for (name, p) in [("$EXTMIN", lo), ("$EXTMAX", hi)] {
        pair(s, 9, name);
        pair(s, 10, format!("{:.10}", p.0));
        pair(s, 20, format!("{:.10}", p.1));
        pair(s, 30, "0.0");
    }
    pair(s, 0, "ENDSEC");
}

/// The DXF's TABLES section: the continuous line type and a layer for each of `layers`
/// and the centre point.
fn dxf_tables(s: &mut String, layers: &[Layer]) {
    pair(s, 0, "SECTION");
    pair(s, 2, "TABLES");
    pair(s, 0, "TABLE");
    pair(s, 2, "LTYPE");
    pair(s, 70, 1);
    pair(s, 0, "LTYPE");
    pair(s, 2, "CONTINUOUS");
    pair(s, 70, 0);
    pair(s, 3, "Solid line");
    pair(s, 72, 65);
    pair(s, 73, 0);
    pair(s, 40, "0.0");
    pair(s, 0, "ENDTAB");
    pair(s, 0, "TABLE");
    pair(s, 2, "LAYER");
    pair(s, 70, layers.len() + 1);
    let centre = Layer {
        name: "CENTRE",
        color: 8,
        points: &[],
    };
    for l in layers.iter().chain([&centre]) {
        pair(s, 0, "LAYER");
        pair(s, 2, l.name);
        pair(s, 70, 0);
        pair(s, 62, l.color);
        pair(s, 6, "CONTINUOUS");
    }
    pair(s, 0, "ENDTAB");
    pair(s, 0, "ENDSEC");
}

/// The DXF's ENTITIES section: `layers` as closed polylines, the centre point, and
/// `note`'s lines as TEXT at (x, top) going down, `height` high and 1.5 heights apart.
fn dxf_entities(s: &mut String, layers: &[Layer], note: &[String], text: (f64, f64, f64)) {
    let (x, text_top, height) = text;
    pair(s, 0, "SECTION");
    pair(s, 2, "ENTITIES");
    for l in layers {
        pair(s, 0, "POLYLINE");
        pair(s, 8, l.name);
        pair(s, 66, 1);
        pair(s, 10, "0.0");
        pair(s, 20, "0.0");
        pair(s, 30, "0.0");
        pair(s, 70, 1);
        for p in l.points {
            pair(s, 0, "VERTEX");
            pair(s, 8, l.name);
            pair(s, 10, format!("{:.10}", p.x));
            pair(s, 20, format!("{:.10}", p.y));
            pair(s, 30, "0.0");
        }
        pair(s, 0, "SEQEND");
        pair(s, 8, l.name);
    }
    pair(s, 0, "POINT");
    pair(s, 8, "CENTRE");
    pair(s, 10, "0.0");
    pair(s, 20, "0.0");
    pair(s, 30, "0.0");
    for (k, line) in note.iter().enumerate() {
        pair(s, 0, "TEXT");
        pair(s, 8, "0");
        pair(s, 10, format!("{x:.10}"));
        pair(s, 20, format!("{:.10}", text_top - 1.5 * height * k as f64));
        pair(s, 30, "0.0");
        pair(s, 40, format!("{height:.10}"));
        pair(s, 1, line);
    }
    pair(s, 0, "ENDSEC");
}

/// A polyline as [`read_dxf`] finds it: layer, closed flag set, vertices (x, y).
pub type DxfPolyline = (String, bool, Vec<(f64, f64)>);

/// What a structural reading of a DXF finds (for the tests: a reader independent of
/// the writer's code paths, from the group-code pairs alone).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DxfSummary {
    /// `$INSUNITS`.
    pub insunits: Option<i64>,
    /// Per POLYLINE: layer, closed flag set, vertices (x, y).
    pub polylines: Vec<DxfPolyline>,
    /// Entities in ENTITIES (POLYLINE counts once; VERTEX and SEQEND are its parts).
    pub entities: usize,
    /// Whether the file ends with `0 EOF`.
    pub eof: bool,
}

/// Reads the group-code pairs of an ASCII DXF into a [`DxfSummary`]; refuses a file
/// whose lines do not pair into (integer code, value).
pub fn read_dxf(text: &str) -> Result<DxfSummary> {
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() % 2 != 0 {
        bail!("odd number of lines: not code/value pairs");
    }
    let mut pairs = Vec::with_capacity(lines.len() / 2);
    for c in lines.chunks(2) {
        let code: i64 = c[0].trim().parse()?;
        pairs.push((code, c[1].trim()));
    }
    let mut sum = DxfSummary::default();
    let mut in_entities = false;
    let mut i = 0;
    while i < pairs.len() {
        let (code, v) = pairs[i];
        if code == 9 && v == "$INSUNITS" {
            sum.insunits = pairs.get(i + 1).and_then(|p| p.1.parse().ok());
        }
        if code == 2 && v == "ENTITIES" {
            in_entities = true;
        }
        if code == 0 && v == "ENDSEC" {
            in_entities = false;
        }
        if code == 0 && v == "EOF" {
            sum.eof = i + 1 == pairs.len();
        }
        if in_entities && code == 0 && v != "VERTEX" && v != "SEQEND" {
            sum.entities += 1;
        }
        if in_entities && code == 0 && v == "POLYLINE" {
            let (mut layer, mut closed) = (String::new(), false);
            let mut verts = Vec::new();
            let mut j = i + 1;
            while j < pairs.len() && pairs[j].0 != 0 {
                match pairs[j].0 {
                    8 => layer = pairs[j].1.to_string(),
                    70 => closed = pairs[j].1.parse::<i64>().unwrap_or(0) & 1 == 1,
                    _ => {}
                }
                j += 1;
            }
            while j < pairs.len() && pairs[j] == (0, "VERTEX") {
                let (mut x, mut y) = (f64::NAN, f64::NAN);
                j += 1;
                while j < pairs.len() && pairs[j].0 != 0 {
                    match pairs[j].0 {
                        10 => x = pairs[j].1.parse()?,
                        20 => y = pairs[j].1.parse()?,
                        _ => {}
                    }
                    j += 1;
                }
                verts.push((x, y));
            }
            if pairs.get(j) != Some(&(0, "SEQEND")) {
                bail!("POLYLINE on layer {layer} without SEQEND");
            }
            sum.polylines.push((layer, closed, verts));
            i = j;
            continue;
        }
        i += 1;
    }
    Ok(sum)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_is_sampled_to_its_sagitta() {
        // A circle of radius ρ: chords of equal length L = 2ρ sin(Δ/2) have the sagitta
        // ρ(1 - cos(Δ/2)). Halving from 72 intervals stops at the first power of two whose
        // sagitta is within the bound: the count is known in closed form.
        let rho = 1.5;
        for bound in [1e-3, 1e-4, 1e-5, 1e-6] {
            let pts = adaptive(
                |t| (rho * t.sin(), rho * t.cos()),
                bound,
                100_000,
                "--chord-error",
            )
            .unwrap();
            let mut n = START_INTERVALS;
            while rho * (1.0 - (std::f64::consts::PI / n as f64).cos()) > bound {
                n *= 2;
            }
            assert_eq!(pts.len(), n, "{bound}");
            let err = max_chord_error(|t| (rho * t.sin(), rho * t.cos()), &pts, 15);
            let sagitta = rho * (1.0 - (std::f64::consts::PI / n as f64).cos());
            assert!(
                err <= bound && (err - sagitta).abs() < 1e-3 * sagitta,
                "{err} {sagitta}"
            );
            // ... and not four times finer than needed.
            assert!(err > bound / 4.1, "{err} {bound}");
        }
    }

    #[test]
    fn too_fine_a_bound_is_refused_by_name() {
        let e = adaptive(|t| (t.sin(), t.cos()), 1e-12, 1000, "--chord-error").unwrap_err();
        assert!(e
            .to_string()
            .starts_with("--chord-error 1e-12: needs more than 1000"));
    }

    #[test]
    fn the_dxf_reads_back_structurally() {
        let pts: Vec<CurvePoint> = (0..10)
            .map(|k| {
                let t = k as f64 * 0.6;
                CurvePoint {
                    theta: t,
                    x: t.sin(),
                    y: -t.cos() * 2.0,
                }
            })
            .collect();
        let text = dxf(
            &[
                Layer {
                    name: "SURFACE",
                    color: 7,
                    points: &pts,
                },
                Layer {
                    name: "PITCH",
                    color: 1,
                    points: &pts[..4],
                },
            ],
            Units::Mm,
            &["Units: mm".to_string()],
        );
        let s = read_dxf(&text).unwrap();
        assert_eq!(s.insunits, Some(4));
        assert!(s.eof);
        // Two polylines, the centre point and the note's one TEXT.
        assert_eq!(s.entities, 4);
        assert_eq!(s.polylines.len(), 2);
        assert_eq!(s.polylines[0].0, "SURFACE");
        assert!(s.polylines.iter().all(|p| p.1));
        assert_eq!(s.polylines[1].2.len(), 4);
        for (p, v) in pts.iter().zip(&s.polylines[0].2) {
            assert!((p.x - v.0).abs() < 1e-9 && (p.y - v.1).abs() < 1e-9);
        }
    }
}
