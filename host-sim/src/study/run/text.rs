//! The text of `camsim run`'s report: the heading and the verdict, the actual or measured
//! cam, each revolution's per-period table, the jumps, the steady state and the solver.

use crate::actual::ProfileStats;
use crate::report::{sorted_pretty_json, Report};
use crate::units::Units;

use super::{ProfileReport, RunReport};

/// The separations of one period of one revolution, as the text report sums them up.
struct JumpBurst {
    /// Revolution, from 1.
    revolution: u32,
    /// Index of the period in the program.
    period: usize,
    /// Separation intervals.
    intervals: usize,
    /// Cam angle of the first separation, degrees.
    first_onset_deg: f64,
    /// Cam angle of the last landing, degrees.
    last_landing_deg: f64,
    /// Degrees of cam angle off the cam, summed over the intervals.
    off_cam_deg: f64,
}

impl Report for RunReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self, units: Units) -> String {
        let mut out = String::new();
        self.write_heading(&mut out, units);
        if let Some(p) = &self.profile {
            p.write_lines(&mut out, units);
        }
        self.write_periods(&mut out, units);
        self.write_jumps(&mut out);
        self.write_steady_state(&mut out);
        self.write_solver(&mut out, units);
        out
    }
}

impl ProfileReport {
    /// The actual or measured cam's lines: what it is, its lift deviation and (measured)
    /// its waviness.
    fn write_lines(&self, out: &mut String, units: Units) {
        use std::fmt::Write;
        match self {
            ProfileReport::Actual(p) => write_actual_cam(p, out, units),
            ProfileReport::Measured(p) => {
                let _ = writeln!(
                    out,
                    "measured cam: column {}, {} points, {} deviation knots",
                    p.column.name(),
                    p.points,
                    p.deviation_knots
                );
            }
        }
        let _ = writeln!(out, "{}", self.deviation_line(units));
        if let ProfileReport::Measured(p) = self {
            let w = crate::measured::MeasuredWaviness::of(p);
            let _ = writeln!(out, "{}", w.line(units));
        }
    }

    /// The lift deviation's line: RMS, mean and largest |e|, RMS of d²e/dθ², and the FPR.
    fn deviation_line(&self, units: Units) -> String {
        use crate::units::{LENGTH, LENGTH_PER_RAD2};
        let (rms, mean, max, curv, fpr) = match self {
            ProfileReport::Actual(p) => (
                p.rms_deviation_in.in_inch(),
                p.mean_deviation_in.in_inch(),
                p.max_abs_deviation_in.in_inch(),
                p.rms_curvature_in_per_rad2.in_inch(),
                p.fpr,
            ),
            ProfileReport::Measured(p) => (
                p.rms_deviation_in,
                p.mean_deviation_in,
                p.max_abs_deviation_in,
                p.rms_curvature_in_per_rad2,
                p.fpr,
            ),
        };
        let (l, lu) = (|x| units.value(LENGTH, x), units.symbol(LENGTH));
        format!(
            "  lift deviation: rms {:.3e} {lu}, mean {:.3e} {lu}, max |e| {:.3e} {lu}, rms d2e/dtheta2 {:.3e} {}; FPR {fpr}",
            l(rms), l(mean), l(max), units.value(LENGTH_PER_RAD2, curv), units.symbol(LENGTH_PER_RAD2)
        )
    }
}

/// An actual cam's lines: how it was drawn (method, seed, tolerances, intervals) and,
/// for the envelope method, the roller and the rotation centre it was cut with.
fn write_actual_cam(p: &ProfileStats, out: &mut String, units: Units) {
    use crate::units::LENGTH;
    use std::fmt::Write;
    let lu = units.symbol(LENGTH);
    let _ = writeln!(
        out,
        "actual cam: {} method, seed {}, sample {}, {} normals; tolerances cam {} {lu}, roller {} {lu}, eccentricity {} {lu}; {} points every {:.4} deg ({})",
        p.method.name(), p.seed, p.sample, p.normal.name(), units.given(LENGTH, p.cam_tolerance_in.in_inch()),
        units.given(LENGTH, p.roller_tolerance_in.in_inch()), units.given(LENGTH, p.eccentricity_tolerance_in.in_inch()),
        p.intervals, p.interval_deg, p.interval_source.label(),
    );
    if let (Some(r), Some(c)) = (p.roller_radius_in, p.centre_offset_in) {
        let _ = writeln!(
            out,
            "  envelope: roller radius {} {lu}, rotation centre offset ({:.2e}, {:.2e}) {lu}, {} deviation knots",
            units.q(LENGTH, r.in_inch(), 6), units.value(LENGTH, c[0]), units.value(LENGTH, c[1]), p.deviation_knots
        );
    }
}

impl RunReport {
    /// The first line (revolutions, speed, model, preload) and the verdict.
    fn write_heading(&self, out: &mut String, units: Units) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "camsim run: {} revolutions at {:.1} rpm, {} DOF model, preload F_p = {} {}",
            self.revolutions,
            self.rpm,
            self.dofs,
            units.show(self.preload_lb, 3),
            units.unit_of(self.preload_lb)
        );
        if let Some(v) = &self.verdict {
            let _ = writeln!(out, "{}", crate::verdict::text(v, units));
        }
    }

    /// The units line, then each revolution's per-period table, then a blank line.
    fn write_periods(&self, out: &mut String, units: Units) {
        use crate::units as u;
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "units: {}, {}, s; torque {}; stress {}; AORD = mean (omega - omega0)/omega0",
            units.symbol(u::LENGTH),
            units.symbol(u::FORCE),
            units.symbol(u::TORQUE),
            units.symbol(u::STRESS)
        );
        let mut last_rev = 0;
        for r in &self.per_period {
            if r.revolution != last_rev {
                last_rev = r.revolution;
                let transient = if r.revolution == 1 {
                    " (transient)"
                } else {
                    ""
                };
                let _ = writeln!(out, "\nrevolution {}{transient}", r.revolution);
                let _ = writeln!(
                    out,
                    "{:<11} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>10} {:>10} {:>10} {:>5}",
                    "period", "rms_y", "rms_v", "rms_a", "T_avg", "T_max", "T_min", "Fc_min", "Fc_max", "Fc_avg",
                    "stress", "aord_m", "aord_cp", "aord_c", "jump"
                );
            }
            // Torques and forces print as 0.00, not -0.00, where they round to zero.
            let (t, f) = (|x| units.show(x, 2), |x| units.show(x, 2));
            let _ = writeln!(
                out,
                "{:<11} {:>10.3e} {:>10.3e} {:>10.3e} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>10.3e} {:>10.3e} {:>10.3e} {:>5}",
                r.period, units.of(r.rms_displacement), units.of(r.rms_velocity),
                units.of(r.rms_acceleration), t(r.torque_avg), t(r.torque_max),
                t(r.torque_min), f(r.contact_force_min), f(r.contact_force_max), f(r.contact_force_avg),
                units.show(r.contact_stress_max, 0),
                r.aord_motor, r.aord_coupling, r.aord_cam, if r.jump { "yes" } else { "no" }
            );
        }
        let _ = writeln!(out);
    }

    /// The steady-state line: the verdict's when it judged one, else the comparison of
    /// the last two revolutions (none with one revolution).
    fn write_steady_state(&self, out: &mut String) {
        use std::fmt::Write;
        match (&self.verdict, &self.steady_state) {
            (
                Some(crate::verdict::Verdict {
                    steady: Some(st), ..
                }),
                _,
            ) => {
                let _ = writeln!(out, "steady state: {}", st.summary);
            }
            (_, Some(c)) => {
                let _ = writeln!(
                    out,
                    "steady state: revolution {} vs {}: largest relative change of the per-period statistics {:.2e} ({})",
                    c.compared[1], c.compared[0], c.max_rel_change, c.statistic
                );
            }
            _ => {}
        }
    }

    /// The solver's line (method, tolerances, work), the run time and the files written.
    fn write_solver(&self, out: &mut String, units: Units) {
        use std::fmt::Write;
        let _ = writeln!(
            out,
            "solver: {} adaptive RK, rtol {:e}, atol {:e} {}: {} steps, {} rejected, {} rhs evaluations",
            method_title(self.method), self.rtol, units.given(crate::units::LENGTH, self.atol_in.in_inch()), units.symbol(crate::units::LENGTH), self.steps, self.rejected_steps, self.rhs_evals
        );
        let _ = writeln!(out, "run time: {:.1} ms", self.wall_ms);
        for f in &self.files {
            let _ = writeln!(out, "wrote {f}");
        }
    }
}

impl RunReport {
    /// The jumps' lines: none, or one summary line per burst of separations.
    fn write_jumps(&self, out: &mut String) {
        use std::fmt::Write;
        if self.jumps.is_empty() {
            let _ = writeln!(out, "jumps: none (the follower stays on the cam)");
        } else {
            // Separations come in bursts (the roller bounces after landing): summarise each
            // revolution and period; --json and --csv keep every interval.
            let _ = writeln!(
                out,
                "jumps: {} separation intervals (every one in --json)",
                self.jumps.len()
            );
            let mut groups: Vec<JumpBurst> = Vec::new();
            for j in &self.jumps {
                match groups.last_mut() {
                    Some(g) if g.revolution == j.revolution && g.period == j.period => {
                        g.intervals += 1;
                        g.last_landing_deg = j.end_deg;
                        g.off_cam_deg += j.end_deg - j.start_deg;
                    }
                    _ => groups.push(JumpBurst {
                        revolution: j.revolution,
                        period: j.period,
                        intervals: 1,
                        first_onset_deg: j.start_deg,
                        last_landing_deg: j.end_deg,
                        off_cam_deg: j.end_deg - j.start_deg,
                    }),
                }
            }
            for g in groups {
                let _ = writeln!(
                out,
                "  revolution {}, {:<10}: {:>4} intervals from {:7.2} to {:7.2} deg, {:6.2} deg off the cam",
                g.revolution,
                self.periods.get(g.period).copied().unwrap_or("?"),
                g.intervals,
                g.first_onset_deg,
                g.last_landing_deg,
                g.off_cam_deg
            );
            }
            if self.jumps_dropped > 0 {
                let _ = writeln!(
                    out,
                    "  ({} more intervals not recorded)",
                    self.jumps_dropped
                );
            }
        }
    }
}

/// The solver line's name of a method (`solver.method`): "England" as before.
fn method_title(name: &str) -> &str {
    match name {
        "england" => "England",
        "merson" => "Merson 4(3)",
        "dormand-prince" => "Dormand-Prince 5(4)",
        other => other,
    }
}
