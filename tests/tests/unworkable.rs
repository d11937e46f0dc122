//! Studies survive an unworkable case: a law whose run leaves the model's valid range
//! (docs/MODEL.md §3.20) is reported "not workable" with its reason and the study goes
//! on; a study none of whose cases is workable exits 1.

use camsim::cli::{main_from, parse_from, Command};
use camsim::cmd::compare::{self, CompareReport};

fn compare_report(extra: &[&str]) -> anyhow::Result<CompareReport> {
    let argv = ["camsim", "compare"].iter().chain(extra).copied();
    match parse_from(argv).unwrap().command {
        Command::Compare(a) => compare::report(&a),
        other => panic!("parsed as {other:?}"),
    }
}

/// Seed 4's actual cam, cut by the thesis's per-point method, throws the straight-line follower into its slide bearing (the
/// thesis marked the straight line "not workable", VI.4.2): compare ranks the other 11
/// laws from 1 to 11, and names straight-line with the core's reason.
#[test]
fn compare_seed_4_ranks_the_workable_laws_and_names_straight_line() {
    let args = ["--seed", "4", "--profile-method", "thesis"];
    let argv = ["camsim", "compare"].iter().chain(&args).chain(&["--json"]);
    assert_eq!(main_from(argv.copied()), 0);
    let r = compare_report(&args).unwrap();
    assert_eq!(r.not_workable.len(), 1, "{:?}", r.not_workable);
    let n = &r.not_workable[0];
    assert_eq!(
        (n.name.as_str(), n.cam.as_str()),
        ("straight-line", "actual")
    );
    assert!(
        n.reason.contains("left its valid range") && n.reason.contains("thrown off the cam"),
        "{}",
        n.reason
    );
    let laws = camsim_core::MotionLaw::ALL.len();
    assert_eq!(r.laws.len(), laws - 1);
    assert!(r.laws.iter().all(|l| l.name != "straight-line"));
    let mut overall: Vec<usize> = r.laws.iter().map(|l| l.ranks.overall).collect();
    overall.sort_unstable();
    assert_eq!(overall, (1..laws).collect::<Vec<_>>(), "ranks 1..11");
    let text = camsim::report::Report::text(&r);
    assert!(text.contains("not workable"), "{text}");
    assert!(
        text.lines()
            .any(|l| l.starts_with("straight-line")
                && l.contains("on the actual cam: the model left")),
        "{text}"
    );
    let json = serde_json::to_value(&r).unwrap();
    assert_eq!(json["not_workable"][0]["name"], "straight-line");
    assert!(json["not_workable"][0]["reason"].is_string());
}

/// At 3 000 rpm every law throws the follower off the theoretical cam already: nothing
/// is workable, the command exits 1 and says so.
#[test]
fn compare_with_no_workable_law_exits_1() {
    let e = compare_report(&["--quick", "--rpm", "3000"]).unwrap_err();
    let msg = format!("{e:#}");
    assert!(msg.contains("no law is workable"), "{msg}");
    assert!(msg.contains("left its valid range"), "{msg}");
    assert_eq!(
        main_from(["camsim", "compare", "--quick", "--rpm", "3000"]),
        1
    );
}

fn sensitivity_report(
    extra: &[&str],
) -> anyhow::Result<camsim::cmd::sensitivity::SensitivityReport> {
    let argv = ["camsim", "sensitivity"].iter().chain(extra).copied();
    match parse_from(argv).unwrap().command {
        Command::Sensitivity(a) => camsim::cmd::sensitivity::report(&a),
        other => panic!("parsed as {other:?}"),
    }
}

/// At 1300 rpm (vertical scene) the follower is thrown into its slide bearing after it
/// separates in most cases, the baselines too: those cases are reported as jumps with
/// the core's reason (text, JSON, plot), the mass -30 % cases keep their outputs, every
/// case is accounted for once, and the study exits 0.
#[test]
fn sensitivity_reports_cases_that_leave_the_range_and_goes_on() {
    let dir = std::env::temp_dir().join(format!("camsim-unworkable-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let plot = dir.to_string_lossy().to_string();
    let args = ["--quick", "--rpm", "1300"];
    let r = sensitivity_report(&[&args[..], &["--plot", &plot]].concat()).unwrap();
    assert!(dir.join("sensitivity.png").is_file());
    // 2 baselines + 3 groups x 2 changes x 2 cams, each once.
    assert_eq!(r.baseline.len() + r.cases.len() + r.not_workable.len(), 14);
    assert!(r.baseline.is_empty(), "{:?}", r.baseline);
    for cam in ["theoretical", "actual"] {
        assert!(
            r.cases
                .iter()
                .any(|c| c.cam == cam && c.group == "mass" && c.change_pct == -30),
            "{cam}"
        );
    }
    assert!(!r.not_workable.is_empty());
    for n in &r.not_workable {
        assert!(n.jump, "{n:?}");
        assert!(n.reason.contains("left its valid range"), "{}", n.reason);
    }
    let text = camsim::report::Report::text(&r);
    assert!(
        text.contains("jumps, then the model left its valid range")
            && text.contains("baseline on the actual cam: the model left its valid range")
            && text.contains("its baseline left the model's valid range"),
        "{text}"
    );
    let json = serde_json::to_value(&r).unwrap();
    assert_eq!(json["not_workable"][0]["group"], "baseline");
    assert_eq!(json["not_workable"][0]["jump"], true);
    let argv = ["camsim", "sensitivity"]
        .iter()
        .chain(&args)
        .chain(&["--json"]);
    assert_eq!(main_from(argv.copied()), 0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A tolerance-study cell by the counting rule (docs/MODEL.md §3.20): cams that all left
/// the range with the follower on the cam make the cell not workable, with the first
/// cam's reason and the count; one cam that jumped and left makes it workable.
#[test]
fn a_tolerance_cell_of_unworkable_cams_is_not_workable_with_its_reason() {
    use camsim::cmd::montecarlo::StudyStats;
    use camsim::cmd::tolerance_study::cell_summary;
    let mut s = StudyStats::default();
    s.add_left_range(1, false, "stalled");
    s.add_left_range(0, false, "stalled first");
    let (sm, why) = cell_summary(&s, 2).unwrap();
    assert_eq!(why.as_deref(), Some("sample 0: stalled first"));
    assert_eq!((sm.samples, sm.not_workable, sm.jump.count), (0, 2, 0));
    s.add_left_range(2, true, "thrown off");
    let (sm, why) = cell_summary(&s, 2).unwrap();
    assert_eq!(why, None);
    assert_eq!((sm.jump.count, sm.jump.p, sm.not_workable), (1, 1.0, 2));
}

/// At 1300 rpm the theoretical cam and every cell's cam (--quick: one a cell) jump and
/// are then thrown off the cam: the study goes on and exits 0, every cell reports
/// P(jump) = 1 of 1 counted as a left-range jump, no acceleration statistics, in text
/// and JSON.
#[test]
fn tolerance_study_cells_that_jump_out_of_range_report_p_jump_1() {
    use camsim::cmd::tolerance_study;
    let args = ["tolerance-study", "--quick", "--rpm", "1300"];
    let argv = ["camsim"].iter().chain(&args).chain(&["--json"]);
    assert_eq!(main_from(argv.copied()), 0);
    let Command::ToleranceStudy(a) = parse_from(["camsim"].iter().chain(&args).copied())
        .unwrap()
        .command
    else {
        panic!("not tolerance-study")
    };
    let r = tolerance_study::report(&a).unwrap();
    assert_eq!(r.cells.len(), 9);
    for c in std::iter::once(&r.theoretical).chain(&r.cells) {
        let s = &c.summary;
        assert_eq!((s.jump.count, s.jump.p, s.left_range_jumps), (1, 1.0, 1));
        assert_eq!((s.samples, c.acc_rms_sum_in_per_s2), (0, None));
        assert!(c.not_workable.is_none());
    }
    let text = camsim::report::Report::text(&r);
    assert_eq!(
        text.matches("no statistics: every cam jumped and then left the model's valid range")
            .count(),
        10,
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&camsim::report::Report::json(&r).unwrap()).unwrap();
    let cell = &json["cells"][0];
    assert!(cell.get("acc_rms_sum_in_per_s2").is_none() && cell.get("not_workable").is_none());
    assert_eq!(cell["summary"]["left_range_jumps"], 1);
    assert_eq!(cell["summary"]["jump"]["p"], 1.0);
}
