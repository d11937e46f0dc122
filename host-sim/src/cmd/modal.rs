//! `camsim modal [--json]`: natural frequencies, normalised modes and modal stiffness of
//! the linearised rotational (Eq. VI.7) and translational (Eq. VI.6) systems of the
//! reference design or a scene (Section VI.2, Eqs. VI.2-VI.5). The study is
//! [`crate::study::modal`]; this command reads the scene into its [`Spec`], runs it and
//! prints the report.

pub use crate::study::modal::*;

/// Command-line options.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Scene file (TOML, see `camsim scene --default`): its masses, stiffnesses and
    /// `design.spring_modal_rate_lb_per_in`; the reference design if omitted.
    #[arg(value_name = "SCENE")]
    pub scene: Option<std::path::PathBuf>,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// The study's spec: the scene's parameters, or the reference design's.
pub fn spec(args: &Args) -> anyhow::Result<Spec> {
    let parameters = match &args.scene {
        Some(p) => parameters(&crate::scene::load(p)?.design),
        None => reference_parameters()?,
    };
    Ok(Spec { parameters })
}

/// Runs the command.
pub fn run(args: Args, units: crate::units::Units) -> anyhow::Result<()> {
    let report = crate::study::modal::report(&spec(&args)?, units)?;
    crate::report::print(&report, args.json, units)
}
