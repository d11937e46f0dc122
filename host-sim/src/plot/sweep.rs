//! The sweep's figure (`camsim sweep --plot DIR`): one panel a quantity against cam
//! speed, the theoretical cam as a line with its points (a cross where the follower
//! jumps), the actual cams' median and 5-95 % band, P(jump) with its Wilson interval in
//! the last panel; the theoretical jump onset's bracket shaded and the operating speed
//! dashed in every panel; the legend in a strip of its own above the panels, off the data.

use camsim_scene_file::units::{Unit, STRESS, TORQUE};

use crate::figure::palette::{BLUE, DARK_GREY, LIGHT_RED, ORANGE, RED};
use crate::figure::{
    At, Axis, Band, Entry, Figure, Mark, Marker, Panel, Series, Shape, Strip, Stroke, Style,
    Swatch, Ticks,
};
use crate::study::sweep::{ActualPoint, Band as Spread, Response, SweepReport};
use crate::units::{Acceleration, Force, Stress, Torque, ACCELERATION, FORCE};

/// Size of the sweep plot, pixels.
pub const PLOT_SIZE: (u32, u32) = (1200, 1800);

/// Colours: the theoretical cam, its jumps, the actual cams, the onset, the operating speed.
const THEORY: crate::figure::Colour = BLUE;
const JUMPS: crate::figure::Colour = RED;
const ACTUAL: crate::figure::Colour = ORANGE;
const ONSET: crate::figure::Colour = LIGHT_RED;
const OPERATING: crate::figure::Colour = DARK_GREY;
/// The actual cams' band and the onset's shading, opacity.
const BAND_ALPHA: f64 = 0.3;
const ONSET_ALPHA: f64 = 0.5;

/// One quantity of the sweep: its title, its unit, the theoretical cam's value at each
/// speed and the actual cams' spread.
struct Quantity {
    title: &'static str,
    unit: Option<Unit>,
    theory: Vec<Option<f64>>,
    spread: Vec<Option<Spread>>,
}

/// A quantity's value on the theoretical cam at one speed.
type Theory = fn(&Response) -> Option<f64>;
/// A quantity's spread over the actual cams at one speed.
type Actual = fn(&ActualPoint) -> Option<Spread>;

/// The sweep's quantities before P(jump): title, unit, the theoretical cam's value and
/// the actual cams' spread.
const QUANTITIES: [(&str, Unit, Theory, Actual); 5] = [
    (
        "smallest contact force",
        FORCE,
        |t| Some(t.min_contact_force_lb.in_inch()),
        |a| a.min_contact_force_lb,
    ),
    (
        "largest contact force",
        FORCE,
        |t| t.peak_contact_force_lb.map(Force::in_inch),
        |a| a.peak_contact_force_lb,
    ),
    (
        "RMS accel. deviation",
        ACCELERATION,
        |t| {
            t.rms_acceleration_deviation_in_per_s2
                .map(Acceleration::in_inch)
        },
        |a| a.rms_acceleration_deviation_in_per_s2,
    ),
    (
        "peak cam torque",
        TORQUE,
        |t| t.peak_cam_torque_lb_in.map(Torque::in_inch),
        |a| a.peak_cam_torque_lb_in,
    ),
    (
        "peak contact stress",
        STRESS,
        |t| t.peak_contact_stress_psi.map(Stress::in_inch),
        |a| a.peak_contact_stress_psi,
    ),
];

/// The sweep's quantities, P(jump) last.
fn quantities(r: &SweepReport) -> Vec<Quantity> {
    let th = |f: Theory| r.theoretical.iter().map(|p| f(&p.response)).collect();
    let spread = |f: Actual| -> Vec<Option<Spread>> {
        r.actual
            .as_ref()
            .map(|a| a.points.iter().map(f).collect())
            .unwrap_or_default()
    };
    let p_jump = r.actual.as_ref().map(|a| {
        a.points
            .iter()
            .map(|p| {
                Some(Spread {
                    p05: p.p_jump.lo95,
                    median: p.p_jump.p,
                    p95: p.p_jump.hi95,
                    cams: a.samples,
                })
            })
            .collect()
    });
    let mut v: Vec<Quantity> = QUANTITIES
        .iter()
        .map(|&(title, unit, theory, actual)| Quantity {
            title,
            unit: Some(unit),
            theory: th(theory),
            spread: spread(actual),
        })
        .collect();
    v.push(Quantity {
        title: "P(jump)",
        unit: None,
        theory: th(|t| Some(if t.jump { 1.0 } else { 0.0 })),
        spread: p_jump.unwrap_or_default(),
    });
    v
}

/// The sweep's figure.
pub fn figure(r: &SweepReport) -> Figure {
    let span = r.grid.to_rpm - r.grid.from_rpm;
    let x = (r.grid.from_rpm - 0.02 * span, r.grid.to_rpm + 0.02 * span);
    let qs = quantities(r);
    let last = qs.len().saturating_sub(1);
    let panels = qs
        .into_iter()
        .enumerate()
        .map(|(k, q)| panel(r, q, x, k == last))
        .collect();
    let mut fig = Figure::new(
        "Operating map: the response against cam speed (revolution 2 of each run)",
        PLOT_SIZE,
        panels,
    );
    fig.strip = Strip {
        entries: legend(r, x),
        columns: 2,
        note: None,
    };
    fig
}

/// The legend: what each panel may show.
fn legend(r: &SweepReport, x: (f64, f64)) -> Vec<Entry> {
    let model_name = |m: &str| m.split(',').next().unwrap_or(m).to_string();
    let e = |swatch, text: String| Entry { swatch, text };
    let mut v = vec![e(
        Swatch::Line(Stroke::solid(THEORY, 2), Some(Mark::Dot)),
        format!("theoretical cam ({})", model_name(&r.model)),
    )];
    if r.theoretical.iter().any(|p| p.response.jump) {
        v.push(e(
            Swatch::Mark(Mark::Cross, JUMPS),
            "theoretical cam: the follower jumps (P(jump) 1)".into(),
        ));
    }
    if let Some(a) = &r.actual {
        let median = format!(
            "{} actual cams: median ({})",
            a.samples,
            model_name(&a.model)
        );
        v.push(e(Swatch::Line(Stroke::solid(ACTUAL, 3), None), median));
        let band = "actual cams: 5-95 % band; P(jump): 95 % Wilson interval".into();
        v.push(e(Swatch::Fill(ACTUAL, BAND_ALPHA), band));
    }
    if let Some(o) = &r.theoretical_onset {
        let text = match o.holds_at_rpm {
            Some(h) => format!(
                "theoretical jump onset lies here ({h:.0}-{:.0} rpm)",
                o.jumps_at_rpm
            ),
            None => format!("jumps from the first speed, {:.0} rpm", o.jumps_at_rpm),
        };
        v.push(e(Swatch::Fill(ONSET, ONSET_ALPHA), text));
    }
    if (x.0..x.1).contains(&r.operating_rpm) {
        v.push(e(
            Swatch::Line(Stroke::dashed(OPERATING, 2), None),
            format!("operating speed {:.0} rpm", r.operating_rpm),
        ));
    }
    if r.theoretical
        .iter()
        .any(|p| p.response.jump && !p.response.left_model_range)
    {
        let text = "off the scale (impacts after a jump): drawn on the top edge".into();
        v.push(e(Swatch::Mark(Mark::Triangle, JUMPS), text));
    }
    if r.theoretical.iter().any(|p| p.response.left_model_range) {
        v.push(e(
            Swatch::Blank,
            "no point: the run left the model's range after the jump".into(),
        ));
    }
    v
}

/// The y range of a quantity: where the theoretical cam holds (after a jump the impacts'
/// values are larger by orders of magnitude and would flatten the range a designer
/// works in), from zero or below, with a margin; P(jump): 0 to 1.
fn y_range(r: &SweepReport, q: &Quantity, pjump: bool) -> (f64, f64) {
    let holds: Vec<bool> = r.theoretical.iter().map(|p| !p.response.jump).collect();
    let any_holds = holds.iter().any(|h| *h);
    let keep = |i: usize| !any_holds || holds.get(i).copied().unwrap_or(false);
    let values = q
        .theory
        .iter()
        .enumerate()
        .filter_map(|(i, v)| v.filter(|_| keep(i)).map(|v| (v, v)));
    let spread = q
        .spread
        .iter()
        .enumerate()
        .filter_map(|(i, b)| b.filter(|_| keep(i)).map(|b| (b.p05, b.p95)));
    let (lo, mut hi) = values
        .chain(spread)
        .fold((0.0f64, f64::NEG_INFINITY), |(l, h), (a, b)| {
            (l.min(a), h.max(b))
        });
    if pjump || !hi.is_finite() || hi <= lo {
        hi = if pjump { 1.0 } else { lo + 1.0 };
    }
    let pad = 0.06 * (hi - lo);
    (lo - if lo < 0.0 { pad } else { 0.03 * (hi - lo) }, hi + pad)
}

/// One quantity's panel over the speeds `x`; values above its range on the top edge.
fn panel(r: &SweepReport, q: Quantity, x: (f64, f64), pjump: bool) -> Panel {
    let (y0, y1) = y_range(r, &q, pjump);
    let x_axis = Axis::plain(
        if pjump { "cam speed" } else { "" },
        if pjump { "rpm" } else { "" },
    );
    let y_axis = match q.unit {
        Some(u) => Axis::of(q.title, u),
        None => Axis::plain(q.title, ""),
    };
    let mut p = Panel::new(
        x_axis.range(x.0, x.1).ticks(Ticks::Auto(12)),
        y_axis.range(y0, y1).ticks(Ticks::Auto(6)),
    );
    if let Some(o) = &r.theoretical_onset {
        let shape = Shape::Span(o.holds_at_rpm.unwrap_or(x.0), o.jumps_at_rpm);
        p.bands.push(Band {
            label: None,
            colour: ONSET,
            alpha: ONSET_ALPHA,
            shape,
        });
    }
    if (x.0..x.1).contains(&r.operating_rpm) {
        let stroke = Some(Stroke::dashed(OPERATING, 2));
        p.markers.push(Marker {
            at: At::X(r.operating_rpm),
            stroke,
            text: None,
            label: None,
        });
    }
    let xs: Vec<f64> = r.theoretical.iter().map(|t| t.rpm).collect();
    spread(&mut p, &xs, &q.spread, y1, pjump);
    theory(&mut p, r, &xs, &q.theory, y1, pjump);
    p
}

/// The actual cams' band and median (P(jump): its interval as whiskers too), clamped to `top`.
fn spread(p: &mut Panel, xs: &[f64], s: &[Option<Spread>], top: f64, pjump: bool) {
    if s.is_empty() {
        return;
    }
    let pts: Vec<(f64, f64, f64)> = xs
        .iter()
        .zip(s)
        .map(|(&x, b)| {
            b.map_or((x, f64::NAN, f64::NAN), |b| {
                (x, b.p05.min(top), b.p95.min(top))
            })
        })
        .collect();
    p.bands.push(Band {
        label: None,
        colour: ACTUAL,
        alpha: BAND_ALPHA,
        shape: Shape::Between(pts.clone()),
    });
    if pjump {
        p.bands.push(Band {
            label: None,
            colour: ACTUAL,
            alpha: 2.0,
            shape: Shape::Whiskers(pts),
        });
    }
    let median = xs
        .iter()
        .zip(s)
        .map(|(&x, b)| (x, b.map_or(f64::NAN, |b| b.median.min(top))))
        .collect();
    p.series
        .push(Series::line(None, median, Stroke::solid(ACTUAL, 3)));
}

/// The theoretical cam: its line with dots, a cross where it jumps, a triangle on the
/// top edge where its value is above `top`.
fn theory(p: &mut Panel, r: &SweepReport, xs: &[f64], v: &[Option<f64>], top: f64, pjump: bool) {
    let at = |k: usize| v.get(k).copied().flatten().filter(|y| y.is_finite());
    let line = xs
        .iter()
        .enumerate()
        .map(|(k, &x)| (x, at(k).map_or(f64::NAN, |y| y.min(top))))
        .collect();
    p.series.push(Series {
        label: None,
        points: line,
        style: Style::Line(Stroke::solid(THEORY, 2), Some(Mark::Dot)),
    });
    let crosses = r
        .theoretical
        .iter()
        .enumerate()
        .filter(|(_, t)| t.response.jump)
        .filter_map(|(k, t)| {
            at(k)
                .filter(|y| *y < top || pjump)
                .map(|y| (t.rpm, y.min(top)))
        })
        .collect();
    p.series.push(Series {
        label: None,
        points: crosses,
        style: Style::Points(Mark::Cross, JUMPS),
    });
    let above = xs
        .iter()
        .enumerate()
        .filter(|(k, _)| at(*k).is_some_and(|y| y > top))
        .map(|(_, &x)| (x, top))
        .collect();
    p.series.push(Series {
        label: None,
        points: above,
        style: Style::Points(Mark::Triangle, JUMPS),
    });
}
