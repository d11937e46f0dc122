//! The follower train's translating mass by its parts.

use camsim_core::Design;
use serde::Serialize;

use crate::units::{Units, Weight};

/// The follower train's translating mass by its parts (weights, lb), as the model has it
/// (docs/MODEL.md §5.1): the load takes what the rest leaves when a scene gives
/// `moving_mass_kg|lb`.
#[derive(Clone, Debug, Serialize)]
pub struct MassVerdict {
    /// The whole translating mass.
    pub moving_mass_lb: Weight,
    /// M_l, the load.
    pub load_mass_lb: Weight,
    /// ρ A (e1 + e2), the follower rod.
    pub rod_mass_lb: Weight,
    /// M_r, the roller.
    pub roller_mass_lb: Weight,
    /// A third of the return spring.
    pub spring_share_mass_lb: Weight,
}

/// Standard gravity, in/s² (a pound-mass is 1/g lb·s²/in).
const G: f64 = camsim_scene_file::units::G_IN_PER_S2;

/// The mass verdict of `design`.
pub fn mass(design: &Design<f64>) -> MassVerdict {
    let m = design.moving_mass();
    MassVerdict {
        moving_mass_lb: Weight::inch(m.total() * G),
        load_mass_lb: Weight::inch(m.load * G),
        rod_mass_lb: Weight::inch(m.rod * G),
        roller_mass_lb: Weight::inch(m.roller * G),
        spring_share_mass_lb: Weight::inch(m.spring_share * G),
    }
}

/// The verdict's mass line.
pub(super) fn mass_text(m: &MassVerdict, units: Units) -> String {
    use crate::units as u;
    let q = |x: Weight| units.show(x, 4);
    format!(
        "  mass:      moving {} {w} = load {} + rod rho*A*(e1+e2) {} + roller {} + a third of the spring {}",
        q(m.moving_mass_lb),
        q(m.load_mass_lb),
        q(m.rod_mass_lb),
        q(m.roller_mass_lb),
        q(m.spring_share_mass_lb),
        w = units.symbol(u::WEIGHT)
    )
}
