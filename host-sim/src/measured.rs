//! Measured profiles: `camsim run --measured FILE.csv`.
//!
//! # File format
//!
//! Text, one row a line, two comma-separated columns; blank lines and lines starting
//! with `#` are skipped (a UTF-8 byte-order mark and `\r\n` line ends are accepted). The
//! first other line is the header, which says what the second column is:
//!
//! * `angle_deg,deviation_in`: the follower's lift deviation from the design's program
//!   (in) at the cam angle (deg): what a roller of the design's radius on the follower
//!   axis reads minus the program's lift;
//! * `angle_deg,lift_in`: the follower's lift itself (in); the deviation is the lift
//!   minus the program's lift at that angle;
//! * `angle_deg,radius_in`: the cam surface's polar radius (in) at the polar angle
//!   (deg) in the cam's own frame, measured from the rotation centre with a pointed
//!   probe (a CMM or a dial on a dividing head); angle 0 is where the follower axis
//!   points at cam angle 0 and angles grow the way the cam angle does. The roller's
//!   lift follows by the exact envelope of the design's roller circle on that contour
//!   (camsim-core's `envelope` module, docs/MODEL.md §8.4).
//!
//! The rows must have finite numbers, angles strictly increasing from a first angle in
//! `[0, 360)`, and cover one revolution: either a last row at exactly first + 360 deg
//! repeating the first row's value (it closes the revolution and is dropped) or a
//! last angle below first + 360 whose gap back to first + 360 is at most 1.5 times the
//! largest step between rows (so a file that stops half way is refused). Radii must be
//! positive. Values must be plausible: a deviation within ±0.1 in (40 times the thesis's
//! loosest tolerance), a lift within [-0.1, 100] in, a radius within [0.01, 100] in (the
//! scene's lengths). At least 4 and at most [`MAX_POINTS`] rows. The profile is the periodic
//! cubic spline through the rows (any spacing).
//!
//! Every error names the line it is about: `line 7: angle_deg "1O" is not a number`.

use std::fmt;
use std::path::Path;

use anyhow::{Context, Result};
use camsim_core::{ActualCam, ActualContour, CubicSpline, Design, DeviatedLift};
use serde::Serialize;

use crate::actual::deviation_stats;
use crate::sim::{HostDeviation, PROFILE_KNOTS};

/// The most rows a measured revolution may have (the host's deviation spline).
pub const MAX_POINTS: usize = PROFILE_KNOTS - 1;

/// What the second column holds (from the header).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Column {
    /// `deviation_in`: the lift deviation from the program, in.
    #[serde(rename = "deviation_in")]
    Deviation,
    /// `lift_in`: the follower lift, in.
    #[serde(rename = "lift_in")]
    Lift,
    /// `radius_in`: the cam surface's polar radius, in.
    #[serde(rename = "radius_in")]
    Radius,
}

impl Column {
    /// The header name.
    pub fn name(self) -> &'static str {
        match self {
            Column::Deviation => "deviation_in",
            Column::Lift => "lift_in",
            Column::Radius => "radius_in",
        }
    }

    /// The plausibility range of the column's values, in, and its reason (the one
    /// validation's ranges, docs/MODEL.md §5.16: lengths 0.01-100 in).
    pub fn plausible(self) -> (f64, f64, &'static str) {
        match self {
            // 40 times the thesis's loosest cam tolerance (±0.0025 in): a larger error
            // is a different cam, not a machined one.
            Column::Deviation => (-0.1, 0.1, "a profile error, at most 40x a loose tolerance"),
            // Below the base circle by at most a deviation, above it at most the longest
            // length a scene may have.
            Column::Lift => (-0.1, 100.0, "a lift from the base circle"),
            Column::Radius => (0.01, 100.0, "a cam radius, as the scene's lengths"),
        }
    }
}

/// A parsed, validated measured revolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// What `values_in` are.
    pub column: Column,
    /// Angles, degrees: strictly increasing, the first in `[0, 360)`, all below the first
    /// + 360 (a closing row is dropped).
    pub angles_deg: Vec<f64>,
    /// The second column, in.
    pub values_in: Vec<f64>,
}

/// Why a measured file was refused: the line (from 1) and what is wrong.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParseError {
    /// Line number, from 1.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "line {}: {}", self.line, self.message)
    }
}

impl std::error::Error for ParseError {}

const HEADERS: &str =
    "\"angle_deg,deviation_in\", \"angle_deg,lift_in\" or \"angle_deg,radius_in\"";

fn err(line: usize, message: impl Into<String>) -> ParseError {
    ParseError {
        line,
        message: message.into(),
    }
}

/// Quotes a field for an error message, cut to 40 characters.
fn quoted(s: &str) -> String {
    let cut: String = s.chars().take(40).collect();
    if cut.len() < s.len() {
        format!("\"{cut}...\"")
    } else {
        format!("\"{cut}\"")
    }
}

/// Plain digits, or an exponent where they would run long (1e300), as core's errors.
fn short(v: f64) -> String {
    if v == 0.0 || (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

fn number(line: usize, name: &str, field: &str) -> Result<f64, ParseError> {
    let v: f64 = field
        .parse()
        .map_err(|_| err(line, format!("{name} {} is not a number", quoted(field))))?;
    if !v.is_finite() {
        return Err(err(line, format!("{name} {} is not finite", quoted(field))));
    }
    Ok(v)
}

/// Parses and validates a measured file's text (see the module docs). Never panics.
pub fn parse(text: &str) -> Result<Measured, ParseError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut column = None;
    let (mut angles, mut values, mut lines) = (Vec::new(), Vec::new(), Vec::new());
    let mut closed = false;
    let mut last_line = 0;
    for (i, raw) in text.split('\n').enumerate() {
        let line = i + 1;
        last_line = line;
        let content = raw.strip_suffix('\r').unwrap_or(raw).trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let Some(col) = column else {
            column = Some(match fields.as_slice() {
                [a, b] if a.eq_ignore_ascii_case("angle_deg") => {
                    match b.to_ascii_lowercase().as_str() {
                        "deviation_in" => Column::Deviation,
                        "lift_in" => Column::Lift,
                        "radius_in" => Column::Radius,
                        _ => {
                            return Err(err(
                                line,
                                format!("the header must be {HEADERS}, found {}", quoted(content)),
                            ))
                        }
                    }
                }
                _ => {
                    return Err(err(
                        line,
                        format!("the header must be {HEADERS}, found {}", quoted(content)),
                    ))
                }
            });
            continue;
        };
        let [a, v] = fields.as_slice() else {
            return Err(err(
                line,
                format!("expected 2 comma-separated values, found {}", fields.len()),
            ));
        };
        if closed {
            return Err(err(
                line,
                "a row after the closing row (first angle + 360 deg) is past one revolution",
            ));
        }
        let angle = number(line, "angle_deg", a)?;
        let value = number(line, col.name(), v)?;
        if col == Column::Radius && value <= 0.0 {
            return Err(err(
                line,
                format!("radius_in must be positive, found {value}"),
            ));
        }
        let (lo, hi, why) = col.plausible();
        if !(lo..=hi).contains(&value) {
            return Err(err(
                line,
                format!(
                    "{} {} must lie in [{lo}, {hi}] in ({why})",
                    col.name(),
                    short(value)
                ),
            ));
        }
        match (angles.first(), angles.last(), lines.last()) {
            (Some(&first), Some(&prev), Some(&prev_line)) => {
                if angle <= prev {
                    return Err(err(
                        line,
                        format!(
                            "angle {angle} deg does not increase (line {prev_line} has {prev} deg)"
                        ),
                    ));
                }
                let end = first + 360.0;
                if (angle - end).abs() <= 1e-9 * end {
                    let v0 = values.first().copied().unwrap_or(value);
                    if (value - v0).abs() > 1e-9 {
                        return Err(err(
                            line,
                            format!(
                                "the closing row at {angle} deg (first angle + 360) must repeat the first row's value {v0}, found {value}"
                            ),
                        ));
                    }
                    closed = true;
                    continue;
                }
                if angle > end {
                    return Err(err(
                        line,
                        format!("angle {angle} deg is past one revolution from the first row's {first} deg"),
                    ));
                }
            }
            _ => {
                if !(0.0..360.0).contains(&angle) {
                    return Err(err(
                        line,
                        format!("the first angle must be in [0, 360) deg, found {angle}"),
                    ));
                }
            }
        }
        if angles.len() >= MAX_POINTS {
            return Err(err(
                line,
                format!("more than {MAX_POINTS} rows in a revolution"),
            ));
        }
        angles.push(angle);
        values.push(value);
        lines.push(line);
    }
    let Some(column) = column else {
        return Err(err(
            last_line.max(1),
            format!("no header: the file must start with {HEADERS}"),
        ));
    };
    let at = lines.last().copied().unwrap_or(last_line.max(1));
    if angles.len() < 4 {
        return Err(err(
            at,
            format!(
                "at least 4 rows a revolution are needed, found {}",
                angles.len()
            ),
        ));
    }
    if !closed {
        let (first, last) = (
            angles.first().copied().unwrap_or(0.0),
            angles.last().copied().unwrap_or(0.0),
        );
        let step = angles.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
        let gap = first + 360.0 - last;
        if gap > 1.5 * step * (1.0 + 1e-9) {
            return Err(err(
                at,
                format!(
                    "the rows end at {last} deg: they must cover a full revolution from {first} deg \
                     (the gap back to {} deg, {gap} deg, is more than 1.5 times the largest step \
                     between rows, {step} deg; or close it with a row at {} deg)",
                    first + 360.0,
                    first + 360.0
                ),
            ));
        }
    }
    Ok(Measured {
        column,
        angles_deg: angles,
        values_in: values,
    })
}

/// Reads and parses a measured file; errors name the file and the line.
pub fn load(path: &Path) -> Result<Measured> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read --measured {}", path.display()))?;
    parse(&text).with_context(|| format!("--measured {}", path.display()))
}

/// What a measured profile is (the JSON `profile` of `camsim run --measured`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasuredStats {
    /// Always "measured".
    pub method: &'static str,
    /// The file's second column.
    pub column: Column,
    /// Rows of the revolution (a closing row not counted).
    pub points: usize,
    /// Knots of the deviation spline over one revolution (the rows, or for radii the
    /// envelope's output points).
    pub deviation_knots: usize,
    /// RMS of the lift deviation over one revolution, in.
    pub rms_deviation_in: f64,
    /// Mean of the lift deviation, in.
    pub mean_deviation_in: f64,
    /// Largest |lift deviation|, in.
    pub max_abs_deviation_in: f64,
    /// RMS of the deviation's second derivative d²e/dθ², in/rad².
    pub rms_curvature_in_per_rad2: f64,
    /// Waviness frequency per revolution (as for `--actual`).
    pub fpr: usize,
}

/// One revolution's periodic spline through `(angles, values)`, closed at the first
/// angle + 360.
fn periodic(angles_deg: &[f64], values: &[f64]) -> Result<CubicSpline<f64, PROFILE_KNOTS>> {
    let first = angles_deg.first().copied().unwrap_or(0.0);
    let mut knots: Vec<f64> = angles_deg.iter().map(|a| a.to_radians()).collect();
    knots.push(first.to_radians() + 2.0 * std::f64::consts::PI);
    let mut v = values.to_vec();
    v.push(values.first().copied().unwrap_or(0.0));
    CubicSpline::periodic(&knots, &v).map_err(|e| anyhow::anyhow!("measured profile: {e}"))
}

impl Measured {
    /// The lift deviation this revolution gives on `design` (see the module docs) and its
    /// statistics.
    pub fn profile(&self, design: &Design<f64>) -> Result<(HostDeviation, MeasuredStats)> {
        let program = &design.program;
        let dev: HostDeviation = match self.column {
            Column::Deviation => {
                DeviatedLift::from_spline(periodic(&self.angles_deg, &self.values_in)?)?
            }
            Column::Lift => {
                let e: Vec<f64> = self
                    .angles_deg
                    .iter()
                    .zip(&self.values_in)
                    .map(|(a, l)| l - program.follower(a.to_radians()).y)
                    .collect();
                DeviatedLift::from_spline(periodic(&self.angles_deg, &e)?)?
            }
            Column::Radius => {
                let xs: Vec<f64> = self
                    .angles_deg
                    .iter()
                    .zip(&self.values_in)
                    .map(|(a, r)| r * a.to_radians().sin())
                    .collect();
                let ys: Vec<f64> = self
                    .angles_deg
                    .iter()
                    .zip(&self.values_in)
                    .map(|(a, r)| r * a.to_radians().cos())
                    .collect();
                let contour = Box::new(ActualContour::<f64, PROFILE_KNOTS>::from_splines(
                    periodic(&self.angles_deg, &xs)?,
                    periodic(&self.angles_deg, &ys)?,
                )?);
                let cam = ActualCam::new(*contour, design.geometry.roller_radius, (0.0, 0.0))?;
                let out = crate::actual::envelope_knots(self.angles_deg.len());
                DeviatedLift::envelope(program, &design.geometry, &cam, out)
                    .context("the roller's envelope on the measured contour")?
            }
        };
        let ds = deviation_stats(&dev)?;
        let knots = dev.spline().len().saturating_sub(1);
        Ok((
            dev,
            MeasuredStats {
                method: "measured",
                column: self.column,
                points: self.angles_deg.len(),
                deviation_knots: knots,
                rms_deviation_in: ds.rms_deviation_in,
                mean_deviation_in: ds.mean_deviation_in,
                max_abs_deviation_in: ds.max_abs_deviation_in,
                rms_curvature_in_per_rad2: ds.rms_curvature_in_per_rad2,
                fpr: ds.fpr,
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_of(text: &str) -> (usize, String) {
        let e = parse(text).unwrap_err();
        (e.line, e.to_string())
    }

    fn uniform(header: &str, n: usize, close: bool) -> String {
        let mut s = format!("{header}\n");
        for k in 0..n {
            s += &format!("{},{}\n", k as f64 * 360.0 / n as f64, 1e-5 * k as f64);
        }
        if close {
            s += "360,0\n";
        }
        s
    }

    #[test]
    fn good_files() {
        let m = parse(&uniform("angle_deg,deviation_in", 360, false)).unwrap();
        assert_eq!((m.column, m.angles_deg.len()), (Column::Deviation, 360));
        let m = parse(&uniform("angle_deg,lift_in", 8, true)).unwrap();
        assert_eq!((m.column, m.angles_deg.len()), (Column::Lift, 8));
        // Comments, blank lines, CRLF, BOM, spaces, upper case header.
        let m = parse("\u{feff}# probe 3\r\n\r\n ANGLE_DEG , Radius_In \r\n0,1.5\r\n90, 1.5\n180,1.5\n# gap\n270,1.5").unwrap();
        assert_eq!(m.column, Column::Radius);
        assert_eq!(m.angles_deg, vec![0.0, 90.0, 180.0, 270.0]);
        // A start off zero, closed at +360.
        let m = parse("angle_deg,lift_in\n10,1\n100,2\n190,3\n280,4\n370,1\n").unwrap();
        assert_eq!(m.values_in, vec![1.0, 2.0, 3.0, 4.0]);
    }

    #[test]
    fn errors_name_the_line() {
        let h = "angle_deg,deviation_in\n";
        let cases: [(String, usize, &str); 15] = [
            (String::new(), 1, "no header"),
            ("# only\n\n".into(), 3, "no header"),
            ("angle,deviation_in\n0,0\n".into(), 1, "the header must be"),
            (
                "angle_deg,deviation_in\n0,0\n90,1e300\n".into(),
                3,
                "deviation_in 1e300 must lie in [-0.1, 0.1] in",
            ),
            (
                "angle_deg,radius_in\n0,1\n90,1e-300\n".into(),
                3,
                "radius_in 1e-300 must lie in [0.01, 100] in",
            ),
            ("angle_deg,deviation_in,x\n".into(), 1, "the header must be"),
            (
                format!("{h}0,0\n1;0\n"),
                3,
                "expected 2 comma-separated values, found 1",
            ),
            (
                format!("{h}0,0\n1O,0\n"),
                3,
                "angle_deg \"1O\" is not a number",
            ),
            (
                format!("{h}0,0\n1,inf\n"),
                3,
                "deviation_in \"inf\" is not finite",
            ),
            (
                format!("{h}0,0\n90,0\n90,0\n"),
                4,
                "angle 90 deg does not increase (line 3 has 90 deg)",
            ),
            (
                format!("{h}-1,0\n"),
                2,
                "the first angle must be in [0, 360)",
            ),
            (
                format!("{h}0,0\n90,0\n180,0\n270,0\n360,0.05\n"),
                6,
                "must repeat the first row's value 0",
            ),
            (
                format!("{h}0,0\n90,0\n180,0\n270,0\n360,0\n361,0\n"),
                7,
                "after the closing row",
            ),
            (format!("{h}0,0\n90,0\n180,0\n"), 4, "at least 4 rows"),
            (
                format!("{h}0,0\n10,0\n20,0\n30,0\n"),
                5,
                "must cover a full revolution",
            ),
        ];
        for (text, line, msg) in cases {
            let (l, m) = line_of(&text);
            assert_eq!(l, line, "{text:?}: {m}");
            assert!(
                m.starts_with(&format!("line {line}: ")) && m.contains(msg),
                "{text:?}: {m}"
            );
        }
        assert!(line_of("angle_deg,radius_in\n0,1\n90,0\n")
            .1
            .contains("radius_in must be positive"));
        assert!(line_of(&format!("{h}0,0\n90,0\n180,0\n270,0\n400,0\n"))
            .1
            .contains("past one revolution"));
        let long = uniform("angle_deg,deviation_in", MAX_POINTS + 1, false);
        assert_eq!(line_of(&long).0, MAX_POINTS + 2);
    }

    #[test]
    fn no_panic_on_odd_input() {
        for text in [
            "\u{feff}",
            ",",
            "angle_deg,lift_in\n,,\n",
            "angle_deg,lift_in\n0,\n",
            "\r\r\n",
            "angle_deg,lift_in\n1e309,0",
        ] {
            assert!(parse(text).is_err(), "{text:?}");
        }
    }
}
