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
    /// wide as the roller), or with its unit (500N).
    #[arg(long, value_name = "LB", allow_hyphen_values = true, value_parser = crate::args::force)]
    pub force: f64,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ContactReport) -> String {
    use crate::units::{self as u, given, symbol, value};
    let (l, f, k, st) = (
        symbol(u::LENGTH),
        symbol(u::FORCE),
        symbol(u::STIFFNESS),
        symbol(u::STRESS),
    );
    // V.11's K_h is the stiffness at a unit force: 1 lb (4.448 N in SI).
    let unit_force = match u::current() {
        u::Units::Inch => "K_h (V.11, unit force)",
        u::Units::Si => "K_h (V.11, F = 1 lbf)",
    };
    format!(
        "Hertz contact, roller d1 = {} {l} on base circle d2 = {} {l}, t = {} {l}\n\
         force                      {:>14.6} {f}\n\
         {unit_force:<27}{:>14.6e} {k}\n\
         K_h at force (F/H)         {:>14.6e} {k}\n\
         contact width w (V.9)      {:>14.6e} {l}\n\
         max Hertz stress 2F/(pi b t) {:>12.6e} {st}",
        given(u::LENGTH, 2.0 * r.roller_radius_in),
        given(u::LENGTH, 2.0 * r.base_radius_in),
        given(u::LENGTH, r.thickness_in),
        value(u::FORCE, r.force_lb),
        value(u::STIFFNESS, r.k_h_lb_per_in),
        value(u::STIFFNESS, r.k_h_at_force_lb_per_in),
        value(u::LENGTH, r.contact_width_in),
        value(u::STRESS, r.max_stress_psi)
    )
}

impl Report for ContactReport {
    fn text(&self, _units: crate::units::Units) -> String {
        render_table(self) + "\n"
    }
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
