//! `camsim predict [--f32] [--json] [--check-log FILE]`: the firmware's cam-timing and
//! jump predictor run on the host with the same scene (the `camsim-chip` crate),
//! the same scripted speed profile and the same core code: the boot-time table, the
//! interpolation check, the prediction and the alarm state for every speed sample.
//!
//! With `--f32` it computes in `f32` exactly as the chip does (same libm code, no FMA
//! contraction in Rust, IEEE single precision on both SSE and the M4F's FPU) and can
//! check the firmware's decoded defmt log bit for bit (`--check-log`): every line of the
//! log starting with `parity ` must equal the host's line at the same position.

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use serde_json::{json, Value};

use camsim_chip::{
    chip_alarm, chip_design, chip_prediction_table, chip_solver_settings, chip_steady_state,
    ChipScene, ScriptedProfile, CHIP_ALARM_OFF_MARGIN_RPM, CHIP_ALARM_ON_MARGIN_RPM,
    CHIP_CHECK_RPM, CHIP_GRID, CHIP_GRID_RPM, CHIP_MAX_RPM, CHIP_RESOLUTION_RPM, CHIP_STATES,
};
use camsim_core::{Real, Scene, SpeedPrediction, SpeedSource, SteadyState};

/// Command-line options of `camsim predict`.
#[derive(clap::Args, Debug, Default)]
pub struct Args {
    /// Compute in f32 like the firmware (default: f64).
    #[arg(long = "f32")]
    pub single: bool,
    /// Print JSON (with the raw f32 bit patterns under --f32).
    #[arg(long)]
    pub json: bool,
    /// Decoded defmt log of the firmware to check bit for bit (needs --f32).
    #[arg(long)]
    pub check_log: Option<PathBuf>,
    /// Scene file compiled into the firmware (`camsim scene --rust FILE`); default: the
    /// reference design (`camsim_chip::chip_design`).
    #[arg(long)]
    pub scene: Option<PathBuf>,
}

/// One direct simulation between grid points against the interpolated prediction.
#[derive(Clone, Copy, Debug)]
pub struct InterpCheck<T> {
    /// Speed, rpm.
    pub rpm: T,
    /// The table's interpolated prediction.
    pub interpolated: SpeedPrediction<T>,
    /// The model run directly at this speed.
    pub direct: SteadyState<T>,
}

/// One speed sample of the scripted profile and what the predictor said.
#[derive(Clone, Copy, Debug)]
pub struct SampleOut<T> {
    /// The prediction.
    pub prediction: SpeedPrediction<T>,
    /// Alarm state after this sample.
    pub alarm: bool,
}

/// Everything the predictor computes for the chip's scene.
#[derive(Clone, Debug)]
pub struct Prediction<T> {
    /// The boot-time table.
    pub table: camsim_core::PredictionTable<T, CHIP_GRID>,
    /// The interpolation checks at `CHIP_CHECK_RPM`.
    pub checks: Vec<InterpCheck<T>>,
    /// The scripted profile's samples.
    pub samples: Vec<SampleOut<T>>,
}

/// Runs the chip's predictor (shared scene, scripted profile) in `T` for the reference
/// design, or for a design record (a scene file compiled in with `camsim scene --rust`):
/// `Design::from_record` is the same conversion the firmware makes, so the bits agree.
pub fn compute<T: Real>(record: Option<&camsim_core::DesignRecord>) -> Result<Prediction<T>> {
    let design = match record {
        Some(r) => {
            camsim_core::Design::<T>::from_record(r).map_err(|e| anyhow::anyhow!("scene: {e}"))?
        }
        None => chip_design::<T>(),
    };
    let table =
        chip_prediction_table(&design).map_err(|e| anyhow::anyhow!("table build: {e:?}"))?;
    let mut checks = Vec::new();
    for r in CHIP_CHECK_RPM {
        let rpm = T::from_f64(r);
        let direct = chip_steady_state(&design, rpm)
            .map_err(|e| anyhow::anyhow!("direct run at {r} rpm: {e:?}"))?;
        checks.push(InterpCheck {
            rpm,
            interpolated: table.predict(rpm),
            direct,
        });
    }
    let mut alarm = chip_alarm::<T>().map_err(|e| anyhow::anyhow!("alarm: {e:?}"))?;
    let mut profile = ScriptedProfile::new();
    let mut samples = Vec::new();
    while let Some(rpm) = SpeedSource::<T>::next_rpm(&mut profile) {
        let prediction = table.predict(rpm);
        let on = alarm.update(prediction.speed_margin_rpm);
        samples.push(SampleOut {
            prediction,
            alarm: on,
        });
    }
    Ok(Prediction {
        table,
        checks,
        samples,
    })
}

fn hex(x: f32) -> String {
    format!("{:#010x}", x.to_bits())
}

fn timing_hex(t: &[f32; 6]) -> String {
    t.iter().map(|v| hex(*v)).collect::<Vec<_>>().join(",")
}

/// The `parity ...` lines the firmware prints, in its order, from the host's f32 run.
pub fn parity_lines(p: &Prediction<f32>) -> Vec<String> {
    let mut out = Vec::new();
    for (i, (rpm, s)) in p.table.rpm.iter().zip(p.table.at.iter()).enumerate() {
        out.push(format!(
            "parity table i={i} rpm={} force={} jumped={} timing={}",
            hex(*rpm),
            hex(s.min_contact_force),
            s.jumped,
            timing_hex(&s.timing_deg)
        ));
    }
    out.push(match p.table.jump_rpm {
        Some(j) => format!("parity jump rpm={}", hex(j)),
        None => "parity jump rpm=none".to_string(),
    });
    for c in &p.checks {
        out.push(format!(
            "parity check rpm={} force={} jumped={} timing={}",
            hex(c.rpm),
            hex(c.direct.min_contact_force),
            c.direct.jumped,
            timing_hex(&c.direct.timing_deg)
        ));
    }
    for (i, s) in p.samples.iter().enumerate() {
        let q = &s.prediction;
        out.push(format!(
            "parity sample i={i} rpm={} force={} speed={} alarm={} timing={}",
            hex(q.rpm),
            hex(q.force_margin_lb),
            hex(q.speed_margin_rpm),
            s.alarm,
            timing_hex(&q.timing_deg)
        ));
    }
    out
}

/// The `parity ...` lines of a decoded firmware log (text from `parity ` to the line end).
pub fn log_parity_lines(log: &str) -> Vec<String> {
    log.lines()
        .filter_map(|l| l.find("parity ").map(|i| l[i..].trim_end().to_string()))
        .collect()
}

/// Compares the firmware's parity lines with the host's; Err names the first difference.
pub fn check_parity(log: &str, host: &[String]) -> Result<usize> {
    let fw = log_parity_lines(log);
    for (k, (f, h)) in fw.iter().zip(host.iter()).enumerate() {
        if f != h {
            bail!(
                "parity mismatch at parity line {} of {}: firmware `{f}` != host `{h}`",
                k + 1,
                host.len()
            );
        }
    }
    if fw.len() != host.len() {
        bail!(
            "parity: the firmware log has {} parity lines, the host {}",
            fw.len(),
            host.len()
        );
    }
    Ok(fw.len())
}

fn f(x: impl Real) -> Value {
    let v = x.to_f64();
    if v.is_finite() {
        json!(v)
    } else if v.is_nan() {
        Value::Null
    } else {
        json!(if v > 0.0 { "inf" } else { "-inf" })
    }
}

fn bits_of<T: Real>(x: T, single: bool) -> Value {
    if single {
        json!(format!("{:#010x}", (x.to_f64() as f32).to_bits()))
    } else {
        json!(format!("{:#018x}", x.to_f64().to_bits()))
    }
}

fn timing_json<T: Real>(t: &[T; 6], single: bool) -> (Value, Value) {
    (
        Value::Array(t.iter().map(|v| f(*v)).collect()),
        Value::Array(t.iter().map(|v| bits_of(*v, single)).collect()),
    )
}

fn to_json<T: Real>(p: &Prediction<T>, single: bool) -> Value {
    let table: Vec<Value> = p
        .table
        .rpm
        .iter()
        .zip(p.table.at.iter())
        .map(|(r, s)| {
            let (t, tb) = timing_json(&s.timing_deg, single);
            json!({"rpm": f(*r), "min_force_lb": f(s.min_contact_force), "min_force_deg": f(s.min_force_deg),
                   "jumped": s.jumped, "timing_deg": t,
                   "bits": {"rpm": bits_of(*r, single), "min_force_lb": bits_of(s.min_contact_force, single), "timing_deg": tb}})
        })
        .collect();
    let checks: Vec<Value> = p
        .checks
        .iter()
        .map(|c| {
            let mut dt = 0.0f64;
            for (a, b) in c.interpolated.timing_deg.iter().zip(c.direct.timing_deg.iter()) {
                dt = dt.max((a.to_f64() - b.to_f64()).abs());
            }
            let (t, tb) = timing_json(&c.direct.timing_deg, single);
            json!({"rpm": f(c.rpm), "interp_force_lb": f(c.interpolated.force_margin_lb),
                   "direct_force_lb": f(c.direct.min_contact_force), "direct_jumped": c.direct.jumped,
                   "abs_err_force_lb": (c.interpolated.force_margin_lb.to_f64() - c.direct.min_contact_force.to_f64()).abs(),
                   "max_abs_err_timing_deg": dt, "direct_timing_deg": t,
                   "bits": {"direct_force_lb": bits_of(c.direct.min_contact_force, single), "direct_timing_deg": tb}})
        })
        .collect();
    let mut prev = false;
    let mut transitions = Vec::new();
    let samples: Vec<Value> = p
        .samples
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let q = &s.prediction;
            if s.alarm != prev {
                transitions.push(json!({"sample": i, "rpm": f(q.rpm), "alarm": s.alarm}));
                prev = s.alarm;
            }
            let (t, tb) = timing_json(&q.timing_deg, single);
            json!({"rpm": f(q.rpm), "force_margin_lb": f(q.force_margin_lb), "speed_margin_rpm": f(q.speed_margin_rpm),
                   "in_grid": q.in_grid, "alarm": s.alarm, "timing_deg": t,
                   "bits": {"force_margin_lb": bits_of(q.force_margin_lb, single),
                            "speed_margin_rpm": bits_of(q.speed_margin_rpm, single), "timing_deg": tb}})
        })
        .collect();
    let s = chip_solver_settings::<f64>();
    json!({
        "precision": if single { "f32" } else { "f64" },
        "scene": {"design": "reference", "states": CHIP_STATES, "dofs": <ChipScene as Scene>::DOFS.name(), "rtol": s.rtol, "atol_in": s.atol,
                  "max_step_fraction": s.max_step_fraction, "grid_rpm": CHIP_GRID_RPM.to_vec(), "max_rpm": CHIP_MAX_RPM,
                  "resolution_rpm": CHIP_RESOLUTION_RPM, "alarm_on_margin_rpm": CHIP_ALARM_ON_MARGIN_RPM,
                  "alarm_off_margin_rpm": CHIP_ALARM_OFF_MARGIN_RPM},
        "jump_rpm": p.table.jump_rpm.map(f),
        "jump_rpm_bits": p.table.jump_rpm.map(|j| bits_of(j, single)),
        "table": table,
        "interp_checks": checks,
        "samples": samples,
        "alarm_transitions": transitions,
    })
}

fn print_text<T: Real>(p: &Prediction<T>, precision: &str) {
    println!(
        "predictor scene: reference design, {CHIP_STATES} states ({}), {precision}",
        <ChipScene as Scene>::DOFS.name()
    );
    println!(
        "{:>8} {:>12} {:>7}  timing error, deg (rise 10/50/90 %, return 10/50/90 %)",
        "rpm", "min F, lb", "jumped"
    );
    for (r, s) in p.table.rpm.iter().zip(p.table.at.iter()) {
        let t: Vec<String> = s
            .timing_deg
            .iter()
            .map(|v| format!("{:+.4}", v.to_f64()))
            .collect();
        println!(
            "{:>8.1} {:>12.4} {:>7}  {}",
            r.to_f64(),
            s.min_contact_force.to_f64(),
            s.jumped,
            t.join(" ")
        );
    }
    match p.table.jump_rpm {
        Some(j) => println!("jump onset: {:.3} rpm", j.to_f64()),
        None => println!("jump onset: none up to {CHIP_MAX_RPM} rpm"),
    }
    for c in &p.checks {
        let mut dt = 0.0f64;
        for (a, b) in c
            .interpolated
            .timing_deg
            .iter()
            .zip(c.direct.timing_deg.iter())
        {
            dt = dt.max((a.to_f64() - b.to_f64()).abs());
        }
        println!(
            "interpolation check at {:.0} rpm: force {:.4} (interp) vs {:.4} (direct) lb, |err| {:.4} lb; max timing |err| {:.5} deg",
            c.rpm.to_f64(),
            c.interpolated.force_margin_lb.to_f64(),
            c.direct.min_contact_force.to_f64(),
            (c.interpolated.force_margin_lb.to_f64() - c.direct.min_contact_force.to_f64()).abs(),
            dt
        );
    }
    let mut prev = false;
    for s in &p.samples {
        let q = &s.prediction;
        let mark = if s.alarm != prev {
            if s.alarm {
                "  <- alarm ON"
            } else {
                "  <- alarm OFF"
            }
        } else {
            ""
        };
        prev = s.alarm;
        println!(
            "speed {:>6.1} rpm: force margin {:>9.4} lb, speed margin {:>8.2} rpm, timing rise50 {:+.4} return50 {:+.4} deg, alarm {}{}",
            q.rpm.to_f64(),
            q.force_margin_lb.to_f64(),
            q.speed_margin_rpm.to_f64(),
            q.timing_deg[1].to_f64(),
            q.timing_deg[4].to_f64(),
            if s.alarm { "on" } else { "off" },
            mark
        );
    }
}

/// Runs the command.
pub fn run(args: Args) -> Result<()> {
    if args.check_log.is_some() && !args.single {
        bail!("--check-log compares the firmware's f32 bits: add --f32");
    }
    let record = match &args.scene {
        Some(p) => Some(crate::scene::load(p)?.design.to_record()),
        None => None,
    };
    if args.single {
        let p = compute::<f32>(record.as_ref())?;
        if let Some(path) = &args.check_log {
            let log = std::fs::read_to_string(path)
                .with_context(|| format!("reading {}", path.display()))?;
            let n = check_parity(&log, &parity_lines(&p))?;
            println!("parity OK: {n} lines (table, jump onset, interpolation checks, every sample) bit-identical");
            return Ok(());
        }
        if args.json {
            println!("{}", to_json(&p, true));
        } else {
            print_text(&p, "f32");
        }
    } else {
        let p = compute::<f64>(record.as_ref())?;
        if args.json {
            println!("{}", to_json(&p, false));
        } else {
            print_text(&p, "f64");
        }
    }
    Ok(())
}
