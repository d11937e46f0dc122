//! The eleven-degree-of-freedom cam-follower model (Eqs. IV.1-IV.3).
//!
//! Degrees of freedom: motor, coupling and cam rotation (θ_m, θ_cp, θ_c); cam
//! vertical and horizontal (y1, x1); roller vertical and horizontal (y2, x2);
//! cantilever portion of the follower vertical and horizontal (y3, x3); follower
//! (y4); load (y5). A [`Scene`] fixes at compile time which of them a model keeps (the
//! ideal drives of [`DriveLaw`] remove rotational DOFs, and the horizontal motion can be
//! dropped) and so the state layout and its length `N` (see [`Scene`] and [`crate::Layout`]).

use core::marker::PhantomData;

use crate::{
    coulomb_friction, damped_contact_force, BearingLevers, Design, DriveKind, Error, FollowerLift,
    LiftProfile, ModelLimit, OdeSystem, Real, Result, Scene, StateMut, StateRef, StateVar,
    TheoreticalLift, TransDof, RELATIVE_TO_LIFT, TRANS_DOFS,
};

/// The bounds of what the model represents (docs/MODEL.md §3.20), from a design: a
/// simulation whose state crosses one ends with [`Error::OutOfModel`]
/// ([`CamModel::check_validity`], called on every accepted state by [`crate::simulate`]).
///
/// Each bound follows from an assumption of the model, not from a fit: the Hertz line
/// contact holds for a penetration small against the radii; the linear supports and the
/// contact geometry (evaluated at the undeflected positions) for deflections small
/// against the roller; the cantilever and the rod only while they have a length; linear
/// torsion only for small twists; the program only for a cam that turns forward.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ValidityBounds<T> {
    /// Largest contact penetration y + y1 - y2, in: min(r_r, R_b) / 100 (the contact's
    /// half-width, about √(δ R), then stays near a tenth of the radius, Hertz's limit).
    pub penetration: T,
    /// Largest elastic deflection, in: r_r / 10 (cam shaft y1 and x1, roller bearing
    /// y2 - y3 and x2 - x3, cantilever bending x3, cantilever compression y4 - y3 and rod
    /// stretch y5 - y4).
    pub deflection: T,
    /// Shortest cantilever e2 - y3 and follower e1 + y3, in: r_r (the roller, of radius
    /// r_r, at the cantilever's end would reach the slide bearing).
    pub length: T,
    /// Largest shaft twist θ_cp - θ_c and θ_m - θ_cp, rad: 0.1 (5.7°, linear torsion).
    pub twist: T,
}

impl<T: Real> ValidityBounds<T> {
    /// The bounds for `design` (docs/MODEL.md §3.20).
    pub fn of(design: &Design<T>) -> Self {
        let r_r = design.geometry.roller_radius;
        let r_min = r_r.min(design.geometry.base_radius);
        ValidityBounds {
            penetration: r_min * T::from_f64(0.01),
            deflection: r_r * T::from_f64(0.1),
            length: r_r,
            twist: T::from_f64(0.1),
        }
    }
}

/// The name of a state quantity in error messages (`"load y5 velocity"`).
pub fn state_quantity_name(var: StateVar) -> &'static str {
    let position = |d: TransDof| match d {
        TransDof::CamY => "cam y1 displacement",
        TransDof::CamX => "cam x1 displacement",
        TransDof::RollerY => "roller y2 displacement",
        TransDof::RollerX => "roller x2 displacement",
        TransDof::CantileverY => "cantilever y3 displacement",
        TransDof::CantileverX => "cantilever x3 displacement",
        TransDof::Follower => "follower y4 displacement",
        TransDof::Load => "load y5 displacement",
    };
    let velocity = |d: TransDof| match d {
        TransDof::CamY => "cam y1 velocity",
        TransDof::CamX => "cam x1 velocity",
        TransDof::RollerY => "roller y2 velocity",
        TransDof::RollerX => "roller x2 velocity",
        TransDof::CantileverY => "cantilever y3 velocity",
        TransDof::CantileverX => "cantilever x3 velocity",
        TransDof::Follower => "follower y4 velocity",
        TransDof::Load => "load y5 velocity",
    };
    match var {
        StateVar::CamAngle => "cam angle",
        StateVar::CouplingCamTwist => "coupling-cam shaft twist",
        StateVar::MotorCouplingTwist => "motor-coupling shaft twist",
        StateVar::CamSpeed => "cam speed",
        StateVar::CouplingSpeed => "coupling speed",
        StateVar::MotorSpeed => "motor speed",
        StateVar::Position(d) => position(d),
        StateVar::Velocity(d) => velocity(d),
    }
}

/// [`CamModel::check_validity`]'s deflections, in its order.
const DEFLECTION_NAMES: [&str; 7] = [
    "cam-shaft deflection y1",
    "cam-shaft deflection x1",
    "roller-bearing deflection y2 - y3",
    "roller-bearing deflection x2 - x3",
    "cantilever bending x3",
    "cantilever compression y4 - y3",
    "follower-rod stretch y5 - y4",
];

/// [`CamModel::check_validity`]'s shaft twists, in its order.
const TWIST_NAMES: [&str; 2] = ["coupling-cam shaft twist", "motor-coupling shaft twist"];

/// Every quantity of the model at one instant (what an observer receives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ModelPoint<T> {
    /// Time, s.
    pub t: T,
    /// Cam angle θ_c, rad (unwrapped: grows by 2π per revolution).
    pub theta_c: T,
    /// Coupling angle θ_cp, rad.
    pub theta_cp: T,
    /// Motor angle θ_m, rad.
    pub theta_m: T,
    /// θ̇_c, rad/s.
    pub omega_c: T,
    /// θ̇_cp, rad/s.
    pub omega_cp: T,
    /// θ̇_m, rad/s.
    pub omega_m: T,
    /// θ̈_c, rad/s².
    pub alpha_c: T,
    /// θ̈_cp, rad/s² (0 for the ideal constant-cam-speed drive).
    pub alpha_cp: T,
    /// θ̈_m, rad/s² (0 for the ideal drives).
    pub alpha_m: T,
    /// Translational displacements (index by [`TransDof`]), in.
    pub pos: [T; TRANS_DOFS],
    /// Translational velocities, in/s.
    pub vel: [T; TRANS_DOFS],
    /// Translational accelerations, in/s².
    pub acc: [T; TRANS_DOFS],
    /// The cam's commanded lift y(θ_c) and its derivatives in θ.
    pub lift: FollowerLift<T>,
    /// Pressure angle φ, rad.
    pub pressure_angle: T,
    /// Hertz contact stiffness K_h at the current contact point, lb/in.
    pub k_h: T,
    /// Cam surface radius of curvature at the contact point (Eq. V.12), in; negative when concave.
    pub surface_radius: T,
    /// Contact force F_c (Eq. V.19 with the contact damping of docs/MODEL.md §3.9), lb; 0 while jumping.
    pub contact_force: T,
    /// False while the follower is off the cam (Eq. V.20).
    pub in_contact: bool,
    /// Slide-bearing friction on the follower y4 (from N1, Eqs. V.15-V.16), lb.
    pub friction_follower: T,
    /// Slide-bearing friction on the cantilever portion y3 (from N2, Eqs. V.15-V.16), lb.
    pub friction_cantilever: T,
    /// Output torque on the cam T_o = F_c cos φ dy/dθ (Eq. IV.1), lb·in.
    pub torque_out: T,
    /// Torque delivered by the drive, lb·in: T_i of the motor law, or for an ideal
    /// drive the torque it must supply to hold its speed.
    pub torque_drive: T,
}

impl<T: Real> ModelPoint<T> {
    /// Displacement of `dof` (absolute), in.
    pub fn position(&self, dof: TransDof) -> T {
        dof.of(&self.pos)
    }
    /// Velocity of `dof`, in/s.
    pub fn velocity(&self, dof: TransDof) -> T {
        dof.of(&self.vel)
    }
    /// Acceleration of `dof`, in/s².
    pub fn acceleration(&self, dof: TransDof) -> T {
        dof.of(&self.acc)
    }
    /// Follower output (load) displacement y5, in.
    pub fn load_displacement(&self) -> T {
        self.position(TransDof::Load)
    }
    /// Follower output (load) velocity, in/s.
    pub fn load_velocity(&self) -> T {
        self.velocity(TransDof::Load)
    }
    /// Follower output (load) acceleration, in/s².
    pub fn load_acceleration(&self) -> T {
        self.acceleration(TransDof::Load)
    }
}

/// The eleven-DOF model of Eqs. IV.1-IV.3 for scene `S`, with its `N`-component state.
///
/// `N` must equal `S::N`; building a model of any other size is a compile error. The
/// scenes' aliases ([`crate::RegulatedFullModel`], ...) fill both in:
///
/// ```
/// use camsim_core::{Design, RegulatedVertical, RegulatedVerticalModel, Scene, TransDof};
/// let m = RegulatedVerticalModel::<f64>::new(Design::reference()).unwrap();
/// let y = m.static_state();
/// assert_eq!(y.len(), RegulatedVertical::N); // 16
/// assert!(m.state(&y).position(TransDof::RollerX).is_none()); // dropped
/// ```
///
/// A state length other than the scene's does not compile (the check runs when the
/// model is monomorphised):
///
/// ```compile_fail
/// use camsim_core::{CamModel, Design, RegulatedVertical};
/// let m = CamModel::<f64, RegulatedVertical, 22>::new(Design::reference());
/// ```
///
/// The fourth parameter is where the lift comes from ([`LiftProfile`]): the theoretical
/// program by default, or an actual cam ([`crate::DeviatedLift`], built with
/// [`CamModel::with_profile`]).
#[derive(Clone, Debug)]
pub struct CamModel<T, S, const N: usize, P = TheoreticalLift> {
    d: Design<T>,
    profile: P,
    preload: T,
    prime_radius: T,
    rho_a: T,
    inv_i_m: T,
    inv_i_cp: T,
    inv_i_c: T,
    inv_m_r: T,
    inv_m_c: T,
    inv_m_l: T,
    c_rb: T,
    levers: BearingLevers<T>,
    bounds: ValidityBounds<T>,
    scene: PhantomData<S>,
}

impl<T: Real, S: Scene, const N: usize> CamModel<T, S, N> {
    /// Builds the model of the theoretical cam for `design`. The design's drive law must
    /// be of the scene's drive kind (`S::DRIVE`); the error names the field otherwise.
    pub fn new(design: Design<T>) -> Result<Self> {
        Self::with_profile(design, TheoreticalLift)
    }
}

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>> CamModel<T, S, N, P> {
    /// Builds the model for `design` whose roller rides on `profile` (an actual cam).
    pub fn with_profile(design: Design<T>, profile: P) -> Result<Self> {
        design.validate()?;
        Self::of_valid(design, profile)
    }

    /// [`CamModel::with_profile`] for a design whose geometry and program passed
    /// [`Design::validate`] before, at another speed (the same design but for
    /// [`Design::set_speed_rpm`]): the undercut scan, which reads only those and costs
    /// about 1.9 M instructions on the chip, is not repeated; the rest of the validation
    /// is. Bit for bit the model [`CamModel::with_profile`] builds.
    pub(crate) fn with_profile_scanned(design: Design<T>, profile: P) -> Result<Self> {
        design.validate_with(false)?;
        Self::of_valid(design, profile)
    }

    /// [`CamModel::with_profile`] of a design already validated.
    fn of_valid(design: Design<T>, profile: P) -> Result<Self> {
        crate::model::scene::assert_fits::<S, N>();
        if design.drive.kind() != S::DRIVE {
            return Err(Error::InvalidParameter {
                field: "drive",
                rule: "the drive law must be of the scene's drive kind (value: its free rotational DOFs)",
                value: design.drive.rotational_dofs() as f64,
            });
        }
        let preload = design.preload()?;
        Ok(Self {
            preload,
            prime_radius: design.geometry.prime_radius(),
            rho_a: design.rho * design.area,
            inv_i_m: T::ONE / design.i_m,
            inv_i_cp: T::ONE / design.i_cp,
            inv_i_c: T::ONE / design.i_c,
            inv_m_r: T::ONE / design.m_r,
            inv_m_c: T::ONE / design.m_c,
            inv_m_l: T::ONE / design.m_l,
            // C_rb = 2ξ√(K_rb M_r) goes with a massless roller's mass (docs/MODEL.md §10).
            c_rb: if S::QUASI_STATIC.contains(TransDof::RollerY) {
                T::ZERO
            } else {
                design.c_rb()
            },
            levers: BearingLevers::new(design.bearing_a, design.bearing_b),
            bounds: ValidityBounds::of(&design),
            d: design,
            profile,
            scene: PhantomData,
        })
    }

    /// The design this model was built from.
    pub fn design(&self) -> &Design<T> {
        &self.d
    }
    /// Where the roller's lift comes from.
    pub fn profile(&self) -> &P {
        &self.profile
    }
    /// The lift the roller rides on at cam angle `theta` (rad): the program plus the
    /// profile's deviation.
    #[inline(always)]
    pub fn lift(&self, theta: T) -> FollowerLift<T> {
        self.profile.follower(&self.d.program, theta)
    }
    /// The return-spring preload F_p (Eq. V.18), lb.
    pub fn preload(&self) -> T {
        self.preload
    }
    /// The contact damping C_h = 2ξ√(K_h M_r) at Hertz stiffness `k_h` (docs/MODEL.md
    /// §3.9); 0 for a massless roller, whose mass it goes with (§10).
    #[inline(always)]
    pub fn contact_damping(&self, k_h: T) -> T {
        if S::QUASI_STATIC.contains(TransDof::RollerY) {
            T::ZERO
        } else {
            self.d.c_h(k_h)
        }
    }
    /// The bounds of what the model represents for this design (docs/MODEL.md §3.20).
    pub fn validity_bounds(&self) -> &ValidityBounds<T> {
        &self.bounds
    }

    /// Whether the evaluated point `p` lies within what the model represents
    /// ([`ValidityBounds`]); otherwise the first bound it crosses, the quantity's value
    /// and the bound. A few comparisons: [`crate::simulate`] calls it on every sample
    /// (the midpoint and the end of each accepted step), not in the right-hand side. One
    /// copy, not inlined into every caller (it costs the chip's flash, not its time).
    #[inline(never)]
    pub fn check_validity(
        &self,
        p: &ModelPoint<T>,
    ) -> core::result::Result<(), (ModelLimit, T, T)> {
        let b = &self.bounds;
        let [y1, x1, y2, x2, y3, x3, y4, y5] = p.pos;
        // Positive while the roller presses into the cam (Eq. V.19's y + y1 - y2).
        let penetration = p.lift.y + y1 - y2;
        if penetration > b.penetration {
            return Err((ModelLimit::Penetration, penetration, b.penetration));
        }
        let cantilever = self.d.e2 - y3;
        if cantilever < b.length {
            return Err((ModelLimit::CantileverLength, cantilever, b.length));
        }
        let follower = self.d.e1 + y3;
        if follower < b.length {
            return Err((ModelLimit::FollowerLength, follower, b.length));
        }
        // The values first and their names only for the one out of range: an array of
        // (name, value) pairs built for every sample cost the chip about 50 instructions
        // a sample.
        let deflections = [y1, x1, y2 - y3, x2 - x3, x3, y4 - y3, y5 - y4];
        for (v, &what) in deflections.into_iter().zip(DEFLECTION_NAMES.iter()) {
            if v.abs() > b.deflection {
                return Err((ModelLimit::Deflection(what), v, b.deflection));
            }
        }
        let twists = [p.theta_cp - p.theta_c, p.theta_m - p.theta_cp];
        for (v, &what) in twists.into_iter().zip(TWIST_NAMES.iter()) {
            if v.abs() > b.twist {
                return Err((ModelLimit::Twist(what), v, b.twist));
            }
        }
        if p.omega_c <= T::ZERO {
            return Err((ModelLimit::CamSpeed, p.omega_c, T::ZERO));
        }
        Ok(())
    }

    /// The name of state component `i` of this scene in error messages
    /// ([`state_quantity_name`]; `"state"` for an index the scene does not have).
    #[inline(never)]
    pub fn state_quantity(&self, i: usize) -> &'static str {
        let vars = StateVar::ROTATIONAL.into_iter().chain(
            TransDof::ALL
                .into_iter()
                .flat_map(|d| [StateVar::Position(d), StateVar::Velocity(d)]),
        );
        for var in vars {
            if S::LAYOUT.index(var) == Some(i) {
                return state_quantity_name(var);
            }
        }
        "state"
    }
    /// Named read access to a state of this model.
    #[inline(always)]
    pub fn state<'a>(&self, y: &'a [T; N]) -> StateRef<'a, T, S, N> {
        StateRef::new(y)
    }

    /// Initial state of VI.1: every speed at ω0, everything else zero.
    pub fn initial_state(&self) -> [T; N] {
        let mut y = [T::ZERO; N];
        let mut s = StateMut::<T, S, N>::new(&mut y);
        let w = self.d.omega0;
        for v in [
            StateVar::CamSpeed,
            StateVar::CouplingSpeed,
            StateVar::MotorSpeed,
        ] {
            s.set(v, w);
        }
        y
    }

    /// Static equilibrium on the base circle (θ_c = 0, a dwell), every speed at ω0.
    ///
    /// With the cam at rest the vertical chain balances (derivation in the tests):
    /// F_c = F_p / (1 + K_rs K_h (1/K_vs + 1/K_rb) / (K_rs + K_h)), y1 = -F_c/K_vs,
    /// y3 = y4 = y5 = (F_c - F_p)/K_rs, y2 = y3 + F_c/K_rb; the shafts carry the steady
    /// drag: K_s2 (θ_cp - θ_c) = K_s1 (θ_m - θ_cp) = C_cc ω0 (the coupling passes it on). Starting here
    /// instead of at the thesis's all-zero state (VI.1) removes the start-up impact the
    /// unbalanced preload causes.
    pub fn static_state(&self) -> [T; N] {
        let d = &self.d;
        let l = self.lift(T::ZERO);
        let k_h = d.hertz.stiffness_fast(
            d.geometry.roller_radius,
            d.geometry.surface_curvature_radius(l.y, l.dy, l.d2y),
        );
        let c = T::ONE / d.k_vs + T::ONE / d.k_rb;
        let f_c = self.preload / (T::ONE + d.k_rs * k_h * c / (d.k_rs + k_h));
        let y3 = (f_c - self.preload) / d.k_rs;
        let pos = [
            -f_c / d.k_vs,     // y1
            T::ZERO,           // x1
            y3 + f_c / d.k_rb, // y2
            T::ZERO,           // x2
            y3,                // y3
            T::ZERO,           // x3
            y3,                // y4
            y3,                // y5
        ];
        let mut y = self.state_from(T::ZERO, &pos, &[T::ZERO; TRANS_DOFS]);
        let drag = d.c_cc * d.omega0;
        let mut s = StateMut::<T, S, N>::new(&mut y);
        // With free play the coupling drives the cam across it: half the play further.
        s.set(
            StateVar::CouplingCamTwist,
            drag / d.k_s2 + d.coupling_backlash * T::HALF,
        );
        // The motor shaft's twist is a state under the regulated drive and under the
        // constant motor speed, but only the regulated drive starts it twisted: under the
        // constant motor speed the coupling starts out of balance by C_cc ω0 (as before
        // scenes existed; the documented balance would twist it by drag / K_s1 too).
        let motor_twist = match S::DRIVE {
            DriveKind::Regulated => drag / d.k_s1,
            _ => T::ZERO,
        };
        s.set(StateVar::MotorCouplingTwist, motor_twist);
        y
    }

    /// The cam angle θ_c of a state at time `t`, rad (ω0 t under a constant cam speed).
    #[inline]
    pub fn cam_angle(&self, t: T, y: &[T; N]) -> T {
        match self.state(y).cam_angle() {
            Some(theta) => theta,
            None => self.d.omega0 * t,
        }
    }

    /// A state vector from translational displacements and velocities in [`TransDof`]
    /// order (the DOFs the scene drops are ignored; the rotational part at its initial
    /// value, θ_c = `theta_c`).
    pub fn state_from(&self, theta_c: T, pos: &[T; TRANS_DOFS], vel: &[T; TRANS_DOFS]) -> [T; N] {
        let mut y = self.initial_state();
        let lift = self.lift(theta_c).y;
        let mut s = StateMut::<T, S, N>::new(&mut y);
        s.set(StateVar::CamAngle, theta_c);
        for (((dof, p), v), rel) in TransDof::ALL
            .into_iter()
            .zip(pos)
            .zip(vel)
            .zip(RELATIVE_TO_LIFT)
        {
            s.set(StateVar::Position(dof), if rel { *p - lift } else { *p });
            s.set(StateVar::Velocity(dof), *v);
        }
        y
    }

    /// Evaluates every force and acceleration at (t, y) (the right-hand side and the outputs).
    pub fn evaluate(&self, t: T, y: &[T; N]) -> ModelPoint<T> {
        self.evaluate_with(t, y, true)
    }

    /// [`Self::evaluate`]; `outputs = false` skips what only observers read (the pressure
    /// angle itself: the forces use its sine and cosine), for the right-hand side. One copy
    /// for both uses (inlined into each it costs the chip's flash; docs/FIRMWARE.md).
    #[inline(never)]
    pub(crate) fn evaluate_with(&self, t: T, y: &[T; N], outputs: bool) -> ModelPoint<T> {
        let mut p = ModelPoint {
            t,
            ..ModelPoint::default()
        };
        let twists = self.gather_state(&mut p, t, y);
        let (cos_phi, sin_phi, k_h) = self.contact_geometry(&mut p, outputs);
        // A reduced scene's quasi-static DOFs balance their forces (docs/MODEL.md §10); the
        // rods' stiffnesses it used (at the carrier's y3) serve the forces below too.
        let rods = if S::QUASI_STATIC.is_empty() {
            None
        } else {
            Some(self.condense(&mut p, k_h, cos_phi, sin_phi))
        };
        // The stored coordinates (relative to the lift for the follower chain); `p.pos`
        // becomes the absolute displacements.
        let (pos, vel) = (p.pos, p.vel);
        let lift_y = p.lift.y;
        for (q, rel) in p.pos.iter_mut().zip(RELATIVE_TO_LIFT) {
            if rel {
                *q += lift_y;
            }
        }
        let (f_v, f_h) = self.contact_and_friction(&mut p, k_h, cos_phi, sin_phi, &pos, &vel);
        self.translational_equations(&mut p, rods, f_v, f_h, &pos, &vel);
        self.rotational_equations(&mut p, f_v, twists);
        p
    }

    /// Gathers the state into `p`: the cam angle, the speeds and shaft angles, the stored
    /// translational coordinates; returns the shaft twists (motor-coupling,
    /// coupling-cam). What the scene's drive imposes is not a state: under a constant cam
    /// speed θ_c = ω0 t with every speed at ω0 and rigid shafts; under a constant motor
    /// speed θ̇_m = ω0. These are branches on the scene's consts.
    #[inline(always)]
    fn gather_state(&self, p: &mut ModelPoint<T>, t: T, y: &[T; N]) -> (T, T) {
        let st = self.state(y);
        let w0 = self.d.omega0;
        p.theta_c = match st.cam_angle() {
            Some(theta) => theta,
            None => w0 * t,
        };
        let tw2 = st.coupling_cam_twist().unwrap_or(T::ZERO);
        let tw1 = st.motor_coupling_twist().unwrap_or(T::ZERO);
        p.omega_c = st.cam_speed().unwrap_or(w0);
        p.omega_cp = st.coupling_speed().unwrap_or(w0);
        p.omega_m = st.motor_speed().unwrap_or(w0);
        p.theta_cp = p.theta_c + tw2;
        p.theta_m = p.theta_cp + tw1;
        // The stored coordinates: q_i = y_i - s(θ_c) for the follower chain; the DOFs the
        // scene drops are held at zero.
        p.pos = st.positions();
        p.vel = st.velocities();
        (tw1, tw2)
    }

    /// The contact geometry at the current cam angle: the lift, the pressure angle's
    /// cosine and sine, the surface radius and the Hertz stiffness (into `p`; returns
    /// `(cos φ, sin φ, K_h)`).
    #[inline(always)]
    fn contact_geometry(&self, p: &mut ModelPoint<T>, outputs: bool) -> (T, T, T) {
        let d = &self.d;
        let (lift, table) = self
            .profile
            .follower_and_contact(&self.d.program, p.theta_c);
        p.lift = lift;
        // Pressure angle: tan φ = (dy/dθ) / (R_a + y); cos and sin without the atan (and
        // from the lift table's 1/hypotenuse without the square root, docs/MODEL.md §3.21).
        let rpy = self.prime_radius + lift.y;
        let (cos_phi, sin_phi) = match table {
            Some(c) => (rpy * c.inv_hyp, lift.dy * c.inv_hyp),
            None => {
                let hyp = (rpy * rpy + lift.dy * lift.dy).sqrt();
                if hyp > T::ZERO {
                    (rpy / hyp, lift.dy / hyp)
                } else {
                    (T::ONE, T::ZERO)
                }
            }
        };
        let k_h_table = table.map(|c| c.k_h);
        if outputs {
            p.pressure_angle = lift.dy.atan2(rpy);
        }
        // Hertz stiffness at the contact point (Eqs. V.9-V.11): from the lift table where
        // the profile is one (docs/MODEL.md §3.21), the surface radius then only for the
        // outputs.
        let k_h = match k_h_table {
            Some(k) => {
                if outputs {
                    p.surface_radius = d
                        .geometry
                        .surface_curvature_radius(lift.y, lift.dy, lift.d2y);
                }
                k
            }
            None => {
                p.surface_radius = d
                    .geometry
                    .surface_curvature_radius(lift.y, lift.dy, lift.d2y);
                d.hertz
                    .stiffness_fast(d.geometry.roller_radius, p.surface_radius)
            }
        };
        p.k_h = k_h;
        (cos_phi, sin_phi, k_h)
    }

    /// The contact force with its jump criterion and the slide-bearing friction (into
    /// `p`), from the stored coordinates `pos`, `vel`; returns the contact force's
    /// vertical and horizontal components on the roller.
    #[inline(always)]
    fn contact_and_friction(
        &self,
        p: &mut ModelPoint<T>,
        k_h: T,
        cos_phi: T,
        sin_phi: T,
        pos: &[T; TRANS_DOFS],
        vel: &[T; TRANS_DOFS],
    ) -> (T, T) {
        let d = &self.d;
        let [y1, _, q2, _, _, _, _, _] = *pos;
        let [v1, _, v2, _, v3, _, v4, _] = *vel;
        // Contact force and jump criterion (Eqs. V.19-V.20) with the contact damping of
        // docs/MODEL.md §3.9; y + y1 - y2 = y1 - q2, its rate y' θ̇_c + ẏ1 - ẏ2.
        let contact = damped_contact_force(
            k_h,
            y1 - q2,
            self.preload,
            self.contact_damping(k_h),
            p.lift.dy * p.omega_c + v1 - v2,
            cos_phi,
        );
        let f_c = contact.force;
        p.contact_force = f_c;
        p.in_contact = contact.in_contact;
        let f_v = f_c * cos_phi; // vertical component on the roller
        let f_h = f_c * sin_phi; // horizontal component

        // Slide-bearing friction (Eqs. V.15-V.16), each opposing its own mass's velocity.
        // At a quasi-static node the condensation has applied (and recorded) it already.
        let (n1, n2) = self.levers.normal_forces(f_c, sin_phi);
        let f1 = if S::QUASI_STATIC.contains(TransDof::Follower) {
            p.friction_follower
        } else {
            coulomb_friction(d.mu, n1, v4, d.friction_smoothing)
        };
        let f2 = if S::QUASI_STATIC.contains(TransDof::CantileverY) {
            p.friction_cantilever
        } else {
            coulomb_friction(d.mu, n2, v3, d.friction_smoothing)
        };
        p.friction_follower = f1;
        p.friction_cantilever = f2;
        (f_v, f_h)
    }

    /// The translational system (Eqs. IV.2, IV.3): each kept DOF's acceleration into
    /// `p.acc`, from the stored coordinates `pos`, `vel`, the contact force's components
    /// and the friction in `p`; `rods` are a reduced scene's rod stiffnesses and damping
    /// (`K_f`, `C_f1`, `K_vc`) from its condensation.
    #[inline(always)]
    fn translational_equations(
        &self,
        p: &mut ModelPoint<T>,
        rods: Option<(T, T, T)>,
        f_v: T,
        f_h: T,
        pos: &[T; TRANS_DOFS],
        vel: &[T; TRANS_DOFS],
    ) {
        let d = &self.d;
        let [y1, _, q2, x2, q3, x3, q4, q5] = *pos;
        let [v1, _, v2, vx2, v3, vx3, v4, v5] = *vel;
        let (f1, f2) = (p.friction_follower, p.friction_cantilever);
        let y3 = q3 + p.lift.y;
        let (k_f, c_f1, k_vc) = match rods {
            Some(r) => r,
            None => {
                let k_f = d.k_f(y3);
                (k_f, d.c_f1_from(k_f), d.k_vc(y3))
            }
        };
        let m_f = d.m_f(y3);
        let m_fc = d.m_fc(y3);
        let f_load = k_f * (q5 - q4) + c_f1 * (v5 - v4);
        let f_vc = k_vc * (q4 - q3);
        // Roller bearing on the roller (the opposite on the cantilever), vertical and
        // horizontal: K_rb and its damper C_rb (docs/MODEL.md §3.13, §3.14).
        let f_rb = crate::spring_damper_force(d.k_rb, q3 - q2, self.c_rb, v3 - v2);
        let f_rb_x = crate::spring_damper_force(d.k_rb, x3 - x2, self.c_rb, vx3 - vx2);
        // A reduced scene's dropped follower masses ride on the first dynamic node beyond
        // its quasi-static run (docs/MODEL.md §10): const branches.
        let qs = S::QUASI_STATIC;
        let qs_roller = qs.contains(TransDof::RollerY);
        let qs_cantilever = qs.contains(TransDof::CantileverY);
        let qs_follower = qs.contains(TransDof::Follower);
        let m_r = d.m_r;
        // Load.
        let a_load = if qs_follower {
            -f_load / (d.m_l + m_f + m_fc + m_r)
        } else {
            -f_load * self.inv_m_l
        };
        // Follower: d(M_f ẏ4)/dt = ρA ẏ3 ẏ4 + M_f ÿ4 (the exchange with the cantilever
        // portion is internal once it rides on the follower).
        let a_follower = if qs_cantilever {
            (f_load + f1 - f_vc) / (m_f + m_fc + m_r)
        } else {
            (f_load + f1 - f_vc - self.rho_a * v3 * v4) / m_f
        };
        // Cantilever: d(M_fc ẏ3)/dt = -ρA ẏ3² + M_fc ÿ3.
        let m_cantilever = if qs_roller { m_fc + m_r } else { m_fc };
        let a_cantilever =
            (f_vc - self.preload - d.k_rs * y3 + f2 - f_rb + self.rho_a * v3 * v3) / m_cantilever;
        // Roller.
        let a_roller = (f_rb + f_v) * self.inv_m_r;
        // Cam and shaft.
        let a_cam = (-f_v - d.k_vs * y1 - d.c_vs * v1) * self.inv_m_c;
        // The first dynamic follower node's acceleration: a quasi-static node moves with it.
        let a_carrier = if qs_follower {
            a_load
        } else if qs_cantilever {
            a_follower
        } else {
            a_cantilever
        };
        // A DOF the scene drops does not accelerate; a quasi-static one moves with its
        // carrier (the cam shaft, quasi-static, with the cam's mass neglected: 0).
        let kept = |dof: TransDof, a: T| {
            if qs.contains(dof) {
                match dof {
                    TransDof::CamY => T::ZERO,
                    _ => a_carrier,
                }
            } else if S::DOFS.contains(dof) {
                a
            } else {
                T::ZERO
            }
        };
        let [a_cam_x, a_roller_x, a_cantilever_x] =
            self.horizontal_equations(f_rb_x, f_h, y3, m_fc, pos, vel);
        p.acc = [
            kept(TransDof::CamY, a_cam),
            a_cam_x,
            kept(TransDof::RollerY, a_roller),
            a_roller_x,
            kept(TransDof::CantileverY, a_cantilever),
            a_cantilever_x,
            kept(TransDof::Follower, a_follower),
            kept(TransDof::Load, a_load),
        ];
    }

    /// The horizontal equations (Eq. IV.3), evaluated only for the scenes that keep them
    /// (zero otherwise): the cam's, the roller's and the cantilever's horizontal
    /// accelerations, from the bearing's horizontal force `f_rb_x`, the contact force's
    /// horizontal component `f_h`, the cantilever's length `y3` and mass `m_fc`.
    #[inline(always)]
    fn horizontal_equations(
        &self,
        f_rb_x: T,
        f_h: T,
        y3: T,
        m_fc: T,
        pos: &[T; TRANS_DOFS],
        vel: &[T; TRANS_DOFS],
    ) -> [T; 3] {
        let d = &self.d;
        let [_, x1, _, _, _, x3, _, _] = *pos;
        let [_, vx1, _, _, v3, vx3, _, _] = *vel;
        let a_cantilever_x = if S::DOFS.contains(TransDof::CantileverX) {
            // d(M_fc ẋ3)/dt = -ρA ẏ3 ẋ3 + M_fc ẍ3 (Eq. IV.3 corrected, docs/MODEL.md §4.4).
            (-f_rb_x - d.k_hc(y3) * x3 + self.rho_a * v3 * vx3) / m_fc
        } else {
            T::ZERO
        };
        let a_roller_x = if S::DOFS.contains(TransDof::RollerX) {
            (f_rb_x - f_h) * self.inv_m_r
        } else {
            T::ZERO
        };
        let a_cam_x = if S::DOFS.contains(TransDof::CamX) {
            (f_h - d.k_hs * x1 - d.c_hs * vx1) * self.inv_m_c
        } else {
            T::ZERO
        };
        [a_cam_x, a_roller_x, a_cantilever_x]
    }

    /// The rotational system (Eq. IV.1) under the scene's drive, into `p`: the output
    /// torque T_o = F_c cos φ dy/dθ (docs/MODEL.md §4.2), the shafts' torques, the
    /// angular accelerations and the drive torque; `twists` are (motor-coupling,
    /// coupling-cam).
    #[inline(always)]
    fn rotational_equations(&self, p: &mut ModelPoint<T>, f_v: T, twists: (T, T)) {
        let d = &self.d;
        let (tw1, tw2) = twists;
        let t_o = f_v * p.lift.dy;
        p.torque_out = t_o;
        // The coupling-cam connection: rigid, or with free play (Appendix G.1).
        let shaft2 = if d.coupling_backlash > T::ZERO {
            crate::backlash_torque(
                d.k_s2,
                d.c_s2,
                d.coupling_backlash,
                tw2,
                p.omega_cp - p.omega_c,
            )
        } else {
            d.c_s2 * (p.omega_cp - p.omega_c) + d.k_s2 * tw2
        };
        let shaft1 = d.c_s1 * (p.omega_m - p.omega_cp) + d.k_s1 * tw1;
        match S::DRIVE {
            DriveKind::ConstantCamSpeed => {
                // The ideal drive holds the cam: it supplies the cam's drag and the output torque.
                p.torque_drive = d.c_cc * p.omega_c + t_o;
            }
            DriveKind::ConstantMotorSpeed => {
                p.alpha_c = (shaft2 - d.c_cc * p.omega_c - t_o) * self.inv_i_c;
                p.alpha_cp = (shaft1 - shaft2) * self.inv_i_cp;
                // Torque that holds the motor at ω0 (its acceleration is zero).
                p.torque_drive = d.c_mb * p.omega_m + shaft1;
            }
            DriveKind::Regulated => {
                p.alpha_c = (shaft2 - d.c_cc * p.omega_c - t_o) * self.inv_i_c;
                p.alpha_cp = (shaft1 - shaft2) * self.inv_i_cp;
                p.torque_drive = d.drive.torque(p.omega_m);
                p.alpha_m = (p.torque_drive - d.c_mb * p.omega_m - shaft1) * self.inv_i_m;
            }
        }
    }

    /// Solves a reduced scene's quasi-static DOFs ([`crate::QuasiStatic`], docs/MODEL.md
    /// §10) into `p.pos` (stored coordinates: relative to the lift for the follower
    /// chain) and `p.vel` (absolute), from the dynamic nodes already there.
    ///
    /// The balance of the massless nodes, in order: a first solve with the contact closed
    /// decides contact (K_h (y1 - q2) + F_p > 0, Eq. V.20); the velocities follow from the
    /// same matrix (the balance differentiated, the stiffnesses' own rates neglected); the
    /// rod's damper and the slide-bearing friction at the quasi-static nodes then act as
    /// given forces (friction's normal force from the first solve's contact force) in the
    /// final solve. A contact that the final solve opens is solved open. Returns the rods'
    /// K_f, C_f1 and K_vc it used, for the forces on the dynamic nodes.
    #[inline(always)]
    fn condense(&self, p: &mut ModelPoint<T>, k_h: T, cos_phi: T, sin_phi: T) -> (T, T, T) {
        let d = &self.d;
        let chain = crate::QUASI_STATIC_CHAIN.map(|dof| dof as usize);
        let [_, _, i3, i4, i5] = chain;
        let at = |a: &[T; TRANS_DOFS], i: usize| a.get(i).copied().unwrap_or(T::ZERO);
        let mut x = chain.map(|i| at(&p.pos, i));
        // The lift's rate s'(θ) θ̇_c: the follower chain's stored coordinates move by it.
        let rate = p.lift.dy * p.omega_c;
        // K_vc and K_f depend on y3 (a few microinches off when y3 is itself quasi-static:
        // the first dynamic follower node's stored coordinate stands for it).
        let y3_est = Self::y3_estimate(p, at, [i3, i4, i5]);
        let k_f = d.k_f(y3_est);
        let c_f1 = d.c_f1_from(k_f);
        let k_vc = d.k_vc(y3_est);
        let c2 = cos_phi * cos_phi;
        let closed = crate::ChainSolve::new(
            S::QUASI_STATIC,
            [k_h * c2, d.k_rb, k_vc, k_f],
            [d.k_vs, T::ZERO, d.k_rs, T::ZERO],
        );
        let mut open = closed;
        if let Some(k) = open.series.first_mut() {
            *k = T::ZERO;
        }
        let closed = closed.factor();
        // Forces that do not depend on the displacements: the contact's preload offset
        // (F_p cos²φ on the roller, its reaction on the cam), the return spring's preload
        // and its pull at the lift, K_rs s.
        let spring = -self.preload - d.k_rs * p.lift.y;
        let offset = self.preload * c2;
        let statics = |contact: bool| {
            if contact {
                [-offset, offset, spring, T::ZERO]
            } else {
                [T::ZERO, T::ZERO, spring, T::ZERO]
            }
        };
        let approach = |x: &[T; 5]| {
            let [y1, q2, ..] = *x;
            k_h * (y1 - q2) + self.preload
        };
        let mut trial = x;
        closed.solve(&mut trial, &statics(true));
        let e0 = approach(&trial);
        let mut contact = e0 > T::ZERO;
        for _ in 0..2 {
            // By value, not a reference to one of two: the run's bounds then stay
            // constants and the solves unroll.
            let c = if contact { closed } else { open.factor() };
            // Velocities in the stored coordinates (y1 absolute, the rest relative).
            let mut xd = chain.map(|i| at(&p.vel, i));
            for v in xd.iter_mut().skip(1) {
                *v -= rate;
            }
            c.solve(&mut xd, &[T::ZERO, T::ZERO, -d.k_rs * rate, T::ZERO]);
            let mut vel = xd;
            for v in vel.iter_mut().skip(1) {
                *v += rate;
            }
            let mut f = statics(contact);
            let f_c = if contact { e0 * cos_phi } else { T::ZERO };
            self.add_given_forces(p, &mut f, &vel, contact, f_c, sin_phi, c_f1);
            let mut sol = x;
            c.solve(&mut sol, &f);
            let e = approach(&sol);
            if contact && e <= T::ZERO {
                // The friction opened it: solve it open.
                contact = false;
                continue;
            }
            x = sol;
            Self::store_quasi_static(p, &chain, &x, &vel);
            break;
        }
        (k_f, c_f1, k_vc)
    }

    /// [`Self::condense`]'s y3 for K_vc and K_f: the stored coordinate of the first dynamic
    /// node of y3, y4, y5 (chain indices `i`) plus the lift.
    #[inline(always)]
    fn y3_estimate(
        p: &ModelPoint<T>,
        at: impl Fn(&[T; TRANS_DOFS], usize) -> T,
        [i3, i4, i5]: [usize; 3],
    ) -> T {
        let node = if S::QUASI_STATIC.contains(TransDof::CantileverY) {
            if S::QUASI_STATIC.contains(TransDof::Follower) {
                at(&p.pos, i5)
            } else {
                at(&p.pos, i4)
            }
        } else {
            at(&p.pos, i3)
        };
        node + p.lift.y
    }

    /// [`Self::condense`]'s given forces on the quasi-static nodes, added to `f`: the cam
    /// shaft's damper, the rod's damper, and the slide-bearing friction (Eqs. V.15-V.16),
    /// whose values it leaves in `p`; `f_c` is the contact force of the first solve.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn add_given_forces(
        &self,
        p: &mut ModelPoint<T>,
        f: &mut [T; 4],
        vel: &[T; 5],
        contact: bool,
        f_c: T,
        sin_phi: T,
        c_f1: T,
    ) {
        let d = &self.d;
        let [v1, _v2, v3, v4, v5] = *vel;
        let (n1, n2) = self.levers.normal_forces(f_c, sin_phi);
        let [f0, _, f2, f3] = f;
        if S::QUASI_STATIC.contains(TransDof::CamY) {
            *f0 -= d.c_vs * v1;
        }
        if S::QUASI_STATIC.contains(TransDof::CantileverY) {
            p.friction_cantilever = if contact {
                crate::coulomb_friction(d.mu, n2, v3, d.friction_smoothing)
            } else {
                T::ZERO
            };
            *f2 += p.friction_cantilever;
        }
        if S::QUASI_STATIC.contains(TransDof::Follower) {
            p.friction_follower = if contact {
                crate::coulomb_friction(d.mu, n1, v4, d.friction_smoothing)
            } else {
                T::ZERO
            };
            *f3 += p.friction_follower + c_f1 * (v5 - v4);
        }
    }

    /// [`Self::condense`]'s result: the quasi-static nodes' positions `x` and velocities
    /// `vel` (chain order) written into `p` at their state indices `chain`.
    #[inline(always)]
    fn store_quasi_static(p: &mut ModelPoint<T>, chain: &[usize; 5], x: &[T; 5], vel: &[T; 5]) {
        for (node, i) in chain.iter().enumerate() {
            let qs = crate::QUASI_STATIC_CHAIN
                .get(node)
                .is_some_and(|dof| S::QUASI_STATIC.contains(*dof));
            if qs {
                if let (Some(o), Some(v)) = (p.pos.get_mut(*i), p.vel.get_mut(*i)) {
                    *o = x.get(node).copied().unwrap_or(T::ZERO);
                    *v = vel.get(node).copied().unwrap_or(T::ZERO);
                }
            }
        }
    }

    /// Writes dy/dt for the state (t, y) given the evaluated point: every quantity the
    /// scene keeps (the layout numbers them 0..N, so every component is written).
    #[inline]
    pub(crate) fn derivative(&self, p: &ModelPoint<T>, dydt: &mut [T; N]) {
        let mut out = StateMut::<T, S, N>::new(dydt);
        out.set(StateVar::CamAngle, p.omega_c);
        out.set(StateVar::CouplingCamTwist, p.omega_cp - p.omega_c);
        out.set(StateVar::MotorCouplingTwist, p.omega_m - p.omega_cp);
        out.set(StateVar::CamSpeed, p.alpha_c);
        out.set(StateVar::CouplingSpeed, p.alpha_cp);
        out.set(StateVar::MotorSpeed, p.alpha_m);
        let dofs = TransDof::ALL.into_iter().zip(RELATIVE_TO_LIFT);
        for ((dof, relative), (v, a)) in dofs.zip(p.vel.iter().zip(p.acc.iter())) {
            // dq/dt = ẏ - s'(θ_c) θ̇_c for the displacements stored relative to the lift.
            let rel = if relative {
                p.lift.dy * p.omega_c
            } else {
                T::ZERO
            };
            out.set(StateVar::Position(dof), *v - rel);
            out.set(StateVar::Velocity(dof), *a);
        }
    }
}

impl<T: Real, S: Scene, const N: usize, P: LiftProfile<T>> OdeSystem<T, N>
    for CamModel<T, S, N, P>
{
    #[inline]
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]) {
        let p = self.evaluate_with(t, y, false);
        self.derivative(&p, dydt);
    }
}

#[cfg(test)]
mod validity_tests {
    use super::*;
    use crate::{RegulatedFull, RegulatedFullModel};

    #[test]
    fn bounds_follow_from_the_roller_and_base_radii() {
        let d = Design::<f64>::reference();
        let b = ValidityBounds::of(&d);
        // r_r = 0.375 in, R_b = 1.5 in: r_min = r_r.
        assert!((b.penetration - 0.375 / 100.0).abs() < 1e-18);
        assert!((b.deflection - 0.0375).abs() < 1e-17);
        assert_eq!((b.length, b.twist), (0.375, 0.1));
        // A roller larger than the base circle: the base circle sets the penetration.
        let mut big = d.clone();
        big.geometry.roller_radius = 2.0;
        assert!((ValidityBounds::of(&big).penetration - 0.015).abs() < 1e-17);
    }

    #[test]
    fn each_bound_is_found_at_its_quantity() {
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let y = m.static_state();
        let p = m.evaluate(0.0, &y);
        assert_eq!(m.check_validity(&p), Ok(()));
        // The follower thrown up to within 0.3 in of the slide bearing: e2 - y3 = 0.3.
        let mut q = p;
        q.pos[TransDof::CantileverY as usize] = 1.7;
        let Err((limit, value, bound)) = m.check_validity(&q) else {
            panic!("not refused")
        };
        assert_eq!(limit, ModelLimit::CantileverLength);
        assert!((value - 0.3).abs() < 1e-15 && bound == 0.375);
        // The cam shaft bent by 0.05 in > 0.0375.
        let mut q = p;
        q.pos[TransDof::CamX as usize] = -0.05;
        let d = m.validity_bounds().deflection;
        assert_eq!(
            m.check_validity(&q),
            Err((ModelLimit::Deflection("cam-shaft deflection x1"), -0.05, d))
        );
        // The roller 0.01 in into the cam (y + y1 - y2 = 0.01 > 0.00375).
        let mut q = p;
        q.pos[TransDof::RollerY as usize] = q.lift.y + q.pos[0] - 0.01;
        let r = m.check_validity(&q);
        assert!(
            matches!(r, Err((ModelLimit::Penetration, v, _)) if (v - 0.01).abs() < 1e-12),
            "{r:?}"
        );
        // A twisted coupling-cam shaft, a stopped cam.
        let mut q = p;
        q.theta_cp = q.theta_c + 0.2;
        q.theta_m = q.theta_cp;
        assert!(matches!(
            m.check_validity(&q),
            Err((ModelLimit::Twist("coupling-cam shaft twist"), _, _))
        ));
        let mut q = p;
        q.omega_c = -1.0;
        assert_eq!(m.check_validity(&q), Err((ModelLimit::CamSpeed, -1.0, 0.0)));
    }

    #[test]
    fn every_state_component_has_a_name() {
        let m = RegulatedFullModel::<f64>::new(Design::reference()).unwrap();
        let names: std::vec::Vec<&str> = (0..<RegulatedFull as Scene>::N)
            .map(|i| m.state_quantity(i))
            .collect();
        assert_eq!(names[0], "cam angle");
        assert_eq!(names[21], "load y5 velocity");
        let mut unique = names.clone();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), names.len());
        assert!(!names.contains(&"state"));
        assert_eq!(m.state_quantity(22), "state");
    }
}
