//! `camsim jump-speed`'s search is core's `OnsetSearch` with the host's early-stopping
//! predicate: it ends for any resolution, brackets the onset to the resolution, and runs
//! as many simulations as doubling-then-bisection must.

use camsim::cmd::jump_speed::{
    find, find_with, render_text, JumpSpeed, JumpSpeedReport, MAX_RPM, START_RPM,
};
use camsim::sim::RunSpec;

#[test]
fn reference_search_runs_the_simulations_bisection_needs() {
    let mut spec = RunSpec::reference();
    spec.solver.start = camsim_core::Start::Static;
    let r = find(&spec, 1.0, MAX_RPM).unwrap();
    // 50, 100, 200, 400, 800 (contact: the study spring holds at the operating speed),
    // 1600 (separation), then the bracket 800 -> 1600 halved to <= 1 rpm: 10 halvings.
    assert_eq!(r.simulations, 6 + 10);
    let (j, n) = (r.jump_rpm.unwrap(), r.no_jump_rpm);
    assert_eq!(j - n, 800.0 / 1024.0);
    // Both ends are on the bisection's lattice 800 + k * 800/1024.
    assert_eq!(((j - 800.0) / (800.0 / 1024.0)).fract(), 0.0);
    // The quasi-static estimate for 100 lb/in is 906.5 rpm (tests/dynamics.rs); the
    // dynamic onset lies a little below it.
    assert!(j > 880.0 && j < 906.5, "{j}");
}

#[test]
fn resolution_below_the_float_spacing_ends_on_adjacent_floats() {
    let onset = 698.437_512_345;
    let mut calls = 0;
    let r = find_with(1e-13, MAX_RPM, |rpm| {
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
    for (onset, res) in [(51.0, 1.0), (123.456, 0.01), (698.4, 1.0), (9000.0, 1e-6)] {
        let r = find_with(res, MAX_RPM, |rpm| Ok(rpm >= onset)).unwrap();
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

#[test]
fn report_feeds_text_and_json() {
    let found = JumpSpeed {
        jump_rpm: Some(698.4375),
        no_jump_rpm: 697.65625,
        simulations: 14,
    };
    let r = JumpSpeedReport::new(&found, 800.0, 1.0, 12.0);
    assert_eq!(r.margin_rpm, Some(698.4375 - 800.0));
    assert_eq!(r.margin_percent, Some(100.0 * (698.4375 - 800.0) / 800.0));
    let v = serde_json::to_value(&r).unwrap();
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    keys.sort_unstable();
    assert_eq!(
        keys,
        [
            "jump_rpm",
            "margin_percent",
            "margin_rpm",
            "no_jump_rpm",
            "operating_rpm",
            "resolution_rpm",
            "simulations",
            "wall_ms"
        ]
    );
    assert_eq!(v["simulations"], 14);
    let text = render_text(&r);
    assert!(text.starts_with(
        "jump speed: 698.4 rpm (steady-state separation; contact holds at 697.7 rpm: the onset lies between)\n"
    ));
    assert!(text.contains("margin -101.6 rpm (-12.7 %)  -- the follower JUMPS"));
    assert!(text.ends_with("14 simulations of 2 revolutions, 12 ms\n"));
    // No onset: the keys are absent from the JSON (never null), one line in the text.
    let none = JumpSpeedReport::new(
        &JumpSpeed {
            jump_rpm: None,
            no_jump_rpm: MAX_RPM,
            simulations: 10,
        },
        800.0,
        1.0,
        1.0,
    );
    let v = serde_json::to_value(&none).unwrap();
    for k in ["jump_rpm", "margin_rpm", "margin_percent"] {
        assert!(v.get(k).is_none(), "{k}: {v}");
    }
    assert!(!serde_json::to_string(&none).unwrap().contains("null"));
    assert!(render_text(&none).starts_with("no jump up to 10000 rpm\n"));
}

/// The more stable program's doubling overshoots to 1600 rpm, where the follower leaves
/// the cam in revolution 1 and the model then leaves its valid range (the follower is
/// thrown into its slide bearing: `Error::OutOfModel`): that counts as separation
/// (without it the search ends in an error), so the search still brackets an onset
/// between 800 rpm (contact holds: the doubling passed it) and 1600.
#[test]
fn a_run_that_fails_after_separating_counts_as_separation() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut spec = camsim::scene::load(&root.join("scenes/stable-4567-rise.toml")).unwrap();
    spec.solver.start = camsim_core::Start::Static;
    let r = find(&spec, 1.0, MAX_RPM).unwrap();
    let j = r.jump_rpm.unwrap();
    assert!(j > 800.0 && j < 1600.0, "{j}");
    assert!(j - r.no_jump_rpm <= 1.0);
}

/// At 1600 rpm a plain run of the more stable program ends in the validity error, which
/// names the physical cause and the cam angle (not the solver's step size), and the
/// jump-speed predicate reads the same run as a separation.
#[test]
fn leaving_the_model_after_separating_is_an_error_for_run_and_a_jump_for_the_search() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut spec = camsim::scene::load(&root.join("scenes/stable-4567-rise.toml")).unwrap();
    spec.solver.start = camsim_core::Start::Static;
    spec.revolutions = 2;
    spec.design.set_speed_rpm(1600.0).unwrap();
    let e = match camsim::sim::run(&spec, &mut camsim::sim::Nothing) {
        Ok(_) => panic!("1600 rpm ran to the end"),
        Err(e) => format!("{e:#}"),
    };
    assert!(
        e.contains("the model left its valid range at cam angle"),
        "{e}"
    );
    assert!(e.contains("cantilever length e2 - y3"), "{e}");
    assert!(!e.contains("step size"), "{e}");
    assert!(camsim::sim::jumps_at(&spec, 1600.0).unwrap());
}
