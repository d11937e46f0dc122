//! The units of the printed results: the thesis's inch family (the default) or SI,
//! `--units inch|si` on every command.
//!
//! The family is decided once, as the command line is parsed ([`decide`], called by
//! `cli::parse_from` before any command runs): `--units` when the command line gives it;
//! otherwise the family of the scene file the command reads, SI when every key with a
//! unit in it is an SI one (`base_radius_mm`, `spring_rate_n_per_mm`), inch for an inch
//! scene, for one that mixes the two families or has no key with a unit, and without a
//! scene. Under SI, whichever decided it, a bare number on an option whose bare number is
//! inch (`--cutter-radius 10`) is refused (`cli::bare_inch_number`).
//!
//! The family is an explicit value: `cli::execute` passes the [`Units`] it decided to
//! every command's `run(args, units)`, and from there to the report's text
//! (`Report::text(&self, units)`), to `report::print` (the JSON) and to the figures
//! (`figure::draw(.., units)`). Its methods format: [`Units::q`] and [`Units::show`]
//! print a value with the inch format's resolution, [`Units::symbol`] and
//! [`Units::label`] name the unit, [`Units::axis`] scales a plot axis.
//!
//! A report's dimensional field is a [`Measure`] ([`Length`], [`Force`], [`Stress`],
//! ...): its value in the inch family, its unit in its type. Its JSON is a marker that
//! [`convert`] (the one conversion, [`json`], used by `report::print`) turns into the
//! number in the output's family, the key named by the type's unit (`base_radius_in` or
//! `base_radius_mm`). A field still a plain number is converted by its key's NAME (the
//! legacy path): a key that ends in an inch-family unit (`_lb_per_in`, `_psi`, `_in`,
//! ...) keeps it in inch output and gets the SI suffix (`_n_per_mm`, `_mpa`, `_mm`) and
//! the converted value in SI; a key the reports share without a unit (the per-period
//! columns `rms_velocity`, `contact_force_min`, `torque_max`, ...) gets its unit
//! appended, and in SI its value converted. The value under such a key may be a number,
//! or an object or array of numbers in that unit (a column's mean, spread and
//! percentiles): every number in it is converted. [`by_name`] lists the keys a report
//! still converts by name; tests/tests/json_units.rs holds that list to a checked-in one
//! that may only shrink. Dimensionless keys (`aord_*`, ratios, probabilities, counts),
//! angles (`_deg`), speeds of the cam (`_rpm`), frequencies (`_hz`) and times (`_s`,
//! `_ms`) are the same in both families and pass unchanged.
//!
//! There is no process-wide family: a function that formats takes the [`Units`] value.
//!
//! The factors are the scene files' exact ones ([`camsim_scene_file::units`]: 1 in =
//! 25.4 mm, 1 lbf = 4.4482216152605 N), so a scene written in SI and the same scene in
//! inch give the same results in either output.

pub mod measure;

pub use measure::{
    Acceleration, Bits, Force, Inertia, Jerk, Kind, Length, LengthPerRad, LengthPerRad2, Mass,
    Measure, MeasureIn, Power, Speed, Stiffness, Stress, Torque, TorsionalStiffness, Weight,
};

use camsim_scene_file::units::{self as su, Unit, MM_PER_IN, N_PER_LBF};

/// The unit family of the output.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Units {
    /// The thesis's: in, lb, psi, lb in (the default; `in` also reads).
    #[default]
    #[value(alias = "in")]
    Inch,
    /// SI with millimetres: mm, N, MPa, N m, N/mm, kg (`mm` also reads).
    #[value(alias = "mm")]
    Si,
}

/// Forces: lb, N.
pub const FORCE: Unit = Unit {
    inch: "lb",
    si: "n",
    si_per_inch: N_PER_LBF,
    inch_symbol: "lb",
    si_symbol: "N",
};
/// Weights given as masses (a spring's): lb, kg (the pound's mass, exact).
pub const WEIGHT: Unit = Unit {
    inch: "lb",
    si: "kg",
    si_per_inch: 0.453_592_37,
    inch_symbol: "lb",
    si_symbol: "kg",
};
/// Accelerations: in/s², mm/s².
pub const ACCELERATION: Unit = Unit {
    inch: "in_per_s2",
    si: "mm_per_s2",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in/s^2",
    si_symbol: "mm/s^2",
};
/// A profile's second derivative in cam angle: in/rad², mm/rad².
pub const LENGTH_PER_RAD2: Unit = Unit {
    inch: "in_per_rad2",
    si: "mm_per_rad2",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in/rad^2",
    si_symbol: "mm/rad^2",
};
/// Power: hp, kW (the mechanical horsepower, 550 ft lbf/s).
pub const POWER: Unit = Unit {
    inch: "hp",
    si: "kw",
    si_per_inch: 0.745_699_871_582_270_2,
    inch_symbol: "hp",
    si_symbol: "kW",
};

/// Every unit a key may end in (the scene files' and the results'); a key takes the
/// longest inch-family suffix it ends in (`_lb_s_per_in` is a damping, not a length).
const SUFFIXES: [Unit; 18] = [
    su::LENGTH,
    su::AREA,
    su::SECOND_MOMENT,
    su::STIFFNESS,
    su::DAMPING,
    su::MASS,
    su::DENSITY,
    su::STRESS,
    su::INERTIA,
    su::TORSIONAL_DAMPING,
    su::TORSIONAL_STIFFNESS,
    su::TORQUE,
    su::GAIN,
    su::SPEED,
    FORCE,
    ACCELERATION,
    LENGTH_PER_RAD2,
    POWER,
];

/// Keys the reports share without a unit, with the unit of their values.
const BARE: [(&str, Unit); 23] = [
    ("rms_displacement", su::LENGTH),
    ("rms_velocity", su::SPEED),
    ("rms_acceleration", ACCELERATION),
    ("acc_rms_sum", ACCELERATION),
    ("acc_rms_cycle1", ACCELERATION),
    ("acc_rms_cycle2", ACCELERATION),
    ("torque_avg", su::TORQUE),
    ("torque_max", su::TORQUE),
    ("torque_min", su::TORQUE),
    ("torque_avg_rise", su::TORQUE),
    ("torque_avg_return", su::TORQUE),
    ("contact_force_min", FORCE),
    ("contact_force_max", FORCE),
    ("contact_force_avg", FORCE),
    ("contact_stress_max", su::STRESS),
    ("acc_rms", ACCELERATION),
    ("acc_rms_err", ACCELERATION),
    ("agree_acc_rms", ACCELERATION),
    ("err_acc_rms", ACCELERATION),
    ("signal_acc_rms", ACCELERATION),
    ("agree_disp_rms", su::LENGTH),
    ("err_disp_rms", su::LENGTH),
    ("signal_disp_rms", su::LENGTH),
];

pub use su::{
    Unit as UnitKind, INERTIA, LENGTH, MASS, SPEED, STIFFNESS, STRESS, TORQUE, TORSIONAL_STIFFNESS,
};

/// A printed quantity in the output's family ([`Units::q`]): an inch-family value and
/// the number of decimals it prints with in inch; the text reports print every
/// dimensional number through this (the tables' and CSV's labels through
/// [`Units::symbol`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantity {
    /// The value in the output's family.
    pub value: f64,
    /// Decimals that keep the inch format's resolution (see [`Units::decimals`]).
    pub decimals: usize,
}

impl std::fmt::Display for Quantity {
    /// The value with its decimals; a width given (`{:>8}`) pads it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = format!("{:.*}", self.decimals, self.value);
        // A value that rounds to zero prints as 0, not -0 (a dwell's torque is zero to
        // rounding, with either sign).
        let s = match s.strip_prefix('-') {
            Some(t) if t.bytes().all(|b| b == b'0' || b == b'.') => t.to_string(),
            _ => s,
        };
        // `{:+}` signs a positive value (and a zero) as `+`, as f64's does.
        let s = if f.sign_plus() && !s.starts_with('-') && !s.starts_with('N') {
            format!("+{s}")
        } else {
            s
        };
        f.pad(&s)
    }
}

impl Units {
    /// `inch_value` (in `unit`'s inch member) printed with `inch_decimals` in inch: in
    /// this family, with [`Units::decimals`].
    pub fn q(self, unit: Unit, inch_value: f64, inch_decimals: usize) -> Quantity {
        Quantity {
            value: self.value(unit, inch_value),
            decimals: self.decimals(unit, inch_decimals),
        }
    }

    /// A value the user gave (a tolerance, a step), in this family and rounded to 12
    /// significant digits, for `{}` or `{:e}`: 0.0005 in prints as `0.0127` mm, not
    /// `0.012700000000000001`.
    pub fn given(self, unit: Unit, inch_value: f64) -> f64 {
        let v = self.value(unit, inch_value);
        format!("{v:.11e}").parse().unwrap_or(v)
    }

    /// `inch_value` (in `unit`'s inch member) in this family.
    pub fn value(self, unit: Unit, inch_value: f64) -> f64 {
        match self {
            Units::Inch => inch_value,
            Units::Si => inch_value * unit.si_per_inch,
        }
    }

    /// A table's unit label: the inch table's own text in inch (`in/s2`, kept byte for
    /// byte), `unit`'s symbol in SI (`mm/s^2`).
    pub fn label(self, unit: Unit, inch: &'static str) -> &'static str {
        match self {
            Units::Inch => inch,
            Units::Si => unit.si_symbol,
        }
    }

    /// `unit`'s key suffix in this family (`psi` or `mpa`).
    pub fn key_suffix(self, unit: Unit) -> &'static str {
        match self {
            Units::Inch => unit.inch,
            Units::Si => unit.si,
        }
    }

    /// `unit`'s symbol in this family (`lb/in` or `N/mm`).
    pub fn symbol(self, unit: Unit) -> &'static str {
        match self {
            Units::Inch => unit.inch_symbol,
            Units::Si => unit.si_symbol,
        }
    }

    /// The decimals a number printed with `inch_decimals` in inch takes in this family:
    /// the same resolution to within a factor of 3, `inch_decimals - round(log10
    /// factor)` (a length: 4 decimals of an inch, 0.0001 in = 0.00254 mm, are 3 of a mm;
    /// a force: 2 of a pound, 1 of a newton; a stress: 0 of a psi, 2 of a MPa).
    pub fn decimals(self, unit: Unit, inch_decimals: usize) -> usize {
        match self {
            Units::Inch => inch_decimals,
            Units::Si => {
                let shift = unit.si_per_inch.log10().round() as i64;
                (inch_decimals as i64 - shift).max(0) as usize
            }
        }
    }

    /// A plot axis's scale for quantity `u` ([`axis_in`]).
    pub fn axis(self, u: Unit) -> (f64, String) {
        axis_in(u, self)
    }
}

/// What decided the output's unit family ([`decide`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum UnitsFrom {
    /// `--units` on the command line.
    Option,
    /// The scene file (its path as given), written in SI keys, without `--units`.
    Scene(std::path::PathBuf),
    /// Neither: the inch family (no scene file, or one not all in SI keys).
    #[default]
    Default,
}

/// The output's unit family for a command line that gives `option` (`--units`) and
/// reads the scene file `scene`: `option` if given, else SI for a scene written in SI
/// keys ([`crate::scene::file_family`]), else inch. A scene that cannot be read or
/// parsed decides nothing here (inch): the command's own reading reports it. Only a
/// regular file is read here: a pipe (`run <(...)`) is read once, by the command.
pub fn decide(option: Option<Units>, scene: Option<&std::path::Path>) -> (Units, UnitsFrom) {
    if let Some(u) = option {
        return (u, UnitsFrom::Option);
    }
    let regular = |p: &std::path::Path| std::fs::metadata(p).is_ok_and(|m| m.is_file());
    let si = scene.filter(|p| regular(p)).is_some_and(|p| {
        camsim_scene_file::read_text(p, camsim_scene_file::MAX_SCENE_BYTES, "the scene file")
            .ok()
            .and_then(|text| crate::scene::file_family(&text).ok().flatten())
            == Some(Units::Si)
    });
    match (si, scene) {
        (true, Some(p)) => (Units::Si, UnitsFrom::Scene(p.to_path_buf())),
        _ => (Units::Inch, UnitsFrom::Default),
    }
}

/// The unit of a key and its stem: `Some((unit, stem, bare))` where `stem` is the key
/// without its inch suffix and `bare` says the key had none.
fn unit_of(key: &str) -> Option<(Unit, &str, bool)> {
    if let Some((_, u)) = BARE.iter().find(|(k, _)| *k == key) {
        return Some((*u, key, true));
    }
    let (u, stem) = SUFFIXES
        .iter()
        .filter_map(|u| {
            key.strip_suffix(u.inch)
                .and_then(|s| s.strip_suffix('_'))
                .map(|stem| (*u, stem))
        })
        .max_by_key(|(u, _)| u.inch.len())?;
    // A weight named as a mass (`mass_lb`, `spring_mass_lb`) is not a force.
    if u == FORCE && stem.ends_with("mass") {
        return Some((WEIGHT, stem, false));
    }
    Some((u, stem, false))
}

/// The key and its scale in `units`: `(new key, factor on the values)`.
pub fn key_in(key: &str, units: Units) -> (String, f64) {
    match unit_of(key) {
        None => (key.to_string(), 1.0),
        Some((u, stem, _)) => match units {
            Units::Inch => (format!("{stem}_{}", u.inch), 1.0),
            Units::Si => (format!("{stem}_{}", u.si), u.si_per_inch),
        },
    }
}

fn scale(v: &mut serde_json::Value, factor: f64) {
    use serde_json::Value;
    match v {
        Value::Number(n) => {
            // An integer (a count) is not scaled, nor is its key renamed (`is_count`).
            if let Some(x) = n.as_f64() {
                if factor != 1.0 {
                    if let Some(m) = serde_json::Number::from_f64(x * factor) {
                        *n = m;
                    }
                }
            }
        }
        Value::Array(a) => a.iter_mut().for_each(|x| scale(x, factor)),
        Value::Object(o) => o.iter_mut().for_each(|(_, x)| scale(x, factor)),
        _ => {}
    }
}

/// Whether `v` is an integer: a count or a rank (`ranks.torque_avg`, a law's place in
/// that column), never a dimensional value (the reports' dimensional numbers are `f64`,
/// which serialize with a decimal point or an exponent): its key and value pass unchanged.
fn is_count(v: &serde_json::Value) -> bool {
    v.as_number().is_some_and(|n| n.is_u64() || n.is_i64())
}

/// `value` with every key in `units` (see the module's account): a [`Measure`]'s marker
/// object becomes its number in `units` and its key takes the unit's suffix
/// ([`measure::key`]); a plain number is converted by its key's name ([`key_in`]).
pub fn convert(value: serde_json::Value, units: Units) -> serde_json::Value {
    use serde_json::Value;
    match value {
        Value::Object(o) => Value::Object(
            o.into_iter()
                .map(|(k, v)| {
                    if let Some(unit) = measure::measured(&v) {
                        return (measure::key(&k, unit, units), measure::unmark(v, units));
                    }
                    if is_count(&v) {
                        return (k, v);
                    }
                    let (key, factor) = key_in(&k, units);
                    let mut v = convert(v, units);
                    if key != k {
                        scale(&mut v, factor);
                    }
                    (key, v)
                })
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.into_iter().map(|v| convert(v, units)).collect()),
        v => v,
    }
}

/// The keys of `value` (a report's JSON as it serializes, before [`convert`]) that
/// [`convert`] names and scales by their NAME, not by a [`Measure`]'s type: a plain value
/// under a key with an inch-family suffix (`min_contact_force_lb`) or under one of the
/// shared bare keys (`rms_velocity`), at any depth; each once, sorted. A field named
/// without its unit's suffix would stay in inch here unnoticed; a [`Measure`] field
/// cannot. tests/tests/json_units.rs keeps this list from growing.
pub fn by_name(value: &serde_json::Value) -> Vec<String> {
    fn walk(v: &serde_json::Value, keys: &mut std::collections::BTreeSet<String>) {
        match v {
            serde_json::Value::Object(o) => {
                for (k, x) in o {
                    if measure::measured(x).is_some() || is_count(x) {
                        continue;
                    }
                    if unit_of(k).is_some() {
                        keys.insert(k.clone());
                    }
                    walk(x, keys);
                }
            }
            serde_json::Value::Array(a) => a.iter().for_each(|x| walk(x, keys)),
            _ => {}
        }
    }
    let mut keys = std::collections::BTreeSet::new();
    walk(value, &mut keys);
    keys.into_iter().collect()
}

/// A report's JSON text (`text`, pretty or compact) rewritten with every key in `units`:
/// the same layout, the keys of every object in sorted order.
pub fn json(text: &str, units: Units) -> serde_json::Result<String> {
    let value = convert(serde_json::from_str(text)?, units);
    if text.trim_end().contains('\n') {
        serde_json::to_string_pretty(&value)
    } else {
        serde_json::to_string(&value)
    }
}

/// Jerks (the SVAJ plot's): in/s³, mm/s³.
pub const JERK: Unit = Unit {
    inch: "in_per_s3",
    si: "mm_per_s3",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in/s^3",
    si_symbol: "mm/s^3",
};
/// A profile's slope in cam angle: in/rad, mm/rad.
pub const LENGTH_PER_RAD: Unit = Unit {
    inch: "in_per_rad",
    si: "mm_per_rad",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in/rad",
    si_symbol: "mm/rad",
};

/// A plot axis's scale for quantity `u` in `units`: the factor on the inch-family
/// values the reports hold, and the unit as an axis title writes it (`in/s²`, `lb·in`,
/// `N·m`, `MPa`).
pub fn axis_in(u: Unit, units: Units) -> (f64, String) {
    let (factor, symbol) = match units {
        Units::Inch => (1.0, u.inch_symbol),
        Units::Si => (u.si_per_inch, u.si_symbol),
    };
    let pretty = symbol
        .replace("^2", "²")
        .replace("^3", "³")
        .replace("^4", "⁴")
        .replace(' ', "·");
    (factor, pretty)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_carry_their_unit_in_either_family() {
        assert_eq!(
            key_in("rms_velocity", Units::Inch).0,
            "rms_velocity_in_per_s"
        );
        assert_eq!(key_in("rms_velocity", Units::Si).0, "rms_velocity_mm_per_s");
        assert_eq!(
            key_in("spring_rate_lb_per_in", Units::Si).0,
            "spring_rate_n_per_mm"
        );
        assert_eq!(
            key_in("peak_cam_torque_lb_in", Units::Si).0,
            "peak_cam_torque_n_m"
        );
        assert_eq!(key_in("mass_lb", Units::Si).0, "mass_kg");
        assert_eq!(
            key_in("min_contact_force_lb", Units::Si).0,
            "min_contact_force_n"
        );
        assert_eq!(
            key_in("max_pressure_angle_deg", Units::Si).0,
            "max_pressure_angle_deg"
        );
        assert_eq!(key_in("aord_cam", Units::Si), ("aord_cam".to_string(), 1.0));
        // The longest suffix: a damping, a mass and a torque, not lengths or forces.
        assert_eq!(key_in("c_hs_lb_s_per_in", Units::Si).0, "c_hs_n_s_per_m");
        assert_eq!(key_in("cam_mass_lb_s2_per_in", Units::Si).0, "cam_mass_kg");
        assert_eq!(key_in("t_max_lb_in", Units::Si).0, "t_max_n_m");
        // The inch family's key is unchanged where it already has its unit.
        assert_eq!(
            key_in("undercut_margin_in", Units::Inch),
            ("undercut_margin_in".into(), 1.0)
        );
    }

    #[test]
    fn the_factors_are_the_exact_definitions() {
        // 1 lbf = 0.45359237 kg x 9.80665 m/s^2; 1 in = 25.4 mm.
        assert_eq!(FORCE.si_per_inch, 0.453_592_37 * 9.806_65);
        // 1 psi = 1 lbf / in^2 = 6.894757... kPa.
        let psi_in_mpa = key_in("x_psi", Units::Si).1;
        assert!((psi_in_mpa - 0.006_894_757_293_168_361).abs() < 1e-15);
        // 1 hp = 550 ft lbf/s = 550 x 12 x 0.0254 m x 4.4482216152605 N / s.
        let hp_w = 550.0 * 12.0 * 0.0254 * N_PER_LBF;
        assert!((POWER.si_per_inch * 1000.0 - hp_w).abs() < 1e-9);
    }

    #[test]
    fn a_column_object_is_converted_whole_and_its_key_renamed() {
        let v = serde_json::json!({
            "contact_force_min": {"mean": 10.0, "p5": 1.0},
            "count": 3,
            "nested": [{"rms_displacement": 2.0}]
        });
        let si = convert(v.clone(), Units::Si);
        assert_eq!(
            si["contact_force_min_n"]["mean"],
            serde_json::json!(10.0 * N_PER_LBF)
        );
        assert_eq!(si["count"], serde_json::json!(3));
        // A rank under a column's name is a count: neither renamed nor scaled.
        let ranks = convert(serde_json::json!({"torque_avg": 3}), Units::Si);
        assert_eq!(ranks, serde_json::json!({"torque_avg": 3}));
        assert_eq!(
            si["nested"][0]["rms_displacement_mm"],
            serde_json::json!(50.8)
        );
        let inch = convert(v, Units::Inch);
        assert_eq!(inch["contact_force_min_lb"]["p5"], serde_json::json!(1.0));
        assert_eq!(
            inch["nested"][0]["rms_displacement_in"],
            serde_json::json!(2.0)
        );
    }

    #[test]
    fn key_in_names_and_scales_every_scene_key_as_the_reader_does() {
        // `camsim scene --units si` writes each key by key_in; the scene reader converts
        // by camsim_scene_file's table: the two agree on every dimensional key.
        for k in camsim_scene_file::units::UNIT_KEYS {
            let (name, factor) = key_in(k.inch(), Units::Si);
            assert_eq!(name, k.si(), "{}", k.inch());
            assert_eq!(factor, k.unit.si_per_inch, "{}", k.inch());
            // An SI key is its own SI name: nothing converts twice.
            assert_eq!(key_in(&name, Units::Si), (name.clone(), 1.0));
        }
    }

    #[test]
    fn by_name_lists_the_keys_named_by_their_suffix_or_bare_not_the_measures() {
        let v = serde_json::json!({
            "base_radius_in": 1.5,
            "rms_velocity": {"mean": 1.0},
            "force": serde_json::to_value(Force::inch(1.0)).unwrap_or_default(),
            "rows": [{"lift_in": 0.5, "count": 2}],
            "max_pressure_angle_deg": 30.0
        });
        assert_eq!(
            by_name(&v),
            ["base_radius_in", "lift_in", "rms_velocity"].map(String::from)
        );
    }

    #[test]
    fn a_signed_quantity_prints_plus_and_never_minus_zero() {
        let q = |value: f64, decimals: usize| Quantity { value, decimals };
        assert_eq!(format!("{:+}", q(-0.0001, 3)), "+0.000");
        assert_eq!(format!("{:+}", q(0.0, 2)), "+0.00");
        assert_eq!(format!("{:>+8}", q(-0.374, 3)), "  -0.374");
        assert_eq!(format!("{:>+8}", q(1.66, 2)), "   +1.66");
        assert_eq!(format!("{}", q(-0.0001, 3)), "0.000");
        assert_eq!(format!("{:+}", q(f64::NAN, 2)), "NaN");
    }

    #[test]
    fn plot_axes_scale_by_the_definitions_and_name_the_si_unit() {
        assert_eq!(axis_in(FORCE, Units::Inch), (1.0, "lb".to_string()));
        // 1 lbf = 0.45359237 kg x 9.80665 m/s^2.
        assert_eq!(
            axis_in(FORCE, Units::Si),
            (0.453_592_37 * 9.806_65, "N".to_string())
        );
        assert_eq!(axis_in(su::LENGTH, Units::Si), (25.4, "mm".to_string()));
        assert_eq!(axis_in(ACCELERATION, Units::Si).1, "mm/s²");
        assert_eq!(axis_in(ACCELERATION, Units::Inch).1, "in/s²");
        assert_eq!(axis_in(su::TORQUE, Units::Inch).1, "lb·in");
        assert_eq!(axis_in(su::TORQUE, Units::Si).1, "N·m");
        // 1 lb in = 4.4482216152605 N x 0.0254 m.
        assert!((axis_in(su::TORQUE, Units::Si).0 - 0.0254 * N_PER_LBF).abs() < 1e-15);
        let (psi, mpa) = axis_in(su::STRESS, Units::Si);
        assert_eq!(mpa, "MPa");
        assert!((psi - N_PER_LBF / (25.4 * 25.4)).abs() < 1e-15);
        assert_eq!(axis_in(JERK, Units::Si).1, "mm/s³");
    }
}
