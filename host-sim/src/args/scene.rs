//! The scene argument group: a scene file (or the reference design) and the options
//! that override its keys, and the run specification they describe ([`spec_from`]).

use std::path::PathBuf;

use anyhow::Result;
use camsim_core::SegmentKind;

use super::{Law, StartArg, StepControlArg};
use crate::sim::RunSpec;

/// The scene and its overrides, shared by every command that simulates a scene.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (TOML, see `camsim scene --default`); the reference design if omitted.
    pub scene: Option<PathBuf>,
    /// Cam speed, rpm, 1-10 000 (default 800).
    #[arg(long, allow_hyphen_values = true, value_parser = super::rpm)]
    pub rpm: Option<f64>,
    /// Motion law of the rise(s) (names as in `camsim laws`).
    #[arg(long = "rise", value_name = "LAW", ignore_case = true)]
    pub rise: Option<Law>,
    /// Motion law of the return(s).
    #[arg(long = "return", value_name = "LAW", ignore_case = true)]
    pub ret: Option<Law>,
    /// Return spring rate K_rs, lb/in (0.01-1e6), or with its unit (17.5N/mm).
    #[arg(long, value_name = "LB_PER_IN", allow_hyphen_values = true, value_parser = super::spring_rate)]
    pub spring_rate: Option<f64>,
    /// Spring length compressed at assembly δ_rs, in (0-100), or with its unit (12.7mm).
    #[arg(long, value_name = "IN", allow_hyphen_values = true, value_parser = super::preload_length)]
    pub preload_length: Option<f64>,
    /// Initial state (default: "thesis" for `run`, "static" for `jump-speed`, whose
    /// steady state the thesis start's impact would pollute).
    #[arg(long, value_enum)]
    pub start: Option<StartArg>,
    /// Solver relative tolerance (1e-13 to 0.1).
    #[arg(long, allow_hyphen_values = true, value_parser = super::rtol)]
    pub rtol: Option<f64>,
    /// Solver absolute tolerance for displacements, in (1e-15 to 1e-3), or with its unit
    /// (mm).
    #[arg(long, value_name = "IN", allow_hyphen_values = true, value_parser = super::atol)]
    pub atol: Option<f64>,
    /// Largest double step, fraction of a revolution (default 1/2000; the reduced
    /// followers take longer steps: 0.01 lets the controller decide).
    #[arg(long, value_name = "FRACTION", allow_hyphen_values = true, value_parser = super::max_step_fraction)]
    pub max_step_fraction: Option<f64>,
    /// How England's method controls its step (default "scaled-cap": the stiffness cap
    /// scaled by rtol, so the error follows rtol; "thesis": the thesis's rule, uncapped).
    #[arg(long, value_enum, value_name = "CONTROL")]
    pub step_control: Option<StepControlArg>,
    /// The integration method (default "auto": Merson's pair at rtol >= 1e-6, England's
    /// method, the thesis's, below).
    #[arg(long, value_enum, value_name = "METHOD")]
    pub method: Option<super::MethodArg>,
    /// The follower's model: the full chain, or a reduced scene whose stiff DOFs are
    /// quasi-static (docs/MODEL.md §10; a reduced one implies the vertical scene).
    #[arg(long, value_enum, value_name = "MODEL")]
    pub follower: Option<super::FollowerArg>,
}

/// Builds the run specification from the scene (or reference) and the overrides (the
/// option values as clap checked them; the core's checks of the result still apply).
pub fn spec_from(args: &SceneArgs) -> Result<RunSpec> {
    let mut spec = match &args.scene {
        Some(p) => crate::scene::load(p)?,
        None => RunSpec::reference(),
    };
    if let Some(r) = args.rpm {
        spec.design.set_speed_rpm(r).map_err(|e| match e {
            camsim_core::Error::InvalidParameter { rule, .. } => {
                anyhow::anyhow!("--rpm {r}: {rule}")
            }
            other => other.into(),
        })?;
    }
    if args.rise.is_some() || args.ret.is_some() {
        let mut segs: Vec<_> = spec.design.program.segments().to_vec();
        for s in &mut segs {
            match (&mut s.kind, args.rise, args.ret) {
                (SegmentKind::Rise(l), Some(r), _) => *l = r.into(),
                (SegmentKind::Return(l), _, Some(r)) => *l = r.into(),
                _ => {}
            }
        }
        spec.design.program = camsim_core::CamProgram::new(&segs)
            .map_err(|e| camsim_scene_file::refusal("design", e))?;
    }
    if let Some(k) = args.spring_rate {
        // The rate and the mass that goes with it (the one wire-and-coil model).
        spec.design
            .set_spring_rate(k)
            .map_err(|e| anyhow::anyhow!("--spring-rate {k}: {e}"))?;
        // A rate alone is the wire-and-coil model's spring, not the scene's part.
        spec.spring = None;
    }
    if let Some(d) = args.preload_length {
        spec.design.delta_rs = d;
    }
    if let Some(s) = args.start {
        spec.solver.start = s.into();
    }
    if let Some(x) = args.rtol {
        spec.solver.rtol = x;
    }
    if let Some(x) = args.atol {
        spec.solver.atol = x;
    }
    if let Some(x) = args.max_step_fraction {
        spec.solver.max_step_fraction = x;
    }
    if let Some(c) = args.step_control {
        spec.solver.step_control = c.into();
    }
    if let Some(m) = args.method {
        spec.solver.method = m.into();
    }
    if let Some(f) = args.follower {
        spec.dofs.follower = f.into();
        if spec.dofs.follower != camsim_core::FollowerModel::Full {
            spec.dofs.horizontal = false;
        }
    }
    // The core's one validation, its refusals under the scene keys (`design.KEY`).
    spec.solver
        .validate()
        .map_err(|e| camsim_scene_file::refusal("solver", e))?;
    spec.design
        .validate()
        .map_err(|e| camsim_scene_file::refusal("design", e))?;
    Ok(spec)
}
