//! Backlash in the coupling (Appendix G.1, docs/MODEL.md §8.5): a free play between the
//! coupling and the cam shaft, off by default.

use std::ops::ControlFlow;

use camsim::sim::{self, RunSpec};
use camsim_core::{
    simulate, CamModel, Design, RegulatedVertical, Sample, Scene, SolverSettings, Start,
};

/// One per-period statistic.
type Stat = fn(&sim::PeriodRow) -> f64;

type Model = CamModel<f64, RegulatedVertical, { <RegulatedVertical as Scene>::N }>;

#[test]
fn the_reference_has_none_and_a_scene_without_the_key_has_none() {
    assert_eq!(Design::<f64>::reference().coupling_backlash, 0.0);
    let spec = camsim::scene::parse("[design]\nk_s2_lb_in_per_rad = 2.0e5\n").unwrap();
    assert_eq!(spec.design.coupling_backlash, 0.0);
    let spec = camsim::scene::parse("[design]\ncoupling_backlash_rad = 0.002\n").unwrap();
    assert_eq!(spec.design.coupling_backlash, 0.002);
    assert!(camsim::scene::parse("[design]\ncoupling_backlash_rad = -0.002\n").is_err());
}

#[test]
fn a_vanishing_free_play_gives_the_rigid_coupling() {
    // The limit b -> 0: the impact pair's dead zone and its no-pull clamp vanish (the
    // shaft carries the steady drag, twisted 4e-4 rad, and reverses through zero twist
    // in the return, where the cam drives): the per-period statistics converge to the
    // rigid coupling's within the solver's tolerance.
    let mut spec = RunSpec::reference();
    spec.revolutions = 2;
    spec.solver.start = Start::Static;
    let rigid = sim::run(&spec, &mut sim::Nothing).unwrap();
    spec.design.coupling_backlash = 1e-9;
    let play = sim::run(&spec, &mut sim::Nothing).unwrap();
    let (a, b) = (
        sim::period_rows(&spec.design, &rigid.stats),
        sim::period_rows(&spec.design, &play.stats),
    );
    assert_eq!(a.len(), b.len());
    let scale = |f: Stat| a.iter().map(|r| f(r).abs()).fold(0.0, f64::max);
    let checks: [(&str, Stat); 5] = [
        ("rms_acceleration", |r| r.rms_acceleration.in_inch()),
        ("torque_avg", |r| r.torque_avg.in_inch()),
        ("torque_max", |r| r.torque_max.in_inch()),
        ("contact_force_max", |r| r.contact_force_max.in_inch()),
        ("aord_cam", |r| r.aord_cam),
    ];
    // Tolerance: 1e-3 of the statistic's largest value over the periods. The solver's own
    // noise is about 1e-4 of it (measured: the rigid run at rtol 0.99e-6 against 1e-6
    // moves rms_acceleration by up to 1.2e-4 of its scale), and the 1e-9 rad play moved
    // it by 2.4e-4.
    for (name, f) in checks {
        let s = scale(f);
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (f(x) - f(y)).abs() <= 1e-3 * s,
                "{name} {} {}: {} vs {}",
                x.revolution,
                x.period,
                f(x),
                f(y)
            );
        }
    }
    // And a real play changes the run (the test can fail).
    spec.design.coupling_backlash = 0.01;
    let loose = sim::run(&spec, &mut sim::Nothing).unwrap();
    let c = sim::period_rows(&spec.design, &loose.stats);
    let s = scale(|r| r.rms_acceleration.in_inch());
    let diff = a
        .iter()
        .zip(&c)
        .map(|(x, y)| (x.rms_acceleration.in_inch() - y.rms_acceleration.in_inch()).abs() / s)
        .fold(0.0, f64::max);
    assert!(diff > 1e-2, "{diff}");
}

#[test]
fn within_the_free_play_the_cam_coasts() {
    // The thesis's start (every speed ω0, every twist zero) puts the coupling in the
    // middle of a free play of 2 rad: the cam is disconnected until the coupling has
    // gained 1 rad on it. On the first dwell dy/dθ = 0, so the output torque is zero and
    // the cam obeys I_c ω̇_c = −C_cc ω_c alone: ω_c = ω0 exp(−C_cc t / I_c), while the
    // coupling, held by the motor, runs on near ω0.
    let mut d = Design::<f64>::reference();
    d.coupling_backlash = 2.0;
    let (w0, tau) = (d.omega0, d.i_c / d.c_cc);
    let dwell_end = d.program.segments()[0].end_deg.to_radians();
    let m = Model::new(d).unwrap();
    let mut settings = SolverSettings::reference();
    settings.start = Start::Thesis;
    let (mut n, mut worst, mut last) = (0, 0.0f64, (0.0, 0.0));
    let _ = simulate(&m, &settings, 1, &mut |s: &Sample<f64>| {
        let p = &s.point;
        if p.theta_c >= dwell_end {
            return ControlFlow::Break(());
        }
        assert!(
            (p.theta_cp - p.theta_c).abs() < 1.0,
            "in contact at {}",
            p.t
        );
        worst = worst.max((p.omega_c - w0 * (-p.t / tau).exp()).abs());
        last = (p.t, p.omega_cp);
        n += 1;
        ControlFlow::Continue(())
    });
    assert!(n > 50, "{n}");
    assert!(worst < 1e-5 * w0, "{worst}");
    // By the end of the dwell the free cam has lost a good part of its speed (the dwell
    // lasts longer than 30° at ω0 would); the coupling has not.
    let (t, omega_cp) = last;
    assert!((-t / tau).exp() < 0.6, "{t}");
    assert!((omega_cp / w0 - 1.0).abs() < 0.02, "{omega_cp}");
}
