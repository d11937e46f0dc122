//! The text of `camsim bench` ([`BenchReport`]'s): the reference run, the stability
//! limits, the table of runs, the costs at equal error and the legend, every error in
//! the output's family.

use std::fmt::Write;

use super::stability::StabilityLimit;
use super::{BenchReport, EqualError, ReferenceInfo, RunRow};
use crate::report::{sorted_pretty_json, Report};
use crate::units::{Units, ACCELERATION, FORCE, LENGTH};

/// `x` in 3 significant digits, scientific.
fn e3(x: f64) -> String {
    format!("{x:.2e}")
}

/// A displacement error in the output's family (`--units`), 3 significant digits.
fn disp_e(units: Units, x: f64) -> String {
    e3(units.value(LENGTH, x))
}

/// An acceleration error in the output's family, 3 significant digits.
fn acc_e(units: Units, x: f64) -> String {
    e3(units.value(ACCELERATION, x))
}

/// A force error in the output's family, 3 significant digits.
fn force_e(units: Units, x: f64) -> String {
    e3(units.value(FORCE, x))
}

/// A run's tolerance column: `h=T/n` for a fixed step, else its rtol.
fn tolerance(fixed_steps_per_rev: Option<u32>, rtol: f64) -> String {
    match fixed_steps_per_rev {
        Some(n) => format!("h=T/{n}"),
        None => format!("{rtol:.0e}"),
    }
}

impl Report for BenchReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self, units: Units) -> String {
        let mut s = String::new();
        heading(self, &mut s);
        reference(&self.reference, units, &mut s);
        stability(&self.stability, &mut s);
        runs_table(self, units, &mut s);
        equal_error_table(&self.equal_error, units, &mut s);
        legend(self, units, &mut s);
        s
    }
}

/// The first line: the scene, the revolutions, how errors and times are taken.
fn heading(b: &BenchReport, s: &mut String) {
    let _ = writeln!(
        s,
        "camsim bench{}: reference design at {} rpm, full 11-DOF scene (22 states), static start, {} revolutions;\n\
         errors over revolution 2 sampled every 0.5° of cam angle through each method's dense output; wall time: median of {}",
        if b.quick { " --quick" } else { "" },
        b.rpm,
        b.revolutions,
        b.repeat
    );
}

/// The reference run, its agreement with the confirming method, its signals and (when
/// measured) its jump onset, in the output's family (`--units`).
fn reference(r: &ReferenceInfo, units: Units, s: &mut String) {
    let (len, acc, lb) = (
        units.symbol(LENGTH),
        units.axis(ACCELERATION).1,
        units.symbol(FORCE),
    );
    // The reference's atol as set (1e-16 in, 2.54e-15 mm).
    let atol = match units {
        Units::Inch => format!("{:.0e}", r.atol_in),
        Units::Si => format!("{:e}", units.given(LENGTH, r.atol_in)),
    };
    let _ = writeln!(
        s,
        "reference: {} at rtol {:.0e} (atol {atol} {len}), {} steps; {} at the same tolerance differs by\n  \
         {} {len} (displacement RMS), {} {acc} (acceleration RMS), {} {lb} (smallest contact force);\n  \
         signal RMS {} {len} and {:.4e} {acc}, smallest contact force {} {lb}",
        r.method,
        r.rtol,
        r.steps,
        r.confirm_method,
        disp_e(units, r.agree_disp_rms),
        acc_e(units, r.agree_acc_rms),
        force_e(units, r.agree_force_min_lb),
        units.q(LENGTH, r.signal_disp_rms, 4),
        units.value(ACCELERATION, r.signal_acc_rms),
        units.q(FORCE, r.force_min_lb, 4)
    );
    if let Some(o) = r.jump_onset_rpm {
        let _ = writeln!(
            s,
            "  jump onset {o:.3} rpm ({}: {})",
            r.confirm_method,
            r.confirm_jump_onset_rpm
                .map_or("failed".to_string(), |c| format!("{c:.3} rpm"))
        );
    }
}

/// The Jacobian's eigenvalues along revolution 2 and the step limits they set.
fn stability(st: &StabilityLimit, s: &mut String) {
    let _ = writeln!(
        s,
        "stability (Jacobian eigenvalues at {} points of revolution 2): spectral radius {:.3e}-{:.3e} 1/s; stiffest\n  \
         λ = {:.4e} ± {:.4e}i (damping ratio {:.4}); stability boundary |hλ| along it: RK4 {:.3}, Dormand-Prince {:.3}\n  \
         (imaginary axis: {:.3}, {:.3}; Merson 4(3) {:.3}); fewest steps per revolution: England {:.0} double steps,\n  \
         RK4 {:.0} (at a fixed step {:.0}), Dormand-Prince {:.0}, Merson {:.0}; the stiffness cap's power iteration / eigenvalue radius {:.4}-{:.4}",
        st.points,
        st.rho_min,
        st.rho_max,
        st.stiffest_eigenvalue[0],
        st.stiffest_eigenvalue[1].abs(),
        st.stiffest_damping_ratio,
        st.rk4_boundary_at_stiffest,
        st.dopri5_boundary_at_stiffest,
        st.rk4_imaginary_boundary,
        st.dopri5_imaginary_boundary,
        st.merson_imaginary_boundary,
        st.england_double_steps_per_rev,
        st.rk4_steps_per_rev,
        st.rk4_fixed_steps_per_rev,
        st.dopri5_steps_per_rev,
        st.merson_steps_per_rev,
        st.power_over_eig_min,
        st.power_over_eig_max
    );
}

/// The table of runs (work, time and errors against the reference), then the failed runs.
fn runs_table(b: &BenchReport, units: Units, s: &mut String) {
    let _ = writeln!(
        s,
        "{:<19} {:<24} {:>9} {:>8} {:>6} {:>5} {:>9} {:>8} {:>7} {:>9} {:>9} {:>9} {:>9}",
        "method",
        "scene/precision",
        "rtol",
        "steps/r2",
        "xlimit",
        "rej%",
        "rhs evals",
        "wall ms",
        "cpu ms",
        "disp err",
        "acc err",
        "Fmin err",
        "onset err"
    );
    for run in &b.runs {
        run_row(run, b.onset_resolution_rpm, units, s);
    }
    for f in &b.failed {
        let _ = writeln!(
            s,
            "{:<19} {:<24} {:>9} {}",
            f.method,
            format!("{} {} {}", f.scene, f.precision, f.math),
            tolerance(f.fixed_steps_per_rev, f.rtol),
            f.status
        );
    }
}

/// One run's row; its onset error below `resolution` (rpm) reads `<resolution`.
fn run_row(run: &RunRow, resolution: f64, units: Units, s: &mut String) {
    let scene = if run.scene == "full_11dof" {
        format!("{} {}", run.precision, run.math)
    } else {
        run.scene.clone()
    };
    let ratio = run
        .steps_over_limit
        .map_or("-".to_string(), |r| format!("{r:.3}"));
    let onset = run.jump_onset_err_rpm.map_or("-".to_string(), |e| {
        if e < resolution {
            format!("<{resolution}")
        } else {
            format!("{e:.3}")
        }
    });
    let _ = writeln!(
        s,
        "{:<19} {:<24} {:>9} {:>8} {:>6} {:>5.1} {:>9} {:>8.1} {:>7} {:>9} {:>9} {:>9} {:>9}{}",
        run.method,
        scene,
        tolerance(run.fixed_steps_per_rev, run.rtol),
        run.steps_rev2,
        ratio,
        100.0 * run.rejected_fraction_rev2,
        run.rhs_evals,
        run.wall_ms,
        run.cpu_ms.map_or("-".to_string(), |c| format!("{c:.1}")),
        disp_e(units, run.err_disp_rms),
        acc_e(units, run.err_acc_rms),
        force_e(units, run.err_force_min_lb),
        onset,
        if run.contact_lost {
            "  (lost contact)"
        } else {
            ""
        }
    );
}

/// Each method's cost against Dormand-Prince's at equal acceleration error (nothing when
/// there is no such comparison).
fn equal_error_table(rows: &[EqualError], units: Units, s: &mut String) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "at equal acceleration error (Dormand-Prince's runs; the method interpolated along its best runs):"
    );
    let _ = writeln!(
        s,
        "  {:<19} {:<16} {:>9} {:>10} {:>12} {:>12} {:>11} {:>10} {:>9}",
        "method",
        "scene/precision",
        "peer rtol",
        "acc err",
        "peer evals",
        "evals",
        "evals ratio",
        "wall ratio",
        "cpu ratio"
    );
    for e in rows {
        let scene = if e.scene == "full_11dof" {
            "full"
        } else {
            "chip"
        };
        let _ = writeln!(
            s,
            "  {:<19} {:<16} {:>9.0e} {:>10} {:>12} {:>12.0} {:>11.3} {:>10} {:>9}",
            e.method,
            format!("{scene} {}", e.precision),
            e.peer_rtol,
            acc_e(units, e.err_acc_rms),
            e.peer_rhs_evals,
            e.rhs_evals,
            e.evals_ratio,
            e.wall_ratio.map_or("-".to_string(), |w| format!("{w:.3}")),
            e.cpu_ratio.map_or("-".to_string(), |w| format!("{w:.3}"))
        );
    }
}

/// What the columns mean, the fixed memory of the model and solvers, and the bench's own
/// time against its estimate.
fn legend(b: &BenchReport, units: Units, s: &mut String) {
    let (len, acc, lb) = (
        units.symbol(LENGTH),
        units.axis(ACCELERATION).1,
        units.symbol(FORCE),
    );
    let m = &b.memory;
    let _ = writeln!(
        s,
        "steps/r2: accepted steps in revolution 2 (England: double steps); xlimit: over the method's stability limit;\n\
         rej%: rejected of attempted steps in revolution 2; rhs evals, wall and CPU time (median): both revolutions;\n\
         disp err, acc err, Fmin err: revolution 2's RMS displacement and acceleration errors and its smallest contact\n\
         force's error against the reference, {len}, {acc}, {lb}; onset err: jump-onset speed against the reference's, rpm\n\
         memory (fixed, no heap in the core): model {} B and England solver {} B (f64, 22 states); model {} B and\n\
         solver {} B (f32, {} states, the chip's); bench {:.1} s (estimated {:.0} s from its reference run's {:.2} s)",
        m.model_f64_22_bytes,
        m.solver_f64_22_bytes,
        m.model_f32_chip_bytes,
        m.solver_f32_chip_bytes,
        m.chip_states,
        b.bench_seconds,
        b.estimated_seconds,
        b.reference_seconds
    );
}
