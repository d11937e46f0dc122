//! The jump margin (`--margin`): the jump-onset speed over the operating speed.

use anyhow::Result;
use camsim_core::Start;
use serde::Serialize;

use crate::sim::RunSpec;

/// The jump margin (`--margin`).
#[derive(Clone, Debug, Serialize)]
pub struct MarginVerdict {
    /// Lowest speed with steady-state separation, rpm (absent: none up to the search's top).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_onset_rpm: Option<f64>,
    /// Highest speed checked that holds contact, rpm.
    pub holds_at_rpm: f64,
    /// The onset over the operating speed, minus 1, in percent (absent without an onset).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_percent: Option<f64>,
    /// Bracket width of the onset, rpm.
    pub bracket_rpm: f64,
    /// Simulations the search ran (2 revolutions each, static start).
    pub simulations: u32,
}

/// The verdict's margin line: the jump onset's margin over the operating speed, no jump up
/// to the search's limit, or not computed (`None`: no `--margin`).
pub(super) fn margin_text(m: Option<&MarginVerdict>) -> String {
    let Some(m) = m else {
        return "  margin:    not computed (--margin: a search of about 15 two-revolution runs)"
            .to_string();
    };
    match (m.jump_onset_rpm, m.margin_percent) {
        (Some(j), Some(p)) => format!(
            "  margin:    jump onset {j:.1} rpm (contact holds at {:.1} rpm; bracket {:.1} rpm), {p:+.1} % over the operating speed; {} simulations",
            m.holds_at_rpm, m.bracket_rpm, m.simulations
        ),
        _ => format!(
            "  margin:    no jump up to {:.0} rpm; {} simulations",
            m.holds_at_rpm, m.simulations
        ),
    }
}

/// The jump margin of `run` at `rpm`: the onset search from the static start.
pub fn margin(run: &RunSpec, rpm: f64) -> Result<MarginVerdict> {
    use crate::study::jump_speed;
    let mut s = run.clone();
    s.solver.start = Start::Static;
    let r = jump_speed::find(&s, 1.0, jump_speed::MAX_RPM)?;
    Ok(MarginVerdict {
        jump_onset_rpm: r.jump_rpm,
        holds_at_rpm: r.no_jump_rpm,
        margin_percent: r.jump_rpm.map(|j| 100.0 * (j / rpm - 1.0)),
        bracket_rpm: r.jump_rpm.map_or(0.0, |j| j - r.no_jump_rpm),
        simulations: r.simulations,
    })
}
