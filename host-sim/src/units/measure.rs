//! A report's dimensional number with its quantity: a [`Measure`] holds the value in the
//! inch family and knows its unit by its type ([`Length`], [`Force`], [`Stress`], ...),
//! so the text ([`Units::show`]), the JSON ([`super::convert`]) and the plots
//! ([`Measure::inch`] with [`Units::axis`] of [`Kind::UNIT`]) convert it from the one
//! table of units, and a field cannot stay in the wrong unit unnoticed: its key gets its
//! unit from its type, not from its name.
//!
//! In JSON a measure serializes as a marker object, `{"$unit": "in", "value": 1.25}`,
//! which [`super::convert`] replaces by the number in the output's family, naming the
//! key with the family's suffix (`base_radius` or `base_radius_in` becomes
//! `base_radius_in` or `base_radius_mm`). A report is never printed with a marker in it.
//! Several numbers of one quantity under one key (a column's mean, spread and
//! percentiles) are one [`Measures`]: a marker whose value is their object, converted
//! whole, its key named by the unit, the object's own keys unchanged.
//! Two markers more: a [`MeasureIn`] holds a value in the family it was measured in (a
//! drawing's lengths), a [`Bits`] a computed value's raw bits, never converted, under the
//! key its value would have.
//!
//! ```
//! use camsim::units::{Length, Units};
//! let r = Length::inch(2.0);
//! assert_eq!(Units::Si.of(r), 50.8);
//! assert_eq!(format!("{}", Units::Si.show(r, 4)), "50.800");
//! ```

use std::marker::PhantomData;

use serde::ser::{Serialize, SerializeStruct, Serializer};

use super::{Quantity, Unit, Units};

/// The key of a measure's marker object in JSON; its value names the unit by both
/// families' suffixes, `lb|kg` (a weight) apart from `lb|n` (a force).
pub const MARKER: &str = "$unit";

/// The marker's name for `unit`: `inch|si`.
fn marker(unit: Unit) -> String {
    format!("{}|{}", unit.inch, unit.si)
}

/// Every unit a measure may have (the kinds below).
const UNITS: [Unit; 15] = [
    super::LENGTH,
    super::SPEED,
    super::ACCELERATION,
    super::JERK,
    super::FORCE,
    super::WEIGHT,
    super::MASS,
    super::STRESS,
    super::TORQUE,
    super::STIFFNESS,
    super::POWER,
    super::LENGTH_PER_RAD,
    super::LENGTH_PER_RAD2,
    super::INERTIA,
    super::TORSIONAL_STIFFNESS,
];

/// The key of a marker object's family, for a value held in the family it was measured
/// in ([`MeasureIn`]): `"inch"` or `"si"`.
const FAMILY: &str = "family";

/// The key of a marker object's raw bits ([`Bits`]).
const BITS: &str = "bits";

/// What a marker object holds.
enum Held<'a> {
    /// A value in the inch family ([`Measure`]); not finite: NaN.
    Inch(f64),
    /// A value in the family it was measured in ([`MeasureIn`]).
    In(Units, f64),
    /// A value's raw bits ([`Bits`]), never converted.
    Bits(&'a str),
    /// Several values in the inch family, an object of numbers ([`Measures`]).
    Group(&'a serde_json::Map<String, serde_json::Value>),
}

/// The unit and content of a marker object, if `v` is one.
fn marked(v: &serde_json::Value) -> Option<(Unit, Held<'_>)> {
    let o = v.as_object()?;
    let name = o.get(MARKER)?.as_str()?;
    let unit = UNITS.into_iter().find(|u| marker(*u) == name)?;
    // A value that is not finite serializes as null: it stays null, not a marker.
    let number = |value: &serde_json::Value| {
        if value.is_null() {
            Some(f64::NAN)
        } else {
            value.as_f64()
        }
    };
    let held = match (o.len(), o.get("value"), o.get(FAMILY), o.get(BITS)) {
        (2, Some(serde_json::Value::Object(group)), None, None) => Held::Group(group),
        (2, Some(value), None, None) => Held::Inch(number(value)?),
        (3, Some(value), Some(family), None) => {
            let family = match family.as_str()? {
                "inch" => Units::Inch,
                "si" => Units::Si,
                _ => return None,
            };
            Held::In(family, number(value)?)
        }
        (2, None, None, Some(bits)) => Held::Bits(bits.as_str()?),
        _ => return None,
    };
    Some((unit, held))
}

/// The unit of `v` if it is a measure, a [`Measures`], or a non-empty array of measures
/// of one unit; an array's flags and words beside its measures (the `[rate, passed]`
/// rows of a search) are not numbers and leave it measured.
pub fn measured(v: &serde_json::Value) -> Option<Unit> {
    match v {
        serde_json::Value::Array(a) => {
            let mut units = a
                .iter()
                .filter(|x| !(x.is_boolean() || x.is_string()))
                .map(measured);
            let first = units.next()??;
            units.all(|u| u == Some(first)).then_some(first)
        }
        v => marked(v).map(|(u, _)| u),
    }
}

/// A number of `unit` held in `family`, in `units`.
fn held_in(unit: Unit, family: Units, value: f64, units: Units) -> f64 {
    match (family, units) {
        (Units::Inch, u) => u.value(unit, value),
        (Units::Si, Units::Si) => value,
        (Units::Si, Units::Inch) => value / unit.si_per_inch,
    }
}

/// `v` (a measure, a [`Measures`] or an array of measures, [`measured`]) with every
/// marker replaced by its number (or its object of numbers) in `units` (a [`Bits`]
/// marker by its bits).
pub fn unmark(v: serde_json::Value, units: Units) -> serde_json::Value {
    let number = |x: f64| {
        serde_json::Number::from_f64(x).map_or(serde_json::Value::Null, serde_json::Value::Number)
    };
    match v {
        serde_json::Value::Array(a) => {
            serde_json::Value::Array(a.into_iter().map(|x| unmark(x, units)).collect())
        }
        v => match marked(&v) {
            Some((unit, Held::Inch(inch))) => number(units.value(unit, inch)),
            Some((unit, Held::In(family, x))) => number(held_in(unit, family, x, units)),
            Some((_, Held::Bits(bits))) => serde_json::Value::String(bits.to_string()),
            Some((unit, Held::Group(o))) => serde_json::Value::Object(
                o.iter()
                    .map(|(k, x)| {
                        let y = x.as_f64().map(|i| number(units.value(unit, i)));
                        (k.clone(), y.unwrap_or_else(|| x.clone()))
                    })
                    .collect(),
            ),
            None => v,
        },
    }
}

/// A measure's key in `units`: `key` without the inch suffix of `unit` (if it ends in
/// it), with the family's suffix (`base_radius_in` and `base_radius` become
/// `base_radius_mm` in SI, `base_radius_in` in inch).
pub fn key(key: &str, unit: Unit, units: Units) -> String {
    let stem = key
        .strip_suffix(unit.inch)
        .and_then(|s| s.strip_suffix('_'))
        .unwrap_or(key);
    format!("{stem}_{}", units.key_suffix(unit))
}

/// A quantity: its unit in both families.
pub trait Kind: Copy + std::fmt::Debug + Default + PartialEq {
    /// The quantity's unit (both families' suffixes, symbols and the factor).
    const UNIT: Unit;
}

/// A report's dimensional value, held in the inch family, of quantity `K`.
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
pub struct Measure<K: Kind> {
    inch: f64,
    kind: PhantomData<K>,
}

impl<K: Kind> Measure<K> {
    /// The measure whose inch-family value is `inch`.
    pub const fn inch(inch: f64) -> Self {
        Self {
            inch,
            kind: PhantomData,
        }
    }

    /// The value in the inch family (the model's own units).
    pub const fn in_inch(self) -> f64 {
        self.inch
    }
}

impl<K: Kind> From<f64> for Measure<K> {
    fn from(inch: f64) -> Self {
        Self::inch(inch)
    }
}

impl<K: Kind> Serialize for Measure<K> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("Measure", 2)?;
        m.serialize_field(MARKER, &marker(K::UNIT))?;
        m.serialize_field("value", &self.inch)?;
        m.end()
    }
}

/// Several numbers of quantity `K` under one key: `T` (a struct of `f64` fields in the
/// inch family, such as a column's mean, spread and percentiles). In JSON one marker
/// whose value is `T`'s object: [`super::convert`] converts every number in it and
/// names its key by `K`'s unit, the object's own keys unchanged.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measures<K: Kind, T> {
    inch: T,
    kind: PhantomData<K>,
}

impl<K: Kind, T> Measures<K, T> {
    /// The numbers `inch`, in the inch family.
    pub const fn inch(inch: T) -> Self {
        Self {
            inch,
            kind: PhantomData,
        }
    }
}

impl<K: Kind, T: Serialize> Serialize for Measures<K, T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("Measure", 2)?;
        m.serialize_field(MARKER, &marker(K::UNIT))?;
        m.serialize_field("value", &self.inch)?;
        m.end()
    }
}

/// A report's dimensional value held in the family it was measured in, of quantity `K`: a
/// drawing's lengths measured on its own points, in its own unit. Printed as is in that
/// family, converted in the other; in JSON a marker with its family,
/// `{"$unit": "in|mm", "family": "si", "value": 12.7}`, its key named as a
/// [`Measure`]'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasureIn<K: Kind> {
    value: f64,
    family: Units,
    kind: PhantomData<K>,
}

impl<K: Kind> MeasureIn<K> {
    /// The measure whose value in `family` is `value`.
    pub const fn new(value: f64, family: Units) -> Self {
        Self {
            value,
            family,
            kind: PhantomData,
        }
    }
}

impl<K: Kind> Serialize for MeasureIn<K> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("MeasureIn", 3)?;
        m.serialize_field(MARKER, &marker(K::UNIT))?;
        let family = match self.family {
            Units::Inch => "inch",
            Units::Si => "si",
        };
        m.serialize_field(FAMILY, family)?;
        m.serialize_field("value", &self.value)?;
        m.end()
    }
}

/// The raw bits of a computed value of quantity `K` (`0x...`, written by the caller),
/// the value as the model computes it, in the inch family. The bits are never converted;
/// their key is named as the value's would be, by its type, so a row's bits sit under
/// the same name as its number in either output (`min_force_lb`, `min_force_n`).
#[derive(Clone, Debug, PartialEq)]
pub struct Bits<K: Kind> {
    bits: String,
    kind: PhantomData<K>,
}

impl<K: Kind> Bits<K> {
    /// The bits `bits`, as written.
    pub fn new(bits: String) -> Self {
        Self {
            bits,
            kind: PhantomData,
        }
    }

    /// The bits as written.
    pub fn as_str(&self) -> &str {
        &self.bits
    }
}

impl<K: Kind> Serialize for Bits<K> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_struct("Bits", 2)?;
        m.serialize_field(MARKER, &marker(K::UNIT))?;
        m.serialize_field(BITS, &self.bits)?;
        m.end()
    }
}

impl Units {
    /// `m` in this family.
    pub fn of<K: Kind>(self, m: Measure<K>) -> f64 {
        self.value(K::UNIT, m.inch)
    }

    /// `m` for the text, printed with `inch_decimals` in inch ([`Units::q`]).
    pub fn show<K: Kind>(self, m: Measure<K>, inch_decimals: usize) -> Quantity {
        self.q(K::UNIT, m.inch, inch_decimals)
    }

    /// `m`'s unit as the text writes it in this family (`lb/in`, `N/mm`).
    pub fn unit_of<K: Kind>(self, _m: Measure<K>) -> &'static str {
        self.symbol(K::UNIT)
    }
}

macro_rules! kinds {
    ($($(#[$doc:meta])* $kind:ident, $alias:ident = $unit:expr;)*) => {
        /// The quantities a report carries (the marker types of [`Measure`]).
        pub mod kind {
            use super::{Kind, Unit};
            $(
                $(#[$doc])*
                #[derive(Clone, Copy, Debug, Default, PartialEq)]
                pub struct $kind;
                impl Kind for $kind {
                    const UNIT: Unit = $unit;
                }
            )*
        }
        $(
            $(#[$doc])*
            pub type $alias = Measure<kind::$kind>;
        )*
    };
}

kinds! {
    /// A length: in, mm.
    Length, Length = crate::units::LENGTH;
    /// A follower speed: in/s, mm/s.
    Speed, Speed = crate::units::SPEED;
    /// An acceleration: in/s², mm/s².
    Acceleration, Acceleration = crate::units::ACCELERATION;
    /// A jerk: in/s³, mm/s³.
    Jerk, Jerk = crate::units::JERK;
    /// A force: lb, N.
    Force, Force = crate::units::FORCE;
    /// A weight given as a mass (a spring's): lb, kg.
    Weight, Weight = crate::units::WEIGHT;
    /// A mass in the model's units: lb s²/in, kg.
    Mass, Mass = crate::units::MASS;
    /// A stress: psi, MPa.
    Stress, Stress = crate::units::STRESS;
    /// A torque: lb in, N m.
    Torque, Torque = crate::units::TORQUE;
    /// A translational stiffness (a spring rate): lb/in, N/mm.
    Stiffness, Stiffness = crate::units::STIFFNESS;
    /// A power: hp, kW.
    Power, Power = crate::units::POWER;
    /// A profile's slope in cam angle: in/rad, mm/rad.
    LengthPerRad, LengthPerRad = crate::units::LENGTH_PER_RAD;
    /// A profile's second derivative in cam angle: in/rad², mm/rad².
    LengthPerRad2, LengthPerRad2 = crate::units::LENGTH_PER_RAD2;
    /// A rotational inertia: lb in s², kg m².
    Inertia, Inertia = crate::units::INERTIA;
    /// A torsional stiffness (a shaft's): lb in/rad, N m/rad.
    TorsionalStiffness, TorsionalStiffness = crate::units::TORSIONAL_STIFFNESS;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_measure_converts_by_its_kind() {
        let f = Force::inch(100.0);
        assert_eq!(Units::Inch.of(f), 100.0);
        assert_eq!(Units::Si.of(f), 100.0 * crate::units::FORCE.si_per_inch);
        assert_eq!(Units::Si.unit_of(f), "N");
        assert_eq!(format!("{}", Units::Inch.show(f, 2)), "100.00");
        assert_eq!(format!("{}", Units::Si.show(f, 2)), "444.8");
    }

    #[test]
    fn a_measure_serializes_as_its_marker() {
        let v = serde_json::to_value(Stress::inch(150_000.0)).unwrap();
        assert_eq!(
            v,
            serde_json::json!({"$unit": "psi|mpa", "value": 150_000.0})
        );
    }

    #[test]
    fn a_measure_that_is_not_finite_prints_null_not_a_marker() {
        let v = serde_json::json!({"f": Force::inch(f64::NAN)});
        let text = serde_json::to_string(&v).unwrap();
        assert_eq!(
            crate::units::json(&text, Units::Si).unwrap(),
            r#"{"f_n":null}"#
        );
    }

    #[test]
    fn a_measure_in_a_family_prints_as_is_there_and_converts_in_the_other() {
        let v = serde_json::json!({"perimeter": MeasureIn::<kind::Length>::new(12.7, Units::Si)});
        let text = serde_json::to_string(&v).unwrap();
        let si = crate::units::json(&text, Units::Si).unwrap();
        assert_eq!(si, r#"{"perimeter_mm":12.7}"#);
        let inch = crate::units::json(&text, Units::Inch).unwrap();
        assert_eq!(inch, r#"{"perimeter_in":0.5}"#);
        let v = serde_json::json!({"e_in": MeasureIn::<kind::Length>::new(0.5, Units::Inch)});
        let text = serde_json::to_string(&v).unwrap();
        assert_eq!(
            crate::units::json(&text, Units::Inch).unwrap(),
            r#"{"e_in":0.5}"#
        );
        assert_eq!(
            crate::units::json(&text, Units::Si).unwrap(),
            r#"{"e_mm":12.7}"#
        );
    }

    #[test]
    fn bits_keep_their_string_under_their_values_key() {
        let v = serde_json::json!({"f_lb": Bits::<kind::Force>::new("0x3f800000".into())});
        let text = serde_json::to_string(&v).unwrap();
        let inch = crate::units::json(&text, Units::Inch).unwrap();
        assert_eq!(inch, r#"{"f_lb":"0x3f800000"}"#);
        let si = crate::units::json(&text, Units::Si).unwrap();
        assert_eq!(si, r#"{"f_n":"0x3f800000"}"#);
        assert!(crate::units::by_name(&v).is_empty());
    }

    #[derive(serde::Serialize)]
    struct R {
        radius_in: Length,
        contact_force_min: Force,
        mass: Weight,
        lifts: Vec<Length>,
        plain_in: f64,
    }

    #[test]
    fn a_report_converts_by_its_fields_types() {
        let r = R {
            radius_in: Length::inch(2.0),
            contact_force_min: Force::inch(10.0),
            mass: Weight::inch(1.0),
            lifts: vec![Length::inch(1.0), Length::inch(0.5)],
            plain_in: 1.0,
        };
        let text = serde_json::to_string(&r).unwrap();
        let inch = crate::units::json(&text, Units::Inch).unwrap();
        assert_eq!(
            inch,
            r#"{"contact_force_min_lb":10.0,"lifts_in":[1.0,0.5],"mass_lb":1.0,"plain_in":1.0,"radius_in":2.0}"#
        );
        let si: serde_json::Value =
            serde_json::from_str(&crate::units::json(&text, Units::Si).unwrap()).unwrap();
        assert_eq!(si["radius_mm"], 50.8);
        assert_eq!(
            si["contact_force_min_n"],
            10.0 * crate::units::FORCE.si_per_inch
        );
        assert_eq!(si["mass_kg"], 0.453_592_37);
        assert_eq!(si["lifts_mm"][1], 12.7);
        assert_eq!(si["plain_mm"], 25.4);
    }

    #[test]
    fn measures_convert_whole_and_keep_their_keys() {
        #[derive(serde::Serialize)]
        struct Two {
            mean: f64,
            sd: f64,
        }
        let v = serde_json::json!({
            "force": Measures::<kind::Force, _>::inch(Two { mean: 10.0, sd: f64::NAN }),
            "plain": {"f": Force::inch(1.0), "l": Length::inch(1.0)},
        });
        let text = serde_json::to_string(&v).unwrap();
        let si: serde_json::Value =
            serde_json::from_str(&crate::units::json(&text, Units::Si).unwrap()).unwrap();
        let n = crate::units::FORCE.si_per_inch;
        assert_eq!(
            si["force_n"],
            serde_json::json!({"mean": 10.0 * n, "sd": null})
        );
        // An object of measures is not one: its keys take their units.
        assert_eq!(si["plain"], serde_json::json!({"f_n": n, "l_mm": 25.4}));
    }

    /// A search's `[value, passed]` rows convert by their measure's type, the flags kept;
    /// an array of flags alone is not a measure.
    #[test]
    fn rows_of_a_measure_and_a_flag_convert_by_the_measure() {
        let v = serde_json::json!({
            "tried": [(Stiffness::inch(10.0), false), (Stiffness::inch(20.0), true)],
            "flags": [true, false],
        });
        let si = crate::units::convert(v.clone(), Units::Si);
        let n_per_mm = crate::units::STIFFNESS.si_per_inch;
        assert_eq!(
            si,
            serde_json::json!({
                "tried_n_per_mm": [[10.0 * n_per_mm, false], [20.0 * n_per_mm, true]],
                "flags": [true, false],
            })
        );
        assert_eq!(measured(&v["flags"]), None);
        assert_eq!(measured(&serde_json::json!([])), None);
    }
}
