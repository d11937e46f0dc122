//! Scene files: the run options, the solver settings and the design in TOML.
//!
//! The file is `[run]` (what to simulate that is not part of the design), `[solver]`
//! (core's [`SolverSettings`]) and `[design]` (core's [`Design`] as it serializes:
//! units in the key names, see [`camsim_core::key`]). Every key is optional and
//! defaults to the reference (`camsim scene --default` prints them all); unknown keys
//! are refused, so a typo never passes silently. The checks are the core's
//! ([`Design::validate`], [`SolverSettings::validate`]); errors name the key and rule.

use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use camsim_core::{key, Design, DriveLaw, SegmentKind, SolverSettings};
use serde::{Deserialize, Serialize};

use crate::sim::{Dofs, RunSpec};

/// `[run]`: what to simulate that is not part of the design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RunOptions {
    /// Revolutions to simulate (1-16).
    pub revolutions: u32,
    /// Keep the horizontal motion (x1, x2, x3).
    pub horizontal_motion: bool,
    /// Cam speed in rpm, instead of `design.omega0_rad_per_s`: moves the design to this
    /// speed like `--rpm` ([`Design::set_speed_rpm`]: ω0, the regulated drive's
    /// reference, its feed-forward scaled with speed). Never written back.
    pub rpm: Option<f64>,
}

impl Default for RunOptions {
    fn default() -> Self {
        let r = RunSpec::reference();
        RunOptions {
            revolutions: r.revolutions,
            horizontal_motion: r.dofs.horizontal,
            rpm: None,
        }
    }
}

/// A whole scene file.
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

/// Reads and validates a scene file (errors start with the file's name).
pub fn load(path: &Path) -> Result<RunSpec> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("{}: cannot read the scene file", path.display()))?;
    parse(&text).map_err(|e| anyhow!("{}: {e:#}", path.display()))
}

/// Parses and validates scene text. Errors are one line: where TOML or serde refused
/// it, the line, column and key; where the checks refused it, the line that sets the
/// key (if the text sets it), the key, the value and the rule.
pub fn parse(text: &str) -> Result<RunSpec> {
    let file: SceneFile = toml::from_str(text).map_err(|e| toml_error(text, &e))?;
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
    file.run_spec()
        .map_err(|e| located(text, &format!("{e:#}")))
}

/// A core check's refusal in `section` (`design`, `solver`): its key under the section,
/// the value and the rule (`design.spring_rate_lb_per_in = -1: must be positive and
/// finite`).
#[derive(Debug)]
struct Refusal {
    section: &'static str,
    error: camsim_core::Error,
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.error {
            // Both start with the key: put the section in front of it.
            camsim_core::Error::InvalidParameter { .. }
            | camsim_core::Error::Inconsistent { .. } => {
                write!(f, "{}.{}", self.section, self.error)
            }
            other => write!(f, "{}: {other}", self.section),
        }
    }
}

impl std::error::Error for Refusal {}

/// One line for a TOML or serde error: line, column, the key there, the message. A
/// program refused as it is read (by the core's `CamProgram::new`) names its own key.
fn toml_error(text: &str, e: &toml::de::Error) -> anyhow::Error {
    let msg = e.message().trim().replace('\n', " ");
    if msg.starts_with(key::PROGRAM_SEGMENT) {
        return located(text, &format!("design.{msg}"));
    }
    let Some(span) = e.span() else {
        return anyhow!("{msg}");
    };
    let (line, col) = line_col(text, span.start);
    match line_paths(text).get(line - 1).filter(|k| !k.is_empty()) {
        Some(k) => anyhow!("line {line}, column {col}: {k}: {msg}"),
        None => anyhow!("line {line}, column {col}: {msg}"),
    }
}

/// `msg` (starting with a key path) prefixed with the line that sets the key, or the
/// line of its nearest enclosing table, if the text has one.
fn located(text: &str, msg: &str) -> anyhow::Error {
    let paths = line_paths(text);
    let mut key = msg.split([' ', ':']).next().unwrap_or("");
    loop {
        let here = |p: &String| {
            p == key
                || p.strip_prefix(key)
                    .is_some_and(|rest| rest.starts_with("[0]"))
        };
        if let Some(i) = paths.iter().position(here) {
            return anyhow!("line {}: {msg}", i + 1);
        }
        match key.rsplit_once('.') {
            Some((parent, _)) => key = parent,
            None => return anyhow!("{msg}"),
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
/// good for the files this program writes and their edits, used only to name places.
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

impl From<&RunSpec> for SceneFile {
    /// A complete scene file describing `spec` (the speed as `design.omega0_rad_per_s`).
    fn from(spec: &RunSpec) -> Self {
        SceneFile {
            run: RunOptions {
                revolutions: spec.revolutions,
                horizontal_motion: spec.dofs.horizontal,
                rpm: None,
            },
            solver: spec.solver,
            design: spec.design.clone(),
        }
    }
}

impl SceneFile {
    /// The validated run specification: the run options checked, `run.rpm` applied,
    /// then the core's [`SolverSettings::validate`] and [`Design::validate`].
    pub fn run_spec(&self) -> Result<RunSpec> {
        let revolutions = self.run.revolutions;
        if !(1..=16).contains(&revolutions) {
            bail!("run.revolutions = {revolutions}: must be between 1 and 16");
        }
        self.solver.validate().map_err(|error| Refusal {
            section: "solver",
            error,
        })?;
        let mut design = self.design.clone();
        if let Some(rpm) = self.run.rpm {
            if !(rpm.is_finite() && rpm > 0.0) {
                bail!("run.rpm = {rpm}: must be positive and finite");
            }
            design
                .set_speed_rpm(rpm)
                .map_err(|e| anyhow!("run.rpm = {rpm}: {e}"))?;
        }
        design.validate().map_err(|error| Refusal {
            section: "design",
            error,
        })?;
        Ok(RunSpec {
            design,
            dofs: Dofs {
                horizontal: self.run.horizontal_motion,
            },
            solver: self.solver,
            revolutions,
        })
    }
}

/// What each `[run]` and `[solver]` key is (for the comments of a written scene).
const HOST_KEYS: &[(&str, &str)] = &[
    ("run.revolutions", "revolutions to simulate (1-16)"),
    (
        "run.horizontal_motion",
        "keep the horizontal motion x1, x2, x3",
    ),
    ("solver.rtol", "relative tolerance"),
    ("solver.atol_in", "absolute tolerance of displacements"),
    (
        "solver.max_step_fraction_rev",
        "largest double step, fraction of a revolution",
    ),
    ("solver.max_steps_per_rev", "step budget per revolution"),
    (
        "solver.start",
        "\"thesis\" (VI.1) or \"static\" (static equilibrium)",
    ),
];

/// `text` with a comment after every known key saying what it is.
fn annotate(text: &str) -> String {
    let mut header = String::new();
    let mut out = String::with_capacity(text.len() * 2);
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
            header = name.to_string();
        } else if let Some(name) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
            header = name.to_string();
        }
        let doc = t.split_once(" = ").and_then(|(k, _)| {
            let path = if header.is_empty() {
                k.to_string()
            } else {
                format!("{header}.{k}")
            };
            let in_design = path.strip_prefix("design.").unwrap_or("");
            HOST_KEYS
                .iter()
                .chain(key::DESIGN_KEYS)
                .find(|(p, _)| *p == path || *p == in_design)
                .map(|(_, d)| *d)
        });
        out.push_str(line);
        if let Some(d) = doc {
            out.push_str("  # ");
            out.push_str(d);
        }
        out.push('\n');
    }
    out
}

/// A complete scene file (TOML text) for `spec`, every key present and commented.
pub fn spec_text(spec: &RunSpec) -> Result<String> {
    Ok(annotate(&toml::to_string_pretty(&SceneFile::from(spec))?))
}

/// The reference design as TOML text.
pub fn default_text() -> Result<String> {
    let body = spec_text(&RunSpec::reference())?;
    Ok(format!(
        "# camsim scene: the reference design of Kim (1982), VI.1, with the documented choices\n\
         # for what the thesis leaves out (core/src/design.rs). Units are in the key names\n\
         # (inch, pound-force, second, radian). Every key is optional: absent keys take these\n\
         # values. [run] rpm = N sets the cam speed in rpm instead of design.omega0_rad_per_s\n\
         # (and moves the regulated drive's reference with it, like --rpm).\n\
         # drive: \"constant-cam-speed\", \"constant-motor-speed\" or a [design.drive.regulated] table.\n\
         # program: [[design.program.segment]] with kind \"dwell\", \"rise\" or \"return\",\n\
         # law (names as in `camsim laws`) for a rise or return, start_deg, end_deg, lift_in.\n\n{body}"
    ))
}

/// Rust source for the firmware: the scene as a `const` [`camsim_core::DesignRecord`]
/// named `SCENE` (every number printed with Rust's round-trip `f64` formatting).
pub fn rust_source(spec: &RunSpec, origin: &str) -> String {
    use std::fmt::Write;
    let r = spec.design.to_record();
    let mut o = String::new();
    let _ = writeln!(
        o,
        "// Generated by `camsim scene --rust {origin}`: the design compiled into the firmware."
    );
    let _ = writeln!(o, "// Do not edit; regenerate from the scene file.");
    let _ = writeln!(o, "/// The scene compiled in (from {origin}).");
    let _ = writeln!(
        o,
        "pub const SCENE: camsim_core::DesignRecord = camsim_core::DesignRecord {{"
    );
    let _ = write!(o, "    values: [");
    for (i, v) in r.values.iter().enumerate() {
        let _ = write!(o, "{}{v:?}_f64", if i == 0 { "" } else { ", " });
    }
    let _ = writeln!(o, "],");
    let drive = match r.drive {
        DriveLaw::ConstantCamSpeed => "camsim_core::DriveLaw::ConstantCamSpeed".to_string(),
        DriveLaw::ConstantMotorSpeed => "camsim_core::DriveLaw::ConstantMotorSpeed".to_string(),
        DriveLaw::Regulated { omega_ref, t_steady, k_p, t_max } => format!(
            "camsim_core::DriveLaw::Regulated {{ omega_ref: {omega_ref:?}_f64, t_steady: {t_steady:?}_f64, k_p: {k_p:?}_f64, t_max: {t_max:?}_f64 }}"
        ),
    };
    let _ = writeln!(o, "    drive: {drive},");
    let _ = writeln!(o, "    segments: [");
    for s in &r.segments {
        let kind = match s.kind {
            SegmentKind::Dwell => "camsim_core::SegmentKind::Dwell".to_string(),
            SegmentKind::Rise(l) => {
                format!("camsim_core::SegmentKind::Rise(camsim_core::MotionLaw::{l:?})")
            }
            SegmentKind::Return(l) => {
                format!("camsim_core::SegmentKind::Return(camsim_core::MotionLaw::{l:?})")
            }
        };
        let _ = writeln!(
            o,
            "        camsim_core::Segment {{ kind: {kind}, start_deg: {:?}_f64, end_deg: {:?}_f64, lift: {:?}_f64 }},",
            s.start_deg, s.end_deg, s.lift
        );
    }
    let _ = writeln!(o, "    ],");
    let _ = writeln!(o, "    segment_count: {},", r.segment_count);
    let _ = writeln!(o, "}};");
    o
}
