//! Scene files: the run options, the solver settings and the design in TOML, read and
//! checked. One parser for everything that reads a scene file: the host (`camsim`, whose
//! `scene` module writes them too) and the firmware's build script (`CAMSIM_SCENE`), so
//! a file the host refuses never reaches the chip and both read the same `Design<f64>`.
//!
//! The file is `[run]` (what to simulate that is not part of the design), `[solver]`
//! (core's [`SolverSettings`]) and `[design]` (core's [`Design`] as it serializes:
//! units in the key names, see [`camsim_core::key`]). Every key is optional and
//! defaults to the reference (`camsim scene --default` prints them all); unknown keys
//! are refused, so a typo never passes silently. The checks are the core's
//! ([`Design::validate`], [`SolverSettings::validate`]); errors are one line naming
//! the line, the key, the value and the rule.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

use std::fmt;
use std::path::Path;

use camsim_core::{key, Design, FollowerModel, SolverSettings};
use serde::{Deserialize, Serialize};

pub mod measured;
pub mod spring;
pub mod units;

/// Revolutions a run simulates unless `run.revolutions` says otherwise.
pub const DEFAULT_REVOLUTIONS: u32 = 3;
/// Most revolutions a run may simulate (the host's statistics hold 16).
pub const MAX_REVOLUTIONS: u32 = 16;

/// `[run]`: what to simulate that is not part of the design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunOptions {
    /// Revolutions to simulate (1-16).
    pub revolutions: u32,
    /// Keep the horizontal motion (x1, x2, x3).
    pub horizontal_motion: bool,
    /// The follower's model: `"full"`, or a reduced one whose stiff DOFs are
    /// quasi-static (`"massless-roller"`, `"quasi-static-cantilever"`,
    /// `"quasi-static-rod"`, `"quasi-static-shaft"`; these need `horizontal_motion =
    /// false`).
    pub follower: FollowerModel,
    /// Cam speed in rpm, instead of `design.omega0_rad_per_s`: moves the design to this
    /// speed like `--rpm` ([`Design::set_speed_rpm`]: ω0, the regulated drive's
    /// reference, its feed-forward scaled with speed). Never written back.
    pub rpm: Option<f64>,
}

impl Default for RunOptions {
    /// [`DEFAULT_REVOLUTIONS`], all DOFs, the design's own speed.
    fn default() -> Self {
        RunOptions {
            revolutions: DEFAULT_REVOLUTIONS,
            horizontal_motion: true,
            follower: FollowerModel::Full,
            rpm: None,
        }
    }
}

/// `[limits]`: what the verdict of `camsim run` judges against (issue 17): the
/// allowable contact stress (psi, or `allowable_contact_stress_mpa`) and the largest
/// pressure angle without a warning. `camsim run --allowable-stress` and
/// `--pressure-angle-limit` override them; absent, the core's documented defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Limits {
    /// Allowable Hertz contact stress, psi
    /// ([`camsim_core::ALLOWABLE_CONTACT_STRESS_PSI`] unless given).
    pub allowable_contact_stress_psi: f64,
    /// Largest pressure angle without a warning, degrees, above 0 and below 90
    /// ([`camsim_core::PRESSURE_ANGLE_LIMIT_DEG`] unless given).
    pub pressure_angle_limit_deg: f64,
}

impl Default for Limits {
    /// The core's documented defaults.
    fn default() -> Self {
        Limits {
            allowable_contact_stress_psi: camsim_core::ALLOWABLE_CONTACT_STRESS_PSI,
            pressure_angle_limit_deg: camsim_core::PRESSURE_ANGLE_LIMIT_DEG,
        }
    }
}

impl Limits {
    /// The limits checked: the stress positive and finite, the angle in (0, 90)
    /// degrees (errors start with the key).
    pub fn check(&self) -> Result<(), Error> {
        let s = self.allowable_contact_stress_psi;
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::new(format!(
                "limits.{} = {}: must be positive and finite (psi)",
                units::ALLOWABLE_CONTACT_STRESS,
                short(s)
            )));
        }
        let a = self.pressure_angle_limit_deg;
        if !(a > 0.0 && a < 90.0) {
            return Err(Error::new(format!(
                "limits.{} = {}: must be above 0 and below 90 (degrees)",
                units::PRESSURE_ANGLE_LIMIT,
                short(a)
            )));
        }
        Ok(())
    }
}

/// A whole scene file as it reads and writes (nothing checked yet: [`SceneFile::check`]).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SceneFile {
    /// `[run]`.
    pub run: RunOptions,
    /// `[solver]`.
    pub solver: SolverSettings<f64>,
    /// `[design]`.
    pub design: Design<f64>,
    /// `[limits]`.
    pub limits: Limits,
    /// `[design.spring]`, the return spring as a part ([`spring`]; read apart from the
    /// design, whose rate and spring mass it gives).
    #[serde(skip)]
    pub spring: Option<spring::SpringTable>,
}

/// A scene file read and checked: what a run or a build uses.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckedScene {
    /// The design at its speed (`run.rpm` applied), validated by [`Design::validate`].
    pub design: Design<f64>,
    /// The solver settings, validated by [`SolverSettings::validate`].
    pub solver: SolverSettings<f64>,
    /// Revolutions to simulate (1-16).
    pub revolutions: u32,
    /// Keep the horizontal motion (x1, x2, x3).
    pub horizontal_motion: bool,
    /// The follower's model.
    pub follower: FollowerModel,
    /// The verdict's limits, checked by [`Limits::check`].
    pub limits: Limits,
    /// The return spring as a part (`[design.spring]`), if the file gives one: the
    /// design's rate and spring mass are its.
    pub spring: Option<spring::SpringPart>,
    /// The file gave its drive as a `[design.drive.motor]` table (the regulated drive
    /// with the motor's values), so messages about the drive name that table.
    pub motor_table: bool,
    /// The file names its drive (`drive = ...`, a `[design.drive.*]` table); false when it
    /// names none and the design inherits the thesis's regulated motor (docs/MODEL.md
    /// §5.17: the verdict then warns on a cam-speed swing past the limit).
    pub drive_given: bool,
}

/// Why a scene file was refused: one line (the file, where it can be told the line and
/// column, the key, the value and the rule).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Error {
    message: String,
}

impl Error {
    /// The refusal, kept on one line: control characters (line breaks, NULs and the like
    /// that a key or a file name copied from the input may carry) are written escaped
    /// (`\r`, `\0`).
    pub(crate) fn new(message: impl Into<String>) -> Self {
        let message: String = message.into();
        let message = if message.chars().any(char::is_control) {
            message
                .chars()
                .map(|c| {
                    if c.is_control() {
                        c.escape_debug().to_string()
                    } else {
                        c.to_string()
                    }
                })
                .collect()
        } else {
            message
        };
        Error { message }
    }
}

impl Error {
    /// The same refusal prefixed with the line of `text` that sets its key (or that
    /// opens the key's nearest enclosing table), if the text has one: for a check made
    /// after reading, such as the design's in another precision.
    pub fn at_line_in(self, text: &str) -> Error {
        located(text, &self.message)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// The largest scene file read, bytes: 1 MB (the reference scene with its comments is
/// 5 kB; a larger file is not a scene, and a device such as `/dev/zero` is not read
/// without end).
pub const MAX_SCENE_BYTES: u64 = 1_000_000;

/// The most segments a program holds (core's `CamProgram` capacity).
pub const PROGRAM_CAPACITY: usize = 8;

/// Opens `path` to read at most `max` bytes: a regular file larger than `max` is refused
/// by its size before any byte is read; any other (a pipe, a device) is read through a
/// limit, and a read past `max` fails with the same refusal. `what` names the file in the
/// refusals (`the shard file`), one line each: unreadable, a directory, over the limit.
pub fn open_limited(path: &Path, max: u64, what: &str) -> Result<LimitedRead, Error> {
    let name = path.display();
    // Only a regular file, a FIFO or a character device (a process substitution, a
    // pipe) is read; a directory is refused here rather than by an odd read error.
    let meta = std::fs::metadata(path);
    if meta.as_ref().is_ok_and(|m| m.is_dir()) {
        return Err(Error::new(format!(
            "{name}: cannot read {what}: is a directory"
        )));
    }
    if let Ok(m) = &meta {
        if m.is_file() && m.len() > max {
            return Err(Error::new(over_limit(path, what, max)));
        }
    }
    let file = std::fs::File::open(path)
        .map_err(|e| Error::new(format!("{name}: cannot read {what}: {e}")))?;
    Ok(LimitedRead {
        file,
        left: max,
        refusal: over_limit(path, what, max),
    })
}

/// The refusal of a file over its read limit.
fn over_limit(path: &Path, what: &str, max: u64) -> String {
    format!(
        "{}: {what} is larger than its limit of {max} bytes (read no further)",
        path.display()
    )
}

/// A file read through [`open_limited`]'s limit: a read past it is an error
/// ([`std::io::ErrorKind::FileTooLarge`]) whose text is the refusal.
#[derive(Debug)]
pub struct LimitedRead {
    file: std::fs::File,
    left: u64,
    refusal: String,
}

impl std::io::Read for LimitedRead {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        // One byte past the limit is asked for, to tell "exactly the limit" from "more".
        let want = buf
            .len()
            .min(usize::try_from(self.left.saturating_add(1)).unwrap_or(usize::MAX));
        let n = self.file.read(buf.get_mut(..want).unwrap_or_default())?;
        match self.left.checked_sub(n as u64) {
            Some(left) => {
                self.left = left;
                Ok(n)
            }
            None => Err(std::io::Error::new(
                std::io::ErrorKind::FileTooLarge,
                self.refusal.clone(),
            )),
        }
    }
}

/// Reads at most `max` bytes of UTF-8 text from `path` ([`open_limited`]): `what` names
/// the file in the refusals (`the scene file`), which are one line each: unreadable,
/// larger than `max` (a regular file by its size, before reading), or not UTF-8 (with the
/// line of the first invalid byte).
pub fn read_text(path: &Path, max: u64, what: &str) -> Result<String, Error> {
    use std::io::Read;
    let name = path.display();
    let mut file = open_limited(path, max, what)?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes).map_err(|e| match e.kind() {
        std::io::ErrorKind::FileTooLarge => Error::new(e.to_string()),
        _ => Error::new(format!("{name}: cannot read {what}: {e}")),
    })?;
    String::from_utf8(bytes).map_err(|e| {
        let good = e.utf8_error().valid_up_to();
        let line = e
            .as_bytes()
            .get(..good)
            .map_or(0, |b| b.iter().filter(|c| **c == b'\n').count())
            + 1;
        Error::new(format!(
            "{name}: line {line}: {what} is not UTF-8 text (its byte {good} is not): a binary file?"
        ))
    })
}

/// Reads and checks a scene file (errors start with the file's name; at most
/// [`MAX_SCENE_BYTES`] are read). A file that is not TOML but reads as a measured
/// profile (a `.csv` name, or an `angle_deg,...` header) is refused with a hint to give
/// it as a measured profile instead.
pub fn load(path: &Path) -> Result<CheckedScene, Error> {
    let text = read_text(path, MAX_SCENE_BYTES, "the scene file")?;
    parse(&text).map_err(|e| {
        let name = path.display();
        let header = text
            .trim_start_matches('\u{feff}')
            .lines()
            .map(str::trim)
            .find(|l| !l.is_empty() && !l.starts_with('#'))
            .unwrap_or("");
        let csv = path
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("csv"))
            || header.to_ascii_lowercase().starts_with("angle_deg");
        if csv {
            Error::new(format!(
                "{name}: not a scene file (TOML) but a measured profile (CSV)? give it as `--measured {name}` (camsim run, camsim predict) with the scene, if any, as the positional argument ({e})"
            ))
        } else {
            Error::new(format!("{name}: {e}"))
        }
    })
}

/// An SI key the reader converted to its inch-family key ([`units`]).
#[derive(Debug, Clone)]
struct Converted {
    /// The table, with indices (`design.program.segment[1]`).
    table: String,
    /// The user's name (`lift_mm`).
    si: String,
    /// The inch-family name it became (`lift_in`).
    inch: &'static str,
    /// Its unit.
    unit: &'static units::Unit,
    /// The user's value, if a number.
    si_value: Option<f64>,
}

impl Converted {
    fn si_path(&self) -> String {
        format!("{}.{}", self.table, self.si)
    }
    fn inch_path(&self) -> String {
        format!("{}.{}", self.table, self.inch)
    }
}

/// A key the file sets: its inch-family path with indices (`design.program.segment[1].lift_in`),
/// the user's path (`...lift_mm`), its value in the inch family if it is a number, and
/// the value as the user wrote it.
#[derive(Debug, Clone)]
struct Present {
    inch_path: String,
    user_path: String,
    value: Option<f64>,
    raw: String,
    /// The value's text if it is a string or a boolean (`"cycloidal"`), for listings.
    word: Option<String>,
}

/// What the first reading of a file found: the conversions and every key set.
#[derive(Debug, Default)]
struct Reading {
    converted: Vec<Converted>,
    present: Vec<Present>,
    /// `design.moving_mass_lb` (pound-mass; `_kg` converted), taken out of the design
    /// table before it is read: not a field of the design but the rule that sets its load.
    moving_mass: Option<f64>,
    /// `[design.drive.motor]`'s values (inch family), taken out of the drive before the
    /// design is read: the rules that set the design's I_m, K_s1 and the regulator.
    motor: Option<Motor>,
}

/// A `[design.drive.motor]` table: a motor with a speed regulator in a designer's terms,
/// each value in the inch family (`None`: not given, the thesis's value is kept).
#[derive(Debug, Default, Clone, Copy)]
struct Motor {
    /// Rotor inertia, lb·in·s² (the design's I_m).
    inertia: Option<f64>,
    /// Motor-coupling shaft stiffness, lb·in/rad (K_s1).
    shaft_stiffness: Option<f64>,
    /// Regulator gain, lb·in·s/rad (the regulated drive's k_p).
    gain: Option<f64>,
    /// Torque limit, lb·in (t_max).
    torque_limit: Option<f64>,
}

/// The motor keys (relative to `[design]`), the design key each sets and what it is.
const MOTOR_RULES: [(&str, &str, &str); 4] = [
    (
        units::MOTOR_INERTIA,
        key::I_M,
        "the rotor inertia is the design's I_m",
    ),
    (
        units::MOTOR_SHAFT_STIFFNESS,
        key::K_S1,
        "the shaft stiffness is the design's K_s1",
    ),
    (
        units::MOTOR_GAIN,
        key::DRIVE_K_P,
        "the regulator's gain is k_p",
    ),
    (
        units::MOTOR_TORQUE_LIMIT,
        key::DRIVE_T_MAX,
        "the torque limit is t_max",
    ),
];

impl Reading {
    /// Whether the file sets `path` (inch-family, with indices) in either family.
    fn sets(&self, path: &str) -> bool {
        self.present.iter().any(|p| p.inch_path == path)
    }
}

fn join(a: &str, b: &str) -> String {
    if a.is_empty() {
        b.to_string()
    } else {
        format!("{a}.{b}")
    }
}

/// A TOML number's value (integers and floats; underscores allowed).
fn number_of(v: &toml::de::DeValue<'_>) -> Option<(f64, String)> {
    use toml::de::DeValue;
    match v {
        DeValue::Float(f) => {
            let t = f.as_str().replace('_', "");
            let x = match t.trim_start_matches(['+', '-']) {
                "nan" => f64::NAN,
                _ => t.parse().ok()?,
            };
            Some((x, f.as_str().to_string()))
        }
        DeValue::Integer(i) => {
            let t = i.as_str().replace('_', "");
            let x = i64::from_str_radix(&t, i.radix()).ok()? as f64;
            Some((x, i.to_string()))
        }
        _ => None,
    }
}

/// A float as TOML writes it (Rust's shortest round-trip digits; `nan`, `inf`).
fn toml_float(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{v:?}")
    }
}

type Visit<'a, 'v> = dyn FnMut(&mut toml::de::DeTable<'a>, &str, &str) -> Result<(), Error> + 'v;

/// Calls `visit(table, path without indices, path with indices)` on `table` and every
/// table under it (arrays of tables and inline tables included), parents first.
fn walk<'a>(
    table: &mut toml::de::DeTable<'a>,
    norm: &str,
    disp: &str,
    visit: &mut Visit<'a, '_>,
) -> Result<(), Error> {
    use toml::de::DeValue;
    visit(table, norm, disp)?;
    for (k, v) in table.iter_mut() {
        let name: &str = k.get_ref();
        let (n, d) = (join(norm, name), join(disp, name));
        match v.get_mut() {
            DeValue::Table(t) => walk(t, &n, &d, visit)?,
            DeValue::Array(a) => {
                for (i, e) in a.iter_mut().enumerate() {
                    if let DeValue::Table(t) = e.get_mut() {
                        walk(t, &n, &format!("{d}[{i}]"), visit)?;
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// The first reading: which keys the file sets, which are SI keys to convert, and the
/// refusal of a quantity given in both families.
fn survey(text: &str) -> Result<Reading, Error> {
    let mut root = toml::de::DeTable::parse(text)
        .map_err(|e| toml_error(text, &e, &Reading::default()))?
        .into_inner();
    let mut reading = Reading::default();
    walk(&mut root, "", "", &mut |t, norm, disp| {
        for (k, v) in t.iter() {
            let name: &str = k.get_ref();
            let user_path = join(disp, name);
            let num = number_of(v.get_ref());
            let raw = num.as_ref().map(|(_, r)| r.clone()).unwrap_or_default();
            let word = match v.get_ref() {
                toml::de::DeValue::String(w) => Some(format!("{w:?}")),
                toml::de::DeValue::Boolean(b) => Some(b.to_string()),
                _ => None,
            };
            match units::lookup(norm, name) {
                Some((uk, true)) => {
                    let inch = uk.inch();
                    if t.contains_key(inch) {
                        return Err(located(
                            text,
                            &format!(
                                "{user_path} and {}: both give the {} (once in {}, once in {}): give one of them",
                                join(disp, inch),
                                uk.stem().replace('_', " "),
                                uk.unit.si_symbol,
                                uk.unit.inch_symbol
                            ),
                        ));
                    }
                    let si_value = num.map(|(x, _)| x);
                    reading.converted.push(Converted {
                        table: disp.to_string(),
                        si: name.to_string(),
                        inch,
                        unit: uk.unit,
                        si_value,
                    });
                    reading.present.push(Present {
                        inch_path: join(disp, inch),
                        user_path,
                        value: si_value.map(|x| x / uk.unit.si_per_inch),
                        raw,
                        word,
                    });
                }
                _ => reading.present.push(Present {
                    inch_path: user_path.clone(),
                    user_path,
                    value: num.map(|(x, _)| x),
                    raw,
                    word,
                }),
            }
        }
        Ok(())
    })?;
    Ok(reading)
}

/// The scene file of `text`, its SI keys converted to the inch family ([`units`]), and
/// what the reading found.
fn read_scene(text: &str) -> Result<(SceneFile, Reading), Error> {
    use toml::de::DeValue;
    use toml::Spanned;
    let mut reading = survey(text)?;
    // The converted values as TOML number text, parsed below into the values of the
    // renamed keys (the parsed table borrows its text).
    let mut numbers = String::new();
    let mut ranges = Vec::with_capacity(reading.converted.len());
    for c in &reading.converted {
        let start = numbers.len();
        if let Some(v) = c.si_value {
            numbers.push_str(&toml_float(v / c.unit.si_per_inch));
        }
        ranges.push(start..numbers.len());
        numbers.push(' ');
    }
    let mut root =
        toml::de::DeTable::parse(text).map_err(|e| toml_error(text, &e, &Reading::default()))?;
    let span = root.span();
    let mut next = 0;
    walk(root.get_mut(), "", "", &mut |t, _, disp| {
        while let Some(c) = reading.converted.get(next).filter(|c| c.table == disp) {
            let range = ranges.get(next).cloned().unwrap_or(0..0);
            next += 1;
            let Some((k, v)) = t.remove_entry(c.si.as_str()) else {
                continue;
            };
            let value = match numbers.get(range).filter(|n| !n.is_empty()) {
                Some(n) => DeValue::parse(n)
                    .map(|p| Spanned::new(v.span(), p.into_inner()))
                    .unwrap_or(v),
                None => v,
            };
            t.insert(
                Spanned::new(k.span(), std::borrow::Cow::Borrowed(c.inch)),
                value,
            );
        }
        Ok(())
    })?;
    reading.moving_mass = take_moving_mass(root.get_mut(), text)?;
    reading.motor = take_drive_preset(root.get_mut(), text)?;
    // `[design.spring]` is read apart: the design has no such key.
    let spring_table = match root.get_mut().get_mut("design").map(|d| d.get_mut()) {
        Some(DeValue::Table(design)) => design.remove("spring"),
        _ => None,
    };
    let de = toml::de::Deserializer::from(Spanned::new(span, root.into_inner()));
    let mut file = SceneFile::deserialize(de).map_err(|e| toml_error(text, &e, &reading))?;
    if let Some(v) = spring_table {
        let span = v.span();
        let DeValue::Table(t) = v.into_inner() else {
            return Err(located(
                text,
                "design.spring: must be a table ([design.spring] with its keys)",
            ));
        };
        let de = toml::de::Deserializer::from(Spanned::new(span, t));
        file.spring =
            Some(spring::SpringTable::deserialize(de).map_err(|e| toml_error(text, &e, &reading))?);
    }
    Ok((file, reading))
}

/// Takes `design.moving_mass_lb` (already converted from `_kg`) out of the root table:
/// its value in pound-mass, if the file gives one (refused if not a number).
fn take_moving_mass(root: &mut toml::de::DeTable<'_>, text: &str) -> Result<Option<f64>, Error> {
    use toml::de::DeValue;
    let Some(DeValue::Table(design)) = root.get_mut("design").map(|v| v.get_mut()) else {
        return Ok(None);
    };
    let Some(v) = design.remove(units::MOVING_MASS) else {
        return Ok(None);
    };
    match number_of(v.get_ref()) {
        Some((x, _)) => Ok(Some(x)),
        None => Err(located(
            text,
            &format!(
                "design.{}: must be a number (the moving mass in lb, or moving_mass_kg in kg)",
                units::MOVING_MASS
            ),
        )),
    }
}

/// Reads the drive names the core does not know: `drive = "thesis"` (the thesis's
/// regulated drive, exactly what a scene without a drive gets: the key is dropped) and
/// `[design.drive.motor]` (dropped too, its values returned: the design keeps the thesis's
/// regulated drive and [`apply_motor`] sets the motor's values into it).
fn take_drive_preset(root: &mut toml::de::DeTable<'_>, text: &str) -> Result<Option<Motor>, Error> {
    use toml::de::DeValue;
    let Some(DeValue::Table(design)) = root.get_mut("design").map(|v| v.get_mut()) else {
        return Ok(None);
    };
    let motor = match design.get("drive").map(|v| v.get_ref()) {
        Some(DeValue::String(s)) if s.as_ref() == "thesis" => None,
        Some(DeValue::Table(t)) if t.contains_key("motor") => match t.get("motor").map(|v| v.get_ref()) {
            Some(DeValue::Table(m)) if t.len() == 1 => Some(motor_of(m, text)?),
            Some(DeValue::Table(_)) => {
                return Err(located(
                    text,
                    "design.drive: give one drive: [design.drive.motor] or [design.drive.regulated], not both",
                ))
            }
            _ => return Err(located(text, "design.drive.motor: must be a table of the motor's keys")),
        },
        _ => return Ok(None),
    };
    design.remove("drive");
    Ok(motor)
}

/// The values of a `[design.drive.motor]` table (already converted to the inch family);
/// an unknown key or a value that is not a number is refused, naming it.
fn motor_of(m: &toml::de::DeTable<'_>, text: &str) -> Result<Motor, Error> {
    let mut motor = Motor::default();
    for (k, v) in m.iter() {
        let name: &str = k.get_ref();
        let slot = match MOTOR_RULES.iter().position(|r| r.0.ends_with(&format!(".{name}"))) {
            Some(0) => &mut motor.inertia,
            Some(1) => &mut motor.shaft_stiffness,
            Some(2) => &mut motor.gain,
            Some(3) => &mut motor.torque_limit,
            _ => {
                return Err(located(
                    text,
                    &format!(
                        "design.drive.motor.{name}: unknown key (the motor's keys: inertia, shaft_stiffness, gain, torque_limit, each with its unit: inertia_kg_m2 or inertia_lb_in_s2, shaft_stiffness_n_m_per_rad, gain_n_m_s_per_rad, torque_limit_n_m)"
                    ),
                ))
            }
        };
        match number_of(v.get_ref()) {
            Some((x, _)) => *slot = Some(x),
            None => {
                return Err(located(
                    text,
                    &format!("design.drive.motor.{name}: must be a number"),
                ))
            }
        }
    }
    Ok(motor)
}

/// Sets a `[design.drive.motor]`'s values into the design by MOTOR_RULES (docs/MODEL.md
/// §5.17): rotor inertia → I_m, shaft stiffness → K_s1, gain → k_p, torque limit → t_max;
/// a key not given keeps the thesis's value. Each value must be positive and finite; the
/// refusal quotes the user's key and value. A file that also sets the design key is refused.
fn apply_motor(d: &mut Design<f64>, m: &Motor, reading: &Reading) -> Result<(), String> {
    let values = [m.inertia, m.shaft_stiffness, m.gain, m.torque_limit];
    for ((motor_key, design_key, _), v) in MOTOR_RULES.iter().zip(values) {
        let Some(v) = v else { continue };
        let path = format!("design.{motor_key}");
        let (user, raw) = reading
            .present
            .iter()
            .find(|p| p.inch_path == path)
            .map_or((path.clone(), String::new()), |p| {
                (p.user_path.clone(), p.raw.clone())
            });
        if !(v.is_finite() && v > 0.0) {
            return Err(format!("{user} = {raw}: must be positive and finite"));
        }
        if reading.sets(&format!("design.{design_key}")) {
            return Err(format!(
                "{user} and design.{design_key} (or its other unit): both set the same value: give one of them"
            ));
        }
    }
    d.i_m = m.inertia.unwrap_or(d.i_m);
    d.k_s1 = m.shaft_stiffness.unwrap_or(d.k_s1);
    if let camsim_core::DriveLaw::Regulated { k_p, t_max, .. } = &mut d.drive {
        *k_p = m.gain.unwrap_or(*k_p);
        *t_max = m.torque_limit.unwrap_or(*t_max);
    }
    Ok(())
}

/// Parses and checks scene text. Errors are one line: where TOML or serde refused
/// it, the line, column and key; where the checks refused it, the line that sets the
/// key (if the text sets it), the key, the value and the rule; for a key the file does
/// not set, the line of the user's key that makes the default fail (see
/// [`CAUSES`]). Keys in SI units are converted as read ([`units`]); a refusal names them
/// as the file wrote them.
pub fn parse(text: &str) -> Result<CheckedScene, Error> {
    let (mut file, reading) = read_scene(text)?;
    // A spring rate without a spring mass: the mass follows the rate by the one
    // wire-and-coil model (camsim-core's `HelicalSpring`, docs/MODEL.md §5.6), as it does
    // for `--spring-rate`. A file that gives the mass keeps it.
    let sets = |k: &str| reading.sets(&format!("design.{k}"));
    if sets(key::K_RS) && !sets(key::M_SPRING) {
        // A rate the wire model gives no finite mass for (1e-310) keeps the reference's
        // mass: the rate's own range check then names the rate, the key the user wrote.
        if let Ok(spring) = camsim_core::HelicalSpring::of_rate(file.design.k_rs) {
            if spring.mass.is_finite() {
                file.design.m_spring = spring.mass;
            }
        }
    }
    if file.spring.is_some() {
        let given = [key::K_RS, key::M_SPRING].into_iter().find_map(|k| {
            let path = format!("design.{k}");
            reading.present.iter().find(|p| p.inch_path == path)
        });
        if let Some(p) = given {
            return Err(located(
                text,
                &format!("{} and [design.spring] both give the spring: [design.spring] sets the rate and the spring mass; give one of them", p.user_path),
            ));
        }
    }
    // The part's rate and mass before the moving mass is shared out (its third of the
    // spring) and the modal rate follows; a part that is refused is refused by `check`.
    if let Some(Ok(p)) = file.spring.as_ref().map(spring::SpringTable::part) {
        file.design.k_rs = p.coil.rate();
        file.design.m_spring = p.coil.mass();
    }
    // The modal analysis's rate follows the spring's unless the file gives it.
    if (sets(key::K_RS) || file.spring.is_some()) && !sets(key::K_RS_MODAL) {
        file.design.k_rs_modal = file.design.k_rs;
    }
    if let Some(lb) = reading.moving_mass {
        apply_moving_mass(&mut file.design, lb, &reading).map_err(|m| located(text, &m))?;
    }
    if let Some(motor) = &reading.motor {
        apply_motor(&mut file.design, motor, &reading).map_err(|m| located(text, &m))?;
    }
    if file.run.rpm.is_some() {
        if let Some(k) = [key::OMEGA0, key::DRIVE_OMEGA_REF]
            .into_iter()
            .find(|k| sets(k))
        {
            return Err(located(
                text,
                &format!("run.rpm and design.{k} both set the cam speed: give one of them"),
            ));
        }
    }
    let motor_table = reading.motor.is_some();
    let drive_given = reading.sets("design.drive");
    file.check()
        .map(|c| CheckedScene {
            motor_table,
            drive_given,
            ..c
        })
        .map_err(|e| {
            located(
                text,
                &explain(&in_user_units(&e.message, &reading), &reading),
            )
        })
}

/// Where the design's values of a scene come from (`camsim scene --check`'s listing): the
/// keys the file sets, and the values the reader derives from them. Every other design
/// value is the reference design's.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Origins {
    /// The keys the file sets: inch-family path with indices
    /// (`design.geometry.base_radius_in`), the path as written (`..._mm`) and the value's
    /// text as written.
    pub from_file: Vec<(String, String, String)>,
    /// The values derived: the derived key's inch-family path, the user's key it comes from
    /// (as written), and the rule.
    pub derived: Vec<(String, String, &'static str)>,
}

/// The [`Origins`] of scene `text` (read, not checked: call [`parse`] for that).
pub fn origins(text: &str) -> Result<Origins, Error> {
    let (_, reading) = read_scene(text)?;
    let user = |inch: &str| {
        reading
            .present
            .iter()
            .find(|p| p.inch_path == inch)
            .map_or(inch.to_string(), |p| p.user_path.clone())
    };
    let d = |k: &str| format!("design.{k}");
    let sets = |k: &str| reading.sets(&d(k));
    let mut derived = Vec::new();
    if sets(key::K_RS) && !sets(key::M_SPRING) {
        derived.push((
            d(key::M_SPRING),
            user(&d(key::K_RS)),
            "the wire-and-coil model: the reference wire and coil diameter wound to the rate (docs/MODEL.md 5.6)",
        ));
    }
    if sets(key::K_RS) && !sets(key::K_RS_MODAL) {
        derived.push((
            d(key::K_RS_MODAL),
            user(&d(key::K_RS)),
            "the modal analysis's rate follows the spring's",
        ));
    }
    if reading.moving_mass.is_some() {
        derived.push((
            d(key::M_L),
            user(&d(units::MOVING_MASS)),
            "the moving mass less the rod rho*A*(e1+e2), the roller and a third of the spring (docs/MODEL.md 5.1)",
        ));
    }
    if let Some(m) = &reading.motor {
        let values = [m.inertia, m.shaft_stiffness, m.gain, m.torque_limit];
        for ((motor_key, design_key, rule), v) in MOTOR_RULES.iter().zip(values) {
            if v.is_some() {
                derived.push((d(design_key), user(&d(motor_key)), *rule));
            }
        }
    }
    if reading.sets("run.rpm") {
        derived.push((
            d(key::OMEGA0),
            "run.rpm".to_string(),
            "the cam speed (and the regulated drive's reference speed and feed-forward)",
        ));
    }
    let from_file = reading
        .present
        .iter()
        .filter_map(|p| {
            let value = match &p.word {
                Some(w) => w.clone(),
                None if p.raw.is_empty() => return None,
                None => p.raw.clone(),
            };
            Some((p.inch_path.clone(), p.user_path.clone(), value))
        })
        .collect();
    Ok(Origins { from_file, derived })
}

/// Sets the load so that the translating mass is `lb` pound-mass (the file's
/// `moving_mass_lb` or `_kg`): the load takes what the rod, roller and spring's share
/// leave (camsim-core's `Design::set_moving_mass`, docs/MODEL.md §5.1). The refusal
/// names the user's key and value and every part in the user's unit.
fn apply_moving_mass(d: &mut Design<f64>, lb: f64, reading: &Reading) -> Result<(), String> {
    let inch_path = format!("design.{}", units::MOVING_MASS);
    let (user, raw) = reading
        .present
        .iter()
        .find(|p| p.inch_path == inch_path)
        .map_or((inch_path.as_str(), ""), |p| {
            (p.user_path.as_str(), p.raw.as_str())
        });
    let si = !user.ends_with(units::POUND_MASS.inch);
    let load_key = match si {
        true => format!(
            "design.{}",
            units::si_name("design", key::M_L).unwrap_or_default()
        ),
        false => format!("design.{}", key::M_L),
    };
    if reading.sets(&format!("design.{}", key::M_L)) {
        return Err(format!(
            "{user} and {load_key} (or its other unit): both set the load: give the moving mass, or the load mass, not both"
        ));
    }
    let unit = if si { "kg" } else { "lb" };
    if !(lb.is_finite() && lb > 0.0) {
        return Err(format!(
            "{user} = {raw}: must be positive and finite ({unit})"
        ));
    }
    let factor = units::G_IN_PER_S2
        * if si {
            units::POUND_MASS.si_per_inch
        } else {
            1.0
        };
    let m = d.moving_mass();
    if d.set_moving_mass(lb / units::G_IN_PER_S2).is_err() {
        let q = |x: f64| format!("{:.4} {unit}", x * factor);
        return Err(format!(
            "{user} = {raw}: leaves no load mass: the follower rod rho*A*(e1+e2) {}, the roller {} and a third of the spring {} already make {} (the load would be {}): give the whole translating mass, or lighter parts (follower_area, e1, e2, roller_mass, the spring)",
            q(m.rod),
            q(m.roller),
            q(m.spring_share),
            q(m.fixed_parts()),
            q(lb / units::G_IN_PER_S2 - m.fixed_parts())
        ));
    }
    Ok(())
}

/// A program's refusal (`design.program.segment = 0.0394: net displacement ...`, the
/// value in inches) in the file's lift unit when the file gives its lifts in mm.
fn program_in_user_units(msg: &str, reading: &Reading) -> String {
    let si = reading.converted.iter().any(|c| c.si == "lift_mm");
    let head = format!("design.{} = ", key::PROGRAM_SEGMENT);
    match (
        si,
        msg.strip_prefix(head.as_str())
            .and_then(|r| r.split_once(": ")),
    ) {
        (true, Some((v, rule))) => match v.parse::<f64>() {
            Ok(x) => format!(
                "design.{} (lift_mm) = {} mm: {rule}",
                key::PROGRAM_SEGMENT,
                short(
                    format!("{:.6e}", x * units::MM_PER_IN)
                        .parse()
                        .unwrap_or(x * units::MM_PER_IN)
                )
            ),
            Err(_) => msg.to_string(),
        },
        _ => msg.to_string(),
    }
}

/// `msg` (a refusal starting with an inch-family key path and ` = value`) written with
/// the key as the file gave it, if the file gave it in SI: `design.geometry.base_radius_mm
/// = 0.1 (0.003937 in): must lie in [0.01, 100] in (...)`.
fn in_user_units(msg: &str, reading: &Reading) -> String {
    for c in &reading.converted {
        let inch = c.inch_path();
        let Some(rest) = msg.strip_prefix(inch.as_str()) else {
            continue;
        };
        if !(rest.starts_with(' ') || rest.starts_with(':')) {
            continue;
        }
        let (si, sym) = (c.si_path(), c.unit.inch_symbol);
        return match (
            rest.strip_prefix(" = ").and_then(|r| r.split_once(": ")),
            c.si_value,
        ) {
            (Some((v, rule)), Some(x)) => {
                // The inch value to 7 significant digits: what the rule's bounds compare.
                let v = v
                    .parse::<f64>()
                    .ok()
                    .and_then(|v| format!("{v:.6e}").parse::<f64>().ok())
                    .map_or(v.to_string(), |v| v.to_string());
                format!("{si} = {} ({v} {sym}): {rule}", short(x))
            }
            _ => format!("{si}{rest}"),
        };
    }
    msg.to_string()
}

/// Keys whose rule involves other keys: when the file does not set the refused key, the
/// refusal is put on the line of the user's key that makes its (default) value fail.
/// `*` stands for any segment's index.
pub const CAUSES: &[(&str, &[&str])] = &[
    ("design.load_mass_lb_s2_per_in", &["design.moving_mass_lb"]),
    (
        "design.spring_modal_rate_lb_per_in",
        &["design.spring_rate_lb_per_in"],
    ),
    (
        "design.e2_in",
        &[
            "design.program.segment[*].lift_in",
            "design.geometry.roller_radius_in",
        ],
    ),
    (
        "design.geometry.roller_radius_in",
        &[
            "design.geometry.base_radius_in",
            "design.program.segment[*].lift_in",
            "design.program.segment[*].law",
            "design.program.segment[*].end_deg",
            "design.program.segment[*].start_deg",
        ],
    ),
    (
        "design.geometry.base_radius_in",
        &[
            "design.geometry.roller_radius_in",
            "design.program.segment[*].lift_in",
        ],
    ),
];

/// The keys of [`CAUSES`] whose value, when the file does not set it, is derived from
/// the user's key (the load from the moving mass, the modal rate from the spring rate).
const DERIVED: &[&str] = &[
    "design.load_mass_lb_s2_per_in",
    "design.spring_modal_rate_lb_per_in",
];

/// Whether `path` (with indices) matches `pattern` (`[*]` for any index).
fn matches(pattern: &str, path: &str) -> bool {
    match pattern.split_once("[*]") {
        None => pattern == path,
        Some((head, tail)) => path
            .strip_prefix(head)
            .and_then(|r| r.strip_prefix('['))
            .and_then(|r| r.split_once(']'))
            .is_some_and(|(i, r)| i.parse::<usize>().is_ok() && r == tail),
    }
}

/// A refusal of a key the file does not set, put on the user's key that causes it
/// ([`CAUSES`]): the cause with the largest value among the first pattern the file sets.
fn explain(msg: &str, reading: &Reading) -> String {
    let Some((head, rule)) = msg.split_once(": ") else {
        return msg.to_string();
    };
    let refused = head.split(' ').next().unwrap_or("");
    if reading.sets(refused) {
        return msg.to_string();
    }
    let Some((_, causes)) = CAUSES.iter().find(|(k, _)| *k == refused) else {
        return msg.to_string();
    };
    for pattern in *causes {
        let cause = reading
            .present
            .iter()
            .filter(|p| matches(pattern, &p.inch_path))
            .fold(None, |best: Option<&Present>, p| match best {
                Some(b) if b.value.unwrap_or(0.0) >= p.value.unwrap_or(0.0) => Some(b),
                _ => Some(p),
            });
        if let Some(p) = cause {
            let value = if p.raw.is_empty() {
                String::new()
            } else {
                format!(" = {}", p.raw)
            };
            let head = if p.user_path != p.inch_path {
                head_in_si(head)
            } else {
                head.to_string()
            };
            // The load and the modal rate follow the user's key; the rest is the reference's.
            let whence = if DERIVED.contains(&refused) {
                "derived from it"
            } else {
                "the reference's value"
            };
            return format!(
                "{}{value}: it makes {head} (not in the file: {whence}) fail: {rule}",
                p.user_path
            );
        }
    }
    msg.to_string()
}

/// `design.e2_in = 2` in the SI family (`design.e2_mm = 50.8`), for a refusal of a key
/// the file does not set, when the key that caused it is in SI.
fn head_in_si(head: &str) -> String {
    let (path, value) = head.split_once(" = ").unwrap_or((head, ""));
    let (table, name) = path.rsplit_once('.').unwrap_or(("", path));
    match units::lookup(table, name) {
        Some((k, false)) => {
            let si = format!("{table}.{}", k.si());
            match value.parse::<f64>() {
                Ok(x) => format!("{si} = {}", short(x * k.unit.si_per_inch)),
                Err(_) => si,
            }
        }
        _ => head.to_string(),
    }
}

/// A core check's refusal in `section` (`design`, `solver`): its key under the section,
/// the value and the rule (`design.spring_rate_lb_per_in = -1: must be positive and
/// finite`).
pub fn refusal(section: &str, error: camsim_core::Error) -> Error {
    Error::new(match error {
        // Both start with the key: put the section in front of it.
        camsim_core::Error::InvalidParameter { .. } | camsim_core::Error::Inconsistent { .. } => {
            format!("{section}.{error}")
        }
        other => format!("{section}: {other}"),
    })
}

/// One line for a TOML or serde error: line, column, the key there, the message. A
/// program refused as it is read (by the core's `CamProgram::new`) names its own key.
fn toml_error(text: &str, e: &toml::de::Error, reading: &Reading) -> Error {
    let msg = short_numbers(&e.message().trim().replace('\n', " "));
    if msg.starts_with(key::PROGRAM_SEGMENT) {
        let msg = program_in_user_units(&format!("design.{msg}"), reading);
        return located(text, &in_user_units(&msg, reading));
    }
    let Some(span) = e.span() else {
        return match deepest_line(text) {
            Some((line, depth)) if msg.contains("recursion limit") => Error::new(format!(
                "line {line}: nested {depth} levels deep, past the TOML reader's limit ({msg}; a scene file's deepest key, design.program.segment, is 3 levels)"
            )),
            _ => Error::new(msg),
        };
    };
    let (line, col) = line_col(text, span.start);
    // A program longer than its capacity: the sequence's own message ("invalid length 9,
    // expected a sequence", at the first segment) says neither the key nor the limit.
    if msg.starts_with("invalid length")
        && line_paths(text)
            .get(line - 1)
            .is_some_and(|k| k.starts_with("design.program.segment"))
    {
        return Error::new(format!(
            "design.{}: more than {PROGRAM_CAPACITY} segments (a program holds at most {PROGRAM_CAPACITY})",
            key::PROGRAM_SEGMENT
        ));
    }
    let path = line_paths(text).get(line - 1).cloned().unwrap_or_default();
    let mut msg = did_you_mean(&msg, &path).unwrap_or(msg);
    // The drives the reader itself takes (take_drive_preset), which serde's list lacks.
    if path.starts_with("design.drive") && msg.starts_with("unknown variant") {
        msg.push_str("; or `thesis`, or a [design.drive.motor] table");
    }
    Error::new(match Some(&path).filter(|k| !k.is_empty()) {
        Some(k) => format!("line {line}, column {col}: {}: {msg}", cut(k)),
        None => format!("line {line}, column {col}: {msg}"),
    })
}

/// At most this many characters of a key the user wrote are quoted in an error.
const MAX_KEY_CHARS: usize = 200;

/// `key` cut after [`MAX_KEY_CHARS`] characters, with "…" when cut.
fn cut(key: &str) -> String {
    match key.char_indices().nth(MAX_KEY_CHARS) {
        Some((i, _)) => format!("{}…", key.get(..i).unwrap_or(key)),
        None => key.to_string(),
    }
}

/// The line (from 1) that nests deepest, and its depth: the `[` and `{` it opens plus the
/// dots of its key or table header (`[a.a.a]` is 3). `None` for an empty text.
fn deepest_line(text: &str) -> Option<(usize, usize)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let code = l.split('#').next().unwrap_or("");
            let key = code.split('=').next().unwrap_or("");
            let opened = code.chars().filter(|c| matches!(c, '[' | '{')).count();
            (i + 1, opened + key.matches('.').count())
        })
        .max_by_key(|&(i, depth)| (depth, std::cmp::Reverse(i)))
}

/// Plain digits, or an exponent where they would run long (1e300), as core's errors.
fn short(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-5..1e16).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Edit distance (Levenshtein) of `a` and `b`, in characters.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row.first().copied().unwrap_or(0);
        if let Some(first) = row.first_mut() {
            *first = i + 1;
        }
        for (j, cb) in b.iter().enumerate() {
            let up = row.get(j + 1).copied().unwrap_or(usize::MAX);
            let left = row.get(j).copied().unwrap_or(usize::MAX);
            let v = (diag + usize::from(ca != *cb))
                .min(up.saturating_add(1))
                .min(left.saturating_add(1));
            diag = up;
            if let Some(x) = row.get_mut(j + 1) {
                *x = v;
            }
        }
    }
    row.last().copied().unwrap_or(0)
}

/// A table path without its indices (`design.program.segment[2]` as `design.program.segment`).
fn without_indices(table: &str) -> String {
    let mut out = String::new();
    let mut skip = false;
    for c in table.chars() {
        match c {
            '[' => skip = true,
            ']' => skip = false,
            _ if !skip => out.push(c),
            _ => {}
        }
    }
    out
}

/// The keys of table `norm` that serde's `expected` list names, each with its SI name
/// where it has one, and the `[limits]` table's SI stress key.
fn key_candidates(norm: &str, expected: &str) -> Vec<String> {
    let mut candidates: Vec<String> = Vec::new();
    for c in expected.split('`').skip(1).step_by(2) {
        candidates.push(c.to_string());
        if let Some(si) = units::si_name(norm, c) {
            candidates.push(si);
        }
    }
    if norm == "limits" {
        candidates.push(format!(
            "{}_{}",
            units::ALLOWABLE_CONTACT_STRESS
                .strip_suffix(units::STRESS.inch)
                .and_then(|s| s.strip_suffix('_'))
                .unwrap_or(""),
            units::STRESS.si
        ));
    }
    candidates
}

/// serde's "unknown field `x`, expected one of `a`, `b`, ..." (a line listing every key
/// of the table) as "unknown field `x`: did you mean `a`?": the keys nearest by edit
/// distance, SI names ([`units`]) included, or the keys that start with the name (a key
/// written without its unit). `path` is the key's path (`design.k_rb`).
fn did_you_mean(msg: &str, path: &str) -> Option<String> {
    let rest = msg.strip_prefix("unknown field `")?;
    let (name, rest) = rest.split_once('`')?;
    let expected = rest.split_once("expected")?.1;
    let table = path.rsplit_once('.').map_or("", |(t, _)| t);
    // A key too long to be a misspelling: not compared, not echoed a second time (the
    // line's path shows its start).
    if name.chars().count() > MAX_KEY_CHARS {
        let shown = if table.is_empty() {
            "the file's top level".to_string()
        } else {
            format!("[{}]", cut(table))
        };
        return Some(format!(
            "unknown field ({} characters long): not a key of {shown} (`camsim scene --default` writes every key)",
            name.chars().count()
        ));
    }
    let norm = without_indices(table);
    let candidates = key_candidates(&norm, expected);
    let lower = name.to_ascii_lowercase();
    let prefixed: Vec<&String> = candidates
        .iter()
        .filter(|c| c.starts_with(&format!("{lower}_")))
        .collect();
    let near: Vec<&String> = if prefixed.is_empty() {
        let best = candidates
            .iter()
            .map(|c| distance(&lower, c))
            .min()
            .unwrap_or(usize::MAX);
        let allowed = (name.chars().count() / 3).max(2);
        if best > allowed {
            Vec::new()
        } else {
            candidates
                .iter()
                .filter(|c| distance(&lower, c) == best)
                .collect()
        }
    } else {
        prefixed
    };
    let list = |v: &[&String]| {
        v.iter()
            .take(4)
            .map(|c| format!("`{c}`"))
            .collect::<Vec<_>>()
            .join(" or ")
    };
    let shown_table = if table.is_empty() {
        "the file's top level".to_string()
    } else {
        format!("[{table}]")
    };
    Some(if near.is_empty() {
        format!(
            "unknown field `{name}`: not a key of {shown_table} (`camsim scene --default` writes every key)"
        )
    } else {
        format!("unknown field `{name}`: did you mean {}?", list(&near))
    })
}

/// `msg` with every long number it quotes in backticks written in short scientific form:
/// serde's type errors print a float with all its digits (1e300 as 301 of them).
fn short_numbers(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len());
    for (i, part) in msg.split('`').enumerate() {
        if i > 0 {
            out.push('`');
        }
        match part.parse::<f64>() {
            Ok(v) if i % 2 == 1 && part.len() > 17 => out.push_str(&format!("{v:e}")),
            _ => out.push_str(part),
        }
    }
    out
}

/// `msg` (starting with a key path) prefixed with the line that sets the key, or the
/// line of its nearest enclosing table, if the text has one.
fn located(text: &str, msg: &str) -> Error {
    let paths = line_paths(text);
    let mut key = msg.split([' ', ':']).next().unwrap_or("");
    loop {
        let here = |p: &String| {
            p == key
                || p.strip_prefix(key)
                    .is_some_and(|rest| rest.starts_with("[0]"))
        };
        if let Some(i) = paths.iter().position(here) {
            return Error::new(format!("line {}: {msg}", i + 1));
        }
        match key.rsplit_once('.') {
            Some((parent, _)) => key = parent,
            None => return Error::new(msg),
        }
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// The key path each line of `text` sets or opens (`design.program.segment[2].law`,
/// `design.geometry`; empty for blank lines and comments): the last table header
/// (arrays of tables counted) and the line's own key. A plain reading of the lines,
/// good for the files camsim writes and their edits, used only to name places.
fn line_paths(text: &str) -> Vec<String> {
    let mut header = String::new();
    let mut seen: Vec<(String, usize)> = Vec::new();
    let join = |h: &str, k: &str| match (h.is_empty(), k.is_empty()) {
        (_, true) => h.to_string(),
        (true, false) => k.to_string(),
        (false, false) => format!("{h}.{k}"),
    };
    text.split('\n')
        .map(|line| {
            let t = line.split('#').next().unwrap_or("").trim();
            if let Some(name) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
                let name = name.trim().to_string();
                let n = match seen.iter_mut().find(|(k, _)| *k == name) {
                    Some((_, n)) => {
                        *n += 1;
                        *n
                    }
                    None => {
                        seen.push((name.clone(), 0));
                        0
                    }
                };
                header = format!("{name}[{n}]");
                header.clone()
            } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
                header = name.trim().to_string();
                header.clone()
            } else {
                match t.split_once('=') {
                    Some((k, _)) => join(&header, k.trim()),
                    None => String::new(),
                }
            }
        })
        .collect()
}

impl SceneFile {
    /// The checked scene: the run options checked, `run.rpm` applied, then the core's
    /// [`SolverSettings::validate`] and [`Design::validate`]. Errors start with the key
    /// (no line: [`parse`] adds it).
    pub fn check(&self) -> Result<CheckedScene, Error> {
        let revolutions = self.run.revolutions;
        if !(1..=MAX_REVOLUTIONS).contains(&revolutions) {
            return Err(Error::new(format!(
                "run.revolutions = {revolutions}: must be between 1 and {MAX_REVOLUTIONS}"
            )));
        }
        let follower = self.run.follower;
        if follower != FollowerModel::Full && self.run.horizontal_motion {
            return Err(Error::new(format!(
                "run.follower = \"{}\": a reduced follower needs run.horizontal_motion = false (its quasi-static roller and cantilever have no horizontal mass)",
                follower.name()
            )));
        }
        self.solver
            .validate()
            .map_err(|error| refusal("solver", error))?;
        self.limits.check()?;
        let mut design = self.design.clone();
        if let Some(rpm) = self.run.rpm {
            // The core's rules for a speed in rpm (positive, finite, 1-10 000 rpm), its
            // refusal under the scene key.
            design.set_speed_rpm(rpm).map_err(|e| match e {
                camsim_core::Error::InvalidParameter { rule, value, .. } => refusal(
                    "run",
                    camsim_core::Error::InvalidParameter {
                        field: key::RPM,
                        rule,
                        value,
                    },
                ),
                other => refusal("run", other),
            })?;
        }
        let spring = match &self.spring {
            Some(t) => Some(t.part()?),
            None => None,
        };
        if let Some(p) = &spring {
            design.k_rs = p.coil.rate();
            design.m_spring = p.coil.mass();
        }
        design
            .validate()
            .map_err(|error| refusal("design", error))?;
        Ok(CheckedScene {
            spring,
            design,
            solver: self.solver,
            revolutions,
            horizontal_motion: self.run.horizontal_motion,
            follower,
            limits: self.limits,
            motor_table: false,
            // The file as a struct holds its design's drive.
            drive_given: true,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_file_is_the_reference_and_rpm_moves_the_design() {
        let s = parse("").unwrap();
        assert_eq!(s.design, Design::<f64>::reference());
        assert_eq!(s.solver, SolverSettings::reference());
        assert_eq!((s.revolutions, s.horizontal_motion), (3, true));
        let fast = parse("[run]\nrpm = 1000\n").unwrap();
        let mut want = Design::<f64>::reference();
        want.set_speed_rpm(1000.0).unwrap();
        assert_eq!(fast.design, want);
        assert_eq!(fast.design.omega0, 1000.0 * std::f64::consts::PI / 30.0);
    }

    /// Found by the scene_file fuzz target: a key with a carriage return and NULs in it
    /// was copied into the refusal raw, which then spanned two lines.
    #[test]
    fn refusals_escape_control_characters_from_the_input() {
        let e = parse("[design]\ncontact_damping_ratio \r\0\0ollower = 1\n")
            .unwrap_err()
            .to_string();
        assert!(!e.contains(|c: char| c.is_control()), "{e:?}");
        assert!(e.starts_with("line 2, column "), "{e}");
        assert!(e.contains("\\r\\0\\0ollower"), "{e}");
        let e = load(Path::new("/nonexistent/a\nb.toml"))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("/nonexistent/a\\nb.toml: cannot read"), "{e}");
        // A measured file's name too (issue 18).
        let dir = std::env::temp_dir().join(format!("camsim-k18-esc-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a\u{1b}[2J\rb.csv");
        std::fs::write(&p, "angle_deg,lift_in\nx,0\n").unwrap();
        let e = measured::load_limited(&p, 10).unwrap_err();
        assert!(!e.contains(|c: char| c.is_control()), "{e:?}");
        assert!(e.contains("a\\u{1b}[2J\\rb.csv: line 2: angle_deg"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn long_numbers_in_type_errors_are_written_short() {
        let e = parse("[run]\nrevolutions = 1e300\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("floating point `1e300`, expected u32"), "{e}");
        let e = parse("[run]\nrevolutions = 1e-300\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`1e-300`"), "{e}");
        // Short ones stay as they are.
        let e = parse("[run]\nrevolutions = 2.5\n").unwrap_err().to_string();
        assert!(e.contains("`2.5`"), "{e}");
    }

    #[test]
    fn refusals_are_one_line_with_the_line_key_and_rule() {
        let e = parse("[run]\nrevolutions = 17\n").unwrap_err().to_string();
        assert_eq!(e, "line 2: run.revolutions = 17: must be between 1 and 16");
        let e = parse("# a comment\n[design]\nk_rb_lb_per_in = -2\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 3: design.k_rb_lb_per_in = -2: must be positive and finite"
        );
        let e = parse("[design]\nk_rb = 1\n").unwrap_err().to_string();
        assert!(
            e.starts_with("line 2, column 1: design.k_rb: unknown field `k_rb`"),
            "{e}"
        );
        let e = load(Path::new("/nonexistent/x.toml"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("/nonexistent/x.toml: cannot read the scene file"),
            "{e}"
        );
    }

    /// The reference scene as the host writes it, every dimensional value scaled by
    /// 1.05 (off the defaults, so a key ignored would show), once with the inch keys and
    /// once with the SI keys (values times the exact factors).
    fn scaled_scene_in_both_families() -> (String, String, usize) {
        let text = toml::to_string(&SceneFile::default()).unwrap();
        let paths = line_paths(&text);
        let (mut inch, mut si, mut n) = (String::new(), String::new(), 0);
        for (line, path) in text.lines().zip(&paths) {
            let norm: String = path
                .split('[')
                .map(|p| p.split_once(']').map_or(p, |(_, r)| r))
                .collect();
            let (table, name) = norm.rsplit_once('.').unwrap_or(("", &norm));
            match (units::lookup(table, name), line.split_once(" = ")) {
                (Some((uk, false)), Some((k, v))) => {
                    let x: f64 = v.trim().parse().unwrap();
                    let x = x * 1.05;
                    n += usize::from(x != 0.0);
                    inch += &format!("{k} = {x:?}\n");
                    si += &format!(
                        "{} = {:?}\n",
                        k.replace(uk.inch(), &uk.si()),
                        x * uk.unit.si_per_inch
                    );
                }
                _ => {
                    inch += &format!("{line}\n");
                    si += &format!("{line}\n");
                }
            }
        }
        (inch, si, n)
    }

    fn numbers(file: &SceneFile) -> Vec<(String, f64)> {
        fn flat(prefix: &str, v: &toml::Value, out: &mut Vec<(String, f64)>) {
            match v {
                toml::Value::Table(t) => {
                    for (k, v) in t {
                        flat(&format!("{prefix}.{k}"), v, out);
                    }
                }
                toml::Value::Array(a) => {
                    for (i, v) in a.iter().enumerate() {
                        flat(&format!("{prefix}[{i}]"), v, out);
                    }
                }
                toml::Value::Float(x) => out.push((prefix.to_string(), *x)),
                toml::Value::Integer(x) => out.push((prefix.to_string(), *x as f64)),
                _ => {}
            }
        }
        let mut out = Vec::new();
        flat("", &toml::Value::try_from(file).unwrap(), &mut out);
        out
    }

    #[test]
    fn the_spring_part_reads_in_either_family_and_gives_the_rate_and_mass() {
        let inch = "[design.spring]\nwire_diameter_in = 0.2\nmean_diameter_in = 1.2\nactive_coils = 6\nmaterial = \"chrome-silicon\"\nfree_length_in = 4\nshear_modulus_psi = 11e6\n";
        let si = "[design.spring]\nwire_diameter_mm = 5.08\nmean_diameter_mm = 30.48\nactive_coils = 6\nmaterial = \"chrome-silicon\"\nfree_length_mm = 101.6\nshear_modulus_mpa = 75842.33022485198\n";
        let (a, b) = (parse(inch).unwrap(), parse(si).unwrap());
        let (pa, pb) = (a.spring.unwrap(), b.spring.unwrap());
        // k = G d^4 / (8 D^3 N_a) = 11e6 * 0.0016 / (8 * 1.728 * 6) = 212.19 lb/in; the
        // explicit G overrides the named wire's 11.2e6 psi.
        let k = 11e6 * 0.2f64.powi(4) / (8.0 * 1.2f64.powi(3) * 6.0);
        assert!((a.design.k_rs / k - 1.0).abs() < 1e-12, "{}", a.design.k_rs);
        assert!((b.design.k_rs / k - 1.0).abs() < 1e-9, "{}", b.design.k_rs);
        // Mass: 8 total coils (squared and ground, the default) of steel wire.
        let m =
            0.2836 / 386.09 * (std::f64::consts::PI * 0.01) * (std::f64::consts::PI * 1.2) * 8.0;
        assert!((a.design.m_spring / m - 1.0).abs() < 1e-12);
        assert!((pb.free_length.unwrap() - 4.0).abs() < 1e-12);
        assert!((pa.coil.wire_diameter - pb.coil.wire_diameter).abs() < 1e-15);
        // The allowable is chrome-silicon's at d: 0.5 * 202 kpsi / 0.2^0.108.
        let allowable = 0.5 * 202e3 / 0.2f64.powf(0.108);
        assert!((pa.coil.material.allowable_shear / allowable - 1.0).abs() < 1e-12);
        // A rate beside the part is refused, named as the user wrote it.
        let e = parse(&format!("[design]\nspring_rate_n_per_mm = 10\n{si}"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "line 2: design.spring_rate_n_per_mm and [design.spring] both give the spring"
            ),
            "{e}"
        );
        let e = parse(&si.replace("chrome-silicon", "piano"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 5: design.spring.material = \"piano\": not a named wire"),
            "{e}"
        );
    }

    #[test]
    fn a_scene_in_si_units_is_the_same_scene_in_inch() {
        let (inch, si, n) = scaled_scene_in_both_families();
        // Every dimensional key of the table appears: the design's, the segments'
        // lifts, the solver's atol and the limits' stress ([design.spring]'s keys are not
        // in the default scene: `the_spring_part_reads_in_either_family`; the motor's four
        // keys are rules that set other keys, not fields a scene writes).
        let spring_keys = units::UNIT_KEYS
            .iter()
            .filter(|k| k.key.starts_with("spring."))
            .count();
        assert!(n >= units::UNIT_KEYS.len() - spring_keys - 2 - 4, "{n}");
        assert!(si.contains("spring_rate_n_per_mm = "), "{si}");
        assert!(si.contains("base_radius_mm = "), "{si}");
        assert!(si.contains("lift_mm = "), "{si}");
        assert!(si.contains("allowable_contact_stress_mpa = "), "{si}");
        let (a, _) = read_scene(&inch).unwrap();
        let (b, _) = read_scene(&si).unwrap();
        let (na, nb) = (numbers(&a), numbers(&b));
        let reference = numbers(&SceneFile::default());
        assert_eq!(na.len(), nb.len());
        let mut moved = 0;
        for (((ka, xa), (kb, xb)), (_, x0)) in na.iter().zip(&nb).zip(&reference) {
            assert_eq!(ka, kb);
            assert!((xa - xb).abs() <= 1e-13 * xa.abs(), "{ka}: {xa} vs {xb}");
            moved += usize::from(xa != x0);
        }
        assert!(
            moved >= n,
            "{moved} of {n} scaled values differ from the reference"
        );
        // Both pass the checks, and the derived spring (the mass follows the rate)
        // is the same.
        let (ca, cb) = (parse(&inch).unwrap(), parse(&si).unwrap());
        assert!((ca.design.m_spring - cb.design.m_spring).abs() <= 1e-13 * ca.design.m_spring);
        assert_eq!(
            ca.limits.pressure_angle_limit_deg,
            cb.limits.pressure_angle_limit_deg
        );
        // 50.8 mm is 2 in; 17.512683524647638 N/mm is 100 lb/in.
        let s = parse("[design]\nspring_rate_n_per_mm = 17.512683524647638\n[design.geometry]\nbase_radius_mm = 50.8\n").unwrap();
        assert!((s.design.k_rs - 100.0).abs() < 1e-12);
        assert!((s.design.geometry.base_radius - 2.0).abs() < 1e-15);
        // Families mix freely.
        let s = parse("[design]\nspring_rate_lb_per_in = 60\ne2_mm = 101.6\n").unwrap();
        assert_eq!((s.design.k_rs, s.design.e2), (60.0, 4.0));
    }

    #[test]
    fn one_quantity_given_twice_names_both_keys() {
        let e = parse("[design]\nspring_rate_lb_per_in = 60\nspring_rate_n_per_mm = 10\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 3: design.spring_rate_n_per_mm and design.spring_rate_lb_per_in: both give the spring rate (once in N/mm, once in lb/in): give one of them"
        );
        let e = parse("[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 0\nend_deg = 360\nlift_in = 0\nlift_mm = 0\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("line 6: design.program.segment[0].lift_mm and design.program.segment[0].lift_in: both give the lift"), "{e}");
    }

    #[test]
    fn a_refused_si_value_is_named_as_written() {
        let e = parse("[design.geometry]\nbase_radius_mm = 0.1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 2: design.geometry.base_radius_mm = 0.1 (0.003937008 in): must lie in [0.01, 100] in"),
            "{e}"
        );
        // Not a number: the type error at the user's line and key.
        let e = parse("[design]\ne2_mm = \"long\"\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 2, column 9: design.e2_mm: invalid type: string"),
            "{e}"
        );
    }

    #[test]
    fn unknown_keys_get_the_nearest_names() {
        let e = parse("[design]\nk_rb_lb_per_inch = 1\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 2, column 1: design.k_rb_lb_per_inch: unknown field `k_rb_lb_per_inch`: did you mean `k_rb_lb_per_in`?"
        );
        // A key without its unit: both families.
        let e = parse("[design]\nspring_rate = 60\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("did you mean `spring_rate_lb_per_in` or `spring_rate_n_per_mm`?"),
            "{e}"
        );
        // An SI misspelling finds the SI name.
        let e = parse("[design.geometry]\nbase_radius_nm = 50\n")
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("did you mean `base_radius_mm`?"), "{e}");
        // Nothing near: no list of every key.
        let e = parse("[run]\nflux_capacitor = 1\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 2, column 1: run.flux_capacitor: unknown field `flux_capacitor`: not a key of [run] (`camsim scene --default` writes every key)"
        );
        assert!(e.len() < 200);
        let e = parse("[limit]\n").unwrap_err().to_string();
        assert!(e.contains("did you mean `limits`?"), "{e}");
    }

    #[test]
    fn a_derived_refusal_is_put_on_the_users_key() {
        // The reference's e2 (2 in) and roller (0.5 in) with a 3 in lift: the user set
        // the lift, not e2.
        let text = "[design]\nspring_rate_lb_per_in = 100\n\n[[design.program.segment]]\nkind = \"rise\"\nlaw = \"cycloidal\"\nstart_deg = 0\nend_deg = 180\nlift_in = 3\n\n[[design.program.segment]]\nkind = \"return\"\nlaw = \"cycloidal\"\nstart_deg = 180\nend_deg = 360\nlift_in = 3\n";
        let e = parse(text).unwrap_err().to_string();
        assert!(
            e.starts_with("line 9: design.program.segment[0].lift_in = 3: it makes design.e2_in = 2 (not in the file: the reference's value) fail: cantilever length must exceed"),
            "{e}"
        );
        // The same in mm names the mm key.
        let e = parse(&text.replace("lift_in = 3", "lift_mm = 76.2"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "line 9: design.program.segment[0].lift_mm = 76.2: it makes design.e2_mm = 50.8 (not in the file"
            ),
            "{e}"
        );
        // A file that sets e2 itself gets the refusal on its own line.
        let e = parse(&text.replace("spring_rate_lb_per_in = 100", "e2_in = 2"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 2: design.e2_in = 2: cantilever length"),
            "{e}"
        );
    }

    /// The moving mass sets the load: the model's translating mass is the given one (1.2
    /// kg is 1.2 / 0.45359237 lb, over g = 386.0886 in/s² in lb·s²/in), in either family.
    #[test]
    fn a_moving_mass_sets_the_load_and_a_light_one_is_refused() {
        let si = parse("[design]\nmoving_mass_kg = 3.2\n").unwrap();
        let want = 3.2 / 0.453_592_37 / (9.806_65 / 0.0254);
        let total = si.design.moving_mass().total();
        assert!((total / want - 1.0).abs() < 1e-12, "{total} {want}");
        let inch = parse("[design]\nmoving_mass_lb = 7.054792389916\n").unwrap();
        assert!((inch.design.m_l / si.design.m_l - 1.0).abs() < 1e-12);
        // Only the load moved.
        let mut d = Design::<f64>::reference();
        d.m_l = si.design.m_l;
        assert_eq!(si.design, d);
        // Lighter than rod, roller and spring share (1.5698 kg): refused,
        // naming the user's key and every part in kg.
        let e = parse("[design]\nmoving_mass_kg = 0.5\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 2: design.moving_mass_kg = 0.5: leaves no load mass: the follower rod rho*A*(e1+e2) 1.5314 kg"),
            "{e}"
        );
        assert!(e.contains(" kg, the roller 0.0228 kg"), "{e}");
        // Not with the load mass as well.
        let e = parse("[design]\nmoving_mass_lb = 5\nload_mass_kg = 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("both set the load"), "{e}");
        let e = parse("[design]\nmoving_mass_lb = -1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("design.moving_mass_lb = -1: must be positive"),
            "{e}"
        );
    }

    /// A spring rate's derived values are refused under the rate (33.8), and the modal
    /// rate follows the rate unless the file gives it.
    #[test]
    fn derived_spring_values_follow_and_name_the_rate() {
        let e = parse("[design]\nspring_rate_lb_per_in = 1e-310\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("design.spring_rate_lb_per_in = 1e-310: must lie in"),
            "{e}"
        );
        let d = parse("[design]\nspring_rate_n_per_mm = 10\n")
            .unwrap()
            .design;
        assert_eq!(d.k_rs_modal, d.k_rs);
        let d = parse("[design]\nspring_rate_lb_per_in = 60\nspring_modal_rate_lb_per_in = 90\n")
            .unwrap()
            .design;
        assert_eq!((d.k_rs, d.k_rs_modal), (60.0, 90.0));
    }

    /// A program that does not close, in mm, is refused in mm.
    #[test]
    fn a_program_refusal_is_in_the_files_lift_unit() {
        let text = "[[design.program.segment]]\nkind = \"rise\"\nlaw = \"cycloidal\"\nstart_deg = 0\nend_deg = 180\nlift_mm = 40\n\n[[design.program.segment]]\nkind = \"return\"\nlaw = \"cycloidal\"\nstart_deg = 180\nend_deg = 360\nlift_mm = 39\n";
        let e = parse(text).unwrap_err().to_string();
        assert!(
            e.contains("design.program.segment (lift_mm) = 1 mm: net displacement"),
            "{e}"
        );
        assert!(!e.contains("_in"), "{e}");
    }

    #[test]
    fn limits_are_scene_keys_in_either_family() {
        let s = parse("").unwrap();
        assert_eq!(s.limits, Limits::default());
        assert_eq!(
            s.limits.allowable_contact_stress_psi,
            camsim_core::ALLOWABLE_CONTACT_STRESS_PSI
        );
        let s =
            parse("[limits]\nallowable_contact_stress_mpa = 1000\npressure_angle_limit_deg = 35\n")
                .unwrap();
        assert!((s.limits.allowable_contact_stress_psi - 145_037.737_730_209).abs() < 1e-6);
        assert_eq!(s.limits.pressure_angle_limit_deg, 35.0);
        let e = parse("[limits]\npressure_angle_limit_deg = 90\n")
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "line 2: limits.pressure_angle_limit_deg = 90: must be above 0 and below 90 (degrees)"
        );
        let e = parse("[limits]\nallowable_contact_stress_mpa = -1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("line 2: limits.allowable_contact_stress_mpa = -1 ("),
            "{e}"
        );
    }

    #[test]
    fn a_measured_profile_given_as_a_scene_gets_a_hint() {
        let dir = std::env::temp_dir().join(format!("camsim-keys18-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("wavy.csv");
        std::fs::write(&p, "# a profile\nangle_deg,deviation_in\n0,0\n").unwrap();
        let e = load(&p).unwrap_err().to_string();
        assert!(
            e.contains("a measured profile (CSV)? give it as `--measured "),
            "{e}"
        );
        let p = dir.join("wavy.txt");
        std::fs::write(&p, "angle_deg,lift_in\n0,0\n").unwrap();
        assert!(load(&p).unwrap_err().to_string().contains("--measured"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
