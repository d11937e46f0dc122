//! `camsim run`: simulate a scene (the built-in reference design by default) and
//! print the per-period table of every revolution, the jumps, the solver statistics
//! and the run time.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result};
use camsim_core::{MotionLaw, SegmentKind};
use serde_json::json;

use crate::sim::{self, RunSpec};
use crate::{csv, plot, scene};

/// The scene and its overrides, shared by `camsim run` and `camsim jump-speed`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (TOML, see `camsim scene --default`); the reference design if omitted.
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm (default 800).
    #[arg(long, allow_negative_numbers = true)]
    pub rpm: Option<f64>,
    /// Motion law of the rise(s) (names as in `camsim laws`).
    #[arg(long = "rise")]
    pub rise: Option<String>,
    /// Motion law of the return(s).
    #[arg(long = "return")]
    pub ret: Option<String>,
    /// Return spring rate K_rs, lb/in.
    #[arg(long, allow_negative_numbers = true)]
    pub spring_rate: Option<f64>,
    /// Spring length compressed at assembly δ_rs, in.
    #[arg(long, allow_negative_numbers = true)]
    pub preload_length: Option<f64>,
    /// Initial state: "thesis" (VI.1: speeds at 800 rpm, all else zero; the default of
    /// `run`) or "static" (static equilibrium under the preload and the steady drag; the
    /// default of `jump-speed`, whose steady state the thesis start's impact would pollute).
    #[arg(long, value_parser = ["thesis", "static"])]
    pub start: Option<String>,
    /// Solver relative tolerance.
    #[arg(long, allow_negative_numbers = true)]
    pub rtol: Option<f64>,
    /// Solver absolute tolerance for displacements, in.
    #[arg(long, allow_negative_numbers = true)]
    pub atol: Option<f64>,
}

/// Command-line options of `camsim run`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct Args {
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Revolutions to simulate (1-16; default 3, or the scene's).
    #[arg(long)]
    pub revolutions: Option<u32>,
    /// Write one CSV row per sample to FILE.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write PNG plots against cam angle into DIR.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
}

/// Parses a motion law name with a helpful error.
pub fn parse_law(name: &str, flag: &str) -> Result<MotionLaw> {
    MotionLaw::from_name(name).with_context(|| {
        let names: Vec<&str> = MotionLaw::ALL.iter().map(|l| l.name()).collect();
        format!(
            "{flag} {name:?}: unknown motion law (one of {})",
            names.join(", ")
        )
    })
}

/// Builds the run specification from the scene (or reference) and the overrides.
pub fn spec_from(args: &SceneArgs) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        anyhow::ensure!(
            r.is_finite() && r > 0.0,
            "--rpm {r}: must be positive and finite"
        );
        spec.design.set_speed_rpm(r)?;
    }
    if args.rise.is_some() || args.ret.is_some() {
        let rise = args
            .rise
            .as_deref()
            .map(|n| parse_law(n, "--rise"))
            .transpose()?;
        let ret = args
            .ret
            .as_deref()
            .map(|n| parse_law(n, "--return"))
            .transpose()?;
        let mut segs: Vec<_> = spec.design.program.segments().to_vec();
        for s in &mut segs {
            match (&mut s.kind, rise, ret) {
                (SegmentKind::Rise(l), Some(r), _) => *l = r,
                (SegmentKind::Return(l), _, Some(r)) => *l = r,
                _ => {}
            }
        }
        spec.design.program = camsim_core::CamProgram::new(&segs)?;
    }
    if let Some(k) = args.spring_rate {
        anyhow::ensure!(
            k.is_finite() && k > 0.0,
            "--spring-rate {k}: must be positive and finite (lb/in)"
        );
        spec.design.k_rs = k;
    }
    if let Some(d) = args.preload_length {
        anyhow::ensure!(
            d.is_finite() && d >= 0.0,
            "--preload-length {d}: must be zero or positive and finite (in)"
        );
        spec.design.delta_rs = d;
    }
    if let Some(s) = args.start.as_deref() {
        spec.solver.start = crate::scene::parse_start(s, "--start")?;
    }
    if let Some(x) = args.rtol {
        anyhow::ensure!(
            x.is_finite() && x > 0.0 && x < 1.0,
            "--rtol {x}: must be in (0, 1)"
        );
        spec.solver.rtol = x;
    }
    if let Some(x) = args.atol {
        anyhow::ensure!(
            x.is_finite() && x > 0.0,
            "--atol {x}: must be positive and finite (in)"
        );
        spec.solver.atol = x;
    }
    spec.design.validate()?;
    Ok(spec)
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    let mut spec = spec_from(&args.scene)?;
    if let Some(n) = args.revolutions {
        spec.revolutions = n;
    }
    let mut csv_out = match &args.csv {
        Some(p) => Some(csv::CsvWriter::create(p)?),
        None => None,
    };
    let mut plot_data = args.plot.as_ref().map(|_| plot::PlotData::default());
    let result = {
        let mut obs = |s: &camsim_core::Sample<f64>| {
            if let Some(c) = csv_out.as_mut() {
                c.row(s);
            }
            if let Some(p) = plot_data.as_mut() {
                p.push(s);
            }
            std::ops::ControlFlow::Continue(())
        };
        sim::run(&spec, &mut obs)?
    };
    if let Some(c) = csv_out {
        c.finish()?;
    }
    if let (Some(dir), Some(data)) = (&args.plot, plot_data) {
        plot::write_all(dir, &data, &result.stats.jumps())?;
    }
    let rows = sim::period_rows(&spec.design, &result.stats);
    let jumps = result.stats.jumps();
    let mut out = std::io::stdout().lock();
    if args.json {
        let v = json!({
            "per_period": rows,
            "jumps": jumps.iter().map(|j| json!({"revolution": j.revolution, "start_deg": j.start_deg, "end_deg": j.end_deg})).collect::<Vec<_>>(),
            "steps": result.solver.accepted,
            "rejected_steps": result.solver.rejected,
            "rhs_evals": result.solver.rhs_evals,
            "jumps_dropped": result.stats.jumps_dropped,
            "steady_state": sim::steady_check(&rows),
            "wall_ms": result.wall_ms,
            "preload_lb": result.preload,
            "rpm": camsim_core::rad_per_s_to_rpm(spec.design.omega0),
            "revolutions": spec.revolutions,
        });
        writeln!(out, "{}", serde_json::to_string_pretty(&v)?)?;
        return Ok(());
    }
    let rpm = camsim_core::rad_per_s_to_rpm(spec.design.omega0);
    writeln!(
        out,
        "camsim run: {} revolutions at {rpm:.1} rpm, {} DOF model, preload F_p = {:.3} lb",
        spec.revolutions, result.scene.dofs, result.preload
    )?;
    writeln!(
        out,
        "units: in, lb, s; torque lb in; stress psi; AORD = mean (omega - omega0)/omega0"
    )?;
    let mut last_rev = 0;
    for r in &rows {
        if r.revolution != last_rev {
            last_rev = r.revolution;
            writeln!(
                out,
                "\nrevolution {}{}",
                r.revolution,
                if r.revolution == 1 {
                    " (transient)"
                } else {
                    ""
                }
            )?;
            writeln!(
                out,
                "{:<11} {:>10} {:>10} {:>10} {:>9} {:>9} {:>9} {:>8} {:>8} {:>8} {:>9} {:>10} {:>10} {:>10} {:>5}",
                "period", "rms_y", "rms_v", "rms_a", "T_avg", "T_max", "T_min", "Fc_min", "Fc_max", "Fc_avg",
                "stress", "aord_m", "aord_cp", "aord_c", "jump"
            )?;
        }
        writeln!(
            out,
            "{:<11} {:>10.3e} {:>10.3e} {:>10.3e} {:>9.2} {:>9.2} {:>9.2} {:>8.2} {:>8.2} {:>8.2} {:>9.0} {:>10.3e} {:>10.3e} {:>10.3e} {:>5}",
            r.period, r.rms_displacement, r.rms_velocity, r.rms_acceleration, r.torque_avg, r.torque_max,
            r.torque_min, r.contact_force_min, r.contact_force_max, r.contact_force_avg, r.contact_stress_max,
            r.aord_motor, r.aord_coupling, r.aord_cam, if r.jump { "yes" } else { "no" }
        )?;
    }
    writeln!(out)?;
    if jumps.is_empty() {
        writeln!(out, "jumps: none (the follower stays on the cam)")?;
    } else {
        // Separations come in bursts (the roller bounces after landing): summarise each
        // revolution and period; --json and --csv keep every interval.
        writeln!(
            out,
            "jumps: {} separation intervals (every one in --json)",
            jumps.len()
        )?;
        let names = sim::period_names(&spec.design);
        let mut groups: Vec<(u32, usize, usize, f64, f64, f64)> = Vec::new();
        for j in &jumps {
            let seg = spec.design.program.segment_at(j.start_deg.to_radians());
            match groups.last_mut() {
                Some(g) if g.0 == j.revolution && g.1 == seg => {
                    g.2 += 1;
                    g.4 = j.end_deg;
                    g.5 += j.end_deg - j.start_deg;
                }
                _ => groups.push((
                    j.revolution,
                    seg,
                    1,
                    j.start_deg,
                    j.end_deg,
                    j.end_deg - j.start_deg,
                )),
            }
        }
        for (rev, seg, n, first, last, total) in groups {
            writeln!(
                out,
                "  revolution {rev}, {:<10}: {n:>4} intervals from {first:7.2} to {last:7.2} deg, {total:6.2} deg off the cam",
                names.get(seg).copied().unwrap_or("?")
            )?;
        }
        if result.stats.jumps_dropped > 0 {
            writeln!(
                out,
                "  ({} more intervals not recorded)",
                result.stats.jumps_dropped
            )?;
        }
    }
    if let Some(c) = sim::steady_check(&rows) {
        writeln!(
            out,
            "steady state: revolution {} vs {}: largest relative change of the per-period statistics {:.2e} ({}){}",
            c.compared[1],
            c.compared[0],
            c.max_rel_change,
            c.statistic,
            if c.max_rel_change > 0.01 { "  -- NOT steady (jumps make it irregular, or run more revolutions)" } else { "" }
        )?;
    }
    let s = &result.solver;
    writeln!(
        out,
        "solver: England adaptive RK, rtol {:e}, atol {:e} in: {} steps, {} rejected, {} rhs evaluations",
        spec.solver.rtol, spec.solver.atol, s.accepted, s.rejected, s.rhs_evals
    )?;
    writeln!(out, "run time: {:.1} ms", result.wall_ms)?;
    Ok(())
}
