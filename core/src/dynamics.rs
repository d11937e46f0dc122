//! The eleven-degree-of-freedom cam-follower model (Eqs. IV.1-IV.3).
//!
//! Degrees of freedom: motor, coupling and cam rotation (θ_m, θ_cp, θ_c); cam
//! vertical and horizontal (y1, x1); roller vertical and horizontal (y2, x2);
//! cantilever portion of the follower vertical and horizontal (y3, x3); follower
//! (y4); load (y5). A scene may drop groups of them ([`DofSet`]): the ideal drives
//! of [`DriveLaw`] remove rotational DOFs, and the horizontal motion can be switched
//! off; the state is then smaller (the const generic `N` of [`CamModel`]).
//!
//! State layout (`N` components):
//! 1. rotational block, by drive law: regulated: `[θ_c, θ_cp - θ_c, θ_m - θ_cp, θ̇_c, θ̇_cp, θ̇_m]`;
//!    constant motor speed: `[θ_c, θ_cp - θ_c, θ_m - θ_cp, θ̇_c, θ̇_cp]`; constant cam
//!    speed: nothing (θ_c = ω0 t). Shaft twists are states, not absolute angles, so the
//!    small twist is not lost to cancellation (this matters in `f32`).
//! 2. the active translational displacements in the order y1, x1, y2, x2, y3, x3, y4, y5;
//!    the follower chain's vertical ones (y2, y3, y4, y5) are stored relative to the
//!    cam's commanded lift, `q_i = y_i - s(θ_c)` ([`RELATIVE_TO_LIFT`]), for the same
//!    reason: in `f32` an absolute y2 near the 1.5 in lift resolves only 1.2e-7 in, i.e.
//!    0.8 lb of Hertz force (K_h ≈ 6.5e6 lb/in), and θ_c's own rounding moves s(θ_c) by
//!    microinches; the spring and contact deflections are formed from the q's instead.
//!    Same physics, different coordinates;
//! 3. their (absolute) velocities in the same order.

use crate::{coulomb_friction, Design, DriveLaw, Error, FollowerLift, OdeSystem, Real, Result};

/// The translational degrees of freedom, in state order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum TransDof {
    /// y1: cam (and shaft) vertical.
    CamY = 0,
    /// x1: cam horizontal.
    CamX = 1,
    /// y2: roller vertical.
    RollerY = 2,
    /// x2: roller horizontal.
    RollerX = 3,
    /// y3: cantilever portion of the follower, vertical.
    CantileverY = 4,
    /// x3: cantilever portion of the follower, horizontal.
    CantileverX = 5,
    /// y4: follower between slide bearing and load.
    Follower = 6,
    /// y5: load (the follower output).
    Load = 7,
}

/// Number of translational DOFs of the full model.
pub const TRANS_DOFS: usize = 8;

/// Which translational DOFs a scene keeps (a bit mask over [`TransDof`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DofSet(u8);

impl DofSet {
    /// All eight translational DOFs.
    pub const ALL: DofSet = DofSet(0xFF);
    /// Vertical motion only: x1, x2, x3 dropped (held at zero).
    pub const VERTICAL: DofSet = DofSet(!0b0010_1010);

    /// Whether `dof` is kept.
    pub const fn contains(self, dof: TransDof) -> bool {
        self.0 & (1 << dof as u8) != 0
    }
    /// This set without `dof`.
    pub const fn without(self, dof: TransDof) -> DofSet {
        DofSet(self.0 & !(1 << dof as u8))
    }
    /// Number of kept DOFs.
    pub const fn count(self) -> usize {
        self.0.count_ones() as usize
    }
}

const NONE: u8 = u8::MAX;

/// Translational DOFs whose displacement state is stored relative to the commanded lift
/// s(θ_c) (the follower chain y2, y3, y4, y5; see the module docs).
pub const RELATIVE_TO_LIFT: [bool; TRANS_DOFS] =
    [false, false, true, false, true, false, true, true];

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
    /// Contact force F_c (Eq. V.19), lb; 0 while jumping.
    pub contact_force: T,
    /// False while the follower is off the cam (Eq. V.20).
    pub in_contact: bool,
    /// Output torque on the cam T_o = F_c cos φ dy/dθ (Eq. IV.1), lb·in.
    pub torque_out: T,
    /// Torque delivered by the drive, lb·in: T_i of the motor law, or for an ideal
    /// drive the torque it must supply to hold its speed.
    pub torque_drive: T,
}

impl<T: Real> ModelPoint<T> {
    /// Follower output (load) displacement y5, in.
    pub fn load_displacement(&self) -> T {
        self.pos[TransDof::Load as usize]
    }
    /// Follower output (load) velocity, in/s.
    pub fn load_velocity(&self) -> T {
        self.vel[TransDof::Load as usize]
    }
    /// Follower output (load) acceleration, in/s².
    pub fn load_acceleration(&self) -> T {
        self.acc[TransDof::Load as usize]
    }
}

/// The eleven-DOF model of Eqs. IV.1-IV.3 with an `N`-component state (see the module docs).
#[derive(Clone, Debug)]
pub struct CamModel<T, const N: usize> {
    d: Design<T>,
    dofs: DofSet,
    rot: usize,
    trans_slot: [u8; TRANS_DOFS],
    n_trans: usize,
    preload: T,
    prime_radius: T,
    rho_a: T,
    inv_i_m: T,
    inv_i_cp: T,
    inv_i_c: T,
    inv_m_r: T,
    inv_m_c: T,
    inv_m_l: T,
    n1_factor: T,
    n2_factor: T,
}

/// The state size a drive law and DOF set need.
pub const fn state_len(rotational_states: usize, dofs: DofSet) -> usize {
    rotational_states + 2 * dofs.count()
}

fn rotational_states<T: Real>(drive: &DriveLaw<T>) -> usize {
    match drive {
        DriveLaw::ConstantCamSpeed => 0,
        DriveLaw::ConstantMotorSpeed => 5,
        DriveLaw::Regulated { .. } => 6,
    }
}

impl<T: Real, const N: usize> CamModel<T, N> {
    /// Builds the model for `design`, keeping the translational DOFs in `dofs` and the
    /// rotational ones the design's drive law leaves free. `N` must equal the state size
    /// (6, 5 or 0 rotational states plus twice the translational DOFs); the error says which.
    pub fn new(design: Design<T>, dofs: DofSet) -> Result<Self> {
        design.validate()?;
        for (dof, field) in [
            (TransDof::RollerY, "dofs: roller vertical y2"),
            (TransDof::CantileverY, "dofs: cantilever vertical y3"),
            (TransDof::Load, "dofs: load y5"),
        ] {
            if !dofs.contains(dof) {
                return Err(Error::InvalidParameter {
                    field,
                    rule: "the contact, the spring and the output need this DOF",
                    value: 0.0,
                });
            }
        }
        let rot = rotational_states(&design.drive);
        let need = state_len(rot, dofs);
        if need != N {
            return Err(Error::InvalidParameter {
                field: "state size N",
                rule: "must equal the rotational states of the drive plus twice the translational DOFs",
                value: need as f64,
            });
        }
        let mut trans_slot = [NONE; TRANS_DOFS];
        let mut k = 0u8;
        for (i, s) in trans_slot.iter_mut().enumerate() {
            if dofs.0 & (1 << i) != 0 {
                *s = k;
                k += 1;
            }
        }
        let preload = design.preload()?;
        let ab = design.bearing_a + design.bearing_b;
        Ok(Self {
            dofs,
            rot,
            trans_slot,
            n_trans: dofs.count(),
            preload,
            prime_radius: design.geometry.prime_radius(),
            rho_a: design.rho * design.area,
            inv_i_m: T::ONE / design.i_m,
            inv_i_cp: T::ONE / design.i_cp,
            inv_i_c: T::ONE / design.i_c,
            inv_m_r: T::ONE / design.m_r,
            inv_m_c: T::ONE / design.m_c,
            inv_m_l: T::ONE / design.m_l,
            n1_factor: ab / design.bearing_b,
            n2_factor: design.bearing_a / design.bearing_b,
            d: design,
        })
    }

    /// The design this model was built from.
    pub fn design(&self) -> &Design<T> {
        &self.d
    }
    /// The translational DOFs kept.
    pub fn dofs(&self) -> DofSet {
        self.dofs
    }
    /// Number of rotational state components (6, 5 or 0).
    pub fn rotational_states(&self) -> usize {
        self.rot
    }
    /// The return-spring preload F_p (Eq. V.18), lb.
    pub fn preload(&self) -> T {
        self.preload
    }

    /// Initial state of VI.1: every speed at ω0, everything else zero.
    pub fn initial_state(&self) -> [T; N] {
        let mut y = [T::ZERO; N];
        let w = self.d.omega0;
        match self.rot {
            6 => {
                if let Some(s) = y.get_mut(3..6) {
                    s.iter_mut().for_each(|v| *v = w);
                }
            }
            5 => {
                if let Some(s) = y.get_mut(3..5) {
                    s.iter_mut().for_each(|v| *v = w);
                }
            }
            _ => {}
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
        let l = d.program.follower(T::ZERO);
        let k_h = d.hertz.stiffness_fast(
            d.geometry.roller_radius,
            d.geometry.surface_curvature_radius(l.y, l.dy, l.d2y),
        );
        let c = T::ONE / d.k_vs + T::ONE / d.k_rb;
        let f_c = self.preload / (T::ONE + d.k_rs * k_h * c / (d.k_rs + k_h));
        let y3 = (f_c - self.preload) / d.k_rs;
        let mut pos = [T::ZERO; TRANS_DOFS];
        pos[TransDof::CamY as usize] = -f_c / d.k_vs;
        pos[TransDof::RollerY as usize] = y3 + f_c / d.k_rb;
        pos[TransDof::CantileverY as usize] = y3;
        pos[TransDof::Follower as usize] = y3;
        pos[TransDof::Load as usize] = y3;
        let mut y = self.state_from(T::ZERO, &pos, &[T::ZERO; TRANS_DOFS]);
        if self.rot >= 5 {
            let drag = d.c_cc * d.omega0;
            if let Some(v) = y.get_mut(1) {
                *v = drag / d.k_s2;
            }
            if let Some(v) = y.get_mut(2) {
                *v = if self.rot == 6 {
                    drag / d.k_s1
                } else {
                    T::ZERO
                };
            }
        }
        y
    }

    /// The cam angle θ_c of a state at time `t`, rad.
    #[inline]
    pub fn cam_angle(&self, t: T, y: &[T; N]) -> T {
        if self.rot == 0 {
            self.d.omega0 * t
        } else {
            y.first().copied().unwrap_or(T::ZERO)
        }
    }

    /// A state vector from translational displacements and velocities (rotational part
    /// at its initial value, θ_c = `theta_c`).
    pub fn state_from(&self, theta_c: T, pos: &[T; TRANS_DOFS], vel: &[T; TRANS_DOFS]) -> [T; N] {
        let mut y = self.initial_state();
        if self.rot > 0 {
            if let Some(v) = y.first_mut() {
                *v = theta_c;
            }
        }
        for i in 0..TRANS_DOFS {
            let s = self.trans_slot[i];
            if s != NONE {
                let s = s as usize;
                let rel = if RELATIVE_TO_LIFT[i] {
                    self.d.program.follower(theta_c).y
                } else {
                    T::ZERO
                };
                if let Some(v) = y.get_mut(self.rot + s) {
                    *v = pos[i] - rel;
                }
                if let Some(v) = y.get_mut(self.rot + self.n_trans + s) {
                    *v = vel[i];
                }
            }
        }
        y
    }

    /// Evaluates every force and acceleration at (t, y) (the right-hand side and the outputs).
    pub fn evaluate(&self, t: T, y: &[T; N]) -> ModelPoint<T> {
        self.evaluate_with(t, y, true)
    }

    /// [`Self::evaluate`]; `outputs = false` skips what only observers read (the pressure
    /// angle itself: the forces use its sine and cosine), for the right-hand side. One copy
    /// for both uses: inlined into each, it cost the chip 5 KB of flash.
    #[inline(never)]
    fn evaluate_with(&self, t: T, y: &[T; N], outputs: bool) -> ModelPoint<T> {
        let d = &self.d;
        let mut p = ModelPoint {
            t,
            ..ModelPoint::default()
        };

        // --- gather the state ---
        let g = |i: usize| y.get(i).copied().unwrap_or(T::ZERO);
        let (tw2, tw1);
        match self.rot {
            0 => {
                p.theta_c = d.omega0 * t;
                p.omega_c = d.omega0;
                p.omega_cp = d.omega0;
                p.omega_m = d.omega0;
                tw2 = T::ZERO;
                tw1 = T::ZERO;
            }
            5 => {
                p.theta_c = g(0);
                tw2 = g(1);
                tw1 = g(2);
                p.omega_c = g(3);
                p.omega_cp = g(4);
                p.omega_m = d.omega0;
            }
            _ => {
                p.theta_c = g(0);
                tw2 = g(1);
                tw1 = g(2);
                p.omega_c = g(3);
                p.omega_cp = g(4);
                p.omega_m = g(5);
            }
        }
        p.theta_cp = p.theta_c + tw2;
        p.theta_m = p.theta_cp + tw1;
        for i in 0..TRANS_DOFS {
            let s = self.trans_slot[i];
            if s != NONE {
                p.pos[i] = g(self.rot + s as usize);
                p.vel[i] = g(self.rot + self.n_trans + s as usize);
            }
        }
        // p.pos holds the stored coordinates here: q_i = y_i - s(θ_c) for the follower chain.
        let [y1, x1, q2, x2, q3, x3, q4, q5] = p.pos;
        let [v1, vx1, _v2, _vx2, v3, vx3, v4, v5] = p.vel;

        // --- contact geometry at the current cam angle ---
        let lift = d.program.follower(p.theta_c);
        p.lift = lift;
        for (pos, rel) in p.pos.iter_mut().zip(RELATIVE_TO_LIFT) {
            if rel {
                *pos += lift.y;
            }
        }
        let y3 = p.pos[TransDof::CantileverY as usize];
        // Pressure angle: tan φ = (dy/dθ) / (R_a + y); cos and sin without the atan.
        let rpy = self.prime_radius + lift.y;
        let hyp = (rpy * rpy + lift.dy * lift.dy).sqrt();
        let (cos_phi, sin_phi) = if hyp > T::ZERO {
            (rpy / hyp, lift.dy / hyp)
        } else {
            (T::ONE, T::ZERO)
        };
        if outputs {
            p.pressure_angle = lift.dy.atan2(rpy);
        }
        p.surface_radius = d
            .geometry
            .surface_curvature_radius(lift.y, lift.dy, lift.d2y);
        // Hertz stiffness at the contact point (Eqs. V.9-V.11).
        let k_h = d
            .hertz
            .stiffness_fast(d.geometry.roller_radius, p.surface_radius);
        p.k_h = k_h;

        // Contact force and jump criterion (Eqs. V.19-V.20).
        let f_c = (k_h * (y1 - q2) + self.preload) * cos_phi;
        let (f_c, in_contact) = if f_c > T::ZERO {
            (f_c, true)
        } else {
            (T::ZERO, false)
        };
        p.contact_force = f_c;
        p.in_contact = in_contact;
        let f_v = f_c * cos_phi; // vertical component on the roller
        let f_h = f_c * sin_phi; // horizontal component

        // Slide-bearing friction (Eqs. V.15-V.16), each opposing its own mass's velocity.
        let side = f_h.abs();
        let f1 = coulomb_friction(d.mu, self.n1_factor * side, v4, d.friction_smoothing);
        let f2 = coulomb_friction(d.mu, self.n2_factor * side, v3, d.friction_smoothing);

        // --- translational system (Eqs. IV.2, IV.3) ---
        let k_f = d.k_f(y3);
        let c_f1 = d.c_f1_from(k_f);
        let k_vc = d.k_vc(y3);
        let m_f = d.m_f(y3);
        let m_fc = d.m_fc(y3);
        let f_load = k_f * (q5 - q4) + c_f1 * (v5 - v4);
        let f_vc = k_vc * (q4 - q3);
        let f_rb = d.k_rb * (q3 - q2);
        let mut a = [T::ZERO; TRANS_DOFS];
        // Load.
        a[7] = -f_load * self.inv_m_l;
        // Follower: d(M_f ẏ4)/dt = ρA ẏ3 ẏ4 + M_f ÿ4.
        a[6] = (f_load + f1 - f_vc - self.rho_a * v3 * v4) / m_f;
        // Cantilever: d(M_fc ẏ3)/dt = -ρA ẏ3² + M_fc ÿ3.
        a[4] = (f_vc - self.preload - d.k_rs * y3 + f2 - f_rb + self.rho_a * v3 * v3) / m_fc;
        // Roller.
        a[2] = (f_rb + f_v) * self.inv_m_r;
        // Cam and shaft.
        a[0] = (-f_v - d.k_vs * y1 - d.c_vs * v1) * self.inv_m_c;
        if self.dofs.contains(TransDof::CantileverX) {
            // d(M_fc ẋ3)/dt = -ρA ẏ3 ẋ3 + M_fc ẍ3 (NOTES, Eq. IV.3).
            a[5] = (d.k_rb * (x2 - x3) - d.k_hc(y3) * x3 + self.rho_a * v3 * vx3) / m_fc;
        }
        if self.dofs.contains(TransDof::RollerX) {
            a[3] = (-d.k_rb * (x2 - x3) - f_h) * self.inv_m_r;
        }
        if self.dofs.contains(TransDof::CamX) {
            a[1] = (f_h - d.k_hs * x1 - d.c_hs * vx1) * self.inv_m_c;
        }
        for (i, ai) in a.iter_mut().enumerate() {
            if self.trans_slot[i] == NONE {
                *ai = T::ZERO;
            }
        }
        p.acc = a;

        // --- rotational system (Eq. IV.1), T_o = F_c cos φ dy/dθ (NOTES) ---
        let t_o = f_v * lift.dy;
        p.torque_out = t_o;
        let shaft2 = d.c_s2 * (p.omega_cp - p.omega_c) + d.k_s2 * tw2;
        let shaft1 = d.c_s1 * (p.omega_m - p.omega_cp) + d.k_s1 * tw1;
        match self.rot {
            0 => {
                // The ideal drive holds the cam: it supplies the cam's drag and the output torque.
                p.torque_drive = d.c_cc * p.omega_c + t_o;
            }
            _ => {
                p.alpha_c = (shaft2 - d.c_cc * p.omega_c - t_o) * self.inv_i_c;
                p.alpha_cp = (shaft1 - shaft2) * self.inv_i_cp;
                if self.rot == 5 {
                    // Torque that holds the motor at ω0 (its acceleration is zero).
                    p.torque_drive = d.c_mb * p.omega_m + shaft1;
                } else {
                    p.torque_drive = d.drive.torque(p.omega_m);
                    p.alpha_m = (p.torque_drive - d.c_mb * p.omega_m - shaft1) * self.inv_i_m;
                }
            }
        }
        p
    }

    /// Writes dy/dt for the state (t, y) given the evaluated point.
    #[inline]
    fn derivative(&self, p: &ModelPoint<T>, dydt: &mut [T; N]) {
        let mut put = |i: usize, v: T| {
            if let Some(o) = dydt.get_mut(i) {
                *o = v;
            }
        };
        if self.rot >= 5 {
            put(0, p.omega_c);
            put(1, p.omega_cp - p.omega_c);
            put(2, p.omega_m - p.omega_cp);
            put(3, p.alpha_c);
            put(4, p.alpha_cp);
            if self.rot == 6 {
                put(5, p.alpha_m);
            }
        }
        let slots = self.trans_slot.iter().zip(RELATIVE_TO_LIFT);
        for ((&s, relative), (v, a)) in slots.zip(p.vel.iter().zip(p.acc.iter())) {
            if s != NONE {
                // dq/dt = ẏ - s'(θ_c) θ̇_c for the displacements stored relative to the lift.
                let rel = if relative {
                    p.lift.dy * p.omega_c
                } else {
                    T::ZERO
                };
                put(self.rot + s as usize, *v - rel);
                put(self.rot + self.n_trans + s as usize, *a);
            }
        }
    }
}

impl<T: Real, const N: usize> OdeSystem<T, N> for CamModel<T, N> {
    #[inline]
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]) {
        let p = self.evaluate_with(t, y, false);
        self.derivative(&p, dydt);
    }
}

/// The full model: regulated drive, all eleven DOFs (22 states).
pub type FullModel<T> = CamModel<T, 22>;
/// Regulated drive, vertical motion only (6 + 2·5 = 16 states).
pub type VerticalModel<T> = CamModel<T, 16>;
/// Constant cam speed, vertical motion only (10 states): the cheapest dynamic scene.
pub type RigidDriveVerticalModel<T> = CamModel<T, 10>;
