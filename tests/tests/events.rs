//! Contact events (`England::integrate_events`): located on England's dense output and
//! restarted there, checked against closed forms.

use std::ops::ControlFlow;

use camsim::bench::settings;
use camsim_core::{
    England, EnglandConfig, Event, EventConfig, EventFunction, OdeSystem, Real, Report,
    StepControl, Tolerance,
};

/// A mass dropped onto a one-sided linear spring under gravity (x up, the spring's
/// surface at x = 0): `x'' = -g + (k/m) max(0, -x)`. The event function is the spring
/// force per unit mass before the clamp, `-ω² x` (positive in contact).
///
/// Closed form, from rest at height `h0`: impact at `t1 = sqrt(2 h0 / g)` with speed
/// `v0 = sqrt(2 g h0)`; in contact `x = -g/ω² + R cos(ω τ + φ)` with
/// `φ = atan2(v0/ω, g/ω²)`, which returns to x = 0 after `τ_c = (2π - 2φ)/ω`, leaving at
/// speed `v0` (energy); the flight back takes `2 v0 / g`. So the events are, for
/// n = 0, 1, ...: contact at `t1 + n (τ_c + 2 v0/g)`, separation `τ_c` later.
struct Bouncer<T> {
    g: T,
    w2: T,
}

impl<T: Real> OdeSystem<T, 2> for Bouncer<T> {
    fn rhs(&self, _t: T, y: &[T; 2], dydt: &mut [T; 2]) {
        dydt[0] = y[1];
        dydt[1] = -self.g + (-self.w2 * y[0]).max(T::ZERO);
    }
}

impl<T: Real> EventFunction<T, 2> for Bouncer<T> {
    fn event(&self, _t: T, y: &[T; 2]) -> T {
        -self.w2 * y[0]
    }
}

const G: f64 = 10.0;
const W: f64 = 100.0;
const H0: f64 = 0.05;

/// The first `n` event times of the closed form and whether each is a contact.
fn closed_form_events(n: usize) -> Vec<(f64, bool)> {
    let t1 = (2.0 * H0 / G).sqrt();
    let v0 = (2.0 * G * H0).sqrt();
    let phi = (v0 / W).atan2(G / (W * W));
    let tau_c = (2.0 * std::f64::consts::PI - 2.0 * phi) / W;
    let cycle = tau_c + 2.0 * v0 / G;
    (0..n)
        .map(|i| {
            let k = (i / 2) as f64;
            if i % 2 == 0 {
                (t1 + k * cycle, true)
            } else {
                (t1 + k * cycle + tau_c, false)
            }
        })
        .collect()
}

struct Run<T> {
    events: Vec<Event<T>>,
    /// Whether some accepted step ended exactly at each event time.
    step_ends_at_event: Vec<bool>,
    y_end: [T; 2],
}

fn run<T: Real>(rtol: f64, tol_t: f64, t_end: f64, control: StepControl<T>) -> Run<T> {
    let sys = Bouncer {
        g: T::from_f64(G),
        w2: T::from_f64(W * W),
    };
    let mut s = England::with_control(
        EnglandConfig {
            tol: Tolerance::scalar(T::from_f64(rtol), T::from_f64(rtol * 1e-2)),
            h_init: T::from_f64(1e-3),
            h_min: T::from_f64(1e-14),
            h_max: T::from_f64(0.02),
            max_steps: 1_000_000,
        },
        control,
    )
    .unwrap();
    let mut y = [T::from_f64(H0), T::ZERO];
    let mut events = Vec::new();
    let mut step_ends_at_event = Vec::new();
    let mut last_end = T::NAN;
    let (_, ev) = s
        .integrate_events(
            &sys,
            &sys,
            &EventConfig::new(T::from_f64(tol_t)),
            T::ZERO,
            &mut y,
            T::from_f64(t_end),
            |r| {
                match r {
                    Report::Step(d) => last_end = d.t_end(),
                    Report::Event(e, _) => {
                        events.push(e);
                        step_ends_at_event.push(last_end == e.t);
                    }
                }
                ControlFlow::Continue(())
            },
        )
        .unwrap();
    assert_eq!(ev.events as usize, events.len());
    Run {
        events,
        step_ends_at_event,
        y_end: y,
    }
}

/// The exact state at `t` (flight or contact phase) from the closed form.
fn exact_state(t: f64) -> [f64; 2] {
    let t1 = (2.0 * H0 / G).sqrt();
    let v0 = (2.0 * G * H0).sqrt();
    let phi = (v0 / W).atan2(G / (W * W));
    let tau_c = (2.0 * std::f64::consts::PI - 2.0 * phi) / W;
    let cycle = tau_c + 2.0 * v0 / G;
    if t < t1 {
        return [H0 - 0.5 * G * t * t, -G * t];
    }
    let u = (t - t1) % cycle;
    if u < tau_c {
        let r = ((G / (W * W)).powi(2) + (v0 / W).powi(2)).sqrt();
        [
            -G / (W * W) + r * (W * u + phi).cos(),
            -r * W * (W * u + phi).sin(),
        ]
    } else {
        let f = u - tau_c;
        [v0 * f - 0.5 * G * f * f, v0 - G * f]
    }
}

#[test]
fn bouncing_mass_events_match_the_closed_form_in_f64() {
    let exact = closed_form_events(6);
    let t_end = 0.75; // past the 6th event (0.7336...), before the 7th (0.9336...)
    for control in [StepControl::classic(), StepControl::pi_capped()] {
        let r = run::<f64>(1e-10, 1e-13, t_end, control);
        assert_eq!(r.events.len(), exact.len(), "{:?}", r.events);
        for ((e, (t, rising)), at_step) in r.events.iter().zip(&exact).zip(&r.step_ends_at_event) {
            assert_eq!(e.rising, *rising);
            // The located time: within the bracket of the root of the computed solution,
            // whose own error at rtol 1e-10 is far below 1e-9 s here.
            assert!((e.t - t).abs() < 1e-9, "event at {} against {t}", e.t);
            assert!(e.bracket <= 1e-13, "{e:?}");
            if e.restarted {
                assert!(*at_step, "a restarted event ends a step: {e:?}");
            }
        }
        assert!(
            r.events.iter().filter(|e| e.restarted).count() >= 5,
            "{:?}",
            r.events
        );
        let y = exact_state(t_end);
        assert!((r.y_end[0] - y[0]).abs() < 1e-9, "{:?} {y:?}", r.y_end);
        assert!((r.y_end[1] - y[1]).abs() < 1e-7, "{:?} {y:?}", r.y_end);
    }
}

#[test]
fn bouncing_mass_events_match_the_closed_form_in_f32() {
    let exact = closed_form_events(4);
    let r = run::<f32>(1e-5, 1e-6, 0.5, StepControl::classic());
    assert_eq!(r.events.len(), exact.len(), "{:?}", r.events);
    for (e, (t, rising)) in r.events.iter().zip(&exact) {
        assert_eq!(e.rising, *rising);
        assert!(
            (f64::from(e.t) - t).abs() < 2e-5,
            "event at {} against {t}",
            e.t
        );
    }
}

/// The work is accounted: a discarded step's 9 evaluations are auxiliary.
#[test]
fn discarded_steps_are_counted() {
    let sys = Bouncer { g: G, w2: W * W };
    let mut s = England::new(EnglandConfig {
        tol: Tolerance::scalar(1e-6, 1e-8),
        h_init: 1e-3,
        h_min: 1e-14,
        h_max: 0.02,
        max_steps: 1_000_000,
    })
    .unwrap();
    let mut y = [H0, 0.0];
    let (stats, ev) = s
        .integrate_events(
            &sys,
            &sys,
            &EventConfig::new(1e-12),
            0.0,
            &mut y,
            0.75,
            |_| ControlFlow::Continue(()),
        )
        .unwrap();
    assert_eq!(ev.events, 6);
    assert_eq!(
        stats.rhs_evals,
        9 * stats.accepted + 7 * stats.rejected + 9 * ev.discarded_steps + 1
    );
    assert_eq!(s.auxiliary_evals(), 9 * ev.discarded_steps + 1);
}

// ---------------------------------------------------------------------------------------
// The cam model with a return spring so weak that the follower leaves the cam every
// revolution (camsim_tests::weak_spring).

use camsim_core::{
    simulate, simulate_events, ContactEventFn, ContactEventSettings, Design, RegulatedFullModel,
};
use camsim_tests::weak_spring::{model_run, weak_spring_model};

/// The contact events of the jumping model: the follower leaves the cam and comes back
/// in each of the 3 revolutions; located events agree with a tight reference's to far
/// better than the step nodes place them, and each separation is where the model's
/// own contact force reaches zero.
#[test]
fn weak_spring_events_are_located_and_agree_with_a_tight_reference() {
    let model = weak_spring_model(500.0);
    let reference = model_run(&model, 1e-11, true);
    let with = model_run(&model, 1e-6, true);
    let without = model_run(&model, 1e-6, false);
    // Separation then recontact, once in each revolution.
    let kinds: Vec<bool> = reference.events.iter().map(|e| e.1).collect();
    assert!(kinds.len() >= 6 && kinds.starts_with(&[true, false, true, false, true, false]));
    // First separation and recontact: located at 1e-6 within 1e-4° of the reference
    // (its solution error, not the bracket of 3.6e-7°, bounds it).
    for k in 0..2 {
        let d = (with.events[k].0 - reference.events[k].0).abs();
        assert!(
            d < 1e-4,
            "event {k}: {:?} against {:?}",
            with.events[k],
            reference.events[k]
        );
        // Without events the first node past it is up to a step (about 0.06°) late.
        let node = without.events[k].0 - reference.events[k].0;
        assert!(node >= 0.0, "{node}");
    }
    // At a restarted separation the model's own contact force is zero and g within
    // rounding of zero.
    let mut seen = Vec::new();
    let (_, ev) = simulate_events(
        &model,
        &settings(1e-6),
        &ContactEventSettings::default(),
        3,
        &mut |_: &camsim_core::Sample<f64>| ControlFlow::Continue(()),
        |e| seen.push(*e),
    )
    .unwrap();
    assert_eq!(ev.events as usize, seen.len());
    let restarted = seen.iter().filter(|e| e.event.restarted).count();
    assert!(2 * restarted > seen.len(), "{restarted} of {}", seen.len());
    for e in &seen {
        // A restarted event's state is the integrator's, on the new side.
        if e.event.restarted {
            assert_eq!(e.sample.point.in_contact, !e.separation, "{e:?}");
        }
        let g = ContactEventFn(&model).of_point(&e.sample.point);
        // One preload's worth (15 lb) times the bracket's relative size: far below 1e-3 lb.
        assert!(g.abs() < 1e-3, "{g} at {e:?}");
    }
}

/// `simulate` is untouched by the events' code: the same samples as `simulate_events`
/// where the latter finds no event (the reference spring at 500 rpm never jumps).
#[test]
fn no_event_no_change() {
    let mut d = Design::reference();
    d.set_speed_rpm(500.0).unwrap();
    let model = RegulatedFullModel::new(d).unwrap();
    let s = settings(1e-6);
    let mut a = Vec::new();
    let mut b = Vec::new();
    let sa = simulate(&model, &s, 1, &mut |x: &camsim_core::Sample<f64>| {
        a.push(x.point.load_acceleration());
        ControlFlow::Continue(())
    })
    .unwrap();
    let (sb, ev) = simulate_events(
        &model,
        &s,
        &ContactEventSettings::default(),
        1,
        &mut |x: &camsim_core::Sample<f64>| {
            b.push(x.point.load_acceleration());
            ControlFlow::Continue(())
        },
        |_| {},
    )
    .unwrap();
    assert_eq!(ev.events, 0);
    assert_eq!((sa.accepted, sa.rejected), (sb.accepted, sb.rejected));
    assert_eq!(a, b);
}
