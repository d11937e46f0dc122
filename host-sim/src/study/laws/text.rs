//! The text and JSON of `camsim laws` ([`LawsReport`]): the table, the reference cam's
//! lengths in the output's family.

use super::LawsReport;
use crate::report::Report;
use crate::units::{Units, LENGTH};

impl Report for LawsReport {
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }

    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let rows = &self.laws;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "Motion laws (Appendix A): peak coefficients for a unit rise over a unit angle,"
        );
        let _ = writeln!(
            s,
            "y = h s(theta/beta): dy/dtheta = cv h/beta, d2y/dtheta2 = ca h/beta^2, d3y/dtheta3 = cj h/beta^3."
        );
        let l = |x: f64| units.given(LENGTH, x);
        let _ = writeln!(
            s,
            "phi_max: largest pressure angle on the reference cam (R_b {} {u}, r_r {} {u}, lift {} {u},",
            l(1.5),
            l(0.375),
            l(1.5),
            u = units.symbol(LENGTH)
        );
        let _ = writeln!(
            s,
            "rise 30-180 deg and return 210-360 deg both with the law)."
        );
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "{:<22}{:>9}{:>10}{:>10}{:>11}{:>11}{:>13}",
            "law", "cv", "ca_max", "ca_min", "cj_max", "cj_min", "phi_max_deg"
        );
        for r in rows {
            let _ = writeln!(
                s,
                "{:<22}{:>9.4}{:>10.4}{:>10.4}{:>11.4}{:>11.4}{:>13.3}",
                r.name, r.cv, r.ca_max, r.ca_min, r.cj_max, r.cj_min, r.pressure_angle_max_deg
            );
        }
        let _ = writeln!(s);
        let _ = writeln!(
            s,
            "Only finite values inside the stroke are listed: the impulses at a velocity or acceleration"
        );
        let _ = writeln!(
            s,
            "jump (straight-line at its ends, parabolic and cubic-1 at mid-stroke, and any law whose"
        );
        let _ = writeln!(
            s,
            "end acceleration is not 0 against a dwell) are not representable and are excluded."
        );
        s
    }
}
