//! Output files under interrupts: a run killed by SIGINT or SIGTERM while writing
//! leaves no temporary behind, no new target, and an old target byte-identical, and
//! exits with 128 + the signal.
//!
//! The writer is this test binary itself, started again in a child mode (the ignored
//! test `child_writer`, driven by environment variables): it opens an output, reports
//! its temporary on stdout, then writes slowly until it is killed.

use std::fs;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use camsim::output::{is_temp_name, Plan};

mod common;
use common::{listing, scratch};

const ENV_TARGET: &str = "CAMSIM_OUTPUT_CHILD_TARGET";
const ENV_MODE: &str = "CAMSIM_OUTPUT_CHILD_MODE";
/// The arguments that start this test binary in its child mode.
const CHILD: [&str; 5] = [
    "child_writer",
    "--exact",
    "--ignored",
    "--nocapture",
    "--test-threads=1",
];

/// The child mode: does nothing unless the parent test set the environment.
#[test]
#[ignore = "child mode of the interrupt tests"]
fn child_writer() {
    let Some(target) = std::env::var_os(ENV_TARGET).map(PathBuf::from) else {
        return;
    };
    let mode = std::env::var(ENV_MODE).unwrap_or_default();
    let deadline = Instant::now() + Duration::from_secs(10);
    let mut stdout = std::io::stdout();
    if mode == "cleanup" {
        // The stale clean-up of the next output in the directory `target`.
        let n = camsim::output::remove_stale_temporaries(&target);
        writeln!(stdout, "REMOVED {n}").unwrap();
        stdout.flush().unwrap();
        return;
    }
    if mode == "fill" {
        // Writes as fast as it can until a write fails (the file size limit), then says
        // how it failed; the output is dropped with the error, as a command's `?` does.
        let mut out = Plan::new(false)
            .file("--csv", &target)
            .unwrap()
            .open()
            .unwrap();
        let tmp = out.temp_path().unwrap().to_owned();
        writeln!(stdout, "READY {}", tmp.display()).unwrap();
        let row = [b'x'; 1000];
        let err = loop {
            if let Err(e) = out.write_all(&row).and_then(|_| out.flush()) {
                break e;
            }
            if Instant::now() > deadline {
                panic!("no file size limit");
            }
        };
        drop(out);
        writeln!(stdout, "FAILED {err}").unwrap();
        stdout.flush().unwrap();
        return;
    }
    if mode == "dir" {
        let mut out = Plan::new(false)
            .dir("--plot", &target, &["a.png", "b.png"])
            .unwrap()
            .open()
            .unwrap();
        out.write("a.png", b"complete a").unwrap();
        let b = out.path("b.png").unwrap();
        let mut f = fs::File::create(&b).unwrap();
        writeln!(stdout, "READY {}", b.display()).unwrap();
        stdout.flush().unwrap();
        while Instant::now() < deadline {
            f.write_all(b"partial b ").unwrap();
            std::thread::sleep(Duration::from_millis(5));
        }
        drop(f);
        out.commit().unwrap();
    } else {
        let force = mode == "force";
        let mut out = Plan::new(force)
            .file("--csv", &target)
            .unwrap()
            .open()
            .unwrap();
        writeln!(out, "t_s,y_in").unwrap();
        out.flush().unwrap();
        let tmp = out.temp_path().unwrap().to_owned();
        writeln!(stdout, "READY {}", tmp.display()).unwrap();
        stdout.flush().unwrap();
        let mut i = 0u64;
        while Instant::now() < deadline {
            writeln!(out, "{i},{}", i * 3).unwrap();
            out.flush().unwrap();
            i += 1;
            std::thread::sleep(Duration::from_millis(5));
        }
        out.commit().unwrap();
    }
}

/// Starts the child writer on `target`, waits until its temporary holds data, sends
/// `signal` ("INT" or "TERM") and returns the exit code and the temporary's path.
fn kill_mid_write(target: &Path, mode: &str, signal: &str) -> (Option<i32>, PathBuf) {
    let (child, tmp) = start_writer(target, mode);
    (kill_and_wait(child, signal), tmp)
}

/// Starts the child writer on `target` and waits until its temporary holds data and
/// keeps growing; the child and the temporary's path.
fn start_writer(target: &Path, mode: &str) -> (std::process::Child, PathBuf) {
    let exe = std::env::current_exe().unwrap();
    let mut child = Command::new(exe)
        .args(CHILD)
        .env(ENV_TARGET, target)
        .env(ENV_MODE, mode)
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let stdout = child.stdout.take().unwrap();
    let mut tmp = None;
    for line in BufReader::new(stdout).lines() {
        let line = line.unwrap();
        // (libtest's "test child_writer ... " may start the same line)
        if let Some(i) = line.find("READY ") {
            tmp = Some(PathBuf::from(&line[i + 6..]));
            break;
        }
    }
    let tmp = tmp.expect("the child never got ready");
    // Mid-write: the temporary exists and keeps growing.
    let t0 = Instant::now();
    let first = fs::metadata(&tmp).unwrap().len();
    while fs::metadata(&tmp).unwrap().len() <= first {
        assert!(
            t0.elapsed() < Duration::from_secs(5),
            "the child does not write"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    (child, tmp)
}

/// Sends `signal` to the child and returns its exit code.
fn kill_and_wait(mut child: std::process::Child, signal: &str) -> Option<i32> {
    let status = Command::new("kill")
        .args([format!("-{signal}"), child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let t0 = Instant::now();
    let code = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s.code();
        }
        if t0.elapsed() > Duration::from_secs(5) {
            let _ = child.kill();
            panic!("the child outlived the signal");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    code
}

/// Kills a writer of a new `out.csv` with `signal` mid-write: it exits with `code` (128 +
/// the signal) and leaves no temporary, no target and nothing else in its directory.
fn signal_mid_write_leaves_nothing(signal: &str, code: i32) {
    let d = scratch(&format!("sig-{signal}"));
    let target = d.join("out.csv");
    let (got, tmp) = kill_mid_write(&target, "new", signal);
    assert_eq!(got, Some(code), "SIG{signal}");
    assert_eq!(tmp.parent(), Some(d.as_path()), "SIG{signal}");
    assert!(!tmp.exists(), "SIG{signal}");
    assert!(!target.exists(), "SIG{signal}");
    assert!(listing(&d).is_empty(), "SIG{signal}: {:?}", listing(&d));
    fs::remove_dir_all(&d).unwrap();
}

#[test]
fn sigint_mid_write_leaves_no_target_and_no_temporary() {
    signal_mid_write_leaves_nothing("INT", 130);
}

#[test]
fn sigterm_mid_write_leaves_the_old_file_byte_identical() {
    let d = scratch("term");
    let target = d.join("out.csv");
    let old: Vec<u8> = (0..50_000u32).flat_map(|i| i.to_le_bytes()).collect();
    fs::write(&target, &old).unwrap();
    let (code, tmp) = kill_mid_write(&target, "force", "TERM");
    assert_eq!(code, Some(143));
    assert!(!tmp.exists());
    assert_eq!(fs::read(&target).unwrap(), old);
    assert_eq!(listing(&d), ["out.csv"]);
    fs::remove_dir_all(&d).unwrap();
}

#[test]
fn sigint_mid_plot_removes_the_partial_files_and_the_new_directory() {
    let d = scratch("dir");
    let plots = d.join("plots");
    let (code, tmp) = kill_mid_write(&plots, "dir", "INT");
    assert_eq!(code, Some(130));
    assert_eq!(tmp.parent(), Some(plots.as_path()));
    assert!(is_temp_name(&tmp.file_name().unwrap().to_string_lossy()));
    assert!(!plots.exists(), "{:?}", listing(&plots));
    assert!(listing(&d).is_empty());
    fs::remove_dir_all(&d).unwrap();
}

/// Issue 20, point 5: a dropped ssh session (SIGHUP) and SIGQUIT clean up like SIGINT.
#[test]
fn sighup_and_sigquit_mid_write_leave_no_temporary() {
    for (sig, code) in [("HUP", 129), ("QUIT", 131)] {
        signal_mid_write_leaves_nothing(sig, code);
    }
}

/// Issue 33, defect 13: every catchable signal that ends a process cleans up like SIGINT
/// (the user signals and the three timers left tens of MB behind).
#[test]
fn the_user_and_timer_signals_mid_write_leave_no_temporary() {
    for (sig, code) in [
        ("USR1", 138),
        ("USR2", 140),
        ("ALRM", 142),
        ("VTALRM", 154),
        ("PROF", 155),
    ] {
        signal_mid_write_leaves_nothing(sig, code);
    }
}

/// Issue 33, defect 2: the stale clean-up of a run in another PID namespace (a container
/// on a shared volume, where the writer's process id is unknown or another process's)
/// leaves a live run's temporary alone, and the live run commits.
#[test]
fn a_clean_up_in_another_pid_namespace_leaves_a_live_temporary() {
    let d = scratch("pidns");
    let target = d.join("out.csv");
    let (child, tmp) = start_writer(&target, "new");
    let exe = std::env::current_exe().unwrap();
    let out = Command::new("unshare")
        .args(["--pid", "--fork", "--mount-proc"])
        .arg(&exe)
        .args(CHILD)
        .env(ENV_TARGET, &d)
        .env(ENV_MODE, "cleanup")
        .stderr(Stdio::null())
        .output();
    let text = match &out {
        Ok(o) if o.status.success() => String::from_utf8_lossy(&o.stdout).into_owned(),
        // No user namespaces here (unprivileged, or no unshare): the rest still runs.
        _ => {
            eprintln!("unshare --pid unavailable: the clean-up runs in this namespace");
            format!("REMOVED {}", camsim::output::remove_stale_temporaries(&d))
        }
    };
    assert!(text.contains("REMOVED 0"), "{text}");
    assert!(tmp.exists(), "the live temporary was removed");
    assert_eq!(kill_and_wait(child, "INT"), Some(130));
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
    fs::remove_dir_all(&d).unwrap();
}

/// Issue 20, point 5: over `ulimit -f` the write fails with an error naming the output
/// and the limit (SIGXFSZ is caught, not fatal), and the temporary goes with the error.
#[test]
fn a_write_over_the_file_size_limit_is_an_error_and_leaves_no_temporary() {
    let d = scratch("ulimit");
    let target = d.join("big.csv");
    let exe = std::env::current_exe().unwrap();
    // 100 blocks of 512 bytes (bash and dash count ulimit -f in 512-byte blocks... or
    // 1024: either way tens of kB, far below what the child writes in 10 s).
    let out = Command::new("sh")
        .arg("-c")
        .arg("ulimit -f 100 && exec \"$0\" child_writer --exact --ignored --nocapture --test-threads=1")
        .arg(&exe)
        .env(ENV_TARGET, &target)
        .env(ENV_MODE, "fill")
        .stderr(Stdio::null())
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{:?}: {text}", out.status);
    let failed = text
        .lines()
        .find_map(|l| l.find("FAILED ").map(|i| l[i + 7..].to_owned()))
        .unwrap_or_else(|| panic!("no failure reported: {text}"));
    assert!(
        failed.contains(&format!("--csv {}: write failed", target.display())),
        "{failed}"
    );
    assert!(failed.contains("ulimit -f"), "{failed}");
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
    fs::remove_dir_all(&d).unwrap();
}

/// The whole flow a command follows: plan every output, run, write, commit.
#[test]
fn plan_run_write_commit() {
    let d = scratch("flow");
    let csv = d.join("out.csv");
    let plots = d.join("plots");
    fs::write(&csv, b"old").unwrap();
    // Refused: the existing CSV without --force; the plot directory is not created.
    let mut plan = Plan::new(false);
    let e = plan.file("--csv", &csv).unwrap_err();
    assert_eq!(
        format!("{e:#}"),
        format!("--csv {}: exists (use --force to overwrite)", csv.display())
    );
    assert_eq!(listing(&d), ["out.csv"]);
    // Accepted with --force.
    let mut plan = Plan::new(true);
    let csv_t = plan
        .file("--csv", &csv)
        .unwrap()
        .limit(100, 1_000_000, "--max-csv-mb N")
        .unwrap();
    let plot_t = plan.dir("--plot", &plots, &["a.png"]).unwrap();
    let mut out = csv_t.open().unwrap();
    let mut dir = plot_t.open().unwrap();
    for i in 0..10 {
        writeln!(out, "{i}").unwrap();
    }
    dir.write("a.png", b"png").unwrap();
    assert_eq!(fs::read(&csv).unwrap(), b"old");
    out.commit().unwrap();
    dir.commit().unwrap();
    let expect: String = (0..10).map(|i| format!("{i}\n")).collect();
    assert_eq!(fs::read_to_string(&csv).unwrap(), expect);
    assert_eq!(fs::read(plots.join("a.png")).unwrap(), b"png");
    assert_eq!(listing(&d), ["out.csv", "plots"]);
    assert_eq!(listing(&plots), ["a.png"]);
    fs::remove_dir_all(&d).unwrap();
}
