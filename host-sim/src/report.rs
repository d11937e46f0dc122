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

/// Prints `report` to standard output, as JSON or as text.
pub fn print<R: Report>(report: &R, json: bool) -> Result<()> {
    let mut out = std::io::stdout().lock();
    if json {
        writeln!(out, "{}", report.json()?)?;
    } else {
        out.write_all(report.text().as_bytes())?;
    }
    out.flush()?;
    Ok(())
}
