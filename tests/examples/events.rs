//! Contact events with and without location on the weak-spring model: a measurement,
//! not a check (docs/BENCHMARKS.md). Run with
//! `cargo run --release -p camsim-tests --example events`.

use camsim_tests::weak_spring::{model_run, rms_diff, weak_spring_model, GRID};

fn main() {
    let model = weak_spring_model(500.0);
    let r1 = model_run(&model, 1e-11, true);
    let r2 = model_run(&model, 1e-10, true);
    let r3 = model_run(&model, 1e-10, false);
    println!(
        "reference (rtol 1e-11, events) against rtol 1e-10 events: acc {:.3e} in/s², force {:.3e} lb; against 1e-10 without events: acc {:.3e}, force {:.3e}",
        rms_diff(&r1.acc, &r2.acc),
        rms_diff(&r1.force, &r2.force),
        rms_diff(&r1.acc, &r3.acc),
        rms_diff(&r1.force, &r3.force)
    );
    println!("reference events (deg): {:?}", &r1.events);
    let acc_rms = (r1.acc.iter().map(|a| a * a).sum::<f64>() / GRID as f64).sqrt();
    let fmax = r1.force.iter().cloned().fold(0.0, f64::max);
    println!("signal: acc RMS {acc_rms:.4e} in/s², largest sampled force {fmax:.4} lb");
    println!("rtol   events accepted rejected rej%  rhs_evals g_evals discarded  sep1 err(deg)  rec1 err(deg)  acc err    force err  fmax err");
    for rtol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
        for events in [false, true] {
            let r = model_run(&model, rtol, events);
            let e = |k: usize| r.events.get(k).map_or(f64::NAN, |x| x.0 - r1.events[k].0);
            let fm = r.force.iter().cloned().fold(0.0, f64::max);
            println!(
                "{rtol:.0e} {events:>6} {:>8} {:>8} {:>5.1} {:>10} {:>7} {:>9} {:>13.3e} {:>14.3e} {:>9.3e} {:>10.3e} {:>9.3e}",
                r.stats.accepted,
                r.stats.rejected,
                100.0 * r.stats.rejected as f64 / (r.stats.accepted + r.stats.rejected) as f64,
                r.stats.rhs_evals,
                r.event_evals,
                r.discarded,
                e(0),
                e(1),
                rms_diff(&r.acc, &r1.acc),
                rms_diff(&r.force, &r1.force),
                fm - fmax
            );
        }
    }
}
