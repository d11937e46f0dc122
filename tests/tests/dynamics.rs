//! The eleven-DOF model against numbers derived independently: statics, the printed
//! model bit for bit, the rigid limit, an energy balance with and without the contact
//! damper, the decay of the roller's ring, contact at 800 rpm, a quasi-static jump
//! estimate and tolerance convergence.

use std::ops::ControlFlow;

use camsim_core::{
    bearing_normal_forces, contact_force, coulomb_friction, damped_contact_force, rad_per_s_to_rpm,
    rpm_to_rad_per_s, simulate, CamModel, ConstCamVertical, ConstCamVerticalModel, Design,
    DriveLaw, England, EnglandConfig, MotionLaw, OdeSystem, Real, RegulatedFull,
    RegulatedFullModel, RegulatedVerticalModel, ResponseStats, Sample, Scene, SolverSettings,
    SolverStats, Start, StateMut, StateVar, StepRule, Tolerance, TransDof,
};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// The reference design without any damping (the contact's too) or friction, driven at
/// constant cam speed.
fn conservative(rpm: f64) -> Design<f64> {
    let mut d = Design::reference();
    d.set_speed_rpm(rpm).unwrap();
    d.drive = DriveLaw::ConstantCamSpeed;
    d.c_vs = 0.0;
    d.c_hs = 0.0;
    d.c_cc = 0.0;
    d.damping_ratio_f1 = 0.0;
    d.contact_damping_ratio = 0.0;
    d.roller_bearing_damping_ratio = 0.0;
    d.mu = 0.0;
    d
}

// ---------------------------------------------------------------- statics

/// With the cam at rest on the base circle the chain balances. By hand (vertical
/// equations of IV.2 with every acceleration and velocity zero, φ = 0, y = 0):
/// cam: F_c = -K_vs y1; roller: K_rb (y3 - y2) = -F_c; load and follower: y5 = y4 = y3;
/// cantilever: F_c = F_p + K_rs y3; contact (V.19): F_c = F_p + K_h (y1 - y2).
/// Eliminating: F_c = F_p / (1 + K_rs K_h (1/K_vs + 1/K_rb) / (K_rs + K_h)).
#[test]
fn statics_contact_force_equals_the_preload() {
    let d = Design::<f64>::reference();
    let m = RegulatedFullModel::new(d.clone()).unwrap();
    // V.18 by hand for the reference (K_rs = 100 lb/in, δ_rs = 0.5 in): K_t = series(K_rb,
    // K_h, K_vs), F_p = K_t K_rs δ/(K_t + K_rs).
    let k_h = d.hertz.stiffness(0.375, 1.5).unwrap();
    let k_t = 1.0 / (1.0 / 1.5e6 + 1.0 / k_h + 1.0 / 1.48e6);
    let f_p = k_t * 100.0 * 0.5 / (k_t + 100.0);
    assert!(
        (m.preload() - f_p).abs() < 1e-9 * f_p,
        "preload {} vs {}",
        m.preload(),
        f_p
    );
    // K_t = 667853.7 lb/in: F_p = 50 K_t / (K_t + 100) = 49.9925 lb.
    assert!((f_p - 49.9925).abs() < 1e-4, "{f_p}");

    let expect = f_p / (1.0 + 100.0 * k_h * (1.0 / 1.48e6 + 1.0 / 1.5e6) / (100.0 + k_h));
    // The cam at rest: a slow speed (the slowest plausible, 1 rpm), so the cam stays on
    // the base circle.
    let mut slow = d.clone();
    slow.set_speed_rpm(1.0).unwrap(); // the slowest plausible speed (key::SPEED_RPM)
    let m = RegulatedFullModel::new(slow).unwrap();
    let y = m.static_state();
    let p = m.evaluate(0.0, &y);
    assert!(p.in_contact);
    assert!(
        (p.contact_force - expect).abs() < 1e-9 * expect,
        "{} vs {}",
        p.contact_force,
        expect
    );
    // It is the preload of V.18 to within the chain's own compliance
    // (K_rs (1/K_vs + 1/K_rb) ~ 1.3e-4).
    let rel = (p.contact_force - f_p).abs() / f_p;
    assert!(
        rel < 2e-4 && rel > 1e-4,
        "relative difference from F_p: {rel}"
    );
    // And it is an equilibrium: the right-hand side vanishes but for the cam angle, which
    // turns at ω0. By name through the scene's layout: the displacements' rates are the
    // (zero) velocities, the velocities' rates the model's accelerations, and those are
    // rounding noise against F_p / M_r (2.3e5 in/s²; seen: 2e-7 in/s²).
    let mut dy = [0.0; 22];
    m.rhs(0.0, &y, &mut dy);
    let rate = m.state(&dy);
    let (w0, m_r) = (m.design().omega0, m.design().m_r);
    assert_eq!(rate.cam_angle(), Some(w0));
    assert_eq!(rate.coupling_cam_twist(), Some(0.0));
    assert_eq!(rate.motor_coupling_twist(), Some(0.0));
    for alpha in [rate.cam_speed(), rate.coupling_speed(), rate.motor_speed()] {
        assert!(alpha.unwrap().abs() < 1e-12, "{alpha:?}");
    }
    for dof in TransDof::ALL {
        assert_eq!(rate.position(dof), Some(0.0), "{dof:?}");
        let a = rate.velocity(dof).unwrap();
        assert_eq!(a, p.acceleration(dof), "{dof:?}");
        assert!(a.abs() < 1e-10 * f_p / m_r, "acceleration of {dof:?}: {a}");
    }
    // Held for a while (the cam does not move), the contact force stays there.
    let mut stats = ResponseStats::<f64, 2, 8, 8>::new(m.design().omega0);
    let mut y = m.static_state();
    let mut solver = England::new(EnglandConfig {
        tol: Tolerance::scalar(1e-10, 1e-14),
        h_init: 1e-7,
        h_min: 1e-16,
        h_max: 1e-4,
        max_steps: 1_000_000,
    })
    .unwrap();
    let mut fmin = f64::INFINITY;
    let mut fmax = 0.0f64;
    solver
        .integrate(&m, 0.0, &mut y, 0.02, |t, y| {
            let s = m.sample(t, y, false);
            fmin = fmin.min(s.point.contact_force);
            fmax = fmax.max(s.point.contact_force);
            let _ = camsim_core::Observer::observe(&mut stats, &s);
            ControlFlow::Continue(())
        })
        .unwrap();
    assert!(
        (fmax - expect).abs() < 1e-6 * expect && (fmin - expect).abs() < 1e-6 * expect,
        "{fmin}..{fmax}"
    );
    // The statistics saw the same samples: the extremes, no jump, the whole 0.02 s in the
    // first period (the dwell) and a time average inside the extremes, at the static force.
    let st = stats.period(1, 0).unwrap();
    assert_eq!((st.force_min, st.force_max, st.jump), (fmin, fmax, false));
    assert!((st.duration - 0.02).abs() < 1e-12, "{}", st.duration);
    let avg = st.force_avg();
    assert!(fmin <= avg && avg <= fmax, "{fmin} <= {avg} <= {fmax}");
    assert!((avg - expect).abs() < 1e-9 * expect, "{avg} vs {expect}");
    assert_eq!(stats.period(1, 1).map(|p| p.samples), Some(0));
}

// ---------------------------------------------------------------- the printed model

/// FNV-1a over the bits of every sample's time, displacements, velocities and contact
/// force: one number that changes if any bit of any sample does.
struct Fingerprint {
    hash: u64,
    samples: u64,
}

impl Fingerprint {
    fn new() -> Self {
        Self {
            hash: 0xcbf2_9ce4_8422_2325,
            samples: 0,
        }
    }
    fn eat(&mut self, bits: u64) {
        for b in bits.to_le_bytes() {
            self.hash ^= u64::from(b);
            self.hash = self.hash.wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn sample<T: Real>(&mut self, s: &Sample<T>) -> ControlFlow<()> {
        let p = &s.point;
        self.eat(p.t.to_f64().to_bits());
        for v in p.pos.iter().chain(&p.vel) {
            self.eat(v.to_f64().to_bits());
        }
        self.eat(p.contact_force.to_f64().to_bits());
        self.samples += 1;
        ControlFlow::Continue(())
    }
}

/// VI.1's listed spring (60 lb/in, with the 0.151 lb mass the model used for it) and no
/// damping at the roller: the design the model ran before that damping existed.
fn listed_printed<T: Real>() -> Design<T> {
    let mut d = Design::<T>::reference();
    d.k_rs = T::from_f64(60.0);
    d.m_spring = T::from_f64(0.151 / camsim_core::GRAVITY_IN_PER_S2);
    d.contact_damping_ratio = T::ZERO;
    d.roller_bearing_damping_ratio = T::ZERO;
    d
}

/// One revolution of the full f64 model from the thesis start: the solver's counts and
/// the fingerprint of every sample.
fn full_run(d: Design<f64>) -> (SolverStats, Fingerprint) {
    let m = RegulatedFullModel::<f64>::new(d).unwrap();
    let mut fp = Fingerprint::new();
    let mut obs = |s: &Sample<f64>| fp.sample(s);
    // England's method under the thesis's rule: the counts and fingerprints were recorded
    // before the run could choose its method and step control.
    let s = SolverSettings {
        step_control: StepRule::Thesis,
        method: camsim_core::Method::England,
        ..SolverSettings::reference()
    };
    let st = simulate(&m, &s, 1, &mut obs).unwrap();
    (st, fp)
}

/// ξ_h = ξ_rb = 0 is the printed model bit for bit: one revolution of the full f64 model
/// from the thesis start (its impact rings and jumps, so every branch of the contact law
/// is taken, and the horizontal motion is excited) and of the chip's f32 vertical model
/// from the static start give the solver counts and the fingerprint of every sample
/// recorded with the code before the damping at the roller (commit 12f8cc7; libm makes
/// them the same on every platform).
#[test]
fn zero_damping_at_the_roller_is_the_printed_model_bit_for_bit() {
    let (st, fp) = full_run(listed_printed());
    assert_eq!(
        (st.accepted, st.rejected, st.rhs_evals, fp.samples),
        (52412, 9517, 538_327, 104_823)
    );
    assert_eq!(fp.hash, 0xb9fb_b46f_8bf8_d565);

    let m = RegulatedVerticalModel::<f32>::new(listed_printed()).unwrap();
    let mut s = SolverSettings::<f32>::reference();
    s.rtol = 1e-3;
    s.start = Start::Static;
    s.step_control = StepRule::Thesis;
    s.method = camsim_core::Method::England;
    let mut fp = Fingerprint::new();
    let st = simulate(&m, &s, 1, &mut |s: &Sample<f32>| fp.sample(s)).unwrap();
    assert_eq!(
        (st.accepted, st.rejected, st.rhs_evals, fp.samples),
        (6513, 2081, 73184, 13026)
    );
    assert_eq!(fp.hash, 0xb6cd_87ed_ce43_3e9c);

    // Either damper alone changes the run (and so can fail this test).
    let mut contact = listed_printed::<f64>();
    contact.contact_damping_ratio = 0.05;
    assert_ne!(full_run(contact).1.hash, 0xb9fb_b46f_8bf8_d565);
    let mut bearing = listed_printed::<f64>();
    bearing.roller_bearing_damping_ratio = 0.05;
    assert_ne!(full_run(bearing).1.hash, 0xb9fb_b46f_8bf8_d565);
}

// ---------------------------------------------------------------- rigid limit

/// The reference at 300 rpm on an ideal constant-speed drive, without friction, with
/// every stiffness but the return spring's scaled by `scale` and every damper at its
/// damping ratio: C_f1 and C_h follow their ratios (V.13) by themselves, the listed
/// C_vs = C_hs are scaled by sqrt(scale) to keep theirs.
fn stiffened(scale: f64) -> Design<f64> {
    let mut d = Design::reference();
    d.set_speed_rpm(300.0).unwrap();
    d.drive = DriveLaw::ConstantCamSpeed;
    d.mu = 0.0;
    d.c_vs *= scale.sqrt();
    d.c_hs *= scale.sqrt();
    d.k_rb *= scale;
    d.k_vs *= scale;
    d.k_hs *= scale;
    d.youngs *= scale; // K_f, K_vc, K_hc
    d.hertz.youngs_1 *= scale; // K_h ∝ E
    d.hertz.youngs_2 *= scale;
    d
}

fn rev2_acc_rms_sum<S: Scene, const N: usize>(
    d: Design<f64>,
    settings: &SolverSettings<f64>,
) -> f64 {
    let m = CamModel::<f64, S, N>::new(d).unwrap();
    let mut stats = ResponseStats::<f64, 2, 8, 8>::new(m.design().omega0);
    simulate(&m, settings, 2, &mut stats).unwrap();
    stats.acceleration_rms_sum(2)
}

/// Very stiff elements and an ideal constant-speed drive: the follower tracks the
/// theoretical law, and the RMS acceleration deviation falls as the stiffness rises: the
/// quasi-static deflection m a / k as 1/k, the vibration it excites (amplitude in
/// acceleration about jerk / ω) at least as 1/sqrt(k), so by at least sqrt(10) per
/// decade of stiffness (seen: 5.8). The damping ratios stay fixed: without damping the
/// residual vibration of each mode after the rise depends on where its frequency falls in
/// the law's spectrum, and the RMS need not fall from one stiffness to the next (seen:
/// the change of the spring's mass alone moved r100/r10 from 0.09 to 0.97).
#[test]
fn rigid_limit_tracks_the_theoretical_law() {
    let mut s = SolverSettings::reference();
    s.rtol = 1e-7;
    s.start = Start::Static;
    const N: usize = ConstCamVertical::N;
    let r1 = rev2_acc_rms_sum::<ConstCamVertical, N>(stiffened(1.0), &s);
    let r10 = rev2_acc_rms_sum::<ConstCamVertical, N>(stiffened(10.0), &s);
    let r100 = rev2_acc_rms_sum::<ConstCamVertical, N>(stiffened(100.0), &s);
    // Theoretical peak acceleration of the rise at 300 rpm: 4.888 h (ω/β)² = 1056 in/s².
    let w = rpm_to_rad_per_s(300.0);
    let peak = 4.888124 * 1.5 * (w / (150f64.to_radians())).powi(2);
    assert!(r1 < 0.2 * peak, "flexible: {r1} vs peak {peak}");
    let decade = 10f64.sqrt();
    assert!(r10 < r1 / decade, "x10 stiffer: {r10} vs {r1}");
    assert!(r100 < r10 / decade, "x100 stiffer: {r100} vs {r10}");
}

// ---------------------------------------------------------------- energy

/// The model plus extra states: the integral of the power that enters the mechanical
/// energy E (kinetic + elastic + spring + contact), that of the drive's share alone and
/// those of the contact damper's and the roller bearing damper's dissipation. By hand,
/// from the vertical equations with no friction, no damping but the contact's and the
/// roller bearing's, and the constant-speed cam:
/// dE/dt = T_o ω0 (the drive's work through the lift)
///       + ½ κ' ω0 δ² + κ δ F_p (1/K_h)' ω0 (the contact stiffness κ = K_h cos²φ and the
///         preload compression F_p/K_h change with the cam angle)
///       + ½ ρA ẏ3 (ẏ3² - ẏ4²) (rod mass passes from the cantilever to the follower)
///       + ½ K_vc' ẏ3 (y4 - y3)² + ½ K_f' ẏ3 (y5 - y4)² (stiffnesses depend on y3)
///       - C_h (δ̇ cos φ)² (the contact damper, while it is not clamped)
///       - C_rb (ẏ3 - ẏ2)² (the roller bearing's damper),
/// where δ = y + y1 - y2 + F_p/K_h (contact only while δ > 0). The damper's share of the
/// vertical contact force, C_h δ̇ cos²φ, does work f (ẏ2 - ẏ1) on roller and cam and
/// takes f y' ω0 from the drive (inside T_o): the net is -f δ̇ with δ̇ = y' ω0 + ẏ1 - ẏ2,
/// that is C_h times the normal approach rate δ̇ cos φ squared.
struct Powered<'a>(&'a ConstCamVerticalModel<f64>);

/// The model's 10 states, the work of all the power terms, that of the drive's alone and
/// the two dampers' dissipation.
const NE: usize = 14;

/// Power terms at one instant, lb·in/s.
struct Power {
    drive: f64,
    total: f64,
    contact: f64,
    bearing: f64,
}

impl Powered<'_> {
    fn kappa_and_inv_kh(&self, t: f64, y: &[f64; 10]) -> (f64, f64) {
        let p = self.0.evaluate(t, y);
        (p.k_h * p.pressure_angle.cos().powi(2), 1.0 / p.k_h)
    }
    fn power(&self, t: f64, y: &[f64; 10]) -> Power {
        let m = self.0;
        let d = m.design();
        let p = m.evaluate(t, y);
        let w = d.omega0;
        let [y1, _, y2, _, y3, _, y4, y5] = p.pos;
        let [v1, _, v2, _, v3, _, v4, _] = p.vel;
        let drive = p.torque_out * w;
        let mut power = drive;
        let mut contact = 0.0;
        let kh = p.k_h;
        let delta = p.lift.y + y1 - y2 + m.preload() / kh;
        if delta > 0.0 {
            let dt = 1e-7 / w; // central difference in cam angle (1e-7 rad)
            let (k_a, i_a) = self.kappa_and_inv_kh(t - dt, y);
            let (k_b, i_b) = self.kappa_and_inv_kh(t + dt, y);
            let kappa = kh * p.pressure_angle.cos().powi(2);
            power += 0.5 * (k_b - k_a) / (2.0 * dt) * delta * delta;
            power += kappa * delta * m.preload() * (i_b - i_a) / (2.0 * dt);
            if p.contact_force > 0.0 {
                let c_h = 2.0 * d.contact_damping_ratio * (kh * d.m_r).sqrt();
                let normal_rate = (p.lift.dy * w + v1 - v2) * p.pressure_angle.cos();
                contact = c_h * normal_rate * normal_rate;
            }
        }
        let ea = d.youngs * d.area;
        power += 0.5 * d.rho * d.area * v3 * (v3 * v3 - v4 * v4);
        power += 0.5 * ea / (d.e2 - y3).powi(2) * v3 * (y4 - y3).powi(2);
        power += 0.5 * (-ea / (d.e1 + y3).powi(2)) * v3 * (y5 - y4).powi(2);
        let c_rb = 2.0 * d.roller_bearing_damping_ratio * (d.k_rb * d.m_r).sqrt();
        Power {
            drive,
            total: power,
            contact,
            bearing: c_rb * (v3 - v2).powi(2),
        }
    }
    fn energy(&self, t: f64, y: &[f64; 10]) -> f64 {
        let m = self.0;
        let d = m.design();
        let p = m.evaluate(t, y);
        let [y1, _, y2, _, y3, _, y4, y5] = p.pos;
        let [v1, _, v2, _, v3, _, v4, v5] = p.vel;
        let kinetic = 0.5
            * (d.m_c * v1 * v1
                + d.m_r * v2 * v2
                + d.m_fc(y3) * v3 * v3
                + d.m_f(y3) * v4 * v4
                + d.m_l * v5 * v5);
        let elastic = 0.5 * d.k_vs * y1 * y1
            + 0.5 * d.k_rb * (y3 - y2).powi(2)
            + 0.5 * d.k_vc(y3) * (y4 - y3).powi(2)
            + 0.5 * d.k_f(y3) * (y5 - y4).powi(2)
            + m.preload() * y3
            + 0.5 * d.k_rs * y3 * y3;
        let delta = (p.lift.y + y1 - y2 + m.preload() / p.k_h).max(0.0);
        let contact = 0.5 * p.k_h * p.pressure_angle.cos().powi(2) * delta * delta;
        kinetic + elastic + contact
    }
}

impl OdeSystem<f64, NE> for Powered<'_> {
    fn rhs(&self, t: f64, y: &[f64; NE], dydt: &mut [f64; NE]) {
        let mut s = [0.0; 10];
        s.copy_from_slice(&y[..10]);
        let mut ds = [0.0; 10];
        self.0.rhs(t, &s, &mut ds);
        dydt[..10].copy_from_slice(&ds);
        let p = self.power(t, &s);
        dydt[10] = p.total - p.contact - p.bearing;
        dydt[11] = p.drive;
        dydt[12] = p.contact;
        dydt[13] = p.bearing;
    }
}

/// The energy balance over one revolution from `y0`.
struct Balance {
    /// Change of E, lb·in.
    d_e: f64,
    /// ∫ (every power term less the dissipation) dt.
    work: f64,
    /// The drive's share ∫ T_o ω0 dt.
    drive: f64,
    /// ∫ C_h (δ̇ cos φ)² dt.
    dissipated: f64,
    /// ∫ C_rb (ẏ3 - ẏ2)² dt.
    bearing: f64,
    /// ∫ |T_o ω0| dt: the gross work.
    gross: f64,
    /// Smallest contact force sampled, lb.
    force_min: f64,
}

fn balance_over_a_revolution(m: &ConstCamVerticalModel<f64>, y0: [f64; 10]) -> Balance {
    let sys = Powered(m);
    let mut y = [0.0; NE];
    y[..10].copy_from_slice(&y0);
    let t_end = TWO_PI / m.design().omega0;
    let mut solver = England::new(EnglandConfig {
        tol: Tolerance::scalar(1e-9, 1e-12),
        h_init: 1e-8,
        h_min: 1e-15,
        h_max: t_end / 4000.0,
        max_steps: 5_000_000,
    })
    .unwrap();
    let mut gross = 0.0;
    let mut force_min = f64::INFINITY;
    let mut last = (0.0, 0.0);
    solver
        .integrate(&sys, 0.0, &mut y, t_end, |t, yy| {
            let mut s = [0.0; 10];
            s.copy_from_slice(&yy[..10]);
            let p = m.evaluate(t, &s);
            let power = p.torque_out * m.design().omega0;
            gross += 0.5 * (power.abs() + last.1) * (t - last.0);
            last = (t, power.abs());
            force_min = force_min.min(p.contact_force);
            ControlFlow::Continue(())
        })
        .unwrap();
    let mut end = [0.0; 10];
    end.copy_from_slice(&y[..10]);
    Balance {
        d_e: sys.energy(t_end, &end) - sys.energy(0.0, &y0),
        work: y[10],
        drive: y[11],
        dissipated: y[12],
        bearing: y[13],
        gross,
        force_min,
    }
}

/// With damping and friction off and a constant-speed drive, the work done on the
/// follower train equals the change of its stored and kinetic energy over a revolution.
#[test]
fn energy_balance_over_a_revolution() {
    let m = ConstCamVerticalModel::new(conservative(500.0)).unwrap();
    let b = balance_over_a_revolution(&m, m.initial_state());
    let (d_e, work, abs_work) = (b.d_e, b.work, b.gross);
    assert_eq!((b.dissipated, b.bearing), (0.0, 0.0));
    // The lift does real work (the spring is compressed and released): far from zero.
    assert!(abs_work > 50.0, "|work| {abs_work}");
    // Over the revolution the lift's work nearly cancels (the spring is compressed and
    // released): ΔE is about 5e-7 lb·in against 375 lb·in of gross work. The balance
    // closes to the integration's relative tolerance (1e-9) of the gross work (seen:
    // 2.7e-10).
    let err = (d_e - work).abs();
    assert!(
        err < 1e-9 * abs_work,
        "ΔE {d_e} vs work {work} (|work| {abs_work}), error {err}"
    );
    // The drive's work through the lift dominates the gross work; the side terms are small
    // corrections (seen: 1e-7 of it) but the balance needs them: without them it would
    // miss by 350 times its error (seen: side 3.6e-5 lb·in, net drive work -3.5e-5).
    let side = work - b.drive;
    assert!(
        side.abs() < 1e-6 * abs_work,
        "side terms {side} vs {abs_work}"
    );
    assert!(side.abs() > 100.0 * err, "side terms {side} vs error {err}");
}

/// The contact damper (ξ_h = 0.05, every other damper and friction off) removes exactly
/// ∫ C_h (δ̇ cos φ)² dt: the same balance closes with that dissipation. From static
/// equilibrium with the roller kicked at 1.5 in/s, its ring (about K_h · 1.5 / ω =
/// 39 lb, ω = 2.5e5 rad/s) stays below the 50 lb static force, so the contact never
/// separates and the damper is never clamped (checked: the smallest force).
#[test]
fn contact_damper_dissipates_its_integral() {
    let mut d = conservative(500.0);
    d.contact_damping_ratio = 0.05;
    let m = ConstCamVerticalModel::new(d).unwrap();
    let mut y0 = m.static_state();
    StateMut::<f64, ConstCamVertical, { ConstCamVertical::N }>::new(&mut y0)
        .set(StateVar::Velocity(TransDof::RollerY), 1.5);
    let b = balance_over_a_revolution(&m, y0);
    assert_eq!(b.bearing, 0.0);
    assert!(b.force_min > 5.0, "smallest force {}", b.force_min);
    // The kick's energy ½ M_r v² = 1.46e-4 lb·in goes almost all into the roller's mode,
    // which the damper empties within a millisecond; a little goes into modes this
    // design leaves undamped, and the damper takes its share of the vibration the program
    // excites (seen: 0.9997 of the kick in all).
    let kick = 0.5 * m.design().m_r * 1.5 * 1.5;
    assert!(
        b.dissipated > 0.9 * kick && b.dissipated < 1.1 * kick,
        "dissipated {} vs kick {kick}",
        b.dissipated
    );
    let err = (b.d_e - b.work).abs();
    assert!(
        err < 1e-9 * b.gross,
        "ΔE {} vs work {} less dissipation {} (gross {}), error {err}",
        b.d_e,
        b.work + b.dissipated,
        b.dissipated,
        b.gross
    );
    // The dissipation is what closes the balance: without it the error would be far
    // larger than the balance's tolerance (seen: 6e6 times).
    assert!(b.dissipated > 100.0 * err, "{} vs {err}", b.dissipated);
    // Without the kick the damper takes only the vibration the program excites, on the
    // flanks where φ ≠ 0, so the cos φ of the normal rate is checked too (seen:
    // 2.8e-7 lb·in, 1e4 times the balance's error).
    let b = balance_over_a_revolution(&m, m.static_state());
    let err = (b.d_e - b.work).abs();
    assert!(err < 1e-9 * b.gross, "no kick: error {err}");
    assert!(
        b.dissipated > 1000.0 * err && b.dissipated < 0.01 * kick,
        "no kick: dissipated {} vs error {err}",
        b.dissipated
    );
}

/// With the roller bearing's damper too (ξ_rb = 0.05) the balance closes with both
/// integrals. Kicked in the shape of the roller's mode ([`roller_mode`]), the whole kick's
/// energy is dissipated, split between the two dampers in proportion to C_h (φ2 - φ1)²
/// and C_rb (φ2 - φ3)² (about √K_h : √K_rb: the cam and the cantilever barely move).
#[test]
fn roller_bearing_damper_dissipates_its_integral() {
    let mut d = conservative(500.0);
    d.contact_damping_ratio = 0.05;
    d.roller_bearing_damping_ratio = 0.05;
    let m = ConstCamVerticalModel::new(d.clone()).unwrap();
    // The kick in the shape of the roller's mode, 1.5 in/s at the roller.
    let (_, _, p) = roller_mode(&d);
    let mut y0 = m.static_state();
    let mut s = StateMut::<f64, ConstCamVertical, { ConstCamVertical::N }>::new(&mut y0);
    let dofs = [
        TransDof::CamY,
        TransDof::RollerY,
        TransDof::CantileverY,
        TransDof::Follower,
        TransDof::Load,
    ];
    let mut kick = 0.0;
    let masses = [d.m_c, d.m_r, d.m_fc(0.0), d.m_f(0.0), d.m_l];
    for ((dof, pi), mi) in dofs.into_iter().zip(p).zip(masses) {
        s.set(StateVar::Velocity(dof), 1.5 * pi);
        kick += 0.5 * mi * (1.5 * pi).powi(2);
    }
    let b = balance_over_a_revolution(&m, y0);
    assert!(b.force_min > 5.0, "smallest force {}", b.force_min);
    let err = (b.d_e - b.work).abs();
    assert!(
        err < 1e-9 * b.gross,
        "ΔE {} vs work {} (gross {}), error {err}",
        b.d_e,
        b.work,
        b.gross
    );
    assert!(b.dissipated > 100.0 * err && b.bearing > 100.0 * err);
    // Less what the dampers take from the program's own vibration (the same run without
    // the kick: the ring and that vibration, far apart in frequency, add), all of the
    // kick's energy is dissipated (seen: to 3e-6 of it; the split to 1e-4).
    let quiet = balance_over_a_revolution(&m, m.static_state());
    assert!((quiet.d_e - quiet.work).abs() < 1e-9 * quiet.gross);
    let contact = b.dissipated - quiet.dissipated;
    let bearing = b.bearing - quiet.bearing;
    assert!(
        ((contact + bearing) / kick - 1.0).abs() < 1e-3,
        "{contact} + {bearing} vs {kick}"
    );
    let k_h = d.k_h_base().unwrap();
    let split = d.k_rb.sqrt() * (p[1] - p[2]).powi(2) / (k_h.sqrt() * (p[1] - p[0]).powi(2));
    assert!(
        (bearing / contact / split - 1.0).abs() < 1e-3,
        "bearing / contact {} vs {split}",
        bearing / contact
    );
}

// ---------------------------------------------------------------- contact damping

/// The free ring at rest on the base circle after a kick that gives y1..y5 the
/// velocities `v` (in/s): (time, contact force) samples over `duration` seconds.
fn ring(d: Design<f64>, v: [f64; 5], duration: f64) -> Vec<(f64, f64)> {
    let m = ConstCamVerticalModel::new(d).unwrap();
    let mut y = m.static_state();
    let mut s = StateMut::<f64, ConstCamVertical, { ConstCamVertical::N }>::new(&mut y);
    let dofs = [
        TransDof::CamY,
        TransDof::RollerY,
        TransDof::CantileverY,
        TransDof::Follower,
        TransDof::Load,
    ];
    for (dof, vi) in dofs.into_iter().zip(v) {
        s.set(StateVar::Velocity(dof), vi);
    }
    let mut solver = England::new(EnglandConfig {
        tol: Tolerance::scalar(1e-10, 1e-14),
        h_init: 1e-9,
        h_min: 1e-16,
        h_max: 2e-7,
        max_steps: 1_000_000,
    })
    .unwrap();
    let mut out = Vec::new();
    solver
        .integrate(&m, 0.0, &mut y, duration, |t, y| {
            out.push((t, m.evaluate(t, y).contact_force));
            ControlFlow::Continue(())
        })
        .unwrap();
    out
}

/// Half the swing between each local maximum of the force and the minimum that follows:
/// (mid time, amplitude).
fn swings(f: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut ext = Vec::new();
    for w in f.windows(3) {
        let (a, b, c) = (w[0].1, w[1].1, w[2].1);
        if (b > a && b >= c) || (b < a && b <= c) {
            ext.push(w[1]);
        }
    }
    ext.windows(2)
        .filter(|e| e[0].1 > e[1].1)
        .map(|e| (0.5 * (e[0].0 + e[1].0), 0.5 * (e[0].1 - e[1].1)))
        .collect()
}

/// Least-squares slope of ln(amplitude) against time.
fn log_slope(a: &[(f64, f64)]) -> f64 {
    let n = a.len() as f64;
    let (st, sl) = a
        .iter()
        .fold((0.0, 0.0), |(st, sl), (t, x)| (st + t, sl + x.ln()));
    let (mt, ml) = (st / n, sl / n);
    let (num, den) = a.iter().fold((0.0, 0.0), |(num, den), (t, x)| {
        (num + (t - mt) * (x.ln() - ml), den + (t - mt) * (t - mt))
    });
    num / den
}

/// The roller's mode of the vertical chain linearised at rest on the base circle (φ = 0,
/// no friction): M = diag(M_c, M_r, M_fc, M_f, M_l); springs K_vs (y1 to the frame), K_h
/// (y1-y2), K_rb (y2-y3), K_rs (y3 to the frame), K_vc (y3-y4), K_f (y4-y5); dampers C_vs
/// (y1), C_h = 2 ξ_h sqrt(K_h M_r) (y1-y2), C_rb = 2 ξ_rb sqrt(K_rb M_r) (y2-y3), C_f1 =
/// 2 ξ sqrt(K_f M_l) (y4-y5). The roller's mode is the highest of K φ = ω² M φ; for light
/// damping it decays as exp(-σ t) with σ = ζω = ½ φᵀCφ (φ M-normalised; first order in
/// the damping, the error is O(ζ²), 0.2 %). Returns ω, σ and the mode's shape scaled to
/// 1 at the roller.
fn roller_mode(d: &Design<f64>) -> (f64, f64, [f64; 5]) {
    let k_h = d.k_h_base().unwrap();
    let y3 = {
        let m = ConstCamVerticalModel::new(d.clone()).unwrap();
        m.evaluate(0.0, &m.static_state())
            .position(TransDof::CantileverY)
    };
    let masses = [d.m_c, d.m_r, d.m_fc(y3), d.m_f(y3), d.m_l];
    let mut mm = [[0.0; 5]; 5];
    for (i, mi) in masses.iter().enumerate() {
        mm[i][i] = *mi;
    }
    // Element matrices: a spring or damper between i and j (None: the frame).
    fn add(a: &mut [[f64; 5]; 5], i: usize, j: Option<usize>, k: f64) {
        a[i][i] += k;
        if let Some(j) = j {
            a[j][j] += k;
            a[i][j] -= k;
            a[j][i] -= k;
        }
    }
    let v13 = |ratio: f64, k: f64, m: f64| 2.0 * ratio * (k * m).sqrt();
    let mut kk = [[0.0; 5]; 5];
    add(&mut kk, 0, None, d.k_vs);
    add(&mut kk, 0, Some(1), k_h);
    add(&mut kk, 1, Some(2), d.k_rb);
    add(&mut kk, 2, None, d.k_rs);
    add(&mut kk, 2, Some(3), d.k_vc(y3));
    add(&mut kk, 3, Some(4), d.k_f(y3));
    let mut cc = [[0.0; 5]; 5];
    add(&mut cc, 0, None, d.c_vs);
    add(
        &mut cc,
        0,
        Some(1),
        v13(d.contact_damping_ratio, k_h, d.m_r),
    );
    add(
        &mut cc,
        1,
        Some(2),
        v13(d.roller_bearing_damping_ratio, d.k_rb, d.m_r),
    );
    add(
        &mut cc,
        3,
        Some(4),
        v13(d.damping_ratio_f1, d.k_f(y3), d.m_l),
    );
    let (lambda, phi) = camsim_core::generalized_eigen(&kk, &mm).unwrap();
    let p: [f64; 5] = core::array::from_fn(|i| phi[i][4]);
    let mut ptcp = 0.0;
    for i in 0..5 {
        for j in 0..5 {
            ptcp += p[i] * cc[i][j] * p[j];
        }
    }
    (lambda[4].sqrt(), 0.5 * ptcp, p.map(|x| x / p[1]))
}

/// The contact damping (and the roller bearing's) makes the roller's free ring decay at
/// the rate the linearised chain predicts ([`roller_mode`]). For the roller alone
/// between a fixed cam and cantilever ω = sqrt((K_h + K_rb) / M_r) = 2.47e5 rad/s and
/// σ = (C_h + C_rb) / (2 M_r) = ξ_h sqrt(K_h / M_r) + ξ_rb sqrt(K_rb / M_r): 1.11e4 1/s
/// from the contact, 0.54e4 from the bearing; the heavier neighbours move both by a few
/// percent. The contact force's swing after a kick at rest in the shape of the mode,
/// 1 in/s at the roller (K_h v / ω = 26 lb, below the 50 lb static force), falls as
/// exp(-σ t) over 200 µs (8 periods; seen: the rate within 1e-4 of σ): with the contact
/// damper alone, and with both. Without either the ring keeps its amplitude: that is the
/// printed model.
#[test]
fn contact_damping_decays_the_roller_ring() {
    let mut d = Design::<f64>::reference();
    assert_eq!(
        (
            d.contact_damping_ratio,
            d.roller_bearing_damping_ratio,
            d.damping_ratio_f1
        ),
        (0.05, 0.05, 0.03)
    );
    d.set_speed_rpm(1.0).unwrap(); // the slowest plausible speed: the cam stays on the base circle
    d.drive = DriveLaw::ConstantCamSpeed;
    let k_h = d.k_h_base().unwrap();
    let duration = 2e-4;
    let mut contact_only = d.clone();
    contact_only.roller_bearing_damping_ratio = 0.0;
    for (case, d) in [
        ("contact", contact_only),
        ("contact and bearing", d.clone()),
    ] {
        let (w, sigma, kick) = roller_mode(&d);
        let w_alone = ((k_h + d.k_rb) / d.m_r).sqrt();
        assert!(
            (w / w_alone - 1.0).abs() < 0.02,
            "roller mode {w} vs {w_alone} rad/s"
        );
        let sigma_alone = d.contact_damping_ratio * (k_h / d.m_r).sqrt()
            + d.roller_bearing_damping_ratio * (d.k_rb / d.m_r).sqrt();
        assert!(
            (sigma / sigma_alone - 1.0).abs() < 0.05,
            "{case}: σ {sigma} vs the roller alone {sigma_alone}"
        );
        // The roller moves most; the cam and the cantilever far less.
        assert!(
            kick.iter()
                .enumerate()
                .all(|(i, k)| i == 1 || k.abs() < 0.25),
            "{kick:?}"
        );
        let a = swings(&ring(d.clone(), kick, duration));
        assert!(a.len() >= 6, "{case}: {} swings", a.len());
        // The first swing, at its mid time: the overlap rings with amplitude
        // (v2 - v1) / ω, the force with K_h (v2 - v1) / ω, less the decay so far.
        let (t0, first) = a[0];
        let expect = k_h * (1.0 - kick[0]) / w * (-sigma * t0).exp();
        assert!(
            (first / expect - 1.0).abs() < 0.02,
            "{case}: first swing {first} vs {expect} lb"
        );
        let measured = -log_slope(&a);
        assert!(
            (measured / sigma - 1.0).abs() < 0.01,
            "{case}: decay rate {measured} vs {sigma} (the roller alone: {sigma_alone})"
        );
        // The swing period is the damped mode's, 2π / (ω sqrt(1 - ζ²)).
        let period = (a[a.len() - 1].0 - a[0].0) / (a.len() - 1) as f64;
        let expect = TWO_PI / (w * (1.0 - (sigma / w).powi(2)).sqrt());
        assert!(
            (period / expect - 1.0).abs() < 0.01,
            "{case}: {period} vs {expect}"
        );
    }

    // Neither: the ring keeps its amplitude (the other dampers hardly touch this mode:
    // seen 0.99997 of it after 200 µs).
    d.contact_damping_ratio = 0.0;
    d.roller_bearing_damping_ratio = 0.0;
    let (_, _, kick) = roller_mode(&d);
    let a = swings(&ring(d, kick, duration));
    let kept = a[a.len() - 1].1 / a[0].1;
    assert!(kept > 0.99, "undamped: the ring fell to {kept}");
}

/// The point of K_rs = 100 lb/in: the reference design holds contact at its own 800 rpm
/// in steady state (revolution 2 from static equilibrium), while VI.1's listed 60 lb/in
/// separates there (its quasi-static onset is 701 rpm).
#[test]
fn reference_holds_contact_at_800_rpm_and_the_listed_spring_does_not() {
    let rev2_min_force = |d: Design<f64>| {
        let m = RegulatedFullModel::new(d).unwrap();
        let mut s = SolverSettings::reference();
        s.start = Start::Static;
        let mut fmin = f64::INFINITY;
        simulate(&m, &s, 2, &mut |smp: &Sample<f64>| {
            if smp.revolution == 2 {
                fmin = fmin.min(smp.point.contact_force);
            }
            ControlFlow::Continue(())
        })
        .unwrap();
        fmin
    };
    let d = Design::<f64>::reference();
    assert_eq!(d.omega0, rpm_to_rad_per_s(800.0));
    let f = rev2_min_force(d.clone());
    assert!(
        f > 0.0,
        "the reference separates at 800 rpm (smallest force {f})"
    );
    let mut listed = d;
    listed.k_rs = camsim_core::LISTED_SPRING_RATE;
    listed.m_spring = camsim_core::LISTED_SPRING_MASS;
    let f = rev2_min_force(listed);
    assert_eq!(f, 0.0, "the listed spring holds contact at 800 rpm");
}

// ---------------------------------------------------------------- jump

/// Quasi-static jump speed of the reference return (4-5-6-7 over 150°, lift h):
/// contact holds while the spring force F_p + K_rs y exceeds the inertia force of the
/// follower train m |y''| ω², so ω_jump² = min over the decelerating part of
/// (F_p + K_rs h s(u)) β² / (m h |s''(u)|), with m = M_l + M_f + M_fc + M_r.
fn quasi_static_jump_rpm(d: &Design<f64>, f_p: f64) -> f64 {
    let h = 1.5;
    let beta = 150f64.to_radians();
    let m = d.m_l + d.m_f(0.0) + d.m_fc(0.0) + d.m_r;
    let mut best = f64::INFINITY;
    for i in 1..20000 {
        let u = i as f64 / 20000.0;
        let s = 35.0 * u.powi(4) - 84.0 * u.powi(5) + 70.0 * u.powi(6) - 20.0 * u.powi(7);
        let a = 420.0 * u.powi(2) - 1680.0 * u.powi(3) + 2100.0 * u.powi(4) - 840.0 * u.powi(5);
        if a < 0.0 {
            best = best.min((f_p + d.k_rs * h * s) * beta * beta / (m * h * -a));
        }
    }
    rad_per_s_to_rpm(best.sqrt())
}

fn steady_jumps(rpm: f64) -> (bool, Vec<camsim_core::JumpInterval<f64>>) {
    let mut d = Design::<f64>::reference();
    d.program =
        camsim_core::CamProgram::with_laws(MotionLaw::ModifiedTrapezoidal, MotionLaw::Poly4567);
    d.set_speed_rpm(rpm).unwrap();
    let m = RegulatedFullModel::new(d).unwrap();
    let mut s = SolverSettings::reference();
    s.rtol = 1e-6;
    s.start = Start::Static;
    let mut stats = ResponseStats::<f64, 3, 8, 256>::new(m.design().omega0);
    let mut jumped = false;
    let mut resumed_after_jump = false;
    let mut obs = |smp: &Sample<f64>| {
        if smp.revolution >= 2 {
            if !smp.point.in_contact {
                jumped = true;
            } else if jumped {
                resumed_after_jump = true;
            }
        }
        ControlFlow::Continue(())
    };
    simulate(&m, &s, 3, &mut camsim_core::Both(&mut stats, &mut obs)).unwrap();
    if jumped {
        assert!(
            resumed_after_jump,
            "contact must resume after a jump at {rpm} rpm"
        );
    }
    (
        jumped,
        stats
            .jumps()
            .into_iter()
            .filter(|j| j.revolution >= 2)
            .collect(),
    )
}

#[test]
fn jump_follows_the_quasi_static_estimate() {
    let d = Design::<f64>::reference();
    let f_p = d.preload().unwrap();
    let est = quasi_static_jump_rpm(&d, f_p);
    // The reference (K_rs = 100 lb/in, F_p = 49.99 lb, m = 0.012392 lb·s²/in): the
    // minimum sits at u = 0.70 of the law (the return runs it backwards: 255°), 906.5 rpm,
    // above the 800 rpm operating speed (VI.1's listed 60 lb/in gives 701 rpm, below it).
    assert!((est - 906.5).abs() < 0.5, "quasi-static estimate {est}");
    let mut listed = d.clone();
    listed.k_rs = camsim_core::LISTED_SPRING_RATE;
    listed.m_spring = camsim_core::LISTED_SPRING_MASS;
    let listed_est = quasi_static_jump_rpm(&listed, listed.preload().unwrap());
    assert!(
        (listed_est - 701.0).abs() < 0.5,
        "listed spring: {listed_est}"
    );
    let (low, _) = steady_jumps(0.75 * est);
    assert!(!low, "no separation expected at {} rpm", 0.75 * est);
    let (high, intervals) = steady_jumps(1.1 * est);
    assert!(high, "separation expected at {} rpm", 1.1 * est);
    // The separation starts in the return's decelerating first part (210°-285°), where
    // the quasi-static estimate puts it, and every interval closes.
    // (Earlier intervals of a revolution can be the bouncing that follows the previous
    // revolution's landing.)
    assert!(
        intervals
            .iter()
            .any(|j| j.start_deg > 210.0 && j.start_deg < 290.0),
        "no onset in the return's first part: {intervals:?}"
    );
    assert!(intervals.iter().all(|j| j.end_deg >= j.start_deg));
}

// ---------------------------------------------------------------- convergence

fn rev2_stats(rtol: f64, atol: f64) -> Vec<f64> {
    let mut d = Design::<f64>::reference();
    d.set_speed_rpm(500.0).unwrap();
    let m = RegulatedFullModel::new(d).unwrap();
    let mut s = SolverSettings::reference();
    s.rtol = rtol;
    s.atol = atol;
    s.start = Start::Static;
    let mut stats = ResponseStats::<f64, 2, 8, 8>::new(m.design().omega0);
    simulate(&m, &s, 2, &mut stats).unwrap();
    let mut out = Vec::new();
    for i in 0..4 {
        let p = stats.period(2, i).unwrap();
        out.extend([
            p.rms_displacement(),
            p.rms_velocity(),
            p.rms_acceleration(),
            p.torque_avg(),
            p.force_avg(),
            p.force_min,
            p.force_max,
        ]);
    }
    out
}

/// Halving the tolerances changes the per-period statistics by less than the tolerance
/// predicts. A displacement error of at most atol moves the contact force by at most
/// K_h atol (K_h = 6.45e6 lb/in), so force statistics (indices 4..6 of each period) may
/// move by that much. The others (RMS deviations of the load's motion, the average
/// torque) must agree to 1e-3 of that statistic's largest value in the revolution: the
/// solver's error is absolute, about the same in every period (seen: 2.9e-3 in/s² on
/// the rise's RMS acceleration of 243 in/s² and on the low dwell's of 3.0), so a period
/// that hardly vibrates is judged on the revolution's scale. Largest seen: 1.5e-4 (the
/// return's average torque).
#[test]
fn halving_tolerance_changes_statistics_within_what_it_predicts() {
    let k_h = Design::<f64>::reference().k_h_base().unwrap();
    for (rtol, atol) in [(1e-5, 1e-7), (1e-6, 1e-8)] {
        let a = rev2_stats(rtol, atol);
        let b = rev2_stats(rtol / 2.0, atol / 2.0);
        for (i, (x, y)) in a.iter().zip(&b).enumerate() {
            let change = (x - y).abs();
            if (4..=6).contains(&(i % 7)) {
                assert!(
                    change < k_h * atol,
                    "atol {atol}: force statistic {i}: {x} vs {y}"
                );
            } else {
                let kind = i % 7;
                let scale = a
                    .iter()
                    .chain(&b)
                    .skip(kind)
                    .step_by(7)
                    .fold(1e-3, |m: f64, v| m.max(v.abs()));
                assert!(
                    change / scale < 1e-3,
                    "atol {atol}: statistic {i}: {x} vs {y} (rel {:e})",
                    change / scale
                );
            }
        }
    }
}

fn rev2_statistics<S: Scene, const N: usize>(rtol: f64, atol: f64) -> Vec<f64> {
    let mut d = Design::<f64>::reference();
    d.set_speed_rpm(500.0).unwrap();
    let m = CamModel::<f64, S, N>::new(d).unwrap();
    let mut s = SolverSettings::reference();
    s.rtol = rtol;
    s.atol = atol;
    s.start = Start::Static;
    let mut stats = ResponseStats::<f64, 2, 8, 8>::new(m.design().omega0);
    simulate(&m, &s, 2, &mut stats).unwrap();
    let mut out = Vec::new();
    for i in 0..4 {
        let p = stats.period(2, i).unwrap();
        out.extend([
            p.rms_displacement(),
            p.rms_velocity(),
            p.rms_acceleration(),
            p.force_avg(),
            p.force_min,
            p.force_max,
        ]);
    }
    out
}

/// The vertical scene (regulated drive, x1, x2, x3 dropped: 16 states) against the full
/// 22-state model at 500 rpm from static equilibrium. In Eqs. IV.1-IV.3 the horizontal
/// motion is driven by the contact force's horizontal component but feeds back into
/// neither the vertical chain nor the drive, so the two scenes share their vertical
/// physics and their revolution-2 statistics differ only by the solver's path (other
/// states, other steps): by the error `camsim bench` measures for this scene (largest
/// relative error, floor 1e-3, against the full model at rtol 1e-10).
#[test]
fn reduced_scenes_have_smaller_states_and_agree_with_the_full_model() {
    use camsim_core::RegulatedVertical;
    assert_eq!(
        (RegulatedFull::N, RegulatedVertical::N, ConstCamVertical::N),
        (22, 16, 10)
    );
    let full = rev2_statistics::<RegulatedFull, { RegulatedFull::N }>(1e-10, 1e-12);
    let vertical = rev2_statistics::<RegulatedVertical, { RegulatedVertical::N }>(1e-6, 1e-8);
    let full_ref = rev2_statistics::<RegulatedFull, { RegulatedFull::N }>(1e-6, 1e-8);
    let err = |a: &[f64]| {
        a.iter()
            .zip(&full)
            .map(|(a, b)| (a - b).abs() / b.abs().max(1e-3))
            .fold(0.0, f64::max)
    };
    // It is the solver's tolerance, not the dropped DOFs: the vertical scene at rtol 1e-6
    // is held to the same bound as the full model at that tolerance. Seen: 4.8e-4 and
    // the full model 3.4e-4 (with the printed model's listed spring and no damping at the
    // roller: 3.79e-4, what `camsim bench` reported then, and 6.0e-4).
    let e = err(&vertical);
    assert!(
        e < 1e-3,
        "vertical scene vs full model: max relative error {e:e}"
    );
    assert!(e > 0.0);
    assert!(err(&full_ref) < 1e-3);
    // A wrong drive kind for the scene is refused, naming the field.
    let mut rigid = Design::<f64>::reference();
    rigid.drive = DriveLaw::ConstantCamSpeed;
    assert!(matches!(
        RegulatedVerticalModel::new(rigid.clone()),
        Err(camsim_core::Error::InvalidParameter { field: "drive", .. })
    ));
    assert!(ConstCamVerticalModel::new(rigid).is_ok());
}

// ---------------------------------------------------------------- forces

/// xorshift64*: a seeded, dependency-free pseudo-random sequence in [0, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn within(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// At random states of the full model (any cam angle, deflections of ±50 µin around the
/// static ones, velocities up to 20 in/s, some near zero where friction is smoothed),
/// the model's contact force and slide-bearing friction are those of the tested force
/// functions (Eqs. V.15-V.16, V.19-V.20 with the contact damping of docs/MODEL.md §3.9)
/// applied to its own displacements, velocities and pressure angle.
#[test]
fn model_forces_are_the_force_functions() {
    let d = Design::<f64>::reference();
    let m = RegulatedFullModel::new(d.clone()).unwrap();
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut touching, mut apart, mut rubbing, mut clamped) = (0, 0, 0, 0);
    for _ in 0..2000 {
        let theta = rng.within(0.0, TWO_PI);
        let lift = d.program.follower(theta).y;
        let mut pos = [0.0; 8];
        let mut vel = [0.0; 8];
        for (i, (p, v)) in pos.iter_mut().zip(vel.iter_mut()).enumerate() {
            let base = if camsim_core::RELATIVE_TO_LIFT[i] {
                lift
            } else {
                0.0
            };
            *p = base + rng.within(-5e-5, 5e-5);
            let speed = if rng.next() < 0.3 { 0.05 } else { 20.0 };
            *v = rng.within(-speed, speed);
        }
        let y = m.state_from(theta, &pos, &vel);
        let p = m.evaluate(0.0, &y);
        let (cos_phi, sin_phi) = (p.pressure_angle.cos(), p.pressure_angle.sin());
        let approach = p.lift.y + p.position(TransDof::CamY) - p.position(TransDof::RollerY);
        // d/dt (y + y1 - y2) = y'(θ_c) θ̇_c + ẏ1 - ẏ2; C_h = 2 ξ_h sqrt(K_h M_r) (V.13).
        let rate =
            p.lift.dy * p.omega_c + p.velocity(TransDof::CamY) - p.velocity(TransDof::RollerY);
        let c_h = 2.0 * d.contact_damping_ratio * (p.k_h * d.m_r).sqrt();
        let c = damped_contact_force(p.k_h, approach, m.preload(), c_h, rate, cos_phi);
        // The model forms y + y1 - y2 from y2 stored relative to the lift and cos φ without
        // the angle: both differ from the test's by rounding (K_h · 1 ulp of 1.5 in ≈ 1.5e-9 lb).
        let tol = 1e-7 + 1e-12 * c.force.abs();
        assert!(
            (p.contact_force - c.force).abs() < tol,
            "θ {theta}: {} vs {}",
            p.contact_force,
            c.force
        );
        if c.force.abs() > tol {
            assert_eq!(p.in_contact, c.in_contact, "θ {theta}");
        }
        // The elastic part alone (the printed V.19): where it is positive but the damper
        // would pull, the force is clamped at 0.
        let elastic = contact_force(p.k_h, approach, m.preload(), cos_phi);
        if elastic.in_contact && !c.in_contact {
            clamped += 1;
        }
        let (n1, n2) = bearing_normal_forces(c.force, sin_phi, d.bearing_a, d.bearing_b);
        let f1 = coulomb_friction(
            d.mu,
            n1,
            p.velocity(TransDof::Follower),
            d.friction_smoothing,
        );
        let f2 = coulomb_friction(
            d.mu,
            n2,
            p.velocity(TransDof::CantileverY),
            d.friction_smoothing,
        );
        assert!(
            (p.friction_follower - f1).abs() < 1e-9 + 1e-12 * f1.abs(),
            "{} vs {f1}",
            p.friction_follower
        );
        assert!(
            (p.friction_cantilever - f2).abs() < 1e-9 + 1e-12 * f2.abs(),
            "{} vs {f2}",
            p.friction_cantilever
        );
        if p.in_contact {
            touching += 1;
        } else {
            apart += 1;
        }
        // The roller's equations (IV.2, IV.3) with the roller bearing's spring and damper
        // C_rb = 2 ξ_rb sqrt(K_rb M_r) (docs/MODEL.md §3.13, §3.14), both directions.
        let c_rb = 2.0 * d.roller_bearing_damping_ratio * (d.k_rb * d.m_r).sqrt();
        let rel = |a: TransDof, b: TransDof| {
            (p.position(a) - p.position(b), p.velocity(a) - p.velocity(b))
        };
        let (dy, dv) = rel(TransDof::CantileverY, TransDof::RollerY);
        let a_roller = (d.k_rb * dy + c_rb * dv + c.force * cos_phi) / d.m_r;
        let got = p.acceleration(TransDof::RollerY);
        assert!(
            (got - a_roller).abs() < 1e-9 * (1.0 + a_roller.abs()) + tol / d.m_r,
            "θ {theta}: roller {got} vs {a_roller}"
        );
        let (dx, dvx) = rel(TransDof::CantileverX, TransDof::RollerX);
        let a_roller_x = (d.k_rb * dx + c_rb * dvx - c.force * sin_phi) / d.m_r;
        let got = p.acceleration(TransDof::RollerX);
        assert!(
            (got - a_roller_x).abs() < 1e-9 * (1.0 + a_roller_x.abs()) + tol / d.m_r,
            "θ {theta}: roller x {got} vs {a_roller_x}"
        );
        if p.friction_follower.abs() > 0.01 {
            rubbing += 1;
        }
    }
    // Both sides of the jump criterion, the clamp and real friction were exercised.
    assert!(
        touching > 200 && apart > 200 && rubbing > 200 && clamped > 20,
        "{touching} {apart} {rubbing} {clamped}"
    );
}
