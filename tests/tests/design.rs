//! `camsim run`'s verdict and `camsim design spring` (issue 17).

use camsim::cmd::design::{spring, SpringArgs};
use camsim::cmd::run::{report, Args as RunArgs, SceneArgs};

fn spring_args(actual: bool, threads: u32) -> SpringArgs {
    SpringArgs {
        scene: SceneArgs::default(),
        margin: 15.0,
        actual: camsim::args::ActualArgs {
            actual,
            ..Default::default()
        },
        p_max: 0.01,
        samples: None,
        threads: Some(threads),
        resolution: 1.0,
        max_rate: 1000.0,
        preload: false,
        max_preload_length: camsim::cmd::design::MAX_PRELOAD_LENGTH,
        quick: true,
        json: false,
    }
}

/// The verdict's extremes against the per-period table the statistics keep on their own:
/// the smallest contact force and the peak stress of the judged revolutions (2-3) are the
/// table's, and the pressure angle is the closed form tan φ = y' / (R_a + y) at its angle.
#[test]
fn verdict_agrees_with_the_table_and_the_geometry() {
    let r = report(&RunArgs::default(), camsim::units::Units::Inch).unwrap();
    let v = r.verdict.as_ref().unwrap();
    let judged = r.per_period.iter().filter(|p| p.revolution >= 2);
    let fmin = judged
        .clone()
        .map(|p| p.contact_force_min.in_inch())
        .fold(f64::INFINITY, f64::min);
    let smax = judged
        .map(|p| p.contact_stress_max.in_inch())
        .fold(0.0, f64::max);
    assert_eq!(v.contact.min_contact_force_lb.in_inch(), fmin);
    assert_eq!(v.loads.peak_contact_stress_psi.in_inch(), smax);
    // Contact holds and nothing warns: the thesis drive's cam-speed swing (3.4 % at 800
    // rpm, past the 2 % limit) is the reference's given drive, stated on the drive line.
    assert!(v.contact.holds, "{:?}", v.warnings);
    assert!(v.warnings.is_empty(), "{:?}", v.warnings);
    let d = camsim_core::Design::<f64>::reference();
    let th = v.geometry.max_pressure_angle_at_deg.to_radians();
    let f = d.program.follower(th);
    let phi = (f.dy / (d.geometry.prime_radius() + f.y))
        .atan()
        .abs()
        .to_degrees();
    assert!((phi - v.geometry.max_pressure_angle_deg).abs() < 1e-9);
    // A limit below it warns, naming the option.
    let mut a = RunArgs {
        revolutions: Some(2),
        ..Default::default()
    };
    a.verdict.pressure_angle_limit = Some(phi - 1.0);
    let r = report(&a, camsim::units::Units::Inch).unwrap();
    let w = &r.verdict.unwrap().warnings;
    assert!(
        w.iter().any(|w| w.contains("--pressure-angle-limit")),
        "{w:?}"
    );
}

/// The theoretical search's answer holds contact at 920 rpm and the rate a bracket below
/// does not (the predicate re-run outside the search), and its own jump onset is above
/// 920 rpm.
#[test]
fn design_spring_theoretical_brackets_the_criterion() {
    let r = spring(&spring_args(false, 1), camsim::units::Units::Inch).unwrap();
    let below = r.failing_rate_lb_per_in.unwrap().in_inch();
    assert!(r.bracket_lb_per_in.in_inch() <= 10.0 && r.bracket_lb_per_in.in_inch() > 0.0);
    let mut spec = camsim::cmd::run::spec_from(&SceneArgs::default()).unwrap();
    spec.solver.start = camsim_core::Start::Static;
    spec.revolutions = 2;
    let at = |k: f64| {
        let mut s = spec.clone();
        s.design.set_spring_rate(k).unwrap();
        camsim::sim::jumps_at(&s, 920.0).unwrap()
    };
    assert!(!at(r.spring_rate_lb_per_in.in_inch()));
    assert!(at(below));
    assert!(r.jump_onset_rpm.unwrap() > 920.0);
    // Issue 30: the spring to build passes every check the verdict makes, re-read as a
    // scene's [design.spring] and judged by the verdict outside the search: contact at
    // 920 rpm with its own rate and mass, surge at least 13 x the cam's 13.33 Hz, Wahl
    // stress at full compression within the allowable, not solid, no spring warning.
    let p = r.part.as_ref().unwrap();
    let c = &p.spring;
    let scene = format!(
        "[design.spring]\nwire_diameter_in = {}\nmean_diameter_in = {}\nactive_coils = {}\nends = \"{}\"\nmaterial = \"{}\"\nfree_length_in = {}\n",
        c.wire_diameter_in.in_inch(), c.mean_diameter_in.in_inch(), c.active_coils, p.ends, p.material, c.free_length_in.in_inch()
    );
    let built = camsim::scene::parse(&scene).unwrap();
    assert!(built.design.k_rs >= r.spring_rate_lb_per_in.in_inch());
    let v = camsim::verdict::spring(&built.design, built.spring.as_ref()).unwrap();
    assert!(v.surge_hz >= 13.0 * 800.0 / 60.0, "{}", v.surge_hz);
    assert!(v.shear_stress_psi.in_inch() <= v.allowable_shear_psi.in_inch());
    assert_eq!(v.solid(), Some(false));
    assert!(camsim::verdict::spring_part_warnings(&v, camsim::units::Units::Inch).is_empty());
    let mut s = spec.clone();
    s.design = built.design.clone();
    assert!(!camsim::sim::jumps_at(&s, 920.0).unwrap());
}

/// The actual-cam search gives the same answer, bit for bit, on 1 and 2 threads.
#[test]
fn design_spring_actual_is_the_same_on_one_and_two_threads() {
    let one = spring(&spring_args(true, 1), camsim::units::Units::Inch).unwrap();
    let two = spring(&spring_args(true, 2), camsim::units::Units::Inch).unwrap();
    assert_eq!(one.spring_rate_lb_per_in, two.spring_rate_lb_per_in);
    assert_eq!(one.rates_tried_lb_per_in, two.rates_tried_lb_per_in);
    assert_eq!(one.p_jump, two.p_jump);
    assert!(one.p_jump.unwrap().hi95 <= 0.1);
}

fn mc_args(threads: u32) -> camsim::cmd::design::McArgs {
    camsim::cmd::design::McArgs {
        scene: SceneArgs::default(),
        p_max: 0.01,
        samples: None,
        threads: Some(threads),
        actual: camsim::args::ActualArgs::default(),
        waviness: false,
        tolerance_factor: None,
        quick: true,
        json: false,
    }
}

/// `design tolerance --waviness` (quick): the roughest waviness (the highest FPR) that
/// passes at VI.1's tolerances; the same on 1 and 2 threads, a whole number of waves,
/// every FPR tried at or below it passes and every one at or above the failing one fails,
/// and the cam tolerance is the one held. At 4 x the tolerances it can only be smoother.
#[test]
fn design_tolerance_waviness_brackets_the_roughest_fpr() {
    use camsim::cmd::design::mc_search;
    let args = |threads, factor| camsim::cmd::design::McArgs {
        waviness: true,
        tolerance_factor: Some(factor),
        ..mc_args(threads)
    };
    let a = mc_search(&args(1, 1.0), false, camsim::units::Units::Inch).unwrap();
    let b = mc_search(&args(2, 1.0), false, camsim::units::Units::Inch).unwrap();
    assert_eq!(
        (a.answer, a.failing, &a.tried),
        (b.answer, b.failing, &b.tried)
    );
    assert_eq!(a.search, "waviness");
    assert_eq!(a.answer.fract(), 0.0);
    let failing = a.failing.unwrap();
    assert!(a
        .tried
        .iter()
        .all(|&(x, ok)| if ok { x <= a.answer } else { x >= failing }));
    assert_eq!(a.cam_tolerance_in, Some(0.0005.into()));
    let loose = mc_search(&args(2, 4.0), false, camsim::units::Units::Inch).unwrap();
    assert!(loose.answer <= a.answer, "{} > {}", loose.answer, a.answer);
}

/// `design speed` and `design tolerance` (quick): the same answer on 1 and 2 threads; the
/// answer passes (its upper Wilson bound at most the quick mode's 0.1) and is the largest
/// value tried below the failing one; a speed above the theoretical cam's onset cannot
/// pass, since there the perfect cam separates and every cam counts as jumping.
#[test]
fn design_speed_and_tolerance_bracket_their_criterion_on_any_thread_count() {
    use camsim::cmd::design::mc_search;
    for speed in [true, false] {
        let a = mc_search(&mc_args(1), speed, camsim::units::Units::Inch).unwrap();
        let b = mc_search(&mc_args(2), speed, camsim::units::Units::Inch).unwrap();
        assert_eq!(
            (a.answer, a.failing, &a.tried),
            (b.answer, b.failing, &b.tried)
        );
        let p = a.p_jump.unwrap();
        assert!(p.hi95 <= 0.1, "{p:?}");
        let failing = a.failing.unwrap();
        assert!(failing > a.answer);
        assert!(a
            .tried
            .iter()
            .all(|&(x, ok)| if ok { x <= a.answer } else { x >= failing }));
        if speed {
            assert!(a.answer < a.theoretical_onset_rpm.unwrap());
        } else {
            assert_eq!(a.cam_tolerance_in.unwrap().in_inch(), 0.0005 * a.answer);
        }
    }
}

/// `design spring --preload`: the rate held, the preload length searched. Its answer holds
/// contact at 920 rpm and the length a bracket below does not (the predicate re-run
/// outside the search); the rate reported is the scene's.
#[test]
fn design_spring_preload_brackets_the_criterion() {
    let mut a = spring_args(false, 1);
    a.preload = true;
    let r = spring(&a, camsim::units::Units::Inch).unwrap();
    assert_eq!(r.searched, "preload length");
    assert_eq!(r.spring_rate_lb_per_in.in_inch(), 100.0);
    let fail = r.failing_preload_length_in.unwrap().in_inch();
    let pass = fail + r.preload_bracket_in.unwrap().in_inch();
    assert!(fail < pass && pass - fail <= 0.1 + 1e-12, "{fail} {pass}");
    // The part is built at the length reported (raised from the length found only when
    // its own mass asked for more), and its scene lines carry that length.
    let part = r.part.as_ref().unwrap();
    assert_eq!(r.preload_length_in, part.preload_length_in);
    assert!(part.preload_length_in.in_inch() >= pass, "{part:?}");
    assert!(
        camsim::report::Report::text(&r, camsim::units::Units::Inch).contains(&format!(
            "and in [design]: spring_preload_length_in = {:.4}",
            part.preload_length_in.in_inch()
        )),
        "{}",
        camsim::report::Report::text(&r, camsim::units::Units::Inch)
    );
    let mut spec = camsim::cmd::run::spec_from(&SceneArgs::default()).unwrap();
    spec.solver.start = camsim_core::Start::Static;
    spec.revolutions = 2;
    let at = |d: f64| {
        let mut s = spec.clone();
        s.design.delta_rs = d;
        camsim::sim::jumps_at(&s, 920.0).unwrap()
    };
    assert!(!at(pass));
    assert!(at(fail));
    // The reference's 0.5 in does not hold at 920 rpm (its onset is 902 rpm): the answer
    // is longer.
    assert!(pass > 0.5);
}

/// A scene file under the temporary directory (removed by the caller).
fn scene_file(name: &str, text: &str) -> std::path::PathBuf {
    let p = std::env::temp_dir().join(format!("camsim-machine-{}-{name}.toml", std::process::id()));
    std::fs::write(&p, text).unwrap();
    p
}

fn run_scene(path: &std::path::Path) -> camsim::verdict::Verdict {
    let mut a = RunArgs {
        revolutions: Some(2),
        ..Default::default()
    };
    a.scene.scene = Some(path.to_path_buf());
    report(&a, camsim::units::Units::Inch)
        .unwrap()
        .verdict
        .unwrap()
}

/// Issue 30: the verdict's mass line is the model's translating mass by its parts (the
/// reference's by hand: M_l 3.428e-3, the rod M_f (1 + e2/e1) with M_f = 0.007764, the
/// roller 0.00013, a third of the spring, times g = 386.0886 in/s^2), and the drive line
/// holds the cam speed's extremes about the nominal. The reference's drive is given (the
/// thesis's machine): its swing past 2 % is stated on the drive line, not warned.
#[test]
fn verdict_prints_the_moving_mass_and_the_drive_swing() {
    let r = report(
        &RunArgs {
            revolutions: Some(2),
            ..Default::default()
        },
        camsim::units::Units::Inch,
    )
    .unwrap();
    let v = r.verdict.unwrap();
    let d = camsim_core::Design::<f64>::reference();
    let g = 9.80665 / 0.0254;
    let rod = 0.007764 * (1.0 + 2.0 / d.e1);
    let hand = (3.428e-3 + rod + 0.00013 + camsim_core::SPRING_MASS / 3.0) * g;
    assert!(
        (v.mass.moving_mass_lb.in_inch() / hand - 1.0).abs() < 1e-9,
        "{}",
        v.mass.moving_mass_lb.in_inch()
    );
    let parts = v.mass.load_mass_lb.in_inch()
        + v.mass.rod_mass_lb.in_inch()
        + v.mass.roller_mass_lb.in_inch()
        + v.mass.spring_share_mass_lb.in_inch();
    assert!((parts / v.mass.moving_mass_lb.in_inch() - 1.0).abs() < 1e-12);
    let dr = &v.drive;
    assert_eq!(dr.drive, "regulated");
    assert!(
        dr.min_cam_speed_rpm < 800.0 && dr.max_cam_speed_rpm > 800.0,
        "{dr:?}"
    );
    let swing = 100.0 * (800.0 - dr.min_cam_speed_rpm).max(dr.max_cam_speed_rpm - 800.0) / 800.0;
    assert!((dr.swing_percent - swing).abs() < 1e-9);
    assert_eq!(dr.swing_limit_percent, 2.0);
    assert!(swing > 2.0 && dr.given, "{dr:?}");
    assert!(v.warnings.is_empty(), "{:?}", v.warnings);
    let text = camsim::verdict::text(&v, camsim::units::Units::Inch);
    let line = text.lines().find(|l| l.contains("drive:")).unwrap();
    assert!(
        line.contains(&format!("{:.2} % from the nominal 800.0 rpm", swing))
            && line.contains("the drive is given, so the result includes"),
        "{line}"
    );
    // The constant-speed drive ("constant-speed" reads as "constant-cam-speed"): the cam
    // speed is exactly the nominal at every sample, no swing, no warning.
    let p = scene_file("constant", "[design]\ndrive = \"constant-speed\"\n");
    let v = run_scene(&p);
    std::fs::remove_file(&p).unwrap();
    assert_eq!(v.drive.drive, "constant-cam-speed");
    assert_eq!(v.drive.min_cam_speed_rpm, v.drive.nominal_rpm);
    assert_eq!(v.drive.max_cam_speed_rpm, v.drive.nominal_rpm);
    assert_eq!(v.drive.swing_percent, 0.0);
    assert!(
        !v.warnings.iter().any(|w| w.contains("cam speed")),
        "{:?}",
        v.warnings
    );
    let text = camsim::verdict::text(&v, camsim::units::Units::Inch);
    assert!(
        text.contains("0.00 % from the nominal 800.0 rpm (limit 2 %)"),
        "{text}"
    );
}

/// Issue 30: the swing warning is for a drive the scene does not name. At 800 rpm a scene
/// without a drive inherits the thesis's motor and swings as the reference does (the same
/// model, 3.4 %, past the 2 % limit): it warns, naming the ways out. The same scene with
/// `drive = "thesis"` (the same drive, named) swings exactly as much and does not warn.
#[test]
fn an_inherited_drive_warns_on_its_swing_and_a_named_one_does_not() {
    let inherited = scene_file("inherited", "[run]\nrpm = 800.0\n");
    let named = scene_file(
        "named",
        "[run]\nrpm = 800.0\n[design]\ndrive = \"thesis\"\n",
    );
    let (i, n) = (run_scene(&inherited), run_scene(&named));
    let _ = (
        std::fs::remove_file(&inherited),
        std::fs::remove_file(&named),
    );
    assert_eq!(i.drive.swing_percent, n.drive.swing_percent);
    assert!(i.drive.swing_percent > 2.0, "{:?}", i.drive);
    assert!(!i.drive.given && n.drive.given);
    assert_eq!(i.warnings.len(), 1, "{:?}", i.warnings);
    let w = &i.warnings[0];
    assert!(
        w.starts_with("the cam speed swings 3.4 %")
            && w.contains("the scene names no drive")
            && w.contains("drive = \"thesis\"")
            && w.contains("[design.drive.motor]"),
        "{w}"
    );
    assert!(n.warnings.is_empty(), "{:?}", n.warnings);
    let text = camsim::verdict::text(&n, camsim::units::Units::Inch);
    assert!(text.contains("the drive is given"), "{text}");
    let text = camsim::verdict::text(&i, camsim::units::Units::Inch);
    assert!(
        text.contains("inherited: the scene names no drive"),
        "{text}"
    );
}

/// Issue 30: a moving mass in kg is the model's translating mass, the verdict's total.
#[test]
fn a_moving_mass_is_the_models_translating_mass() {
    let p = scene_file("moving", "[design]\nmoving_mass_kg = 2.5\n");
    let v = run_scene(&p);
    std::fs::remove_file(&p).unwrap();
    let kg = v.mass.moving_mass_lb.in_inch() * 0.453_592_37;
    assert!((kg - 2.5).abs() < 1e-9, "{kg}");
}

/// Issue 30: `scene --new`'s templates (inch and SI) read back and are the designer's
/// machine: the keys they give are the design's, and the drive is named.
#[test]
fn scene_new_templates_read_back() {
    use camsim::cmd::scene::new_template;
    use camsim::units::Units;
    for (text, kg) in [
        (new_template(Units::Inch), 4.5 * 0.453_592_37),
        (new_template(Units::Si), 2.0),
    ] {
        let spec = camsim::scene::parse(&text).unwrap();
        let total = spec.design.moving_mass().total() * 9.80665 / 0.0254 * 0.453_592_37;
        assert!((total - kg).abs() < 1e-9, "{total} {kg}");
        assert_eq!(spec.design.drive, camsim_core::DriveLaw::ConstantCamSpeed);
        assert_eq!(spec.design.k_rs_modal, spec.design.k_rs);
        assert!((camsim_core::rad_per_s_to_rpm(spec.design.omega0) - 300.0).abs() < 1e-9);
        // Every line with a key carries a comment.
        for l in text
            .lines()
            .filter(|l| l.contains(" = ") && !l.starts_with('#'))
        {
            let key = l.split(" = ").next().unwrap();
            if !["kind", "start_deg", "end_deg"].contains(&key) {
                assert!(l.contains("  # "), "{l}");
            }
        }
    }
}

/// The keys of `scene` output (the listing's `# path = value` lines and the scene's
/// `key = value` lines), without their table path.
fn output_keys(out: &str) -> Vec<String> {
    out.lines()
        .filter_map(|l| l.trim_start_matches(['#', ' ']).split_once(" = "))
        .map(|(k, _)| k.rsplit('.').next().unwrap().to_string())
        .collect()
}

/// Issue 30: `scene --check` on an SI file lists and prints it back in SI whatever
/// `--units` says (every key with a unit is the SI one: converting it to SI leaves it
/// as it is), the user's values as written and the derived ones under SI keys; an inch
/// file under the default units stays in inch (the check can fail).
#[test]
fn scene_check_keeps_an_si_files_unit_family() {
    use camsim::units::{key_in, Units};
    let si = scene_file("check-si", &camsim::cmd::scene::new_template(Units::Si));
    let inch = scene_file("check-inch", &camsim::cmd::scene::new_template(Units::Inch));
    let out = |p: &std::path::Path, json: bool| {
        let mut argv = vec!["camsim", "scene", "--check", p.to_str().unwrap()];
        if json {
            argv.push("--json");
        }
        let camsim::cli::Command::Scene(a) = camsim::cli::parse_from(argv).unwrap().command else {
            panic!("not scene")
        };
        camsim::cmd::scene::output(&a, Units::Inch).unwrap()
    };
    let text = out(&si, false);
    let keys = output_keys(&text);
    assert!(keys.len() > 100, "{text}");
    for k in &keys {
        assert_eq!(
            key_in(k, Units::Si).0,
            *k,
            "an inch key in an SI file's check:\n{text}"
        );
    }
    for line in [
        "#   design.moving_mass_kg = 2.0",
        "#   design.spring_rate_n_per_mm = 10.0",
        "#   design.load_mass_kg = ",
        "#   design.e2_mm = 80.0",
        "#     follower_density_kg_per_m3 = 7849.99",
        "\nbase_radius_mm = 60",
    ] {
        assert!(text.contains(line), "{line:?} missing:\n{text}");
    }
    let json: serde_json::Value = serde_json::from_str(&out(&si, true)).unwrap();
    assert_eq!(json["design"]["geometry"]["base_radius_mm"], 60.0);
    assert!(json["design"]["geometry"].get("base_radius_in").is_none());
    let inch_text = out(&inch, false);
    assert!(inch_text.contains("#   design.moving_mass_lb = 4.5"));
    assert!(output_keys(&inch_text)
        .iter()
        .all(|k| key_in(k, Units::Inch).0 == *k));
    let _ = (std::fs::remove_file(&si), std::fs::remove_file(&inch));
}

/// Issue 30: `scene --check` on a constant-speed scene lists the drive's inertias, shafts
/// and motor bearing as not used (the model drops the rotations: docs/MODEL.md §5.17), not
/// as inherited; the cam's drag C_cc (the ideal drive supplies it) and the speed stay
/// inherited. A scene with the regulated drive lists them all as inherited.
#[test]
fn scene_check_lists_a_constant_speed_drives_values_as_not_used() {
    let check = |text: &str| {
        let p = scene_file("check-drive", text);
        let argv = ["camsim", "scene", "--check", p.to_str().unwrap()];
        let camsim::cli::Command::Scene(a) = camsim::cli::parse_from(argv).unwrap().command else {
            panic!("not scene")
        };
        let out = camsim::cmd::scene::output(&a, camsim::units::Units::Inch).unwrap();
        std::fs::remove_file(&p).unwrap();
        out
    };
    let unused = [
        "i_m_lb_in_s2",
        "i_cp_lb_in_s2",
        "i_c_lb_in_s2",
        "c_mb_",
        "c_s1_",
        "c_s2_",
        "k_s1_",
        "k_s2_",
        "coupling_backlash_rad",
    ];
    let listing = |out: &str| {
        let end = out.find("\n[run]").unwrap();
        out[..end].to_string()
    };
    let out = listing(&check("[design]\ndrive = \"constant-speed\"\n"));
    let (inherited, not_used) = out.split_once("# not used (constant-speed drive").unwrap();
    for k in unused {
        assert!(
            !inherited.contains(k) && not_used.contains(k),
            "{k}:\n{out}"
        );
    }
    for k in ["c_cc_", "omega0_rad_per_s"] {
        assert!(
            inherited.contains(k) && !not_used.contains(k),
            "{k}:\n{out}"
        );
    }
    let out = listing(&check("[run]\nrpm = 300.0\n"));
    assert!(!out.contains("not used"), "{out}");
    for k in unused {
        assert!(out.contains(&format!("#     {k}")), "{k}:\n{out}");
    }
}

/// Issue 30's task from `scene --new --units si`: the template with only its values
/// changed to a 40 mm rise and return over 120° each (modified sine), base radius 60 mm,
/// roller 15 mm, 1.2 kg moving, 300 rpm, 10 N/mm with 30 mm preload. It reads back (the
/// template's rod leaves a load, and its e2 clears a 40 mm lift with a 15 mm roller),
/// its mass line is the closed form (the template's 16 mm steel rod,
/// rho A (e1 + e2) = 7849.99 kg/m^3 x 201.06 mm^2 x 230 mm), and it runs: contact holds,
/// as it must where the spring's least force k delta = 300 N exceeds the largest
/// inertia force 1.2 kg x C_a h (omega/beta)^2 = 59.7 N (modified sine, C_a = 5.528).
#[test]
fn the_issues_task_runs_from_the_si_template() {
    let task = [
        ("moving_mass_kg", "1.2"),
        ("spring_rate_n_per_mm", "10.0"),
        ("spring_preload_length_mm", "30.0"),
        ("base_radius_mm", "60.0"),
        ("roller_radius_mm", "15.0"),
        ("lift_mm", "40.0"),
        ("rpm", "300.0"),
    ];
    let template = camsim::cmd::scene::new_template(camsim::units::Units::Si);
    let mut changed = 0;
    let text: String = template
        .lines()
        .map(|l| {
            let key = l.split(" = ").next().unwrap();
            match task.iter().find(|(k, _)| *k == key) {
                Some((k, v)) => {
                    changed += 1;
                    format!("{k} = {v}\n")
                }
                None => format!("{l}\n"),
            }
        })
        .collect();
    assert_eq!(changed, 8, "every task value has its key in the template");
    let p = scene_file("task", &text);
    let v = run_scene(&p);
    std::fs::remove_file(&p).unwrap();
    let kg = 0.453_592_37;
    let rod = 7849.99 * 201.06e-9 * 230.0;
    assert!((v.mass.moving_mass_lb.in_inch() * kg - 1.2).abs() < 1e-9);
    assert!(
        (v.mass.rod_mass_lb.in_inch() * kg / rod - 1.0).abs() < 1e-5,
        "{:?}",
        v.mass
    );
    assert!(v.mass.load_mass_lb.in_inch() * kg > 0.7, "{:?}", v.mass);
    assert!(v.contact.holds, "{:?}", v.contact);
    let inertia = 1.2
        * 5.528
        * 0.040
        * (10.0 * std::f64::consts::PI / (2.0 * std::f64::consts::PI / 3.0)).powi(2);
    assert!((inertia - 59.7).abs() < 0.1, "{inertia}");
    assert!(v.contact.min_contact_force_lb.in_inch() * 4.448_221_615_260_5 > 300.0 - inertia);
}

/// Issue 30: the drive's texts name scene forms the reader accepts. A scene without a
/// drive at 800 rpm swings past the 2 % limit (3.4 %) with the thesis drive it inherits;
/// the same motor given as a `[design.drive.motor]` table (the thesis's armature inertia)
/// swings the same, its drive line names that table and, the drive being given, nothing
/// warns; the inherited drive's warning names the motor table, and both forms read.
#[test]
fn the_drive_texts_name_the_scenes_own_table() {
    let swing = |v: &camsim::verdict::Verdict| {
        v.warnings
            .iter()
            .find(|w| w.starts_with("the cam speed swings"))
            .cloned()
            .unwrap_or_default()
    };
    let motor = scene_file(
        "motor",
        "[run]\nrpm = 800.0\n[design.drive.motor]\ninertia_lb_in_s2 = 0.0291\n",
    );
    let thesis = scene_file("thesis", "[run]\nrpm = 800.0\n");
    let (m, t) = (run_scene(&motor), run_scene(&thesis));
    let _ = (std::fs::remove_file(&motor), std::fs::remove_file(&thesis));
    assert!((m.drive.swing_percent - t.drive.swing_percent).abs() < 1e-9);
    assert!(t.drive.swing_percent > 2.0, "{:?}", t.drive);
    assert_eq!((m.drive.drive, t.drive.drive), ("motor", "regulated"));
    assert!(m
        .drive
        .description
        .contains("the scene's [design.drive.motor]"));
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    let w = swing(&t);
    assert!(w.contains("a [design.drive.motor] table (inertia"), "{w}");
    for form in [
        "[design.drive.regulated]\nk_p_lb_in_s_per_rad = 40.0\nt_max_lb_in = 900.0\n",
        "[design.drive.motor]\ngain_lb_in_s_per_rad = 40.0\ntorque_limit_lb_in = 900.0\n",
    ] {
        let spec = camsim::scene::parse(form).unwrap();
        let camsim_core::DriveLaw::Regulated { k_p, t_max, .. } = spec.design.drive else {
            panic!("{form}")
        };
        assert_eq!((k_p, t_max), (40.0, 900.0), "{form}");
    }
}

/// Issue 30: the verdict's spring checks on a `[design.spring]` part, against the closed
/// forms: force at full compression k (δ_rs + h), Wahl's stress τ = K_W 8 F D / (π d³),
/// solid height d N_t (squared and ground), and the free-length check L_0 − (δ_rs + h) > L_s.
#[test]
fn the_spring_part_is_judged_on_stress_and_solid_height() {
    use camsim::verdict::{spring as spring_verdict, spring_part_warnings};
    let scene = |free: f64, wire: f64| {
        camsim::scene::parse(&format!(
            "[design]\nspring_preload_length_in = 0.5\n[design.spring]\nwire_diameter_in = {wire}\nmean_diameter_in = 1.2\nactive_coils = 6\nmaterial = \"chrome-silicon\"\nfree_length_in = {free}\n"
        ))
        .unwrap()
    };
    let spec = scene(4.0, 0.2);
    let v = spring_verdict(&spec.design, spec.spring.as_ref()).unwrap();
    let h = spec.design.program.max_lift();
    assert_eq!(h, 1.5, "the reference program's lift");
    let k = 11.2e6 * 0.2f64.powi(4) / (8.0 * 1.2f64.powi(3) * 6.0);
    let f = k * (0.5 + h);
    assert!((v.full_compression_force_lb.in_inch() / f - 1.0).abs() < 1e-12);
    let c = 6.0;
    let kw = (4.0 * c - 1.0) / (4.0 * c - 4.0) + 0.615 / c;
    let tau = kw * 8.0 * f * 1.2 / (std::f64::consts::PI * 0.008);
    assert!(
        (v.shear_stress_psi.in_inch() / tau - 1.0).abs() < 1e-12,
        "{}",
        v.shear_stress_psi.in_inch()
    );
    assert!((v.solid_height_in.in_inch() - 0.2 * 8.0).abs() < 1e-12);
    // 4 in free, 2 in of compression: 2.0 in at full lift, above the solid 1.6 in; the
    // stress (about 197 kpsi) is over chrome-silicon's 0.5 * 202 / 0.2^0.108 = 119 kpsi.
    assert_eq!(v.solid(), Some(false));
    let w = spring_part_warnings(&v, camsim::units::Units::Inch);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].starts_with("spring shear stress"), "{w:?}");
    // 3.5 in free: 1.5 in at full lift, below the solid 1.6 in.
    let spec = scene(3.5, 0.2);
    let v = spring_verdict(&spec.design, spec.spring.as_ref()).unwrap();
    assert_eq!(v.solid(), Some(true));
    assert_eq!(
        spring_part_warnings(&v, camsim::units::Units::Inch).len(),
        2
    );
    // A thicker wire at the same coil: k grows as d^4, the stress as K_W F / d^3; with
    // 0.3 in wire (C = 4) the 6-coil spring is solid at 2.4 in, so 5 in free passes that.
    let spec = scene(5.0, 0.3);
    let v = spring_verdict(&spec.design, spec.spring.as_ref()).unwrap();
    assert_eq!(v.solid(), Some(false));
    assert!(
        v.shear_stress_psi.in_inch() > v.allowable_shear_psi.in_inch(),
        "k grows faster than d^3"
    );
    // An assumed spring (the rate alone) is shown, not judged.
    let reference = camsim::sim::RunSpec::reference();
    let v = spring_verdict(&reference.design, None).unwrap();
    assert!(!v.given);
    assert!(spring_part_warnings(&v, camsim::units::Units::Inch).is_empty());
    assert_eq!(v.free_length_in, None);
    assert!((v.least_free_length_in.in_inch() - (1.05 + 2.0)).abs() < 1e-12);
    // Its text says so on the lines that hold the stress and the solid height, and a
    // given part's text does not.
    let text = |v: &camsim::verdict::SpringVerdict| {
        let mut out = String::new();
        camsim::verdict::spring_lines(&mut out, v, camsim::units::Units::Inch);
        out
    };
    let assumed = text(&v);
    let stress = assumed.lines().find(|l| l.contains("(Wahl)")).unwrap();
    assert!(stress.ends_with("(the assumed wire's: not judged; give [design.spring], or camsim design spring for one)"), "{assumed}");
    let solid = assumed
        .lines()
        .find(|l| l.contains("solid height"))
        .unwrap();
    assert!(solid.contains("(the assumed wire's)"), "{assumed}");
    let given = text(&spring_verdict(&spec.design, spec.spring.as_ref()).unwrap());
    assert!(!given.contains("assumed"), "{given}");
}

/// Issue 30: a stiffer speed regulator holds the cam speed closer: on the reference design
/// (800 rpm, 2 revolutions) the measured swing falls as `[design.drive.motor]`'s gain
/// rises through half, once and twice the thesis's (the middle one is the thesis drive, so
/// its swing is the default's).
#[test]
fn a_stiffer_regulator_gives_a_smaller_cam_speed_swing() {
    let camsim_core::DriveLaw::Regulated { k_p, .. } =
        camsim_core::Design::<f64>::reference().drive
    else {
        panic!("the reference drive is regulated");
    };
    let p = scene_file("no-drive", "");
    let default = run_scene(&p).drive.swing_percent;
    std::fs::remove_file(&p).unwrap();
    let swings: Vec<f64> = [0.5, 1.0, 2.0]
        .iter()
        .map(|f| {
            let text = format!(
                "[design.drive.motor]\ngain_lb_in_s_per_rad = {:?}\n",
                f * k_p
            );
            let p = scene_file(&format!("gain-{f}"), &text);
            let v = run_scene(&p);
            std::fs::remove_file(&p).unwrap();
            v.drive.swing_percent
        })
        .collect();
    assert_eq!(swings[1], default, "{swings:?}");
    assert!(
        swings.windows(2).all(|w| w[1] < w[0]) && swings.iter().all(|s| s.is_finite()),
        "{swings:?}"
    );
}

/// `design tolerance --waviness-fpr 17,57`: each row of the table is the single-FPR
/// search's answer (the same cams, seeded, at every FPR), the roller and eccentricity
/// tolerances held as given, and a second FPR is refused where one search is made.
#[test]
fn design_tolerance_table_rows_are_the_single_fpr_answers() {
    use camsim::cmd::design::{mc_search, tolerance_table};
    let args = |fprs: Vec<u32>| camsim::cmd::design::McArgs {
        actual: camsim::args::ActualArgs {
            waviness_fpr: fprs,
            roller_tolerance: Some(0.00005),
            eccentricity_tolerance: Some(0.0),
            ..Default::default()
        },
        p_max: 0.3,
        samples: Some(10),
        ..mc_args(2)
    };
    let table = tolerance_table(&args(vec![17, 57]), camsim::units::Units::Inch).unwrap();
    assert_eq!(table.0.len(), 2);
    for (row, f) in table.0.iter().zip([17u32, 57]) {
        let row = row.answer().unwrap();
        let single = mc_search(&args(vec![f]), false, camsim::units::Units::Inch).unwrap();
        assert_eq!(row.waviness_fpr, Some(f));
        assert_eq!(
            (row.answer, row.failing),
            (single.answer, single.failing),
            "FPR {f}"
        );
        assert_eq!(row.tried, single.tried, "FPR {f}");
        assert_eq!(row.roller_tolerance_in, Some(0.00005.into()));
        assert_eq!(row.eccentricity_tolerance_in, Some(0.0.into()));
        assert_eq!(row.cam_tolerance_in, Some((0.0005 * row.answer).into()));
    }
    let e = mc_search(&args(vec![17, 57]), false, camsim::units::Units::Inch)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--waviness-fpr 17,57") && e.contains("list"),
        "{e}"
    );
}

/// Issue 30: "JSON arrays name their unit in their key". `design tolerance`'s values
/// tried are factors on VI.1's tolerances, with --waviness waviness FPRs: each report's
/// array is under the key that says so, and no bare `tried` is left; the FPRs are whole
/// numbers and the factors the search's doubling from 0.1.
#[test]
fn design_tolerances_tried_values_name_their_unit() {
    use camsim::cmd::design::What;
    use camsim::report::Report;
    let json = |extra: &[&str]| {
        let mut argv = vec!["camsim", "design", "tolerance", "--quick", "--threads", "1"];
        argv.extend_from_slice(extra);
        let camsim::cli::Command::Design(a) = camsim::cli::parse_from(argv).unwrap().command else {
            panic!("not design")
        };
        let What::Tolerance(t) = a.what else {
            panic!("not tolerance")
        };
        let text = camsim::cmd::design::tolerance_table(&t, camsim::units::Units::Inch)
            .unwrap()
            .json()
            .unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()
    };
    let wavy = json(&["--waviness"]);
    let rows = wavy.as_array().unwrap();
    assert_eq!(rows.len(), 1);
    assert!(rows[0].get("tried").is_none());
    let fprs = rows[0]["waviness_fprs_tried"].as_array().unwrap();
    assert!(!fprs.is_empty());
    for f in fprs {
        let x = f[0].as_f64().unwrap();
        assert_eq!(x, x.round(), "{f}");
    }
    let tol = json(&["--waviness-fpr", "17"]);
    for row in tol.as_array().unwrap() {
        assert!(row.get("tried").is_none());
        let factors = row["tolerance_factors_tried"].as_array().unwrap();
        assert_eq!(factors[0][0].as_f64().unwrap(), 0.1, "{row}");
        assert_eq!(factors[1][0].as_f64().unwrap(), 0.2, "{row}");
    }
}

/// Issue 30's re-run: `design spring`'s "as a scene" lines are TOML a designer pastes in
/// place of the spring rate: pasted under the reference scene they read back as that
/// part (its rate the answer's part's, from the Shigley closed form the scene computes).
/// The headline's rate is that part's own, the search's least rate beside it.
#[test]
fn design_springs_scene_lines_paste_into_a_scene() {
    use camsim::report::Report;
    let r = spring(&spring_args(false, 1), camsim::units::Units::Inch).unwrap();
    let part = r.part.as_ref().unwrap();
    let text = r.text(camsim::units::Units::Inch);
    let lines: String = text
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("as a scene"))
        .skip(1)
        .take_while(|l| l.starts_with("      "))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(lines.trim_start().starts_with("[design.spring]"), "{text}");
    let head = text.lines().next().unwrap();
    let want = format!(
        "camsim design spring: {:.1} lb/in at preload length",
        part.spring.rate_lb_per_in.in_inch()
    );
    let found = format!(
        "; the least rate the search found: {:.1} lb/in",
        r.spring_rate_lb_per_in.in_inch()
    );
    assert!(head.starts_with(&want) && head.ends_with(&found), "{head}");
    assert!(
        text.contains(&format!(
            "; rate {:.1} lb/in,",
            part.spring.rate_lb_per_in.in_inch()
        )),
        "{text}"
    );
    let spec = camsim::scene::parse(&lines).unwrap();
    let rate = spec.design.k_rs;
    let read = spec.spring.as_ref().unwrap().coil;
    // The diameters are printed to 6 significant digits (relative error at most 5e-6
    // each), so the part read back is the part printed: each diameter within 5e-6 and
    // the rate (d^4/D^3) within 4*5e-6 + 3*5e-6 = 3.5e-5.
    for (got, want) in [
        (read.wire_diameter, part.spring.wire_diameter_in.in_inch()),
        (read.mean_diameter, part.spring.mean_diameter_in.in_inch()),
    ] {
        assert!((got / want - 1.0).abs() <= 5e-6, "{got} {want}");
    }
    assert!(
        (rate / part.spring.rate_lb_per_in.in_inch() - 1.0).abs() < 3.5e-5,
        "{rate} {:?}",
        part.spring
    );
}
