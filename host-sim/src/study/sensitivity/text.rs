//! The report's text: the group tables of each cam, the cases that left the model's valid
//! range and `--per-key`'s ranked elasticities.

use super::outputs::OUTPUTS;
use super::per_key::PerKey;
use super::{Case, NotWorkableCase, SensitivityReport};
use crate::report::Report;
use crate::units::Units;

/// A change in % to one decimal with its sign, `0.0` without one when it rounds to zero
/// (`-0.0%` read as a decrease where there is none to the printed digit).
pub(crate) fn signed_pct_1(d: f64) -> String {
    let text = format!("{d:+.1}");
    if text == "+0.0" || text == "-0.0" {
        "0.0".to_string()
    } else {
        text
    }
}

/// The change of `v` from `base`, % (None when the baseline is 0).
pub(crate) fn pct(v: f64, base: f64) -> Option<f64> {
    (base != 0.0).then(|| 100.0 * (v / base - 1.0))
}

/// An output's value as a designer reads it: stress in whole psi, others with four
/// significant digits, in plain notation from 0.001 up.
/// The unit of output `i` of [`OUTPUTS`] (`None`: the cam speed's rad/s, the same in
/// either family).
pub(crate) fn output_unit(i: usize) -> Option<camsim_scene_file::units::Unit> {
    use crate::units::{ACCELERATION, LENGTH, SPEED, STRESS};
    match i {
        0 => Some(LENGTH),
        1 => Some(SPEED),
        2 => Some(ACCELERATION),
        4 => Some(STRESS),
        _ => None,
    }
}

/// The unit label of output `i` in `units`: the table's own (`in/s2`) in inch.
fn output_label(i: usize, units: Units) -> &'static str {
    let inch = OUTPUTS.get(i).map_or("", |o| o.2);
    output_unit(i).map_or(inch, |u| units.label(u, inch))
}

/// Output `i`'s value `v` (inch family) in `units`: four significant digits; the
/// stress to the psi in inch (to 0.01 MPa in SI).
pub(crate) fn fmt_value(i: usize, v: f64, units: Units) -> String {
    let unit = output_unit(i);
    let v = unit.map_or(v, |u| units.value(u, v));
    if i == 4 {
        let d = unit.map_or(0, |u| units.decimals(u, 0));
        return format!("{v:.d$}");
    }
    if v.abs() >= 1e4 {
        return format!("{v:.0}");
    }
    if v == 0.0 {
        return "0".to_string();
    }
    if v.abs() < 1e-3 {
        return format!("{v:.3e}");
    }
    let digits = (3 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.digits$}")
}

/// Output `i`'s cell: its value `v` in `units`, and its change from the baseline's `bv`
/// when there is one (`bv` not NaN, the baseline row none) and it is not zero.
fn cell(i: usize, v: f64, bv: f64, units: Units) -> String {
    match pct(v, bv).filter(|_| !bv.is_nan()) {
        Some(d) => format!("{} {:>6}%", fmt_value(i, v, units), signed_pct_1(d)),
        None => fmt_value(i, v, units),
    }
}

/// A cam's table rows of the cases that left the model's valid range, and a note when its
/// baseline did (`has_baseline` false).
fn left_range_rows(out: &mut String, cases: &[NotWorkableCase], cam: &str, has_baseline: bool) {
    use std::fmt::Write;
    for n in cases.iter().filter(|n| n.cam == cam) {
        let change = format!("{:+}", n.change_pct);
        let _ = writeln!(out, "  {:<10} {change:>5}%  {}", n.group, n.verdict());
    }
    if !has_baseline {
        let _ = writeln!(
            out,
            "  (its baseline left the model's valid range: the changes are not computed against it)"
        );
    }
}

/// The cases that left the model's valid range, each with the core's reason.
fn left_range_text(out: &mut String, cases: &[NotWorkableCase]) {
    use std::fmt::Write;
    if cases.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nleft the model's valid range (docs/MODEL.md §3.20; after a separation the case is a jump, as in `camsim jump-speed`):"
    );
    for n in cases {
        let _ = writeln!(out, "  {}: {}", n.name(), n.reason);
    }
}

impl Report for SensitivityReport {
    fn text(&self, units: Units) -> String {
        use std::fmt::Write;
        let mut out = String::new();
        let p = &self.actual_profile;
        let _ = writeln!(
            out,
            "camsim sensitivity (VI.4.3): every mass, every damper, every structural stiffness changed together, \
             at {:.1} rpm, {} model; revolution {} whole",
            self.rpm,
            if self.quick { "vertical (--quick)" } else { "full 11-DOF" },
            self.revolution
        );
        let _ = writeln!(
            out,
            "actual cam: sample 0 of seed {}, tolerances cam {} / roller {} / eccentricity {} {}, {} intervals \
             ({:.2} deg, {}), FPR {}; the same cam in every case",
            p.seed,
            units.given(crate::units::LENGTH, p.cam_tolerance_in.in_inch()),
            units.given(crate::units::LENGTH, p.roller_tolerance_in.in_inch()),
            units.given(crate::units::LENGTH, p.eccentricity_tolerance_in.in_inch()),
            units.symbol(crate::units::LENGTH),
            p.intervals,
            p.interval_deg,
            p.interval_source.name(),
            p.fpr
        );
        let _ = writeln!(
            out,
            "outputs: RMS deviations of the load from the theoretical response (displacement {}, velocity {}, \
             acceleration {}), RMS deviation of the cam speed from its nominal (rad/s), time-averaged Hertz \
             stress ({}); each case's value, then its change from the baseline",
            output_label(0, units),
            output_label(1, units),
            output_label(2, units),
            output_label(4, units)
        );
        for cam in ["theoretical", "actual"] {
            let b = self.baseline.iter().find(|c| c.cam == cam);
            let _ = writeln!(out, "\n{cam} cam");
            let _ = write!(out, "  {:<10} {:>6}", "group", "change");
            for (i, (_, h, _)) in OUTPUTS.iter().enumerate() {
                let _ = write!(out, " {:>19}", format!("{h} ({})", output_label(i, units)));
            }
            let _ = writeln!(out, "  jump");
            let row = |out: &mut String, c: &Case| {
                let _ = write!(
                    out,
                    "  {:<10} {:>5}%",
                    c.group,
                    format!("{:+}", c.change_pct)
                );
                let base = b.map_or([f64::NAN; 5], |b| b.outputs.values());
                for (i, (v, bv)) in c.outputs.values().into_iter().zip(base).enumerate() {
                    let bv = if c.group == "baseline" { f64::NAN } else { bv };
                    let _ = write!(out, " {:>19}", cell(i, v, bv, units));
                }
                let _ = writeln!(out, "  {}", if c.outputs.jump { "yes" } else { "no" });
            };
            if let Some(b) = b {
                row(&mut out, b);
            }
            for c in self.cases.iter().filter(|c| c.cam == cam) {
                row(&mut out, c);
            }
            left_range_rows(&mut out, &self.not_workable, cam, b.is_some());
        }
        left_range_text(&mut out, &self.not_workable);
        if let Some(pk) = &self.per_key {
            per_key_table(&mut out, pk, units);
        }
        let _ = writeln!(out, "\nrun time: {:.1} s", self.wall_s);
        out
    }
}

/// `--per-key`'s table: each key's elasticities, ranked, a not-workable key on a line of
/// its own.
fn per_key_table(out: &mut String, pk: &PerKey, units: Units) {
    use std::fmt::Write;
    let _ = writeln!(
            out,
            "\nelasticity d ln(output) / d ln(key), central differences at ±{} % on the theoretical cam; \
             jump onset {} (static start, resolution {} rpm); ranked by |onset elasticity|",
            pk.step * 100.0,
            pk.baseline_jump_onset_rpm
                .map_or("none up to 10 000 rpm".to_string(), |r| format!("{r:.2} rpm")),
            pk.onset_resolution_rpm
        );
    let _ = write!(out, "  {:>4} {:<42}", "rank", "key");
    for (_, h, _) in OUTPUTS {
        let _ = write!(out, " {h:>10}");
    }
    let _ = writeln!(out, " {:>10}", "onset");
    for (i, k) in pk.keys.iter().enumerate() {
        // The key under its name in `units` (an elasticity is the same in either).
        let key = crate::units::key_in(k.key, units).0;
        if let Some(n) = &k.not_workable {
            let _ = writeln!(out, "  {:>4} {key:<42} {}", "-", n.text());
            continue;
        }
        let _ = write!(out, "  {:>4} {:<42}", i + 1, key);
        for v in k.elasticity.values() {
            match v {
                Some(v) => {
                    let _ = write!(out, " {v:>10.4}");
                }
                None => {
                    let _ = write!(out, " {:>10}", "-");
                }
            }
        }
        let _ = writeln!(out);
    }
}
