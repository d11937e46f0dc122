//! What a command prints: one `Serialize` report struct per command, rendered either as
//! text (the tables) or as JSON (`--json`) from the same values.

use std::io::Write;

use anyhow::Result;
use serde::Serialize;

/// A command's report: the values it computed, serializable (`--json`) and renderable
/// as the human-readable text. Fields a report keeps only for the text are
/// `#[serde(skip)]`.
pub trait Report: Serialize {
    /// The text the command prints without `--json` (ending with a newline).
    fn text(&self) -> String;

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
/// serde_json writes NaN and the infinities as `null`, so a `null` in the serialized
/// report is a non-finite number: the reports skip an absent optional value
/// (`skip_serializing_if = "Option::is_none"`) instead of writing `null`, so that `--json`
/// never prints `null` for a number and this check finds every non-finite one.
pub fn non_finite<R: Serialize + ?Sized>(report: &R) -> Result<Option<String>> {
    fn walk(v: &serde_json::Value, path: &mut String) -> bool {
        match v {
            serde_json::Value::Null => true,
            serde_json::Value::Array(a) => a.iter().enumerate().any(|(i, x)| {
                let len = path.len();
                path.push_str(&format!("[{i}]"));
                let found = walk(x, path);
                if !found {
                    path.truncate(len);
                }
                found
            }),
            serde_json::Value::Object(o) => o.iter().any(|(k, x)| {
                let len = path.len();
                if !path.is_empty() {
                    path.push('.');
                }
                path.push_str(k);
                let found = walk(x, path);
                if !found {
                    path.truncate(len);
                }
                found
            }),
            _ => false,
        }
    }
    let value = serde_json::to_value(report)?;
    let mut path = String::new();
    Ok(walk(&value, &mut path).then_some(path))
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
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())?;
    out.flush()?;
    Ok(())
}

/// Prints `report` to standard output, as JSON or as text, after checking that every
/// number in it is finite ([`ensure_finite`]) and its contact stresses and forces are
/// physical ([`ensure_physical`]).
pub fn print<R: Report>(report: &R, json: bool) -> Result<()> {
    ensure_finite(report)?;
    ensure_physical(report)?;
    if json {
        out(&format!("{}\n", report.json()?))
    } else {
        out(&report.text())
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
}
