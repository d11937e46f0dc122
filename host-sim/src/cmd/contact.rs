//! `camsim contact --force F`: Hertz stiffness (Eqs. V.9-V.11), contact width and
//! maximum Hertz stress of the reference roller on the reference cam's base circle (or a
//! scene's pair). The study and its table are [`crate::study::contact`].

pub use crate::study::contact::{
    compute, compute_for, render_table, ContactReport, BASE_CIRCLE_DIAMETER_IN, CAM_THICKNESS_IN,
    ROLLER_DIAMETER_IN,
};

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML, see `camsim scene --default`): its roller, base circle,
    /// thickness and materials (`design.geometry`, `design.hertz`); the reference pair if
    /// omitted.
    #[arg(value_name = "SCENE")]
    pub scene: Option<std::path::PathBuf>,
    /// Contact force in pounds (1e-6 up to about 1.5e6, where the Hertz band is as
    /// wide as the roller), or with its unit (500N).
    #[arg(long, value_name = "LB", allow_hyphen_values = true, value_parser = crate::args::force)]
    pub force: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> anyhow::Result<()> {
    let report = match &args.scene {
        Some(p) => {
            let d = crate::scene::load(p)?.design;
            compute_for(
                args.force,
                &d.hertz,
                d.geometry.roller_radius,
                d.geometry.base_radius,
            )?
        }
        None => compute(args.force)?,
    };
    crate::report::print(&report, args.json, units)
}
