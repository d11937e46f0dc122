//! The reference design of the thesis (VI.1) and every value it leaves out.
//!
//! This is the one place where the model's parameters live. Values from VI.1 are
//! quoted with their symbol; values the thesis does not give are chosen once here,
//! each with its reason (docs/MODEL.md §5, §6). Nothing here is tuned to
//! reproduce a published figure.

use crate::model::keys::{segment_key, SegmentField};
use crate::{
    non_negative, positive, CamGeometry, CamProgram, DriveLaw, Error, HertzContact, Real, Result,
};

/// Standard gravity in in/s² (9.80665 m/s² is 386.0886 in/s²; 386.09 to the five figures
/// handbooks quote): what turns a weight in pounds into the thesis's mass unit, lb·s²/in
/// (mass = weight / g), and back.
pub const GRAVITY_IN_PER_S2: f64 = 386.09;
/// Pounds-mass per cubic inch of steel (0.2836 lb/in³) over g ([`GRAVITY_IN_PER_S2`]):
/// lb·s²/in⁴.
pub const STEEL_DENSITY: f64 = 0.2836 / GRAVITY_IN_PER_S2;
/// Young's modulus of steel (VI.1), psi.
pub const STEEL_YOUNGS: f64 = 30.0e6;
/// Shear modulus of steel (VI.1), psi.
pub const STEEL_SHEAR: f64 = 11.4e6;
/// Poisson's ratio of steel (VI.1).
pub const STEEL_POISSON: f64 = 0.295;
/// Nominal cam speed of VI.1: 800 rpm.
pub const REFERENCE_RPM: f64 = 800.0;
/// Structural damping ratio for the follower rod C_f1 (Eq. V.13 with ξ = 0.03, V.14).
pub const STRUCTURAL_DAMPING_RATIO: f64 = 0.03;
/// Damping ratio ξ_rb of the roller bearing, C_rb = 2 ξ_rb sqrt(K_rb M_r) (Eq. V.13): 0.05,
/// V.14's lower end for well-lubricated machine parts (the roller's needle bearing is
/// one). docs/MODEL.md §3.13, §3.14, §6.2.
pub const ROLLER_BEARING_DAMPING_RATIO: f64 = 0.05;
/// Return spring rate K_rs of the reference design, lb/in: 100, the rate of VI.2's modal
/// analysis, not VI.1's listed 60 (docs/MODEL.md §6.1). With 60 lb/in and the listed
/// δ_rs = 0.5 in the reference program separates below its own 800 rpm, while the
/// thesis's study results show it running without a jump at 800 rpm with forces that
/// follow from 100 lb/in: a choice between two printed values, not a fit.
pub const REFERENCE_SPRING_RATE: f64 = 100.0;
/// VI.1's listed return spring rate, lb/in (the `scenes/listed-spring-60.toml` variant).
pub const LISTED_SPRING_RATE: f64 = 60.0;
/// Return-spring wire diameter d, in (not given: a steel helical spring, docs/MODEL.md §5.6).
pub const SPRING_WIRE_DIAMETER: f64 = 0.14;
/// Return-spring mean coil diameter D, in (not given, docs/MODEL.md §5.6).
pub const SPRING_MEAN_DIAMETER: f64 = 1.0;
/// Active coils n of the reference spring: k = G d⁴ / (8 D³ n) = 547.4 / n lb/in with
/// G = 11.4e6 psi, d = 0.14 in, D = 1.0 in, so n = 5.47 for 100 lb/in; 5.5 coils give
/// 99.5 lb/in (the listed 60 lb/in spring had 9, 60.8 lb/in).
pub const SPRING_ACTIVE_COILS: f64 = 5.5;
/// Total coils: the active ones plus one closed coil at each end (squared and ground).
pub const SPRING_TOTAL_COILS: f64 = SPRING_ACTIVE_COILS + 2.0;
/// Mass of the reference return spring, lb·s²/in: steel wire of area π d²/4 over
/// π D per coil, 7.5 coils: 0.3627 in³, 0.1029 lb, 2.664e-4 lb·s²/in (the listed
/// 60 lb/in spring, 11 coils, weighed 0.151 lb: the mass goes with the total coils).
pub const SPRING_MASS: f64 = STEEL_DENSITY
    * (core::f64::consts::PI * SPRING_WIRE_DIAMETER * SPRING_WIRE_DIAMETER / 4.0)
    * (core::f64::consts::PI * SPRING_MEAN_DIAMETER)
    * SPRING_TOTAL_COILS;
/// Mass of the listed 60 lb/in spring, lb·s²/in: 9 active, 11 total coils of the same wire
/// and diameter, 0.150869 lb, what [`HelicalSpring::of_rate`] gives for 60 lb/in (before
/// the wire model the listed scene gave the rounded 0.151 lb).
pub const LISTED_SPRING_MASS: f64 = STEEL_DENSITY
    * (core::f64::consts::PI * SPRING_WIRE_DIAMETER * SPRING_WIRE_DIAMETER / 4.0)
    * (core::f64::consts::PI * SPRING_MEAN_DIAMETER)
    * 11.0;
/// Coils of a return spring are counted to a quarter turn ([`HelicalSpring::of_rate`]):
/// the reference's 5.5 and the listed spring's 9 active coils are such counts.
pub const SPRING_COIL_STEP: f64 = 0.25;
/// The fewest active coils the wire model gives (a quarter turn): above
/// G d⁴ / (8 D³ · 0.25) = 2190 lb/in the reference wire cannot make the rate at all and
/// the mass stays that of 2.25 coils.
pub const SPRING_MIN_ACTIVE_COILS: f64 = SPRING_COIL_STEP;
/// A spring's surge (its own first axial mode, both ends fixed) should lie at least this
/// many times above the cam's rotation frequency: a rule of thumb for cam springs
/// (Norton, *Cam Design and Manufacturing Handbook*, spring surge: a cam program's
/// harmonics above about the 13th carry little of its acceleration). `camsim run` warns
/// below it (docs/MODEL.md §5.6).
pub const SURGE_HARMONIC_MARGIN: f64 = 13.0;
/// The largest swing of the cam speed about its nominal, (ω_max − ω_min)'s larger side
/// over ω0, that `camsim run` accepts without a warning: 2 %. Every kinematic design
/// figure (the law's acceleration, the spring's margin, the pressure angle per degree)
/// assumes a constant cam speed; the inertia force goes with ω², so a 2 % swing moves it
/// by about 4 %, beyond which the constant-speed design calculation no longer describes
/// the machine and the drive (motor, shaft, regulator) must be designed with the cam
/// (docs/MODEL.md §5.17). Not from the thesis.
pub const CAM_SPEED_SWING_LIMIT: f64 = 0.02;

/// A spring-wire grade: its shear modulus, density, and static allowable shear stress as
/// a fraction of its tensile strength S_ut = A / d^m (Shigley, *Mechanical Engineering
/// Design*, 9th ed., tables 10-4, 10-5, 10-6; docs/MODEL.md §5.6). The allowable is
/// Shigley's for static service with the set not removed: the cam spring's fatigue is
/// not checked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringWire {
    /// The name a scene writes (`music-wire`).
    pub name: &'static str,
    /// What it is, for a spring maker (`music wire, ASTM A228`).
    pub title: &'static str,
    /// Shear modulus G, psi.
    pub shear_modulus_psi: f64,
    /// Weight density, lb/in³.
    pub weight_density_lb_per_in3: f64,
    /// Diameter bands of table 10-4: (largest d of the band in inches, A in psi·in^m,
    /// m); the last band covers every larger wire.
    pub strength: [(f64, f64, f64); 3],
    /// Allowable static shear stress over S_ut (table 10-6).
    pub static_fraction: f64,
}

impl SpringWire {
    /// Tensile strength S_ut of wire `d` in, psi: A / d^m of d's band.
    pub fn tensile_strength<T: Real>(&self, d: T) -> T {
        let (a, m) = self
            .strength
            .iter()
            .find(|b| d.to_f64() <= b.0)
            .or(self.strength.last())
            .map_or((f64::NAN, 1.0), |b| (b.1, b.2));
        T::from_f64(a) / d.powf(T::from_f64(m))
    }

    /// The material of wire `d` in: G, density, and the allowable static shear stress.
    pub fn material<T: Real>(&self, d: T) -> crate::SpringMaterial<T> {
        crate::SpringMaterial {
            shear_modulus: T::from_f64(self.shear_modulus_psi),
            density: T::from_f64(self.weight_density_lb_per_in3 / GRAVITY_IN_PER_S2),
            allowable_shear: T::from_f64(self.static_fraction) * self.tensile_strength(d),
        }
    }

    /// The grade named `name` (one of [`SPRING_WIRES`]).
    pub fn named(name: &str) -> Option<&'static SpringWire> {
        SPRING_WIRES.iter().find(|w| w.name == name)
    }
}

/// Steel spring wire's weight density, lb/in³ (0.2836: the model's steel, VI.1's).
const SPRING_STEEL_WEIGHT: f64 = 0.2836;

/// The named spring wires (Shigley, tables 10-4 to 10-6): G for wire of about 0.1 in
/// (table 10-5 varies it by a few percent with the diameter), A and m of S_ut = A/d^m, and
/// the static allowable's fraction of S_ut (45 % for cold-drawn music wire, 50 % for
/// hardened and tempered steels, 35 % for austenitic stainless). Stainless 302's weight
/// density, 0.286 lb/in³ (7.92 g/cm³), is AISI 302's.
pub const SPRING_WIRES: [SpringWire; 4] = [
    SpringWire {
        name: "music-wire",
        title: "music wire, ASTM A228",
        shear_modulus_psi: 11.75e6,
        weight_density_lb_per_in3: SPRING_STEEL_WEIGHT,
        strength: [(f64::INFINITY, 201e3, 0.145); 3],
        static_fraction: 0.45,
    },
    SpringWire {
        name: "oil-tempered",
        title: "oil-tempered wire, ASTM A229",
        shear_modulus_psi: 11.2e6,
        weight_density_lb_per_in3: SPRING_STEEL_WEIGHT,
        strength: [(f64::INFINITY, 147e3, 0.187); 3],
        static_fraction: 0.50,
    },
    SpringWire {
        name: "chrome-silicon",
        title: "chrome-silicon wire, ASTM A401",
        shear_modulus_psi: 11.2e6,
        weight_density_lb_per_in3: SPRING_STEEL_WEIGHT,
        strength: [(f64::INFINITY, 202e3, 0.108); 3],
        static_fraction: 0.50,
    },
    SpringWire {
        name: "stainless-302",
        title: "stainless 302 wire, ASTM A313",
        shear_modulus_psi: 10.0e6,
        weight_density_lb_per_in3: 0.286,
        strength: [
            (0.10, 169e3, 0.146),
            (0.20, 128e3, 0.263),
            (f64::INFINITY, 90e3, 0.478),
        ],
        static_fraction: 0.35,
    },
];

/// The wire of a spring given by its rate alone (`--spring-rate`, a scene's rate
/// without `[design.spring]`): [`HelicalSpring`]'s steel of VI.1's G, judged with music
/// wire's allowable (the commonest spring wire).
pub const ASSUMED_SPRING_WIRE: &SpringWire = &SPRING_WIRES[0];

/// Standard wire diameters `camsim design spring` searches, in: the R20 preferred
/// numbers (ISO 3) from 0.5 to 12.5 mm, the series spring-wire sizes are drawn to.
pub const STANDARD_WIRE_DIAMETERS_MM: [f64; 29] = [
    0.5, 0.56, 0.63, 0.71, 0.8, 0.9, 1.0, 1.12, 1.25, 1.4, 1.6, 1.8, 2.0, 2.24, 2.5, 2.8, 3.15,
    3.55, 4.0, 4.5, 5.0, 5.6, 6.3, 7.1, 8.0, 9.0, 10.0, 11.2, 12.5,
];

/// Spring indexes C = D/d `camsim design spring` tries: 4 to 12 in steps of 0.5, Shigley's
/// recommended range (below 4 the coil is hard to wind, above 12 it tangles and buckles).
pub const SPRING_INDEX_RANGE: (f64, f64, f64) = (4.0, 12.0, 0.5);

/// Fractional overrun to closure ξ: a spring's free length leaves 15 % of its working
/// deflection before it is solid, L_0 = L_s + (1 + ξ) y_max (Shigley, ξ ≥ 0.15). `camsim
/// design spring` winds its answer to this free length.
pub const SPRING_CLASH_ALLOWANCE: f64 = 0.15;
/// Allowable Hertz contact stress of the cam and roller, psi: 150 000, the surface
/// endurance strength of through-hardened steel at 400 Brinell for 10⁸ cycles by
/// Buckingham's S_C = 0.4 H_B − 10 kpsi (Shigley, *Mechanical Engineering Design*, surface
/// fatigue). Not in the thesis; `camsim run --allowable-stress` changes it.
pub const ALLOWABLE_CONTACT_STRESS_PSI: f64 = 150_000.0;
/// The largest pressure angle of a translating roller follower that `camsim run` accepts
/// without a warning, degrees: 30, the usual limit for a translating follower (Rothbart,
/// *Cam Design Handbook*; Norton). `camsim run --pressure-angle-limit` changes it.
pub const PRESSURE_ANGLE_LIMIT_DEG: f64 = 30.0;

/// A return spring of the reference wire (d = [`SPRING_WIRE_DIAMETER`]) and coil diameter
/// (D = [`SPRING_MEAN_DIAMETER`]) wound to a rate: the one wire-and-coil model behind
/// every spring rate (`--spring-rate`, a scene's `spring_rate_lb_per_in` without
/// `spring_mass_lb_s2_per_in`, `camsim design spring`), so the spring's mass and surge
/// frequency follow its rate (docs/MODEL.md §5.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HelicalSpring<T> {
    /// The rate asked for, lb/in (the model's K_rs).
    pub rate: T,
    /// Active coils n = G d⁴ / (8 D³ k), to the nearest quarter turn, at least
    /// [`SPRING_MIN_ACTIVE_COILS`].
    pub active_coils: T,
    /// Total coils: the active ones and one closed coil at each end.
    pub total_coils: T,
    /// Mass of the whole spring, lb·s²/in (steel wire of area π d²/4 over π D per coil).
    pub mass: T,
    /// Surge frequency, Hz: the first axial mode of the active coils between fixed ends,
    /// f = ½ √(k / m_active) (k in lb/in, m in lb·s²/in; Wahl's result, Appendix F.2's
    /// wave equation without the rotary inertia).
    pub surge_hz: T,
}

impl<T: Real> HelicalSpring<T> {
    /// The spring of rate `rate` lb/in (positive and finite; the error names
    /// `spring_rate_lb_per_in`).
    pub fn of_rate(rate: T) -> Result<Self> {
        positive(crate::key::K_RS, rate)?;
        let f = T::from_f64;
        let d = f(SPRING_WIRE_DIAMETER);
        let big_d = f(SPRING_MEAN_DIAMETER);
        let exact = f(STEEL_SHEAR) * d * d * d * d / (f(8.0) * big_d * big_d * big_d * rate);
        let step = f(SPRING_COIL_STEP);
        let active = ((exact / step + f(0.5)).floor() * step).max(f(SPRING_MIN_ACTIVE_COILS));
        let total = active + T::TWO;
        // The same product, in the same order, as SPRING_MASS: bit for bit at 5.5 coils.
        let per_coil = f(STEEL_DENSITY) * (T::PI * d * d / f(4.0)) * (T::PI * big_d);
        let mass = per_coil * total;
        let surge_hz = (rate / (per_coil * active)).sqrt() / T::TWO;
        Ok(HelicalSpring {
            rate,
            active_coils: active,
            total_coils: total,
            mass,
            surge_hz,
        })
    }

    /// The part this spring is: the reference wire and coil, squared and ground ends
    /// (two closed coils), VI.1's steel, judged with [`ASSUMED_SPRING_WIRE`]'s allowable.
    pub fn part(&self) -> crate::CoilSpring<T> {
        let d = T::from_f64(SPRING_WIRE_DIAMETER);
        let wire = ASSUMED_SPRING_WIRE.material(d);
        crate::CoilSpring {
            wire_diameter: d,
            mean_diameter: T::from_f64(SPRING_MEAN_DIAMETER),
            active_coils: self.active_coils,
            ends: crate::CoilEnds::SquaredGround,
            material: crate::SpringMaterial {
                shear_modulus: T::from_f64(STEEL_SHEAR),
                density: T::from_f64(STEEL_DENSITY),
                allowable_shear: wire.allowable_shear,
            },
        }
    }
}

/// Damping ratio ξ_h of the cam-roller contact, C_h = 2 ξ_h sqrt(K_h M_r) (Eq. V.13): 0.05,
/// the lower end of V.14's 0.05-0.07 for well-lubricated machine parts (a lubricated
/// rolling contact is one). docs/MODEL.md §6.2.
pub const CONTACT_DAMPING_RATIO: f64 = 0.05;
/// The largest Hertz contact stress a reported result may hold, psi: 1e6 psi, 1.7 times
/// the static contact capacity of hardened bearing steel (4 000 MPa, 5.8e5 psi, ISO 76)
/// and 8 times the reference's peak (1.2e5 psi at 800 rpm). Not from the thesis: a
/// plausibility bound, so that a result no steel cam survives (an edge on a measured
/// profile, a stress of 1e8 psi) is refused instead of reported as a success.
pub const MAX_PLAUSIBLE_CONTACT_STRESS_PSI: f64 = 1.0e6;
/// The largest contact force a reported result may hold, lb: 1e6 lb, where the Hertz
/// band on the reference pair is nearly as wide as the roller (1.51e6 lb) and 4 000
/// times the reference's peak (about 230 lb). Not from the thesis, as
/// [`MAX_PLAUSIBLE_CONTACT_STRESS_PSI`].
pub const MAX_PLAUSIBLE_CONTACT_FORCE_LB: f64 = 1.0e6;

/// Every parameter of the eleven-degree-of-freedom model (Eqs. IV.1-IV.3).
///
/// Units: inch, pound-force, second, radian. Rotational inertia lb·in·s²,
/// torsional stiffness lb·in/rad, torsional damping lb·in·s/rad, mass lb·s²/in,
/// stiffness lb/in, damping lb·s/in.
///
/// With the `serde` feature every field has its scene key, units in the name
/// ([`crate::key`]); `drive`, `geometry`, `hertz` and `program` are sub-tables. Every
/// key is optional (absent keys take [`Design::reference`]'s values) and unknown keys
/// are refused. Deserializing checks the program only: call [`Design::validate`] on
/// the result. The derives use no `flatten`, no `skip_serializing_if` and no untagged
/// enums, so non-self-describing formats (postcard) read what they write.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(
        deny_unknown_fields,
        default,
        expecting = "a design: a table of its parameters",
        bound(
            serialize = "T: Real + serde::Serialize",
            deserialize = "T: Real + serde::Deserialize<'de>"
        )
    )
)]
pub struct Design<T> {
    // --- rotational system (Eq. IV.1) ---
    /// I_m: motor armature polar moment of inertia (VI.1: 0.0291).
    #[cfg_attr(feature = "serde", serde(rename = "i_m_lb_in_s2"))]
    pub i_m: T,
    /// I_cp: coupling polar moment of inertia (VI.1: 0.25).
    #[cfg_attr(feature = "serde", serde(rename = "i_cp_lb_in_s2"))]
    pub i_cp: T,
    /// I_c: cam polar moment of inertia (VI.1: 0.0102).
    #[cfg_attr(feature = "serde", serde(rename = "i_c_lb_in_s2"))]
    pub i_c: T,
    /// C_mb: motor bearing viscous damping (VI.1: 0.8).
    #[cfg_attr(feature = "serde", serde(rename = "c_mb_lb_in_s"))]
    pub c_mb: T,
    /// C_s1: shaft damping motor-coupling (VI.1: 0.11982).
    #[cfg_attr(feature = "serde", serde(rename = "c_s1_lb_in_s"))]
    pub c_s1: T,
    /// C_s2: shaft damping coupling-cam (VI.1 lists "C_b2" = 0.12: read C_s2, docs/MODEL.md §4.8).
    #[cfg_attr(feature = "serde", serde(rename = "c_s2_lb_in_s"))]
    pub c_s2: T,
    /// C_cc: cam-shaft bearing and air damping (VI.1: 1.0).
    #[cfg_attr(feature = "serde", serde(rename = "c_cc_lb_in_s"))]
    pub c_cc: T,
    /// K_s1: shaft stiffness motor-coupling (VI.1: 2e5).
    #[cfg_attr(feature = "serde", serde(rename = "k_s1_lb_in_per_rad"))]
    pub k_s1: T,
    /// K_s2: shaft stiffness coupling-cam (VI.1: 2e5).
    #[cfg_attr(feature = "serde", serde(rename = "k_s2_lb_in_per_rad"))]
    pub k_s2: T,
    /// Total angular free play (backlash) between the coupling and the cam shaft, rad:
    /// an impact pair (Appendix G.1) in series with K_s2, C_s2 ([`crate::backlash_torque`]).
    /// Not in the thesis's model (its coupling is rigid, IV.1); 0, the reference, gives
    /// the rigid coupling bit for bit. docs/MODEL.md §8.5.
    #[cfg_attr(feature = "serde", serde(rename = "coupling_backlash_rad"))]
    pub coupling_backlash: T,
    /// The motor law T_i(θ̇_m) (not in the thesis; see [`DriveLaw`]).
    pub drive: DriveLaw<T>,
    /// Initial and reference cam speed, rad/s (VI.1: 800 rpm = 83.776 rad/s).
    #[cfg_attr(feature = "serde", serde(rename = "omega0_rad_per_s"))]
    pub omega0: T,

    // --- cam and its shaft (Eqs. IV.2-IV.3, cam equations) ---
    /// M_c (VI.1's M_cs): mass of cam and shaft (0.0291).
    #[cfg_attr(feature = "serde", serde(rename = "cam_mass_lb_s2_per_in"))]
    pub m_c: T,
    /// K_vs: vertical stiffness of the cam shaft and its bearings (VI.1: 1.48e6).
    #[cfg_attr(feature = "serde", serde(rename = "k_vs_lb_per_in"))]
    pub k_vs: T,
    /// C_vs: vertical damping of the cam shaft (VI.1: 4.30474).
    #[cfg_attr(feature = "serde", serde(rename = "c_vs_lb_s_per_in"))]
    pub c_vs: T,
    /// K_hs: horizontal cam-shaft stiffness (not listed: K_hs = K_vs, docs/MODEL.md §4.11).
    #[cfg_attr(feature = "serde", serde(rename = "k_hs_lb_per_in"))]
    pub k_hs: T,
    /// C_hs: horizontal cam-shaft damping (not listed: C_hs = C_vs, docs/MODEL.md §4.11).
    #[cfg_attr(feature = "serde", serde(rename = "c_hs_lb_s_per_in"))]
    pub c_hs: T,

    // --- roller ---
    /// M_r (VI.1's "M_T"): roller mass (0.00013).
    #[cfg_attr(feature = "serde", serde(rename = "roller_mass_lb_s2_per_in"))]
    pub m_r: T,
    /// K_rb: roller bearing and its shaft (VI.1: 1.5e6), vertical and horizontal.
    #[cfg_attr(feature = "serde", serde(rename = "k_rb_lb_per_in"))]
    pub k_rb: T,
    /// ξ_rb of the roller-bearing damping C_rb = 2 ξ_rb sqrt(K_rb M_r) (Eq. V.13), acting
    /// beside K_rb vertically and horizontally. Not in the printed model; 0.05 from V.14
    /// for well-lubricated machine parts ([`ROLLER_BEARING_DAMPING_RATIO`], docs/MODEL.md
    /// §6.2). 0, with [`Design::contact_damping_ratio`] 0, gives the printed model bit for bit.
    pub roller_bearing_damping_ratio: T,
    /// ξ_h of the contact damping C_h = 2 ξ_h sqrt(K_h M_r) (Eq. V.13), K_h at the current
    /// contact point. Not in the printed model (which has none, so the roller's mode rings
    /// undamped); 0.05 from V.14 for well-lubricated machine parts ([`CONTACT_DAMPING_RATIO`],
    /// docs/MODEL.md §3.9, §6.2). 0, with [`Design::roller_bearing_damping_ratio`] 0, gives
    /// the printed model bit for bit.
    pub contact_damping_ratio: T,

    // --- follower rod ---
    /// ρ: follower material density (steel, lb·s²/in⁴).
    #[cfg_attr(feature = "serde", serde(rename = "follower_density_lb_s2_per_in4"))]
    pub rho: T,
    /// E of the follower rod (VI.1: 30e6 psi).
    #[cfg_attr(feature = "serde", serde(rename = "follower_youngs_psi"))]
    pub youngs: T,
    /// A: follower cross-section, in². Not given: from M_f = ρ A e1 = 0.007764 (VI.1)
    /// and K_f = E A / e1 = 1.265e6 (from the modal data, docs/MODEL.md §5.2): A = sqrt(M_f K_f / (ρ E)),
    /// a round rod of about 0.92 in.
    #[cfg_attr(feature = "serde", serde(rename = "follower_area_in2"))]
    pub area: T,
    /// Second moment of the rod section, in⁴ (round rod of area A: A²/(4π)), for K_hc = 3EI/(e2 - y3)³.
    #[cfg_attr(feature = "serde", serde(rename = "follower_second_moment_in4"))]
    pub inertia_moment: T,
    /// e1: follower length from load to slide bearing at rest, in (E A / K_f, about 15.8 in; docs/MODEL.md §5.2).
    #[cfg_attr(feature = "serde", serde(rename = "e1_in"))]
    pub e1: T,
    /// e2: cantilever length from slide bearing to roller at rest, in. Not given; 2 in (docs/MODEL.md §5.3):
    /// it must exceed the lift, and 2 in leaves 0.5 in at full lift.
    #[cfg_attr(feature = "serde", serde(rename = "e2_in"))]
    pub e2: T,
    /// A of Eq. V.16: bearing-to-roller lever, in. Not given; taken equal to e2 (2 in).
    #[cfg_attr(feature = "serde", serde(rename = "bearing_a_in"))]
    pub bearing_a: T,
    /// B of Eq. V.16: distance between the two slide-bearing reactions, in. Not given; 3 in (docs/MODEL.md §5.4).
    #[cfg_attr(feature = "serde", serde(rename = "bearing_b_in"))]
    pub bearing_b: T,
    /// μ: kinetic friction coefficient of the slide bearing (VI.1: 0.08).
    #[cfg_attr(feature = "serde", serde(rename = "friction_coefficient"))]
    pub mu: T,
    /// Smoothing velocity v_s (in/s) of the slide-bearing Coulomb friction,
    /// F = -μ|N| tanh(v/v_s), which keeps the right-hand side smooth (docs/MODEL.md §3.10).
    /// Not in the thesis: 0.01 in/s, about 1e-4 of the follower's peak speed at 800 rpm
    /// (docs/MODEL.md §5.7).
    #[cfg_attr(feature = "serde", serde(rename = "friction_smoothing_in_per_s"))]
    pub friction_smoothing: T,
    /// ξ of C_f1 = 2 ξ sqrt(K_f M_l) (Eq. V.13; 0.03 structural damping, docs/MODEL.md §5.8).
    pub damping_ratio_f1: T,
    /// M_l: load mass. Not in VI.1; 3.428e-3 from the modal analysis (docs/MODEL.md §5.1).
    #[cfg_attr(feature = "serde", serde(rename = "load_mass_lb_s2_per_in"))]
    pub m_l: T,
    /// Mass of the return spring, lb·s²/in; one third joins M_fc (Appendix F.1). Not given:
    /// a steel helical spring of 100 lb/in (wire 0.14 in, mean diameter 1.0 in, 5.5 active
    /// and 7.5 total coils: G d⁴ / (8 D³ n) = 99.5 lb/in) weighs 0.103 lb = 2.66e-4 lb·s²/in
    /// ([`SPRING_MASS`]; the listed 60 lb/in spring: [`LISTED_SPRING_MASS`]).
    #[cfg_attr(feature = "serde", serde(rename = "spring_mass_lb_s2_per_in"))]
    pub m_spring: T,

    // --- return spring and preload (V.4) ---
    /// K_rs: return spring rate, 100 lb/in: VI.2's modal rate, not VI.1's listed 60
    /// ([`REFERENCE_SPRING_RATE`], docs/MODEL.md §6.1).
    #[cfg_attr(feature = "serde", serde(rename = "spring_rate_lb_per_in"))]
    pub k_rs: T,
    /// δ_rs: spring length compressed during assembly (VI.1: 0.5 in).
    #[cfg_attr(feature = "serde", serde(rename = "spring_preload_length_in"))]
    pub delta_rs: T,
    /// K_rs used by the thesis's modal analysis (Eq. VI.6): 100 lb/in, the same as the
    /// dynamic model's [`Design::k_rs`] in the reference design.
    #[cfg_attr(feature = "serde", serde(rename = "spring_modal_rate_lb_per_in"))]
    pub k_rs_modal: T,

    // --- geometry, contact, program ---
    /// Base circle, roller and thickness (VI.1: R_b 1.5, r_r 0.375 in; t 0.25 in, docs/MODEL.md §5.5).
    pub geometry: CamGeometry<T>,
    /// Hertz contact between roller and cam (both steel, VI.1).
    pub hertz: HertzContact<T>,
    /// The motion program (VI.1: D-R-D-R, modified trapezoidal rise, 4-5-6-7 return, 1.5 in).
    pub program: CamProgram<T>,
}

impl<T: Real> Design<T> {
    /// The reference design of VI.1 with the documented choices for what it leaves out.
    pub fn reference() -> Self {
        let f = T::from_f64;
        let rho = f(STEEL_DENSITY);
        let youngs = f(STEEL_YOUNGS);
        // From M_f = ρ A e1 and K_f = E A / e1 (docs/MODEL.md §5.2): A² = M_f K_f / (ρ E).
        let m_f0 = f(0.007764);
        let k_f0 = f(1.265e6);
        let area = (m_f0 * k_f0 / (rho * youngs)).sqrt();
        let e1 = youngs * area / k_f0;
        let inertia_moment = area * area / (f(4.0) * T::PI);
        let omega0 = f(crate::rpm_to_rad_per_s(REFERENCE_RPM));
        Design {
            i_m: f(0.0291),
            i_cp: f(0.25),
            i_c: f(0.0102),
            c_mb: f(0.8),
            c_s1: f(0.11982),
            c_s2: f(0.12),
            c_cc: f(1.0),
            k_s1: f(2.0e5),
            k_s2: f(2.0e5),
            coupling_backlash: T::ZERO,
            drive: DriveLaw::reference(omega0, f(0.8), f(1.0)),
            omega0,
            m_c: f(0.0291),
            k_vs: f(1.48e6),
            c_vs: f(4.30474),
            k_hs: f(1.48e6),
            c_hs: f(4.30474),
            m_r: f(0.00013),
            k_rb: f(1.5e6),
            roller_bearing_damping_ratio: f(ROLLER_BEARING_DAMPING_RATIO),
            contact_damping_ratio: f(CONTACT_DAMPING_RATIO),
            rho,
            youngs,
            area,
            inertia_moment,
            e1,
            e2: f(2.0),
            bearing_a: f(2.0),
            bearing_b: f(3.0),
            mu: f(0.08),
            friction_smoothing: f(0.01),
            damping_ratio_f1: f(STRUCTURAL_DAMPING_RATIO),
            m_l: f(3.428e-3),
            m_spring: f(SPRING_MASS),
            k_rs: f(REFERENCE_SPRING_RATE),
            delta_rs: f(0.5),
            k_rs_modal: f(100.0),
            geometry: CamGeometry::reference(),
            hertz: HertzContact::reference(),
            program: CamProgram::reference(),
        }
    }

    /// M_f = ρ A (e1 + y3): follower mass between load and slide bearing (Eq. IV.2).
    #[inline(always)]
    pub fn m_f(&self, y3: T) -> T {
        self.rho * self.area * (self.e1 + y3)
    }
    /// M_fc = ρ A (e2 - y3) + m_spring/3: cantilever mass with a third of the spring (Eq. IV.2, F.1).
    #[inline(always)]
    pub fn m_fc(&self, y3: T) -> T {
        self.rho * self.area * (self.e2 - y3) + crate::spring_effective_mass(self.m_spring)
    }
    /// K_f = E A / (e1 + y3): axial stiffness of the follower between slide bearing and load (Eq. V.7, docs/MODEL.md §3.11).
    #[inline(always)]
    pub fn k_f(&self, y3: T) -> T {
        self.youngs * self.area / (self.e1 + y3)
    }
    /// K_vc = E A / (e2 - y3): axial stiffness of the cantilever portion (Eq. V.7, docs/MODEL.md §3.11).
    #[inline(always)]
    pub fn k_vc(&self, y3: T) -> T {
        self.youngs * self.area / (self.e2 - y3)
    }
    /// K_hc = 3 E I / (e2 - y3)³: lateral stiffness of the cantilever portion (Eq. V.8, docs/MODEL.md §3.11).
    #[inline(always)]
    pub fn k_hc(&self, y3: T) -> T {
        let l = self.e2 - y3;
        T::from_f64(3.0) * self.youngs * self.inertia_moment / (l * l * l)
    }
    /// C_f1 = 2 ξ sqrt(K_f M_l): structural damping of the follower rod (Eq. V.13).
    #[inline(always)]
    pub fn c_f1(&self, y3: T) -> T {
        self.c_f1_from(self.k_f(y3))
    }
    /// C_f1 for an already computed K_f (the right-hand side has it at hand).
    #[inline(always)]
    pub fn c_f1_from(&self, k_f: T) -> T {
        T::TWO * self.damping_ratio_f1 * (k_f * self.m_l).sqrt()
    }

    /// C_h = 2 ξ_h sqrt(K_h M_r): the contact damping for the Hertz stiffness `k_h` at the
    /// contact point (Eq. V.13, docs/MODEL.md §3.9); exactly 0 when ξ_h = 0.
    #[inline(always)]
    pub fn c_h(&self, k_h: T) -> T {
        crate::damping_coefficient(self.contact_damping_ratio, k_h, self.m_r)
    }

    /// C_rb = 2 ξ_rb sqrt(K_rb M_r): the roller bearing's damping (Eq. V.13,
    /// docs/MODEL.md §3.13); exactly 0 when ξ_rb = 0.
    #[inline(always)]
    pub fn c_rb(&self) -> T {
        crate::damping_coefficient(self.roller_bearing_damping_ratio, self.k_rb, self.m_r)
    }

    /// K_h on the base circle at unit force (Eq. V.11), the value the preload uses.
    pub fn k_h_base(&self) -> Result<T> {
        self.hertz
            .stiffness(self.geometry.roller_radius, self.geometry.base_radius)
    }

    /// F_p of Eq. V.18: the preload after assembly, with K_t the series of K_rb, K_h (base circle) and K_vs.
    pub fn preload(&self) -> Result<T> {
        let k_h = self.k_h_base()?;
        let k_t = crate::series_stiffness(&[self.k_rb, k_h, self.k_vs]);
        Ok(crate::return_spring_preload(k_t, self.k_rs, self.delta_rs)?.force)
    }

    /// The value of every numeric scene key of the design (but the program's), in the
    /// order of [`crate::key::DESIGN_KEYS`] and of [`crate::key::RANGES`]'s first entries;
    /// the regulated drive's four (the last of them) only with that drive.
    fn scalars(&self) -> impl Iterator<Item = T> {
        let g = &self.geometry;
        let h = &self.hertz;
        let drive = match self.drive {
            DriveLaw::Regulated {
                omega_ref,
                t_steady,
                k_p,
                t_max,
            } => Some([omega_ref, t_steady, k_p, t_max]),
            _ => None,
        };
        [
            self.i_m,
            self.i_cp,
            self.i_c,
            self.c_mb,
            self.c_s1,
            self.c_s2,
            self.c_cc,
            self.k_s1,
            self.k_s2,
            self.coupling_backlash,
            self.omega0,
            self.m_c,
            self.k_vs,
            self.c_vs,
            self.k_hs,
            self.c_hs,
            self.m_r,
            self.k_rb,
            self.roller_bearing_damping_ratio,
            self.contact_damping_ratio,
            self.rho,
            self.youngs,
            self.area,
            self.inertia_moment,
            self.e1,
            self.e2,
            self.bearing_a,
            self.bearing_b,
            self.mu,
            self.friction_smoothing,
            self.damping_ratio_f1,
            self.m_l,
            self.m_spring,
            self.k_rs,
            self.delta_rs,
            self.k_rs_modal,
            g.base_radius,
            g.roller_radius,
            g.thickness,
            h.youngs_1,
            h.poisson_1,
            h.youngs_2,
            h.poisson_2,
            h.thickness,
        ]
        .into_iter()
        .chain(drive.into_iter().flatten())
    }

    /// Checks every parameter, the geometry, the contact data and the drive, and that
    /// the roller fits the profile. The error names the scene key ([`crate::key`]),
    /// the value and the rule it broke.
    ///
    /// In this order: signs and finiteness (`must be positive and finite`), the
    /// physical plausibility range of every key ([`crate::key::RANGES`], docs/MODEL.md
    /// §5.16), then what the keys must satisfy together: no undercut, the cantilever
    /// longer than the lift by more than the roller radius, a Hertz stiffness on the base
    /// circle and a preload.
    ///
    /// One copy, not inlined where it is called (on the chip: at boot and in every
    /// steady-state run), which would cost flash for no time worth saving.
    pub fn validate(&self) -> Result<()> {
        self.validate_with(true)
    }

    /// [`Design::validate`] without the undercut scan (`undercut = false`), for a design
    /// whose geometry and program, all the scan reads, were validated already and whose
    /// speed alone changed ([`Design::set_speed_rpm`]): the scan costs about 1.9 M
    /// instructions on the chip, the rest a few thousand.
    #[inline(never)]
    pub(crate) fn validate_with(&self, undercut: bool) -> Result<()> {
        use crate::key as k;
        self.validate_signs()?;
        self.geometry.validate()?;
        self.hertz.validate()?;
        self.drive.validate()?;
        // Physical plausibility: the table's design entries, in the order of `scalars`
        // (the test `range_table_follows_the_design_keys` holds the two in step).
        for ((field, range), v) in k::RANGES.iter().zip(self.scalars()) {
            range.check(field, v)?;
        }
        for (i, s) in self.program.segments().iter().enumerate() {
            k::LENGTH_OR_ZERO.check(segment_key(SegmentField::LiftIn, i), s.lift)?;
        }
        self.validate_fit(undercut)?;
        self.validate_contact()
    }

    /// [`Self::validate`]'s signs: the quantities that must be positive, then those that
    /// must not be negative.
    fn validate_signs(&self) -> Result<()> {
        use crate::key as k;
        for (field, v) in [
            (k::I_M, self.i_m),
            (k::I_CP, self.i_cp),
            (k::I_C, self.i_c),
            (k::K_S1, self.k_s1),
            (k::K_S2, self.k_s2),
            (k::OMEGA0, self.omega0),
            (k::M_C, self.m_c),
            (k::K_VS, self.k_vs),
            (k::K_HS, self.k_hs),
            (k::M_R, self.m_r),
            (k::K_RB, self.k_rb),
            (k::RHO, self.rho),
            (k::YOUNGS, self.youngs),
            (k::AREA, self.area),
            (k::INERTIA_MOMENT, self.inertia_moment),
            (k::E1, self.e1),
            (k::E2, self.e2),
            (k::BEARING_B, self.bearing_b),
            (k::FRICTION_SMOOTHING, self.friction_smoothing),
            (k::M_L, self.m_l),
            (k::K_RS, self.k_rs),
            (k::K_RS_MODAL, self.k_rs_modal),
        ] {
            positive(field, v)?;
        }
        for (field, v) in [
            (k::C_MB, self.c_mb),
            (k::C_S1, self.c_s1),
            (k::C_S2, self.c_s2),
            (k::C_CC, self.c_cc),
            (k::C_VS, self.c_vs),
            (k::C_HS, self.c_hs),
            (k::BEARING_A, self.bearing_a),
            (k::COUPLING_BACKLASH, self.coupling_backlash),
            (k::MU, self.mu),
            (k::DAMPING_RATIO_F1, self.damping_ratio_f1),
            (k::CONTACT_DAMPING_RATIO, self.contact_damping_ratio),
            (
                k::ROLLER_BEARING_DAMPING_RATIO,
                self.roller_bearing_damping_ratio,
            ),
            (k::M_SPRING, self.m_spring),
            (k::DELTA_RS, self.delta_rs),
        ] {
            non_negative(field, v)?;
        }
        Ok(())
    }

    /// [`Self::validate`]'s fit of the roller: no undercut (scanned when `undercut`), and
    /// clear of the slide bearing at full lift.
    fn validate_fit(&self, undercut: bool) -> Result<()> {
        use crate::key as k;
        // The roller must fit the profile: no undercut (a convex pitch radius below r_r).
        if undercut && self.geometry.undercut(&self.program, 3600)?.undercut {
            return Err(Error::InvalidParameter {
                field: k::ROLLER_RADIUS,
                rule: "undercut: larger than the smallest convex pitch-curve radius of the profile (use a smaller roller, a larger base circle or a gentler program)",
                value: self.geometry.roller_radius.to_f64(),
            });
        }
        // At full lift the roller (radius r_r, at the cantilever's end) must clear the
        // slide bearing: e2 - lift > r_r (docs/MODEL.md §3.20, the bound the run checks).
        let lift = self.program.max_lift();
        if self.e2 - lift <= self.geometry.roller_radius {
            return Err(Error::InvalidParameter {
                field: k::E2,
                rule: "cantilever length must exceed the program's largest lift by more than the roller radius (the roller would reach the slide bearing)",
                value: self.e2.to_f64(),
            });
        }
        Ok(())
    }

    /// [`Self::validate`]'s contact: a Hertz stiffness on the base circle and a preload,
    /// their errors named by the design's keys.
    fn validate_contact(&self) -> Result<()> {
        use crate::key as k;
        // K_h on the base circle: the roller and base radii must carry a line contact.
        self.k_h_base().map_err(|e| match e {
            Error::InvalidParameter {
                field: "r2", rule, ..
            } => Error::InvalidParameter {
                field: k::BASE_RADIUS,
                rule,
                value: self.geometry.base_radius.to_f64(),
            },
            Error::InvalidParameter {
                field: "r1", rule, ..
            } => Error::InvalidParameter {
                field: k::ROLLER_RADIUS,
                rule,
                value: self.geometry.roller_radius.to_f64(),
            },
            _ => Error::Inconsistent {
                field: "hertz",
                rule: "the contact data give no unit-load Hertz stiffness on the base circle",
            },
        })?;
        // The preload's own checks name its inputs by their symbols: name the keys.
        self.preload().map_err(|e| match e {
            Error::InvalidParameter {
                field: "delta_rs",
                rule,
                value,
            } => Error::InvalidParameter {
                field: k::DELTA_RS,
                rule,
                value,
            },
            Error::InvalidParameter { rule, value, .. } => Error::InvalidParameter {
                field: k::K_RS,
                rule,
                value,
            },
            other => other,
        })?;
        Ok(())
    }
}

impl<T: Real> Default for Design<T> {
    /// [`Design::reference`].
    fn default() -> Self {
        Self::reference()
    }
}

impl<T: Real> Design<T> {
    /// Sets the return spring rate K_rs and its mass from the one wire-and-coil model
    /// ([`HelicalSpring::of_rate`]): what `--spring-rate` does.
    ///
    /// The modal analysis's rate K_rs (modal) follows when it equals the old rate (it
    /// was not set apart, as in the reference): `camsim modal` then uses the new spring.
    pub fn set_spring_rate(&mut self, rate: T) -> Result<()> {
        let s = HelicalSpring::of_rate(rate)?;
        if self.k_rs_modal == self.k_rs {
            self.k_rs_modal = rate;
        }
        self.k_rs = rate;
        self.m_spring = s.mass;
        Ok(())
    }

    /// The return spring as the wire-and-coil model makes it at this design's rate.
    pub fn spring(&self) -> Result<HelicalSpring<T>> {
        HelicalSpring::of_rate(self.k_rs)
    }

    /// Moves the design to a new cam speed (rpm): ω0 and the drive's reference speed.
    ///
    /// The error names `rpm` ([`crate::key::RPM`]; the host's scene key is `run.rpm`, its
    /// flag `--rpm`): it must be positive and finite and lie in
    /// [`crate::key::SPEED_RPM`] (1-10 000 rpm).
    pub fn set_speed_rpm(&mut self, rpm: T) -> Result<()> {
        positive(crate::key::RPM, rpm)?;
        crate::key::SPEED_RPM.check(crate::key::RPM, rpm)?;
        let w = crate::rpm_to_rad_per_s(rpm);
        self.omega0 = w;
        self.drive = self.drive.at_speed(w);
        Ok(())
    }
}

/// The follower train's translating mass as the model splits it (lb·s²/in): what a
/// designer weighs as "the moving mass" (docs/MODEL.md §5.1). The rod's share is
/// ρ A (e1 + e2), its whole length at rest (M_f + the cantilever's ρ A (e2 − y3) at
/// y3 = 0), the spring's a third of its mass (Appendix F.1), the roller M_r whole.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingMass<T> {
    /// M_l, the load at the rod's end.
    pub load: T,
    /// ρ A (e1 + e2), the follower rod.
    pub rod: T,
    /// M_r, the roller.
    pub roller: T,
    /// m_spring / 3, the return spring's share.
    pub spring_share: T,
}

impl<T: Real> MovingMass<T> {
    /// The parts other than the load: rod, roller and the spring's share.
    pub fn fixed_parts(&self) -> T {
        self.rod + self.roller + self.spring_share
    }
    /// The whole translating mass: the load and [`Self::fixed_parts`].
    pub fn total(&self) -> T {
        self.load + self.fixed_parts()
    }
}

impl<T: Real> Design<T> {
    /// The translating mass of the follower train, by its parts.
    pub fn moving_mass(&self) -> MovingMass<T> {
        MovingMass {
            load: self.m_l,
            rod: self.rho * self.area * (self.e1 + self.e2),
            roller: self.m_r,
            spring_share: crate::spring_effective_mass(self.m_spring),
        }
    }

    /// Sets the load M_l so that the translating mass is `total` (lb·s²/in): the load
    /// takes what the rod, roller and spring's share leave (docs/MODEL.md §5.1). Refused
    /// (naming `load_mass_lb_s2_per_in` with the load it would be) when that is not
    /// positive and finite; the design is then unchanged.
    pub fn set_moving_mass(&mut self, total: T) -> Result<()> {
        let load = total - self.moving_mass().fixed_parts();
        positive(crate::key::M_L, load)?;
        self.m_l = load;
        Ok(())
    }
}

impl<T: Real> Design<T> {
    /// The design in precision `U`: every number converted with [`Real::cast`]
    /// (`U::from_f64(x.to_f64())`, no other arithmetic), the drive, geometry and contact
    /// with theirs, the program rebuilt by [`CamProgram::new`] in `U` (its typed error,
    /// naming the segment's key, if it does not hold in `U`). Nothing else is checked:
    /// call [`Design::validate`] on the result.
    ///
    /// The firmware's build-time scene and `camsim predict --f32 --scene` both narrow the
    /// scene file's `Design<f64>` with this, so their `f32` bits agree.
    pub fn cast<U: Real>(&self) -> Result<Design<U>> {
        let c = |x: T| x.cast::<U>();
        Ok(Design {
            i_m: c(self.i_m),
            i_cp: c(self.i_cp),
            i_c: c(self.i_c),
            c_mb: c(self.c_mb),
            c_s1: c(self.c_s1),
            c_s2: c(self.c_s2),
            c_cc: c(self.c_cc),
            k_s1: c(self.k_s1),
            k_s2: c(self.k_s2),
            coupling_backlash: c(self.coupling_backlash),
            drive: self.drive.cast(),
            omega0: c(self.omega0),
            m_c: c(self.m_c),
            k_vs: c(self.k_vs),
            c_vs: c(self.c_vs),
            k_hs: c(self.k_hs),
            c_hs: c(self.c_hs),
            m_r: c(self.m_r),
            k_rb: c(self.k_rb),
            contact_damping_ratio: c(self.contact_damping_ratio),
            roller_bearing_damping_ratio: c(self.roller_bearing_damping_ratio),
            rho: c(self.rho),
            youngs: c(self.youngs),
            area: c(self.area),
            inertia_moment: c(self.inertia_moment),
            e1: c(self.e1),
            e2: c(self.e2),
            bearing_a: c(self.bearing_a),
            bearing_b: c(self.bearing_b),
            mu: c(self.mu),
            friction_smoothing: c(self.friction_smoothing),
            damping_ratio_f1: c(self.damping_ratio_f1),
            m_l: c(self.m_l),
            m_spring: c(self.m_spring),
            k_rs: c(self.k_rs),
            delta_rs: c(self.delta_rs),
            k_rs_modal: c(self.k_rs_modal),
            geometry: self.geometry.cast(),
            hertz: self.hertz.cast(),
            program: self.program.cast()?,
        })
    }
}

#[cfg(test)]
mod range_tests {
    use super::*;
    use crate::key;

    /// `validate` pairs `scalars` with the range table by position: the table's first
    /// entries are the design keys in `DESIGN_KEYS` order, the drive's last, and
    /// `scalars` yields one value per key (the drive's only with the regulated drive).
    #[test]
    fn range_table_follows_the_design_keys() {
        let table: std::vec::Vec<&str> = key::RANGES.iter().map(|(k, _)| *k).collect();
        let design: std::vec::Vec<&str> = key::DESIGN_KEYS.iter().map(|(k, _)| *k).collect();
        assert_eq!(table.get(..design.len()), Some(design.as_slice()));
        assert_eq!(
            design.get(design.len() - 4..),
            Some(
                &[
                    key::DRIVE_OMEGA_REF,
                    key::DRIVE_T_STEADY,
                    key::DRIVE_K_P,
                    key::DRIVE_T_MAX
                ][..]
            )
        );
        let d = Design::<f64>::reference();
        assert_eq!(d.scalars().count(), design.len());
        let mut ideal = d.clone();
        ideal.drive = DriveLaw::ConstantCamSpeed;
        assert_eq!(ideal.scalars().count(), design.len() - 4);
        // Each value is its key's: spot checks by a distinct value per key.
        let vals: std::vec::Vec<f64> = d.scalars().collect();
        assert_eq!(vals[0], d.i_m);
        assert_eq!(
            vals[table.iter().position(|k| *k == key::E2).unwrap()],
            d.e2
        );
        assert_eq!(
            vals[table
                .iter()
                .position(|k| *k == key::CONTACT_LENGTH)
                .unwrap()],
            d.hertz.thickness
        );
        assert_eq!(
            vals[table.iter().position(|k| *k == key::ROLLER_RADIUS).unwrap()],
            d.geometry.roller_radius
        );
        // Out of range by a key: refused under that key with its rule.
        let mut bad = d.clone();
        bad.hertz.youngs_2 = 2e10;
        assert_eq!(
            bad.validate(),
            Err(Error::InvalidParameter {
                field: key::CAM_YOUNGS,
                rule: key::MODULUS.rule,
                value: 2e10
            })
        );
    }
}

#[cfg(test)]
mod spring_tests {
    use super::*;

    /// The spring constants by hand: k = G d⁴ / (8 D³ n) with G = 11.4e6 psi,
    /// d⁴ = 3.8416e-4 in⁴, D = 1 in: 4379.42 / (8 n) = 547.43 / n lb/in; the wire's
    /// volume per coil π² d² D / 4 = 0.0483611 in³.
    #[test]
    fn spring_wire_strengths_are_shigleys() {
        // Shigley (9th ed.) Example 10-1: no. 16 music wire, d = 0.037 in: S_ut = 201 /
        // 0.037^0.145 = 324 kpsi, S_sy = 0.45 S_ut = 146 kpsi.
        let music = SpringWire::named("music-wire").unwrap();
        let m = music.material(0.037);
        assert!((music.tensile_strength(0.037) / 324.2e3 - 1.0).abs() < 1e-3);
        assert!((m.allowable_shear / 145.9e3 - 1.0).abs() < 1e-3);
        // Stainless 302 changes band at 0.10 in: 169/0.1^0.146 = 236.4 kpsi below,
        // 128/0.1^0.263 = 234.6 kpsi above (table 10-4's bands meet within 1 %).
        let ss = SpringWire::named("stainless-302").unwrap();
        assert!((ss.tensile_strength(0.1) / 236.4e3 - 1.0).abs() < 1e-3);
        assert!((ss.tensile_strength(0.1000001) / 234.6e3 - 1.0).abs() < 1e-3);
        assert!(SpringWire::named("piano").is_none());
        // The assumed wire model's part has the wire model's rate, mass and surge.
        let h = HelicalSpring::<f64>::of_rate(REFERENCE_SPRING_RATE).unwrap();
        let p = h.part();
        let k = STEEL_SHEAR * 0.14f64.powi(4) / (8.0 * 5.5);
        assert!((p.rate() / k - 1.0).abs() < 1e-12);
        assert!((p.mass() / h.mass - 1.0).abs() < 1e-12);
        // The wire model's surge takes the rate asked (100), the part its coils' (99.53):
        // sqrt(99.53 / 100) = 0.99765.
        assert!((p.surge_hz() / h.surge_hz - (k / 100.0).sqrt()).abs() < 1e-12);
        // Squared and ground: solid height d N_t = 0.14 * 7.5 in.
        assert!((p.solid_height() - 1.05).abs() < 1e-12);
    }

    #[test]
    fn spring_rate_and_mass_follow_from_the_wire() {
        let rate = |n: f64| {
            STEEL_SHEAR * SPRING_WIRE_DIAMETER.powi(4) / (8.0 * SPRING_MEAN_DIAMETER.powi(3) * n)
        };
        assert!((rate(1.0) - 547.428).abs() < 1e-3);
        // Reference: 5.5 active coils, 99.53 lb/in, within 0.5 % of 100.
        assert!((rate(SPRING_ACTIVE_COILS) / REFERENCE_SPRING_RATE - 1.0).abs() < 5e-3);
        // The listed spring: 9 active coils, 60.8 lb/in.
        assert!((rate(9.0) - 60.825).abs() < 1e-3);
        // Mass: 7.5 coils of 0.0483611 in³ of steel at 0.2836 lb/in³.
        let lb = 7.5 * 0.048_361_1 * 0.2836;
        assert!(
            (SPRING_MASS * GRAVITY_IN_PER_S2 / lb - 1.0).abs() < 1e-6,
            "{lb}"
        );
        // The listed spring's 0.151 lb is the same wire over 11 coils (0.15087 lb, rounded).
        assert!((LISTED_SPRING_MASS / SPRING_MASS - 11.0 / 7.5).abs() < 2e-3);
        let d = Design::<f64>::reference();
        assert_eq!(
            (d.k_rs, d.k_rs_modal, d.m_spring),
            (100.0, 100.0, SPRING_MASS)
        );
    }

    /// The wire model against the hand figures above: 100 lb/in is the reference's 5.5
    /// active coils (its mass bit for bit), 60 lb/in the listed spring's 9 (11 total:
    /// 0.150869 lb); the surge ½ √(k/m_active) by hand; the mass falls as the rate rises.
    #[test]
    fn wire_model_gives_mass_and_surge_from_the_rate() {
        let s = HelicalSpring::<f64>::of_rate(100.0).unwrap();
        assert_eq!((s.active_coils, s.total_coils), (5.5, 7.5));
        assert_eq!(s.mass, SPRING_MASS);
        let l = HelicalSpring::<f64>::of_rate(LISTED_SPRING_RATE).unwrap();
        assert_eq!((l.active_coils, l.total_coils), (9.0, 11.0));
        let lb = 11.0 * 0.048_361_1 * 0.2836;
        assert!((l.mass * GRAVITY_IN_PER_S2 / lb - 1.0).abs() < 1e-6);
        // Surge by hand: m_active = 5.5 coils of 0.0483611 in³ at 0.2836/386.09.
        let m_active = 5.5 * 0.048_361_1 * 0.2836 / GRAVITY_IN_PER_S2;
        let f = 0.5 * (100.0 / m_active).sqrt();
        assert!((s.surge_hz / f - 1.0).abs() < 1e-6, "{} {f}", s.surge_hz);
        assert!(HelicalSpring::<f64>::of_rate(200.0).unwrap().mass < s.mass);
        assert!(HelicalSpring::<f64>::of_rate(-1.0).is_err());
        assert!(HelicalSpring::<f64>::of_rate(f64::NAN).is_err());
        // Beyond the wire: the fewest coils, a finite mass and surge.
        let stiff = HelicalSpring::<f64>::of_rate(1e6).unwrap();
        assert_eq!(stiff.active_coils, SPRING_MIN_ACTIVE_COILS);
        assert!(stiff.surge_hz.is_finite());
        let mut d = Design::<f64>::reference();
        d.set_spring_rate(60.0).unwrap();
        assert_eq!((d.k_rs, d.m_spring), (60.0, l.mass));
    }
}

#[cfg(test)]
mod cast_tests {
    use super::*;
    use crate::{MotionLaw, Segment, SegmentKind};
    use std::string::String;
    use std::vec::Vec;

    /// Every `field: number` of a value's `Debug` text before its `program` (whose
    /// prepared data is derived, not converted), in order, parsed as `R` (`Debug` prints
    /// the shortest digits that read back to the same `R`).
    fn numbers<R: core::str::FromStr>(debug: &str) -> Vec<R> {
        let head = debug.split("program:").next().unwrap_or("");
        head.split(": ")
            .skip(1)
            .filter_map(|t| t.split([',', ' ', '}']).next()?.parse::<R>().ok())
            .collect()
    }

    /// The reference with every scalar distinct (so a field converted into another's
    /// place shows), values `f32` cannot hold exactly, the stable laws and 650 rpm.
    fn distinct() -> Design<f64> {
        let mut d = Design::<f64>::reference();
        d.k_s2 = 2.1e5;
        d.m_c = 0.0301;
        d.k_hs = 1.4e6;
        d.c_hs = 4.1;
        d.bearing_a = 2.2;
        d.coupling_backlash = 0.003;
        d.contact_damping_ratio = 0.051;
        d.roller_bearing_damping_ratio = 0.052;
        d.k_rb = 1.0 / 3.0 * 4.5e6;
        d.hertz.youngs_2 = 29.0e6;
        d.hertz.poisson_2 = 0.3;
        d.hertz.thickness = 0.2;
        d.program = CamProgram::with_laws(MotionLaw::Poly4567, MotionLaw::ModifiedTrapezoidal);
        d.set_speed_rpm(650.0).unwrap();
        d
    }

    #[test]
    fn cast_rounds_every_number_to_nearest_and_nothing_else() {
        let mut rigid = Design::<f64>::reference();
        rigid.drive = DriveLaw::ConstantCamSpeed;
        let third = 100.0 / 3.0;
        rigid.program = CamProgram::new(&[
            Segment {
                kind: SegmentKind::Dwell,
                start_deg: 0.0,
                end_deg: third,
                lift: 0.0,
            },
            Segment {
                kind: SegmentKind::Rise(MotionLaw::Cycloidal),
                start_deg: third,
                end_deg: 170.0,
                lift: 0.1 + 0.2,
            },
            Segment {
                kind: SegmentKind::Return(MotionLaw::Poly345),
                start_deg: 170.0,
                end_deg: 360.0,
                lift: 0.1 + 0.2,
            },
        ])
        .unwrap();
        for d in [Design::<f64>::reference(), distinct(), rigid] {
            let d32 = d.cast::<f32>().unwrap();
            let wide: Vec<f64> = numbers(&std::format!("{d:?}"));
            let narrow: Vec<f32> = numbers(&std::format!("{d32:?}"));
            // 36 scalar fields, 3 of the geometry, 5 of the contact; 4 of a regulated drive.
            let drive_numbers = if d.drive.kind() == crate::DriveKind::Regulated {
                4
            } else {
                0
            };
            assert_eq!(wide.len(), 44 + drive_numbers);
            assert_eq!(narrow.len(), wide.len());
            for (k, (w, n)) in wide.iter().zip(&narrow).enumerate() {
                assert_eq!(n.to_bits(), (*w as f32).to_bits(), "number {k}: {w}");
            }
            assert_eq!(d32.program.segments().len(), d.program.segments().len());
            for (a, b) in d32.program.segments().iter().zip(d.program.segments()) {
                assert_eq!(a.kind, b.kind);
                for (x, y) in [
                    (a.start_deg, b.start_deg),
                    (a.end_deg, b.end_deg),
                    (a.lift, b.lift),
                ] {
                    assert_eq!(x.to_bits(), (y as f32).to_bits());
                }
            }
            // Rebuilt, not copied: the f32 program is the one CamProgram::new makes.
            assert_eq!(
                d32.program,
                CamProgram::new(d32.program.segments()).unwrap()
            );
            d32.validate().unwrap();
            // f64 to f64 is the identity; f32 widened and narrowed again too.
            assert_eq!(d.cast::<f64>().unwrap(), d);
            let again = d32.cast::<f64>().unwrap().cast::<f32>().unwrap();
            assert_eq!(std::format!("{again:?}"), std::format!("{d32:?}"));
        }
    }

    #[test]
    fn cast_does_not_validate_and_a_derived_rule_can_fail_in_f32() {
        let mut d = distinct();
        d.k_rb = -1.0;
        assert_eq!(d.cast::<f32>().unwrap().k_rb, -1.0f32);
        // The ranges hold in both precisions (rounding is monotone and the bounds are
        // f32 numbers), but a rule between keys can fail in f32 alone: e2 just above
        // lift + r_r = 1.875 in rounds to 1.875 in f32.
        let mut tight = Design::<f64>::reference();
        tight.e2 = 1.875 + 1e-9;
        tight.validate().unwrap();
        let e = tight.cast::<f32>().unwrap().validate().unwrap_err();
        assert!(matches!(
            e,
            Error::InvalidParameter { field: "e2_in", value, .. } if value == 1.875
        ));
        let _: String = std::format!("{e}");
    }
}

#[cfg(test)]
mod moving_mass_tests {
    use super::*;

    /// The parts by hand for the reference: rod ρ A (e1 + e2) with ρ A e1 = M_f = 0.007764
    /// (§5.2), so the rod is 0.007764 (1 + 2 / e1); roller 0.00013; a third of the spring.
    #[test]
    fn moving_mass_is_the_sum_of_its_parts_and_sets_the_load() {
        let d = Design::<f64>::reference();
        let m = d.moving_mass();
        let rod = 0.007764 * (1.0 + 2.0 / d.e1);
        assert!((m.rod / rod - 1.0).abs() < 1e-12, "{} {rod}", m.rod);
        assert_eq!(m.roller, 0.00013);
        assert_eq!(m.spring_share, SPRING_MASS / 3.0);
        assert_eq!(m.load, 3.428e-3);
        let total = 3.428e-3 + rod + 0.00013 + SPRING_MASS / 3.0;
        assert!((m.total() / total - 1.0).abs() < 1e-12);
        // A given total: the model's translating mass is that total.
        let mut e = d.clone();
        e.set_moving_mass(0.02).unwrap();
        assert!((e.moving_mass().total() - 0.02).abs() < 1e-15);
        assert!((e.m_l - (0.02 - rod - 0.00013 - SPRING_MASS / 3.0)).abs() < 1e-15);
        e.validate().unwrap();
        // A total the fixed parts exceed is refused, the design unchanged.
        let mut f = d.clone();
        let err = f.set_moving_mass(0.005).unwrap_err();
        assert!(matches!(
            err,
            Error::InvalidParameter { field: "load_mass_lb_s2_per_in", value, .. } if value < 0.0
        ));
        assert_eq!(f, d);
        assert!(f.set_moving_mass(f64::NAN).is_err());
    }

    /// The modal rate follows `set_spring_rate` unless it was set apart.
    #[test]
    fn modal_rate_follows_the_spring_rate_unless_set_apart() {
        let mut d = Design::<f64>::reference();
        d.set_spring_rate(57.1).unwrap();
        assert_eq!((d.k_rs, d.k_rs_modal), (57.1, 57.1));
        d.k_rs_modal = 80.0;
        d.set_spring_rate(60.0).unwrap();
        assert_eq!((d.k_rs, d.k_rs_modal), (60.0, 80.0));
    }
}
