//! The firmware's predictor on the host (`camsim predict`): its f32 run (bit-identical to
//! the chip's, checked in scripts/firmware-ci.sh) against the f64 run of the same scene,
//! the alarm over the scripted machine's readings, and the parity-line checker.
//!
//! Tolerances f32 vs f64 (both runs take their own adaptive steps, so they differ by the
//! solver's error, not by rounding alone):
//! - contact force: the contact deflection y1 - q2 is controlled to atol = 1e-8 in per
//!   double step; times the Hertz stiffness K_h ≈ 6.45e6 lb/in that is 0.065 lb per step
//!   for each run; allow three of them: 0.19 lb.
//! - jump onset: two bisection resolutions (1 rpm each) plus the force tolerance over
//!   the slope of the smallest contact force between the last two grid speeds below the
//!   jump (the onset moves by that much if the force curve shifts by 0.19 lb).
//! - timing errors (runs without a jump): the load position is resolved to 3 atol in
//!   (0.03 µin) over the slope dy/dθ at the crossing, plus the f32 cam angle's resolution
//!   in the second revolution (θ < 4π: ulp 9.5e-7 rad = 5.5e-5 deg) four times: 2.5e-4 deg.
//!   Rows that jumped are excluded: after a separation the follower's timing depends on
//!   the impact history (chaotic under a change of step sequence).

use camsim::cmd::predict::{
    check_parity, compute, parity_lines, render_text, Num, PredictReport, Prediction,
    REFERENCE_SCENE,
};
use camsim::units::Units;
use camsim_chip::{
    CHIP_ALARM_OFF_MARGIN_RPM, CHIP_ALARM_ON_MARGIN_RPM, CHIP_GRID_RPM, CHIP_MAX_RPM,
    CHIP_RESOLUTION_RPM, CHIP_TICK_HZ,
};

const FORCE_TOL_LB: f64 = 3.0 * 1e-8 * 6.45e6;

/// How far the chip's f32 timing may be from the host's f64: the accuracy the chip's
/// scene and tolerance were chosen for (`camsim models`: timing at the lift points within
/// 0.01° of the full model). At rtol 1e-2 one step's allowed error is atol + rtol |q5|
/// (q5 = y5 - s, up to the chain's 4e-4 in deflection under 200 lb), 0.03° on the
/// flattest timing point's 0.05 in/rad; f32 and f64 take different steps, so their
/// difference is the solvers' global errors' (seen: 3.8e-3°), bounded by the accuracy
/// asked of both.
fn timing_tol_deg() -> f64 {
    let d = camsim_core::Design::<f64>::reference();
    let pts = camsim_core::timing_points(&d.program);
    let slope = pts
        .iter()
        .map(|p| d.program.follower(p.theory_deg.to_radians()).dy.abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        slope > 0.05,
        "timing points sit on the flanks: slope {slope}"
    );
    camsim::cmd::models::enough::TIMING_DEG
}

fn both() -> (Prediction<f32>, Prediction<f64>) {
    (
        compute::<f32>(None, None).unwrap(),
        compute::<f64>(None, None).unwrap(),
    )
}

#[test]
fn f32_and_f64_agree_within_the_chips_accuracy() {
    let (p32, p64) = both();
    let ttol = timing_tol_deg();
    assert_eq!(ttol, 0.01);
    let mut worst_f = 0.0f64;
    let mut worst_t = 0.0f64;
    for (a, b) in p32.table.at.iter().zip(p64.table.at.iter()) {
        assert_eq!(a.jumped, b.jumped, "jump flag differs on the grid");
        let df = (a.min_contact_force as f64 - b.min_contact_force).abs();
        worst_f = worst_f.max(df);
        assert!(df <= FORCE_TOL_LB, "min contact force differs by {df} lb");
        if !a.jumped {
            for (x, y) in a.timing_deg.iter().zip(b.timing_deg.iter()) {
                let dt = (*x as f64 - y).abs();
                worst_t = worst_t.max(dt);
                assert!(dt <= ttol, "timing differs by {dt} deg (tolerance {ttol})");
            }
        }
    }
    for (a, b) in p32.checks.iter().zip(p64.checks.iter()) {
        let df = (a.direct.min_contact_force as f64 - b.direct.min_contact_force).abs();
        worst_f = worst_f.max(df);
        assert!(
            df <= FORCE_TOL_LB,
            "direct run at {} rpm: force differs by {df} lb",
            b.rpm
        );
    }
    // Jump onset: slope of the force curve between the last two grid speeds with contact.
    let held: Vec<usize> = (0..CHIP_GRID_RPM.len())
        .filter(|&i| !p64.table.at[i].jumped)
        .collect();
    let (i, j) = (held[held.len() - 2], held[held.len() - 1]);
    let slope = (p64.table.at[i].min_contact_force - p64.table.at[j].min_contact_force).abs()
        / (CHIP_GRID_RPM[j] - CHIP_GRID_RPM[i]);
    assert!(slope > 0.0);
    let jtol = 2.0 * CHIP_RESOLUTION_RPM + FORCE_TOL_LB / slope;
    let (j32, j64) = (
        p32.table.jump_rpm.unwrap() as f64,
        p64.table.jump_rpm.unwrap(),
    );
    assert!(
        (j32 - j64).abs() <= jtol,
        "jump onset {j32} (f32) vs {j64} (f64), tolerance {jtol}"
    );
    // The jump lies between the grid's last contact and first jump, or above the grid's
    // last speed (and within the search's limit) when no grid speed jumps.
    let above = CHIP_GRID_RPM.get(j + 1).copied().unwrap_or(CHIP_MAX_RPM);
    assert!(j64 > CHIP_GRID_RPM[j] && j64 <= above, "jump onset {j64}");
    eprintln!("f32 vs f64: worst force {worst_f:.4} lb (tol {FORCE_TOL_LB}), worst timing {worst_t:.2e} deg (tol {ttol:.2e}), jump {j32} vs {j64} (tol {jtol:.2})");
}

#[test]
fn alarm_follows_the_hysteresis_over_the_scripted_machine() {
    let (p32, p64) = both();
    for (name, seq) in [
        (
            "f32",
            p32.samples
                .iter()
                .map(|s| {
                    (
                        s.prediction
                            .map(|q| (q.rpm as f64, q.speed_margin_rpm as f64)),
                        s.alarm,
                    )
                })
                .collect::<Vec<_>>(),
        ),
        (
            "f64",
            p64.samples
                .iter()
                .map(|s| (s.prediction.map(|q| (q.rpm, q.speed_margin_rpm)), s.alarm))
                .collect(),
        ),
    ] {
        // The alarm starts asserted; a reading without a vouched speed asserts it; a
        // vouched one applies the hysteresis to its margin.
        let mut prev = true;
        let (mut on_at, mut off_at) = (None, None);
        for (k, (vouched, on)) in seq.iter().enumerate() {
            let expect = match vouched {
                None => true,
                Some((_, m)) if *m <= CHIP_ALARM_ON_MARGIN_RPM => true,
                Some((_, m)) if *m > CHIP_ALARM_OFF_MARGIN_RPM => false,
                Some(_) => prev,
            };
            assert_eq!(*on, expect, "{name}: reading {k} {vouched:?}");
            if let Some((rpm, _)) = vouched {
                // A vouched speed is the scripted one (a multiple of 25 rpm) to within
                // one tick of its period: n^2 / (60 f), plus the division's rounding.
                let n = (rpm / 25.0).round() * 25.0;
                let tick = n * n / (60.0 * f64::from(CHIP_TICK_HZ));
                assert!((rpm - n).abs() <= tick, "{name}: {rpm} rpm");
                if *on && !prev && on_at.is_none() {
                    on_at = Some(*rpm);
                } else if !*on && prev && on_at.is_some() && off_at.is_none() {
                    off_at = Some(*rpm);
                }
            }
            prev = *on;
        }
        // The machine crosses the jump once up and once down: a vouched margin turns the
        // alarm on once, and the hysteresis band releases it at a lower speed.
        let (on_at, off_at) = (on_at.unwrap(), off_at.unwrap());
        assert!(
            off_at < on_at,
            "{name}: off at {off_at} rpm, on at {on_at} rpm"
        );
    }
}

#[test]
fn parity_checker_accepts_its_own_lines_and_names_a_flipped_bit() {
    let p = compute::<f32>(None, None).unwrap();
    let lines = parity_lines(&p);
    // Table rows, the jump line, the interpolation checks, every reading of the
    // scripted machine (60: camsim-chip's tests count them).
    assert_eq!(p.samples.len(), 60);
    assert_eq!(
        lines.len(),
        CHIP_GRID_RPM.len() + 1 + camsim_chip::CHIP_CHECK_RPM.len() + p.samples.len()
    );
    let log: String = lines
        .iter()
        .map(|l| format!("INFO  {l}\n└─ src/bin/predictor.rs:1\n"))
        .collect();
    assert_eq!(check_parity(&log, &lines).unwrap(), lines.len());
    // Flip the last bit of the first vouched sample's force.
    let k = lines
        .iter()
        .position(|l| l.starts_with("parity sample i="))
        .unwrap();
    let first = p.samples.iter().find_map(|s| s.prediction).unwrap();
    let mut bad = lines.clone();
    let bits = f32::to_bits(first.force_margin_lb);
    bad[k] = bad[k].replace(
        &format!("force={bits:#010x}"),
        &format!("force={:#010x}", bits ^ 1),
    );
    assert_ne!(bad[k], lines[k]);
    let log: String = bad.iter().map(|l| format!("{l}\n")).collect();
    let e = check_parity(&log, &lines).unwrap_err().to_string();
    assert!(e.contains(&format!("parity line {}", k + 1)), "{e}");
    assert!(check_parity("", &lines).is_err());
}

#[test]
fn interpolation_is_exact_on_the_grid() {
    let p = compute::<f64>(None, None).unwrap();
    for (r, s) in p.table.rpm.iter().zip(p.table.at.iter()) {
        let q = p.table.predict(*r);
        assert!(q.in_grid);
        assert_eq!(q.force_margin_lb, s.min_contact_force);
        assert_eq!(q.speed_margin_rpm, p.table.jump_rpm.unwrap() - r);
    }
}

#[test]
fn report_names_its_scene_and_feeds_text_and_json() {
    let p = compute::<f32>(None, None).unwrap();
    for design in [REFERENCE_SCENE, "scenes/stable-4567-rise.toml"] {
        let r = PredictReport::of(&p, true, design, None);
        let v = serde_json::to_value(&r).unwrap();
        let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "alarm_transitions",
                "faults",
                "interp_checks",
                "jump_rpm",
                "jump_rpm_bits",
                "precision",
                "samples",
                "scene",
                "table"
            ]
        );
        assert_eq!(v["scene"]["design"], design);
        assert_eq!(v["precision"], "f32");
        // The numbers are the computed ones, the bits their f32 patterns.
        let j = p.table.jump_rpm.unwrap();
        assert_eq!(v["jump_rpm"].as_f64(), Some(j as f64));
        assert_eq!(v["jump_rpm_bits"], format!("{:#010x}", j.to_bits()));
        assert_eq!(v["table"].as_array().unwrap().len(), CHIP_GRID_RPM.len());
        let vouched = p.samples.iter().filter(|s| s.prediction.is_some()).count();
        assert_eq!(v["samples"].as_array().unwrap().len(), vouched);
        assert_eq!(
            v["faults"].as_array().unwrap().len(),
            p.samples.len() - vouched
        );
        // The text is the same report: header naming the scene, then the table rows, the
        // jump line, the checks and one line per reading.
        let text = render_text(&r, Units::Inch);
        let first = text.lines().next().unwrap();
        let name = if design == REFERENCE_SCENE {
            "reference design"
        } else {
            design
        };
        assert_eq!(
            first,
            format!("predictor scene: {name}, 10 states (vertical), f32")
        );
        assert_eq!(
            text.lines().count(),
            2 + CHIP_GRID_RPM.len() + 1 + camsim_chip::CHIP_CHECK_RPM.len() + p.samples.len()
        );
        assert!(text.contains(&format!("jump onset: {j:.3} rpm")));
    }
    // NaN and the infinities are numbers the finiteness check finds (a report with one is
    // refused, never printed as null or as a string).
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY] {
        assert!(camsim::report::non_finite(&Num(bad)).unwrap().is_some());
    }
    assert_eq!(serde_json::to_string(&Num(0.5)).unwrap(), "0.5");
}

#[test]
fn a_scene_is_checked_in_the_precision_it_runs_in() {
    // Valid in f64 (the scene file is valid), refused in f32: e2 just above the largest
    // lift plus the roller radius (1.875 in) rounds to 1.875 in f32. The f32 run refuses
    // the scene with its key, as the firmware's build refuses it; the f64 conversion is
    // the scene's own design (identity).
    let mut d = camsim_core::Design::<f64>::reference();
    d.e2 = 1.875 + 1e-9;
    d.validate().unwrap();
    let e = format!("{:#}", compute::<f32>(Some(&d), None).unwrap_err());
    assert_eq!(
        e,
        "scene in f32: design.e2_in = 1.875: cantilever length must exceed the program's largest lift by more than the roller radius (the roller would reach the slide bearing)"
    );
    assert_eq!(camsim_chip::chip_design_from::<f64>(&d).unwrap(), d);
    let r = camsim_core::Design::<f64>::reference();
    assert_eq!(
        camsim_chip::chip_design_from::<f32>(&r).unwrap(),
        r.cast::<f32>().unwrap()
    );
}

#[test]
fn a_measured_profile_is_read_as_the_firmware_reads_it() {
    use camsim::cmd::predict::ProfileKnots;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let r = camsim_core::Design::<f64>::reference();
    // CI's profile: 360 rows every 1 deg -> 361 knots (the closing one included), and the
    // roller on it lowers the f32 table's jump onset: the waviness adds acceleration the
    // spring must hold (the firmware's log and scripts/firmware-ci.sh's parity check have
    // the same bits).
    let k = ProfileKnots::load(&root.join("scenes/measured-wavy.csv"), &r).unwrap();
    assert_eq!(k.knots_rad.len(), 361);
    assert_eq!(k.values_in.first(), k.values_in.last());
    let p = compute::<f32>(None, Some(&k)).unwrap();
    let theoretical = compute::<f32>(None, None).unwrap().table.jump_rpm.unwrap();
    let wavy = p.table.jump_rpm.unwrap();
    // 15 waves of 0.0004 in at 800 rpm: e'' ω² = 15² 0.0004 83.8² = 632 in/s² peak against the
    // program's few thousand: a lower onset, by less than a tenth.
    assert!(
        wavy < theoretical && wavy > 0.9 * theoretical,
        "{wavy} vs {theoretical}"
    );
    // Refusals are one line naming the file and the line; the chip's limit is 720 rows.
    let dir = std::env::temp_dir().join(format!("camsim-measured-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "angle_deg,deviation_in\n0,0\n1O,0\n").unwrap();
    let e = format!("{:#}", ProfileKnots::load(&bad, &r).unwrap_err());
    assert_eq!(
        e,
        format!(
            "{}: line 3: angle_deg \"1O\" is not a number",
            bad.display()
        )
    );
    let long = dir.join("long.csv");
    let rows: String = (0..721)
        .map(|i| format!("{},0\n", i as f64 * 0.4))
        .collect();
    std::fs::write(&long, format!("angle_deg,deviation_in\n{rows}")).unwrap();
    let Err(e) = ProfileKnots::load(&long, &r) else {
        panic!("721 rows accepted")
    };
    let e = format!("{e:#}");
    assert!(
        e.ends_with("line 722: more than 720 rows in a revolution"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn with_no_jump_onset_the_speed_margin_is_absent_with_its_reason() {
    // A spring twice as stiff as the reference's holds contact up to the predictor's search limit:
    // no onset, so no margin exists. The report leaves the number out and says why; it
    // never prints an infinity, "inf" or null.
    let mut d = camsim_core::Design::<f64>::reference();
    d.k_rs *= 2.0;
    d.validate().unwrap();
    let p = compute::<f64>(Some(&d), None).unwrap();
    assert_eq!(p.table.jump_rpm, None);
    let r = PredictReport::of(&p, false, "stiff", None);
    assert!(camsim::report::non_finite(&r).unwrap().is_none());
    let v = serde_json::to_value(&r).unwrap();
    let samples = v["samples"].as_array().unwrap();
    assert!(!samples.is_empty());
    let reason = format!(
        "no jump onset up to the search limit of {} rpm",
        CHIP_MAX_RPM
    );
    for s in samples {
        assert!(s.get("speed_margin_rpm").is_none(), "{s}");
        assert_eq!(s["speed_margin_absent"], reason.as_str());
    }
    let text = render_text(&r, Units::Inch);
    assert!(!text.contains("inf"), "{text}");
    assert!(text.contains("speed margin none (no onset)"), "{text}");
    assert!(text.contains(&format!("jump onset: none up to {} rpm", CHIP_MAX_RPM)));
}
