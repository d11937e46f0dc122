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
    let text = camsim::report::Report::text(&r, camsim::units::Units::Inch);
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
    let cli = parse_from(argv).unwrap();
    match cli.command {
        Command::Sensitivity(a) => camsim::cmd::sensitivity::report(&a, cli.units),
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
    let text = camsim::report::Report::text(&r, camsim::units::Units::Inch);
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
    let r = tolerance_study::report(&a, camsim::units::Units::Inch).unwrap();
    assert_eq!(r.cells.len(), 9);
    for c in std::iter::once(&r.theoretical).chain(&r.cells) {
        let s = &c.summary;
        assert_eq!((s.jump.count, s.jump.p, s.left_range_jumps), (1, 1.0, 1));
        assert_eq!((s.samples, c.acc_rms_sum_in_per_s2), (0, None));
        assert!(c.not_workable.is_none());
    }
    let text = camsim::report::Report::text(&r, camsim::units::Units::Inch);
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

/// The reference scene with `edits` (key line prefix, new line) applied, written to a
/// fresh file.
fn scene_with(name: &str, edits: &[(&str, &str)]) -> std::path::PathBuf {
    let mut text = camsim::scene::default_text().unwrap();
    for (prefix, line) in edits {
        let old = text
            .lines()
            .find(|l| l.starts_with(prefix))
            .unwrap_or_else(|| panic!("no {prefix}"))
            .to_string();
        text = text.replace(&old, line);
    }
    let p = std::env::temp_dir().join(format!(
        "camsim-unworkable-{}-{name}.toml",
        std::process::id()
    ));
    std::fs::write(&p, text).unwrap();
    p
}

/// `sensitivity --per-key` on a cantilever 1.885 in long: at full lift (1.5 in) it
/// clears the roller (0.375 in) by 0.01 in, 0.99 of it by −0.009 in, which the design
/// check refuses (the length bound of docs/MODEL.md §3.20). That key is reported not
/// workable at x0.99 with its reason (text, JSON without numbers), ranked last; the
/// roller radius +1 % (0.00375 in) still clears; every other key has its elasticities;
/// the study exits 0.
#[test]
fn sensitivity_per_key_reports_a_key_that_leaves_the_range_and_goes_on() {
    let scene = scene_with("e2", &[("e2_in = ", "e2_in = 1.885")]);
    let s = scene.to_string_lossy().to_string();
    let args = [s.as_str(), "--quick", "--per-key"];
    let r = sensitivity_report(&args).unwrap();
    let pk = r.per_key.as_ref().unwrap();
    let bad: Vec<_> = pk
        .keys
        .iter()
        .filter(|k| k.not_workable.is_some())
        .collect();
    assert_eq!(bad.len(), 1, "{bad:?}");
    let n = bad[0].not_workable.as_ref().unwrap();
    assert_eq!((bad[0].key, n.factor, n.jump), ("e2_in", 0.99, false));
    assert!(
        n.reason.contains("e2_in = 1.86") && n.reason.contains("cantilever length must exceed"),
        "{}",
        n.reason
    );
    assert_eq!(pk.keys.last().unwrap().key, "e2_in");
    for k in &pk.keys[..pk.keys.len() - 1] {
        assert!(
            k.elasticity.values()[..5].iter().any(Option::is_some),
            "{}",
            k.key
        );
    }
    let text = camsim::report::Report::text(&r, camsim::units::Units::Inch);
    assert!(
        text.lines().any(|l| l.contains("e2_in")
            && l.contains("not workable at x0.99: the design check refuses it")),
        "{text}"
    );
    let json: serde_json::Value =
        serde_json::from_str(&camsim::report::Report::json(&r).unwrap()).unwrap();
    let row = json["per_key"]["keys"]
        .as_array()
        .unwrap()
        .iter()
        .find(|k| k["key"] == "e2_in")
        .unwrap();
    assert_eq!(row["elasticity"], serde_json::json!({}));
    assert!(row["not_workable"]["reason"].is_string());
    let _ = std::fs::remove_file(&scene);
}

fn tolerance_args(extra: &[&str]) -> camsim::cmd::design::McArgs {
    let base = ["camsim", "design", "tolerance", "--quick", "--rpm", "900"];
    let tail = ["--samples", "5", "--p-max", "0.5", "--threads", "1"];
    let argv = base.iter().chain(extra).chain(&tail).copied();
    let Command::Design(a) = parse_from(argv).unwrap().command else {
        panic!("not design")
    };
    let camsim::cmd::design::What::Tolerance(t) = a.what else {
        panic!("not tolerance")
    };
    t
}

/// `design tolerance` at 900 rpm, 5 cams a step, --p-max 0.5: at FPR 17 a tolerance
/// passes; at FPR 57 nothing does, not even the search's first, 0.1 x VI.1's ±0.0005 in
/// cam tolerance (the held ±0.001 in eccentricity throws the follower off). The table
/// gives FPR 57's row as "nothing passes down to ±0.00005 in" with P(jump) there above
/// --p-max (text and JSON, no answer) and goes on; FPR 57 alone fails with that line.
#[test]
fn design_tolerance_reports_an_fpr_where_nothing_passes_and_goes_on() {
    use camsim::report::Report;
    let table = camsim::cmd::design::tolerance_table(
        &tolerance_args(&["--waviness-fpr", "17,57"]),
        camsim::units::Units::Inch,
    )
    .unwrap();
    assert_eq!(table.0.len(), 2);
    let ok = table.0[0].answer().unwrap();
    assert_eq!(ok.waviness_fpr, Some(17));
    assert!(ok.answer >= 0.1 && ok.p_jump.unwrap().hi95 <= 0.5);
    let n = table.0[1].nothing_passes().unwrap();
    assert_eq!((n.waviness_fpr, n.smallest_factor_tried), (57, 0.1));
    assert_eq!(n.smallest_cam_tolerance_in.in_inch(), 0.0005 * 0.1);
    assert!(n.p_jump.unwrap().hi95 > 0.5);
    assert_eq!(n.tolerance_factors_tried, vec![(0.1, false)]);
    let text = table.text(camsim::units::Units::Inch);
    let row = text
        .lines()
        .find(|l| l.trim_start().starts_with("57"))
        .unwrap();
    assert!(
        row.contains(
            "nothing passes down to ±0.00005 in (0.1 x VI.1's cam tolerance): P(jump) there"
        ) && row.contains("above --p-max 0.5"),
        "{text}"
    );
    assert!(
        text.contains("held: roller ±0.000100 in, eccentricity ±0.00100 in"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(&table.json().unwrap()).unwrap();
    let rows = json.as_array().unwrap();
    assert!(rows[0]["answer"].is_number());
    assert!(rows[1].get("answer").is_none() && rows[1]["nothing_passes"].is_string());
    assert_eq!(rows[1]["waviness_fpr"], 57);
    let e = camsim::cmd::design::tolerance_table(
        &tolerance_args(&["--waviness-fpr", "57"]),
        camsim::units::Units::Inch,
    )
    .unwrap_err();
    let msg = format!("{e:#}");
    assert!(
        msg.starts_with("FPR 57: nothing passes down to ±0.00005 in") && !msg.contains('\n'),
        "{msg}"
    );
}

/// tolerance-study on a soft cam and roller (E = 1e5 psi, the modulus range's least, on
/// a 0.1 in line contact): the Hertz penetration passes its bound (a hundredth of the
/// roller radius) in revolution 1 with the follower on the cam, on the theoretical cam
/// and in every cell: nothing is workable, the command exits 1 with one line naming
/// the bound, and writes no plot.
#[test]
fn tolerance_study_with_no_workable_cell_exits_1_and_writes_nothing() {
    let scene = scene_with(
        "soft",
        &[
            ("roller_youngs_psi = ", "roller_youngs_psi = 100000.0"),
            ("cam_youngs_psi = ", "cam_youngs_psi = 100000.0"),
            ("contact_length_in = ", "contact_length_in = 0.1"),
        ],
    );
    let dir =
        std::env::temp_dir().join(format!("camsim-unworkable-{}-ts-plot", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let s = scene.to_string_lossy().to_string();
    let d = dir.to_string_lossy().to_string();
    let argv = ["camsim", "tolerance-study", &s, "--quick", "--plot", &d];
    let Command::ToleranceStudy(a) = parse_from(argv).unwrap().command else {
        panic!("not tolerance-study")
    };
    let msg = format!(
        "{:#}",
        camsim::cmd::tolerance_study::report(&a, camsim::units::Units::Inch).unwrap_err()
    );
    assert!(
        msg.starts_with("no cell is workable")
            && msg.contains("contact penetration")
            && msg.contains("beyond its bound")
            && !msg.contains('\n'),
        "{msg}"
    );
    assert!(!dir.exists(), "the plot directory was written");
    assert_eq!(main_from(argv.iter().copied().chain(["--json"])), 1);
    assert!(!dir.exists(), "the plot directory was written");
    let _ = std::fs::remove_file(&scene);
}
