//! The text of `camsim tolerance-study`: each cell's per-period table, then the grid of
//! P(jump) and acceleration RMS, in the output's units.

use std::fmt::Write;

use super::report::{column_label, Cell, ToleranceReport};
use crate::report::Report;
use crate::units::{Units, ACCELERATION, FORCE, LENGTH, SPEED, STRESS, TORQUE};
use camsim_scene_file::units::Unit;

/// The columns of the per-cell table: (column, header, unit, decimals in inch; `None`:
/// scientific with three).
const TABLE: [(&str, &str, Unit, Option<usize>); 9] = [
    ("rms_displacement", "rms_y", LENGTH, None),
    ("rms_velocity", "rms_v", SPEED, None),
    ("rms_acceleration", "rms_a", ACCELERATION, None),
    ("torque_avg", "T_avg", TORQUE, Some(2)),
    ("torque_max", "T_max", TORQUE, Some(2)),
    ("torque_min", "T_min", TORQUE, Some(2)),
    ("contact_force_min", "Fc_min", FORCE, Some(2)),
    ("contact_force_max", "Fc_max", FORCE, Some(2)),
    ("contact_stress_max", "stress", STRESS, Some(0)),
];

impl Report for ToleranceReport {
    fn text(&self, units: Units) -> String {
        let mut out = String::new();
        header_text(&mut out, self, units);
        cell_text(
            &mut out,
            "theoretical cam (no tolerance)",
            &self.theoretical,
            units,
        );
        for c in &self.cells {
            let _ = writeln!(out);
            cell_text(&mut out, &cell_title(c, units), c, units);
        }
        grid_text(&mut out, self, units);
        let _ = writeln!(out, "\nrun time: {:.1} s", self.wall_s);
        out
    }
}

/// The study's first lines: the program, the model, the cams, and the units.
fn header_text(out: &mut String, r: &ToleranceReport, units: Units) {
    let _ = writeln!(
        out,
        "camsim tolerance-study (VI.4.1): {} rise, {} return at {:.1} rpm, {} model; revolution 2, mean of {} actual \
         cams per cell (seed {}, the same deviates in every cell)",
        r.program[0],
        r.program[1],
        r.rpm,
        if r.quick { "vertical (--quick)" } else { "full 11-DOF" },
        r.samples_per_cell,
        r.seed
    );
    let _ = writeln!(
        out,
        "units: rms_y {}, rms_v {}, rms_a {}, torque {}, force {}, stress {}\n",
        units.symbol(LENGTH),
        units.symbol(SPEED),
        units.label(ACCELERATION, "in/s2"),
        units.symbol(TORQUE),
        units.symbol(FORCE),
        units.symbol(STRESS)
    );
}

/// A cell's title: its tolerances, its waviness asked and its interval, and its
/// profiles.
fn cell_title(c: &Cell, units: Units) -> String {
    format!(
        "cam ±{} {lu}, roller ±{} {lu}, eccentricity ±{} {lu}, {}interval {:.4} deg{}",
        units.given(LENGTH, c.cam_tolerance_in.in_inch()),
        units.given(LENGTH, c.roller_tolerance_in.in_inch()),
        units.given(LENGTH, c.eccentricity_tolerance_in.in_inch()),
        c.target_fpr
            .map_or(String::new(), |f| format!("waviness asked FPR {f}, ")),
        c.interval_deg.unwrap_or(0.0),
        profile_text(c, units),
        lu = units.symbol(LENGTH)
    )
}

/// A cell's profiles: the waviness achieved and the RMS lift deviation (none when no
/// cam has statistics).
fn profile_text(c: &Cell, units: Units) -> String {
    let p = &c.summary.profile;
    match (p.get("fpr"), p.get("rms_deviation_in")) {
        (Some(f), Some(d)) => format!(
            ": FPR {:.1} (sd {:.1}), rms lift deviation {:.3e} {}",
            f.mean,
            f.sd,
            units.value(LENGTH, d.mean),
            units.symbol(LENGTH)
        ),
        _ => String::new(),
    }
}

/// A cell's acceleration RMS sum in the report's unit, or why it has none.
fn acc_text(c: &Cell, units: Units) -> String {
    match (&c.not_workable, c.acc_rms_sum_in_per_s2) {
        (Some(_), _) => "not workable".into(),
        (None, None) => "no statistics".into(),
        (None, Some(a)) => units.show(a, 0).to_string(),
    }
}

/// A cell under `title`: why it is not workable, or that it has no statistics, or its
/// per-period table with the revolution's acceleration RMS and P(jump).
fn cell_text(out: &mut String, title: &str, c: &Cell, units: Units) {
    let s = &c.summary;
    let _ = writeln!(out, "{title}");
    if let Some(why) = &c.not_workable {
        let _ = writeln!(
            out,
            "  not workable: each of its {} cams left the model's valid range with the follower on the cam (docs/MODEL.md §3.20; first: {why})",
            s.not_workable
        );
        return;
    }
    if s.samples == 0 {
        let _ = writeln!(
            out,
            "  jump anywhere {} of {}: p = {} (95 % Wilson interval); no statistics: every cam jumped and then left the model's valid range (docs/MODEL.md §3.20)",
            s.jump.count,
            s.left_range_jumps,
            s.jump.text(3)
        );
        return;
    }
    period_table(out, c, units);
    let acc = s.whole_revolution.get("acc_rms_sum");
    let _ = writeln!(
        out,
        "  sum of rms_a {:.4e} {} (sd {:.2e}), jump anywhere {} of {}: p = {} (95 % Wilson interval)",
        units.value(ACCELERATION, acc.map_or(0.0, |m| m.mean)),
        units.label(ACCELERATION, "in/s2"),
        units.value(ACCELERATION, acc.map_or(0.0, |m| m.sd)),
        s.jump.count,
        s.samples + s.left_range_jumps,
        s.jump.text(3)
    );
    if s.left_range_jumps + s.not_workable > 0 {
        let _ = writeln!(
            out,
            "  left the model's valid range: {} cams after the follower separated (jumps, without statistics), {} with the follower on the cam (not workable, excluded)",
            s.left_range_jumps, s.not_workable
        );
    }
}

/// A cell's per-period table: the means of [`TABLE`]'s columns and P(jump).
fn period_table(out: &mut String, c: &Cell, units: Units) {
    let _ = write!(out, "  {:<11}", "period");
    for (_, h, _, _) in TABLE {
        let _ = write!(out, " {:>10}", h);
    }
    let _ = writeln!(out, " {:>7}", "P(jump)");
    for p in &c.summary.periods {
        let _ = write!(out, "  {:<11}", p.period);
        for (col, _, unit, decimals) in TABLE {
            let m = p.columns.get(col).map_or(f64::NAN, |m| m.mean);
            match decimals {
                None => {
                    let _ = write!(out, " {:>10.3e}", units.value(unit, m));
                }
                Some(d) => {
                    let _ = write!(out, " {:>10}", units.q(unit, m, d));
                }
            }
        }
        let _ = writeln!(out, " {:>7.3}", p.jump.p);
    }
}

/// The summary grid: P(jump) with its interval and the acceleration RMS, a row per
/// tolerance, a column per waviness.
fn grid_text(out: &mut String, r: &ToleranceReport, units: Units) {
    let cols = r.columns.max(1);
    let _ = writeln!(
        out,
        "\nthe grid (revolution 2, {} cams a cell): P(jump) [95 % Wilson interval]; acceleration RMS summed over the periods, {} \
         (theoretical cam: {}, {}); columns: waviness asked (FPR achieved, mean)",
        r.samples_per_cell,
        units.label(ACCELERATION, "in/s2"),
        acc_text(&r.theoretical, units),
        if r.theoretical.summary.jump.count > 0 { "jumps" } else { "no jump" }
    );
    let _ = write!(out, "{:<28}", "cam / roller tolerance");
    for j in 0..cols.min(r.cells.len()) {
        let _ = write!(out, " {:>32}", column_label(&r.cells, cols, j));
    }
    let _ = writeln!(out);
    for row in r.cells.chunks(cols) {
        let Some(first) = row.first() else { continue };
        let _ = write!(
            out,
            "{:<28}",
            format!(
                "±{} / ±{} {}",
                units.given(LENGTH, first.cam_tolerance_in.in_inch()),
                units.given(LENGTH, first.roller_tolerance_in.in_inch()),
                units.symbol(LENGTH)
            )
        );
        for c in row {
            let _ = write!(
                out,
                " {:>32}",
                match c.not_workable {
                    Some(_) => "not workable".to_string(),
                    None => format!("{}; {}", c.summary.jump.text(2), acc_text(c, units)),
                }
            );
        }
        let _ = writeln!(out);
    }
}
