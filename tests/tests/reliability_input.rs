//! Issue 33 (reliability, third pass), the input defects: each as a test that failed on
//! 6b065a3. The commands run through `camsim::cli` as the binary runs them:
//! [`camsim::cli::bare_inch_number`] for the unit rule under `--units si`, the parse and
//! [`camsim::cli::execute`] for a refusal's line.

use camsim::cli;

mod common;
use common::outcome;

/// The refusal of a bare number under `--units si`, if any.
fn si_bare(args: &[&str]) -> Option<String> {
    let argv: Vec<std::ffi::OsString> = std::iter::once("camsim")
        .chain(args.iter().copied())
        .map(Into::into)
        .collect();
    cli::bare_inch_number(&argv)
}

// Defect 7: stress in psi or MPa with a range; the lengths and the spring search's
// resolution take their unit.
#[test]
fn stress_and_length_options_take_their_unit_and_stress_has_a_range() {
    // A psi number under --units si is refused, not read as 150 000 MPa.
    let e = si_bare(&["--units", "si", "run", "--allowable-stress", "150000"]).unwrap();
    assert!(
        e.contains("--allowable-stress 150000") && e.contains("150000MPa"),
        "{e}"
    );
    // 1034 MPa and 149 969 psi (1034 / 0.0068947572931783...) are one allowable.
    let parse = |v: &str| {
        let c = cli::parse_from(["camsim", "run", "--allowable-stress", v]).unwrap();
        let cli::Command::Run(a) = c.command else {
            panic!("not run")
        };
        a.verdict.allowable_stress.unwrap()
    };
    let psi_per_mpa = 25.4 * 25.4 / 4.448_221_615_260_5;
    assert!((parse("1034MPa") - 1034.0 * psi_per_mpa).abs() < 1e-9);
    assert_eq!(parse("150000psi"), 150_000.0);
    // Far outside any cam material's endurance: refused with the range.
    for bad in ["0.001", "1e9", "1e6MPa", "-5", "nan"] {
        let e = outcome(&["run", "--allowable-stress", bad]);
        assert!(
            e.contains("--allowable-stress") && e.contains("[1000, 1000000] psi"),
            "{bad}: {e}"
        );
    }
    // The lengths of profile and the resolution of design spring take their unit.
    for argv in [
        &["profile", "--cutter-radius", "12.7mm"][..],
        &["profile", "--chord-error", "0.002mm"],
        &["design", "spring", "--resolution", "1N/mm"],
    ] {
        let c = cli::parse_from(std::iter::once("camsim").chain(argv.iter().copied()));
        assert!(c.is_ok(), "{argv:?}: {:?}", c.err().map(|e| e.to_string()));
        let mut si = vec!["--units", "si"];
        si.extend_from_slice(argv);
        assert_eq!(si_bare(&si), None, "{si:?}");
        // Without the unit under si: refused naming the option.
        si.pop();
        si.push("1");
        let e = si_bare(&si).unwrap();
        assert!(
            e.starts_with(&format!("{} 1: with --units si", argv[argv.len() - 2])),
            "{e}"
        );
    }
    let c = cli::parse_from(["camsim", "profile", "--cutter-radius", "12.7mm"]).unwrap();
    let cli::Command::Profile(a) = c.command else {
        panic!("not profile")
    };
    assert_eq!(a.cutter_radius, Some(0.5));
}

// Defect 10: a negative value reaches the option's own rule, and the message names the
// option (not clap's "unexpected argument '-1' found").
#[test]
fn negative_values_reach_the_options_rule() {
    for (argv, rule) in [
        (
            &["design", "tolerance", "--waviness-fpr", "-1"][..],
            "--waviness-fpr",
        ),
        (&["design", "spring", "--actual", "--seed", "-1"], "--seed"),
        (&["waviness", "--seeds", "1,-1"], "--seeds"),
        (&["tolerance-study", "--seed", "-1"], "--seed"),
        (&["montecarlo", "--samples", "-3"], "--samples"),
        (
            &[
                "montecarlo",
                "--samples",
                "2",
                "--out",
                "x",
                "--shard",
                "-1/2",
            ],
            "--shard",
        ),
        (&["sweep", "--rpm", "-100:100:3"], "--rpm"),
        (&["sweep", "--threads", "-2"], "--threads"),
    ] {
        let e = outcome(argv);
        assert!(
            e.starts_with("usage: invalid value '-") && e.contains(rule),
            "{argv:?}: {e}"
        );
        assert!(!e.contains("unexpected argument"), "{argv:?}: {e}");
    }
    // The rules say what they take.
    let e = outcome(&["design", "spring", "--actual", "--seed", "-1"]);
    assert!(
        e.contains("whole number from 0 to 18446744073709551615"),
        "{e}"
    );
    let e = outcome(&["sweep", "--rpm", "-100:100:3"]);
    assert!(e.contains("FROM -100: must lie in [1, 10000] rpm"), "{e}");
}

// Defect 3: a --p-max no study within the sample limit can show is refused before any
// work, naming the smallest p the limit allows; that p is itself accepted.
#[test]
fn an_impossible_p_max_is_refused_naming_the_smallest_it_allows() {
    for argv in [
        &["design", "tolerance", "--p-max", "1e-9"][..],
        &["design", "speed", "--p-max", "1e-12"],
        &["design", "spring", "--actual", "--p-max", "1e-12"],
    ] {
        let e = outcome(argv);
        assert!(
            e.contains("over the sample limit of a study")
                && e.contains("the smallest --p-max it allows is"),
            "{argv:?}: {e}"
        );
    }
    let e = outcome(&["design", "tolerance", "--p-max", "1e-9"]);
    let p: f64 = e
        .rsplit("allows is ")
        .next()
        .unwrap()
        .trim_end_matches(')')
        .parse()
        .unwrap();
    // Independently: the Wilson upper 95 % bound with no jump in n cams is
    // z^2 / (n + z^2), z = 1.959963984540054; at n = 1e6 it is 3.8415e-6.
    let z2 = 1.959_963_984_540_054_f64.powi(2);
    let bound = z2 / (1e6 + z2);
    assert!(p >= bound && p < bound * 1.01, "{p} vs {bound}");
    // The p it names needs at most the limit's cams, the same limit as --samples.
    assert!(camsim::cmd::design::samples_for(p) <= camsim::study_limits::MAX_STUDY_SAMPLES);
    assert!(outcome(&["design", "tolerance", "--samples", "1000001"]).contains("1 to 1000000"));
}

/// Every command's long help, depth first, with its path (`camsim design spring`).
fn helps(cmd: &mut clap::Command, path: &str, out: &mut Vec<(String, String)>) {
    let path = format!("{path} {}", cmd.get_name()).trim().to_string();
    out.push((path.clone(), cmd.render_long_help().to_string()));
    for sub in cmd.get_subcommands_mut() {
        helps(sub, &path, out);
    }
}

// Issue 30 point 5: each command's summary names its subcommands; no rustdoc link text
// in any help; --units explained once, at the top, with one line in each command.
#[test]
fn help_names_subcommands_has_no_rustdoc_links_and_explains_units_once() {
    let mut top = cli::command();
    top.build();
    let mut all = Vec::new();
    helps(&mut top, "", &mut all);
    assert!(all.len() > 20, "{}", all.len());
    for (path, text) in &all {
        assert!(!text.contains("[`"), "{path}: rustdoc link text in help");
        if path != "camsim" {
            assert!(
                !text.contains("Units (--units"),
                "{path}: --units explained again"
            );
            if text.contains("--units <FAMILY>") {
                let line = text
                    .lines()
                    .skip_while(|l| !l.contains("--units <FAMILY>"))
                    .nth(1)
                    .unwrap();
                assert!(line.contains("see `camsim --help`"), "{path}: {line}");
            }
        }
    }
    let top_help = &all[0].1;
    assert_eq!(top_help.matches("Units (--units").count(), 1);
    let design = top.find_subcommand("design").unwrap();
    let about = design.get_about().unwrap().to_string();
    for sub in design.get_subcommands().filter(|s| s.get_name() != "help") {
        assert!(
            about.contains(&format!("`design {}`", sub.get_name())),
            "{about}"
        );
    }
    let mc = top.find_subcommand("montecarlo").unwrap();
    let about = mc.get_about().unwrap().to_string();
    assert!(about.contains("`montecarlo merge`"), "{about}");
}

// Defect 4: a weak spring (5 lb/in) leaves the follower off the cam at every grid speed,
// so no timing point is crossed: predict refuses, naming the first row and point, where
// on 6b065a3 it exited 0 with NaN in its table and null in its JSON.
#[test]
fn predict_refuses_a_timing_point_never_crossed() {
    let scene = std::env::temp_dir().join(format!("camsim-weak-{}.toml", std::process::id()));
    std::fs::write(&scene, "[design]\nspring_rate_lb_per_in = 5\n").unwrap();
    let e = outcome(&["predict", "--json", "--scene", scene.to_str().unwrap()]);
    // Its force speaks the output's family: 4 decimals of a pound, 3 of a newton.
    let si = outcome(&["predict", "--units", "si", scene.to_str().unwrap()]);
    let _ = std::fs::remove_file(&scene);
    assert!(
        e.starts_with("not reached: at 300.0 rpm") && e.contains("rise 10 % lift point"),
        "{e}"
    );
    assert!(e.contains("smallest contact force 0.0000 lb)"), "{e}");
    assert!(si.contains("smallest contact force 0.000 N)"), "{si}");
}

// Defect 11: an absurd --tolerance-factor is refused naming that option and its limit
// (6b065a3 ran the search and reported `--waviness-fpr 8` and "the profiles with 4
// points"): VI.1's largest tolerance, 0.001 in, times the factor must stay within the
// tolerances' own limit of 0.1 in, so at most 100.
#[test]
fn an_absurd_tolerance_factor_is_refused_naming_it() {
    let base = ["design", "tolerance", "--waviness", "--tolerance-factor"];
    for bad in ["1e300", "100.5"] {
        let argv = std::iter::once("camsim").chain(base).chain([bad]);
        let e = cli::usage_message(&cli::parse_from(argv).unwrap_err());
        assert!(
            e.contains(&format!("'{bad}' for '--tolerance-factor")) && e.contains("at most 100"),
            "{e}"
        );
    }
    let argv = std::iter::once("camsim").chain(base).chain(["100"]);
    assert!(cli::parse_from(argv).is_ok());
}

// Defect 11: a 10 000-deep TOML header is refused with its line (6b065a3: "recursion
// limit" alone); a 900 kB unknown key is quoted once, cut (6b065a3 echoed it twice, a
// 1.8 MB error line).
#[test]
fn deep_and_huge_keys_give_short_errors_with_a_line() {
    let d = common::scratch("deep-keys");
    let deep = d.join("deep.toml");
    let header = vec!["a"; 10_000].join(".");
    std::fs::write(&deep, format!("# a scene\n\n[{header}]\nx = 1\n")).unwrap();
    let e = outcome(&["run", "--revolutions", "1", deep.to_str().unwrap()]);
    assert!(
        e.contains("deep.toml: line 3: nested 10000 levels deep") && e.len() < 400,
        "{e}"
    );
    let long = d.join("long.toml");
    let key = "k".repeat(900_000);
    std::fs::write(&long, format!("{key} = 1\n")).unwrap();
    let e = outcome(&["run", "--revolutions", "1", long.to_str().unwrap()]);
    assert!(
        e.len() < 600,
        "{} bytes: {}",
        e.len(),
        &e[..600.min(e.len())]
    );
    assert!(
        e.contains("line 1, column 1: ")
            && e.contains(&format!(
                "{}…: unknown field (900000 characters long)",
                "k".repeat(200)
            )),
        "{e}"
    );
    assert_eq!(e.matches("kkkk").count(), 50, "the key quoted once: {e}");
}
