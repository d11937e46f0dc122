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
    fn new(message: impl Into<String>) -> Self {
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

/// Reads at most `max` bytes of UTF-8 text from `path`: `what` names the file in the
/// refusals (`the scene file`), which are one line each: unreadable, larger than `max`,
/// or not UTF-8 (with the line of the first invalid byte).
pub fn read_text(path: &Path, max: u64, what: &str) -> Result<String, Error> {
    use std::io::Read;
    let name = path.display();
    // Only a regular file, a FIFO or a character device (a process substitution, a
    // pipe) is read; a directory is refused here rather than by an odd read error.
    if std::fs::metadata(path).is_ok_and(|m| m.is_dir()) {
        return Err(Error::new(format!(
            "{name}: cannot read {what}: is a directory"
        )));
    }
    let file = std::fs::File::open(path)
        .map_err(|e| Error::new(format!("{name}: cannot read {what}: {e}")))?;
    let mut bytes = Vec::new();
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| Error::new(format!("{name}: cannot read {what}: {e}")))?;
    if bytes.len() as u64 > max {
        return Err(Error::new(format!(
            "{name}: {what} is larger than its limit of {max} bytes (read no further)"
        )));
    }
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
/// [`MAX_SCENE_BYTES`] are read).
pub fn load(path: &Path) -> Result<CheckedScene, Error> {
    let text = read_text(path, MAX_SCENE_BYTES, "the scene file")?;
    parse(&text).map_err(|e| Error::new(format!("{}: {e}", path.display())))
}

/// Parses and checks scene text. Errors are one line: where TOML or serde refused
/// it, the line, column and key; where the checks refused it, the line that sets the
/// key (if the text sets it), the key, the value and the rule.
pub fn parse(text: &str) -> Result<CheckedScene, Error> {
    let mut file: SceneFile = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
    // A spring rate without a spring mass: the mass follows the rate by the one
    // wire-and-coil model (camsim-core's `HelicalSpring`, docs/MODEL.md §5.6), as it does
    // for `--spring-rate`. A file that gives the mass keeps it.
    let sets = |k: &str| -> bool {
        toml::from_str::<toml::Table>(text)
            .ok()
            .and_then(|t| t.get("design")?.as_table().map(|d| d.contains_key(k)))
            .unwrap_or(false)
    };
    if sets(key::K_RS) && !sets(key::M_SPRING) {
        if let Ok(spring) = camsim_core::HelicalSpring::of_rate(file.design.k_rs) {
            file.design.m_spring = spring.mass;
        }
    }
    let rpm_conflict = || -> Option<&'static str> {
        let t: toml::Table = toml::from_str(text).ok()?;
        let d = t.get("design")?.as_table()?;
        if d.contains_key(key::OMEGA0) {
            return Some(key::OMEGA0);
        }
        let r = d.get("drive")?.get("regulated")?.as_table()?;
        let omega_ref = key::DRIVE_OMEGA_REF.rsplit('.').next()?;
        r.contains_key(omega_ref).then_some(key::DRIVE_OMEGA_REF)
    };
    if file.run.rpm.is_some() {
        if let Some(k) = rpm_conflict() {
            return Err(located(
                text,
                &format!("run.rpm and design.{k} both set the cam speed: give one of them"),
            ));
        }
    }
    file.check().map_err(|e| located(text, &e.message))
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
fn toml_error(text: &str, e: &toml::de::Error) -> Error {
    let msg = short_numbers(&e.message().trim().replace('\n', " "));
    if msg.starts_with(key::PROGRAM_SEGMENT) {
        return located(text, &format!("design.{msg}"));
    }
    let Some(span) = e.span() else {
        return Error::new(msg);
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
    Error::new(
        match line_paths(text).get(line - 1).filter(|k| !k.is_empty()) {
            Some(k) => format!("line {line}, column {col}: {k}: {msg}"),
            None => format!("line {line}, column {col}: {msg}"),
        },
    )
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
        design
            .validate()
            .map_err(|error| refusal("design", error))?;
        Ok(CheckedScene {
            design,
            solver: self.solver,
            revolutions,
            horizontal_motion: self.run.horizontal_motion,
            follower,
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
}
