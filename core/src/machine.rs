//! What a machine feeds the cam-timing predictor, and the alarm it drives.
//!
//! Hardware stays out of the core: a board adapts its timer capture or controller
//! link to [`SpeedSource`], and its alarm pin to the boolean that [`JumpAlarm`]
//! returns. The same code runs on the host (`camsim predict`) and on the chip.

use crate::Real;

/// A source of measured cam speed samples (rpm), e.g. from a once-per-revolution index pulse.
pub trait SpeedSource<T> {
    /// The next speed sample in rpm, or `None` when the source has no new sample (or has ended).
    fn next_rpm(&mut self) -> Option<T>;
}

/// Jump alarm with hysteresis: turns on when the speed margin to jump falls to
/// `on_margin_rpm` or below, and off only once it exceeds `off_margin_rpm`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JumpAlarm<T> {
    /// Margin (rpm below the jump-onset speed) at or under which the alarm turns on.
    pub on_margin_rpm: T,
    /// Margin above which an active alarm turns off (larger than `on_margin_rpm`).
    pub off_margin_rpm: T,
    active: bool,
}

impl<T: Real> JumpAlarm<T> {
    /// New alarm, initially off. `off_margin_rpm` must exceed `on_margin_rpm`.
    pub fn new(on_margin_rpm: T, off_margin_rpm: T) -> crate::Result<Self> {
        crate::finite("on_margin_rpm", on_margin_rpm)?;
        crate::finite("off_margin_rpm", off_margin_rpm)?;
        if off_margin_rpm <= on_margin_rpm {
            return Err(crate::Error::InvalidParameter {
                field: "off_margin_rpm",
                rule: "must exceed on_margin_rpm (hysteresis)",
                value: off_margin_rpm.to_f64(),
            });
        }
        Ok(Self {
            on_margin_rpm,
            off_margin_rpm,
            active: false,
        })
    }

    /// Whether the alarm is on.
    pub fn is_active(&self) -> bool {
        self.active
    }

    /// Feeds a new speed margin (jump-onset speed minus current speed, rpm); returns the alarm state.
    /// A NaN margin turns the alarm on (fail safe).
    pub fn update(&mut self, margin_rpm: T) -> bool {
        if margin_rpm.is_nan() || margin_rpm <= self.on_margin_rpm {
            self.active = true;
        } else if margin_rpm > self.off_margin_rpm {
            self.active = false;
        }
        self.active
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hysteresis_switches_at_both_thresholds() {
        let mut a = JumpAlarm::new(50.0f32, 100.0).unwrap();
        assert!(!a.update(200.0));
        assert!(!a.update(51.0));
        assert!(a.update(50.0));
        assert!(a.update(99.0)); // inside the band: stays on
        assert!(a.update(100.0));
        assert!(!a.update(100.5));
        assert!(!a.update(60.0)); // inside the band: stays off
        assert!(a.update(f32::NAN));
    }

    #[test]
    fn hysteresis_band_must_be_positive() {
        assert!(JumpAlarm::new(100.0f64, 100.0).is_err());
    }
}
