//! The arguments layer: the argument groups commands flatten (the scene and its
//! overrides [`SceneArgs`], the output [`OutputArgs`], the actual cam [`ActualArgs`], a
//! Monte Carlo study [`StudyArgs`]), and the values of the command line that clap checks:
//! the motion laws and the initial state as [`ValueEnum`]s, and the numeric rules as value
//! parsers. A refused value is a clap
//! error, one line naming the option, the value and the rule
//! (`invalid value '-5' for '--rpm <RPM>': must lie in [1, 10000] rpm (...)`). An option
//! that sets a scene key is checked against that key's plausibility range (core's
//! [`camsim_core::key::RANGES`]); the numeric options take values with a leading hyphen
//! (`allow_hyphen_values`), so `-1` and `-inf` are refused by the rule, not taken for flags.

use camsim_core::{MotionLaw, Start};
use clap::builder::PossibleValue;
use clap::ValueEnum;

mod actual;
mod csv;
mod output;
mod scene;
mod study;
mod verdict;

pub use actual::{value_name, ActualArgs};
pub use csv::CsvArgs;
pub use output::OutputArgs;
pub use scene::{spec_from, SceneArgs};
pub use study::StudyArgs;
pub use verdict::VerdictArgs;

/// A usage error found after clap parsed the command line (an option that needs another,
/// a flag a command does not take): the binary prints it on one line and exits 2, as it
/// does for clap's own errors ([`crate::cli::main_from`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// A [`UsageError`] as an error to return (`return Err(usage("--x needs --y"))`).
pub fn usage(msg: impl Into<String>) -> anyhow::Error {
    anyhow::Error::new(UsageError(msg.into()))
}

/// Whether `e` (or an error it wraps) is a [`UsageError`].
pub fn is_usage(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.is::<UsageError>())
}

/// A motion law on the command line (`--rise`, `--return`), by its
/// [`MotionLaw::name`] (the names `camsim laws` prints; ASCII case ignored where the
/// option says `ignore_case`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Law(pub MotionLaw);

/// [`MotionLaw::ALL`] as command-line values, in the same order.
static LAWS: [Law; MotionLaw::ALL.len()] = {
    let mut laws = [Law(MotionLaw::StraightLine); MotionLaw::ALL.len()];
    let mut i = 0;
    while i < laws.len() {
        laws[i] = Law(MotionLaw::ALL[i]);
        i += 1;
    }
    laws
};

impl ValueEnum for Law {
    fn value_variants<'a>() -> &'a [Self] {
        &LAWS
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()))
    }
}

impl From<Law> for MotionLaw {
    fn from(l: Law) -> Self {
        l.0
    }
}

/// The initial state of a simulation (`--start`; the scene's `solver.start`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StartArg {
    /// The thesis's (VI.1): every speed at ω0, everything else zero.
    Thesis,
    /// Static equilibrium on the base circle under the preload and the steady drag.
    Static,
}

impl From<StartArg> for Start {
    fn from(s: StartArg) -> Self {
        match s {
            StartArg::Thesis => Start::Thesis,
            StartArg::Static => Start::Static,
        }
    }
}

/// `--step-control`: how England's method controls its step
/// ([`camsim_core::StepRule`]; the scene's `solver.step_control`, docs/MODEL.md §3.16).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum StepControlArg {
    /// The thesis's rule: England's controller, uncapped.
    Thesis,
    /// England's controller with the stiffness cap scaled by rtol (the default).
    ScaledCap,
    /// The PI controller with the same scaled cap.
    PiScaledCap,
}

impl From<StepControlArg> for camsim_core::StepRule {
    fn from(s: StepControlArg) -> Self {
        match s {
            StepControlArg::Thesis => Self::Thesis,
            StepControlArg::ScaledCap => Self::ScaledCap,
            StepControlArg::PiScaledCap => Self::PiScaledCap,
        }
    }
}

/// `--method`: how a run integrates the model ([`camsim_core::Method`]; the scene's
/// `solver.method`, docs/MODEL.md §3.16).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum MethodArg {
    /// Merson's pair at rtol >= 1e-6, where it needs fewer evaluations, England's method
    /// below (the default).
    Auto,
    /// England's double step, the thesis's method.
    England,
    /// Merson's 4(3) pair, built for the imaginary axis (capped at the stiffness limit
    /// unless --step-control thesis).
    Merson,
    /// Dormand and Prince's 5(4) pair, for a step held by accuracy.
    DormandPrince,
}

impl From<MethodArg> for camsim_core::Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Auto => Self::Auto,
            MethodArg::England => Self::England,
            MethodArg::Merson => Self::Merson,
            MethodArg::DormandPrince => Self::DormandPrince,
        }
    }
}

/// `--follower`: the follower's model ([`camsim_core::FollowerModel`], docs/MODEL.md §10).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum FollowerArg {
    /// Every mass of the chain.
    Full,
    /// The roller massless: the Hertz contact and K_rb in series.
    MasslessRoller,
    /// The roller and the cantilever portion y3 quasi-static.
    QuasiStaticCantilever,
    /// The roller, the cantilever and the follower rod quasi-static (the load carries the train).
    QuasiStaticRod,
    /// The whole chain up to the load quasi-static, the cam shaft too.
    QuasiStaticShaft,
}

impl From<FollowerArg> for camsim_core::FollowerModel {
    fn from(f: FollowerArg) -> Self {
        use camsim_core::FollowerModel as F;
        match f {
            FollowerArg::Full => F::Full,
            FollowerArg::MasslessRoller => F::MasslessRoller,
            FollowerArg::QuasiStaticCantilever => F::QuasiStaticCantilever,
            FollowerArg::QuasiStaticRod => F::QuasiStaticRod,
            FollowerArg::QuasiStaticShaft => F::QuasiStaticShaft,
        }
    }
}

/// The names of a [`ValueEnum`]'s values, for a parser that keeps the text
/// (`PossibleValuesParser::new(possible_values::<StartArg>())`).
pub fn possible_values<E: ValueEnum>() -> Vec<PossibleValue> {
    E::value_variants()
        .iter()
        .filter_map(ValueEnum::to_possible_value)
        .collect()
}

fn number(s: &str) -> Result<f64, String> {
    s.trim()
        .parse::<f64>()
        .map_err(|_| "not a number".to_string())
}

/// An option's number and the unit written after it, if any (`17.5N/mm`, `12.7 mm`,
/// `1e-3in`): the number is the longest prefix that reads as one, the unit the rest.
fn number_and_unit(s: &str) -> Result<(f64, Option<&str>), String> {
    let t = s.trim();
    let end = (1..=t.len())
        .rev()
        .filter(|&i| t.is_char_boundary(i))
        .find(|&i| t[..i].trim_end().parse::<f64>().is_ok());
    let Some(end) = end else {
        return Err("not a number".to_string());
    };
    let x = number(&t[..end])?;
    let unit = t[end..].trim();
    Ok((x, (!unit.is_empty()).then_some(unit)))
}

/// The unit written after an option's value (`Some("N/mm")` for `17.5N/mm`), `None` for a
/// bare number or something that is not a number.
pub fn unit_of(s: &str) -> Option<&str> {
    number_and_unit(s).ok().and_then(|(_, u)| u)
}

/// Whether `written` names `symbol` (case and spaces aside, `lbf` for `lb`).
fn names_unit(written: &str, symbol: &str) -> bool {
    let norm = |u: &str| {
        u.chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase()
            .replace("lbf", "lb")
    };
    norm(written) == norm(symbol)
}

/// An option's value in `unit`'s inch family (the unit camsim computes in): a bare
/// number is already in it; a number with the inch family's or SI's symbol after it
/// (`100lb/in`, `17.5N/mm`, `12.7 mm`) is converted; any other unit is refused, naming
/// the two it takes.
pub fn in_inch_family(s: &str, unit: camsim_scene_file::units::Unit) -> Result<f64, String> {
    let (x, written) = number_and_unit(s)?;
    match written {
        None => Ok(x),
        Some(u) if names_unit(u, unit.inch_symbol) => Ok(x),
        Some(u) if names_unit(u, unit.si_symbol) => Ok(x / unit.si_per_inch),
        Some(u) => Err(format!(
            "unit {u:?} is not one this option takes: {} or {} (a bare number is {})",
            unit.inch_symbol, unit.si_symbol, unit.inch_symbol
        )),
    }
}

/// A positive, finite number (speeds, stiffnesses, tolerances, forces).
pub fn positive_finite(s: &str) -> Result<f64, String> {
    match number(s)? {
        x if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err("must be positive and finite".into()),
    }
}

/// Zero or a positive finite number (lengths that may vanish).
pub fn non_negative_finite(s: &str) -> Result<f64, String> {
    match number(s)? {
        x if x.is_finite() && x >= 0.0 => Ok(x),
        _ => Err("must be zero or positive and finite".into()),
    }
}

/// A number strictly between 0 and 1 (relative tolerances).
pub fn unit_interval(s: &str) -> Result<f64, String> {
    match number(s)? {
        x if x > 0.0 && x < 1.0 => Ok(x),
        _ => Err("must be in (0, 1)".into()),
    }
}

/// A number within the plausibility range of scene key `key` (core's
/// [`camsim_core::key::RANGES`], the ranges [`camsim_core::Design::validate`] checks):
/// the option and its scene key are judged by one rule.
fn in_range(s: &str, key: &str) -> Result<f64, String> {
    in_range_of(number(s)?, key)
}

/// [`in_range`] of a value already read.
fn in_range_of(x: f64, key: &str) -> Result<f64, String> {
    let Some(r) = camsim_core::key::range(key) else {
        return Err(format!("no range for {key}"));
    };
    if r.contains(x) {
        Ok(x)
    } else {
        Err(r.rule.to_string())
    }
}

/// A cam speed, rpm: [`camsim_core::key::SPEED_RPM`] (1-10 000 rpm).
pub fn rpm(s: &str) -> Result<f64, String> {
    in_range(s, camsim_core::key::RPM)
}

/// A pressure-angle limit, degrees: above 0 and below 90.
pub fn pressure_angle_limit(s: &str) -> Result<f64, String> {
    let v = number(s)?;
    if v > 0.0 && v < 90.0 {
        Ok(v)
    } else {
        Err("must be above 0 and below 90 (degrees)".into())
    }
}

/// A return-spring rate, lb/in (or with its unit, [`in_inch_family`]): the range of
/// `design.spring_rate_lb_per_in`.
pub fn spring_rate(s: &str) -> Result<f64, String> {
    in_range_of(
        in_inch_family(s, camsim_scene_file::units::STIFFNESS)?,
        camsim_core::key::K_RS,
    )
}

/// A spring compression at assembly, in (or with its unit): the range of
/// `design.spring_preload_length_in`.
pub fn preload_length(s: &str) -> Result<f64, String> {
    in_range_of(
        in_inch_family(s, camsim_scene_file::units::LENGTH)?,
        camsim_core::key::DELTA_RS,
    )
}

/// A positive, finite length, in (or with its unit).
pub fn positive_length(s: &str) -> Result<f64, String> {
    match in_inch_family(s, camsim_scene_file::units::LENGTH)? {
        x if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err("must be positive and finite".into()),
    }
}

/// A relative tolerance: the range of `solver.rtol`.
pub fn rtol(s: &str) -> Result<f64, String> {
    in_range(s, camsim_core::key::RTOL)
}

/// The largest double step, fraction of a revolution: the range of
/// `solver.max_step_fraction_rev`.
pub fn max_step_fraction(s: &str) -> Result<f64, String> {
    in_range(s, camsim_core::key::MAX_STEP_FRACTION)
}

/// An absolute displacement tolerance, in (or with its unit): the range of
/// `solver.atol_in`.
pub fn atol(s: &str) -> Result<f64, String> {
    in_range_of(
        in_inch_family(s, camsim_scene_file::units::LENGTH)?,
        camsim_core::key::ATOL,
    )
}

/// A contact force, lb: positive, from [`MIN_FORCE_LB`] to [`max_force_lb`] (the force
/// at which the Hertz band of the reference pair is as wide as the roller: beyond it
/// Hertz's theory, a narrow band on two cylinders, no longer describes the contact).
pub fn force(s: &str) -> Result<f64, String> {
    let x = in_inch_family(s, crate::units::FORCE)?;
    if !(x.is_finite() && x > 0.0) {
        return Err("must be positive and finite".into());
    }
    match x {
        x if x < MIN_FORCE_LB => Err(format!(
            "must be at least {MIN_FORCE_LB:e} lb (smaller forces underflow the contact band)"
        )),
        x if x <= max_force_lb() => Ok(x),
        _ => Err(force_range_rule()),
    }
}

/// The smallest contact force `--force` takes, lb: 1e-6 lb (a band of 6e-7 in, a
/// thousandth of the finest cam finish; below about 1e-300 lb the band's square root
/// underflows, and nothing between is a cam contact).
pub const MIN_FORCE_LB: f64 = 1e-6;

/// The largest contact force `--force` takes, lb: the force at which the contact width
/// of Eq. V.9 on the reference pair equals the roller's diameter (w grows as √F), about
/// 1.5e6 lb (the reference's contact force is about 50 lb).
pub fn max_force_lb() -> f64 {
    use crate::study::contact::{BASE_CIRCLE_DIAMETER_IN, CAM_THICKNESS_IN, ROLLER_DIAMETER_IN};
    let w1 = camsim_core::HertzContact::<f64>::steel(CAM_THICKNESS_IN).width(
        1.0,
        ROLLER_DIAMETER_IN,
        BASE_CIRCLE_DIAMETER_IN,
    );
    // Rounded down to 3 significant digits, so the printed bound is itself accepted.
    let exact = (ROLLER_DIAMETER_IN / w1).powi(2);
    let scale = 10f64.powi(exact.log10().floor() as i32 - 2);
    (exact / scale).floor() * scale
}

/// The rule of a force above [`max_force_lb`].
pub fn force_range_rule() -> String {
    format!(
        "must be at most {:.3e} lb (there the Hertz band is as wide as the roller: beyond Hertz's theory)",
        max_force_lb()
    )
}

/// The largest manufacturing tolerance (`--cam-tolerance`, `--roller-tolerance`,
/// `--eccentricity-tolerance`), ± in: 0.1 in, 40 times the thesis's loosest tolerance
/// (±0.0025 in) and the bound of a measured deviation (`deviation_in`). A larger error
/// is a different cam, not a machined one; and with the roller's at most 0.1 in on the
/// reference 0.375 in roller, a drawn radius stays positive (sum-of-12 deviates reach 2
/// tolerances at most; the exact normal would need 11 standard deviations).
pub const MAX_TOLERANCE_IN: f64 = 0.1;

/// A tolerance, ± in: zero or positive, at most [`MAX_TOLERANCE_IN`].
pub fn tolerance_in(s: &str) -> Result<f64, String> {
    let x = in_inch_family(s, camsim_scene_file::units::LENGTH)?;
    if !(x.is_finite() && x >= 0.0) {
        return Err("must be zero or positive and finite".into());
    }
    match x {
        x if x <= MAX_TOLERANCE_IN => Ok(x),
        _ => Err(format!(
            "must be at most {MAX_TOLERANCE_IN} in (40 times a loose machining tolerance: a larger error is a different cam)"
        )),
    }
}

/// The range `--allowable-stress` takes, psi: 1 000 psi (6.9 MPa) to 1 000 000 psi
/// (6 895 MPa). The contact endurance strength of cam materials lies inside it, from
/// about 8 000 psi for a cast nylon to about 300 000 psi for a carburised steel (Norton,
/// Cam Design and Manufacturing Handbook); a value outside is a slip of the unit (a
/// psi number read as MPa is 145 times too large) or of a digit.
pub const ALLOWABLE_STRESS_PSI: (f64, f64) = (1.0e3, 1.0e6);

/// An allowable contact stress, psi (or with its unit, MPa): within
/// [`ALLOWABLE_STRESS_PSI`].
pub fn allowable_stress(s: &str) -> Result<f64, String> {
    let x = in_inch_family(s, camsim_scene_file::units::STRESS)?;
    let (lo, hi) = ALLOWABLE_STRESS_PSI;
    if x.is_finite() && (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(format!(
            "must lie in [{lo}, {hi}] psi = [6.89, 6895] MPa (the contact endurance of cam materials; give the unit, 150000psi or 1034MPa)"
        ))
    }
}

/// A spring-rate resolution, lb/in (or with its unit, N/mm): positive and finite.
pub fn rate_resolution(s: &str) -> Result<f64, String> {
    match in_inch_family(s, camsim_scene_file::units::STIFFNESS)? {
        x if x.is_finite() && x > 0.0 => Ok(x),
        _ => Err("must be positive and finite".into()),
    }
}

/// A speed resolution, rpm: positive, at most the whole speed range (10 000 rpm); below
/// the numbers' spacing the bisection ends on neighbouring speeds.
pub fn resolution_rpm(s: &str) -> Result<f64, String> {
    match positive_finite(s)? {
        x if x <= camsim_core::key::SPEED_RPM.max => Ok(x),
        _ => Err("must be at most 10000 rpm (the whole speed range)".into()),
    }
}

/// A random seed: a whole number from 0 to 2^64 - 1 (`-1` is refused by this rule, not
/// taken for a flag).
pub fn seed(s: &str) -> Result<u64, String> {
    s.trim()
        .parse::<u64>()
        .map_err(|_| format!("must be a whole number from 0 to {}", u64::MAX))
}

/// A whole number from `LO` to `HI` (counts: samples, threads, points), read so that a
/// negative or fractional value is refused by the option's own range.
pub fn whole_u64<const LO: u64, const HI: u64>(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(n) if (LO..=HI).contains(&n) => Ok(n),
        _ => Err(format!("must be a whole number from {LO} to {HI}")),
    }
}

/// [`whole_u64`] for a `u32` count.
pub fn whole_u32<const LO: u32, const HI: u32>(s: &str) -> Result<u32, String> {
    match s.trim().parse::<u32>() {
        Ok(n) if (LO..=HI).contains(&n) => Ok(n),
        _ => Err(format!("must be a whole number from {LO} to {HI}")),
    }
}

/// A whole number of megabytes, at least 1 (size limits).
pub fn megabytes(s: &str) -> Result<u64, String> {
    match s.trim().parse::<u64>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err("must be a whole number of MB, at least 1".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A value with its unit reads in the inch family by the exact factors (1 in =
    /// 25.4 mm, 1 lbf = 4.4482216152605 N), a bare number as it is, and a unit of another
    /// quantity is refused naming the two the option takes.
    #[test]
    fn option_values_take_their_unit() {
        use camsim_scene_file::units::{LENGTH, STIFFNESS};
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        // 100 lb/in in N/mm, written out: 100 x 4.4482216152605 / 25.4.
        let n_per_mm = 100.0 * 4.448_221_615_260_5 / 25.4;
        assert!(rel(spring_rate(&format!("{n_per_mm}N/mm")).unwrap(), 100.0) < 1e-14);
        assert!(rel(spring_rate(&format!("{n_per_mm} n/mm")).unwrap(), 100.0) < 1e-14);
        assert_eq!(spring_rate("100lb/in"), Ok(100.0));
        assert_eq!(spring_rate("100 lbf/in"), Ok(100.0));
        assert_eq!(spring_rate("100"), Ok(100.0));
        assert_eq!(preload_length("12.7mm"), Ok(0.5));
        assert_eq!(tolerance_in("0.0127 mm"), Ok(0.0005));
        assert!(rel(atol("2.54e-7mm").unwrap(), 1e-8) < 1e-12);
        assert!(rel(force("4.4482216152605N").unwrap(), 1.0) < 1e-15);
        assert!(rel(positive_length("254mm").unwrap(), 10.0) < 1e-15);
        // The range is judged on the inch value: 1e7 N/mm is 5.7e7 lb/in, above 1e6.
        assert!(spring_rate("1e7N/mm").is_err());
        let e = spring_rate("12mm").unwrap_err();
        assert!(
            e.contains("\"mm\"") && e.contains("lb/in") && e.contains("N/mm"),
            "{e}"
        );
        assert!(tolerance_in("-0.01mm").is_err());
        assert_eq!(spring_rate("abc"), Err("not a number".to_string()));
        assert_eq!(in_inch_family("1e-3in", LENGTH), Ok(1e-3));
        assert_eq!(in_inch_family("7", STIFFNESS), Ok(7.0));
        assert_eq!(unit_of("17.5N/mm"), Some("N/mm"));
        assert_eq!(unit_of(" 1e5 "), None);
        assert_eq!(unit_of("x"), None);
    }

    #[test]
    fn every_law_is_a_value_by_its_name_in_order() {
        let names: Vec<String> = possible_values::<Law>()
            .iter()
            .map(|v| v.get_name().to_string())
            .collect();
        let expect: Vec<&str> = MotionLaw::ALL.iter().map(|l| l.name()).collect();
        assert_eq!(names, expect);
        for law in MotionLaw::ALL {
            assert_eq!(Law::from_str(law.name(), false), Ok(Law(law)));
            let upper = law.name().to_ascii_uppercase();
            assert_eq!(Law::from_str(&upper, true), Ok(Law(law)));
        }
        assert!(Law::from_str("modified trapezoidal", true).is_err());
    }

    #[test]
    fn start_names_are_the_scene_names() {
        for (s, name) in [(Start::Thesis, "thesis"), (Start::Static, "static")] {
            let arg = StartArg::from_str(name, false).unwrap();
            assert_eq!(Start::from(arg), s);
            // The scene file spells it the same way.
            let toml = toml::to_string(&std::collections::BTreeMap::from([("start", s)])).unwrap();
            assert_eq!(toml.trim(), format!("start = \"{name}\""));
        }
    }

    #[test]
    fn range_rules_are_the_scene_keys() {
        assert_eq!(rpm("800"), Ok(800.0));
        assert_eq!(rpm("10000"), Ok(10000.0));
        for bad in ["0", "-1", "0.5", "10001", "1e300", "nan", "inf"] {
            let e = rpm(bad).unwrap_err();
            assert!(e.contains("[1, 10000] rpm"), "{bad}: {e}");
        }
        assert_eq!(spring_rate("60"), Ok(60.0));
        assert!(spring_rate("1e300").is_err() && spring_rate("0").is_err());
        assert_eq!(preload_length("0"), Ok(0.0));
        assert!(preload_length("-0.1").is_err() && preload_length("1e3").is_err());
        assert_eq!(rtol("1e-6"), Ok(1e-6));
        assert!(rtol("1e-300").is_err() && rtol("0.5").is_err());
        assert_eq!(atol("1e-8"), Ok(1e-8));
        assert!(atol("1").is_err());
        assert_eq!(force("50"), Ok(50.0));
        assert!(force("1e300").is_err() && force("0").is_err());
    }

    #[test]
    fn numeric_rules() {
        assert_eq!(positive_finite(" 12.5"), Ok(12.5));
        for bad in ["0", "-1", "NaN", "inf", "-inf", "", "abc"] {
            assert!(positive_finite(bad).is_err(), "{bad}");
        }
        assert_eq!(non_negative_finite("0"), Ok(0.0));
        assert!(non_negative_finite("-0.1").is_err());
        assert!(non_negative_finite("inf").is_err());
        assert_eq!(unit_interval("1e-6"), Ok(1e-6));
        for bad in ["0", "1", "2", "NaN", "-1e-6"] {
            assert!(unit_interval(bad).is_err(), "{bad}");
        }
        assert_eq!(positive_finite("x").unwrap_err(), "not a number");
        assert_eq!(megabytes("1000"), Ok(1000));
        for bad in ["0", "-1", "1.5", "", "1e3"] {
            assert!(megabytes(bad).is_err(), "{bad}");
        }
    }
}
