//! The scene schema: core's `Design` and `SolverSettings` as serde reads and writes them.
//! The written reference reads back bit for bit, the core's key table and the serialized
//! keys are the same set, every key refuses a bad value under its own name, and a
//! non-self-describing format (postcard, as the firmware would use) round-trips too.

use camsim::scene::parse;
use camsim::sim::RunSpec;
use camsim_core::{
    key, CamProgram, Design, DriveLaw, MotionLaw, ProgramData, SegmentData, SegmentType,
    SolverSettings,
};

fn err(text: &str) -> String {
    format!("{:#}", parse(text).unwrap_err())
}

/// A design as postcard bytes: every number as its raw little-endian bits, the drive's
/// and the segments' tags, in field order; equal bytes mean f64-identical designs.
fn bits(d: &Design<f64>) -> Vec<u8> {
    postcard::to_allocvec(d).unwrap()
}

#[test]
fn the_default_scene_reads_back_to_the_reference_bit_for_bit() {
    let text = camsim::scene::default_text().unwrap();
    let spec = parse(&text).unwrap();
    let r = RunSpec::reference();
    assert_eq!(bits(&spec.design), bits(&r.design));
    assert_eq!(spec.design, r.design);
    assert_eq!(spec.solver.rtol.to_bits(), r.solver.rtol.to_bits());
    assert_eq!(spec.solver.atol.to_bits(), r.solver.atol.to_bits());
    assert_eq!(
        spec.solver.max_step_fraction.to_bits(),
        r.solver.max_step_fraction.to_bits()
    );
    assert_eq!(spec.solver, r.solver);
    assert_eq!((spec.revolutions, spec.dofs), (r.revolutions, r.dofs));
    // An empty file is the reference run too (the scene-file crate's own defaults).
    let empty = parse("").unwrap();
    assert_eq!(bits(&empty.design), bits(&r.design));
    assert_eq!((empty.revolutions, empty.dofs), (r.revolutions, r.dofs));
    // The check command's output is the same text (without the header comment).
    assert!(text.ends_with(&camsim::scene::spec_text(&spec).unwrap()));
}

#[test]
fn the_stable_scene_is_the_reference_with_its_laws_swapped() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/stable-4567-rise.toml"
    );
    let spec = camsim::scene::load(std::path::Path::new(path)).unwrap();
    let mut want = Design::<f64>::reference();
    want.program = CamProgram::with_laws(MotionLaw::Poly4567, MotionLaw::ModifiedTrapezoidal);
    assert_eq!(bits(&spec.design), bits(&want));
    assert_eq!(spec.solver, SolverSettings::reference());
}

/// The shipped variants of the reference: VI.1's listed spring (with its mass) and the
/// printed model without damping at the roller differ from the reference in those keys
/// only.
#[test]
fn the_shipped_variants_are_the_reference_with_their_keys() {
    let load = |name: &str| {
        let path = format!("{}/../scenes/{name}", env!("CARGO_MANIFEST_DIR"));
        camsim::scene::load(std::path::Path::new(&path)).unwrap()
    };
    let spec = load("listed-spring-60.toml");
    let mut want = Design::<f64>::reference();
    want.k_rs = camsim_core::LISTED_SPRING_RATE;
    want.m_spring = camsim_core::LISTED_SPRING_MASS;
    // The modal analysis's rate follows the rate the file gives (issue 30).
    want.k_rs_modal = camsim_core::LISTED_SPRING_RATE;
    assert_eq!(bits(&spec.design), bits(&want));
    // The mass follows the rate by the wire model, as `--spring-rate 60` makes it.
    assert_eq!(
        spec.design.m_spring,
        camsim_core::HelicalSpring::of_rate(60.0).unwrap().mass
    );
    let flag = camsim::cmd::run::spec_from(&camsim::cmd::run::SceneArgs {
        spring_rate: Some(60.0),
        ..Default::default()
    })
    .unwrap();
    assert_eq!(bits(&flag.design), bits(&spec.design));
    assert_eq!(spec.solver, SolverSettings::reference());

    let spec = load("undamped-printed.toml");
    let mut want = Design::<f64>::reference();
    want.contact_damping_ratio = 0.0;
    want.roller_bearing_damping_ratio = 0.0;
    assert_eq!(bits(&spec.design), bits(&want));
    assert_eq!(spec.solver, SolverSettings::reference());
}

/// The value at a dotted path of a TOML table.
fn at<'a>(t: &'a toml::Table, path: &str) -> Option<&'a toml::Value> {
    let mut parts = path.split('.');
    let mut v = t.get(parts.next()?)?;
    for p in parts {
        v = v.as_table()?.get(p)?;
    }
    Some(v)
}

/// Every scalar leaf of `t` as a dotted path (arrays of tables left out).
fn leaves(t: &toml::Table, prefix: &str, out: &mut Vec<String>) {
    for (k, v) in t {
        let p = if prefix.is_empty() {
            k.clone()
        } else {
            format!("{prefix}.{k}")
        };
        match v {
            toml::Value::Table(t) => leaves(t, &p, out),
            toml::Value::Array(_) => {}
            _ => out.push(p),
        }
    }
}

#[test]
fn the_key_table_and_the_serialized_keys_are_the_same_set() {
    let d: toml::Table = toml::Table::try_from(Design::<f64>::reference()).unwrap();
    let mut serialized = Vec::new();
    leaves(&d, "", &mut serialized);
    let mut table: Vec<String> = key::DESIGN_KEYS
        .iter()
        .map(|(k, _)| k.to_string())
        .collect();
    serialized.sort();
    table.sort();
    assert_eq!(serialized, table);
    for (k, doc) in key::DESIGN_KEYS {
        assert!(at(&d, k).is_some_and(|v| v.as_float().is_some()), "{k}");
        assert!(!doc.is_empty());
    }
    // The program's segments carry exactly the segment keys.
    let segs = at(&d, key::PROGRAM_SEGMENT).unwrap().as_array().unwrap();
    let rise = segs[1].as_table().unwrap();
    let mut seg_keys: Vec<&str> = rise.keys().map(String::as_str).collect();
    let mut want = key::SEGMENT_KEYS.to_vec();
    seg_keys.sort_unstable();
    want.sort_unstable();
    assert_eq!(seg_keys, want);
    // Solver keys.
    let s: toml::Table = toml::Table::try_from(SolverSettings::<f64>::reference()).unwrap();
    let mut solver: Vec<&str> = s.keys().map(String::as_str).collect();
    let mut want = key::SOLVER_KEYS.to_vec();
    solver.sort_unstable();
    want.sort_unstable();
    assert_eq!(solver, want);
}

/// A scene setting the design key `k` (a path under `[design]`) to `v`.
fn design_scene(k: &str, v: &str) -> String {
    match k.rsplit_once('.') {
        Some((table, leaf)) => format!("[design.{table}]\n{leaf} = {v}\n"),
        None => format!("[design]\n{k} = {v}\n"),
    }
}

#[test]
fn every_design_key_refuses_nan_infinity_and_negatives_under_its_own_name() {
    for (k, _) in key::DESIGN_KEYS {
        for (v, shown) in [
            ("nan", "NaN"),
            ("inf", "inf"),
            ("-inf", "-inf"),
            ("-1.0", "-1"),
        ] {
            // A negative feed-forward torque is allowed (a drive that brakes).
            if *k == key::DRIVE_T_STEADY && v == "-1.0" {
                continue;
            }
            let e = err(&design_scene(k, v));
            let want = format!("line 2: design.{k} = {shown}: must ");
            assert!(e.contains(&want), "{k} = {v}: got {e:?}, want {want:?}");
            assert!(!e.contains('\n'));
        }
        // The reference value itself, written explicitly, is accepted.
        let d: toml::Table = toml::Table::try_from(Design::<f64>::reference()).unwrap();
        let v = at(&d, k).unwrap().to_string();
        assert!(parse(&design_scene(k, &v)).is_ok(), "{k} = {v}");
    }
}

/// Every numeric key has a plausibility range: the design's, the solver's (not `start`, `step_control`, `method`)
/// and the speed in rpm; the reference design, the solver's reference settings and the
/// chip's lie inside; every bound is an `f32` number that keeps its sign.
#[test]
fn every_numeric_key_has_a_range_and_the_references_lie_inside() {
    let mut want: Vec<&str> = key::DESIGN_KEYS.iter().map(|(k, _)| *k).collect();
    want.extend(
        key::SOLVER_KEYS
            .iter()
            .filter(|k| ![key::START, key::STEP_CONTROL, key::METHOD].contains(*k)),
    );
    want.push(key::RPM);
    let mut have: Vec<&str> = key::RANGES.iter().map(|(k, _)| *k).collect();
    want.sort_unstable();
    have.sort_unstable();
    assert_eq!(have, want);
    for (k, r) in key::RANGES {
        assert!(
            r.min <= r.max && r.min.is_finite() && r.max.is_finite(),
            "{k}"
        );
        assert_eq!(r.min == 0.0, r.min as f32 == 0.0, "{k}");
        assert!((r.max as f32).is_finite(), "{k}");
        assert!(r.rule.starts_with("must "), "{k}");
        assert_eq!(key::range(k), Some(*r));
    }
    let d: toml::Table = toml::Table::try_from(Design::<f64>::reference()).unwrap();
    for (k, _) in key::DESIGN_KEYS {
        let v = at(&d, k).unwrap().as_float().unwrap();
        assert!(key::range(k).unwrap().contains(v), "{k} = {v}");
    }
    for s in [
        SolverSettings::<f64>::reference(),
        camsim_chip::chip_solver_settings(),
    ] {
        for (k, v) in [
            (key::RTOL, s.rtol),
            (key::ATOL, s.atol),
            (key::MAX_STEP_FRACTION, s.max_step_fraction),
            (key::MAX_STEPS_PER_REV, f64::from(s.max_steps_per_rev)),
        ] {
            assert!(key::range(k).unwrap().contains(v), "{k} = {v}");
        }
    }
    for rpm in camsim_chip::CHIP_GRID_RPM {
        assert!(key::SPEED_RPM.contains(rpm));
    }
}

/// Just outside its range, every key is refused under its own name with its range's rule,
/// from a scene file (the line, the key, the value) and, for the speed, from `run.rpm`.
#[test]
fn every_key_is_refused_just_outside_its_range_under_its_own_name() {
    for (k, r) in key::RANGES {
        let mut outside = vec![r.max * (1.0 + 1e-9)];
        if r.min > 0.0 {
            outside.push(r.min * (1.0 - 1e-9));
        }
        for v in outside {
            let (text, name) = if *k == key::RPM {
                (format!("[run]\nrpm = {v:?}\n"), "run.rpm".to_string())
            } else if key::SOLVER_KEYS.contains(k) {
                // A count: the whole number just outside.
                let v = if *k == key::MAX_STEPS_PER_REV {
                    let n = if v > r.max { r.max + 1.0 } else { r.min - 1.0 };
                    format!("{}", n as u64)
                } else {
                    format!("{v:?}")
                };
                (format!("[solver]\n{k} = {v}\n"), format!("solver.{k}"))
            } else {
                (design_scene(k, &format!("{v:?}")), format!("design.{k}"))
            };
            // A drive key needs the regulated drive, which the reference has.
            let e = err(&text);
            assert!(
                e.starts_with(&format!("line 2: {name} = ")) && e.ends_with(r.rule),
                "{text:?}: {e}"
            );
        }
    }
    // Inside by a hair at the ends a range may be met exactly (a bound is a value).
    assert!(parse("[design]\nfriction_coefficient = 1.0\n").is_ok());
    assert!(parse("[design]\nfriction_coefficient = 0.0\n").is_ok());
    assert!(parse("[run]\nrpm = 10000\n").is_ok());
}

#[test]
fn refusals_name_the_key_and_the_rule() {
    let seg = |kind: &str, law: Option<&str>, a: f64, b: f64, lift: f64| {
        format!(
            "[[design.program.segment]]\nkind = \"{kind}\"\n{}start_deg = {a:?}\nend_deg = {b:?}\nlift_in = {lift:?}\n",
            law.map(|l| format!("law = \"{l}\"\n")).unwrap_or_default()
        )
    };
    let cases = [
        // Unknown keys, at every level.
        ("kam = 1\n".to_string(), "line 1, column 1: kam: unknown field `kam`"),
        (
            "[design.geometry]\nradius_in = 1\n".into(),
            "line 2, column 1: design.geometry.radius_in: unknown field `radius_in`",
        ),
        (
            "[design.drive.regulated]\nk_i = 1\n".into(),
            "line 2, column 1: design.drive.regulated.k_i: unexpected keys in table: k_i",
        ),
        (
            seg("dwell", None, 0.0, 360.0, 0.0) + "colour = 'red'\n",
            "line 6, column 1: design.program.segment[0].colour: unknown field `colour`",
        ),
        // Negative mass and stiffness.
        (
            "[design]\nroller_mass_lb_s2_per_in = -0.001\n".into(),
            "line 2: design.roller_mass_lb_s2_per_in = -0.001: must be positive and finite",
        ),
        (
            "[design]\nk_vs_lb_per_in = -1e6\n".into(),
            "line 2: design.k_vs_lb_per_in = -1000000: must be positive and finite",
        ),
        // NaN and infinity in the solver.
        (
            "[solver]\natol_in = nan\n".into(),
            "line 2: solver.atol_in = NaN: must be positive and finite",
        ),
        (
            "[solver]\nrtol = inf\n".into(),
            "line 2: solver.rtol = inf: must be positive and finite",
        ),
        // A program that does not close over 360 degrees (levels and angles).
        (
            seg("dwell", None, 0.0, 90.0, 0.0)
                + &seg("rise", Some("cycloidal"), 90.0, 180.0, 1.0)
                + &seg("dwell", None, 180.0, 360.0, 0.0),
            "line 1: design.program.segment = 1: net displacement over the revolution must be 0",
        ),
        (
            seg("dwell", None, 0.0, 90.0, 0.0) + &seg("dwell", None, 90.0, 300.0, 0.0),
            "line 9: design.program.segment[1].end_deg = 300: must be 360",
        ),
        (
            seg("dwell", None, 0.0, 90.0, 0.0) + &seg("dwell", None, 100.0, 360.0, 0.0),
            "line 4: design.program.segment[0].end_deg = 90: must equal the next segment's start_deg",
        ),
        // A bad motion law, a missing one, one on a dwell.
        (
            seg("rise", Some("sine"), 0.0, 360.0, 1.0),
            "line 3, column 7: design.program.segment[0].law: unknown variant `sine`, expected one of `straight-line`",
        ),
        (
            seg("dwell", None, 0.0, 180.0, 0.0) + &seg("rise", None, 180.0, 360.0, 1.0),
            "line 6: design.program.segment[1].law: a rise or return needs a motion law",
        ),
        (
            seg("dwell", Some("cycloidal"), 0.0, 360.0, 0.0),
            "line 3: design.program.segment[0].law: a dwell takes no motion law",
        ),
        (
            seg("dwell", None, 0.0, 360.0, 0.5),
            "line 5: design.program.segment[0].lift_in = 0.5: must be 0 for a dwell",
        ),
        // A bad drive law, as a name and as a table.
        (
            "[design]\ndrive = \"turbo\"\n".into(),
            "line 2, column 9: design.drive: unknown variant `turbo`, expected one of `constant-cam-speed`, `constant-speed`, `constant-motor-speed`, `regulated`; or `thesis`, or a [design.drive.motor] table",
        ),
        (
            "[design.drive.pid]\nk_p = 1\n".into(),
            "design.drive.pid: unknown variant `pid`",
        ),
        (
            "[design.drive.regulated]\nt_max_lb_in = 0\n".into(),
            "line 2: design.drive.regulated.t_max_lb_in = 0: must be positive and finite",
        ),
        // Undercut.
        // (30-degree cycloidal rise and return of 1.5 in on a 0.1 in base circle).
        (
            "[design.geometry]\nbase_radius_in = 0.1\nroller_radius_in = 0.6\n".to_string()
                + &seg("dwell", None, 0.0, 30.0, 0.0)
                + &seg("rise", Some("cycloidal"), 30.0, 60.0, 1.5)
                + &seg("dwell", None, 60.0, 210.0, 0.0)
                + &seg("return", Some("cycloidal"), 210.0, 240.0, 1.5)
                + &seg("dwell", None, 240.0, 360.0, 0.0),
            "line 3: design.geometry.roller_radius_in = 0.6: undercut",
        ),
        // Run options.
        (
            "[run]\nrpm = -800\n".into(),
            "line 2: run.rpm = -800: must be positive and finite",
        ),
        (
            "[run]\nrpm = 900\n[design.drive.regulated]\nomega_ref_rad_per_s = 90\n".into(),
            "run.rpm and design.drive.regulated.omega_ref_rad_per_s both set the cam speed",
        ),
    ];
    for (text, want) in &cases {
        let e = err(text);
        assert!(e.contains(want), "{text:?}:\n got {e:?}\nwant {want:?}");
        assert!(!e.contains('\n'), "one line: {e:?}");
    }
}

#[test]
fn run_rpm_moves_the_design_like_the_rpm_flag() {
    let spec = parse("[run]\nrpm = 1000\n").unwrap();
    let mut want = Design::<f64>::reference();
    want.set_speed_rpm(1000.0).unwrap();
    assert_eq!(bits(&spec.design), bits(&want));
    assert_eq!(spec.design.omega0, 1000.0 * std::f64::consts::PI / 30.0);
    // Written back, the speed is the design's (no run.rpm): one source of truth.
    let text = camsim::scene::spec_text(&spec).unwrap();
    assert!(!text.contains("rpm ="));
    assert_eq!(bits(&parse(&text).unwrap().design), bits(&want));
}

#[test]
fn motion_laws_are_named_as_in_camsim_laws() {
    for law in MotionLaw::ALL {
        let s = serde_json::to_string(&law).unwrap();
        assert_eq!(s, format!("\"{}\"", law.name()));
        assert_eq!(serde_json::from_str::<MotionLaw>(&s).unwrap(), law);
    }
}

#[test]
fn postcard_round_trips_the_design_and_refuses_a_bad_program() {
    // f64 and f32 (the firmware's precision), a changed drive and program too.
    let d64 = Design::<f64>::reference();
    let bytes = postcard::to_allocvec(&d64).unwrap();
    assert_eq!(postcard::from_bytes::<Design<f64>>(&bytes).unwrap(), d64);
    let d32 = Design::<f32>::reference();
    let bytes32 = postcard::to_allocvec(&d32).unwrap();
    assert_eq!(postcard::from_bytes::<Design<f32>>(&bytes32).unwrap(), d32);
    // 41 scalars of 4 bytes, 4 drive values, 4 segments of 3 numbers, a few tags.
    assert!(
        bytes32.len() < 41 * 4 + 4 * 4 + 4 * 3 * 4 + 32,
        "{}",
        bytes32.len()
    );
    let mut other = Design::<f32>::reference();
    other.drive = DriveLaw::ConstantCamSpeed;
    other.program = CamProgram::with_laws(MotionLaw::Cycloidal, MotionLaw::Poly345);
    let b = postcard::to_allocvec(&other).unwrap();
    assert_eq!(postcard::from_bytes::<Design<f32>>(&b).unwrap(), other);
    let s = SolverSettings::<f32>::reference();
    let b = postcard::to_allocvec(&s).unwrap();
    assert_eq!(postcard::from_bytes::<SolverSettings<f32>>(&b).unwrap(), s);
    // A program that does not close is refused as it is read.
    let mut open: ProgramData<f32> = CamProgram::<f32>::reference().into();
    open.segment[3] = SegmentData {
        kind: SegmentType::Return,
        law: Some(MotionLaw::Poly4567),
        start_deg: 210.0,
        end_deg: 360.0,
        lift: 1.0,
    };
    let b = postcard::to_allocvec(&open).unwrap();
    assert!(postcard::from_bytes::<CamProgram<f32>>(&b).is_err());
}

/// A segment that does end after its start, but by less than the angle tolerance, is told
/// so: not "must exceed the segment's start_deg" as if it did not.
#[test]
fn a_sliver_of_a_segment_is_refused_by_the_tolerance_it_misses() {
    let text = "[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 0\nend_deg = 30\n\
        [[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 30\nend_deg = 30.0000001\n\
        [[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 30.0000001\nend_deg = 360\n";
    assert_eq!(
        err(text),
        "line 8: design.program.segment[1].end_deg = 30.0000001: must exceed the segment's start_deg by more than the angle tolerance (1e-6 deg; 3.4e-4 deg in f32)"
    );
}

/// Issue 30: `drive = "thesis"` names the drive a scene without one gets: bit for bit.
#[test]
fn the_thesis_drive_by_name_is_the_default_bit_for_bit() {
    let named = parse("[design]\ndrive = \"thesis\"\n").unwrap();
    let none = parse("").unwrap();
    assert_eq!(bits(&named.design), bits(&none.design));
    assert_eq!(bits(&named.design), bits(&RunSpec::reference().design));
}

/// Issue 30: a `[design.drive.motor]` with the thesis's rotor inertia, shaft stiffness,
/// gain and torque limit (given in SI, converted back) is the thesis drive; each key sets
/// its design value and no other; a key not given keeps the thesis's value.
#[test]
fn a_motor_with_the_thesis_values_is_the_thesis_drive() {
    let r = RunSpec::reference().design;
    let DriveLaw::Regulated { k_p, t_max, .. } = r.drive else {
        panic!("the reference drive is regulated");
    };
    let nm = 4.448_221_615_260_5 * 0.0254; // N m per lb in
    let text = format!(
        "[design.drive.motor]\ninertia_kg_m2 = {:?}\nshaft_stiffness_n_m_per_rad = {:?}\ngain_n_m_s_per_rad = {:?}\ntorque_limit_n_m = {:?}\n",
        r.i_m * nm,
        r.k_s1 * nm,
        k_p * nm,
        t_max * nm
    );
    let d = parse(&text).unwrap().design;
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-14;
    assert!(close(d.i_m, r.i_m) && close(d.k_s1, r.k_s1), "{d:?}");
    let DriveLaw::Regulated {
        k_p: k2,
        t_max: t2,
        omega_ref,
        t_steady,
    } = d.drive
    else {
        panic!("a motor drive is regulated");
    };
    assert!(close(k2, k_p) && close(t2, t_max));
    // In the inch family, the very numbers: bit for bit.
    let text = format!(
        "[design.drive.motor]\ninertia_lb_in_s2 = {:?}\nshaft_stiffness_lb_in_per_rad = {:?}\ngain_lb_in_s_per_rad = {:?}\ntorque_limit_lb_in = {:?}\n",
        r.i_m, r.k_s1, k_p, t_max
    );
    assert_eq!(bits(&parse(&text).unwrap().design), bits(&r));
    // One key: only its value moves.
    let d = parse("[design.drive.motor]\ngain_lb_in_s_per_rad = 82\n")
        .unwrap()
        .design;
    assert_eq!((d.i_m, d.k_s1), (r.i_m, r.k_s1));
    let DriveLaw::Regulated {
        k_p: k3,
        t_max: t3,
        omega_ref: o3,
        t_steady: s3,
    } = d.drive
    else {
        panic!("a motor drive is regulated");
    };
    assert_eq!((k3, t3, o3, s3), (82.0, t_max, omega_ref, t_steady));
}

/// Issue 30: a motor key's refusal quotes the key and value as written and the rule.
#[test]
fn a_bad_motor_key_is_refused_by_name() {
    let cases = [
        (
            "[design.drive.motor]\ngain_n_m_s_per_rad = -3\n",
            "line 2: design.drive.motor.gain_n_m_s_per_rad = -3: must be positive and finite",
        ),
        (
            "[design.drive.motor]\ninertia_kg_m2 = 0\n",
            "line 2: design.drive.motor.inertia_kg_m2 = 0: must be positive and finite",
        ),
        (
            "[design.drive.motor]\nhorsepower = 2\n",
            "design.drive.motor.horsepower: unknown key",
        ),
        (
            "[design]\ni_m_lb_in_s2 = 0.03\n[design.drive.motor]\ninertia_lb_in_s2 = 0.03\n",
            "design.drive.motor.inertia_lb_in_s2 and design.i_m_lb_in_s2",
        ),
    ];
    for (text, want) in cases {
        let e = err(text);
        assert!(e.contains(want), "{text:?}: {e}");
    }
}
