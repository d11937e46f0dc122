//! Determinism (issue 10): the same scene gives bit-identical results on repeated runs
//! and whatever runs beside it on other threads, in `f64` (the host's runs, reports and
//! the jump-speed search) and in `f32` (the chip's model on the host). The firmware's
//! `f32` results equal the host's `f32` run by the parity check of
//! `camsim predict --f32 --check-log` (tests/predict.rs, firmware CI).
//!
//! Nothing in a run may depend on time, addresses, hashing or thread scheduling: the
//! core has no global state and no heap; the host's statistics are plain folds in sample
//! order. The checks compare every number by its bits.

use camsim::cmd::run::RunReport;
use camsim::sim::{self, Nothing, RunSpec};
use camsim_core::{
    simulate, Design, RegulatedFullModel, RegulatedVerticalModel, ResponseStats, SolverSettings,
    SolverStats, Start,
};

/// Threads that run the same work side by side.
const THREADS: usize = 3;

/// The scenes: the reference from static equilibrium (contact holds), the reference from
/// the thesis's start (an impact, then bouncing), and the listed 60 lb/in spring (jumps
/// every revolution), two revolutions each.
fn specs() -> Vec<(&'static str, RunSpec)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut stat = RunSpec::reference();
    stat.solver.start = Start::Static;
    let thesis = RunSpec::reference();
    let listed = camsim::scene::load(&root.join("scenes/listed-spring-60.toml")).unwrap();
    let mut out = vec![
        ("reference, static start", stat),
        ("reference, thesis start", thesis),
        ("listed spring", listed),
    ];
    for (_, s) in &mut out {
        s.revolutions = 2;
    }
    out
}

/// Every number of a run's report as its JSON (shortest round-trip digits: equal text is
/// equal bits), without the wall time; the solver's counters beside it.
fn fingerprint(spec: &RunSpec) -> (String, SolverStats) {
    let r = sim::run(spec, &mut Nothing).unwrap();
    let mut report = RunReport::new(spec, &r);
    report.wall_ms = 0.0;
    (serde_json::to_string(&report).unwrap(), r.solver)
}

#[test]
fn host_f64_runs_are_bit_identical_repeated_and_on_parallel_threads() {
    for (name, spec) in specs() {
        let first = fingerprint(&spec);
        // The run is not trivial: it has per-period rows and took steps.
        assert!(
            first.0.contains("per_period") && first.1.accepted > 1000,
            "{name}"
        );
        assert_eq!(fingerprint(&spec), first, "{name}: a second run differs");
        let parallel: Vec<(String, SolverStats)> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..THREADS)
                .map(|_| s.spawn(|| fingerprint(&spec)))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for (k, p) in parallel.iter().enumerate() {
            assert_eq!(p, &first, "{name}: thread {k} differs");
        }
    }
}

/// The statistics of revolution 2 of a `ResponseStats` as bits, and the solver counters.
fn stats_bits<T: camsim_core::Real>(
    stats: &ResponseStats<T, 2, 8, 64>,
    solver: SolverStats,
) -> Vec<u64> {
    let mut v = vec![
        u64::from(solver.accepted),
        u64::from(solver.rejected),
        u64::from(solver.rhs_evals),
    ];
    for rev in 1..=2 {
        for i in 0..8 {
            let Some(p) = stats.period(rev, i).filter(|p| p.samples > 0) else {
                continue;
            };
            v.push(u64::from(p.samples));
            for x in [
                p.rms_displacement(),
                p.rms_velocity(),
                p.rms_acceleration(),
                p.torque_avg(),
                p.force_avg(),
                p.aord_motor(),
                p.aord_coupling(),
                p.aord_cam(),
                p.torque_max,
                p.torque_min,
                p.force_max,
                p.force_min,
                p.stress_max,
            ] {
                v.push(x.to_f64().to_bits());
            }
        }
    }
    for j in stats.jumps() {
        v.push(u64::from(j.revolution));
        v.push(j.start_deg.to_f64().to_bits());
        v.push(j.end_deg.to_f64().to_bits());
    }
    v
}

/// The full model in `f32` at 800 rpm (the thesis's start: impacts and bouncing) and the
/// chip's vertical model, at the chip's tolerances.
fn f32_runs() -> Vec<Vec<u64>> {
    let settings: SolverSettings<f32> = camsim_chip::chip_solver_settings();
    let mut thesis = settings;
    thesis.start = Start::Thesis;
    let d = Design::<f32>::reference();
    let full = RegulatedFullModel::<f32>::new(d.clone()).unwrap();
    let mut s = ResponseStats::<f32, 2, 8, 64>::new(d.omega0);
    let a = simulate(&full, &thesis, 2, &mut s).unwrap();
    let full_bits = stats_bits(&s, a);
    let vertical = RegulatedVerticalModel::<f32>::new(d.clone()).unwrap();
    let mut s = ResponseStats::<f32, 2, 8, 64>::new(d.omega0);
    let b = simulate(&vertical, &settings, 2, &mut s).unwrap();
    let vertical_bits = stats_bits(&s, b);
    // The chip's steady state at two speeds, one of them jumping.
    let chip: Vec<u64> = [700.0f32, 950.0]
        .iter()
        .flat_map(|rpm| {
            let st = camsim_chip::ChipConfig::new(&d).steady_state(*rpm).unwrap();
            let mut v = vec![
                u64::from(st.min_contact_force.to_bits()),
                u64::from(st.min_force_deg.to_bits()),
                u64::from(st.jumped),
            ];
            v.extend(st.timing_deg.iter().map(|t| u64::from(t.to_bits())));
            v
        })
        .collect();
    vec![full_bits, vertical_bits, chip]
}

#[test]
fn host_f32_runs_are_bit_identical_repeated_and_on_parallel_threads() {
    let first = f32_runs();
    assert!(first.iter().all(|v| v.len() > 10));
    assert_eq!(f32_runs(), first, "a second f32 run differs");
    let parallel: Vec<Vec<Vec<u64>>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..THREADS).map(|_| s.spawn(f32_runs)).collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (k, p) in parallel.iter().enumerate() {
        assert_eq!(p, &first, "thread {k} differs");
    }
}

#[test]
fn the_jump_speed_search_is_bit_identical_repeated_and_on_parallel_threads() {
    let mut spec = RunSpec::reference();
    spec.solver.start = Start::Static;
    let search = |spec: &RunSpec| {
        let r = camsim::cmd::jump_speed::find(spec, 4.0, 2000.0).unwrap();
        (
            r.jump_rpm.map(f64::to_bits),
            r.no_jump_rpm.to_bits(),
            r.simulations,
        )
    };
    let first = search(&spec);
    assert!(first.0.is_some());
    assert_eq!(search(&spec), first);
    let parallel: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..2).map(|_| s.spawn(|| search(&spec))).collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert!(parallel.iter().all(|p| *p == first));
}

/// The checks can fail: a run at another tolerance has other bits.
#[test]
fn a_different_run_has_a_different_fingerprint() {
    let (_, spec) = specs().remove(0);
    let mut other = spec.clone();
    other.solver.rtol = 2e-6;
    assert_ne!(fingerprint(&other).0, fingerprint(&spec).0);
}
