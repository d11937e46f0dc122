//! A cam program: dwells, rises and returns over one revolution (VI.1, Appendix A.5).
//!
//! The return is the rise law mirrored in time (Appendix A.5: θ in the rise equation
//! replaced by `-(θ - β₂ - c)`): over a return of lift `h` from angle `c` to `c + β₂`,
//! `y = y_low + h s(1 - u)` with `u = (θ - c)/β₂`. It is not point-symmetric in force;
//! for the point-symmetric laws the two readings coincide.

use crate::model::keys::{segment_key, SegmentField};
use crate::{key, Error, MotionLaw, Real, Result};

/// What a program segment does.
///
/// With the `serde` feature on its own: `"dwell"`, `{ rise = "<law>" }` or
/// `{ return = "<law>" }`; inside a [`Segment`] it is split into `kind` and `law`
/// ([`SegmentData`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum SegmentKind {
    /// The follower rests (lift 0).
    Dwell,
    /// The follower rises by the segment's lift with this law (Appendix A.1-A.4).
    Rise(MotionLaw),
    /// The follower returns by the segment's lift with this law mirrored in time (A.5).
    Return(MotionLaw),
}

/// One segment of a cam program, in degrees of cam angle and inches of lift.
///
/// With the `serde` feature it reads and writes as a [`SegmentData`]
/// (`kind`, `law`, `start_deg`, `end_deg`, `lift_in`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        try_from = "SegmentData<T>",
        into = "SegmentData<T>",
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct Segment<T> {
    /// Dwell, rise or return.
    pub kind: SegmentKind,
    /// Cam angle where the segment starts (deg).
    pub start_deg: T,
    /// Cam angle where the segment ends (deg).
    pub end_deg: T,
    /// Follower travel over the segment (in), positive; 0 for a dwell.
    pub lift: T,
}

/// The follower's commanded lift and its cam-angle derivatives at one cam angle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FollowerLift<T> {
    /// Lift above the base circle (in).
    pub y: T,
    /// dy/dθ (in/rad).
    pub dy: T,
    /// d²y/dθ² (in/rad²).
    pub d2y: T,
    /// d³y/dθ³ (in/rad³).
    pub d3y: T,
}

/// A segment prepared for fast evaluation.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Prepared<T> {
    kind: SegmentKind,
    /// Bounds in radians; consecutive segments share their bound exactly.
    start: T,
    end: T,
    /// 1/β (1/rad).
    inv_beta: T,
    /// Lift at the segment's lower end (the level before a rise, after a return).
    base: T,
    /// The lift h (in) and h/β, h/β², h/β³.
    h: T,
    h1: T,
    h2: T,
    h3: T,
}

impl<T: Real> Prepared<T> {
    /// The law's argument `u` in `[0, 1]`, with a `u` within an angle's rounding of a
    /// bound taken as the bound. A cam angle that should sit on a segment's bound (a
    /// sample at a segment start: `2πk + start`, wrapped) lands a few ulps beside it,
    /// and `1/β` times `β` is not exactly 1; a law with a high-order zero there (4-5-6-7:
    /// `v ~ (1 - u)^3`) then gives `dy ~ 1e-43` instead of 0, and a return's largest
    /// output torque came out as `-2e-44 lb in`. The rounding bound is 16 ulps of 2π,
    /// the grid's own "same angle" (run/grid.rs), and at most a millionth of the segment
    /// (a 0.01° segment in `f32` would otherwise lose 7 % of it at each end).
    #[inline]
    fn snap(&self, u: T) -> T {
        let tol = (T::EPSILON * T::from_f64(16.0) * T::TWO * T::PI * self.inv_beta)
            .min(T::from_f64(1e-6));
        if u <= tol {
            T::ZERO
        } else if u >= T::ONE - tol {
            T::ONE
        } else {
            u
        }
    }
}

/// A cam program over 360 degrees with at most `N` segments (VI.1's is D-R-D-R).
///
/// With the `serde` feature it reads and writes as a [`ProgramData`] (a list `segment`
/// of [`SegmentData`]) and is validated by [`CamProgram::new`] as it is read: a program
/// that deserializes is valid, and the error names the key (`program.segment[2].end_deg`).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        try_from = "ProgramData<T, N>",
        into = "ProgramData<T, N>",
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct CamProgram<T, const N: usize = 8> {
    segs: heapless::Vec<Segment<T>, N>,
    pre: heapless::Vec<Prepared<T>, N>,
    max_lift: T,
}

/// A segment's kind without its law, as scene files name it (`kind = "rise"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum SegmentType {
    /// The follower rests.
    Dwell,
    /// The follower rises.
    Rise,
    /// The follower returns.
    Return,
}

/// One segment as plain data, the form scene files use: `kind`, a `law` for a rise or
/// return (none for a dwell), the angles and the lift (0 or absent for a dwell).
/// [`SegmentData::to_segment`] checks that kind and law fit; [`CamProgram::new`] the rest.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        deny_unknown_fields,
        rename = "Segment",
        expecting = "a segment: a table of kind, law, start_deg, end_deg, lift_in",
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct SegmentData<T> {
    /// `"dwell"`, `"rise"` or `"return"`.
    pub kind: SegmentType,
    /// The motion law of a rise or return (names as in `camsim laws`); none for a dwell.
    pub law: Option<MotionLaw>,
    /// Cam angle where the segment starts (deg).
    pub start_deg: T,
    /// Cam angle where the segment ends (deg).
    pub end_deg: T,
    /// Follower travel (in); 0 for a dwell, which may leave it out.
    #[cfg_attr(feature = "serde", serde(rename = "lift_in", default))]
    pub lift: T,
}

/// A program as plain data: its segments in order (`[[program.segment]]` in a scene).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        deny_unknown_fields,
        rename = "CamProgram",
        expecting = "a program: a table with a list `segment` of segments",
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct ProgramData<T, const N: usize = 8> {
    /// The segments.
    pub segment: heapless::Vec<SegmentData<T>, N>,
}

impl<T: Real> SegmentData<T> {
    /// The segment of index `i` in its program (the index names the key in errors):
    /// a rise or return needs a law, a dwell takes none.
    pub fn to_segment(&self, i: usize) -> Result<Segment<T>> {
        let kind = match (self.kind, self.law) {
            (SegmentType::Dwell, None) => SegmentKind::Dwell,
            (SegmentType::Rise, Some(l)) => SegmentKind::Rise(l),
            (SegmentType::Return, Some(l)) => SegmentKind::Return(l),
            (SegmentType::Dwell, Some(_)) => {
                return Err(Error::Inconsistent {
                    field: segment_key(SegmentField::Law, i),
                    rule: "a dwell takes no motion law",
                })
            }
            (_, None) => {
                return Err(Error::Inconsistent {
                    field: segment_key(SegmentField::Law, i),
                    rule: "a rise or return needs a motion law (names as in `camsim laws`)",
                })
            }
        };
        Ok(Segment {
            kind,
            start_deg: self.start_deg,
            end_deg: self.end_deg,
            lift: self.lift,
        })
    }
}

impl<T: Real> Segment<T> {
    /// The same segment in precision `U`, angles and lift converted with [`Real::cast`]
    /// (not checked: [`CamProgram::new`] checks segments in their program).
    pub fn cast<U: Real>(&self) -> Segment<U> {
        Segment {
            kind: self.kind,
            start_deg: self.start_deg.cast(),
            end_deg: self.end_deg.cast(),
            lift: self.lift.cast(),
        }
    }
}

impl<T: Real> From<Segment<T>> for SegmentData<T> {
    fn from(s: Segment<T>) -> Self {
        let (kind, law) = match s.kind {
            SegmentKind::Dwell => (SegmentType::Dwell, None),
            SegmentKind::Rise(l) => (SegmentType::Rise, Some(l)),
            SegmentKind::Return(l) => (SegmentType::Return, Some(l)),
        };
        SegmentData {
            kind,
            law,
            start_deg: s.start_deg,
            end_deg: s.end_deg,
            lift: s.lift,
        }
    }
}

impl<T: Real> TryFrom<SegmentData<T>> for Segment<T> {
    type Error = Error;
    /// A segment on its own (errors name `program.segment[..]`).
    fn try_from(d: SegmentData<T>) -> Result<Self> {
        d.to_segment(usize::MAX)
    }
}

impl<T: Real, const N: usize> From<CamProgram<T, N>> for ProgramData<T, N> {
    fn from(p: CamProgram<T, N>) -> Self {
        let mut segment = heapless::Vec::new();
        for &s in &p.segs {
            // Same capacity N: never full.
            let _ = segment.push(SegmentData::from(s));
        }
        ProgramData { segment }
    }
}

impl<T: Real, const N: usize> TryFrom<ProgramData<T, N>> for CamProgram<T, N> {
    type Error = Error;
    /// Checks kind and law of every segment, then the program ([`CamProgram::new`]).
    fn try_from(d: ProgramData<T, N>) -> Result<Self> {
        let mut segs: heapless::Vec<Segment<T>, N> = heapless::Vec::new();
        for (i, s) in d.segment.iter().enumerate() {
            if segs.push(s.to_segment(i)?).is_err() {
                return Err(Error::Capacity {
                    what: "cam program segments",
                    capacity: N,
                });
            }
        }
        Self::new(&segs)
    }
}

fn invalid<T: Real>(field: &'static str, rule: &'static str, value: T) -> Error {
    Error::InvalidParameter {
        field,
        rule,
        value: value.to_f64(),
    }
}

impl<T: Real, const N: usize> CamProgram<T, N> {
    /// Compile-time check that the reference program fits in `N`.
    const FITS_REFERENCE: () = assert!(
        N >= 4,
        "CamProgram::reference needs a capacity of at least 4"
    );

    /// A validated program: contiguous from 0 to 360 deg, positive lengths, positive
    /// finite lifts (0 for dwells), the follower never below the base circle and back
    /// at 0 after the revolution.
    ///
    /// Angles must meet within `max(1e-6, 2880 ε)` deg (ε the precision's epsilon, so
    /// 1e-6 deg in `f64`, 3.4e-4 deg in `f32`); the levels must close within
    /// `64 ε` times the sum of the lifts.
    pub fn new(segments: &[Segment<T>]) -> Result<Self> {
        if segments.is_empty() {
            return Err(invalid(
                key::PROGRAM_SEGMENT,
                "must hold at least one segment",
                T::ZERO,
            ));
        }
        if segments.len() > N {
            return Err(Error::Capacity {
                what: "cam program segments",
                capacity: N,
            });
        }
        let full = T::from_i32(360);
        let tol_deg = T::from_f64(1e-6).max(full * T::from_i32(8) * T::EPSILON);
        let lift_sum = Self::check_angles_and_lifts(segments, full, tol_deg)?;
        let tol_lift = T::from_i32(64) * T::EPSILON * lift_sum;
        let (program, level) = Self::prepare(segments, tol_lift)?;
        if level.abs() > tol_lift {
            return Err(invalid(
                key::PROGRAM_SEGMENT,
                "net displacement over the revolution must be 0 (the returns must undo the rises)",
                level,
            ));
        }
        Ok(program)
    }

    /// The segments' angles (finite, from 0 to 360 deg, contiguous within `tol_deg`,
    /// each longer than it) and lifts (0 for a dwell, positive and finite for a rise or
    /// return); returns the sum of the lifts.
    fn check_angles_and_lifts(segments: &[Segment<T>], full: T, tol_deg: T) -> Result<T> {
        for (i, s) in segments.iter().enumerate() {
            if !s.start_deg.is_finite() {
                return Err(invalid(
                    segment_key(SegmentField::StartDeg, i),
                    "must be finite",
                    s.start_deg,
                ));
            }
            if !s.end_deg.is_finite() {
                return Err(invalid(
                    segment_key(SegmentField::EndDeg, i),
                    "must be finite",
                    s.end_deg,
                ));
            }
        }

        // Angles and lifts, one segment at a time.
        let mut lift_sum = T::ZERO;
        for (i, s) in segments.iter().enumerate() {
            if i == 0 && s.start_deg.abs() > tol_deg {
                return Err(invalid(
                    segment_key(SegmentField::StartDeg, 0),
                    "must be 0 (the program starts at 0 deg)",
                    s.start_deg,
                ));
            }
            // Both ends are finite here, so `<=` is the negation of `>`.
            if s.end_deg - s.start_deg <= tol_deg {
                return Err(invalid(
                    segment_key(SegmentField::EndDeg, i),
                    "must exceed the segment's start_deg by more than the angle tolerance (1e-6 deg; 3.4e-4 deg in f32)",
                    s.end_deg,
                ));
            }
            if let Some(next) = segments.get(i + 1) {
                if (s.end_deg - next.start_deg).abs() > tol_deg {
                    return Err(invalid(
                        segment_key(SegmentField::EndDeg, i),
                        "must equal the next segment's start_deg",
                        s.end_deg,
                    ));
                }
            } else if (s.end_deg - full).abs() > tol_deg {
                return Err(invalid(
                    segment_key(SegmentField::EndDeg, i),
                    "must be 360 (the program covers one revolution)",
                    s.end_deg,
                ));
            }
            match s.kind {
                SegmentKind::Dwell => {
                    if s.lift != T::ZERO {
                        return Err(invalid(
                            segment_key(SegmentField::LiftIn, i),
                            "must be 0 for a dwell",
                            s.lift,
                        ));
                    }
                }
                SegmentKind::Rise(_) | SegmentKind::Return(_) => {
                    if !(s.lift.is_finite() && s.lift > T::ZERO) {
                        return Err(invalid(
                            segment_key(SegmentField::LiftIn, i),
                            "must be positive and finite for a rise or return",
                            s.lift,
                        ));
                    }
                    lift_sum += s.lift;
                }
            }
        }
        Ok(lift_sum)
    }

    /// The program of checked `segments`, their levels and prepared forms (the
    /// follower never below the base circle by more than `tol_lift`), and the level
    /// after the revolution (for [`Self::new`] to check that it closes).
    fn prepare(segments: &[Segment<T>], tol_lift: T) -> Result<(Self, T)> {
        let two_pi = T::TWO * T::PI;
        let last = segments.len().saturating_sub(1);
        // Levels and the prepared segments.
        let mut segs = heapless::Vec::new();
        let mut pre = heapless::Vec::new();
        let mut level = T::ZERO;
        let mut max_lift = T::ZERO;
        let mut start = T::ZERO;
        for (i, s) in segments.iter().enumerate() {
            let end = if i == last {
                two_pi
            } else {
                s.end_deg.to_radians()
            };
            let beta = end - start;
            let inv_beta = T::ONE / beta;
            if !(beta > T::ZERO && inv_beta.is_finite()) {
                return Err(invalid(
                    segment_key(SegmentField::EndDeg, i),
                    "must exceed the segment's start_deg by a representable angle",
                    s.end_deg,
                ));
            }
            let (base, after) = match s.kind {
                SegmentKind::Dwell => (level, level),
                SegmentKind::Rise(_) => (level, level + s.lift),
                SegmentKind::Return(_) => {
                    let mut low = level - s.lift;
                    if low < -tol_lift {
                        return Err(invalid(
                            segment_key(SegmentField::LiftIn, i),
                            "must not exceed the follower level before the return (the follower would go below the base circle)",
                            s.lift,
                        ));
                    }
                    if low.abs() <= tol_lift {
                        low = T::ZERO;
                    }
                    (low, level)
                }
            };
            let h = s.lift;
            let p = Prepared {
                kind: s.kind,
                start,
                end,
                inv_beta,
                base,
                h,
                h1: h * inv_beta,
                h2: h * inv_beta * inv_beta,
                h3: h * inv_beta * inv_beta * inv_beta,
            };
            level = match s.kind {
                SegmentKind::Return(_) => base,
                _ => after,
            };
            max_lift = max_lift.max(level);
            if segs.push(*s).is_err() || pre.push(p).is_err() {
                return Err(Error::Capacity {
                    what: "cam program segments",
                    capacity: N,
                });
            }
            start = end;
        }
        let program = CamProgram {
            segs,
            pre,
            max_lift,
        };
        Ok((program, level))
    }

    /// The reference program of VI.1: dwell 0-30 deg, modified-trapezoidal rise 30-180,
    /// dwell 180-210, 4-5-6-7 return 210-360, lift 1.5 in.
    pub fn reference() -> Self {
        Self::with_laws(MotionLaw::ModifiedTrapezoidal, MotionLaw::Poly4567)
    }

    /// The reference timing of VI.1 (lift 1.5 in) with other rise and return laws.
    pub fn with_laws(rise: MotionLaw, ret: MotionLaw) -> Self {
        #[allow(clippy::let_unit_value)]
        let () = Self::FITS_REFERENCE;
        let d = |k: SegmentKind, a: i32, b: i32, lift: f64| Segment {
            kind: k,
            start_deg: T::from_i32(a),
            end_deg: T::from_i32(b),
            lift: T::from_f64(lift),
        };
        let segs = [
            d(SegmentKind::Dwell, 0, 30, 0.0),
            d(SegmentKind::Rise(rise), 30, 180, 1.5),
            d(SegmentKind::Dwell, 180, 210, 0.0),
            d(SegmentKind::Return(ret), 210, 360, 1.5),
        ];
        // Always valid and within capacity (checked at compile time above); the empty
        // fallback (follower at rest on the base circle) is never taken.
        Self::new(&segs).unwrap_or_else(|_| CamProgram {
            segs: heapless::Vec::new(),
            pre: heapless::Vec::new(),
            max_lift: T::ZERO,
        })
    }

    /// The commanded lift and its derivatives at cam angle `theta` (rad, any real,
    /// wrapped into `[0, 2π)`): `y = h s(u)` on a rise, `y = h s(1-u)` above the lower
    /// level on a return (Appendix A.5), constant on a dwell. At a bound the segment it
    /// starts is used (matters only where a law's slope or acceleration jumps).
    #[inline]
    pub fn follower(&self, theta: T) -> FollowerLift<T> {
        let th = wrap_angle(theta);
        let Some(p) = self.pre.iter().find(|p| th < p.end).or(self.pre.last()) else {
            return FollowerLift::default();
        };
        match p.kind {
            SegmentKind::Dwell => FollowerLift {
                y: p.base,
                dy: T::ZERO,
                d2y: T::ZERO,
                d3y: T::ZERO,
            },
            SegmentKind::Rise(law) => {
                let v = law.eval(p.snap((th - p.start) * p.inv_beta));
                FollowerLift {
                    y: p.base + p.h * v.s,
                    dy: p.h1 * v.v,
                    d2y: p.h2 * v.a,
                    d3y: p.h3 * v.j,
                }
            }
            SegmentKind::Return(law) => {
                let v = law.eval(p.snap((p.end - th) * p.inv_beta));
                FollowerLift {
                    y: p.base + p.h * v.s,
                    // 0 - x, not -x: a slope of zero is +0 (a -0 printed as `-0.0`).
                    dy: T::ZERO - p.h1 * v.v,
                    d2y: p.h2 * v.a,
                    d3y: T::ZERO - p.h3 * v.j,
                }
            }
        }
    }

    /// Index of the segment containing `theta` (rad, wrapped into `[0, 2π)`); a bound
    /// between two segments belongs to the one it starts.
    pub fn segment_at(&self, theta: T) -> usize {
        let th = wrap_angle(theta);
        self.pre
            .iter()
            .position(|p| th < p.end)
            .unwrap_or(self.pre.len().saturating_sub(1))
    }

    /// The same program in precision `U`: every segment's angles and lift converted
    /// with [`Real::cast`], then rebuilt and checked by [`CamProgram::new`] in `U` (whose
    /// tolerances depend on the precision: a program whose angles meet within `f32`'s
    /// tolerance but not `f64`'s is refused when widened, with the segment's key).
    pub fn cast<U: Real>(&self) -> Result<CamProgram<U, N>> {
        let mut segs: heapless::Vec<Segment<U>, N> = heapless::Vec::new();
        for s in &self.segs {
            // Same capacity N as `self.segs`: never full.
            let _ = segs.push(s.cast());
        }
        CamProgram::new(&segs)
    }

    /// The validated segments, in order.
    pub fn segments(&self) -> &[Segment<T>] {
        &self.segs
    }

    /// The highest follower level the program reaches (in).
    pub fn max_lift(&self) -> T {
        self.max_lift
    }
}

/// `theta` wrapped into `[0, 2π)` (2π itself maps to 0; NaN stays NaN).
#[inline]
pub(crate) fn wrap_angle<T: Real>(theta: T) -> T {
    let two_pi = T::TWO * T::PI;
    if theta >= T::ZERO && theta < two_pi {
        return theta;
    }
    let th = theta - two_pi * (theta / two_pi).floor();
    if th >= two_pi {
        th - two_pi
    } else if th < T::ZERO {
        T::ZERO
    } else {
        th
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    fn seg(kind: SegmentKind, a: f64, b: f64, lift: f64) -> Segment<f64> {
        Segment {
            kind,
            start_deg: a,
            end_deg: b,
            lift,
        }
    }

    fn field_of(e: Error) -> &'static str {
        match e {
            Error::InvalidParameter { field, .. } => field,
            _ => "",
        }
    }

    #[test]
    fn cast_rebuilds_the_program_under_the_new_precision_s_tolerances() {
        // Angles that meet within f32's tolerance (3.4e-4 deg) but not f64's (1e-6 deg).
        let segs: [Segment<f32>; 3] = [
            Segment {
                kind: SegmentKind::Dwell,
                start_deg: 0.0,
                end_deg: 90.0,
                lift: 0.0,
            },
            Segment {
                kind: SegmentKind::Rise(MotionLaw::Cycloidal),
                start_deg: 90.0001,
                end_deg: 180.0,
                lift: 1.0,
            },
            Segment {
                kind: SegmentKind::Return(MotionLaw::Cycloidal),
                start_deg: 180.0,
                end_deg: 360.0,
                lift: 1.0,
            },
        ];
        let p = CamProgram::<f32>::new(&segs).unwrap();
        let e = p.cast::<f64>().unwrap_err();
        assert_eq!(field_of(e), "program.segment[0].end_deg");
        // Narrowing the reference keeps every segment, converted number by number.
        let r = CamProgram::<f64>::reference();
        let n = r.cast::<f32>().unwrap();
        assert_eq!(n.segments().len(), 4);
        for (a, b) in n.segments().iter().zip(r.segments()) {
            assert_eq!(a.kind, b.kind);
            assert_eq!(a.end_deg.to_bits(), (b.end_deg as f32).to_bits());
        }
        assert_eq!(n.max_lift(), 1.5f32);
    }

    #[test]
    fn a_bound_reached_by_a_rounded_angle_has_the_bound_s_slope() {
        // The return's start (210 deg) as a run's later revolutions reach it: 2πk +
        // 210°, wrapped. The 4-5-6-7 law's v(1) = 0 exactly, so dy is exactly 0 (it was
        // -1e-43 a few ulps into the return), and the rise's start likewise.
        let p = CamProgram::<f64, 8>::reference();
        for k in 0..17 {
            for start_deg in [30.0_f64, 210.0] {
                let th = (360.0 * f64::from(k) + start_deg).to_radians();
                let l = p.follower(th);
                assert_eq!(l.dy, 0.0, "revolution {k}, {start_deg} deg");
                assert!(l.dy.is_sign_positive(), "revolution {k}: -0");
            }
        }
        // Inside the segment the law is untouched: one degree in, the slope is the
        // law's own (4-5-6-7: v(u) = 140 u^3 (1-u)^3, h/β = 1.5/(150°)).
        let u = 1.0 / 150.0;
        let l = p.follower(211.0_f64.to_radians());
        let v = 140.0 * (u * (1.0 - u)).powi(3);
        let want = -1.5 / 150.0_f64.to_radians() * v;
        assert!(
            (l.dy - want).abs() <= 1e-12 * want.abs(),
            "{} vs {want}",
            l.dy
        );
    }

    #[test]
    fn reference_program_levels() {
        let p = CamProgram::<f64>::reference();
        assert_eq!(p.segments().len(), 4);
        assert_eq!(p.max_lift(), 1.5);
        let at = |deg: f64| p.follower(deg.to_radians());
        assert_eq!(at(0.0).y, 0.0);
        assert_eq!(
            at(15.0),
            FollowerLift {
                y: 0.0,
                dy: 0.0,
                d2y: 0.0,
                d3y: 0.0
            }
        );
        assert!((at(180.0).y - 1.5).abs() < 1e-12);
        assert!((at(195.0).y - 1.5).abs() < 1e-15);
        // Midpoint of the modified-trapezoidal rise: s = 1/2, v = cv = 2.
        let mid = at(105.0);
        let beta = 150f64.to_radians();
        assert!((mid.y - 0.75).abs() < 1e-12);
        assert!((mid.dy - 1.5 * 2.0 / beta).abs() < 1e-9);
        // Midpoint of the 4-5-6-7 return: s = 1/2, v = -140/64 h/β.
        let r = at(285.0);
        assert!((r.y - 0.75).abs() < 1e-12);
        assert!((r.dy + 1.5 * 140.0 / 64.0 / beta).abs() < 1e-9);
        assert_eq!(p.segment_at(0.0), 0);
        assert_eq!(p.segment_at(100f64.to_radians()), 1);
        assert_eq!(p.segment_at(200f64.to_radians()), 2);
        assert_eq!(p.segment_at(359f64.to_radians()), 3);
        assert_eq!(p.segment_at(2.0 * PI), 0);
    }

    #[test]
    fn wrap_around_is_exact() {
        let p = CamProgram::<f64>::with_laws(MotionLaw::Cycloidal, MotionLaw::DoubleHarmonic);
        assert_eq!(p.follower(2.0 * PI), p.follower(0.0));
        assert_eq!(p.follower(-2.0 * PI), p.follower(0.0));
        for k in -5..5 {
            let th = 1.234 + 2.0 * PI * k as f64;
            let (a, b) = (p.follower(th), p.follower(1.234));
            assert!(
                (a.y - b.y).abs() < 1e-12 && (a.dy - b.dy).abs() < 1e-12,
                "k = {k}"
            );
        }
        // Just below a full turn the follower is (continuously) back on the base circle.
        assert!(p.follower(2.0 * PI - 1e-12).y.abs() < 1e-12);
        let q = CamProgram::<f32>::reference();
        assert_eq!(q.follower(2.0 * core::f32::consts::PI), q.follower(0.0));
        // Bad angles give a value, not a panic.
        let _ = p.follower(f64::NAN);
        let _ = p.follower(f64::INFINITY);
        let _ = p.segment_at(f64::NEG_INFINITY);
    }

    #[test]
    fn return_is_the_rise_mirrored_in_time() {
        for law in MotionLaw::ALL {
            let p = CamProgram::<f64>::with_laws(law, law);
            for k in 0..150 {
                let x = k as f64 + 0.5;
                let ret = p.follower((210.0 + x).to_radians());
                let rise = p.follower((180.0 - x).to_radians());
                assert!((ret.y - rise.y).abs() < 1e-12, "{law:?} y at {x}");
                assert!((ret.dy + rise.dy).abs() < 1e-9, "{law:?} dy at {x}");
                // Away from the jumps of the parabolic and cubic-1 laws at mid-stroke.
                if (x - 75.0).abs() > 1e-9 {
                    assert!(
                        (ret.d2y - rise.d2y).abs() < 1e-8 * (1.0 + rise.d2y.abs()),
                        "{law:?} d2y at {x}"
                    );
                    assert!(
                        (ret.d3y + rise.d3y).abs() < 1e-7 * (1.0 + rise.d3y.abs()),
                        "{law:?} d3y at {x}"
                    );
                }
            }
        }
        // For the asymmetric double harmonic, mirroring in time is not point symmetry:
        // the return starts gently (as the rise starts) and ends hard.
        let p = CamProgram::<f64>::with_laws(MotionLaw::DoubleHarmonic, MotionLaw::DoubleHarmonic);
        let beta = 150f64.to_radians();
        let r_start = p.follower(210.0f64.to_radians() + 1e-12);
        let r_end = p.follower(360.0f64.to_radians() - 1e-12);
        assert!(
            (r_start.d2y - 1.5 * (-PI * PI) / (beta * beta)).abs() < 1e-6,
            "{}",
            r_start.d2y
        );
        assert!(r_end.d2y.abs() < 1e-6, "{}", r_end.d2y);
    }

    #[test]
    fn derivatives_match_differences_of_the_lift() {
        let p = CamProgram::<f64>::reference();
        let h = 1e-5;
        for k in 0..720 {
            let th = (k as f64 + 0.3) * PI / 360.0;
            let (m, c, q) = (p.follower(th - h), p.follower(th), p.follower(th + h));
            if p.segment_at(th - h) != p.segment_at(th + h) {
                continue;
            }
            assert!(((q.y - m.y) / (2.0 * h) - c.dy).abs() < 1e-6, "dy at {th}");
            assert!(
                ((q.dy - m.dy) / (2.0 * h) - c.d2y).abs() < 1e-5,
                "d2y at {th}"
            );
            assert!(
                ((q.d2y - m.d2y) / (2.0 * h) - c.d3y).abs() < 1e-4,
                "d3y at {th}"
            );
        }
    }

    #[test]
    fn continuity_across_segments() {
        // Level and slope are continuous at every segment bound for every law pair.
        for rise in MotionLaw::ALL {
            for ret in MotionLaw::ALL {
                let p = CamProgram::<f64>::with_laws(rise, ret);
                for deg in [30.0f64, 180.0, 210.0, 360.0] {
                    let th = deg.to_radians();
                    let (a, b) = (p.follower(th - 1e-10), p.follower(th + 1e-10));
                    assert!((a.y - b.y).abs() < 1e-9, "{rise:?}/{ret:?} y at {deg}");
                    if rise != MotionLaw::StraightLine && ret != MotionLaw::StraightLine {
                        assert!((a.dy - b.dy).abs() < 1e-8, "{rise:?}/{ret:?} dy at {deg}");
                    }
                }
            }
        }
    }

    #[test]
    fn validation_names_the_field() {
        let ok = [
            seg(SegmentKind::Rise(MotionLaw::Cycloidal), 0.0, 90.0, 1.0),
            seg(SegmentKind::Dwell, 90.0, 180.0, 0.0),
            seg(SegmentKind::Return(MotionLaw::Cycloidal), 180.0, 360.0, 1.0),
        ];
        assert!(CamProgram::<f64, 3>::new(&ok).is_ok());
        assert_eq!(
            CamProgram::<f64, 2>::new(&ok).err(),
            Some(Error::Capacity {
                what: "cam program segments",
                capacity: 2
            })
        );
        let mut gap = ok;
        gap[1].end_deg = 170.0;
        let e = CamProgram::<f64>::new(&gap).unwrap_err();
        assert_eq!(field_of(e), "program.segment[1].end_deg");
        assert!(matches!(
            e,
            Error::InvalidParameter {
                rule: "must equal the next segment's start_deg",
                ..
            }
        ));

        let mut late = ok;
        late[0].start_deg = 1.0;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&late).unwrap_err()),
            "program.segment[0].start_deg"
        );
        let mut short = ok;
        short[2].end_deg = 359.0;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&short).unwrap_err()),
            "program.segment[2].end_deg"
        );
        let mut back = ok;
        back[1].end_deg = 90.0;
        back[2].start_deg = 90.0;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&back).unwrap_err()),
            "program.segment[1].end_deg"
        );
        let mut dwell_lift = ok;
        dwell_lift[1].lift = 0.1;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&dwell_lift).unwrap_err()),
            "program.segment[1].lift_in"
        );
        let mut neg = ok;
        neg[0].lift = -1.0;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&neg).unwrap_err()),
            "program.segment[0].lift_in"
        );
        let mut nan = ok;
        nan[2].lift = f64::NAN;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&nan).unwrap_err()),
            "program.segment[2].lift_in"
        );
        let mut open = ok;
        open[2].lift = 0.5;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&open).unwrap_err()),
            "program.segment"
        );
        let below = [
            seg(SegmentKind::Return(MotionLaw::Cycloidal), 0.0, 90.0, 1.0),
            seg(SegmentKind::Rise(MotionLaw::Cycloidal), 90.0, 360.0, 1.0),
        ];
        assert_eq!(
            field_of(CamProgram::<f64>::new(&below).unwrap_err()),
            "program.segment[0].lift_in"
        );
        assert_eq!(
            field_of(CamProgram::<f64>::new(&[]).unwrap_err()),
            "program.segment"
        );
        let mut inf = ok;
        inf[1].start_deg = f64::INFINITY;
        assert_eq!(
            field_of(CamProgram::<f64>::new(&inf).unwrap_err()),
            "program.segment[1].start_deg"
        );
    }

    #[test]
    fn levels_close_within_rounding() {
        // 0.1 + 0.2 - 0.3 is not 0 in binary; it closes within the tolerance.
        let s = [
            seg(SegmentKind::Rise(MotionLaw::Poly345), 0.0, 60.0, 0.1),
            seg(SegmentKind::Rise(MotionLaw::Poly345), 60.0, 120.0, 0.2),
            seg(SegmentKind::Return(MotionLaw::Poly345), 120.0, 360.0, 0.3),
        ];
        let p = CamProgram::<f64>::new(&s).unwrap();
        assert!((p.max_lift() - 0.3).abs() < 1e-15);
        assert_eq!(p.follower(0.0).y, 0.0);
        assert!(p.follower(2.0 * PI - 1e-9).y >= 0.0);
        // A dwell-only program is a plain base circle.
        let c = CamProgram::<f64, 1>::new(&[seg(SegmentKind::Dwell, 0.0, 360.0, 0.0)]).unwrap();
        assert_eq!(c.follower(1.0), FollowerLift::default());
    }

    /// f32 against f64 (micromath's approximate f32 functions are not held to this).
    #[cfg(not(feature = "micromath"))]
    #[test]
    fn single_precision_reference() {
        let (p, q) = (
            CamProgram::<f64>::reference(),
            CamProgram::<f32>::reference(),
        );
        for k in 0..360 {
            let th = (k as f64 + 0.5).to_radians();
            let (a, b) = (p.follower(th), q.follower(th as f32));
            assert!(
                (a.y - b.y as f64).abs() < 2e-6,
                "y at {k}: {} vs {}",
                a.y,
                b.y
            );
            assert!((a.dy - b.dy as f64).abs() < 1e-5, "dy at {k}");
            assert!((a.d2y - b.d2y as f64).abs() < 1e-4, "d2y at {k}");
        }
    }
}
