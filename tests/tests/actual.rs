//! The actual cam: the exact envelope of the roller circle (camsim-core's `envelope`
//! module, docs/MODEL.md §8) against closed forms.

use camsim_core::{
    ActualCam, ActualContour, CamGeometry, CamProgram, Design, DeviatedLift, RandomStream,
    Tolerances,
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
        let contour =
            ActualContour::<f64, 361>::generate(p, g, &Tolerances::none(), 360, &mut rng).unwrap();
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
        let c = ActualContour::<f32, 181>::generate(&p, &g, &Tolerances::none(), 180, &mut rng)
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
