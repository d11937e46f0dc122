//! The actual cam: the exact envelope of the roller circle (camsim-core's `envelope`
//! module, docs/MODEL.md §8) against closed forms.

use camsim_core::{
    ActualCam, ActualContour, CamGeometry, CamProgram, Design, DeviatedLift, ProfileSpec,
    RandomStream, Tolerances,
};
use std::f64::consts::PI;

/// Runs `f` on a thread with a large stack (the contours hold up to 7201 knots).
fn big_stack<R: Send + 'static>(f: impl FnOnce() -> R + Send + 'static) -> R {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap()
}

#[test]
fn perfect_cam_gives_the_theoretical_lift() {
    big_stack(|| {
        let d = Design::<f64>::reference();
        let (p, g) = (&d.program, &d.geometry);
        let mut rng = RandomStream::new(1, Default::default());
        let contour = ActualContour::<f64, 361>::generate(
            &ProfileSpec {
                program: p,
                geometry: g,
                tolerances: &Tolerances::none(),
                intervals: 360,
            },
            &mut rng,
        )
        .unwrap();
        // ε: how far the splined contour strays from the theoretical surface (the
        // distance between the two points of the same setting angle bounds the distance
        // to the surface), on a 0.01° grid.
        let mut eps = 0.0f64;
        for k in 0..36_000 {
            let th = (k as f64 * 0.01).to_radians();
            let f = p.follower(th);
            let (x, y) = g.surface_point(th, f.y, f.dy);
            let q = contour.point(th);
            eps = eps.max((q.x - x).hypot(q.y - y));
        }
        // The surface point depends on the slope y' (through the pressure angle), so the
        // laws' jerk steps are steps in the contour's second derivative and the spline's
        // error is O(h²) next to the segment bounds: 7.7e-6 in at 1°.
        assert!(eps > 0.0 && eps < 2e-5, "{eps}");
        let (phi_max, _) = g.max_pressure_angle(p, 3600);
        let bound = eps / phi_max.cos() * 1.01 + 1e-12;
        let cam = ActualCam::new(contour, g.roller_radius, (0.0, 0.0)).unwrap();
        let mut worst = 0.0f64;
        for k in 0..3600 {
            let th = (k as f64 * 0.1 + 0.037).to_radians();
            let e = cam.roller_centre(th).unwrap() - g.prime_radius() - p.follower(th).y;
            worst = worst.max(e.abs());
        }
        assert!(worst <= bound, "{worst} > {bound}");
        // As a deviation spline at 0.25°: the knots within the bound, and between them
        // within the periodic cubic spline's Lebesgue constant (1.5492) times it.
        let dev = DeviatedLift::<f64, 1441>::envelope(p, g, &cam, 1440).unwrap();
        for (k, e) in dev.spline().values().iter().enumerate() {
            assert!(e.abs() <= bound, "knot {k}: {e}");
        }
        for k in 0..7200 {
            let th = (k as f64 * 0.05 + 0.013).to_radians();
            assert!(dev.deviation(th).y.abs() <= 1.55 * bound, "at {th}");
        }
        eprintln!("perfect cam: eps {eps:.3e}, worst {worst:.3e}, bound {bound:.3e}");
    });
}

/// The roller centre over a crest (θ = 0) and over the valley next to it (θ = π/n) of
/// the contour ρ(φ) = R + A cos nφ sampled at `knots` points, roller radius `r`.
fn crest_and_valley<const N: usize>(knots: usize, rb: f64, amp: f64, n: f64, r: f64) -> (f64, f64) {
    let contour = ActualContour::<f64, N>::from_fn(knots, |k| {
        let phi = 2.0 * PI * k as f64 / knots as f64;
        let rho = rb + amp * (n * phi).cos();
        (rho * phi.sin(), rho * phi.cos())
    })
    .unwrap();
    let cam = ActualCam::new(contour, r, (0.0, 0.0)).unwrap();
    (
        cam.roller_centre(0.0).unwrap(),
        cam.roller_centre(PI / n).unwrap(),
    )
}

#[test]
fn long_and_shallow_waviness_passes_whole() {
    // ρ = R + A cos nφ: over a crest d = R + A + r, and where the roller fits the valley
    // (A n² ≤ ρ(ρ + r)/r, ρ = R − A) d = R − A + r: the lift swings by 2A. With R = 1.5,
    // r = 0.375, A = 5e-4 the limit is n ≤ 122.44: n = 10 (λ = 0.94 in, 2.5 roller
    // diameters... well above the roller) and n = 100 (λ = 0.094 in, a quarter of the
    // roller's diameter: shorter than the roller yet shallow enough).
    let (rb, r, amp): (f64, f64, f64) = (1.5, 0.375, 5e-4);
    let rho = rb - amp;
    let n_max = (rho * (rho + r) / (r * amp)).sqrt();
    assert!((n_max - 122.44).abs() < 0.01, "{n_max}");
    big_stack(move || {
        for n in [10.0, 100.0] {
            let (crest, valley) = crest_and_valley::<3601>(3600, rb, amp, n, r);
            // The spline's own error at ≥ 36 knots a wave: (5/384)(2π/36)⁴ A < 1e-8.
            assert!(
                (crest - (rb + amp + r)).abs() < 1e-8,
                "n {n}: crest {crest}"
            );
            assert!(
                (valley - (rb - amp + r)).abs() < 1e-8,
                "n {n}: valley {valley}"
            );
        }
    });
}

#[test]
fn waviness_much_shorter_than_the_roller_is_bridged() {
    // n = 360 on R = 1.5: λ = 0.0262 in, a fourteenth of the roller radius; A = 2e-3
    // (A n² = 259 ≫ 122² A): the roller rests on the crests. Its swing is at most the
    // tip-rest bound (R + A + r) − [(R + A) cos(π/n) + √(r² − (R + A)² sin²(π/n))],
    // ≈ λ²(1 + r/R)/(8r) whatever A, and equals the osculating-circle estimate: the
    // roller's centre at r + R_c from the crests' curvature centres (R_c = (R+A)²/(R + A
    // + A n²) at R + A − R_c, angle ±π/n).
    let (rb, r, amp, n): (f64, f64, f64, f64) = (1.5, 0.375, 2e-3, 360.0);
    let ro = rb + amp;
    let t = PI / n;
    let tip_rest = ro * t.cos() + (r * r - (ro * t.sin()).powi(2)).sqrt();
    let bound = ro + r - tip_rest;
    let lambda = 2.0 * PI * rb / n;
    assert!((bound / (lambda * lambda * (1.0 + r / rb) / (8.0 * r)) - 1.0).abs() < 0.01);
    let rc = ro * ro / (ro + amp * n * n);
    let oc = (ro - rc) * t.cos() + ((r + rc).powi(2) - ((ro - rc) * t.sin()).powi(2)).sqrt();
    let osculating = ro + r - oc;
    let (crest, valley) = big_stack(move || crest_and_valley::<7201>(7200, rb, amp, n, r));
    let swing = crest - valley;
    eprintln!(
        "bridged: swing {swing:.4e}, bound {bound:.4e}, osculating {osculating:.4e}, 2A {}",
        2.0 * amp
    );
    // Over the crest exactly R + A + r (20 knots a wave: spline error < 2e-6 A).
    assert!((crest - (ro + r)).abs() < 1e-8, "{crest}");
    assert!(swing <= bound + 1e-8, "{swing} > {bound}");
    assert!(
        (swing / osculating - 1.0).abs() < 0.05,
        "{swing} vs {osculating}"
    );
    // Attenuated: the swing is a small part of the 2A the thesis's method would keep.
    assert!(swing < 0.08 * 2.0 * amp, "{swing}");
}

#[test]
fn envelope_runs_in_f32() {
    // The firmware's precision: a perfect cam within f32's rounding of the lift.
    big_stack(|| {
        let p = CamProgram::<f32>::reference();
        let g = CamGeometry::<f32>::reference();
        let mut rng = RandomStream::<f32>::new(1, Default::default());
        let c = ActualContour::<f32, 181>::generate(
            &ProfileSpec {
                program: &p,
                geometry: &g,
                tolerances: &Tolerances::none(),
                intervals: 180,
            },
            &mut rng,
        )
        .unwrap();
        let cam = ActualCam::new(c, g.roller_radius, (0.0, 0.0)).unwrap();
        let dev = DeviatedLift::<f32, 361>::envelope(&p, &g, &cam, 360).unwrap();
        let worst = dev
            .spline()
            .values()
            .iter()
            .fold(0.0f32, |m, e| m.max(e.abs()));
        // 2° setting points: the spline's error (O(h³) at the laws' jerk steps) and
        // f32's rounding of lengths near 2 in (2.4e-7).
        assert!(worst < 2e-5, "{worst}");
    });
}

// ---- camsim run --actual / --measured -------------------------------------------

use camsim::cli::{self, Command as Cmd};
use camsim::cmd::run;

mod common;
use common::scratch;

/// `camsim run ARGS` as the binary parses and runs it: the report, or the error on one
/// line.
fn run_cli(args: &[&str]) -> Result<run::RunReport, String> {
    let argv = ["camsim", "run"].iter().chain(args).copied();
    let a = match cli::parse_from(argv) {
        Ok(c) => match c.command {
            Cmd::Run(a) => a,
            other => panic!("not run: {other:?}"),
        },
        Err(e) => return Err(cli::usage_line(&e)),
    };
    run::report(&a, camsim::units::Units::Inch).map_err(|e| format!("{e:#}"))
}

/// A quick run: 500 rpm from static equilibrium, 2 revolutions.
const QUICK: [&str; 6] = ["--rpm", "500", "--start", "static", "--revolutions", "2"];

fn quick(extra: &[&str]) -> Vec<String> {
    QUICK.iter().chain(extra).map(|s| s.to_string()).collect()
}

fn strs(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

/// The per-period table as JSON (every statistic, bit for bit).
fn table(r: &run::RunReport) -> String {
    serde_json::to_string(&r.per_period).unwrap()
}

#[test]
fn a_measured_theoretical_cam_gives_back_the_theoretical_run() {
    let d = scratch("theory");
    let design = Design::<f64>::reference();
    let p = &design.program;
    let theory = run_cli(&strs(&quick(&[]))).unwrap();
    assert!(theory.profile.is_none() && theory.fpr.is_none());
    // Deviation 0 at every degree: the deviation spline is zero, the run bit-identical.
    let zero = d.join("zero.csv");
    let mut text = String::from("# a perfect cam\nangle_deg,deviation_in\n");
    for k in 0..360 {
        text += &format!("{k},0\n");
    }
    std::fs::write(&zero, &text).unwrap();
    let r = run_cli(&strs(&quick(&["--measured", zero.to_str().unwrap()]))).unwrap();
    assert_eq!(table(&r), table(&theory));
    assert_eq!(r.fpr, Some(0));
    // The lift itself, written with Rust's shortest round-trip digits: the deviation at
    // every row is exactly zero again, closed at 360.
    let lift = d.join("lift.csv");
    let mut text = String::from("angle_deg,lift_in\n");
    for k in 0..=360 {
        text += &format!("{k},{}\n", p.follower((k as f64).to_radians()).y);
    }
    std::fs::write(&lift, &text).unwrap();
    let r = run_cli(&strs(&quick(&["--measured", lift.to_str().unwrap()]))).unwrap();
    assert_eq!(table(&r), table(&theory));
    // The surface's polar radius every 0.5° of cam angle (the surface points of Eq. E.6
    // in polar form, their angles uneven): the roller's envelope gives the lift back
    // within the contour spline's error (a few 1e-7 in, see
    // perfect_cam_gives_the_theoretical_lift), so the table agrees to that order.
    let radius = d.join("radius.csv");
    let g = &design.geometry;
    let mut text = String::from("angle_deg,radius_in\n");
    for k in 0..720 {
        let th = (k as f64 * 0.5).to_radians();
        let f = p.follower(th);
        let (x, y) = g.surface_point(th, f.y, f.dy);
        let psi = x.atan2(y).to_degrees().rem_euclid(360.0);
        text += &format!("{psi},{}\n", x.hypot(y));
    }
    std::fs::write(&radius, &text).unwrap();
    let r = run_cli(&strs(&quick(&["--measured", radius.to_str().unwrap()]))).unwrap();
    let Some(run::ProfileReport::Measured(m)) = &r.profile else {
        panic!("{:?}", r.profile)
    };
    assert_eq!(
        (m.points, m.deviation_knots, m.fpr),
        (720, 3600, 0),
        "{m:?}"
    );
    assert!(m.max_abs_deviation_in < 1e-8, "{m:?}");
    let scale = |f: fn(&camsim::sim::PeriodRow) -> f64| {
        theory
            .per_period
            .iter()
            .map(|r| f(r).abs())
            .fold(0.0, f64::max)
    };
    let (sa, sf) = (
        scale(|r| r.rms_acceleration.in_inch()),
        scale(|r| r.contact_force_max.in_inch()),
    );
    assert_eq!(r.per_period.len(), theory.per_period.len());
    for (a, b) in r.per_period.iter().zip(&theory.per_period) {
        let at = format!("{} {}", a.revolution, a.period);
        assert!(
            (a.rms_displacement.in_inch() - b.rms_displacement.in_inch()).abs() < 1e-6,
            "{at}"
        );
        assert!(
            (a.rms_acceleration.in_inch() - b.rms_acceleration.in_inch()).abs() < 1e-3 * sa,
            "{at}"
        );
        assert!(
            (a.contact_force_max.in_inch() - b.contact_force_max.in_inch()).abs() < 1e-3 * sf,
            "{at}"
        );
        assert_eq!(a.jump, b.jump, "{at}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_measured_files_are_refused_on_one_line_naming_it() {
    let d = scratch("bad");
    let f = d.join("m.csv");
    let p = f.to_str().unwrap();
    for (text, want) in [
        (
            "angle_deg,deviation_in\n0,0\n90,0\n45,0\n",
            "line 4: angle 45 deg does not increase",
        ),
        (
            "angle_deg,deviation_in\n0,0\n90,x\n",
            "line 3: deviation_in \"x\" is not a number",
        ),
        ("angle,dev\n", "line 1: the header must be"),
        (
            "angle_deg,deviation_in\n0,0\n90,0\n180,0\n",
            "line 4: at least 4 rows",
        ),
    ] {
        std::fs::write(&f, text).unwrap();
        let e = run_cli(&["--measured", p, "--revolutions", "1"]).unwrap_err();
        assert!(!e.contains('\n'), "{e}");
        assert!(e.starts_with(&format!("--measured {p}: {want}")), "{e}");
    }
    let e = run_cli(&["--measured", "/nonexistent/m.csv"]).unwrap_err();
    assert!(
        e.starts_with("--measured /nonexistent/m.csv: cannot read the measured profile"),
        "{e}"
    );
    // --measured and --actual exclude each other; the profile options need --actual.
    assert!(run_cli(&["--measured", p, "--actual"])
        .unwrap_err()
        .contains("cannot be used with"));
    let e = run_cli(&["--seed", "3"]).unwrap_err();
    assert!(
        e.contains("--seed 3 shapes an actual cam: add --actual"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn run_actual_reports_the_profile_and_is_reproducible() {
    let args = quick(&["--actual", "--seed", "7", "--interval-deg", "5"]);
    let a = run_cli(&strs(&args)).unwrap();
    let b = run_cli(&strs(&args)).unwrap();
    assert_eq!(table(&a), table(&b));
    let Some(run::ProfileReport::Actual(p)) = &a.profile else {
        panic!("{:?}", a.profile)
    };
    // The per-cam method splines at 20 points an interval (1440 a revolution).
    assert_eq!(
        (p.seed, p.sample, p.intervals, p.deviation_knots),
        (7, 0, 72, 1440)
    );
    assert_eq!(a.fpr, Some(p.fpr));
    // The profile is camsim::actual::build_profile's sample 0.
    let design = Design::<f64>::reference();
    let argv = [
        "camsim",
        "run",
        "--actual",
        "--seed",
        "7",
        "--interval-deg",
        "5",
    ];
    let Cmd::Run(parsed) = cli::parse_from(argv).unwrap().command else {
        unreachable!()
    };
    let (_, stats) = camsim::actual::build_profile(&design, &parsed.actual.cams(), 0).unwrap();
    assert_eq!(&stats, p);
    // Another seed, another cam.
    let c = run_cli(&strs(&quick(&[
        "--actual",
        "--seed",
        "8",
        "--interval-deg",
        "5",
    ])))
    .unwrap();
    assert_ne!(table(&a), table(&c));
    // JSON: fpr at the top, the profile's statistics under "profile".
    let json: serde_json::Value =
        serde_json::from_str(&camsim::report::Report::json(&a).unwrap()).unwrap();
    assert_eq!(json["fpr"], serde_json::json!(p.fpr));
    for key in [
        "rms_deviation_in",
        "max_abs_deviation_in",
        "intervals",
        "method",
        "seed",
    ] {
        assert!(json["profile"].get(key).is_some(), "{key}");
    }
    assert_eq!(json["profile"]["method"], "per-cam");
    // --plot adds the profile deviation against cam angle.
    let d = scratch("plot");
    let dir = d.join("plots");
    let args = quick(&["--actual", "--plot", dir.to_str().unwrap()]);
    run_cli(&strs(&args)).unwrap();
    let png = std::fs::read(dir.join(camsim::plot::PROFILE_FILE)).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        camsim::plot::FILES_WITH_PROFILE.len()
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn what_a_measured_profile_costs_the_firmware() {
    // A DeviatedLift<f32, K> is one CubicSpline<f32, K>: knots, values and second
    // derivatives (3 K f32 = 12 K B) plus the point count (usize), 1/h̄ (f32) and the
    // periodic flag, rounded up to the alignment: 12 K + 9 B rounded to 4 on the chip
    // (usize 4 B: 4 344 B at 1°, K = 361; 8 664 B at 0.5°, K = 721; checked by a const
    // assertion built for thumbv7em-none-eabihf) and 12 K + 13 B rounded to 8 here.
    use std::mem::size_of;
    let host = |k: usize| (12 * k + 13).div_ceil(8) * 8;
    assert_eq!(size_of::<DeviatedLift<f32, 361>>(), host(361)); // 4 352 B
    assert_eq!(size_of::<DeviatedLift<f32, 721>>(), host(721)); // 8 672 B
                                                                // The host's f64 spline: 24 K + 17 B rounded to 8.
    assert_eq!(size_of::<DeviatedLift<f64, 3601>>(), 86_448);
}
