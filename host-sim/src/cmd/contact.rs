//! `camsim contact --force F`: Hertz stiffness (Eqs. V.9-V.11), contact width and
//! maximum Hertz stress of the reference roller on the reference cam's base circle.

use crate::report::Report;
pub use crate::study::contact::{
    compute, compute_for, ContactReport, BASE_CIRCLE_DIAMETER_IN, CAM_THICKNESS_IN,
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
    /// wide as the roller).
    #[arg(long, value_name = "LB", allow_hyphen_values = true, value_parser = crate::args::force)]
    pub force: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ContactReport) -> String {
    format!(
        "Hertz contact, roller d1 = {} in on base circle d2 = {} in, t = {} in\n\
         force                      {:>14.6} lb\n\
         K_h (V.11, unit force)     {:>14.6e} lb/in\n\
         K_h at force (F/H)         {:>14.6e} lb/in\n\
         contact width w (V.9)      {:>14.6e} in\n\
         max Hertz stress 2F/(pi b t) {:>12.6e} psi",
        2.0 * r.roller_radius_in,
        2.0 * r.base_radius_in,
        r.thickness_in,
        r.force_lb,
        r.k_h_lb_per_in,
        r.k_h_at_force_lb_per_in,
        r.contact_width_in,
        r.max_stress_psi
    )
}

impl Report for ContactReport {
    fn text(&self) -> String {
        render_table(self) + "\n"
    }
}

/// Runs the command.
pub fn run(args: Args) -> anyhow::Result<()> {
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
    crate::report::print(&report, args.json)
}
