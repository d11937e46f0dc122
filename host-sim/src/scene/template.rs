//! `camsim scene --new`'s template: what a designer must decide, one table for both unit
//! families.

use crate::units::Units;

/// One line of `scene --new`'s template.
enum Line {
    /// The same in both unit families (a table header, a key without a unit, a comment).
    Same(&'static str),
    /// `key = value  # note`: the key in the inch family (its SI name is
    /// [`crate::units::key_in`]'s), a round value in each family.
    Key {
        key: &'static str,
        inch: f64,
        si: f64,
        note: &'static str,
    },
}

use Line::{Key, Same};

/// `scene --new`'s template: what a designer must decide, one table for both unit
/// families. In inch, a machine of the reference's size at 300 rpm with a 0.75 in rise
/// and return; in SI the same machine in round mm, kg and N/mm with a 20 mm lift. The
/// follower rod (0.625 in, 16 mm steel) is light enough for the moving masses a
/// designer of such a cam gives, and its cantilever e2 long enough for a 40 mm lift
/// with a 15 mm roller.
const TEMPLATE: &[Line] = &[
    Same("# Every key not here is the reference design's (docs/MODEL.md section 5).\n\n[run]"),
    Same("rpm = 300.0  # cam speed, rpm\n\n[design]"),
    Key {
        key: "moving_mass_lb",
        inch: 4.5,
        si: 2.0,
        note: "all that translates: load, follower rod, roller and a third of the spring",
    },
    Key {
        key: "spring_rate_lb_per_in",
        inch: 60.0,
        si: 10.0,
        note: "return spring rate (or a [design.spring] part: camsim design spring gives one)",
    },
    Key {
        key: "spring_preload_length_in",
        inch: 1.0,
        si: 25.0,
        note: "how far the spring is compressed with the roller on the base circle",
    },
    Same(
        "drive = \"constant-cam-speed\"  # the cam turns at exactly rpm; or \"thesis\" (its regulated \
         1.75 hp motor), or a [design.drive.motor] table (inertia, shaft_stiffness, gain, torque_limit)",
    ),
    Same("# The follower rod (steel), guided by a slide bearing between the load and the roller:"),
    Key {
        key: "follower_area_in2",
        inch: 0.3068,
        si: 201.06,
        note: "rod cross-section pi d^2/4 (a 16 mm, 0.625 in rod): its mass rho*A*(e1+e2) and axial stiffness E*A/e1, E*A/e2",
    },
    Key {
        key: "follower_second_moment_in4",
        inch: 0.00749,
        si: 3217.0,
        note: "rod second moment of area pi d^4/64 (the same rod): the cantilever's side stiffness 3*E*I/e2^3",
    },
    Key {
        key: "e1_in",
        inch: 6.0,
        si: 150.0,
        note: "rod length from the slide bearing to the load: mass and axial stiffness E*A/e1",
    },
    Key {
        key: "e2_in",
        inch: 3.0,
        si: 80.0,
        note: "rod length from the slide bearing to the roller centre: more than the lift plus the roller radius",
    },
    Key {
        key: "bearing_a_in",
        inch: 3.0,
        si: 80.0,
        note: "lever of the side load from the roller to the near bearing reaction (as e2)",
    },
    Key {
        key: "bearing_b_in",
        inch: 3.0,
        si: 80.0,
        note: "distance between the two bearing reactions: with bearing_a, the friction the side load makes",
    },
    Same("\n[design.geometry]"),
    Key {
        key: "base_radius_in",
        inch: 2.5,
        si: 60.0,
        note: "base circle radius",
    },
    Key {
        key: "roller_radius_in",
        inch: 0.5,
        si: 12.5,
        note: "roller radius",
    },
    Key {
        key: "thickness_in",
        inch: 0.375,
        si: 10.0,
        note: "cam width (its mass)",
    },
    Same("\n[design.hertz]"),
    Key {
        key: "contact_length_in",
        inch: 0.375,
        si: 10.0,
        note: "cam width in contact with the roller (sets the contact stress)",
    },
    Same(
        "\n[[design.program.segment]]  # rise over 120 deg from 0 deg (the roller on the base circle)\n\
         kind = \"rise\"\nlaw = \"modified-sine\"  # camsim laws lists the motion laws\n\
         start_deg = 0.0\nend_deg = 120.0",
    ),
    Key {
        key: "lift_in",
        inch: 0.75,
        si: 20.0,
        note: "lift of this segment",
    },
    Same(
        "\n[[design.program.segment]]  # dwell at full lift\nkind = \"dwell\"\nstart_deg = 120.0\n\
         end_deg = 180.0\n\n[[design.program.segment]]  # return over 120 deg\nkind = \"return\"\n\
         law = \"modified-sine\"  # the return's motion law\nstart_deg = 180.0\nend_deg = 300.0",
    ),
    Key {
        key: "lift_in",
        inch: 0.75,
        si: 20.0,
        note: "the returns undo the rises",
    },
    Same(
        "\n[[design.program.segment]]  # dwell on the base circle\nkind = \"dwell\"\n\
         start_deg = 300.0\nend_deg = 360.0",
    ),
];

/// `scene --new`'s template in `units` (`TEMPLATE`).
pub fn new_template(units: Units) -> String {
    let flag = match units {
        Units::Inch => "",
        Units::Si => " --units si",
    };
    let mut s = format!(
        "# A cam machine in a designer's terms (camsim scene --new{flag}): decide each value, then\n\
         # `camsim scene --check FILE` (everything the model takes from elsewhere) and `camsim run FILE`.\n"
    );
    for line in TEMPLATE {
        match line {
            Same(text) => s.push_str(text),
            Key {
                key,
                inch,
                si,
                note,
            } => {
                let (key, _) = crate::units::key_in(key, units);
                let v = if units == Units::Si { si } else { inch };
                let mut v = format!("{v}");
                if !v.contains('.') {
                    v.push_str(".0");
                }
                s.push_str(&format!("{key} = {v}  # {note}"));
            }
        }
        s.push('\n');
    }
    s
}
