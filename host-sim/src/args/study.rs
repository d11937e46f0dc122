//! The Monte Carlo study argument group (`camsim montecarlo`, the tolerance grid): how
//! many actual cams, the scene and its reduced models, and how the cams are made.

use super::{ActualArgs, SceneArgs};

/// What a study is: the scene, the reduced-model options and the actual cam.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct StudyArgs {
    /// Number of actual cams.
    #[arg(long, required = true, value_parser = crate::args::whole_u64::<1, 100_000_000>)]
    pub samples: Option<u64>,
    /// The scene and its overrides.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Revolutions to simulate, 1-16 (default 2: the statistics are revolution 2's;
    /// with 1, a reduced study, revolution 1's: give it --start static).
    #[arg(long, value_parser = crate::args::whole_u32::<1, 16>)]
    pub revolutions: Option<u32>,
    /// Reduced model: drop the horizontal motion (x1, x2, x3).
    #[arg(long)]
    pub vertical: bool,
    /// Reduced model: an ideal constant cam speed (no motor, coupling or cam rotation).
    #[arg(long)]
    pub constant_cam_speed: bool,
    /// The actual cams (every sample is one).
    #[command(flatten)]
    pub actual: ActualArgs,
}

impl StudyArgs {
    /// The study these arguments describe (scene loaded and checked, interval chosen).
    pub fn study(&self) -> anyhow::Result<crate::study::montecarlo::Study> {
        let samples = self
            .samples
            .ok_or_else(|| anyhow::anyhow!("--samples N is required"))?;
        let mut spec = super::spec_from(&self.scene)?;
        spec.revolutions = self
            .revolutions
            .unwrap_or(crate::study::montecarlo::REVOLUTION);
        spec.dofs.horizontal &= !self.vertical;
        if self.constant_cam_speed {
            spec.design.drive = camsim_core::DriveLaw::ConstantCamSpeed;
        }
        crate::study::montecarlo::Study::from_spec(spec, &self.actual.cams(), samples)
    }
}
