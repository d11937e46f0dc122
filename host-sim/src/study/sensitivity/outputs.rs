//! The study's outputs over one revolution ([`Outputs`]) and the observer that integrates
//! them ([`RevolutionIntegrals`]).

use std::ops::ControlFlow;

use anyhow::{anyhow, Result};
use camsim_core::{jump_verdict, Both, JumpWatch, Observer, Sample};
use serde::Serialize;

use super::REVOLUTION;
use crate::sim::{self, RunSpec};
use crate::study::montecarlo::LeftRange;
use crate::units::{Acceleration, Length, Speed, Stress};

/// The study's outputs over the whole of one revolution.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outputs {
    /// RMS of the load's displacement deviation from the theoretical response, in.
    pub rms_displacement_in: Length,
    /// RMS of the load's velocity deviation, in/s.
    pub rms_velocity_in_per_s: Speed,
    /// RMS of the load's acceleration deviation, in/s².
    pub rms_acceleration_in_per_s2: Acceleration,
    /// RMS of the cam's angular-velocity deviation from ω0, rad/s.
    pub rms_angular_velocity_rad_per_s: f64,
    /// Time average of the largest Hertz contact stress, psi (0 while separated).
    pub contact_stress_avg_psi: Stress,
    /// Whether the follower left the cam in the revolution.
    pub jump: bool,
}

/// The names of the five numeric outputs, in [`Outputs::values`]'s order, with the
/// text table's header and unit.
pub const OUTPUTS: [(&str, &str, &str); 5] = [
    ("rms_displacement_in", "rms y", "in"),
    ("rms_velocity_in_per_s", "rms v", "in/s"),
    ("rms_acceleration_in_per_s2", "rms a", "in/s2"),
    ("rms_angular_velocity_rad_per_s", "rms w_cam", "rad/s"),
    ("contact_stress_avg_psi", "avg stress", "psi"),
];

impl Outputs {
    /// The five numbers, in [`OUTPUTS`]' order.
    pub fn values(&self) -> [f64; 5] {
        [
            self.rms_displacement_in.in_inch(),
            self.rms_velocity_in_per_s.in_inch(),
            self.rms_acceleration_in_per_s2.in_inch(),
            self.rms_angular_velocity_rad_per_s,
            self.contact_stress_avg_psi.in_inch(),
        ]
    }
}

/// Whole-revolution RMS from per-period RMS values over their own spans:
/// sqrt(Σ dᵢ rmsᵢ² / Σ dᵢ) for `(duration dᵢ, rmsᵢ)` pairs (each period's mean square
/// is its integral over its duration, so the revolution's integral is the sum of
/// dᵢ rmsᵢ²). 0 for no duration.
pub fn combine_rms(periods: &[(f64, f64)]) -> f64 {
    let (num, den) = periods.iter().fold((0.0, 0.0), |(n, d), &(dur, rms)| {
        (n + dur * rms * rms, d + dur)
    });
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}

/// Time integrals over one revolution, trapezoidal between consecutive samples that both
/// lie in it (as the per-period statistics, but across the period boundaries too): the
/// cam-speed deviation and the contact stress, which the per-period statistics do not
/// keep, and the three load deviations (to check [`combine_rms`] against).
#[derive(Clone, Debug, Default)]
pub struct RevolutionIntegrals {
    /// The revolution (from 1).
    pub revolution: u32,
    /// ω0, rad/s.
    pub omega0: f64,
    /// Time covered, s.
    pub duration: f64,
    /// ∫ (y − y_th)² dt, ∫ (v − v_th)² dt, ∫ (a − a_th)² dt, ∫ (ω_c − ω0)² dt, ∫ σ dt.
    pub sums: [f64; 5],
    prev: Option<(f64, [f64; 5])>,
}

impl RevolutionIntegrals {
    /// Empty integrals of `revolution` about the speed `omega0`.
    pub fn new(revolution: u32, omega0: f64) -> Self {
        Self {
            revolution,
            omega0,
            ..Self::default()
        }
    }

    /// RMS (the first four) or mean (the stress) over the time covered.
    pub fn means(&self) -> [f64; 5] {
        let m = |s: f64| {
            if self.duration > 0.0 {
                s / self.duration
            } else {
                0.0
            }
        };
        let [y, v, a, w, s] = self.sums;
        [m(y).sqrt(), m(v).sqrt(), m(a).sqrt(), m(w).sqrt(), m(s)]
    }
}

impl Observer<f64> for RevolutionIntegrals {
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        if s.revolution != self.revolution {
            self.prev = None;
            return ControlFlow::Continue(());
        }
        let p = &s.point;
        let f = [
            (p.load_displacement() - s.theory.y).powi(2),
            (p.load_velocity() - s.theory.v).powi(2),
            (p.load_acceleration() - s.theory.a).powi(2),
            (p.omega_c - self.omega0).powi(2),
            s.contact_stress,
        ];
        if let Some((t0, f0)) = self.prev {
            let dt = p.t - t0;
            if dt > 0.0 {
                self.duration += dt;
                for ((sum, a), b) in self.sums.iter_mut().zip(f0).zip(f) {
                    *sum += 0.5 * dt * (a + b);
                }
            }
        }
        self.prev = Some((p.t, f));
        ControlFlow::Continue(())
    }
}

/// Simulates `spec` (its `revolutions` set to [`REVOLUTION`]) and returns revolution 2's
/// outputs: the three load deviations from the per-period statistics ([`combine_rms`]),
/// the cam-speed deviation and the stress from [`RevolutionIntegrals`], and the jump
/// from the periods' flags.
pub fn outputs(spec: &RunSpec) -> Result<Outputs> {
    outputs_or_left_range(spec)?.map_err(|l| anyhow!(l.reason))
}

/// [`outputs`], or how the run left the model's valid range (docs/MODEL.md §3.20):
/// after a separation (a jump, the rule of `camsim jump-speed`) or with the follower on
/// the cam. Any other failure is an error.
pub fn outputs_or_left_range(spec: &RunSpec) -> Result<std::result::Result<Outputs, LeftRange>> {
    let mut s = spec.clone();
    s.revolutions = REVOLUTION;
    let mut integrals = RevolutionIntegrals::new(REVOLUTION, s.design.omega0);
    let mut watch = JumpWatch::<f64>::new();
    let r = match sim::run(&s, &mut Both(&mut integrals, &mut watch)) {
        Ok(r) => r,
        Err(e) => {
            let separated = jump_verdict::<(), (), f64>(Err(()), &watch).is_ok();
            if !crate::study::sweep::out_of_model(&e) {
                return Err(e);
            }
            let reason = format!("{}", e.root_cause());
            return Ok(Err(LeftRange { separated, reason }));
        }
    };
    let periods: Vec<_> = (0..s.design.program.segments().len())
        .filter_map(|i| r.stats.period(REVOLUTION, i))
        .filter(|p| p.samples > 0)
        .collect();
    anyhow::ensure!(
        !periods.is_empty(),
        "revolution {REVOLUTION} has no samples"
    );
    let combine = |f: fn(&camsim_core::PeriodStats<f64>) -> f64| {
        combine_rms(
            &periods
                .iter()
                .map(|p| (p.duration, f(p)))
                .collect::<Vec<_>>(),
        )
    };
    let m = integrals.means();
    let out = Outputs {
        rms_displacement_in: Length::inch(combine(|p| p.rms_displacement())),
        rms_velocity_in_per_s: Speed::inch(combine(|p| p.rms_velocity())),
        rms_acceleration_in_per_s2: Acceleration::inch(combine(|p| p.rms_acceleration())),
        rms_angular_velocity_rad_per_s: m[3],
        contact_stress_avg_psi: Stress::inch(m[4]),
        jump: periods.iter().any(|p| p.jump),
    };
    for ((name, _, _), v) in OUTPUTS.iter().zip(out.values()) {
        anyhow::ensure!(v.is_finite(), "{name} is {v}");
    }
    Ok(Ok(out))
}
