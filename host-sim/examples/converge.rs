//! Issue 22's experiment: the error of each method against its tolerance on the reference
//! design (full 22-state scene, static start, 2 revolutions, the load's acceleration RMS
//! over revolution 2 at 720 cam angles against England at rtol 1e-13: `camsim bench`'s
//! model, settings, sampler and reference), with the RMS error of every state component,
//! so that the component whose error stops converging shows. docs/BENCHMARKS.md (issue 22's
//! section) gives what each mode showed.
//!
//! `cargo run --release -p camsim --example converge -- [rpm] [rtol...]` (500 rpm, rtol
//! 1e-5 to 1e-8 by default): England, PI-capped England and Dormand-Prince at each rtol.
//! Modes (environment variables; the first set wins):
//! - `CONVERGE_EXTRAP=0|1`: England's double step in a plain loop with the classic rule,
//!   advancing with `y2` (0) or with the fifth-order `y2 + E` (1); with
//!   `CONVERGE_DWELL_H=<s>` its double step is at most that in the dwells (0-31°, 179-211°).
//! - `CONVERGE_VARIANT=atolf,vfac[,frac]`: England with atol `atolf·rtol` in, the velocities'
//!   and speeds' atol times `vfac`, the largest step `frac` of a revolution; with
//!   `CONVERGE_CAP=<fraction>` PI-capped England with that stiffness-cap fraction instead.
//! - `CONVERGE_END=1`: the state at 2 nominal periods (no interpolant) per component.
//! - `CONVERGE_LOCAL=<rtol>`: every accepted step of England: cam angle, double step,
//!   estimated error ratio, true ratio (the step redone from its start at 1e-13), its worst
//!   component, the load velocity's true local error; `CONVERGE_VFAC` scales the
//!   velocities' atol; `CONVERGE_AT=<deg>` also prints each component and the step halved
//!   five times at the steps starting within 0.05° after that angle.
//! - `CONVERGE_DUMP=<rtol>`: England's error of every component at every sample.
//! - `CONVERGE_SCALED=<r0>`: England classic (capped) and PI-capped with the stiffness cap
//!   shrinking as `(rtol/r0)^(1/5)` below `r0` (`StiffnessCap::tolerance_scaled`), then
//!   the capped imaginary-axis method (Merson) the same.
//! - `CONVERGE_EPUS=<h_ref>`: England classic and PI-capped with error per unit step
//!   (`camsim_core::PerUnitStep`), reference double step `h_ref` revolutions at ω0.
//!
//! Model variants: `CONVERGE_MU=<μ>`, `CONVERGE_VS=<in/s>` (friction and its smoothing),
//! `CONVERGE_SMOOTH=1` (4-5-6-7 rise and return), `CONVERGE_STABLE=1`
//! (`scenes/stable-4567-rise.toml`'s program); the reference is computed on the same
//! model.

use anyhow::Result;
use camsim::bench::methods::{run, Method};
use camsim::bench::sample::{Sampler, Samples};
use camsim::bench::{design_at, settings, MEASURED, REFERENCE_RTOL, REVOLUTIONS};
use camsim_core::{
    solver_config, CamModel, England, EnglandConfig, OdeSystem, RegulatedFull, Scene, StateVar,
    TransDof,
};

type Model = CamModel<f64, RegulatedFull, { RegulatedFull::N }>;

fn sampled(model: &Model, method: Method, rtol: f64) -> Result<(Samples, u64)> {
    let mut s = Sampler::new(model, REVOLUTIONS, Some(MEASURED)).keep_states();
    let w = run(method, model, &settings::<f64>(rtol), REVOLUTIONS, &mut s)?;
    Ok((s.samples, w.evals))
}

/// England's double step of size `h` from `(t0, y0)`: the end point and `E`.
fn england_step<S: OdeSystem<f64, N>, const N: usize>(
    sys: &S,
    t0: f64,
    y0: &[f64; N],
    h: f64,
) -> ([f64; N], [f64; N]) {
    let s = 0.5 * h;
    let f = |t: f64, y: &[f64; N]| {
        let mut d = [0.0; N];
        sys.rhs(t, y, &mut d);
        d.map(|v| v * s)
    };
    let lin = |c: &[(f64, &[f64; N])]| {
        let mut o = *y0;
        for (w, k) in c {
            for (oi, ki) in o.iter_mut().zip(k.iter()) {
                *oi += w * ki;
            }
        }
        o
    };
    let k1 = f(t0, y0);
    let k2 = f(t0 + s / 2.0, &lin(&[(0.5, &k1)]));
    let k3 = f(t0 + s / 2.0, &lin(&[(0.25, &k1), (0.25, &k2)]));
    let k4 = f(t0 + s, &lin(&[(-1.0, &k2), (2.0, &k3)]));
    let y1 = lin(&[(1.0 / 6.0, &k1), (4.0 / 6.0, &k3), (1.0 / 6.0, &k4)]);
    let t1 = t0 + s;
    let from1 = |c: &[(f64, &[f64; N])]| {
        let mut o = y1;
        for (w, k) in c {
            for (oi, ki) in o.iter_mut().zip(k.iter()) {
                *oi += w * ki;
            }
        }
        o
    };
    let k5 = f(t1, &y1);
    let k6 = f(t1 + s / 2.0, &from1(&[(0.5, &k5)]));
    let k7 = f(t1 + s / 2.0, &from1(&[(0.25, &k5), (0.25, &k6)]));
    let k8 = f(t1 + s, &from1(&[(-1.0, &k6), (2.0, &k7)]));
    let y2 = from1(&[(1.0 / 6.0, &k5), (4.0 / 6.0, &k7), (1.0 / 6.0, &k8)]);
    let k9 = f(
        t0 + 2.0 * s,
        &lin(&[
            (-1.0 / 6.0, &k1),
            (-96.0 / 6.0, &k2),
            (92.0 / 6.0, &k3),
            (-121.0 / 6.0, &k4),
            (144.0 / 6.0, &k5),
            (1.0, &k6),
            (-2.0, &k7),
        ]),
    );
    let mut e = [0.0; N];
    for i in 0..N {
        e[i] = (-k1[i] + 4.0 * k3[i] + 17.0 * k4[i] - 23.0 * k5[i] + 4.0 * k7[i] - k9[i]) / 90.0;
    }
    (y2, e)
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rpm: f64 = args.first().map_or(Ok(500.0), |a| a.parse())?;
    let rtols: Vec<f64> = if args.len() > 1 {
        args[1..]
            .iter()
            .map(|a| a.parse())
            .collect::<Result<_, _>>()?
    } else {
        vec![1e-5, 1e-6, 1e-7, 1e-8]
    };
    let mut design = design_at(rpm)?;
    if let Ok(v) = std::env::var("CONVERGE_MU") {
        design.mu = v.parse()?;
    }
    if let Ok(v) = std::env::var("CONVERGE_VS") {
        design.friction_smoothing = v.parse()?;
    }
    if std::env::var("CONVERGE_SMOOTH").is_ok() {
        // Both laws 4-5-6-7 (jerk zero at the ends) instead of the modified trapezoidal rise.
        design.program = camsim_core::CamProgram::with_laws(
            camsim_core::MotionLaw::Poly4567,
            camsim_core::MotionLaw::Poly4567,
        );
    }
    if std::env::var("CONVERGE_STABLE").is_ok() {
        // scenes/stable-4567-rise.toml: 4-5-6-7 rise, modified trapezoidal return.
        design.program = camsim_core::CamProgram::with_laws(
            camsim_core::MotionLaw::Poly4567,
            camsim_core::MotionLaw::ModifiedTrapezoidal,
        );
    }
    let model = Model::new(design)?;
    let (r, _) = sampled(&model, Method::England, REFERENCE_RTOL)?;
    let layout = RegulatedFull::LAYOUT;
    let mut names = vec![String::new(); RegulatedFull::N];
    for v in StateVar::ROTATIONAL {
        if let Some(i) = layout.index(v) {
            names[i] = format!("{v:?}");
        }
    }
    for d in TransDof::ALL {
        for (v, p) in [(StateVar::Position(d), "q"), (StateVar::Velocity(d), "v")] {
            if let Some(i) = layout.index(v) {
                names[i] = format!("{p}:{d:?}");
            }
        }
    }
    if let Ok(spec) = std::env::var("CONVERGE_EXTRAP") {
        // CONVERGE_EXTRAP=0|1: England's double step with its classic step-size rule in a
        // plain loop, advancing with y2 (0) or the fifth-order y2 + E (1: local
        // extrapolation), sampled through the cubic Hermite of the step ends.
        let extrap = spec == "1";
        // CONVERGE_DWELL_H: largest double step in the dwells (0-30 and 180-210 deg).
        let dwell_h: f64 =
            std::env::var("CONVERGE_DWELL_H").map_or(f64::MAX, |v| v.parse().unwrap_or(f64::MAX));
        for &rtol in &rtols {
            let cfg = solver_config(&model, &settings::<f64>(rtol), REVOLUTIONS)?;
            let mut sampler = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
            let mut nodes = camsim::bench::sample::NodeHermite::default();
            let mut y = model.static_state();
            let mut t = 0.0;
            let mut h = cfg.h_init;
            let mut f = [0.0; RegulatedFull::N];
            let mut evals = 1u64;
            model.rhs(t, &y, &mut f);
            let _ = nodes.push(&mut sampler, t, &y, &f);
            let mut rejected_last = false;
            loop {
                let (y2, e) = england_step(&model, t, &y, h);
                evals += 9;
                let mut err: f64 = 0.0;
                for i in 0..RegulatedFull::N {
                    let sc = cfg.tol.atol[i] + rtol * y[i].abs().max(y2[i].abs());
                    err = err.max(e[i].abs() / sc);
                }
                if !err.is_finite() {
                    anyhow::bail!("non-finite at t {t}");
                }
                if err <= 1.0 {
                    t += h;
                    for i in 0..RegulatedFull::N {
                        y[i] = if extrap { y2[i] + e[i] } else { y2[i] };
                    }
                    model.rhs(t, &y, &mut f);
                    evals += 1;
                    let fac = (0.9 * err.max(1e-10).powf(-0.2))
                        .clamp(0.2, if rejected_last { 1.0 } else { 5.0 });
                    h = (h * fac).min(cfg.h_max);
                    let deg = model.cam_angle(t, &y).to_degrees() % 360.0;
                    if deg < 31.0 || (179.0..211.0).contains(&deg) {
                        h = h.min(dwell_h);
                    }
                    rejected_last = false;
                    if nodes.push(&mut sampler, t, &y, &f).is_break() {
                        break;
                    }
                } else {
                    h *= (0.9 * err.powf(-0.2)).clamp(0.2, 1.0);
                    rejected_last = true;
                }
            }
            println!(
                "extrap {extrap} rtol {rtol:e}: evals {evals} acc err {:.3e} disp err {:.3e}",
                Samples::rms_diff(&sampler.samples.acc, &r.acc),
                Samples::rms_diff(&sampler.samples.disp, &r.disp)
            );
        }
        return Ok(());
    }
    if let Ok(spec) = std::env::var("CONVERGE_VARIANT") {
        // CONVERGE_VARIANT=atolf,vfac,rtolv: England (classic) with atol = atolf·rtol in,
        // velocity atol multiplied by vfac, and rtol of the velocities multiplied by rtolv
        // (emulated through atol: rtolv<1 adds nothing, it is reported only).
        let v: Vec<f64> = spec
            .split(',')
            .map(|x| x.parse())
            .collect::<Result<_, _>>()?;
        for &rtol in &rtols {
            let mut st = settings::<f64>(rtol);
            st.atol = v[0] * rtol;
            if let Some(f) = v.get(2) {
                st.max_step_fraction = *f;
            }
            let mut cfg = solver_config(&model, &st, REVOLUTIONS)?;
            for (i, n) in names.iter().enumerate() {
                if n.starts_with("v:") || n.ends_with("Speed") {
                    cfg.tol.atol[i] *= v[1];
                }
            }
            let mut sampler = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
            let mut solver = match std::env::var("CONVERGE_CAP") {
                Ok(f) => {
                    let mut c = camsim_core::StepControl::pi_capped();
                    if let Some(cap) = c.stiffness_cap.as_mut() {
                        cap.fraction = f.parse()?;
                    }
                    England::with_control(cfg, c)?
                }
                Err(_) => England::new(cfg)?,
            };
            let mut y = model.static_state();
            let t_end = 8.0 * std::f64::consts::PI / model.design().omega0;
            let stats = solver.integrate_dense(&model, 0.0, &mut y, t_end, |d| sampler.feed(d))?;
            println!(
                "variant {spec} rtol {rtol:e}: evals {} acc err {:.3e} disp err {:.3e}",
                stats.rhs_evals,
                Samples::rms_diff(&sampler.samples.acc, &r.acc),
                Samples::rms_diff(&sampler.samples.disp, &r.disp)
            );
        }
        return Ok(());
    }
    if std::env::var("CONVERGE_END").is_ok() {
        // The state at t = 2 nominal periods (a step lands there), per component, against
        // England at 1e-13: no interpolant involved.
        let t_end = 4.0 * std::f64::consts::PI / model.design().omega0;
        let end_state = |rtol: f64| -> Result<[f64; RegulatedFull::N]> {
            let cfg = solver_config(&model, &settings::<f64>(rtol), REVOLUTIONS)?;
            let mut solver = England::new(cfg)?;
            let mut y = model.static_state();
            solver.integrate(&model, 0.0, &mut y, t_end, |_, _| {
                std::ops::ControlFlow::Continue(())
            })?;
            Ok(y)
        };
        let yr = end_state(REFERENCE_RTOL)?;
        let ar = model.evaluate(t_end, &yr).load_acceleration();
        for &rtol in &rtols {
            let y = end_state(rtol)?;
            let a = model.evaluate(t_end, &y).load_acceleration();
            let mut line = format!("end rtol {rtol:e}: acc err {:+.3e}", a - ar);
            for i in [3, 6, 13, 14, 15, 17, 20, 21] {
                line += &format!(" {}={:+.2e}", names[i], y[i] - yr[i]);
            }
            println!("{line}");
        }
        return Ok(());
    }
    if let Ok(spec) = std::env::var("CONVERGE_LOCAL") {
        // CONVERGE_LOCAL=rtol: every accepted step of England (classic) over 2 revolutions:
        // its error ratio (the estimate) against the true local error ratio (the same step
        // from the same start by England at rtol 1e-13), with the cam angle.
        let rtol: f64 = spec.parse()?;
        let st = settings::<f64>(rtol);
        let mut cfg = solver_config(&model, &st, REVOLUTIONS)?;
        // CONVERGE_VFAC: the velocities' and speeds' atol multiplied by this.
        if let Ok(f) = std::env::var("CONVERGE_VFAC") {
            let f: f64 = f.parse()?;
            for (i, n) in names.iter().enumerate() {
                if n.starts_with("v:") || n.ends_with("Speed") {
                    cfg.tol.atol[i] *= f;
                }
            }
        }
        let mut solver = England::new(cfg)?;
        let tight = solver_config(&model, &settings::<f64>(REFERENCE_RTOL), REVOLUTIONS)?;
        let mut y = model.static_state();
        let mut t = 0.0;
        let t_end = 2.0 * 2.0 * std::f64::consts::PI / model.design().omega0;
        let mut mid = (0.0, y);
        println!("deg h est true worst_component");
        while t < t_end {
            let (t0, y0) = (t, y);
            let est = solver.step(&model, &mut t, &mut y, t_end, &mut mid)?;
            let mut yr = y0;
            let mut fine = England::new(EnglandConfig {
                h_init: (t - t0) * 0.01,
                ..tight
            })?;
            fine.integrate(&model, t0, &mut yr, t, |_, _| {
                std::ops::ControlFlow::Continue(())
            })?;
            if let Ok(deg) = std::env::var("CONVERGE_AT") {
                let a: f64 = deg.parse()?;
                let th = model.cam_angle(t0, &y0).to_degrees();
                if th >= a && th < a + 0.05 {
                    for div in [1.0, 2.0, 4.0, 8.0, 16.0, 32.0] {
                        let hh = (t - t0) / div;
                        let (y2, e) = england_step(&model, t0, &y0, hh);
                        let mut yf = y0;
                        let mut fine = England::new(EnglandConfig {
                            h_init: hh * 0.01,
                            ..tight
                        })?;
                        fine.integrate(&model, t0, &mut yf, t0 + hh, |_, _| {
                            std::ops::ControlFlow::Continue(())
                        })?;
                        let mut line = format!("  h/{div}:");
                        for i in [3, 8, 16, 18, 21] {
                            line += &format!(
                                " {} E {:+.2e} true {:+.2e}",
                                names[i],
                                e[i],
                                yf[i] - y2[i]
                            );
                        }
                        println!("{line}");
                    }
                    let (y2, e) = england_step(&model, t0, &y0, t - t0);
                    for i in 0..RegulatedFull::N {
                        let sc = cfg.tol.atol[i] + rtol * y0[i].abs().max(y[i].abs());
                        println!(
                            "  {:>14} y {:+.6e} E/sc {:+.3e} true/sc {:+.3e} (y2-solver {:.1e})",
                            names[i],
                            y[i],
                            e[i] / sc,
                            (yr[i] - y[i]) / sc,
                            y2[i] - y[i]
                        );
                    }
                }
            }
            let mut worst = (0.0f64, 0usize);
            for i in 0..RegulatedFull::N {
                let sc = cfg.tol.atol[i] + rtol * y0[i].abs().max(y[i].abs());
                let e = (y[i] - yr[i]).abs() / sc;
                if e > worst.0 {
                    worst = (e, i);
                }
            }
            // Last column: the load velocity's true local error, in/s.
            let load_v = RegulatedFull::LAYOUT
                .index(StateVar::Velocity(TransDof::Load))
                .unwrap_or(0);
            println!(
                "{:.4} {:.3e} {:.3e} {:.3e} {} {:.3e}",
                model.cam_angle(t0, &y0).to_degrees(),
                t - t0,
                est,
                worst.0,
                names[worst.1],
                yr[load_v] - y[load_v]
            );
        }
        return Ok(());
    }
    if let Ok(spec) = std::env::var("CONVERGE_DUMP") {
        // CONVERGE_DUMP=rtol: the error of every state component at every sample.
        let rtol: f64 = spec.parse()?;
        let (s, _) = sampled(&model, Method::England, rtol)?;
        println!("deg acc_err {}", names.join(" "));
        for k in 0..s.states.len() {
            let mut line = format!("{:.1} {:.3e}", k as f64 * 0.5, s.acc[k] - r.acc[k]);
            for i in 0..names.len() {
                line += &format!(" {:.3e}", s.states[k][i] - r.states[k][i]);
            }
            println!("{line}");
        }
        return Ok(());
    }
    if let Ok(spec) = std::env::var("CONVERGE_SCALED") {
        // CONVERGE_SCALED=r0: England classic and PI, each with the stiffness cap shrinking
        // as (rtol/r0)^(1/5) below r0 (StiffnessCap::tolerance_scaled).
        let r0: f64 = spec.parse()?;
        let cap = Some(camsim_core::StiffnessCap::tolerance_scaled(r0));
        for (name, base) in [
            ("england_capped", camsim_core::StepControl::classic_capped()),
            ("england_pi_capped", camsim_core::StepControl::pi_capped()),
        ] {
            let control = camsim_core::StepControl {
                stiffness_cap: cap,
                ..base
            };
            for &rtol in &rtols {
                let mut s = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
                let w = camsim::bench::methods::run_england(
                    &model,
                    &settings::<f64>(rtol),
                    control,
                    REVOLUTIONS,
                    &mut s,
                )?;
                println!(
                    "{name} scaled-cap {r0:e} rtol {rtol:e}: evals {} acc err {:.3e} disp err {:.3e}",
                    w.evals,
                    Samples::rms_diff(&s.samples.acc, &r.acc),
                    Samples::rms_diff(&s.samples.disp, &r.disp)
                );
            }
        }
        for &rtol in &rtols {
            let mut s = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
            let w = camsim::bench::methods::run_merson(
                &model,
                &settings::<f64>(rtol),
                cap,
                REVOLUTIONS,
                &mut s,
            )?;
            println!(
                "merson_capped scaled-cap {r0:e} rtol {rtol:e}: evals {} acc err {:.3e} disp err {:.3e}",
                w.evals,
                Samples::rms_diff(&s.samples.acc, &r.acc),
                Samples::rms_diff(&s.samples.disp, &r.disp)
            );
        }
        return Ok(());
    }
    if let Ok(spec) = std::env::var("CONVERGE_EPUS") {
        // CONVERGE_EPUS=f: England classic and PI-capped with error per unit step,
        // reference double step h_ref = f revolutions at omega0.
        let f: f64 = spec.parse()?;
        let period = 2.0 * std::f64::consts::PI / model.design().omega0;
        let pus = Some(camsim_core::PerUnitStep::new(f * period));
        for (name, base) in [
            ("england", camsim_core::StepControl::classic()),
            ("england_pi_capped", camsim_core::StepControl::pi_capped()),
        ] {
            let control = camsim_core::StepControl {
                per_unit_step: pus,
                ..base
            };
            for &rtol in &rtols {
                let mut s = Sampler::new(&model, REVOLUTIONS, Some(MEASURED));
                let w = camsim::bench::methods::run_england(
                    &model,
                    &settings::<f64>(rtol),
                    control,
                    REVOLUTIONS,
                    &mut s,
                )?;
                println!(
                    "{name} per-unit-step {f:e} rev rtol {rtol:e}: evals {} acc err {:.3e} disp err {:.3e}",
                    w.evals,
                    Samples::rms_diff(&s.samples.acc, &r.acc),
                    Samples::rms_diff(&s.samples.disp, &r.disp)
                );
            }
        }
        return Ok(());
    }
    for method in [Method::England, Method::EnglandPiCapped, Method::Dopri5] {
        for &rtol in &rtols {
            let (s, evals) = match sampled(&model, method, rtol) {
                Ok(x) => x,
                Err(e) => {
                    println!("{} rtol {rtol:e}: failed: {e}", method.name());
                    continue;
                }
            };
            println!(
                "{} rtol {rtol:e}: evals {evals} acc err {:.3e} disp err {:.3e}",
                method.name(),
                Samples::rms_diff(&s.acc, &r.acc),
                Samples::rms_diff(&s.disp, &r.disp)
            );
            let mut line = String::from("   ");
            for (i, n) in names.iter().enumerate() {
                let a: Vec<f64> = s.states.iter().map(|x| x[i]).collect();
                let b: Vec<f64> = r.states.iter().map(|x| x[i]).collect();
                line += &format!(" {n}={:.2e}", Samples::rms_diff(&a, &b));
            }
            println!("{line}");
        }
    }
    Ok(())
}
