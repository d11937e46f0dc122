//! Plots of the studies (histograms, bar charts, curves), drawn with the run plots'
//! embedded font: `montecarlo`, `compare`, `sensitivity` and `tolerance-study` draw with
//! these.
use anyhow::{anyhow, Result};
use plotters::prelude::*;

use crate::output::AtomicDir;

const BAR: RGBColor = RGBColor(31, 119, 180);
/// Colours of the curves of a line chart, in order.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

fn err<E: std::fmt::Display>(file: &str) -> impl Fn(E) -> anyhow::Error + '_ {
    move |e| anyhow!("cannot draw plot {file}: {e}")
}

/// Renders `size` pixels with `draw` and writes the PNG as `file` in `dir`.
pub fn png(
    dir: &mut AtomicDir,
    file: &str,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>) -> Result<()>,
) -> Result<()> {
    crate::plot::ensure_font()?;
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(err(file))?;
        draw(&root)?;
        root.present().map_err(err(file))?;
    }
    crate::plot::save_png(dir, file, &buf, size)
}

/// Bin counts of `values` over `bins` equal bins spanning their range.
pub fn bin(values: &[f64], bins: usize) -> (f64, f64, Vec<u32>) {
    let bins = bins.max(1);
    let (mut lo, mut hi) = values
        .iter()
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if lo > hi {
        (lo, hi) = (0.0, 1.0);
    }
    if hi - lo <= 1e-12 * hi.abs().max(lo.abs()).max(1e-300) {
        let half = if hi != 0.0 { 0.01 * hi.abs() } else { 0.5 };
        (lo, hi) = (lo - half, hi + half);
    }
    let mut counts = vec![0u32; bins];
    for &v in values.iter().filter(|v| v.is_finite()) {
        let k = (((v - lo) / (hi - lo)) * bins as f64).floor() as usize;
        counts[k.min(bins - 1)] += 1;
    }
    (lo, hi, counts)
}

/// A histogram binned for a plot: (lo, hi, counts of equal bins over lo..hi).
pub type Binned = (f64, f64, Vec<u32>);

/// Colour of the samples that kept contact, and of those that jumped.
pub const HELD: RGBColor = BAR;
/// Colour of the samples that jumped.
pub const JUMPED: RGBColor = RGBColor(214, 39, 40);

/// The power of ten (a power of 1000) that shows `lo..hi` in plain numbers between
/// about 0.1 and 1000, and its name for the axis title ("1000", "0.001"; "" for 1).
pub fn axis_scale(lo: f64, hi: f64) -> (f64, &'static str) {
    let m = lo.abs().max(hi.abs());
    const SCALES: [(f64, &str); 6] = [
        (1e9, "10^9"),
        (1e6, "10^6"),
        (1e3, "1000"),
        (1e-3, "0.001"),
        (1e-6, "10^-6"),
        (1e-9, "10^-9"),
    ];
    if !m.is_finite() || m == 0.0 || (0.1..1e4).contains(&m) {
        return (1.0, "");
    }
    if m >= 1e4 {
        SCALES
            .iter()
            .find(|(s, _)| *s >= 1.0 && m / s >= 10.0)
            .copied()
            .unwrap_or((1.0, ""))
    } else {
        SCALES
            .iter()
            .find(|(s, _)| *s < 1.0 && m / s >= 0.1)
            .copied()
            .unwrap_or((1.0, ""))
    }
}

/// An axis title: `quantity (unit)`, with the scale of [`axis_scale`] in the unit
/// ("stress (1000 psi)", "FPR (× 1000)").
pub fn axis_title(quantity: &str, unit: &str, scale: &str) -> String {
    match (unit.is_empty(), scale.is_empty()) {
        (true, true) => quantity.to_string(),
        (true, false) => format!("{quantity} (× {scale})"),
        (false, true) => format!("{quantity} ({unit})"),
        (false, false) => format!("{quantity} ({scale} {unit})"),
    }
}

/// One panel of a grid of histograms: the samples that kept contact and those that
/// jumped, counted over the same equal bins of `lo..hi`, stacked.
pub struct HistPanel {
    /// The panel's caption.
    pub caption: String,
    /// The quantity on the x axis, without its unit.
    pub quantity: String,
    /// Its unit ("" for none).
    pub unit: String,
    /// The bins' range.
    pub lo: f64,
    /// The bins' range.
    pub hi: f64,
    /// Counts of the samples that kept contact.
    pub held: Vec<u32>,
    /// Counts of the samples that jumped (as many bins as `held`).
    pub jumped: Vec<u32>,
    /// A line written across the panel (every sample at one value, say).
    pub note: Option<String>,
    /// The colour of `held` when the panel does not split the samples (`jumped` all 0).
    pub colour: RGBColor,
}

/// Colour of a histogram of every sample, not split by jump (the profiles).
pub const ALL: RGBColor = RGBColor(127, 127, 127);

/// Draws a legend of `entries` (colour, text) in a row centred at `y` on `area`.
pub fn legend_row<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    entries: &[(RGBColor, String)],
    y: i32,
) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let font = (crate::plot::FONT, 16).into_font().color(&BLACK);
    let widths: Vec<i32> = entries
        .iter()
        .map(|(_, t)| {
            area.estimate_text_size(t, &font)
                .map_or(8 * t.len() as i32, |(w, _)| w as i32)
        })
        .collect();
    let total: i32 = widths.iter().map(|w| w + 22 + 30).sum::<i32>() - 30;
    let (w, _) = area.dim_in_pixel();
    let mut x = (w as i32 - total) / 2;
    for ((c, t), tw) in entries.iter().zip(&widths) {
        area.draw(&Rectangle::new([(x, y - 7), (x + 14, y + 7)], c.filled()))?;
        area.draw(&Text::new(
            t.as_str(),
            (x + 22, y),
            font.clone().pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Left,
                plotters::style::text_anchor::VPos::Center,
            )),
        ))?;
        x += tw + 22 + 30;
    }
    Ok(())
}

/// A grid of stacked histograms (held below, jumped on top), `cols` panels a row,
/// titled `title` with a legend of the two colours under it, as `file` in `dir`. The
/// count axis is titled `count` ("cams").
pub fn stacked_histograms(
    dir: &mut AtomicDir,
    file: &str,
    title: &str,
    legend: &[(RGBColor, String)],
    count: &str,
    panels: &[HistPanel],
    cols: usize,
) -> Result<()> {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let size = (400 * cols as u32, 90 + 320 * rows as u32);
    png(dir, file, size, |root| {
        let (head, body) = root.split_vertically(90);
        crate::plot::draw_title(&head, title, 24, 10).map_err(err(file))?;
        legend_row(&head, legend, 66).map_err(err(file))?;
        let areas = body.split_evenly((rows, cols));
        for (p, area) in panels.iter().zip(areas.iter()) {
            let (scale, sname) = axis_scale(p.lo, p.hi);
            let (lo, hi) = (p.lo / scale, p.hi / scale);
            let top = p
                .held
                .iter()
                .zip(&p.jumped)
                .map(|(a, b)| a + b)
                .max()
                .unwrap_or(1)
                .max(1);
            let mut chart = ChartBuilder::on(area)
                .caption(&p.caption, (crate::plot::FONT, 17))
                .margin(10)
                .margin_right(20)
                .x_label_area_size(48)
                .y_label_area_size(58)
                .build_cartesian_2d(lo..hi, 0u32..top + top / 8 + 1)
                .map_err(err(file))?;
            let span = hi - lo;
            // plotters may step by as little as span / 10 for 5 labels: decimals for that.
            let x_fmt = |v: &f64| {
                let v = if v.abs() < 1e-9 * span { 0.0 } else { *v };
                crate::plot::fmt_tick(v, span * 0.8)
            };
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(5)
                .y_labels(6)
                .x_label_formatter(&x_fmt)
                .y_label_formatter(&|v| format!("{v}"))
                .x_desc(axis_title(&p.quantity, &p.unit, sname))
                .y_desc(count)
                .label_style((crate::plot::FONT, 13))
                .axis_desc_style((crate::plot::FONT, 14))
                .light_line_style(RGBColor(240, 240, 240))
                .bold_line_style(RGBColor(215, 215, 215))
                .draw()
                .map_err(err(file))?;
            let w = (hi - lo) / p.held.len().max(1) as f64;
            chart
                .draw_series(
                    p.held
                        .iter()
                        .enumerate()
                        .filter(|(_, c)| **c > 0)
                        .map(|(k, &c)| {
                            let x0 = lo + k as f64 * w;
                            Rectangle::new([(x0, 0), (x0 + w, c)], p.colour.filled())
                        }),
                )
                .map_err(err(file))?;
            chart
                .draw_series(
                    p.held
                        .iter()
                        .zip(&p.jumped)
                        .enumerate()
                        .filter(|(_, (_, j))| **j > 0)
                        .map(|(k, (&h, &j))| {
                            let x0 = lo + k as f64 * w;
                            Rectangle::new([(x0, h), (x0 + w, h + j)], JUMPED.filled())
                        }),
                )
                .map_err(err(file))?;
            if let Some(note) = &p.note {
                let (px, py) = chart.plotting_area().get_pixel_range();
                let font = (crate::plot::FONT, 15).into_font().color(&BLACK).pos(
                    plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        plotters::style::text_anchor::VPos::Top,
                    ),
                );
                let (ax, ay) = area.get_base_pixel();
                area.draw(&Text::new(
                    note.as_str(),
                    ((px.start + px.end) / 2 - ax, py.start + 8 - ay),
                    font,
                ))
                .map_err(err(file))?;
            }
        }
        Ok(())
    })
}

/// One bar of a probability chart: its name, the count of n and its interval.
pub struct ProbBar {
    /// The bar's name (a period, "whole revolution").
    pub name: String,
    /// The probability with its 95 % interval.
    pub p: crate::stats::Probability,
}

/// A chart of probabilities with their 95 % intervals (a dot and a bar from lo95 to
/// hi95 each, its count of `n` and interval written beside it), as `file` in `dir`.
pub fn probability_chart(
    dir: &mut AtomicDir,
    file: &str,
    title: &str,
    y_desc: &str,
    n: u64,
    bars: &[ProbBar],
) -> Result<()> {
    let size = (260 * bars.len().max(2) as u32 + 160, 620);
    png(dir, file, size, |root| {
        let (head, body) = root.split_vertically(50);
        crate::plot::draw_title(&head, title, 22, 12).map_err(err(file))?;
        let top = bars
            .iter()
            .map(|b| b.p.hi95)
            .fold(0.0f64, f64::max)
            .mul_add(1.25, 0.0)
            .clamp(0.01, 1.0);
        let k = bars.len() as f64;
        let names: Vec<String> = bars.iter().map(|b| b.name.clone()).collect();
        let mut chart = ChartBuilder::on(&body)
            .margin(14)
            .margin_right(30)
            .x_label_area_size(60)
            .y_label_area_size(80)
            .build_cartesian_2d(-0.5..k - 0.5, 0.0..top)
            .map_err(err(file))?;
        let x_fmt = |v: &f64| {
            let i = v.round();
            if (v - i).abs() < 1e-6 && i >= 0.0 {
                names.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        };
        let y_fmt = |v: &f64| crate::plot::fmt_tick(*v, top);
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(bars.len() + 1)
            .x_label_formatter(&x_fmt)
            .y_labels(8)
            .y_label_formatter(&y_fmt)
            .y_desc(y_desc)
            .x_desc(format!(
                "each over {n} cams; the bar is the 95 % Wilson interval"
            ))
            .label_style((crate::plot::FONT, 15))
            .axis_desc_style((crate::plot::FONT, 16))
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()
            .map_err(err(file))?;
        let style = ShapeStyle::from(&JUMPED).stroke_width(3);
        for (i, b) in bars.iter().enumerate() {
            let x = i as f64;
            for line in [
                vec![(x, b.p.lo95), (x, b.p.hi95)],
                vec![(x - 0.06, b.p.lo95), (x + 0.06, b.p.lo95)],
                vec![(x - 0.06, b.p.hi95), (x + 0.06, b.p.hi95)],
            ] {
                chart
                    .draw_series([PathElement::new(line, style)])
                    .map_err(err(file))?;
            }
        }
        chart
            .draw_series(
                bars.iter()
                    .enumerate()
                    .map(|(i, b)| Circle::new((i as f64, b.p.p), 5, JUMPED.filled())),
            )
            .map_err(err(file))?;
        let font = (crate::plot::FONT, 14).into_font().color(&BLACK);
        chart
            .draw_series(bars.iter().enumerate().map(|(i, b)| {
                // Centred above the interval, or below it when it reaches the top.
                let (y, v) = if b.p.hi95 < 0.85 * top {
                    (
                        b.p.hi95 + 0.02 * top,
                        plotters::style::text_anchor::VPos::Bottom,
                    )
                } else {
                    (
                        b.p.lo95 - 0.02 * top,
                        plotters::style::text_anchor::VPos::Top,
                    )
                };
                Text::new(
                    format!("{} of {n}: {}", b.p.count, b.p.text(3)),
                    (i as f64, y),
                    font.clone().pos(plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        v,
                    )),
                )
            }))
            .map_err(err(file))?;
        Ok(())
    })
}
