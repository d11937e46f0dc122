//! The studies: a Monte Carlo study is the same bit for bit for any thread count and
//! for any split into shards merged back; the merge refuses files that are not one
//! study's complete set; its statistics are the textbook ones; `compare` ranks every
//! law as its column values order them; the statistics measure the deviation from
//! the perfect cam.

use std::path::{Path, PathBuf};

use camsim::cli::{parse_from, Command};
use camsim::cmd::compare::{self, CompareReport, RANKED};
use camsim::cmd::montecarlo::{
    self, execute, merge, Moments, Outcome, OutputArgs, Probability, SampleRecord, Study,
};

mod common;
use common::CHEAP;

fn montecarlo_args(extra: &[&str]) -> montecarlo::Args {
    let mut argv = vec!["camsim", "montecarlo"];
    argv.extend_from_slice(extra);
    match parse_from(argv).unwrap().command {
        Command::Montecarlo(a) => a,
        other => panic!("parsed as {other:?}"),
    }
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("camsim-mc-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Every number of the records, as bits (so 0.0 and -0.0 differ, NaN equals itself).
fn bits(records: &[SampleRecord]) -> Vec<u64> {
    let mut out = Vec::new();
    for r in records {
        out.extend([
            r.index,
            r.fpr as u64,
            r.rms_deviation_in.to_bits(),
            r.steps as u64,
        ]);
        for p in &r.periods {
            out.extend(p.values.iter().map(|v| v.to_bits()));
            out.push(p.jump as u64);
        }
    }
    out
}

fn study(samples: u64) -> Study {
    let a = montecarlo_args(&[&["--samples", &samples.to_string()], &CHEAP[..]].concat());
    a.study.study().unwrap()
}

#[test]
fn bit_identical_for_any_thread_count_and_sample_order() {
    let s = study(6);
    let all: Vec<u64> = (0..6).collect();
    let one = s.run(&all, 1, false).unwrap();
    // The samples are different cams with different responses (a test that cannot fail
    // otherwise).
    assert_ne!(one[0].rms_deviation_in, one[1].rms_deviation_in);
    assert_ne!(one[0].periods[1].values, one[1].periods[1].values);
    let reference = bits(&one);
    let summary = serde_json::to_string(&montecarlo::summarize(&one, 2).unwrap()).unwrap();
    for threads in [2, 3] {
        let r = s.run(&all, threads, false).unwrap();
        assert_eq!(bits(&r), reference, "{threads} threads");
        let sm = serde_json::to_string(&montecarlo::summarize(&r, 2).unwrap()).unwrap();
        assert_eq!(sm, summary, "{threads} threads");
    }
    // Sample 4 alone, after others in reverse order: the same record.
    let rev: Vec<u64> = all.iter().rev().copied().collect();
    let back = s.run(&rev, 2, false).unwrap();
    assert_eq!(bits(&back[1..2]), bits(&one[4..5]));
    let alone = s.sample(4).unwrap();
    assert_eq!(bits(&[alone]), bits(&one[4..5]));
}

fn shard(k: usize, n: usize, samples: u64, file: &Path, seed: &str) -> Outcome {
    let shard = format!("{k}/{n}");
    let samples = samples.to_string();
    let out = file.to_str().unwrap();
    let mut argv = vec![
        "--samples",
        &samples,
        "--shard",
        &shard,
        "--out",
        out,
        "--force",
    ];
    argv.extend_from_slice(&CHEAP[..4]);
    argv.extend_from_slice(&["--seed", seed, "--threads", "2"]);
    execute(&montecarlo_args(&argv), camsim::units::Units::Inch).unwrap()
}

fn merge_err(files: &[&Path]) -> String {
    let files: Vec<PathBuf> = files.iter().map(|p| p.to_path_buf()).collect();
    let e = merge(&files, &OutputArgs::default(), camsim::units::Units::Inch).unwrap_err();
    let line = format!("{e:#}");
    assert!(!line.contains('\n'), "one line: {line}");
    line
}

fn single(samples: &str, threads: &str) -> montecarlo::MonteCarloReport {
    match execute(
        &montecarlo_args(&[&["--samples", samples, "--threads", threads], &CHEAP[..]].concat()),
        camsim::units::Units::Inch,
    )
    .unwrap()
    {
        Outcome::Study(r) => *r,
        Outcome::Shard(_) => panic!("not a shard run"),
    }
}

#[test]
fn three_way_shard_and_merge_equals_the_single_run_bit_for_bit() {
    let n = 7u64;
    let single = single("7", "1");
    // 1 and 2 threads: the same bits (the samples finish in another order).
    let two = self::single("7", "2");
    assert_eq!(
        serde_json::to_string(&two.summary).unwrap(),
        serde_json::to_string(&single.summary).unwrap()
    );
    // The streamed statistics are those of the records, bit for bit (summarize adds the
    // records in index order; the study added them as the threads finished).
    let s = study(7);
    let direct = s.run(&(0..7).collect::<Vec<_>>(), 2, false).unwrap();
    assert_eq!(
        serde_json::to_string(&montecarlo::summarize(&direct, 2).unwrap()).unwrap(),
        serde_json::to_string(&single.summary).unwrap()
    );
    // 1-, 2- and 3-way splits, merged in any order of the files.
    for ways in [1usize, 2, 3] {
        let files: Vec<PathBuf> = (1..=ways)
            .map(|k| tmp(&format!("s{k}of{ways}.json")))
            .collect();
        for (k, f) in files.iter().enumerate() {
            match shard(k + 1, ways, n, f, "7") {
                Outcome::Shard(r) => {
                    // Strided: shard K holds the samples i ≡ K − 1 (mod N).
                    let expect = (k as u64..n).step_by(ways).count() as u64;
                    assert_eq!(r.samples, expect);
                }
                Outcome::Study(_) => panic!("a shard run printed a study"),
            }
            let file = montecarlo::read_shard(f).unwrap();
            assert_eq!(file.samples, (k as u64..n).step_by(ways).count() as u64);
            assert_eq!(file.stats.samples, file.samples);
        }
        let mut order = files.clone();
        order.reverse();
        let merged = merge(&order, &OutputArgs::default(), camsim::units::Units::Inch).unwrap();
        assert_eq!(merged.study, single.study);
        assert_eq!(
            serde_json::to_string(&merged.summary).unwrap(),
            serde_json::to_string(&single.summary).unwrap(),
            "{ways}-way"
        );
        assert_eq!(merged.summary, single.summary);
    }
    let files: Vec<PathBuf> = (1..=3).map(|k| tmp(&format!("s{k}of3.json"))).collect();

    // Refusals, each one line.
    let e = merge_err(&[&files[0], &files[1]]);
    assert!(
        e.contains("2 of the study's 7 samples are missing (first: 2, 5; shards 3/3)"),
        "{e}"
    );
    let e = merge_err(&[&files[0], &files[1], &files[2], &files[0]]);
    assert!(e.contains("is given twice"), "{e}");
    // A copy of a shard under another name: the same samples twice.
    let copy = tmp("copy.json");
    std::fs::copy(&files[1], &copy).unwrap();
    let e = merge_err(&[&files[0], &files[1], &files[2], &copy]);
    assert!(
        e.contains("shard 2/3 is in") && e.contains("exactly one shard"),
        "{e}"
    );
    // Shards of two splits.
    let e = merge_err(&[&files[0], &tmp("s2of2.json")]);
    assert!(e.contains("one split K/N with one N"), "{e}");
    // Another study: a different seed, or a different number of samples.
    let other = tmp("other-seed.json");
    shard(1, 3, n, &other, "8");
    let e = merge_err(&[&files[0], &files[1], &other]);
    assert!(
        e.contains("belongs to another study") && e.contains("seed 8 vs 7"),
        "{e}"
    );
    let other_n = tmp("other-n.json");
    shard(3, 3, 8, &other_n, "7");
    let e = merge_err(&[&files[0], &files[1], &other_n]);
    assert!(e.contains("--samples 8 vs 7"), "{e}");
    // Not a shard file at all, and a damaged one.
    let junk = tmp("junk.json");
    std::fs::write(&junk, "{\"laws\": []}").unwrap();
    let e = merge_err(&[&junk]);
    assert!(e.contains("not a camsim montecarlo shard file"), "{e}");
    let text = std::fs::read_to_string(&files[0]).unwrap();
    std::fs::write(&junk, text.replace("\"steps\":", "\"stepz\":")).unwrap();
    let e = merge_err(&[&junk]);
    assert!(e.contains("bad shard file") && e.contains("stepz"), "{e}");
    // A version 2 shard (every sample's record) is named as such.
    std::fs::write(&junk, text.replace("\"version\":5", "\"version\":2")).unwrap();
    let e = merge_err(&[&junk]);
    assert!(
        e.contains("shard file version 2 (this camsim reads version 5)"),
        "{e}"
    );
    if let Some(dir) = junk.parent() {
        let _ = std::fs::remove_dir_all(dir);
    }
}

/// CHEAP without the constant cam speed (the reduced followers need the regulated drive).
const TWO_LEVEL: [&str; 5] = ["--vertical", "--interval-deg", "10", "--seed", "7"];

fn study_report(argv: &[&str]) -> montecarlo::MonteCarloReport {
    match execute(&montecarlo_args(argv), camsim::units::Units::Inch).unwrap() {
        Outcome::Study(r) => *r,
        Outcome::Shard(_) => panic!("not a shard run"),
    }
}

#[test]
fn two_level_is_the_same_for_any_threads_and_shards() {
    let base = [&["--samples", "6", "--two-level", "3"], &TWO_LEVEL[..]].concat();
    let run = |threads: &str| study_report(&[&base[..], &["--threads", threads]].concat());
    let (one, two) = (run("1"), run("2"));
    let json = |r: &montecarlo::MonteCarloReport| {
        (
            serde_json::to_string(&r.summary).unwrap(),
            serde_json::to_string(&r.two_level).unwrap(),
        )
    };
    assert!(one.two_level.is_some());
    assert_eq!(json(&one), json(&two));
    let t = one.two_level.as_ref().unwrap();
    assert_eq!((t.samples, t.full_samples), (6, 3));
    // The text names the subsample's cams, 0-2, the same after any merge of shards.
    let header = |r: &montecarlo::MonteCarloReport| {
        let text = camsim::report::Report::text(r, camsim::units::Units::Inch);
        assert!(text.contains("(3 cams on both)"), "{text}");
        let h = text
            .lines()
            .find(|l| l.starts_with("full model, two-level"));
        h.unwrap_or_default().to_string()
    };
    assert!(
        header(&one).ends_with("cams 0-2 on the full model too"),
        "{}",
        header(&one)
    );
    assert_eq!(
        t.jump.value,
        (t.jump.reduced + t.jump.correction).clamp(0.0, 1.0)
    );
    // 2- and 3-way shards merged: the same bits.
    for ways in [2usize, 3] {
        let files: Vec<PathBuf> = (1..=ways)
            .map(|k| tmp(&format!("two-level-{k}of{ways}.json")))
            .collect();
        for (k, f) in files.iter().enumerate() {
            let shard = format!("{}/{ways}", k + 1);
            let argv = [
                &base[..],
                &["--shard", &shard, "--out", f.to_str().unwrap(), "--force"],
            ]
            .concat();
            execute(&montecarlo_args(&argv), camsim::units::Units::Inch).unwrap();
            let file = montecarlo::read_shard(f).unwrap();
            // The subsample is samples 0-2: shard K holds those of them ≡ K − 1.
            let pairs = (k as u64..3).step_by(ways).count() as u64;
            assert_eq!(file.two_level.as_ref().unwrap().full.samples, pairs);
        }
        let merged = merge(&files, &OutputArgs::default(), camsim::units::Units::Inch).unwrap();
        assert_eq!(json(&merged), json(&one), "{ways}-way");
        assert_eq!(header(&merged), header(&one), "{ways}-way");
    }
    // A one-model shard does not merge with a two-level one.
    let plain = tmp("plain-1of2.json");
    let argv = [
        &[
            "--samples",
            "6",
            "--two-level",
            "0",
            "--shard",
            "1/2",
            "--out",
            plain.to_str().unwrap(),
            "--force",
        ],
        &TWO_LEVEL[..],
    ]
    .concat();
    execute(&montecarlo_args(&argv), camsim::units::Units::Inch).unwrap();
    let e = merge_err(&[&plain, &tmp("two-level-2of2.json")]);
    assert!(e.contains("--two-level 3 vs one model"), "{e}");
}

#[test]
fn two_level_over_every_cam_is_the_full_models_study() {
    // n = N: the reduced model cancels, and the estimate is the full model's own study
    // of the same cams (the same actual cam on both models).
    let full = study_report(&[&["--samples", "4", "--two-level", "0"], &TWO_LEVEL[..]].concat());
    let two = study_report(&[&["--samples", "4", "--two-level", "4"], &TWO_LEVEL[..]].concat());
    let t = two.two_level.clone().unwrap();
    assert_eq!(t.subsample_full_jump, full.summary.jump);
    assert!((t.jump.value - full.summary.jump.p).abs() < 1e-12);
    for c in &t.whole_revolution {
        let m = full.summary.whole_revolution.get(&c.column).unwrap().mean;
        assert!(
            (c.mean.value - m).abs() <= 1e-12 * m.abs(),
            "{}: {} vs {m}",
            c.column,
            c.mean.value
        );
    }
    // The reduced model is another model: its acceleration sum differs.
    let acc = |r: &montecarlo::MonteCarloReport| {
        r.summary.whole_revolution.get("acc_rms_sum").unwrap().mean
    };
    assert_ne!(acc(&two), acc(&full));
    // Refusals: more full-model cams than cams; a drive the reduced followers lack; a
    // forced follower.
    let e = execute(
        &montecarlo_args(&[&["--samples", "4", "--two-level", "2"], &CHEAP[..]].concat()),
        camsim::units::Units::Inch,
    )
    .unwrap_err();
    assert!(format!("{e:#}").contains("regulated drive only"), "{e:#}");
    let e = execute(
        &montecarlo_args(&[&["--samples", "4", "--two-level", "5"], &TWO_LEVEL[..]].concat()),
        camsim::units::Units::Inch,
    )
    .unwrap_err();
    assert!(format!("{e:#}").contains("at most --samples (4)"), "{e:#}");
    let e = parse_from([
        "camsim",
        "montecarlo",
        "--samples",
        "4",
        "--two-level",
        "2",
        "--follower",
        "quasi-static-rod",
    ])
    .unwrap_err();
    assert!(camsim::cli::usage_line(&e).contains("--follower"), "{e}");
}

#[test]
fn the_default_is_two_level_and_its_estimate_lies_in_the_full_models_interval() {
    // Cams cut on 5° intervals: rough enough that some jump and some do not on the
    // regulated drive (P(jump) well inside (0, 1)), so the estimate has something to
    // estimate. The same 24 cams on the full model alone (--two-level 0) and by default
    // with n = 8 of them on the full model too.
    let cams = ["--samples", "24", "--interval-deg", "5", "--seed", "3"];
    let full = study_report(&[&cams[..], &["--two-level", "0"]].concat());
    let jumped = full.summary.jump.count;
    assert!(
        0 < jumped && jumped < 24,
        "{jumped} of 24 jump on the full model"
    );
    assert_eq!(
        full.study.one_model.as_deref(),
        Some("the full model alone (--two-level 0)")
    );
    let two = study_report(&[&cams[..], &["--two-level", "8"]].concat());
    let t = two.two_level.as_ref().unwrap();
    assert_eq!((t.samples, t.full_samples), (24, 8));
    let (lo, hi) = (full.summary.jump.lo95, full.summary.jump.hi95);
    assert!(
        lo <= t.jump.value && t.jump.value <= hi,
        "two-level {} outside the full model's [{lo}, {hi}]",
        t.jump.value
    );
    // No option: the two-level estimate with the default subsample (all 24: at least 30).
    let default = study_report(&cams);
    assert_eq!(default.two_level.as_ref().unwrap().full_samples, 24);
    assert_eq!(montecarlo::default_full_samples(24), 24);
    assert_eq!(montecarlo::default_full_samples(1000), 100);
    assert_eq!(montecarlo::default_full_samples(10_001), 1001);
    // A constant cam speed: the full model alone, and the report says why.
    let constant =
        study_report(&[&["--samples", "2", "--constant-cam-speed"], &TWO_LEVEL[..]].concat());
    assert!(constant.two_level.is_none());
    assert!(
        constant
            .study
            .one_model
            .as_deref()
            .is_some_and(|w| w.contains("regulated drive")),
        "{:?}",
        constant.study.one_model
    );
}

#[test]
fn shard_and_option_errors_are_usage_errors() {
    for (argv, what) in [
        (vec!["--samples", "5", "--shard", "1/3"], "--out"),
        (
            vec!["--samples", "5", "--shard", "4/3", "--out", "x"],
            "K/N",
        ),
        (
            vec!["--samples", "5", "--shard", "0/3", "--out", "x"],
            "K/N",
        ),
        (vec!["--samples", "0"], "samples"),
        (vec!["--seed", "3"], "--samples"),
    ] {
        let mut full = vec!["camsim", "montecarlo"];
        full.extend(argv.iter());
        let e = parse_from(full).unwrap_err();
        let line = camsim::cli::usage_line(&e);
        assert!(line.contains(what), "{argv:?}: {line}");
    }
    // `merge` needs files.
    assert!(parse_from(["camsim", "montecarlo", "merge"]).is_err());
    assert!(parse_from(["camsim", "montecarlo", "merge", "a.json", "b.json"]).is_ok());
}

#[test]
fn statistics_are_the_textbook_ones() {
    // 1, 2, ..., 101: mean 51; sample variance n(n + 1)/12 = 858.5; type-7 percentiles
    // at ranks 5, 50, 95 (from 0) are 6, 51, 96.
    let v: Vec<f64> = (1..=101).map(f64::from).collect();
    let m = Moments::of("x", &v).unwrap();
    assert_eq!(
        (m.mean, m.p5, m.p50, m.p95, m.min, m.max),
        (51.0, 6.0, 51.0, 96.0, 1.0, 101.0)
    );
    assert!((m.sd - 858.5f64.sqrt()).abs() < 1e-12, "{}", m.sd);
    // Interpolated: 0, 10 → p5 = 0.5, p95 = 9.5.
    let m = Moments::of("x", &[10.0, 0.0]).unwrap();
    assert_eq!((m.p5, m.p50, m.p95, m.sd), (0.5, 5.0, 9.5, 50f64.sqrt()));
    // One sample: sd 0.
    assert_eq!(Moments::of("x", &[3.0]).unwrap().sd, 0.0);
    // Non-finite is an error, never a result.
    for bad in [f64::NAN, f64::INFINITY] {
        let e = Moments::of("rise.rms_acceleration", &[1.0, bad]).unwrap_err();
        assert!(format!("{e}").contains("rise.rms_acceleration"), "{e}");
    }
    assert!(Moments::of("x", &[]).is_err());
    // Binomial: 3 of 10 → p = 0.3 with its Wilson interval [0.10779, 0.60322]
    // (hand-computed); 0 of 10 is no point: [0, z²/(10 + z²)] = [0, 0.27753].
    let p = Probability::of(3, 10);
    assert_eq!((p.count, p.p), (3, 0.3));
    assert!(
        (p.lo95 - 0.107_791_3).abs() < 1e-6 && (p.hi95 - 0.603_221_9).abs() < 1e-6,
        "{p:?}"
    );
    let z = Probability::of(0, 10);
    assert!(
        z.lo95 == 0.0 && (z.hi95 - 0.277_532_8).abs() < 1e-6,
        "{z:?}"
    );
}

#[test]
fn the_statistics_measure_the_deviation_from_the_perfect_cam() {
    // An actual cam 2e-3 in larger everywhere (a constant deviation: same slope and
    // curvature) lifts the follower by 2e-3 in. Against the perfect cam's response the
    // low dwell's RMS displacement deviation is then 2e-3 in up to the theoretical
    // cam's own deviation (7e-5 in) and the 0.2 lb more spring force; against the
    // lift the roller rides on it would stay at the theoretical cam's 7e-5 in.
    use camsim::sim::{self, HostDeviation, Nothing, RunSpec};
    use std::sync::Arc;
    let e = 2e-3;
    let mut spec = RunSpec::reference();
    spec.revolutions = 2;
    spec.dofs.horizontal = false;
    let dwell = |spec: &RunSpec| {
        let r = sim::run(spec, &mut Nothing).unwrap();
        sim::period_rows(&spec.design, &r.stats)
            .into_iter()
            .find(|p| p.revolution == 2 && p.period == "dwell_low")
            .unwrap()
            .rms_displacement
            .in_inch()
    };
    let perfect = dwell(&spec);
    assert!(perfect > 0.0 && perfect < 2e-4, "{perfect}");
    let step = 2.0 * std::f64::consts::PI / 36.0;
    spec.profile = Some(Arc::new(HostDeviation::uniform(step, 36, |_| e).unwrap()));
    let shifted = dwell(&spec);
    assert!(
        (shifted - e).abs() < 2.0 * perfect,
        "{shifted} vs {e} ± {perfect}"
    );
}

#[test]
fn ranks_are_a_permutation_that_follows_the_values() {
    // Ties keep the laws' order; larger-is-better reverses.
    assert_eq!(compare::rank(&[3.0, 1.0, 2.0, 1.0], true), vec![4, 1, 3, 2]);
    assert_eq!(
        compare::rank(&[3.0, 1.0, 2.0, 1.0], false),
        vec![1, 3, 2, 4]
    );

    let args = match parse_from(["camsim", "compare", "--quick", "--interval-deg", "30"])
        .unwrap()
        .command
    {
        Command::Compare(a) => a,
        other => panic!("parsed as {other:?}"),
    };
    let r: CompareReport = compare::report(&args).unwrap();
    let n = camsim_core::MotionLaw::ALL.len();
    assert_eq!(r.laws.len(), n);
    for (l, law) in r.laws.iter().zip(camsim_core::MotionLaw::ALL) {
        assert_eq!(l.name, law.name());
    }
    for (col, smaller_better) in RANKED.iter().copied() {
        let mut ranks: Vec<usize> = r.laws.iter().map(|l| l.ranks.get(col).unwrap()).collect();
        ranks.sort_unstable();
        assert_eq!(ranks, (1..=n).collect::<Vec<_>>(), "{col}: a permutation");
        for a in &r.laws {
            for b in &r.laws {
                let (ra, rb) = (a.ranks.get(col).unwrap(), b.ranks.get(col).unwrap());
                let (va, vb) = (a.values.get(col).unwrap(), b.values.get(col).unwrap());
                if ra < rb {
                    let ok = if smaller_better { va <= vb } else { va >= vb };
                    assert!(
                        ok,
                        "{col}: {} rank {ra} ({va}) vs {} rank {rb} ({vb})",
                        a.name, b.name
                    );
                }
            }
        }
    }
    // Overall: every law that holds contact on the theoretical cam before every law that
    // separates, each group ordered by the sum of its ranks.
    let mut overall: Vec<usize> = r.laws.iter().map(|l| l.ranks.overall).collect();
    overall.sort_unstable();
    assert_eq!(overall, (1..=n).collect::<Vec<_>>());
    for a in &r.laws {
        for b in &r.laws {
            if a.ranks.overall < b.ranks.overall {
                let key = |l: &compare::LawStudy| (l.flexibility.jump, l.values.overall);
                assert!(key(a) <= key(b), "overall: {} before {}", a.name, b.name);
            }
        }
    }
    for l in &r.laws {
        // The columns are what §9 defines, recomputed from the per-period values.
        let sum =
            |p: &[compare::LawPeriod]| p.iter().map(|p| p.acc_rms_cycle2.in_inch()).sum::<f64>();
        let f = &l.flexibility;
        assert_eq!(f.sensitivity, sum(&f.per_period));
        assert_eq!(l.actual.cam.sensitivity, sum(&l.actual.cam.per_period));
        assert_eq!(
            l.actual.sensitivity_to_tolerance,
            l.actual.cam.sensitivity - f.sensitivity
        );
        let shock: f64 = f
            .per_period
            .iter()
            .filter(|p| p.period == "rise" || p.period == "return")
            .map(|p| {
                let (one, two) = (p.acc_rms_cycle1.in_inch(), p.acc_rms_cycle2.in_inch());
                (one - two) / one
            })
            .sum();
        assert_eq!(f.shock_index, shock);
        let fmin = f
            .per_period
            .iter()
            .map(|p| p.contact_force_min.in_inch())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(l.values.contact_force_min, fmin);
        assert_eq!(l.values.sensitivity_to_flexibility, f.sensitivity);
        let rank_sum: usize = RANKED.iter().map(|(c, _)| l.ranks.get(c).unwrap()).sum();
        assert_eq!(l.values.overall, rank_sum as f64);
        assert_eq!(
            l.jump_rise,
            l.actual
                .cam
                .per_period
                .iter()
                .any(|p| p.period == "rise" && p.jump)
        );
        assert_eq!(l.actual.profile.intervals, 12);
    }
    // The straight-line law's velocity steps at the ends of the rise and return are
    // infinite accelerations: the follower must leave the cam, at any speed. The
    // cycloidal law's acceleration is continuous and its peak coefficient (2π = 6.28)
    // is below the 4-5-6-7's (7.51), whose return holds contact up to 902 rpm in the
    // reference design: at 800 rpm the cycloidal cam keeps contact.
    let by = |name: &str| r.laws.iter().find(|l| l.name == name).unwrap();
    assert!(by("straight-line").flexibility.jump);
    assert!(!by("cycloidal").flexibility.jump);
    assert!(by("cycloidal").flexibility.contact_force_min.in_inch() > 0.0);
}

/// The counting rule (docs/MODEL.md §3.20): a sample that leaves the model's valid range
/// after the follower separated is a jump (in P(jump), without statistics); one that
/// leaves it with the follower on the cam is not workable (excluded, counted). A study
/// of not-workable samples alone fails; one whose workable samples all jumped and left
/// reports P(jump) = 1.
#[test]
fn left_range_samples_are_jumps_or_not_workable() {
    use camsim::cmd::montecarlo::StudyStats;
    let mut s = StudyStats::default();
    s.add_left_range(3, true, "thrown off");
    s.add_left_range(1, false, "stalled");
    s.add_left_range(2, false, "stalled again");
    assert_eq!(
        (s.left_range_jumps, s.not_workable, s.accounted()),
        (1, 2, 3)
    );
    let sm = s.summary(2).unwrap();
    assert_eq!((sm.jump.count, sm.samples), (1, 0));
    assert_eq!(sm.jump.p, 1.0);
    assert_eq!(sm.not_workable, 2);
    assert_eq!(sm.not_workable_reason.as_deref(), Some("sample 1: stalled"));
    assert!(sm.steps.is_none() && sm.periods.is_empty());
    let mut nw = StudyStats::default();
    nw.add_left_range(0, false, "stalled");
    let e = nw.summary(2).unwrap_err().to_string();
    assert!(
        e.contains("no sample is workable") && e.contains("stalled"),
        "{e}"
    );
}

/// At 1300 rpm every cam jumps and is then thrown into the slide bearing: P(jump) = 1 in
/// text and JSON, the study exits 0. At 1200 rpm five of six do, the sixth jumps with
/// statistics: P(jump) = 6/6, one sample with statistics.
#[test]
fn a_study_whose_cams_jump_out_of_range_reports_p_jump_1_and_exits_0() {
    let argv = |rpm: &'static str, n: &'static str| {
        ["--samples", n, "--rpm", rpm, "--two-level", "0"].to_vec()
    };
    for (rpm, n, left, with_stats) in [("1300", 4u64, 4u64, 0u64), ("1200", 6, 5, 1)] {
        let a = montecarlo_args(&argv(rpm, if n == 4 { "4" } else { "6" }));
        let Outcome::Study(r) = execute(&a, camsim::units::Units::Inch).unwrap() else {
            panic!("not a study")
        };
        let sm = &r.summary;
        assert_eq!((sm.jump.count, sm.jump.p), (n, 1.0), "{rpm}");
        assert_eq!(
            (sm.left_range_jumps, sm.samples, sm.not_workable),
            (left, with_stats, 0)
        );
        let text = camsim::report::Report::text(r.as_ref(), camsim::units::Units::Inch);
        assert!(
            text.contains(&format!(
                "jump anywhere in revolution 2: {n} of {n}, p = 1.0000"
            )) && text.contains(&format!(
                "of which {left} left the model's valid range after the follower separated"
            )),
            "{text}"
        );
        let json: serde_json::Value =
            serde_json::from_str(&camsim::report::Report::json(r.as_ref()).unwrap()).unwrap();
        assert_eq!(json["summary"]["jump"]["count"], n);
        assert_eq!(json["summary"]["left_range_jumps"], left);
        assert_eq!(json["summary"]["not_workable"], 0);
    }
    let mut cli = vec!["camsim", "montecarlo", "--json"];
    cli.extend(argv("1300", "4"));
    assert_eq!(camsim::cli::main_from(cli), 0);
}

/// The same rule under the two-level estimate (the default: at 6 samples every cam is on
/// both models). At 1300 and 1200 rpm every cam jumps on both models, most of them then
/// leave the range: no error, P(jump) = 1 on the reduced model and as the full model's
/// estimate (reduced 1 + correction 0), no disagreement; a cam that left the reduced
/// model's range is a pair without statistics; the counts in text and JSON; exit 0.
#[test]
fn a_two_level_study_whose_cams_jump_out_of_range_reports_p_jump_1() {
    for rpm in ["1300", "1200"] {
        let a = montecarlo_args(&["--samples", "6", "--rpm", rpm]);
        let Outcome::Study(r) = execute(&a, camsim::units::Units::Inch).unwrap() else {
            panic!("not a study")
        };
        let (sm, t) = (&r.summary, r.two_level.as_ref().expect("two-level"));
        assert_eq!((sm.jump.count, sm.jump.p), (6, 1.0), "{rpm}");
        assert!(sm.left_range_jumps > 0 && sm.not_workable == 0, "{rpm}");
        assert_eq!((t.samples, t.full_samples, t.full_not_workable), (6, 6, 0));
        assert_eq!(
            (t.jump.value, t.jump.reduced, t.jump.correction),
            (1.0, 1.0, 0.0)
        );
        assert_eq!(
            (t.disagreements.full_only, t.disagreements.reduced_only),
            (0, 0)
        );
        assert_eq!(t.subsample_full_jump.count, 6);
        assert!(t.jump_only_pairs >= sm.left_range_jumps, "{rpm}");
        let text = camsim::report::Report::text(r.as_ref(), camsim::units::Units::Inch);
        assert!(
            text.contains(&format!(
                "of which {} left a model's valid range after the follower separated",
                t.jump_only_pairs
            )) && text.contains("full-model jump anywhere: p = 1.0000"),
            "{text}"
        );
        let json: serde_json::Value =
            serde_json::from_str(&camsim::report::Report::json(r.as_ref()).unwrap()).unwrap();
        assert_eq!(json["two_level"]["jump"]["value"], 1.0);
        assert_eq!(json["two_level"]["jump_only_pairs"], t.jump_only_pairs);
        assert_eq!(json["two_level"]["full_not_workable"], 0);
        assert_eq!(json["summary"]["left_range_jumps"], sm.left_range_jumps);
    }
    let cli = [
        "camsim",
        "montecarlo",
        "--json",
        "--samples",
        "6",
        "--rpm",
        "1300",
    ];
    assert_eq!(camsim::cli::main_from(cli.to_vec()), 0);
}
