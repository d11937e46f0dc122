//! What a command prints: one `Serialize` report struct per command, rendered either as
//! text (the tables) or as JSON (`--json`) from the same values.

use std::io::Write;

use anyhow::Result;
use serde::Serialize;

/// A command's report: the values it computed, serializable (`--json`) and renderable
/// as the human-readable text. Fields a report keeps only for the text are
/// `#[serde(skip)]`.
pub trait Report: Serialize {
    /// The text the command prints without `--json` (ending with a newline), every
    /// dimensional number in `units`.
    fn text(&self, units: crate::units::Units) -> String;

    /// The JSON the command prints with `--json` (pretty unless a command says
    /// otherwise).
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string_pretty(self)
    }
}

/// Pretty JSON with the keys of every object sorted (what `serde_json::json!` built
/// before the reports were structs: `run` and `bench` keep that order).
pub fn sorted_pretty_json<T: Serialize + ?Sized>(value: &T) -> serde_json::Result<String> {
    serde_json::to_string_pretty(&serde_json::to_value(value)?)
}

/// Where in `report` a number is not finite (JSON path, `per_period[3].torque_avg`), if
/// anywhere.
///
/// The report is walked as it serializes (not through its JSON, where serde_json writes
/// NaN and the infinities as `null`, like an absent value): every `f32`/`f64` is
/// checked, and an absent optional value (`None`, a unit) is not a number at all, so a
/// value absent by design is never taken for a non-finite one. The reports still skip
/// an absent value (`skip_serializing_if = "Option::is_none"`), so that `--json` never
/// prints `null`.
pub fn non_finite<R: Serialize + ?Sized>(report: &R) -> Result<Option<String>> {
    let mut path = String::new();
    match report.serialize(finite::Check { path: &mut path }) {
        Ok(()) => Ok(None),
        Err(finite::Error::Found(p)) => Ok(Some(p)),
        Err(finite::Error::Other(e)) => Err(anyhow::anyhow!("checking the result: {e}")),
    }
}

/// The serializer behind [`non_finite`]: it writes nothing and stops at the first
/// non-finite number with its path.
mod finite {
    use serde::ser::{self, Serialize};

    #[derive(Debug)]
    pub enum Error {
        Found(String),
        Other(String),
    }

    impl std::fmt::Display for Error {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            match self {
                Error::Found(p) => write!(f, "{p} is not finite"),
                Error::Other(e) => f.write_str(e),
            }
        }
    }

    impl std::error::Error for Error {}

    impl ser::Error for Error {
        fn custom<T: std::fmt::Display>(msg: T) -> Self {
            Error::Other(msg.to_string())
        }
    }

    pub struct Check<'a> {
        pub path: &'a mut String,
    }

    impl Check<'_> {
        fn float(self, v: f64) -> Result<(), Error> {
            if v.is_finite() {
                Ok(())
            } else {
                Err(Error::Found(self.path.clone()))
            }
        }
    }

    /// Serializes `v` at `path` + `seg` (`.name` or `[i]`), the path restored after.
    fn at<T: Serialize + ?Sized>(path: &mut String, seg: &str, v: &T) -> Result<(), Error> {
        let len = path.len();
        if !seg.starts_with('[') && !path.is_empty() {
            path.push('.');
        }
        path.push_str(seg);
        v.serialize(Check { path })?;
        path.truncate(len);
        Ok(())
    }

    pub struct Compound<'a> {
        path: &'a mut String,
        index: usize,
        key: String,
        /// A measure's marker (`units::Measure`): its number is at the field's own path.
        measure: bool,
    }

    impl<'a> Compound<'a> {
        fn new(path: &'a mut String) -> Self {
            Compound {
                path,
                index: 0,
                key: String::new(),
                measure: false,
            }
        }
        fn element<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
            let seg = format!("[{}]", self.index);
            self.index += 1;
            at(self.path, &seg, v)
        }
    }

    macro_rules! seq_like {
        ($($tr:ident :: $m:ident),*) => {$(
            impl ser::$tr for Compound<'_> {
                type Ok = ();
                type Error = Error;
                fn $m<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
                    self.element(v)
                }
                fn end(self) -> Result<(), Error> {
                    Ok(())
                }
            }
        )*};
    }
    seq_like!(
        SerializeSeq::serialize_element,
        SerializeTuple::serialize_element,
        SerializeTupleStruct::serialize_field,
        SerializeTupleVariant::serialize_field
    );

    macro_rules! struct_like {
        ($($tr:ident),*) => {$(
            impl ser::$tr for Compound<'_> {
                type Ok = ();
                type Error = Error;
                fn serialize_field<T: Serialize + ?Sized>(
                    &mut self,
                    key: &'static str,
                    v: &T,
                ) -> Result<(), Error> {
                    if self.measure {
                        // `per_period[1].contact_stress_max`, not `...max.value`.
                        return v.serialize(Check { path: self.path });
                    }
                    at(self.path, key, v)
                }
                fn end(self) -> Result<(), Error> {
                    Ok(())
                }
            }
        )*};
    }
    struct_like!(SerializeStruct, SerializeStructVariant);

    impl ser::SerializeMap for Compound<'_> {
        type Ok = ();
        type Error = Error;
        fn serialize_key<T: Serialize + ?Sized>(&mut self, key: &T) -> Result<(), Error> {
            self.key = match serde_json::to_value(key) {
                Ok(serde_json::Value::String(s)) => s,
                Ok(v) => v.to_string(),
                Err(e) => return Err(Error::Other(e.to_string())),
            };
            Ok(())
        }
        fn serialize_value<T: Serialize + ?Sized>(&mut self, v: &T) -> Result<(), Error> {
            let key = std::mem::take(&mut self.key);
            at(self.path, &key, v)
        }
        fn end(self) -> Result<(), Error> {
            Ok(())
        }
    }

    impl<'a> ser::Serializer for Check<'a> {
        type Ok = ();
        type Error = Error;
        type SerializeSeq = Compound<'a>;
        type SerializeTuple = Compound<'a>;
        type SerializeTupleStruct = Compound<'a>;
        type SerializeTupleVariant = Compound<'a>;
        type SerializeMap = Compound<'a>;
        type SerializeStruct = Compound<'a>;
        type SerializeStructVariant = Compound<'a>;

        fn serialize_f64(self, v: f64) -> Result<(), Error> {
            self.float(v)
        }
        fn serialize_f32(self, v: f32) -> Result<(), Error> {
            self.float(f64::from(v))
        }
        fn serialize_bool(self, _: bool) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_i8(self, _: i8) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_i16(self, _: i16) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_i32(self, _: i32) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_i64(self, _: i64) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_u8(self, _: u8) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_u16(self, _: u16) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_u32(self, _: u32) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_u64(self, _: u64) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_char(self, _: char) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_str(self, _: &str) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_bytes(self, _: &[u8]) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_none(self) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_some<T: Serialize + ?Sized>(self, v: &T) -> Result<(), Error> {
            v.serialize(self)
        }
        fn serialize_unit(self) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_unit_struct(self, _: &'static str) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_unit_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
        ) -> Result<(), Error> {
            Ok(())
        }
        fn serialize_newtype_struct<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            v: &T,
        ) -> Result<(), Error> {
            v.serialize(self)
        }
        fn serialize_newtype_variant<T: Serialize + ?Sized>(
            self,
            _: &'static str,
            _: u32,
            variant: &'static str,
            v: &T,
        ) -> Result<(), Error> {
            at(self.path, variant, v)
        }
        fn serialize_seq(self, _: Option<usize>) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
        fn serialize_tuple(self, _: usize) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
        fn serialize_tuple_struct(self, _: &'static str, _: usize) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
        fn serialize_tuple_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
        fn serialize_map(self, _: Option<usize>) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
        fn serialize_struct(self, name: &'static str, _: usize) -> Result<Compound<'a>, Error> {
            let mut c = Compound::new(self.path);
            c.measure = matches!(name, "Measure" | "MeasureIn");
            Ok(c)
        }
        fn serialize_struct_variant(
            self,
            _: &'static str,
            _: u32,
            _: &'static str,
            _: usize,
        ) -> Result<Compound<'a>, Error> {
            Ok(Compound::new(self.path))
        }
    }
}

/// Refuses a report with a number that is not finite ([`non_finite`]): a result is
/// reported as a success only when every number in it is finite.
pub fn ensure_finite<R: Serialize + ?Sized>(report: &R) -> Result<()> {
    if let Some(path) = non_finite(report)? {
        anyhow::bail!(
            "the result is not finite: {path} is NaN or infinite (the computation left the range where its numbers mean something; nothing was reported)"
        );
    }
    Ok(())
}

/// Refuses a report whose contact stress or contact force is beyond a physical bound
/// (camsim-core's [`camsim_core::MAX_PLAUSIBLE_CONTACT_STRESS_PSI`] and
/// [`camsim_core::MAX_PLAUSIBLE_CONTACT_FORCE_LB`]): every number under a key that
/// starts with `contact_stress` or `contact_force` (a column, its statistics) is
/// checked. `camsim contact` (a calculator at a force the user gives) names its
/// fields otherwise and is not held to them.
pub fn ensure_physical<R: Serialize + ?Sized>(report: &R) -> Result<()> {
    fn walk(
        v: &serde_json::Value,
        path: &mut String,
        bound: Option<(f64, &str)>,
    ) -> Option<(String, f64, f64, &'static str)> {
        match v {
            serde_json::Value::Number(n) => {
                let (max, unit) = bound?;
                let x = n.as_f64()?;
                (x.abs() > max).then(|| {
                    (
                        path.clone(),
                        x,
                        max,
                        if unit == "psi" { "psi" } else { "lb" },
                    )
                })
            }
            serde_json::Value::Array(a) => a.iter().enumerate().find_map(|(i, x)| {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                let found = walk(x, path, bound);
                path.truncate(len);
                found
            }),
            serde_json::Value::Object(o) => o.iter().find_map(|(k, x)| {
                let len = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                let b = if k.starts_with("contact_stress") {
                    Some((camsim_core::MAX_PLAUSIBLE_CONTACT_STRESS_PSI, "psi"))
                } else if k.starts_with("contact_force") {
                    Some((camsim_core::MAX_PLAUSIBLE_CONTACT_FORCE_LB, "lb"))
                } else {
                    bound
                };
                let found = walk(x, path, b);
                path.truncate(len);
                found
            }),
            _ => None,
        }
    }
    let value = serde_json::to_value(report)?;
    let mut path = String::new();
    if let Some((at, x, max, unit)) = walk(&value, &mut path, None) {
        anyhow::bail!(
            "the result is not physical: {at} = {x:.3e} {unit}, beyond {max:.0e} {unit} (no steel cam carries it: an edge or a notch in the profile, or a model far outside its range; nothing was reported)"
        );
    }
    Ok(())
}

/// Writes `text` to standard output and flushes it (an error, not a panic, when the
/// reader has gone: the binary ends quietly on a closed pipe).
pub fn out(text: &str) -> Result<()> {
    use anyhow::Context as _;
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .context("standard output: write failed")
}

/// Prints `report` to standard output, as JSON or as text, after checking that every
/// number in it is finite ([`ensure_finite`]) and its contact stresses and forces are
/// physical ([`ensure_physical`]), every dimensional number in `units`.
pub fn print<R: Report>(report: &R, json: bool, units: crate::units::Units) -> Result<()> {
    ensure_finite(report)?;
    ensure_physical(report)?;
    if json {
        // Every numeric key with its unit, in the family --units chose.
        let text = crate::units::json(&report.json()?, units)?;
        out(&format!("{text}\n"))
    } else {
        out(&report.text(units))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct R {
        a: f64,
        rows: Vec<Row>,
        #[serde(skip_serializing_if = "Option::is_none")]
        absent: Option<f64>,
    }
    #[derive(Serialize)]
    struct Row {
        x: f64,
    }

    #[test]
    fn the_first_non_finite_number_is_named_by_its_path() {
        let mut r = R {
            a: 1.0,
            rows: vec![Row { x: 2.0 }, Row { x: 3.0 }],
            absent: None,
        };
        assert_eq!(non_finite(&r).unwrap(), None);
        ensure_finite(&r).unwrap();
        r.rows[1].x = f64::NAN;
        assert_eq!(non_finite(&r).unwrap().as_deref(), Some("rows[1].x"));
        r.a = f64::NEG_INFINITY;
        assert_eq!(non_finite(&r).unwrap().as_deref(), Some("a"));
        let e = ensure_finite(&r).unwrap_err().to_string();
        assert!(
            e.starts_with("the result is not finite: a is NaN or infinite"),
            "{e}"
        );
        r.a = 0.0;
        r.rows[1].x = 1.0;
        r.absent = Some(f64::INFINITY);
        assert_eq!(non_finite(&r).unwrap().as_deref(), Some("absent"));
    }

    #[test]
    fn a_measure_is_named_by_its_field_not_its_marker() {
        #[derive(Serialize)]
        struct M {
            rows: Vec<crate::units::Force>,
        }
        let r = M {
            rows: vec![
                crate::units::Force::inch(1.0),
                crate::units::Force::inch(f64::NAN),
            ],
        };
        assert_eq!(non_finite(&r).unwrap().as_deref(), Some("rows[1]"));
    }

    #[test]
    fn an_absent_value_is_not_a_non_finite_number() {
        // What broke tolerance-study: an Option written as null (no skip) is absent by
        // design, not NaN; a NaN inside an Option, a tuple, a map or a nested array is.
        #[derive(Serialize)]
        struct T {
            absent: Option<f64>,
            unit: (),
            pair: (f64, Option<f32>),
            map: std::collections::BTreeMap<String, Vec<f64>>,
        }
        let mut t = T {
            absent: None,
            unit: (),
            pair: (1.0, None),
            map: [("k".to_string(), vec![1.0, 2.0])].into_iter().collect(),
        };
        assert_eq!(non_finite(&t).unwrap(), None);
        t.pair.1 = Some(f32::NAN);
        assert_eq!(non_finite(&t).unwrap().as_deref(), Some("pair[1]"));
        t.pair.1 = None;
        t.map.get_mut("k").unwrap()[1] = f64::INFINITY;
        assert_eq!(non_finite(&t).unwrap().as_deref(), Some("map.k[1]"));
        t.map.get_mut("k").unwrap()[1] = 0.0;
        t.absent = Some(f64::NAN);
        assert_eq!(non_finite(&t).unwrap().as_deref(), Some("absent"));
    }
}
