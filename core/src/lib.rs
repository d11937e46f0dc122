#![cfg_attr(not(any(test, feature = "std")), no_std)]
#![forbid(unsafe_code)]
#![warn(missing_docs)]
#![doc = include_str!("../README.md")]

// Foundations: the numeric trait (f32, f64) and the typed errors.
mod error;
mod num;
pub use error::{finite, non_negative, positive, Error, ModelLimit, Result, SimFailure};
pub use num::{rad_per_s_to_rpm, rpm_to_rad_per_s, Real};

mod kinematics;
pub use kinematics::geometry::{CamGeometry, CamMassProperties, UndercutReport, SEGMENT_SAMPLES};
pub use kinematics::lift::{LiftProfile, TheoreticalLift};
pub use kinematics::motion::{LawValue, MotionLaw};
pub use kinematics::program::{
    CamProgram, FollowerLift, ProgramData, Segment, SegmentData, SegmentKind, SegmentType,
};
pub use kinematics::table::{
    ContactTerms, LiftTable, TableKnot, TablePiece, TABLE_PER_KNOT, TABLE_SEGMENT_MULTIPLE,
};

mod forces;
pub use forces::coil_spring::{spring_key, CoilEnds, CoilSpring, SpringMaterial};
pub use forces::contact::{
    bearing_normal_forces, contact_force, coulomb_friction, damped_contact_force,
    damping_coefficient, spring_damper_force, BearingLevers, ContactForce, HertzContact,
};
pub use forces::drive::{
    backlash_torque, DriveKind, DriveLaw, HORSEPOWER_IN_LB_PER_S, MOTOR_BREAKDOWN_RATIO,
    MOTOR_RATED_HP, MOTOR_RATED_SLIP,
};
pub use forces::spring::{return_spring_preload, series_stiffness, spring_effective_mass, Preload};

mod model;
pub use model::design::{
    Design, HelicalSpring, MovingMass, ALLOWABLE_CONTACT_STRESS_PSI, CAM_SPEED_SWING_LIMIT,
    CONTACT_DAMPING_RATIO, GRAVITY_IN_PER_S2, LISTED_SPRING_MASS, LISTED_SPRING_RATE,
    MAX_PLAUSIBLE_CONTACT_FORCE_LB, MAX_PLAUSIBLE_CONTACT_STRESS_PSI, PRESSURE_ANGLE_LIMIT_DEG,
    REFERENCE_RPM, REFERENCE_SPRING_RATE, ROLLER_BEARING_DAMPING_RATIO, SPRING_ACTIVE_COILS,
    SPRING_COIL_STEP, SPRING_MASS, SPRING_MEAN_DIAMETER, SPRING_MIN_ACTIVE_COILS,
    SPRING_TOTAL_COILS, SPRING_WIRE_DIAMETER, STEEL_DENSITY, STEEL_POISSON, STEEL_SHEAR,
    STEEL_YOUNGS, STRUCTURAL_DAMPING_RATIO, SURGE_HARMONIC_MARGIN,
};
pub use model::design::{
    SpringWire, ASSUMED_SPRING_WIRE, SPRING_CLASH_ALLOWANCE, SPRING_INDEX_RANGE, SPRING_WIRES,
    STANDARD_WIRE_DIAMETERS_MM,
};
pub use model::dynamics::{state_quantity_name, CamModel, ModelPoint, ValidityBounds};
pub use model::keys::key;
pub use model::modal::{
    generalized_eigen, modal_analysis, rotational_system, translational_system, ModalAnalysis,
};
pub use model::quasistatic::{
    run_bounds, ChainFactor, ChainSolve, FollowerModel, QuasiStatic, CHAIN_NODES,
};
pub use model::scene::{
    ConstCamFull, ConstCamFullModel, ConstCamVertical, ConstCamVerticalModel, ConstMotorFull,
    ConstMotorFullModel, ConstMotorVertical, ConstMotorVerticalModel, DofSet, Layout,
    RegulatedFull, RegulatedFullModel, RegulatedMasslessRoller, RegulatedMasslessRollerModel,
    RegulatedQsCantilever, RegulatedQsCantileverModel, RegulatedQsRod, RegulatedQsRodModel,
    RegulatedQsShaft, RegulatedQsShaftModel, RegulatedVertical, RegulatedVerticalModel, Scene,
    SceneId, SceneVisitor, StateMut, StateRef, StateVar, TransDof, QUASI_STATIC_CHAIN,
    RELATIVE_TO_LIFT, TRANS_DOFS,
};

mod solve;
pub use solve::dense::Dense;
#[cfg(feature = "pairs")]
pub use solve::dormand_prince::{DormandPrince, DORMAND_PRINCE, DP_IMAGINARY_BOUNDARY, DP_STAGES};
pub use solve::england::{England, EnglandConfig, SolverStats};
pub use solve::events::{Event, EventConfig, EventFunction, EventStats, Report};
#[cfg(feature = "pairs")]
pub use solve::imaginary::{hermite, merson_pi, Merson, IMAGINARY_BOUNDARY, MERSON};
#[cfg(feature = "pairs")]
pub use solve::pair::{Pair, PairTableau};
pub use solve::rk4::{rk4_integrate, rk4_step, rk4_step_from};
pub use solve::spectral_radius::spectral_radius;
pub use solve::step_control::{
    PerUnitStep, PiSettings, StepControl, StepRule, StiffnessCap, SCALED_CAP_FULL_RTOL,
};
pub use solve::step_size::initial_step;
pub use solve::system::{OdeSystem, Tolerance};

mod run;
pub use run::grid::{simulate_on_grid, AngleGrid};
pub use run::jump::{jump_verdict, JumpVerdict, JumpWatch, STEADY_FROM_REVOLUTION};
pub use run::method::{Method, AUTO_MERSON_MIN_RTOL};
pub use run::response::{
    period_name, simulate, simulate_events, solver_config, Both, ContactEvent, ContactEventFn,
    ContactEventSettings, GridPointKind, JumpInterval, Observer, PeriodStats, ResponseStats,
    Sample, SolverSettings, Start, Theoretical, SAMPLE_NUMBERS,
};
pub use run::search::{Onset, OnsetSearch, Peak, PeakScan, ScanEnds};

mod actual;
pub use actual::deviation::{DeviatedLift, AXIS_KNOTS};
pub use actual::envelope::{ActualCam, ENVELOPE_REFINE, ENVELOPE_SUBSTEPS};
pub use actual::follower_axis::AxisErrors;
pub use actual::profile::{
    check_interval, choose_interval, lift_sensitivity, ActualContour, ActualLift, ContourPoint,
    IntervalCheck, IntervalChoice, LiftSensitivity, ProfileSpec, Tolerances, CHECK_SUBSTEPS,
};
pub use actual::random::{sample_seed, splitmix64, NormalMethod, RandomStream};
pub use actual::sampled::{
    check_envelope, envelope_intervals, sampled_deviation, EnvelopeLimits, SampledError, Samples,
    ENVELOPE_KNOTS_PER_ROW,
};
pub use actual::spline::{CubicSpline, SplineEnds, SplineError, SplinePoint};
pub use actual::waviness::{count_extrema_open, waviness_fpr, waviness_fpr_of};

mod predictor;
pub use predictor::index_pulse::{
    CaptureEvent, CaptureTimer, IndexPulse, IndexPulseConfig, Rejection, SpeedReading,
};
pub use predictor::predict::{
    steady_state, timing_points, JumpAlarm, PredictionTable, SpeedPrediction, SteadyState,
    SteadyStateObserver, TimingPoint, TIMING_FRACTIONS, TIMING_POINTS,
};
