//! Issue 20 (reliability, second pass): each defect of the hostile-user report as a test
//! that failed before its fix. The commands run through `camsim::cli`, what the binary
//! runs: [`camsim::cli::main_from`] for exit codes, [`camsim::cli::execute`] for the
//! refusal's line.

use std::fs;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use camsim::cli;

mod common;
use common::{outcome, s, scratch, CHEAP};

// Point 1 and 4: no write into anything but a regular file; no hang on a FIFO.
#[test]
fn devices_fifos_and_links_to_devices_are_refused_as_outputs_before_anything_runs() {
    let d = scratch("devices");
    let fifo = d.join("fifo");
    assert!(std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let link = d.join("disk");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let t0 = Instant::now();
    for (target, kind) in [
        ("/dev/zero", "a character device"),
        (s(&fifo), "a FIFO"),
        (s(&link), "a character device"),
    ] {
        for force in [false, true] {
            let mut args = vec!["run", "--revolutions", "1", "--csv", target];
            if force {
                args.push("--force");
            }
            let e = outcome(&args);
            assert_eq!(
                e,
                format!("--csv {target}: is {kind}, not a regular file: outputs go to a regular file or a new name (/dev/stdout and /dev/null are allowed)")
            );
        }
    }
    // Refused at once (the FIFO is never opened: no reader, no hang, no simulation).
    assert!(t0.elapsed() < Duration::from_secs(5), "{:?}", t0.elapsed());
    assert_eq!(cli::main_from(["camsim", "run", "--csv", s(&fifo)]), 1);
    fs::remove_dir_all(&d).unwrap();
}

// Point 11: --force never replaces the run's own input.
#[test]
fn an_output_never_replaces_the_scene_or_the_measured_input() {
    let d = scratch("inputs");
    let scene = d.join("scene.toml");
    fs::write(&scene, "[run]\nrevolutions = 1\n").unwrap();
    let e = outcome(&["run", s(&scene), "--csv", s(&scene), "--force"]);
    assert!(
        e.starts_with(&format!("--csv {}: is the input scene file", s(&scene))),
        "{e}"
    );
    assert_eq!(
        fs::read_to_string(&scene).unwrap(),
        "[run]\nrevolutions = 1\n"
    );
    let measured = d.join("m.csv");
    let rows: String = (0..36).map(|k| format!("{},0\n", k * 10)).collect();
    fs::write(&measured, format!("angle_deg,deviation_in\n{rows}")).unwrap();
    let e = outcome(&[
        "run",
        "--measured",
        s(&measured),
        "--csv",
        s(&measured),
        "--force",
    ]);
    assert!(e.contains("is the input --measured"), "{e}");
    assert!(fs::read_to_string(&measured)
        .unwrap()
        .starts_with("angle_deg"));
    // Every command that writes files: montecarlo --out, and a plot directory holding
    // the scene under a plot's name (compare, montecarlo --plot), refused before any run.
    let text = "[run]\nrevolutions = 1\n";
    let e = outcome(&[
        "montecarlo",
        s(&scene),
        "--samples",
        "2",
        "--out",
        s(&scene),
        "--force",
    ]);
    assert!(
        e.starts_with(&format!("--out {}: is the input scene file", s(&scene))),
        "{e}"
    );
    let plots = d.join("plots");
    fs::create_dir_all(&plots).unwrap();
    for (cmd, name) in [
        ("compare", "rankings.png"),
        ("montecarlo", "histograms.png"),
    ] {
        let inside = plots.join(name);
        fs::write(&inside, text).unwrap();
        let mut args = vec![cmd, s(&inside), "--plot", s(&plots), "--force"];
        if cmd == "montecarlo" {
            args.extend(["--samples", "2"]);
        }
        let e = outcome(&args);
        assert!(
            e.contains(&format!("{}: is the input scene file", s(&inside))),
            "{cmd}: {e}"
        );
        assert_eq!(fs::read_to_string(&inside).unwrap(), text);
    }
    assert_eq!(fs::read_to_string(&scene).unwrap(), text);
    fs::remove_dir_all(&d).unwrap();
}

// Point 2: one size cap per input kind, checked while reading.
#[test]
fn measured_inputs_are_read_with_one_cap_and_name_the_line_of_a_bad_byte() {
    let cap = camsim::measured::MAX_MEASURED_BYTES;
    // /dev/zero: refused after at most the cap, not read without end.
    let t0 = Instant::now();
    let e = outcome(&["run", "--measured", "/dev/zero"]);
    assert_eq!(
        e,
        format!("--measured /dev/zero: the measured profile is larger than its limit of {cap} bytes (read no further)")
    );
    assert!(t0.elapsed() < Duration::from_secs(10));
    // A file over the cap: run and predict refuse it alike (neither says "not a scene").
    let d = scratch("caps");
    let big = d.join("big.csv");
    let mut text = String::from("angle_deg,deviation_in\n");
    while (text.len() as u64) <= cap {
        text.push_str("# a long comment line to fill the file past the cap\n");
    }
    fs::write(&big, &text).unwrap();
    for cmd in ["run", "predict"] {
        let e = outcome(&[cmd, "--measured", s(&big)]);
        // Both name the option and the file, in the same words.
        assert_eq!(
            e,
            format!(
                "--measured {}: the measured profile is larger than its limit of {cap} bytes (read no further)",
                big.display()
            ),
            "{cmd}"
        );
    }
    // Not UTF-8: the line is named by run as by predict.
    let bin = d.join("bin.csv");
    fs::write(&bin, b"angle_deg,deviation_in\n0,0\n\xff\xfe\n").unwrap();
    let e = outcome(&["run", "--measured", s(&bin)]);
    assert!(
        e.contains("line 3: the measured profile is not UTF-8"),
        "{e}"
    );
    // The firmware log of predict --check-log is capped too.
    let e = outcome(&["predict", "--f32", "--check-log", "/dev/zero"]);
    assert!(e.contains("larger than its limit of 16000000 bytes"), "{e}");
    fs::remove_dir_all(&d).unwrap();
}

// Point 8: what a measured radius profile implies is held to the lift form's rules,
// and no report carries a stress or force no steel cam survives.
#[test]
fn implausible_radius_profiles_are_refused() {
    let design = camsim_core::Design::<f64>::reference();
    let radius = |f: &dyn Fn(f64, usize) -> f64, n: usize| {
        let mut t = String::from("angle_deg,radius_in\n");
        for k in 0..n {
            let a = k as f64 * 360.0 / n as f64;
            t += &format!("{a},{}\n", f(a, k));
        }
        camsim::measured::parse(&t).unwrap()
    };
    // A 0.5 in deep, 20 deg wide notch in a 2.0 in radius: the roller bridges it.
    let notch = radius(
        &|a, _| {
            if (100.0..120.0).contains(&a) {
                1.5
            } else {
                2.0
            }
        },
        3600,
    );
    let e = notch.deviation(&design).unwrap_err();
    assert!(e.contains("convex cam surface radius"), "{e}");
    // 0.01 in everywhere: a lift of -1.49 in (a lift_in column is refused below -0.1 in).
    let tiny = radius(&|_, _| 0.01, 360);
    let e = tiny.deviation(&design).unwrap_err();
    assert!(e.contains("implies a lift of -1.4900 in"), "{e}");
    assert!(e.contains("[-0.1, 100]"), "{e}");
    // 2.0 +- 1e-4 in alternating on 3600 rows: a ridge every 0.2 deg.
    let alt = radius(&|_, k| if k % 2 == 1 { 2.0001 } else { 1.9999 }, 3600);
    let e = alt.deviation(&design).unwrap_err();
    assert!(e.contains("convex cam surface radius"), "{e}");
    // A smooth radius profile that is not the scene's cam (a circle of the base
    // radius: lift 0 everywhere, 1.5 in below the program's rise) is refused as
    // another cam (issue 18: a gap beyond a deviation's 0.1 in).
    let circle = radius(&|_, _| 1.5, 360);
    let e = circle.deviation(&design).unwrap_err();
    assert!(
        e.contains("departs from the scene's program lift by 1.5000 in"),
        "{e}"
    );
}

#[test]
fn reports_with_a_stress_or_force_beyond_steel_are_refused() {
    use serde_json::json;
    // A field not named contact_* (camsim contact's calculator) is not held to it.
    let ok = json!({"per_period": [{"contact_force_max": 225.6, "contact_stress_max": 1.2e5}],
                    "max_stress_psi": 1e7});
    camsim::report::ensure_physical(&ok).unwrap();
    let bad = json!({"per_period": [
        {"contact_force_max": 225.6, "contact_stress_max": 1.2e5},
        {"contact_force_max": 300.0, "contact_stress_max": 7.5e8}]});
    let e = format!("{:#}", camsim::report::ensure_physical(&bad).unwrap_err());
    assert!(
        e.contains("per_period[1].contact_stress_max = 7.500e8 psi, beyond 1e6 psi"),
        "{e}"
    );
    let force = json!({"stats": {"contact_force_max": {"mean": 2e6}}});
    let e = format!("{:#}", camsim::report::ensure_physical(&force).unwrap_err());
    assert!(
        e.contains("stats.contact_force_max.mean = 2.000e6 lb"),
        "{e}"
    );
}

// Point 9: the undercut check finds a short segment's curvature extreme.
#[test]
fn a_scene_with_a_short_steep_rise_is_refused_as_undercut() {
    for width in [5.0, 0.5, 0.1, 0.01] {
        let text = format!(
            "[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 0.0\nend_deg = 30.0\nlift_in = 0.0\n\n\
             [[design.program.segment]]\nkind = \"rise\"\nlaw = \"cycloidal\"\nstart_deg = 30.0\nend_deg = {}\nlift_in = 1.5\n\n\
             [[design.program.segment]]\nkind = \"dwell\"\nstart_deg = {}\nend_deg = 210.0\nlift_in = 0.0\n\n\
             [[design.program.segment]]\nkind = \"return\"\nlaw = \"cycloidal\"\nstart_deg = 210.0\nend_deg = 360.0\nlift_in = 1.5\n",
            30.0 + width,
            30.0 + width
        );
        let e = camsim::scene::parse(&text).unwrap_err();
        let e = format!("{e:#}");
        assert!(e.contains("undercut"), "{width} deg: {e}");
    }
}

// Point 10: tolerances have a range, and the refusal names the option.
#[test]
fn tolerances_are_bounded_and_named() {
    for (opt, v) in [
        ("--roller-tolerance", "1"),
        ("--cam-tolerance", "1e300"),
        ("--eccentricity-tolerance", "0.2"),
    ] {
        let e = outcome(&["run", "--actual", opt, v]);
        assert_eq!(
            e,
            format!("usage: invalid value '{v}' for '{opt} <IN>': must be at most 0.1 in (40 times a loose machining tolerance: a larger error is a different cam)")
        );
        assert_eq!(cli::main_from(["camsim", "run", "--actual", opt, v]), 2);
    }
    let argv = ["camsim", "run", "--actual", "--roller-tolerance", "0.1"];
    assert!(cli::parse_from(argv).is_ok());
}

// Point 11: usage errors exit 2 and name the option; bounds that are documented hold.
#[test]
fn usage_errors_exit_2_and_name_the_option() {
    for args in [
        &["compare", "--rpm", "0.5"][..],
        &["tolerance-study", "--rpm", "0.5"],
        &["scene"],
        &["predict", "--check-log", "x.log"],
        &["contact", "--force", "1e7"],
        &["contact", "--force", "5e-324"],
    ] {
        let argv = std::iter::once("camsim").chain(args.iter().copied());
        assert_eq!(cli::main_from(argv), 2, "{args:?}");
    }
    let e = outcome(&["compare", "--rpm", "0.5"]);
    assert!(e.contains("'--rpm <RPM>'"), "{e}");
    let e = outcome(&["contact", "--force", "5e-324"]);
    assert!(e.contains("must be at least 1e-6 lb"), "{e}");
    assert!(!e.contains("beyond Hertz"), "{e}");
    // The largest force the message states is itself accepted and computed.
    let max = camsim::args::max_force_lb();
    assert!(outcome(&["contact", "--force", "1e7"]).contains(&format!("{max:.3e}")));
    let r = camsim::cmd::contact::compute(max).unwrap();
    camsim::report::ensure_finite(&r).unwrap();
    // Independent: the Hertz width grows as sqrt(F), and at the bound it is at most
    // the roller's 0.75 in diameter, within 1 % of it.
    assert!(
        r.contact_width_in.in_inch() <= 0.75 && r.contact_width_in.in_inch() > 0.75 * 0.99,
        "{r:?}"
    );
}

// Issue 18: a usage error found after parsing exits 2 as clap's do, and names the options
// the user gave; a flag that would change nothing is refused, not ignored.
#[test]
fn usage_errors_after_parsing_exit_2_and_name_what_was_given() {
    for (args, says) in [
        (
            &["run", "--cam-tolerance", "0.0005"][..],
            "--cam-tolerance 0.0005 shapes an actual cam: add --actual",
        ),
        (
            &["run", "--seed", "3", "--normal", "polar"],
            "--seed 3, --normal polar shape an actual cam",
        ),
        (
            &["profile", "--waviness-fpr", "39"],
            "--waviness-fpr 39 shapes an actual cam",
        ),
        (
            &["jump-speed", "--samples", "4"],
            "--samples 4 counts actual cams: add --actual",
        ),
        (
            &["compare", "--actual"],
            "compare always runs actual cams: drop --actual",
        ),
        (
            &["sensitivity", "--actual"],
            "sensitivity always runs actual cams: drop --actual",
        ),
        (
            &["montecarlo", "--samples", "2", "--actual"],
            "montecarlo always runs actual cams: drop --actual",
        ),
    ] {
        let argv = std::iter::once("camsim").chain(args.iter().copied());
        assert_eq!(cli::main_from(argv), 2, "{args:?}");
        let e = outcome(args);
        assert!(e.contains(says), "{args:?}: {e}");
    }
    // The same options with --actual are not usage errors (they parse and are checked).
    let argv = ["camsim", "run", "--actual", "--cam-tolerance", "0.0005"];
    assert!(cli::parse_from(argv).is_ok());
    // --actual is gone from the help of the commands that refuse it.
    let cmd = cli::command();
    for name in ["compare", "sensitivity", "montecarlo"] {
        let sub = cmd.find_subcommand(name).unwrap();
        let actual = sub
            .get_arguments()
            .find(|a| a.get_id() == "actual")
            .unwrap();
        assert!(actual.is_hide_set(), "{name}");
    }
    let run = cmd.find_subcommand("run").unwrap();
    let actual = run
        .get_arguments()
        .find(|a| a.get_id() == "actual")
        .unwrap();
    assert!(!actual.is_hide_set());
}

// Issue 18 point 7: `models` (the reduced models' adequacy) is no longer one letter from
// `scene`; `scenes` still runs it, hidden, with a note.
#[test]
fn scenes_is_a_hidden_alias_of_models() {
    let c = cli::parse_from(["camsim", "scenes", "--quick", "--json"]).unwrap();
    match c.command {
        cli::Command::Scenes(a) => assert!(a.quick && a.json),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        cli::parse_from(["camsim", "models", "--quick"])
            .unwrap()
            .command,
        cli::Command::Models(_)
    ));
    let cmd = cli::command();
    let listed: Vec<&str> = cmd
        .get_subcommands()
        .filter(|c| !c.is_hide_set())
        .map(|c| c.get_name())
        .collect();
    assert!(listed.contains(&"models") && listed.contains(&"scene"));
    assert!(!listed.contains(&"scenes"));
    assert!(cli::SCENES_RENAMED.contains("`scenes` is now `models`"));
    // A bare `camsim` lists the commands without the hidden one.
    let e = outcome(&[]);
    assert!(e.contains("models") && !e.contains("scenes"), "{e}");
}

#[test]
fn control_characters_of_an_input_name_are_escaped() {
    let e = outcome(&["run", "--measured", "x\u{1b}[2J.csv"]);
    assert!(!e.contains('\u{1b}'), "{e:?}");
    assert!(e.contains("x\\u{1b}[2J.csv"), "{e}");
    assert_eq!(cli::one_line("a\nb\rc\0"), "a b\\rc\\0");
}

#[test]
fn a_wide_jump_speed_bracket_is_stated_as_a_range() {
    use camsim::cmd::jump_speed::{render_text, JumpSpeed, JumpSpeedReport};
    let r = JumpSpeed {
        jump_rpm: Some(1600.0),
        no_jump_rpm: 800.0,
        simulations: 5,
    };
    let text = render_text(&JumpSpeedReport::new(&r, 800.0, 10_000.0, 1.0));
    assert!(
        text.contains("margin between +0.0 and +800.0 rpm (+0.0 % to +100.0 %"),
        "{text}"
    );
    assert!(text.contains("contact holds at 800.0 rpm: the onset lies between"));
    // A narrow bracket keeps the single margin.
    let r = JumpSpeed {
        jump_rpm: Some(901.8),
        no_jump_rpm: 901.5,
        simulations: 12,
    };
    let text = render_text(&JumpSpeedReport::new(&r, 800.0, 0.5, 1.0));
    assert!(text.contains("margin +101.8 rpm (+12.7 %)"), "{text}");
}

/// `camsim montecarlo ARGS` parsed as the binary parses it.
fn montecarlo(args: &[&str]) -> camsim::cmd::montecarlo::Args {
    let argv = ["camsim", "montecarlo"].iter().chain(args).copied();
    match cli::parse_from(argv).unwrap().command {
        cli::Command::Montecarlo(a) => a,
        other => panic!("{other:?}"),
    }
}

// Point 6: --out fails before the first sample, not after the study.
#[test]
fn a_bad_out_name_fails_before_the_first_sample() {
    let d = scratch("mc-name");
    // 257 bytes: over NAME_MAX (255 bytes, a legal name, is written: reliability_io.rs).
    let long = d.join(format!("{}.json", "n".repeat(252)));
    let mut argv = vec!["--samples", "2000", "--threads", "1", "--out", s(&long)];
    argv.extend_from_slice(&CHEAP);
    let t0 = Instant::now();
    let e = camsim::cmd::montecarlo::execute(&montecarlo(&argv), camsim::units::Units::Inch)
        .unwrap_err();
    let e = format!("{e:#}");
    assert!(
        e.contains("the file name is 257 bytes, over the 255 a file system allows"),
        "{e}"
    );
    // 2000 samples take minutes; the refusal comes before the first.
    assert!(t0.elapsed() < Duration::from_secs(20), "{:?}", t0.elapsed());
    fs::remove_dir_all(&d).unwrap();
}

// Point 3: memory no longer limits a study (its statistics stream); one that would take
// days is refused after its first sample, naming the way out.
#[test]
fn a_study_past_the_time_limit_is_refused_after_one_sample() {
    let mut argv = vec!["--samples", "100000000", "--threads", "1"];
    argv.extend_from_slice(&CHEAP);
    let t0 = Instant::now();
    let e = camsim::cmd::montecarlo::execute(&montecarlo(&argv), camsim::units::Units::Inch)
        .unwrap_err();
    let e = format!("{e:#}");
    // At least 1 ms a sample on one thread: 1e8 samples are over a day.
    assert!(
        e.contains("--samples 100000000: would take about") && e.contains("24.0 h limit"),
        "{e}"
    );
    assert!(e.contains("--allow-long") && e.contains("--shard"), "{e}");
    assert!(t0.elapsed() < Duration::from_secs(20));
}

// Point 7: an edited shard does not merge silently.
#[test]
fn edited_or_insane_shards_are_refused_at_merge() {
    use camsim::cmd::montecarlo::{merge, read_shard, OutputArgs, COLUMNS};
    let d = scratch("shards");
    let files: Vec<PathBuf> = (1..=3).map(|k| d.join(format!("s{k}.json"))).collect();
    for (k, f) in files.iter().enumerate() {
        let shard = format!("{}/3", k + 1);
        let mut argv = vec!["--samples", "7", "--threads", "1", "--shard", &shard];
        argv.extend_from_slice(&["--out", s(f)]);
        argv.extend_from_slice(&CHEAP);
        camsim::cmd::montecarlo::execute(&montecarlo(&argv), camsim::units::Units::Inch).unwrap();
    }
    assert!(merge(&files, &OutputArgs::default(), camsim::units::Units::Inch).is_ok());
    let merge_err = |edited: &ShardEdit| -> String {
        let target = d.join("edited.json");
        let mut file = read_shard(&files[1]).unwrap();
        let resign = edited(&mut file);
        if resign {
            file.digest = camsim::shard::digest(&file).unwrap();
        }
        fs::write(&target, serde_json::to_string(&file).unwrap()).unwrap();
        let e = merge(
            &[files[0].clone(), target.clone(), files[2].clone()],
            &OutputArgs::default(),
            camsim::units::Units::Inch,
        )
        .unwrap_err();
        format!("{e:#}")
    };
    let col = |n: &str| COLUMNS.iter().position(|c| *c == n).unwrap();
    // One number changed by hand (the digest left as written): a histogram count.
    let (fmin, fmax) = (col("contact_force_min"), col("contact_force_max"));
    let e = merge_err(&move |f| {
        let text = serde_json::to_string(&f.stats.periods[0].columns[fmin]).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        let mut v = v;
        let c = v["bins"][0][1].as_u64().unwrap();
        v["bins"][0][1] = (c + 1).into();
        v["n"] = (v["n"].as_u64().unwrap() + 1).into();
        f.stats.periods[0].columns[fmin] = serde_json::from_value(v).unwrap();
        false
    });
    assert!(e.contains("digest does not match"), "{e}");
    // A stream as a run writes it, with its values moved by `by` (min, max, bins).
    fn shifted(s: &camsim::stats::stream::Stream, by: f64) -> camsim::stats::stream::Stream {
        let mut out = camsim::stats::stream::Stream::default();
        let (lo, hi) = s.range().unwrap();
        for k in 0..s.count() {
            let x = if k == 0 { lo } else { hi };
            out.add("x", x + by).unwrap();
        }
        out
    }
    let cases: [(&ShardEdit, &str); 5] = [
        (
            &|f| {
                let s = shifted(&f.stats.rms_deviation_in, -5.0);
                f.stats.rms_deviation_in = s;
                true
            },
            "rms_deviation_in: minimum -4.99",
        ),
        (
            &move |f| {
                let p = &mut f.stats.periods[0];
                let top = p.columns[fmax].range().unwrap().1;
                let lo = p.columns[fmin].range().unwrap().0;
                p.columns[fmin] = shifted(&p.columns[fmin], top + 1.0 - lo);
                true
            },
            "the minimum must not exceed",
        ),
        (
            &|f| {
                let lo = f.stats.steps.range().unwrap().0;
                f.stats.steps = shifted(&f.stats.steps, -lo);
                true
            },
            "steps = 0",
        ),
        (
            &|f| {
                f.shard.index = 0;
                f.shard.count = 0;
                true
            },
            "must be K/N with 1 <= K <= N",
        ),
        (
            &|f| {
                f.shard.index = 5;
                f.shard.count = 3;
                true
            },
            "must be K/N with 1 <= K <= N",
        ),
    ];
    for (edit, want) in cases {
        let e = merge_err(edit);
        assert!(e.contains(want), "{want}: {e}");
    }
    fs::remove_dir_all(&d).unwrap();
}

type ShardEdit = dyn Fn(&mut camsim::cmd::montecarlo::ShardFile) -> bool;
