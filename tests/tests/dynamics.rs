//! The eleven-DOF model against numbers derived independently: statics, the rigid
//! limit, an energy balance, a quasi-static jump estimate and tolerance convergence.

use std::ops::ControlFlow;

use camsim_core::{
    bearing_normal_forces, contact_force, coulomb_friction, damped_contact_force, simulate,
    CamModel, ConstCamVertical, ConstCamVerticalModel, Design, DriveLaw, England, EnglandConfig,
    MotionLaw, OdeSystem, Real, RegulatedFull, RegulatedFullModel, RegulatedVerticalModel,
    ResponseStats, Sample, Scene, SolverSettings, Start, Tolerance, TransDof,
};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

fn rpm_to_rad(rpm: f64) -> f64 {
    rpm * std::f64::consts::PI / 30.0
}

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
    // V.18 by hand for the reference: K_t = series(K_rb, K_h, K_vs), F_p = K_t K_rs δ/(K_t + K_rs).
    let k_h = d.hertz.stiffness(0.375, 1.5).unwrap();
    let k_t = 1.0 / (1.0 / 1.5e6 + 1.0 / k_h + 1.0 / 1.48e6);
    let f_p = k_t * 60.0 * 0.5 / (k_t + 60.0);
    assert!(
        (m.preload() - f_p).abs() < 1e-9 * f_p,
        "preload {} vs {}",
        m.preload(),
        f_p
    );
    assert!((f_p - 29.997).abs() < 1e-3);

    let expect = f_p / (1.0 + 60.0 * k_h * (1.0 / 1.48e6 + 1.0 / 1.5e6) / (60.0 + k_h));
    // The cam at rest: a negligible speed, so the cam stays on the base circle.
    let mut slow = d.clone();
    slow.set_speed_rpm(1e-9).unwrap();
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
    // It is the preload of V.18 to within the chain's own compliance (K_rs (1/K_vs + 1/K_rb) ~ 8e-5).
    let rel = (p.contact_force - f_p).abs() / f_p;
    assert!(
        rel < 1e-4 && rel > 1e-5,
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
/// contact damping: the design the model ran before contact damping existed.
fn listed_printed<T: Real>() -> Design<T> {
    let mut d = Design::<T>::reference();
    d.k_rs = T::from_f64(60.0);
    d.m_spring = T::from_f64(0.151 / 386.09);
    d.contact_damping_ratio = T::ZERO;
    d
}

/// ξ_h = 0 is the printed model bit for bit: one revolution of the full f64 model from
/// the thesis start (its impact rings and jumps, so every branch of the contact law is
/// taken) and of the chip's f32 vertical model from the static start give the solver
/// counts and the fingerprint of every sample recorded with the code before contact
/// damping (commit 12f8cc7; libm makes them the same on every platform).
#[test]
fn zero_contact_damping_is_the_printed_model_bit_for_bit() {
    let m = RegulatedFullModel::<f64>::new(listed_printed()).unwrap();
    let mut fp = Fingerprint::new();
    let st = simulate(&m, &SolverSettings::reference(), 1, &mut |s: &Sample<
        f64,
    >| {
        fp.sample(s)
    })
    .unwrap();
    assert_eq!(
        (st.accepted, st.rejected, st.rhs_evals, fp.samples),
        (52412, 9517, 538_327, 104_823)
    );
    assert_eq!(fp.hash, 0xb9fb_b46f_8bf8_d565);

    let m = RegulatedVerticalModel::<f32>::new(listed_printed()).unwrap();
    let mut s = SolverSettings::<f32>::reference();
    s.rtol = 1e-3;
    s.start = Start::Static;
    let mut fp = Fingerprint::new();
    let st = simulate(&m, &s, 1, &mut |s: &Sample<f32>| fp.sample(s)).unwrap();
    assert_eq!(
        (st.accepted, st.rejected, st.rhs_evals, fp.samples),
        (6513, 2081, 73184, 13026)
    );
    assert_eq!(fp.hash, 0xb6cd_87ed_ce43_3e9c);

    // The default contact damping changes the run (and so can fail this test).
    let mut damped = listed_printed::<f64>();
    damped.contact_damping_ratio = 0.05;
    let m = RegulatedFullModel::<f64>::new(damped).unwrap();
    let mut fp = Fingerprint::new();
    simulate(&m, &SolverSettings::reference(), 1, &mut |s: &Sample<
        f64,
    >| {
        fp.sample(s)
    })
    .unwrap();
    assert_ne!(fp.hash, 0xb9fb_b46f_8bf8_d565);
}

// ---------------------------------------------------------------- rigid limit

fn stiffened(scale: f64) -> Design<f64> {
    let mut d = conservative(300.0);
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

/// Very stiff elements, an ideal constant-speed drive and no damping: the follower
/// tracks the theoretical law, and the RMS acceleration deviation falls as the
/// stiffness rises (the quasi-static deflection m a / k and the vibration it excites
/// both shrink).
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
    let w = rpm_to_rad(300.0);
    let peak = 4.888124 * 1.5 * (w / (150f64.to_radians())).powi(2);
    assert!(r1 < 0.2 * peak, "flexible: {r1} vs peak {peak}");
    assert!(r10 < 0.5 * r1, "x10 stiffer: {r10} vs {r1}");
    assert!(r100 < 0.5 * r10, "x100 stiffer: {r100} vs {r10}");
}

// ---------------------------------------------------------------- energy

/// The model plus one extra state: the integral of the power that enters the mechanical
/// energy E (kinetic + elastic + spring + contact). By hand, from the vertical equations
/// with no damping and no friction, and the constant-speed cam:
/// dE/dt = T_o ω0 (the drive's work through the lift)
///       + ½ κ' ω0 δ² + κ δ F_p (1/K_h)' ω0 (the contact stiffness κ = K_h cos²φ and the
///         preload compression F_p/K_h change with the cam angle)
///       + ½ ρA ẏ3 (ẏ3² - ẏ4²) (rod mass passes from the cantilever to the follower)
///       + ½ K_vc' ẏ3 (y4 - y3)² + ½ K_f' ẏ3 (y5 - y4)² (stiffnesses depend on y3),
/// where δ = y + y1 - y2 + F_p/K_h (contact only while δ > 0).
struct Powered<'a>(&'a ConstCamVerticalModel<f64>);

/// The model's 10 states, the work of all the power terms and that of the drive's alone.
const NE: usize = 12;

impl Powered<'_> {
    fn kappa_and_inv_kh(&self, t: f64, y: &[f64; 10]) -> (f64, f64) {
        let p = self.0.evaluate(t, y);
        (p.k_h * p.pressure_angle.cos().powi(2), 1.0 / p.k_h)
    }
    /// The drive's power T_o ω0 and the total power into E.
    fn power(&self, t: f64, y: &[f64; 10]) -> (f64, f64) {
        let m = self.0;
        let d = m.design();
        let p = m.evaluate(t, y);
        let w = d.omega0;
        let [y1, _, y2, _, y3, _, y4, y5] = p.pos;
        let [_, _, _, _, v3, _, v4, _] = p.vel;
        let drive = p.torque_out * w;
        let mut power = drive;
        let kh = p.k_h;
        let delta = p.lift.y + y1 - y2 + m.preload() / kh;
        if delta > 0.0 {
            let dt = 1e-7 / w; // central difference in cam angle (1e-7 rad)
            let (k_a, i_a) = self.kappa_and_inv_kh(t - dt, y);
            let (k_b, i_b) = self.kappa_and_inv_kh(t + dt, y);
            let kappa = kh * p.pressure_angle.cos().powi(2);
            power += 0.5 * (k_b - k_a) / (2.0 * dt) * delta * delta;
            power += kappa * delta * m.preload() * (i_b - i_a) / (2.0 * dt);
        }
        let ea = d.youngs * d.area;
        power += 0.5 * d.rho * d.area * v3 * (v3 * v3 - v4 * v4);
        power += 0.5 * ea / (d.e2 - y3).powi(2) * v3 * (y4 - y3).powi(2);
        power += 0.5 * (-ea / (d.e1 + y3).powi(2)) * v3 * (y5 - y4).powi(2);
        (drive, power)
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
        let (drive, total) = self.power(t, &s);
        dydt[10] = total;
        dydt[11] = drive;
    }
}

/// With damping and friction off and a constant-speed drive, the work done on the
/// follower train equals the change of its stored and kinetic energy over a revolution.
#[test]
fn energy_balance_over_a_revolution() {
    let m = ConstCamVerticalModel::new(conservative(500.0)).unwrap();
    let sys = Powered(&m);
    let y10 = m.initial_state();
    let mut y = [0.0; NE];
    y[..10].copy_from_slice(&y10);
    let t_end = TWO_PI / m.design().omega0;
    let mut solver = England::new(EnglandConfig {
        tol: Tolerance::scalar(1e-9, 1e-12),
        h_init: 1e-8,
        h_min: 1e-15,
        h_max: t_end / 4000.0,
        max_steps: 5_000_000,
    })
    .unwrap();
    let mut abs_work = 0.0;
    let mut last = (0.0, 0.0);
    solver
        .integrate(&sys, 0.0, &mut y, t_end, |t, yy| {
            let mut s = [0.0; 10];
            s.copy_from_slice(&yy[..10]);
            let p = m.evaluate(t, &s).torque_out * m.design().omega0;
            abs_work += 0.5 * (p.abs() + last.1) * (t - last.0);
            last = (t, p.abs());
            ControlFlow::Continue(())
        })
        .unwrap();
    let mut end = [0.0; 10];
    end.copy_from_slice(&y[..10]);
    let d_e = sys.energy(t_end, &end) - sys.energy(0.0, &y10);
    let work = y[10];
    // The lift does real work (the spring is compressed and released): far from zero.
    assert!(abs_work > 50.0, "|work| {abs_work}");
    // Over the revolution the lift's work nearly cancels (the spring is compressed and
    // released): ΔE is about 1.6e-6 lb·in against 225 lb·in of gross work. The balance
    // closes to the integration's relative tolerance (1e-9) of the gross work (seen:
    // 2e-10).
    let err = (d_e - work).abs();
    assert!(
        err < 1e-9 * abs_work,
        "ΔE {d_e} vs work {work} (|work| {abs_work}), error {err}"
    );
    // The drive's work through the lift dominates the gross work; the side terms are small
    // corrections (seen: 2e-7 of it) but the balance needs them: without them it would
    // miss by 900 times its error (seen: side 4.3e-5 lb·in, net drive work -4.5e-5).
    let drive = y[11];
    let side = work - drive;
    assert!(
        side.abs() < 1e-6 * abs_work,
        "side terms {side} vs {abs_work}"
    );
    assert!(side.abs() > 100.0 * err, "side terms {side} vs error {err}");
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
    best.sqrt() * 30.0 / std::f64::consts::PI
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
    // About 700 rpm for the reference: below its 800 rpm operating speed.
    assert!(est > 600.0 && est < 800.0, "quasi-static estimate {est}");
    let (low, _) = steady_jumps(0.75 * est);
    assert!(!low, "no separation expected at {} rpm", 0.75 * est);
    let (high, intervals) = steady_jumps(1.25 * est);
    assert!(high, "separation expected at {} rpm", 1.25 * est);
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
/// move by that much; the others are kinematic and must agree to 1e-3 relative (the
/// floor seen is ~1e-4: the trapezoidal time average of the sampled vibration).
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
                let scale = x.abs().max(y.abs()).max(1e-3);
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
    // Seen: 3.79e-4 (what `camsim bench` reports for this scene). It is the solver's
    // tolerance, not the dropped DOFs: the full model at the same tolerance is 6.0e-4 off.
    let e = err(&vertical);
    assert!(
        e < 4.5e-4,
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
