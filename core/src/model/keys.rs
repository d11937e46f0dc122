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
//!
//! Every numeric key has a physical plausibility range ([`key::RANGES`], [`key::Range`]),
//! each with its reason at its constant and in docs/MODEL.md §5.16: the one table that
//! [`crate::Design::validate`], [`crate::SolverSettings::validate`] and the host's option
//! parsers check.

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
    /// [`crate::SolverSettings::step_control`].
    pub const STEP_CONTROL: &str = "step_control";
    /// [`crate::SolverSettings::method`].
    pub const METHOD: &str = "method";
    /// Every solver key.
    pub const SOLVER_KEYS: &[&str] = &[
        RTOL,
        ATOL,
        MAX_STEP_FRACTION,
        MAX_STEPS_PER_REV,
        START,
        STEP_CONTROL,
        METHOD,
    ];

    /// The cam speed in rpm: the name [`crate::Design::set_speed_rpm`]'s refusals use (the
    /// host's scene key `run.rpm`, its option `--rpm`).
    pub const RPM: &str = "rpm";

    // --- plausibility ranges ---

    /// A physical plausibility range: a value must be finite and lie in `[min, max]`
    /// (in the key's unit). `rule` is the refusal's text; the reason for each range is
    /// given at its constant below and in docs/MODEL.md §5.16.
    ///
    /// The ranges are wide (most span several decades around the reference value): they
    /// refuse what no cam mechanism has (a 1e300 in base circle, a 1e-300 psi modulus),
    /// so that nothing the model cannot mean runs to a "successful" result, and keep
    /// every derived quantity (frequencies, step sizes, the step budget) within what
    /// the solver handles in `f32` as in `f64`.
    #[derive(Clone, Copy, Debug, PartialEq)]
    pub struct Range {
        /// Smallest plausible value.
        pub min: f64,
        /// Largest plausible value.
        pub max: f64,
        /// The rule a refusal states (`must lie in [0.01, 100] in (...)`).
        pub rule: &'static str,
    }

    impl Range {
        /// Whether `value` is finite and within `[min, max]`.
        pub fn contains(&self, value: f64) -> bool {
            value.is_finite() && value >= self.min && value <= self.max
        }

        /// `value` if it is finite and within the range (compared in `T`: the bounds
        /// are converted with [`crate::Real::from_f64`]), else the refusal naming `field`.
        /// One copy (a validation checks some fifty keys: inlined, they cost the chip
        /// kilobytes of flash).
        #[inline(never)]
        pub fn check<T: crate::Real>(&self, field: &'static str, value: T) -> crate::Result<T> {
            if value.is_finite() && value >= T::from_f64(self.min) && value <= T::from_f64(self.max)
            {
                Ok(value)
            } else {
                Err(crate::Error::InvalidParameter {
                    field,
                    rule: self.rule,
                    value: value.to_f64(),
                })
            }
        }
    }

    /// Polar moments of inertia, lb·in·s²: 1e-6 (a steel disc 1 in across and 0.1 in
    /// thick, 7e-6) to 1e5 (a press flywheel 80 in across, 1.5e4).
    pub const INERTIA: Range = Range {
        min: 1e-6,
        max: 1e5,
        rule: "must lie in [1e-6, 1e5] lb in s^2 (a small disc to a press flywheel)",
    };
    /// Torsional viscous damping, lb·in·s/rad: 0 (none) to 1e4, which at 1 rad/s of
    /// slip already takes 1e4 lb·in, more than the reference drive's breakdown torque
    /// (345 lb·in) 30 times over.
    pub const TORSIONAL_DAMPING: Range = Range {
        min: 0.0,
        max: 1e4,
        rule: "must lie in [0, 1e4] lb in s/rad (none to far beyond any bearing drag)",
    };
    /// Torsional shaft stiffness, lb·in/rad: 1e2 (a steel shaft 0.25 in across and
    /// 10 in long, G J / L = 440) to 1e10 (10 in across and 1 in long, 1.1e10).
    pub const TORSIONAL_STIFFNESS: Range = Range {
        min: 1e2,
        max: 1e10,
        rule: "must lie in [1e2, 1e10] lb in/rad (a thin long shaft to a short massive one)",
    };
    /// Free play of the coupling-cam connection, rad: 0 (none, the reference) to π (half
    /// a turn: a connection looser than that no longer couples; worn keyways and gear
    /// pairs have milliradians).
    pub const BACKLASH: Range = Range {
        min: 0.0,
        max: core::f64::consts::PI,
        rule: "must lie in [0, 3.14] rad (none to half a turn of free play)",
    };
    /// Cam speed, rpm: 1 (a cam that turns once a minute) to 10 000 (above any cam
    /// drive: automotive valve trains turn their cams at up to about 4 000 rpm).
    pub const SPEED_RPM: Range = Range {
        min: 1.0,
        max: 10_000.0,
        rule: "must lie in [1, 10000] rpm (once a minute to above any cam drive)",
    };
    /// Cam speed, rad/s: [`SPEED_RPM`] in rad/s, 2π/60 to 2π·10 000/60 (rounded out).
    pub const SPEED_RAD_PER_S: Range = Range {
        min: 0.1047,
        max: 1047.2,
        rule: "must lie in [0.1047, 1047.2] rad/s (1 to 10000 rpm)",
    };
    /// Masses, lb·s²/in: 1e-6 (0.4 g) to 10 (a 3 860 lb slide).
    pub const MASS: Range = Range {
        min: 1e-6,
        max: 10.0,
        rule: "must lie in [1e-6, 10] lb s^2/in (0.4 g to 3860 lb)",
    };
    /// The return spring's mass, lb·s²/in: [`MASS`]'s upper end, and 0 (a massless
    /// spring, as the printed model without F.1).
    pub const SPRING_MASS: Range = Range {
        min: 0.0,
        max: 10.0,
        rule: "must lie in [0, 10] lb s^2/in (massless to 3860 lb)",
    };
    /// Translational stiffness, lb/in: 1e2 (a soft mount) to 1e10 (beyond the stiffest
    /// steel shafts and bearings; the reference's are 1.5e6, its Hertz contact 6.5e6).
    pub const STIFFNESS: Range = Range {
        min: 1e2,
        max: 1e10,
        rule: "must lie in [1e2, 1e10] lb/in (a soft mount to beyond a massive steel shaft)",
    };
    /// Translational viscous damping, lb·s/in: 0 to 1e5 (above critical damping of
    /// the reference's supports, 2√(K_vs M_c) ≈ 400 lb·s/in).
    pub const DAMPING: Range = Range {
        min: 0.0,
        max: 1e5,
        rule: "must lie in [0, 1e5] lb s/in (none to far beyond critical damping)",
    };
    /// Damping ratios: 0 (undamped, the printed model) to 1 (critical damping; a
    /// structural or bearing damping ratio is a few hundredths, V.14).
    pub const DAMPING_RATIO: Range = Range {
        min: 0.0,
        max: 1.0,
        rule: "must lie in [0, 1] (undamped to critically damped)",
    };
    /// Densities, lb·s²/in⁴: 1e-5 (a foamed polymer, 0.004 lb/in³) to 3e-3 (above
    /// tungsten alloys, 1.8e-3); steel is 7.3e-4.
    pub const DENSITY: Range = Range {
        min: 1e-5,
        max: 3e-3,
        rule: "must lie in [1e-5, 3e-3] lb s^2/in^4 (a foamed polymer to tungsten)",
    };
    /// Young's moduli, psi: 1e5 (a soft engineering polymer) to 1e10 (sixty times
    /// diamond's 1.7e8: the near-rigid limit a study may take, steel's 3e7 scaled by
    /// 100 and more).
    pub const MODULUS: Range = Range {
        min: 1e5,
        max: 1e10,
        rule: "must lie in [1e5, 1e10] psi (a soft polymer to a near-rigid limit)",
    };
    /// Poisson's ratios: 0 to 0.5 (the incompressible limit; the contact data refuse
    /// 0.5 itself).
    pub const POISSON: Range = Range {
        min: 0.0,
        max: 0.5,
        rule: "must be in [0, 0.5)",
    };
    /// Cross-sections, in²: 1e-4 (a rod 0.011 in across) to 1e3 (36 in across).
    pub const CROSS_SECTION: Range = Range {
        min: 1e-4,
        max: 1e3,
        rule: "must lie in [1e-4, 1e3] in^2 (a wire to a 36 in column)",
    };
    /// Second moments of area, in⁴: 1e-9 (a round rod 0.012 in across) to 1e6.
    pub const SECOND_MOMENT: Range = Range {
        min: 1e-9,
        max: 1e6,
        rule: "must lie in [1e-9, 1e6] in^4 (a wire to a 36 in column)",
    };
    /// Lengths and radii, in: 0.01 (a watch part) to 100 (an 8 ft machine part).
    pub const LENGTH: Range = Range {
        min: 0.01,
        max: 100.0,
        rule: "must lie in [0.01, 100] in (a watch part to an 8 ft machine part)",
    };
    /// Lengths that may vanish (a lever, an assembly compression, a dwell's lift), in:
    /// 0 to 100.
    pub const LENGTH_OR_ZERO: Range = Range {
        min: 0.0,
        max: 100.0,
        rule: "must lie in [0, 100] in (none to an 8 ft machine part)",
    };
    /// Friction coefficients: 0 (frictionless) to 1 (dry clean steel on steel is about
    /// 0.8; a lubricated slide bearing 0.05-0.1, VI.1's 0.08).
    pub const FRICTION: Range = Range {
        min: 0.0,
        max: 1.0,
        rule: "must lie in [0, 1] (frictionless to dry clean steel)",
    };
    /// The friction's smoothing speed v_s, in/s: 1e-6 to 10, small against the
    /// follower's speeds (about 100 in/s at the reference's 800 rpm) so that the
    /// tanh law is Coulomb's wherever the follower moves, and not so small that the
    /// solver must resolve a step in force at every reversal (docs/MODEL.md §5.7).
    pub const SMOOTHING: Range = Range {
        min: 1e-6,
        max: 10.0,
        rule: "must lie in [1e-6, 10] in/s (small against the follower's speeds, large enough to resolve)",
    };
    /// Return-spring rates, lb/in: 1e-2 to 1e6 (the reference's 100; a valve spring
    /// is a few hundred).
    pub const SPRING_RATE: Range = Range {
        min: 1e-2,
        max: 1e6,
        rule: "must lie in [0.01, 1e6] lb/in (a hair spring to a die spring stack)",
    };
    /// Motor torques, lb·in: magnitudes up to 1e6 (a 1 000 hp drive at 60 rpm is 1.05e6);
    /// the torque limit at least 1e-2.
    pub const TORQUE_LIMIT: Range = Range {
        min: 1e-2,
        max: 1e6,
        rule: "must lie in [0.01, 1e6] lb in (a fractional to a 1000 hp drive)",
    };
    /// The regulated drive's feed-forward torque, lb·in: -1e6 to 1e6 (as
    /// [`TORQUE_LIMIT`], either sign).
    pub const TORQUE: Range = Range {
        min: -1e6,
        max: 1e6,
        rule: "must lie in [-1e6, 1e6] lb in (up to a 1000 hp drive)",
    };
    /// The regulated drive's proportional gain, lb·in·s/rad: 0 (open loop) to 1e6
    /// (the reference's 41: 1e6 holds a 1 000 hp drive within 1 rad/s).
    pub const GAIN: Range = Range {
        min: 0.0,
        max: 1e6,
        rule: "must lie in [0, 1e6] lb in s/rad (open loop to a 1000 hp drive held within 1 rad/s)",
    };
    /// Relative tolerance: 1e-13 (f64 arithmetic, 2.2e-16 a rounding, cannot meet less
    /// over the steps of a revolution) to 0.1 (the thesis ran at 2 %).
    pub const RTOL_RANGE: Range = Range {
        min: 1e-13,
        max: 0.1,
        rule: "must lie in [1e-13, 0.1] (what f64 arithmetic resolves to 10 %)",
    };
    /// Absolute displacement tolerance, in: 1e-15 to 1e-3 (the deflections the model
    /// resolves are 1e-5 to 1e-3 in: a looser tolerance resolves none of them).
    pub const ATOL_RANGE: Range = Range {
        min: 1e-15,
        max: 1e-3,
        rule: "must lie in [1e-15, 1e-3] in (a looser tolerance resolves no deflection)",
    };
    /// Largest double step, revolutions: 1e-6 (finer needs a million steps a revolution,
    /// half the default budget) to 0.25 (coarser misses the program's periods).
    pub const STEP_FRACTION: Range = Range {
        min: 1e-6,
        max: 0.25,
        rule: "must lie in [1e-6, 0.25] revolution",
    };
    /// Step budget per revolution: 1 to 1e7 (five times the default: 9e7 right-hand
    /// sides, about half a minute a revolution on a PC, so a run of 16 stays bounded; a
    /// step of 1e-6 revolution, the smallest cap, needs 1e6).
    pub const STEPS_PER_REV: Range = Range {
        min: 1.0,
        max: 1e7,
        rule: "must lie in [1, 1e7] (a run stays bounded)",
    };

    /// The plausibility range of every numeric scene key of a design
    /// ([`DESIGN_KEYS`]), of the solver ([`SOLVER_KEYS`] but `start`, `step_control` and `method`) and of [`RPM`];
    /// a segment's `lift_in` takes [`LENGTH_OR_ZERO`]. [`crate::Design::validate`],
    /// [`crate::SolverSettings::validate`] and [`crate::Design::set_speed_rpm`] check
    /// these, and the host's option parsers check the same ranges.
    pub const RANGES: &[(&str, Range)] = &[
        (I_M, INERTIA),
        (I_CP, INERTIA),
        (I_C, INERTIA),
        (C_MB, TORSIONAL_DAMPING),
        (C_S1, TORSIONAL_DAMPING),
        (C_S2, TORSIONAL_DAMPING),
        (C_CC, TORSIONAL_DAMPING),
        (K_S1, TORSIONAL_STIFFNESS),
        (K_S2, TORSIONAL_STIFFNESS),
        (COUPLING_BACKLASH, BACKLASH),
        (OMEGA0, SPEED_RAD_PER_S),
        (M_C, MASS),
        (K_VS, STIFFNESS),
        (C_VS, DAMPING),
        (K_HS, STIFFNESS),
        (C_HS, DAMPING),
        (M_R, MASS),
        (K_RB, STIFFNESS),
        (ROLLER_BEARING_DAMPING_RATIO, DAMPING_RATIO),
        (CONTACT_DAMPING_RATIO, DAMPING_RATIO),
        (RHO, DENSITY),
        (YOUNGS, MODULUS),
        (AREA, CROSS_SECTION),
        (INERTIA_MOMENT, SECOND_MOMENT),
        (E1, LENGTH),
        (E2, LENGTH),
        (BEARING_A, LENGTH_OR_ZERO),
        (BEARING_B, LENGTH),
        (MU, FRICTION),
        (FRICTION_SMOOTHING, SMOOTHING),
        (DAMPING_RATIO_F1, DAMPING_RATIO),
        (M_L, MASS),
        (M_SPRING, SPRING_MASS),
        (K_RS, SPRING_RATE),
        (DELTA_RS, LENGTH_OR_ZERO),
        (K_RS_MODAL, SPRING_RATE),
        (BASE_RADIUS, LENGTH),
        (ROLLER_RADIUS, LENGTH),
        (THICKNESS, LENGTH),
        (ROLLER_YOUNGS, MODULUS),
        (ROLLER_POISSON, POISSON),
        (CAM_YOUNGS, MODULUS),
        (CAM_POISSON, POISSON),
        (CONTACT_LENGTH, LENGTH),
        (DRIVE_OMEGA_REF, SPEED_RAD_PER_S),
        (DRIVE_T_STEADY, TORQUE),
        (DRIVE_K_P, GAIN),
        (DRIVE_T_MAX, TORQUE_LIMIT),
        (RTOL, RTOL_RANGE),
        (ATOL, ATOL_RANGE),
        (MAX_STEP_FRACTION, STEP_FRACTION),
        (MAX_STEPS_PER_REV, STEPS_PER_REV),
        (RPM, SPEED_RPM),
    ];

    /// The plausibility range of `key` (a key of [`RANGES`]).
    pub fn range(key: &str) -> Option<Range> {
        RANGES.iter().find(|(k, _)| *k == key).map(|(_, r)| *r)
    }
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
