//! The text of `camsim modal` ([`render_table`]) and its JSON (the modal stiffness and
//! mass under keys carrying their system's unit).

use super::{ModalReport, SystemModes};
use crate::report::Report;
use crate::units::measure::kind;
use crate::units::{Kind, Measure, UnitKind as Unit, Units};

fn render_system(out: &mut String, title: &str, s: &SystemModes, units: Units) {
    use std::fmt::Write;
    let _ = writeln!(out, "{title}");
    let _ = writeln!(
        out,
        "  mode  {:>14}  {:>12}  {:>14}  {:>14}  shape ({})",
        "omega rad/s",
        "f Hz",
        "k_modal",
        "m_modal",
        s.coordinates.join(", ")
    );
    for j in 0..s.omega_rad_s.len() {
        let shape: Vec<String> = s.modes[j].iter().map(|v| format!("{v:>10.6}")).collect();
        let rigid = if s.omega_rad_s[j] == 0.0 {
            "  (rigid body)"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "  {:>4}  {:>14.3}  {:>12.3}  {:>14.6e}  {:>14.6e}  [{}]{rigid}",
            j + 1,
            s.omega_rad_s[j],
            s.hz[j],
            units.value(s.stiffness, s.modal_stiffness[j]),
            units.value(s.mass, s.modal_mass[j]),
            shape.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "  modal stiffness in {}, modal mass in {}; modes normalised to the first row (VI.4)",
        units.label(s.stiffness, s.stiffness_unit),
        units.label(s.mass, s.mass_unit)
    );
}

/// Renders the report as the human-readable table.
pub fn render_table(r: &ModalReport, units: Units) -> String {
    let p = &r.parameters;
    // The scene's values: as given in inch; in SI to 5 significant digits (`0.0102` lb
    // in s^2 is `1.1524e-3` kg m^2).
    let conv = |u: Unit, x: f64| match units {
        Units::Inch => format!("{x}"),
        Units::Si => format!("{:.4e}", units.value(u, x)),
    };
    let (i, k) = (
        |x| conv(crate::units::INERTIA, x),
        |x| conv(crate::units::TORSIONAL_STIFFNESS, x),
    );
    let (m, ks) = (
        |x| conv(crate::units::MASS, x),
        |x| conv(crate::units::STIFFNESS, x),
    );
    // The stiffnesses print as `{:e}` in inch (`2e5`).
    let sci = |x: f64, f: &dyn Fn(f64) -> String| match units {
        Units::Inch => format!("{x:e}"),
        Units::Si => f(x),
    };
    let mut out = String::new();
    render_system(
        &mut out,
        &format!(
            "Rotational system (Eq. VI.7): I_m = {}, I_cp = {}, I_c = {} {}; K_s1 = {}, K_s2 = {} {}",
            i(p.i_m.in_inch()),
            i(p.i_cp.in_inch()),
            i(p.i_c.in_inch()),
            units.label(crate::units::INERTIA, "lb*in*s^2"),
            sci(p.k_s1.in_inch(), &k),
            sci(p.k_s2.in_inch(), &k),
            units.label(crate::units::TORSIONAL_STIFFNESS, "lb*in/rad")
        ),
        &r.rotational,
        units,
    );
    out.push('\n');
    render_system(
        &mut out,
        &format!(
            "Translational system (Eq. VI.6): M_r = {}, M_f = {}, M_l = {} {}; K_rb = {}, K_f = {:.6e}, K_rs = {} {}",
            m(p.m_r.in_inch()),
            match units {
                Units::Inch => format!("{:.6}", p.m_f.in_inch()),
                Units::Si => m(p.m_f.in_inch()),
            },
            m(p.m_l.in_inch()),
            units.label(crate::units::MASS, "lb*s^2/in"),
            sci(p.k_rb.in_inch(), &ks),
            units.of(p.k_f),
            ks(p.k_rs.in_inch()),
            units.label(crate::units::STIFFNESS, "lb/in")
        ),
        &r.translational,
        units,
    );
    out
}

impl Report for ModalReport {
    fn text(&self, units: Units) -> String {
        render_table(self, units)
    }
    /// The struct's JSON with the modal stiffness and mass under keys that carry their
    /// system's unit (`modal_stiffness_lb_in_per_rad`, `modal_mass_lb_s2_per_in`), as
    /// measures of the system's kinds, which `--units` converts by their type; the unit
    /// strings in the output's family.
    fn json(&self) -> serde_json::Result<String> {
        let mut v = serde_json::to_value(self)?;
        let (r, t) = (&self.rotational, &self.translational);
        let systems = [
            (
                "rotational",
                r,
                measures::<kind::TorsionalStiffness>(&r.modal_stiffness)?,
                measures::<kind::Inertia>(&r.modal_mass)?,
            ),
            (
                "translational",
                t,
                measures::<kind::Stiffness>(&t.modal_stiffness)?,
                measures::<kind::Mass>(&t.modal_mass)?,
            ),
        ];
        for (name, s, stiffness, mass) in systems {
            if let Some(o) = v.get_mut(name).and_then(|x| x.as_object_mut()) {
                for (key, unit, label, x) in [
                    ("modal_stiffness", s.stiffness, s.stiffness_unit, stiffness),
                    ("modal_mass", s.mass, s.mass_unit, mass),
                ] {
                    o.remove(key);
                    o.insert(format!("{key}_{}", unit.inch), x);
                    o.insert(
                        format!("{}_unit", key.trim_start_matches("modal_")),
                        serde_json::Value::from(self.json_units.label(unit, label)),
                    );
                }
            }
        }
        serde_json::to_string_pretty(&v)
    }
}

/// `xs` (inch-family values) as the JSON of measures of kind `K`.
fn measures<K: Kind>(xs: &[f64]) -> serde_json::Result<serde_json::Value> {
    serde_json::to_value(
        xs.iter()
            .map(|&x| Measure::<K>::inch(x))
            .collect::<Vec<_>>(),
    )
}
