//! `camsim jump-speed`'s search is core's `OnsetSearch` with the host's early-stopping
//! predicate: it ends for any resolution, brackets the onset to the resolution, and runs
//! as many simulations as doubling-then-bisection must.

use camsim::cmd::jump_speed::{find, find_with, START_RPM};
use camsim::sim::RunSpec;

#[test]
fn reference_search_runs_the_simulations_bisection_needs() {
    let mut spec = RunSpec::reference();
    spec.solver.start = camsim_core::Start::Static;
    let r = find(&spec, 1.0, 20000.0).unwrap();
    // 50, 100, 200, 400 (contact), 800 (the reference separates below its operating
    // speed), then the bracket 400 -> 800 halved to <= 1 rpm: 9 halvings.
    assert_eq!(r.simulations, 5 + 9);
    let (j, n) = (r.jump_rpm.unwrap(), r.no_jump_rpm);
    assert_eq!(j - n, 400.0 / 512.0);
    // Both ends are on the bisection's lattice 400 + k * 400/512.
    assert_eq!(((j - 400.0) / (400.0 / 512.0)).fract(), 0.0);
    // The f32 predictor's table (grid 700 holds, 800 jumps) agrees within a few rpm.
    assert!(j > 690.0 && j < 705.0, "{j}");
}

#[test]
fn resolution_below_the_float_spacing_ends_on_adjacent_floats() {
    let onset = 698.437_512_345;
    let mut calls = 0;
    let r = find_with(1e-13, 20000.0, |rpm| {
        calls += 1;
        Ok(rpm >= onset)
    })
    .unwrap();
    let (j, n) = (r.jump_rpm.unwrap(), r.no_jump_rpm);
    assert!(n < onset && onset <= j);
    // 1e-13 is below the spacing of f64 near 700 rpm (1.1e-13): the bisection ends when
    // the bracket's ends are neighbouring floats.
    assert_eq!(n.to_bits() + 1, j.to_bits());
    assert_eq!(r.simulations, calls);
    assert!(calls < 5 + 64, "{calls}");
}

#[test]
fn step_onsets_are_bracketed_to_the_resolution() {
    for (onset, res) in [(51.0, 1.0), (123.456, 0.01), (698.4, 1.0), (15000.0, 1e-6)] {
        let r = find_with(res, 20000.0, |rpm| Ok(rpm >= onset)).unwrap();
        let (j, n) = (r.jump_rpm.unwrap(), r.no_jump_rpm);
        assert!(
            n < onset && onset <= j && j - n <= res,
            "{onset}: ({n}, {j}]"
        );
    }
    // No onset up to the limit, onset below the start, the predicate's failure.
    let none = find_with(1.0, 1000.0, |_| Ok(false)).unwrap();
    assert_eq!((none.jump_rpm, none.no_jump_rpm), (None, 1000.0));
    // 50, 100, 200, 400, 800, 1000.
    assert_eq!(none.simulations, 6);
    let early = find_with(1.0, 1000.0, |_| Ok(true)).unwrap_err();
    assert!(early
        .to_string()
        .contains(&format!("already at {START_RPM} rpm")));
    let failed = find_with(1.0, 1000.0, |rpm| {
        anyhow::ensure!(rpm < 300.0, "diverged at {rpm}");
        Ok(false)
    });
    assert!(failed.unwrap_err().to_string().contains("diverged at 400"));
    assert!(find_with(0.0, 1000.0, |_| Ok(true)).is_err());
    assert!(find_with(1.0, f64::NAN, |_| Ok(true)).is_err());
}
