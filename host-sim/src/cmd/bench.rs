//! `camsim bench`: run time against error (the measurements are [`crate::bench`]'s).

use std::fmt::Write;

use anyhow::Result;

use crate::args::OutputArgs;
use crate::bench::{self, BenchReport, Options};
use crate::output::Plan;
use crate::report::{sorted_pretty_json, Report};

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
pub fn run(args: Args) -> Result<()> {
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
    crate::report::print(&report, args.output.json)
}

/// `x` in 3 significant digits, scientific.
fn e3(x: f64) -> String {
    format!("{x:.2e}")
}

impl Report for BenchReport {
    fn json(&self) -> serde_json::Result<String> {
        sorted_pretty_json(self)
    }

    fn text(&self) -> String {
        use crate::units::{axis, given, q, symbol, value, ACCELERATION, FORCE, LENGTH};
        let mut s = String::new();
        let r = &self.reference;
        // The errors and signals in the output's family (`--units`); the header names
        // the units of the error columns.
        let (len, acc, lb) = (symbol(LENGTH), axis(ACCELERATION).1, symbol(FORCE));
        let disp_e = |x: f64| e3(value(LENGTH, x));
        let acc_e = |x: f64| e3(value(ACCELERATION, x));
        let force_e = |x: f64| e3(value(FORCE, x));
        // The reference's atol as set (1e-16 in, 2.54e-15 mm).
        let atol = match crate::units::current() {
            crate::units::Units::Inch => format!("{:.0e}", r.atol_in),
            crate::units::Units::Si => format!("{:e}", given(LENGTH, r.atol_in)),
        };
        let st = &self.stability;
        let _ = writeln!(
            s,
            "camsim bench{}: reference design at {} rpm, full 11-DOF scene (22 states), static start, {} revolutions;\n\
             errors over revolution 2 sampled every 0.5° of cam angle through each method's dense output; wall time: median of {}",
            if self.quick { " --quick" } else { "" },
            self.rpm,
            self.revolutions,
            self.repeat
        );
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
        for run in &self.runs {
            let tol = match run.fixed_steps_per_rev {
                Some(n) => format!("h=T/{n}"),
                None => format!("{:.0e}", run.rtol),
            };
            let scene = if run.scene == "full_11dof" {
                format!("{} {}", run.precision, run.math)
            } else {
                run.scene.clone()
            };
            let ratio = run
                .steps_over_limit
                .map_or("-".to_string(), |r| format!("{r:.3}"));
            let onset = run.jump_onset_err_rpm.map_or("-".to_string(), |e| {
                if e < self.onset_resolution_rpm {
                    format!("<{}", self.onset_resolution_rpm)
                } else {
                    format!("{e:.3}")
                }
            });
            let _ = writeln!(
                s,
                "{:<19} {:<24} {:>9} {:>8} {:>6} {:>5.1} {:>9} {:>8.1} {:>7} {:>9} {:>9} {:>9} {:>9}{}",
                run.method,
                scene,
                tol,
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
        for f in &self.failed {
            let tol = match f.fixed_steps_per_rev {
                Some(n) => format!("h=T/{n}"),
                None => format!("{:.0e}", f.rtol),
            };
            let _ = writeln!(
                s,
                "{:<19} {:<24} {:>9} {}",
                f.method,
                format!("{} {} {}", f.scene, f.precision, f.math),
                tol,
                f.status
            );
        }
        if !self.equal_error.is_empty() {
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
            for e in &self.equal_error {
                let _ = writeln!(
                    s,
                    "  {:<19} {:<16} {:>9.0e} {:>10} {:>12} {:>12.0} {:>11.3} {:>10} {:>9}",
                    e.method,
                    format!(
                        "{} {}",
                        if e.scene == "full_11dof" {
                            "full"
                        } else {
                            "chip"
                        },
                        e.precision
                    ),
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
        let m = &self.memory;
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
            self.bench_seconds,
            self.estimated_seconds,
            self.reference_seconds
        );
        s
    }
}
