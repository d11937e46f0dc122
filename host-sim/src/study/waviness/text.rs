//! The text of `camsim waviness`: the table ([`WavinessReport`]) and the measured
//! revolution's line ([`MeasuredWaviness`]), lengths in the output's family.

use super::WavinessReport;
use crate::measured::MeasuredWaviness;
use crate::report::Report;
use crate::units::{Units, LENGTH};

impl Report for MeasuredWaviness {
    fn text(&self, units: Units) -> String {
        format!("{}\n", self.line(units))
    }
}

fn range(v: &[usize]) -> String {
    let lo = v.iter().min().copied().unwrap_or(0);
    let hi = v.iter().max().copied().unwrap_or(0);
    if lo == hi {
        format!("{lo}")
    } else {
        format!("{lo}-{hi}")
    }
}

impl Report for WavinessReport {
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        // Lengths in the output's family (`--units`); the tolerances as given (VI.1's).
        let unit = units.symbol(LENGTH);
        let tol = camsim_core::Tolerances::<f64>::reference();
        let seeds: Vec<String> = self.seeds.iter().map(|s| s.to_string()).collect();
        let _ = writeln!(
            out,
            "camsim waviness: the reference design at VI.1's tolerances (cam ±{}, roller ±{}, eccentricity ±{} {unit}); \
             FPR of the master seeds' profiles ({}) against the interval, both profile methods; the criteria of IV.2.3 on seed {}'s \
             (thesis method). Roller radius {} {unit}, prime radius {} {unit}; the theoretical displacement's smallest radius of \
             curvature (abscissa R_p theta) {} {unit}. FPR 2n = a single harmonic of n undulations a revolution (UPR).",
            units.given(LENGTH, tol.cam),
            units.given(LENGTH, tol.roller),
            units.given(LENGTH, tol.eccentricity),
            seeds.join(", "),
            seeds.first().cloned().unwrap_or_default(),
            units.show(self.roller_radius_in, 4),
            units.show(self.prime_radius_in, 4),
            units.show(self.theoretical_min_displacement_radius_in, 4)
        );
        let _ = writeln!(
            out,
            "{:>8} {:>8} {:>11} {:>12} {:>10} {:>8} {:>10} {:>10} {:>8}",
            "deg",
            "points",
            "FPR thesis",
            "FPR envelope",
            "crit. 3",
            "rho_p",
            "crit. 1",
            "crit. 2",
            "rho_y"
        );
        let yn = |b: bool| if b { "yes" } else { "no" };
        for r in &self.rows {
            let _ = writeln!(
                out,
                "{:>8} {:>8} {:>11} {:>12} {:>10} {:>8} {:>10} {:>10} {:>8}",
                r.interval_deg,
                360 / r.interval_deg,
                range(&r.fpr_thesis),
                range(&r.fpr_envelope),
                yn(r.divides_program),
                units.show(r.min_pitch_radius_in, 3),
                yn(r.pitch_curvature_ok),
                yn(r.rms_ok),
                units.show(r.min_displacement_radius_in, 3)
            );
        }
        let _ = writeln!(
            out,
            "crit. 3: divides every period of the program; rho_p: smallest radius of curvature of the actual pitch curve, {unit} \
             (crit. 1 as read: rho_p >= roller radius); crit. 2: RMS deviation <= mean sigma; rho_y: smallest radius of \
             curvature of the actual displacement curve, {unit} (the second reading of crit. 1: rho_y >= roller radius)"
        );
        out
    }
}
