//! The lift hook of the dynamic model: an actual cam with no deviation is the theoretical
//! cam bit for bit, and a constant deviation (a larger base circle by `e`) only shifts
//! the lift by `e` and leaves its derivatives unchanged.

use std::ops::ControlFlow;

use camsim_core::{
    simulate, CamModel, Design, DeviatedLift, LiftProfile, RegulatedVertical, Sample, Scene,
    SolverSettings,
};

type Model<P> = CamModel<f64, RegulatedVertical, { <RegulatedVertical as Scene>::N }, P>;
const STEP: f64 = 2.0 * std::f64::consts::PI / 360.0;

/// Every sample's contact force and load acceleration over one revolution.
fn trace<P: LiftProfile<f64>>(m: &Model<P>) -> Vec<(f64, f64, f64)> {
    let mut out = Vec::new();
    simulate(m, &SolverSettings::reference(), 1, &mut |s: &Sample<
        f64,
    >| {
        out.push((
            s.point.t,
            s.point.contact_force,
            s.point.load_acceleration(),
        ));
        ControlFlow::Continue(())
    })
    .unwrap();
    out
}

#[test]
fn zero_deviation_is_the_theoretical_cam_bit_for_bit() {
    let d = Design::<f64>::reference();
    let zero = DeviatedLift::<f64, 400>::uniform(STEP, 360, |_| 0.0).unwrap();
    let theory = trace(&Model::new(d.clone()).unwrap());
    let actual = trace(&Model::with_profile(d, zero).unwrap());
    assert!(theory.len() > 1000);
    assert_eq!(theory, actual);
}

#[test]
fn constant_deviation_shifts_the_lift_only() {
    let d = Design::<f64>::reference();
    let e = 2e-3;
    let dev = DeviatedLift::<f64, 400>::uniform(STEP, 360, |_| e).unwrap();
    for k in 0..720 {
        let th = k as f64 * 0.5f64.to_radians() - 1.0;
        let (t, a) = (d.program.follower(th), dev.follower(&d.program, th));
        assert!((a.y - t.y - e).abs() < 1e-15, "y at {th}");
        assert_eq!(
            (a.dy, a.d2y, a.d3y),
            (t.dy, t.d2y, t.d3y),
            "derivatives at {th}"
        );
    }
    // A deviation over anything but one revolution is refused.
    assert!(DeviatedLift::<f64, 400>::uniform(STEP, 180, |_| 0.0).is_err());
}
