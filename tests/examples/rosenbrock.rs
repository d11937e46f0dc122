//! The linearly implicit Rosenbrock-W method of `camsim bench` (ROS34PW2,
//! host-sim/src/bench/rosenbrock.rs) against England on the model: a measurement, not a
//! check, run with `cargo run --release -p camsim-tests --example rosenbrock`.
//! (Its order on closed forms is tested in host-sim's unit tests.)

use std::time::Instant;

use camsim::bench::methods::{run, Method};
use camsim::bench::sample::{Sampler, Samples};
use camsim::bench::settings;
use camsim_core::{Design, RegulatedFullModel};

fn main() {
    let mut d = Design::reference();
    d.set_speed_rpm(500.0).unwrap();
    let model = RegulatedFullModel::new(d).unwrap();
    let mut r = Sampler::new(&model, 2, Some(2));
    run(Method::England, &model, &settings(1e-13), 2, &mut r).unwrap();
    let reference = r.samples;
    let cases: Vec<(Method, f64)> = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
        .iter()
        .flat_map(|&rt| {
            [
                (Method::England, rt),
                (Method::EnglandPiCapped, rt),
                (Method::Rosenbrock { jac_every: 1 }, rt),
                (Method::Rosenbrock { jac_every: 10 }, rt),
            ]
        })
        .collect();
    println!("method                   rtol  accepted rejected    evals   wall ms   acc err (in/s²)  Fmin err (lb)");
    for (m, rt) in cases {
        let mut s = Sampler::new(&model, 2, Some(2));
        let t0 = Instant::now();
        let w = run(m, &model, &settings(rt), 2, &mut s);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        match w {
            Ok(w) => println!(
                "{:<24} {rt:.0e} {:>9} {:>8} {:>8} {:>9.1} {:>16.3e} {:>14.3e}",
                m.name(),
                w.accepted,
                w.rejected,
                w.evals,
                ms,
                Samples::rms_diff(&s.samples.acc, &reference.acc),
                (s.samples.force_min() - reference.force_min()).abs()
            ),
            Err(e) => println!("{:<24} {rt:.0e} failed: {e:#}", m.name()),
        }
    }
}
