//! The figure layer: its data (ranges, refusals, units) and a few of the renderer's pixels.

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

/// A marker line widens only its own axis, a bar both: a vertical line at x = 10 and a
/// horizontal one at y = -4 beside a bar over x -2..1, y 0..3 give x -2..10 and y -4..3,
/// each with its 5 % margin.
#[test]
fn markers_widen_their_own_axis_and_bars_both() {
    let mut p = Panel::new(Axis::plain("x", ""), Axis::plain("y", ""));
    p.bars.push(Bar {
        x: (-2.0, 1.0),
        y: (0.0, 3.0),
        colour: palette::BLUE,
        edge: None,
    });
    for at in [At::X(10.0), At::Y(-4.0)] {
        p.markers.push(Marker {
            at,
            stroke: None,
            text: None,
            label: None,
        });
    }
    let ((x0, x1), (y0, y1)) = ranges(&p, 0.0).unwrap();
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    assert!(close(x0, -2.0 - 0.6) && close(x1, 10.0 + 0.6), "{x0} {x1}");
    assert!(close(y0, -4.0 - 0.35) && close(y1, 3.0 + 0.35), "{y0} {y1}");
}

/// A signed axis (a change) writes a rise with its sign, a fall with its minus and zero
/// bare; an unsigned one writes a rise bare.
#[test]
fn a_signed_axis_writes_the_sign_of_a_rise() {
    let mut a = Axis::plain("change", "%");
    let span = (-40.0, 40.0);
    assert_eq!(super::render::tick_label(&a, 20.0, span), "20");
    a.signed = true;
    let t = |v| super::render::tick_label(&a, v, span);
    assert_eq!(
        (t(20.0), t(-20.0), t(0.0)),
        ("+20".into(), "-20".into(), "0".into())
    );
}

/// One panel a row, two rows: the rows' titles push each row's plotting area down and
/// the figure keeps its size.
#[test]
fn row_titles_take_room_above_their_rows() {
    let panels = vec![
        panel(vec![(0.0, 1.0), (1.0, 2.0)]),
        panel(vec![(0.0, 1.0), (1.0, 2.0)]),
    ];
    let plain = Figure::new("t", (400, 400), panels);
    let mut titled = plain.clone();
    titled.row_titles = vec!["first".into(), "second".into()];
    let (buf, without) = super::render::render(&plain).unwrap();
    let (buf2, with) = super::render::render(&titled).unwrap();
    assert_eq!(buf.len(), buf2.len());
    for (a, b) in without.iter().zip(&with) {
        assert!(b.1.start > a.1.start, "{:?} {:?}", a.1, b.1);
    }
}

/// A heat map's cell is outlined: a white bar with a black edge over the middle half of
/// the plotting area leaves black pixels on its left edge, a bar without one leaves none.
#[test]
fn a_cell_with_an_edge_is_outlined() {
    let black_at_left_edge = |edge: Option<Colour>| {
        let mut p = Panel::new(
            Axis::plain("x", "").range(0.0, 4.0),
            Axis::plain("y", "").range(0.0, 4.0),
        );
        p.bars.push(Bar {
            x: (1.0, 3.0),
            y: (1.0, 3.0),
            colour: palette::ORANGE,
            edge,
        });
        let fig = Figure::new("t", (400, 400), vec![p]);
        let (buf, areas) = super::render::render(&fig).unwrap();
        let (px, py) = areas[0].clone();
        let x = px.start + (px.end - px.start) / 4;
        let y = (py.start + py.end) / 2;
        (x - 1..=x + 1).any(|x| {
            let i = 3 * (y as usize * 400 + x as usize);
            buf[i..i + 3] == [0, 0, 0]
        })
    };
    assert!(black_at_left_edge(Some(palette::BLACK)));
    assert!(!black_at_left_edge(None));
}
