//! Bounds on long studies (`camsim montecarlo`): an estimate of time after the first
//! sample, a refusal past the stated limit unless `--allow-long` asks for it (memory needs
//! no limit: the statistics stream, `crate::stats::study`), and progress lines on standard error when it is not a terminal (a batch
//! job's log), where the progress bar is hidden.

use std::io::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use anyhow::{bail, Result};

/// The longest a study may be estimated to run without `--allow-long`: 24 hours, the
/// usual wall-time limit of a batch queue; beyond it a run is lost to the queue's kill.
pub const MAX_STUDY_SECONDS: f64 = 24.0 * 3600.0;

/// The option that lifts the limit.
pub const ALLOW_LONG: &str = "--allow-long";

/// Refuses a study whose first sample took `first_s` seconds when `samples` samples on
/// `threads` threads would take longer than [`MAX_STUDY_SECONDS`], unless `allow`;
/// returns the estimate, s.
pub fn check_time(first_s: f64, samples: u64, threads: usize, allow: bool) -> Result<f64> {
    let estimate = first_s * samples as f64 / threads.max(1) as f64;
    if estimate > MAX_STUDY_SECONDS && !allow {
        bail!(
            "--samples {samples}: would take about {} on {threads} threads (the first sample took {first_s:.2} s), over the {} limit of a study (split it with --shard K/N and merge, or use {ALLOW_LONG})",
            duration(estimate),
            duration(MAX_STUDY_SECONDS)
        );
    }
    Ok(estimate)
}

/// The most samples any study takes: an explicit `--samples` and the count a `--p-max`
/// implies are held to the same 1 000 000 (at the reference's few milliseconds a
/// two-revolution sample, about a day on one core: [`MAX_STUDY_SECONDS`]).
pub const MAX_STUDY_SAMPLES: u64 = 1_000_000;

/// Refuses a `--p-max` whose study needs more than [`MAX_STUDY_SAMPLES`] cams a step
/// (`needed`, the fewest whose upper bound with no jump is `p_max`), naming the smallest
/// p the limit allows (`smallest`, the bound at [`MAX_STUDY_SAMPLES`] cams).
pub fn check_p_max(p_max: f64, needed: u64, smallest: f64) -> Result<()> {
    if needed > MAX_STUDY_SAMPLES {
        // Rounded up to 3 significant digits, so the p printed is itself allowed.
        let scale = 10f64.powi(smallest.log10().floor() as i32 - 2);
        let smallest = (smallest / scale).ceil() * scale;
        bail!(
            "--p-max {p_max:e}: showing it needs more than {MAX_STUDY_SAMPLES} actual cams a step with no jump, over the sample limit of a study (the smallest --p-max it allows is {smallest:.2e})"
        );
    }
    Ok(())
}

/// Refuses a search of up to `steps` steps of `samples` samples each whose estimate from
/// one sample (`first_s` seconds) on `threads` threads is over [`MAX_STUDY_SECONDS`]:
/// the same time limit as a Monte Carlo study's, checked before the search starts.
pub fn check_search(first_s: f64, samples: u64, steps: u64, threads: usize) -> Result<f64> {
    let total = samples.saturating_mul(steps);
    let estimate = first_s * total as f64 / threads.max(1) as f64;
    if estimate > MAX_STUDY_SECONDS {
        bail!(
            "up to {steps} search steps of {samples} actual cams would take about {} on {threads} threads (one cam took {first_s:.3} s), over the {} limit of a study (give a larger --p-max or fewer --samples)",
            duration(estimate),
            duration(MAX_STUDY_SECONDS)
        );
    }
    Ok(estimate)
}

/// A duration in words: "3.2 h", "12 min", "40 s", "5.1 days".
pub fn duration(s: f64) -> String {
    if s >= 2.0 * 86_400.0 {
        format!("{:.1} days", s / 86_400.0)
    } else if s >= 3600.0 {
        format!("{:.1} h", s / 3600.0)
    } else if s >= 60.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{s:.0} s")
    }
}

/// A progress bar on standard error when it is a terminal and `want`, hidden otherwise,
/// drawn with indicatif's `template` (`{pos}/{len} samples, eta {eta}`).
pub fn progress_bar(len: u64, want: bool, template: &str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    use std::io::IsTerminal;
    if !want || !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

/// Seconds between progress lines: 10, or `CAMSIM_PROGRESS_INTERVAL_S` (a positive
/// number) where a batch log wants them more or less often.
pub fn progress_interval() -> Duration {
    std::env::var("CAMSIM_PROGRESS_INTERVAL_S")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s > 0.0 && *s < 1e6)
        .map_or(Duration::from_secs(10), Duration::from_secs_f64)
}

/// Progress lines on standard error, at most one an interval:
/// `camsim montecarlo: 1200/10000 samples (12.0 %), 3.1 samples/s, about 47 min left`.
#[derive(Debug)]
pub struct ProgressLines {
    what: String,
    total: u64,
    done: AtomicU64,
    start: Instant,
    interval: Duration,
    last: Mutex<Instant>,
    on: bool,
}

impl ProgressLines {
    /// Lines for `total` items of `what`, on when `on` (a batch run: the progress bar is
    /// hidden because standard error is not a terminal).
    pub fn new(what: &str, total: u64, on: bool) -> Self {
        let now = Instant::now();
        Self {
            what: what.to_owned(),
            total,
            done: AtomicU64::new(0),
            start: now,
            interval: progress_interval(),
            last: Mutex::new(now),
            on,
        }
    }

    /// Whether standard error is not a terminal (where the lines replace the bar).
    pub fn batch() -> bool {
        use std::io::IsTerminal;
        !std::io::stderr().is_terminal()
    }

    /// One more item done; prints a line if an interval has passed since the last.
    pub fn inc(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if !self.on {
            return;
        }
        let now = Instant::now();
        let Ok(mut last) = self.last.try_lock() else {
            return;
        };
        if now.duration_since(*last) < self.interval {
            return;
        }
        *last = now;
        let line = self.line(done, now.duration_since(self.start).as_secs_f64());
        let _ = writeln!(std::io::stderr().lock(), "{line}");
    }

    /// The line at `done` items after `elapsed` seconds.
    pub fn line(&self, done: u64, elapsed: f64) -> String {
        let rate = done as f64 / elapsed.max(1e-9);
        let left = self.total.saturating_sub(done) as f64 / rate.max(1e-12);
        format!(
            "{}: {done}/{} samples ({:.1} %), {rate:.2} samples/s, about {} left",
            self.what,
            self.total,
            100.0 * done as f64 / self.total.max(1) as f64,
            duration(left)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_refuse_and_name_the_way_out() {
        // 1 s a sample, 2 threads: 172 800 samples is exactly a day.
        assert_eq!(check_time(1.0, 172_800, 2, false).unwrap(), 86_400.0);
        let e = check_time(1.0, 172_802, 2, false).unwrap_err().to_string();
        assert!(
            e.contains("about 24.0 h") && e.contains("24.0 h limit"),
            "{e}"
        );
        assert!(check_time(1.0, 1_000_000, 2, true).is_ok());
    }

    #[test]
    fn progress_lines_say_where_and_how_long() {
        let p = ProgressLines::new("camsim montecarlo", 10_000, false);
        assert_eq!(
            p.line(1_200, 400.0),
            "camsim montecarlo: 1200/10000 samples (12.0 %), 3.00 samples/s, about 49 min left"
        );
        assert_eq!(duration(5.0 * 86_400.0), "5.0 days");
    }
}
