//! Cam speed from a once-per-revolution index pulse, without hardware.
//!
//! A board captures a free-running 32-bit timer on every edge of the index sensor (one
//! pulse per cam revolution) and hands the captured count to [`IndexPulse::capture`]; its
//! main loop also hands the current count to [`IndexPulse::poll`] so that a stopped
//! machine is noticed. Each capture yields a typed [`SpeedReading`]: a speed the
//! predictor may use ([`SpeedReading::Rpm`]), a measured speed outside the range its
//! table covers ([`SpeedReading::OutOfRange`], never extrapolated silently), a rejected
//! pulse ([`SpeedReading::Rejected`] with its [`Rejection`]), a lost speed
//! ([`SpeedReading::Lost`]), not enough pulses yet ([`SpeedReading::Acquiring`]) or an
//! edge the capture hardware lost ([`SpeedReading::Overrun`]).
//! Only [`SpeedReading::Rpm`] vouches for the speed; a board drives its alarm to the safe
//! state on every other reading (feed `NaN` to [`crate::JumpAlarm::update`]).
//!
//! What times the pulses is behind one small trait, [`CaptureTimer`] (the pending capture
//! and the counter now), and [`IndexPulse::service`] is the one loop step that reads it:
//! a board implements the trait with its timer's input capture, a scripted pulse train
//! (the QEMU image, the host's `camsim predict`) with a list of edge times, and both run
//! the same code from the captured count on.
//!
//! All tick arithmetic is integer (`u32` with wrapping differences, `u64` products); the
//! only floating-point operation is the final `rpm = 60 · tick_hz / period` in `T`.
//!
//! # The rules, in the order they are applied to a capture at count `t`
//! Let `p = t - t_ref` (wrapping `u32` difference) be the time since the reference
//! pulse, the last pulse taken as real, and `L` the last accepted period.
//! 1. No reference yet: `t` becomes the reference, [`SpeedReading::Acquiring`].
//! 2. `p` longer than one revolution at [`IndexPulseConfig::lost_rpm`] (the pulses had
//!    stopped and [`IndexPulse::poll`] was not called in time): [`SpeedReading::Lost`];
//!    `t` starts a new acquisition.
//! 3. `p` shorter than one revolution at [`IndexPulseConfig::limit_rpm`], the fastest
//!    the machine can turn: [`Rejection::TooShort`] (noise or bounce); the pulse is
//!    ignored, the reference stays.
//! 4. `p` shorter than [`IndexPulseConfig::bounce_percent`] % of `L`: [`Rejection::Bounce`];
//!    the pulse is ignored, the reference stays.
//! 5. `p` within [`IndexPulseConfig::max_change_percent`] % of `L`: accepted.
//! 6. `p` within that band of the previous unconfirmed period (the candidate): accepted
//!    (a genuine speed change, confirmed by a second revolution).
//! 7. Otherwise the pulse becomes the reference but its period is not believed: with an
//!    `L`, [`Rejection::Step`] (a missed pulse, or a change faster than a cam shaft makes
//!    in one revolution); without one, [`SpeedReading::Acquiring`]. The period becomes the
//!    candidate, unless the span contained an ignored pulse (then the next period must
//!    agree with `L`: otherwise a train faster than `limit_rpm`, whose every other pulse
//!    is ignored, would read as half its speed).
//!
//! An accepted period gives [`SpeedReading::Rpm`] if `min_rpm <= rpm <= max_rpm`
//! (checked exactly in integers), [`SpeedReading::OutOfRange`] otherwise.
//! After [`SpeedReading::Lost`] or [`IndexPulse::resync`], the first reading needs three
//! pulses (two agreeing periods).
//!
//! What timing alone cannot tell: a sensor that from some revolution on misses every
//! other pulse looks like the speed halving within one revolution; it is rejected once
//! ([`Rejection::Step`]) and then believed. A second sensor or a comparison with the
//! drive's commanded speed catches that.
//!
//! # Range and resolution of a 32-bit capture timer
//! A speed `n` (rpm) gives a period of `N = 60 f / n` ticks at tick rate `f`; one tick of
//! period error moves the speed by `Δn = n / N = n² / (60 f)`, and a capture is exact to
//! one tick at each end, so a reading is within `n² / (60 f)` of the true mean speed over
//! the revolution (plus two roundings of `T`). The slowest speed a 32-bit counter
//! measures is one revolution per wrap, `60 f / (2³² − 1)`.
//!
//! | tick rate | wrap (slowest speed) | Δn at 300 rpm | Δn at 800 rpm | Δn at 1600 rpm |
//! | --- | --- | --- | --- | --- |
//! | 1 MHz (STM32F446 TIM2, prescaler 90) | 4295 s (0.0140 rpm) | 0.0015 rpm | 0.0107 rpm | 0.0427 rpm |
//! | 90 MHz (TIM2 undivided at 180 MHz) | 47.7 s (1.26 rpm) | 1.7e-5 rpm | 1.2e-4 rpm | 4.7e-4 rpm |
//!
//! `f32` carries a speed near 800 rpm to 6.1e-5 rpm, finer than a 1 MHz tick.
//! [`IndexPulse::poll`] must see the counter at least once per wrap minus the timeout
//! (over an hour at 1 MHz), or a wrapped difference hides the gap.

use core::marker::PhantomData;

use crate::{Error, Real, Result};

/// How the index pulse is timed and which speeds are believed (all integers: rpm and ticks).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IndexPulseConfig {
    /// Tick rate of the capture timer, Hz.
    pub tick_hz: u32,
    /// Slowest speed the predictor's table covers, rpm: slower readings are
    /// [`SpeedReading::OutOfRange`].
    pub min_rpm: u32,
    /// Fastest speed the predictor's table covers, rpm: faster readings are
    /// [`SpeedReading::OutOfRange`].
    pub max_rpm: u32,
    /// Fastest speed the machine can turn, rpm: a shorter period is noise
    /// ([`Rejection::TooShort`]). At least `max_rpm`.
    pub limit_rpm: u32,
    /// Slowest speed still measured, rpm: no pulse for longer than one revolution at this
    /// speed is [`SpeedReading::Lost`]. At most `min_rpm`, so speeds between the two are
    /// reported (as [`SpeedReading::OutOfRange`]) before the speed counts as lost.
    pub lost_rpm: u32,
    /// A period shorter than this percentage of the last accepted one is a bounce
    /// ([`Rejection::Bounce`]). 1..=99; with `max_change_percent` at most 100, so that no
    /// period is both a bounce and in agreement.
    pub bounce_percent: u32,
    /// Two periods agree when they differ by at most this percentage of the earlier one:
    /// the largest speed change per revolution taken as genuine without confirmation. 1..=99.
    pub max_change_percent: u32,
}

impl IndexPulseConfig {
    /// Timer ticks per minute (`60 · tick_hz`).
    pub fn ticks_per_minute(&self) -> u64 {
        60 * u64::from(self.tick_hz)
    }

    /// Period of one revolution at `rpm`, ticks, rounded down (`None` for 0 rpm).
    pub fn period_ticks(&self, rpm: u32) -> Option<u64> {
        self.ticks_per_minute().checked_div(u64::from(rpm))
    }

    /// Checks the rules stated on each field.
    pub fn validate(&self) -> Result<()> {
        fn bad(field: &'static str, rule: &'static str, value: u64) -> Error {
            // u64 to f64 rounds above 2^53: only on the error path, for the message.
            Error::InvalidParameter {
                field,
                rule,
                value: value as f64,
            }
        }
        let c = self;
        if c.tick_hz == 0 {
            return Err(bad("tick_hz", "must be positive", 0));
        }
        if c.lost_rpm == 0 {
            return Err(bad("lost_rpm", "must be positive", 0));
        }
        if c.lost_rpm > c.min_rpm {
            return Err(bad(
                "lost_rpm",
                "must not exceed min_rpm",
                u64::from(c.lost_rpm),
            ));
        }
        if c.min_rpm >= c.max_rpm {
            return Err(bad(
                "min_rpm",
                "must be below max_rpm",
                u64::from(c.min_rpm),
            ));
        }
        if c.limit_rpm < c.max_rpm {
            return Err(bad(
                "limit_rpm",
                "must be at least max_rpm",
                u64::from(c.limit_rpm),
            ));
        }
        let lost = self.ticks_per_minute().div_ceil(u64::from(c.lost_rpm));
        if lost > u64::from(u32::MAX) {
            return Err(bad(
                "lost_rpm",
                "one revolution at lost_rpm must fit the 32-bit timer (raise lost_rpm or lower tick_hz)",
                u64::from(c.lost_rpm),
            ));
        }
        // One tick is at most 1 % of a revolution at the table's fastest speed.
        if self.ticks_per_minute() < 100 * u64::from(c.max_rpm) {
            return Err(bad(
                "tick_hz",
                "must give at least 100 ticks per revolution at max_rpm",
                u64::from(c.tick_hz),
            ));
        }
        if !(1..=99).contains(&c.max_change_percent) {
            return Err(bad(
                "max_change_percent",
                "must lie in 1..=99",
                u64::from(c.max_change_percent),
            ));
        }
        if !(1..=99).contains(&c.bounce_percent) {
            return Err(bad(
                "bounce_percent",
                "must lie in 1..=99",
                u64::from(c.bounce_percent),
            ));
        }
        if c.bounce_percent + c.max_change_percent > 100 {
            return Err(bad(
                "bounce_percent",
                "plus max_change_percent must not exceed 100 (a bounce never agrees)",
                u64::from(c.bounce_percent),
            ));
        }
        Ok(())
    }
}

/// Why a pulse was not used for a speed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rejection {
    /// Shorter than one revolution at [`IndexPulseConfig::limit_rpm`]: noise or a bounce.
    /// The pulse is ignored; the reference pulse stays.
    TooShort {
        /// Ticks since the reference pulse.
        period_ticks: u32,
    },
    /// Shorter than [`IndexPulseConfig::bounce_percent`] % of the last accepted period:
    /// a bounce. The pulse is ignored; the reference pulse stays.
    Bounce {
        /// Ticks since the reference pulse.
        period_ticks: u32,
    },
    /// Differs from the last accepted period by more than
    /// [`IndexPulseConfig::max_change_percent`] %: a missed pulse, or a speed change
    /// faster than a cam shaft makes in one revolution. The pulse becomes the reference;
    /// the period is believed only once the next one agrees with it.
    Step {
        /// Ticks since the reference pulse.
        period_ticks: u32,
    },
}

/// What one capture (or a timeout) says about the cam speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpeedReading<T> {
    /// Measured speed inside the predictor's range, rpm: the only reading that vouches
    /// for the speed.
    Rpm(T),
    /// Measured speed outside `min_rpm..=max_rpm`, rpm: the table does not cover it (not
    /// extrapolated).
    OutOfRange(T),
    /// The pulse was not used.
    Rejected(Rejection),
    /// No pulse for longer than one revolution at [`IndexPulseConfig::lost_rpm`]: the
    /// machine stopped or the sensor failed. A new acquisition starts.
    Lost,
    /// Not enough consistent pulses yet (after start, [`SpeedReading::Lost`] or
    /// [`IndexPulse::resync`]).
    Acquiring,
    /// The capture hardware lost an edge ([`CaptureEvent::Overrun`]): every pulse is
    /// forgotten and the later edge starts a new acquisition.
    Overrun,
}

impl<T: Copy> SpeedReading<T> {
    /// The speed if the reading vouches for it ([`SpeedReading::Rpm`]), else `None`.
    pub fn vouched_rpm(&self) -> Option<T> {
        match self {
            SpeedReading::Rpm(r) => Some(*r),
            _ => None,
        }
    }

    /// A short name of the reading for logs: `rpm`, `out_of_range`, `too_short`,
    /// `bounce`, `step`, `lost`, `acquiring` or `overrun`.
    pub fn kind(&self) -> &'static str {
        match self {
            SpeedReading::Rpm(_) => "rpm",
            SpeedReading::OutOfRange(_) => "out_of_range",
            SpeedReading::Rejected(Rejection::TooShort { .. }) => "too_short",
            SpeedReading::Rejected(Rejection::Bounce { .. }) => "bounce",
            SpeedReading::Rejected(Rejection::Step { .. }) => "step",
            SpeedReading::Lost => "lost",
            SpeedReading::Acquiring => "acquiring",
            SpeedReading::Overrun => "overrun",
        }
    }
}

impl Rejection {
    /// Ticks since the reference pulse.
    pub fn period_ticks(&self) -> u32 {
        match *self {
            Rejection::TooShort { period_ticks }
            | Rejection::Bounce { period_ticks }
            | Rejection::Step { period_ticks } => period_ticks,
        }
    }
}

/// What a [`CaptureTimer`] has for the speed measurement at one poll.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CaptureEvent {
    /// The count latched at an index edge.
    Edge(u32),
    /// Two edges came before the first was read: one is lost. The count is the later one.
    Overrun(u32),
}

/// The timer that captures the index pulse: what a board implements with its hardware
/// (a free-running 32-bit timer with input capture) and a scripted pulse train with a
/// list of edge times, so that both feed [`IndexPulse::service`] the same way.
pub trait CaptureTimer {
    /// Tick rate of the counter, Hz.
    fn tick_hz(&self) -> u32;
    /// The capture pending since the last call, if any (each edge is returned once).
    fn poll_capture(&mut self) -> Option<CaptureEvent>;
    /// The free-running counter now, ticks (for the timeout of a lost speed).
    fn now(&mut self) -> u32;
}

/// The index-pulse state machine (see the module documentation for its rules).
#[derive(Clone, Copy, Debug)]
pub struct IndexPulse<T> {
    config: IndexPulseConfig,
    /// Periods shorter than this are [`Rejection::TooShort`].
    min_period: u32,
    /// Gaps longer than this are [`SpeedReading::Lost`].
    lost_period: u32,
    /// The reference pulse: the last pulse taken as real.
    reference: Option<u32>,
    /// The last accepted period.
    accepted: Option<u32>,
    /// The last period not believed yet (waits for an agreeing one).
    candidate: Option<u32>,
    /// A pulse was ignored since the reference.
    spans_ignored: bool,
    _real: PhantomData<fn() -> T>,
}

impl<T: Real> IndexPulse<T> {
    /// A state machine waiting for its first pulse; fails if `config` breaks its rules.
    pub fn new(config: IndexPulseConfig) -> Result<Self> {
        config.validate()?;
        let tpm = config.ticks_per_minute();
        // Validated: the rpm are positive and one revolution at lost_rpm fits a u32;
        // the period at limit_rpm is shorter still.
        let min_period = u32::try_from(tpm / u64::from(config.limit_rpm.max(1)))
            .unwrap_or(u32::MAX)
            .max(1);
        let lost_period =
            u32::try_from(tpm.div_ceil(u64::from(config.lost_rpm.max(1)))).unwrap_or(u32::MAX);
        Ok(Self {
            config,
            min_period,
            lost_period,
            reference: None,
            accepted: None,
            candidate: None,
            spans_ignored: false,
            _real: PhantomData,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &IndexPulseConfig {
        &self.config
    }

    /// Shortest period accepted, ticks (one revolution at `limit_rpm`, rounded down).
    pub fn min_period_ticks(&self) -> u32 {
        self.min_period
    }

    /// Longest gap before the speed is lost, ticks (one revolution at `lost_rpm`, rounded up).
    pub fn lost_period_ticks(&self) -> u32 {
        self.lost_period
    }

    /// The last accepted period, ticks.
    pub fn last_period_ticks(&self) -> Option<u32> {
        self.accepted
    }

    /// Forgets every pulse (for example after the capture hardware lost one): the next
    /// reading needs a new acquisition.
    pub fn resync(&mut self) {
        self.reference = None;
        self.accepted = None;
        self.candidate = None;
        self.spans_ignored = false;
    }

    /// Checks for a timeout at timer count `now`: `Some(Lost)` once when no pulse came
    /// for longer than one revolution at `lost_rpm` (then a new acquisition starts),
    /// `None` otherwise. Call it at least once per counter wrap.
    pub fn poll(&mut self, now: u32) -> Option<SpeedReading<T>> {
        let reference = self.reference?;
        if now.wrapping_sub(reference) > self.lost_period {
            self.resync();
            return Some(SpeedReading::Lost);
        }
        None
    }

    /// One step of a main loop: reads `timer` once and returns the reading it gives, if
    /// any. A capture goes to [`Self::capture`]; an overrun forgets every pulse
    /// ([`Self::resync`]), starts a new acquisition with the later edge and reads
    /// [`SpeedReading::Overrun`]; without a capture the counter goes to [`Self::poll`] (a
    /// lost speed). Call it at least once per counter wrap.
    pub fn service<C: CaptureTimer + ?Sized>(&mut self, timer: &mut C) -> Option<SpeedReading<T>> {
        match timer.poll_capture() {
            Some(CaptureEvent::Edge(t)) => Some(self.capture(t)),
            Some(CaptureEvent::Overrun(t)) => {
                self.resync();
                // The first pulse of an acquisition only becomes the reference.
                let _ = self.capture(t);
                Some(SpeedReading::Overrun)
            }
            None => {
                let now = timer.now();
                self.poll(now)
            }
        }
    }

    /// Feeds the timer count captured at an index pulse.
    pub fn capture(&mut self, ticks: u32) -> SpeedReading<T> {
        let Some(reference) = self.reference else {
            self.reference = Some(ticks);
            return SpeedReading::Acquiring;
        };
        let p = ticks.wrapping_sub(reference);
        if p > self.lost_period {
            self.resync();
            self.reference = Some(ticks);
            return SpeedReading::Lost;
        }
        if p < self.min_period {
            self.spans_ignored = true;
            return SpeedReading::Rejected(Rejection::TooShort { period_ticks: p });
        }
        if let Some(l) = self.accepted {
            if u64::from(p) * 100 < u64::from(l) * u64::from(self.config.bounce_percent) {
                self.spans_ignored = true;
                return SpeedReading::Rejected(Rejection::Bounce { period_ticks: p });
            }
        }
        let spans_ignored = self.spans_ignored;
        self.reference = Some(ticks);
        self.spans_ignored = false;
        let agrees_with = |q: Option<u32>| q.is_some_and(|q| self.agree(p, q));
        if agrees_with(self.accepted) || (!spans_ignored && agrees_with(self.candidate)) {
            self.accepted = Some(p);
            self.candidate = None;
            return self.reading(p);
        }
        self.candidate = if spans_ignored { None } else { Some(p) };
        if self.accepted.is_some() {
            SpeedReading::Rejected(Rejection::Step { period_ticks: p })
        } else {
            SpeedReading::Acquiring
        }
    }

    /// Whether period `p` lies within `max_change_percent` of the earlier period `q`.
    fn agree(&self, p: u32, q: u32) -> bool {
        u64::from(p.abs_diff(q)) * 100 <= u64::from(q) * u64::from(self.config.max_change_percent)
    }

    /// The reading of an accepted period `p` (> 0: at least `min_period` >= 1 tick).
    fn reading(&self, p: u32) -> SpeedReading<T> {
        let c = &self.config;
        let tpm = c.ticks_per_minute();
        // rpm = tpm / p; the range test in exact integers.
        let in_range = tpm >= u64::from(c.min_rpm) * u64::from(p)
            && tpm <= u64::from(c.max_rpm) * u64::from(p);
        let rpm = T::from_usize(c.tick_hz as usize) * T::from_i32(60) / T::from_usize(p as usize);
        if in_range {
            SpeedReading::Rpm(rpm)
        } else {
            SpeedReading::OutOfRange(rpm)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn config() -> IndexPulseConfig {
        IndexPulseConfig {
            tick_hz: 1_000_000,
            min_rpm: 300,
            max_rpm: 800,
            limit_rpm: 1600,
            lost_rpm: 150,
            bounce_percent: 25,
            max_change_percent: 25,
        }
    }

    #[test]
    fn derived_periods() {
        let ip = IndexPulse::<f32>::new(config()).unwrap();
        assert_eq!(ip.min_period_ticks(), 37_500); // 60e6 / 1600
        assert_eq!(ip.lost_period_ticks(), 400_000); // 60e6 / 150
    }

    #[test]
    fn each_rule_of_the_config_refuses() {
        let ok = config();
        assert!(ok.validate().is_ok());
        let cases: [(IndexPulseConfig, &str); 9] = [
            (IndexPulseConfig { tick_hz: 0, ..ok }, "tick_hz"),
            (IndexPulseConfig { lost_rpm: 0, ..ok }, "lost_rpm"),
            (
                IndexPulseConfig {
                    lost_rpm: 301,
                    ..ok
                },
                "lost_rpm",
            ),
            (IndexPulseConfig { min_rpm: 800, ..ok }, "min_rpm"),
            (
                IndexPulseConfig {
                    limit_rpm: 799,
                    ..ok
                },
                "limit_rpm",
            ),
            // 60 · 90 MHz / 1 rpm does not fit 32 bits.
            (
                IndexPulseConfig {
                    tick_hz: 90_000_000,
                    lost_rpm: 1,
                    ..ok
                },
                "lost_rpm",
            ),
            // 60 · 1 kHz = 60 000 ticks/min < 100 · 800.
            (
                IndexPulseConfig {
                    tick_hz: 1_000,
                    ..ok
                },
                "tick_hz",
            ),
            (
                IndexPulseConfig {
                    max_change_percent: 0,
                    ..ok
                },
                "max_change_percent",
            ),
            (
                IndexPulseConfig {
                    bounce_percent: 80,
                    ..ok
                },
                "bounce_percent",
            ),
        ];
        for (c, field) in cases {
            match IndexPulse::<f64>::new(c) {
                Err(Error::InvalidParameter { field: f, .. }) => assert_eq!(f, field, "{c:?}"),
                other => panic!("{c:?}: {other:?}"),
            }
        }
    }
}
