//! The drawing helpers `sensitivity` and `tolerance-study` still call directly (a PNG
//! canvas, a legend row, a palette); every other command describes its figures as data
//! for the one renderer, [`crate::figure`]. The axis scale in powers of 1000 is shared
//! with it.
use anyhow::{anyhow, Result};
use plotters::prelude::*;

use crate::output::AtomicDir;

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
