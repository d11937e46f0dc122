//! The actual cam's command-line options ([`ActualArgs`], `#[command(flatten)]`ed by every
//! command that simulates an actual cam) and their checks: what the study library takes
//! is the plain [`Cams`] that [`ActualArgs::cams`] makes.

use anyhow::Result;
use clap::ValueEnum;

use crate::actual::{fpr_list, Cams, IntervalRule, NormalArg, ProfileMethod};

/// Command-line options of an actual cam (`#[command(flatten)]` them).
#[derive(clap::Args, Debug, Clone, Default, PartialEq)]
pub struct ActualArgs {
    /// Simulate an actual (machined) cam drawn from the tolerances below instead of the
    /// theoretical cam.
    #[arg(long)]
    pub actual: bool,
    /// Cam profile tolerance, ± in (3σ of each coordinate of a cutter setting point;
    /// default 0.0005, the thesis's VI.1), or with its unit (0.0127mm).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub cam_tolerance: Option<f64>,
    /// Roller radius tolerance, ± in (default 0.0001), or with its unit (mm).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub roller_tolerance: Option<f64>,
    /// Camshaft-bearing non-roundness and base-circle eccentricity together, ± in
    /// (default 0.001), or with its unit (mm).
    #[arg(long, value_name = "IN", allow_negative_numbers = true, value_parser = crate::args::tolerance_in)]
    pub eccentricity_tolerance: Option<f64>,
    /// Profile point interval, degrees (360/interval a whole number, at most 3600
    /// points); overrides --waviness-fpr and --interval.
    #[arg(long, value_name = "DEG", allow_negative_numbers = true, value_parser = crate::actual::interval_deg)]
    pub interval_deg: Option<f64>,
    /// The cam's waviness, in the thesis's FPR (VI.4.1: curve portions between
    /// inflection points of the displacement a revolution, Fig. VI.14; a single
    /// harmonic of n undulations per revolution, UPR in roundness metrology (ISO
    /// 12181), has FPR 2n). The interval is the whole number of points a revolution
    /// whose profile, drawn from the master seed, has the FPR nearest N. Default 17,
    /// the thesis's study cams at VI.1's tolerances (Table VI.2); 39 its rougher cam,
    /// 57 its cams at ±0.0025/±0.0005 in. `design tolerance` takes a comma list
    /// (17,39,57) and answers for each; every other command takes one.
    #[arg(long, value_name = "N", value_delimiter = ',', value_parser = crate::args::whole_u32::<2, 2000>)]
    pub waviness_fpr: Vec<u32>,
    /// How the interval is set when --interval-deg is not given: `waviness` (the FPR of
    /// --waviness-fpr, default 17) or `criteria` (the smallest whole-degree interval
    /// passing the three criteria of IV.2.3 on the master seed's profile: 2 deg, FPR
    /// about 140, for the reference design; docs/MODEL.md §9.6).
    #[arg(long, value_enum, default_value_t = IntervalRule::Waviness)]
    pub interval: IntervalRule,
    /// Master seed: sample i's profile comes from (seed, i) alone (default 1).
    #[arg(long, value_parser = crate::args::seed)]
    pub seed: Option<u64>,
    /// How the lift is made from the tolerances: per-cam (roller radius and axis offset
    /// one value a cam, exact geometry), thesis (IV.2.3: every error drawn at every
    /// point) or envelope (the roller on the random contour).
    #[arg(long, value_enum, default_value_t = ProfileMethod::PerCam)]
    pub profile_method: ProfileMethod,
    /// Normal deviates: sum12 (Appendix B) or polar (exact; alias "exact").
    #[arg(long, value_enum, default_value_t = NormalArg::Sum12)]
    pub normal: NormalArg,
}

impl ActualArgs {
    /// The options as the study library takes them (no interval chosen yet).
    pub fn cams(&self) -> Cams {
        Cams {
            actual: self.actual,
            cam_tolerance: self.cam_tolerance,
            roller_tolerance: self.roller_tolerance,
            eccentricity_tolerance: self.eccentricity_tolerance,
            interval_deg: self.interval_deg,
            waviness_fpr: self.waviness_fpr.clone(),
            interval: self.interval,
            seed: self.seed,
            profile_method: self.profile_method,
            normal: self.normal,
            resolved: None,
        }
    }

    /// Whether any option other than `--actual` was given ([`Cams::any_profile_option`]).
    pub fn any_profile_option(&self) -> bool {
        self.cams().any_profile_option()
    }

    /// [`Cams::ensure_actual_if_options`] of these options.
    pub fn ensure_actual_if_options(&self) -> Result<()> {
        self.cams().ensure_actual_if_options()
    }

    /// [`Cams::refuse_actual_flag`] of these options.
    pub fn refuse_actual_flag(&self, command: &str) -> Result<()> {
        self.cams().refuse_actual_flag(command)
    }
}

/// The command-line checks of an actual cam's options: they name the options as the user
/// wrote them.
impl Cams {
    /// Whether any option other than `--actual` was given (a caller that simulates
    /// the theoretical cam refuses them).
    pub fn any_profile_option(&self) -> bool {
        !self.given_profile_options().is_empty()
    }

    /// The profile options given (`--cam-tolerance 0.0005`, `--seed 3`, ...), as the
    /// user wrote them.
    pub fn given_profile_options(&self) -> Vec<String> {
        let d = Cams::default();
        let mut given = Vec::new();
        let mut num = |name: &str, v: Option<f64>| {
            if let Some(v) = v {
                given.push(format!("--{name} {v}"));
            }
        };
        num("cam-tolerance", self.cam_tolerance);
        num("roller-tolerance", self.roller_tolerance);
        num("eccentricity-tolerance", self.eccentricity_tolerance);
        num("interval-deg", self.interval_deg);
        if !self.waviness_fpr.is_empty() {
            given.push(format!("--waviness-fpr {}", fpr_list(&self.waviness_fpr)));
        }
        if let Some(s) = self.seed {
            given.push(format!("--seed {s}"));
        }
        if self.interval != d.interval {
            given.push(format!("--interval {}", value_name(&self.interval)));
        }
        if self.profile_method != d.profile_method {
            given.push(format!(
                "--profile-method {}",
                value_name(&self.profile_method)
            ));
        }
        if self.normal != d.normal {
            given.push(format!("--normal {}", value_name(&self.normal)));
        }
        given
    }

    /// A command that simulates the theoretical cam unless `--actual` is given refuses
    /// the profile options without it: a usage error naming them.
    pub fn ensure_actual_if_options(&self) -> Result<()> {
        let given = self.given_profile_options();
        if self.actual || given.is_empty() {
            return Ok(());
        }
        let verb = if given.len() == 1 { "shapes" } else { "shape" };
        Err(crate::args::usage(format!(
            "{} {verb} an actual cam: add --actual (without it the theoretical cam runs)",
            given.join(", ")
        )))
    }

    /// A command whose study always runs actual cams refuses `--actual` (a usage error:
    /// the flag would change nothing; it is hidden from the command's help).
    pub fn refuse_actual_flag(&self, command: &str) -> Result<()> {
        if self.actual {
            return Err(crate::args::usage(format!(
                "{command} always runs actual cams: drop --actual"
            )));
        }
        Ok(())
    }
}

/// The command-line name of a [`ValueEnum`] value.
pub fn value_name<V: ValueEnum>(v: &V) -> String {
    v.to_possible_value()
        .map(|p| p.get_name().to_string())
        .unwrap_or_default()
}
