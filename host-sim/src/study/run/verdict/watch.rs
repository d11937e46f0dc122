//! What the verdict watches sample by sample: the extremes of the steady revolutions
//! (the smallest contact force, the peak torque, power and stress, where each occurred,
//! and the cam speed's range).

use std::ops::ControlFlow;

use camsim_core::{Observer, Sample};

use super::At;

/// The extremes of the steady revolutions, watched sample by sample.
#[derive(Clone, Debug)]
pub struct Watch {
    /// First revolution watched (2 when the run has two or more, else 1).
    pub from_revolution: u32,
    /// Smallest contact force in contact, lb, and where.
    pub min_force: Option<(f64, At)>,
    /// Largest |cam output torque|, lb·in (signed value), and where.
    pub peak_torque: Option<(f64, At)>,
    /// Largest motor power T_i ω_m, lb·in/s, and where.
    pub peak_power: Option<(f64, At)>,
    /// Largest Hertz stress, psi, and where.
    pub peak_stress: Option<(f64, At)>,
    /// Smallest and largest cam speed θ̇_c, rad/s.
    pub cam_speed: Option<(f64, f64)>,
}

impl Watch {
    /// A watch of the revolutions from `from_revolution` on.
    pub fn new(from_revolution: u32) -> Self {
        Watch {
            from_revolution,
            min_force: None,
            peak_torque: None,
            peak_power: None,
            peak_stress: None,
            cam_speed: None,
        }
    }

    /// The revolution a run of `revolutions` judges from: 2 (the thesis's steady state),
    /// or 1 for a one-revolution run.
    pub fn steady_from(revolutions: u32) -> u32 {
        if revolutions >= 2 {
            2
        } else {
            1
        }
    }
}

fn keep(slot: &mut Option<(f64, At)>, v: f64, at: At, better: impl Fn(f64, f64) -> bool) {
    if !v.is_finite() {
        return;
    }
    match slot {
        Some((old, _)) if !better(v, *old) => {}
        _ => *slot = Some((v, at)),
    }
}

impl Observer<f64> for Watch {
    fn needs_stress(&self) -> bool {
        true
    }
    fn observe(&mut self, s: &Sample<f64>) -> ControlFlow<()> {
        if s.revolution < self.from_revolution {
            return ControlFlow::Continue(());
        }
        let at = At {
            revolution: s.revolution,
            cam_angle_deg: s.angle_deg,
        };
        let p = &s.point;
        if p.in_contact {
            keep(&mut self.min_force, p.contact_force, at, |a, b| a < b);
        }
        keep(&mut self.peak_torque, p.torque_out, at, |a, b| {
            a.abs() > b.abs()
        });
        keep(
            &mut self.peak_power,
            p.torque_drive * p.omega_m,
            at,
            |a, b| a > b,
        );
        keep(&mut self.peak_stress, s.contact_stress, at, |a, b| a > b);
        if p.omega_c.is_finite() {
            let (lo, hi) = self.cam_speed.unwrap_or((p.omega_c, p.omega_c));
            self.cam_speed = Some((lo.min(p.omega_c), hi.max(p.omega_c)));
        }
        ControlFlow::Continue(())
    }
}
