//! The report of a prediction: its rows built from the table, the interpolation checks
//! and the readings, each number with its bits as computed.

use camsim_chip::{
    chip_solver_settings, ChipScene, ChipStep, CHIP_ALARM_OFF_MARGIN_RPM, CHIP_ALARM_ON_MARGIN_RPM,
    CHIP_GRID, CHIP_GRID_RPM, CHIP_MAX_RPM, CHIP_RESOLUTION_RPM, CHIP_STATES,
};
use camsim_core::{Real, Scene, SpeedPrediction, SpeedReading};

use super::report::{bits_of, AlarmTransition, CheckBits, CheckRow, FaultRow, Num, PredictReport};
use super::report::{SampleBits, SampleRow, SceneReport, TableBits, TableRow};
use super::{InterpCheck, Prediction};
use crate::units::measure::kind;
use crate::units::{Bits, Force, Length};

/// The six timing errors of a row and their bits.
fn timing<T: Real>(t: &[T; 6], single: bool) -> ([Num; 6], [String; 6]) {
    (t.map(Num::of), t.map(|v| bits_of(v, single)))
}

/// A force computed in `T`, in lb.
fn force<T: Real>(x: T) -> Force {
    Force::inch(x.to_f64())
}

/// The bits of a force computed in `T`.
fn force_bits<T: Real>(x: T, single: bool) -> Bits<kind::Force> {
    Bits::new(bits_of(x, single))
}

impl PredictReport {
    /// The report of a prediction computed in `T` (`single`: f32 bits) for the scene
    /// `design`, naming the `measured` profile the roller rode on (its file and knots).
    pub fn of<T: Real>(
        p: &Prediction<T>,
        single: bool,
        design: &str,
        measured: Option<(&str, usize)>,
    ) -> Self {
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
        atol_in: Length::inch(s.atol),
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
                min_force_lb: force(s.min_contact_force),
                min_force_deg: Num::of(s.min_force_deg),
                jumped: s.jumped,
                timing_deg,
                bits: TableBits {
                    rpm: bits_of(*r, single),
                    min_force_lb: force_bits(s.min_contact_force, single),
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
        interp_force_lb: force(c.interpolated.force_margin_lb),
        direct_force_lb: force(c.direct.min_contact_force),
        direct_jumped: c.direct.jumped,
        abs_err_force_lb: Force::inch(
            (c.interpolated.force_margin_lb.to_f64() - c.direct.min_contact_force.to_f64()).abs(),
        ),
        max_abs_err_timing_deg: dt,
        direct_timing_deg,
        bits: CheckBits {
            direct_force_lb: force_bits(c.direct.min_contact_force, single),
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
        force_margin_lb: force(q.force_margin_lb),
        speed_margin_rpm: margin.then(|| Num::of(q.speed_margin_rpm)),
        speed_margin_absent: (!margin)
            .then(|| format!("no jump onset up to the search limit of {CHIP_MAX_RPM} rpm")),
        in_grid: q.in_grid,
        alarm,
        timing_deg,
        bits: SampleBits {
            force_margin_lb: force_bits(q.force_margin_lb, single),
            speed_margin_rpm: bits_of(q.speed_margin_rpm, single),
            timing_deg: timing_bits,
        },
    }
}
