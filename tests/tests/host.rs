//! The host harness: scene files round-trip and refuse bad input by name, CSV rows
//! carry every column, the per-period table covers every revolution and period.
//! (tests/scene.rs checks the scene schema against the core's key table.)

use camsim::scene::parse;
use camsim::sim::{self, RunSpec};

#[test]
fn default_scene_round_trips_to_the_reference_design() {
    let text = camsim::scene::default_text().unwrap();
    let spec = parse(&text).unwrap();
    let r = RunSpec::reference();
    assert_eq!(spec.design, r.design);
    assert_eq!(spec.revolutions, r.revolutions);
    assert_eq!(spec.dofs, r.dofs);
    assert_eq!(spec.solver, r.solver);
    // An empty scene is the reference too (every key optional).
    assert_eq!(parse("").unwrap().design, r.design);
    // Every key is present in the default text (a complete description).
    for key in [
        "i_m_lb_in_s2",
        "k_rb_lb_per_in",
        "e2_in",
        "spring_rate_lb_per_in",
        "[design.drive.regulated]",
        "[[design.program.segment]]",
        "law = \"4-5-6-7\"",
    ] {
        assert!(text.contains(key), "missing {key}");
    }
    // A changed scene survives the round trip through its own text.
    let mut other = RunSpec::reference();
    other.design.set_speed_rpm(1234.5).unwrap();
    other.design.drive = camsim_core::DriveLaw::ConstantMotorSpeed;
    other.design.program = camsim_core::CamProgram::with_laws(
        camsim_core::MotionLaw::Poly4567,
        camsim_core::MotionLaw::ModifiedTrapezoidal,
    );
    other.dofs.horizontal = false;
    other.solver.start = camsim_core::Start::Static;
    let other_text = camsim::scene::spec_text(&other).unwrap();
    assert!(other_text.contains("drive = \"constant-motor-speed\""));
    let back = parse(&other_text).unwrap();
    assert_eq!(back.design, other.design);
    assert_eq!(back.dofs, other.dofs);
    assert_eq!(back.solver, other.solver);
}

fn err(text: &str) -> String {
    format!("{:#}", parse(text).unwrap_err())
}

#[test]
fn bad_scenes_are_refused_with_the_key_and_the_rule() {
    let cases = [
        (
            "[design]\ncam_mass_lb_s2_per_in = -1\n",
            "line 2: design.cam_mass_lb_s2_per_in = -1: must be positive",
        ),
        (
            "[design]\nk_rb_lb_per_in = 0\n",
            "design.k_rb_lb_per_in = 0: must be positive",
        ),
        (
            "[design]\nload_mass_lb_s2_per_in = nan\n",
            "design.load_mass_lb_s2_per_in = NaN: must be positive and finite",
        ),
        (
            "[design]\ne2_in = 1.0\n",
            "design.e2_in = 1: cantilever length must exceed",
        ),
        ("[run]\nrevolutions = 0\n", "run.revolutions = 0"),
        (
            "[design]\nmas = 1\n",
            "line 2, column 1: design.mas: unknown field `mas`",
        ),
        (
            "[design]\ndrive = \"turbo\"\n",
            "design.drive: unknown variant `turbo`",
        ),
        (
            "[design.drive.regulated]\nk_p_lb_in_s_per_rad = -3\n",
            "design.drive.regulated.k_p_lb_in_s_per_rad = -3: must be zero or positive",
        ),
        (
            "[design.hertz]\nroller_poisson = 0.5\n",
            "design.hertz.roller_poisson = 0.5: must be in [0, 0.5)",
        ),
        (
            "[run]\nrpm = \"fast\"\n",
            "line 2, column 7: run.rpm: invalid type",
        ),
        (
            "[solver]\nrtol = 2\n",
            "solver.rtol = 2: must lie in [1e-13, 0.1]",
        ),
        (
            "[run]\nrpm = 900\n[design]\nomega0_rad_per_s = 90\n",
            "run.rpm and design.omega0_rad_per_s both set the cam speed",
        ),
    ];
    for (text, want) in cases {
        let e = err(text);
        assert!(e.contains(want), "{text:?}: got {e:?}, want {want:?}");
        assert!(!e.contains('\n'), "one line: {e:?}");
    }
    // A program that does not close over 360 degrees.
    let prog = "[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 0\nend_deg = 30\n\
                [[design.program.segment]]\nkind = \"rise\"\nlaw = \"cycloidal\"\nstart_deg = 30\nend_deg = 180\nlift_in = 1.0\n\
                [[design.program.segment]]\nkind = \"return\"\nlaw = \"cycloidal\"\nstart_deg = 180\nend_deg = 350\nlift_in = 1.0\n";
    let e = err(prog);
    assert!(
        e.contains("line 15: design.program.segment[2].end_deg = 350: must be 360"),
        "{e}"
    );
    // A law that does not exist.
    let e = err("[[design.program.segment]]\nkind = \"rise\"\nlaw = \"bogus\"\nstart_deg = 0\nend_deg = 360\nlift_in = 1\n");
    assert!(
        e.contains("line 3, column 7: design.program.segment[0].law: unknown variant `bogus`"),
        "{e}"
    );
}

/// Smallest convex radius of curvature of the pitch curve `r = R_a + y(θ)` of a
/// cycloidal rise of `h` over `beta` rad on prime radius `ra` (polar-curve formula
/// `(r² + r'²)^1.5 / (r² + 2r'² - r r'')`, sampled), independent of the core's check.
fn cycloidal_min_convex_pitch_radius(ra: f64, h: f64, beta: f64) -> f64 {
    use std::f64::consts::TAU;
    (0..=200_000)
        .map(|i| {
            let u = i as f64 / 200_000.0;
            let y = h * (u - (TAU * u).sin() / TAU);
            let y1 = h / beta * (1.0 - (TAU * u).cos());
            let y2 = h / (beta * beta) * TAU * (TAU * u).sin();
            let r = ra + y;
            let den = r * r + 2.0 * y1 * y1 - r * y2;
            if den > 0.0 {
                (r * r + y1 * y1).powf(1.5) / den
            } else {
                f64::INFINITY
            }
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn a_small_roller_on_a_steep_cam_is_accepted_and_a_large_one_refused() {
    // 30-degree cycloidal rise and return of 1.5 in on the 1.5 in base circle.
    let steep = |roller: f64| {
        format!(
            "[design.geometry]\nroller_radius_in = {roller:?}\n\
             [[design.program.segment]]\nkind='dwell'\nstart_deg=0\nend_deg=30\n\
             [[design.program.segment]]\nkind='rise'\nlaw='cycloidal'\nstart_deg=30\nend_deg=60\nlift_in=1.5\n\
             [[design.program.segment]]\nkind='dwell'\nstart_deg=60\nend_deg=210\n\
             [[design.program.segment]]\nkind='return'\nlaw='cycloidal'\nstart_deg=210\nend_deg=240\nlift_in=1.5\n\
             [[design.program.segment]]\nkind='dwell'\nstart_deg=240\nend_deg=360\n"
        )
    };
    let beta = 30f64.to_radians();
    // The premises, from the closed form: 0.5 in exceeds the smallest convex pitch radius
    // (0.44 in on R_a = 2.0 in), 0.3 in stays below it (0.40 in on R_a = 1.8 in).
    let (large, small) = (0.5, 0.3);
    assert!(cycloidal_min_convex_pitch_radius(1.5 + large, 1.5, beta) < 0.9 * large);
    assert!(cycloidal_min_convex_pitch_radius(1.5 + small, 1.5, beta) > 1.3 * small);
    let e = err(&steep(large));
    assert!(
        e.starts_with("line 2: design.geometry.roller_radius_in = 0.5: undercut"),
        "{e}"
    );
    let spec = parse(&steep(small)).unwrap();
    assert_eq!(spec.design.geometry.roller_radius, small);
    assert_eq!(spec.design.program.segments().len(), 5);
}

#[test]
fn garbage_is_refused_on_one_line_and_never_panics() {
    for text in [
        "[[[",
        "[design.geometry]\nroller_radius_in = 1e-300\n",
        "[design.geometry]\nroller_radius_in = -0.1\n",
        "[solver]\nrtol = 2\n",
        "[solver]\nmax_steps_per_rev = -1\n",
        "design = 5\n",
        "[design.program]\nsegment = 3\n",
        "\u{0}",
    ] {
        let e = err(text);
        assert!(!e.contains('\n'), "{text:?}: {e}");
    }
}

#[test]
fn csv_rows_and_period_table_cover_the_run() {
    let mut spec = RunSpec::reference();
    spec.revolutions = 2;
    spec.design.set_speed_rpm(400.0).unwrap();
    spec.solver.start = camsim_core::Start::Static;
    let path = std::env::temp_dir().join(format!("camsim-test-{}.csv", std::process::id()));
    let _ = std::fs::remove_file(&path);
    let file = camsim::output::Plan::new(false)
        .file("--csv", &path)
        .unwrap()
        .open()
        .unwrap();
    let mut w = camsim::csv::CsvOut::new(file, camsim::units::Units::Inch);
    let mut n = 0usize;
    let mut obs = |s: &camsim_core::Sample<f64>| {
        n += 1;
        w.row(s)
    };
    let r = sim::run(&spec, &mut obs).unwrap();
    w.into_file().unwrap().commit().unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let cols = header.split(',').count();
    assert_eq!(cols, 46);
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), n);
    assert!(rows.iter().all(|l| l.split(',').count() == cols));
    // Cam angle grows monotonically through the file.
    let idx = header.split(',').position(|c| c == "theta_c_rad").unwrap();
    let theta: Vec<f64> = rows
        .iter()
        .map(|l| l.split(',').nth(idx).unwrap().parse().unwrap())
        .collect();
    assert!(theta.windows(2).all(|w| w[1] >= w[0]));
    // Two revolutions x four periods, named as the JSON promises.
    let rows = sim::period_rows(&spec.design, &r.stats);
    let names: Vec<_> = rows.iter().map(|r| (r.revolution, r.period)).collect();
    assert_eq!(
        names,
        [
            (1, "dwell_low"),
            (1, "rise"),
            (1, "dwell_high"),
            (1, "return"),
            (2, "dwell_low"),
            (2, "rise"),
            (2, "dwell_high"),
            (2, "return")
        ]
    );
    // At 400 rpm the reference holds contact: no jump, minimum force above zero.
    assert!(rows
        .iter()
        .all(|r| !r.jump && r.contact_force_min.in_inch() > 0.0));
    // In the dwells the cam does no work: zero output torque (dy/dθ = 0).
    assert_eq!(rows[0].torque_avg.in_inch(), 0.0);
    // The default method (Merson's pair): one evaluation at the start, five per accepted
    // step (four stages and the end point's derivative, which the continuous extension
    // and the next step share), four per rejected one; the default step control (the
    // tolerance-scaled stiffness cap, `StepRule::ScaledCap`) adds its spectral-radius
    // estimates: one at the start and one every 25 accepted steps, each at most 1 + 20
    // power iterations.
    let merson = 1 + 5 * r.solver.accepted + 4 * r.solver.rejected;
    let estimates = 1 + r.solver.accepted / 25;
    assert!(
        r.solver.rhs_evals > merson && r.solver.rhs_evals <= merson + 21 * estimates,
        "{:?}",
        r.solver
    );
}

#[test]
fn an_undercut_cam_is_refused_naming_the_roller() {
    // 30-degree cycloidal rise and return of 1.5 in on a 0.1 in base circle: the pitch
    // curve's convex radius falls below a 0.6 in roller.
    let text = "[design.geometry]\nroller_radius_in = 0.6\nbase_radius_in = 0.1\n\
        [[design.program.segment]]\nkind='dwell'\nstart_deg=0\nend_deg=30\n\
        [[design.program.segment]]\nkind='rise'\nlaw='cycloidal'\nstart_deg=30\nend_deg=60\nlift_in=1.5\n\
        [[design.program.segment]]\nkind='dwell'\nstart_deg=60\nend_deg=210\n\
        [[design.program.segment]]\nkind='return'\nlaw='cycloidal'\nstart_deg=210\nend_deg=240\nlift_in=1.5\n\
        [[design.program.segment]]\nkind='dwell'\nstart_deg=240\nend_deg=360\n";
    let e = err(text);
    assert!(
        e.starts_with("line 2: design.geometry.roller_radius_in = 0.6: undercut"),
        "{e}"
    );
    // The same program with a small roller on a big base circle is fine.
    let ok = text
        .replace("roller_radius_in = 0.6", "roller_radius_in = 0.1")
        .replace("base_radius_in = 0.1", "base_radius_in = 3.0");
    assert!(parse(&ok).is_ok());
}

/// Issue 18: a spring the drive cannot turn stalls it, and the refusal says so: the
/// spring's quasi-static torque K_rs (δ_rs + y) y' against the drive's torque limit.
#[test]
fn a_stalled_drive_names_the_spring_against_the_drive() {
    let mut spec = RunSpec::reference();
    spec.revolutions = 1;
    spec.design.set_spring_rate(17.5e3).unwrap();
    let Err(e) = sim::run(&spec, &mut sim::Nothing) else {
        panic!("a 17 500 lb/in spring ran")
    };
    let e = format!("{e:#}");
    assert!(e.contains("the drive stalled"), "{e}");
    assert!(
        e.contains("Why: the return spring (K_rs = 17500 lb/in"),
        "{e}"
    );
    assert!(
        e.contains("more than the drive's torque limit of 345 lb in"),
        "{e}"
    );
    // The peak torque it quotes lies between the rise's mean (the spring's energy
    // over the rise, K_rs (δ h + h²/2) / β) and K_rs (δ + h) times the largest slope.
    let d = &spec.design;
    let hint = sim::stall_hint(d).unwrap();
    let peak: f64 = hint
        .split("alone takes up to ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap()
        .parse()
        .unwrap();
    let rise = d
        .program
        .segments()
        .iter()
        .find(|s| matches!(s.kind, camsim_core::SegmentKind::Rise(_)))
        .unwrap();
    let (h, beta) = (rise.lift, (rise.end_deg - rise.start_deg).to_radians());
    let mean = d.k_rs * (d.delta_rs * h + h * h / 2.0) / beta;
    let max_slope = (0..3600)
        .map(|i| {
            d.program
                .follower(i as f64 * std::f64::consts::TAU / 3600.0)
                .dy
        })
        .fold(0.0, f64::max);
    assert!(
        peak >= mean && peak <= d.k_rs * (d.delta_rs + h) * max_slope + 1.0,
        "{peak} {mean}"
    );
    // A spring the drive turns gives no hint (a run that does not stall).
    assert!(sim::run(
        &RunSpec {
            revolutions: 1,
            ..RunSpec::reference()
        },
        &mut sim::Nothing
    )
    .is_ok());
}

/// Issue 17: the verdict's limits are scene keys (`[limits]`, SI or inch), the options
/// override them, the core's constants are the defaults.
#[test]
fn the_verdict_limits_come_from_the_scene_and_the_options_override() {
    use camsim::cmd::run::VerdictArgs;
    let spec =
        parse("[limits]\nallowable_contact_stress_mpa = 1000\npressure_angle_limit_deg = 25\n")
            .unwrap();
    let l = VerdictArgs::default().limits(&spec.limits, camsim::units::Units::Inch);
    // 1000 MPa = 1e9 Pa / 6894.757293168 Pa/psi.
    assert!((l.allowable_contact_stress_psi - 1e9 / 6_894.757_293_168).abs() < 1e-6);
    assert_eq!(l.pressure_angle_limit_deg, 25.0);
    assert_eq!(l.allowable_source, "the scene's [limits]");
    let args = VerdictArgs {
        allowable_stress: Some(120_000.0),
        pressure_angle_limit: Some(35.0),
        ..VerdictArgs::default()
    };
    let l = args.limits(&spec.limits, camsim::units::Units::Inch);
    assert_eq!(
        (l.allowable_contact_stress_psi, l.pressure_angle_limit_deg),
        (120_000.0, 35.0)
    );
    assert_eq!(l.allowable_source, "--allowable-stress");
    let l = VerdictArgs::default().limits(&RunSpec::reference().limits, camsim::units::Units::Inch);
    assert_eq!(
        (l.allowable_contact_stress_psi, l.pressure_angle_limit_deg),
        (
            camsim_core::ALLOWABLE_CONTACT_STRESS_PSI,
            camsim_core::PRESSURE_ANGLE_LIMIT_DEG
        )
    );
    assert_eq!(l.allowable_source, camsim::verdict::ALLOWABLE_SOURCE);
}

/// `[solver] step_control` and `--step-control` (docs/MODEL.md §3.16): absent, the default
/// (the tolerance-scaled cap); each name read, echoed by the scene text and read back;
/// a bad name refused in one line naming the key, the value and the accepted names, by the
/// scene file and by the command line (a usage error: exit status 2).
#[test]
fn step_control_is_read_echoed_and_refused_by_name() {
    use camsim_core::StepRule;
    assert_eq!(parse("").unwrap().solver.step_control, StepRule::ScaledCap);
    for rule in StepRule::ALL {
        let spec = parse(&format!("[solver]\nstep_control = \"{}\"\n", rule.name())).unwrap();
        assert_eq!(spec.solver.step_control, rule);
        assert_eq!(StepRule::from_name(rule.name()), Some(rule));
        // The echo (what `run --json` and `scene --check` print) reproduces the run.
        let text = camsim::scene::spec_text(&spec).unwrap();
        assert!(
            text.contains(&format!("step_control = \"{}\"", rule.name())),
            "{text}"
        );
        assert_eq!(parse(&text).unwrap().solver, spec.solver);
        // The option sets the same rule on the reference scene.
        let cli =
            camsim::cli::parse_from(["camsim", "run", "--step-control", rule.name()]).unwrap();
        let camsim::cli::Command::Run(a) = cli.command else {
            panic!("not run")
        };
        let from_option = camsim::args::spec_from(&a.scene).unwrap();
        assert_eq!(from_option.solver.step_control, rule);
    }
    let e = err("[solver]\nstep_control = \"capped\"\n");
    assert!(
        e.starts_with("line 2, column 16: solver.step_control: unknown variant `capped`, expected one of `thesis`, `scaled-cap`, `pi-scaled-cap`"),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
    let usage = camsim::cli::usage_line(
        &camsim::cli::parse_from(["camsim", "run", "--step-control", "capped"]).unwrap_err(),
    );
    assert!(
        usage.starts_with("invalid value 'capped' for '--step-control <CONTROL>'")
            && usage.contains("thesis, scaled-cap, pi-scaled-cap"),
        "{usage}"
    );
    assert_eq!(
        camsim::cli::main_from(["camsim", "run", "--step-control", "capped"]),
        2
    );
}
