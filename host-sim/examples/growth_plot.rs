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
use camsim::figure::render::render;
use camsim::figure::{
    palette, Axis, Colour, Figure, Legend, Mark, Panel, Scale, Series, Stroke, Style, Ticks,
};
use camsim::plot::log_key_points;

/// The figure's size, pixels: three panels side by side.
const SIZE: (u32, u32) = (1800, 640);

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

/// A plain tick: no exponent, no trailing zeros (the refused speeds' note).
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

/// One series of a panel: its label, colour and points.
type Line<'a> = (&'a str, Colour, Vec<(f64, f64)>);

/// A log axis over `lo..hi`, labelled at 1, 2 and 5 times each power of ten.
fn log_axis(title: &str, unit: &str, (lo, hi): (f64, f64)) -> Axis {
    let mut a = Axis::plain(title, unit).range(lo, hi).ticks(Ticks::At {
        major: log_key_points(lo, hi, &[1.0, 2.0, 5.0]),
        minor: Vec::new(),
    });
    a.scale = Scale::Log;
    a
}

/// A log-log panel of `lines`, each its measured points on its own dashed slope-1 line
/// through the first one (a point off the line shows; a solid line through the points
/// hid it).
fn loglog(caption: &str, x: (&str, &str), y: (&str, &str), lines: &[Line<'_>]) -> Panel {
    let all: Vec<(f64, f64)> = lines.iter().flat_map(|l| l.2.iter().copied()).collect();
    let ((x0, x1), (y0, y1)) = bounds(&all);
    let mut p = Panel::new(
        log_axis(x.0, x.1, (x0 / 1.5, x1 * 1.5)),
        // Room above the points for the legend, upper right.
        log_axis(y.0, y.1, (y0 / 2.0, y1 * 8.0)),
    );
    p.caption = Some(caption.to_string());
    p.legend = Legend::Inside { rows: lines.len() };
    for (label, colour, pts) in lines {
        if let Some(&(xa, ya)) = pts.first() {
            let xb = pts.last().map_or(xa, |q| q.0);
            let guide = vec![(xa, ya), (xb, ya * xb / xa)];
            p.series
                .push(Series::line(None, guide, Stroke::dashed(*colour, 2)));
        }
        p.series.push(Series {
            label: Some(label.to_string()),
            points: pts.clone(),
            style: Style::Points(Mark::Dot, *colour),
        });
    }
    p
}

/// The linear panel of run time against cam speed.
fn against_speed(rpm: &[(f64, f64)], remark: Option<String>) -> Panel {
    let ((x0, x1), (_, y1)) = bounds(rpm);
    let mut p = Panel::new(
        Axis::plain("cam speed", "rpm").range(x0 - 100.0, x1 + 100.0),
        Axis::plain("run time", "ms").range(0.0, y1 * 1.2),
    );
    p.caption = Some("Full model, 2 revolutions: cam speed".to_string());
    p.remark = remark;
    p.series.push(Series {
        label: None,
        points: rpm.to_vec(),
        style: Style::Line(Stroke::solid(palette::BLUE, 2), Some(Mark::Dot)),
    });
    p
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
    let (blue, orange) = (palette::BLUE, palette::ORANGE);
    let revs = series(&rows, "revolutions", None);
    let rpm = series(&rows, "rpm", None);
    let one = series(&rows, "samples", Some(1));
    let refused: Vec<String> = series(&rows, "refused", None)
        .iter()
        .map(|p| tick(p.0))
        .collect();
    let refused_note = (!refused.is_empty()).then(|| {
        format!(
            "no result at {} rpm (refused: docs/BENCHMARKS.md says why)",
            refused.join(", ")
        )
    });
    let two = series(&rows, "samples", Some(2));
    anyhow::ensure!(
        !revs.is_empty() && !rpm.is_empty() && !two.is_empty(),
        "{csv}: needs revolutions, rpm and samples rows"
    );
    let mut mc = vec![("2 threads", blue, two)];
    if !one.is_empty() {
        mc.push(("1 thread", orange, one));
    }
    let panels = vec![
        loglog(
            "Full model, 800 rpm: revolutions",
            ("revolutions simulated", ""),
            ("run time", "ms"),
            &[("camsim run --revolutions R", blue, revs)],
        ),
        against_speed(&rpm, refused_note),
        loglog(
            "Monte Carlo, quasi-static cantilever: samples",
            ("actual cams (samples)", ""),
            ("wall time", "s"),
            &mc,
        ),
    ];
    let mut fig = Figure::new(
        "How camsim's run time grows (scripts/growth.sh): points measured; dashed, time proportional to x through the first point",
        SIZE,
        panels,
    );
    fig.columns = 3;
    let (rgb, _) = render(&fig)?;
    let tmp = format!("{png}.tmp.png");
    image::save_buffer_with_format(
        &tmp,
        &rgb,
        SIZE.0,
        SIZE.1,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .with_context(|| format!("writing {tmp}"))?;
    std::fs::rename(&tmp, png).with_context(|| format!("writing {png}"))?;
    Ok(())
}
