//! The bad-input corpus (issue 10): every key of the default scene set to each of -1, 0,
//! nan, inf, 1e300, 1e-300 (and to nothing and to a word), empty, binary, truncated, huge
//! and wrong-unit scene files, and bad values of every numeric command-line option.
//!
//! Each input must end in one of two ways:
//! - a clean refusal: one line, no panic, no backtrace, no Rust debug structure, no long
//!   digit string, naming the key or the option (a refusal of the run itself names the
//!   cam angle where the model left its range or the solver stopped);
//! - a finite, plausible result: every number of the report finite
//!   (`camsim::report::ensure_finite`, what every command checks before it prints) and
//!   within physical bounds.
//!
//! The inputs go through the library the binary runs (`camsim::scene`, `camsim::cli`,
//! the commands' report functions) on two threads; a panic is caught and counted as a
//! defect. The corpus size and the outcome counts are printed (`--nocapture`; with
//! `CAMSIM_CORPUS_LIST=1` every input's outcome too).

use std::collections::{BTreeMap, HashMap};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use camsim::cli::{self, Command};
use camsim::cmd::run::RunReport;
use camsim::report::ensure_finite;
use camsim::sim::{self, Nothing, RunSpec};

/// What one input did.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Outcome {
    /// Refused before anything ran (a scene key, a file, an option).
    Refused,
    /// Accepted, and the run refused to report: the model left its valid range or the
    /// solver stopped, named with the cam angle.
    RefusedAtRun,
    /// Accepted and every number of the result finite and plausible.
    Finite,
}

/// One input of the corpus.
enum Input {
    /// Scene text, parsed as `camsim::scene::parse` does; `names` are the words one of
    /// which a refusal must contain (the key).
    Scene { text: String, names: Vec<String> },
    /// A scene file's bytes, read with `camsim::scene::load` from a temporary file.
    File { bytes: Vec<u8> },
    /// A command line (without the program name); `option` must be named by a refusal.
    Cli { args: Vec<String>, option: String },
}

struct Case {
    label: String,
    input: Input,
}

/// The bad values every key gets.
const BAD: [&str; 8] = ["-1", "0", "nan", "inf", "1e300", "1e-300", "", "\"abc\""];

/// Whether a message is a clean refusal: one non-empty line without a panic, a
/// backtrace hint, a Rust debug structure or a value printed with dozens of digits.
fn clean(msg: &str) -> Result<(), String> {
    let bad = |why: &str| Err(format!("{why}: {msg:?}"));
    if msg.trim().is_empty() {
        return bad("empty message");
    }
    if msg.contains('\n') {
        return bad("more than one line");
    }
    for word in [
        "panicked",
        "RUST_BACKTRACE",
        "stack backtrace",
        "Some(",
        "Os {",
    ] {
        if msg.contains(word) {
            return bad(word);
        }
    }
    // A debug structure: `Name { field: ...`.
    let b = msg.as_bytes();
    for (i, w) in b.windows(3).enumerate() {
        if w == b" { " {
            let before = &msg[..i];
            let ident = before.rsplit(|c: char| !c.is_alphanumeric()).next();
            if ident.is_some_and(|s| s.starts_with(|c: char| c.is_ascii_uppercase())) {
                return bad("debug structure");
            }
        }
    }
    let mut run = 0;
    for c in msg.chars() {
        run = if c.is_ascii_digit() { run + 1 } else { 0 };
        if run > 24 {
            return bad("a number printed with more than 24 digits");
        }
    }
    Ok(())
}

/// Runs an accepted scene (at most two revolutions: the corpus is about whether the
/// result is finite and plausible, which the first two show) and judges the outcome.
fn run_scene(mut spec: RunSpec) -> Result<Outcome, String> {
    spec.revolutions = spec.revolutions.min(2);
    match sim::run(&spec, &mut Nothing) {
        Ok(r) => {
            let report = RunReport::new(&spec, &r);
            ensure_finite(&report).map_err(|e| format!("{e:#}"))?;
            plausible(&spec, &report)?;
            Ok(Outcome::Finite)
        }
        Err(e) => {
            let msg = cli::error_line(&e);
            clean(&msg)?;
            if !msg.contains("cam angle") {
                return Err(format!("a failed run must name the cam angle: {msg}"));
            }
            Ok(Outcome::RefusedAtRun)
        }
    }
}

/// Physical bounds of a finished run: a positive preload, a contact force that never
/// pulls and stays below what the validity bounds allow (K_h times the largest
/// penetration is below 1e6 lb for any plausible design), follower deviations smaller
/// than the cantilever, rows for every revolution.
fn plausible(spec: &RunSpec, r: &RunReport) -> Result<(), String> {
    let e2 = spec.design.e2;
    let fail = |why: String| Err(format!("implausible result: {why}"));
    let preload = r.preload_lb.in_inch();
    if !(0.0..1e6).contains(&preload) {
        return fail(format!("preload {}", preload));
    }
    if r.per_period.is_empty() {
        return fail("no per-period rows".into());
    }
    for row in &r.per_period {
        if row.contact_force_min.in_inch() < 0.0 || row.contact_force_max.in_inch() > 1e7 {
            return fail(format!(
                "contact force {}..{} lb",
                row.contact_force_min.in_inch(),
                row.contact_force_max.in_inch()
            ));
        }
        if row.rms_displacement.in_inch() > e2 {
            return fail(format!(
                "rms displacement {} in",
                row.rms_displacement.in_inch()
            ));
        }
    }
    Ok(())
}

/// Judges one case; `Err` describes a defect.
fn judge(case: &Case, scratch: &std::path::Path) -> Result<Outcome, String> {
    match &case.input {
        Input::Scene { text, names } => match camsim::scene::parse(text) {
            Ok(spec) => run_scene(spec),
            Err(e) => {
                let msg = cli::error_line(&e);
                clean(&msg)?;
                if !names.iter().any(|n| msg.contains(n.as_str())) {
                    return Err(format!("the refusal names none of {names:?}: {msg}"));
                }
                Ok(Outcome::Refused)
            }
        },
        Input::File { bytes } => {
            let path = scratch.join(format!("{}.toml", case.label.replace(['/', ' '], "_")));
            std::fs::write(&path, bytes).map_err(|e| e.to_string())?;
            let r = camsim::scene::load(&path);
            let _ = std::fs::remove_file(&path);
            match r {
                Ok(spec) => run_scene(spec),
                Err(e) => {
                    let msg = cli::error_line(&e);
                    clean(&msg)?;
                    if !msg.contains(path.to_str().unwrap_or("?")) {
                        return Err(format!("the refusal does not name the file: {msg}"));
                    }
                    Ok(Outcome::Refused)
                }
            }
        }
        Input::Cli { args, option } => {
            let argv = std::iter::once("camsim".to_string()).chain(args.iter().cloned());
            match cli::parse_from(argv) {
                Err(e) => {
                    let msg = cli::usage_message(&e);
                    clean(&msg)?;
                    if !msg.contains(option.as_str()) {
                        return Err(format!("the refusal does not name {option}: {msg}"));
                    }
                    Ok(Outcome::Refused)
                }
                Ok(parsed) => run_cli(parsed.command, option),
            }
        }
    }
}

/// A command line that parsed: what the command computes from it, without printing.
fn run_cli(command: Command, option: &str) -> Result<Outcome, String> {
    let refused = |e: anyhow::Error| -> Result<Outcome, String> {
        let msg = cli::error_line(&e);
        clean(&msg)?;
        if msg.contains(option) || msg.contains("cam angle") {
            Ok(Outcome::Refused)
        } else {
            Err(format!(
                "the refusal names neither {option} nor a cam angle: {msg}"
            ))
        }
    };
    match command {
        Command::Run(mut a) => {
            a.revolutions = Some(1);
            match camsim::cmd::run::report(&a, camsim::units::Units::Inch) {
                Ok(r) => {
                    ensure_finite(&r).map_err(|e| format!("{e:#}"))?;
                    Ok(Outcome::Finite)
                }
                Err(e) => refused(e),
            }
        }
        Command::Contact(a) => match camsim::cmd::contact::compute(a.force) {
            Ok(r) => {
                ensure_finite(&r).map_err(|e| format!("{e:#}"))?;
                Ok(Outcome::Finite)
            }
            Err(e) => refused(e),
        },
        // Accepted search and bench options: their values are what the commands take
        // (a full search or bench per value is too slow for the corpus).
        Command::JumpSpeed(a) => {
            let ok = a.resolution.is_finite()
                && a.resolution > 0.0
                && a.resolution <= camsim_core::key::SPEED_RPM.max
                && camsim_core::key::SPEED_RPM.contains(a.max_rpm)
                && camsim::cmd::run::spec_from(&a.scene).is_ok();
            if ok {
                Ok(Outcome::Finite)
            } else {
                Err(format!("jump-speed accepted {a:?}"))
            }
        }
        Command::Bench(a) => {
            if camsim_core::key::SPEED_RPM.contains(a.rpm)
                && a.repeat.is_none_or(|r| (1..=100).contains(&r))
            {
                Ok(Outcome::Finite)
            } else {
                Err(format!("bench accepted {a:?}"))
            }
        }
        other => Err(format!("unexpected command {other:?}")),
    }
}

/// `key = value` lines of a scene text: (line index, key, full key path).
fn key_lines(text: &str) -> Vec<(usize, String, String)> {
    let mut header = String::new();
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if let Some(h) = t.strip_prefix("[[").and_then(|r| r.strip_suffix("]]")) {
            header = h.to_string();
        } else if let Some(h) = t.strip_prefix('[').and_then(|r| r.strip_suffix(']')) {
            header = h.to_string();
        } else if let Some((k, _)) = t.split_once(" = ") {
            if !k.starts_with('#') {
                out.push((i, k.to_string(), format!("{header}.{k}")));
            }
        }
    }
    out
}

/// Deterministic bytes (xorshift64*), for the binary files.
fn noise(n: usize, mut seed: u64) -> Vec<u8> {
    (0..n)
        .map(|_| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 56) as u8
        })
        .collect()
}

/// Builds the corpus from the default scene.
fn corpus() -> Vec<Case> {
    let text = camsim::scene::default_text().unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut cases = Vec::new();
    let scene = |label: String, text: String, names: Vec<String>| Case {
        label,
        input: Input::Scene { text, names },
    };

    // Every key of the default scene set to every bad value. A refusal names the key
    // (its last part: the line's own key), or for a program's segment the program (its
    // angles and lifts are judged together: a wrong start_deg is the previous segment's
    // end_deg mismatch).
    for (i, key, path) in key_lines(&text) {
        for v in BAD {
            let mut edited: Vec<String> = lines.iter().map(|l| l.to_string()).collect();
            edited[i] = format!("{key} = {v}");
            let mut names = vec![key.clone()];
            if path.starts_with("design.program.segment") {
                names.push("design.program.segment".into());
            }
            cases.push(scene(format!("{path} = {v}"), edited.join("\n"), names));
        }
    }
    // run.rpm, absent from the default scene.
    for v in BAD {
        cases.push(scene(
            format!("run.rpm = {v}"),
            format!("[run]\nrpm = {v}\n"),
            vec!["run.rpm".into()],
        ));
    }

    // Empty and next to empty.
    for (label, t) in [
        ("empty", ""),
        ("whitespace", " \n\t\n"),
        ("comments only", "# nothing\n# else\n"),
        ("empty tables", "[run]\n[solver]\n[design]\n"),
    ] {
        cases.push(scene(label.into(), t.into(), vec![]));
    }

    // Truncated: the default scene cut at every 53rd byte (mid-key, mid-number,
    // mid-header, mid-string).
    let mut cut = 1;
    while cut < text.len() {
        if text.is_char_boundary(cut) {
            let t = &text[..cut];
            // The key of the cut line, if the cut is inside one.
            let names = match t
                .lines()
                .last()
                .and_then(|l| l.split(['=', ' ', '[', ']']).next())
            {
                Some(k) if !k.is_empty() && !k.starts_with('#') => {
                    vec![k.trim().to_string(), "line ".into()]
                }
                _ => vec!["line ".into()],
            };
            cases.push(scene(format!("truncated at {cut}"), t.into(), names));
        }
        cut += 53;
    }

    // Wrong units: each a plausible-looking mistake.
    let wrong_units: [(&str, &str, &[&str]); 12] = [
        // Lengths in mm: every length in range, the run itself stalls the drive.
        (
            "lengths in mm",
            "[design]\ne2_in = 50.8\n[design.geometry]\nbase_radius_in = 38.1\nroller_radius_in = 9.525\nthickness_in = 6.35\n",
            &["design.", "cam angle"],
        ),
        // Lengths in m: a roller of 0.0095 m is below the 0.01 in a length may be.
        (
            "lengths in m",
            "[design.geometry]\nbase_radius_in = 0.0381\nroller_radius_in = 0.009525\n",
            &["geometry"],
        ),
        ("modulus in Pa", "[design]\nfollower_youngs_psi = 2.07e11\n", &["follower_youngs_psi"]),
        ("modulus in GPa", "[design.hertz]\ncam_youngs_psi = 207\n", &["cam_youngs_psi"]),
        ("mass in lb", "[design]\ncam_mass_lb_s2_per_in = 11.24\n", &["cam_mass_lb_s2_per_in"]),
        ("mass in kg", "[design]\nload_mass_lb_s2_per_in = 0.6\n", &["load_mass_lb_s2_per_in", "cam angle"]),
        ("stiffness in N/m", "[design]\nk_rb_lb_per_in = 2.63e8\n", &["k_rb_lb_per_in", "cam angle"]),
        ("speed in rpm as rad/s", "[design]\nomega0_rad_per_s = 800\n", &["omega0_rad_per_s", "cam angle"]),
        ("speed in rad/s as rpm", "[run]\nrpm = 83.8\n", &["run.rpm"]),
        ("unit in the value", "[design]\nk_rb_lb_per_in = \"1.5e6 lb/in\"\n", &["k_rb_lb_per_in"]),
        ("SI key", "[design]\nk_rb_N_per_m = 2.63e8\n", &["k_rb_N_per_m"]),
        (
            "angles in radians",
            "[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = 0\nend_deg = 6.283185307179586\n",
            &["design.program.segment"],
        ),
    ];
    for (label, t, names) in wrong_units {
        cases.push(scene(
            label.into(),
            t.into(),
            names.iter().map(|s| s.to_string()).collect(),
        ));
    }

    // Huge: a number with 5000 digits, a key of 100 000 characters, 300 000 table
    // headers, nested arrays.
    cases.push(scene(
        "5000-digit number".into(),
        format!("[design]\nk_rb_lb_per_in = {}\n", "9".repeat(5000)),
        vec!["k_rb_lb_per_in".into()],
    ));
    cases.push(scene(
        "huge key".into(),
        format!("[design]\n{} = 1\n", "k".repeat(100_000)),
        vec!["design.k".into()],
    ));
    cases.push(scene(
        "many tables".into(),
        "[design]\n".repeat(300_000),
        vec!["design".into()],
    ));
    cases.push(scene(
        "deep arrays".into(),
        format!(
            "[design]\nk_rb_lb_per_in = {}1{}\n",
            "[".repeat(5000),
            "]".repeat(5000)
        ),
        vec!["k_rb_lb_per_in".into(), "line ".into()],
    ));
    cases.push(scene(
        "nine segments".into(),
        (0..9)
            .map(|i| {
                format!(
                    "[[design.program.segment]]\nkind = \"dwell\"\nstart_deg = {}\nend_deg = {}\n",
                    i * 40,
                    (i + 1) * 40
                )
            })
            .collect(),
        vec!["design.program.segment".into()],
    ));

    // Files: binary, invalid UTF-8 inside the scene, NUL bytes, a BOM, too large.
    let file = |label: &str, bytes: Vec<u8>| Case {
        label: label.into(),
        input: Input::File { bytes },
    };
    for seed in 1..=8u64 {
        cases.push(file(&format!("binary {seed}"), noise(4096, seed)));
    }
    let mut invalid = text.clone().into_bytes();
    invalid.insert(text.len() / 2, 0xff);
    cases.push(file("invalid UTF-8 mid-scene", invalid));
    cases.push(file("NUL bytes", vec![0; 1000]));
    cases.push(file(
        "BOM",
        [b"\xef\xbb\xbf".as_slice(), text.as_bytes()].concat(),
    ));
    cases.push(file("empty file", Vec::new()));
    let mut big = text.clone().into_bytes();
    big.extend(b"# filler\n".repeat(200_000));
    cases.push(file("2 MB of comments", big));
    let mut just_under = text.clone().into_bytes();
    just_under
        .extend(b"#\n".repeat((camsim::scene::MAX_SCENE_BYTES as usize - text.len()) / 2 - 1));
    cases.push(file("just under the size limit", just_under));

    // The command line: every numeric option of every command with every bad value
    // (a value that parses is run: `run` for one revolution, `contact` at once).
    let options: [(&str, &str); 12] = [
        ("run", "--rpm"),
        ("run", "--spring-rate"),
        ("run", "--preload-length"),
        ("run", "--rtol"),
        ("run", "--atol"),
        ("run", "--revolutions"),
        ("run", "--max-csv-mb"),
        ("jump-speed", "--resolution"),
        ("jump-speed", "--max-rpm"),
        ("bench", "--rpm"),
        ("bench", "--repeat"),
        ("contact", "--force"),
    ];
    for (cmd, opt) in options {
        for v in [
            "-1", "0", "nan", "inf", "1e300", "1e-300", "", "abc", "1e3000", "-inf",
        ] {
            cases.push(Case {
                label: format!("{cmd} {opt} {v}"),
                input: Input::Cli {
                    args: vec![cmd.into(), opt.into(), v.into()],
                    option: opt.into(),
                },
            });
        }
    }
    issue_20_cases(&mut cases);
    cases
}

/// Where the corpus's input files of issue 20 are written (removed by the test).
fn files_dir() -> PathBuf {
    std::env::temp_dir().join(format!("camsim-corpus-files-{}", std::process::id()))
}

/// Issue 20: outputs that are not regular files, unbounded and implausible measured
/// inputs, tolerances without a range, forces beyond the documented bounds.
fn issue_20_cases(cases: &mut Vec<Case>) {
    let dir = files_dir();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let cli = |label: String, args: Vec<String>, option: &str| Case {
        label,
        input: Input::Cli {
            args,
            option: option.into(),
        },
    };
    // Outputs: devices, a FIFO, a link to a device (with and without --force).
    assert!(std::process::Command::new("mkfifo")
        .arg(path("fifo"))
        .status()
        .unwrap()
        .success());
    std::os::unix::fs::symlink("/dev/zero", path("zero-link")).unwrap();
    for target in [
        "/dev/zero".to_owned(),
        "/dev/full".to_owned(),
        path("fifo"),
        path("zero-link"),
    ] {
        for force in [false, true] {
            let mut args: Vec<String> = ["run", "--csv", &target].map(String::from).to_vec();
            if force {
                args.push("--force".into());
            }
            cases.push(cli(
                format!("run --csv {target} force={force}"),
                args,
                "--csv",
            ));
        }
    }
    // Measured inputs: endless, too large, binary, implausible radius profiles, a
    // name with an escape sequence.
    let radius = |f: &dyn Fn(f64, usize) -> f64, n: usize| {
        let mut t = String::from("angle_deg,radius_in\n");
        for k in 0..n {
            let a = k as f64 * 360.0 / n as f64;
            t += &format!("{a},{}\n", f(a, k));
        }
        t
    };
    let mut big = String::from("angle_deg,deviation_in\n");
    while big.len() < 5_000_000 {
        big += "# filler filler filler filler filler filler filler\n";
    }
    let files: [(&str, Vec<u8>); 6] = [
        ("big.csv", big.into_bytes()),
        (
            "binary.csv",
            b"angle_deg,deviation_in\n0,0\n\xff\xfe\n".to_vec(),
        ),
        (
            "notch.csv",
            radius(
                &|a, _| {
                    if (100.0..120.0).contains(&a) {
                        1.5
                    } else {
                        2.0
                    }
                },
                3600,
            )
            .into_bytes(),
        ),
        ("tiny-radius.csv", radius(&|_, _| 0.01, 360).into_bytes()),
        (
            "alternating.csv",
            radius(&|_, k| if k % 2 == 1 { 2.0001 } else { 1.9999 }, 3600).into_bytes(),
        ),
        ("lift-below.csv", {
            let mut t = String::from("angle_deg,lift_in\n");
            for k in 0..36 {
                t += &format!("{},-3\n", k * 10);
            }
            t.into_bytes()
        }),
    ];
    for (name, bytes) in files {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    for m in [
        "/dev/zero".to_owned(),
        path("big.csv"),
        path("binary.csv"),
        path("notch.csv"),
        path("tiny-radius.csv"),
        path("alternating.csv"),
        path("lift-below.csv"),
        path("fifo-missing\u{1b}[2J.csv"),
        dir.to_str().unwrap().to_owned(),
    ] {
        cases.push(cli(
            format!("run --measured {m:?}"),
            ["run", "--measured", &m].map(String::from).to_vec(),
            "--measured",
        ));
    }
    // Tolerances: every bad value, and values past the 0.1 in range.
    for opt in [
        "--cam-tolerance",
        "--roller-tolerance",
        "--eccentricity-tolerance",
    ] {
        for v in [
            "-1",
            "nan",
            "inf",
            "1e300",
            "1",
            "0.5",
            "0.1000001",
            "",
            "abc",
        ] {
            cases.push(cli(
                format!("run --actual {opt} {v}"),
                ["run", "--actual", opt, v].map(String::from).to_vec(),
                opt,
            ));
        }
    }
    // Forces at and past the documented bounds.
    for v in ["1e7", "2e6", "5e-324", "1e-7"] {
        cases.push(cli(
            format!("contact --force {v}"),
            ["contact", "--force", v].map(String::from).to_vec(),
            "--force",
        ));
    }
}

#[test]
fn every_bad_input_is_refused_cleanly_or_gives_a_finite_plausible_result() {
    let cases = corpus();
    let scratch = std::env::temp_dir().join(format!("camsim-corpus-{}", std::process::id()));
    std::fs::create_dir_all(&scratch).unwrap();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<(usize, Result<Outcome, String>)>> = Mutex::new(Vec::new());
    // Identical accepted scenes are run once (truncations often cut off only defaults):
    // a scene text that parses to a scene already judged takes that outcome.
    let seen: Mutex<HashMap<String, Result<Outcome, String>>> = Mutex::new(HashMap::new());
    let work = |scratch: PathBuf| loop {
        let i = next.fetch_add(1, Ordering::Relaxed);
        let Some(case) = cases.get(i) else { break };
        let same = match &case.input {
            Input::Scene { text, .. } => catch_unwind(|| camsim::scene::parse(text).ok())
                .ok()
                .flatten()
                .and_then(|spec| camsim::scene::spec_text(&spec).ok()),
            _ => None,
        };
        if let Some(r) = same
            .as_ref()
            .and_then(|k| seen.lock().unwrap().get(k).cloned())
        {
            results.lock().unwrap().push((i, r));
            continue;
        }
        let r = catch_unwind(AssertUnwindSafe(|| judge(case, &scratch)))
            .unwrap_or_else(|_| Err("PANIC".into()));
        if let Some(k) = same {
            seen.lock().unwrap().insert(k, r.clone());
        }
        results.lock().unwrap().push((i, r));
    };
    std::thread::scope(|s| {
        let a = s.spawn(|| work(scratch.clone()));
        work(scratch.clone());
        a.join().unwrap();
    });
    let _ = std::fs::remove_dir_all(&scratch);
    let _ = std::fs::remove_dir_all(files_dir());

    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|(i, _)| *i);
    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut defects = Vec::new();
    for (i, r) in &results {
        let kind = match &cases[*i].input {
            Input::Scene { .. } => "scene text",
            Input::File { .. } => "scene file",
            Input::Cli { .. } => "command line",
        };
        let outcome = match r {
            Ok(o) => format!("{o:?}"),
            Err(e) => {
                defects.push(format!("{}: {e}", cases[*i].label));
                "defect".into()
            }
        };
        if std::env::var_os("CAMSIM_CORPUS_LIST").is_some() {
            println!("{outcome:>12}  {}", cases[*i].label);
        }
        *counts.entry(format!("{kind}: {outcome}")).or_default() += 1;
        *counts.entry(format!("all: {outcome}")).or_default() += 1;
    }
    println!("bad-input corpus: {} inputs", cases.len());
    for (k, n) in &counts {
        println!("  {k}: {n}");
    }
    assert_eq!(results.len(), cases.len());
    assert!(
        defects.is_empty(),
        "{} defects:\n{}",
        defects.len(),
        defects.join("\n")
    );
    // The corpus is what it says: the bad values of every key are refused far more often
    // than not, and some inputs do run to a finite result (zero damping, say).
    assert!(counts.get("all: Refused").copied().unwrap_or(0) > cases.len() / 2);
    assert!(counts.get("all: Finite").copied().unwrap_or(0) > 0);
    assert!(counts.get("all: RefusedAtRun").copied().unwrap_or(0) > 0);
}

/// The checks of the corpus can fail: a message with a panic, two lines, a debug
/// structure or 300 digits is not clean.
#[test]
fn the_cleanliness_check_refuses_what_it_should() {
    assert!(clean("design.k_rb_lb_per_in = -1: must be positive and finite").is_ok());
    assert!(clean("thread 'main' panicked at src/x.rs").is_err());
    assert!(clean("two\nlines").is_err());
    assert!(clean("").is_err());
    assert!(clean("table build: InvalidParameter { field: \"k\" }").is_err());
    assert!(clean(&format!("k = {}", "1".repeat(301))).is_err());
    assert!(clean("note: run with `RUST_BACKTRACE=1`").is_err());
}
