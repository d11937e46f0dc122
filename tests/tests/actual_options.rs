//! One argument group for the actual cams (issue 31): montecarlo, `design spring
//! --actual`, `design speed`, `design tolerance`, `sweep --actual` and `jump-speed
//! --actual` take the same tolerance, waviness and profile-method options, and each
//! option given reaches the cams the command reports on (its JSON's `profile` and
//! `seed`).

use camsim::cli::{parse_from, Command};
use camsim::cmd::design::What;
use camsim::report::Report;
use serde_json::Value;

/// Each command in its cheapest form that still runs actual cams.
const COMMANDS: [&[&str]; 6] = [
    &["montecarlo", "--samples", "1", "--two-level", "0"],
    // At 300 rpm: the criteria's rough cam (FPR about 140) jumps at 800 rpm on every
    // spring up to --max-rate.
    &[
        "design",
        "spring",
        "--actual",
        "--quick",
        "--samples",
        "1",
        "--p-max",
        "0.9",
        "--rpm",
        "300",
    ],
    &[
        "design",
        "speed",
        "--quick",
        "--samples",
        "1",
        "--p-max",
        "0.9",
    ],
    &[
        "design",
        "tolerance",
        "--quick",
        "--samples",
        "1",
        "--p-max",
        "0.9",
    ],
    &["sweep", "--rpm", "700:800:2", "--actual", "--samples", "1"],
    &[
        "jump-speed",
        "--actual",
        "--samples",
        "1",
        "--max-rpm",
        "900",
        "--resolution",
        "400",
        "--follower",
        "quasi-static-cantilever",
        "--rtol",
        "1e-4",
    ],
];

/// Every option of the group, at a value other than its default.
const OPTIONS: [&[&str]; 9] = [
    &["--cam-tolerance", "0.0003"],
    &["--roller-tolerance", "0.00005"],
    &["--eccentricity-tolerance", "0.0005"],
    &["--waviness-fpr", "39"],
    &["--interval-deg", "5"],
    &["--interval", "criteria"],
    &["--seed", "3"],
    &["--profile-method", "thesis"],
    &["--normal", "polar"],
];

/// `design tolerance` searches the cam tolerance and sets the interval from the
/// waviness: these it refuses, by name.
const DESIGN_TOLERANCE_REFUSES: [&str; 3] = ["--cam-tolerance", "--interval-deg", "--interval"];

/// The command's report as JSON (what `--json` prints).
fn json_of(argv: &[&str]) -> anyhow::Result<Value> {
    let cli = parse_from(std::iter::once("camsim").chain(argv.iter().copied()))
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let text = match cli.command {
        Command::Montecarlo(a) => {
            match camsim::cmd::montecarlo::execute(&a, camsim::units::Units::Inch)? {
                camsim::cmd::montecarlo::Outcome::Study(r) => r.json()?,
                camsim::cmd::montecarlo::Outcome::Shard(_) => panic!("a shard"),
            }
        }
        Command::Design(d) => match d.what {
            What::Spring(a) => {
                camsim::cmd::design::spring(&a, camsim::units::Units::Inch)?.json()?
            }
            What::Speed(a) => {
                camsim::cmd::design::mc_search(&a, true, camsim::units::Units::Inch)?.json()?
            }
            What::Tolerance(a) => {
                camsim::cmd::design::tolerance_table(&a, camsim::units::Units::Inch)?.json()?
            }
        },
        Command::Sweep(a) => {
            camsim::study::sweep::run(&camsim::cmd::sweep::sweep_of(&a)?, cli.units)?.json()?
        }
        Command::JumpSpeed(a) => {
            let mut scene = a.scene.clone();
            scene.start = Some(camsim::args::StartArg::Static);
            let spec = camsim::args::spec_from(&scene)?;
            camsim::study::jump_speed_actual::study(
                &spec,
                &a.actual.cams(),
                a.samples.unwrap_or(1),
                1,
                a.resolution,
                a.max_rpm,
            )?
            .json()?
        }
        other => panic!("{other:?}"),
    };
    Ok(serde_json::from_str(&text)?)
}

/// The settings that say which cams ran: every `profile` object and `seed` in the
/// report (design tolerance's is an array of rows).
fn echoed(v: &Value, out: &mut Vec<String>) {
    match v {
        Value::Object(o) => {
            for (k, x) in o {
                if k == "profile" && x.get("method").is_some() || k == "seed" {
                    out.push(format!("{k}: {x}"));
                } else {
                    echoed(x, out);
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|x| echoed(x, out)),
        _ => {}
    }
}

fn echo(argv: &[&str]) -> anyhow::Result<Vec<String>> {
    let mut out = Vec::new();
    echoed(&json_of(argv)?, &mut out);
    Ok(out)
}

/// Every command parses every option of the group (clap's own check: the group is one
/// flattened struct, no copy with another rule).
#[test]
fn every_actual_cam_command_parses_every_option() {
    for cmd in COMMANDS {
        for opt in OPTIONS {
            let argv: Vec<&str> = std::iter::once("camsim")
                .chain(cmd.iter().copied())
                .chain(opt.iter().copied())
                .collect();
            if let Err(e) = parse_from(&argv) {
                panic!("{argv:?}: {e}");
            }
        }
    }
}

/// Each option changes the cams each command reports on (its JSON's `profile` or
/// `seed`), and `design tolerance` refuses the three it sets itself with a usage error
/// naming the option.
#[test]
fn every_option_reaches_the_cams_each_command_reports() {
    for cmd in COMMANDS {
        let base = echo(cmd).unwrap_or_else(|e| panic!("{cmd:?}: {e:#}"));
        assert!(
            base.iter().any(|s| s.starts_with("profile:")),
            "{cmd:?}: {base:?}"
        );
        for opt in OPTIONS {
            let argv: Vec<&str> = cmd.iter().chain(opt.iter()).copied().collect();
            if cmd[1] == "tolerance" && DESIGN_TOLERANCE_REFUSES.contains(&opt[0]) {
                let e = json_of(&argv).unwrap_err();
                assert!(camsim::args::is_usage(&e), "{argv:?}: {e:#}");
                assert!(format!("{e}").contains(opt[0]), "{argv:?}: {e}");
                continue;
            }
            let got = echo(&argv).unwrap_or_else(|e| panic!("{argv:?}: {e:#}"));
            assert_ne!(got, base, "{argv:?} changed nothing the report echoes");
        }
    }
}

/// A list of FPRs is `design tolerance`'s alone: every other command refuses it on one
/// line naming the option and the values.
#[test]
fn only_design_tolerance_takes_a_list_of_fprs() {
    for cmd in COMMANDS.iter().filter(|c| c[1] != "tolerance") {
        let argv: Vec<&str> = cmd
            .iter()
            .copied()
            .chain(["--waviness-fpr", "17,39"])
            .collect();
        let e = json_of(&argv).unwrap_err();
        let msg = format!("{e:#}");
        assert!(camsim::args::is_usage(&e), "{argv:?}: {msg}");
        assert!(
            msg.contains("--waviness-fpr 17,39: one FPR here"),
            "{argv:?}: {msg}"
        );
    }
}

/// Without --actual, `design spring` refuses the options of the actual cams, naming them
/// (the theoretical cam would ignore them).
#[test]
fn design_spring_without_actual_refuses_the_cam_options() {
    let e = json_of(&["design", "spring", "--quick", "--cam-tolerance", "0.001"]).unwrap_err();
    assert!(camsim::args::is_usage(&e), "{e:#}");
    assert!(
        format!("{e}").contains("--cam-tolerance 0.001") && format!("{e}").contains("--actual"),
        "{e}"
    );
}
