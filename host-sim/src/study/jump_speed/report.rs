//! The report of `camsim jump-speed` on the theoretical cam: the onset bracket and the
//! operating point's margin.

use serde::Serialize;

use super::JumpSpeed;

/// What `camsim jump-speed` prints: the text output and `--json` are both this report.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JumpSpeedReport {
    /// Lowest speed with steady-state separation, rpm (absent: none up to `--max-rpm`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm: Option<f64>,
    /// Highest speed checked without separation, rpm.
    pub no_jump_rpm: f64,
    /// The scene's operating speed, rpm.
    pub operating_rpm: f64,
    /// Jump speed minus operating speed, rpm (absent without a jump speed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_rpm: Option<f64>,
    /// The margin in percent of the operating speed (absent without a jump speed).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin_percent: Option<f64>,
    /// Bisection resolution asked for, rpm.
    pub resolution_rpm: f64,
    /// Simulations run.
    pub simulations: u32,
    /// Wall time of the search, ms.
    pub wall_ms: f64,
}

impl JumpSpeedReport {
    /// The report of a search result at operating speed `operating_rpm`.
    pub fn new(r: &JumpSpeed, operating_rpm: f64, resolution_rpm: f64, wall_ms: f64) -> Self {
        let margin_rpm = r.jump_rpm.map(|j| j - operating_rpm);
        Self {
            jump_rpm: r.jump_rpm,
            no_jump_rpm: r.no_jump_rpm,
            operating_rpm,
            margin_rpm,
            margin_percent: margin_rpm.map(|m| 100.0 * m / operating_rpm),
            resolution_rpm,
            simulations: r.simulations,
            wall_ms,
        }
    }
}
