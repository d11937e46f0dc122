//! `camsim sensitivity` (VI.4.3): the quick study's shape (a baseline per cam at change
//! 0, every group × change × cam once), the same numbers for any thread count, each
//! case the outputs of its scaled design, no null in the JSON, the plot written, and
//! usage errors.

use camsim::cli::{main_from, parse_from, Command};
use camsim::cmd::sensitivity::{self, Group, QUICK_CHANGES_PCT};
use camsim::report::non_finite;
use camsim::sim::RunSpec;

fn args(extra: &[&str]) -> sensitivity::Args {
    let mut argv = vec![
        "camsim",
        "sensitivity",
        "--quick",
        "--interval-deg",
        "10",
        "--seed",
        "7",
    ];
    argv.extend_from_slice(extra);
    match parse_from(argv).unwrap().command {
        Command::Sensitivity(a) => a,
        other => panic!("parsed as {other:?}"),
    }
}

/// The report's JSON without its run time.
fn json(r: &sensitivity::SensitivityReport) -> serde_json::Value {
    let mut v = serde_json::to_value(r).unwrap();
    v.as_object_mut().unwrap().remove("wall_s");
    v
}

#[test]
fn the_quick_study_has_every_case_once_and_the_same_numbers_on_any_thread_count() {
    let one = sensitivity::report(&args(&["--threads", "1"]), camsim::units::Units::Inch).unwrap();
    let two = sensitivity::report(&args(&["--threads", "2"]), camsim::units::Units::Inch).unwrap();
    assert_eq!(json(&one), json(&two));
    assert_eq!(non_finite(&one).unwrap(), None);

    // Baselines: one per cam, change 0.
    assert_eq!(one.baseline.len(), 2);
    for (b, cam) in one.baseline.iter().zip(["theoretical", "actual"]) {
        assert_eq!((b.group, b.change_pct, b.cam), ("baseline", 0, cam));
    }
    // Every group, change and cam once.
    assert_eq!(one.cases.len(), 3 * QUICK_CHANGES_PCT.len() * 2);
    for g in Group::ALL {
        for c in QUICK_CHANGES_PCT {
            for cam in ["theoretical", "actual"] {
                let n = one
                    .cases
                    .iter()
                    .filter(|x| x.group == g.name() && x.change_pct == c && x.cam == cam)
                    .count();
                assert_eq!(n, 1, "{g:?} {c} {cam}");
            }
        }
    }
    // The JSON's keys are the issue's.
    let v = json(&one);
    let case = &v["cases"][0];
    for k in [
        "group",
        "change_pct",
        "cam",
        "rms_displacement_in",
        "rms_velocity_in_per_s",
        "rms_acceleration_in_per_s2",
        "rms_angular_velocity_rad_per_s",
        "contact_stress_avg_psi",
        "jump",
    ] {
        assert!(case.get(k).is_some(), "{k} missing from {case}");
    }
    assert_eq!(v["baseline"][1]["change_pct"], 0);
    assert_eq!(v["actual_profile"]["intervals"], 36);

    // A case is its scaled design's outputs; the baseline the design's own.
    let mut spec = RunSpec::reference();
    spec.dofs.horizontal = false;
    let b = sensitivity::outputs(&spec).unwrap();
    assert_eq!(one.baseline[0].outputs, b);
    let mut s = spec.clone();
    s.design = sensitivity::scaled(&spec.design, Group::Stiffness, 0.7);
    let c = one
        .cases
        .iter()
        .find(|x| x.group == "stiffness" && x.change_pct == -30 && x.cam == "theoretical")
        .unwrap();
    assert_eq!(c.outputs, sensitivity::outputs(&s).unwrap());
    // The actual cam deviates more from the theoretical response than the perfect cam.
    assert!(
        one.baseline[1].outputs.rms_acceleration_in_per_s2.in_inch()
            > b.rms_acceleration_in_per_s2.in_inch()
    );
}

#[test]
fn the_plot_is_written_and_usage_errors_exit_2() {
    let dir = std::env::temp_dir().join(format!("camsim-sens-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let d = dir.to_str().unwrap();
    assert_eq!(
        main_from([
            "camsim",
            "sensitivity",
            "--quick",
            "--interval-deg",
            "10",
            "--plot",
            d,
            "--json"
        ]),
        0
    );
    let png = std::fs::read(dir.join("sensitivity.png")).unwrap();
    assert_eq!(png.get(..4), Some(&b"\x89PNG"[..]));
    // Again without --force: refused, the plot left as it was.
    assert_eq!(
        main_from([
            "camsim",
            "sensitivity",
            "--quick",
            "--interval-deg",
            "10",
            "--plot",
            d
        ]),
        1
    );
    assert_eq!(std::fs::read(dir.join("sensitivity.png")).unwrap(), png);
    let _ = std::fs::remove_dir_all(&dir);
    for bad in [
        &["camsim", "sensitivity", "--threads", "0"][..],
        &["camsim", "sensitivity", "--rpm", "-5"][..],
        &["camsim", "sensitivity", "--rpm", "1e300"][..],
        &["camsim", "sensitivity", "--interval-deg", "7"][..],
    ] {
        assert_eq!(main_from(bad.iter().copied()), 2, "{bad:?}");
    }
}
