//! Scene keys: the one list of the names a design's parameters have in scene files.
//!
//! Each key is the parameter's serde name (with the `serde` feature) with its unit in
//! the name, and the same string is the `field` of the [`crate::Error::InvalidParameter`]
//! that validation returns, with its section path relative to the [`crate::Design`]
//! (`k_rb_lb_per_in`, `geometry.roller_radius_in`, `program.segment[2].end_deg`).
//! Solver keys ([`key::SOLVER_KEYS`]) are relative to [`crate::SolverSettings`].
//!
//! Serde's `rename` takes only literals, so the literals in the derives repeat these
//! strings; the host's tests check that every key here names a value of the serialized
//! reference design and that every serialized value has a key here.

/// Scene key constants (see the module documentation).
pub mod key {
    // --- rotational system ---
    /// [`crate::Design::i_m`].
    pub const I_M: &str = "i_m_lb_in_s2";
    /// [`crate::Design::i_cp`].
    pub const I_CP: &str = "i_cp_lb_in_s2";
    /// [`crate::Design::i_c`].
    pub const I_C: &str = "i_c_lb_in_s2";
    /// [`crate::Design::c_mb`].
    pub const C_MB: &str = "c_mb_lb_in_s";
    /// [`crate::Design::c_s1`].
    pub const C_S1: &str = "c_s1_lb_in_s";
    /// [`crate::Design::c_s2`].
    pub const C_S2: &str = "c_s2_lb_in_s";
    /// [`crate::Design::c_cc`].
    pub const C_CC: &str = "c_cc_lb_in_s";
    /// [`crate::Design::k_s1`].
    pub const K_S1: &str = "k_s1_lb_in_per_rad";
    /// [`crate::Design::k_s2`].
    pub const K_S2: &str = "k_s2_lb_in_per_rad";
    /// [`crate::Design::omega0`].
    pub const OMEGA0: &str = "omega0_rad_per_s";
    /// [`crate::Design::coupling_backlash`].
    pub const COUPLING_BACKLASH: &str = "coupling_backlash_rad";

    // --- cam and shaft ---
    /// [`crate::Design::m_c`].
    pub const M_C: &str = "cam_mass_lb_s2_per_in";
    /// [`crate::Design::k_vs`].
    pub const K_VS: &str = "k_vs_lb_per_in";
    /// [`crate::Design::c_vs`].
    pub const C_VS: &str = "c_vs_lb_s_per_in";
    /// [`crate::Design::k_hs`].
    pub const K_HS: &str = "k_hs_lb_per_in";
    /// [`crate::Design::c_hs`].
    pub const C_HS: &str = "c_hs_lb_s_per_in";

    // --- roller ---
    /// [`crate::Design::m_r`].
    pub const M_R: &str = "roller_mass_lb_s2_per_in";
    /// [`crate::Design::k_rb`].
    pub const K_RB: &str = "k_rb_lb_per_in";
    /// [`crate::Design::roller_bearing_damping_ratio`].
    pub const ROLLER_BEARING_DAMPING_RATIO: &str = "roller_bearing_damping_ratio";
    /// [`crate::Design::contact_damping_ratio`].
    pub const CONTACT_DAMPING_RATIO: &str = "contact_damping_ratio";

    // --- follower rod ---
    /// [`crate::Design::rho`].
    pub const RHO: &str = "follower_density_lb_s2_per_in4";
    /// [`crate::Design::youngs`].
    pub const YOUNGS: &str = "follower_youngs_psi";
    /// [`crate::Design::area`].
    pub const AREA: &str = "follower_area_in2";
    /// [`crate::Design::inertia_moment`].
    pub const INERTIA_MOMENT: &str = "follower_second_moment_in4";
    /// [`crate::Design::e1`].
    pub const E1: &str = "e1_in";
    /// [`crate::Design::e2`].
    pub const E2: &str = "e2_in";
    /// [`crate::Design::bearing_a`].
    pub const BEARING_A: &str = "bearing_a_in";
    /// [`crate::Design::bearing_b`].
    pub const BEARING_B: &str = "bearing_b_in";
    /// [`crate::Design::mu`].
    pub const MU: &str = "friction_coefficient";
    /// [`crate::Design::friction_smoothing`].
    pub const FRICTION_SMOOTHING: &str = "friction_smoothing_in_per_s";
    /// [`crate::Design::damping_ratio_f1`].
    pub const DAMPING_RATIO_F1: &str = "damping_ratio_f1";
    /// [`crate::Design::m_l`].
    pub const M_L: &str = "load_mass_lb_s2_per_in";
    /// [`crate::Design::m_spring`].
    pub const M_SPRING: &str = "spring_mass_lb_s2_per_in";

    // --- return spring ---
    /// [`crate::Design::k_rs`].
    pub const K_RS: &str = "spring_rate_lb_per_in";
    /// [`crate::Design::delta_rs`].
    pub const DELTA_RS: &str = "spring_preload_length_in";
    /// [`crate::Design::k_rs_modal`].
    pub const K_RS_MODAL: &str = "spring_modal_rate_lb_per_in";

    // --- geometry (`[geometry]`, [`crate::CamGeometry`]) ---
    /// [`crate::CamGeometry::base_radius`].
    pub const BASE_RADIUS: &str = "geometry.base_radius_in";
    /// [`crate::CamGeometry::roller_radius`].
    pub const ROLLER_RADIUS: &str = "geometry.roller_radius_in";
    /// [`crate::CamGeometry::thickness`].
    pub const THICKNESS: &str = "geometry.thickness_in";

    // --- Hertz contact (`[hertz]`, [`crate::HertzContact`]) ---
    /// [`crate::HertzContact::youngs_1`].
    pub const ROLLER_YOUNGS: &str = "hertz.roller_youngs_psi";
    /// [`crate::HertzContact::poisson_1`].
    pub const ROLLER_POISSON: &str = "hertz.roller_poisson";
    /// [`crate::HertzContact::youngs_2`].
    pub const CAM_YOUNGS: &str = "hertz.cam_youngs_psi";
    /// [`crate::HertzContact::poisson_2`].
    pub const CAM_POISSON: &str = "hertz.cam_poisson";
    /// [`crate::HertzContact::thickness`].
    pub const CONTACT_LENGTH: &str = "hertz.contact_length_in";

    // --- drive (`drive = "constant-cam-speed"`, `"constant-motor-speed"` or
    // `[drive.regulated]`, [`crate::DriveLaw`]) ---
    /// The drive law itself.
    pub const DRIVE: &str = "drive";
    /// [`crate::DriveLaw::Regulated`]'s `omega_ref`.
    pub const DRIVE_OMEGA_REF: &str = "drive.regulated.omega_ref_rad_per_s";
    /// [`crate::DriveLaw::Regulated`]'s `t_steady`.
    pub const DRIVE_T_STEADY: &str = "drive.regulated.t_steady_lb_in";
    /// [`crate::DriveLaw::Regulated`]'s `k_p`.
    pub const DRIVE_K_P: &str = "drive.regulated.k_p_lb_in_s_per_rad";
    /// [`crate::DriveLaw::Regulated`]'s `t_max`.
    pub const DRIVE_T_MAX: &str = "drive.regulated.t_max_lb_in";

    // --- program (`[[program.segment]]`, [`crate::CamProgram`]) ---
    /// The program's segment list.
    pub const PROGRAM_SEGMENT: &str = "program.segment";
    /// Keys of one segment, relative to `program.segment[i]`.
    pub const SEGMENT_KEYS: [&str; 5] = ["kind", "law", "start_deg", "end_deg", "lift_in"];

    /// Every scalar key of a design (not the program's segments) with a short description:
    /// the symbol of the thesis where it has one and what the parameter is.
    pub const DESIGN_KEYS: &[(&str, &str)] = &[
        (I_M, "I_m, motor armature polar moment of inertia"),
        (I_CP, "I_cp, coupling polar moment of inertia"),
        (I_C, "I_c, cam polar moment of inertia"),
        (C_MB, "C_mb, motor bearing damping"),
        (C_S1, "C_s1, shaft damping motor-coupling"),
        (C_S2, "C_s2, shaft damping coupling-cam"),
        (C_CC, "C_cc, cam shaft bearing and air damping"),
        (K_S1, "K_s1, shaft stiffness motor-coupling"),
        (K_S2, "K_s2, shaft stiffness coupling-cam"),
        (
            COUPLING_BACKLASH,
            "free play of the coupling-cam connection (Appendix G.1; 0 = none)",
        ),
        (OMEGA0, "initial cam speed (rad/s; run.rpm sets it in rpm)"),
        (M_C, "M_c, mass of cam and shaft"),
        (K_VS, "K_vs, vertical cam shaft stiffness"),
        (C_VS, "C_vs, vertical cam shaft damping"),
        (K_HS, "K_hs, horizontal cam shaft stiffness"),
        (C_HS, "C_hs, horizontal cam shaft damping"),
        (M_R, "M_r, roller mass"),
        (K_RB, "K_rb, roller bearing stiffness"),
        (
            ROLLER_BEARING_DAMPING_RATIO,
            "xi_rb of C_rb, roller bearing damping ratio",
        ),
        (
            CONTACT_DAMPING_RATIO,
            "xi_h of C_h, cam-roller contact damping ratio",
        ),
        (RHO, "rho, follower rod density"),
        (YOUNGS, "E, follower rod Young's modulus"),
        (AREA, "A, follower rod cross-section"),
        (INERTIA_MOMENT, "I, follower rod second moment of area"),
        (E1, "e1, follower length load to slide bearing"),
        (E2, "e2, cantilever length slide bearing to roller"),
        (BEARING_A, "A of Eq. V.16, bearing-to-roller lever"),
        (
            BEARING_B,
            "B of Eq. V.16, distance between the bearing reactions",
        ),
        (MU, "mu, slide bearing friction coefficient"),
        (
            FRICTION_SMOOTHING,
            "smoothing speed v_s of the friction, F = -mu |N| tanh(v / v_s)",
        ),
        (
            DAMPING_RATIO_F1,
            "xi of C_f1, follower structural damping ratio",
        ),
        (M_L, "M_l, load mass"),
        (M_SPRING, "return spring mass (a third joins the follower)"),
        (K_RS, "K_rs, return spring rate"),
        (DELTA_RS, "delta_rs, spring compression at assembly"),
        (K_RS_MODAL, "K_rs of the modal analysis (Eq. VI.6)"),
        (BASE_RADIUS, "R_b, base circle radius"),
        (ROLLER_RADIUS, "r_r, roller radius"),
        (THICKNESS, "t, cam thickness"),
        (ROLLER_YOUNGS, "E_1, roller Young's modulus"),
        (ROLLER_POISSON, "nu_1, roller Poisson's ratio"),
        (CAM_YOUNGS, "E_2, cam Young's modulus"),
        (CAM_POISSON, "nu_2, cam Poisson's ratio"),
        (CONTACT_LENGTH, "axial length of the line contact"),
        (DRIVE_OMEGA_REF, "regulated drive's reference speed"),
        (DRIVE_T_STEADY, "regulated drive's feed-forward torque"),
        (DRIVE_K_P, "regulated drive's proportional gain"),
        (DRIVE_T_MAX, "regulated drive's torque limit"),
    ];

    // --- solver settings ([`crate::SolverSettings`], relative to `[solver]`) ---
    /// [`crate::SolverSettings::rtol`].
    pub const RTOL: &str = "rtol";
    /// [`crate::SolverSettings::atol`].
    pub const ATOL: &str = "atol_in";
    /// [`crate::SolverSettings::max_step_fraction`].
    pub const MAX_STEP_FRACTION: &str = "max_step_fraction_rev";
    /// [`crate::SolverSettings::max_steps_per_rev`].
    pub const MAX_STEPS_PER_REV: &str = "max_steps_per_rev";
    /// [`crate::SolverSettings::start`].
    pub const START: &str = "start";
    /// Every solver key.
    pub const SOLVER_KEYS: &[&str] = &[RTOL, ATOL, MAX_STEP_FRACTION, MAX_STEPS_PER_REV, START];
}

/// `program.segment[i].<field>` as a `&'static str` (no allocation): indices above 15
/// read `program.segment[..]`.
macro_rules! segment_keys {
    ($f:literal) => {
        [
            concat!("program.segment[0].", $f),
            concat!("program.segment[1].", $f),
            concat!("program.segment[2].", $f),
            concat!("program.segment[3].", $f),
            concat!("program.segment[4].", $f),
            concat!("program.segment[5].", $f),
            concat!("program.segment[6].", $f),
            concat!("program.segment[7].", $f),
            concat!("program.segment[8].", $f),
            concat!("program.segment[9].", $f),
            concat!("program.segment[10].", $f),
            concat!("program.segment[11].", $f),
            concat!("program.segment[12].", $f),
            concat!("program.segment[13].", $f),
            concat!("program.segment[14].", $f),
            concat!("program.segment[15].", $f),
            concat!("program.segment[..].", $f),
        ]
    };
}
const SEG_LAW: [&str; 17] = segment_keys!("law");
const SEG_START: [&str; 17] = segment_keys!("start_deg");
const SEG_END: [&str; 17] = segment_keys!("end_deg");
const SEG_LIFT: [&str; 17] = segment_keys!("lift_in");

/// A field of one program segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum SegmentField {
    Law,
    StartDeg,
    EndDeg,
    LiftIn,
}

/// The scene key of `field` of segment `i` (`program.segment[i].end_deg`).
pub(crate) fn segment_key(field: SegmentField, i: usize) -> &'static str {
    let names = match field {
        SegmentField::Law => &SEG_LAW,
        SegmentField::StartDeg => &SEG_START,
        SegmentField::EndDeg => &SEG_END,
        SegmentField::LiftIn => &SEG_LIFT,
    };
    names
        .get(i)
        .or(names.last())
        .copied()
        .unwrap_or(key::PROGRAM_SEGMENT)
}
