//! Log-log plots of the bench (`camsim bench --plot DIR`): the error of revolution 2
//! against right-hand-side evaluations, against wall time and against the bench thread's
//! CPU time (what a run cost on a machine shared with other work), one line per method and
//! precision (f32 dashed), the acceleration's error above, the displacement's below. A
//! point whose error is within 10× of the two references' own disagreement is left out
//! (it would measure the reference), and the disagreement is drawn as a grey line.

use anyhow::Result;

use super::{BenchReport, RunRow};
use crate::figure::{
    At, Axis, Colour, Figure, Legend, Mark, Marker, Panel, Scale, Series, Stroke, Style, Ticks,
};
use crate::output::AtomicDir;
use crate::plot::log_key_points;
use crate::units::Units;

/// Every integer mantissa of a decade: a log axis's light grid lines.
const ALL_MANTISSAS: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];

/// The files `--plot DIR` writes.
pub const FILES: [&str; 3] = [
    "error_vs_evals.png",
    "error_vs_time.png",
    "error_vs_cpu_time.png",
];

/// Size of each plot, pixels.
pub const SIZE: (u32, u32) = (1200, 1000);

/// The scene the plots compare.
const SCENE: &str = "full_11dof";

/// A method's colour.
fn color(method: &str) -> Colour {
    use crate::figure::palette::{BLUE, BROWN, CYAN, GREEN, OLIVE, ORANGE, PINK, PURPLE, RED};
    match method {
        "england" => BLUE,
        "england_pi_capped" => GREEN,
        "england_scaled_cap" => PINK,
        "rk4_fixed" => ORANGE,
        "rosenbrock_ros34pw2" => PURPLE,
        "rosenbrock_ros34pw2_j10" => BROWN,
        "merson_4_3" => CYAN,
        "merson_4_3_capped" => OLIVE,
        _ => RED,
    }
}

/// One line: its label, whether dashed, and its points (x, y) in the order of the tolerance.
struct Line {
    label: String,
    color: Colour,
    dashed: bool,
    points: Vec<(f64, f64)>,
}

/// The lines of one panel.
fn lines(runs: &[RunRow], x: fn(&RunRow) -> f64, y: fn(&RunRow) -> f64, floor: f64) -> Vec<Line> {
    let mut keys: Vec<(String, String, String)> = Vec::new();
    for r in runs.iter().filter(|r| r.scene == SCENE) {
        let k = (r.method.clone(), r.precision.clone(), r.math.clone());
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let mut out = Vec::new();
    for (method, precision, math) in keys {
        // In the order of the tolerance (loosest first; RK4: fewest steps first), the
        // path the method takes as it is asked for more accuracy.
        let mut mine: Vec<&RunRow> = runs
            .iter()
            .filter(|r| {
                r.scene == SCENE && r.method == method && r.precision == precision && r.math == math
            })
            .collect();
        mine.sort_by(|a, b| {
            b.rtol
                .total_cmp(&a.rtol)
                .then(a.fixed_steps_per_rev.cmp(&b.fixed_steps_per_rev))
        });
        let points: Vec<(f64, f64)> = mine
            .iter()
            .map(|r| (x(r), y(r)))
            .filter(|(a, b)| a.is_finite() && *a > 0.0 && b.is_finite() && *b > 10.0 * floor)
            .collect();
        if points.is_empty() {
            continue;
        }
        let label = if precision == "f64" {
            method.clone()
        } else {
            format!("{method} ({precision}, {math})")
        };
        out.push(Line {
            label,
            color: color(&method),
            dashed: precision != "f64",
            points,
        });
    }
    out
}

/// The smallest and largest of the values that a log axis can show (finite, positive);
/// `None` if there is none.
fn positive_span(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    (lo.is_finite() && hi > 0.0).then_some((lo, hi))
}

/// Bounds around the values at 1, 2 or 5 times a power of ten (the x axis: the runs'
/// work or time spans less than a decade, and whole decades would leave most of the
/// panel empty).
fn bounds_125(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let Some((lo, hi)) = positive_span(v) else {
        return (1.0, 10.0);
    };
    let steps = |x: f64| {
        let d = 10f64.powf(x.log10().floor());
        [d, 2.0 * d, 5.0 * d, 10.0 * d]
    };
    let below = steps(lo)
        .into_iter()
        .filter(|s| *s <= lo * (1.0 + 1e-12))
        .fold(lo, |_, s| s);
    let above = steps(hi)
        .into_iter()
        .find(|s| *s >= hi * (1.0 - 1e-12))
        .unwrap_or(hi);
    if above > below {
        (below, above)
    } else {
        (below, 2.0 * below)
    }
}

/// A run's quantity on an axis.
type Pick = fn(&RunRow) -> f64;

/// Width of the legend column right of each panel, pixels (the legend stays off the data).
const LEGEND_WIDTH: u32 = 320;

/// A log axis over `lo..hi`, labelled at the mantissas `labelled` of each decade, light
/// grid lines at every integer mantissa (an axis without a unit: its ticks do not move).
fn log_axis(mut a: Axis, (lo, hi): (f64, f64), labelled: &[f64]) -> Axis {
    a.scale = Scale::Log;
    a.ticks = Ticks::At {
        major: log_key_points(lo, hi, labelled),
        minor: log_key_points(lo, hi, &ALL_MANTISSAS),
    };
    a.range(lo, hi)
}

/// One panel: the error `y` (quantity `y_axis`, inch family) of every method against
/// `x` over the shared x range, the references' disagreement `floor` dashed.
fn panel(
    runs: &[RunRow],
    x: (Pick, &Axis, (f64, f64)),
    y_axis: Axis,
    y: fn(&RunRow) -> f64,
    floor: f64,
) -> Panel {
    let ls = lines(runs, x.0, y, floor);
    // The y axis: whole decades around the errors and the floor, in the output's units
    // (the renderer's log range once the figure is converted).
    let mut y_axis = y_axis.ticks(Ticks::Auto(1));
    y_axis.scale = Scale::Log;
    let x_axis = log_axis(x.1.clone(), x.2, &[1.0, 2.0, 5.0]);
    let mut p = Panel::new(x_axis, y_axis);
    p.legend = Legend::Right(LEGEND_WIDTH);
    if floor > 0.0 && floor.is_finite() {
        p.markers.push(Marker {
            at: At::Y(floor),
            stroke: Some(Stroke::dashed(crate::figure::Colour(120, 120, 120), 1)),
            text: None,
            label: Some("the two references' difference".into()),
        });
    }
    for l in ls {
        // f64: filled markers on a solid line; f32: open markers on a dashed one.
        let (stroke, mark) = if l.dashed {
            (Stroke::dashed(l.color, 2), Mark::Ring)
        } else {
            (Stroke::solid(l.color, 2), Mark::Dot)
        };
        p.series.push(Series {
            label: Some(l.label),
            points: l.points,
            style: Style::Line(stroke, Some(mark)),
        });
    }
    p.legend_notes = [
        "open markers, dashed lines: f32;",
        "points within 10× of the references'",
        "difference are not drawn",
    ]
    .map(String::from)
    .to_vec();
    p
}

/// One figure: the acceleration's and the displacement's error against `x`.
fn figure(
    title: String,
    x_title: &str,
    x: fn(&RunRow) -> f64,
    runs: &[RunRow],
    floor: (f64, f64),
) -> Figure {
    use crate::units::ACCELERATION;
    use camsim_scene_file::units::LENGTH;
    // One x axis for the panels of a figure (each leaves out its own unresolved points).
    let xr = bounds_125(
        [(|r: &RunRow| r.err_acc_rms) as fn(&RunRow) -> f64, |r| {
            r.err_disp_rms
        }]
        .iter()
        .zip([floor.0, floor.1])
        .flat_map(|(y, f)| lines(runs, x, *y, f))
        .flat_map(|l| l.points.into_iter().map(|p| p.0)),
    );
    let x_axis = Axis::plain(x_title, "");
    let acc = Axis::of("load acceleration RMS error", ACCELERATION);
    let disp = Axis::of("load displacement RMS error", LENGTH);
    let panels = vec![
        panel(runs, (x, &x_axis, xr), acc, |r| r.err_acc_rms, floor.0),
        panel(runs, (x, &x_axis, xr), disp, |r| r.err_disp_rms, floor.1),
    ];
    Figure::new(title, SIZE, panels)
}

/// Draws [`FILES`] of `report` into the directory output `out` (the caller commits it).
pub fn draw_all(out: &mut AtomicDir, report: &BenchReport, units: Units) -> Result<()> {
    let r = &report.reference;
    draw_runs(
        out,
        &report.runs,
        report.rpm,
        (r.agree_acc_rms, r.agree_disp_rms),
        units,
    )
}

/// Draws [`FILES`] for `runs` at `rpm`; `floor`: the references' (acceleration,
/// displacement) disagreement, in `units`.
pub fn draw_runs(
    out: &mut AtomicDir,
    runs: &[RunRow],
    rpm: f64,
    floor: (f64, f64),
    units: Units,
) -> Result<()> {
    let title = |what: &str| {
        format!("Error of revolution 2 against {what}: reference design, {rpm} rpm, full 11-DOF")
    };
    let evals: fn(&RunRow) -> f64 = |r| r.rhs_evals as f64;
    let wall: fn(&RunRow) -> f64 = |r| r.wall_ms;
    let cpu: fn(&RunRow) -> f64 = |r| r.cpu_ms.unwrap_or(f64::NAN);
    for (file, what, x_title, x) in [
        (
            FILES[0],
            "right-hand-side evaluations",
            "right-hand-side evaluations (2 revolutions)",
            evals,
        ),
        (
            FILES[1],
            "wall time",
            "wall time, ms (2 revolutions, median)",
            wall,
        ),
        (
            FILES[2],
            "CPU time",
            "CPU time of the bench's thread, ms (2 revolutions, median)",
            cpu,
        ),
    ] {
        let fig = figure(title(what), x_title, x, runs, floor);
        crate::figure::draw(out, file, &fig, units)?;
    }
    Ok(())
}

#[cfg(test)]
mod log_tick_tests {
    #[test]
    fn log_ticks_are_plain_in_the_middle_and_powers_outside() {
        assert_eq!(crate::figure::render::log_tick(200_000.0), "200 000");
        assert_eq!(crate::figure::render::log_tick(1_000.0), "1 000");
        assert_eq!(crate::figure::render::log_tick(5.0), "5");
        assert_eq!(crate::figure::render::log_tick(0.05), "0.05");
        assert_eq!(crate::figure::render::log_tick(0.001), "0.001");
        assert_eq!(crate::figure::render::log_tick(1e-5), "1e-5");
        assert_eq!(crate::figure::render::log_tick(1e7), "1e7");
    }

    #[test]
    fn x_bounds_are_the_nearest_1_2_5_around_the_data() {
        let b = |v: &[f64]| super::bounds_125(v.iter().copied());
        assert_eq!(b(&[107_635.0, 487_893.0]), (100_000.0, 500_000.0));
        assert_eq!(b(&[14.4, 75.7]), (10.0, 100.0));
        assert_eq!(b(&[0.9, 1.5]), (0.5, 2.0));
        // On a bound: that bound.
        assert_eq!(b(&[200.0, 500.0]), (200.0, 500.0));
        // One value: an interval around it.
        assert_eq!(b(&[300.0]), (200.0, 500.0));
        assert_eq!(b(&[200.0]), (200.0, 400.0));
        assert_eq!(b(&[]), (1.0, 10.0));
    }
}
