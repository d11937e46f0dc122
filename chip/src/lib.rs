//! The cam predictor chip's product configuration, in ONE place read by the firmware and
//! by `camsim predict` (host parity): the scene, solver settings, speed grid, jump-onset
//! resolution, alarm thresholds, the speed measurement ([`ChipMonitor`]: index pulses ->
//! speed reading -> prediction -> alarm, the same for the board, the QEMU image and the
//! host) and the scripted machine of the QEMU run ([`CHIP_SCRIPT`], fed through
//! [`ScriptedPulseTrain`], a [`CaptureTimer`] like the board's timer capture). The
//! predictor itself (table, observer, alarm, onset search, index pulse) is `camsim_core`'s.
//!
//! Chosen by measurement (the figures are in docs/FIRMWARE.md and `camsim models`): the
//! quasi-static-rod scene (regulated drive, vertical, the roller, the cantilever portion
//! and the follower rod quasi-static, the train's mass on the load: 10 states,
//! docs/MODEL.md §10), the fastest scene whose jump onset stays within 1 % of the full
//! model's (`camsim models` measures both), at rtol 1e-2 (the thesis ran at 2 %) with atol
//! 1e-8 in (docs/MODEL.md §5.12).

#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

use camsim_core::{
    steady_state, CamModel, CaptureEvent, CaptureTimer, Design, DeviatedLift, IndexPulse,
    IndexPulseConfig, JumpAlarm, LiftProfile, LiftTable, Method, PredictionTable, Real,
    RegulatedQsRod, Result, Scene, SolverSettings, SpeedPrediction, SpeedReading, Start,
    SteadyState, StepRule, TheoreticalLift,
};

mod log_line;
pub mod memory_map;
pub use log_line::{
    realtime_factor, BudgetLine, MemoryFields, ParityLine, ProductLine, ReactionLine,
    CHIP_CLOCK_HZ, CHIP_NOMINAL_RPM,
};

/// The chip's scene: regulated drive, vertical, the follower train quasi-static up to the
/// load (docs/MODEL.md §10).
pub type ChipScene = RegulatedQsRod;
/// State size of the chip's model (6 + 2·2 = 10).
pub const CHIP_STATES: usize = <ChipScene as Scene>::N;
/// The chip's model type.
pub type ChipModel<T> = CamModel<T, ChipScene, CHIP_STATES>;
/// Largest interval of the chip's lift table, degrees of cam angle (docs/MODEL.md §3.21):
/// the lift, its derivatives and the Hertz stiffness are tabulated once
/// ([`ChipConfig::tabulate`]; for the chip by its build script, into flash) and
/// interpolated in every right-hand side. 1° keeps the
/// reference design's lift within 6e-9 in, y'' within 1.3e-7 in/rad² and K_h within
/// 4e-11 relative of the closed form (the Hermite bound `h⁴/384 max|f⁽⁴⁾|`, far below
/// `f32`'s rounding), and follows a measured profile's deviation knots (0.5° apart, the
/// spline between them cubic) at a quarter of the memory a 0.5° grid would take.
pub const CHIP_TABLE_STEP_DEG: f64 = 1.0;
/// Knots of the chip's lift table: enough for any program of at most 8 segments at
/// [`CHIP_TABLE_STEP_DEG`] (each segment rounds up to a multiple of 8 intervals, 8° of
/// them: `360 + 8·8` intervals and a closing knot per segment). 24 B a knot in `f32`.
/// The host's capacity: the firmware keeps exactly the knots its design uses, in flash.
pub const CHIP_TABLE_KNOTS: usize = 432;
/// The chip's lift table at [`CHIP_TABLE_KNOTS`]' capacity (`camsim predict` and the
/// firmware's build script fill it; the firmware keeps its used knots in flash).
pub type ChipTable<T> = LiftTable<T, CHIP_TABLE_KNOTS>;

/// Number of grid speeds of the boot-time table.
pub const CHIP_GRID: usize = 10;
/// Grid speeds of the boot-time table, rpm (ascending; denser towards the reference
/// design's jump onset, which lies between 900 and 950 rpm with the study spring).
pub const CHIP_GRID_RPM: [f64; CHIP_GRID] = [
    300.0, 400.0, 500.0, 600.0, 700.0, 750.0, 800.0, 850.0, 900.0, 950.0,
];
/// Upper limit of the jump search when no grid speed jumps, rpm.
pub const CHIP_MAX_RPM: f64 = 1200.0;
/// Resolution of the jump-onset bisection, rpm.
pub const CHIP_RESOLUTION_RPM: f64 = 1.0;
/// Speeds between grid points where the boot check compares the interpolated
/// prediction with a direct simulation, rpm.
pub const CHIP_CHECK_RPM: [f64; 3] = [450.0, 650.0, 825.0];
/// The jump alarm turns on at this speed margin (rpm) or less.
pub const CHIP_ALARM_ON_MARGIN_RPM: f64 = 50.0;
/// An active jump alarm turns off once the speed margin exceeds this (rpm).
pub const CHIP_ALARM_OFF_MARGIN_RPM: f64 = 100.0;

/// The design compiled into the chip and run by the host's parity check when no scene
/// is chosen: the reference design of VI.1.
pub fn chip_design<T: Real>() -> Design<T> {
    Design::reference()
}

/// A scene file's design (`Design<f64>`, as `camsim_scene_file` reads it) in the chip's
/// precision `T`: [`Design::cast`], then [`Design::validate`] in `T`. The firmware's
/// build script (`CAMSIM_SCENE`) and `camsim predict --scene` both call this, so the
/// chip and the host's parity check run the same bits.
pub fn chip_design_from<T: Real>(scene: &Design<f64>) -> Result<Design<T>> {
    let d = scene.cast::<T>()?;
    d.validate()?;
    Ok(d)
}

/// Solver settings of the chip's predictor: rtol 1e-2, atol 1e-8 in, at most 1/100
/// revolution per double step (the reduced scene's steps are longer than 1/500: the
/// controller, not the cap, sets them), from static equilibrium. The thesis's all-zero start
/// leaves a start-up impact whose roller ringing is still there in the second revolution,
/// so it is not a steady state (docs/MODEL.md §5.11, §7.3; its effect on the jump speed
/// is measured in docs/FIRMWARE.md). The step control is the thesis's rule, England
/// uncapped ([`StepRule::Thesis`]), chosen here and not inherited from the host's default:
/// at rtol 1e-2 accuracy, not stability, holds the chip's step, so the cap only adds its
/// power iterations (PI with the cap measured +15 % instructions per revolution on the
/// chip, docs/FIRMWARE.md), and `camsim predict --f32` runs exactly these settings, so
/// the parity with the firmware stays bit for bit. The method is England's, not the host's
/// default Merson: on the chip's lift table at rtol 1e-2 Merson takes 0.73× the
/// evaluations a revolution but misses the smallest contact force at 800 rpm by 0.21 lb
/// against England's 0.11 (its samples are only the step ends), so it does not win at
/// equal error (the `chip_method` example, docs/FIRMWARE.md).
pub fn chip_solver_settings<T: Real>() -> SolverSettings<T> {
    SolverSettings {
        rtol: T::from_f64(1e-2),
        atol: T::from_f64(1e-8),
        max_step_fraction: T::from_f64(1.0 / 100.0),
        max_steps_per_rev: 2_000_000,
        start: Start::Static,
        step_control: StepRule::Thesis,
        method: Method::England,
    }
}

/// [`CHIP_GRID_RPM`] in `T`.
pub fn chip_grid_rpm<T: Real>() -> [T; CHIP_GRID] {
    CHIP_GRID_RPM.map(T::from_f64)
}

/// The chip's predictor for one design on one lift, with its solver settings: the value
/// the firmware builds at boot and `camsim predict --f32` builds on the host, so both run
/// the same arithmetic. [`ChipConfig::new`] gives the chip's settings on the theoretical
/// cam; [`ChipConfig::on`] puts the roller on a measured profile and
/// [`ChipConfig::with_settings`] changes the settings (the firmware's boot-fault test
/// gives an impossible step budget).
///
/// ```
/// use camsim_chip::{chip_design, ChipConfig};
/// let design = chip_design::<f64>();
/// let chip = ChipConfig::new(&design);
/// let direct = chip.steady_state(600.0).unwrap();
/// assert!(!direct.jumped);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ChipConfig<'a, T, P = TheoreticalLift> {
    /// The design (the one compiled in, or a scene's in the chip's precision).
    pub design: &'a Design<T>,
    /// The lift the roller rides on: the program, or a reference to a measured profile's
    /// [`ChipDeviation`].
    pub lift: P,
    /// The solver settings ([`chip_solver_settings`] unless changed).
    pub settings: SolverSettings<T>,
}

impl<'a, T: Real> ChipConfig<'a, T> {
    /// The chip's configuration for `design` on the theoretical cam.
    pub fn new(design: &'a Design<T>) -> Self {
        Self {
            design,
            lift: TheoreticalLift,
            settings: chip_solver_settings(),
        }
    }
}

impl<'a, T: Real, P: LiftProfile<T> + Copy> ChipConfig<'a, T, P> {
    /// The same configuration with the roller riding on `lift`.
    pub fn on<Q: LiftProfile<T> + Copy>(self, lift: Q) -> ChipConfig<'a, T, Q> {
        ChipConfig {
            design: self.design,
            lift,
            settings: self.settings,
        }
    }

    /// Fills `table` with this configuration's lift (the program, or the measured
    /// profile) on the chip's grid ([`CHIP_TABLE_STEP_DEG`]) and returns the same
    /// configuration riding on it: the firmware's boot and `camsim predict` both call
    /// this, so the table (and with it every right-hand side) is the same arithmetic.
    pub fn tabulate<'t>(
        &self,
        table: &'t mut ChipTable<T>,
    ) -> Result<ChipConfig<'a, T, &'t ChipTable<T>>> {
        table.fill(
            self.design,
            &self.lift,
            T::from_f64(CHIP_TABLE_STEP_DEG).to_radians(),
        )?;
        Ok(ChipConfig {
            design: self.design,
            lift: &*table,
            settings: self.settings,
        })
    }

    /// The same configuration with other solver settings.
    pub fn with_settings(self, settings: SolverSettings<T>) -> Self {
        Self { settings, ..self }
    }

    /// The prediction table over [`CHIP_GRID_RPM`] and its jump onset (the boot-time
    /// computation).
    pub fn prediction_table(&self) -> Result<PredictionTable<T, CHIP_GRID>> {
        PredictionTable::build_on::<ChipScene, CHIP_STATES, P>(
            self.design,
            self.lift,
            chip_grid_rpm(),
            T::from_f64(CHIP_MAX_RPM),
            T::from_f64(CHIP_RESOLUTION_RPM),
            &self.settings,
        )
    }

    /// The steady state simulated directly at `rpm` with the chip's model (the
    /// interpolation check).
    pub fn steady_state(&self, rpm: T) -> Result<SteadyState<T>> {
        steady_state::<T, ChipScene, CHIP_STATES, P>(self.design, self.lift, rpm, &self.settings)
    }
}

// ---------------------------------------------------------------------------
// A measured cam profile (the firmware's `CAMSIM_PROFILE`, `camsim predict --measured`).
// ---------------------------------------------------------------------------

/// Most knots of a measured profile's deviation spline the chip carries (its rows and the
/// closing knot: 720 rows, one every 0.5°). Each knot costs 8 B of flash (angle and
/// deviation, f32) and 12 B of RAM (the spline's knot, value and second derivative) plus
/// 4 B of stack while the spline is solved at boot (docs/FIRMWARE.md has the measured
/// figures).
pub const CHIP_PROFILE_MAX_KNOTS: usize = 721;

/// The roller's lift on a measured cam in the chip's precision: the program plus a
/// periodic deviation spline of at most `K` knots.
pub type ChipDeviation<T, const K: usize> = DeviatedLift<T, K>;

/// The measured profile's deviation from its knots (returned by value: `3 K + 3` words;
/// the firmware, whose spline lives in a `static`, calls
/// [`DeviatedLift::refit_periodic`] in place, as this does): `knots_rad` (strictly
/// increasing, one revolution from the first to the last, the closing knot) and
/// `values_in` (the last repeating the first), already in `T` (`T::from_f64` of the
/// shared reader's `Measured::deviation_knots`). The firmware (knots compiled into flash)
/// and `camsim predict --measured` build the same spline. Errors (never a panic) on too
/// few or too many knots, a non-finite or non-increasing knot, or a span other than one
/// revolution.
pub fn chip_deviation<T: Real, const K: usize>(
    knots_rad: &[T],
    values_in: &[T],
) -> Result<ChipDeviation<T, K>> {
    let mut dev = ChipDeviation::EMPTY;
    dev.refit_periodic(knots_rad, values_in)?;
    Ok(dev)
}

/// The chip's jump alarm (thresholds [`CHIP_ALARM_ON_MARGIN_RPM`], [`CHIP_ALARM_OFF_MARGIN_RPM`]).
pub fn chip_alarm<T: Real>() -> Result<JumpAlarm<T>> {
    JumpAlarm::new(
        T::from_f64(CHIP_ALARM_ON_MARGIN_RPM),
        T::from_f64(CHIP_ALARM_OFF_MARGIN_RPM),
    )
}

// ---------------------------------------------------------------------------
// The speed measurement: index pulses -> speed reading -> prediction -> alarm.
// ---------------------------------------------------------------------------

/// Tick rate of the index-pulse capture timer, Hz: the board's TIM2 (90 MHz / 90) and
/// the scripted pulse train of the QEMU image and the host alike.
pub const CHIP_TICK_HZ: u32 = 1_000_000;

/// Slowest speed the boot table covers, rpm: its first grid speed, rounded up. Slower
/// measured speeds are [`SpeedReading::OutOfRange`].
pub const CHIP_RANGE_MIN_RPM: u32 = {
    let x = CHIP_GRID_RPM[0];
    let t = x as u32;
    if (t as f64) < x {
        t + 1
    } else {
        t
    }
};
/// Fastest speed the boot table covers, rpm: its last grid speed, rounded down. Faster
/// measured speeds are [`SpeedReading::OutOfRange`].
pub const CHIP_RANGE_MAX_RPM: u32 = CHIP_GRID_RPM[CHIP_GRID - 1] as u32;
/// Fastest speed the machine can turn, rpm: twice the table's top. A shorter period is
/// noise ([`camsim_core::Rejection::TooShort`]).
pub const CHIP_LIMIT_RPM: u32 = 2 * CHIP_RANGE_MAX_RPM;
/// Below half the table's slowest speed the speed counts as lost: one such revolution
/// without a pulse is [`SpeedReading::Lost`].
pub const CHIP_LOST_RPM: u32 = CHIP_RANGE_MIN_RPM / 2;
/// A period under this share of the last accepted one is a bounce, %.
pub const CHIP_BOUNCE_PERCENT: u32 = 25;
/// Consecutive periods agree within this share, %: a cam shaft's speed changes less per
/// revolution; a larger step is believed after one confirming revolution.
pub const CHIP_MAX_CHANGE_PERCENT: u32 = 25;

/// The chip's index-pulse configuration for a capture timer ticking at `tick_hz`.
pub fn chip_index_pulse_config(tick_hz: u32) -> IndexPulseConfig {
    IndexPulseConfig {
        tick_hz,
        min_rpm: CHIP_RANGE_MIN_RPM,
        max_rpm: CHIP_RANGE_MAX_RPM,
        limit_rpm: CHIP_LIMIT_RPM,
        lost_rpm: CHIP_LOST_RPM,
        bounce_percent: CHIP_BOUNCE_PERCENT,
        max_change_percent: CHIP_MAX_CHANGE_PERCENT,
    }
}

/// What the chip's predictor made of one speed reading ([`ChipMonitor::step`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChipStep<T> {
    /// The reading of the index pulse.
    pub reading: SpeedReading<T>,
    /// The table's prediction, at a vouched speed ([`SpeedReading::Rpm`]) only: every
    /// other reading is never interpolated or extrapolated.
    pub prediction: Option<SpeedPrediction<T>>,
    /// Whether the alarm is asserted after this reading.
    pub alarm: bool,
}

/// The chip's speed monitor, one policy for the board, the QEMU image and `camsim
/// predict`: a [`CaptureTimer`] -> [`IndexPulse`] ([`chip_index_pulse_config`]) -> a
/// speed reading -> the table's prediction at a vouched speed -> the [`JumpAlarm`]
/// ([`chip_alarm`]). Only a vouched speed feeds its speed margin to the alarm; every other
/// reading (out of the table's range, a rejected pulse, a lost speed, an acquisition, a
/// capture overrun) feeds NaN, which asserts it; it is released only once a vouched
/// margin exceeds the release threshold. It starts asserted.
#[derive(Clone, Copy, Debug)]
pub struct ChipMonitor<T> {
    pulse: IndexPulse<T>,
    alarm: JumpAlarm<T>,
}

impl<T: Real> ChipMonitor<T> {
    /// A monitor for a capture timer ticking at `tick_hz`, waiting for its first pulse,
    /// the alarm asserted. Fails if the configuration breaks [`IndexPulseConfig`]'s rules
    /// at that tick rate.
    pub fn new(tick_hz: u32) -> Result<Self> {
        let pulse = IndexPulse::new(chip_index_pulse_config(tick_hz))?;
        let mut alarm = chip_alarm()?;
        alarm.update(T::NAN);
        Ok(Self { pulse, alarm })
    }

    /// One step of the main loop: reads `timer` once ([`IndexPulse::service`]); with a
    /// reading, predicts and updates the alarm ([`Self::react`]).
    pub fn step<C: CaptureTimer + ?Sized>(
        &mut self,
        table: &PredictionTable<T, CHIP_GRID>,
        timer: &mut C,
    ) -> Option<ChipStep<T>> {
        let reading = self.pulse.service(timer)?;
        Some(self.react(table, reading))
    }

    /// The prediction (at a vouched speed only) and the alarm after `reading`.
    pub fn react(
        &mut self,
        table: &PredictionTable<T, CHIP_GRID>,
        reading: SpeedReading<T>,
    ) -> ChipStep<T> {
        let prediction = reading.vouched_rpm().map(|rpm| table.predict(rpm));
        let margin = prediction.map_or(T::NAN, |p| p.speed_margin_rpm);
        let alarm = self.alarm.update(margin);
        ChipStep {
            reading,
            prediction,
            alarm,
        }
    }

    /// Whether the alarm is asserted.
    pub fn alarm_asserted(&self) -> bool {
        self.alarm.is_active()
    }

    /// The alarm's thresholds and state.
    pub fn alarm(&self) -> &JumpAlarm<T> {
        &self.alarm
    }

    /// The index-pulse state machine (its configuration and derived periods).
    pub fn pulse(&self) -> &IndexPulse<T> {
        &self.pulse
    }
}

/// A reading as logged in a `parity reading` line: its [`SpeedReading::kind`] and one
/// number, the f32 bits of the speed for [`SpeedReading::OutOfRange`], the period in
/// ticks for a rejection, 0 otherwise.
pub fn reading_parity(reading: &SpeedReading<f32>) -> (&'static str, u32) {
    let value = match reading {
        SpeedReading::Rpm(r) | SpeedReading::OutOfRange(r) => r.to_bits(),
        SpeedReading::Rejected(why) => why.period_ticks(),
        SpeedReading::Lost | SpeedReading::Acquiring | SpeedReading::Overrun => 0,
    };
    (reading.kind(), value)
}

// ---------------------------------------------------------------------------
// The scripted machine (QEMU image and host): its index pulses, with the faults.
// ---------------------------------------------------------------------------

/// One item of the scripted machine's index pulse train ([`CHIP_SCRIPT`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ScriptItem {
    /// One revolution at each speed from `from_rpm` to `to_rpm` (inclusive, up or down)
    /// in steps of `step_rpm`, one index pulse at the end of each.
    Ramp {
        /// First speed, rpm.
        from_rpm: u32,
        /// Last speed, rpm.
        to_rpm: u32,
        /// Step, rpm (positive).
        step_rpm: u32,
    },
    /// An extra pulse `after_ticks` after the last one (a bouncing contact, electrical
    /// noise); the next revolution's pulse comes on time.
    Extra {
        /// Ticks after the last pulse.
        after_ticks: u32,
    },
    /// One more revolution at the last speed, whose pulse the sensor misses.
    Missed,
    /// No pulse for `ticks` (the machine stopped, the sensor's cable cut); the next
    /// revolution's pulse comes a period after that.
    Silence {
        /// Ticks without a pulse.
        ticks: u32,
    },
}

/// The scripted machine of the QEMU run and of `camsim predict`, one index pulse per
/// revolution, with every fault the predictor must survive:
/// - 300 -> 800 rpm by 25 rpm, a step to 925 rpm (across the reference design's jump
///   onset), 950, then 975 and 1000 rpm, above the table's grid (flagged, never
///   extrapolated), back down by 25 rpm to 300 rpm, then 275 and 250 rpm, below the
///   grid; at the end the pulses stop (the speed is lost);
/// - on the way up a bounce at 400 rpm (an extra pulse 35 000 ticks after the real one:
///   longer than a revolution at the machine's limit, under 25 % of the period) and
///   contact chatter at 500 rpm (an extra pulse 2 000 ticks after: faster than the
///   machine's limit); on the way down a missed pulse after 725 rpm and, at 600 rpm, one
///   second without pulses (the speed is lost; the pulses then resume at 600 rpm).
pub const CHIP_SCRIPT: [ScriptItem; 13] = [
    ScriptItem::Ramp {
        from_rpm: 300,
        to_rpm: 400,
        step_rpm: 25,
    },
    ScriptItem::Extra {
        after_ticks: 35_000,
    },
    ScriptItem::Ramp {
        from_rpm: 425,
        to_rpm: 500,
        step_rpm: 25,
    },
    ScriptItem::Extra { after_ticks: 2_000 },
    ScriptItem::Ramp {
        from_rpm: 525,
        to_rpm: 800,
        step_rpm: 25,
    },
    ScriptItem::Ramp {
        from_rpm: 925,
        to_rpm: 1000,
        step_rpm: 25,
    },
    ScriptItem::Ramp {
        from_rpm: 975,
        to_rpm: 725,
        step_rpm: 25,
    },
    ScriptItem::Missed,
    ScriptItem::Ramp {
        from_rpm: 700,
        to_rpm: 600,
        step_rpm: 25,
    },
    ScriptItem::Silence { ticks: 1_000_000 },
    ScriptItem::Ramp {
        from_rpm: 600,
        to_rpm: 300,
        step_rpm: 25,
    },
    ScriptItem::Ramp {
        from_rpm: 275,
        to_rpm: 250,
        step_rpm: 25,
    },
    ScriptItem::Silence { ticks: 1_000_000 },
];

/// The edge times of a script, ticks since its start (an iterator).
#[derive(Clone, Debug)]
pub struct ScriptedEdges<'a> {
    script: &'a [ScriptItem],
    tick_hz: u32,
    /// Index of the current item.
    item: usize,
    /// The next speed of the current ramp.
    ramp_rpm: Option<u32>,
    /// Time of the last revolution's end (its pulse, or where the pulse would have been).
    last: u64,
    /// Speed of the last revolution, rpm.
    last_rpm: u32,
}

impl<'a> ScriptedEdges<'a> {
    /// The edges of `script` with a timer at `tick_hz`.
    pub fn new(script: &'a [ScriptItem], tick_hz: u32) -> Self {
        Self {
            script,
            tick_hz,
            item: 0,
            ramp_rpm: None,
            last: 0,
            last_rpm: 0,
        }
    }

    /// One revolution at `rpm`, ticks, rounded to the nearest (0 for 0 rpm).
    pub fn period_ticks(&self, rpm: u32) -> u64 {
        let tpm = 60 * u64::from(self.tick_hz);
        (tpm + u64::from(rpm) / 2)
            .checked_div(u64::from(rpm))
            .unwrap_or(0)
    }

    /// Where the script's time ends (after its last pulse and any silence after it) once
    /// the iterator has returned `None`.
    pub fn end_ticks(&self) -> u64 {
        self.last
    }
}

impl Iterator for ScriptedEdges<'_> {
    type Item = u64;

    fn next(&mut self) -> Option<u64> {
        loop {
            let item = *self.script.get(self.item)?;
            match item {
                ScriptItem::Ramp {
                    from_rpm,
                    to_rpm,
                    step_rpm,
                } => {
                    let rpm = self.ramp_rpm.unwrap_or(from_rpm);
                    // The ramp's next speed; None after its last.
                    let next = if rpm == to_rpm || step_rpm == 0 {
                        None
                    } else if to_rpm > from_rpm {
                        rpm.checked_add(step_rpm).filter(|n| *n <= to_rpm)
                    } else {
                        rpm.checked_sub(step_rpm).filter(|n| *n >= to_rpm)
                    };
                    if next.is_none() {
                        self.item += 1;
                    }
                    self.ramp_rpm = next;
                    if rpm == 0 {
                        continue;
                    }
                    self.last += self.period_ticks(rpm);
                    self.last_rpm = rpm;
                    return Some(self.last);
                }
                ScriptItem::Extra { after_ticks } => {
                    self.item += 1;
                    return Some(self.last + u64::from(after_ticks));
                }
                ScriptItem::Missed => {
                    self.item += 1;
                    self.last += self.period_ticks(self.last_rpm);
                }
                ScriptItem::Silence { ticks } => {
                    self.item += 1;
                    self.last += u64::from(ticks);
                }
            }
        }
    }
}
/// Ticks between two polls of the scripted machine's timer while no pulse is due (1 ms
/// at [`CHIP_TICK_HZ`]): the main loop's period in the script's time.
pub const SCRIPT_POLL_TICKS: u32 = 1_000;
/// The scripted counter at the script's start: 2^32 - 2^20, so it wraps about a second
/// in (after five revolutions), as a free-running 32-bit timer does.
pub const SCRIPT_START_COUNT: u32 = 0xFFF0_0000;

/// A scripted machine's index pulses behind the [`CaptureTimer`] trait the board's timer
/// capture implements: the QEMU image and `camsim predict` feed it to the same
/// [`ChipMonitor`] (and so the same [`IndexPulse`]) as the board. Time is virtual: a poll
/// without a pulse due advances the counter by [`SCRIPT_POLL_TICKS`]; a pulse due before
/// that is returned at its exact count ([`SCRIPT_START_COUNT`] + its time, wrapping).
#[derive(Clone, Debug)]
pub struct ScriptedPulseTrain<'a> {
    edges: ScriptedEdges<'a>,
    /// The next edge, ticks since the start.
    pending: Option<u64>,
    /// The virtual time now, ticks since the start.
    clock: u64,
}

impl ScriptedPulseTrain<'static> {
    /// The chip's scripted machine ([`CHIP_SCRIPT`] at [`CHIP_TICK_HZ`]).
    pub fn chip() -> Self {
        Self::new(&CHIP_SCRIPT, CHIP_TICK_HZ)
    }
}

impl<'a> ScriptedPulseTrain<'a> {
    /// The pulses of `script` on a timer at `tick_hz`.
    pub fn new(script: &'a [ScriptItem], tick_hz: u32) -> Self {
        let mut edges = ScriptedEdges::new(script, tick_hz);
        let pending = edges.next();
        Self {
            edges,
            pending,
            clock: 0,
        }
    }

    /// Whether the script is over: no pulse left and its time (any final silence) passed.
    pub fn finished(&self) -> bool {
        self.pending.is_none() && self.clock >= self.edges.end_ticks()
    }

    /// The virtual time since the start, ticks.
    pub fn elapsed_ticks(&self) -> u64 {
        self.clock
    }

    /// The 32-bit counter at time `t` (ticks since the start): it wraps.
    fn count(t: u64) -> u32 {
        SCRIPT_START_COUNT.wrapping_add((t & u64::from(u32::MAX)) as u32)
    }
}

impl CaptureTimer for ScriptedPulseTrain<'_> {
    fn tick_hz(&self) -> u32 {
        self.edges.tick_hz
    }

    fn poll_capture(&mut self) -> Option<CaptureEvent> {
        let step = u64::from(SCRIPT_POLL_TICKS);
        match self.pending {
            Some(e) if e <= self.clock + step => {
                self.clock = self.clock.max(e);
                self.pending = self.edges.next();
                Some(CaptureEvent::Edge(Self::count(e)))
            }
            _ => {
                self.clock += step;
                None
            }
        }
    }

    fn now(&mut self) -> u32 {
        Self::count(self.clock)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    extern crate std;
    use std::vec::Vec;

    /// The speeds of the revolutions that end in a pulse, as the script's doc lists them.
    fn scripted_revolutions() -> Vec<u32> {
        let mut v: Vec<u32> = (300..=800).step_by(25).collect();
        v.extend((925..=1000).step_by(25));
        v.extend((725..=975).rev().step_by(25));
        v.extend((600..=700).rev().step_by(25));
        v.extend((300..=600).rev().step_by(25));
        v.extend([275, 250]);
        v
    }

    #[test]
    fn the_script_has_its_documented_edges() {
        let revs = scripted_revolutions();
        assert_eq!(revs.len(), 56);
        let mut edges = ScriptedEdges::new(&CHIP_SCRIPT, CHIP_TICK_HZ);
        let times: Vec<u64> = edges.by_ref().collect();
        // Every revolution's pulse and the two extra pulses, ascending.
        assert_eq!(times.len(), revs.len() + 2);
        assert!(times.windows(2).all(|w| w[0] < w[1]));
        // The first pulse ends a revolution at 300 rpm: 60 s / 300 at 1 MHz.
        assert_eq!(times[0], 200_000);
        // The bounce 35 000 ticks after the 400 rpm pulse (the fifth), then 425 rpm.
        assert_eq!(times[5] - times[4], 35_000);
        assert_eq!(times[6] - times[4], 141_176); // 6e7 / 425 = 141 176.5 -> nearest
                                                  // The script's time: every revolution, the missed one (at 725 rpm) and both
                                                  // silences.
        let p = |n: u32| (60_000_000 + u64::from(n) / 2) / u64::from(n);
        let total: u64 = revs.iter().map(|n| p(*n)).sum::<u64>() + p(725) + 2_000_000;
        assert_eq!(edges.end_ticks(), total);
        assert_eq!(*times.last().unwrap() + 1_000_000, total);
    }

    #[test]
    fn the_scripted_train_gives_each_fault_once_and_wraps_the_counter() {
        let mut train = ScriptedPulseTrain::chip();
        let mut ip = IndexPulse::<f32>::new(chip_index_pulse_config(CHIP_TICK_HZ)).unwrap();
        let mut readings = Vec::new();
        let mut wrapped = false;
        let mut last_now = train.now();
        while !train.finished() {
            if let Some(r) = ip.service(&mut train) {
                readings.push(r);
            }
            let now = train.now();
            wrapped |= now < last_now;
            last_now = now;
        }
        assert!(wrapped, "the 32-bit counter wraps during the script");
        let count = |k: &str| readings.iter().filter(|r| r.kind() == k).count();
        // 58 edges and two timeouts. Acquiring: the first two pulses, and two after the
        // silence at 600 rpm; rejected: the bounce, the chatter, the period spanning the
        // missed pulse; out of range: 975, 1000, 975 and 275, 250 rpm; lost: the two
        // silences; the rest read.
        assert_eq!(readings.len(), 60);
        assert_eq!(count("acquiring"), 4);
        assert_eq!(count("bounce"), 1);
        assert_eq!(count("too_short"), 1);
        assert_eq!(count("step"), 1);
        assert_eq!(count("out_of_range"), 5);
        assert_eq!(count("lost"), 2);
        assert_eq!(count("overrun"), 0);
        assert_eq!(count("rpm"), 46);
        assert_eq!(readings.last(), Some(&SpeedReading::Lost));
        // Each vouched speed is 60 f / N of a revolution's period N rounded to a tick.
        let p = |n: u32| (60_000_000 + n / 2) / n;
        for r in &readings {
            if let SpeedReading::Rpm(v) | SpeedReading::OutOfRange(v) = r {
                let n = v.round() as u32;
                assert_eq!(*v, 60_000_000.0f32 / p(n) as f32, "{r:?}");
                let inside = (CHIP_RANGE_MIN_RPM..=CHIP_RANGE_MAX_RPM).contains(&n);
                assert_eq!(r.vouched_rpm().is_some(), inside, "{r:?}");
            }
        }
        assert_eq!(
            readings.iter().find(|r| r.kind() == "bounce"),
            Some(&SpeedReading::Rejected(camsim_core::Rejection::Bounce {
                period_ticks: 35_000
            }))
        );
    }

    #[test]
    fn the_monitor_starts_asserted_and_asserts_on_every_reading_but_a_vouched_one() {
        let table = PredictionTable::<f32, CHIP_GRID> {
            rpm: chip_grid_rpm(),
            at: [SteadyState::default(); CHIP_GRID],
            jump_rpm: Some(900.0),
        };
        let mut m = ChipMonitor::<f32>::new(CHIP_TICK_HZ).unwrap();
        assert!(m.alarm_asserted());
        // Margin 400 rpm > 100: released; then each other reading asserts it.
        for r in [
            SpeedReading::Lost,
            SpeedReading::Acquiring,
            SpeedReading::Overrun,
            SpeedReading::OutOfRange(1000.0),
            SpeedReading::Rejected(camsim_core::Rejection::Step { period_ticks: 9 }),
        ] {
            let s = m.react(&table, SpeedReading::Rpm(500.0));
            assert!(!s.alarm && s.prediction.is_some());
            let s = m.react(&table, r);
            assert!(s.alarm && s.prediction.is_none(), "{r:?}");
        }
        // Margin 75 rpm (inside the hysteresis band) does not release it.
        assert!(m.react(&table, SpeedReading::Rpm(825.0)).alarm);
    }

    #[test]
    fn a_measured_deviation_is_refused_on_bad_knots_without_a_panic() {
        let tau = 2.0 * core::f32::consts::PI;
        let k = [0.0, tau / 4.0, tau / 2.0, 3.0 * tau / 4.0, tau];
        let v = [1e-3, 0.0, -1e-3, 0.0, 1e-3];
        let d = chip_deviation::<f32, 5>(&k, &v).unwrap();
        assert_eq!(d.deviation(0.0).y, 1e-3);
        // Too many knots for the capacity, too few, a NaN, not increasing, not one
        // revolution, lengths differing: errors; a failed refit leaves no knots.
        assert!(chip_deviation::<f32, 4>(&k, &v).is_err());
        assert!(chip_deviation::<f32, 8>(&k[..3], &v[..3]).is_err());
        let mut bad = k;
        bad[2] = f32::NAN;
        assert!(chip_deviation::<f32, 8>(&bad, &v).is_err());
        bad[2] = bad[1];
        assert!(chip_deviation::<f32, 8>(&bad, &v).is_err());
        let half = k.map(|x| x / 2.0);
        let mut dev = ChipDeviation::<f32, 8>::EMPTY;
        assert!(dev.refit_periodic(&half, &v).is_err());
        assert!(dev.spline().is_empty());
        assert!(dev.refit_periodic(&k, &v[..4]).is_err());
        assert!(dev.refit_periodic(&k, &v).is_ok());
        assert_eq!(dev, chip_deviation::<f32, 8>(&k, &v).unwrap());
    }

    #[test]
    fn grid_ascends_and_brackets_the_checks() {
        assert!(CHIP_GRID_RPM.windows(2).all(|w| w[0] < w[1]));
        for c in CHIP_CHECK_RPM {
            assert!(
                !CHIP_GRID_RPM.contains(&c)
                    && c > CHIP_GRID_RPM[0]
                    && c < CHIP_GRID_RPM[CHIP_GRID - 1]
            );
        }
        assert!(chip_alarm::<f32>().is_ok());
    }
}
