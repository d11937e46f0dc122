//! What the board and the QEMU image share around the chip's speed monitor
//! ([`camsim_chip::ChipMonitor`]: index pulses -> speed reading -> prediction -> alarm):
//! the fail-safe alarm output, the reading counters, and the log lines that name every
//! reason the alarm is asserted. A board adds only its HAL glue: a
//! [`camsim_core::CaptureTimer`] for its index capture and an `OutputPin` for the alarm.
//!
//! ## The alarm output's safe state
//! **LOW = alarm asserted = the safe state**; HIGH = the predictor vouches for the speed
//! and its margin to jump onset. The safe state is the one a dead controller produces: a
//! pin without power, in reset (it floats; a pull-down on the driver reads low), a broken
//! wire or a stopped program all read as the alarm, so no failure of the controller can
//! show "all clear". [`FailSafeOutput::new`] drives the pin low before anything else; the
//! firmware releases it only while a vouched speed's margin allows
//! ([`camsim_chip::ChipMonitor`]), and drives it low again on every fault (out of the
//! table's range, a rejected pulse, the speed lost, an acquisition, a capture overrun) and
//! before it stops on any error (a failed boot).

use camsim_chip::{
    ChipMonitor, ChipStep, CHIP_BOUNCE_PERCENT, CHIP_LIMIT_RPM, CHIP_LOST_RPM,
    CHIP_MAX_CHANGE_PERCENT, CHIP_RANGE_MAX_RPM, CHIP_RANGE_MIN_RPM,
};
use camsim_core::{Rejection, SpeedReading};
use embedded_hal::digital::{OutputPin, StatefulOutputPin};

/// The alarm output with its fail-safe polarity: asserted = LOW.
#[derive(Debug)]
pub struct FailSafeOutput<P> {
    pin: P,
    asserted: bool,
    transitions: u32,
}

impl<P: OutputPin> FailSafeOutput<P> {
    /// Takes the pin and drives it to the safe state (alarm asserted, LOW).
    pub fn new(mut pin: P) -> Result<Self, P::Error> {
        pin.set_low()?;
        Ok(Self {
            pin,
            asserted: true,
            transitions: 0,
        })
    }

    /// Asserts (LOW) or releases (HIGH) the alarm; true if the level changed.
    pub fn set_asserted(&mut self, asserted: bool) -> Result<bool, P::Error> {
        if asserted {
            self.pin.set_low()?;
        } else {
            self.pin.set_high()?;
        }
        let changed = asserted != self.asserted;
        self.asserted = asserted;
        self.transitions += u32::from(changed);
        Ok(changed)
    }

    /// Whether the alarm is asserted (what was last written).
    pub fn is_asserted(&self) -> bool {
        self.asserted
    }

    /// Level changes so far.
    pub fn transitions(&self) -> u32 {
        self.transitions
    }
}

impl<P: StatefulOutputPin> FailSafeOutput<P> {
    /// The level the pin's output register holds, read back (true: LOW, the safe state).
    pub fn reads_low(&mut self) -> Result<bool, P::Error> {
        self.pin.is_set_low()
    }
}

/// How many readings of each kind the monitor gave.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, defmt::Format)]
pub struct Counts {
    /// Vouched speeds ([`SpeedReading::Rpm`]).
    pub vouched: u32,
    /// Speeds outside the table's range.
    pub out_of_range: u32,
    /// Pulses faster than the machine's limit.
    pub too_short: u32,
    /// Pulses under the bounce fraction of the period.
    pub bounce: u32,
    /// Periods too far off the last (a missed pulse or a step).
    pub step: u32,
    /// Speeds lost (no pulse for a revolution at the slowest measured speed).
    pub lost: u32,
    /// Capture overruns.
    pub overrun: u32,
    /// Readings while acquiring.
    pub acquiring: u32,
}

impl Counts {
    /// Counts one reading.
    pub fn add<T>(&mut self, r: &SpeedReading<T>) {
        let c = match r {
            SpeedReading::Rpm(_) => &mut self.vouched,
            SpeedReading::OutOfRange(_) => &mut self.out_of_range,
            SpeedReading::Rejected(Rejection::TooShort { .. }) => &mut self.too_short,
            SpeedReading::Rejected(Rejection::Bounce { .. }) => &mut self.bounce,
            SpeedReading::Rejected(Rejection::Step { .. }) => &mut self.step,
            SpeedReading::Lost => &mut self.lost,
            SpeedReading::Overrun => &mut self.overrun,
            SpeedReading::Acquiring => &mut self.acquiring,
        };
        *c += 1;
    }

    /// All readings.
    pub fn total(&self) -> u32 {
        self.vouched
            + self.out_of_range
            + self.too_short
            + self.bounce
            + self.step
            + self.lost
            + self.overrun
            + self.acquiring
    }
}

/// Logs the monitor's configuration (range, rejection and timeout periods, thresholds).
pub fn log_config(m: &ChipMonitor<f32>) {
    let (pulse, alarm) = (m.pulse(), m.alarm());
    defmt::info!(
        "index pulse: tick_hz={=u32}; table {=u32}..{=u32} rpm; periods under {=u32} ticks ({=u32} rpm) rejected; lost after {=u32} ticks ({=u32} rpm); bounce under {=u32} %, agreement within {=u32} %; alarm on at margin <= {=f32} rpm, off above {=f32} rpm",
        pulse.config().tick_hz,
        CHIP_RANGE_MIN_RPM,
        CHIP_RANGE_MAX_RPM,
        pulse.min_period_ticks(),
        CHIP_LIMIT_RPM,
        pulse.lost_period_ticks(),
        CHIP_LOST_RPM,
        CHIP_BOUNCE_PERCENT,
        CHIP_MAX_CHANGE_PERCENT,
        alarm.on_margin_rpm,
        alarm.off_margin_rpm
    );
}

/// Logs why a reading does not vouch for the speed (a warning for each fault; nothing
/// for a vouched speed, an info line while acquiring).
pub fn log_fault(m: &ChipMonitor<f32>, r: &SpeedReading<f32>) {
    match *r {
        SpeedReading::Rpm(_) => {}
        SpeedReading::OutOfRange(rpm) => defmt::warn!(
            "speed {=f32} rpm outside the table's {=u32}..{=u32} rpm: flagged, not extrapolated",
            rpm,
            CHIP_RANGE_MIN_RPM,
            CHIP_RANGE_MAX_RPM
        ),
        SpeedReading::Rejected(Rejection::TooShort { period_ticks }) => defmt::warn!(
            "pulse rejected: {=u32} ticks since the last, faster than {=u32} rpm (noise or bounce)",
            period_ticks,
            CHIP_LIMIT_RPM
        ),
        SpeedReading::Rejected(Rejection::Bounce { period_ticks }) => defmt::warn!(
            "pulse rejected: {=u32} ticks, under {=u32} % of the last period (bounce)",
            period_ticks,
            CHIP_BOUNCE_PERCENT
        ),
        SpeedReading::Rejected(Rejection::Step { period_ticks }) => defmt::warn!(
            "period rejected: {=u32} ticks, more than {=u32} % off the last (missed pulse or step)",
            period_ticks,
            CHIP_MAX_CHANGE_PERCENT
        ),
        SpeedReading::Lost => defmt::warn!(
            "speed lost: no index pulse for {=u32} ticks (a revolution at {=u32} rpm)",
            m.pulse().lost_period_ticks(),
            CHIP_LOST_RPM
        ),
        SpeedReading::Overrun => {
            defmt::warn!("capture overrun: an index edge was lost; acquiring again")
        }
        SpeedReading::Acquiring => defmt::info!("acquiring the speed (alarm asserted)"),
    }
}

/// Logs a change of the alarm output (`pin` names it, e.g. "PA5", "LED0").
pub fn log_alarm_change(pin: &str, step: &ChipStep<f32>) {
    match (step.alarm, step.prediction) {
        (true, Some(p)) => defmt::warn!(
            "alarm ASSERTED ({=str} low): rpm={=f32} speed_margin_rpm={=f32} <= {=f32}",
            pin,
            p.rpm,
            p.speed_margin_rpm,
            camsim_chip::CHIP_ALARM_ON_MARGIN_RPM as f32
        ),
        (true, None) => defmt::warn!(
            "alarm ASSERTED ({=str} low): {=str}",
            pin,
            step.reading.kind()
        ),
        (false, p) => defmt::info!(
            "alarm released ({=str} high): rpm={=f32} speed_margin_rpm={=f32} > {=f32}",
            pin,
            p.map_or(f32::NAN, |p| p.rpm),
            p.map_or(f32::NAN, |p| p.speed_margin_rpm),
            camsim_chip::CHIP_ALARM_OFF_MARGIN_RPM as f32
        ),
    }
}

/// A short name of a core error for the log (core::fmt would cost ~20 KB of flash).
pub fn error_name(e: &camsim_core::Error) -> &'static str {
    e.summary()
}
