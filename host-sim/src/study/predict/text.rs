//! `camsim predict`'s text: the scene, the table with its jump onset and interpolation
//! checks, then every reading in order with the alarm after it, forces in the output's
//! family.

use std::fmt::Write;

use super::report::{FaultRow, PredictReport, SampleRow};
use super::REFERENCE_SCENE;
use crate::units::{Force, Units, FORCE};

/// A row's speed margin as the text prints it: rpm, or "none (no onset)" when it is absent.
fn margin_text(s: &SampleRow) -> String {
    s.speed_margin_rpm.map_or_else(
        || "none (no onset)".to_string(),
        |m| format!("{:>8.2} rpm", m.0),
    )
}

/// The human-readable output, forces in `units`.
pub fn render_text(r: &PredictReport, units: Units) -> String {
    let mut out = String::new();
    write_table(r, units, &mut out);
    write_readings(r, units, &mut out);
    out
}

/// The scene, the prediction table (force and timing errors by speed), its jump onset
/// and the interpolation checks, forces in the output's family (`--units`).
fn write_table(r: &PredictReport, units: Units, out: &mut String) {
    // Forces in the output's family (`--units`), 4 decimals of a pound.
    let lb = units.symbol(FORCE);
    let force = |v: Force| units.show(v, 4);
    let sc = &r.scene;
    let name = if sc.design == REFERENCE_SCENE {
        "reference design"
    } else {
        &sc.design
    };
    let _ = writeln!(
        out,
        "predictor scene: {name}, {} states ({}), {}",
        sc.states, sc.dofs, r.precision
    );
    if let (Some(f), Some(k)) = (&sc.measured, sc.measured_knots) {
        let _ = writeln!(out, "measured profile: {f} ({k} deviation knots)");
    }
    let _ = writeln!(
        out,
        "{:>8} {:>12} {:>7}  timing error, deg (rise 10/50/90 %, return 10/50/90 %)",
        "rpm",
        format!("min F, {lb}"),
        "jumped"
    );
    for row in &r.table {
        let t: Vec<String> = row
            .timing_deg
            .iter()
            .map(|v| format!("{:+.4}", v.0))
            .collect();
        let _ = writeln!(
            out,
            "{:>8.1} {:>12} {:>7}  {}",
            row.rpm.0,
            force(row.min_force_lb),
            row.jumped,
            t.join(" ")
        );
    }
    let _ = match r.jump_rpm {
        Some(j) => writeln!(out, "jump onset: {:.3} rpm", j.0),
        None => writeln!(out, "jump onset: none up to {} rpm", sc.max_rpm),
    };
    for c in &r.interp_checks {
        let _ = writeln!(
            out,
            "interpolation check at {:.0} rpm: force {} (interp) vs {} (direct) {lb}, |err| {} {lb}; max timing |err| {:.5} deg",
            c.rpm.0, force(c.interp_force_lb), force(c.direct_force_lb), force(c.abs_err_force_lb), c.max_abs_err_timing_deg
        );
    }
}

/// Every reading in order: the vouched ones with their prediction, the others named;
/// each with the alarm after it, marked where it turns on or off.
fn write_readings(r: &PredictReport, units: Units, out: &mut String) {
    let mut prev = true;
    let (mut si, mut fi) = (r.samples.iter().peekable(), r.faults.iter().peekable());
    loop {
        let (line, alarm) = match (si.peek(), fi.peek()) {
            (Some(s), f) if f.is_none_or(|f| s.reading < f.reading) => {
                let a = (sample_text(s, units), s.alarm);
                si.next();
                a
            }
            (_, Some(f)) => {
                let a = (fault_text(f), f.alarm);
                fi.next();
                a
            }
            (None, None) => break,
            // Unreachable: the first arm takes a sample whenever no fault is left.
            (Some(_), None) => break,
        };
        let mark = match (alarm != prev, alarm) {
            (true, true) => "  <- alarm ON",
            (true, false) => "  <- alarm OFF",
            _ => "",
        };
        prev = alarm;
        let _ = writeln!(
            out,
            "{line}, alarm {}{mark}",
            if alarm { "on" } else { "off" }
        );
    }
}

/// A vouched reading: its speed, the force and speed margins and the timing errors at
/// half rise and half return.
fn sample_text(s: &SampleRow, units: Units) -> String {
    format!(
        "speed {:>6.1} rpm: force margin {:>9} {}, speed margin {}, timing rise50 {:+.4} return50 {:+.4} deg",
        s.rpm.0,
        units.show(s.force_margin_lb, 4),
        units.symbol(FORCE),
        margin_text(s),
        s.timing_deg[1].0,
        s.timing_deg[4].0,
    )
}

/// Any other reading, named for the machine's operator.
fn fault_text(f: &FaultRow) -> String {
    match f.kind {
        "out_of_range" => format!(
            "speed {:.1} rpm outside the table's grid: not extrapolated",
            f.rpm.map_or(f64::NAN, |n| n.0)
        ),
        "too_short" => format!(
            "pulse rejected: {} ticks, faster than the machine's limit (noise or bounce)",
            f.period_ticks.unwrap_or(0)
        ),
        "bounce" => format!(
            "pulse rejected: {} ticks, a bounce",
            f.period_ticks.unwrap_or(0)
        ),
        "step" => format!(
            "period rejected: {} ticks, a missed pulse or a step",
            f.period_ticks.unwrap_or(0)
        ),
        "lost" => "speed lost: no index pulse".to_string(),
        "acquiring" => "acquiring the speed".to_string(),
        other => other.to_string(),
    }
}

impl crate::report::Report for PredictReport {
    fn text(&self, units: Units) -> String {
        render_text(self, units)
    }
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }
}
