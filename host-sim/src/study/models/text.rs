//! The models study's text: what was run, the errors table and the verdicts.

use std::fmt::Write;

use super::{enough, scene_settings, ScenesReport, ROW_RTOLS};
use crate::report::{sorted_pretty_json, Report};
use crate::units::{Units, ACCELERATION, FORCE, LENGTH};

/// A stated value in at most 3 significant digits: `1` lb, `4.45` N.
fn short(x: f64) -> String {
    let v: f64 = format!("{x:.2e}").parse().unwrap_or(x);
    format!("{v}")
}

/// A stated tolerance in at most 3 significant digits, scientific: `1e-8` in,
/// `2.54e-7` mm.
fn short_e(x: f64) -> String {
    let v: f64 = format!("{x:.2e}").parse().unwrap_or(x);
    format!("{v:e}")
}

fn yes(b: bool) -> &'static str {
    if b {
        "yes"
    } else {
        "no"
    }
}

impl Report for ScenesReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self, units: Units) -> String {
        let acc = units.axis(ACCELERATION).1;
        let mut s = self.heading(units);
        self.error_table(&mut s, units);
        self.verdict_table(&mut s, units);
        let _ = writeln!(
            s,
            "model/solver: size_of in f64, bytes; steps/r: accepted double steps per revolution; limit/r: the fewest the scene's\n\
             Jacobian eigenvalues allow England (stiffest: largest spectral radius, 1/s); ms/2rev: the 2 revolutions of one\n\
             steady-state evaluation (the chip's pipeline; the model built beforehand), median; onset%: at the row's rtol; model%: the scene converged (rtol 1e-6), the model's own\n\
             error; the onset verdict needs both; acc err: RMS over revolution 2 every 0.5°, {acc}; {:.1} s in all",
            self.seconds
        );
        s
    }
}

impl ScenesReport {
    /// What was run, and the reference's values.
    fn heading(&self, units: Units) -> String {
        let mut s = String::new();
        let r = &self.reference;
        // Forces, lengths and accelerations in the output's family (`--units`).
        let (lb, acc) = (units.symbol(FORCE), units.axis(ACCELERATION).1);
        let _ = writeln!(
            s,
            "camsim models{}: the reference design at {} rpm, regulated drive, static start, 2 revolutions; every scene at\n\
             rtol 1e-3 (the chip's) and 1e-2, atol {} {}, largest step 1/100 revolution, England as `run` uses it; errors\n\
             against the full model at rtol {:.0e}: jump onset {:.2} rpm, smallest contact force {} {lb}, load acceleration\n\
             RMS {:.4e} {acc}",
            if self.quick { " --quick" } else { "" },
            self.rpm,
            short_e(units.value(LENGTH, scene_settings(ROW_RTOLS[0]).atol)),
            units.symbol(LENGTH),
            r.rtol,
            r.onset_rpm,
            units.show(r.fmin_lb, 3),
            units.of(r.acc_rms)
        );
        s
    }

    /// Each row's cost and its errors against the reference.
    fn error_table(&self, s: &mut String, units: Units) {
        let _ = writeln!(
            s,
            "{:<24} {:>5} {:>4} {:>3} {:>6} {:>6} {:>7} {:>5} {:>8} {:>7} {:>9} {:>7} {:>8} {:>8} {:>8} {:>8} {:>9} {:>8}",
            "scene", "rtol", "N", "dof", "model", "solver", "steps/r", "rej%", "evals/r", "ms/2rev", "stiffest", "limit/r",
            "onset", "onset%", "model%", "Fmin err", "timing°", "acc err"
        );
        for w in &self.rows {
            let _ = writeln!(
                s,
                "{:<24} {:>5.0e} {:>4} {:>3} {:>6} {:>6} {:>7.0} {:>5.1} {:>8.0} {:>7.2} {:>9.3e} {:>7.0} {:>8.2} {:>+8.3} {:>+8.3} {:>+8} {:>9.2e} {:>8.2e}",
                w.scene,
                w.rtol,
                w.states,
                w.dofs,
                w.model_bytes,
                w.solver_bytes,
                w.steps_per_rev,
                w.rejected_pct,
                w.rhs_evals_per_rev,
                w.ms_2rev,
                w.stiffest_rad_s,
                w.limit_steps_per_rev,
                w.onset_rpm,
                w.onset_err_pct,
                w.model_onset_err_pct,
                units.show(w.fmin_err_lb, 3),
                w.timing_err_deg,
                units.of(w.acc_rms_err)
            );
        }
    }

    /// Which rows are accurate enough, and their f32 bytes.
    fn verdict_table(&self, s: &mut String, units: Units) {
        let lb = units.symbol(FORCE);
        let _ = writeln!(
            s,
            "\naccurate enough for (onset within {:.0} %, Fmin within {} {lb}, timing within {}°, acceleration RMS error within {:.0} % of the signal):",
            100.0 * enough::ONSET_REL,
            short(units.value(FORCE, enough::FMIN_LB)),
            enough::TIMING_DEG,
            100.0 * enough::ACC_REL
        );
        let _ = writeln!(
            s,
            "{:<24} {:>5} {:>6} {:>6} {:>7} {:>13} {:>9}",
            "scene", "rtol", "onset", "Fmin", "timing", "acceleration", "f32 bytes"
        );
        for w in &self.rows {
            let _ = writeln!(
                s,
                "{:<24} {:>5.0e} {:>6} {:>6} {:>7} {:>13} {:>9}",
                w.scene,
                w.rtol,
                yes(w.ok_onset),
                yes(w.ok_fmin),
                yes(w.ok_timing),
                yes(w.ok_acc),
                w.model_f32_bytes + w.solver_f32_bytes
            );
        }
    }
}
