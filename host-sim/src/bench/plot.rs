//! Log-log plots of the bench (`camsim bench --plot DIR`): the error of revolution 2
//! against right-hand-side evaluations, against wall time and against the bench thread's
//! CPU time (what a run cost on a machine shared with other work), one line per method and
//! precision (f32 dashed), the acceleration's error above, the displacement's below. A
//! point whose error is within 10× of the two references' own disagreement is left out
//! (it would measure the reference), and the disagreement is drawn as a grey line.

use anyhow::{anyhow, Result};
use plotters::coord::combinators::BindKeyPoints;
use plotters::element::DashedPathElement;
use plotters::prelude::*;

use super::{BenchReport, RunRow};
use crate::output::AtomicDir;
use crate::plot::{ensure_font, log_key_points, FONT};

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

fn color(method: &str) -> RGBColor {
    match method {
        "england" => RGBColor(31, 119, 180),
        "england_pi_capped" => RGBColor(44, 160, 44),
        "england_scaled_cap" => RGBColor(227, 119, 194),
        "rk4_fixed" => RGBColor(255, 127, 14),
        "rosenbrock_ros34pw2" => RGBColor(148, 103, 189),
        "rosenbrock_ros34pw2_j10" => RGBColor(140, 86, 75),
        "merson_4_3" => RGBColor(23, 190, 207),
        "merson_4_3_capped" => RGBColor(188, 189, 34),
        _ => RGBColor(214, 39, 40),
    }
}

/// One line: its label, whether dashed, and its points (x, y) in the order of the tolerance.
struct Line {
    label: String,
    color: RGBColor,
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

/// A log axis's tick in plain digits from 0.001 to 10 000 000 ("200 000", "0.05"), in
/// powers of ten outside ("1e-9").
fn log_tick(v: f64) -> String {
    if !(1e-3..1e7).contains(&v.abs()) {
        return format!("{v:.0e}");
    }
    if v.abs() >= 1.0 {
        let digits = format!("{:.0}", v.round());
        let n = digits.len();
        let mut out = String::new();
        for (i, ch) in digits.chars().enumerate() {
            if i > 0 && (n - i) % 3 == 0 && ch.is_ascii_digit() {
                out.push(' ');
            }
            out.push(ch);
        }
        return out;
    }
    let decimals = (-v.abs().log10().floor()) as usize;
    format!("{v:.decimals$}")
}

/// The smallest and largest of the values that a log axis can show (finite, positive);
/// `None` if there is none.
fn positive_span(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = v
        .filter(|x| x.is_finite() && *x > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    (lo.is_finite() && hi > 0.0).then_some((lo, hi))
}

/// Decade bounds around the values.
fn log_bounds(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let Some((lo, hi)) = positive_span(v) else {
        return (1.0, 10.0);
    };
    (
        10f64.powf(lo.log10().floor()),
        10f64.powf(hi.log10().ceil().max(lo.log10().floor() + 1.0)),
    )
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

/// A panel: its y axis title, the quantity (inch family), the references' floor (inch
/// family) and the factor to the output's units.
type Panel<'a> = (&'a str, fn(&RunRow) -> f64, f64, f64);

/// Width of the legend column right of each panel, pixels (the legend stays off the data).
const LEGEND_WIDTH: i32 = 320;

/// One legend entry: its text, colour, whether the line is dashed, and whether its
/// marker is filled (f64) or open (f32).
struct Entry {
    text: String,
    color: RGBColor,
    dashed: bool,
    filled: Option<bool>,
}

/// Draws `entries` one below the other from the top of `area` (the legend column), each
/// a line sample with its marker and its text, and `note` under them.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    entries: &[Entry],
    note: &[&str],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let font = (FONT, 15).into_font().color(&BLACK);
    let left = |text: &str, x: i32, y: i32| {
        Text::new(
            text.to_string(),
            (x, y),
            font.clone().pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Left,
                plotters::style::text_anchor::VPos::Center,
            )),
        )
    };
    let (x0, row) = (6, 19);
    let mut y = 24;
    for e in entries {
        let style = e.color.stroke_width(2);
        let seg = vec![(x0, y), (x0 + 30, y)];
        if e.dashed {
            area.draw(&DashedPathElement::new(seg, 7, 5, style))?;
        } else {
            area.draw(&PathElement::new(seg, style))?;
        }
        if let Some(filled) = e.filled {
            let c = (x0 + 15, y);
            if filled {
                area.draw(&Circle::new(c, 4, e.color.filled()))?;
            } else {
                area.draw(&Circle::new(c, 4, WHITE.filled()))?;
                area.draw(&Circle::new(c, 4, e.color.stroke_width(1)))?;
            }
        }
        area.draw(&left(&e.text, x0 + 40, y))?;
        y += row;
    }
    for line in note {
        y += row;
        area.draw(&left(line, x0, y))?;
    }
    Ok(())
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    x_desc: &str,
    x: fn(&RunRow) -> f64,
    panels: &[Panel<'_>],
    runs: &[RunRow],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (title_area, body) = root.split_vertically(48);
    title_area.titled(title, (FONT, 24))?;
    let areas = body.split_evenly((panels.len(), 1));
    let panel_lines: Vec<Vec<Line>> = panels
        .iter()
        .map(|(_, y, floor, factor)| {
            let mut ls = lines(runs, x, *y, *floor);
            for l in &mut ls {
                l.points.iter_mut().for_each(|p| p.1 *= factor);
            }
            ls
        })
        .collect();
    // One x axis for the panels of a figure (each leaves out its own unresolved points).
    let (x0, x1) = bounds_125(
        panel_lines
            .iter()
            .flatten()
            .flat_map(|l| l.points.iter().map(|p| p.0)),
    );
    for ((area, (y_desc, _, floor, factor)), ls) in areas.iter().zip(panels).zip(&panel_lines) {
        let (w, _) = area.dim_in_pixel();
        let (plot_area, legend_area) = area.split_horizontally(w as i32 - LEGEND_WIDTH);
        let floor = &(floor * factor);
        let (y0, y1) = log_bounds(
            ls.iter()
                .flat_map(|l| l.points.iter().map(|p| p.1))
                .chain(std::iter::once(*floor)),
        );
        let mut chart = ChartBuilder::on(&plot_area)
            .margin(12)
            // Room for the last x label ("1 000 000") centred on the axis's end.
            .margin_right(40)
            .x_label_area_size(50)
            .y_label_area_size(90)
            // Our own key points (plotters' repeat a decade's end, whose label then reads
            // bold): x labelled at 1, 2 and 5 of each decade, y at each decade, and light
            // grid lines at every integer mantissa.
            .build_cartesian_2d(
                (x0..x1)
                    .log_scale()
                    .with_key_points(log_key_points(x0, x1, &[1.0, 2.0, 5.0]))
                    .with_light_points(log_key_points(x0, x1, &ALL_MANTISSAS)),
                (y0..y1)
                    .log_scale()
                    .with_key_points(log_key_points(y0, y1, &[1.0]))
                    .with_light_points(log_key_points(y0, y1, &ALL_MANTISSAS)),
            )?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(*y_desc)
            .x_label_formatter(&|v| log_tick(*v))
            .y_label_formatter(&|v| log_tick(*v))
            .label_style((FONT, 16))
            .axis_desc_style((FONT, 18))
            .bold_line_style(RGBColor(215, 215, 215))
            .light_line_style(RGBColor(240, 240, 240))
            .draw()?;
        let mut entries = Vec::new();
        if *floor > 0.0 && floor.is_finite() {
            let grey = RGBColor(120, 120, 120);
            chart.draw_series(DashedLineSeries::new(
                vec![(x0, *floor), (x1, *floor)],
                8,
                6,
                grey.stroke_width(1),
            ))?;
            entries.push(Entry {
                text: "the two references' difference".to_string(),
                color: grey,
                dashed: true,
                filled: None,
            });
        }
        for l in ls {
            let c = l.color;
            let style = c.stroke_width(2);
            if l.dashed {
                chart.draw_series(DashedLineSeries::new(l.points.clone(), 10, 6, style))?;
            } else {
                chart.draw_series(LineSeries::new(l.points.clone(), style))?;
            }
            // f64: filled markers on a solid line; f32: open markers on a dashed one.
            let filled = !l.dashed;
            chart.draw_series(l.points.iter().map(|p| {
                Circle::new(
                    *p,
                    4,
                    if filled {
                        c.filled()
                    } else {
                        c.stroke_width(2)
                    },
                )
            }))?;
            entries.push(Entry {
                text: l.label.clone(),
                color: c,
                dashed: l.dashed,
                filled: Some(filled),
            });
        }
        legend(
            &legend_area,
            &entries,
            &[
                "open markers, dashed lines: f32;",
                "points within 10× of the references'",
                "difference are not drawn",
            ],
        )?;
    }
    Ok(())
}

/// Draws [`FILES`] of `report` into the directory output `out` (the caller commits it).
pub fn draw_all(out: &mut AtomicDir, report: &BenchReport) -> Result<()> {
    let r = &report.reference;
    draw_runs(
        out,
        &report.runs,
        report.rpm,
        (r.agree_acc_rms, r.agree_disp_rms),
    )
}

/// Draws [`FILES`] for `runs` at `rpm`; `floor`: the references' (acceleration,
/// displacement) disagreement.
pub fn draw_runs(out: &mut AtomicDir, runs: &[RunRow], rpm: f64, floor: (f64, f64)) -> Result<()> {
    ensure_font()?;
    let title = |what: &str| {
        format!("Error of revolution 2 against {what}: reference design, {rpm} rpm, full 11-DOF")
    };
    let acc: fn(&RunRow) -> f64 = |r| r.err_acc_rms;
    let disp: fn(&RunRow) -> f64 = |r| r.err_disp_rms;
    let (fa, ua) = crate::units::axis(crate::units::ACCELERATION);
    let (fy, uy) = crate::units::axis(camsim_scene_file::units::LENGTH);
    let (acc_desc, disp_desc) = (
        format!("load acceleration RMS error ({ua})"),
        format!("load displacement RMS error ({uy})"),
    );
    let panels: [Panel<'_>; 2] = [
        (&acc_desc, acc, floor.0, fa),
        (&disp_desc, disp, floor.1, fy),
    ];
    let evals: fn(&RunRow) -> f64 = |r| r.rhs_evals as f64;
    let wall: fn(&RunRow) -> f64 = |r| r.wall_ms;
    let cpu: fn(&RunRow) -> f64 = |r| r.cpu_ms.unwrap_or(f64::NAN);
    for (file, what, x_desc, x) in [
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
        crate::plot::study::png(out, file, SIZE, |root| {
            draw(root, &title(what), x_desc, x, &panels, runs)
                .map_err(|e| anyhow!("cannot draw plot {file}: {e}"))
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod log_tick_tests {
    #[test]
    fn log_ticks_are_plain_in_the_middle_and_powers_outside() {
        assert_eq!(super::log_tick(200_000.0), "200 000");
        assert_eq!(super::log_tick(1_000.0), "1 000");
        assert_eq!(super::log_tick(5.0), "5");
        assert_eq!(super::log_tick(0.05), "0.05");
        assert_eq!(super::log_tick(0.001), "0.001");
        assert_eq!(super::log_tick(1e-5), "1e-5");
        assert_eq!(super::log_tick(1e7), "1e7");
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
