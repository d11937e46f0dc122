//! The drive: what turns the motor (the thesis's T_i, not given in VI.1).
//!
//! The thesis gives a 1.75 hp motor and initial speeds of 800 rpm, but not the
//! torque-speed law T_i(θ̇_m). The listed viscous drags (C_mb + C_cc) alone absorb
//! about 150 lb·in at 800 rpm, so an unregulated torque would let the machine slow
//! down. The default is therefore a speed-regulated motor ([`DriveLaw::Regulated`]):
//! the steady drag torque at the reference speed plus a proportional term on the
//! speed error, limited to the motor's breakdown torque. Two ideal drives drop
//! rotational degrees of freedom for simpler scenes.

use crate::{finite, key, non_negative, positive, Real, Result};

/// One horsepower in lb·in/s.
pub const HORSEPOWER_IN_LB_PER_S: f64 = 6600.0;
/// Rated power of the thesis's motor (VI.1): 1.75 hp.
pub const MOTOR_RATED_HP: f64 = 1.75;
/// Rated slip of the regulated drive's torque-speed line: 4 %, a typical 4-pole
/// NEMA design B induction motor (3-5 %); the proportional gain follows from it.
pub const MOTOR_RATED_SLIP: f64 = 0.04;
/// Breakdown torque over rated torque: 2.5, typical of NEMA design B motors (2-3).
pub const MOTOR_BREAKDOWN_RATIO: f64 = 2.5;

/// What kind of drive a scene has: which rotational degrees of freedom stay free (a
/// [`Scene`](crate::Scene)'s const; the numbers of a regulated drive are the design's
/// [`DriveLaw`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DriveKind {
    /// [`DriveLaw::Regulated`]: motor, coupling and cam rotations free.
    Regulated,
    /// [`DriveLaw::ConstantMotorSpeed`]: coupling and cam rotations free.
    ConstantMotorSpeed,
    /// [`DriveLaw::ConstantCamSpeed`]: the rotational system is rigid.
    ConstantCamSpeed,
}

impl DriveKind {
    /// Number of rotational degrees of freedom this kind leaves free (3, 2 or 0).
    pub const fn rotational_dofs(self) -> usize {
        match self {
            DriveKind::Regulated => 3,
            DriveKind::ConstantMotorSpeed => 2,
            DriveKind::ConstantCamSpeed => 0,
        }
    }
}

/// The motor law T_i(θ̇_m) and which rotational degrees of freedom it leaves free.
///
/// Scene form (`serde` feature): `drive = "constant-cam-speed"`,
/// `drive = "constant-motor-speed"`, or a table `[drive.regulated]` with
/// `omega_ref_rad_per_s`, `t_steady_lb_in`, `k_p_lb_in_s_per_rad`, `t_max_lb_in` (absent
/// keys take the reference drive's values). Unknown laws and keys are refused.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        rename_all = "kebab-case",
        deny_unknown_fields,
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub enum DriveLaw<T> {
    /// Ideal constant cam speed ω0: the rotational system is rigid (motor, coupling
    /// and cam DOFs dropped). The cam angle is ω0 t; this is the "theoretical" speed, the
    /// kinematic assumption of every cam textbook (`drive = "constant-speed"` also reads).
    #[cfg_attr(feature = "serde", serde(alias = "constant-speed"))]
    ConstantCamSpeed,
    /// Motor held at ω0 by an ideal source; coupling and cam rotations stay free.
    ConstantMotorSpeed,
    /// Speed-regulated motor: T_i = t_steady + k_p (ω_ref - θ̇_m), clamped to ±t_max.
    Regulated {
        /// Reference speed ω_ref, rad/s.
        #[cfg_attr(
            feature = "serde",
            serde(rename = "omega_ref_rad_per_s", default = "reference_field::<T, 0>")
        )]
        omega_ref: T,
        /// Feed-forward torque: the steady drag (C_mb + C_cc) ω_ref, lb·in.
        #[cfg_attr(
            feature = "serde",
            serde(rename = "t_steady_lb_in", default = "reference_field::<T, 1>")
        )]
        t_steady: T,
        /// Proportional gain, lb·in·s/rad: rated torque over rated slip speed.
        #[cfg_attr(
            feature = "serde",
            serde(rename = "k_p_lb_in_s_per_rad", default = "reference_field::<T, 2>")
        )]
        k_p: T,
        /// Torque limit (breakdown torque), lb·in.
        #[cfg_attr(
            feature = "serde",
            serde(rename = "t_max_lb_in", default = "reference_field::<T, 3>")
        )]
        t_max: T,
    },
}

/// Field `I` (omega_ref, t_steady, k_p, t_max) of the reference design's drive: the
/// default of an absent key in a `[drive.regulated]` table.
#[cfg(feature = "serde")]
fn reference_field<T: Real, const I: usize>() -> T {
    match crate::Design::<T>::reference().drive {
        DriveLaw::Regulated {
            omega_ref,
            t_steady,
            k_p,
            t_max,
        } => [omega_ref, t_steady, k_p, t_max]
            .get(I)
            .copied()
            .unwrap_or(T::ZERO),
        _ => T::ZERO,
    }
}

impl<T: Real> DriveLaw<T> {
    /// The default regulated drive at `omega0` for the given motor and cam bearing drags.
    ///
    /// Rated torque T_r = P / ω0 (1.75 hp); k_p = T_r / (s_r ω0) with s_r = 4 % rated
    /// slip (41 lb·in·s/rad at 800 rpm); t_max = 2.5 T_r; t_steady = (C_mb + C_cc) ω0.
    pub fn reference(omega0: T, c_mb: T, c_cc: T) -> Self {
        let t_rated = T::from_f64(MOTOR_RATED_HP * HORSEPOWER_IN_LB_PER_S) / omega0;
        DriveLaw::Regulated {
            omega_ref: omega0,
            t_steady: (c_mb + c_cc) * omega0,
            k_p: t_rated / (T::from_f64(MOTOR_RATED_SLIP) * omega0),
            t_max: T::from_f64(MOTOR_BREAKDOWN_RATIO) * t_rated,
        }
    }

    /// The same law with every number converted by `f` (e.g. to another precision).
    pub fn map<U>(self, f: impl Fn(T) -> U) -> DriveLaw<U> {
        match self {
            DriveLaw::ConstantCamSpeed => DriveLaw::ConstantCamSpeed,
            DriveLaw::ConstantMotorSpeed => DriveLaw::ConstantMotorSpeed,
            DriveLaw::Regulated {
                omega_ref,
                t_steady,
                k_p,
                t_max,
            } => DriveLaw::Regulated {
                omega_ref: f(omega_ref),
                t_steady: f(t_steady),
                k_p: f(k_p),
                t_max: f(t_max),
            },
        }
    }

    /// The same law in precision `U`, every number converted with [`Real::cast`].
    pub fn cast<U: Real>(self) -> DriveLaw<U> {
        self.map(Real::cast)
    }

    /// The same law moved to a new reference speed (regulated: feed-forward scaled with speed).
    pub fn at_speed(self, omega_new: T) -> Self {
        match self {
            DriveLaw::Regulated {
                omega_ref,
                t_steady,
                k_p,
                t_max,
            } => DriveLaw::Regulated {
                omega_ref: omega_new,
                t_steady: if omega_ref > T::ZERO {
                    t_steady * omega_new / omega_ref
                } else {
                    t_steady
                },
                k_p,
                t_max,
            },
            other => other,
        }
    }

    /// The kind of this law.
    pub fn kind(&self) -> DriveKind {
        match self {
            DriveLaw::ConstantCamSpeed => DriveKind::ConstantCamSpeed,
            DriveLaw::ConstantMotorSpeed => DriveKind::ConstantMotorSpeed,
            DriveLaw::Regulated { .. } => DriveKind::Regulated,
        }
    }

    /// Number of rotational degrees of freedom this law leaves free (0, 2 or 3).
    pub fn rotational_dofs(&self) -> usize {
        self.kind().rotational_dofs()
    }

    /// Motor torque T_i at motor speed `omega_m` (0 for the ideal drives, which impose speed).
    #[inline(always)]
    pub fn torque(&self, omega_m: T) -> T {
        match *self {
            DriveLaw::Regulated {
                omega_ref,
                t_steady,
                k_p,
                t_max,
            } => {
                // `clamp(-t_max, t_max)` as two plain compares (a NaN torque gives -t_max,
                // as `clamp` does): a law that passed `validate` has a finite `t_max`, so
                // `Real::clamp`'s tests for a NaN bound are not needed (about 8
                // instructions an evaluation on the chip). An unvalidated NaN `t_max`
                // gives NaN here, where `clamp` would pass the torque through.
                let t = t_steady + k_p * (omega_ref - omega_m);
                let t = if t >= -t_max { t } else { -t_max };
                if t <= t_max {
                    t
                } else {
                    t_max
                }
            }
            _ => T::ZERO,
        }
    }

    /// Checks the law's parameters; errors name the scene key
    /// (`drive.regulated.t_max_lb_in`).
    pub fn validate(&self) -> Result<()> {
        if let DriveLaw::Regulated {
            omega_ref,
            t_steady,
            k_p,
            t_max,
        } = *self
        {
            positive(key::DRIVE_OMEGA_REF, omega_ref)?;
            positive(key::DRIVE_T_MAX, t_max)?;
            non_negative(key::DRIVE_K_P, k_p)?;
            finite(key::DRIVE_T_STEADY, t_steady)?;
        }
        Ok(())
    }
}

/// The torque a shaft passes through a connection with free play (backlash): the impact
/// pair of Appendix G.1 in series with the shaft's stiffness `k` and damping `c`.
///
/// `twist` is the relative rotation of the two sides (the shaft's elastic twist plus the
/// position within the free play), `rate` its rate, `free_play` the total angular play
/// (≥ 0). Within `|twist| < free_play/2` the sides do not touch and no torque passes (G.1
/// "no contact"); beyond it the shaft is twisted by `|twist| − free_play/2` and passes
/// `k (twist ∓ free_play/2) + c·rate`, which is never allowed to pull the sides apart
/// (clamped to the side in contact, as the contact force is). With no play the clamp
/// would still act: the model calls this only for `free_play > 0` and keeps the linear
/// `k·twist + c·rate` of the rigid coupling otherwise (docs/MODEL.md §8.5).
#[inline(always)]
pub fn backlash_torque<T: Real>(k: T, c: T, free_play: T, twist: T, rate: T) -> T {
    let half = free_play * T::HALF;
    if twist > half {
        (k * (twist - half) + c * rate).max(T::ZERO)
    } else if twist < -half {
        (k * (twist + half) + c * rate).min(T::ZERO)
    } else {
        T::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn backlash_is_a_dead_zone_that_never_pulls() {
        let (k, c, b) = (2.0e5, 0.12, 0.01);
        // Free within ±b/2, whatever the rate.
        for tw in [-0.005, -0.002, 0.0, 0.004999] {
            assert_eq!(backlash_torque(k, c, b, tw, 30.0), 0.0, "{tw}");
        }
        // In contact: the shaft twisted by |tw| − b/2.
        assert_eq!(backlash_torque(k, c, b, 0.006, 0.0), k * (0.006 - 0.005));
        assert_eq!(
            backlash_torque(k, c, b, -0.007, 1.0),
            k * (-0.007 + 0.005) + c
        );
        // Separating fast: the damping would pull; the torque stops at zero.
        assert_eq!(backlash_torque(k, c, b, 0.0050001, -1e3), 0.0);
        assert_eq!(backlash_torque(k, c, b, -0.0050001, 1e3), 0.0);
        // No play, pushing: the rigid coupling's torque.
        assert_eq!(backlash_torque(k, c, 0.0, 1e-4, 2.0), k * 1e-4 + c * 2.0);
    }

    #[test]
    fn reference_gain_from_rated_slip() {
        let w = crate::rpm_to_rad_per_s(800.0f64);
        let d = DriveLaw::reference(w, 0.8, 1.0);
        // At the reference speed the motor delivers exactly the steady drag.
        assert!((d.torque(w) - 1.8 * w).abs() < 1e-12);
        // 4 % slow: rated torque above the drag (1.75 hp at 800 rpm = 137.9 lb in).
        let t_rated = 1.75 * 6600.0 / w;
        assert!((t_rated - 137.87).abs() < 0.01);
        assert!((d.torque(0.96 * w) - 1.8 * w - t_rated).abs() < 1e-9);
        // Limited to the breakdown torque.
        assert!((d.torque(0.0) - 2.5 * t_rated).abs() < 1e-9);
    }

    /// The torque's two compares give `Real::clamp`'s values for a validated law: within
    /// the limits, at each limit, beyond both (the motor driven backwards above its
    /// speed gives -t_max), and for a NaN speed (-t_max, as `clamp` gives).
    #[test]
    fn torque_is_the_clamped_line() {
        let w = crate::rpm_to_rad_per_s(800.0f64);
        let d = DriveLaw::reference(w, 0.8, 1.0);
        let DriveLaw::Regulated {
            omega_ref,
            t_steady,
            k_p,
            t_max,
        } = d
        else {
            panic!("the reference drive is regulated")
        };
        assert!(d.validate().is_ok());
        let line = |omega: f64| t_steady + k_p * (omega_ref - omega);
        let at_max = omega_ref - (t_max - t_steady) / k_p;
        let at_min = omega_ref + (t_max + t_steady) / k_p;
        for omega in [
            0.0,
            0.5 * at_max,
            at_max,
            w,
            0.5 * (w + at_min),
            at_min,
            2.0 * at_min,
            f64::NAN,
        ] {
            assert_eq!(
                d.torque(omega).to_bits(),
                <f64 as Real>::clamp(line(omega), -t_max, t_max).to_bits(),
                "at {omega} rad/s"
            );
        }
        assert_eq!(d.torque(0.0), t_max);
        assert_eq!(d.torque(2.0 * at_min), -t_max);
        assert_eq!(d.torque(f64::NAN), -t_max);
    }

    #[test]
    fn ideal_drives_drop_rotational_dofs() {
        assert_eq!(DriveLaw::<f32>::ConstantCamSpeed.rotational_dofs(), 0);
        assert_eq!(DriveLaw::<f32>::ConstantMotorSpeed.rotational_dofs(), 2);
        assert_eq!(
            DriveLaw::reference(83.776f32, 0.8, 1.0).rotational_dofs(),
            3
        );
    }
}
