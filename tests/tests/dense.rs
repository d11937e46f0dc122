//! England's dense output (`England::integrate_dense`, `Dense`): the quintic Hermite
//! interpolant through the start, midpoint and end of each double step and the
//! derivatives there. Checked against exact solutions: its interpolation error is sixth
//! order with the leading constant of the Hermite remainder, its local error within one
//! step is fifth order (the nodes' own), its global error fourth order with no loss
//! between the nodes; it reproduces the nodes bit for bit, and they are the points
//! `England::integrate` passes through.
//!
//! Measured numbers quoted in comments come from
//! `cargo test -p camsim-tests --test dense -- --nocapture`.

use core::ops::ControlFlow;

use camsim_core::{
    Dense, England, EnglandConfig, Error, OdeSystem, SolverStats, StepControl, Tolerance,
};

mod common;
use common::loglog_slope;

fn max_abs_diff<const N: usize>(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The unit oscillator and z' = -z² (z = 1/(1 + t)): smooth, partly nonlinear.
struct Smooth;
impl OdeSystem<f64, 3> for Smooth {
    fn rhs(&self, _t: f64, y: &[f64; 3], d: &mut [f64; 3]) {
        d[0] = y[1];
        d[1] = -y[0];
        d[2] = -y[2] * y[2];
    }
}
fn smooth_exact(t: f64) -> [f64; 3] {
    [t.cos(), -t.sin(), 1.0 / (1.0 + t)]
}

/// Kepler's problem (eccentricity 0.6 from pericentre): strongly varying step sizes.
struct Kepler;
impl OdeSystem<f64, 4> for Kepler {
    fn rhs(&self, _t: f64, y: &[f64; 4], d: &mut [f64; 4]) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        d[0] = y[2];
        d[1] = y[3];
        d[2] = -y[0] / r3;
        d[3] = -y[1] / r3;
    }
}

/// England with every double step exactly h (h_min = h_max, a tolerance it always meets).
fn fixed(h: f64) -> England<f64, 3> {
    England::new(EnglandConfig {
        tol: Tolerance::scalar(0.0, 1e6),
        h_init: h,
        h_min: h,
        h_max: h,
        max_steps: 1_000_000,
    })
    .unwrap()
}

#[test]
fn quintic_hermite_interpolation_is_sixth_order_with_the_remainder_constant() {
    // Exact data of y = (sin 2t, e^(2t)) at t0, t0 + h/2, t0 + h. The remainder is
    // y⁽⁶⁾(ξ) ψ(t)² / 6! with ψ = (t-t0)(t-t1)(t-t2), max ψ² = h⁶/432 (at
    // t - t1 = ±h/√12), so the largest error tends to |y⁽⁶⁾(t1)| h⁶ / (720 · 432).
    let y = |t: f64| [(2.0 * t).sin(), (2.0 * t).exp()];
    let f = |t: f64| [2.0 * (2.0 * t).cos(), 2.0 * (2.0 * t).exp()];
    let y6 = |t: f64| [-64.0 * (2.0 * t).sin(), 64.0 * (2.0 * t).exp()];
    let t0 = 0.4;
    let hs = [0.4, 0.2, 0.1, 0.05, 0.025];
    let mut errs = [Vec::new(), Vec::new()];
    let mut ratio = [0.0; 2];
    for &h in &hs {
        let t = [t0, t0 + 0.5 * h, t0 + h];
        let (ya, yb, yc) = (y(t[0]), y(t[1]), y(t[2]));
        let (fa, fb, fc) = (f(t[0]), f(t[1]), f(t[2]));
        let d = Dense::new(t, [&ya, &yb, &yc], [&fa, &fb, &fc]).unwrap();
        let mut worst = [0.0f64; 2];
        let mut out = [0.0; 2];
        for k in 0..=400 {
            let tt = t0 + h * k as f64 / 400.0;
            d.eval(tt, &mut out);
            let ex = y(tt);
            for c in 0..2 {
                worst[c] = worst[c].max((out[c] - ex[c]).abs());
            }
        }
        for c in 0..2 {
            errs[c].push(worst[c]);
            ratio[c] = worst[c] / (y6(t[1])[c].abs() * h.powi(6) / (720.0 * 432.0));
        }
    }
    for c in 0..2 {
        let p = loglog_slope(&hs, &errs[c]);
        println!(
            "component {c}: errors {:?}, order {p:.3}, error/remainder at the smallest h {:.4}",
            errs[c], ratio[c]
        );
        assert!((p - 6.0).abs() < 0.3, "component {c}: order {p}");
        assert!((ratio[c] - 1.0).abs() < 0.05, "component {c}: {}", ratio[c]);
    }
}

#[test]
fn dense_output_reproduces_the_nodes_bit_for_bit_and_they_are_integrates_points() {
    for control in [StepControl::classic(), StepControl::pi_capped()] {
        let cfg = EnglandConfig {
            tol: Tolerance::scalar(1e-9, 1e-9),
            h_init: 1e-3,
            h_min: 1e-12,
            h_max: 1.0,
            max_steps: 1_000_000,
        };
        let y0 = [0.4, 0.0, 0.0, (1.6f64 / 0.4).sqrt()];
        let t_end = 7.0;

        let mut plain = England::with_control(cfg, control).unwrap();
        let mut points = Vec::new();
        let mut y = y0;
        let stats_plain = plain
            .integrate(&Kepler, 0.0, &mut y, t_end, |t, y| {
                points.push((t, *y));
                ControlFlow::Continue(())
            })
            .unwrap();

        let mut dense = England::with_control(cfg, control).unwrap();
        let mut nodes = vec![(0.0, y0)];
        let mut yd = y0;
        let mut out = [0.0; 4];
        let mut calls = 0u32;
        let stats = dense
            .integrate_dense(&Kepler, 0.0, &mut yd, t_end, |d| {
                calls += 1;
                let [a, b, c] = d.nodes();
                assert_eq!(d.t_start(), nodes.last().unwrap().0);
                assert_eq!(*a, nodes.last().unwrap().1);
                for (t, node) in [(d.t_start(), a), (d.t_mid(), b), (d.t_end(), c)] {
                    d.eval(t, &mut out);
                    assert_eq!(out.map(f64::to_bits), node.map(f64::to_bits), "t = {t}");
                }
                nodes.push((d.t_mid(), *b));
                nodes.push((d.t_end(), *c));
                ControlFlow::Continue(())
            })
            .unwrap();
        assert_eq!(calls, stats.accepted);
        assert_eq!(nodes.len(), points.len());
        for ((t1, y1), (t2, y2)) in nodes.iter().zip(&points) {
            assert_eq!(t1.to_bits(), t2.to_bits());
            assert_eq!(y1.map(f64::to_bits), y2.map(f64::to_bits));
        }
        assert_eq!(yd, y);
        // The end derivative is the next step's first stage: one evaluation more in all.
        assert_eq!(stats.accepted, stats_plain.accepted);
        assert_eq!(stats.rejected, stats_plain.rejected);
        assert_eq!(stats.rhs_evals, stats_plain.rhs_evals + 1);
        assert_eq!(dense.auxiliary_evals(), plain.auxiliary_evals() + 1);
    }
}

#[test]
fn dense_output_local_error_is_fifth_order_like_the_step_itself() {
    // One double step from the exact state: the nodes carry the RK4 local errors O(h⁵),
    // the interpolation adds O(h⁶), so the largest error inside the step is O(h⁵).
    // (From h = 0.4 the error ratios per halving are 21, 25, 28, 30: asymptotic below 0.1.)
    let t0 = 0.3;
    let hs = [0.1, 0.05, 0.025, 0.0125];
    let mut errs = Vec::new();
    let mut node_errs = Vec::new();
    for &h in &hs {
        let mut s = fixed(h);
        let mut y = smooth_exact(t0);
        let mut worst = 0.0f64;
        let mut worst_node = 0.0f64;
        let mut out = [0.0; 3];
        s.integrate_dense(&Smooth, t0, &mut y, t0 + h, |d| {
            for k in 0..=200 {
                let t = d.t_start() + (d.t_end() - d.t_start()) * k as f64 / 200.0;
                d.eval(t, &mut out);
                worst = worst.max(max_abs_diff(&out, &smooth_exact(t)));
            }
            let [_, b, c] = d.nodes();
            worst_node = worst_node
                .max(max_abs_diff(b, &smooth_exact(d.t_mid())))
                .max(max_abs_diff(c, &smooth_exact(d.t_end())));
            ControlFlow::Continue(())
        })
        .unwrap();
        errs.push(worst);
        node_errs.push(worst_node);
    }
    let p = loglog_slope(&hs, &errs);
    println!("local: dense {errs:?}, nodes {node_errs:?}, order {p:.3}");
    assert!((p - 5.0).abs() < 0.3, "order {p}");
    // Between the nodes no worse than at them (measured ratio 1.0).
    for (e, n) in errs.iter().zip(&node_errs) {
        assert!(*e <= 1.5 * n, "{e} vs {n}");
    }
}

#[test]
fn dense_output_global_error_is_fourth_order_with_no_loss_between_nodes() {
    let t_end = 2.0;
    let hs = [0.2, 0.1, 0.05, 0.025, 0.0125];
    let mut errs = Vec::new();
    let mut node_errs = Vec::new();
    for &h in &hs {
        let mut s = fixed(h);
        let mut y = smooth_exact(0.0);
        let mut worst = 0.0f64;
        let mut worst_node = 0.0f64;
        let mut out = [0.0; 3];
        s.integrate_dense(&Smooth, 0.0, &mut y, t_end, |d| {
            for k in 0..=20 {
                let t = d.t_start() + (d.t_end() - d.t_start()) * k as f64 / 20.0;
                d.eval(t, &mut out);
                worst = worst.max(max_abs_diff(&out, &smooth_exact(t)));
            }
            for (t, node) in [(d.t_mid(), d.nodes()[1]), (d.t_end(), d.nodes()[2])] {
                worst_node = worst_node.max(max_abs_diff(node, &smooth_exact(t)));
            }
            ControlFlow::Continue(())
        })
        .unwrap();
        errs.push(worst);
        node_errs.push(worst_node);
    }
    let p = loglog_slope(&hs, &errs);
    println!("global: dense {errs:?}, nodes {node_errs:?}, order {p:.3}");
    assert!((p - 4.0).abs() < 0.3, "order {p}");
    for (e, n) in errs.iter().zip(&node_errs) {
        assert!(*e <= 1.5 * n, "{e} vs {n}");
    }
}

#[test]
fn dense_derivative_matches_f_at_the_nodes_and_is_continuous_across_steps() {
    let cfg = EnglandConfig {
        tol: Tolerance::scalar(1e-8, 1e-8),
        h_init: 1e-2,
        h_min: 1e-12,
        h_max: 1.0,
        max_steps: 100_000,
    };
    let mut s = England::new(cfg).unwrap();
    let mut y = [0.4, 0.0, 0.0, (1.6f64 / 0.4).sqrt()];
    let mut prev_end: Option<[f64; 4]> = None;
    let (mut dd, mut f) = ([0.0; 4], [0.0; 4]);
    let mut worst: f64 = 0.0;
    s.integrate_dense(&Kepler, 0.0, &mut y, 6.0, |d| {
        let ts = [d.t_start(), d.t_mid(), d.t_end()];
        for (j, &t) in ts.iter().enumerate() {
            d.eval_derivative(t, &mut dd);
            Kepler.rhs(t, d.nodes()[j], &mut f);
            let scale = f.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            worst = worst.max(max_abs_diff(&dd, &f) / scale);
            // f at the start and end is evaluated; at the midpoint it is k5/s (one rounding).
            if j == 1 {
                assert!(max_abs_diff(d.derivatives()[j], &f) <= 4.0 * f64::EPSILON * scale);
            } else {
                assert_eq!(
                    d.derivatives()[j].map(f64::to_bits),
                    f.map(f64::to_bits),
                    "{j}"
                );
            }
        }
        d.eval_derivative(d.t_start(), &mut dd);
        if let Some(p) = prev_end {
            let scale = p.iter().fold(1.0f64, |a, v| a.max(v.abs()));
            assert!(max_abs_diff(&p, &dd) <= 1e-9 * scale, "{p:?} {dd:?}");
        }
        d.eval_derivative(d.t_end(), &mut dd);
        prev_end = Some(dd);
        ControlFlow::Continue(())
    })
    .unwrap();
    println!("largest relative derivative mismatch at a node: {worst:e}");
    assert!(worst < 1e-9);
}

#[test]
fn dense_samples_on_a_uniform_grid_follow_the_tolerance() {
    // Sampling the adaptive solution on a grid independent of the steps: the grid's
    // error is the nodes' error (global error ∝ tol^(4/5)), not worse.
    let e = 0.6f64;
    let kepler_exact = |t: f64| {
        let mut ea = t + e * t.sin();
        for _ in 0..50 {
            ea -= (ea - e * ea.sin() - t) / (1.0 - e * ea.cos());
        }
        let (s, c) = ea.sin_cos();
        let b = (1.0 - e * e).sqrt();
        let r = 1.0 - e * c;
        [c - e, b * s, -s / r, b * c / r]
    };
    for tol in [1e-8, 1e-10] {
        let mut s = England::new(EnglandConfig {
            tol: Tolerance::scalar(tol, tol),
            h_init: 1e-3,
            h_min: 1e-12,
            h_max: 1.0,
            max_steps: 1_000_000,
        })
        .unwrap();
        let mut y = kepler_exact(0.0);
        let (mut grid, mut nodes) = (0.0f64, 0.0f64);
        let mut next = 0.0;
        let mut out = [0.0; 4];
        let stats = s
            .integrate_dense(&Kepler, 0.0, &mut y, 6.0, |d| {
                while next <= d.t_end() {
                    d.eval(next, &mut out);
                    grid = grid.max(max_abs_diff(&out, &kepler_exact(next)));
                    next += 1e-3;
                }
                nodes = nodes.max(max_abs_diff(d.nodes()[2], &kepler_exact(d.t_end())));
                ControlFlow::Continue(())
            })
            .unwrap();
        println!("tol {tol:e}: grid error {grid:.3e}, node error {nodes:.3e}, {stats:?}");
        assert!(next > 6.0);
        assert!(grid <= 1.5 * nodes, "{grid} vs {nodes}");
    }
}

#[test]
fn dense_output_edges() {
    // No step, no call.
    let mut s = fixed(0.1);
    let mut y = smooth_exact(0.0);
    let stats = s
        .integrate_dense(&Smooth, 1.0, &mut y, 1.0, |_| panic!("no step expected"))
        .unwrap();
    assert_eq!(stats, SolverStats::default());
    // Break after the first step: y at its end.
    let mut first = (0.0, [0.0; 3]);
    let stats = s
        .integrate_dense(&Smooth, 0.0, &mut y, 1.0, |d| {
            first = (d.t_end(), *d.nodes()[2]);
            ControlFlow::Break(())
        })
        .unwrap();
    assert_eq!(stats.accepted, 1);
    assert_eq!(first.0, 0.1);
    assert_eq!(y, first.1);
    // The nodes must be finite and strictly increasing.
    let z = [0.0; 1];
    for t in [
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [1.0, 0.5, 2.0],
        [0.0, f64::NAN, 1.0],
    ] {
        match Dense::new(t, [&z, &z, &z], [&z, &z, &z]) {
            Err(Error::InvalidParameter { field: "t", .. }) => {}
            other => panic!("{t:?}: {other:?}"),
        }
    }
    // Unequal spacing is allowed: a cubic is reproduced exactly by a quintic.
    let p = |t: f64| [2.0 - t + 0.5 * t * t * t];
    let dp = |t: f64| [-1.0 + 1.5 * t * t];
    let t = [0.0, 0.3, 1.0];
    let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
    let (da, db, dc) = (dp(t[0]), dp(t[1]), dp(t[2]));
    let d = Dense::new(t, [&a, &b, &c], [&da, &db, &dc]).unwrap();
    let mut out = [0.0];
    for k in 0..=10 {
        let tt = -0.2 + 0.14 * k as f64;
        d.eval(tt, &mut out);
        assert!((out[0] - p(tt)[0]).abs() < 1e-13, "{tt}");
    }
}
