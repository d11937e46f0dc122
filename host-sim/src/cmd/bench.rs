//! `camsim bench`: run time against error (the measurements are [`crate::bench`]'s).

use std::fmt::Write;

use anyhow::Result;

use crate::args::OutputArgs;
use crate::bench::stability::StabilityLimit;
use crate::bench::{self, BenchReport, EqualError, Options, ReferenceInfo, RunRow};
use crate::output::Plan;
use crate::report::{sorted_pretty_json, Report};
use crate::units::{axis, given, q, symbol, value, ACCELERATION, FORCE, LENGTH};

/// Command-line options of `camsim bench`.
#[derive(clap::Args, Debug)]
#[command(mut_arg("json", |a| a.help("Print JSON: {\"runs\": [...], ...}")))]
#[command(mut_arg("plot", |a| a.help("Write error_vs_evals.png, error_vs_time.png and error_vs_cpu_time.png (log-log) into DIR (created if missing; its parent must exist; existing plots need --force)")))]
#[command(mut_arg("force", |a| a.help("Replace existing --plot files")))]
pub struct Args {
    /// Cam speed, rpm (500: the reference holds contact, so the errors are reproducible;
    /// at 800 and above it jumps and the impacts make the motion chaotic).
    #[arg(long, default_value_t = 500.0, allow_hyphen_values = true, value_parser = crate::args::rpm)]
    pub rpm: f64,
    /// A few points only (what CI runs): 3 tolerances in f64, one in f32, no jump onset.
    #[arg(long)]
    pub quick: bool,
    /// Timed repetitions of each run, the median reported [default: 5, 3 with --quick].
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::whole_u32::<1, 100>)]
    pub repeat: Option<u32>,
    /// Run a bench estimated (from its first, reference run) past 1 hour, which is
    /// otherwise refused (`camsim::bench::MAX_BENCH_SECONDS`).
    #[arg(long)]
    pub allow_long: bool,
    /// What it prints and draws.
    #[command(flatten)]
    pub output: OutputArgs,
}

/// Runs the command: the plot directory is checked before anything runs, written to
/// temporaries and committed when every plot was drawn.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    let mut plan = Plan::new(args.output.force);
    let plot_target = match &args.output.plot {
        Some(dir) => Some(plan.dir("--plot", dir, &bench::plot::FILES)?),
        None => None,
    };
    let opts = Options {
        rpm: args.rpm,
        quick: args.quick,
        repeat: args.repeat.unwrap_or(if args.quick { 3 } else { 5 }),
        onset: !args.quick,
        allow_long: args.allow_long,
        progress: true,
    };
    let report = bench::measure(&opts)?;
    if let Some(t) = plot_target {
        let mut out = t.open()?;
        bench::plot::draw_all(&mut out, &report)?;
        out.commit()?;
    }
    crate::report::print(&report, args.output.json, units)
}

/// `x` in 3 significant digits, scientific.
fn e3(x: f64) -> String {
    format!("{x:.2e}")
}

/// A displacement error in the output's family (`--units`), 3 significant digits.
fn disp_e(x: f64) -> String {
    e3(value(LENGTH, x))
}

/// An acceleration error in the output's family, 3 significant digits.
fn acc_e(x: f64) -> String {
    e3(value(ACCELERATION, x))
}

/// A force error in the output's family, 3 significant digits.
fn force_e(x: f64) -> String {
    e3(value(FORCE, x))
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

    fn text(&self, _units: crate::units::Units) -> String {
        let mut s = String::new();
        heading(self, &mut s);
        reference(&self.reference, &mut s);
        stability(&self.stability, &mut s);
        runs_table(self, &mut s);
        equal_error_table(&self.equal_error, &mut s);
        legend(self, &mut s);
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
fn reference(r: &ReferenceInfo, s: &mut String) {
    let (len, acc, lb) = (symbol(LENGTH), axis(ACCELERATION).1, symbol(FORCE));
    // The reference's atol as set (1e-16 in, 2.54e-15 mm).
    let atol = match crate::units::current() {
        crate::units::Units::Inch => format!("{:.0e}", r.atol_in),
        crate::units::Units::Si => format!("{:e}", given(LENGTH, r.atol_in)),
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
        disp_e(r.agree_disp_rms),
        acc_e(r.agree_acc_rms),
        force_e(r.agree_force_min_lb),
        q(LENGTH, r.signal_disp_rms, 4),
        value(ACCELERATION, r.signal_acc_rms),
        q(FORCE, r.force_min_lb, 4)
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
fn runs_table(b: &BenchReport, s: &mut String) {
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
        run_row(run, b.onset_resolution_rpm, s);
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
fn run_row(run: &RunRow, resolution: f64, s: &mut String) {
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
        disp_e(run.err_disp_rms),
        acc_e(run.err_acc_rms),
        force_e(run.err_force_min_lb),
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
fn equal_error_table(rows: &[EqualError], s: &mut String) {
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
            acc_e(e.err_acc_rms),
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
fn legend(b: &BenchReport, s: &mut String) {
    let (len, acc, lb) = (symbol(LENGTH), axis(ACCELERATION).1, symbol(FORCE));
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
