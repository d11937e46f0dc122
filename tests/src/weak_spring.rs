//! The cam model with a return spring so weak that the follower leaves the cam every
//! revolution (30 lb/in instead of 100, the jump onset near 494 rpm; tests/stress.rs), at
//! 500 rpm from static equilibrium: shared by the contact-event tests (tests/events.rs)
//! and their measurement (`cargo run --release -p camsim-tests --example events`).

use std::ops::ControlFlow;

use camsim::bench::settings;
use camsim_core::{
    solver_config, ContactEventFn, Design, England, EventConfig, RegulatedFullModel, Report,
    SolverStats,
};

/// The reference design with a 30 lb/in return spring at `rpm`.
pub fn weak_spring_model(rpm: f64) -> RegulatedFullModel<f64> {
    let mut d = Design::reference();
    d.set_speed_rpm(rpm).unwrap();
    d.k_rs = 30.0;
    d.k_rs_modal = 30.0;
    RegulatedFullModel::new(d).unwrap()
}

/// What one run of the model gives: work, event angles, and samples on a uniform time
/// grid of revolution 2 (through the dense output).
#[derive(Debug, Default)]
pub struct ModelRun {
    /// Solver counters.
    pub stats: SolverStats,
    /// Event-function evaluations.
    pub event_evals: u32,
    /// Steps discarded at events.
    pub discarded: u32,
    /// (cam angle in degrees, unwrapped; separation?) of each event: located, or with
    /// events off the first step node on the new side.
    pub events: Vec<(f64, bool)>,
    /// Load acceleration and contact force at the grid times.
    pub acc: Vec<f64>,
    /// Contact force at the grid times.
    pub force: Vec<f64>,
}

/// Samples of revolution 2 on a uniform time grid.
pub const GRID: usize = 1440;

/// Runs `model` 3 revolutions from static equilibrium at `rtol`, with or without
/// contact events.
pub fn model_run(model: &RegulatedFullModel<f64>, rtol: f64, events: bool) -> ModelRun {
    let s = settings(rtol);
    let revs = 3;
    let config = solver_config(model, &s, revs).unwrap();
    let mut solver = England::new(config).unwrap();
    let mut y = model.static_state();
    let period = 2.0 * std::f64::consts::PI / model.design().omega0;
    let t_end = revs as f64 * period;
    let grid: Vec<f64> = (0..GRID)
        .map(|k| period * (1.0 + k as f64 / GRID as f64))
        .collect();
    let mut out = ModelRun::default();
    let mut next = 0usize;
    let mut yd = [0.0; 22];
    let mut contact = model.evaluate(0.0, &y).in_contact;
    let gfn = ContactEventFn(model);
    let mut on_step = |d: &camsim_core::Dense<'_, f64, 22>, out: &mut ModelRun, events: bool| {
        while next < GRID && grid[next] <= d.t_end() {
            d.eval(grid[next], &mut yd);
            let p = model.evaluate(grid[next], &yd);
            out.acc.push(p.load_acceleration());
            out.force.push(p.contact_force);
            next += 1;
        }
        if !events {
            for (t, yn) in [(d.t_mid(), d.nodes()[1]), (d.t_end(), d.nodes()[2])] {
                let p = model.evaluate(t, yn);
                if p.in_contact != contact {
                    contact = p.in_contact;
                    out.events.push((p.theta_c.to_degrees(), !contact));
                }
            }
        }
    };
    if events {
        let mut found = Vec::new();
        let (stats, ev) = solver
            .integrate_events(
                model,
                &gfn,
                &EventConfig::new(1e-9 * period),
                0.0,
                &mut y,
                t_end,
                |r| {
                    match r {
                        Report::Step(d) => on_step(d, &mut out, true),
                        Report::Event(e, ye) => {
                            let p = model.evaluate(e.t, ye);
                            found.push((p.theta_c.to_degrees(), !e.rising));
                        }
                    }
                    ControlFlow::Continue(())
                },
            )
            .unwrap();
        out.stats = stats;
        out.event_evals = ev.event_evals;
        out.discarded = ev.discarded_steps;
        out.events = found;
    } else {
        out.stats = solver
            .integrate_dense(model, 0.0, &mut y, t_end, |d| {
                on_step(d, &mut out, false);
                ControlFlow::Continue(())
            })
            .unwrap();
    }
    assert_eq!(out.acc.len(), GRID);
    out
}

/// RMS of the difference of two equally long series.
pub fn rms_diff(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
}
