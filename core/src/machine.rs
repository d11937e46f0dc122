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

use core::ops::ControlFlow;

use crate::{
    simulate, CamModel, Design, Observer, OnsetSearch, Result, Sample, Scene, SegmentKind,
    SolverSettings,
};

/// Fractions of a rise or return at which the follower's timing is measured.
pub const TIMING_FRACTIONS: [f64; 3] = [0.1, 0.5, 0.9];
/// Timing points: the fractions of the first rise, then of the first return.
pub const TIMING_POINTS: usize = 6;

/// Where the theoretical lift crosses a level: the cam angle (degrees) and the level.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimingPoint<T> {
    /// Lift level, in.
    pub level: T,
    /// Theoretical crossing angle, degrees within the revolution.
    pub theory_deg: T,
    /// +1 for a rise (upward crossing), -1 for a return.
    pub direction: i8,
    /// Search window start (segment start), degrees.
    pub from_deg: T,
    /// Search window end, degrees (segment end plus a margin).
    pub to_deg: T,
}

/// The timing points of a program: 10, 50 and 90 % of its first rise and first return.
pub fn timing_points<T: Real, const N: usize>(
    program: &crate::CamProgram<T, N>,
) -> [TimingPoint<T>; TIMING_POINTS] {
    let mut out = [TimingPoint::default(); TIMING_POINTS];
    let mut level = T::ZERO;
    let mut rise_done = false;
    let mut ret_done = false;
    for s in program.segments() {
        let (slot, dir, base) = match s.kind {
            SegmentKind::Rise(_) if !rise_done => (0, 1i8, level),
            SegmentKind::Return(_) if !ret_done => (3, -1i8, level),
            _ => (usize::MAX, 0, level),
        };
        match s.kind {
            SegmentKind::Rise(_) => level += s.lift,
            SegmentKind::Return(_) => level -= s.lift,
            SegmentKind::Dwell => {}
        }
        if slot == usize::MAX {
            continue;
        }
        if dir > 0 {
            rise_done = true;
        } else {
            ret_done = true;
        }
        for (k, frac) in TIMING_FRACTIONS.iter().enumerate() {
            let f = T::from_f64(*frac);
            let target = if dir > 0 {
                base + f * s.lift
            } else {
                base - f * s.lift
            };
            // Bisection on the monotone segment for the theoretical crossing angle.
            let (mut a, mut b) = (s.start_deg, s.end_deg);
            for _ in 0..60 {
                let m = (a + b) * T::HALF;
                let y = program.follower(m.to_radians()).y;
                let below = if dir > 0 { y < target } else { y > target };
                if below {
                    a = m;
                } else {
                    b = m;
                }
            }
            if let Some(p) = out.get_mut(slot + k) {
                *p = TimingPoint {
                    level: target,
                    theory_deg: (a + b) * T::HALF,
                    direction: dir,
                    from_deg: s.start_deg,
                    to_deg: s.end_deg + T::from_f64(30.0),
                };
            }
        }
    }
    out
}

/// Steady-state figures of one revolution: contact-force margin, jump, timing errors.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SteadyState<T> {
    /// Smallest contact force over the revolution, lb (the margin to separation).
    pub min_contact_force: T,
    /// Cam angle of the smallest contact force, degrees.
    pub min_force_deg: T,
    /// Whether the follower separated.
    pub jumped: bool,
    /// Load timing error at each timing point, degrees of cam angle (positive: the load lags
    /// the theoretical law). NaN where the load never crossed the level in its window.
    pub timing_deg: [T; TIMING_POINTS],
}

/// Observer that measures [`SteadyState`] in one revolution.
pub struct SteadyStateObserver<T> {
    revolution: u32,
    points: [TimingPoint<T>; TIMING_POINTS],
    prev: Option<(T, T)>,
    /// The result so far.
    pub result: SteadyState<T>,
    seen: bool,
}

impl<T: Real> SteadyStateObserver<T> {
    /// Measures `revolution` (from 1) against the program's timing points.
    pub fn new(revolution: u32, points: [TimingPoint<T>; TIMING_POINTS]) -> Self {
        let nan = T::NAN;
        Self {
            revolution,
            points,
            prev: None,
            result: SteadyState {
                min_contact_force: T::INFINITY,
                min_force_deg: T::ZERO,
                jumped: false,
                timing_deg: [nan; TIMING_POINTS],
            },
            seen: false,
        }
    }
}

impl<T: Real> Observer<T> for SteadyStateObserver<T> {
    fn needs_stress(&self) -> bool {
        false
    }
    fn observe(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        if s.revolution < self.revolution {
            return ControlFlow::Continue(());
        }
        if s.revolution > self.revolution {
            return ControlFlow::Break(());
        }
        self.seen = true;
        let p = &s.point;
        if p.contact_force < self.result.min_contact_force {
            self.result.min_contact_force = p.contact_force;
            self.result.min_force_deg = s.angle_deg;
        }
        self.result.jumped |= !p.in_contact;
        let y = p.load_displacement();
        let a = s.angle_deg;
        if let Some((a0, y0)) = self.prev {
            for (tp, out) in self.points.iter().zip(self.result.timing_deg.iter_mut()) {
                if !out.is_nan() || a < tp.from_deg || a0 > tp.to_deg || tp.direction == 0 {
                    continue;
                }
                let crossed = if tp.direction > 0 {
                    y0 < tp.level && y >= tp.level
                } else {
                    y0 > tp.level && y <= tp.level
                };
                if crossed && y != y0 {
                    let ang = a0 + (a - a0) * (tp.level - y0) / (y - y0);
                    *out = ang - tp.theory_deg;
                }
            }
        }
        self.prev = Some((a, y));
        ControlFlow::Continue(())
    }
}

/// Simulates the design at `rpm` for two revolutions and measures the steady state
/// (the second revolution) with the model of scene `S` (`N = S::N`).
pub fn steady_state_at<T: Real, S: Scene, const N: usize>(
    design: &Design<T>,
    rpm: T,
    settings: &SolverSettings<T>,
) -> Result<SteadyState<T>> {
    let mut d = design.clone();
    d.set_speed_rpm(rpm)?;
    let points = timing_points(&d.program);
    let model = CamModel::<T, S, N>::new(d)?;
    let mut obs = SteadyStateObserver::new(2, points);
    simulate(&model, settings, 2, &mut obs)?;
    Ok(obs.result)
}

/// A table of steady-state predictions over a grid of `G` speeds, computed once at boot,
/// interpolated linearly in the loop.
#[derive(Clone, Debug)]
pub struct PredictionTable<T, const G: usize> {
    /// Grid speeds, rpm, ascending.
    pub rpm: [T; G],
    /// Steady state at each grid speed.
    pub at: [SteadyState<T>; G],
    /// Jump-onset speed, rpm (None: no jump up to the search limit).
    pub jump_rpm: Option<T>,
}

/// What the predictor says for one measured speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpeedPrediction<T> {
    /// The measured speed, rpm.
    pub rpm: T,
    /// Interpolated smallest contact force, lb (the force margin to separation).
    pub force_margin_lb: T,
    /// Jump-onset speed minus the measured speed, rpm (infinite if no jump was found).
    pub speed_margin_rpm: T,
    /// Interpolated timing errors, degrees.
    pub timing_deg: [T; TIMING_POINTS],
    /// False when the speed lies outside the grid (values clamped to the nearest end).
    pub in_grid: bool,
}

impl<T: Real, const G: usize> PredictionTable<T, G> {
    /// Computes the table: the steady state at every grid speed and the jump-onset speed
    /// ([`OnsetSearch`]: bisection to `resolution_rpm` between the grid's fastest speed
    /// without a jump and the first speed with one; without a jump on the grid, `max_rpm`
    /// is tried and the bracket up to it bisected).
    pub fn build<S: Scene, const N: usize>(
        design: &Design<T>,
        rpm: [T; G],
        max_rpm: T,
        resolution_rpm: T,
        settings: &SolverSettings<T>,
    ) -> Result<Self> {
        let mut at = [SteadyState::default(); G];
        let mut prev = T::ZERO;
        for (r, a) in rpm.iter().zip(at.iter_mut()) {
            if r.partial_cmp(&prev) != Some(core::cmp::Ordering::Greater) {
                return Err(crate::Error::InvalidParameter {
                    field: "grid rpm",
                    rule: "must be positive and strictly ascending",
                    value: r.to_f64(),
                });
            }
            prev = *r;
            *a = steady_state_at::<T, S, N>(design, *r, settings)?;
        }
        // Bracket the onset from the grid where possible: the fastest grid speed without
        // a jump below the first one with a jump.
        let mut below = None;
        let mut above = None;
        for (r, a) in rpm.iter().zip(at.iter()) {
            if a.jumped {
                above = Some(*r);
                break;
            }
            below = Some(*r);
        }
        let jumps = |r: T| steady_state_at::<T, S, N>(design, r, settings).map(|s| s.jumped);
        let jump_rpm = match (below, above) {
            // The slowest grid speed jumps already.
            (None, Some(first)) => Some(first),
            (None, None) => {
                return Err(crate::Error::InvalidParameter {
                    field: "grid rpm",
                    rule: "must hold at least one speed",
                    value: 0.0,
                })
            }
            // The grid shows contact at `lo` and a jump at `hi`: bisect between them.
            (Some(lo), Some(hi)) => OnsetSearch::new(lo, None, hi, resolution_rpm)?
                .bisect(lo, hi, jumps)?
                .at(),
            // No jump on the grid, which reaches the search limit.
            (Some(lo), None) if lo >= max_rpm => None,
            // No jump on the grid: try `max_rpm`, bisect if it jumps.
            (Some(lo), None) => OnsetSearch::new(lo, None, max_rpm, resolution_rpm)?
                .find_above(jumps)?
                .at(),
        };
        Ok(Self { rpm, at, jump_rpm })
    }

    /// Interpolates the prediction at a measured speed.
    pub fn predict(&self, rpm: T) -> SpeedPrediction<T> {
        let nan = T::NAN;
        let speed_margin_rpm = match self.jump_rpm {
            Some(j) => j - rpm,
            None => T::INFINITY,
        };
        let mut out = SpeedPrediction {
            rpm,
            force_margin_lb: nan,
            speed_margin_rpm,
            timing_deg: [nan; TIMING_POINTS],
            in_grid: false,
        };
        let (Some(first), Some(last)) = (self.rpm.first(), self.rpm.last()) else {
            return out;
        };
        let pick = |i: usize, j: usize, w: T, out: &mut SpeedPrediction<T>| {
            if let (Some(a), Some(b)) = (self.at.get(i), self.at.get(j)) {
                out.force_margin_lb =
                    a.min_contact_force + w * (b.min_contact_force - a.min_contact_force);
                for k in 0..TIMING_POINTS {
                    if let (Some(x), Some(y), Some(o)) = (
                        a.timing_deg.get(k),
                        b.timing_deg.get(k),
                        out.timing_deg.get_mut(k),
                    ) {
                        *o = *x + w * (*y - *x);
                    }
                }
            }
        };
        if rpm
            .partial_cmp(first)
            .is_none_or(|o| o == core::cmp::Ordering::Less)
        {
            pick(0, 0, T::ZERO, &mut out);
            return out;
        }
        if rpm >= *last {
            out.in_grid = rpm == *last;
            pick(G - 1, G - 1, T::ZERO, &mut out);
            return out;
        }
        for i in 0..G.saturating_sub(1) {
            if let (Some(a), Some(b)) = (self.rpm.get(i), self.rpm.get(i + 1)) {
                if rpm >= *a && rpm < *b {
                    let w = (rpm - *a) / (*b - *a);
                    out.in_grid = true;
                    pick(i, i + 1, w, &mut out);
                    break;
                }
            }
        }
        out
    }
}

/// The predictor scene compiled into the chip, in ONE place read by the firmware and by
/// `camsim predict` (host parity): the scene, solver settings, speed grid,
/// bisection resolution, alarm thresholds and the scripted speed profile.
///
/// Chosen by measurement (firmware/README.md): the full 22-state model costs more per
/// evaluation and needs more steps than the vertical 16-state one for the same jump
/// speed; rtol 1e-3 (the thesis ran at 2 %) with atol 1e-7 in keeps the f32 jump speed
/// within about 1 rpm and the contact-force margin within about 0.3 lb of the f64 model.
pub mod predictor_scene {
    use crate::{
        CamModel, Design, JumpAlarm, PredictionTable, Real, RegulatedVertical, Result, Scene,
        SolverSettings, SpeedSource,
    };

    /// The chip's scene: regulated drive, vertical DOFs only.
    pub type ChipScene = RegulatedVertical;
    /// State size of the chip's model (6 + 2·5 = 16).
    pub const CHIP_STATES: usize = <ChipScene as Scene>::N;
    /// The chip's model type.
    pub type ChipModel<T> = CamModel<T, ChipScene, CHIP_STATES>;
    /// Number of grid speeds of the boot-time table.
    pub const CHIP_GRID: usize = 10;
    /// Grid speeds of the boot-time table, rpm (ascending; denser near the jump).
    pub const CHIP_GRID_RPM: [f64; CHIP_GRID] = [
        300.0, 400.0, 500.0, 550.0, 600.0, 625.0, 650.0, 675.0, 700.0, 800.0,
    ];
    /// Upper limit of the jump search when no grid speed jumps, rpm.
    pub const CHIP_MAX_RPM: f64 = 1000.0;
    /// Resolution of the jump-onset bisection, rpm.
    pub const CHIP_RESOLUTION_RPM: f64 = 1.0;
    /// Speeds between grid points where the boot check compares the interpolated
    /// prediction with a direct simulation, rpm.
    pub const CHIP_CHECK_RPM: [f64; 3] = [450.0, 575.0, 660.0];
    /// The jump alarm turns on at this speed margin (rpm) or less.
    pub const CHIP_ALARM_ON_MARGIN_RPM: f64 = 50.0;
    /// An active jump alarm turns off once the speed margin exceeds this (rpm).
    pub const CHIP_ALARM_OFF_MARGIN_RPM: f64 = 100.0;

    /// The design compiled into the chip and run by the host's parity check: the reference
    /// design of VI.1. Another scene is chosen here at build time (never parsed on the chip).
    pub fn chip_design<T: Real>() -> Design<T> {
        Design::reference()
    }

    /// Solver settings of the chip's predictor: rtol 1e-3, atol 1e-8 in, at most 1/500
    /// revolution per double step, from static equilibrium. The thesis's all-zero start
    /// leaves a start-up impact whose lightly damped roller chatter is still there in the
    /// second revolution, so it is not a steady state: with it the jump speed moves from
    /// 698 to 668 rpm and depends on the tolerance; from static equilibrium it converges
    /// (697.7 rpm at rtol 1e-3, 698.4 rpm at 1e-4 to 1e-7: `camsim jump-speed --rtol X`).
    pub fn chip_solver_settings<T: Real>() -> SolverSettings<T> {
        SolverSettings {
            rtol: T::from_f64(1e-3),
            atol: T::from_f64(1e-8),
            max_step_fraction: T::from_f64(1.0 / 500.0),
            max_steps_per_rev: 2_000_000,
            start: crate::Start::Static,
        }
    }

    /// [`CHIP_GRID_RPM`] in `T`.
    pub fn chip_grid_rpm<T: Real>() -> [T; CHIP_GRID] {
        CHIP_GRID_RPM.map(T::from_f64)
    }

    /// Builds the chip's prediction table for `design` (the boot-time computation).
    pub fn chip_prediction_table<T: Real>(
        design: &Design<T>,
    ) -> Result<PredictionTable<T, CHIP_GRID>> {
        PredictionTable::build::<ChipScene, CHIP_STATES>(
            design,
            chip_grid_rpm(),
            T::from_f64(CHIP_MAX_RPM),
            T::from_f64(CHIP_RESOLUTION_RPM),
            &chip_solver_settings(),
        )
    }

    /// The direct steady state at `rpm` with the chip's model (for the interpolation check).
    pub fn chip_steady_state<T: Real>(design: &Design<T>, rpm: T) -> Result<crate::SteadyState<T>> {
        crate::steady_state_at::<T, ChipScene, CHIP_STATES>(design, rpm, &chip_solver_settings())
    }

    /// The chip's jump alarm (thresholds [`CHIP_ALARM_ON_MARGIN_RPM`], [`CHIP_ALARM_OFF_MARGIN_RPM`]).
    pub fn chip_alarm<T: Real>() -> Result<JumpAlarm<T>> {
        JumpAlarm::new(
            T::from_f64(CHIP_ALARM_ON_MARGIN_RPM),
            T::from_f64(CHIP_ALARM_OFF_MARGIN_RPM),
        )
    }

    /// Scripted cam speed for the QEMU run and the host: a ramp 300 -> 600 rpm in 25 rpm
    /// steps, a step up to 700 rpm, a ramp to 900 rpm, then back down to 300 rpm in 25 rpm
    /// steps (46 samples, one per revolution).
    #[derive(Clone, Debug)]
    pub struct ScriptedProfile {
        next: Option<i32>,
        rising: bool,
    }

    impl ScriptedProfile {
        /// Lowest speed, rpm.
        pub const LOW_RPM: i32 = 300;
        /// Highest speed, rpm.
        pub const HIGH_RPM: i32 = 900;
        /// Ramp increment per sample, rpm.
        pub const STEP_RPM: i32 = 25;
        /// Speed after which the step up happens, rpm.
        pub const STEP_AT_RPM: i32 = 600;
        /// Speed the step goes to, rpm.
        pub const STEP_TO_RPM: i32 = 700;
        /// Samples in the whole profile: 13 (300..=600) + 9 (700..=900) + 24 (875..=300).
        pub const SAMPLES: usize = 46;

        /// The profile from its first sample.
        pub fn new() -> Self {
            Self {
                next: Some(Self::LOW_RPM),
                rising: true,
            }
        }
    }

    impl Default for ScriptedProfile {
        fn default() -> Self {
            Self::new()
        }
    }

    impl<T: Real> SpeedSource<T> for ScriptedProfile {
        fn next_rpm(&mut self) -> Option<T> {
            let rpm = self.next?;
            self.next = if self.rising {
                if rpm == Self::STEP_AT_RPM {
                    Some(Self::STEP_TO_RPM)
                } else if rpm >= Self::HIGH_RPM {
                    self.rising = false;
                    Some(rpm - Self::STEP_RPM)
                } else {
                    Some(rpm + Self::STEP_RPM)
                }
            } else if rpm <= Self::LOW_RPM {
                None
            } else {
                Some(rpm - Self::STEP_RPM)
            };
            Some(T::from_i32(rpm))
        }
    }

    #[cfg(test)]
    mod tests {
        use super::*;

        #[test]
        fn profile_has_the_documented_samples() {
            let mut p = ScriptedProfile::new();
            let mut v = [0.0f64; 64];
            let mut n = 0;
            while let Some(r) = SpeedSource::<f64>::next_rpm(&mut p) {
                v[n] = r;
                n += 1;
            }
            assert_eq!(n, ScriptedProfile::SAMPLES);
            assert_eq!(&v[..3], &[300.0, 325.0, 350.0]);
            assert_eq!(&v[12..14], &[600.0, 700.0]); // the step
            assert_eq!(v[21], 900.0);
            assert_eq!(v[22], 875.0);
            assert_eq!(v[45], 300.0);
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
}
pub use predictor_scene::*;
