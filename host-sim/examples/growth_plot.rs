//! Draws `docs/growth.png` from `docs/growth.csv`, the measurements `scripts/growth.sh`
//! writes (issue 21 point 6): run time against revolutions and against cam speed, and a Monte
//! Carlo study's wall time against its samples on one and two threads.
//!
//!     cargo run --release -p camsim --example growth_plot -- docs/growth.csv docs/growth.png
//!
//! The CSV has a header `table,x,threads,value` and one row a measurement: `revolutions`
//! (x revolutions, value ms), `rpm` (x rpm, value ms), `samples` (x samples, value s) or
//! `refused` (x a cam speed, rpm, whose run was refused). On the log-log panels each
//! series is its measured points on a dashed line of slope 1 (time proportional to x)
//! through the first one: points on the line grow in proportion, points above it faster.

use std::path::Path;

use anyhow::{bail, Context, Result};
use camsim::plot::log_key_points;
use plotters::coord::combinators::BindKeyPoints;
use plotters::prelude::*;

/// One measurement.
struct Row {
    table: String,
    x: f64,
    threads: u32,
    value: f64,
}

fn read(path: &Path) -> Result<Vec<Row>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some("table,x,threads,value") {
        bail!(
            "{}: the header must be table,x,threads,value",
            path.display()
        );
    }
    let mut rows = Vec::new();
    for (i, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let [table, x, threads, value] = f[..] else {
            bail!(
                "{} line {}: expected 4 fields: {line}",
                path.display(),
                i + 2
            );
        };
        let num = |s: &str| -> Result<f64> {
            let v: f64 = s.trim().parse().with_context(|| {
                format!("{} line {}: {s:?} is not a number", path.display(), i + 2)
            })?;
            anyhow::ensure!(
                v.is_finite() && v > 0.0,
                "{} line {}: {v} must be positive",
                path.display(),
                i + 2
            );
            Ok(v)
        };
        rows.push(Row {
            table: table.trim().to_string(),
            x: num(x)?,
            threads: threads.trim().parse().with_context(|| {
                format!(
                    "{} line {}: threads {threads:?} is not a whole number",
                    path.display(),
                    i + 2
                )
            })?,
            value: num(value)?,
        });
    }
    Ok(rows)
}

fn series(rows: &[Row], table: &str, threads: Option<u32>) -> Vec<(f64, f64)> {
    let mut v: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.table == table && threads.is_none_or(|t| r.threads == t))
        .map(|r| (r.x, r.value))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0));
    v
}

/// A plain tick: no exponent, no trailing zeros.
fn tick(v: f64) -> String {
    if v >= 1.0 {
        format!("{}", v.round() as i64)
    } else {
        format!("{v}")
    }
}

fn bounds(points: &[(f64, f64)]) -> ((f64, f64), (f64, f64)) {
    let fold = |f: fn(&(f64, f64)) -> f64| {
        points
            .iter()
            .map(f)
            .fold((f64::MAX, f64::MIN), |(lo, hi), v| (lo.min(v), hi.max(v)))
    };
    (fold(|p| p.0), fold(|p| p.1))
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;
/// One series of a panel: its label, colour and points.
type Line<'a> = (&'a str, RGBColor, Vec<(f64, f64)>);

/// A log-log panel of `lines` (label, colour, points), each with its slope-1 guide.
fn loglog(
    area: &Area<'_>,
    title: &str,
    x_label: &str,
    y_label: &str,
    lines: &[Line<'_>],
) -> Result<()> {
    let all: Vec<(f64, f64)> = lines.iter().flat_map(|l| l.2.iter().copied()).collect();
    let ((x0, x1), (y0, y1)) = bounds(&all);
    let (xr, yr) = ((x0 / 1.5, x1 * 1.5), (y0 / 2.0, y1 * 2.0));
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 22))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (xr.0..xr.1)
                .log_scale()
                .with_key_points(log_key_points(xr.0, xr.1, &[1.0, 2.0, 5.0])),
            (yr.0..yr.1)
                .log_scale()
                .with_key_points(log_key_points(yr.0, yr.1, &[1.0, 2.0, 5.0])),
        )?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .light_line_style(TRANSPARENT)
        .bold_line_style(BLACK.mix(0.12))
        .label_style(("sans-serif", 15))
        .axis_desc_style(("sans-serif", 17))
        .draw()?;
    // Each series as its measured points on its own slope-1 line through the first one
    // (dashed, so a point off the line shows; a solid line through the points hid it).
    for (label, color, pts) in lines {
        if let Some(&(xa, ya)) = pts.first() {
            let xb = pts.last().map_or(xa, |p| p.0);
            chart.draw_series(DashedLineSeries::new(
                [(xa, ya), (xb, ya * xb / xa)],
                8,
                5,
                color.mix(0.8).stroke_width(2),
            ))?;
        }
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 5, color.filled())))?
            .label(*label)
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, color.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.3))
        .draw()?;
    Ok(())
}

fn main() {
    if let Err(e) = run() {
        eprintln!("growth_plot: {e:#}");
        std::process::exit(1);
    }
}

fn run() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [csv, png] = &args[..] else {
        bail!("usage: growth_plot GROWTH.csv OUT.png");
    };
    let rows = read(Path::new(csv))?;
    camsim::figure::render::ensure_font()?;
    let blue = RGBColor(31, 119, 180);
    let orange = RGBColor(255, 127, 14);
    let revs = series(&rows, "revolutions", None);
    let rpm = series(&rows, "rpm", None);
    let one = series(&rows, "samples", Some(1));
    let refused: Vec<String> = series(&rows, "refused", None)
        .iter()
        .map(|p| tick(p.0))
        .collect();
    let refused_note = if refused.is_empty() {
        "cam speed (rpm)".to_string()
    } else {
        format!(
            "cam speed (rpm); no result at {} rpm (refused: docs/BENCHMARKS.md says why)",
            refused.join(", ")
        )
    };
    let two = series(&rows, "samples", Some(2));
    anyhow::ensure!(
        !revs.is_empty() && !rpm.is_empty() && !two.is_empty(),
        "{csv}: needs revolutions, rpm and samples rows"
    );
    let tmp = format!("{png}.tmp.png");
    {
        let root = BitMapBackend::new(&tmp, (1800, 640)).into_drawing_area();
        root.fill(&WHITE)?;
        let (top, body) = root.split_vertically(50);
        top.draw(&Text::new(
            "How camsim's run time grows (scripts/growth.sh): points measured; dashed, time proportional to x through the first point",
            (20, 15),
            ("sans-serif", 24),
        ))?;
        let panels = body.split_evenly((1, 3));
        let [a, b, c] = &panels[..] else {
            bail!("three panels")
        };
        loglog(
            a,
            "Full model, 800 rpm: revolutions",
            "revolutions simulated",
            "run time (ms)",
            &[("camsim run --revolutions R", blue, revs)],
        )?;
        {
            let ((x0, x1), (_, y1)) = bounds(&rpm);
            let mut chart = ChartBuilder::on(b)
                .caption("Full model, 2 revolutions: cam speed", ("sans-serif", 22))
                .margin(20)
                .x_label_area_size(50)
                .y_label_area_size(70)
                .build_cartesian_2d(x0 - 100.0..x1 + 100.0, 0.0..y1 * 1.2)?;
            chart
                .configure_mesh()
                .x_desc(refused_note.as_str())
                .y_desc("run time (ms)")
                .x_label_formatter(&|v| tick(*v))
                .y_label_formatter(&|v| tick(*v))
                .light_line_style(TRANSPARENT)
                .bold_line_style(BLACK.mix(0.12))
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 17))
                .draw()?;
            chart.draw_series(LineSeries::new(rpm.iter().copied(), blue.stroke_width(2)))?;
            chart.draw_series(rpm.iter().map(|&p| Circle::new(p, 4, blue.filled())))?;
        }
        let mut mc = vec![("2 threads", blue, two)];
        if !one.is_empty() {
            mc.push(("1 thread", orange, one));
        }
        loglog(
            c,
            "Monte Carlo, quasi-static cantilever: samples",
            "actual cams (samples)",
            "wall time (s)",
            &mc,
        )?;
        root.present()?;
    }
    std::fs::rename(&tmp, png).with_context(|| format!("writing {png}"))?;
    Ok(())
}
