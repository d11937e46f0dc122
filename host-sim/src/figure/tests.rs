//! The figure layer's data: ranges, refusals and units, without pixels.

use super::render::ranges;
use super::*;
use crate::units::FORCE;
use camsim_scene_file::units::{LENGTH, MM_PER_IN, N_PER_LBF, STRESS};

fn panel(points: Vec<(f64, f64)>) -> Panel {
    let mut p = Panel::new(
        Axis::plain("cam speed", "rpm"),
        Axis::of("contact force", FORCE),
    );
    p.series
        .push(Series::line(None, points, Stroke::solid(palette::BLUE, 2)));
    p
}

/// The data's range holds every series point and every band's ends, with the 5 % margin
/// each side: series y 1..3 and a band 0..5 over x 2..4 give y -0.25..5.25.
#[test]
fn the_ranges_hold_the_series_and_the_bands() {
    let mut p = panel(vec![(1.0, 1.0), (3.0, 3.0)]);
    p.bands.push(Band {
        label: None,
        colour: palette::ORANGE,
        alpha: 0.3,
        shape: Shape::Between(vec![(2.0, 0.0, 5.0), (4.0, 0.5, 4.0)]),
    });
    let ((x0, x1), (y0, y1)) = ranges(&p, 0.0).unwrap();
    assert!(
        (x0 - 0.85).abs() < 1e-12 && (x1 - 4.15).abs() < 1e-12,
        "{x0} {x1}"
    );
    assert!(
        (y0 + 0.25).abs() < 1e-12 && (y1 - 5.25).abs() < 1e-12,
        "{y0} {y1}"
    );
    // A span widens x alone.
    p.bands.push(Band {
        label: None,
        colour: palette::LIGHT_RED,
        alpha: 0.5,
        shape: Shape::Span(-6.0, 0.0),
    });
    let ((x0, _), (y0, _)) = ranges(&p, 0.0).unwrap();
    assert!((x0 - (-6.0 - 0.05 * 10.0)).abs() < 1e-12, "{x0}");
    assert!((y0 + 0.25).abs() < 1e-12);
}

/// A legend box of a fraction f of the height leaves the data (1 - f) of it: the top
/// margin is 1.05 f / (1 - f) of the data's span.
#[test]
fn a_legend_box_raises_the_top_and_leaves_the_data_below_it() {
    let p = panel(vec![(0.0, 0.0), (1.0, 10.0)]);
    let (_, (y0, y1)) = ranges(&p, 0.2).unwrap();
    assert!((y0 + 0.5).abs() < 1e-12);
    assert!((y1 - (10.0 + 10.0 * 1.05 * 0.2 / 0.8)).abs() < 1e-9, "{y1}");
    // Flat data still get a window: ±1 % of the value, then the margin.
    let (_, (y0, y1)) = ranges(&panel(vec![(0.0, 83.8), (1.0, 83.8)]), 0.0).unwrap();
    assert!(y0 < 83.8 && y1 > 83.8 && y1 - y0 < 3.0, "{y0} {y1}");
}

/// A panel with no finite value is refused, naming it; the renderer refuses the
/// figure before drawing.
#[test]
fn a_panel_without_finite_data_is_refused() {
    let p = panel(vec![(1.0, f64::NAN), (2.0, f64::INFINITY)]);
    let e = ranges(&p, 0.0).unwrap_err();
    assert_eq!(
        e,
        FigureError::NoFiniteData {
            panel: "contact force".into()
        }
    );
    let fig = Figure::new("t", (300, 200), vec![p]);
    let msg = format!("{:#}", render::render(&fig).unwrap_err());
    assert!(msg.contains("'contact force' has no finite value"), "{msg}");
    // A log axis draws positive values only.
    let mut q = panel(vec![(1.0, 0.0), (2.0, -3.0)]);
    q.y.scale = Scale::Log;
    assert!(matches!(
        ranges(&q, 0.0),
        Err(FigureError::NoFiniteData { .. })
    ));
    q.series[0].points.push((3.0, 20.0));
    assert_eq!(ranges(&q, 0.0).unwrap().1, (10.0, 100.0));
}

/// A given range must be finite and increasing.
#[test]
fn a_reversed_range_is_refused() {
    let mut p = panel(vec![(1.0, 1.0)]);
    p.x = p.x.clone().range(5.0, 5.0);
    assert!(matches!(ranges(&p, 0.0), Err(FigureError::BadRange { .. })));
}

/// In SI every coordinate on a force axis is times N per lbf and the title says N; a
/// length axis says mm; in inch nothing moves and the titles say lb and in.
#[test]
fn axes_carry_the_unit_of_the_chosen_family() {
    let mut p = panel(vec![(800.0, 10.0)]);
    p.markers.push(Marker {
        at: At::Y(2.0),
        stroke: None,
        text: None,
        label: None,
    });
    let mut q = Panel::new(Axis::plain("cam angle", "deg"), Axis::of("lift", LENGTH));
    q.series.push(Series::line(
        None,
        vec![(90.0, 0.5)],
        Stroke::solid(palette::BLUE, 1),
    ));
    let fig = Figure::new("t", (300, 200), vec![p, q]);
    let si = fig.clone().in_units(Units::Si);
    assert_eq!(si.panels[0].y.label(), "contact force (N)");
    assert_eq!(si.panels[0].x.label(), "cam speed (rpm)");
    assert_eq!(si.panels[0].series[0].points[0], (800.0, 10.0 * N_PER_LBF));
    assert_eq!(si.panels[0].markers[0].at, At::Y(2.0 * N_PER_LBF));
    assert_eq!(si.panels[1].y.label(), "lift (mm)");
    assert_eq!(si.panels[1].series[0].points[0], (90.0, 0.5 * MM_PER_IN));
    let inch = fig.in_units(Units::Inch);
    assert_eq!(inch.panels[0].y.label(), "contact force (lb)");
    assert_eq!(inch.panels[1].y.label(), "lift (in)");
    assert_eq!(inch.panels[1].series[0].points[0], (90.0, 0.5));
}

/// An axis of large values in a power of 1000: 120 000 psi reads 120 (1000 psi).
#[test]
fn large_values_read_in_thousands() {
    let mut p = Panel::new(Axis::of("stress", STRESS), Axis::plain("cams", ""));
    p.x.thousands = true;
    p.bars.push(Bar {
        x: (110_000.0, 120_000.0),
        y: (0.0, 3.0),
        colour: palette::BLUE,
        edge: None,
    });
    let fig = Figure::new("t", (300, 200), vec![p]).in_units(Units::Inch);
    assert_eq!(fig.panels[0].x.label(), "stress (1000 psi)");
    assert_eq!(fig.panels[0].bars[0].x, (110.0, 120.0));
}
