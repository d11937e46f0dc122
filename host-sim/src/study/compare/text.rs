//! The text of [`CompareReport`]: the heading, the acceleration RMS tables, the inertial
//! responses, the ranks and the laws not workable, in the output's units.

use std::fmt::Write;

use super::{CompareReport, LawStudy, NotWorkable};
use crate::report::Report;
use crate::units::{self, Units};

/// Column headers of the ranking table.
pub const HEADERS: [(&str, &str); 9] = [
    ("sensitivity_to_flexibility", "S_flex"),
    ("sensitivity_to_tolerance", "S_tol"),
    ("shock_index", "shock"),
    ("torque_avg", "T_avg"),
    ("torque_max", "T_max"),
    ("contact_force_min", "Fc_min"),
    ("contact_force_max", "Fc_max"),
    ("contact_stress_max", "stress"),
    ("overall", "overall"),
];

impl Report for CompareReport {
    fn text(&self, units: Units) -> String {
        let mut out = String::new();
        self.write_heading(&mut out, units);
        self.write_acceleration(&mut out, units);
        self.write_inertial(&mut out, units);
        self.write_ranks(&mut out);
        not_workable_text(&mut out, &self.not_workable);
        let _ = writeln!(out, "\nrun time: {:.2} s", self.wall_s);
        out
    }
}

impl CompareReport {
    /// The first lines: the study (speed, model, cycles), the actual cam it drew and the
    /// units of the tables.
    fn write_heading(&self, out: &mut String, units: Units) {
        let _ = writeln!(
            out,
            "camsim compare: every motion law for rise and return at {:.1} rpm, {} model; cycle I = revolution 1 \
             (thesis start), cycle II = revolution 2",
            self.rpm,
            if self.quick { "vertical (--quick)" } else { "full 11-DOF" }
        );
        if let Some(l) = self.laws.first() {
            let p = &l.actual.profile;
            let _ = writeln!(
                out,
                "actual cam: sample 0 of seed {}, tolerances cam {} / roller {} / eccentricity {} {}, {} intervals ({:.4} deg, {}); FPR {}",
                self.seed,
                units.given(units::LENGTH, p.cam_tolerance_in.in_inch()),
                units.given(units::LENGTH, p.roller_tolerance_in.in_inch()),
                units.given(units::LENGTH, p.eccentricity_tolerance_in.in_inch()),
                units.symbol(units::LENGTH),
                p.intervals, p.interval_deg,
                self.interval_source.label(),
                self.fpr_range()
            );
        }
        let _ = writeln!(
            out,
            "units: acceleration RMS {}, torque {}, force {}, stress {} (docs/MODEL.md §9 defines each measure)\n",
            units.label(units::ACCELERATION, "in/s2"),
            units.symbol(units::TORQUE),
            units.symbol(units::FORCE),
            units.symbol(units::STRESS)
        );
    }

    /// The actual cams' FPR: one number, or its range when it differs by law.
    fn fpr_range(&self) -> String {
        let (lo, hi) = self.laws.iter().fold((usize::MAX, 0), |(a, b), l| {
            (a.min(l.actual.profile.fpr), b.max(l.actual.profile.fpr))
        });
        if lo == hi {
            format!("{lo}")
        } else {
            format!("{lo}-{hi} (by law)")
        }
    }

    /// The acceleration RMS of each law's periods, cycles I and II, on the theoretical
    /// cam and on the actual one, with its sensitivity, shock index and jumps.
    fn write_acceleration(&self, out: &mut String, units: Units) {
        let periods: Vec<String> = self
            .laws
            .first()
            .map(|l| {
                l.flexibility
                    .per_period
                    .iter()
                    .map(|p| p.period.clone())
                    .collect()
            })
            .unwrap_or_default();
        for (title, actual) in [
            ("theoretical cam (flexibility alone): acceleration RMS per period, cycle I / cycle II", false),
            ("actual cam (flexibility and tolerance): acceleration RMS per period, cycle I / cycle II", true),
        ] {
            let _ = writeln!(out, "{title}");
            let _ = write!(out, "{:<21}", "law");
            for p in &periods {
                let _ = write!(out, " {:>21}", p);
            }
            let _ = writeln!(
                out,
                " {:>10} {:>7} {:>6}",
                if actual { "S_act" } else { "S_flex" },
                "shock",
                "jumps"
            );
            for l in &self.laws {
                acceleration_row(out, l, actual, units);
            }
            let _ = writeln!(out);
        }
    }

    /// The ranks of each law on every measure and overall, best first, with its jumps.
    fn write_ranks(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "ranks (1 = best; S_tol and the jumps on the actual cam, the rest on the theoretical cam; Fc_min larger is better;\n\
             overall: the laws holding contact on the theoretical cam first, then by the sum of the ranks)"
        );
        let _ = write!(out, "{:<21}", "law");
        for (_, h) in HEADERS {
            let _ = write!(out, " {:>7}", h);
        }
        let _ = writeln!(out, " {:>11}", "jump r/ret");
        let mut order: Vec<&LawStudy> = self.laws.iter().collect();
        order.sort_by_key(|l| l.ranks.overall);
        for l in order {
            let _ = write!(out, "{:<21}", l.name);
            for (c, _) in HEADERS {
                let _ = write!(out, " {:>7}", l.ranks.get(c).unwrap_or(0));
            }
            let yn = |b: bool| if b { "yes" } else { "no" };
            let _ = writeln!(
                out,
                " {:>11}",
                format!("{}/{}", yn(l.jump_rise), yn(l.jump_return))
            );
        }
    }

    /// The inertial responses' tables, cycle II, on the theoretical and the actual cam.
    fn write_inertial(&self, out: &mut String, units: Units) {
        for (title, actual) in [
            ("inertial responses, cycle II, theoretical cam", false),
            ("inertial responses, cycle II, actual cam", true),
        ] {
            let _ = writeln!(out, "{title}");
            let _ = writeln!(
                out,
                "{:<21} {:>9} {:>9} {:>9} {:>8} {:>8} {:>9}",
                "law", "T_avg_r", "T_avg_ret", "|T|_max", "Fc_min", "Fc_max", "stress"
            );
            for l in &self.laws {
                let c = if actual {
                    &l.actual.cam
                } else {
                    &l.flexibility
                };
                let _ = writeln!(
                    out,
                    "{:<21} {:>9} {:>9} {:>9} {:>8} {:>8} {:>9}",
                    l.name,
                    units.show(c.torque_avg_rise, 2),
                    units.show(c.torque_avg_return, 2),
                    units.show(c.torque_max, 2),
                    units.show(c.contact_force_min, 2),
                    units.show(c.contact_force_max, 2),
                    units.show(c.contact_stress_max, 0)
                );
            }
            let _ = writeln!(out);
        }
    }
}

/// One law's row of the acceleration table: cycle I / cycle II of every period on the
/// theoretical (or the `actual`) cam, its sensitivity, shock index and jumps.
fn acceleration_row(out: &mut String, l: &LawStudy, actual: bool, units: Units) {
    let c = if actual {
        &l.actual.cam
    } else {
        &l.flexibility
    };
    let _ = write!(out, "{:<21}", l.name);
    for p in &c.per_period {
        let _ = write!(
            out,
            " {:>10}/{:<10}",
            units.show(p.acc_rms_cycle1, 1),
            units.show(p.acc_rms_cycle2, 1)
        );
    }
    let jumps: String = c
        .per_period
        .iter()
        .map(|p| if p.jump { 'J' } else { '-' })
        .collect();
    let _ = writeln!(
        out,
        " {:>10} {:>7.3} {:>6}",
        units.q(units::ACCELERATION, c.sensitivity, 1),
        c.shock_index,
        jumps
    );
}

/// The laws not ranked, each with the reason its run stopped.
fn not_workable_text(out: &mut String, laws: &[NotWorkable]) {
    if laws.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        "\nnot workable (the run left the model's valid range, docs/MODEL.md §3.20; not ranked):"
    );
    for n in laws {
        let _ = writeln!(out, "{:<21} on the {} cam: {}", n.name, n.cam, n.reason);
    }
}
