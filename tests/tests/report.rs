//! `camsim run` reports and output files, through the command line the binary parses:
//! an existing `--csv` needs `--force`, a refused or failed run leaves every file as
//! it was, an interrupted one leaves nothing, `--json` has no null numbers, the CSV has
//! the documented header and one row of finite numbers per sample.

use std::fs;
use std::ops::ControlFlow;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use camsim::cli::{self, Command as Cmd};
use camsim::cmd::run::{self, Args};
use camsim::output::is_temp_name;
use camsim::report::Report;
use camsim::sim;

mod common;
use common::{listing, scratch};

/// `camsim run ARGS` as the binary parses it (Err: the usage error, on one line).
fn parse_run(args: &[&str]) -> Result<Args, String> {
    let argv = ["camsim", "run"].iter().chain(args).copied();
    match cli::parse_from(argv) {
        Ok(c) => match c.command {
            Cmd::Run(a) => Ok(a),
            other => panic!("not run: {other:?}"),
        },
        Err(e) => Err(cli::usage_line(&e)),
    }
}

/// Runs `camsim run ARGS` without printing: the report, or the error on one line.
fn run_cli(args: &[&str]) -> Result<run::RunReport, String> {
    let a = parse_run(args)?;
    run::report(&a, camsim::units::Units::Inch).map_err(|e| format!("{e:#}"))
}

/// A quick run: 500 rpm from static equilibrium (the reference holds contact there).
const QUICK: [&str; 4] = ["--rpm", "500", "--start", "static"];

fn quick(extra: &[&str]) -> Vec<String> {
    QUICK.iter().chain(extra).map(|s| s.to_string()).collect()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

#[test]
fn csv_to_an_existing_file_needs_force_and_leaves_it_byte_identical() {
    let d = scratch("exists");
    let csv = d.join("out.csv");
    let old: Vec<u8> = (0..=255u8).cycle().take(10_000).collect();
    fs::write(&csv, &old).unwrap();
    let p = csv.to_str().unwrap();
    let e = run_cli(&strs(&quick(&["--csv", p, "--revolutions", "1"]))).unwrap_err();
    assert_eq!(e, format!("--csv {p}: exists (use --force to overwrite)"));
    assert_eq!(fs::read(&csv).unwrap(), old);
    assert_eq!(listing(&d), ["out.csv"]);
    // With --force the run replaces it with the CSV.
    run_cli(&strs(&quick(&[
        "--csv",
        p,
        "--force",
        "--revolutions",
        "1",
    ])))
    .unwrap();
    let text = fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with(camsim::csv::HEADER), "{}", &text[..80]);
    assert_eq!(listing(&d), ["out.csv"]);
    fs::remove_dir_all(&d).unwrap();
}

#[test]
fn a_refused_or_failed_run_never_creates_or_touches_the_csv() {
    let d = scratch("refused");
    let old_csv = d.join("old.csv");
    fs::write(&old_csv, b"the user's data\n").unwrap();
    let plots = d.join("plots");
    fs::create_dir(&plots).unwrap();
    fs::write(plots.join("velocity.png"), b"an old plot").unwrap();
    let budget = d.join("tiny-budget.toml");
    fs::write(&budget, "[solver]\nmax_steps_per_rev = 50\n").unwrap();
    let bad_scene = d.join("bad.toml");
    fs::write(&bad_scene, "[design]\nk_rb_lb_per_in = 0\n").unwrap();
    let expect = ["bad.toml", "old.csv", "plots", "tiny-budget.toml"];
    let (new, old) = (d.join("new.csv"), old_csv.to_str().unwrap());
    let new = new.to_str().unwrap();
    let (plot_dir, budget) = (plots.to_str().unwrap(), budget.to_str().unwrap());
    let new_plots = d.join("new-plots");
    let new_plots = new_plots.to_str().unwrap();

    // Refused by clap: one line naming the option, the value and the rule.
    for (bad, option, rule) in [
        (["--rpm", "-5"], "--rpm", "must lie in [1, 10000] rpm"),
        (["--rpm", "1e300"], "--rpm", "must lie in [1, 10000] rpm"),
        (
            ["--rise", "nope"],
            "--rise",
            "possible values: straight-line",
        ),
        (
            ["--revolutions", "0"],
            "--revolutions",
            "must be a whole number from 1 to 16",
        ),
        (["--rtol", "1"], "--rtol", "must lie in [1e-13, 0.1]"),
        (
            ["--spring-rate", "1e300"],
            "--spring-rate",
            "must lie in [0.01, 1e6] lb/in",
        ),
        (
            ["--start", "cold"],
            "--start",
            "possible values: thesis, static",
        ),
        (["--max-csv-mb", "0"], "--max-csv-mb", "at least 1"),
    ] {
        for csv in [new, old] {
            let e = parse_run(&["--csv", csv, "--force", bad[0], bad[1]]).unwrap_err();
            assert!(e.contains(&format!("'{}'", bad[1])), "{e}");
            assert!(e.contains(&format!("'{option} <")), "{e}");
            assert!(e.contains(rule), "{e}");
            assert!(!e.contains('\n'), "{e}");
        }
    }
    // Refused after parsing, before the simulation.
    let bad_scene = bad_scene.to_str().unwrap();
    let refusals: [(Vec<&str>, &str); 6] = [
        // Another output refused: the CSV (planned first) is not created either.
        (vec!["--plot", plot_dir], "velocity.png exists (use --force"),
        // The size guard: one row per step, 16 revolutions are estimated at 1.63 GB.
        (
            vec!["--revolutions", "16", "--csv-every-step"],
            "would be about 1.63 GB, over the 1.00 GB limit (use --max-csv-mb N",
        ),
        (
            vec![
                "--revolutions",
                "1",
                "--max-csv-mb",
                "1",
                "--csv-every-step",
            ],
            "would be about 102 MB, over the 1.00 MB limit",
        ),
        // On the angle grid the rows are counted: every 0.001° is 360 000 points and the
        // four segment starts a revolution, 16 revolutions of 850 B rows: 4.90 GB.
        (
            vec!["--revolutions", "16", "--csv-every-deg", "0.001"],
            "would be about 4.90 GB, over the 1.00 GB limit",
        ),
        (
            vec!["/nonexistent/scene.toml"],
            "cannot read the scene file",
        ),
        (
            vec![bad_scene],
            "design.k_rb_lb_per_in = 0: must be positive",
        ),
    ];
    for (extra, why) in &refusals {
        let args = quick(extra);
        let mut args = strs(&args);
        args.extend(["--csv", new]);
        let e = run_cli(&args).unwrap_err();
        assert!(e.contains(why), "{extra:?}: {e}");
        assert_eq!(listing(&d), expect, "{extra:?}");
    }
    // A run that fails (its step budget used up): no new file, the old one (replaced
    // with --force only on success) and the plots untouched, no new plot directory.
    for csv in [new, old] {
        let e = run_cli(&[budget, "--csv", csv, "--force", "--plot", new_plots]).unwrap_err();
        assert!(e.contains("step budget"), "{e}");
        // The message names the scene key that raises the budget.
        assert!(e.contains("solver.max_steps_per_rev"), "{e}");
        assert_eq!(listing(&d), expect);
        let e = run_cli(&[budget, "--csv", csv, "--force", "--plot", plot_dir]).unwrap_err();
        assert!(e.contains("step budget"), "{e}");
        assert_eq!(listing(&d), expect);
    }
    assert_eq!(fs::read(&old_csv).unwrap(), b"the user's data\n");
    assert_eq!(listing(&plots), ["velocity.png"]);
    assert_eq!(
        fs::read(plots.join("velocity.png")).unwrap(),
        b"an old plot"
    );
    fs::remove_dir_all(&d).unwrap();
}

/// Every null and every number in a JSON value, with its path.
fn nulls(v: &serde_json::Value, path: &str, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Null => out.push(path.to_string()),
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                nulls(x, &format!("{path}[{i}]"), out);
            }
        }
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                nulls(x, &format!("{path}.{k}"), out);
            }
        }
        _ => {}
    }
}

#[test]
fn run_json_has_no_null_numbers_and_the_text_shows_the_same_values() {
    // The reference (800 rpm, thesis start) jumps: contact forces of 0, jump intervals.
    let r = run_cli(&["--revolutions", "2"]).unwrap();
    assert!(!r.jumps.is_empty(), "the reference separates at 800 rpm");
    let json = r.json().unwrap();
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    let mut found = Vec::new();
    nulls(&v, "", &mut found);
    assert!(found.is_empty(), "null (NaN or infinite) at {found:?}");
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "camsim_version",
            "jumps",
            "jumps_dropped",
            "per_period",
            "preload_lb",
            "rejected_steps",
            "revolutions",
            "rhs_evals",
            "rpm",
            "scene",
            "steady_state",
            "steps",
            "verdict",
            "wall_ms"
        ]
    );
    assert_eq!(v["per_period"].as_array().unwrap().len(), 8);
    assert_eq!(v["steps"], r.steps);
    assert_eq!(v["rpm"].as_f64(), Some(r.rpm));
    let j = &v["jumps"][0];
    assert_eq!(
        j.as_object().unwrap().keys().collect::<Vec<_>>(),
        ["end_deg", "revolution", "start_deg"]
    );
    // The text renders the same report.
    let text = r.text(camsim::units::Units::Inch);
    assert!(text.contains(&format!(
        "{} steps, {} rejected, {} rhs evaluations",
        r.steps, r.rejected_steps, r.rhs_evals
    )));
    assert!(text.contains(&format!("jumps: {} separation intervals", r.jumps.len())));
    assert!(text.starts_with("camsim run: 2 revolutions at 800.0 rpm, 11 DOF model"));
}

/// By default the CSV is on the cam-angle grid: a row every 0.5°, 720 a revolution
/// (the reference program's segment starts are whole degrees, on the grid) and the end
/// (the last revolution's 360°), each at its
/// angle exactly, the period and revolution as the grid labels them; and with
/// `--csv-every-deg 7` the 52 multiples of 7° below 360 and the four segment starts off
/// them.
#[test]
fn the_csv_is_on_the_cam_angle_grid_by_default() {
    let d = scratch("grid");
    let starts: Vec<f64> = camsim_core::Design::<f64>::reference()
        .program
        .segments()
        .iter()
        .map(|s| s.start_deg)
        .collect();
    for (step, per_rev) in [
        ("0.5", 720usize),
        ("7", 52 + starts.iter().filter(|a| *a % 7.0 != 0.0).count()),
    ] {
        let csv = d.join(format!("grid-{step}.csv"));
        let args = quick(&[
            "--revolutions",
            "2",
            "--csv-every-deg",
            step,
            "--csv",
            csv.to_str().unwrap(),
        ]);
        run_cli(&strs(&args)).unwrap();
        let text = fs::read_to_string(&csv).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some(camsim::csv::HEADER));
        let header: Vec<&str> = camsim::csv::HEADER.split(',').collect();
        let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
        let (rev, angle, theta) = (col("revolution"), col("cam_angle_deg"), col("theta_c_rad"));
        let rows: Vec<Vec<f64>> = lines
            .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
            .collect();
        // And the run's end: revolution 2 at 360°.
        assert_eq!(rows.len(), 2 * per_rev + 1, "--csv-every-deg {step}");
        assert_eq!(
            (rows[2 * per_rev][rev], rows[2 * per_rev][angle]),
            (2.0, 360.0)
        );
        for (i, v) in rows.iter().enumerate() {
            assert!(v.iter().all(|x| x.is_finite()));
            assert_eq!(v[rev], (i / per_rev + 1).min(2) as f64);
            let abs = 360.0 * (v[rev] - 1.0) + v[angle];
            assert!((v[theta] - abs.to_radians()).abs() < 1e-9, "row {i}: {v:?}");
        }
        if step == "0.5" {
            let angles: Vec<f64> = rows[..720].iter().map(|v| v[angle]).collect();
            let want: Vec<f64> = (0..720).map(|k| 0.5 * k as f64).collect();
            assert_eq!(angles, want);
        }
    }
    fs::remove_dir_all(&d).unwrap();
}

#[test]
fn the_csv_has_the_documented_header_and_one_finite_row_per_sample() {
    let d = scratch("rows");
    let csv = d.join("run.csv");
    let args = quick(&[
        "--revolutions",
        "2",
        "--csv-every-step",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let r = run_cli(&strs(&args)).unwrap();
    // The samples of the same run, counted by an observer.
    let spec = {
        let a = parse_run(&strs(&args)).unwrap();
        let mut s = run::spec_from(&a.scene).unwrap();
        s.revolutions = a.revolutions.unwrap();
        s
    };
    let mut samples = 0usize;
    sim::run(&spec, &mut |_: &camsim_core::Sample<f64>| {
        samples += 1;
        ControlFlow::Continue(())
    })
    .unwrap();
    let text = fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(camsim::csv::HEADER));
    let header: Vec<&str> = camsim::csv::HEADER.split(',').collect();
    assert_eq!(header.len(), 46);
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let (rev, contact, theta) = (col("revolution"), col("in_contact"), col("theta_c_rad"));
    let mut rows = 0usize;
    let mut last_theta = f64::NEG_INFINITY;
    for line in lines {
        let v: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
        assert_eq!(v.len(), header.len(), "{line}");
        assert!(v.iter().all(|x| x.is_finite()), "{line}");
        assert!(v[rev] == 1.0 || v[rev] == 2.0, "{line}");
        assert!(v[contact] == 0.0 || v[contact] == 1.0, "{line}");
        assert!(v[theta] >= last_theta, "{line}");
        last_theta = v[theta];
        rows += 1;
    }
    assert_eq!(rows, samples);
    // One sample per accepted step of the default method (Merson's pair; England's double
    // step gives two, what the size estimate assumes; the first sample is the start, the
    // one past the last revolution is not written).
    assert!(
        rows.abs_diff(r.steps as usize) <= 1,
        "{rows} rows, {} steps",
        r.steps
    );
    assert!(text.ends_with('\n'));
    assert_eq!(listing(&d), ["run.csv"]);
    fs::remove_dir_all(&d).unwrap();
}

const ENV_ARGS: &str = "CAMSIM_REPORT_CHILD_ARGS";

/// The child of the interrupt test: `camsim run` with the arguments in the environment
/// (separated by the unit separator, 0x1f).
#[test]
#[ignore = "child mode of the interrupt test"]
fn child_run() {
    let Ok(args) = std::env::var(ENV_ARGS) else {
        return;
    };
    let argv: Vec<&str> = ["camsim", "run"]
        .into_iter()
        .chain(args.split('\x1f'))
        .collect();
    let _ = cli::execute(cli::parse_from(argv).unwrap());
}

/// Starts `camsim run ARGS` in a child, waits until its CSV temporary in `dir` holds
/// data, sends SIGINT and returns the exit code.
fn interrupt_run(dir: &Path, args: &[&str]) -> Option<i32> {
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args(["child_run", "--exact", "--ignored", "--test-threads=1"])
        .env(ENV_ARGS, args.join("\x1f"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    loop {
        let temps: Vec<u64> = fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| is_temp_name(&e.file_name().to_string_lossy()))
            .filter_map(|e| e.metadata().ok().map(|m| m.len()))
            .collect();
        if temps.iter().any(|&n| n > 0) {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(30),
            "the run never wrote"
        );
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        std::thread::sleep(Duration::from_millis(2));
    }
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let t0 = Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s.code();
        }
        if t0.elapsed() > Duration::from_secs(10) {
            let _ = child.kill();
            panic!("the run outlived SIGINT");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn an_interrupted_run_leaves_nothing_behind() {
    let d = scratch("interrupt");
    // 100 rpm from the thesis start: some 400 000 steps a revolution, seconds of writing.
    let csv = d.join("new.csv");
    let plots = d.join("plots");
    let args = [
        "--rpm",
        "100",
        "--revolutions",
        "3",
        "--csv-every-step",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plots.to_str().unwrap(),
    ];
    assert_eq!(interrupt_run(&d, &args), Some(130));
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
    // An existing file with --force stays byte-identical.
    let old = d.join("old.csv");
    fs::write(&old, b"keep me").unwrap();
    let args = [
        "--rpm",
        "100",
        "--revolutions",
        "3",
        "--csv-every-step",
        "--csv",
        old.to_str().unwrap(),
        "--force",
    ];
    assert_eq!(interrupt_run(&d, &args), Some(130));
    assert_eq!(listing(&d), ["old.csv"]);
    assert_eq!(fs::read(&old).unwrap(), b"keep me");
    fs::remove_dir_all(&d).unwrap();
}

const ENV_CLI: &str = "CAMSIM_REPORT_CHILD_CLI";

/// The child of the command-line tests: prints READY (so the parent may close standard
/// output after the test harness's own header), waits a little, then does what the
/// binary does with the arguments in the environment (unit-separated) and exits with its
/// status.
#[test]
#[ignore = "child mode of the command-line tests"]
fn child_cli() {
    use std::io::Write;
    let Ok(args) = std::env::var(ENV_CLI) else {
        return;
    };
    {
        let mut out = std::io::stdout().lock();
        let _ = writeln!(out, "READY");
        let _ = out.flush();
    }
    std::thread::sleep(Duration::from_millis(300));
    let argv = std::iter::once("camsim").chain(args.split('\x1f').filter(|a| !a.is_empty()));
    std::process::exit(i32::from(cli::main_from(argv)));
}

/// Runs the binary's `main` on `args` in a child; `close_stdout` closes the reading end
/// of its standard output before it writes. Returns the exit code and standard error.
fn binary(args: &[&str], close_stdout: bool) -> (Option<i32>, String) {
    use std::io::{BufRead, Read};
    let mut child = Command::new(std::env::current_exe().unwrap())
        .args(["child_cli", "--exact", "--ignored", "--test-threads=1"])
        .env(ENV_CLI, args.join("\x1f"))
        .env_remove("RUST_BACKTRACE")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = std::io::BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    while stdout.read_line(&mut line).unwrap() > 0 && !line.contains("READY") {
        line.clear();
    }
    if close_stdout {
        drop(stdout);
    } else {
        std::thread::spawn(move || {
            let mut rest = Vec::new();
            let _ = stdout.read_to_end(&mut rest);
        });
    }
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    (child.wait().unwrap().code(), err)
}

#[test]
fn the_binary_fails_on_one_line_and_ends_quietly_on_a_closed_pipe() {
    // Bare camsim: a usage error that names the commands, not the tool's description.
    let (code, err) = binary(&[], false);
    assert_eq!(code, Some(2));
    assert_eq!(
        err,
        "camsim: error: a command is required: laws, modal, contact, run, jump-speed, scene, bench, models, predict, firmware-check, montecarlo, profile, compare, tolerance-study, sensitivity, waviness, sweep, design (see camsim --help)\n"
    );
    // Speeds of 1e300 rpm: refused by the range, before anything runs.
    for cmd in ["run", "bench", "jump-speed"] {
        let (code, err) = binary(&[cmd, "--rpm", "1e300"], false);
        assert_eq!(code, Some(2), "{cmd}: {err}");
        assert_eq!(
            err,
            "camsim: error: invalid value '1e300' for '--rpm <RPM>': must lie in [1, 10000] rpm (once a minute to above any cam drive) (see camsim --help)\n",
            "{cmd}"
        );
    }
    // A run that leaves the model's range: one line with the cause and the cam angle.
    let (code, err) = binary(&["run", "--rpm", "1600", "--revolutions", "1"], false);
    assert_eq!(code, Some(1));
    assert!(
        err.starts_with(
            "camsim: error: simulation failed: the model left its valid range at cam angle "
        ),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);
    // Standard output closed by its reader (`| head`): no error, status 0.
    for args in [&["scene", "--default"][..], &["laws"], &["modal", "--json"]] {
        let (code, err) = binary(args, true);
        assert_eq!((code, err.as_str()), (Some(0), ""), "{args:?}");
    }
    // Only the closed pipe is quiet: a command that fails still reports its error when
    // standard output is closed.
    let (code, err) = binary(&["run", "/nonexistent.toml"], true);
    assert_eq!(code, Some(1));
    assert!(err.contains("cannot read the scene file"), "{err}");
}

#[test]
fn a_broken_pipe_is_recognised_through_the_context() {
    let e = anyhow::Error::from(std::io::Error::from(std::io::ErrorKind::BrokenPipe))
        .context("writing");
    assert!(cli::is_broken_pipe(&e));
    let other = anyhow::Error::from(std::io::Error::from(std::io::ErrorKind::NotFound));
    assert!(!cli::is_broken_pipe(&other));
    assert!(!cli::is_broken_pipe(&anyhow::anyhow!("broken pipe")));
}

/// Runs the binary's `main` on `args` in a child; returns the exit code, standard output
/// and standard error.
fn binary_output(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(std::env::current_exe().unwrap())
        .args(["child_cli", "--exact", "--ignored", "--test-threads=1"])
        .env(ENV_CLI, args.join("\x1f"))
        .env_remove("RUST_BACKTRACE")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    // The child's own output starts after its READY line.
    let stdout = stdout
        .split_once("READY\n")
        .map_or(stdout.clone(), |(_, rest)| rest.to_string());
    (
        out.status.code(),
        stdout,
        String::from_utf8_lossy(&out.stderr).to_string(),
    )
}

#[test]
fn every_command_reports_absent_values_as_absent_not_as_non_finite() {
    // Issue 16: tolerance-study failed in every form because its theoretical cell's
    // interval (absent by design) was taken for NaN. Each command's --json (quick forms)
    // exits 0 and prints JSON without a null: an absent value is left out, and a value
    // absent by design is not refused as non-finite.
    let cases: &[&[&str]] = &[
        &["laws", "--json"],
        &["modal", "--json"],
        &["contact", "--force", "100", "--json"],
        &["run", "--revolutions", "1", "--json"],
        &["run", "--revolutions", "1", "--actual", "--json"],
        &["jump-speed", "--resolution", "50", "--json"],
        &["scene", "--default"],
        &["montecarlo", "--samples", "2", "--vertical", "--json"],
        &["compare", "--quick", "--json"],
        &["tolerance-study", "--quick", "--json"],
        &[
            "tolerance-study",
            "--quick",
            "--samples",
            "1",
            "--waviness-fpr",
            "17",
            "--json",
        ],
        &["waviness", "--seeds", "1", "--json"],
        &["predict", "--json"],
        &["models", "--quick", "--json"],
        &["bench", "--quick", "--json"],
    ];
    for args in cases {
        let (code, out, err) = binary_output(args);
        assert_eq!(code, Some(0), "camsim {}: {err}", args.join(" "));
        if !args.contains(&"--json") {
            assert!(!out.trim().is_empty(), "camsim {}", args.join(" "));
            continue;
        }
        let v: serde_json::Value = serde_json::from_str(&out)
            .unwrap_or_else(|e| panic!("camsim {}: not JSON ({e}): {out}", args.join(" ")));
        let mut found = Vec::new();
        nulls(&v, "", &mut found);
        assert!(
            found.is_empty(),
            "camsim {}: null at {found:?}",
            args.join(" ")
        );
    }
    // The grid's theoretical cell has no interval and no FPR, and passes the check; a
    // NaN put in its place does not.
    let (_, out, _) = binary_output(&["tolerance-study", "--quick", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(v["theoretical"].get("interval_deg").is_none());
    assert!(v["cells"][0]["interval_deg"].is_number() && v["cells"][0]["fpr"].is_number());
    assert_eq!(camsim::report::non_finite(&v).unwrap(), None);
    // The typed check: None (absent) passes, Some(NaN) is named.
    let absent: (Option<f64>, f64) = (None, 1.0);
    assert_eq!(camsim::report::non_finite(&absent).unwrap(), None);
    let nan: (Option<f64>, f64) = (Some(f64::NAN), 1.0);
    assert_eq!(
        camsim::report::non_finite(&nan).unwrap().as_deref(),
        Some("[0]")
    );
}
