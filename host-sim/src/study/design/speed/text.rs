//! The text and JSON of a Monte Carlo design search's report ([`McSearchReport`]).

use super::McSearchReport;
use crate::report::Report;
use crate::units::{self, Length, Units};

/// The first lines of a search's text: its answer in the user's words.
fn search_headline(r: &McSearchReport, out: &mut String, units: Units) {
    use std::fmt::Write;
    if r.search == "speed" {
        let _ = writeln!(
            out,
            "camsim design speed: {:.1} rpm on actual cams",
            r.answer
        );
        if let Some(t) = r.theoretical_onset_rpm {
            let _ = writeln!(
                out,
                "  theoretical cam's jump onset: {t:.1} rpm (full model)"
            );
        }
    } else if r.search == "waviness" {
        let _ = writeln!(
            out,
            "camsim design tolerance --waviness: FPR {:.0} is the roughest waviness that passes at {} x VI.1's tolerances (cam ±{} {lu}, roller ±{} {lu})",
            r.answer,
            r.tolerance_factor.unwrap_or(1.0),
            units.q(units::LENGTH, r.cam_tolerance_in.map_or(0.0, Length::in_inch), 5),
            units.q(units::LENGTH, r.roller_tolerance_in.map_or(0.0, Length::in_inch), 6),
            lu = units.symbol(units::LENGTH)
        );
        let _ = writeln!(
            out,
            "  roughest = the highest FPR, the shortest waves (the acceleration a wave imposes grows as FPR², docs/MODEL.md §9.6)"
        );
    } else {
        let _ = writeln!(
            out,
            "camsim design tolerance: cam ±{} {lu} ({:.3} x VI.1's) at FPR {}; held: roller ±{} {lu}, eccentricity ±{} {lu}",
            units.q(units::LENGTH, r.cam_tolerance_in.map_or(0.0, Length::in_inch), 5),
            r.answer,
            r.waviness_fpr.unwrap_or(crate::actual::DEFAULT_FPR),
            units.q(units::LENGTH, r.roller_tolerance_in.map_or(0.0, Length::in_inch), 6),
            units.q(units::LENGTH, r.eccentricity_tolerance_in.map_or(0.0, Length::in_inch), 5),
            lu = units.symbol(units::LENGTH)
        );
    }
}

impl McSearchReport {
    /// The JSON key of the values tried, naming their unit: `speeds_tried_rpm`,
    /// `tolerance_factors_tried` (factors on VI.1's tolerances) or `waviness_fprs_tried`.
    pub fn tried_key(&self) -> &'static str {
        match self.search.as_str() {
            "speed" => "speeds_tried_rpm",
            "waviness" => "waviness_fprs_tried",
            _ => "tolerance_factors_tried",
        }
    }

    /// The report as JSON, the values tried under [`Self::tried_key`].
    pub(crate) fn json_value(&self) -> serde_json::Result<serde_json::Value> {
        let mut v = serde_json::to_value(self)?;
        if let Some(o) = v.as_object_mut() {
            if let Some(t) = o.remove("tried") {
                o.insert(self.tried_key().into(), t);
            }
        }
        Ok(v)
    }
}

impl Report for McSearchReport {
    fn json(&self) -> serde_json::Result<String> {
        crate::report::sorted_pretty_json(&self.json_value()?)
    }
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        search_headline(self, &mut out, units);
        let d = if self.search == "waviness" { 0 } else { 4 };
        match self.failing {
            Some(f) => {
                let _ = writeln!(
                    out,
                    "  bracket: passes at {:.d$}, fails at {f:.d$} (width {:.d$} {})",
                    self.answer, self.bracket, self.unit
                );
            }
            None => {
                let _ = writeln!(
                    out,
                    "  nothing failed up to the search's limit {:.4}",
                    self.answer
                );
            }
        }
        if let Some(p) = &self.p_jump {
            let _ = writeln!(
                out,
                "  P(jump) at the answer: {} of {}: {} (95 % Wilson)",
                p.count,
                self.samples,
                p.text(4)
            );
        }
        let _ = writeln!(out, "  criterion: {}", self.criterion);
        let _ = writeln!(out, "  model: {}", self.model);
        let tried: Vec<String> = self
            .tried
            .iter()
            .map(|(x, ok)| {
                let d = if self.search == "waviness" { 0 } else { 3 };
                format!("{x:.d$}{}", if *ok { "+" } else { "-" })
            })
            .collect();
        let _ = writeln!(out, "  values tried (+ passes): {}", tried.join(" "));
        let _ = writeln!(
            out,
            "  {} model runs of 2 revolutions, {:.1} s",
            self.model_runs, self.wall_s
        );
        out
    }
}
