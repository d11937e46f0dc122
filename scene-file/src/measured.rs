//! Measured cam profiles (CSV): one reader for the host (`camsim run --measured`,
//! `camsim predict --measured`) and the firmware's build script (`CAMSIM_PROFILE`), so a
//! file the host refuses never reaches the chip and both turn it into the same deviation
//! knots.
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
//! Each header may end in `_mm` instead (`angle_deg,lift_mm`, `radius_mm`,
//! `deviation_mm`): the values are millimetres, read as exactly 1/25.4 in.
//!
//! The rows must have finite numbers, angles strictly increasing from a first angle in
//! `[0, 360)`, and cover one revolution: either a last row at exactly first + 360 deg
//! repeating the first row's value (it closes the revolution and is dropped) or a
//! last angle below first + 360 whose gap back to first + 360 is at most 1.5 times the
//! largest step between rows (so a file that stops half way is refused). Radii must be
//! positive. Values must be plausible: a deviation within ±0.1 in (40 times the thesis's
//! loosest tolerance), a lift within [-0.1, 100] in, a radius within [0.01, 100] in (the
//! scene's lengths). At least 4 and at most [`MAX_POINTS`] rows ([`parse_limited`]: fewer,
//! e.g. the chip's capacity). The profile is the periodic cubic spline through the rows
//! (any spacing): [`Measured::deviation`]. A lift or radius profile must follow the
//! scene's program within the deviation's ±0.1 in (a larger gap is another cam, or a
//! file whose unit is not its header's: the refusal says which unit would fit).
//!
//! Every error names the line it is about: `line 7: angle_deg "1O" is not a number`.

use std::fmt;
use std::path::Path;

use camsim_core::{
    check_envelope, sampled_deviation, Design, DeviatedLift, EnvelopeLimits, SampledError, Samples,
};
use serde::Serialize;

/// Knots of a measured revolution's deviation spline on the host: one revolution at down
/// to 0.1° (the host's `PROFILE_KNOTS`).
pub const MEASURED_KNOTS: usize = 3601;

/// A measured profile's lift deviation in `f64` (the program plus this spline).
pub type MeasuredDeviation = DeviatedLift<f64, MEASURED_KNOTS>;

/// The most rows a measured revolution may have (the host's deviation spline).
pub const MAX_POINTS: usize = MEASURED_KNOTS - 1;

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

/// A measured file's length unit: its column header's suffix (`lift_in`, `lift_mm`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Unit {
    /// `_in`: inches, the thesis's unit.
    #[serde(rename = "in")]
    Inch,
    /// `_mm`: millimetres (exactly 1/25.4 in).
    #[serde(rename = "mm")]
    Millimetre,
}

impl Unit {
    /// The suffix (`in`, `mm`).
    pub fn name(self) -> &'static str {
        match self {
            Unit::Inch => "in",
            Unit::Millimetre => "mm",
        }
    }

    /// The unit's count in one inch (1, or exactly 25.4).
    pub fn per_inch(self) -> f64 {
        match self {
            Unit::Inch => 1.0,
            Unit::Millimetre => crate::units::MM_PER_IN,
        }
    }

    /// The unit in words (`inches`).
    pub fn long(self) -> &'static str {
        match self {
            Unit::Inch => "inches",
            Unit::Millimetre => "millimetres",
        }
    }

    /// The other unit.
    fn other(self) -> Unit {
        match self {
            Unit::Inch => Unit::Millimetre,
            Unit::Millimetre => Unit::Inch,
        }
    }
}

impl Column {
    /// The header name in `unit` (`lift_mm`).
    pub fn header(self, unit: Unit) -> String {
        let name = self.name();
        format!(
            "{}_{}",
            name.strip_suffix("_in").unwrap_or(name),
            unit.name()
        )
    }
}

/// The smallest convex cam surface radius a radius profile may imply along the roller's
/// path, in: 0.01 in, the smallest length a scene may have (docs/MODEL.md §5.16) and the
/// bound of a `radius_in` value. Below it the surface is an edge: at the reference's
/// 200 lb peak contact force its Hertz stress would pass 6e5 psi, beyond the static
/// capacity of hardened bearing steel.
pub const MIN_SURFACE_RADIUS_IN: f64 = 0.01;

/// A parsed, validated measured revolution.
#[derive(Clone, Debug, PartialEq)]
pub struct Measured {
    /// What `values_in` are.
    pub column: Column,
    /// The file's length unit (its header's suffix); `values_in` are in inches.
    pub unit: Unit,
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
    "\"angle_deg,deviation_in\", \"angle_deg,lift_in\" or \"angle_deg,radius_in\" (or _mm for millimetres)";

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
    parse_limited(text, MAX_POINTS)
}

/// [`parse`] with at most `max_points` rows (at most [`MAX_POINTS`]): the chip's
/// capacity refuses a longer file at its first row too many, naming the line.
pub fn parse_limited(text: &str, max_points: usize) -> Result<Measured, ParseError> {
    let max_points = max_points.min(MAX_POINTS);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header = None;
    let mut rows = Rows::default();
    let mut last_line = 0;
    for (i, raw) in text.split('\n').enumerate() {
        let line = i + 1;
        last_line = line;
        let content = raw.strip_suffix('\r').unwrap_or(raw).trim();
        if content.is_empty() || content.starts_with('#') {
            continue;
        }
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let Some((col, unit)) = header else {
            header = Some(column_of_header(line, content, &fields)?);
            continue;
        };
        let [a, v] = fields.as_slice() else {
            return Err(err(
                line,
                format!("expected 2 comma-separated values, found {}", fields.len()),
            ));
        };
        if rows.closed {
            return Err(err(
                line,
                "a row after the closing row (first angle + 360 deg) is past one revolution",
            ));
        }
        let angle = number(line, "angle_deg", a)?;
        let value = value_in_inches(line, col, unit, v)?;
        rows.push(line, angle, value, max_points)?;
    }
    let Some((column, unit)) = header else {
        return Err(err(
            last_line.max(1),
            format!("no header: the file must start with {HEADERS}"),
        ));
    };
    rows.check_revolution(last_line)?;
    Ok(Measured {
        column,
        unit,
        angles_deg: rows.angles,
        values_in: rows.values,
    })
}

/// The second column and the unit a header line names (`angle_deg,lift_mm`).
fn column_of_header(
    line: usize,
    content: &str,
    fields: &[&str],
) -> Result<(Column, Unit), ParseError> {
    let refused = || {
        err(
            line,
            format!("the header must be {HEADERS}, found {}", quoted(content)),
        )
    };
    let [a, b] = fields else {
        return Err(refused());
    };
    if !a.eq_ignore_ascii_case("angle_deg") {
        return Err(refused());
    }
    let b = b.to_ascii_lowercase();
    let (name, unit) = match b.rsplit_once('_') {
        Some((n, "in")) => (n, Unit::Inch),
        Some((n, "mm")) => (n, Unit::Millimetre),
        _ => ("", Unit::Inch),
    };
    let column = match name {
        "deviation" => Column::Deviation,
        "lift" => Column::Lift,
        "radius" => Column::Radius,
        _ => return Err(refused()),
    };
    Ok((column, unit))
}

/// A row's second-column field, checked (finite, a positive radius, plausible in the
/// file's unit) and converted to inches.
fn value_in_inches(line: usize, col: Column, unit: Unit, field: &str) -> Result<f64, ParseError> {
    let header = col.header(unit);
    let value = number(line, &header, field)?;
    if col == Column::Radius && value <= 0.0 {
        return Err(err(
            line,
            format!("{header} must be positive, found {value}"),
        ));
    }
    let (lo, hi, why) = col.plausible();
    let (lo, hi) = (lo * unit.per_inch(), hi * unit.per_inch());
    if !(lo..=hi).contains(&value) {
        return Err(err(
            line,
            format!(
                "{header} {} must lie in [{}, {}] {} ({why})",
                short(value),
                short(lo),
                short(hi),
                unit.name()
            ),
        ));
    }
    // Kept in inches.
    Ok(value / unit.per_inch())
}

/// The rows of one revolution read so far: angles (deg), values (in), their lines, and
/// whether a closing row (first angle + 360 deg) has been read.
#[derive(Default)]
struct Rows {
    angles: Vec<f64>,
    values: Vec<f64>,
    lines: Vec<usize>,
    closed: bool,
}

impl Rows {
    /// Adds a row at `line`: its angle must increase and stay within one revolution of
    /// the first; a row at exactly first + 360 deg must repeat the first value and
    /// closes the revolution (it is not kept).
    fn push(
        &mut self,
        line: usize,
        angle: f64,
        value: f64,
        max_points: usize,
    ) -> Result<(), ParseError> {
        match (self.angles.first(), self.angles.last(), self.lines.last()) {
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
                    let v0 = self.values.first().copied().unwrap_or(value);
                    if (value - v0).abs() > 1e-9 {
                        return Err(err(
                            line,
                            format!(
                                "the closing row at {angle} deg (first angle + 360) must repeat the first row's value {v0}, found {value}"
                            ),
                        ));
                    }
                    self.closed = true;
                    return Ok(());
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
        if self.angles.len() >= max_points {
            return Err(err(
                line,
                format!("more than {max_points} rows in a revolution"),
            ));
        }
        self.angles.push(angle);
        self.values.push(value);
        self.lines.push(line);
        Ok(())
    }

    /// At least 4 rows, and (unless closed) a last row whose gap back to first + 360 deg
    /// is at most 1.5 times the largest step; an error names the last row's line (or
    /// `last_line`, the file's last, when there is none).
    fn check_revolution(&self, last_line: usize) -> Result<(), ParseError> {
        let angles = &self.angles;
        let at = self.lines.last().copied().unwrap_or(last_line.max(1));
        if angles.len() < 4 {
            return Err(err(
                at,
                format!(
                    "at least 4 rows a revolution are needed, found {}",
                    angles.len()
                ),
            ));
        }
        if self.closed {
            return Ok(());
        }
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
        Ok(())
    }
}

/// Most bytes of a measured file read (3 600 rows of long numbers fit many times over).
pub const MAX_MEASURED_BYTES: u64 = 4 << 20;

/// Reads `path` (at most [`MAX_MEASURED_BYTES`]) and parses it with at most `max_points`
/// rows ([`parse_limited`]); the error is one line and starts with the file's name.
pub fn load_limited(path: &Path, max_points: usize) -> Result<Measured, String> {
    let text = crate::read_text(path, MAX_MEASURED_BYTES, "the measured profile")
        .map_err(|e| e.to_string())?;
    // The name escaped as a scene file's is (`crate::Error`): one line whatever it holds.
    parse_limited(&text, max_points)
        .map_err(|e| crate::Error::new(format!("{}: {e}", path.display())).to_string())
}

/// The envelope's output knots for a contour of `intervals` rows: 8 per row, within the
/// spline's capacity (camsim-core's `envelope_intervals`; the host's `--actual` envelope
/// uses the same rule).
pub fn envelope_knots(intervals: usize) -> usize {
    camsim_core::envelope_intervals::<MEASURED_KNOTS>(intervals)
}

/// A cam angle (rad) as this reader's messages give it: degrees in `[0, 360)`.
fn degrees(rad: f64) -> f64 {
    rad.to_degrees().rem_euclid(360.0)
}

/// The one-line message of a core geometry error (the lift range of a `lift_in`
/// column and [`MIN_SURFACE_RADIUS_IN`] are the limits the core checked against).
fn geometry_message(e: SampledError, roller_radius: f64) -> String {
    match e {
        SampledError::Spline(e) => format!("measured profile: {e}"),
        SampledError::Profile(e) => format!("measured profile: {e}"),
        SampledError::Envelope(e) => format!("the roller's envelope on the measured contour: {e}"),
        SampledError::ImpliedLift { lift, at_rad } => {
            let (lo, hi, why) = Column::Lift.plausible();
            format!(
                "measured profile: it implies a lift of {lift:.4} in at {:.2} deg, outside [{lo}, {hi}] in ({why}, the rule of a lift_in column)",
                degrees(at_rad)
            )
        }
        SampledError::SurfaceRadius { radius, at_rad } => format!(
            "measured profile: the roller's path on it has a convex cam surface radius of {radius:.3e} in at {:.2} deg, below {MIN_SURFACE_RADIUS_IN} in (the roller of radius {roller_radius} in bridges a notch or rides over a ridge there: an edge, whose contact stress has no bound; smooth the measurement or check the file)",
            degrees(at_rad)
        ),
    }
}

impl Measured {
    /// The lift deviation this revolution gives on `design` (see the module docs), or why
    /// not (one line). Boxed: the spline holds [`MEASURED_KNOTS`] knots (86 KB).
    pub fn deviation(&self, design: &Design<f64>) -> Result<Box<MeasuredDeviation>, String> {
        let dev = self.raw_deviation(design)?;
        self.check_implied(design, &dev)?;
        Ok(dev)
    }

    /// What a radius profile implies, checked as the lift form's values are (so that
    /// every form of a profile meets the same rules): camsim-core's
    /// `check_envelope` with [`Column::Lift`]'s range and
    /// [`MIN_SURFACE_RADIUS_IN`]; then, as for a lift profile, [`Self::check_follows`].
    fn check_implied(&self, design: &Design<f64>, dev: &MeasuredDeviation) -> Result<(), String> {
        // The deviation and lift forms' rows are checked as read; what their spline
        // does between sparse rows is the file's own interpolation, not checked again.
        if self.column == Column::Deviation {
            return Ok(());
        }
        if self.column == Column::Radius {
            let (lo, hi, _) = Column::Lift.plausible();
            let limits = EnvelopeLimits {
                lift: (lo, hi),
                min_surface_radius: MIN_SURFACE_RADIUS_IN,
            };
            check_envelope(dev, &design.program, &design.geometry, limits)
                .map_err(|e| geometry_message(e, design.geometry.roller_radius))?;
        }
        self.check_follows(design, dev)
    }

    /// The largest |deviation| at the spline's knots, in, and its cam angle, degrees.
    fn worst(dev: &MeasuredDeviation) -> (f64, f64) {
        let (w, at) = dev.largest_at_knots();
        (w, degrees(at))
    }

    /// A lift or radius profile must follow the scene's program within a deviation's
    /// plausibility range (±0.1 in, as a `deviation_in` column): a larger gap is another
    /// cam, or the file's unit is not its header's. Read in the other unit, a file that
    /// then follows the program is named as such: a millimetre file headed `_in`.
    fn check_follows(&self, design: &Design<f64>, dev: &MeasuredDeviation) -> Result<(), String> {
        let (lo, hi, why) = Column::Deviation.plausible();
        let (worst, at) = Self::worst(dev);
        if worst <= hi.max(-lo) {
            return Ok(());
        }
        let header = self.column.header(self.unit);
        let other = self.unit.other();
        let scale = self.unit.per_inch() / other.per_inch();
        let alt = Measured {
            unit: other,
            values_in: self.values_in.iter().map(|v| v * scale).collect(),
            ..self.clone()
        };
        let hint = match alt.raw_deviation(design).map(|d| Self::worst(&d)) {
            Ok((w, _)) if w <= hi.max(-lo) => format!(
                "read in {} (a {} header) the file follows it within {w:.4} in: is the file in {}? then head its column {}",
                other.long(),
                self.column.header(other),
                other.long(),
                self.column.header(other),
            ),
            _ => format!(
                "is it this scene's cam (its program, base circle and roller), and is the file in {} as its header ({header}) says?",
                self.unit.long()
            ),
        };
        Err(format!(
            "measured profile: its {header} column departs from the scene's program lift by {:.4} in at {at:.2} deg, beyond the [{lo}, {hi}] in of a deviation ({why}): {hint}",
            if worst.is_nan() { f64::NAN } else { worst }
        ))
    }

    /// The deviation before [`Self::check_implied`] (camsim-core's `sampled_deviation`).
    /// A radius row becomes its contour point here (`r sin φ`, `r cos φ`, with std's
    /// sine and cosine, whose last bits the figures printed so far rest on).
    fn raw_deviation(&self, design: &Design<f64>) -> Result<Box<MeasuredDeviation>, String> {
        let (xs, ys): (Vec<f64>, Vec<f64>);
        let samples = match self.column {
            Column::Deviation => Samples::Deviation(&self.values_in),
            Column::Lift => Samples::Lift(&self.values_in),
            Column::Radius => {
                let polar = || self.angles_deg.iter().zip(&self.values_in);
                xs = polar().map(|(a, r)| r * a.to_radians().sin()).collect();
                ys = polar().map(|(a, r)| r * a.to_radians().cos()).collect();
                Samples::Contour { x: &xs, y: &ys }
            }
        };
        sampled_deviation(&self.angles_deg, samples, &design.program, &design.geometry)
            .map(Box::new)
            .map_err(|e| geometry_message(e, design.geometry.roller_radius))
    }

    /// The knots (rad, over one revolution from the first row's angle, the closing knot
    /// included) and values (in) of [`Self::deviation`]'s spline: what the chip carries,
    /// narrowed to its precision (`camsim_chip::chip_deviation`).
    pub fn deviation_knots(&self, design: &Design<f64>) -> Result<(Vec<f64>, Vec<f64>), String> {
        let dev = self.deviation(design)?;
        let s = dev.spline();
        Ok((s.knots().to_vec(), s.values().to_vec()))
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
    fn a_limit_names_the_first_row_too_many() {
        let text = uniform("angle_deg,deviation_in", 10, false);
        assert!(parse_limited(&text, 10).is_ok());
        let e = parse_limited(&text, 9).unwrap_err();
        assert_eq!(e.to_string(), "line 11: more than 9 rows in a revolution");
    }

    #[test]
    fn deviation_knots_close_the_revolution() {
        let m = parse("angle_deg,deviation_in\n10,0.001\n100,0\n190,-0.001\n280,0\n").unwrap();
        let (k, v) = m.deviation_knots(&Design::reference()).unwrap();
        assert_eq!(k.len(), 5);
        assert_eq!(v, vec![0.001, 0.0, -0.001, 0.0, 0.001]);
        assert!((k[4] - k[0] - 2.0 * std::f64::consts::PI).abs() < 1e-12);
        // A lift column subtracts the program's lift.
        let y = |deg: f64| {
            Design::<f64>::reference()
                .program
                .follower(deg.to_radians())
                .y
        };
        let text = format!(
            "angle_deg,lift_in\n0,{}\n90,{}\n180,{}\n270,{}\n",
            y(0.0),
            y(90.0) + 0.01,
            y(180.0),
            y(270.0)
        );
        let m = parse(&text).unwrap();
        let (_, v) = m.deviation_knots(&Design::reference()).unwrap();
        assert!((v[1] - 0.01).abs() < 1e-15, "{v:?}");
    }

    /// Issue 18: a measured file in millimetres reads with a `_mm` header, and one in
    /// millimetres headed `_in` is refused with the hint, not run as another cam.
    #[test]
    fn millimetre_files_read_and_mislabelled_ones_are_refused() {
        let design = Design::<f64>::reference();
        let y = |deg: f64| design.program.follower(deg.to_radians()).y;
        let rows = |scale: f64, header: &str| {
            let mut t = format!("angle_deg,{header}\n");
            for k in 0..72 {
                let a = 5.0 * k as f64;
                t += &format!(
                    "{a},{}\n",
                    (y(a) + 0.001 * (3.0 * a.to_radians()).sin()) * scale
                );
            }
            t
        };
        let inch = parse(&rows(1.0, "lift_in")).unwrap();
        let mm = parse(&rows(25.4, "lift_mm")).unwrap();
        assert_eq!((mm.unit, inch.unit), (Unit::Millimetre, Unit::Inch));
        let (a, b) = (
            inch.deviation_knots(&design).unwrap().1,
            mm.deviation_knots(&design).unwrap().1,
        );
        for (a, b) in a.iter().zip(&b) {
            assert!((a - b).abs() < 1e-14, "{a} {b}");
        }
        // A 0.001 in waviness of 3 waves: the deviation at 30 deg is 0.001 sin(90 deg).
        assert!((a[6] - 0.001).abs() < 1e-12, "{}", a[6]);
        // Millimetres under an inch header.
        let e = parse(&rows(25.4, "lift_in"))
            .unwrap()
            .deviation(&design)
            .unwrap_err();
        assert!(
            e.contains("read in millimetres (a lift_mm header) the file follows it within 0.0010 in: is the file in millimetres? then head its column lift_mm"),
            "{e}"
        );
        // Inches under a millimetre header.
        let e = parse(&rows(1.0, "lift_mm"))
            .unwrap()
            .deviation(&design)
            .unwrap_err();
        assert!(
            e.contains("is the file in inches? then head its column lift_in"),
            "{e}"
        );
        // Issue 18's file: four rows of 0.1 in a lift column.
        let e = parse("angle_deg,lift_in\n0,0.1\n90,0.1\n180,0.1\n270,0.1\n")
            .unwrap()
            .deviation(&design)
            .unwrap_err();
        assert!(
            e.contains("departs from the scene's program lift by"),
            "{e}"
        );
        // Range errors speak the file's unit.
        let e = parse("angle_deg,radius_mm\n0,5000\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 2: radius_mm 5000 must lie in [0.254, 2540] mm (a cam radius, as the scene's lengths)"
        );
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
