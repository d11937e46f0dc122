//! The text of `camsim jump-speed`'s reports: the theoretical cam's onset and margin,
//! and the machined cams' onset distribution.

use super::actual::ActualOnsetReport;
use super::report::JumpSpeedReport;
use crate::report::Report;

/// The human-readable output.
pub fn render_text(r: &JumpSpeedReport) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let op = r.operating_rpm;
    match (r.jump_rpm, r.margin_rpm, r.margin_percent) {
        (Some(j), Some(m), Some(pct)) => {
            let below = r.no_jump_rpm;
            let _ = writeln!(
                out,
                "jump speed: {j:.1} rpm (steady-state separation; contact holds at {below:.1} rpm: the onset lies between)",
            );
            let jumps = if m <= 0.0 {
                "  -- the follower JUMPS at the operating speed"
            } else {
                ""
            };
            // A bracket wider than 1 % of the operating speed is stated as the range it
            // is: the margin is only known to lie between its ends.
            if j - below > 0.01 * op {
                let (m_lo, pct_lo) = (below - op, 100.0 * (below - op) / op);
                let _ = writeln!(
                    out,
                    "operating point {op:.1} rpm: margin between {m_lo:+.1} and {m:+.1} rpm ({pct_lo:+.1} % to {pct:+.1} %; a smaller --resolution narrows it){jumps}"
                );
            } else {
                let _ = writeln!(
                    out,
                    "operating point {op:.1} rpm: margin {m:+.1} rpm ({pct:+.1} %){jumps}"
                );
            }
        }
        _ => {
            let _ = writeln!(out, "no jump up to {:.0} rpm", r.no_jump_rpm);
        }
    }
    let _ = writeln!(
        out,
        "{} simulations of 2 revolutions, {:.0} ms",
        r.simulations, r.wall_ms
    );
    out
}

impl Report for JumpSpeedReport {
    fn text(&self, _units: crate::units::Units) -> String {
        render_text(self)
    }
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }
}

impl Report for ActualOnsetReport {
    fn text(&self, _units: crate::units::Units) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let f = |x: Option<f64>| x.map_or("none".to_string(), |v| format!("{v:.1}"));
        let _ = writeln!(
            s,
            "jump onset of {} machined cams (seed {}), rpm, to {} rpm:",
            self.samples, self.seed, self.resolution_rpm
        );
        let _ = writeln!(
            s,
            "  min {}  5% {}  25% {}  median {}  75% {}  max {}",
            f(self.min_rpm),
            f(self.q05_rpm),
            f(self.q25_rpm),
            f(self.median_rpm),
            f(self.q75_rpm),
            f(self.max_onset_rpm)
        );
        let _ =
            writeln!(
            s,
            "  theoretical cam: {} rpm; operating point {:.1} rpm: {} of {} samples jump at it, P(jump) {} (95 % Wilson){}",
            f(self.theoretical_jump_rpm),
            self.operating_rpm,
            self.jump_at_operating,
            self.samples,
            self.p_jump_at_operating.text(3),
            if self.beyond_max > 0 {
                format!("; {} without onset up to {} rpm", self.beyond_max, self.max_rpm)
            } else {
                String::new()
            }
        );
        let _ = writeln!(
            s,
            "{} simulations of 2 revolutions on {} threads, {:.0} ms",
            self.simulations, self.threads, self.wall_ms
        );
        s
    }
}
