//! Output on a cam-angle grid (`simulate_on_grid`, `AngleGrid`): the grid's samples are
//! at the grid's angles, in order, one per point; asking for them leaves the solver's
//! steps bit for bit as `simulate` takes them; and a grid sample is as accurate as the
//! solver itself.

use std::ops::ControlFlow;

use camsim_core::{
    simulate, simulate_on_grid, AngleGrid, Design, RegulatedFullModel, Sample, SolverSettings,
    Start,
};

fn settings(rtol: f64) -> SolverSettings<f64> {
    let mut s = SolverSettings::reference();
    s.rtol = rtol;
    s.start = Start::Static;
    s
}

/// A node sample's time, cam angle and load acceleration.
type Node = (f64, f64, f64);

/// Runs `revs` revolutions on a grid of `step` degrees: the node samples (as t, state
/// fingerprint) and the grid samples.
fn grid_run(
    d: &Design<f64>,
    s: &SolverSettings<f64>,
    revs: u32,
    step: f64,
) -> (Vec<Node>, Vec<Sample<f64>>) {
    let m = RegulatedFullModel::new(d.clone()).unwrap();
    let mut nodes = Vec::new();
    let mut grid = Vec::new();
    simulate_on_grid(
        &m,
        s,
        revs,
        AngleGrid::new(step).unwrap(),
        &mut |x: &Sample<f64>| {
            nodes.push((x.point.t, x.point.theta_c, x.point.load_acceleration()));
            ControlFlow::Continue(())
        },
        &mut |x: &Sample<f64>| {
            grid.push(*x);
            ControlFlow::Continue(())
        },
    )
    .unwrap();
    (nodes, grid)
}

#[test]
fn grid_samples_sit_on_the_grid_in_order_and_leave_the_steps_unchanged() {
    let d = Design::<f64>::reference();
    let s = settings(1e-3);
    let (nodes, grid) = grid_run(&d, &s, 2, 0.5);
    // Two revolutions of 720 points each: the reference program's segment starts are
    // whole degrees, on the grid, so they add none.
    assert_eq!(grid.len(), 2 * 720);
    for (i, g) in grid.iter().enumerate() {
        let k = i % 720;
        let rev = (i / 720) as u32 + 1;
        assert_eq!(g.revolution, rev);
        assert_eq!(g.angle_deg, 0.5 * k as f64);
        let want = (360.0 * (rev - 1) as f64 + 0.5 * k as f64).to_radians();
        // The interpolated state's cam angle is the grid's angle (Newton on the
        // interpolant, to rounding).
        assert!(
            (g.point.theta_c - want).abs() <= 1e-12 * want.max(1.0),
            "point {i}: {} rad against {want}",
            g.point.theta_c
        );
        assert_eq!(
            g.segment,
            d.program.segment_at(want + 1e-12),
            "point {i} at {} deg",
            g.angle_deg
        );
    }
    assert!(grid.windows(2).all(|w| w[0].point.t < w[1].point.t));
    // The steps are simulate's, bit for bit.
    let m = RegulatedFullModel::new(d.clone()).unwrap();
    let mut plain = Vec::new();
    simulate(&m, &s, 2, &mut |x: &Sample<f64>| {
        plain.push((x.point.t, x.point.theta_c, x.point.load_acceleration()));
        ControlFlow::Continue(())
    })
    .unwrap();
    assert_eq!(nodes, plain);
}

#[test]
fn a_segment_start_off_the_grid_is_a_point_of_its_own() {
    let d = Design::<f64>::reference();
    // 7° does not divide the reference program's segment starts (0, 90, 180, 270 or the
    // like, whatever they are): each start off the grid adds one point.
    let starts: Vec<f64> = d.program.segments().iter().map(|s| s.start_deg).collect();
    let off = starts.iter().filter(|a| (*a / 7.0).fract() != 0.0).count();
    let (_, grid) = grid_run(&d, &settings(1e-3), 1, 7.0);
    assert_eq!(grid.len(), 52 + off, "starts {starts:?}");
    for a in &starts {
        let g = grid.iter().find(|g| g.angle_deg == *a).unwrap();
        assert_eq!(g.segment, starts.iter().position(|b| b == a).unwrap());
    }
}

#[test]
fn a_grid_sample_is_as_accurate_as_the_solver() {
    let d = Design::<f64>::reference();
    // The follower's acceleration at every 0.5° of revolution 2 against rtol 1e-10.
    let accel = |rtol: f64| -> Vec<f64> {
        let (_, g) = grid_run(&d, &settings(rtol), 2, 0.5);
        g[720..]
            .iter()
            .map(|x| x.point.load_acceleration())
            .collect()
    };
    let reference = accel(1e-10);
    let scale = reference.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let err = |rtol: f64| {
        accel(rtol)
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / scale
    };
    let (e5, e8) = (err(1e-5), err(1e-8));
    // Within the solver's own accuracy: the interpolant's order is checked in dense.rs;
    // here a located time or a wrong step would show as errors of the size of the
    // acceleration's change over a step (1e-2 of its peak and more). England's error
    // itself stops falling near 1e-7 of the peak below rtol 1e-6 (issue 22).
    assert!(e5 < 1e-5, "rtol 1e-5: {e5:.2e}");
    assert!(e8 < 1e-6, "rtol 1e-8: {e8:.2e}");
    assert!(e8 < e5, "rtol 1e-5: {e5:.2e}, rtol 1e-8: {e8:.2e}");
}

#[test]
fn a_grid_step_outside_its_range_is_refused() {
    for bad in [0.0, -1.0, 1e-4, 361.0, f64::NAN, f64::INFINITY] {
        assert!(AngleGrid::new(bad).is_err(), "{bad}");
    }
    assert_eq!(AngleGrid::new(0.5).unwrap().points_per_revolution(), 720);
    assert_eq!(AngleGrid::new(7.0).unwrap().points_per_revolution(), 52);
}
