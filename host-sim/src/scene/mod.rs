//! Scene files: the run options, the solver settings and the design in TOML.
//!
//! Reading and checking is the `camsim-scene-file` crate's ([`camsim_scene_file::parse`]),
//! the one parser the firmware's build script (`CAMSIM_SCENE`) uses too; this module
//! turns its result into a [`RunSpec`] and writes scene files (`camsim scene`). The file
//! is `[run]`, `[solver]` (core's [`camsim_core::SolverSettings`]) and `[design]` (core's
//! [`camsim_core::Design`] as it serializes: units in the key names, see
//! [`camsim_core::key`]). Every key is optional and defaults to the reference; unknown
//! keys are refused; errors name the line, the key and the rule.

pub mod template;

use std::path::Path;

use anyhow::Result;
use camsim_core::key;
pub use camsim_scene_file::{CheckedScene, RunOptions, SceneFile, MAX_SCENE_BYTES};

use crate::sim::{Dofs, RunSpec};

/// Reads and validates a scene file (errors start with the file's name).
pub fn load(path: &Path) -> Result<RunSpec> {
    Ok(run_spec(camsim_scene_file::load(path)?))
}

/// Parses and validates scene text. Errors are one line: where TOML or serde refused
/// it, the line, column and key; where the checks refused it, the line that sets the
/// key (if the text sets it), the key, the value and the rule.
pub fn parse(text: &str) -> Result<RunSpec> {
    Ok(run_spec(camsim_scene_file::parse(text)?))
}

/// The run specification of a checked scene.
pub fn run_spec(scene: CheckedScene) -> RunSpec {
    RunSpec {
        design: scene.design,
        dofs: Dofs {
            horizontal: scene.horizontal_motion,
            follower: scene.follower,
        },
        solver: scene.solver,
        revolutions: scene.revolutions,
        profile: None,
        limits: scene.limits,
        spring: scene.spring,
        motor_table: scene.motor_table,
        drive_given: scene.drive_given,
    }
}

/// A complete scene file describing `spec` (the speed as `design.omega0_rad_per_s`).
fn scene_file(spec: &RunSpec) -> SceneFile {
    SceneFile {
        run: RunOptions {
            revolutions: spec.revolutions,
            horizontal_motion: spec.dofs.horizontal,
            follower: spec.dofs.follower,
            rpm: None,
        },
        solver: spec.solver,
        design: spec.design.clone(),
        limits: spec.limits,
        spring: None,
    }
}

/// What each `[run]` and `[solver]` key is (for the comments of a written scene).
const HOST_KEYS: &[(&str, &str)] = &[
    ("run.revolutions", "revolutions to simulate (1-16)"),
    (
        "run.horizontal_motion",
        "keep the horizontal motion x1, x2, x3",
    ),
    (
        "run.follower",
        "\"full\", or quasi-static: \"massless-roller\", \"quasi-static-cantilever\", \"quasi-static-rod\", \"quasi-static-shaft\"",
    ),
    ("solver.rtol", "relative tolerance"),
    ("solver.atol_in", "absolute tolerance of displacements"),
    (
        "solver.max_step_fraction_rev",
        "largest double step, fraction of a revolution",
    ),
    ("solver.max_steps_per_rev", "step budget per revolution"),
    (
        "limits.allowable_contact_stress_psi",
        "allowable Hertz contact stress of the verdict (--allowable-stress)",
    ),
    (
        "limits.pressure_angle_limit_deg",
        "largest pressure angle without a warning, 0-90 (--pressure-angle-limit)",
    ),
    (
        "solver.start",
        "\"thesis\" (VI.1) or \"static\" (static equilibrium)",
    ),
    (
        "solver.step_control",
        "\"scaled-cap\" (England, stiffness cap scaled by rtol), \"pi-scaled-cap\" or \"thesis\" (England uncapped)",
    ),
    (
        "solver.method",
        "\"auto\" (merson at rtol >= 1e-6, england below), \"england\" (the thesis's), \"merson\" (imaginary axis) or \"dormand-prince\" (accuracy-limited)",
    ),
];

/// The table a trimmed TOML line opens (`[design.geometry]`, `[[design.program.segment]]`),
/// if it opens one.
fn table_header(line: &str) -> Option<&str> {
    line.strip_prefix("[[")
        .and_then(|r| r.strip_suffix("]]"))
        .or_else(|| line.strip_prefix('[').and_then(|r| r.strip_suffix(']')))
}

/// `text` with a comment after every known key saying what it is.
fn annotate(text: &str) -> String {
    use camsim_scene_file::units::lookup;
    let mut header = String::new();
    let mut out = String::with_capacity(text.len() * 2);
    for line in text.lines() {
        let t = line.trim();
        if let Some(name) = table_header(t) {
            header = name.to_string();
        }
        let doc = t.split_once(" = ").and_then(|(k, _)| {
            // A key in SI is described by its inch-family name's description.
            let k = lookup(&header, k).map_or(k, |(unit_key, _)| unit_key.inch());
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
    Ok(annotate(&toml::to_string_pretty(&scene_file(spec))?))
}

/// [`spec_text`] with its keys in SI (`base_radius_mm`, ...): the same scene, reading
/// back to the same design. The tree is the scene's, in the order the inch file writes
/// it; each key of the unit table is named and converted by the table (`in_si`).
pub fn spec_text_si(spec: &RunSpec) -> Result<String> {
    let file = scene_file(spec);
    let inch = toml::to_string_pretty(&file)?;
    let order = toml::de::DeTable::parse(&inch)?;
    let mut tree = Node::of(toml::Value::try_from(&file)?, order.get_ref());
    in_si(&mut tree, "");
    Ok(annotate(&toml::to_string_pretty(&tree)?))
}

/// A scene's TOML tree whose tables keep their keys' order (`toml`'s own table sorts
/// them): the order the scene's types give, as the inch file writes it.
enum Node {
    /// A value that is not a table or an array.
    Leaf(toml::Value),
    /// A table's entries in order.
    Table(Vec<(String, Node)>),
    /// An array (of tables: `[[design.program.segment]]`).
    Array(Vec<Node>),
}

impl Node {
    /// `value` with its tables' keys in the order of `written`, its document as read.
    fn of(value: toml::Value, written: &toml::de::DeTable) -> Node {
        Self::ordered(value, &toml::de::DeValue::Table(written.clone()))
    }

    fn ordered(value: toml::Value, written: &toml::de::DeValue) -> Node {
        use toml::de::DeValue;
        match (value, written) {
            (toml::Value::Table(mut t), DeValue::Table(w)) => {
                let mut keys: Vec<_> = w.iter().collect();
                keys.sort_by_key(|(k, _)| k.span().start);
                let entries = keys.into_iter().filter_map(|(k, wv)| {
                    let k: &str = k.get_ref();
                    let v = t.remove(k)?;
                    Some((k.to_string(), Self::ordered(v, wv.get_ref())))
                });
                Node::Table(entries.collect())
            }
            (toml::Value::Array(a), DeValue::Array(w)) => Node::Array(
                a.into_iter()
                    .zip(w.iter())
                    .map(|(v, wv)| Self::ordered(v, wv.get_ref()))
                    .collect(),
            ),
            (v, _) => Node::Leaf(v),
        }
    }
}

impl serde::Serialize for Node {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        match self {
            Node::Leaf(v) => v.serialize(s),
            Node::Table(entries) => {
                let mut m = s.serialize_map(Some(entries.len()))?;
                for (k, v) in entries {
                    m.serialize_entry(k, v)?;
                }
                m.end()
            }
            Node::Array(items) => s.collect_seq(items),
        }
    }
}

/// The part of the scene file's header that both unit families share.
const KEYS_NOTE: &str = "# Every key is optional: absent keys take these\n\
         # values. [run] rpm = N sets the cam speed in rpm instead of design.omega0_rad_per_s\n\
         # (and moves the regulated drive's reference with it, like --rpm).\n\
         # drive: \"constant-cam-speed\" (or \"constant-speed\"), \"constant-motor-speed\", \"thesis\" (the\n\
         # default below), a [design.drive.regulated] table, or a [design.drive.motor] table (inertia,\n\
         # shaft_stiffness, gain, torque_limit, each with its unit; see docs/MODEL.md 5.17).\n\
         # program: [[design.program.segment]] with kind \"dwell\", \"rise\" or \"return\",\n\
         # law (names as in `camsim laws`) for a rise or return, start_deg, end_deg, ";

/// The reference design as TOML text.
pub fn default_text() -> Result<String> {
    let body = spec_text(&RunSpec::reference())?;
    Ok(format!(
        "# camsim scene: the reference design of Kim (1982), VI.1, with the documented choices\n\
         # for what the thesis leaves out (core/src/model/design.rs). Units are in the key names\n\
         # (inch, pound-force, second, radian); every key with a unit also reads in SI, the\n\
         # same name with the SI unit (base_radius_mm, spring_rate_n_per_mm, youngs_mpa, _kg).\n\
         {KEYS_NOTE}lift_in.\n\n{body}"
    ))
}

/// The reference design as TOML text in SI keys (`camsim scene --default --units si`).
pub fn default_text_si() -> Result<String> {
    let body = spec_text_si(&RunSpec::reference())?;
    Ok(format!(
        "# camsim scene: the reference design of Kim (1982), VI.1, with the documented choices\n\
         # for what the thesis leaves out (core/src/model/design.rs). Units are in the key names\n\
         # (SI: mm, N, kg, MPa, second, radian), converted from the thesis's inch family by the\n\
         # exact factors (25.4 mm to the inch, 4.4482216152605 N to the pound-force) to 10\n\
         # significant digits;\n\
         # every key with a unit also reads in the inch family (base_radius_in, spring_rate_lb_per_in).\n\
         {KEYS_NOTE}lift_mm.\n\n{body}"
    ))
}

/// Significant digits of a value written in SI: the conversion's rounding (5e-10
/// relative) is far below the solver's tolerance, so the file reads back to the same
/// results; a value exact in SI (1.5 in = 38.1 mm) prints exactly.
const SI_DIGITS: usize = 10;

/// A value of a scene written in SI, rounded to [`SI_DIGITS`] significant digits (TOML
/// writes it without trailing zeros, always with a decimal point).
fn si_number(v: f64) -> f64 {
    format!("{v:.*e}", SI_DIGITS - 1).parse().unwrap_or(v)
}

/// `node` (a scene's table at dotted path `path` from the file's root, or an array of
/// such tables) with every key of the scene files' unit table
/// ([`camsim_scene_file::units::UNIT_KEYS`]) under its SI name and its value converted
/// by its unit's factor ([`si_number`]); the keys without a unit keep their names and
/// values, every key its place.
fn in_si(node: &mut Node, path: &str) {
    use camsim_scene_file::units::lookup;
    match node {
        Node::Table(entries) => {
            for (k, v) in entries.iter_mut() {
                if let Node::Leaf(toml::Value::Float(x)) = v {
                    if let Some((unit_key, false)) = lookup(path, k) {
                        *k = unit_key.si();
                        *x = si_number(*x * unit_key.unit.si_per_inch);
                    }
                } else if path.is_empty() {
                    in_si(v, k);
                } else {
                    in_si(v, &format!("{path}.{k}"));
                }
            }
        }
        // An array of tables: every one is the same section (`design.program.segment`).
        Node::Array(items) => items.iter_mut().for_each(|t| in_si(t, path)),
        Node::Leaf(_) => {}
    }
}

/// The groups of `scene --check`'s listing of inherited values, in order.
const GROUPS: [&str; 5] = [
    "drive",
    "follower rod and bearings",
    "cam width and materials",
    "masses",
    "spring, cam and program",
];

/// The group (index into [`GROUPS`]) of a design key (relative to `[design]`).
fn group_of(rel: &str) -> usize {
    let rod = [
        key::E1,
        key::E2,
        key::BEARING_A,
        key::BEARING_B,
        key::MU,
        key::FRICTION_SMOOTHING,
        key::DAMPING_RATIO_F1,
        key::K_RB,
        key::ROLLER_BEARING_DAMPING_RATIO,
        key::K_VS,
        key::C_VS,
        key::K_HS,
        key::C_HS,
    ];
    // The drive: what a constant-cam-speed run drops, and the cam's drag and speed.
    let drive =
        NOT_USED_AT_CONSTANT_CAM_SPEED.contains(&rel) || [key::C_CC, key::OMEGA0].contains(&rel);
    if rel.starts_with("drive") || drive {
        0
    } else if rel.contains("mass") {
        3
    } else if rel.starts_with("follower_") || rod.contains(&rel) {
        1
    } else if rel.starts_with("hertz.")
        || rel == key::THICKNESS
        || rel == key::CONTACT_DAMPING_RATIO
    {
        2
    } else {
        4
    }
}

/// Every value of `design` but the program's, by its path relative to `[design]`
/// (`geometry.base_radius_in`), as TOML writes it.
fn design_values(design: &camsim_core::Design<f64>) -> Result<Vec<(String, toml::Value)>> {
    fn flat(prefix: &str, v: &toml::Value, out: &mut Vec<(String, toml::Value)>) {
        match v {
            toml::Value::Table(t) => {
                for (k, v) in t {
                    let p = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    if p != "program" {
                        flat(&p, v, out);
                    }
                }
            }
            other => out.push((prefix.to_string(), other.clone())),
        }
    }
    let mut out = Vec::new();
    flat("", &toml::Value::try_from(design)?, &mut out);
    Ok(out)
}

/// `path = value` in the output's unit family (`--units`): the key renamed and the number
/// converted, to 7 significant digits.
fn in_family(path: &str, v: &toml::Value, units: crate::units::Units) -> String {
    let (table, name) = path.rsplit_once('.').unwrap_or(("", path));
    let joined = |n: &str| {
        if table.is_empty() {
            n.to_string()
        } else {
            format!("{table}.{n}")
        }
    };
    let x = match v {
        toml::Value::Float(x) => *x,
        toml::Value::Integer(i) => *i as f64,
        other => return format!("{path} = {other}"),
    };
    let (name, factor) = crate::units::key_in(name, units);
    let y = x * factor;
    let y: f64 = format!("{y:.6e}").parse().unwrap_or(y);
    format!("{} = {y}", joined(&name))
}

/// The unit family scene `text`'s keys are written in: `Some(Si)` when every key with a
/// unit is an SI one (`base_radius_mm`), `Some(Inch)` when every one is in the inch
/// family, `None` when it has none or mixes them.
pub fn file_family(text: &str) -> Result<Option<crate::units::Units>> {
    use crate::units::{key_in, Units};
    let origins = camsim_scene_file::origins(text)?;
    let (mut si, mut inch) = (false, false);
    for (inch_path, user, _) in &origins.from_file {
        let name = user.rsplit('.').next().unwrap_or(user);
        if *inch_path != *user {
            si = true;
        } else if key_in(name, Units::Si).0 != name {
            inch = true;
        }
    }
    Ok(match (si, inch) {
        (true, false) => Some(Units::Si),
        (false, true) => Some(Units::Inch),
        _ => None,
    })
}

/// `scene --check`'s listing, as TOML comments: the values taken from the file (as
/// written), the values derived (and from which of the user's keys), and the values
/// inherited from the reference design, grouped.
pub fn listing(text: &str, spec: &RunSpec, units: crate::units::Units) -> Result<String> {
    use std::fmt::Write;
    let origins = camsim_scene_file::origins(text)?;
    let values = design_values(&spec.design)?;
    let mut out = String::from("# where every value comes from (camsim scene --check):\n");
    let _ = writeln!(out, "# taken from the file:");
    if origins.from_file.is_empty() {
        let _ = writeln!(out, "#   nothing: the file is the reference design");
    }
    for (_, user, raw) in &origins.from_file {
        let _ = writeln!(out, "#   {user} = {raw}");
    }
    let _ = writeln!(out, "# derived:");
    if origins.derived.is_empty() {
        let _ = writeln!(out, "#   nothing");
    }
    for (path, from, rule) in &origins.derived {
        let rel = path.strip_prefix("design.").unwrap_or(path);
        let value = values
            .iter()
            .find(|(p, _)| p == rel)
            .map_or(path.clone(), |(p, v)| {
                format!("design.{}", in_family(p, v, units))
            });
        let _ = writeln!(out, "#   {value} (from {from}: {rule})");
    }
    let _ = writeln!(
        out,
        "# inherited from the reference design (not in the file):"
    );
    let set = |rel: &str| {
        let path = format!("design.{rel}");
        origins.from_file.iter().any(|(p, _, _)| *p == path)
            || origins.derived.iter().any(|(p, _, _)| *p == path)
    };
    let unused = |p: &str| {
        spec.design.drive == camsim_core::DriveLaw::ConstantCamSpeed
            && NOT_USED_AT_CONSTANT_CAM_SPEED.contains(&p)
    };
    for (g, name) in GROUPS.iter().enumerate() {
        let group: Vec<_> = values
            .iter()
            .filter(|(p, _)| group_of(p) == g && !set(p) && !unused(p))
            .collect();
        if !group.is_empty() {
            let _ = writeln!(out, "#   {name}:");
        }
        for (p, v) in group {
            let _ = writeln!(out, "#     {}", in_family(p, v, units));
        }
    }
    let idle: Vec<_> = values.iter().filter(|(p, _)| unused(p)).collect();
    if !idle.is_empty() {
        let _ = writeln!(
            out,
            "# not used (constant-speed drive: the cam turns at exactly the nominal speed, so the motor, shafts and coupling do not enter the run):"
        );
    }
    for (p, v) in idle {
        let _ = writeln!(out, "#     {}", in_family(p, v, units));
    }
    Ok(out)
}

/// The drive's values a constant-cam-speed run does not use (docs/MODEL.md §5.17: the
/// model drops the motor, coupling and cam rotations). The cam's drag C_cc stays: the
/// ideal drive supplies it, so it is in the drive torque and power the run reports.
const NOT_USED_AT_CONSTANT_CAM_SPEED: [&str; 9] = [
    key::I_M,
    key::I_CP,
    key::I_C,
    key::C_MB,
    key::C_S1,
    key::C_S2,
    key::K_S1,
    key::K_S2,
    key::COUPLING_BACKLASH,
];
