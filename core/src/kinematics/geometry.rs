//! Disk cam with an inline translating roller follower: pressure angle, radius of
//! curvature (Eq. V.12), cam surface coordinates (Eqs. V.1 / E.6), mass and polar
//! moment of inertia (Eqs. V.2-V.4), undercut.
//!
//! Cam-fixed frame: the roller centre (pitch point) at cam angle θ is
//! `(R_a + y)(sin θ, cos θ)` with `R_a = R_b + r_r`; the contact point on the cam
//! surface lies `r_r` from it along the pitch curve's inward normal.

use crate::{
    key, non_negative, positive, CamProgram, Error, Peak, PeakScan, Real, Result, ScanEnds,
};

/// Dimensions of a disk cam and its inline translating roller follower (in).
///
/// Scene keys (`[geometry]`): `base_radius_in`, `roller_radius_in`, `thickness_in`;
/// absent keys take the reference values.
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
pub struct CamGeometry<T> {
    /// Base circle radius R_b (in).
    #[cfg_attr(feature = "serde", serde(rename = "base_radius_in"))]
    pub base_radius: T,
    /// Roller radius r_r (in); 0 is a knife edge.
    #[cfg_attr(feature = "serde", serde(rename = "roller_radius_in"))]
    pub roller_radius: T,
    /// Cam thickness t (in), for the cam's mass properties.
    #[cfg_attr(feature = "serde", serde(rename = "thickness_in"))]
    pub thickness: T,
}

impl<T: Real> Default for CamGeometry<T> {
    /// [`CamGeometry::reference`].
    fn default() -> Self {
        Self::reference()
    }
}

/// Area, volume, mass and polar moment of inertia of a disk cam (Eqs. V.2-V.4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CamMassProperties<T> {
    /// Area of the cam face (in²).
    pub area: T,
    /// Volume, area times thickness (in³).
    pub volume: T,
    /// Mass (lb·s²/in with a density in lb·s²/in⁴).
    pub mass: T,
    /// Polar moment of inertia about the camshaft, `ρ t ∮ r⁴/4 dα` with `α` the polar
    /// angle of the surface point (lb·in·s²).
    pub polar_inertia: T,
    /// Eq. V.4 taken literally, `ρ t ∫ r⁴/4 dθ` over the cam angle `θ` rather than the
    /// surface point's own polar angle (lb·in·s²); equal on a circle, close elsewhere.
    pub polar_inertia_eq_v4: T,
}

/// Where a cam profile is tightest (Eq. V.12) and whether it is undercut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UndercutReport<T> {
    /// Smallest cam surface radius of curvature (pitch radius − r_r) where the pitch
    /// curve is convex (in); `T::INFINITY` if there is no convex sample.
    pub min_convex_surface_radius: T,
    /// Cam angle where it occurs (rad).
    pub min_convex_at: T,
    /// Smallest magnitude of the pitch-curve radius where the pitch curve is concave
    /// (in); `T::INFINITY` if the profile is nowhere concave.
    pub min_concave_pitch_radius: T,
    /// Cam angle where it occurs (rad).
    pub min_concave_at: T,
    /// True if the surface radius changes sign in a convex region (pitch radius below
    /// the roller radius): the roller cannot generate that part of the profile.
    ///
    /// Concave regions never undercut an inline roller: there the surface radius
    /// magnitude is the pitch radius magnitude plus r_r, always larger than the roller.
    pub undercut: bool,
}

impl<T: Real> CamGeometry<T> {
    /// Validated dimensions: base radius and thickness positive, roller radius
    /// non-negative, all finite.
    pub fn new(base_radius: T, roller_radius: T, thickness: T) -> Result<Self> {
        let g = CamGeometry {
            base_radius,
            roller_radius,
            thickness,
        };
        g.validate()?;
        Ok(g)
    }

    /// Checks the dimensions of [`CamGeometry::new`]; errors name the scene key
    /// (`geometry.roller_radius_in`).
    pub fn validate(&self) -> Result<()> {
        positive(key::BASE_RADIUS, self.base_radius)?;
        non_negative(key::ROLLER_RADIUS, self.roller_radius)?;
        positive(key::THICKNESS, self.thickness)?;
        Ok(())
    }

    /// The same dimensions in precision `U`, each converted with [`Real::cast`]
    /// (not checked: [`CamGeometry::validate`] does that).
    pub fn cast<U: Real>(&self) -> CamGeometry<U> {
        CamGeometry {
            base_radius: self.base_radius.cast(),
            roller_radius: self.roller_radius.cast(),
            thickness: self.thickness.cast(),
        }
    }

    /// The reference cam of VI.1: R_b = 1.5 in, r_r = 0.375 in, t = 0.25 in.
    pub fn reference() -> Self {
        CamGeometry {
            base_radius: T::from_f64(1.5),
            roller_radius: T::from_f64(0.375),
            thickness: T::from_f64(0.25),
        }
    }

    /// Prime radius R_a = R_b + r_r (Eq. V.12), the pitch curve's radius at zero lift.
    #[inline]
    pub fn prime_radius(&self) -> T {
        self.base_radius + self.roller_radius
    }

    /// Pressure angle φ (rad) from `tan φ = (dy/dθ) / (R_a + y)`; signed like `dy`.
    #[inline]
    pub fn pressure_angle(&self, y: T, dy: T) -> T {
        dy.atan2(self.prime_radius() + y)
    }

    /// Numerator and denominator of Eq. V.12 for the pitch curve.
    #[inline]
    fn curvature_terms(&self, y: T, dy: T, d2y: T) -> (T, T) {
        let r = self.prime_radius() + y;
        let r2 = r * r;
        let d2 = dy * dy;
        let q = r2 + d2;
        (q * q.sqrt(), r2 + T::TWO * d2 - r * d2y)
    }

    /// Radius of curvature of the pitch curve (the roller centre's path), Eq. V.12
    /// without the `- r_1`: `[(R_a+y)² + y'²]^{3/2} / [(R_a+y)² + 2y'² - (R_a+y) y'']`
    /// (in; positive convex, negative concave, `T::INFINITY` where straight).
    #[inline]
    pub fn pitch_curvature_radius(&self, y: T, dy: T, d2y: T) -> T {
        let (num, den) = self.curvature_terms(y, dy, d2y);
        if den == T::ZERO {
            T::INFINITY
        } else {
            num / den
        }
    }

    /// Radius of curvature of the cam surface, Eq. V.12: the pitch radius minus r_r
    /// (in; positive convex, negative concave).
    #[inline]
    pub fn surface_curvature_radius(&self, y: T, dy: T, d2y: T) -> T {
        self.pitch_curvature_radius(y, dy, d2y) - self.roller_radius
    }

    /// Cam surface point in contact with the roller at cam angle θ, Eqs. V.1 / E.6:
    /// `x = (y + R_a) sin θ + r_r cos(ψ - θ)`, `y = (y + R_a) cos θ + r_r sin(ψ - θ)`,
    /// `ψ = φ - π/2` (in, cam-fixed frame).
    #[inline]
    pub fn surface_point(&self, theta: T, y: T, dy: T) -> (T, T) {
        let r = self.prime_radius() + y;
        let phi = self.pressure_angle(y, dy);
        let (st, ct) = theta.sin_cos();
        // cos(ψ - θ) = sin(φ - θ), sin(ψ - θ) = -cos(φ - θ).
        let (sd, cd) = (phi - theta).sin_cos();
        (
            r * st + self.roller_radius * sd,
            r * ct - self.roller_radius * cd,
        )
    }

    /// Pitch-curve point (the roller centre) at cam angle θ, cam-fixed frame of
    /// [`Self::surface_point`]: `(R_a + y)(sin θ, cos θ)` (in).
    #[inline]
    pub fn pitch_point(&self, theta: T, y: T) -> (T, T) {
        let r = self.prime_radius() + y;
        let (st, ct) = theta.sin_cos();
        (r * st, r * ct)
    }

    /// The point at signed distance `d` from the pitch curve along its outward normal
    /// at cam angle θ (in): `d = -r_r` is the cam surface ([`Self::surface_point`]),
    /// `d = r_c - r_r` the centre of a cutter (grinding wheel or end mill) of radius
    /// `r_c` cutting that surface from outside. The outward unit normal of the pitch
    /// curve is `(-sin(φ - θ), cos(φ - θ))` (Eq. V.1's roller term with its sign
    /// turned), φ the pressure angle.
    #[inline]
    pub fn pitch_offset_point(&self, theta: T, y: T, dy: T, d: T) -> (T, T) {
        let (px, py) = self.pitch_point(theta, y);
        let (sd, cd) = (self.pressure_angle(y, dy) - theta).sin_cos();
        (px - d * sd, py + d * cd)
    }

    /// Area, volume, mass and polar moment of inertia of the cam cut for `program`,
    /// Eqs. V.2-V.4, from `samples` (at least 16) equally spaced cam angles.
    ///
    /// The surface points (Eq. V.1) are joined into a polygon whose area and polar
    /// moment are exact (Green's theorem), so both converge as `1/samples²`; the
    /// literal Eq. V.4 (integrated over the cam angle) is reported alongside.
    /// `density` is a mass density (lb·s²/in⁴).
    pub fn mass_properties<const N: usize>(
        &self,
        program: &CamProgram<T, N>,
        density: T,
        samples: usize,
    ) -> Result<CamMassProperties<T>> {
        let density = positive("density", density)?;
        check_samples(samples)?;
        let n = T::from_usize(samples);
        let step = T::TWO * T::PI / n;
        let point = |k: usize| {
            let th = T::from_usize(k) * step;
            let f = program.follower(th);
            self.surface_point(th, f.y, f.dy)
        };
        let first = point(0);
        let (mut prev, mut area2, mut j12, mut v4) = (first, T::ZERO, T::ZERO, T::ZERO);
        for k in 1..=samples {
            let cur = if k == samples { first } else { point(k) };
            let (x0, y0) = prev;
            let (x1, y1) = cur;
            let cross = x0 * y1 - x1 * y0;
            area2 += cross;
            j12 += cross * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1);
            v4 += (x0 * x0 + y0 * y0).sq();
            prev = cur;
        }
        // θ runs clockwise in this frame: the signed sums are negative.
        let area = area2.abs() * T::HALF;
        let volume = area * self.thickness;
        let rho_t = density * self.thickness;
        Ok(CamMassProperties {
            area,
            volume,
            mass: density * volume,
            polar_inertia: rho_t * j12.abs() / T::from_i32(12),
            polar_inertia_eq_v4: rho_t * v4 * step / T::from_i32(4),
        })
    }

    /// The tightest convex and concave curvature of the profile for `program` from
    /// `samples` (at least 16) cam angles, and from [`SEGMENT_SAMPLES`] angles across
    /// each rise and return however short it is (a 0.01° rise falls between the
    /// revolution's samples), each minimum refined between its neighbours; and whether
    /// the cam is undercut (Eq. V.12). A curvature that is not a number (a segment so
    /// short that the lift's derivatives overflow) counts as an undercut.
    pub fn undercut<const N: usize>(
        &self,
        program: &CamProgram<T, N>,
        samples: usize,
    ) -> Result<UndercutReport<T>> {
        check_samples(samples)?;
        let step = T::TWO * T::PI / T::from_usize(samples);
        // Objectives to maximize: minus the convex surface radius, minus |concave pitch
        // radius|; -∞ outside their region; +∞ (the worst) where not a number.
        let convex = |th: T| {
            let f = program.follower(th);
            let (num, den) = self.curvature_terms(f.y, f.dy, f.d2y);
            if !(num.is_finite() && den.is_finite()) {
                T::INFINITY
            } else if den > T::ZERO {
                self.roller_radius - num / den
            } else {
                -T::INFINITY
            }
        };
        let concave = |th: T| {
            let f = program.follower(th);
            let (num, den) = self.curvature_terms(f.y, f.dy, f.d2y);
            if den < T::ZERO && num.is_finite() {
                num / den
            } else {
                -T::INFINITY
            }
        };
        let (mut cx_at, mut cx) = argmax_refined(convex, step, samples);
        let (mut cc_at, mut cc) = argmax_refined(concave, step, samples);
        for seg in program.segments() {
            if seg.kind == crate::SegmentKind::Dwell {
                continue;
            }
            let start = seg.start_deg.to_radians();
            let mut width = seg.end_deg.to_radians() - start;
            if width <= T::ZERO {
                width += T::TWO * T::PI;
            }
            let scan = PeakScan {
                start,
                step: width / T::from_usize(SEGMENT_SAMPLES - 1),
                points: SEGMENT_SAMPLES,
                ends: ScanEnds::Clamped,
                iterations: REFINE_ITERATIONS,
            };
            if let Some(p) = scan.maximize(convex) {
                if p.value > cx {
                    (cx_at, cx) = (wrap_two_pi(p.at), p.value);
                }
            }
            if let Some(p) = scan.maximize(concave) {
                if p.value > cc {
                    (cc_at, cc) = (wrap_two_pi(p.at), p.value);
                }
            }
        }
        let min_convex_surface_radius = -cx;
        Ok(UndercutReport {
            min_convex_surface_radius,
            min_convex_at: cx_at,
            min_concave_pitch_radius: -cc,
            min_concave_at: cc_at,
            undercut: min_convex_surface_radius <= T::ZERO || min_convex_surface_radius.is_nan(),
        })
    }

    /// Largest pressure-angle magnitude over the revolution (rad) and the cam angle
    /// where it occurs (rad), from `samples` cam angles (16 at least are used) refined
    /// between the neighbours of the best one.
    pub fn max_pressure_angle<const N: usize>(
        &self,
        program: &CamProgram<T, N>,
        samples: usize,
    ) -> (T, T) {
        let samples = samples.max(MIN_SAMPLES);
        let step = T::TWO * T::PI / T::from_usize(samples);
        let phi = |th: T| {
            let f = program.follower(th);
            self.pressure_angle(f.y, f.dy.abs())
        };
        let (at, value) = argmax_refined(phi, step, samples);
        (value, at)
    }
}

/// Angles scanned across each rise and return by [`CamGeometry::undercut`], whatever
/// its length: 64, so that a segment's curvature extreme (near its ends for the usual
/// laws) lies within 1/63 of the segment of a sample before the golden-section refinement.
pub const SEGMENT_SAMPLES: usize = 64;

/// Golden-section steps of the scans: enough to reach the precision's resolution.
const REFINE_ITERATIONS: u32 = 80;

/// An angle wrapped into [0, 2π).
fn wrap_two_pi<T: Real>(at: T) -> T {
    let two_pi = T::TWO * T::PI;
    let a = if at < T::ZERO { at + two_pi } else { at };
    if a >= two_pi {
        a - two_pi
    } else {
        a
    }
}

/// Fewest samples the profile scans accept.
const MIN_SAMPLES: usize = 16;

fn check_samples(samples: usize) -> Result<()> {
    if samples < MIN_SAMPLES {
        return Err(Error::InvalidParameter {
            field: "samples",
            rule: "must be at least 16",
            value: samples as f64,
        });
    }
    Ok(())
}

/// Maximum of `f` over the angles `k * step`, `k < samples`, then refined by golden
/// section between the best sample's neighbours ([`PeakScan`], periodic); returns the
/// best point seen, wrapped into [0, 2π), and its value (so a maximum at a kink or a jump
/// is never lost), or (0, −∞) when `f` is −∞ everywhere.
fn argmax_refined<T: Real>(f: impl Fn(T) -> T, step: T, samples: usize) -> (T, T) {
    let scan = PeakScan {
        start: T::ZERO,
        step,
        points: samples,
        ends: ScanEnds::Periodic,
        // Enough steps to reach the precision's resolution of the bracket.
        iterations: if T::EPSILON < T::from_f64(1e-10) {
            80
        } else {
            40
        },
    };
    let Some(Peak { at, value }) = scan.maximize(f) else {
        return (T::ZERO, -T::INFINITY);
    };
    let two_pi = T::TWO * T::PI;
    let wrapped = if at < T::ZERO { at + two_pi } else { at };
    (
        if wrapped >= two_pi {
            wrapped - two_pi
        } else {
            wrapped
        },
        value,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MotionLaw, Segment, SegmentKind};
    use core::f64::consts::PI;

    const STEEL: f64 = crate::STEEL_DENSITY;

    fn base_circle() -> CamProgram<f64, 1> {
        CamProgram::new(&[Segment {
            kind: SegmentKind::Dwell,
            start_deg: 0.0,
            end_deg: 360.0,
            lift: 0.0,
        }])
        .unwrap()
    }

    #[test]
    fn validation() {
        assert!(CamGeometry::new(1.5, 0.375, 0.25).is_ok());
        assert!(CamGeometry::new(1.5, 0.0, 0.25).is_ok());
        let field = |r: Result<CamGeometry<f64>>| match r {
            Err(Error::InvalidParameter { field, .. }) => field,
            _ => "",
        };
        assert_eq!(
            field(CamGeometry::new(0.0, 0.375, 0.25)),
            "geometry.base_radius_in"
        );
        assert_eq!(
            field(CamGeometry::new(1.5, -0.1, 0.25)),
            "geometry.roller_radius_in"
        );
        assert_eq!(
            field(CamGeometry::new(1.5, 0.375, f64::NAN)),
            "geometry.thickness_in"
        );
        let g = CamGeometry::<f64>::reference();
        assert_eq!(g, CamGeometry::new(1.5, 0.375, 0.25).unwrap());
        let p = CamProgram::<f64>::reference();
        assert!(g.mass_properties(&p, STEEL, 15).is_err());
        assert!(g.mass_properties(&p, -1.0, 64).is_err());
        assert!(g.undercut(&p, 8).is_err());
    }

    #[test]
    fn base_circle_closed_forms() {
        let g = CamGeometry::<f64>::reference();
        let (rb, ra) = (1.5, 1.875);
        assert_eq!(g.prime_radius(), ra);
        assert_eq!(g.pressure_angle(0.0, 0.0), 0.0);
        assert_eq!(g.pitch_curvature_radius(0.0, 0.0, 0.0), ra);
        assert_eq!(g.surface_curvature_radius(0.0, 0.0, 0.0), rb);
        for k in 0..12 {
            let th = k as f64 * 0.5;
            let (x, y) = g.surface_point(th, 0.0, 0.0);
            assert!((x.hypot(y) - rb).abs() < 1e-15);
            assert!((x - rb * th.sin()).abs() < 1e-15 && (y - rb * th.cos()).abs() < 1e-15);
        }
        // The polygon of n points on the base circle: area (n/2) R² sin(2π/n) and polar
        // moment (n/12) R⁴ sin(2π/n) (2 + cos(2π/n)), both tending to πR², πR⁴/2.
        let c = base_circle();
        for n in [16usize, 360, 4096] {
            let m = g.mass_properties(&c, STEEL, n).unwrap();
            let a = 2.0 * PI / n as f64;
            let area = n as f64 / 2.0 * rb * rb * a.sin();
            let j = n as f64 / 12.0 * rb.powi(4) * a.sin() * (2.0 + a.cos());
            assert!((m.area - area).abs() < 1e-12, "area {n}");
            assert!((m.polar_inertia - STEEL * 0.25 * j).abs() < 1e-15, "J {n}");
            assert!((m.polar_inertia_eq_v4 - STEEL * 0.25 * PI * rb.powi(4) / 2.0).abs() < 1e-15);
            assert!((m.volume - 0.25 * m.area).abs() < 1e-15);
            assert!((m.mass - STEEL * m.volume).abs() < 1e-18);
        }
        let m = g.mass_properties(&c, STEEL, 1 << 14).unwrap();
        assert!((m.area / (PI * rb * rb) - 1.0).abs() < 1e-7);
        assert!((m.polar_inertia / (STEEL * 0.25 * PI * rb.powi(4) / 2.0) - 1.0).abs() < 1e-7);
        // A base circle is neither undercut nor concave, and its pressure angle is 0.
        let u = g.undercut(&c, 64).unwrap();
        assert!((u.min_convex_surface_radius - rb).abs() < 1e-12);
        assert_eq!(u.min_concave_pitch_radius, f64::INFINITY);
        assert!(!u.undercut);
        assert_eq!(g.max_pressure_angle(&c, 64).0, 0.0);
    }

    #[test]
    fn pressure_angle_is_the_pitch_normal_against_the_follower_axis() {
        // For an inline follower the pressure angle is the angle between the pitch
        // curve's tangent and the circumferential direction, from the curve itself.
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let ra = g.prime_radius();
        let pitch = |th: f64| {
            let r = ra + p.follower(th).y;
            (r * th.sin(), r * th.cos())
        };
        let h = 1e-6;
        for k in 0..72 {
            let th = (k as f64 * 5.0 + 1.3).to_radians();
            let ((xm, ym), (xp, yp)) = (pitch(th - h), pitch(th + h));
            let (tx, ty) = ((xp - xm) / (2.0 * h), (yp - ym) / (2.0 * h));
            let (er, et) = ((th.sin(), th.cos()), (th.cos(), -th.sin()));
            let want = (tx * er.0 + ty * er.1).atan2(tx * et.0 + ty * et.1);
            let f = p.follower(th);
            assert!((g.pressure_angle(f.y, f.dy) - want).abs() < 1e-8, "at {k}");
        }
    }

    #[test]
    fn curvature_matches_finite_differences_of_the_pitch_curve() {
        let g = CamGeometry::<f64>::reference();
        for (rise, ret) in [
            (MotionLaw::ModifiedTrapezoidal, MotionLaw::Poly4567),
            (MotionLaw::Cycloidal, MotionLaw::DoubleHarmonic),
        ] {
            let p = CamProgram::<f64>::with_laws(rise, ret);
            let pitch = |th: f64| {
                let r = g.prime_radius() + p.follower(th).y;
                (r * th.sin(), r * th.cos())
            };
            let h = 1e-4;
            for k in 0..120 {
                let th = (k as f64 * 3.0 + 0.7).to_radians();
                let ((x0, y0), (x1, y1), (x2, y2)) = (pitch(th - h), pitch(th), pitch(th + h));
                let (dx, dy) = ((x2 - x0) / (2.0 * h), (y2 - y0) / (2.0 * h));
                let (ddx, ddy) = (
                    (x2 - 2.0 * x1 + x0) / (h * h),
                    (y2 - 2.0 * y1 + y0) / (h * h),
                );
                // θ runs clockwise, so a convex curve has a negative signed curvature.
                let kappa = -(dx * ddy - dy * ddx) / (dx * dx + dy * dy).powf(1.5);
                let f = p.follower(th);
                let rho = g.pitch_curvature_radius(f.y, f.dy, f.d2y);
                assert!(
                    (1.0 / rho - kappa).abs() < 1e-5,
                    "{rise:?} at {k}: 1/{rho} vs {kappa}"
                );
                assert_eq!(g.surface_curvature_radius(f.y, f.dy, f.d2y), rho - 0.375);
            }
        }
    }

    #[test]
    fn surface_point_is_the_roller_offset_along_the_normal() {
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let ra = g.prime_radius();
        let h = 1e-6;
        for k in 0..90 {
            let th = (k as f64 * 4.0 + 2.1).to_radians();
            let f = p.follower(th);
            let (cx, cy) = ((ra + f.y) * th.sin(), (ra + f.y) * th.cos());
            let (sx, sy) = g.surface_point(th, f.y, f.dy);
            // r_r from the roller centre ...
            assert!(((sx - cx).hypot(sy - cy) - 0.375).abs() < 1e-12);
            // ... perpendicular to the pitch curve ...
            let pitch = |t: f64| {
                let r = ra + p.follower(t).y;
                (r * t.sin(), r * t.cos())
            };
            let ((xm, ym), (xp, yp)) = (pitch(th - h), pitch(th + h));
            let (tx, ty) = (xp - xm, yp - ym);
            let dot = (tx * (sx - cx) + ty * (sy - cy)) / tx.hypot(ty);
            assert!(dot.abs() < 1e-7, "at {k}: {dot}");
            // ... and towards the cam centre.
            assert!(sx.hypot(sy) < cx.hypot(cy));
        }
    }

    #[test]
    fn offset_points_are_the_pitch_curve_moved_along_its_normal() {
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let ra = g.prime_radius();
        for k in 0..90 {
            let th = (k as f64 * 4.0 + 2.1).to_radians();
            let f = p.follower(th);
            let (cx, cy) = g.pitch_point(th, f.y);
            assert!(((cx - (ra + f.y) * th.sin()).abs()) < 1e-15);
            // d = -r_r is the surface, exactly.
            let s = g.surface_point(th, f.y, f.dy);
            let o = g.pitch_offset_point(th, f.y, f.dy, -g.roller_radius);
            assert!((s.0 - o.0).abs() < 1e-15 && (s.1 - o.1).abs() < 1e-15);
            // A cutter of radius 2 in: 2 - r_r outside the pitch curve, at distance |d|.
            let d = 2.0 - g.roller_radius;
            let (qx, qy) = g.pitch_offset_point(th, f.y, f.dy, d);
            assert!(((qx - cx).hypot(qy - cy) - d).abs() < 1e-12);
            assert!(qx.hypot(qy) > cx.hypot(cy));
        }
        // On the base circle (a dwell at zero lift) the offset is radial: R_a + d.
        let (x, y) = g.pitch_offset_point(0.3, 0.0, 0.0, 0.5);
        assert!((x.hypot(y) - (ra + 0.5)).abs() < 1e-15);
    }

    #[test]
    fn mass_properties_converge_at_second_order() {
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let fine = g.mass_properties(&p, STEEL, 360 * 256).unwrap();
        let mut last: Option<(f64, f64)> = None;
        for n in [360usize, 720, 1440, 2880] {
            let m = g.mass_properties(&p, STEEL, n).unwrap();
            let e = (
                (m.area - fine.area).abs(),
                (m.polar_inertia - fine.polar_inertia).abs(),
            );
            if let Some((ea, ej)) = last {
                assert!(
                    ea / e.0 > 3.5 && ea / e.0 < 4.5,
                    "area ratio {} at {n}",
                    ea / e.0
                );
                assert!(
                    ej / e.1 > 3.5 && ej / e.1 < 4.5,
                    "J ratio {} at {n}",
                    ej / e.1
                );
            }
            last = Some(e);
        }
        // The literal Eq. V.4 converges too, to a slightly different value.
        let a = g
            .mass_properties(&p, STEEL, 3600)
            .unwrap()
            .polar_inertia_eq_v4;
        assert!((a - fine.polar_inertia_eq_v4).abs() < 1e-6 * a);
        assert!((a / fine.polar_inertia - 1.0).abs() < 0.1);
        // Lift adds material: the cam is heavier than its base circle disk.
        let disk = PI * 1.5 * 1.5;
        assert!(fine.area > disk && fine.area < PI * 3.0 * 3.0);
    }

    #[test]
    fn undercut_detection() {
        /// Dense scan of Eq. V.12: (min convex surface radius, min |concave pitch radius|).
        fn scan<const N: usize>(g: &CamGeometry<f64>, p: &CamProgram<f64, N>) -> (f64, f64) {
            let (mut convex, mut concave) = (f64::INFINITY, f64::INFINITY);
            for k in 0..400_000 {
                let f = p.follower(k as f64 * 2.0 * PI / 400_000.0);
                let rho = g.pitch_curvature_radius(f.y, f.dy, f.d2y);
                if rho > 0.0 {
                    convex = convex.min(rho - g.roller_radius);
                } else {
                    concave = concave.min(-rho);
                }
            }
            (convex, concave)
        }
        // The reference cam is not undercut and nowhere concave; the refined search
        // finds the tightest convex spot of a dense scan.
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let u = g.undercut(&p, 720).unwrap();
        let (convex, concave) = scan(&g, &p);
        assert!(!u.undercut);
        assert!(
            (u.min_convex_surface_radius - convex).abs() < 1e-6,
            "{u:?} vs {convex}"
        );
        assert!(u.min_convex_surface_radius <= convex + 1e-12);
        assert_eq!(concave, f64::INFINITY);
        assert_eq!(u.min_concave_pitch_radius, f64::INFINITY);
        let f = p.follower(u.min_convex_at);
        assert!(
            (g.surface_curvature_radius(f.y, f.dy, f.d2y) - u.min_convex_surface_radius).abs()
                < 1e-12
        );
        // A small cam with a steep rise and a big roller is undercut at the nose and
        // concave on the flanks.
        let seg = |kind, start_deg, end_deg, lift| Segment {
            kind,
            start_deg,
            end_deg,
            lift,
        };
        let steep = CamProgram::<f64, 4>::new(&[
            seg(SegmentKind::Rise(MotionLaw::Cycloidal), 0.0, 40.0, 1.5),
            seg(SegmentKind::Dwell, 40.0, 60.0, 0.0),
            seg(SegmentKind::Return(MotionLaw::Cycloidal), 60.0, 100.0, 1.5),
            seg(SegmentKind::Dwell, 100.0, 360.0, 0.0),
        ])
        .unwrap();
        let small = CamGeometry::new(0.5, 0.5, 0.25).unwrap();
        let u = small.undercut(&steep, 720).unwrap();
        let (convex, concave) = scan(&small, &steep);
        assert!(u.undercut && convex < 0.0);
        assert!(
            (u.min_convex_surface_radius - convex).abs() < 1e-6 * (1.0 + convex.abs()),
            "{u:?} vs {convex}"
        );
        assert!(concave.is_finite());
        assert!(
            (u.min_concave_pitch_radius - concave).abs() < 1e-6 * concave,
            "{u:?} vs {concave}"
        );
        // The same profile followed by a knife edge (surface = pitch curve) is not.
        let knife = CamGeometry::new(0.5, 0.0, 0.25).unwrap();
        assert!(!knife.undercut(&steep, 720).unwrap().undercut);
    }

    /// Issue 20, point 9: a 1.5 in cycloidal rise on the reference cam is undercut
    /// however short it is; the revolution's 3600 samples alone missed it below 1°.
    /// Independent check: near the rise's end, where y'' = -4π² h ε / β² at ε of the
    /// segment from it and y' is still small, the pitch radius is about
    /// R² / (R + 4π² h ε / β²), far below the roller once β is a degree or less.
    #[test]
    fn a_short_steep_segment_is_undercut_however_short() {
        let g = CamGeometry::<f64>::reference();
        let seg = |kind, start_deg, end_deg, lift| Segment {
            kind,
            start_deg,
            end_deg,
            lift,
        };
        for width in [5.0, 1.0, 0.5, 0.1, 0.01, 1e-5] {
            let p = CamProgram::<f64, 4>::new(&[
                seg(SegmentKind::Dwell, 0.0, 10.0, 0.0),
                seg(
                    SegmentKind::Rise(MotionLaw::Cycloidal),
                    10.0,
                    10.0 + width,
                    1.5,
                ),
                seg(SegmentKind::Dwell, 10.0 + width, 180.0, 0.0),
                seg(SegmentKind::Return(MotionLaw::Cycloidal), 180.0, 360.0, 1.5),
            ])
            .unwrap();
            let u = g.undercut(&p, 3600).unwrap();
            assert!(u.undercut, "{width} deg: {u:?}");
            let at = u.min_convex_at.to_degrees();
            assert!(
                (10.0 - 1e-6..=10.0 + width + 1e-6).contains(&at),
                "{width} deg at {at}"
            );
            // f32 too (the firmware's precision), where the program is not refused
            // already (1e-5 deg is below f32's angle tolerance).
            if let Ok(p32) = p.cast::<f32>() {
                let u32 = CamGeometry::<f32>::reference()
                    .undercut(&p32, 3600)
                    .unwrap();
                assert!(u32.undercut, "f32 {width} deg: {u32:?}");
            }
        }
    }

    #[test]
    fn straight_line_pressure_angle_closed_form() {
        // Constant dy = h/β over the strokes: the pressure angle peaks where y = 0,
        // at the start of the rise (and the end of the return): atan((h/β)/R_a).
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::with_laws(MotionLaw::StraightLine, MotionLaw::StraightLine);
        let (phi, at) = g.max_pressure_angle(&p, 3600);
        let want = (1.5 / 150f64.to_radians() / 1.875).atan();
        assert!((phi - want).abs() < 1e-9, "{phi} vs {want}");
        let deg = at.to_degrees();
        assert!(
            (deg - 30.0).abs() < 0.2 || !(0.2..=359.8).contains(&deg),
            "at {deg}"
        );
    }

    #[test]
    fn refined_pressure_angle_beats_the_grid() {
        let g = CamGeometry::<f64>::reference();
        let p = CamProgram::<f64>::reference();
        let (coarse, _) = g.max_pressure_angle(&p, 90);
        let (fine, at) = g.max_pressure_angle(&p, 100_000);
        assert!((coarse - fine).abs() < 1e-10, "{coarse} vs {fine}");
        let f = p.follower(at);
        assert_eq!(g.pressure_angle(f.y, f.dy).abs(), fine);
    }

    /// f32 against f64 (micromath's approximate f32 functions are not held to this).
    #[cfg(not(feature = "micromath"))]
    #[test]
    fn single_precision_geometry() {
        let g = CamGeometry::<f64>::reference();
        let fine = g
            .mass_properties(&CamProgram::<f64>::reference(), STEEL, 3600)
            .unwrap();
        let f = CamGeometry::<f32>::reference()
            .mass_properties(&CamProgram::<f32>::reference(), STEEL as f32, 3600)
            .unwrap();
        assert!((f.area as f64 / fine.area - 1.0).abs() < 1e-5);
        assert!((f.polar_inertia as f64 / fine.polar_inertia - 1.0).abs() < 1e-5);
        let want = (1.5 / 150f64.to_radians() / 1.875).atan();
        let (pf, _) = CamGeometry::<f32>::reference().max_pressure_angle(
            &CamProgram::<f32>::with_laws(MotionLaw::StraightLine, MotionLaw::StraightLine),
            3600,
        );
        assert!((pf as f64 - want).abs() < 1e-5);
    }
}
