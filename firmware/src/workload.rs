//! The model workload the firmware runs and measures: camsim-core's cam-follower model
//! in `f32`, integrated by the core's England solver, with the chip's predictor scene
//! from the `camsim-chip` crate (the one place the host's `camsim predict --f32`
//! reads too, so both run exactly the same arithmetic).
//!
//! The binaries call just these items:
//! - [`chip_design`]: the design compiled in (the reference design of VI.1), both;
//! - [`Predictor`]: the boot-time table (`PredictionTable`) and its interpolation, the
//!   `predictor` binary (the QEMU demonstration image; it instantiates only the chip's model);
//! - [`chip_table`]: the chip's lift table, built at build time into flash (both);
//! - [`RHS_REPS`], [`rhs_probe`], [`evaluate_rhs`], [`revolution_model`],
//!   [`simulate_revolution`]: the budget
//!   probes, generic over the scene and the lift, which the `budget` binary instantiates for the chip's
//!   model ([`camsim_chip::ChipModel`], the quasi-static-rod scene's 10 states) and, for comparison, the full 22-state
//!   model ([`camsim_core::RegulatedFullModel`]).
//!
//! Another scene is chosen at build time, never parsed as text on the chip: build with
//! `CAMSIM_SCENE=$PWD/my.toml` (a host scene file); `build.rs` reads and checks it with
//! the host's reader, narrows its design to `f32` (`camsim_chip::chip_design_from`) and
//! stores it as postcard, which [`chip_design`] decodes. `camsim predict --f32 --scene
//! my.toml` makes the same conversion and reproduces the chip bit for bit.

use core::ops::ControlFlow;

use camsim_chip::{chip_solver_settings, ChipConfig, CHIP_GRID};
use camsim_core::{
    simulate, CamModel, Design, LiftProfile, LiftTable, Observer, PredictionTable, Sample, Scene,
    SolverSettings, SpeedPrediction, SteadyState,
};

/// The lift table built at build time (`build.rs`: `camsim_chip::ChipConfig::tabulate` on
/// the host, for the design and lift compiled in), in flash.
mod lift_table {
    include!(concat!(env!("OUT_DIR"), "/lift_table.rs"));
}

/// The chip's lift table: exactly the knots and segments of the compiled-in design's
/// table, which `build.rs` filled on the host with the code `camsim predict --f32` runs
/// (`camsim_chip::ChipConfig::tabulate`) and wrote out bit for bit: a `static` in flash,
/// no RAM and no work at boot.
pub type FlashTable = LiftTable<f32, { lift_table::TABLE_KNOTS }, { lift_table::TABLE_PIECES }>;

/// The chip's lift table ([`FlashTable`]).
pub fn chip_table() -> &'static FlashTable {
    &lift_table::LIFT_TABLE
}

/// Right-hand-side evaluations timed to get instructions per evaluation.
pub const RHS_REPS: u32 = 1000;

/// Nominal cam speed of the measured revolution (rpm): `camsim_chip::CHIP_NOMINAL_RPM`,
/// the reference design's 800 rpm (the real-time factor is `camsim_chip::realtime_factor`).
pub const NOMINAL_RPM: f32 = camsim_chip::CHIP_NOMINAL_RPM as f32;

/// The scene chosen at build time (`CAMSIM_SCENE`): the chip's `Design<f32>` in postcard,
/// written by `build.rs`.
#[cfg(camsim_scene)]
static SCENE_POSTCARD: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/scene.postcard"));

/// Which design is compiled in: "reference", or the file name of the scene chosen at
/// build time (`CAMSIM_SCENE`).
#[cfg(camsim_scene)]
pub const SCENE_NAME: &str = env!("CAMSIM_SCENE_NAME");
/// Which design is compiled in: "reference", or the file name of the scene chosen at
/// build time (`CAMSIM_SCENE`).
#[cfg(not(camsim_scene))]
pub const SCENE_NAME: &str = "reference";

/// Which cam the roller rides on: "theoretical", or the file name of the measured profile
/// chosen at build time (`CAMSIM_PROFILE`).
#[cfg(camsim_profile)]
pub const PROFILE_NAME: &str = env!("CAMSIM_PROFILE_NAME");
/// Which cam the roller rides on: "theoretical", or the file name of the measured profile
/// chosen at build time (`CAMSIM_PROFILE`).
#[cfg(not(camsim_profile))]
pub const PROFILE_NAME: &str = "theoretical";

/// Knots of the measured profile's deviation spline the lift table was built on (0: the
/// theoretical cam); the spline itself stays on the host (`build.rs`).
pub const PROFILE_KNOTS: usize = lift_table::PROFILE_KNOTS;

/// The design compiled into the chip: the reference design of VI.1
/// (`camsim_chip::chip_design`), or the scene chosen at build time, decoded from its
/// postcard bytes (the `f32` design `build.rs` got from `camsim_chip::chip_design_from`,
/// as `camsim predict --f32 --scene` does) and validated. A scene that does not decode
/// or validate stops the firmware with a failure exit.
pub fn chip_design() -> Design<f32> {
    #[cfg(camsim_scene)]
    {
        let Ok(d) = postcard::from_bytes::<Design<f32>>(SCENE_POSTCARD) else {
            defmt::error!("the compiled-in scene does not decode");
            crate::exit_failure()
        };
        if let Err(e) = d.validate() {
            // No core::fmt here: it would cost tens of KiB of flash.
            if let camsim_core::Error::InvalidParameter { field, value, .. } = e {
                defmt::error!(
                    "the compiled-in scene is invalid: {=str} = {=f64}",
                    field,
                    value
                );
            } else {
                defmt::error!("the compiled-in scene is invalid");
            }
            crate::exit_failure()
        }
        d
    }
    #[cfg(not(camsim_scene))]
    {
        camsim_chip::chip_design()
    }
}

/// The model of scene `S` (`N = S::N`) for the chip's design at [`NOMINAL_RPM`] with the
/// roller on `profile` (the chip's lift table, or the closed form for comparison), and a
/// mid-rise state (100 degrees, on the reference program's rise) for [`evaluate_rhs`];
/// `None` if the model cannot be built. Kept out of the timed span: building a model
/// validates the design (including its undercut scan), which costs millions of
/// instructions.
pub fn rhs_probe<S: Scene, const N: usize, P: LiftProfile<f32>>(
    profile: P,
) -> Option<(CamModel<f32, S, N, P>, [f32; N])> {
    let mut d = chip_design();
    d.set_speed_rpm(NOMINAL_RPM).ok()?;
    let model = CamModel::<f32, S, N, P>::with_profile(d, profile).ok()?;
    let y = model.state_from(100.0f32.to_radians(), &[0.0; 8], &[0.0; 8]);
    Some((model, y))
}

/// Evaluates the model's right-hand side `reps` times at `y`; returns a checksum so the
/// work cannot be optimised away.
#[inline(never)]
pub fn evaluate_rhs<S: Scene, const N: usize, P: LiftProfile<f32>>(
    model: &CamModel<f32, S, N, P>,
    y: &[f32; N],
    reps: u32,
) -> f32 {
    use camsim_core::OdeSystem;
    let mut dydt = [0.0f32; N];
    let mut acc = 0.0f32;
    for i in 0..reps {
        let t = core::hint::black_box(i as f32 * 1.0e-6);
        model.rhs(t, core::hint::black_box(y), &mut dydt);
        for v in core::hint::black_box(&dydt) {
            acc += *v;
        }
    }
    acc
}

/// What one simulated revolution produced.
#[derive(Clone, Copy, Debug, defmt::Format)]
pub struct Revolution {
    /// Right-hand-side evaluations spent.
    pub rhs_evals: u32,
    /// Double steps attempted (accepted + rejected).
    pub steps: u32,
    /// Load displacement at the last sample, in.
    pub load_in: f32,
    /// Load velocity at the last sample, in/s.
    pub load_in_per_s: f32,
}

/// The model of scene `S` (`N = S::N`) for the chip's design at `rpm` with the roller on
/// `profile`, for [`simulate_revolution`]. Building it validates the design (its undercut
/// scan is most of the cost: about 1.9 M instructions on the chip), which the steady state
/// pays once per speed, not per revolution: the budget times it apart.
#[inline(never)]
pub fn revolution_model<S: Scene, const N: usize, P: LiftProfile<f32>>(
    profile: P,
    rpm: f32,
) -> Option<CamModel<f32, S, N, P>> {
    let mut d = chip_design();
    d.set_speed_rpm(rpm).ok()?;
    CamModel::<f32, S, N, P>::with_profile(d, profile).ok()
}

/// Simulates one cam revolution of `model` (built by [`revolution_model`]) with the chip's
/// solver settings, sampled as the predictor's runs are (no contact stress, no outputs).
#[inline(never)]
pub fn simulate_revolution<S: Scene, const N: usize, P: LiftProfile<f32>>(
    model: &CamModel<f32, S, N, P>,
) -> Option<Revolution> {
    let mut obs = LastLoad::default();
    let stats = simulate(model, &chip_solver_settings(), 1, &mut obs).ok()?;
    Some(Revolution {
        rhs_evals: stats.rhs_evals,
        steps: stats.accepted + stats.rejected,
        load_in: obs.load.0,
        load_in_per_s: obs.load.1,
    })
}

/// The revolution probe's observer: the last sample's load, asking for what the
/// predictor's observer (`camsim_core::SteadyStateObserver`) asks for: neither the contact
/// stress nor the outputs (pressure angle, theoretical response).
#[derive(Default)]
struct LastLoad {
    load: (f32, f32),
}

impl Observer<f32> for LastLoad {
    fn needs_stress(&self) -> bool {
        false
    }
    fn needs_outputs(&self) -> bool {
        false
    }
    fn observe(&mut self, s: &Sample<f32>) -> ControlFlow<()> {
        self.load = (s.point.load_displacement(), s.point.load_velocity());
        ControlFlow::Continue(())
    }
}

/// The chip's predictor: the boot-time table over the scene's speed grid, interpolated,
/// on the compiled-in lift through the chip's lift table ([`chip_table`]).
#[derive(Clone, Debug)]
pub struct Predictor {
    design: Design<f32>,
    lift: &'static FlashTable,
    /// The table computed at boot.
    pub table: PredictionTable<f32, CHIP_GRID>,
}

impl Predictor {
    /// Computes the table for the chip's design (the boot-time work).
    pub fn boot() -> Result<Self, camsim_core::Error> {
        Self::boot_with(&chip_solver_settings())
    }

    /// [`Self::boot`] with other solver settings (the `boot_fault` binary's impossible
    /// step budget).
    pub fn boot_with(settings: &SolverSettings<f32>) -> Result<Self, camsim_core::Error> {
        let design = chip_design();
        let lift = chip_table();
        let table = ChipConfig::new(&design)
            .on(lift)
            .with_settings(*settings)
            .prediction_table()?;
        Ok(Self {
            design,
            lift,
            table,
        })
    }

    /// The prediction at a measured speed (linear interpolation in the table).
    pub fn predict(&self, rpm: f32) -> SpeedPrediction<f32> {
        self.table.predict(rpm)
    }

    /// The model run directly at `rpm` (for the interpolation-accuracy check at boot).
    pub fn direct(&self, rpm: f32) -> Result<SteadyState<f32>, camsim_core::Error> {
        ChipConfig::new(&self.design)
            .on(self.lift)
            .steady_state(rpm)
    }
}
