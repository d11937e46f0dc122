//! `camsim predict [--f32] [--json] [--check-log FILE]`: the firmware's cam-timing and
//! jump predictor run on the host with the same scene (the `camsim-chip` crate), the
//! same scripted machine (`CHIP_SCRIPT`'s index pulses through the chip's `ChipMonitor`,
//! as the QEMU image feeds them) and the same core code: the boot-time table, the
//! interpolation check, and for every speed reading (a vouched speed, or a fault: out of
//! the grid, a rejected pulse, the speed lost, an acquisition) the prediction and the
//! alarm state.
//!
//! With `--f32` it computes in `f32` exactly as the chip does (same libm code, no FMA
//! contraction in Rust, IEEE single precision on both SSE and the M4F's FPU) and can
//! check the firmware's decoded defmt log bit for bit (`--check-log`): every line of the
//! log starting with `parity ` must equal the host's line at the same position.
//!
//! With `--measured FILE.csv` the roller rides on a measured cam profile, as the firmware
//! built with `CAMSIM_PROFILE=FILE.csv` does: the same reader
//! (`camsim_scene_file::measured`, at most `CHIP_PROFILE_MAX_KNOTS - 1` rows), the same
//! deviation knots on the scene's `f64` design, narrowed to `T` and splined by
//! `DeviatedLift::refit_periodic`, the chip's `ChipDeviation`.

use std::path::PathBuf;

use crate::measured::MeasuredProfile;
use anyhow::{bail, Result};
use serde::Serialize;

use camsim_chip::{
    chip_design, chip_design_from, chip_solver_settings, ChipConfig, ChipDeviation, ChipMonitor,
    ChipScene, ChipStep, ChipTable, ParityLine, ScriptedPulseTrain, CHIP_ALARM_OFF_MARGIN_RPM,
    CHIP_ALARM_ON_MARGIN_RPM, CHIP_CHECK_RPM, CHIP_GRID, CHIP_GRID_RPM, CHIP_MAX_RPM,
    CHIP_PROFILE_MAX_KNOTS, CHIP_RESOLUTION_RPM, CHIP_STATES, CHIP_TICK_HZ,
};
use camsim_core::{
    Design, LiftProfile, Real, Scene, SpeedPrediction, SpeedReading, SteadyState, TheoreticalLift,
};

/// Command-line options of `camsim predict`.
#[derive(clap::Args, Debug, Default)]
pub struct Args {
    /// Compute in f32 like the firmware (default: f64).
    #[arg(long = "f32")]
    pub single: bool,
    /// Print JSON (with the raw f32 bit patterns under --f32).
    #[arg(long)]
    pub json: bool,
    /// Decoded defmt log of the firmware to check bit for bit (needs --f32; at most
    /// 16 MB read).
    #[arg(long, requires = "single")]
    pub check_log: Option<PathBuf>,
    /// Scene file compiled into the firmware (`CAMSIM_SCENE=FILE` at its build), positional
    /// like `run`'s; default: the reference design (`camsim_chip::chip_design`).
    #[arg(value_name = "SCENE")]
    pub scene_file: Option<PathBuf>,
    /// The scene file as an option (the same as the positional SCENE).
    #[arg(long, value_name = "SCENE", conflicts_with = "scene_file")]
    pub scene: Option<PathBuf>,
    /// Measured cam profile compiled into the firmware (`CAMSIM_PROFILE=FILE.csv` at its
    /// build; the CSV of `camsim run --measured`, at most 720 rows); default: the
    /// theoretical cam.
    #[arg(long)]
    pub measured: Option<PathBuf>,
}

/// A measured profile's deviation knots as the chip carries them, in `f64` before the
/// narrowing (`camsim_scene_file::measured::Measured::deviation_knots`).
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileKnots {
    /// Knots, rad: one revolution, the closing knot included.
    pub knots_rad: Vec<f64>,
    /// Deviation at the knots, in (the last repeats the first).
    pub values_in: Vec<f64>,
}

impl ProfileKnots {
    /// Reads a measured file as the firmware's build script does (`CAMSIM_PROFILE`): at
    /// most [`CHIP_PROFILE_MAX_KNOTS`] − 1 rows, the deviation on `design` (the scene's,
    /// in f64), at most [`CHIP_PROFILE_MAX_KNOTS`] knots.
    pub fn load(path: &std::path::Path, design: &Design<f64>) -> Result<Self> {
        let m = camsim_scene_file::measured::load_limited(path, CHIP_PROFILE_MAX_KNOTS - 1)
            .map_err(anyhow::Error::msg)?;
        let (knots_rad, values_in) = m
            .deviation_knots(design)
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        if knots_rad.len() > CHIP_PROFILE_MAX_KNOTS {
            bail!(
                "{}: the deviation has {} knots, more than the chip's {CHIP_PROFILE_MAX_KNOTS} (a radius profile's envelope has 8 a row)",
                path.display(),
                knots_rad.len()
            );
        }
        Ok(Self {
            knots_rad,
            values_in,
        })
    }
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

/// Everything the predictor computes for the chip's scene.
#[derive(Clone, Debug)]
pub struct Prediction<T> {
    /// The boot-time table.
    pub table: camsim_core::PredictionTable<T, CHIP_GRID>,
    /// The interpolation checks at `CHIP_CHECK_RPM`.
    pub checks: Vec<InterpCheck<T>>,
    /// Every speed reading of the scripted machine, in order, with the prediction (at a
    /// vouched speed) and the alarm state after it.
    pub samples: Vec<ChipStep<T>>,
}

/// Runs the chip's predictor (shared scene, scripted machine) in `T` for the reference
/// design, or for a scene file's design (`Design<f64>`, as the firmware's build script
/// reads `CAMSIM_SCENE`): `camsim_chip::chip_design_from` is the conversion the
/// firmware's image carries, so the bits agree.
pub fn compute<T: Real>(
    scene: Option<&Design<f64>>,
    profile: Option<&ProfileKnots>,
) -> Result<Prediction<T>> {
    let design = match scene {
        Some(d) => chip_design_from::<T>(d).map_err(|e| {
            let why = camsim_scene_file::refusal("design", e);
            anyhow::anyhow!("scene in {}: {why}", std::any::type_name::<T>())
        })?,
        None => chip_design::<T>(),
    };
    match profile {
        None => compute_on(&design, TheoreticalLift),
        Some(k) => {
            // The firmware's narrowing (build.rs) and spline (boot): the same calls.
            let knots: Vec<T> = k.knots_rad.iter().map(|x| T::from_f64(*x)).collect();
            let values: Vec<T> = k.values_in.iter().map(|x| T::from_f64(*x)).collect();
            let mut dev = Box::new(ChipDeviation::<T, CHIP_PROFILE_MAX_KNOTS>::EMPTY);
            dev.refit_periodic(&knots, &values).map_err(|e| {
                anyhow::anyhow!(
                    "the measured profile in {}: {e}",
                    std::any::type_name::<T>()
                )
            })?;
            compute_on(&design, &*dev)
        }
    }
}

/// [`compute`] for a design whose roller rides on `profile`.
fn compute_on<T: Real, P: LiftProfile<T> + Copy>(
    design: &Design<T>,
    profile: P,
) -> Result<Prediction<T>> {
    // The lift table the firmware's build script fills into the chip's flash
    // (camsim_chip::ChipConfig::tabulate).
    let mut lift_table = Box::new(ChipTable::<T>::EMPTY);
    let chip = ChipConfig::new(design)
        .on(profile)
        .tabulate(&mut lift_table)
        .map_err(|e| anyhow::anyhow!("the lift table (built into the chip's flash): {e}"))?;
    let table = chip
        .prediction_table()
        .map_err(|e| anyhow::anyhow!("the predictor's table (at boot on the chip): {e}"))?;
    let mut checks = Vec::new();
    for r in CHIP_CHECK_RPM {
        let rpm = T::from_f64(r);
        let direct = chip
            .steady_state(rpm)
            .map_err(|e| anyhow::anyhow!("the interpolation check's direct run at {r} rpm: {e}"))?;
        checks.push(InterpCheck {
            rpm,
            interpolated: table.predict(rpm),
            direct,
        });
    }
    // The firmware's loop (src/bin/predictor.rs): the same train, monitor and steps.
    let mut monitor =
        ChipMonitor::<T>::new(CHIP_TICK_HZ).map_err(|e| anyhow::anyhow!("the monitor: {e}"))?;
    let mut train = ScriptedPulseTrain::chip();
    let mut samples = Vec::new();
    while !train.finished() {
        if let Some(step) = monitor.step(&table, &mut train) {
            samples.push(step);
        }
    }
    Ok(Prediction {
        table,
        checks,
        samples,
    })
}

/// The `parity ...` lines the firmware prints, in its order, from the host's f32 run
/// (the text of [`ParityLine`], the type the firmware logs with defmt).
pub fn parity_lines(p: &Prediction<f32>) -> Vec<String> {
    let mut out = Vec::new();
    for (i, (rpm, s)) in p.table.rpm.iter().zip(p.table.at.iter()).enumerate() {
        out.push(ParityLine::table(i as u32, *rpm, s));
    }
    out.push(ParityLine::jump(p.table.jump_rpm));
    for c in &p.checks {
        out.push(ParityLine::check(c.rpm, &c.direct));
    }
    for (i, s) in p.samples.iter().enumerate() {
        let i = i as u32;
        out.push(match &s.prediction {
            Some(q) => ParityLine::sample(i, q, s.alarm),
            None => ParityLine::reading(i, &s.reading, s.alarm),
        });
    }
    out.iter().map(ParityLine::to_string).collect()
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

/// A number of the report, the `f64` it is. A report is printed only when every number in
/// it is finite (`ensure_reached`, `report::ensure_finite`), so no `null` reaches the output;
/// a value that does not exist (the speed margin with no jump onset) is an absent field
/// with its reason, never an infinity. The text output formats the `f64` itself.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Num(pub f64);

impl Num {
    fn of(x: impl Real) -> Self {
        Num(x.to_f64())
    }
}

impl Serialize for Num {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_f64(self.0)
    }
}

/// The raw bits of a value as computed: `0x` + 8 hex digits under `--f32`, 16 under f64.
fn bits_of<T: Real>(x: T, single: bool) -> String {
    if single {
        format!("{:#010x}", (x.to_f64() as f32).to_bits())
    } else {
        format!("{:#018x}", x.to_f64().to_bits())
    }
}

/// The scene the predictor ran and its fixed configuration (`camsim-chip`).
#[derive(Clone, Debug, Serialize)]
pub struct SceneReport {
    /// The scene file given with `--scene`, or "reference" (the reference design).
    pub design: String,
    /// The measured profile given with `--measured` (absent: the theoretical cam).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured: Option<String>,
    /// Knots of its deviation spline (the closing knot included).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured_knots: Option<usize>,
    /// State size of the chip's model.
    pub states: usize,
    /// Degrees of freedom of the chip's scene.
    pub dofs: &'static str,
    /// Solver relative tolerance.
    pub rtol: f64,
    /// Solver absolute tolerance, in.
    pub atol_in: f64,
    /// Largest step, fraction of a revolution.
    pub max_step_fraction: f64,
    /// Step control (the chip's choice, `"thesis"`: England's rule, uncapped).
    pub step_control: &'static str,
    /// Grid speeds of the table, rpm.
    pub grid_rpm: [f64; CHIP_GRID],
    /// Upper limit of the jump search, rpm.
    pub max_rpm: f64,
    /// Resolution of the jump-onset bisection, rpm.
    pub resolution_rpm: f64,
    /// Alarm-on speed margin, rpm.
    pub alarm_on_margin_rpm: f64,
    /// Alarm-off speed margin, rpm.
    pub alarm_off_margin_rpm: f64,
}

/// Raw bits of a table row.
#[derive(Clone, Debug, Serialize)]
pub struct TableBits {
    /// Grid speed.
    pub rpm: String,
    /// Smallest contact force.
    pub min_force_lb: String,
    /// Timing errors.
    pub timing_deg: [String; 6],
}

/// One grid speed of the boot-time table.
#[derive(Clone, Debug, Serialize)]
pub struct TableRow {
    /// Grid speed, rpm.
    pub rpm: Num,
    /// Smallest contact force in revolution 2, lb.
    pub min_force_lb: Num,
    /// Its cam angle, degrees.
    pub min_force_deg: Num,
    /// Whether the follower separated.
    pub jumped: bool,
    /// Timing errors (rise 10/50/90 %, return 10/50/90 %), degrees.
    pub timing_deg: [Num; 6],
    /// The same as raw bits.
    pub bits: TableBits,
}

/// Raw bits of an interpolation check.
#[derive(Clone, Debug, Serialize)]
pub struct CheckBits {
    /// Direct smallest contact force.
    pub direct_force_lb: String,
    /// Direct timing errors.
    pub direct_timing_deg: [String; 6],
}

/// One interpolation check: the table's prediction against a direct simulation.
#[derive(Clone, Debug, Serialize)]
pub struct CheckRow {
    /// Speed, rpm.
    pub rpm: Num,
    /// Interpolated smallest contact force, lb.
    pub interp_force_lb: Num,
    /// Directly simulated smallest contact force, lb.
    pub direct_force_lb: Num,
    /// Whether the direct run separated.
    pub direct_jumped: bool,
    /// |interpolated − direct| force, lb.
    pub abs_err_force_lb: f64,
    /// Largest |interpolated − direct| timing error, degrees.
    pub max_abs_err_timing_deg: f64,
    /// Direct timing errors, degrees.
    pub direct_timing_deg: [Num; 6],
    /// The direct values as raw bits.
    pub bits: CheckBits,
}

/// Raw bits of a sample's prediction.
#[derive(Clone, Debug, Serialize)]
pub struct SampleBits {
    /// Force margin.
    pub force_margin_lb: String,
    /// Speed margin.
    pub speed_margin_rpm: String,
    /// Timing errors.
    pub timing_deg: [String; 6],
}

/// A vouched speed reading of the scripted machine and the prediction for it.
#[derive(Clone, Debug, Serialize)]
pub struct SampleRow {
    /// Index of the reading (among all readings, faults included).
    pub reading: usize,
    /// Measured speed, rpm.
    pub rpm: Num,
    /// Interpolated smallest contact force, lb.
    pub force_margin_lb: Num,
    /// Jump-onset speed minus the measured speed, rpm (absent when no jump onset was found
    /// up to the search limit: `speed_margin_absent` says so).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_margin_rpm: Option<Num>,
    /// Why `speed_margin_rpm` is absent.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_margin_absent: Option<String>,
    /// Whether the speed lies on the grid.
    pub in_grid: bool,
    /// Alarm state after this sample.
    pub alarm: bool,
    /// Interpolated timing errors, degrees.
    pub timing_deg: [Num; 6],
    /// The prediction as raw bits.
    pub bits: SampleBits,
}

/// A reading that does not vouch for the speed: the predictor makes no prediction and
/// asserts the alarm.
#[derive(Clone, Debug, Serialize)]
pub struct FaultRow {
    /// Index of the reading (among all readings).
    pub reading: usize,
    /// What it is: `out_of_range`, `too_short`, `bounce`, `step`, `lost`, `acquiring`,
    /// `overrun` (`camsim_core::SpeedReading::kind`).
    pub kind: &'static str,
    /// The measured speed of an `out_of_range` reading, rpm.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Num>,
    /// The period of a rejected pulse, ticks of the 1 MHz capture timer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub period_ticks: Option<u32>,
    /// Alarm state after this reading.
    pub alarm: bool,
}

/// A reading at which the alarm switched.
#[derive(Clone, Debug, Serialize)]
pub struct AlarmTransition {
    /// Index of the reading.
    pub reading: usize,
    /// What it is (`camsim_core::SpeedReading::kind`).
    pub kind: &'static str,
    /// Its speed, rpm, if it measured one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rpm: Option<Num>,
    /// The new alarm state (true: asserted).
    pub alarm: bool,
}

/// What `camsim predict` prints: the text output and `--json` are both this report.
#[derive(Clone, Debug, Serialize)]
pub struct PredictReport {
    /// "f32" or "f64".
    pub precision: &'static str,
    /// The scene run and the chip's configuration.
    pub scene: SceneReport,
    /// Jump-onset speed, rpm (absent: none up to the search limit).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm: Option<Num>,
    /// Its raw bits (absent with it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jump_rpm_bits: Option<String>,
    /// The boot-time table.
    pub table: Vec<TableRow>,
    /// The interpolation checks.
    pub interp_checks: Vec<CheckRow>,
    /// Every vouched reading of the scripted machine with its prediction.
    pub samples: Vec<SampleRow>,
    /// Every other reading (faults and acquisitions): no prediction, alarm asserted.
    pub faults: Vec<FaultRow>,
    /// The readings at which the alarm switched.
    pub alarm_transitions: Vec<AlarmTransition>,
}

/// The scene name of the report when no scene file is given.
pub const REFERENCE_SCENE: &str = "reference";

fn timing<T: Real>(t: &[T; 6], single: bool) -> ([Num; 6], [String; 6]) {
    (t.map(Num::of), t.map(|v| bits_of(v, single)))
}

/// The report of a prediction computed in `T` (`single`: f32 bits) for the scene `design`.
pub fn report<T: Real>(p: &Prediction<T>, single: bool, design: &str) -> PredictReport {
    report_measured(p, single, design, None)
}

/// [`report`] naming the measured profile the roller rode on (its file and knots).
pub fn report_measured<T: Real>(
    p: &Prediction<T>,
    single: bool,
    design: &str,
    measured: Option<(&str, usize)>,
) -> PredictReport {
    let (samples, faults, alarm_transitions) = readings(&p.samples, single);
    PredictReport {
        precision: if single { "f32" } else { "f64" },
        scene: scene_report(design, measured),
        jump_rpm: p.table.jump_rpm.map(Num::of),
        jump_rpm_bits: p.table.jump_rpm.map(|j| bits_of(j, single)),
        table: table_rows(&p.table, single),
        interp_checks: p.checks.iter().map(|c| check_row(c, single)).collect(),
        samples,
        faults,
        alarm_transitions,
    }
}

/// The scene `design` (on the `measured` profile, its file and knots) and the chip's fixed
/// configuration.
fn scene_report(design: &str, measured: Option<(&str, usize)>) -> SceneReport {
    let s = chip_solver_settings::<f64>();
    SceneReport {
        design: design.to_string(),
        measured: measured.map(|(f, _)| f.to_string()),
        measured_knots: measured.map(|(_, k)| k),
        states: CHIP_STATES,
        dofs: <ChipScene as Scene>::DOFS.name(),
        rtol: s.rtol,
        atol_in: s.atol,
        max_step_fraction: s.max_step_fraction,
        step_control: s.step_control.name(),
        grid_rpm: CHIP_GRID_RPM,
        max_rpm: CHIP_MAX_RPM,
        resolution_rpm: CHIP_RESOLUTION_RPM,
        alarm_on_margin_rpm: CHIP_ALARM_ON_MARGIN_RPM,
        alarm_off_margin_rpm: CHIP_ALARM_OFF_MARGIN_RPM,
    }
}

/// The boot-time table's rows: each grid speed's smallest contact force and timing errors.
fn table_rows<T: Real>(
    table: &camsim_core::PredictionTable<T, CHIP_GRID>,
    single: bool,
) -> Vec<TableRow> {
    table
        .rpm
        .iter()
        .zip(table.at.iter())
        .map(|(r, s)| {
            let (timing_deg, timing_bits) = timing(&s.timing_deg, single);
            TableRow {
                rpm: Num::of(*r),
                min_force_lb: Num::of(s.min_contact_force),
                min_force_deg: Num::of(s.min_force_deg),
                jumped: s.jumped,
                timing_deg,
                bits: TableBits {
                    rpm: bits_of(*r, single),
                    min_force_lb: bits_of(s.min_contact_force, single),
                    timing_deg: timing_bits,
                },
            }
        })
        .collect()
}

/// An interpolation check's row: the table's prediction against the direct simulation, and
/// their largest differences in force and timing.
fn check_row<T: Real>(c: &InterpCheck<T>, single: bool) -> CheckRow {
    let mut dt = 0.0f64;
    for (a, b) in c
        .interpolated
        .timing_deg
        .iter()
        .zip(c.direct.timing_deg.iter())
    {
        dt = dt.max((a.to_f64() - b.to_f64()).abs());
    }
    let (direct_timing_deg, timing_bits) = timing(&c.direct.timing_deg, single);
    CheckRow {
        rpm: Num::of(c.rpm),
        interp_force_lb: Num::of(c.interpolated.force_margin_lb),
        direct_force_lb: Num::of(c.direct.min_contact_force),
        direct_jumped: c.direct.jumped,
        abs_err_force_lb: (c.interpolated.force_margin_lb.to_f64()
            - c.direct.min_contact_force.to_f64())
        .abs(),
        max_abs_err_timing_deg: dt,
        direct_timing_deg,
        bits: CheckBits {
            direct_force_lb: bits_of(c.direct.min_contact_force, single),
            direct_timing_deg: timing_bits,
        },
    }
}

/// The scripted machine's readings sorted into the vouched ones with their predictions,
/// the faults, and the readings at which the alarm switched (it starts asserted, the
/// monitor's boot state).
fn readings<T: Real>(
    steps: &[ChipStep<T>],
    single: bool,
) -> (Vec<SampleRow>, Vec<FaultRow>, Vec<AlarmTransition>) {
    let mut prev = true;
    let mut alarm_transitions = Vec::new();
    let mut faults = Vec::new();
    let mut samples = Vec::new();
    for (i, s) in steps.iter().enumerate() {
        let measured = match s.reading {
            SpeedReading::Rpm(r) | SpeedReading::OutOfRange(r) => Some(Num::of(r)),
            _ => None,
        };
        if s.alarm != prev {
            alarm_transitions.push(AlarmTransition {
                reading: i,
                kind: s.reading.kind(),
                rpm: measured,
                alarm: s.alarm,
            });
            prev = s.alarm;
        }
        match &s.prediction {
            Some(q) => samples.push(sample_row(i, q, s.alarm, single)),
            None => faults.push(fault_row(i, s, measured)),
        }
    }
    (samples, faults, alarm_transitions)
}

/// The report's row of reading `reading`, a fault `s` (no prediction; `measured`: its speed,
/// if it measured one).
fn fault_row<T: Real>(reading: usize, s: &ChipStep<T>, measured: Option<Num>) -> FaultRow {
    FaultRow {
        reading,
        kind: s.reading.kind(),
        rpm: measured,
        period_ticks: match s.reading {
            SpeedReading::Rejected(why) => Some(why.period_ticks()),
            _ => None,
        },
        alarm: s.alarm,
    }
}

/// The report's row of vouched reading `reading`: its prediction `q`, the alarm after it, and
/// the bits of its numbers. With no jump onset there is no speed margin: the field is absent
/// and `speed_margin_absent` says why.
fn sample_row<T: Real>(
    reading: usize,
    q: &SpeedPrediction<T>,
    alarm: bool,
    single: bool,
) -> SampleRow {
    let (timing_deg, timing_bits) = timing(&q.timing_deg, single);
    let margin = q.speed_margin_rpm.is_finite();
    SampleRow {
        reading,
        rpm: Num::of(q.rpm),
        force_margin_lb: Num::of(q.force_margin_lb),
        speed_margin_rpm: margin.then(|| Num::of(q.speed_margin_rpm)),
        speed_margin_absent: (!margin)
            .then(|| format!("no jump onset up to the search limit of {CHIP_MAX_RPM} rpm")),
        in_grid: q.in_grid,
        alarm,
        timing_deg,
        bits: SampleBits {
            force_margin_lb: bits_of(q.force_margin_lb, single),
            speed_margin_rpm: bits_of(q.speed_margin_rpm, single),
            timing_deg: timing_bits,
        },
    }
}

/// A row's speed margin as the text prints it: rpm, or "none (no onset)" when it is absent.
fn margin_text(s: &SampleRow) -> String {
    s.speed_margin_rpm.map_or_else(
        || "none (no onset)".to_string(),
        |m| format!("{:>8.2} rpm", m.0),
    )
}

/// The human-readable output.
pub fn render_text(r: &PredictReport) -> String {
    let mut out = String::new();
    write_table(r, &mut out);
    write_readings(r, &mut out);
    out
}

/// The scene, the prediction table (force and timing errors by speed), its jump onset
/// and the interpolation checks, forces in the output's family (`--units`).
fn write_table(r: &PredictReport, out: &mut String) {
    use crate::units::{q, symbol, FORCE};
    use std::fmt::Write;
    // Forces in the output's family (`--units`), 4 decimals of a pound.
    let lb = symbol(FORCE);
    let force = |v: f64| q(FORCE, v, 4);
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
            force(row.min_force_lb.0),
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
            c.rpm.0, force(c.interp_force_lb.0), force(c.direct_force_lb.0), force(c.abs_err_force_lb), c.max_abs_err_timing_deg
        );
    }
}

/// Every reading in order: the vouched ones with their prediction, the others named;
/// each with the alarm after it, marked where it turns on or off.
fn write_readings(r: &PredictReport, out: &mut String) {
    use std::fmt::Write;
    let mut prev = true;
    let (mut si, mut fi) = (r.samples.iter().peekable(), r.faults.iter().peekable());
    loop {
        let (line, alarm) = match (si.peek(), fi.peek()) {
            (Some(s), f) if f.is_none_or(|f| s.reading < f.reading) => {
                let a = (sample_text(s), s.alarm);
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
fn sample_text(s: &SampleRow) -> String {
    use crate::units::{q, symbol, FORCE};
    format!(
        "speed {:>6.1} rpm: force margin {:>9} {}, speed margin {}, timing rise50 {:+.4} return50 {:+.4} deg",
        s.rpm.0,
        q(FORCE, s.force_margin_lb.0, 4),
        symbol(FORCE),
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

/// Most bytes of a `--check-log` file read: 16 MB. The host checks 74 parity lines of
/// about 100 bytes; the decoded log of a firmware run around them (boot, timing and
/// defmt lines) is tens of kB, so the cap leaves two orders of magnitude and refuses a
/// device or a runaway capture instead of reading it without end.
pub const MAX_LOG_BYTES: u64 = 16_000_000;

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> Result<()> {
    if args.check_log.is_some() && !args.single {
        bail!("--check-log compares the firmware's f32 bits: add --f32");
    }
    let scene_path = args.scene.clone().or_else(|| args.scene_file.clone());
    let scene = match &scene_path {
        Some(p) => Some(crate::scene::load(p)?.design),
        None => None,
    };
    let design = match &scene_path {
        Some(p) => p.display().to_string(),
        None => REFERENCE_SCENE.to_string(),
    };
    let profile = match &args.measured {
        Some(p) => {
            let d64 = scene.clone().unwrap_or_else(chip_design::<f64>);
            // `run --measured`'s checks first: a profile it refuses is refused here
            // with its reason, named as the option as it names it.
            crate::measured::load(p)?
                .profile(&d64)
                .map_err(|e| anyhow::anyhow!("--measured {}: {e:#}", p.display()))?;
            Some(ProfileKnots::load(p, &d64).map_err(|e| anyhow::anyhow!("--measured {e:#}"))?)
        }
        None => None,
    };
    let measured_name = args.measured.as_ref().map(|p| p.display().to_string());
    let measured = measured_name
        .as_deref()
        .zip(profile.as_ref().map(|k| k.knots_rad.len()));
    let report = if args.single {
        let p = compute::<f32>(scene.as_ref(), profile.as_ref())?;
        if let Some(path) = &args.check_log {
            let log = camsim_scene_file::read_text(path, MAX_LOG_BYTES, "the firmware log")
                .map_err(|e| anyhow::anyhow!("--check-log {e}"))?;
            let n = check_parity(&log, &parity_lines(&p))?;
            return crate::report::out(&format!("parity OK: {n} lines (table, jump onset, interpolation checks, every reading of the scripted machine) bit-identical\n"));
        }
        report_measured(&p, true, &design, measured)
    } else {
        report_measured(
            &compute::<f64>(scene.as_ref(), profile.as_ref())?,
            false,
            &design,
            measured,
        )
    };
    ensure_reached(&report)?;
    crate::report::ensure_finite(&report)?;
    crate::report::print(&report, args.json, units)
}

/// The six timing points of a row, in the order of `timing_deg`.
const TIMING_POINTS: [&str; 6] = [
    "rise 10 %",
    "rise 50 %",
    "rise 90 %",
    "return 10 %",
    "return 50 %",
    "return 90 %",
];

/// Refuses a table with a timing point the follower never crossed (its timing error is
/// not a number): the first such row and point, with the row's contact, as the error.
fn ensure_reached(r: &PredictReport) -> Result<()> {
    for row in &r.table {
        let missing = row.timing_deg.iter().zip(TIMING_POINTS);
        if let Some((_, point)) = missing.into_iter().find(|(v, _)| !v.0.is_finite()) {
            bail!(
                "not reached: at {:.1} rpm the follower never crosses the {point} lift point ({}, smallest contact force {:.4} lb), so the timing table has no value there; nothing was reported (a stiffer spring or a lower speed range keeps the follower on the cam)",
                row.rpm.0,
                if row.jumped { "it left the cam" } else { "it stayed on the cam" },
                row.min_force_lb.0
            );
        }
    }
    Ok(())
}

impl crate::report::Report for PredictReport {
    fn text(&self, _units: crate::units::Units) -> String {
        render_text(self)
    }
    fn json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
    }
}
