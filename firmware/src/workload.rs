//! The model workload the firmware runs and measures: THE ONLY FILE TO EDIT
//! when camsim-core's eleven-degree-of-freedom model lands.
//!
//! The binary calls just these items:
//! - [`RHS_REPS`] and [`evaluate_rhs`]: right-hand-side evaluations to time;
//! - [`simulate_revolution`]: one simulated cam revolution at the nominal speed;
//! - [`JumpPredictor`]: speed (rpm) -> margin to jump onset (rpm), for the alarm.
//!
//! ## PLACEHOLDER (until the core's model and solver are on main)
//! Everything below marked PLACEHOLDER is a stand-in with the right shape and a
//! similar arithmetic mix (a cam-driven chain of five masses, 11 states, with a
//! one-sided contact spring and a trigonometric lift), integrated by a local
//! fixed-step RK4. To plug in the real model:
//! 1. delete the local `OdeSystem` trait and use `camsim_core::OdeSystem`;
//! 2. replace `PlaceholderModel` by the core's model (built from the reference
//!    design) and `N` by its state length;
//! 3. in `simulate_revolution`, replace `rk4_fixed` by `camsim_core::England`
//!    (`England::new(EnglandConfig { tol: Tolerance::scalar(rtol, atol), h_init,
//!    h_min, h_max, max_steps })`, `integrate(&sys, t0, &mut y, t_end, |_, _|
//!    ControlFlow::Continue(()))`) and report `stats.rhs_evals`;
//! 4. make `JumpPredictor` use the core's predictor.

use camsim_core::Real;

/// Number of states of the workload model.
pub const N: usize = 11;

/// Right-hand-side evaluations timed to get instructions per evaluation.
pub const RHS_REPS: u32 = 1000;

/// Nominal cam speed of the simulated revolution (rpm).
pub const NOMINAL_RPM: f32 = 800.0;

/// PLACEHOLDER: same signature as `camsim_core::OdeSystem` (being written on the solver branch).
pub trait OdeSystem<T: Real, const N: usize> {
    /// dy/dt at time t.
    fn rhs(&self, t: T, y: &[T; N], dydt: &mut [T; N]);
}

/// PLACEHOLDER model: a harmonic cam (lift h/2 (1 - cos theta)) pushing a chain
/// of five masses through a one-sided contact spring; the last mass sits on a
/// preloaded return spring. State: [theta, x1..x5, v1..v5] (in, in/s, rad).
#[derive(Clone, Copy, Debug)]
pub struct PlaceholderModel {
    /// Cam speed (rad/s).
    pub omega: f32,
    /// Total lift (in).
    pub lift: f32,
    /// Each mass (lb s^2/in).
    pub mass: f32,
    /// Contact stiffness (lb/in).
    pub k_contact: f32,
    /// Chain stiffness between neighbours (lb/in).
    pub k_chain: f32,
    /// Chain damping (lb s/in).
    pub c_chain: f32,
    /// Return-spring rate (lb/in).
    pub k_return: f32,
    /// Return-spring preload (lb).
    pub preload: f32,
}

impl PlaceholderModel {
    /// The placeholder at a cam speed in rpm.
    pub fn at_rpm(rpm: f32) -> Self {
        Self {
            omega: rpm * (core::f32::consts::PI / 30.0),
            lift: 0.5,
            mass: 0.002,
            k_contact: 2.0e5,
            k_chain: 1.0e5,
            c_chain: 5.0,
            k_return: 100.0,
            preload: 40.0,
        }
    }

    /// Static state at t = 0: all masses settled on the cam's base circle under the preload.
    pub fn initial_state(&self) -> [f32; N] {
        let mut y = [0.0f32; N];
        // Every spring in the chain carries the preload: x_i = -F/k_c - (i-1) F/k.
        let mut x = -self.preload / self.k_contact;
        for xi in y[1..6].iter_mut() {
            *xi = x;
            x -= self.preload / self.k_chain;
        }
        y
    }
}

impl OdeSystem<f32, N> for PlaceholderModel {
    fn rhs(&self, _t: f32, y: &[f32; N], dydt: &mut [f32; N]) {
        let theta = y[0];
        let lift = 0.5 * self.lift * (1.0 - Real::cos(theta));
        // One-sided contact: no tension (a jump when it reaches zero).
        let fc = (self.k_contact * (lift - y[1])).max(0.0);
        let inv_m = 1.0 / self.mass;
        dydt[0] = self.omega;
        let mut f_prev = fc;
        for i in 0..5 {
            let x = y[1 + i];
            let v = y[6 + i];
            let f_next = if i < 4 {
                self.k_chain * (x - y[2 + i]) + self.c_chain * (v - y[7 + i])
            } else {
                self.preload + self.k_return * x
            };
            dydt[1 + i] = v;
            dydt[6 + i] = (f_prev - f_next) * inv_m;
            f_prev = f_next;
        }
    }
}

/// PLACEHOLDER solver: classical fixed-step RK4, `steps` steps from t0 to t1.
/// Returns the number of right-hand-side evaluations.
pub fn rk4_fixed<S: OdeSystem<f32, N>>(
    sys: &S,
    t0: f32,
    y: &mut [f32; N],
    t1: f32,
    steps: u32,
) -> u32 {
    let h = (t1 - t0) / steps as f32;
    let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (
        [0.0f32; N],
        [0.0f32; N],
        [0.0f32; N],
        [0.0f32; N],
        [0.0f32; N],
    );
    for s in 0..steps {
        let t = t0 + h * s as f32;
        sys.rhs(t, y, &mut k1);
        for ((o, a), k) in tmp.iter_mut().zip(y.iter()).zip(k1.iter()) {
            *o = a + 0.5 * h * k;
        }
        sys.rhs(t + 0.5 * h, &tmp, &mut k2);
        for ((o, a), k) in tmp.iter_mut().zip(y.iter()).zip(k2.iter()) {
            *o = a + 0.5 * h * k;
        }
        sys.rhs(t + 0.5 * h, &tmp, &mut k3);
        for ((o, a), k) in tmp.iter_mut().zip(y.iter()).zip(k3.iter()) {
            *o = a + h * k;
        }
        sys.rhs(t + h, &tmp, &mut k4);
        for (i, yi) in y.iter_mut().enumerate() {
            *yi += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    4 * steps
}

/// Evaluates the model's right-hand side `reps` times at a representative state
/// (mid-rise); returns a checksum so the work cannot be optimised away.
#[inline(never)]
pub fn evaluate_rhs(reps: u32) -> f32 {
    let sys = PlaceholderModel::at_rpm(NOMINAL_RPM);
    let mut y = sys.initial_state();
    y[0] = 1.0; // rad, on the rise
    let mut dydt = [0.0f32; N];
    let mut acc = 0.0f32;
    for i in 0..reps {
        let t = core::hint::black_box(i as f32 * 1.0e-5);
        sys.rhs(t, core::hint::black_box(&y), &mut dydt);
        acc += core::hint::black_box(dydt[6]);
    }
    acc
}

/// What one simulated revolution produced.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub struct Revolution {
    /// Right-hand-side evaluations spent.
    pub rhs_evals: u32,
    /// Steps taken (accepted + rejected for an adaptive solver).
    pub steps: u32,
    /// Final follower (first mass) displacement, in (for host parity).
    pub follower_in: f32,
    /// Final follower velocity, in/s (for host parity).
    pub follower_in_per_s: f32,
}

/// Simulates one cam revolution at [`NOMINAL_RPM`] from the static state.
#[inline(never)]
pub fn simulate_revolution() -> Revolution {
    // PLACEHOLDER: 720 fixed RK4 steps (half a degree each).
    const STEPS: u32 = 720;
    let sys = PlaceholderModel::at_rpm(NOMINAL_RPM);
    let mut y = sys.initial_state();
    let period = 2.0 * core::f32::consts::PI / sys.omega;
    let rhs_evals = rk4_fixed(&sys, 0.0, &mut y, period, STEPS);
    Revolution {
        rhs_evals,
        steps: STEPS,
        follower_in: y[1],
        follower_in_per_s: y[6],
    }
}

/// Speed -> margin to jump onset, fed to `camsim_core::JumpAlarm`.
#[derive(Clone, Copy, Debug)]
pub struct JumpPredictor {
    onset_rpm: f32,
}

impl JumpPredictor {
    /// PLACEHOLDER jump-onset speed (rpm), not derived from any model.
    pub const PLACEHOLDER_ONSET_RPM: f32 = 1450.0;

    /// A predictor for the reference design.
    pub fn new() -> Self {
        Self {
            onset_rpm: Self::PLACEHOLDER_ONSET_RPM,
        }
    }

    /// Jump-onset speed currently predicted (rpm).
    pub fn onset_rpm(&self) -> f32 {
        self.onset_rpm
    }

    /// Margin (rpm) between the predicted jump onset and the measured speed.
    pub fn margin_rpm(&mut self, rpm: f32) -> f32 {
        self.onset_rpm - rpm
    }
}

impl Default for JumpPredictor {
    fn default() -> Self {
        Self::new()
    }
}
