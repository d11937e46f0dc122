//! The index-pulse state machine (`camsim_core::IndexPulse`) on synthetic pulse trains:
//! constant speed, a ramp, the 32-bit counter wrapping, bounces, a dropout, a stop, speeds
//! outside the table's range and above the machine's limit, and a "recorded" train with
//! seeded jitter, bounces and dropouts; and `IndexPulse::service`, the loop step a board
//! runs on its capture timer (`CaptureTimer`), on a recorded list of timer events.
//!
//! Tolerances are derived, not tuned: a capture is exact to half a tick at each end (the
//! pulse times below are rounded to whole ticks), so a measured period N_m is within one
//! tick of the true N = 60 f / n and the speed within n / (N - 1) ≈ n² / (60 f)
//! (`resolution`), plus the roundings of the final division in T.

use camsim_core::{
    CaptureEvent, CaptureTimer, IndexPulse, IndexPulseConfig, JumpAlarm, Rejection, SpeedReading,
};

const F: u32 = 1_000_000;

/// The board's configuration: 1 MHz ticks, the chip table's 300..800 rpm, a machine
/// limit of 1600 rpm, lost below 150 rpm, bounce under 25 %, agreement within 25 %.
fn config() -> IndexPulseConfig {
    IndexPulseConfig {
        tick_hz: F,
        min_rpm: 300,
        max_rpm: 800,
        limit_rpm: 1600,
        lost_rpm: 150,
        bounce_percent: 25,
        max_change_percent: 25,
    }
}

fn machine<T: camsim_core::Real>() -> IndexPulse<T> {
    IndexPulse::new(config()).expect("valid config")
}

/// Speed error bound of one reading at `rpm`: one tick of period error (n / (N - 1)),
/// plus 4 ulp of T for the conversion and division.
fn resolution(rpm: f64, ulp: f64) -> f64 {
    let n = 60.0 * f64::from(F) / rpm;
    rpm / (n - 1.0) + 4.0 * ulp * rpm
}

/// Pulse counts (wrapping u32) at the given speeds, one revolution each, from `start`.
fn train(start: u32, rpm: &[f64]) -> Vec<u32> {
    let mut t = 0.0f64;
    let mut out = vec![start];
    for n in rpm {
        t += 60.0 * f64::from(F) / n;
        out.push(start.wrapping_add(t.round() as u64 as u32));
    }
    out
}

fn run<T: camsim_core::Real>(ip: &mut IndexPulse<T>, times: &[u32]) -> Vec<SpeedReading<T>> {
    times.iter().map(|t| ip.capture(*t)).collect()
}

#[test]
fn constant_speed_reads_exactly_after_two_agreeing_periods() {
    // 600 rpm at 1 MHz: exactly 100 000 ticks per revolution.
    let times = train(1_000, &[600.0; 6]);
    let r = run(&mut machine::<f32>(), &times);
    assert_eq!(r[0], SpeedReading::Acquiring); // the first pulse: a reference only
    assert_eq!(r[1], SpeedReading::Acquiring); // one period: a candidate
    for x in &r[2..] {
        assert_eq!(*x, SpeedReading::Rpm(600.0f32));
    }
    let r = run(&mut machine::<f64>(), &times);
    assert_eq!(r[6], SpeedReading::Rpm(600.0f64));
}

#[test]
fn constant_speed_with_a_fractional_period_is_within_one_tick() {
    // 700 rpm: 85 714.29 ticks, so measured periods are 85 714 or 85 715.
    let times = train(0, &[700.0; 20]);
    let tol = resolution(700.0, f32::EPSILON as f64);
    // One tick: n²/(60 f) = 0.00817 rpm; f32's four roundings add 3.3e-4 rpm.
    assert!((tol - 0.008_17 - 3.3e-4).abs() < 1e-5, "{tol}");
    let r = run(&mut machine::<f32>(), &times);
    for x in &r[2..] {
        let SpeedReading::Rpm(v) = *x else {
            panic!("{x:?}")
        };
        assert!((f64::from(v) - 700.0).abs() <= tol, "{v}");
    }
    // Both period values occur, so the bound is actually exercised on both sides.
    let periods: Vec<u32> = times.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(periods.contains(&85_714) && periods.contains(&85_715));
}

#[test]
fn ramp_tracks_every_revolution() {
    // 300 -> 800 rpm in 5 rpm per revolution (1.7 % per revolution at most).
    let rpm: Vec<f64> = (0..=100).map(|k| 300.0 + 5.0 * k as f64).collect();
    let times = train(12_345, &rpm);
    let r = run(&mut machine::<f64>(), &times);
    // Reading k (pulse k) measures revolution k - 1 at rpm[k - 1].
    for (k, x) in r.iter().enumerate().skip(2) {
        let n = rpm[k - 1];
        let SpeedReading::Rpm(v) = *x else {
            panic!("pulse {k}: {x:?}")
        };
        assert!(
            (v - n).abs() <= resolution(n, f64::EPSILON),
            "pulse {k}: {v} vs {n}"
        );
    }
}

#[test]
fn the_32_bit_counter_wraps_without_a_trace() {
    // Start 250 000 ticks before the wrap: the third period straddles it.
    let start = u32::MAX - 250_000;
    let times = train(start, &[600.0; 8]);
    assert!(times.windows(2).any(|w| w[1] < w[0]), "the train must wrap");
    let mut ip = machine::<f32>();
    let r = run(&mut ip, &times);
    for x in &r[2..] {
        assert_eq!(*x, SpeedReading::Rpm(600.0f32));
    }
    // Polling across the wrap is no timeout either.
    let last = times[times.len() - 1];
    assert_eq!(ip.poll(last.wrapping_add(399_999)), None);
}

#[test]
fn a_bounce_50_us_after_a_pulse_is_ignored() {
    let mut t = train(0, &[600.0; 4]);
    t.insert(3, t[2] + 50); // a bounce 50 µs after pulse 2
    let r = run(&mut machine::<f32>(), &t);
    assert_eq!(r[2], SpeedReading::Rpm(600.0f32));
    assert_eq!(
        r[3],
        SpeedReading::Rejected(Rejection::TooShort { period_ticks: 50 })
    );
    // The next real pulse is timed from the real one before the bounce.
    assert_eq!(r[4], SpeedReading::Rpm(600.0f32));
    assert_eq!(r[5], SpeedReading::Rpm(600.0f32));

    // During the acquisition too; the period that spans the ignored pulse cannot be the
    // one that confirms a speed, so the acquisition takes one pulse more.
    let mut t = train(0, &[600.0; 3]);
    t.insert(1, 50);
    let r = run(&mut machine::<f32>(), &t);
    assert_eq!(
        r,
        [
            SpeedReading::Acquiring,
            SpeedReading::Rejected(Rejection::TooShort { period_ticks: 50 }),
            SpeedReading::Acquiring,
            SpeedReading::Acquiring,
            SpeedReading::Rpm(600.0f32),
        ]
    );
}

#[test]
fn a_pulse_under_the_bounce_fraction_of_the_period_is_ignored() {
    // 300 rpm: 200 000 ticks. 45 000 ticks is slower than the 1600 rpm limit (37 500)
    // but under 25 % of the period (50 000): a bounce, not a speed.
    let mut t = train(0, &[300.0; 4]);
    t.insert(3, t[2] + 45_000);
    let r = run(&mut machine::<f64>(), &t);
    assert_eq!(r[2], SpeedReading::Rpm(300.0));
    assert_eq!(
        r[3],
        SpeedReading::Rejected(Rejection::Bounce {
            period_ticks: 45_000
        })
    );
    assert_eq!(r[4], SpeedReading::Rpm(300.0));
}

#[test]
fn a_noise_pulse_mid_revolution_never_reads_as_a_speed() {
    // 60 % into a 300 rpm revolution: neither a bounce (>= 25 %) nor agreeing (> 25 % off).
    let mut t = train(0, &[300.0; 5]);
    t.insert(3, t[2] + 120_000);
    let r = run(&mut machine::<f64>(), &t);
    assert_eq!(
        r[3],
        SpeedReading::Rejected(Rejection::Step {
            period_ticks: 120_000
        })
    );
    // 80 000 ticks to the next real pulse: agrees with neither 200 000 nor 120 000.
    assert_eq!(
        r[4],
        SpeedReading::Rejected(Rejection::Step {
            period_ticks: 80_000
        })
    );
    assert_eq!(r[5], SpeedReading::Rpm(300.0));
    assert_eq!(r[6], SpeedReading::Rpm(300.0));
}

#[test]
fn a_dropout_is_rejected_then_the_speed_returns() {
    let mut t = train(0, &[600.0; 6]);
    t.remove(3); // pulse 3 missing: one period of 200 000 ticks
    let r = run(&mut machine::<f32>(), &t);
    assert_eq!(r[2], SpeedReading::Rpm(600.0f32));
    assert_eq!(
        r[3],
        SpeedReading::Rejected(Rejection::Step {
            period_ticks: 200_000
        })
    );
    assert_eq!(r[4], SpeedReading::Rpm(600.0f32));
    assert_eq!(r[5], SpeedReading::Rpm(600.0f32));
}

#[test]
fn a_genuine_speed_step_is_believed_after_one_confirming_revolution() {
    // 400 -> 700 rpm in one revolution (a 43 % shorter period): rejected once, then read.
    let mut rpm = vec![400.0; 4];
    rpm.extend([700.0; 4]);
    let t = train(0, &rpm);
    let r = run(&mut machine::<f64>(), &t);
    assert_eq!(r[4], SpeedReading::Rpm(400.0));
    assert!(matches!(
        r[5],
        SpeedReading::Rejected(Rejection::Step { .. })
    ));
    for x in &r[6..] {
        let SpeedReading::Rpm(v) = *x else {
            panic!("{x:?}")
        };
        assert!((v - 700.0).abs() <= resolution(700.0, f64::EPSILON));
    }
}

#[test]
fn stop_is_lost_after_one_revolution_at_the_slowest_speed() {
    let t = train(7, &[600.0; 3]);
    let mut ip = machine::<f32>();
    run(&mut ip, &t);
    let last = t[3];
    // lost_rpm 150: 400 000 ticks.
    assert_eq!(ip.poll(last + 100_000), None);
    assert_eq!(ip.poll(last + 400_000), None);
    assert_eq!(ip.poll(last + 400_001), Some(SpeedReading::Lost));
    assert_eq!(ip.poll(last + 500_000), None); // reported once
    assert_eq!(ip.last_period_ticks(), None);
    // The machine restarts: a new acquisition.
    let t = train(last + 2_000_000, &[600.0; 3]);
    let r = run(&mut ip, &t);
    assert_eq!(
        r,
        [
            SpeedReading::Acquiring,
            SpeedReading::Acquiring,
            SpeedReading::Rpm(600.0f32),
            SpeedReading::Rpm(600.0f32),
        ]
    );
    // A pulse after a gap nobody polled is Lost too, and starts over.
    let late = t[3] + 400_001;
    assert_eq!(ip.capture(late), SpeedReading::Lost);
    assert_eq!(ip.capture(late + 100_000), SpeedReading::Acquiring);
}

#[test]
fn speeds_outside_the_table_are_flagged_not_extrapolated() {
    for (n, inside) in [
        (150.0, false), // the slowest measured speed: 400 000 ticks, not yet lost
        (200.0, false),
        (299.0, false),
        (300.0, true),
        (800.0, true),
        (801.0, false),
        (900.0, false),
        (1600.0, false), // the machine's limit: still measured
    ] {
        let t = train(0, &[n; 4]);
        let r = run(&mut machine::<f64>(), &t);
        for x in &r[2..] {
            let v = match *x {
                SpeedReading::Rpm(v) if inside => v,
                SpeedReading::OutOfRange(v) if !inside => v,
                other => panic!("{n} rpm: {other:?}"),
            };
            assert!((v - n).abs() <= resolution(n, f64::EPSILON), "{n}: {v}");
        }
    }
    // 149 rpm: each revolution is longer than the timeout.
    let t = train(0, &[149.0; 4]);
    let r = run(&mut machine::<f64>(), &t);
    assert_eq!(r[0], SpeedReading::Acquiring);
    assert!(r[1..].iter().all(|x| *x == SpeedReading::Lost));
}

#[test]
fn a_train_above_the_limit_never_reads_as_half_its_speed() {
    // 1700 rpm: every period is TooShort; two of them (850 rpm, in the table's range
    // neighbourhood) must not establish a speed.
    let t = train(0, &[1700.0; 30]);
    let r = run(&mut machine::<f64>(), &t);
    for x in &r {
        assert!(x.vouched_rpm().is_none(), "{x:?}");
        assert!(!matches!(x, SpeedReading::OutOfRange(_)), "{x:?}");
    }
    // Accelerating through the limit from a believed speed: no reading below 1000 rpm
    // once the train is faster than the limit.
    let rpm: Vec<f64> = (0..40).map(|k| 1400.0 + 10.0 * k as f64).collect();
    let t = train(0, &rpm);
    let r = run(&mut machine::<f64>(), &t);
    for (k, x) in r.iter().enumerate().skip(1) {
        if let SpeedReading::OutOfRange(v) | SpeedReading::Rpm(v) = *x {
            assert!((v - rpm[k - 1]).abs() <= resolution(rpm[k - 1], f64::EPSILON));
            assert!(rpm[k - 1] <= 1600.0, "pulse {k}: {v}");
        }
    }
}

/// splitmix64: a small seeded generator, so the "recording" is the same on every run.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn a_recorded_train_with_jitter_bounces_and_dropouts() {
    // 600 revolutions: the speed wanders 560..740 rpm (a slow sine), each edge jitters
    // uniformly by up to ±J ticks, 5 % of the pulses bounce 20..100 µs later, 1 % are
    // missed. The counter starts near the wrap.
    const J: f64 = 20.0;
    let mut rng = Rng(0x5EED_CA75);
    let start = u32::MAX - 3_000_000;
    let mut t_true = 0.0f64; // ideal edge time, ticks
    let mut edges: Vec<(f64, bool, bool)> = Vec::new(); // (time, bounces, missed)
    let mut rpm_of_rev = Vec::new();
    for k in 0..600 {
        edges.push((t_true, rng.unit() < 0.05, k > 3 && rng.unit() < 0.01));
        let n = 650.0 + 90.0 * (k as f64 * 0.02).sin();
        rpm_of_rev.push(n);
        t_true += 60.0 * f64::from(F) / n;
    }
    let mut ip = machine::<f32>();
    let (mut bounces, mut missed, mut readings) = (0, 0, 0);
    let mut last_real: Option<usize> = None;
    let mut after_miss = false;
    for (k, &(t, bounce, miss)) in edges.iter().enumerate() {
        if miss {
            missed += 1;
            after_miss = true;
            continue;
        }
        let jitter = (rng.unit() * 2.0 - 1.0) * J;
        let count = start.wrapping_add((t + jitter).round() as u64 as u32);
        match ip.capture(count) {
            SpeedReading::Rpm(v) => {
                readings += 1;
                // The true mean speed over revolution k - 1; the period is off by at most
                // 2 J + 1 ticks.
                let n = rpm_of_rev[k - 1];
                let period = 60.0 * f64::from(F) / n;
                let tol = n * (2.0 * J + 1.0) / (period - 2.0 * J - 1.0)
                    + 4.0 * f64::from(f32::EPSILON) * n;
                assert!(
                    (f64::from(v) - n).abs() <= tol,
                    "rev {k}: {v} vs {n} (tol {tol})"
                );
                assert_eq!(last_real, Some(k - 1), "rev {k}: read across a gap");
                assert!(!after_miss);
            }
            SpeedReading::Rejected(Rejection::Step { period_ticks }) => {
                assert!(after_miss, "rev {k}: a step without a dropout");
                // It spans two revolutions, to the jitter.
                let two = edges[k].0 - edges[k - 2].0;
                assert!((f64::from(period_ticks) - two).abs() <= 2.0 * J + 1.0);
                after_miss = false;
            }
            SpeedReading::Acquiring => assert!(k < 2, "rev {k}"),
            other => panic!("rev {k}: {other:?}"),
        }
        last_real = Some(k);
        if bounce {
            bounces += 1;
            let b = count.wrapping_add(20 + (rng.unit() * 80.0) as u32);
            assert!(matches!(
                ip.capture(b),
                SpeedReading::Rejected(Rejection::TooShort { .. })
            ));
        }
    }
    // Every revolution read except the two of the acquisition, each dropout's two
    // revolutions, and nothing else.
    assert!(
        bounces > 15 && missed > 2,
        "{bounces} bounces, {missed} missed"
    );
    assert_eq!(readings, 600 - 2 - 2 * missed);
}

#[test]
fn every_reading_but_rpm_holds_the_alarm_in_its_safe_state() {
    // The board's rule: margin = jump onset - rpm for Rpm readings, NaN otherwise.
    let jump_rpm = 697.0f32;
    let mut alarm = JumpAlarm::new(50.0f32, 100.0).unwrap();
    let mut ip = machine::<f32>();
    let mut t = train(0, &[500.0; 6]);
    t.insert(4, t[3] + 50); // a bounce
    let mut states = Vec::new();
    for c in t {
        let r = ip.capture(c);
        let margin = r.vouched_rpm().map_or(f32::NAN, |n| jump_rpm - n);
        states.push((r.vouched_rpm().is_some(), alarm.update(margin)));
    }
    // Acquiring x2: on; 500 rpm (margin 197 > 100): off; bounce: on; 500 rpm: off again.
    assert_eq!(
        states,
        [
            (false, true),
            (false, true),
            (true, false),
            (true, false),
            (false, true),
            (true, false),
            (true, false),
            (true, false),
        ]
    );
}

/// A capture timer that plays back a list of polls: `Some(event)` a capture, `None` a
/// poll without one at the given counter value.
struct Playback {
    polls: Vec<(Option<CaptureEvent>, u32)>,
    next: usize,
    now: u32,
}

impl CaptureTimer for Playback {
    fn tick_hz(&self) -> u32 {
        F
    }
    fn poll_capture(&mut self) -> Option<CaptureEvent> {
        let (event, now) = *self.polls.get(self.next)?;
        self.next += 1;
        self.now = now;
        event
    }
    fn now(&mut self) -> u32 {
        self.now
    }
}

#[test]
fn service_reads_captures_timeouts_and_overruns_as_capture_and_poll_do() {
    use CaptureEvent::{Edge, Overrun};
    // 600 rpm from near the wrap: 100 000 ticks a revolution.
    let s = u32::MAX - 150_000;
    let at = |k: u32| s.wrapping_add(k * 100_000);
    let polls = vec![
        (Some(Edge(at(0))), at(0)),
        (None, at(0) + 50_000),
        (Some(Edge(at(1))), at(1)),
        (Some(Edge(at(2))), at(2)), // the counter has wrapped
        (Some(Edge(at(3))), at(3)),
        // An edge lost in the capture hardware: the later one is reported.
        (Some(Overrun(at(5))), at(5)),
        (Some(Edge(at(6))), at(6)),
        (Some(Edge(at(7))), at(7)),
        (Some(Edge(at(8))), at(8)),
        // The pulses stop: a poll at 400 000 ticks is not yet lost, one tick later is.
        (None, at(8).wrapping_add(400_000)),
        (None, at(8).wrapping_add(400_001)),
        (None, at(8).wrapping_add(900_000)),
    ];
    let n = polls.len();
    let mut timer = Playback {
        polls,
        next: 0,
        now: 0,
    };
    let mut ip = machine::<f32>();
    let got: Vec<Option<SpeedReading<f32>>> = (0..n).map(|_| ip.service(&mut timer)).collect();
    let r600 = Some(SpeedReading::Rpm(600.0f32));
    assert_eq!(
        got,
        [
            Some(SpeedReading::Acquiring),
            None,
            Some(SpeedReading::Acquiring),
            r600,
            r600,
            Some(SpeedReading::Overrun),
            // After the overrun the later edge was the reference: a new acquisition.
            Some(SpeedReading::Acquiring),
            r600,
            r600,
            None,
            Some(SpeedReading::Lost),
            None,
        ]
    );
    // The same timeline through capture/poll directly, with the overrun as a resync.
    let mut direct = machine::<f32>();
    for (k, (event, now)) in timer.polls.iter().enumerate() {
        let want = match event {
            Some(Edge(t)) => Some(direct.capture(*t)),
            Some(Overrun(t)) => {
                direct.resync();
                direct.capture(*t);
                Some(SpeedReading::Overrun)
            }
            None => direct.poll(*now),
        };
        assert_eq!(got[k], want, "poll {k}");
    }
}

#[test]
fn reading_kinds_and_rejection_periods() {
    let kinds = [
        (SpeedReading::Rpm(1.0f32), "rpm"),
        (SpeedReading::OutOfRange(1.0), "out_of_range"),
        (
            SpeedReading::Rejected(Rejection::TooShort { period_ticks: 3 }),
            "too_short",
        ),
        (
            SpeedReading::Rejected(Rejection::Bounce { period_ticks: 3 }),
            "bounce",
        ),
        (
            SpeedReading::Rejected(Rejection::Step { period_ticks: 3 }),
            "step",
        ),
        (SpeedReading::Lost, "lost"),
        (SpeedReading::Acquiring, "acquiring"),
        (SpeedReading::Overrun, "overrun"),
    ];
    for (r, k) in kinds {
        assert_eq!(r.kind(), k);
        if let SpeedReading::Rejected(why) = r {
            assert_eq!(why.period_ticks(), 3);
        }
    }
}
