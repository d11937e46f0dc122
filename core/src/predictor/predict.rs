//! The cam-timing and jump predictor: the alarm it drives ([`JumpAlarm`]), the steady-state observer ([`SteadyStateObserver`],
//! [`steady_state`]) and the boot-time table ([`PredictionTable`]) with its jump-onset
//! search ([`OnsetSearch`] over [`steady_state`]).
//!
//! Hardware stays out of the core: a board adapts its timer capture to
//! [`crate::CaptureTimer`] (read by [`crate::IndexPulse`], which turns index pulses into
//! vouched speeds), and its alarm pin to the boolean that [`JumpAlarm`] returns. The same
//! code runs on the host (`camsim predict`) and on the chip; the chip's product
//! configuration (scene, grid, thresholds, the scripted machine) is the `camsim-chip`
//! crate.

use core::ops::ControlFlow;

use crate::{
    simulate, CamModel, Design, LiftProfile, Observer, OnsetSearch, Real, Result, Sample, Scene,
    SegmentKind, SolverSettings, TheoreticalLift,
};

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
    fn needs_outputs(&self) -> bool {
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

/// Simulates the design at `rpm` for two revolutions with the model of scene `S`
/// (`N = S::N`), the roller riding on `profile` ([`TheoreticalLift`] for the perfect cam;
/// an actual or measured cam, [`crate::DeviatedLift`], by reference to share one profile
/// between runs), and measures the steady state (the second revolution). The timing
/// errors are measured against the design's program.
pub fn steady_state<T: Real, S: Scene, const N: usize, P: LiftProfile<T>>(
    design: &Design<T>,
    profile: P,
    rpm: T,
    settings: &SolverSettings<T>,
) -> Result<SteadyState<T>> {
    steady_state_at::<T, S, N, P>(design, profile, rpm, settings, false)
}

/// [`steady_state`]; `scanned`: the design passed [`Design::validate`] already, so its
/// model at `rpm` skips the undercut scan ([`CamModel::with_profile_scanned`], bit for bit
/// the same model).
fn steady_state_at<T: Real, S: Scene, const N: usize, P: LiftProfile<T>>(
    design: &Design<T>,
    profile: P,
    rpm: T,
    settings: &SolverSettings<T>,
    scanned: bool,
) -> Result<SteadyState<T>> {
    let mut d = design.clone();
    d.set_speed_rpm(rpm)?;
    let model = if scanned {
        CamModel::<T, S, N, P>::with_profile_scanned(d, profile)?
    } else {
        CamModel::<T, S, N, P>::with_profile(d, profile)?
    };
    let points = timing_points(&model.design().program);
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
        Self::build_on::<S, N, _>(
            design,
            TheoreticalLift,
            rpm,
            max_rpm,
            resolution_rpm,
            settings,
        )
    }

    /// [`Self::build`] with the roller riding on `profile` (an actual or measured cam;
    /// a reference to a [`crate::DeviatedLift`] is `Copy`): every run of the table and
    /// of the onset search uses it ([`steady_state`]).
    pub fn build_on<S: Scene, const N: usize, P: LiftProfile<T> + Copy>(
        design: &Design<T>,
        profile: P,
        rpm: [T; G],
        max_rpm: T,
        resolution_rpm: T,
        settings: &SolverSettings<T>,
    ) -> Result<Self> {
        // The design's undercut scan once; each speed's model as `steady_state` builds it
        // otherwise (`CamModel::with_profile_scanned`).
        design.validate()?;
        let run = |r: T| steady_state_at::<T, S, N, P>(design, profile, r, settings, true);
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
            *a = run(*r)?;
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
        let jumps = |r: T| run(r).map(|s| s.jumped);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{RegulatedVertical, TheoreticalLift};

    /// The table's runs (one undercut scan, `with_profile_scanned` at each speed) are bit
    /// for bit `steady_state`'s (a full validation at each speed), timing NaNs included.
    #[test]
    fn table_runs_are_steady_state_runs_bit_for_bit() {
        let d = Design::<f32>::reference();
        let mut settings = SolverSettings::<f32>::reference();
        settings.rtol = 1e-2;
        let grid = [600.0f32, 950.0];
        const N: usize = <RegulatedVertical as Scene>::N;
        let table = PredictionTable::<f32, 2>::build::<RegulatedVertical, N>(
            &d, grid, 1000.0, 50.0, &settings,
        )
        .unwrap();
        for (r, at) in grid.iter().zip(table.at.iter()) {
            let direct =
                steady_state::<f32, RegulatedVertical, N, _>(&d, TheoreticalLift, *r, &settings)
                    .unwrap();
            let bits = |s: &SteadyState<f32>| {
                (
                    s.min_contact_force.to_bits(),
                    s.min_force_deg.to_bits(),
                    s.jumped,
                    s.timing_deg.map(f32::to_bits),
                )
            };
            assert_eq!(bits(at), bits(&direct), "{r} rpm");
        }
    }

    /// `with_profile_scanned` checks what `with_profile` checks after the undercut scan
    /// (here: the cantilever against the largest lift and the roller).
    #[test]
    fn a_scanned_model_still_checks_the_rest_of_the_design() {
        const N: usize = <RegulatedVertical as Scene>::N;
        type M = CamModel<f64, RegulatedVertical, N, TheoreticalLift>;
        let mut short = Design::<f64>::reference();
        short.e2 = short.program.max_lift() + 0.5 * short.geometry.roller_radius;
        for r in [
            M::with_profile(short.clone(), TheoreticalLift),
            M::with_profile_scanned(short, TheoreticalLift),
        ] {
            assert!(
                matches!(r, Err(crate::Error::InvalidParameter { field, .. }) if field == crate::key::E2),
                "{r:?}"
            );
        }
    }

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
