//! Hertz line contact between roller and cam (Eqs. V.9-V.11), the contact force and
//! jump criterion (Eqs. V.19-V.20) with the contact damper of docs/MODEL.md §3.9, the
//! roller bearing's spring and damper (§3.13), and the slide-bearing friction (Eqs.
//! V.15-V.16).
//!
//! Everything here sits inside the ODE right-hand side, so the hot-path functions are
//! branch-light, never panic and never allocate. The checked variants (`new`,
//! [`HertzContact::stiffness`], [`HertzContact::stiffness_at`]) return typed errors
//! that name the offending field; [`HertzContact::stiffness_fast`] is the unchecked
//! fast path with a finite fallback.
//!
//! Depressed depths are computed as `h = b^2 / (r + sqrt(r^2 - b^2))`, algebraically
//! identical to the thesis's `h = r - sqrt(r^2 - b^2)` (Eq. V.10) but free of the
//! cancellation that would leave no correct digit in `f32` (h is about 1e-7 in against
//! r of 0.375 in), and it takes a flat surface (`r = inf`, `h = 0`) without `inf - inf`.

use crate::{key, Error, Real, Result};

/// Material and thickness of a roller-on-cam Hertz line contact (Eq. V.9's data).
///
/// Build it with [`HertzContact::new`] (validated) or [`HertzContact::steel`]; the
/// fields are public for reading, and a value assembled by hand skips the checks
/// ([`HertzContact::validate`] makes them). Scene keys (`[hertz]`): `roller_youngs_psi`,
/// `roller_poisson`, `cam_youngs_psi`, `cam_poisson`, `contact_length_in`; absent keys
/// take the reference values.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        deny_unknown_fields,
        default,
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct HertzContact<T> {
    /// Young's modulus of body 1, the roller (psi).
    #[cfg_attr(feature = "serde", serde(rename = "roller_youngs_psi"))]
    pub youngs_1: T,
    /// Poisson's ratio of body 1, the roller.
    #[cfg_attr(feature = "serde", serde(rename = "roller_poisson"))]
    pub poisson_1: T,
    /// Young's modulus of body 2, the cam (psi).
    #[cfg_attr(feature = "serde", serde(rename = "cam_youngs_psi"))]
    pub youngs_2: T,
    /// Poisson's ratio of body 2, the cam.
    #[cfg_attr(feature = "serde", serde(rename = "cam_poisson"))]
    pub poisson_2: T,
    /// Axial length of the line contact (in): the cam thickness t, or the roller's
    /// width if that is narrower.
    #[cfg_attr(feature = "serde", serde(rename = "contact_length_in"))]
    pub thickness: T,
}

impl<T: Real> Default for HertzContact<T> {
    /// [`HertzContact::reference`].
    fn default() -> Self {
        Self::reference()
    }
}

/// Why a stiffness evaluation failed (internal: no values, so the fast path never
/// widens to `f64`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum StiffnessFault {
    /// r1 not positive and finite.
    RollerRadius,
    /// r2 zero or NaN.
    SurfaceRadius,
    /// Concave with |r2| <= r1: the roller does not fit.
    RollerDoesNotFit,
    /// w/2 > r1.
    HalfWidthRoller,
    /// w/2 > |r2|.
    HalfWidthSurface,
    /// Force not positive and finite.
    Force,
}

impl<T: Real> HertzContact<T> {
    /// Validated contact data: `E > 0`, `0 <= nu < 0.5`, `t > 0`, all finite (Eq. V.9).
    pub fn new(youngs_1: T, poisson_1: T, youngs_2: T, poisson_2: T, thickness: T) -> Result<Self> {
        let h = Self {
            youngs_1,
            poisson_1,
            youngs_2,
            poisson_2,
            thickness,
        };
        h.validate()?;
        Ok(h)
    }

    /// Checks the data of [`HertzContact::new`]; errors name the scene key
    /// (`hertz.roller_poisson`).
    pub fn validate(&self) -> Result<()> {
        crate::positive(key::ROLLER_YOUNGS, self.youngs_1)?;
        poisson_ratio(key::ROLLER_POISSON, self.poisson_1)?;
        crate::positive(key::CAM_YOUNGS, self.youngs_2)?;
        poisson_ratio(key::CAM_POISSON, self.poisson_2)?;
        crate::positive(key::CONTACT_LENGTH, self.thickness)?;
        Ok(())
    }

    /// The same data in precision `U`, each number converted with [`Real::cast`]
    /// (not checked: [`HertzContact::validate`] does that).
    pub fn cast<U: Real>(&self) -> HertzContact<U> {
        HertzContact {
            youngs_1: self.youngs_1.cast(),
            poisson_1: self.poisson_1.cast(),
            youngs_2: self.youngs_2.cast(),
            poisson_2: self.poisson_2.cast(),
            thickness: self.thickness.cast(),
        }
    }

    /// The reference contact of VI.1: steel on steel over the 0.25 in cam thickness.
    pub fn reference() -> Self {
        Self::steel(T::from_f64(0.25))
    }

    /// Steel roller on a steel cam: E = 30e6 psi, nu = 0.295 for both (VI.1 data).
    ///
    /// `thickness` is not checked here; pass untrusted values through [`HertzContact::new`].
    pub fn steel(thickness: T) -> Self {
        let e = T::from_f64(30.0e6);
        let nu = T::from_f64(0.295);
        Self {
            youngs_1: e,
            poisson_1: nu,
            youngs_2: e,
            poisson_2: nu,
            thickness,
        }
    }

    /// Combined compliance `(1 - nu1^2)/E1 + (1 - nu2^2)/E2` (1/psi), the bracketed
    /// numerator of Eq. V.9 (the reciprocal of the contact modulus E*).
    #[inline]
    pub fn compliance(&self) -> T {
        (T::ONE - self.poisson_1.sq()) / self.youngs_1
            + (T::ONE - self.poisson_2.sq()) / self.youngs_2
    }

    /// Width w of the rectangular contact band under `force` (Eq. V.9).
    ///
    /// `d1`, `d2` are the diameters (twice the radii of curvature); `d2 < 0` for a
    /// concave cam surface, entering `1/d1 + 1/d2` with its sign; `d2 = inf` is a flat
    /// surface. `force <= 0` gives 0 (no load, no band). When `1/d1 + 1/d2 <= 0`
    /// (a concave radius the roller does not fit, or conformal surfaces) the band is
    /// unbounded and the result is `+inf`. NaN inputs give NaN.
    #[inline]
    pub fn width(&self, force: T, d1: T, d2: T) -> T {
        if force <= T::ZERO {
            return T::ZERO;
        }
        let curvature = T::ONE / d1 + T::ONE / d2;
        if curvature <= T::ZERO {
            return T::INFINITY;
        }
        let two = T::TWO;
        two * (two * force / (T::PI * self.thickness) * (self.compliance() / curvature)).sqrt()
    }

    /// Hertz contact stiffness at unit force, Eqs. V.10-V.11, exactly as the thesis
    /// states: `w` from Eq. V.9 at F = 1 lb, `h_i = r_i - sqrt(r_i^2 - (w/2)^2)`,
    /// convex (`r2 > 0`): `K_h = 1/(h1 + h2)`; concave (`r2 < 0`):
    /// `K_h = 1/(2 (h1 - h2))` with `h2` from `|r2|` (lb/in).
    ///
    /// `r1` is the roller radius, `r2` the signed radius of curvature of the cam surface
    /// (Eq. V.12); `r2 = +inf` or `-inf` is a flat surface and takes the convex formula
    /// with `h2 = 0`.
    ///
    /// Discontinuity: to leading order in the small band width, V.11 gives
    /// `K_h = pi t / (2 C)` for every convex radius (C = [`HertzContact::compliance`])
    /// but half of it for every concave one, because of the printed factor 2. K_h
    /// therefore jumps by about 2x where the cam surface curvature changes sign (at an
    /// inflection of the profile, or flat-to-concave). The model follows the thesis.
    ///
    /// Errors: `r1` not positive and finite; `r2` zero or NaN; concave `|r2| <= r1`
    /// (the roller does not fit); half band `w/2` larger than `r1` or `|r2|`.
    pub fn stiffness(&self, r1: T, r2: T) -> Result<T> {
        self.stiffness_core(T::ONE, r1, r2)
            .map_err(|f| fault_error(f, T::ONE, r1, r2))
    }

    /// Secant Hertz stiffness `K = F / H` with the band `w` of Eq. V.9 evaluated at
    /// `force` instead of 1 lb (Eqs. V.9-V.11); shows that [`HertzContact::stiffness`]
    /// is nearly independent of the force (lb/in).
    ///
    /// Errors: as [`HertzContact::stiffness`], plus `force` not positive and finite.
    pub fn stiffness_at(&self, force: T, r1: T, r2: T) -> Result<T> {
        self.stiffness_core(force, r1, r2)
            .map_err(|f| fault_error(f, force, r1, r2))
    }

    /// Unit-force Hertz stiffness of Eqs. V.10-V.11 for the ODE right-hand side: the
    /// same value as [`HertzContact::stiffness`], never an error.
    ///
    /// Precondition (the caller's): `r1 > 0` and the geometry admissible (which the
    /// profile check guarantees, no undercut and concave radii larger than the roller).
    /// When it is not, returns the finite fallback `pi t / (2 C)`, the radius-independent
    /// small-band limit of the convex formula, so the integration continues.
    #[inline]
    pub fn stiffness_fast(&self, r1: T, r2: T) -> T {
        match self.stiffness_core(T::ONE, r1, r2) {
            Ok(k) => k,
            Err(_) => T::PI * self.thickness / (T::TWO * self.compliance()),
        }
    }

    /// Maximum Hertz contact pressure `p_max = 2 F / (pi b t)` with `b = w/2` from
    /// Eq. V.9 (psi). Equals the textbook `sqrt(F E* / (pi t R*))`.
    ///
    /// `force <= 0` gives 0; an unbounded band (`1/d1 + 1/d2 <= 0`, see
    /// [`HertzContact::width`]) gives 0, the conformal limit.
    #[inline]
    pub fn max_stress(&self, force: T, d1: T, d2: T) -> T {
        let b = T::HALF * self.width(force, d1, d2);
        if b > T::ZERO {
            T::TWO * force / (T::PI * b * self.thickness)
        } else if b.is_nan() {
            b
        } else {
            T::ZERO
        }
    }

    /// Shared body of the stiffness functions: `F / H` at the band of `force`.
    #[inline]
    fn stiffness_core(&self, force: T, r1: T, r2: T) -> core::result::Result<T, StiffnessFault> {
        if !(force > T::ZERO && force.is_finite()) {
            return Err(StiffnessFault::Force);
        }
        if !(r1 > T::ZERO && r1.is_finite()) {
            return Err(StiffnessFault::RollerRadius);
        }
        if r2.is_nan() || r2 == T::ZERO {
            return Err(StiffnessFault::SurfaceRadius);
        }
        let concave = r2 < T::ZERO && r2.is_finite();
        let r2_abs = r2.abs();
        if concave && r2_abs <= r1 {
            return Err(StiffnessFault::RollerDoesNotFit);
        }
        // Eq. V.9 with diameters; signed d2 for the concave case, 1/inf = 0 for flat.
        let d2 = if concave {
            -(T::TWO * r2_abs)
        } else {
            T::TWO * r2_abs
        };
        let w = self.width(force, T::TWO * r1, d2);
        let b = T::HALF * w;
        if b > r1 || b.is_nan() {
            return Err(StiffnessFault::HalfWidthRoller);
        }
        if b > r2_abs {
            return Err(StiffnessFault::HalfWidthSurface);
        }
        // Eq. V.10, cancellation-free.
        let h1 = depressed_depth(r1, b);
        let h2 = depressed_depth(r2_abs, b);
        // Eq. V.11 (K = F / H).
        let depth = if concave { T::TWO * (h1 - h2) } else { h1 + h2 };
        if depth > T::ZERO {
            Ok(force / depth)
        } else {
            // Only reachable for a band that underflowed to zero.
            Err(StiffnessFault::Force)
        }
    }
}

/// Depressed depth `r - sqrt(r^2 - b^2)` of a circle of radius r under a chord of
/// half-length b (Eq. V.10), as `b^2 / (r + sqrt(r^2 - b^2))`; 0 for `r = inf`.
#[inline]
fn depressed_depth<T: Real>(r: T, b: T) -> T {
    if !r.is_finite() {
        return T::ZERO;
    }
    let b2 = b.sq();
    b2 / (r + (r.sq() - b2).max(T::ZERO).sqrt())
}

/// Checks a Poisson's ratio: finite and in `[0, 0.5)`.
fn poisson_ratio<T: Real>(field: &'static str, nu: T) -> Result<T> {
    if nu.is_finite() && nu >= T::ZERO && nu < T::HALF {
        Ok(nu)
    } else {
        Err(Error::InvalidParameter {
            field,
            rule: "must be in [0, 0.5)",
            value: nu.to_f64(),
        })
    }
}

/// Turns a stiffness fault into the public error naming its field.
fn fault_error<T: Real>(fault: StiffnessFault, force: T, r1: T, r2: T) -> Error {
    let (field, rule, value) = match fault {
        StiffnessFault::Force => ("force", "must be positive and finite", force),
        StiffnessFault::RollerRadius => ("r1", "roller radius must be positive and finite", r1),
        StiffnessFault::SurfaceRadius => {
            ("r2", "cam surface radius must be nonzero (infinite for a flat surface)", r2)
        }
        StiffnessFault::RollerDoesNotFit => (
            "r2",
            "concave surface radius |r2| must exceed the roller radius r1 (the roller does not fit)",
            r2,
        ),
        StiffnessFault::HalfWidthRoller => {
            ("r1", "half contact width w/2 must not exceed the roller radius", r1)
        }
        StiffnessFault::HalfWidthSurface => {
            ("r2", "half contact width w/2 must not exceed the cam surface radius |r2|", r2)
        }
    };
    Error::InvalidParameter {
        field,
        rule,
        value: value.to_f64(),
    }
}

/// Contact force between cam and roller and whether they touch (Eqs. V.19-V.20).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactForce<T> {
    /// Contact force F_c (lb), never negative (0 during a jump).
    pub force: T,
    /// False during separation (jump, Eq. V.20).
    pub in_contact: bool,
}

/// Contact force and jump criterion, Eqs. V.19-V.20:
/// `F_c = K_h (y + y1 + F_p/K_h - y2) cos(phi)` while positive, else 0 (jump).
///
/// `approach` is `y + y1 - y2`: the cam's commanded lift `y` at the current cam angle
/// (the printed "y_dot" is y, docs/MODEL.md §4.6) plus the cam's vertical displacement `y1`
/// minus the roller's `y2` (the model, which stores y2 relative to the lift, forms it as
/// `y1 - (y2 - y)`); `preload` is the return-spring preload F_p (Eq. V.18), `cos_phi`
/// the cosine of the pressure angle (the model forms it from R_a + y and dy/dθ, without
/// the angle). Computed as `(K_h approach + F_p) cos(phi)`, which needs no division by
/// K_h. Exactly at the boundary `approach = -F_p/K_h` the force is 0 and `in_contact` is
/// false (V.20 counts equality as separation). With `cos_phi > 0`, as for any pressure
/// angle, the sign of the force is that of the overlap. NaN inputs give a NaN force
/// (not in contact) so the solver's non-finite check reports them.
#[inline]
pub fn contact_force<T: Real>(k_h: T, approach: T, preload: T, cos_phi: T) -> ContactForce<T> {
    ContactForce::clamped((k_h * approach + preload) * cos_phi)
}

impl<T: Real> ContactForce<T> {
    /// A contact can only push: a positive force is contact, zero or less is separation
    /// with force 0 (V.20), NaN stays NaN and out of contact (the solver reports it).
    #[inline]
    fn clamped(f: T) -> Self {
        if f > T::ZERO {
            ContactForce {
                force: f,
                in_contact: true,
            }
        } else if f.is_nan() {
            ContactForce {
                force: f,
                in_contact: false,
            }
        } else {
            ContactForce {
                force: T::ZERO,
                in_contact: false,
            }
        }
    }
}

/// Viscous damping coefficient by the thesis's rule for damping that is not measured,
/// Eq. V.13: `C = 2 xi sqrt(K M)` (lb·s/in for K in lb/in and M in lb·s²/in).
///
/// For the contact (docs/MODEL.md §3.9) `K` is the Hertz stiffness K_h at the contact
/// point and `M` the roller mass M_r, the mass whose mode the damping is for. `xi = 0`
/// gives exactly 0 for any finite `K M`.
#[inline]
pub fn damping_coefficient<T: Real>(ratio: T, stiffness: T, mass: T) -> T {
    T::TWO * ratio * (stiffness * mass).sqrt()
}

/// Force of a spring `k` and a parallel damper `c` (Kelvin-Voigt) on the body at one end:
/// `k dx + c dv`, with `dx` and `dv` the other end's displacement and velocity relative
/// to this body's (lb). Used for the roller bearing K_rb with its damper C_rb
/// (docs/MODEL.md §3.13). `c == 0` returns `k dx` bit for bit, whatever `dv`.
#[inline]
pub fn spring_damper_force<T: Real>(k: T, dx: T, c: T, dv: T) -> T {
    if c == T::ZERO {
        k * dx
    } else {
        k * dx + c * dv
    }
}

/// Contact force with viscous damping at the contact (docs/MODEL.md §3.9): Eqs.
/// V.19-V.20 plus a damper `C_h` on the rate of approach, acting only in contact and
/// never pulling:
///
/// `F_c = max(0, (K_h (y + y1 - y2) + F_p + C_h d/dt(y + y1 - y2)) cos(phi))` while the
/// elastic part `(K_h (y + y1 - y2) + F_p) cos(phi)` is positive, else 0 (jump).
///
/// `approach`, `preload`, `cos_phi` are those of [`contact_force`]; `c_h` is the contact
/// damping coefficient (lb·s/in, [`damping_coefficient`]), expected `>= 0`;
/// `approach_rate` the time derivative of the approach, `y'(θ_c) θ̇_c + ẏ1 - ẏ2` (in/s,
/// positive while the cam and roller close in). The damper acts only while the elastic
/// overlap is positive: at the first touch the force jumps from 0 to `C_h rate cos(phi)`
/// (a Kelvin-Voigt contact). While the surfaces part faster than the elastic overlap
/// recovers, the damper would pull; the force is then 0 and the follower counts as out
/// of contact (`in_contact` is `force > 0`, as in V.20). The clamp makes the force
/// continuous where it engages.
///
/// `c_h == 0` returns [`contact_force`]'s result unchanged, bit for bit (the printed
/// model). NaN inputs give a NaN force (not in contact) so the solver's non-finite check
/// reports them.
#[inline]
pub fn damped_contact_force<T: Real>(
    k_h: T,
    approach: T,
    preload: T,
    c_h: T,
    approach_rate: T,
    cos_phi: T,
) -> ContactForce<T> {
    // The elastic term once: (e + c r) cos φ is the printed (K_h δ + F_p + c r) cos φ.
    let e = k_h * approach + preload;
    let elastic = ContactForce::clamped(e * cos_phi);
    if !elastic.in_contact || c_h == T::ZERO {
        return elastic;
    }
    ContactForce::clamped((e + c_h * approach_rate) * cos_phi)
}

/// Normal forces (N1, N2) in the follower's slide bearings, Eq. V.16:
/// `N1 = (A+B)/B |F_c sin(phi)|`, `N2 = A/B |F_c sin(phi)|` (magnitudes, lb).
///
/// `sin_phi` is the sine of the pressure angle (the model forms it without the angle),
/// `a` the distance A from the roller to the near bearing, `b` the bearing span B
/// (Fig. V.2). Precondition: `b > 0` (validated where the model is built); otherwise
/// both are NaN so the solver's non-finite check reports the bad geometry.
#[inline]
pub fn bearing_normal_forces<T: Real>(f_c: T, sin_phi: T, a: T, b: T) -> (T, T) {
    BearingLevers::new(a, b).normal_forces(f_c, sin_phi)
}

/// The lever ratios of Eq. V.16, `(A+B)/B` and `A/B`, divided once where a model is
/// built so its right-hand side only multiplies ([`bearing_normal_forces`] in two steps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BearingLevers<T> {
    n1: T,
    n2: T,
}

impl<T: Real> BearingLevers<T> {
    /// The ratios for bearing distance `a` (A) and span `b` (B); NaN unless `b > 0`.
    pub fn new(a: T, b: T) -> Self {
        if b > T::ZERO {
            Self {
                n1: (a + b) / b,
                n2: a / b,
            }
        } else {
            let nan = T::from_f64(f64::NAN);
            Self { n1: nan, n2: nan }
        }
    }

    /// (N1, N2) for contact force `f_c` and pressure-angle sine `sin_phi` (lb).
    #[inline]
    pub fn normal_forces(&self, f_c: T, sin_phi: T) -> (T, T) {
        let lateral = (f_c * sin_phi).abs();
        (self.n1 * lateral, self.n2 * lateral)
    }
}

/// Slide-bearing Coulomb friction on a mass, Eq. V.15: `F = -mu |N| tanh(v / v_smooth)`,
/// the force acting on the mass, opposing its velocity (lb).
///
/// The exact Coulomb law `-mu |N| sign(v)` jumps at `v = 0`, which an adaptive
/// Runge-Kutta step controller cannot resolve (its error estimate assumes a smooth
/// right-hand side). `tanh` keeps the right-hand side smooth: the force is within 0.5 %
/// of `mu |N|` once `|v| > 3 v_smooth` and passes through 0 with slope
/// `mu |N| / v_smooth`. Choose `v_smooth` far below the follower's working velocities
/// (the reference design uses 0.01 in/s, docs/MODEL.md §5.7). `v_smooth <= 0` (or NaN) selects the exact, discontinuous
/// law with `sign(0) = 0`. `mu` is the kinetic coefficient, expected `>= 0`.
#[inline]
pub fn coulomb_friction<T: Real>(mu: T, normal: T, velocity: T, v_smooth: T) -> T {
    let magnitude = mu * normal.abs();
    let shape = if v_smooth > T::ZERO {
        smooth_sign(velocity / v_smooth)
    } else if velocity > T::ZERO {
        T::ONE
    } else if velocity < T::ZERO {
        -T::ONE
    } else {
        // 0 stays 0, NaN stays NaN.
        velocity
    };
    -(magnitude * shape)
}

/// `tanh(x)` as `sign(x) (1 - 2 / (exp(2|x|) + 1))`, overflow-safe (exp(inf) = inf
/// gives exactly 1) and odd by construction. Above [`Real::TANH_SATURATES`] that
/// expression rounds to exactly 1, which is returned without the `exp` (the same bits).
#[inline]
fn smooth_sign<T: Real>(x: T) -> T {
    let ax = x.abs();
    let t = if ax > T::TANH_SATURATES {
        T::ONE
    } else {
        T::ONE - T::TWO / ((T::TWO * ax).exp() + T::ONE)
    };
    if x < T::ZERO {
        -t
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The short cut above `TANH_SATURATES` gives the bits the full expression gives:
    /// exactly 1, from the threshold up to where exp overflows (and beyond).
    #[test]
    fn smooth_sign_saturates_to_the_same_bits() {
        fn full<T: Real>(x: T) -> T {
            T::ONE - T::TWO / ((T::TWO * x).exp() + T::ONE)
        }
        let mut x = f32::TANH_SATURATES;
        while x < 200.0 {
            assert_eq!(full(x), 1.0, "f32 at {x}");
            assert_eq!(smooth_sign(-x), -1.0);
            x = x * 1.001 + 1e-3;
        }
        let mut x = f64::TANH_SATURATES;
        while x < 800.0 {
            assert_eq!(full(x), 1.0, "f64 at {x}");
            x = x * 1.001 + 1e-3;
        }
        // Below the threshold it is not yet 1 somewhere (the threshold is not far off).
        assert!(full(8.0f32) < 1.0 && full(18.0f64) < 1.0);
        // libm's exp keeps a NaN; micromath's fast exp does not promise to (the model's
        // non-finite checks catch it either way).
        #[cfg(not(feature = "micromath"))]
        assert!(smooth_sign(f32::NAN).is_nan());
    }

    const R1: f64 = 0.375;
    const R2: f64 = 1.5;

    fn steel() -> HertzContact<f64> {
        HertzContact::steel(0.25)
    }

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// Eqs. V.9-V.11 by hand for the reference pair, with the thesis's own
    /// `r - sqrt(r^2 - b^2)` (f64 keeps ~10 digits of it here).
    #[test]
    fn unit_force_stiffness_hand_calculation() {
        // C = 2 (1 - 0.295^2) / 30e6 = 2 * 0.912975 / 30e6 = 6.0865e-8 1/psi.
        let c = 2.0 * (1.0 - 0.295 * 0.295) / 30.0e6;
        assert!(rel(c, 6.0865e-8) < 1e-12);
        // 1/d1 + 1/d2 = 1/0.75 + 1/3 = 5/3 1/in.
        let curv = 1.0 / 0.75 + 1.0 / 3.0;
        // w = 2 sqrt(2 * 1 / (pi 0.25) * C / (5/3)) = 6.0990120e-4 in.
        let w = 2.0 * (2.0 / (core::f64::consts::PI * 0.25) * c / curv).sqrt();
        assert!(rel(w, 6.099_012_046_827_48e-4) < 1e-12);
        let b = w / 2.0;
        let h1 = R1 - (R1 * R1 - b * b).sqrt();
        let h2 = R2 - (R2 * R2 - b * b).sqrt();
        let k = 1.0 / (h1 + h2);
        // Same value from 40-digit arithmetic: 6451967.9446 lb/in.
        assert!(rel(k, 6_451_967.944_615_91) < 1e-8);
        let got = steel().stiffness(R1, R2).unwrap();
        assert!(rel(got, 6_451_967.944_615_91) < 1e-12, "{got}");
        assert!(rel(steel().stiffness_fast(R1, R2), got) < 1e-15);
        assert!(rel(steel().width(1.0, 0.75, 3.0), 6.099_012_046_827_48e-4) < 1e-13);
    }

    /// Leading order h = b^2/(2r): H = (w^2/8)(1/r1 + 1/r2) = 2 F C / (pi t), so
    /// K_h -> pi t / (2C) for any convex pair and half of it for a concave one.
    #[test]
    fn leading_order_is_radius_independent_and_concave_halves_it() {
        let h = steel();
        let k0 = core::f64::consts::PI * 0.25 / (2.0 * 6.0865e-8);
        for r2 in [0.5, 1.5, 10.0, f64::INFINITY] {
            let k = h.stiffness(R1, r2).unwrap();
            assert!(rel(k, k0) < 1e-6, "r2 = {r2}: {k} vs {k0}");
            assert!(k < k0, "higher-order terms only soften");
        }
        for r2 in [-0.5, -1.5, -10.0] {
            let k = h.stiffness(R1, r2).unwrap();
            assert!(rel(k, 0.5 * k0) < 1e-5, "r2 = {r2}: {k}");
        }
        // The documented 2x jump across the change of sign of the curvature.
        let ratio = h.stiffness(R1, 1.0e6).unwrap() / h.stiffness(R1, -1.0e6).unwrap();
        assert!((ratio - 2.0).abs() < 1e-6, "{ratio}");
    }

    #[test]
    fn flat_surface_works_both_signs_of_infinity() {
        let h = steel();
        let kp = h.stiffness(R1, f64::INFINITY).unwrap();
        let kn = h.stiffness(R1, f64::NEG_INFINITY).unwrap();
        assert_eq!(kp, kn);
        // 40-digit value of 1/h1 with 1/d2 = 0: 6451967.4779 lb/in.
        assert!(rel(kp, 6_451_967.477_949_13) < 1e-12, "{kp}");
    }

    #[test]
    fn concave_reference_value() {
        // Concave radius 3 in (40-digit value of 1/(2 (h1 - h2))).
        let k = steel().stiffness(R1, -3.0).unwrap();
        assert!(rel(k, 3_225_983.536_593_575) < 1e-11, "{k}");
    }

    /// Series h = (w^2/(8r))(1 + w^2/(16 r^2) + ...): relative softening of K from
    /// F = 1 to F lb is delta(F) - delta(1) with delta = (w^2/16) sum r^-3 / sum r^-1.
    #[test]
    fn stiffness_nearly_constant_in_force() {
        let h = steel();
        let k1 = h.stiffness_at(1.0, R1, R2).unwrap();
        assert_eq!(k1, h.stiffness(R1, R2).unwrap());
        let k1000 = h.stiffness_at(1000.0, R1, R2).unwrap();
        let w2 = h.width(1000.0, 0.75, 3.0).powi(2);
        let delta = w2 / 16.0 * (R1.powi(-3) + R2.powi(-3)) / (1.0 / R1 + 1.0 / R2);
        let change = (k1 - k1000) / k1;
        assert!(change > 0.0);
        assert!((change - delta).abs() < 0.01 * delta, "{change} vs {delta}");
        assert!(change < 1.5e-4);
    }

    #[test]
    fn width_scales_as_sqrt_force() {
        let h = steel();
        let w1 = h.width(1.0, 0.75, 3.0);
        for f in [4.0, 100.0, 2500.0] {
            assert!(rel(h.width(f, 0.75, 3.0), w1 * f.sqrt()) < 1e-14);
        }
        assert_eq!(h.width(0.0, 0.75, 3.0), 0.0);
        assert_eq!(h.width(-5.0, 0.75, 3.0), 0.0);
        assert_eq!(h.width(1.0, 0.75, -0.75), f64::INFINITY);
        assert!(h.width(f64::NAN, 0.75, 3.0).is_nan());
    }

    #[test]
    fn max_stress_matches_textbook_form() {
        let h = steel();
        let e_star = 1.0 / (2.0 * (1.0 - 0.295f64.powi(2)) / 30.0e6);
        let r_star = 1.0 / (1.0 / R1 + 1.0 / R2);
        for f in [1.0, 100.0, 1000.0] {
            let textbook = (f * e_star / (core::f64::consts::PI * 0.25 * r_star)).sqrt();
            assert!(rel(h.max_stress(f, 0.75, 3.0), textbook) < 1e-13);
        }
        // 40-digit value at 100 lb.
        assert!(rel(h.max_stress(100.0, 0.75, 3.0), 83_504.642_060_673_6) < 1e-13);
        assert_eq!(h.max_stress(0.0, 0.75, 3.0), 0.0);
        assert_eq!(h.max_stress(1.0, 0.75, -0.5), 0.0);
    }

    #[test]
    fn geometry_errors_name_the_field() {
        let h = steel();
        let field = |r: Result<f64>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            other => panic!("expected an error, got {other:?}"),
        };
        assert_eq!(field(h.stiffness(0.0, 1.0)), "r1");
        assert_eq!(field(h.stiffness(f64::NAN, 1.0)), "r1");
        assert_eq!(field(h.stiffness(R1, 0.0)), "r2");
        assert_eq!(field(h.stiffness(R1, f64::NAN)), "r2");
        assert_eq!(field(h.stiffness(R1, -R1)), "r2");
        assert_eq!(field(h.stiffness(R1, -0.2)), "r2");
        assert_eq!(field(h.stiffness_at(0.0, R1, R2)), "force");
        assert_eq!(field(h.stiffness_at(f64::INFINITY, R1, R2)), "force");
        // w/2 > r1: w = 2 sqrt(4 F C R*/(pi t)) grows without bound with F.
        assert_eq!(field(h.stiffness_at(1.0e7, 1.0e-3, R2)), "r1");
        assert_eq!(field(h.stiffness_at(1.0e7, R2, 1.0e-3)), "r2");
        // Concave but barely fitting: band explodes past the roller.
        assert_eq!(field(h.stiffness(R1, -(R1 + 1e-12))), "r1");
        let k0 = core::f64::consts::PI * 0.25 / (2.0 * h.compliance());
        assert_eq!(h.stiffness_fast(R1, -0.2), k0);
        assert_eq!(h.stiffness_fast(-1.0, 1.0), k0);
        assert!(h.stiffness_fast(f64::NAN, f64::NAN).is_finite());
    }

    #[test]
    fn new_checks_each_field() {
        let field = |r: Result<HertzContact<f64>>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            other => panic!("expected an error, got {other:?}"),
        };
        assert!(HertzContact::new(30e6, 0.295, 30e6, 0.295, 0.25).is_ok());
        assert_eq!(
            HertzContact::new(30e6, 0.0, 10e6, 0.49, 0.25)
                .unwrap()
                .youngs_2,
            10e6
        );
        assert_eq!(
            field(HertzContact::new(0.0, 0.3, 30e6, 0.3, 0.25)),
            "hertz.roller_youngs_psi"
        );
        assert_eq!(
            field(HertzContact::new(30e6, 0.5, 30e6, 0.3, 0.25)),
            "hertz.roller_poisson"
        );
        assert_eq!(
            field(HertzContact::new(30e6, -0.1, 30e6, 0.3, 0.25)),
            "hertz.roller_poisson"
        );
        assert_eq!(
            field(HertzContact::new(30e6, 0.3, f64::INFINITY, 0.3, 0.25)),
            "hertz.cam_youngs_psi"
        );
        assert_eq!(
            field(HertzContact::new(30e6, 0.3, 30e6, f64::NAN, 0.25)),
            "hertz.cam_poisson"
        );
        assert_eq!(
            field(HertzContact::new(30e6, 0.3, 30e6, 0.3, -0.25)),
            "hertz.contact_length_in"
        );
    }

    #[test]
    fn f32_agrees_with_f64() {
        let h32 = HertzContact::<f32>::steel(0.25);
        let k32 = h32.stiffness(0.375, 1.5).unwrap();
        assert!(rel(k32 as f64, 6_451_967.944_615_91) < 1e-5, "{k32}");
        let k32c = h32.stiffness(0.375, -3.0).unwrap();
        assert!(rel(k32c as f64, 3_225_983.536_593_575) < 1e-4, "{k32c}");
    }

    #[test]
    fn contact_force_overlap_boundary_and_jump() {
        let cos = 0.3f64.cos();
        // Overlap 1e-5 in with 10 lb preload: y + y1 - y2 = 0.5 + 1e-5 - 0.5.
        let c = contact_force(6.0e6, 0.5 + 1.0e-5 - 0.5, 10.0, cos);
        assert!(c.in_contact);
        assert!(rel(c.force, (60.0 + 10.0) * cos) < 1e-9);
        // Zero preload: K_h * overlap * cos(phi), with y + y1 - y2 = 0.5 + 0 - (0.5 - 2e-6).
        let c = contact_force(6.0e6, 0.5 - (0.5 - 2.0e-6), 0.0, cos);
        assert!(rel(c.force, 6.0e6 * 2.0e-6 * cos) < 1e-8);
        // Exactly at the boundary (binary-exact numbers): 2 * (0 + 0 - 0.5) + 1 = 0.
        let c = contact_force(2.0, -0.5, 1.0, cos);
        assert_eq!(
            c,
            ContactForce {
                force: 0.0,
                in_contact: false
            }
        );
        // Separated: y2 0.1 in above y + y1.
        let c = contact_force(6.0e6, 0.5 - 0.6, 10.0, cos);
        assert_eq!(
            c,
            ContactForce {
                force: 0.0,
                in_contact: false
            }
        );
        assert!(contact_force(6.0e6, f64::NAN, 10.0, cos).force.is_nan());
        assert!(!contact_force(6.0e6, 1e-5, 10.0, f64::NAN).in_contact);
    }

    /// Every input of the printed model's table, and some that are not finite: with
    /// `c_h = 0` the damped law returns [`contact_force`]'s result bit for bit, whatever
    /// the rate (even NaN or infinite).
    #[test]
    fn damped_contact_force_without_damping_is_the_printed_law() {
        let cos = 0.3f64.cos();
        let approaches = [1e-5, 2e-6, -0.5, -0.1, 0.0, -1e-300, f64::NAN, 1e300];
        let preloads = [0.0, 1.0, 10.0, 50.0];
        let rates = [0.0, -3.0, 7.5, 1e9, -1e9, f64::NAN, f64::INFINITY];
        for a in approaches {
            for p in preloads {
                for k in [2.0, 6.0e6] {
                    let printed = contact_force(k, a, p, cos);
                    for r in rates {
                        let damped = damped_contact_force(k, a, p, 0.0, r, cos);
                        assert_eq!(
                            damped.force.to_bits(),
                            printed.force.to_bits(),
                            "{k} {a} {p} {r}"
                        );
                        assert_eq!(damped.in_contact, printed.in_contact);
                    }
                }
            }
        }
    }

    /// The damping term by hand with binary-exact numbers, the clamp, and no damping
    /// outside contact.
    #[test]
    fn damped_contact_force_adds_the_damper_in_contact_and_never_pulls() {
        // K_h = 4, approach 0.5, F_p = 1: elastic bracket 3; C_h = 0.25, cos φ = 0.5.
        let f = |rate: f64| damped_contact_force(4.0, 0.5, 1.0, 0.25, rate, 0.5);
        // Closing at 4 in/s: (3 + 0.25 · 4) · 0.5 = 2.
        assert_eq!(
            f(4.0),
            ContactForce {
                force: 2.0,
                in_contact: true
            }
        );
        // Opening at 4 in/s: (3 - 1) · 0.5 = 1.
        assert_eq!(f(-4.0).force, 1.0);
        // Opening at exactly 12 in/s the damper cancels the elastic part: 0, a jump (V.20).
        assert_eq!(
            f(-12.0),
            ContactForce {
                force: 0.0,
                in_contact: false
            }
        );
        // Faster it would pull: clamped at 0.
        assert_eq!(
            f(-100.0),
            ContactForce {
                force: 0.0,
                in_contact: false
            }
        );
        // Continuous where the clamp engages: the force falls linearly to 0 at -12 in/s.
        for r in [-11.0, -11.9, -11.99] {
            let got = f(r).force;
            assert!((got - 0.125 * (r + 12.0)).abs() < 1e-15, "{r}: {got}");
        }
        // No damping while the elastic part is not positive, however fast the approach:
        // at the touching point (elastic 0) and separated.
        for a in [-0.25, -0.3] {
            assert_eq!(
                damped_contact_force(4.0, a, 1.0, 0.25, 1e6, 0.5),
                ContactForce {
                    force: 0.0,
                    in_contact: false
                }
            );
        }
        // Bad values reach the solver as NaN.
        assert!(damped_contact_force(4.0, 0.5, 1.0, f64::NAN, 1.0, 0.5)
            .force
            .is_nan());
        assert!(damped_contact_force(4.0, 0.5, 1.0, 0.25, f64::NAN, 0.5)
            .force
            .is_nan());
        assert!(!damped_contact_force(4.0, 0.5, 1.0, 0.25, f64::NAN, 0.5).in_contact);
        // V.13: C = 2 ξ sqrt(K M); 2 · 0.05 · sqrt(4e6 · 1e-4) = 2.
        assert!((damping_coefficient(0.05, 4.0e6, 1.0e-4) - 2.0).abs() < 1e-15);
        assert_eq!(damping_coefficient(0.0, 6.45e6, 1.3e-4), 0.0);
    }

    /// The roller bearing's spring and damper by hand, and `c = 0` as the spring alone
    /// bit for bit (whatever the velocity, the sign of a zero kept).
    #[test]
    fn spring_damper_force_by_hand_and_without_damping() {
        assert_eq!(spring_damper_force(4.0, 0.5, 0.25, -4.0), 1.0);
        assert_eq!(spring_damper_force(4.0, -0.5, 0.25, 4.0), -1.0);
        assert_eq!(spring_damper_force(1.5e6, 0.0, 1.4, 2.0), 2.8);
        for (k, dx) in [(1.5e6, 1e-6), (1.5e6, -3e-7), (2.0, -0.0), (1.5e6, 0.0)] {
            for dv in [0.0, -0.0, 5.0, f64::NAN, f64::INFINITY] {
                assert_eq!(
                    spring_damper_force(k, dx, 0.0, dv).to_bits(),
                    (k * dx).to_bits(),
                    "{k} {dx} {dv}"
                );
            }
        }
        assert!(spring_damper_force(1.0, 1.0, 1.0, f64::NAN).is_nan());
    }

    /// Rebound of a mass m from a wall through this contact (k, c = 2 ζ sqrt(k m), no
    /// preload, cos φ = 1), integrated by classic RK4 with a small step. By hand: in
    /// contact δ'' + 2ζω δ' + ω² δ = 0 from δ = 0, δ' = v0, so
    /// δ = (v0/ω_d) e^(-ζωt) sin(ω_d t), ω_d = ω sqrt(1 - ζ²). The force k δ + c δ'
    /// reaches 0 (the clamp) where ω²(1 - 2ζ²) sin + 2ζω ω_d cos = 0, that is
    /// ω_d t* = π - 2α with sin α = ζ, while the overlap is still positive; there
    /// δ'(t*) = -v0 e^(-ζω t*) exactly, and the mass leaves with that velocity (after t*
    /// k δ + c δ' < 0 as δ falls, so it never touches again). Coefficient of restitution
    /// e = exp(-ζ (π - 2 asin ζ) / sqrt(1 - ζ²)): larger than the unclamped Kelvin-Voigt
    /// exp(-ζ π / sqrt(1 - ζ²)), which would pull the mass back until δ = 0.
    #[test]
    fn damped_contact_restitution_matches_the_clamped_kelvin_voigt_closed_form() {
        let (m, k, v0) = (2.0f64, 50.0f64, 3.0f64);
        let w = (k / m).sqrt();
        for zeta in [0.0, 0.05, 0.2, 0.5] {
            let c = damping_coefficient(zeta, k, m);
            let accel = |d: f64, v: f64| -damped_contact_force(k, d, 0.0, c, v, 1.0).force / m;
            let h = 1e-5 / w;
            let (mut d, mut v, mut t) = (0.0f64, v0, 0.0f64);
            let mut touched = false;
            let mut t_release = f64::NAN;
            // Until the mass is clear of the wall (δ < 0) after having been in contact.
            while !(touched && d < 0.0) {
                let (k1d, k1v) = (v, accel(d, v));
                let (k2d, k2v) = (
                    v + 0.5 * h * k1v,
                    accel(d + 0.5 * h * k1d, v + 0.5 * h * k1v),
                );
                let (k3d, k3v) = (
                    v + 0.5 * h * k2v,
                    accel(d + 0.5 * h * k2d, v + 0.5 * h * k2v),
                );
                let (k4d, k4v) = (v + h * k3v, accel(d + h * k3d, v + h * k3v));
                d += h / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                t += h;
                let f = damped_contact_force(k, d, 0.0, c, v, 1.0);
                if f.in_contact {
                    touched = true;
                } else if touched && t_release.is_nan() {
                    t_release = t;
                }
                assert!(t < 10.0 / w, "no rebound");
            }
            let s = (1.0 - zeta * zeta).sqrt();
            let e = (-zeta * (core::f64::consts::PI - 2.0 * zeta.asin()) / s).exp();
            let got = -v / v0;
            assert!((got - e).abs() < 1e-5, "ζ {zeta}: e {got} vs {e}");
            let t_star = (core::f64::consts::PI - 2.0 * zeta.asin()) / (w * s);
            assert!(
                (t_release - t_star).abs() < 3.0 * h,
                "ζ {zeta}: released at {t_release}, expected {t_star}"
            );
            let e_unclamped = (-zeta * core::f64::consts::PI / s).exp();
            if zeta > 0.0 {
                assert!(got - e_unclamped > 1e-3, "ζ {zeta}: {got} vs {e_unclamped}");
            }
        }
    }

    #[test]
    fn bearing_forces() {
        let (n1, n2) = bearing_normal_forces(100.0, (-0.5f64).sin(), 2.0, 3.0);
        let s = 0.5f64.sin() * 100.0;
        assert!(rel(n1, 5.0 / 3.0 * s) < 1e-14);
        assert!(rel(n2, 2.0 / 3.0 * s) < 1e-14);
        // Moment balance about the far bearing and force balance (Fig. V.2).
        assert!(((n1 - n2) - s).abs() < 1e-12);
        let (a, b) = bearing_normal_forces(100.0, 0.3f64.sin(), 2.0, 0.0);
        assert!(a.is_nan() && b.is_nan());
    }

    #[test]
    fn friction_opposes_velocity_and_is_continuous() {
        let (mu, n, vs) = (0.08, 50.0, 1.0e-3);
        assert!(rel(coulomb_friction(mu, n, 1.0, vs), -4.0) < 1e-12);
        assert!(rel(coulomb_friction(mu, -n, -1.0, vs), 4.0) < 1e-12);
        assert_eq!(coulomb_friction(mu, n, 0.0, vs), 0.0);
        // tanh(1) = 0.7615941559557649.
        assert!(
            rel(
                coulomb_friction(mu, n, vs, vs),
                -4.0 * 0.761_594_155_955_764_9
            ) < 1e-14
        );
        // Continuity through 0: slope mu N / v_smooth.
        let dv = 1.0e-9;
        let slope =
            (coulomb_friction(mu, n, dv, vs) - coulomb_friction(mu, n, -dv, vs)) / (2.0 * dv);
        assert!(rel(slope, -mu * n / vs) < 1e-6, "{slope}");
        // Monotone non-increasing in v over a sweep.
        let mut last = f64::INFINITY;
        for i in -200..=200 {
            let f = coulomb_friction(mu, n, f64::from(i) * 2.5e-5, vs);
            assert!(f <= last);
            last = f;
        }
        // Exact law when v_smooth <= 0; huge argument saturates without NaN.
        assert_eq!(coulomb_friction(mu, n, 1.0e-12, 0.0), -4.0);
        assert_eq!(coulomb_friction(mu, n, 0.0, 0.0), 0.0);
        assert_eq!(coulomb_friction(mu, n, 1.0e300, 1.0e-300), -4.0);
        assert_eq!(coulomb_friction(mu, n, -1.0e300, 1.0e-300), 4.0);
    }
}
