//! The one table of dimensional scene keys and their two unit families: every key with a
//! unit reads in the inch family of the thesis (`base_radius_in`, `spring_rate_lb_per_in`,
//! the names the core's [`camsim_core::key`] gives and `camsim scene` writes) or in SI
//! (`base_radius_mm`, `spring_rate_n_per_mm`): the same stem with the other family's
//! suffix, converted by an exact factor as the file is read. A file may mix the families;
//! giving one quantity in both is refused, naming both keys.
//!
//! The factors are exact by definition: 1 in = 25.4 mm (international inch, 1959) and
//! 1 lbf = 4.4482216152605 N (the international pound, 0.45359237 kg, times standard
//! gravity 9.80665 m/s²); every other factor is a product of these.

use camsim_core::key;

/// One pound-force, N (exact: 0.45359237 kg × 9.80665 m/s²).
pub const N_PER_LBF: f64 = 4.448_221_615_260_5;
/// One inch, mm (exact).
pub const MM_PER_IN: f64 = 25.4;
/// One inch, m (exact).
const M_PER_IN: f64 = 0.0254;

/// A unit as the two families name it in a key's suffix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unit {
    /// The inch family's key suffix (`lb_per_in`).
    pub inch: &'static str,
    /// The SI family's key suffix (`n_per_mm`).
    pub si: &'static str,
    /// SI units per inch-family unit: a value in SI is the inch value times this.
    pub si_per_inch: f64,
    /// The inch unit as a designer writes it (`lb/in`).
    pub inch_symbol: &'static str,
    /// The SI unit as a designer writes it (`N/mm`).
    pub si_symbol: &'static str,
}

/// Lengths: in, mm.
pub const LENGTH: Unit = Unit {
    inch: "in",
    si: "mm",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in",
    si_symbol: "mm",
};
/// Areas: in², mm².
pub const AREA: Unit = Unit {
    inch: "in2",
    si: "mm2",
    si_per_inch: MM_PER_IN * MM_PER_IN,
    inch_symbol: "in^2",
    si_symbol: "mm^2",
};
/// Second moments of area: in⁴, mm⁴.
pub const SECOND_MOMENT: Unit = Unit {
    inch: "in4",
    si: "mm4",
    si_per_inch: MM_PER_IN * MM_PER_IN * MM_PER_IN * MM_PER_IN,
    inch_symbol: "in^4",
    si_symbol: "mm^4",
};
/// Translational stiffness (spring rates): lb/in, N/mm.
pub const STIFFNESS: Unit = Unit {
    inch: "lb_per_in",
    si: "n_per_mm",
    si_per_inch: N_PER_LBF / MM_PER_IN,
    inch_symbol: "lb/in",
    si_symbol: "N/mm",
};
/// Translational viscous damping: lb·s/in, N·s/m.
pub const DAMPING: Unit = Unit {
    inch: "lb_s_per_in",
    si: "n_s_per_m",
    si_per_inch: N_PER_LBF / M_PER_IN,
    inch_symbol: "lb s/in",
    si_symbol: "N s/m",
};
/// Masses: lb·s²/in, kg.
pub const MASS: Unit = Unit {
    inch: "lb_s2_per_in",
    si: "kg",
    si_per_inch: N_PER_LBF / M_PER_IN,
    inch_symbol: "lb s^2/in",
    si_symbol: "kg",
};
/// Densities: lb·s²/in⁴, kg/m³.
pub const DENSITY: Unit = Unit {
    inch: "lb_s2_per_in4",
    si: "kg_per_m3",
    si_per_inch: N_PER_LBF / (M_PER_IN * M_PER_IN * M_PER_IN * M_PER_IN),
    inch_symbol: "lb s^2/in^4",
    si_symbol: "kg/m^3",
};
/// Stresses and moduli: psi, MPa.
pub const STRESS: Unit = Unit {
    inch: "psi",
    si: "mpa",
    si_per_inch: N_PER_LBF / (MM_PER_IN * MM_PER_IN),
    inch_symbol: "psi",
    si_symbol: "MPa",
};
/// Polar moments of inertia: lb·in·s², kg·m².
pub const INERTIA: Unit = Unit {
    inch: "lb_in_s2",
    si: "kg_m2",
    si_per_inch: N_PER_LBF * M_PER_IN,
    inch_symbol: "lb in s^2",
    si_symbol: "kg m^2",
};
/// Torsional viscous damping: lb·in·s (per rad), N·m·s.
pub const TORSIONAL_DAMPING: Unit = Unit {
    inch: "lb_in_s",
    si: "n_m_s",
    si_per_inch: N_PER_LBF * M_PER_IN,
    inch_symbol: "lb in s",
    si_symbol: "N m s",
};
/// Torsional stiffness: lb·in/rad, N·m/rad.
pub const TORSIONAL_STIFFNESS: Unit = Unit {
    inch: "lb_in_per_rad",
    si: "n_m_per_rad",
    si_per_inch: N_PER_LBF * M_PER_IN,
    inch_symbol: "lb in/rad",
    si_symbol: "N m/rad",
};
/// Torques: lb·in, N·m.
pub const TORQUE: Unit = Unit {
    inch: "lb_in",
    si: "n_m",
    si_per_inch: N_PER_LBF * M_PER_IN,
    inch_symbol: "lb in",
    si_symbol: "N m",
};
/// A drive's proportional gain: lb·in·s/rad, N·m·s/rad.
pub const GAIN: Unit = Unit {
    inch: "lb_in_s_per_rad",
    si: "n_m_s_per_rad",
    si_per_inch: N_PER_LBF * M_PER_IN,
    inch_symbol: "lb in s/rad",
    si_symbol: "N m s/rad",
};
/// Speeds: in/s, mm/s.
pub const SPEED: Unit = Unit {
    inch: "in_per_s",
    si: "mm_per_s",
    si_per_inch: MM_PER_IN,
    inch_symbol: "in/s",
    si_symbol: "mm/s",
};

/// Masses a designer weighs: lb (pound-mass), kg (exact: 0.45359237 kg).
pub const POUND_MASS: Unit = Unit {
    inch: "lb",
    si: "kg",
    si_per_inch: 0.453_592_37,
    inch_symbol: "lb",
    si_symbol: "kg",
};
/// Standard gravity in the inch family, in/s² (exact: 9.80665 m/s² over 0.0254 m/in): a
/// pound-mass is 1/g lb·s²/in.
pub const G_IN_PER_S2: f64 = 9.806_65 / M_PER_IN;
/// The `[design]` table's moving mass (lb; `_kg` in SI): the follower train's whole
/// translating mass, from which the reader sets the load mass (camsim-core's
/// `Design::set_moving_mass`, docs/MODEL.md §5.1). Not a field of the design.
pub const MOVING_MASS: &str = "moving_mass_lb";
/// `[design.spring]`'s free length (in; `_mm` in SI).
pub const SPRING_FREE_LENGTH: &str = "spring.free_length_in";

/// `[design.drive.motor]`: the rotor's polar moment of inertia (becomes the design's I_m).
pub const MOTOR_INERTIA: &str = "drive.motor.inertia_lb_in_s2";
/// `[design.drive.motor]`: the motor-coupling shaft's torsional stiffness (becomes K_s1).
pub const MOTOR_SHAFT_STIFFNESS: &str = "drive.motor.shaft_stiffness_lb_in_per_rad";
/// `[design.drive.motor]`: the speed regulator's proportional gain (becomes k_p).
pub const MOTOR_GAIN: &str = "drive.motor.gain_lb_in_s_per_rad";
/// `[design.drive.motor]`: the motor's torque limit (becomes t_max).
pub const MOTOR_TORQUE_LIMIT: &str = "drive.motor.torque_limit_lb_in";

/// The `[limits]` table's allowable contact stress (psi; `_mpa` in SI).
pub const ALLOWABLE_CONTACT_STRESS: &str = "allowable_contact_stress_psi";
/// The `[limits]` table's pressure-angle limit, degrees (no other family).
pub const PRESSURE_ANGLE_LIMIT: &str = "pressure_angle_limit_deg";

/// A dimensional scene key: the section it is under (`design`, `solver`, `limits`, or
/// `design.program.segment` for every segment), its inch-family name there (the core's
/// key: `geometry.base_radius_in` under `design`) and its unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnitKey {
    /// The section (dotted path from the file's root; arrays of tables without an index).
    pub section: &'static str,
    /// The key's inch-family path in the section, its unit suffix last
    /// (`spring_rate_lb_per_in`, `geometry.base_radius_in`).
    pub key: &'static str,
    /// Its unit.
    pub unit: &'static Unit,
}

impl UnitKey {
    /// The table the key is in (`design.geometry`).
    pub fn table(&self) -> String {
        match self.key.rsplit_once('.') {
            Some((t, _)) => format!("{}.{t}", self.section),
            None => self.section.to_string(),
        }
    }

    /// The key's inch-family name in its table (`base_radius_in`).
    pub fn inch(&self) -> &'static str {
        self.key.rsplit('.').next().unwrap_or(self.key)
    }

    /// The quantity's name without a unit (`base_radius`).
    pub fn stem(&self) -> &'static str {
        let inch = self.inch();
        inch.strip_suffix(self.unit.inch)
            .and_then(|s| s.strip_suffix('_'))
            .unwrap_or(inch)
    }

    /// The key's SI name in its table (`base_radius_mm`).
    pub fn si(&self) -> String {
        format!("{}_{}", self.stem(), self.unit.si)
    }
}

/// A design key (the core's, relative to `[design]`) with its unit.
const fn design(key: &'static str, unit: &'static Unit) -> UnitKey {
    UnitKey {
        section: "design",
        key,
        unit,
    }
}

/// Every dimensional scene key, with its unit: the one table the reader converts by,
/// and docs/MODEL.md's key table lists (a test checks the two agree). Keys without a
/// unit (ratios, coefficients) and keys already in SI units (radians, rad/s, degrees)
/// have one name only.
pub const UNIT_KEYS: &[UnitKey] = &[
    design(key::I_M, &INERTIA),
    design(key::I_CP, &INERTIA),
    design(key::I_C, &INERTIA),
    design(key::C_MB, &TORSIONAL_DAMPING),
    design(key::C_S1, &TORSIONAL_DAMPING),
    design(key::C_S2, &TORSIONAL_DAMPING),
    design(key::C_CC, &TORSIONAL_DAMPING),
    design(key::K_S1, &TORSIONAL_STIFFNESS),
    design(key::K_S2, &TORSIONAL_STIFFNESS),
    design(key::M_C, &MASS),
    design(key::K_VS, &STIFFNESS),
    design(key::C_VS, &DAMPING),
    design(key::K_HS, &STIFFNESS),
    design(key::C_HS, &DAMPING),
    design(key::M_R, &MASS),
    design(key::K_RB, &STIFFNESS),
    design(key::RHO, &DENSITY),
    design(key::YOUNGS, &STRESS),
    design(key::AREA, &AREA),
    design(key::INERTIA_MOMENT, &SECOND_MOMENT),
    design(key::E1, &LENGTH),
    design(key::E2, &LENGTH),
    design(key::BEARING_A, &LENGTH),
    design(key::BEARING_B, &LENGTH),
    design(key::FRICTION_SMOOTHING, &SPEED),
    design(key::M_L, &MASS),
    design(MOVING_MASS, &POUND_MASS),
    design(key::M_SPRING, &MASS),
    design(key::K_RS, &STIFFNESS),
    design(key::DELTA_RS, &LENGTH),
    design(key::K_RS_MODAL, &STIFFNESS),
    design(camsim_core::spring_key::WIRE, &LENGTH),
    design(camsim_core::spring_key::MEAN, &LENGTH),
    design(camsim_core::spring_key::SHEAR, &STRESS),
    design(camsim_core::spring_key::DENSITY, &DENSITY),
    design(camsim_core::spring_key::ALLOWABLE, &STRESS),
    design(SPRING_FREE_LENGTH, &LENGTH),
    design(key::BASE_RADIUS, &LENGTH),
    design(key::ROLLER_RADIUS, &LENGTH),
    design(key::THICKNESS, &LENGTH),
    design(key::ROLLER_YOUNGS, &STRESS),
    design(key::CAM_YOUNGS, &STRESS),
    design(key::CONTACT_LENGTH, &LENGTH),
    design(key::DRIVE_T_STEADY, &TORQUE),
    design(key::DRIVE_K_P, &GAIN),
    design(key::DRIVE_T_MAX, &TORQUE),
    design(MOTOR_INERTIA, &INERTIA),
    design(MOTOR_SHAFT_STIFFNESS, &TORSIONAL_STIFFNESS),
    design(MOTOR_GAIN, &GAIN),
    design(MOTOR_TORQUE_LIMIT, &TORQUE),
    UnitKey {
        section: "design.program.segment",
        key: "lift_in",
        unit: &LENGTH,
    },
    UnitKey {
        section: "solver",
        key: key::ATOL,
        unit: &LENGTH,
    },
    UnitKey {
        section: "limits",
        key: ALLOWABLE_CONTACT_STRESS,
        unit: &STRESS,
    },
];

/// The dimensional key of `table` whose inch or SI name is `name`, and whether `name` is
/// the SI one.
pub fn lookup(table: &str, name: &str) -> Option<(&'static UnitKey, bool)> {
    UNIT_KEYS
        .iter()
        .filter(|k| k.table() == table)
        .find_map(|k| {
            if k.inch() == name {
                Some((k, false))
            } else if k.si() == name {
                Some((k, true))
            } else {
                None
            }
        })
}

/// The SI name of a table's inch-family key, if it has one.
pub fn si_name(table: &str, inch: &str) -> Option<String> {
    UNIT_KEYS
        .iter()
        .find(|k| k.table() == table && k.inch() == inch)
        .map(UnitKey::si)
}

/// [`UNIT_KEYS`] as the Markdown table docs/MODEL.md §1.4 prints (a test checks the
/// document holds exactly this table).
pub fn markdown_table() -> String {
    let mut out = String::from(
        "| table | inch key | SI key | SI per inch unit |\n| --- | --- | --- | --- |\n",
    );
    for k in UNIT_KEYS {
        out += &format!(
            "| `[{}]` | `{}` ({}) | `{}` ({}) | {:?} |\n",
            k.table(),
            k.inch(),
            k.unit.inch_symbol,
            k.si(),
            k.unit.si_symbol,
            k.unit.si_per_inch
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_model_document_lists_the_table() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/MODEL.md");
        let doc = std::fs::read_to_string(path).unwrap();
        let (begin, end) = ("<!-- unit-keys:begin -->\n", "<!-- unit-keys:end -->");
        let body = doc
            .split_once(begin)
            .and_then(|(_, r)| r.split_once(end))
            .map(|(t, _)| t)
            .expect("docs/MODEL.md has the unit-keys markers");
        let table = markdown_table();
        assert!(
            body == table,
            "docs/MODEL.md's key table differs from units::UNIT_KEYS; between its unit-keys \
             markers it should read:\n{table}"
        );
    }

    #[test]
    fn every_design_key_with_an_inch_unit_is_in_the_table() {
        // The core's design keys either have a row here (rebuilt to the core's name) or
        // carry no inch-family unit.
        let si_or_none = [
            "rad_per_s",
            "_rad",
            "ratio",
            "coefficient",
            "poisson",
            "damping_ratio_f1",
        ];
        for (k, _) in key::DESIGN_KEYS {
            let row = UNIT_KEYS
                .iter()
                .find(|u| u.section == "design" && u.key == *k);
            match row {
                Some(u) => assert!(k.ends_with(&format!("_{}", u.unit.inch)), "{k}"),
                None => assert!(
                    si_or_none.iter().any(|s| k.ends_with(s)),
                    "{k} has no unit row"
                ),
            }
        }
    }

    #[test]
    fn names_and_factors() {
        let (k, si) = lookup("design", "spring_rate_n_per_mm").unwrap();
        assert!(si);
        assert_eq!(k.inch(), "spring_rate_lb_per_in");
        assert_eq!(
            lookup("design.geometry", "base_radius_mm")
                .unwrap()
                .0
                .inch(),
            "base_radius_in"
        );
        assert_eq!(
            si_name("design", "follower_density_lb_s2_per_in4").unwrap(),
            "follower_density_kg_per_m3"
        );
        assert_eq!(
            si_name("design.drive.regulated", "k_p_lb_in_s_per_rad").unwrap(),
            "k_p_n_m_s_per_rad"
        );
        // Independent values: 1 lb/in = 175.1268 N/m; 1 psi = 6894.757 Pa; steel's
        // 7.3e-4 lb s^2/in^4 is 7800 kg/m^3; 1 lb s^2/in = 175.1268 kg.
        assert!((STIFFNESS.si_per_inch * 1000.0 - 175.126_835_246_476).abs() < 1e-9);
        assert!((STRESS.si_per_inch * 1e6 - 6_894.757_293_168).abs() < 1e-6);
        assert!((DENSITY.si_per_inch * 7.3e-4 - 7_801.43).abs() < 0.01);
        assert!((MASS.si_per_inch - 175.126_835_246_476).abs() < 1e-9);
        // Every SI name is unique in its table and differs from every inch name.
        for a in UNIT_KEYS {
            for b in UNIT_KEYS {
                if a.table() == b.table() && a.inch() != b.inch() {
                    assert_ne!(a.si(), b.si());
                    assert_ne!(a.si(), b.inch());
                }
            }
        }
    }
}
