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

/// A grid of histograms, `cols` panels a row, titled `title`, as `file` in `dir`.
pub fn histograms(
    dir: &mut AtomicDir,
    file: &str,
    title: &str,
    panels: &[(String, Vec<f64>)],
    cols: usize,
) -> Result<()> {
    let binned: Vec<(String, Binned)> = panels
        .iter()
        .map(|(name, values)| {
            let bins = ((values.len() as f64).sqrt().ceil() as usize).clamp(5, 50);
            (name.clone(), bin(values, bins))
        })
        .collect();
    histograms_binned(dir, file, title, &binned, cols)
}

/// A grid of histograms already binned (`(lo, hi, counts)` a panel, equal bins).
pub fn histograms_binned(
    dir: &mut AtomicDir,
    file: &str,
    title: &str,
    panels: &[(String, Binned)],
    cols: usize,
) -> Result<()> {
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let size = (360 * cols as u32, 60 + 280 * rows as u32);
    png(dir, file, size, |root| {
        let root = root.titled(title, ("sans-serif", 24)).map_err(err(file))?;
        let areas = root.split_evenly((rows, cols));
        for ((name, (lo, hi, counts)), area) in panels.iter().zip(areas.iter()) {
            let (lo, hi) = (*lo, *hi);
            let top = counts.iter().copied().max().unwrap_or(1).max(1);
            let mut chart = ChartBuilder::on(area)
                .caption(name, ("sans-serif", 15))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(lo..hi, 0u32..top + top / 10 + 1)
                .map_err(err(file))?;
            chart
                .configure_mesh()
                .disable_x_mesh()
                .x_labels(4)
                .y_labels(5)
                .x_label_formatter(&|v| format!("{v:.3e}"))
                .label_style(("sans-serif", 11))
                .draw()
                .map_err(err(file))?;
            let w = (hi - lo) / counts.len() as f64;
            chart
                .draw_series(counts.iter().enumerate().map(|(k, &c)| {
                    let x0 = lo + k as f64 * w;
                    Rectangle::new([(x0, 0), (x0 + w, c)], BAR.filled())
                }))
                .map_err(err(file))?;
        }
        Ok(())
    })
}
