//! Issue 33 (reliability, third pass), the output layer: descriptor paths, temporaries
//! that other runs cannot take for stale ones, long names, `--force` into an output
//! directory, writes to standard output and a small stack. Each test failed on 6b065a3.
//!
//! The commands run through `camsim::cli`, what the binary runs. The tests that need the
//! process's own standard output (a full disk behind it, a pipe closed by its reader) or a
//! small stack start this test binary again in a child mode (the ignored test
//! `child_command`, driven by environment variables), which runs one command line with
//! [`camsim::cli::main_from`] and reports its exit status on standard error.

use std::fs;
use std::io::{Read, Write};
use std::os::fd::AsRawFd;
use std::path::Path;
use std::process::{Command, Stdio};

use camsim::cli;

mod common;
use common::{listing, outcome, s, scratch};

const ENV_ARGS: &str = "CAMSIM_RELIO_CHILD_ARGS";
const ENV_STDOUT: &str = "CAMSIM_RELIO_CHILD_STDOUT";

/// The child mode: does nothing unless the parent set the environment. Runs the command
/// line in `ENV_ARGS` (separated by `\x1f`) with standard output as `ENV_STDOUT` says:
/// `full` (/dev/full), `pipe100` (a pipe whose reader takes 100 bytes and closes it) or
/// `null`; then prints `EXIT <status>` on standard error and exits with that status.
#[test]
#[ignore = "child mode of the standard-output and stack tests"]
fn child_command() {
    let Ok(args) = std::env::var(ENV_ARGS) else {
        return;
    };
    let argv: Vec<&str> = std::iter::once("camsim")
        .chain(args.split('\x1f'))
        .collect();
    let mut reader = None;
    match std::env::var(ENV_STDOUT).as_deref() {
        Ok("full") => {
            let f = fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap();
            nix::unistd::dup2(f.as_raw_fd(), 1).unwrap();
        }
        Ok("pipe100") => {
            let (r, w) = nix::unistd::pipe().unwrap();
            nix::unistd::dup2(w.as_raw_fd(), 1).unwrap();
            drop(w);
            reader = Some(std::thread::spawn(move || {
                let mut r = fs::File::from(r);
                let mut buf = [0u8; 100];
                r.read_exact(&mut buf).unwrap();
                // Closed here: the writer's next write finds no reader.
            }));
        }
        _ => {
            let f = fs::OpenOptions::new()
                .write(true)
                .open("/dev/null")
                .unwrap();
            nix::unistd::dup2(f.as_raw_fd(), 1).unwrap();
        }
    }
    let code = cli::main_from(argv);
    if let Some(r) = reader {
        r.join().unwrap();
    }
    let mut err = std::io::stderr();
    writeln!(err, "EXIT {code}").unwrap();
    err.flush().unwrap();
    std::process::exit(i32::from(code));
}

/// Runs `args` in the child mode; its exit status and what it wrote to standard error
/// (libtest's lines aside).
fn child(args: &[&str], stdout: &str, env: &[(&str, &str)]) -> (i32, String) {
    let exe = std::env::current_exe().unwrap();
    let mut cmd = Command::new(exe);
    cmd.args([
        "child_command",
        "--exact",
        "--ignored",
        "--nocapture",
        "--test-threads=1",
    ])
    .env(ENV_ARGS, args.join("\x1f"))
    .env(ENV_STDOUT, stdout)
    .stdout(Stdio::null())
    .stderr(Stdio::piped());
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    (out.status.code().unwrap_or(-1), err)
}

// Defect 1: a descriptor path never writes into a file open for reading or an input.
#[test]
fn descriptor_paths_never_write_into_a_file_open_for_reading_or_an_input() {
    let d = scratch("descriptors");
    let scene = d.join("scene.toml");
    let text = "[run]\nrevolutions = 1\n";
    fs::write(&scene, text).unwrap();
    // `--csv /dev/fd/N < scene.toml`: the descriptor is open for reading only.
    let reading = fs::File::open(&scene).unwrap();
    let n = reading.as_raw_fd();
    for p in [format!("/dev/fd/{n}"), format!("/proc/self/fd/{n}")] {
        for force in [false, true] {
            let mut args = vec!["run", "--revolutions", "1", "--csv", &p];
            if force {
                args.push("--force");
            }
            assert_eq!(
                outcome(&args),
                format!("--csv {p}: descriptor {n} is open for reading only: an output never writes into a file open for reading")
            );
        }
    }
    drop(reading);
    // Open for writing (`>> scene.toml`), but the run's own scene.
    let appending = fs::OpenOptions::new().append(true).open(&scene).unwrap();
    let p = format!("/dev/fd/{}", appending.as_raw_fd());
    let e = outcome(&["run", s(&scene), "--csv", &p, "--force"]);
    assert_eq!(
        e,
        format!("--csv {p}: is the input scene file {}: an output never replaces an input, even with --force", s(&scene))
    );
    drop(appending);
    // Open for reading and writing (`<> file`).
    let other = d.join("other.csv");
    fs::write(&other, "keep").unwrap();
    let both = fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&other)
        .unwrap();
    let p = format!("/dev/fd/{}", both.as_raw_fd());
    assert!(
        outcome(&["run", "--csv", &p]).ends_with("is a file open for reading and writing: an output never writes into a file open for reading"),
    );
    drop(both);
    // Not open, and not a descriptor number.
    let e = outcome(&["run", "--csv", "/dev/fd/987"]);
    assert!(
        e.starts_with("--csv /dev/fd/987: descriptor 987 is not open"),
        "{e}"
    );
    let e = outcome(&["run", "--csv", "/dev/fd/x"]);
    assert!(e.starts_with("--csv /dev/fd/x: names no descriptor"), "{e}");
    assert_eq!(fs::read_to_string(&scene).unwrap(), text);
    assert_eq!(fs::read_to_string(&other).unwrap(), "keep");
    // A descriptor open for writing only (`> out.csv`) is written through.
    let out = d.join("out.csv");
    let writing = fs::File::create(&out).unwrap();
    let p = format!("/dev/fd/{}", writing.as_raw_fd());
    assert_eq!(outcome(&["run", "--revolutions", "1", "--csv", &p]), "OK");
    drop(writing);
    let csv = fs::read_to_string(&out).unwrap();
    assert!(
        csv.starts_with("t_s,") && csv.lines().count() > 700,
        "{}",
        &csv[..80]
    );
    fs::remove_dir_all(&d).unwrap();
}

// Defect 2: a user's file named as an earlier version's temporary is never removed, even
// when the process id in its name is dead.
#[test]
fn a_file_named_like_an_old_temporary_is_never_removed() {
    let d = scratch("legacy");
    let mut c = Command::new("true").spawn().unwrap();
    let dead = c.id();
    c.wait().unwrap();
    let users = [
        format!(".X.camsim-{dead}-0.tmp"),
        format!(".notes.camsim-somehost-{dead}-1.tmp"),
    ];
    for n in &users {
        fs::write(d.join(n), "the user's").unwrap();
    }
    let csv = d.join("out.csv");
    assert_eq!(
        outcome(&["run", "--revolutions", "1", "--csv", s(&csv)]),
        "OK"
    );
    let mut expect = vec!["out.csv".to_owned()];
    expect.extend(users.iter().cloned());
    expect.sort();
    assert_eq!(listing(&d), expect);
    fs::remove_dir_all(&d).unwrap();
}

// Defect 9: any legal file name (up to 255 bytes) can be an output.
#[test]
fn legal_long_output_names_are_written() {
    let d = scratch("long");
    for len in [233, 255] {
        let name = format!("{}.csv", "c".repeat(len - 4));
        let csv = d.join(&name);
        assert_eq!(
            outcome(&["run", "--revolutions", "1", "--csv", s(&csv)]),
            "OK",
            "{len} bytes"
        );
        assert!(fs::metadata(&csv).unwrap().len() > 1000);
        assert_eq!(listing(&d), std::slice::from_ref(&name));
        fs::remove_file(&csv).unwrap();
    }
    // One byte more is no legal name: refused before the run, by the option.
    let csv = d.join(format!("{}.csv", "c".repeat(252)));
    assert_eq!(
        outcome(&["run", "--csv", s(&csv)]),
        format!(
            "--csv {}: the file name is 256 bytes, over the 255 a file system allows",
            s(&csv)
        )
    );
    assert!(listing(&d).is_empty());
    fs::remove_dir_all(&d).unwrap();
}

// Defect 5: `--force` into an output directory replaces the whole set of files.
#[test]
fn a_forced_profile_out_leaves_no_file_of_the_earlier_design() {
    let d = scratch("profile-set");
    let out = d.join("pd");
    let first = outcome(&["profile", "--out", s(&out), "--cutter-radius", "0.5"]);
    assert_eq!(first, "OK");
    assert!(out.join("cutter.csv").exists());
    let without = listing(&out);
    // Without force, the earlier cutter path refuses the output like any of its files.
    let e = outcome(&["profile", "--out", s(&out)]);
    assert!(e.contains("exists (use --force to overwrite)"), "{e}");
    assert_eq!(outcome(&["profile", "--out", s(&out), "--force"]), "OK");
    let after = listing(&out);
    assert!(!after.contains(&"cutter.csv".to_owned()), "{after:?}");
    let mut expect: Vec<String> = without.into_iter().filter(|n| n != "cutter.csv").collect();
    expect.sort();
    assert_eq!(after, expect);
    fs::remove_dir_all(&d).unwrap();
}

// Defect 12: a failed write of --version or --help is an error naming standard output.
#[test]
fn version_and_help_into_a_full_disk_fail_naming_standard_output() {
    for args in [&["--version"][..], &["--help"], &["run", "--help"]] {
        let (code, err) = child(args, "full", &[]);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(
            err.contains("camsim: error: standard output: write failed: No space left on device"),
            "{args:?}: {err}"
        );
    }
    let (code, err) = child(&["--version"], "null", &[]);
    assert_eq!(code, 0, "{err}");
}

// Defect 12: a closed pipe ends the run quietly (`run --csv /dev/stdout | head -c 100`).
#[test]
fn a_closed_pipe_on_the_csv_ends_quietly() {
    let (code, err) = child(
        &["run", "--revolutions", "1", "--csv", "/dev/stdout"],
        "pipe100",
        &[],
    );
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("camsim:"), "{err}");
    assert!(err.contains("EXIT 0"), "{err}");
}

// Defect 15: the command does not run on the caller's stack. The child's test thread
// (which calls `main_from`, as the binary's main thread does) gets 256 KiB, as
// `ulimit -s 256` gives the binary's main thread.
#[test]
fn a_run_needs_no_more_than_256_kib_of_the_callers_stack() {
    let (code, err) = child(
        &["run", "--revolutions", "1"],
        "null",
        &[("RUST_MIN_STACK", "262144")],
    );
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("EXIT 0"), "{err}");
}

// Defect 5: `run --plot DIR --force` after a run on an actual cam leaves no profile plot
// of the earlier cam; the report lists what the run wrote.
#[test]
fn a_forced_run_plot_leaves_no_profile_plot_of_the_earlier_cam() {
    let d = scratch("run-plot-set");
    let plots = d.join("plots");
    let first = outcome(&["run", "--revolutions", "1", "--actual", "--plot", s(&plots)]);
    assert_eq!(first, "OK");
    assert!(plots.join("profile_deviation.png").exists());
    let argv = [
        "camsim",
        "run",
        "--revolutions",
        "1",
        "--plot",
        s(&plots),
        "--force",
    ];
    let cli::Command::Run(args) = cli::parse_from(argv).unwrap().command else {
        unreachable!()
    };
    let report = camsim::cmd::run::report(&args, camsim::units::Units::Inch).unwrap();
    let left = listing(&plots);
    assert!(
        !left.contains(&"profile_deviation.png".to_owned()),
        "{left:?}"
    );
    let written: Vec<String> = (report.files.iter())
        .map(|f| {
            Path::new(f)
                .file_name()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    let mut sorted = written.clone();
    sorted.sort();
    assert_eq!(sorted, left, "the report lists exactly the files in DIR");
    assert_eq!(written.len(), camsim::plot::FILES.len());
    fs::remove_dir_all(&d).unwrap();
}

// Defect 11: a command's failed write to standard output names standard output (6b065a3:
// "No space left on device (os error 28)" alone), firmware-check's lines included
// (6b065a3's println! there would panic).
#[test]
fn a_full_standard_output_is_named() {
    let d = scratch("full-stdout");
    let mx = d.join("memory.x");
    fs::write(
        &mx,
        "MEMORY { FLASH : ORIGIN = 0, LENGTH = 128K\n RAM : ORIGIN = 0, LENGTH = 16K }\n",
    )
    .unwrap();
    let log = d.join("boot.log");
    fs::write(&log, "ERROR boot: table build failed: step budget exceeded\nERROR alarm asserted (LED0 low: true), stopped: boot failed\n").unwrap();
    let fw = [
        "firmware-check",
        "--memory-x",
        s(&mx),
        "--boot-fault",
        s(&log),
    ];
    for args in [&["scene", "--default"][..], &fw] {
        let (code, err) = child(args, "full", &[]);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(
            err.contains("camsim: error: standard output: write failed: No space left on device"),
            "{args:?}: {err}"
        );
        let (code, err) = child(args, "null", &[]);
        assert_eq!(code, 0, "{args:?}: {err}");
    }
}
